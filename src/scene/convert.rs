//! Converting the tables of one body (`[mesh]`, `[discretization]`, `[material]`, `[loads]`,
//! `[[traction]]`, `[[dirichlet]]`, `[contact]`) from their raw TOML form, with every check and
//! its location. The same functions read the top level of a single-body scene and each
//! `[[body]]` of a scene with several bodies (`[body.mesh]`, `[[body.traction]]`...): a
//! [`Scope`] says which, so that missing-key errors point at the right header and messages name
//! the right table.
use super::contact::{contact_spec, ContactSpec};
use super::diagnostic::{describe, Source};
use super::evolution::load_name;
use super::raw::{
    first_span, Leaf, RawContact, RawDirichlet, RawDiscretization, RawLoads, RawMaterial, RawMesh, RawRefine,
    RawTraction,
};
use super::{
    DirichletSpec, DirichletTarget, Load, MaterialSpec, MeshSpec, Mesher, PlaneSpec, RefineSpec, TractionSpec,
    MAX_TRIANGLES,
};
use crate::error::{Location, Result};
use crate::fem::Element;
use crate::mesh::Order;
use std::ops::Range;
use std::path::Path;
use toml::{Spanned, Value};

/// Where the tables of one body are written: the top level of a single-body scene (`[mesh]`),
/// or one `[[body]]` table (`[body.mesh]`, found between its header and the next `[[body]]`).
#[derive(Debug, Clone)]
pub(super) struct Scope<'n> {
    /// The body's name, `None` at the top level.
    pub body: Option<&'n str>,
    /// The bytes of the scene text that hold this body's tables (the whole text at the top level).
    pub within: Range<usize>,
    /// Where a missing table or key of this body is reported when no header locates it: the
    /// start of the text at the top level, the `[[body]]` header for a body.
    pub anchor: Range<usize>,
}

impl<'n> Scope<'n> {
    pub fn top_level(text: &str) -> Self {
        Scope { body: None, within: 0..text.len(), anchor: 0..0 }
    }

    /// `mesh` at the top level, `body.mesh` in a `[[body]]`.
    pub fn header(&self, table: &str) -> String {
        match self.body {
            None => table.to_string(),
            Some(_) => format!("body.{table}"),
        }
    }

    /// How messages name a table: `[mesh]`, or `[body.mesh] of body `punch``.
    pub fn name(&self, table: &str, array: bool) -> String {
        let bracketed = match array {
            true => format!("[[{}]]", self.header(table)),
            false => format!("[{}]", self.header(table)),
        };
        match self.body {
            None => bracketed,
            Some(body) => format!("{bracketed} of body `{body}`"),
        }
    }

    /// The `occurrence`-th `table` of this body, located by its header, else its first key,
    /// else the scope's anchor.
    pub fn table<'s, 'a>(
        &self,
        src: &'s Source<'a>,
        table: &str,
        array: bool,
        occurrence: usize,
        first_key: Option<Range<usize>>,
    ) -> Table<'s, 'a> {
        let span = src
            .table_header_within(&self.header(table), array, occurrence, self.within.clone())
            .or(first_key)
            .unwrap_or(self.anchor.clone());
        Table { src, name: self.name(table, array), span }
    }
}

/// The tables of one body, borrowed from the top level of the scene or from one `[[body]]`.
pub(super) struct BodyTables<'r> {
    pub mesh: Option<&'r RawMesh>,
    pub discretization: Option<&'r RawDiscretization>,
    pub material: Option<&'r RawMaterial>,
    pub loads: Option<&'r RawLoads>,
    pub traction: &'r [RawTraction],
    pub dirichlet: &'r [RawDirichlet],
    pub contact: Option<&'r RawContact>,
}

/// One body's data, converted and checked (everything but its name and placement).
pub(super) struct BodyData {
    pub mesh: MeshSpec,
    pub order: Order,
    pub element: Element,
    pub material: MaterialSpec,
    pub body_force: [f64; 2],
    pub body_force_name: Option<String>,
    pub tractions: Vec<TractionSpec>,
    pub dirichlet: Vec<DirichletSpec>,
    pub contact: Option<ContactSpec>,
}

/// Convert the tables of one body. `[mesh]` and `[material]` are required.
pub(super) fn body_data(src: &Source, scope: &Scope, tables: &BodyTables, scene_dir: &Path) -> Result<BodyData> {
    let Some(raw_mesh) = tables.mesh else {
        let (message, hint) = match scope.body {
            None => (
                "the scene has no [mesh] table".to_string(),
                "add a [mesh] table, e.g. [mesh] shape = \"rectangle\", size = [1.0, 0.2], cell_size = 0.02"
                    .to_string(),
            ),
            Some(body) => (
                format!("body `{body}` has no mesh"),
                "add a [body.mesh] table after this [[body]] header (the keys of [mesh]), or \
                 mesh = { shape = \"rectangle\", size = [1.0, 0.2], cell_size = 0.02 }"
                    .to_string(),
            ),
        };
        return Err(src.error(&scope.anchor, message, hint));
    };
    let mesh = mesh_spec(src, scope, raw_mesh, scene_dir)?;
    let order = order(src, tables.discretization.and_then(|d| d.order.as_ref()))?;
    let Some(raw_material) = tables.material else {
        let (message, hint) = match scope.body {
            None => (
                "the scene has no [material] table".to_string(),
                "add a [material] table, e.g. [material] young = 210e9, poisson = 0.3".to_string(),
            ),
            Some(body) => (
                format!("body `{body}` has no material"),
                "add a [body.material] table after this [[body]] header, or material = { young = 210e9, \
                 poisson = 0.3 }"
                    .to_string(),
            ),
        };
        return Err(src.error(&scope.anchor, message, hint));
    };
    let material = material_spec(src, scope, raw_material)?;
    let element = element(src, tables.discretization.and_then(|d| d.element.as_ref()), order, &material)?;
    let body_force = match tables.loads.and_then(|l| l.body_force.as_ref()) {
        Some(v) => src.vector(v, "body_force")?,
        None => [0.0; 2],
    };
    let body_force_name = match tables.loads {
        Some(loads) => {
            let name = load_name(src, &loads.name)?;
            if let (Some(name_v), None) = (&loads.name, &loads.body_force) {
                return Err(src.error(
                    &name_v.span(),
                    format!("{} names its body force, but has no `body_force`", scope.name("loads", false)),
                    "`name` names the body force for [evolution.factor]: add body_force = [fx, fy], or remove the \
                     name",
                ));
            }
            name
        }
        None => None,
    };
    let tractions =
        tables.traction.iter().enumerate().map(|(i, t)| traction_spec(src, scope, t, i)).collect::<Result<Vec<_>>>()?;
    let dirichlet = tables
        .dirichlet
        .iter()
        .enumerate()
        .map(|(i, d)| dirichlet_spec(src, scope, d, i))
        .collect::<Result<Vec<_>>>()?;
    let contact = tables.contact.map(|c| contact_spec(src, scope, c, &dirichlet)).transpose()?;
    Ok(BodyData { mesh, order, element, material, body_force, body_force_name, tractions, dirichlet, contact })
}

// ---- conversion, one function per table -------------------------------------------------------

/// A table being converted: its display name and where to point when a key is missing.
pub(super) struct Table<'s, 'a> {
    pub src: &'s Source<'a>,
    pub name: String,
    pub span: Range<usize>,
}

impl<'s, 'a> Table<'s, 'a> {
    pub fn require<'v>(&self, leaf: &'v Leaf, key: &str, example: &str) -> Result<&'v Spanned<Value>> {
        leaf.as_ref().ok_or_else(|| {
            self.src.error(&self.span, format!("{} is missing `{key}`", self.name), format!("add `{example}`"))
        })
    }
}

const SHAPES: &[&str] = &["rectangle", "disc", "half_disc", "quarter_disc", "file"];
const MESHERS: &[&str] = &["structured", "gmsh"];
const RECTANGLE_KEYS: &[&str] = &["shape", "origin", "size", "cell_size", "mesher", "refine"];
const DISC_KEYS: &[&str] = &["shape", "center", "radius", "cell_size", "refine"];
const FILE_KEYS: &[&str] = &["shape", "file", "geometry"];

pub(super) fn mesh_spec(src: &Source, scope: &Scope, m: &RawMesh, scene_dir: &Path) -> Result<MeshSpec> {
    let table = scope.table(src, "mesh", false, 0, m.first_span());
    let shape_v = table.require(
        &m.shape,
        "shape",
        "shape = \"rectangle\" (or \"disc\", \"half_disc\", \"quarter_disc\", \"file\")",
    )?;
    let shape = src.choice(shape_v, "shape", SHAPES)?;
    let allowed = match shape {
        "rectangle" => RECTANGLE_KEYS,
        "disc" | "half_disc" | "quarter_disc" => DISC_KEYS,
        _ => FILE_KEYS,
    };
    if let Some((key, span)) = m.present_keys().into_iter().find(|(k, _)| !allowed.contains(k)) {
        let hint = match (shape, key) {
            ("file", _) => format!("a mesh file is used as it is: remove `{key}` (refine the mesh in gmsh instead)"),
            (_, "mesher") => {
                "disc, half_disc and quarter_disc meshes are always made by gmsh: remove `mesher`".to_string()
            }
            _ => format!("remove `{key}`; shape = \"{shape}\" takes {}", allowed.join(", ")),
        };
        return Err(src.error(&span, format!("`{key}` does not apply to shape = \"{shape}\""), hint));
    }
    let table = Table { name: format!("{} with shape = \"{shape}\"", scope.name("mesh", false)), ..table };

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
                "quarter_disc" => MeshSpec::QuarterDisc { center, radius, cell_size, refine: None },
                _ => MeshSpec::HalfDisc { center, radius, cell_size, refine: None },
            }
        }
    };
    let area = match &spec {
        MeshSpec::Rectangle { size, .. } => size[0] * size[1],
        MeshSpec::Disc { radius, .. } => std::f64::consts::PI * radius * radius,
        MeshSpec::HalfDisc { radius, .. } => std::f64::consts::PI * radius * radius / 2.0,
        MeshSpec::QuarterDisc { radius, .. } => std::f64::consts::PI * radius * radius / 4.0,
        MeshSpec::File { .. } => 0.0,
    };
    check_cell_count(src, cell_v, "cell_size", cell_size, area)?;
    if let Some(r) = &m.refine {
        let rt = scope.table(src, "mesh.refine", false, 0, r.first_span().or(Some(table.span.clone())));
        if let MeshSpec::Rectangle { mesher: Mesher::Structured, .. } = spec {
            return Err(src.error(
                &rt.span,
                "`refine` needs mesher = \"gmsh\"",
                "the structured mesher makes a uniform grid: add mesher = \"gmsh\" to [mesh], or remove refine",
            ));
        }
        let parsed = refine_spec(src, r, rt, cell_size)?;
        match &mut spec {
            MeshSpec::Rectangle { refine, .. }
            | MeshSpec::Disc { refine, .. }
            | MeshSpec::HalfDisc { refine, .. }
            | MeshSpec::QuarterDisc { refine, .. } => *refine = Some(parsed),
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

pub(super) fn order(src: &Source, v: Option<&Spanned<Value>>) -> Result<Order> {
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
pub(super) fn element(
    src: &Source,
    v: Option<&Spanned<Value>>,
    order: Order,
    material: &MaterialSpec,
) -> Result<Element> {
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

pub(super) fn material_spec(src: &Source, scope: &Scope, m: &RawMaterial) -> Result<MaterialSpec> {
    let first = first_span(&[&m.young, &m.poisson, &m.plane]);
    let table = scope.table(src, "material", false, 0, first);
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
        Some(v) => match src.choice(v, "plane", &["strain", "stress", "axisymmetric"])? {
            "stress" => PlaneSpec::Stress,
            "axisymmetric" => PlaneSpec::Axisymmetric,
            _ => PlaneSpec::Strain,
        },
        None => PlaneSpec::Strain,
    };
    Ok(MaterialSpec { young, poisson, plane })
}

fn part_name(src: &Source, table: &Table, leaf: &Leaf) -> Result<(String, Location)> {
    let v = table.require(leaf, "part", "part = \"left\" (a boundary physical name of the mesh)")?;
    Ok((src.nonempty_string(v, "part")?.to_string(), src.location(v.span().start)))
}

fn traction_spec(src: &Source, scope: &Scope, t: &RawTraction, index: usize) -> Result<TractionSpec> {
    let first = first_span(&[&t.part, &t.traction, &t.pressure, &t.name]);
    let table = scope.table(src, "traction", true, index, first);
    let table = Table { name: format!("this {} table", table.name), ..table };
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
    let name = load_name(src, &t.name)?;
    Ok(TractionSpec { part, load, name, at })
}

fn dirichlet_spec(src: &Source, scope: &Scope, d: &RawDirichlet, index: usize) -> Result<DirichletSpec> {
    let first = first_span(&[&d.part, &d.point, &d.ux, &d.uy, &d.name]);
    let table = scope.table(src, "dirichlet", true, index, first);
    let table = Table { name: format!("this {} table", table.name), ..table };
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
    let name = load_name(src, &d.name)?;
    Ok(DirichletSpec { target, ux, uy, name, at })
}

pub(super) fn petsc_options(src: &Source, v: &Spanned<Value>) -> Result<Vec<String>> {
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
