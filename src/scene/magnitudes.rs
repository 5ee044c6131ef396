//! Refusing data whose products overflow double precision.
//!
//! Each value is finite on its own (the parser checks that), but the solve multiplies them: a
//! load `t` on a body of size L and modulus E gives forces `t L`, displacements `t L / E` and
//! energies `t² L² / E`; the contact checks multiply forces by displacements. A scene whose
//! energy scale passes 1e280 (double precision ends near 1.8e308) cannot be solved reliably:
//! it is refused by name before anything is solved, with the location of the value. Along a
//! load path (`[evolution]`) each load counts with the largest |factor| it reaches
//! ([`Scene::largest_factor`]).
use super::{DirichletTarget, Load, Scene};
use crate::error::{Error, Location, Result};
use crate::mesh::Mesh;

/// Largest energy scale accepted (J per unit thickness, in the scene's units).
const MAX_ENERGY: f64 = 1e280;

fn refuse(at: &Location, what: String) -> Error {
    Error::Scene {
        location: at.clone(),
        message: format!(
            "{what}: the products the solve forms (forces × displacements) would overflow double precision"
        ),
        hint: "use consistent units of moderate size (e.g. N, m, Pa or N, mm, MPa)".into(),
    }
}

impl Scene {
    /// Refuse loads and prescribed displacements whose energy scale overflows, given the body's
    /// size (the mesh's bounding-box diagonal).
    pub fn check_magnitudes(&self, mesh: &Mesh) -> Result<()> {
        let size = mesh.diagonal();
        let young = self.material.young;
        let energy_of_traction = |t: f64| (t * size) * (t * size / young);
        for t in &self.tractions {
            let (value, name) = match t.load {
                Load::Traction(v) => (v[0].abs().max(v[1].abs()), "traction"),
                Load::Pressure(p) => (p.abs(), "pressure"),
            };
            let value = value * self.largest_factor(t.name.as_deref());
            let energy = energy_of_traction(value);
            if !(energy.is_finite() && energy <= MAX_ENERGY) {
                return Err(refuse(
                    &t.at,
                    format!("{name} {value:e} on part '{}' of a body of size {size:.3e} with E = {young:e}", t.part),
                ));
            }
        }
        let b = self.body_force[0].abs().max(self.body_force[1].abs())
            * self.largest_factor(self.body_force_name.as_deref());
        let energy = energy_of_traction(b * size);
        if !(energy.is_finite() && energy <= MAX_ENERGY) {
            let at = Location { file: self.source.clone(), line: 1, column: 1 };
            return Err(refuse(&at, format!("body force {b:e} on a body of size {size:.3e} with E = {young:e}")));
        }
        for d in &self.dirichlet {
            let factor = self.largest_factor(d.name.as_deref());
            for u0 in [d.ux, d.uy].into_iter().flatten().map(|u| u * factor) {
                let energy = young * u0 * u0;
                if !(energy.is_finite() && energy <= MAX_ENERGY) {
                    let target = match &d.target {
                        DirichletTarget::Part(p) => format!("part '{p}'"),
                        DirichletTarget::Point(p) => format!("point {p:?}"),
                    };
                    return Err(refuse(
                        &d.at,
                        format!("prescribed displacement {u0:e} on {target} with E = {young:e}"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The largest |factor| a load named `name` (`None`: unnamed) reaches along the scene's load
    /// path: the largest |value| of its table's rows (the extremes of a piecewise-linear
    /// function), or of the ramp `t / t_end` at the path's ends; 1 without a load path.
    pub fn largest_factor(&self, name: Option<&str>) -> f64 {
        let Some(e) = &self.evolution else { return 1.0 };
        match name.and_then(|n| e.function(n)) {
            Some(f) => f.points.iter().map(|p| p[1].abs()).fold(0.0, f64::max),
            None => e.factor(None, e.start).abs().max(e.factor(None, e.end()).abs()),
        }
    }
}
