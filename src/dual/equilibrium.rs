//! # Equilibrium of the contact forces (a body held, in some direction, only by the obstacle)
//!
//! `E r = e`, one row per condition closed through Γc (force x, force y, moment), imposed by a
//! Newton iteration on their multipliers, the rigid displacements `ρ`, around an unchanged
//! condensed solver: see [`super::contact`] for the method. The solves it needs with `W` — the
//! bonded model `E W⁻¹ Eᵀ` that starts it and the active-set derivative
//! `−E P (R W P)⁻¹ R Eᵀ` of each step — use the Cholesky and LU factorisations of a dense `W`,
//! or, with the implicit storage of `W` ([`super::condensation`]), Jacobi-preconditioned
//! conjugate gradients (M. R. Hestenes, E. Stiefel 1952) or GMRES (Y. Saad, M. H. Schultz 1986,
//! for the non-symmetric `R W P` of sliding Coulomb points) on products: one right-hand side
//! per condition (at most three) per outer step, each iteration one product.
use nalgebra::{DMatrix, DVector};

use super::system::DualSystem;
use crate::contact::{krylov, CondensedProblem, ContactSolution, FrictionLaw, SolverSettings};
use crate::error::{Error, Result};

/// The equilibrium conditions `E r = e` on the contact forces (dense, one row per condition).
#[derive(Debug, Clone)]
pub struct ContactEquilibrium {
    /// `E`: one row per condition, one column per contact unknown.
    pub matrix: DMatrix<f64>,
    /// `e`.
    pub rhs: Vec<f64>,
}

impl ContactEquilibrium {
    /// The conditions of `system` (`AffineDofs::contact_equilibrium`).
    pub fn new(system: &DualSystem) -> Self {
        let rows = &system.affine.contact_equilibrium;
        let n = system.affine.num_contact;
        let mut matrix = DMatrix::zeros(rows.len(), n);
        for (i, (terms, _)) in rows.iter().enumerate() {
            for &(j, c) in terms {
                matrix[(i, j)] += c;
            }
        }
        ContactEquilibrium { matrix, rhs: rows.iter().map(|r| r.1).collect() }
    }

    /// Whether there are no conditions.
    pub fn is_empty(&self) -> bool {
        self.rhs.is_empty()
    }

    /// `E r − e` and, per row, its scale `|e_i| + Σ_j |E_ij r_j|`.
    pub fn residual(&self, r: &[f64]) -> (Vec<f64>, Vec<f64>) {
        (0..self.rhs.len())
            .map(|i| {
                let row = self.matrix.row(i);
                let value: f64 = row.iter().zip(r).map(|(a, b)| a * b).sum::<f64>() - self.rhs[i];
                let scale: f64 = self.rhs[i].abs() + row.iter().zip(r).map(|(a, b)| (a * b).abs()).sum::<f64>();
                (value, scale)
            })
            .unzip()
    }

    /// The largest `|E r − e|_i / scale_i`.
    /// relative to the largest scale of all rows (a row that round-off only balances, such as
    /// the horizontal force of a symmetric frictionless problem, is measured against the loads).
    pub fn relative_residual(&self, r: &[f64]) -> f64 {
        let (value, scale) = self.residual(r);
        let scale = scale.iter().fold(0.0f64, |m, s| m.max(*s)).max(f64::MIN_POSITIVE);
        value.iter().fold(0.0f64, |m, v| m.max(v.abs())) / scale
    }

    /// `Eᵀ ρ`.
    pub fn transpose_times(&self, rho: &[f64]) -> Vec<f64> {
        (self.matrix.transpose() * DVector::from_column_slice(rho)).iter().copied().collect()
    }
}

/// Outer (Newton) steps on the rigid displacements at most.
const MAX_OUTER: usize = 50;
/// The smallest tolerance asked of a solve, in units of the products' accuracy.
pub const NOISE_MARGIN: f64 = 100.0;
/// Relative residual of `E r = e` accepted when the iteration cannot go further.
const EQUILIBRIUM_TOLERANCE: f64 = 1e-10;

/// Solve `problem` subject to `E r = e` (see the module documentation). `run` solves one
/// box-constrained problem; it is called with `u_free + Eᵀ ρ` for the current rigid
/// displacements `ρ`. `accuracy` is the relative accuracy of `W`'s products (0 when exact, see
/// [`super::condensation::ColumnCondensation::product_accuracy`]): no solve is asked for a
/// tolerance below [`NOISE_MARGIN`] times it (the residuals computed with noisy products
/// stagnate there: measured 30× on the square block at 1e4 dofs).
pub fn solve_with_equilibrium(
    problem: &CondensedProblem,
    equilibrium: &ContactEquilibrium,
    settings: &SolverSettings,
    accuracy: f64,
    run: impl Fn(&CondensedProblem, &SolverSettings) -> Result<ContactSolution>,
) -> Result<(ContactSolution, Vec<f64>, usize)> {
    let floor = NOISE_MARGIN * accuracy;
    // Without friction the tangential forces stay zero: drop them from the conditions; a row
    // left empty (the tangential resultant) must hold already, or the body slides.
    let original = equilibrium;
    let reduced;
    let mut kept: Vec<usize> = (0..original.rhs.len()).collect();
    let frictionless = matches!(problem.friction(), FrictionLaw::None);
    let equilibrium = if frictionless {
        let mut matrix = original.matrix.clone();
        for j in (1..matrix.ncols()).step_by(2) {
            matrix.column_mut(j).fill(0.0);
        }
        let load = original.rhs.iter().fold(0.0f64, |m, e| m.max(e.abs()));
        kept.retain(|&i| matrix.row(i).amax() > 0.0);
        for i in 0..original.rhs.len() {
            if !kept.contains(&i) && original.rhs[i].abs() > 1e-9 * load {
                return Err(Error::NoEquilibrium(format!(
                    "dual formulation: the contact is frictionless, so the contact forces cannot carry the load \
                     {:.4e} along the obstacle (equilibrium condition {i}): the body slides",
                    original.rhs[i]
                )));
            }
        }
        reduced = ContactEquilibrium {
            matrix: DMatrix::from_fn(kept.len(), matrix.ncols(), |i, j| matrix[(kept[i], j)]),
            rhs: kept.iter().map(|&i| original.rhs[i]).collect(),
        };
        &reduced
    } else {
        original
    };
    if equilibrium.is_empty() {
        let mut settings = settings.clone();
        settings.tolerance = settings.tolerance.max(floor);
        return Ok((run(problem, &settings)?, vec![0.0; original.rhs.len()], 1));
    }
    let e = &equilibrium.matrix;
    let k = equilibrium.rhs.len();
    // The bonded model (every component free): M = E W⁻¹ Eᵀ; its ρ balances the loads when
    // every point is closed and sticks, the starting point of the iteration.
    let flexibility = Flexibility::new(problem)?;
    let w_inv_et = flexibility.solve(&e.transpose())?;
    let m_bonded = e * &w_inv_et;
    let shifted: Vec<f64> = problem
        .free_displacement()
        .iter()
        .enumerate()
        .map(|(j, u)| if j % 2 == 0 { u - problem.gap()[j / 2] } else { *u })
        .collect();
    let free_force = flexibility.solve(&DMatrix::from_column_slice(shifted.len(), 1, &shifted))?.column(0).into_owned();
    let target = DVector::from_column_slice(&equilibrium.rhs) + e * free_force;
    let bonded = m_bonded
        .clone()
        .cholesky()
        .ok_or_else(|| Error::Usage("the equilibrium conditions of the contact forces are dependent".into()))?;
    let mut rho: Vec<f64> = (-bonded.solve(&target)).iter().copied().collect();
    // Inner solves 100× tighter than asked: a warm-started solver stops at once when the
    // change of one outer step is below its tolerance.
    let mut settings = settings.clone();
    settings.tolerance = (settings.tolerance * 1e-2).max(floor);
    let target_residual = 1e-14f64.max(0.1 * settings.tolerance);
    let acceptable = EQUILIBRIUM_TOLERANCE.max(target_residual);
    let solve_at = |rho: &[f64], settings: &SolverSettings| -> Result<ContactSolution> {
        let extra = equilibrium.transpose_times(rho);
        let u: Vec<f64> = problem.free_displacement().iter().zip(&extra).map(|(a, b)| a + b).collect();
        run(&problem.with_free_displacement(u)?, settings)
    };
    let mut solution = solve_at(&rho, &settings)?;
    let mut relative = equilibrium.relative_residual(&solution.force);
    let (mut iterations, mut all_history) = (solution.iterations, solution.history.clone());
    for outer in 1..=MAX_OUTER {
        if relative <= target_residual || (outer == MAX_OUTER && relative <= acceptable) {
            return Ok(finish(
                problem,
                original,
                equilibrium,
                &kept,
                solution,
                &rho,
                outer,
                relative,
                iterations,
                all_history,
            ));
        }
        // Newton step: d(E r)/dρ = −E P (R W P)⁻¹ R Eᵀ on the current contact set, P mapping
        // the free parameters (normal force of a closed point, tangential force of a sticking
        // one) to r — a slipping Coulomb point's rT follows its rN — and R selecting their rows.
        let jac = active_set_jacobian(problem, &flexibility, e, &solution.force)?;
        // Regularised by the bonded model where the contact set does not control a direction
        // (no closed point, a sliding direction): the step is then the bonded one, shortened.
        let scale = m_bonded.diagonal().max();
        let regularised = jac + &m_bonded * 1e-8 + DMatrix::identity(k, k) * (1e-14 * scale);
        let Some(lu) = regularised.lu().try_inverse() else {
            return Err(no_equilibrium_detail(equilibrium, &solution));
        };
        let (residual, _) = equilibrium.residual(&solution.force);
        let step = lu * DVector::from_column_slice(&residual);
        // Backtracking on the equilibrium residual.
        let mut accepted = None;
        let mut length = 1.0;
        for _ in 0..12 {
            let trial: Vec<f64> = rho.iter().zip(step.iter()).map(|(r, d)| r + length * d).collect();
            settings.initial_force = Some(solution.force.clone());
            let candidate = solve_at(&trial, &settings)?;
            let value = equilibrium.relative_residual(&candidate.force);
            iterations += candidate.iterations;
            all_history.extend(candidate.history.iter().copied());
            if value < relative || value <= target_residual {
                accepted = Some((trial, candidate, value));
                break;
            }
            length *= 0.5;
        }
        match accepted {
            Some((trial, candidate, value)) => {
                rho = trial;
                solution = candidate;
                relative = value;
            }
            None if relative <= acceptable => {
                return Ok(finish(
                    problem,
                    original,
                    equilibrium,
                    &kept,
                    solution,
                    &rho,
                    outer,
                    relative,
                    iterations,
                    all_history,
                ))
            }
            None => return Err(no_equilibrium_detail(equilibrium, &solution)),
        }
    }
    Err(no_equilibrium_detail(equilibrium, &solution))
}

/// `E P (R W P)⁻¹ R Eᵀ` on the contact set of `r` (see [`solve_with_equilibrium`]).
fn active_set_jacobian(
    problem: &CondensedProblem,
    flexibility: &Flexibility,
    e: &DMatrix<f64>,
    r: &[f64],
) -> Result<DMatrix<f64>> {
    let m = problem.points();
    let scale = r.iter().fold(0.0f64, |a, v| a.max(v.abs())).max(f64::MIN_POSITIVE);
    let tiny = 1e-12 * scale;
    // Columns of P as (row of R, sparse column): (component, [(index, value)]).
    let mut columns: Vec<(usize, Vec<(usize, f64)>)> = Vec::new();
    for i in 0..m {
        let (rn, rt) = (r[2 * i], r[2 * i + 1]);
        if rn >= -tiny {
            continue; // open: rN = 0 at its bound
        }
        let threshold = problem.threshold_at(i, rn);
        let friction = !matches!(problem.friction(), FrictionLaw::None);
        let sticking = friction && rt.abs() < threshold - tiny;
        let mut normal = vec![(2 * i, 1.0)];
        if friction && !sticking {
            if let FrictionLaw::Coulomb { mu } = problem.friction() {
                // rT = σ μ (−rN): drT/drN = −σ μ.
                normal.push((2 * i + 1, -rt.signum() * mu[i]));
            }
        }
        columns.push((2 * i, normal));
        if sticking {
            columns.push((2 * i + 1, vec![(2 * i + 1, 1.0)]));
        }
    }
    let nf = columns.len();
    let k = e.nrows();
    if nf == 0 {
        return Ok(DMatrix::zeros(k, k));
    }
    // (R W P)⁻¹ R Eᵀ and E P.
    let ep = DMatrix::from_fn(k, nf, |row, b| columns[b].1.iter().map(|&(j, v)| e[(row, j)] * v).sum::<f64>());
    let re_t = DMatrix::from_fn(nf, k, |a, row| e[(row, columns[a].0)]);
    Ok(match flexibility.solve_reduced(&columns, &re_t)? {
        Some(x) => ep * x,
        None => DMatrix::zeros(k, k),
    })
}

/// Solves with `W` (the bonded model) and with its active-set reductions `R W P`: by Cholesky
/// and LU factorisations of a dense `W`; for an implicit `W` by Jacobi-preconditioned
/// conjugate gradients (GMRES for a non-symmetric `R W P`: sliding Coulomb points) on products
/// — a few right-hand sides (one per equilibrium condition) per outer step.
struct Flexibility<'p> {
    problem: &'p CondensedProblem<'p>,
    /// A dense `W` and its Cholesky factor.
    dense: Option<(&'p DMatrix<f64>, nalgebra::Cholesky<f64, nalgebra::Dyn>)>,
}

/// Relative residual of the Krylov solves with an implicit `W`.
const KRYLOV_TOLERANCE: f64 = 1e-10;

impl<'p> Flexibility<'p> {
    fn new(problem: &'p CondensedProblem<'p>) -> Result<Self> {
        let dense = match problem.delassus().as_dense() {
            Some(w) => Some((
                w,
                w.clone().cholesky().ok_or_else(|| {
                    Error::Usage("the flexibility of the dual contact forces is not positive definite".into())
                })?,
            )),
            None => None,
        };
        Ok(Flexibility { problem, dense })
    }

    /// `W⁻¹ B`.
    fn solve(&self, b: &DMatrix<f64>) -> Result<DMatrix<f64>> {
        match &self.dense {
            Some((_, cholesky)) => Ok(cholesky.solve(b)),
            None => {
                let w = self.problem.delassus();
                krylov_columns(&|x, y| w.apply(x, y), self.problem.diagonal(), b, true, "the bonded model W")
            }
        }
    }

    /// `(R W P)⁻¹ B`, `None` when singular (dense LU).
    fn solve_reduced(&self, columns: &[(usize, Vec<(usize, f64)>)], b: &DMatrix<f64>) -> Result<Option<DMatrix<f64>>> {
        let nf = columns.len();
        if let Some((w, _)) = &self.dense {
            let rwp = DMatrix::from_fn(nf, nf, |a, c| {
                columns[c].1.iter().map(|&(j, v)| w[(columns[a].0, j)] * v).sum::<f64>()
            });
            return Ok(rwp.lu().solve(b));
        }
        let w = self.problem.delassus();
        let n = w.size();
        let apply = |y: &[f64], out: &mut [f64]| {
            let mut x = vec![0.0; n];
            for ((_, column), yc) in columns.iter().zip(y) {
                for &(j, v) in column {
                    x[j] += v * yc;
                }
            }
            let mut wx = vec![0.0; n];
            w.apply(&x, &mut wx);
            for (o, (row, _)) in out.iter_mut().zip(columns) {
                *o = wx[*row];
            }
        };
        let symmetric = columns.iter().all(|(row, column)| column.len() == 1 && column[0].0 == *row);
        let diagonal: Vec<f64> = columns.iter().map(|(row, _)| self.problem.diagonal()[*row]).collect();
        krylov_columns(&apply, &diagonal, b, symmetric, "the active-set system R W P").map(Some)
    }
}

/// Solve `A X = B` column by column by a Krylov method on products (`symmetric`: CG, else
/// GMRES); an unconverged solve is an error naming `what`.
fn krylov_columns(
    apply: &dyn Fn(&[f64], &mut [f64]),
    diagonal: &[f64],
    b: &DMatrix<f64>,
    symmetric: bool,
    what: &str,
) -> Result<DMatrix<f64>> {
    let n = b.nrows();
    let max_iterations = 10 * n + 100;
    let mut x = DMatrix::zeros(n, b.ncols());
    for c in 0..b.ncols() {
        let rhs: Vec<f64> = b.column(c).iter().copied().collect();
        let result = if symmetric {
            krylov::conjugate_gradient(apply, diagonal, &rhs, KRYLOV_TOLERANCE, max_iterations)
        } else {
            krylov::gmres(apply, diagonal, &rhs, KRYLOV_TOLERANCE, 50, max_iterations)
        };
        if !result.converged {
            return Err(Error::SolverDiverged {
                solver: format!(
                    "dual formulation: {} on the implicit flexibility",
                    if symmetric { "conjugate gradients" } else { "GMRES" }
                ),
                reason: format!(
                    "{what} of the equilibrium conditions was not solved (relative residual {:.2e})",
                    result.relative_residual
                ),
                iterations: result.iterations,
                residual: result.relative_residual,
                tried: format!("Jacobi preconditioning, up to {max_iterations} iterations"),
            });
        }
        x.column_mut(c).copy_from_slice(&result.x);
    }
    Ok(x)
}

/// Make the contact forces balance the loads to round-off: `r ← r − E_Aᵀ (E_A E_Aᵀ)⁻¹ (E r − e)`
/// on the active components `A` (the normal force of a closed point and, with friction, its
/// tangential force), so that open points keep a zero force. Returns the relative residual
/// after the correction (unchanged forces and `None` when the active set does not control
/// every condition).
///
/// Why: the iteration stops at a relative residual of 1e-12 (a fraction of the solver's
/// tolerance), and the field is built by integrating the tractions around the boundary
/// ([`super::boundary`]): whatever the forces leave unbalanced is taken up by the one edge
/// where that integration closes, as a traction error of the force residual over `h` and of
/// the moment residual over `h²`. On the frictionless contact patch this gave a traction
/// residual of 5e-8 of the pressure at h = 0.03 (from an equilibrium residual of 1.7e-12) and
/// 1e-6 at h = 0.0115 with the forces as unknowns: the admissibility check refused the answer.
/// The correction is of the size of that residual, far below the contact checks' tolerances.
fn balance_exactly(equilibrium: &ContactEquilibrium, problem: &CondensedProblem, force: &mut [f64]) -> Option<f64> {
    let friction = !matches!(problem.friction(), FrictionLaw::None);
    let active: Vec<usize> = (0..force.len())
        .filter(|&j| force[j - j % 2] < 0.0 && (j % 2 == 0 || friction))
        .filter(|&j| equilibrium.matrix.column(j).amax() > 0.0)
        .collect();
    let k = equilibrium.rhs.len();
    if active.is_empty() || k == 0 {
        return None;
    }
    let ea = DMatrix::from_fn(k, active.len(), |i, a| equilibrium.matrix[(i, active[a])]);
    let gram = &ea * ea.transpose();
    let (residual, _) = equilibrium.residual(force);
    let multiplier = gram.cholesky()?.solve(&DVector::from_column_slice(&residual));
    let correction = ea.transpose() * multiplier;
    let mut corrected = force.to_vec();
    for (a, &j) in active.iter().enumerate() {
        corrected[j] -= correction[a];
    }
    // A correction that would flip the sign of a normal force is not round-off: keep the answer.
    if active.iter().any(|&j| j % 2 == 0 && corrected[j] > 0.0) {
        return None;
    }
    let after = equilibrium.relative_residual(&corrected);
    if after > equilibrium.relative_residual(force) {
        return None;
    }
    force.copy_from_slice(&corrected);
    Some(after)
}

/// The answer with its notes, and the rigid displacements of all the original rows.
#[allow(clippy::too_many_arguments)]
fn finish(
    problem: &CondensedProblem,
    original: &ContactEquilibrium,
    equilibrium: &ContactEquilibrium,
    kept: &[usize],
    mut solution: ContactSolution,
    rho: &[f64],
    outer: usize,
    relative: f64,
    iterations: usize,
    history: Vec<crate::contact::IterationRecord>,
) -> (ContactSolution, Vec<f64>, usize) {
    let balanced = balance_exactly(equilibrium, problem, &mut solution.force);
    let mut rigid = vec![0.0; original.rhs.len()];
    for (k, &i) in kept.iter().enumerate() {
        rigid[i] = rho[k];
    }
    solution.iterations = iterations;
    solution.history = history;
    solution.notes.push(format!(
        "equilibrium of the contact forces imposed by {outer} Newton step(s) on the rigid displacements, \
         relative residual {relative:.2e}{}",
        balanced.map_or(String::new(), |after| format!(", {after:.2e} after the final balance of the closed points"))
    ));
    // The displacement of the original problem: W r + u_free + Eᵀ ρ.
    if let Ok(mut u) = problem.displacement(&solution.force) {
        for (a, b) in u.iter_mut().zip(original.transpose_times(&rigid)) {
            *a += b;
        }
        solution.displacement = u;
    }
    (solution, rigid, outer)
}

fn no_equilibrium_detail(equilibrium: &ContactEquilibrium, solution: &ContactSolution) -> Error {
    let (residual, scale) = equilibrium.residual(&solution.force);
    no_equilibrium(&residual, &scale, solution)
}

fn no_equilibrium(residual: &[f64], scale: &[f64], solution: &ContactSolution) -> Error {
    let (normal, tangential) = solution.force.chunks(2).fold((0.0, 0.0), |(n, t), f| (n + f[0], t + f[1].abs()));
    Error::NoEquilibrium(format!(
        "dual formulation: the contact forces cannot balance the loads: the equilibrium conditions through the \
         contact part keep a residual {:?} against loads of {:?}; the body slides (the tangential load exceeds \
         what friction can carry) or is pulled away from the obstacle (normal contact force {normal:.4e}, \
         sum of |tangential| {tangential:.4e})",
        residual.iter().map(|v| format!("{v:.4e}")).collect::<Vec<_>>(),
        scale.iter().map(|v| format!("{v:.4e}")).collect::<Vec<_>>(),
    ))
}
