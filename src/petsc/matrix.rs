//! PETSc AIJ matrices (`MATSEQAIJ` / `MATMPIAIJ`) built from our own CSR rows with exact
//! preallocation: the diagonal-block and off-diagonal-block counts of every owned row are
//! computed from the pattern, so PETSc never allocates during insertion.
use std::marker::PhantomData;
use std::ops::Range;

use super::{petsc, to_petsc_int, Comm, Session, Vector};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// A PETSc AIJ matrix (distributed by rows over the session's ranks), owned: destroyed on drop.
pub struct Matrix<'s> {
    pub(crate) raw: sys::Mat,
    global: usize,
    range: Range<usize>,
    _session: PhantomData<&'s Session>,
}

impl<'s> Matrix<'s> {
    /// A square matrix of order `global` from the CSR rows `first_row .. first_row + nrows` this
    /// rank owns (`indptr.len() == nrows + 1`, global column indices, sorted per row). The
    /// ranks' blocks must follow each other in rank order. `symmetric_positive_definite` is
    /// passed to PETSc as `MAT_SPD` (lets Cholesky and CG be chosen safely).
    #[allow(clippy::too_many_arguments)]
    pub fn from_csr_rows(
        _session: &'s Session,
        comm: Comm,
        global: usize,
        first_row: usize,
        indptr: &[usize],
        indices: &[usize],
        values: &[f64],
        block_size: usize,
        symmetric_positive_definite: bool,
    ) -> Result<Self> {
        // The rows are checked on each rank; the outcome is agreed before MatCreate (collective),
        // so that a rank whose rows are wrong does not leave the others waiting in it.
        let checked = (|| -> Result<(usize, Vec<sys::PetscInt>, Vec<sys::PetscInt>)> {
            let nrows = indptr.len().checked_sub(1).ok_or_else(|| Error::PetscUsage("CSR indptr is empty".into()))?;
            if indptr[0] != 0 || indptr[nrows] != indices.len() || indices.len() != values.len() {
                return Err(Error::PetscUsage(format!(
                    "CSR arrays disagree: indptr ends at {}, {} column indices, {} values",
                    indptr[nrows],
                    indices.len(),
                    values.len()
                )));
            }
            if first_row + nrows > global {
                return Err(Error::PetscUsage(format!(
                    "rows {first_row}..{} exceed the matrix order {global}",
                    first_row + nrows
                )));
            }
            if block_size == 0 || nrows % block_size != 0 || !first_row.is_multiple_of(block_size) {
                return Err(Error::PetscUsage(format!(
                    "owned rows {first_row}..{} are not aligned on the block size {block_size}",
                    first_row + nrows
                )));
            }
            let owned = first_row..first_row + nrows;
            let mut d_nnz = Vec::with_capacity(nrows);
            let mut o_nnz = Vec::with_capacity(nrows);
            for r in 0..nrows {
                let cols = &indices[indptr[r]..indptr[r + 1]];
                if indptr[r + 1] < indptr[r] {
                    return Err(Error::PetscUsage(format!("CSR row {} has a negative length", first_row + r)));
                }
                let mut d = 0;
                for (k, &c) in cols.iter().enumerate() {
                    if c >= global {
                        return Err(Error::PetscUsage(format!(
                            "row {}: column {c} out of range (order {global})",
                            first_row + r
                        )));
                    }
                    if k > 0 && cols[k - 1] >= c {
                        return Err(Error::PetscUsage(format!(
                            "row {}: column indices not strictly increasing",
                            first_row + r
                        )));
                    }
                    if owned.contains(&c) {
                        d += 1;
                    }
                }
                d_nnz.push(to_petsc_int(d, "row length")?);
                o_nnz.push(to_petsc_int(cols.len() - d, "row length")?);
            }
            Ok((nrows, d_nnz, o_nnz))
        })();
        let (nrows, d_nnz, o_nnz) = comm.agree(checked, "checking a matrix's rows")?;
        let owned = first_row..first_row + nrows;
        let mut raw: sys::Mat = std::ptr::null_mut();
        petsc!(MatCreate(comm.raw(), &mut raw))?;
        let m = Matrix { raw, global, range: owned.clone(), _session: PhantomData };
        let nloc = to_petsc_int(nrows, "local rows")?;
        let nglob = to_petsc_int(global, "matrix order")?;
        petsc!(MatSetSizes(m.raw, nloc, nloc, nglob, nglob))?;
        petsc!(MatSetType(m.raw, c"aij".as_ptr()))?;
        petsc!(MatSetBlockSize(m.raw, to_petsc_int(block_size, "block size")?))?;
        petsc!(MatSeqAIJSetPreallocation(m.raw, 0, d_nnz.as_ptr()))?;
        petsc!(MatMPIAIJSetPreallocation(m.raw, 0, d_nnz.as_ptr(), 0, o_nnz.as_ptr()))?;
        petsc!(MatSetOption(m.raw, sys::MatOption::MAT_NEW_NONZERO_ALLOCATION_ERR, sys::PetscBool::PETSC_TRUE))?;
        let (mut lo, mut hi): (sys::PetscInt, sys::PetscInt) = (0, 0);
        petsc!(MatGetOwnershipRange(m.raw, &mut lo, &mut hi))?;
        let layout = if lo as usize != owned.start || hi as usize != owned.end {
            Err(Error::PetscUsage(format!(
                "this rank passed rows {}..{} but PETSc's layout gives it {lo}..{hi}: ranks must own consecutive blocks in rank order",
                owned.start, owned.end
            )))
        } else {
            Ok(())
        };
        // Agreed before the assembly (collective).
        comm.agree(layout, "checking a matrix's row layout")?;
        let cols32: Vec<sys::PetscInt> = indices.iter().map(|&c| c as sys::PetscInt).collect();
        for r in 0..nrows {
            let row = (first_row + r) as sys::PetscInt;
            let (a, b) = (indptr[r], indptr[r + 1]);
            petsc!(MatSetValues(
                m.raw,
                1,
                &row,
                (b - a) as sys::PetscInt,
                cols32[a..b].as_ptr(),
                values[a..b].as_ptr(),
                sys::InsertMode::INSERT_VALUES
            ))?;
        }
        petsc!(MatAssemblyBegin(m.raw, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
        petsc!(MatAssemblyEnd(m.raw, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
        if symmetric_positive_definite {
            petsc!(MatSetOption(m.raw, sys::MatOption::MAT_SYMMETRIC, sys::PetscBool::PETSC_TRUE))?;
            petsc!(MatSetOption(m.raw, sys::MatOption::MAT_SPD, sys::PetscBool::PETSC_TRUE))?;
        }
        Ok(m)
    }

    /// Declare the matrix symmetric (not necessarily definite): MUMPS then factors it as
    /// LDLᵀ under `-pc_type cholesky` (a saddle point, for instance).
    pub fn set_symmetric(&self) -> Result<()> {
        petsc!(MatSetOption(self.raw, sys::MatOption::MAT_SYMMETRIC, sys::PetscBool::PETSC_TRUE))?;
        petsc!(MatSetOption(self.raw, sys::MatOption::MAT_SYMMETRY_ETERNAL, sys::PetscBool::PETSC_TRUE))
    }

    /// Number of rows (and columns) of the whole matrix.
    pub fn global_size(&self) -> usize {
        self.global
    }
    /// The global rows this rank owns.
    pub fn owned_rows(&self) -> Range<usize> {
        self.range.clone()
    }

    /// A zero vector laid out like the matrix rows.
    pub fn create_vector(&self) -> Result<Vector<'s>> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        petsc!(MatCreateVecs(self.raw, std::ptr::null_mut(), &mut raw))?;
        let v = Vector::from_raw(raw)?;
        petsc!(VecZeroEntries(v.raw))?;
        Ok(v)
    }

    /// The true relative residual ‖b − A x‖ / ‖b‖ (‖b − A x‖ when b = 0), the independent check
    /// applied to every linear solve.
    pub fn relative_residual(&self, x: &Vector<'s>, b: &Vector<'s>) -> Result<f64> {
        let mut r = b.duplicate()?;
        self.multiply(x, &mut r)?;
        r.axpy(-1.0, b)?;
        let bnorm = b.norm2()?;
        let rnorm = r.norm2()?;
        Ok(if bnorm > 0.0 { rnorm / bnorm } else { rnorm })
    }

    /// y = A x
    pub fn multiply(&self, x: &Vector<'s>, y: &mut Vector<'s>) -> Result<()> {
        if x.global_size() != self.global || y.global_size() != self.global {
            return Err(Error::PetscUsage("multiply: vector size differs from the matrix order".into()));
        }
        petsc!(MatMult(self.raw, x.raw, y.raw))
    }
}

impl Drop for Matrix<'_> {
    fn drop(&mut self) {
        if !self.raw.is_null() {
            // SAFETY: owned handle; errors ignored (Drop never panics).
            let _ = unsafe { sys::MatDestroy(&mut self.raw) };
        }
    }
}
