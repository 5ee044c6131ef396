//! Mesh adaptation to a target error: the optimal size map (refine and coarsen), the adaptive
//! loop, and the convergence study that checks the estimate against a reference solution.
//!
//! The estimator ([`crate::estimate`]) gives an error `e_E` per element; [`size_map`] turns it
//! into a new element size `h*_E = r_E h_E` that reaches a target global error with as few
//! elements as possible. The remeshing itself (Gmsh with the sizes as a background field)
//! is separate: estimator, marking (here, the size map) and refinement stay apart.
//! [`driver`] runs the loop (solve, dual, estimate, size map, remesh), [`report`] writes its
//! table and plot, [`mod@study`] measures true errors and rates on uniform refinements.
pub mod driver;
pub mod locate;
pub mod remesh;
pub mod report;
pub mod size_map;
pub mod study;

pub use driver::{adapt, adapt_inspecting, AdaptOptions, AdaptOutcome, AdaptStatus, AdaptStep, RateModel};
pub use remesh::{element_sizes, nodal_sizes, remesh, size_view};
pub use report::{write_adapt_outputs, write_study_outputs};
pub use size_map::{optimal_size_map, SizeMap, SizeMapLimits};
pub use study::{study, ReferenceField, StudyOptions, StudyOutcome, TrueErrors};
