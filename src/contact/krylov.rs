//! Krylov solvers for the Newton systems when `W` is only available through products.
//!
//! - Preconditioned conjugate gradients (M. R. Hestenes, E. Stiefel, J. Res. Nat. Bur.
//!   Standards 49, 1952) for the symmetric positive definite systems of frictionless and
//!   Tresca problems (principal sub-matrices of `W`).
//! - Restarted GMRES (Y. Saad, M. H. Schultz, SIAM J. Sci. Stat. Comput. 7, 1986) with right
//!   preconditioning and Givens rotations, for the non-symmetric systems of Coulomb problems.
//!
//! Both use the Jacobi preconditioner `diag⁻¹` and start from zero; `tolerance` is relative to
//! `‖b‖₂`.

#[derive(Debug, Clone)]
pub(crate) struct KrylovResult {
    pub x: Vec<f64>,
    pub iterations: usize,
    pub relative_residual: f64,
    pub converged: bool,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

pub(crate) fn conjugate_gradient(
    apply: &dyn Fn(&[f64], &mut [f64]),
    diagonal: &[f64],
    b: &[f64],
    tolerance: f64,
    max_iterations: usize,
) -> KrylovResult {
    let n = b.len();
    let b_norm = norm(b);
    let mut x = vec![0.0; n];
    if b_norm == 0.0 {
        return KrylovResult { x, iterations: 0, relative_residual: 0.0, converged: true };
    }
    let mut residual = b.to_vec();
    let mut z: Vec<f64> = residual.iter().zip(diagonal).map(|(r, d)| r / d).collect();
    let mut direction = z.clone();
    let mut rz = dot(&residual, &z);
    let mut a_direction = vec![0.0; n];
    for iteration in 1..=max_iterations {
        apply(&direction, &mut a_direction);
        let curvature = dot(&direction, &a_direction);
        if curvature.is_nan() || curvature <= 0.0 {
            return KrylovResult {
                x,
                iterations: iteration,
                relative_residual: norm(&residual) / b_norm,
                converged: false,
            };
        }
        let alpha = rz / curvature;
        for k in 0..n {
            x[k] += alpha * direction[k];
            residual[k] -= alpha * a_direction[k];
        }
        let relative = norm(&residual) / b_norm;
        if relative <= tolerance {
            return KrylovResult { x, iterations: iteration, relative_residual: relative, converged: true };
        }
        for k in 0..n {
            z[k] = residual[k] / diagonal[k];
        }
        let rz_next = dot(&residual, &z);
        let beta = rz_next / rz;
        rz = rz_next;
        for k in 0..n {
            direction[k] = z[k] + beta * direction[k];
        }
    }
    let relative = norm(&residual) / b_norm;
    KrylovResult { x, iterations: max_iterations, relative_residual: relative, converged: relative <= tolerance }
}

pub(crate) fn gmres(
    apply: &dyn Fn(&[f64], &mut [f64]),
    diagonal: &[f64],
    b: &[f64],
    tolerance: f64,
    restart: usize,
    max_iterations: usize,
) -> KrylovResult {
    let n = b.len();
    let b_norm = norm(b);
    let mut x = vec![0.0; n];
    if b_norm == 0.0 {
        return KrylovResult { x, iterations: 0, relative_residual: 0.0, converged: true };
    }
    let restart = restart.max(1).min(n.max(1));
    let mut total = 0;
    let mut work = vec![0.0; n];
    let mut relative = 1.0;
    while total < max_iterations {
        // r = b − A x
        apply(&x, &mut work);
        let r: Vec<f64> = b.iter().zip(&work).map(|(bi, ai)| bi - ai).collect();
        let beta = norm(&r);
        relative = beta / b_norm;
        if relative <= tolerance {
            return KrylovResult { x, iterations: total, relative_residual: relative, converged: true };
        }
        let mut basis: Vec<Vec<f64>> = vec![r.iter().map(|v| v / beta).collect()];
        let mut hessenberg: Vec<Vec<f64>> = Vec::new(); // column j has j + 2 entries
        let mut cosines: Vec<f64> = Vec::new();
        let mut sines: Vec<f64> = Vec::new();
        let mut g = vec![beta];
        let mut steps = 0;
        for j in 0..restart {
            if total >= max_iterations {
                break;
            }
            total += 1;
            steps = j + 1;
            // w = A M⁻¹ v_j
            let preconditioned: Vec<f64> = basis[j].iter().zip(diagonal).map(|(v, d)| v / d).collect();
            apply(&preconditioned, &mut work);
            let mut w = work.clone();
            let mut column = vec![0.0; j + 2];
            for (i, v) in basis.iter().enumerate() {
                let h = dot(&w, v);
                column[i] = h;
                for k in 0..n {
                    w[k] -= h * v[k];
                }
            }
            let w_norm = norm(&w);
            column[j + 1] = w_norm;
            for i in 0..j {
                let (c, s) = (cosines[i], sines[i]);
                let (a, b2) = (column[i], column[i + 1]);
                column[i] = c * a + s * b2;
                column[i + 1] = -s * a + c * b2;
            }
            let (a, b2) = (column[j], column[j + 1]);
            let rho = a.hypot(b2);
            let (c, s) = if rho == 0.0 { (1.0, 0.0) } else { (a / rho, b2 / rho) };
            cosines.push(c);
            sines.push(s);
            column[j] = rho;
            column[j + 1] = 0.0;
            let gj = g[j];
            g[j] = c * gj;
            g.push(-s * gj);
            hessenberg.push(column);
            relative = g[j + 1].abs() / b_norm;
            if relative <= tolerance || w_norm == 0.0 {
                break;
            }
            basis.push(w.iter().map(|v| v / w_norm).collect());
        }
        // Back substitution H y = g, then x += M⁻¹ V y.
        let mut y = vec![0.0; steps];
        for i in (0..steps).rev() {
            let mut value = g[i];
            for k in (i + 1)..steps {
                value -= hessenberg[k][i] * y[k];
            }
            y[i] = if hessenberg[i][i] != 0.0 { value / hessenberg[i][i] } else { 0.0 };
        }
        for (k, yk) in y.iter().enumerate() {
            for i in 0..n {
                x[i] += yk * basis[k][i] / diagonal[i];
            }
        }
        if relative <= tolerance {
            apply(&x, &mut work);
            let true_relative = norm(&b.iter().zip(&work).map(|(bi, ai)| bi - ai).collect::<Vec<_>>()) / b_norm;
            if true_relative <= 10.0 * tolerance {
                return KrylovResult { x, iterations: total, relative_residual: true_relative, converged: true };
            }
        }
    }
    KrylovResult { x, iterations: total, relative_residual: relative, converged: false }
}
