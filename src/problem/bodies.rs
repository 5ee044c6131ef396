//! Several deformable bodies in contact: the driver's part for scenes with `[[body]]` and
//! `[[contact_pair]]` tables.
//!
//! ```text
//! setup     every body meshed, placed and checked (scene::BodiesModel), united into one mesh
//!           whose parts are `body.part`; one material per cell; each body's Dirichlet
//!           conditions on its own nodes; contact points of every pair from the mortar coupling
//!           (contact::mortar: dual basis on the slave side, B rows on the slave node and on the
//!           master nodes), and of every body's rigid obstacle, merged into one ContactBoundary
//! solve     the full-space Newton of full_space/ (default), or the condensed route of
//!           contact.rs: W = B K⁻¹ Bᵀ from one factorisation of the
//!           block-diagonal K of all bodies (its Schur complement on every dof B touches, both
//!           sides of every pair), any condensed solver, u = K⁻¹ (f + Bᵀ r), the independent
//!           check on (r, B u) with u from the field solve
//! verify    global equilibrium (as for one body), and for each body separately: its loads,
//!           the reactions of its supports and the contact forces on its nodes balance; for each
//!           pair, action and reaction: the resultants of the two sides cancel
//! ```
//!
//! ## Bodies held by contact
//!
//! A body that its Dirichlet conditions do not hold (a block pressed on a foundation, held
//! vertically by the contact alone) makes `K` singular. As for one body on a rigid obstacle
//! (contact.rs), springs `S = k I` are added at every free dof that `B` touches (slave and
//! master nodes of every pair: the free body may be either side), anchored at the previous
//! iterate: proximal-point iterations whose spring force vanishes at convergence, so the answer
//! is that of the unstabilised problem. A body that the contact cannot hold either (it lifts
//! off, or friction cannot hold it sideways) never converges, and the run says so.
//!
//! ## Solver: the full-space Newton by default
//!
//! `newton_full` (the default) is the full-space semi-smooth Newton of `full_space/` on
//! `(u¹, u², …, λ)`: its contact rows carry every entry of the mortar rows of `B` (slave and
//! master nodes), its rigid-motion check has 3 rigid motions per body. On one process its
//! Jacobian solves use one MUMPS factorisation for the whole iteration: the block elimination
//! when every body is held by its Dirichlet conditions, the floating elimination (springs at
//! pinned dofs of each body the contact holds, removed in every step) otherwise; under MPI,
//! SNES's LU of the mixed Jacobian (`mpirun -n 2` takes the serial steps to the serial answer).
//! A body free to move in a mode the closed rows do not see (a cylinder turning about its
//! centre on frictionless contact) gets springs on that mode only, which leave the Newton steps
//! exact while the loads do not drive it. If the full-space iteration fails it hands over to
//! the condensed semi-smooth Newton (`solver = "newton"`, which any scene may also ask for),
//! saying so in the contact notes. `snes_vi` is refused.
use crate::contact::boundary::ContactBoundary;
use crate::contact::mortar::{MortarCoupling, MortarOptions, MortarSide, UncoveredNodes};
use crate::error::{Error, Location, Result};
use crate::fem::assembly::Constraints;
use crate::fem::material::{CellMaterials, Material, PlaneModel};
use crate::mesh::{self, Mesh};
use crate::scene::{
    self, BodiesModel, ContactSolverSpec, ContactSpec, DirichletSpec, DirichletTarget, FrictionSpec, ObstacleSpec,
    Scene, TractionSpec,
};

use crate::contact_routes::condensed_route::{obstacle_of, spring_dofs, ContactSetup};
use crate::report::warnings::Warning;

/// Slave points farther from the master side than this fraction of the smaller side's extent
/// are not paired (see [`contact_of_bodies`]).
pub const PAIRING_DISTANCE: f64 = 0.1;

/// The contact parts of a scene with several bodies: pairs between bodies and rigid obstacles
/// of single bodies, each with its friction law, and the part of every contact point.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactParts {
    /// Every contact part: the pairs, then the bodies' rigid obstacles.
    pub parts: Vec<ContactPart>,
    /// The part of each contact point (index into `parts`).
    pub part_of: Vec<usize>,
}

/// One contact part of a scene with several bodies.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPart {
    /// `slave.part / master.part` for a pair, `body.part` for a rigid obstacle.
    pub name: String,
    /// The body whose nodes are the contact points (the slave side of a pair).
    pub slave_body: usize,
    /// The slave side's boundary group in the union mesh.
    pub slave_group: usize,
    /// The other side of a pair; `None` for a rigid obstacle.
    pub master: Option<MasterSide>,
    /// The part's friction law.
    pub friction: FrictionSpec,
    /// The part's interface law (`None`: Signorini with `friction`).
    pub interface: Option<scene::InterfaceSpec>,
    /// Where the part's table starts.
    pub at: Location,
}

/// The master side of a contact pair: its body and its boundary group in the union mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MasterSide {
    /// The master body's index.
    pub body: usize,
    /// The master part's boundary group in the union mesh.
    pub group: usize,
    /// Slave nodes farther than this from the master side are not contact points.
    pub pairing_distance: f64,
}

impl ContactParts {
    /// The friction law of contact point `i`.
    pub fn friction_of_point(&self, i: usize) -> FrictionSpec {
        self.part_of.get(i).map_or(FrictionSpec::None, |&p| self.parts[p].friction)
    }

    /// Every part's friction law, for the report (one law when they all have the same).
    pub fn friction_report(&self) -> crate::report::contact::FrictionReport {
        crate::report::contact::FrictionReport::of_parts(self.parts.iter().map(|p| (p.name.as_str(), p.friction)))
    }
}

/// What the driver needs of a scene with several bodies: the scene flattened onto the union
/// mesh (parts renamed `body.part`, the first body's material as the scene's), the union mesh,
/// the materials per cell, the constraints and the contact.
pub(super) struct BodiesSetup {
    pub scene: Scene,
    pub mesh: Mesh,
    pub material: Material,
    pub cell_materials: CellMaterials,
    pub constraints: Constraints,
    pub contact: Option<ContactSetup>,
    pub model: BodiesModel,
    /// Warnings known at set-up: contact pairs out of the pairing range.
    pub warnings: Vec<Warning>,
}

/// The material a scene's (or a body's) `[material]` table describes.
pub(super) fn material_of(spec: &scene::MaterialSpec) -> Material {
    Material {
        young: spec.young,
        poisson: spec.poisson,
        plane: match spec.plane {
            scene::PlaneSpec::Strain => PlaneModel::Strain,
            scene::PlaneSpec::Stress => PlaneModel::Stress,
            scene::PlaneSpec::Axisymmetric => PlaneModel::Axisymmetric,
        },
    }
}

/// Set up a scene with several bodies on its model (see the module documentation).
pub(super) fn setup_bodies(scene: Scene, mut model: BodiesModel) -> Result<BodiesSetup> {
    // Axisymmetry: the union's measure and axis nodes, copied to every body's own mesh.
    let plane = material_of(&model.bodies[0].material).plane;
    super::axisymmetry::prepare_mesh(&mut model.mesh, plane, None)?;
    super::axisymmetry::refuse_interface_laws(&scene)?;
    for (body, range) in model.body_meshes.iter_mut().zip(&model.layout.bodies) {
        body.measure = model.mesh.measure;
        body.nodes.copy_from_slice(&model.mesh.nodes[range.nodes.clone()]);
    }
    let flat = flatten(&scene, &model)?;
    let mesh = model.mesh.clone();
    // Materials: one per body, in body order.
    let materials: Vec<Material> = model.bodies.iter().map(|b| material_of(&b.material)).collect();
    let cell_materials = CellMaterials::per_cell(materials.clone(), model.layout.cell_body.clone())?;
    // Each body's Dirichlet conditions on its own nodes.
    let mut constraints = Constraints::new(2 * mesh.num_nodes());
    for (d, nodes) in flat.dirichlet.iter().zip(dirichlet_nodes(&model)?) {
        for node in nodes {
            if let Some(ux) = d.ux {
                constraints.fix(2 * node, ux);
            }
            if let Some(uy) = d.uy {
                constraints.fix(2 * node + 1, uy);
            }
        }
    }
    super::axisymmetry::fix_axis(&mesh, &mut constraints)?;
    let free_motions = free_motions_of_bodies(&model, &constraints);
    let mut warnings = Vec::new();
    let contact = contact_of_bodies(&model, &constraints, free_motions.clone(), scene.contact_solver, &mut warnings)?;
    // A body held by nothing because its pair is out of range: the warning says why.
    let out_of_range = |e: Error| match e {
        Error::Unconstrained(message) if !warnings.is_empty() => Error::Unconstrained(format!(
            "{message}; {}",
            warnings.iter().map(|w| w.message.as_str()).collect::<Vec<_>>().join("; ")
        )),
        other => other,
    };
    check_every_body_is_held(&model, &constraints, contact.as_ref()).map_err(out_of_range)?;
    if contact.is_none() {
        if let Some(free) = free_motions {
            return Err(out_of_range(Error::Unconstrained(free)));
        }
    }
    Ok(BodiesSetup { scene: flat, mesh, material: materials[0], cell_materials, constraints, contact, model, warnings })
}

/// The union-mesh nodes of every body's Dirichlet conditions, in the order of the flattened
/// scene's `dirichlet` (body by body, each body's in file order): each found on its own body's
/// mesh, so that a point condition takes its body's node, not another body's node at the same
/// place (two blocks touching at a corner).
pub(crate) fn dirichlet_nodes(model: &BodiesModel) -> Result<Vec<Vec<usize>>> {
    let mut out = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        let offset = model.layout.bodies[b].nodes.start;
        for d in &body.dirichlet {
            out.push(d.nodes(&model.body_meshes[b])?.into_iter().map(|k| k + offset).collect());
        }
    }
    Ok(out)
}

/// The scene's single-body fields for the union mesh: every body's tractions and Dirichlet
/// conditions with their parts renamed `body.part`, no rigid contact (it is in the contact
/// setup), the first body's material and mesh. Bodies with different body forces or elements
/// are refused (one body force and one element per run).
fn flatten(scene: &Scene, model: &BodiesModel) -> Result<Scene> {
    let first = &model.bodies[0];
    let mut tractions = Vec::new();
    let mut dirichlet = Vec::new();
    for body in &model.bodies {
        if body.body_force != first.body_force {
            return Err(Error::Scene {
                location: body.at.clone(),
                message: format!(
                    "body `{}` has the body force {:?}, body `{}` {:?}: bodies with different body forces are not \
                     solved yet",
                    body.name, body.body_force, first.name, first.body_force
                ),
                hint: "give every body the same body_force (or none)".into(),
            });
        }
        if body.element != first.element {
            return Err(Error::Scene {
                location: body.at.clone(),
                message: format!("body `{}` has another element than body `{}`", body.name, first.name),
                hint: "give every body the same [discretization] element".into(),
            });
        }
        for t in &body.tractions {
            tractions.push(TractionSpec { part: format!("{}.{}", body.name, t.part), ..t.clone() });
        }
        for d in &body.dirichlet {
            let target = match &d.target {
                DirichletTarget::Part(part) => DirichletTarget::Part(format!("{}.{part}", body.name)),
                DirichletTarget::Point(p) => DirichletTarget::Point(*p),
            };
            dirichlet.push(DirichletSpec { target, ..d.clone() });
        }
    }
    Ok(Scene {
        mesh: first.mesh.clone(),
        order: first.order,
        element: first.element,
        material: first.material,
        body_force: first.body_force,
        tractions,
        dirichlet,
        contact: None,
        ..scene.clone()
    })
}

/// Which rigid motions the Dirichlet conditions leave free, body by body (`None`: every body is
/// held by its supports).
fn free_motions_of_bodies(model: &BodiesModel, constraints: &Constraints) -> Option<String> {
    let mut free = Vec::new();
    for (b, body) in model.bodies.iter().enumerate() {
        let range = &model.layout.bodies[b];
        let body_mesh = &model.body_meshes[b];
        let mut own = Constraints::new(2 * body_mesh.num_nodes());
        for (dof, value) in constraints.fixed() {
            if range.dofs().contains(&dof) {
                own.fix(dof - range.dofs().start, value);
            }
        }
        if let Err(e) = own.check_rigid_motions(body_mesh) {
            free.push(format!("body `{}`: {e}", body.name));
        }
    }
    (!free.is_empty()).then(|| free.join("; "))
}

/// The contact points of every pair (mortar coupling, the slave side's nodes) and of every
/// body's rigid obstacle, merged; `None` when the scene has neither.
fn contact_of_bodies(
    model: &BodiesModel,
    constraints: &Constraints,
    free_motions: Option<String>,
    run_solver: Option<ContactSolverSpec>,
    warnings: &mut Vec<Warning>,
) -> Result<Option<ContactSetup>> {
    let mesh = &model.mesh;
    let prescribed = |node: usize| [constraints.value(2 * node), constraints.value(2 * node + 1)];
    let mut boundaries = Vec::new();
    let mut parts = Vec::new();
    let body_index = |name: &str| model.bodies.iter().position(|b| b.name == name).unwrap_or(0);
    for pair in &model.contact_pairs {
        let group_of = |side: &scene::PartRef| {
            model.part_group(side).ok_or_else(|| Error::Scene {
                location: side.at.clone(),
                message: format!("no boundary part `{side}` in the bodies' meshes"),
                hint: "name a part of the body's mesh".into(),
            })
        };
        let (slave_group, master_group) = (group_of(&pair.slave)?, group_of(&pair.master)?);
        let slave = MortarSide::from_mesh(mesh, slave_group)?;
        let master = MortarSide::from_mesh(mesh, master_group)?;
        // Slave nodes that do not face the master side, or face it from farther than a tenth
        // of the smaller side's extent, cannot touch it (small sliding); pairing far-away
        // points would only make the curved sides' normal lines cross each other.
        let extent = side_extent(mesh, slave_group).min(side_extent(mesh, master_group));
        let options = MortarOptions { uncovered: UncoveredNodes::LeaveOut, max_distance: PAIRING_DISTANCE * extent };
        let coupling = MortarCoupling::new(&slave, &master, &options).map_err(|e| in_pair(e, pair))?;
        if coupling.points() == 0 {
            // Facing, but farther apart than the pairing distance: no contact point, no force
            // (small sliding: they are taken as never touching), and a warning; the pointwise
            // check after the solve still measures the two sides (bodies_report.rs).
            let anywhere = MortarOptions { max_distance: f64::INFINITY, ..options };
            if let Some(nearest) = MortarCoupling::new(&slave, &master, &anywhere)
                .ok()
                .and_then(|c| c.gap.iter().copied().reduce(f64::min))
            {
                warnings.push(Warning {
                    kind: "contact_pair_out_of_range",
                    message: format!(
                        "contact pair `{}` / `{}` ({}:{}): the two parts face each other {nearest:.3e} apart at \
                         the nearest, farther than the pairing distance {:.3e} (a tenth of the smaller part's \
                         extent): it has no contact point and carries no force in this run (the pairing is made \
                         once, on the initial geometry); place the bodies closer if they are to touch",
                        pair.slave,
                        pair.master,
                        pair.at.file.display(),
                        pair.at.line,
                        options.max_distance
                    ),
                });
                continue;
            }
            return Err(Error::Scene {
                location: pair.at.clone(),
                message: format!(
                    "no node of `{}` faces `{}`: the two parts do not overlap along the slave normals",
                    pair.slave, pair.master
                ),
                hint: "check the two parts (and the bodies' placement)".into(),
            });
        }
        let edges: Vec<usize> = mesh.edges_in_group(slave_group).collect();
        boundaries.push(ContactBoundary::from_mortar(&coupling, edges, &prescribed)?);
        parts.push(ContactPart {
            name: format!("{} / {}", pair.slave, pair.master),
            slave_body: body_index(&pair.slave.body),
            slave_group,
            master: Some(MasterSide {
                body: body_index(&pair.master.body),
                group: master_group,
                pairing_distance: options.max_distance,
            }),
            friction: pair.friction,
            interface: pair.interface.clone(),
            at: pair.at.clone(),
        });
    }
    let mut solver_spec: Option<&ContactSpec> = None;
    for (b, body) in model.bodies.iter().enumerate() {
        let Some(spec) = &body.contact else { continue };
        let name = format!("{}.{}", body.name, spec.part);
        let group = mesh.require_group(&name, 1)?;
        let obstacle = obstacle_of(&spec.obstacle)?;
        boundaries.push(ContactBoundary::with_prescribed(mesh, group, &obstacle, spec.gap, &prescribed)?);
        parts.push(ContactPart {
            name,
            slave_body: b,
            slave_group: group,
            master: None,
            friction: spec.friction,
            interface: spec.interface.clone(),
            at: spec.at.clone(),
        });
        solver_spec.get_or_insert(spec);
    }
    if boundaries.is_empty() {
        return Ok(None);
    }
    // One friction law per run: Tresca and Coulomb parts cannot be mixed (frictionless ones can
    // join either).
    let coulomb = parts.iter().find(|p| matches!(p.friction, FrictionSpec::Coulomb { .. }));
    let tresca = parts.iter().find(|p| matches!(p.friction, FrictionSpec::Tresca { .. }));
    if let (Some(c), Some(t)) = (coulomb, tresca) {
        return Err(Error::Scene {
            location: t.at.clone(),
            message: format!(
                "contact `{}` has Tresca friction and `{}` Coulomb friction: one run takes one friction law",
                t.name, c.name
            ),
            hint: "give every contact the same law (frictionless contacts can be mixed with either)".into(),
        });
    }
    // Solver settings: a body's [contact] table's, else the default (the full-space Newton).
    let mut spec = match solver_spec {
        Some(s) => s.clone(),
        None => ContactSpec {
            part: String::new(),
            obstacle: ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] },
            gap: 0.0,
            friction: FrictionSpec::None,
            solver: ContactSolverSpec::FullSpaceNewton,
            tolerance: None,
            max_iterations: None,
            motion: None,
            name: None,
            interface: None,
            at: parts[0].at.clone(),
        },
    };
    if let Some(solver) = run_solver {
        spec.solver = solver;
    }
    if spec.solver == ContactSolverSpec::SnesVi {
        return Err(Error::Scene {
            location: spec.at.clone(),
            message: "solver \"snes_vi\" bounds one node's displacement per contact point, and the contact \
                      between two bodies couples several nodes per point"
                .into(),
            hint: "leave out `solver` (the full-space semi-smooth Newton) or choose a condensed solver".into(),
        });
    }
    spec.part = parts.iter().map(|p| p.name.as_str()).collect::<Vec<_>>().join(", ");
    spec.friction = coulomb.or(tresca).map_or(FrictionSpec::None, |p| p.friction);
    let (boundary, part_of) = ContactBoundary::merge(boundaries);
    let spring_dofs = spring_dofs(&boundary, &prescribed);
    Ok(Some(ContactSetup {
        spec,
        boundary,
        spring: None,
        free_motions,
        spring_dofs,
        parts: Some(ContactParts { parts, part_of }),
        interface: None,
    }))
}

/// The diagonal of the bounding box of a boundary part's nodes.
pub(crate) fn side_extent(mesh: &Mesh, group: usize) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for e in mesh.edges_in_group(group) {
        for &k in mesh.edge(e) {
            for c in 0..2 {
                lo[c] = lo[c].min(mesh.nodes[k][c]);
                hi[c] = hi[c].max(mesh.nodes[k][c]);
            }
        }
    }
    (hi[0] - lo[0]).hypot(hi[1] - lo[1])
}

/// An error of the mortar coupling, located at the pair's table.
fn in_pair(e: Error, pair: &scene::ContactPairSpec) -> Error {
    match e {
        Error::Formulation { message, hint } => Error::Scene {
            location: pair.at.clone(),
            message: format!("contact pair `{}` / `{}`: {message}", pair.slave, pair.master),
            hint,
        },
        Error::Usage(message) => Error::Scene {
            location: pair.at.clone(),
            message: format!("contact pair `{}` / `{}`: {message}", pair.slave, pair.master),
            hint: "check the two parts".into(),
        },
        other => other,
    }
}

/// Every connected piece of every body must be held by a Dirichlet condition or touch a
/// contact (a pair's side or a rigid obstacle's part).
fn check_every_body_is_held(
    model: &BodiesModel,
    constraints: &Constraints,
    contact: Option<&ContactSetup>,
) -> Result<()> {
    let mesh = &model.mesh;
    let contact_nodes = contact.map(|c| c.boundary.support_nodes()).unwrap_or_default();
    if let Some(loose) =
        super::first_loose_piece(mesh, &mesh::pieces::node_pieces(mesh), constraints, contact_nodes.into_iter())
    {
        let first = loose.first;
        let body = model.layout.node_body(first).map_or("?", |b| model.bodies[b].name.as_str());
        let x = mesh.nodes[first];
        return Err(Error::Unconstrained(format!(
            "body `{body}` (its piece with node {first} at ({:?}, {:?})) is held by nothing: no Dirichlet condition, \
             no contact pair and no rigid obstacle touches it, so it would float away; hold it with a \
             [[body.dirichlet]] condition or a [[contact_pair]]",
            x[0], x[1]
        )));
    }
    Ok(())
}
