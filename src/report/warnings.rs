//! Physics warnings: answers that are right for the model solved but where the model itself is
//! doubtful. They go to `report.json` under `warnings` and to the terminal.
//!
//! - `large_displacement`: max |u| above 1 % of the body's size (bounding-box diagonal): the
//!   small-strain model (and the linearised contact gap) is not valid for such motions;
//! - `large_rotation`: a rigid rotation above 1e-2 rad, from the least-squares fit of a rigid
//!   motion to the nodal displacements, `ω = Σ (x − x̄) × u / Σ |x − x̄|²`;
//! - `locking`: ν ≥ 0.49 with a displacement element that locks (P1, P2 Lagrange);
//! - `contact_open`: every point of a contact part stays open: the contact carries nothing
//!   (a normal pointing the wrong way, a gap too large, loads that pull the body away); the
//!   warning names the part and the obstacle, and says when the body lies inside the obstacle;
//! - `polygonal_boundary`: a P1 mesh file read with `order = 2` (the mid nodes are put on the
//!   chords: curved boundaries stay polygonal).
use crate::fem::material::PlaneModel;
use crate::fem::mixed_pressure::Element;
use crate::mesh::{Mesh, Order};

/// One warning: a machine-readable kind and what it means.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Warning {
    /// A machine-readable kind, e.g. `"locking"`, `"polygonal_boundary"`.
    pub kind: &'static str,
    /// What the warning means and what to do.
    pub message: String,
}

/// The centroid of the nodes.
fn centroid(mesh: &Mesh) -> [f64; 2] {
    let n = mesh.num_nodes().max(1) as f64;
    [mesh.nodes.iter().map(|p| p[0]).sum::<f64>() / n, mesh.nodes.iter().map(|p| p[1]).sum::<f64>() / n]
}

/// Warnings about the model, known before solving.
pub fn before_solving(
    mesh: &Mesh,
    element: Element,
    poisson: f64,
    plane: PlaneModel,
    file_order: Option<Order>,
) -> Vec<Warning> {
    let mut out = Vec::new();
    if poisson >= 0.49 && plane != PlaneModel::Stress && element == Element::Lagrange {
        let (model, dual) = match plane {
            PlaneModel::Axisymmetric => ("in axisymmetry", ""),
            _ => ("in plane strain", ", or formulation = \"dual\" for the stresses"),
        };
        out.push(Warning {
            kind: "locking",
            message: format!(
                "nu = {poisson} with {:?} displacement elements {model}: they lock near incompressibility \
                 (stresses polluted, contact pressures low); use order = 2 with element = \"p2p0\" in \
                 [discretization]{dual}",
                mesh.order
            ),
        });
    }
    if file_order == Some(Order::P1) && mesh.order == Order::P2 {
        out.push(Warning {
            kind: "polygonal_boundary",
            message: "the mesh file has linear (3-node) triangles and the scene asks for order = 2: the mid nodes \
                      are put on the straight sides, so curved boundaries stay polygonal; export a second-order \
                      mesh (gmsh -order 2) to follow them"
                .into(),
        });
    }
    out
}

/// A contact part none of whose `points` closed: `obstacle` describes a rigid obstacle (`None`
/// for a pair between two bodies), `wrong_side` says when the body lies inside it.
pub fn contact_open(part: &str, points: usize, obstacle: Option<&str>, wrong_side: Option<&str>) -> Warning {
    let message = match (obstacle, wrong_side) {
        (Some(obstacle), Some(why)) => {
            format!("no point of contact part '{part}' touches {obstacle} (all {points} points open): {why}")
        }
        (Some(obstacle), None) => format!(
            "no point of contact part '{part}' touches {obstacle} (all {points} points open): the contact carries \
             nothing; if the body should press on the obstacle, check the normal's sign, the gap and the loads"
        ),
        (None, _) => format!(
            "no point of contact pair '{part}' is closed (all {points} points open): the bodies do not touch under \
             these loads; check the gap between them and the loads"
        ),
    };
    Warning { kind: "contact_open", message }
}

/// Warnings about the answer `u` (`u[2 node + c]`).
pub fn after_solving(mesh: &Mesh, u: &[f64]) -> Vec<Warning> {
    let mut out = Vec::new();
    let (size, centre) = (mesh.diagonal(), centroid(mesh));
    let max_u = u.chunks(2).map(|d| d[0].hypot(d[1])).fold(0.0, f64::max);
    if max_u > 1e-2 * size {
        out.push(Warning {
            kind: "large_displacement",
            message: format!(
                "max |u| = {max_u:.3e} is {:.1} % of the body's size {size:.3e}: outside small strains, where the \
                 linear model and the linearised contact gap hold; check the loads, the units and the supports",
                100.0 * max_u / size
            ),
        });
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (p, d) in mesh.nodes.iter().zip(u.chunks(2)) {
        let r = [p[0] - centre[0], p[1] - centre[1]];
        num += r[0] * d[1] - r[1] * d[0];
        den += r[0] * r[0] + r[1] * r[1];
    }
    let rotation = if den > 0.0 { num / den } else { 0.0 };
    if rotation.abs() > 1e-2 {
        out.push(Warning {
            kind: "large_rotation",
            message: format!(
                "the body turns by {rotation:.3e} rad as a whole (least-squares rigid fit): small-strain kinematics \
                 are not valid beyond about 1e-2 rad; check what holds the body against rotation"
            ),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::structured;

    #[test]
    fn each_warning_fires_on_its_case_only() {
        let mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 4, 2, Order::P1).unwrap();
        let small: Vec<f64> = mesh.nodes.iter().flat_map(|p| [1e-6 * p[0], -1e-6 * p[1]]).collect();
        assert!(after_solving(&mesh, &small).is_empty());
        let far: Vec<f64> = mesh.nodes.iter().flat_map(|_| [0.1, 0.0]).collect();
        let w = after_solving(&mesh, &far);
        assert_eq!(w.iter().map(|w| w.kind).collect::<Vec<_>>(), ["large_displacement"]);
        // Rigid rotations about the centre (largest |u| = θ × 1.118 at the corners, against
        // 1e-2 × the diagonal 2.236): 0.015 rad turns too much but moves little (|u| = 0.0168 <
        // 0.0224), 0.03 rad both (|u| = 0.0335).
        let turn = |theta: f64| -> Vec<&str> {
            let u: Vec<f64> = mesh.nodes.iter().flat_map(|p| [-theta * (p[1] - 0.5), theta * (p[0] - 1.0)]).collect();
            after_solving(&mesh, &u).iter().map(|w| w.kind).collect()
        };
        assert_eq!(turn(0.015), ["large_rotation"]);
        assert_eq!(turn(0.03), ["large_displacement", "large_rotation"]);
        assert!(turn(0.005).is_empty());
        assert!(before_solving(&mesh, Element::Lagrange, 0.3, PlaneModel::Strain, None).is_empty());
        let w = before_solving(&mesh, Element::Lagrange, 0.4999, PlaneModel::Strain, None);
        assert_eq!(w[0].kind, "locking");
        assert!(before_solving(&mesh, Element::P2P0, 0.4999, PlaneModel::Strain, None).is_empty());
        assert!(before_solving(&mesh, Element::Lagrange, 0.4999, PlaneModel::Stress, None).is_empty());
        let w = before_solving(&mesh, Element::Lagrange, 0.4999, PlaneModel::Axisymmetric, None);
        assert!(w.len() == 1 && w[0].message.contains("in axisymmetry") && !w[0].message.contains("dual"), "{w:?}");
        let p2 = mesh.to_quadratic();
        let w = before_solving(&p2, Element::Lagrange, 0.3, PlaneModel::Strain, Some(Order::P1));
        assert_eq!(w[0].kind, "polygonal_boundary");
    }
}
