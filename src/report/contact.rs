//! What the primal contact route reports (`report.json` → `contact`): the solver's history,
//! the point counts and resultants, the closed zones, and the independent check's residuals.
use crate::contact::PointStatus;

#[derive(Debug, Clone, serde::Serialize)]
/// The independent check of a contact solution: the five relative residuals of
/// [`crate::contact::ContactResiduals`] (formulas in `contact::residuals`), computed from the
/// contact forces and the displacement of the field solve, each ≥ 0 and 0 at an exact solution.
pub struct ContactResidualsReport {
    /// Largest penetration into the obstacle, relative to the displacement scale.
    pub max_penetration: f64,
    /// Largest pulling (positive) normal contact force, relative to the force scale.
    pub max_wrong_sign_pressure: f64,
    /// Largest excess of a tangential force over its friction threshold, relative to the force
    /// scale.
    pub max_cone_violation: f64,
    /// Largest violation of "force or gap is zero" at a point.
    pub normal_complementarity: f64,
    /// Largest violation of the friction law: a sticking point that moves, or a slipping point that
    /// does not slip against its force (the natural-map residual).
    pub tangential_complementarity: f64,
    /// The force scale `F` the residuals are relative to (N per unit thickness).
    pub force_scale: f64,
    /// The displacement scale `U` the residuals are relative to (m).
    pub displacement_scale: f64,
}

impl From<&crate::contact::ContactResiduals> for ContactResidualsReport {
    fn from(r: &crate::contact::ContactResiduals) -> Self {
        ContactResidualsReport {
            max_penetration: r.max_penetration,
            max_wrong_sign_pressure: r.max_wrong_sign_pressure,
            max_cone_violation: r.max_cone_violation,
            normal_complementarity: r.normal_complementarity,
            tangential_complementarity: r.tangential_complementarity,
            force_scale: r.scale.force,
            displacement_scale: r.scale.displacement,
        }
    }
}

#[derive(Debug, Clone, serde::Serialize)]
/// What a contact solve reports (`report.json` under `contact`).
pub struct ContactReport {
    /// The contact part (with several bodies, the contact parts' names).
    pub part: String,
    /// The friction law, e.g. `"Coulomb, mu = 0.3"`.
    pub friction: String,
    /// The contact solver as run, with its linear solver (and a fallback, if one was taken).
    pub solver: String,
    /// Iterations of the contact solver.
    pub iterations: usize,
    /// Status changes (open/stick/slip) per iteration of the contact solver.
    pub status_changes: Vec<usize>,
    /// The contact solver's residual after each iteration (relative; what `convergence.svg`
    /// plots).
    pub residual_history: Vec<f64>,
    /// What happened on the way (fallbacks, stabilisation), in words.
    pub notes: Vec<String>,
    /// Contact points (nodes of the contact part that can move).
    pub points: usize,
    /// Points without contact force.
    pub open: usize,
    /// Points in contact, sticking.
    pub stick: usize,
    /// Points in contact, slipping (every closed point of frictionless contact).
    pub slip: usize,
    /// Resultant of the contact forces on the body in x and y (N per unit thickness).
    pub resultant: [f64; 2],
    /// Sums of the normal and tangential contact forces (local frames).
    pub normal_resultant: f64,
    /// Sum of the tangential contact forces in the points' local frames (N per unit thickness).
    pub tangential_resultant: f64,
    /// Extent of the closed contact zone along the first point's tangent: [min, max] of x·t.
    /// Kept for compatibility; `zones` is right for every obstacle.
    pub zone: Option<[f64; 2]>,
    /// The largest nodal contact pressure and where it is.
    pub peak_pressure: Option<super::contact_zones::PeakPressure>,
    /// Each connected run of closed points, as an interval of arc length along the part.
    pub zones: Vec<super::contact_zones::ClosedZone>,
    /// Independent check: relative residuals of (r, B u) with u from the field solve.
    pub residuals: ContactResidualsReport,
    /// Resultant of the stabilisation springs at the last proximal iteration (0 when none
    /// were needed) and the number of proximal iterations.
    pub stabilisation_force: [f64; 2],
    /// Proximal iterations with stabilisation springs (0 when none were needed).
    pub stabilisation_iterations: usize,
    /// The contact solver's iterations in each proximal iteration (their sum is `iterations`);
    /// empty when no springs were needed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stabilisation_step_iterations: Vec<usize>,
    /// Linear solves with the factorised stiffness (1 free + columns of W + 1 final).
    pub linear_solves: usize,
}

/// The contact solution of the primal route.
pub struct ContactOutcome {
    /// Contact force per point, `[rN_i, rT_i]` for each point i in turn (2 per point; N per unit
    /// thickness; `rN ≤ 0` in contact).
    pub force: Vec<f64>,
    /// Open, stick or slip, per contact point.
    pub status: Vec<PointStatus>,
    /// The summary written to `report.json`.
    pub report: ContactReport,
}
