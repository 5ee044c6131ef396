//! # The cohesive–frictional joint (masonry): Mohr–Coulomb with a tension cut-off, softening
//!
//! A mortar joint between two bricks (or a brick and a rigid support) holds the faces together
//! until it yields; then it cracks in tension, slips in shear, and its strengths decay with the
//! energy it dissipates, down to pure Coulomb friction. This is the interface model of
//! Lourenço and Rots (1997) without its compressive cap, made rigid before it yields, and
//! written as a [`PointModification`] of the condensed contact problem (module
//! [`crate::interface_law`]).
//!
//! ## The law (tractions in Pa, jumps in m; σ = −t_N the compression)
//!
//! ```text
//!   tension cut-off      t_N ≤ f_t(ξ)                           (t_N = rN / w, tension > 0)
//!   Mohr–Coulomb         |τ| ≤ max(0, c(ξ) + μ σ)                (τ = rT / w)
//!   opening              o ≥ 0,  o (f_t − t_N) = 0               (o = g0 − uN: rigid until it opens)
//!   slip                 Δs ≠ 0 ⇒ |τ| = c + μσ and τ Δs ≤ 0      (Δs: the increment's slip; rigid until it slips)
//!   softening            c = c0 e^(−ξ),  f_t = f_t0 e^(−ξ),  ξ = f_t0 κ_I / G_I + c0 κ_II / G_II
//!   internal variables   κ_I  = the largest opening so far        (m)
//!                        κ_II = the accumulated slip Σ |Δs|       (m)
//! ```
//!
//! Source: P. B. Lourenço and J. G. Rots, "Multisurface interface model for analysis of masonry
//! structures", J. Eng. Mech. 123(7), 660–668, 1997 (and Lourenço's thesis, TU Delft, 1996): a
//! composite yield surface of a straight tension cut-off `f1 = σ_t − f_t(κ1)`, the Coulomb
//! friction envelope `f2 = |τ| + σ_t tan φ − c(κ2)` (σ_t the normal traction, tension
//! positive) and an elliptical compressive cap, with exponential softening
//! `f_t = f_t0 exp(−f_t0 κ1 / G_f^I)` and `c = c0 exp(−c0 κ2 / G_f^II)`, G_f^I and G_f^II the
//! mode-I and mode-II fracture energies, and *isotropic coupling* of the two softening modes
//! ("the percentage of softening in the cohesion is the same as in the tensile strength"):
//! `κ̇1 = λ1 + (G_f^I c0)/(G_f^II f_t0) λ2`, `κ̇2 = (G_f^II f_t0)/(G_f^I c0) λ1 + λ2`, λ1 and λ2
//! the plastic multipliers of the two modes (the opening and the slip rates here). Integrated,
//! this coupling is exactly the single softening variable ξ above:
//! `f_t0 κ1 / G_f^I = c0 κ2 / G_f^II = f_t0 ∫λ1 / G_f^I + c0 ∫λ2 / G_f^II`. (Checked against
//! the description of the model in OOFEM's material manual, `Masonry02`, which implements it.)
//! Pure mode I dissipates `∫ f_t dκ_I = G_I`, pure mode II `∫ c dκ_II = G_II` besides friction.
//!
//! What this law leaves out of Lourenço–Rots, and why:
//! - the elastic stiffnesses k_n, k_s of the joint: the joint is *rigid before it yields* (a
//!   thin elastic layer in series is the thin-layer law's business);
//! - the compressive cap (crushing of the masonry): a bulk failure, not an interface one;
//! - the friction angle's softening `tan φ0 → tan φr` and the dilatancy ψ: one μ (the residual
//!   one is the physically meaningful value after softening), no dilatancy (dilatancy would need
//!   a normal gap shift driven by the slip, which [`PointModification`] does not offer);
//! - L&R's quadratic combination of the two multipliers in the corner (when both modes are
//!   active at once): the linear sum above is used everywhere (the corner is rare with a rigid
//!   joint: open *and* slipping, i.e. `t_N = f_t` and `|τ| = c − μ f_t`).
//!
//! The classic data the law is calibrated on are van der Pluijm's (1993) deformation-controlled
//! shear tests on single bed joints at σ = 0.1, 0.5 and 1.0 MPa (solid clay bricks): the τ–δ
//! curves rise to a peak `c0 + μσ`, then decay exponentially to the residual friction `μσ`,
//! the area between the curve and the residual level being G_II (which the tests show grows
//! with σ; one G_II per joint here). The example `examples/scenes/masonry_joint.toml` uses the
//! parameters of OOFEM's illustration of the model (c0 = 0.8 MPa, G_II = 0.05 N/mm,
//! f_t0 = 0.2 MPa, G_I = 0.018 N/mm) with the residual μ = 0.75.
//!
//! ## As a modification of the contact problem
//!
//! At a point of weight w (force = traction × w), from the trial variables (ξ) and the last
//! solution's total normal force `rN` (the previous staggered iteration's):
//!
//! ```text
//!   force offset   o = (f_t(ξ) w, 0)                   tension carried up to the strength
//!   contact        true: r = r' + o, Signorini on r'   (r'_N ≤ 0 ⇔ t_N ≤ f_t; open ⇔ t_N = f_t)
//!   friction       Tresca on r' with s = max(0, c(ξ) w − μ rN)     (= (c + μσ) w, σ = −rN/w)
//! ```
//!
//! so the solve sees a plain Signorini–Tresca problem, and the staggered loop of the driver
//! makes `rN` and ξ consistent (the fixed point: the threshold from the solution's own normal
//! force, the strengths from the variables at the increment's end). The update is implicit:
//! `κ_I = max(κ_I committed, opening)`, `κ_II = κ_II committed + |Δs|`.
//! A point with an initial gap g0 > 0 is a joint already opened by g0: ξ uses `max(κ_I, g0)`,
//! so a gap much wider than G_I / f_t0 transmits nothing; the joint is meant where the faces
//! touch (g0 = 0).
//!
//! ## Behaviour along a path
//!
//! - **Loading in shear** at constant σ: rigid (stick) until |τ| reaches `c0 + μσ`, then the
//!   slip grows and `τ = c0 exp(−c0 δ / G_II) + μσ` (monotonic slip δ = κ_II), tending to
//!   Coulomb's `μσ`.
//! - **Unloading and reversal**: below the current threshold the joint sticks (rigid): the slip
//!   is permanent (plastic) because the law acts on the slip *increment* (the path's slip
//!   shift), and nothing softens. Reversed slip adds its magnitude to κ_II: the threshold keeps
//!   decaying in both directions.
//! - **Tension**: rigid until `t_N = f_t0`; then the crack opens, carrying `f_t(ξ)` exactly while
//!   open (rigid–softening). Unloading from an opening closes the crack *at constant traction*
//!   `f_t(ξ)` (the opening is not a plastic variable: the normal law acts on the total gap),
//!   then the closed joint carries any traction ≤ f_t(ξ). L&R's elastic–plastic joint would
//!   instead keep a plastic opening; with a rigid joint and the contact's normal law on the
//!   total gap, the crack closes as soon as the tension falls below the current strength.
//! - **A crack that closes under compression**: Signorini with Coulomb's threshold plus the
//!   remaining cohesion, `|τ| ≤ c(ξ) + μσ`; since the softening is coupled, a crack opened
//!   well beyond G_I / f_t0 has lost its cohesion too, and it is then a Signorini–Coulomb
//!   contact (L&R's coupling; with independent softening a cracked joint would keep its full
//!   cohesion in shear).
//! - **Full softening** (ξ → ∞, numerically e^(−ξ) = 0 beyond ξ ≈ 745): o = 0 and
//!   s = −μ rN: pure Signorini–Coulomb, as the fixed point on the thresholds. Likewise with
//!   c0 = f_t0 = 0 from the start, and G_I, G_II → ∞ is a joint that never softens.
//!
//! ## Stability of softening, and what the staggered loop does when it fails
//!
//! A joint of slip δ under a body of shear stiffness k_b (Pa/m: for a block of height H and
//! shear modulus G sheared by its top, `k_b = G / H`), the top driven by Δ (displacement
//! control): equilibrium `k_b (Δ − δ) = c(δ) + μσ`. It has a unique solution δ(Δ), continuous
//! in Δ, if and only if `k_b > max |dc/dδ| = c0² / G_II` (at the peak); otherwise the
//! equilibrium curve snaps back (the τ–δ curve falls faster than the body unloads) and
//! displacement control cannot follow it. In tension the same holds with `k_b = E' / H` (E' the
//! constrained modulus) and `f_t0² / G_I`: [`CohesiveJoint::critical_stiffness`].
//!
//! The staggered loop is the fixed point `δ ← F(δ) = Δ − (c(δ) + μσ) / k_b` (when slipping),
//! started from the committed slip. F is increasing (c decreases) with slope
//! `ρ = c0 c(ξ) / (G_II k_b)`, so the iteration is monotone and converges to the *first*
//! equilibrium beyond the start, where necessarily ρ ≤ 1:
//! - stable softening (`k_b > c0²/G_II`): that is the unique equilibrium; the loop converges
//!   linearly at rate ρ < 1 (about ρ ≤ 0.9 for its 200 iterations to reach 1e-10);
//! - snap-back (`k_b < c0²/G_II`): past the peak the loop still converges, to the next stable
//!   equilibrium down the curve: the slip *jumps* within one increment (the sudden slip of a
//!   rig without closed-loop control, the energy released dissipated in the jump), and the path
//!   goes on from there. The unit test `staggered_loop_jumps_past_a_snap_back` shows it
//!   (k_b = c0²/(2 G_II): a slip increment of 14.6 drive steps in one increment, every
//!   converged state an equilibrium on the curve with ρ ≤ 1).
//! - The loop is slow only near a limit point, where the landing equilibrium is tangent
//!   (ρ → 1): there its 200 iterations can run out, `Error::SolverDiverged` follows, and the
//!   load path halves the increment (which moves the increment's end off the tangency); at the
//!   smallest increment the path stops with its clear error.
//!
//! Following the unstable branch itself needs arc-length control (not implemented). In a mesh
//! the same holds mode by mode: k_b is the body's stiffness for the slip mode that softens, the
//! most compliant one (a uniform slip of the whole joint) being the one to check.
//!
//! ## Outputs
//!
//! `damage = 1 − e^(−ξ)`, which with the coupled softening is both `1 − c/c0` and `1 − f_t/f_t0`
//! (the fraction of the joint's strength lost); a joint without any strength (c0 = f_t0 = 0)
//! reports 1 (a crack from the start).
use super::{InterfaceLaw, InterfaceOutputs, InterfacePoint, PointFriction, PointModification, PointSolution};
use crate::scene::CohesiveJointSpec;

/// A cohesive–frictional joint (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveJoint {
    /// The initial cohesion c0 (Pa).
    pub cohesion: f64,
    /// The initial tensile strength f_t0 (Pa).
    pub tensile_strength: f64,
    /// The friction coefficient μ.
    pub mu: f64,
    /// The mode-I fracture energy G_I (J/m²); `f64::INFINITY`: no softening in tension.
    pub fracture_energy_tension: f64,
    /// The mode-II fracture energy G_II (J/m²); `f64::INFINITY`: no softening in shear.
    pub fracture_energy_shear: f64,
}

/// The index of κ_I (the largest opening) in a point's variables.
pub const LARGEST_OPENING: usize = 0;
/// The index of κ_II (the accumulated slip) in a point's variables.
pub const ACCUMULATED_SLIP: usize = 1;

/// `strength · κ / G`, 0 when κ = 0 (so that a zero strength or an infinite energy gives 0, and
/// G = 0 a brittle loss of the strength at the first opening or slip).
fn softening_term(strength: f64, kappa: f64, energy: f64) -> f64 {
    if kappa <= 0.0 || strength <= 0.0 {
        0.0
    } else {
        strength * kappa / energy
    }
}

impl CohesiveJoint {
    /// The law with the scene's parameters (validated by the scene: c0, f_t0, μ ≥ 0, G_I, G_II > 0).
    pub fn new(spec: &CohesiveJointSpec) -> Self {
        CohesiveJoint {
            cohesion: spec.cohesion,
            tensile_strength: spec.tensile_strength,
            mu: spec.mu,
            fracture_energy_tension: spec.fracture_energy_tension,
            fracture_energy_shear: spec.fracture_energy_shear,
        }
    }

    /// The softening variable ξ = f_t0 κ_I / G_I + c0 κ_II / G_II at a point with initial gap
    /// `gap` (κ_I counts at least the initial gap).
    pub fn softening(&self, gap: f64, state: &[f64]) -> f64 {
        let opening = state[LARGEST_OPENING].max(gap);
        softening_term(self.tensile_strength, opening, self.fracture_energy_tension)
            + softening_term(self.cohesion, state[ACCUMULATED_SLIP], self.fracture_energy_shear)
    }

    /// The current cohesion c and tensile strength f_t (Pa) for the softening variable ξ.
    pub fn strengths(&self, xi: f64) -> (f64, f64) {
        let remaining = (-xi).exp();
        (self.cohesion * remaining, self.tensile_strength * remaining)
    }

    /// The shear strength `max(0, c + μσ)` (Pa) at normal traction `t_n` (tension > 0).
    pub fn shear_strength(&self, cohesion: f64, t_n: f64) -> f64 {
        (cohesion - self.mu * t_n).max(0.0)
    }

    /// The τ–δ curve of a joint sheared at constant compression σ ≥ 0 with monotonic slip
    /// δ ≥ 0 from the intact state (and no opening): `c0 exp(−c0 δ / G_II) + μσ`, the oracle of
    /// the shear patch tests.
    pub fn shear_curve(&self, compression: f64, slip: f64) -> f64 {
        let (c, _) = self.strengths(softening_term(self.cohesion, slip, self.fracture_energy_shear));
        self.shear_strength(c, -compression)
    }

    /// The tension curve of a joint opened monotonically by `opening` ≥ 0 from the intact state
    /// (no slip): `f_t0 exp(−f_t0 o / G_I)`.
    pub fn tension_curve(&self, opening: f64) -> f64 {
        self.strengths(softening_term(self.tensile_strength, opening, self.fracture_energy_tension)).1
    }

    /// The stiffness k_b (Pa/m) a body must exceed for the softening to be stable under
    /// displacement control (module documentation): `max(c0² / G_II, f_t0² / G_I)`.
    pub fn critical_stiffness(&self) -> f64 {
        let shear = softening_term(self.cohesion, self.cohesion, self.fracture_energy_shear);
        let tension = softening_term(self.tensile_strength, self.tensile_strength, self.fracture_energy_tension);
        shear.max(tension)
    }
}

impl InterfaceLaw for CohesiveJoint {
    fn name(&self) -> &'static str {
        "cohesive_joint"
    }

    fn has_memory(&self) -> bool {
        true
    }

    fn initial(&self) -> Vec<f64> {
        vec![0.0, 0.0]
    }

    /// The joint's own μ governs its friction: the scene's contact friction is not used.
    fn modification(
        &self,
        point: &InterfacePoint,
        _friction: PointFriction,
        trial: &[f64],
        last: Option<&PointSolution>,
    ) -> PointModification {
        let w = point.weight;
        let (c, f_t) = self.strengths(self.softening(point.gap, trial));
        let normal_force = last.map_or(0.0, |s| s.force[0]);
        let threshold = (c * w - self.mu * normal_force).max(0.0);
        PointModification {
            compliance: [0.0; 2],
            stiffness: [0.0; 2],
            spring_offset: [0.0; 2],
            force_offset: [f_t * w, 0.0],
            contact: true,
            friction: PointFriction::Tresca(threshold),
        }
    }

    fn update(&self, _point: &InterfacePoint, committed: &[f64], solution: &PointSolution, _dt: f64) -> Vec<f64> {
        vec![
            committed[LARGEST_OPENING].max(solution.opening),
            committed[ACCUMULATED_SLIP] + solution.slip_increment.abs(),
        ]
    }

    /// The largest of, in units of the stress scale S = max(c0, f_t0, |t_N|, |τ|) and the
    /// length scale L = max(|o|, |Δs|, κ_I, κ_II, 10⁻⁶ w) (w the point's weight, a mesh
    /// length: the floor keeps round-off openings and slips of a bonded point from counting):
    /// - the normal complementarity `|min(o / L, (f_t − t_N) / S)|` (the cut-off, o ≥ 0, and the
    ///   crack open only at the strength);
    /// - the friction residual `|τ − clamp(τ − (S/L) Δs, −s, s)| / S`, s = max(0, c + μσ)
    ///   (Mohr–Coulomb, stick below the threshold, slip at it against τ);
    /// - the consistency of the variables with the update, `|κ_I − max(κ_I⁰, o)| / L` and
    ///   `|κ_II − κ_II⁰ − |Δs|| / L`.
    ///
    /// The strengths are those of the final variables.
    fn residual(
        &self,
        point: &InterfacePoint,
        committed: &[f64],
        state: &[f64],
        solution: &PointSolution,
        _dt: f64,
    ) -> f64 {
        let w = point.weight;
        let (c, f_t) = self.strengths(self.softening(point.gap, state));
        let t_n = solution.force[0] / w;
        let tau = solution.force[1] / w;
        let opening = solution.opening;
        let slip = solution.slip_increment;
        let mut stress =
            self.cohesion.max(self.tensile_strength).max(t_n.abs()).max(tau.abs()).max(point.traction_scale);
        if stress == 0.0 {
            stress = 1.0;
        }
        let length = opening
            .abs()
            .max(slip.abs())
            .max(state[LARGEST_OPENING].abs())
            .max(state[ACCUMULATED_SLIP].abs())
            .max(point.displacement_scale)
            .max(1e-6 * w);
        let normal = (opening / length).min((f_t - t_n) / stress).abs();
        let s = self.shear_strength(c, t_n);
        let friction = (tau - (tau - stress / length * slip).clamp(-s, s)).abs() / stress;
        let largest_opening = (state[LARGEST_OPENING] - committed[LARGEST_OPENING].max(opening)).abs() / length;
        let accumulated_slip = (state[ACCUMULATED_SLIP] - committed[ACCUMULATED_SLIP] - slip.abs()).abs() / length;
        normal.max(friction).max(largest_opening).max(accumulated_slip)
    }

    fn outputs(&self, state: &[f64]) -> InterfaceOutputs {
        let damage = if self.cohesion > 0.0 || self.tensile_strength > 0.0 {
            1.0 - (-self.softening(0.0, state)).exp()
        } else {
            1.0
        };
        InterfaceOutputs { adhesion: None, damage: Some(damage) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// OOFEM's illustration of the Lourenço–Rots model (c0 = 0.8 MPa, G_II = 0.05 N/mm,
    /// f_t0 = 0.2 MPa, G_I = 0.018 N/mm), μ = 0.75.
    fn masonry() -> CohesiveJoint {
        CohesiveJoint::new(&CohesiveJointSpec {
            cohesion: 0.8e6,
            tensile_strength: 0.2e6,
            mu: 0.75,
            fracture_energy_tension: 18.0,
            fracture_energy_shear: 50.0,
        })
    }

    fn point(weight: f64) -> InterfacePoint {
        InterfacePoint { weight, gap: 0.0, slip_before: 0.0, traction_scale: 0.0, displacement_scale: 0.0 }
    }

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance * b.abs().max(1e-300)
    }

    #[test]
    fn softening_matches_the_hand_computation() {
        let joint = masonry();
        // κ_II = 0.1 mm: ξ = 0.8e6 · 1e-4 / 50 = 1.6; κ_I = 0.02 mm: ξ += 0.2e6 · 2e-5 / 18.
        let xi = joint.softening(0.0, &[2e-5, 1e-4]);
        let expected = 1.6 + 0.2e6 * 2e-5 / 18.0;
        assert!(close(xi, expected, 1e-14), "{xi} vs {expected}");
        let (c, f_t) = joint.strengths(xi);
        assert!(close(c, 0.8e6 * (-expected).exp(), 1e-14));
        assert!(close(f_t, 0.2e6 * (-expected).exp(), 1e-14));
        // The coupled softening keeps f_t / c = f_t0 / c0 (Lourenço–Rots isotropic softening).
        assert!(close(f_t / c, 0.25, 1e-14));
        // An initial gap counts as an opening already reached.
        assert!(close(joint.softening(3e-5, &[2e-5, 0.0]), 0.2e6 * 3e-5 / 18.0, 1e-14));
        // The curves of the patch tests.
        assert!(close(joint.shear_curve(0.6e6, 1e-4), 0.8e6 * (-1.6f64).exp() + 0.75 * 0.6e6, 1e-14));
        assert!(close(joint.tension_curve(1e-4), 0.2e6 * (-0.2e6 * 1e-4 / 18.0f64).exp(), 1e-14));
        assert!(close(joint.critical_stiffness(), 0.8e6 * 0.8e6 / 50.0, 1e-14));
    }

    /// The area under the softening curves is the fracture energy (trapezoidal rule on a fine
    /// grid to 40 characteristic lengths): the exponentials are normalised as L&R's.
    #[test]
    fn softening_curves_dissipate_the_fracture_energies() {
        let joint = masonry();
        let area = |f: &dyn Fn(f64) -> f64, length: f64| {
            let n = 400_000;
            let h = 40.0 * length / n as f64;
            (0..n).map(|i| 0.5 * h * (f(i as f64 * h) + f((i + 1) as f64 * h))).sum::<f64>()
        };
        let mode_two = area(&|d| joint.shear_curve(0.0, d), 50.0 / 0.8e6);
        let mode_one = area(&|o| joint.tension_curve(o), 18.0 / 0.2e6);
        assert!(close(mode_two, 50.0, 1e-8), "G_II: {mode_two}");
        assert!(close(mode_one, 18.0, 1e-8), "G_I: {mode_one}");
        // Residual friction: at constant σ the curve tends to μσ.
        assert!(close(joint.shear_curve(0.5e6, 1.0), 0.75 * 0.5e6, 1e-12));
    }

    #[test]
    fn update_is_the_largest_opening_and_the_accumulated_slip() {
        let joint = masonry();
        let p = point(0.01);
        let solution = |opening: f64, slip_increment: f64| PointSolution {
            opening,
            slip: 0.0,
            slip_increment,
            force: [0.0; 2],
            contact_force: [0.0; 2],
        };
        assert_eq!(joint.update(&p, &[1e-5, 2e-5], &solution(3e-5, -4e-5), 1.0), vec![3e-5, 2e-5 + 4e-5]);
        assert_eq!(joint.update(&p, &[1e-5, 2e-5], &solution(0.5e-5, 1e-5), 1.0), vec![1e-5, 2e-5 + 1e-5]);
        // A closed crack (opening 0, round-off below) keeps its largest opening.
        assert_eq!(joint.update(&p, &[1e-5, 0.0], &solution(-1e-20, 0.0), 1.0), vec![1e-5, 0.0]);
        assert_eq!(joint.initial(), vec![0.0, 0.0]);
        assert!(joint.has_memory());
        assert_eq!(joint.name(), "cohesive_joint");
    }

    #[test]
    fn modification_carries_the_tension_and_the_mohr_coulomb_threshold() {
        let joint = masonry();
        let w = 0.01;
        let p = point(w);
        let trial = [0.0, 1e-4];
        let (c, f_t) = (0.8e6 * (-1.6f64).exp(), 0.2e6 * (-1.6f64).exp());
        let last = PointSolution {
            opening: 0.0,
            slip: 1e-4,
            slip_increment: 1e-5,
            force: [-0.6e6 * w, 0.3e6 * w],
            contact_force: [-0.6e6 * w - f_t * w, 0.3e6 * w],
        };
        let m = joint.modification(&p, PointFriction::Coulomb(0.3), &trial, Some(&last));
        assert!(m.contact);
        assert_eq!(m.compliance, [0.0; 2]);
        assert_eq!(m.stiffness, [0.0; 2]);
        assert!(close(m.force_offset[0], f_t * w, 1e-14) && m.force_offset[1] == 0.0);
        match m.friction {
            PointFriction::Tresca(s) => assert!(close(s, (c + 0.75 * 0.6e6) * w, 1e-14), "{s}"),
            other => panic!("{other:?}"),
        }
        // In tension beyond the apex c/μ of the Coulomb cone the threshold is 0.
        let pulled = PointSolution { force: [2.0 * c / 0.75 * w, 0.0], ..last };
        assert_eq!(
            joint.modification(&p, PointFriction::None, &trial, Some(&pulled)).friction,
            PointFriction::Tresca(0.0)
        );
        // The first solve of a run (no last solution): the cohesion alone.
        match joint.modification(&p, PointFriction::None, &[0.0, 0.0], None).friction {
            PointFriction::Tresca(s) => assert!(close(s, 0.8e6 * w, 1e-14)),
            other => panic!("{other:?}"),
        }
    }

    /// G_I, G_II → ∞: nothing softens, whatever the opening and slip.
    #[test]
    fn infinite_fracture_energies_never_soften() {
        let joint =
            CohesiveJoint { fracture_energy_tension: f64::INFINITY, fracture_energy_shear: f64::INFINITY, ..masonry() };
        let state = [1.0, 10.0];
        assert_eq!(joint.softening(0.5, &state), 0.0);
        assert_eq!(joint.strengths(joint.softening(0.0, &state)), (0.8e6, 0.2e6));
        assert_eq!(joint.outputs(&state).damage, Some(0.0));
        assert_eq!(joint.critical_stiffness(), 0.0);
        let m = joint.modification(&point(0.02), PointFriction::None, &state, None);
        assert_eq!(m.force_offset, [0.2e6 * 0.02, 0.0]);
    }

    /// c0 = f_t0 = 0: the modification is plain Signorini with Tresca's threshold μ|rN| of the
    /// last normal force (Coulomb as the fixed point on the thresholds), damage 1.
    #[test]
    fn without_cohesion_the_joint_is_coulomb() {
        let joint = CohesiveJoint { cohesion: 0.0, tensile_strength: 0.0, ..masonry() };
        let last = PointSolution { force: [-300.0, 100.0], ..Default::default() };
        for state in [[0.0, 0.0], [1e-3, 5e-3]] {
            let m = joint.modification(&point(0.01), PointFriction::Coulomb(0.75), &state, Some(&last));
            assert_eq!(m, PointModification::plain(PointFriction::Tresca(0.75 * 300.0)));
            assert_eq!(joint.outputs(&state).damage, Some(1.0));
        }
    }

    #[test]
    fn damage_is_the_lost_fraction_of_the_strength() {
        let joint = masonry();
        let state = [18.0 / 0.2e6, 50.0 / 0.8e6]; // ξ = 1 + 1
        let damage = joint.outputs(&state).damage.unwrap();
        assert!(close(damage, 1.0 - (-2.0f64).exp(), 1e-14));
        let (c, f_t) = joint.strengths(joint.softening(0.0, &state));
        assert!(close(damage, 1.0 - c / 0.8e6, 1e-14) && close(damage, 1.0 - f_t / 0.2e6, 1e-14));
        assert_eq!(joint.outputs(&[0.0, 0.0]).damage, Some(0.0));
        assert_eq!(joint.outputs(&[0.0, 0.0]).adhesion, None);
    }

    /// The residual is round-off at exact states (slipping at the softened threshold, open at
    /// the strength, sticking below) and measures each violation by hand.
    #[test]
    fn residual_is_zero_at_exact_states_and_measures_violations() {
        let joint = masonry();
        let w = 0.01;
        let p = point(w);
        let sigma = 0.5e6;
        // Slipping by 2e-5 (direction +) from κ_II = 1e-4: τ = −(c + μσ) (opposes the slip).
        let state = [0.0, 1.2e-4];
        let (c, f_t) = joint.strengths(joint.softening(0.0, &state));
        let s = c + 0.75 * sigma;
        let slipping = PointSolution {
            opening: 0.0,
            slip: 1.2e-4,
            slip_increment: 2e-5,
            force: [-sigma * w, -s * w],
            contact_force: [-sigma * w - f_t * w, -s * w],
        };
        let committed = [0.0, 1e-4];
        assert!(joint.residual(&p, &committed, &state, &slipping, 1.0) < 1e-14);
        // The same with the wrong sign of τ (friction pushing the slip): ρ Δs / S with
        // ρ = S / L, L = κ_II = 1.2e-4: 1/6.
        let pushing = PointSolution { force: [-sigma * w, s * w], ..slipping };
        let r = joint.residual(&p, &committed, &state, &pushing, 1.0);
        assert!(close(r, 2e-5 / 1.2e-4, 1e-9), "{r}");
        // Sticking at 90 % of the threshold: exact; at 101 %: the excess 0.01 s / S.
        let stick = |fraction: f64| PointSolution {
            opening: 0.0,
            slip: 1e-4,
            slip_increment: 0.0,
            force: [-sigma * w, fraction * s * w],
            contact_force: [-sigma * w - f_t * w, fraction * s * w],
        };
        let kept = [0.0, 1e-4];
        let (c_kept, _) = joint.strengths(joint.softening(0.0, &kept));
        let s_kept = c_kept + 0.75 * sigma;
        let stick = |fraction: f64| PointSolution { force: [-sigma * w, fraction * s_kept * w], ..stick(fraction) };
        assert!(joint.residual(&p, &kept, &kept, &stick(0.9), 1.0) < 1e-15);
        let excess = joint.residual(&p, &kept, &kept, &stick(1.01), 1.0);
        let scale = 0.8e6f64.max(sigma).max(1.01 * s_kept);
        assert!(close(excess, 0.01 * s_kept / scale, 1e-9), "{excess}");
        // Variables inconsistent with the update (κ_II not advanced by the slip): |Δs| / L.
        let stale = joint.residual(&p, &committed, &committed, &slipping, 1.0);
        assert!(stale >= 2e-5 / 1.2e-4 * 0.999, "{stale}");
        // Open by 3e-5 at the strength of κ_I = 3e-5: exact; at a stale strength: O(1).
        let open_state = [3e-5, 0.0];
        let (_, f_open) = joint.strengths(joint.softening(0.0, &open_state));
        let open = PointSolution {
            opening: 3e-5,
            slip: 0.0,
            slip_increment: 0.0,
            force: [f_open * w, 0.0],
            contact_force: [0.0, 0.0],
        };
        assert!(joint.residual(&p, &[0.0, 0.0], &open_state, &open, 1.0) < 1e-15);
        let intact_strength = PointSolution { force: [0.2e6 * w, 0.0], ..open };
        let r = joint.residual(&p, &[0.0, 0.0], &open_state, &intact_strength, 1.0);
        assert!(close(r, (0.2e6 - f_open) / 0.8e6, 1e-9), "{r}");
        // Tension beyond the cut-off of a closed joint.
        let over = PointSolution { opening: 0.0, force: [1.1 * 0.2e6 * w, 0.0], ..open };
        let r = joint.residual(&p, &[0.0, 0.0], &[0.0, 0.0], &over, 1.0);
        assert!(close(r, 0.1 * 0.2e6 / 0.8e6, 1e-9), "{r}");
    }

    /// One point under a shear spring of stiffness k_b (Pa/m) driven by Δ (displacement
    /// control) at constant compression σ, with the staggered loop of the driver written out:
    /// the modification, the one-point Tresca solve in closed form, the update, until the
    /// variables stop changing (1e-10 relative, 200 iterations). Returns the slip and the shear
    /// traction at each Δ, or the Δ where the loop did not converge.
    fn drive(joint: &CohesiveJoint, k_b: f64, sigma: f64, drives: &[f64]) -> Result<Vec<(f64, f64)>, f64> {
        let w = 0.01;
        let p = point(w);
        let flexibility = 1.0 / (k_b * w); // u_T = W r_T + u_free
        let mut committed = joint.initial();
        let mut slip = 0.0;
        let mut last = PointSolution { force: [-sigma * w, 0.0], ..Default::default() };
        let mut out = Vec::new();
        for &delta in drives {
            let mut trial = committed.clone();
            let mut converged = false;
            for _ in 0..200 {
                let m = joint.modification(&p, PointFriction::None, &trial, Some(&last));
                let PointFriction::Tresca(s) = m.friction else { unreachable!() };
                let free = delta - slip; // the slip increment if no force acted
                let stick_force = -free / flexibility;
                let r_t = stick_force.clamp(-s, s);
                let increment = flexibility * r_t + free;
                last = PointSolution {
                    opening: 0.0,
                    slip: slip + increment,
                    slip_increment: increment,
                    force: [-sigma * w, r_t],
                    contact_force: [-sigma * w - m.force_offset[0], r_t],
                };
                let next = joint.update(&p, &committed, &last, 1.0);
                let change = (next[1] - trial[1]).abs();
                trial = next;
                if change <= 1e-10 * trial[1].abs().max(1e-12) {
                    converged = true;
                    break;
                }
            }
            if !converged {
                return Err(delta);
            }
            assert!(joint.residual(&p, &committed, &trial, &last, 1.0) < 1e-9);
            committed = trial;
            slip = last.slip;
            out.push((slip, -last.force[1] / w));
        }
        Ok(out)
    }

    /// The slip solving `k_b (Δ − δ) = c(δ) + μσ` in [lo, hi] by bisection (the function
    /// `k_b (Δ − δ) − c(δ) − μσ` changes sign once there).
    fn equilibrium_slip(joint: &CohesiveJoint, k_b: f64, sigma: f64, delta: f64, mut lo: f64, mut hi: f64) -> f64 {
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if k_b * (delta - mid) > joint.shear_curve(sigma, mid) {
                lo = mid
            } else {
                hi = mid
            }
        }
        0.5 * (lo + hi)
    }

    /// The staggered loop on one point follows the τ–δ curve when the body is stiff enough
    /// (k_b = 4 c0²/G_II: ρ ≤ 1/4): at each drive Δ the slip solves k_b (Δ − δ) = c(δ) + μσ
    /// (found here by bisection, independently), 0 before the peak.
    #[test]
    fn staggered_loop_follows_the_curve_when_stable() {
        let joint = masonry();
        let sigma = 0.1e6;
        let k_b = 4.0 * joint.critical_stiffness();
        let peak = 0.8e6 + 0.75 * sigma;
        let drives: Vec<f64> = (1..=60).map(|k| k as f64 * 0.2 * peak / k_b).collect();
        let path = drive(&joint, k_b, sigma, &drives).expect("stable softening converges");
        for (&delta, &(slip, tau)) in drives.iter().zip(&path) {
            let expected =
                if k_b * delta <= peak { 0.0 } else { equilibrium_slip(&joint, k_b, sigma, delta, 0.0, delta) };
            assert!((slip - expected).abs() <= 1e-9 * (50.0 / 0.8e6), "Δ = {delta}: slip {slip}, expected {expected}");
            let expected_tau = if expected == 0.0 { k_b * delta } else { joint.shear_curve(sigma, expected) };
            assert!(close(tau, expected_tau, 1e-8), "Δ = {delta}: τ {tau}, expected {expected_tau}");
        }
        assert!(path.last().unwrap().0 > 2.0 * 50.0 / 0.8e6, "the drive goes well past the peak");
    }

    /// A body too soft for the softening (k_b = c0²/(2 G_II)): past the peak the equilibrium
    /// curve snaps back, and the staggered loop (a monotone fixed-point iteration from the
    /// committed slip) converges to the first equilibrium beyond the start, which is a stable
    /// one (|dc/dδ| ≤ k_b there): the slip *jumps* within one increment, as a rig without
    /// closed-loop control snaps through. Every converged state is an equilibrium on the curve.
    #[test]
    fn staggered_loop_jumps_past_a_snap_back() {
        let joint = masonry();
        let sigma = 0.1e6;
        let k_b = 0.5 * joint.critical_stiffness();
        let peak = 0.8e6 + 0.75 * sigma;
        let step = 0.05 * peak / k_b;
        let drives: Vec<f64> = (1..=60).map(|k| k as f64 * step).collect();
        let path = drive(&joint, k_b, sigma, &drives).expect("the loop converges past the snap-back");
        let mut largest_jump = 0.0f64;
        let mut previous = 0.0;
        for (&delta, &(slip, tau)) in drives.iter().zip(&path) {
            largest_jump = largest_jump.max(slip - previous);
            previous = slip;
            if slip.abs() <= 1e-15 {
                // Stick (the slip is round-off).
                assert!(k_b * delta <= peak && close(tau, k_b * delta, 1e-9));
                continue;
            }
            assert!(close(tau, joint.shear_curve(sigma, slip), 1e-9), "Δ = {delta}: off the curve");
            assert!(close(tau, k_b * (delta - slip), 1e-7), "Δ = {delta}: not in equilibrium");
            let slope = 0.8e6 / 50.0 * (joint.shear_curve(sigma, slip) - 0.75 * sigma);
            assert!(slope <= k_b * (1.0 + 1e-9), "Δ = {delta}: an unstable equilibrium");
        }
        eprintln!("snap-back: largest slip increment {largest_jump:.3e} m for a drive step {step:.3e} m");
        assert!(largest_jump > 10.0 * step, "no jump: {largest_jump} vs the drive's step {step}");
    }
}
