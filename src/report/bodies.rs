//! The independent checks of a solution with several bodies, body by body and pair by pair
//! (`report.json` → `bodies`), made from the displacement field and the contact forces alone.
//!
//! ```text
//! body b:   F_b = Σ_{dofs of b} f            (loads)
//!           R_b = Σ_{fixed dofs of b} (K u − f)   (reactions of its supports)
//!           C_b = Σ_{dofs of b} (Bᵀ r)        (contact forces on its nodes, every pair and obstacle)
//!           equilibrium_residual = |F_b + R_b + C_b| / (|F_b| + |R_b| + Σ_parts |C_part,b| + E' max|u_b|·…)
//! pair p:   S_p = Σ over its points of the slave side's force (n rN + t rT)
//!           M_p = Σ over its points of the master side's force (the coupled nodes' entries of Bᵀ r)
//!           action_reaction_residual = |S_p + M_p| / |S_p|
//!           and the residuals of contact/residuals.rs on its points alone (same scales as the
//!           whole problem's check)
//! ```
//!
//! Per pair, too, every node the weak constraint does not see — the master nodes, and the slave
//! nodes that are not contact points of the pair — is measured pointwise against the other
//! side (`contact/mortar/interpenetration.rs`): its penetration beyond the reference overlap,
//! relative to the displacement scale, is `node_penetration` and an error above
//! `NODE_PENETRATION_CHECK` = 10⁻³. That bound is a discretisation allowance: master nodes
//! between slave nodes sit on chords of the deformed slave side, `O(h² |u''|)` off; measured
//! 2e-6 to 7e-5 on the Hertz and Cattaneo cases (cells down to a/5), 2e-16 on the patch test,
//! while a node left out of the pairing goes in by a good part of the displacements (4 % to
//! 23 % on two cylinders pressed 2 to 8 cm together).
//!
//! With the dual (biorthogonal) mortar basis `Σ_j M_ij = D_i` on every fully covered slave
//! node, so `S_p + M_p` vanishes to round-off; partly covered slave nodes (at the end of the
//! master side) transmit only the covered fraction, and the residual says how much.
use std::collections::HashSet;

use crate::contact::{self, PointStatus};
use crate::error::{Error, Result};

use crate::contact::mortar::{MortarSide, NodePenetration};
use crate::problem::{ContactPart, ContactSetup, ElasticityProblem, MasterSide, EQUILIBRIUM_CHECK};
use crate::scene::BodiesModel;

/// The largest pointwise penetration of a pair's nodes (relative to the displacement scale)
/// that the check accepts (module documentation).
const NODE_PENETRATION_CHECK: f64 = 1e-3;

/// The checks of every body and every contact part.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BodiesReport {
    /// Each body's equilibrium, in scene order.
    pub bodies: Vec<BodyReport>,
    /// Each contact part: the pairs, then the bodies' rigid obstacles.
    pub contacts: Vec<ContactPartReport>,
}

/// One body's equilibrium.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BodyReport {
    /// The body's name.
    pub name: String,
    /// The body's mesh nodes.
    pub nodes: usize,
    /// The body's triangles.
    pub elements: usize,
    /// Resultant of the loads on the body: body force and tractions (N per unit thickness; N for the full revolution of a body of revolution).
    pub applied_force: [f64; 2],
    /// Resultant of its Dirichlet reactions (N per unit thickness; N for the full revolution of a body of revolution).
    pub reaction: [f64; 2],
    /// Resultant of the contact forces on it (N per unit thickness; N for the full revolution of a body of revolution).
    pub contact_force: [f64; 2],
    /// Largest displacement magnitude over its nodes (m).
    pub max_displacement: f64,
    /// `|F + R + C|` relative to the forces involved (module documentation).
    pub equilibrium_residual: f64,
}

/// One contact part (a pair, or a body's rigid obstacle).
#[derive(Debug, Clone, serde::Serialize)]
pub struct ContactPartReport {
    /// `slave.part / master.part` for a pair, `body.part` for a rigid obstacle.
    pub name: String,
    /// The friction law (an object: `{"law": "coulomb", "mu": 0.3}`).
    pub friction: super::contact::FrictionReport,
    /// Contact points of the part.
    pub points: usize,
    /// Points without contact force.
    pub open: usize,
    /// Closed points (stick + slip under friction; `stick` and `slip` are 0 without).
    pub closed: usize,
    /// Points in contact, sticking (0 without friction).
    pub stick: usize,
    /// Points in contact, slipping.
    pub slip: usize,
    /// The force the part's contact exerts on its slave body (N/m; N in axisymmetry).
    pub slave_resultant: [f64; 2],
    /// On the master body (pairs; absent for a rigid obstacle).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub master_resultant: Option<[f64; 2]>,
    /// `|S + M| / |S|` (pairs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub action_reaction_residual: Option<f64>,
    /// The independent check's residuals on this part's points.
    pub residuals: super::contact::ContactResidualsReport,
    /// Pairs: every node of both sides measured against the other side (module documentation).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub node_penetration: Option<NodePenetrationReport>,
}

/// The pointwise interpenetration check of a pair (`contact/mortar/interpenetration.rs`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct NodePenetrationReport {
    /// Nodes of the two sides that face the other side and were measured.
    pub measured_nodes: usize,
    /// The largest penetration beyond the reference overlap, relative to the displacement scale.
    pub max_penetration: f64,
    /// The same in length units.
    pub max_penetration_length: f64,
    /// Where it is: the node (union numbering) ...
    pub node: usize,
    /// ... and the body it belongs to.
    pub body: String,
}

impl ElasticityProblem<'_> {
    /// The checks of a solution with several bodies (module documentation); an error when a
    /// body is not in equilibrium.
    /// `on_supports`: the contact shares on supported dofs (`add_forces_on_supports`), which the
    /// supports receive.
    pub(crate) fn check_bodies(
        &self,
        u: &[f64],
        f: &[f64],
        ku: &[f64],
        on_supports: &[f64],
    ) -> Result<Option<BodiesReport>> {
        let Some(model) = &self.bodies else { return Ok(None) };
        let contact = self.contact.as_ref().zip(self.contact_outcome.as_ref());
        // Bᵀ r split by contact part, slave and master sides apart.
        let parts = contact.and_then(|(c, _)| c.parts.as_ref());
        let num_parts = parts.map_or(0, |p| p.parts.len());
        let n = u.len();
        let mut on_dofs = vec![vec![0.0; n]; num_parts];
        let mut slave_force = vec![[0.0f64; 2]; num_parts];
        let mut master_force = vec![[0.0f64; 2]; num_parts];
        if let (Some((c, outcome)), Some(parts)) = (contact, parts) {
            let b = &c.boundary;
            for i in 0..b.points() {
                let p = parts.part_of[i];
                // The whole force of the point on each side (`point_force`); the shares that
                // land on supported dofs are taken out of those supports' reactions below.
                let whole = b.point_force(i, &outcome.force);
                for comp in 0..2 {
                    on_dofs[p][2 * b.nodes[i] + comp] += whole[comp];
                    slave_force[p][comp] += whole[comp];
                    for cn in b.coupled_to(i) {
                        on_dofs[p][2 * cn.node + comp] -= cn.transfer * whole[comp];
                        master_force[p][comp] -= cn.transfer * whole[comp];
                    }
                }
            }
        }
        let plane_modulus = self.cell_materials.materials().iter().map(|m| m.plane_modulus()).fold(0.0, f64::max);
        let mut bodies = Vec::new();
        for (b, body) in model.bodies.iter().enumerate() {
            let range = &model.layout.bodies[b];
            let dofs = range.dofs();
            let (mut applied, mut reaction, mut contact_force) = ([0.0f64; 2], [0.0f64; 2], [0.0f64; 2]);
            let mut contact_magnitude = 0.0;
            for dof in dofs.clone() {
                applied[dof % 2] += f[dof];
                if self.constraints.is_fixed(dof) {
                    reaction[dof % 2] += ku[dof] - f[dof] - on_supports[dof];
                }
            }
            for part in &on_dofs {
                let mut c = [0.0f64; 2];
                for dof in dofs.clone() {
                    c[dof % 2] += part[dof];
                }
                contact_force[0] += c[0];
                contact_force[1] += c[1];
                contact_magnitude += c[0].hypot(c[1]);
            }
            let max_displacement = u[dofs.clone()].chunks(2).map(|d| d[0].hypot(d[1])).fold(0.0, f64::max);
            let magnitude = (applied[0].hypot(applied[1]) + reaction[0].hypot(reaction[1]) + contact_magnitude)
                .max(plane_modulus * max_displacement * self.mesh.force_length());
            let imbalance = self.mesh.measure.imbalance([0, 1].map(|c| applied[c] + reaction[c] + contact_force[c]));
            let residual = if magnitude > 0.0 { imbalance / magnitude } else { 0.0 };
            if !(residual <= EQUILIBRIUM_CHECK) {
                return Err(Error::SolverDiverged {
                    solver: "the independent check of the answer".into(),
                    reason: format!(
                        "body `{}` is not in equilibrium: loads ({:.4e}, {:.4e}) + reactions ({:.4e}, {:.4e}) + contact \
                         forces ({:.4e}, {:.4e}) leave {imbalance:.3e} against forces of {magnitude:.3e}",
                        body.name,
                        applied[0],
                        applied[1],
                        reaction[0],
                        reaction[1],
                        contact_force[0],
                        contact_force[1]
                    ),
                    iterations: self.stats.as_ref().map_or(0, |s| s.iterations),
                    residual,
                    tried: self.stats.as_ref().map_or_else(String::new, |s| format!("{} + {}", s.ksp_type, s.pc_type)),
                });
            }
            bodies.push(BodyReport {
                name: body.name.clone(),
                nodes: range.nodes.len(),
                elements: range.cells.len(),
                applied_force: applied,
                reaction,
                contact_force,
                max_displacement,
                equilibrium_residual: residual,
            });
        }
        let mut contacts = Vec::new();
        if let (Some((c, outcome)), Some(parts)) = (contact, parts) {
            contacts = part_reports(
                model,
                c,
                &outcome.force,
                &outcome.status,
                u,
                &outcome.report,
                parts,
                &slave_force,
                &master_force,
            )?;
        }
        contacts.extend(out_of_range_pairs(model, parts, u, contacts.first().map(|c| c.residuals.displacement_scale))?);
        Ok(Some(BodiesReport { bodies, contacts }))
    }
}

/// The reports of the contact pairs that have no contact point (their parts face each other
/// farther apart than the pairing distance: `bodies.rs`): no force, and the pointwise check of
/// every node of both sides, which catches displacements that closed the distance anyway.
/// `displacement_scale`: the other parts' (the contact residuals'), else max |u|.
fn out_of_range_pairs(
    model: &BodiesModel,
    parts: Option<&crate::problem::ContactParts>,
    u: &[f64],
    displacement_scale: Option<f64>,
) -> Result<Vec<ContactPartReport>> {
    let mut out = Vec::new();
    let scale = displacement_scale.unwrap_or_else(|| u.chunks(2).map(|d| d[0].hypot(d[1])).fold(0.0, f64::max));
    for pair in &model.contact_pairs {
        let name = format!("{} / {}", pair.slave, pair.master);
        if parts.is_some_and(|p| p.parts.iter().any(|q| q.name == name)) {
            continue;
        }
        let (Some(slave_group), Some(master_group)) = (model.part_group(&pair.slave), model.part_group(&pair.master))
        else {
            continue;
        };
        let body = |name: &str| model.bodies.iter().position(|b| b.name == name).unwrap_or(0);
        let extent = crate::problem::bodies::side_extent(&model.mesh, slave_group)
            .min(crate::problem::bodies::side_extent(&model.mesh, master_group));
        let master = MasterSide {
            body: body(&pair.master.body),
            group: master_group,
            pairing_distance: crate::problem::bodies::PAIRING_DISTANCE * extent,
        };
        let part = ContactPart {
            name,
            slave_body: body(&pair.slave.body),
            slave_group,
            master: Some(master),
            friction: pair.friction,
            interface: pair.interface.clone(),
            at: pair.at.clone(),
        };
        let node_penetration = node_penetration(model, &HashSet::new(), &part, master, u, scale)?;
        out.push(ContactPartReport {
            name: part.name,
            friction: part.friction.into(),
            points: 0,
            open: 0,
            closed: 0,
            stick: 0,
            slip: 0,
            slave_resultant: [0.0; 2],
            master_resultant: Some([0.0; 2]),
            action_reaction_residual: Some(0.0),
            residuals: super::contact::ContactResidualsReport {
                max_penetration: 0.0,
                max_wrong_sign_pressure: 0.0,
                max_cone_violation: 0.0,
                normal_complementarity: 0.0,
                tangential_complementarity: 0.0,
                force_scale: 0.0,
                displacement_scale: scale,
            },
            node_penetration: Some(node_penetration),
        });
    }
    Ok(out)
}

#[allow(clippy::too_many_arguments)]
fn part_reports(
    model: &BodiesModel,
    c: &ContactSetup,
    force: &[f64],
    status: &[PointStatus],
    u: &[f64],
    whole: &crate::problem::ContactReport,
    parts: &crate::problem::ContactParts,
    slave_force: &[[f64; 2]],
    master_force: &[[f64; 2]],
) -> Result<Vec<ContactPartReport>> {
    let b = &c.boundary;
    let uc = b.gather(u);
    let law = c.friction_law();
    let scale =
        contact::ResidualScale { force: whole.residuals.force_scale, displacement: whole.residuals.displacement_scale };
    let mut out = Vec::new();
    for (p, part) in parts.parts.iter().enumerate() {
        let points: Vec<usize> = (0..b.points()).filter(|&i| parts.part_of[i] == p).collect();
        let pick = |v: &[f64]| points.iter().flat_map(|&i| [v[2 * i], v[2 * i + 1]]).collect::<Vec<f64>>();
        let (r, d) = (pick(force), pick(&uc));
        let gap: Vec<f64> = points.iter().map(|&i| b.gap[i]).collect();
        let threshold = |k: usize, rn: f64| law.threshold(points[k], rn);
        let residuals = contact::evaluate_residuals(&r, &d, &gap, &threshold, scale);
        let frictional = part.friction != crate::scene::FrictionSpec::None;
        let counts = super::contact::StateCounts::of(points.iter().map(|&i| (status[i], frictional)));
        let s = slave_force[p];
        let (master_resultant, action_reaction_residual) = match part.master {
            Some(_) => {
                let m = master_force[p];
                let size = s[0].hypot(s[1]);
                let residual = if size > 0.0 { (s[0] + m[0]).hypot(s[1] + m[1]) / size } else { 0.0 };
                (Some(m), Some(residual))
            }
            None => (None, None),
        };
        out.push(ContactPartReport {
            name: part.name.clone(),
            friction: part.friction.into(),
            points: points.len(),
            open: counts.open,
            closed: counts.closed,
            stick: counts.stick,
            slip: counts.slip,
            slave_resultant: s,
            master_resultant,
            action_reaction_residual,
            residuals: (&residuals).into(),
            // With an interface law the two sides overlap by the layer's compression (a zero
            // thickness model of the layer): the interface's own check replaces this one.
            node_penetration: match part.master.filter(|_| part.interface.is_none()) {
                Some(master) => {
                    let nodes: HashSet<usize> = points.iter().map(|&i| b.nodes[i]).collect();
                    Some(node_penetration(model, &nodes, part, master, u, scale.displacement)?)
                }
                None => None,
            },
        });
    }
    Ok(out)
}

/// The pointwise interpenetration of a pair's two sides (`contact/mortar/interpenetration.rs`):
/// every node of each side against the other side, within the pairing distance plus the
/// largest displacement of the two sides (a node farther than that cannot reach the other
/// side). An error above [`NODE_PENETRATION_CHECK`] of the displacement scale.
fn node_penetration(
    model: &BodiesModel,
    contact_points: &HashSet<usize>,
    part: &ContactPart,
    master: MasterSide,
    u: &[f64],
    displacement_scale: f64,
) -> Result<NodePenetrationReport> {
    let mesh = &model.mesh;
    let slave = MortarSide::from_mesh(mesh, part.slave_group)?;
    let master_side = MortarSide::from_mesh(mesh, master.group)?;
    let moved =
        slave.nodes().iter().chain(master_side.nodes()).map(|&k| u[2 * k].hypot(u[2 * k + 1])).fold(0.0, f64::max);
    let reach = master.pairing_distance + 2.0 * moved;
    // The contact points are checked by the weak constraint (the part's residuals); every other
    // node of the two sides is measured here.
    let is_point = |k: usize| contact_points.contains(&k);
    let measured = slave
        .penetration_into(&master_side, u, reach, |k| !is_point(k))?
        .max(master_side.penetration_into(&slave, u, reach, |_| true)?);
    let scale = displacement_scale.max(f64::MIN_POSITIVE);
    let (node, length) = measured.worst.map_or((0, 0.0), |w| (w.node, w.excess));
    let body = model.layout.bodies.iter().find(|r| r.nodes.contains(&node)).map_or(String::new(), |r| r.name.clone());
    let report = NodePenetrationReport {
        measured_nodes: measured.measured,
        max_penetration: length / scale,
        max_penetration_length: length,
        node,
        body,
    };
    if report.max_penetration > NODE_PENETRATION_CHECK {
        let w = measured.worst.expect("a penetration was measured");
        let unpaired = format!(
            "in the reference configuration they do not face each other, or lie farther apart than the pairing \
             distance {:.3e}: displacements this large are outside the small sliding the pairing assumes (it is \
             made once, in the reference configuration); reduce the load, or place the bodies so that they already \
             touch where they will",
            master.pairing_distance
        );
        let why = if slave.position(node).is_some() && !is_point(node) {
            format!("it is a slave node that is not a contact point: {unpaired}")
        } else if slave.position(node).is_some() {
            "it is a contact point: the weak (mortar) constraint holds there, but not pointwise: refine the contact sides"
                .to_string()
        } else if !w.facing.iter().any(|&k| is_point(k)) {
            format!("it is a master node facing slave nodes that are not contact points: {unpaired}")
        } else {
            master_node_cause(&slave, &master_side, node, &w, &is_point, &part.name)
        };
        return Err(Error::SolverDiverged {
            solver: "the independent check of the answer".into(),
            reason: format!(
                "node {node} of body `{}` on contact `{}` penetrates the other side by {length:.4e} \
                 ({:.1e} of the displacement scale; reference gap {:.4e}, gap after the solve {:.4e})",
                report.body, part.name, report.max_penetration, w.initial_gap, w.gap
            ),
            iterations: 0,
            residual: report.max_penetration,
            tried: why,
        });
    }
    Ok(report)
}

/// Why a master node facing the contact points of a pair goes into the slave side between two
/// slave nodes, where the weak constraint does not test it; `w` its measurement.
///
/// - The master side ends there, inside the slave side (one master edge at the node, or one of
///   the two slave nodes around it is not a contact point): the slave side reaches beyond the
///   master's end, its last contact point faces the master only on part of its support, the
///   next slave node not at all, and nothing holds the master's end corner between them.
///   Measured on a block whose bottom is the master side, on a foundation twice as fine
///   (the slave side, reaching beyond the block): 1.3e-2 to 7.2e-2 of the displacement scale
///   as the corner moves from 0.2 to 0.9 of a slave edge past the last contact point, falling
///   only as h^0.6 under refinement; the block as the slave side passes (2e-5 to 6e-5).
/// - Else the slave chords around the node are longer than the master's: the slave side is
///   coarser there (the weak constraint is tested on the slave's functions).
/// - Else the slave side is as fine: the node moved far towards the other side (beyond small
///   sliding) or the deformed slave side bends sharply there.
fn master_node_cause(
    slave: &MortarSide,
    master: &MortarSide,
    node: usize,
    w: &NodePenetration,
    is_point: &dyn Fn(usize) -> bool,
    pair: &str,
) -> String {
    let vertex_of = |e: &Vec<usize>| e[0] == node || e[1] == node;
    let master_edges = master.edges().iter().filter(|e| vertex_of(e)).count();
    let is_mid_node = master.edges().iter().any(|e| e.len() == 3 && e[2] == node);
    let ends_here = (master_edges == 1 && !is_mid_node) || !w.facing.iter().all(|&k| is_point(k));
    let (slave_name, master_name) = pair.split_once(" / ").unwrap_or((pair, ""));
    if ends_here {
        return format!(
            "it is a master node at the end of the master side `{master_name}`, which ends inside the slave side \
             `{slave_name}`: the slave nodes beyond it face no master edge and are not contact points, the last \
             contact point faces the master side on part of its support only, and the weak constraint does not \
             hold the master's end between them (a finer slave side does not help). Make the slave side the part \
             that lies within the other one (swap `slave` and `master` in the [[contact_pair]]), or trim the slave \
             part to the stretch the master part faces"
        );
    }
    let length = |side: &MortarSide, a: usize, b: usize| match (side.position(a), side.position(b)) {
        (Some(x), Some(y)) => (x[0] - y[0]).hypot(x[1] - y[1]),
        _ => 0.0,
    };
    let slave_chord = length(slave, w.facing[0], w.facing[1]);
    let master_chords: Vec<f64> = master
        .edges()
        .iter()
        .flat_map(|e| {
            let path: Vec<usize> = if e.len() == 3 { vec![e[0], e[2], e[1]] } else { e.clone() };
            path.windows(2).filter(|c| c.contains(&node)).map(|c| length(master, c[0], c[1])).collect::<Vec<_>>()
        })
        .collect();
    let master_chord = master_chords.iter().sum::<f64>() / master_chords.len().max(1) as f64;
    if slave_chord > 1.01 * master_chord {
        format!(
            "it is a master node pushing into the slave side between two slave nodes {slave_chord:.3e} apart, where \
             the master nodes are {master_chord:.3e} apart: the slave side is coarser than the master side there, \
             and the weak constraint is tested on the slave side's functions; make the slave side at least as fine \
             as the master side, or swap `slave` and `master`"
        )
    } else {
        format!(
            "it is a master node pushing into the slave side between two slave nodes {slave_chord:.3e} apart (the \
             master nodes are {master_chord:.3e} apart: the slave side is as fine), where the weak constraint does \
             not test it pointwise: the node moved {:.3e} towards a side {:.3e} away, beyond the small sliding the \
             linearised pairing assumes (reduce the load), or the deformed slave side bends sharply there (refine \
             both sides near it)",
            w.initial_gap - w.gap,
            w.initial_gap
        )
    }
}
