//! The condensed frictional contact problem and its solvers (src/contact).
//!
//! Delassus matrices come from a genuine elastic model: a plane-strain P1 layer
//! `[-L/2, L/2] × [0, H]`, clamped on top, whose bottom edge is the contact side (outward
//! normal −y, tangent +x). `W = P K⁻¹ Pᵀ` restricted to the bottom nodes, computed with a
//! banded Cholesky factorization.

mod failures;
mod fallbacks;
mod interface;
mod layer_agreement;
mod newton;
mod operator;
mod residuals;
mod small_cases;
mod validation;

use nalgebra::DMatrix;
use signorini::contact::{
    solve, CondensedProblem, ContactSolution, ContactSolver, Delassus, FrictionLaw, PointStatus, SolverSettings,
};

// ---------------------------------------------------------------------------------------------
// Elastic model
// ---------------------------------------------------------------------------------------------

/// Symmetric banded matrix, lower band stored row by row: `band[i * (bw + 1) + (i - j)]`.
struct Banded {
    n: usize,
    bw: usize,
    band: Vec<f64>,
}

impl Banded {
    fn new(n: usize, bw: usize) -> Self {
        Banded { n, bw, band: vec![0.0; n * (bw + 1)] }
    }
    fn add(&mut self, i: usize, j: usize, v: f64) {
        if i >= j {
            assert!(i - j <= self.bw);
            self.band[i * (self.bw + 1) + (i - j)] += v;
        }
    }
    /// In-place Cholesky: the band then holds L (K = L Lᵀ).
    fn factor(&mut self) {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        for j in 0..n {
            let lo = j.saturating_sub(bw);
            let mut d = self.band[j * w];
            for k in lo..j {
                let l = self.band[j * w + (j - k)];
                d -= l * l;
            }
            assert!(d > 0.0, "stiffness not positive definite");
            let d = d.sqrt();
            self.band[j * w] = d;
            for i in (j + 1)..(j + bw + 1).min(n) {
                let lo_i = i.saturating_sub(bw).max(lo);
                let mut v = self.band[i * w + (i - j)];
                for k in lo_i..j {
                    v -= self.band[i * w + (i - k)] * self.band[j * w + (j - k)];
                }
                self.band[i * w + (i - j)] = v / d;
            }
        }
    }
    fn solve(&self, b: &mut [f64]) {
        let (n, bw) = (self.n, self.bw);
        let w = bw + 1;
        for i in 0..n {
            let mut v = b[i];
            for k in i.saturating_sub(bw)..i {
                v -= self.band[i * w + (i - k)] * b[k];
            }
            b[i] = v / self.band[i * w];
        }
        for i in (0..n).rev() {
            let mut v = b[i];
            for k in (i + 1)..(i + bw + 1).min(n) {
                v -= self.band[k * w + (k - i)] * b[k];
            }
            b[i] = v / self.band[i * w];
        }
    }
}

/// Flexibility of the bottom edge of a clamped plane-strain layer, `m` contact points,
/// ordered (N_0, T_0, ...), N = −y, T = +x. Also returns the x coordinates of the points.
fn layer_delassus(m: usize, height: f64, nu: f64) -> (DMatrix<f64>, Vec<f64>) {
    let (length, young) = (2.0, 1.0);
    let nx = m - 1;
    let xs: Vec<f64> = (0..=nx).map(|i| -0.5 * length + length * i as f64 / nx as f64).collect();
    let mut ys = vec![0.0];
    let mut h = length / nx as f64;
    while *ys.last().unwrap() < height {
        let next = (ys.last().unwrap() + h).min(height);
        if height - next < 0.3 * h {
            ys.push(height);
        } else {
            ys.push(next);
        }
        h *= 1.3;
    }
    let ny = ys.len() - 1;
    let node = |ix: usize, iy: usize| ix * (ny + 1) + iy;
    let n = 2 * (nx + 1) * (ny + 1);
    let bw = 2 * (ny + 2) + 1;
    let mut k = Banded::new(n, bw);
    let c = young / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let d = [[c * (1.0 - nu), c * nu, 0.0], [c * nu, c * (1.0 - nu), 0.0], [0.0, 0.0, c * (1.0 - 2.0 * nu) / 2.0]];
    for ix in 0..nx {
        for iy in 0..ny {
            let quad = [node(ix, iy), node(ix + 1, iy), node(ix + 1, iy + 1), node(ix, iy + 1)];
            let coords = [[xs[ix], ys[iy]], [xs[ix + 1], ys[iy]], [xs[ix + 1], ys[iy + 1]], [xs[ix], ys[iy + 1]]];
            for tri in [[0, 1, 2], [0, 2, 3]] {
                let p: Vec<[f64; 2]> = tri.iter().map(|&a| coords[a]).collect();
                let area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
                let b = [p[1][1] - p[2][1], p[2][1] - p[0][1], p[0][1] - p[1][1]];
                let cc = [p[2][0] - p[1][0], p[0][0] - p[2][0], p[1][0] - p[0][0]];
                let mut bm = [[0.0; 6]; 3];
                for a in 0..3 {
                    bm[0][2 * a] = b[a] / area2;
                    bm[1][2 * a + 1] = cc[a] / area2;
                    bm[2][2 * a] = cc[a] / area2;
                    bm[2][2 * a + 1] = b[a] / area2;
                }
                let dofs: Vec<usize> = tri.iter().flat_map(|&a| [2 * quad[a], 2 * quad[a] + 1]).collect();
                for (p1, &i) in dofs.iter().enumerate() {
                    for (q1, &j) in dofs.iter().enumerate() {
                        let mut v = 0.0;
                        for r in 0..3 {
                            for s in 0..3 {
                                v += bm[r][p1] * d[r][s] * bm[s][q1];
                            }
                        }
                        k.add(i, j, 0.5 * area2 * v);
                    }
                }
            }
        }
    }
    // Clamp the top: identity rows and columns.
    for ix in 0..=nx {
        for dof in [2 * node(ix, ny), 2 * node(ix, ny) + 1] {
            for j in dof.saturating_sub(bw)..(dof + bw + 1).min(n) {
                if j <= dof {
                    k.band[dof * (bw + 1) + (dof - j)] = 0.0;
                } else {
                    k.band[j * (bw + 1) + (j - dof)] = 0.0;
                }
            }
            k.band[dof * (bw + 1)] = 1.0;
        }
    }
    k.factor();
    // Contact dofs: (N, T) of bottom node ix = (−uy, ux).
    let contact: Vec<(usize, f64)> =
        (0..=nx).flat_map(|ix| [(2 * node(ix, 0) + 1, -1.0), (2 * node(ix, 0), 1.0)]).collect();
    let size = contact.len();
    let mut w = DMatrix::zeros(size, size);
    let mut column = vec![0.0; n];
    for (j, &(dof_j, sign_j)) in contact.iter().enumerate() {
        column.iter_mut().for_each(|v| *v = 0.0);
        column[dof_j] = sign_j;
        k.solve(&mut column);
        for (i, &(dof_i, sign_i)) in contact.iter().enumerate() {
            w[(i, j)] = sign_i * column[dof_i];
        }
    }
    let w = (&w + w.transpose()) * 0.5;
    (w, xs)
}

/// The indentation problem on the layer: gap `(x − x0)²/(2R)`, the top pushed down by
/// `depth` and sideways by `shift` (so `u_free = (depth, shift)` at every point).
fn indentation(m: usize, friction: FrictionLaw, depth: f64, shift: f64) -> CondensedProblem<'static> {
    let (w, xs) = layer_delassus(m, 0.5, 0.3);
    indentation_with(w, &xs, friction, depth, shift)
}

fn indentation_with(
    w: DMatrix<f64>,
    xs: &[f64],
    friction: FrictionLaw,
    depth: f64,
    shift: f64,
) -> CondensedProblem<'static> {
    let radius = 2.0;
    let gap: Vec<f64> = xs.iter().map(|x| (x - 0.05).powi(2) / (2.0 * radius)).collect();
    let free: Vec<f64> = xs.iter().flat_map(|_| [depth, shift]).collect();
    CondensedProblem::new(Delassus::Dense(w), free, gap, friction, None).expect("valid problem")
}

fn all_solvers() -> Vec<ContactSolver> {
    vec![
        ContactSolver::ProjectedRelaxation { omega: 1.0 },
        ContactSolver::ProjectedRelaxation { omega: 1.3 },
        ContactSolver::DPana,
        ContactSolver::Uzawa { accelerated: false },
        ContactSolver::Uzawa { accelerated: true },
        ContactSolver::SemismoothNewton,
        ContactSolver::TrescaFixedPoint { inner: Box::new(ContactSolver::SemismoothNewton) },
        ContactSolver::TrescaFixedPoint { inner: Box::new(ContactSolver::ProjectedRelaxation { omega: 1.0 }) },
    ]
}

fn tight() -> SolverSettings {
    SolverSettings { tolerance: 1e-11, max_iterations: 100_000, ..SolverSettings::default() }
}

fn counts(solution: &ContactSolution) -> (usize, usize, usize) {
    let open = solution.status.iter().filter(|s| **s == PointStatus::Open).count();
    let stick = solution.status.iter().filter(|s| **s == PointStatus::Stick).count();
    (open, stick, solution.status.len() - open - stick)
}

fn max_relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().chain(b).fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs())) / scale
}

/// Solve with every solver and check each answer against `reference` (relative 1e-6), its
/// own residuals, and the statuses. Returns the reference solution (semi-smooth Newton).
fn assert_all_solvers_agree(problem: &CondensedProblem, what: &str) -> ContactSolution {
    let reference = solve(problem, &ContactSolver::SemismoothNewton, &tight())
        .unwrap_or_else(|e| panic!("{what}: Newton failed: {e}"));
    for solver in all_solvers() {
        let solution = solve(problem, &solver, &tight()).unwrap_or_else(|e| panic!("{what}: {e}"));
        let difference = max_relative_difference(&solution.force, &reference.force);
        assert!(difference < 1e-6, "{what}: {} differs from Newton by {difference:e}", solver.name());
        assert!(solution.residuals.is_acceptable(1e-11), "{what}: {}", solution.residuals);
        let independent = problem.residuals(&solution.force).unwrap();
        assert_eq!(independent, solution.residuals, "{what}: reported residuals are the independent ones");
        assert_eq!(solution.status, reference.status, "{what}: {} statuses", solver.name());
        assert_eq!(solution.history.len(), solution.iterations, "{what}: {}", solver.name());
    }
    reference
}

/// One point, W = [[2, 0.5], [0.5, 1]].
fn one_point(friction: FrictionLaw, free: [f64; 2], gap: f64) -> CondensedProblem<'static> {
    let w = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
    CondensedProblem::new(Delassus::Dense(w), free.to_vec(), vec![gap], friction, None).unwrap()
}
