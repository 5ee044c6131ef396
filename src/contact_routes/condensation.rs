//! The condensed route's linear algebra and solver choice: the flexibility from a factor with
//! the Schur complement, the factorised stiffness (MUMPS Schur factor or the configured KSP),
//! TAO on the Tresca box QP, and the condensed solver a scene names (see `condensed_route.rs`).
use nalgebra::DMatrix;

use crate::contact::boundary::ContactBoundary;
use crate::contact::{self, CondensedProblem, ContactSolver, Delassus, FrictionLaw};
use crate::error::{Error, Result};
use crate::petsc::schur::SchurFactor;
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats, Vector};
use crate::scene::ContactSolverSpec;

/// The flexibility `W = B K⁻¹ Bᵀ` (`2m × 2m`, each point's rows and columns in its frame
/// `(n, t)`) from a factor with the Schur complement `S` on the dofs `B` touches
/// ([`schur_dofs`]: both dofs of every node of [`ContactBoundary::support_nodes`], in that
/// order): `(K⁻¹)_ss = S⁻¹` and `W = B_s S⁻¹ B_sᵀ`, `B_s` the columns of `B` on those dofs
/// (against a rigid obstacle, `W_ij = R_iᵀ (S⁻¹)_{ij} R_j` with `R = [n t]`).
pub(crate) fn flexibility_from_schur(factor: &SchurFactor<'_>, b: &ContactBoundary) -> Result<DMatrix<f64>> {
    let m = b.points();
    let dofs = schur_dofs(b);
    let k = factor.size();
    if k != dofs.len() {
        return Err(Error::PetscUsage(format!(
            "Schur complement of order {k} for {} dofs touched by {m} contact points",
            dofs.len()
        )));
    }
    let inverse = DMatrix::from_row_slice(k, k, factor.inverse_block());
    if (0..k).map(|i| inverse[(i, i)]).any(|d| d.is_nan() || d <= 0.0 || d.is_infinite()) {
        return Err(Error::Unconstrained(
            "the Schur complement of the stiffness on the contact dofs is not positive definite".into(),
        ));
    }
    let rows = rows_on_schur(b, &dofs);
    let mut w = DMatrix::<f64>::zeros(2 * m, 2 * m);
    for a in 0..2 * m {
        for c in 0..=a {
            let mut v = 0.0;
            for &(p, bp) in &rows[a] {
                for &(q, bq) in &rows[c] {
                    v += bp * inverse[(p, q)] * bq;
                }
            }
            w[(a, c)] = v;
            w[(c, a)] = v;
        }
    }
    Ok(w)
}

/// The rows of `B` (`2m`, each point's normal then tangential row) on the positions of
/// `dofs` (increasing; [`schur_dofs`]): `(position, coefficient)` pairs, zeros left out.
pub(crate) fn rows_on_schur(b: &ContactBoundary, dofs: &[usize]) -> Vec<Vec<(usize, f64)>> {
    (0..2 * b.points())
        .map(|j| {
            b.b_row(j)
                .into_iter()
                .filter(|&(_, c)| c != 0.0)
                .filter_map(|(dof, c)| dofs.binary_search(&dof).ok().map(|p| (p, c)))
                .collect()
        })
        .collect()
}

/// The dofs of the Schur complement of the condensed route: both dofs of every node `B`
/// touches, increasing.
pub(crate) fn schur_dofs(b: &ContactBoundary) -> Vec<usize> {
    b.support_nodes().into_iter().flat_map(|k| [2 * k, 2 * k + 1]).collect()
}

/// The factorised stiffness the condensed route solves with: a MUMPS factor with the Schur
/// complement on the contact dofs, or the configured KSP (any PETSc options, any ranks).
pub(crate) enum Factorised<'a, 's> {
    /// The factor and the seconds its factorisation took; the last solve's statistics.
    Schur(SchurFactor<'s>, f64),
    Krylov(&'a mut LinearSolver<'s>),
}

impl<'s> Factorised<'_, 's> {
    /// Solve `K x = b`; the factor's answers get the same independent residual check as the
    /// KSP's (‖b − Kx‖/‖b‖ ≤ 1e-6).
    pub(crate) fn solve(&mut self, matrix: &Matrix<'s>, b: &Vector<'s>, x: &mut Vector<'s>) -> Result<()> {
        match self {
            Factorised::Krylov(ksp) => ksp.solve(matrix, b, x).map(|_| ()),
            Factorised::Schur(factor, _) => {
                factor.solve(b, x)?;
                let relative = matrix.relative_residual(x, b)?;
                if !(relative <= 1e-6) {
                    return Err(Error::SolverDiverged {
                        solver: "MUMPS Cholesky with Schur complement".into(),
                        reason: format!("true relative residual {relative:.3e}"),
                        iterations: 1,
                        residual: relative,
                        tried: "give -ksp_type/-pc_type to use the KSP route instead".into(),
                    });
                }
                Ok(())
            }
        }
    }

    /// What the linear solves were, for the report (the KSP records its own).
    pub(crate) fn stats(&self) -> Option<SolveStats> {
        match self {
            Factorised::Krylov(ksp) => ksp.last_stats(),
            Factorised::Schur(_, seconds) => Some(SolveStats {
                ksp_type: "preonly".into(),
                pc_type: "cholesky".into(),
                factor_package: Some("mumps (Schur complement on the contact dofs)".into()),
                iterations: 1,
                converged_reason: "factorised once; every solve checked (relative residual <= 1e-6)".into(),
                relative_residual: 0.0,
                seconds: *seconds,
            }),
        }
    }
}

/// TAO on the Tresca box QP: min ½ rᵀ W r + rᵀ (u_free − g̃), rN ≤ 0, |rT| ≤ s.
pub(crate) fn tao_box_qp(session: &Session, problem: &CondensedProblem) -> Result<contact::ContactSolution> {
    let m = problem.points();
    let w = match problem.delassus() {
        Delassus::Dense(w) => w,
        _ => return Err(Error::Usage("TAO needs the dense flexibility matrix".into())),
    };
    let n2 = 2 * m;
    let h: Vec<f64> = (0..n2 * n2).map(|k| w[(k / n2, k % n2)]).collect();
    let mut c = problem.free_displacement().to_vec();
    for i in 0..m {
        c[2 * i] -= problem.gap()[i];
    }
    let thresholds = match problem.friction() {
        FrictionLaw::Tresca { threshold } => threshold.clone(),
        _ => return Err(Error::Usage("TAO solves the Tresca problem (friction = \"tresca\")".into())),
    };
    let inf = f64::INFINITY;
    let lower: Vec<f64> = (0..n2).map(|k| if k % 2 == 0 { -inf } else { -thresholds[k / 2] }).collect();
    let upper: Vec<f64> = (0..n2).map(|k| if k % 2 == 0 { 0.0 } else { thresholds[k / 2] }).collect();
    let mut r = vec![0.0; n2];
    let run = crate::petsc::bounded::solve_box_qp(session, &h, &c, &lower, &upper, &mut r, "contact_")?;
    let displacement = problem.displacement(&r)?;
    let residuals = problem.residuals(&r)?;
    let status = problem.status(&r)?;
    Ok(contact::ContactSolution {
        force: r,
        displacement,
        iterations: run.iterations,
        history: Vec::new(),
        status,
        residuals,
        solver: run.method,
        notes: vec![run.converged_reason],
    })
}

/// The condensed solver of a scene's `solver = ...` (the full-space Newton maps to the condensed
/// semi-smooth Newton); `None` for the solvers that only run on the full system (SNESVI) or
/// outside [`contact::solve`] (TAO).
pub(crate) fn condensed_solver(spec: &ContactSolverSpec) -> Option<ContactSolver> {
    Some(match spec {
        ContactSolverSpec::Newton | ContactSolverSpec::FullSpaceNewton => ContactSolver::SemismoothNewton,
        ContactSolverSpec::Relaxation { omega } => ContactSolver::ProjectedRelaxation { omega: *omega },
        ContactSolverSpec::DPana => ContactSolver::DPana,
        ContactSolverSpec::Uzawa => ContactSolver::Uzawa { accelerated: true },
        ContactSolverSpec::TrescaFixedPoint => {
            ContactSolver::TrescaFixedPoint { inner: Box::new(ContactSolver::SemismoothNewton) }
        }
        ContactSolverSpec::SnesVi | ContactSolverSpec::Tao => return None,
    })
}

/// The condensed solvers' settings for the scene's `[contact]`: its tolerance and iteration
/// limit where it gives them, and LAPACK's LU for the semi-smooth Newton's dense steps.
pub(crate) fn solver_settings(spec: &crate::scene::ContactSpec) -> contact::SolverSettings {
    let defaults = contact::SolverSettings::default();
    contact::SolverSettings {
        tolerance: spec.tolerance.unwrap_or(defaults.tolerance),
        max_iterations: spec.max_iterations.unwrap_or(defaults.max_iterations),
        dense_solver: Some(lapack_dense_solver()),
        ..defaults
    }
}

/// The condensed semi-smooth Newton's dense solver: LAPACK's LU through PETSc
/// (`petsc::dense_lu`), with nalgebra's LU if PETSc fails for any other reason than a zero
/// pivot (the step then reports a singular system only if both do).
fn lapack_dense_solver() -> contact::DenseSolver {
    contact::DenseSolver(std::sync::Arc::new(|a: &DMatrix<f64>, b: &nalgebra::DVector<f64>| {
        match crate::petsc::dense_lu::solve_once(a, b.as_slice()) {
            Ok(x) => x.map(nalgebra::DVector::from_vec),
            Err(_) => a.clone().lu().solve(b),
        }
    }))
}
