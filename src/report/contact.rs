//! What the primal contact route reports (`report.json` → `contact`): the solver's history,
//! the point counts and resultants, the closed zones, and the independent check's residuals.
//!
//! A point's state as reported ([`ContactState`]): `open`, or closed; closed points are
//! `stick` or `slip` under a friction law, and `closed` without friction (where sticking and
//! slipping are not told apart: the solvers' internal "slip" of a frictionless point means no
//! more than closed).
use std::collections::BTreeMap;
use std::fmt;

use crate::contact::PointStatus;
use crate::scene::FrictionSpec;

/// A friction law as `report.json` writes it: `{"law": "none"}`, `{"law": "coulomb", "mu":
/// 0.3}`, `{"law": "tresca", "threshold": 5e7}` (the slip threshold on the tangential traction,
/// Pa = N/m², as in the scene), or with contact parts of different laws or coefficients
/// `{"law": "per_part", "parts": {"NAME": {...}, ...}}`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum FrictionReport {
    /// Frictionless contact.
    None,
    /// Coulomb friction.
    Coulomb {
        /// The friction coefficient μ.
        mu: f64,
    },
    /// Tresca friction.
    Tresca {
        /// The slip threshold on the tangential traction (Pa).
        threshold: f64,
    },
    /// Contact parts with different laws or coefficients.
    PerPart {
        /// Each part's law, by part name.
        parts: BTreeMap<String, FrictionReport>,
    },
}

impl From<FrictionSpec> for FrictionReport {
    fn from(f: FrictionSpec) -> Self {
        match f {
            FrictionSpec::None => FrictionReport::None,
            FrictionSpec::Coulomb { mu } => FrictionReport::Coulomb { mu },
            FrictionSpec::Tresca { threshold } => FrictionReport::Tresca { threshold },
        }
    }
}

impl FrictionReport {
    /// The law of several named parts: theirs when they all have the same, else per part.
    pub fn of_parts<'a>(parts: impl IntoIterator<Item = (&'a str, FrictionSpec)>) -> Self {
        let parts: Vec<(&str, FrictionSpec)> = parts.into_iter().collect();
        match parts.first() {
            Some((_, first)) if parts.iter().all(|(_, f)| f == first) => (*first).into(),
            None => FrictionReport::None,
            Some(_) => FrictionReport::PerPart {
                parts: parts.into_iter().map(|(name, f)| (name.to_string(), f.into())).collect(),
            },
        }
    }

    /// Is there friction (on some part)?
    pub fn is_frictional(&self) -> bool {
        match self {
            FrictionReport::None => false,
            FrictionReport::PerPart { parts } => parts.values().any(FrictionReport::is_frictional),
            _ => true,
        }
    }
}

/// As the terminal and the plot titles write it: `Coulomb, mu = 0.3`, `Tresca, threshold =
/// 5e7 Pa`, `none`.
impl fmt::Display for FrictionReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FrictionReport::None => write!(f, "none"),
            FrictionReport::Coulomb { mu } => write!(f, "Coulomb, mu = {mu}"),
            FrictionReport::Tresca { threshold } => write!(f, "Tresca, threshold = {threshold:e} Pa"),
            FrictionReport::PerPart { parts } => {
                let each: Vec<String> = parts.iter().map(|(name, law)| format!("{name}: {law}")).collect();
                write!(f, "{}", each.join("; "))
            }
        }
    }
}

/// A contact point's state as the outputs write it (`contact.csv`, the `.vtu` field
/// `contact_status`, the counts of the report).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactState {
    /// No contact force.
    Open,
    /// Closed, sticking (with friction).
    Stick,
    /// Closed, slipping (with friction).
    Slip,
    /// Closed without friction.
    Closed,
}

impl ContactState {
    /// The reported state of a solver's status, with or without friction at the point.
    pub fn of(status: PointStatus, frictional: bool) -> Self {
        match (status, frictional) {
            (PointStatus::Open, _) => ContactState::Open,
            (_, false) => ContactState::Closed,
            (PointStatus::Stick, true) => ContactState::Stick,
            (PointStatus::Slip, true) => ContactState::Slip,
        }
    }

    /// Its name in `contact.csv`.
    pub fn name(self) -> &'static str {
        match self {
            ContactState::Open => "open",
            ContactState::Stick => "stick",
            ContactState::Slip => "slip",
            ContactState::Closed => "closed",
        }
    }

    /// Its value in the `.vtu` point field `contact_status` (-1 where no contact point is).
    pub fn code(self) -> f64 {
        match self {
            ContactState::Open => 0.0,
            ContactState::Stick => 1.0,
            ContactState::Slip => 2.0,
            ContactState::Closed => 3.0,
        }
    }
}

/// The points per reported state: `closed` counts every closed point (stick + slip under
/// friction); `stick` and `slip` are 0 without friction.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StateCounts {
    /// Points without contact force.
    pub open: usize,
    /// Closed points (stick + slip under friction).
    pub closed: usize,
    /// Sticking points (0 without friction).
    pub stick: usize,
    /// Slipping points (0 without friction).
    pub slip: usize,
}

impl StateCounts {
    /// The counts of `(status, frictional)` per point.
    pub fn of(points: impl IntoIterator<Item = (PointStatus, bool)>) -> Self {
        let mut c = StateCounts::default();
        for (s, frictional) in points {
            match ContactState::of(s, frictional) {
                ContactState::Open => c.open += 1,
                ContactState::Stick => c.stick += 1,
                ContactState::Slip => c.slip += 1,
                ContactState::Closed => {}
            }
            if s != PointStatus::Open {
                c.closed += 1;
            }
        }
        c
    }
}

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
    /// The force scale `F` the residuals are relative to (N per unit thickness; N for the full revolution of a body of revolution).
    pub force_scale: f64,
    /// The displacement scale `U` the residuals are relative to (m).
    pub displacement_scale: f64,
}

impl ContactResidualsReport {
    /// The largest of the five relative residuals (`+∞` if any is not a number), as
    /// [`crate::contact::ContactResiduals::worst`].
    pub fn worst(&self) -> f64 {
        [
            self.max_penetration,
            self.max_wrong_sign_pressure,
            self.max_cone_violation,
            self.normal_complementarity,
            self.tangential_complementarity,
        ]
        .into_iter()
        .map(|v| if v.is_nan() { f64::INFINITY } else { v })
        .fold(0.0, f64::max)
    }
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
    /// The friction law (an object: `{"law": "coulomb", "mu": 0.3}`).
    pub friction: FrictionReport,
    /// The contact solver as run, with its linear solver (and a fallback, if one was taken).
    pub solver: String,
    /// How the contact solve's linear algebra was organised: `dense_schur` or `sparse_lu` (the
    /// full-space Newton's routes), `options` (its inner solver named by the options),
    /// `condensed` (the condensed route, `W = B K⁻¹ Bᵀ`) or `dual` (the dual formulation's
    /// condensation onto the contact forces).
    pub route: String,
    /// Why that route: the cost model's predictions, or the option or scene setting that chose it.
    pub route_reason: String,
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
    /// Closed points (stick + slip under friction).
    pub closed: usize,
    /// Sticking and slipping points (0 without friction: its closed points are `closed`).
    pub stick: usize,
    /// Points in contact, slipping (0 without friction).
    pub slip: usize,
    /// Resultant of the contact forces on the body in x and y (N per unit thickness; N for the full revolution of a body of revolution).
    pub resultant: [f64; 2],
    /// Sums of the normal and tangential contact forces (local frames).
    pub normal_resultant: f64,
    /// Sum of the tangential contact forces in the points' local frames (N per unit thickness; N for the full revolution of a body of revolution).
    pub tangential_resultant: f64,
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
