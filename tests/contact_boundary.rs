//! Rigid obstacles (closest-point projections) and the discretized contact boundary of a mesh
//! part: frames, gaps, consistent weights, the operator B, and pressure recovery without the
//! P2 vertex/mid-node checkerboard.
use signorini::contact::boundary::ContactBoundary;
use signorini::contact::obstacle::{Obstacle, Projection};
use signorini::fem::{load_vector, EdgeLoad, Loads, Traction};
use signorini::mesh::gmsh::{generate, MeshRequest, Refinement, Shape};
use signorini::mesh::structured::rectangle;
use signorini::mesh::{Mesh, Order};
use signorini::Error;

const SQRT2: f64 = std::f64::consts::SQRT_2;

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[track_caller]
fn assert_close(a: f64, b: f64, tol: f64) {
    assert!(close(a, b, tol), "{a} != {b} (tol {tol})");
}

#[track_caller]
fn assert_projection(p: Projection, point: [f64; 2], normal: [f64; 2], d: f64) {
    for c in 0..2 {
        assert_close(p.point[c], point[c], 1e-14);
        assert_close(p.normal[c], normal[c], 1e-14);
    }
    assert_close(p.signed_distance, d, 1e-14);
}

/// `x = p + d ν` and `|ν| = 1` for every projection.
#[track_caller]
fn assert_orthogonal(x: [f64; 2], p: Projection) {
    assert_close(p.normal[0].hypot(p.normal[1]), 1.0, 1e-15);
    for ((pc, nc), xc) in p.point.iter().zip(p.normal).zip(x) {
        assert_close(pc + p.signed_distance * nc, xc, 1e-14);
    }
}

fn usage_message(e: Error) -> String {
    match e {
        Error::Usage(m) => m,
        other => panic!("expected Error::Usage, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Obstacles

#[test]
fn line_with_an_oblique_normal() {
    // Line through (1, 2) with normal (1, 1)/√2 (given unnormalized).
    let line = Obstacle::new_line([1.0, 2.0], [3.0, 3.0]).unwrap();
    let nu = [1.0 / SQRT2, 1.0 / SQRT2];
    let Obstacle::Line { point, normal } = line else { panic!("{line:?}") };
    assert_eq!(point, [1.0, 2.0]);
    assert_close(normal[0], nu[0], 1e-15);
    assert_close(normal[1], nu[1], 1e-15);
    // Body side: (3, 2) − (1, 2) = (2, 0), d = 2/√2 = √2, foot (2, 1).
    let x = [3.0, 2.0];
    let p = line.project(x);
    assert_projection(p, [2.0, 1.0], nu, SQRT2);
    assert_orthogonal(x, p);
    // Obstacle side: (0, 0), d = (−1, −2)·ν = −3/√2, foot (1.5, 1.5).
    let x = [0.0, 0.0];
    let p = line.project(x);
    assert_projection(p, [1.5, 1.5], nu, -3.0 / SQRT2);
    assert_orthogonal(x, p);
    // On the line.
    assert_projection(line.project([0.0, 3.0]), [0.0, 3.0], nu, 0.0);
}

#[test]
fn circle_outside_inside_and_centre() {
    let circle = Obstacle::new_circle([1.0, -1.0], 2.0).unwrap();
    // (4, 3) − c = (3, 4): distance 5, d = 3, ν = (0.6, 0.8), foot c + 2ν = (2.2, 0.6).
    let x = [4.0, 3.0];
    let p = circle.project(x);
    assert_projection(p, [2.2, 0.6], [0.6, 0.8], 3.0);
    assert_orthogonal(x, p);
    // Inside: (1, 0), distance 1, d = −1, ν = (0, 1), foot (1, 1).
    let x = [1.0, 0.0];
    let p = circle.project(x);
    assert_projection(p, [1.0, 1.0], [0.0, 1.0], -1.0);
    assert_orthogonal(x, p);
    // On the circle.
    assert_projection(circle.project([-1.0, -1.0]), [-1.0, -1.0], [-1.0, 0.0], 0.0);
    // Centre: documented choice ν = (0, −1), d = −R.
    assert_projection(circle.project([1.0, -1.0]), [1.0, -3.0], [0.0, -1.0], -2.0);
}

/// Travelling left to right, body above:
///
/// ```text
///   ... (0,0) ------ (2,0)                    (6,0) ...
///                        \                   /
///                        (3,-1) -------- (5,-1)
/// ```
/// (2, 0): right turn, convex obstacle corner; (3, −1), (5, −1): left turns, concave corners.
fn profile() -> Obstacle {
    Obstacle::new_polyline(vec![[0.0, 0.0], [2.0, 0.0], [3.0, -1.0], [5.0, -1.0], [6.0, 0.0]]).unwrap()
}

#[test]
fn polyline_on_segments() {
    let obstacle = profile();
    // First segment, above and below.
    assert_projection(obstacle.project([1.0, 0.5]), [1.0, 0.0], [0.0, 1.0], 0.5);
    assert_projection(obstacle.project([1.0, -0.25]), [1.0, 0.0], [0.0, 1.0], -0.25);
    // Sloping segment (2,0)→(3,−1), normal (1, 1)/√2: from (3, −0.5) the foot is (2.75, −0.75)
    // (closer than the concave vertex (3, −1) at distance 0.5).
    let x = [3.0, -0.5];
    let p = obstacle.project(x);
    assert_projection(p, [2.75, -0.75], [1.0 / SQRT2, 1.0 / SQRT2], 0.25 * SQRT2);
    assert_orthogonal(x, p);
    // Bottom segment, body side and obstacle side.
    assert_projection(obstacle.project([4.0, 1.0]), [4.0, -1.0], [0.0, 1.0], 2.0);
    assert_projection(obstacle.project([4.0, -1.5]), [4.0, -1.0], [0.0, 1.0], -0.5);
    // Below a concave corner, equidistant foot on the bottom segment's start.
    assert_projection(obstacle.project([3.0, -1.5]), [3.0, -1.0], [0.0, 1.0], -0.5);
}

#[test]
fn polyline_at_vertices() {
    let obstacle = profile();
    // Convex corner (2, 0), body side: x in the cone between the normals (0,1) and (1,1)/√2,
    // neither foot lies on its segment; ν = (x − V)/|x − V| = (0.6, 0.8), d = +0.5.
    let x = [2.3, 0.4];
    let p = obstacle.project(x);
    assert_projection(p, [2.0, 0.0], [0.6, 0.8], 0.5);
    assert_orthogonal(x, p);
    // Concave corner (3, −1), obstacle side: x − V = (−0.1, −0.3), d = −√0.1, ν = (V − x)/|V − x|.
    let x = [2.9, -1.3];
    let p = obstacle.project(x);
    let l = 0.1f64.sqrt();
    assert_projection(p, [3.0, -1.0], [0.1 / l, 0.3 / l], -l);
    assert_orthogonal(x, p);
    // Exactly on the convex corner: the normalized sum of the two normals.
    let s = [1.0 / SQRT2, 1.0 + 1.0 / SQRT2];
    let ls = s[0].hypot(s[1]);
    assert_projection(obstacle.project([2.0, 0.0]), [2.0, 0.0], [s[0] / ls, s[1] / ls], 0.0);
}

#[test]
fn polyline_beyond_the_ends_continues_the_end_segments() {
    let obstacle = profile();
    // Before the first point: the half-line y = 0, x < 0.
    assert_projection(obstacle.project([-3.0, 1.0]), [-3.0, 0.0], [0.0, 1.0], 1.0);
    assert_projection(obstacle.project([-3.0, -2.0]), [-3.0, 0.0], [0.0, 1.0], -2.0);
    // After the last point: the half-line from (5, −1) in direction (1, 1)/√2, left normal
    // (−1, 1)/√2. (7, 3): foot (8, 2), d = √2 (body side, above-left).
    let nu = [-1.0 / SQRT2, 1.0 / SQRT2];
    let x = [7.0, 3.0];
    let p = obstacle.project(x);
    assert_projection(p, [8.0, 2.0], nu, SQRT2);
    assert_orthogonal(x, p);
    // (8, 1): foot (7.5, 1.5), d = −1/√2 (inside the obstacle, below-right).
    assert_projection(obstacle.project([8.0, 1.0]), [7.5, 1.5], nu, -1.0 / SQRT2);
    // A single segment is an infinite line.
    let line = Obstacle::new_polyline(vec![[0.0, 0.0], [1.0, 0.0]]).unwrap();
    assert_projection(line.project([-5.0, 2.0]), [-5.0, 0.0], [0.0, 1.0], 2.0);
    assert_projection(line.project([7.0, -1.0]), [7.0, 0.0], [0.0, 1.0], -1.0);
}

#[test]
fn projections_are_orthogonal_everywhere() {
    let obstacles = [
        Obstacle::new_line([0.3, -0.2], [-1.0, 2.0]).unwrap(),
        Obstacle::new_circle([0.5, 0.5], 0.7).unwrap(),
        profile(),
    ];
    for obstacle in &obstacles {
        for i in 0..41 {
            for j in 0..41 {
                let x = [-2.0 + 0.25 * i as f64 + 0.013, -3.0 + 0.2 * j as f64 + 0.007];
                assert_orthogonal(x, obstacle.project(x));
            }
        }
    }
}

#[test]
fn degenerate_obstacles_are_usage_errors() {
    let m = usage_message(Obstacle::new_line([0.0, 0.0], [0.0, 0.0]).unwrap_err());
    assert!(m.contains("line obstacle") && m.contains("normal"), "{m}");
    let m = usage_message(Obstacle::new_line([f64::NAN, 0.0], [0.0, 1.0]).unwrap_err());
    assert!(m.contains("line obstacle") && m.contains("point"), "{m}");
    // A directly built line with a non-unit normal is caught by validate.
    let m = usage_message(Obstacle::Line { point: [0.0, 0.0], normal: [0.0, 2.0] }.validate().unwrap_err());
    assert!(m.contains("unit"), "{m}");

    for radius in [0.0, -1.0, f64::INFINITY] {
        let m = usage_message(Obstacle::new_circle([0.0, 0.0], radius).unwrap_err());
        assert!(m.contains("circle obstacle") && m.contains("radius"), "{m}");
    }

    let m = usage_message(Obstacle::new_polyline(vec![[0.0, 0.0]]).unwrap_err());
    assert!(m.contains("polyline obstacle") && m.contains("at least two points"), "{m}");
    let m = usage_message(Obstacle::new_polyline(vec![[0.0, 0.0], [1.0, f64::INFINITY]]).unwrap_err());
    assert!(m.contains("point 1"), "{m}");
    let m = usage_message(Obstacle::new_polyline(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [2.0, 1.0]]).unwrap_err());
    assert!(m.contains("segment 1") && m.contains("zero length"), "{m}");
    let m = usage_message(Obstacle::new_polyline(vec![[0.0, 0.0], [2.0, 0.0], [1.0, 0.0]]).unwrap_err());
    assert!(m.contains("turns back") && m.contains("point 1"), "{m}");
    // Finite segments crossing: segment 3 crosses segment 0 at (1, 0).
    let m = usage_message(
        Obstacle::new_polyline(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 2.0], [1.0, -1.0]]).unwrap_err(),
    );
    assert!(m.contains("segment 0") && m.contains("segment 3") && m.contains("intersect"), "{m}");
    // The last half-line (downwards from (−1, 0.5)) meets the first one (x < 0, y = 0) at (−1, 0).
    let m = usage_message(
        Obstacle::new_polyline(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [-1.0, 1.0], [-1.0, 0.5]]).unwrap_err(),
    );
    assert!(m.contains("half-line") && m.contains("intersect"), "{m}");
    // A cup (body inside) is fine: its end half-lines are parallel.
    Obstacle::new_polyline(vec![[-1.0, 1.0], [-1.0, 0.0], [1.0, 0.0], [1.0, 1.0]]).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Contact boundary on a structured rectangle [0, 2] × [0, 1], 4 × 2 cells (h = 0.5 along the
// bottom), against the line y = −0.1.

const LX: f64 = 2.0;
const NX: usize = 4;
const H: f64 = LX / NX as f64;

fn block(order: Order) -> Mesh {
    rectangle([0.0, 0.0], [LX, 1.0], NX, 2, order).unwrap()
}

fn floor() -> Obstacle {
    Obstacle::new_line([0.0, -0.1], [0.0, 1.0]).unwrap()
}

fn bottom(mesh: &Mesh) -> usize {
    mesh.require_group("bottom", 1).unwrap()
}

fn no_exclusion(_: usize) -> bool {
    false
}

/// Is `x` a grid vertex (a multiple of h) along the bottom?
fn is_vertex(x: f64) -> bool {
    let s = x / H;
    (s - s.round()).abs() < 1e-9
}

fn is_end(x: f64) -> bool {
    x.abs() < 1e-12 || (x - LX).abs() < 1e-12
}

#[test]
fn frame_gaps_and_weights_p1_and_p2() {
    for order in [Order::P1, Order::P2] {
        let mesh = block(order);
        let cb = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &no_exclusion).unwrap();
        let expected_points = if order == Order::P1 { NX + 1 } else { 2 * NX + 1 };
        assert_eq!(cb.points(), expected_points, "{order:?}");
        assert_eq!(cb.edges.len(), NX);
        assert!(cb.nodes.windows(2).all(|w| w[0] < w[1]), "nodes sorted");
        for (i, &k) in cb.nodes.iter().enumerate() {
            let x = mesh.nodes[k];
            assert_eq!(x[1], 0.0, "node {k} is on the bottom");
            assert_close(cb.gap[i], 0.1, 1e-15);
            assert_eq!(cb.normal[i], [0.0, -1.0]);
            // t = n rotated by +90°: along +x, the direction of the bottom edges.
            assert_eq!(cb.tangent[i], [1.0, 0.0]);
            let expected_weight = match (order, is_vertex(x[0]), is_end(x[0])) {
                (Order::P1, _, true) => H / 2.0,
                (Order::P1, _, false) => H,
                (Order::P2, true, true) => H / 6.0,
                (Order::P2, true, false) => H / 3.0,
                (Order::P2, false, _) => 2.0 * H / 3.0,
            };
            assert_close(cb.weight[i], expected_weight, 1e-14);
        }
        assert_close(cb.weight.iter().sum::<f64>(), LX, 1e-14);
        if order == Order::P2 {
            // Per edge: 1 : 4 : 1 (v0, v1, mid).
            for &e in &cb.edges {
                let w = |k: usize| cb.weight[cb.nodes.binary_search(&k).unwrap()];
                let ed = mesh.edge(e);
                let (w0, w1, wm) = (w(ed[0]), w(ed[1]), w(ed[2]));
                // A vertex shared by two edges carries 1/6 + 1/6 of the edge length.
                let share = |k: usize, wk: f64| if is_end(mesh.nodes[k][0]) { wk } else { wk / 2.0 };
                assert_close(wm / share(ed[0], w0), 4.0, 1e-13);
                assert_close(wm / share(ed[1], w1), 4.0, 1e-13);
            }
        }
        // Extra gap adds to every gap.
        let cb2 = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.05, &no_exclusion).unwrap();
        assert!(cb2.gap.iter().all(|&g| close(g, 0.15, 1e-15)));
        let cb3 = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), -0.3, &no_exclusion).unwrap();
        assert!(cb3.gap.iter().all(|&g| close(g, -0.2, 1e-15)));
    }
}

struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

#[test]
fn gather_and_scatter_add_are_adjoint() {
    // A circle under the block gives every contact point its own frame.
    let circle = Obstacle::new_circle([0.7, -3.0], 2.5).unwrap();
    let mut rng = Lcg(12345);
    for order in [Order::P1, Order::P2] {
        let mesh = block(order);
        let cb = ContactBoundary::new(&mesh, bottom(&mesh), &circle, 0.0, &no_exclusion).unwrap();
        let m = cb.points();
        // Frames: unit, orthogonal, right-handed, pointing from the node to the circle centre.
        for (i, &k) in cb.nodes.iter().enumerate() {
            let (n, t) = (cb.normal[i], cb.tangent[i]);
            let x = mesh.nodes[k];
            let to_centre = [0.7 - x[0], -3.0 - x[1]];
            let dist = to_centre[0].hypot(to_centre[1]);
            assert_close(n[0], to_centre[0] / dist, 1e-14);
            assert_close(n[1], to_centre[1] / dist, 1e-14);
            assert_close(cb.gap[i], dist - 2.5, 1e-14);
            assert_close(n[0] * n[0] + n[1] * n[1], 1.0, 1e-15);
            assert!(dot(&n, &t).abs() < 1e-15);
            assert_close(n[0] * t[1] - n[1] * t[0], 1.0, 1e-15);
        }
        for _ in 0..5 {
            let u: Vec<f64> = (0..2 * mesh.num_nodes()).map(|_| rng.next()).collect();
            let r: Vec<f64> = (0..2 * m).map(|_| rng.next()).collect();
            let bu = cb.gather(&u);
            assert_eq!(bu.len(), 2 * m);
            let mut btr = vec![0.0; u.len()];
            cb.scatter_add(&r, &mut btr);
            let (lhs, rhs) = (dot(&r, &bu), dot(&btr, &u));
            assert!((lhs - rhs).abs() <= 1e-13 * (lhs.abs() + 1.0), "rᵀBu = {lhs}, (Bᵀr)ᵀu = {rhs}");
            // scatter_add adds (does not overwrite), and touches only contact dofs.
            let mut twice = btr.clone();
            cb.scatter_add(&r, &mut twice);
            for (a, b) in twice.iter().zip(&btr) {
                assert_close(*a, 2.0 * b, 1e-15);
            }
            for k in 0..mesh.num_nodes() {
                if cb.nodes.binary_search(&k).is_err() {
                    assert_eq!([btr[2 * k], btr[2 * k + 1]], [0.0, 0.0]);
                }
            }
            // b_row is the same operator.
            for (j, &buj) in bu.iter().enumerate() {
                let row = cb.b_row(j);
                let value: f64 = row.iter().map(|&(dof, c)| c * u[dof]).sum();
                assert_eq!(value, buj, "row {j}");
                assert_eq!(row[1].0, row[0].0 + 1);
                assert_eq!(row[0].0, 2 * cb.nodes[j / 2]);
            }
        }
    }
}

/// Consistent nodal forces of a pressure field `p(x)` on the bottom (the FE load vector),
/// as contact forces of the boundary: `rN_i = n_i · F_i = −∫ p φ_i ds`.
fn contact_forces(mesh: &Mesh, cb: &ContactBoundary, p: &(dyn Fn(f64) -> f64 + Sync)) -> Vec<f64> {
    let field = |x: [f64; 2], n: [f64; 2]| [-p(x[0]) * n[0], -p(x[0]) * n[1]];
    let loads = Loads {
        body_force: None,
        edge_loads: vec![EdgeLoad { group: bottom(mesh), traction: Traction::Field(&field) }],
    };
    cb.gather(&load_vector(mesh, &loads))
}

#[test]
fn uniform_pressure_is_recovered_exactly_and_lumped_weights_would_checkerboard() {
    let p = 3.5;
    for order in [Order::P1, Order::P2] {
        let mesh = block(order);
        let cb = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &no_exclusion).unwrap();
        let loads = Loads {
            body_force: None,
            edge_loads: vec![EdgeLoad { group: bottom(&mesh), traction: Traction::Pressure(p) }],
        };
        let r = cb.gather(&load_vector(&mesh, &loads));
        for i in 0..cb.points() {
            assert!(r[2 * i] < 0.0, "compressive");
            assert!(r[2 * i + 1].abs() < 1e-14);
        }
        let (pressure, friction) = cb.tractions(&r);
        for i in 0..cb.points() {
            assert_close(pressure[i], p, 1e-13);
            assert!(friction[i].abs() < 1e-13);
        }
        let recovered = cb.recovered_pressure(&mesh, &r);
        for &q in &recovered {
            assert_close(q, p, 1e-12);
        }

        // Tributary ("lumped") lengths of the chain through all nodes: node spacing h/2 for P2.
        let spacing = if order == Order::P1 { H } else { H / 2.0 };
        let lumped = |x: f64| if is_end(x) { spacing / 2.0 } else { spacing };
        let naive: Vec<f64> = cb.nodes.iter().enumerate().map(|(i, &k)| -r[2 * i] / lumped(mesh.nodes[k][0])).collect();
        if order == Order::P1 {
            // For P1 the tributary lengths are the consistent weights: no oscillation.
            assert!(naive.iter().all(|&q| close(q, p, 1e-13)));
        } else {
            // The checkerboard: 2p/3 at every vertex, 4p/3 at every mid node.
            for (i, &k) in cb.nodes.iter().enumerate() {
                let expected = if is_vertex(mesh.nodes[k][0]) { 2.0 * p / 3.0 } else { 4.0 * p / 3.0 };
                assert_close(naive[i], expected, 1e-13);
            }
        }
    }
}

#[test]
fn recovered_pressure_is_exact_in_the_trace_space() {
    let quadratic = |x: f64| 1.0 + 0.5 * x - 0.3 * x * x;
    let linear = |x: f64| 2.0 - 0.6 * x;
    // P2: quadratic pressures are reproduced; division by the weights is not exact for them.
    let mesh = block(Order::P2);
    let cb = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &no_exclusion).unwrap();
    let r = contact_forces(&mesh, &cb, &quadratic);
    let recovered = cb.recovered_pressure(&mesh, &r);
    let (divided, _) = cb.tractions(&r);
    let mut division_error = 0.0f64;
    for (i, &k) in cb.nodes.iter().enumerate() {
        let exact = quadratic(mesh.nodes[k][0]);
        assert_close(recovered[i], exact, 1e-12);
        division_error = division_error.max((divided[i] - exact).abs());
    }
    assert!(division_error > 1e-3, "division by the weights is only exact for constants: {division_error}");
    // P1: linear pressures are reproduced.
    let mesh = block(Order::P1);
    let cb = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &no_exclusion).unwrap();
    let r = contact_forces(&mesh, &cb, &linear);
    for (i, &q) in cb.recovered_pressure(&mesh, &r).iter().enumerate() {
        assert_close(q, linear(mesh.nodes[cb.nodes[i]][0]), 1e-12);
    }
    // ... but not quadratic ones (the test can fail).
    let r = contact_forces(&mesh, &cb, &quadratic);
    let worst = cb
        .recovered_pressure(&mesh, &r)
        .iter()
        .enumerate()
        .map(|(i, q)| (q - quadratic(mesh.nodes[cb.nodes[i]][0])).abs())
        .fold(0.0, f64::max);
    assert!(worst > 1e-4, "{worst}");
}

#[test]
fn recovered_pressure_on_an_unstructured_p2_part() {
    // Unequal edge lengths along the bottom (Gmsh): the mass-matrix recovery stays exact.
    let mesh = generate(&MeshRequest {
        shape: Shape::Rectangle { origin: [0.0, 0.0], size: [2.0, 1.0] },
        cell_size: 0.3,
        refinement: Some(Refinement { point: [0.6, 0.0], cell_size: 0.08, radius: 0.3 }),
        order: Order::P2,
    })
    .unwrap();
    let cb = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &no_exclusion).unwrap();
    let lengths: Vec<f64> = cb.edges.iter().map(|&e| mesh.edge_normal(e).1).collect();
    let (lmin, lmax) = lengths.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &l| (a.min(l), b.max(l)));
    assert!(lmax - lmin > 1e-6, "want unequal edges: {lmin} .. {lmax}");
    assert_close(cb.weight.iter().sum::<f64>(), 2.0, 1e-13);
    let quadratic = |x: f64| 0.2 + x * (2.0 - x);
    let r = contact_forces(&mesh, &cb, &quadratic);
    for (i, &q) in cb.recovered_pressure(&mesh, &r).iter().enumerate() {
        assert_close(q, quadratic(mesh.nodes[cb.nodes[i]][0]), 1e-11);
    }
    let (pressure, _) = cb.tractions(&contact_forces(&mesh, &cb, &|_| 0.7));
    assert!(pressure.iter().all(|&q| close(q, 0.7, 1e-13)));
}

#[test]
fn excluded_nodes_are_dropped() {
    for order in [Order::P1, Order::P2] {
        let mesh = block(order);
        let full = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &no_exclusion).unwrap();
        // Exclude the two corners of the bottom (as if fixed by Dirichlet conditions).
        let corner = |k: usize| mesh.nodes[k][1] == 0.0 && is_end(mesh.nodes[k][0]);
        let cb = ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &corner).unwrap();
        assert_eq!(cb.points(), full.points() - 2);
        assert!(cb.nodes.iter().all(|&k| !corner(k)));
        assert_eq!(cb.edges, full.edges);
        for (i, &k) in cb.nodes.iter().enumerate() {
            let j = full.nodes.binary_search(&k).unwrap();
            assert_eq!(cb.weight[i], full.weight[j]);
            assert_eq!(cb.gap[i], full.gap[j]);
        }
        // Everything excluded: an error naming the part.
        let m = usage_message(ContactBoundary::new(&mesh, bottom(&mesh), &floor(), 0.0, &|_| true).unwrap_err());
        assert!(m.contains("'bottom'") && m.contains("excluded"), "{m}");
    }
}

#[test]
fn bad_parts_and_arguments_are_errors_naming_the_part() {
    let mesh = block(Order::P1);
    let domain = mesh.require_group("domain", 2).unwrap();
    let m = usage_message(ContactBoundary::new(&mesh, domain, &floor(), 0.0, &no_exclusion).unwrap_err());
    assert!(m.contains("'domain'") && m.contains("region"), "{m}");
    let m = usage_message(ContactBoundary::new(&mesh, 99, &floor(), 0.0, &no_exclusion).unwrap_err());
    assert!(m.contains("99"), "{m}");
    let bad = Obstacle::Circle { center: [0.0, -1.0], radius: -1.0 };
    let m = usage_message(ContactBoundary::new(&mesh, bottom(&mesh), &bad, 0.0, &no_exclusion).unwrap_err());
    assert!(m.contains("'bottom'") && m.contains("radius"), "{m}");
    let m = usage_message(ContactBoundary::new(&mesh, bottom(&mesh), &floor(), f64::NAN, &no_exclusion).unwrap_err());
    assert!(m.contains("'bottom'") && m.contains("extra gap"), "{m}");
    // A group without edges.
    let mut empty = mesh.clone();
    let top = empty.require_group("top", 1).unwrap();
    for g in empty.edge_group.iter_mut() {
        if *g == top {
            *g = bottom(&mesh);
        }
    }
    match ContactBoundary::new(&empty, top, &floor(), 0.0, &no_exclusion).unwrap_err() {
        Error::Mesh { entity, message, .. } => {
            assert!(entity.contains("'top'") && message.contains("no boundary edges"), "{entity}: {message}")
        }
        other => panic!("expected Error::Mesh, got {other:?}"),
    }
}

#[test]
fn curved_p2_half_disc_on_a_line() {
    let (c, radius) = ([0.0, 1.0], 1.0);
    let mesh = generate(&MeshRequest {
        shape: Shape::HalfDisc { center: c, radius },
        cell_size: 0.2,
        refinement: None,
        order: Order::P2,
    })
    .unwrap();
    let arc = mesh.require_group("arc", 1).unwrap();
    let ymin = mesh.nodes.iter().map(|x| x[1]).fold(f64::INFINITY, f64::min);
    let floor = Obstacle::new_line([0.0, ymin], [0.0, 1.0]).unwrap();
    let cb = ContactBoundary::new(&mesh, arc, &floor, 0.0, &no_exclusion).unwrap();
    // Every node of the arc's edges, mid nodes included.
    let mut arc_nodes: Vec<usize> = cb.edges.iter().flat_map(|&e| mesh.edge(e).to_vec()).collect();
    arc_nodes.sort_unstable();
    arc_nodes.dedup();
    assert_eq!(cb.nodes, arc_nodes);
    assert_eq!(cb.points(), 2 * cb.edges.len() + 1, "an open chain of P2 edges");
    assert!(cb.gap.iter().all(|&g| g >= 0.0));
    let lowest =
        (0..cb.points()).min_by(|&a, &b| mesh.nodes[cb.nodes[a]][1].total_cmp(&mesh.nodes[cb.nodes[b]][1])).unwrap();
    assert_eq!(cb.gap[lowest], 0.0);
    assert_eq!(mesh.nodes[cb.nodes[lowest]], [c[0], c[1] - radius], "the bottom of the arc is a node");
    for (i, &k) in cb.nodes.iter().enumerate() {
        assert_eq!(cb.gap[i], mesh.nodes[k][1] - ymin);
        assert_eq!(cb.normal[i], [0.0, -1.0]);
        assert_eq!(cb.tangent[i], [1.0, 0.0]);
        assert!(cb.weight[i] > 0.0);
    }
    // The weights add up to the length of the isoparametric arc: π R to O(h⁴).
    let total: f64 = cb.weight.iter().sum();
    assert!((total - std::f64::consts::PI * radius).abs() < 1e-4, "{total}");
    // The weights are the row sums of the (curved) boundary mass matrix, so the forces
    // rN_i = −p w_i of a uniform pressure are recovered as exactly p at every node.
    let r: Vec<f64> = cb.weight.iter().flat_map(|&w| [-2.0 * w, 0.0]).collect();
    for q in cb.recovered_pressure(&mesh, &r) {
        assert_close(q, 2.0, 1e-12);
    }
}
