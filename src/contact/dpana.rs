//! D-PANA block relaxation (P. Bisegna, F. Lebon, F. Maceri, "D-PANA: a convergent
//! block-relaxation solution method for the discretized dual formulation of the
//! Signorini–Coulomb contact problem", C. R. Acad. Sci. Paris, Série I, 333, 2001, 1053–1058).
//!
//! The unknowns are split into the normal block `rN` and the tangential block `rT`, and two
//! convex sub-problems alternate (outer iteration `k`):
//!
//! ```text
//!   contact (rT frozen):   minimize ½ rNᵀ W_NN rN − rNᵀ (g0 − u_free,N − W_NT rT)
//!                          over rN ≤ 0                                        (Signorini)
//!   friction (rN frozen):  s = μ |rN|   (Coulomb; Tresca: the given thresholds)
//!                          minimize ½ rTᵀ W_TT rT − rTᵀ (−u_free,T − W_TN rN)
//!                          over −s ≤ rT ≤ s                                    (Tresca box)
//! ```
//!
//! Each sub-problem is a box-constrained QP solved by the primal–dual active set method with a
//! projected Gauss–Seidel fallback (`box_qp.rs`), to a tolerance ten times tighter than the
//! outer one. The outer loop stops on the residuals of the full problem.
//!
//! For Tresca (and frictionless) problems this is block coordinate descent on the strictly
//! convex energy `J` and converges for any data. For Coulomb it is a fixed point whose
//! contraction needs a small friction coefficient (the cited paper proves convergence for μ
//! below a bound depending on `W`); a residual that stops decreasing (no 0.1 % progress of
//! the best residual in 50 outer iterations) or grows 1e3-fold is reported as
//! [`Error::SolverDiverged`](crate::error::Error::SolverDiverged).
use nalgebra::DMatrix;

use super::{
    box_qp, classify, needs_dense, residuals, update_states, CondensedProblem, FrictionLaw, IterationRecord, Run,
    SolverSettings,
};
use crate::error::Result;

/// Outer iterations without a 0.1 % improvement of the best residual before giving up.
const STAGNATION_WINDOW: usize = 50;

pub(crate) fn run(problem: &CondensedProblem, settings: &SolverSettings, initial: Vec<f64>) -> Result<Run> {
    let name = super::ContactSolver::DPana.name();
    let w = problem.delassus().as_dense().ok_or_else(|| needs_dense(&name))?;
    let m = problem.points();
    let sub = |row_offset: usize, col_offset: usize| {
        DMatrix::from_fn(m, m, |i, j| w[(2 * i + row_offset, 2 * j + col_offset)])
    };
    let w_nn = sub(0, 0);
    let w_nt = sub(0, 1); // (W_NT)_ij = W[N_i, T_j]
    let w_tt = sub(1, 1);
    let frictional = !matches!(problem.friction(), FrictionLaw::None);
    let max_mu = match problem.friction() {
        FrictionLaw::Coulomb { mu } => mu.iter().copied().fold(0.0, f64::max),
        _ => 0.0,
    };
    let tried = format!(
        "{name}: alternating contact-only and friction-only box QPs (primal–dual active set, \
         projected Gauss–Seidel fallback), up to {} outer iterations{}",
        settings.max_iterations,
        if max_mu > 0.0 {
            format!(
                "; D-PANA converges for Coulomb only for small friction coefficients (here up to \
                 mu = {max_mu}): use the semi-smooth Newton method"
            )
        } else {
            String::new()
        }
    );
    let inner_tolerance = 0.1 * settings.tolerance;
    let max_sweeps = settings.max_iterations.max(1000);
    let mut r_n: Vec<f64> = (0..m).map(|i| initial[2 * i]).collect();
    let mut r_t: Vec<f64> = (0..m).map(|i| initial[2 * i + 1]).collect();
    let mut r = initial;
    let mut u = problem.displacement_unchecked(&r);
    let mut states = classify(problem, &r, &u);
    let mut history = Vec::new();
    let mut notes = Vec::new();
    let mut stagnation = super::Stagnation::new(STAGNATION_WINDOW);
    let mut first_residual = None;
    let mut inner_fallbacks = 0;
    let lower_n = vec![f64::NEG_INFINITY; m];
    let upper_n = vec![0.0; m];
    let run = |force: Vec<f64>, iterations, history, notes: Vec<String>, failure| Run {
        force,
        iterations,
        history,
        notes,
        failure,
        tried: tried.clone(),
        solver: name.clone(),
    };
    for k in 1..=settings.max_iterations {
        // Contact problem, tangential forces frozen.
        let b_n: Vec<f64> = (0..m)
            .map(|i| {
                let coupling: f64 = (0..m).map(|j| w_nt[(i, j)] * r_t[j]).sum();
                problem.gap()[i] - problem.free_displacement()[2 * i] - coupling
            })
            .collect();
        let normal = box_qp::solve(&w_nn, &b_n, &lower_n, &upper_n, &r_n, inner_tolerance, max_sweeps);
        inner_fallbacks += usize::from(normal.gauss_seidel_sweeps > 0);
        if !normal.converged {
            return Ok(run(
                r,
                k,
                history,
                notes,
                Some(format!(
                    "the contact sub-problem of outer iteration {k} did not converge (relative \
                     residual {:.2e} after {} active-set iterations and {} Gauss–Seidel sweeps)",
                    normal.residual, normal.active_set_iterations, normal.gauss_seidel_sweeps
                )),
            ));
        }
        r_n = normal.x;
        // Friction problem, normal forces frozen.
        if frictional {
            let thresholds: Vec<f64> = (0..m)
                .map(|i| if problem.has_friction_at(i) { problem.threshold_at(i, r_n[i]) } else { 0.0 })
                .collect();
            let lower_t: Vec<f64> = thresholds.iter().map(|s| -s).collect();
            let b_t: Vec<f64> = (0..m)
                .map(|i| {
                    let coupling: f64 = (0..m).map(|j| w_nt[(j, i)] * r_n[j]).sum();
                    -problem.free_displacement()[2 * i + 1] - coupling
                })
                .collect();
            let tangential = box_qp::solve(&w_tt, &b_t, &lower_t, &thresholds, &r_t, inner_tolerance, max_sweeps);
            inner_fallbacks += usize::from(tangential.gauss_seidel_sweeps > 0);
            if !tangential.converged {
                return Ok(run(
                    r,
                    k,
                    history,
                    notes,
                    Some(format!(
                        "the friction sub-problem of outer iteration {k} did not converge \
                         (relative residual {:.2e})",
                        tangential.residual
                    )),
                ));
            }
            r_t = tangential.x;
            // Points without friction keep exactly rT = 0 (their box is [0, 0]).
        }
        for i in 0..m {
            r[2 * i] = r_n[i];
            r[2 * i + 1] = r_t[i];
        }
        u = problem.displacement_unchecked(&r);
        let status_changes = update_states(problem, &r, &u, &mut states);
        let residual = residuals::compute(problem, &r, &u).worst();
        history.push(IterationRecord { residual, status_changes });
        if inner_fallbacks > 0 && !notes.iter().any(|n: &String| n.starts_with("box QP")) {
            notes.push("box QP: the active-set method cycled, projected Gauss–Seidel finished it".into());
        }
        if residual <= settings.tolerance {
            return Ok(run(r, k, history, notes, None));
        }
        let first = *first_residual.get_or_insert(residual);
        if !residual.is_finite() || residual > 1e3 * first.max(settings.tolerance) {
            return Ok(run(
                r,
                k,
                history,
                notes,
                Some(format!(
                    "the residual grew from {first:.2e} to {residual:.2e}: the block relaxation \
                     diverges (friction coefficient too large for D-PANA)"
                )),
            ));
        }
        if stagnation.stalled(residual, k) {
            let best = stagnation.best();
            return Ok(run(
                r,
                k,
                history,
                notes,
                Some(format!(
                    "the residual stagnated at {best:.2e} (no 0.1 % progress in \
                     {STAGNATION_WINDOW} outer iterations): the block relaxation does not \
                     contract (friction coefficient too large for D-PANA?)"
                )),
            ));
        }
    }
    Ok(run(
        r,
        settings.max_iterations,
        history,
        notes,
        Some(format!("iteration limit of {} outer iterations reached", settings.max_iterations)),
    ))
}
