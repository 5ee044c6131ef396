//! A MUMPS Cholesky factorisation of a distributed SPD matrix that also returns a block of its
//! inverse, on any number of ranks.
//!
//! For an SPD matrix `K` and a set `c` of rows, MUMPS computes selected entries of `K⁻¹`
//! (ICNTL(30), PETSc's `MatMumpsGetInverse`): the entries `(K⁻¹)_ij`, `i, j ∈ c`, are the rows
//! `c` of the solutions `K⁻¹ e_j`, and MUMPS prunes its triangular solves to the parts of the
//! elimination tree those sparse right-hand sides and wanted rows reach (P. R. Amestoy,
//! I. S. Duff, J.-Y. L'Excellent, F.-H. Rouet, "Parallel computation of entries of A⁻¹",
//! SIAM J. Sci. Comput. 37 (2015) C268–C284). Unlike the Schur complement of
//! [`SchurFactor`](super::schur::SchurFactor), which PETSc 3.18 computes on one process only
//! (its `MatSolve` refuses a parallel factor with a Schur complement), this works on a
//! factorisation distributed over the ranks, and the same factor then solves full systems
//! `K x = b` with distributed vectors (`MatSolve`).
//!
//! PETSc's interface wants the pattern of the wanted entries as the transpose of a sparse
//! matrix (`MatCreateTranspose` of `Bᵀ`, `Bᵀ` row `j` holding the rows `i` wanted in column
//! `j`; `n × n`: MUMPS wants as many right-hand sides as the matrix order, INFOG(1) = -47
//! otherwise, the columns not wanted are empty), all of it on rank 0 (an MPI AIJ matrix whose
//! rows and columns rank 0 owns); MUMPS writes the entries into that matrix's values on rank 0, and they are then summed to every
//! rank (ranks other than 0 contribute zeros). `MatMumpsGetInverse` leaves ICNTL(30) = 1 and
//! ICNTL(21) = 0 (centralized solution) set on the factor; both are put back (0, and 1 on
//! several ranks: PETSc's parallel `MatSolve` reads a distributed solution), or the next
//! `MatSolve` would compute inverse entries again or read the solution from the wrong place.
//!
//! [`InverseBlockFactor::with_schur_complement`] is the other way PETSc 3.18 allows in
//! parallel: the Schur complement returned centralized on rank 0 (ICNTL(19) = 1). MUMPS then
//! returns one triangle of `S` only (PETSc transposes it, and LAPACK's Cholesky reads the
//! other), so the triangle is mirrored before `S` is inverted. PETSc refuses `MatSolve` on
//! such a factor in parallel.
//!
//! ## Measured: the block is not faster on two ranks
//!
//! `examples/inverse_block_timing.rs` (a square P1 grid clamped on its top side, the block on
//! the bottom side's dofs, as the square block's contact dofs; 2-core machine shared with
//! other builds, `OMP_NUM_THREADS=1`), wall-clock seconds; `--oversubscribe` makes Open MPI
//! yield when idle:
//!
//! ```text
//!   load 7-8 (other builds running)
//!   dofs    block  ranks  factorisation alone   factorisation + selected inverse   with the Schur complement
//!   2.0e5     632      1  1.09, 1.25, 1.75      1.55; 2.57 (1.64 + 0.94)            0.94 (schur.rs), 0.95
//!   2.0e5     632      2  1.96, 2.07, 2.43      6.81; 15.53 (2.32 + 13.21)          2.08 (2.02 + 0.06)
//!                         (--oversubscribe)     ICNTL(27) = 8, 128, 632: inverse 41.2, 7.6, 5.0
//!   1.0e6    1416      1  7.01, 10.08, 13.39    12.05                               12.09 (schur.rs), 7.95
//!   1.0e6    1416      2  8.87, 14.26           182.7                               > 12 min (stopped)
//!
//!   load 2-3.5: analysis + numerical factorisation
//!   2.0e5     632      1  0.07 + 0.54          1.13 (0.74 + 0.40 inverse)
//!   2.0e5     632      2  0.16 + 0.60          5.39 (0.90 + 4.50 inverse)          1.22 (1.19 + 0.03)
//!   1.0e6    1416      1  0.39 + 3.83, 0.43 + 4.73, 0.38 + 4.28                      5.62 (5.49 + 0.13)
//!   1.0e6    1416      2  0.42 + 2.53, 0.51 + 3.40, 0.79 + 3.96                      > 115 s (stopped)
//!                         --oversubscribe: 0.64 + 3.46, 0.79 + 4.32
//! ```
//!
//! The distributed factorisation alone gains 1.1 to 1.45 on two ranks when two cores are free
//! (nothing with `--oversubscribe`). But MUMPS's parallel solve phase with the sparse
//! right-hand sides is 5 to 40 times slower than its sequential one (and took 105 s for a
//! 2-entry block at 2e5 dofs: it seems to walk every one of the `n` right-hand sides), and the
//! distributed factorisation with the Schur complement on rank 0 took twice the sequential time
//! at 2e5 dofs and more than 20 times it at 1e6. So the contact routes keep the sequential
//! Schur factorisation (`schur.rs`); this module is kept for the measurements and for a MUMPS
//! or a machine where they turn out otherwise.
use std::marker::PhantomData;

use super::{petsc, to_petsc_int, Matrix, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// A MUMPS Cholesky factorisation (distributed over the matrix's ranks) with the block
/// `(K⁻¹)_cc` on chosen rows, the same on every rank.
pub struct InverseBlockFactor<'s> {
    factor: sys::Mat,
    size: usize,
    inverse: Vec<f64>,
    seconds: [f64; 3],
    /// Built by [`InverseBlockFactor::with_schur_complement`]: no solves.
    schur_only: bool,
    _session: PhantomData<&'s Session>,
}

impl<'s> InverseBlockFactor<'s> {
    /// Factorise `matrix` (SPD, distributed by rows over the session's ranks) with MUMPS and
    /// compute `(K⁻¹)_cc` on `rows` (none: the factorisation alone; global indices, the same on every rank; the block's rows
    /// and columns follow this order). Collective.
    pub fn new(session: &'s Session, matrix: &Matrix<'s>, rows: &[usize]) -> Result<Self> {
        let n = matrix.global_size();
        if rows.iter().any(|&r| r >= n) {
            return Err(Error::PetscUsage(format!("inverse rows must be below the matrix order {n}")));
        }
        let mut sorted = rows.to_vec();
        sorted.sort_unstable();
        if sorted.windows(2).any(|w| w[0] == w[1]) {
            return Err(Error::PetscUsage("inverse rows must be distinct".into()));
        }
        let (mut this, start) = Self::factorise(session, matrix, rows.len(), None)?;
        let f = this.factor;
        if !rows.is_empty() {
            this.inverse = selected_inverse(session, f, n, rows, &sorted)?;
        }
        this.seconds[2] = start.elapsed().as_secs_f64() - this.seconds[0] - this.seconds[1];
        Ok(this)
    }

    /// `(K⁻¹)_cc`, row-major `size × size`, on every rank.
    pub fn inverse_block(&self) -> &[f64] {
        &self.inverse
    }

    /// The factorisation distributed over the ranks with the Schur complement `S` on `rows`
    /// returned centralized on rank 0 (ICNTL(19) = 1: rank 0 names the rows, the others an empty
    /// set), `(K⁻¹)_cc = S⁻¹` inverted there by LAPACK and summed to every rank. Measured against
    /// [`InverseBlockFactor::new`] (`examples/inverse_block_timing.rs`); PETSc 3.18 refuses
    /// `MatSolve` on such a factor in parallel, so its [`InverseBlockFactor::solve`] is refused
    /// too. Collective.
    pub fn with_schur_complement(session: &'s Session, matrix: &Matrix<'s>, rows: &[usize]) -> Result<Self> {
        let n = matrix.global_size();
        if rows.is_empty() || rows.iter().any(|&r| r >= n) {
            return Err(Error::PetscUsage(format!("Schur rows must be non-empty and below the matrix order {n}")));
        }
        // Rank 0 names the Schur rows, the others an empty set (ICNTL(19) = 1).
        let mine: &[usize] = if session.rank() == 0 { rows } else { &[] };
        let (mut this, start) = Self::factorise(session, matrix, rows.len(), Some(mine))?;
        let f = this.factor;
        let m = rows.len();
        if session.rank() == 0 {
            fill_symmetric_schur(f, m)?;
        }
        petsc!(MatFactorInvertSchurComplement(f))?;
        let mut block = vec![0.0; m * m];
        if session.rank() == 0 {
            let (inverse, _) = super::schur::read_schur(f, m)?;
            block = inverse;
        }
        this.inverse = session.world().sum(&block)?;
        this.seconds[2] = start.elapsed().as_secs_f64() - this.seconds[0] - this.seconds[1];
        Ok(this)
    }

    /// The distributed MUMPS Cholesky factorisation of `matrix` for a block of `size` rows,
    /// with the Schur complement on `schur_rows` (this rank's list) when given; the analysis
    /// and numerical times in `seconds[0..2]`, and the clock they started from.
    fn factorise(
        session: &'s Session,
        matrix: &Matrix<'s>,
        size: usize,
        schur_rows: Option<&[usize]>,
    ) -> Result<(Self, std::time::Instant)> {
        session.prefer_amf_ordering("")?;
        let mut f: sys::Mat = std::ptr::null_mut();
        petsc!(MatGetFactor(matrix.raw, c"mumps".as_ptr(), sys::MatFactorType::MAT_FACTOR_CHOLESKY, &mut f))?;
        // Owned from here: dropped (destroyed) on every error below.
        let mut this = InverseBlockFactor {
            factor: f,
            size,
            inverse: Vec::new(),
            seconds: [0.0; 3],
            schur_only: schur_rows.is_some(),
            _session: PhantomData,
        };
        let start = std::time::Instant::now();
        if let Some(rows) = schur_rows {
            super::schur::set_schur_rows(f, session.world(), rows)?;
        }
        let mut info = sys::MatFactorInfo::default();
        petsc!(MatFactorInfoInitialize(&mut info))?;
        petsc!(MatCholeskyFactorSymbolic(f, matrix.raw, std::ptr::null_mut(), &info))?;
        this.seconds[0] = start.elapsed().as_secs_f64();
        petsc!(MatCholeskyFactorNumeric(f, matrix.raw, &info))?;
        let mut infog = 0 as sys::PetscInt;
        petsc!(MatMumpsGetInfog(f, 1, &mut infog))?;
        if infog < 0 {
            return Err(super::schur::factor_failure(infog as i64));
        }
        this.seconds[1] = start.elapsed().as_secs_f64() - this.seconds[0];
        Ok((this, start))
    }

    /// Wall-clock seconds of the analysis (ordering, symbolic factorisation), the numerical
    /// factorisation and the block of the inverse (this rank's view).
    pub fn seconds(&self) -> [f64; 3] {
        self.seconds
    }

    /// The number of rows of the block.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Solve `K x = b` with the factor (distributed vectors of the matrix's layout; collective).
    pub fn solve(&self, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<()> {
        if self.schur_only {
            return Err(Error::PetscUsage("InverseBlockFactor::solve on a factor with a Schur complement".into()));
        }
        if b.global_size() != x.global_size() {
            return Err(Error::PetscUsage("InverseBlockFactor::solve: vector sizes differ".into()));
        }
        petsc!(MatSolve(self.factor, b.raw, x.raw))
    }
}

/// The entries `(K⁻¹)_{rows[a], rows[b]}` from the factor `f` (module documentation), row-major,
/// on every rank. `sorted`: `rows` in increasing order.
fn selected_inverse(session: &Session, f: sys::Mat, n: usize, rows: &[usize], sorted: &[usize]) -> Result<Vec<f64>> {
    let s = rows.len();
    let host = session.rank() == 0;
    let world = session.world();
    // Bᵀ (n × n: MUMPS wants as many right-hand sides as the order, INFOG(1) = -47 otherwise):
    // row `r` of each wanted row holds every wanted row, the others are empty; rank 0 owns it
    // all.
    let local = if host { n } else { 0 };
    let mut indptr: Vec<sys::PetscInt> = Vec::new();
    let mut indices: Vec<sys::PetscInt> = Vec::new();
    if host {
        let columns: Vec<sys::PetscInt> =
            sorted.iter().map(|&r| to_petsc_int(r, "inverse row")).collect::<Result<_>>()?;
        indptr.reserve(n + 1);
        indptr.push(0);
        indices.reserve(s * s);
        let mut wanted = sorted.iter().peekable();
        for r in 0..n {
            if wanted.next_if_eq(&&r).is_some() {
                indices.extend_from_slice(&columns);
            }
            indptr.push(to_petsc_int(indices.len(), "inverse entries")?);
        }
    } else {
        indptr.push(0);
    }
    let zeros = vec![0.0f64; indices.len()];
    let mut bt: sys::Mat = std::ptr::null_mut();
    petsc!(MatCreate(world.raw(), &mut bt))?;
    let mut transposed: sys::Mat = std::ptr::null_mut();
    let result = (|| -> Result<Vec<f64>> {
        petsc!(MatSetSizes(
            bt,
            to_petsc_int(local, "matrix order")?,
            to_petsc_int(local, "matrix order")?,
            to_petsc_int(n, "matrix order")?,
            to_petsc_int(n, "matrix order")?
        ))?;
        petsc!(MatSetType(bt, c"aij".as_ptr()))?;
        // Only the preallocation of bt's actual type acts; the other is ignored.
        petsc!(MatSeqAIJSetPreallocationCSR(bt, indptr.as_ptr(), indices.as_ptr(), zeros.as_ptr()))?;
        petsc!(MatMPIAIJSetPreallocationCSR(bt, indptr.as_ptr(), indices.as_ptr(), zeros.as_ptr()))?;
        petsc!(MatCreateTranspose(bt, &mut transposed))?;
        let computed = petsc!(MatMumpsGetInverse(f, transposed));
        // Back to ordinary solves (module documentation).
        petsc!(MatMumpsSetIcntl(f, 30, 0))?;
        if session.size() > 1 {
            petsc!(MatMumpsSetIcntl(f, 21, 1))?;
        }
        computed?;
        let mut infog = 0 as sys::PetscInt;
        petsc!(MatMumpsGetInfog(f, 1, &mut infog))?;
        if infog < 0 {
            return Err(super::schur::factor_failure(infog as i64));
        }
        // Position of each sorted row in the caller's order.
        let mut position = vec![0usize; s];
        for (a, &r) in rows.iter().enumerate() {
            position[sorted.binary_search(&r).map_err(|_| Error::PetscUsage("inverse rows".into()))?] = a;
        }
        let read = (|| -> Result<Vec<f64>> {
            let mut block = vec![0.0f64; s * s];
            if !host {
                return Ok(block);
            }
            for (j, &r) in sorted.iter().enumerate() {
                let row = to_petsc_int(r, "inverse row")?;
                let mut ncols: sys::PetscInt = 0;
                let mut cols: *const sys::PetscInt = std::ptr::null();
                let mut vals: *const f64 = std::ptr::null();
                petsc!(MatGetRow(bt, row, &mut ncols, &mut cols, &mut vals))?;
                let read = if ncols as usize == s {
                    // SAFETY: PETSc returns ncols column indices and values for the row.
                    let (c, v) = unsafe { (std::slice::from_raw_parts(cols, s), std::slice::from_raw_parts(vals, s)) };
                    for (i, (&col, &value)) in c.iter().zip(v).enumerate() {
                        debug_assert_eq!(col as usize, sorted[i]);
                        block[position[i] * s + position[j]] = value;
                    }
                    Ok(())
                } else {
                    Err(Error::PetscUsage(format!("MUMPS returned {ncols} inverse entries in a column of {s}")))
                };
                petsc!(MatRestoreRow(bt, row, &mut ncols, &mut cols, &mut vals))?;
                read?;
            }
            Ok(block)
        })();
        // Rank 0 alone reads: agree before the reduction, so that its error stops every rank.
        let mut block = world.agree(read, "reading the selected entries of the inverse")?;
        if session.size() > 1 {
            block = world.sum(&block)?;
        }
        Ok(block)
    })();
    if !transposed.is_null() {
        // SAFETY: owned handles; errors ignored on cleanup.
        let _ = unsafe { sys::MatDestroy(&mut transposed) };
    }
    let _ = unsafe { sys::MatDestroy(&mut bt) };
    result
}

/// MUMPS returns one triangle of a symmetric Schur complement centralized by rows (ICNTL(19) =
/// 1, the parallel case; PETSc transposes it in place); LAPACK's Cholesky reads the lower one:
/// mirror the triangle MUMPS filled (the other is zero) into the other. Rank 0.
fn fill_symmetric_schur(f: sys::Mat, m: usize) -> Result<()> {
    let mut s: sys::Mat = std::ptr::null_mut();
    let mut status = sys::MatFactorSchurStatus::MAT_FACTOR_SCHUR_UNFACTORED;
    petsc!(MatFactorGetSchurComplement(f, &mut s, &mut status))?;
    let mut ptr: *mut f64 = std::ptr::null_mut();
    let write = petsc!(MatDenseGetArray(s, &mut ptr));
    if write.is_ok() {
        // SAFETY: a sequential dense m × m matrix, column-major with leading dimension m.
        let a = unsafe { std::slice::from_raw_parts_mut(ptr, m * m) };
        let (mut lower, mut upper) = (0.0f64, 0.0f64);
        for j in 0..m {
            for i in 0..m {
                if i > j {
                    lower += a[j * m + i].abs();
                } else if i < j {
                    upper += a[j * m + i].abs();
                }
            }
        }
        for j in 0..m {
            for i in j + 1..m {
                if upper > lower {
                    a[j * m + i] = a[i * m + j];
                } else {
                    a[i * m + j] = a[j * m + i];
                }
            }
        }
        let _ = unsafe { sys::MatDenseRestoreArray(s, &mut ptr) };
    }
    let restore = petsc!(MatFactorRestoreSchurComplement(f, &mut s, status));
    write?;
    restore
}

impl Drop for InverseBlockFactor<'_> {
    fn drop(&mut self) {
        if !self.factor.is_null() {
            // SAFETY: owned factor; errors ignored (Drop never panics).
            let _ = unsafe { sys::MatDestroy(&mut self.factor) };
        }
    }
}
