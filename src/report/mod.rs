//! What a run reports and writes: the contact report and its curve along the contact part,
//! the closed zones, the several-bodies checks, the physics warnings, and the result files
//! (`solution.vtu`, `report.json`, `contact.csv`, the pictures; `<body>.vtu` and
//! `solution.pvd` for several bodies).
//!
//! ```text
//! contact        ContactReport: solver, iterations, statuses, resultants, residuals
//! contact_curve  the contact quantities point by point along the part (contact.csv)
//! contact_zones  arc length, closed zones and the peak pressure
//! bodies         each body's equilibrium and each contact part's checks (several bodies)
//! warnings       doubts about the model (large displacement or rotation, locking, ...)
//! option_warnings PETSc options no solver of the run read, with the route and prefix
//! files          the result files of a run, written atomically, all or none
//! bodies_files   one .vtu per body and the ParaView collection
//! interface      the interface law's entry of the report and its history along a load path
//! ```
pub mod bodies;
mod bodies_files;
pub mod contact;
pub mod contact_curve;
pub mod contact_zones;
pub(crate) mod files;
pub mod interface;
pub(crate) mod option_warnings;
pub mod warnings;
