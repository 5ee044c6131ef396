//! # The optimal size map
//!
//! A priori, the error of element `E` behaves as `e_E = O(h_E^{p_E})`: `p_E = 1` in the volume
//! for P1 elasticity (primal or dual), `2/3` on contact edges for primal Coulomb friction, `1/2`
//! for dual Tresca (F. Lebon, "Modèles d'interface et formulations pour le contact frottant :
//! résultats et calcul d'erreur", slides "Adaptation de maillage"; the rates are Capatina-Cocou's
//! and Capatina-Lebon's). Shrinking the element by `r_E = h*_E / h_E` turns its error into
//! `e_E r_E^{p_E}` and, in 2D, replaces it by about `r_E^{−2}` elements. The optimal mesh
//! minimises the element count at the target error `e_0`:
//!
//! ```text
//!   minimise  N(r) = Σ_E r_E^{−2}   subject to   Σ_E e_E² r_E^{2 p_E} = e_0².
//! ```
//!
//! Stationarity of `N + λ (Σ e_E² r_E^{2p_E} − e_0²)` gives, element by element,
//!
//! ```text
//!   r_E^{2 p_E + 2} = 1 / (λ p_E e_E²),
//! ```
//!
//! and with one rate `p` everywhere the closed form (P. Ladevèze, J.-P. Pelle, *Mastering
//! Calculations in Linear and Nonlinear Mechanics*, Springer 2005, ch. 5; Coffignal 1987)
//!
//! ```text
//!   r_E = e_E^{−1/(p+1)} [ e_0² / Σ_F e_F^{2/(p+1)} ]^{1/(2p)}.
//! ```
//!
//! With a rate per element the constraint `Φ(λ) = Σ_E e_E² r_E(λ)^{2p_E} = e_0²` is solved for
//! the multiplier: every `r_E(λ)` decreases with `λ`, so `Φ` is monotone and bisection on
//! `log λ` finds it robustly whatever the spread of the errors. The ratios are clamped to
//! `[min_ratio, max_ratio]` (a mesher cannot divide an element by 1000 in one step, and an
//! element with no error would otherwise grow without bound); clamped elements keep their
//! clamped ratio and the others absorb the target, which keeps `Φ` monotone. Ratios above 1
//! coarsen: the map both refines and coarsens. When even every element at `min_ratio` cannot
//! reach the target, the map aims at 5 % above that floor instead of at the target: with the
//! target itself `λ → ∞` and every element, however small its error, would be divided by the
//! largest factor (on a rigid flat punch from 128 elements at 43 %: 13214 elements, of which
//! the next step coarsened most).
use crate::error::{Error, Result};

/// Bounds on the reduction ratios `r_E = h*_E / h_E`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SizeMapLimits {
    /// Smallest ratio (strongest refinement in one step), e.g. 1/10.
    pub min_ratio: f64,
    /// Largest ratio (strongest coarsening in one step), e.g. 4.
    pub max_ratio: f64,
}

impl Default for SizeMapLimits {
    fn default() -> Self {
        SizeMapLimits { min_ratio: 0.1, max_ratio: 4.0 }
    }
}

/// The outcome of [`optimal_size_map`].
#[derive(Debug, Clone)]
pub struct SizeMap {
    /// `r_E` per element.
    pub ratios: Vec<f64>,
    /// The Lagrange multiplier λ.
    pub multiplier: f64,
    /// `(Σ e_E² r_E^{2p_E})^½`: the error the a priori model predicts on the new mesh (the
    /// target, unless the clamps made it unreachable).
    pub predicted_error: f64,
    /// `Σ r_E^{−2}`: the element count the model predicts.
    pub predicted_elements: f64,
    /// True when the clamps keep the predicted error above the target (every element at
    /// `min_ratio` would be needed and is not enough): more steps are needed. The map then
    /// aims at `1 + UNREACHABLE_SLACK` times the best error the clamps allow.
    pub target_unreachable: bool,
}

/// When the clamps cannot reach the target, the map aims this fraction above the best error
/// they allow (every element at `min_ratio`).
pub const UNREACHABLE_SLACK: f64 = 0.05;

fn ratio(lambda: f64, error: f64, rate: f64, limits: SizeMapLimits) -> f64 {
    if error <= 0.0 {
        return limits.max_ratio;
    }
    // r = (λ p e²)^{−1/(2p+2)}, in logarithms to stay finite for any spread of e and λ.
    let log_r = -(lambda.ln() + rate.ln() + 2.0 * error.ln()) / (2.0 * rate + 2.0);
    log_r.exp().clamp(limits.min_ratio, limits.max_ratio)
}

fn predicted_error_squared(lambda: f64, errors: &[f64], rates: &[f64], limits: SizeMapLimits) -> f64 {
    errors.iter().zip(rates).map(|(&e, &p)| e * e * ratio(lambda, e, p, limits).powf(2.0 * p)).sum()
}

/// The optimal reduction ratios for element errors `errors` (`e_E ≥ 0`), a priori rates
/// `rates` (`p_E > 0`, one per element) and the target global error `target` (`e_0 > 0`, same
/// units as the errors).
pub fn optimal_size_map(errors: &[f64], rates: &[f64], target: f64, limits: SizeMapLimits) -> Result<SizeMap> {
    if errors.len() != rates.len() {
        return Err(Error::Usage(format!(
            "size map: {} element errors but {} rates; give one rate per element",
            errors.len(),
            rates.len()
        )));
    }
    if !(target.is_finite() && target > 0.0) {
        return Err(Error::Usage(format!("size map: the target error must be finite and positive, got {target}")));
    }
    if !(limits.min_ratio > 0.0 && limits.min_ratio <= 1.0 && limits.max_ratio >= 1.0 && limits.max_ratio.is_finite()) {
        return Err(Error::Usage(format!(
            "size map: ratio limits must satisfy 0 < min_ratio <= 1 <= max_ratio < inf, got [{}, {}]",
            limits.min_ratio, limits.max_ratio
        )));
    }
    if let Some(e) = errors.iter().position(|e| !(e.is_finite() && *e >= 0.0)) {
        return Err(Error::Usage(format!(
            "size map: element {e} has error {}; element errors must be finite and non-negative",
            errors[e]
        )));
    }
    if let Some(e) = rates.iter().position(|p| !(p.is_finite() && *p > 0.0)) {
        return Err(Error::Usage(format!(
            "size map: element {e} has rate {}; a priori rates must be finite and positive",
            rates[e]
        )));
    }
    // The best the clamps allow in one step: every element with an error at `min_ratio`. When
    // that is above the target, aim a little above it instead (UNREACHABLE_SLACK): the
    // elements whose refinement pays (the large errors) go to `min_ratio` and the others keep
    // their optimal ratio, rather than every element being divided by the largest factor.
    let floor_sq: f64 = errors.iter().zip(rates).map(|(&e, &p)| e * e * limits.min_ratio.powf(2.0 * p)).sum();
    let target_unreachable = floor_sq > target * target * (1.0 + 1e-9);
    let target_sq = if target_unreachable { floor_sq * (1.0 + UNREACHABLE_SLACK).powi(2) } else { target * target };
    let phi = |log_lambda: f64| predicted_error_squared(log_lambda.exp(), errors, rates, limits);
    // Φ decreases with λ. Bracket the root in log λ, then bisect.
    let (mut lo, mut hi) = (-50.0f64, 50.0f64);
    while phi(lo) < target_sq && lo > -2000.0 {
        lo -= 50.0;
    }
    while phi(hi) > target_sq && hi < 2000.0 {
        hi += 50.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if phi(mid) > target_sq {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-13 * (1.0 + hi.abs()) {
            break;
        }
    }
    let multiplier = hi.exp();
    let ratios: Vec<f64> = errors.iter().zip(rates).map(|(&e, &p)| ratio(multiplier, e, p, limits)).collect();
    let predicted_sq: f64 = errors.iter().zip(rates).zip(&ratios).map(|((&e, &p), &r)| e * e * r.powf(2.0 * p)).sum();
    let predicted_elements = ratios.iter().map(|r| r.powi(-2)).sum();
    Ok(SizeMap { ratios, multiplier, predicted_error: predicted_sq.sqrt(), predicted_elements, target_unreachable })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wide() -> SizeMapLimits {
        SizeMapLimits { min_ratio: 1e-6, max_ratio: 1e6 }
    }

    #[test]
    fn one_rate_matches_the_closed_form() {
        let errors = [0.3, 0.01, 0.2, 0.05, 1e-3, 0.7];
        for p in [1.0, 0.5, 2.0 / 3.0] {
            let target = 0.1;
            let map = optimal_size_map(&errors, &vec![p; errors.len()], target, wide()).unwrap();
            let sum: f64 = errors.iter().map(|e: &f64| e.powf(2.0 / (p + 1.0))).sum();
            for (e, r) in errors.iter().zip(&map.ratios) {
                let closed = e.powf(-1.0 / (p + 1.0)) * (target * target / sum).powf(1.0 / (2.0 * p));
                assert!((r - closed).abs() <= 1e-9 * closed, "p = {p}: {r} vs {closed}");
            }
            assert!((map.predicted_error - target).abs() <= 1e-9 * target);
            assert!(!map.target_unreachable);
        }
    }

    #[test]
    fn the_map_is_optimal_among_maps_reaching_the_target() {
        // Perturb the optimum along the constraint surface: the element count never drops.
        let errors = [0.4, 0.05, 0.1, 0.02];
        let rates = [1.0, 0.5, 1.0, 2.0 / 3.0];
        let map = optimal_size_map(&errors, &rates, 0.05, wide()).unwrap();
        let count = |r: &[f64]| r.iter().map(|x| x.powi(-2)).sum::<f64>();
        for k in 0..errors.len() {
            let mut r = map.ratios.clone();
            r[k] *= 1.05;
            // Restore the constraint by scaling element (k + 1) % n.
            let j = (k + 1) % errors.len();
            let rest: f64 =
                (0..errors.len()).filter(|&i| i != j).map(|i| errors[i] * errors[i] * r[i].powf(2.0 * rates[i])).sum();
            let need = 0.05f64.powi(2) - rest;
            if need <= 0.0 {
                continue;
            }
            r[j] = (need / (errors[j] * errors[j])).powf(1.0 / (2.0 * rates[j]));
            assert!(count(&r) >= map.predicted_elements * (1.0 - 1e-12), "perturbing {k} lowered the count");
        }
    }

    #[test]
    fn small_errors_coarsen_large_ones_refine_and_clamps_hold() {
        let errors = [1.0, 1e-4, 1e-4, 1e-4];
        let limits = SizeMapLimits { min_ratio: 0.2, max_ratio: 3.0 };
        let map = optimal_size_map(&errors, &[1.0; 4], 0.5, limits).unwrap();
        assert!(map.ratios[0] < 1.0);
        assert!(map.ratios[1..].iter().all(|&r| r == 3.0), "{:?}", map.ratios);
        assert!((map.predicted_error - 0.5).abs() < 1e-9);
        // A target the clamps cannot reach in one step is said to be unreachable; the map then
        // refines the large error to the clamp, not the negligible ones, and predicts 5 % above
        // the best error the clamps allow.
        let map = optimal_size_map(&errors, &[1.0; 4], 1e-3, limits).unwrap();
        assert!(map.target_unreachable);
        assert!(map.ratios[0] < 0.2 * (1.0 + UNREACHABLE_SLACK) + 1e-12, "{:?}", map.ratios);
        assert!(map.ratios[1..].iter().all(|&r| r > 1.0), "{:?}", map.ratios);
        let best = (errors.iter().map(|e| e * e * 0.04).sum::<f64>()).sqrt();
        assert!((map.predicted_error / best - 1.0 - UNREACHABLE_SLACK).abs() < 1e-9, "{}", map.predicted_error);
    }

    #[test]
    fn bad_input_is_refused() {
        let limits = SizeMapLimits::default();
        assert!(optimal_size_map(&[1.0], &[1.0, 1.0], 0.1, limits).is_err());
        assert!(optimal_size_map(&[1.0], &[1.0], 0.0, limits).is_err());
        assert!(optimal_size_map(&[f64::NAN], &[1.0], 0.1, limits).is_err());
        assert!(optimal_size_map(&[1.0], &[0.0], 0.1, limits).is_err());
        let bad = SizeMapLimits { min_ratio: 2.0, max_ratio: 4.0 };
        assert!(optimal_size_map(&[1.0], &[1.0], 0.1, bad).is_err());
    }
}
