//! Exact solves of the full-space Newton's mixed Jacobian by block elimination, with one
//! factorisation of the stiffness for the whole Newton iteration.
//!
//! The Jacobian of the full-space semi-smooth Newton (`full_space.rs`) is
//!
//! ```text
//!   J = [ K     −Bᵀ ]      K: the constrained stiffness (constant)
//!       [ P B    Q  ]      P, Q: per contact point, the piece of the generalized Jacobian
//! ```
//!
//! with `B u = (n_i·u_k, t_i·u_k)_i` the contact displacements in the points' frames. Only
//! `P` and `Q` change from one Newton step to the next. With `y = K⁻¹ r_u` and the flexibility
//! `W = B K⁻¹ Bᵀ`, `J (du, dλ) = (r_u, r_λ)` is
//!
//! ```text
//!   (P W + Q) dλ = r_λ − P B y,        du = K⁻¹ (r_u + Bᵀ dλ)
//! ```
//!
//! (block Gaussian elimination, exact in exact arithmetic). `K` is factorised once (MUMPS
//! Cholesky) with its Schur complement `S` on the contact dofs, which gives `W = R S⁻¹ Rᵀ`
//! ([`flexibility_from_schur`](super::contact::flexibility_from_schur)); each Newton step then
//! costs one or two solves with the factor (the first, `y = K⁻¹ r_u`, is skipped when the force
//! residual is round-off — after any full Newton step, the force rows being linear — below
//! `10⁻¹²` of the largest load) and one small dense system, instead of a sparse LU of the
//! whole mixed matrix. The Newton iterates are those of the LU route (same equations, same
//! pieces); the residual is always evaluated in full space, so the round-off of the
//! elimination (about `10⁻¹⁰` relative) only slows the last step, it does not limit the
//! accuracy of the answer.
//!
//! ## The small system
//!
//! Per point the rows are of three kinds (`full_space.rs`, "Generalized Jacobian"):
//!
//! ```text
//!   displacement row   (B du)_r = r_λ,r               closed normal row, sticking tangential row
//!   force row          dλ_r / ρ_r = r_λ,r             open normal row, free or Tresca-slip tangential row
//!   Coulomb slip row   a (B du)_N + b dλN + c dλT = r_λ,T     (the point's normal row is closed)
//! ```
//!
//! Force rows give `dλ_r = ρ_r r_λ,r` at once; a Coulomb slip row, with `(B du)_N = r_λ,N`
//! from its closed normal row, gives `dλT = (r_λ,T − a r_λ,N − b dλN) / c`. What remains is one
//! equation `(W dλ)_r = r_λ,r − (B y)_r` per displacement row, in the unknowns `dλ_r` of the
//! displacement rows (the same reduced system as the condensed semi-smooth Newton's,
//! `contact/semismooth_newton.rs`): LU, factorised once per Newton step.
//!
//! Used when it applies: one process (PETSc 3.18 computes MUMPS Schur complements
//! sequentially), a body held by its Dirichlet conditions (`K` nonsingular), and no
//! `-contact_ksp_type`/`-contact_pc_type` (those select the inner solver of the whole mixed
//! system). `-contact_full_space_lu` turns it off (MUMPS LU of the mixed Jacobian).
use nalgebra::{DMatrix, DVector};

use super::contact::flexibility_from_schur;
use crate::contact::boundary::ContactBoundary;
use crate::error::{Error, Result};
use crate::petsc::schur::SchurFactor;
use crate::petsc::{Matrix, Session, Vector};

/// How a contact row enters the Newton step (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum ContactRow {
    Displacement,
    Force { rho: f64 },
    CoulombSlip { a: f64, b: f64, c: f64 },
}

pub(super) struct BlockElimination<'s> {
    factor: SchurFactor<'s>,
    /// `W` in the points' frames, `2m × 2m` (frictionless: only the normal rows are used).
    w: DMatrix<f64>,
    nodes: Vec<usize>,
    normal: Vec<[f64; 2]>,
    tangent: Vec<[f64; 2]>,
    per_point: usize,
    num_u: usize,
    rhs: Vector<'s>,
    solution: Vector<'s>,
    /// The current step's rows (`per_point` per point), the unknowns (row numbers in `W`'s
    /// numbering `2i + k`) and the factorised reduced matrix.
    rows: Vec<ContactRow>,
    unknowns: Vec<usize>,
    reduced: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
    /// The largest load entry: force residuals below 10⁻¹² of it are round-off.
    load_scale: f64,
}

impl<'s> BlockElimination<'s> {
    /// Factorise `stiffness` (SPD, one process) with the Schur complement on the contact
    /// nodes' dofs and build `W`.
    pub fn new(
        session: &'s Session,
        stiffness: &Matrix<'s>,
        boundary: &ContactBoundary,
        per_point: usize,
        load: &[f64],
    ) -> Result<Self> {
        let rows: Vec<usize> = boundary.nodes.iter().flat_map(|&k| [2 * k, 2 * k + 1]).collect();
        let factor = SchurFactor::new(session, stiffness, &rows)?;
        let w = flexibility_from_schur(&factor, boundary)?;
        let load_scale = load.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let num_u = stiffness.global_size();
        Ok(BlockElimination {
            factor,
            w,
            nodes: boundary.nodes.clone(),
            normal: boundary.normal.clone(),
            tangent: boundary.tangent.clone(),
            per_point,
            num_u,
            rhs: stiffness.create_vector()?,
            solution: stiffness.create_vector()?,
            rows: Vec::new(),
            unknowns: Vec::new(),
            reduced: None,
            load_scale,
        })
    }

    /// The row of point `i`, component `k`, in `W`'s numbering.
    fn w_index(&self, r: usize) -> usize {
        2 * (r / self.per_point) + r % self.per_point
    }

    /// Take the pieces of a new Jacobian (`per_point` rows per point, in point order) and
    /// factorise the reduced matrix.
    pub fn set_rows(&mut self, rows: Vec<ContactRow>) -> Result<()> {
        if rows.len() != self.per_point * self.nodes.len() {
            return Err(Error::PetscUsage(format!("{} contact rows for {} points", rows.len(), self.nodes.len())));
        }
        let unknowns: Vec<usize> =
            (0..rows.len()).filter(|&r| rows[r] == ContactRow::Displacement).map(|r| self.w_index(r)).collect();
        let position = |wi: usize| unknowns.binary_search(&wi).ok();
        let mut a = DMatrix::<f64>::zeros(unknowns.len(), unknowns.len());
        for (p, &row) in unknowns.iter().enumerate() {
            for (q, &col) in unknowns.iter().enumerate() {
                a[(p, q)] = self.w[(row, col)];
            }
        }
        for (r, kind) in rows.iter().enumerate() {
            if let ContactRow::CoulombSlip { b, c, .. } = *kind {
                // dλT = … − (b/c) dλN: the column of the point's normal unknown gains −(b/c) W_{·,T}.
                let (t, n) = (self.w_index(r), self.w_index(r) - 1);
                let q = position(n)
                    .ok_or_else(|| Error::PetscUsage(format!("Coulomb slip row {r} without a closed normal row")))?;
                for (p, &row) in unknowns.iter().enumerate() {
                    a[(p, q)] -= b / c * self.w[(row, t)];
                }
            }
        }
        self.reduced = if unknowns.is_empty() { None } else { Some(a.lu()) };
        self.rows = rows;
        self.unknowns = unknowns;
        Ok(())
    }

    /// `(du, dλ) = J⁻¹ (r_u, r_λ)` with the pieces of the last [`BlockElimination::set_rows`];
    /// `r` and `d` hold the displacement entries then the contact entries.
    pub fn solve(&mut self, r: &[f64], d: &mut [f64]) -> Result<()> {
        let n = self.num_u;
        let (r_u, r_c) = r.split_at(n);
        // y = K⁻¹ r_u and its contact displacements B y. After a full Newton step the force
        // rows hold (they are linear): r_u is round-off and y is not computed.
        let m = self.nodes.len();
        let mut by = vec![0.0; 2 * m];
        let largest = r_u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if largest > 1e-12 * self.load_scale {
            self.rhs.set_owned(r_u)?;
            self.factor.solve(&self.rhs, &mut self.solution)?;
            let y = self.solution.owned_values()?;
            for (i, &k) in self.nodes.iter().enumerate() {
                by[2 * i] = self.normal[i][0] * y[2 * k] + self.normal[i][1] * y[2 * k + 1];
                by[2 * i + 1] = self.tangent[i][0] * y[2 * k] + self.tangent[i][1] * y[2 * k + 1];
            }
        }
        // Known parts of dλ (force rows, the constant part of Coulomb slip rows).
        let mut dl = vec![0.0; 2 * m];
        for (row, kind) in self.rows.iter().enumerate() {
            let wi = self.w_index(row);
            match *kind {
                ContactRow::Force { rho } => dl[wi] = rho * r_c[row],
                ContactRow::CoulombSlip { a, c, .. } => dl[wi] = (r_c[row] - a * r_c[row - 1]) / c,
                ContactRow::Displacement => {}
            }
        }
        if let Some(lu) = &self.reduced {
            let mut rhs = DVector::<f64>::zeros(self.unknowns.len());
            let known_columns: Vec<usize> = (0..2 * m).filter(|&j| dl[j] != 0.0).collect();
            for (p, &wi) in self.unknowns.iter().enumerate() {
                let row = self.per_point * (wi / 2) + wi % 2;
                let known: f64 = known_columns.iter().map(|&j| self.w[(wi, j)] * dl[j]).sum();
                rhs[p] = r_c[row] - by[wi] - known;
            }
            let x = lu.solve(&rhs).ok_or_else(|| Error::SolverDiverged {
                solver: "block elimination of the mixed Jacobian".into(),
                reason: "the reduced contact system is singular".into(),
                iterations: 0,
                residual: f64::NAN,
                tried: "MUMPS Cholesky of K with the Schur complement on the contact dofs; \
                        -contact_full_space_lu factorises the whole mixed Jacobian instead"
                    .into(),
            })?;
            for (p, &wi) in self.unknowns.iter().enumerate() {
                dl[wi] = x[p];
            }
            for (row, kind) in self.rows.iter().enumerate() {
                if let ContactRow::CoulombSlip { b, c, .. } = *kind {
                    let wi = self.w_index(row);
                    dl[wi] -= b / c * dl[wi - 1];
                }
            }
        }
        // du = K⁻¹ (r_u + Bᵀ dλ).
        let mut load = r_u.to_vec();
        for (i, &k) in self.nodes.iter().enumerate() {
            for c in 0..2 {
                load[2 * k + c] += self.normal[i][c] * dl[2 * i] + self.tangent[i][c] * dl[2 * i + 1];
            }
        }
        self.rhs.set_owned(&load)?;
        self.factor.solve(&self.rhs, &mut self.solution)?;
        d[..n].copy_from_slice(&self.solution.owned_values()?);
        for (row, out) in d[n..].iter_mut().enumerate() {
            *out = dl[self.w_index(row)];
        }
        Ok(())
    }
}
