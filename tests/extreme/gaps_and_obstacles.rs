//! Initial gaps and overlaps, tilted and nearly tangent obstacles, a polyline corner.

use crate::{answer, Block};

// ---------------------------------------------------------------- gaps and obstacle geometry

#[test]
fn initial_gap_closed_by_a_held_body() {
    // The block hangs 1e-5 above the plane, its top pushed down by 2e-5: the gap closes.
    let b = Block {
        left: false,
        right: false,
        p: 0.0,
        extra: "[[dirichlet]]\npart = \"top\"\nuy = -2e-5\n\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n".into(),
        contact: "friction = \"none\"\ngap = 1e-5".into(),
        ..Default::default()
    };
    let (_, r) = answer("gap", &b.toml(), &[]);
    assert!(r["contact"]["points"].as_u64().unwrap() > 0);
    assert!(r["contact"]["normal_resultant"].as_f64().unwrap() < 0.0, "the gap must close: {}", r["contact"]);
}

#[test]
fn initial_gap_never_closed() {
    // Pushed down by less than the gap: no contact force at all, every point open.
    let b = Block {
        left: false,
        right: false,
        p: 0.0,
        extra: "[[dirichlet]]\npart = \"top\"\nuy = -5e-6\n\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n".into(),
        contact: "friction = \"none\"\ngap = 1e-5".into(),
        ..Default::default()
    };
    let (_, r) = answer("gap_open", &b.toml(), &[]);
    assert_eq!(r["contact"]["normal_resultant"].as_f64(), Some(0.0));
    assert_eq!(r["contact"]["open"], r["contact"]["points"]);
}

#[test]
fn declared_initial_overlap() {
    // gap = −1e-6: the body starts 1 µm inside the plane, which the scene declares; held by
    // its top, the plane pushes it back out.
    let b = Block {
        left: false,
        right: false,
        p: 0.0,
        extra: "[[dirichlet]]\npart = \"top\"\nuy = 0.0\n\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n".into(),
        contact: "friction = \"none\"\ngap = -1e-6".into(),
        ..Default::default()
    };
    let (_, r) = answer("overlap", &b.toml(), &[]);
    assert!(r["contact"]["normal_resultant"].as_f64().unwrap() < 0.0);
}

fn tilted(normal: [f64; 2], push: f64) -> String {
    // A block standing on a tilted line through its lower-left corner (the rest of its bottom
    // above the line), its top clamped and pushed by `push` along −normal.
    let n = normal[0].hypot(normal[1]);
    let d = [-push * normal[0] / n, -push * normal[1] / n];
    format!(
        r#"[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.25
mesher = "gmsh"

[material]
young = 90e9
poisson = 0.3

[[dirichlet]]
part = "top"
ux = {dx:e}
uy = {dy:e}

[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [{nx:e}, {ny:e}]
friction = "coulomb"
mu = 0.3
"#,
        dx = d[0],
        dy = d[1],
        nx = normal[0],
        ny = normal[1]
    )
}

#[test]
fn tilted_obstacle() {
    let (_, r) = answer("tilted", &tilted([5e-4, 1.0], 2e-3), &[]);
    assert!(r["contact"]["open"].as_u64().unwrap() < r["contact"]["points"].as_u64().unwrap());
}

#[test]
fn nearly_tangent_obstacle_normal() {
    let (_, r) = answer("near_tangent", &tilted([1e-9, 1.0], 1e-5), &[]);
    assert_eq!(r["contact"]["open"].as_u64(), Some(0), "{}", r["contact"]);
}

#[test]
fn polyline_corner_under_the_body() {
    let b = Block { contact: "friction = \"none\"".into(), ..Default::default() };
    // A shallow valley whose corner lies under the middle of the block (0.5 mm below its
    // bottom corners' level at x = 0 and 2): the block sinks onto the two slopes.
    let scene = b.toml().replace(
        "obstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]",
        "obstacle = \"polyline\"\npoints = [[-1.0, 0.0], [1.0, -1e-3], [3.0, 0.0]]",
    );
    let (_, r) = answer("polyline", &scene, &[]);
    assert!(r["contact"]["normal_resultant"].as_f64().unwrap() < 0.0);
}
