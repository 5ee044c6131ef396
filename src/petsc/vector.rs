//! Distributed PETSc vectors (`VECMPI` or `VECSEQ` by communicator size).
use std::marker::PhantomData;
use std::ops::Range;

use super::{petsc, to_petsc_int, Comm, Session};
use crate::error::{Error, Result};
use signorini_sys as sys;

/// An owned PETSc vector; `range` is the block of global indices this rank owns.
pub struct Vector<'s> {
    pub(crate) raw: sys::Vec,
    global: usize,
    range: Range<usize>,
    _session: PhantomData<&'s Session>,
}

impl<'s> Vector<'s> {
    /// A vector of `global` entries of which this rank owns `local` (the owned blocks follow rank
    /// order).
    pub fn new(_session: &'s Session, comm: Comm, local: usize, global: usize) -> Result<Self> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        petsc!(VecCreate(comm.raw(), &mut raw))?;
        let mut v = Vector { raw, global, range: 0..0, _session: PhantomData };
        petsc!(VecSetSizes(
            v.raw,
            to_petsc_int(local, "local vector size")?,
            to_petsc_int(global, "global vector size")?
        ))?;
        petsc!(VecSetFromOptions(v.raw))?;
        v.range = v.query_range()?;
        Ok(v)
    }

    pub(crate) fn from_raw(raw: sys::Vec) -> Result<Self> {
        let mut v = Vector { raw, global: 0, range: 0..0, _session: PhantomData };
        let mut n: sys::PetscInt = 0;
        petsc!(VecGetSize(v.raw, &mut n))?;
        v.global = n as usize;
        v.range = v.query_range()?;
        Ok(v)
    }

    fn query_range(&self) -> Result<Range<usize>> {
        let (mut lo, mut hi): (sys::PetscInt, sys::PetscInt) = (0, 0);
        petsc!(VecGetOwnershipRange(self.raw, &mut lo, &mut hi))?;
        Ok(lo as usize..hi as usize)
    }

    /// Length of the whole vector.
    pub fn global_size(&self) -> usize {
        self.global
    }
    /// The global entries this rank owns.
    pub fn owned_range(&self) -> Range<usize> {
        self.range.clone()
    }

    /// Overwrite the owned entries (`values.len()` must equal the owned size).
    pub fn set_owned(&mut self, values: &[f64]) -> Result<()> {
        if values.len() != self.range.len() {
            return Err(Error::PetscUsage(format!(
                "set_owned: {} values for a vector owning {} entries",
                values.len(),
                self.range.len()
            )));
        }
        let mut ptr: *mut f64 = std::ptr::null_mut();
        petsc!(VecGetArray(self.raw, &mut ptr))?;
        // SAFETY: VecGetArray gives the owned block, of the length checked above.
        unsafe { std::slice::from_raw_parts_mut(ptr, values.len()) }.copy_from_slice(values);
        petsc!(VecRestoreArray(self.raw, &mut ptr))
    }

    /// A copy of the owned entries.
    pub fn owned_values(&self) -> Result<Vec<f64>> {
        let mut ptr: *const f64 = std::ptr::null();
        petsc!(VecGetArrayRead(self.raw, &mut ptr))?;
        // SAFETY: the owned block has range.len() entries.
        let out = if self.range.is_empty() {
            Vec::new()
        } else {
            unsafe { std::slice::from_raw_parts(ptr, self.range.len()) }.to_vec()
        };
        petsc!(VecRestoreArrayRead(self.raw, &mut ptr))?;
        Ok(out)
    }

    /// Every entry of the vector, on every rank (`VecScatterCreateToAll`).
    pub fn gather_all(&self) -> Result<Vec<f64>> {
        let mut scatter: sys::VecScatter = std::ptr::null_mut();
        let mut all: sys::Vec = std::ptr::null_mut();
        petsc!(VecScatterCreateToAll(self.raw, &mut scatter, &mut all))?;
        let all = Vector::from_raw(all)?;
        let result = (|| {
            petsc!(VecScatterBegin(
                scatter,
                self.raw,
                all.raw,
                sys::InsertMode::INSERT_VALUES,
                sys::ScatterMode::SCATTER_FORWARD
            ))?;
            petsc!(VecScatterEnd(
                scatter,
                self.raw,
                all.raw,
                sys::InsertMode::INSERT_VALUES,
                sys::ScatterMode::SCATTER_FORWARD
            ))?;
            all.owned_values()
        })();
        let _ = unsafe { sys::VecScatterDestroy(&mut scatter) };
        result
    }

    /// The Euclidean norm of the whole vector.
    pub fn norm2(&self) -> Result<f64> {
        let mut n = 0.0;
        petsc!(VecNorm(self.raw, sys::NormType::NORM_2, &mut n))?;
        Ok(n)
    }

    /// A new vector with the same layout, zero-filled.
    pub fn duplicate(&self) -> Result<Vector<'s>> {
        let mut raw: sys::Vec = std::ptr::null_mut();
        petsc!(VecDuplicate(self.raw, &mut raw))?;
        let v = Vector { raw, global: self.global, range: self.range.clone(), _session: PhantomData };
        petsc!(VecZeroEntries(v.raw))?;
        Ok(v)
    }

    /// self = alpha * x + self
    pub fn axpy(&mut self, alpha: f64, x: &Vector<'s>) -> Result<()> {
        if x.global != self.global {
            return Err(Error::PetscUsage("axpy: vectors of different sizes".into()));
        }
        petsc!(VecAXPY(self.raw, alpha, x.raw))
    }
}

impl Drop for Vector<'_> {
    fn drop(&mut self) {
        if !self.raw.is_null() {
            // SAFETY: we own the handle; errors are ignored (Drop never panics).
            let _ = unsafe { sys::VecDestroy(&mut self.raw) };
        }
    }
}
