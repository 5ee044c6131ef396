//! The dual problem as a saddle point: every HCT dof kept, the boundary constraints imposed by
//! multipliers (the "brute" route of the source talk, solved there by SYMMLQ).
//!
//! The eliminated problem ([`DualSystem::assemble`]) writes each constrained dof `d` (a slave of
//! the traction data, or fixed) as an affine function of the free ones,
//! `φ_d = Σ_k a_dk z_k + c_d`. Here those relations are rows of a constraint matrix B instead:
//!
//! ```text
//!   [ S   Bᵀ ] [ φ ]   [ l − b_p ]        S      HCT stiffness of the compliance, all dofs
//!   [ B   0  ] [ λ ] = [ c       ]        B φ = c  one row per constrained dof:
//!                                                  s_d (φ_d − Σ_k a_dk φ_{m(k)}) = s_d c_d
//! ```
//!
//! (m(k) the dof of free unknown k, l the prescribed-displacement functional and b_p the body
//! force's cross term, as in the eliminated system). The minimiser of the complementary energy
//! under the constraints is the φ part of the solution, the same as the eliminated one. Each
//! constraint row is scaled by `s_d = √S_dd`, so that after a symmetric diagonal scaling the
//! constraint block is O(1) against the stiffness block: an iterative method preconditioned by
//! Jacobi (whose zero diagonal entries, those of the multipliers, become 1) then sees a
//! reasonably scaled saddle point.
//!
//! The matrix is symmetric indefinite. Solvers: MUMPS LDLᵀ by default (`-pc_type cholesky` on a
//! matrix declared symmetric, not definite), or SYMMLQ with a symmetric positive definite
//! preconditioner (`-ksp_type symmlq -pc_type jacobi`); CG and incomplete Cholesky do not
//! apply to an indefinite matrix.
//!
//! After the solve the constraints are restored exactly: the free unknowns are read off φ and
//! the constrained dofs recomputed from them (an iterative solve satisfies B φ = c only to its
//! tolerance, and the stress field must be exactly statically admissible for the error in the
//! constitutive relation to be an upper bound).
use std::ops::Range;

use nalgebra::SMatrix;

use super::boundary::DofRole;
use super::system::{DualSystem, ReducedRows};
use crate::error::Result;
use crate::fem::csr_assembly::CsrAssembler;
use crate::fem::hct::HCT_DOFS;
use crate::mesh::Mesh;
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats};

impl DualSystem {
    /// The constrained dofs (slaves and fixed), in increasing order: constraint j is dof
    /// `constrained()[j]`.
    pub fn constrained(&self) -> Vec<usize> {
        (0..self.dofs.len()).filter(|&d| !matches!(self.affine.role[d], DofRole::Master(_))).collect()
    }

    /// Order of the saddle-point system: every HCT dof plus one multiplier per constraint.
    pub fn saddle_point_size(&self) -> usize {
        2 * self.dofs.len() - self.num_unknowns()
    }

    /// The dof of each free unknown.
    fn master_dofs(&self) -> Vec<usize> {
        let mut out = vec![0; self.num_unknowns()];
        for (d, role) in self.affine.role.iter().enumerate() {
            if let DofRole::Master(k) = role {
                out[*k] = d;
            }
        }
        out
    }

    /// The diagonal of S over every dof.
    fn stiffness_diagonal(&self, mesh: &Mesh) -> Vec<f64> {
        let mut diagonal = vec![0.0; self.dofs.len()];
        for (c, element) in self.elements.iter().enumerate() {
            let s: SMatrix<f64, HCT_DOFS, HCT_DOFS> = element.compliance_stiffness(&self.material);
            for (i, d) in self.dofs.cell_dofs(mesh, c).into_iter().enumerate() {
                diagonal[d] += s[(i, i)];
            }
        }
        diagonal
    }

    /// Rows `rows` of the saddle-point system (see the module doc); every rank computes every
    /// element and keeps its rows.
    pub fn assemble_saddle_point(&self, mesh: &Mesh, rows: Range<usize>) -> ReducedRows {
        let n = self.dofs.len();
        let size = self.saddle_point_size();
        let constrained = self.constrained();
        let masters = self.master_dofs();
        let diagonal = self.stiffness_diagonal(mesh);
        let positive_mean = {
            let (sum, count) = diagonal.iter().filter(|&&v| v > 0.0).fold((0.0, 0usize), |(s, c), &v| (s + v, c + 1));
            if count > 0 {
                sum / count as f64
            } else {
                1.0
            }
        };
        let scale = |d: usize| if diagonal[d] > 0.0 { diagonal[d].sqrt() } else { positive_mean.sqrt() };
        // Constraint j: its (dof, coefficient) terms and its right-hand side, scaled.
        let constraint = |j: usize| -> (Vec<(usize, f64)>, f64) {
            let d = constrained[j];
            let s = scale(d);
            match &self.affine.role[d] {
                DofRole::Slave(terms, c) => {
                    let mut t = vec![(d, s)];
                    t.extend(terms.iter().map(|&(k, a)| (masters[k], -a * s)));
                    (t, s * c)
                }
                DofRole::Fixed(v) => (vec![(d, s)], s * v),
                DofRole::Master(_) => (Vec::new(), 0.0),
            }
        };
        // Pattern: each element couples its 12 dofs; each constraint its multiplier and dofs.
        let mut group_ptr = vec![0];
        let mut group_indices = Vec::with_capacity(HCT_DOFS * self.elements.len() + 3 * constrained.len());
        for c in 0..self.elements.len() {
            group_indices.extend(self.dofs.cell_dofs(mesh, c));
            group_ptr.push(group_indices.len());
        }
        for j in 0..constrained.len() {
            group_indices.push(n + j);
            for (d, _) in constraint(j).0 {
                if !group_indices[group_ptr[group_ptr.len() - 1]..].contains(&d) {
                    group_indices.push(d);
                }
            }
            group_ptr.push(group_indices.len());
        }
        let mut matrix = CsrAssembler::new(rows.clone(), size, &group_ptr, &group_indices);
        drop((group_ptr, group_indices));
        let mut rhs = vec![0.0; rows.len()];
        let mut add_rhs = |row: usize, v: f64| {
            if rows.contains(&row) {
                rhs[row - rows.start] += v;
            }
        };
        for (d, v) in self.load_functional().into_iter().enumerate() {
            if v != 0.0 {
                add_rhs(d, v);
            }
        }
        for (c, element) in self.elements.iter().enumerate() {
            let cell_dofs = self.dofs.cell_dofs(mesh, c);
            if !cell_dofs.iter().any(|d| rows.contains(d)) {
                continue;
            }
            let s: SMatrix<f64, HCT_DOFS, HCT_DOFS> = element.compliance_stiffness(&self.material);
            let bp = self.particular_cross_term(element);
            for (i, &di) in cell_dofs.iter().enumerate() {
                if !rows.contains(&di) {
                    continue;
                }
                add_rhs(di, -bp[i]);
                for (j, &dj) in cell_dofs.iter().enumerate() {
                    matrix.add(di, dj, s[(i, j)]);
                }
            }
        }
        for j in 0..constrained.len() {
            let (terms, c) = constraint(j);
            add_rhs(n + j, c);
            for (d, b) in terms {
                matrix.add(n + j, d, b);
                matrix.add(d, n + j, b);
            }
        }
        let (indptr, indices, values) = matrix.into_parts();
        ReducedRows { first_row: rows.start, indptr, indices, values, rhs }
    }

    /// Assemble and solve the saddle point with the KSP of options prefix `prefix`; returns
    /// all HCT dofs with the constraints restored exactly (see the module doc), on every rank.
    pub fn solve_saddle_point(&self, session: &Session, mesh: &Mesh, prefix: &str) -> Result<(Vec<f64>, SolveStats)> {
        let size = self.saddle_point_size();
        let (ranks, rank) = (session.size(), session.rank());
        let rows = (rank * size / ranks)..((rank + 1) * size / ranks);
        let r = self.assemble_saddle_point(mesh, rows);
        let matrix = Matrix::from_csr_rows(
            session,
            session.world(),
            size,
            r.first_row,
            &r.indptr,
            &r.indices,
            &r.values,
            1,
            false,
        )?;
        matrix.set_symmetric()?;
        let mut b = matrix.create_vector()?;
        b.set_owned(&r.rhs)?;
        let mut x = matrix.create_vector()?;
        let mut ksp = LinearSolver::new(session, session.world(), prefix)?;
        ksp.set_indefinite();
        ksp.prefer_ordering(4);
        ksp.set_operator(&matrix)?;
        let stats = ksp.solve(&matrix, &b, &mut x)?;
        let all = x.gather_all()?;
        let z: Vec<f64> = self.master_dofs().iter().map(|&d| all[d]).collect();
        Ok((self.affine.expand(&z), stats))
    }
}
