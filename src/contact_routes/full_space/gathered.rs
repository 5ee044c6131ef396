//! The gathered dense route under MPI (`dense_schur_gathered`): every rank receives the whole
//! constrained stiffness `K` and load, and runs the one-process full-space route on them alone
//! (`Session::alone`: its PETSc objects and agreements on `PETSC_COMM_SELF`).
//!
//! Why (measured on the project's 2-core machine, square block, Coulomb, 2e5 dofs, 8 Newton
//! steps, `OMP_NUM_THREADS=1`): on one process the cost model takes the dense Schur route, one
//! MUMPS Cholesky of `K` with the Schur complement on the contact dofs (1.0–1.1 s of solve).
//! PETSc 3.18 computes MUMPS's Schur complement on one process only, so under `mpirun` the
//! route was the distributed sparse LU of the mixed Jacobian, one LU per Newton step: 8 LUs of
//! 4.4–6.8 s on two ranks against 4.4–4.8 s on one. MUMPS's own statistics of that LU are the
//! same on one and two ranks (`-contact_ksp_view`, first step: estimated flops RINFOG(1) 5.98e9
//! against 6.26e9, factor entries INFOG(3) 21.1e6 against 21.2e6, AMD ordering INFOG(7) = 2 on
//! both, no maximum transversal INFOG(23) = 0 on both, 0 off-diagonal pivots, 714–886 delayed
//! pivots against 743–920), so the distributed LU is not worse-conditioned or fuller: it is
//! eight factorisations against one, and two ranks on two shared cores gain little on each
//! (0.7–1.25×). The route on several ranks that costs what one does: each rank runs the
//! one-process route on the gathered problem, so two ranks take the serial Newton steps to the
//! serial answer, at the serial cost plus the gather (one broadcast of each rank's rows), and
//! no rank waits for another's answer.
//!
//! Each rank holds the whole factor of `K` (the memory of one process, on every rank). The
//! rows are sent exactly (indices as `u64`, values as `f64` bits), so the gathered `K` is the
//! one a single process assembles, to the round-off of the summation order of the element
//! contributions.
use std::ops::Range;

use crate::error::{Error, Result};
use crate::fem::assembly::{CsrRows, LinearSystem};
use crate::petsc::Session;

/// This rank's rows (`system`) of the constrained system, on every rank: the whole system
/// (rows `0..n`). Collective.
pub fn gather_system(session: &Session, system: &LinearSystem, n: usize) -> Result<LinearSystem> {
    let pieces = session.world().all_gather_bytes(encode(system))?;
    let mut matrix = CsrRows { first_row: 0, num_cols: n, indptr: vec![0], indices: Vec::new(), values: Vec::new() };
    let mut rhs = Vec::with_capacity(n);
    for (rank, bytes) in pieces.iter().enumerate() {
        decode(bytes, &mut matrix, &mut rhs).map_err(|why| {
            Error::PetscUsage(format!(
                "gathering the stiffness for the gathered contact route: rank {rank}'s rows: {why}"
            ))
        })?;
    }
    if matrix.num_rows() != n || rhs.len() != n {
        return Err(Error::PetscUsage(format!(
            "gathering the stiffness for the gathered contact route: {} rows and {} loads gathered for {n} dofs",
            matrix.num_rows(),
            rhs.len()
        )));
    }
    Ok(LinearSystem { matrix, rhs })
}

/// The dof ranges of one process holding every row.
pub fn whole(n: usize) -> Vec<Range<usize>> {
    vec![0..n]
}

/// `first_row`, rows, entries, then the row lengths, columns, values and loads (little endian).
fn encode(system: &LinearSystem) -> Vec<u8> {
    let k = &system.matrix;
    let rows = k.num_rows();
    let mut out = Vec::with_capacity(24 + 8 * (rows + 2 * k.nnz() + system.rhs.len()));
    for v in [k.first_row, rows, k.nnz()] {
        out.extend_from_slice(&(v as u64).to_le_bytes());
    }
    for r in 0..rows {
        out.extend_from_slice(&((k.indptr[r + 1] - k.indptr[r]) as u64).to_le_bytes());
    }
    for &c in &k.indices[k.indptr[0]..k.indptr[rows]] {
        out.extend_from_slice(&(c as u64).to_le_bytes());
    }
    for &v in &k.values[k.indptr[0]..k.indptr[rows]] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for &b in &system.rhs {
        out.extend_from_slice(&b.to_le_bytes());
    }
    out
}

/// Append one rank's rows (see [`encode`]) to `matrix` and `rhs`; they must follow the rows
/// already there.
fn decode(bytes: &[u8], matrix: &mut CsrRows, rhs: &mut Vec<f64>) -> std::result::Result<(), String> {
    let mut words = bytes.chunks_exact(8).map(|w| {
        let mut a = [0u8; 8];
        a.copy_from_slice(w);
        a
    });
    if bytes.len() % 8 != 0 {
        return Err(format!("{} bytes, not a whole number of words", bytes.len()));
    }
    let mut next = || words.next().ok_or_else(|| "the message ends early".to_string());
    let int = |w: [u8; 8]| usize::try_from(u64::from_le_bytes(w)).map_err(|_| "an index too large".to_string());
    let first_row = int(next()?)?;
    let rows = int(next()?)?;
    let entries = int(next()?)?;
    if first_row != matrix.num_rows() {
        return Err(format!("starts at row {first_row}, after {} rows", matrix.num_rows()));
    }
    let mut end = *matrix.indptr.last().unwrap_or(&0);
    for _ in 0..rows {
        end += int(next()?)?;
        matrix.indptr.push(end);
    }
    for _ in 0..entries {
        let c = int(next()?)?;
        if c >= matrix.num_cols {
            return Err(format!("column {c} beyond {}", matrix.num_cols));
        }
        matrix.indices.push(c);
    }
    for _ in 0..entries {
        matrix.values.push(f64::from_le_bytes(next()?));
    }
    for _ in 0..rows {
        rhs.push(f64::from_le_bytes(next()?));
    }
    if matrix.indices.len() != end || next().is_ok() {
        return Err("row lengths, entries and loads do not match".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(
        first_row: usize,
        indptr: Vec<usize>,
        indices: Vec<usize>,
        values: Vec<f64>,
        rhs: Vec<f64>,
    ) -> LinearSystem {
        LinearSystem { matrix: CsrRows { first_row, num_cols: 3, indptr, indices, values }, rhs }
    }

    #[test]
    fn two_ranks_rows_decode_to_the_whole_system() {
        let top = rows(0, vec![0, 2], vec![0, 1], vec![4.0, -1.0], vec![1.5]);
        let bottom = rows(1, vec![0, 2, 4], vec![0, 1, 1, 2], vec![-1.0, 4.0, -0.5, 2.0], vec![0.25, -3.0]);
        let mut m = CsrRows { first_row: 0, num_cols: 3, indptr: vec![0], indices: vec![], values: vec![] };
        let mut rhs = Vec::new();
        decode(&encode(&top), &mut m, &mut rhs).unwrap();
        decode(&encode(&bottom), &mut m, &mut rhs).unwrap();
        assert_eq!(m.indptr, vec![0, 2, 4, 6]);
        assert_eq!(m.indices, vec![0, 1, 0, 1, 1, 2]);
        assert_eq!(m.values, vec![4.0, -1.0, -1.0, 4.0, -0.5, 2.0]);
        assert_eq!(rhs, vec![1.5, 0.25, -3.0]);
        // Out of order, or cut short: refused.
        let mut m2 = CsrRows { first_row: 0, num_cols: 3, indptr: vec![0], indices: vec![], values: vec![] };
        assert!(decode(&encode(&bottom), &mut m2, &mut Vec::new()).unwrap_err().contains("starts at row 1"));
        let bytes = encode(&top);
        let mut m3 = CsrRows { first_row: 0, num_cols: 3, indptr: vec![0], indices: vec![], values: vec![] };
        assert!(decode(&bytes[..bytes.len() - 8], &mut m3, &mut Vec::new()).unwrap_err().contains("ends early"));
    }
}
