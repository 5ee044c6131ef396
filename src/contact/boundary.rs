//! # The discretized contact boundary of a mesh part against a rigid obstacle
//!
//! This module turns a boundary part `Γc` of a [`Mesh`] (a physical group of edges) and an
//! [`Obstacle`] into the data of the condensed problem of [`super`]: one contact point per mesh
//! node of `Γc`, its frame `(n_i, t_i)`, its initial gap `g0_i`, its weight `w_i`, and the
//! operator `B` that maps global displacements to contact displacements.
//!
//! ## Contact points: nodal collocation at every node of `Γc`
//!
//! Every node of the part's edges is a contact point, P2 mid nodes included. Node numbering of a
//! contact edge (mesh order `v0, v1, [mid]`, domain on the left):
//!
//! ```text
//!        body                                  body
//!   v0 -------- v1        P1                v0 --- mid --- v1        P2
//!   φ0 = 1 − s, φ1 = s                      φ0 = (1 − s)(1 − 2s), φ1 = s (2s − 1),
//!   ∫φ ds = L/2, L/2                        φmid = 4 s (1 − s)
//!                                           ∫φ ds = L/6, L/6, 2L/3   (straight edge)
//!   ////// obstacle //////                  ////////// obstacle //////////
//!
//!   two P2 edges of length L sharing v1:   v0 ---- m ---- v1 ---- m' ---- v2
//!   weights  w:                            L/6    2L/3   L/3     2L/3    L/6     (1 : 4 : 2 : 4 : 1)
//! ```
//!
//! For node `i` at position `x_i`, the obstacle's closest point gives the normal `ν` of the
//! obstacle (towards the body) and the signed distance `d_i` ([`Obstacle::project`]). The frame
//! and gap of the point are
//!
//! ```text
//!   n_i = −ν            the body's contact direction (towards the obstacle; on a flat
//!                       contact it is the body's outward normal),
//!   t_i = (−n_y, n_x)   n_i rotated by +90°: (n_i, t_i) is right-handed (n × t = +1), and on
//!                       a flat contact t_i runs along the boundary edges (domain on the
//!                       left), i.e. counter-clockwise around the body,
//!   g0_i = d_i + extra_gap,
//! ```
//!
//! and the linearized non-penetration `(x_i + u_i − p_i)·ν ≥ 0` is `uN_i = n_i·u_i ≤ g0_i`, the
//! convention of [`super`]. The contact unknowns are interleaved `(N_0, T_0, N_1, T_1, …)`;
//! `B` has one row per unknown with two nonzeros, `B_{2i} = n_iᵀ` and `B_{2i+1} = t_iᵀ` on the
//! two dofs `2k, 2k+1` of node `k` ([`ContactBoundary::b_row`]); [`ContactBoundary::gather`] is
//! `B u` and [`ContactBoundary::scatter_add`] is `f += Bᵀ r`. The contact unknowns `rN_i, rT_i`
//! are **nodal forces** (force units), the Lagrange multipliers of the nodal constraints.
//!
//! ## Contact nodes with prescribed displacement components
//!
//! A node whose `ux` and `uy` are both prescribed cannot move: it is left out of the contact
//! points, and its penetration `n·u − g0` is checked after the solve like any other
//! ([`ContactBoundary::left_out`]). A node with ONE prescribed component `u_k = u0` (a
//! symmetry plane, a roller, a pin on the contact part) can still move along the other axis
//! `d = e_(1−k)`: it stays a contact point whose normal condition acts on the free component,
//!
//! ```text
//!   n·u = n_k u0 + (n·d) u_d ≤ g0    ⇔    B_N = (n·d) dᵀ,   g0' = g0 − n_k u0,
//! ```
//!
//! so `B_N` touches only the free dof, and its friction threshold is zero: the support, not
//! friction, carries the tangential force there (its multiplier `rT` vanishes; `B_T` keeps the
//! unit tangent so that every solver sees a regular problem). When the free axis is tangent to
//! the obstacle (`|n·d| < 1e-6`, e.g. `uy` prescribed on a flat contact) the support carries the
//! normal force too and the node is left out, with its penetration checked.
//!
//! ## Why this works with quadratic elements (no pressure checkerboard)
//!
//! With nodal collocation the multiplier `rN_i` is the nodal force that the contact pressure
//! exerts on node `i`. The variationally consistent meaning of a nodal force is the work of a
//! pressure field `p_h = Σ_j p_j φ_j` against the shape function of the node:
//!
//! ```text
//!   −rN_i = ∫_Γc p_h φ_i ds = Σ_j M_ij p_j,        M_ij = ∫_Γc φ_i φ_j ds  (boundary mass matrix),
//! ```
//!
//! because this is how a traction enters the finite element load vector. Two recoveries follow:
//!
//! - [`ContactBoundary::recovered_pressure`] solves `M p = −rN`: exact whenever the pressure is
//!   in the trace space (any quadratic pressure for P2, any linear one for P1).
//! - [`ContactBoundary::tractions`] divides by the consistent weights `w_i = ∫_Γc φ_i ds`
//!   (`= Σ_j M_ij`, the row sums of `M`): `p_i = −rN_i / w_i`. Exact for a uniform pressure,
//!   since `Σ_j M_ij p = p w_i`, and a local (no solve) approximation otherwise.
//!
//! In 2D every consistent weight is positive: `L/2, L/2` on a P1 edge and the Simpson weights
//! `L/6, L/6, 2L/3` on a straight P2 edge (curved edges: computed with the true length element,
//! and checked to be positive). This is the difference with quadratic faces in 3D, where the
//! vertex integrals of the 6-node triangle vanish (`∫λ(2λ − 1) = 0`), so that nodal contact
//! with quadratic faces needs modified bases there (Popp, Wohlmuth, Gee & Wall, "Dual quadratic mortar finite
//! element methods for 3D finite deformation contact", SIAM J. Sci. Comput. 34 (2012)
//! B421–B446).
//!
//! The checkerboard that users of other codes see (a known complaint about quadratic elements with nodal contact) comes from dividing the
//! consistent nodal forces by the wrong weights, the "tributary lengths" of a P1 chain through
//! all P2 nodes (`L/4, L/4, L/2` per edge). Under a uniform pressure `p` on edges of length `L`:
//!
//! ```text
//!                         force −rN              tributary weight     "pressure"
//!   interior vertex:  pL/6 + pL/6 = pL/3         L/4 + L/4 = L/2      2p/3
//!   mid node:         2pL/3                      L/2                  4p/3
//! ```
//!
//! so the nodal pressures alternate `2p/3, 4p/3, 2p/3, …` along the contact zone although the
//! force resultant is right: a spurious vertex/mid-node oscillation created by post-processing
//! alone. With the consistent weights both rows give exactly `p`.
//!
//! References: N. Kikuchi, J. T. Oden, *Contact Problems in Elasticity*, SIAM 1988 (nodal
//! discretization of the Signorini conditions); P. Wriggers, *Computational Contact Mechanics*,
//! 2nd ed., Springer 2006 (chapters on contact kinematics and on the discretization of the
//! contact interface: gap from the closest-point projection, node-to-surface contact);
//! S. Hüeber, B. Wohlmuth, "A primal–dual active set strategy for non-linear multibody contact
//! problems", Comput. Methods Appl. Mech. Engrg. 194 (2005) 3147–3166 (weighted nodal contact
//! conditions). The boundary mass matrix and the weights are
//! integrated with a 6-point Gauss–Legendre rule per edge (exact for straight edges; the
//! isoparametric length element of curved P2 edges is integrated to high accuracy).
use super::obstacle::Obstacle;
use crate::error::{Error, Result};
use crate::fem::lagrange::map_edge_point;
use crate::fem::quadrature::gauss_legendre;
use crate::mesh::{Measure, Mesh};

/// Gauss–Legendre points per edge for weights and the boundary mass matrix (exact to degree 11).
const EDGE_QUADRATURE_POINTS: usize = 6;

/// The contact points of a boundary part against an obstacle. See the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactBoundary {
    /// Mesh nodes of the contact points (all nodes of the part's edges, P2 mid nodes included,
    /// minus the excluded ones), sorted increasingly. Contact point `i` is node `nodes[i]`.
    pub nodes: Vec<usize>,
    /// `n_i = −ν`: the body's contact direction (towards the obstacle), unit.
    pub normal: Vec<[f64; 2]>,
    /// `t_i = (−n_y, n_x)`: `n_i` rotated by +90°, so `(n_i, t_i)` is right-handed.
    pub tangent: Vec<[f64; 2]>,
    /// `g0_i` = signed distance to the obstacle + extra gap (`≥ 0` when not overlapping).
    pub gap: Vec<f64>,
    /// `w_i = ∫_Γc φ_i ds` over the part's edges (consistent weights, `> 0`; in axisymmetry
    /// `∫ φ_i 2π r ds`, which vanishes at a P2 vertex on the axis, see [`AxisPressure`]).
    pub weight: Vec<f64>,
    /// The mesh boundary edges of the part, increasing.
    pub edges: Vec<usize>,
    /// The prescribed component `(k, u0)` of each contact point, if one is (see the module
    /// documentation: its normal acts on the free component, its friction threshold is zero).
    pub prescribed: Vec<Option<(usize, f64)>>,
    /// Nodes of the part that are not contact points (both components prescribed, or the free
    /// one tangent to the obstacle), with the contact direction and gap to check them with.
    pub left_out: Vec<LeftOutNode>,
    /// For contact between two bodies: the nodes of the other (master) side of each point and
    /// their entries in the point's two rows of `B` (empty against a rigid obstacle, else one
    /// list per point). See [`ContactBoundary::from_mortar`].
    pub coupled: Vec<Vec<CoupledNode>>,
    /// The unit contact frame `(n_i, t_i)` of each point before prescribed components were taken
    /// out of its rows: the direction of the force between the two sides (equal to
    /// `(normal, tangent)` where nothing is prescribed).
    pub frame: Vec<[[f64; 2]; 2]>,
    /// In axisymmetry: the contact nodes on the axis whose weight vanishes (P2 vertices), with
    /// the extrapolation that gives their pressure (empty otherwise).
    pub axis_pressure: Vec<AxisPressure>,
}

/// A contact node on the axis whose consistent weight `∫ φ_i 2π r ds` vanishes (the vertex of a
/// straight P2 edge on the axis: `∫₀¹ (1 − s)(1 − 2s) s ds = 0`; on a curved edge it is a small
/// number of either sign, of the order of the edge's sag), so that `−rN_i / w_i` says nothing
/// about its pressure: every P2 vertex on the axis. Its pressure is extrapolated from the two other nodes of its
/// edge with the even profile `p(r) = A + B r²` that symmetry imposes about the axis:
/// `p_i = c_1 p_1 + c_2 p_2`, `c_1 = r_2² / (r_2² − r_1²)`, `c_2 = −r_1² / (r_2² − r_1²)` (4/3 and
/// −1/3 for the mid node and far vertex of a straight edge); its friction traction is 0 (the
/// radial shear vanishes on the axis by symmetry).
#[derive(Debug, Clone, PartialEq)]
pub struct AxisPressure {
    /// The node on the axis.
    pub node: usize,
    /// The two nodes it is extrapolated from, with their coefficients.
    pub from: [(usize, f64); 2],
}

impl AxisPressure {
    /// The extrapolation to `node` (on the axis) from the two other nodes of its edge, given as
    /// `(node, r)`; `None` unless there are two.
    pub(crate) fn even(node: usize, mut others: Vec<(usize, f64)>) -> Option<Self> {
        others.sort_by(|a, b| a.1.total_cmp(&b.1));
        match others[..] {
            [(near, r1), (far, r2)] => {
                let (r1, r2) = (r1 * r1, r2 * r2);
                Some(AxisPressure { node, from: [(near, r2 / (r2 - r1)), (far, -r1 / (r2 - r1))] })
            }
            _ => None,
        }
    }
}

/// A node of the other body in the rows of a contact point between two bodies: `B_N` has
/// `normal` and `B_T` has `tangent` on its two dofs (`−(M_ij/D_i) n_i` and `−(M_ij/D_i) t_i`
/// for the mortar coupling, without the node's prescribed components), and it receives the
/// share `transfer` (`M_ij/D_i`) of the point's force, reversed.
#[derive(Debug, Clone, PartialEq)]
pub struct CoupledNode {
    /// The node of the other body.
    pub node: usize,
    /// Its coefficients in the point's `B_N` row (x and y).
    pub normal: [f64; 2],
    /// Its coefficients in the point's `B_T` row (x and y).
    pub tangent: [f64; 2],
    /// Its share `M_ij/D_i` of the point's force, reversed.
    pub transfer: f64,
}

/// A node of the contact part left out of the contact points, to be checked for penetration.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftOutNode {
    /// The node.
    pub node: usize,
    /// Its unit outward normal.
    pub normal: [f64; 2],
    /// Its initial gap `g0` (m).
    pub gap: f64,
}

/// `(shape values, quadrature weight × ds)` at the Gauss points of an edge (parameter `s ∈ [0, 1]`).
fn edge_quadrature(coords: &[[f64; 2]], measure: Measure) -> impl Iterator<Item = ([f64; 3], f64)> + '_ {
    let rule = gauss_legendre(EDGE_QUADRATURE_POINTS);
    (0..rule.points.len()).map(move |q| {
        let p = map_edge_point(coords, rule.points[q]);
        (p.values, rule.weights[q] * p.length_element * measure.factor(p.x))
    })
}

/// The contact points `i` (nodes `nodes[i]`) for which `on_axis(i)` holds, with the
/// extrapolation of their pressure from the other nodes of their edge ([`AxisPressure`]).
fn axis_pressures(mesh: &Mesh, edges: &[usize], nodes: &[usize], on_axis: &dyn Fn(usize) -> bool) -> Vec<AxisPressure> {
    (0..nodes.len())
        .filter(|&i| on_axis(i))
        .filter_map(|i| {
            // The edge of the part through the node (one, since the part meets the axis there).
            let node = nodes[i];
            let edge = edges.iter().map(|&e| mesh.edge(e)).find(|edge| edge.contains(&node))?;
            AxisPressure::even(node, edge.iter().filter(|&&k| k != node).map(|&k| (k, mesh.nodes[k][0])).collect())
        })
        .collect()
}

/// The consistent weights `w_k = ∫ φ_k ds` of the nodes of boundary edges `edges` (module
/// documentation), as `(node, w_k)` by increasing node.
pub fn edge_weights(mesh: &Mesh, edges: &[usize]) -> Vec<(usize, f64)> {
    let mut weights: std::collections::BTreeMap<usize, f64> = std::collections::BTreeMap::new();
    let mut coords = Vec::with_capacity(3);
    for &e in edges {
        let edge = mesh.edge(e);
        coords.clear();
        coords.extend(edge.iter().map(|&k| mesh.nodes[k]));
        for (values, wds) in edge_quadrature(&coords, mesh.measure) {
            for (a, &k) in edge.iter().enumerate() {
                *weights.entry(k).or_insert(0.0) += wds * values[a];
            }
        }
    }
    weights.into_iter().collect()
}

impl ContactBoundary {
    /// The contact points of boundary group `group` (an index into `mesh.groups`, dimension 1)
    /// against `obstacle`, with `extra_gap` added to every gap (positive: clearance, negative:
    /// interference). Nodes for which `excluded_nodes(node)` is true are not contact points
    /// (e.g. nodes whose displacement a Dirichlet condition fixes: the driver decides).
    ///
    /// Errors: [`Error::Usage`] for a group index out of range or naming a region, an invalid
    /// obstacle, a non-finite `extra_gap`, or a part whose nodes are all excluded;
    /// [`Error::Mesh`] for a part without edges or a contact node whose consistent weight is
    /// not positive (a badly placed P2 mid node on a curved edge). Messages name the part.
    pub fn new(
        mesh: &Mesh,
        group: usize,
        obstacle: &Obstacle,
        extra_gap: f64,
        excluded_nodes: &dyn Fn(usize) -> bool,
    ) -> Result<Self> {
        Self::with_prescribed(mesh, group, obstacle, extra_gap, &|k| {
            if excluded_nodes(k) {
                [Some(0.0), Some(0.0)]
            } else {
                [None, None]
            }
        })
    }

    /// As [`ContactBoundary::new`], with the prescribed displacement components of each node
    /// (`prescribed(node)[k]` for component k): see the module documentation.
    pub fn with_prescribed(
        mesh: &Mesh,
        group: usize,
        obstacle: &Obstacle,
        extra_gap: f64,
        prescribed: &dyn Fn(usize) -> [Option<f64>; 2],
    ) -> Result<Self> {
        let Some(part) = mesh.groups.get(group) else {
            return Err(Error::Usage(format!(
                "contact boundary: group index {group} is out of range (the mesh has {} physical groups)",
                mesh.groups.len()
            )));
        };
        let name = &part.name;
        if part.dim != 1 {
            return Err(Error::Usage(format!(
                "contact part '{name}': it is a region (dimension {}), a contact part must be a boundary (curve) group",
                part.dim
            )));
        }
        obstacle.validate().map_err(|e| match e {
            Error::Usage(message) => Error::Usage(format!("contact part '{name}': {message}")),
            other => other,
        })?;
        if !extra_gap.is_finite() {
            return Err(Error::Usage(format!(
                "contact part '{name}': the extra gap is {extra_gap}, it must be finite"
            )));
        }
        let edges: Vec<usize> = mesh.edges_in_group(group).collect();
        if edges.is_empty() {
            return Err(Error::mesh(
                format!("physical group '{name}'"),
                "has no boundary edges, so it cannot be a contact part",
            ));
        }
        let mut all_nodes: Vec<usize> = edges.iter().flat_map(|&e| mesh.edge(e).iter().copied()).collect();
        all_nodes.sort_unstable();
        all_nodes.dedup();
        // Every node must start on the obstacle's side, up to a declared overlap (a negative
        // extra gap): a body inside the obstacle is a geometry mistake, not a contact state.
        let tolerance = 1e-9 * mesh.diagonal();
        let allowed = extra_gap.min(0.0) - tolerance;
        if let Some((k, d)) = all_nodes
            .iter()
            .map(|&k| (k, obstacle.project(mesh.nodes[k]).signed_distance))
            .filter(|&(_, d)| d < allowed)
            .min_by(|a, b| a.1.total_cmp(&b.1))
        {
            let x = mesh.nodes[k];
            return Err(Error::Formulation {
                message: format!(
                    "contact part '{name}': node {k} at ({:?}, {:?}) starts {:.4e} inside the obstacle (the deepest \
                     node of the part{}): the body must start on the obstacle's side",
                    x[0],
                    x[1],
                    -d,
                    if extra_gap < 0.0 {
                        format!(", beyond the declared overlap {:.4e}", -extra_gap)
                    } else {
                        String::new()
                    }
                ),
                hint: "move the obstacle or the body, check the side the obstacle's normal (or the polyline's \
                       direction) puts the body on, or declare an initial overlap with a negative `gap` in [contact]"
                    .into(),
            });
        }
        // Classify every node of the part (module documentation).
        let mut nodes = Vec::with_capacity(all_nodes.len());
        let mut fixed = Vec::with_capacity(all_nodes.len());
        let mut left_out = Vec::new();
        for &k in &all_nodes {
            let projection = obstacle.project(mesh.nodes[k]);
            let n = [-projection.normal[0], -projection.normal[1]];
            let g = projection.signed_distance + extra_gap;
            match prescribed(k) {
                [None, None] => {
                    nodes.push(k);
                    fixed.push(None);
                }
                [Some(_), Some(_)] => left_out.push(LeftOutNode { node: k, normal: n, gap: g }),
                [a, b] => {
                    let (comp, u0) = if let Some(v) = a { (0, v) } else { (1, b.unwrap_or(0.0)) };
                    if n[1 - comp].abs() < 1e-6 {
                        left_out.push(LeftOutNode { node: k, normal: n, gap: g });
                    } else {
                        nodes.push(k);
                        fixed.push(Some((comp, u0)));
                    }
                }
            }
        }
        if nodes.is_empty() {
            return Err(Error::Usage(format!(
                "contact part '{name}': all its {} nodes are excluded (their displacement is prescribed), \
                 so no contact point remains; remove the Dirichlet condition from the contact part or \
                 choose another contact part",
                all_nodes.len()
            )));
        }

        let mut weight = vec![0.0; nodes.len()];
        let mut coords = Vec::with_capacity(3);
        for &e in &edges {
            let edge = mesh.edge(e);
            coords.clear();
            coords.extend(edge.iter().map(|&k| mesh.nodes[k]));
            for (values, wds) in edge_quadrature(&coords, mesh.measure) {
                for (a, &k) in edge.iter().enumerate() {
                    if let Ok(i) = nodes.binary_search(&k) {
                        weight[i] += wds * values[a];
                    }
                }
            }
        }
        // In axisymmetry a P2 vertex on the axis has a vanishing weight (see `AxisPressure`): 0
        // on a straight edge, and a small number of either sign on a curved one (the Hertz
        // sphere's pole: dividing by it gave 3.4e12 Pa for 7.2e9), so it is told by what it is,
        // not by its weight.
        let p2_vertices: std::collections::BTreeSet<usize> = if mesh.order == crate::mesh::Order::P2 {
            edges.iter().flat_map(|&e| mesh.edge(e)[..2].to_vec()).collect()
        } else {
            Default::default()
        };
        let on_axis = |i: usize| {
            mesh.measure.is_axisymmetric() && mesh.nodes[nodes[i]][0] == 0.0 && p2_vertices.contains(&nodes[i])
        };
        let axis_pressure = axis_pressures(mesh, &edges, &nodes, &on_axis);
        if let Some(i) = weight.iter().enumerate().position(|(i, &w)| !(on_axis(i) || w > 0.0 && w.is_finite())) {
            return Err(Error::mesh(
                format!("node {} of contact part '{name}'", nodes[i]),
                format!(
                    "its consistent contact weight ∫φ ds is {:e}, not positive: a P2 mid node of an edge \
                     through it is too far from the middle of the edge; remesh the part",
                    weight[i]
                ),
            ));
        }

        let mut normal = Vec::with_capacity(nodes.len());
        let mut tangent = Vec::with_capacity(nodes.len());
        let mut gap = Vec::with_capacity(nodes.len());
        let mut frame = Vec::with_capacity(nodes.len());
        for (&k, f) in nodes.iter().zip(&fixed) {
            let projection = obstacle.project(mesh.nodes[k]);
            let n = [-projection.normal[0], -projection.normal[1]];
            tangent.push([-n[1], n[0]]);
            frame.push([n, [-n[1], n[0]]]);
            let g = projection.signed_distance + extra_gap;
            match *f {
                None => {
                    normal.push(n);
                    gap.push(g);
                }
                Some((comp, u0)) => {
                    // B_N = (n·d) dᵀ on the free axis d, the prescribed part moved into the gap.
                    let mut restricted = [0.0; 2];
                    restricted[1 - comp] = n[1 - comp];
                    normal.push(restricted);
                    gap.push(g - n[comp] * u0);
                }
            }
        }
        Ok(ContactBoundary {
            nodes,
            normal,
            tangent,
            gap,
            weight,
            edges,
            prescribed: fixed,
            left_out,
            coupled: Vec::new(),
            frame,
            axis_pressure,
        })
    }

    /// The largest penetration `n·u − g0` of the left-out nodes (0 when none penetrates), and
    /// the node where it is.
    pub fn left_out_penetration(&self, u: &[f64]) -> (f64, Option<usize>) {
        let mut worst = (0.0f64, None);
        for l in &self.left_out {
            let p = l.normal[0] * u[2 * l.node] + l.normal[1] * u[2 * l.node + 1] - l.gap;
            if p > worst.0 {
                worst = (p, Some(l.node));
            }
        }
        worst
    }

    /// Number of contact points `m` (the condensed problem has `2m` unknowns).
    pub fn points(&self) -> usize {
        self.nodes.len()
    }

    /// `B u`: the contact displacements `(uN_i, uT_i)` of a global displacement vector
    /// (`dof = 2·node + comp`), interleaved `(N_0, T_0, N_1, T_1, …)`.
    ///
    /// # Panics
    /// If `u` is shorter than `2·(largest contact node + 1)`.
    pub fn gather(&self, u: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(2 * self.points());
        for (i, ((&k, n), t)) in self.nodes.iter().zip(&self.normal).zip(&self.tangent).enumerate() {
            let (ux, uy) = (u[2 * k], u[2 * k + 1]);
            let (mut un, mut ut) = (n[0] * ux + n[1] * uy, t[0] * ux + t[1] * uy);
            for c in self.coupled_to(i) {
                let (vx, vy) = (u[2 * c.node], u[2 * c.node + 1]);
                un += c.normal[0] * vx + c.normal[1] * vy;
                ut += c.tangent[0] * vx + c.tangent[1] * vy;
            }
            out.push(un);
            out.push(ut);
        }
        out
    }

    /// `f += Bᵀ r`: adds the contact forces `r = (rN_0, rT_0, …)` to a global force vector,
    /// `f[2k + c] += n_c rN + t_c rT` (and the coupled nodes' entries, between two bodies).
    ///
    /// # Panics
    /// If `r` does not hold `2m` values or `f` is too short for the contact nodes.
    pub fn scatter_add(&self, r: &[f64], f: &mut [f64]) {
        assert_eq!(r.len(), 2 * self.points(), "contact boundary: r must hold 2 values per contact point");
        for (i, ((&k, n), t)) in self.nodes.iter().zip(&self.normal).zip(&self.tangent).enumerate() {
            let (rn, rt) = (r[2 * i], r[2 * i + 1]);
            f[2 * k] += n[0] * rn + t[0] * rt;
            f[2 * k + 1] += n[1] * rn + t[1] * rt;
            for c in self.coupled_to(i) {
                f[2 * c.node] += c.normal[0] * rn + c.tangent[0] * rt;
                f[2 * c.node + 1] += c.normal[1] * rn + c.tangent[1] * rt;
            }
        }
    }

    /// The force of contact point `i` (forces `r`) on its node before any support takes a
    /// share: along the unreduced [`ContactBoundary::frame`] (the obstacle's or the master's
    /// normal and tangent), so that between two bodies each master node `j` receives
    /// `−transfer_j` times it ([`CoupledNode::transfer`]).
    ///
    /// At a point with a prescribed component `k` the node's force splits in the obstacle's
    /// frame: the contact carries `rN n + rT t` (along the whole normal: `rN` is what the free
    /// axis `d` sees, `(n·d) rN`, divided by `n·d`), the support the rest of the node's force
    /// along `e_k`. On the rotated patch test that support's reaction is zero, as it must be.
    pub fn point_force(&self, i: usize, r: &[f64]) -> [f64; 2] {
        let (rn, rt) = (r[2 * i], r[2 * i + 1]);
        let [n, t] = self.frame[i];
        [n[0] * rn + t[0] * rt, n[1] * rn + t[1] * rt]
    }

    /// The forces that prescribed components took out of `B` (`f += B̄ᵀ r − Bᵀ r`, `B̄` the rows
    /// of [`ContactBoundary::point_force`] and its master shares): nonzero only on prescribed
    /// dofs of contact points (against a rigid obstacle or between two bodies), where the
    /// support, not the body, receives them.
    pub fn add_forces_on_supports(&self, r: &[f64], f: &mut [f64]) {
        for i in 0..self.points() {
            if self.coupled_to(i).is_empty() && self.prescribed[i].is_none() {
                continue;
            }
            let (rn, rt) = (r[2 * i], r[2 * i + 1]);
            let whole = self.point_force(i, r);
            for comp in 0..2 {
                f[2 * self.nodes[i] + comp] += whole[comp] - (self.normal[i][comp] * rn + self.tangent[i][comp] * rt);
                for c in self.coupled_to(i) {
                    f[2 * c.node + comp] += -c.transfer * whole[comp] - (c.normal[comp] * rn + c.tangent[comp] * rt);
                }
            }
        }
    }

    /// The sparse row `j` of `B` (contact unknown `j`: `N_i` for `j = 2i`, `T_i` for
    /// `j = 2i + 1`): `(dof, coefficient)` pairs by increasing dof; against a rigid obstacle the
    /// two dofs of the point's node, x then y.
    ///
    /// # Panics
    /// If `j ≥ 2m`.
    pub fn b_row(&self, j: usize) -> Vec<(usize, f64)> {
        let i = j / 2;
        let k = self.nodes[i];
        let normal_row = j.is_multiple_of(2);
        let v = if normal_row { self.normal[i] } else { self.tangent[i] };
        let mut row = vec![(2 * k, v[0]), (2 * k + 1, v[1])];
        for c in self.coupled_to(i) {
            let w = if normal_row { c.normal } else { c.tangent };
            row.push((2 * c.node, w[0]));
            row.push((2 * c.node + 1, w[1]));
        }
        row.sort_by_key(|&(dof, _)| dof);
        row
    }

    /// The other body's nodes in the rows of point `i` (none against a rigid obstacle).
    pub fn coupled_to(&self, i: usize) -> &[CoupledNode] {
        self.coupled.get(i).map_or(&[], |c| c.as_slice())
    }

    /// Whether the points are coupled to another body (a contact pair) rather than to a rigid
    /// obstacle, for some point.
    pub fn is_coupled(&self) -> bool {
        self.coupled.iter().any(|c| !c.is_empty())
    }

    /// Every node whose dofs some row of `B` touches: the contact nodes and the coupled nodes,
    /// increasing, each once.
    pub fn support_nodes(&self) -> Vec<usize> {
        let mut nodes: Vec<usize> =
            self.nodes.iter().copied().chain(self.coupled.iter().flatten().map(|c| c.node)).collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }

    /// Nodal pressures `p_i = −rN_i / w_i` and friction tractions `rT_i / w_i` (force per unit
    /// length), from the contact forces `r`. Exact for a uniform traction (module documentation).
    ///
    /// # Panics
    /// If `r` does not hold `2m` values.
    pub fn tractions(&self, r: &[f64]) -> (Vec<f64>, Vec<f64>) {
        assert_eq!(r.len(), 2 * self.points(), "contact boundary: r must hold 2 values per contact point");
        let mut pressure: Vec<f64> = self.weight.iter().enumerate().map(|(i, w)| -r[2 * i] / w).collect();
        let mut friction: Vec<f64> = self.weight.iter().enumerate().map(|(i, w)| r[2 * i + 1] / w).collect();
        let point = |node: usize| self.nodes.iter().position(|&k| k == node);
        for axis in &self.axis_pressure {
            let Some(i) = point(axis.node) else { continue };
            let mut p = 0.0;
            for &(k, c) in &axis.from {
                p += c * point(k).map_or(0.0, |j| pressure[j]);
            }
            pressure[i] = p;
            friction[i] = 0.0;
        }
        (pressure, friction)
    }

    /// Variationally consistent nodal pressures: the solution of `M p = −rN`, with `M` the
    /// boundary mass matrix `∫ φ_i φ_j ds` of the part's edges (P1 or P2 line elements, curved
    /// P2 edges with their true length element) restricted to the contact nodes. Reproduces any
    /// pressure of the trace space exactly (quadratic for P2, linear for P1), without
    /// vertex/mid-node oscillation.
    ///
    /// `mesh` must be the mesh the boundary was built from (edges it does not have are
    /// skipped). `M` is symmetric positive definite and, scaled by its diagonal, uniformly well
    /// conditioned (A. J. Wathen, "Realistic eigenvalue bounds for the Galerkin mass matrix",
    /// IMA J. Numer. Anal. 7 (1987) 449–457): Jacobi-preconditioned conjugate gradients reach
    /// round-off in a few tens of iterations whatever the mesh size.
    ///
    /// # Panics
    /// If `r` does not hold `2m` values.
    pub fn recovered_pressure(&self, mesh: &Mesh, r: &[f64]) -> Vec<f64> {
        assert_eq!(r.len(), 2 * self.points(), "contact boundary: r must hold 2 values per contact point");
        let m = self.points();
        // Sparse rows of M: (column, value), at most 5 distinct columns per row.
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); m];
        let mut coords = Vec::with_capacity(3);
        for &e in &self.edges {
            if e >= mesh.num_edges() {
                continue;
            }
            let edge = mesh.edge(e);
            let local: Vec<Option<usize>> = edge.iter().map(|k| self.nodes.binary_search(k).ok()).collect();
            coords.clear();
            coords.extend(edge.iter().map(|&k| mesh.nodes[k]));
            let mut element = [[0.0; 3]; 3];
            for (values, wds) in edge_quadrature(&coords, mesh.measure) {
                for a in 0..edge.len() {
                    for b in 0..edge.len() {
                        element[a][b] += wds * values[a] * values[b];
                    }
                }
            }
            for a in 0..edge.len() {
                let Some(i) = local[a] else { continue };
                for b in 0..edge.len() {
                    let Some(j) = local[b] else { continue };
                    match rows[i].iter_mut().find(|(c, _)| *c == j) {
                        Some(entry) => entry.1 += element[a][b],
                        None => rows[i].push((j, element[a][b])),
                    }
                }
            }
        }
        let rhs: Vec<f64> = (0..m).map(|i| -r[2 * i]).collect();
        solve_mass(&rows, &rhs)
    }
}

/// `y = M x` for sparse rows.
fn multiply(rows: &[Vec<(usize, f64)>], x: &[f64], y: &mut [f64]) {
    for (yi, row) in y.iter_mut().zip(rows) {
        *yi = row.iter().map(|&(j, v)| v * x[j]).sum();
    }
}

/// Solve `M x = b` (`M` symmetric positive definite) by Jacobi-preconditioned conjugate
/// gradients, to a residual of `1e-15 ‖b‖` (or `2m + 100` iterations, far more than needed).
fn solve_mass(rows: &[Vec<(usize, f64)>], b: &[f64]) -> Vec<f64> {
    let m = b.len();
    let mut x = vec![0.0; m];
    let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    if b_norm == 0.0 {
        return x;
    }
    let inv_diag: Vec<f64> = rows
        .iter()
        .enumerate()
        .map(|(i, row)| {
            let d = row.iter().find(|(j, _)| *j == i).map_or(0.0, |e| e.1);
            if d > 0.0 {
                1.0 / d
            } else {
                1.0
            }
        })
        .collect();
    let mut res = b.to_vec();
    let mut z: Vec<f64> = res.iter().zip(&inv_diag).map(|(r, d)| r * d).collect();
    let mut p = z.clone();
    let mut q = vec![0.0; m];
    let mut rz: f64 = res.iter().zip(&z).map(|(a, b)| a * b).sum();
    for _ in 0..2 * m + 100 {
        multiply(rows, &p, &mut q);
        let pq: f64 = p.iter().zip(&q).map(|(a, b)| a * b).sum();
        if pq <= 0.0 || pq.is_nan() {
            break;
        }
        let alpha = rz / pq;
        for i in 0..m {
            x[i] += alpha * p[i];
            res[i] -= alpha * q[i];
        }
        let r_norm = res.iter().map(|v| v * v).sum::<f64>().sqrt();
        if r_norm <= 1e-15 * b_norm {
            break;
        }
        for i in 0..m {
            z[i] = res[i] * inv_diag[i];
        }
        let rz_new: f64 = res.iter().zip(&z).map(|(a, b)| a * b).sum();
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..m {
            p[i] = z[i] + beta * p[i];
        }
    }
    x
}
