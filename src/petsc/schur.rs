//! A MUMPS Cholesky factorisation that also returns the Schur complement on chosen rows.
//!
//! For an SPD matrix `K` and a set `c` of rows (the rest `i`), MUMPS (ICNTL(19), through
//! PETSc's `MatFactorSetSchurIS`) computes during the factorisation
//!
//! ```text
//!   S = K_cc − K_ci K_ii⁻¹ K_ic,      and   (K⁻¹)_cc = S⁻¹
//! ```
//!
//! so the block of the inverse on `c` — the flexibility of the contact dofs — costs one
//! factorisation instead of one solve per row of `c`. `S` is inverted in place by PETSc's dense
//! routines (LAPACK `potrf`/`potri`, `MatFactorInvertSchurComplement`: at 1412 contact dofs
//! 0.1 s against 0.8 s for a Cholesky inverse in nalgebra). The same factor then solves full
//! systems `K x = b` (`MatSolve`, PETSc condensing on the Schur complement, applying `S⁻¹` with
//! a product and expanding). Sequential only: PETSc 3.18's MUMPS interface computes Schur
//! complements on one process.
//!
//! ## Interior solves ([`SchurFactor::with_complement`])
//!
//! Where the Schur unknowns are known (the contact forces of the dual formulation, once the
//! contact problem is solved) only the interior is wanted, `x_i = K_ii⁻¹ (b_i − K_ic x_c)`.
//! Applying an explicit `S⁻¹` and reading `x_c` back loses `cond(S)·ε` in `x_c`, and the
//! interior follows the perturbed `x_c` (measured: 1.5e-7 relative at 1e4 dual dofs, enough to
//! fail the independent complementarity check). So this mode keeps `S` for the caller and sets
//! the factor's Schur block to `s I`, marked inverted: MUMPS's condensation phase then returns
//! `b_c − K_ci K_ii⁻¹ b_i = b_c + ℓ` (`ℓ = −K_ci K_ii⁻¹ b_i`, the condensed load), PETSc
//! multiplies it by `s`, and the expansion phase computes `x_i = K_ii⁻¹ (b_i − K_ic y)` with
//! `y = s (b_c + ℓ)`. With `b_c = 0` the solve yields `s ℓ`; with `b_c = x_c / s − ℓ` it yields
//! `y = x_c` and the interior for the given `x_c` ([`SchurFactor::solve_interior`]).
//!
//! The pass-through factor `s = 1 / mean(diag S)` converts units: `b_c + ℓ` has the unit of the
//! Schur rows (a displacement, where the Schur unknowns are forces), `x_c` that of the unknowns.
//! The sum `x_c / s − ℓ` is rounded to `ε max(|x_c| / s, |ℓ|)`, so `y` carries an error of
//! `ε max(|x_c|, s |ℓ|)`, the same whatever the scale of the matrix. With the identity (`s = 1`)
//! the error was `ε max(|x_c|, |ℓ|)`, a force error `ε |ℓ|` proportional to the compliance: on a
//! block pressed on a plane the independent complementarity of the dual contact check grew as
//! `1/E` (1e-13 at `E = 1e3`, 1.2e-6 at `E = 1e-3`, the same stresses).
use std::marker::PhantomData;

use super::{petsc, to_petsc_int, Matrix, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// A MUMPS factorisation of a matrix with the Schur complement on a set of its rows (the contact
/// dofs), for the condensed and full-space contact routes.
pub struct SchurFactor<'s> {
    factor: sys::Mat,
    size: usize,
    inverse: Vec<f64>,
    /// `S` itself, row-major, when asked for ([`SchurFactor::with_complement`]); then the
    /// factor's Schur block is `pass_through · I` and only interior solves are offered.
    complement: Vec<f64>,
    /// `s = 1 / mean(diag S)` for [`SchurFactor::with_complement`], 1 otherwise (module
    /// documentation).
    pass_through: f64,
    _session: PhantomData<&'s Session>,
}

/// The error of a MUMPS factorisation that failed with `INFOG(1) = infog < 0`: out of memory
/// (-9, -11, -13, -14, -15, -17, -19, -20), a zero pivot (-10), or another MUMPS error.
pub(crate) fn factor_failure(infog: i64) -> Error {
    let method = "MUMPS Cholesky with the Schur complement on the contact dofs";
    let message = match infog {
        -9 | -11 | -13 | -14 | -15 | -17 | -19 | -20 => format!(
            "the factorisation ran out of memory (MUMPS INFOG(1) = {infog}); give MUMPS more workspace \
             (-mat_mumps_icntl_14 100, or -mat_mumps_icntl_23 <MB per process>), use fewer dofs (a larger \
             cell_size), or solve without this factorisation: --contact-solver newton -ksp_type cg -pc_type hypre \
             (the condensed route with iterative solves)"
        ),
        -10 => "the factorisation met a zero pivot (MUMPS INFOG(1) = -10): the stiffness is singular; check that \
                the supports, with the contact, remove every rigid motion of every body"
            .to_string(),
        _ => format!(
            "MUMPS failed (INFOG(1) = {infog}, see the MUMPS users' guide, \"Error diagnostics\"); run with \
             -mat_mumps_icntl_4 2 to see its messages"
        ),
    };
    Error::Factorization { method, message }
}

impl<'s> SchurFactor<'s> {
    /// Factorise `matrix` (SPD) with MUMPS and compute the Schur complement on `rows` (global
    /// indices; the complement's rows and columns follow this order).
    pub fn new(session: &'s Session, matrix: &Matrix<'s>, rows: &[usize]) -> Result<Self> {
        Self::build(session, matrix, rows, false)
    }

    /// Factorise with the Schur complement on `rows`, keep `S` itself
    /// ([`SchurFactor::complement`]) — the flexibility of the contact forces in the dual
    /// formulation, where the contact unknowns are forces — and offer interior solves for given
    /// values of the Schur unknowns ([`SchurFactor::solve_interior`], module documentation)
    /// instead of full solves.
    pub fn with_complement(session: &'s Session, matrix: &Matrix<'s>, rows: &[usize]) -> Result<Self> {
        Self::build(session, matrix, rows, true)
    }

    fn build(session: &'s Session, matrix: &Matrix<'s>, rows: &[usize], keep_complement: bool) -> Result<Self> {
        if session.size() != 1 {
            return Err(Error::PetscUsage(
                "MUMPS Schur complements are computed on one process in PETSc 3.18: use the solve-per-column route in parallel".into(),
            ));
        }
        let n = matrix.global_size();
        if rows.is_empty() || rows.iter().any(|&r| r >= n) {
            return Err(Error::PetscUsage(format!("Schur rows must be non-empty and below the matrix order {n}")));
        }
        session.prefer_amf_ordering("")?;
        let mut f: sys::Mat = std::ptr::null_mut();
        petsc!(MatGetFactor(matrix.raw, c"mumps".as_ptr(), sys::MatFactorType::MAT_FACTOR_CHOLESKY, &mut f))?;
        let mut this = SchurFactor {
            factor: f,
            size: rows.len(),
            inverse: Vec::new(),
            complement: Vec::new(),
            pass_through: 1.0,
            _session: PhantomData,
        };
        set_schur_rows(f, session.self_comm(), rows)?;
        let mut info = sys::MatFactorInfo::default();
        petsc!(MatFactorInfoInitialize(&mut info))?;
        petsc!(MatCholeskyFactorSymbolic(f, matrix.raw, std::ptr::null_mut(), &info))?;
        petsc!(MatCholeskyFactorNumeric(f, matrix.raw, &info))?;
        // MUMPS reports a failed factorisation in INFOG(1) (MUMPS users' guide, "Error
        // diagnostics"), not as a PETSc error: without this check its factor gives NaN.
        let mut infog = 0 as sys::PetscInt;
        petsc!(MatMumpsGetInfog(f, 1, &mut infog))?;
        if infog < 0 {
            return Err(factor_failure(infog as i64));
        }
        let m = rows.len();
        if keep_complement {
            let (complement, status) = read_schur(f, m)?;
            if status != sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_UNFACTORED {
                return Err(Error::PetscUsage("PETSc returned a factored Schur complement".into()));
            }
            let trace: f64 = (0..m).map(|k| complement[k * m + k]).sum();
            let pass_through = m as f64 / trace;
            this.pass_through = if pass_through.is_finite() && pass_through > 0.0 { pass_through } else { 1.0 };
            this.complement = complement;
            set_schur_to_multiple_of_identity(f, m, this.pass_through)?;
            return Ok(this);
        }
        // S⁻¹ in place, by PETSc's dense (LAPACK) Cholesky factorisation and inversion; the
        // factor's solves then apply it with a product instead of triangular solves.
        petsc!(MatFactorInvertSchurComplement(f))?;
        let (inverse, status) = read_schur(f, m)?;
        this.inverse = inverse;
        if status != sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_INVERTED {
            return Err(Error::PetscUsage("PETSc did not invert the Schur complement".into()));
        }
        Ok(this)
    }

    /// The Schur complement `S` itself, row-major `size × size` (empty unless built by
    /// [`SchurFactor::with_complement`]).
    pub fn complement(&self) -> &[f64] {
        &self.complement
    }

    /// The inverse of the Schur complement, `S⁻¹ = (K⁻¹)_cc`, row-major `size × size` (empty
    /// for a factor built by [`SchurFactor::with_complement`]).
    pub fn inverse_block(&self) -> &[f64] {
        &self.inverse
    }

    /// Size of the factored matrix.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Solve `K x = b` with the factor (not for a factor built by
    /// [`SchurFactor::with_complement`]: use [`SchurFactor::solve_interior`]).
    pub fn solve(&self, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<()> {
        if !self.complement.is_empty() {
            return Err(Error::PetscUsage(
                "SchurFactor::solve on a factor built with_complement: its solves are interior solves".into(),
            ));
        }
        self.mat_solve(b, x)
    }

    /// The pass-through factor `s` of [`SchurFactor::solve_interior`] (1 for a factor built by
    /// [`SchurFactor::new`]).
    pub fn pass_through(&self) -> f64 {
        self.pass_through
    }

    /// For a factor built by [`SchurFactor::with_complement`]: with `b = (b_i, b_c)`, return
    /// `x = (K_ii⁻¹ (b_i − K_ic y), y)` with `y = s (b_c + ℓ)`, `ℓ = −K_ci K_ii⁻¹ b_i` and `s`
    /// the [`SchurFactor::pass_through`] factor (module documentation). `b_c = 0` gives `s ℓ`;
    /// `b_c = x_c / s − ℓ` the interior for given `x_c`.
    pub fn solve_interior(&self, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<()> {
        if self.complement.is_empty() {
            return Err(Error::PetscUsage("SchurFactor::solve_interior needs a factor built with_complement".into()));
        }
        self.mat_solve(b, x)
    }

    fn mat_solve(&self, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<()> {
        if b.global_size() != x.global_size() {
            return Err(Error::PetscUsage("SchurFactor::solve: vector sizes differ".into()));
        }
        petsc!(MatSolve(self.factor, b.raw, x.raw))
    }
}

/// Give the MUMPS factor `f` (before its symbolic factorisation) the Schur rows this rank
/// lists, over `comm` (on several ranks PETSc 3.18 wants them all on rank 0, none elsewhere).
pub(crate) fn set_schur_rows(f: sys::Mat, comm: super::Comm, rows: &[usize]) -> Result<()> {
    let idx: Vec<sys::PetscInt> = rows.iter().map(|&r| to_petsc_int(r, "Schur row")).collect::<Result<_>>()?;
    let mut is: sys::IS = std::ptr::null_mut();
    petsc!(ISCreateGeneral(
        comm.raw(),
        to_petsc_int(idx.len(), "Schur size")?,
        idx.as_ptr(),
        sys::PetscCopyMode::PETSC_COPY_VALUES,
        &mut is
    ))?;
    let set = petsc!(MatFactorSetSchurIS(f, is));
    // SAFETY: `is` was created above and is not used after this.
    let _ = unsafe { sys::ISDestroy(&mut is) };
    set
}

/// The factor's current Schur matrix (`S`, or `S⁻¹` once inverted), row-major, and its status.
pub(crate) fn read_schur(f: sys::Mat, m: usize) -> Result<(Vec<f64>, sys::MatFactorSchurStatus)> {
    let mut s: sys::Mat = std::ptr::null_mut();
    let mut status = sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_UNFACTORED;
    petsc!(MatFactorGetSchurComplement(f, &mut s, &mut status))?;
    let mut out = Vec::new();
    let mut ptr: *const f64 = std::ptr::null();
    let read = petsc!(MatDenseGetArrayRead(s, &mut ptr));
    if read.is_ok() {
        // SAFETY: a sequential dense m × m matrix, column-major with leading dimension m.
        let col_major = unsafe { std::slice::from_raw_parts(ptr, m * m) };
        out = (0..m * m).map(|k| col_major[(k % m) * m + k / m]).collect();
        let _ = unsafe { sys::MatDenseRestoreArrayRead(s, &mut ptr) };
    }
    let restore = petsc!(MatFactorRestoreSchurComplement(f, &mut s, status));
    read?;
    restore?;
    Ok((out, status))
}

/// Overwrite the factor's Schur block with `scale · I` and mark it inverted, so that its solves
/// pass the condensed right-hand side through, times `scale` (module documentation).
fn set_schur_to_multiple_of_identity(f: sys::Mat, m: usize, scale: f64) -> Result<()> {
    let mut s: sys::Mat = std::ptr::null_mut();
    let mut status = sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_UNFACTORED;
    petsc!(MatFactorGetSchurComplement(f, &mut s, &mut status))?;
    let mut ptr: *mut f64 = std::ptr::null_mut();
    let write = petsc!(MatDenseGetArray(s, &mut ptr));
    if write.is_ok() {
        // SAFETY: a sequential dense m × m matrix, column-major with leading dimension m.
        let values = unsafe { std::slice::from_raw_parts_mut(ptr, m * m) };
        values.fill(0.0);
        for k in 0..m {
            values[k * m + k] = scale;
        }
        let _ = unsafe { sys::MatDenseRestoreArray(s, &mut ptr) };
    }
    let restore =
        petsc!(MatFactorRestoreSchurComplement(f, &mut s, sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_INVERTED));
    write?;
    restore
}

impl Drop for SchurFactor<'_> {
    fn drop(&mut self) {
        if !self.factor.is_null() {
            // SAFETY: owned factor; errors ignored (Drop never panics).
            let _ = unsafe { sys::MatDestroy(&mut self.factor) };
        }
    }
}
