//! # The Hsieh–Clough–Tocher (HCT) element
//!
//! The C¹ triangle of the dual (stress) formulation: the Airy stress function φ gives the
//! stresses through its second derivatives, `σxx = φ,yy`, `σyy = φ,xx`, `σxy = −φ,xy`, which
//! are in equilibrium (no body force) inside every element and, because φ and ∇φ are
//! continuous, transmit continuous tractions across every edge: statically admissible by
//! construction. Lagrange elements are only C⁰; the HCT macro-element is the classical C¹
//! element that needs only first derivatives as degrees of freedom (R. W. Clough, J. L.
//! Tocher, "Finite element stiffness matrices for analysis of plate bending", Proc. Conf.
//! Matrix Methods in Structural Mechanics, Wright-Patterson AFB, 1965; P. G. Ciarlet, *The
//! Finite Element Method for Elliptic Problems*, North-Holland 1978, §6.1).
//!
//! ## Degrees of freedom (full HCT, 12)
//!
//! ```text
//!                 a2
//!                 /|\                 vertex k:  dofs 3k, 3k+1, 3k+2 = φ, ∂φ/∂x, ∂φ/∂y at a_k
//!                / | \                edge k (a_k -> a_k+1): dof 9+k = ∂φ/∂n at its midpoint m_k
//!           m2  /  |  \  m1
//!              / T2| T1\              T_k = (a_k, a_k+1, c): the sub-triangle on edge k,
//!             /   c*    \             c the barycentre; one cubic polynomial on each
//!            /  .  T0  . \
//!          a0 ----------- a1
//!                  m0
//! ```
//!
//! The normal of the midpoint dof has ONE global orientation so that the two elements sharing
//! an edge agree: the edge is oriented from its lower to its higher global vertex number,
//! `t = (b − a)/|b − a|`, and `n = (t_y, −t_x)` (t turned clockwise). For a counter-clockwise
//! element that is the outward normal of edge k when `a_k < a_k+1` (globally), and minus it
//! otherwise: the element takes a sign per edge ([`HctElement::new`]'s `edge_sign`).
//!
//! ## Construction
//!
//! On a triangle, each piece is a cubic in the scaled coordinates `ξ = (x − c)/h` (c the
//! barycentre, h the longest edge), 10 coefficients per piece, 30 in all. They are fixed by
//! - C¹ across the three interior edges `c a_k` (shared by T_k−1 and T_k): equal values at 4
//!   points (a cubic along the edge) and equal normal derivatives at 3 points (a quadratic):
//!   21 conditions, 3 of them redundant;
//! - the 12 degrees of freedom.
//!
//! The 33 × 30 system has rank 30; it is solved for the 12 right-hand sides at once through
//! a QR factorisation (least squares, exact for a consistent system). Derivative conditions are
//! written for `h ∂/∂x` so that every row is O(1) whatever the size of the triangle, and the
//! basis functions of derivative dofs are multiplied back by `h`.
//!
//! That QR is done once, on the reference triangle `(0,0), (1,0), (0,1)` (with outward
//! normals). The space of C¹ piecewise cubics on the barycentric split is invariant under the
//! affine map `x = a_0 + J x̂`, `J = [a_1 − a_0, a_2 − a_0]` (it maps the split onto the split),
//! but the degrees of freedom are not, so a physical element is the reference one composed
//! with a 12 × 12 change of dofs `d̂ = G d` (as for the Argyris element: V. Domínguez,
//! F.-J. Sayas, "Algorithm 884", ACM TOMS 35(2), 2008; and for HCT in Ciarlet's book §6.1):
//! ```text
//!   φ̂(â_k)            = φ(a_k)
//!   ∇̂φ̂(â_k)           = Jᵀ ∇φ(a_k)
//!   ∂φ̂/∂n̂_k(m̂_k)      = ∇φ(m_k)·(J n̂_k) = γ ∂φ/∂n_k(m_k) + δ ∂φ/∂t_k(m_k),   J n̂_k = γ n_k + δ t_k
//!   ∂φ/∂t_k(m_k)       = 3/(2L) (φ(a_k+1) − φ(a_k)) − ¼ t_k·(∇φ(a_k) + ∇φ(a_k+1))
//! ```
//! (the last line is the midpoint slope of the cubic along the outer edge of length L, which
//! only the vertex data define), and `ψ_j ∘ F = Σ_k G[k][j] ψ̂_k`. The basis is kept in the
//! reference scaled coordinates `ξ̂ = K (x − a_0) + o`; gradients and Hessians follow by the chain rule
//! (`∇ = Kᵀ∇̂`, `H = Kᵀ Ĥ K`). This is ~20× cheaper than a QR per element; the direct
//! construction stays as [`HctElement::from_conditions`] and the two agree to round-off
//! (tested). Both reproduce every cubic exactly (tested on strongly distorted triangles).
//!
//! ## Stiffness of the complementary energy
//!
//! `S_E[i][j] = ∫_E σ(ψ_i) : C⁻¹ σ(ψ_j)` with `σ(ψ) = (ψ,yy, ψ,xx, −ψ,xy)` (Voigt) and C⁻¹ the
//! compliance of [`Material`] (plane strain or plane stress). Second derivatives are linear on
//! each piece, so a degree-2 rule per sub-triangle is exact. Its kernel is the affine functions
//! (zero stress).
use nalgebra::SMatrix;

use super::material::Material;
use super::quadrature;
use crate::error::{Error, Result};

/// Number of degrees of freedom of the element.
pub const HCT_DOFS: usize = 12;

/// Monomials of a cubic in (ξ, η): 1, ξ, η, ξ², ξη, η², ξ³, ξ²η, ξη², η³.
const MONOMIALS: usize = 10;

/// Conditions of the construction: 21 for C¹ across the interior edges, 12 degrees of freedom.
const CONDITIONS: usize = 33;

fn monomials(p: [f64; 2]) -> [f64; MONOMIALS] {
    let (x, y) = (p[0], p[1]);
    [1.0, x, y, x * x, x * y, y * y, x * x * x, x * x * y, x * y * y, y * y * y]
}

/// `∂/∂ξ` and `∂/∂η` of the monomials.
fn monomial_gradients(p: [f64; 2]) -> [[f64; MONOMIALS]; 2] {
    let (x, y) = (p[0], p[1]);
    [
        [0.0, 1.0, 0.0, 2.0 * x, y, 0.0, 3.0 * x * x, 2.0 * x * y, y * y, 0.0],
        [0.0, 0.0, 1.0, 0.0, x, 2.0 * y, 0.0, x * x, 2.0 * x * y, 3.0 * y * y],
    ]
}

/// `∂²/∂ξ²`, `∂²/∂η²`, `∂²/∂ξ∂η` of the monomials.
fn monomial_hessians(p: [f64; 2]) -> [[f64; MONOMIALS]; 3] {
    let (x, y) = (p[0], p[1]);
    [
        [0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 6.0 * x, 2.0 * y, 0.0, 0.0],
        [0.0, 0.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 2.0 * x, 6.0 * y],
        [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 2.0 * x, 2.0 * y, 0.0],
    ]
}

/// The coefficients of the 12 basis functions on each piece, `[piece][basis][monomial]`.
type PieceCoefficients = [[[f64; MONOMIALS]; HCT_DOFS]; 3];

/// One HCT triangle: its geometry and the coefficients of its 12 basis functions on each of
/// the three pieces, as cubics in the scaled coordinates `ξ = K (x − x₀) + o` of the reference
/// element (see "Construction").
#[derive(Debug, Clone)]
pub struct HctElement {
    vertices: [[f64; 2]; 3],
    center: [f64; 2],
    /// `K`, `x₀` and `o` of `ξ = K (x − x₀) + o` (the difference first: no cancellation for
    /// small triangles far from the origin).
    map: [[f64; 2]; 2],
    origin: [f64; 2],
    offset: [f64; 2],
    /// `coefficients[piece][basis][monomial]`, in the scaled coordinates.
    coefficients: PieceCoefficients,
}

/// The reference element `(0,0), (1,0), (0,1)` with outward edge normals, built once by
/// [`solve_conditions`]: its coefficients in `ξ̂ = (x̂ − ĉ)/ĥ`, and ĉ, ĥ.
struct Reference {
    coefficients: PieceCoefficients,
    center: [f64; 2],
    h: f64,
}

fn reference() -> &'static Reference {
    static REFERENCE: std::sync::OnceLock<Reference> = std::sync::OnceLock::new();
    REFERENCE.get_or_init(|| {
        let (coefficients, center, h) = solve_conditions([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], [1.0; 3])
            .expect("the reference HCT triangle is not degenerate");
        Reference { coefficients, center, h }
    })
}

/// Twice the signed area and the longest edge; an error for a degenerate or clockwise triangle.
fn checked_geometry(vertices: [[f64; 2]; 3]) -> Result<(f64, f64)> {
    let [a, b, c] = vertices;
    let area2 = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    let h = (0..3)
        .map(|k| {
            let (p, q) = (vertices[k], vertices[(k + 1) % 3]);
            (q[0] - p[0]).hypot(q[1] - p[1])
        })
        .fold(0.0f64, f64::max);
    if !(area2.is_finite() && h.is_finite() && area2 > 1e-12 * h * h) {
        return Err(Error::mesh(
            format!("triangle ({:?}, {:?}), ({:?}, {:?}), ({:?}, {:?})", a[0], a[1], b[0], b[1], c[0], c[1]),
            "degenerate or clockwise triangle: the HCT element needs a counter-clockwise triangle of positive area",
        ));
    }
    Ok((area2, h))
}

/// The basis of the element on `vertices` from its 33 conditions (see "Construction"), in the
/// coordinates `ξ = (x − c)/h`: the coefficients, c and h.
#[allow(clippy::needless_range_loop)] // k indexes vertices, pieces and edges together
fn solve_conditions(vertices: [[f64; 2]; 3], edge_sign: [f64; 3]) -> Result<(PieceCoefficients, [f64; 2], f64)> {
    let [a, b, c] = vertices;
    let (_, h) = checked_geometry(vertices)?;
    let center = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
    let scaled = |p: [f64; 2]| [(p[0] - center[0]) / h, (p[1] - center[1]) / h];
    let sv: Vec<[f64; 2]> = vertices.iter().map(|&v| scaled(v)).collect();
    let sc = [0.0, 0.0];
    // Unknowns: piece k's coefficients at columns 10k..10k+10.
    let mut rows: Vec<[f64; 3 * MONOMIALS]> = Vec::with_capacity(CONDITIONS);
    let mut dof_row = [usize::MAX; HCT_DOFS];
    // C¹ across the interior edge c -> a_k, shared by pieces k−1 (left) and k (right).
    for k in 0..3 {
        let (left, right) = ((k + 2) % 3, k);
        let (p, q) = (sc, sv[k]);
        let d = [q[0] - p[0], q[1] - p[1]];
        let len = d[0].hypot(d[1]);
        let normal = [d[1] / len, -d[0] / len];
        for t in [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0] {
            let x = [p[0] + t * d[0], p[1] + t * d[1]];
            let m = monomials(x);
            let mut row = [0.0; 3 * MONOMIALS];
            for i in 0..MONOMIALS {
                row[MONOMIALS * left + i] = m[i];
                row[MONOMIALS * right + i] = -m[i];
            }
            rows.push(row);
        }
        for t in [0.0, 0.5, 1.0] {
            let x = [p[0] + t * d[0], p[1] + t * d[1]];
            let g = monomial_gradients(x);
            let mut row = [0.0; 3 * MONOMIALS];
            for i in 0..MONOMIALS {
                let dn = normal[0] * g[0][i] + normal[1] * g[1][i];
                row[MONOMIALS * left + i] = dn;
                row[MONOMIALS * right + i] = -dn;
            }
            rows.push(row);
        }
    }
    // Vertex dofs on the piece k (a_k is its first vertex); in scaled coordinates the
    // derivative rows are h ∂/∂x = ∂/∂ξ.
    for k in 0..3 {
        let m = monomials(sv[k]);
        let g = monomial_gradients(sv[k]);
        for (component, values) in [m, g[0], g[1]].into_iter().enumerate() {
            let mut row = [0.0; 3 * MONOMIALS];
            row[MONOMIALS * k..MONOMIALS * (k + 1)].copy_from_slice(&values);
            dof_row[3 * k + component] = rows.len();
            rows.push(row);
        }
    }
    // Edge-midpoint normal derivatives on piece k (edge k is its outer edge).
    for k in 0..3 {
        let (p, q) = (sv[k], sv[(k + 1) % 3]);
        let d = [q[0] - p[0], q[1] - p[1]];
        let len = d[0].hypot(d[1]);
        let normal = [edge_sign[k] * d[1] / len, -edge_sign[k] * d[0] / len];
        let g = monomial_gradients([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
        let mut row = [0.0; 3 * MONOMIALS];
        for i in 0..MONOMIALS {
            row[MONOMIALS * k + i] = normal[0] * g[0][i] + normal[1] * g[1][i];
        }
        dof_row[9 + k] = rows.len();
        rows.push(row);
    }
    debug_assert_eq!(rows.len(), CONDITIONS);
    // Fixed sizes: no allocation per element (the dual builds one per cell).
    let matrix = SMatrix::<f64, CONDITIONS, { 3 * MONOMIALS }>::from_fn(|r, c| rows[r][c]);
    let mut rhs = SMatrix::<f64, CONDITIONS, HCT_DOFS>::zeros();
    for (j, &r) in dof_row.iter().enumerate() {
        rhs[(r, j)] = 1.0;
    }
    // Least squares through QR: the 33 × 30 system has full column rank (its 3 redundant
    // rows are consistent), so R is invertible and x = R⁻¹ Qᵀ b solves it exactly.
    // Qᵀ b by the Householder reflections themselves (Q is never formed).
    let qr = matrix.qr();
    let mut qtb = rhs;
    qr.q_tr_mul(&mut qtb);
    let top = qtb.fixed_rows::<{ 3 * MONOMIALS }>(0).into_owned();
    let solution = qr.r().solve_upper_triangular(&top).ok_or_else(|| {
        Error::mesh("HCT element", "cannot build the basis on this triangle (singular system); it is too distorted")
    })?;
    let mut coefficients = [[[0.0; MONOMIALS]; HCT_DOFS]; 3];
    for (piece, per_piece) in coefficients.iter_mut().enumerate() {
        for (j, basis) in per_piece.iter_mut().enumerate() {
            // Derivative dofs were imposed on h ∂/∂x: scale their basis functions back.
            let scale = if j >= 9 || j % 3 != 0 { h } else { 1.0 };
            for (i, c) in basis.iter_mut().enumerate() {
                *c = scale * solution[(MONOMIALS * piece + i, j)];
            }
        }
    }
    Ok((coefficients, center, h))
}

impl HctElement {
    /// The element on the counter-clockwise triangle `vertices`; `edge_sign[k]` is +1 when the
    /// global normal of edge k (a_k → a_k+1) is its outward normal, −1 when it is the inward
    /// one (see the module doc). Built from the reference element (see "Construction").
    pub fn new(vertices: [[f64; 2]; 3], edge_sign: [f64; 3]) -> Result<Self> {
        let (area2, _) = checked_geometry(vertices)?;
        let [a, b, c] = vertices;
        let reference = reference();
        // x = a + J x̂, J = [b − a, c − a]; ξ̂ = (x̂ − ĉ)/ĥ = K (x − a) + o.
        let j = [[b[0] - a[0], c[0] - a[0]], [b[1] - a[1], c[1] - a[1]]];
        let inv = [[j[1][1] / area2, -j[0][1] / area2], [-j[1][0] / area2, j[0][0] / area2]];
        let map = [0, 1].map(|r| [0, 1].map(|col| inv[r][col] / reference.h));
        let offset = [0, 1].map(|r| -reference.center[r] / reference.h);
        // G: the reference dofs of φ∘F from the physical dofs of φ, d̂ = G d.
        let mut g = [[0.0; HCT_DOFS]; HCT_DOFS];
        for k in 0..3 {
            g[3 * k][3 * k] = 1.0;
            // ∇̂φ̂ = Jᵀ ∇φ.
            for r in 0..2 {
                for col in 0..2 {
                    g[3 * k + 1 + r][3 * k + 1 + col] = j[col][r];
                }
            }
        }
        let reference_vertices = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        for e in 0..3 {
            let (i, l) = (e, (e + 1) % 3);
            let (p, q) = (vertices[i], vertices[l]);
            let len = (q[0] - p[0]).hypot(q[1] - p[1]);
            let t = [(q[0] - p[0]) / len, (q[1] - p[1]) / len];
            let n = [edge_sign[e] * t[1], -edge_sign[e] * t[0]];
            let (rp, rq): ([f64; 2], [f64; 2]) = (reference_vertices[i], reference_vertices[l]);
            let rlen = (rq[0] - rp[0]).hypot(rq[1] - rp[1]);
            let rn = [(rq[1] - rp[1]) / rlen, -(rq[0] - rp[0]) / rlen];
            // ∂φ̂/∂n̂ = ∇φ · (J n̂), J n̂ = γ n + δ t; the tangential derivative at the midpoint
            // is that of the cubic along the edge, from the end values and slopes.
            let v = [j[0][0] * rn[0] + j[0][1] * rn[1], j[1][0] * rn[0] + j[1][1] * rn[1]];
            let (gamma, delta) = (v[0] * n[0] + v[1] * n[1], v[0] * t[0] + v[1] * t[1]);
            let row = &mut g[9 + e];
            row[9 + e] = gamma;
            row[3 * i] -= 1.5 * delta / len;
            row[3 * l] += 1.5 * delta / len;
            for vertex in [i, l] {
                row[3 * vertex + 1] -= 0.25 * delta * t[0];
                row[3 * vertex + 2] -= 0.25 * delta * t[1];
            }
        }
        // ψ_j ∘ F = Σ_k G[k][j] ψ̂_k.
        let mut coefficients = [[[0.0; MONOMIALS]; HCT_DOFS]; 3];
        for (piece, per_piece) in coefficients.iter_mut().enumerate() {
            for (k, g_row) in g.iter().enumerate() {
                let reference_basis = &reference.coefficients[piece][k];
                for (jdof, &gk) in g_row.iter().enumerate() {
                    if gk != 0.0 {
                        for (o, r) in per_piece[jdof].iter_mut().zip(reference_basis) {
                            *o += gk * r;
                        }
                    }
                }
            }
        }
        let center = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
        Ok(HctElement { vertices, center, map, origin: a, offset, coefficients })
    }

    /// The element built directly from its 33 conditions on the physical triangle (slower;
    /// a cross-check of [`HctElement::new`]).
    pub fn from_conditions(vertices: [[f64; 2]; 3], edge_sign: [f64; 3]) -> Result<Self> {
        let (coefficients, center, h) = solve_conditions(vertices, edge_sign)?;
        let map = [[1.0 / h, 0.0], [0.0, 1.0 / h]];
        Ok(HctElement { vertices, center, map, origin: center, offset: [0.0, 0.0], coefficients })
    }

    /// The three sub-triangles `(a_k, a_k+1, c)`, counter-clockwise.
    pub fn pieces(&self) -> [[[f64; 2]; 3]; 3] {
        let v = self.vertices;
        [[v[0], v[1], self.center], [v[1], v[2], self.center], [v[2], v[0], self.center]]
    }

    /// The piece containing `x` (the one whose barycentric coordinates are least negative,
    /// so a point on a shared edge or slightly outside gets a neighbouring piece).
    pub fn locate(&self, x: [f64; 2]) -> usize {
        let mut best = (0, f64::NEG_INFINITY);
        for (k, [a, b, c]) in self.pieces().into_iter().enumerate() {
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            let l1 = ((x[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (x[1] - a[1])) / det;
            let l2 = ((b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1])) / det;
            let worst = l1.min(l2).min(1.0 - l1 - l2);
            if worst > best.1 {
                best = (k, worst);
            }
        }
        best.0
    }

    fn scaled(&self, x: [f64; 2]) -> [f64; 2] {
        let (k, d) = (&self.map, [x[0] - self.origin[0], x[1] - self.origin[1]]);
        [k[0][0] * d[0] + k[0][1] * d[1] + self.offset[0], k[1][0] * d[0] + k[1][1] * d[1] + self.offset[1]]
    }

    /// The 12 basis functions at `x`, on piece `piece`.
    pub fn values(&self, piece: usize, x: [f64; 2]) -> [f64; HCT_DOFS] {
        let m = monomials(self.scaled(x));
        let mut out = [0.0; HCT_DOFS];
        for (o, c) in out.iter_mut().zip(&self.coefficients[piece]) {
            *o = c.iter().zip(&m).map(|(a, b)| a * b).sum();
        }
        out
    }

    /// Gradients `(∂/∂x, ∂/∂y)` of the basis functions at `x` on `piece`.
    pub fn gradients(&self, piece: usize, x: [f64; 2]) -> [[f64; 2]; HCT_DOFS] {
        let g = monomial_gradients(self.scaled(x));
        let mut out = [[0.0; 2]; HCT_DOFS];
        let k = &self.map;
        for (o, c) in out.iter_mut().zip(&self.coefficients[piece]) {
            // ∂/∂x_d = Σ_r K[r][d] ∂/∂ξ_r.
            let d: [f64; 2] = [0, 1].map(|r| c.iter().zip(&g[r]).map(|(a, b)| a * b).sum::<f64>());
            *o = [k[0][0] * d[0] + k[1][0] * d[1], k[0][1] * d[0] + k[1][1] * d[1]];
        }
        out
    }

    /// Second derivatives `(∂²/∂x², ∂²/∂y², ∂²/∂x∂y)` of the basis functions at `x` on `piece`.
    pub fn hessians(&self, piece: usize, x: [f64; 2]) -> [[f64; 3]; HCT_DOFS] {
        let g = monomial_hessians(self.scaled(x));
        let k = &self.map;
        let mut out = [[0.0; 3]; HCT_DOFS];
        for (o, c) in out.iter_mut().zip(&self.coefficients[piece]) {
            // H = Kᵀ Ĥ K.
            let [hxx, hyy, hxy] = [0, 1, 2].map(|r| c.iter().zip(&g[r]).map(|(a, b)| a * b).sum::<f64>());
            let entry = |p: usize, q: usize| {
                k[0][p] * (hxx * k[0][q] + hxy * k[1][q]) + k[1][p] * (hxy * k[0][q] + hyy * k[1][q])
            };
            *o = [entry(0, 0), entry(1, 1), entry(0, 1)];
        }
        out
    }

    /// The Airy stresses `(σxx, σyy, σxy) = (ψ,yy, ψ,xx, −ψ,xy)` of the basis functions.
    pub fn stresses(&self, piece: usize, x: [f64; 2]) -> [[f64; 3]; HCT_DOFS] {
        let mut s = self.hessians(piece, x);
        for v in s.iter_mut() {
            *v = [v[1], v[0], -v[2]];
        }
        s
    }

    /// `S_E[i][j] = ∫_E σ(ψ_i) : C⁻¹ σ(ψ_j)` (see the module doc).
    pub fn compliance_stiffness(&self, material: &Material) -> SMatrix<f64, HCT_DOFS, HCT_DOFS> {
        let compliance = material.compliance();
        let rule = quadrature::triangle(2);
        let mut s = SMatrix::<f64, HCT_DOFS, HCT_DOFS>::zeros();
        for (piece, triangle) in self.pieces().into_iter().enumerate() {
            for (x, w) in quadrature::on_triangle(&rule, triangle) {
                let sig = self.stresses(piece, x);
                let mut strain = [[0.0; 3]; HCT_DOFS];
                for (e, s) in strain.iter_mut().zip(&sig) {
                    for r in 0..3 {
                        e[r] = (0..3).map(|q| compliance[r][q] * s[q]).sum();
                    }
                }
                for i in 0..HCT_DOFS {
                    for j in 0..HCT_DOFS {
                        s[(i, j)] += w * (0..3).map(|r| sig[i][r] * strain[j][r]).sum::<f64>();
                    }
                }
            }
        }
        s
    }

    /// The degree-of-freedom values of a function given with its gradient (for interpolation
    /// and tests): `f(x) -> (φ, φ,x, φ,y)`. `edge_sign` as in [`HctElement::new`].
    pub fn interpolate(
        vertices: [[f64; 2]; 3],
        edge_sign: [f64; 3],
        f: impl Fn([f64; 2]) -> [f64; 3],
    ) -> [f64; HCT_DOFS] {
        let mut dofs = [0.0; HCT_DOFS];
        for k in 0..3 {
            let v = f(vertices[k]);
            dofs[3 * k..3 * k + 3].copy_from_slice(&v);
            let (p, q) = (vertices[k], vertices[(k + 1) % 3]);
            let d = [q[0] - p[0], q[1] - p[1]];
            let len = d[0].hypot(d[1]);
            let n = [edge_sign[k] * d[1] / len, -edge_sign[k] * d[0] / len];
            let m = f([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]);
            dofs[9 + k] = n[0] * m[1] + n[1] * m[2];
        }
        dofs
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::material::PlaneModel;

    /// The cubic `Σ c_i m_i((x − o)/s)` with its gradient and Hessian (xx, yy, xy).
    fn cubic(c: [f64; 10], o: [f64; 2], s: f64) -> impl Fn([f64; 2]) -> ([f64; 3], [f64; 3]) {
        move |x: [f64; 2]| {
            let p = [(x[0] - o[0]) / s, (x[1] - o[1]) / s];
            let m = monomials(p);
            let g = monomial_gradients(p);
            let h = monomial_hessians(p);
            let dot = |a: &[f64; 10]| a.iter().zip(&c).map(|(x, y)| x * y).sum::<f64>();
            (
                [dot(&m), dot(&g[0]) / s, dot(&g[1]) / s],
                [dot(&h[0]) / (s * s), dot(&h[1]) / (s * s), dot(&h[2]) / (s * s)],
            )
        }
    }

    fn triangles() -> Vec<[[f64; 2]; 3]> {
        vec![
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]],
            // Aspect ratio 1e2.
            [[0.0, 0.0], [1.0, 0.0], [0.5, 0.01]],
            // An obtuse angle of about 170 degrees.
            [[0.0, 0.0], [2.0, 0.0], [1.0, 0.0882]],
            // Tiny, far from the origin.
            [[1e4, 2e4], [1e4 + 1e-3, 2e4 + 2e-4], [1e4 - 3e-4, 2e4 + 1.1e-3]],
            // Big.
            [[-3e3, 1e3], [5e3, -2e3], [1e3, 4e3]],
        ]
    }

    fn check_reproduction(t: [[f64; 2]; 3], signs: [f64; 3], c: [f64; 10]) {
        // The cubic in coordinates centred on the triangle and scaled by its size, so that its
        // value, gradient and Hessian are all of their natural sizes there.
        let o = t[0];
        let size = (t[1][0] - o[0]).hypot(t[1][1] - o[1]);
        let f = cubic(c, o, size);
        let element = HctElement::new(t, signs).unwrap();
        let dofs = HctElement::interpolate(t, signs, |x| f(x).0);
        let (mut scale_v, mut scale_g, mut scale_h) = (0.0f64, 0.0f64, 0.0f64);
        let mut points = Vec::new();
        for (piece, [a, b, cc]) in element.pieces().into_iter().enumerate() {
            for (l1, l2) in [(0.2, 0.3), (0.6, 0.1), (0.1, 0.8), (1.0 / 3.0, 1.0 / 3.0), (0.0, 0.5), (1.0, 0.0)] {
                let x =
                    [a[0] + l1 * (b[0] - a[0]) + l2 * (cc[0] - a[0]), a[1] + l1 * (b[1] - a[1]) + l2 * (cc[1] - a[1])];
                let (v, h) = f(x);
                scale_v = scale_v.max(v[0].abs());
                scale_g = scale_g.max(v[1].abs()).max(v[2].abs());
                scale_h = scale_h.max(h[0].abs()).max(h[1].abs()).max(h[2].abs());
                points.push((piece, x, v, h));
            }
        }
        // One scale for the function, its derivatives times the size, and so on.
        // The coordinates themselves carry round-off of eps·|x| (1e-12 on the tiny triangle far
        // from the origin, 1e-9 of its size): that is the floor of any comparison.
        let far = t.iter().map(|p| p[0].abs().max(p[1].abs())).fold(0.0f64, f64::max);
        let geometric = f64::EPSILON * far / size;
        let scale = scale_v.max(scale_g * size).max(scale_h * size * size);
        let (tol_v, tol_g, tol_h) = (1e-11 + 10.0 * geometric, 1e-10 + 1e2 * geometric, 1e-8 + 1e4 * geometric);
        let (bound_v, bound_g, bound_h) = (tol_v * scale, tol_g * scale / size, tol_h * scale / (size * size));
        for (piece, x, v, h) in points {
            let values = element.values(piece, x);
            let grads = element.gradients(piece, x);
            let hess = element.hessians(piece, x);
            let phi: f64 = values.iter().zip(&dofs).map(|(a, b)| a * b).sum();
            assert!((phi - v[0]).abs() <= bound_v, "{t:?} value {phi} vs {}", v[0]);
            for d in 0..2 {
                let g: f64 = grads.iter().zip(&dofs).map(|(a, b)| a[d] * b).sum();
                assert!((g - v[1 + d]).abs() <= bound_g, "{t:?} gradient {d}: {g} vs {}", v[1 + d]);
            }
            for d in 0..3 {
                let s: f64 = hess.iter().zip(&dofs).map(|(a, b)| a[d] * b).sum();
                assert!((s - h[d]).abs() <= bound_h, "{t:?} hessian {d}: {s} vs {}", h[d]);
            }
        }
    }

    #[test]
    fn reproduces_every_cubic_on_distorted_triangles() {
        for t in triangles() {
            for k in 0..10 {
                let mut c = [0.0; 10];
                c[k] = 1.0;
                check_reproduction(t, [1.0, -1.0, 1.0], c);
            }
            check_reproduction(t, [-1.0, 1.0, 1.0], [0.3, -1.2, 0.7, 2.0, -0.4, 1.1, 0.9, -0.6, 0.25, -1.7]);
        }
    }

    #[test]
    fn neighbours_are_c1_across_their_shared_edge() {
        // Two triangles sharing the edge (p, q), seen in opposite directions; global vertex
        // numbers 0: p, 1: q, 2: r, 3: s. Random shared dofs, random private ones.
        let (p, q, r, s) = ([0.1, -0.2], [1.3, 0.4], [0.2, 1.1], [1.0, -1.0]);
        let left = [p, q, r]; // edge 0 = p -> q, numbers 0 -> 1: sign +1
        let right = [q, p, s]; // edge 0 = q -> p, numbers 1 -> 0: sign −1
        let signs_left = [1.0, -1.0, 1.0]; // q(1) -> r(2): +1; r(2) -> p(0): −1
        let signs_right = [-1.0, 1.0, -1.0]; // p(0) -> s(3): +1; s(3) -> q(1): −1
        let el = HctElement::new(left, signs_left).unwrap();
        let er = HctElement::new(right, signs_right).unwrap();
        let vp = [0.3, -1.1, 0.8];
        let vq = [-0.7, 0.2, 1.9];
        let dn_pq = 0.45;
        let dl = [vp[0], vp[1], vp[2], vq[0], vq[1], vq[2], 2.0, -0.3, 0.6, dn_pq, 0.9, -1.4];
        let dr = [vq[0], vq[1], vq[2], vp[0], vp[1], vp[2], -1.2, 0.8, 0.1, dn_pq, -0.5, 0.35];
        let eval = |e: &HctElement, dofs: &[f64; 12], x: [f64; 2]| {
            let piece = e.locate(x);
            let v = e.values(piece, x);
            let g = e.gradients(piece, x);
            let phi: f64 = v.iter().zip(dofs).map(|(a, b)| a * b).sum();
            let gx: f64 = g.iter().zip(dofs).map(|(a, b)| a[0] * b).sum();
            let gy: f64 = g.iter().zip(dofs).map(|(a, b)| a[1] * b).sum();
            (phi, gx, gy)
        };
        for k in 0..=20 {
            let t = k as f64 / 20.0;
            let x = [p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])];
            let (a, b) = (eval(&el, &dl, x), eval(&er, &dr, x));
            assert!((a.0 - b.0).abs() < 1e-13, "value jump {} at t = {t}", a.0 - b.0);
            assert!((a.1 - b.1).abs() < 1e-12 && (a.2 - b.2).abs() < 1e-12, "gradient jump at t = {t}: {a:?} {b:?}");
        }
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn c1_inside_the_element() {
        let t = [[0.0, 0.0], [2.0, 0.3], [0.4, 1.5]];
        let e = HctElement::new(t, [1.0, 1.0, -1.0]).unwrap();
        let dofs = [0.3, -1.0, 0.5, 1.2, 0.1, -0.7, -0.4, 0.9, 0.2, 1.5, -0.8, 0.6];
        let c = [(t[0][0] + t[1][0] + t[2][0]) / 3.0, (t[0][1] + t[1][1] + t[2][1]) / 3.0];
        for k in 0..3 {
            // Interior edge c -> a_k between pieces k−1 and k.
            for s in [0.0, 0.25, 0.5, 0.9] {
                let x = [c[0] + s * (t[k][0] - c[0]), c[1] + s * (t[k][1] - c[1])];
                let (l, r) = ((k + 2) % 3, k);
                let vl: f64 = e.values(l, x).iter().zip(&dofs).map(|(a, b)| a * b).sum();
                let vr: f64 = e.values(r, x).iter().zip(&dofs).map(|(a, b)| a * b).sum();
                assert!((vl - vr).abs() < 1e-13);
                let (gl, gr) = (e.gradients(l, x), e.gradients(r, x));
                for d in 0..2 {
                    let a: f64 = gl.iter().zip(&dofs).map(|(g, b)| g[d] * b).sum();
                    let b: f64 = gr.iter().zip(&dofs).map(|(g, b)| g[d] * b).sum();
                    assert!((a - b).abs() < 1e-12, "gradient jump {} across c-a{k}", a - b);
                }
            }
        }
    }

    #[test]
    fn compliance_stiffness_kernel_is_the_affine_functions_and_energy_is_exact() {
        let t = [[0.0, 0.0], [2.0, 0.3], [0.4, 1.5]];
        let signs = [1.0, -1.0, 1.0];
        let e = HctElement::new(t, signs).unwrap();
        for plane in [PlaneModel::Strain, PlaneModel::Stress] {
            let material = Material::new(2e11, 0.3, plane);
            let s = e.compliance_stiffness(&material);
            assert!((s - s.transpose()).abs().max() <= 1e-14 * s.abs().max());
            let mut eig = s.symmetric_eigenvalues().as_slice().to_vec();
            eig.sort_by(|a, b| a.partial_cmp(b).unwrap());
            let top = eig[11];
            assert!(eig[..3].iter().all(|v| v.abs() < 1e-12 * top), "{eig:?}");
            assert!(eig[3] > 1e-8 * top, "kernel larger than the affine functions: {eig:?}");
            // φ = a x²/2 + b x y + c y²/2: σ = (c, a, −b) uniform; energy = area · σ:C⁻¹σ.
            let (a, b, c) = (1.3, -0.4, 2.1);
            let dofs = HctElement::interpolate(t, signs, |p| {
                [
                    a * p[0] * p[0] / 2.0 + b * p[0] * p[1] + c * p[1] * p[1] / 2.0,
                    a * p[0] + b * p[1],
                    b * p[0] + c * p[1],
                ]
            });
            let v = nalgebra::SVector::<f64, 12>::from_column_slice(&dofs);
            let energy = (v.transpose() * s * v)[(0, 0)];
            let area = 0.5 * ((t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]));
            let exact = 2.0 * area * material.complementary_energy_density([c, a, -b]);
            assert!((energy - exact).abs() <= 1e-12 * exact, "{energy} vs {exact}");
        }
    }

    #[test]
    fn reference_construction_agrees_with_the_direct_one() {
        for t in triangles() {
            for signs in [[1.0, 1.0, 1.0], [-1.0, 1.0, -1.0]] {
                let fast = HctElement::new(t, signs).unwrap();
                let direct = HctElement::from_conditions(t, signs).unwrap();
                let size = (t[1][0] - t[0][0]).abs().max((t[2][1] - t[0][1]).abs()).max((t[1][1] - t[0][1]).abs());
                let far = t.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                let tol = 1e-11 + 100.0 * f64::EPSILON * far / size;
                for (piece, [p, q, r]) in fast.pieces().into_iter().enumerate() {
                    for w in [[0.2, 0.3, 0.5], [0.6, 0.2, 0.2], [0.1, 0.1, 0.8]] {
                        let x = [0, 1].map(|d| w[0] * p[d] + w[1] * q[d] + w[2] * r[d]);
                        let (v1, v2) = (fast.values(piece, x), direct.values(piece, x));
                        let (g1, g2) = (fast.gradients(piece, x), direct.gradients(piece, x));
                        let (h1, h2) = (fast.hessians(piece, x), direct.hessians(piece, x));
                        // Relative to each quantity's largest entry (anisotropic triangles
                        // have large second derivatives across their thin direction), plus the
                        // round-off of coordinates far from the origin relative to the size.
                        let vmax = v2.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                        let gmax = g2.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                        let hmax = h2.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
                        for j in 0..HCT_DOFS {
                            assert!((v1[j] - v2[j]).abs() < tol * vmax, "{t:?} value {j}: {} vs {}", v1[j], v2[j]);
                            for d in 0..2 {
                                assert!((g1[j][d] - g2[j][d]).abs() < tol * gmax, "{t:?} gradient {j}");
                            }
                            for d in 0..3 {
                                let (a, b) = (h1[j][d], h2[j][d]);
                                assert!((a - b).abs() < tol * hmax, "{t:?} hessian {j}: {a} vs {b}");
                            }
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn degenerate_triangles_are_refused() {
        assert!(HctElement::new([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]], [1.0; 3]).is_err());
        assert!(HctElement::new([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]], [1.0; 3]).is_err());
    }
}
