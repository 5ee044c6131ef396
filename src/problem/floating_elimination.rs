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
//! motion (`full_space.rs` checks that at every Jacobian). While they do not (the first steps of
//! a body resting on the obstacle, before the contact zone has formed), the step is regularised
//! as on the full-space route — springs `k = 10⁻³ max diag K / m` at every free contact dof,
//! Levenberg–Marquardt on the free rigid motions — but with springs on the rigid motions only:
//! `K + k Q Qᵀ`, `Q` an orthonormal basis of the rigid motions over the contact dofs (the same
//! energy for every rigid motion). Both changes of `K̂` are low-rank and live on the contact
//! dofs, `U C Uᵀ` (`C = −k_q` for the pins, `+k` for `Q`), and enter the small system the same
//! way: `(I + H C) π − Gᵀ dλ = …` with `G = B K̂⁻¹ U`, `H = Uᵀ K̂⁻¹ U`, `π = Uᵀ du`.
//!
//! The iterate stays `(u, λ)` (unlike the held body's `(v, λ)`): each step costs one solve with
//! the factor for `du` (two when the force rows are not at round-off) and the small system.
//! The pins' springs `k_q` are the pinned dofs' own diagonal stiffness: removing them costs no
//! digits (`I − k H` is of order one).
use nalgebra::{DMatrix, DVector};

use super::block_elimination::{ContactRow, StepRows};
use super::condensed_route::flexibility_from_schur;
use crate::contact::boundary::ContactBoundary;
use crate::error::{Error, Result};
use crate::petsc::schur::SchurFactor;
use crate::petsc::{Matrix, Session, Vector};

/// A change `U C Uᵀ` of `K̂` supported on the contact dofs: `u` (`2m × q`, columns over the Schur
/// rows), `c` (the diagonal of `C`), and `G = B K̂⁻¹ U` (frames), `H = Uᵀ K̂⁻¹ U`.
struct Correction {
    u: DMatrix<f64>,
    c: Vec<f64>,
    g: DMatrix<f64>,
    h: DMatrix<f64>,
}

impl Correction {
    fn new(u: DMatrix<f64>, c: Vec<f64>, inverse: &DMatrix<f64>, b: &ContactBoundary) -> Self {
        let vu = inverse * &u;
        let m = b.points();
        let g = DMatrix::from_fn(2 * m, u.ncols(), |wi, q| {
            let (i, a) = (wi / 2, wi % 2);
            let dir = if a == 0 { b.normal[i] } else { b.tangent[i] };
            dir[0] * vu[(2 * i, q)] + dir[1] * vu[(2 * i + 1, q)]
        });
        let h = u.transpose() * vu;
        Correction { u, c, g, h }
    }

    fn len(&self) -> usize {
        self.c.len()
    }
}

/// One pinned dof: its global dof, its index among the Schur rows and its spring.
#[derive(Debug, Clone, Copy)]
struct Pin {
    dof: usize,
    schur: usize,
    spring: f64,
}

pub(super) struct FloatingElimination<'s> {
    factor: SchurFactor<'s>,
    /// `Ŵ` in the points' frames (`2m × 2m`).
    w: DMatrix<f64>,
    /// The low-rank changes of `K̂` of the exact step (the pins, removed) and of the regularised
    /// step (the pins removed, springs on the rigid motions added).
    exact: Correction,
    regularizing: Correction,
    step: StepRows,
    num_u: usize,
    rhs: Vector<'s>,
    solution: Vector<'s>,
    /// The springs stay in this step's Jacobian (no `π` unknowns).
    regularized: bool,
    reduced: Option<nalgebra::LU<f64, nalgebra::Dyn, nalgebra::Dyn>>,
}

impl<'s> FloatingElimination<'s> {
    /// Factorise `K + Eᵀ k E` (`stiffness` holds `K`: every row, one process; `pinned` the
    /// dofs of `E`, each a dof of a contact node) with the Schur complement on the contact
    /// nodes' dofs.
    pub fn new(
        session: &'s Session,
        stiffness: &crate::fem::assembly::CsrRows,
        boundary: &ContactBoundary,
        per_point: usize,
        pinned: &[usize],
        scaled_positions: &[[f64; 2]],
    ) -> Result<Self> {
        let n = stiffness.num_cols;
        if stiffness.first_row != 0 || stiffness.num_rows() != n {
            return Err(Error::PetscUsage("the floating-body elimination needs every row of K (one process)".into()));
        }
        let rows: Vec<usize> = boundary.nodes.iter().flat_map(|&k| [2 * k, 2 * k + 1]).collect();
        let mut pins = Vec::with_capacity(pinned.len());
        for &dof in pinned {
            let schur = rows
                .iter()
                .position(|&r| r == dof)
                .ok_or_else(|| Error::PetscUsage(format!("pinned dof {dof} is not a dof of a contact node")))?;
            let spring = stiffness.get(dof, dof);
            if !(spring > 0.0 && spring.is_finite()) {
                return Err(Error::PetscUsage(format!("pinned dof {dof} has no positive stiffness")));
            }
            pins.push(Pin { dof, schur, spring });
        }
        let mut values = stiffness.values.clone();
        for pin in &pins {
            let (start, end) =
                (stiffness.indptr[pin.dof - stiffness.first_row], stiffness.indptr[pin.dof - stiffness.first_row + 1]);
            let at = (start..end)
                .find(|&p| stiffness.indices[p] == pin.dof)
                .ok_or_else(|| Error::PetscUsage(format!("pinned dof {}: no diagonal stiffness entry", pin.dof)))?;
            values[at] += pin.spring;
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
        let factor = SchurFactor::new(session, &matrix, &rows)?;
        let w = flexibility_from_schur(&factor, boundary)?;
        let size = rows.len();
        let inverse = DMatrix::from_row_slice(size, size, factor.inverse_block());
        let mut u_pins = DMatrix::<f64>::zeros(size, pins.len());
        for (q, pin) in pins.iter().enumerate() {
            u_pins[(pin.schur, q)] = 1.0;
        }
        let removed: Vec<f64> = pins.iter().map(|p| -p.spring).collect();
        let exact = Correction::new(u_pins.clone(), removed.clone(), &inverse, boundary);
        // The regularised step: the springs of the full-space route on the rigid motions only
        // (the same energy for a rigid motion as k at every free contact dof, k = 10⁻³ max diag K
        // / m), an orthonormal basis of the rigid motions over the contact dofs.
        let m = boundary.points();
        let max_diagonal = (0..n).map(|d| stiffness.get(d, d).abs()).fold(0.0f64, f64::max);
        let spring = 1e-3 * max_diagonal / m.max(1) as f64;
        let mut rigid = DMatrix::<f64>::zeros(size, 3);
        for i in 0..m {
            let p = scaled_positions[i];
            for c in 0..2 {
                if boundary.prescribed[i].is_some_and(|(pc, _)| pc == c) {
                    continue;
                }
                rigid[(2 * i + c, c)] = 1.0;
                rigid[(2 * i + c, 2)] = if c == 0 { -p[1] } else { p[0] };
            }
        }
        let svd = rigid.svd(true, false);
        let largest = svd.singular_values.max();
        let basis: Vec<usize> = (0..3).filter(|&j| svd.singular_values[j] > 1e-10 * largest).collect();
        let left = svd.u.ok_or_else(|| Error::PetscUsage("no SVD basis of the rigid motions".into()))?;
        let mut u_reg = DMatrix::<f64>::zeros(size, pins.len() + basis.len());
        u_reg.columns_mut(0, pins.len()).copy_from(&u_pins);
        for (k, &j) in basis.iter().enumerate() {
            u_reg.set_column(pins.len() + k, &left.column(j));
        }
        let mut c_reg = removed;
        c_reg.extend(std::iter::repeat_n(spring, basis.len()));
        let regularizing = Correction::new(u_reg, c_reg, &inverse, boundary);
        Ok(FloatingElimination {
            rhs: matrix.create_vector()?,
            solution: matrix.create_vector()?,
            factor,
            w,
            exact,
            regularizing,
            step: StepRows::new(boundary, per_point),
            num_u: n,
            regularized: false,
            reduced: None,
        })
    }

    /// Take the pieces of a new Jacobian and factorise the small system; `regularized`: keep the
    /// springs in this step (the contact rows do not hold the body yet).
    pub fn set_rows(&mut self, rows: Vec<ContactRow>, regularized: bool) -> Result<()> {
        self.step.set(rows)?;
        self.regularized = regularized;
        let (unknowns, columns) = (&self.step.unknowns, &self.step.columns);
        let d = unknowns.len();
        let cor = if regularized { &self.regularizing } else { &self.exact };
        let p = cor.len();
        // Rows: Ŵ_D dλ − G_D C π = …, (I + H C) π − Gᵀ dλ = … (module documentation, C = −k for
        // the pins).
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
            for (row, &wi) in unknowns.iter().enumerate() {
                a[(row, d + q)] = -cor.g[(wi, q)] * cor.c[q];
            }
            for q2 in 0..p {
                a[(d + q2, d + q)] = if q == q2 { 1.0 } else { 0.0 } + cor.h[(q2, q)] * cor.c[q];
            }
        }
        self.reduced = if d + p == 0 { None } else { Some(a.lu()) };
        Ok(())
    }

    /// `(du, dλ) = J⁻¹ (r_u, r_λ)` with the pieces of the last [`FloatingElimination::set_rows`]
    /// (`r`, `d`: the force entries, then the contact entries). Force residuals no larger than
    /// `negligible` are round-off: `y = 0` without a solve.
    pub fn solve(&mut self, r: &[f64], d: &mut [f64], negligible: f64) -> Result<()> {
        let n = self.num_u;
        let (r_u, r_c) = r.split_at(n);
        let m = self.step.nodes().len();
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
        let cor = if self.regularized { &self.regularizing } else { &self.exact };
        let p = cor.len();
        let mut pi = vec![0.0; p];
        // Uᵀ y over the contact dofs.
        let y_contact = DVector::from_iterator(2 * m, self.step.nodes().iter().flat_map(|&k| [y[2 * k], y[2 * k + 1]]));
        let uty = cor.u.transpose() * &y_contact;
        if let Some(lu) = &self.reduced {
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
            let x = lu.solve(&rhs).ok_or_else(|| Error::SolverDiverged {
                solver: "block elimination of the mixed Jacobian (body held by the contact)".into(),
                reason: "the reduced contact system is singular".into(),
                iterations: 0,
                residual: f64::NAN,
                tried: "MUMPS Cholesky of K with springs at pinned contact dofs, removed in the step; \
                        -contact_full_space_lu factorises the whole mixed Jacobian instead"
                    .into(),
            })?;
            self.step.add_unknowns(&mut dl, x.as_slice());
            pi.copy_from_slice(&x.as_slice()[d_count..]);
        }
        // du = y + K̂⁻¹ (Bᵀ dλ − U C π).
        let change = &cor.u * DVector::from_iterator(p, (0..p).map(|q| cor.c[q] * pi[q]));
        let mut load = self.step.load(&dl, n);
        for (k, &node) in self.step.nodes().iter().enumerate() {
            for c in 0..2 {
                load[2 * node + c] -= change[2 * k + c];
            }
        }
        if load.iter().any(|&v| v != 0.0) {
            self.rhs.set_owned(&load)?;
            self.factor.solve(&self.rhs, &mut self.solution)?;
            let response = self.solution.owned_values()?;
            for (out, (a, b)) in d[..n].iter_mut().zip(y.iter().zip(&response)) {
                *out = a + b;
            }
        } else {
            d[..n].copy_from_slice(&y);
        }
        self.step.write_changes(&dl, &mut d[n..]);
        Ok(())
    }
}
