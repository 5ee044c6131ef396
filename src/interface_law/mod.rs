//! # Interface laws: what an interface transmits beyond Signorini and Coulomb
//!
//! Three laws, chosen per contact in the scene (`[contact.interface]`,
//! `[contact_pair.interface]`, see [`crate::scene::InterfaceSpec`]):
//!
//! | law | file | memory | internal variables |
//! |---|---|---|---|
//! | thin elastic layer (imperfect interface), bonded or cut | `thin_layer.rs` | none | none |
//! | adhesion + unilateral contact + friction (RCCM) | `rccm.rs` | yes | adhesion intensity β |
//! | cohesive–frictional joint (Mohr–Coulomb, softening) | `cohesive_joint.rs` | yes | the softening variables |
//!
//! Every law is local: at each contact point it changes the condensed contact problem of the
//! solve (module [`crate::contact`]: `u = W r + u_free`, the law on `u − shift`) by a
//! [`PointModification`] computed from its internal variables, and after the solve it updates
//! those variables from the point's [`PointSolution`] (implicitly: the variables at the end of
//! the increment are those of the end of the increment's solution). The driver iterates
//! solve → update at a fixed increment until the variables no longer change (a staggered
//! scheme), then commits them.
//!
//! ## The modified problem
//!
//! At a point with modification `(c, k, a, o, contact)` (componentwise in the (N, T) frame):
//!
//! ```text
//!   total force        r = r' + o − k ∘ (u − g̃ + a)        r' the unilateral contact force
//!   series compliance  the unilateral law (Signorini + friction) acts on u' = u + c ∘ r
//!   contact = false    r' = 0 (no unilateral condition: springs only)
//! ```
//!
//! A law uses either series compliance (a layer or joint in series with the contact) or parallel
//! springs (adhesion beside the contact), not both.
pub mod cohesive_joint;
pub mod condensed;
pub mod rccm;
pub mod staggered;
pub mod thin_layer;

use crate::error::{Error, Result};
use crate::fem::material::PlaneModel;
use crate::scene::{InterfaceLawSpec, Scene};

/// The law of a scene's interface table in the plane model `plane`.
pub fn law_of(spec: &InterfaceLawSpec, plane: PlaneModel) -> Box<dyn InterfaceLaw> {
    match spec {
        InterfaceLawSpec::ThinLayer(s) => Box::new(thin_layer::ThinLayer::new(s, plane)),
        InterfaceLawSpec::Rccm(s) => Box::new(rccm::Rccm::new(s)),
        InterfaceLawSpec::CohesiveJoint(s) => Box::new(cohesive_joint::CohesiveJoint::new(s)),
    }
}

/// The interface tables of a scene, with the contact each belongs to (its part, or the pair's
/// `slave / master`).
pub fn interfaces_of(scene: &Scene) -> Vec<(String, &crate::scene::InterfaceSpec)> {
    let mut found = Vec::new();
    if let Some(c) = &scene.contact {
        if let Some(i) = &c.interface {
            found.push((c.part.clone(), i));
        }
    }
    for body in &scene.bodies {
        if let Some(c) = &body.contact {
            if let Some(i) = &c.interface {
                found.push((format!("{}.{}", body.name, c.part), i));
            }
        }
    }
    for pair in &scene.contact_pairs {
        if let Some(i) = &pair.interface {
            found.push((format!("{} / {}", pair.slave, pair.master), i));
        }
    }
    found
}

/// The dual formulation and the estimate with an interface law: refused (the error in the
/// constitutive relation has no interface term yet).
pub fn refuse_dual(scene: &Scene, what: &str) -> Result<()> {
    match interfaces_of(scene).first() {
        None => Ok(()),
        Some((contact, spec)) => Err(Error::Formulation {
            message: format!(
                "{what}: the error in the constitutive relation with an interface law is not implemented: the contact \
                 on `{contact}` has the interface law `{}` ({}:{}), and the dual formulation and the estimate know \
                 Signorini and Coulomb only",
                law_name(&spec.law),
                spec.at.file.display(),
                spec.at.line
            ),
            hint: "run the primal formulation without --estimate (remove --formulation dual / --estimate), or \
                   remove the [contact.interface] / [contact_pair.interface] table"
                .into(),
        }),
    }
}

/// The scene name of a law.
pub fn law_name(spec: &InterfaceLawSpec) -> &'static str {
    match spec {
        InterfaceLawSpec::ThinLayer(_) => "thin_layer",
        InterfaceLawSpec::Rccm(_) => "rccm",
        InterfaceLawSpec::CohesiveJoint(_) => "cohesive_joint",
    }
}

/// A contact point as a law sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfacePoint {
    /// The point's share of the interface (m per unit thickness): force = traction × weight.
    pub weight: f64,
    /// The initial gap g0 (m) between the faces along the normal.
    pub gap: f64,
    /// The whole tangential jump at the start of the increment (m; 0 in a static run): the law
    /// sees the slip increment, springs need the whole slip (their `spring_offset` along T).
    pub slip_before: f64,
    /// The largest traction `|r| / w` over the interface's points at the solution a residual is
    /// computed for (Pa; 0 otherwise): the stress scale of a law's residual at a point that
    /// carries little, where its own tractions are no scale (a joint without cohesion).
    pub traction_scale: f64,
    /// The largest relative displacement `|uN|`, `|slip|` over the interface's points at that
    /// solution (m; 0 otherwise): the length scale of a residual where every jump is round-off
    /// (a joint that sticks everywhere).
    pub displacement_scale: f64,
}

/// The friction the scene gives the contact force at a point (force units: Tresca's threshold
/// already multiplied by the weight).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PointFriction {
    /// `rT' = 0`.
    None,
    /// `|rT'| ≤ threshold` (N/m).
    Tresca(f64),
    /// `|rT'| ≤ −μ rN'`.
    Coulomb(f64),
}

/// What a law asks of the contact solve at one point (module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointModification {
    /// Series compliance `[cN, cT]` ≥ 0 (m per N/m): the unilateral law acts on `u + c ∘ r`.
    pub compliance: [f64; 2],
    /// Parallel springs `[kN, kT]` ≥ 0 (N/m per m): a force `−k ∘ (u − g̃ + a)` besides `r'`.
    pub stiffness: [f64; 2],
    /// The springs' rest offset `a = [aN, aT]` (m): along T the slip before the increment (the
    /// law sees the slip increment, the springs the whole slip).
    pub spring_offset: [f64; 2],
    /// A force `o = [oN, oT]` added at the point (N/m): a tensile strength along N.
    pub force_offset: [f64; 2],
    /// Whether the unilateral contact force `r'` exists (false: springs only).
    pub contact: bool,
    /// The friction of `r'`.
    pub friction: PointFriction,
}

impl PointModification {
    /// Plain Signorini contact with the given friction: nothing added.
    pub fn plain(friction: PointFriction) -> Self {
        PointModification {
            compliance: [0.0; 2],
            stiffness: [0.0; 2],
            spring_offset: [0.0; 2],
            force_offset: [0.0; 2],
            contact: true,
            friction,
        }
    }
}

/// One point at the end of a solve, in its (N, T) frame (obstacle's motion removed).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PointSolution {
    /// The opening `g0 − (uN − dN)` (m): the distance between the faces, > 0 when separated.
    pub opening: f64,
    /// The whole tangential jump since the start of the path (m).
    pub slip: f64,
    /// Its change over the increment (m).
    pub slip_increment: f64,
    /// The total force on the body `[rN, rT]` (N/m): all the interface transmits.
    pub force: [f64; 2],
    /// The unilateral contact force `r'` (N/m), a part of `force`.
    pub contact_force: [f64; 2],
}

/// What the outputs show of a point's internal variables.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct InterfaceOutputs {
    /// The adhesion intensity β in [0, 1] (RCCM).
    pub adhesion: Option<f64>,
    /// The damage in [0, 1] (the cohesive joint: 1 − the remaining fraction of its strength).
    pub damage: Option<f64>,
}

/// A local interface law.
pub trait InterfaceLaw: std::fmt::Debug {
    /// The law's name in the scene (`"thin_layer"`, `"rccm"`, `"cohesive_joint"`).
    fn name(&self) -> &'static str;
    /// Whether the law has internal variables that evolve along a load path.
    fn has_memory(&self) -> bool;
    /// The internal variables of a point before the path starts (empty without memory).
    fn initial(&self) -> Vec<f64>;
    /// The point's modification for a solve, from the trial internal variables and the point's
    /// last solution: the previous staggered iteration's, at an increment's first solve the
    /// last increment's end; `None` only at the first solve of a run.
    fn modification(
        &self,
        point: &InterfacePoint,
        friction: PointFriction,
        trial: &[f64],
        last: Option<&PointSolution>,
    ) -> PointModification;
    /// The internal variables at the end of an increment of duration `dt > 0` (implicit: from
    /// the solution at its end), given those at its start.
    fn update(&self, point: &InterfacePoint, committed: &[f64], solution: &PointSolution, dt: f64) -> Vec<f64>;
    /// The law's own residual at a converged point, dimensionless (0 exact): its inequalities,
    /// complementarities and evolution law, recomputed from the solution and the variables.
    fn residual(
        &self,
        point: &InterfacePoint,
        committed: &[f64],
        state: &[f64],
        solution: &PointSolution,
        dt: f64,
    ) -> f64;
    /// What the outputs show of the variables.
    fn outputs(&self, state: &[f64]) -> InterfaceOutputs;
}

/// A point of the interface at the end of a solve, for the outputs.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InterfacePointState {
    /// Its position (m).
    pub x: [f64; 2],
    /// The opening (m).
    pub opening: f64,
    /// The tangential jump since the start (m).
    pub slip: f64,
    /// The normal traction `rN / w` (Pa, < 0 compression).
    pub traction_normal: f64,
    /// The tangential traction `rT / w` (Pa).
    pub traction_tangential: f64,
    /// β (RCCM).
    pub adhesion: Option<f64>,
    /// The damage (cohesive joint).
    pub damage: Option<f64>,
    /// The law's residual at the point ([`InterfaceLaw::residual`]).
    pub law_residual: f64,
}

/// The interface at the end of a solve (a static run, or an increment of a load path).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InterfaceSnapshot {
    /// The path's time (1 for a static run).
    pub time: f64,
    /// The law of each contact part, in the order of the points' parts.
    pub laws: Vec<String>,
    /// Every contact point, in the order of the contact points.
    pub points: Vec<InterfacePointState>,
    /// Staggered iterations (solve → update) the solve took.
    pub iterations: usize,
}
