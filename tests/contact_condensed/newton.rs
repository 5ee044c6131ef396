//! Semi-smooth Newton: iterations independent of the size, cycling, history.

use crate::{counts, indentation, indentation_with, layer_delassus, max_relative_difference, tight};
use signorini::contact::{solve, CondensedProblem, ContactSolver, FrictionLaw, SolverSettings};
use signorini::Error;

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
