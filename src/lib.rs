//! # signorini
//!
//! 2D frictional contact in linear elasticity with certified error control, on PETSc.
//!
//! # Quick start
//!
//! A block pressed onto a rigid floor with Coulomb friction, solved and checked:
//!
//! ```
//! use signorini::{petsc::Session, problem::ElasticityProblem, scene::SceneBuilder};
//! let scene = SceneBuilder::rectangle([0.0, 0.0], [2.0, 1.0], 0.25) // 2 m × 1 m, cells of 0.25 m
//!     .material(210e9, 0.3) // Young's modulus (Pa), Poisson's ratio
//!     .pressure("top", 1e6) // N/m², pushing into the block
//!     .contact_line("bottom", [0.0, 0.0], [0.0, 1.0]) // the floor y = 0, normal towards the block
//!     .coulomb(0.3)
//!     .dirichlet_point([0.0, 1.0], Some(0.0), None) // the top-left corner held sideways
//!     .build()?;
//! let session = Session::init(&[])?; // PETSc and MPI: one session per process
//! let mut problem = ElasticityProblem::setup_system(&session, scene)?;
//! problem.assemble()?;
//! problem.solve()?;
//! problem.postprocess()?;
//! let contact = problem.report()?.contact.expect("a scene with contact reports on its contact");
//! // The floor pushes the block up with the whole load: 1 MPa over 2 m (N per metre of thickness).
//! assert!((contact.resultant[1] - 2e6).abs() < 1e-6 * 2e6, "{:?}", contact.resultant);
//! # Ok::<(), signorini::Error>(())
//! ```
//!
//! # The pipeline
//!
//! ```text
//! scene::SceneBuilder ──build()──▶ scene::Scene ◀── Scene::from_file / from_str (a TOML scene file)
//!                                       │
//! petsc::Session::init ──▶ problem::ElasticityProblem::setup_system(&session, scene)
//!                               .assemble()      stiffness and loads
//!                               .solve()         linear solve, or the contact solve
//!                               .postprocess()   stresses, reactions, the independent checks
//!                               .report()        problem::Report (what report.json holds)
//!                               .write_output(dir)   solution.vtu, report.json, contact files
//! ```
//!
//! - A scene describes one problem: geometry and mesh, material, loads, displacement
//!   conditions, contact with a rigid obstacle or between bodies, solver choices. Its reference
//!   is `docs/scene-format.md`; [`scene::SceneBuilder`] has one call per key (several bodies:
//!   [`scene::BodiesBuilder`]), and every scene, however made, gets the checks of a scene file.
//! - [`petsc::Session`] initialises PETSc and MPI once per process; its arguments are PETSc
//!   options (`-ksp_type cg`), which override the scene's.
//! - [`problem::ElasticityProblem`] runs the steps in order (a step out of order is an
//!   [`Error`]); its public fields hold the mesh, the displacement, the post-processed
//!   [`problem::Results`] and the contact outcome. [`problem::Report`] sums the run up.
//! - Every failure is an [`Error`] saying where and what to do: a scene mistake with its file
//!   and line (or builder call), a singular problem, a solver that did not converge.
//!
//! # Modules
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
//! - [`evolution`]: load paths, increments with friction memory, their records.
//! - [`interface_law`]: interface laws on a contact (thin layer, RCCM adhesion, cohesive joint),
//!   the modified condensed problem and the staggered loop.
//! - [`adapt`]: the optimal size map, remeshing, the adaptive loop and studies of the estimator.
//! - [`export`]: the condensed contact problem in the FCLIB format (HDF5), for other solvers.
//! - [`bench`](mod@bench): the benchmark cases the `signorini bench` subcommands run.
//!
//! The library never prints or exits; the `signorini` binary does.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod adapt;
pub mod bench;
pub mod contact;
mod contact_routes;
pub mod dual;
pub mod error;
pub mod estimate;
pub mod evolution;
pub mod export;
pub mod fem;
pub mod interface_law;
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
