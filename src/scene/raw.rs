//! The scene file as TOML sees it: one struct per table, every key optional and kept with its
//! byte span, so that all checks beyond "is this key allowed here" are done (and reported with
//! a location) by the conversion in the parent module.
//!
//! Tables themselves are *not* wrapped in `toml::Spanned`: toml 0.8 cannot give a span to a
//! table defined implicitly (`[mesh.refine]` without `[mesh]`, or dotted keys `mesh.shape = ..`)
//! and then fails with a confusing message. Table locations are found in the text instead
//! (see `diagnostic::Source::table_span`).
//!
//! To add a section: add a `Raw...` struct here, its field in [`RawScene`],
//! its key list in [`TABLE_KEYS`], and a conversion function in the parent module.
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use toml::{Spanned, Value};

/// A leaf value with the byte span of its text, absent if the key is not written.
pub(super) type Leaf = Option<Spanned<Value>>;

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a scene (a TOML document)")]
pub(super) struct RawScene {
    pub title: Leaf,
    pub mesh: Option<RawMesh>,
    pub discretization: Option<RawDiscretization>,
    pub material: Option<RawMaterial>,
    pub loads: Option<RawLoads>,
    #[serde(default)]
    pub traction: Vec<RawTraction>,
    #[serde(default)]
    pub dirichlet: Vec<RawDirichlet>,
    pub contact: Option<RawContact>,
    pub solver: Option<RawSolver>,
    pub output: Option<RawOutput>,
    pub estimate: Option<RawEstimate>,
    #[serde(default)]
    pub body: Vec<RawBody>,
    #[serde(default)]
    pub contact_pair: Vec<RawContactPair>,
    pub evolution: Option<RawEvolution>,
}

/// `[evolution]`: a load path. Its `[evolution.factor]` table maps load names (any key) to
/// their tables `[[t, factor], ...]`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [evolution] table")]
pub(super) struct RawEvolution {
    pub steps: Leaf,
    pub times: Leaf,
    pub start: Leaf,
    pub monitor: Leaf,
    pub profiles: Leaf,
    pub factor: Option<BTreeMap<String, Spanned<Value>>>,
}

/// One `[[body]]` table: a name, a placement, and the tables of a single-body scene under
/// `body.` (`[body.mesh]`, `[[body.traction]]`...).
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [[body]] table")]
pub(super) struct RawBody {
    pub name: Leaf,
    pub rotate: Leaf,
    pub translate: Leaf,
    pub mesh: Option<RawMesh>,
    pub discretization: Option<RawDiscretization>,
    pub material: Option<RawMaterial>,
    pub loads: Option<RawLoads>,
    #[serde(default)]
    pub traction: Vec<RawTraction>,
    #[serde(default)]
    pub dirichlet: Vec<RawDirichlet>,
    pub contact: Option<RawContact>,
}

/// One `[[contact_pair]]` table: contact between a part of one body and a part of another.
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [[contact_pair]] table")]
pub(super) struct RawContactPair {
    pub slave: Leaf,
    pub master: Leaf,
    pub friction: Leaf,
    pub mu: Leaf,
    pub threshold: Leaf,
    pub max_initial_overlap: Leaf,
    pub interface: Option<RawInterface>,
}

/// `[contact.interface]`, `[contact_pair.interface]` (or `interface = { ... }`): the interface
/// law of a contact. Every law's keys are accepted here; which apply to the chosen `law` is
/// checked by the conversion (`interface::interface_spec`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "an interface table")]
pub(super) struct RawInterface {
    pub law: Leaf,
    pub young: Leaf,
    pub poisson: Leaf,
    pub thickness: Leaf,
    pub bonded: Leaf,
    pub normal_stiffness: Leaf,
    pub tangential_stiffness: Leaf,
    pub adhesion_energy: Leaf,
    pub viscosity: Leaf,
    pub mu: Leaf,
    pub initial_adhesion: Leaf,
    pub cohesion: Leaf,
    pub tensile_strength: Leaf,
    pub fracture_energy_tension: Leaf,
    pub fracture_energy_shear: Leaf,
    pub trace: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [mesh] table")]
pub(super) struct RawMesh {
    pub shape: Leaf,
    pub origin: Leaf,
    pub size: Leaf,
    pub center: Leaf,
    pub radius: Leaf,
    pub file: Leaf,
    pub geometry: Leaf,
    pub cell_size: Leaf,
    pub mesher: Leaf,
    pub refine: Option<RawRefine>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a table { point = [x, y], cell_size = h, radius = r }")]
pub(super) struct RawRefine {
    pub point: Leaf,
    pub cell_size: Leaf,
    pub radius: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [discretization] table")]
pub(super) struct RawDiscretization {
    pub order: Leaf,
    pub element: Leaf,
    pub formulation: Leaf,
    pub dual_constraints: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [estimate] table")]
pub(super) struct RawEstimate {
    pub enabled: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [material] table")]
pub(super) struct RawMaterial {
    pub young: Leaf,
    pub poisson: Leaf,
    pub plane: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [loads] table")]
pub(super) struct RawLoads {
    pub body_force: Leaf,
    pub name: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [[traction]] table")]
pub(super) struct RawTraction {
    pub part: Leaf,
    pub traction: Leaf,
    pub pressure: Leaf,
    pub name: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "a [[dirichlet]] table")]
pub(super) struct RawDirichlet {
    pub part: Leaf,
    pub point: Leaf,
    pub ux: Leaf,
    pub uy: Leaf,
    pub name: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [contact] table")]
pub(super) struct RawContact {
    pub part: Leaf,
    pub obstacle: Leaf,
    pub point: Leaf,
    pub normal: Leaf,
    pub center: Leaf,
    pub radius: Leaf,
    pub points: Leaf,
    pub gap: Leaf,
    pub friction: Leaf,
    pub mu: Leaf,
    pub threshold: Leaf,
    pub solver: Leaf,
    pub tolerance: Leaf,
    pub max_iterations: Leaf,
    pub omega: Leaf,
    pub motion: Leaf,
    pub name: Leaf,
    pub interface: Option<RawInterface>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [solver] table")]
pub(super) struct RawSolver {
    pub petsc_options: Leaf,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, expecting = "the [output] table")]
pub(super) struct RawOutput {
    pub dir: Leaf,
}

/// Every table with its allowed keys, as written in error messages. Serde reports an unknown key
/// with the list of allowed ones; matching that list against these names the table. Keep each
/// list equal (as a set) to its struct's fields: `tests/scene/syntax_and_keys.rs` checks every
/// table.
pub(super) const TABLE_KEYS: &[(&str, &[&str])] = &[
    (
        "the top level",
        &[
            "title",
            "mesh",
            "discretization",
            "material",
            "loads",
            "traction",
            "dirichlet",
            "contact",
            "solver",
            "output",
            "estimate",
            "body",
            "contact_pair",
            "evolution",
        ],
    ),
    (
        "[[body]]",
        &[
            "name",
            "rotate",
            "translate",
            "mesh",
            "discretization",
            "material",
            "loads",
            "traction",
            "dirichlet",
            "contact",
        ],
    ),
    ("[[contact_pair]]", &["slave", "master", "friction", "mu", "threshold", "max_initial_overlap", "interface"]),
    (
        "an interface table ([contact.interface] or [contact_pair.interface])",
        &[
            "law",
            "young",
            "poisson",
            "thickness",
            "bonded",
            "normal_stiffness",
            "tangential_stiffness",
            "adhesion_energy",
            "viscosity",
            "mu",
            "initial_adhesion",
            "cohesion",
            "tensile_strength",
            "fracture_energy_tension",
            "fracture_energy_shear",
            "trace",
        ],
    ),
    ("[mesh]", &["shape", "origin", "size", "center", "radius", "file", "geometry", "cell_size", "mesher", "refine"]),
    ("mesh.refine", &["point", "cell_size", "radius"]),
    ("[discretization]", &["order", "element", "formulation", "dual_constraints"]),
    ("[estimate]", &["enabled"]),
    ("[material]", &["young", "poisson", "plane"]),
    ("[loads]", &["body_force", "name"]),
    ("[[traction]]", &["part", "traction", "pressure", "name"]),
    ("[[dirichlet]]", &["part", "point", "ux", "uy", "name"]),
    (
        "[contact]",
        &[
            "part",
            "obstacle",
            "point",
            "normal",
            "center",
            "radius",
            "points",
            "gap",
            "friction",
            "mu",
            "threshold",
            "solver",
            "tolerance",
            "max_iterations",
            "omega",
            "motion",
            "name",
            "interface",
        ],
    ),
    ("[solver]", &["petsc_options"]),
    ("[output]", &["dir"]),
    ("[evolution]", &["steps", "times", "start", "monitor", "profiles", "factor"]),
];

fn span_of(leaf: &Leaf) -> Option<Range<usize>> {
    leaf.as_ref().map(|v| v.span())
}

/// The first present key's span among `leaves`, in file order.
pub(super) fn first_span(leaves: &[&Leaf]) -> Option<Range<usize>> {
    leaves.iter().filter_map(|l| span_of(l)).min_by_key(|s| s.start)
}

impl RawMesh {
    /// The keys written in `[mesh]`, each with the span of its value (for `refine`, of its first
    /// key).
    pub fn present_keys(&self) -> Vec<(&'static str, Range<usize>)> {
        let mut keys: Vec<(&'static str, Range<usize>)> = [
            ("shape", &self.shape),
            ("origin", &self.origin),
            ("size", &self.size),
            ("center", &self.center),
            ("radius", &self.radius),
            ("file", &self.file),
            ("geometry", &self.geometry),
            ("cell_size", &self.cell_size),
            ("mesher", &self.mesher),
        ]
        .into_iter()
        .filter_map(|(k, leaf)| span_of(leaf).map(|s| (k, s)))
        .collect();
        if let Some(refine) = &self.refine {
            keys.push(("refine", refine.first_span().unwrap_or(0..0)));
        }
        keys.sort_by_key(|(_, s)| s.start);
        keys
    }
    pub fn first_span(&self) -> Option<Range<usize>> {
        self.present_keys().first().map(|(_, s)| s.clone())
    }
}

impl RawRefine {
    pub fn first_span(&self) -> Option<Range<usize>> {
        first_span(&[&self.point, &self.cell_size, &self.radius])
    }
}

impl RawBody {
    /// The span of the first leaf key written directly in the `[[body]]` table.
    pub fn first_span(&self) -> Option<Range<usize>> {
        first_span(&[&self.name, &self.rotate, &self.translate])
    }
}

impl RawContactPair {
    pub fn first_span(&self) -> Option<Range<usize>> {
        first_span(&[&self.slave, &self.master, &self.friction, &self.mu, &self.threshold, &self.max_initial_overlap])
    }
}

impl RawInterface {
    /// The keys written in the interface table, each with the span of its value, in file order.
    pub fn present_keys(&self) -> Vec<(&'static str, Range<usize>)> {
        let mut keys: Vec<(&'static str, Range<usize>)> = [
            ("law", &self.law),
            ("young", &self.young),
            ("poisson", &self.poisson),
            ("thickness", &self.thickness),
            ("bonded", &self.bonded),
            ("normal_stiffness", &self.normal_stiffness),
            ("tangential_stiffness", &self.tangential_stiffness),
            ("adhesion_energy", &self.adhesion_energy),
            ("viscosity", &self.viscosity),
            ("mu", &self.mu),
            ("initial_adhesion", &self.initial_adhesion),
            ("cohesion", &self.cohesion),
            ("tensile_strength", &self.tensile_strength),
            ("fracture_energy_tension", &self.fracture_energy_tension),
            ("fracture_energy_shear", &self.fracture_energy_shear),
            ("trace", &self.trace),
        ]
        .into_iter()
        .filter_map(|(k, leaf)| span_of(leaf).map(|s| (k, s)))
        .collect();
        keys.sort_by_key(|(_, s)| s.start);
        keys
    }
}

impl RawContact {
    /// The keys written in `[contact]`, each with the span of its value, in file order.
    pub fn present_keys(&self) -> Vec<(&'static str, Range<usize>)> {
        let mut keys: Vec<(&'static str, Range<usize>)> = [
            ("part", &self.part),
            ("obstacle", &self.obstacle),
            ("point", &self.point),
            ("normal", &self.normal),
            ("center", &self.center),
            ("radius", &self.radius),
            ("points", &self.points),
            ("gap", &self.gap),
            ("friction", &self.friction),
            ("mu", &self.mu),
            ("threshold", &self.threshold),
            ("solver", &self.solver),
            ("tolerance", &self.tolerance),
            ("max_iterations", &self.max_iterations),
            ("omega", &self.omega),
            ("motion", &self.motion),
            ("name", &self.name),
        ]
        .into_iter()
        .filter_map(|(k, leaf)| span_of(leaf).map(|s| (k, s)))
        .collect();
        keys.sort_by_key(|(_, s)| s.start);
        keys
    }
}
