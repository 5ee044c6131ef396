//! # The condensed contact problem modified by interface laws
//!
//! A law changes the condensed problem of [`crate::contact`] point by point
//! ([`PointModification`]); this module turns the base problem `u = W r + u_free` (dense `W`,
//! the load path's shift already subtracted from `u_free`) and one modification per point into a
//! standard [`CondensedProblem`] that every existing solver runs unchanged, maps its answer back
//! to the total force the interface transmits, and gives the law variables `(r', u')` of a
//! displacement obtained some other way (the field recomputed from `K u = f + Bᵀ r`) for the
//! independent check.
//!
//! ## Derivation
//!
//! Notation (module [`crate::interface_law`]): `C = diag c`, `D = diag k` (2m × 2m, in the
//! (N, T) frames), `a` the springs' rest offset, `o` the force offset, `g̃ = (g0, 0)` per point,
//! `z = u_free − g̃`, `v = u − g̃`. The interface transmits
//!
//! ```text
//!   r  = r' + o − D (v + a)                 (total force on the body)
//!   v  = W r + z                            (the body, condensed)
//!   v' = v + C r                            (the unilateral law acts on v' = u' − g̃ and r')
//! ```
//!
//! Eliminating `r`: `(I + W D) v = W r' + z + W o − W D a`. With
//! `W' = (I + W D)⁻¹ W = (W⁻¹ + D)⁻¹` (symmetric positive definite: the inverse of the sum of
//! two SPD/PSD matrices) and `(I + W D)⁻¹ = I − W' D` this is
//!
//! ```text
//!   v  = z + W' (r' + p),      p = o − D (z + a)
//!   r  = r' + o − D (v + a)
//! ```
//!
//! A law uses either series compliance or parallel springs on a component, never both
//! (`c_k k_k = 0`, checked), so `C D = 0` and `C r = C (r' + o)`:
//!
//! ```text
//!   v' = (W' + C) r' + z + W' p + C o
//! ```
//!
//! which is the standard problem on `W'' = W' + C` with the free displacement
//! `u_free'' = u_free + W' p + C o`, the same gaps, weights and the modifications' friction.
//! Series only (`D = 0`): `W'' = W + C`, `u_free'' = u_free + (W + C) o`; parallel only
//! (`C = 0`): `W'' = W'`.
//!
//! `W'` is computed without inverting `W` or forming `I + W D`: with the Cholesky factor
//! `W = L Lᵀ`, `W' = L (I + Lᵀ D L)⁻¹ Lᵀ = Yᵀ Y` where `M = I + Lᵀ D L = R Rᵀ` (Cholesky) and
//! `Y = R⁻¹ Lᵀ` (a triangular solve). `Yᵀ Y` is symmetric to the last bit and positive
//! semi-definite by construction, and the computation stays accurate as `D` grows (then
//! `W' → D⁻¹` on the sprung components, where forming `W − W D^½ (I + …)⁻¹ D^½ W` would cancel).
//!
//! ## Base force
//!
//! When the base problem's free displacement is that of a body held by weak springs (the
//! stabilisation of a body held by the contact alone, `contact_routes::condensed_route`), `z`
//! is the weak springs' large displacement and `v = z + W' p` cancels it to the answer's size:
//! the parallel springs lose `|z|/|v|` digits (1e4 on the bonded patch). The route then
//! solves with the free displacement under `f + Bᵀ r_b` (`r_b` the last total force), i.e.
//! `z_b = z + W r_b`; since `(I − W' D) W = W'`,
//! `v = z_b + W' (r' + o − r_b − D (z_b + a))`: the same formulas with `p = o − r_b − D (z_b + a)`,
//! the total force `r = r' + o − D (v + a)` unchanged.
//!
//! ## Points without a unilateral contact (`contact = false`)
//!
//! Their `r'` is zero, so they are removed from the solved problem: the standard problem is
//! posed on the points with `contact = true` only (`W''` and `u_free''` restricted to them),
//! which is exact — the eliminated points still enter through `W'` and `p`. With no such point
//! there is no contact solve at all (`r' = 0`). This is sounder than giving those points a huge
//! gap (which would change the residual scales and leave a threshold to choose).
//!
//! ## Friction
//!
//! The solvers take one [`FrictionLaw`] per problem. The points' frictions become: Coulomb if
//! some point has Coulomb (the others μ = 0), else Tresca if some point has Tresca, else none;
//! when Tresca and Coulomb points are mixed, Tresca with the Coulomb points' thresholds
//! `μ max(−rN', 0)` from the last iterate's contact force ([`unify_friction`]; zero at the first
//! solve): the staggered loop iterates them to a fixed point.
//!
//! ## The independent check
//!
//! From the total force `r` and a displacement `u` computed elsewhere, [`ModifiedProblem::law_variables`]
//! recomputes `r' = r − o + D (u − g̃ + a)` and `u' = u + C r`; the contact part is checked by
//! [`CondensedProblem::residuals_at`] of the solved problem on `(r', u')`, and the springs by
//! the largest `|r'|` at the points without contact relative to the force scale (it vanishes
//! when `u` is the displacement the springs were computed with).
use nalgebra::DMatrix;

use super::{PointFriction, PointModification};
use crate::contact::{CondensedProblem, ContactResiduals, Delassus, FrictionLaw, PointStatus, ResidualScale};
use crate::error::{Error, Result};

/// The condensed problem of a solve with interface laws (module documentation).
#[derive(Debug, Clone)]
pub struct ModifiedProblem {
    /// The number of contact points `m`.
    points: usize,
    /// The points with a unilateral contact, increasing: the solved problem's points.
    active: Vec<usize>,
    /// `W' = (W⁻¹ + D)⁻¹` on all `2m` unknowns.
    w_springs: DMatrix<f64>,
    /// `c`, `k`, `a`, `o` per unknown (2m each, N/T interleaved).
    compliance: Vec<f64>,
    stiffness: Vec<f64>,
    spring_offset: Vec<f64>,
    force_offset: Vec<f64>,
    /// `g̃`.
    gap_vector: Vec<f64>,
    /// `z = u_free − g̃` of the base problem, and `p = o − D (z + a)`.
    z: Vec<f64>,
    p: Vec<f64>,
    /// The standard problem on the active points (`None`: no point has a unilateral contact).
    solved: Option<CondensedProblem<'static>>,
    /// Whether some point has parallel springs (else `W' = W`).
    has_springs: bool,
}

/// The total and contact forces of an answer, and its displacement.
#[derive(Debug, Clone, PartialEq)]
pub struct ModifiedAnswer {
    /// `r`: what the interface transmits to the body (2m).
    pub force: Vec<f64>,
    /// `r'`: the unilateral contact force (2m; zero at the points without contact).
    pub contact_force: Vec<f64>,
    /// `u = W r + u_free` (2m, the base problem's displacement).
    pub displacement: Vec<f64>,
}

/// The independent check of an answer of the modified problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModifiedResiduals {
    /// The contact law on `(r', u')` at the points with contact (zero without any).
    pub contact: ContactResiduals,
    /// The largest `|r'|` at the points without contact, relative to the force scale.
    pub springs: f64,
}

impl ModifiedResiduals {
    /// The largest of the contact residuals and the springs' residual (`+∞` for NaN).
    pub fn worst(&self) -> f64 {
        let s = if self.springs.is_nan() { f64::INFINITY } else { self.springs };
        self.contact.worst().max(s)
    }

    /// Every component within `tolerance`.
    pub fn is_acceptable(&self, tolerance: f64) -> bool {
        self.contact.is_acceptable(tolerance) && self.springs.is_finite() && self.springs <= tolerance
    }
}

impl std::fmt::Display for ModifiedResiduals {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}; springs {:.2e}", self.contact, self.springs)
    }
}

/// The friction of each point as one [`FrictionLaw`] (module documentation): `frictions` per
/// point, `last_contact_force` the last iterate's `r'` (2m) for the thresholds of Coulomb points
/// mixed with Tresca points (zero if `None`).
pub fn unify_friction(frictions: &[PointFriction], last_contact_force: Option<&[f64]>) -> FrictionLaw {
    let coulomb = frictions.iter().any(|f| matches!(f, PointFriction::Coulomb(mu) if *mu > 0.0));
    let tresca = frictions.iter().any(|f| matches!(f, PointFriction::Tresca(s) if *s > 0.0));
    let normal = |i: usize| last_contact_force.map_or(0.0, |r| r[2 * i]);
    if coulomb && tresca {
        FrictionLaw::Tresca {
            threshold: frictions
                .iter()
                .enumerate()
                .map(|(i, f)| match *f {
                    PointFriction::None => 0.0,
                    PointFriction::Tresca(s) => s,
                    PointFriction::Coulomb(mu) => mu * (-normal(i)).max(0.0),
                })
                .collect(),
        }
    } else if coulomb {
        FrictionLaw::Coulomb {
            mu: frictions.iter().map(|f| if let PointFriction::Coulomb(mu) = *f { mu } else { 0.0 }).collect(),
        }
    } else if tresca {
        FrictionLaw::Tresca {
            threshold: frictions.iter().map(|f| if let PointFriction::Tresca(s) = *f { s } else { 0.0 }).collect(),
        }
    } else {
        FrictionLaw::None
    }
}

/// Whether Tresca and Coulomb points are mixed (the thresholds then follow the last iterate).
pub fn mixed_friction(frictions: &[PointFriction]) -> bool {
    frictions.iter().any(|f| matches!(f, PointFriction::Coulomb(mu) if *mu > 0.0))
        && frictions.iter().any(|f| matches!(f, PointFriction::Tresca(s) if *s > 0.0))
}

fn check_modification(i: usize, m: &PointModification) -> Result<()> {
    let bad = |what: &str, v: f64, rule: &str| {
        Err(Error::Usage(format!(
            "interface law at contact point {i}: the {what} is {v}; it must be finite and {rule}"
        )))
    };
    for k in 0..2 {
        let axis = ["normal", "tangential"][k];
        let (c, s) = (m.compliance[k], m.stiffness[k]);
        if !(c.is_finite() && c >= 0.0) {
            return bad(&format!("{axis} series compliance"), c, ">= 0");
        }
        if !(s.is_finite() && s >= 0.0) {
            return bad(&format!("{axis} spring stiffness"), s, ">= 0");
        }
        if !m.spring_offset[k].is_finite() {
            return bad(&format!("{axis} spring offset"), m.spring_offset[k], "a number");
        }
        if !m.force_offset[k].is_finite() {
            return bad(&format!("{axis} force offset"), m.force_offset[k], "a number");
        }
        if c > 0.0 && s > 0.0 {
            return Err(Error::Usage(format!(
                "interface law at contact point {i}: the {axis} component has both a series compliance ({c}) and a \
                 parallel spring ({s}); a law uses one or the other"
            )));
        }
    }
    match m.friction {
        PointFriction::Tresca(v) | PointFriction::Coulomb(v) if !(v.is_finite() && v >= 0.0) => {
            bad("friction threshold or coefficient", v, ">= 0")
        }
        _ => Ok(()),
    }
}

impl ModifiedProblem {
    /// The modified problem of `base` (dense `W`) with one modification per point;
    /// `last_contact_force` (2m, `r'` of the last iterate) gives the thresholds of Coulomb points
    /// mixed with Tresca points ([`unify_friction`]).
    pub fn new(
        base: &CondensedProblem,
        modifications: &[PointModification],
        last_contact_force: Option<&[f64]>,
    ) -> Result<Self> {
        Self::with_base_force(base, modifications, last_contact_force, None)
    }

    /// [`ModifiedProblem::new`] for a base problem whose free displacement already includes
    /// the response `W r_b` to a force `r_b` (2m, `base_force`): `z_b = z + W r_b`, and
    /// `v = z_b + W' (r' + o − r_b − D (z_b + a))` (module documentation, "Base force"); the
    /// answer's force is still the total `r`.
    pub fn with_base_force(
        base: &CondensedProblem,
        modifications: &[PointModification],
        last_contact_force: Option<&[f64]>,
        base_force: Option<&[f64]>,
    ) -> Result<Self> {
        let m = base.points();
        if let Some(r) = base_force {
            if r.len() != 2 * m || r.iter().any(|v| !v.is_finite()) {
                return Err(Error::Usage(format!(
                    "interface laws: the base force has {} entries (expected {}) or a non-finite one",
                    r.len(),
                    2 * m
                )));
            }
        }
        if modifications.len() != m {
            return Err(Error::Usage(format!(
                "interface laws: {} point modifications for {m} contact points",
                modifications.len()
            )));
        }
        if let Some(r) = last_contact_force {
            if r.len() != 2 * m {
                return Err(Error::Usage(format!(
                    "interface laws: the last contact force has {} entries, expected {}",
                    r.len(),
                    2 * m
                )));
            }
        }
        for (i, md) in modifications.iter().enumerate() {
            check_modification(i, md)?;
        }
        let w = base.delassus().as_dense().ok_or_else(|| {
            Error::Usage(
                "interface laws need the entries of the flexibility W (Delassus::Dense): the modified problem is \
                 formed from them"
                    .into(),
            )
        })?;
        let per_unknown =
            |f: &dyn Fn(&PointModification) -> [f64; 2]| -> Vec<f64> { modifications.iter().flat_map(f).collect() };
        let compliance = per_unknown(&|md| md.compliance);
        let stiffness = per_unknown(&|md| md.stiffness);
        let spring_offset = per_unknown(&|md| md.spring_offset);
        let force_offset = per_unknown(&|md| md.force_offset);
        let has_springs = stiffness.iter().any(|&k| k > 0.0);
        let w_springs = if has_springs { with_parallel_springs(w, &stiffness)? } else { w.clone() };
        let mut gap_vector = vec![0.0; 2 * m];
        for (i, g) in base.gap().iter().enumerate() {
            gap_vector[2 * i] = *g;
        }
        let z: Vec<f64> = base.free_displacement().iter().zip(&gap_vector).map(|(u, g)| u - g).collect();
        let base_at = |k: usize| base_force.map_or(0.0, |r| r[k]);
        let p: Vec<f64> =
            (0..2 * m).map(|k| force_offset[k] - base_at(k) - stiffness[k] * (z[k] + spring_offset[k])).collect();
        let active: Vec<usize> = (0..m).filter(|&i| modifications[i].contact).collect();
        let mut problem = ModifiedProblem {
            points: m,
            active,
            w_springs,
            compliance,
            stiffness,
            spring_offset,
            force_offset,
            gap_vector,
            z,
            p,
            solved: None,
            has_springs,
        };
        problem.solved = problem.solved_problem(base, modifications, last_contact_force)?;
        Ok(problem)
    }

    /// `W'' = W' + C` and `u_free'' = u_free + W' p + C o` on the active points.
    fn solved_problem(
        &self,
        base: &CondensedProblem,
        modifications: &[PointModification],
        last_contact_force: Option<&[f64]>,
    ) -> Result<Option<CondensedProblem<'static>>> {
        if self.active.is_empty() {
            return Ok(None);
        }
        let n = 2 * self.active.len();
        let unknowns: Vec<usize> = self.active.iter().flat_map(|&i| [2 * i, 2 * i + 1]).collect();
        let wp = self.w_springs_times(&self.p);
        let mut w = DMatrix::<f64>::zeros(n, n);
        for (a, &ka) in unknowns.iter().enumerate() {
            for (b, &kb) in unknowns.iter().enumerate() {
                w[(a, b)] = self.w_springs[(ka, kb)];
            }
            w[(a, a)] += self.compliance[ka];
        }
        // u_free'' = u_free + W' p + C o (C o: the series law acts on u + C r with the total r).
        let free: Vec<f64> = unknowns
            .iter()
            .map(|&k| base.free_displacement()[k] + wp[k] + self.compliance[k] * self.force_offset[k])
            .collect();
        let gap: Vec<f64> = self.active.iter().map(|&i| base.gap()[i]).collect();
        let weights: Vec<f64> = self.active.iter().map(|&i| base.weights()[i]).collect();
        let frictions: Vec<PointFriction> = self.active.iter().map(|&i| modifications[i].friction).collect();
        let last: Option<Vec<f64>> = last_contact_force.map(|r| self.restrict(r));
        let friction = unify_friction(&frictions, last.as_deref());
        CondensedProblem::new(Delassus::Dense(w), free, gap, friction, Some(weights)).map(Some)
    }

    fn w_springs_times(&self, x: &[f64]) -> Vec<f64> {
        let n = x.len();
        (0..n).map(|i| (0..n).map(|j| self.w_springs[(i, j)] * x[j]).sum()).collect()
    }

    /// The standard problem the solvers run on (`None`: no point has a unilateral contact,
    /// `r' = 0` everywhere).
    pub fn problem(&self) -> Option<&CondensedProblem<'static>> {
        self.solved.as_ref()
    }

    /// The points of the solved problem (those with a unilateral contact), increasing.
    pub fn active_points(&self) -> &[usize] {
        &self.active
    }

    /// The entries of the active points of a vector of all points (2m → 2 per active point).
    pub fn restrict(&self, all: &[f64]) -> Vec<f64> {
        self.active.iter().flat_map(|&i| [all[2 * i], all[2 * i + 1]]).collect()
    }

    /// A vector of the active points extended to all points with zeros.
    pub fn expand(&self, active: &[f64]) -> Vec<f64> {
        let mut all = vec![0.0; 2 * self.points];
        for (a, &i) in self.active.iter().enumerate() {
            all[2 * i] = active[2 * a];
            all[2 * i + 1] = active[2 * a + 1];
        }
        all
    }

    /// The answer of the original equations from the contact force `r'` of all points (2m,
    /// zero at the points without contact): `v = z + W' (r' + p)`, `r = r' + o − D (v + a)`,
    /// `u = v + g̃`.
    pub fn answer(&self, contact_force: &[f64]) -> ModifiedAnswer {
        let shifted: Vec<f64> = contact_force.iter().zip(&self.p).map(|(r, p)| r + p).collect();
        let wr = self.w_springs_times(&shifted);
        let v: Vec<f64> = self.z.iter().zip(&wr).map(|(z, w)| z + w).collect();
        let force: Vec<f64> = (0..2 * self.points)
            .map(|k| contact_force[k] + self.force_offset[k] - self.stiffness[k] * (v[k] + self.spring_offset[k]))
            .collect();
        let displacement = v.iter().zip(&self.gap_vector).map(|(v, g)| v + g).collect();
        ModifiedAnswer { force, contact_force: contact_force.to_vec(), displacement }
    }

    /// The law variables of a total force `r` and a displacement `u` (of the base problem,
    /// computed elsewhere): `r' = r − o + D (u − g̃ + a)`, `u' = u + C r`.
    pub fn law_variables(&self, force: &[f64], displacement: &[f64]) -> (Vec<f64>, Vec<f64>) {
        let contact_force = (0..2 * self.points)
            .map(|k| {
                force[k] - self.force_offset[k]
                    + self.stiffness[k] * (displacement[k] - self.gap_vector[k] + self.spring_offset[k])
            })
            .collect();
        let law_displacement = (0..2 * self.points).map(|k| displacement[k] + self.compliance[k] * force[k]).collect();
        (contact_force, law_displacement)
    }

    /// The independent check of a total force `r` against a displacement `u` computed
    /// elsewhere (module documentation).
    pub fn residuals_at(&self, force: &[f64], displacement: &[f64]) -> Result<ModifiedResiduals> {
        self.check_length(force, "force")?;
        self.check_length(displacement, "displacement")?;
        let (rc, uc) = self.law_variables(force, displacement);
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let contact = match &self.solved {
            Some(problem) => problem.residuals_at(&self.restrict(&rc), &self.restrict(&uc))?,
            None => ContactResiduals {
                max_penetration: 0.0,
                max_wrong_sign_pressure: 0.0,
                max_cone_violation: 0.0,
                normal_complementarity: 0.0,
                tangential_complementarity: 0.0,
                scale: ResidualScale { force: 1.0, displacement: 1.0 },
                worst_point: 0,
            },
        };
        let mut scale = largest(force).max(largest(&rc));
        if self.solved.is_some() {
            scale = scale.max(contact.scale.force);
        }
        if scale.is_nan() || scale <= 0.0 {
            scale = 1.0;
        }
        let mut springs = 0.0f64;
        for i in (0..self.points).filter(|i| self.active.binary_search(i).is_err()) {
            springs = springs.max(rc[2 * i].abs().max(rc[2 * i + 1].abs()) / scale);
        }
        if springs.is_nan() {
            springs = f64::INFINITY;
        }
        Ok(ModifiedResiduals { contact, springs })
    }

    /// Per point: the active points' status from `(r', u')`; a point without contact is held by
    /// its springs and reported as sticking.
    pub fn status_at(&self, force: &[f64], displacement: &[f64]) -> Result<Vec<PointStatus>> {
        self.check_length(force, "force")?;
        self.check_length(displacement, "displacement")?;
        let mut status = vec![PointStatus::Stick; self.points];
        if let Some(problem) = &self.solved {
            let (rc, uc) = self.law_variables(force, displacement);
            for (a, s) in problem.status_at(&self.restrict(&rc), &self.restrict(&uc))?.into_iter().enumerate() {
                status[self.active[a]] = s;
            }
        }
        Ok(status)
    }

    /// Whether some point has parallel springs.
    pub fn has_springs(&self) -> bool {
        self.has_springs
    }

    fn check_length(&self, v: &[f64], what: &str) -> Result<()> {
        if v.len() != 2 * self.points {
            return Err(Error::Usage(format!(
                "interface laws: the {what} has {} entries, expected {}",
                v.len(),
                2 * self.points
            )));
        }
        Ok(())
    }
}

/// `W' = (W⁻¹ + D)⁻¹ = L (I + Lᵀ D L)⁻¹ Lᵀ` (module documentation), `D = diag(stiffness)`.
fn with_parallel_springs(w: &DMatrix<f64>, stiffness: &[f64]) -> Result<DMatrix<f64>> {
    let n = w.nrows();
    let not_spd = || {
        Error::Usage(
            "interface laws: the flexibility W is not positive definite (its Cholesky factorisation failed)".into(),
        )
    };
    let l = w.clone().cholesky().ok_or_else(not_spd)?.l();
    // M = I + Lᵀ D L.
    let mut dl = l.clone();
    for (i, k) in stiffness.iter().enumerate() {
        dl.row_mut(i).scale_mut(*k);
    }
    let mut mm = l.transpose() * dl;
    for i in 0..n {
        mm[(i, i)] += 1.0;
    }
    // Exactly symmetric before its factorisation.
    let mm = 0.5 * (&mm + mm.transpose());
    let r = mm.cholesky().ok_or_else(not_spd)?.l();
    let y = r.solve_lower_triangular(&l.transpose()).ok_or_else(not_spd)?;
    let wp = y.transpose() * &y;
    Ok(0.5 * (&wp + wp.transpose()))
}
