//! Failures are reported, never hidden: iteration limits and divergence.

use crate::{all_solvers, indentation, indentation_with, layer_delassus, max_relative_difference, tight};
use signorini::contact::{solve, ContactSolver, FrictionLaw, SolverSettings};
use signorini::Error;

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
