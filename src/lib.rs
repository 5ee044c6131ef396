//! # signorini
//!
//! 2D frictional contact in linear elasticity with certified error control, on PETSc.
//!
//! Layers, bottom up:
//! - [`petsc`]: the only module that touches the PETSc FFI crate (`signorini-sys`); all `unsafe`
//!   code lives there.
//! - [`mesh`]: triangle meshes (P1/P2), Gmsh MSH 4.1 input, Gmsh-driven and structured generation.
//! - [`fem`]: Lagrange elements, quadrature, Hooke's law, assembly, post-processing.
//! - [`scene`]: the TOML scene format.
//! - [`output`]: `.vtu` for ParaView and meshio, `report.json`.
//! - [`export`]: the condensed contact problem in the FCLIB format (HDF5), for other solvers.
//! - [`problem`]: the driver, whose methods read like the algorithm.
//! - [`sparse`]: sparse-matrix algorithms in Rust (threshold incomplete Cholesky, `-pc_type ict`).
//!
//! The library never prints or exits; the `signorini` binary does.
#![deny(unsafe_code)]

pub mod adapt;
pub mod bench;
pub mod contact;
pub mod dual;
pub mod error;
pub mod estimate;
pub mod export;
pub mod fem;
pub mod mesh;
pub mod output;
#[allow(unsafe_code)]
pub mod petsc;
pub mod problem;
pub mod resources;
pub mod scene;
pub mod sparse;

pub use error::{Error, Result};
