//! Every fallback of the condensed solvers forced through its inputs, and its answer compared
//! with the normal route's (forces to 1e-8 relative, the same statuses):
//!
//! - the semi-smooth Newton's fallback to projected relaxation (src/contact/semismooth_newton.rs)
//!   on each trigger other than active-set cycles (tested in newton.rs): a singular Newton
//!   system, a failed line search, a non-finite iterate, no progress. The triggers are forced
//!   through `SolverSettings::dense_solver` (the solver of each step's dense system, replaced by
//!   one that fails, points uphill or is slow) and `initial_force`;
//! - D-PANA's inner box QP (src/contact/box_qp.rs): its primal–dual active set method cycles on a
//!   normal block that is not an M-matrix, and projected Gauss–Seidel finishes the sub-problem.

use std::sync::{Arc, Mutex};

use crate::{counts, layer_delassus, max_relative_difference, tight};
use nalgebra::{DMatrix, DVector};
use signorini::contact::{
    solve, CondensedProblem, ContactSolution, ContactSolver, Delassus, DenseSolver, FrictionLaw, SolverSettings,
};

/// A flat rigid punch pressed into the layer (gap 0, every point pushed down by 0.05 and
/// sideways by `shift`): every point is closed from the first Newton step on. Frictionless
/// with `mu = 0`, else Coulomb.
fn flat_punch(mu: f64, shift: f64) -> CondensedProblem<'static> {
    let m = 16;
    let (w, _) = layer_delassus(m, 0.5, 0.3);
    let free: Vec<f64> = (0..m).flat_map(|_| [0.05, shift]).collect();
    let friction = if mu == 0.0 { FrictionLaw::None } else { FrictionLaw::Coulomb { mu: vec![mu; m] } };
    CondensedProblem::new(Delassus::Dense(w), free, vec![0.0; m], friction, None).unwrap()
}

/// The Coulomb punch: some points stick, some slip (asserted where it is used).
fn coulomb_punch() -> CondensedProblem<'static> {
    let problem = flat_punch(0.3, 0.01);
    let (open, stick, slip) = counts(&reference(&problem));
    assert!(open == 0 && stick > 0 && slip > 0, "{open} open, {stick} stick, {slip} slip");
    problem
}

/// The normal route: the semi-smooth Newton method without any fallback.
fn reference(problem: &CondensedProblem) -> ContactSolution {
    let solution = solve(problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    assert!(solution.notes.iter().all(|n| !n.contains("fallback")), "{:?}", solution.notes);
    solution
}

/// The fallback answered, said why (`reason` in its notes), and gave the normal route's answer.
fn assert_fell_back_to_the_same_answer(problem: &CondensedProblem, settings: &SolverSettings, reason: &str) {
    let solution = solve(problem, &ContactSolver::SemismoothNewton, settings).unwrap();
    let notes = solution.notes.join("; ");
    assert!(notes.contains(reason) && notes.contains("fallback to projected relaxation"), "{notes}");
    assert!(solution.solver.contains("then projected relaxation"), "{}", solution.solver);
    let normal = reference(problem);
    let difference = max_relative_difference(&solution.force, &normal.force);
    assert!(difference < 1e-8, "{reason}: the fallback's forces differ from Newton's by {difference:e}");
    assert_eq!(solution.status, normal.status, "{reason}: statuses");
    assert_eq!(counts(&solution), counts(&normal));
    assert!(solution.residuals.is_acceptable(1e-11), "{}", solution.residuals);
}

/// LU of the step's dense system (the normal route's answer).
fn exact(a: &DMatrix<f64>, b: &DVector<f64>) -> Option<DVector<f64>> {
    a.clone().lu().solve(b)
}

fn dense_solver(
    f: impl Fn(&DMatrix<f64>, &DVector<f64>) -> Option<DVector<f64>> + Send + Sync + 'static,
) -> DenseSolver {
    DenseSolver(Arc::new(f))
}

#[test]
fn newton_singular_step_falls_back_to_relaxation() {
    let problem = coulomb_punch();
    let settings = SolverSettings { dense_solver: Some(dense_solver(|_, _| None)), ..tight() };
    assert_fell_back_to_the_same_answer(&problem, &settings, "is singular");
}

#[test]
fn newton_line_search_failure_falls_back_to_relaxation() {
    // Each step's target reflected through zero: from r = 0 the step points uphill (tension
    // where the punch presses), no step length decreases the merit function.
    let problem = coulomb_punch();
    let uphill = dense_solver(|a, b| exact(a, b).map(|x| -x));
    let settings = SolverSettings { dense_solver: Some(uphill), ..tight() };
    assert_fell_back_to_the_same_answer(&problem, &settings, "the line search failed at Newton step 1");
}

#[test]
fn newton_non_finite_iterate_falls_back_to_relaxation() {
    // An admissible but enormous starting force: W r overflows, the residual is not finite;
    // the fallback restarts from zero.
    let problem = coulomb_punch();
    let start: Vec<f64> = (0..problem.points()).flat_map(|_| [-f64::MAX, 0.0]).collect();
    let settings = SolverSettings { initial_force: Some(start), ..tight() };
    assert_fell_back_to_the_same_answer(&problem, &settings, "the iterate became non-finite");
}

#[test]
fn newton_without_progress_falls_back_to_relaxation() {
    // Every step goes 2 % of the way to the Newton target (the unknowns keep the same meaning
    // throughout: every point stays closed): the merit falls (the steps are accepted), but the
    // residual does not halve within 20 steps. Frictionless: the statuses cannot change.
    let problem = flat_punch(0.0, 0.0);
    let previous: Mutex<Option<DVector<f64>>> = Mutex::new(None);
    let slow = dense_solver(move |a, b| {
        let x = exact(a, b)?;
        let mut previous = previous.lock().unwrap();
        let from = previous.clone().filter(|p| p.len() == x.len()).unwrap_or_else(|| DVector::zeros(x.len()));
        let next = &from + (&x - &from) * 0.02;
        *previous = Some(next.clone());
        Some(next)
    });
    let settings = SolverSettings { dense_solver: Some(slow), ..tight() };
    assert_fell_back_to_the_same_answer(&problem, &settings, "no progress in 20 Newton steps");
}

/// Three points whose normal block A is positive definite but not an M-matrix: the primal–dual
/// active set method on `min ½ rᵀ A r − rᵀ b, r ≤ 0` cycles from r = 0 (found by a search over
/// random 3 × 3 matrices; the sets of iterations 1 and 3 are equal), and projected
/// Gauss–Seidel finishes the sub-problem.
#[test]
fn dpana_box_qp_cycle_is_finished_by_projected_gauss_seidel() {
    let a = [[3.18, 3.42, -3.23], [3.42, 5.78, -6.11], [-3.23, -6.11, 6.82]];
    let b = [0.05, 1.55, -1.76];
    let m = 3;
    let w = DMatrix::from_fn(2 * m, 2 * m, |i, j| match (i % 2, j % 2) {
        (0, 0) => a[i / 2][j / 2],
        (1, 1) if i == j => 1.0,
        _ => 0.0,
    });
    // The normal sub-problem's right-hand side is gap − free normal displacement.
    let free: Vec<f64> = b.iter().flat_map(|bi| [-bi, 0.0]).collect();
    let problem = CondensedProblem::new(Delassus::Dense(w), free, vec![0.0; m], FrictionLaw::None, None).unwrap();
    let solution = solve(&problem, &ContactSolver::DPana, &tight()).unwrap();
    assert!(
        solution.notes.iter().any(|n| n.contains("box QP: the active-set method cycled, projected Gauss–Seidel")),
        "{:?}",
        solution.notes
    );
    let normal = reference(&problem);
    let difference = max_relative_difference(&solution.force, &normal.force);
    assert!(difference < 1e-8, "D-PANA with projected Gauss–Seidel differs from Newton by {difference:e}");
    assert_eq!(solution.status, normal.status);
    // Not a trivial answer: some points press, some are open.
    let (open, _, _) = counts(&solution);
    assert!(open > 0 && open < m, "{:?}", solution.force);
}
