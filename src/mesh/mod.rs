//! Triangle meshes: nodes, P1/P2 triangles, boundary edges carrying physical group names.
//!
//! Node numbering follows Gmsh and VTK (both use the same order for these cells):
//!
//! ```text
//!   P1 triangle          P2 triangle            P1 / P2 edge
//!
//!   2                    2
//!   |\                   |\                     0 ----- 1        0 --- 2 --- 1
//!   | \                  5  4
//!   |  \                 |    \
//!   0---1                0--3--1
//! ```
//!
//! Conventions every constructor guarantees (through [`Mesh::validate`]):
//! - triangles are counter-clockwise (positive area);
//! - boundary edges run with the domain on their left, so the outward normal of edge
//!   `v0 -> v1` is `(dy, -dx) / len`;
//! - every node is used by some triangle.
pub mod build;
pub mod cache;
pub mod gmsh;
pub mod msh;
pub mod pieces;
pub mod shared;
pub mod structured;
pub mod union;
mod validate;

use crate::error::{Error, Result};

/// Polynomial order of the cells' geometry (and of the Lagrange space built on them).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
pub enum Order {
    /// Linear triangles: 3 nodes per cell, 2 per edge.
    P1,
    /// Quadratic triangles: 6 nodes per cell (vertices, then the mid nodes of edges 01, 12, 20), 3
    /// per edge.
    P2,
}

impl Order {
    /// Nodes per triangle: 3 or 6.
    pub fn nodes_per_cell(self) -> usize {
        match self {
            Order::P1 => 3,
            Order::P2 => 6,
        }
    }
    /// Nodes per boundary edge: 2 or 3.
    pub fn nodes_per_edge(self) -> usize {
        match self {
            Order::P1 => 2,
            Order::P2 => 3,
        }
    }
    /// The polynomial degree: 1 or 2.
    pub fn degree(self) -> usize {
        match self {
            Order::P1 => 1,
            Order::P2 => 2,
        }
    }
}

/// A named physical group (Gmsh's `$PhysicalNames`): a region (dim 2) or a boundary part (dim 1).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PhysicalGroup {
    /// The group's name: a boundary part or region name of the scene.
    pub name: String,
    /// Gmsh's physical tag (the `part_id` of the outputs).
    pub tag: i32,
    /// Dimension: 2 for a region of triangles, 1 for a boundary part of edges.
    pub dim: u8,
}

/// Marker for a cell or edge that belongs to no physical group.
pub const NO_GROUP: usize = usize::MAX;

#[derive(Debug, Clone)]
/// A triangle mesh (P1 or P2) with its boundary edges and named physical groups.
pub struct Mesh {
    /// Linear or quadratic triangles (geometry and field).
    pub order: Order,
    /// Node coordinates (m).
    pub nodes: Vec<[f64; 2]>,
    /// Flat connectivity, `order.nodes_per_cell()` node indices per triangle.
    pub cells: Vec<usize>,
    /// Index into `groups` of each triangle's region, or [`NO_GROUP`].
    pub cell_group: Vec<usize>,
    /// Flat connectivity of the boundary edges, `order.nodes_per_edge()` nodes each (v0, v1 and, for P2, the mid node).
    pub edges: Vec<usize>,
    /// Index into `groups` of each boundary edge's part (always set: edges come from groups).
    pub edge_group: Vec<usize>,
    /// The physical groups: regions (dim 2) and boundary parts (dim 1).
    pub groups: Vec<PhysicalGroup>,
    /// What the mesh stands for: a plane section of unit thickness, or the meridian half-plane
    /// of a body of revolution (every integral then carries `2π r`).
    pub measure: Measure,
}

/// The measure of the integrals over a mesh: what a unit of area and of boundary length stand for.
///
/// In axisymmetry the mesh is the meridian half-plane `(r, z) = (x, y)`, `r ≥ 0`, of a body of
/// revolution; a cell of area `dA` at radius `r` is a ring of volume `2π r dA` and a boundary
/// edge of length `ds` a band of area `2π r ds`. Every integral (stiffness, loads, contact
/// weights, mortar integrals) takes the factor `2π r`: forces, reactions and energies are those
/// of the **full revolution** (N and J, not per radian).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Measure {
    /// A plane section of unit thickness (plane strain, plane stress): forces per unit thickness.
    #[default]
    Plane,
    /// The meridian half-plane of a body of revolution: `x = r ≥ 0`, `y = z`, the axis at `r = 0`.
    Axisymmetric,
}

impl Measure {
    /// The factor of `dA` and `ds` at `x`: 1 (plane) or `2π x[0]` (axisymmetric).
    #[inline(always)]
    pub fn factor(self, x: [f64; 2]) -> f64 {
        match self {
            Measure::Plane => 1.0,
            Measure::Axisymmetric => 2.0 * std::f64::consts::PI * x[0],
        }
    }

    /// Whether this is the axisymmetric measure.
    pub fn is_axisymmetric(self) -> bool {
        self == Measure::Axisymmetric
    }

    /// What forces are per, as `report.json` says it: "unit thickness" or "full revolution".
    pub fn forces_per(self) -> &'static str {
        match self {
            Measure::Plane => "unit thickness",
            Measure::Axisymmetric => "full revolution",
        }
    }

    /// The unit of a force: "N/m" (per unit thickness) or "N" (the full revolution).
    pub fn force_unit(self) -> &'static str {
        match self {
            Measure::Plane => "N/m",
            Measure::Axisymmetric => "N",
        }
    }

    /// The part of a sum of forces that equilibrium makes vanish: both components in the plane;
    /// for a body of revolution the axial one only (the radial components of ring forces do not
    /// add up to a resultant: a ring pulled outwards all round is in equilibrium).
    pub fn imbalance(self, sum: [f64; 2]) -> f64 {
        match self {
            Measure::Plane => sum[0].hypot(sum[1]),
            Measure::Axisymmetric => sum[1].abs(),
        }
    }
}

impl Mesh {
    /// The length that turns a stress times a length of the section into a force: 1 (m, plane:
    /// forces per unit thickness) or `2π r_max` (axisymmetric: forces of the full revolution).
    /// Scales of force checks use it.
    pub fn force_length(&self) -> f64 {
        match self.measure {
            Measure::Plane => 1.0,
            Measure::Axisymmetric => {
                let r_max = self.nodes.iter().fold(0.0f64, |m, p| m.max(p[0]));
                if r_max > 0.0 {
                    2.0 * std::f64::consts::PI * r_max
                } else {
                    1.0
                }
            }
        }
    }

    /// Number of nodes (P2 mid nodes included).
    pub fn num_nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Number of triangles.
    pub fn num_cells(&self) -> usize {
        self.cells.len() / self.order.nodes_per_cell()
    }
    /// Number of boundary edges.
    pub fn num_edges(&self) -> usize {
        self.edges.len() / self.order.nodes_per_edge()
    }
    /// The node indices of triangle `c`.
    pub fn cell(&self, c: usize) -> &[usize] {
        let n = self.order.nodes_per_cell();
        &self.cells[c * n..(c + 1) * n]
    }
    /// The node indices of boundary edge `e` (v0, v1 and, for P2, the mid node).
    pub fn edge(&self, e: usize) -> &[usize] {
        let n = self.order.nodes_per_edge();
        &self.edges[e * n..(e + 1) * n]
    }
    /// Index of the physical group with this name and dimension.
    pub fn group_index(&self, name: &str, dim: u8) -> Option<usize> {
        self.groups.iter().position(|g| g.name == name && g.dim == dim)
    }
    /// Like [`Mesh::group_index`], but an error naming the known groups when absent.
    pub fn require_group(&self, name: &str, dim: u8) -> Result<usize> {
        self.group_index(name, dim).ok_or_else(|| {
            let known: Vec<&str> = self.groups.iter().filter(|g| g.dim == dim).map(|g| g.name.as_str()).collect();
            Error::mesh(
                format!("physical group '{name}'"),
                format!(
                    "no {} group of that name; the mesh has: {}",
                    if dim == 1 { "boundary (curve)" } else { "region (surface)" },
                    if known.is_empty() { "none".to_string() } else { known.join(", ") }
                ),
            )
        })
    }
    /// Boundary edge indices belonging to a group.
    pub fn edges_in_group(&self, group: usize) -> impl Iterator<Item = usize> + '_ {
        (0..self.num_edges()).filter(move |&e| self.edge_group[e] == group)
    }
    /// The nodes of a group's boundary edges (P2 mid nodes included), increasing, each once.
    pub fn group_nodes(&self, group: usize) -> Vec<usize> {
        let mut nodes: Vec<usize> = self.edges_in_group(group).flat_map(|e| self.edge(e).to_vec()).collect();
        nodes.sort_unstable();
        nodes.dedup();
        nodes
    }
    /// Unit outward normal and length of boundary edge `e` (chord of its end vertices).
    pub fn edge_normal(&self, e: usize) -> ([f64; 2], f64) {
        let ed = self.edge(e);
        let (a, b) = (self.nodes[ed[0]], self.nodes[ed[1]]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = (dx * dx + dy * dy).sqrt();
        ([dy / len, -dx / len], len)
    }
    /// The diagonal of the bounding box of the nodes (0 for a mesh without nodes): the size
    /// of the body, the scale of geometric tolerances.
    pub fn diagonal(&self) -> f64 {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &self.nodes {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if self.nodes.is_empty() {
            0.0
        } else {
            (hi[0] - lo[0]).hypot(hi[1] - lo[1])
        }
    }

    /// Smallest and largest edge length over all triangles (vertex chords).
    pub fn size_range(&self) -> (f64, f64) {
        let (mut hmin, mut hmax) = (f64::INFINITY, 0.0f64);
        for c in 0..self.num_cells() {
            let v = self.cell(c);
            for k in 0..3 {
                let (a, b) = (self.nodes[v[k]], self.nodes[v[(k + 1) % 3]]);
                let l = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
                hmin = hmin.min(l);
                hmax = hmax.max(l);
            }
        }
        (hmin, hmax)
    }
}
