//! Mesh checks ([`Mesh::validate`]) and the P1 -> P2 conversion ([`Mesh::to_quadratic`]).
//!
//! # Orientation and degeneracy
//!
//! The signed area of a triangle with vertices `a, b, c` is
//!
//! ```text
//!   A = ((b - a) x (c - a)) / 2 = ((bx - ax)(cy - ay) - (by - ay)(cx - ax)) / 2
//! ```
//!
//! positive when `a -> b -> c` turns counter-clockwise. A triangle is degenerate when
//! `|A| <= 1e-12 * l_max^2`, `l_max` its longest side: the test is invariant under scaling of
//! the mesh. If every triangle is clockwise the whole mesh is mirrored in its numbering and we
//! flip all of them; a mix of both orientations means folded or overlapping cells and is an
//! error.
//!
//! Flipping swaps vertices 1 and 2; for P2 the mid nodes follow their sides:
//!
//! ```text
//!   2                        1
//!   |\                       |\
//!   5  4       flip ->       3  4       (v0, v1, v2, m01, m12, m20)
//!   |    \                   |    \       -> (v0, v2, v1, m20, m12, m01)
//!   0--3--1                  0--5--2
//! ```
//!
//! # P2 geometry
//!
//! A P2 triangle is the image of the reference triangle `{xi, eta >= 0, xi + eta <= 1}` under
//! `x(xi, eta) = sum_i N_i(xi, eta) x_i` with the quadratic Lagrange functions in barycentric
//! coordinates `l0 = 1 - xi - eta`, `l1 = xi`, `l2 = eta`:
//!
//! ```text
//!   N0 = l0 (2 l0 - 1)   N1 = l1 (2 l1 - 1)   N2 = l2 (2 l2 - 1)
//!   N3 = 4 l0 l1         N4 = 4 l1 l2         N5 = 4 l2 l0
//! ```
//!
//! (Zienkiewicz, Taylor & Zhu, *The Finite Element Method: Its Basis and Fundamentals*, 7th ed.,
//! §6.5 and §6.6 on isoparametric maps). The map is admissible only where
//! `det J = x_xi y_eta - x_eta y_xi > 0`. `det J` is a quadratic polynomial on the reference
//! triangle; we sample it at the three vertices and the centroid, which catches mid nodes pushed
//! past the opposite side or beyond an adjacent vertex. It is a necessary check, not a proof of
//! validity everywhere (for that see Johnen, Remacle & Geuzaine, "Geometrical validity of
//! curvilinear finite elements", J. Comput. Phys. 233, 2013).
//!
//! # Edge numbering
//!
//! Boundary checks and the P2 conversion need the unique undirected edges of the triangles. We
//! number them without hashing, in one pass over the `3 T` triangle sides: each vertex keeps a
//! linked list of the edges for which it is the smaller end; a side `{a, b}` looks for
//! `max(a, b)` in the (short: a handful of entries) list of `min(a, b)` and creates the edge if
//! it is absent. Edges are numbered in the order the triangles first meet them, so a mesh with
//! local triangle numbering gets local mid-node numbers in `to_quadratic`.
//!
//! Side `k` of a triangle `(v0, v1, v2)` runs from `v_k` to `v_{k+1 mod 3}`; its P2 mid node is
//! node `3 + k` of the cell. In a counter-clockwise triangle the cell lies on the left of each
//! side so directed, which is how boundary edges must run.
use super::{Mesh, Order, NO_GROUP};
use crate::error::{Error, Result};

/// Integer type of the [`EdgeTable`] arrays: `u32` halves the memory traffic (the table build
/// is the costliest step of `validate`), `usize` serves meshes beyond its range.
pub(crate) trait EdgeIndex: Copy + Eq {
    const NONE: Self;
    fn from_usize(i: usize) -> Self;
    fn to_usize(self) -> usize;
}

impl EdgeIndex for u32 {
    const NONE: Self = u32::MAX;
    fn from_usize(i: usize) -> Self {
        i as u32
    }
    fn to_usize(self) -> usize {
        self as usize
    }
}

impl EdgeIndex for usize {
    const NONE: Self = usize::MAX;
    fn from_usize(i: usize) -> Self {
        i
    }
    fn to_usize(self) -> usize {
        self
    }
}

/// Unique undirected edges between triangle vertices.
pub(crate) struct EdgeTable<I: EdgeIndex> {
    /// Most recently created edge having each vertex as its smaller end (`NONE` if none); the
    /// other edges of that vertex follow through `link[e].1`.
    head: Vec<I>,
    /// (larger end vertex, next edge of the same smaller vertex) of each edge.
    link: Vec<(I, I)>,
    /// The first triangle side (`3 * cell + k`) found on each edge.
    first_side: Vec<I>,
    /// Edge of each triangle side `3 * cell + k`.
    side_edge: Vec<I>,
    npc: usize,
}

impl EdgeTable<u32> {
    /// Whether node and side numbers of `mesh` fit in `u32` (below its `NONE` marker).
    pub fn fits(mesh: &Mesh) -> bool {
        let limit = u32::MAX as usize;
        mesh.num_nodes() < limit && mesh.num_cells() < limit / 3
    }
}

impl<I: EdgeIndex> EdgeTable<I> {
    /// Build the table. The caller guarantees that every vertex index is below `num_nodes` and
    /// that node and side numbers fit in `I` (see [`EdgeTable::fits`]).
    pub fn new(mesh: &Mesh) -> Self {
        let npc = mesh.order.nodes_per_cell();
        let nt = mesh.num_cells();
        let mut table = EdgeTable {
            head: vec![I::NONE; mesh.num_nodes()],
            link: Vec::with_capacity(3 * nt / 2 + 16),
            first_side: Vec::with_capacity(3 * nt / 2 + 16),
            side_edge: Vec::with_capacity(3 * nt),
            npc,
        };
        for (c, cell) in mesh.cells.chunks_exact(npc).enumerate() {
            for k in 0..3 {
                let (a, b) = (cell[k], cell[(k + 1) % 3]);
                let (lo, hi) = (a.min(b), I::from_usize(a.max(b)));
                let e = match table.find_from(lo, hi) {
                    Some(e) => e,
                    None => {
                        let e = I::from_usize(table.link.len());
                        table.link.push((hi, table.head[lo]));
                        table.first_side.push(I::from_usize(3 * c + k));
                        table.head[lo] = e;
                        e
                    }
                };
                table.side_edge.push(e);
            }
        }
        table
    }

    fn find_from(&self, lo: usize, hi: I) -> Option<I> {
        let mut e = *self.head.get(lo)?;
        while e != I::NONE {
            let (other, next) = self.link[e.to_usize()];
            if other == hi {
                return Some(e);
            }
            e = next;
        }
        None
    }

    pub fn num_edges(&self) -> usize {
        self.link.len()
    }

    /// Number of triangle sides (three per triangle).
    pub fn num_sides(&self) -> usize {
        self.side_edge.len()
    }

    /// The edge of triangle side `s = 3 * cell + k`.
    pub fn side_edge(&self, s: usize) -> usize {
        self.side_edge[s].to_usize()
    }

    /// The first triangle side found on edge `e`.
    pub fn first_side(&self, e: usize) -> usize {
        self.first_side[e].to_usize()
    }

    /// The edge joining vertices `a` and `b`, if some triangle has that side.
    pub fn find(&self, a: usize, b: usize) -> Option<usize> {
        let hi = a.max(b);
        if hi >= self.head.len() {
            return None;
        }
        self.find_from(a.min(b), I::from_usize(hi)).map(I::to_usize)
    }

    /// The two end vertices of edge `e` (smaller first), given the cells the table was built from.
    pub fn vertices(&self, cells: &[usize], e: usize) -> (usize, usize) {
        let s = self.first_side(e);
        let (c, k) = (s / 3, s % 3);
        let (a, b) = (cells[c * self.npc + k], cells[c * self.npc + (k + 1) % 3]);
        (a.min(b), a.max(b))
    }
}

/// Signed area of triangle `a, b, c` (positive counter-clockwise).
fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

/// `det J` of the P2 isoparametric map at reference point `(xi, eta)`.
fn p2_jacobian_det(x: &[[f64; 2]; 6], xi: f64, eta: f64) -> f64 {
    let (l0, l1, l2) = (1.0 - xi - eta, xi, eta);
    let d_xi = [-(4.0 * l0 - 1.0), 4.0 * l1 - 1.0, 0.0, 4.0 * (l0 - l1), 4.0 * l2, -4.0 * l2];
    let d_eta = [-(4.0 * l0 - 1.0), 0.0, 4.0 * l2 - 1.0, -4.0 * l1, 4.0 * l1, 4.0 * (l0 - l2)];
    let (mut x_xi, mut y_xi, mut x_eta, mut y_eta) = (0.0, 0.0, 0.0, 0.0);
    for i in 0..6 {
        x_xi += d_xi[i] * x[i][0];
        y_xi += d_xi[i] * x[i][1];
        x_eta += d_eta[i] * x[i][0];
        y_eta += d_eta[i] * x[i][1];
    }
    x_xi * y_eta - x_eta * y_xi
}

fn fmt_point(p: [f64; 2]) -> String {
    format!("({}, {})", p[0], p[1])
}

impl Mesh {
    fn describe_cell(&self, c: usize) -> String {
        let v = self.cell(c);
        let list: Vec<String> = v.iter().map(|n| n.to_string()).collect();
        format!("triangle {c} (nodes {})", list.join(", "))
    }

    fn describe_node(&self, n: usize) -> String {
        format!("node {n} at {}", fmt_point(self.nodes[n]))
    }

    fn describe_edge(&self, e: usize) -> String {
        let group = match self.groups.get(self.edge_group[e]) {
            Some(g) => format!("'{}'", g.name),
            None => format!("#{}", self.edge_group[e]),
        };
        let list: Vec<String> = self.edge(e).iter().map(|n| n.to_string()).collect();
        format!("boundary edge {e} of group {group} (nodes {})", list.join(", "))
    }

    /// Check the mesh and bring it to the conventions of [`Mesh`]: counter-clockwise triangles,
    /// boundary edges with the domain on their left.
    ///
    /// Fails with [`Error::Mesh`] naming the first offending entity on: inconsistent array
    /// lengths, out-of-range node or group indices, groups of the wrong dimension or defined
    /// twice, non-finite coordinates, degenerate triangles, mixed orientations, a P2 map with a
    /// nonpositive Jacobian (at the vertices or the centroid), a node used by no triangle, a
    /// triangle side shared by more than two triangles, neighbours disagreeing on a P2 mid node,
    /// and boundary edges that are not a side of exactly one triangle, do not carry that side's
    /// mid node, or repeat another edge of the same group. If every triangle is clockwise, all
    /// are flipped (mid nodes permuted accordingly).
    pub fn validate(&mut self) -> Result<()> {
        self.check_structure()?;
        self.check_groups()?;
        self.check_indices_and_coordinates()?;
        self.check_areas_and_orientation()?;
        if self.order == Order::P2 {
            self.check_p2_jacobians()?;
        }
        self.check_node_use()?;
        if EdgeTable::<u32>::fits(self) {
            self.check_edges(&EdgeTable::<u32>::new(self))
        } else {
            self.check_edges(&EdgeTable::<usize>::new(self))
        }
    }

    fn check_structure(&self) -> Result<()> {
        let (npc, npe) = (self.order.nodes_per_cell(), self.order.nodes_per_edge());
        let mesh = || "mesh".to_string();
        if !self.cells.len().is_multiple_of(npc) {
            return Err(Error::mesh(
                mesh(),
                format!(
                    "cell connectivity has {} entries, not a multiple of {npc} ({:?})",
                    self.cells.len(),
                    self.order
                ),
            ));
        }
        if !self.edges.len().is_multiple_of(npe) {
            return Err(Error::mesh(
                mesh(),
                format!(
                    "edge connectivity has {} entries, not a multiple of {npe} ({:?})",
                    self.edges.len(),
                    self.order
                ),
            ));
        }
        if self.num_cells() == 0 {
            return Err(Error::mesh(mesh(), "the mesh has no triangles"));
        }
        if self.cell_group.len() != self.num_cells() {
            return Err(Error::mesh(
                mesh(),
                format!("{} triangles but {} cell group entries", self.num_cells(), self.cell_group.len()),
            ));
        }
        if self.edge_group.len() != self.num_edges() {
            return Err(Error::mesh(
                mesh(),
                format!("{} boundary edges but {} edge group entries", self.num_edges(), self.edge_group.len()),
            ));
        }
        Ok(())
    }

    fn check_groups(&self) -> Result<()> {
        for (i, g) in self.groups.iter().enumerate() {
            if g.dim != 1 && g.dim != 2 {
                return Err(Error::mesh(
                    format!("physical group '{}'", g.name),
                    format!("has dimension {}; only curves (1) and surfaces (2) are used", g.dim),
                ));
            }
            if self.groups[..i].iter().any(|h| h.name == g.name && h.dim == g.dim) {
                return Err(Error::mesh(
                    format!("physical group '{}'", g.name),
                    format!("defined twice with dimension {}; give each group a distinct name", g.dim),
                ));
            }
        }
        for c in 0..self.num_cells() {
            let g = self.cell_group[c];
            if g != NO_GROUP && self.groups.get(g).map(|g| g.dim) != Some(2) {
                let what = match self.groups.get(g) {
                    Some(grp) => format!("group '{}' of dimension {}", grp.name, grp.dim),
                    None => format!("group index {g}, out of range ({} groups)", self.groups.len()),
                };
                return Err(Error::mesh(
                    self.describe_cell(c),
                    format!("belongs to {what}; a triangle's region must be a surface (dimension 2) group"),
                ));
            }
        }
        for e in 0..self.num_edges() {
            let g = self.edge_group[e];
            if self.groups.get(g).map(|g| g.dim) != Some(1) {
                let what = match self.groups.get(g) {
                    Some(grp) => format!("group '{}' of dimension {}", grp.name, grp.dim),
                    None => format!("group index {g}, out of range ({} groups)", self.groups.len()),
                };
                return Err(Error::mesh(
                    self.describe_edge(e),
                    format!("belongs to {what}; a boundary edge must belong to a curve (dimension 1) group"),
                ));
            }
        }
        Ok(())
    }

    fn check_indices_and_coordinates(&self) -> Result<()> {
        let n = self.num_nodes();
        for c in 0..self.num_cells() {
            if let Some(&bad) = self.cell(c).iter().find(|&&v| v >= n) {
                return Err(Error::mesh(
                    self.describe_cell(c),
                    format!("refers to node {bad}, but the mesh has {n} nodes"),
                ));
            }
        }
        for e in 0..self.num_edges() {
            if let Some(&bad) = self.edge(e).iter().find(|&&v| v >= n) {
                return Err(Error::mesh(
                    self.describe_edge(e),
                    format!("refers to node {bad}, but the mesh has {n} nodes"),
                ));
            }
        }
        if let Some(i) = self.nodes.iter().position(|p| !(p[0].is_finite() && p[1].is_finite())) {
            return Err(Error::mesh(self.describe_node(i), "coordinates are not finite numbers"));
        }
        Ok(())
    }

    fn check_areas_and_orientation(&mut self) -> Result<()> {
        let nt = self.num_cells();
        let (mut first_cw, mut first_ccw) = (None, None);
        let mut num_cw = 0usize;
        for c in 0..nt {
            let v = self.cell(c);
            let (a, b, p) = (self.nodes[v[0]], self.nodes[v[1]], self.nodes[v[2]]);
            let area = signed_area(a, b, p);
            let sq = |p: [f64; 2], q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
            let longest2 = sq(a, b).max(sq(b, p)).max(sq(p, a));
            if area.abs() <= 1e-12 * longest2 {
                return Err(Error::mesh(
                    self.describe_cell(c),
                    format!(
                        "degenerate: area {area:e} with longest side {:e} (vertices {}, {}, {}); \
                         remove the sliver or fix coincident/collinear nodes",
                        longest2.sqrt(),
                        fmt_point(a),
                        fmt_point(b),
                        fmt_point(p)
                    ),
                ));
            }
            if area < 0.0 {
                num_cw += 1;
                first_cw.get_or_insert(c);
            } else {
                first_ccw.get_or_insert(c);
            }
        }
        if num_cw == nt {
            let npc = self.order.nodes_per_cell();
            for cell in self.cells.chunks_exact_mut(npc) {
                cell.swap(1, 2);
                if npc == 6 {
                    cell.swap(3, 5);
                }
            }
        } else if num_cw > 0 {
            // Name a triangle of the minority orientation (clockwise on a tie).
            let (c, this, other, n_other) = if 2 * num_cw <= nt {
                (first_cw.unwrap_or(0), "clockwise", "counter-clockwise", nt - num_cw)
            } else {
                (first_ccw.unwrap_or(0), "counter-clockwise", "clockwise", num_cw)
            };
            return Err(Error::mesh(
                self.describe_cell(c),
                format!(
                    "inverted: it is {this} while {n_other} other triangles are {other}; \
                     the mesh folds over itself or mixes orientations"
                ),
            ));
        }
        Ok(())
    }

    fn check_p2_jacobians(&self) -> Result<()> {
        const SAMPLES: [(f64, f64, &str); 4] = [
            (0.0, 0.0, "vertex 0"),
            (1.0, 0.0, "vertex 1"),
            (0.0, 1.0, "vertex 2"),
            (1.0 / 3.0, 1.0 / 3.0, "the centroid"),
        ];
        for c in 0..self.num_cells() {
            let v = self.cell(c);
            let x: [[f64; 2]; 6] = std::array::from_fn(|i| self.nodes[v[i]]);
            for &(xi, eta, at) in &SAMPLES {
                let det = p2_jacobian_det(&x, xi, eta);
                if det.is_nan() || det <= 0.0 {
                    return Err(Error::mesh(
                        self.describe_cell(c),
                        format!(
                            "the quadratic (P2) map is not invertible: Jacobian determinant {det:e} at {at}; \
                             a mid node is too far from its side's midpoint (curved side too bent for the cell size)"
                        ),
                    ));
                }
            }
        }
        Ok(())
    }

    fn check_node_use(&self) -> Result<()> {
        let mut used = vec![false; self.num_nodes()];
        for &v in &self.cells {
            used[v] = true;
        }
        if let Some(i) = used.iter().position(|&u| !u) {
            return Err(Error::mesh(
                self.describe_node(i),
                "no triangle uses this node; remove it (in Gmsh, save only the physical groups) \
                 or fix the connectivity",
            ));
        }
        Ok(())
    }

    fn check_edges<I: EdgeIndex>(&mut self, table: &EdgeTable<I>) -> Result<()> {
        let count = self.check_sides(table)?;
        self.check_and_orient_boundary(table, &count)
    }

    /// Triangle sides: at most two triangles per side; P2 neighbours share the mid node.
    /// Returns the number of triangles on each edge.
    fn check_sides<I: EdgeIndex>(&self, table: &EdgeTable<I>) -> Result<Vec<u8>> {
        let npc = self.order.nodes_per_cell();
        let mut count = vec![0u8; table.num_edges()];
        for s in 0..table.num_sides() {
            let (e, c) = (table.side_edge(s), s / 3);
            let first = table.first_side(e);
            if count[e] == 2 {
                let (a, b) = table.vertices(&self.cells, e);
                return Err(Error::mesh(
                    format!("edge ({a}, {b})"),
                    format!(
                        "is a side of more than two triangles (at least {}, {} and {c}): the mesh is not a \
                         manifold; remove duplicated or overlapping triangles",
                        first / 3,
                        (first / 3 + 1..c).find(|&t| (0..3).any(|k| table.side_edge(3 * t + k) == e)).unwrap_or(c)
                    ),
                ));
            }
            count[e] += 1;
            if self.order == Order::P2 && s != first {
                let m = self.cells[c * npc + 3 + s % 3];
                let m_first = self.cells[(first / 3) * npc + 3 + first % 3];
                if m != m_first {
                    let (a, b) = table.vertices(&self.cells, e);
                    return Err(Error::mesh(
                        self.describe_cell(c),
                        format!(
                            "its side ({a}, {b}) has mid node {m}, but the neighbouring {} has mid node {m_first} \
                             on it; neighbours must share their mid nodes",
                            self.describe_cell(first / 3),
                        ),
                    ));
                }
            }
        }
        Ok(count)
    }

    fn check_and_orient_boundary<I: EdgeIndex>(&mut self, table: &EdgeTable<I>, count: &[u8]) -> Result<()> {
        let npc = self.order.nodes_per_cell();
        let npe = self.order.nodes_per_edge();
        let mut seen: Vec<(usize, usize, usize)> = Vec::with_capacity(self.num_edges());
        for b in 0..self.num_edges() {
            let (v0, v1) = (self.edges[b * npe], self.edges[b * npe + 1]);
            let Some(e) = table.find(v0, v1) else {
                return Err(Error::mesh(
                    self.describe_edge(b),
                    "is not a side of any triangle; boundary edges must lie on the boundary of the meshed region",
                ));
            };
            if count[e] != 1 {
                return Err(Error::mesh(
                    self.describe_edge(b),
                    format!(
                        "is a side of {} triangles, so it is interior; a boundary group must lie on the outer \
                         boundary (split the domain into separate meshes for interfaces)",
                        count[e]
                    ),
                ));
            }
            let s = table.first_side(e);
            let (c, k) = (s / 3, s % 3);
            let cell = &self.cells[c * npc..(c + 1) * npc];
            if self.order == Order::P2 && self.edges[b * npe + 2] != cell[3 + k] {
                return Err(Error::mesh(
                    self.describe_edge(b),
                    format!(
                        "its mid node {} differs from mid node {} of {} on the same side",
                        self.edges[b * npe + 2],
                        cell[3 + k],
                        self.describe_cell(c)
                    ),
                ));
            }
            if v0 != cell[k] {
                self.edges.swap(b * npe, b * npe + 1);
            }
            seen.push((e, self.edge_group[b], b));
        }
        seen.sort_unstable();
        for w in seen.windows(2) {
            if w[0].0 == w[1].0 && w[0].1 == w[1].1 {
                return Err(Error::mesh(
                    self.describe_edge(w[1].2),
                    format!("repeats boundary edge {} of the same group; remove the duplicate", w[0].2),
                ));
            }
        }
        Ok(())
    }

    /// The P2 version of a P1 mesh: a mid node on each straight side, shared by the two
    /// neighbours of an interior side. Vertices keep their numbers; the new nodes follow, one per
    /// edge. A P2 mesh is returned unchanged.
    pub fn to_quadratic(&self) -> Mesh {
        self.to_quadratic_with(|_, p| p)
    }

    /// Like [`Mesh::to_quadratic`], but the mid node of each boundary edge is placed at
    /// `snap(edge_group, midpoint)`, e.g. the projection of the chord midpoint on the curve the
    /// group follows. Snapping can invert cells that are coarse next to a curved boundary: call
    /// [`Mesh::validate`] on the result.
    ///
    /// A boundary edge that is not a side of a triangle gets a mid node of its own.
    ///
    /// # Panics
    /// If a node index is out of range (a mesh that passed `validate` has none).
    pub fn to_quadratic_with(&self, snap: impl Fn(usize, [f64; 2]) -> [f64; 2]) -> Mesh {
        if self.order == Order::P2 {
            return self.clone();
        }
        if EdgeTable::<u32>::fits(self) {
            self.quadratic_from(&EdgeTable::<u32>::new(self), snap)
        } else {
            self.quadratic_from(&EdgeTable::<usize>::new(self), snap)
        }
    }

    fn quadratic_from<I: EdgeIndex>(&self, table: &EdgeTable<I>, snap: impl Fn(usize, [f64; 2]) -> [f64; 2]) -> Mesh {
        let nv = self.num_nodes();
        let ne = table.num_edges();
        let mut nodes = Vec::with_capacity(nv + ne);
        nodes.extend_from_slice(&self.nodes);
        let midpoint = |a: usize, b: usize| {
            let (p, q) = (self.nodes[a], self.nodes[b]);
            [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]
        };
        nodes.extend((0..ne).map(|e| {
            let (a, b) = table.vertices(&self.cells, e);
            midpoint(a, b)
        }));
        let nt = self.num_cells();
        let mut cells = Vec::with_capacity(6 * nt);
        for c in 0..nt {
            let v = &self.cells[3 * c..3 * c + 3];
            cells.extend_from_slice(v);
            for k in 0..3 {
                cells.push(nv + table.side_edge(3 * c + k));
            }
        }
        let mut edges = Vec::with_capacity(3 * self.num_edges());
        for b in 0..self.num_edges() {
            let (v0, v1) = (self.edges[2 * b], self.edges[2 * b + 1]);
            let m = match table.find(v0, v1) {
                Some(e) => nv + e,
                None => {
                    nodes.push(midpoint(v0, v1));
                    nodes.len() - 1
                }
            };
            nodes[m] = snap(self.edge_group[b], midpoint(v0, v1));
            edges.extend_from_slice(&[v0, v1, m]);
        }
        Mesh {
            order: Order::P2,
            nodes,
            cells,
            cell_group: self.cell_group.clone(),
            edges,
            edge_group: self.edge_group.clone(),
            groups: self.groups.clone(),
            measure: self.measure,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_tables_of_both_index_types_agree() {
        let mesh = crate::mesh::structured::rectangle([0.0, 0.0], [1.0, 1.0], 7, 5, Order::P2).unwrap();
        let (small, large) = (EdgeTable::<u32>::new(&mesh), EdgeTable::<usize>::new(&mesh));
        // V + T - 1 edges for a simply connected mesh.
        assert_eq!(small.num_edges(), 8 * 6 + 70 - 1);
        assert_eq!(small.num_edges(), large.num_edges());
        for s in 0..small.num_sides() {
            assert_eq!(small.side_edge(s), large.side_edge(s));
        }
        for e in 0..small.num_edges() {
            let (a, b) = small.vertices(&mesh.cells, e);
            assert_eq!((a, b), large.vertices(&mesh.cells, e));
            assert_eq!(small.find(b, a), Some(e));
            assert_eq!(large.find(a, b), Some(e));
        }
        assert_eq!(small.find(0, mesh.num_nodes()), None);
        let p2 = mesh.clone();
        let mut q = p2.clone();
        q.check_edges(&EdgeTable::<usize>::new(&p2)).unwrap();
    }
}
