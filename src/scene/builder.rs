//! Scenes built in Rust go through exactly the checks of a scene file.
//!
//! [`Scene::to_toml`] writes any scene as scene-file text; [`Scene::validated`] reads that text
//! back with the scene reader, so a `Scene` made field by field (or with [`SceneBuilder`]) is
//! checked by the same code as a file, and the problem driver does this for every scene it is
//! given. A mistake in a scene built in Rust is reported at `<scene built in Rust>` with the
//! builder call and the key that hold the value (``SceneBuilder::material (`poisson = 0.6`)``);
//! in a scene read from a file and changed in Rust, at the file with the generated line quoted.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::bodies::{BodySpec, ContactPairSpec, PartRef, Placement};
use super::contact::{ContactSolverSpec, ContactSpec, FrictionSpec, ObstacleSpec};
use super::interface::{InterfaceLawSpec, InterfaceSpec};
use super::{
    DirichletSpec, DirichletTarget, DualConstraints, EvolutionSpec, Formulation, Load, MaterialSpec, MeshSpec, Mesher,
    PlaneSpec, RefineSpec, Scene, TractionSpec,
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
fn refine_line(t: &mut String, refine: &Option<RefineSpec>) {
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
                    contact_friction_lines(&mut t, p.friction, &p.interface);
                    if let Some(overlap) = p.max_initial_overlap {
                        let _ = writeln!(t, "max_initial_overlap = {}", num(overlap));
                    }
                    if let Some(interface) = &p.interface {
                        interface_lines(&mut t, "contact_pair.interface", interface);
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
        if let Some(e) = &self.evolution {
            let tables: Vec<(String, Vec<[f64; 2]>)> =
                e.factors.iter().map(|f| (f.name.clone(), f.points.clone())).collect();
            let path = PendingEvolution {
                increments: Some(Increments::Times(e.times.clone())),
                start: Some(e.start),
                tables,
                monitor: e.monitor.clone(),
                profiles: Some(e.profiles.clone()),
            };
            path.write(&mut t);
        }
        t
    }

    /// The scene read back from [`Scene::to_toml`] by the scene reader: every check a scene file
    /// gets. Scenes read from a file pass unchanged (their source is kept). A mistake is an
    /// [`Error::Scene`]: for a scene built in Rust (its `source` [`BUILT_IN_RUST`] or empty), at
    /// [`BUILT_IN_RUST`] without a line, the message naming the builder call and the key; for a
    /// scene read from a file and changed since, at the file, quoting the generated line.
    pub fn validated(&self) -> Result<Scene> {
        let source =
            if self.source.as_os_str().is_empty() { PathBuf::from(BUILT_IN_RUST) } else { self.source.clone() };
        // The text is read only to check it: the scene keeps its own locations (a later error,
        // such as a part the mesh does not have, then points into the scene's own file).
        checked_text(&self.to_toml(), &source).map(|_| {
            let mut s = self.clone();
            s.source = source.clone();
            s
        })
    }
}

/// `text` (generated by [`Scene::to_toml`]) read by the scene reader under `source`, a mistake
/// reported as [`Scene::validated`] says.
fn checked_text(text: &str, source: &Path) -> Result<Scene> {
    Scene::from_str(text, source).map_err(|e| match e {
        // Built in Rust: the builder call and key, not a line of text the user never saw.
        Error::Scene { location, message, hint } if source == Path::new(BUILT_IN_RUST) => Error::Scene {
            location: here(),
            message: format!("{}: {message}", builder_call(text, location.line)),
            hint,
        },
        Error::Scene { location, message, hint } => {
            let line = text.lines().nth(location.line.saturating_sub(1)).unwrap_or("").trim().to_string();
            Error::Scene {
                location: Location { file: source.to_path_buf(), line: location.line, column: location.column },
                message: format!("in `{line}`: {message}"),
                hint,
            }
        }
        other => other,
    })
}

/// The increments of a load path being built: a count or the end times.
#[derive(Debug, Clone, PartialEq)]
enum Increments {
    Steps(usize),
    Times(Vec<f64>),
}

/// A load path as the builders' calls give it (written as an `[evolution]` table and read by
/// the scene reader, which expands `steps` and checks everything).
#[derive(Debug, Clone, Default, PartialEq)]
struct PendingEvolution {
    increments: Option<Increments>,
    start: Option<f64>,
    tables: Vec<(String, Vec<[f64; 2]>)>,
    monitor: Option<String>,
    profiles: Option<Vec<f64>>,
}

impl PendingEvolution {
    fn is_empty(&self) -> bool {
        *self == PendingEvolution::default()
    }

    /// The `[evolution]` and `[evolution.factor]` tables.
    fn write(&self, t: &mut String) {
        let list = |v: &[f64]| format!("[{}]", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", "));
        t.push_str("[evolution]\n");
        match &self.increments {
            Some(Increments::Steps(n)) => {
                let _ = writeln!(t, "steps = {n}");
            }
            Some(Increments::Times(times)) => {
                let _ = writeln!(t, "times = {}", list(times));
            }
            None => {}
        }
        if let Some(start) = self.start {
            let _ = writeln!(t, "start = {}", num(start));
        }
        if let Some(monitor) = &self.monitor {
            let _ = writeln!(t, "monitor = {}", string(monitor));
        }
        if let Some(profiles) = &self.profiles {
            let _ = writeln!(t, "profiles = {}", list(profiles));
        }
        if !self.tables.is_empty() {
            t.push_str("[evolution.factor]\n");
            for (name, points) in &self.tables {
                let rows: Vec<String> = points.iter().map(|p| pair(*p)).collect();
                let _ = writeln!(t, "{} = [{}]", string(name), rows.join(", "));
            }
        }
    }

    /// The checks of the builders before the reader's: a path needs its increments.
    fn refusal(&self, builder: &str) -> Option<(String, String, String)> {
        if self.is_empty() || self.increments.is_some() {
            return None;
        }
        let calls: Vec<String> = [
            (self.start.is_some(), "evolution_start"),
            (!self.tables.is_empty(), "load_factor"),
            (self.monitor.is_some(), "evolution_monitor"),
            (self.profiles.is_some(), "evolution_profiles"),
        ]
        .iter()
        .filter(|(given, _)| *given)
        .map(|(_, call)| format!("{builder}::{call}"))
        .collect();
        Some((
            calls.join(", "),
            "the load path has no increments: without them this setting would be ignored".into(),
            format!(
                "add .evolution_steps(n) (n equal increments) or .evolution_times(&[..]) (their end times) to the \
                 {builder}, or remove the call"
            ),
        ))
    }

    /// The path read back by the scene reader after `scene`'s tables: the expanded
    /// [`EvolutionSpec`] (at [`BUILT_IN_RUST`]), `None` if no call set it.
    fn read(&self, scene: &Scene) -> Result<Option<EvolutionSpec>> {
        if self.is_empty() {
            return Ok(None);
        }
        let mut text = scene.to_toml();
        self.write(&mut text);
        let parsed = checked_text(&text, Path::new(BUILT_IN_RUST))?;
        Ok(parsed.evolution.map(|mut e| {
            e.at = here();
            e.monitor_at = e.monitor.as_ref().map(|_| here());
            for f in &mut e.factors {
                f.at = here();
            }
            e
        }))
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
        | MeshSpec::HalfDisc { center, radius, cell_size, refine }
        | MeshSpec::QuarterDisc { center, radius, cell_size, refine } => {
            let shape = match body.mesh {
                MeshSpec::Disc { .. } => "disc",
                MeshSpec::HalfDisc { .. } => "half_disc",
                _ => "quarter_disc",
            };
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
        plane.name()
    );
    let _ = writeln!(t, "[{prefix}loads]\nbody_force = {}", pair(body.body_force));
    name_line(t, &body.body_force_name);
    for tr in &body.tractions {
        let _ = writeln!(t, "[[{prefix}traction]]\npart = {}", string(&tr.part));
        name_line(t, &tr.name);
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
        name_line(t, &d.name);
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
        contact_friction_lines(t, c.friction, &c.interface);
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
        if let Some(m) = c.motion {
            let _ = writeln!(t, "motion = {}", pair(m));
        }
        name_line(t, &c.name);
        if let Some(interface) = &c.interface {
            interface_lines(t, &format!("{prefix}contact.interface"), interface);
        }
    }
}

/// The friction lines of a contact, but no `friction = "none"` beside an interface law that
/// has its own friction or none (the reader refuses any friction key there).
fn contact_friction_lines(t: &mut String, friction: FrictionSpec, interface: &Option<InterfaceSpec>) {
    let law_owns_friction = interface.as_ref().is_some_and(|i| !i.law.takes_contact_friction());
    if !(law_owns_friction && friction == FrictionSpec::None) {
        friction_lines(t, friction);
    }
}

/// The interface table `[header]` (written last in its contact's tables).
fn interface_lines(t: &mut String, header: &str, interface: &InterfaceSpec) {
    let _ = writeln!(t, "[{header}]\nlaw = \"{}\"", interface.law.name());
    match &interface.law {
        InterfaceLawSpec::ThinLayer(l) => {
            let _ = writeln!(
                t,
                "young = {}\npoisson = {}\nthickness = {}\nbonded = {}",
                num(l.young),
                num(l.poisson),
                num(l.thickness),
                l.bonded
            );
        }
        InterfaceLawSpec::Rccm(l) => {
            let _ = writeln!(
                t,
                "normal_stiffness = {}\ntangential_stiffness = {}\nadhesion_energy = {}\nviscosity = {}\nmu = {}\n\
                 initial_adhesion = {}",
                num(l.normal_stiffness),
                num(l.tangential_stiffness),
                num(l.adhesion_energy),
                num(l.viscosity),
                num(l.mu),
                num(l.initial_adhesion)
            );
        }
        InterfaceLawSpec::CohesiveJoint(l) => {
            let _ = writeln!(
                t,
                "cohesion = {}\ntensile_strength = {}\nmu = {}\nfracture_energy_tension = {}\n\
                 fracture_energy_shear = {}",
                num(l.cohesion),
                num(l.tensile_strength),
                num(l.mu),
                num(l.fracture_energy_tension),
                num(l.fracture_energy_shear)
            );
        }
    }
    if !interface.trace.is_empty() {
        let list: Vec<String> = interface.trace.iter().map(|p| pair(*p)).collect();
        let _ = writeln!(t, "trace = [{}]", list.join(", "));
    }
}

/// The `name = ...` line of a named load.
fn name_line(t: &mut String, name: &Option<String>) {
    if let Some(name) = name {
        let _ = writeln!(t, "name = {}", string(name));
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

/// Build a single-body scene in Rust: every key of a scene file has a call, the calls may come
/// in any order, and [`SceneBuilder::build`] checks the scene as a scene file is checked.
///
/// Start from the shape ([`rectangle`](Self::rectangle), [`disc`](Self::disc),
/// [`half_disc`](Self::half_disc), [`quarter_disc`](Self::quarter_disc), [`mesh_file`](Self::mesh_file)), then add what the scene
/// needs. [`material`](Self::material) is required; everything else has the scene format's
/// default (docs/scene-format.md, the table beside each call). Units are SI: m, Pa (N/m²),
/// N/m³.
///
/// | Call | Scene-file key |
/// |---|---|
/// | [`rectangle`](Self::rectangle), [`disc`](Self::disc), [`half_disc`](Self::half_disc), [`quarter_disc`](Self::quarter_disc), [`mesh_file`](Self::mesh_file), [`mesh_file_with_geometry`](Self::mesh_file_with_geometry) | `[mesh]` `shape` and its keys |
/// | [`gmsh`](Self::gmsh), [`refine`](Self::refine) | `[mesh]` `mesher = "gmsh"`, `refine` |
/// | [`title`](Self::title) | `title` |
/// | [`quadratic`](Self::quadratic), [`p2p0`](Self::p2p0) | `[discretization]` `order = 2`, `element = "p2p0"` |
/// | [`formulation`](Self::formulation), [`dual_constraints`](Self::dual_constraints), [`estimate`](Self::estimate) | `[discretization]` `formulation`, `dual_constraints`; `[estimate]` |
/// | [`material`](Self::material), [`plane_stress`](Self::plane_stress), [`axisymmetric`](Self::axisymmetric) | `[material]` |
/// | [`body_force`](Self::body_force) | `[loads]` |
/// | [`traction`](Self::traction), [`pressure`](Self::pressure) (any number) | `[[traction]]` |
/// | [`dirichlet`](Self::dirichlet), [`dirichlet_point`](Self::dirichlet_point) (any number) | `[[dirichlet]]` |
/// | [`contact_line`](Self::contact_line), [`contact_circle`](Self::contact_circle), [`contact_polyline`](Self::contact_polyline) | `[contact]` `part`, `obstacle` and its keys |
/// | [`gap`](Self::gap), [`coulomb`](Self::coulomb), [`tresca`](Self::tresca) | `[contact]` `gap`, `friction` with `mu` or `threshold` |
/// | [`contact_solver`](Self::contact_solver), [`contact_tolerance`](Self::contact_tolerance), [`contact_max_iterations`](Self::contact_max_iterations) | `[contact]` `solver` (and `omega`), `tolerance`, `max_iterations` |
/// | [`petsc_options`](Self::petsc_options), [`output_dir`](Self::output_dir) | `[solver]`, `[output]` |
/// | [`named`](Self::named) (after a load's call) | `name` of `[[traction]]`, `[[dirichlet]]`, `[loads]`, `[contact]` |
/// | [`obstacle_motion`](Self::obstacle_motion) | `[contact]` `motion` |
/// | [`interface`](Self::interface), [`interface_trace`](Self::interface_trace) | `[contact.interface]` (`law` and its keys), its `trace` |
/// | [`evolution_steps`](Self::evolution_steps), [`evolution_times`](Self::evolution_times), [`evolution_start`](Self::evolution_start), [`evolution_monitor`](Self::evolution_monitor), [`evolution_profiles`](Self::evolution_profiles) | `[evolution]` `steps`, `times`, `start`, `monitor`, `profiles` |
/// | [`load_factor`](Self::load_factor) (any number) | `[evolution.factor]` |
///
/// Several bodies: build each body with a `SceneBuilder` and join them with [`BodiesBuilder`].
///
/// **No call is lost.** A call that would have no effect is refused by `build()` with an
/// [`Error::Scene`] naming it: a contact setting ([`coulomb`](Self::coulomb),
/// [`gap`](Self::gap), ...) without a contact obstacle, [`refine`](Self::refine) or
/// [`gmsh`](Self::gmsh) on a mesh file, and a second call of a setter (a second
/// [`material`](Self::material), a second obstacle, [`coulomb`](Self::coulomb) after
/// [`tresca`](Self::tresca), ...), which would replace the first. Only [`traction`](Self::traction),
/// [`pressure`](Self::pressure), [`dirichlet`](Self::dirichlet),
/// [`dirichlet_point`](Self::dirichlet_point), [`load_factor`](Self::load_factor) and
/// [`petsc_options`](Self::petsc_options) add up. A load-path setting
/// ([`load_factor`](Self::load_factor), [`evolution_start`](Self::evolution_start), ...)
/// without [`evolution_steps`](Self::evolution_steps) or
/// [`evolution_times`](Self::evolution_times) is refused, and so is [`named`](Self::named)
/// after a call that adds no load.
///
/// **Mistakes are named by their call.** A value the scene reader refuses (ν = 0.6, μ < 0, a
/// P2–P0 element on linear triangles, ...) gives the reader's message and hint, at
/// [`BUILT_IN_RUST`], prefixed with the call and the key: ``SceneBuilder::material
/// (`poisson = 0.6`): `poisson` must be below 0.5, found 0.6``. Part names and point
/// conditions are checked against the mesh when the problem is set up.
///
/// ```
/// use signorini::scene::{ContactSolverSpec, SceneBuilder};
/// // A half disc pressed onto a rigid plane with Coulomb friction, on a quadratic Gmsh mesh
/// // refined at the expected contact point (the calls may come in any order).
/// let scene = SceneBuilder::half_disc([0.0, 1.0], 1.0, 0.2)
///     .coulomb(0.3)
///     .contact_line("arc", [0.0, 0.0], [0.0, 1.0])
///     .quadratic()
///     .refine([0.0, 0.0], 0.02, 0.2)
///     .material(210e9, 0.3)
///     .pressure("flat", 1e6)
///     .dirichlet_point([0.0, 1.0], Some(0.0), None)
///     .contact_solver(ContactSolverSpec::Newton)
///     .build()?;
/// assert!(scene.contact.is_some_and(|c| c.friction == signorini::scene::FrictionSpec::Coulomb { mu: 0.3 }));
/// // A call that would be ignored is refused, and named.
/// let refused = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.3).coulomb(0.3).build();
/// assert!(refused.unwrap_err().to_string().contains("SceneBuilder::coulomb"));
/// # Ok::<(), signorini::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct SceneBuilder {
    /// The scene so far: mesh, discretization, material, loads and conditions (the contact is
    /// put together at `build()`).
    scene: Scene,
    material_given: bool,
    gmsh: bool,
    refine: Option<RefineSpec>,
    /// The `[contact]` part and obstacle, and the call that gave them.
    obstacle: Option<(String, ObstacleSpec)>,
    gap: Option<f64>,
    friction: Option<FrictionSpec>,
    solver: Option<ContactSolverSpec>,
    tolerance: Option<f64>,
    max_iterations: Option<usize>,
    /// The obstacle's `motion` and its load name.
    motion: Option<[f64; 2]>,
    motion_name: Option<String>,
    /// `[contact.interface]`: the law and its trace points.
    interface: Option<InterfaceLawSpec>,
    interface_trace: Option<Vec<[f64; 2]>>,
    /// The load path (`[evolution]`).
    evolution: PendingEvolution,
    /// The load the previous call added or set (which [`SceneBuilder::named`] names), or the
    /// previous call if it was not a load.
    last_load: std::result::Result<LoadSlot, &'static str>,
    /// The setters called so far, each with the setting it sets (a second call for a setting
    /// is refused).
    called: Vec<(&'static str, &'static str)>,
    /// Calls refused so far: the call and why (the first is `build()`'s error).
    refused: Vec<(String, String, String)>,
}

/// Where the items of a scene built in Rust are: [`BUILT_IN_RUST`], no line (the builder's
/// errors name the call instead).
fn here() -> Location {
    Location { file: PathBuf::from(BUILT_IN_RUST), line: 0, column: 0 }
}

/// A scene error at [`BUILT_IN_RUST`].
fn built_in_rust_error(message: String, hint: String) -> Error {
    Error::Scene { location: here(), message, hint }
}

/// The settings of the contact (each needs an obstacle), as [`SceneBuilder`]'s calls name them.
const CONTACT_SETTINGS: [&str; 8] = [
    "the gap",
    "the friction",
    "the contact solver",
    "the contact tolerance",
    "the contact iteration limit",
    "the obstacle's motion",
    "the interface law",
    "the interface's trace points",
];

/// A load a builder call added or set, for [`SceneBuilder::named`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum LoadSlot {
    Traction(usize),
    Dirichlet(usize),
    BodyForce,
    Motion,
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
                material: MaterialSpec { young: f64::NAN, poisson: f64::NAN, plane: PlaneSpec::Strain },
                body_force: [0.0, 0.0],
                body_force_name: None,
                tractions: Vec::new(),
                dirichlet: Vec::new(),
                contact: None,
                petsc_options: Vec::new(),
                output_dir: None,
                bodies: Vec::new(),
                contact_pairs: Vec::new(),
                contact_solver: None,
                evolution: None,
            },
            material_given: false,
            gmsh: false,
            refine: None,
            obstacle: None,
            gap: None,
            friction: None,
            solver: None,
            tolerance: None,
            max_iterations: None,
            motion: None,
            motion_name: None,
            interface: None,
            interface_trace: None,
            evolution: PendingEvolution::default(),
            last_load: Err("the shape"),
            called: Vec::new(),
            refused: Vec::new(),
        }
    }

    /// Record a setter's call; a second call for `group` (one setting, possibly given by
    /// several calls: `coulomb` and `tresca` both set the friction) is refused, as it would
    /// replace the first.
    fn once(&mut self, call: &'static str, group: &'static str) {
        self.last_load = Err(call);
        match self.called.iter().find(|(g, _)| *g == group) {
            Some((_, first)) => self.refused.push((
                format!("SceneBuilder::{call}"),
                format!("{group} is set twice (by SceneBuilder::{first} before): this call would replace it"),
                format!("keep one call that sets {group}"),
            )),
            None => self.called.push((group, call)),
        }
    }

    /// A rectangle `[origin, origin + size]` (m), meshed with cells of about `cell_size` (m);
    /// boundary parts `bottom`, `right`, `top`, `left`. Structured mesh (a grid of split
    /// rectangles) unless [`gmsh`](Self::gmsh) is called.
    pub fn rectangle(origin: [f64; 2], size: [f64; 2], cell_size: f64) -> Self {
        Self::from_mesh(MeshSpec::Rectangle { origin, size, cell_size, mesher: Mesher::Structured, refine: None })
    }
    /// The full disc of `radius` (m) around `center`, meshed by Gmsh with cells of about
    /// `cell_size`; boundary part `circle`.
    pub fn disc(center: [f64; 2], radius: f64, cell_size: f64) -> Self {
        Self::from_mesh(MeshSpec::Disc { center, radius, cell_size, refine: None })
    }
    /// The lower half of the disc of `radius` around `center` (flat side on top, at
    /// `center[1]`), meshed by Gmsh with cells of about `cell_size`; boundary parts `arc` and
    /// `flat`.
    pub fn half_disc(center: [f64; 2], radius: f64, cell_size: f64) -> Self {
        Self::from_mesh(MeshSpec::HalfDisc { center, radius, cell_size, refine: None })
    }
    /// The lower-right quarter of the disc of `radius` around `center` (`x >= center[0]`,
    /// `y <= center[1]`): with `center[0] = 0` the meridian section of the lower half of a
    /// sphere ([`axisymmetric`](Self::axisymmetric)). Meshed by Gmsh with cells of about
    /// `cell_size`; boundary parts `arc`, `flat` (top) and `axis` (left).
    pub fn quarter_disc(center: [f64; 2], radius: f64, cell_size: f64) -> Self {
        Self::from_mesh(MeshSpec::QuarterDisc { center, radius, cell_size, refine: None })
    }
    /// A mesh file (Gmsh MSH 4.1); its boundary parts are its physical curve names. A relative
    /// path is relative to the current directory.
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
    /// Mesh the rectangle with Gmsh (unstructured, Frontal-Delaunay) instead of the structured
    /// grid: `mesher = "gmsh"`. Discs and half discs are always meshed by Gmsh (the call is
    /// accepted and changes nothing); a mesh file is refused.
    pub fn gmsh(mut self) -> Self {
        self.once("gmsh", "the mesher");
        self.gmsh = true;
        self
    }
    /// Local refinement of a Gmsh mesh: cells of about `cell_size` (m) within `radius` (m) of
    /// `point`, growing back to the mesh's cell size away from it (`refine = { ... }`). A
    /// rectangle needs [`gmsh`](Self::gmsh) too; a mesh file is refused.
    pub fn refine(mut self, point: [f64; 2], cell_size: f64, radius: f64) -> Self {
        self.once("refine", "the refinement");
        self.refine = Some(RefineSpec { point, cell_size, radius });
        self
    }
    /// A name for the problem, copied to the outputs (`title`).
    pub fn title(mut self, title: &str) -> Self {
        self.once("title", "the title");
        self.scene.title = Some(title.to_string());
        self
    }
    /// Quadratic (P2) triangles and displacements (`order = 2`; the default is linear, P1).
    pub fn quadratic(mut self) -> Self {
        self.once("quadratic", "the order");
        self.scene.order = Order::P2;
        self
    }
    /// The locking-free P2–P0 element for nearly incompressible materials
    /// (`element = "p2p0"`): needs [`quadratic`](Self::quadratic) and plane strain.
    pub fn p2p0(mut self) -> Self {
        self.once("p2p0", "the element");
        self.scene.element = Element::P2P0;
        self
    }
    /// Which field is solved for (`formulation`; the default is [`Formulation::Primal`],
    /// displacements).
    pub fn formulation(mut self, formulation: Formulation) -> Self {
        self.once("formulation", "the formulation");
        self.scene.formulation = formulation;
        self
    }
    /// How the dual formulation imposes its boundary constraints (`dual_constraints`; the
    /// default is [`DualConstraints::Eliminated`]).
    pub fn dual_constraints(mut self, dual_constraints: DualConstraints) -> Self {
        self.once("dual_constraints", "the dual constraints");
        self.scene.dual_constraints = dual_constraints;
        self
    }
    /// Also solve the other formulation and estimate the error (`[estimate]`).
    pub fn estimate(mut self) -> Self {
        self.once("estimate", "the estimate");
        self.scene.estimate = true;
        self
    }
    /// Young's modulus (Pa, > 0) and Poisson's ratio (in (-1, 0.5)); plane strain unless
    /// [`plane_stress`](Self::plane_stress). Required.
    pub fn material(mut self, young: f64, poisson: f64) -> Self {
        self.once("material", "the material");
        self.material_given = true;
        self.scene.material.young = young;
        self.scene.material.poisson = poisson;
        self
    }
    /// Plane stress (σzz = 0, a thin plate) instead of plane strain (`plane = "stress"`).
    pub fn plane_stress(mut self) -> Self {
        self.once("plane_stress", "the plane model");
        self.scene.material.plane = PlaneSpec::Stress;
        self
    }
    /// A body of revolution (`plane = "axisymmetric"`): the mesh is the meridian half-plane
    /// `(r, z) = (x, y)` with `r ≥ 0`, and forces are for the full revolution.
    pub fn axisymmetric(mut self) -> Self {
        self.once("axisymmetric", "the plane model");
        self.scene.material.plane = PlaneSpec::Axisymmetric;
        self
    }
    /// Force per unit volume (N/m³), e.g. `[0.0, -ρ g]` (`[loads] body_force`).
    pub fn body_force(mut self, f: [f64; 2]) -> Self {
        self.once("body_force", "the body force");
        self.scene.body_force = f;
        self.last_load = Ok(LoadSlot::BodyForce);
        self
    }
    /// A traction `t` (N/m², global x and y) on the boundary part `part`: σn = t.
    pub fn traction(mut self, part: &str, t: [f64; 2]) -> Self {
        self.scene.tractions.push(TractionSpec { part: part.into(), load: Load::Traction(t), name: None, at: here() });
        self.last_load = Ok(LoadSlot::Traction(self.scene.tractions.len() - 1));
        self
    }
    /// A normal pressure `p` (N/m², positive pushes into the body) on the boundary part `part`:
    /// σn = −p n.
    pub fn pressure(mut self, part: &str, p: f64) -> Self {
        self.scene.tractions.push(TractionSpec { part: part.into(), load: Load::Pressure(p), name: None, at: here() });
        self.last_load = Ok(LoadSlot::Traction(self.scene.tractions.len() - 1));
        self
    }
    /// Prescribed displacement components (m) on every node of the boundary part `part`;
    /// `None` leaves a component free.
    pub fn dirichlet(mut self, part: &str, ux: Option<f64>, uy: Option<f64>) -> Self {
        self.scene.dirichlet.push(DirichletSpec {
            target: DirichletTarget::Part(part.into()),
            ux,
            uy,
            name: None,
            at: here(),
        });
        self.last_load = Ok(LoadSlot::Dirichlet(self.scene.dirichlet.len() - 1));
        self
    }
    /// Prescribed displacement components (m) of the mesh node at `point`; `None` leaves a
    /// component free.
    pub fn dirichlet_point(mut self, point: [f64; 2], ux: Option<f64>, uy: Option<f64>) -> Self {
        self.scene.dirichlet.push(DirichletSpec {
            target: DirichletTarget::Point(point),
            ux,
            uy,
            name: None,
            at: here(),
        });
        self.last_load = Ok(LoadSlot::Dirichlet(self.scene.dirichlet.len() - 1));
        self
    }
    fn obstacle(mut self, call: &'static str, part: &str, obstacle: ObstacleSpec) -> Self {
        self.once(call, "the contact obstacle");
        self.obstacle = Some((part.into(), obstacle));
        self
    }
    /// Contact of the boundary part `part` with the rigid half-plane behind the line through
    /// `point`, `normal` pointing from the obstacle towards the body (`obstacle = "line"`).
    /// Frictionless unless [`coulomb`](Self::coulomb) or [`tresca`](Self::tresca).
    pub fn contact_line(self, part: &str, point: [f64; 2], normal: [f64; 2]) -> Self {
        self.obstacle("contact_line", part, ObstacleSpec::Line { point, normal })
    }
    /// Contact of the boundary part `part` with the rigid disc of `radius` (m) around `center`,
    /// the body outside it (`obstacle = "circle"`).
    pub fn contact_circle(self, part: &str, center: [f64; 2], radius: f64) -> Self {
        self.obstacle("contact_circle", part, ObstacleSpec::Circle { center, radius })
    }
    /// Contact of the boundary part `part` with the rigid region on the right of the polyline
    /// `points` (the body on its left, the end segments extended without end;
    /// `obstacle = "polyline"`).
    pub fn contact_polyline(self, part: &str, points: &[[f64; 2]]) -> Self {
        self.obstacle("contact_polyline", part, ObstacleSpec::Polyline { points: points.to_vec() })
    }
    /// Added to the distance between the body and the obstacle (m); negative is an initial
    /// overlap (`gap`, default 0).
    pub fn gap(mut self, gap: f64) -> Self {
        self.once("gap", "the gap");
        self.gap = Some(gap);
        self
    }
    /// Coulomb friction with coefficient `mu` ≥ 0 on the contact (`friction = "coulomb"`).
    pub fn coulomb(mut self, mu: f64) -> Self {
        self.once("coulomb", "the friction");
        self.friction = Some(FrictionSpec::Coulomb { mu });
        self
    }
    /// Tresca friction with slip threshold `threshold` > 0 (N/m²) on the contact
    /// (`friction = "tresca"`).
    pub fn tresca(mut self, threshold: f64) -> Self {
        self.once("tresca", "the friction");
        self.friction = Some(FrictionSpec::Tresca { threshold });
        self
    }
    /// The contact algorithm (`solver`, and `omega` for [`ContactSolverSpec::Relaxation`]);
    /// the default is [`ContactSolverSpec::FullSpaceNewton`].
    pub fn contact_solver(mut self, solver: ContactSolverSpec) -> Self {
        self.once("contact_solver", "the contact solver");
        self.solver = Some(solver);
        self
    }
    /// Relative residual tolerance of the contact solve, in (0, 1e-3] (`tolerance`; the
    /// solver's default otherwise).
    pub fn contact_tolerance(mut self, tolerance: f64) -> Self {
        self.once("contact_tolerance", "the contact tolerance");
        self.tolerance = Some(tolerance);
        self
    }
    /// Iteration limit of the contact solve, ≥ 1 (`max_iterations`; the solver's default
    /// otherwise).
    pub fn contact_max_iterations(mut self, max_iterations: usize) -> Self {
        self.once("contact_max_iterations", "the contact iteration limit");
        self.max_iterations = Some(max_iterations);
        self
    }
    /// The interface law of the contact (`[contact.interface]`): a thin layer, RCCM adhesion or
    /// a cohesive joint, checked as in a scene file (RCCM and the joint need a load path,
    /// [`evolution_steps`](Self::evolution_steps), and take no [`coulomb`](Self::coulomb) or
    /// [`tresca`](Self::tresca): their friction is the law's `mu`; nor does a bonded layer).
    /// Needs a contact obstacle.
    pub fn interface(mut self, law: InterfaceLawSpec) -> Self {
        self.once("interface", "the interface law");
        self.interface = Some(law);
        self
    }
    /// The points whose τ–δ curves the outputs plot (`[contact.interface] trace`: the contact
    /// point nearest each; default the first, middle and last). Needs
    /// [`interface`](Self::interface).
    pub fn interface_trace(mut self, points: &[[f64; 2]]) -> Self {
        self.once("interface_trace", "the interface's trace points");
        self.interface_trace = Some(points.to_vec());
        self
    }
    /// PETSc options as on a command line, split at whitespace (`[solver] petsc_options`); a
    /// second call adds its options after the first's. Command-line options win over them.
    pub fn petsc_options(mut self, options: &str) -> Self {
        self.last_load = Err("petsc_options");
        self.scene.petsc_options.extend(options.split_whitespace().map(str::to_string));
        self
    }
    /// The obstacle's displacement `[dx, dy]` (m) at factor 1 (`[contact] motion`): along a
    /// load path the obstacle is translated by `factor(t) · motion`; without one, in full.
    /// Needs a contact obstacle.
    pub fn obstacle_motion(mut self, motion: [f64; 2]) -> Self {
        self.once("obstacle_motion", "the obstacle's motion");
        self.motion = Some(motion);
        self.last_load = Ok(LoadSlot::Motion);
        self
    }
    /// Names the load of the call just before (`name = "..."` of its table):
    /// [`traction`](Self::traction), [`pressure`](Self::pressure),
    /// [`dirichlet`](Self::dirichlet), [`dirichlet_point`](Self::dirichlet_point),
    /// [`body_force`](Self::body_force) or [`obstacle_motion`](Self::obstacle_motion). Along a
    /// load path it is multiplied by the factor table of that name
    /// ([`load_factor`](Self::load_factor)); several loads may share a name. After any other
    /// call it is refused by `build()`.
    pub fn named(mut self, name: &str) -> Self {
        let slot = std::mem::replace(&mut self.last_load, Err("named"));
        let target = match slot {
            Ok(LoadSlot::Traction(i)) => &mut self.scene.tractions[i].name,
            Ok(LoadSlot::Dirichlet(i)) => &mut self.scene.dirichlet[i].name,
            Ok(LoadSlot::BodyForce) => &mut self.scene.body_force_name,
            Ok(LoadSlot::Motion) => &mut self.motion_name,
            Err(previous) => {
                self.refused.push((
                    format!("SceneBuilder::named(\"{name}\")"),
                    format!(
                        "it names the load of the call just before it, but that call (SceneBuilder::{previous}) adds \
                         no load"
                    ),
                    "call .named(..) right after the load it names: .traction, .pressure, .dirichlet, \
                     .dirichlet_point, .body_force or .obstacle_motion"
                        .into(),
                ));
                return self;
            }
        };
        *target = Some(name.to_string());
        self
    }
    /// A load path of `n` equal increments (`[evolution] steps = n`) over the path (from
    /// [`evolution_start`](Self::evolution_start), to the last time of the factor tables, or
    /// over [0, 1] without tables), with the tables' times inserted.
    pub fn evolution_steps(mut self, n: usize) -> Self {
        self.once("evolution_steps", "the list of increments");
        self.evolution.increments = Some(Increments::Steps(n));
        self
    }
    /// A load path whose increments end at `times`, strictly increasing (`[evolution] times`).
    pub fn evolution_times(mut self, times: &[f64]) -> Self {
        self.once("evolution_times", "the list of increments");
        self.evolution.increments = Some(Increments::Times(times.to_vec()));
        self
    }
    /// The pseudo-time of the load path's initial state (`[evolution] start`; default: the
    /// first time of the factor tables, or 0).
    pub fn evolution_start(mut self, start: f64) -> Self {
        self.once("evolution_start", "the start of the load path");
        self.evolution.start = Some(start);
        self
    }
    /// The factor table of the loads named `name` ([`named`](Self::named)): rows `[t, factor]`,
    /// times strictly increasing, linear between them (`[evolution.factor] name = [...]`). Any
    /// number of calls, one per name.
    pub fn load_factor(mut self, name: &str, points: &[[f64; 2]]) -> Self {
        self.last_load = Err("load_factor");
        self.evolution.tables.push((name.to_string(), points.to_vec()));
        self
    }
    /// The boundary part whose mean displacement the load path's history records
    /// (`[evolution] monitor`; default: the contact part).
    pub fn evolution_monitor(mut self, part: &str) -> Self {
        self.once("evolution_monitor", "the monitored part");
        self.evolution.monitor = Some(part.to_string());
        self
    }
    /// The increment times at which the contact profiles are plotted (`[evolution] profiles`;
    /// default: the end of the path).
    pub fn evolution_profiles(mut self, times: &[f64]) -> Self {
        self.once("evolution_profiles", "the list of profile times");
        self.evolution.profiles = Some(times.to_vec());
        self
    }
    /// Where the CLI writes results (`[output] dir`; relative to the current directory).
    pub fn output_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.once("output_dir", "the output directory");
        self.scene.output_dir = Some(dir.as_ref().to_path_buf());
        self
    }

    /// The scene, checked as a scene file is. [`Error::Scene`] at [`BUILT_IN_RUST`] naming the
    /// call: for a refused call (see the type's documentation), a missing
    /// [`material`](Self::material), or a value the scene reader refuses.
    pub fn build(self) -> Result<Scene> {
        let SceneBuilder {
            mut scene,
            material_given,
            gmsh,
            refine,
            obstacle,
            gap,
            friction,
            solver,
            tolerance,
            max_iterations,
            motion,
            motion_name,
            interface,
            interface_trace,
            evolution,
            last_load: _,
            called,
            mut refused,
        } = self;
        let contact_calls: Vec<String> = called
            .iter()
            .filter(|(group, _)| CONTACT_SETTINGS.contains(group))
            .map(|(_, call)| format!("SceneBuilder::{call}"))
            .collect();
        if obstacle.is_none() && !contact_calls.is_empty() {
            refused.push((
                contact_calls.join(", "),
                "there is no contact: without an obstacle this contact setting would be ignored".into(),
                "add the contact with .contact_line(..), .contact_circle(..) or .contact_polyline(..) (the calls \
                 may come in any order), or remove the call"
                    .into(),
            ));
        }
        if interface_trace.as_ref().is_some_and(|t| t.is_empty()) {
            refused.push((
                "SceneBuilder::interface_trace".into(),
                "the list of trace points holds no point".into(),
                "give the points whose τ–δ curves are plotted, or remove the call for the default (the first, \
                 middle and last contact points)"
                    .into(),
            ));
        }
        if interface.is_none() && interface_trace.is_some() {
            refused.push((
                "SceneBuilder::interface_trace".into(),
                "there is no interface law: without one the trace points would be ignored".into(),
                "add the law with .interface(..), or remove the call".into(),
            ));
        }
        match &mut scene.mesh {
            MeshSpec::Rectangle { mesher, refine: r, .. } => {
                if gmsh {
                    *mesher = Mesher::Gmsh;
                }
                *r = refine;
            }
            MeshSpec::Disc { refine: r, .. }
            | MeshSpec::HalfDisc { refine: r, .. }
            | MeshSpec::QuarterDisc { refine: r, .. } => *r = refine,
            MeshSpec::File { .. } => {
                for (given, call) in [(gmsh, "gmsh"), (refine.is_some(), "refine")] {
                    if given {
                        refused.push((
                            format!("SceneBuilder::{call}"),
                            "a mesh file is used as it is: it is not meshed again, and this call would be ignored"
                                .into(),
                            "remove the call, or describe the body with SceneBuilder::rectangle, disc or half_disc"
                                .into(),
                        ));
                    }
                }
            }
        }
        refused.extend(evolution.refusal("SceneBuilder"));
        if let Some((call, message, hint)) = refused.into_iter().next() {
            return Err(built_in_rust_error(format!("{call}: {message}"), hint));
        }
        if !material_given {
            return Err(built_in_rust_error(
                "the scene has no material: SceneBuilder::material was not called".into(),
                "add .material(young, poisson): Young's modulus (Pa) and Poisson's ratio".into(),
            ));
        }
        // A line's normal is stored unit, as the reader stores it (a zero one is refused by it).
        let obstacle = obstacle.map(|(part, obstacle)| match obstacle {
            ObstacleSpec::Line { point, normal } if normal[0].hypot(normal[1]) > 0.0 => {
                let length = normal[0].hypot(normal[1]);
                (part, ObstacleSpec::Line { point, normal: [normal[0] / length, normal[1] / length] })
            }
            other => (part, other),
        });
        scene.contact = obstacle.map(|(part, obstacle)| ContactSpec {
            part,
            obstacle,
            gap: gap.unwrap_or(0.0),
            // Coulomb with μ = 0 is frictionless, as in a file (the reader stores it so).
            friction: match friction {
                Some(FrictionSpec::Coulomb { mu: 0.0 }) => FrictionSpec::None,
                other => other.unwrap_or(FrictionSpec::None),
            },
            solver: solver.unwrap_or(ContactSolverSpec::FullSpaceNewton),
            tolerance,
            max_iterations,
            motion,
            name: motion_name,
            interface: interface.map(|law| InterfaceSpec {
                law,
                trace: interface_trace.unwrap_or_default(),
                at: here(),
            }),
            at: here(),
        });
        scene.evolution = evolution.read(&scene)?;
        scene.validated()
    }
}

/// A scene with several bodies built in Rust: each body a single-body scene (from
/// [`SceneBuilder`]) with a name and a placement, and the contact pairs between their parts
/// (`[[body]]` and `[[contact_pair]]` tables). [`BodiesBuilder::build`] checks it as a scene
/// file with `[[body]]` tables is checked.
///
/// Each body's scene carries the body's data only (mesh, order, element, material, loads,
/// conditions, a rigid contact); the settings of the whole scene (title, PETSc options, output
/// directory, contact solver) are the `BodiesBuilder`'s. A body's scene that sets one of them,
/// which would be ignored, is refused by `build()`, as is a scene that has several bodies
/// itself. Body names and pairs are checked as in a file.
///
/// ```
/// use signorini::scene::{BodiesBuilder, FrictionSpec, SceneBuilder};
/// let block = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.3).traction("top", [0.0, -1e6]).build()?;
/// let base = SceneBuilder::rectangle([-0.5, -1.0], [2.0, 1.0], 0.15).material(2e9, 0.3).dirichlet("bottom", Some(0.0), Some(0.0)).build()?;
/// let scene = BodiesBuilder::new("block on a base")
///     .body("block", block)
///     .body("base", base)
///     .pair("block.bottom", "base.top", FrictionSpec::Coulomb { mu: 0.3 })
///     .build()?;
/// assert_eq!(scene.bodies.len(), 2);
/// # Ok::<(), signorini::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct BodiesBuilder {
    title: String,
    bodies: Vec<(BodySpec, Scene)>,
    pairs: Vec<ContactPairSpec>,
    petsc_options: Vec<String>,
    output_dir: Option<PathBuf>,
    contact_solver: Option<ContactSolverSpec>,
    evolution: PendingEvolution,
    /// Calls set twice (the first is `build()`'s error).
    twice: Vec<&'static str>,
    /// Calls refused otherwise: the call, why and what to do (after `twice`).
    refused: Vec<(String, String, String)>,
}

impl BodiesBuilder {
    /// An empty scene titled `title`: add bodies with [`body`](Self::body) and pairs with
    /// [`pair`](Self::pair).
    pub fn new(title: &str) -> Self {
        BodiesBuilder {
            title: title.into(),
            bodies: Vec::new(),
            pairs: Vec::new(),
            petsc_options: Vec::new(),
            output_dir: None,
            contact_solver: None,
            evolution: PendingEvolution::default(),
            twice: Vec::new(),
            refused: Vec::new(),
        }
    }

    /// A body named `name` (letters, digits, `_`, `-`): the body of the single-body scene
    /// `scene` (its mesh, order, element, material, loads, conditions and rigid contact), where
    /// its mesh says.
    pub fn body(self, name: &str, scene: Scene) -> Self {
        self.placed_body(name, scene, Placement::default())
    }

    /// [`BodiesBuilder::body`] moved by `placement` (rotation, then translation).
    pub fn placed_body(mut self, name: &str, scene: Scene, placement: Placement) -> Self {
        let mut body = scene.bodies()[0].clone();
        body.name = name.into();
        body.placement = placement;
        body.at = here();
        self.bodies.push((body, scene));
        self
    }

    /// Contact between `slave` and `master`, each `"body.part"`, with `friction`.
    pub fn pair(self, slave: &str, master: &str, friction: FrictionSpec) -> Self {
        self.pair_spec(slave, master, friction, None)
    }

    /// [`BodiesBuilder::pair`] accepting an initial interpenetration of the two bodies of up to
    /// `max_initial_overlap` (m, ≥ 0; `max_initial_overlap` of `[[contact_pair]]`).
    pub fn pair_with_overlap(
        self,
        slave: &str,
        master: &str,
        friction: FrictionSpec,
        max_initial_overlap: f64,
    ) -> Self {
        self.pair_spec(slave, master, friction, Some(max_initial_overlap))
    }

    fn pair_spec(mut self, slave: &str, master: &str, friction: FrictionSpec, overlap: Option<f64>) -> Self {
        let part = |s: &str| {
            let (body, part) = s.split_once('.').unwrap_or((s, ""));
            PartRef { body: body.into(), part: part.into(), at: here() }
        };
        let friction = match friction {
            FrictionSpec::Coulomb { mu: 0.0 } => FrictionSpec::None,
            other => other,
        };
        self.pairs.push(ContactPairSpec {
            slave: part(slave),
            master: part(master),
            friction,
            max_initial_overlap: overlap,
            interface: None,
            at: here(),
        });
        self
    }

    /// The interface law of the pair added just before (`[contact_pair.interface]`), checked as
    /// in a scene file (see [`SceneBuilder::interface`]; RCCM and the joint take the pair's
    /// friction `FrictionSpec::None`). Refused by `build()` before any pair, or a second time for
    /// the same pair.
    pub fn pair_interface(mut self, law: InterfaceLawSpec) -> Self {
        match self.pairs.last_mut() {
            Some(ContactPairSpec { interface: Some(_), slave, master, .. }) => self.refused.push((
                format!("BodiesBuilder::pair_interface (pair {slave} / {master})"),
                "the pair's interface law is set twice: this call would replace the first".into(),
                "keep one .pair_interface(..) after each .pair(..)".into(),
            )),
            Some(pair) => pair.interface = Some(InterfaceSpec { law, trace: Vec::new(), at: here() }),
            None => self.refused.push((
                "BodiesBuilder::pair_interface".into(),
                "it sets the interface of the pair added just before it, but no pair was added yet".into(),
                "call .pair_interface(..) right after the .pair(..) it applies to".into(),
            )),
        }
        self
    }

    /// The trace points of the interface of the pair added just before
    /// ([`SceneBuilder::interface_trace`]); after [`pair_interface`](Self::pair_interface).
    pub fn pair_interface_trace(mut self, points: &[[f64; 2]]) -> Self {
        match self.pairs.last_mut().and_then(|p| p.interface.as_mut()) {
            Some(interface) if interface.trace.is_empty() => interface.trace = points.to_vec(),
            Some(_) => self.refused.push((
                "BodiesBuilder::pair_interface_trace".into(),
                "the trace points of the pair's interface are set twice: this call would replace the first".into(),
                "keep one .pair_interface_trace(..) per pair".into(),
            )),
            None => self.refused.push((
                "BodiesBuilder::pair_interface_trace".into(),
                "the pair added just before has no interface law: the trace points would be ignored".into(),
                "call .pair_interface(..) first, right after the .pair(..)".into(),
            )),
        }
        self
    }

    /// PETSc options of the whole run, split at whitespace (`[solver] petsc_options`); a
    /// second call adds its options after the first's.
    pub fn petsc_options(mut self, options: &str) -> Self {
        self.petsc_options.extend(options.split_whitespace().map(str::to_string));
        self
    }

    /// Where the CLI writes results (`[output] dir`).
    pub fn output_dir(mut self, dir: impl AsRef<Path>) -> Self {
        self.output_dir = Some(dir.as_ref().to_path_buf());
        self
    }

    /// The contact solver of every contact, pairs and rigid obstacles (as the command line's
    /// `--contact-solver`: [`Scene::contact_solver`]; a scene file has no key for it).
    pub fn contact_solver(mut self, solver: ContactSolverSpec) -> Self {
        self.contact_solver = Some(solver);
        self
    }

    /// A load path of `n` equal increments for the whole scene (as
    /// [`SceneBuilder::evolution_steps`]; the bodies' loads are named on their
    /// `SceneBuilder`s with [`SceneBuilder::named`]).
    pub fn evolution_steps(mut self, n: usize) -> Self {
        if self.evolution.increments.is_some() {
            self.twice.push("evolution_steps");
        }
        self.evolution.increments = Some(Increments::Steps(n));
        self
    }
    /// A load path whose increments end at `times` (as [`SceneBuilder::evolution_times`]).
    pub fn evolution_times(mut self, times: &[f64]) -> Self {
        if self.evolution.increments.is_some() {
            self.twice.push("evolution_times");
        }
        self.evolution.increments = Some(Increments::Times(times.to_vec()));
        self
    }
    /// The pseudo-time of the initial state (as [`SceneBuilder::evolution_start`]).
    pub fn evolution_start(mut self, start: f64) -> Self {
        if self.evolution.start.is_some() {
            self.twice.push("evolution_start");
        }
        self.evolution.start = Some(start);
        self
    }
    /// The factor table of the loads named `name` (as [`SceneBuilder::load_factor`]).
    pub fn load_factor(mut self, name: &str, points: &[[f64; 2]]) -> Self {
        self.evolution.tables.push((name.to_string(), points.to_vec()));
        self
    }
    /// The part whose mean displacement the history records, `"body.part"` (as
    /// [`SceneBuilder::evolution_monitor`]).
    pub fn evolution_monitor(mut self, part: &str) -> Self {
        if self.evolution.monitor.is_some() {
            self.twice.push("evolution_monitor");
        }
        self.evolution.monitor = Some(part.to_string());
        self
    }
    /// The increment times at which the contact profiles are plotted (as
    /// [`SceneBuilder::evolution_profiles`]).
    pub fn evolution_profiles(mut self, times: &[f64]) -> Self {
        if self.evolution.profiles.is_some() {
            self.twice.push("evolution_profiles");
        }
        self.evolution.profiles = Some(times.to_vec());
        self
    }

    /// The scene, checked ([`Error::Scene`] at [`BUILT_IN_RUST`] for a mistake, naming the
    /// builder call and key; [`Error::Usage`] without any body).
    pub fn build(self) -> Result<Scene> {
        let Some((_, first)) = self.bodies.first() else {
            return Err(Error::Usage("BodiesBuilder::build: no body was given".into()));
        };
        for (body, scene) in &self.bodies {
            let ignored = [
                (scene.has_body_tables(), "several bodies of its own (BodiesBuilder scenes do not nest)"),
                (scene.title.is_some(), "a title (SceneBuilder::title)"),
                (!scene.petsc_options.is_empty(), "PETSc options (SceneBuilder::petsc_options)"),
                (scene.output_dir.is_some(), "an output directory (SceneBuilder::output_dir)"),
                (scene.estimate, "the estimate (SceneBuilder::estimate)"),
                (scene.formulation != Formulation::Primal, "a formulation (SceneBuilder::formulation)"),
                (
                    scene.dual_constraints != DualConstraints::Eliminated,
                    "dual constraints (SceneBuilder::dual_constraints)",
                ),
                (scene.contact_solver.is_some(), "a contact solver for the whole run"),
                (scene.evolution.is_some(), "a load path (SceneBuilder::evolution_steps, ...)"),
            ];
            if let Some((_, what)) = ignored.iter().find(|(set, _)| *set) {
                return Err(built_in_rust_error(
                    format!(
                        "BodiesBuilder::body(\"{}\", ..): the body's scene sets {what}, which would be ignored: a \
                         body's scene gives the body's data only",
                        body.name
                    ),
                    "set the scene-wide settings on the BodiesBuilder (new's title, petsc_options, output_dir, \
                     contact_solver, the load path's evolution_* and load_factor), not on a body's SceneBuilder"
                        .into(),
                ));
            }
        }
        if let Some(call) = self.twice.first() {
            return Err(built_in_rust_error(
                format!("BodiesBuilder::{call}: the setting is given twice: this call would replace the first"),
                "keep one call for each setting of the load path".into(),
            ));
        }
        if let Some((call, message, hint)) = self.refused.first() {
            return Err(built_in_rust_error(format!("{call}: {message}"), hint.clone()));
        }
        if let Some((call, message, hint)) = self.evolution.refusal("BodiesBuilder") {
            return Err(built_in_rust_error(format!("{call}: {message}"), hint));
        }
        let mut scene = Scene {
            source: PathBuf::from(BUILT_IN_RUST),
            title: Some(self.title.clone()),
            bodies: self.bodies.iter().map(|(b, _)| b.clone()).collect(),
            contact_pairs: self.pairs.clone(),
            petsc_options: self.petsc_options.clone(),
            output_dir: self.output_dir.clone(),
            contact_solver: self.contact_solver,
            ..first.clone()
        };
        scene.evolution = self.evolution.read(&scene)?;
        scene.validated()
    }
}

/// The builder call that wrote line `line` (1-based) of `text`, the scene text [`Scene::to_toml`]
/// generated for a scene built in Rust, with the key written on that line:
/// ``SceneBuilder::material (`poisson = 0.6`)``; for a `[[body]]`'s tables, prefixed with
/// `BodiesBuilder::body("name", ..)`.
fn builder_call(text: &str, line: usize) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let Some(last) = lines.len().checked_sub(1) else { return "SceneBuilder".into() };
    let index = line.saturating_sub(1).min(last);
    let written = lines[index].trim();
    let key = written.split_once(" = ").map(|(k, _)| k.trim());
    // The table of the line: the nearest header at or above it, and its lines.
    let start = (0..=index).rev().find(|&i| lines[i].starts_with('['));
    let header = start.map_or("", |i| lines[i].trim_matches(|c| c == '[' || c == ']'));
    let table: Vec<&str> = match start {
        Some(s) => lines[s + 1..].iter().take_while(|l| !l.starts_with('[')).copied().collect(),
        None => Vec::new(),
    };
    let value = |k: &str| {
        table.iter().find_map(|l| l.strip_prefix(k).and_then(|r| r.strip_prefix(" = "))).unwrap_or("..").to_string()
    };
    let (body, table_name) = match header.strip_prefix("body.") {
        Some(t) => {
            // The enclosing [[body]]'s name.
            let name = start
                .and_then(|s| (0..s).rev().find(|&i| lines[i] == "[[body]]"))
                .and_then(|b| lines[b + 1].strip_prefix("name = "))
                .unwrap_or("..");
            (Some(name), t)
        }
        None => (None, header),
    };
    let of_value = |k: &str, choices: &[(&str, &'static str)], otherwise: &'static str| {
        let v = value(k);
        choices.iter().find(|(c, _)| v.trim_matches('"') == *c).map_or(otherwise, |(_, call)| call)
    };
    // The load path is the BodiesBuilder's in a scene with several bodies.
    let path_builder = if lines.contains(&"[[body]]") { "BodiesBuilder" } else { "SceneBuilder" };
    let call = match (table_name, key) {
        ("", _) => "SceneBuilder::title".to_string(),
        (t, Some("name")) if t != "body" => "SceneBuilder::named".into(),
        ("contact", Some("motion")) => "SceneBuilder::obstacle_motion".into(),
        ("evolution", Some(k @ ("steps" | "times" | "start" | "monitor" | "profiles"))) => {
            format!("{path_builder}::evolution_{k}")
        }
        ("evolution", _) => format!("{path_builder}::evolution_steps"),
        ("evolution.factor", Some(k)) => format!("{path_builder}::load_factor({k}, ..)"),
        ("mesh", Some("mesher")) => "SceneBuilder::gmsh".into(),
        ("mesh", Some("refine")) => "SceneBuilder::refine".into(),
        ("mesh", _) => format!(
            "SceneBuilder::{}",
            of_value(
                "shape",
                &[
                    ("rectangle", "rectangle"),
                    ("disc", "disc"),
                    ("half_disc", "half_disc"),
                    ("quarter_disc", "quarter_disc")
                ],
                "mesh_file"
            )
        ),
        ("discretization", Some("element")) => "SceneBuilder::p2p0".into(),
        ("discretization", Some("formulation")) => "SceneBuilder::formulation".into(),
        ("discretization", Some("dual_constraints")) => "SceneBuilder::dual_constraints".into(),
        ("discretization", _) => "SceneBuilder::quadratic".into(),
        ("material", Some("plane")) if value("plane").contains("axisymmetric") => "SceneBuilder::axisymmetric".into(),
        ("material", Some("plane")) => "SceneBuilder::plane_stress".into(),
        ("material", _) => "SceneBuilder::material".into(),
        ("loads", _) => "SceneBuilder::body_force".into(),
        ("traction", _) => {
            let call = if value("pressure") != ".." { "pressure" } else { "traction" };
            format!("SceneBuilder::{call}({}, ..)", value("part"))
        }
        ("dirichlet", _) => match value("point") {
            p if p != ".." => format!("SceneBuilder::dirichlet_point({p}, ..)"),
            _ => format!("SceneBuilder::dirichlet({}, ..)", value("part")),
        },
        ("contact.interface", Some("trace")) => "SceneBuilder::interface_trace".into(),
        ("contact.interface", _) => "SceneBuilder::interface".into(),
        ("contact_pair.interface", Some("trace")) => "BodiesBuilder::pair_interface_trace".into(),
        ("contact_pair.interface", _) => "BodiesBuilder::pair_interface".into(),
        ("contact", Some("gap")) => "SceneBuilder::gap".into(),
        ("contact", Some("friction" | "mu" | "threshold")) => {
            format!("SceneBuilder::{}", of_value("friction", &[("tresca", "tresca")], "coulomb"))
        }
        ("contact", Some("solver" | "omega")) => "SceneBuilder::contact_solver".into(),
        ("contact", Some("tolerance")) => "SceneBuilder::contact_tolerance".into(),
        ("contact", Some("max_iterations")) => "SceneBuilder::contact_max_iterations".into(),
        ("contact", _) => format!(
            "SceneBuilder::{}",
            of_value("obstacle", &[("circle", "contact_circle"), ("polyline", "contact_polyline")], "contact_line")
        ),
        ("solver", _) => "SceneBuilder::petsc_options".into(),
        ("output", _) => "SceneBuilder::output_dir".into(),
        ("estimate", _) => "SceneBuilder::estimate".into(),
        ("body", _) => format!("BodiesBuilder::body({}, ..)", value("name")),
        ("contact_pair", Some("max_initial_overlap")) => {
            format!("BodiesBuilder::pair_with_overlap({}, {}, ..)", value("slave"), value("master"))
        }
        ("contact_pair", _) => format!("BodiesBuilder::pair({}, {}, ..)", value("slave"), value("master")),
        (other, _) => format!("[{other}]"),
    };
    let call = match body {
        Some(name) => format!("BodiesBuilder::body({name}, ..), its {call}"),
        None => call,
    };
    match key {
        Some(_) => format!("{call} (`{written}`)"),
        None => call,
    }
}
