//! Convergence rates on a manufactured solution, the banded solver and the energy norm.

use crate::{all_dofs, dirichlet, solve, solve_banded, steel, Distortion, Grid, Random, BOTTOM, LEFT, RIGHT, TOP};
use signorini::fem::{
    assemble, energy_error, energy_norm, l2_error, residual_forces, EdgeLoad, Loads, Material, PlaneModel, Traction,
};
use signorini::mesh::Order;
use std::f64::consts::PI;

// ---------------------------------------------------------------------------------------------
// Convergence on a manufactured solution.
// ---------------------------------------------------------------------------------------------

fn manufactured(x: [f64; 2]) -> [f64; 2] {
    let (sx, sy) = ((PI * x[0]).sin(), (PI * x[1]).sin());
    [sx * sy + 0.2 * x[0] * x[1], x[0] * x[0] * x[1] * (1.0 - x[1]) + 0.1 * sy]
}

fn manufactured_gradient(x: [f64; 2]) -> [[f64; 2]; 2] {
    let (sx, sy, cx, cy) = ((PI * x[0]).sin(), (PI * x[1]).sin(), (PI * x[0]).cos(), (PI * x[1]).cos());
    [
        [PI * cx * sy + 0.2 * x[1], PI * sx * cy + 0.2 * x[0]],
        [2.0 * x[0] * x[1] * (1.0 - x[1]), x[0] * x[0] * (1.0 - 2.0 * x[1]) + 0.1 * PI * cy],
    ]
}

/// −div σ(u) for the manufactured u.
fn manufactured_force(m: &Material, x: [f64; 2]) -> [f64; 2] {
    let [[c11, c12, _], _, [_, _, c33]] = m.elasticity();
    let (sx, sy, cx, cy) = ((PI * x[0]).sin(), (PI * x[1]).sin(), (PI * x[0]).cos(), (PI * x[1]).cos());
    let uxx = -PI * PI * sx * sy;
    let uyy = -PI * PI * sx * sy;
    let uxy = PI * PI * cx * cy + 0.2;
    let vxx = 2.0 * x[1] * (1.0 - x[1]);
    let vyy = -2.0 * x[0] * x[0] - 0.1 * PI * PI * sy;
    let vxy = 2.0 * x[0] * (1.0 - 2.0 * x[1]);
    [-(c11 * uxx + c12 * vxy + c33 * (uyy + vxy)), -(c33 * (uxy + vxx) + c12 * uxy + c11 * vyy)]
}

fn manufactured_stress(m: &Material, x: [f64; 2]) -> [f64; 3] {
    let g = manufactured_gradient(x);
    m.stress([g[0][0], g[1][1], g[0][1] + g[1][0]])
}

/// (h, energy error, L2 error) over a refinement sequence.
fn convergence(order: Order, sizes: &[usize], m: &Material, neumann: bool) -> Vec<(f64, f64, f64)> {
    let force = |x: [f64; 2]| manufactured_force(m, x);
    let traction = |x: [f64; 2], n: [f64; 2]| {
        let s = manufactured_stress(m, x);
        [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]]
    };
    sizes
        .iter()
        .map(|&n| {
            let mesh = Grid::new(n, order).distorted(Distortion::Smooth(0.04)).build();
            let (groups, edge_loads): (&[usize], _) = if neumann {
                (
                    &[BOTTOM, LEFT],
                    vec![
                        EdgeLoad { group: RIGHT, traction: Traction::Field(&traction) },
                        EdgeLoad { group: TOP, traction: Traction::Field(&traction) },
                    ],
                )
            } else {
                (&[BOTTOM, RIGHT, TOP, LEFT], vec![])
            };
            let c = dirichlet(&mesh, groups, &manufactured);
            let loads = Loads { body_force: Some(&force), edge_loads };
            let u = solve_banded(&mesh, &assemble(&mesh, m, &c, &loads, all_dofs(&mesh)));
            let e = energy_error(&mesh, m, &u, manufactured_gradient);
            let l2 = l2_error(&mesh, &u, manufactured);
            (1.0 / n as f64, e, l2)
        })
        .collect()
}

fn assert_rates(what: &str, results: &[(f64, f64, f64)], energy_rate: f64, l2_rate: f64) {
    let rates: Vec<(f64, f64)> = results
        .windows(2)
        .map(|w| {
            let r = (w[0].0 / w[1].0).ln();
            ((w[0].1 / w[1].1).ln() / r, (w[0].2 / w[1].2).ln() / r)
        })
        .collect();
    eprintln!("{what}: errors {results:?}, rates {rates:?}");
    // The last two refinements must show the asymptotic rates.
    for &(re, rl) in &rates[rates.len().saturating_sub(2)..] {
        assert!(re >= energy_rate, "{what}: energy rate {re:.3} < {energy_rate} ({rates:?})");
        assert!(rl >= l2_rate, "{what}: L2 rate {rl:.3} < {l2_rate} ({rates:?})");
    }
}

#[test]
fn convergence_rates_p1() {
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        let res = convergence(Order::P1, &[4, 8, 16, 32], &m, false);
        assert_rates(&format!("P1 {plane:?} Dirichlet"), &res, 0.9, 1.8);
    }
}

#[test]
fn convergence_rates_p2() {
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        let res = convergence(Order::P2, &[2, 4, 8, 16], &m, false);
        assert_rates(&format!("P2 {plane:?} Dirichlet"), &res, 1.8, 2.7);
    }
}

#[test]
fn convergence_rates_with_traction_field() {
    let m = Material::new(1.0e3, 0.25, PlaneModel::Strain);
    let res = convergence(Order::P1, &[4, 8, 16, 32], &m, true);
    assert_rates("P1 Neumann", &res, 0.9, 1.8);
    let res = convergence(Order::P2, &[2, 4, 8, 16], &m, true);
    assert_rates("P2 Neumann", &res, 1.8, 2.7);
}

#[test]
fn banded_solver_agrees_with_dense_cholesky() {
    for order in [Order::P1, Order::P2] {
        let m = steel(PlaneModel::Strain);
        let mesh = Grid::new(6, order).distorted(Distortion::Random(0.2)).build();
        let c = dirichlet(&mesh, &[LEFT, BOTTOM], &manufactured);
        let force = |x: [f64; 2]| manufactured_force(&m, x);
        let loads = Loads {
            body_force: Some(&force),
            edge_loads: vec![EdgeLoad { group: TOP, traction: Traction::Pressure(1e8) }],
        };
        let system = assemble(&mesh, &m, &c, &loads, all_dofs(&mesh));
        let (dense, banded) = (solve(&system), solve_banded(&mesh, &system));
        let scale = dense.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        for (a, b) in dense.iter().zip(&banded) {
            assert!((a - b).abs() < 1e-11 * scale, "{order:?}: {a} vs {b}");
        }
    }
}

#[test]
fn energy_norm_is_the_stiffness_energy() {
    for order in [Order::P1, Order::P2] {
        let mesh = Grid::new(3, order).distorted(Distortion::Random(0.2)).build();
        let m = steel(PlaneModel::Stress);
        let mut rng = Random(11);
        let u: Vec<f64> = (0..2 * mesh.num_nodes()).map(|_| 1e-3 * rng.next()).collect();
        let ku = residual_forces(&mesh, &m, &u);
        let utku: f64 = u.iter().zip(&ku).map(|(a, b)| a * b).sum();
        let e = energy_norm(&mesh, &m, &u);
        assert!((e * e - utku).abs() < 1e-12 * utku, "{order:?}: {} vs {utku}", e * e);
        assert!((energy_error(&mesh, &m, &u, |_| [[0.0; 2]; 2]) - e).abs() < 1e-12 * e);
        assert!((l2_error(&mesh, &u, |_| [0.0, 0.0]) > 0.0));
    }
}
