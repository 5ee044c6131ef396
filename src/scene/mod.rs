//! Scenes: one plane-elasticity problem described in a TOML file (format reference with a
//! complete example: `docs/scene-format.md`).
//!
//! # The problem a scene describes
//!
//! Find the displacement `u = (ux, uy)` of a body `Ω ⊂ R²` such that
//!
//! ```text
//!   -div σ(u) = f                 in Ω           f   = [loads] body_force        (N/m³)
//!   σ(u) = λ tr(ε(u)) I + 2μ ε(u)                ε(u) = (∇u + ∇uᵀ)/2
//!   u_i = g_i                     on a part      [[dirichlet]] ux and/or uy      (m)
//!   u_i = g_i                     at a node      [[dirichlet]] point = [x, y]
//!   σ(u) n = t                    on a part      [[traction]] traction = t       (N/m²)
//!   σ(u) n = -p n                 on a part      [[traction]] pressure = p       (N/m²)
//!   σ(u) n = 0                    on the rest of ∂Ω
//!   Signorini + friction          on a part      [contact] (see `contact`)
//! ```
//!
//! with `n` the unit outward normal, so a positive pressure pushes into the body. With an
//! `[evolution]` table (`evolution`, [`EvolutionSpec`]) the problem is solved along a load
//! path: each load (traction, prescribed displacement, body force, the obstacle's `motion`)
//! multiplied by a piecewise-linear factor of a pseudo-time, at a list of increments. Components
//! `i` not listed in a `[[dirichlet]]` table stay free on that part. From Young's modulus `E`
//! and Poisson's ratio `ν` (`[material]`), the Lamé constants are
//!
//! ```text
//!   plane strain (εzz = 0):   μ = E / (2(1+ν)),   λ = E ν / ((1+ν)(1-2ν))
//!   plane stress (σzz = 0):   μ = E / (2(1+ν)),   λ = E ν / (1-ν²)
//! ```
//!
//! (Timoshenko & Goodier, *Theory of Elasticity*, 3rd ed., §§ 16-17; Barber, *Elasticity*,
//! 3rd ed., § 3.1). Plane strain needs `-1 < ν < 1/2` (λ blows up at 1/2: incompressibility),
//! which is the range accepted for both models.
//!
//! A point condition fixes the one mesh node at the point: the node nearest to it, which must be
//! closer than [`POINT_TOLERANCE`] times the diagonal of the mesh's bounding box
//! ([`point_tolerance`]). A node of the contact part whose two components are both prescribed
//! cannot move, and is left out of the contact set by the solver.
//!
//! # Parsing
//!
//! The TOML text is first deserialized (serde, `deny_unknown_fields`) into the raw structs of
//! `raw`, whose leaves keep their byte spans; the conversion below then checks every value and
//! builds the plain spec types. Every mistake becomes [`Error::Scene`] with the 1-based line and
//! column of the offending value (or of the table header when a key is missing), a message
//! saying what is wrong and a hint saying what to do. Boundary part names can only be checked
//! once the mesh exists, and so can point conditions (is there a node at the point?):
//! [`Scene::check_against_mesh`].
//!
//! The tables of one body (`[mesh]` ... `[contact]`) are converted by `convert::body_data`,
//! called for the top level of a single-body scene and for every `[[body]]` of a scene with
//! several bodies (`bodies`: `[[body]]` and `[[contact_pair]]`, [`Scene::bodies`], and
//! [`BodiesModel`] for their meshes, their union and the overlap check). Scenes with several
//! bodies are solved by `problem::bodies` (`signorini run`); the other commands take one body.
//!
//! Adding a section: a raw struct and its key list in `raw`, a field in [`Scene`], a conversion
//! function called from [`Scene::from_str`] (in its own file if it is long, like `contact`), and
//! a table in `docs/scene-format.md`. A table of one body goes into `convert::BodyTables` and
//! `raw::RawBody` too, so that every `[[body]]` takes it.
mod bodies;
mod builder;
mod contact;
mod convert;
mod diagnostic;
mod evolution;
mod interface;
mod magnitudes;
mod model;
mod raw;

pub use bodies::{BodySpec, ContactPairSpec, PartRef, Placement, SINGLE_BODY_NAME};
pub use builder::{BodiesBuilder, SceneBuilder, BUILT_IN_RUST};
pub use contact::{ContactSolverSpec, ContactSpec, FrictionSpec, ObstacleSpec};
pub use evolution::{piecewise_linear, EvolutionSpec, LoadFunction, MAX_STEPS, TIME_TOLERANCE};
pub use interface::{CohesiveJointSpec, InterfaceLawSpec, InterfaceSpec, RccmSpec, ThinLayerSpec};
pub use model::{BodiesModel, DEFAULT_OVERLAP_FRACTION};

use crate::error::{Error, Location, Result};
use crate::fem::Element;
pub use crate::mesh::build::{MeshSpec, Mesher, RefineSpec};
use crate::mesh::{Mesh, Order};
use convert::{body_data, petsc_options, BodyData, BodyTables, Scope};
use diagnostic::{closest, Source};
use raw::RawScene;
use std::fmt;
use std::path::{Path, PathBuf};

/// The text of the built-in scene (`examples/scenes/default.toml`).
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../examples/scenes/default.toml");
/// The name [`Scene::default_scene`] reports errors and outputs under.
pub const DEFAULT_SCENE_SOURCE: &str = "<default scene>";
/// Generated meshes are refused beyond this estimated number of triangles (2·area / cell_size²):
/// a mistyped `cell_size` should be an error, not an exhausted memory.
pub const MAX_TRIANGLES: f64 = 1e7;
/// A point condition's node must lie within this fraction of the diagonal of the mesh's bounding
/// box from the point ([`point_tolerance`]).
pub const POINT_TOLERANCE: f64 = 1e-8;

/// A parsed and checked scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// The scene file, or `<default scene>`.
    pub source: PathBuf,
    /// `title`: a name for the problem, copied to the outputs.
    pub title: Option<String>,
    /// `[mesh]`: the geometry and how to mesh it.
    pub mesh: MeshSpec,
    /// Order of the triangles and of the Lagrange finite-element space.
    pub order: Order,
    /// `[discretization] element`: Lagrange (default) or the locking-free P2–P0 element.
    pub element: Element,
    /// `[discretization] formulation`: displacements (primal, the default) or stresses (dual).
    pub formulation: Formulation,
    /// `[discretization] dual_constraints`: how the dual's boundary constraints are imposed.
    pub dual_constraints: DualConstraints,
    /// `[estimate]`: also solve the other formulation and estimate the error (see
    /// [`crate::estimate`]).
    pub estimate: bool,
    /// `[material]`: Young's modulus, Poisson's ratio and the plane model.
    pub material: MaterialSpec,
    /// Body force per unit volume (N/m³), e.g. `[0, -ρ g]`.
    pub body_force: [f64; 2],
    /// `[loads] name`: the load name of the body force, whose factor table in
    /// `[evolution.factor]` multiplies it (see [`EvolutionSpec::factor`]).
    pub body_force_name: Option<String>,
    /// The `[[traction]]` tables, in file order.
    pub tractions: Vec<TractionSpec>,
    /// The `[[dirichlet]]` tables, in file order.
    pub dirichlet: Vec<DirichletSpec>,
    /// The `[contact]` table, if any.
    pub contact: Option<ContactSpec>,
    /// PETSc options from `[solver] petsc_options`, split on whitespace (command-line options are
    /// applied after these and so override them).
    pub petsc_options: Vec<String>,
    /// `[output] dir` as written (relative to the current directory, not to the scene).
    pub output_dir: Option<PathBuf>,
    /// The `[[body]]` tables, in file order; empty for a single-body scene (the fields above
    /// describe its one body). A scene with `[[body]]` tables has its first body's data in the
    /// single-body fields above (`mesh`, `order`, ..., `contact`), only so that code reading one
    /// body finds a valid one: [`Scene::bodies`] is the view of every scene as bodies; the driver
    /// solves such scenes on the bodies' union mesh (see [`Scene::has_body_tables`]).
    pub bodies: Vec<BodySpec>,
    /// The `[[contact_pair]]` tables, in file order (only with `[[body]]` tables).
    pub contact_pairs: Vec<ContactPairSpec>,
    /// A contact solver for the whole run, set by the command line (`--contact-solver`), not
    /// by the file: it replaces the `[contact]` table's `solver`, and with several bodies the
    /// solver of every contact (pairs included).
    pub contact_solver: Option<ContactSolverSpec>,
    /// `[evolution]`: a load path (every load multiplied by a factor of a pseudo-time, solved at
    /// a list of increments); `None`: one static solve with every load in full.
    pub evolution: Option<EvolutionSpec>,
}

/// Which field the scene is solved for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Formulation {
    /// Displacements (Lagrange elements): the default.
    #[default]
    Primal,
    /// Stresses: the Airy stress function on HCT elements ([`crate::dual`]).
    Dual,
}

impl Formulation {
    /// The name written in a scene: `"primal"` or `"dual"`.
    pub fn name(self) -> &'static str {
        match self {
            Formulation::Primal => "primal",
            Formulation::Dual => "dual",
        }
    }
}

/// How the boundary constraints of the dual formulation (the traction data on φ and ∂φ/∂n,
/// and the affine kernel) are imposed ([`crate::dual::saddle_point`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DualConstraints {
    /// Eliminated: the constrained dofs are expressed through the free ones, and the reduced
    /// system is symmetric positive definite (the default).
    #[default]
    Eliminated,
    /// Kept as rows of a saddle point with multipliers, symmetric indefinite (MUMPS LDLᵀ, or
    /// SYMMLQ with a positive definite preconditioner).
    Multipliers,
}

impl DualConstraints {
    /// The name written in a scene: `"eliminated"` or `"multipliers"`.
    pub fn name(self) -> &'static str {
        match self {
            DualConstraints::Eliminated => "eliminated",
            DualConstraints::Multipliers => "multipliers",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
/// A homogeneous, isotropic, linear elastic material (`[material]`).
pub struct MaterialSpec {
    /// Young's modulus E (Pa), finite and > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (-1, 0.5).
    pub poisson: f64,
    /// Plane strain, plane stress or axisymmetric.
    pub plane: PlaneSpec,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// The plane model of the 2D problem (`[material] plane`).
pub enum PlaneSpec {
    /// εzz = 0: a long body loaded uniformly along z.
    Strain,
    /// σzz = 0: a thin plate loaded in its plane.
    Stress,
    /// A body of revolution: the mesh is its meridian half-plane `(r, z) = (x, y)`, `r ≥ 0`;
    /// forces are for the full revolution.
    Axisymmetric,
}

impl PlaneSpec {
    /// The scene's spelling: "strain", "stress" or "axisymmetric".
    pub fn name(self) -> &'static str {
        match self {
            PlaneSpec::Strain => "strain",
            PlaneSpec::Stress => "stress",
            PlaneSpec::Axisymmetric => "axisymmetric",
        }
    }
}

/// Prescribed displacement components on a boundary part or at a node.
#[derive(Debug, Clone, PartialEq)]
pub struct DirichletSpec {
    /// The boundary part or the node whose displacement is prescribed.
    pub target: DirichletTarget,
    /// Prescribed x displacement (m); `None` leaves it free.
    pub ux: Option<f64>,
    /// Prescribed y displacement (m); `None` leaves it free.
    pub uy: Option<f64>,
    /// `name`: the load name whose factor table multiplies the prescribed components
    /// ([`EvolutionSpec::factor`]); `None`: the proportional ramp.
    pub name: Option<String>,
    /// Where `part = ...` or `point = ...` is written, for errors found later (unknown part, no
    /// node at the point).
    pub at: Location,
}

/// What a `[[dirichlet]]` table fixes.
#[derive(Debug, Clone, PartialEq)]
pub enum DirichletTarget {
    /// Every node of a boundary part (P2 mid nodes included): `part = "left"`.
    Part(String),
    /// The mesh node at this point: `point = [x, y]` (see [`point_tolerance`]).
    Point([f64; 2]),
}

/// The part's name, or `point [x, y]` (the name of a point condition's reaction in reports).
impl fmt::Display for DirichletTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DirichletTarget::Part(name) => write!(f, "{name}"),
            DirichletTarget::Point(p) => write!(f, "point [{}, {}]", p[0], p[1]),
        }
    }
}

impl DirichletSpec {
    /// The mesh nodes this condition fixes, in increasing order: the nodes of the part's edges
    /// (P2 mid nodes included), or the one node at the point. [`Error::Scene`] at [`Self::at`]
    /// for a part that is not a boundary part of `mesh`, or a point with no node.
    pub fn nodes(&self, mesh: &Mesh) -> Result<Vec<usize>> {
        match &self.target {
            DirichletTarget::Part(part) => {
                let group = boundary_group(mesh, part, &self.at)?;
                Ok(mesh.group_nodes(group))
            }
            DirichletTarget::Point(point) => Ok(vec![node_at(mesh, *point, &self.at)?]),
        }
    }
}

/// The node of `mesh` nearest to `point` and its distance (the first such node on a tie), or
/// `None` for a mesh without nodes.
pub fn nearest_node(mesh: &Mesh, point: [f64; 2]) -> Option<(usize, f64)> {
    mesh.nodes.iter().map(|p| (p[0] - point[0]).hypot(p[1] - point[1])).enumerate().fold(
        None,
        |best, (i, d)| match best {
            Some((_, b)) if b <= d => best,
            _ => Some((i, d)),
        },
    )
}

/// [`POINT_TOLERANCE`] times the diagonal of the bounding box of the mesh's nodes: the largest
/// distance from a point condition's point to its node.
pub fn point_tolerance(mesh: &Mesh) -> f64 {
    POINT_TOLERANCE * mesh.diagonal()
}

/// The node at `point` (within [`point_tolerance`]), or [`Error::Scene`] at `at`.
fn node_at(mesh: &Mesh, point: [f64; 2], at: &Location) -> Result<usize> {
    let tolerance = point_tolerance(mesh);
    let shown = DirichletTarget::Point(point);
    match nearest_node(mesh, point) {
        Some((node, distance)) if distance <= tolerance => Ok(node),
        Some((node, distance)) => {
            let p = mesh.nodes[node];
            Err(Error::Scene {
                location: at.clone(),
                message: format!(
                    "the mesh has no node at {shown}: the nearest, node {node} at [{}, {}], is {distance:.3e} away",
                    p[0], p[1]
                ),
                hint: format!(
                    "a point condition fixes one mesh node: give the coordinates of a node, e.g. a corner of the \
                     domain or a geometry point of its shape (to within {tolerance:.1e}, {POINT_TOLERANCE:e} times \
                     the mesh's extent)"
                ),
            })
        }
        None => Err(Error::Scene {
            location: at.clone(),
            message: format!("the mesh has no node at {shown}: it has no nodes at all"),
            hint: "check the mesh".to_string(),
        }),
    }
}

/// The index of the boundary group `part` of `mesh`, or [`Error::Scene`] at `at` naming the
/// mesh's boundary parts (and the closest one).
fn boundary_group(mesh: &Mesh, part: &str, at: &Location) -> Result<usize> {
    if let Some(group) = mesh.group_index(part, 1) {
        return Ok(group);
    }
    let names: Vec<&str> = mesh.groups.iter().filter(|g| g.dim == 1).map(|g| g.name.as_str()).collect();
    let message = match mesh.group_index(part, 2) {
        Some(_) => format!("`{part}` is a region (surface group) of the mesh, not a boundary part"),
        None => format!("the mesh has no boundary part named `{part}`"),
    };
    let known = match names.is_empty() {
        true => "the mesh has no named boundary parts: give its boundary curves physical names".to_string(),
        false => format!("the mesh's boundary parts are: {}", names.join(", ")),
    };
    let hint = match closest(part, &names) {
        Some(guess) => format!("did you mean `{guess}`? {known}"),
        None => known,
    };
    Err(Error::Scene { location: at.clone(), message, hint })
}

/// A surface load on a boundary part.
#[derive(Debug, Clone, PartialEq)]
pub struct TractionSpec {
    /// The boundary part loaded.
    pub part: String,
    /// The traction or pressure on it.
    pub load: Load,
    /// `name`: the load name whose factor table multiplies it ([`EvolutionSpec::factor`]);
    /// `None`: the proportional ramp.
    pub name: Option<String>,
    /// Where `part = ...` is written, for errors found later (unknown part).
    pub at: Location,
}

#[derive(Debug, Clone, Copy, PartialEq)]
/// A surface load (`traction` or `pressure` of a `[[traction]]` table).
pub enum Load {
    /// σ n = t, a force per unit area in global x and y (N/m²).
    Traction([f64; 2]),
    /// σ n = -p n: a normal pressure (N/m²), positive pushes into the body.
    Pressure(f64),
}

impl Scene {
    /// Read and parse a scene file.
    pub fn from_file(path: &Path) -> Result<Scene> {
        let bytes = std::fs::read(path).map_err(|e| Error::io(path, "reading the scene file", e))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            // Located like any other mistake: the line and column of the first bad byte.
            let good = &e.as_bytes()[..e.utf8_error().valid_up_to()];
            let line = 1 + good.iter().filter(|&&b| b == b'\n').count();
            let line_start = good.iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
            let column = 1 + String::from_utf8_lossy(&good[line_start..]).chars().count();
            let byte = e.as_bytes()[e.utf8_error().valid_up_to()];
            Error::Scene {
                location: crate::error::Location { file: path.to_path_buf(), line, column },
                message: format!("the scene is not valid UTF-8 text (byte 0x{byte:02x})"),
                hint: "save the scene file as UTF-8 (TOML files are UTF-8)".into(),
            }
        })?;
        Scene::from_str(&text, path)
    }

    /// Parse scene text; `source` names it in errors and anchors relative mesh-file paths (they
    /// are resolved against `source`'s directory).
    #[allow(clippy::should_implement_trait)]
    pub fn from_str(text: &str, source: &Path) -> Result<Scene> {
        let src = Source { file: source, text };
        let raw: RawScene = toml::from_str(text).map_err(|e| src.toml_error(&e))?;
        let scene_dir = source.parent().unwrap_or(Path::new(""));

        let title = raw.title.as_ref().map(|v| src.string(v, "title").map(str::to_string)).transpose()?;
        // One body at the top level, or several in [[body]] tables (`bodies`); the top-level
        // fields of a scene with [[body]] tables are those of its first body.
        let (data, bodies, contact_pairs) = match raw.body.is_empty() {
            true => {
                bodies::refuse_pairs_without_bodies(&src, &raw)?;
                let tables = BodyTables {
                    mesh: raw.mesh.as_ref(),
                    discretization: raw.discretization.as_ref(),
                    material: raw.material.as_ref(),
                    loads: raw.loads.as_ref(),
                    traction: &raw.traction,
                    dirichlet: &raw.dirichlet,
                    contact: raw.contact.as_ref(),
                };
                (body_data(&src, &Scope::top_level(text), &tables, scene_dir)?, Vec::new(), Vec::new())
            }
            false => {
                bodies::refuse_top_level_body_tables(&src, &raw)?;
                let bodies = bodies::body_specs(&src, &raw.body, scene_dir)?;
                let pairs = bodies::contact_pair_specs(&src, &raw.contact_pair, &bodies)?;
                (bodies[0].data(), bodies, pairs)
            }
        };
        let formulation = match raw.discretization.as_ref().and_then(|d| d.formulation.as_ref()) {
            Some(v) => match src.choice(v, "formulation", &["primal", "dual"])? {
                "dual" => Formulation::Dual,
                _ => Formulation::Primal,
            },
            None => Formulation::Primal,
        };
        let dual_constraints = match raw.discretization.as_ref().and_then(|d| d.dual_constraints.as_ref()) {
            Some(v) => match src.choice(v, "dual_constraints", &["eliminated", "multipliers"])? {
                "multipliers" => DualConstraints::Multipliers,
                _ => DualConstraints::Eliminated,
            },
            None => DualConstraints::Eliminated,
        };
        let estimate = match &raw.estimate {
            None => false,
            Some(e) => match e.enabled.as_ref() {
                None => true,
                Some(v) => match v.get_ref() {
                    toml::Value::Boolean(b) => *b,
                    _ => {
                        return Err(src.error(
                            &v.span(),
                            format!("`enabled` must be true or false, found {}", src.written(v)),
                            "write enabled = true (or remove the [estimate] table)",
                        ))
                    }
                },
            },
        };
        let petsc_options = match raw.solver.as_ref().and_then(|s| s.petsc_options.as_ref()) {
            Some(v) => petsc_options(&src, v)?,
            None => Vec::new(),
        };
        let output_dir = match raw.output.as_ref().and_then(|o| o.dir.as_ref()) {
            Some(v) => Some(PathBuf::from(src.nonempty_string(v, "dir")?)),
            None => None,
        };
        let evolution = match &raw.evolution {
            Some(e) => {
                let names: Vec<&str> = bodies.iter().map(|b: &BodySpec| b.name.as_str()).collect();
                Some(evolution::evolution_spec(&src, e, &evolution::load_names(&raw), &names)?)
            }
            None => None,
        };
        if raw.evolution.is_none() {
            let rigid = raw.contact.iter().chain(raw.body.iter().filter_map(|b| b.contact.as_ref()));
            let interfaces = rigid
                .filter_map(|c| c.interface.as_ref())
                .chain(raw.contact_pair.iter().filter_map(|p| p.interface.as_ref()));
            interface::memory_law_without_evolution(&src, interfaces)?;
        }
        let BodyData { mesh, order, element, material, body_force, body_force_name, tractions, dirichlet, contact } =
            data;
        Ok(Scene {
            source: source.to_path_buf(),
            title,
            mesh,
            order,
            element,
            formulation,
            dual_constraints,
            estimate,
            material,
            body_force,
            body_force_name,
            tractions,
            dirichlet,
            contact,
            petsc_options,
            output_dir,
            contact_solver: None,
            bodies,
            contact_pairs,
            evolution,
        })
    }

    /// The built-in scene ([`DEFAULT_SCENE_TOML`]), reported as `<default scene>`.
    pub fn default_scene() -> Scene {
        // The text is part of the binary and parsed by the test suite: this cannot fail.
        Scene::from_str(DEFAULT_SCENE_TOML, Path::new(DEFAULT_SCENE_SOURCE))
            .expect("the built-in examples/scenes/default.toml is a valid scene")
    }

    /// Every boundary part the scene names, with where it is named: tractions, Dirichlet
    /// parts, the contact part, each in file order. For a scene with `[[body]]` tables: its
    /// first body's (every body's: [`BodySpec::boundary_parts`] of [`Scene::bodies`]).
    pub fn boundary_parts(&self) -> impl Iterator<Item = (&str, &Location)> {
        bodies::named_parts(&self.tractions, &self.dirichlet, self.contact.as_ref())
    }

    /// Check that every part named by the scene is a boundary (dimension-1) group of `mesh`,
    /// and that every point condition's point is a node of `mesh`; and the `[evolution]`
    /// `monitor` part of a single-body scene. For a scene with `[[body]]` tables this checks the
    /// first body only: [`BodiesModel::on_meshes`] checks them all, and the monitor.
    pub fn check_against_mesh(&self, mesh: &Mesh) -> Result<()> {
        bodies::check_named_against_mesh(mesh, &self.tractions, &self.dirichlet, self.contact.as_ref())?;
        if let Some(EvolutionSpec { monitor: Some(part), monitor_at, .. }) = &self.evolution {
            if !self.has_body_tables() {
                boundary_group(mesh, part, monitor_at.as_ref().unwrap_or(&self.evolution_location()))?;
            }
        }
        Ok(())
    }

    /// Where `[evolution]` is written (the start of the file without one).
    fn evolution_location(&self) -> Location {
        match &self.evolution {
            Some(e) => e.at.clone(),
            None => Location { file: self.source.clone(), line: 1, column: 1 },
        }
    }
}
