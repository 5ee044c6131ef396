//! Plane linear elasticity (small strains) with Lagrange P1 / P2 triangles.
//!
//! - [`quadrature`]: rules on the reference triangle (degrees 1–5 and beyond) and Gauss–Legendre
//!   on `[0, 1]`.
//! - [`lagrange`]: shape functions, the isoparametric map (curved P2 cells), edge functions.
//! - [`material`]: Hooke's law in plane strain / plane stress, von Mises, energy densities.
//! - [`assembly`]: Dirichlet constraints and the rigid-motion check, loads, the global CSR
//!   system assembled row block by row block (one block per MPI rank).
//! - [`postprocess`]: cell and nodal stresses, energy and L2 error norms.
//! - [`mixed_pressure`]: the locking-free P2–P0 element (pressure condensed cell by cell) for
//!   nearly incompressible materials, and the stresses of its solutions.
//!
//! Degrees of freedom are interleaved: `dof = 2 * node + component` (0 = x, 1 = y), with the
//! node numbering of [`crate::mesh::Mesh`].
pub mod assembly;
pub mod csr_assembly;
pub mod hct;
pub mod lagrange;
pub mod material;
pub mod mixed_pressure;
pub mod postprocess;
pub mod quadrature;

pub use assembly::{
    assemble, element_stiffness, load_vector, residual_forces, Constraints, CsrRows, EdgeLoad, LinearSystem, Loads,
    Traction,
};
pub use material::{CellMaterials, Material, PlaneModel};
pub use mixed_pressure::Element;
pub use postprocess::{cell_stress, energy_error, energy_norm, l2_error, nodal_stress};
