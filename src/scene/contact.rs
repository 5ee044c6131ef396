//! The `[contact]` table: frictional contact of one boundary part with a rigid obstacle.
//!
//! # The conditions
//!
//! On the contact part Γc, with `n` the outward normal of the body, `uN = u·n`, `σN = n·σn`,
//! `σT = σn − σN n` and `g0` the initial gap (Kikuchi & Oden, *Contact Problems
//! in Elasticity*, SIAM 1988, ch. 2 and 5):
//!
//! ```text
//!   Signorini:  uN − g0 ≤ 0,   σN ≤ 0,   σN (uN − g0) = 0
//!   none:       σT = 0
//!   Tresca:     |σT| ≤ s;       |σT| < s ⇒ uT = 0;   |σT| = s ⇒ uT = −λ σT, λ ≥ 0
//!   Coulomb:    the same with s = −μ σN
//! ```
//!
//! `s` is `threshold` (a traction, N/m²: force per unit boundary length and unit thickness), `μ`
//! is `mu`. Coulomb with `mu = 0` is frictionless and is stored as [`FrictionSpec::None`], so
//! that no friction machinery runs.
//!
//! # Obstacles and the gap
//!
//! The obstacle is a rigid region; `contact::obstacle::Obstacle::project` (the one
//! implementation, used by the driver) gives, for a point `x` of the body,
//! the closest point `c` of the obstacle's surface, the unit normal `ν` of the surface at `c`
//! pointing from the obstacle towards the body, and the signed distance `d` (> 0 on the body's
//! side, < 0 inside the obstacle). The initial gap of a contact node is `g0 = d + gap` along the
//! direction `n = −ν` (the usual node-to-rigid-surface gap, Wriggers, *Computational Contact
//! Mechanics*, 2nd ed., Springer 2006, § 4.1).
//!
//! ```text
//!   line { point p, normal m }        circle { center c, radius R }     polyline p0 p1 ... pk
//!
//!        body   ^ ν = m/|m|             body outside              body on the LEFT of travel
//!   ____________|_________                 .---.                     ^ν0        ^ν1
//!   //// obstacle ////////               /  c  \  ν radial       p0 ------ p1 \
//!        d = (x − p)·ν                   \  R  /                               \ p2
//!                                          '---'   d = |x − c| − R      ////// obstacle
//! ```
//!
//! - Line: `d = (x − p)·ν`, `c = x − d ν`.
//! - Circle (a rigid disc, the body outside it): `d = |x − c| − R`, `ν = (x − c)/|x − c|`
//!   (`ν = (0, 1)` at the centre itself, where every direction is as close).
//! - Polyline: the obstacle is on the right of the direction of travel, and the first and last
//!   segments are extended to infinity (so the surface divides the plane in two). With `νk`
//!   the left normal of segment `k`, a point whose closest point lies inside segment `k` has
//!   `d = (x − pk)·νk`, `ν = νk`; a point closest to an inner vertex `pj` has
//!   `d = ±|x − pj|` with the sign of `(x − pj)·(ν(j−1) + νj)` (the pseudo-normal test of
//!   Bærentzen & Aanæs, *Signed distance computation using the angle weighted pseudonormal*,
//!   IEEE TVCG 11(3), 2005, whose two weights are equal in 2D), and `ν = ±(x − pj)/|x − pj|`.
//!   A polyline must not cross itself (not checked) and must not turn back on itself (checked).
use super::convert::{Scope, Table};
use super::diagnostic::Source;
use super::evolution::load_name;
use super::interface::{interface_spec, ContactFrictionKeys};
use super::raw::Leaf;
use super::raw::RawContact;
use super::{DirichletSpec, DirichletTarget};
use crate::error::{Location, Result};

/// Contact of one boundary part with a rigid obstacle (`[contact]`).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSpec {
    /// The boundary part that may touch the obstacle.
    pub part: String,
    /// The rigid obstacle.
    pub obstacle: ObstacleSpec,
    /// Added to the geometric distance to the obstacle (m); negative means an initial overlap.
    pub gap: f64,
    /// The friction law.
    pub friction: FrictionSpec,
    /// The contact algorithm (the command line's `--contact-solver` replaces it).
    pub solver: ContactSolverSpec,
    /// Relative residual tolerance of the contact solve, in (0, 1); the solver's default if `None`.
    pub tolerance: Option<f64>,
    /// Iteration limit of the contact solve, ≥ 1; the solver's default if `None`.
    pub max_iterations: Option<usize>,
    /// `motion`: the obstacle's displacement (m) at factor 1; at pseudo-time `t` of a load path
    /// the obstacle is translated by `factor(t) · motion` ([`ContactSpec::obstacle_at`]).
    /// Without `[evolution]` it is applied in full. `None`: the obstacle stays.
    pub motion: Option<[f64; 2]>,
    /// `name`: the load name of the obstacle's motion, whose factor table multiplies it
    /// ([`super::EvolutionSpec::factor`]); `None`: the proportional ramp.
    pub name: Option<String>,
    /// `[contact.interface]`: the interface law (`None`: Signorini with `friction`).
    pub interface: Option<super::InterfaceSpec>,
    /// Where `part = ...` is written, for errors found later (unknown part).
    pub at: Location,
}

/// A rigid obstacle (see the module documentation for the geometry and the gap).
#[derive(Debug, Clone, PartialEq)]
pub enum ObstacleSpec {
    /// The half-plane `{(x − point)·normal ≤ 0}`; `normal` is a unit vector pointing from the
    /// obstacle towards the body.
    Line {
        /// A point of the line (m).
        point: [f64; 2],
        /// Unit normal, from the obstacle towards the body.
        normal: [f64; 2],
    },
    /// The disc of `radius > 0` around `center`; the body is outside it.
    Circle {
        /// Centre of the rigid disc (m).
        center: [f64; 2],
        /// Its radius (m), > 0.
        radius: f64,
    },
    /// At least two points, no two consecutive ones equal, never turning back; the body is on
    /// the left of the direction of travel, the end segments are extended to infinity.
    Polyline {
        /// The vertices (m), in the direction of travel (the body on the left).
        points: Vec<[f64; 2]>,
    },
}

/// The friction law on the contact part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionSpec {
    /// Frictionless (also Coulomb with `mu = 0`).
    None,
    /// `|σT| ≤ threshold`, a given slip threshold > 0 (N/m²).
    Tresca {
        /// The slip threshold on |σT| (N/m²), > 0.
        threshold: f64,
    },
    /// `|σT| ≤ −mu σN`, `mu > 0`.
    Coulomb {
        /// The friction coefficient μ, > 0.
        mu: f64,
    },
}

/// The algorithm for the contact problem (`solver = "..."`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactSolverSpec {
    /// Semi-smooth Newton on the Alart–Curnier function of the condensed problem (flexibility
    /// `W = B K⁻¹ Bᵀ` from `2m` solves), `solver = "newton"`.
    Newton,
    /// Semi-smooth Newton on the whole mixed (displacement, contact force) system through PETSc
    /// SNES, `solver = "newton_full"` (the default); its linear algebra: `-contact_route`.
    FullSpaceNewton,
    /// Projected block Gauss–Seidel / SOR, over-relaxation factor `omega` in (0, 2).
    Relaxation {
        /// The over-relaxation factor ω, in (0, 2) (1 is Gauss–Seidel).
        omega: f64,
    },
    /// D-PANA block relaxation (contact and friction alternately).
    DPana,
    /// Uzawa: projected gradient on the contact forces.
    Uzawa,
    /// Fixed point on Tresca thresholds `s = μ|σN|`.
    TrescaFixedPoint,
    /// PETSc SNESVI (frictionless only).
    SnesVi,
    /// PETSc TAO bound-constrained QP (Tresca only).
    Tao,
}

impl ContactSpec {
    /// The obstacle moved by `factor · motion` (unmoved without a `motion`): the obstacle at a
    /// pseudo-time whose factor for this contact's load name is `factor`
    /// ([`super::EvolutionSpec::factor`] with [`ContactSpec::name`]).
    pub fn obstacle_at(&self, factor: f64) -> ObstacleSpec {
        match self.motion {
            Some(m) => self.obstacle.translated([factor * m[0], factor * m[1]]),
            None => self.obstacle.clone(),
        }
    }
}

impl ObstacleSpec {
    /// The obstacle translated by `d` (m): the line's point, the circle's centre, every
    /// polyline point.
    pub fn translated(&self, d: [f64; 2]) -> ObstacleSpec {
        let shift = |p: [f64; 2]| [p[0] + d[0], p[1] + d[1]];
        match self {
            ObstacleSpec::Line { point, normal } => ObstacleSpec::Line { point: shift(*point), normal: *normal },
            ObstacleSpec::Circle { center, radius } => ObstacleSpec::Circle { center: shift(*center), radius: *radius },
            ObstacleSpec::Polyline { points } => {
                ObstacleSpec::Polyline { points: points.iter().map(|&p| shift(p)).collect() }
            }
        }
    }
}

impl ContactSolverSpec {
    /// The name written in a scene (`solver = "newton"`).
    pub fn scene_name(&self) -> &'static str {
        match self {
            ContactSolverSpec::Newton => "newton",
            ContactSolverSpec::FullSpaceNewton => "newton_full",
            ContactSolverSpec::Relaxation { .. } => "relaxation",
            ContactSolverSpec::DPana => "dpana",
            ContactSolverSpec::Uzawa => "uzawa",
            ContactSolverSpec::TrescaFixedPoint => "tresca_fixed_point",
            ContactSolverSpec::SnesVi => "snes_vi",
            ContactSolverSpec::Tao => "tao",
        }
    }

    /// The solver a scene names `name` (relaxation with ω = 1); `None` for an unknown name.
    pub fn from_scene_name(name: &str) -> Option<Self> {
        [
            ContactSolverSpec::FullSpaceNewton,
            ContactSolverSpec::Newton,
            ContactSolverSpec::Relaxation { omega: 1.0 },
            ContactSolverSpec::DPana,
            ContactSolverSpec::Uzawa,
            ContactSolverSpec::TrescaFixedPoint,
            ContactSolverSpec::SnesVi,
            ContactSolverSpec::Tao,
        ]
        .into_iter()
        .find(|s| s.scene_name() == name)
    }
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

// ---- conversion -------------------------------------------------------------------------------

const OBSTACLES: &[&str] = &["line", "circle", "polyline"];
const OBSTACLE_KEYS: &[&str] = &["point", "normal", "center", "radius", "points"];
const FRICTIONS: &[&str] = &["none", "tresca", "coulomb"];
const SOLVERS: &[&str] =
    &["newton", "newton_full", "relaxation", "dpana", "uzawa", "tresca_fixed_point", "snes_vi", "tao"];

/// Convert and check `[contact]`; `dirichlet` are the scene's `[[dirichlet]]` tables (a clamped
/// contact part is refused).
pub(super) fn contact_spec(
    src: &Source,
    scope: &Scope,
    c: &RawContact,
    dirichlet: &[DirichletSpec],
) -> Result<ContactSpec> {
    let first = c.present_keys().first().map(|(_, s)| s.clone());
    let table = scope.table(src, "contact", false, 0, first);

    let part_v = table.require(&c.part, "part", "part = \"bottom\" (the boundary part that may touch the obstacle)")?;
    let part = src.nonempty_string(part_v, "part")?.to_string();
    let at = src.location(part_v.span().start);

    let obstacle_v = table.require(
        &c.obstacle,
        "obstacle",
        "obstacle = \"line\" with point = [x, y] and normal = [nx, ny] (or \"circle\", \"polyline\")",
    )?;
    let kind = src.choice(obstacle_v, "obstacle", OBSTACLES)?;
    let obstacle = obstacle_spec(src, c, &table, kind)?;

    let gap = c.gap.as_ref().map(|v| src.number(v, "gap")).transpose()?.unwrap_or(0.0);
    // Before the friction: a friction key beside a law with its own friction gets the law's
    // message, not the friction table's.
    let interface = match &c.interface {
        Some(raw) => {
            let first = raw.present_keys().first().map(|(_, s)| s.clone());
            let table = scope.table(src, "contact.interface", false, 0, first);
            let keys = ContactFrictionKeys {
                friction: &c.friction,
                mu: &c.mu,
                threshold: &c.threshold,
                table: scope.name("contact", false),
            };
            Some(interface_spec(src, &table, raw, &keys)?)
        }
        None => None,
    };
    let friction = friction_spec(src, c)?;
    let solver = solver_spec(src, c, &friction)?;

    let tolerance = match &c.tolerance {
        Some(v) => {
            let t = src.positive(v, "tolerance", "a relative tolerance")?;
            // The answer is accepted only when its independent check is within the tolerance
            // asked for; above 1e-3 that check would accept answers visibly off (a tolerance of
            // 0.9 missed complementarity by 85 %).
            if t > 1e-3 {
                return Err(src.error(
                    &v.span(),
                    format!("`tolerance` must be at most 1e-3, found {}", src.written(v)),
                    "the tolerance is relative to the size of the contact forces and displacements, and the \
                     answer's independent check uses it: larger values accept visibly wrong answers; write e.g. \
                     tolerance = 1e-9 (or leave it out for the solver's default)",
                ));
            }
            Some(t)
        }
        None => None,
    };
    let max_iterations = c.max_iterations.as_ref().map(|v| src.positive_integer(v, "max_iterations")).transpose()?;

    // A part whose ux and uy are both prescribed cannot move towards the obstacle.
    let clamping: Vec<&DirichletSpec> =
        dirichlet.iter().filter(|d| matches!(&d.target, DirichletTarget::Part(p) if *p == part)).collect();
    if clamping.iter().any(|d| d.ux.is_some()) && clamping.iter().any(|d| d.uy.is_some()) {
        let lines: Vec<String> = clamping.iter().map(|d| d.at.line.to_string()).collect();
        let (noun, verb) = if lines.len() == 1 { ("line", "fixes") } else { ("lines", "fix") };
        return Err(src.error(
            &part_v.span(),
            format!(
                "the contact part `{part}` is clamped: the [[dirichlet]] on `{part}` ({noun} {}) {verb} both ux and uy",
                lines.join(" and ")
            ),
            format!(
                "a clamped part cannot come into contact: choose another contact part, or prescribe at most one \
                 component on `{part}`"
            ),
        ));
    }

    let motion = c.motion.as_ref().map(|v| src.vector(v, "motion")).transpose()?;
    let name = load_name(src, &c.name)?;
    if let (Some(name_v), None) = (&c.name, &c.motion) {
        return Err(src.error(
            &name_v.span(),
            format!("{} names the obstacle's motion, but has no `motion`", scope.name("contact", false)),
            "`name` names the obstacle's motion for [evolution.factor]: add motion = [dx, dy] (the obstacle's \
             displacement at factor 1, m), or remove the name",
        ));
    }
    Ok(ContactSpec { part, obstacle, gap, friction, solver, tolerance, max_iterations, motion, name, interface, at })
}

fn obstacle_spec(src: &Source, c: &RawContact, table: &Table, kind: &str) -> Result<ObstacleSpec> {
    let allowed: &[&str] = match kind {
        "line" => &["point", "normal"],
        "circle" => &["center", "radius"],
        _ => &["points"],
    };
    let misplaced = c.present_keys().into_iter().find(|(k, _)| OBSTACLE_KEYS.contains(k) && !allowed.contains(k));
    if let Some((key, span)) = misplaced {
        return Err(src.error(
            &span,
            format!("`{key}` does not apply to obstacle = \"{kind}\""),
            format!("remove `{key}`; obstacle = \"{kind}\" takes {}", allowed.join(", ")),
        ));
    }
    let table =
        Table { src: table.src, name: format!("{} with obstacle = \"{kind}\"", table.name), span: table.span.clone() };
    match kind {
        "line" => {
            let point =
                src.vector(table.require(&c.point, "point", "point = [x, y] (a point of the line)")?, "point")?;
            let normal_v =
                table.require(&c.normal, "normal", "normal = [0.0, 1.0] (from the obstacle towards the body)")?;
            let normal = src.vector(normal_v, "normal")?;
            let length = norm(normal);
            let unit = [normal[0] / length, normal[1] / length];
            if !(length > 0.0 && unit[0].is_finite() && unit[1].is_finite()) {
                return Err(src.error(
                    &normal_v.span(),
                    format!("`normal` must not be zero, found {}", src.written(normal_v)),
                    "give a direction pointing from the obstacle towards the body, e.g. normal = [0.0, 1.0] for \
                     a floor under the body (any length: it is normalised)",
                ));
            }
            Ok(ObstacleSpec::Line { point, normal: unit })
        }
        "circle" => {
            let center = src.vector(table.require(&c.center, "center", "center = [x, y]")?, "center")?;
            let radius_v = table.require(&c.radius, "radius", "radius = 1.0 (of the rigid disc)")?;
            let radius = src.positive(radius_v, "radius", "the radius of the rigid disc")?;
            Ok(ObstacleSpec::Circle { center, radius })
        }
        _ => {
            let points_v = table.require(
                &c.points,
                "points",
                "points = [[-1.0, 0.0], [1.0, 0.0]] (the body on the left of the direction of travel)",
            )?;
            let points = src.points(points_v, "points")?;
            check_polyline(src, points_v, &points)?;
            Ok(ObstacleSpec::Polyline { points })
        }
    }
}

fn check_polyline(src: &Source, v: &toml::Spanned<toml::Value>, points: &[[f64; 2]]) -> Result<()> {
    if points.len() < 2 {
        return Err(src.error(
            &v.span(),
            format!("a polyline obstacle needs at least 2 points, found {}", points.len()),
            "give the points in order, the body on the left of the direction of travel, e.g. \
             points = [[-1.0, 0.0], [1.0, 0.0]] for a floor under the body",
        ));
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = [lo[0].min(p[0]), lo[1].min(p[1])];
        hi = [hi[0].max(p[0]), hi[1].max(p[1])];
    }
    let extent = norm(sub(hi, lo));
    for k in 0..points.len() - 1 {
        let length = norm(sub(points[k + 1], points[k]));
        if length <= 1e-12 * extent {
            return Err(src.error(
                &v.span(),
                format!(
                    "points[{k}] and points[{}] of the polyline are the same point [{}, {}]",
                    k + 1,
                    points[k][0],
                    points[k][1]
                ),
                "remove the repeated point: every segment of the polyline needs a length",
            ));
        }
    }
    for k in 1..points.len() - 1 {
        let (a, b) = (sub(points[k], points[k - 1]), sub(points[k + 1], points[k]));
        let cos = dot(a, b) / (norm(a) * norm(b));
        let sin = (a[0] * b[1] - a[1] * b[0]) / (norm(a) * norm(b));
        if cos < 0.0 && sin.abs() < 1e-12 {
            return Err(src.error(
                &v.span(),
                format!("the polyline turns back on itself at points[{k}] = [{}, {}]", points[k][0], points[k][1]),
                "the obstacle's surface must not fold back: remove the points that retrace the previous segment",
            ));
        }
    }
    Ok(())
}

fn friction_spec(src: &Source, c: &RawContact) -> Result<FrictionSpec> {
    friction_from(src, &c.friction, &c.mu, &c.threshold)
}

/// The friction law from the keys `friction`, `mu` and `threshold` of a `[contact]` or a
/// `[[contact_pair]]` table: `mu` only with Coulomb, `threshold` only with Tresca.
pub(super) fn friction_from(src: &Source, friction: &Leaf, mu: &Leaf, threshold: &Leaf) -> Result<FrictionSpec> {
    let kind = friction.as_ref().map(|v| src.choice(v, "friction", FRICTIONS)).transpose()?;
    let named = |k: Option<&str>| match k {
        Some(k) => format!("friction = \"{k}\""),
        None => "the default friction (\"none\")".to_string(),
    };
    if let (Some(v), false) = (mu, kind == Some("coulomb")) {
        let hint = match kind {
            Some("tresca") => "Tresca friction takes a fixed slip `threshold` (N/m²): remove `mu`, or write \
                               friction = \"coulomb\" for a friction coefficient"
                .to_string(),
            _ => "`mu` is the Coulomb friction coefficient: add friction = \"coulomb\", or remove `mu`".to_string(),
        };
        return Err(src.error(&v.span(), format!("`mu` does not apply to {}", named(kind)), hint));
    }
    if let (Some(v), false) = (threshold, kind == Some("tresca")) {
        let hint = match kind {
            Some("coulomb") => "Coulomb friction takes `mu` (its threshold is mu·|σN|): remove `threshold`, or \
                                write friction = \"tresca\" for a fixed threshold"
                .to_string(),
            _ => {
                "`threshold` is the Tresca slip threshold: add friction = \"tresca\", or remove `threshold`".to_string()
            }
        };
        return Err(src.error(&v.span(), format!("`threshold` does not apply to {}", named(kind)), hint));
    }
    let friction_span = friction.as_ref().map(|v| v.span()).unwrap_or(0..0);
    match kind {
        None | Some("none") => Ok(FrictionSpec::None),
        Some("tresca") => {
            let Some(v) = threshold else {
                return Err(src.error(
                    &friction_span,
                    "friction = \"tresca\" needs `threshold`",
                    "add threshold = 1e5 (the slip threshold on |σT|, N/m², > 0)",
                ));
            };
            let threshold = src.positive(v, "threshold", "a slip threshold (N/m²)")?;
            Ok(FrictionSpec::Tresca { threshold })
        }
        _ => {
            let Some(v) = mu else {
                return Err(src.error(
                    &friction_span,
                    "friction = \"coulomb\" needs `mu`",
                    "add mu = 0.3 (the friction coefficient, ≥ 0; 0 is frictionless)",
                ));
            };
            let mu = src.number(v, "mu")?;
            if mu < 0.0 {
                return Err(src.error(
                    &v.span(),
                    format!("`mu` must not be negative, found {}", src.written(v)),
                    "the friction coefficient is ≥ 0 (steel on steel: about 0.15-0.6; 0 is frictionless)",
                ));
            }
            Ok(if mu == 0.0 { FrictionSpec::None } else { FrictionSpec::Coulomb { mu } })
        }
    }
}

fn solver_spec(src: &Source, c: &RawContact, friction: &FrictionSpec) -> Result<ContactSolverSpec> {
    let name = c.solver.as_ref().map(|v| src.choice(v, "solver", SOLVERS)).transpose()?;
    if let (Some(v), false) = (&c.omega, name == Some("relaxation")) {
        let which = match name {
            Some(n) => format!("solver = \"{n}\""),
            None => "the default solver (\"newton_full\")".to_string(),
        };
        return Err(src.error(
            &v.span(),
            format!("`omega` does not apply to {which}"),
            "`omega` is the over-relaxation factor of solver = \"relaxation\": remove it, or write \
             solver = \"relaxation\"",
        ));
    }
    let solver_span = c.solver.as_ref().map(|v| v.span()).unwrap_or(0..0);
    let written = c.friction.as_ref().and_then(|v| src.choice(v, "friction", FRICTIONS).ok());
    let friction_name = match (friction, written) {
        (FrictionSpec::None, Some("coulomb")) => "friction = \"coulomb\" with mu = 0 (frictionless)".to_string(),
        (FrictionSpec::None, _) => "frictionless contact".to_string(),
        (FrictionSpec::Tresca { .. }, _) => "friction = \"tresca\"".to_string(),
        (FrictionSpec::Coulomb { .. }, _) => "friction = \"coulomb\"".to_string(),
    };
    Ok(match name {
        None | Some("newton_full") => ContactSolverSpec::FullSpaceNewton,
        Some("newton") => ContactSolverSpec::Newton,
        Some("relaxation") => {
            let omega = match &c.omega {
                Some(v) => {
                    let omega = src.number(v, "omega")?;
                    if !(omega > 0.0 && omega < 2.0) {
                        return Err(src.error(
                            &v.span(),
                            format!("`omega` must be in (0, 2), found {}", src.written(v)),
                            "projected SOR converges for 0 < omega < 2: 1 is Gauss–Seidel (the default), \
                             values in (1, 2) over-relax",
                        ));
                    }
                    omega
                }
                None => 1.0,
            };
            ContactSolverSpec::Relaxation { omega }
        }
        Some("dpana") => ContactSolverSpec::DPana,
        Some("uzawa") => ContactSolverSpec::Uzawa,
        Some("tresca_fixed_point") => ContactSolverSpec::TrescaFixedPoint,
        Some("snes_vi") => {
            if *friction != FrictionSpec::None {
                return Err(src.error(
                    &solver_span,
                    format!("solver = \"snes_vi\" cannot handle {friction_name}"),
                    "PETSc's SNESVI solves bound-constrained problems: it handles the frictionless case only; \
                     use solver = \"newton_full\" (semi-smooth Newton, any friction)",
                ));
            }
            ContactSolverSpec::SnesVi
        }
        _ => {
            if !matches!(friction, FrictionSpec::Tresca { .. }) {
                return Err(src.error(
                    &solver_span,
                    format!("solver = \"tao\" needs friction = \"tresca\", found {friction_name}"),
                    "TAO's bound-constrained QP (tron, gpcg, bqpip) is for the Tresca problem; use \
                     solver = \"newton_full\" (any friction), or \"snes_vi\" for frictionless contact",
                ));
            }
            ContactSolverSpec::Tao
        }
    })
}
