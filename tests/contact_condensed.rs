//! The condensed frictional contact problem and its solvers (src/contact).
//!
//! Delassus matrices come from a genuine elastic model: a plane-strain P1 layer
//! `[-L/2, L/2] × [0, H]`, clamped on top, whose bottom edge is the contact side (outward
//! normal −y, tangent +x). `W = P K⁻¹ Pᵀ` restricted to the bottom nodes, computed with a
//! banded Cholesky factorization.
use nalgebra::DMatrix;
use signorini::contact::{
    solve, CondensedProblem, ContactSolution, ContactSolver, Delassus, FrictionLaw, PointStatus, SolverSettings,
};
use signorini::Error;

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

// ---------------------------------------------------------------------------------------------
// Exact small cases
// ---------------------------------------------------------------------------------------------

/// One point, W = [[2, 0.5], [0.5, 1]].
fn one_point(friction: FrictionLaw, free: [f64; 2], gap: f64) -> CondensedProblem<'static> {
    let w = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
    CondensedProblem::new(Delassus::Dense(w), free.to_vec(), vec![gap], friction, None).unwrap()
}

fn assert_every_solver_gives(problem: &CondensedProblem, expected: [f64; 2], status: PointStatus, what: &str) {
    for solver in all_solvers() {
        let solution = solve(problem, &solver, &tight()).unwrap_or_else(|e| panic!("{what}: {e}"));
        for k in 0..2 {
            assert!(
                (solution.force[k] - expected[k]).abs() <= 1e-9 * expected[0].abs().max(1e-3),
                "{what}: {} gives {:?}, expected {expected:?}",
                solver.name(),
                solution.force
            );
        }
        assert_eq!(solution.status, vec![status], "{what}: {}", solver.name());
    }
}

#[test]
fn one_point_open() {
    // uN_free = 0.1 < g0 = 0.2: no force, whatever the friction.
    for friction in
        [FrictionLaw::None, FrictionLaw::Tresca { threshold: vec![0.05] }, FrictionLaw::Coulomb { mu: vec![0.3] }]
    {
        let problem = one_point(friction.clone(), [0.1, 0.3], 0.2);
        if let FrictionLaw::Tresca { .. } = friction {
            // Tresca acts without contact: |rT| = s opposite to the slip, rN = 0.
            // rT = -0.05: uN = 0.5 (-0.05) + 0.1 < 0.2, uT = -0.05 + 0.3 > 0: slip.
            for solver in all_solvers() {
                let solution = solve(&problem, &solver, &tight()).unwrap();
                assert_eq!(solution.force[0], 0.0, "{}", solver.name());
                assert!((solution.force[1] + 0.05).abs() < 1e-12, "{}: {:?}", solver.name(), solution.force);
                assert_eq!(solution.status, vec![PointStatus::Open]);
            }
        } else {
            assert_every_solver_gives(&problem, [0.0, 0.0], PointStatus::Open, &format!("{friction:?}"));
        }
    }
}

#[test]
fn one_point_frictionless_contact() {
    // uN = 2 rN + 1 = 0.2 → rN = -0.4; rT stays exactly 0, the tangential slip is free.
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    assert_every_solver_gives(&problem, [-0.4, 0.0], PointStatus::Slip, "frictionless");
}

#[test]
fn one_point_stick() {
    // W r = (g0 - uN_free, -uT_free) = (-0.8, -0.3); W⁻¹ = [[1, -0.5], [-0.5, 2]] / 1.75.
    let expected = [-0.65 / 1.75, -0.2 / 1.75];
    let tresca = one_point(FrictionLaw::Tresca { threshold: vec![0.2] }, [1.0, 0.3], 0.2);
    assert_every_solver_gives(&tresca, expected, PointStatus::Stick, "Tresca stick");
    // Coulomb sticks iff mu ≥ |rT| / |rN| = 0.2 / 0.65.
    let coulomb = one_point(FrictionLaw::Coulomb { mu: vec![0.5] }, [1.0, 0.3], 0.2);
    assert_every_solver_gives(&coulomb, expected, PointStatus::Stick, "Coulomb stick");
}

#[test]
fn one_point_slip() {
    // Tresca s = 0.05: rT = -0.05, 2 rN + 0.5 rT = -0.8 → rN = -0.3875; uT = 0.05625 > 0.
    let tresca = one_point(FrictionLaw::Tresca { threshold: vec![0.05] }, [1.0, 0.3], 0.2);
    assert_every_solver_gives(&tresca, [-0.3875, -0.05], PointStatus::Slip, "Tresca slip");
    let solution = solve(&tresca, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    assert!((solution.displacement[1] - 0.05625).abs() < 1e-12);
    assert!((solution.displacement[0] - 0.2).abs() < 1e-12);
    // Coulomb mu = 0.1: rT = 0.1 rN, (2 + 0.05) rN = -0.8.
    let rn = -0.8 / 2.05;
    let coulomb = one_point(FrictionLaw::Coulomb { mu: vec![0.1] }, [1.0, 0.3], 0.2);
    assert_every_solver_gives(&coulomb, [rn, 0.1 * rn], PointStatus::Slip, "Coulomb slip");
}

/// Two points, W = [[2, .3, 1, .2], [.3, 1, .1, .4], [1, .1, 2, .3], [.2, .4, .3, 1]] (SPD).
fn two_points(friction: FrictionLaw, free: [f64; 4], gap: [f64; 2]) -> CondensedProblem<'static> {
    let w = DMatrix::from_row_slice(
        4,
        4,
        &[2.0, 0.3, 1.0, 0.2, 0.3, 1.0, 0.1, 0.4, 1.0, 0.1, 2.0, 0.3, 0.2, 0.4, 0.3, 1.0],
    );
    CondensedProblem::new(Delassus::Dense(w), free.to_vec(), gap.to_vec(), friction, None).unwrap()
}

#[test]
fn two_points_frictionless() {
    // Point 0 in contact, point 1 open: rN0 = -1/2, uN1 = 1 (-1/2) + 0.2 = -0.3 < 0.5.
    let problem = two_points(FrictionLaw::None, [1.0, 0.0, 0.2, 0.0], [0.0, 0.5]);
    for solver in all_solvers() {
        let solution = solve(&problem, &solver, &tight()).unwrap();
        assert!(max_relative_difference(&solution.force, &[-0.5, 0.0, 0.0, 0.0]) < 1e-10, "{}", solver.name());
        assert_eq!(solution.status, vec![PointStatus::Slip, PointStatus::Open]);
        assert!((solution.displacement[2] + 0.3).abs() < 1e-10);
    }
    // Both in contact: [[2, 1], [1, 2]] rN = -(1, 1) → rN = -(1/3, 1/3).
    let problem = two_points(FrictionLaw::None, [1.0, 0.0, 1.0, 0.0], [0.0, 0.0]);
    for solver in all_solvers() {
        let solution = solve(&problem, &solver, &tight()).unwrap();
        let third = 1.0 / 3.0;
        assert!(max_relative_difference(&solution.force, &[-third, 0.0, -third, 0.0]) < 1e-10, "{}", solver.name());
    }
}

#[test]
fn two_points_tresca_stick_is_the_linear_solution() {
    // Large thresholds: both stick, W r = g̃ - u_free.
    let free = [1.0, 0.1, 0.8, -0.2];
    let problem = two_points(FrictionLaw::Tresca { threshold: vec![10.0, 10.0] }, free, [0.1, 0.0]);
    let w = problem.delassus().as_dense().unwrap().clone();
    let rhs = nalgebra::DVector::from_vec(vec![0.1 - free[0], -free[1], -free[2], -free[3]]);
    let expected = w.lu().solve(&rhs).unwrap();
    assert!(expected[0] < 0.0 && expected[2] < 0.0, "the data must give compression");
    for solver in all_solvers() {
        let solution = solve(&problem, &solver, &tight()).unwrap();
        assert!(max_relative_difference(&solution.force, expected.as_slice()) < 1e-9, "{}", solver.name());
        assert_eq!(solution.status, vec![PointStatus::Stick, PointStatus::Stick]);
    }
}

// ---------------------------------------------------------------------------------------------
// Elastic model: all solvers agree
// ---------------------------------------------------------------------------------------------

#[test]
fn layer_flexibility_is_a_genuine_spd_flexibility() {
    let (w, _) = layer_delassus(20, 0.5, 0.3);
    assert!(w.clone().cholesky().is_some());
    // A downward point force (rN < 0) moves that point away from the obstacle the most.
    let column = w.column(20);
    assert!(column[20] > 0.0);
    for i in (0..40).step_by(2) {
        assert!(column[i] <= column[20] + 1e-15);
    }
    // Normal–tangential coupling (Dundurs-like, plus the free ends) is odd in x: opposite
    // signs at the two ends of the edge, and not small.
    assert!(w[(0, 1)] * w[(38, 39)] < 0.0);
    assert!(w[(0, 1)].abs() > 0.05 * w[(0, 0)] && w[(38, 39)].abs() > 0.05 * w[(38, 38)]);
}

#[test]
fn solvers_agree_frictionless() {
    let problem = indentation(40, FrictionLaw::None, 0.08, 0.01);
    let solution = assert_all_solvers_agree(&problem, "frictionless");
    let (open, stick, slip) = counts(&solution);
    assert!(open > 5 && slip > 5 && stick == 0, "{open} open, {stick} stick, {slip} slip");
    assert!(solution.force.iter().skip(1).step_by(2).all(|&t| t == 0.0));
}

#[test]
fn solvers_agree_tresca() {
    let m = 40;
    let problem = indentation(m, FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] }, 0.08, 0.01);
    let solution = assert_all_solvers_agree(&problem, "Tresca");
    let (open, stick, slip) = counts(&solution);
    assert!(open > 5 && stick > 5 && slip > 2, "{open} open, {stick} stick, {slip} slip");
}

#[test]
fn solvers_agree_coulomb() {
    let m = 40;
    let problem = indentation(m, FrictionLaw::Coulomb { mu: vec![0.3; m] }, 0.08, 0.03);
    let solution = assert_all_solvers_agree(&problem, "Coulomb");
    let (open, stick, slip) = counts(&solution);
    assert!(open > 5 && stick > 5 && slip > 5, "{open} open, {stick} stick, {slip} slip");
    // Slipping points: uT opposite to rT, |rT| = mu |rN|.
    for (i, status) in solution.status.iter().enumerate() {
        let (rn, rt, ut) = (solution.force[2 * i], solution.force[2 * i + 1], solution.displacement[2 * i + 1]);
        match status {
            PointStatus::Slip => {
                assert!((rt.abs() - 0.3 * rn.abs()).abs() < 1e-9 * rn.abs().max(1e-12));
                assert!(rt * ut < 0.0);
            }
            PointStatus::Stick => assert!(ut.abs() < 1e-12),
            PointStatus::Open => assert_eq!(rn, 0.0),
        }
    }
}

#[test]
fn coulomb_friction_from_0_to_10() {
    let m = 30;
    let (w, xs) = layer_delassus(m, 0.5, 0.3);
    let mut previous_stick = 0;
    for mu in [0.0, 0.05, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0] {
        let problem = indentation_with(w.clone(), &xs, FrictionLaw::Coulomb { mu: vec![mu; m] }, 0.08, 0.03);
        let solution = assert_all_solvers_agree(&problem, &format!("Coulomb mu = {mu}"));
        let (_, stick, slip) = counts(&solution);
        assert!(stick >= previous_stick, "mu = {mu}: more friction, fewer sticking points");
        previous_stick = stick;
        if mu == 0.0 {
            assert_eq!(problem.friction(), &FrictionLaw::None);
            assert!(solution.force.iter().skip(1).step_by(2).all(|&t| t == 0.0));
        }
        if mu == 10.0 {
            assert_eq!(slip, 0, "mu = 10 sticks everywhere on this load");
        }
    }
}

#[test]
fn zero_friction_leaves_tangential_forces_exactly_zero() {
    let m = 30;
    let (w, xs) = layer_delassus(m, 0.5, 0.3);
    // Per-point zero coefficients and thresholds, mixed with nonzero ones.
    let mu: Vec<f64> = (0..m).map(|i| if i % 2 == 0 { 0.0 } else { 0.3 }).collect();
    let threshold: Vec<f64> = (0..m).map(|i| if i % 3 == 0 { 0.0 } else { 0.001 }).collect();
    for friction in [FrictionLaw::Coulomb { mu: mu.clone() }, FrictionLaw::Tresca { threshold: threshold.clone() }] {
        let problem = indentation_with(w.clone(), &xs, friction.clone(), 0.08, 0.03);
        for solver in all_solvers() {
            let solution = solve(&problem, &solver, &tight()).unwrap();
            for i in 0..m {
                let frictionless = match &friction {
                    FrictionLaw::Coulomb { .. } => mu[i] == 0.0,
                    _ => threshold[i] == 0.0,
                };
                if frictionless {
                    assert_eq!(solution.force[2 * i + 1], 0.0, "{}: point {i}", solver.name());
                }
            }
            assert!(solution.force.iter().skip(1).step_by(2).any(|&t| t != 0.0));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Residuals detect each violation
// ---------------------------------------------------------------------------------------------

fn assert_only(residuals: &signorini::contact::ContactResiduals, component: &str, value: f64) {
    let all = [
        ("penetration", residuals.max_penetration),
        ("wrong-sign pressure", residuals.max_wrong_sign_pressure),
        ("cone violation", residuals.max_cone_violation),
        ("normal complementarity", residuals.normal_complementarity),
        ("tangential complementarity", residuals.tangential_complementarity),
    ];
    for (name, v) in all {
        if name == component {
            assert!((v - value).abs() <= 1e-12 * value, "{name}: {v} expected {value}");
        } else {
            assert!(v <= 1e-14, "{name} = {v} should be zero ({residuals})");
        }
    }
    assert_eq!(residuals.worst_component(), component);
    assert!(!residuals.is_acceptable(0.5 * value));
    assert!(residuals.is_acceptable(2.0 * value));
    assert!(residuals.to_string().contains(component));
}

#[test]
fn residual_detects_penetration() {
    // No force although uN_free = 1 > g0 = 0.2.
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    let residuals = problem.residuals(&[0.0, 0.0]).unwrap();
    assert_eq!(residuals.scale.displacement, 1.0); // max |u| = |u_free|∞ = 1
    assert_only(&residuals, "penetration", 0.8);
}

#[test]
fn residual_detects_wrong_sign_pressure() {
    // rN = +0.05 (tension) on an open point: uN = 0.1 + 0.1 = 0.2 = g0, so nothing else fails.
    let problem = one_point(FrictionLaw::None, [0.1, 0.0], 0.2);
    let residuals = problem.residuals(&[0.05, 0.0]).unwrap();
    let scale = residuals.scale;
    assert!((scale.displacement - 0.2).abs() < 1e-15);
    assert!((scale.force - 0.1).abs() < 1e-15); // U / max diag = 0.2 / 2 > |r| = 0.05
    assert_only(&residuals, "wrong-sign pressure", 0.05 / scale.force);
}

#[test]
fn residual_detects_cone_violation() {
    // Tresca s = 0.05 with |rT| = 0.08 and uT = 0 (so the natural map sees only the excess).
    let problem = one_point(FrictionLaw::Tresca { threshold: vec![0.05] }, [1.0, 0.3], 0.2);
    // Choose r with uN = g0 and uT = 0: that is the stick solution, with rT = -0.2/1.75 ≈ -0.114.
    let r = [-0.65 / 1.75, -0.2 / 1.75];
    let residuals = problem.residuals(&r).unwrap();
    let excess = 0.2 / 1.75 - 0.05;
    assert!(residuals.max_cone_violation > 0.0);
    // The natural map also reports the excess (|rT - clamp(rT)|), which is the same number.
    assert!((residuals.max_cone_violation - excess / residuals.scale.force).abs() < 1e-12);
    assert!((residuals.tangential_complementarity - residuals.max_cone_violation).abs() < 1e-12);
    assert!(residuals.max_penetration < 1e-14 && residuals.normal_complementarity < 1e-14);
    assert!(residuals.max_wrong_sign_pressure == 0.0);
    // Coulomb: |rT| > mu |rN|.
    let coulomb = one_point(FrictionLaw::Coulomb { mu: vec![0.1] }, [1.0, 0.3], 0.2);
    let residuals = coulomb.residuals(&r).unwrap();
    let excess = 0.2 / 1.75 - 0.1 * 0.65 / 1.75;
    assert!((residuals.max_cone_violation - excess / residuals.scale.force).abs() < 1e-12);
    assert_eq!(residuals.worst_component(), "cone violation");
}

#[test]
fn residual_detects_normal_complementarity() {
    // rN = -0.05 on a point that is not touching: uN = -0.1 + 0.1 = 0 < g0 = 0.2.
    let problem = one_point(FrictionLaw::None, [0.1, 0.0], 0.2);
    let residuals = problem.residuals(&[-0.05, 0.0]).unwrap();
    let scale = residuals.scale;
    let expected = (0.05 / scale.force).min(0.2 / scale.displacement);
    assert_only(&residuals, "normal complementarity", expected);
}

#[test]
fn residual_detects_sticking_point_that_moves() {
    // Tresca s = 1 (large): rT = 0 strictly inside, but uT = 0.5 (-0.4) + 0.3 = 0.1 ≠ 0.
    let problem = one_point(FrictionLaw::Tresca { threshold: vec![1.0] }, [1.0, 0.3], 0.2);
    let residuals = problem.residuals(&[-0.4, 0.0]).unwrap();
    let scale = residuals.scale;
    // |0 - clamp(0 - c 0.1, -1, 1)| / F = 0.1 / U  (c 0.1 < 1 here).
    assert!((scale.force / scale.displacement) * 0.1 < 1.0);
    assert_only(&residuals, "tangential complementarity", 0.1 / scale.displacement);
}

#[test]
fn residual_detects_slip_in_the_wrong_direction() {
    // Tresca s = 0.05, rT = +0.05 on the threshold, but then uT = 0.5 rN + 0.05 + 0.3 > 0:
    // the point slips along its friction force.
    let problem = one_point(FrictionLaw::Tresca { threshold: vec![0.05] }, [1.0, 0.3], 0.2);
    let rn = (-0.8 - 0.5 * 0.05) / 2.0; // uN = g0
    let residuals = problem.residuals(&[rn, 0.05]).unwrap();
    let ut = 0.5 * rn + 0.05 + 0.3;
    assert!(ut > 0.0);
    let scale = residuals.scale;
    let c = scale.force / scale.displacement;
    let expected = (0.05 - (0.05 - c * ut).clamp(-0.05, 0.05)).abs() / scale.force;
    assert_only(&residuals, "tangential complementarity", expected);
    // The correct answer has none of it.
    let good = problem.residuals(&[-0.3875, -0.05]).unwrap();
    assert!(good.is_acceptable(1e-14), "{good}");
}

#[test]
fn residual_reports_wrong_lengths_and_non_finite_forces() {
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    assert!(matches!(problem.residuals(&[0.0]), Err(Error::Usage(m)) if m.contains("expected 2")));
    assert!(matches!(problem.residuals(&[f64::NAN, 0.0]), Err(Error::Usage(m)) if m.contains("contact point 0")));
}

// ---------------------------------------------------------------------------------------------
// Semi-smooth Newton: size independence, cycling, history
// ---------------------------------------------------------------------------------------------

#[test]
fn newton_iterations_do_not_grow_with_the_size() {
    let mut table = Vec::new();
    for m in [10, 25, 50, 100, 200, 400] {
        let (w, xs) = layer_delassus(m, 0.5, 0.3);
        let cases = [
            ("frictionless", FrictionLaw::None, 0.08, 0.0),
            ("Tresca", FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] }, 0.08, 0.01),
            ("Coulomb 0.3", FrictionLaw::Coulomb { mu: vec![0.3; m] }, 0.08, 0.03),
            ("Coulomb 1", FrictionLaw::Coulomb { mu: vec![1.0; m] }, 0.08, 0.03),
        ];
        for (name, friction, depth, shift) in cases {
            let problem = indentation_with(w.clone(), &xs, friction, depth, shift);
            let solution = solve(&problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
            let (open, _, _) = counts(&solution);
            assert!(open > m / 4 && open < 3 * m / 4, "{name}, m = {m}: contact zone is a real fraction");
            assert!(solution.notes.iter().all(|n| !n.contains("fallback")), "{name}, m = {m}: {:?}", solution.notes);
            table.push((m, name, solution.iterations));
            assert!(solution.iterations <= 12, "{name}, m = {m}: {} Newton steps", solution.iterations);
        }
    }
    // From 10 to 400 points (40× the unknowns) the count grows by a few steps at most.
    for name in ["frictionless", "Tresca", "Coulomb 0.3", "Coulomb 1"] {
        let small = table.iter().find(|(m, n, _)| *m == 10 && *n == name).unwrap().2;
        let large = table.iter().find(|(m, n, _)| *m == 400 && *n == name).unwrap().2;
        assert!(large <= small + 8, "{name}: {small} → {large} Newton steps ({table:?})");
    }
}

/// μ = 10 with a large tangential drive: the undamped active set ping-pongs between two
/// contact sets (one edge point in and out), neither of them the solution.
fn cycling_problem() -> CondensedProblem<'static> {
    let m = 20;
    let (w, xs) = layer_delassus(m, 0.5, 0.3);
    indentation_with(w, &xs, FrictionLaw::Coulomb { mu: vec![10.0; m] }, 0.02, 0.1)
}

#[test]
fn undamped_newton_cycles_and_says_so() {
    let problem = cycling_problem();
    let raw = SolverSettings { newton_globalization: false, ..tight() };
    match solve(&problem, &ContactSolver::SemismoothNewton, &raw) {
        Err(Error::SolverDiverged { solver, reason, iterations, .. }) => {
            assert!(solver.contains("semi-smooth Newton"), "{solver}");
            assert!(reason.contains("active-set cycle"), "{reason}");
            assert!(iterations < 10);
        }
        other => panic!("expected a cycling failure, got {other:?}"),
    }
}

#[test]
fn globalized_newton_breaks_the_cycle() {
    let problem = cycling_problem();
    let solution = solve(&problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    assert!(solution.notes.iter().any(|n| n.contains("active-set cycle")), "{:?}", solution.notes);
    assert!(solution.notes.iter().any(|n| n.contains("steps capped")), "{:?}", solution.notes);
    assert!(solution.notes.iter().any(|n| n.contains("fallback")), "{:?}", solution.notes);
    assert!(solution.solver.contains("then projected relaxation"), "{}", solution.solver);
    for other in [ContactSolver::ProjectedRelaxation { omega: 1.0 }, ContactSolver::DPana] {
        let reference = solve(&problem, &other, &tight()).unwrap();
        assert!(max_relative_difference(&solution.force, &reference.force) < 1e-6);
    }
    let (open, stick, _) = counts(&solution);
    assert!(stick > 0 && open > 0);
}

#[test]
fn history_records_residuals_and_status_changes() {
    let m = 40;
    let problem = indentation(m, FrictionLaw::Coulomb { mu: vec![0.3; m] }, 0.08, 0.03);
    for solver in
        [ContactSolver::SemismoothNewton, ContactSolver::ProjectedRelaxation { omega: 1.0 }, ContactSolver::DPana]
    {
        let solution = solve(&problem, &solver, &tight()).unwrap();
        assert_eq!(solution.history.len(), solution.iterations, "{}", solver.name());
        let changes: usize = solution.history.iter().map(|h| h.status_changes).sum();
        assert!(changes > 0, "{}: starting from zero force, statuses must change", solver.name());
        let last = solution.history.last().unwrap();
        assert_eq!(last.status_changes, 0, "{}", solver.name());
        assert!(last.residual <= 1e-11);
        assert_eq!(last.residual, solution.residuals.worst());
    }
}

#[test]
fn newton_from_the_solution_takes_no_step() {
    let m = 30;
    let problem = indentation(m, FrictionLaw::Coulomb { mu: vec![0.3; m] }, 0.08, 0.03);
    let solution = solve(&problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    let warm = SolverSettings { initial_force: Some(solution.force.clone()), ..tight() };
    let again = solve(&problem, &ContactSolver::SemismoothNewton, &warm).unwrap();
    assert_eq!(again.iterations, 0);
    assert_eq!(again.force, solution.force);
}

// ---------------------------------------------------------------------------------------------
// Failures are reported, never hidden
// ---------------------------------------------------------------------------------------------

#[test]
fn iteration_limit_gives_solver_diverged() {
    let m = 40;
    let problem = indentation(m, FrictionLaw::Coulomb { mu: vec![0.3; m] }, 0.08, 0.03);
    let one = SolverSettings { max_iterations: 1, ..tight() };
    for solver in all_solvers() {
        match solve(&problem, &solver, &one) {
            Err(Error::SolverDiverged { solver: name, reason, iterations, residual, tried }) => {
                let short = solver.name();
                let short = short.split(' ').next().unwrap();
                assert!(name.contains(short), "{name} / {short}");
                assert!(name.contains("Coulomb"), "{name}");
                assert!(reason.contains("iteration limit"), "{}: {reason}", solver.name());
                assert!(iterations <= 1, "{}: {iterations}", solver.name());
                assert!(residual > 1e-11);
                assert!(!tried.is_empty());
            }
            other => panic!("{}: expected SolverDiverged, got {other:?}", solver.name()),
        }
    }
}

#[test]
fn dpana_reports_divergence_for_large_friction() {
    // ν = 0 (strong normal–tangential coupling) and mu = 3: the block relaxation stalls,
    // while the semi-smooth Newton method solves the problem.
    let m = 30;
    let (w, xs) = layer_delassus(m, 0.5, 0.0);
    let problem = indentation_with(w, &xs, FrictionLaw::Coulomb { mu: vec![3.0; m] }, 0.02, 0.1);
    match solve(&problem, &ContactSolver::DPana, &tight()) {
        Err(Error::SolverDiverged { solver, reason, tried, .. }) => {
            assert!(solver.contains("D-PANA"), "{solver}");
            assert!(reason.contains("stagnated") || reason.contains("grew"), "{reason}");
            assert!(tried.contains("mu = 3") && tried.contains("semi-smooth Newton"), "{tried}");
        }
        other => panic!("expected D-PANA to fail, got {other:?}"),
    }
    let solution = solve(&problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    assert!(solution.residuals.is_acceptable(1e-11));
    // The small-friction version of the same problem is fine for D-PANA.
    let (w, xs) = layer_delassus(m, 0.5, 0.0);
    let gentle = indentation_with(w, &xs, FrictionLaw::Coulomb { mu: vec![0.5; m] }, 0.02, 0.1);
    let a = solve(&gentle, &ContactSolver::DPana, &tight()).unwrap();
    let b = solve(&gentle, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    assert!(max_relative_difference(&a.force, &b.force) < 1e-6);
}

// ---------------------------------------------------------------------------------------------
// Implicit operator
// ---------------------------------------------------------------------------------------------

fn as_operator(problem: &CondensedProblem) -> CondensedProblem<'static> {
    let w = problem.delassus().as_dense().unwrap().clone();
    let size = w.nrows();
    let diagonal = w.diagonal().iter().copied().collect();
    let apply = move |x: &[f64], y: &mut [f64]| {
        let product = &w * nalgebra::DVector::from_column_slice(x);
        y.copy_from_slice(product.as_slice());
    };
    CondensedProblem::new(
        Delassus::Operator { size, apply: Box::new(apply), diagonal },
        problem.free_displacement().to_vec(),
        problem.gap().to_vec(),
        problem.friction().clone(),
        None,
    )
    .unwrap()
}

#[test]
fn operator_and_dense_give_the_same_answer() {
    let m = 40;
    for friction in [
        FrictionLaw::None,
        FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] },
        FrictionLaw::Coulomb { mu: vec![0.3; m] },
    ] {
        let dense = indentation(m, friction.clone(), 0.08, 0.03);
        let operator = as_operator(&dense);
        let reference = solve(&dense, &ContactSolver::SemismoothNewton, &tight()).unwrap();
        for solver in [
            ContactSolver::SemismoothNewton,
            ContactSolver::Uzawa { accelerated: true },
            ContactSolver::Uzawa { accelerated: false },
            ContactSolver::TrescaFixedPoint { inner: Box::new(ContactSolver::SemismoothNewton) },
        ] {
            let solution = solve(&operator, &solver, &tight()).unwrap_or_else(|e| panic!("{friction:?}: {e}"));
            let difference = max_relative_difference(&solution.force, &reference.force);
            assert!(difference < 1e-6, "{friction:?}, {}: {difference:e}", solver.name());
        }
        let newton = solve(&operator, &ContactSolver::SemismoothNewton, &tight()).unwrap();
        assert!(newton.notes.iter().any(|n| n.contains("Krylov")), "{:?}", newton.notes);
    }
}

#[test]
fn dense_only_solvers_refuse_an_operator() {
    let operator = as_operator(&indentation(10, FrictionLaw::Coulomb { mu: vec![0.3; 10] }, 0.08, 0.03));
    for solver in [ContactSolver::ProjectedRelaxation { omega: 1.0 }, ContactSolver::DPana] {
        match solve(&operator, &solver, &tight()) {
            Err(Error::Usage(message)) => assert!(message.contains("Delassus::Dense"), "{message}"),
            other => panic!("expected a usage error, got {other:?}"),
        }
    }
}

/// An implicit operator whose product borrows local data (a matrix, a counter in a `Cell`):
/// neither `'static` nor `Sync`, as a product by PETSc solves is. The problem lives as long as
/// what the product borrows; Uzawa and the semi-smooth Newton method solve it like the dense
/// one, the dense-only solvers refuse it naming those that work.
#[test]
fn borrowed_operator_solves_like_dense() {
    let m = 20;
    let dense = indentation(m, FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] }, 0.08, 0.03);
    let w = dense.delassus().as_dense().unwrap().clone();
    let products = std::cell::Cell::new(0usize);
    let apply = |x: &[f64], y: &mut [f64]| {
        products.set(products.get() + 1);
        let product = &w * nalgebra::DVector::from_column_slice(x);
        y.copy_from_slice(product.as_slice());
    };
    let diagonal = w.diagonal().iter().copied().collect();
    let borrowed = CondensedProblem::new(
        Delassus::Operator { size: w.nrows(), apply: Box::new(apply), diagonal },
        dense.free_displacement().to_vec(),
        dense.gap().to_vec(),
        dense.friction().clone(),
        None,
    )
    .unwrap();
    let reference = solve(&dense, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    for solver in [ContactSolver::Uzawa { accelerated: true }, ContactSolver::SemismoothNewton] {
        let before = products.get();
        let solution = solve(&borrowed, &solver, &tight()).unwrap();
        assert!(products.get() > before, "{} used no product", solver.name());
        let difference = max_relative_difference(&solution.force, &reference.force);
        assert!(difference < 1e-6, "{}: {difference:e}", solver.name());
    }
    match solve(&borrowed, &ContactSolver::ProjectedRelaxation { omega: 1.0 }, &tight()) {
        Err(Error::Usage(message)) => {
            assert!(message.contains("Uzawa") && message.contains("semi-smooth Newton"), "{message}")
        }
        other => panic!("expected a usage error, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------------

fn usage_message(result: Result<CondensedProblem, Error>) -> String {
    match result {
        Err(Error::Usage(message)) => message,
        other => panic!("expected Error::Usage, got {other:?}"),
    }
}

#[test]
fn invalid_problems_are_rejected_naming_the_entity() {
    let w = || {
        DMatrix::from_row_slice(4, 4, &[2.0, 0.3, 1.0, 0.2, 0.3, 1.0, 0.1, 0.4, 1.0, 0.1, 2.0, 0.3, 0.2, 0.4, 0.3, 1.0])
    };
    let free = vec![1.0, 0.0, 0.2, 0.0];
    let gap = vec![0.0, 0.5];
    let ok = CondensedProblem::new(Delassus::Dense(w()), free.clone(), gap.clone(), FrictionLaw::None, None);
    assert!(ok.is_ok());

    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(DMatrix::identity(3, 3)),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("3×3") && m.contains("4×4"), "{m}");
    let mut asymmetric = w();
    asymmetric[(0, 2)] = 1.5;
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(asymmetric),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("not symmetric") && m.contains("contact points 1 and 0"), "{m}");
    let mut indefinite = w();
    indefinite[(0, 2)] = 3.0;
    indefinite[(2, 0)] = 3.0;
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(indefinite),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("not positive definite"), "{m}");
    let mut bad_diagonal = w();
    bad_diagonal[(3, 3)] = -1.0;
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(bad_diagonal),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("contact point 1") && m.contains("tangential"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        vec![0.0, f64::NAN],
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("contact point 1") && m.contains("gap"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        vec![1.0, 0.0, 0.2],
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("free displacement has 3 entries"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        gap.clone(),
        FrictionLaw::Coulomb { mu: vec![0.3, -0.1] },
        None,
    ));
    assert!(m.contains("contact point 1") && m.contains("friction coefficient"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        gap.clone(),
        FrictionLaw::Tresca { threshold: vec![0.3] },
        None,
    ));
    assert!(m.contains("Tresca threshold has 1 entries"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        Some(vec![1.0, 0.0]),
    ));
    assert!(m.contains("contact point 1") && m.contains("weight"), "{m}");
    let m = usage_message(CondensedProblem::new(Delassus::Dense(w()), free.clone(), vec![], FrictionLaw::None, None));
    assert!(m.contains("no contact point"), "{m}");
    let asymmetric_operator = Delassus::Operator {
        size: 4,
        apply: Box::new(|x: &[f64], y: &mut [f64]| {
            for i in 0..4 {
                y[i] = 2.0 * x[i] + if i == 0 { x[3] } else { 0.0 };
            }
        }),
        diagonal: vec![2.0; 4],
    };
    let m =
        usage_message(CondensedProblem::new(asymmetric_operator, free.clone(), gap.clone(), FrictionLaw::None, None));
    assert!(m.contains("not symmetric"), "{m}");
}

#[test]
fn settings_are_validated() {
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    let check =
        |solver: ContactSolver, settings: SolverSettings, needle: &str| match solve(&problem, &solver, &settings) {
            Err(Error::Usage(message)) => assert!(message.contains(needle), "{message}"),
            other => panic!("expected a usage error, got {other:?}"),
        };
    check(ContactSolver::ProjectedRelaxation { omega: 2.5 }, tight(), "omega");
    check(ContactSolver::SemismoothNewton, SolverSettings { tolerance: 0.0, ..tight() }, "tolerance");
    check(ContactSolver::SemismoothNewton, SolverSettings { max_iterations: 0, ..tight() }, "max_iterations");
    check(
        ContactSolver::SemismoothNewton,
        SolverSettings { initial_force: Some(vec![0.0]), ..tight() },
        "initial force",
    );
}

#[test]
fn pressure_divides_by_the_weights() {
    let w = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
    let problem =
        CondensedProblem::new(Delassus::Dense(w), vec![1.0, 0.3], vec![0.2], FrictionLaw::None, Some(vec![0.5]))
            .unwrap();
    let solution = solve(&problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    let pressure = problem.pressure(&solution.force).unwrap();
    assert!((pressure[0] + 0.8).abs() < 1e-12);
    assert_eq!(pressure[1], 0.0);
    let displacement = problem.displacement(&solution.force).unwrap();
    assert_eq!(displacement, solution.displacement);
    assert_eq!(problem.status(&solution.force).unwrap(), solution.status);
}
