//! Several bodies in one mesh: the disjoint union of their meshes, and the search for bodies
//! that overlap.
//!
//! # The union
//!
//! Body `b` (in the given order) keeps its nodes, triangles and boundary edges, shifted by the
//! counts of the bodies before it:
//!
//! ```text
//!   node   k of body b  ->  nodes.start(b) + k,      dofs 2 node, 2 node + 1 (x, y)
//!   cell   c of body b  ->  cells.start(b) + c,      edge e -> edges.start(b) + e
//!   group  "part" of b  ->  "b.part" (same dimension), tags renumbered 1, 2, ... in order
//! ```
//!
//! so node, cell, edge and dof ranges of a body are contiguous ([`BodyRange`]), and
//! [`BodyLayout::cell_body`] gives the body of every triangle (to look up its material). No
//! node is shared: the bodies are coupled only by their contact pairs. All bodies must have the
//! same [`Order`](super::Order) (a [`Mesh`] has one).
//!
//! # Overlap
//!
//! Body `A` overlaps body `B` where a point of `A`'s boundary lies inside `B`; the overlap
//! depth there is its distance to the boundary of `B` (the chords of `B`'s boundary edges).
//! [`deepest_overlap`] measures two kinds of points and returns the deepest:
//!
//! ```text
//!   nodes:   every node p of A in a triangle of B (the straight triangle of its vertices)
//!   edges:   every boundary chord p0 p1 of A that crosses a chord of B's boundary, cut at the
//!            crossings t1 < t2 < ... into pieces; a piece whose middle m is in B is measured
//!            at m
//!
//!            A's chord  p0 ----x====m====x---- p1        x: crossings, m inside B
//!                              |         |
//!                              |    B    |               (two bars crossing like a plus sign,
//!                              |         |                no node of one inside the other)
//! ```
//!
//! A crossing is a chord of `B` whose line has `p0` and `p1` strictly on either side, and which
//! has its own end points not strictly on one side of `p0 p1`: sides that only touch (collinear
//! chords, a vertex on the other side) are not cut, and a piece along `B`'s boundary measures
//! 0. Every point of `∂A ∩ B` is on a piece, or a node: two meshes that overlap have a node
//! or a piece of edge of one inside the other, whatever their cell sizes. The middle of a piece
//! is where a chord crossing `B` is deepest when `B` is locally a strip (a bar), a lower bound
//! otherwise; for a piece ending at a node, the node is measured too.
//!
//! Cost: the triangles and the boundary chords of `B` are put in uniform grids (about one
//! triangle, one chord per bucket); a point finds its triangle in its bucket, a chord of `A`
//! meets the chords of `B` in the buckets its box covers, and a distance to `B`'s boundary
//! searches rings of buckets around the point until they are farther than the nearest chord
//! found. Two meshes of 40 004 boundary edges and 80 000 triangles each, touching along a side
//! of 20 000 edges, are checked both ways in 0.28 s (release build).
use super::{Mesh, PhysicalGroup};
use crate::error::{Error, Result};
use std::ops::Range;

/// Where one body is in the union mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BodyRange {
    /// The body's name.
    pub name: String,
    /// Its nodes in the union.
    pub nodes: Range<usize>,
    /// Its triangles in the union.
    pub cells: Range<usize>,
    /// Its boundary edges in the union.
    pub edges: Range<usize>,
    /// Its groups (renamed `name.part`) in the union's `groups`.
    pub groups: Range<usize>,
}

impl BodyRange {
    /// Its displacement unknowns: `2 node` (x) and `2 node + 1` (y) for its nodes.
    pub fn dofs(&self) -> Range<usize> {
        2 * self.nodes.start..2 * self.nodes.end
    }
}

/// The bodies of a union mesh.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BodyLayout {
    /// Each body's ranges, in scene order.
    pub bodies: Vec<BodyRange>,
    /// The body (index into `bodies`) of every triangle of the union.
    pub cell_body: Vec<usize>,
}

impl BodyLayout {
    /// The index of the body named `name`.
    pub fn index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
    /// The body of a node of the union.
    pub fn node_body(&self, node: usize) -> Option<usize> {
        self.bodies.iter().position(|b| b.nodes.contains(&node))
    }
}

/// The disjoint union of `bodies` (name, mesh), see the module documentation. An error if the
/// meshes have different orders or there are none.
pub fn disjoint_union(bodies: &[(&str, &Mesh)]) -> Result<(Mesh, BodyLayout)> {
    let Some((_, first)) = bodies.first() else {
        return Err(Error::mesh("union of bodies", "no bodies"));
    };
    let order = first.order;
    let mut union = Mesh {
        order,
        nodes: Vec::new(),
        cells: Vec::new(),
        cell_group: Vec::new(),
        edges: Vec::new(),
        edge_group: Vec::new(),
        groups: Vec::new(),
        measure: first.measure,
    };
    let mut layout = BodyLayout { bodies: Vec::with_capacity(bodies.len()), cell_body: Vec::new() };
    for (index, (name, mesh)) in bodies.iter().enumerate() {
        if mesh.order != order {
            return Err(Error::mesh(
                format!("body `{name}`"),
                format!(
                    "its triangles are of order {}, the first body's of order {}: the bodies of one mesh need the same order",
                    mesh.order.degree(),
                    order.degree()
                ),
            ));
        }
        let (node0, cell0, edge0, group0) =
            (union.num_nodes(), union.num_cells(), union.num_edges(), union.groups.len());
        union.nodes.extend_from_slice(&mesh.nodes);
        union.cells.extend(mesh.cells.iter().map(|&k| k + node0));
        union.edges.extend(mesh.edges.iter().map(|&k| k + node0));
        let shift = |g: usize| if g == super::NO_GROUP { g } else { g + group0 };
        union.cell_group.extend(mesh.cell_group.iter().map(|&g| shift(g)));
        union.edge_group.extend(mesh.edge_group.iter().map(|&g| shift(g)));
        union.groups.extend(mesh.groups.iter().enumerate().map(|(k, g)| PhysicalGroup {
            name: format!("{name}.{}", g.name),
            tag: i32::try_from(group0 + k + 1).unwrap_or(i32::MAX),
            dim: g.dim,
        }));
        layout.cell_body.extend(std::iter::repeat_n(index, mesh.num_cells()));
        layout.bodies.push(BodyRange {
            name: name.to_string(),
            nodes: node0..union.num_nodes(),
            cells: cell0..union.num_cells(),
            edges: edge0..union.num_edges(),
            groups: group0..union.groups.len(),
        });
    }
    Ok((union, layout))
}

/// What lies inside the other mesh: a node, or a piece of a boundary edge between two crossings
/// of the two boundaries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OverlapWitness {
    /// A node of the first mesh given to [`deepest_overlap`].
    Node(usize),
    /// A piece of boundary edge `edge` (its chord) of the first mesh, whose chord crosses the
    /// other mesh's boundary at `crossing`.
    Edge {
        /// The boundary edge (its index among the first mesh's edges).
        edge: usize,
        /// Where its chord crosses the other mesh's boundary (m).
        crossing: [f64; 2],
    },
}

/// A point of one mesh inside another, and how deep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// What is inside: a node, or a piece of a boundary edge.
    pub witness: OverlapWitness,
    /// The point (m): the node, or the middle of the piece of edge inside the other mesh.
    pub position: [f64; 2],
    /// Its distance to the boundary of the other mesh.
    pub depth: f64,
}

/// Bounding box `[xmin, ymin, xmax, ymax]` of points.
fn bounds(points: impl Iterator<Item = [f64; 2]>) -> [f64; 4] {
    points.fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |b, p| {
        [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])]
    })
}

/// Distance from `p` to the segment `a b`.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let length2 = dx * dx + dy * dy;
    let t = if length2 > 0.0 { (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

/// `(v − u) × (w − u)`: twice the signed area of `u v w` (positive counter-clockwise).
fn orientation(u: [f64; 2], v: [f64; 2], w: [f64; 2]) -> f64 {
    (v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0])
}

/// Whether `p` lies in the (counter-clockwise) triangle `a b c`, boundary included up to a
/// relative round-off.
fn in_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    let area = orientation(a, b, c);
    let slack = -1e-12 * area.abs();
    orientation(a, b, p) >= slack && orientation(b, c, p) >= slack && orientation(c, a, p) >= slack
}

/// A uniform grid of buckets over a box: items are put in every bucket their bounding box meets.
struct Grid {
    origin: [f64; 2],
    cell: f64,
    size: [usize; 2],
    buckets: Vec<Vec<usize>>,
}

impl Grid {
    /// A grid over `area` of about `target` square buckets (at least 1, at most 4·10⁶).
    fn new(area: [f64; 4], target: usize) -> Grid {
        let (w, h) = ((area[2] - area[0]).max(0.0), (area[3] - area[1]).max(0.0));
        let target = target.clamp(1, 4_000_000) as f64;
        let mut cell = (w * h / target).sqrt();
        if cell.is_nan() || cell <= 0.0 {
            cell = (w.max(h) / target).max(f64::MIN_POSITIVE);
        }
        let count = |l: f64| ((l / cell).floor() as usize + 1).min(4_000_000);
        let size = [count(w), count(h)];
        Grid { origin: [area[0], area[1]], cell, size, buckets: vec![Vec::new(); size[0] * size[1]] }
    }
    /// The bucket coordinates of `p`, clamped to the grid.
    fn slot(&self, p: [f64; 2]) -> [usize; 2] {
        let at = |c: usize| {
            let i = ((p[c] - self.origin[c]) / self.cell).floor();
            if i.is_nan() || i < 0.0 {
                0
            } else {
                (i as usize).min(self.size[c] - 1)
            }
        };
        [at(0), at(1)]
    }
    /// The buckets a box meets.
    fn range(&self, b: [f64; 4]) -> impl Iterator<Item = usize> + '_ {
        let (lo, hi) = (self.slot([b[0], b[1]]), self.slot([b[2], b[3]]));
        (lo[1]..=hi[1]).flat_map(move |j| (lo[0]..=hi[0]).map(move |i| j * self.size[0] + i))
    }
    fn insert(&mut self, item: usize, b: [f64; 4]) {
        let slots: Vec<usize> = self.range(b).collect();
        for s in slots {
            self.buckets[s].push(item);
        }
    }
}

/// The triangles and the boundary chords of a mesh, in grids: which triangles may hold a
/// point, which chords may cross a segment, the distance of a point to the boundary.
struct MeshIndex<'a> {
    mesh: &'a Mesh,
    area: [f64; 4],
    triangles: Grid,
    /// Boundary edge `e`'s chord (its two vertices).
    chords: Vec<[[f64; 2]; 2]>,
    chord_grid: Grid,
}

impl<'a> MeshIndex<'a> {
    fn new(mesh: &'a Mesh) -> MeshIndex<'a> {
        let vertex = |c: usize, k: usize| mesh.nodes[mesh.cell(c)[k]];
        let chords: Vec<[[f64; 2]; 2]> = (0..mesh.num_edges())
            .map(|e| {
                let edge = mesh.edge(e);
                [mesh.nodes[edge[0]], mesh.nodes[edge[1]]]
            })
            .collect();
        let area = bounds(
            (0..mesh.num_cells())
                .flat_map(|c| (0..3).map(move |k| vertex(c, k)))
                .chain(chords.iter().flatten().copied()),
        );
        // About one triangle per bucket; the chords: about as many buckets as chords, a chord
        // in the buckets its box meets.
        let mut triangles = Grid::new(area, mesh.num_cells());
        for c in 0..mesh.num_cells() {
            triangles.insert(c, bounds((0..3).map(|k| vertex(c, k))));
        }
        let mut chord_grid = Grid::new(area, chords.len());
        for (e, chord) in chords.iter().enumerate() {
            chord_grid.insert(e, bounds(chord.iter().copied()));
        }
        MeshIndex { mesh, area, triangles, chords, chord_grid }
    }

    fn in_box(&self, p: [f64; 2]) -> bool {
        p[0] >= self.area[0] && p[0] <= self.area[2] && p[1] >= self.area[1] && p[1] <= self.area[3]
    }

    /// Whether `p` lies in a triangle of the mesh (the straight triangle of its vertices).
    fn contains(&self, p: [f64; 2]) -> bool {
        if !self.in_box(p) {
            return false;
        }
        let [i, j] = self.triangles.slot(p);
        let vertex = |c: usize, k: usize| self.mesh.nodes[self.mesh.cell(c)[k]];
        self.triangles.buckets[j * self.triangles.size[0] + i]
            .iter()
            .any(|&c| in_triangle(p, vertex(c, 0), vertex(c, 1), vertex(c, 2)))
    }

    /// The distance from `p` (in the grid's box) to the nearest boundary chord: the buckets in
    /// growing square rings around `p` until the rings are farther than the nearest chord
    /// found.
    fn boundary_distance(&self, p: [f64; 2]) -> f64 {
        let g = &self.chord_grid;
        let [i0, j0] = g.slot(p);
        let mut best = f64::INFINITY;
        let rings = g.size[0].max(g.size[1]);
        for r in 0..=rings {
            let (i_lo, i_hi) = (i0 as isize - r as isize, i0 as isize + r as isize);
            let (j_lo, j_hi) = (j0 as isize - r as isize, j0 as isize + r as isize);
            for j in j_lo..=j_hi {
                if j < 0 || j >= g.size[1] as isize {
                    continue;
                }
                let on_edge = j == j_lo || j == j_hi;
                let step = if on_edge { 1 } else { (i_hi - i_lo).max(1) as usize };
                for i in (i_lo..=i_hi).step_by(step) {
                    if i < 0 || i >= g.size[0] as isize {
                        continue;
                    }
                    for &e in &g.buckets[j as usize * g.size[0] + i as usize] {
                        best = best.min(segment_distance(p, self.chords[e][0], self.chords[e][1]));
                    }
                }
            }
            // A chord in none of rings 0..=r lies in buckets of ring r + 1 or beyond, at least
            // r buckets away from `p`'s.
            if best <= r as f64 * g.cell {
                break;
            }
        }
        best
    }

    /// The parameters `t ∈ (0, 1)` where the segment `a b` crosses a boundary chord of the mesh
    /// (its end points strictly on both sides of the chord's line, the chord's end points not
    /// strictly on one side of the segment's), sorted.
    fn crossings(&self, a: [f64; 2], b: [f64; 2], seen: &mut [usize], stamp: usize) -> Vec<f64> {
        let mut out = Vec::new();
        let slots: Vec<usize> = self.chord_grid.range(bounds([a, b].into_iter())).collect();
        for s in slots {
            for &e in &self.chord_grid.buckets[s] {
                if seen[e] == stamp {
                    continue;
                }
                seen[e] = stamp;
                let [q0, q1] = self.chords[e];
                let (d0, d1) = (orientation(q0, q1, a), orientation(q0, q1, b));
                if !((d0 < 0.0 && d1 > 0.0) || (d0 > 0.0 && d1 < 0.0)) {
                    continue;
                }
                let (e0, e1) = (orientation(a, b, q0), orientation(a, b, q1));
                if (e0 < 0.0 && e1 < 0.0) || (e0 > 0.0 && e1 > 0.0) {
                    continue;
                }
                out.push(d0 / (d0 - d1));
            }
        }
        out.sort_by(f64::total_cmp);
        out
    }
}

/// The deepest point of `a` inside `b` (see the module documentation), if one lies deeper than
/// `tolerance`: a node of `a` inside a triangle of `b`, or the middle of a piece of a boundary
/// chord of `a` between two points where it crosses `b`'s boundary, that lies inside `b`;
/// depths are distances to `b`'s boundary chords. Among points equally deep, nodes first, then
/// the first found.
pub fn deepest_overlap(a: &Mesh, b: &Mesh, tolerance: f64) -> Option<Overlap> {
    if a.num_nodes() == 0 || b.num_cells() == 0 {
        return None;
    }
    let index = MeshIndex::new(b);
    let mut deepest: Option<Overlap> = None;
    let mut keep = |o: Overlap| {
        if o.depth > tolerance && deepest.is_none_or(|d| o.depth > d.depth) {
            deepest = Some(o);
        }
    };
    for (node, &p) in a.nodes.iter().enumerate() {
        if index.contains(p) {
            keep(Overlap { witness: OverlapWitness::Node(node), position: p, depth: index.boundary_distance(p) });
        }
    }
    // Boundary chords of `a` that cross `b`'s boundary: each piece between two crossings (or a
    // crossing and an end) is inside `b` or outside; a piece inside is measured at its middle.
    let mut seen = vec![usize::MAX; index.chords.len()];
    for e in 0..a.num_edges() {
        let edge = a.edge(e);
        let (p0, p1) = (a.nodes[edge[0]], a.nodes[edge[1]]);
        let chord_box = bounds([p0, p1].into_iter());
        if chord_box[2] < index.area[0]
            || chord_box[0] > index.area[2]
            || chord_box[3] < index.area[1]
            || chord_box[1] > index.area[3]
        {
            continue;
        }
        let cuts = index.crossings(p0, p1, &mut seen, e);
        if cuts.is_empty() {
            continue;
        }
        let at = |t: f64| [p0[0] + t * (p1[0] - p0[0]), p0[1] + t * (p1[1] - p0[1])];
        let mut ends = vec![0.0];
        ends.extend(&cuts);
        ends.push(1.0);
        for (k, w) in ends.windows(2).enumerate() {
            let middle = at(0.5 * (w[0] + w[1]));
            if w[1] > w[0] && index.contains(middle) {
                // The crossing that bounds the piece (the one before it, or after the first piece).
                let crossing = at(if k == 0 { w[1] } else { w[0] });
                keep(Overlap {
                    witness: OverlapWitness::Edge { edge: e, crossing },
                    position: middle,
                    depth: index.boundary_distance(middle),
                });
            }
        }
    }
    deepest
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{structured, Order};

    #[test]
    fn union_shifts_indices_and_renames_groups() {
        let a = structured::rectangle([0.0, 0.0], [1.0, 1.0], 2, 2, Order::P1).unwrap();
        let b = structured::rectangle([0.0, 1.0], [1.0, 1.0], 1, 1, Order::P1).unwrap();
        let (mut u, layout) = disjoint_union(&[("a", &a), ("b", &b)]).unwrap();
        assert_eq!(u.num_nodes(), a.num_nodes() + b.num_nodes());
        assert_eq!(u.num_cells(), 8 + 2);
        assert_eq!(layout.bodies[1].nodes, 9..13);
        assert_eq!(layout.bodies[1].dofs(), 18..26);
        assert_eq!(u.cell(8), &b.cell(0).iter().map(|k| k + 9).collect::<Vec<_>>()[..]);
        assert_eq!(layout.cell_body[7..9], [0, 1]);
        let top_of_b = u.group_index("b.top", 1).unwrap();
        assert!(layout.bodies[1].groups.contains(&top_of_b));
        assert_eq!(u.edges_in_group(top_of_b).count(), 1);
        u.validate().unwrap();
    }

    #[test]
    fn touching_blocks_do_not_overlap_and_shifted_ones_do() {
        let a = structured::rectangle([0.0, 0.0], [1.0, 1.0], 4, 4, Order::P1).unwrap();
        let b = structured::rectangle([0.0, 1.0], [1.0, 1.0], 3, 3, Order::P1).unwrap();
        assert_eq!(deepest_overlap(&a, &b, 1e-12), None);
        assert_eq!(deepest_overlap(&b, &a, 1e-12), None);
        let c = structured::rectangle([0.5, 0.6], [1.0, 1.0], 2, 2, Order::P1).unwrap();
        let o = deepest_overlap(&c, &a, 1e-12).unwrap();
        assert_eq!((o.witness, o.position), (OverlapWitness::Node(0), [0.5, 0.6]));
        assert!((o.depth - 0.4).abs() < 1e-12, "{o:?}");
        assert_eq!(deepest_overlap(&c, &a, 0.5), None);
    }

    /// Two bars of width 0.1 crossing like a plus sign, 2 cells along each: no node of one is
    /// inside the other (the nodes are at −1, 0.1, 1.2 along the bars, and −0.45, 0.65 for
    /// P2), only their sides cross.
    fn plus_sign(order: Order) -> (Mesh, Mesh) {
        let across = structured::rectangle([-1.0, -0.05], [2.2, 0.1], 2, 1, order).unwrap();
        let up = structured::rectangle([-0.05, -1.0], [0.1, 2.2], 1, 2, order).unwrap();
        (across, up)
    }

    #[test]
    fn bars_crossing_without_a_node_inside_overlap_by_their_half_width() {
        for order in [Order::P1, Order::P2] {
            let (across, up) = plus_sign(order);
            for (a, b) in [(&across, &up), (&up, &across)] {
                // No node of one bar is in the other: only the edges see the overlap.
                let index = MeshIndex::new(b);
                assert!(a.nodes.iter().all(|&p| !index.contains(p)), "{order:?}");
                let o = deepest_overlap(a, b, 1e-12).unwrap_or_else(|| panic!("{order:?}: not found"));
                // The middle of a side of one bar inside the other: 0.05 from its sides.
                assert!((o.depth - 0.05).abs() < 1e-12, "{order:?}: {o:?}");
                assert!(o.position[0].abs().max(o.position[1].abs()) <= 0.05 + 1e-12, "{o:?}");
                let OverlapWitness::Edge { crossing, .. } = o.witness else { panic!("{o:?}") };
                assert!((crossing[0].abs() - 0.05).abs() < 1e-12 && (crossing[1].abs() - 0.05).abs() < 1e-12);
                assert_eq!(deepest_overlap(a, b, 0.06), None);
            }
        }
    }

    #[test]
    fn touching_meshes_with_different_cells_do_not_overlap() {
        for order in [Order::P1, Order::P2] {
            // Side by side (nodes of one on the other's side between its nodes), on top, and at
            // a corner only.
            let a = structured::rectangle([0.0, 0.0], [1.0, 1.0], 3, 7, order).unwrap();
            for (origin, size, n) in [
                ([1.0, -0.3], [0.5, 1.7], (2, 5)),
                ([0.2, 1.0], [0.5, 0.5], (4, 4)),
                ([1.0, 1.0], [1.0, 1.0], (1, 1)),
                ([-0.5, -2.0], [3.0, 2.0], (5, 3)),
            ] {
                let b = structured::rectangle(origin, size, n.0, n.1, order).unwrap();
                assert_eq!(deepest_overlap(&a, &b, 1e-12), None, "{order:?} {origin:?}");
                assert_eq!(deepest_overlap(&b, &a, 1e-12), None, "{order:?} {origin:?}");
            }
            // The same, 1e-3 into it: the node or the edge crossing sees it.
            let b = structured::rectangle([0.999, -0.3], [0.5, 1.7], 2, 5, order).unwrap();
            for o in [deepest_overlap(&a, &b, 1e-6).unwrap(), deepest_overlap(&b, &a, 1e-6).unwrap()] {
                assert!((o.depth - 1e-3).abs() < 1e-12, "{o:?}");
            }
        }
    }

    #[test]
    fn a_chord_through_a_vertex_is_cut_there() {
        // The across bar's top side passes exactly through the corner vertices of a square
        // rotated by 45 degrees (a diamond) whose vertices are at (±0.3, 0.05) and (0, 0.05 ± 0.3).
        let across = structured::rectangle([-1.0, -0.05], [2.0, 0.1], 1, 1, Order::P1).unwrap();
        let mut diamond = structured::rectangle([0.0, 0.0], [1.0, 1.0], 1, 1, Order::P1).unwrap();
        let (s, c) = std::f64::consts::FRAC_PI_4.sin_cos();
        for p in &mut diamond.nodes {
            let [x, y] = [p[0] - 0.5, p[1] - 0.5];
            let r = 0.3 / 0.5_f64.hypot(0.5);
            *p = [r * (c * x - s * y), 0.05 + r * (s * x + c * y)];
        }
        let o = deepest_overlap(&across, &diamond, 1e-9).unwrap();
        // The side from (−0.3, 0.05) to (0.3, 0.05) runs through the diamond's middle: 0.3/√2 deep.
        assert!((o.depth - 0.3 / 2f64.sqrt()).abs() < 1e-12, "{o:?}");
    }

    #[test]
    fn long_sides_are_checked_through_the_grids() {
        // Two combs of 2 x 20 000 cells touching along a side of 20 000 edges each, with offset
        // nodes: no overlap; moved 1e-4 into each other: found, at the right depth. (Measured
        // in release: 0.28 s for the two ways, 40 004 boundary edges per mesh.)
        let n = 20_000;
        let a = structured::rectangle([0.0, 0.0], [1.0, 0.01], n, 2, Order::P1).unwrap();
        let b = structured::rectangle([0.3 / n as f64, 0.01], [1.0, 0.01], n, 2, Order::P1).unwrap();
        let start = std::time::Instant::now();
        assert_eq!(deepest_overlap(&a, &b, 1e-12), None);
        assert_eq!(deepest_overlap(&b, &a, 1e-12), None);
        eprintln!("two sides of {n} edges: {:.3} s", start.elapsed().as_secs_f64());
        let c = structured::rectangle([0.3 / n as f64, 0.01 - 1e-4], [1.0, 0.01], n, 2, Order::P1).unwrap();
        let o = deepest_overlap(&c, &a, 1e-6).unwrap();
        assert!((o.depth - 1e-4).abs() < 1e-12, "{o:?}");
    }
}
