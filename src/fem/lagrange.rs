//! Lagrange P1 / P2 shape functions on the reference triangle, the isoparametric map, and the
//! 2- and 3-node edge functions used for boundary integrals.
//!
//! # Reference triangle and node numbering (Gmsh / VTK order)
//!
//! ```text
//!   η                      P1:  N0 = λ0,  N1 = λ1,  N2 = λ2
//!   2 (0,1)
//!   |\                     P2:  N0 = λ0 (2λ0 − 1)   N3 = 4 λ0 λ1   (mid 0-1)
//!   | \                         N1 = λ1 (2λ1 − 1)   N4 = 4 λ1 λ2   (mid 1-2)
//!   5  4                        N2 = λ2 (2λ2 − 1)   N5 = 4 λ2 λ0   (mid 2-0)
//!   |   \
//!   0--3--1  ξ            λ0 = 1 − ξ − η,  λ1 = ξ,  λ2 = η
//!  (0,0) (1,0)
//! ```
//!
//! P1 nodes are 0, 1, 2; P2 adds the mid-edge nodes 3 (½,0), 4 (½,½), 5 (0,½).
//!
//! # Isoparametric map
//!
//! The geometry uses the same functions as the field: `x(ξ) = Σ_k N_k(ξ) x_k`. With P2 nodes
//! that are not edge midpoints (Gmsh `-order 2` on curved boundaries) the triangle is curved.
//!
//! ```text
//!   J = ∂x/∂ξ = [ ∂x/∂ξ  ∂x/∂η ]  = Σ_k x_k ⊗ ∇_ξ N_k,     det J > 0 for a valid (CCW) cell,
//!               [ ∂y/∂ξ  ∂y/∂η ]
//!   ∇_x N = J^{-T} ∇_ξ N,    dx = det J dξ.
//! ```
//!
//! # Edges
//!
//! A boundary edge is parametrised by `t ∈ [0, 1]`, node 0 at `t = 0`, node 1 at `t = 1` and
//! (P2) the mid node 2 at `t = 1/2`:
//!
//! ```text
//!   0 ----- 1          0 --- 2 --- 1
//!   N0 = 1 − t         N0 = (1 − t)(1 − 2t),  N1 = t (2t − 1),  N2 = 4 t (1 − t)
//!   N1 = t
//! ```
//!
//! `x'(t) = Σ_k N_k'(t) x_k` gives the length element `ds = |x'(t)| dt` from the edge's own nodes,
//! so curved P2 edges integrate over their true (parabolic) length, and, with the domain on the
//! left of the edge, the outward normal `n = (y', −x') / |x'|`. Note `n ds = (y', −x') dt` is a
//! polynomial in `t`.
//!
//! Reference: T. J. R. Hughes, *The Finite Element Method*, Dover 2000, §3.1–3.2 (isoparametric
//! elements); O. C. Zienkiewicz, R. L. Taylor, *The Finite Element Method*, vol. 1, §8 (Lagrange
//! triangles in area coordinates).
use crate::mesh::Order;

/// Largest number of nodes of a cell (P2).
pub const MAX_CELL_NODES: usize = 6;
/// Largest number of nodes of an edge (P2).
pub const MAX_EDGE_NODES: usize = 3;

/// Reference coordinates of the cell nodes, in the mesh's node order.
pub fn reference_nodes(order: Order) -> &'static [[f64; 2]] {
    const NODES: [[f64; 2]; 6] = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [0.5, 0.0], [0.5, 0.5], [0.0, 0.5]];
    &NODES[..order.nodes_per_cell()]
}

/// Shape function values at `xi`; entries past `order.nodes_per_cell()` are zero.
pub fn shape_values(order: Order, xi: [f64; 2]) -> [f64; MAX_CELL_NODES] {
    let (l1, l2) = (xi[0], xi[1]);
    let l0 = 1.0 - l1 - l2;
    match order {
        Order::P1 => [l0, l1, l2, 0.0, 0.0, 0.0],
        Order::P2 => [
            l0 * (2.0 * l0 - 1.0),
            l1 * (2.0 * l1 - 1.0),
            l2 * (2.0 * l2 - 1.0),
            4.0 * l0 * l1,
            4.0 * l1 * l2,
            4.0 * l2 * l0,
        ],
    }
}

/// Reference gradients `(∂N/∂ξ, ∂N/∂η)` at `xi`; entries past `order.nodes_per_cell()` are zero.
pub fn shape_gradients(order: Order, xi: [f64; 2]) -> [[f64; 2]; MAX_CELL_NODES] {
    let (l1, l2) = (xi[0], xi[1]);
    let l0 = 1.0 - l1 - l2;
    match order {
        Order::P1 => [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0], [0.0; 2], [0.0; 2], [0.0; 2]],
        Order::P2 => {
            // ∇λ0 = (−1, −1), ∇λ1 = (1, 0), ∇λ2 = (0, 1).
            let a0 = 4.0 * l0 - 1.0;
            [
                [-a0, -a0],
                [4.0 * l1 - 1.0, 0.0],
                [0.0, 4.0 * l2 - 1.0],
                [4.0 * (l0 - l1), -4.0 * l1],
                [4.0 * l2, 4.0 * l1],
                [-4.0 * l2, 4.0 * (l0 - l2)],
            ]
        }
    }
}

/// `x(ξ) = Σ N_k(ξ) x_k` for shape values `n` and node coordinates `coords`.
pub fn map_point(coords: &[[f64; 2]], n: &[f64]) -> [f64; 2] {
    let mut x = [0.0; 2];
    for (p, &nk) in coords.iter().zip(n) {
        x[0] += nk * p[0];
        x[1] += nk * p[1];
    }
    x
}

/// Jacobian `J[i][j] = ∂x_i/∂ξ_j` from node coordinates and reference gradients.
pub fn jacobian(coords: &[[f64; 2]], ref_grads: &[[f64; 2]]) -> [[f64; 2]; 2] {
    let mut j = [[0.0; 2]; 2];
    for (p, g) in coords.iter().zip(ref_grads) {
        j[0][0] += p[0] * g[0];
        j[0][1] += p[0] * g[1];
        j[1][0] += p[1] * g[0];
        j[1][1] += p[1] * g[1];
    }
    j
}

/// `det J`.
pub fn determinant(j: &[[f64; 2]; 2]) -> f64 {
    j[0][0] * j[1][1] - j[0][1] * j[1][0]
}

/// Physical gradients `∇_x N_k = J^{-T} ∇_ξ N_k` for the first `ref_grads.len()` functions.
pub fn physical_gradients(j: &[[f64; 2]; 2], det: f64, ref_grads: &[[f64; 2]]) -> [[f64; 2]; MAX_CELL_NODES] {
    let inv = 1.0 / det;
    let mut g = [[0.0; 2]; MAX_CELL_NODES];
    for (gk, r) in g.iter_mut().zip(ref_grads) {
        gk[0] = (j[1][1] * r[0] - j[1][0] * r[1]) * inv;
        gk[1] = (-j[0][1] * r[0] + j[0][0] * r[1]) * inv;
    }
    g
}

/// Everything about the isoparametric map at one reference point.
#[derive(Debug, Clone, Copy)]
pub struct MappedPoint {
    /// Physical position `x(ξ)`.
    pub x: [f64; 2],
    /// Shape function values at the point (the first `nodes_per_cell` entries).
    pub values: [f64; MAX_CELL_NODES],
    /// Jacobian `∂x/∂ξ` of the map, `jacobian[i][j] = ∂x_i/∂ξ_j`.
    pub jacobian: [[f64; 2]; 2],
    /// Its determinant (> 0 for a counter-clockwise cell).
    pub det: f64,
    /// Physical gradients of the shape functions.
    pub gradients: [[f64; 2]; MAX_CELL_NODES],
}

/// Map the reference point `xi` of the cell with node coordinates `coords`
/// (`order.nodes_per_cell()` of them, in mesh order).
pub fn map_cell_point(order: Order, coords: &[[f64; 2]], xi: [f64; 2]) -> MappedPoint {
    let n = order.nodes_per_cell();
    let values = shape_values(order, xi);
    let ref_grads = shape_gradients(order, xi);
    let jacobian = jacobian(&coords[..n], &ref_grads[..n]);
    let det = determinant(&jacobian);
    let gradients = physical_gradients(&jacobian, det, &ref_grads[..n]);
    MappedPoint { x: map_point(&coords[..n], &values[..n]), values, jacobian, det, gradients }
}

/// True when every P2 mid node lies at the midpoint of its vertex chord (to `1e-12` relative to
/// the edge length): the map is then affine. P1 cells are always affine.
pub fn is_affine(coords: &[[f64; 2]]) -> bool {
    if coords.len() < 6 {
        return true;
    }
    const EDGES: [(usize, usize, usize); 3] = [(0, 1, 3), (1, 2, 4), (2, 0, 5)];
    EDGES.iter().all(|&(a, b, m)| {
        let (pa, pb, pm) = (coords[a], coords[b], coords[m]);
        let len2 = (pb[0] - pa[0]).powi(2) + (pb[1] - pa[1]).powi(2);
        let dx = pm[0] - 0.5 * (pa[0] + pb[0]);
        let dy = pm[1] - 0.5 * (pa[1] + pb[1]);
        dx * dx + dy * dy <= 1e-24 * len2
    })
}

/// Edge shape function values at `t ∈ [0, 1]` for an edge of `nodes` (2 or 3) nodes.
pub fn edge_shape_values(nodes: usize, t: f64) -> [f64; MAX_EDGE_NODES] {
    if nodes >= 3 {
        [(1.0 - t) * (1.0 - 2.0 * t), t * (2.0 * t - 1.0), 4.0 * t * (1.0 - t)]
    } else {
        [1.0 - t, t, 0.0]
    }
}

/// Edge shape function derivatives `dN/dt` at `t` for an edge of `nodes` (2 or 3) nodes.
pub fn edge_shape_derivatives(nodes: usize, t: f64) -> [f64; MAX_EDGE_NODES] {
    if nodes >= 3 {
        [4.0 * t - 3.0, 4.0 * t - 1.0, 4.0 - 8.0 * t]
    } else {
        [-1.0, 1.0, 0.0]
    }
}

/// The map of a boundary edge at one parameter value.
#[derive(Debug, Clone, Copy)]
pub struct EdgePoint {
    /// Physical position of the point.
    pub x: [f64; 2],
    /// Shape function values of the edge's nodes at the point.
    pub values: [f64; MAX_EDGE_NODES],
    /// `x'(t)`.
    pub tangent: [f64; 2],
    /// `|x'(t)|`: `ds = length_element dt`.
    pub length_element: f64,
    /// Unit outward normal `(y', −x') / |x'|` (domain on the left of the edge).
    pub normal: [f64; 2],
}

/// Map parameter `t` of the edge with node coordinates `coords` (`v0, v1` or `v0, v1, mid`).
pub fn map_edge_point(coords: &[[f64; 2]], t: f64) -> EdgePoint {
    let n = coords.len().min(MAX_EDGE_NODES);
    let values = edge_shape_values(n, t);
    let dn = edge_shape_derivatives(n, t);
    let mut x = [0.0; 2];
    let mut tangent = [0.0; 2];
    for k in 0..n {
        x[0] += values[k] * coords[k][0];
        x[1] += values[k] * coords[k][1];
        tangent[0] += dn[k] * coords[k][0];
        tangent[1] += dn[k] * coords[k][1];
    }
    let length_element = tangent[0].hypot(tangent[1]);
    let normal =
        if length_element > 0.0 { [tangent[1] / length_element, -tangent[0] / length_element] } else { [0.0, 0.0] };
    EdgePoint { x, values, tangent, length_element, normal }
}
