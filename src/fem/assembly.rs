//! Assembly of the plane-elasticity system `K u = f` with Dirichlet constraints, row block by
//! row block.
//!
//! # Weak form and element matrices
//!
//! Find `u ∈ V_h` with `u = g` on Γ_D and, for all `v ∈ V_h` vanishing on Γ_D,
//!
//! ```text
//!   ∫_Ω ε(v) : C ε(u) dx  =  ∫_Ω F · v dx  +  ∫_Γ_N t · v ds .
//! ```
//!
//! Unknowns are interleaved: `dof = 2 * node + component` (0 = x, 1 = y). With the strain
//! operator of node `a`
//!
//! ```text
//!         [ ∂N_a/∂x     0     ]                                   (εxx)
//!   B_a = [    0     ∂N_a/∂y  ] ,   e = (εxx, εyy, γxy) = Σ_a B_a (u_a),
//!         [ ∂N_a/∂y  ∂N_a/∂x  ]                                   (γxy = 2 εxy)
//! ```
//!
//! the 2×2 block coupling nodes `a` and `b` is `K_ab = ∫_T B_aᵀ C B_b dx`
//! (Hughes, *The Finite Element Method*, §2.8), integrated on the reference triangle with
//! `dx = det J dξ`:
//!
//! | cell | integrand | rule |
//! |---|---|---|
//! | P1 | constant | exact, closed form (`area · B_aᵀ C B_b`) |
//! | P2, straight edges | degree 2 | 3 points, exact |
//! | P2, curved (isoparametric) | rational | 6 points (degree 4) |
//! | body force `F · N_a` | any | degree `2·order + 1` (6 points for P1, 7 for P2) |
//! | traction `t · N_a ds` | any | Gauss–Legendre with `order + 2` points on the edge |
//!
//! On curved P2 edges `n ds = (y', −x') dt` is polynomial, so pressure loads integrate exactly.
//!
//! # Axisymmetry
//!
//! On a mesh of the meridian half-plane (`mesh.measure` is [`crate::mesh::Measure::Axisymmetric`],
//! the material's plane model [`PlaneModel::Axisymmetric`]), `(x, y) = (r, z)`, the strain gains the
//! hoop component `εθθ = u_r / r` and every integral the factor `2π r`:
//!
//! ```text
//!         [ ∂N_a/∂r     0     ]
//!   B_a = [    0     ∂N_a/∂z  ] ,   K_ab = ∫ B_aᵀ C B_b 2π r dA,   f_a = ∫ F N_a 2π r dA + ∫ t N_a 2π r ds,
//!         [ ∂N_a/∂z  ∂N_a/∂r  ]
//!         [  N_a/r      0     ]
//! ```
//!
//! so forces are those of the full revolution (N). The hoop term `N_a N_b / r` is rational: P1
//! cells take 3 points (degree 2), P2 cells 6 (degree 4, straight) or 7 (degree 5, curved). The
//! quadrature points are inside the cells, so `r > 0` wherever `1/r` is evaluated, also in cells
//! touching the axis; the axis nodes themselves get `u_r = 0` from the driver (the hoop strain
//! `u_r / r` would be infinite otherwise). The internal forces of a constant stress field are
//! integrated exactly (`N_a/r · σθθ · r` is a polynomial), so the patch test `u = (a r, b z)`
//! holds to round-off. (Zienkiewicz, Taylor, Zhu, *The Finite Element Method: Its Basis and
//! Fundamentals*, 7th ed., 2013, §6.2.)
//!
//! [`assemble_with`] and [`residual_forces_with`] take the element: the Lagrange element above,
//! or the locking-free P2–P0 element of [`super::mixed_pressure`] (same dofs and sparsity, its
//! own element matrices).
//!
//! # Dirichlet conditions: symmetric elimination
//!
//! For a fixed dof `j` with value `g_j`: its row and column are zeroed except for a diagonal
//! entry `E` (Young's modulus), its right-hand side becomes `E g_j`, and each free row `i` loses
//! `K_ij g_j`. The matrix stays symmetric positive definite (when the rigid motions are removed,
//! see [`Constraints::check_rigid_motions`]) and the solution has `u_j = g_j` exactly. In 2D the
//! stiffness entries scale like `E` (they are `∫ ∇N C ∇N`, dimensionless geometry times `C`),
//! so the diagonal `E` keeps the eliminated rows at the scale of the others and does not spoil
//! the condition number; it is a global constant so it is independent of the row partition.
//! The fixed dofs stay in the system (no renumbering): the numbering is the same with any set of
//! constraints.
//!
//! # Sparsity and row blocks
//!
//! The pattern is the node adjacency (nodes sharing a cell) expanded to 2×2 blocks, minus the
//! eliminated entries: a free row holds the free dofs of its node's neighbours, a fixed row holds
//! only its diagonal. No entry is stored that no element contributes to (entries whose
//! contributions cancel numerically, e.g. the xx coupling across the diagonal of a right-angled
//! structured grid, are kept). [`assemble`] produces the rows of one contiguous range of dofs (an
//! MPI rank's block; every rank holds the whole mesh): it visits only the cells touching an owned
//! node, and scatters with the position of each neighbour in the sorted adjacency of the row's
//! node plus the precomputed count of free dofs before it.
use std::borrow::Cow;
use std::ops::Range;

use super::lagrange::{self, MAX_CELL_NODES};
use super::material::{CellMaterials, Material, PlaneModel};
use super::mixed_pressure::{Element, MixedKernel};
use super::quadrature;
use crate::error::{Error, Result};
use crate::mesh::{Mesh, Order};

/// Prescribed displacement components, per dof (`dof = 2 * node + component`).
#[derive(Debug, Clone, PartialEq)]
pub struct Constraints {
    values: Vec<Option<f64>>,
}

impl Constraints {
    /// No dof fixed among `num_dofs` (`2 * mesh.num_nodes()`).
    pub fn new(num_dofs: usize) -> Self {
        Constraints { values: vec![None; num_dofs] }
    }

    /// The number of dofs (fixed and free).
    pub fn num_dofs(&self) -> usize {
        self.values.len()
    }

    /// Fix `dof` to `value` (a later call overrides an earlier one).
    ///
    /// # Panics
    /// If `dof >= self.num_dofs()` (a programming error: dofs come from the mesh).
    pub fn fix(&mut self, dof: usize, value: f64) {
        self.values[dof] = Some(value);
    }

    /// The prescribed value of `dof`, `None` if free (or out of range).
    pub fn value(&self, dof: usize) -> Option<f64> {
        self.values.get(dof).copied().flatten()
    }

    /// Whether `dof` is prescribed.
    pub fn is_fixed(&self, dof: usize) -> bool {
        self.value(dof).is_some()
    }

    /// The number of prescribed dofs.
    pub fn num_fixed(&self) -> usize {
        self.values.iter().filter(|v| v.is_some()).count()
    }

    /// The fixed dofs and their values, in increasing dof order.
    pub fn fixed(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.values.iter().enumerate().filter_map(|(d, v)| v.map(|g| (d, g)))
    }

    /// Fix component `comp` (0 = x, 1 = y) of every node on the edges of `group` (incl. P2 mid
    /// nodes) to `f(x)`.
    ///
    /// # Panics
    /// If `comp > 1` or the constraints were made for fewer dofs than the mesh has.
    pub fn fix_group(&mut self, mesh: &Mesh, group: usize, comp: usize, f: impl Fn([f64; 2]) -> f64) {
        assert!(comp < 2, "displacement component must be 0 (x) or 1 (y), got {comp}");
        for e in mesh.edges_in_group(group) {
            for &n in mesh.edge(e) {
                self.fix(2 * n + comp, f(mesh.nodes[n]));
            }
        }
    }

    /// `Error::Unconstrained` naming the rigid motions ("translation in x", "translation in y",
    /// "rotation about z") that the fixed dofs leave free.
    ///
    /// A rigid motion `(a − ω y, b + ω x)` is blocked iff some fixed dof sees it: a fixed x dof at
    /// `(x, y)` imposes `a − ω y = 0`, a fixed y dof `b + ω x = 0`. Stacking the rows `(1, 0, −y)`
    /// and `(0, 1, x)` (coordinates centred on the mesh's bounding box and scaled by its size, so
    /// the test does not depend on units or position), the motions are all blocked iff the 3×3
    /// Gram matrix of the rows has rank 3; the rank counts eigenvalues above `1e-10` times the
    /// largest.
    ///
    /// In axisymmetry the one rigid motion is the translation along the axis (`u_z` constant): a
    /// radial translation and an in-plane rotation stretch the hoop fibres. It is blocked iff
    /// some `u_z` (y dof) is fixed.
    pub fn check_rigid_motions(&self, mesh: &Mesh) -> Result<()> {
        if mesh.measure.is_axisymmetric() {
            if self.fixed().any(|(dof, _)| dof % 2 == 1 && dof / 2 < mesh.num_nodes()) {
                return Ok(());
            }
            return Err(Error::Unconstrained(
                "the displacement conditions leave 1 rigid motion free: translation in z (along the axis; no uy \
                 component is fixed); fix uy on a boundary part (e.g. a symmetry plane z = const) or at one node"
                    .into(),
            ));
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &mesh.nodes {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let centre = if mesh.nodes.is_empty() { [0.0; 2] } else { [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])] };
        let mut scale = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if !(scale.is_finite() && scale > 0.0) {
            scale = 1.0;
        }
        let mut gram = nalgebra::Matrix3::<f64>::zeros();
        let (mut num_x, mut num_y) = (0usize, 0usize);
        for (dof, _) in self.fixed() {
            let Some(p) = mesh.nodes.get(dof / 2) else {
                continue;
            };
            let (x, y) = ((p[0] - centre[0]) / scale, (p[1] - centre[1]) / scale);
            let row = if dof % 2 == 0 {
                num_x += 1;
                nalgebra::Vector3::new(1.0, 0.0, -y)
            } else {
                num_y += 1;
                nalgebra::Vector3::new(0.0, 1.0, x)
            };
            gram += row * row.transpose();
        }
        let eigen = nalgebra::SymmetricEigen::new(gram);
        let largest = eigen.eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
        let null: Vec<usize> = (0..3).filter(|&k| largest == 0.0 || eigen.eigenvalues[k] <= 1e-10 * largest).collect();
        if null.is_empty() {
            return Ok(());
        }
        let mut free = Vec::new();
        if num_x == 0 {
            free.push("translation in x".to_string());
        }
        if num_y == 0 {
            free.push("translation in y".to_string());
        }
        if null.len() > free.len() {
            if free.is_empty() && null.len() == 1 {
                // One free motion, a pure rotation (a − ω Y, b + ω X) about (X, Y) = (−b/ω, a/ω).
                let v = eigen.eigenvectors.column(null[0]);
                let (a, b) = (v[0] / v[2], v[1] / v[2]);
                // Snap round-off to zero so the point reads cleanly.
                let snap = |v: f64| if v.abs() <= 1e-12 * scale { 0.0 } else { v };
                let px = snap(centre[0] - scale * b);
                let py = snap(centre[1] + scale * a);
                free.push(format!("rotation about z (about the point ({px:.6e}, {py:.6e}))"));
            } else {
                free.push("rotation about z".to_string());
            }
        }
        Err(Error::Unconstrained(format!(
            "the displacement conditions leave {} rigid motion{} free: {} ({} x and {} y displacement components are fixed); \
             fix more components, e.g. clamp a boundary part, or fix x and y at one node and the normal component at another node away from it",
            free.len(),
            if free.len() == 1 { "" } else { "s" },
            free.join(", "),
            num_x,
            num_y
        )))
    }
}

/// A surface load on the edges of a boundary group.
#[derive(Clone, Copy)]
pub enum Traction<'a> {
    /// A constant traction vector `t` (force per unit area of the boundary: per unit length of
    /// an edge and unit thickness in the plane, per unit area of the revolved surface in axisymmetry).
    Constant([f64; 2]),
    /// A pressure `p`: `t = −p n` (positive pushes into the body).
    Pressure(f64),
    /// `t = f(x, n)` with `n` the unit outward normal at `x`.
    Field(&'a (dyn Fn([f64; 2], [f64; 2]) -> [f64; 2] + Sync)),
}

impl Traction<'_> {
    /// The traction vector at `x` on an edge of unit outward normal `n`.
    pub fn at(&self, x: [f64; 2], n: [f64; 2]) -> [f64; 2] {
        match self {
            Traction::Constant(t) => *t,
            Traction::Pressure(p) => [-p * n[0], -p * n[1]],
            Traction::Field(f) => f(x, n),
        }
    }
}

/// A traction applied on the boundary edges of group `group` (an index into `mesh.groups`).
#[derive(Clone, Copy)]
pub struct EdgeLoad<'a> {
    /// The boundary group (index into `mesh.groups`).
    pub group: usize,
    /// The traction on it.
    pub traction: Traction<'a>,
}

/// Volume and surface loads.
#[derive(Clone, Default)]
pub struct Loads<'a> {
    /// Body force per unit volume `F(x)` (N/m³).
    pub body_force: Option<&'a (dyn Fn([f64; 2]) -> [f64; 2] + Sync)>,
    /// Tractions on boundary groups.
    pub edge_loads: Vec<EdgeLoad<'a>>,
}

/// Rows `first_row .. first_row + indptr.len() − 1` of the global CSR matrix. `indptr` is local
/// (starts at 0); column indices are global and sorted within each row.
#[derive(Debug, Clone, PartialEq)]
pub struct CsrRows {
    /// Global index of the first row held.
    pub first_row: usize,
    /// Number of columns of the global matrix.
    pub num_cols: usize,
    /// Start of each row in `indices` and `values` (local rows, length rows + 1).
    pub indptr: Vec<usize>,
    /// Global column index of each stored entry.
    pub indices: Vec<usize>,
    /// Value of each stored entry.
    pub values: Vec<f64>,
}

impl CsrRows {
    /// Number of rows held.
    pub fn num_rows(&self) -> usize {
        self.indptr.len().saturating_sub(1)
    }
    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.indices.len()
    }
    /// Column indices and values of global row `row` (empty if not owned).
    pub fn row(&self, row: usize) -> (&[usize], &[f64]) {
        match row.checked_sub(self.first_row) {
            Some(r) if r < self.num_rows() => {
                let span = self.indptr[r]..self.indptr[r + 1];
                (&self.indices[span.clone()], &self.values[span])
            }
            _ => (&[], &[]),
        }
    }
    /// Entry `(row, col)`, 0 when not stored.
    pub fn get(&self, row: usize, col: usize) -> f64 {
        let (cols, vals) = self.row(row);
        cols.binary_search(&col).map(|k| vals[k]).unwrap_or(0.0)
    }
}

/// The owned rows of the constrained system and their right-hand side.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearSystem {
    /// The owned rows of the stiffness matrix, constraints applied.
    pub matrix: CsrRows,
    /// Right-hand side of the owned rows only (`rhs[r]` is global row `matrix.first_row + r`).
    pub rhs: Vec<f64>,
}

/// 2×2 coupling block `[component of row node][component of column node]`.
type Block = [[f64; 2]; 2];

/// The element stiffness computations of one mesh, with the reference tables they need.
struct StiffnessKernel {
    c: [[f64; 3]; 3],
    /// P2 straight cells (degree 2) and curved cells (degree 4): weights and reference gradients.
    straight: ReferenceTable,
    curved: ReferenceTable,
    /// In axisymmetry: the hoop terms and their quadrature tables.
    axisymmetric: Option<AxisymmetricKernel>,
}

/// The axisymmetric element matrices `K_ab = ∫ B_aᵀ C B_b 2π r dA` (module doc): the strain
/// operator of node `a` has the hoop row `(N_a / r, 0)`, and `C` couples the hoop strain to the
/// normal strains with `coupling` and to itself with `diagonal` (`λ` and `λ + 2μ` for Hooke's law;
/// `−2G/3` and `4G/3` for the deviatoric part of [`super::mixed_pressure`]).
pub(super) struct AxisymmetricKernel {
    pub(super) coupling: f64,
    pub(super) diagonal: f64,
    /// P1 cells: degree 2 (3 points); P2 straight: degree 4 (6 points); P2 curved: degree 5 (7).
    p1: ReferenceTable,
    pub(super) straight: ReferenceTable,
    pub(super) curved: ReferenceTable,
}

impl AxisymmetricKernel {
    pub(super) fn new(coupling: f64, diagonal: f64) -> Self {
        AxisymmetricKernel {
            coupling,
            diagonal,
            p1: ReferenceTable::new(Order::P1, 2),
            straight: ReferenceTable::new(Order::P2, 4),
            curved: ReferenceTable::new(Order::P2, 5),
        }
    }

    /// `∫ B_aᵀ C B_b 2π r dA` over the cell of coordinates `x` (3 or 6 nodes), `c` the in-plane
    /// block of `C`. Every quadrature point is inside the cell, so `r > 0` there (the mesh has
    /// `r ≥ 0` and cells of positive area).
    pub(super) fn cell<const N: usize>(&self, c: &[[f64; 3]; 3], x: &[[f64; 2]; N]) -> [[Block; N]; N] {
        let table = match N {
            3 => &self.p1,
            _ if lagrange::is_affine(x) => &self.straight,
            _ => &self.curved,
        };
        let mut k = [[[[0.0; 2]; 2]; N]; N];
        for q in 0..table.weights.len() {
            let (values, rg) = (&table.values[q][..N], &table.grads[q][..N]);
            let j = lagrange::jacobian(x, rg);
            let det = lagrange::determinant(&j);
            let g = lagrange::physical_gradients(&j, det, rg);
            let r = lagrange::map_point(x, values)[0];
            let w = table.weights[q] * det * 2.0 * std::f64::consts::PI * r;
            let inv_r = 1.0 / r;
            for a in 0..N {
                for b in a..N {
                    add_btcb(&mut k[a][b], c, g[a], g[b], w);
                    self.add_hoop(&mut k[a][b], (g[a], values[a] * inv_r), (g[b], values[b] * inv_r), w);
                }
            }
        }
        symmetrize(&mut k);
        k
    }

    /// The hoop terms of `w · B_aᵀ C B_b`: `ha = N_a / r`, `hb = N_b / r`, `C` with
    /// `C_θθ,rr = C_θθ,zz = coupling` and `C_θθ,θθ = diagonal` (and `C_θθ,rz = 0`).
    #[inline(always)]
    fn add_hoop(&self, block: &mut Block, (ga, ha): ([f64; 2], f64), (gb, hb): ([f64; 2], f64), w: f64) {
        let (coupling, diagonal) = (self.coupling, self.diagonal);
        block[0][0] += w * (coupling * (ha * gb[0] + ga[0] * hb) + diagonal * ha * hb);
        block[0][1] += w * coupling * ha * gb[1];
        block[1][0] += w * coupling * ga[1] * hb;
    }
}

pub(super) struct ReferenceTable {
    pub(super) weights: Vec<f64>,
    pub(super) values: Vec<[f64; MAX_CELL_NODES]>,
    pub(super) grads: Vec<[[f64; 2]; MAX_CELL_NODES]>,
}

impl ReferenceTable {
    pub(super) fn new(order: Order, degree: usize) -> Self {
        let rule = quadrature::triangle(degree);
        ReferenceTable {
            values: rule.points.iter().map(|&p| lagrange::shape_values(order, p)).collect(),
            grads: rule.points.iter().map(|&p| lagrange::shape_gradients(order, p)).collect(),
            weights: rule.weights,
        }
    }
}

/// `block += w · B_aᵀ C B_b` for physical gradients `ga`, `gb`.
#[inline(always)]
fn add_btcb(block: &mut Block, c: &[[f64; 3]; 3], ga: [f64; 2], gb: [f64; 2], w: f64) {
    let (ax, ay) = (ga[0], ga[1]);
    let (bx, by) = (gb[0], gb[1]);
    // Columns of C B_b for the x and y displacement of node b: C (bx, 0, by) and C (0, by, bx).
    let cx = [c[0][0] * bx + c[0][2] * by, c[1][0] * bx + c[1][2] * by, c[2][0] * bx + c[2][2] * by];
    let cy = [c[0][1] * by + c[0][2] * bx, c[1][1] * by + c[1][2] * bx, c[2][1] * by + c[2][2] * bx];
    block[0][0] += w * (ax * cx[0] + ay * cx[2]);
    block[0][1] += w * (ax * cy[0] + ay * cy[2]);
    block[1][0] += w * (ay * cx[1] + ax * cx[2]);
    block[1][1] += w * (ay * cy[1] + ax * cy[2]);
}

/// Fill the lower triangle of blocks from the upper one (`K_ba = K_abᵀ`).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // block indices read best as indices
fn symmetrize<const N: usize>(k: &mut [[Block; N]; N]) {
    for a in 0..N {
        for b in 0..a {
            let t = k[b][a];
            k[a][b] = [[t[0][0], t[1][0]], [t[0][1], t[1][1]]];
        }
    }
}

impl StiffnessKernel {
    fn new(material: &Material) -> Self {
        let (lambda, mu) = material.lame();
        StiffnessKernel {
            c: material.elasticity(),
            straight: ReferenceTable::new(Order::P2, 2),
            curved: ReferenceTable::new(Order::P2, 4),
            axisymmetric: (material.plane == PlaneModel::Axisymmetric)
                .then(|| AxisymmetricKernel::new(lambda, lambda + 2.0 * mu)),
        }
    }

    /// P1: gradients are constant, `K_ab = area · B_aᵀ C B_b` (axisymmetric: quadrature).
    #[inline(always)]
    fn p1(&self, x: &[[f64; 2]; 3]) -> [[Block; 3]; 3] {
        if let Some(axi) = &self.axisymmetric {
            return axi.cell(&self.c, x);
        }
        let j = [[x[1][0] - x[0][0], x[2][0] - x[0][0]], [x[1][1] - x[0][1], x[2][1] - x[0][1]]];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        let inv = 1.0 / det;
        // ∇N1 = (J11, −J01)/det, ∇N2 = (−J10, J00)/det, ∇N0 = −∇N1 − ∇N2.
        let g1 = [j[1][1] * inv, -j[0][1] * inv];
        let g2 = [-j[1][0] * inv, j[0][0] * inv];
        let g = [[-g1[0] - g2[0], -g1[1] - g2[1]], g1, g2];
        let area = 0.5 * det;
        let mut k = [[[[0.0; 2]; 2]; 3]; 3];
        for a in 0..3 {
            for b in a..3 {
                add_btcb(&mut k[a][b], &self.c, g[a], g[b], area);
            }
        }
        symmetrize(&mut k);
        k
    }

    /// P2 (straight or curved): quadrature on the reference triangle.
    fn p2(&self, x: &[[f64; 2]; 6]) -> [[Block; 6]; 6] {
        if let Some(axi) = &self.axisymmetric {
            return axi.cell(&self.c, x);
        }
        let table = if lagrange::is_affine(x) { &self.straight } else { &self.curved };
        let mut k = [[[[0.0; 2]; 2]; 6]; 6];
        for (w, rg) in table.weights.iter().zip(&table.grads) {
            let j = lagrange::jacobian(x, rg);
            let det = lagrange::determinant(&j);
            let g = lagrange::physical_gradients(&j, det, rg);
            let wd = w * det;
            for a in 0..6 {
                for b in a..6 {
                    add_btcb(&mut k[a][b], &self.c, g[a], g[b], wd);
                }
            }
        }
        symmetrize(&mut k);
        k
    }
}

/// The element stiffness matrix of one cell, row-major `(2n) × (2n)` with `n =
/// order.nodes_per_cell()` and local dof `2 * local_node + component`; `coords` are the cell's
/// node coordinates in mesh order (`n` of them). Quadrature as in the module doc.
pub fn element_stiffness(order: Order, coords: &[[f64; 2]], material: &Material) -> Vec<f64> {
    let kernel = StiffnessKernel::new(material);
    match order {
        Order::P1 => blocks_to_dense(&kernel.p1(&std::array::from_fn(|k| coords[k]))),
        Order::P2 => blocks_to_dense(&kernel.p2(&std::array::from_fn(|k| coords[k]))),
    }
}

fn blocks_to_dense<const N: usize>(k: &[[Block; N]; N]) -> Vec<f64> {
    let m = 2 * N;
    let mut out = vec![0.0; m * m];
    for a in 0..N {
        for b in 0..N {
            for c in 0..2 {
                for d in 0..2 {
                    out[(2 * a + c) * m + 2 * b + d] = k[a][b][c][d];
                }
            }
        }
    }
    out
}

/// Loads integrated cell by cell and edge by edge; `sink(dof, value)` receives each contribution.
/// `touches(node)` selects the cells / edges to visit (those with at least one such node).
#[allow(clippy::needless_range_loop)] // local node indices address several arrays
fn integrate_loads(mesh: &Mesh, loads: &Loads, touches: impl Fn(usize) -> bool, mut sink: impl FnMut(usize, f64)) {
    let order = mesh.order;
    let npc = order.nodes_per_cell();
    if let Some(force) = loads.body_force {
        let table = ReferenceTable::new(order, 2 * order.degree() + 1);
        let mut x = [[0.0; 2]; MAX_CELL_NODES];
        for c in 0..mesh.num_cells() {
            let nodes = mesh.cell(c);
            if !nodes.iter().any(|&n| touches(n)) {
                continue;
            }
            for (xk, &n) in x.iter_mut().zip(nodes) {
                *xk = mesh.nodes[n];
            }
            let mut fe = [[0.0; 2]; MAX_CELL_NODES];
            for q in 0..table.weights.len() {
                let rg = &table.grads[q][..npc];
                let det = if order == Order::P1 {
                    (x[1][0] - x[0][0]) * (x[2][1] - x[0][1]) - (x[2][0] - x[0][0]) * (x[1][1] - x[0][1])
                } else {
                    lagrange::determinant(&lagrange::jacobian(&x[..npc], rg))
                };
                let nv = &table.values[q];
                let point = lagrange::map_point(&x[..npc], &nv[..npc]);
                let f = force(point);
                let w = table.weights[q] * det * mesh.measure.factor(point);
                for a in 0..npc {
                    fe[a][0] += w * nv[a] * f[0];
                    fe[a][1] += w * nv[a] * f[1];
                }
            }
            for a in 0..npc {
                sink(2 * nodes[a], fe[a][0]);
                sink(2 * nodes[a] + 1, fe[a][1]);
            }
        }
    }
    if loads.edge_loads.is_empty() {
        return;
    }
    let npe = order.nodes_per_edge();
    let rule = quadrature::gauss_legendre(order.degree() + 2);
    for load in &loads.edge_loads {
        for e in mesh.edges_in_group(load.group) {
            let nodes = mesh.edge(e);
            if !nodes.iter().any(|&n| touches(n)) {
                continue;
            }
            let x: Vec<[f64; 2]> = nodes.iter().map(|&n| mesh.nodes[n]).collect();
            let mut fe = [[0.0; 2]; 3];
            for (&t, &w) in rule.points.iter().zip(&rule.weights) {
                let p = lagrange::map_edge_point(&x, t);
                let tr = load.traction.at(p.x, p.normal);
                let wds = w * p.length_element * mesh.measure.factor(p.x);
                for a in 0..npe {
                    fe[a][0] += wds * p.values[a] * tr[0];
                    fe[a][1] += wds * p.values[a] * tr[1];
                }
            }
            for a in 0..npe {
                sink(2 * nodes[a], fe[a][0]);
                sink(2 * nodes[a] + 1, fe[a][1]);
            }
        }
    }
}

/// The global load vector (all `2 * num_nodes` dofs, no constraints): `∫ F · N + ∫ t · N`.
pub fn load_vector(mesh: &Mesh, loads: &Loads) -> Vec<f64> {
    let mut f = vec![0.0; 2 * mesh.num_nodes()];
    integrate_loads(mesh, loads, |_| true, |dof, v| f[dof] += v);
    f
}

/// `K u` for the unconstrained stiffness `K` (all dofs), computed cell by cell. On a fixed dof,
/// `(K u − f)_i` is the reaction force; on a free dof it is the equilibrium residual.
///
/// `u` must hold `2 * mesh.num_nodes()` values.
pub fn residual_forces(mesh: &Mesh, material: &Material, u: &[f64]) -> Vec<f64> {
    residual_forces_with(mesh, material, Element::Lagrange, u)
}

/// [`residual_forces`] with the stiffness of `element` (e.g. the condensed P2–P0 element).
pub fn residual_forces_with(mesh: &Mesh, material: &Material, element: Element, u: &[f64]) -> Vec<f64> {
    residual_forces_cells(mesh, &CellMaterials::uniform(*material), element, u)
}

/// [`residual_forces_with`] with a material per cell (several bodies).
pub fn residual_forces_cells(mesh: &Mesh, materials: &CellMaterials, element: Element, u: &[f64]) -> Vec<f64> {
    let kernels: Vec<StiffnessKernel> = materials.materials().iter().map(StiffnessKernel::new).collect();
    let mut y = vec![0.0; 2 * mesh.num_nodes()];
    match (mesh.order, element) {
        (Order::P1, _) => apply_cells::<3>(mesh, u, &mut y, |c, x| kernels[materials.index_of(c)].p1(x)),
        (Order::P2, Element::Lagrange) => {
            apply_cells::<6>(mesh, u, &mut y, |c, x| kernels[materials.index_of(c)].p2(x))
        }
        (Order::P2, Element::P2P0) => {
            let mixed: Vec<MixedKernel> = materials.materials().iter().map(MixedKernel::new).collect();
            apply_cells::<6>(mesh, u, &mut y, |c, x| mixed[materials.index_of(c)].p2(x))
        }
    }
    y
}

fn apply_cells<const N: usize>(
    mesh: &Mesh,
    u: &[f64],
    y: &mut [f64],
    element: impl Fn(usize, &[[f64; 2]; N]) -> [[Block; N]; N],
) {
    for (cell, nodes) in mesh.cells.chunks_exact(N).enumerate() {
        let x: [[f64; 2]; N] = std::array::from_fn(|k| mesh.nodes[nodes[k]]);
        let k = element(cell, &x);
        for a in 0..N {
            let (mut y0, mut y1) = (0.0, 0.0);
            for b in 0..N {
                let (u0, u1) = (u[2 * nodes[b]], u[2 * nodes[b] + 1]);
                y0 += k[a][b][0][0] * u0 + k[a][b][0][1] * u1;
                y1 += k[a][b][1][0] * u0 + k[a][b][1][1] * u1;
            }
            y[2 * nodes[a]] += y0;
            y[2 * nodes[a] + 1] += y1;
        }
    }
}

/// Sparsity of the owned rows: sorted neighbour lists of the owned nodes, and for each
/// neighbour entry the offset of its first free dof inside the row.
struct RowPattern {
    node_lo: usize,
    node_hi: usize,
    adj_ptr: Vec<usize>,
    adj: Vec<usize>,
    /// For adjacency entry `e` of node `n`: number of free dofs among the neighbours before it.
    offset: Vec<usize>,
}

impl RowPattern {
    fn new(mesh: &Mesh, fixed: &[Option<f64>], node_lo: usize, node_hi: usize) -> (Self, Vec<usize>) {
        let npc = mesh.order.nodes_per_cell();
        let nloc = node_hi - node_lo;
        // Node -> cells, for the owned nodes.
        let mut cell_ptr = vec![0usize; nloc + 1];
        for &n in &mesh.cells {
            if n >= node_lo && n < node_hi {
                cell_ptr[n - node_lo + 1] += 1;
            }
        }
        for k in 0..nloc {
            cell_ptr[k + 1] += cell_ptr[k];
        }
        let mut cursor = cell_ptr.clone();
        let mut node_cells = vec![0usize; cell_ptr[nloc]];
        for (k, &n) in mesh.cells.iter().enumerate() {
            if n >= node_lo && n < node_hi {
                node_cells[cursor[n - node_lo]] = k / npc;
                cursor[n - node_lo] += 1;
            }
        }
        drop(cursor);
        // Neighbour lists (including the node itself), sorted.
        let mut marker = vec![usize::MAX; mesh.num_nodes()];
        let mut adj_ptr = Vec::with_capacity(nloc + 1);
        adj_ptr.push(0);
        let mut adj = Vec::with_capacity(nloc * if npc == 3 { 7 } else { 19 });
        for n in node_lo..node_hi {
            let start = adj.len();
            for &c in &node_cells[cell_ptr[n - node_lo]..cell_ptr[n - node_lo + 1]] {
                for &m in mesh.cell(c) {
                    if marker[m] != n {
                        marker[m] = n;
                        adj.push(m);
                    }
                }
            }
            adj[start..].sort_unstable();
            adj_ptr.push(adj.len());
        }
        // Offsets of each neighbour's free dofs within the (free) rows of the node.
        let free = |d: usize| fixed[d].is_none() as usize;
        let mut offset = vec![0usize; adj.len()];
        let mut free_len = vec![0usize; nloc];
        for k in 0..nloc {
            let mut count = 0;
            for e in adj_ptr[k]..adj_ptr[k + 1] {
                offset[e] = count;
                count += free(2 * adj[e]) + free(2 * adj[e] + 1);
            }
            free_len[k] = count;
        }
        (RowPattern { node_lo, node_hi, adj_ptr, adj, offset }, free_len)
    }

    fn neighbours(&self, n: usize) -> (usize, &[usize]) {
        let k = n - self.node_lo;
        let start = self.adj_ptr[k];
        (start, &self.adj[start..self.adj_ptr[k + 1]])
    }
}

/// Assemble rows `rows` (a contiguous range of global dofs, clamped to `0..2 * num_nodes`) of
/// the constrained system (symmetric elimination, see the module doc). Every cell touching an
/// owned row contributes; loads are added to the owned free rows.
pub fn assemble(
    mesh: &Mesh,
    material: &Material,
    constraints: &Constraints,
    loads: &Loads,
    rows: Range<usize>,
) -> LinearSystem {
    assemble_with(mesh, material, Element::Lagrange, constraints, loads, rows)
}

/// [`assemble`] with the element matrices of `element` (e.g. the condensed P2–P0 element of
/// [`super::mixed_pressure`]; same dofs and sparsity).
pub fn assemble_with(
    mesh: &Mesh,
    material: &Material,
    element: Element,
    constraints: &Constraints,
    loads: &Loads,
    rows: Range<usize>,
) -> LinearSystem {
    assemble_cells(mesh, &CellMaterials::uniform(*material), element, constraints, loads, rows)
}

/// [`assemble_with`] with a material per cell (several bodies). The Dirichlet rows get the
/// largest Young's modulus as their diagonal.
pub fn assemble_cells(
    mesh: &Mesh,
    materials: &CellMaterials,
    element: Element,
    constraints: &Constraints,
    loads: &Loads,
    rows: Range<usize>,
) -> LinearSystem {
    let num_dofs = 2 * mesh.num_nodes();
    let end = rows.end.min(num_dofs);
    let start = rows.start.min(end);
    let num_rows = end - start;
    // Constraints made for another size: missing dofs are free, extra ones ignored.
    let fixed: Cow<[Option<f64>]> = if constraints.values.len() == num_dofs {
        Cow::Borrowed(&constraints.values)
    } else {
        let mut v = constraints.values.clone();
        v.resize(num_dofs, None);
        Cow::Owned(v)
    };
    let fixed: &[Option<f64>] = &fixed;
    let (node_lo, node_hi) = if num_rows == 0 { (0, 0) } else { (start / 2, end.div_ceil(2)) };
    let (pattern, free_len) = RowPattern::new(mesh, fixed, node_lo, node_hi);

    // Row pointers and column indices.
    let mut indptr = Vec::with_capacity(num_rows + 1);
    indptr.push(0usize);
    for i in start..end {
        let len = if fixed[i].is_some() { 1 } else { free_len[i / 2 - node_lo] };
        indptr.push(indptr[indptr.len() - 1] + len);
    }
    let nnz = indptr[num_rows];
    let mut indices = Vec::with_capacity(nnz);
    for i in start..end {
        if fixed[i].is_some() {
            indices.push(i);
        } else {
            let (_, neighbours) = pattern.neighbours(i / 2);
            for &m in neighbours {
                for d in [2 * m, 2 * m + 1] {
                    if fixed[d].is_none() {
                        indices.push(d);
                    }
                }
            }
        }
    }
    let mut values = vec![0.0; nnz];
    let mut rhs = vec![0.0; num_rows];
    let young = materials.max_young();
    for i in start..end {
        if let Some(g) = fixed[i] {
            values[indptr[i - start]] = young;
            rhs[i - start] = young * g;
        }
    }

    // Element matrices, scattered into the owned free rows.
    let kernels: Vec<StiffnessKernel> = materials.materials().iter().map(StiffnessKernel::new).collect();
    let mut scatter =
        Scatter { pattern: &pattern, fixed, start, end, indptr: &indptr, values: &mut values, rhs: &mut rhs };
    match (mesh.order, element) {
        (Order::P1, _) => scatter.cells::<3>(mesh, |c, x| kernels[materials.index_of(c)].p1(x)),
        (Order::P2, Element::Lagrange) => scatter.cells::<6>(mesh, |c, x| kernels[materials.index_of(c)].p2(x)),
        (Order::P2, Element::P2P0) => {
            let mixed: Vec<MixedKernel> = materials.materials().iter().map(MixedKernel::new).collect();
            scatter.cells::<6>(mesh, |c, x| mixed[materials.index_of(c)].p2(x))
        }
    }

    // Loads on the owned free rows.
    integrate_loads(
        mesh,
        loads,
        |n| n >= node_lo && n < node_hi,
        |dof, v| {
            if dof >= start && dof < end && fixed[dof].is_none() {
                rhs[dof - start] += v;
            }
        },
    );

    LinearSystem { matrix: CsrRows { first_row: start, num_cols: num_dofs, indptr, indices, values }, rhs }
}

struct Scatter<'a> {
    pattern: &'a RowPattern,
    fixed: &'a [Option<f64>],
    start: usize,
    end: usize,
    indptr: &'a [usize],
    values: &'a mut [f64],
    rhs: &'a mut [f64],
}

impl Scatter<'_> {
    fn cells<const N: usize>(&mut self, mesh: &Mesh, element: impl Fn(usize, &[[f64; 2]; N]) -> [[Block; N]; N]) {
        let (lo, hi) = (self.pattern.node_lo, self.pattern.node_hi);
        if lo == hi {
            return;
        }
        let whole = lo == 0 && hi == mesh.num_nodes();
        for (cell, nodes) in mesh.cells.chunks_exact(N).enumerate() {
            let nodes: &[usize; N] = nodes.try_into().unwrap_or(&[0; N]);
            if !whole && !nodes.iter().any(|&n| n >= lo && n < hi) {
                continue;
            }
            let x: [[f64; 2]; N] = std::array::from_fn(|k| mesh.nodes[nodes[k]]);
            let k = element(cell, &x);
            self.add::<N>(nodes, &k);
        }
    }

    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // local node indices address several arrays
    fn add<const N: usize>(&mut self, nodes: &[usize; N], k: &[[Block; N]; N]) {
        let fixed = self.fixed;
        for a in 0..N {
            let na = nodes[a];
            if na < self.pattern.node_lo || na >= self.pattern.node_hi {
                continue;
            }
            let (first, neighbours) = self.pattern.neighbours(na);
            let mut pos = [0usize; N];
            for b in 0..N {
                // Every cell node is a neighbour of na by construction.
                let e = neighbours.binary_search(&nodes[b]).unwrap_or(0);
                pos[b] = self.pattern.offset[first + e];
            }
            for c in 0..2 {
                let i = 2 * na + c;
                if i < self.start || i >= self.end || fixed[i].is_some() {
                    continue;
                }
                let r = i - self.start;
                let row_start = self.indptr[r];
                let mut rhs = 0.0;
                for b in 0..N {
                    let nb = nodes[b];
                    let base = row_start + pos[b];
                    let blk = &k[a][b][c];
                    match fixed[2 * nb] {
                        Some(g) => rhs -= blk[0] * g,
                        None => self.values[base] += blk[0],
                    }
                    match fixed[2 * nb + 1] {
                        Some(g) => rhs -= blk[1] * g,
                        None => self.values[base + fixed[2 * nb].is_none() as usize] += blk[1],
                    }
                }
                self.rhs[r] += rhs;
            }
        }
    }
}
