//! Symmetry planes and pins on contact nodes, and contact on the whole boundary.

use crate::{answer, contact_points, patch, Block};
use std::path::Path;

/// The node at (x, y) is a contact node and closed (status ≥ 1 in solution.vtu), not dropped
/// from the contact set by its Dirichlet condition (status −1, absent from `contact_points`).
fn assert_closed_contact_node(name: &str, dir: &Path, x: f64, y: f64) {
    let points = contact_points(dir);
    let node = points.iter().find(|p| (p[0] - x).abs() < 1e-12 && (p[1] - y).abs() < 1e-12);
    match node {
        Some(p) => assert!(p[3] >= 1.0, "{name}: the contact node ({x}, {y}) is open: {p:?}"),
        None => panic!("{name}: ({x}, {y}) is not a contact node: {points:?}"),
    }
}

// ---------------------------------------------------------------- constrained contact nodes

#[test]
fn symmetry_plane_through_a_contact_node() {
    // The frictionless patch test with its left face on a symmetry plane (ux = 0) instead of
    // the lateral pressure: the same exact solution (ux = 0 everywhere), and the corner node
    // (0, 0) has ux prescribed and must stay a contact node.
    let b = Block { left: false, extra: "[[dirichlet]]\npart = \"left\"\nux = 0.0\n".into(), ..Default::default() };
    let dir = patch("symmetry_plane", &b, &[]);
    assert_closed_contact_node("symmetry_plane", &dir, 0.0, 0.0);
}

#[test]
fn symmetry_plane_through_a_contact_node_p2_friction() {
    let b = Block {
        left: false,
        order: 2,
        extra: "[[dirichlet]]\npart = \"left\"\nux = 0.0\n".into(),
        contact: "friction = \"coulomb\"\nmu = 0.3".into(),
        ..Default::default()
    };
    let dir = patch("symmetry_plane_p2", &b, &[]);
    assert_closed_contact_node("symmetry_plane_p2", &dir, 0.0, 0.0);
}

#[test]
fn pin_at_a_contact_node() {
    // ux = 0 at the contact node (0, 0) instead of the top-left corner.
    let b = Block { extra: "[[dirichlet]]\npoint = [0.0, 0.0]\nux = 0.0\n".into(), ..Default::default() };
    let dir = patch("pin_contact_node", &b, &[]);
    assert_closed_contact_node("pin_contact_node", &dir, 0.0, 0.0);
}

#[test]
fn whole_boundary_contact_part() {
    // A disc whose whole boundary may touch, resting on a plane under its weight, held
    // sideways by friction only.
    let scene = r#"[mesh]
shape = "disc"
center = [0.0, 0.1]
radius = 0.1
cell_size = 0.01

[material]
young = 210e9
poisson = 0.3

[loads]
body_force = [0.0, -7.7e4]

[contact]
part = "circle"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = 0.3
"#;
    let (_, r) = answer("disc_whole_boundary", scene, &[]);
    // The weight of the meshed (polygonal) disc.
    let weight = -r["results"]["applied_force"][1].as_f64().unwrap();
    assert!((weight - 7.7e4 * std::f64::consts::PI * 0.01).abs() < 1e-2 * weight);
    let n = r["contact"]["normal_resultant"].as_f64().unwrap();
    assert!((n + weight).abs() < 1e-7 * weight, "normal resultant {n} vs weight {weight}");
}
