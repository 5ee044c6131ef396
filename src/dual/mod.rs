//! # The dual (stress) formulation: the Airy stress function on HCT elements
//!
//! In plane elasticity without body force every stress field in equilibrium derives from an
//! Airy function φ, `σxx = φ,yy`, `σyy = φ,xx`, `σxy = −φ,xy`; with a constant body force F a
//! particular field `σp = diag(−Fx x, −Fy y)` is added. Discretising φ with the C¹ HCT element
//! ([`crate::fem::hct`]) gives stress fields that are in equilibrium inside every element and
//! across every edge, and the known tractions are imposed exactly on the boundary
//! ([`boundary`]): the fields are statically admissible, which is what the error in the
//! constitutive relation ([`crate::estimate`]) needs. Among them, the dual solution minimises
//! the complementary energy (F. Lebon's talk "Modèles d'interface et formulations pour le contact frottant", "Formulation en contraintes"):
//!
//! ```text
//!   J*(σ) = ½ ∫Ω σ : C⁻¹ σ − ∫ΓD u0 · σ n        over statically admissible σ.
//! ```
//!
//! What it needs: a simply connected domain (on a domain with holes φ is multivalued: Michell's
//! conditions; refused with [`crate::Error::Formulation`]); supports distributed over boundary
//! parts (a point support carries a point force, which no C¹ Airy function represents). The
//! geometry is the straight-sided mesh of the cell vertices (a P2 mesh's curved edges are
//! replaced by their chords).
//!
//! - [`dofs`]: the global HCT numbering.
//! - [`boundary`]: traction conditions as constraints on the boundary dofs, eliminated.
//! - [`system`]: assembly, PETSc solve, the stress field and its checks.
//! - [`contact`]: contact with a rigid obstacle: the contact forces as unknowns, condensed onto
//!   the same [`crate::contact::CondensedProblem`] as the primal's; [`condensation`]: the
//!   talk's condensations and storages of `W` (dense, or implicit: products by interior
//!   solves, Uzawa on the full dual system; under MPI `A_zz` distributed, the condensed
//!   problem held and solved by every rank); [`equilibrium`]: the equilibrium of the contact
//!   forces of a body held only by the obstacle; [`local_contact`]: the contact part's own dofs
//!   as unknowns instead of the forces (no dense block), for the Schur condensation.
pub mod boundary;
pub mod checks;
pub mod condensation;
pub mod contact;
pub mod dofs;
pub mod equilibrium;
pub mod local_contact;
pub mod saddle_point;
pub mod system;

pub use checks::{check, DualCheck};
pub use dofs::HctDofs;
pub use system::{particular_stress, BodyLoad, ContactSide, DualData, DualField, DualSystem};
