//! Mesh adaptation to a target error: the optimal size map (refine and coarsen).
//!
//! The estimator ([`crate::estimate`]) gives an error `e_E` per element; [`size_map`] turns it
//! into a new element size `h*_E = r_E h_E` that reaches a target global error with as few
//! elements as possible. The remeshing itself (Gmsh with the sizes as a background field)
//! is separate: estimator, marking (here, the size map) and refinement stay apart.
pub mod remesh;
pub mod size_map;

pub use remesh::{element_sizes, nodal_sizes, remesh, size_view};
pub use size_map::{optimal_size_map, SizeMap, SizeMapLimits};
