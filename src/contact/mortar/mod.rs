//! # Mortar coupling of two deformable bodies on non-matching meshes (small sliding)
//!
//! Two bodies touch along an interface; each side has its own mesh (P1 or P2 boundary edges,
//! straight or curved), and the meshes do not match. One side is the **slave** (non-mortar)
//! side, which carries the contact unknowns, one `(N, T)` pair per slave node like
//! [`super::boundary`]; the other is the **master** (mortar) side. Small sliding: the pairing of
//! the two sides and the normals are computed once, in the reference configuration.
//!
//! ## Frame, gap and constraint (sign conventions of [`super`])
//!
//! At slave node `i`: `n_i` is the unit outward normal of the SLAVE body (towards the master
//! body), `t_i = (−n_y, n_x)` (as in [`super::boundary`]). Along the slave side the normal
//! field `n(s)` interpolates the nodal normals. A slave point `x_s(s)` is paired with the point
//! `x_m(s)` where the line `x_s(s) + τ n(s)` meets the master side; the gap function is
//! `g(s) = (x_m(s) − x_s(s))·n(s)`: positive when the sides are apart, negative when they
//! overlap. Non-penetration, linearized, is `(u_s − u_m)·n ≤ g`, tested against the dual basis
//! `ψ_i` of the slave side (below). In the rows, `n_i` is then turned to the bisector of the
//! two sides' normals ("Contact direction" below; the same on a straight interface):
//!
//! ```text
//!   D_i  = ∫ φ_i ds          M_ij = ∫ ψ_i φ_j^m ds          g0_i = (1/D_i) ∫ ψ_i g ds
//!
//!   uN_i = n_i·(u_i − Σ_j (M_ij/D_i) u_j) ≤ g0_i,   uT_i = t_i·(u_i − Σ_j (M_ij/D_i) u_j),
//! ```
//!
//! integrals over the slave side, `φ_i` the slave Lagrange basis, `φ_j^m` the master one seen
//! through the pairing, `u_i` slave and `u_j` master nodal displacements. This is `uN ≤ g0` of
//! [`super`] with the relative displacement in place of the displacement. So `B` has one row per
//! contact unknown: row `2i` is `n_iᵀ` on the dofs `2k, 2k+1` of slave node `k` and
//! `−(M_ij/D_i) n_iᵀ` on those of every master node `j`; row `2i + 1` the same with `t_i`
//! ([`MortarCoupling::b_row`], [`MortarCoupling::gather`] = `B u`,
//! [`MortarCoupling::scatter_add`] = `f += Bᵀ r`). The unknowns `rN_i, rT_i` are nodal FORCES on
//! the slave node (`rN ≤ 0` in compression); the master nodes receive `−(M_ij/D_i) r_i`, the
//! reactions distributed by the mortar weights. A uniform pressure `p` is `rN_i = −p D_i`.
//!
//! ## Contact direction: the bisector of the two sides' normals
//!
//! The pairing (which master point a slave point faces) follows the slave normal field, but
//! the direction `n_i` of point `i`'s rows is the bisector of the slave nodal normal `ν_s` and
//! the master normal `ν_m` where the slave node's normal line meets the master side (the
//! master nodal normals interpolated there; outward normals of each body):
//!
//! ```text
//!                master body                  ν_s: outward normal of the slave at node i
//!      ~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~~    ν_m: outward normal of the master where the
//!           ν_s ↖   ↑ n_i   ↗ −ν_m                 normal line of node i meets it
//!      ____________ x_i ______________        n_i = (ν_s − ν_m) / |ν_s − ν_m|,  t_i = (−n_y, n_x)
//!                slave body                   g0_i ← g0_i (ν_s·n_i)
//! ```
//!
//! On a straight interface (`ν_m = −ν_s`) this is the slave normal, and nothing above changes.
//! On two curved sides the slave normal differs from the master's by the angle between them
//! (`2x/R` on two cylinders of radius `R` touching at `x = 0`): a force along the slave normal
//! then has a tangential component `≈ 2p x/R` in the master's frame, odd in `x`, which shifted
//! the Cattaneo–Mindlin stick zone by `e/a ≈ 0.65 (a/R)/μ` (0.11 at a/R = 0.05, μ = 0.3). Along
//! the bisector both bodies see the same tilt, as the small-strain theory's common normal to
//! the tangent plane (K. L. Johnson, Contact Mechanics, 1985, §4.1): the shift is gone (e/a
//! below 1e-4) and Hertz's p0 for two cylinders moved from +0.22 % to +0.02 %. The gap, the
//! weighted distance along the slave normals, is projected on `n_i`. A node whose normal line
//! meets no master edge within the distance (covered only through its edges' segments) uses
//! the master nodal normals its row weighs, `Σ_j (M_ij/D_i) ν_m,j`.
//!
//! ## Segmentation (after Popp, Gee & Wall 2009, section 4, for 2D)
//!
//! ```text
//!                            master body
//!      m0 ------------------------ m1 ----------------------------- m2    master edges (m0, m1),
//!       :                          :                                 :     (m1, m2): body on the
//!       :                          : n(σ)                            :     left, so left to right
//!       :                          :                                 :
//!  x2 ====== x1 ======================================================= x0   slave edges (x0, x1),
//!           s = 1                s = σ                              s = 0   (x1, x2): body on the
//!            [      segment 2     ][              segment 1          ]      left, right to left
//!              paired with (m0, m1)      paired with (m1, m2)
//!                            slave body       n ↑ (outward, towards the master)
//! ```
//!
//! (P2 mid nodes are not drawn; the dotted lines are normal lines of the slave normal field.)
//!
//! For each slave edge `e` (parameter `s ∈ [0, 1]`) and each master edge `f`, the part of
//! `[0, 1]` that `f` faces is the hull of (a) the slave end points `s = 0, 1` whose normal line
//! meets `f`, and (b) the feet on `e` of the end vertices of `f` that fall in `[0, 1]`: the
//! foot `σ` of a master vertex `x_m` solves `(x_m − x_s(σ)) × n(σ) = 0`, the slave normal line
//! through it (Newton from the projection on the chord; exact in one step on straight sides).
//! (a) covers master edges much longer than the slave edge, whose feet lie far outside.
//! Feet inside `(0, 1)` cut the slave edge into segments; each segment is paired with the
//! master edge that faces its midpoint, that faces the slave side (`n_m·n < 0`), and that is
//! nearest along the normal (so a master side folding back, or lying farther than
//! `MortarOptions::max_distance`, is not paired twice). On each segment an 8-point
//! Gauss–Legendre rule (exact to degree 15; on straight sides with centred mid nodes the
//! products `ψ_i φ_j^m` have degree 2 for P1–P1, 3 for P1–P2 and P2–P1, 4 for P2–P2) gives
//! the Gauss points `s_q`, whose normal lines `x_s(s_q) + τ n(s_q)` meet the master edge at
//! `η_q` (Newton on P2 edges). Then `M_ij += w_q |x_s'(s_q)| ψ_i(s_q) φ_j^m(η_q)` and the gap
//! likewise. Newton iterations stop when the residual is at its round-off level (on short
//! edges far from the origin the parameter cannot be resolved beyond `ε |x| / h`).
//!
//! **Projection direction.** Everything is projected along the slave normal field, and
//! integrated over the slave side: the multiplier lives on the slave side, so `ψ_i ds` is the
//! natural measure, and a continuous normal field has no gaps or overlaps at slave vertices
//! (the piecewise edge normals would leave wedges uncovered at convex corners and count
//! others twice). **Nodal normals**: `n_i` is the normalized sum of the unit outward normals,
//! at node `i`, of the slave edges through it (the exact normal of a P2 edge at its mid node);
//! on a smooth interface each is an `O(h^p)` approximation of the true normal, the average is
//! symmetric and it is what the normal field interpolates.
//!
//! ## Dual (biorthogonal) basis (Wohlmuth 2000)
//!
//! On each slave edge, `ψ_a = Σ_b A_ab φ_b` with `∫_e ψ_a φ_b ds = δ_ab ∫_e φ_b ds`, i.e.
//! `A = D_e M_e⁻¹`, `M_e = (∫_e φ_a φ_b ds)` and `D_e = diag(∫_e φ_a ds)`. On a straight edge
//! (`φ0 = 1 − s`, `φ1 = s` for P1; `φ0 = (1 − s)(1 − 2s)`, `φ1 = s(2s − 1)`, `φm = 4s(1 − s)`
//! for P2, node order `v0, v1, mid`):
//!
//! ```text
//!   P1:  A = | 2 −1 |         ψ0 = 2 − 3s,   ψ1 = 3s − 1
//!            |−1  2 |
//!
//!   P2:  M_e = L/30 |  4 −1  2 |   D_e = L diag(1/6, 1/6, 2/3),   A = |  3/2  1/2 −1/4 |
//!                   | −1  4  2 |                                       |  1/2  3/2 −1/4 |
//!                   |  2  2 16 |                                       | −1   −1    3/2 |
//!
//!        ψ0 = 3/2 − 6s + 5s²,   ψ1 = 1/2 − 4s + 5s²,   ψm = −1 + 10s − 10s²
//! ```
//!
//! `Σ_a ψ_a = 1` (because `D_e 1 = M_e 1`), so the dual basis reproduces constants. In 2D the
//! P2 vertex weights `L/6` are positive, so `D_e` is invertible and no modified basis is needed
//! (unlike quadratic faces in 3D). On curved P2 edges `M_e` and `D_e` are computed with the
//! true length element, with the same composite segment rule as the mortar integrals, so that
//! `∫ ψ_i ds = D_i` and constants transfer exactly on any covered node.
//!
//! **Why the dual basis.** With the standard basis the constraint of node `i` is
//! `Σ_k (∫ φ_i φ_k) u_k·n − …`, coupling all slave nodes of the interface through the slave
//! mass matrix, and the multiplier can only be eliminated by inverting it. With `ψ_i`,
//! `∫ ψ_i φ_k ds = D_i δ_ik`: the slave part of each constraint is the single node `i`, the
//! multiplier is eliminated node by node (force `rN_i = D_i λ_i`), and the constraint row of
//! node `i` is local (the node and the few master nodes facing the support of `ψ_i`). The
//! condensed problem and its semi-smooth Newton machinery keep one `(N, T)` pair per slave node
//! with the Signorini and Coulomb conditions node by node, exactly as against a rigid obstacle
//! (Hüeber & Wohlmuth 2005). The price, `ψ_i` taking negative values, is harmless for the
//! weighted conditions (Wohlmuth 2000 proves the optimal a priori estimates).
//!
//! ## Patch test
//!
//! A uniform pressure `p` is `rN_i = −p D_i`: the slave nodes receive `−p D_i n = −p ∫ φ_i ds n`,
//! the consistent load, and master node `j` receives `p Σ_i M_ij n = p ∫ (Σ_i ψ_i) φ_j^m ds n =
//! p ∫ φ_j^m ds n`, its consistent load too, as soon as the two sides coincide (`ds` on the slave
//! is `ds` on the master) and are straight (then `n` is uniform); exact up to round-off since
//! the products are polynomials integrated exactly. On a straight interface linear fields
//! transfer exactly as well (`Σ_j M_ij x_j^m = ∫ ψ_i x_s ds = D_i x_i`), so `g0 = 0` where the
//! sides touch and `g0 = d` for parallel sides at distance `d`.
//!
//! ## Coverage
//!
//! A slave node is covered when its normal line meets a facing master edge (parameter
//! tolerance `1e-9`). Uncovered nodes are an error by default ([`Error::Formulation`], naming
//! the node and its position), or, with [`UncoveredNodes::LeaveOut`], left out of the contact
//! points and listed in [`MortarCoupling::uncovered`].
//!
//! A covered node whose `ψ_i` support is only partly faced by the master side (the master
//! side ends inside one of its edges, or beyond the pairing distance) is tested on the faced
//! part only, the slave term included: its weight is `D_i = ∫_covered ψ_i ds = Σ_j M_ij`
//! (the master basis sums to 1), the slave displacement being lumped at the node as on a
//! fully covered support, where biorthogonality makes it exact. Then `Σ_j M_ij / D_i = 1`:
//! a rigid translation of both sides leaves `uN = 0`, a parallel offset `d` gives `g0 = d`,
//! and the slave node's force goes wholly to the master nodes facing it. (Weighed by the whole
//! `∫ φ_i ds` instead, the row of the last slave node facing the end of a master side read
//! `u_i − ½ ū_master` on half a support: the master corner could sink into the slave side by
//! half its displacement, 8.5 % of the displacement scale on a block whose corner is a master
//! node on a finer foundation.) The faced part of a covered node's support contains a
//! neighbourhood of the node, on which `∫ ψ_i > 0` (P1: `2t − 3t²/2` over `[0, t]`; P2 vertex
//! `t (3/2 − 3t + 5t²/3)`, mid node likewise): a node whose covered weight is below `10⁻⁶`
//! of `∫ φ_i ds` (faced only at the node itself) is left out as uncovered. Partly covered
//! nodes are listed in [`MortarCoupling::partly_covered`] with their covered fraction.
//!
//! ## Axisymmetry
//!
//! On the meridian half-plane of bodies of revolution ([`crate::mesh::Measure::Axisymmetric`],
//! both sides; [`MortarSide::from_mesh`] takes the mesh's measure) every integral above is over
//! the revolved surface: `ds` stands for `2π r ds`, `r` the radius of the SLAVE point
//! (`D_i = ∫ φ_i 2π r ds`, `M_ij = ∫ ψ_i φ_j^m 2π r ds`, `g0_i`, and the edge matrices `M_e`,
//! `D_e` of the dual basis, with the same composite rule), so that `rN_i = −p D_i` is the force
//! of the full ring (N) and `−rN_i / D_i` a pressure (Pa). On a straight edge the products carry
//! one more degree (at most 5: the 8-point rule is still exact); the patch test and the transfer
//! of constants and of linear fields hold as in the plane (the proofs only use `Σ_a ψ_a = 1`
//! and biorthogonality, which the weighted `M_e`, `D_e` keep).
//!
//! At a node on the axis the nodal normal is the axis direction (`(0, ±1)`, by symmetry; the
//! normal of a curved P2 edge at its vertex is off by `O(θ³)`), for both sides.
//!
//! **A P2 vertex on the axis.** Its weight vanishes: on a straight edge from the axis
//! `r = r_1 s` and `∫₀¹ (1 − s)(1 − 2s) s ds = 0` (on an arc of angle `θ` it is `O(θ²)` of the
//! others, of either sign). Then `A = D_e M_e⁻¹` has a zero row, `ψ_i ≡ 0`, and the node has no
//! weighted constraint at all: by biorthogonality `∫ ψ_a φ_i 2π r ds = D_i δ_ai = 0`, its
//! displacement enters no other row either, so it could sink into the master side freely. Such a
//! node (P2, a vertex of the slave side with `r = 0` exactly, as the setup snaps it; whatever its
//! computed weight) gets `D_i = 0` and a **node-to-segment row**: `uN_i = n_i·(u_i − Σ_j
//! φ_j^m(η_i) u_j) ≤ g_i`, `η_i` where its normal line meets the nearest facing master edge,
//! `g_i = (x_m(η_i) − x_i)·n_i` (in [`MortarCoupling::mortar`] the coefficients `φ_j^m(η_i)`
//! themselves, which [`MortarCoupling::transfer`] returns). This is the nodal constraint the node
//! has against a rigid obstacle ([`super::boundary`]);
//! `B` keeps full row rank (no other row holds `u_i`), and the weighted constraints of the
//! other nodes are untouched (`∫ ψ_a 2π r ds = D_a` still, so constants transfer exactly). Its
//! force `rN_i` is a concentrated force on the axis, the consistent share of a smooth pressure
//! being `∫ φ_i p 2π r ds = O(h⁴)`; its pressure is not `−rN_i / D_i` but the even
//! extrapolation `p = A + B r²` from the two other nodes of its edge, its friction traction 0
//! ([`MortarCoupling::axis_pressure`], [`AxisPressure`]). (Alternatives: leaving the node out
//! lets it penetrate; a modified quadratic basis with positive vertex weights (Popp, Wohlmuth,
//! Gee, Wall, SIAM J. Sci. Comput. 34 (2012) B421) changes the slave displacement basis, hence
//! every row and the recovery.) A P1 vertex on the axis keeps a positive weight
//! (`∫ (1 − s) s ds = 1/6`) and needs nothing special.
//!
//! ## Accuracy and cost
//!
//! Measured in `tests/mortar.rs` on irregular non-matching meshes: constants and linear fields
//! transfer to `1e-15` on straight interfaces (every pair of orders, sides up to 20 times finer
//! than the other, and 1500 against 2300 edges), the patch test holds to `4e-16`, matching
//! meshes give `M_ij / D_i = δ` to `1e-14`. On a curved interface (both sides on one circle),
//! constants still transfer to `1e-15` (by construction, above); a linear field transfers up to
//! the weighted normal distance between the two discrete curves, which is also `g0_i`: with
//! P2 sides (mid nodes on the circle) about `1.6e-3 h⁴ / R³`, with a P1 side (chords) `0.03 to
//! 0.08 h² / R`, `h` the longest edge. The search examines every pair of slave and master
//! edges (bounding boxes prune it when `max_distance` is finite): 1500 × 2300 edges take 0.7 to
//! 1.3 s (release build, shared machine); a spatial index would be the next step for much longer interfaces.
//!
//! References: B. I. Wohlmuth, "A mortar finite element method using dual spaces for the
//! Lagrange multiplier", SIAM J. Numer. Anal. 38 (2000) 989–1012 (dual basis, biorthogonality,
//! a priori estimates); A. Popp, M. W. Gee, W. A. Wall, "A finite deformation mortar contact
//! formulation using a primal–dual active set strategy", Int. J. Numer. Meth. Engng 79 (2009)
//! 1354–1391 (2D segmentation along the interpolated slave normal field, weighted gaps);
//! S. Hüeber, B. I. Wohlmuth, "A primal–dual active set strategy for non-linear multibody
//! contact problems", Comput. Methods Appl. Mech. Engrg. 194 (2005) 3147–3166.
mod interpenetration;
mod points;
mod segments;

pub use interpenetration::{Interpenetration, NodePenetration};

use crate::contact::boundary::AxisPressure;
use crate::error::{Error, Result};
use crate::mesh::{Measure, Mesh, Order};
use segments::{Edge, SlaveEdge, NODE_PARAMETER};

/// One side of the interface: boundary edges (global node ids) and the positions of their nodes.
#[derive(Debug, Clone, PartialEq)]
pub struct MortarSide {
    name: String,
    order: Order,
    /// `v0, v1` (P1) or `v0, v1, mid` (P2), domain on the left.
    edges: Vec<Vec<usize>>,
    /// The nodes of the edges, sorted increasingly, and their positions.
    nodes: Vec<usize>,
    positions: Vec<[f64; 2]>,
    /// Plane, or axisymmetric (every mortar integral then carries `2π r`).
    measure: Measure,
}

impl MortarSide {
    /// A side from its edges, whose node ids index `positions` (a global node numbering). Edges
    /// run with their body on the left (the mesh convention), so that `(dy, −dx)` is outward.
    ///
    /// Errors: [`Error::Usage`] for an empty side, an edge with the wrong number of nodes, a node
    /// id out of range, a repeated node in an edge or a non-finite position; [`Error::Mesh`] for
    /// a degenerate edge (zero length element). Messages name the side.
    pub fn new(name: impl Into<String>, order: Order, edges: Vec<Vec<usize>>, positions: &[[f64; 2]]) -> Result<Self> {
        let name = name.into();
        let usage = |m: String| Error::Usage(format!("mortar side '{name}': {m}"));
        if edges.is_empty() {
            return Err(usage("it has no edges".into()));
        }
        let per_edge = order.nodes_per_edge();
        for (e, edge) in edges.iter().enumerate() {
            if edge.len() != per_edge {
                return Err(usage(format!("edge {e} has {} nodes, a {order:?} edge has {per_edge}", edge.len())));
            }
            if let Some(&k) = edge.iter().find(|&&k| k >= positions.len()) {
                return Err(usage(format!("edge {e}: node {k} has no position (there are {})", positions.len())));
            }
            if (1..per_edge).any(|a| edge[..a].contains(&edge[a])) {
                return Err(usage(format!("edge {e} repeats a node: {edge:?}")));
            }
            if let Some(&k) = edge.iter().find(|&&k| !positions[k].iter().all(|c| c.is_finite())) {
                return Err(usage(format!("node {k} has a non-finite position {:?}", positions[k])));
            }
        }
        let mut nodes: Vec<usize> = edges.iter().flatten().copied().collect();
        nodes.sort_unstable();
        nodes.dedup();
        let positions = nodes.iter().map(|&k| positions[k]).collect();
        let side = MortarSide { name, order, edges, nodes, positions, measure: Measure::Plane };
        for e in 0..side.edges.len() {
            let edge = side.edge(e);
            let chord = (edge.x[1][0] - edge.x[0][0]).hypot(edge.x[1][1] - edge.x[0][1]);
            if [0.0, 0.25, 0.5, 0.75, 1.0].iter().any(|&s| {
                let j = edge.at(s).length_element;
                j.is_nan() || j <= 1e-12 * chord
            }) {
                return Err(Error::mesh(
                    format!("edge {e} (nodes {:?}) of mortar side '{}'", side.edges[e], side.name),
                    "is degenerate (zero length, or a P2 edge folded on itself)",
                ));
            }
        }
        Ok(side)
    }

    /// The side of boundary group `group` of `mesh` (node ids are the mesh's; see
    /// [`MortarSide::with_node_offset`] for a second mesh in a common numbering).
    ///
    /// Errors: [`Error::Usage`] for a group out of range or a region; [`Error::Mesh`] for a
    /// group without edges; those of [`MortarSide::new`].
    pub fn from_mesh(mesh: &Mesh, group: usize) -> Result<Self> {
        let Some(part) = mesh.groups.get(group) else {
            return Err(Error::Usage(format!(
                "mortar side: group index {group} is out of range (the mesh has {} physical groups)",
                mesh.groups.len()
            )));
        };
        if part.dim != 1 {
            return Err(Error::Usage(format!(
                "mortar side '{}': it is a region (dimension {}), a contact side must be a boundary (curve) group",
                part.name, part.dim
            )));
        }
        let edges: Vec<Vec<usize>> = mesh.edges_in_group(group).map(|e| mesh.edge(e).to_vec()).collect();
        if edges.is_empty() {
            return Err(Error::mesh(format!("physical group '{}'", part.name), "has no boundary edges"));
        }
        Ok(Self::new(part.name.clone(), mesh.order, edges, &mesh.nodes)?.with_measure(mesh.measure))
    }

    /// The same side with the measure `measure` ([`MortarSide::new`] makes a plane side;
    /// [`MortarSide::from_mesh`] takes the mesh's): in axisymmetry every mortar integral carries
    /// `2π r` (module documentation, "Axisymmetry").
    pub fn with_measure(mut self, measure: Measure) -> Self {
        self.measure = measure;
        self
    }

    /// Its measure: plane or axisymmetric.
    pub fn measure(&self) -> Measure {
        self.measure
    }

    /// The same side with every node id increased by `offset` (the numbering of a second body
    /// whose nodes follow the first body's).
    pub fn with_node_offset(mut self, offset: usize) -> Self {
        self.edges.iter_mut().flatten().for_each(|k| *k += offset);
        self.nodes.iter_mut().for_each(|k| *k += offset);
        self
    }

    /// The side's name (`body.part`).
    pub fn name(&self) -> &str {
        &self.name
    }
    /// The order of its edges.
    pub fn order(&self) -> Order {
        self.order
    }
    /// Its edges, each as its node indices.
    pub fn edges(&self) -> &[Vec<usize>] {
        &self.edges
    }
    /// The nodes of the side, sorted increasingly.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }
    /// The position of node `k`, if it is a node of the side.
    pub fn position(&self, k: usize) -> Option<[f64; 2]> {
        self.nodes.binary_search(&k).ok().map(|i| self.positions[i])
    }

    fn edge(&self, e: usize) -> Edge {
        let ids = &self.edges[e];
        let mut edge = Edge { len: ids.len(), nodes: [0; 3], x: [[0.0; 2]; 3] };
        for (a, &k) in ids.iter().enumerate() {
            edge.nodes[a] = k;
            edge.x[a] = self.positions[self.nodes.binary_search(&k).expect("edge node of the side")];
        }
        edge
    }

    /// The even extrapolation of the pressure at node `k` on the axis from the two other nodes
    /// of its edge ([`AxisPressure::even`]).
    fn axis_extrapolation(&self, k: usize) -> Option<AxisPressure> {
        let ids = self.edges.iter().find(|edge| edge.contains(&k))?;
        let others = ids.iter().filter(|&&j| j != k).map(|&j| (j, self.position(j).expect("edge node of the side")[0]));
        AxisPressure::even(k, others.collect())
    }

    /// Unit outward normals at the nodes (aligned with [`MortarSide::nodes`]): the normalized sum
    /// of the outward normals, at the node, of the edges through it; in axisymmetry, at a node
    /// on the axis (`r = 0`), the unit vector along the axis on the same side (symmetry).
    ///
    /// Errors: [`Error::Mesh`] at a node where the edges' normals cancel (edges of opposite
    /// orientations, or a cusp).
    pub fn nodal_normals(&self) -> Result<Vec<[f64; 2]>> {
        let mut sum = vec![[0.0; 2]; self.nodes.len()];
        for e in 0..self.edges.len() {
            let edge = self.edge(e);
            for (k, &s) in edge.nodes[..edge.len].iter().zip(&NODE_PARAMETER) {
                let n = edge.at(s).normal;
                let i = self.nodes.binary_search(k).expect("edge node of the side");
                sum[i][0] += n[0];
                sum[i][1] += n[1];
            }
        }
        sum.iter()
            .zip(&self.nodes)
            .map(|(v, &k)| {
                let l = v[0].hypot(v[1]);
                // In axisymmetry the normal at a node on the axis is along the axis (by
                // symmetry); a curved P2 edge's own normal there is off by O(θ³).
                if self.measure.is_axisymmetric() && self.position(k).is_some_and(|x| x[0] == 0.0) && v[1] != 0.0 {
                    return Ok([0.0, v[1].signum()]);
                }
                if l < 1e-6 {
                    Err(Error::mesh(
                        format!("node {k} of mortar side '{}'", self.name),
                        "the outward normals of its edges cancel: the edges through it run in opposite directions \
                         (or meet in a cusp)",
                    ))
                } else {
                    Ok([v[0] / l, v[1] / l])
                }
            })
            .collect()
    }
}

/// A partly covered slave node whose covered weight `∫_covered ψ_i ds` is below this fraction of
/// `∫ φ_i ds` is left out as uncovered (the master side ends at the node itself).
const COVERED_WEIGHT: f64 = 1e-6;

/// What to do with slave nodes whose normal line misses the master side.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UncoveredNodes {
    /// [`Error::Formulation`] naming the first such node and its position (the default).
    #[default]
    Error,
    /// Leave them out of the contact points and list them in [`MortarCoupling::uncovered`].
    LeaveOut,
}

/// Options of [`MortarCoupling::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MortarOptions {
    /// Master points farther than this along the slave normal (`|g| >`) are not paired
    /// (default: infinite, every facing master edge is a candidate, the nearest is paired).
    pub max_distance: f64,
    /// What to do with slave nodes the master side does not face.
    pub uncovered: UncoveredNodes,
}

impl Default for MortarOptions {
    fn default() -> Self {
        MortarOptions { max_distance: f64::INFINITY, uncovered: UncoveredNodes::Error }
    }
}

/// A slave node whose normal line misses the master side.
#[derive(Debug, Clone, PartialEq)]
pub struct UncoveredNode {
    /// The slave node.
    pub node: usize,
    /// Its coordinates.
    pub position: [f64; 2],
    /// Its normal, along which no master edge was found.
    pub normal: [f64; 2],
}

/// A contact node whose `ψ` support is only partly faced by the master side.
#[derive(Debug, Clone, PartialEq)]
pub struct PartlyCovered {
    /// The contact node.
    pub node: usize,
    /// `∫_covered ψ_i ds / ∫ φ_i ds`, the fraction of its weight the master side faces (its
    /// weight `D_i` is the covered one, so that `Σ_j M_ij / D_i = 1` all the same).
    pub coverage: f64,
}

/// The mortar coupling of a slave side with a master side. See the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct MortarCoupling {
    /// Slave nodes that are contact points (covered), sorted increasingly. Point `i` is node
    /// `nodes[i]`.
    pub nodes: Vec<usize>,
    /// `D_i = ∫ φ_i ds` over the slave side (`> 0`; `∫ φ_i 2π r ds` in axisymmetry, `0` exactly
    /// for a P2 vertex on the axis); for a partly covered node, over the part the master side
    /// faces, `∫_covered ψ_i ds = Σ_j M_ij` (module documentation, "Coverage").
    pub weight: Vec<f64>,
    /// `n_i`: the contact direction, the bisector of the slave body's outward normal at the
    /// node (towards the master) and the master side's inward one (module documentation).
    pub normal: Vec<[f64; 2]>,
    /// `t_i = (−n_y, n_x)`.
    pub tangent: Vec<[f64; 2]>,
    /// `g0_i = (1/D_i) ∫ ψ_i (x_m − x_s)·n ds` (`> 0` apart, `0` touching, `< 0` overlapping).
    pub gap: Vec<f64>,
    /// `(master node j, M_ij = ∫ ψ_i φ_j^m ds)`, by increasing master node; for a point of
    /// weight `D_i = 0` (a P2 vertex on the axis in axisymmetry) the node-to-segment
    /// coefficients `φ_j^m(η_i)` themselves (module documentation, "Axisymmetry").
    pub mortar: Vec<Vec<(usize, f64)>>,
    /// Slave nodes left out because their normal line misses the master side
    /// ([`UncoveredNodes::LeaveOut`]).
    pub uncovered: Vec<UncoveredNode>,
    /// Contact nodes whose support is only partly covered (`Σ_j M_ij / D_i ≠ 1`).
    pub partly_covered: Vec<PartlyCovered>,
    /// In axisymmetry: the contact nodes of weight 0 (P2 vertices on the axis), with the even
    /// extrapolation of their pressure from the two other nodes of their slave edge.
    pub axis_pressure: Vec<AxisPressure>,
}

impl MortarCoupling {
    /// The coupling of `slave` with `master`. See the module documentation.
    ///
    /// With [`UncoveredNodes::LeaveOut`] the coupling may have no points at all (no slave node
    /// faces the master side within `max_distance`).
    ///
    /// Errors: [`Error::Usage`] for a `max_distance` that is not positive; [`Error::Mesh`] for
    /// a slave node whose edges' normals cancel, a non-positive weight, or edges too curved to
    /// pair consistently; [`Error::Formulation`] for an uncovered slave node with
    /// [`UncoveredNodes::Error`].
    pub fn new(slave: &MortarSide, master: &MortarSide, options: &MortarOptions) -> Result<Self> {
        if options.max_distance.is_nan() || options.max_distance <= 0.0 {
            return Err(Error::Usage(format!(
                "mortar coupling: max_distance is {}, it must be positive (or infinite)",
                options.max_distance
            )));
        }
        if slave.measure != master.measure {
            return Err(Error::Usage(format!(
                "mortar coupling of slave side '{}' ({:?}) with master side '{}' ({:?}): the two sides must have the \
                 same measure (both plane or both axisymmetric)",
                slave.name, slave.measure, master.name, master.measure
            )));
        }
        let normals = slave.nodal_normals()?;
        let master_normals = master.nodal_normals()?;
        let masters: Vec<Edge> = (0..master.edges.len()).map(|f| master.edge(f)).collect();
        let master_edge_normals: Vec<[[f64; 2]; 3]> = masters
            .iter()
            .map(|edge| {
                let mut out = [[0.0; 2]; 3];
                for a in 0..edge.len {
                    out[a] = master_normals[master.nodes.binary_search(&edge.nodes[a]).expect("edge node of the side")];
                }
                out
            })
            .collect();
        let m = slave.nodes.len();
        let mut weight = vec![0.0; m];
        let mut gap = vec![0.0; m];
        let mut rows: Vec<Vec<(usize, f64)>> = vec![Vec::new(); m];
        let mut covered = vec![false; m];
        let mut partly = vec![false; m];
        let mut axis = vec![false; m];
        for e in 0..slave.edges.len() {
            let edge = slave.edge(e);
            let mut local = [0; 3];
            let mut edge_normals = [[0.0; 2]; 3];
            for a in 0..edge.len {
                local[a] = slave.nodes.binary_search(&edge.nodes[a]).expect("edge node of the side");
                edge_normals[a] = normals[local[a]];
            }
            let integrals = segments::integrate(
                &SlaveEdge { edge, normals: edge_normals, measure: slave.measure },
                &masters,
                options.max_distance,
            )
            .map_err(|message| {
                Error::mesh(format!("edge {e} (nodes {:?}) of slave side '{}'", slave.edges[e], slave.name), message)
            })?;
            for (a, &i) in local.iter().enumerate().take(edge.len) {
                weight[i] += integrals.weight[a];
                gap[i] += integrals.gap[a];
                for &(j, v) in &integrals.mortar[a] {
                    segments::add(&mut rows[i], j, v);
                }
                covered[i] |= integrals.covered[a];
                axis[i] |= integrals.axis[a];
                partly[i] |= integrals.uncovered_length > 0.0;
            }
        }

        let mut coupling = MortarCoupling {
            nodes: Vec::new(),
            weight: Vec::new(),
            normal: Vec::new(),
            tangent: Vec::new(),
            gap: Vec::new(),
            mortar: Vec::new(),
            uncovered: Vec::new(),
            partly_covered: Vec::new(),
            axis_pressure: Vec::new(),
        };
        for (i, &k) in slave.nodes.iter().enumerate() {
            let n = normals[i];
            if !covered[i] {
                coupling.uncovered.push(UncoveredNode { node: k, position: slave.positions[i], normal: n });
                continue;
            }
            if axis[i] {
                // A P2 vertex on the axis (`D_i = 0`, `ψ_i ≡ 0`): a node-to-segment row, the
                // master shape functions where the node's normal line meets the master side
                // (module documentation, "Axisymmetry").
                let Some((row, g, nm)) = segments::node_to_segment(
                    slave.positions[i],
                    n,
                    &masters,
                    &master_edge_normals,
                    options.max_distance,
                ) else {
                    coupling.uncovered.push(UncoveredNode { node: k, position: slave.positions[i], normal: n });
                    continue;
                };
                let (bx, by) = (n[0] - nm[0], n[1] - nm[1]);
                let length = bx.hypot(by);
                let b = if length > 0.5 { [bx / length, by / length] } else { n };
                coupling.nodes.push(k);
                coupling.weight.push(0.0);
                coupling.normal.push(b);
                coupling.tangent.push([-b[1], b[0]]);
                coupling.gap.push(g * (n[0] * b[0] + n[1] * b[1]));
                coupling.mortar.push(row);
                coupling.axis_pressure.extend(slave.axis_extrapolation(k));
                continue;
            }
            let full = weight[i];
            if !(full > 0.0 && full.is_finite()) {
                return Err(Error::mesh(
                    format!("node {k} of slave side '{}'", slave.name),
                    format!("its consistent weight ∫φ ds is {full:e}, not positive; remesh the side"),
                ));
            }
            let mut row = std::mem::take(&mut rows[i]);
            row.sort_by_key(|&(j, _)| j);
            // A partly covered node weighs the part of its support the master side faces:
            // `D_i = ∫_covered ψ_i ds = Σ_j M_ij` (module documentation, "Coverage").
            let mut d = full;
            if partly[i] {
                let covered: f64 = row.iter().map(|&(_, v)| v).sum();
                if !(covered > COVERED_WEIGHT * full && covered.is_finite()) {
                    coupling.uncovered.push(UncoveredNode { node: k, position: slave.positions[i], normal: n });
                    continue;
                }
                coupling.partly_covered.push(PartlyCovered { node: k, coverage: covered / full });
                d = covered;
            }
            // The contact direction: the bisector of the slave normal and the master normal
            // where the slave node's normal line meets the master side (module documentation,
            // "Contact direction"); if it meets none within the distance (a node covered only
            // through its edges), the master normals its mortar row weighs.
            let seen =
                segments::master_normal_at(slave.positions[i], n, &masters, &master_edge_normals, options.max_distance)
                    .unwrap_or_else(|| {
                        let mut seen = [0.0; 2];
                        for &(j, v) in &row {
                            let nm = master_normals[master.nodes.binary_search(&j).expect("master node of the side")];
                            seen[0] += v / d * nm[0];
                            seen[1] += v / d * nm[1];
                        }
                        seen
                    });
            let (bx, by) = (n[0] - seen[0], n[1] - seen[1]);
            let length = bx.hypot(by);
            let b = if length > 0.5 { [bx / length, by / length] } else { n };
            coupling.nodes.push(k);
            coupling.weight.push(d);
            coupling.normal.push(b);
            coupling.tangent.push([-b[1], b[0]]);
            coupling.gap.push(gap[i] / d * (n[0] * b[0] + n[1] * b[1]));
            coupling.mortar.push(row);
        }
        if options.uncovered == UncoveredNodes::Error {
            if let Some(first) = coupling.uncovered.first() {
                let more = coupling.uncovered.len() - 1;
                return Err(Error::Formulation {
                    message: format!(
                        "mortar coupling of slave side '{}' with master side '{}': slave node {} at ({:?}, {:?}) is \
                         not covered, the slave normal through it misses the master side{}",
                        slave.name,
                        master.name,
                        first.node,
                        first.position[0],
                        first.position[1],
                        if more > 0 { format!(" (and {more} more slave nodes)") } else { String::new() }
                    ),
                    hint: "make the slave side the one facing the master side everywhere (usually the shorter one), \
                           trim the slave part to the region the master part faces, or leave such nodes out \
                           (UncoveredNodes::LeaveOut) and check them separately"
                        .into(),
                });
            }
        }
        // With `UncoveredNodes::LeaveOut` every node may be left out (sides out of each other's
        // reach): the caller decides what a coupling without points means.
        Ok(coupling)
    }

    /// Number of contact points `m` (the condensed problem has `2m` unknowns).
    pub fn points(&self) -> usize {
        self.nodes.len()
    }

    /// `(master node j, M_ij / D_i)` of contact point `i`: the transfer coefficients (for a
    /// point of weight 0, a P2 vertex on the axis, its node-to-segment coefficients `φ_j^m(η_i)`).
    pub fn transfer(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let d = if self.weight[i] == 0.0 { 1.0 } else { self.weight[i] };
        self.mortar[i].iter().map(move |&(j, v)| (j, v / d))
    }

    /// `Σ_j M_ij / D_i` (1 up to round-off for a fully covered point).
    pub fn coverage(&self, i: usize) -> f64 {
        self.transfer(i).map(|(_, c)| c).sum()
    }

    /// The relative displacement `u_i − Σ_j (M_ij/D_i) u_j` of contact point `i`.
    fn relative(&self, i: usize, u: &[f64]) -> [f64; 2] {
        let k = self.nodes[i];
        let mut r = [u[2 * k], u[2 * k + 1]];
        for (j, c) in self.transfer(i) {
            r[0] -= c * u[2 * j];
            r[1] -= c * u[2 * j + 1];
        }
        r
    }

    /// `B u`: `(uN_i, uT_i)` interleaved, from a global displacement vector (`dof = 2·node + comp`).
    ///
    /// # Panics
    /// If `u` is too short for the slave and master nodes.
    pub fn gather(&self, u: &[f64]) -> Vec<f64> {
        let mut out = Vec::with_capacity(2 * self.points());
        for i in 0..self.points() {
            let r = self.relative(i, u);
            let (n, t) = (self.normal[i], self.tangent[i]);
            out.push(n[0] * r[0] + n[1] * r[1]);
            out.push(t[0] * r[0] + t[1] * r[1]);
        }
        out
    }

    /// `f += Bᵀ r`: the slave node of point `i` receives `n rN + t rT`, master node `j` receives
    /// `−(M_ij/D_i) (n rN + t rT)`.
    ///
    /// # Panics
    /// If `r` does not hold `2m` values or `f` is too short.
    pub fn scatter_add(&self, r: &[f64], f: &mut [f64]) {
        assert_eq!(r.len(), 2 * self.points(), "mortar coupling: r must hold 2 values per contact point");
        for i in 0..self.points() {
            let (n, t) = (self.normal[i], self.tangent[i]);
            let force = [n[0] * r[2 * i] + t[0] * r[2 * i + 1], n[1] * r[2 * i] + t[1] * r[2 * i + 1]];
            let k = self.nodes[i];
            f[2 * k] += force[0];
            f[2 * k + 1] += force[1];
            for (j, c) in self.transfer(i) {
                f[2 * j] -= c * force[0];
                f[2 * j + 1] -= c * force[1];
            }
        }
    }

    /// The sparse row `j` of `B` (`N_i` for `j = 2i`, `T_i` for `j = 2i + 1`): `(dof, coefficient)`
    /// pairs by increasing dof, a node shared by both sides summed once.
    ///
    /// # Panics
    /// If `j ≥ 2m`.
    pub fn b_row(&self, j: usize) -> Vec<(usize, f64)> {
        let i = j / 2;
        let v = if j.is_multiple_of(2) { self.normal[i] } else { self.tangent[i] };
        let k = self.nodes[i];
        let mut row = vec![(2 * k, v[0]), (2 * k + 1, v[1])];
        for (node, c) in self.transfer(i) {
            segments::add(&mut row, 2 * node, -c * v[0]);
            segments::add(&mut row, 2 * node + 1, -c * v[1]);
        }
        row.sort_by_key(|&(dof, _)| dof);
        row
    }
}
