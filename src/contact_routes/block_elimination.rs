//! Exact solves of the full-space Newton's mixed Jacobian by block elimination, with one
//! factorisation of the stiffness for the whole Newton iteration and no solve with it in the
//! steps after the first.
//!
//! The Jacobian of the full-space semi-smooth Newton (`full_space/`) in the unknowns `(u, λ)` is
//!
//! ```text
//!   J = [ K     −Bᵀ ]      K: the constrained stiffness (constant)
//!       [ P B    Q  ]      P, Q: per contact point, the piece of the generalized Jacobian
//! ```
//!
//! with `B u = (n_i·u_k, t_i·u_k)_i` the contact displacements in the points' frames. Only
//! `P` and `Q` change from one Newton step to the next.
//!
//! ## The unknowns `(v, λ)`
//!
//! When this elimination applies, the SNES iterates on `(v, λ)` with `u = v + K⁻¹ Bᵀ λ` (a
//! fixed linear change of the unknowns, so the Newton iterates are those of `(u, λ)`): the force
//! rows `K u − Bᵀ λ − f` become `K v − f`, the contact displacements `B u = B v + W λ` with the
//! flexibility `W = B K⁻¹ Bᵀ`, and the Jacobian becomes block triangular,
//!
//! ```text
//!   J' = [ K     0      ]      dv = K⁻¹ r_v,
//!        [ P B   P W + Q ]     (P W + Q) dλ = r_λ − P B dv.
//! ```
//!
//! The force rows are linear, so after the first step `r_v` is round-off and `dv` is not
//! computed (skipped below `10⁻¹³` of the force rows' scale, the size of `K`'s row terms): every
//! later step costs one small dense system and no solve with the factor, and `u` is recovered
//! once at the end ([`BlockElimination::displacement`], one solve). `K` is factorised once
//! (MUMPS Cholesky) with its Schur complement `S` on the contact dofs, which gives
//! `W = R S⁻¹ Rᵀ` ([`flexibility_from_schur`](super::condensed_route::flexibility_from_schur)). The
//! residual and the convergence test stay those of the full-space equations, and the answer is
//! checked afterwards in `(u, λ)` like every other solver's.
//!
//! ## The small system
//!
//! Per point the rows are of three kinds (`full_space/`, "Generalized Jacobian"), with
//! `B du = B dv + W dλ` the change of the contact displacements:
//!
//! ```text
//!   displacement row   (B du)_r = r_λ,r               closed normal row, sticking tangential row
//!   force row          dλ_r / ρ_r = r_λ,r             open normal row, free or Tresca-slip tangential row
//!   Coulomb slip row   a (B du)_N + b dλN + c dλT = r_λ,T     (the point's normal row is closed)
//! ```
//!
//! Force rows give `dλ_r = ρ_r r_λ,r` at once; a Coulomb slip row, with `(B du)_N = r_λ,N`
//! from its closed normal row, gives `dλT = (r_λ,T − a r_λ,N − b dλN) / c`. What remains is one
//! equation `(W dλ)_r = r_λ,r − (B dv)_r` per displacement row, in the unknowns `dλ_r` of the
//! displacement rows (the same reduced system as the condensed semi-smooth Newton's,
//! `contact/semismooth_newton.rs`): LU, factorised once per Newton step.
//!
//! Used when it applies: one process (PETSc 3.18 computes MUMPS Schur complements
//! sequentially), a body held by its Dirichlet conditions (`K` nonsingular), and no
//! `-contact_ksp_type`/`-contact_pc_type` (those select the inner solver of the whole mixed
//! system). `-contact_full_space_lu` turns it off (MUMPS LU of the mixed Jacobian in `(u, λ)`).
use nalgebra::{DMatrix, DVector};

use super::condensation::{flexibility_from_schur, schur_dofs};
use crate::contact::boundary::ContactBoundary;
use crate::error::{Error, Result};
use crate::petsc::dense_lu::DenseLu;
use crate::petsc::schur::SchurFactor;
use crate::petsc::{Matrix, Session, Vector};

/// How a contact row enters the Newton step (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ContactRow {
    Displacement,
    Force { rho: f64 },
    CoulombSlip { a: f64, b: f64, c: f64 },
}

/// The contact points' nodes and frames, and the current Newton step's contact rows with the
/// unknowns they leave: the part of the small system that both eliminations (this one and
/// `floating_elimination.rs`) share.
pub(crate) struct StepRows {
    nodes: Vec<usize>,
    /// The contact points with their rows of `B` (`gather`: `B y`, `scatter_add`: `Bᵀ λ`).
    boundary: ContactBoundary,
    per_point: usize,
    /// The current step's rows (`per_point` per point, in point order).
    rows: Vec<ContactRow>,
    /// The unknowns: the displacement rows, in `W`'s numbering `2i + k`.
    pub unknowns: Vec<usize>,
    /// How the multiplier changes depend on the unknowns: `(unknown, W index, coefficient)` — 1
    /// for the unknown itself, `−b/c` for the tangential change of a Coulomb slip point, which
    /// follows its normal one (`dλT = … − (b/c) dλN`).
    pub columns: Vec<(usize, usize, f64)>,
}

impl StepRows {
    pub fn new(boundary: &ContactBoundary, per_point: usize) -> Self {
        StepRows {
            nodes: boundary.nodes.clone(),
            boundary: boundary.clone(),
            per_point,
            rows: Vec::new(),
            unknowns: Vec::new(),
            columns: Vec::new(),
        }
    }

    /// The row of point `i`, component `k`, in `W`'s numbering.
    fn w_index(&self, r: usize) -> usize {
        2 * (r / self.per_point) + r % self.per_point
    }

    /// The contact row of a `W` index.
    pub fn contact_row(&self, wi: usize) -> usize {
        self.per_point * (wi / 2) + wi % 2
    }

    /// Take the rows of a new Jacobian: their unknowns and columns.
    pub fn set(&mut self, rows: Vec<ContactRow>) -> Result<()> {
        if rows.len() != self.per_point * self.nodes.len() {
            return Err(Error::PetscUsage(format!("{} contact rows for {} points", rows.len(), self.nodes.len())));
        }
        let unknowns: Vec<usize> =
            (0..rows.len()).filter(|&r| rows[r] == ContactRow::Displacement).map(|r| self.w_index(r)).collect();
        let mut columns: Vec<(usize, usize, f64)> = unknowns.iter().enumerate().map(|(p, &wi)| (p, wi, 1.0)).collect();
        for (r, kind) in rows.iter().enumerate() {
            if let ContactRow::CoulombSlip { b, c, .. } = *kind {
                let (t, n) = (self.w_index(r), self.w_index(r) - 1);
                let p = unknowns
                    .binary_search(&n)
                    .map_err(|_| Error::PetscUsage(format!("Coulomb slip row {r} without a closed normal row")))?;
                columns.push((p, t, -b / c));
            }
        }
        self.rows = rows;
        self.unknowns = unknowns;
        self.columns = columns;
        Ok(())
    }

    /// `B y`: the contact displacements of `y` in the points' frames (with a contact pair, the
    /// slave node's minus the mortar-weighted master nodes').
    pub fn frame_components(&self, y: &[f64]) -> Vec<f64> {
        self.boundary.gather(y)
    }

    /// The parts of `dλ` the contact rows `r_c` fix by themselves (force rows, the constant
    /// part of Coulomb slip rows), in `W`'s numbering; 0 for the unknowns.
    pub fn known_changes(&self, r_c: &[f64]) -> Vec<f64> {
        let mut dl = vec![0.0; 2 * self.nodes.len()];
        for (row, kind) in self.rows.iter().enumerate() {
            let wi = self.w_index(row);
            match *kind {
                ContactRow::Force { rho } => dl[wi] = rho * r_c[row],
                ContactRow::CoulombSlip { a, c, .. } => dl[wi] = (r_c[row] - a * r_c[row - 1]) / c,
                ContactRow::Displacement => {}
            }
        }
        dl
    }

    /// Add the unknowns' part `x` to the known changes `dl`.
    pub fn add_unknowns(&self, dl: &mut [f64], x: &[f64]) {
        for &(col, wj, coef) in &self.columns {
            dl[wj] += coef * x[col];
        }
    }

    /// `dλ` in the contact rows' order (the second part of a Newton step).
    pub fn write_changes(&self, dl: &[f64], out: &mut [f64]) {
        for (row, o) in out.iter_mut().enumerate() {
            *o = dl[self.w_index(row)];
        }
    }

    /// `Bᵀ λ` (`λ` in the points' frames) as a load on `n` dofs.
    pub fn load(&self, lambda: &[f64], n: usize) -> Vec<f64> {
        let mut load = vec![0.0; n];
        self.boundary.scatter_add(lambda, &mut load);
        load
    }
}

pub(crate) struct BlockElimination<'s> {
    factor: SchurFactor<'s>,
    /// `W` in the points' frames, `2m × 2m` (frictionless: only the normal rows are used).
    w: DMatrix<f64>,
    step: StepRows,
    num_u: usize,
    rhs: Vector<'s>,
    solution: Vector<'s>,
    /// The factorised reduced matrix of the current step.
    reduced: Reduced<'s>,
    session: &'s Session,
}

/// The factorised small system of a Newton step (LAPACK's LU, `petsc/dense_lu.rs`).
pub(crate) enum Reduced<'s> {
    /// No unknowns left (every row a force row).
    Empty,
    /// An exactly zero pivot.
    Singular,
    Factor(DenseLu<'s>),
}

impl<'s> Reduced<'s> {
    pub fn factorise(session: &'s Session, a: &DMatrix<f64>) -> Result<Self> {
        if a.nrows() == 0 {
            return Ok(Reduced::Empty);
        }
        Ok(DenseLu::new(session, a)?.map_or(Reduced::Singular, Reduced::Factor))
    }

    /// `A⁻¹ b`; `None` when there are no unknowns; `singular` is the error of a zero pivot.
    pub fn solve(&self, b: &[f64], singular: impl FnOnce() -> Error) -> Result<Option<Vec<f64>>> {
        match self {
            Reduced::Empty => Ok(None),
            Reduced::Singular => Err(singular()),
            Reduced::Factor(lu) => lu.solve(b).map(Some),
        }
    }
}

impl<'s> BlockElimination<'s> {
    /// Factorise `stiffness` (SPD, one process) with the Schur complement on the contact
    /// nodes' dofs and build `W`.
    pub fn new(
        session: &'s Session,
        stiffness: &Matrix<'s>,
        boundary: &ContactBoundary,
        per_point: usize,
    ) -> Result<Self> {
        // Every dof a row of B touches (with contact pairs, both sides'), as the condensed route.
        let rows = schur_dofs(boundary);
        let factor = SchurFactor::new(session, stiffness, &rows)?;
        let w = flexibility_from_schur(&factor, boundary)?;
        let num_u = stiffness.global_size();
        Ok(BlockElimination {
            factor,
            w,
            step: StepRows::new(boundary, per_point),
            num_u,
            rhs: stiffness.create_vector()?,
            solution: stiffness.create_vector()?,
            reduced: Reduced::Empty,
            session,
        })
    }

    /// Take the pieces of a new Jacobian (`per_point` rows per point, in point order) and
    /// factorise the reduced matrix.
    pub fn set_rows(&mut self, rows: Vec<ContactRow>) -> Result<()> {
        self.step.set(rows)?;
        let unknowns = &self.step.unknowns;
        let mut a = DMatrix::<f64>::zeros(unknowns.len(), unknowns.len());
        for &(q, col, coef) in &self.step.columns {
            for (p, &row) in unknowns.iter().enumerate() {
                a[(p, q)] += coef * self.w[(row, col)];
            }
        }
        self.reduced = Reduced::factorise(self.session, &a)?;
        Ok(())
    }

    /// `(dv, dλ) = J'⁻¹ (r_v, r_λ)` with the pieces of the last [`BlockElimination::set_rows`];
    /// `r` and `d` hold the force entries then the contact entries. Force residuals no larger
    /// than `negligible` are round-off: `dv = 0` without a solve.
    pub fn solve(&mut self, r: &[f64], d: &mut [f64], negligible: f64) -> Result<()> {
        let n = self.num_u;
        let (r_v, r_c) = r.split_at(n);
        let largest = r_v.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let by = if largest > negligible {
            self.rhs.set_owned(r_v)?;
            self.factor.solve(&self.rhs, &mut self.solution)?;
            let y = self.solution.owned_values()?;
            d[..n].copy_from_slice(&y);
            self.step.frame_components(&y)
        } else {
            d[..n].fill(0.0);
            vec![0.0; self.w.nrows()]
        };
        let mut dl = self.step.known_changes(r_c);
        let unknowns = &self.step.unknowns;
        let known_columns: Vec<usize> = (0..dl.len()).filter(|&j| dl[j] != 0.0).collect();
        let rhs: Vec<f64> = unknowns
            .iter()
            .map(|&wi| {
                let known: f64 = known_columns.iter().map(|&j| self.w[(wi, j)] * dl[j]).sum();
                r_c[self.step.contact_row(wi)] - by[wi] - known
            })
            .collect();
        let x = self.reduced.solve(&rhs, || Error::SolverDiverged {
            solver: "block elimination of the mixed Jacobian".into(),
            reason: "the reduced contact system is singular".into(),
            iterations: 0,
            residual: f64::NAN,
            tried: "MUMPS Cholesky of K with the Schur complement on the contact dofs; \
                    -contact_full_space_lu factorises the whole mixed Jacobian instead"
                .into(),
        })?;
        if let Some(x) = x {
            self.step.add_unknowns(&mut dl, &x);
        }
        self.step.write_changes(&dl, &mut d[n..]);
        Ok(())
    }

    /// `W λ`, both in the points' frames (`2i`: normal, `2i + 1`: tangential).
    pub fn flexibility_times(&self, lambda: &[f64]) -> Vec<f64> {
        (&self.w * DVector::from_column_slice(lambda)).as_slice().to_vec()
    }

    /// The displacement `u = v + K⁻¹ Bᵀ λ` (`λ` in the points' frames): one solve.
    pub fn displacement(&mut self, v: &[f64], lambda: &[f64]) -> Result<Vec<f64>> {
        let load = self.step.load(lambda, self.num_u);
        v_plus_response(&self.factor, &mut self.rhs, &mut self.solution, &load, v)
    }
}

/// `v + F⁻¹ load` with the factor `F` (one solve; `rhs`, `solution`: its work vectors).
pub(crate) fn v_plus_response<'s>(
    factor: &SchurFactor<'s>,
    rhs: &mut Vector<'s>,
    solution: &mut Vector<'s>,
    load: &[f64],
    v: &[f64],
) -> Result<Vec<f64>> {
    rhs.set_owned(load)?;
    factor.solve(rhs, solution)?;
    let response = solution.owned_values()?;
    Ok(v.iter().zip(&response).map(|(a, b)| a + b).collect())
}
