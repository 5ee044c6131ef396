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
//! Body `A` overlaps body `B` at a node `p` of `A` when `p` lies in a triangle of `B` (the
//! straight triangle of its three vertices) and its distance to the boundary of `B` (the chords
//! of `B`'s boundary edges) is the overlap depth. [`deepest_overlap`] finds the deepest node of
//! `A` in `B`; candidate triangles come from a uniform grid over `B`'s triangles' bounding boxes.
//! Two meshes may still cross without any node of one inside the other (thin slivers crossing
//! near their tips): this check finds overlaps of the size of a cell, not every crossing.
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

/// A node of one mesh inside another.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// The node (of the first mesh given to [`deepest_overlap`]).
    pub node: usize,
    /// Its coordinates (m).
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

/// Whether `p` lies in the (counter-clockwise) triangle `a b c`, boundary included up to a
/// relative round-off.
fn in_triangle(p: [f64; 2], a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    let cross = |u: [f64; 2], v: [f64; 2], w: [f64; 2]| (v[0] - u[0]) * (w[1] - u[1]) - (v[1] - u[1]) * (w[0] - u[0]);
    let area = cross(a, b, c);
    let slack = -1e-12 * area.abs();
    cross(a, b, p) >= slack && cross(b, c, p) >= slack && cross(c, a, p) >= slack
}

/// The node of `a` deepest inside `b` (see the module documentation), if any lies inside `b`
/// deeper than `tolerance`; among nodes equally deep, the first.
pub fn deepest_overlap(a: &Mesh, b: &Mesh, tolerance: f64) -> Option<Overlap> {
    if a.num_nodes() == 0 || b.num_cells() == 0 {
        return None;
    }
    let vertex = |c: usize, k: usize| b.nodes[b.cell(c)[k]];
    let box_b = bounds((0..b.num_cells()).flat_map(|c| (0..3).map(move |k| vertex(c, k))));
    // A uniform grid of about one triangle per grid cell.
    let n = ((b.num_cells() as f64).sqrt().ceil() as usize).clamp(1, 2048);
    let (w, h) = ((box_b[2] - box_b[0]).max(f64::MIN_POSITIVE), (box_b[3] - box_b[1]).max(f64::MIN_POSITIVE));
    let slot = |x: f64, y: f64| {
        let i = (((x - box_b[0]) / w * n as f64) as usize).min(n - 1);
        let j = (((y - box_b[1]) / h * n as f64) as usize).min(n - 1);
        (i, j)
    };
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); n * n];
    for c in 0..b.num_cells() {
        let bb = bounds((0..3).map(|k| vertex(c, k)));
        let (i0, j0) = slot(bb[0], bb[1]);
        let (i1, j1) = slot(bb[2], bb[3]);
        for j in j0..=j1 {
            for i in i0..=i1 {
                grid[j * n + i].push(c);
            }
        }
    }
    let mut deepest: Option<Overlap> = None;
    for (node, &p) in a.nodes.iter().enumerate() {
        if p[0] < box_b[0] || p[0] > box_b[2] || p[1] < box_b[1] || p[1] > box_b[3] {
            continue;
        }
        let (i, j) = slot(p[0], p[1]);
        let inside = grid[j * n + i].iter().any(|&c| in_triangle(p, vertex(c, 0), vertex(c, 1), vertex(c, 2)));
        if !inside {
            continue;
        }
        let depth = (0..b.num_edges())
            .map(|e| {
                let edge = b.edge(e);
                segment_distance(p, b.nodes[edge[0]], b.nodes[edge[1]])
            })
            .fold(f64::INFINITY, f64::min);
        if depth > tolerance && deepest.is_none_or(|d| depth > d.depth) {
            deepest = Some(Overlap { node, position: p, depth });
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
        assert_eq!(o.position, [0.5, 0.6]);
        assert!((o.depth - 0.4).abs() < 1e-12, "{o:?}");
        assert_eq!(deepest_overlap(&c, &a, 0.5), None);
    }
}
