//! Invalid problems and settings are rejected, naming the entity.

use crate::{one_point, tight};
use nalgebra::DMatrix;
use signorini::contact::{solve, CondensedProblem, ContactSolver, Delassus, FrictionLaw, SolverSettings};
use signorini::Error;

// ---------------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------------

fn usage_message(result: Result<CondensedProblem, Error>) -> String {
    match result {
        Err(Error::Usage(message)) => message,
        other => panic!("expected Error::Usage, got {other:?}"),
    }
}

#[test]
fn invalid_problems_are_rejected_naming_the_entity() {
    let w = || {
        DMatrix::from_row_slice(4, 4, &[2.0, 0.3, 1.0, 0.2, 0.3, 1.0, 0.1, 0.4, 1.0, 0.1, 2.0, 0.3, 0.2, 0.4, 0.3, 1.0])
    };
    let free = vec![1.0, 0.0, 0.2, 0.0];
    let gap = vec![0.0, 0.5];
    let ok = CondensedProblem::new(Delassus::Dense(w()), free.clone(), gap.clone(), FrictionLaw::None, None);
    assert!(ok.is_ok());

    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(DMatrix::identity(3, 3)),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("3×3") && m.contains("4×4"), "{m}");
    let mut asymmetric = w();
    asymmetric[(0, 2)] = 1.5;
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(asymmetric),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("not symmetric") && m.contains("contact points 1 and 0"), "{m}");
    let mut indefinite = w();
    indefinite[(0, 2)] = 3.0;
    indefinite[(2, 0)] = 3.0;
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(indefinite),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("not positive definite"), "{m}");
    let mut bad_diagonal = w();
    bad_diagonal[(3, 3)] = -1.0;
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(bad_diagonal),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("contact point 1") && m.contains("tangential"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        vec![0.0, f64::NAN],
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("contact point 1") && m.contains("gap"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        vec![1.0, 0.0, 0.2],
        gap.clone(),
        FrictionLaw::None,
        None,
    ));
    assert!(m.contains("free displacement has 3 entries"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        gap.clone(),
        FrictionLaw::Coulomb { mu: vec![0.3, -0.1] },
        None,
    ));
    assert!(m.contains("contact point 1") && m.contains("friction coefficient"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        gap.clone(),
        FrictionLaw::Tresca { threshold: vec![0.3] },
        None,
    ));
    assert!(m.contains("Tresca threshold has 1 entries"), "{m}");
    let m = usage_message(CondensedProblem::new(
        Delassus::Dense(w()),
        free.clone(),
        gap.clone(),
        FrictionLaw::None,
        Some(vec![1.0, -1.0]),
    ));
    assert!(m.contains("contact point 1") && m.contains("weight") && m.contains(">= 0"), "{m}");
    // A zero weight (a P2 vertex on the axis in axisymmetry) is accepted; its pressure is not finite.
    let zero =
        CondensedProblem::new(Delassus::Dense(w()), free.clone(), gap.clone(), FrictionLaw::None, Some(vec![1.0, 0.0]))
            .unwrap();
    assert!(!zero.pressure(&[-1.0, 0.0, -1.0, 0.0]).unwrap()[2].is_finite());
    let m = usage_message(CondensedProblem::new(Delassus::Dense(w()), free.clone(), vec![], FrictionLaw::None, None));
    assert!(m.contains("no contact point"), "{m}");
    let asymmetric_operator = Delassus::Operator {
        size: 4,
        apply: Box::new(|x: &[f64], y: &mut [f64]| {
            for i in 0..4 {
                y[i] = 2.0 * x[i] + if i == 0 { x[3] } else { 0.0 };
            }
        }),
        diagonal: vec![2.0; 4],
    };
    let m =
        usage_message(CondensedProblem::new(asymmetric_operator, free.clone(), gap.clone(), FrictionLaw::None, None));
    assert!(m.contains("not symmetric"), "{m}");
}

#[test]
fn settings_are_validated() {
    let problem = one_point(FrictionLaw::None, [1.0, 0.3], 0.2);
    let check =
        |solver: ContactSolver, settings: SolverSettings, needle: &str| match solve(&problem, &solver, &settings) {
            Err(Error::Usage(message)) => assert!(message.contains(needle), "{message}"),
            other => panic!("expected a usage error, got {other:?}"),
        };
    check(ContactSolver::ProjectedRelaxation { omega: 2.5 }, tight(), "omega");
    check(ContactSolver::SemismoothNewton, SolverSettings { tolerance: 0.0, ..tight() }, "tolerance");
    check(ContactSolver::SemismoothNewton, SolverSettings { max_iterations: 0, ..tight() }, "max_iterations");
    check(
        ContactSolver::SemismoothNewton,
        SolverSettings { initial_force: Some(vec![0.0]), ..tight() },
        "initial force",
    );
}

#[test]
fn pressure_divides_by_the_weights() {
    let w = DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]);
    let problem =
        CondensedProblem::new(Delassus::Dense(w), vec![1.0, 0.3], vec![0.2], FrictionLaw::None, Some(vec![0.5]))
            .unwrap();
    let solution = solve(&problem, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    let pressure = problem.pressure(&solution.force).unwrap();
    assert!((pressure[0] + 0.8).abs() < 1e-12);
    assert_eq!(pressure[1], 0.0);
    let displacement = problem.displacement(&solution.force).unwrap();
    assert_eq!(displacement, solution.displacement);
    assert_eq!(problem.status(&solution.force).unwrap(), solution.status);
}
