//! The residuals detect each violation of the contact conditions.

use crate::one_point;
use signorini::contact::FrictionLaw;
use signorini::Error;

// ---------------------------------------------------------------------------------------------
// Residuals detect each violation
// ---------------------------------------------------------------------------------------------

fn assert_only(residuals: &signorini::contact::ContactResiduals, component: &str, value: f64) {
    let all = [
        ("penetration", residuals.max_penetration),
        ("wrong-sign pressure", residuals.max_wrong_sign_pressure),
        ("cone violation", residuals.max_cone_violation),
        ("normal complementarity", residuals.normal_complementarity),
        ("tangential complementarity", residuals.tangential_complementarity),
    ];
    for (name, v) in all {
        if name == component {
            assert!((v - value).abs() <= 1e-12 * value, "{name}: {v} expected {value}");
        } else {
            assert!(v <= 1e-14, "{name} = {v} should be zero ({residuals})");
        }
    }
    assert_eq!(residuals.worst_component(), component);
    assert!(!residuals.is_acceptable(0.5 * value));
    assert!(residuals.is_acceptable(2.0 * value));
    assert!(residuals.to_string().contains(component));
}

#[test]
fn residual_detects_penetration() {
    // No force although uN_free = 1 > g0 = 0.2.
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    let residuals = problem.residuals(&[0.0, 0.0]).unwrap();
    assert_eq!(residuals.scale.displacement, 1.0); // max |u| = |u_free|∞ = 1
    assert_only(&residuals, "penetration", 0.8);
}

#[test]
fn residual_detects_wrong_sign_pressure() {
    // rN = +0.05 (tension) on an open point: uN = 0.1 + 0.1 = 0.2 = g0, so nothing else fails.
    let problem = one_point(FrictionLaw::None, [0.1, 0.0], 0.2);
    let residuals = problem.residuals(&[0.05, 0.0]).unwrap();
    let scale = residuals.scale;
    assert!((scale.displacement - 0.2).abs() < 1e-15);
    assert!((scale.force - 0.1).abs() < 1e-15); // U / max diag = 0.2 / 2 > |r| = 0.05
    assert_only(&residuals, "wrong-sign pressure", 0.05 / scale.force);
}

#[test]
fn residual_detects_cone_violation() {
    // Tresca s = 0.05 with |rT| = 0.08 and uT = 0 (so the natural map sees only the excess).
    let problem = one_point(FrictionLaw::Tresca { threshold: vec![0.05] }, [1.0, 0.3], 0.2);
    // Choose r with uN = g0 and uT = 0: that is the stick solution, with rT = -0.2/1.75 ≈ -0.114.
    let r = [-0.65 / 1.75, -0.2 / 1.75];
    let residuals = problem.residuals(&r).unwrap();
    let excess = 0.2 / 1.75 - 0.05;
    assert!(residuals.max_cone_violation > 0.0);
    // The natural map also reports the excess (|rT - clamp(rT)|), which is the same number.
    assert!((residuals.max_cone_violation - excess / residuals.scale.force).abs() < 1e-12);
    assert!((residuals.tangential_complementarity - residuals.max_cone_violation).abs() < 1e-12);
    assert!(residuals.max_penetration < 1e-14 && residuals.normal_complementarity < 1e-14);
    assert!(residuals.max_wrong_sign_pressure == 0.0);
    // Coulomb: |rT| > mu |rN|.
    let coulomb = one_point(FrictionLaw::Coulomb { mu: vec![0.1] }, [1.0, 0.3], 0.2);
    let residuals = coulomb.residuals(&r).unwrap();
    let excess = 0.2 / 1.75 - 0.1 * 0.65 / 1.75;
    assert!((residuals.max_cone_violation - excess / residuals.scale.force).abs() < 1e-12);
    assert_eq!(residuals.worst_component(), "cone violation");
}

#[test]
fn residual_detects_normal_complementarity() {
    // rN = -0.05 on a point that is not touching: uN = -0.1 + 0.1 = 0 < g0 = 0.2.
    let problem = one_point(FrictionLaw::None, [0.1, 0.0], 0.2);
    let residuals = problem.residuals(&[-0.05, 0.0]).unwrap();
    let scale = residuals.scale;
    let expected = (0.05 / scale.force).min(0.2 / scale.displacement);
    assert_only(&residuals, "normal complementarity", expected);
}

#[test]
fn residual_detects_sticking_point_that_moves() {
    // Tresca s = 1 (large): rT = 0 strictly inside, but uT = 0.5 (-0.4) + 0.3 = 0.1 ≠ 0.
    let problem = one_point(FrictionLaw::Tresca { threshold: vec![1.0] }, [1.0, 0.3], 0.2);
    let residuals = problem.residuals(&[-0.4, 0.0]).unwrap();
    let scale = residuals.scale;
    // |0 - clamp(0 - c 0.1, -1, 1)| / F = 0.1 / U  (c 0.1 < 1 here).
    assert!((scale.force / scale.displacement) * 0.1 < 1.0);
    assert_only(&residuals, "tangential complementarity", 0.1 / scale.displacement);
}

#[test]
fn residual_detects_slip_in_the_wrong_direction() {
    // Tresca s = 0.05, rT = +0.05 on the threshold, but then uT = 0.5 rN + 0.05 + 0.3 > 0:
    // the point slips along its friction force.
    let problem = one_point(FrictionLaw::Tresca { threshold: vec![0.05] }, [1.0, 0.3], 0.2);
    let rn = (-0.8 - 0.5 * 0.05) / 2.0; // uN = g0
    let residuals = problem.residuals(&[rn, 0.05]).unwrap();
    let ut = 0.5 * rn + 0.05 + 0.3;
    assert!(ut > 0.0);
    let scale = residuals.scale;
    let c = scale.force / scale.displacement;
    let expected = (0.05 - (0.05 - c * ut).clamp(-0.05, 0.05)).abs() / scale.force;
    assert_only(&residuals, "tangential complementarity", expected);
    // The correct answer has none of it.
    let good = problem.residuals(&[-0.3875, -0.05]).unwrap();
    assert!(good.is_acceptable(1e-14), "{good}");
}

#[test]
fn residual_reports_wrong_lengths_and_non_finite_forces() {
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    assert!(matches!(problem.residuals(&[0.0]), Err(Error::Usage(m)) if m.contains("expected 2")));
    assert!(matches!(problem.residuals(&[f64::NAN, 0.0]), Err(Error::Usage(m)) if m.contains("contact point 0")));
}
