//! What the primal contact route reports (`report.json` → `contact`): the solver's history,
//! the point counts and resultants, the closed zones, and the independent check's residuals.
use crate::contact::PointStatus;

#[derive(Debug, Clone, serde::Serialize)]
pub struct ContactResidualsReport {
    pub max_penetration: f64,
    pub max_wrong_sign_pressure: f64,
    pub max_cone_violation: f64,
    pub normal_complementarity: f64,
    pub tangential_complementarity: f64,
    pub force_scale: f64,
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
pub struct ContactReport {
    pub part: String,
    pub friction: String,
    pub solver: String,
    pub iterations: usize,
    /// Status changes (open/stick/slip) per iteration of the contact solver.
    pub status_changes: Vec<usize>,
    /// The contact solver's residual after each iteration (relative; what `convergence.svg`
    /// plots).
    pub residual_history: Vec<f64>,
    pub notes: Vec<String>,
    pub points: usize,
    pub open: usize,
    pub stick: usize,
    pub slip: usize,
    /// Resultant of the contact forces on the body in x and y (N per unit thickness).
    pub resultant: [f64; 2],
    /// Sums of the normal and tangential contact forces (local frames).
    pub normal_resultant: f64,
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
    pub stabilisation_iterations: usize,
    /// The contact solver's iterations in each proximal iteration (their sum is `iterations`);
    /// empty when no springs were needed.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub stabilisation_step_iterations: Vec<usize>,
    /// Linear solves with the factorised stiffness (1 free + columns of W + 1 final).
    pub linear_solves: usize,
}

pub struct ContactOutcome {
    pub force: Vec<f64>,
    pub status: Vec<PointStatus>,
    pub report: ContactReport,
}
