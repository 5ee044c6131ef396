//! # The error in the constitutive relation (CRE)
//!
//! Given a displacement field `u_h` that is kinematically admissible (the primal solution: it
//! meets the prescribed displacements and, with contact, non-penetration) and a stress field
//! `σ_h` that is statically admissible (the dual solution: in equilibrium with the body force in
//! every element and across every edge, and with the given tractions on the boundary), the
//! error in the constitutive relation measures how far the pair is from Hooke's law:
//!
//! ```text
//!   e_vol² = ‖σ_h − C ε(u_h)‖²_{C⁻¹} = Σ_E e_vol,E²,
//!   e_vol,E² = ∫_E (σ_h − C ε(u_h)) : C⁻¹ (σ_h − C ε(u_h)).
//! ```
//!
//! **Elasticity (no contact): the Prager–Synge hypercircle identity.** With `u`, `σ = C ε(u)`
//! the exact solution,
//!
//! ```text
//!   ‖σ_h − C ε(u_h)‖² = ‖σ − σ_h‖² + ‖σ − C ε(u_h)‖²        (norms in C⁻¹),
//! ```
//!
//! so `e_vol` is a guaranteed upper bound of the error of each field, and equals the talk's
//! `e_r = (‖Δu‖²_a + ‖Δσ‖²_b)^½` exactly (W. Prager, J. L. Synge, Quart. Appl. Math. 5 (1947)
//! 241–269; P. Ladevèze, D. Leguillon, SIAM J. Numer. Anal. 20 (1983) 485–509).
//!
//! **Contact terms.** With a contact boundary Γc the pair is admissible only up to the contact
//! laws, and the bound gains a boundary integral (F. Lebon, "Modèles d'interface et
//! formulations pour le contact frottant : résultats et calcul d'erreur", slides "Qualité des
//! solutions" and "Adaptation de maillage"; see also Coorevits, Hild, Pelle, Comput. Methods
//! Appl. Mech. Engrg 188 (2000)):
//!
//! ```text
//!   e² ≤ e_vol² + 2 ∫_Γc c(u_h, σ_h) ds,
//!   c = σhN (uhN − g0) + σhT·uhT + g |uhT|        (Tresca, threshold g: a guaranteed bound)
//!   c = σhN (uhN − g0) + σhT·uhT + μ |σhN| |uhT|  (Coulomb: an estimator, not a bound)
//!   c = σhN (uhN − g0)                            (frictionless)
//! ```
//!
//! with `n` the body's contact direction, `σhN = n·σ_h n`, `σhT = σ_h n − σhN n`. For an
//! admissible pair (`uhN ≤ g0`, `σhN ≤ 0`, `|σhT| ≤ g`) every term is `≥ 0` pointwise:
//! `σhN (uhN − g0) ≥ 0` as a product of two non-positive numbers and `σhT·uhT + g|uhT| ≥
//! (g − |σhT|)|uhT| ≥ 0`. [`contact_terms`] asserts this at every quadrature point and reports
//! the most negative value it met (a negative value means one of the two fields is not
//! admissible, and the bound is then not guaranteed).
//!
//! **Per element** (what mesh adaptation consumes): `e_E² = e_vol,E² + e_c,E` with
//! `e_c,E = 2 ∫_{∂E ∩ Γc} c ds`, and `e² = Σ_E e_E²` (the talk's `e = (Σ_E (e_E² + e_Ec))^½`).
//!
//! **Relative error.** The talk reports errors as a percentage of the solution's energy norm.
//! The exact solution being unknown, we divide by the norm of the centre of the hypercircle,
//!
//! ```text
//!   ε = e / ‖½ (σ_h + C ε(u_h))‖_{C⁻¹},
//! ```
//!
//! which is the best estimate of `‖σ‖_{C⁻¹}` the pair gives (by Prager–Synge, `½(σ_h + Cε(u_h))`
//! is at distance `e/2` from `σ`); `ε` equals the talk's `(‖Δu‖² + ‖Δσ‖²)^½ / ‖σ‖` up to that
//! choice of denominator. (Ladevèze's `‖σ_h − Cε(u_h)‖ / ‖σ_h + Cε(u_h)‖` is exactly `ε / 2`.)
//!
//! The stress field enters through the [`StressField`] trait: the piecewise-polynomial pieces
//! of each cell (the three sub-triangles of an HCT cell) and the stress on each, so this module
//! does not depend on how `σ_h` was built.
pub mod constitutive_relation;
pub mod contact_terms;

pub use constitutive_relation::{pair_degree, volume_terms, ExactStress, StressField, VolumeTerms};
pub use contact_terms::{contact_integrand, ContactLawTerm, ContactSample, ContactTerms};

/// What the estimate is, for the report: a guaranteed bound or an estimator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EstimateKind {
    /// Elasticity, frictionless or Tresca contact: `e` bounds the true error from above
    /// (provided every contact term is non-negative).
    GuaranteedBound,
    /// Coulomb friction: the problem is not a minimisation and `e` is an estimator only.
    Estimator,
}

/// The estimate of one primal–dual pair, globally and per element.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Estimate {
    /// Which estimate: the pure elastic one, or with the contact terms.
    pub kind: EstimateKind,
    /// `e = (e_vol² + e_contact²)^½`, energy units^½ (J^½ per unit thickness).
    pub error: f64,
    /// `e_vol = ‖σ_h − Cε(u_h)‖_{C⁻¹}`.
    pub volume: f64,
    /// `e_contact = (2 ∫_Γc c ds)^½` (0 without contact).
    pub contact: f64,
    /// `‖½(σ_h + Cε(u_h))‖_{C⁻¹}`, the norm `relative_percent` divides by.
    pub reference_norm: f64,
    /// `100 e / reference_norm`.
    pub relative_percent: f64,
    /// Most negative contact integrand met (0 when all are ≥ 0); see the module doc.
    pub min_contact_integrand: f64,
    /// `e_E² = e_vol,E² + e_c,E` per cell (the cell data `error` is `e_E`).
    #[serde(skip)]
    pub element_squared: Vec<f64>,
    /// `e_c,E` per cell.
    #[serde(skip)]
    pub element_contact: Vec<f64>,
}

impl Estimate {
    /// Combine the volume part and (optionally) the contact part.
    pub fn new(kind: EstimateKind, volume: &VolumeTerms, contact: Option<&ContactTerms>) -> Self {
        let mut element_squared = volume.element_squared.clone();
        let mut element_contact = vec![0.0; element_squared.len()];
        let (mut contact_total, mut min_integrand) = (0.0, 0.0);
        if let Some(c) = contact {
            for (e, &v) in c.element.iter().enumerate() {
                element_squared[e] += v;
                element_contact[e] = v;
            }
            contact_total = c.element.iter().sum::<f64>();
            min_integrand = c.min_integrand;
        }
        let volume_sq: f64 = volume.element_squared.iter().sum();
        let error = (volume_sq + contact_total.max(0.0)).sqrt();
        let reference_norm = volume.mean_squared.max(0.0).sqrt();
        let relative_percent = if reference_norm > 0.0 { 100.0 * error / reference_norm } else { 0.0 };
        Estimate {
            kind,
            error,
            volume: volume_sq.sqrt(),
            contact: contact_total.max(0.0).sqrt(),
            reference_norm,
            relative_percent,
            min_contact_integrand: min_integrand,
            element_squared,
            element_contact,
        }
    }

    /// `e_E` per cell.
    pub fn element_error(&self) -> Vec<f64> {
        self.element_squared.iter().map(|v| v.max(0.0).sqrt()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn volume_and_contact_parts_combine_per_element_and_globally() {
        let volume = VolumeTerms {
            element_squared: vec![9.0, 16.0],
            mean_squared: 2500.0,
            primal_squared: 2500.0,
            dual_squared: 2500.0,
        };
        let mut contact = ContactTerms::new(2);
        contact.add_edge(
            1,
            [ContactSample {
                weight: 1.0,
                traction: [0.0, 2.0],
                displacement: [0.0, 0.5],
                normal: [0.0, -1.0],
                gap: 0.0,
            }],
            ContactLawTerm::Frictionless,
        );
        // c = σN (uN − g0) = (−2)(−0.5) = 1, e_c = 2.
        let e = Estimate::new(EstimateKind::GuaranteedBound, &volume, Some(&contact));
        assert_eq!(e.element_squared, vec![9.0, 18.0]);
        assert_eq!(e.element_contact, vec![0.0, 2.0]);
        assert!((e.error - 27f64.sqrt()).abs() < 1e-14);
        assert!((e.volume - 5.0).abs() < 1e-14 && (e.contact - 2f64.sqrt()).abs() < 1e-14);
        assert!((e.relative_percent - 100.0 * 27f64.sqrt() / 50.0).abs() < 1e-12);
        assert_eq!(e.element_error()[0], 3.0);
        let without = Estimate::new(EstimateKind::GuaranteedBound, &volume, None);
        assert_eq!(without.error, 5.0);
        assert_eq!(without.contact, 0.0);
    }
}
