//! The contact routes: how the driver ([`crate::problem`]) solves a scene's contact, from the
//! contact points to a checked answer.
//!
//! ```text
//! full_space/            the default (`newton_full`): semi-smooth Newton on the mixed system
//!                        (u, λ) through PETSc SNES, each step solved by
//!   block_elimination    ... one Cholesky of K with the Schur complement on the contact dofs
//!                            (a body held by its Dirichlet conditions)
//!   floating_elimination ... the same with springs at pinned dofs removed in every step
//!                            (a body held only by the contact)
//!                        or by MUMPS LU of the mixed Jacobian, kept across steps (sparse_lu)
//! route_choice           which of the two (`-contact_route`, or a cost model over m, dofs, ranks)
//! condensed_route        the contact points of a scene (ContactSetup) and the condensed route:
//!                        W = B K⁻¹ Bᵀ, the scene's condensed solver, SNESVI, TAO; the fallback
//!                        of the full-space Newton
//! condensation           the condensed route's linear algebra: W from a Schur factor, the
//!                        factorised stiffness, the solver a scene names
//! ```
//!
//! Every route ends in the same independent check of its answer ([`crate::contact::residuals`]
//! on the recomputed field) and the same report ([`crate::report::contact`]).
pub(crate) mod block_elimination;
pub(crate) mod condensation;
pub(crate) mod condensed_route;
pub(crate) mod floating_elimination;
pub(crate) mod full_space;
pub(crate) mod route_choice;
