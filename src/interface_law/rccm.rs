//! # The RCCM adhesion law: unilateral contact, Coulomb friction and an adhesion intensity β
//!
//! Raous, Cangémi and Cocou (*A consistent model coupling adhesion, friction, and unilateral
//! contact*, Comput. Methods Appl. Mech. Engrg. 177, 1999, pp. 383–399), extended by Monerie
//! (thesis, 2000) and Raous and Monerie (2002); reviewed in Raous, *Interface models coupling
//! adhesion and friction*, C. R. Mécanique 339 (2011) 491–501, and Raous, *The art of modeling
//! in contact mechanics*, CISM courses 570 (2016). The adhesion intensity β ∈ [0, 1] (Frémond's
//! variable: 1 fully glued, 0 no bond) weights springs of stiffness `C_N`, `C_T` (Pa/m) between
//! the faces; the debonded fraction rubs with friction `μ (1 − β)`.
//!
//! ## The model (stated in the paper's variables, tractions per unit area)
//!
//! With `u_N ≥ 0` the opening, `u_T` the whole tangential jump, `R_N` the normal traction
//! (tension > 0, as in this crate), `R_T` the tangential traction on the body:
//!
//! ```text
//!   unilateral contact with adhesion   R'_N = R_N − C_N β² u_N ≤ 0,  u_N ≥ 0,  R'_N u_N = 0
//!   tangential                         R_T = −C_T β² u_T + R'_T  (the springs restore)
//!   Coulomb on the rest                |R'_T| ≤ μ (1 − β) |R'_N|, R'_T opposes the slip rate
//!                                      and |R'_T| = μ (1 − β) |R'_N| when it slips
//!   evolution of β                     b β̇ = −(w − β (C_N u_N² + C_T u_T²))⁻   (β ∈ ]0, 1])
//!                                      b β̇ ≤ −(w − β (…))⁻                    (β = 0)
//! ```
//!
//! `x⁻ = max(0, −x)` (so β̇ ≤ 0: the bond never heals), `w` (J/m²) Dupré's adhesion energy, `b`
//! (J·s/m²) the viscosity of the bond's breaking. The law derives from the free energy
//! `ψ = ½ β² (C_N u_N² + C_T u_T²) − w β` (plus the indicators of `u_N ≥ 0` and `β ∈ [0, 1]`):
//! `−∂ψ/∂β = w − β E` with `E = C_N u_N² + C_T u_T²` is the energy release rate that drives β, and
//! the dissipation potential `½ b β̇² + I_{β̇ ≤ 0}` gives the evolution law above. Paper's signs:
//! the 1999 paper writes the reaction with `R_N ≥ 0` in tension and `−R_N + C_N β² u_N ≥ 0`
//! (our `R'_N ≤ 0`); the friction threshold `μ (1 − β) |R_N − C_N β² u_N|` is the one of
//! SCIENCE.md §11 (checked). Monerie's thesis adds an exponent `p` to the rate
//! (`β̇ = −((w − βE)⁻ / b)^{1/p}`); the scene's parameters are those of the 1999 paper, `p = 1`.
//! Note that the energy is a traction energy density: `C u²` is J/m² (Pa/m × m²), as `w`.
//!
//! ## Time discretisation (implicit Euler) and the increment's problem
//!
//! Over an increment of duration `Δt`, with `β⁰` the committed value and `E` the energy at the
//! *end* of the increment, `b (β − β⁰)/Δt = −(w − β E)⁻` has the closed-form solution
//!
//! ```text
//!   β⁰ E ≤ w :   β = β⁰                                  (nothing breaks)
//!   β⁰ E > w :   β = (b β⁰ + w Δt) / (b + E Δt)          (then β E > w and β < β⁰)
//!   b = 0    :   β = min(β⁰, w / E)                      (the rate-independent limit)
//! ```
//!
//! so β stays in `[0, β⁰]` without a projection. The same update is LMGC90's `MAC_CZM`
//! (Monerie–Acary–Cangémi cohesive zone, `mod_tact_behav.f90`, `updt_CZM`:
//! `beta = (H w + beta_old b) / (b + H (ct |u_T|² + cn (u_N⁺)²))` applied when
//! `w ≤ beta_old E`), which also uses the positive part of the opening in `E`, as done here.
//!
//! At fixed β the increment's problem is the unilateral contact problem of the crate with parallel
//! springs (module [`crate::interface_law`]): `k = (C_N β², C_T β²) × weight`, the tangential
//! spring's rest offset the slip before the increment (the springs act on the whole jump, the
//! contact problem sees the slip increment), and Coulomb friction on the unilateral force `r'`
//! with the coefficient `μ (1 − β)`. β is the trial value of the staggered iteration (solve →
//! update → solve …), so at convergence the springs, the friction coefficient and β are those of
//! the end of the increment: the scheme is fully implicit. The friction of the scene's contact is
//! replaced by the law's own `μ`.
//!
//! ## The pull-off response (the validation's closed form)
//!
//! A point pulled open by `u` from the glued state with `b = 0` and no slip carries
//! `R_N = C_N β² u` with `β = min(1, w/(C_N u²))`: `R_N = C_N u` up to `u_c = √(w/C_N)`, where the
//! traction peaks at `√(C_N w)`, then `R_N = w²/(C_N u³)`; unloading follows the secant
//! `C_N β² u` back to 0 (β does not heal). LMGC90's law check (`MAC_CZM` in the law test script
//! `examples/mecaMAILx_2D/2Q4-traction/all_cohesive_laws.py`: `new_beta = w/(ct|u_T|² + cn u_N²)` when `w − β E < 0`) computes the
//! same curve.
//!
//! ## Sources checked, and the validation
//!
//! - The model's structure (unilateral contact, Coulomb friction, adhesion intensity β from a
//!   free energy and a dissipation potential, an incremental formulation solved as a sequence of
//!   constrained minimisations, the micro-indentation of a fiber/matrix interface in a ceramic
//!   composite): the 1999 paper's summary (zbMATH Zbl 0949.74008). The formulas above are those of
//!   SCIENCE.md §11 and of the papers as recalled; the figures and parameter tables of the
//!   papers (micro-indentation, Monerie's thesis) were not available to this work, so no curve
//!   of theirs is reproduced.
//! - The time discretisation and the rate-independent limit: LMGC90 (the authors' group's code),
//!   `src/Core/shared/mod_tact_behav.f90` (`updt_CZM`, law `MAC_CZM`) and
//!   `examples/mecaMAILx_2D/2Q4-traction/all_cohesive_laws.py`; the same closed forms as here.
//!   LMGC90's default friction for `MAC_CZM` interpolates `(1 − β) μ_d + β μ_s`; with `μ_s = 0`
//!   it is the paper's `μ (1 − β)`.
//! - Tests: `tests/interface_rccm.rs` (the update against its closed forms and an RK4
//!   integration, the residual at exact and perturbed states) and the PETSc cases
//!   `rccm_pull_off_closed_form` (a glued block pulled off: the 1D series model and the closed
//!   form above to ~1e-11; b > 0 at order 1 in the time step), `rccm_published_peak_and_separation_energy`
//!   (the peak √(C_N w) at √(w/C_N), the work of separation w), `rccm_without_adhesion_is_signorini_coulomb`
//!   (β0 = 0 is Signorini–Coulomb: identical displacements) and `rccm_adhesive_shear_debonds_then_slides`.
use super::{InterfaceLaw, InterfaceOutputs, InterfacePoint, PointFriction, PointModification, PointSolution};
use crate::scene::RccmSpec;

/// The RCCM law with its parameters (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rccm {
    /// `C_N` (Pa/m).
    pub normal_stiffness: f64,
    /// `C_T` (Pa/m).
    pub tangential_stiffness: f64,
    /// `w` (J/m²).
    pub adhesion_energy: f64,
    /// `b` (J·s/m²), ≥ 0.
    pub viscosity: f64,
    /// `μ` ≥ 0.
    pub mu: f64,
    /// `β0` in [0, 1].
    pub initial_adhesion: f64,
}

impl Rccm {
    /// The law of the scene's parameters (validated by the scene's reader).
    pub fn new(spec: &RccmSpec) -> Self {
        Rccm {
            normal_stiffness: spec.normal_stiffness,
            tangential_stiffness: spec.tangential_stiffness,
            adhesion_energy: spec.adhesion_energy,
            viscosity: spec.viscosity,
            mu: spec.mu,
            initial_adhesion: spec.initial_adhesion,
        }
    }

    /// The energy `E = C_N (u_N⁺)² + C_T u_T²` (J/m²) that drives β, from the opening and the
    /// whole tangential jump.
    pub fn energy(&self, opening: f64, slip: f64) -> f64 {
        let open = opening.max(0.0);
        self.normal_stiffness * open * open + self.tangential_stiffness * slip * slip
    }

    /// β at the end of an increment of duration `dt` from `beta_committed` at its start and the
    /// energy `energy` at its end: implicit Euler of `b β̇ = −(w − β E)⁻` (module documentation).
    pub fn beta_update(&self, beta_committed: f64, energy: f64, dt: f64) -> f64 {
        let w = self.adhesion_energy;
        if beta_committed * energy <= w {
            return beta_committed;
        }
        let b = self.viscosity;
        let beta = if b == 0.0 { w / energy } else { (b * beta_committed + w * dt) / (b + energy * dt) };
        beta.clamp(0.0, beta_committed)
    }

    /// The opening at which the glued bond starts to break in pure opening, `√(w/C_N)` (m): the
    /// law's length scale.
    pub fn critical_opening(&self) -> f64 {
        (self.adhesion_energy / self.normal_stiffness).sqrt()
    }

    /// The peak traction of the bond in pure opening with `b = 0`, `√(C_N w)` (Pa).
    pub fn peak_traction(&self) -> f64 {
        (self.adhesion_energy * self.normal_stiffness).sqrt()
    }
}

impl InterfaceLaw for Rccm {
    fn name(&self) -> &'static str {
        "rccm"
    }

    fn has_memory(&self) -> bool {
        true
    }

    fn initial(&self) -> Vec<f64> {
        vec![self.initial_adhesion]
    }

    fn modification(
        &self,
        point: &InterfacePoint,
        _friction: PointFriction,
        trial: &[f64],
        _last: Option<&PointSolution>,
    ) -> PointModification {
        let beta = trial[0];
        let b2 = beta * beta;
        PointModification {
            compliance: [0.0; 2],
            stiffness: [self.normal_stiffness * b2 * point.weight, self.tangential_stiffness * b2 * point.weight],
            spring_offset: [0.0, point.slip_before],
            force_offset: [0.0; 2],
            contact: true,
            friction: PointFriction::Coulomb(self.mu * (1.0 - beta)),
        }
    }

    fn update(&self, _point: &InterfacePoint, committed: &[f64], solution: &PointSolution, dt: f64) -> Vec<f64> {
        let energy = self.energy(solution.opening, solution.slip);
        vec![self.beta_update(committed[0], energy, dt)]
    }

    /// The worst of (each dimensionless):
    /// - the evolution law: `|β − β_update(β⁰, E(solution), Δt)|`, `β ∉ [0, 1]`, `β > β⁰`;
    /// - the split of the force: `r' = r + k∘(jump)` recomputed from the total force, the opening
    ///   and the slip, against the reported `contact_force`, over the force scale `F`;
    /// - the unilateral condition on `r'`: `|min(opening / L, −r'_N / F)|` (both ≥ 0, one 0);
    /// - Coulomb on `r'` with `μ (1 − β)`: `(|r'_T| − s)⁺ / F` and the sliding rule
    ///   `(r'_T Δs + s |Δs|) / (F L)` (zero iff `r'_T = −s sign Δs` when it slips).
    ///
    /// Scales: `L = max(√(w/C_N), |opening|, |slip|)`, `F = max(|r|, |r'|, √(C_N w) × weight)`.
    fn residual(
        &self,
        point: &InterfacePoint,
        committed: &[f64],
        state: &[f64],
        solution: &PointSolution,
        dt: f64,
    ) -> f64 {
        let beta = state[0];
        let beta0 = committed[0];
        let expected = self.beta_update(beta0, self.energy(solution.opening, solution.slip), dt);
        let evolution =
            (beta - expected).abs().max((-beta).max(0.0)).max((beta - 1.0).max(0.0)).max((beta - beta0).max(0.0));

        let b2 = beta * beta;
        let k_n = self.normal_stiffness * b2 * point.weight;
        let k_t = self.tangential_stiffness * b2 * point.weight;
        let [r_n, r_t] = solution.force;
        // r = r' − k (u − g̃ + a): along N, u_N − g0 = −opening; along T the whole slip.
        let contact_n = r_n - k_n * solution.opening;
        let contact_t = r_t + k_t * solution.slip;
        let length = self.critical_opening().max(solution.opening.abs()).max(solution.slip.abs());
        let force = r_n
            .abs()
            .max(r_t.abs())
            .max(solution.contact_force[0].abs())
            .max(solution.contact_force[1].abs())
            .max(self.peak_traction() * point.weight)
            .max(f64::MIN_POSITIVE);
        let split =
            ((contact_n - solution.contact_force[0]).abs()).max((contact_t - solution.contact_force[1]).abs()) / force;
        let unilateral = (solution.opening / length).min(-contact_n / force).abs();
        let threshold = self.mu * (1.0 - beta) * (-contact_n).max(0.0);
        let dslip = solution.slip_increment;
        let coulomb = ((contact_t.abs() - threshold).max(0.0) / force)
            .max((contact_t * dslip + threshold * dslip.abs()).abs() / (force * length));
        evolution.max(split).max(unilateral).max(coulomb)
    }

    fn outputs(&self, state: &[f64]) -> InterfaceOutputs {
        InterfaceOutputs { adhesion: Some(state[0]), damage: None }
    }
}
