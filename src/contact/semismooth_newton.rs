//! Semi-smooth (generalized) Newton method on the Alart–Curnier function.
//!
//! P. Alart, A. Curnier, "A mixed formulation for frictional contact problems prone to Newton
//! like solution methods", Comput. Methods Appl. Mech. Engrg. 92, 1991, 353–375. For the
//! Signorini part this is the primal–dual active set method (M. Hintermüller, K. Ito,
//! K. Kunisch, "The primal–dual active set strategy as a semismooth Newton method", SIAM J.
//! Optim. 13(3), 2002, 865–888), whose iteration count is nearly independent of the mesh.
//!
//! ## The equations
//!
//! With `u = W r + u_free` and, per point, the augmentation parameters `ρN = 1/W_NN`,
//! `ρT = 1/W_TT` (from the diagonal of `W`: no user parameter):
//!
//! ```text
//!   τN = rN − ρN (uN − g0)              F_N = rN − min(τN, 0)
//!   τT = rT − ρT uT                     F_T = rT − clamp(τT, −s, s)
//!   s  = Tresca threshold, or μ max(−τN, 0) (Coulomb, with the augmented normal force)
//! ```
//!
//! `F(r) = 0` is exactly the contact law. `F` is piecewise affine in `r`; on each piece (a
//! "status" of the points: open / in contact, and free / stick / slip+ / slip−) the Newton
//! step from `r` lands on the solution `x` of the linear system of that piece:
//!
//! ```text
//!   open:                     xN = 0
//!   in contact:               (W x)_N = g0 − u_free,N          (uN = g0)
//!   no friction / zero s:     xT = 0
//!   stick:                    (W x)_T = −u_free,T              (uT = 0)
//!   slip σ = ±1, Tresca:      xT = σ s
//!   slip σ = ±1, Coulomb:     xT = −σ μ xN                     (non-symmetric coupling)
//! ```
//!
//! The unknowns of the system are the normal forces in contact and the tangential forces that
//! stick; the others are fixed or linked to a normal force. For frictionless and Tresca
//! problems the matrix is a principal sub-matrix of `W` (Cholesky); for Coulomb it gains the
//! columns `−σ μ W_{·,T}` (LU). With [`Delassus::Operator`](super::Delassus::Operator) the
//! same systems are solved by conjugate gradients or GMRES on products with `W`.
//!
//! A point whose slip direction reverses from one step to the next is put in the stick state
//! for that step (it must cross the interior of the friction interval, as a two-sided bound
//! in a primal–dual active set method): on dense flexibility operators, which are far from
//! M-matrices, the plain rule makes whole slip zones flip sign back and forth.
//!
//! ## Globalization (on by default, [`SolverSettings::newton_globalization`])
//!
//! - Non-monotone Armijo line search (L. Grippo, F. Lampariello, S. Lucidi, SIAM J. Numer.
//!   Anal. 23, 1986) on the merit `Θ = ½ ‖F‖²`, against the largest of the last 5 values:
//!   accept `t` if `Θ(r + t δ) ≤ (1 − 10⁻⁴ t) max Θ`, halving `t` down to `10⁻⁶`.
//! - Active-set cycling: the status set of every iteration is remembered; meeting one seen
//!   two or more iterations before (a ping-pong such as A → B → A) is a cycle. First two
//!   cycles (damping): the line search becomes monotone and the steps are capped at 1/2, then
//!   1/4, until an iteration leaves every status unchanged (then the next full step is exact,
//!   so the cap is lifted). Third cycle, a failed line search, a singular system or 20
//!   iterations without halving the residual: fallback, from the current iterate, to projected
//!   relaxation (dense `W` only) and, if that fails too (it can for large μ), to accelerated
//!   Uzawa.
//!   All of this is recorded in the notes of the solution.
//!
//! Without globalization the raw method runs full steps and stops with
//! [`Error::SolverDiverged`](crate::error::Error::SolverDiverged) on the first cycle.
//!
//! [`SolverSettings::newton_globalization`]: super::SolverSettings::newton_globalization
use std::collections::{HashMap, VecDeque};

use nalgebra::{DMatrix, DVector};

use super::{
    classify, krylov, projected_relaxation, residuals, stick_reversed_slips, update_states, uzawa, CondensedProblem,
    ContactSolver, DenseSolver, FrictionLaw, IterationRecord, PointState, Run, SolverSettings, TangentialState,
};
use crate::error::Result;

const MERIT_MEMORY: usize = 5;
const ARMIJO: f64 = 1e-4;
const SMALLEST_STEP: f64 = 1e-6;
const CYCLES_BEFORE_FALLBACK: usize = 3;
const ITERATIONS_WITHOUT_PROGRESS: usize = 20;

/// How an entry of the Newton target `x` is determined.
#[derive(Debug, Clone, Copy)]
enum Entry {
    /// An unknown of the linear system (position in the unknown list).
    Unknown(usize),
    Fixed(f64),
    /// `x_T = coefficient · x_N` with `x_N` the unknown at this position.
    Linked {
        position: usize,
        coefficient: f64,
    },
}

/// The Alart–Curnier merit `½ ‖F(r)‖²`.
fn merit(problem: &CondensedProblem, r: &[f64], u: &[f64]) -> f64 {
    let rho = problem.augmentation();
    let coulomb = matches!(problem.friction(), FrictionLaw::Coulomb { .. });
    let mut sum = 0.0;
    for i in 0..problem.points() {
        let tau_n = r[2 * i] - rho[2 * i] * (u[2 * i] - problem.gap()[i]);
        let f_n = r[2 * i] - tau_n.min(0.0);
        let f_t = if problem.has_friction_at(i) {
            let s = if coulomb { problem.threshold_at(i, tau_n) } else { problem.threshold_at(i, r[2 * i]) };
            let tau_t = r[2 * i + 1] - rho[2 * i + 1] * u[2 * i + 1];
            r[2 * i + 1] - tau_t.clamp(-s, s)
        } else {
            r[2 * i + 1]
        };
        sum += f_n * f_n + f_t * f_t;
    }
    0.5 * sum
}

/// The linear system of a status set: which entries are unknowns, fixed or linked.
fn layout(problem: &CondensedProblem, states: &[PointState]) -> (Vec<Entry>, Vec<usize>, bool) {
    let mu: Option<&Vec<f64>> = match problem.friction() {
        FrictionLaw::Coulomb { mu } => Some(mu),
        _ => None,
    };
    let mut entries = vec![Entry::Fixed(0.0); 2 * problem.points()];
    let mut unknowns = Vec::new();
    let mut symmetric = true;
    for (i, state) in states.iter().enumerate() {
        let (kn, kt) = (2 * i, 2 * i + 1);
        if state.contact {
            entries[kn] = Entry::Unknown(unknowns.len());
            unknowns.push(kn);
        }
        match state.tangential {
            TangentialState::Free => {}
            TangentialState::Stick => {
                entries[kt] = Entry::Unknown(unknowns.len());
                unknowns.push(kt);
            }
            TangentialState::Slip { positive } => {
                let sigma = if positive { 1.0 } else { -1.0 };
                match (mu, entries[kn]) {
                    (Some(mu), Entry::Unknown(position)) => {
                        entries[kt] = Entry::Linked { position, coefficient: -sigma * mu[i] };
                        symmetric = false;
                    }
                    (Some(_), _) => {} // open Coulomb point: threshold 0
                    (None, _) => entries[kt] = Entry::Fixed(sigma * problem.threshold_at(i, 0.0)),
                }
            }
        }
    }
    (entries, unknowns, symmetric)
}

/// Right-hand side value of an unknown row: `g0 − u_free,N` or `−u_free,T`.
fn row_target(problem: &CondensedProblem, k: usize) -> f64 {
    if k.is_multiple_of(2) {
        problem.gap()[k / 2] - problem.free_displacement()[k]
    } else {
        -problem.free_displacement()[k]
    }
}

/// Expand the unknown values `y` into the full target vector.
fn expand(entries: &[Entry], y: &[f64], include_fixed: bool) -> Vec<f64> {
    entries
        .iter()
        .map(|e| match *e {
            Entry::Unknown(p) => y[p],
            Entry::Fixed(v) => {
                if include_fixed {
                    v
                } else {
                    0.0
                }
            }
            Entry::Linked { position, coefficient } => coefficient * y[position],
        })
        .collect()
}

/// Outcome of the linear solve of a Newton step.
struct Target {
    x: Vec<f64>,
    krylov_iterations: usize,
}

fn newton_target(
    problem: &CondensedProblem,
    states: &[PointState],
    linear_tolerance: f64,
    dense_solver: Option<&DenseSolver>,
) -> std::result::Result<Target, String> {
    let (entries, unknowns, symmetric) = layout(problem, states);
    let fixed = expand(&entries, &vec![0.0; unknowns.len()], true);
    if unknowns.is_empty() {
        return Ok(Target { x: fixed, krylov_iterations: 0 });
    }
    let k = unknowns.len();
    let n = entries.len();
    match problem.delassus().as_dense() {
        Some(w) => {
            let mut matrix = DMatrix::<f64>::zeros(k, k);
            let mut rhs = DVector::<f64>::zeros(k);
            // Columns of the reduced matrix: one per unknown, plus linked contributions.
            for (q, &col) in unknowns.iter().enumerate() {
                let column = w.column(col);
                for (p, &row) in unknowns.iter().enumerate() {
                    matrix[(p, q)] = column[row];
                }
            }
            for (j, entry) in entries.iter().enumerate() {
                match *entry {
                    Entry::Linked { position, coefficient } => {
                        let column = w.column(j);
                        for (p, &row) in unknowns.iter().enumerate() {
                            matrix[(p, position)] += coefficient * column[row];
                        }
                    }
                    Entry::Fixed(v) if v != 0.0 => {
                        let column = w.column(j);
                        for (p, &row) in unknowns.iter().enumerate() {
                            rhs[p] -= v * column[row];
                        }
                    }
                    _ => {}
                }
            }
            for (p, &row) in unknowns.iter().enumerate() {
                rhs[p] += row_target(problem, row);
            }
            let solution = if let Some(solver) = dense_solver {
                (solver.0)(&matrix, &rhs)
            } else if symmetric {
                match nalgebra::Cholesky::new(matrix.clone()) {
                    Some(c) => Some(c.solve(&rhs)),
                    None => matrix.lu().solve(&rhs),
                }
            } else {
                matrix.lu().solve(&rhs)
            };
            match solution {
                Some(y) if y.iter().all(|v| v.is_finite()) => {
                    Ok(Target { x: expand(&entries, y.as_slice(), true), krylov_iterations: 0 })
                }
                _ => Err(format!("the Newton system of {k} unknowns is singular")),
            }
        }
        None => {
            let delassus = problem.delassus();
            let mut w_fixed = vec![0.0; n];
            delassus.apply(&fixed, &mut w_fixed);
            let rhs: Vec<f64> = unknowns.iter().map(|&row| row_target(problem, row) - w_fixed[row]).collect();
            let diagonal: Vec<f64> = unknowns.iter().map(|&row| problem.diagonal()[row]).collect();
            let apply = |y: &[f64], out: &mut [f64]| {
                let x = expand(&entries, y, false);
                let mut wx = vec![0.0; n];
                delassus.apply(&x, &mut wx);
                for (o, &row) in out.iter_mut().zip(&unknowns) {
                    *o = wx[row];
                }
            };
            let max_iterations = 10 * k + 100;
            let result = if symmetric {
                krylov::conjugate_gradient(&apply, &diagonal, &rhs, linear_tolerance, max_iterations)
            } else {
                krylov::gmres(&apply, &diagonal, &rhs, linear_tolerance, 50, max_iterations)
            };
            if !result.converged {
                return Err(format!(
                    "{} did not solve the Newton system of {k} unknowns (relative residual {:.2e} \
                     after {} iterations)",
                    if symmetric { "conjugate gradients" } else { "GMRES" },
                    result.relative_residual,
                    result.iterations
                ));
            }
            Ok(Target { x: expand(&entries, &result.x, true), krylov_iterations: result.iterations })
        }
    }
}

fn describe_states(states: &[PointState]) -> String {
    let open = states.iter().filter(|s| !s.contact).count();
    let stick = states.iter().filter(|s| s.contact && s.tangential == TangentialState::Stick).count();
    format!("{open} open, {stick} stick, {} slip", states.len() - open - stick)
}

pub(crate) fn run(problem: &CondensedProblem, settings: &SolverSettings, initial: Vec<f64>) -> Result<Run> {
    let name = ContactSolver::SemismoothNewton.name();
    let globalize = settings.newton_globalization;
    let tried = format!(
        "{name}, augmentation 1/diag(W), {}, up to {} Newton steps",
        if globalize {
            "non-monotone line search, damping on active-set cycles, fallback to relaxation"
        } else {
            "undamped (globalization off)"
        },
        settings.max_iterations
    );
    let mut r = initial;
    let mut u = problem.displacement_unchecked(&r);
    let mut states = classify(problem, &r, &u);
    let mut residual = residuals::compute(problem, &r, &u).worst();
    let mut history: Vec<IterationRecord> = Vec::new();
    let mut notes: Vec<String> = Vec::new();
    let mut seen: HashMap<Vec<PointState>, usize> = HashMap::new();
    let mut merits: VecDeque<f64> = VecDeque::new();
    let mut step_cap = 1.0f64;
    let mut monotone = false;
    let mut previous_step_states: Option<Vec<PointState>> = None;
    let mut cycles = 0usize;
    let mut krylov_iterations = 0usize;
    let mut best = residual;
    let mut best_at = 0usize;
    let mut iteration = 0usize;
    let fallback_reason: String;
    loop {
        if residual <= settings.tolerance {
            if krylov_iterations > 0 {
                notes.push(format!("{krylov_iterations} Krylov iterations in the Newton systems"));
            }
            return Ok(Run { force: r, iterations: iteration, history, notes, failure: None, tried, solver: name });
        }
        if !residual.is_finite() {
            fallback_reason = "the iterate became non-finite".into();
            break;
        }
        if iteration >= settings.max_iterations {
            return Ok(Run {
                force: r,
                iterations: iteration,
                history,
                notes,
                failure: Some(format!("iteration limit of {} Newton steps reached", settings.max_iterations)),
                tried,
                solver: name,
            });
        }
        // Cycle detection on the status set that defines this step.
        if let Some(&earlier) = seen.get(&states) {
            if earlier + 1 < iteration {
                cycles += 1;
                let what = format!(
                    "active-set cycle: the status set of iteration {iteration} ({}) repeats \
                     that of iteration {earlier}",
                    describe_states(&states)
                );
                if !globalize {
                    return Ok(Run {
                        force: r,
                        iterations: iteration,
                        history,
                        notes,
                        failure: Some(format!("{what} (undamped Newton ping-pongs)")),
                        tried,
                        solver: name,
                    });
                }
                if cycles >= CYCLES_BEFORE_FALLBACK {
                    notes.push(what);
                    fallback_reason = format!("{CYCLES_BEFORE_FALLBACK} active-set cycles despite damping");
                    break;
                }
                step_cap = 0.5f64.powi(cycles as i32);
                monotone = true;
                notes.push(format!(
                    "{what}; steps capped at {step_cap} until the status set settles, monotone line search"
                ));
                seen.clear();
            }
        }
        seen.insert(states.clone(), iteration);
        // A slip point whose slip direction reverses goes through stick first.
        let mut step_states = states.clone();
        if let Some(previous) = &previous_step_states {
            stick_reversed_slips(&mut step_states, previous);
        }
        previous_step_states = Some(step_states.clone());
        if globalize && iteration >= best_at + ITERATIONS_WITHOUT_PROGRESS {
            fallback_reason = format!("no progress in {ITERATIONS_WITHOUT_PROGRESS} Newton steps");
            break;
        }
        let linear_tolerance = (0.01 * residual).clamp(1e-13, 1e-4);
        let target = match newton_target(problem, &step_states, linear_tolerance, settings.dense_solver.as_ref()) {
            Ok(t) => t,
            Err(reason) => {
                if !globalize {
                    return Ok(Run {
                        force: r,
                        iterations: iteration,
                        history,
                        notes,
                        failure: Some(reason),
                        tried,
                        solver: name,
                    });
                }
                fallback_reason = reason;
                break;
            }
        };
        krylov_iterations += target.krylov_iterations;
        let delta: Vec<f64> = target.x.iter().zip(&r).map(|(x, ri)| x - ri).collect();
        let mut step = step_cap;
        if globalize {
            let mut w_delta = vec![0.0; delta.len()];
            problem.delassus().apply(&delta, &mut w_delta);
            let current = merit(problem, &r, &u);
            merits.push_back(current);
            let memory = if monotone { 1 } else { MERIT_MEMORY };
            while merits.len() > memory {
                merits.pop_front();
            }
            let reference = merits.iter().copied().fold(0.0, f64::max);
            let mut trial_r = vec![0.0; r.len()];
            let mut trial_u = vec![0.0; r.len()];
            loop {
                for k in 0..r.len() {
                    trial_r[k] = r[k] + step * delta[k];
                    trial_u[k] = u[k] + step * w_delta[k];
                }
                if merit(problem, &trial_r, &trial_u) <= (1.0 - ARMIJO * step) * reference {
                    break;
                }
                step *= 0.5;
                if step < SMALLEST_STEP {
                    break;
                }
            }
            if step < SMALLEST_STEP {
                fallback_reason = format!("the line search failed at Newton step {}", iteration + 1);
                break;
            }
        }
        for (ri, di) in r.iter_mut().zip(&delta) {
            *ri += step * di;
        }
        u = problem.displacement_unchecked(&r);
        iteration += 1;
        let status_changes = update_states(problem, &r, &u, &mut states);
        if status_changes == 0 {
            // Same affine piece: the next full step is exact, no cycling possible.
            step_cap = 1.0;
        }
        residual = residuals::compute(problem, &r, &u).worst();
        history.push(IterationRecord { residual, status_changes });
        if residual < 0.5 * best {
            best = residual;
            best_at = iteration;
        }
    }
    // Fallback from the current iterate, or from zero when it is not finite, or when its
    // displacement is not (a finite force whose W r overflows: the fallback would fail on it
    // too).
    let mut start = r.clone();
    if !residual.is_finite() || start.iter().any(|v| !v.is_finite()) {
        start = vec![0.0; r.len()];
    }
    problem.project_admissible(&mut start);
    let mut chain = Vec::new();
    if problem.delassus().as_dense().is_some() {
        chain.push(ContactSolver::ProjectedRelaxation { omega: 1.0 });
    }
    chain.push(ContactSolver::Uzawa { accelerated: true });
    notes.push(format!(
        "after {iteration} Newton steps: {fallback_reason}; fallback to {}",
        chain.iter().map(|c| c.name()).collect::<Vec<_>>().join(", then ")
    ));
    let mut iterations = iteration;
    let mut tried_all = tried;
    let mut solver = name;
    let mut last_failure = None;
    let mut force = start.clone();
    for fallback_solver in chain {
        let fallback = match fallback_solver {
            ContactSolver::ProjectedRelaxation { omega } => {
                projected_relaxation::run(problem, omega, settings, start.clone())?
            }
            _ => uzawa::run(problem, true, settings, start.clone()),
        };
        history.extend(fallback.history);
        notes.extend(fallback.notes);
        iterations += fallback.iterations;
        tried_all = format!("{tried_all}; then {}", fallback.tried);
        solver = format!("{solver}, then {}", fallback.solver);
        force = fallback.force;
        last_failure = fallback.failure;
        match &last_failure {
            None => break,
            Some(reason) => notes.push(format!("{} failed: {reason}", fallback_solver.name())),
        }
    }
    Ok(Run { force, iterations, history, notes, failure: last_failure, tried: tried_all, solver })
}
