//! What one increment of a load path leaves behind: its [`StepRecord`] (one row of
//! `history.csv`, one entry of `report.json` → `steps`) and, at the steps asked for, the
//! [`ContactProfile`] along the contact part (the pressure and traction plots).
use serde::Serialize;

use crate::report::contact::ContactState;

/// One converged increment of a load path (units: N/m and J/m, per metre of thickness).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepRecord {
    /// The increment's number, 1 for the first.
    pub step: usize,
    /// The pseudo-time at its end.
    pub time: f64,
    /// How many times the increment was cut in two before it converged (0: as listed).
    pub halvings: usize,
    /// The total contact force on the body (bodies: on the slave sides), `[x, y]`.
    pub contact_resultant: [f64; 2],
    /// Sum of the normal contact forces (compression negative).
    pub normal_resultant: f64,
    /// Sum of the tangential contact forces.
    pub tangential_resultant: f64,
    /// Contact points without contact force.
    pub open: usize,
    /// Closed points sticking (friction).
    pub stick: usize,
    /// Closed points slipping (friction).
    pub slip: usize,
    /// Every closed point (stick and slip included; without friction: the closed points).
    pub closed: usize,
    /// Iterations of the contact solver in this increment.
    pub iterations: usize,
    /// The independent check's worst relative residual at the end of the increment.
    pub worst_residual: f64,
    /// The friction law's dissipation in the increment, `−Σ rT·Δs ≥ 0` (J/m; the force at
    /// the end of the increment, the slip increment).
    pub dissipation: f64,
    /// The same since the start of the path (J/m).
    pub total_dissipation: f64,
    /// Work of the loads since the start of the path (J/m).
    pub work: f64,
    /// Elastic energy stored at the end of the increment, `½ uᵀ K u` (J/m).
    pub stored_energy: f64,
    /// Mean displacement of the monitored part, along the contact tangent (m): the abscissa of
    /// the hysteresis loop.
    pub monitor_displacement: f64,
    /// The estimated relative error of the increment's problem (%), when asked for
    /// ([`crate::evolution::EachIncrement::Estimate`]).
    pub estimate_percent: Option<f64>,
    /// Wall-clock seconds the increment took.
    pub seconds: f64,
}

/// The contact tractions along the contact part at the end of one increment.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactProfile {
    /// The increment ([`StepRecord::step`]).
    pub step: usize,
    /// Its pseudo-time.
    pub time: f64,
    /// Position of each contact point along the contact part (m), increasing.
    pub abscissa: Vec<f64>,
    /// Contact pressure at each point (Pa, compression positive).
    pub pressure: Vec<f64>,
    /// Tangential traction at each point (Pa).
    pub traction: Vec<f64>,
    /// State of each point.
    pub state: Vec<ContactState>,
}
