//! Exact solves of the full-space Newton's mixed Jacobian for a body that its Dirichlet
//! conditions do not hold (held by the contact, or not yet held), with one factorisation of the
//! stiffness for the whole Newton iteration.
//!
//! The Jacobian is that of `block_elimination.rs`,
//!
//! ```text
//!   J = [ K     −Bᵀ ]      K: the constrained stiffness, singular on the free rigid motions
//!       [ P B    Q  ]
//! ```
//!
//! but `K` cannot be factorised. Springs `k_q` at a few contact dofs (the *pins* `E`, chosen so
//! that with the Dirichlet rows they block every rigid motion) make `K̂ = K + Eᵀ k E` positive
//! definite: it is factorised once (MUMPS Cholesky, Schur complement on the contact dofs), and
//! the springs are removed again inside every Newton step. With `π = E du` (the pins'
//! displacements) the force rows `K du − Bᵀ dλ = r_u` read `K̂ du = r_u + Bᵀ dλ + Eᵀ k π`, so
//!
//! ```text
//!   du  = y + K̂⁻¹ (Bᵀ dλ + Eᵀ k π),          y = K̂⁻¹ r_u
//!   B du = B y + Ŵ dλ + G k π,                 Ŵ = B K̂⁻¹ Bᵀ,  G = B K̂⁻¹ Eᵀ
//!   π    = E y + Gᵀ dλ + H k π,                H = E K̂⁻¹ Eᵀ
//! ```
//!
//! The contact rows give `dλ` at once on force rows and `dλT` from `dλN` on Coulomb slip rows
//! (as in `block_elimination.rs`); what remains is the small dense system
//!
//! ```text
//!   [ Ŵ_DD    k G_D   ] [ dλ_D ]   [ r_λ,D − (B y)_D − Ŵ_D· dλ_known ]
//!   [ −G_Dᵀ   I − k H ] [  π   ] = [ E y + Gᵀ dλ_known                ]
//! ```
//!
//! (`D`: the displacement rows — closed normal rows, sticking tangential rows), of the size of
//! the held body's reduced system plus the number of pins. It is nonsingular exactly when `J`
//! is, that is when the closed and sticking rows with the Dirichlet rows block every rigid
//! motion (`full_space/` checks that at every Jacobian). While they do not (the first steps of
//! a body resting on the obstacle, before the contact zone has formed; a cylinder free to turn
//! about its centre on frictionless contact), the step is regularised with springs on the
//! *free* rigid motions only — those that neither the Dirichlet rows nor the closed and
//! sticking rows block, the null space of the rigid-motion check's Gram matrix: `K + k Q Qᵀ`,
//! `Q` an orthonormal basis of those motions over the contact dofs, `k = 10⁻³ max diag K / m`
//! (the energy of springs `k` at every contact dof). The regularised Jacobian differs from `J`
//! on `J`'s null space only, so when the residual has no part along a free motion (a cylinder
//! whose loads have no moment about its centre) the step is an exact Newton step, the one
//! without rigid motion along `Q`; otherwise it is a Levenberg–Marquardt step that moves the
//! body towards the contact. Both changes of `K̂` are low-rank and live on the contact dofs,
//! `U C Uᵀ` (`C = −k_q` for the pins, `+k` for `Q`), and enter the small system the same way:
//! `(I + H C) π − Gᵀ dλ = …` with `G = B K̂⁻¹ U`, `H = Uᵀ K̂⁻¹ U`, `π = Uᵀ du`.
//!
//! ## Several bodies
//!
//! With contact pairs a row of `B` touches the slave node and master nodes of another body
//! (mortar rows): the Schur complement is taken on every dof a row touches (`schur_dofs`, as
//! the condensed route and `block_elimination.rs`), `B` acts on those dofs through its rows
//! (`rows_on_schur`), and the pins and rigid motions are per body: pins on each body the
//! Dirichlet rows do not hold, chosen among the dofs the rows touch (`choose_pins` in
//! `full_space/mixed_system.rs`), 3 rigid motions per body.
//!
//! The pins' springs `k_q` are the pinned dofs' own diagonal stiffness. The small system is
//! solved in the unknowns `dλ` and `|C| π` (forces, so that every entry is a compliance).
//!
//! ## The unknowns (v, λ)
//!
//! As the held body's (`block_elimination.rs`), the SNES iterates on `(v, λ)` with
//! `u = v + K̂⁻¹ Bᵀ λ`, a fixed linear change of unknowns (the same Newton iterates). With
//! `K = K̂ − Eᵀ k E` the force rows `K u − Bᵀ λ − f` become `K v − Eᵀ k Gᵀ λ − f`: linear, and
//! `λ` enters only the pinned rows (`G = B K̂⁻¹ Eᵀ`, [`FloatingElimination::pinned_forces`]); the
//! contact displacements are `B u = B v + Ŵ λ`. A step's `(du, dλ)` from the small system above
//! gives `dv = du − K̂⁻¹ Bᵀ dλ = y − K̂⁻¹ U C π`: with `K̂⁻¹ U` computed once (one solve per pin
//! at the factorisation, one per free rigid motion when a regularised step first needs it), a
//! step costs the small system and no solve with the factor once the force rows are at
//! round-off (after the first step); `u` is recovered by one solve at the end. On the
//! `block_on_block` row of `bench contact` at 1e6 dofs this halves the contact solve (25.9 s →
//! 11.6 s, 13 steps).
//!
//! The residual in `(v, λ)` takes `Ŵ` from the dense inverse of the Schur complement of `K̂`,
//! and `u` from a solve with the factor: for a very ill-conditioned `K̂` (a slab 1000 times
//! longer than thick held by a few pins) the two disagree beyond the tolerance, and the answer
//! fails the independent check. The run then iterates again in `(u, λ)` (`in_v = false`: each
//! step solves for `du = y + K̂⁻¹ (Bᵀ dλ − U C π)`, one solve, and the residual is evaluated on
//! `u` itself), and says so in the contact notes.
use nalgebra::{DMatrix, DVector};

use super::block_elimination::{v_plus_response, ContactRow, Reduced, StepRows};
use super::condensation::{flexibility_from_schur, rows_on_schur, schur_dofs};
use crate::contact::boundary::ContactBoundary;
use crate::error::{Error, Result};
use crate::petsc::schur::SchurFactor;
use crate::petsc::{Matrix, Session, Vector};

/// A change `U C Uᵀ` of `K̂` supported on the contact dofs: `u` (`s × q`, columns over the Schur
/// rows), `c` (the diagonal of `C`), and `G = B K̂⁻¹ U` (frames), `H = Uᵀ K̂⁻¹ U`.
struct Correction {
    u: DMatrix<f64>,
    c: Vec<f64>,
    g: DMatrix<f64>,
    h: DMatrix<f64>,
    /// `K̂⁻¹ U`, one column (all `n` dofs) per column of `U`.
    responses: Vec<Vec<f64>>,
}

impl Correction {
    fn new(
        u: DMatrix<f64>,
        c: Vec<f64>,
        inverse: &DMatrix<f64>,
        b_rows: &[Vec<(usize, f64)>],
        responses: Vec<Vec<f64>>,
    ) -> Self {
        let vu = inverse * &u;
        let g = DMatrix::from_fn(b_rows.len(), u.ncols(), |wi, q| {
            b_rows[wi].iter().map(|&(position, coef)| coef * vu[(position, q)]).sum()
        });
        let h = u.transpose() * vu;
        Correction { u, c, g, h, responses }
    }

    fn len(&self) -> usize {
        self.c.len()
    }
}

pub(crate) struct FloatingElimination<'s> {
    factor: SchurFactor<'s>,
    /// The Schur rows: every dof a row of `B` touches, increasing.
    schur: Vec<usize>,
    /// `(K̂⁻¹)` on the Schur rows (`S⁻¹`), and `B`'s rows on their positions.
    inverse: DMatrix<f64>,
    b_rows: Vec<Vec<(usize, f64)>>,
    /// `Ŵ` in the points' frames (`2m × 2m`).
    w: DMatrix<f64>,
    /// The pins' columns of `U`, their dofs and their springs.
    pins: DMatrix<f64>,
    pinned: Vec<usize>,
    pin_springs: Vec<f64>,
    /// The rigid motions over the Schur rows (3 per body; zero on prescribed dofs) and the
    /// spring of the regularised steps.
    rigid: DMatrix<f64>,
    spring: f64,
    /// The low-rank change of `K̂` of the exact step (the pins, removed).
    exact: Correction,
    /// That of the last regularised step (the pins removed, springs on the free rigid
    /// motions), with the free motions it was built for.
    regularizing: Option<(DMatrix<f64>, Correction)>,
    step: StepRows,
    num_u: usize,
    rhs: Vector<'s>,
    solution: Vector<'s>,
    /// The springs stay in this step's Jacobian (no `π` unknowns).
    regularized: bool,
    /// The iteration runs on `(v, λ)` (no solve per step) rather than on `(u, λ)`.
    pub in_v: bool,
    reduced: Reduced<'s>,
    session: &'s Session,
}

impl<'s> FloatingElimination<'s> {
    /// Factorise `K + Eᵀ k E` (`stiffness` holds `K`: every row, one process; `pinned` the
    /// dofs of `E`, each a dof some row of `B` touches) with the Schur complement on the dofs
    /// the rows of `B` touch. `rigid`: the rigid motions over those dofs (`schur_dofs` order,
    /// one column per rigid motion of each body, zero on prescribed dofs).
    pub fn new(
        session: &'s Session,
        stiffness: &crate::fem::assembly::CsrRows,
        boundary: &ContactBoundary,
        per_point: usize,
        pinned: &[usize],
        rigid: DMatrix<f64>,
        in_v: bool,
    ) -> Result<Self> {
        let n = stiffness.num_cols;
        if stiffness.first_row != 0 || stiffness.num_rows() != n {
            return Err(Error::PetscUsage("the floating-body elimination needs every row of K (one process)".into()));
        }
        let schur = schur_dofs(boundary);
        if rigid.nrows() != schur.len() {
            return Err(Error::PetscUsage(format!(
                "{} rigid-motion rows for {} dofs touched by the contact rows",
                rigid.nrows(),
                schur.len()
            )));
        }
        let mut values = stiffness.values.clone();
        let mut pins = DMatrix::<f64>::zeros(schur.len(), pinned.len());
        let mut pin_springs = Vec::with_capacity(pinned.len());
        for (q, &dof) in pinned.iter().enumerate() {
            let position = schur
                .binary_search(&dof)
                .map_err(|_| Error::PetscUsage(format!("pinned dof {dof} is not a dof the contact rows touch")))?;
            let spring = stiffness.get(dof, dof);
            if !(spring > 0.0 && spring.is_finite()) {
                return Err(Error::PetscUsage(format!("pinned dof {dof} has no positive stiffness")));
            }
            let (start, end) = (stiffness.indptr[dof], stiffness.indptr[dof + 1]);
            let at = (start..end)
                .find(|&p| stiffness.indices[p] == dof)
                .ok_or_else(|| Error::PetscUsage(format!("pinned dof {dof}: no diagonal stiffness entry")))?;
            values[at] += spring;
            pins[(position, q)] = 1.0;
            pin_springs.push(spring);
        }
        let matrix = Matrix::from_csr_rows(
            session,
            session.world(),
            n,
            stiffness.first_row,
            &stiffness.indptr,
            &stiffness.indices,
            &values,
            2,
            true,
        )?;
        let factor = SchurFactor::new(session, &matrix, &schur)?;
        let w = flexibility_from_schur(&factor, boundary)?;
        let size = schur.len();
        let inverse = DMatrix::from_row_slice(size, size, factor.inverse_block());
        let b_rows = rows_on_schur(boundary, &schur);
        let removed: Vec<f64> = pin_springs.iter().map(|k| -k).collect();
        let mut rhs = matrix.create_vector()?;
        let mut solution = matrix.create_vector()?;
        let responses = responses_of(&factor, &schur, &pins, n, &mut rhs, &mut solution)?;
        let exact = Correction::new(pins.clone(), removed, &inverse, &b_rows, responses);
        // k = 10⁻³ max diag K / m: the energy of a rigid motion under springs k at every
        // contact dof (module documentation).
        let m = boundary.points();
        let max_diagonal = (0..n).map(|d| stiffness.get(d, d).abs()).fold(0.0f64, f64::max);
        let spring = 1e-3 * max_diagonal / m.max(1) as f64;
        Ok(FloatingElimination {
            rhs,
            solution,
            factor,
            schur,
            inverse,
            b_rows,
            w,
            pins,
            pinned: pinned.to_vec(),
            pin_springs,
            rigid,
            spring,
            exact,
            regularizing: None,
            step: StepRows::new(boundary, per_point),
            num_u: n,
            regularized: false,
            in_v,
            reduced: Reduced::Empty,
            session,
        })
    }

    /// The change of `K̂` of a regularised step with free rigid motions `free` (columns over
    /// the rigid-motion coordinates): the pins removed, springs on an orthonormal basis of the
    /// free motions over the contact dofs. Kept while the free motions stay the same.
    fn regularizing_for(&mut self, free: &DMatrix<f64>) -> Result<&Correction> {
        let same = self.regularizing.as_ref().is_some_and(|(f, _)| f == free);
        if !same {
            let motions = &self.rigid * free;
            let svd = motions.clone().svd(true, false);
            let largest = svd.singular_values.max();
            let basis: Vec<usize> =
                (0..svd.singular_values.len()).filter(|&j| svd.singular_values[j] > 1e-10 * largest).collect();
            let left = svd.u.ok_or_else(|| Error::PetscUsage("no SVD basis of the free rigid motions".into()))?;
            let p = self.pin_springs.len();
            let mut u = DMatrix::<f64>::zeros(self.schur.len(), p + basis.len());
            u.columns_mut(0, p).copy_from(&self.pins);
            for (k, &j) in basis.iter().enumerate() {
                u.set_column(p + k, &left.column(j));
            }
            let mut c: Vec<f64> = self.pin_springs.iter().map(|k| -k).collect();
            c.extend(std::iter::repeat_n(self.spring, basis.len()));
            let free_columns = u.columns(p, basis.len()).into_owned();
            let mut responses = self.exact.responses.clone();
            responses.extend(responses_of(
                &self.factor,
                &self.schur,
                &free_columns,
                self.num_u,
                &mut self.rhs,
                &mut self.solution,
            )?);
            let correction = Correction::new(u, c, &self.inverse, &self.b_rows, responses);
            self.regularizing = Some((free.clone(), correction));
        }
        self.regularizing.as_ref().map(|(_, c)| c).ok_or_else(|| Error::PetscUsage("no regularising correction".into()))
    }

    /// Take the pieces of a new Jacobian and factorise the small system; `free`: the rigid
    /// motions the Dirichlet, closed and sticking rows leave free (columns over the rigid-motion
    /// coordinates), `None` when they hold every body: springs on those in this step.
    pub fn set_rows(&mut self, rows: Vec<ContactRow>, free: Option<&DMatrix<f64>>) -> Result<()> {
        self.step.set(rows)?;
        self.regularized = free.is_some();
        if let Some(free) = free {
            self.regularizing_for(free)?;
        }
        let (unknowns, columns) = (&self.step.unknowns, &self.step.columns);
        let d = unknowns.len();
        let cor = self.correction();
        let p = cor.len();
        // Rows: Ŵ_D dλ − G_D C π = …, (I + H C) π − Gᵀ dλ = … (module documentation, C = −k for
        // the pins), in the unknowns dλ and |C| π (forces, like dλ: every entry is then a
        // compliance, and the LU loses no digits to the scales of E and 1/E).
        let mut a = DMatrix::<f64>::zeros(d + p, d + p);
        for &(col, wj, coef) in columns {
            for (row, &wi) in unknowns.iter().enumerate() {
                a[(row, col)] += self.w[(wi, wj)] * coef;
            }
            for q in 0..p {
                a[(d + q, col)] -= cor.g[(wj, q)] * coef;
            }
        }
        for q in 0..p {
            let sign = cor.c[q].signum();
            for (row, &wi) in unknowns.iter().enumerate() {
                a[(row, d + q)] = -cor.g[(wi, q)] * sign;
            }
            for q2 in 0..p {
                a[(d + q2, d + q)] = (if q == q2 { 1.0 } else { 0.0 }) / cor.c[q].abs() + cor.h[(q2, q)] * sign;
            }
        }
        self.reduced = Reduced::factorise(self.session, &a)?;
        Ok(())
    }

    /// The change of `K̂` of the current step.
    fn correction(&self) -> &Correction {
        match (&self.regularizing, self.regularized) {
            (Some((_, c)), true) => c,
            _ => &self.exact,
        }
    }

    /// `(du, dλ) = J⁻¹ (r_u, r_λ)` with the pieces of the last [`FloatingElimination::set_rows`]
    /// (`r`, `d`: the force entries, then the contact entries). Force residuals no larger than
    /// `negligible` are round-off: `y = 0` without a solve.
    pub fn solve(&mut self, r: &[f64], d: &mut [f64], negligible: f64) -> Result<()> {
        let n = self.num_u;
        let (r_u, r_c) = r.split_at(n);
        let largest = r_u.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let y = if largest > negligible {
            self.rhs.set_owned(r_u)?;
            self.factor.solve(&self.rhs, &mut self.solution)?;
            self.solution.owned_values()?
        } else {
            vec![0.0; n]
        };
        let by = self.step.frame_components(&y);
        let mut dl = self.step.known_changes(r_c);
        let d_count = self.step.unknowns.len();
        let cor = self.correction();
        let p = cor.len();
        let mut pi = vec![0.0; p];
        // Uᵀ y over the contact dofs.
        let y_contact = DVector::from_iterator(self.schur.len(), self.schur.iter().map(|&dof| y[dof]));
        let uty = cor.u.transpose() * &y_contact;
        if !matches!(self.reduced, Reduced::Empty) {
            let known = DVector::from_column_slice(&dl);
            let w_known = &self.w * &known;
            let g_known = cor.g.transpose() * &known;
            let mut rhs = DVector::<f64>::zeros(d_count + p);
            for (row, &wi) in self.step.unknowns.iter().enumerate() {
                rhs[row] = r_c[self.step.contact_row(wi)] - by[wi] - w_known[wi];
            }
            for q in 0..p {
                rhs[d_count + q] = uty[q] + g_known[q];
            }
            let x = self.reduced.solve(rhs.as_slice(), || Error::SolverDiverged {
                solver: "block elimination of the mixed Jacobian (body held by the contact)".into(),
                reason: "the reduced contact system is singular".into(),
                iterations: 0,
                residual: f64::NAN,
                tried: "MUMPS Cholesky of K with springs at pinned contact dofs, removed in the step; \
                        -contact_full_space_lu factorises the whole mixed Jacobian instead"
                    .into(),
            })?;
            let x = x.unwrap_or_default();
            self.step.add_unknowns(&mut dl, &x);
            for (q, v) in pi.iter_mut().enumerate() {
                *v = x[d_count + q] / cor.c[q].abs();
            }
        }
        if self.in_v {
            // dv = du − K̂⁻¹ Bᵀ dλ = y − K̂⁻¹ U C π: no solve (module documentation, "The
            // unknowns (v, λ)").
            d[..n].copy_from_slice(&y);
            for (q, response) in cor.responses.iter().enumerate() {
                let scale = cor.c[q] * pi[q];
                if scale != 0.0 {
                    for (out, r) in d[..n].iter_mut().zip(response) {
                        *out -= scale * r;
                    }
                }
            }
        } else {
            // du = y + K̂⁻¹ (Bᵀ dλ − U C π): one solve.
            let change = &cor.u * DVector::from_iterator(p, (0..p).map(|q| cor.c[q] * pi[q]));
            let mut load = self.step.load(&dl, n);
            for (position, &dof) in self.schur.iter().enumerate() {
                load[dof] -= change[position];
            }
            let du = v_plus_response(&self.factor, &mut self.rhs, &mut self.solution, &load, &y)?;
            d[..n].copy_from_slice(&du);
        }
        self.step.write_changes(&dl, &mut d[n..]);
        Ok(())
    }

    /// `Ŵ λ`, both in the points' frames (`2i`: normal, `2i + 1`: tangential): with
    /// [`FloatingElimination::pinned_forces`], what the unknowns `(v, λ)` need.
    pub fn flexibility_times(&self, lambda: &[f64]) -> Vec<f64> {
        (&self.w * DVector::from_column_slice(lambda)).as_slice().to_vec()
    }

    /// The `λ` part of the force rows in `(v, λ)`, `−Eᵀ k Gᵀ λ`: `(pinned dof, value)`.
    pub fn pinned_forces(&self, lambda: &[f64]) -> Vec<(usize, f64)> {
        let lambda = DVector::from_column_slice(lambda);
        let gl = self.exact.g.transpose() * lambda;
        self.pinned.iter().enumerate().map(|(q, &dof)| (dof, -self.pin_springs[q] * gl[q])).collect()
    }

    /// The displacement `u = v + K̂⁻¹ Bᵀ λ` (`λ` in the points' frames): one solve.
    pub fn displacement(&mut self, v: &[f64], lambda: &[f64]) -> Result<Vec<f64>> {
        let load = self.step.load(lambda, self.num_u);
        v_plus_response(&self.factor, &mut self.rhs, &mut self.solution, &load, v)
    }
}

/// `K̂⁻¹ U` for the columns of `u` (over the Schur rows `schur`): one solve per column.
fn responses_of<'s>(
    factor: &SchurFactor<'s>,
    schur: &[usize],
    u: &DMatrix<f64>,
    n: usize,
    rhs: &mut Vector<'s>,
    solution: &mut Vector<'s>,
) -> Result<Vec<Vec<f64>>> {
    let mut responses = Vec::with_capacity(u.ncols());
    for q in 0..u.ncols() {
        let mut load = vec![0.0; n];
        for (position, &dof) in schur.iter().enumerate() {
            load[dof] = u[(position, q)];
        }
        rhs.set_owned(&load)?;
        factor.solve(rhs, solution)?;
        responses.push(solution.owned_values()?);
    }
    Ok(responses)
}
