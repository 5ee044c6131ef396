//! `-pc_type ict`: the threshold incomplete Cholesky of [`crate::sparse::incomplete_cholesky`]
//! as a PETSc preconditioner (a PCSHELL named "ict").
//!
//! PETSc does not know the type "ict", so [`super::LinearSolver::set_operator`] rewrites
//! `-{prefix}pc_type ict` to `shell` for `KSPSetFromOptions` (and puts "ict" back after), then
//! calls [`install`]: a boxed [`IctShell`] becomes the shell's context, freed by the destroy
//! callback. The setup callback reads the preconditioning matrix row by row (`MatGetRow`) and
//! factors it in Rust; the apply callback runs the two triangular solves. A failure inside a
//! callback (an unsymmetric matrix, a non-positive diagonal) is kept in the context and
//! returned by `LinearSolver::solve` as the typed error, instead of PETSc's generic one.
//!
//! Options (any prefix): `-{prefix}pc_ict_drop_tolerance τ` (default 1e-3),
//! `-{prefix}pc_ict_fill p` (keep at most n_j + p entries per column; default: no limit) and
//! `-{prefix}pc_ict_ordering natural|rcm` (factor the matrix in its own order, the default, or
//! in reverse Cuthill–McKee order, the default).
//! Sequential only: on more than one process `-pc_type ict` is refused with a typed error that
//! names the parallel alternatives (hypre's Euclid/PILUT, block Jacobi + ICC).
use std::ffi::c_void;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use super::{from_c, petsc, Session};
use crate::error::{Error, Result};
use crate::sparse::{CsrMatrix, IctOptions, IncompleteCholesky};
use signorini_sys as sys;

/// The default drop tolerance τ of `-pc_type ict`.
pub const DEFAULT_DROP_TOLERANCE: f64 = 1e-3;
/// The shell's name (what `-ksp_view` and the solve report show).
pub const NAME: &str = "ict";
/// The code a failed callback returns to PETSc (`PETSC_ERR_LIB`: error in a library called by
/// PETSc); the error itself is kept in the context.
const CALLBACK_FAILED: sys::PetscErrorCode = 76;

/// The context of one ICT shell: its options, the factor after setup, and what went wrong.
pub(crate) struct IctShell {
    options: IctOptions,
    factor: Option<IncompleteCholesky>,
    error: Option<Error>,
    setup_seconds: f64,
}

/// Read `-{prefix}pc_ict_drop_tolerance` and `-{prefix}pc_ict_fill`; a value that is not a
/// number ≥ 0 (an integer ≥ 0 for the fill) is an [`Error::PetscOption`] naming the option.
pub(crate) fn options_from_database(session: &Session, prefix: &str) -> Result<IctOptions> {
    let tol_name = format!("-{prefix}pc_ict_drop_tolerance");
    let fill_name = format!("-{prefix}pc_ict_fill");
    let mut options = IctOptions { drop_tolerance: DEFAULT_DROP_TOLERANCE, fill: None, ..IctOptions::default() };
    if let Some(v) = session.option(&tol_name)? {
        match v.trim().parse::<f64>() {
            Ok(t) if t.is_finite() && t >= 0.0 => options.drop_tolerance = t,
            _ => {
                return Err(Error::PetscOption {
                    message: format!(
                        "{tol_name} {v}: the drop tolerance of -{prefix}pc_type ict must be a number ≥ 0 \
                         (0 keeps every entry: the exact Cholesky factor), e.g. {tol_name} 1e-3"
                    ),
                    option: tol_name,
                })
            }
        }
    }
    if let Some(v) = session.option(&fill_name)? {
        match v.trim().parse::<usize>() {
            Ok(p) => options.fill = Some(p),
            Err(_) => {
                return Err(Error::PetscOption {
                    message: format!(
                        "{fill_name} {v}: the fill limit of -{prefix}pc_type ict must be an integer ≥ 0 (each \
                         column of the factor keeps at most its count in the matrix + this many entries), \
                         e.g. {fill_name} 20"
                    ),
                    option: fill_name,
                })
            }
        }
    }
    let ordering_name = format!("-{prefix}pc_ict_ordering");
    if let Some(v) = session.option(&ordering_name)? {
        options.reverse_cuthill_mckee = match v.trim() {
            "natural" => false,
            "rcm" => true,
            _ => {
                return Err(Error::PetscOption {
                    message: format!(
                        "{ordering_name} {v}: the ordering of -{prefix}pc_type ict is rcm (reverse Cuthill–McKee, \
                         the default) or natural (the matrix's own)"
                    ),
                    option: ordering_name,
                })
            }
        };
    }
    Ok(options)
}

/// Make `pc` (already of type shell) the ICT preconditioner with these options. On a shell
/// that is already ours (a second `set_operator`), only the options change and the factor is
/// redone at the next setup.
pub(crate) fn install(pc: sys::PC, options: IctOptions) -> Result<()> {
    if let Some(shell) = context(pc)? {
        shell.options = options;
        shell.factor = None;
        shell.error = None;
        return Ok(());
    }
    let shell = Box::new(IctShell { options, factor: None, error: None, setup_seconds: 0.0 });
    let raw = Box::into_raw(shell) as *mut c_void;
    if let Err(e) = petsc!(PCShellSetContext(pc, raw)) {
        // SAFETY: PETSc did not take the context: it is still ours alone.
        drop(unsafe { Box::from_raw(raw as *mut IctShell) });
        return Err(e);
    }
    // From here the destroy callback owns the box (PETSc calls it when the PC is destroyed or
    // its type changes).
    petsc!(PCShellSetDestroy(pc, Some(ict_destroy)))?;
    petsc!(PCShellSetSetUp(pc, Some(ict_setup)))?;
    petsc!(PCShellSetApply(pc, Some(ict_apply)))?;
    let name = super::cstring(NAME)?;
    petsc!(PCShellSetName(pc, name.as_ptr()))?;
    Ok(())
}

/// The ICT context of `pc`, if `pc` is a shell named "ict".
fn context<'a>(pc: sys::PC) -> Result<Option<&'a mut IctShell>> {
    let mut ty: sys::PCType = std::ptr::null();
    petsc!(PCGetType(pc, &mut ty))?;
    if ty.is_null() || from_c(ty) != "shell" {
        return Ok(None);
    }
    let mut name: *const std::ffi::c_char = std::ptr::null();
    petsc!(PCShellGetName(pc, &mut name))?;
    if name.is_null() || from_c(name) != NAME {
        return Ok(None);
    }
    let mut ctx: *mut c_void = std::ptr::null_mut();
    petsc!(PCShellGetContext(pc, &mut ctx as *mut *mut c_void as *mut c_void))?;
    // SAFETY: a shell named "ict" has the boxed IctShell of `install` as its context (or
    // NULL once destroyed); PETSc objects are used from one thread.
    Ok(unsafe { (ctx as *mut IctShell).as_mut() })
}

/// The error a callback of `pc`'s ICT kept, if any (taken: reported once).
pub(crate) fn take_error(pc: sys::PC) -> Option<Error> {
    context(pc).ok().flatten().and_then(|c| c.error.take())
}

/// What the report says of `pc` when it is the ICT shell: "ict (drop tolerance 1e-3, fill
/// limit 20, shift 2e-3, 41234 entries)"; `None` for any other PC.
pub(crate) fn describe(pc: sys::PC) -> Result<Option<String>> {
    let Some(c) = context(pc)? else { return Ok(None) };
    let mut parts = vec![format!("drop tolerance {:e}", c.options.drop_tolerance)];
    if let Some(p) = c.options.fill {
        parts.push(format!("fill limit {p}"));
    }
    if c.options.reverse_cuthill_mckee {
        parts.push("RCM order".into());
    }
    if let Some(f) = &c.factor {
        if f.shift() > 0.0 {
            parts.push(format!("shift {:e}", f.shift()));
        }
        parts.push(format!("{} entries in L", f.nnz()));
        parts.push(format!("setup {:.3} s", c.setup_seconds));
    }
    Ok(Some(format!("{NAME} ({})", parts.join(", "))))
}

/// Run `body` on the shell's context, catching panics and keeping errors for
/// `LinearSolver::solve`.
fn guarded(pc: sys::PC, body: impl FnOnce(&mut IctShell) -> Result<()>) -> sys::PetscErrorCode {
    let outcome = catch_unwind(AssertUnwindSafe(|| -> std::result::Result<(), Option<Error>> {
        let shell = context(pc).map_err(Some)?.ok_or(None)?;
        body(shell).map_err(|e| {
            shell.error = Some(e);
            None
        })
    }));
    match outcome {
        Ok(Ok(())) => 0,
        Ok(Err(None)) => CALLBACK_FAILED,
        Ok(Err(Some(e))) => {
            keep(pc, e);
            CALLBACK_FAILED
        }
        Err(panic) => {
            let message = super::panic_message(panic.as_ref());
            keep(pc, Error::PetscUsage(format!("the ict preconditioner panicked: {message}")));
            CALLBACK_FAILED
        }
    }
}

fn keep(pc: sys::PC, e: Error) {
    if let Ok(Some(c)) = context(pc) {
        c.error = Some(e);
    }
}

/// A full CSR matrix: order, indptr, column indices, values.
type OwnedCsr = (usize, Vec<usize>, Vec<usize>, Vec<f64>);

/// The preconditioning matrix of `pc` as a full CSR.
fn read_matrix(pc: sys::PC) -> Result<OwnedCsr> {
    let (mut amat, mut pmat): (sys::Mat, sys::Mat) = (std::ptr::null_mut(), std::ptr::null_mut());
    petsc!(PCGetOperators(pc, &mut amat, &mut pmat))?;
    let (mut rows, mut cols): (sys::PetscInt, sys::PetscInt) = (0, 0);
    petsc!(MatGetSize(pmat, &mut rows, &mut cols))?;
    let (mut lo, mut hi): (sys::PetscInt, sys::PetscInt) = (0, 0);
    petsc!(MatGetOwnershipRange(pmat, &mut lo, &mut hi))?;
    if lo != 0 || hi != rows {
        return Err(Error::PetscOption { option: "-pc_type".into(), message: parallel_message() });
    }
    if rows != cols {
        return Err(Error::Factorization {
            method: "incomplete Cholesky (ict)",
            message: format!("the matrix is not square ({rows} × {cols})"),
        });
    }
    let n = rows.max(0) as usize;
    let mut indptr = Vec::with_capacity(n + 1);
    let (mut indices, mut values) = (Vec::new(), Vec::new());
    indptr.push(0);
    for i in 0..rows {
        let mut len: sys::PetscInt = 0;
        let mut c: *const sys::PetscInt = std::ptr::null();
        let mut v: *const f64 = std::ptr::null();
        petsc!(MatGetRow(pmat, i, &mut len, &mut c, &mut v))?;
        if len > 0 && !c.is_null() && !v.is_null() {
            // SAFETY: MatGetRow returned `len` column indices and values, valid until restored.
            let (cs, vs) =
                unsafe { (std::slice::from_raw_parts(c, len as usize), std::slice::from_raw_parts(v, len as usize)) };
            indices.extend(cs.iter().map(|&k| k.max(0) as usize));
            values.extend_from_slice(vs);
        }
        petsc!(MatRestoreRow(pmat, i, &mut len, &mut c, &mut v))?;
        indptr.push(indices.len());
    }
    Ok((n, indptr, indices, values))
}

/// The message of the typed error for `-pc_type ict` on more than one process.
pub(crate) fn parallel_message() -> String {
    "-pc_type ict runs on one process; use -pc_type hypre -pc_hypre_type euclid/pilut or \
     -pc_type bjacobi -sub_pc_type icc in parallel"
        .to_string()
}

unsafe extern "C" fn ict_setup(pc: sys::PC) -> sys::PetscErrorCode {
    guarded(pc, |shell| {
        let start = Instant::now();
        shell.factor = None;
        let (n, indptr, indices, values) = read_matrix(pc)?;
        let a = CsrMatrix { num_rows: n, num_cols: n, indptr: &indptr, indices: &indices, values: &values };
        shell.factor = Some(IncompleteCholesky::factor(&a, &shell.options)?);
        shell.setup_seconds = start.elapsed().as_secs_f64();
        Ok(())
    })
}

unsafe extern "C" fn ict_apply(pc: sys::PC, r: sys::Vec, z: sys::Vec) -> sys::PetscErrorCode {
    guarded(pc, |shell| {
        let factor = shell
            .factor
            .as_ref()
            .ok_or_else(|| Error::PetscUsage("the ict preconditioner was applied before its setup".into()))?;
        let n = factor.order();
        let (mut nr, mut nz): (sys::PetscInt, sys::PetscInt) = (0, 0);
        petsc!(VecGetLocalSize(r, &mut nr))?;
        petsc!(VecGetLocalSize(z, &mut nz))?;
        if nr as usize != n || nz as usize != n {
            return Err(Error::PetscUsage(format!(
                "the ict preconditioner of order {n} was applied to vectors of local sizes {nr} and {nz}"
            )));
        }
        let mut rp: *const f64 = std::ptr::null();
        petsc!(VecGetArrayRead(r, &mut rp))?;
        let mut zp: *mut f64 = std::ptr::null_mut();
        if let Err(e) = petsc!(VecGetArray(z, &mut zp)) {
            petsc!(VecRestoreArrayRead(r, &mut rp))?;
            return Err(e);
        }
        let outcome = if n == 0 {
            Ok(())
        } else {
            // SAFETY: both arrays hold n (checked local size) doubles; PCApply refuses r == z.
            let (rs, zs) = unsafe { (std::slice::from_raw_parts(rp, n), std::slice::from_raw_parts_mut(zp, n)) };
            factor.apply(rs, zs)
        };
        petsc!(VecRestoreArray(z, &mut zp))?;
        petsc!(VecRestoreArrayRead(r, &mut rp))?;
        outcome
    })
}

unsafe extern "C" fn ict_destroy(pc: sys::PC) -> sys::PetscErrorCode {
    let outcome = catch_unwind(AssertUnwindSafe(|| {
        let mut ctx: *mut c_void = std::ptr::null_mut();
        // SAFETY: the context of our shell is the box leaked by `install` (or NULL).
        let code = unsafe { sys::PCShellGetContext(pc, &mut ctx as *mut *mut c_void as *mut c_void) };
        if code == 0 && !ctx.is_null() {
            // SAFETY: the box of `install`, freed here once: the pointer is cleared just after.
            drop(unsafe { Box::from_raw(ctx as *mut IctShell) });
            // SAFETY: clearing the context of a live PC.
            let _ = unsafe { sys::PCShellSetContext(pc, std::ptr::null_mut()) };
        }
    }));
    if outcome.is_ok() {
        0
    } else {
        CALLBACK_FAILED
    }
}
