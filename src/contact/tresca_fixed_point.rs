//! Coulomb friction as a fixed point on Tresca thresholds.
//!
//! The classical existence proof and algorithm for the static Coulomb problem (J. Nečas,
//! J. Jarušek, J. Haslinger, "On the solution of the variational inequality to the Signorini
//! problem with small friction", Boll. Unione Mat. Ital. 17-B, 1980; J. Haslinger, I.
//! Hlaváček, J. Nečas, "Numerical methods for unilateral problems in solid mechanics",
//! Handbook of Numerical Analysis IV, 1996): the map
//!
//! ```text
//!   s  ↦  r(s) = solution of the Tresca problem with thresholds s   ↦   μ |rN(s)|
//! ```
//!
//! is a contraction for small μ; its fixed point solves Coulomb. Outer iteration `k`:
//! `s_k = μ |rN_{k−1}|`, solve the Tresca problem with the inner solver (warm-started from the
//! last force, to a tolerance ten times tighter), and stop when the residuals of the COULOMB
//! problem are within the tolerance. No progress (0.1 %) of the best residual in 30 outer
//! iterations, or a 1e3-fold growth, is reported as non-convergence.
//!
//! For frictionless or Tresca problems the outer loop is void: the inner solver is run once.
use super::{
    classify, residuals, run_solver, update_states, CondensedProblem, ContactSolver, FrictionLaw, IterationRecord, Run,
    SolverSettings,
};
use crate::error::Result;

const STAGNATION_WINDOW: usize = 30;

pub(crate) fn run(
    problem: &CondensedProblem,
    inner: &ContactSolver,
    settings: &SolverSettings,
    initial: Vec<f64>,
) -> Result<Run> {
    let name = ContactSolver::TrescaFixedPoint { inner: Box::new(inner.clone()) }.name();
    let mu = match problem.friction() {
        FrictionLaw::Coulomb { mu } => mu.clone(),
        _ => {
            let mut run = run_solver(problem, inner, settings, initial)?;
            run.notes.push(format!("{name}: not a Coulomb problem, inner solver used directly"));
            return Ok(run);
        }
    };
    let m = problem.points();
    let tried = format!(
        "{name}: outer loop s = mu |rN| on Tresca problems, up to {} outer iterations",
        settings.max_iterations
    );
    let inner_settings =
        SolverSettings { tolerance: 0.1 * settings.tolerance, initial_force: None, ..settings.clone() };
    let mut r = initial;
    let mut u = problem.displacement_unchecked(&r);
    let mut states = classify(problem, &r, &u);
    let mut history = Vec::new();
    let mut notes = Vec::new();
    let mut inner_iterations = 0;
    let mut stagnation = super::Stagnation::new(STAGNATION_WINDOW);
    let mut first = None;
    for k in 1..=settings.max_iterations {
        let threshold: Vec<f64> = (0..m).map(|i| mu[i] * (-r[2 * i]).max(0.0)).collect();
        let tresca = problem.with_friction(FrictionLaw::Tresca { threshold })?;
        let mut start = r.clone();
        tresca.project_admissible(&mut start);
        let run = run_solver(&tresca, inner, &inner_settings, start)?;
        inner_iterations += run.iterations;
        if let Some(reason) = run.failure {
            return Ok(Run {
                force: run.force,
                iterations: k,
                history,
                notes,
                failure: Some(format!("the Tresca problem of outer iteration {k} was not solved: {reason}")),
                tried: format!("{tried}; inner: {}", run.tried),
                solver: name,
            });
        }
        r = run.force;
        u = problem.displacement_unchecked(&r);
        let status_changes = update_states(problem, &r, &u, &mut states);
        let residual = residuals::compute(problem, &r, &u).worst();
        history.push(IterationRecord { residual, status_changes });
        if residual <= settings.tolerance {
            notes.push(format!("{inner_iterations} inner iterations in {k} Tresca solves"));
            return Ok(Run { force: r, iterations: k, history, notes, failure: None, tried, solver: name });
        }
        let first = *first.get_or_insert(residual);
        let failure = if !residual.is_finite() || residual > 1e3 * f64::max(first, settings.tolerance) {
            Some(format!("the residual grew from {first:.2e} to {residual:.2e}: the threshold map does not contract"))
        } else if stagnation.stalled(residual, k) {
            Some(format!(
                "the residual stagnated at {:.2e} (no 0.1 % progress in {STAGNATION_WINDOW} \
                 outer iterations): the threshold map does not contract (friction too large?)",
                stagnation.best()
            ))
        } else {
            None
        };
        if failure.is_some() {
            notes.push(format!("{inner_iterations} inner iterations"));
            return Ok(Run { force: r, iterations: k, history, notes, failure, tried, solver: name });
        }
    }
    Ok(Run {
        force: r,
        iterations: settings.max_iterations,
        history,
        notes,
        failure: Some(format!("iteration limit of {} outer iterations reached", settings.max_iterations)),
        tried,
        solver: name,
    })
}
