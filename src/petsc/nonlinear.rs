//! Nonlinear systems `F(x) = 0` through PETSc SNES, with the residual, the Jacobian and the
//! convergence test written in Rust ([`NonlinearSystem`]).
//!
//! ```text
//!   NonlinearSolver::new     the Jacobian's sparsity (this rank's CSR rows, global columns):
//!                            an AIJ matrix preallocated exactly (every entry of the pattern is
//!                            stored, zeros included), and the "ghosted" layout of x below
//!   NonlinearSolver::solve   SNES newtonls (line search "basic": full Newton steps; any
//!                            -<prefix>snes_linesearch_type from the options), KSP preonly + LU
//!                            (MUMPS) unless -<prefix>ksp_type / -<prefix>pc_type are given,
//!                            or KSP preonly + a shell preconditioner that calls the system's
//!                            own exact Jacobian solver when it has one
//!                            (NonlinearSystem::jacobian_solver / solve_jacobian)
//! ```
//!
//! ## What the callbacks see
//!
//! Every callback gets the **ghosted** iterate `x_local`: first this rank's owned entries (in
//! global order), then the *ghosts* — the off-rank entries that appear as columns of the owned
//! rows of the Jacobian pattern, in increasing global order. So the residual of a row may use
//! every unknown its Jacobian row couples to, and nothing else (that is what the pattern
//! means). [`NonlinearSolver::local_columns`] maps each pattern entry to its position in
//! `x_local`. The ghosts are brought in by one `VecScatter` per callback.
//!
//! - residual: `f[r] = F_{first_row + r}(x)` for the owned rows;
//! - Jacobian: the values of the owned rows in the pattern's order (`values[k]` is the entry
//!   of pattern position `k`); the matrix is refilled from them at every evaluation (a solver
//!   may modify its Jacobian in place, and the pattern never changes, so the LU symbolic
//!   analysis is reused) — except when the system solves its own Jacobians (shell
//!   preconditioner with KSP preonly: the matrix is never applied);
//! - convergence: called after every Newton step (and once at the initial guess, iteration 0)
//!   with the iterate and its residual; it decides (PETSc's norm tests are not used: a mixed
//!   system's residual mixes units);
//! - step length: a factor in `(0, 1]` applied to every Newton direction before PETSc's line
//!   search (with the default line search "basic", the step actually taken): the system's own
//!   globalization (a line search on its own merit function, damping when its active set
//!   cycles). It sees the ghosted iterate and the ghosted direction.
//!
//! ## Safety rules
//!
//! Callbacks run inside `catch_unwind` (a panic never crosses the FFI boundary: it becomes an
//! error). A callback's `Err` is kept and returned by [`NonlinearSolver::solve`] instead of
//! PETSc's generic code. Under MPI every callback's outcome is agreed over the ranks (one
//! reduction per callback): a failure on one rank makes every rank's callback fail, so that
//! SNES stops everywhere at the same point instead of leaving the other ranks waiting in its
//! next collective operation ([`super::Comm::first_failure`]; the ranks that did not fail
//! return [`Error::OtherRank`]). A system's callback that itself calls a collective operation
//! (a reduction) must not return early before it on one rank only: the others would wait there
//! (the full-space contact system computes its local quantities, which cannot fail, before its
//! reductions, and fails only after them, on every rank alike). The context pointer given to
//! PETSc points to a box that lives on `solve`'s stack frame until the SNES, which holds the
//! pointer, is destroyed (a guard destroys it before the box is dropped). A negative SNES reason becomes
//! [`Error::SolverDiverged`] with the method that ran and the options to try.
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::{cstring, from_c, petsc, to_petsc_int, Comm, Matrix, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// PETSc error code returned by a callback that failed or panicked (PETSC_ERR_LIB).
const CALLBACK_FAILED: sys::PetscErrorCode = 76;
/// MUMPS's workspace margin (percent) for the LU of a mixed system (see
/// [`Session::prefer_mumps_workspace`]).
const MIXED_LU_WORKSPACE: i32 = 100;
/// GMRES iterations allowed beyond [`FactorisationReuse::max_changed_rows`] (round-off).
const REUSE_EXTRA_ITERATIONS: usize = 10;
/// GMRES relative tolerance on the weighted residual when the factorisation is kept: each
/// Newton step is exact to this fraction of the residual it starts from.
const REUSE_RTOL: f64 = 1e-12;

/// The verdict of [`NonlinearSystem::converged`].
#[derive(Debug, Clone, PartialEq)]
pub enum Convergence {
    /// Not converged yet: go on.
    Iterating,
    /// Converged; the text says by which test (it becomes the reported reason).
    Converged(String),
    /// Give up; the text says why.
    Diverged(String),
}

/// A nonlinear system for [`NonlinearSolver::solve`] (see the module documentation for what
/// `x` holds in each callback).
pub trait NonlinearSystem {
    /// `f = F(x)` on the owned rows.
    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<()>;
    /// The Jacobian's values at `x`, one per pattern entry of the owned rows.
    fn jacobian(&mut self, x: &[f64], values: &mut [f64]) -> Result<()>;
    /// After Newton step `iteration` (0: the initial guess), with `f = F(x)` on the owned rows.
    fn converged(&mut self, iteration: usize, x: &[f64], f: &[f64]) -> Result<Convergence>;
    /// Length `t ∈ (0, 1]` of the next step along the Newton direction `d` (the update is
    /// `x − t d`, PETSc's sign convention), from the ghosted `x` and `d` (as the other
    /// callbacks see `x`): the system's own line search or damping. Default 1 (full steps).
    fn step_length(&mut self, x: &[f64], direction: &[f64]) -> Result<f64> {
        let _ = (x, direction);
        Ok(1.0)
    }
    /// Whether the system solves its own Jacobians (asked once, before the solve), and under
    /// which name the reports show that solver. When it does, and no
    /// `-<prefix>ksp_type`/`-<prefix>pc_type` is given, the KSP is `preonly` with a shell
    /// preconditioner calling [`NonlinearSystem::solve_jacobian`].
    fn jacobian_solver(&self) -> Option<String> {
        None
    }
    /// `d = J⁻¹ r` (owned entries) with the Jacobian of the last [`NonlinearSystem::jacobian`]
    /// call. Called only when [`NonlinearSystem::jacobian_solver`] names a solver.
    fn solve_jacobian(&mut self, r: &[f64], d: &mut [f64]) -> Result<()> {
        let _ = (r, d);
        Err(Error::PetscUsage("this nonlinear system does not solve its Jacobians".into()))
    }
    /// Whether the default inner solver (LU) may keep its factorisation from one Newton step to
    /// the next (asked once, before the solve; see "Keeping the factorisation" in the module
    /// documentation). Ignored when the system solves its own Jacobians or the options choose
    /// the inner solver.
    fn factorisation_reuse(&self) -> Option<FactorisationReuse> {
        None
    }
}

/// How the default LU inner solver keeps its factorisation across Newton steps (see the
/// module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct FactorisationReuse {
    /// Refactorise when more Jacobian rows than this (over all ranks) differ from the
    /// factorised ones; GMRES then converges in at most that many iterations plus one.
    pub max_changed_rows: usize,
    /// A weight per owned row (powers of two: scaling and unscaling are exact), so that the
    /// rows' residuals are comparable in GMRES's norm (forces and displacements, say).
    pub row_weights: Vec<f64>,
}

/// What a nonlinear solve did.
#[derive(Debug, Clone, serde::Serialize)]
pub struct NonlinearSolve {
    /// e.g. "PETSc SNES newtonls (line search basic), KSP preonly + lu (mumps)".
    pub method: String,
    /// The Krylov method of the inner linear solves.
    pub ksp_type: String,
    /// Their preconditioner.
    pub pc_type: String,
    /// The factorisation package (mumps, petsc, ...) for direct inner solves.
    pub factor_package: Option<String>,
    /// Newton steps.
    pub iterations: usize,
    /// Krylov iterations over all steps (1 per step for a direct solve).
    pub linear_iterations: usize,
    /// Evaluations of the residual function.
    pub residual_evaluations: usize,
    /// With [`FactorisationReuse`]: the numeric factorisations of the Jacobian (at most one per
    /// Newton step); `None` otherwise.
    pub factorisations: Option<usize>,
    /// SNES's converged reason, or ours.
    pub converged_reason: String,
}

/// A SNES solver for one sparsity pattern (see the module documentation).
pub struct NonlinearSolver<'s> {
    session: &'s Session,
    comm: Comm,
    jacobian: Matrix<'s>,
    first_row: usize,
    indptr: Vec<usize>,
    columns: Vec<sys::PetscInt>,
    local_columns: Vec<usize>,
    ghosts: Vec<usize>,
    local: Vector<'s>,
    scatter: ScatterGuard,
    prefix: String,
}

struct ScatterGuard(sys::VecScatter);
impl Drop for ScatterGuard {
    fn drop(&mut self) {
        // SAFETY: owned handle; errors ignored (Drop never panics).
        let _ = unsafe { sys::VecScatterDestroy(&mut self.0) };
    }
}
struct SnesGuard(sys::SNES);
impl Drop for SnesGuard {
    fn drop(&mut self) {
        // SAFETY: owned handle; errors ignored.
        let _ = unsafe { sys::SNESDestroy(&mut self.0) };
    }
}
struct IsGuard(sys::IS);
impl Drop for IsGuard {
    fn drop(&mut self) {
        // SAFETY: owned handle; errors ignored.
        let _ = unsafe { sys::ISDestroy(&mut self.0) };
    }
}

impl<'s> NonlinearSolver<'s> {
    /// The solver for a system of order `global` whose Jacobian has, on this rank, the CSR rows
    /// `first_row .. first_row + indptr.len() − 1` (global column indices, strictly increasing
    /// per row; the ranks' blocks follow each other in rank order). Options are read with
    /// `prefix` (e.g. `contact_`: `-contact_snes_monitor`, `-contact_ksp_type gmres`).
    pub fn new(
        session: &'s Session,
        comm: Comm,
        global: usize,
        first_row: usize,
        indptr: &[usize],
        indices: &[usize],
        prefix: &str,
    ) -> Result<Self> {
        let zeros = vec![0.0; indices.len()];
        // Checks the pattern (sorted, in range, layout) and stores every entry, zeros included.
        let jacobian = Matrix::from_csr_rows(session, comm, global, first_row, indptr, indices, &zeros, 1, false)?;
        let owned = jacobian.owned_rows();
        let mut ghosts: Vec<usize> = indices.iter().copied().filter(|c| !owned.contains(c)).collect();
        ghosts.sort_unstable();
        ghosts.dedup();
        let local_columns: Vec<usize> =
            indices
                .iter()
                .map(|&c| {
                    if owned.contains(&c) {
                        c - owned.start
                    } else {
                        owned.len() + ghosts.binary_search(&c).unwrap_or(0)
                    }
                })
                .collect();
        let columns =
            indices.iter().map(|&c| to_petsc_int(c, "column index")).collect::<Result<Vec<sys::PetscInt>>>()?;
        let from: Vec<sys::PetscInt> = owned
            .clone()
            .chain(ghosts.iter().copied())
            .map(|c| to_petsc_int(c, "ghosted index"))
            .collect::<Result<_>>()?;
        let n_local = from.len();
        let local = Vector::new(session, session.self_comm(), n_local, n_local)?;
        let template = jacobian.create_vector()?;
        let mut is: sys::IS = std::ptr::null_mut();
        petsc!(ISCreateGeneral(
            session.self_comm().raw(),
            to_petsc_int(n_local, "ghosted size")?,
            from.as_ptr(),
            sys::PetscCopyMode::PETSC_COPY_VALUES,
            &mut is
        ))?;
        let is = IsGuard(is);
        let mut scatter: sys::VecScatter = std::ptr::null_mut();
        petsc!(VecScatterCreate(template.raw, is.0, local.raw, std::ptr::null_mut(), &mut scatter))?;
        Ok(NonlinearSolver {
            session,
            comm,
            jacobian,
            first_row,
            indptr: indptr.to_vec(),
            columns,
            local_columns,
            ghosts,
            local,
            scatter: ScatterGuard(scatter),
            prefix: prefix.to_string(),
        })
    }

    /// For each entry of the pattern (in order), its position in the ghosted `x` of the
    /// callbacks.
    pub fn local_columns(&self) -> &[usize] {
        &self.local_columns
    }

    /// The off-rank unknowns the owned rows couple to (global indices, increasing); they follow
    /// the owned entries in the ghosted `x`.
    pub fn ghosts(&self) -> &[usize] {
        &self.ghosts
    }

    /// Do the options choose the inner linear solver (`-<prefix>ksp_type` or `-<prefix>pc_type`)?
    /// Then it solves the Jacobians, whatever the system offers.
    pub fn inner_solver_from_options(&self) -> Result<bool> {
        Ok(self.session.has_option(&format!("-{}ksp_type", self.prefix))?
            || self.session.has_option(&format!("-{}pc_type", self.prefix))?)
    }

    /// Solve `F(x) = 0` from the initial guess `x` (this rank's owned entries), which receives
    /// the solution. At most `max_iterations` Newton steps.
    pub fn solve(
        &mut self,
        x: &mut [f64],
        system: &mut dyn NonlinearSystem,
        max_iterations: usize,
    ) -> Result<NonlinearSolve> {
        let owned = self.jacobian.owned_rows();
        if x.len() != owned.len() {
            return Err(Error::PetscUsage(format!(
                "nonlinear solve: {} initial values for {} owned unknowns",
                x.len(),
                owned.len()
            )));
        }
        let mut xv = self.jacobian.create_vector()?;
        xv.set_owned(x)?;
        let residual = xv.duplicate()?;
        let mut context = Box::new(Context {
            system,
            scatter: self.scatter.0,
            local: self.local.raw,
            owned: owned.len(),
            first_row: self.first_row,
            indptr: &self.indptr,
            columns: &self.columns,
            values: vec![0.0; self.columns.len()],
            error: None,
            verdict: None,
            own_solver: false,
            reuse: None,
            comm: self.comm,
            ranks: self.comm.size()?,
        });
        let ctx = &mut *context as *mut Context as *mut c_void;
        let mut snes: sys::SNES = std::ptr::null_mut();
        petsc!(SNESCreate(self.comm.raw(), &mut snes))?;
        let guard = SnesGuard(snes);
        let prefix = cstring(&self.prefix)?;
        petsc!(SNESSetOptionsPrefix(snes, prefix.as_ptr()))?;
        petsc!(SNESSetType(snes, c"newtonls".as_ptr()))?;
        petsc!(SNESSetFunction(snes, residual.raw, Some(residual_callback), ctx))?;
        petsc!(SNESSetJacobian(snes, self.jacobian.raw, self.jacobian.raw, Some(jacobian_callback), ctx))?;
        petsc!(SNESSetConvergenceTest(snes, Some(convergence_callback), ctx, None))?;
        let max_it = to_petsc_int(max_iterations.max(1), "iteration limit")?;
        petsc!(SNESSetTolerances(snes, 0.0, 0.0, 0.0, max_it, 1_000_000))?;
        let mut line_search: sys::SNESLineSearch = std::ptr::null_mut();
        petsc!(SNESGetLineSearch(snes, &mut line_search))?;
        petsc!(SNESLineSearchSetType(line_search, c"basic".as_ptr()))?;
        let mut ksp: sys::KSP = std::ptr::null_mut();
        petsc!(SNESGetKSP(snes, &mut ksp))?;
        let user_inner = self.inner_solver_from_options()?;
        let own_solver = if user_inner { None } else { context.system.jacobian_solver() };
        if let Some(name) = own_solver {
            let mut pc: sys::PC = std::ptr::null_mut();
            petsc!(KSPGetPC(ksp, &mut pc))?;
            petsc!(KSPSetType(ksp, c"preonly".as_ptr()))?;
            petsc!(PCSetType(pc, c"shell".as_ptr()))?;
            petsc!(PCShellSetContext(pc, ctx))?;
            petsc!(PCShellSetApply(pc, Some(shell_apply_callback)))?;
            let name = cstring(&name)?;
            petsc!(PCShellSetName(pc, name.as_ptr()))?;
            context.own_solver = true;
        } else if !user_inner {
            let mut pc: sys::PC = std::ptr::null_mut();
            petsc!(KSPGetPC(ksp, &mut pc))?;
            petsc!(PCSetType(pc, c"lu".as_ptr()))?;
            petsc!(PCFactorSetMatSolverType(pc, c"mumps".as_ptr()))?;
            self.session.prefer_amf_ordering(&self.prefix)?;
            self.session.prefer_mumps_workspace(&self.prefix, MIXED_LU_WORKSPACE)?;
            match context.system.factorisation_reuse() {
                Some(policy) if policy.row_weights.len() == owned.len() => {
                    // GMRES on the (row-weighted) Jacobian, preconditioned on the right by the
                    // last factorisation: its residual is the true one.
                    // A fresh factorisation solves exactly (preonly); kept factors switch the
                    // KSP to GMRES for that step (keep_or_refactorise).
                    let limit = to_petsc_int(policy.max_changed_rows + REUSE_EXTRA_ITERATIONS, "GMRES iterations")?;
                    petsc!(KSPSetType(ksp, c"preonly".as_ptr()))?;
                    petsc!(KSPSetPCSide(ksp, sys::PCSide::PC_RIGHT))?;
                    // A step whose GMRES stopped at its limit is still a descent step of the
                    // system's own globalization; the next Jacobian is then factorised afresh.
                    petsc!(SNESSetMaxLinearSolveFailures(snes, to_petsc_int(max_iterations.max(1), "failures")?))?;
                    let mut weights = xv.duplicate()?;
                    weights.set_owned(&policy.row_weights)?;
                    petsc!(KSPSetPreSolve(ksp, Some(weigh_rhs_callback), ctx))?;
                    petsc!(KSPSetPostSolve(ksp, Some(unweigh_rhs_callback), ctx))?;
                    context.reuse = Some(ReuseState {
                        max_changed_rows: policy.max_changed_rows,
                        weights: policy.row_weights,
                        weight_vector: weights,
                        factored: None,
                        filled: None,
                        limit,
                        factorisations: 0,
                    });
                }
                Some(policy) => {
                    return Err(Error::PetscUsage(format!(
                        "factorisation reuse: {} row weights for {} owned rows",
                        policy.row_weights.len(),
                        owned.len()
                    )))
                }
                None => petsc!(KSPSetType(ksp, c"preonly".as_ptr()))?,
            }
        } else {
            // Iterative inner solves: tight by default, so that Newton keeps its speed.
            petsc!(KSPSetTolerances(ksp, 1e-12, 1e-50, 1e8, 10_000))?;
        }
        petsc!(SNESSetFromOptions(snes))?;
        // After SetFromOptions: a line search type chosen there keeps the damping hook.
        petsc!(SNESGetLineSearch(snes, &mut line_search))?;
        petsc!(SNESLineSearchSetPreCheck(line_search, Some(precheck_callback), ctx))?;
        let code = {
            // SAFETY: snes and xv are live handles; ctx outlives the call (it is dropped after
            // the SNES guard).
            unsafe { sys::SNESSolve(snes, std::ptr::null_mut(), xv.raw) }
        };
        if let Some(e) = context.error.take() {
            return Err(e);
        }
        super::check(code, "SNESSolve")?;
        let mut reason = sys::SNESConvergedReason(0);
        petsc!(SNESGetConvergedReason(snes, &mut reason))?;
        let mut reason_str: *const std::ffi::c_char = std::ptr::null();
        petsc!(SNESGetConvergedReasonString(snes, &mut reason_str))?;
        let (mut its, mut lits, mut fevals): (sys::PetscInt, sys::PetscInt, sys::PetscInt) = (0, 0, 0);
        petsc!(SNESGetIterationNumber(snes, &mut its))?;
        petsc!(SNESGetLinearSolveIterations(snes, &mut lits))?;
        petsc!(SNESGetNumberFunctionEvals(snes, &mut fevals))?;
        let mut fnorm = 0.0;
        petsc!(SNESGetFunctionNorm(snes, &mut fnorm))?;
        let (ksp_type, mut pc_type, factor_package) = ksp_names(ksp)?;
        if pc_type == "shell" {
            let mut pc: sys::PC = std::ptr::null_mut();
            petsc!(KSPGetPC(ksp, &mut pc))?;
            let mut name: *const std::ffi::c_char = std::ptr::null();
            petsc!(PCShellGetName(pc, &mut name))?;
            if !name.is_null() {
                pc_type = format!("shell ({})", from_c(name));
            }
        }
        let mut ls_type: sys::SNESLineSearchType = std::ptr::null();
        petsc!(SNESLineSearchGetType(line_search, &mut ls_type))?;
        let mut snes_type: sys::SNESType = std::ptr::null();
        petsc!(SNESGetType(snes, &mut snes_type))?;
        let method = format!(
            "PETSc SNES {} (line search {}), KSP {ksp_type} + {pc_type}{}",
            from_c(snes_type),
            from_c(ls_type),
            factor_package.as_ref().map(|p| format!(" ({p})")).unwrap_or_default()
        );
        let verdict = context.verdict.take();
        let factorisations = context.reuse.as_ref().map(|r| r.factorisations);
        drop(guard);
        drop(context);
        let petsc_reason = from_c(reason_str);
        let solve = NonlinearSolve {
            method: method.clone(),
            ksp_type,
            pc_type,
            factor_package,
            iterations: its.max(0) as usize,
            linear_iterations: lits.max(0) as usize,
            residual_evaluations: fevals.max(0) as usize,
            factorisations,
            converged_reason: match &verdict {
                Some(Convergence::Converged(why)) => why.clone(),
                _ => petsc_reason.clone(),
            },
        };
        if reason.0 < 0 {
            let petsc_reason_name = petsc_reason.clone();
            let why = match verdict {
                Some(Convergence::Diverged(why)) => why,
                _ => petsc_reason,
            };
            return Err(Error::SolverDiverged {
                solver: method.clone(),
                reason: why,
                iterations: solve.iterations,
                residual: fnorm,
                tried: format!(
                    "{method}, up to {max_iterations} Newton steps; {}; watch it with -{p}snes_monitor \
                     -{p}snes_converged_reason",
                    advice(&petsc_reason_name, &self.prefix),
                    p = self.prefix
                ),
            });
        }
        x.copy_from_slice(&xv.owned_values()?);
        Ok(solve)
    }
}

/// What to try after SNES stopped for `reason` (PETSc's reason name), options under `prefix`.
/// Each suggestion is one that changes the outcome of that failure (the contact tests force
/// these failures and follow the advice).
fn advice(reason: &str, prefix: &str) -> String {
    let p = prefix;
    match reason {
        "DIVERGED_MAX_IT" => format!("allow more steps (-{p}snes_max_it, or max_iterations in the scene)"),
        "DIVERGED_LINEAR_SOLVE" => format!(
            "the inner linear solver failed: leave -{p}ksp_type and -{p}pc_type at their default (a direct \
             factorisation; the system is indefinite)"
        ),
        "DIVERGED_FNORM_NAN" => "the residual is not finite: check the loads, the material and the geometry \
             for values whose products overflow"
            .to_string(),
        "DIVERGED_LINE_SEARCH" | "DIVERGED_LOCAL_MIN" => format!(
            "the line search stalled: leave -{p}snes_linesearch_type at its default (basic: the full Newton step)"
        ),
        _ => format!("try the default inner solver (no -{p}ksp_type/-{p}pc_type) and more steps (-{p}snes_max_it)"),
    }
}

fn ksp_names(ksp: sys::KSP) -> Result<(String, String, Option<String>)> {
    let mut kt: sys::KSPType = std::ptr::null();
    petsc!(KSPGetType(ksp, &mut kt))?;
    let mut pc: sys::PC = std::ptr::null_mut();
    petsc!(KSPGetPC(ksp, &mut pc))?;
    let mut pt: sys::PCType = std::ptr::null();
    petsc!(PCGetType(pc, &mut pt))?;
    let (k, p) = (from_c(kt), from_c(pt));
    let package = if p == "lu" || p == "cholesky" {
        let mut st: sys::MatSolverType = std::ptr::null();
        petsc!(PCFactorGetMatSolverType(pc, &mut st))?;
        Some(if st.is_null() { "petsc".to_string() } else { from_c(st) })
    } else {
        None
    };
    Ok((k, p, package))
}

/// What the callbacks reach through PETSc's context pointer.
struct Context<'a> {
    system: &'a mut dyn NonlinearSystem,
    scatter: sys::VecScatter,
    /// The ghosted sequential vector.
    local: sys::Vec,
    owned: usize,
    first_row: usize,
    indptr: &'a [usize],
    columns: &'a [sys::PetscInt],
    values: Vec<f64>,
    /// The first error a callback returned (or a panic), reported by `solve`.
    error: Option<Error>,
    /// The last verdict of the convergence test.
    verdict: Option<Convergence>,
    /// The system solves its own Jacobians (shell preconditioner, KSP preonly).
    own_solver: bool,
    /// The default LU keeps its factorisation across steps ([`FactorisationReuse`]).
    reuse: Option<ReuseState<'a>>,
    /// The solver's communicator and its size: every callback's outcome is agreed over it.
    comm: Comm,
    ranks: usize,
}

/// The factorisation kept by the default LU (see [`FactorisationReuse`]).
struct ReuseState<'s> {
    max_changed_rows: usize,
    /// The row weights, and the same as a PETSc vector (the right-hand side is weighted in
    /// KSP's pre-solve hook and restored in its post-solve hook).
    weights: Vec<f64>,
    weight_vector: Vector<'s>,
    /// The Jacobian values (owned rows, pattern order) of the last factorisation.
    factored: Option<Vec<f64>>,
    /// The values last filled into the matrix (rows that did not change are not set again).
    filled: Option<Vec<f64>>,
    /// The GMRES iteration limit of a step with kept factors.
    limit: sys::PetscInt,
    factorisations: usize,
}

impl Context<'_> {
    fn keep(&mut self, e: Error) -> sys::PetscErrorCode {
        if self.error.is_none() {
            self.error = Some(e);
        }
        CALLBACK_FAILED
    }

    /// Scatter `x` into the ghosted vector and run `f` on its entries.
    fn with_ghosted<T>(&mut self, x: sys::Vec, f: impl FnOnce(&mut Self, &[f64]) -> T) -> Result<T> {
        petsc!(VecScatterBegin(
            self.scatter,
            x,
            self.local,
            sys::InsertMode::INSERT_VALUES,
            sys::ScatterMode::SCATTER_FORWARD
        ))?;
        petsc!(VecScatterEnd(
            self.scatter,
            x,
            self.local,
            sys::InsertMode::INSERT_VALUES,
            sys::ScatterMode::SCATTER_FORWARD
        ))?;
        let mut n: sys::PetscInt = 0;
        petsc!(VecGetLocalSize(self.local, &mut n))?;
        let mut ptr: *const f64 = std::ptr::null();
        petsc!(VecGetArrayRead(self.local, &mut ptr))?;
        let copy: Vec<f64> = if n > 0 {
            // SAFETY: the array holds n entries until restored.
            unsafe { std::slice::from_raw_parts(ptr, n as usize) }.to_vec()
        } else {
            Vec::new()
        };
        petsc!(VecRestoreArrayRead(self.local, &mut ptr))?;
        Ok(f(self, &copy))
    }
}

/// Run `body` on the context, catching panics and keeping errors.
fn guarded(ctx: *mut c_void, body: impl FnOnce(&mut Context) -> Result<()>) -> sys::PetscErrorCode {
    // SAFETY: ctx is the boxed Context of `solve`, alive during SNESSolve; PETSc calls back
    // on this thread only, one callback at a time.
    let context = unsafe { &mut *(ctx as *mut Context) };
    let outcome = catch_unwind(AssertUnwindSafe(|| body(&mut *context)));
    let code = match outcome {
        Ok(Ok(())) => 0,
        Ok(Err(e)) => context.keep(e),
        Err(panic) => {
            let message = super::panic_message(panic.as_ref());
            context.keep(Error::PetscUsage(format!("a nonlinear-system callback panicked: {message}")))
        }
    };
    // Every rank returns the same verdict: a failure on one rank alone would leave the others
    // waiting in SNES's next collective operation.
    if context.ranks > 1 {
        match context.comm.first_failure(code != 0) {
            Ok(Some(rank)) if code == 0 => {
                return context.keep(Error::OtherRank { rank, during: "a nonlinear-system callback" })
            }
            Ok(_) => {}
            Err(e) => return context.keep(e),
        }
    }
    code
}

unsafe extern "C" fn residual_callback(
    _snes: sys::SNES,
    x: sys::Vec,
    f: sys::Vec,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    guarded(ctx, |c| {
        let owned = c.owned;
        let mut ptr: *mut f64 = std::ptr::null_mut();
        petsc!(VecGetArray(f, &mut ptr))?;
        let result = c.with_ghosted(x, |c, xl| {
            let out: &mut [f64] = if owned > 0 {
                // SAFETY: f has the layout of the unknowns: `owned` local entries.
                unsafe { std::slice::from_raw_parts_mut(ptr, owned) }
            } else {
                &mut []
            };
            c.system.residual(xl, out)
        });
        petsc!(VecRestoreArray(f, &mut ptr))?;
        result?
    })
}

unsafe extern "C" fn jacobian_callback(
    snes: sys::SNES,
    x: sys::Vec,
    jac: sys::Mat,
    pre: sys::Mat,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    guarded(ctx, |c| {
        let mut values = std::mem::take(&mut c.values);
        let result = c.with_ghosted(x, |c, xl| c.system.jacobian(xl, &mut values));
        let fill = |m: sys::Mat, c: &Context| -> Result<()> {
            let mut weighted = Vec::new();
            // With the default LU kept by this wrapper (never factorised in place), the matrix
            // holds the last values filled: only rows that changed are set again (the force
            // rows of a contact problem never do).
            let filled = c.reuse.as_ref().and_then(|r| r.filled.as_ref());
            for r in 0..c.indptr.len() - 1 {
                let (a, b) = (c.indptr[r], c.indptr[r + 1]);
                if filled.is_some_and(|f| f[a..b] == values[a..b]) {
                    continue;
                }
                let row = (c.first_row + r) as sys::PetscInt;
                let row_values = match &c.reuse {
                    Some(reuse) => {
                        weighted.clear();
                        weighted.extend(values[a..b].iter().map(|v| v * reuse.weights[r]));
                        &weighted[..]
                    }
                    None => &values[a..b],
                };
                petsc!(MatSetValues(
                    m,
                    1,
                    &row,
                    (b - a) as sys::PetscInt,
                    c.columns[a..b].as_ptr(),
                    row_values.as_ptr(),
                    sys::InsertMode::INSERT_VALUES
                ))?;
            }
            petsc!(MatAssemblyBegin(m, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
            petsc!(MatAssemblyEnd(m, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))
        };
        let outcome = result.and_then(|r| r).and_then(|_| {
            if c.own_solver {
                // The shell preconditioner solves with the system's own data: the matrix is
                // never applied (KSP preonly), so it is not refilled.
                return Ok(());
            }
            fill(pre, c)?;
            if jac != pre {
                fill(jac, c)?;
            }
            if c.reuse.is_some() {
                keep_or_refactorise(snes, c, &values)?;
            }
            if let Some(reuse) = c.reuse.as_mut() {
                match &mut reuse.filled {
                    Some(filled) => filled.copy_from_slice(&values),
                    None => reuse.filled = Some(values.clone()),
                }
            }
            Ok(())
        });
        c.values = values;
        outcome
    })
}

/// Keep the last factorisation for this Jacobian, or let the next solve factorise it: kept
/// while at most `max_changed_rows` rows (over all ranks) differ from the factorised ones and
/// the last GMRES converged within its limit.
fn keep_or_refactorise(snes: sys::SNES, c: &mut Context, values: &[f64]) -> Result<()> {
    let mut ksp: sys::KSP = std::ptr::null_mut();
    petsc!(SNESGetKSP(snes, &mut ksp))?;
    let mut reason = sys::KSPConvergedReason(0);
    petsc!(KSPGetConvergedReason(ksp, &mut reason))?;
    let Some(reuse) = c.reuse.as_mut() else { return Ok(()) };
    let changed = match &reuse.factored {
        Some(factored) => (0..c.indptr.len() - 1)
            .filter(|&r| {
                let (a, b) = (c.indptr[r], c.indptr[r + 1]);
                values[a..b] != factored[a..b]
            })
            .count(),
        None => usize::MAX,
    };
    let changed = if c.ranks > 1 { c.comm.sum(&[changed.min(1 << 50) as f64])?[0] as usize } else { changed };
    let keep = reuse.factored.is_some() && changed <= reuse.max_changed_rows && reason.0 >= 0;
    if !keep {
        reuse.factored = Some(values.to_vec());
        reuse.factorisations += 1;
    }
    // SNES sets KSP's reuse flag after this callback from its preconditioner lag: −1 keeps
    // the factors, −2 rebuilds them once (then −1).
    petsc!(SNESSetLagPreconditioner(snes, if keep { -1 } else { -2 }))?;
    if keep {
        petsc!(KSPSetType(ksp, c"gmres".as_ptr()))?;
        petsc!(KSPGMRESSetRestart(ksp, reuse.limit))?;
        petsc!(KSPSetPCSide(ksp, sys::PCSide::PC_RIGHT))?;
        petsc!(KSPSetTolerances(ksp, REUSE_RTOL, 0.0, 1e8, reuse.limit))
    } else {
        petsc!(KSPSetType(ksp, c"preonly".as_ptr()))
    }
}

/// KSP's pre-solve hook with a kept factorisation: weigh the right-hand side's rows (the
/// Jacobian's rows were weighed when filled).
unsafe extern "C" fn weigh_rhs_callback(
    _ksp: sys::KSP,
    b: sys::Vec,
    _x: sys::Vec,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    weigh_rhs(b, ctx, true)
}

/// KSP's post-solve hook: the right-hand side (SNES's residual vector) restored exactly (the
/// weights are powers of two).
unsafe extern "C" fn unweigh_rhs_callback(
    _ksp: sys::KSP,
    b: sys::Vec,
    _x: sys::Vec,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    weigh_rhs(b, ctx, false)
}

/// `b` times the row weights (`multiply`), or divided by them.
fn weigh_rhs(b: sys::Vec, ctx: *mut c_void, multiply: bool) -> sys::PetscErrorCode {
    guarded(ctx, |c| match &c.reuse {
        Some(reuse) if multiply => petsc!(VecPointwiseMult(b, b, reuse.weight_vector.raw)),
        Some(reuse) => petsc!(VecPointwiseDivide(b, b, reuse.weight_vector.raw)),
        None => Ok(()),
    })
}

unsafe extern "C" fn convergence_callback(
    snes: sys::SNES,
    iteration: sys::PetscInt,
    _xnorm: f64,
    _snorm: f64,
    _fnorm: f64,
    reason: *mut sys::SNESConvergedReason,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    guarded(ctx, |c| {
        let mut x: sys::Vec = std::ptr::null_mut();
        petsc!(SNESGetSolution(snes, &mut x))?;
        let mut f: sys::Vec = std::ptr::null_mut();
        petsc!(SNESGetFunction(snes, &mut f, std::ptr::null_mut(), std::ptr::null_mut()))?;
        let f_owned = read_owned(f, c.owned)?;
        let verdict = c.with_ghosted(x, |c, xl| c.system.converged(iteration.max(0) as usize, xl, &f_owned))??;
        let code = match &verdict {
            Convergence::Iterating => sys::SNESConvergedReason::SNES_CONVERGED_ITERATING,
            Convergence::Converged(_) => sys::SNESConvergedReason::SNES_CONVERGED_FNORM_ABS,
            Convergence::Diverged(_) => sys::SNESConvergedReason::SNES_DIVERGED_DTOL,
        };
        // SAFETY: PETSc passes a valid pointer to the reason.
        unsafe { *reason = code };
        c.verdict = Some(verdict);
        Ok(())
    })
}

/// The `owned` local entries of a vector with the unknowns' layout, copied.
fn read_owned(v: sys::Vec, owned: usize) -> Result<Vec<f64>> {
    let mut ptr: *const f64 = std::ptr::null();
    petsc!(VecGetArrayRead(v, &mut ptr))?;
    let out = if owned > 0 {
        // SAFETY: the vector has `owned` local entries until restored.
        unsafe { std::slice::from_raw_parts(ptr, owned) }.to_vec()
    } else {
        Vec::new()
    };
    petsc!(VecRestoreArrayRead(v, &mut ptr))?;
    Ok(out)
}

unsafe extern "C" fn shell_apply_callback(pc: sys::PC, r: sys::Vec, d: sys::Vec) -> sys::PetscErrorCode {
    let mut ctx: *mut c_void = std::ptr::null_mut();
    // SAFETY: the shell's context is the boxed Context of `solve` (set with the shell).
    let code = unsafe { sys::PCShellGetContext(pc, &mut ctx as *mut *mut c_void as *mut c_void) };
    if code != 0 || ctx.is_null() {
        return CALLBACK_FAILED;
    }
    guarded(ctx, |c| {
        let owned = c.owned;
        let rhs = read_owned(r, owned)?;
        let mut out = vec![0.0; owned];
        c.system.solve_jacobian(&rhs, &mut out)?;
        let mut dp: *mut f64 = std::ptr::null_mut();
        petsc!(VecGetArray(d, &mut dp))?;
        if owned > 0 {
            // SAFETY: as above.
            unsafe { std::slice::from_raw_parts_mut(dp, owned) }.copy_from_slice(&out);
        }
        petsc!(VecRestoreArray(d, &mut dp))
    })
}

unsafe extern "C" fn precheck_callback(
    _line_search: sys::SNESLineSearch,
    x: sys::Vec,
    y: sys::Vec,
    changed: *mut sys::PetscBool,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    guarded(ctx, |c| {
        // Both ghosted: a row's quantities may read off-rank entries (every rank scatters).
        let xs = c.with_ghosted(x, |_, xl| xl.to_vec())?;
        let ys = c.with_ghosted(y, |_, yl| yl.to_vec())?;
        let scale = c.system.step_length(&xs, &ys)?;
        if !(scale > 0.0 && scale <= 1.0) {
            return Err(Error::PetscUsage(format!("step scale {scale} is not in (0, 1]")));
        }
        if scale < 1.0 {
            petsc!(VecScale(y, scale))?;
            // SAFETY: PETSc passes a valid pointer.
            unsafe { *changed = sys::PetscBool::PETSC_TRUE };
        }
        Ok(())
    })
}
