//! Contact with a rigid obstacle: the full-space semi-smooth Newton method on the mixed
//! (displacement, contact force) system through PETSc SNES — the driver's part.
//!
//! P. Alart, A. Curnier, "A mixed formulation for frictional contact problems prone to Newton
//! like solution methods", Comput. Methods Appl. Mech. Engrg. 92 (1991) 353–375; for the
//! Signorini part this is the primal–dual active set method (M. Hintermüller, K. Ito,
//! K. Kunisch, SIAM J. Optim. 13 (2002) 865–888; S. Hüeber, B. Wohlmuth, Comput. Methods Appl.
//! Mech. Engrg. 194 (2005) 3147–3166 for the semi-smooth Newton form on the whole system).
//! The iterate is the whole `(u, λ)` and the residual is evaluated in full space. Each Newton
//! step's linear system is solved, on one process with a body held by its Dirichlet conditions,
//! by block elimination with one MUMPS factorisation of `K` (Schur complement on the contact
//! dofs) kept for the whole iteration (`block_elimination.rs`). The SNES then iterates on
//! `(v, λ)` with `u = v + K⁻¹ Bᵀ λ` — the same Newton iterates, but after the first step a
//! step costs a small dense system and no solve with the factor; `u` is recovered by one solve
//! at the end. A body its Dirichlet conditions do not hold (held by the contact: Hertz, a body
//! held sideways by friction alone) has a singular `K`: springs at a few pinned contact dofs
//! make it definite, it is factorised once the same way, and the springs are removed inside
//! every Newton step by a low-rank correction of the small system (`floating_elimination.rs`);
//! the SNES then iterates on `(v, λ)` too, with no solve per step after the first (and again in
//! `(u, λ)`, one solve per step, if that answer fails the independent check). Otherwise (the
//! cost model's `sparse_lu` route, or `-contact_ksp_type`, `-contact_pc_type`,
//! `-contact_full_space_lu`) SNES's KSP solves the mixed Jacobian in `(u, λ)` (MUMPS LU by
//! default, distributed under MPI): one sparse LU per step. Under MPI the cost model may also
//! take `dense_schur_gathered` (`gathered.rs`): `K` gathered on rank 0, which runs the
//! one-process route alone and sends the answer: the serial answer at the serial cost.
//!
//! ## Unknowns and equations
//!
//! `z = (u, λ)`: `u` the displacements (`dof = 2·node + component`, Dirichlet rows eliminated
//! as in the linear solve), `λ = (λN_i, λT_i)` the contact forces of the condensed problem's
//! conventions (`contact/mod.rs`: force on the body in the frame `(n_i, t_i)`, compression
//! `λN ≤ 0`). Without friction the tangential forces are not unknowns at all (one `λN` per
//! point; no friction machinery runs). With `uN = n·u_k`, `uT = t·u_k` at the point's node `k`:
//!
//! ```text
//!   F_u = K u − f − Bᵀ λ                                        (force rows)
//!   τN  = λN − ρN (uN − g0)        C_N = (λN − min(τN, 0)) / ρN  (displacement rows)
//!   τT  = λT − ρT uT               C_T = (λT − clamp(τT, −s, s)) / ρT
//!   s   = Tresca threshold (force per point, g·w_i), or μ max(−τN, 0) (Coulomb)
//! ```
//!
//! `C = 0` is exactly the contact law (Signorini + friction, `contact/mod.rs`): the
//! Alart–Curnier projections, divided by `ρ` so that the rows are displacements (`C_N = uN − g0`
//! on a closed point, `C_T = uT` on a sticking one).
//!
//! ### The augmentation ρ (no user parameter)
//!
//! `ρN_i = ρT_i = 2 E' w_i / L`: `E'` the plane modulus (`E/(1 − ν²)` in plane strain, `E` in
//! plane stress), `w_i = ∫ φ_i ds` the point's weight on the contact boundary (its share of the
//! boundary length, of the order of `h`), `L` the body's diameter. Read per unit of weight,
//! `ρ/w_i = 2 E'/L` is a traction per displacement — the stiffness of the body against a
//! traction spread over its contact face — fixed whatever the mesh. That is the scaling under
//! which the semi-smooth Newton method for friction is posed in function space, with
//! iteration counts that do not grow with refinement (G. Stadler, "Semismooth Newton and
//! augmented Lagrangian methods for a simplified friction problem", SIAM J. Optim. 15 (2004)
//! 39–62; S. Hüeber, G. Stadler, B. Wohlmuth, SIAM J. Sci. Comput. 30 (2008) 572–596). A
//! nodal stiffness (`ρ ≈ K_kk`, of the order of `E'` on every mesh) is `L/h` times larger and
//! made the slip front creep by one or two nodes per step: 7, 10, 12, 14 steps on the square
//! block from 10³ to 10⁶ dofs, against 4, 5, 8, 10 now. The factor 2 was the best of
//! 1/4 … 4 on that benchmark (the others took 2 to 6 more steps at 10⁴–10⁶ dofs; none failed).
//!
//! With contact pairs a point's two sides are two bodies whose stiffnesses act in series:
//! `ρ_i = 2 w_i / (L_s/E'_s + L_m/E'_m)`, each body's own plane modulus and diameter (one body
//! against a rigid obstacle: the formula above). A stiff foundation under a soft block gets the
//! block's scale, whichever body comes first in the scene.
//!
//! In axisymmetry a P2 vertex on the axis has weight 0 ([`crate::contact::boundary::AxisPressure`];
//! its force is a concentrated one): it takes the weight of the node its pressure is
//! extrapolated from (the nearer one, on its own edge), which gives its augmentation the scale
//! of that edge's (`ρ = 0` would leave the point's rows without their displacement term).
//! `ρN` and `ρT` are kept equal: with `ρT ≪ ρN` a point coming back from open was taken as
//! sticking, and single points then flipped open/stick for dozens of steps.
//!
//! Once a Newton step has been taken, the normal tests and the stick test reduce to signs
//! (closed points have `uN = g0`, sticking ones `uT = 0`); `ρ` enters where a displacement
//! meets a force: the first frictional classification and slip reversals.
//!
//! ### Generalized Jacobian
//!
//! `[K, −Bᵀ; ∂C/∂u, ∂C/∂λ]`, with per point (columns `u_k,x  u_k,y  λN  λT`):
//!
//! ```text
//!   closed  (τN ≤ 0):   C_N row  [ nᵀ          0        0    ]
//!   open    (τN > 0):   C_N row  [ 0           1/ρN     0    ]
//!   stick   (|τT| < s): C_T row  [ tᵀ          0        0    ]
//!   free    (s = 0):    C_T row  [ 0           0        1/ρT ]
//!   slip σ, Tresca:     C_T row  [ 0           0        1/ρT ]
//!   slip σ, Coulomb:    C_T row  [ −σμρN/ρT nᵀ σμ/ρT    1/ρT ]   (non-symmetric)
//! ```
//!
//! the same pieces as the condensed semi-smooth Newton (`contact/semismooth_newton.rs`) with
//! `uN = (B u)_N`.
//!
//! ### Several bodies: mortar rows
//!
//! With contact pairs (`bodies.rs`, `contact/mortar/`) a point's rows of `B` touch its slave
//! node and the master nodes (`ContactBoundary::b_row`): `nᵀ` above stands for the whole
//! normal row (`n_i` on the slave node, `−(M_ij/D_i) n_i` on master node `j`), and `tᵀ` for
//! the tangential one. The contact rows of the pattern hold every dof of the point's rows then
//! its multipliers; the force rows of every dof a row touches get the `−Bᵀ` entries; `uN`,
//! `uT` are `(B u)` over all entries. The rigid-motion check runs on 3 rigid motions per
//! connected piece of the mesh (per body): a closed row constrains the relative motion of the
//! two bodies it touches. The block elimination takes its Schur complement on every dof a row
//! touches (`schur_dofs`, as the condensed route), and so does the floating elimination of the
//! bodies held only by the contact of a pair (pins among the dofs the rows touch, per body;
//! springs of the regularised steps on each body's free rigid motions). Under MPI the mortar
//! rows run as they are, with SNES's LU of the mixed Jacobian (the eliminations are
//! one-process): a row's master dofs may be another rank's (ghosts, "Layout over MPI ranks");
//! `mpirun -n 2` and `-n 3` take the serial Newton steps to the serial answer (displacements to
//! 1e-14 on the block scenes, 1e-11 on `two_cylinders.toml`).
//!
//! ### The first steps
//!
//! At `τN = 0` (a point touching with no force: every point of a body resting on
//! the obstacle at the first step) the closed branch is taken; a point with threshold `s = 0`
//! is free. For Coulomb friction the first step therefore solves the *frictionless* problem on
//! the touching points, and the next one classifies stick and slip from its tangential
//! displacements and normal forces (`|τT| = ρT |uT|` against `μ |λN|`); a body that the
//! frictionless contact leaves free sideways gets the regularised first step described below.
//! (Starting from the bonded problem instead — every touching point sticking — the slip zone
//! grew by a few nodes per step: twice the steps on fine meshes.) A body that only the contact
//! holds keeps that bonded start (a closed point with `s = 0` and `τT = 0` sticks): the
//! frictionless first step would let it slide away, and friction would never catch it. A
//! point whose slip
//! direction reverses from one step to the next sticks for that step (as in the condensed
//! method). The residual is always the continuous formula above, so these choices only pick an
//! element of the generalized Jacobian.
//!
//! ## Layout over MPI ranks
//!
//! ```text
//!   global unknowns:  [ u rows of rank 0 | λ of rank 0's points | u rows of rank 1 | λ of rank 1's points | … ]
//!   rank r's block:   offset_r = Σ_{q<r} (2 n_q + c m_q)
//!     u dof d (owned by r)        → offset_r + (d − first_dof_r)
//!     λ component k of point i    → offset_r + 2 n_r + c (i − first_point_r) + k       (c = 1 or 2)
//! ```
//!
//! Rank `r` owns the rows of its nodes (the driver's contiguous node blocks) and the contact
//! points whose node it owns (contact nodes are sorted, so these are a contiguous run of
//! points). Every rank computes the whole map ([`MixedLayout`]) from the node partition and the
//! contact nodes, which every rank knows. The force rows couple to off-rank displacements
//! through `K` (the ghosts of the SNES wrapper, `petsc/nonlinear.rs`). Against a rigid
//! obstacle a contact row couples only to unknowns of its own rank; a mortar row (contact
//! pairs) also to its master dofs, which may be another rank's, and the force row of such a
//! dof gets the `−Bᵀ` entries of points another rank owns: both are ghosts too, and every
//! callback (the step length included) sees them. Rows are stored with increasing global
//! columns, so a master dof of a later rank comes after the point's multipliers
//! (`OwnedPoint::slots` says where each entry goes). The Jacobian's pattern `[K  Bᵀ; B  D]`
//! (every entry of the contact rows stored, zeros included) is preallocated exactly and
//! refilled at every Newton step.
//!
//! When an elimination iterates in `(v, λ)` (one process), SNES never factorises that
//! Jacobian: the eliminations solve the steps, and the force rows `K v − f` are evaluated from
//! `K`'s own rows (`MixedSystem::stiffness`). The pattern's force rows then keep their
//! diagonal entry alone (`pattern.rs`, `lean`), so the Jacobian, the pattern and the callbacks'
//! copies of it cost the contact rows only: the peak memory of the 1e6-dof benchmark rows went
//! from 2.7 GB to 1.9 GB (a linear solve of the same mesh peaks at 1.3 GB).
//!
//! ## Bodies held by contact (before the contact set closes)
//!
//! With Dirichlet conditions that leave a rigid motion free, the mixed Jacobian is nonsingular
//! as soon as the closed normal rows and the sticking tangential rows, with the Dirichlet rows,
//! block every rigid motion (`K` is singular only on rigid motions, `B` restricted to the
//! closed rows has full row rank: one node per point). That is checked at every Jacobian
//! evaluation, exactly as the driver checks the Dirichlet conditions (rank of the 3×3 Gram
//! matrix of the constraint rows applied to the rigid motions `(a − ωy, b + ωx)`). When it fails
//! — typically at the first steps, before the contact zone has formed — springs `S = k I` at the
//! contact nodes (`k = 10⁻³ · max diag K / m`, as the condensed route's) are added to the
//! Jacobian only: the residual is unchanged, so the step is a regularised Newton step
//! (Levenberg–Marquardt on the free rigid motions) and the solution is the exact one. With
//! the floating elimination (one process) the springs act on the free rigid motions only — the
//! null space of that Gram matrix — so a mode the loads do not drive (a cylinder free to turn
//! about its centre on frictionless contact) leaves the steps exact Newton steps
//! (`floating_elimination.rs`). Once the set closes, steps are exact Newton steps again. A body that stays unheld (it lifts off, or
//! friction cannot hold the tangential load) keeps a regularised Jacobian and an equilibrium
//! residual that does not decrease: after three such steps the run stops and says why
//! ([`Error::Unconstrained`] "lifts off", or [`Error::NoEquilibrium`] "slides").
//!
//! ## Convergence, globalization, fallback
//!
//! Converged when the backward error of the force rows,
//! `max|F_u| / max_r (Σ_j |K_rj u_j| + |Bᵀλ|_r + |f_r|)`, and the contact rows `max|C| / U`
//! (`U` the largest displacement or gap) are below `10⁻² × tolerance` (`10⁻¹¹` by default), or
//! below the tolerance after an exact full step that changed no point's status (the
//! semi-smooth Newton step on an unchanged active set is the solution of that piece).
//!
//! Steps are full Newton steps (SNES line search "basic": the primal–dual active set method).
//! Active-set cycles (a status set met again two or more steps later without the merit
//! `½ (‖C‖² + ‖F_u / max diag K‖²)` having halved since) cap the steps at 1/2 then 1/4 until
//! the statuses settle, and switch on a monotone Armijo line search on that merit; 20 steps
//! without halving the merit switch it on too. A third cycle, 20 more steps without progress,
//! a failed line search, the iteration limit or a singular Jacobian stop SNES, and the run
//! falls back to the condensed semi-smooth Newton (with its own damping and relaxation
//! fallbacks), saying so in the notes (and in the error, if that fails too). The answer is
//! then verified independently, as on the other routes: the contact residuals of `(λ, B u)`
//! with `u` from the solve, and the equilibrium of the force rows recomputed from the gathered
//! solution.
mod gathered;
mod layout;
mod mixed_system;
mod pattern;
mod refinement;

use std::ops::Range;

use nalgebra::{DMatrix, DVector};

use super::block_elimination::BlockElimination;
use super::condensation::schur_dofs;
use super::condensed_route::{ContactOutcome, ContactSetup};
use super::floating_elimination::FloatingElimination;
use super::route_choice::{self, Route, RouteInputs, MAX_CHANGED_ROWS};
use crate::contact::{self, ContactSolution, FrictionLaw, IterationRecord, PointState, PointStatus, TangentialState};
use crate::error::{Error, Result};
use crate::fem::assembly::{Constraints, LinearSystem};
use crate::fem::material::CellMaterials;
use crate::mesh::Mesh;
use crate::petsc::nonlinear::FactorisationReuse;
use crate::petsc::nonlinear::{Convergence, NonlinearSolve, NonlinearSolver, NonlinearSystem};
use crate::petsc::{Comm, LinearSolver, Matrix, Session, SolveStats, Vector};
pub use layout::{dof_ranges, MixedLayout};
use mixed_system::{choose_pins, dof_rigid_row, evaluate, status_of, Floating, Law, MixedSystem, RigidCheck};
use pattern::{augmentation, augmentation_range, check_contact_blocks, spring_dofs_of, Pattern, PatternInput, Pieces};
use refinement::Equations;

/// A contact solve's answer: the displacement field (every rank), the checked contact
/// outcome and what the solver did.
type Solved = (Vec<f64>, ContactOutcome, SolveStats);

/// Options prefix of the full-space SNES (`-contact_snes_monitor`, `-contact_ksp_type`, ...).
pub const OPTIONS_PREFIX: &str = "contact_";
/// `c` in the augmentation `ρN_i = ρT_i = c E' w_i / L` (see the module documentation).
const AUGMENTATION: f64 = 2.0;
/// Force residuals below this fraction of the force rows' scale are round-off: the block
/// elimination then takes `dv = 0` without a solve.
const ROUND_OFF: f64 = 1e-13;
/// The inner solver's name in the reports when the Jacobians are solved by block elimination.
const ELIMINATION_NAME: &str = "block elimination, MUMPS Cholesky of K with Schur complement on the contact dofs";
/// The same for a body held by the contact (`floating_elimination.rs`).
const FLOATING_ELIMINATION_NAME: &str =
    "block elimination, MUMPS Cholesky of K + springs at pinned contact dofs (removed in each step)";
/// Option turning the block elimination off (MUMPS LU of the whole mixed Jacobian instead).
pub const FULL_SPACE_LU_OPTION: &str = "-contact_full_space_lu";
/// Option turning the sparse LU route's reuse of its factorisation off (`false`: one LU per
/// Newton step).
pub const LU_REUSE_OPTION: &str = "-contact_lu_reuse";
/// Option turning the eliminations' iterative refinement against K off (`refinement.rs`; to
/// see what it corrects: the independent check then refuses a slender body's answer).
pub const REFINE_OPTION: &str = "-contact_full_space_refine";
/// Newton steps allowed when the scene does not say.
const DEFAULT_MAX_ITERATIONS: usize = 100;
/// Cycles of the active set before giving up on the full-space iteration.
const CYCLES_BEFORE_FALLBACK: usize = 3;
/// Regularised steps without halving the equilibrium residual after which the body is taken
/// as not held.
const FLOATING_STEPS: usize = 3;
/// Line search after a cycle: Armijo constant, smallest step.
const ARMIJO: f64 = 1e-4;
const SMALLEST_STEP: f64 = 1e-6;
/// Newton steps without halving the merit after which the full-space iteration gives up.
const STEPS_WITHOUT_PROGRESS: usize = 20;

impl ContactSetup {
    /// The full-space semi-smooth Newton method (see the module documentation). `system` holds
    /// this rank's rows of the constrained stiffness (no stabilisation springs) and load;
    /// `dof_ranges` the owned dofs of every rank. Returns the displacement field (every rank),
    /// the checked contact outcome and what the solver did.
    #[allow(clippy::too_many_arguments)]
    pub fn solve_full_space(
        &self,
        session: &Session,
        mesh: &Mesh,
        materials: &CellMaterials,
        constraints: &Constraints,
        system: &LinearSystem,
        dof_ranges: &[Range<usize>],
        progress: &dyn crate::problem::Progress,
    ) -> Result<Solved> {
        let run = |in_v: Option<String>| {
            self.full_space_run(session, mesh, materials, constraints, system, dof_ranges, progress, in_v)
        };
        match run(None)? {
            Ok(done) => Ok(done),
            Err(failure) => {
                // The floating elimination's (v, λ) answer failed the independent check: the
                // same Newton iteration in (u, λ), whose residual is evaluated on u itself.
                progress.note(&format!("contact: {failure}; iterating again in (u, λ)"));
                run(Some(failure))?
                    .map_err(|f| Error::PetscUsage(format!("the (u, λ) iteration asked for a second rerun: {f}")))
            }
        }
    }

    /// One full-space run; `retry`: the failure of a first run in `(v, λ)`, when this one
    /// iterates in `(u, λ)`. `Ok(Err(why))`: the floating elimination ran in `(v, λ)` and its
    /// answer failed the independent check.
    #[allow(clippy::too_many_arguments)]
    fn full_space_run(
        &self,
        session: &Session,
        mesh: &Mesh,
        materials: &CellMaterials,
        constraints: &Constraints,
        system: &LinearSystem,
        dof_ranges: &[Range<usize>],
        progress: &dyn crate::problem::Progress,
        retry: Option<String>,
    ) -> Result<std::result::Result<Solved, String>> {
        let start = std::time::Instant::now();
        let comm = session.world();
        let rank = session.rank();
        let b = &self.boundary;
        let m = b.points();
        let n = 2 * mesh.num_nodes();
        let law = Law::of(self.friction_law());
        let per_point = if law.frictional() { 2 } else { 1 };
        let k = &system.matrix;
        let owned_dofs =
            dof_ranges.get(rank).cloned().ok_or_else(|| Error::PetscUsage(format!("no dof range for rank {rank}")));
        let owned_dofs = session.agree(
            owned_dofs.and_then(|owned| {
                if k.first_row != owned.start || k.num_rows() != owned.len() || system.rhs.len() != owned.len() {
                    return Err(Error::PetscUsage(format!(
                        "full-space contact: the stiffness rows {}..{} differ from this rank's dofs {owned:?}",
                        k.first_row,
                        k.first_row + k.num_rows()
                    )));
                }
                Ok(owned)
            }),
            "the full-space contact's rows",
        )?;
        let layout = MixedLayout::new(dof_ranges, &b.nodes, per_point);
        let block = layout.owned(rank);
        let my_points = layout.points(rank);
        let num_u = owned_dofs.len();
        let coupled = b.is_coupled();
        let pieces = Pieces::of(mesh, coupled);
        let rho_of = augmentation(b, mesh, materials, &pieces);
        let rho = |i: usize| [rho_of[i]; 2];
        check_contact_blocks(comm, k, b, my_points.clone(), &rho_of, &self.spec.part)?;
        let spring_at = spring_dofs_of(b, &self.spring_dofs);
        let scaled = |p: [f64; 2]| pieces.scaled(p);
        let rigid = self.free_motions.as_ref().map(|_| {
            let mut gram = DMatrix::<f64>::zeros(3 * pieces.count, 3 * pieces.count);
            for (dof, _) in constraints.fixed() {
                if let Some(&p) = mesh.nodes.get(dof / 2) {
                    let r = dof_rigid_row(dof, scaled(p));
                    let at = 3 * pieces.piece_of[dof / 2];
                    let mut rows = DVector::<f64>::zeros(3 * pieces.count);
                    rows.rows_mut(at, 3).copy_from(&r);
                    gram += &rows * rows.transpose();
                }
            }
            RigidCheck { dirichlet: gram }
        });
        // Exact Jacobian solves by block elimination with one factor of K, when they apply
        // (block_elimination.rs); otherwise SNES's KSP solves the mixed Jacobian. A body the
        // Dirichlet conditions do not hold: the same with springs at a few pinned contact dofs,
        // removed in every step (floating_elimination.rs).
        let candidates = schur_dofs(b);
        let inputs = RouteInputs {
            dofs: n,
            points: m,
            per_point,
            schur_size: candidates.len(),
            ranks: session.size(),
            memory_limit: route_choice::memory_limit(session)?,
        };
        let choice = session.agree(route_choice::choose(session, &inputs), "the contact route")?;
        progress.note(&format!("contact: route {} ({})", choice.route.name(), choice.reason));
        if choice.route == Route::DenseSchurGathered {
            return self.gathered_run(session, mesh, materials, constraints, system, progress, &choice).map(Ok);
        }
        let eliminations_apply = choice.route == Route::DenseSchur && m > 0;
        let block_elimination = eliminations_apply && self.free_motions.is_none();
        let pins = match (&rigid, eliminations_apply && !block_elimination) {
            (Some(check), true) => {
                let fixed = |dof: usize| constraints.is_fixed(dof);
                choose_pins(&candidates, mesh, &pieces.piece_of, &fixed, &scaled, &check.dirichlet)
            }
            _ => None,
        };
        // Iterating in (v, λ), the force rows are K v − f (+ the pins' terms), evaluated from
        // K's rows: the pattern's force rows keep their diagonal entry alone (module doc).
        let lean = block_elimination || (pins.is_some() && retry.is_none());
        let pattern = Pattern::new(
            k,
            b,
            mesh,
            &pieces,
            PatternInput {
                layout: &layout,
                owned_dofs: owned_dofs.clone(),
                per_point,
                my_points,
                block_start: block.start,
                rho: &rho_of,
                spring_at: &spring_at,
                lean,
            },
        );
        let Pattern { indptr, indices, base, spring_positions, mut points } =
            session.agree(pattern, "the full-space contact's pattern")?;
        let mut solver =
            NonlinearSolver::new(session, comm, layout.global_size(), block.start, &indptr, &indices, OPTIONS_PREFIX)?;
        // Where each point's displacement columns sit in the ghosted iterate.
        for p in &mut points {
            p.positions =
                p.slots[..p.coefficients.len()].iter().map(|&s| solver.local_columns()[p.start + s]).collect();
        }
        let max_diag = (0..num_u).map(|r| k.get(owned_dofs.start + r, owned_dofs.start + r).abs()).fold(0.0, f64::max);
        let force_scale = comm.max(&[max_diag])?[0].max(f64::MIN_POSITIVE);
        let tolerance = self.spec.tolerance.unwrap_or(1e-9);
        let gap_scale = b.gap.iter().fold(0.0f64, |a, g| a.max(g.abs()));
        let elimination = if block_elimination {
            progress.note("contact: factorising K with the Schur complement on the contact dofs");
            let matrix =
                Matrix::from_csr_rows(session, comm, n, k.first_row, &k.indptr, &k.indices, &k.values, 2, true)?;
            Some(BlockElimination::new(session, &matrix, b, per_point)?)
        } else {
            None
        };
        let held_by_contact = match pins {
            Some(pins) => {
                progress.note("contact: factorising K with springs at pinned contact dofs");
                // The rigid motions over the dofs the rows touch (zero on prescribed ones).
                let motions = DMatrix::from_fn(candidates.len(), 3 * pieces.count, |r, c| {
                    let dof = candidates[r];
                    let node = dof / 2;
                    if c / 3 != pieces.piece_of[node] || constraints.is_fixed(dof) {
                        return 0.0;
                    }
                    dof_rigid_row(dof, scaled(mesh.nodes[node]))[c % 3]
                });
                Some(FloatingElimination::new(session, k, b, per_point, &pins, motions, retry.is_none())?)
            }
            None => None,
        };
        // The sparse LU route keeps its factorisation while few rows change; GMRES weighs the
        // contact rows (displacements) by the force rows' scale (a power of two).
        let reuse = (choice.route == Route::SparseLu && session.flag(LU_REUSE_OPTION)?.unwrap_or(true)).then(|| {
            let weight = 2f64.powi(force_scale.log2().round() as i32);
            FactorisationReuse {
                max_changed_rows: MAX_CHANGED_ROWS,
                row_weights: (0..block.len()).map(|r| if r < num_u { 1.0 } else { weight }).collect(),
            }
        });
        let mut mixed = MixedSystem {
            progress,
            comm,
            elimination,
            held_by_contact,
            reuse,
            law: law.clone(),
            per_point,
            num_u,
            first_dof: owned_dofs.start,
            local_columns: solver.local_columns().to_vec(),
            indptr,
            base,
            stiffness: lean.then_some(k),
            rhs: system.rhs.clone(),
            fixed_row: owned_dofs.clone().map(|d| constraints.is_fixed(d)).collect(),
            points,
            spring: self.spring.map(|k| (k, spring_positions)),
            rigid,
            gap_scale,
            tight: (1e-2 * tolerance).max(1e-14),
            tolerance,
            step_states: None,
            previous: None,
            seen: Vec::new(),
            history: Vec::new(),
            notes: Vec::new(),
            cycles: 0,
            step_cap: 1.0,
            last_step_scale: 1.0,
            regularized: false,
            regularized_steps: 0,
            floating_steps: 0,
            previous_equilibrium: f64::INFINITY,
            floating: None,
            equilibrium: f64::NAN,
            contact_residual: f64::NAN,
            force_terms: 0.0,
            force_scale,
            force_merit: 0.0,
            merit: 0.0,
            monotone: false,
            line_search_failed: false,
            shortened_steps: 0,
            best_merit: f64::INFINITY,
            best_at: 0,
        };
        progress.note(&format!(
            "  contact: {m} points, full-space semi-smooth Newton on {} unknowns ({} friction)",
            layout.global_size(),
            law.name()
        ));
        let max_iterations = self.spec.max_iterations.unwrap_or(DEFAULT_MAX_ITERATIONS);
        let mut z = vec![0.0; block.len()];
        let run = match solver.solve(&mut z, &mut mixed, max_iterations) {
            Ok(run) => run,
            Err(Error::SolverDiverged { solver: method, reason, iterations, residual, tried }) => {
                // With contact pairs a body may stay unheld only in a mode the closed rows do
                // not see (a cylinder turning about its centre on frictionless contact): the
                // condensed route's proximal iterations handle that, and say so if the body is
                // not held at all.
                if let (true, Some(floating), false) = (mixed.regularized, mixed.floating, coupled) {
                    return Err(self.not_held(mesh, floating, iterations));
                }
                let failure = format!(
                    "{method} stopped after {iterations} Newton steps: {reason} (residual {residual:.3e}; {tried})"
                );
                return self.fall_back(session, mesh, system, failure, mixed.notes, start, progress).map(Ok);
            }
            Err(e) => return Err(e),
        };

        // Gather (u, λ) everywhere and check the answer independently of the iteration.
        let global = layout.global_size();
        let mut zv = Vector::new(session, comm, block.len(), global)?;
        zv.set_owned(&z)?;
        let z_all = zv.gather_all()?;
        let mut u: Vec<f64> = (0..n).map(|d| z_all[layout.u(d)]).collect();
        let mut force = vec![0.0; 2 * m];
        for i in 0..m {
            for c in 0..per_point {
                force[2 * i + c] = z_all[layout.lambda(i, c)];
            }
        }
        // The iteration ran in (v, λ): u = v + K⁻¹ Bᵀ λ (block_elimination.rs), or
        // v + K̂⁻¹ Bᵀ λ (floating_elimination.rs).
        if let Some(elimination) = &mut mixed.elimination {
            u = elimination.displacement(&u, &force)?;
        } else if let Some(floating) = mixed.held_by_contact.as_mut().filter(|f| f.in_v) {
            u = floating.displacement(&u, &force)?;
        }
        // The eliminations' answer refined against K itself (refinement.rs).
        let refine = session.flag(REFINE_OPTION)?.unwrap_or(true);
        let refinement = if refine && (mixed.elimination.is_some() || mixed.held_by_contact.is_some()) {
            let equations =
                Equations { stiffness: k, rhs: &system.rhs, boundary: b, law: &law, rho: &rho_of, per_point };
            Some(mixed.refine(&equations, &mut u, &mut force)?)
        } else {
            None
        };
        let uc = b.gather(&u);
        // Displacement scale: the largest displacement of the body or gap (the contact
        // displacements alone are round-off on a body resting on the obstacle).
        let scale = contact::ResidualScale::from_field(&force, &u, &b.gap);
        let residuals = contact::evaluate_residuals(&force, &uc, &b.gap, &|i, rn| law.threshold(i, rn), scale);
        // Equilibrium of the force rows, recomputed from the gathered solution.
        let mut contact_load = vec![0.0; n];
        b.scatter_add(&force, &mut contact_load);
        let (mut num, mut den) = (0.0f64, 0.0f64);
        for r in 0..num_u {
            let dof = owned_dofs.start + r;
            let (cols, vals) = k.row(dof);
            let (mut ku, mut terms) = (0.0, 0.0);
            for (&c, &v) in cols.iter().zip(vals) {
                ku += v * u[c];
                terms += (v * u[c]).abs();
            }
            num = num.max((ku - system.rhs[r] - contact_load[dof]).abs());
            den = den.max(terms + system.rhs[r].abs() + contact_load[dof].abs());
        }
        let nd = comm.max(&[num, den])?;
        let equilibrium = if nd[1] > 0.0 { nd[0] / nd[1] } else { nd[0] };
        // The full-space route converges to 1e-2 × the tolerance and refines the eliminations'
        // answer against K: its answer must meet the tolerance itself (100 × it before, which
        // let the (v, λ) answer of a slender floating body through with 1e-8 of penetration
        // and its pressure wrong at 1e-6; refinement.rs).
        let accepted = self.acceptance(tolerance).min(tolerance);
        if !residuals.is_acceptable(accepted) || equilibrium.is_nan() || equilibrium > accepted {
            if mixed.held_by_contact.as_ref().is_some_and(|f| f.in_v) {
                return Ok(Err(format!(
                    "the floating elimination's answer in (v, λ) fails the independent check ({residuals}; \
                     equilibrium of the force rows {equilibrium:.3e})"
                )));
            }
            return Err(Error::SolverDiverged {
                solver: run.method.clone(),
                reason: format!(
                    "{} but the answer fails the independent check: {residuals}; equilibrium of the force rows {equilibrium:.3e}",
                    run.converged_reason
                ),
                iterations: run.iterations,
                residual: residuals.worst().max(equilibrium),
                tried: "full-space semi-smooth Newton; use solver = \"newton\" (condensed semi-smooth Newton)".into(),
            });
        }
        let status: Vec<PointStatus> = (0..m)
            .map(|i| {
                let e =
                    evaluate(&law, i, rho(i), b.gap[i], [uc[2 * i], uc[2 * i + 1]], [force[2 * i], force[2 * i + 1]]);
                status_of(&law, &e)
            })
            .collect();
        let span = augmentation_range(&rho_of, &b.weight);
        let mut notes = vec![
            run.converged_reason.clone(),
            if coupled {
                format!(
                    "augmentation ρ_i = 2 w_i / (L_s/E'_s + L_m/E'_m) = {:.4e} to {:.4e} · w_i (the point's two bodies in \
                     series: E' plane modulus, L body diameter; w_i point weight)",
                    span.0, span.1
                )
            } else {
                format!(
                    "augmentation ρ_i = 2 E' w_i / L = {:.4e} · w_i (E' plane modulus, w_i point weight, L body diameter)",
                    span.1
                )
            },
        ];
        if mixed.shortened_steps > 0 {
            notes.push(format!("{} steps shortened by the line search", mixed.shortened_steps));
        }
        if mixed.regularized_steps > 0 {
            notes.push(format!(
                "{} regularised steps (springs in the Jacobian while the closed points left a rigid motion free)",
                mixed.regularized_steps
            ));
        }
        if let Some(refined) = refinement.filter(|r| r.steps > 0) {
            notes.push(format!(
                "{} step(s) of iterative refinement against K: residual {:.1e} -> {:.1e}",
                refined.steps, refined.before, refined.after
            ));
        }
        if let Some(first) = &retry {
            notes.push(format!("{first}; iterated again in (u, λ), one solve per step"));
        }
        if let Some(f) = run.factorisations {
            notes.push(format!(
                "{f} LU factorisation(s) of the mixed Jacobian for {} Newton steps (kept while at most \
                 {MAX_CHANGED_ROWS} rows changed; {} GMRES iterations in all)",
                run.iterations, run.linear_iterations
            ));
        }
        notes.extend(mixed.notes.iter().cloned());
        let solution = ContactSolution {
            force: force.clone(),
            displacement: uc,
            iterations: run.iterations,
            history: mixed.history.clone(),
            status: status.clone(),
            residuals,
            solver: format!("full-space semi-smooth Newton (Alart–Curnier), {}", run.method),
            notes,
        };
        let mut report = self.report(&force, &status, &u, &residuals, run.iterations, &solution);
        report.route = choice.route.name().into();
        report.route_reason = choice.reason.clone();
        let mut stats = stats_of(&run, equilibrium, start.elapsed().as_secs_f64());
        if mixed.elimination.is_some() {
            stats.factor_package = Some("mumps (Cholesky of K, Schur complement on the contact dofs)".into());
        }
        Ok(Ok((u, ContactOutcome { force, status, report }, stats)))
    }

    /// The gathered dense route under MPI (`gathered.rs`): `K` and the load gathered on rank 0,
    /// which runs the one-process route on them alone and sends the answer to the other ranks.
    /// The answer is the serial one on every rank; the report names the route and why, then
    /// the one-process run's own reason.
    #[allow(clippy::too_many_arguments)]
    fn gathered_run(
        &self,
        session: &Session,
        mesh: &Mesh,
        materials: &CellMaterials,
        constraints: &Constraints,
        system: &LinearSystem,
        progress: &dyn crate::problem::Progress,
        choice: &route_choice::RouteChoice,
    ) -> Result<Solved> {
        let n = 2 * mesh.num_nodes();
        let gather_start = std::time::Instant::now();
        let whole = gathered::gather_system(session, system, n);
        let whole = session.agree(whole, "gathering the stiffness on rank 0")?;
        let world = session.world();
        let Some(whole) = whole else {
            // The other ranks: rank 0's answer, or its failure.
            let bytes = world.broadcast_from_rank_0_sleeping(Vec::new())?;
            let (ok, answer) = bytes
                .split_first()
                .ok_or_else(|| Error::PetscUsage("the gathered contact route: rank 0 sent an empty answer".into()))?;
            if *ok == 0 {
                return Err(Error::OtherRank { rank: 0, during: "the gathered contact solve" });
            }
            let answer = gathered::decode_answer(answer)?;
            let residuals = answer.report.contact_residuals();
            let solution = ContactSolution {
                force: answer.force.clone(),
                displacement: self.boundary.gather(&answer.u),
                iterations: answer.report.iterations,
                history: Vec::new(),
                status: answer.status.clone(),
                residuals,
                solver: String::new(),
                notes: Vec::new(),
            };
            let mut report = self.report(
                &answer.force,
                &answer.status,
                &answer.u,
                &residuals,
                answer.report.linear_solves,
                &solution,
            );
            answer.report.apply(&mut report);
            return Ok((answer.u, ContactOutcome { force: answer.force, status: answer.status, report }, answer.stats));
        };
        let gather_seconds = gather_start.elapsed().as_secs_f64();
        let entries = whole.matrix.nnz();
        let solve_start = std::time::Instant::now();
        let solved = session.alone(|alone| {
            self.solve_full_space(alone, mesh, materials, constraints, &whole, &gathered::whole(n), progress)
        });
        drop(whole);
        let solved = solved.map(|(u, mut outcome, stats)| {
            let report = &mut outcome.report;
            if report.route == Route::DenseSchur.name() {
                report.route = Route::DenseSchurGathered.name().into();
            }
            report.route_reason = format!("{}; on rank 0 alone: {}", choice.reason, report.route_reason);
            report.notes.push(format!(
                "K ({entries} entries) gathered on rank 0 in {gather_seconds:.2} s; the one-process route there took \
                 {:.2} s",
                solve_start.elapsed().as_secs_f64()
            ));
            (u, outcome, stats)
        });
        let message = match &solved {
            Ok((u, outcome, stats)) => {
                let mut m = vec![1u8];
                m.extend(gathered::encode_answer(u, outcome, stats));
                m
            }
            Err(_) => vec![0u8],
        };
        world.broadcast_from_rank_0_sleeping(message)?;
        solved
    }

    /// The error for a body that the contact does not hold (see the module documentation).
    fn not_held(&self, mesh: &Mesh, floating: Floating, iterations: usize) -> Error {
        let free = self.free_motions.clone().unwrap_or_default();
        if floating.closed == 0 {
            self.lift_off(mesh, &free)
        } else {
            Error::NoEquilibrium(format!(
                "no static equilibrium: the loads are not balanced by the contact forces on '{}' and the supports \
                 ({free}); the body slides or moves away (unbalanced force ({:.4e}, {:.4e}) after {iterations} \
                 full-space Newton steps with {} closed points, friction {})",
                self.spec.part,
                floating.imbalance[0],
                floating.imbalance[1],
                floating.closed,
                self.friction_report()
            ))
        }
    }

    /// The condensed semi-smooth Newton on the same problem, after a failed full-space run.
    #[allow(clippy::too_many_arguments)]
    fn fall_back(
        &self,
        session: &Session,
        mesh: &Mesh,
        system: &LinearSystem,
        failure: String,
        notes: Vec<String>,
        start: std::time::Instant,
        progress: &dyn crate::problem::Progress,
    ) -> Result<Solved> {
        // The condensed route holds W = B K⁻¹ Bᵀ dense (2m × 2m, and copies): with thousands of
        // points it may not fit, and then the full-space failure is the answer.
        let schur = 2 * self.boundary.points();
        let needed = route_choice::dense_bytes(schur);
        if let Some(limit) = route_choice::memory_limit(session)?.filter(|&limit| needed > limit) {
            return Err(Error::SolverDiverged {
                solver: "full-space semi-smooth Newton".into(),
                reason: failure,
                iterations: 0,
                residual: f64::NAN,
                tried: format!(
                    "no fallback: the condensed route's dense W on {schur} contact unknowns needs about {} and {} \
                     are available; try -contact_route dense_schur or sparse_lu, or more Newton steps \
                     (-contact_snes_max_it)",
                    route_choice::megabytes(needed),
                    route_choice::megabytes(limit)
                ),
            });
        }
        progress.note(&format!("contact: {failure}; falling back to the condensed semi-smooth Newton"));
        let k = &system.matrix;
        let mut values = k.values.clone();
        if let Some(spring) = self.spring {
            self.add_spring_values(spring, k.first_row, &k.indptr, &k.indices, &mut values)?;
        }
        let n = 2 * mesh.num_nodes();
        let matrix =
            Matrix::from_csr_rows(session, session.world(), n, k.first_row, &k.indptr, &k.indices, &values, 2, true)?;
        let mut rhs = matrix.create_vector()?;
        rhs.set_owned(&system.rhs)?;
        let mut ksp = LinearSolver::new(session, session.world(), "")?;
        ksp.set_operator(&matrix)?;
        let (u, mut outcome, condensed_stats) =
            self.solve(session, &matrix, &rhs, &mut ksp, progress).map_err(|e| match e {
                Error::SolverDiverged { solver, reason, iterations, residual, tried } => Error::SolverDiverged {
                    solver: format!("{solver} (fallback from the full-space semi-smooth Newton)"),
                    reason,
                    iterations,
                    residual,
                    tried: format!("first the full-space semi-smooth Newton: {failure}; then {tried}"),
                },
                other => other,
            })?;
        let mut all = vec![format!("full-space semi-smooth Newton failed ({failure}); fell back to the condensed one")];
        all.extend(notes);
        all.append(&mut outcome.report.notes);
        outcome.report.notes = all;
        outcome.report.solver = format!("condensed {} (fallback from the full-space Newton)", outcome.report.solver);
        outcome.report.route_reason =
            format!("fallback: the full-space Newton failed ({failure}); {}", outcome.report.route_reason);
        // The condensed solve reports its own linear solves (the Schur factorisation on one
        // process); the KSP's are the per-column route's.
        let mut stats = condensed_stats
            .or_else(|| ksp.last_stats())
            .ok_or_else(|| Error::PetscUsage("the condensed fallback recorded no linear solve".into()))?;
        stats.seconds = start.elapsed().as_secs_f64();
        Ok((u, outcome, stats))
    }
}

fn stats_of(run: &NonlinearSolve, equilibrium: f64, seconds: f64) -> SolveStats {
    SolveStats {
        ksp_type: format!("snes newtonls + {}", run.ksp_type),
        pc_type: run.pc_type.clone(),
        factor_package: run.factor_package.clone(),
        iterations: run.iterations,
        converged_reason: run.converged_reason.clone(),
        relative_residual: equilibrium,
        seconds,
    }
}
