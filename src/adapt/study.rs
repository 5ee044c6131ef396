//! # Convergence study: true errors against a reference solution, the estimate, rates
//!
//! The talk's check of the estimator (F. Lebon, "Modèles d'interface et formulations pour le
//! contact frottant : résultats et calcul d'erreur", slides "Qualité des solutions"): with no
//! analytic solution, errors are measured against a very fine mesh. Level `k = 0 … N−1`
//! meshes the scene's geometry at the cell size `h_k = h_0 / 2^k` (the refinement zone too) and
//! solves the primal, the dual and the estimate; the reference meshes it at
//! `h_0 / 2^{N−1+m}` (`m` = 1 or 2 more halvings) with P2 elements and solves the primal. With
//! `u_ref`, `σ_ref = Cε(u_ref)` on the reference mesh,
//!
//! ```text
//!   ‖Δu‖² = ∫ (ε(u_ref) − ε(u_h)) : C (ε(u_ref) − ε(u_h))       (energy norm a)
//!   ‖Δσ‖² = ∫ (σ_ref − σ_h) : C⁻¹ (σ_ref − σ_h)                   (complementary norm b)
//!   ε     = (‖Δu‖² + ‖Δσ‖²)^½ / ‖σ_ref‖_{C⁻¹}                    (the talk's ε ref, %)
//!   effectivity = e / (‖Δu‖² + ‖Δσ‖²)^½                          (1 when the estimate is exact)
//! ```
//!
//! integrated with a degree-4 rule on every reference cell (through its isoparametric map). The
//! meshes are nested only approximately (Gmsh remeshes each level), so the coarse fields are
//! evaluated at the reference quadrature points by point location ([`super::locate`]): `ε(u_h)`
//! through the coarse cell's isoparametric map, `σ_h` on the HCT piece holding the point. By
//! Prager–Synge the exact `e² = ‖u − u_h‖²_a + ‖σ − σ_h‖²_b`, so the effectivity tends to 1 as
//! the reference error becomes negligible.
//!
//! Observed rates: the least-squares slope of `log error` against `log h`, with `h` the mean
//! cell size `(|Ω| / elements)^½` of each level (for a structured mesh, the cell size up to a
//! constant). A priori: `h^1` for P1 on a smooth problem, `h^{min(k, λ)}` with a singularity of
//! exponent `λ`; the talk's frictional case showed `h^0.5`.
use std::time::Instant;

use super::driver::mesh_request;
use super::locate::Locator;
use crate::error::{Error, Result};
use crate::estimate::constitutive_relation::strain_at_point;
use crate::fem::lagrange::{self, MAX_CELL_NODES};
use crate::fem::material::Material;
use crate::fem::quadrature;
use crate::mesh::{Mesh, Order};
use crate::petsc::Session;
use crate::problem::ElasticityProblem;
use crate::scene::{MeshSpec, Scene};

/// How many levels and how fine the reference.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct StudyOptions {
    /// Meshes at `h_0, h_0/2, …, h_0/2^{levels−1}` (≥ 1).
    pub levels: usize,
    /// The reference is `reference_halvings` (1 or 2) halvings finer than the last level, P2.
    pub reference_halvings: usize,
}

/// One level of the study.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StudyLevel {
    /// Level number, 0 the coarsest.
    pub level: usize,
    /// The scene's cell size at this level.
    pub cell_size: f64,
    /// `(|Ω| / elements)^½`, the `h` of the rates.
    pub mean_size: f64,
    /// Mesh nodes.
    pub nodes: usize,
    /// Mesh triangles.
    pub elements: usize,
    /// Displacement unknowns.
    pub dofs: usize,
    /// `‖u_ref − u_h‖_a`, `‖σ_ref − σ_h‖_b` (σ_h the dual solution) and their combination
    /// `(‖Δu‖² + ‖Δσ‖²)^½`.
    pub error_displacement: f64,
    /// `‖σ_ref − σ_h‖` of the dual solution.
    pub error_stress: f64,
    /// `(‖Δu‖² + ‖Δσ‖²)^½`.
    pub error_true: f64,
    /// `100 error_true / ‖σ_ref‖`.
    pub true_percent: f64,
    /// The estimate `e`, its relative value (its own denominator) and `e / error_true`.
    pub estimate: f64,
    /// The estimate relative to its own denominator (percent).
    pub estimate_percent: f64,
    /// `e / error_true` (≥ 1 for a guaranteed bound).
    pub effectivity: f64,
    /// Run time of the level (mesh, solves, estimate, true errors).
    pub seconds: f64,
}

/// The reference solution.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StudyReference {
    /// The reference mesh's cell size (m).
    pub cell_size: f64,
    /// The reference's polynomial order (2).
    pub order: u8,
    /// Reference mesh nodes.
    pub nodes: usize,
    /// Reference mesh triangles.
    pub elements: usize,
    /// Reference displacement unknowns.
    pub dofs: usize,
    /// `‖σ_ref‖_{C⁻¹} = a(u_ref, u_ref)^½`.
    pub energy_norm: f64,
    /// Seconds of the reference solve.
    pub seconds: f64,
}

/// Least-squares slopes of `log error` against `log h` (`None` with fewer than 2 levels).
#[derive(Debug, Clone, serde::Serialize)]
pub struct StudyRates {
    /// Rate of the displacement error.
    pub displacement: Option<f64>,
    /// Rate of the dual stress error.
    pub stress: Option<f64>,
    /// Rate of the combined true error.
    pub true_error: Option<f64>,
    /// Rate of the estimate.
    pub estimate: Option<f64>,
}

/// The whole study (`study.json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct StudyOutcome {
    /// The program and its version.
    pub program: String,
    /// The scene's source.
    pub scene: String,
    /// The scene's title.
    pub title: Option<String>,
    /// The levels' polynomial order.
    pub order: u8,
    /// The options of the study.
    pub options: StudyOptions,
    /// The reference solution.
    pub reference: StudyReference,
    /// Every level, coarsest first.
    pub levels: Vec<StudyLevel>,
    /// The convergence rates.
    pub rates: StudyRates,
}

/// The scene with its cell sizes (and refinement size) multiplied by `factor`, at `order`.
pub fn scaled(scene: &Scene, factor: f64, order: Order) -> Scene {
    let mut s = scene.clone();
    s.order = order;
    match &mut s.mesh {
        MeshSpec::Rectangle { cell_size, refine, .. }
        | MeshSpec::Disc { cell_size, refine, .. }
        | MeshSpec::HalfDisc { cell_size, refine, .. }
        | MeshSpec::QuarterDisc { cell_size, refine, .. } => {
            *cell_size *= factor;
            if let Some(r) = refine {
                r.cell_size *= factor;
            }
        }
        MeshSpec::File { .. } => {}
    }
    s
}

/// The scene's cell size (NaN for a mesh file).
pub fn cell_size(scene: &Scene) -> f64 {
    match &scene.mesh {
        MeshSpec::Rectangle { cell_size, .. }
        | MeshSpec::Disc { cell_size, .. }
        | MeshSpec::HalfDisc { cell_size, .. }
        | MeshSpec::QuarterDisc { cell_size, .. } => *cell_size,
        MeshSpec::File { .. } => f64::NAN,
    }
}

/// The least-squares slope of `ln y` against `ln x`.
pub fn fitted_rate(x: &[f64], y: &[f64]) -> Option<f64> {
    let pts: Vec<(f64, f64)> =
        x.iter().zip(y).filter(|(a, b)| **a > 0.0 && **b > 0.0).map(|(a, b)| (a.ln(), b.ln())).collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let (mx, my) = (pts.iter().map(|p| p.0).sum::<f64>() / n, pts.iter().map(|p| p.1).sum::<f64>() / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

fn area(mesh: &Mesh) -> f64 {
    (0..mesh.num_cells())
        .map(|c| {
            let v = mesh.cell(c);
            let (a, b, d) = (mesh.nodes[v[0]], mesh.nodes[v[1]], mesh.nodes[v[2]]);
            0.5 * ((b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1])).abs()
        })
        .sum()
}

fn quadratic(m: &[[f64; 3]; 3], v: [f64; 3]) -> f64 {
    (0..3).map(|i| (0..3).map(|j| v[i] * m[i][j] * v[j]).sum::<f64>()).sum()
}

/// The reference strain at every quadrature point of the reference mesh, with its weight: all
/// the true errors need of the reference solution (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceField {
    /// `(x, w |det J|, ε(u_ref)(x))` per quadrature point.
    pub points: Vec<([f64; 2], f64, [f64; 3])>,
}

/// The true errors of a primal–dual pair against a reference ([`ReferenceField::true_errors`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrueErrors {
    /// `‖u_ref − u_h‖_a`.
    pub displacement: f64,
    /// `‖σ_ref − σ_h‖_b` (σ_h the dual solution).
    pub stress: f64,
}

impl TrueErrors {
    /// `(‖Δu‖² + ‖Δσ‖²)^½`.
    pub fn combined(&self) -> f64 {
        self.displacement.hypot(self.stress)
    }
}

impl ReferenceField {
    /// The strains of the displacement `u` on `mesh` at the points of a degree-4 rule.
    pub fn new(mesh: &Mesh, u: &[f64]) -> Self {
        let rule = quadrature::triangle(4);
        let mut points = Vec::with_capacity(mesh.num_cells() * rule.len());
        let mut coords = [[0.0; 2]; MAX_CELL_NODES];
        for c in 0..mesh.num_cells() {
            let nodes = mesh.cell(c);
            for (x, &n) in coords.iter_mut().zip(nodes) {
                *x = mesh.nodes[n];
            }
            for (xi, w) in rule.points.iter().zip(&rule.weights) {
                let p = lagrange::map_cell_point(mesh.order, &coords[..nodes.len()], *xi);
                let mut e = [0.0; 3];
                for (g, &n) in p.gradients[..nodes.len()].iter().zip(nodes) {
                    let (ux, uy) = (u[2 * n], u[2 * n + 1]);
                    e[0] += g[0] * ux;
                    e[1] += g[1] * uy;
                    e[2] += g[1] * ux + g[0] * uy;
                }
                points.push((p.x, w * p.det.abs(), e));
            }
        }
        ReferenceField { points }
    }

    /// `‖σ_ref‖_{C⁻¹} = a(u_ref, u_ref)^½`.
    pub fn energy_norm(&self, material: &Material) -> f64 {
        let c = material.elasticity();
        self.points.iter().map(|(_, w, e)| w * quadratic(&c, *e)).sum::<f64>().sqrt()
    }

    /// The true errors of the solved pair of `problem` (primal displacement and dual stresses,
    /// after `solve`, `solve_dual`), integrated on the reference's points.
    pub fn true_errors(&self, problem: &ElasticityProblem) -> Result<TrueErrors> {
        let (Some(u), Some(dual)) = (&problem.displacement, &problem.dual) else {
            return Err(Error::PetscUsage("true errors: the primal and the dual must be solved first".into()));
        };
        let mesh = &problem.mesh;
        let material = &problem.material;
        let (c, s) = (material.elasticity(), material.compliance());
        let sigma = dual.system.field(mesh, &dual.phi);
        let locator = Locator::new(mesh);
        let (mut du, mut ds) = (0.0, 0.0);
        for (x, w, e_ref) in &self.points {
            let Some(cell) = locator.locate(*x) else { continue };
            let e_h = strain_at_point(mesh, u, cell, *x);
            let d = [e_ref[0] - e_h[0], e_ref[1] - e_h[1], e_ref[2] - e_h[2]];
            du += w * quadratic(&c, d);
            let s_ref = material.stress(*e_ref);
            let s_h = sigma.stress_at(cell, *x);
            ds += w * quadratic(&s, [s_ref[0] - s_h[0], s_ref[1] - s_h[1], s_ref[2] - s_h[2]]);
        }
        Ok(TrueErrors { displacement: du.sqrt(), stress: ds.sqrt() })
    }

    /// The field as bytes: the point count (u64), then 6 f64 per point (x, y, weight, three
    /// strains), little-endian.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(8 + 48 * self.points.len());
        out.extend_from_slice(&(self.points.len() as u64).to_le_bytes());
        for (x, w, e) in &self.points {
            for v in [x[0], x[1], *w, e[0], e[1], e[2]] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        out
    }

    /// The field from [`Self::to_bytes`]; `None` when the bytes are not such a field.
    pub fn from_bytes(bytes: &[u8]) -> Option<Self> {
        let n = u64::from_le_bytes(bytes.get(..8)?.try_into().ok()?) as usize;
        if bytes.len() != 8 + 48 * n {
            return None;
        }
        let f = |k: usize| f64::from_le_bytes(bytes[8 + 8 * k..16 + 8 * k].try_into().expect("8 bytes"));
        let points = (0..n)
            .map(|i| {
                let k = 6 * i;
                ([f(k), f(k + 1)], f(k + 2), [f(k + 3), f(k + 4), f(k + 5)])
            })
            .collect();
        Some(ReferenceField { points })
    }
}

/// Run the study of `scene`; `on_level` is called after the reference (level `None`) and after
/// each level. Elasticity scenes with a geometry (not a mesh file).
pub fn study(
    session: &Session,
    scene: &Scene,
    options: StudyOptions,
    on_level: &mut dyn FnMut(Option<&StudyLevel>, &StudyReference),
) -> Result<StudyOutcome> {
    crate::problem::axisymmetry::refuse_in_axisymmetry(scene, "the convergence study (signorini study)")?;
    if options.levels == 0 {
        return Err(Error::Usage("study: --levels must be at least 1".into()));
    }
    if !(1..=2).contains(&options.reference_halvings) {
        return Err(Error::Usage(format!(
            "study: the reference is 1 or 2 halvings finer than the last level, got {}",
            options.reference_halvings
        )));
    }
    mesh_request(scene, "study")?; // refuses mesh files
    if options.levels + options.reference_halvings > 12 {
        return Err(Error::Usage(format!(
            "study: {} levels and {} reference halvings divide the cell size by 2^{}: too fine",
            options.levels,
            options.reference_halvings,
            options.levels - 1 + options.reference_halvings
        )));
    }
    let h0 = cell_size(scene);
    // The reference: P2, m halvings below the last level.
    let start = Instant::now();
    let factor = 0.5f64.powi((options.levels - 1 + options.reference_halvings) as i32);
    let mut problem = ElasticityProblem::setup_system(session, scaled(scene, factor, Order::P2))?;
    problem.assemble()?;
    problem.solve()?;
    problem.postprocess()?;
    let material: Material = problem.material;
    let ref_mesh = problem.mesh.clone();
    let u_ref = problem.displacement.clone().ok_or_else(|| Error::PetscUsage("study: no reference solution".into()))?;
    let reference_dofs = problem.num_dofs();
    drop(problem);
    let field = ReferenceField::new(&ref_mesh, &u_ref);
    let reference = StudyReference {
        cell_size: h0 * factor,
        order: 2,
        nodes: ref_mesh.num_nodes(),
        elements: ref_mesh.num_cells(),
        dofs: reference_dofs,
        energy_norm: field.energy_norm(&material),
        seconds: start.elapsed().as_secs_f64(),
    };
    drop(u_ref);
    on_level(None, &reference);

    let mut levels = Vec::new();
    for k in 0..options.levels {
        let start = Instant::now();
        let level_scene = scaled(scene, 0.5f64.powi(k as i32), scene.order);
        let mut problem = ElasticityProblem::setup_system(session, level_scene)?;
        problem.assemble()?;
        problem.solve()?;
        problem.postprocess()?;
        problem.solve_dual()?;
        problem.estimate()?;
        let Some(est) = &problem.estimate else {
            return Err(Error::PetscUsage("study: a level was not solved".into()));
        };
        let errors = field.true_errors(&problem)?;
        let error_true = errors.combined();
        let mesh = &problem.mesh;
        levels.push(StudyLevel {
            level: k,
            cell_size: cell_size(&problem.scene),
            mean_size: (area(mesh) / mesh.num_cells() as f64).sqrt(),
            nodes: mesh.num_nodes(),
            elements: mesh.num_cells(),
            dofs: problem.num_dofs(),
            error_displacement: errors.displacement,
            error_stress: errors.stress,
            error_true,
            true_percent: if reference.energy_norm > 0.0 { 100.0 * error_true / reference.energy_norm } else { 0.0 },
            estimate: est.estimate.error,
            estimate_percent: est.estimate.relative_percent,
            effectivity: if error_true > 0.0 { est.estimate.error / error_true } else { f64::NAN },
            seconds: start.elapsed().as_secs_f64(),
        });
        on_level(levels.last(), &reference);
    }
    let h: Vec<f64> = levels.iter().map(|l| l.mean_size).collect();
    let rate = |f: fn(&StudyLevel) -> f64| fitted_rate(&h, &levels.iter().map(f).collect::<Vec<_>>());
    let rates = StudyRates {
        displacement: rate(|l| l.error_displacement),
        stress: rate(|l| l.error_stress),
        true_error: rate(|l| l.error_true),
        estimate: rate(|l| l.estimate),
    };
    Ok(StudyOutcome {
        program: format!("signorini {} ({})", env!("CARGO_PKG_VERSION"), env!("SIGNORINI_COMMIT")),
        scene: scene.source.display().to_string(),
        title: scene.title.clone(),
        order: scene.order.degree() as u8,
        options,
        reference,
        levels,
        rates,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_fields_round_trip_through_bytes() {
        let field =
            ReferenceField { points: vec![([0.5, -1.0], 0.25, [1e-3, -2e-4, 3.5e-5]), ([1.0, 2.0], 1e-9, [0.0; 3])] };
        let bytes = field.to_bytes();
        assert_eq!(bytes.len(), 8 + 2 * 48);
        assert_eq!(ReferenceField::from_bytes(&bytes), Some(field));
        assert_eq!(ReferenceField::from_bytes(&bytes[..bytes.len() - 1]), None);
        assert_eq!(ReferenceField::from_bytes(&[1, 2]), None);
    }

    #[test]
    fn fitted_rate_recovers_a_power_law() {
        let h = [0.4, 0.2, 0.1, 0.05];
        let e: Vec<f64> = h.iter().map(|h: &f64| 3.0 * h.powf(1.3)).collect();
        assert!((fitted_rate(&h, &e).unwrap() - 1.3).abs() < 1e-12);
        assert!(fitted_rate(&[0.1], &[1.0]).is_none());
        assert!(fitted_rate(&[0.1, 0.1], &[1.0, 2.0]).is_none());
    }
}
