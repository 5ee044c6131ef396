//! The Delassus operator given implicitly solves like the dense matrix.

use crate::{indentation, max_relative_difference, tight};
use signorini::contact::{solve, CondensedProblem, ContactSolver, Delassus, FrictionLaw};
use signorini::Error;

// ---------------------------------------------------------------------------------------------
// Implicit operator
// ---------------------------------------------------------------------------------------------

fn as_operator(problem: &CondensedProblem) -> CondensedProblem<'static> {
    let w = problem.delassus().as_dense().unwrap().clone();
    let size = w.nrows();
    let diagonal = w.diagonal().iter().copied().collect();
    let apply = move |x: &[f64], y: &mut [f64]| {
        let product = &w * nalgebra::DVector::from_column_slice(x);
        y.copy_from_slice(product.as_slice());
    };
    CondensedProblem::new(
        Delassus::Operator { size, apply: Box::new(apply), diagonal },
        problem.free_displacement().to_vec(),
        problem.gap().to_vec(),
        problem.friction().clone(),
        None,
    )
    .unwrap()
}

#[test]
fn operator_and_dense_give_the_same_answer() {
    let m = 40;
    for friction in [
        FrictionLaw::None,
        FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] },
        FrictionLaw::Coulomb { mu: vec![0.3; m] },
    ] {
        let dense = indentation(m, friction.clone(), 0.08, 0.03);
        let operator = as_operator(&dense);
        let reference = solve(&dense, &ContactSolver::SemismoothNewton, &tight()).unwrap();
        for solver in [
            ContactSolver::SemismoothNewton,
            ContactSolver::Uzawa { accelerated: true },
            ContactSolver::Uzawa { accelerated: false },
            ContactSolver::TrescaFixedPoint { inner: Box::new(ContactSolver::SemismoothNewton) },
        ] {
            let solution = solve(&operator, &solver, &tight()).unwrap_or_else(|e| panic!("{friction:?}: {e}"));
            let difference = max_relative_difference(&solution.force, &reference.force);
            assert!(difference < 1e-6, "{friction:?}, {}: {difference:e}", solver.name());
        }
        let newton = solve(&operator, &ContactSolver::SemismoothNewton, &tight()).unwrap();
        assert!(newton.notes.iter().any(|n| n.contains("Krylov")), "{:?}", newton.notes);
    }
}

#[test]
fn dense_only_solvers_refuse_an_operator() {
    let operator = as_operator(&indentation(10, FrictionLaw::Coulomb { mu: vec![0.3; 10] }, 0.08, 0.03));
    for solver in [ContactSolver::ProjectedRelaxation { omega: 1.0 }, ContactSolver::DPana] {
        match solve(&operator, &solver, &tight()) {
            Err(Error::Usage(message)) => assert!(message.contains("Delassus::Dense"), "{message}"),
            other => panic!("expected a usage error, got {other:?}"),
        }
    }
}

/// An implicit operator whose product borrows local data (a matrix, a counter in a `Cell`):
/// neither `'static` nor `Sync`, as a product by PETSc solves is. The problem lives as long as
/// what the product borrows; Uzawa and the semi-smooth Newton method solve it like the dense
/// one, the dense-only solvers refuse it naming those that work.
#[test]
fn borrowed_operator_solves_like_dense() {
    let m = 20;
    let dense = indentation(m, FrictionLaw::Tresca { threshold: vec![0.04 / m as f64; m] }, 0.08, 0.03);
    let w = dense.delassus().as_dense().unwrap().clone();
    let products = std::cell::Cell::new(0usize);
    let apply = |x: &[f64], y: &mut [f64]| {
        products.set(products.get() + 1);
        let product = &w * nalgebra::DVector::from_column_slice(x);
        y.copy_from_slice(product.as_slice());
    };
    let diagonal = w.diagonal().iter().copied().collect();
    let borrowed = CondensedProblem::new(
        Delassus::Operator { size: w.nrows(), apply: Box::new(apply), diagonal },
        dense.free_displacement().to_vec(),
        dense.gap().to_vec(),
        dense.friction().clone(),
        None,
    )
    .unwrap();
    let reference = solve(&dense, &ContactSolver::SemismoothNewton, &tight()).unwrap();
    for solver in [ContactSolver::Uzawa { accelerated: true }, ContactSolver::SemismoothNewton] {
        let before = products.get();
        let solution = solve(&borrowed, &solver, &tight()).unwrap();
        assert!(products.get() > before, "{} used no product", solver.name());
        let difference = max_relative_difference(&solution.force, &reference.force);
        assert!(difference < 1e-6, "{}: {difference:e}", solver.name());
    }
    match solve(&borrowed, &ContactSolver::ProjectedRelaxation { omega: 1.0 }, &tight()) {
        Err(Error::Usage(message)) => {
            assert!(message.contains("Uzawa") && message.contains("semi-smooth Newton"), "{message}")
        }
        other => panic!("expected a usage error, got {other:?}"),
    }
}
