//! The contact part of the error in the constitutive relation (see [`crate::estimate`]):
//! `e_c,E = 2 ∫_{∂E ∩ Γc} c(u_h, σ_h) ds`, accumulated from quadrature samples along the
//! contact edges of each cell.
//!
//! At a sample, with `n` the body's unit contact direction (the primal's: `n = −ν`, ν the
//! obstacle normal towards the body), `t = σ_h n_body` the traction of the stress field,
//! `u` the displacement and `g0` the initial gap:
//!
//! ```text
//!   σN = t·n,  σT = t − σN n,  uN = u·n,  uT = u − uN n,
//!   c = σN (uN − g0) + σT·uT + { 0 | g |uT| | μ |σN| |uT| }   (frictionless | Tresca | Coulomb).
//! ```
//!
//! For an admissible pair every `c ≥ 0`; the smallest value met and the scale of the terms are
//! kept so that the caller can tell round-off from a real violation.

/// The friction part of the contact integrand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactLawTerm {
    /// No friction term.
    Frictionless,
    /// Slip threshold `g` (traction units, N/m²).
    Tresca {
        /// The threshold `g`.
        threshold: f64,
    },
    /// Friction coefficient `μ`.
    Coulomb {
        /// The coefficient `μ`.
        mu: f64,
    },
}

/// One quadrature sample on a contact edge.
#[derive(Debug, Clone, Copy)]
pub struct ContactSample {
    /// Quadrature weight times the length element (`w_q ds`).
    pub weight: f64,
    /// Traction `σ_h n_body` of the stress field.
    pub traction: [f64; 2],
    /// Displacement `u_h`.
    pub displacement: [f64; 2],
    /// Unit contact direction `n` (the direction the gap is measured along).
    pub normal: [f64; 2],
    /// Initial gap `g0 ≥ 0`.
    pub gap: f64,
}

/// The integrand `c` at one sample, and the sum of the absolute values of its terms (its scale).
pub fn contact_integrand(s: &ContactSample, law: ContactLawTerm) -> (f64, f64) {
    let n = s.normal;
    let sn = s.traction[0] * n[0] + s.traction[1] * n[1];
    let st = [s.traction[0] - sn * n[0], s.traction[1] - sn * n[1]];
    let un = s.displacement[0] * n[0] + s.displacement[1] * n[1];
    let ut = [s.displacement[0] - un * n[0], s.displacement[1] - un * n[1]];
    let ut_norm = ut[0].hypot(ut[1]);
    let normal = sn * (un - s.gap);
    let tangential = st[0] * ut[0] + st[1] * ut[1];
    let friction = match law {
        ContactLawTerm::Frictionless => 0.0,
        ContactLawTerm::Tresca { threshold } => threshold * ut_norm,
        ContactLawTerm::Coulomb { mu } => mu * sn.abs() * ut_norm,
    };
    (normal + tangential + friction, normal.abs() + tangential.abs() + friction.abs())
}

/// Contact terms accumulated per cell.
#[derive(Debug, Clone)]
pub struct ContactTerms {
    /// `e_c,E = 2 ∫_{∂E ∩ Γc} c ds` per cell.
    pub element: Vec<f64>,
    /// Smallest integrand `c` met (0 when none is negative).
    pub min_integrand: f64,
    /// Largest scale `|σN (uN − g0)| + |σT·uT| + |friction|` met, to judge `min_integrand`.
    pub max_scale: f64,
}

impl ContactTerms {
    /// Zero terms on `num_cells` cells.
    pub fn new(num_cells: usize) -> Self {
        ContactTerms { element: vec![0.0; num_cells], min_integrand: 0.0, max_scale: 0.0 }
    }

    /// Add the samples of one contact edge of `cell`.
    pub fn add_edge(&mut self, cell: usize, samples: impl IntoIterator<Item = ContactSample>, law: ContactLawTerm) {
        for s in samples {
            let (c, scale) = contact_integrand(&s, law);
            self.element[cell] += 2.0 * s.weight * c;
            self.min_integrand = self.min_integrand.min(c);
            self.max_scale = self.max_scale.max(scale);
        }
    }

    /// `2 ∫_Γc c ds`.
    pub fn total(&self) -> f64 {
        self.element.iter().sum()
    }

    /// True when no integrand is below `−tolerance · max_scale` (the pair is admissible up to
    /// round-off and the bound is guaranteed for frictionless and Tresca contact).
    pub fn all_nonnegative(&self, tolerance: f64) -> bool {
        self.min_integrand >= -tolerance * self.max_scale
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(traction: [f64; 2], displacement: [f64; 2], gap: f64) -> ContactSample {
        ContactSample { weight: 1.0, traction, displacement, normal: [0.0, -1.0], gap }
    }

    #[test]
    fn admissible_pairs_give_nonnegative_terms() {
        // Normal n = (0, -1): a compressive traction pushes up, t = (tx, +p).
        let law = ContactLawTerm::Tresca { threshold: 2.0 };
        // Closed, sticking, exact: every term vanishes.
        assert_eq!(contact_integrand(&sample([1.0, 5.0], [0.0, 0.0], 0.0), law).0, 0.0);
        // Open gap with zero pressure: zero with Coulomb; Tresca's threshold acts everywhere.
        let open = sample([0.0, 0.0], [0.3, 0.1], 0.2);
        assert_eq!(contact_integrand(&open, ContactLawTerm::Coulomb { mu: 0.5 }).0, 0.0);
        assert!((contact_integrand(&open, law).0 - 0.6).abs() < 1e-15);
        // Pressure across an open gap: σN (uN − g0) = (−5)(−0.1 − 0.2) = 1.5 > 0.
        let (c, _) = contact_integrand(&sample([0.0, 5.0], [0.0, 0.1], 0.2), law);
        assert!((c - 1.5).abs() < 1e-15);
        // Slip with the traction on the threshold, opposing the slip: σT·uT + g|uT| = 0.
        let (c, _) = contact_integrand(&sample([-2.0, 5.0], [0.5, 0.0], 0.0), law);
        assert!(c.abs() < 1e-15);
        // Slip with the traction helping the slip: 2·0.5 + 2·0.5 = 2 > 0.
        let (c, _) = contact_integrand(&sample([2.0, 5.0], [0.5, 0.0], 0.0), law);
        assert!((c - 2.0).abs() < 1e-15);
    }

    #[test]
    fn coulomb_uses_the_normal_traction_and_inadmissible_pairs_are_seen() {
        let law = ContactLawTerm::Coulomb { mu: 0.5 };
        // |σN| = 4, threshold 2, traction −2 opposing slip 1: −2 + 2 = 0.
        let (c, _) = contact_integrand(&sample([-2.0, 4.0], [1.0, 0.0], 0.0), law);
        assert!(c.abs() < 1e-15);
        // Tangential traction above the cone (−3 > 2): negative, the pair is not admissible.
        let mut terms = ContactTerms::new(2);
        terms.add_edge(1, [sample([-3.0, 4.0], [1.0, 0.0], 0.0)], law);
        assert!((terms.element[1] + 2.0).abs() < 1e-15);
        assert!(!terms.all_nonnegative(1e-12));
        // Penetration (uN > g0) under pressure: negative too.
        let mut terms = ContactTerms::new(1);
        terms.add_edge(0, [sample([0.0, 4.0], [0.0, -0.1], 0.0)], ContactLawTerm::Frictionless);
        assert!(terms.min_integrand < 0.0 && !terms.all_nonnegative(1e-12));
    }
}
