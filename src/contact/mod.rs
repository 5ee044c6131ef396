//! # The condensed frictional contact problem and its solvers
//!
//! Every formulation of the project ends in the same small problem posed on the contact
//! unknowns only. The primal formulation gets it by condensing the stiffness onto the contact
//! degrees of freedom (the flexibility, or Delassus, operator `W = P K⁻¹ Pᵀ`); the dual
//! formulation (Airy stress function on HCT elements) gets it by condensing the saddle-point
//! system onto the contact forces (the talk's `D f_C = G + G_C`, with `D = W` and
//! `G + G_C = g̃ − u_free` in the notation below). This module knows nothing of meshes or
//! displacement fields: it only sees the operator `W`, the free displacements and the gaps.
//!
//! ## Unknowns and conventions (2D, `m` contact points)
//!
//! ```text
//!   unknown vector, 2m entries:   r = ( rN_0, rT_0, rN_1, rT_1, ..., rN_{m-1}, rT_{m-1} )
//!
//!              body
//!        ----------------        n  : outward normal of the body at the point
//!              |  point i        t  : tangent (n, t) is the local frame
//!              v n               rN : force on the body along n  (compression: rN <= 0)
//!      ////////////////////      rT : force on the body along t
//!        rigid obstacle, at distance g0_i >= 0 along n (g0 < 0: initial overlap)
//! ```
//!
//! - Relative displacements `u = W r + u_free`, `W` symmetric positive definite (2m × 2m),
//!   `u_free` the displacements under the loads when no contact force acts.
//! - Signorini: `uN_i − g0_i ≤ 0`, `rN_i ≤ 0`, `rN_i (uN_i − g0_i) = 0`.
//! - Friction with threshold `s_i ≥ 0`: `|rT_i| ≤ s_i`; `|rT_i| < s_i ⇒ uT_i = 0` (stick);
//!   `|rT_i| = s_i ⇒ uT_i = −λ rT_i, λ ≥ 0` (slip, the friction force opposes the slip).
//!   Tresca: `s_i` given. Coulomb: `s_i = −μ_i rN_i`. No friction: `rT_i = 0`, and the
//!   tangential unknowns are never touched (they stay exactly `0.0`).
//! - Optional weights `w_i ≥ 0` (quadrature or tributary areas): only used to report pressures
//!   `r / w` ([`CondensedProblem::pressure`]). A weight is 0 at a P2 vertex on the axis of a
//!   body of revolution (its force is a concentrated one; `ContactBoundary::tractions`
//!   extrapolates its pressure instead, see `boundary::AxisPressure`).
//!
//! ## Variational form (why the solvers work)
//!
//! With `g̃ = (g0_0, 0, g0_1, 0, ...)` and the admissible set
//! `K(s) = { r : rN_i ≤ 0, |rT_i| ≤ s_i }`, the Tresca problem is the box-constrained quadratic
//! program (the complementary energy of the talk's dual formulation)
//!
//! ```text
//!   minimize  J(r) = ½ rᵀ W r + rᵀ (u_free − g̃)   over r ∈ K(s),
//! ```
//!
//! whose optimality conditions `∇J = u − g̃` are exactly Signorini + Tresca above (KKT of the
//! bound `rN ≤ 0` gives `uN − g0 ≤ 0` with complementarity; KKT of `|rT| ≤ s` gives stick or
//! slip opposite to `rT`). Equivalently (Alart & Curnier 1991), for any `ρ > 0`,
//! `r = P_K(r − ρ (u − g̃))`, with the projections `P_N(x) = min(x, 0)` and
//! `P_T(x) = clamp(x, −s, s)`. Coulomb is the quasi-variational version with `s = −μ rN`:
//! it has solutions for every μ and a unique one for small μ only.
//!
//! ## Solvers ([`ContactSolver`])
//!
//! | solver | file | needs | Coulomb |
//! |---|---|---|---|
//! | projected relaxation (block Gauss–Seidel / SOR, Moreau, Jean) | `projected_relaxation.rs` | `Dense` | exact local 2×2 Coulomb solve |
//! | D-PANA block relaxation (Bisegna, Lebon, Maceri 2001) | `dpana.rs` | `Dense` | by design (thresholds from the last normal forces) |
//! | Uzawa / projected gradient on the multipliers, optional Nesterov acceleration | `uzawa.rs` | products | thresholds updated inside the iteration |
//! | semi-smooth Newton on the Alart–Curnier function (primal–dual active set) | `semismooth_newton.rs` | `Dense` (LU/Cholesky) or products (CG/GMRES) | directly (non-symmetric Jacobian) |
//! | fixed point on Tresca thresholds around any of the above | `tresca_fixed_point.rs` | inner solver's | outer loop `s = μ|rN|` |
//!
//! No solver takes a tuning parameter: steps and augmentation parameters are derived from `W`
//! (its diagonal or an estimate of its largest eigenvalue). Every solver ends by recomputing the
//! residuals of [`CondensedProblem::residuals`] from the force alone, independently of its own
//! bookkeeping, and returns [`Error::SolverDiverged`] if they are not within the tolerance: no
//! unchecked answer ever leaves this module.
//!
//! Input mistakes (sizes, non-finite values, a `W` that is not symmetric positive definite, a
//! solver that needs matrix entries given an implicit operator) are reported as
//! [`Error::Usage`], naming the contact point or entry at fault.
pub mod boundary;
mod box_qp;
mod delassus;
mod dpana;
pub(crate) mod krylov;
pub mod mortar;
pub mod obstacle;
mod projected_relaxation;
mod residuals;
mod semismooth_newton;
mod tresca_fixed_point;
mod uzawa;

use delassus::validate_delassus;
pub use delassus::{Delassus, DelassusProduct};
pub use residuals::{evaluate as evaluate_residuals, ContactResiduals, ResidualScale};

use std::rc::Rc;

use crate::error::{Error, Result};

/// Relative tolerance on the symmetry of a dense Delassus matrix (relative to its largest
/// entry); the stored matrix is the symmetric part.
const SYMMETRY_TOLERANCE: f64 = 1e-8;

/// Iterations without a 0.1 % improvement of the best residual after which the relaxation
/// methods (projected relaxation, Uzawa) declare stagnation.
pub(crate) const STAGNATION_WINDOW: usize = 500;

/// The best residual of an iterative solver so far, and whether it has stopped improving: no
/// 0.1 % progress in `window` iterations.
pub(crate) struct Stagnation {
    best: f64,
    best_at: usize,
    window: usize,
}

impl Stagnation {
    pub(crate) fn new(window: usize) -> Self {
        Stagnation { best: f64::INFINITY, best_at: 0, window }
    }

    /// Record the residual of `iteration`; true when the solver has stagnated.
    pub(crate) fn stalled(&mut self, residual: f64, iteration: usize) -> bool {
        if residual < self.best * (1.0 - 1e-3) {
            self.best = residual;
            self.best_at = iteration;
            false
        } else {
            iteration - self.best_at >= self.window
        }
    }

    pub(crate) fn best(&self) -> f64 {
        self.best
    }
}

/// The friction law on the contact points.
#[derive(Debug, Clone, PartialEq)]
pub enum FrictionLaw {
    /// Frictionless: `rT = 0`, the tangential unknowns are never touched.
    None,
    /// Tresca: `|rT_i| ≤ threshold_i` with a given threshold `≥ 0` per point (force units).
    Tresca {
        /// The threshold of each point.
        threshold: Vec<f64>,
    },
    /// Coulomb: `|rT_i| ≤ −mu_i rN_i`, one friction coefficient `≥ 0` per point.
    Coulomb {
        /// The coefficient of each point.
        mu: Vec<f64>,
    },
}

impl FrictionLaw {
    /// The friction threshold of point `i` given its normal force: 0 without friction, the
    /// given threshold for Tresca, `μ_i max(−rN, 0)` for Coulomb.
    pub fn threshold(&self, i: usize, normal_force: f64) -> f64 {
        match self {
            FrictionLaw::None => 0.0,
            FrictionLaw::Tresca { threshold } => threshold[i],
            FrictionLaw::Coulomb { mu } => mu[i] * (-normal_force).max(0.0),
        }
    }

    fn name(&self) -> &'static str {
        match self {
            FrictionLaw::None => "frictionless",
            FrictionLaw::Tresca { .. } => "Tresca",
            FrictionLaw::Coulomb { .. } => "Coulomb",
        }
    }
}

/// The condensed contact problem. Built by [`CondensedProblem::new`], which validates it.
#[derive(Debug, Clone)]
pub struct CondensedProblem<'a> {
    delassus: Rc<Delassus<'a>>,
    free_displacement: Vec<f64>,
    gap: Vec<f64>,
    friction: FrictionLaw,
    weights: Vec<f64>,
    /// Diagonal of `W` (cached: residual scales use it).
    diagonal: Vec<f64>,
    /// Alart–Curnier augmentation parameter per component (see [`augmentation`]).
    augmentation: Vec<f64>,
}

/// State of a contact point in a solution or an iterate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PointStatus {
    /// No normal contact force (`rN = 0`).
    Open,
    /// In contact, tangential displacement zero, strictly inside the friction threshold.
    Stick,
    /// In contact, on the friction threshold (also: in contact without friction, where the
    /// threshold is zero and the tangential displacement is free).
    Slip,
}

/// One iteration of a solver (a sweep, an outer iteration or a Newton step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationRecord {
    /// [`ContactResiduals::worst`] after the iteration.
    pub residual: f64,
    /// Number of points whose state (open / stick / slip and slip direction) changed in the
    /// iteration, as classified by the Alart–Curnier map.
    pub status_changes: usize,
}

/// A checked solution of the condensed problem.
#[derive(Debug, Clone)]
pub struct ContactSolution {
    /// Contact forces `r`, ordered `(N_0, T_0, N_1, T_1, ...)`.
    pub force: Vec<f64>,
    /// Relative displacements `u = W r + u_free`, same ordering.
    pub displacement: Vec<f64>,
    /// Iterations of the solver that produced the answer (for a fallback: all of them).
    pub iterations: usize,
    /// The solver's record of each iteration (residual, status changes).
    pub history: Vec<IterationRecord>,
    /// Per point, from the final force.
    pub status: Vec<PointStatus>,
    /// The independent check of the answer (always within the requested tolerance).
    pub residuals: ContactResiduals,
    /// Which solver produced the answer (e.g. "semi-smooth Newton (Alart–Curnier)").
    pub solver: String,
    /// What happened on the way: cycles detected, damping, fallbacks, parameters derived.
    pub notes: Vec<String>,
}

/// The solvers of the condensed problem.
#[derive(Debug, Clone, PartialEq)]
pub enum ContactSolver {
    /// Block Gauss–Seidel (`omega = 1`) or SOR sweeps over the points, each point's 2×2
    /// problem solved exactly. `0 < omega < 2`. Needs [`Delassus::Dense`].
    ProjectedRelaxation {
        /// The relaxation factor ω.
        omega: f64,
    },
    /// D-PANA: alternate contact-only and friction-only box QPs. Needs [`Delassus::Dense`].
    /// Converges for Tresca; for Coulomb only for small μ.
    DPana,
    /// Projected gradient (Uzawa) on the contact forces with the step `1/λmax(W)`;
    /// `accelerated` adds Nesterov momentum with adaptive restart.
    Uzawa {
        /// With Nesterov momentum.
        accelerated: bool,
    },
    /// Semi-smooth Newton on the Alart–Curnier function (= primal–dual active set).
    SemismoothNewton,
    /// Coulomb as a fixed point on Tresca thresholds `s = μ|rN|`, each Tresca problem solved
    /// by `inner`. For Tresca or frictionless problems it is just `inner`.
    TrescaFixedPoint {
        /// The solver of each Tresca problem.
        inner: Box<ContactSolver>,
    },
}

impl ContactSolver {
    /// A human-readable name, used in errors and in [`ContactSolution::solver`].
    pub fn name(&self) -> String {
        match self {
            ContactSolver::ProjectedRelaxation { omega } => {
                if *omega == 1.0 {
                    "projected relaxation (block Gauss–Seidel)".to_string()
                } else {
                    format!("projected relaxation (block SOR, omega = {omega})")
                }
            }
            ContactSolver::DPana => "D-PANA block relaxation".to_string(),
            ContactSolver::Uzawa { accelerated: false } => "Uzawa (projected gradient)".to_string(),
            ContactSolver::Uzawa { accelerated: true } => "Uzawa (accelerated projected gradient)".to_string(),
            ContactSolver::SemismoothNewton => "semi-smooth Newton (Alart–Curnier)".to_string(),
            ContactSolver::TrescaFixedPoint { inner } => {
                format!("fixed point on Tresca thresholds around {}", inner.name())
            }
        }
    }
}

/// Stopping rules and options shared by the solvers.
#[derive(Debug, Clone, PartialEq)]
pub struct SolverSettings {
    /// Acceptance threshold on [`ContactResiduals::worst`] (relative, see [`ResidualScale`]).
    pub tolerance: f64,
    /// Iteration limit: sweeps, outer iterations or Newton steps, depending on the solver.
    /// A fallback solver gets the same limit again.
    pub max_iterations: usize,
    /// Starting force (projected onto the admissible set first); zero if `None`.
    pub initial_force: Option<Vec<f64>>,
    /// Semi-smooth Newton only: line search on the merit function, damping when the active set
    /// cycles and fallback to a relaxation method. Switch off only to study the raw method.
    pub newton_globalization: bool,
    /// Semi-smooth Newton only: the solver of each step's dense system; nalgebra's LU (or
    /// Cholesky) if `None`. The problem drivers pass LAPACK's (`petsc::dense_lu`), blocked and
    /// several times faster from a few hundred unknowns on.
    pub dense_solver: Option<DenseSolver>,
}

/// A solver of dense square systems `A x = b` (`None`: singular), shared by the settings'
/// copies. Equal when it is the same solver.
#[derive(Clone)]
pub struct DenseSolver(pub std::sync::Arc<DenseSolve>);

/// `x = A⁻¹ b`, `None` when `A` is singular.
pub type DenseSolve =
    dyn Fn(&nalgebra::DMatrix<f64>, &nalgebra::DVector<f64>) -> Option<nalgebra::DVector<f64>> + Send + Sync;

impl std::fmt::Debug for DenseSolver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("DenseSolver")
    }
}

impl PartialEq for DenseSolver {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-9,
            max_iterations: 10_000,
            initial_force: None,
            newton_globalization: true,
            dense_solver: None,
        }
    }
}

/// Validate a friction law for `m` points; an all-zero threshold or coefficient is no friction
/// (so that no friction machinery runs for μ = 0).
fn checked_friction(friction: FrictionLaw, m: usize) -> Result<FrictionLaw> {
    Ok(match friction {
        FrictionLaw::None => FrictionLaw::None,
        FrictionLaw::Tresca { threshold } => {
            check_per_point(&threshold, m, "Tresca threshold", false)?;
            if threshold.iter().all(|&s| s == 0.0) {
                FrictionLaw::None
            } else {
                FrictionLaw::Tresca { threshold }
            }
        }
        FrictionLaw::Coulomb { mu } => {
            check_per_point(&mu, m, "Coulomb friction coefficient", false)?;
            if mu.iter().all(|&v| v == 0.0) {
                FrictionLaw::None
            } else {
                FrictionLaw::Coulomb { mu }
            }
        }
    })
}

fn check_finite(values: &[f64], what: &str) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(Error::Usage(format!(
            "condensed contact problem: {what} entry {i} (contact point {}) is {}; \
             every entry must be a finite number",
            i / 2,
            values[i]
        ))),
        None => Ok(()),
    }
}

fn check_per_point(values: &[f64], m: usize, what: &str, must_be_positive: bool) -> Result<()> {
    if values.len() != m {
        return Err(Error::Usage(format!(
            "condensed contact problem: {what} has {} entries, expected one per contact point ({m})",
            values.len()
        )));
    }
    for (i, &v) in values.iter().enumerate() {
        let ok = v.is_finite() && if must_be_positive { v > 0.0 } else { v >= 0.0 };
        if !ok {
            let required = if must_be_positive { "> 0" } else { ">= 0" };
            return Err(Error::Usage(format!(
                "condensed contact problem: contact point {i}: {what} is {v}, it must be finite and {required}"
            )));
        }
    }
    Ok(())
}

impl<'a> CondensedProblem<'a> {
    /// Validates and builds the problem.
    ///
    /// - `delassus`: `2m × 2m`, symmetric (to 1e-8 relative; the symmetric part is kept) and
    ///   positive definite (checked by a Cholesky factorization for `Dense`; for `Operator`,
    ///   positive diagonal and two probe products checked for symmetry and positivity);
    /// - `free_displacement`: `2m` finite values; `gap`: `m` finite values;
    /// - friction data: one value `≥ 0` per point. A friction law whose thresholds or
    ///   coefficients are all zero is stored as [`FrictionLaw::None`];
    /// - `weights`: one value `≥ 0` per point (0: a P2 vertex on the axis in axisymmetry,
    ///   whose [`CondensedProblem::pressure`] is then not finite), or `None` for unit weights.
    pub fn new(
        delassus: Delassus<'a>,
        free_displacement: Vec<f64>,
        gap: Vec<f64>,
        friction: FrictionLaw,
        weights: Option<Vec<f64>>,
    ) -> Result<Self> {
        let m = gap.len();
        if m == 0 {
            return Err(Error::Usage("condensed contact problem: no contact point (the gap vector is empty)".into()));
        }
        let n = 2 * m;
        check_finite(&gap, "gap").map_err(|_| {
            let i = gap.iter().position(|g| !g.is_finite()).unwrap_or(0);
            Error::Usage(format!("condensed contact problem: contact point {i}: gap is {}; it must be finite", gap[i]))
        })?;
        if free_displacement.len() != n {
            return Err(Error::Usage(format!(
                "condensed contact problem: free displacement has {} entries, expected 2 per \
                 contact point (2 × {m} = {n}, ordered N_0, T_0, N_1, T_1, ...)",
                free_displacement.len()
            )));
        }
        check_finite(&free_displacement, "free displacement")?;
        let friction = checked_friction(friction, m)?;
        let weights = match weights {
            Some(w) => {
                check_per_point(&w, m, "weight", false)?;
                w
            }
            None => vec![1.0; m],
        };
        let delassus = validate_delassus(delassus, n)?;
        let diagonal = delassus.diagonal();
        let augmentation = augmentation(&diagonal);
        Ok(CondensedProblem {
            delassus: Rc::new(delassus),
            free_displacement,
            gap,
            friction,
            weights,
            diagonal,
            augmentation,
        })
    }

    /// Number of contact points `m`.
    pub fn points(&self) -> usize {
        self.gap.len()
    }

    /// The flexibility `W = B K⁻¹ Bᵀ` (dense or as an operator).
    pub fn delassus(&self) -> &Delassus<'a> {
        &self.delassus
    }

    /// The free displacement `u_free` of the contact unknowns (without contact forces).
    pub fn free_displacement(&self) -> &[f64] {
        &self.free_displacement
    }

    /// The initial gap `g0` of each point.
    pub fn gap(&self) -> &[f64] {
        &self.gap
    }

    /// The friction law of the points.
    pub fn friction(&self) -> &FrictionLaw {
        &self.friction
    }

    /// The boundary weight of each point (its share of the contact part's length).
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The same problem with another friction law (shares `W`; validates the new data).
    pub fn with_friction(&self, friction: FrictionLaw) -> Result<Self> {
        let m = self.points();
        let friction = checked_friction(friction, m)?;
        Ok(CondensedProblem { friction, ..self.clone() })
    }

    /// The same problem with other free displacements (shares `W`; validates the new data).
    pub fn with_free_displacement(&self, free_displacement: Vec<f64>) -> Result<Self> {
        if free_displacement.len() != 2 * self.points() {
            return Err(Error::Usage(format!(
                "condensed contact problem: free displacement has {} entries, expected {}",
                free_displacement.len(),
                2 * self.points()
            )));
        }
        check_finite(&free_displacement, "free displacement")?;
        Ok(CondensedProblem { free_displacement, ..self.clone() })
    }

    /// `u = W r + u_free`.
    pub fn displacement(&self, force: &[f64]) -> Result<Vec<f64>> {
        self.check_force(force, "force")?;
        Ok(self.displacement_unchecked(force))
    }

    /// Pressures `r / w` (per unit weight), same ordering as the force.
    pub fn pressure(&self, force: &[f64]) -> Result<Vec<f64>> {
        self.check_force(force, "force")?;
        Ok(force.iter().enumerate().map(|(k, f)| f / self.weights[k / 2]).collect())
    }

    /// The residuals of a candidate force, computed from `r` alone (`u = W r + u_free`),
    /// independently of any solver. See [`ContactResiduals`] for the definitions.
    pub fn residuals(&self, force: &[f64]) -> Result<ContactResiduals> {
        self.check_force(force, "force")?;
        let u = self.displacement_unchecked(force);
        Ok(residuals::compute(self, force, &u))
    }

    /// The same problem with `shift` (`2m` values) subtracted from the free displacement: the
    /// law then acts on `u − shift` (an increment of a load path: the obstacle's motion, and the
    /// slip so far along the tangent, see [`crate::evolution`]). Shares `W`.
    pub fn shifted(&self, shift: &[f64]) -> Result<Self> {
        if shift.len() != self.free_displacement.len() {
            return Err(Error::Usage(format!(
                "a shift of the contact displacements needs {} values, got {}",
                self.free_displacement.len(),
                shift.len()
            )));
        }
        self.with_free_displacement(self.free_displacement.iter().zip(shift).map(|(u, s)| u - s).collect())
    }

    /// The residuals of a force against displacements obtained some other way — e.g. `B u` of
    /// the displacement field recomputed from `K u = f + Bᵀ r` by a separate linear solve —
    /// so that the check does not trust `W` either.
    pub fn residuals_at(&self, force: &[f64], displacement: &[f64]) -> Result<ContactResiduals> {
        self.check_force(force, "force")?;
        self.check_force(displacement, "displacement")?;
        Ok(residuals::compute(self, force, displacement))
    }

    /// Per point status of `force` against given displacements (see [`Self::status`]).
    pub fn status_at(&self, force: &[f64], displacement: &[f64]) -> Result<Vec<PointStatus>> {
        self.check_force(force, "force")?;
        self.check_force(displacement, "displacement")?;
        Ok(classify(self, force, displacement).iter().map(|c| c.point_status()).collect())
    }

    /// Per point status of a force (open / stick / slip), classified with the Alart–Curnier
    /// map: in contact iff `rN − ρN (uN − g0) < 0`, sticking iff `|rT − ρT uT| < s`, with
    /// `ρ = 1 / diag(W)`.
    pub fn status(&self, force: &[f64]) -> Result<Vec<PointStatus>> {
        self.check_force(force, "force")?;
        let u = self.displacement_unchecked(force);
        Ok(classify(self, force, &u).iter().map(|c| c.point_status()).collect())
    }

    fn check_force(&self, force: &[f64], what: &str) -> Result<()> {
        let n = 2 * self.points();
        if force.len() != n {
            return Err(Error::Usage(format!(
                "condensed contact problem: the {what} has {} entries, expected 2 per contact \
                 point (2 × {} = {n})",
                force.len(),
                self.points()
            )));
        }
        check_finite(force, what)
    }

    pub(crate) fn displacement_unchecked(&self, force: &[f64]) -> Vec<f64> {
        let mut u = vec![0.0; force.len()];
        self.delassus.apply(force, &mut u);
        for (ui, fi) in u.iter_mut().zip(&self.free_displacement) {
            *ui += fi;
        }
        u
    }

    /// Does point `i` carry friction at all (a nonzero threshold or coefficient)?
    pub(crate) fn has_friction_at(&self, i: usize) -> bool {
        match &self.friction {
            FrictionLaw::None => false,
            FrictionLaw::Tresca { threshold } => threshold[i] > 0.0,
            FrictionLaw::Coulomb { mu } => mu[i] > 0.0,
        }
    }

    /// Friction threshold of point `i` given its normal force (Coulomb: `μ max(−rN, 0)`).
    pub(crate) fn threshold_at(&self, i: usize, normal_force: f64) -> f64 {
        self.friction.threshold(i, normal_force)
    }

    pub(crate) fn diagonal(&self) -> &[f64] {
        &self.diagonal
    }

    pub(crate) fn augmentation(&self) -> &[f64] {
        &self.augmentation
    }

    /// Right-hand side `g̃`: the gap on normal entries, zero on tangential ones.
    pub(crate) fn gap_vector(&self) -> Vec<f64> {
        let mut g = vec![0.0; 2 * self.points()];
        for (i, gi) in self.gap.iter().enumerate() {
            g[2 * i] = *gi;
        }
        g
    }

    /// Projection onto the admissible set: `rN ≤ 0`, `|rT| ≤ s(rN)`, `rT = 0` without friction.
    pub(crate) fn project_admissible(&self, force: &mut [f64]) {
        for i in 0..self.points() {
            force[2 * i] = force[2 * i].min(0.0);
            if self.has_friction_at(i) {
                let s = self.threshold_at(i, force[2 * i]);
                force[2 * i + 1] = force[2 * i + 1].clamp(-s, s);
            } else {
                force[2 * i + 1] = 0.0;
            }
        }
    }
}

/// Alart–Curnier augmentation parameters, one per component: `ρ_k = 1 / W_kk`.
///
/// With this choice a point decoupled from the others is solved in one Newton step, and the
/// parameter follows the units and the mesh without any user input.
fn augmentation(diagonal: &[f64]) -> Vec<f64> {
    diagonal.iter().map(|d| 1.0 / d).collect()
}

/// Tangential state of a point in the Alart–Curnier classification.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum TangentialState {
    /// No friction at the point, or a zero threshold: `rT = 0`.
    Free,
    Stick,
    /// On the threshold, `rT = sign · s`.
    Slip {
        positive: bool,
    },
}

/// State of a point in the Alart–Curnier classification (the "active set").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) struct PointState {
    pub contact: bool,
    pub tangential: TangentialState,
}

impl PointState {
    pub(crate) fn point_status(self) -> PointStatus {
        match (self.contact, self.tangential) {
            (false, _) => PointStatus::Open,
            (true, TangentialState::Stick) => PointStatus::Stick,
            (true, _) => PointStatus::Slip,
        }
    }
}

/// The Alart–Curnier classification of every point at `(r, u)`, with `ρ = 1/diag(W)`:
/// contact iff `τN = rN − ρN (uN − g0) < 0`; threshold `s` (Coulomb: `μ max(−τN, 0)`);
/// stick iff `|τT| < s` with `τT = rT − ρT uT`; slip otherwise, in the direction of `τT`.
pub(crate) fn classify(problem: &CondensedProblem, r: &[f64], u: &[f64]) -> Vec<PointState> {
    let rho = problem.augmentation();
    (0..problem.points())
        .map(|i| {
            let tau_n = r[2 * i] - rho[2 * i] * (u[2 * i] - problem.gap[i]);
            let contact = tau_n < 0.0;
            let tangential = if !problem.has_friction_at(i) {
                TangentialState::Free
            } else {
                let s = match &problem.friction {
                    FrictionLaw::Coulomb { mu } => mu[i] * (-tau_n).max(0.0),
                    _ => problem.threshold_at(i, r[2 * i]),
                };
                if s == 0.0 {
                    TangentialState::Free
                } else {
                    let tau_t = r[2 * i + 1] - rho[2 * i + 1] * u[2 * i + 1];
                    if tau_t.abs() < s {
                        TangentialState::Stick
                    } else {
                        TangentialState::Slip { positive: tau_t > 0.0 }
                    }
                }
            };
            PointState { contact, tangential }
        })
        .collect()
}

/// Number of points whose state differs.
/// Classify the points at `(r, u)`, replace `states` with the result and return how many
/// points changed state (the per-iteration count every solver records).
pub(crate) fn update_states(problem: &CondensedProblem, r: &[f64], u: &[f64], states: &mut Vec<PointState>) -> usize {
    let new_states = classify(problem, r, u);
    let changes = count_changes(states, &new_states);
    *states = new_states;
    changes
}

/// A point whose slip direction reverses between the previous Newton step's states `before`
/// and `states` sticks for this step: it must cross the interior of the friction interval
/// (the rule of both semi-smooth Newton methods, condensed and full-space).
pub(crate) fn stick_reversed_slips(states: &mut [PointState], before: &[PointState]) {
    for (now, before) in states.iter_mut().zip(before) {
        if let (TangentialState::Slip { positive: a }, TangentialState::Slip { positive: b }) =
            (now.tangential, before.tangential)
        {
            if a != b {
                now.tangential = TangentialState::Stick;
            }
        }
    }
}

pub(crate) fn count_changes(a: &[PointState], b: &[PointState]) -> usize {
    a.iter().zip(b).filter(|(x, y)| x != y).count()
}

/// What a solver's iteration produced, before the independent check.
#[derive(Debug, Clone)]
pub(crate) struct Run {
    pub force: Vec<f64>,
    pub iterations: usize,
    pub history: Vec<IterationRecord>,
    pub notes: Vec<String>,
    /// Why the iteration stopped without converging; `None` if it believes it converged.
    pub failure: Option<String>,
    /// What the solver did, for the error message.
    pub tried: String,
    /// Name of the method that produced the force (changes after a fallback).
    pub solver: String,
}

/// Solve the condensed problem with one of the solvers.
///
/// Returns a [`ContactSolution`] whose independent residuals are within
/// `settings.tolerance`, or [`Error::SolverDiverged`] (iteration limit, stagnation, cycling,
/// singular Jacobian, or a failed final check), or [`Error::Usage`] for bad settings or a
/// solver that needs [`Delassus::Dense`].
pub fn solve(problem: &CondensedProblem, solver: &ContactSolver, settings: &SolverSettings) -> Result<ContactSolution> {
    let initial = initial_force(problem, settings)?;
    let run = run_solver(problem, solver, settings, initial)?;
    certify(problem, run, settings.tolerance)
}

fn initial_force(problem: &CondensedProblem, settings: &SolverSettings) -> Result<Vec<f64>> {
    if !(settings.tolerance.is_finite() && settings.tolerance > 0.0) {
        return Err(Error::Usage(format!(
            "contact solver settings: tolerance is {}, it must be a positive number",
            settings.tolerance
        )));
    }
    if settings.max_iterations == 0 {
        return Err(Error::Usage("contact solver settings: max_iterations is 0, it must be at least 1".into()));
    }
    match &settings.initial_force {
        None => Ok(vec![0.0; 2 * problem.points()]),
        Some(f) => {
            problem.check_force(f, "initial force")?;
            let mut f = f.clone();
            problem.project_admissible(&mut f);
            Ok(f)
        }
    }
}

pub(crate) fn run_solver(
    problem: &CondensedProblem,
    solver: &ContactSolver,
    settings: &SolverSettings,
    initial: Vec<f64>,
) -> Result<Run> {
    match solver {
        ContactSolver::ProjectedRelaxation { omega } => {
            if !(omega.is_finite() && *omega > 0.0 && *omega < 2.0) {
                return Err(Error::Usage(format!(
                    "projected relaxation: omega = {omega}; the relaxation factor must be in (0, 2)"
                )));
            }
            projected_relaxation::run(problem, *omega, settings, initial)
        }
        ContactSolver::DPana => dpana::run(problem, settings, initial),
        ContactSolver::Uzawa { accelerated } => Ok(uzawa::run(problem, *accelerated, settings, initial)),
        ContactSolver::SemismoothNewton => semismooth_newton::run(problem, settings, initial),
        ContactSolver::TrescaFixedPoint { inner } => tresca_fixed_point::run(problem, inner, settings, initial),
    }
}

/// The error for a solver that needs explicit entries of `W`.
pub(crate) fn needs_dense(solver: &str) -> Error {
    Error::Usage(format!(
        "{solver} needs the entries of the Delassus matrix (Delassus::Dense), but it was given \
         as an implicit operator; use Uzawa or the semi-smooth Newton method, which only need \
         products"
    ))
}

/// Recompute the residuals from the force alone and accept or reject the run.
pub(crate) fn certify(problem: &CondensedProblem, run: Run, tolerance: f64) -> Result<ContactSolution> {
    let u = problem.displacement_unchecked(&run.force);
    let residuals = residuals::compute(problem, &run.force, &u);
    let residual = residuals.worst();
    let reason = match run.failure {
        Some(reason) => Some(reason),
        None if !residuals.is_acceptable(tolerance) => {
            Some(format!("the independent residual check failed ({residuals}; tolerance {tolerance:e})"))
        }
        None => None,
    };
    if let Some(reason) = reason {
        let history_tail: Vec<String> =
            run.history.iter().rev().take(3).rev().map(|h| format!("{:.2e}", h.residual)).collect();
        return Err(Error::SolverDiverged {
            solver: format!("{} on the {} condensed problem", run.solver, problem.friction.name()),
            reason: format!("{reason}; last residuals [{}]", history_tail.join(", ")),
            iterations: run.iterations,
            residual,
            tried: if run.notes.is_empty() { run.tried } else { format!("{} ({})", run.tried, run.notes.join("; ")) },
        });
    }
    let status = classify(problem, &run.force, &u).iter().map(|c| c.point_status()).collect();
    Ok(ContactSolution {
        force: run.force,
        displacement: u,
        iterations: run.iterations,
        history: run.history,
        status,
        residuals,
        solver: run.solver,
        notes: run.notes,
    })
}
