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
//! In axisymmetry (a material of [`PlaneModel::Axisymmetric`] on a mesh of
//! [`crate::mesh::Measure::Axisymmetric`]) the stresses include the hoop strain `εθθ = u_r / r` (its
//! limit `∂u_r/∂r` on the axis) and the integrals carry `2π r`: the energy is
//! `∫ (σ : ε + σθθ εθθ) 2π r dA`, the energy of the body of revolution. The error in energy needs
//! the exact `u_r` for the hoop term: [`energy_error_with_displacement`].
//!
//! Every function expects `u.len() == 2 * mesh.num_nodes()`.
use super::lagrange::{self, MAX_CELL_NODES};
use super::material::{Material, PlaneModel};
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

/// The hoop strain `εθθ = u_r / r` of `u` at a point `x` of a cell with nodes `nodes`, shape
/// values `values` and gradients `gradients`; on the axis (`r ≤ axis_tolerance`, e.g. `1e-12`
/// times the cell's size) its limit `∂u_r/∂r`. 0 unless `material` is axisymmetric.
pub(super) fn hoop_strain(
    material: &Material,
    (x, values, gradients): ([f64; 2], &[f64], &[[f64; 2]]),
    nodes: &[usize],
    u: &[f64],
    axis_tolerance: f64,
) -> f64 {
    if material.plane != PlaneModel::Axisymmetric {
        return 0.0;
    }
    if x[0] <= axis_tolerance {
        nodes.iter().zip(gradients).map(|(&n, g)| g[0] * u[2 * n]).sum()
    } else {
        nodes.iter().zip(values).map(|(&n, v)| v * u[2 * n]).sum::<f64>() / x[0]
    }
}

/// Stress of `u` at reference point `xi` of cell `c` (in axisymmetry with the hoop strain's share
/// in σrr and σzz).
fn stress_at(mesh: &Mesh, material: &Material, u: &[f64], c: usize, xi: [f64; 2]) -> [f64; 3] {
    let nodes = mesh.cell(c);
    let npc = nodes.len();
    let x = cell_coords(mesh, nodes);
    let p = lagrange::map_cell_point(mesh.order, &x[..npc], xi);
    let e = strain(&p.gradients[..npc], nodes, u);
    if material.plane == PlaneModel::Axisymmetric {
        let point = (p.x, &p.values[..npc], &p.gradients[..npc]);
        let hoop = hoop_strain(material, point, nodes, u, 1e-12 * p.det.abs().sqrt());
        material.axisymmetric_stress(e, hoop).0
    } else {
        material.stress(e)
    }
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
            visit(xq, rule.weights[q] * det * mesh.measure.factor(xq), &values[q][..npc], &g[..npc], nodes);
        }
    }
}

/// `ε : C ε` of the strain `e` and the hoop strain `hoop` (0 in the plane).
fn energy(material: &Material, e: [f64; 3], hoop: f64) -> f64 {
    if material.plane == PlaneModel::Axisymmetric {
        let (s, s_hoop) = material.axisymmetric_stress(e, hoop);
        return s[0] * e[0] + s[1] * e[1] + s[2] * e[2] + s_hoop * hoop;
    }
    let s = material.stress(e);
    s[0] * e[0] + s[1] * e[1] + s[2] * e[2]
}

/// Energy norm `(∫ ε(u) : C ε(u))^½` (`2π r dA` and the hoop strain in axisymmetry).
pub fn energy_norm(mesh: &Mesh, material: &Material, u: &[f64]) -> f64 {
    let mut total = 0.0;
    for_each_point(mesh, |x, w, n, g, nodes| {
        let hoop = hoop_strain(material, (x, n, g), nodes, u, 0.0);
        total += w * energy(material, strain(g, nodes, u), hoop)
    });
    total.max(0.0).sqrt()
}

/// Energy norm of the error `(∫ (ε_h − ε) : C (ε_h − ε))^½` against the exact displacement
/// gradient `G[i][j] = ∂u_i/∂x_j`. Plane models only: the hoop strain of axisymmetry needs the
/// exact displacement too ([`energy_error_with_displacement`]); on an axisymmetric material this
/// returns NaN rather than a norm without its hoop term.
pub fn energy_error(
    mesh: &Mesh,
    material: &Material,
    u: &[f64],
    exact_displacement_gradient: impl Fn([f64; 2]) -> [[f64; 2]; 2],
) -> f64 {
    if material.plane == PlaneModel::Axisymmetric {
        return f64::NAN;
    }
    energy_error_with_displacement(mesh, material, u, |x| ([0.0; 2], exact_displacement_gradient(x)))
}

/// [`energy_error`] against `exact(x) = (u(x), G(x))`, the exact displacement and its gradient:
/// any plane model, and axisymmetry (hoop strain `u_r / r`, `2π r dA`).
pub fn energy_error_with_displacement(
    mesh: &Mesh,
    material: &Material,
    u: &[f64],
    exact: impl Fn([f64; 2]) -> ([f64; 2], [[f64; 2]; 2]),
) -> f64 {
    let mut total = 0.0;
    for_each_point(mesh, |x, w, n, g, nodes| {
        let eh = strain(g, nodes, u);
        let (displacement, grad) = exact(x);
        let d = [eh[0] - grad[0][0], eh[1] - grad[1][1], eh[2] - grad[0][1] - grad[1][0]];
        let hoop = if material.plane == PlaneModel::Axisymmetric && x[0] > 0.0 {
            hoop_strain(material, (x, n, g), nodes, u, 0.0) - displacement[0] / x[0]
        } else {
            0.0
        };
        total += w * energy(material, d, hoop);
    });
    total.max(0.0).sqrt()
}

/// `‖u_h − u‖_L2` against the exact displacement (over the body of revolution in axisymmetry).
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
