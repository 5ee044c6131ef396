//! Sparse-matrix algorithms written in Rust (no PETSc): the threshold incomplete Cholesky
//! factorisation behind `-pc_type ict`, see [`incomplete_cholesky`].
pub mod incomplete_cholesky;
pub mod ordering;

pub use incomplete_cholesky::{CsrMatrix, IctOptions, IncompleteCholesky};
