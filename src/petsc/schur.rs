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
use std::marker::PhantomData;

use super::{petsc, to_petsc_int, Matrix, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

pub struct SchurFactor<'s> {
    factor: sys::Mat,
    size: usize,
    inverse: Vec<f64>,
    _session: PhantomData<&'s Session>,
}

impl<'s> SchurFactor<'s> {
    /// Factorise `matrix` (SPD) with MUMPS and compute the Schur complement on `rows` (global
    /// indices; the complement's rows and columns follow this order).
    pub fn new(session: &'s Session, matrix: &Matrix<'s>, rows: &[usize]) -> Result<Self> {
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
        let mut this = SchurFactor { factor: f, size: rows.len(), inverse: Vec::new(), _session: PhantomData };
        let idx: Vec<sys::PetscInt> = rows.iter().map(|&r| r as sys::PetscInt).collect();
        let mut is: sys::IS = std::ptr::null_mut();
        petsc!(ISCreateGeneral(
            session.self_comm().raw(),
            to_petsc_int(rows.len(), "Schur size")?,
            idx.as_ptr(),
            sys::PetscCopyMode::PETSC_COPY_VALUES,
            &mut is
        ))?;
        let set = petsc!(MatFactorSetSchurIS(f, is));
        let _ = unsafe { sys::ISDestroy(&mut is) };
        set?;
        let mut info = sys::MatFactorInfo::default();
        petsc!(MatFactorInfoInitialize(&mut info))?;
        petsc!(MatCholeskyFactorSymbolic(f, matrix.raw, std::ptr::null_mut(), &info))?;
        petsc!(MatCholeskyFactorNumeric(f, matrix.raw, &info))?;
        // S⁻¹ in place, by PETSc's dense (LAPACK) Cholesky factorisation and inversion; the
        // factor's solves then apply it with a product instead of triangular solves.
        petsc!(MatFactorInvertSchurComplement(f))?;
        let mut s: sys::Mat = std::ptr::null_mut();
        let mut status = sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_UNFACTORED;
        petsc!(MatFactorGetSchurComplement(f, &mut s, &mut status))?;
        let m = rows.len();
        let mut ptr: *const f64 = std::ptr::null();
        let read = petsc!(MatDenseGetArrayRead(s, &mut ptr));
        if read.is_ok() {
            // SAFETY: a sequential dense m × m matrix, column-major with leading dimension m.
            let col_major = unsafe { std::slice::from_raw_parts(ptr, m * m) };
            this.inverse = (0..m * m).map(|k| col_major[(k % m) * m + k / m]).collect();
            let _ = unsafe { sys::MatDenseRestoreArrayRead(s, &mut ptr) };
        }
        let restore = petsc!(MatFactorRestoreSchurComplement(f, &mut s, status));
        read?;
        restore?;
        if status != sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_INVERTED {
            return Err(Error::PetscUsage("PETSc did not invert the Schur complement".into()));
        }
        Ok(this)
    }

    /// The inverse of the Schur complement, `S⁻¹ = (K⁻¹)_cc`, row-major `size × size`.
    pub fn inverse_block(&self) -> &[f64] {
        &self.inverse
    }

    pub fn size(&self) -> usize {
        self.size
    }

    /// Solve `K x = b` with the factor.
    pub fn solve(&self, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<()> {
        if b.global_size() != x.global_size() {
            return Err(Error::PetscUsage("SchurFactor::solve: vector sizes differ".into()));
        }
        petsc!(MatSolve(self.factor, b.raw, x.raw))
    }
}

impl Drop for SchurFactor<'_> {
    fn drop(&mut self) {
        if !self.factor.is_null() {
            // SAFETY: owned factor; errors ignored (Drop never panics).
            let _ = unsafe { sys::MatDestroy(&mut self.factor) };
        }
    }
}
