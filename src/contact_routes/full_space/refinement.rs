//! Iterative refinement of the eliminations' answer against `K` itself.
//!
//! The block eliminations (`block_elimination.rs`, `floating_elimination.rs`) iterate in
//! `(v, λ)` with `u = v + K̂⁻¹ Bᵀ λ`: the contact displacements of the iteration are
//! `B v + Ŵ λ`, with `Ŵ` from the dense inverse of the Schur complement of the factorised
//! `K̂`, while `u` is recovered at the end by a solve with the factor. Both are backward stable,
//! but their forward errors are `cond(K̂) ε` apart, and `K̂` can be far worse conditioned than the
//! problem: a slender body held by the contact and a few pins (`K̂ = K + Eᵀ k E`) bends under
//! the pins' springs, `cond(K̂) ≈ (L/h)⁴`. On a 250 × 1 strip resting on the obstacle (P1,
//! `h = 0.25`) the recovered `u` penetrated the obstacle by 1.4e-8 of the displacement scale
//! where the iteration had seen 4e-15, and the contact pressure, uniform in the exact solution,
//! came out uniform to 3e-6 only (SNES's LU of the mixed Jacobian: 2e-13).
//!
//! The answer `(u, λ)` is therefore refined (J. H. Wilkinson, *Rounding Errors in Algebraic
//! Processes*, 1963; N. J. Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed.,
//! SIAM 2002, ch. 12): the residual of the full-space equations is evaluated on `(u, λ)` itself,
//!
//! ```text
//!   F_u = K u − f − Bᵀ λ          (K's own rows: no springs, no Schur complement)
//!   C   = the Alart–Curnier contact rows at (B u, λ)
//! ```
//!
//! and a Newton step of the last Jacobian, solved by the elimination in the unknowns `(u, λ)`
//! (`du` by a solve with the factor, not through `Ŵ`), corrects it: `u ← u − du`, `λ ← λ − dλ`.
//! Each step multiplies the error by about `cond(K̂) ε` (here 1e-7), so one or two steps reach
//! the round-off of the problem itself; a step is kept only if it halves the residual, and at
//! most [`MAX_STEPS`] are taken. A residual already at round-off ([`ROUND_OFF`]) is not
//! refined: on a well-conditioned body this costs one product with `K`.
use super::mixed_system::{evaluate, Law, MixedSystem};
use crate::contact::boundary::ContactBoundary;
use crate::error::{Error, Result};
use crate::fem::assembly::CsrRows;

/// At most this many refinement steps.
pub(super) const MAX_STEPS: usize = 3;
/// A residual (the larger of the force rows' backward error and the contact rows relative to
/// the displacement scale) at or below this is round-off: no refinement.
pub(super) const ROUND_OFF: f64 = 1e-14;

/// What the refinement did.
#[derive(Debug, Clone, Copy)]
pub(super) struct Refinement {
    pub steps: usize,
    pub before: f64,
    pub after: f64,
}

/// The full-space problem on one process, as the refinement sees it.
pub(super) struct Equations<'a> {
    pub stiffness: &'a CsrRows,
    pub rhs: &'a [f64],
    pub boundary: &'a ContactBoundary,
    pub law: &'a Law,
    pub rho: &'a [f64],
    pub per_point: usize,
}

impl Equations<'_> {
    /// The residual `(F_u, C)` in the mixed layout (the dofs, then `per_point` rows per point)
    /// and its size: `max(max|F_u| / max_r (Σ_j |K_rj u_j| + |f_r| + |Bᵀλ|_r), max|C| / U)`,
    /// `U` the largest displacement or gap.
    fn residual(&self, u: &[f64], force: &[f64]) -> (Vec<f64>, f64) {
        let (k, b) = (self.stiffness, self.boundary);
        let n = u.len();
        let m = b.points();
        let mut contact_load = vec![0.0; n];
        b.scatter_add(force, &mut contact_load);
        let mut r = vec![0.0; n + self.per_point * m];
        let (mut num, mut den, mut u_scale) = (0.0f64, 0.0f64, 0.0f64);
        for dof in 0..n {
            let (cols, vals) = k.row(dof);
            let (mut ku, mut terms) = (0.0, 0.0);
            for (&c, &v) in cols.iter().zip(vals) {
                ku += v * u[c];
                terms += (v * u[c]).abs();
            }
            r[dof] = ku - self.rhs[dof] - contact_load[dof];
            num = num.max(r[dof].abs());
            den = den.max(terms + self.rhs[dof].abs() + contact_load[dof].abs());
            u_scale = u_scale.max(u[dof].abs());
        }
        let uc = b.gather(u);
        let mut c_max = 0.0f64;
        for i in 0..m {
            u_scale = u_scale.max(b.gap[i].abs());
            let e = evaluate(
                self.law,
                i,
                [self.rho[i]; 2],
                b.gap[i],
                [uc[2 * i], uc[2 * i + 1]],
                [force[2 * i], force[2 * i + 1]],
            );
            r[n + self.per_point * i] = e.c_n;
            c_max = c_max.max(e.c_n.abs());
            if self.per_point == 2 {
                r[n + 2 * i + 1] = e.c_t;
                c_max = c_max.max(e.c_t.abs());
            }
        }
        let equilibrium = if den > 0.0 { num / den } else { num };
        let contact = if u_scale > 0.0 { c_max / u_scale } else { c_max };
        let size = equilibrium.max(contact);
        (r, if size.is_nan() { f64::INFINITY } else { size })
    }
}

impl MixedSystem<'_, '_> {
    /// Refine `(u, λ)` (`force`: `λ` in the points' frames, `2m`) against `K` with the
    /// elimination's last Jacobian (module documentation). One process, an elimination set up.
    pub(super) fn refine(
        &mut self,
        equations: &Equations,
        u: &mut Vec<f64>,
        force: &mut Vec<f64>,
    ) -> Result<Refinement> {
        let n = u.len();
        let per_point = equations.per_point;
        let (mut r, mut size) = equations.residual(u, force);
        let before = size;
        let mut steps = 0;
        while steps < MAX_STEPS && size > ROUND_OFF {
            let mut d = vec![0.0; r.len()];
            // The step's force change, from its contact rows (a frictionless point has one).
            let force_change = |d: &[f64]| {
                let mut change = vec![0.0; force.len()];
                for (i, c) in change.chunks_mut(2).enumerate() {
                    c[..per_point].copy_from_slice(&d[n + per_point * i..n + per_point * (i + 1)]);
                }
                change
            };
            let (du, change) = if let Some(elimination) = &mut self.elimination {
                // (dv, dλ), then du = dv + K⁻¹ Bᵀ dλ (one solve).
                elimination.solve(&r, &mut d, 0.0)?;
                let change = force_change(&d);
                (elimination.displacement(&d[..n], &change)?, change)
            } else if let Some(floating) = &mut self.held_by_contact {
                // The (u, λ) form of the step: du by a solve with the factor.
                let in_v = floating.in_v;
                floating.in_v = false;
                let solved = floating.solve(&r, &mut d, 0.0);
                floating.in_v = in_v;
                solved?;
                (d[..n].to_vec(), force_change(&d))
            } else {
                return Err(Error::PetscUsage("refinement without an elimination".into()));
            };
            let trial_u: Vec<f64> = u.iter().zip(&du).map(|(a, b)| a - b).collect();
            let trial_force: Vec<f64> = force.iter().zip(&change).map(|(a, b)| a - b).collect();
            let (trial_r, trial_size) = equations.residual(&trial_u, &trial_force);
            // (Sizes are never NaN: `residual` maps NaN to +∞.)
            if trial_size > 0.5 * size {
                break;
            }
            (*u, *force, r, size) = (trial_u, trial_force, trial_r, trial_size);
            steps += 1;
        }
        Ok(Refinement { steps, before, after: size })
    }
}
