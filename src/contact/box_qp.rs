//! Box-constrained quadratic programs: the sub-problems of D-PANA.
//!
//! ```text
//!   minimize  ½ xᵀ A x − bᵀ x   subject to  l ≤ x ≤ u     (A symmetric positive definite,
//!                                                          l_i may be −∞, u_i may be +∞)
//! ```
//!
//! Primal–dual active set method (Hintermüller, Ito & Kunisch, "The primal–dual active set
//! strategy as a semismooth Newton method", SIAM J. Optim. 13(3), 2002), written as the
//! semi-smooth Newton method on the natural map `x − clamp(x − D⁻¹(Ax − b), l, u)` with
//! `D = diag(A)`:
//!
//! ```text
//!   τ = x − D⁻¹ (A x − b)
//!   L = { i : τ_i ≤ l_i },  U = { i : τ_i ≥ u_i },  I = the others
//!   x_L = l_L,  x_U = u_U,  A_II x_I = b_I − A_IL l_L − A_IU u_U     (Cholesky)
//! ```
//!
//! When the sets repeat from one iteration to the next, `x` is the exact minimizer (the KKT
//! conditions hold by construction). The method converges in finitely many steps for
//! M-matrices; for a general SPD `A` it can cycle: a repeated set (or too many iterations)
//! switches to projected Gauss–Seidel sweeps (exact minimization along each coordinate
//! followed by the clamp), which converge for any SPD `A` (Cryer 1971).
use nalgebra::DMatrix;

/// Outcome of a box QP solve.
#[derive(Debug, Clone)]
pub(crate) struct BoxQpResult {
    pub x: Vec<f64>,
    pub active_set_iterations: usize,
    pub gauss_seidel_sweeps: usize,
    /// Relative natural-map residual of the returned `x`.
    pub residual: f64,
    pub converged: bool,
}

/// Relative natural-map residual `max_i |x_i − clamp(x_i − (Ax − b)_i / A_ii)| / scale`.
fn natural_residual(a: &DMatrix<f64>, b: &[f64], lower: &[f64], upper: &[f64], x: &[f64]) -> f64 {
    let n = x.len();
    let mut scale = 0.0f64;
    let mut worst = 0.0f64;
    for i in 0..n {
        let ax: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum();
        let step = (ax - b[i]) / a[(i, i)];
        let projected = (x[i] - step).clamp(lower[i], upper[i]);
        worst = worst.max((x[i] - projected).abs());
        scale = scale.max(x[i].abs()).max((b[i] / a[(i, i)]).abs());
    }
    if scale == 0.0 {
        worst
    } else {
        worst / scale
    }
}

/// Solve the box QP to the relative natural-map residual `tolerance`, starting from `start`.
pub(crate) fn solve(
    a: &DMatrix<f64>,
    b: &[f64],
    lower: &[f64],
    upper: &[f64],
    start: &[f64],
    tolerance: f64,
    max_sweeps: usize,
) -> BoxQpResult {
    let n = b.len();
    let mut x: Vec<f64> = (0..n).map(|i| start[i].clamp(lower[i], upper[i])).collect();
    if n == 0 {
        return BoxQpResult { x, active_set_iterations: 0, gauss_seidel_sweeps: 0, residual: 0.0, converged: true };
    }
    // Primal–dual active set.
    #[derive(Clone, Copy, PartialEq, Eq, Hash)]
    enum Bound {
        Lower,
        Upper,
        Free,
    }
    let mut seen: Vec<Vec<Bound>> = Vec::new();
    let mut previous: Option<Vec<Bound>> = None;
    let mut active_set_iterations = 0;
    let max_active_set_iterations = 50 + n;
    loop {
        let sets: Vec<Bound> = (0..n)
            .map(|i| {
                if lower[i] == upper[i] {
                    return Bound::Lower;
                }
                let ax: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum();
                let tau = x[i] - (ax - b[i]) / a[(i, i)];
                if tau <= lower[i] {
                    Bound::Lower
                } else if tau >= upper[i] {
                    Bound::Upper
                } else {
                    Bound::Free
                }
            })
            .collect();
        if previous.as_ref() == Some(&sets) {
            let residual = natural_residual(a, b, lower, upper, &x);
            if residual <= tolerance {
                return BoxQpResult { x, active_set_iterations, gauss_seidel_sweeps: 0, residual, converged: true };
            }
        }
        if seen.contains(&sets) && previous.as_ref() != Some(&sets)
            || active_set_iterations >= max_active_set_iterations
        {
            break; // cycling or too slow: projected Gauss–Seidel below
        }
        seen.push(sets.clone());
        active_set_iterations += 1;
        let free: Vec<usize> = (0..n).filter(|&i| sets[i] == Bound::Free).collect();
        let mut next = vec![0.0; n];
        for i in 0..n {
            next[i] = match sets[i] {
                Bound::Lower => lower[i],
                Bound::Upper => upper[i],
                Bound::Free => 0.0,
            };
        }
        if !free.is_empty() {
            let k = free.len();
            let mut matrix = DMatrix::<f64>::zeros(k, k);
            let mut rhs = nalgebra::DVector::<f64>::zeros(k);
            for (p, &i) in free.iter().enumerate() {
                let mut value = b[i];
                for j in 0..n {
                    if sets[j] != Bound::Free {
                        value -= a[(i, j)] * next[j];
                    }
                }
                rhs[p] = value;
                for (q, &j) in free.iter().enumerate() {
                    matrix[(p, q)] = a[(i, j)];
                }
            }
            match nalgebra::Cholesky::new(matrix) {
                Some(cholesky) => {
                    let solution = cholesky.solve(&rhs);
                    for (p, &i) in free.iter().enumerate() {
                        next[i] = solution[p];
                    }
                }
                None => break,
            }
        }
        if next.iter().any(|v| !v.is_finite()) {
            break;
        }
        x = next;
        previous = Some(sets);
    }
    // Projected Gauss–Seidel from the best feasible point we have.
    for i in 0..n {
        x[i] = x[i].clamp(lower[i], upper[i]);
    }
    let mut sweeps = 0;
    let mut residual = natural_residual(a, b, lower, upper, &x);
    while residual > tolerance && sweeps < max_sweeps {
        for i in 0..n {
            let ax: f64 = (0..n).map(|j| a[(i, j)] * x[j]).sum();
            x[i] = (x[i] - (ax - b[i]) / a[(i, i)]).clamp(lower[i], upper[i]);
        }
        sweeps += 1;
        if sweeps % 10 == 0 || sweeps == max_sweeps {
            residual = natural_residual(a, b, lower, upper, &x);
        }
    }
    residual = natural_residual(a, b, lower, upper, &x);
    BoxQpResult { x, active_set_iterations, gauss_seidel_sweeps: sweeps, residual, converged: residual <= tolerance }
}
