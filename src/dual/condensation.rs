//! # How the dual contact problem is condensed onto the contact forces
//!
//! The reduced dual system, unknowns `x = (z, r)` (free HCT dofs, contact forces),
//!
//! ```text
//!   [ A_zz  A_zr ] [ z ]   [ b_z ]            W = A_rr − A_rz A_zz⁻¹ A_zr      (the talk's D)
//!   [ A_rz  A_rr ] [ r ] = [ b_r ] + u,       u_free = −(b_r + ℓ),  ℓ = −A_rz A_zz⁻¹ b_z
//! ```
//!
//! is condensed onto `r` in one of the source talk's ways ("Résolution numérique duale"):
//!
//! - **`schur`** (the default): one MUMPS factorisation of the whole matrix with the Schur
//!   complement on `r` ([`crate::petsc::schur::SchurFactor`]): `W` comes out of the
//!   factorisation itself.
//! - **`columns`**, the talk's three-step condensation: (1) solve `A_zz X = A_zr` column by
//!   column, (2) form `W = A_rr − A_rz X`, (3) solve the contact problem on `W`. Step (1) uses
//!   the dual's linear solver with every PETSc option: MUMPS (`-ksp_type preonly -pc_type
//!   cholesky`, factorised once, then one pair of triangular solves per column), or a Krylov
//!   method with incomplete Cholesky by fill level (`-ksp_type cg -pc_type icc
//!   -pc_factor_levels k`), by drop tolerance, SSOR (`-pc_type sor -pc_sor_symmetric`), hypre;
//!   with `-ksp_type symmlq` it is the talk's "brute" condensation by SYMMLQ. One solve per
//!   contact force (`2 × points`), then one for `ℓ` and one for the field.
//!
//! `W` is dense in both (the talk's "dense storage of D"). The route is chosen by
//! `-dual_contact_condensation schur|columns`; without it, `columns` when the dual's linear
//! solver is configured (`-ksp_type`/`-pc_type`, under `-dual_` next to a primal solve), else
//! `schur` — as the primal chooses between its Schur factorisation and its KSP.
use nalgebra::DMatrix;

use super::system::ReducedRows;
use crate::error::{Error, Result};
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats};

/// The option that names the condensation.
pub const CONDENSATION_OPTION: &str = "-dual_contact_condensation";

/// The talk's condensation strategies (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Condensation {
    Schur,
    Columns,
}

impl Condensation {
    pub fn name(self) -> &'static str {
        match self {
            Condensation::Schur => "schur",
            Condensation::Columns => "columns",
        }
    }

    /// The condensation asked for (see the module documentation); `prefix` is the dual's
    /// PETSc options prefix.
    pub fn from_options(session: &Session, prefix: &str) -> Result<Self> {
        let configured =
            session.has_option(&format!("-{prefix}ksp_type"))? || session.has_option(&format!("-{prefix}pc_type"))?;
        match session.option(CONDENSATION_OPTION)?.as_deref() {
            None => Ok(if configured { Condensation::Columns } else { Condensation::Schur }),
            Some("schur") if configured => Err(Error::Usage(format!(
                "{CONDENSATION_OPTION} schur factorises with MUMPS and the Schur complement: drop -{prefix}ksp_type and \
                 -{prefix}pc_type, or use {CONDENSATION_OPTION} columns to condense with that solver"
            ))),
            Some("schur") => Ok(Condensation::Schur),
            Some("columns") => Ok(Condensation::Columns),
            Some(other) => Err(Error::Usage(format!("{CONDENSATION_OPTION} takes schur or columns (got \"{other}\")"))),
        }
    }
}

/// The three-step condensation's pieces: `A_zz` with its solver, the coupling `A_zr` by
/// columns and `A_rr`.
pub struct ColumnCondensation<'s> {
    interior: Matrix<'s>,
    solver: LinearSolver<'s>,
    /// Column `j` of `A_zr` (rows of `z`), sparse; by symmetry row `j` of `A_rz`.
    coupling: Vec<Vec<(usize, f64)>>,
    a_rr: DMatrix<f64>,
    num_interior: usize,
    /// Linear solves so far, and their iterations.
    pub solves: usize,
    pub iterations: usize,
    pub seconds: f64,
}

impl<'s> ColumnCondensation<'s> {
    /// Split the assembled rows (all rows, one process) at `num_interior` and set up the solver
    /// of `A_zz` with the options under `prefix`.
    pub fn new(session: &'s Session, rows: &ReducedRows, num_interior: usize, prefix: &str) -> Result<Self> {
        let n = rows.indptr.len() - 1;
        let nz = num_interior;
        let m = n - nz;
        let (mut indptr, mut indices, mut values) = (vec![0usize], Vec::new(), Vec::new());
        let mut coupling = vec![Vec::new(); m];
        let mut a_rr = DMatrix::zeros(m, m);
        for i in 0..n {
            for k in rows.indptr[i]..rows.indptr[i + 1] {
                let (j, v) = (rows.indices[k], rows.values[k]);
                match (i < nz, j < nz) {
                    (true, true) => {
                        indices.push(j);
                        values.push(v);
                    }
                    (true, false) => coupling[j - nz].push((i, v)),
                    (false, false) => a_rr[(i - nz, j - nz)] = v,
                    (false, true) => {}
                }
            }
            if i < nz {
                indptr.push(indices.len());
            }
        }
        let interior = Matrix::from_csr_rows(session, session.world(), nz, 0, &indptr, &indices, &values, 1, true)?;
        let mut solver = LinearSolver::new(session, session.world(), prefix)?;
        solver.prefer_ordering(4);
        solver.set_operator(&interior)?;
        Ok(ColumnCondensation {
            interior,
            solver,
            coupling,
            a_rr,
            num_interior: nz,
            solves: 0,
            iterations: 0,
            seconds: 0.0,
        })
    }

    fn solve(&mut self, rhs: &[f64]) -> Result<Vec<f64>> {
        let mut b = self.interior.create_vector()?;
        b.set_owned(rhs)?;
        let mut x = self.interior.create_vector()?;
        let stats = self.solver.solve(&self.interior, &b, &mut x)?;
        self.solves += 1;
        self.iterations += stats.iterations;
        self.seconds += stats.seconds;
        x.gather_all()
    }

    /// `A_rz y` for `y` on the interior rows.
    fn coupling_transpose(&self, y: &[f64]) -> Vec<f64> {
        self.coupling.iter().map(|col| col.iter().map(|&(i, v)| v * y[i]).sum()).collect()
    }

    /// `W = A_rr − A_rz A_zz⁻¹ A_zr`, one solve per column (symmetrised), with `progress`
    /// told every 50 columns.
    pub fn flexibility(&mut self, progress: &mut dyn FnMut(usize, usize)) -> Result<DMatrix<f64>> {
        let m = self.coupling.len();
        let mut w = self.a_rr.clone();
        let mut rhs = vec![0.0; self.num_interior];
        for j in 0..m {
            rhs.fill(0.0);
            for &(i, v) in &self.coupling[j] {
                rhs[i] = v;
            }
            let x = self.solve(&rhs)?;
            for (i, v) in self.coupling_transpose(&x).into_iter().enumerate() {
                w[(i, j)] -= v;
            }
            if j % 50 == 49 {
                progress(j + 1, m);
            }
        }
        Ok(0.5 * (&w + w.transpose()))
    }

    /// `ℓ = −A_rz A_zz⁻¹ b_z`.
    pub fn condensed_load(&mut self, b_z: &[f64]) -> Result<Vec<f64>> {
        let x = self.solve(b_z)?;
        Ok(self.coupling_transpose(&x).into_iter().map(|v| -v).collect())
    }

    /// The interior `z = A_zz⁻¹ (b_z − A_zr r)` for the forces `r`.
    pub fn interior(&mut self, b_z: &[f64], r: &[f64]) -> Result<Vec<f64>> {
        let mut rhs = b_z.to_vec();
        for (col, rj) in self.coupling.iter().zip(r) {
            for &(i, v) in col {
                rhs[i] -= v * rj;
            }
        }
        self.solve(&rhs)
    }

    /// What the solves were, for the report.
    pub fn stats(&self) -> SolveStats {
        let mut s = self.solver.last_stats().unwrap_or(SolveStats {
            ksp_type: String::new(),
            pc_type: String::new(),
            factor_package: None,
            iterations: 0,
            converged_reason: String::new(),
            relative_residual: 0.0,
            seconds: 0.0,
        });
        s.iterations = self.iterations;
        s.seconds = self.seconds;
        s.converged_reason = format!("{} solves with A_zz (three-step condensation)", self.solves);
        s
    }
}
