//! Exports of signorini's discrete problems to formats that other solvers read, so that they
//! can be solved and compared on exactly the same data.
//!
//! - [`fclib`]: the condensed contact problem (`W`, the free displacement, the gaps, μ) as an
//!   FCLIB "local" frictional contact problem in HDF5, the input of Siconos and of the other
//!   FCLIB readers; optionally with our solution.
pub mod fclib;

pub use fclib::{check_friction, write_fclib, FclibInfo, FclibLocal, FclibSolution, FclibSummary};
