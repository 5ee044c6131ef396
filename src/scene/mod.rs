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
//! with `n` the unit outward normal, so a positive pressure pushes into the body. Components
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
//! Adding a section: a raw struct and its key list in `raw`, a field in [`Scene`], a conversion
//! function called from [`Scene::from_str`] (in its own file if it is long, like `contact`), and
//! a table in `docs/scene-format.md`.
mod builder;
mod contact;
mod diagnostic;
mod magnitudes;
mod raw;

pub use builder::{SceneBuilder, BUILT_IN_RUST};
pub use contact::{ContactSolverSpec, ContactSpec, FrictionSpec, ObstacleSpec};

use crate::error::{Error, Location, Result};
use crate::fem::Element;
use crate::mesh::{Mesh, Order};
use diagnostic::{closest, describe, Source};
use raw::{first_span, Leaf, RawDirichlet, RawMesh, RawRefine, RawScene, RawTraction};
use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::{Spanned, Value};

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
    pub title: Option<String>,
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
    pub material: MaterialSpec,
    /// Body force per unit volume (N/m³), e.g. `[0, -ρ g]`.
    pub body_force: [f64; 2],
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
    pub fn name(self) -> &'static str {
        match self {
            DualConstraints::Eliminated => "eliminated",
            DualConstraints::Multipliers => "multipliers",
        }
    }
}

/// The geometry and how to mesh it.
#[derive(Debug, Clone, PartialEq)]
pub enum MeshSpec {
    /// `[origin, origin + size]`; boundary parts `bottom`, `right`, `top`, `left`.
    Rectangle { origin: [f64; 2], size: [f64; 2], cell_size: f64, mesher: Mesher, refine: Option<RefineSpec> },
    /// Full disc; boundary part `circle`. Always meshed by gmsh.
    Disc { center: [f64; 2], radius: f64, cell_size: f64, refine: Option<RefineSpec> },
    /// Lower half disc (flat side on top, at `center.y`); boundary parts `arc` and `flat`.
    /// Always meshed by gmsh.
    HalfDisc { center: [f64; 2], radius: f64, cell_size: f64, refine: Option<RefineSpec> },
    /// A Gmsh MSH 4.1 file; the path is already resolved against the scene's directory.
    /// `geometry`: the Gmsh `.geo` script the file was meshed from (`geometry = "part.geo"`),
    /// which `signorini adapt` remeshes with its size map.
    File { path: PathBuf, geometry: Option<PathBuf> },
}

/// Who meshes a rectangle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mesher {
    /// A uniform grid of right triangles (no gmsh needed).
    Structured,
    /// An unstructured gmsh mesh.
    Gmsh,
}

/// Local refinement for gmsh: cells of size about `cell_size` within `radius` of `point`,
/// growing back to the mesh's `cell_size` away from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefineSpec {
    pub point: [f64; 2],
    pub cell_size: f64,
    pub radius: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MaterialSpec {
    /// Young's modulus E (Pa), finite and > 0.
    pub young: f64,
    /// Poisson's ratio ν, in (-1, 0.5).
    pub poisson: f64,
    pub plane: PlaneSpec,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlaneSpec {
    /// εzz = 0: a long body loaded uniformly along z.
    Strain,
    /// σzz = 0: a thin plate loaded in its plane.
    Stress,
}

/// Prescribed displacement components on a boundary part or at a node.
#[derive(Debug, Clone, PartialEq)]
pub struct DirichletSpec {
    pub target: DirichletTarget,
    pub ux: Option<f64>,
    pub uy: Option<f64>,
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
                let mut nodes: Vec<usize> = mesh.edges_in_group(group).flat_map(|e| mesh.edge(e).to_vec()).collect();
                nodes.sort_unstable();
                nodes.dedup();
                Ok(nodes)
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
    pub part: String,
    pub load: Load,
    /// Where `part = ...` is written, for errors found later (unknown part).
    pub at: Location,
}

#[derive(Debug, Clone, Copy, PartialEq)]
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
        let Some(raw_mesh) = &raw.mesh else {
            return Err(src.error(
                &(0..0),
                "the scene has no [mesh] table",
                "add a [mesh] table, e.g. [mesh] shape = \"rectangle\", size = [1.0, 0.2], cell_size = 0.02",
            ));
        };
        let mesh = mesh_spec(&src, raw_mesh, scene_dir)?;
        let order = order(&src, raw.discretization.as_ref().and_then(|d| d.order.as_ref()))?;
        let Some(raw_material) = &raw.material else {
            return Err(src.error(
                &(0..0),
                "the scene has no [material] table",
                "add a [material] table, e.g. [material] young = 210e9, poisson = 0.3",
            ));
        };
        let material = material_spec(&src, raw_material)?;
        let element = element(&src, raw.discretization.as_ref().and_then(|d| d.element.as_ref()), order, &material)?;
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
        let body_force = match raw.loads.as_ref().and_then(|l| l.body_force.as_ref()) {
            Some(v) => src.vector(v, "body_force")?,
            None => [0.0; 2],
        };
        let tractions =
            raw.traction.iter().enumerate().map(|(i, t)| traction_spec(&src, t, i)).collect::<Result<Vec<_>>>()?;
        let dirichlet =
            raw.dirichlet.iter().enumerate().map(|(i, d)| dirichlet_spec(&src, d, i)).collect::<Result<Vec<_>>>()?;
        let contact = raw.contact.as_ref().map(|c| contact::contact_spec(&src, c, &dirichlet)).transpose()?;
        let petsc_options = match raw.solver.as_ref().and_then(|s| s.petsc_options.as_ref()) {
            Some(v) => petsc_options(&src, v)?,
            None => Vec::new(),
        };
        let output_dir = match raw.output.as_ref().and_then(|o| o.dir.as_ref()) {
            Some(v) => Some(PathBuf::from(src.nonempty_string(v, "dir")?)),
            None => None,
        };
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
            tractions,
            dirichlet,
            contact,
            petsc_options,
            output_dir,
        })
    }

    /// The built-in scene ([`DEFAULT_SCENE_TOML`]), reported as `<default scene>`.
    pub fn default_scene() -> Scene {
        // The text is part of the binary and parsed by the test suite: this cannot fail.
        Scene::from_str(DEFAULT_SCENE_TOML, Path::new(DEFAULT_SCENE_SOURCE))
            .expect("the built-in examples/scenes/default.toml is a valid scene")
    }

    /// Every boundary part the scene names, with where it is named: tractions, Dirichlet
    /// parts, the contact part, each in file order.
    pub fn boundary_parts(&self) -> impl Iterator<Item = (&str, &Location)> {
        let t = self.tractions.iter().map(|t| (t.part.as_str(), &t.at));
        let d = self.dirichlet.iter().filter_map(|d| match &d.target {
            DirichletTarget::Part(part) => Some((part.as_str(), &d.at)),
            DirichletTarget::Point(_) => None,
        });
        let c = self.contact.iter().map(|c| (c.part.as_str(), &c.at));
        t.chain(d).chain(c)
    }

    /// Check that every part named by the scene is a boundary (dimension-1) group of `mesh`,
    /// and that every point condition's point is a node of `mesh`.
    pub fn check_against_mesh(&self, mesh: &Mesh) -> Result<()> {
        for (part, at) in self.boundary_parts() {
            boundary_group(mesh, part, at)?;
        }
        for d in &self.dirichlet {
            if let DirichletTarget::Point(point) = d.target {
                node_at(mesh, point, &d.at)?;
            }
        }
        Ok(())
    }
}

// ---- conversion, one function per table -------------------------------------------------------

/// A table being converted: its display name and where to point when a key is missing.
struct Table<'s, 'a> {
    src: &'s Source<'a>,
    name: String,
    span: Range<usize>,
}

impl<'s, 'a> Table<'s, 'a> {
    /// `header` is found as `[header]` (or `[[header]]`, the `occurrence`-th); a table written
    /// inline or with dotted keys is located by its first key, else by `fallback`.
    fn locate(
        src: &'s Source<'a>,
        name: impl Into<String>,
        header: (&str, bool, usize),
        first_key: Option<Range<usize>>,
        fallback: Range<usize>,
    ) -> Self {
        let span = src.table_header(header.0, header.1, header.2).or(first_key).unwrap_or(fallback);
        Table { src, name: name.into(), span }
    }

    fn require<'v>(&self, leaf: &'v Leaf, key: &str, example: &str) -> Result<&'v Spanned<Value>> {
        leaf.as_ref().ok_or_else(|| {
            self.src.error(&self.span, format!("{} is missing `{key}`", self.name), format!("add `{example}`"))
        })
    }
}

const SHAPES: &[&str] = &["rectangle", "disc", "half_disc", "file"];
const MESHERS: &[&str] = &["structured", "gmsh"];
const RECTANGLE_KEYS: &[&str] = &["shape", "origin", "size", "cell_size", "mesher", "refine"];
const DISC_KEYS: &[&str] = &["shape", "center", "radius", "cell_size", "refine"];
const FILE_KEYS: &[&str] = &["shape", "file", "geometry"];

fn mesh_spec(src: &Source, m: &RawMesh, scene_dir: &Path) -> Result<MeshSpec> {
    let table = Table::locate(src, "[mesh]", ("mesh", false, 0), m.first_span(), 0..0);
    let shape_v = table.require(&m.shape, "shape", "shape = \"rectangle\" (or \"disc\", \"half_disc\", \"file\")")?;
    let shape = src.choice(shape_v, "shape", SHAPES)?;
    let allowed = match shape {
        "rectangle" => RECTANGLE_KEYS,
        "disc" | "half_disc" => DISC_KEYS,
        _ => FILE_KEYS,
    };
    if let Some((key, span)) = m.present_keys().into_iter().find(|(k, _)| !allowed.contains(k)) {
        let hint = match (shape, key) {
            ("file", _) => format!("a mesh file is used as it is: remove `{key}` (refine the mesh in gmsh instead)"),
            (_, "mesher") => "disc and half_disc meshes are always made by gmsh: remove `mesher`".to_string(),
            _ => format!("remove `{key}`; shape = \"{shape}\" takes {}", allowed.join(", ")),
        };
        return Err(src.error(&span, format!("`{key}` does not apply to shape = \"{shape}\""), hint));
    }
    let table = Table { name: format!("[mesh] with shape = \"{shape}\""), ..table };

    if shape == "file" {
        let v = table.require(&m.file, "file", "file = \"part.msh\" (a Gmsh MSH 4.1 file)")?;
        let name = src.nonempty_string(v, "file")?;
        let path = scene_dir.join(name);
        if !path.is_file() {
            let what = if path.is_dir() { "is a directory" } else { "does not exist" };
            return Err(src.error(
                &v.span(),
                format!("mesh file `{name}` {what} (looked for {})", path.display()),
                "check the name; a relative path is read from the scene file's directory",
            ));
        }
        let geometry = match &m.geometry {
            None => None,
            Some(v) => {
                let name = src.nonempty_string(v, "geometry")?;
                let geometry = scene_dir.join(name);
                if !geometry.is_file() {
                    return Err(src.error(
                        &v.span(),
                        format!("geometry script `{name}` does not exist (looked for {})", geometry.display()),
                        "give the Gmsh .geo script the mesh file was made from; a relative path is read from the \
                         scene file's directory",
                    ));
                }
                Some(geometry)
            }
        };
        return Ok(MeshSpec::File { path, geometry });
    }

    let cell_v = table.require(&m.cell_size, "cell_size", "cell_size = 0.05 (target edge length)")?;
    let cell_size = src.positive(cell_v, "cell_size", "a target edge length")?;
    let vector_or_zero = |leaf: &Leaf, key| leaf.as_ref().map(|v| src.vector(v, key)).transpose();
    let mut spec = match shape {
        "rectangle" => {
            let origin = vector_or_zero(&m.origin, "origin")?.unwrap_or([0.0; 2]);
            let size_v = table.require(&m.size, "size", "size = [width, height]")?;
            let size = src.vector(size_v, "size")?;
            if size[0] <= 0.0 || size[1] <= 0.0 {
                return Err(src.error(
                    &size_v.span(),
                    format!("`size` must be positive in both directions, found {}", src.written(size_v)),
                    "write size = [width, height] with width > 0 and height > 0 (use `origin` to place the corner)",
                ));
            }
            let mesher = match &m.mesher {
                Some(v) if src.choice(v, "mesher", MESHERS)? == "gmsh" => Mesher::Gmsh,
                _ => Mesher::Structured,
            };
            MeshSpec::Rectangle { origin, size, cell_size, mesher, refine: None }
        }
        _ => {
            let center = vector_or_zero(&m.center, "center")?.unwrap_or([0.0; 2]);
            let radius_v = table.require(&m.radius, "radius", "radius = 1.0")?;
            let radius = src.positive(radius_v, "radius", "a radius")?;
            match shape {
                "disc" => MeshSpec::Disc { center, radius, cell_size, refine: None },
                _ => MeshSpec::HalfDisc { center, radius, cell_size, refine: None },
            }
        }
    };
    let area = match &spec {
        MeshSpec::Rectangle { size, .. } => size[0] * size[1],
        MeshSpec::Disc { radius, .. } => std::f64::consts::PI * radius * radius,
        MeshSpec::HalfDisc { radius, .. } => std::f64::consts::PI * radius * radius / 2.0,
        MeshSpec::File { .. } => 0.0,
    };
    check_cell_count(src, cell_v, "cell_size", cell_size, area)?;
    if let Some(r) = &m.refine {
        let fallback = table.span.clone();
        let rt = Table::locate(src, "mesh.refine", ("mesh.refine", false, 0), r.first_span(), fallback);
        if let MeshSpec::Rectangle { mesher: Mesher::Structured, .. } = spec {
            return Err(src.error(
                &rt.span,
                "`refine` needs mesher = \"gmsh\"",
                "the structured mesher makes a uniform grid: add mesher = \"gmsh\" to [mesh], or remove refine",
            ));
        }
        let parsed = refine_spec(src, r, rt, cell_size)?;
        match &mut spec {
            MeshSpec::Rectangle { refine, .. } | MeshSpec::Disc { refine, .. } | MeshSpec::HalfDisc { refine, .. } => {
                *refine = Some(parsed)
            }
            MeshSpec::File { .. } => {}
        }
    }
    Ok(spec)
}

fn refine_spec(src: &Source, r: &RawRefine, table: Table, mesh_cell_size: f64) -> Result<RefineSpec> {
    let point = src.vector(table.require(&r.point, "point", "point = [x, y]")?, "point")?;
    let cell_v = table.require(&r.cell_size, "cell_size", "cell_size = 0.01 (the edge length near point)")?;
    let cell_size = src.positive(cell_v, "cell_size", "a target edge length")?;
    if cell_size > mesh_cell_size {
        return Err(src.error(
            &cell_v.span(),
            format!(
                "refine's `cell_size` ({}) is larger than the mesh's cell_size ({mesh_cell_size})",
                src.written(cell_v)
            ),
            "a refinement needs a smaller cell_size than [mesh] cell_size",
        ));
    }
    let radius_v = table.require(&r.radius, "radius", "radius = 0.1 (the size of the refined zone)")?;
    let radius = src.positive(radius_v, "radius", "the radius of the refined zone")?;
    let area = std::f64::consts::PI * radius * radius;
    check_cell_count(src, cell_v, "refine's cell_size", cell_size, area)?;
    Ok(RefineSpec { point, cell_size, radius })
}

fn check_cell_count(src: &Source, cell_v: &Spanned<Value>, key: &str, cell_size: f64, area: f64) -> Result<()> {
    let estimate = 2.0 * area / (cell_size * cell_size);
    if estimate > MAX_TRIANGLES {
        return Err(src.error(
            &cell_v.span(),
            format!("{key} = {} would make about {estimate:.1e} triangles", src.written(cell_v)),
            format!(
                "use a larger {key} (at most {MAX_TRIANGLES:.0e} triangles are accepted: 2·area / cell_size² ≤ {MAX_TRIANGLES:.0e})"
            ),
        ));
    }
    Ok(())
}

fn order(src: &Source, v: Option<&Spanned<Value>>) -> Result<Order> {
    match v.map(|v| (v, v.get_ref())) {
        None => Ok(Order::P1),
        Some((_, Value::Integer(1))) => Ok(Order::P1),
        Some((_, Value::Integer(2))) => Ok(Order::P2),
        Some((v, other)) => Err(src.error(
            &v.span(),
            format!("`order` must be 1 or 2, found {}", describe(other)),
            "write order = 1 for linear (P1) triangles or order = 2 for quadratic (P2) triangles",
        )),
    }
}

/// `[discretization] element`: "lagrange" (default) or "p2p0", the latter only with `order = 2`
/// in plane strain (P1 cells have a constant divergence already, and plane stress does not lock).
fn element(src: &Source, v: Option<&Spanned<Value>>, order: Order, material: &MaterialSpec) -> Result<Element> {
    let Some(v) = v else {
        return Ok(Element::Lagrange);
    };
    if src.choice(v, "element", &["lagrange", "p2p0"])? == "lagrange" {
        return Ok(Element::Lagrange);
    }
    if order != Order::P2 {
        return Err(src.error(
            &v.span(),
            "element = \"p2p0\" needs quadratic triangles, but the scene uses order = 1",
            "add order = 2 to [discretization] (P2 displacements with a cell-wise constant pressure)",
        ));
    }
    if material.plane == PlaneSpec::Stress {
        return Err(src.error(
            &v.span(),
            "element = \"p2p0\" is for plane strain, but [material] plane = \"stress\"",
            "remove `element` (plane stress does not lock: its in-plane Lamé constant stays below E), or use plane = \"strain\"",
        ));
    }
    Ok(Element::P2P0)
}

fn material_spec(src: &Source, m: &raw::RawMaterial) -> Result<MaterialSpec> {
    let first = first_span(&[&m.young, &m.poisson, &m.plane]);
    let table = Table::locate(src, "[material]", ("material", false, 0), first, 0..0);
    let young_v = table.require(&m.young, "young", "young = 210e9 (Young's modulus in Pa)")?;
    let young = src.number(young_v, "young")?;
    if young <= 0.0 {
        return Err(src.error(
            &young_v.span(),
            format!("`young` must be positive, found {}", src.written(young_v)),
            "Young's modulus is in Pa and must be > 0, e.g. young = 210e9 for steel, 70e9 for aluminium",
        ));
    }
    let poisson_v = table.require(&m.poisson, "poisson", "poisson = 0.3 (Poisson's ratio, in (-1, 0.5))")?;
    let poisson = src.number(poisson_v, "poisson")?;
    if poisson >= 0.5 {
        return Err(src.error(
            &poisson_v.span(),
            format!("`poisson` must be below 0.5, found {}", src.written(poisson_v)),
            "0.5 is an incompressible material, which a displacement formulation cannot represent: use a \
             value < 0.5 (nearly incompressible, e.g. 0.4999: use order = 2 with element = \"p2p0\", since P1 \
             and P2 displacements lock)",
        ));
    }
    if poisson <= -1.0 {
        return Err(src.error(
            &poisson_v.span(),
            format!("`poisson` must be above -1, found {}", src.written(poisson_v)),
            "a stable isotropic material has -1 < poisson < 0.5 (metals: about 0.3)",
        ));
    }
    let plane = match &m.plane {
        Some(v) if src.choice(v, "plane", &["strain", "stress"])? == "stress" => PlaneSpec::Stress,
        _ => PlaneSpec::Strain,
    };
    Ok(MaterialSpec { young, poisson, plane })
}

fn part_name(src: &Source, table: &Table, leaf: &Leaf) -> Result<(String, Location)> {
    let v = table.require(leaf, "part", "part = \"left\" (a boundary physical name of the mesh)")?;
    Ok((src.nonempty_string(v, "part")?.to_string(), src.location(v.span().start)))
}

fn traction_spec(src: &Source, t: &RawTraction, index: usize) -> Result<TractionSpec> {
    let first = first_span(&[&t.part, &t.traction, &t.pressure]);
    let table = Table::locate(src, "this [[traction]] table", ("traction", true, index), first, 0..0);
    let (part, at) = part_name(src, &table, &t.part)?;
    let load = match (&t.traction, &t.pressure) {
        (Some(v), None) => Load::Traction(src.vector(v, "traction")?),
        (None, Some(v)) => Load::Pressure(src.number(v, "pressure")?),
        (Some(_), Some(p)) => {
            return Err(src.error(
                &p.span(),
                format!("the [[traction]] on `{part}` gives both `traction` and `pressure`"),
                "keep one (write a second [[traction]] table on the same part to add the other)",
            ))
        }
        (None, None) => {
            return Err(src.error(
                &table.span,
                format!("the [[traction]] on `{part}` has neither `traction` nor `pressure`"),
                "add traction = [tx, ty] (force per area, N/m²) or pressure = p (normal, positive pushes \
                 into the body)",
            ))
        }
    };
    Ok(TractionSpec { part, load, at })
}

fn dirichlet_spec(src: &Source, d: &RawDirichlet, index: usize) -> Result<DirichletSpec> {
    let first = first_span(&[&d.part, &d.point, &d.ux, &d.uy]);
    let table = Table::locate(src, "this [[dirichlet]] table", ("dirichlet", true, index), first, 0..0);
    let (target, at) = match (&d.part, &d.point) {
        (Some(_), None) => {
            let (part, at) = part_name(src, &table, &d.part)?;
            (DirichletTarget::Part(part), at)
        }
        (None, Some(v)) => (DirichletTarget::Point(src.vector(v, "point")?), src.location(v.span().start)),
        (Some(part), Some(point)) => {
            let later = if part.span().start > point.span().start { part } else { point };
            return Err(src.error(
                &later.span(),
                "this [[dirichlet]] table gives both `part` and `point`",
                "a [[dirichlet]] table fixes either a boundary part or one node: keep one (write a second \
                 [[dirichlet]] table for the other)",
            ));
        }
        (None, None) => {
            return Err(src.error(
                &table.span,
                "this [[dirichlet]] table has neither `part` nor `point`",
                "add part = \"left\" (a boundary physical name of the mesh) or point = [x, y] (the mesh node \
                 at that point)",
            ))
        }
    };
    let ux = d.ux.as_ref().map(|v| src.number(v, "ux")).transpose()?;
    let uy = d.uy.as_ref().map(|v| src.number(v, "uy")).transpose()?;
    if ux.is_none() && uy.is_none() {
        let on = match &target {
            DirichletTarget::Part(part) => format!("on `{part}`"),
            point => format!("at {point}"),
        };
        return Err(src.error(
            &table.span,
            format!("the [[dirichlet]] {on} fixes neither `ux` nor `uy`"),
            "add ux = 0.0 and/or uy = 0.0 (the prescribed displacement components, in m)",
        ));
    }
    Ok(DirichletSpec { target, ux, uy, at })
}

fn petsc_options(src: &Source, v: &Spanned<Value>) -> Result<Vec<String>> {
    let options: Vec<String> = src.string(v, "petsc_options")?.split_whitespace().map(str::to_string).collect();
    if let Some(first) = options.first() {
        if !first.starts_with('-') {
            return Err(src.error(
                &v.span(),
                format!("`petsc_options` must start with an option name, found `{first}`"),
                "PETSc options are written as on a command line, e.g. petsc_options = \"-ksp_type cg -pc_type gamg\"",
            ));
        }
    }
    Ok(options)
}
