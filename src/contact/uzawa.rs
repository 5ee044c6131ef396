//! Uzawa's method on the contact forces (projected gradient on the multipliers).
//!
//! In the talk's dual algebraic system the contact forces `f_C` are multipliers; Uzawa's
//! algorithm (K. J. Arrow, L. Hurwicz, H. Uzawa, "Studies in linear and non-linear
//! programming", Stanford University Press, 1958; for contact: N. Kikuchi, J. T. Oden,
//! "Contact problems in elasticity", SIAM, 1988, ch. 6) alternates a solve with a fixed
//! factorization and a projected update of the multipliers. Once condensed, the solve is the
//! product `u = W r + u_free` and the iteration is the projected gradient method on the
//! complementary energy `J(r) = ½ rᵀ W r + rᵀ (u_free − g̃)`:
//!
//! ```text
//!   rN ← P_N(rN − ρ (uN − g0)) = min(rN − ρ (uN − g0), 0)
//!   rT ← P_T(rT − ρ uT)        = clamp(rT − ρ uT, −s, s)
//! ```
//!
//! with `s` the Tresca threshold, or for Coulomb `μ |rN|` from the NEW normal force (the
//! friction threshold is updated inside the iteration: a fixed point of the Alart–Curnier
//! map, convergent for small μ).
//!
//! Step: `ρ = 1 / λ̂` with `λ̂ = min(1.05 λ_power, ‖W‖∞)`, `λ_power` the Rayleigh quotient
//! after 50 power iterations (a lower bound of `λmax(W)`, so `ρ < 2/λmax` as long as the
//! estimate is within a factor 2.1; `‖W‖∞` is an upper bound, available for dense `W`).
//! For convex (frictionless, Tresca) problems the energy must decrease at every step; if it
//! does not, `ρ` is halved (recorded in the notes). No user parameter.
//!
//! `accelerated`: Nesterov's momentum (FISTA, A. Beck, M. Teboulle, SIAM J. Imaging Sci. 2,
//! 2009) with the gradient-based adaptive restart of B. O'Donoghue, E. Candès (Found. Comput.
//! Math. 15, 2015): iteration counts grow like `√cond(W)` instead of `cond(W)`.
//!
//! 500 iterations without a 0.1 % improvement of the best residual (Coulomb with a large μ)
//! end the iteration with [`Error::SolverDiverged`](crate::error::Error::SolverDiverged).
//!
//! Works with [`Delassus::Operator`](super::Delassus::Operator) (products only). On the dual
//! formulation's implicit flexibility, whose product is one solve of the dual system with the
//! forces as data, this is Uzawa on the full dual system ([`crate::dual::condensation`]).
use super::{
    classify, residuals, update_states, CondensedProblem, ContactSolver, FrictionLaw, IterationRecord, Run,
    SolverSettings,
};

const POWER_ITERATIONS: usize = 50;

/// Estimate of the largest eigenvalue of `W` (see the module documentation).
pub(crate) fn largest_eigenvalue_estimate(problem: &CondensedProblem) -> f64 {
    let w = problem.delassus();
    let n = w.size();
    let mut x: Vec<f64> = (0..n).map(|k| 1.0 + 0.1 * ((k % 7) as f64) / 7.0).collect();
    let mut y = vec![0.0; n];
    let mut rayleigh = 0.0;
    for _ in 0..POWER_ITERATIONS {
        let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm == 0.0 || !norm.is_finite() {
            break;
        }
        x.iter_mut().for_each(|v| *v /= norm);
        w.apply(&x, &mut y);
        rayleigh = x.iter().zip(&y).map(|(a, b)| a * b).sum::<f64>();
        std::mem::swap(&mut x, &mut y);
    }
    let max_diagonal = problem.diagonal().iter().copied().fold(0.0, f64::max);
    let mut estimate = (1.05 * rayleigh).max(max_diagonal);
    if let Some(dense) = w.as_dense() {
        let infinity_norm = (0..n).map(|i| dense.column(i).iter().map(|v| v.abs()).sum::<f64>()).fold(0.0, f64::max);
        estimate = estimate.min(infinity_norm);
    }
    estimate
}

fn energy(r: &[f64], u: &[f64], free: &[f64], gap_vector: &[f64]) -> f64 {
    // J = ½ rᵀ W r + rᵀ (u_free − g̃) = ½ rᵀ (u + u_free) − rᵀ g̃.
    r.iter().enumerate().map(|(k, rk)| rk * (0.5 * (u[k] + free[k]) - gap_vector[k])).sum()
}

/// The projected step from `y` with displacement `u_y`: `P(y − ρ (u_y − g̃))`.
fn projected_step(problem: &CondensedProblem, y: &[f64], u_y: &[f64], rho: f64, out: &mut [f64]) {
    for i in 0..problem.points() {
        let rn = (y[2 * i] - rho * (u_y[2 * i] - problem.gap()[i])).min(0.0);
        out[2 * i] = rn;
        out[2 * i + 1] = if problem.has_friction_at(i) {
            let s = problem.threshold_at(i, rn);
            (y[2 * i + 1] - rho * u_y[2 * i + 1]).clamp(-s, s)
        } else {
            0.0
        };
    }
}

pub(crate) fn run(problem: &CondensedProblem, accelerated: bool, settings: &SolverSettings, initial: Vec<f64>) -> Run {
    let name = ContactSolver::Uzawa { accelerated }.name();
    let n = 2 * problem.points();
    let convex = !matches!(problem.friction(), FrictionLaw::Coulomb { .. });
    let lambda = largest_eigenvalue_estimate(problem);
    let mut rho = 1.0 / lambda;
    let mut notes = vec![format!("step rho = 1/{lambda:.4e} (largest eigenvalue estimate of W)")];
    let tried = format!("{name} with step 1/lambda_max(W), up to {} iterations", settings.max_iterations);
    let gap_vector = problem.gap_vector();
    let free = problem.free_displacement();
    let mut r = initial;
    let mut u = problem.displacement_unchecked(&r);
    let mut states = classify(problem, &r, &u);
    let mut history = Vec::new();
    let mut y = r.clone();
    let mut u_y = u.clone();
    let mut next = vec![0.0; n];
    let mut u_next = vec![0.0; n];
    let mut momentum = 1.0f64;
    let mut restarts = 0usize;
    let mut step_halvings = 0usize;
    let mut current_energy = energy(&r, &u, free, &gap_vector);
    let mut iteration = 0;
    let mut stagnation = super::Stagnation::new(super::STAGNATION_WINDOW);
    while iteration < settings.max_iterations {
        projected_step(problem, &y, &u_y, rho, &mut next);
        problem.delassus().apply(&next, &mut u_next);
        for (a, b) in u_next.iter_mut().zip(free) {
            *a += b;
        }
        if convex && !accelerated {
            let next_energy = energy(&next, &u_next, free, &gap_vector);
            let slack = 1e-12 * (current_energy.abs() + next_energy.abs());
            if next_energy > current_energy + slack && step_halvings < 30 {
                rho *= 0.5;
                step_halvings += 1;
                continue; // retry the step from the same point (not counted)
            }
            current_energy = next_energy;
        }
        iteration += 1;
        if accelerated {
            // Restart when the momentum points uphill: (y − next)·(next − r) > 0.
            let uphill: f64 = (0..n).map(|k| (y[k] - next[k]) * (next[k] - r[k])).sum();
            let previous = std::mem::replace(&mut r, next.clone());
            std::mem::swap(&mut u, &mut u_next);
            if uphill > 0.0 {
                momentum = 1.0;
                restarts += 1;
                y.copy_from_slice(&r);
                u_y.copy_from_slice(&u);
            } else {
                let momentum_next = 0.5 * (1.0 + (1.0 + 4.0 * momentum * momentum).sqrt());
                let beta = (momentum - 1.0) / momentum_next;
                momentum = momentum_next;
                for k in 0..n {
                    y[k] = r[k] + beta * (r[k] - previous[k]);
                    // u is affine in r: u_y = u + β (u − u_previous), u_previous in u_next now.
                    u_y[k] = u[k] + beta * (u[k] - u_next[k]);
                }
                // Points without friction keep exactly rT = 0 (β·0 = 0).
            }
        } else {
            r.copy_from_slice(&next);
            std::mem::swap(&mut u, &mut u_next);
            y.copy_from_slice(&r);
            u_y.copy_from_slice(&u);
        }
        let status_changes = update_states(problem, &r, &u, &mut states);
        let mut residual = residuals::compute(problem, &r, &u).worst();
        if residual <= settings.tolerance {
            u = problem.displacement_unchecked(&r);
            residual = residuals::compute(problem, &r, &u).worst();
            if accelerated {
                u_y = u.clone();
                y.copy_from_slice(&r);
                momentum = 1.0;
            }
        }
        history.push(IterationRecord { residual, status_changes });
        if !residual.is_finite() {
            return Run {
                force: r,
                iterations: iteration,
                history,
                notes,
                failure: Some("the iterate became non-finite".into()),
                tried,
                solver: name,
            };
        }
        if stagnation.stalled(residual, iteration) {
            let best = stagnation.best();
            return Run {
                force: r,
                iterations: iteration,
                history,
                notes,
                failure: Some(format!(
                    "the residual stagnated at {best:.2e} (no 0.1 % progress in {} iterations)",
                    super::STAGNATION_WINDOW
                )),
                tried,
                solver: name,
            };
        }
        if residual <= settings.tolerance {
            if restarts > 0 {
                notes.push(format!("{restarts} momentum restarts"));
            }
            if step_halvings > 0 {
                notes.push(format!("step halved {step_halvings} times (energy increase)"));
            }
            return Run { force: r, iterations: iteration, history, notes, failure: None, tried, solver: name };
        }
    }
    if step_halvings > 0 {
        notes.push(format!("step halved {step_halvings} times (energy increase)"));
    }
    Run {
        force: r,
        iterations: settings.max_iterations,
        history,
        notes,
        failure: Some(format!("iteration limit of {} iterations reached", settings.max_iterations)),
        tried,
        solver: name,
    }
}
