//! LU factorisation of a small dense matrix by LAPACK, through PETSc's sequential dense
//! matrices (`MatLUFactor` calls `getrf`, `MatSolve` calls `getrs`, both from the BLAS/LAPACK
//! PETSc is linked with: the OpenBLAS of `setup.sh`).
//!
//! The full-space Newton's eliminations (`contact_routes/block_elimination.rs`,
//! `contact_routes/floating_elimination.rs`) factorise one dense system per Newton step, of the order
//! of the number of closed and sticking contact rows: about 1 100 unknowns on the two-body
//! benchmark at 10⁶ dofs. nalgebra's LU is unblocked (0.15 s at n = 1 100, 2.2 s at
//! n = 2 000 on this project's machine, where it leaves the cache), against a blocked `getrf`
//! that runs at the speed of the BLAS's matrix product.
//!
//! A zero pivot (an exactly singular matrix, as nalgebra's LU reports it) is `Ok(None)` from
//! [`DenseLu::new`]; every other PETSc failure is an error.
use std::marker::PhantomData;

use nalgebra::DMatrix;

use super::{petsc, Session};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// PETSc's error code for a zero pivot in an LU factorisation (`PETSC_ERR_MAT_LU_ZRPVT`).
const ZERO_PIVOT: i32 = 71;

/// The LU factors of a square dense matrix, with the work vectors of its solves. One process.
pub struct DenseLu<'s> {
    factor: sys::Mat,
    rhs: sys::Vec,
    solution: sys::Vec,
    n: usize,
    _session: PhantomData<&'s Session>,
}

impl<'s> DenseLu<'s> {
    /// Factorise `a` (square, at least 1 × 1); `None` if a pivot is exactly zero.
    pub fn new(_session: &'s Session, a: &DMatrix<f64>) -> Result<Option<Self>> {
        Self::factorise(a)
    }

    /// [`DenseLu::new`] for a caller that has checked that a session is alive.
    fn factorise(a: &DMatrix<f64>) -> Result<Option<Self>> {
        let n = a.nrows();
        if n == 0 || a.ncols() != n {
            return Err(Error::PetscUsage(format!("DenseLu of a {} × {} matrix", a.nrows(), a.ncols())));
        }
        let size = sys::PetscInt::try_from(n).map_err(|_| Error::PetscUsage("DenseLu: matrix too large".into()))?;
        // SAFETY: valid while a session is alive (checked by the callers).
        let comm = unsafe { sys::signorini_comm_self() };
        let mut this = DenseLu {
            factor: std::ptr::null_mut(),
            rhs: std::ptr::null_mut(),
            solution: std::ptr::null_mut(),
            n,
            _session: PhantomData,
        };
        // PETSc allocates the storage (a null array) and the factor works in place.
        petsc!(MatCreateSeqDense(comm, size, size, std::ptr::null_mut(), &mut this.factor))?;
        let mut values: *mut f64 = std::ptr::null_mut();
        petsc!(MatDenseGetArray(this.factor, &mut values))?;
        // SAFETY: a sequential dense n × n matrix, column-major with leading dimension n (PETSc
        // allocated it so), the layout of nalgebra's storage.
        unsafe { std::slice::from_raw_parts_mut(values, n * n) }.copy_from_slice(a.as_slice());
        petsc!(MatDenseRestoreArray(this.factor, &mut values))?;
        petsc!(MatAssemblyBegin(this.factor, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
        petsc!(MatAssemblyEnd(this.factor, sys::MatAssemblyType::MAT_FINAL_ASSEMBLY))?;
        // SAFETY: MatFactorInfoInitialize fills every field of the struct.
        let mut info: sys::MatFactorInfo = unsafe { std::mem::zeroed() };
        petsc!(MatFactorInfoInitialize(&mut info))?;
        match petsc!(MatLUFactor(this.factor, std::ptr::null_mut(), std::ptr::null_mut(), &info)) {
            Ok(()) => {}
            Err(Error::Petsc { code: ZERO_PIVOT, .. }) => return Ok(None),
            Err(e) => return Err(e),
        }
        petsc!(VecCreateSeq(comm, size, &mut this.rhs))?;
        petsc!(VecCreateSeq(comm, size, &mut this.solution))?;
        Ok(Some(this))
    }

    /// `x = A⁻¹ b`.
    pub fn solve(&self, b: &[f64]) -> Result<Vec<f64>> {
        if b.len() != self.n {
            return Err(Error::PetscUsage(format!("DenseLu::solve: {} values for order {}", b.len(), self.n)));
        }
        let mut values: *mut f64 = std::ptr::null_mut();
        petsc!(VecGetArray(self.rhs, &mut values))?;
        // SAFETY: a sequential vector of n values.
        unsafe { std::slice::from_raw_parts_mut(values, self.n) }.copy_from_slice(b);
        petsc!(VecRestoreArray(self.rhs, &mut values))?;
        petsc!(MatSolve(self.factor, self.rhs, self.solution))?;
        let mut read: *const f64 = std::ptr::null();
        petsc!(VecGetArrayRead(self.solution, &mut read))?;
        // SAFETY: a sequential vector of n values.
        let x = unsafe { std::slice::from_raw_parts(read, self.n) }.to_vec();
        petsc!(VecRestoreArrayRead(self.solution, &mut read))?;
        Ok(x)
    }
}

/// Solve `A x = b` once (factorise, solve, free), for a caller that holds no session reference:
/// the condensed solvers get it as their `contact::DenseSolver`, which the `contact` module
/// calls without knowing PETSc. `None` if a pivot is exactly zero; an error unless a PETSc
/// session is alive in this process.
pub fn solve_once(a: &DMatrix<f64>, b: &[f64]) -> Result<Option<Vec<f64>>> {
    if !super::session_alive() {
        return Err(Error::PetscUsage("dense_lu::solve_once needs a live PETSc session".into()));
    }
    match DenseLu::factorise(a)? {
        Some(lu) => lu.solve(b).map(Some),
        None => Ok(None),
    }
}

impl Drop for DenseLu<'_> {
    fn drop(&mut self) {
        // SAFETY: owned handles (or null: PETSc's destroy functions accept a null handle);
        // errors ignored (Drop never panics).
        unsafe {
            let _ = sys::VecDestroy(&mut self.rhs);
            let _ = sys::VecDestroy(&mut self.solution);
            let _ = sys::MatDestroy(&mut self.factor);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The library's unit tests run without a PETSc session: the one-shot solve refuses.
    #[test]
    fn solve_once_without_a_session_is_a_usage_error() {
        let a = DMatrix::<f64>::identity(2, 2);
        assert!(matches!(solve_once(&a, &[1.0, 2.0]), Err(Error::PetscUsage(_))));
    }
}
