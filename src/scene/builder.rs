//! Scenes built in Rust go through exactly the checks of a scene file.
//!
//! [`Scene::to_toml`] writes any scene as scene-file text; [`Scene::validated`] reads that text
//! back with the scene reader, so a `Scene` made field by field (or with [`SceneBuilder`]) is
//! checked by the same code as a file, and the problem driver does this for every scene it is
//! given. A mistake is reported as in a file, at `<scene built in Rust>`, with the line of the
//! generated text quoted in the message.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::bodies::{BodySpec, ContactPairSpec, PartRef, Placement};
use super::contact::{ContactSolverSpec, ContactSpec, FrictionSpec, ObstacleSpec};
use super::{
    DirichletSpec, DirichletTarget, DualConstraints, Formulation, Load, MaterialSpec, MeshSpec, Mesher, PlaneSpec,
    Scene, TractionSpec,
};
use crate::error::{Error, Location, Result};
use crate::fem::mixed_pressure::Element;
use crate::mesh::Order;

/// The name under which a scene built in Rust reports its mistakes.
pub const BUILT_IN_RUST: &str = "<scene built in Rust>";

fn num(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.is_infinite() {
        if v > 0.0 {
            "inf".into()
        } else {
            "-inf".into()
        }
    } else {
        format!("{v:?}")
    }
}

fn pair(p: [f64; 2]) -> String {
    format!("[{}, {}]", num(p[0]), num(p[1]))
}

/// The `refine = { ... }` line of a mesh table.
fn refine_line(t: &mut String, refine: &Option<super::RefineSpec>) {
    if let Some(r) = refine {
        let _ = writeln!(
            t,
            "refine = {{ point = {}, cell_size = {}, radius = {} }}",
            pair(r.point),
            num(r.cell_size),
            num(r.radius)
        );
    }
}

fn string(s: &str) -> String {
    // TOML basic strings: escape the backslash and the quote.
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

impl Scene {
    /// The scene as scene-file text (the format of docs/scene-format.md).
    pub fn to_toml(&self) -> String {
        let mut t = String::new();
        if let Some(title) = &self.title {
            let _ = writeln!(t, "title = {}", string(title));
        }
        match self.has_body_tables() {
            false => write_body(&mut t, &self.bodies()[0], "", Some((self.formulation, self.dual_constraints))),
            true => {
                for b in &self.bodies {
                    let _ = writeln!(
                        t,
                        "[[body]]\nname = {}\nrotate = {}\ntranslate = {}",
                        string(&b.name),
                        num(b.placement.rotate),
                        pair(b.placement.translate)
                    );
                    write_body(&mut t, b, "body.", None);
                }
                for p in &self.contact_pairs {
                    let _ = writeln!(
                        t,
                        "[[contact_pair]]\nslave = {}\nmaster = {}",
                        string(&p.slave.to_string()),
                        string(&p.master.to_string())
                    );
                    friction_lines(&mut t, p.friction);
                    if let Some(overlap) = p.max_initial_overlap {
                        let _ = writeln!(t, "max_initial_overlap = {}", num(overlap));
                    }
                }
            }
        }
        if !self.petsc_options.is_empty() {
            let _ = writeln!(t, "[solver]\npetsc_options = {}", string(&self.petsc_options.join(" ")));
        }
        if let Some(dir) = &self.output_dir {
            let _ = writeln!(t, "[output]\ndir = {}", string(&dir.display().to_string()));
        }
        if self.estimate {
            t.push_str("[estimate]\nenabled = true\n");
        }
        t
    }

    /// The scene read back from [`Scene::to_toml`] by the scene reader: every check a scene file
    /// gets. Scenes read from a file pass unchanged (their source is kept); a mistake in a scene
    /// built in Rust is an [`Error::Scene`] at `<scene built in Rust>` quoting the generated line.
    pub fn validated(&self) -> Result<Scene> {
        let text = self.to_toml();
        let source =
            if self.source.as_os_str().is_empty() { PathBuf::from(BUILT_IN_RUST) } else { self.source.clone() };
        // The text is read only to check it: the scene keeps its own locations (a later error,
        // such as a part the mesh does not have, then points into the scene's own file).
        Scene::from_str(&text, &source)
            .map(|_| {
                let mut s = self.clone();
                s.source = source.clone();
                s
            })
            .map_err(|e| match e {
                Error::Scene { location, message, hint } => {
                    let line = text.lines().nth(location.line.saturating_sub(1)).unwrap_or("").trim().to_string();
                    Error::Scene {
                        location: Location { file: source.clone(), line: location.line, column: location.column },
                        message: format!("in `{line}`: {message}"),
                        hint,
                    }
                }
                other => other,
            })
    }
}

/// The tables of one body: the top level of a single-body scene (`prefix` "", with `top` the
/// scene-wide discretization keys), or the subtables of a `[[body]]` (`prefix` "body.").
fn write_body(t: &mut String, body: &BodySpec, prefix: &str, top: Option<(Formulation, DualConstraints)>) {
    let _ = writeln!(t, "[{prefix}mesh]");
    match &body.mesh {
        MeshSpec::Rectangle { origin, size, cell_size, mesher, refine } => {
            let _ = writeln!(
                t,
                "shape = \"rectangle\"\norigin = {}\nsize = {}\ncell_size = {}",
                pair(*origin),
                pair(*size),
                num(*cell_size)
            );
            let _ = writeln!(t, "mesher = \"{}\"", if *mesher == Mesher::Gmsh { "gmsh" } else { "structured" });
            refine_line(t, refine);
        }
        MeshSpec::Disc { center, radius, cell_size, refine }
        | MeshSpec::HalfDisc { center, radius, cell_size, refine } => {
            let shape = if matches!(body.mesh, MeshSpec::Disc { .. }) { "disc" } else { "half_disc" };
            let _ = writeln!(
                t,
                "shape = \"{shape}\"\ncenter = {}\nradius = {}\ncell_size = {}",
                pair(*center),
                num(*radius),
                num(*cell_size)
            );
            refine_line(t, refine);
        }
        MeshSpec::File { path, geometry } => {
            // Absolute, so that reading the text back resolves it to the same file.
            let absolute = |p: &PathBuf| std::path::absolute(p).unwrap_or_else(|_| p.clone());
            let _ = writeln!(t, "shape = \"file\"\nfile = {}", string(&absolute(path).display().to_string()));
            if let Some(g) = geometry {
                let _ = writeln!(t, "geometry = {}", string(&absolute(g).display().to_string()));
            }
        }
    }
    let _ = writeln!(
        t,
        "[{prefix}discretization]\norder = {}\nelement = \"{}\"",
        body.order.degree(),
        if body.element == Element::P2P0 { "p2p0" } else { "lagrange" }
    );
    if let Some((formulation, dual_constraints)) = top {
        let _ =
            writeln!(t, "formulation = \"{}\"\ndual_constraints = \"{}\"", formulation.name(), dual_constraints.name());
    }
    let MaterialSpec { young, poisson, plane } = body.material;
    let _ = writeln!(
        t,
        "[{prefix}material]\nyoung = {}\npoisson = {}\nplane = \"{}\"",
        num(young),
        num(poisson),
        if plane == PlaneSpec::Stress { "stress" } else { "strain" }
    );
    let _ = writeln!(t, "[{prefix}loads]\nbody_force = {}", pair(body.body_force));
    for tr in &body.tractions {
        let _ = writeln!(t, "[[{prefix}traction]]\npart = {}", string(&tr.part));
        match tr.load {
            Load::Traction(v) => {
                let _ = writeln!(t, "traction = {}", pair(v));
            }
            Load::Pressure(p) => {
                let _ = writeln!(t, "pressure = {}", num(p));
            }
        }
    }
    for d in &body.dirichlet {
        let _ = writeln!(t, "[[{prefix}dirichlet]]");
        match &d.target {
            DirichletTarget::Part(p) => {
                let _ = writeln!(t, "part = {}", string(p));
            }
            DirichletTarget::Point(p) => {
                let _ = writeln!(t, "point = {}", pair(*p));
            }
        }
        for (key, v) in [("ux", d.ux), ("uy", d.uy)] {
            if let Some(v) = v {
                let _ = writeln!(t, "{key} = {}", num(v));
            }
        }
    }
    if let Some(c) = &body.contact {
        let _ = writeln!(t, "[{prefix}contact]\npart = {}", string(&c.part));
        match &c.obstacle {
            ObstacleSpec::Line { point, normal } => {
                let _ = writeln!(t, "obstacle = \"line\"\npoint = {}\nnormal = {}", pair(*point), pair(*normal));
            }
            ObstacleSpec::Circle { center, radius } => {
                let _ = writeln!(t, "obstacle = \"circle\"\ncenter = {}\nradius = {}", pair(*center), num(*radius));
            }
            ObstacleSpec::Polyline { points } => {
                let list: Vec<String> = points.iter().map(|p| pair(*p)).collect();
                let _ = writeln!(t, "obstacle = \"polyline\"\npoints = [{}]", list.join(", "));
            }
        }
        let _ = writeln!(t, "gap = {}", num(c.gap));
        friction_lines(t, c.friction);
        let _ = writeln!(t, "solver = \"{}\"", c.solver.scene_name());
        if let ContactSolverSpec::Relaxation { omega } = c.solver {
            let _ = writeln!(t, "omega = {}", num(omega));
        }
        if let Some(tol) = c.tolerance {
            let _ = writeln!(t, "tolerance = {}", num(tol));
        }
        if let Some(n) = c.max_iterations {
            let _ = writeln!(t, "max_iterations = {n}");
        }
    }
}

/// The `friction = ...` line of a contact table or pair, with `mu` or `threshold`.
fn friction_lines(t: &mut String, friction: FrictionSpec) {
    match friction {
        FrictionSpec::None => t.push_str("friction = \"none\"\n"),
        FrictionSpec::Coulomb { mu } => {
            let _ = writeln!(t, "friction = \"coulomb\"\nmu = {}", num(mu));
        }
        FrictionSpec::Tresca { threshold } => {
            let _ = writeln!(t, "friction = \"tresca\"\nthreshold = {}", num(threshold));
        }
    }
}

/// Build a scene in Rust; [`SceneBuilder::build`] checks it as a scene file is checked.
///
/// ```no_run
/// # use signorini::scene::SceneBuilder;
/// let scene = SceneBuilder::rectangle([0.0, 0.0], [2.0, 1.0], 0.1)
///     .material(210e9, 0.3)
///     .pressure("top", 1e6)
///     .contact_line("bottom", [0.0, 0.0], [0.0, 1.0])
///     .coulomb(0.3)
///     .dirichlet_point([0.0, 1.0], Some(0.0), None)
///     .build()
///     .unwrap();
/// ```
#[derive(Debug, Clone)]
pub struct SceneBuilder {
    scene: Scene,
}

fn here() -> Location {
    Location { file: PathBuf::from(BUILT_IN_RUST), line: 1, column: 1 }
}

impl SceneBuilder {
    fn from_mesh(mesh: MeshSpec) -> Self {
        SceneBuilder {
            scene: Scene {
                source: PathBuf::from(BUILT_IN_RUST),
                title: None,
                mesh,
                order: Order::P1,
                element: Element::Lagrange,
                formulation: Formulation::Primal,
                dual_constraints: DualConstraints::Eliminated,
                estimate: false,
                material: MaterialSpec { young: f64::NAN, poisson: 0.3, plane: PlaneSpec::Strain },
                body_force: [0.0, 0.0],
                tractions: Vec::new(),
                dirichlet: Vec::new(),
                contact: None,
                petsc_options: Vec::new(),
                output_dir: None,
                bodies: Vec::new(),
                contact_pairs: Vec::new(),
                contact_solver: None,
            },
        }
    }
    /// A rectangle `[origin, origin + size]` on a structured mesh of about `cell_size`.
    pub fn rectangle(origin: [f64; 2], size: [f64; 2], cell_size: f64) -> Self {
        Self::from_mesh(MeshSpec::Rectangle { origin, size, cell_size, mesher: Mesher::Structured, refine: None })
    }
    /// A mesh file (MSH 4.1).
    pub fn mesh_file(path: impl AsRef<Path>) -> Self {
        Self::from_mesh(MeshSpec::File { path: path.as_ref().to_path_buf(), geometry: None })
    }
    /// A mesh file (MSH 4.1) and the Gmsh `.geo` script it was made from (for `adapt`).
    pub fn mesh_file_with_geometry(path: impl AsRef<Path>, geometry: impl AsRef<Path>) -> Self {
        Self::from_mesh(MeshSpec::File {
            path: path.as_ref().to_path_buf(),
            geometry: Some(geometry.as_ref().to_path_buf()),
        })
    }
    pub fn title(mut self, title: &str) -> Self {
        self.scene.title = Some(title.to_string());
        self
    }
    /// Quadratic (P2) triangles.
    pub fn quadratic(mut self) -> Self {
        self.scene.order = Order::P2;
        self
    }
    /// Young's modulus and Poisson's ratio (plane strain).
    pub fn material(mut self, young: f64, poisson: f64) -> Self {
        self.scene.material.young = young;
        self.scene.material.poisson = poisson;
        self
    }
    pub fn plane_stress(mut self) -> Self {
        self.scene.material.plane = PlaneSpec::Stress;
        self
    }
    pub fn body_force(mut self, f: [f64; 2]) -> Self {
        self.scene.body_force = f;
        self
    }
    pub fn traction(mut self, part: &str, t: [f64; 2]) -> Self {
        self.scene.tractions.push(TractionSpec { part: part.into(), load: Load::Traction(t), at: here() });
        self
    }
    pub fn pressure(mut self, part: &str, p: f64) -> Self {
        self.scene.tractions.push(TractionSpec { part: part.into(), load: Load::Pressure(p), at: here() });
        self
    }
    pub fn dirichlet(mut self, part: &str, ux: Option<f64>, uy: Option<f64>) -> Self {
        self.scene.dirichlet.push(DirichletSpec { target: DirichletTarget::Part(part.into()), ux, uy, at: here() });
        self
    }
    pub fn dirichlet_point(mut self, point: [f64; 2], ux: Option<f64>, uy: Option<f64>) -> Self {
        self.scene.dirichlet.push(DirichletSpec { target: DirichletTarget::Point(point), ux, uy, at: here() });
        self
    }
    /// Frictionless contact of `part` with the rigid half-plane behind the line through
    /// `point`, `normal` pointing towards the body.
    pub fn contact_line(mut self, part: &str, point: [f64; 2], normal: [f64; 2]) -> Self {
        self.scene.contact = Some(ContactSpec {
            part: part.into(),
            obstacle: ObstacleSpec::Line { point, normal },
            gap: 0.0,
            friction: FrictionSpec::None,
            solver: ContactSolverSpec::FullSpaceNewton,
            tolerance: None,
            max_iterations: None,
            at: here(),
        });
        self
    }
    /// Coulomb friction with coefficient `mu` on the contact.
    pub fn coulomb(mut self, mu: f64) -> Self {
        if let Some(c) = self.scene.contact.as_mut() {
            c.friction = FrictionSpec::Coulomb { mu };
        }
        self
    }
    /// Tresca friction with threshold `g` (N/m²) on the contact.
    pub fn tresca(mut self, threshold: f64) -> Self {
        if let Some(c) = self.scene.contact.as_mut() {
            c.friction = FrictionSpec::Tresca { threshold };
        }
        self
    }
    /// The scene, checked as a scene file is.
    pub fn build(self) -> Result<Scene> {
        self.scene.validated()
    }
}

/// A scene with several bodies built in Rust: each body a single-body scene (from
/// [`SceneBuilder`]) with a name and a placement, and the contact pairs between their parts.
/// [`BodiesBuilder::build`] checks it as a scene file with `[[body]]` tables is checked.
///
/// ```no_run
/// use signorini::scene::{BodiesBuilder, FrictionSpec, SceneBuilder};
/// let block = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.3).traction("top", [0.0, -1e6]).build()?;
/// let base = SceneBuilder::rectangle([-0.5, -1.0], [2.0, 1.0], 0.15).material(2e9, 0.3).dirichlet("bottom", Some(0.0), Some(0.0)).build()?;
/// let scene = BodiesBuilder::new("block on a base")
///     .body("block", block)
///     .body("base", base)
///     .pair("block.bottom", "base.top", FrictionSpec::Coulomb { mu: 0.3 })
///     .build()?;
/// # Ok::<(), signorini::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct BodiesBuilder {
    title: String,
    bodies: Vec<(BodySpec, Scene)>,
    pairs: Vec<ContactPairSpec>,
}

impl BodiesBuilder {
    pub fn new(title: &str) -> Self {
        BodiesBuilder { title: title.into(), bodies: Vec::new(), pairs: Vec::new() }
    }

    fn here() -> Location {
        Location { file: PathBuf::from(BUILT_IN_RUST), line: 0, column: 0 }
    }

    /// A body named `name`: the body of the single-body scene `scene` (its mesh, order, element,
    /// material, loads, conditions and rigid contact), where its mesh says.
    pub fn body(self, name: &str, scene: Scene) -> Self {
        self.placed_body(name, scene, Placement::default())
    }

    /// [`BodiesBuilder::body`] moved by `placement` (rotation, then translation).
    pub fn placed_body(mut self, name: &str, scene: Scene, placement: Placement) -> Self {
        let mut body = scene.bodies()[0].clone();
        body.name = name.into();
        body.placement = placement;
        body.at = Self::here();
        self.bodies.push((body, scene));
        self
    }

    /// Contact between `slave` and `master`, each `"body.part"`, with `friction`.
    pub fn pair(mut self, slave: &str, master: &str, friction: FrictionSpec) -> Self {
        let part = |s: &str| {
            let (body, part) = s.split_once('.').unwrap_or((s, ""));
            PartRef { body: body.into(), part: part.into(), at: Self::here() }
        };
        self.pairs.push(ContactPairSpec {
            slave: part(slave),
            master: part(master),
            friction,
            max_initial_overlap: None,
            at: Self::here(),
        });
        self
    }

    /// The scene, checked ([`Error::Scene`] at `<scene built in Rust>` for a mistake, quoting
    /// the generated line; [`Error::Usage`] without any body).
    pub fn build(self) -> Result<Scene> {
        let Some((_, first)) = self.bodies.first() else {
            return Err(Error::Usage("BodiesBuilder::build: no body was given".into()));
        };
        let scene = Scene {
            title: Some(self.title.clone()),
            bodies: self.bodies.iter().map(|(b, _)| b.clone()).collect(),
            contact_pairs: self.pairs.clone(),
            ..first.clone()
        };
        scene.validated()
    }
}
