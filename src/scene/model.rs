//! The model of a scene's bodies: each body's mesh, built by the single-body mesh builders and
//! placed, checked against the body's tables and the contact pairs, the bodies checked for
//! overlaps, and their disjoint union ([`crate::mesh::union`]).
//!
//! # Initial overlap
//!
//! Two bodies overlap by `d` when a point of the boundary of one (a node, or a piece of a
//! boundary edge between two crossings of the boundaries) lies inside the other at distance `d`
//! from its boundary ([`crate::mesh::union::deepest_overlap`], both ways). Every pair of bodies
//! is checked, with the tolerance
//!
//! ```text
//!   tol(a, b) = max over the [[contact_pair]] tables joining a and b of their max_initial_overlap,
//!               a pair without one counting DEFAULT_OVERLAP_FRACTION · min(h_a, h_b),
//!   tol(a, b) = DEFAULT_OVERLAP_FRACTION · min(h_a, h_b)           if no pair joins them,
//! ```
//!
//! `h_b` the smallest triangle edge of body `b`: bodies that touch (a node of one on the boundary
//! of the other, or curved boundaries whose chords touch) pass, bodies that overlap by a
//! visible fraction of a cell do not.
use super::bodies::{BodySpec, ContactPairSpec, PartRef};
use super::{boundary_group, MaterialSpec, Scene};
use crate::error::{Error, Location, Result};
use crate::mesh::union::{deepest_overlap, disjoint_union, BodyLayout, OverlapWitness};
use crate::mesh::Mesh;

/// The default accepted initial overlap of two bodies, as a fraction of the smaller of their
/// smallest cell edges (see the module documentation).
pub const DEFAULT_OVERLAP_FRACTION: f64 = 1e-6;

/// The bodies of a scene, meshed, placed, checked and united in one mesh.
#[derive(Debug, Clone)]
pub struct BodiesModel {
    /// [`Scene::bodies`].
    pub bodies: Vec<BodySpec>,
    /// The scene's `[[contact_pair]]` tables.
    pub contact_pairs: Vec<ContactPairSpec>,
    /// Each body's mesh in the common coordinates, with its own part names.
    pub body_meshes: Vec<Mesh>,
    /// The disjoint union of `body_meshes`: parts renamed `body.part`.
    pub mesh: Mesh,
    /// Node, cell, edge, dof and group ranges of each body in `mesh`, and the body of each cell.
    pub layout: BodyLayout,
}

impl BodiesModel {
    /// Mesh every body of `scene` with the builders of single-body scenes (structured, Gmsh with
    /// its cache, or a file), then [`BodiesModel::on_meshes`].
    pub fn build(scene: &Scene) -> Result<BodiesModel> {
        let meshes = scene
            .bodies()
            .iter()
            .map(|b| crate::mesh::build::build(&b.mesh, b.order).map(|(mesh, _, _)| mesh))
            .collect::<Result<Vec<_>>>()?;
        Self::on_meshes(scene, meshes)
    }

    /// The model on given meshes, one per body of [`Scene::bodies`] in order, each in the body's
    /// own coordinates: place them, check every body's parts and points against its mesh and its
    /// loads' magnitudes ([`Scene::check_magnitudes`]), the contact pairs' parts, and overlaps ([`Error::Scene`] at the table concerned), and unite.
    pub fn on_meshes(scene: &Scene, meshes: Vec<Mesh>) -> Result<BodiesModel> {
        let bodies = scene.bodies().into_owned();
        if meshes.len() != bodies.len() {
            return Err(Error::mesh("bodies", format!("{} meshes given for {} bodies", meshes.len(), bodies.len())));
        }
        let mut body_meshes = meshes;
        for (body, mesh) in bodies.iter().zip(&mut body_meshes) {
            if !body.placement.is_identity() {
                for p in &mut mesh.nodes {
                    *p = body.placement.apply(*p);
                }
            }
            body.check_against_mesh(mesh)?;
            one_body_scene(scene, body).check_magnitudes(mesh)?;
        }
        let index = |r: &PartRef| bodies.iter().position(|b| b.name == r.body);
        for pair in &scene.contact_pairs {
            for side in [&pair.slave, &pair.master] {
                let Some(b) = index(side) else {
                    return Err(Error::Scene {
                        location: side.at.clone(),
                        message: format!("no body named `{}`", side.body),
                        hint: "name one of the [[body]] tables".into(),
                    });
                };
                boundary_group(&body_meshes[b], &side.part, &side.at).map_err(|e| in_body(e, &side.body))?;
            }
        }
        if let Some(super::EvolutionSpec { monitor: Some(monitor), monitor_at, at, .. }) = &scene.evolution {
            // "body.part", the body checked by the reader.
            if let Some((body, part)) = monitor.split_once('.') {
                if let Some(b) = bodies.iter().position(|x| x.name == body) {
                    boundary_group(&body_meshes[b], part, monitor_at.as_ref().unwrap_or(at))
                        .map_err(|e| in_body(e, body))?;
                }
            }
        }
        check_overlaps(&bodies, &scene.contact_pairs, &body_meshes)?;
        let named: Vec<(&str, &Mesh)> = bodies.iter().map(|b| b.name.as_str()).zip(&body_meshes).collect();
        let (mesh, layout) = disjoint_union(&named)?;
        Ok(BodiesModel { bodies, contact_pairs: scene.contact_pairs.clone(), body_meshes, mesh, layout })
    }

    /// The material of a triangle of the union mesh.
    pub fn material_of_cell(&self, cell: usize) -> &MaterialSpec {
        &self.bodies[self.layout.cell_body[cell]].material
    }

    /// The boundary group of the union mesh holding a body's part (`body.part`).
    pub fn part_group(&self, part: &PartRef) -> Option<usize> {
        self.mesh.group_index(&part.to_string(), 1)
    }
}

/// `body` as a single-body scene (for the checks written for one: magnitudes).
fn one_body_scene(scene: &Scene, body: &BodySpec) -> Scene {
    Scene {
        mesh: body.mesh.clone(),
        order: body.order,
        element: body.element,
        material: body.material,
        body_force: body.body_force,
        body_force_name: body.body_force_name.clone(),
        tractions: body.tractions.clone(),
        dirichlet: body.dirichlet.clone(),
        contact: body.contact.clone(),
        bodies: Vec::new(),
        contact_pairs: Vec::new(),
        ..scene.clone()
    }
}

/// A missing-part error of a contact pair, saying whose mesh lacks the part.
fn in_body(e: Error, body: &str) -> Error {
    match e {
        Error::Scene { location, message, hint } => Error::Scene {
            location,
            message: message.replacen("the mesh", &format!("the mesh of body `{body}`"), 1),
            hint: hint.replacen("the mesh's", &format!("body `{body}`'s"), 1),
        },
        other => other,
    }
}

/// Refuse two bodies overlapping by more than their tolerance (module documentation).
fn check_overlaps(bodies: &[BodySpec], pairs: &[ContactPairSpec], meshes: &[Mesh]) -> Result<()> {
    let smallest_edge: Vec<f64> = meshes.iter().map(|m| m.size_range().0).collect();
    for a in 0..bodies.len() {
        for b in a + 1..bodies.len() {
            let default = DEFAULT_OVERLAP_FRACTION * smallest_edge[a].min(smallest_edge[b]);
            let joining: Vec<&ContactPairSpec> = pairs
                .iter()
                .filter(|p| {
                    let (s, m) = (p.slave.body.as_str(), p.master.body.as_str());
                    (s, m) == (&bodies[a].name, &bodies[b].name) || (m, s) == (&bodies[a].name, &bodies[b].name)
                })
                .collect();
            let tolerance = match joining.is_empty() {
                true => default,
                false => joining.iter().map(|p| p.max_initial_overlap.unwrap_or(default)).fold(0.0, f64::max),
            };
            let found = [(b, a), (a, b)]
                .into_iter()
                .filter_map(|(inner, outer)| {
                    deepest_overlap(&meshes[inner], &meshes[outer], tolerance).map(|o| (inner, outer, o))
                })
                .max_by(|x, y| x.2.depth.total_cmp(&y.2.depth));
            let Some((inner, outer, overlap)) = found else {
                continue;
            };
            let (location, stated): (Location, String) = match joining.first() {
                Some(p) => (p.at.clone(), "the accepted initial overlap of this [[contact_pair]]".into()),
                None => (bodies[b].at.clone(), "the default accepted overlap (no [[contact_pair]] joins them)".into()),
            };
            let [x, y] = overlap.position;
            let what = match overlap.witness {
                OverlapWitness::Node(_) => format!("the node of `{}` at [{x}, {y}]", bodies[inner].name),
                OverlapWitness::Edge { crossing: [cx, cy], .. } => format!(
                    "their boundaries cross at [{cx:.4e}, {cy:.4e}], and the boundary of `{}` at [{x:.4e}, {y:.4e}]",
                    bodies[inner].name
                ),
            };
            return Err(Error::Scene {
                location,
                message: format!(
                    "bodies `{}` and `{}` overlap: {what} is {:.3e} inside `{}`, more than {stated}, {tolerance:.3e}",
                    bodies[a].name, bodies[b].name, overlap.depth, bodies[outer].name
                ),
                hint: "bodies must start apart or touching: move one (its [[body]] `translate`, or its mesh's \
                       `origin`/`center`), or, for an intended interpenetration, give max_initial_overlap (m) in \
                       the [[contact_pair]] joining them"
                    .into(),
            });
        }
    }
    Ok(())
}
