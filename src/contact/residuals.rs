//! Residuals of a candidate contact force, computed from the force alone.
//!
//! With `u = W r + u_free`, the force scale `F` and displacement scale `U` of
//! [`ResidualScale`], the threshold `s_i` (Tresca: given; Coulomb: `μ_i max(−rN_i, 0)`;
//! frictionless: 0) and `c = F / U`, per point `i`:
//!
//! ```text
//!   penetration                (uN_i − g0_i)₊ / U
//!   wrong-sign pressure        (rN_i)₊ / F
//!   cone violation             (|rT_i| − s_i)₊ / F
//!   normal complementarity     min(|rN_i| / F, |uN_i − g0_i| / U)
//!   tangential complementarity |rT_i − clamp(rT_i − c uT_i, −s_i, s_i)| / F
//! ```
//!
//! Each reported component is the maximum over the points. All five vanish exactly at a
//! solution. The normal complementarity is zero iff the force or the gap is zero (with the
//! first two rows, that is Signorini). The tangential one is the natural-map residual of the
//! friction law (Alart & Curnier 1991): a sticking point (`|rT| < s`) must have `uT = 0`
//! (violation `|uT|/U`); a point on the threshold must slip opposite to its force
//! (violation `min(|uT|/U, 2 s/F)` when `uT` has the sign of `rT`). For a frictionless point
//! it measures `|rT|/F`.
//!
//! Scales: `U = max(‖u_free‖∞, ‖u‖∞, max(−g0, 0))`, or `‖g0‖∞` if that is zero, or 1;
//! `F = max(‖r‖∞, U / max_i W_ii)` (the second term: the force that produces a displacement
//! `U` at the most flexible entry, so that a zero force has a meaningful scale), or 1 if zero.
use std::fmt;

use super::CondensedProblem;

/// What the residuals are relative to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidualScale {
    /// Force scale `F` (same unit as the contact forces).
    pub force: f64,
    /// Displacement scale `U` (same unit as the displacements and gaps).
    pub displacement: f64,
}

/// The five relative residuals of a candidate force (see the module documentation of
/// `contact::residuals` for the formulas). All are `≥ 0` and vanish at a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactResiduals {
    /// Largest penetration `(uN − g0)₊ / U`.
    pub max_penetration: f64,
    /// Largest pulling normal force `(rN)₊ / F`.
    pub max_wrong_sign_pressure: f64,
    /// Largest excess over the friction threshold `(|rT| − s)₊ / F`.
    pub max_cone_violation: f64,
    /// Largest `min(|rN| / F, |uN − g0| / U)`: a point with both force and gap.
    pub normal_complementarity: f64,
    /// Includes the slip direction: sticking points must have `uT = 0`, slipping points `uT`
    /// opposite to `rT`.
    pub tangential_complementarity: f64,
    /// The scales `F` and `U` the residuals are relative to.
    pub scale: ResidualScale,
    /// Contact point where the worst component is reached.
    pub worst_point: usize,
}

impl ContactResiduals {
    fn components(&self) -> [(&'static str, f64); 5] {
        [
            ("penetration", self.max_penetration),
            ("wrong-sign pressure", self.max_wrong_sign_pressure),
            ("cone violation", self.max_cone_violation),
            ("normal complementarity", self.normal_complementarity),
            ("tangential complementarity", self.tangential_complementarity),
        ]
    }

    /// The largest component (`+∞` if any is not a number).
    pub fn worst(&self) -> f64 {
        self.components().iter().map(|&(_, v)| if v.is_nan() { f64::INFINITY } else { v }).fold(0.0, f64::max)
    }

    /// Name of the largest component.
    pub fn worst_component(&self) -> &'static str {
        let mut best = ("penetration", -1.0);
        for (name, v) in self.components() {
            let v = if v.is_nan() { f64::INFINITY } else { v };
            if v > best.1 {
                best = (name, v);
            }
        }
        best.0
    }

    /// Every component within `tolerance` (and finite).
    pub fn is_acceptable(&self, tolerance: f64) -> bool {
        self.components().iter().all(|&(_, v)| v.is_finite() && v <= tolerance)
    }
}

impl fmt::Display for ContactResiduals {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.components().iter().map(|(name, v)| format!("{name} {v:.2e}")).collect();
        write!(
            f,
            "{}; worst: {} at contact point {}; relative to force {:.3e}, displacement {:.3e}",
            parts.join(", "),
            self.worst_component(),
            self.worst_point,
            self.scale.force,
            self.scale.displacement
        )
    }
}

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, |acc, x| if x.is_nan() { f64::INFINITY } else { acc.max(x.abs()) })
}

impl ResidualScale {
    /// Scales for full-space solvers (no W): the largest contact force, and the largest
    /// displacement of the whole body or gap — not the contact displacements alone, which are
    /// round-off for a body resting on the obstacle. Zero scales become 1.
    pub fn from_field(force: &[f64], body_displacement: &[f64], gap: &[f64]) -> Self {
        let largest = |v: &mut dyn Iterator<Item = &f64>| v.fold(0.0f64, |a, x| a.max(x.abs()));
        let nonzero = |x: f64| if x == 0.0 { 1.0 } else { x };
        ResidualScale {
            force: nonzero(largest(&mut force.iter())),
            displacement: nonzero(largest(&mut body_displacement.iter().chain(gap.iter()))),
        }
    }
}

/// The scales of the residuals at `(r, u)`.
pub(crate) fn scale(problem: &CondensedProblem, r: &[f64], u: &[f64]) -> ResidualScale {
    let mut displacement = max_abs(problem.free_displacement().iter().copied())
        .max(max_abs(u.iter().copied()))
        .max(max_abs(problem.gap().iter().map(|g| g.min(0.0))));
    if displacement == 0.0 {
        displacement = max_abs(problem.gap().iter().copied());
    }
    if displacement == 0.0 {
        displacement = 1.0;
    }
    let max_diagonal = problem.diagonal().iter().copied().fold(0.0, f64::max);
    let mut force = max_abs(r.iter().copied()).max(displacement / max_diagonal);
    if !force.is_finite() {
        force = f64::INFINITY;
    } else if force <= 0.0 {
        force = 1.0;
    }
    ResidualScale { force, displacement }
}

/// The residuals at `(r, u)` with `u = W r + u_free` supplied by the caller.
pub(crate) fn compute(problem: &CondensedProblem, r: &[f64], u: &[f64]) -> ContactResiduals {
    let scale = scale(problem, r, u);
    evaluate(r, u, problem.gap(), &|i, rn| problem.threshold_at(i, rn), scale)
}

/// The five residuals of forces `r` and relative displacements `u` (both `(N_i, T_i)`
/// interleaved) against the gaps, the friction threshold `threshold(i, rN_i)` and the given
/// scales — for callers that have no flexibility operator (full-space solvers).
pub fn evaluate(
    r: &[f64],
    u: &[f64],
    gap: &[f64],
    threshold: &dyn Fn(usize, f64) -> f64,
    scale: ResidualScale,
) -> ContactResiduals {
    let (f_scale, u_scale) = (scale.force, scale.displacement);
    let c = f_scale / u_scale;
    let mut out = ContactResiduals {
        max_penetration: 0.0,
        max_wrong_sign_pressure: 0.0,
        max_cone_violation: 0.0,
        normal_complementarity: 0.0,
        tangential_complementarity: 0.0,
        scale,
        worst_point: 0,
    };
    let mut worst = -1.0;
    let nan_to_inf = |v: f64| if v.is_nan() { f64::INFINITY } else { v };
    for i in 0..gap.len() {
        let (rn, rt) = (r[2 * i], r[2 * i + 1]);
        let (un, ut) = (u[2 * i], u[2 * i + 1]);
        let d = un - gap[i];
        let s = threshold(i, rn);
        let penetration = nan_to_inf(d.max(0.0) / u_scale);
        let wrong_sign = nan_to_inf(rn.max(0.0) / f_scale);
        let cone = nan_to_inf((rt.abs() - s).max(0.0) / f_scale);
        let normal = nan_to_inf((rn.abs() / f_scale).min(d.abs() / u_scale));
        let tangential = nan_to_inf((rt - (rt - c * ut).clamp(-s, s)).abs() / f_scale);
        out.max_penetration = out.max_penetration.max(penetration);
        out.max_wrong_sign_pressure = out.max_wrong_sign_pressure.max(wrong_sign);
        out.max_cone_violation = out.max_cone_violation.max(cone);
        out.normal_complementarity = out.normal_complementarity.max(normal);
        out.tangential_complementarity = out.tangential_complementarity.max(tangential);
        let here = penetration.max(wrong_sign).max(cone).max(normal).max(tangential);
        if here > worst {
            worst = here;
            out.worst_point = i;
        }
    }
    out
}
