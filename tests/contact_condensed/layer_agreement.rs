//! On the elastic layer all solvers agree, frictionless, Tresca and Coulomb.

use crate::{all_solvers, assert_all_solvers_agree, counts, indentation, indentation_with, layer_delassus, tight};
use signorini::contact::{solve, FrictionLaw, PointStatus};

// ---------------------------------------------------------------------------------------------
// Elastic model: all solvers agree
// ---------------------------------------------------------------------------------------------

#[test]
fn layer_flexibility_is_a_genuine_spd_flexibility() {
    let (w, _) = layer_delassus(20, 0.5, 0.3);
    assert!(w.clone().cholesky().is_some());
    // A downward point force (rN < 0) moves that point away from the obstacle the most.
    let column = w.column(20);
    assert!(column[20] > 0.0);
    for i in (0..40).step_by(2) {
        assert!(column[i] <= column[20] + 1e-15);
    }
    // Normal–tangential coupling (Dundurs-like, plus the free ends) is odd in x: opposite
    // signs at the two ends of the edge, and not small.
    assert!(w[(0, 1)] * w[(38, 39)] < 0.0);
    assert!(w[(0, 1)].abs() > 0.05 * w[(0, 0)] && w[(38, 39)].abs() > 0.05 * w[(38, 38)]);
}

#[test]
fn solvers_agree_frictionless() {
    let problem = indentation(40, FrictionLaw::None, 0.08, 0.01);
    let solution = assert_all_solvers_agree(&problem, "frictionless");
    let (open, stick, slip) = counts(&solution);
    assert!(open > 5 && slip > 5 && stick == 0, "{open} open, {stick} stick, {slip} slip");
    assert!(solution.force.iter().skip(1).step_by(2).all(|&t| t == 0.0));
}

#[test]
fn solvers_agree_tresca() {
    let m = 40;
    let problem = indentation(m, FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] }, 0.08, 0.01);
    let solution = assert_all_solvers_agree(&problem, "Tresca");
    let (open, stick, slip) = counts(&solution);
    assert!(open > 5 && stick > 5 && slip > 2, "{open} open, {stick} stick, {slip} slip");
}

#[test]
fn solvers_agree_coulomb() {
    let m = 40;
    let problem = indentation(m, FrictionLaw::Coulomb { mu: vec![0.3; m] }, 0.08, 0.03);
    let solution = assert_all_solvers_agree(&problem, "Coulomb");
    let (open, stick, slip) = counts(&solution);
    assert!(open > 5 && stick > 5 && slip > 5, "{open} open, {stick} stick, {slip} slip");
    // Slipping points: uT opposite to rT, |rT| = mu |rN|.
    for (i, status) in solution.status.iter().enumerate() {
        let (rn, rt, ut) = (solution.force[2 * i], solution.force[2 * i + 1], solution.displacement[2 * i + 1]);
        match status {
            PointStatus::Slip => {
                assert!((rt.abs() - 0.3 * rn.abs()).abs() < 1e-9 * rn.abs().max(1e-12));
                assert!(rt * ut < 0.0);
            }
            PointStatus::Stick => assert!(ut.abs() < 1e-12),
            PointStatus::Open => assert_eq!(rn, 0.0),
        }
    }
}

#[test]
fn coulomb_friction_from_0_to_10() {
    let m = 30;
    let (w, xs) = layer_delassus(m, 0.5, 0.3);
    let mut previous_stick = 0;
    for mu in [0.0, 0.05, 0.1, 0.3, 0.5, 1.0, 2.0, 5.0, 10.0] {
        let problem = indentation_with(w.clone(), &xs, FrictionLaw::Coulomb { mu: vec![mu; m] }, 0.08, 0.03);
        let solution = assert_all_solvers_agree(&problem, &format!("Coulomb mu = {mu}"));
        let (_, stick, slip) = counts(&solution);
        assert!(stick >= previous_stick, "mu = {mu}: more friction, fewer sticking points");
        previous_stick = stick;
        if mu == 0.0 {
            assert_eq!(problem.friction(), &FrictionLaw::None);
            assert!(solution.force.iter().skip(1).step_by(2).all(|&t| t == 0.0));
        }
        if mu == 10.0 {
            assert_eq!(slip, 0, "mu = 10 sticks everywhere on this load");
        }
    }
}

#[test]
fn zero_friction_leaves_tangential_forces_exactly_zero() {
    let m = 30;
    let (w, xs) = layer_delassus(m, 0.5, 0.3);
    // Per-point zero coefficients and thresholds, mixed with nonzero ones.
    let mu: Vec<f64> = (0..m).map(|i| if i % 2 == 0 { 0.0 } else { 0.3 }).collect();
    let threshold: Vec<f64> = (0..m).map(|i| if i % 3 == 0 { 0.0 } else { 0.001 }).collect();
    for friction in [FrictionLaw::Coulomb { mu: mu.clone() }, FrictionLaw::Tresca { threshold: threshold.clone() }] {
        let problem = indentation_with(w.clone(), &xs, friction.clone(), 0.08, 0.03);
        for solver in all_solvers() {
            let solution = solve(&problem, &solver, &tight()).unwrap();
            for i in 0..m {
                let frictionless = match &friction {
                    FrictionLaw::Coulomb { .. } => mu[i] == 0.0,
                    _ => threshold[i] == 0.0,
                };
                if frictionless {
                    assert_eq!(solution.force[2 * i + 1], 0.0, "{}: point {i}", solver.name());
                }
            }
            assert!(solution.force.iter().skip(1).step_by(2).any(|&t| t != 0.0));
        }
    }
}
