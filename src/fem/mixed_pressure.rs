//! A locking-free element for nearly incompressible materials: P2 displacements with a
//! discontinuous, piecewise constant (P0) pressure that is eliminated cell by cell.
//!
//! # Why
//!
//! In plane strain the volumetric stiffness `λ = Eν / ((1 + ν)(1 − 2ν))` grows without bound as
//! `ν → ½` (λ / μ = 5000 at ν = 0.4999). The displacement formulation then asks `div u_h ≈ 0`
//! pointwise of P2 fields, which on general triangulations leaves too few functions: the
//! displacement locks and the stress `λ div u_h` oscillates from node to node (Hertz contact at
//! ν = 0.4999: peak pressure 2.6 % low, stresses oscillating by 4 % between nodes). Plane
//! stress does not lock (its in-plane `λ* = Eν / (1 − ν²)` stays below `E`).
//!
//! # The mixed formulation and its condensation
//!
//! Split Hooke's law (plane strain, `εzz = 0`, so `tr ε = εxx + εyy`) into a deviatoric and a
//! volumetric part with the shear modulus `G = μ` and the bulk modulus `κ = λ + 2G/3`:
//!
//! ```text
//!   σ = 2G (ε − ⅓ tr ε I₃) + p I₃ ,   p = κ tr ε ,
//!   ε : C ε = 2G |dev ε|² + κ (tr ε)² .
//! ```
//!
//! In Voigt notation (engineering shear) the in-plane deviatoric matrix is
//! `C_dev = [[4G/3, −2G/3, 0], [−2G/3, 4G/3, 0], [0, 0, G]]`, and `C = C_dev + κ m mᵀ` with
//! `m = (1, 1, 0)`. The mixed (perturbed Lagrangian) problem: find `u_h ∈ V_h` (P2, continuous)
//! and `p_h ∈ Q_h` (P0, discontinuous) with
//!
//! ```text
//!   ∫ ε(v) : C_dev ε(u_h) + ∫ p_h div v = ℓ(v)       for all v ∈ V_h,
//!   ∫ q div u_h − ∫ q p_h / κ = 0                    for all q ∈ Q_h.
//! ```
//!
//! Since `Q_h` is discontinuous, the second equation is local: `p_E = κ (1/|E|) ∫_E div u_h`,
//! κ times the cell mean of the divergence. Substituting it, the displacement solves the SPD
//! system with element matrices
//!
//! ```text
//!   K_E = ∫_E Bᵀ C_dev B dx + (κ / |E|) b_E b_Eᵀ ,    b_E = ∫_E div φ dx = ∫_E mᵀ B dx
//! ```
//!
//! (the "B-bar" / selective reduced integration of the volumetric term: its strain is replaced by
//! its L2 projection onto constants). The global matrix is a symmetric positive definite
//! displacement stiffness on the same dofs and sparsity as P2, so every solver route (MUMPS
//! Cholesky, the contact solvers, MPI row blocks) runs unchanged.
//!
//! Stresses are those of the mixed solution: `σ = C_dev e(u_h) + p_E m` in the plane and
//! `σzz = −(2G/3) tr ε(u_h) + p_E`, so that `p_E = (σxx + σyy + σzz)/3` is the mean stress.
//!
//! # Stability and accuracy
//!
//! The pair P2–P0 satisfies the discrete inf-sup condition on any triangulation in 2D: a Fortin
//! operator exists that preserves the mean normal flux through every edge (the P2 edge bubbles
//! provide it), hence `∫_E div` on every cell. D. Boffi, F. Brezzi, M. Fortin, *Mixed Finite
//! Element Methods and Applications*, Springer 2013, ch. 8 (incompressible materials; the
//! P2–P0 element), and F. Brezzi, M. Fortin, *Mixed and Hybrid Finite Element Methods*,
//! Springer 1991, ch. VI. The error is therefore bounded independently of `λ` (no locking),
//! `‖u − u_h‖₁ + ‖p − p_h‖₀ ≤ C (inf ‖u − v‖₁ + inf ‖p − q‖₀) = O(h)`: first order, limited by the
//! constant pressure (the P2 displacement-only element is second order, but with a constant that
//! grows with `λ/μ`). P2 with a discontinuous P1 pressure is *not* stable on general meshes (it
//! needs special meshes such as barycentric refinements; same references), which is why the
//! pressure here is constant. Measured (tests/mixed_pressure.rs, ν = 0.4999): relative L2 stress
//! error rate 1.00 with a varying pressure, errors within 5 % of those at ν = 0.3.
//!
//! Plane stress: the split is not needed (no locking) and the element equals Lagrange P2 there
//! (`κ = 0`, `C_dev = C`). On P1 cells `div u` is already constant, so the element would equal P1
//! (which locks): the scene accepts `element = "p2p0"` only with `order = 2` in plane strain.
//!
//! Quadrature: straight cells 3 points (degree 2, exact for `Bᵀ C_dev B` and for `b_E`), curved
//! (isoparametric) cells 6 points (degree 4), as for P2 in [`super::assembly`].
use super::assembly::AxisymmetricKernel;
use super::lagrange::{self, MAX_CELL_NODES};
use super::material::{CellMaterials, Material, PlaneModel};
use super::quadrature;
use crate::mesh::{Mesh, Order};

/// The finite element of the displacement (and, for the mixed one, of the pressure).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Element {
    /// Lagrange triangles of the mesh's order (P1 or P2): the displacement formulation.
    #[default]
    Lagrange,
    /// P2 displacements with a discontinuous P0 pressure eliminated cell by cell (see the module
    /// doc); on P1 meshes and in plane stress it equals [`Element::Lagrange`].
    P2P0,
}

impl Element {
    /// The name `report.json` gives the element on a mesh of `order`: "P1", "P2" or "P2-P0".
    pub fn report_name(self, order: Order) -> &'static str {
        match (self, order) {
            (_, Order::P1) => "P1",
            (Element::Lagrange, Order::P2) => "P2",
            (Element::P2P0, Order::P2) => "P2-P0",
        }
    }
}

/// 2×2 coupling of two nodes: `[row component][column component]`.
pub(super) type Block = [[f64; 2]; 2];

/// The deviatoric / volumetric split of a material: `C = C_dev + κ m mᵀ`.
#[derive(Debug, Clone, Copy)]
struct Split {
    dev: [[f64; 3]; 3],
    bulk: f64,
    shear: f64,
    plane: PlaneModel,
}

impl Split {
    fn new(material: &Material) -> Self {
        let (lambda, g) = material.lame();
        match material.plane {
            PlaneModel::Strain => Split {
                dev: [[4.0 * g / 3.0, -2.0 * g / 3.0, 0.0], [-2.0 * g / 3.0, 4.0 * g / 3.0, 0.0], [0.0, 0.0, g]],
                bulk: lambda + 2.0 * g / 3.0,
                shear: g,
                plane: PlaneModel::Strain,
            },
            PlaneModel::Axisymmetric => Split {
                plane: PlaneModel::Axisymmetric,
                ..Split::new(&Material { plane: PlaneModel::Strain, ..*material })
            },
            PlaneModel::Stress => Split { dev: material.elasticity(), bulk: 0.0, shear: g, plane: PlaneModel::Stress },
        }
    }

    /// Stress `(σxx, σyy, σxy)` and the out-of-plane `σzz` (σθθ in axisymmetry) from the strain
    /// `e`, the hoop strain `hoop` (0 in the plane) and the cell pressure `p`.
    fn stress(&self, e: [f64; 3], hoop: f64, p: f64) -> ([f64; 3], f64) {
        let c = &self.dev;
        let h = -2.0 * self.shear / 3.0 * hoop;
        let s = [c[0][0] * e[0] + c[0][1] * e[1] + h + p, c[1][0] * e[0] + c[1][1] * e[1] + h + p, c[2][2] * e[2]];
        let zz = match self.plane {
            PlaneModel::Strain => -2.0 * self.shear / 3.0 * (e[0] + e[1]) + p,
            PlaneModel::Axisymmetric => -2.0 * self.shear / 3.0 * (e[0] + e[1]) + 4.0 * self.shear / 3.0 * hoop + p,
            PlaneModel::Stress => 0.0,
        };
        (s, zz)
    }
}

/// Weights and reference gradients of one quadrature rule (P2 functions).
struct Table {
    weights: Vec<f64>,
    grads: Vec<[[f64; 2]; MAX_CELL_NODES]>,
}

impl Table {
    fn new(degree: usize) -> Self {
        let rule = quadrature::triangle(degree);
        Table {
            grads: rule.points.iter().map(|&p| lagrange::shape_gradients(Order::P2, p)).collect(),
            weights: rule.weights,
        }
    }
}

/// The condensed P2–P0 element matrices of one material.
pub(super) struct MixedKernel {
    split: Split,
    straight: Table,
    curved: Table,
    /// In axisymmetry: the deviatoric hoop terms (`−2G/3`, `4G/3`) and their tables.
    axisymmetric: Option<AxisymmetricKernel>,
}

impl MixedKernel {
    pub(super) fn new(material: &Material) -> Self {
        let split = Split::new(material);
        let axisymmetric = (material.plane == PlaneModel::Axisymmetric)
            .then(|| AxisymmetricKernel::new(-2.0 * split.shear / 3.0, 4.0 * split.shear / 3.0));
        MixedKernel { split, straight: Table::new(2), curved: Table::new(4), axisymmetric }
    }

    /// Axisymmetric `K_E = ∫ Bᵀ C_dev B 2πr dA + (κ/V) b bᵀ` with `V = ∫ 2πr dA` and
    /// `b = ∫ div φ 2πr dA`, `div (N e_r) = ∂N/∂r + N/r`, `div (N e_z) = ∂N/∂z`.
    #[allow(clippy::needless_range_loop)] // local node indices address several arrays
    fn p2_axisymmetric(&self, axi: &AxisymmetricKernel, x: &[[f64; 2]; 6]) -> [[Block; 6]; 6] {
        let mut k = axi.cell(&self.split.dev, x);
        let table = if lagrange::is_affine(x) { &axi.straight } else { &axi.curved };
        let (mut b, mut volume) = ([[0.0; 2]; 6], 0.0);
        for q in 0..table.weights.len() {
            let (values, rg) = (&table.values[q][..6], &table.grads[q][..6]);
            let j = lagrange::jacobian(x, rg);
            let det = lagrange::determinant(&j);
            let g = lagrange::physical_gradients(&j, det, rg);
            let r = lagrange::map_point(x, values)[0];
            let w = table.weights[q] * det * 2.0 * std::f64::consts::PI * r;
            volume += w;
            for a in 0..6 {
                b[a][0] += w * (g[a][0] + values[a] / r);
                b[a][1] += w * g[a][1];
            }
        }
        let s = if volume > 0.0 { self.split.bulk / volume } else { 0.0 };
        for a in 0..6 {
            for bb in 0..6 {
                for r in 0..2 {
                    for q in 0..2 {
                        k[a][bb][r][q] += s * b[a][r] * b[bb][q];
                    }
                }
            }
        }
        k
    }

    /// `K_E = ∫ Bᵀ C_dev B + (κ/|E|) b bᵀ` of the P2 cell with node coordinates `x`.
    #[allow(clippy::needless_range_loop)] // local node indices address several arrays
    pub(super) fn p2(&self, x: &[[f64; 2]; 6]) -> [[Block; 6]; 6] {
        if let Some(axi) = &self.axisymmetric {
            return self.p2_axisymmetric(axi, x);
        }
        let table = if lagrange::is_affine(x) { &self.straight } else { &self.curved };
        let c = &self.split.dev;
        let mut k = [[[[0.0; 2]; 2]; 6]; 6];
        let mut b = [[0.0; 2]; 6];
        let mut area = 0.0;
        for (w, rg) in table.weights.iter().zip(&table.grads) {
            let j = lagrange::jacobian(x, &rg[..6]);
            let det = lagrange::determinant(&j);
            let g = lagrange::physical_gradients(&j, det, &rg[..6]);
            let wd = w * det;
            area += wd;
            for a in 0..6 {
                b[a][0] += wd * g[a][0];
                b[a][1] += wd * g[a][1];
                for bb in a..6 {
                    // B_aᵀ C B_b with B = [[gx, 0], [0, gy], [gy, gx]] (C has no normal-shear coupling).
                    let (ga, gb) = (g[a], g[bb]);
                    let blk = &mut k[a][bb];
                    blk[0][0] += wd * (ga[0] * c[0][0] * gb[0] + ga[1] * c[2][2] * gb[1]);
                    blk[0][1] += wd * (ga[0] * c[0][1] * gb[1] + ga[1] * c[2][2] * gb[0]);
                    blk[1][0] += wd * (ga[1] * c[1][0] * gb[0] + ga[0] * c[2][2] * gb[1]);
                    blk[1][1] += wd * (ga[1] * c[1][1] * gb[1] + ga[0] * c[2][2] * gb[0]);
                }
            }
        }
        let s = if area > 0.0 { self.split.bulk / area } else { 0.0 };
        for a in 0..6 {
            for bb in a..6 {
                for r in 0..2 {
                    for q in 0..2 {
                        k[a][bb][r][q] += s * b[a][r] * b[bb][q];
                    }
                }
            }
        }
        // Lower blocks from the upper ones: K_ba = K_abᵀ.
        for a in 0..6 {
            for bb in 0..a {
                let upper = k[bb][a];
                k[a][bb] = [[upper[0][0], upper[1][0]], [upper[0][1], upper[1][1]]];
            }
        }
        k
    }
}

/// The condensed P2–P0 element matrix of one P2 cell (coordinates in mesh order, 6 of them),
/// row-major 12 × 12 with local dof `2 * local_node + component`, as
/// [`super::assembly::element_stiffness`] gives it for the Lagrange elements.
pub fn element_stiffness(coords: &[[f64; 2]; 6], material: &Material) -> Vec<f64> {
    let k = MixedKernel::new(material).p2(coords);
    let mut out = vec![0.0; 144];
    for a in 0..6 {
        for b in 0..6 {
            for c in 0..2 {
                for d in 0..2 {
                    out[(2 * a + c) * 12 + 2 * b + d] = k[a][b][c][d];
                }
            }
        }
    }
    out
}

fn cell_coords(mesh: &Mesh, nodes: &[usize]) -> [[f64; 2]; MAX_CELL_NODES] {
    let mut x = [[0.0; 2]; MAX_CELL_NODES];
    for (xk, &n) in x.iter_mut().zip(nodes) {
        *xk = mesh.nodes[n];
    }
    x
}

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

/// The pressure of every cell, `p_E = κ (1/|E|) ∫_E div u` (plane strain, P2 mesh); zeros
/// when the element has no pressure (Lagrange, plane stress or a P1 mesh).
pub fn cell_pressure(mesh: &Mesh, material: &Material, element: Element, u: &[f64]) -> Vec<f64> {
    let split = Split::new(material);
    if element == Element::Lagrange || mesh.order == Order::P1 || split.bulk == 0.0 {
        return vec![0.0; mesh.num_cells()];
    }
    let axisymmetric = material.plane == PlaneModel::Axisymmetric;
    let rule = quadrature::triangle(if axisymmetric { 4 } else { 2 });
    let curved_rule = quadrature::triangle(if axisymmetric { 5 } else { 4 });
    (0..mesh.num_cells())
        .map(|c| {
            let nodes = mesh.cell(c);
            let x = cell_coords(mesh, nodes);
            let rule = if lagrange::is_affine(&x[..6]) { &rule } else { &curved_rule };
            let (mut div, mut area) = (0.0, 0.0);
            for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
                let p = lagrange::map_cell_point(Order::P2, &x[..6], xi);
                let e = strain(&p.gradients[..6], nodes, u);
                let hoop = hoop_strain(material, &p, nodes, u);
                let w = w * p.det * mesh.measure.factor(p.x);
                div += w * (e[0] + e[1] + hoop);
                area += w;
            }
            split.bulk * div / area
        })
        .collect()
}

/// Stress `((σxx, σyy, σxy), σzz)` of `u` at reference point `xi` of cell `c`, given the cell
/// pressures `pressure` of [`cell_pressure`] (for [`Element::Lagrange`]: Hooke's law).
fn stress_at(
    mesh: &Mesh,
    material: &Material,
    element: Element,
    pressure: &[f64],
    u: &[f64],
    c: usize,
    xi: [f64; 2],
) -> ([f64; 3], f64) {
    let nodes = mesh.cell(c);
    let npc = nodes.len();
    let x = cell_coords(mesh, nodes);
    let p = lagrange::map_cell_point(mesh.order, &x[..npc], xi);
    let e = strain(&p.gradients[..npc], nodes, u);
    let hoop = hoop_strain(material, &p, nodes, u);
    if element == Element::P2P0 && mesh.order == Order::P2 && material.plane != PlaneModel::Stress {
        Split::new(material).stress(e, hoop, pressure[c])
    } else if material.plane == PlaneModel::Axisymmetric {
        material.axisymmetric_stress(e, hoop)
    } else {
        let s = material.stress(e);
        (s, material.sigma_zz(s))
    }
}

/// The hoop strain `εθθ = u_r / r` at the mapped point `p` in axisymmetry (0 in the plane); on
/// the axis (`r` below `1e-12` times the cell's size) its limit `∂u_r/∂r`.
fn hoop_strain(material: &Material, p: &lagrange::MappedPoint, nodes: &[usize], u: &[f64]) -> f64 {
    super::postprocess::hoop_strain(material, (p.x, &p.values, &p.gradients), nodes, u, 1e-12 * p.det.abs().sqrt())
}

/// Stresses at the nodes, `(σxx, σyy, σxy)` and `σzz`: the plain average over the cells sharing
/// a node of each cell's stress at that node (as [`super::postprocess::nodal_stress`]). For
/// [`Element::P2P0`] the stress of the mixed solution (module doc), otherwise Hooke's law.
pub fn nodal_stress(mesh: &Mesh, material: &Material, element: Element, u: &[f64]) -> (Vec<[f64; 3]>, Vec<f64>) {
    nodal_stress_cells(mesh, &CellMaterials::uniform(*material), element, u)
}

/// [`nodal_stress`] with a material per cell (several bodies; the bodies' meshes are disjoint,
/// so no node averages two materials).
pub fn nodal_stress_cells(
    mesh: &Mesh,
    materials: &CellMaterials,
    element: Element,
    u: &[f64],
) -> (Vec<[f64; 3]>, Vec<f64>) {
    let per_material: Vec<Vec<f64>> =
        materials.materials().iter().map(|m| cell_pressure(mesh, m, element, u)).collect();
    let pressure: Vec<f64> = (0..mesh.num_cells()).map(|c| per_material[materials.index_of(c)][c]).collect();
    let mut sum = vec![[0.0; 4]; mesh.num_nodes()];
    let mut count = vec![0usize; mesh.num_nodes()];
    let reference = lagrange::reference_nodes(mesh.order);
    for c in 0..mesh.num_cells() {
        for (k, &n) in mesh.cell(c).iter().enumerate() {
            let (s, zz) = stress_at(mesh, materials.of(c), element, &pressure, u, c, reference[k]);
            for i in 0..3 {
                sum[n][i] += s[i];
            }
            sum[n][3] += zz;
            count[n] += 1;
        }
    }
    let mut stress = Vec::with_capacity(mesh.num_nodes());
    let mut zz = Vec::with_capacity(mesh.num_nodes());
    for (s, &k) in sum.iter().zip(&count) {
        let f = if k > 0 { 1.0 / k as f64 } else { 0.0 };
        stress.push([s[0] * f, s[1] * f, s[2] * f]);
        zz.push(s[3] * f);
    }
    (stress, zz)
}

/// Von Mises stress from the in-plane stress `s` and `σzz`.
pub fn von_mises(s: [f64; 3], zz: f64) -> f64 {
    let (sxx, syy, sxy) = (s[0], s[1], s[2]);
    (0.5 * ((sxx - syy).powi(2) + (syy - zz).powi(2) + (zz - sxx).powi(2)) + 3.0 * sxy * sxy).sqrt()
}

/// `‖σ_h − σ‖_L2` over the mesh (Frobenius norm of the 3D stress tensor, σzz included), with the
/// exact stress `exact(x) = (σxx, σyy, σxy, σzz)`; degree-5 quadrature on every cell. In
/// axisymmetry `σzz` is the hoop stress σθθ and the integral is over the body of revolution
/// (`2π r dA`).
pub fn stress_l2_error(
    mesh: &Mesh,
    material: &Material,
    element: Element,
    u: &[f64],
    exact: impl Fn([f64; 2]) -> [f64; 4],
) -> f64 {
    let pressure = cell_pressure(mesh, material, element, u);
    let rule = quadrature::triangle(5);
    let npc = mesh.order.nodes_per_cell();
    let mut total = 0.0;
    for c in 0..mesh.num_cells() {
        let x = cell_coords(mesh, mesh.cell(c));
        for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
            let p = lagrange::map_cell_point(mesh.order, &x[..npc], xi);
            let (s, zz) = stress_at(mesh, material, element, &pressure, u, c, xi);
            let t = exact(p.x);
            let d = [s[0] - t[0], s[1] - t[1], s[2] - t[2], zz - t[3]];
            total +=
                w * p.det * mesh.measure.factor(p.x) * (d[0] * d[0] + d[1] * d[1] + 2.0 * d[2] * d[2] + d[3] * d[3]);
        }
    }
    total.max(0.0).sqrt()
}
