//! Bound-constrained problems through PETSc: SNESVI for `lower ≤ v ≤ upper` complementarity
//! problems on distributed sparse matrices, and TAO for small dense box-constrained QPs.
//!
//! Both solve the convex quadratic program
//!
//! ```text
//!   minimize ½ vᵀ A v − bᵀ v   subject to   lower ≤ v ≤ upper      (A symmetric positive definite)
//! ```
//!
//! - [`solve_vi`]: SNES of type `vinewtonrsls` (reduced-space active set Newton, Benson &
//!   Munson) on F(v) = A v − b with Jacobian A, which Debian's build may modify in place: it is
//!   refilled from A at every Jacobian evaluation (TOOLCHAIN.md). The inner KSP defaults to a
//!   MUMPS LU of the reduced matrix. Options prefix: the caller's (e.g. `contact_`), so
//!   `-contact_snes_monitor`, `-contact_ksp_type ...` work from the command line.
//! - [`solve_box_qp`]: TAO `gpcg` (gradient projection conjugate gradient, Moré & Toraldo) by
//!   default, `-<prefix>tao_type tron` also works; `bqpip` fails with infinite bounds in 3.18.
//!
//! PETSc's reasons are checked, but the caller must still judge the answer by its own KKT
//! residuals (TOOLCHAIN.md): these functions only report what PETSc says.
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};

use super::{cstring, from_c, petsc, to_petsc_int, Matrix, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// What a bound-constrained solve returned.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BoundedSolve {
    /// The method, e.g. "PETSc SNES vinewtonrsls" or "PETSc TAO tron".
    pub method: String,
    /// Outer iterations.
    pub iterations: usize,
    /// Krylov iterations over all outer iterations.
    pub linear_iterations: usize,
    /// PETSc's converged reason.
    pub converged_reason: String,
}

/// PETSc error code returned by a callback that panicked (PETSC_ERR_LIB).
const CALLBACK_PANIC: sys::PetscErrorCode = 76;

struct LinearOperator {
    a: sys::Mat,
    b: sys::Vec,
}

unsafe extern "C" fn vi_function(_snes: sys::SNES, x: sys::Vec, f: sys::Vec, ctx: *mut c_void) -> sys::PetscErrorCode {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: ctx is the LinearOperator that outlives SNESSolve (see solve_vi).
        let op = unsafe { &*(ctx as *const LinearOperator) };
        let code = unsafe { sys::MatMult(op.a, x, f) };
        if code != 0 {
            return code;
        }
        unsafe { sys::VecAXPY(f, -1.0, op.b) }
    }))
    .unwrap_or(CALLBACK_PANIC)
}

unsafe extern "C" fn vi_jacobian(
    _snes: sys::SNES,
    _x: sys::Vec,
    jac: sys::Mat,
    pre: sys::Mat,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: as above. The VI solver may have modified J: copy A back in.
        let op = unsafe { &*(ctx as *const LinearOperator) };
        let code = unsafe { sys::MatCopy(op.a, jac, sys::MatStructure::SAME_NONZERO_PATTERN) };
        if code != 0 || pre == jac {
            return code;
        }
        unsafe { sys::MatCopy(op.a, pre, sys::MatStructure::SAME_NONZERO_PATTERN) }
    }))
    .unwrap_or(CALLBACK_PANIC)
}

fn bound_vector<'s>(like: &Vector<'s>, values: &[f64]) -> Result<Vector<'s>> {
    let mut v = like.duplicate()?;
    let inf = unsafe { sys::signorini_petsc_infinity() };
    let clamped: Vec<f64> = values.iter().map(|&x| x.clamp(-inf, inf)).collect();
    v.set_owned(&clamped)?;
    Ok(v)
}

/// Solve `lower ≤ v ≤ upper` complementarity for F(v) = A v − b with SNESVI (see module doc).
/// `bounds = (lower, upper)` and `x` are this rank's owned entries (±infinity allowed); `x`
/// holds the initial guess and receives the solution. Converged when `|F|` falls by 1e-12 or
/// below `absolute` (the caller's round-off floor; 0 for none).
pub fn solve_vi<'s>(
    session: &'s Session,
    a: &Matrix<'s>,
    b: &Vector<'s>,
    (lower, upper): (&[f64], &[f64]),
    x: &mut Vector<'s>,
    absolute: f64,
    prefix: &str,
) -> Result<BoundedSolve> {
    let owned = a.owned_rows().len();
    if lower.len() != owned
        || upper.len() != owned
        || b.global_size() != a.global_size()
        || x.global_size() != a.global_size()
    {
        return Err(Error::PetscUsage("solve_vi: bounds or vectors do not match the matrix layout".into()));
    }
    let op = Box::new(LinearOperator { a: a.raw, b: b.raw });
    let ctx = &*op as *const LinearOperator as *mut c_void;
    let mut snes: sys::SNES = std::ptr::null_mut();
    petsc!(SNESCreate(session.world().raw(), &mut snes))?;
    let guard = SnesGuard(snes);
    let mut jac: sys::Mat = std::ptr::null_mut();
    petsc!(MatDuplicate(a.raw, sys::MatDuplicateOption::MAT_COPY_VALUES, &mut jac))?;
    let jac_guard = MatGuard(jac);
    let residual = b.duplicate()?;
    let lo = bound_vector(b, lower)?;
    let hi = bound_vector(b, upper)?;
    let p = cstring(prefix)?;
    petsc!(SNESSetOptionsPrefix(snes, p.as_ptr()))?;
    petsc!(SNESSetType(snes, c"vinewtonrsls".as_ptr()))?;
    petsc!(SNESSetFunction(snes, residual.raw, Some(vi_function), ctx))?;
    petsc!(SNESSetJacobian(snes, jac, jac, Some(vi_jacobian), ctx))?;
    petsc!(SNESVISetVariableBounds(snes, lo.raw, hi.raw))?;
    // Converged at 1e-12 of the initial residual, or at `absolute`: on a stiff body the
    // round-off floor of |A v − b| can lie above 1e-12 of it (the Hertz sphere at E = 210 GPa:
    // 1.8e-12 of |b|, where the line search then fails on an answer already exact to
    // round-off). The caller's independent check judges the answer in any case.
    petsc!(SNESSetTolerances(snes, absolute.max(1e-50), 1e-12, 1e-50, 200, 100_000))?;
    // At least one Newton step even when the initial guess already meets `absolute`: a caller
    // iterating on a small change of `b` (the proximal iterations of a floating body) needs its
    // solution to move with it.
    petsc!(SNESSetForceIteration(snes, sys::PetscBool::PETSC_TRUE))?;
    let mut ksp: sys::KSP = std::ptr::null_mut();
    petsc!(SNESGetKSP(snes, &mut ksp))?;
    if !session.has_option(&format!("-{prefix}ksp_type"))? && !session.has_option(&format!("-{prefix}pc_type"))? {
        let mut pc: sys::PC = std::ptr::null_mut();
        petsc!(KSPGetPC(ksp, &mut pc))?;
        petsc!(KSPSetType(ksp, c"preonly".as_ptr()))?;
        petsc!(PCSetType(pc, c"lu".as_ptr()))?;
        petsc!(PCFactorSetMatSolverType(pc, c"mumps".as_ptr()))?;
    }
    // PETSc counts a variable within `-snes_vi_zero_tolerance` of a bound as on it, 1e-8 by
    // default, in the units of v: with displacements of 1e-4 m (the Hertz sphere) the points
    // within 1e-8 m of the obstacle at the edge of the contact zone were held there, and the
    // answer was 1e-5 off the other routes'. Here: 1e-12 of the largest finite bound (the gaps'
    // scale), unless the options set it.
    let zero_option = format!("-{prefix}snes_vi_zero_tolerance");
    let ours = !session.has_option(&zero_option)?;
    if ours {
        let largest = lower.iter().chain(upper).filter(|b| b.is_finite()).fold(0.0f64, |m, b| m.max(b.abs()));
        let largest = session.world().max(&[largest])?[0];
        session.set_option(&zero_option, Some(&format!("{:e}", ZERO_TOLERANCE * largest)))?;
    }
    let configured = petsc!(SNESSetFromOptions(snes));
    if ours {
        session.clear_option(&zero_option)?;
    }
    configured?;
    petsc!(SNESSolve(snes, std::ptr::null_mut(), x.raw))?;
    let mut reason = sys::SNESConvergedReason(0);
    petsc!(SNESGetConvergedReason(snes, &mut reason))?;
    let mut reason_str: *const std::ffi::c_char = std::ptr::null();
    petsc!(SNESGetConvergedReasonString(snes, &mut reason_str))?;
    let (mut its, mut lits): (sys::PetscInt, sys::PetscInt) = (0, 0);
    petsc!(SNESGetIterationNumber(snes, &mut its))?;
    petsc!(SNESGetLinearSolveIterations(snes, &mut lits))?;
    drop(jac_guard);
    drop(guard);
    drop(op);
    let result = BoundedSolve {
        method: "PETSc SNESVI (vinewtonrsls)".into(),
        iterations: its.max(0) as usize,
        linear_iterations: lits.max(0) as usize,
        converged_reason: from_c(reason_str),
    };
    if reason.0 < 0 {
        return Err(Error::SolverDiverged {
            solver: result.method.clone(),
            reason: result.converged_reason.clone(),
            iterations: result.iterations,
            residual: f64::NAN,
            tried: format!("reduced-space active-set Newton, {} Newton steps; try -{prefix}snes_monitor, or the condensed semi-smooth Newton (solver = \"newton\")", result.iterations),
        });
    }
    Ok(result)
}

/// SNESVI's zero tolerance (a variable this close to a bound is on it), relative to the
/// largest finite bound.
const ZERO_TOLERANCE: f64 = 1e-12;

struct SnesGuard(sys::SNES);
impl Drop for SnesGuard {
    fn drop(&mut self) {
        // SAFETY: owned handle; errors ignored (Drop never panics).
        let _ = unsafe { sys::SNESDestroy(&mut self.0) };
    }
}
struct MatGuard(sys::Mat);
impl Drop for MatGuard {
    fn drop(&mut self) {
        let _ = unsafe { sys::MatDestroy(&mut self.0) };
    }
}
struct TaoGuard(sys::Tao);
impl Drop for TaoGuard {
    fn drop(&mut self) {
        let _ = unsafe { sys::TaoDestroy(&mut self.0) };
    }
}

struct DenseQp {
    h: sys::Mat,
    c: sys::Vec,
}

unsafe extern "C" fn qp_objective_gradient(
    _tao: sys::Tao,
    x: sys::Vec,
    f: *mut f64,
    g: sys::Vec,
    ctx: *mut c_void,
) -> sys::PetscErrorCode {
    catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: ctx is the DenseQp that outlives TaoSolve; f points to one double.
        let qp = unsafe { &*(ctx as *const DenseQp) };
        let code = unsafe { sys::MatMult(qp.h, x, g) };
        if code != 0 {
            return code;
        }
        let (mut xhx, mut cx) = (0.0, 0.0);
        let code = unsafe { sys::VecDot(x, g, &mut xhx) };
        if code != 0 {
            return code;
        }
        let code = unsafe { sys::VecDot(x, qp.c, &mut cx) };
        if code != 0 {
            return code;
        }
        unsafe { *f = 0.5 * xhx + cx };
        unsafe { sys::VecAXPY(g, 1.0, qp.c) }
    }))
    .unwrap_or(CALLBACK_PANIC)
}

unsafe extern "C" fn qp_hessian(
    _tao: sys::Tao,
    _x: sys::Vec,
    _h: sys::Mat,
    _p: sys::Mat,
    _ctx: *mut c_void,
) -> sys::PetscErrorCode {
    0 // constant Hessian, set once
}

/// Minimize ½ xᵀ H x + cᵀ x over lower ≤ x ≤ upper with TAO on one process (`H` dense,
/// row-major n × n, symmetric positive definite). `x` holds the initial guess and receives
/// the solution.
pub fn solve_box_qp(
    session: &Session,
    h: &[f64],
    c: &[f64],
    lower: &[f64],
    upper: &[f64],
    x: &mut [f64],
    prefix: &str,
) -> Result<BoundedSolve> {
    let n = c.len();
    if h.len() != n * n || lower.len() != n || upper.len() != n || x.len() != n {
        return Err(Error::PetscUsage(format!("solve_box_qp: sizes disagree (n = {n}, H has {} entries)", h.len())));
    }
    let comm = session.self_comm();
    let ni = to_petsc_int(n, "QP size")?;
    let mut hm: sys::Mat = std::ptr::null_mut();
    petsc!(MatCreateDense(comm.raw(), ni, ni, ni, ni, std::ptr::null_mut(), &mut hm))?;
    let h_guard = MatGuard(hm);
    let idx: Vec<sys::PetscInt> = (0..ni).collect();
    petsc!(MatSetValues(hm, ni, idx.as_ptr(), ni, idx.as_ptr(), h.as_ptr(), sys::InsertMode::INSERT_VALUES))?;
    petsc!(MatAssemblyBegin(hm, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
    petsc!(MatAssemblyEnd(hm, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
    let mut cv = Vector::new(session, comm, n, n)?;
    cv.set_owned(c)?;
    let lo = bound_vector(&cv, lower)?;
    let hi = bound_vector(&cv, upper)?;
    let mut xv = cv.duplicate()?;
    xv.set_owned(x)?;
    let qp = Box::new(DenseQp { h: hm, c: cv.raw });
    let ctx = &*qp as *const DenseQp as *mut c_void;
    let mut tao: sys::Tao = std::ptr::null_mut();
    petsc!(TaoCreate(comm.raw(), &mut tao))?;
    let guard = TaoGuard(tao);
    let p = cstring(prefix)?;
    petsc!(TaoSetOptionsPrefix(tao, p.as_ptr()))?;
    petsc!(TaoSetType(tao, c"gpcg".as_ptr()))?;
    petsc!(TaoSetSolution(tao, xv.raw))?;
    petsc!(TaoSetObjectiveAndGradient(tao, std::ptr::null_mut(), Some(qp_objective_gradient), ctx))?;
    petsc!(TaoSetHessian(tao, hm, hm, Some(qp_hessian), ctx))?;
    petsc!(TaoSetVariableBounds(tao, lo.raw, hi.raw))?;
    petsc!(TaoSetTolerances(tao, 0.0, 1e-14, 0.0))?;
    petsc!(TaoSetMaximumIterations(tao, 10_000))?;
    petsc!(TaoSetFromOptions(tao))?;
    petsc!(TaoSolve(tao))?;
    let (mut its, mut f, mut gnorm, mut cnorm, mut xdiff) = (0 as sys::PetscInt, 0.0, 0.0, 0.0, 0.0);
    let mut reason = sys::TaoConvergedReason(0);
    petsc!(TaoGetSolutionStatus(tao, &mut its, &mut f, &mut gnorm, &mut cnorm, &mut xdiff, &mut reason))?;
    let mut ttype: sys::TaoType = std::ptr::null();
    petsc!(TaoGetType(tao, &mut ttype))?;
    let method = format!("PETSc TAO {}", from_c(ttype));
    x.copy_from_slice(&xv.owned_values()?);
    drop(guard);
    drop(h_guard);
    drop(qp);
    let result = BoundedSolve {
        method,
        iterations: its.max(0) as usize,
        linear_iterations: 0,
        converged_reason: format!("TAO reason {} (gradient norm {gnorm:.3e})", reason.0),
    };
    if reason.0 < 0 {
        return Err(Error::SolverDiverged {
            solver: result.method.clone(),
            reason: result.converged_reason.clone(),
            iterations: result.iterations,
            residual: gnorm,
            tried: format!("-{prefix}tao_type {}; try -{prefix}tao_type tron, or solver = \"newton\"", result.method),
        });
    }
    Ok(result)
}
