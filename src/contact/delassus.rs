//! The Delassus (flexibility) operator `W` of the condensed problem: explicit entries, or an
//! operator giving products only; validated when a [`super::CondensedProblem`] is built
//! (sizes, finite entries, symmetry, a positive diagonal, positive definiteness — for the
//! operator by two deterministic probes).
//!
//! ## Implicit operators and lifetimes
//!
//! An implicit `W` is a product callback `y = W x` ([`DelassusProduct`]). The callback may
//! borrow (or share through an `Rc`) what computes the products — in the dual formulation a
//! factorisation or a KSP of the interior block, PETSc handles that live as long as the PETSc
//! session `'s` and are neither `Send` nor `Sync` — so [`Delassus`] and
//! [`super::CondensedProblem`] carry the lifetime `'a` of the callback, and the callback is not
//! required to be `'static`, `Send` or `Sync`: a problem built on it lives only as long as what
//! it borrows, which the borrow checker enforces. A dense `W` (or an owning closure) gives
//! `Delassus<'static>`. A product that can fail (a linear solve) cannot return an error through
//! the solvers: it writes NaN into `y` (every solver stops on a non-finite iterate) and its owner
//! keeps the error, to be returned in place of the solver's (see `crate::dual::condensation`).
use std::fmt;

use nalgebra::DMatrix;

use super::{check_finite, SYMMETRY_TOLERANCE};
use crate::error::{Error, Result};

/// `y = W x` for an implicit Delassus operator (`x`, `y` of the operator's size), valid for
/// the lifetime `'a` (module documentation).
pub type DelassusProduct<'a> = Box<dyn Fn(&[f64], &mut [f64]) + 'a>;

/// The Delassus (flexibility) operator `W`, symmetric positive definite, `2m × 2m`.
pub enum Delassus<'a> {
    /// Explicit entries.
    Dense(DMatrix<f64>),
    /// Implicit: only products `y = W x` are available (plus the diagonal, for scaling: the
    /// augmentation parameters, the Jacobi preconditioner of the Krylov solves and the
    /// residual scales; an estimate of it is enough, every solver stays correct).
    /// Enough for Uzawa and the semi-smooth Newton method (Krylov linear solves).
    Operator {
        /// Number of contact unknowns.
        size: usize,
        /// The product `y = W x`.
        apply: DelassusProduct<'a>,
        /// `W`'s diagonal (or an estimate of it).
        diagonal: Vec<f64>,
    },
}

impl fmt::Debug for Delassus<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Delassus::Dense(w) => write!(f, "Delassus::Dense({}×{})", w.nrows(), w.ncols()),
            Delassus::Operator { size, .. } => write!(f, "Delassus::Operator({size}×{size})"),
        }
    }
}

impl Delassus<'_> {
    /// Number of rows (= columns) of `W`.
    pub fn size(&self) -> usize {
        match self {
            Delassus::Dense(w) => w.nrows(),
            Delassus::Operator { size, .. } => *size,
        }
    }

    /// `y = W x`. Sizes are checked by the callers (they are fixed at construction).
    pub fn apply(&self, x: &[f64], y: &mut [f64]) {
        match self {
            Delassus::Dense(w) => {
                // W is symmetric: row i is column i, which is contiguous in column-major storage.
                let n = w.nrows();
                let data = w.as_slice();
                for (i, yi) in y.iter_mut().enumerate() {
                    let column = &data[i * n..(i + 1) * n];
                    *yi = column.iter().zip(x).map(|(a, b)| a * b).sum();
                }
            }
            Delassus::Operator { apply, .. } => apply(x, y),
        }
    }

    /// The diagonal of `W`.
    pub fn diagonal(&self) -> Vec<f64> {
        match self {
            Delassus::Dense(w) => w.diagonal().iter().copied().collect(),
            Delassus::Operator { diagonal, .. } => diagonal.clone(),
        }
    }

    /// The matrix, if the entries are explicit.
    pub fn as_dense(&self) -> Option<&DMatrix<f64>> {
        match self {
            Delassus::Dense(w) => Some(w),
            Delassus::Operator { .. } => None,
        }
    }
}

pub(super) fn validate_delassus(delassus: Delassus<'_>, n: usize) -> Result<Delassus<'_>> {
    match delassus {
        Delassus::Dense(w) => {
            if w.nrows() != n || w.ncols() != n {
                return Err(Error::Usage(format!(
                    "condensed contact problem: the Delassus matrix is {}×{}, expected {n}×{n} \
                     (2 per contact point)",
                    w.nrows(),
                    w.ncols()
                )));
            }
            let mut largest = 0.0f64;
            for j in 0..n {
                for i in 0..n {
                    let v = w[(i, j)];
                    if !v.is_finite() {
                        return Err(Error::Usage(format!(
                            "condensed contact problem: Delassus entry ({i}, {j}) (contact points \
                             {} and {}) is {v}; every entry must be finite",
                            i / 2,
                            j / 2
                        )));
                    }
                    largest = largest.max(v.abs());
                }
            }
            for j in 0..n {
                for i in (j + 1)..n {
                    if (w[(i, j)] - w[(j, i)]).abs() > SYMMETRY_TOLERANCE * largest {
                        return Err(Error::Usage(format!(
                            "condensed contact problem: the Delassus matrix is not symmetric: \
                             entry ({i}, {j}) = {} but ({j}, {i}) = {} (contact points {} and {})",
                            w[(i, j)],
                            w[(j, i)],
                            i / 2,
                            j / 2
                        )));
                    }
                }
            }
            for i in 0..n {
                if w[(i, i)] <= 0.0 {
                    return Err(Error::Usage(format!(
                        "condensed contact problem: Delassus diagonal entry {i} (contact point \
                         {}, {} component) is {}; a flexibility must have a positive diagonal",
                        i / 2,
                        if i % 2 == 0 { "normal" } else { "tangential" },
                        w[(i, i)]
                    )));
                }
            }
            let symmetric = (&w + w.transpose()) * 0.5;
            if nalgebra::Cholesky::new(symmetric.clone()).is_none() {
                return Err(Error::Usage(
                    "condensed contact problem: the Delassus matrix is not positive definite \
                     (Cholesky factorization failed); a body held only by contact has no \
                     flexibility: constrain its rigid motions or use the dual formulation"
                        .into(),
                ));
            }
            Ok(Delassus::Dense(symmetric))
        }
        Delassus::Operator { size, apply, diagonal } => {
            if size != n || diagonal.len() != n {
                return Err(Error::Usage(format!(
                    "condensed contact problem: the Delassus operator has size {size} and a \
                     diagonal of {} entries, expected {n} (2 per contact point)",
                    diagonal.len()
                )));
            }
            for (i, &d) in diagonal.iter().enumerate() {
                if !(d.is_finite() && d > 0.0) {
                    return Err(Error::Usage(format!(
                        "condensed contact problem: Delassus diagonal entry {i} (contact point \
                         {}) is {d}; it must be finite and positive",
                        i / 2
                    )));
                }
            }
            // Two deterministic probes: xᵀWy = yᵀWx and xᵀWx > 0.
            let x: Vec<f64> = (0..n).map(|k| 1.0 + 0.37 * ((k * 7 % 11) as f64)).collect();
            let y: Vec<f64> = (0..n).map(|k| ((k * 5 % 13) as f64) - 6.0).collect();
            let mut wx = vec![0.0; n];
            let mut wy = vec![0.0; n];
            apply(&x, &mut wx);
            apply(&y, &mut wy);
            check_finite(&wx, "Delassus operator product")?;
            check_finite(&wy, "Delassus operator product")?;
            let xwy: f64 = x.iter().zip(&wy).map(|(a, b)| a * b).sum();
            let ywx: f64 = y.iter().zip(&wx).map(|(a, b)| a * b).sum();
            let xwx: f64 = x.iter().zip(&wx).map(|(a, b)| a * b).sum();
            let norm = |v: &[f64]| v.iter().map(|a| a * a).sum::<f64>().sqrt();
            let scale = norm(&x) * norm(&wy).max(norm(&wx)).max(f64::MIN_POSITIVE);
            if (xwy - ywx).abs() > 1e-8 * scale {
                return Err(Error::Usage(format!(
                    "condensed contact problem: the Delassus operator is not symmetric \
                     (probe products xᵀWy = {xwy:e}, yᵀWx = {ywx:e})"
                )));
            }
            if xwx <= 0.0 {
                return Err(Error::Usage(format!(
                    "condensed contact problem: the Delassus operator is not positive definite \
                     (probe product xᵀWx = {xwx:e})"
                )));
            }
            Ok(Delassus::Operator { size, apply, diagonal })
        }
    }
}
