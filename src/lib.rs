//! # signorini
//!
//! 2D frictional contact in linear elasticity with certified error control, on PETSc.
//!
//! Modules, bottom up:
//! - [`petsc`]: the only module that touches the PETSc FFI crate (`signorini-sys`); all `unsafe`
//!   code lives there. One process-wide session, vectors, matrices, KSP, SNES, TAO, MUMPS.
//! - [`error`]: the one error type, [`Error`], whose variants carry the file, line, entity or
//!   PETSc code.
//! - [`resources`]: timings per phase and peak memory.
//! - [`sparse`]: sparse-matrix algorithms in Rust (threshold incomplete Cholesky, `-pc_type ict`).
//! - [`mesh`]: triangle meshes (P1/P2), Gmsh MSH 4.1 input, Gmsh-driven and structured
//!   generation, the mesh cache, and building the mesh a scene describes.
//! - [`fem`]: Lagrange elements, the HCT element, quadrature, Hooke's law, assembly,
//!   post-processing.
//! - [`scene`]: the TOML scene format and `SceneBuilder`.
//! - [`contact`]: the contact points, rigid obstacles, mortar coupling of two bodies, the
//!   condensed contact problem and its solvers, the independent residuals.
//! - [`dual`]: the dual (stress) formulation: the Airy function on HCT elements, with contact.
//! - [`estimate`]: the error in the constitutive relation from the primal–dual pair.
//! - [`output`]: `.vtu` for ParaView and meshio, atomic files, SVG plots.
//! - `contact_routes` (internal): how the driver solves contact, the full-space Newton with its
//!   eliminations and the condensed route.
//! - [`report`]: what a run reports (contact, several bodies, warnings) and the files it writes.
//! - [`problem`]: the driver, whose methods read like the algorithm.
//! - [`adapt`]: the optimal size map, remeshing, the adaptive loop and studies of the estimator.
//! - [`export`]: the condensed contact problem in the FCLIB format (HDF5), for other solvers.
//! - [`bench`]: the benchmark cases the `signorini bench` subcommands run.
//!
//! The library never prints or exits; the `signorini` binary does.
#![deny(unsafe_code)]

pub mod adapt;
pub mod bench;
pub mod contact;
mod contact_routes;
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
pub mod report;
pub mod resources;
pub mod scene;
pub mod sparse;

pub use error::{Error, Result};
