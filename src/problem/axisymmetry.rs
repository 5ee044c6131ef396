//! Bodies of revolution (`[material] plane = "axisymmetric"`): what the driver does to a mesh and
//! to its constraints before assembling, and what it refuses.
//!
//! ```text
//!        z (= y)
//!        ^
//!        |  axis r = 0: u_r = 0 on every node there
//!        |-----+
//!        |     |      the mesh: the meridian half-plane r = x >= 0 of the body;
//!        |     |      a cell of area dA at radius r is a ring of volume 2 pi r dA
//!        |-----+
//!        +-----------> r (= x)
//! ```
//!
//! - The mesh gets the axisymmetric [`Measure`]: every integral carries `2π r`, so that forces,
//!   reactions and energies are those of the **full revolution** (N, J), as in a 3D model.
//! - A node with `r < −1e-9 L` (`L` the mesh's size) is an error naming it: the mesh must lie in
//!   `r ≥ 0`. Nodes with `|r| ≤ 1e-9 L` are on the axis: their `r` is set to 0 and their radial
//!   displacement to 0 (the hoop strain `u_r / r` would be infinite otherwise; by symmetry the
//!   exact solution has `u_r = 0` there).
//! - The one rigid motion is the translation along z ([`Constraints::check_rigid_motions`]).
//! - Refused: the dual formulation and the estimate (the Airy stress function gives plane
//!   equilibrium only: an axisymmetric stress field satisfies `∂σrr/∂r + ∂σrz/∂z + (σrr − σθθ)/r = 0`,
//!   which no Airy function of `(r, z)` generates, so the error in the constitutive relation would
//!   need a stress field equilibrated by another construction, e.g. Ladevèze's element
//!   equilibration), hence mesh adaptation, and the interface laws (their laws are per unit
//!   length of a plane interface; a point on the axis has no area).
//!
//! Reference: O. C. Zienkiewicz, R. L. Taylor, J. Z. Zhu, *The Finite Element Method: Its Basis
//! and Fundamentals*, 7th ed., Butterworth-Heinemann 2013, §6.2 (axisymmetric stress analysis,
//! the axis condition `u_r = 0`).
use std::path::Path;

use crate::error::{Error, Result};
use crate::fem::assembly::Constraints;
use crate::fem::material::PlaneModel;
use crate::mesh::{Measure, Mesh};
use crate::scene::{PlaneSpec, Scene};

/// Relative distance (to the mesh's size) within which a node is on the axis.
pub const AXIS_TOLERANCE: f64 = 1e-9;

/// Give `mesh` the measure of `plane`; in axisymmetry check `r ≥ 0` and put the nodes near the
/// axis on it (`r = 0` exactly). `source` names the mesh file in the error, if there is one.
pub fn prepare_mesh(mesh: &mut Mesh, plane: PlaneModel, source: Option<&Path>) -> Result<()> {
    if plane != PlaneModel::Axisymmetric {
        mesh.measure = Measure::Plane;
        return Ok(());
    }
    mesh.measure = Measure::Axisymmetric;
    let size = mesh_size(mesh);
    let tolerance = AXIS_TOLERANCE * size;
    if let Some((node, p)) = mesh.nodes.iter().enumerate().find(|(_, p)| p[0] < -tolerance) {
        let error = Error::mesh(
            format!("node {node} at ({:e}, {:e})", p[0], p[1]),
            format!(
                "has r = x = {:e} < 0, but an axisymmetric mesh (plane = \"axisymmetric\") is the meridian half-plane \
                 r = x >= 0 of the body, its axis the line x = 0: move or cut the geometry so that every node has \
                 x >= 0 (a body on the axis has its axis edge at x = 0)",
                p[0]
            ),
        );
        return Err(match source {
            Some(file) => error.in_mesh_file(file),
            None => error,
        });
    }
    for p in &mut mesh.nodes {
        if p[0].abs() <= tolerance {
            p[0] = 0.0;
        }
    }
    Ok(())
}

/// The nodes on the axis (`r = 0` after [`prepare_mesh`]); none on a plane mesh.
pub fn axis_nodes(mesh: &Mesh) -> Vec<usize> {
    if !mesh.measure.is_axisymmetric() {
        return Vec::new();
    }
    (0..mesh.num_nodes()).filter(|&k| mesh.nodes[k][0] == 0.0).collect()
}

/// `u_r = 0` on the axis nodes (a plane mesh: nothing). A Dirichlet condition that prescribes a
/// nonzero `ux` there is an error (it would tear the axis open).
pub fn fix_axis(mesh: &Mesh, constraints: &mut Constraints) -> Result<()> {
    for node in axis_nodes(mesh) {
        match constraints.value(2 * node) {
            Some(u) if u != 0.0 => {
                return Err(Error::mesh(
                    format!("node {node} at (0, {:e}) on the axis", mesh.nodes[node][1]),
                    format!(
                        "a [[dirichlet]] condition prescribes ux = {u:e} there, but a node on the axis of a body of \
                         revolution cannot move radially (ux = u_r = 0 by symmetry): remove ux from the condition or \
                         keep its part off the axis"
                    ),
                ))
            }
            _ => constraints.fix(2 * node, 0.0),
        }
    }
    Ok(())
}

/// The dual formulation, the estimate (hence mesh adaptation) and the interface laws are
/// refused on an axisymmetric scene (module doc), before any work; `what` names the request.
pub fn refuse_in_axisymmetry(scene: &Scene, what: &str) -> Result<()> {
    if !is_axisymmetric(scene) {
        return Ok(());
    }
    Err(Error::Formulation {
        message: format!(
            "{what} is not available for a body of revolution ([material] plane = \"axisymmetric\" in {}): the dual \
             formulation's Airy stress function gives plane equilibrium only, and the error in the constitutive \
             relation needs a stress field in equilibrium with the axisymmetric loads (the hoop stress enters the \
             radial equilibrium)",
            scene.source.display()
        ),
        hint: "run the primal formulation without --estimate (remove --formulation dual / --estimate / [estimate]); \
               the run still reports its contact residuals and equilibrium"
            .into(),
    })
}

/// Interface laws on an axisymmetric scene: refused (module doc).
pub fn refuse_interface_laws(scene: &Scene) -> Result<()> {
    if !is_axisymmetric(scene) {
        return Ok(());
    }
    match crate::interface_law::interfaces_of(scene).first() {
        None => Ok(()),
        Some((contact, spec)) => Err(Error::Formulation {
            message: format!(
                "the interface law `{}` on `{contact}` ({}:{}) is for plane interfaces: it is not available with \
                 plane = \"axisymmetric\"",
                crate::interface_law::law_name(&spec.law),
                spec.at.file.display(),
                spec.at.line
            ),
            hint: "remove the [contact.interface] / [contact_pair.interface] table, or model a plane section \
                   (plane = \"strain\")"
                .into(),
        }),
    }
}

/// Whether the scene (or its first body) is axisymmetric.
pub fn is_axisymmetric(scene: &Scene) -> bool {
    scene.material.plane == PlaneSpec::Axisymmetric
        || scene.bodies.first().is_some_and(|b| b.material.plane == PlaneSpec::Axisymmetric)
}

fn mesh_size(mesh: &Mesh) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &mesh.nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let size = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if size.is_finite() && size > 0.0 {
        size
    } else {
        1.0
    }
}
