//! Stresses and error norms of a displacement field `u` (`u[2 * node + component]`).
//!
//! Strain at a point of a cell, from the physical shape gradients (see [`super::lagrange`]):
//!
//! ```text
//!   εxx = Σ_a ∂N_a/∂x u_ax,   εyy = Σ_a ∂N_a/∂y u_ay,   γxy = Σ_a (∂N_a/∂y u_ax + ∂N_a/∂x u_ay)
//! ```
//!
//! and `σ = C e` ([`Material::stress`]). Stresses of a P1 field are constant per cell; of a P2
//! field, linear on straight cells.
//!
//! Norms (integrated with the degree-5, 7-point rule on every cell, exact for the P2 energy on
//! straight cells):
//!
//! ```text
//!   ‖u_h‖_E  = ( ∫_Ω ε(u_h) : C ε(u_h) )^½                    (= (uᵀ K u)^½)
//!   ‖u_h − u‖_E = ( ∫_Ω (ε_h − ε) : C (ε_h − ε) )^½
//!   ‖u_h − u‖_L2 = ( ∫_Ω |u_h − u|² )^½
//! ```
//!
//! Nodal stresses are the plain average, over the cells sharing a node, of each cell's stress
//! evaluated at that node (no area weighting): simple, exact for a uniform stress, and what
//! VTK point data expects.
//!
//! Every function expects `u.len() == 2 * mesh.num_nodes()`.
use super::lagrange::{self, MAX_CELL_NODES};
use super::material::Material;
use super::quadrature;
use crate::mesh::Mesh;

/// Quadrature degree of the norms.
const NORM_DEGREE: usize = 5;

fn cell_coords(mesh: &Mesh, nodes: &[usize]) -> [[f64; 2]; MAX_CELL_NODES] {
    let mut x = [[0.0; 2]; MAX_CELL_NODES];
    for (xk, &n) in x.iter_mut().zip(nodes) {
        *xk = mesh.nodes[n];
    }
    x
}

/// Voigt strain `(εxx, εyy, γxy)` from physical gradients and the cell's nodal displacements.
fn strain(gradients: &[[f64; 2]], nodes: &[usize], u: &[f64]) -> [f64; 3] {
    let mut e = [0.0; 3];
    for (g, &n) in gradients.iter().zip(nodes) {
        let (ux, uy) = (u[2 * n], u[2 * n + 1]);
        e[0] += g[0] * ux;
        e[1] += g[1] * uy;
        e[2] += g[1] * ux + g[0] * uy;
    }
    e
}

/// Stress of `u` at reference point `xi` of cell `c`.
fn stress_at(mesh: &Mesh, material: &Material, u: &[f64], c: usize, xi: [f64; 2]) -> [f64; 3] {
    let nodes = mesh.cell(c);
    let npc = nodes.len();
    let x = cell_coords(mesh, nodes);
    let p = lagrange::map_cell_point(mesh.order, &x[..npc], xi);
    material.stress(strain(&p.gradients[..npc], nodes, u))
}

/// Stress `(σxx, σyy, σxy)` of each cell at its centroid (reference point (1/3, 1/3)).
pub fn cell_stress(mesh: &Mesh, material: &Material, u: &[f64]) -> Vec<[f64; 3]> {
    (0..mesh.num_cells()).map(|c| stress_at(mesh, material, u, c, [1.0 / 3.0, 1.0 / 3.0])).collect()
}

/// Stress at each node: the average over the cells sharing the node of the cell's stress
/// evaluated at that node.
pub fn nodal_stress(mesh: &Mesh, material: &Material, u: &[f64]) -> Vec<[f64; 3]> {
    let mut sum = vec![[0.0; 3]; mesh.num_nodes()];
    let mut count = vec![0usize; mesh.num_nodes()];
    let reference = lagrange::reference_nodes(mesh.order);
    for c in 0..mesh.num_cells() {
        for (k, &n) in mesh.cell(c).iter().enumerate() {
            let s = stress_at(mesh, material, u, c, reference[k]);
            for i in 0..3 {
                sum[n][i] += s[i];
            }
            count[n] += 1;
        }
    }
    for (s, &k) in sum.iter_mut().zip(&count) {
        if k > 0 {
            for v in s.iter_mut() {
                *v /= k as f64;
            }
        }
    }
    sum
}

/// Visit every quadrature point of every cell: `visit(x, weight · det J, shape values,
/// physical gradients, cell nodes)`.
fn for_each_point(mesh: &Mesh, mut visit: impl FnMut([f64; 2], f64, &[f64], &[[f64; 2]], &[usize])) {
    let order = mesh.order;
    let npc = order.nodes_per_cell();
    let rule = quadrature::triangle(NORM_DEGREE);
    let values: Vec<_> = rule.points.iter().map(|&p| lagrange::shape_values(order, p)).collect();
    let grads: Vec<_> = rule.points.iter().map(|&p| lagrange::shape_gradients(order, p)).collect();
    for c in 0..mesh.num_cells() {
        let nodes = mesh.cell(c);
        let x = cell_coords(mesh, nodes);
        for q in 0..rule.len() {
            let j = lagrange::jacobian(&x[..npc], &grads[q][..npc]);
            let det = lagrange::determinant(&j);
            let g = lagrange::physical_gradients(&j, det, &grads[q][..npc]);
            let xq = lagrange::map_point(&x[..npc], &values[q][..npc]);
            visit(xq, rule.weights[q] * det, &values[q][..npc], &g[..npc], nodes);
        }
    }
}

fn energy(material: &Material, e: [f64; 3]) -> f64 {
    let s = material.stress(e);
    s[0] * e[0] + s[1] * e[1] + s[2] * e[2]
}

/// Energy norm `(∫ ε(u) : C ε(u))^½`.
pub fn energy_norm(mesh: &Mesh, material: &Material, u: &[f64]) -> f64 {
    let mut total = 0.0;
    for_each_point(mesh, |_, w, _, g, nodes| total += w * energy(material, strain(g, nodes, u)));
    total.max(0.0).sqrt()
}

/// Energy norm of the error `(∫ (ε_h − ε) : C (ε_h − ε))^½` against the exact displacement
/// gradient `G[i][j] = ∂u_i/∂x_j`.
pub fn energy_error(
    mesh: &Mesh,
    material: &Material,
    u: &[f64],
    exact_displacement_gradient: impl Fn([f64; 2]) -> [[f64; 2]; 2],
) -> f64 {
    let mut total = 0.0;
    for_each_point(mesh, |x, w, _, g, nodes| {
        let eh = strain(g, nodes, u);
        let grad = exact_displacement_gradient(x);
        let d = [eh[0] - grad[0][0], eh[1] - grad[1][1], eh[2] - grad[0][1] - grad[1][0]];
        total += w * energy(material, d);
    });
    total.max(0.0).sqrt()
}

/// `‖u_h − u‖_L2` against the exact displacement.
pub fn l2_error(mesh: &Mesh, u: &[f64], exact: impl Fn([f64; 2]) -> [f64; 2]) -> f64 {
    let mut total = 0.0;
    for_each_point(mesh, |x, w, n, _, nodes| {
        let mut uh = [0.0; 2];
        for (&nk, &node) in n.iter().zip(nodes) {
            uh[0] += nk * u[2 * node];
            uh[1] += nk * u[2 * node + 1];
        }
        let ue = exact(x);
        total += w * ((uh[0] - ue[0]).powi(2) + (uh[1] - ue[1]).powi(2));
    });
    total.sqrt()
}
