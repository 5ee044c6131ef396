//! # Contact in the dual formulation: the contact forces as unknowns, condensed
//!
//! On the contact part Γc the traction of a statically admissible field is unknown. With the
//! full HCT element the traction of `σ(φ)` is linear along every boundary edge (`∇φ` is
//! quadratic there), so the discrete contact force space is **the traction at the two ends of
//! every contact edge**, in the contact frame `(n, t)` of the end (the obstacle's normal at the
//! node, as in the primal: [`crate::contact::boundary`]):
//!
//! ```text
//!        a ------------------- b          contact edge a → b, length L, w = L/2
//!        t(s) = (1 − s/L) T_a + (s/L) T_b,     T_k = (rN_k n_k + rT_k t_k) / w
//!        unknowns of the edge: (rN_a, rT_a, rN_b, rT_b)   (forces, N per unit thickness)
//! ```
//!
//! The tractions are integrated along the boundary like known ones ([`super::boundary`]), with
//! the forces as extra unknowns: every such traction is represented exactly, and conversely
//! every field's contact traction is one of them. A linear traction meets `σN ≤ 0` and the
//! (convex) friction cone on the whole edge iff it does at both ends: imposing the conditions
//! on these unknowns imposes them pointwise (exactly for a straight obstacle, where the frame
//! is the same at both ends; for curved obstacles the frame turns between the ends).
//!
//! ## The condensed problem (the talk's `D f_C = G + G_C`)
//!
//! With the reduced unknowns `x = (z, r)` (free HCT dofs, contact forces) the complementary
//! energy is `½ xᵀ A x − bᵀ x − g̃ᵀ r`, where `g̃` is the gap conjugate to `rN`
//! (`−∫Γc g0 σN ds` with `g0` linear on the edge: `g̃_a = (2 g0_a + g0_b)/3`). Minimising over
//! `z` for given `r` leaves
//!
//! ```text
//!   J(r) = ½ rᵀ W r + rᵀ (u_free − g̃),   W = A_rr − A_rz A_zz⁻¹ A_zr,   u_free = −W r_0,
//! ```
//!
//! with `r_0` the contact forces of the unconstrained minimiser (the body glued to the
//! obstacle). `W` is the flexibility of the contact forces: symmetric positive definite, a
//! [`crate::contact::CondensedProblem`] like the primal's, so every condensed solver applies.
//! `u = W r + u_free` is the dual contact displacement (the multiplier of the force
//! constraints: a weighted mean of the displacement near each edge end). `W` comes from one
//! MUMPS factorisation of `A` with the Schur complement on the contact forces
//! ([`crate::petsc::schur::SchurFactor`]; under MPI, where that complement is not available,
//! from the three-step condensation on the distributed `A_zz`: [`super::condensation`]) — taken, where the boundary walk allows it, in the
//! local parametrisation of the contact part ([`super::local_contact`]: on the deviations `ξ`,
//! then `W = B⁻ᵀ S B⁻¹`, without the dense block of the forces as unknowns); `u_free` and, for the solver's `r`, `z` each from one
//! interior solve with the same factor (`z = A_zz⁻¹ (b_z − A_zr r)`): no solve with `W`, whose
//! conditioning would otherwise perturb the forces the field is built from.
//!
//! ## Equilibrium through the contact
//!
//! Where the tractions around the boundary close through Γc (a body held, in some direction,
//! only by the obstacle), global equilibrium is a linear condition on the forces:
//! `E r = e` (one row per closed component: force x, force y, moment). Its multipliers `ρ`
//! are rigid displacements, `u = W r + u_free + Eᵀ ρ`. No rigid motion exists in stress space,
//! so nothing needs stabilising. The conditions are imposed by a Newton iteration on `ρ` around
//! the unchanged condensed solver: for given `ρ` the solver solves the box-constrained problem
//! with the free displacement `u_free + Eᵀ ρ`; the map `ρ ↦ E r(ρ) − e` is piecewise linear, with
//! derivative `−E P (R W P)⁻¹ R Eᵀ` on the current contact set (`P` maps the free parameters —
//! the normal force of a closed point, the tangential force of a sticking one, a sliding Coulomb
//! point's tangential force following its normal one — to `r`, `R` selects their rows). The
//! first `ρ` is that of the bonded model (every point closed and sticking:
//! `ρ₀ = −(E W⁻¹ Eᵀ)⁻¹ (e + E W⁻¹ (u_free − g))`), each step is backtracked on the equilibrium
//! residual, and a direction the contact set does not control (no closed point yet, a sliding
//! direction) is regularised by the bonded model. While the contact set does not change, one
//! step is exact; Hertz's narrow zone takes a handful. (An augmented Lagrangian with
//! `W + κ EᵀE` was tried first: its inner Newton solves stalled on the fine Hertz mesh.) Loads the
//! obstacle cannot balance (a body pulled away, or a tangential load beyond the friction
//! capacity) leave `E r − e` stuck away from zero: a [`crate::Error::NoEquilibrium`].
//!
//! References: F. Lebon, "Modèles d'interface et formulations pour le contact frottant :
//! résultats et calcul d'erreur" (slides "Formulation en contraintes", "Résolution numérique
//! duale 1–4"); the semi-smooth (piecewise linear) Newton step: L. Qi, J. Sun, "A nonsmooth
//! version of Newton's method", Math. Programming 58 (1993).
use std::rc::Rc;

use nalgebra::DMatrix;

use super::condensation::{ColumnCondensation, Condensation, Storage};
pub use super::equilibrium::{solve_with_equilibrium, ContactEquilibrium};
use super::system::DualSystem;
use crate::contact::{self, CondensedProblem, ContactSolution, ContactSolver, Delassus, FrictionLaw, SolverSettings};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::petsc::schur::SchurFactor;
use crate::petsc::{Matrix, Session, SolveStats};

/// One contact point of the dual: one end of a contact edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DualContactPoint {
    /// Index of the edge in [`DualSystem::edges`].
    pub edge: usize,
    /// 0 at the edge's start `a`, 1 at its end `b`.
    pub end: usize,
    /// The mesh node at that end.
    pub node: usize,
    /// Its coordinates (m).
    pub position: [f64; 2],
    /// The unit contact normal at the end.
    pub normal: [f64; 2],
    /// The unit tangent at the end.
    pub tangent: [f64; 2],
    /// `w = L/2`: the traction at the end is the force over `w`.
    pub weight: f64,
    /// The initial gap at the node (signed distance to the obstacle plus the scene's gap).
    pub node_gap: f64,
    /// The gap conjugate to `rN`: `(2 g0_end + g0_other) / 3`.
    pub gap: f64,
}

/// The contact points of a dual system, in the order of the contact unknowns (point `p` owns
/// unknowns `2p` (N) and `2p + 1` (T)). `node_gap(x)` is the initial gap at `x`.
pub fn contact_points(system: &DualSystem, mesh: &Mesh, node_gap: &dyn Fn([f64; 2]) -> f64) -> Vec<DualContactPoint> {
    let mut points = vec![None; system.affine.num_contact / 2];
    for (k, e) in system.edges.iter().enumerate() {
        let Some(c) = e.contact else { continue };
        let (pa, pb) = (mesh.nodes[e.a], mesh.nodes[e.b]);
        let weight = 0.5 * (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let gaps = [node_gap(pa), node_gap(pb)];
        for end in 0..2 {
            points[c.first / 2 + end] = Some(DualContactPoint {
                edge: k,
                end,
                node: [e.a, e.b][end],
                position: [pa, pb][end],
                normal: c.frames[end][0],
                tangent: c.frames[end][1],
                weight,
                node_gap: gaps[end],
                gap: (2.0 * gaps[end] + gaps[1 - end]) / 3.0,
            });
        }
    }
    points.into_iter().flatten().collect()
}

/// The assembled and factorised dual contact problem, condensed onto the contact forces.
pub struct CondensedDual<'s> {
    /// `W` (dense, or implicit: products by interior solves), `u_free`, the gaps, the friction
    /// law and the weights `w`.
    pub problem: CondensedProblem<'s>,
    /// Whether `W` is formed (dense) or applied by interior solves (implicit).
    pub storage: Storage,
    /// The equilibrium conditions `E r = e` on the contact forces.
    pub equilibrium: ContactEquilibrium,
    /// The reduced system's matrix (PETSc).
    pub matrix: Matrix<'s>,
    /// The reduced right-hand side `b` (all rows).
    pub rhs: Vec<f64>,
    /// `ℓ = −A_rz A_zz⁻¹ b_z`, the load condensed onto the contact unknowns (the forces, or
    /// the deviations `ξ` in the local parametrisation).
    condensed_load: Vec<f64>,
    interior: Interior<'s>,
    /// Whether `matrix` and `rhs` are in the local parametrisation of the contact part
    /// ([`DualSystem::local`], module `local_contact`): unknowns `(z, ξ)`, forces `r = B ξ`.
    pub local: bool,
    /// Seconds: assembly, factorisation with the Schur complement.
    pub assemble_seconds: f64,
    /// Seconds of the factorisation.
    pub factor_seconds: f64,
}

/// How the interior `z` is solved for given forces (see [`super::condensation`]).
enum Interior<'s> {
    /// The MUMPS factor of the whole matrix, its Schur block the identity.
    Schur(SchurFactor<'s>),
    /// `A_zz` and its linear solver (three-step condensation, or implicit storage: then
    /// shared with the product of `W`).
    Columns(Rc<ColumnCondensation<'s>>),
}

/// Assemble the dual system with its contact forces and condense it onto them, by
/// `condensation` (the `columns` route reads its linear solver's options under `prefix`), `W`
/// stored as `storage` says (implicit: `condensation` must be `Columns`, whose solver gives
/// the products); `progress(done, total)` is told of the flexibility columns.
#[allow(clippy::too_many_arguments)]
pub fn condense<'s>(
    session: &'s Session,
    system: &DualSystem,
    mesh: &Mesh,
    points: &[DualContactPoint],
    friction: FrictionLaw,
    condensation: Condensation,
    storage: Storage,
    prefix: &str,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<CondensedDual<'s>> {
    if storage == Storage::Implicit && condensation != Condensation::Columns {
        return Err(Error::Usage(
            "the implicit storage of W computes its products with the interior solver of the three-step \
             condensation (columns), not with the Schur complement"
                .into(),
        ));
    }
    if condensation == Condensation::Schur && session.size() > 1 {
        return Err(Error::SingleProcess {
            feature: "the dual contact's Schur condensation".into(),
            reason: format!(
                "started on {} MPI processes: PETSc 3.18 computes MUMPS Schur complements on one process; condense \
                 by columns ({} columns), distributed",
                session.size(),
                super::condensation::CONDENSATION_OPTION
            ),
        });
    }
    let nm = system.num_unknowns();
    let nz = system.affine.num_masters;
    if points.len() * 2 != nm - nz || points.is_empty() {
        return Err(Error::Usage(format!(
            "dual contact: {} contact points for {} contact unknowns",
            points.len(),
            nm - nz
        )));
    }
    // The Schur route works in the local parametrisation of the contact part when there is
    // one (module `local_contact`: no dense block); the other routes keep the forces.
    let local = system.local.as_ref().filter(|_| condensation == Condensation::Schur);
    let start = std::time::Instant::now();
    // Every rank assembles every row (the condensation's coupling blocks and the right-hand
    // side are held by every rank) and gives PETSc its own contiguous block of them.
    let rows = system.assemble_in(local.map_or(&system.affine, |l| &l.affine), mesh, 0..nm);
    let owned = (session.rank() * nm / session.size())..((session.rank() + 1) * nm / session.size());
    let (first, last) = (rows.indptr[owned.start], rows.indptr[owned.end]);
    let owned_indptr: Vec<usize> = rows.indptr[owned.start..=owned.end].iter().map(|k| k - first).collect();
    let matrix = Matrix::from_csr_rows(
        session,
        session.world(),
        nm,
        owned.start,
        &owned_indptr,
        &rows.indices[first..last],
        &rows.values[first..last],
        1,
        true,
    )?;
    let assemble_seconds = start.elapsed().as_secs_f64();
    let start = std::time::Instant::now();
    let m2 = nm - nz;
    let (delassus, condensed_load, interior) = match (condensation, storage) {
        (Condensation::Schur, _) => {
            let schur_rows: Vec<usize> = (nz..nm).collect();
            session.prefer_mumps_ordering("", 4)?;
            let factor = SchurFactor::with_complement(session, &matrix, &schur_rows)?;
            let s = factor.complement();
            // MUMPS returns a symmetric Schur complement in one triangle only: mirror the filled one.
            let upper_empty = (0..m2).all(|i| (i + 1..m2).all(|j| s[i * m2 + j] == 0.0));
            let lower_empty = (0..m2).all(|i| (0..i).all(|j| s[i * m2 + j] == 0.0));
            let w = DMatrix::from_fn(m2, m2, |i, j| {
                let (lo, hi) = (s[i.max(j) * m2 + i.min(j)], s[i.min(j) * m2 + i.max(j)]);
                match (upper_empty, lower_empty) {
                    (true, false) => lo,
                    (false, true) => hi,
                    _ => 0.5 * (lo + hi),
                }
            });
            // In the local parametrisation S is on the deviations ξ = B⁻¹ r: W = B⁻ᵀ S B⁻¹.
            let w = match local {
                Some(l) => l.congruence(&w),
                None => w,
            };
            // The condensed load from an interior solve with zero forces.
            let mut glued = rows.rhs.clone();
            glued[nz..].fill(0.0);
            let mut b = matrix.create_vector()?;
            let owned = b.owned_range();
            b.set_owned(&glued[owned])?;
            let mut x = matrix.create_vector()?;
            factor.solve_interior(&b, &mut x)?;
            // The solve returns s ℓ (`SchurFactor::solve_interior`).
            let pass_through = factor.pass_through();
            let condensed_load = x.gather_all()?[nz..].iter().map(|v| v / pass_through).collect();
            (Delassus::Dense(w), condensed_load, Interior::Schur(factor))
        }
        (Condensation::Columns, Storage::Dense) => {
            let columns = Rc::new(ColumnCondensation::new(session, &rows, nz, prefix)?);
            let w = columns.flexibility(progress)?;
            let condensed_load = columns.condensed_load(&rows.rhs[..nz])?;
            (Delassus::Dense(w), condensed_load, Interior::Columns(columns))
        }
        (Condensation::Columns, Storage::Implicit) => {
            let columns = Rc::new(ColumnCondensation::new(session, &rows, nz, prefix)?);
            let condensed_load = columns.condensed_load(&rows.rhs[..nz])?;
            let diagonal = columns.diagonal_estimate()?;
            let shared = Rc::clone(&columns);
            let apply: contact::DelassusProduct<'s> = Box::new(move |x: &[f64], y: &mut [f64]| shared.product(x, y));
            (Delassus::Operator { size: m2, apply, diagonal }, condensed_load, Interior::Columns(columns))
        }
    };
    let factor_seconds = start.elapsed().as_secs_f64();
    // The unconstrained minimiser (contact glued) has W r_0 = b_r + ℓ, so u_free = −W r_0 =
    // −(b_r + ℓ) without any solve with W (locally: −B⁻ᵀ (b_ξ + ℓ_ξ)).
    let condensed_rhs: Vec<f64> = (0..m2).map(|k| rows.rhs[nz + k] + condensed_load[k]).collect();
    let condensed_rhs = match local {
        Some(l) => l.transpose_solve(&condensed_rhs),
        None => condensed_rhs,
    };
    let u_free: Vec<f64> = condensed_rhs.iter().map(|v| -v).collect();
    let problem = CondensedProblem::new(
        delassus,
        u_free,
        points.iter().map(|p| p.gap).collect(),
        friction,
        Some(points.iter().map(|p| p.weight).collect()),
    );
    // The validation's probe products are solves: their error first.
    if let Interior::Columns(columns) = &interior {
        if let Some(e) = columns.take_error() {
            return Err(e);
        }
    }
    let problem = problem?;
    Ok(CondensedDual {
        problem,
        storage,
        equilibrium: ContactEquilibrium::new(system),
        matrix,
        rhs: rows.rhs,
        condensed_load,
        interior,
        local: local.is_some(),
        assemble_seconds,
        factor_seconds,
    })
}

/// A condensed solver from outside this module (TAO).
pub type ExternalSolver<'f> = &'f dyn Fn(&CondensedProblem) -> Result<ContactSolution>;

/// A solved dual contact problem.
pub struct DualContactAnswer {
    /// The contact forces, statuses and the condensed solver's report.
    pub solution: ContactSolution,
    /// The rigid displacements of the equilibrium conditions (one per row of `E`).
    pub rigid: Vec<f64>,
    /// Outer Newton steps on the rigid displacements (1 without equilibrium conditions).
    pub outer_iterations: usize,
    /// All reduced unknowns `(z, r)` (`(z, ξ)` in the local parametrisation) and all HCT dofs.
    pub reduced: Vec<f64>,
    /// All HCT dofs of φ.
    pub phi: Vec<f64>,
    /// The contact displacement recomputed from the assembled matrix, `(A x − b)_r + Eᵀ ρ`,
    /// independently of `W`.
    pub displacement_check: Vec<f64>,
}

impl CondensedDual<'_> {
    /// The linear solves of the condensation, for the report (`outer_iterations`: the Newton
    /// steps on the rigid displacements, the Schur route's iteration count).
    pub fn linear_stats(&self, contact_seconds: f64, outer_iterations: usize) -> SolveStats {
        match &self.interior {
            Interior::Schur(_) => SolveStats {
                ksp_type: "preonly".into(),
                pc_type: "cholesky".into(),
                factor_package: Some("mumps (Schur complement on the contact forces)".into()),
                iterations: outer_iterations,
                converged_reason: "contact solved on the condensed problem".into(),
                relative_residual: 0.0,
                seconds: self.assemble_seconds + self.factor_seconds + contact_seconds,
            },
            Interior::Columns(c) => {
                let mut s = c.stats(self.storage);
                s.seconds = self.assemble_seconds + self.factor_seconds + contact_seconds;
                s
            }
        }
    }

    /// Solve the contact problem (with the equilibrium conditions) and recover the field.
    pub fn solve(
        &mut self,
        system: &DualSystem,
        solver: &ContactSolver,
        settings: &SolverSettings,
        tao: Option<ExternalSolver<'_>>,
    ) -> Result<DualContactAnswer> {
        let run = |p: &CondensedProblem, s: &SolverSettings| match tao {
            Some(f) => f(p),
            None => contact::solve(p, solver, s),
        };
        let accuracy = match (&self.interior, self.storage) {
            (Interior::Columns(columns), Storage::Implicit) => columns.product_accuracy()?,
            _ => 0.0,
        };
        let outcome = solve_with_equilibrium(&self.problem, &self.equilibrium, settings, accuracy, run);
        // A failed product (implicit storage) made the solver fail: its error is the cause.
        if let Interior::Columns(columns) = &self.interior {
            if let Some(e) = columns.take_error() {
                return Err(e);
            }
        }
        let (mut solution, rigid, outer_iterations) = outcome?;
        if let (Storage::Implicit, Interior::Columns(columns)) = (self.storage, &self.interior) {
            let floor = super::equilibrium::NOISE_MARGIN * accuracy;
            solution.notes.push(format!(
                "implicit storage of W: {} products W x, each one solve with the interior block; relative accuracy of \
                 the products {accuracy:.1e} (symmetry probe){}",
                columns.products(),
                if floor > 1e-2 * settings.tolerance {
                    format!(", so no inner solve asked below {floor:.1e}")
                } else {
                    String::new()
                }
            ));
        }
        // z = A_zz⁻¹ (b_z − A_zr r), never through W⁻¹: with the Schur factor one interior solve
        // (r / s − ℓ on the contact rows: see `SchurFactor::solve_interior`), with the
        // three-step condensation one solve with A_zz.
        let nz = system.affine.num_masters;
        let local = system.local.as_ref().filter(|_| self.local);
        // The contact unknowns of the matrix: the forces, or their deviations ξ = B⁻¹ r.
        // In the local parametrisation, ξ balanced so that the field's own closure holds.
        let unknowns = match local {
            Some(l) => {
                let mut xi = l.deviations(&solution.force);
                l.balance(&mut xi);
                xi
            }
            None => solution.force.clone(),
        };
        let mut reduced = match &mut self.interior {
            Interior::Schur(factor) => {
                // y = s (b_c + ℓ) = r for b_c = r / s − ℓ: in the unit of the contact rows, so
                // that the rounding of the sum is relative to the loads, whatever E.
                let pass_through = factor.pass_through();
                let mut rhs = self.rhs.clone();
                for (k, (r, l)) in unknowns.iter().zip(&self.condensed_load).enumerate() {
                    rhs[nz + k] = r / pass_through - l;
                }
                let mut b = self.matrix.create_vector()?;
                let owned = b.owned_range();
                b.set_owned(&rhs[owned])?;
                let mut x = self.matrix.create_vector()?;
                factor.solve_interior(&b, &mut x)?;
                x.gather_all()?
            }
            Interior::Columns(columns) => {
                let mut z = columns.interior(&self.rhs[..nz], &solution.force)?;
                z.extend_from_slice(&solution.force);
                z
            }
        };
        // The contact forces are the solver's exactly (the Schur solve returns them to ε max(|r|, s |ℓ|)).
        reduced[nz..].copy_from_slice(&unknowns);
        // Independent displacement: the contact rows of A x − b, plus the rigid part.
        let mut full = self.matrix.create_vector()?;
        let owned = full.owned_range();
        full.set_owned(&reduced[owned])?;
        let mut product = self.matrix.create_vector()?;
        self.matrix.multiply(&full, &mut product)?;
        let product = product.gather_all()?;
        let rigid_part = if self.equilibrium.is_empty() {
            vec![0.0; solution.force.len()]
        } else {
            self.equilibrium.transpose_times(&rigid)
        };
        // In the local parametrisation the forces' multiplier is B⁻ᵀ (A x − b)_ξ.
        let residual: Vec<f64> = (0..solution.force.len()).map(|k| product[nz + k] - self.rhs[nz + k]).collect();
        let residual = match local {
            Some(l) => l.transpose_solve(&residual),
            None => residual,
        };
        let displacement_check: Vec<f64> = residual.iter().zip(&rigid_part).map(|(u, rho)| u + rho).collect();
        let phi = local.map_or(&system.affine, |l| &l.affine).expand(&reduced);
        Ok(DualContactAnswer { solution, rigid, outer_iterations, reduced, phi, displacement_check })
    }
}
