//! The volume part of the error in the constitutive relation, cell by cell (see the module doc
//! of [`crate::estimate`] for the formulas).
//!
//! Integration: the stress field is polynomial on each of its pieces (straight triangles that
//! tile the cell: the cell itself for a Lagrange stress, the three sub-triangles of an HCT
//! cell), so each piece gets its own Gauss rule, mapped affinely from the reference triangle:
//!
//! ```text
//!   x(ξ, η) = a + ξ (b − a) + η (c − a),   dx = 2 |abc| dξ dη,
//! ```
//!
//! and the strain of `u_h` is evaluated at the physical quadrature point by inverting the
//! cell's isoparametric map (exact in one step on straight cells, a few Newton steps on curved
//! P2 cells; on a curved cell the pieces tile the straight vertex triangle, so the integral is
//! over the polygonal domain the dual mesh sees).
use crate::fem::lagrange::{self, MAX_CELL_NODES};
use crate::fem::material::Material;
use crate::fem::quadrature;
use crate::mesh::Mesh;

/// A stress field given piece by piece on the cells of a mesh.
pub trait StressField {
    /// Straight triangles (counter-clockwise vertex triples) tiling cell `cell`, on each of which
    /// the field is a polynomial.
    fn pieces(&self, cell: usize) -> Vec<[[f64; 2]; 3]>;
    /// `(σxx, σyy, σxy)` at the physical point `x` of piece `piece` of cell `cell`.
    fn stress(&self, cell: usize, piece: usize, x: [f64; 2]) -> [f64; 3];
}

/// A stress field given by a function of position (an exact solution), on the straight vertex
/// triangle of every cell.
pub struct ExactStress<'m, F> {
    /// The mesh whose cells the stress is integrated on.
    pub mesh: &'m Mesh,
    /// The exact stress `[σxx, σyy, σxy]` (Pa) at a point.
    pub stress: F,
}

impl<F: Fn([f64; 2]) -> [f64; 3]> StressField for ExactStress<'_, F> {
    fn pieces(&self, cell: usize) -> Vec<[[f64; 2]; 3]> {
        let v = self.mesh.cell(cell);
        vec![[self.mesh.nodes[v[0]], self.mesh.nodes[v[1]], self.mesh.nodes[v[2]]]]
    }
    fn stress(&self, _cell: usize, _piece: usize, x: [f64; 2]) -> [f64; 3] {
        (self.stress)(x)
    }
}

/// The volume terms of one primal–dual pair.
#[derive(Debug, Clone)]
pub struct VolumeTerms {
    /// `e_vol,E² = ∫_E (σ_h − Cε(u_h)) : C⁻¹ (σ_h − Cε(u_h))` per cell.
    pub element_squared: Vec<f64>,
    /// `‖½(σ_h + Cε(u_h))‖²_{C⁻¹}` (the reference norm of the relative error).
    pub mean_squared: f64,
    /// `‖Cε(u_h)‖²_{C⁻¹} = a(u_h, u_h)`.
    pub primal_squared: f64,
    /// `‖σ_h‖²_{C⁻¹} = b(σ_h, σ_h)`.
    pub dual_squared: f64,
}

/// `σ : C⁻¹ σ` for Voigt stresses (the compliance maps them to engineering strains).
fn compliance_product(c: &[[f64; 3]; 3], s: [f64; 3]) -> f64 {
    let mut total = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            total += s[i] * c[i][j] * s[j];
        }
    }
    total
}

/// The reference point of cell `cell` that its isoparametric map sends to the physical point
/// `x` (exact on straight cells; Newton's method on curved P2 cells, started from the vertex
/// triangle's affine inverse), and the map there.
pub fn reference_point(mesh: &Mesh, cell: usize, x: [f64; 2]) -> ([f64; 2], lagrange::MappedPoint) {
    let nodes = mesh.cell(cell);
    let npc = nodes.len();
    let mut coords = [[0.0; 2]; MAX_CELL_NODES];
    for (c, &n) in coords.iter_mut().zip(nodes) {
        *c = mesh.nodes[n];
    }
    // Affine guess from the vertex triangle: x = x0 + ξ (x1 − x0) + η (x2 − x0).
    let (a, b, c) = (coords[0], coords[1], coords[2]);
    let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    let r = [x[0] - a[0], x[1] - a[1]];
    let mut xi = [(r[0] * e2[1] - r[1] * e2[0]) / det, (e1[0] * r[1] - e1[1] * r[0]) / det];
    let mut p = lagrange::map_cell_point(mesh.order, &coords[..npc], xi);
    if !lagrange::is_affine(&coords[..npc]) {
        for _ in 0..30 {
            let d = [x[0] - p.x[0], x[1] - p.x[1]];
            let j = p.jacobian;
            let step = [(j[1][1] * d[0] - j[0][1] * d[1]) / p.det, (-j[1][0] * d[0] + j[0][0] * d[1]) / p.det];
            xi = [xi[0] + step[0], xi[1] + step[1]];
            p = lagrange::map_cell_point(mesh.order, &coords[..npc], xi);
            if step[0].abs() + step[1].abs() < 1e-15 {
                break;
            }
        }
    }
    (xi, p)
}

/// The displacement `u` at the physical point `x`, seen from cell `cell`.
pub fn displacement_at_point(mesh: &Mesh, u: &[f64], cell: usize, x: [f64; 2]) -> [f64; 2] {
    let nodes = mesh.cell(cell);
    let (_, p) = reference_point(mesh, cell, x);
    let mut out = [0.0; 2];
    for (v, &n) in p.values[..nodes.len()].iter().zip(nodes) {
        out[0] += v * u[2 * n];
        out[1] += v * u[2 * n + 1];
    }
    out
}

/// Strain `(εxx, εyy, γxy)` of `u` at the physical point `x`, seen from cell `cell`.
pub fn strain_at_point(mesh: &Mesh, u: &[f64], cell: usize, x: [f64; 2]) -> [f64; 3] {
    let nodes = mesh.cell(cell);
    let (_, p) = reference_point(mesh, cell, x);
    let mut e = [0.0; 3];
    for (g, &n) in p.gradients[..nodes.len()].iter().zip(nodes) {
        let (ux, uy) = (u[2 * n], u[2 * n + 1]);
        e[0] += g[0] * ux;
        e[1] += g[1] * uy;
        e[2] += g[1] * ux + g[0] * uy;
    }
    e
}

/// The quadrature degree for a Lagrange displacement against an HCT stress field: 2 when every
/// cell is straight (both stresses are linear on each piece, so the integrands are quadratic
/// and the rule is exact), 4 when some P2 cell is curved (the strain is then rational).
pub fn pair_degree(mesh: &Mesh) -> usize {
    let curved = (0..mesh.num_cells()).any(|c| {
        let coords: Vec<[f64; 2]> = mesh.cell(c).iter().map(|&n| mesh.nodes[n]).collect();
        !lagrange::is_affine(&coords)
    });
    if curved {
        4
    } else {
        2
    }
}

/// The volume terms of the pair (`u`, `sigma`), integrated exactly for polynomial integrands of
/// total degree `degree` on each piece (2 suffices for an HCT stress against a P1 or P2 field
/// on straight cells).
pub fn volume_terms(
    mesh: &Mesh,
    material: &Material,
    u: &[f64],
    sigma: &dyn StressField,
    degree: usize,
) -> VolumeTerms {
    let compliance = material.compliance();
    let rule = quadrature::triangle(degree);
    let mut element_squared = vec![0.0; mesh.num_cells()];
    let (mut mean_squared, mut primal_squared, mut dual_squared) = (0.0, 0.0, 0.0);
    for (cell, slot) in element_squared.iter_mut().enumerate() {
        for (piece, triangle) in sigma.pieces(cell).into_iter().enumerate() {
            for (x, wq) in quadrature::on_triangle(&rule, triangle) {
                let s_h = sigma.stress(cell, piece, x);
                let s_u = material.stress(strain_at_point(mesh, u, cell, x));
                let diff = [s_h[0] - s_u[0], s_h[1] - s_u[1], s_h[2] - s_u[2]];
                let mean = [0.5 * (s_h[0] + s_u[0]), 0.5 * (s_h[1] + s_u[1]), 0.5 * (s_h[2] + s_u[2])];
                *slot += wq * compliance_product(&compliance, diff);
                mean_squared += wq * compliance_product(&compliance, mean);
                primal_squared += wq * compliance_product(&compliance, s_u);
                dual_squared += wq * compliance_product(&compliance, s_h);
            }
        }
    }
    VolumeTerms { element_squared, mean_squared, primal_squared, dual_squared }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::material::PlaneModel;
    use crate::fem::postprocess;
    use crate::mesh::structured;

    #[test]
    fn pair_degree_is_two_on_straight_cells_and_four_on_curved_ones() {
        let mut mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 3, 2, crate::mesh::Order::P2).unwrap();
        assert_eq!(pair_degree(&mesh), 2);
        // Bend one edge: move a midpoint node off its chord.
        let mid = mesh.cell(0)[3];
        mesh.nodes[mid][1] += 0.05;
        assert_eq!(pair_degree(&mesh), 4);
    }

    #[test]
    fn exact_stress_gives_the_primal_energy_error() {
        // u_h interpolates a quadratic field on P1: the CRE against the exact stress is the
        // primal energy error, which postprocess computes independently.
        let material = Material::new(200.0, 0.3, PlaneModel::Strain);
        let mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 6, 3, crate::mesh::Order::P1).unwrap();
        let exact = |x: [f64; 2]| [0.1 * x[0] * x[0] + 0.05 * x[1], 0.02 * x[0] * x[1] - 0.03 * x[1] * x[1]];
        let grad = |x: [f64; 2]| [[0.2 * x[0], 0.05], [0.02 * x[1], 0.02 * x[0] - 0.06 * x[1]]];
        let u: Vec<f64> = mesh.nodes.iter().flat_map(|&x| exact(x)).collect();
        let sigma = ExactStress {
            mesh: &mesh,
            stress: |x: [f64; 2]| {
                let g = grad(x);
                material.stress([g[0][0], g[1][1], g[0][1] + g[1][0]])
            },
        };
        let terms = volume_terms(&mesh, &material, &u, &sigma, 5);
        let cre: f64 = terms.element_squared.iter().sum::<f64>().sqrt();
        let reference = postprocess::energy_error(&mesh, &material, &u, grad);
        assert!((cre - reference).abs() <= 1e-10 * reference, "{cre} vs {reference}");
        let primal = postprocess::energy_norm(&mesh, &material, &u);
        assert!((terms.primal_squared.sqrt() - primal).abs() <= 1e-10 * primal);
    }

    #[test]
    fn reference_points_are_found_inside_curved_cells() {
        let mut mesh = structured::rectangle([0.0, 0.0], [1.0, 1.0], 2, 2, crate::mesh::Order::P2).unwrap();
        // Bend the first mid node of every cell (cells stay valid): the maps become curved.
        for c in 0..mesh.num_cells() {
            let m = mesh.cell(c)[3];
            mesh.nodes[m][1] += 0.03 * (mesh.nodes[m][0] - 0.3);
        }
        let mut curved = 0;
        for c in 0..mesh.num_cells() {
            let v = mesh.cell(c).to_vec();
            let coords: Vec<[f64; 2]> = v.iter().map(|&n| mesh.nodes[n]).collect();
            curved += usize::from(!lagrange::is_affine(&coords));
            for target in [[0.2, 0.3], [0.6, 0.1], [0.1, 0.1]] {
                let x = lagrange::map_cell_point(mesh.order, &coords, target).x;
                let (xi, p) = reference_point(&mesh, c, x);
                assert!((xi[0] - target[0]).abs() < 1e-12 && (xi[1] - target[1]).abs() < 1e-12, "cell {c}: {xi:?}");
                assert!((p.x[0] - x[0]).abs() < 1e-14 && (p.x[1] - x[1]).abs() < 1e-14);
            }
        }
        assert!(curved > 0);
    }
}
