//! The independent check of a dual answer: is the stress field statically admissible?
//!
//! Recomputed from the field itself and the scene's loads, not from the solver:
//! - traction residual: `|σ n − t|` at three Gauss points of every boundary edge, for every
//!   traction component the scene prescribes (traction parts, free edges, the free component of
//!   a partly supported part);
//! - interior equilibrium: `|div σ + F|` at the centroid of every piece (central differences of
//!   the piecewise-linear field, exact up to round-off);
//! - stress jump: `|[σ] n|` at three Gauss points of every interior edge (continuity of the
//!   traction between neighbours, which the C¹ continuity of φ guarantees).
//!
//! Each is relative to the largest stress met (and, for the divergence, to that stress over the
//! piece's size). The complementary energy `½ b(σ, σ) − l(σ)` is computed on the way.
use super::boundary::TractionComponent;
use super::system::{DualData, DualField};
use crate::estimate::StressField;
use crate::fem::quadrature;

/// The residuals of a dual answer (all relative; round-off for an admissible field).
#[derive(Debug, Clone, serde::Serialize)]
pub struct DualCheck {
    /// Largest `|σ n − t|` on the boundary where the traction is prescribed, relative to
    /// `stress_scale`.
    pub traction_residual: f64,
    /// Largest `|div σ + F|` inside, relative.
    pub interior_equilibrium: f64,
    /// Largest traction jump `|[σ] n|` across interior edges, relative.
    pub stress_jump: f64,
    /// The largest stress component met, the scale of the residuals.
    pub stress_scale: f64,
    /// `½ ∫ σ : C⁻¹ σ − ∫ΓD u0·σn` (J per unit thickness).
    pub complementary_energy: f64,
}

impl DualCheck {
    /// The largest of the three residuals.
    pub fn worst(&self) -> f64 {
        self.traction_residual.max(self.interior_equilibrium).max(self.stress_jump)
    }
}

fn gauss3(a: [f64; 2], b: [f64; 2]) -> [([f64; 2], f64); 3] {
    let rule = quadrature::gauss_legendre(3);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    [0, 1, 2].map(|i| {
        let t = rule.points[i];
        ([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])], rule.weights[i] * len)
    })
}

/// Check the field against the loads it was computed for.
pub fn check(field: &DualField, data: &DualData) -> DualCheck {
    let (mesh, system) = (field.mesh, field.system);
    let dofs = &system.dofs;
    // The cells of every HCT edge.
    let mut cells_of_edge: Vec<Vec<usize>> = vec![Vec::new(); dofs.edges.len()];
    for (c, edges) in dofs.cell_edges.iter().enumerate() {
        for &e in edges {
            cells_of_edge[e].push(c);
        }
    }
    let mut stress_scale = 0.0f64;
    let mut note = |s: [f64; 3]| stress_scale = stress_scale.max(s[0].abs()).max(s[1].abs()).max(s[2].abs());
    // Boundary: traction residual and the load functional.
    let (mut traction, mut load_value) = (0.0f64, 0.0);
    for e in &system.edges {
        let cell = cells_of_edge[e.edge][0];
        let (pa, pb) = (mesh.nodes[e.a], mesh.nodes[e.b]);
        let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let n = [(pb[1] - pa[1]) / len, -(pb[0] - pa[0]) / len];
        let group = mesh.edge_group[e.mesh_edge];
        for (x, w) in gauss3(pa, pb) {
            let s = field.stress_at(cell, x);
            note(s);
            let sn = [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]];
            let mut t = [0.0; 2];
            for load in data.edge_loads.iter().filter(|l| l.group == group) {
                let ti = load.traction.at(x, n);
                t = [t[0] + ti[0], t[1] + ti[1]];
            }
            for k in 0..2 {
                match e.components[k] {
                    TractionComponent::Known(_) => traction = traction.max((sn[k] - t[k]).abs()),
                    TractionComponent::Prescribed(u0) => load_value += w * u0 * sn[k],
                    TractionComponent::Free => {}
                }
            }
        }
    }
    // Interior edges: traction continuity.
    let mut jump = 0.0f64;
    for (e, cells) in cells_of_edge.iter().enumerate() {
        if cells.len() != 2 {
            continue;
        }
        let [p, q] = dofs.edges[e];
        let (pa, pb) = (mesh.nodes[p], mesh.nodes[q]);
        let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let n = [(pb[1] - pa[1]) / len, -(pb[0] - pa[0]) / len];
        for (x, _) in gauss3(pa, pb) {
            let (s1, s2) = (field.stress_at(cells[0], x), field.stress_at(cells[1], x));
            let d = [s1[0] - s2[0], s1[1] - s2[1], s1[2] - s2[2]];
            jump = jump.max((d[0] * n[0] + d[2] * n[1]).hypot(d[2] * n[0] + d[1] * n[1]));
        }
    }
    // Pieces: equilibrium at the centroid, and the energy.
    let compliance = system.material.compliance();
    let rule = quadrature::triangle(2);
    let (mut divergence, mut energy) = (0.0f64, 0.0);
    for c in 0..mesh.num_cells() {
        for (piece, triangle) in field.pieces(c).into_iter().enumerate() {
            let [a, b, cc] = triangle;
            let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [cc[0] - a[0], cc[1] - a[1]]);
            for (x, w) in quadrature::on_triangle(&rule, triangle) {
                let s = field.stress(c, piece, x);
                note(s);
                let quad: f64 = (0..3).map(|r| (0..3).map(|q| s[r] * compliance[r][q] * s[q]).sum::<f64>()).sum();
                energy += 0.5 * w * quad;
            }
            let centroid = [(a[0] + b[0] + cc[0]) / 3.0, (a[1] + b[1] + cc[1]) / 3.0];
            let size = e1[0].hypot(e1[1]).max(e2[0].hypot(e2[1]));
            // With a constant body force the field is linear on the piece: a wide step keeps
            // round-off small. A variable force's particular field is not: a short step.
            let h = if matches!(system.body_force, super::system::BodyLoad::Constant(_)) { 0.25 } else { 1e-3 } * size;
            let sx = |dx: f64| field.stress(c, piece, [centroid[0] + dx, centroid[1]]);
            let sy = |dy: f64| field.stress(c, piece, [centroid[0], centroid[1] + dy]);
            let (px, mx, py, my) = (sx(h), sx(-h), sy(h), sy(-h));
            let f = system.body_force.force(centroid);
            let div = [
                (px[0] - mx[0]) / (2.0 * h) + (py[2] - my[2]) / (2.0 * h) + f[0],
                (px[2] - mx[2]) / (2.0 * h) + (py[1] - my[1]) / (2.0 * h) + f[1],
            ];
            divergence = divergence.max(div[0].hypot(div[1]) * size);
        }
    }
    let scale = stress_scale.max(f64::MIN_POSITIVE);
    DualCheck {
        traction_residual: traction / scale,
        interior_equilibrium: divergence / scale,
        stress_jump: jump / scale,
        stress_scale,
        complementary_energy: energy - load_value,
    }
}
