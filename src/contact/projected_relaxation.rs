//! Projected relaxation: block Gauss–Seidel / SOR sweeps over the contact points.
//!
//! This is the non-smooth Gauss–Seidel method of Moreau and Jean (J. J. Moreau, "Numerical
//! aspects of the sweeping process", Comput. Methods Appl. Mech. Engrg. 177, 1999; M. Jean,
//! "The non-smooth contact dynamics method", same volume, 235–257), the talk's "relaxation
//! projetée". For each point `i` in turn, with the other points' forces frozen,
//!
//! ```text
//!   u_i = W_ii r_i + q_i,   q_i = u_free,i + Σ_{j≠i} W_ij r_j       (W_ii: the 2×2 block)
//! ```
//!
//! and the local law (Signorini + friction) is solved EXACTLY for `r_i`, coupling `W_NT`
//! included:
//!
//! - frictionless (or zero threshold): `rN = P_N((g0 − qN) / W_NN) = min(·, 0)`, `rT = 0`;
//! - Tresca: the 2D box QP `min ½ rᵀ W_ii r − rᵀ b`, `b = (g0 − qN, −qT)`, over
//!   `rN ≤ 0, |rT| ≤ s`: the unconstrained minimizer if admissible, otherwise the best of the
//!   edge minimizers (`rN = 0` with `rT = P_T(b_T / W_TT)`; `rT = ±s` with
//!   `rN = P_N((b_N ∓ W_NT s) / W_NN)`) — exact because the objective is convex;
//! - Coulomb: enumeration of the four cases — open (`r = 0`, admissible if `qN ≤ g0`);
//!   stick (`r = W_ii⁻¹ b`, admissible if `|rT| ≤ −μ rN`); slip with `rT = −σ μ rN`,
//!   `σ = ±1`, where `uN = g0` gives `rN = (g0 − qN) / (W_NN − σ μ W_NT)`, admissible if
//!   that denominator is positive, `rN ≤ 0` and `σ uT ≤ 0`. The first admissible case is
//!   taken (for small μ exactly one is); if round-off rejects all, the least violating one.
//!
//! SOR (`omega ≠ 1`): `r_i ← P(r_i + ω (r̂_i − r_i))` with `r̂_i` the local solution and `P`
//! the projection onto the admissible set of the point. The displacements `u = W r + u_free`
//! are updated incrementally after each point (one column pair of `W`, O(m) per point) and
//! recomputed from scratch before convergence is declared. Needs [`Delassus::Dense`].
//!
//! For Coulomb with a large μ the sweeps can oscillate (the local maps stop contracting):
//! 500 sweeps without a 0.1 % improvement of the best residual end the iteration with
//! [`Error::SolverDiverged`](crate::error::Error::SolverDiverged).
//!
//! [`Delassus::Dense`]: super::Delassus::Dense
use super::{
    classify, needs_dense, update_states, CondensedProblem, FrictionLaw, IterationRecord, Run, SolverSettings,
};
use crate::error::Result;

/// The 2×2 block of a point: `[[nn, nt], [nt, tt]]`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LocalBlock {
    pub nn: f64,
    pub nt: f64,
    pub tt: f64,
}

/// Local frictionless solve.
fn local_frictionless(block: LocalBlock, b_normal: f64) -> f64 {
    (b_normal / block.nn).min(0.0)
}

/// Local Tresca solve: minimize `½ rᵀ A r − bᵀ r` over `rN ≤ 0, |rT| ≤ s`.
pub(crate) fn local_tresca(block: LocalBlock, b: [f64; 2], s: f64) -> [f64; 2] {
    let objective = |r: [f64; 2]| {
        0.5 * (block.nn * r[0] * r[0] + 2.0 * block.nt * r[0] * r[1] + block.tt * r[1] * r[1])
            - b[0] * r[0]
            - b[1] * r[1]
    };
    let det = block.nn * block.tt - block.nt * block.nt;
    let free = [(block.tt * b[0] - block.nt * b[1]) / det, (block.nn * b[1] - block.nt * b[0]) / det];
    if free[0] <= 0.0 && free[1].abs() <= s {
        return free;
    }
    let candidates = [
        [0.0, (b[1] / block.tt).clamp(-s, s)],
        [((b[0] - block.nt * s) / block.nn).min(0.0), s],
        [((b[0] + block.nt * s) / block.nn).min(0.0), -s],
    ];
    let mut best = candidates[0];
    let mut best_value = objective(best);
    for c in &candidates[1..] {
        let v = objective(*c);
        if v < best_value {
            best = *c;
            best_value = v;
        }
    }
    best
}

/// Local Coulomb solve by enumeration of open / stick / slip±.
pub(crate) fn local_coulomb(block: LocalBlock, b: [f64; 2], mu: f64) -> [f64; 2] {
    let (gn, gt) = (b[0], b[1]); // b = (g0 − qN, −qT)
                                 // Open.
    if gn >= 0.0 {
        return [0.0, 0.0];
    }
    let scale = (gn.abs() / block.nn).max(gt.abs() / block.tt);
    let slack = 1e-13 * scale;
    let mut least: Option<([f64; 2], f64)> = None;
    let mut consider = |r: [f64; 2], violation: f64| {
        if least.is_none_or(|(_, v)| violation < v) {
            least = Some((r, violation));
        }
    };
    // Open case violation, for the record.
    consider([0.0, 0.0], -gn / block.nn);
    // Stick.
    let det = block.nn * block.tt - block.nt * block.nt;
    let stick = [(block.tt * gn - block.nt * gt) / det, (block.nn * gt - block.nt * gn) / det];
    let stick_violation = stick[0].max(0.0) + (stick[1].abs() - mu * (-stick[0]).max(0.0)).max(0.0);
    if stick_violation <= slack {
        return stick;
    }
    consider(stick, stick_violation);
    // Slip in direction sigma: rT = −σ μ rN.
    for sigma in [1.0, -1.0] {
        let denominator = block.nn - sigma * mu * block.nt;
        if denominator <= 0.0 {
            continue;
        }
        let rn = gn / denominator;
        let rt = -sigma * mu * rn;
        // uT − (−qT) ... u_T = nt rN + tt rT + qT = nt rN + tt rT − gt.
        let ut = block.nt * rn + block.tt * rt - gt;
        let violation = rn.max(0.0) + (sigma * ut).max(0.0) / block.tt;
        if violation <= slack {
            return [rn, rt];
        }
        consider([rn, rt], violation);
    }
    let (mut r, _) = least.unwrap_or(([0.0, 0.0], 0.0));
    r[0] = r[0].min(0.0);
    let s = mu * (-r[0]);
    r[1] = r[1].clamp(-s, s);
    r
}

pub(crate) fn run(problem: &CondensedProblem, omega: f64, settings: &SolverSettings, initial: Vec<f64>) -> Result<Run> {
    let name = super::ContactSolver::ProjectedRelaxation { omega }.name();
    let w = problem.delassus().as_dense().ok_or_else(|| needs_dense(&name))?;
    let m = problem.points();
    let n = 2 * m;
    let data = w.as_slice();
    let gap = problem.gap();
    let mut r = initial;
    let mut u = problem.displacement_unchecked(&r);
    let mut states = classify(problem, &r, &u);
    let mut history = Vec::new();
    let mut notes = Vec::new();
    let tried = format!(
        "{name}: sweeps over the {m} points with exact local 2×2 solves, up to {} sweeps",
        settings.max_iterations
    );
    let mu: Option<&[f64]> = match problem.friction() {
        FrictionLaw::Coulomb { mu } => Some(mu),
        _ => None,
    };
    let mut stagnation = super::Stagnation::new(super::STAGNATION_WINDOW);
    for sweep in 1..=settings.max_iterations {
        for i in 0..m {
            let (kn, kt) = (2 * i, 2 * i + 1);
            let block = LocalBlock { nn: data[kn * n + kn], nt: data[kt * n + kn], tt: data[kt * n + kt] };
            let (rn, rt) = (r[kn], r[kt]);
            let qn = u[kn] - block.nn * rn - block.nt * rt;
            let qt = u[kt] - block.nt * rn - block.tt * rt;
            let b = [gap[i] - qn, -qt];
            let friction = problem.has_friction_at(i);
            let local = if !friction {
                [local_frictionless(block, b[0]), 0.0]
            } else if let Some(mu) = mu {
                local_coulomb(block, b, mu[i])
            } else {
                local_tresca(block, b, problem.threshold_at(i, 0.0))
            };
            let mut next =
                if omega == 1.0 { local } else { [rn + omega * (local[0] - rn), rt + omega * (local[1] - rt)] };
            next[0] = next[0].min(0.0);
            if friction {
                let s = problem.threshold_at(i, next[0]);
                next[1] = next[1].clamp(-s, s);
            } else {
                next[1] = 0.0;
            }
            let (dn, dt) = (next[0] - rn, next[1] - rt);
            if dn != 0.0 {
                let column = &data[kn * n..(kn + 1) * n];
                for (uk, wk) in u.iter_mut().zip(column) {
                    *uk += wk * dn;
                }
            }
            if dt != 0.0 {
                let column = &data[kt * n..(kt + 1) * n];
                for (uk, wk) in u.iter_mut().zip(column) {
                    *uk += wk * dt;
                }
            }
            r[kn] = next[0];
            r[kt] = next[1];
        }
        let status_changes = update_states(problem, &r, &u, &mut states);
        let mut residual = super::residuals::compute(problem, &r, &u).worst();
        if residual <= settings.tolerance || sweep % 100 == 0 {
            // Remove the drift of the incremental updates before trusting the residual.
            u = problem.displacement_unchecked(&r);
            residual = super::residuals::compute(problem, &r, &u).worst();
        }
        history.push(IterationRecord { residual, status_changes });
        if !residual.is_finite() {
            return Ok(Run {
                force: r,
                iterations: sweep,
                history,
                notes,
                failure: Some("the iterate became non-finite".into()),
                tried,
                solver: name,
            });
        }
        if stagnation.stalled(residual, sweep) {
            let best = stagnation.best();
            return Ok(Run {
                force: r,
                iterations: sweep,
                history,
                notes,
                failure: Some(format!(
                    "the residual stagnated at {best:.2e} (no 0.1 % progress in {} sweeps)",
                    super::STAGNATION_WINDOW
                )),
                tried,
                solver: name,
            });
        }
        if residual <= settings.tolerance {
            if omega != 1.0 {
                notes.push(format!("relaxation factor omega = {omega}"));
            }
            return Ok(Run { force: r, iterations: sweep, history, notes, failure: None, tried, solver: name });
        }
    }
    Ok(Run {
        force: r,
        iterations: settings.max_iterations,
        history,
        notes,
        failure: Some(format!("iteration limit of {} sweeps reached", settings.max_iterations)),
        tried,
        solver: name,
    })
}
