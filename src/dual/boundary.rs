//! Boundary conditions of the Airy stress function: known tractions become linear constraints
//! on the HCT dofs of the boundary, eliminated once and for all (master–slave elimination).
//!
//! Along a boundary edge `a → b` (counter-clockwise, length L, tangent τ, outward normal
//! `n = (τ_y, −τ_x)`) the traction of `σ(φ)` is the arc-length derivative of `∇φ` turned by a
//! right angle (F. Lebon's talk "Modèles d'interface et formulations pour le contact frottant", "Formulation en contraintes"):
//!
//! ```text
//!   t_x = d(φ,y)/ds,    t_y = −d(φ,x)/ds.
//! ```
//!
//! With the full HCT element `φ` is cubic along the edge (Hermite: φ and φ,s at the ends) and
//! `φ,n` quadratic (ends and midpoint), so `g = ∇φ` is quadratic along the edge, fixed by its
//! values at `a`, at `b` and at the midpoint `m`, where
//!
//! ```text
//!   g(m)·τ = 3 (φ(b) − φ(a)) / (2L) − (g(a)·τ + g(b)·τ) / 4,     g(m)·n = ± (midpoint dof).
//! ```
//!
//! A traction component that is known and linear along the edge (a constant traction, a
//! pressure, or what is left of them once the particular field of a constant body force is
//! taken off) fixes the matching component of `g` everywhere along the edge, exactly, through
//! two conditions at the nodes of the quadratic:
//!
//! ```text
//!   g_c(b) − g_c(a) = I_c(L),    g_c(m) − g_c(a) = I_c(L/2),    I(s) = ∫_0^s (−t_y, t_x) ds'
//! ```
//!
//! (the integrals of a linear function are exact with the trapezoid rule). Where a traction
//! component is unknown (a prescribed displacement component, a contact) there is no
//! constraint; a prescribed displacement enters the complementary energy instead,
//! `l(σ) = ∫ u0·σn ds = u0x [φ,y]_a^b − u0y [φ,x]_a^b` for a constant `u0` on the edge.
//!
//! ## Elimination
//!
//! The constraints are processed edge by edge along the boundary loop, starting where a run of
//! known tractions starts (with tractions and contact only, where a contact run starts, so that
//! the walk closes on known tractions); each one is solved for one dof of the edge's end vertex `b` or of
//! its midpoint (the one with the largest scaled coefficient) in terms of dofs already free,
//! so every constrained dof becomes an affine function of the remaining (master) dofs. This
//! is the integration of the tractions along the boundary, done by linear algebra, component
//! by component (a symmetry plane `ux = 0` leaves the shear traction known and the normal one
//! free). Where a run of known tractions closes on itself (a boundary loaded by tractions
//! only) the last conditions are redundant: they are the global equilibrium of the loads
//! (force and moment), checked instead of imposed. The affine kernel of φ (φ + α + β·x has the
//! same stresses) is removed by fixing φ, φ,x, φ,y at one vertex whose dofs are all free.
use std::collections::BTreeMap;

use super::dofs::HctDofs;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// What is known of one traction component along a boundary edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TractionComponent {
    /// Known, linear along the edge: its values at the start, the midpoint and the end.
    Known([f64; 3]),
    /// Unknown; the displacement component is prescribed (`u0`, constant on the edge).
    Prescribed(f64),
    /// Unknown and no displacement prescribed (a contact edge): no constraint, no load.
    Free,
}

/// One boundary edge of the dual problem.
#[derive(Debug, Clone)]
pub struct BoundaryEdge {
    /// Index of the edge in `mesh.edges`.
    pub mesh_edge: usize,
    /// Start and end nodes (counter-clockwise: the domain on the left).
    pub a: usize,
    /// End node (the domain on the left of `a → b`).
    pub b: usize,
    /// The HCT edge index.
    pub edge: usize,
    /// x and y traction components.
    pub components: [TractionComponent; 2],
    /// On a contact edge: its traction is linear along the edge with unknown end values
    /// ([`ContactEdge`]); `components` are then both [`TractionComponent::Free`].
    pub contact: Option<ContactEdge>,
}

/// The traction of a contact edge `a → b` in terms of contact unknowns (forces, N per unit
/// thickness): at each end `k` (0 = a, 1 = b) the traction is `(rN_k n_k + rT_k t_k) / w`
/// with `w = L/2`, linear in between. The unknowns are numbered `first .. first + 4` as
/// `(N_a, T_a, N_b, T_b)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactEdge {
    /// Index of the edge's first contact unknown.
    pub first: usize,
    /// Unit normal `n_k` and tangent `t_k` at each end.
    pub frames: [[[f64; 2]; 2]; 2],
}

/// How each global dof depends on the unknowns of the reduced problem.
#[derive(Debug, Clone, PartialEq)]
pub enum DofRole {
    /// Reduced unknown number k.
    Master(usize),
    /// An affine function of masters: `Σ c_j z_j + constant`.
    Slave(Vec<(usize, f64)>, f64),
    /// A fixed value.
    Fixed(f64),
}

/// The affine map from the reduced unknowns `z` to all HCT dofs.
///
/// The reduced unknowns are the free HCT dofs (`0 .. num_masters`) followed, with contact, by
/// the contact forces (`num_masters .. num_masters + num_contact`, see [`ContactEdge`]).
#[derive(Debug, Clone)]
pub struct AffineDofs {
    /// The role of every HCT dof: reduced unknown, affine function of them, or fixed.
    pub role: Vec<DofRole>,
    /// Number of free HCT dofs among the reduced unknowns (numbered first).
    pub num_masters: usize,
    /// Contact unknowns (4 per contact edge), numbered after the masters.
    pub num_contact: usize,
    /// The vertex (mesh node) whose φ and gradient were fixed to remove the affine kernel.
    pub anchor: usize,
    /// Where a run of known tractions closes through contact edges, global equilibrium becomes
    /// a linear condition on the contact forces: `Σ c_j r_j = e` (`j` a contact unknown).
    pub contact_equilibrium: Vec<(Vec<(usize, f64)>, f64)>,
}

impl AffineDofs {
    /// All dofs from the reduced unknowns.
    /// All reduced unknowns (free HCT dofs, then contact forces).
    pub fn num_unknowns(&self) -> usize {
        self.num_masters + self.num_contact
    }

    /// All HCT dofs from the reduced unknowns `z`.
    pub fn expand(&self, z: &[f64]) -> Vec<f64> {
        self.role
            .iter()
            .map(|r| match r {
                DofRole::Master(k) => z[*k],
                DofRole::Slave(terms, c) => c + terms.iter().map(|(k, a)| a * z[*k]).sum::<f64>(),
                DofRole::Fixed(v) => *v,
            })
            .collect()
    }
}

/// The boundary edges in counter-clockwise loop order, checked to form one closed loop.
pub fn boundary_loop(mesh: &Mesh) -> Result<Vec<usize>> {
    let mut next: BTreeMap<usize, usize> = BTreeMap::new();
    for e in 0..mesh.num_edges() {
        let ed = mesh.edge(e);
        if next.insert(ed[0], e).is_some() {
            return Err(formulation_error(
                format!("boundary node {} starts two boundary edges", ed[0]),
                "the boundary must be a simple closed curve",
            ));
        }
    }
    let Some((&start, &first)) = next.iter().next() else {
        return Err(formulation_error("the mesh has no boundary edges".into(), "check the mesh"));
    };
    let mut order = vec![first];
    let mut node = mesh.edge(first)[1];
    while node != start {
        let e = *next.get(&node).ok_or_else(|| {
            formulation_error(format!("the boundary is open at node {node}"), "the boundary must be a closed curve")
        })?;
        order.push(e);
        node = mesh.edge(e)[1];
        if order.len() > mesh.num_edges() {
            break;
        }
    }
    if order.len() != mesh.num_edges() {
        return Err(formulation_error(
            format!(
                "the boundary has more than one closed loop ({} of its {} edges are on the first): the domain has a hole \
                 or several pieces, and the Airy stress function is then multivalued (Michell's conditions)",
                order.len(),
                mesh.num_edges()
            ),
            "use the primal formulation, or cut the domain along a line of symmetry so that it is simply connected",
        ));
    }
    Ok(order)
}

pub(crate) fn formulation_error(message: String, hint: &str) -> Error {
    Error::Formulation { message: format!("dual formulation: {message}"), hint: hint.to_string() }
}

/// An affine expression `Σ c_j dof_j + constant` of free dofs.
type Expansion = (Vec<(usize, f64)>, f64);

/// A linear constraint `Σ c_d dof_d = rhs`, with the dofs it may be solved for.
struct Row {
    terms: Vec<(usize, f64)>,
    rhs: f64,
    candidates: Vec<usize>,
}

/// Eliminate the traction constraints of `edges` (in loop order) and fix the affine kernel.
/// The redundant conditions of a closed run (global equilibrium) are checked against the size
/// of the loads (force per unit thickness).
pub fn eliminate(mesh: &Mesh, dofs: &HctDofs, edges: &[BoundaryEdge]) -> Result<AffineDofs> {
    Ok(eliminate_with(mesh, dofs, edges, false)?.0)
}

/// The elimination with the local parametrisation of the contact part
/// ([`super::local_contact`]): the contact edges' own dofs are their deviations `ξ` from the
/// run's affine base, the forces local functions of `ξ` (one [`EdgeForceMap`] per contact edge,
/// in walk order). Its `contact_equilibrium` holds the same conditions as that of
/// [`eliminate`], on the deviations `ξ` instead of the forces: the closure of the boundary
/// integration as the field computes it ([`super::local_contact::LocalContact::balance`]).
pub fn eliminate_local(mesh: &Mesh, dofs: &HctDofs, edges: &[BoundaryEdge]) -> Result<(AffineDofs, Vec<EdgeForceMap>)> {
    eliminate_with(mesh, dofs, edges, true)
}

/// The forces of one contact edge as a function of the deviations (local parametrisation):
/// `r_e = R [ξ_own; ξ_prev]`, `ξ_own` = `(g_b,x, g_b,y, φ_b, φ,n(m))` of the edge (contact
/// slots `first .. first + 4`), `ξ_prev` = `(g_a,x, g_a,y, φ_a)` of the previous edge of the
/// run (slots `prev .. prev + 3`), zero at the run's first vertex.
#[derive(Debug, Clone, PartialEq)]
pub struct EdgeForceMap {
    /// Slot of the edge's own deviations `ξ_own` (4).
    pub first: usize,
    /// Slot of the previous edge's deviations `ξ_prev` (3), `None` at a run's first edge.
    pub prev: Option<usize>,
    /// The 4 × 7 matrix `R` of `r_e = R [ξ_own; ξ_prev]`.
    pub map: nalgebra::SMatrix<f64, 4, 7>,
}

/// A linear combination of expansions.
fn combine(parts: &[(&Expansion, f64)]) -> Expansion {
    let mut terms: BTreeMap<usize, f64> = BTreeMap::new();
    let mut constant = 0.0;
    for (e, a) in parts {
        constant += a * e.1;
        for &(d, c) in &e.0 {
            *terms.entry(d).or_insert(0.0) += a * c;
        }
    }
    (terms.into_iter().filter(|t| t.1 != 0.0).collect(), constant)
}

/// The local force map of contact edge `e` (see [`EdgeForceMap`] and [`super::local_contact`]):
/// the edge's four conditions written for the deviations, solved for its four forces.
fn edge_force_map(
    contact: &ContactEdge,
    tau: [f64; 2],
    normal: [f64; 2],
    sign: f64,
    len: f64,
    prev: Option<usize>,
) -> Option<EdgeForceMap> {
    use nalgebra::{Matrix4, SMatrix};
    // Columns of M: own (g_bx, g_by, φ_b, mid) 0..4, previous (g_ax, g_ay, φ_a) 4..7.
    let mut m = SMatrix::<f64, 4, 7>::zeros();
    let mut d = Matrix4::<f64>::zeros();
    for c in 0..2 {
        let (k, sign_c) = if c == 1 { (0, 1.0) } else { (1, -1.0) };
        for (row, weights) in [(c, [1.0, 1.0]), (2 + c, [0.75, 0.25])] {
            for end in 0..2 {
                let [normal_end, tangent_end] = contact.frames[end];
                d[(row, 2 * end)] = -sign_c * weights[end] * normal_end[k];
                d[(row, 2 * end + 1)] = -sign_c * weights[end] * tangent_end[k];
            }
        }
        m[(c, c)] = 1.0;
        m[(c, 4 + c)] = -1.0;
        let row = 2 + c;
        m[(row, 2)] = 1.5 * tau[c] / len;
        m[(row, 6)] = -1.5 * tau[c] / len;
        m[(row, 3)] = normal[c] * sign;
        for j in 0..2 {
            m[(row, j)] -= 0.25 * tau[c] * tau[j];
            m[(row, 4 + j)] -= 0.25 * tau[c] * tau[j];
        }
        m[(row, 4 + c)] -= 1.0;
    }
    let mut map = -(d.try_inverse()? * m);
    if prev.is_none() {
        map.columns_mut(4, 3).fill(0.0);
    }
    Some(EdgeForceMap { first: contact.first, prev, map })
}

fn eliminate_with(
    mesh: &Mesh,
    dofs: &HctDofs,
    edges: &[BoundaryEdge],
    local: bool,
) -> Result<(AffineDofs, Vec<EdgeForceMap>)> {
    let n = dofs.len();
    let mut force_maps = Vec::new();
    // The local parametrisation: the affine base of the current contact run (φ, φ,x, φ,y at
    // its first vertex, and that vertex), and the previous contact edge's first slot.
    let mut run: Option<([Expansion; 3], [f64; 2], Option<usize>)> = None;
    // Contact forces are numbered after the HCT dofs (`n + j`) during the elimination: they
    // are never solved for, so they stay free.
    let num_contact = edges.iter().filter_map(|e| e.contact.map(|c| c.first + 4)).max().unwrap_or(0);
    let total = n + num_contact;
    // Slave expressions in terms of free global dofs.
    let mut slave: Vec<Option<Expansion>> = vec![None; total];
    let mut referenced = vec![false; total];
    let mut contact_equilibrium = Vec::new();
    // Start the walk where a run of known tractions starts (after an edge with an unknown
    // component), so that the first vertex of every run stays free.
    let fully_known =
        |e: &BoundaryEdge| e.contact.is_some() || e.components.iter().all(|c| matches!(c, TractionComponent::Known(_)));
    let previous = |i: usize| &edges[(i + edges.len() - 1) % edges.len()];
    // With tractions and contact only, start where a contact run starts, so that the walk closes
    // on an edge of known tractions: closing through a contact edge would leave that edge's
    // forces in the global equilibrium conditions alone (no dof downstream depends on them: a
    // zero flexibility) and leaves no dofs for the local parametrisation.
    let start = (0..edges.len())
        .find(|&i| !fully_known(previous(i)))
        .or_else(|| (0..edges.len()).find(|&i| edges[i].contact.is_some() && previous(i).contact.is_none()))
        .unwrap_or(0);
    let mut load_scale = 0.0f64;
    let mut closures = Vec::new();
    for step in 0..edges.len() {
        let e = &edges[(start + step) % edges.len()];
        let (pa, pb) = (mesh.nodes[e.a], mesh.nodes[e.b]);
        let d = [pb[0] - pa[0], pb[1] - pa[1]];
        let len = d[0].hypot(d[1]);
        let tau = [d[0] / len, d[1] / len];
        let normal = [tau[1], -tau[0]];
        // The midpoint dof is ∂φ/∂n along the global normal: sign relative to the outward one.
        let sign = if e.a < e.b { 1.0 } else { -1.0 };
        let ga = [dofs.node_dof(e.a, 1), dofs.node_dof(e.a, 2)];
        let gb = [dofs.node_dof(e.b, 1), dofs.node_dof(e.b, 2)];
        let (phi_a, phi_b, mid) = (dofs.node_dof(e.a, 0), dofs.node_dof(e.b, 0), dofs.edge_dof(e.edge));
        let candidates = vec![gb[0], gb[1], phi_b, mid];
        if let (true, Some(contact)) = (local, &e.contact) {
            let expansion = |d: usize| slave[d].clone().unwrap_or((vec![(d, 1.0)], 0.0));
            let (base, x0, prev) = match run.take() {
                Some(r) => r,
                None => ([expansion(phi_a), expansion(ga[0]), expansion(ga[1])], pa, None),
            };
            if candidates.iter().any(|&d| referenced[d] || slave[d].is_some()) {
                return Err(formulation_error(
                    format!("the contact edge {} -> {} closes the boundary walk", e.a, e.b),
                    "report this mesh: it should not happen (the walk starts where a contact run starts)",
                ));
            }
            let map = edge_force_map(contact, tau, normal, sign, len, prev).ok_or_else(|| {
                formulation_error(format!("singular contact frames at edge {} -> {}", e.a, e.b), "check the obstacle")
            })?;
            force_maps.push(map);
            let xi = |k: usize| (vec![(n + contact.first + k, 1.0)], 0.0);
            // φ_b = base(b) + ξ, base(x) = φ0 + g0·(x − x0); g_b = g0 + ξ; mid = ±n·g0 + ξ.
            let values = [
                combine(&[(&base[1], 1.0), (&xi(0), 1.0)]),
                combine(&[(&base[2], 1.0), (&xi(1), 1.0)]),
                combine(&[(&base[0], 1.0), (&base[1], pb[0] - x0[0]), (&base[2], pb[1] - x0[1]), (&xi(2), 1.0)]),
                combine(&[(&base[1], sign * normal[0]), (&base[2], sign * normal[1]), (&xi(3), 1.0)]),
            ];
            for (&p, value) in candidates.iter().zip(values) {
                for &(d, _) in &value.0 {
                    referenced[d] = true;
                }
                slave[p] = Some(value);
            }
            run = Some((base, x0, Some(contact.first)));
            continue;
        }
        run = None;
        let mut rows = Vec::new();
        // A known traction component k fixes gradient component c: t_x drives φ,y (c = 1),
        // t_y drives φ,x (c = 0) with a minus sign.
        for (k, comp) in e.components.iter().enumerate() {
            let TractionComponent::Known(t) = comp else { continue };
            let (c, rate) = if k == 0 { (1, [t[0], t[1], t[2]]) } else { (0, [-t[0], -t[1], -t[2]]) };
            let i_half = 0.25 * len * (rate[0] + rate[1]);
            let i_full = i_half + 0.25 * len * (rate[1] + rate[2]);
            load_scale = load_scale
                .max(i_full.abs())
                .max(i_half.abs())
                .max(len * rate.iter().fold(0.0f64, |m, r| m.max(r.abs())));
            rows.push(Row { terms: vec![(gb[c], 1.0), (ga[c], -1.0)], rhs: i_full, candidates: candidates.clone() });
            // g_c(m) = τ_c [3(φb − φa)/(2L) − (g(a)·τ + g(b)·τ)/4] + n_c · sign · mid.
            let mut terms = vec![(phi_b, 1.5 * tau[c] / len), (phi_a, -1.5 * tau[c] / len), (mid, normal[c] * sign)];
            for j in 0..2 {
                terms.push((ga[j], -0.25 * tau[c] * tau[j]));
                terms.push((gb[j], -0.25 * tau[c] * tau[j]));
            }
            terms.push((ga[c], -1.0));
            rows.push(Row { terms, rhs: i_half, candidates: candidates.clone() });
        }
        if let Some(contact) = &e.contact {
            // The traction is (rN n + rT t)/w at each end with w = L/2, linear in between:
            // ∫_0^L rate ds = (L/2)(rate_a + rate_b) and ∫_0^{L/2} rate ds = (L/8)(3 rate_a + rate_b),
            // so in forces the two conditions of component c carry the weights (1, 1) and (3/4, 1/4).
            // Both gradient-difference rows first (they fix g(b)), then both midpoint rows,
            // whose pivots φ_b and the midpoint dof form a rotation: always solvable.
            let (mut differences, mut midpoints) = (Vec::new(), Vec::new());
            for c in 0..2 {
                // rate = t_x for c = 1 (φ,y), −t_y for c = 0 (φ,x).
                let (k, sign_c) = if c == 1 { (0, 1.0) } else { (1, -1.0) };
                let force_terms = |weights: [f64; 2]| {
                    let mut terms = Vec::with_capacity(4);
                    for end in 0..2 {
                        let [normal_end, tangent_end] = contact.frames[end];
                        terms.push((n + contact.first + 2 * end, -sign_c * weights[end] * normal_end[k]));
                        terms.push((n + contact.first + 2 * end + 1, -sign_c * weights[end] * tangent_end[k]));
                    }
                    terms
                };
                let mut full = vec![(gb[c], 1.0), (ga[c], -1.0)];
                full.extend(force_terms([1.0, 1.0]));
                differences.push(Row { terms: full, rhs: 0.0, candidates: candidates.clone() });
                let mut terms =
                    vec![(phi_b, 1.5 * tau[c] / len), (phi_a, -1.5 * tau[c] / len), (mid, normal[c] * sign)];
                for j in 0..2 {
                    terms.push((ga[j], -0.25 * tau[c] * tau[j]));
                    terms.push((gb[j], -0.25 * tau[c] * tau[j]));
                }
                terms.push((ga[c], -1.0));
                terms.extend(force_terms([0.75, 0.25]));
                midpoints.push(Row { terms, rhs: 0.0, candidates: candidates.clone() });
            }
            rows.extend(differences);
            rows.extend(midpoints);
        }
        // Dofs referenced by this edge's own slaves may still be solved for by a later row of
        // the edge (the two midpoint conditions share φ_b and the midpoint dof): the earlier
        // slaves are then updated, and only at the end of the edge are their terms marked.
        let mut edge_slaves: Vec<usize> = Vec::new();
        for row in rows {
            // Substitute what is already eliminated.
            let mut expanded: BTreeMap<usize, f64> = BTreeMap::new();
            let mut constant = 0.0;
            for &(dof, coeff) in &row.terms {
                match &slave[dof] {
                    Some((terms, c)) => {
                        constant += coeff * c;
                        for &(m, a) in terms {
                            *expanded.entry(m).or_insert(0.0) += coeff * a;
                        }
                    }
                    None => *expanded.entry(dof).or_insert(0.0) += coeff,
                }
            }
            let scaled = |dof: usize, coeff: f64| {
                if dof.is_multiple_of(3) && dof < 3 * dofs.num_vertices() {
                    coeff * len
                } else {
                    coeff
                }
            };
            // HCT terms decide whether the row can be imposed; contact-force terms are kept.
            let largest =
                expanded.iter().filter(|(&d, _)| d < n).map(|(&d, &c)| scaled(d, c).abs()).fold(0.0f64, f64::max);
            let pivot = row
                .candidates
                .iter()
                .filter(|&&d| !referenced[d] && slave[d].is_none())
                .filter_map(|&d| expanded.get(&d).map(|&c| (d, c)))
                .filter(|&(d, c)| scaled(d, c).abs() > 1e-8 * largest.max(1e-300))
                .max_by(|x, y| scaled(x.0, x.1).abs().total_cmp(&scaled(y.0, y.1).abs()));
            match pivot {
                Some((p, cp)) => {
                    let mut terms = Vec::with_capacity(expanded.len());
                    for (&d, &c) in &expanded {
                        if d != p && c != 0.0 {
                            terms.push((d, -c / cp));
                        }
                    }
                    let value = (row.rhs - constant) / cp;
                    for &s in &edge_slaves {
                        let Some((old_terms, old_constant)) = slave[s].take() else { continue };
                        let Some(k) = old_terms.iter().position(|t| t.0 == p) else {
                            slave[s] = Some((old_terms, old_constant));
                            continue;
                        };
                        let a = old_terms[k].1;
                        let mut merged: BTreeMap<usize, f64> = BTreeMap::new();
                        for &(d, c) in old_terms.iter().filter(|t| t.0 != p) {
                            *merged.entry(d).or_insert(0.0) += c;
                        }
                        for &(d, c) in &terms {
                            *merged.entry(d).or_insert(0.0) += a * c;
                        }
                        slave[s] =
                            Some((merged.into_iter().filter(|t| t.1 != 0.0).collect(), old_constant + a * value));
                    }
                    slave[p] = Some((terms, value));
                    edge_slaves.push(p);
                }
                None => {
                    // A redundant condition: it must already hold (global equilibrium), or,
                    // through contact edges, it is a condition on the contact forces.
                    let forces: Vec<(usize, f64)> =
                        expanded.iter().filter(|(&d, &c)| d >= n && c != 0.0).map(|(&d, &c)| (d - n, c)).collect();
                    let force_size = forces.iter().fold(0.0f64, |m, t| m.max(t.1.abs()));
                    if largest <= 1e-8 && force_size > 1e-8 {
                        contact_equilibrium.push((forces, row.rhs - constant));
                        continue;
                    }
                    if largest > 1e-8 {
                        return Err(formulation_error(
                            format!(
                                "the traction conditions at boundary edge {} -> {} cannot be imposed on the HCT dofs",
                                e.a, e.b
                            ),
                            "report this mesh: it should not happen",
                        ));
                    }
                    closures.push((row.rhs - constant, e.a, e.b));
                }
            }
        }
        for &p in &edge_slaves {
            if let Some((terms, _)) = &slave[p] {
                for &(d, _) in terms {
                    referenced[d] = true;
                }
            }
        }
    }
    for &(residual, a, b) in &closures {
        if residual.abs() > 1e-9 * load_scale.max(f64::MIN_POSITIVE) {
            return Err(Error::NoEquilibrium(format!(
                "dual formulation: the loads on the boundary (tractions and body force) are not in equilibrium: \
                 integrating them around the boundary leaves {residual:.4e} (N per unit thickness) at edge {a} -> {b}, \
                 against loads of {load_scale:.4e}; with tractions only on the whole boundary the resultant force and \
                 moment must vanish — add a Dirichlet part (a support), or correct the loads"
            )));
        }
    }
    // Remove the affine kernel at a vertex whose three dofs are all free.
    let free = |v: usize| (0..3).all(|k| slave[3 * v + k].is_none());
    let first_start = edges.get(start).map(|e| dofs.vertex_of_node[e.a]);
    let anchor = first_start
        .filter(|&v| free(v))
        .or_else(|| (0..dofs.num_vertices()).find(|&v| free(v)))
        .ok_or_else(|| formulation_error("no vertex left to fix the affine part of φ".into(), "refine the mesh"))?;
    let mut role = Vec::with_capacity(n);
    let mut master_of = vec![usize::MAX; total];
    let mut num_masters = 0;
    for d in 0..n {
        if d / 3 == anchor && d < 3 * dofs.num_vertices() {
            role.push(DofRole::Fixed(0.0));
        } else if slave[d].is_none() {
            master_of[d] = num_masters;
            role.push(DofRole::Master(num_masters));
            num_masters += 1;
        } else {
            role.push(DofRole::Fixed(0.0)); // replaced below
        }
    }
    for j in 0..num_contact {
        master_of[n + j] = num_masters + j;
    }
    for d in 0..n {
        if let Some((terms, c)) = &slave[d] {
            let constant = *c;
            let mut reduced = Vec::with_capacity(terms.len());
            // The anchor's dofs are fixed to zero: their terms vanish.
            for &(m, a) in terms {
                if master_of[m] != usize::MAX {
                    reduced.push((master_of[m], a));
                }
            }
            role[d] = DofRole::Slave(reduced, constant);
        }
    }
    let affine = AffineDofs { role, num_masters, num_contact, anchor: dofs.vertex_nodes[anchor], contact_equilibrium };
    Ok((affine, force_maps))
}
