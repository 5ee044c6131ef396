//! Initial gaps and overlaps, tilted and nearly tangent obstacles, a polyline corner.

use crate::edit::Edit;

use crate::{answer, assert_uniform_pressure, contact_points, Block};

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
    let (dir, r) = answer("gap", &b.toml(), &[]);
    assert!(r["contact"]["points"].as_u64().unwrap() > 0);
    // Exact: after closing the gap the block is squeezed by 2e-5 − 1e-5 = 1e-5 over h = 1,
    // uniaxially (free sides, frictionless base): σyy = E ε / (1 − ν²) in plane strain.
    uniaxial_squeeze("gap", &b, &dir, &r, 1e-5);
}

/// The block squeezed by `squeeze` over its height between the plane and its held top, sides
/// free, frictionless: the exact uniform pressure E ε / (1 − ν²) (plane strain, σxx = 0) on
/// every closed point, and the normal resultant −σ w.
fn uniaxial_squeeze(name: &str, b: &Block, dir: &std::path::Path, r: &serde_json::Value, squeeze: f64) {
    let sigma = b.young * (squeeze / b.h) / (1.0 - b.poisson * b.poisson);
    let n = r["contact"]["normal_resultant"].as_f64().unwrap();
    assert!((n + sigma * b.w).abs() <= 1e-8 * sigma * b.w, "{name}: normal resultant {n}, exact {}", -sigma * b.w);
    assert_uniform_pressure(name, dir, sigma, 1e-8);
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
    let (dir, r) = answer("overlap", &b.toml(), &[]);
    // Exact: the plane pushes the bottom out by 1e-6 against the held top.
    uniaxial_squeeze("overlap", &b, &dir, &r, 1e-6);
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
    let normal = [5e-4, 1.0];
    let (_, r) = answer("tilted", &tilted(normal, 2e-3), &[]);
    assert!(r["contact"]["open"].as_u64().unwrap() < r["contact"]["points"].as_u64().unwrap());
    // The obstacle's force on the body lies in the friction cone (μ = 0.3) around the line's
    // normal (a sum of forces in a convex cone is in it) ...
    let resultant: Vec<f64> =
        r["contact"]["resultant"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let len = normal[0].hypot(normal[1]);
    let (n, t) = ([normal[0] / len, normal[1] / len], [normal[1] / len, -normal[0] / len]);
    let along_n = resultant[0] * n[0] + resultant[1] * n[1];
    let along_t = resultant[0] * t[0] + resultant[1] * t[1];
    assert!(
        along_n > 0.0 && along_t.abs() <= 0.3 * along_n * (1.0 + 1e-9),
        "resultant {resultant:?}: normal {along_n}, tangential {along_t}"
    );
    // ... and it balances the reaction of the held top (no other load).
    let top: Vec<f64> =
        r["results"]["reactions"]["top"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    for k in 0..2 {
        assert!(
            (top[k] + resultant[k]).abs() <= 1e-8 * along_n,
            "equilibrium: top reaction {top:?} vs contact {resultant:?}"
        );
    }
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
    let line = b.toml();
    let scene = line.edit(
        "obstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]",
        "obstacle = \"polyline\"\npoints = [[-1.0, 0.0], [1.0, -1e-3], [3.0, 0.0]]",
    );
    assert_ne!(scene, line, "the obstacle was not replaced: the block's scene text changed");
    let (dir, r) = answer("polyline", &scene, &[]);
    // The flat bottom (sunk by 5e-4 + its own 1e-5 squeeze) rests on its two ends, one on each
    // slope; the middle, above the valley's corner, stays open.
    let closed: Vec<[f64; 4]> = contact_points(&dir).into_iter().filter(|p| p[3] >= 1.0).collect();
    let near = |x: f64| closed.iter().filter(|p| (p[0] - x).abs() < 0.5).count();
    assert!(near(0.0) > 0 && near(2.0) > 0 && near(0.0) + near(2.0) == closed.len(), "closed points {closed:?}");
    // The vertical resultant carries the top load p w; the horizontal parts of the two slopes'
    // forces cancel (the valley is symmetric, the pin at the top-left corner carries the rest).
    let resultant = &r["contact"]["resultant"];
    let vertical = resultant[1].as_f64().unwrap();
    assert!((vertical - b.p * b.w).abs() <= 1e-8 * b.p * b.w, "vertical resultant {vertical} vs p w = {}", b.p * b.w);
}
