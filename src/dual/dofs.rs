//! Global numbering of the HCT degrees of freedom on a triangle mesh.
//!
//! Only the corner nodes of the cells carry HCT dofs (on a P2 mesh the mid-edge nodes do not:
//! the dual mesh is the straight-sided mesh of the vertices). Numbering:
//!
//! ```text
//!   vertex v (0 .. nv):  3v, 3v+1, 3v+2  =  φ, ∂φ/∂x, ∂φ/∂y
//!   edge e   (0 .. ne):  3 nv + e        =  ∂φ/∂n at the midpoint, n = (t_y, −t_x),
//!                                           t from the lower to the higher node number
//! ```
use crate::error::Result;
use crate::fem::hct::{HctElement, HCT_DOFS};
use crate::mesh::Mesh;

/// The HCT numbering of a mesh.
#[derive(Debug, Clone)]
pub struct HctDofs {
    /// Vertex index of each mesh node (`usize::MAX` for mid-edge nodes).
    pub vertex_of_node: Vec<usize>,
    /// Mesh node of each vertex.
    pub vertex_nodes: Vec<usize>,
    /// The two end nodes of each edge, lower node number first.
    pub edges: Vec<[usize; 2]>,
    /// Edge index of each cell's local edge k (a_k → a_k+1).
    pub cell_edges: Vec<[usize; 3]>,
    /// The edge of each (lower node, higher node) pair.
    edge_index: std::collections::HashMap<[usize; 2], usize>,
}

impl HctDofs {
    /// The HCT dofs of `mesh`'s vertices and edges.
    pub fn new(mesh: &Mesh) -> Self {
        let mut vertex_of_node = vec![usize::MAX; mesh.num_nodes()];
        let mut vertex_nodes = Vec::new();
        for c in 0..mesh.num_cells() {
            for &n in &mesh.cell(c)[..3] {
                if vertex_of_node[n] == usize::MAX {
                    vertex_of_node[n] = vertex_nodes.len();
                    vertex_nodes.push(n);
                }
            }
        }
        let mut index = std::collections::HashMap::with_capacity(3 * mesh.num_cells() / 2 + 8);
        let mut edges = Vec::new();
        let mut cell_edges = Vec::with_capacity(mesh.num_cells());
        for c in 0..mesh.num_cells() {
            let v = mesh.cell(c);
            let mut local = [0; 3];
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                let key = [a.min(b), a.max(b)];
                local[k] = *index.entry(key).or_insert_with(|| {
                    edges.push(key);
                    edges.len() - 1
                });
            }
            cell_edges.push(local);
        }
        HctDofs { vertex_of_node, vertex_nodes, edges, cell_edges, edge_index: index }
    }

    /// The edge between nodes `a` and `b`, if the cells have one.
    pub fn edge_between(&self, a: usize, b: usize) -> Option<usize> {
        self.edge_index.get(&[a.min(b), a.max(b)]).copied()
    }

    /// Number of vertices (mesh nodes at triangle corners).
    pub fn num_vertices(&self) -> usize {
        self.vertex_nodes.len()
    }

    /// Total number of dofs: 3 per vertex, 1 per edge.
    pub fn len(&self) -> usize {
        3 * self.vertex_nodes.len() + self.edges.len()
    }

    /// Whether the mesh has no vertices.
    pub fn is_empty(&self) -> bool {
        self.vertex_nodes.is_empty()
    }

    /// Dof `component` (0: φ, 1: φ,x, 2: φ,y) of mesh node `node` (a vertex).
    pub fn node_dof(&self, node: usize, component: usize) -> usize {
        3 * self.vertex_of_node[node] + component
    }

    /// The dof (normal derivative) of HCT edge `edge`.
    pub fn edge_dof(&self, edge: usize) -> usize {
        3 * self.vertex_nodes.len() + edge
    }

    /// Sign of the global normal of cell `c`'s local edge k relative to its outward normal.
    pub fn edge_signs(&self, mesh: &Mesh, c: usize) -> [f64; 3] {
        let v = mesh.cell(c);
        [0, 1, 2].map(|k| if v[k] < v[(k + 1) % 3] { 1.0 } else { -1.0 })
    }

    /// The 12 global dofs of cell `c`, in the element's order.
    pub fn cell_dofs(&self, mesh: &Mesh, c: usize) -> [usize; HCT_DOFS] {
        let v = mesh.cell(c);
        let mut d = [0; HCT_DOFS];
        for k in 0..3 {
            for comp in 0..3 {
                d[3 * k + comp] = self.node_dof(v[k], comp);
            }
            d[9 + k] = self.edge_dof(self.cell_edges[c][k]);
        }
        d
    }

    /// The HCT element of cell `c` (on its vertex triangle).
    pub fn element(&self, mesh: &Mesh, c: usize) -> Result<HctElement> {
        let v = mesh.cell(c);
        HctElement::new([mesh.nodes[v[0]], mesh.nodes[v[1]], mesh.nodes[v[2]]], self.edge_signs(mesh, c)).map_err(|e| {
            match e {
                crate::error::Error::Mesh { message, .. } => {
                    crate::error::Error::mesh(format!("triangle {c}"), message)
                }
                other => other,
            }
        })
    }
}
