//! Tests of the plane-elasticity finite elements (no PETSc: systems are solved densely with
//! nalgebra).
#![allow(clippy::needless_range_loop)]
use std::collections::{HashMap, HashSet};
use std::f64::consts::PI;

use nalgebra::{DMatrix, DVector};
use signorini::error::Error;
use signorini::fem::lagrange;
use signorini::fem::quadrature;
use signorini::fem::{
    assemble, cell_stress, element_stiffness, energy_error, energy_norm, l2_error, load_vector, nodal_stress,
    residual_forces, Constraints, EdgeLoad, LinearSystem, Loads, Material, PlaneModel, Traction,
};
use signorini::mesh::{Mesh, Order, PhysicalGroup};

// ---------------------------------------------------------------------------------------------
// A private structured mesh generator of the unit square.
// ---------------------------------------------------------------------------------------------

const BOTTOM: usize = 0;
const RIGHT: usize = 1;
const TOP: usize = 2;
const LEFT: usize = 3;

/// Deterministic pseudo-random numbers in [−1, 1] (xorshift64*).
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (v >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

#[derive(Clone, Copy)]
enum Distortion {
    None,
    /// Interior vertices moved by up to this fraction of h, at random.
    Random(f64),
    /// Interior vertices moved by the smooth map x + a sin(2πx) sin(2πy) (a nested-like family).
    Smooth(f64),
}

#[derive(Clone, Copy)]
struct Grid {
    n: usize,
    order: Order,
    distortion: Distortion,
    /// P2: interior mid nodes moved off the chord by up to this fraction of h (curved cells).
    curve_interior: f64,
    /// P2: mid nodes of the right and top sides moved by up to this fraction of h (curved
    /// boundary).
    curve_boundary: f64,
}

impl Grid {
    fn new(n: usize, order: Order) -> Self {
        Grid { n, order, distortion: Distortion::None, curve_interior: 0.0, curve_boundary: 0.0 }
    }
    fn distorted(mut self, d: Distortion) -> Self {
        self.distortion = d;
        self
    }
    fn curved(mut self, interior: f64, boundary: f64) -> Self {
        self.curve_interior = interior;
        self.curve_boundary = boundary;
        self
    }

    /// Triangles of the unit square (n × n squares, alternating diagonals), CCW; boundary edges
    /// with the domain on their left in groups bottom, right, top, left; region "domain".
    fn build(&self) -> Mesh {
        let n = self.n;
        let h = 1.0 / n as f64;
        let mut rng = Random(0x9e37_79b9_7f4a_7c15 ^ (n as u64 * 7919));
        let vid = |i: usize, j: usize| j * (n + 1) + i;
        let mut nodes = Vec::new();
        for j in 0..=n {
            for i in 0..=n {
                let (mut x, mut y) = (i as f64 * h, j as f64 * h);
                let interior = i > 0 && i < n && j > 0 && j < n;
                match self.distortion {
                    Distortion::None => {}
                    Distortion::Random(a) if interior => {
                        x += a * h * rng.next();
                        y += a * h * rng.next();
                    }
                    Distortion::Smooth(a) if interior => {
                        let (x0, y0) = (x, y);
                        x = x0 + a * (2.0 * PI * x0).sin() * (2.0 * PI * y0).sin();
                        y = y0 + a * (2.0 * PI * (x0 + 0.25)).sin() * (PI * y0).sin() * (PI * x0).sin();
                    }
                    _ => {}
                }
                nodes.push([x, y]);
            }
        }
        let mut tris = Vec::new();
        for j in 0..n {
            for i in 0..n {
                let (a, b, c, d) = (vid(i, j), vid(i + 1, j), vid(i + 1, j + 1), vid(i, j + 1));
                if (i + j) % 2 == 0 {
                    tris.push([a, b, c]);
                    tris.push([a, c, d]);
                } else {
                    tris.push([a, b, d]);
                    tris.push([b, c, d]);
                }
            }
        }
        // Boundary edges (v0, v1), domain on the left.
        let mut sides: Vec<(usize, [usize; 2])> = Vec::new();
        for i in 0..n {
            sides.push((BOTTOM, [vid(i, 0), vid(i + 1, 0)]));
        }
        for j in 0..n {
            sides.push((RIGHT, [vid(n, j), vid(n, j + 1)]));
        }
        for i in (0..n).rev() {
            sides.push((TOP, [vid(i + 1, n), vid(i, n)]));
        }
        for j in (0..n).rev() {
            sides.push((LEFT, [vid(0, j + 1), vid(0, j)]));
        }
        let key = |a: usize, b: usize| (a.min(b), a.max(b));
        let side_of: HashMap<(usize, usize), usize> = sides.iter().map(|&(g, [a, b])| (key(a, b), g)).collect();

        let mut cells = Vec::new();
        let mut mids: HashMap<(usize, usize), usize> = HashMap::new();
        for t in &tris {
            cells.extend_from_slice(t);
            if self.order == Order::P2 {
                for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                    let id = *mids.entry(key(a, b)).or_insert_with(|| {
                        let (pa, pb) = (nodes[a], nodes[b]);
                        let mut m = [0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])];
                        let amount = match side_of.get(&key(a, b)) {
                            None => self.curve_interior,
                            Some(&RIGHT) | Some(&TOP) => self.curve_boundary,
                            Some(_) => 0.0,
                        };
                        if amount != 0.0 {
                            let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
                            let len = dx.hypot(dy);
                            let s = amount * h * rng.next();
                            m[0] += s * dy / len;
                            m[1] -= s * dx / len;
                        }
                        nodes.push(m);
                        nodes.len() - 1
                    });
                    cells.push(id);
                }
            }
        }
        let mut edges = Vec::new();
        let mut edge_group = Vec::new();
        for &(g, [a, b]) in &sides {
            edges.extend_from_slice(&[a, b]);
            if self.order == Order::P2 {
                edges.push(mids[&key(a, b)]);
            }
            edge_group.push(g);
        }
        let num_cells = tris.len();
        let groups = ["bottom", "right", "top", "left"]
            .iter()
            .enumerate()
            .map(|(k, name)| PhysicalGroup { name: name.to_string(), tag: k as i32 + 1, dim: 1 })
            .chain(std::iter::once(PhysicalGroup { name: "domain".into(), tag: 5, dim: 2 }))
            .collect();
        let mesh = Mesh { order: self.order, nodes, cells, cell_group: vec![4; num_cells], edges, edge_group, groups };
        assert_positive_jacobians(&mesh);
        mesh
    }
}

/// Every cell's map has det J > 0 at the degree-5 quadrature points and at its nodes.
fn assert_positive_jacobians(mesh: &Mesh) {
    let rule = quadrature::triangle(5);
    let npc = mesh.order.nodes_per_cell();
    for c in 0..mesh.num_cells() {
        let x: Vec<[f64; 2]> = mesh.cell(c).iter().map(|&k| mesh.nodes[k]).collect();
        for &xi in rule.points.iter().chain(lagrange::reference_nodes(mesh.order)) {
            let p = lagrange::map_cell_point(mesh.order, &x[..npc], xi);
            assert!(
                p.det > 0.0,
                "test mesh ({:?}, {} cells): cell {c} is inverted at {xi:?}",
                mesh.order,
                mesh.num_cells()
            );
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Helpers.
// ---------------------------------------------------------------------------------------------

fn steel(plane: PlaneModel) -> Material {
    Material { young: 200.0e9, poisson: 0.3, plane }
}

fn to_dense(system: &LinearSystem) -> DMatrix<f64> {
    let m = &system.matrix;
    let mut a = DMatrix::zeros(m.num_rows(), m.num_cols);
    for r in 0..m.num_rows() {
        for k in m.indptr[r]..m.indptr[r + 1] {
            a[(r, m.indices[k])] += m.values[k];
        }
    }
    a
}

/// Solve a full (all rows) system by dense Cholesky.
fn solve(system: &LinearSystem) -> Vec<f64> {
    assert_eq!(system.matrix.first_row, 0);
    assert_eq!(system.matrix.num_rows(), system.matrix.num_cols);
    let a = to_dense(system);
    let chol = a.cholesky().expect("the constrained stiffness matrix must be SPD");
    chol.solve(&DVector::from_column_slice(&system.rhs)).as_slice().to_vec()
}

/// Solve a full system by banded Cholesky, with the dofs ordered by node position (x, then y)
/// so the half-bandwidth stays a few node columns: fast enough for the convergence studies at
/// the test profile's optimisation level.
fn solve_banded(mesh: &Mesh, system: &LinearSystem) -> Vec<f64> {
    let a = &system.matrix;
    let n = a.num_rows();
    assert_eq!((a.first_row, a.num_cols), (0, n));
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| {
        let (p, q) = (mesh.nodes[i / 2], mesh.nodes[j / 2]);
        p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1])).then(i.cmp(&j))
    });
    let mut position = vec![0; n];
    for (k, &d) in order.iter().enumerate() {
        position[d] = k;
    }
    let mut b = 0;
    for i in 0..n {
        for &j in a.row(i).0 {
            b = b.max(position[i].abs_diff(position[j]));
        }
    }
    // Lower band, row-major: entry (i, j), i − b ≤ j ≤ i, at i (b + 1) + j + b − i.
    let w = b + 1;
    let at = |i: usize, j: usize| i * w + j + b - i;
    let mut l = vec![0.0; n * w];
    for i in 0..n {
        let (cols, vals) = a.row(i);
        for (&j, &v) in cols.iter().zip(vals) {
            let (pi, pj) = (position[i], position[j]);
            if pj <= pi {
                l[at(pi, pj)] += v;
            }
        }
    }
    for i in 0..n {
        let lo_i = i.saturating_sub(b);
        for j in lo_i..=i {
            let lo = lo_i.max(j.saturating_sub(b));
            let mut s = l[at(i, j)];
            for k in lo..j {
                s -= l[at(i, k)] * l[at(j, k)];
            }
            l[at(i, j)] = if i == j {
                assert!(s > 0.0, "banded Cholesky: matrix not positive definite at {i}");
                s.sqrt()
            } else {
                s / l[at(j, j)]
            };
        }
    }
    let mut y: Vec<f64> = (0..n).map(|k| system.rhs[order[k]]).collect();
    for i in 0..n {
        for k in i.saturating_sub(b)..i {
            y[i] -= l[at(i, k)] * y[k];
        }
        y[i] /= l[at(i, i)];
    }
    for i in (0..n).rev() {
        for k in i + 1..(i + b + 1).min(n) {
            y[i] -= l[at(k, i)] * y[k];
        }
        y[i] /= l[at(i, i)];
    }
    let mut u = vec![0.0; n];
    for k in 0..n {
        u[order[k]] = y[k];
    }
    u
}

fn all_dofs(mesh: &Mesh) -> std::ops::Range<usize> {
    0..2 * mesh.num_nodes()
}

/// Fix both components of the nodes of `groups` to the exact displacement.
fn dirichlet(mesh: &Mesh, groups: &[usize], exact: &dyn Fn([f64; 2]) -> [f64; 2]) -> Constraints {
    let mut c = Constraints::new(2 * mesh.num_nodes());
    for &g in groups {
        c.fix_group(mesh, g, 0, |x| exact(x)[0]);
        c.fix_group(mesh, g, 1, |x| exact(x)[1]);
    }
    c
}

/// max_i |u_h(x_i) − u(x_i)| / max_i |u(x_i)| over all nodes.
fn nodal_error(mesh: &Mesh, u: &[f64], exact: &dyn Fn([f64; 2]) -> [f64; 2]) -> f64 {
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for (n, &x) in mesh.nodes.iter().enumerate() {
        let e = exact(x);
        for c in 0..2 {
            err = err.max((u[2 * n + c] - e[c]).abs());
            size = size.max(e[c].abs());
        }
    }
    err / size
}

fn monomial_integral(a: u32, b: u32) -> f64 {
    let fact = |k: u32| (1..=k).map(|i| i as f64).product::<f64>();
    fact(a) * fact(b) / fact(a + b + 2)
}

// ---------------------------------------------------------------------------------------------
// Quadrature.
// ---------------------------------------------------------------------------------------------

#[test]
fn triangle_rules_integrate_monomials_exactly() {
    for degree in 0..=10 {
        let rule = quadrature::triangle(degree);
        assert!(rule.degree >= degree, "rule for degree {degree} claims only {}", rule.degree);
        assert!(rule.weights.iter().all(|&w| w > 0.0), "degree {degree}: a weight is not positive");
        assert!(
            rule.points.iter().all(|p| p[0] >= 0.0 && p[1] >= 0.0 && p[0] + p[1] <= 1.0),
            "degree {degree}: a point lies outside the reference triangle"
        );
        for total in 0..=rule.degree as u32 {
            for a in 0..=total {
                let b = total - a;
                let q: f64 = rule
                    .points
                    .iter()
                    .zip(&rule.weights)
                    .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32))
                    .sum();
                let exact = monomial_integral(a, b);
                assert!((q - exact).abs() <= 1e-14 * exact, "degree {degree} rule: x^{a} y^{b}: {q} vs {exact}");
            }
        }
    }
    // The tabled rules are not exact one degree higher (so the test above can fail).
    for (degree, points) in [(1, 1), (2, 3), (4, 6), (5, 7)] {
        let rule = quadrature::triangle(degree);
        assert_eq!(rule.len(), points);
        let d = rule.degree as u32 + 1;
        let worst = (0..=d)
            .map(|a| {
                let q: f64 = rule
                    .points
                    .iter()
                    .zip(&rule.weights)
                    .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi((d - a) as i32))
                    .sum();
                (q - monomial_integral(a, d - a)).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst > 1e-6, "degree {degree} rule is unexpectedly exact for degree {d}");
    }
}

#[test]
fn gauss_legendre_integrates_monomials_exactly() {
    for n in 1..=8 {
        let rule = quadrature::gauss_legendre(n);
        assert_eq!(rule.len(), n);
        assert_eq!(rule.degree, 2 * n - 1);
        assert!(rule.weights.iter().all(|&w| w > 0.0));
        assert!(rule.points.windows(2).all(|p| p[0] < p[1]));
        for k in 0..=2 * n as i32 {
            let q: f64 = rule.points.iter().zip(&rule.weights).map(|(x, w)| w * x.powi(k)).sum();
            let exact = 1.0 / (k as f64 + 1.0);
            if k < 2 * n as i32 {
                assert!((q - exact).abs() <= 1e-15, "{n} points, x^{k}: {q} vs {exact}");
            } else {
                assert!((q - exact).abs() > 1e-12, "{n} points exact for x^{k}?");
            }
        }
    }
    // Known values: 2 points at 1/2 ± 1/(2√3).
    let r = quadrature::gauss_legendre(2);
    assert!((r.points[0] - (0.5 - 0.5 / 3f64.sqrt())).abs() < 1e-16);
    assert_eq!(quadrature::line(5).len(), 3);
}

// ---------------------------------------------------------------------------------------------
// Lagrange elements and the isoparametric map.
// ---------------------------------------------------------------------------------------------

#[test]
fn shape_functions_are_nodal_and_complete() {
    for order in [Order::P1, Order::P2] {
        let n = order.nodes_per_cell();
        let nodes = lagrange::reference_nodes(order);
        for (i, &xi) in nodes.iter().enumerate() {
            let v = lagrange::shape_values(order, xi);
            for j in 0..n {
                assert!((v[j] - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15, "{order:?}: N{j} at node {i}");
            }
        }
        let mut rng = Random(42);
        for _ in 0..20 {
            let (a, b) = (0.5 * (rng.next() + 1.0), 0.5 * (rng.next() + 1.0));
            let xi = if a + b <= 1.0 { [a, b] } else { [1.0 - a, 1.0 - b] };
            let v = lagrange::shape_values(order, xi);
            let g = lagrange::shape_gradients(order, xi);
            assert!((v[..n].iter().sum::<f64>() - 1.0).abs() < 1e-15);
            // Reproduce ξ, η (and ξη, ξ² for P2) and compare gradients with finite differences.
            let fns: Vec<Box<dyn Fn([f64; 2]) -> f64>> = match order {
                Order::P1 => vec![Box::new(|p: [f64; 2]| p[0]), Box::new(|p: [f64; 2]| 2.0 * p[1] - p[0] + 1.0)],
                Order::P2 => vec![
                    Box::new(|p: [f64; 2]| p[0] * p[1]),
                    Box::new(|p: [f64; 2]| p[0] * p[0] - 3.0 * p[1] * p[1] + p[1]),
                ],
            };
            for f in &fns {
                let interp: f64 = (0..n).map(|k| v[k] * f(nodes[k])).sum();
                assert!((interp - f(xi)).abs() < 1e-14);
            }
            for k in 0..n {
                let eps = 1e-6;
                for d in 0..2 {
                    let (mut p, mut m) = (xi, xi);
                    p[d] += eps;
                    m[d] -= eps;
                    let fd = (lagrange::shape_values(order, p)[k] - lagrange::shape_values(order, m)[k]) / (2.0 * eps);
                    assert!((fd - g[k][d]).abs() < 1e-8, "{order:?}: dN{k}/dξ{d}: {fd} vs {}", g[k][d]);
                }
            }
        }
    }
}

/// A P2 triangle with vertices (0,0), (2,0), (0,1) whose edge 0-1 bulges outward by `delta`.
fn curved_p2_triangle(delta: f64) -> Vec<[f64; 2]> {
    vec![[0.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, -delta], [1.0, 0.5], [0.0, 0.5]]
}

#[test]
fn isoparametric_map_of_a_curved_triangle() {
    let delta = 0.2;
    let x = curved_p2_triangle(delta);
    assert!(!lagrange::is_affine(&x));
    assert!(lagrange::is_affine(&curved_p2_triangle(0.0)));
    // Area: straight triangle + parabolic segment (2/3 · chord · sagitta); det J is quadratic.
    let rule = quadrature::triangle(2);
    let area: f64 =
        rule.points.iter().zip(&rule.weights).map(|(&p, w)| w * lagrange::map_cell_point(Order::P2, &x, p).det).sum();
    let exact = 1.0 + 2.0 / 3.0 * 2.0 * delta;
    assert!((area - exact).abs() < 1e-14, "area {area} vs {exact}");
    // The physical gradients of the coordinate functions are exact: Σ x_k ∇N_k = (1, 0).
    let mut rng = Random(7);
    for _ in 0..10 {
        let (a, b) = (0.5 * (rng.next() + 1.0), 0.5 * (rng.next() + 1.0));
        let xi = if a + b <= 1.0 { [a, b] } else { [1.0 - a, 1.0 - b] };
        let p = lagrange::map_cell_point(Order::P2, &x, xi);
        let mut gx = [0.0; 2];
        let mut gy = [0.0; 2];
        for k in 0..6 {
            for d in 0..2 {
                gx[d] += x[k][0] * p.gradients[k][d];
                gy[d] += x[k][1] * p.gradients[k][d];
            }
        }
        assert!(
            (gx[0] - 1.0).abs() < 1e-14 && gx[1].abs() < 1e-14 && gy[0].abs() < 1e-14 && (gy[1] - 1.0).abs() < 1e-14
        );
        let v = lagrange::shape_values(Order::P2, xi);
        assert_eq!(p.x, lagrange::map_point(&x, &v[..6]));
    }
}

#[test]
fn edge_maps_integrate_curved_edges() {
    // Parabolic edge from (0,0) to (L,0) through (L/2, −δ): ∫ n ds = (Δy, −Δx) exactly, and the
    // length has a closed form.
    let (l, delta) = (2.0, 0.3);
    let edge = [[0.0, 0.0], [l, 0.0], [0.5 * l, -delta]];
    let rule = quadrature::gauss_legendre(3);
    let mut n_ds = [0.0; 2];
    for (&t, &w) in rule.points.iter().zip(&rule.weights) {
        let p = lagrange::map_edge_point(&edge, t);
        n_ds[0] += w * p.length_element * p.normal[0];
        n_ds[1] += w * p.length_element * p.normal[1];
    }
    assert!(n_ds[0].abs() < 1e-15 && (n_ds[1] + l).abs() < 1e-15, "∫ n ds = {n_ds:?}");
    let k = 4.0 * delta;
    let exact_length = 0.5 * ((l * l + k * k).sqrt() + l * l / k * (k / l).asinh());
    let fine = quadrature::gauss_legendre(30);
    let length: f64 = fine
        .points
        .iter()
        .zip(&fine.weights)
        .map(|(&t, &w)| w * lagrange::map_edge_point(&edge, t).length_element)
        .sum();
    assert!((length - exact_length).abs() < 1e-13, "{length} vs {exact_length}");
    // Outward normal at the middle of the bulge points down (domain on the left of 0 -> 1).
    let mid = lagrange::map_edge_point(&edge, 0.5);
    assert!((mid.normal[0]).abs() < 1e-15 && (mid.normal[1] + 1.0).abs() < 1e-15);
    assert_eq!(mid.x, [0.5 * l, -delta]);
    // Straight 2-node edge.
    let p = lagrange::map_edge_point(&[[1.0, 1.0], [1.0, 3.0]], 0.25);
    assert_eq!(p.x, [1.0, 1.5]);
    assert_eq!(p.length_element, 2.0);
    assert_eq!(p.normal, [1.0, 0.0]);
}

// ---------------------------------------------------------------------------------------------
// Material.
// ---------------------------------------------------------------------------------------------

#[test]
fn hooke_law_plane_strain_and_plane_stress() {
    let (e, nu) = (210.0e9, 0.3);
    let strain = Material::new(e, nu, PlaneModel::Strain);
    let stress = Material::new(e, nu, PlaneModel::Stress);
    let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let cs = strain.elasticity();
    let expect = [[f * (1.0 - nu), f * nu, 0.0], [f * nu, f * (1.0 - nu), 0.0], [0.0, 0.0, f * (1.0 - 2.0 * nu) / 2.0]];
    let g = e / (1.0 - nu * nu);
    let cp = stress.elasticity();
    let expect_p = [[g, g * nu, 0.0], [g * nu, g, 0.0], [0.0, 0.0, g * (1.0 - nu) / 2.0]];
    for i in 0..3 {
        for j in 0..3 {
            assert!((cs[i][j] - expect[i][j]).abs() <= 1e-15 * f);
            assert!((cp[i][j] - expect_p[i][j]).abs() <= 1e-15 * g);
        }
    }
    for m in [strain, stress] {
        let (c, s) = (m.elasticity(), m.compliance());
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| c[i][k] * s[k][j]).sum();
                assert!((p - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14, "C C^-1 != I for {:?}", m.plane);
            }
        }
        // w*(C e) = w(e) = ½ e·C e.
        let eps = [1e-3, -4e-4, 6e-4];
        let sig = m.stress(eps);
        let w = m.strain_energy_density(eps);
        assert!((m.complementary_energy_density(sig) - w).abs() < 1e-12 * w);
        let half_s_cinv_s: f64 =
            0.5 * (0..3).map(|i| (0..3).map(|j| sig[i] * s[i][j] * sig[j]).sum::<f64>()).sum::<f64>();
        assert!((m.complementary_energy_density(sig) - half_s_cinv_s).abs() < 1e-12 * w);
    }
    // σzz and von Mises.
    let s = [100.0, 40.0, 30.0];
    assert!((strain.sigma_zz(s) - 42.0).abs() < 1e-12);
    assert_eq!(stress.sigma_zz(s), 0.0);
    assert!((stress.von_mises([100.0, 0.0, 0.0]) - 100.0).abs() < 1e-12);
    assert!((stress.von_mises([0.0, 0.0, 50.0]) - 50.0 * 3f64.sqrt()).abs() < 1e-12);
    // Plane strain, equibiaxial: σzz = 2νσ, σ_vm = |σ − σzz|.
    assert!((strain.von_mises([10.0, 10.0, 0.0]) - 10.0 * (1.0 - 2.0 * nu)).abs() < 1e-12);
    let szz = strain.sigma_zz(s);
    let vm = (0.5 * ((s[0] - s[1]).powi(2) + (s[1] - szz).powi(2) + (szz - s[0]).powi(2)) + 3.0 * s[2] * s[2]).sqrt();
    assert!((strain.von_mises(s) - vm).abs() < 1e-12);
    // Complementary energy ½ σ : C⁻¹ σ, written out.
    let ws = (1.0 + nu) / (2.0 * e)
        * ((1.0 - nu) * (s[0] * s[0] + s[1] * s[1]) - 2.0 * nu * s[0] * s[1] + 2.0 * s[2] * s[2]);
    assert!((strain.complementary_energy_density(s) - ws).abs() < 1e-14 * ws);
    let wp = (s[0] * s[0] + s[1] * s[1] - 2.0 * nu * s[0] * s[1] + 2.0 * (1.0 + nu) * s[2] * s[2]) / (2.0 * e);
    assert!((stress.complementary_energy_density(s) - wp).abs() < 1e-14 * wp);
}

#[test]
fn material_check_rejects_bad_constants() {
    assert!(steel(PlaneModel::Strain).check().is_ok());
    assert!(Material::new(1.0, -0.99, PlaneModel::Stress).check().is_ok());
    for (e, nu, word) in [
        (0.0, 0.3, "Young"),
        (-1.0, 0.3, "Young"),
        (f64::NAN, 0.3, "Young"),
        (f64::INFINITY, 0.3, "Young"),
        (1.0, 0.5, "Poisson"),
        (1.0, -1.0, "Poisson"),
        (1.0, f64::NAN, "Poisson"),
    ] {
        let err = Material::new(e, nu, PlaneModel::Strain).check().expect_err("must be rejected");
        assert!(err.contains(word), "message for E={e}, nu={nu} should mention {word}: {err}");
    }
}

// ---------------------------------------------------------------------------------------------
// Element stiffness.
// ---------------------------------------------------------------------------------------------

fn check_element_stiffness(order: Order, x: &[[f64; 2]], what: &str) {
    let m = steel(PlaneModel::Strain);
    let n = 2 * order.nodes_per_cell();
    let k = DMatrix::from_row_slice(n, n, &element_stiffness(order, x, &m));
    let scale = k.amax();
    assert!((&k - k.transpose()).amax() <= 1e-14 * scale, "{what}: not symmetric");
    let mut eig: Vec<f64> = k.clone().symmetric_eigen().eigenvalues.iter().copied().collect();
    eig.sort_by(f64::total_cmp);
    let zero = 1e-10 * eig[n - 1];
    assert!(eig[0] > -zero, "{what}: negative eigenvalue {}", eig[0]);
    assert!(eig[..3].iter().all(|l| l.abs() < zero), "{what}: eigenvalues {eig:?}");
    assert!(eig[3] > 1e-4 * eig[n - 1], "{what}: more than 3 zero-energy modes: {eig:?}");
    // The rigid motions are in the kernel.
    for r in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
        let v = DVector::from_iterator(n, x.iter().flat_map(|p| [r[0] - r[2] * p[1], r[1] + r[2] * p[0]]));
        assert!((&k * v).amax() < 1e-12 * scale, "{what}: rigid motion {r:?} has energy");
    }
}

#[test]
fn element_stiffness_is_symmetric_psd_with_three_rigid_modes() {
    check_element_stiffness(Order::P1, &[[0.1, 0.0], [1.3, 0.2], [0.4, 0.9]], "P1");
    let v = [[0.1, 0.0], [1.3, 0.2], [0.4, 0.9]];
    let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let straight = [v[0], v[1], v[2], mid(v[0], v[1]), mid(v[1], v[2]), mid(v[2], v[0])];
    check_element_stiffness(Order::P2, &straight, "P2 straight");
    check_element_stiffness(Order::P2, &curved_p2_triangle(0.25), "P2 curved");
    // P1 against the closed form for the unit right triangle in plane stress, E = 1, ν = 0:
    // K = ½ [B^T C B] with C = diag(1, 1, ½).
    let m = Material::new(1.0, 0.0, PlaneModel::Stress);
    let k = element_stiffness(Order::P1, &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &m);
    #[rustfmt::skip]
    let expect = [
        0.75, 0.25, -0.5, -0.25, -0.25, 0.0,
        0.25, 0.75, 0.0, -0.25, -0.25, -0.5,
        -0.5, 0.0, 0.5, 0.0, 0.0, 0.0,
        -0.25, -0.25, 0.0, 0.25, 0.25, 0.0,
        -0.25, -0.25, 0.0, 0.25, 0.25, 0.0,
        0.0, -0.5, 0.0, 0.0, 0.0, 0.5,
    ];
    for i in 0..36 {
        assert!((k[i] - expect[i]).abs() < 1e-15, "entry {i}: {} vs {}", k[i], expect[i]);
    }
}

// ---------------------------------------------------------------------------------------------
// Constraints and the rigid-motion check.
// ---------------------------------------------------------------------------------------------

fn unconstrained_message(mesh: &Mesh, c: &Constraints) -> String {
    match c.check_rigid_motions(mesh) {
        Err(Error::Unconstrained(msg)) => msg,
        other => panic!("expected Error::Unconstrained, got {other:?}"),
    }
}

#[test]
fn rigid_motion_check_names_the_free_motions() {
    let mesh = Grid::new(4, Order::P1).build();
    let ndof = 2 * mesh.num_nodes();
    let none = Constraints::new(ndof);
    let msg = unconstrained_message(&mesh, &none);
    for m in ["translation in x", "translation in y", "rotation about z", "3 rigid motions"] {
        assert!(msg.contains(m), "{msg}");
    }
    // One x-fixed node: translation in y and a rotation remain.
    let mut one = Constraints::new(ndof);
    one.fix(0, 0.0);
    let msg = unconstrained_message(&mesh, &one);
    assert!(
        msg.contains("translation in y") && msg.contains("rotation about z") && !msg.contains("translation in x"),
        "{msg}"
    );
    assert!(msg.contains("2 rigid motions"), "{msg}");
    // One node fully fixed: rotation about that node.
    let node = 7; // (2h, h) on the 5 × 5 vertex grid
    let mut pin = Constraints::new(ndof);
    pin.fix(2 * node, 0.0);
    pin.fix(2 * node + 1, 0.0);
    let msg = unconstrained_message(&mesh, &pin);
    assert!(
        msg.contains("1 rigid motion free: rotation about z (about the point (5.000000e-1, 2.500000e-1))"),
        "{msg}"
    );
    // x fixed along the bottom, y at one bottom node: rotation about that node is still free.
    let mut rollers = Constraints::new(ndof);
    rollers.fix_group(&mesh, BOTTOM, 0, |_| 0.0);
    let node = 1; // (h, 0)
    rollers.fix(2 * node + 1, 0.0);
    let msg = unconstrained_message(&mesh, &rollers);
    assert!(msg.contains("rotation about z (about the point (2.500000e-1, 0.000000e0))"), "{msg}");
    // Rollers on two sides, or a clamped side: all blocked.
    let mut sym = Constraints::new(ndof);
    sym.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
    sym.fix_group(&mesh, LEFT, 0, |_| 0.0);
    assert!(sym.check_rigid_motions(&mesh).is_ok());
    let clamped = dirichlet(&mesh, &[LEFT], &|_| [0.0, 0.0]);
    assert!(clamped.check_rigid_motions(&mesh).is_ok());
    // Also far from the origin and at a small scale.
    let mut far = mesh.clone();
    for p in &mut far.nodes {
        *p = [1e6 + 1e-3 * p[0], -3e5 + 1e-3 * p[1]];
    }
    let clamped = dirichlet(&far, &[LEFT], &|_| [0.0, 0.0]);
    assert!(clamped.check_rigid_motions(&far).is_ok());
    let mut line = Constraints::new(ndof);
    line.fix_group(&far, BOTTOM, 1, |_| 0.0);
    let msg = unconstrained_message(&far, &line);
    assert!(
        msg.contains("translation in x") && !msg.contains("translation in y") && !msg.contains("rotation"),
        "{msg}"
    );
}

#[test]
fn constraints_bookkeeping_and_fix_group_includes_mid_nodes() {
    let mesh = Grid::new(3, Order::P2).build();
    let mut c = Constraints::new(2 * mesh.num_nodes());
    assert_eq!(c.num_fixed(), 0);
    c.fix_group(&mesh, TOP, 1, |x| x[0] * 2.0);
    // 3 edges on the top: 4 vertices + 3 mid nodes.
    assert_eq!(c.num_fixed(), 7);
    for (dof, v) in c.fixed() {
        assert_eq!(dof % 2, 1);
        let x = mesh.nodes[dof / 2];
        assert!((x[1] - 1.0).abs() < 1e-15);
        assert_eq!(v, 2.0 * x[0]);
    }
    let mids = c.fixed().filter(|(d, _)| d / 2 >= 16).count();
    assert_eq!(mids, 3);
    c.fix(0, 1.5);
    assert_eq!(c.value(0), Some(1.5));
    assert_eq!(c.value(1), None);
    assert_eq!(c.value(10_000_000), None);
}

// ---------------------------------------------------------------------------------------------
// Assembly: pattern, elimination, row blocks.
// ---------------------------------------------------------------------------------------------

/// The unconstrained global stiffness, dense, from the element matrices.
fn dense_stiffness(mesh: &Mesh, m: &Material) -> DMatrix<f64> {
    let n = 2 * mesh.num_nodes();
    let npc = mesh.order.nodes_per_cell();
    let mut k = DMatrix::zeros(n, n);
    for c in 0..mesh.num_cells() {
        let nodes = mesh.cell(c);
        let x: Vec<[f64; 2]> = nodes.iter().map(|&i| mesh.nodes[i]).collect();
        let ke = element_stiffness(mesh.order, &x, m);
        for a in 0..2 * npc {
            for b in 0..2 * npc {
                k[(2 * nodes[a / 2] + a % 2, 2 * nodes[b / 2] + b % 2)] += ke[a * 2 * npc + b];
            }
        }
    }
    k
}

#[test]
fn assembly_eliminates_dirichlet_symmetrically_with_an_exact_pattern() {
    for (order, grid) in [(Order::P1, 4), (Order::P2, 3)] {
        let mesh = Grid::new(grid, order).distorted(Distortion::Random(0.2)).curved(0.1, 0.0).build();
        let m = steel(PlaneModel::Strain);
        let ndof = 2 * mesh.num_nodes();
        let mut c = Constraints::new(ndof);
        c.fix_group(&mesh, LEFT, 0, |x| 1e-3 * x[1]);
        c.fix_group(&mesh, LEFT, 1, |x| -2e-3 * x[1]);
        c.fix_group(&mesh, BOTTOM, 1, |x| 5e-4 * x[0]);
        let force = |x: [f64; 2]| [1e6 * x[1], -2e6];
        let loads = Loads {
            body_force: Some(&force),
            edge_loads: vec![EdgeLoad { group: TOP, traction: Traction::Pressure(3e7) }],
        };
        let system = assemble(&mesh, &m, &c, &loads, all_dofs(&mesh));
        let k = dense_stiffness(&mesh, &m);
        let f = load_vector(&mesh, &loads);
        // Expected pattern: free rows hold the free dofs of the neighbouring nodes.
        let mut neighbours = vec![HashSet::new(); mesh.num_nodes()];
        for cell in mesh.cells.chunks(order.nodes_per_cell()) {
            for &a in cell {
                neighbours[a].extend(cell.iter().copied());
            }
        }
        let a = &system.matrix;
        assert_eq!((a.first_row, a.num_rows(), a.num_cols), (0, ndof, ndof));
        for i in 0..ndof {
            let (cols, vals) = a.row(i);
            assert!(cols.windows(2).all(|w| w[0] < w[1]), "row {i}: columns not sorted");
            match c.value(i) {
                Some(g) => {
                    assert_eq!(cols, &[i]);
                    assert_eq!(vals, &[m.young]);
                    assert_eq!(system.rhs[i], m.young * g);
                }
                None => {
                    let mut expect: Vec<usize> = neighbours[i / 2]
                        .iter()
                        .flat_map(|&nb| [2 * nb, 2 * nb + 1])
                        .filter(|&j| !c.is_fixed(j))
                        .collect();
                    expect.sort();
                    assert_eq!(cols, &expect[..], "row {i}: pattern");
                    for (&j, &v) in cols.iter().zip(vals) {
                        assert!((v - k[(i, j)]).abs() <= 1e-12 * k[(i, i)].abs(), "row {i} col {j}");
                    }
                    let lifted: f64 = c.fixed().map(|(j, g)| k[(i, j)] * g).sum();
                    let expect_rhs = f[i] - lifted;
                    assert!((system.rhs[i] - expect_rhs).abs() <= 1e-10 * (f[i].abs() + lifted.abs() + 1.0), "rhs {i}");
                }
            }
        }
        // Symmetric and, with the rigid motions removed, positive definite.
        let dense = to_dense(&system);
        assert!((&dense - dense.transpose()).amax() <= 1e-14 * dense.amax());
        assert!(dense.clone().cholesky().is_some());
        // residual_forces is K u.
        let mut rng = Random(3);
        let u: Vec<f64> = (0..ndof).map(|_| rng.next()).collect();
        let ku = &k * DVector::from_column_slice(&u);
        let r = residual_forces(&mesh, &m, &u);
        for i in 0..ndof {
            assert!((r[i] - ku[i]).abs() <= 1e-12 * k.amax() * 10.0, "K u at {i}");
        }
    }
}

#[test]
fn row_blocks_match_the_full_assembly() {
    for order in [Order::P1, Order::P2] {
        let mesh = Grid::new(4, order).distorted(Distortion::Random(0.2)).build();
        let m = steel(PlaneModel::Stress);
        let ndof = 2 * mesh.num_nodes();
        let mut c = dirichlet(&mesh, &[LEFT], &|x| [0.0, 1e-3 * x[1]]);
        c.fix(2 * 13, 0.0);
        let force = |x: [f64; 2]| [x[0], 1.0 - x[1]];
        let field = |_x: [f64; 2], n: [f64; 2]| [n[1], -n[0]];
        let loads = Loads {
            body_force: Some(&force),
            edge_loads: vec![
                EdgeLoad { group: RIGHT, traction: Traction::Constant([1e5, -3e4]) },
                EdgeLoad { group: TOP, traction: Traction::Field(&field) },
            ],
        };
        let full = assemble(&mesh, &m, &c, &loads, 0..ndof);
        // Split inside a node (odd boundary), into three blocks, one of them a single row.
        let cuts = [0, ndof / 2 + 1, ndof / 2 + 2, ndof];
        let mut total_nnz = 0;
        for w in cuts.windows(2) {
            let part = assemble(&mesh, &m, &c, &loads, w[0]..w[1]);
            assert_eq!(part.matrix.first_row, w[0]);
            assert_eq!(part.matrix.num_rows(), w[1] - w[0]);
            assert_eq!(part.rhs.len(), w[1] - w[0]);
            total_nnz += part.matrix.nnz();
            for i in w[0]..w[1] {
                assert_eq!(part.matrix.row(i), full.matrix.row(i), "{order:?} row {i}");
                assert_eq!(part.rhs[i - w[0]], full.rhs[i], "{order:?} rhs {i}");
            }
        }
        assert_eq!(total_nnz, full.matrix.nnz());
        // Out-of-range and empty ranges are clamped.
        let empty = assemble(&mesh, &m, &c, &loads, ndof..ndof + 10);
        assert_eq!(empty.matrix.num_rows(), 0);
        assert_eq!(empty.matrix.indptr, vec![0]);
        let tail = assemble(&mesh, &m, &c, &loads, ndof - 3..ndof + 10);
        assert_eq!(tail.matrix.num_rows(), 3);
    }
}

#[test]
fn load_vector_resultants() {
    let mesh = Grid::new(5, Order::P2).distorted(Distortion::Random(0.2)).curved(0.06, 0.1).build();
    let force = |_: [f64; 2]| [2.0, -3.0];
    let p = 7.0;
    let loads = Loads {
        body_force: Some(&force),
        edge_loads: vec![
            EdgeLoad { group: BOTTOM, traction: Traction::Pressure(p) },
            EdgeLoad { group: LEFT, traction: Traction::Constant([0.5, 0.25]) },
        ],
    };
    let f = load_vector(&mesh, &loads);
    let fx: f64 = f.iter().step_by(2).sum();
    let fy: f64 = f.iter().skip(1).step_by(2).sum();
    // Area: the curved right and top sides change it; compute it by quadrature of det J.
    let mut area = 0.0;
    let rule = quadrature::triangle(2);
    for c in 0..mesh.num_cells() {
        let x: Vec<[f64; 2]> = mesh.cell(c).iter().map(|&k| mesh.nodes[k]).collect();
        for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
            area += w * lagrange::map_cell_point(Order::P2, &x, xi).det;
        }
    }
    // Pressure on the bottom (n = (0, −1)): t = (0, p); constant traction on the left (length 1).
    let ex = 2.0 * area + 0.5;
    let ey = -3.0 * area + p + 0.25;
    assert!((fx - ex).abs() < 1e-13 && (fy - ey).abs() < 1e-13, "({fx}, {fy}) vs ({ex}, {ey})");
    assert!((area - 1.0).abs() > 1e-4, "the curved boundary should change the area");
}

// ---------------------------------------------------------------------------------------------
// Patch tests.
// ---------------------------------------------------------------------------------------------

/// The linear field of the patch tests (uniform strain) and its stress.
fn linear_field(x: [f64; 2]) -> [f64; 2] {
    [1e-3 + 2e-3 * x[0] - 1e-3 * x[1], -5e-4 + 7e-4 * x[0] + 1.5e-3 * x[1]]
}
const LINEAR_STRAIN: [f64; 3] = [2e-3, 1.5e-3, -1e-3 + 7e-4];

fn patch_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("P1 distorted", Grid::new(5, Order::P1).distorted(Distortion::Random(0.2)).build()),
        ("P2 distorted", Grid::new(4, Order::P2).distorted(Distortion::Random(0.2)).build()),
        ("P2 curved", Grid::new(4, Order::P2).distorted(Distortion::Random(0.2)).curved(0.06, 0.1).build()),
    ]
}

fn assert_uniform_stress(what: &str, mesh: &Mesh, m: &Material, u: &[f64], s: [f64; 3]) {
    let scale = s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for (k, cs) in cell_stress(mesh, m, u).iter().chain(nodal_stress(mesh, m, u).iter()).enumerate() {
        for i in 0..3 {
            assert!((cs[i] - s[i]).abs() < 1e-9 * scale, "{what}: stress {k} component {i}: {} vs {}", cs[i], s[i]);
        }
    }
}

#[test]
fn patch_test_dirichlet_all_around() {
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        for (what, mesh) in patch_meshes() {
            let c = dirichlet(&mesh, &[BOTTOM, RIGHT, TOP, LEFT], &linear_field);
            let u = solve(&assemble(&mesh, &m, &c, &Loads::default(), all_dofs(&mesh)));
            let err = nodal_error(&mesh, &u, &linear_field);
            assert!(err < 1e-12, "{what} {plane:?}: nodal error {err:e}");
            let s = m.stress(LINEAR_STRAIN);
            assert_uniform_stress(what, &mesh, &m, &u, s);
            let e = energy_error(&mesh, &m, &u, |_| [[2e-3, -1e-3], [7e-4, 1.5e-3]]);
            let norm = energy_norm(&mesh, &m, &u);
            assert!(e < 1e-10 * norm, "{what}: energy error {e:e} of {norm:e}");
            // Reactions balance: the sum of (K u − f) over all dofs is zero (no loads).
            let r = residual_forces(&mesh, &m, &u);
            let scale = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let (rx, ry): (f64, f64) = (r.iter().step_by(2).sum(), r.iter().skip(1).step_by(2).sum());
            assert!(rx.abs() < 1e-10 * scale && ry.abs() < 1e-10 * scale, "{what}: reactions ({rx}, {ry})");
        }
    }
}

#[test]
fn patch_test_with_tractions() {
    let m = steel(PlaneModel::Strain);
    let s = m.stress(LINEAR_STRAIN);
    let sigma_n = move |_x: [f64; 2], n: [f64; 2]| [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]];
    for (what, mesh) in patch_meshes() {
        // Right (straight): constant traction σ (1, 0); top (curved for "P2 curved"): σ n.
        let right = if what == "P2 curved" { Traction::Field(&sigma_n) } else { Traction::Constant([s[0], s[2]]) };
        let loads = Loads {
            body_force: None,
            edge_loads: vec![
                EdgeLoad { group: RIGHT, traction: right },
                EdgeLoad { group: TOP, traction: Traction::Field(&sigma_n) },
            ],
        };
        let c = dirichlet(&mesh, &[BOTTOM, LEFT], &linear_field);
        c.check_rigid_motions(&mesh).unwrap();
        let u = solve(&assemble(&mesh, &m, &c, &loads, all_dofs(&mesh)));
        let err = nodal_error(&mesh, &u, &linear_field);
        assert!(err < 1e-12, "{what}: nodal error {err:e}");
        assert_uniform_stress(what, &mesh, &m, &u, s);
        // Reactions on the fixed dofs balance the applied tractions.
        let r = residual_forces(&mesh, &m, &u);
        let f = load_vector(&mesh, &loads);
        let total: [f64; 2] =
            [(0..r.len()).step_by(2).map(|i| r[i] - f[i]).sum(), (1..r.len()).step_by(2).map(|i| r[i] - f[i]).sum()];
        let reactions: [f64; 2] = [
            c.fixed().filter(|(d, _)| d % 2 == 0).map(|(d, _)| r[d] - f[d]).sum(),
            c.fixed().filter(|(d, _)| d % 2 == 1).map(|(d, _)| r[d] - f[d]).sum(),
        ];
        let applied: [f64; 2] = [f.iter().step_by(2).sum(), f.iter().skip(1).step_by(2).sum()];
        for k in 0..2 {
            assert!((reactions[k] + applied[k]).abs() < 1e-9 * applied[k].abs().max(1.0), "{what}: equilibrium {k}");
            assert!(
                (total[k] - reactions[k]).abs() < 1e-9 * applied[k].abs().max(1.0),
                "{what}: free dofs not in equilibrium"
            );
        }
    }
}

#[test]
fn patch_test_with_pressure() {
    // Hydrostatic state σ = −p I: u = −p/(2(λ* + μ)) x, traction −p n (Pressure) on the free sides.
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        let p = 4e7;
        let (lambda, mu) = m.lame();
        let k = -p / (2.0 * (lambda + mu));
        let exact = move |x: [f64; 2]| [k * x[0], k * x[1]];
        for (what, mesh) in patch_meshes() {
            let mut c = Constraints::new(2 * mesh.num_nodes());
            c.fix_group(&mesh, LEFT, 0, |_| 0.0);
            c.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
            let loads = Loads {
                body_force: None,
                edge_loads: vec![
                    EdgeLoad { group: RIGHT, traction: Traction::Pressure(p) },
                    EdgeLoad { group: TOP, traction: Traction::Pressure(p) },
                ],
            };
            let u = solve(&assemble(&mesh, &m, &c, &loads, all_dofs(&mesh)));
            let err = nodal_error(&mesh, &u, &exact);
            assert!(err < 1e-12, "{what} {plane:?}: nodal error {err:e}");
            assert_uniform_stress(what, &mesh, &m, &u, [-p, -p, 0.0]);
        }
    }
}

#[test]
fn p2_reproduces_a_quadratic_field_with_its_body_force() {
    let m = steel(PlaneModel::Strain);
    let [[c11, c12, _], _, [_, _, c33]] = m.elasticity();
    // u = (x² − xy + 2y², −3x² + 4xy + y²) · 1e-3.
    let exact = |x: [f64; 2]| {
        [
            1e-3 * (x[0] * x[0] - x[0] * x[1] + 2.0 * x[1] * x[1]),
            1e-3 * (-3.0 * x[0] * x[0] + 4.0 * x[0] * x[1] + x[1] * x[1]),
        ]
    };
    let (uxx, uxy, uyy) = (2e-3, -1e-3, 4e-3); // second derivatives of u_x
    let (vxx, vxy, vyy) = (-6e-3, 4e-3, 2e-3); // of u_y
    let f = [-(c11 * uxx + c12 * vxy + c33 * (uyy + vxy)), -(c33 * (uxy + vxx) + c12 * uxy + c11 * vyy)];
    let force = move |_: [f64; 2]| f;
    let mesh = Grid::new(4, Order::P2).distorted(Distortion::Random(0.2)).build();
    let c = dirichlet(&mesh, &[BOTTOM, RIGHT, TOP, LEFT], &exact);
    let loads = Loads { body_force: Some(&force), edge_loads: vec![] };
    let u = solve(&assemble(&mesh, &m, &c, &loads, all_dofs(&mesh)));
    let err = nodal_error(&mesh, &u, &exact);
    assert!(err < 1e-12, "nodal error {err:e}");
    let l2 = l2_error(&mesh, &u, exact);
    assert!(l2 < 1e-14, "L2 error {l2:e}");
    // P1 cannot: the same problem has a visible error.
    let mesh1 = Grid::new(4, Order::P1).distorted(Distortion::Random(0.2)).build();
    let c1 = dirichlet(&mesh1, &[BOTTOM, RIGHT, TOP, LEFT], &exact);
    let u1 = solve(&assemble(&mesh1, &m, &c1, &loads, all_dofs(&mesh1)));
    assert!(l2_error(&mesh1, &u1, exact) > 1e-7);
}

// ---------------------------------------------------------------------------------------------
// Convergence on a manufactured solution.
// ---------------------------------------------------------------------------------------------

fn manufactured(x: [f64; 2]) -> [f64; 2] {
    let (sx, sy) = ((PI * x[0]).sin(), (PI * x[1]).sin());
    [sx * sy + 0.2 * x[0] * x[1], x[0] * x[0] * x[1] * (1.0 - x[1]) + 0.1 * sy]
}

fn manufactured_gradient(x: [f64; 2]) -> [[f64; 2]; 2] {
    let (sx, sy, cx, cy) = ((PI * x[0]).sin(), (PI * x[1]).sin(), (PI * x[0]).cos(), (PI * x[1]).cos());
    [
        [PI * cx * sy + 0.2 * x[1], PI * sx * cy + 0.2 * x[0]],
        [2.0 * x[0] * x[1] * (1.0 - x[1]), x[0] * x[0] * (1.0 - 2.0 * x[1]) + 0.1 * PI * cy],
    ]
}

/// −div σ(u) for the manufactured u.
fn manufactured_force(m: &Material, x: [f64; 2]) -> [f64; 2] {
    let [[c11, c12, _], _, [_, _, c33]] = m.elasticity();
    let (sx, sy, cx, cy) = ((PI * x[0]).sin(), (PI * x[1]).sin(), (PI * x[0]).cos(), (PI * x[1]).cos());
    let uxx = -PI * PI * sx * sy;
    let uyy = -PI * PI * sx * sy;
    let uxy = PI * PI * cx * cy + 0.2;
    let vxx = 2.0 * x[1] * (1.0 - x[1]);
    let vyy = -2.0 * x[0] * x[0] - 0.1 * PI * PI * sy;
    let vxy = 2.0 * x[0] * (1.0 - 2.0 * x[1]);
    [-(c11 * uxx + c12 * vxy + c33 * (uyy + vxy)), -(c33 * (uxy + vxx) + c12 * uxy + c11 * vyy)]
}

fn manufactured_stress(m: &Material, x: [f64; 2]) -> [f64; 3] {
    let g = manufactured_gradient(x);
    m.stress([g[0][0], g[1][1], g[0][1] + g[1][0]])
}

/// (h, energy error, L2 error) over a refinement sequence.
fn convergence(order: Order, sizes: &[usize], m: &Material, neumann: bool) -> Vec<(f64, f64, f64)> {
    let force = |x: [f64; 2]| manufactured_force(m, x);
    let traction = |x: [f64; 2], n: [f64; 2]| {
        let s = manufactured_stress(m, x);
        [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]]
    };
    sizes
        .iter()
        .map(|&n| {
            let mesh = Grid::new(n, order).distorted(Distortion::Smooth(0.04)).build();
            let (groups, edge_loads): (&[usize], _) = if neumann {
                (
                    &[BOTTOM, LEFT],
                    vec![
                        EdgeLoad { group: RIGHT, traction: Traction::Field(&traction) },
                        EdgeLoad { group: TOP, traction: Traction::Field(&traction) },
                    ],
                )
            } else {
                (&[BOTTOM, RIGHT, TOP, LEFT], vec![])
            };
            let c = dirichlet(&mesh, groups, &manufactured);
            let loads = Loads { body_force: Some(&force), edge_loads };
            let u = solve_banded(&mesh, &assemble(&mesh, m, &c, &loads, all_dofs(&mesh)));
            let e = energy_error(&mesh, m, &u, manufactured_gradient);
            let l2 = l2_error(&mesh, &u, manufactured);
            (1.0 / n as f64, e, l2)
        })
        .collect()
}

fn assert_rates(what: &str, results: &[(f64, f64, f64)], energy_rate: f64, l2_rate: f64) {
    let rates: Vec<(f64, f64)> = results
        .windows(2)
        .map(|w| {
            let r = (w[0].0 / w[1].0).ln();
            ((w[0].1 / w[1].1).ln() / r, (w[0].2 / w[1].2).ln() / r)
        })
        .collect();
    eprintln!("{what}: errors {results:?}, rates {rates:?}");
    // The last two refinements must show the asymptotic rates.
    for &(re, rl) in &rates[rates.len().saturating_sub(2)..] {
        assert!(re >= energy_rate, "{what}: energy rate {re:.3} < {energy_rate} ({rates:?})");
        assert!(rl >= l2_rate, "{what}: L2 rate {rl:.3} < {l2_rate} ({rates:?})");
    }
}

#[test]
fn convergence_rates_p1() {
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        let res = convergence(Order::P1, &[4, 8, 16, 32], &m, false);
        assert_rates(&format!("P1 {plane:?} Dirichlet"), &res, 0.9, 1.8);
    }
}

#[test]
fn convergence_rates_p2() {
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        let res = convergence(Order::P2, &[2, 4, 8, 16], &m, false);
        assert_rates(&format!("P2 {plane:?} Dirichlet"), &res, 1.8, 2.7);
    }
}

#[test]
fn convergence_rates_with_traction_field() {
    let m = Material::new(1.0e3, 0.25, PlaneModel::Strain);
    let res = convergence(Order::P1, &[4, 8, 16, 32], &m, true);
    assert_rates("P1 Neumann", &res, 0.9, 1.8);
    let res = convergence(Order::P2, &[2, 4, 8, 16], &m, true);
    assert_rates("P2 Neumann", &res, 1.8, 2.7);
}

#[test]
fn banded_solver_agrees_with_dense_cholesky() {
    for order in [Order::P1, Order::P2] {
        let m = steel(PlaneModel::Strain);
        let mesh = Grid::new(6, order).distorted(Distortion::Random(0.2)).build();
        let c = dirichlet(&mesh, &[LEFT, BOTTOM], &manufactured);
        let force = |x: [f64; 2]| manufactured_force(&m, x);
        let loads = Loads {
            body_force: Some(&force),
            edge_loads: vec![EdgeLoad { group: TOP, traction: Traction::Pressure(1e8) }],
        };
        let system = assemble(&mesh, &m, &c, &loads, all_dofs(&mesh));
        let (dense, banded) = (solve(&system), solve_banded(&mesh, &system));
        let scale = dense.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in dense.iter().zip(&banded) {
            assert!((a - b).abs() < 1e-11 * scale, "{order:?}: {a} vs {b}");
        }
    }
}

#[test]
fn energy_norm_is_the_stiffness_energy() {
    for order in [Order::P1, Order::P2] {
        let mesh = Grid::new(3, order).distorted(Distortion::Random(0.2)).build();
        let m = steel(PlaneModel::Stress);
        let mut rng = Random(11);
        let u: Vec<f64> = (0..2 * mesh.num_nodes()).map(|_| 1e-3 * rng.next()).collect();
        let ku = residual_forces(&mesh, &m, &u);
        let utku: f64 = u.iter().zip(&ku).map(|(a, b)| a * b).sum();
        let e = energy_norm(&mesh, &m, &u);
        assert!((e * e - utku).abs() < 1e-12 * utku, "{order:?}: {} vs {utku}", e * e);
        assert!((energy_error(&mesh, &m, &u, |_| [[0.0; 2]; 2]) - e).abs() < 1e-12 * e);
        assert!((l2_error(&mesh, &u, |_| [0.0, 0.0]) > 0.0));
    }
}
