//! Patch tests: linear fields exact with Dirichlet data, tractions and pressure; P2 with a body force.

use crate::{all_dofs, dirichlet, nodal_error, solve, steel, Distortion, Grid, BOTTOM, LEFT, RIGHT, TOP};
use signorini::fem::{
    assemble, cell_stress, energy_error, energy_norm, l2_error, load_vector, nodal_stress, residual_forces,
    Constraints, EdgeLoad, Loads, Material, PlaneModel, Traction,
};
use signorini::mesh::{Mesh, Order};

// ---------------------------------------------------------------------------------------------
// Patch tests.
// ---------------------------------------------------------------------------------------------

/// The linear field of the patch tests (uniform strain) and its stress.
fn linear_field(x: [f64; 2]) -> [f64; 2] {
    [1e-3 + 2e-3 * x[0] - 1e-3 * x[1], -5e-4 + 7e-4 * x[0] + 1.5e-3 * x[1]]
}
const LINEAR_STRAIN: [f64; 3] = [2e-3, 1.5e-3, -1e-3 + 7e-4];

fn patch_meshes() -> Vec<(&'static str, Mesh)> {
    vec![
        ("P1 distorted", Grid::new(5, Order::P1).distorted(Distortion::Random(0.2)).build()),
        ("P2 distorted", Grid::new(4, Order::P2).distorted(Distortion::Random(0.2)).build()),
        ("P2 curved", Grid::new(4, Order::P2).distorted(Distortion::Random(0.2)).curved(0.06, 0.1).build()),
    ]
}

fn assert_uniform_stress(what: &str, mesh: &Mesh, m: &Material, u: &[f64], s: [f64; 3]) {
    let scale = s.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    for (k, cs) in cell_stress(mesh, m, u).iter().chain(nodal_stress(mesh, m, u).iter()).enumerate() {
        for i in 0..3 {
            assert!((cs[i] - s[i]).abs() < 1e-9 * scale, "{what}: stress {k} component {i}: {} vs {}", cs[i], s[i]);
        }
    }
}

#[test]
fn patch_test_dirichlet_all_around() {
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        for (what, mesh) in patch_meshes() {
            let c = dirichlet(&mesh, &[BOTTOM, RIGHT, TOP, LEFT], &linear_field);
            let u = solve(&assemble(&mesh, &m, &c, &Loads::default(), all_dofs(&mesh)));
            let err = nodal_error(&mesh, &u, &linear_field);
            assert!(err < 1e-12, "{what} {plane:?}: nodal error {err:e}");
            let s = m.stress(LINEAR_STRAIN);
            assert_uniform_stress(what, &mesh, &m, &u, s);
            let e = energy_error(&mesh, &m, &u, |_| [[2e-3, -1e-3], [7e-4, 1.5e-3]]);
            let norm = energy_norm(&mesh, &m, &u);
            assert!(e < 1e-10 * norm, "{what}: energy error {e:e} of {norm:e}");
            // Reactions balance: the sum of (K u − f) over all dofs is zero (no loads).
            let r = residual_forces(&mesh, &m, &u);
            let scale = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let (rx, ry): (f64, f64) = (r.iter().step_by(2).sum(), r.iter().skip(1).step_by(2).sum());
            assert!(rx.abs() < 1e-10 * scale && ry.abs() < 1e-10 * scale, "{what}: reactions ({rx}, {ry})");
        }
    }
}

#[test]
fn patch_test_with_tractions() {
    let m = steel(PlaneModel::Strain);
    let s = m.stress(LINEAR_STRAIN);
    let sigma_n = move |_x: [f64; 2], n: [f64; 2]| [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]];
    for (what, mesh) in patch_meshes() {
        // Right (straight): constant traction σ (1, 0); top (curved for "P2 curved"): σ n.
        let right = if what == "P2 curved" { Traction::Field(&sigma_n) } else { Traction::Constant([s[0], s[2]]) };
        let loads = Loads {
            body_force: None,
            edge_loads: vec![
                EdgeLoad { group: RIGHT, traction: right },
                EdgeLoad { group: TOP, traction: Traction::Field(&sigma_n) },
            ],
        };
        let c = dirichlet(&mesh, &[BOTTOM, LEFT], &linear_field);
        c.check_rigid_motions(&mesh).unwrap();
        let u = solve(&assemble(&mesh, &m, &c, &loads, all_dofs(&mesh)));
        let err = nodal_error(&mesh, &u, &linear_field);
        assert!(err < 1e-12, "{what}: nodal error {err:e}");
        assert_uniform_stress(what, &mesh, &m, &u, s);
        // Reactions on the fixed dofs balance the applied tractions.
        let r = residual_forces(&mesh, &m, &u);
        let f = load_vector(&mesh, &loads);
        let total: [f64; 2] =
            [(0..r.len()).step_by(2).map(|i| r[i] - f[i]).sum(), (1..r.len()).step_by(2).map(|i| r[i] - f[i]).sum()];
        let reactions: [f64; 2] = [
            c.fixed().filter(|(d, _)| d % 2 == 0).map(|(d, _)| r[d] - f[d]).sum(),
            c.fixed().filter(|(d, _)| d % 2 == 1).map(|(d, _)| r[d] - f[d]).sum(),
        ];
        let applied: [f64; 2] = [f.iter().step_by(2).sum(), f.iter().skip(1).step_by(2).sum()];
        for k in 0..2 {
            assert!((reactions[k] + applied[k]).abs() < 1e-9 * applied[k].abs().max(1.0), "{what}: equilibrium {k}");
            assert!(
                (total[k] - reactions[k]).abs() < 1e-9 * applied[k].abs().max(1.0),
                "{what}: free dofs not in equilibrium"
            );
        }
    }
}

#[test]
fn patch_test_with_pressure() {
    // Hydrostatic state σ = −p I: u = −p/(2(λ* + μ)) x, traction −p n (Pressure) on the free sides.
    for plane in [PlaneModel::Strain, PlaneModel::Stress] {
        let m = steel(plane);
        let p = 4e7;
        let (lambda, mu) = m.lame();
        let k = -p / (2.0 * (lambda + mu));
        let exact = move |x: [f64; 2]| [k * x[0], k * x[1]];
        for (what, mesh) in patch_meshes() {
            let mut c = Constraints::new(2 * mesh.num_nodes());
            c.fix_group(&mesh, LEFT, 0, |_| 0.0);
            c.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
            let loads = Loads {
                body_force: None,
                edge_loads: vec![
                    EdgeLoad { group: RIGHT, traction: Traction::Pressure(p) },
                    EdgeLoad { group: TOP, traction: Traction::Pressure(p) },
                ],
            };
            let u = solve(&assemble(&mesh, &m, &c, &loads, all_dofs(&mesh)));
            let err = nodal_error(&mesh, &u, &exact);
            assert!(err < 1e-12, "{what} {plane:?}: nodal error {err:e}");
            assert_uniform_stress(what, &mesh, &m, &u, [-p, -p, 0.0]);
        }
    }
}

#[test]
fn p2_reproduces_a_quadratic_field_with_its_body_force() {
    let m = steel(PlaneModel::Strain);
    let [[c11, c12, _], _, [_, _, c33]] = m.elasticity();
    // u = (x² − xy + 2y², −3x² + 4xy + y²) · 1e-3.
    let exact = |x: [f64; 2]| {
        [
            1e-3 * (x[0] * x[0] - x[0] * x[1] + 2.0 * x[1] * x[1]),
            1e-3 * (-3.0 * x[0] * x[0] + 4.0 * x[0] * x[1] + x[1] * x[1]),
        ]
    };
    let (uxx, uxy, uyy) = (2e-3, -1e-3, 4e-3); // second derivatives of u_x
    let (vxx, vxy, vyy) = (-6e-3, 4e-3, 2e-3); // of u_y
    let f = [-(c11 * uxx + c12 * vxy + c33 * (uyy + vxy)), -(c33 * (uxy + vxx) + c12 * uxy + c11 * vyy)];
    let force = move |_: [f64; 2]| f;
    let mesh = Grid::new(4, Order::P2).distorted(Distortion::Random(0.2)).build();
    let c = dirichlet(&mesh, &[BOTTOM, RIGHT, TOP, LEFT], &exact);
    let loads = Loads { body_force: Some(&force), edge_loads: vec![] };
    let u = solve(&assemble(&mesh, &m, &c, &loads, all_dofs(&mesh)));
    let err = nodal_error(&mesh, &u, &exact);
    assert!(err < 1e-12, "nodal error {err:e}");
    let l2 = l2_error(&mesh, &u, exact);
    assert!(l2 < 1e-14, "L2 error {l2:e}");
    // P1 cannot: the same problem has a visible error.
    let mesh1 = Grid::new(4, Order::P1).distorted(Distortion::Random(0.2)).build();
    let c1 = dirichlet(&mesh1, &[BOTTOM, RIGHT, TOP, LEFT], &exact);
    let u1 = solve(&assemble(&mesh1, &m, &c1, &loads, all_dofs(&mesh1)));
    assert!(l2_error(&mesh1, &u1, exact) > 1e-7);
}
