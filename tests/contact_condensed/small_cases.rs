//! Exact small cases: one and two contact points, every solver, every friction law.

use crate::{all_solvers, max_relative_difference, one_point, tight};
use nalgebra::DMatrix;
use signorini::contact::{solve, CondensedProblem, ContactSolver, Delassus, FrictionLaw, PointStatus};

// ---------------------------------------------------------------------------------------------
// Exact small cases
// ---------------------------------------------------------------------------------------------

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
