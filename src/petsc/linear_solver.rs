//! Linear solves through PETSc KSP, configured from the options database.
//!
//! Default (no option given): a direct solve, `-ksp_type preonly -pc_type cholesky
//! -pc_factor_mat_solver_type mumps` (the matrix is symmetric positive definite after our
//! symmetric Dirichlet elimination). Any option overrides it, e.g.
//! `-ksp_type cg -pc_type icc -pc_factor_levels 2`. One convenience: when `-pc_type` names a
//! preconditioner that is not a direct factorisation and `-ksp_type` is not given, the Krylov
//! method becomes CG instead of `preonly` (which would apply the preconditioner once and
//! return a wrong answer). The default MUMPS factorisation uses the AMF ordering
//! (`-mat_mumps_icntl_7 2`), about twice as fast as Debian's fallback PORD (no METIS there).
//!
//! `-pc_type ict` (any prefix) is our threshold incomplete Cholesky
//! ([`crate::sparse::incomplete_cholesky`]) as a PCSHELL: `-pc_ict_drop_tolerance τ` (default
//! 1e-3), `-pc_ict_fill p` (default: no limit); one process only (see `super::ict`). Like any
//! non-direct `-pc_type` it gets CG when `-ksp_type` is not given; the report's `pc_type` reads
//! "ict (drop tolerance …)".
//!
//! Every solve is checked twice: PETSc's converged reason (a negative reason is
//! [`Error::SolverDiverged`]) and, independently, the true relative residual ‖b − Ax‖/‖b‖
//! computed after the solve, which must not exceed `max(1e-6, 100·rtol)`.
//!
//! SYMMLQ: PETSc 3.18 reports its iteration-0 residual on a different scale, so we give it an
//! absolute tolerance rtol·‖b‖_{M⁻¹} (rtol 1e-8 by default) and no divergence test, see
//! `fix_symmlq_tolerance`.
use std::marker::PhantomData;

use super::{cstring, from_c, ict, petsc, Comm, Matrix, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// What a solve did, for the report.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SolveStats {
    /// The Krylov method, e.g. `"cg"`, `"preonly"`.
    pub ksp_type: String,
    /// The preconditioner, e.g. `"cholesky"`, `"gamg"`.
    pub pc_type: String,
    /// The factorisation package (mumps, petsc, ...) for direct solves.
    pub factor_package: Option<String>,
    /// Krylov iterations (1 for a direct solve).
    pub iterations: usize,
    /// PETSc's converged reason, e.g. `"CONVERGED_RTOL"`.
    pub converged_reason: String,
    /// ‖b − Ax‖ / ‖b‖, computed by us after the solve.
    pub relative_residual: f64,
    /// Wall-clock seconds of the solve (setup and factorisation included).
    pub seconds: f64,
}

/// A PETSc KSP: a linear solver for one matrix, configured from the options database (MUMPS
/// Cholesky by default).
pub struct LinearSolver<'s> {
    raw: sys::KSP,
    comm: Comm,
    last: Option<SolveStats>,
    prefix: String,
    session: &'s Session,
    /// The MUMPS ordering (ICNTL(7)) used unless the user gives one: AMF (2) by default.
    ordering: i32,
    /// The operator is symmetric indefinite (a saddle point): the Krylov default for a
    /// non-direct `-pc_type` is SYMMLQ instead of CG.
    indefinite: bool,
    _p: PhantomData<&'s Session>,
}

const DIRECT_PCS: [&str; 2] = ["lu", "cholesky"];

impl<'s> LinearSolver<'s> {
    /// A KSP on `comm` whose options are read with `prefix` (e.g. "" for the main solver,
    /// "contact_" for an inner one).
    pub fn new(session: &'s Session, comm: Comm, prefix: &str) -> Result<Self> {
        let mut raw: sys::KSP = std::ptr::null_mut();
        petsc!(KSPCreate(comm.raw(), &mut raw))?;
        let ksp = LinearSolver {
            raw,
            comm,
            last: None,
            prefix: prefix.to_string(),
            session,
            ordering: 2,
            indefinite: false,
            _p: PhantomData,
        };
        if !prefix.is_empty() {
            let p = cstring(prefix)?;
            petsc!(KSPSetOptionsPrefix(ksp.raw, p.as_ptr()))?;
        }
        Ok(ksp)
    }

    /// Use MUMPS ordering `icntl_7` (ICNTL(7)) when the direct default is used and the user
    /// gives no ordering; call before [`LinearSolver::set_operator`].
    pub fn prefer_ordering(&mut self, icntl_7: i32) {
        self.ordering = icntl_7;
    }

    /// The operator will be symmetric indefinite: with a non-direct `-pc_type` and no
    /// `-ksp_type`, use SYMMLQ (CG would break down); the preconditioner must then be
    /// symmetric positive definite (`-pc_type jacobi`, whose zero diagonal entries become 1).
    /// The direct default stays MUMPS "Cholesky", an LDLᵀ factorisation for such a matrix.
    pub fn set_indefinite(&mut self) {
        self.indefinite = true;
    }

    /// Set the operator and configure the solver: defaults first, then the options database.
    pub fn set_operator(&mut self, matrix: &Matrix<'s>) -> Result<()> {
        petsc!(KSPSetOperators(self.raw, matrix.raw, matrix.raw))?;
        let ksp_opt = format!("-{}ksp_type", self.prefix);
        let pc_opt = format!("-{}pc_type", self.prefix);
        let user_ksp = self.session.option(&ksp_opt)?;
        let user_pc = self.session.option(&pc_opt)?;
        let mut pc: sys::PC = std::ptr::null_mut();
        petsc!(KSPGetPC(self.raw, &mut pc))?;
        // `-pc_type ict` is ours: PETSc sees `shell` in KSPSetFromOptions, then the shell is
        // made the ICT preconditioner (the options are read and checked first).
        let ict_options = if user_pc.as_deref() == Some(ict::NAME) {
            if self.comm.size()? > 1 {
                return Err(Error::PetscOption { option: pc_opt, message: ict::parallel_message() });
            }
            let options = ict::options_from_database(self.session, &self.prefix)?;
            self.session.set_option(&pc_opt, Some("shell"))?;
            Some(options)
        } else {
            None
        };
        match (&user_ksp, &user_pc) {
            (None, Some(p)) if !DIRECT_PCS.contains(&p.as_str()) => {
                let krylov = if self.indefinite { c"symmlq" } else { c"cg" };
                petsc!(KSPSetType(self.raw, krylov.as_ptr()))?;
            }
            (None, None) | (Some(_), None) if user_ksp.as_deref().is_none_or(|k| k == "preonly") => {
                petsc!(KSPSetType(self.raw, c"preonly".as_ptr()))?;
                petsc!(PCSetType(pc, c"cholesky".as_ptr()))?;
                petsc!(PCFactorSetMatSolverType(pc, c"mumps".as_ptr()))?;
                self.session.prefer_mumps_ordering(&self.prefix, self.ordering)?;
            }
            _ => {}
        }
        // Tight default tolerances for iterative methods: answers must agree across solvers.
        petsc!(KSPSetTolerances(self.raw, 1e-10, 1e-50, 1e8, 10000))?;
        let from_options = petsc!(KSPSetFromOptions(self.raw));
        if let Some(options) = ict_options {
            // Put the user's choice back (for the next solver with this prefix), marked used.
            self.session.set_option(&pc_opt, Some(ict::NAME))?;
            self.session.option(&pc_opt)?;
            from_options?;
            return ict::install(pc, options);
        }
        from_options
    }

    /// PETSc 3.18's SYMMLQ measures its iteration-0 residual on another scale than the later
    /// iterates (seen: 2e-7 against 1e-1 on the same system), so a relative tolerance is never
    /// met. Unless the user set `-ksp_atol`, give it the absolute tolerance rtol·‖b‖_{M⁻¹}
    /// (one preconditioner application), with rtol 1e-8 by default: its short recurrences
    /// stagnate near 1e-10 in double precision.
    fn fix_symmlq_tolerance(&mut self, b: &Vector<'s>) -> Result<()> {
        let (ksp_type, _, _) = self.type_names()?;
        if ksp_type != "symmlq" || self.session.has_option(&format!("-{}ksp_atol", self.prefix))? {
            return Ok(());
        }
        let (mut rtol, mut abstol, mut dtol, mut maxits) = (0.0, 0.0, 0.0, 0 as sys::PetscInt);
        petsc!(KSPGetTolerances(self.raw, &mut rtol, &mut abstol, &mut dtol, &mut maxits))?;
        if !self.session.has_option(&format!("-{}ksp_rtol", self.prefix))? {
            rtol = 1e-8;
        }
        petsc!(KSPSetUp(self.raw))?;
        let mut pc: sys::PC = std::ptr::null_mut();
        petsc!(KSPGetPC(self.raw, &mut pc))?;
        let z = b.duplicate()?;
        petsc!(PCApply(pc, b.raw, z.raw))?;
        let mut bz = 0.0;
        petsc!(VecDot(b.raw, z.raw, &mut bz))?;
        let atol = rtol * bz.abs().sqrt();
        // The same scale mismatch makes the divergence test (‖r_k‖ > dtol ‖r_0‖) fire at once
        // on systems with small entries (seen: a saddle point whose stiffness is O(1/E)):
        // off unless the user set it; the iteration limit and our residual check remain.
        if !self.session.has_option(&format!("-{}ksp_divtol", self.prefix))? {
            dtol = f64::MAX;
        }
        petsc!(KSPSetTolerances(self.raw, rtol, atol, dtol, maxits))
    }

    fn type_names(&self) -> Result<(String, String, Option<String>)> {
        let mut kt: sys::KSPType = std::ptr::null();
        petsc!(KSPGetType(self.raw, &mut kt))?;
        let mut pc: sys::PC = std::ptr::null_mut();
        petsc!(KSPGetPC(self.raw, &mut pc))?;
        let mut pt: sys::PCType = std::ptr::null();
        petsc!(PCGetType(pc, &mut pt))?;
        let (k, mut p) = (from_c(kt), from_c(pt));
        if p == "shell" {
            if let Some(described) = ict::describe(pc)? {
                p = described;
            }
        }
        let pkg = if DIRECT_PCS.contains(&p.as_str()) {
            let mut st: sys::MatSolverType = std::ptr::null();
            petsc!(PCFactorGetMatSolverType(pc, &mut st))?;
            Some(if st.is_null() { "petsc".to_string() } else { from_c(st) })
        } else {
            None
        };
        Ok((k, p, pkg))
    }

    /// Solve A x = b (x is the initial guess for iterative methods) and check the answer.
    pub fn solve(&mut self, matrix: &Matrix<'s>, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<SolveStats> {
        if b.global_size() != matrix.global_size() || x.global_size() != matrix.global_size() {
            return Err(Error::PetscUsage("solve: vector sizes differ from the matrix order".into()));
        }
        let start = std::time::Instant::now();
        let run = self.fix_symmlq_tolerance(b).and_then(|_| petsc!(KSPSolve(self.raw, b.raw, x.raw)));
        if let Err(e) = run {
            // A failure inside our own preconditioner (ict) has a typed error of its own.
            let mut pc: sys::PC = std::ptr::null_mut();
            petsc!(KSPGetPC(self.raw, &mut pc))?;
            return Err(ict::take_error(pc).unwrap_or(e));
        }
        let seconds = start.elapsed().as_secs_f64();
        let mut reason = sys::KSPConvergedReason(0);
        petsc!(KSPGetConvergedReason(self.raw, &mut reason))?;
        let mut reason_str: *const std::ffi::c_char = std::ptr::null();
        petsc!(KSPGetConvergedReasonString(self.raw, &mut reason_str))?;
        let mut its: sys::PetscInt = 0;
        petsc!(KSPGetIterationNumber(self.raw, &mut its))?;
        let (ksp_type, pc_type, factor_package) = self.type_names()?;
        let described = match &factor_package {
            Some(p) => format!("KSP {ksp_type} + {pc_type} ({p})"),
            None => format!("KSP {ksp_type} + {pc_type}"),
        };
        // Independent check: the true residual.
        let relative_residual = matrix.relative_residual(x, b)?;
        let (mut rtol, mut abstol, mut dtol, mut maxits) = (0.0, 0.0, 0.0, 0 as sys::PetscInt);
        petsc!(KSPGetTolerances(self.raw, &mut rtol, &mut abstol, &mut dtol, &mut maxits))?;
        let stats = SolveStats {
            ksp_type,
            pc_type,
            factor_package,
            iterations: its.max(0) as usize,
            converged_reason: from_c(reason_str),
            relative_residual,
            seconds,
        };
        if reason.0 < 0 {
            // Name the cause: a failed factorisation is not a Krylov method that did not converge.
            let mut pc: sys::PC = std::ptr::null_mut();
            petsc!(KSPGetPC(self.raw, &mut pc))?;
            let mut failed = sys::PCFailedReason(0);
            petsc!(PCGetFailedReason(pc, &mut failed))?;
            // MUMPS says why in INFOG(1) (MUMPS users' guide, "Error diagnostics").
            let mut infog = 0 as sys::PetscInt;
            if stats.factor_package.as_deref() == Some("mumps") {
                let mut f: sys::Mat = std::ptr::null_mut();
                if petsc!(PCFactorGetMatrix(pc, &mut f)).is_ok() && !f.is_null() {
                    let _ = petsc!(MatMumpsGetInfog(f, 1, &mut infog));
                }
            }
            let failed = match infog {
                -9 | -11 | -13 | -14 | -15 | -17 | -19 | -20 => sys::PCFailedReason::PC_FACTOR_OUTMEMORY,
                -10 => sys::PCFailedReason::PC_FACTOR_NUMERIC_ZEROPIVOT,
                _ => failed,
            };
            let (cause, tried) = match failed {
                sys::PCFailedReason::PC_FACTOR_OUTMEMORY => (
                    if infog < 0 {
                        format!("the factorisation ran out of memory (MUMPS INFOG(1) = {infog})")
                    } else {
                        "the factorisation ran out of memory".to_string()
                    },
                    "give MUMPS more workspace (-mat_mumps_icntl_14 100, -mat_mumps_icntl_23 <MB per process>), \
                     use an iterative solver (-ksp_type cg -pc_type hypre) or more MPI ranks"
                        .to_string(),
                ),
                sys::PCFailedReason::PC_FACTOR_STRUCT_ZEROPIVOT | sys::PCFailedReason::PC_FACTOR_NUMERIC_ZEROPIVOT => (
                    "the factorisation met a zero pivot: the matrix is singular".to_string(),
                    "check that the supports remove every rigid motion of every piece of the mesh".to_string(),
                ),
                sys::PCFailedReason::PC_FACTOR_OTHER | sys::PCFailedReason::PC_SETUP_ERROR => (
                    "the preconditioner or factorisation failed to set up".to_string(),
                    "run with -ksp_view and -ksp_error_if_not_converged to see PETSc's message; try the direct \
                     default (no -ksp_type/-pc_type)"
                        .to_string(),
                ),
                _ if !relative_residual.is_finite() => (
                    format!("{}: the residual is not finite", stats.converged_reason),
                    "check the loads, the material and the geometry for values whose products overflow".to_string(),
                ),
                _ if self.indefinite => (
                    stats.converged_reason.clone(),
                    format!(
                        "rtol {rtol:e}, max {maxits} iterations on a symmetric indefinite (saddle-point) system; \
                         raise -{p}ksp_max_it, or use the direct default (no -{p}ksp_type/-{p}pc_type: MUMPS LDLᵀ)",
                        p = self.prefix
                    ),
                ),
                _ => (
                    stats.converged_reason.clone(),
                    format!(
                        "rtol {rtol:e}, max {maxits} iterations; try a stronger preconditioner (-pc_type hypre, -pc_type icc -pc_factor_levels 2) or the direct default (no -ksp_type/-pc_type)"
                    ),
                ),
            };
            return Err(Error::SolverDiverged {
                solver: described,
                reason: cause,
                iterations: stats.iterations,
                residual: relative_residual,
                tried,
            });
        }
        let accepted = (100.0 * rtol).max(1e-6);
        if !(relative_residual <= accepted) {
            return Err(Error::SolverDiverged {
                solver: described,
                reason: format!(
                    "PETSc reported {} but the true relative residual is {relative_residual:.3e} > {accepted:.1e}",
                    stats.converged_reason
                ),
                iterations: stats.iterations,
                residual: relative_residual,
                tried:
                    "the answer was rejected by the independent residual check; with -ksp_type preonly use a direct \
                        -pc_type (lu, cholesky), otherwise use a Krylov method (-ksp_type cg) or tighten -ksp_rtol"
                        .into(),
            });
        }
        self.last = Some(stats.clone());
        Ok(stats)
    }

    /// Solve `A X = B` for `columns` right-hand sides at once, when the solver is a direct
    /// `preonly` one (one `KSPMatSolve`: MUMPS solves the block with level-3 BLAS, its
    /// distributed solve phase entered once per block instead of once per column); `None` for
    /// any other solver (the caller then solves column by column with [`LinearSolver::solve`]).
    /// `rhs` holds this rank's rows of `B` (the matrix's owned rows), column after column; the
    /// answer holds this rank's rows of `X` the same way. Call after
    /// [`LinearSolver::set_operator`]. Independent check as in [`LinearSolver::solve`]: every
    /// column's true relative residual `‖A x − b‖ / ‖b‖` is recomputed (`A X − B` by one
    /// sparse–dense product) and must be at most 1e-6 (100 rtol for a direct solver).
    pub fn solve_block(&mut self, matrix: &Matrix<'s>, rhs: &[f64], columns: usize) -> Result<Option<Vec<f64>>> {
        petsc!(KSPSetUp(self.raw))?;
        let (ksp_type, pc_type, factor_package) = self.type_names()?;
        if ksp_type != "preonly" || !DIRECT_PCS.contains(&pc_type.as_str()) {
            return Ok(None);
        }
        let owned = matrix.owned_rows();
        if rhs.len() != owned.len() * columns {
            return Err(Error::PetscUsage(format!(
                "solve_block: {} values for {} owned rows and {columns} columns",
                rhs.len(),
                owned.len()
            )));
        }
        let start = std::time::Instant::now();
        let local = super::to_petsc_int(owned.len(), "owned rows")?;
        let global = super::to_petsc_int(matrix.global_size(), "matrix order")?;
        let k = super::to_petsc_int(columns, "right-hand sides")?;
        let dense = |values: Option<&[f64]>| -> Result<DenseGuard> {
            let mut m: sys::Mat = std::ptr::null_mut();
            petsc!(MatCreateDense(self.comm.raw(), local, sys::PETSC_DECIDE, global, k, std::ptr::null_mut(), &mut m))?;
            let guard = DenseGuard(m);
            if let Some(values) = values {
                guard.write(values)?;
            }
            petsc!(MatAssemblyBegin(m, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
            petsc!(MatAssemblyEnd(m, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
            Ok(guard)
        };
        let b = dense(Some(rhs))?;
        let x = dense(None)?;
        petsc!(KSPMatSolve(self.raw, b.0, x.0))?;
        let seconds = start.elapsed().as_secs_f64();
        let mut reason = sys::KSPConvergedReason(0);
        petsc!(KSPGetConvergedReason(self.raw, &mut reason))?;
        let solution = x.read(rhs.len())?;
        // Independent check: R = A X − B, column norms against those of B.
        let mut product: sys::Mat = std::ptr::null_mut();
        petsc!(MatMatMult(
            matrix.raw,
            x.0,
            sys::MatReuse::MAT_INITIAL_MATRIX,
            sys::PETSC_DEFAULT as f64,
            &mut product
        ))?;
        let product = DenseGuard(product);
        petsc!(MatAXPY(product.0, -1.0, b.0, sys::MatStructure::SAME_NONZERO_PATTERN))?;
        let (mut residual, mut scale) = (vec![0.0; columns], vec![0.0; columns]);
        petsc!(MatGetColumnNorms(product.0, sys::NormType::NORM_2, residual.as_mut_ptr()))?;
        petsc!(MatGetColumnNorms(b.0, sys::NormType::NORM_2, scale.as_mut_ptr()))?;
        // f64::max drops NaN: a non-finite column is caught on its own.
        let non_finite = residual.iter().any(|r| !r.is_finite());
        let worst = if non_finite {
            f64::NAN
        } else {
            residual.iter().zip(&scale).fold(0.0f64, |m, (r, s)| m.max(if *s > 0.0 { r / s } else { *r }))
        };
        let described = format!("KSP {ksp_type} + {pc_type} ({})", factor_package.as_deref().unwrap_or("petsc"));
        if reason.0 < 0 || non_finite || worst > 1e-6 {
            return Err(Error::SolverDiverged {
                solver: described,
                reason: format!(
                    "the block solve of {columns} right-hand sides failed: converged reason {}, worst true relative \
                     residual {worst:.3e}",
                    reason.0
                ),
                iterations: 0,
                residual: worst,
                tried: "run with -ksp_view to see the factorisation, or use an iterative solver (-ksp_type cg \
                        -pc_type hypre), solved column by column"
                    .into(),
            });
        }
        self.last = Some(SolveStats {
            ksp_type,
            pc_type,
            factor_package,
            iterations: 0,
            converged_reason: format!("{columns} right-hand sides in one block solve"),
            relative_residual: worst,
            seconds,
        });
        Ok(Some(solution))
    }

    /// What the last successful solve did (for the report when one KSP serves many solves).
    pub fn last_stats(&self) -> Option<SolveStats> {
        self.last.clone()
    }
}

impl Drop for LinearSolver<'_> {
    fn drop(&mut self) {
        if !self.raw.is_null() {
            // SAFETY: owned handle; errors ignored.
            let _ = unsafe { sys::KSPDestroy(&mut self.raw) };
        }
    }
}

/// A dense PETSc matrix (the block solve's right-hand sides and answer), destroyed on drop.
struct DenseGuard(sys::Mat);

impl DenseGuard {
    /// Overwrite this rank's rows (column-major, the leading dimension the owned row count).
    fn write(&self, values: &[f64]) -> Result<()> {
        let mut ptr: *mut f64 = std::ptr::null_mut();
        petsc!(MatDenseGetArray(self.0, &mut ptr))?;
        // SAFETY: a dense matrix created with the local row count and all columns holds
        // local rows × columns values there, column-major with that leading dimension; the
        // caller checked `values.len()` against that product.
        unsafe { std::slice::from_raw_parts_mut(ptr, values.len()) }.copy_from_slice(values);
        petsc!(MatDenseRestoreArray(self.0, &mut ptr))
    }

    /// A copy of this rank's rows (column-major).
    fn read(&self, len: usize) -> Result<Vec<f64>> {
        let mut ptr: *mut f64 = std::ptr::null_mut();
        petsc!(MatDenseGetArray(self.0, &mut ptr))?;
        // SAFETY: as in `write`.
        let values = unsafe { std::slice::from_raw_parts(ptr, len) }.to_vec();
        petsc!(MatDenseRestoreArray(self.0, &mut ptr))?;
        Ok(values)
    }
}

impl Drop for DenseGuard {
    fn drop(&mut self) {
        if !self.0.is_null() {
            // SAFETY: owned handle; errors ignored (Drop never panics).
            let _ = unsafe { sys::MatDestroy(&mut self.0) };
        }
    }
}
