//! Scenes with several bodies: `[[body]]` and `[[contact_pair]]` tables.
//!
//! # The problem
//!
//! Bodies `Ω_1, ..., Ω_n` (disjoint open sets of the plane, up to a stated initial overlap),
//! each with its own mesh, element order, material `(E_b, ν_b)`, loads and Dirichlet conditions,
//! and optionally its own rigid obstacle (`[body.contact]`, the `[contact]` of one body):
//!
//! ```text
//!   -div σ_b(u_b) = f_b   in Ω_b,     σ_b(u) = λ_b tr ε(u) I + 2 μ_b ε(u)      b = 1..n
//!   u_b = g, σ_b n = t    on the parts named by the body's [[body.dirichlet]], [[body.traction]]
//! ```
//!
//! and, for every `[[contact_pair]]` between a part `Γs` of a body `s` (the slave) and a part
//! `Γm` of another body `m` (the master), with `n` the outward normal of the slave, `x ↦ y(x)`
//! the closest point of `Γm` (taken on the initial configuration), the gap
//! `g = g0 − (u_s(x) − u_m(y))·n` and the slave's contact traction `σN = n·σ_s n`,
//! `σT = σ_s n − σN n` (the master carries the opposite traction):
//!
//! ```text
//!   Signorini:  g ≥ 0,   σN ≤ 0,   σN g = 0
//!   friction:   none | Tresca (|σT| ≤ threshold) | Coulomb (|σT| ≤ −mu σN), slip against σT
//! ```
//!
//! (Wriggers, *Computational Contact Mechanics*, 2nd ed., Springer 2006, ch. 4; the mortar
//! discretisation of the pair is `contact::mortar`'s business.) The plane model (strain or
//! stress) is the same for every body: it is an assumption about the out-of-plane direction of
//! the whole assembly (a plane-stress plate against a plane-strain body has no consistent
//! thickness), so differing `plane` values are refused.
//!
//! # Placement
//!
//! A body's mesh is described in its own coordinates (`[body.mesh]`: the same keys as `[mesh]`,
//! and its `refine` point in the same coordinates), then moved rigidly:
//! `x = R(rotate) x_mesh + translate`, with `R(θ)` the counter-clockwise rotation by `θ` degrees
//! about the mesh's point `(0, 0)`. Everything else in the scene (Dirichlet points, obstacles)
//! is in the common coordinates. A rotation keeps triangles counter-clockwise and boundary edges
//! with the body on their left, so a placed mesh keeps the conventions of [`crate::mesh`].
//!
//! # Names
//!
//! A body's name is made of letters, digits, `_` and `-` (no `.`): a part of a body is written
//! `"body.part"` (split at the first `.`, so the part name may hold dots). A single-body scene is
//! one body named [`SINGLE_BODY_NAME`] ([`Scene::bodies`]).
use super::contact::friction_from;
use super::convert::{body_data, BodyData, BodyTables, Scope, Table};
use super::diagnostic::{closest, Source};
use super::interface::{interface_spec, ContactFrictionKeys};
use super::raw::{RawBody, RawContactPair, RawScene};
use super::{
    boundary_group, node_at, ContactSpec, DirichletSpec, DirichletTarget, FrictionSpec, MaterialSpec, MeshSpec,
    PlaneSpec, Scene, TractionSpec,
};
use crate::error::{Location, Result};
use crate::fem::Element;
use crate::mesh::{Mesh, Order};
use std::borrow::Cow;
use std::fmt;
use std::ops::Range;
use std::path::Path;

/// The name of the one body of a single-body scene in [`Scene::bodies`] (and of its parts in a
/// union mesh: `body.bottom`).
pub const SINGLE_BODY_NAME: &str = "body";

/// A rigid placement of a body's mesh: `x = R(rotate) x_mesh + translate`, the rotation
/// counter-clockwise by `rotate` degrees about the mesh's `(0, 0)`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Placement {
    /// Degrees, counter-clockwise.
    pub rotate: f64,
    /// Translation (m), applied after the rotation.
    pub translate: [f64; 2],
}

impl Placement {
    /// The common coordinates of the mesh point `p`.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.rotate.to_radians().sin_cos();
        // Exact quarter turns, so that a rectangle turned by 90° keeps its corners on the grid.
        let quarter_turns = self.rotate.rem_euclid(360.0) / 90.0;
        let (s, c) = match quarter_turns.fract() == 0.0 {
            true => [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][quarter_turns as usize % 4],
            false => (s, c),
        };
        [c * p[0] - s * p[1] + self.translate[0], s * p[0] + c * p[1] + self.translate[1]]
    }
    /// Whether the placement moves nothing (no rotation, no translation).
    pub fn is_identity(&self) -> bool {
        self.rotate == 0.0 && self.translate == [0.0, 0.0]
    }
}

/// One body: the data of a single-body scene, with a name and a placement.
#[derive(Debug, Clone, PartialEq)]
pub struct BodySpec {
    /// The body's name (letters, digits, `_`, `-`), unique in the scene.
    pub name: String,
    /// Where the body's mesh is placed in the scene's coordinates.
    pub placement: Placement,
    /// The mesh in the body's own coordinates (moved by `placement`).
    pub mesh: MeshSpec,
    /// Order of the triangles (the same for every body of a scene).
    pub order: Order,
    /// The displacement element: Lagrange or P2–P0.
    pub element: Element,
    /// The body's material.
    pub material: MaterialSpec,
    /// Body force per unit volume (N/m³).
    pub body_force: [f64; 2],
    /// `[body.loads] name`: the load name of the body force ([`super::EvolutionSpec::factor`]).
    pub body_force_name: Option<String>,
    /// The body's `[[traction]]` tables, in file order.
    pub tractions: Vec<TractionSpec>,
    /// The body's `[[dirichlet]]` tables, in file order.
    pub dirichlet: Vec<DirichletSpec>,
    /// Contact of a part of this body with a rigid obstacle.
    pub contact: Option<ContactSpec>,
    /// Where `name = ...` is written (the start of the file for a single-body scene).
    pub at: Location,
}

/// The boundary parts named by a body's tables, with where: tractions, Dirichlet parts, the
/// rigid contact part, each in file order (a body's or a single-body scene's).
pub(super) fn named_parts<'a>(
    tractions: &'a [TractionSpec],
    dirichlet: &'a [DirichletSpec],
    contact: Option<&'a ContactSpec>,
) -> impl Iterator<Item = (&'a str, &'a Location)> {
    let t = tractions.iter().map(|t| (t.part.as_str(), &t.at));
    let d = dirichlet.iter().filter_map(|d| match &d.target {
        DirichletTarget::Part(part) => Some((part.as_str(), &d.at)),
        DirichletTarget::Point(_) => None,
    });
    let c = contact.into_iter().map(|c| (c.part.as_str(), &c.at));
    t.chain(d).chain(c)
}

/// Every part named is a boundary part of `mesh`, every point condition has a node of `mesh`
/// at its point.
pub(super) fn check_named_against_mesh(
    mesh: &Mesh,
    tractions: &[TractionSpec],
    dirichlet: &[DirichletSpec],
    contact: Option<&ContactSpec>,
) -> Result<()> {
    for (part, at) in named_parts(tractions, dirichlet, contact) {
        boundary_group(mesh, part, at)?;
    }
    for d in dirichlet {
        if let DirichletTarget::Point(point) = d.target {
            node_at(mesh, point, &d.at)?;
        }
    }
    Ok(())
}

impl BodySpec {
    /// Every boundary part the body's tables name, with where: tractions, Dirichlet parts, the
    /// rigid contact part, each in file order.
    pub fn boundary_parts(&self) -> impl Iterator<Item = (&str, &Location)> {
        named_parts(&self.tractions, &self.dirichlet, self.contact.as_ref())
    }

    /// Check the body's tables against its placed mesh: every part named is a boundary part of
    /// `mesh`, every point condition has a node of `mesh` at its point.
    pub fn check_against_mesh(&self, mesh: &Mesh) -> Result<()> {
        check_named_against_mesh(mesh, &self.tractions, &self.dirichlet, self.contact.as_ref())
    }

    pub(super) fn data(&self) -> BodyData {
        BodyData {
            mesh: self.mesh.clone(),
            order: self.order,
            element: self.element,
            material: self.material,
            body_force: self.body_force,
            body_force_name: self.body_force_name.clone(),
            tractions: self.tractions.clone(),
            dirichlet: self.dirichlet.clone(),
            contact: self.contact.clone(),
        }
    }
}

/// A boundary part of a body, written `"body.part"`.
#[derive(Debug, Clone, PartialEq)]
pub struct PartRef {
    /// The body's name.
    pub body: String,
    /// One of the body's boundary parts.
    pub part: String,
    /// Where the `"body.part"` string is written.
    pub at: Location,
}

impl fmt::Display for PartRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.body, self.part)
    }
}

/// Contact between a part of one body (the slave) and a part of another (the master).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPairSpec {
    /// The slave part: the contact conditions are written on its side (choose the finer mesh).
    pub slave: PartRef,
    /// The master part, of another body.
    pub master: PartRef,
    /// Coulomb with `mu = 0` is stored as [`FrictionSpec::None`], as in `[contact]`.
    pub friction: FrictionSpec,
    /// The largest initial interpenetration of the two bodies accepted (m, ≥ 0); `None`: the
    /// default, [`super::DEFAULT_OVERLAP_FRACTION`] times the smaller of the two bodies' smallest
    /// cell edges.
    pub max_initial_overlap: Option<f64>,
    /// `[contact_pair.interface]`: the interface law (`None`: Signorini with `friction`).
    pub interface: Option<super::InterfaceSpec>,
    /// Where the `[[contact_pair]]` table starts.
    pub at: Location,
}

impl Scene {
    /// Whether the scene is written with `[[body]]` tables (even a single one). Such scenes are
    /// solved by `signorini run` (the primal formulation); the dual formulation, the estimate,
    /// `export`, `adapt` and `study` take one body.
    pub fn has_body_tables(&self) -> bool {
        !self.bodies.is_empty()
    }

    /// Every scene as bodies: the `[[body]]` tables, or for a single-body scene its one body,
    /// named [`SINGLE_BODY_NAME`], unmoved.
    pub fn bodies(&self) -> Cow<'_, [BodySpec]> {
        if self.has_body_tables() {
            return Cow::Borrowed(&self.bodies);
        }
        Cow::Owned(vec![BodySpec {
            name: SINGLE_BODY_NAME.to_string(),
            placement: Placement::default(),
            mesh: self.mesh.clone(),
            order: self.order,
            element: self.element,
            material: self.material,
            body_force: self.body_force,
            body_force_name: self.body_force_name.clone(),
            tractions: self.tractions.clone(),
            dirichlet: self.dirichlet.clone(),
            contact: self.contact.clone(),
            at: Location { file: self.source.clone(), line: 1, column: 1 },
        }])
    }

    /// The index of the body named `name` in [`Scene::bodies`].
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies().iter().position(|b| b.name == name)
    }
}

// ---- conversion -------------------------------------------------------------------------------

/// A `[[contact_pair]]` without `[[body]]` tables.
pub(super) fn refuse_pairs_without_bodies(src: &Source, raw: &RawScene) -> Result<()> {
    let Some(pair) = raw.contact_pair.first() else {
        return Ok(());
    };
    let span = src.table_header("contact_pair", true, 0).or(pair.first_span()).unwrap_or(0..0);
    Err(src.error(
        &span,
        "a [[contact_pair]] needs bodies, but the scene has no [[body]] tables",
        "contact pairs join parts of two bodies declared with [[body]] tables (see \"Several bodies\" in \
         docs/scene-format.md); a single body touches a rigid obstacle through [contact]",
    ))
}

/// The single-body tables written at the top level of a scene with `[[body]]` tables.
pub(super) fn refuse_top_level_body_tables(src: &Source, raw: &RawScene) -> Result<()> {
    let written: [(&str, bool, bool); 8] = [
        ("mesh", false, raw.mesh.is_some()),
        ("discretization", false, raw.discretization.is_some()),
        ("material", false, raw.material.is_some()),
        ("loads", false, raw.loads.is_some()),
        ("traction", true, !raw.traction.is_empty()),
        ("dirichlet", true, !raw.dirichlet.is_empty()),
        ("contact", false, raw.contact.is_some()),
        ("estimate", false, raw.estimate.is_some()),
    ];
    for (table, array, present) in written {
        if !present {
            continue;
        }
        let header = match array {
            true => format!("[[{table}]]"),
            false => format!("[{table}]"),
        };
        // Written with a header, or inline / with dotted keys: then the key itself.
        let span = src.table_header(table, array, 0).or_else(|| top_level_key(src, table)).unwrap_or(0..0);
        let hint = match table {
            "estimate" => "the error estimate solves the dual (stress) formulation, which takes a single body: \
                           remove [estimate]"
                .to_string(),
            _ => format!(
                "in a scene with [[body]] tables every body has its own tables: move this one under a [[body]] \
                 header as [{}body.{table}{}] (or write the scene with one body and no [[body]] tables)",
                if array { "[" } else { "" },
                if array { "]" } else { "" }
            ),
        };
        return Err(src.error(
            &span,
            format!("{header} at the top level cannot be combined with [[body]] tables"),
            hint,
        ));
    }
    Ok(())
}

/// The span of a top-level line `key = ...` or `key.x = ...` (a table written inline or with
/// dotted keys), before the first header.
fn top_level_key(src: &Source, key: &str) -> Option<Range<usize>> {
    let mut start = 0;
    for line in src.text.split_inclusive('\n') {
        let here = start;
        start += line.len();
        let trimmed = line.trim_start();
        if trimmed.starts_with('[') {
            return None;
        }
        let lhs = trimmed.split('=').next().unwrap_or("").trim();
        if lhs == key || lhs.starts_with(&format!("{key}.")) {
            let indent = line.len() - trimmed.len();
            return Some(here + indent..here + line.trim_end().len());
        }
    }
    None
}

/// Convert the `[[body]]` tables: each body's tables, its name and placement; names unique,
/// one element order and one plane model for all.
pub(super) fn body_specs(src: &Source, raw: &[RawBody], scene_dir: &Path) -> Result<Vec<BodySpec>> {
    let mut bodies: Vec<BodySpec> = Vec::with_capacity(raw.len());
    for (index, body) in raw.iter().enumerate() {
        let header = src.table_header("body", true, index);
        let next = src.table_header("body", true, index + 1).map_or(src.text.len(), |h| h.start);
        let within = header.as_ref().map_or(0..0, |h| h.start..next);
        let anchor = header.clone().or(body.first_span()).unwrap_or(0..0);

        let Some(name_v) = &body.name else {
            return Err(src.error(
                &anchor,
                format!("[[body]] number {} has no `name`", index + 1),
                "add name = \"punch\" (letters, digits, `_` and `-`): contact pairs and messages refer to the \
                 body by its name",
            ));
        };
        let name = src.nonempty_string(name_v, "name")?;
        if let Some(bad) = name.chars().find(|c| !(c.is_alphanumeric() || *c == '_' || *c == '-')) {
            return Err(src.error(
                &name_v.span(),
                format!("the body name `{name}` contains `{bad}`"),
                "a body name holds letters, digits, `_` and `-` only (a part of a body is written \"body.part\")",
            ));
        }
        if let Some(first) = bodies.iter().find(|b| b.name == name) {
            return Err(src.error(
                &name_v.span(),
                format!("two bodies are named `{name}` (the first on line {})", first.at.line),
                "give every [[body]] its own name",
            ));
        }
        let scope = Scope { body: Some(name), within, anchor };
        if let Some(d) = &body.discretization {
            for (key, leaf) in [("formulation", &d.formulation), ("dual_constraints", &d.dual_constraints)] {
                if let Some(v) = leaf {
                    return Err(src.error(
                        &v.span(),
                        format!("`{key}` does not apply to one body"),
                        "a scene with several bodies is solved for displacements (the primal formulation): \
                         remove it; a body's discretization takes `order` and `element`",
                    ));
                }
            }
        }
        let tables = BodyTables {
            mesh: body.mesh.as_ref(),
            discretization: body.discretization.as_ref(),
            material: body.material.as_ref(),
            loads: body.loads.as_ref(),
            traction: &body.traction,
            dirichlet: &body.dirichlet,
            contact: body.contact.as_ref(),
        };
        let BodyData { mesh, order, element, material, body_force, body_force_name, tractions, dirichlet, contact } =
            body_data(src, &scope, &tables, scene_dir)?;
        let rotate = body.rotate.as_ref().map(|v| src.number(v, "rotate")).transpose()?.unwrap_or(0.0);
        let translate = body.translate.as_ref().map(|v| src.vector(v, "translate")).transpose()?.unwrap_or([0.0; 2]);

        if let Some(first) = bodies.first() {
            let order_v = body.discretization.as_ref().and_then(|d| d.order.as_ref());
            if order != first.order {
                let span = order_v.map(|v| v.span()).unwrap_or(scope.anchor.clone());
                return Err(src.error(
                    &span,
                    format!(
                        "body `{name}` has order = {}, but body `{}` (line {}) has order = {}",
                        order.degree(),
                        first.name,
                        first.at.line,
                        first.order.degree()
                    ),
                    "the bodies are meshed into one mesh, whose triangles all have the same order: give every \
                     body the same [body.discretization] order",
                ));
            }
            if material.plane != first.material.plane {
                let plane_v = body.material.as_ref().and_then(|m| m.plane.as_ref());
                let span = match plane_v {
                    Some(v) => v.span(),
                    None => scope.table(src, "material", false, 0, None).span,
                };
                let named = |p: PlaneSpec| format!("\"{}\"", p.name());
                return Err(src.error(
                    &span,
                    format!(
                        "body `{name}` is in plane = {}, but body `{}` (line {}) is in plane = {}",
                        named(material.plane),
                        first.name,
                        first.at.line,
                        named(first.material.plane)
                    ),
                    "the plane model is an assumption about the whole assembly (plane strain: long bodies; \
                     plane stress: thin plates; axisymmetric: bodies of revolution): give every body the same [body.material] plane",
                ));
            }
        }
        bodies.push(BodySpec {
            name: name.to_string(),
            placement: Placement { rotate, translate },
            mesh,
            order,
            element,
            material,
            body_force,
            body_force_name,
            tractions,
            dirichlet,
            contact,
            at: src.location(name_v.span().start),
        });
    }
    Ok(bodies)
}

/// Convert the `[[contact_pair]]` tables against the bodies (their parts are checked once the
/// meshes exist: [`super::BodiesModel::build`]).
pub(super) fn contact_pair_specs(
    src: &Source,
    raw: &[RawContactPair],
    bodies: &[BodySpec],
) -> Result<Vec<ContactPairSpec>> {
    let mut pairs: Vec<ContactPairSpec> = Vec::with_capacity(raw.len());
    for (index, pair) in raw.iter().enumerate() {
        let span = src.table_header("contact_pair", true, index).or(pair.first_span()).unwrap_or(0..0);
        let missing = |key: &str, example: &str| {
            src.error(
                &span,
                format!("this [[contact_pair]] table is missing `{key}`"),
                format!("add `{key} = \"{example}\"` (a body name and one of its boundary parts)"),
            )
        };
        let slave_v = pair.slave.as_ref().ok_or_else(|| missing("slave", "punch.bottom"))?;
        let master_v = pair.master.as_ref().ok_or_else(|| missing("master", "foundation.top"))?;
        let slave = part_ref(src, slave_v, "slave", bodies)?;
        let master = part_ref(src, master_v, "master", bodies)?;
        if slave.body == master.body {
            let message = match slave.part == master.part {
                true => format!("`slave` and `master` are the same part `{slave}`"),
                false => {
                    format!("`slave` `{slave}` and `master` `{master}` are parts of the same body `{}`", slave.body)
                }
            };
            return Err(src.error(
                &master_v.span(),
                message,
                "a contact pair joins parts of two different bodies (contact of a body with itself is not \
                 supported): name a part of another body as `master`",
            ));
        }
        let same = |a: &PartRef, b: &PartRef| a.body == b.body && a.part == b.part;
        if let Some(earlier) = pairs.iter().find(|p| {
            (same(&p.slave, &slave) && same(&p.master, &master)) || (same(&p.slave, &master) && same(&p.master, &slave))
        }) {
            return Err(src.error(
                &span,
                format!(
                    "this pair of `{slave}` and `{master}` repeats the [[contact_pair]] of line {}",
                    earlier.at.line
                ),
                "write one [[contact_pair]] per pair of parts: remove this one",
            ));
        }
        let interface = match &pair.interface {
            Some(raw) => {
                // The pair's interface table: its [contact_pair.interface] header between this
                // pair's header and the next one, else its first key (written inline).
                let next = src.table_header("contact_pair", true, index + 1).map_or(src.text.len(), |h| h.start);
                let first = raw.present_keys().first().map(|(_, s)| s.clone());
                let header = src.table_header_within("contact_pair.interface", false, 0, span.start..next);
                let table = Table {
                    src,
                    name: "[contact_pair.interface]".to_string(),
                    span: header.or(first).unwrap_or(span.clone()),
                };
                let keys = ContactFrictionKeys {
                    friction: &pair.friction,
                    mu: &pair.mu,
                    threshold: &pair.threshold,
                    table: "this [[contact_pair]]".to_string(),
                };
                Some(interface_spec(src, &table, raw, &keys)?)
            }
            None => None,
        };
        let friction = friction_from(src, &pair.friction, &pair.mu, &pair.threshold)?;
        let max_initial_overlap = match &pair.max_initial_overlap {
            Some(v) => {
                let overlap = src.number(v, "max_initial_overlap")?;
                if overlap < 0.0 {
                    return Err(src.error(
                        &v.span(),
                        format!("`max_initial_overlap` must not be negative, found {}", src.written(v)),
                        "give the largest initial interpenetration of the two bodies to accept, a length ≥ 0 (m)",
                    ));
                }
                Some(overlap)
            }
            None => None,
        };
        pairs.push(ContactPairSpec {
            slave,
            master,
            friction,
            max_initial_overlap,
            interface,
            at: src.location(span.start),
        });
    }
    Ok(pairs)
}

/// `"body.part"` naming a declared body.
fn part_ref(src: &Source, v: &toml::Spanned<toml::Value>, key: &str, bodies: &[BodySpec]) -> Result<PartRef> {
    let text = src.nonempty_string(v, key)?;
    let at = src.location(v.span().start);
    let names: Vec<&str> = bodies.iter().map(|b| b.name.as_str()).collect();
    let Some((body, part)) = text.split_once('.').filter(|(b, p)| !b.is_empty() && !p.is_empty()) else {
        return Err(src.error(
            &v.span(),
            format!("`{key}` must name a body and one of its boundary parts as \"body.part\", found \"{text}\""),
            format!("write e.g. `{key} = \"{}.bottom\"`; the bodies are: {}", names[0], names.join(", ")),
        ));
    };
    if !names.contains(&body) {
        let known = format!("the bodies are: {}", names.join(", "));
        let hint = match closest(body, &names) {
            Some(guess) => format!("did you mean `{guess}`? {known}"),
            None => known,
        };
        return Err(src.error(&v.span(), format!("`{key}` names an unknown body `{body}`"), hint));
    }
    Ok(PartRef { body: body.to_string(), part: part.to_string(), at })
}
