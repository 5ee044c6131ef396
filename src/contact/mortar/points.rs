//! The contact points of a mortar coupling as a [`ContactBoundary`], so that the condensed
//! problem, its solvers and the independent checks of a rigid obstacle serve two bodies too,
//! and the merge of several contact boundaries (pairs and rigid obstacles) into one.
//!
//! Point `i` of a coupling is slave node `k`; its rows of `B` are `n_iᵀ` (`t_iᵀ`) on `k` and
//! `−(M_ij/D_i) n_iᵀ` (`t_iᵀ`) on every master node `j` ([`super`]): the [`CoupledNode`]s. Its
//! weight is `D_i = ∫ φ_i ds` (`∫ φ_i 2π r ds` in axisymmetry, 0 at a P2 vertex on the axis,
//! whose pressure is extrapolated: [`MortarCoupling::axis_pressure`]), so that `−rN_i / D_i` is
//! the pressure, as against an obstacle.
//!
//! Slave nodes with prescribed displacement components are treated as in
//! [`crate::contact::boundary`]: a prescribed component `u_c = u0` leaves the slave entries of
//! that component out of the rows and moves `n_c u0` into the gap, and the point gets no
//! friction (the support carries its tangential force); the master entries stay, since the
//! master side still moves. A prescribed component of a master node leaves the rows likewise
//! (its entries `−c n_c`, `−c t_c` dropped, `−c n_c u0` moved into the gap): `B` acts on free
//! dofs only, and the support carries that share of the force. A point whose rows are then
//! empty is left out; a point whose tangential row alone is empty (in axisymmetry, a slave
//! node on the axis paired node to segment with the master's node on the axis, both with
//! `u_r = 0`) keeps the unit tangent on its slave node, as against a rigid obstacle
//! ([`crate::contact::boundary`], "Contact nodes with prescribed displacement components"):
//! it has no friction, so `rT = 0`, and the condensed flexibility stays positive definite. The unreduced frame
//! and each master node's share `c = M_ij/D_i` are kept ([`ContactBoundary::frame`],
//! [`CoupledNode::transfer`]) for the action–reaction check.
use crate::contact::boundary::{ContactBoundary, CoupledNode};
use crate::error::Result;

use super::MortarCoupling;

impl ContactBoundary {
    /// The contact points of `coupling` (see the module documentation). `edges` are the mesh
    /// edges of the slave side (for the pressure recovery and the contact zones);
    /// `prescribed(node)` the prescribed displacement components of a node.
    pub fn from_mortar(
        coupling: &MortarCoupling,
        edges: Vec<usize>,
        prescribed: &dyn Fn(usize) -> [Option<f64>; 2],
    ) -> Result<Self> {
        let m = coupling.points();
        let mut b = ContactBoundary {
            nodes: Vec::with_capacity(m),
            normal: Vec::with_capacity(m),
            tangent: Vec::with_capacity(m),
            gap: Vec::with_capacity(m),
            weight: Vec::with_capacity(m),
            edges,
            prescribed: Vec::with_capacity(m),
            left_out: Vec::new(),
            coupled: Vec::with_capacity(m),
            frame: Vec::with_capacity(m),
            axis_pressure: coupling.axis_pressure.clone(),
        };
        for i in 0..m {
            let k = coupling.nodes[i];
            let (mut n, mut t) = (coupling.normal[i], coupling.tangent[i]);
            let mut gap = coupling.gap[i];
            // Master entries; a prescribed master component leaves the rows too, its known
            // displacement moved into the gap (`uN` holds `−c n_c u0` for it).
            let coupled: Vec<CoupledNode> = coupling
                .transfer(i)
                .map(|(j, c)| {
                    let mut node = CoupledNode {
                        node: j,
                        normal: [-c * coupling.normal[i][0], -c * coupling.normal[i][1]],
                        tangent: [-c * coupling.tangent[i][0], -c * coupling.tangent[i][1]],
                        transfer: c,
                    };
                    take_out_prescribed(prescribed(j), &mut node.normal, &mut node.tangent, &mut gap);
                    node
                })
                .collect();
            let fixed = prescribed(k);
            take_out_prescribed(fixed, &mut n, &mut t, &mut gap);
            // A tangential row left empty (a slave node on the axis, `u_r` prescribed, paired
            // node to segment with the master's axis node, `u_r` prescribed too) keeps the unit
            // tangent on the slave node, as against a rigid obstacle: the point has no friction
            // (a prescribed component), `rT = 0`, and every solver sees a regular problem.
            // (Round-off: the bisector of two axial normals can be 1e-17 off the axis.)
            let tiny = |v: [f64; 2]| v[0].abs() <= 1e-12 && v[1].abs() <= 1e-12;
            if tiny(t) && coupled.iter().all(|c| tiny(c.tangent)) {
                t = coupling.tangent[i];
            }
            let first_fixed = (0..2).find_map(|comp| fixed[comp].map(|u0| (comp, u0)));
            let no_master_entry = coupled.iter().all(|c| c.normal == [0.0; 2] && c.tangent == [0.0; 2]);
            if fixed.iter().all(Option::is_some) && no_master_entry {
                continue;
            }
            b.nodes.push(k);
            b.normal.push(n);
            b.tangent.push(t);
            b.gap.push(gap);
            b.weight.push(coupling.weight[i]);
            b.prescribed.push(first_fixed);
            b.coupled.push(coupled);
            b.frame.push([coupling.normal[i], coupling.tangent[i]]);
        }
        Ok(b)
    }

    /// One boundary with the points of every part, ordered by node (stable: a node in two
    /// parts keeps its parts' order); also the part of each point, in the new order.
    pub fn merge(parts: Vec<ContactBoundary>) -> (ContactBoundary, Vec<usize>) {
        let mut all = ContactBoundary {
            nodes: Vec::new(),
            normal: Vec::new(),
            tangent: Vec::new(),
            gap: Vec::new(),
            weight: Vec::new(),
            edges: Vec::new(),
            prescribed: Vec::new(),
            left_out: Vec::new(),
            coupled: Vec::new(),
            frame: Vec::new(),
            axis_pressure: Vec::new(),
        };
        let any_coupled = parts.iter().any(|p| p.is_coupled());
        let mut part_of = Vec::new();
        for (p, mut b) in parts.into_iter().enumerate() {
            let m = b.points();
            if any_coupled && b.coupled.is_empty() {
                b.coupled = vec![Vec::new(); m];
            }
            all.nodes.extend(b.nodes);
            all.normal.extend(b.normal);
            all.tangent.extend(b.tangent);
            all.gap.extend(b.gap);
            all.weight.extend(b.weight);
            all.edges.extend(b.edges);
            all.prescribed.extend(b.prescribed);
            all.left_out.extend(b.left_out);
            all.coupled.extend(b.coupled);
            all.frame.extend(b.frame);
            all.axis_pressure.extend(b.axis_pressure);
            part_of.extend(std::iter::repeat_n(p, m));
        }
        let mut order: Vec<usize> = (0..all.nodes.len()).collect();
        order.sort_by_key(|&i| all.nodes[i]);
        pick(&mut all.nodes, &order);
        pick(&mut all.normal, &order);
        pick(&mut all.tangent, &order);
        pick(&mut all.gap, &order);
        pick(&mut all.weight, &order);
        pick(&mut all.prescribed, &order);
        pick(&mut all.frame, &order);
        pick(&mut part_of, &order);
        if !all.coupled.is_empty() {
            let old = std::mem::take(&mut all.coupled);
            let mut old: Vec<Option<Vec<CoupledNode>>> = old.into_iter().map(Some).collect();
            all.coupled = order.iter().map(|&i| old[i].take().unwrap_or_default()).collect();
        }
        all.edges.sort_unstable();
        all.edges.dedup();
        (all, part_of)
    }
}

/// A node's prescribed components `fixed` leave its entries in a point's rows (`normal` in
/// `B_N`, `tangent` in `B_T`): the known displacement `u0` moves into the gap, `g −= B_N,c u0`.
fn take_out_prescribed(fixed: [Option<f64>; 2], normal: &mut [f64; 2], tangent: &mut [f64; 2], gap: &mut f64) {
    for (comp, value) in fixed.into_iter().enumerate() {
        if let Some(u0) = value {
            *gap -= normal[comp] * u0;
            normal[comp] = 0.0;
            tangent[comp] = 0.0;
        }
    }
}

/// Reorder `v` so that its `i`-th entry is the old `v[order[i]]`.
fn pick<T: Copy>(v: &mut Vec<T>, order: &[usize]) {
    let old = std::mem::take(v);
    *v = order.iter().map(|&i| old[i]).collect();
}
