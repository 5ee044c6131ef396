//! Tests of the plane-elasticity finite elements (no PETSc: systems are solved densely with
//! nalgebra).
#![allow(clippy::needless_range_loop)]

mod axisymmetric;
mod constraints_and_assembly;
mod convergence;
mod material_and_stiffness;
mod patch_tests;
mod quadrature_and_shapes;

use nalgebra::{DMatrix, DVector};
use signorini::fem::{lagrange, quadrature, Constraints, LinearSystem, Material, PlaneModel};
use signorini::mesh::{Mesh, Order, PhysicalGroup};
use std::collections::HashMap;
use std::f64::consts::PI;

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
        let mesh = Mesh {
            order: self.order,
            nodes,
            cells,
            cell_group: vec![4; num_cells],
            edges,
            edge_group,
            groups,
            measure: Default::default(),
        };
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

/// A P2 triangle with vertices (0,0), (2,0), (0,1) whose edge 0-1 bulges outward by `delta`.
fn curved_p2_triangle(delta: f64) -> Vec<[f64; 2]> {
    vec![[0.0, 0.0], [2.0, 0.0], [0.0, 1.0], [1.0, -delta], [1.0, 0.5], [0.0, 0.5]]
}
