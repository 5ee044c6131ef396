//! # Quasi-static evolution: load paths, friction with memory
//!
//! A load path multiplies every load of a scene by a piecewise-linear function of a
//! pseudo-time `t` and solves a sequence of increments `t_0 < t_1 < ... < t_N`. Friction has
//! memory: at each increment Coulomb's and Tresca's laws act on the slip *increment* since the
//! last converged state (the backward-Euler time discretisation of the rate law, see
//! `../shared/reference/SCIENCE.md`, "the incremental problem").
mod driver;
pub mod history;
pub mod load_path;
pub mod record;

pub use driver::{
    ContactShift, EachIncrement, EnergyBalance, LoadFactors, LoadPathReport, LoadPathSummary, MAX_HALVINGS,
};
pub use load_path::LoadPath;
pub use record::{ContactProfile, StepRecord};
