//! Axisymmetric elasticity (issue 27): the kernels of `fem::assembly` (P1, P2) and
//! `fem::mixed_pressure` (P2–P0) on meshes of the meridian half-plane `(r, z) = (x, y)`.
//!
//! - Patch test `u = (a r, b z + c)`: uniform strain `(εrr, εzz, εθθ) = (a, b, a)`, uniform stress
//!   with `σθθ = σrr`; exact to round-off at the nodes and in the nodal stresses (hoop included),
//!   with Dirichlet data all around and with tractions (r-weighted loads).
//! - Lamé's thick cylinder under internal pressure, `u_z = 0` on top and bottom: `u_r = A r + B/r`
//!   (Timoshenko & Goodier, Theory of Elasticity, 1970, §28). `B/r` is not a polynomial, so no
//!   element reproduces it: P1 converges at rate 1 and P2 at rate 2 in the energy norm, and P2–P0
//!   at ν = 0.4999 without locking.
//! - The axis: a solid cylinder under a uniform radial pressure on its outer face, `u_r = C r`
//!   exactly (`C = −q (1 + ν)(1 − 2ν)/E`), with `u_r = 0` on the axis: exact to round-off, no
//!   NaN in the stresses at `r = 0` (the hoop strain's limit there is `∂u_r/∂r`).
//!
//! The energy norm is computed here, independently of the library's norms:
//! `‖u_h − u‖_E² = ∫ (ε_h − ε) : C (ε_h − ε) 2π r dA` with the hoop strain `u_r / r`; the
//! library's `fem::postprocess::energy_error_with_displacement` is checked against it.
use crate::{solve_banded, Distortion, Grid, BOTTOM, LEFT, RIGHT, TOP};
use signorini::fem::assembly::assemble_with;
use signorini::fem::mixed_pressure::{nodal_stress, stress_l2_error};
use signorini::fem::{lagrange, quadrature, Constraints, EdgeLoad, Element, Loads, Material, PlaneModel, Traction};
use signorini::mesh::{Measure, Mesh, Order};
use std::f64::consts::PI;

/// The unit-square grid moved to `r ∈ [r0, r0 + width]`, `z ∈ [0, height]`, as a meridian mesh.
fn meridian(grid: Grid, r0: f64, width: f64, height: f64) -> Mesh {
    let mut mesh = grid.build();
    for x in &mut mesh.nodes {
        *x = [r0 + width * x[0], height * x[1]];
    }
    mesh.measure = Measure::Axisymmetric;
    mesh
}

fn material(poisson: f64) -> Material {
    Material::new(2.0e11, poisson, PlaneModel::Axisymmetric)
}

/// `u_r = 0` on the nodes with `r = 0` (what the driver does, `problem::axisymmetry::fix_axis`).
fn fix_axis(mesh: &Mesh, c: &mut Constraints) -> usize {
    let mut count = 0;
    for (k, x) in mesh.nodes.iter().enumerate() {
        if x[0] == 0.0 {
            c.fix(2 * k, 0.0);
            count += 1;
        }
    }
    count
}

/// `‖u_h − u‖_E` over the body of revolution (module documentation), with the exact
/// `(u_r, ∂u_r/∂r, ∂u_z/∂z)` of a field with `u_r(r)`, `u_z(z)` only (no shear), degree-5 rule.
fn energy_error(mesh: &Mesh, m: &Material, u: &[f64], exact: impl Fn([f64; 2]) -> [f64; 3]) -> f64 {
    let rule = quadrature::triangle(5);
    let npc = mesh.order.nodes_per_cell();
    let mut total = 0.0;
    for c in 0..mesh.num_cells() {
        let nodes = mesh.cell(c);
        let x: Vec<[f64; 2]> = nodes.iter().map(|&k| mesh.nodes[k]).collect();
        for (&xi, &w) in rule.points.iter().zip(&rule.weights) {
            let p = lagrange::map_cell_point(mesh.order, &x, xi);
            let (mut e, mut ur) = ([0.0; 3], 0.0);
            for a in 0..npc {
                let (g, k) = (p.gradients[a], nodes[a]);
                e[0] += g[0] * u[2 * k];
                e[1] += g[1] * u[2 * k + 1];
                e[2] += g[1] * u[2 * k] + g[0] * u[2 * k + 1];
                ur += p.values[a] * u[2 * k];
            }
            let r = p.x[0];
            let t = exact(p.x);
            let d = [e[0] - t[1], e[1] - t[2], e[2]];
            let hoop = ur / r - t[0] / r;
            let (s, s_hoop) = m.axisymmetric_stress(d, hoop);
            total += w * p.det * 2.0 * PI * r * (s[0] * d[0] + s[1] * d[1] + s[2] * d[2] + s_hoop * hoop);
        }
    }
    total.max(0.0).sqrt()
}

fn rates(h: &[f64], e: &[f64]) -> Vec<f64> {
    h.windows(2).zip(e.windows(2)).map(|(h, e)| (e[0] / e[1]).ln() / (h[0] / h[1]).ln()).collect()
}

// ---------------------------------------------------------------------------------------------
// Patch test u = (a r, b z + c).
// ---------------------------------------------------------------------------------------------

const A: f64 = 2e-3;
const B: f64 = -1.2e-3;
const C: f64 = 3e-4;

fn patch_field(x: [f64; 2]) -> [f64; 2] {
    [A * x[0], B * x[1] + C]
}

fn patch_meshes() -> Vec<(&'static str, Mesh)> {
    let p2 = Grid::new(4, Order::P2).distorted(Distortion::Random(0.2));
    vec![
        ("P1 distorted", meridian(Grid::new(5, Order::P1).distorted(Distortion::Random(0.2)), 0.5, 1.0, 1.0)),
        ("P2 distorted", meridian(p2, 0.5, 1.0, 1.0)),
        ("P2 curved", meridian(p2.curved(0.06, 0.1), 0.5, 1.0, 1.0)),
        // Touching the axis: the left side at r = 0.
        ("P2 on the axis", meridian(p2, 0.0, 1.0, 1.0)),
    ]
}

/// Nodal displacements and nodal stresses (σrr, σzz, σrz and σθθ) against the patch field, to
/// `1e-12` (displacements) and `1e-9` (stresses) at ν = 0.3; at ν = 0.4999 the round-off is
/// amplified by the bulk-to-shear ratio (1.7e3): `1e-10` and `1e-8` (measured 1.3e-9 of the
/// displacement without this allowance, `tests/mixed_pressure.rs` takes the same).
fn check_patch(what: &str, mesh: &Mesh, m: &Material, element: Element, u: &[f64]) {
    let (tol_u, tol_s) = if m.poisson > 0.49 { (1e-10, 1e-8) } else { (1e-12, 1e-9) };
    let scale = mesh.nodes.iter().map(|&x| patch_field(x)[0].abs().max(patch_field(x)[1].abs())).fold(0.0, f64::max);
    for (k, &x) in mesh.nodes.iter().enumerate() {
        let e = patch_field(x);
        for c in 0..2 {
            assert!(
                (u[2 * k + c] - e[c]).abs() < tol_u * scale,
                "{what}: node {k} at {x:?}: u {} vs {}",
                u[2 * k + c],
                e[c]
            );
        }
    }
    let (s, s_hoop) = m.axisymmetric_stress([A, B, 0.0], A);
    let size = s.iter().fold(s_hoop.abs(), |a, v| a.max(v.abs()));
    let (nodal, hoop) = nodal_stress(mesh, m, element, u);
    for k in 0..mesh.num_nodes() {
        for i in 0..3 {
            assert!(
                (nodal[k][i] - s[i]).abs() < tol_s * size,
                "{what}: node {k}: stress {i} {} vs {}",
                nodal[k][i],
                s[i]
            );
        }
        assert!((hoop[k] - s_hoop).abs() < tol_s * size, "{what}: node {k}: hoop stress {} vs {s_hoop}", hoop[k]);
    }
    // σθθ = σrr for this field.
    assert!((s_hoop - s[0]).abs() < 1e-12 * size);
}

#[test]
fn axisymmetric_patch_test_dirichlet_all_around_is_exact() {
    for (what, mesh) in patch_meshes() {
        for (element, poisson) in [(Element::Lagrange, 0.3), (Element::P2P0, 0.3), (Element::P2P0, 0.4999)] {
            if element == Element::P2P0 && mesh.order == Order::P1 {
                continue;
            }
            let m = material(poisson);
            let mut c = Constraints::new(2 * mesh.num_nodes());
            for g in [BOTTOM, RIGHT, TOP, LEFT] {
                c.fix_group(&mesh, g, 0, |x| patch_field(x)[0]);
                c.fix_group(&mesh, g, 1, |x| patch_field(x)[1]);
            }
            let u =
                solve_banded(&mesh, &assemble_with(&mesh, &m, element, &c, &Loads::default(), 0..2 * mesh.num_nodes()));
            check_patch(&format!("{what} {element:?} ν = {poisson}"), &mesh, &m, element, &u);
        }
    }
}

#[test]
fn axisymmetric_patch_test_with_tractions_is_exact() {
    // Dirichlet u_r on the inner face and u_z at the bottom; the outer face r = 1.5 carries
    // σrr, the top σzz (2π r-weighted loads), curved for the P2 curved mesh.
    for (what, mesh) in patch_meshes().into_iter().filter(|(w, _)| *w != "P2 on the axis") {
        for (element, poisson) in [(Element::Lagrange, 0.3), (Element::P2P0, 0.4999)] {
            if element == Element::P2P0 && mesh.order == Order::P1 {
                continue;
            }
            let m = material(poisson);
            let (s, _) = m.axisymmetric_stress([A, B, 0.0], A);
            let traction = move |_x: [f64; 2], n: [f64; 2]| [s[0] * n[0] + s[2] * n[1], s[2] * n[0] + s[1] * n[1]];
            let loads = Loads {
                body_force: None,
                edge_loads: vec![
                    EdgeLoad { group: RIGHT, traction: Traction::Field(&traction) },
                    EdgeLoad { group: TOP, traction: Traction::Field(&traction) },
                ],
            };
            let mut c = Constraints::new(2 * mesh.num_nodes());
            c.fix_group(&mesh, LEFT, 0, |x| patch_field(x)[0]);
            c.fix_group(&mesh, BOTTOM, 1, |x| patch_field(x)[1]);
            c.check_rigid_motions(&mesh).unwrap();
            let u = solve_banded(&mesh, &assemble_with(&mesh, &m, element, &c, &loads, 0..2 * mesh.num_nodes()));
            check_patch(&format!("{what} {element:?} ν = {poisson}, tractions"), &mesh, &m, element, &u);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Lamé's thick cylinder.
// ---------------------------------------------------------------------------------------------

const INNER: f64 = 1.0;
const OUTER: f64 = 2.0;
const PRESSURE: f64 = 1e8;

/// `(u_r, ∂u_r/∂r, ∂u_z/∂z = 0)` of Lamé's cylinder with `ε_z = 0`: `u_r = A r + B/r`,
/// `A = p a² (1 + ν)(1 − 2ν) / (E (b² − a²))`, `B = p a² b² (1 + ν) / (E (b² − a²))`.
fn lame(m: &Material) -> impl Fn([f64; 2]) -> [f64; 3] {
    let (a2, b2, e, nu) = (INNER * INNER, OUTER * OUTER, m.young, m.poisson);
    let ca = PRESSURE * a2 * (1.0 + nu) * (1.0 - 2.0 * nu) / (e * (b2 - a2));
    let cb = PRESSURE * a2 * b2 * (1.0 + nu) / (e * (b2 - a2));
    move |x| [ca * x[0] + cb / x[0], ca - cb / (x[0] * x[0]), 0.0]
}

/// `(σrr, σzz, σrz, σθθ)` of Lamé's cylinder (`σzz = ν (σrr + σθθ)`).
fn lame_stress(m: &Material) -> impl Fn([f64; 2]) -> [f64; 4] {
    let (a2, b2, nu) = (INNER * INNER, OUTER * OUTER, m.poisson);
    let k = PRESSURE * a2 / (b2 - a2);
    move |x| {
        let r2 = x[0] * x[0];
        let (rr, tt) = (k * (1.0 - b2 / r2), k * (1.0 + b2 / r2));
        [rr, nu * (rr + tt), 0.0, tt]
    }
}

/// Lamé on an `n × n` grid (smoothly distorted) of `[1, 2] × [0, 0.5]`: pressure on the bore,
/// `u_z = 0` on top and bottom. Returns (energy error / energy norm of the exact field, stress
/// L2 error / exact stress norm).
fn lame_errors(order: Order, element: Element, poisson: f64, n: usize) -> (f64, f64) {
    let mesh = meridian(Grid::new(n, order).distorted(Distortion::Smooth(0.03)), INNER, OUTER - INNER, 0.5);
    let m = material(poisson);
    let mut c = Constraints::new(2 * mesh.num_nodes());
    c.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
    c.fix_group(&mesh, TOP, 1, |_| 0.0);
    let loads =
        Loads { body_force: None, edge_loads: vec![EdgeLoad { group: LEFT, traction: Traction::Pressure(PRESSURE) }] };
    let u = solve_banded(&mesh, &assemble_with(&mesh, &m, element, &c, &loads, 0..2 * mesh.num_nodes()));
    let exact = lame(&m);
    let zero = vec![0.0; u.len()];
    let energy = energy_error(&mesh, &m, &u, &exact) / energy_error(&mesh, &m, &zero, &exact);
    let stress = stress_l2_error(&mesh, &m, element, &u, lame_stress(&m))
        / stress_l2_error(&mesh, &m, Element::Lagrange, &zero, lame_stress(&m));
    (energy, stress)
}

#[test]
fn axisymmetric_lame_cylinder_energy_rates_p1_and_p2() {
    // Measured (n = 4, 8, 16, 32 for P1; 2, 4, 8, 16 for P2): relative energy errors P1 9.39e-2,
    // 4.77e-2, 2.40e-2, 1.20e-2 (rates 0.976, 0.993, 0.998); P2 2.56e-2, 7.43e-3, 1.95e-3,
    // 5.00e-4 (rates 1.787, 1.927, 1.965).
    for (order, sizes, rate) in [(Order::P1, [4, 8, 16, 32], 0.95), (Order::P2, [2, 4, 8, 16], 1.9)] {
        let errors: Vec<(f64, f64)> = sizes.iter().map(|&n| lame_errors(order, Element::Lagrange, 0.3, n)).collect();
        let h: Vec<f64> = sizes.iter().map(|&n| 1.0 / n as f64).collect();
        let energy: Vec<f64> = errors.iter().map(|e| e.0).collect();
        let r = rates(&h, &energy);
        eprintln!("Lamé {order:?} ν = 0.3: relative energy errors {energy:?}, rates {r:.3?}");
        for &x in &r[1..] {
            assert!(x >= rate, "Lamé {order:?}: energy rate {x:.3} < {rate} ({energy:?})");
        }
        // Not exact: B/r is not a polynomial.
        assert!(energy[energy.len() - 1] > 1e-8, "{energy:?}");
    }
}

/// Measured: relative stress L2 errors 1.48e-2, 4.32e-3, 1.14e-3, 2.93e-4 (rates 1.775, 1.919,
/// 1.964), 0.97 times those at ν = 0.3 (1.52e-2 … 3.01e-4) on every mesh.
#[test]
fn axisymmetric_lame_cylinder_near_incompressible_p2p0_does_not_lock() {
    let sizes = [2, 4, 8, 16];
    let h: Vec<f64> = sizes.iter().map(|&n| 1.0 / n as f64).collect();
    let mixed: Vec<(f64, f64)> = sizes.iter().map(|&n| lame_errors(Order::P2, Element::P2P0, 0.4999, n)).collect();
    let moderate: Vec<(f64, f64)> = sizes.iter().map(|&n| lame_errors(Order::P2, Element::P2P0, 0.3, n)).collect();
    let stress: Vec<f64> = mixed.iter().map(|e| e.1).collect();
    let energy: Vec<f64> = mixed.iter().map(|e| e.0).collect();
    let (rs, re) = (rates(&h, &stress), rates(&h, &energy));
    let stress_moderate: Vec<f64> = moderate.iter().map(|e| e.1).collect();
    eprintln!(
        "Lamé P2-P0 ν = 0.4999: relative stress L2 errors {stress:?} (rates {rs:.3?}), displacement energy \
         errors {energy:?} (rates {re:.3?}); at ν = 0.3: {stress_moderate:?}"
    );
    for &x in &rs[1..] {
        assert!(x >= 1.0, "P2-P0 stress rate {x:.3} < 1 ({stress:?})");
    }
    // No locking: the error at ν = 0.4999 is that at ν = 0.3 within a factor 3 on every mesh.
    for (a, b) in stress.iter().zip(&stress_moderate) {
        assert!(*a < 3.0 * b, "P2-P0 at ν = 0.4999: {stress:?} against {stress_moderate:?} at 0.3");
    }
}

// ---------------------------------------------------------------------------------------------
// The axis: a solid cylinder under a radial pressure.
// ---------------------------------------------------------------------------------------------

#[test]
fn axisymmetric_solid_cylinder_is_exact_on_the_axis() {
    let q = 5e7;
    for (order, element) in [(Order::P1, Element::Lagrange), (Order::P2, Element::Lagrange), (Order::P2, Element::P2P0)]
    {
        let m = material(0.3);
        let grid = Grid::new(4, order).distorted(Distortion::Random(0.2));
        let mesh = meridian(if order == Order::P2 { grid.curved(0.05, 0.0) } else { grid }, 0.0, 1.0, 0.8);
        let mut c = Constraints::new(2 * mesh.num_nodes());
        c.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
        c.fix_group(&mesh, TOP, 1, |_| 0.0);
        let on_axis = fix_axis(&mesh, &mut c);
        assert!(on_axis >= 5, "{on_axis} axis nodes");
        let loads =
            Loads { body_force: None, edge_loads: vec![EdgeLoad { group: RIGHT, traction: Traction::Pressure(q) }] };
        let u = solve_banded(&mesh, &assemble_with(&mesh, &m, element, &c, &loads, 0..2 * mesh.num_nodes()));
        // u_r = C r, C = −q (1 + ν)(1 − 2ν)/E; σrr = σθθ = −q, σzz = −2νq.
        let slope = -q * (1.0 + m.poisson) * (1.0 - 2.0 * m.poisson) / m.young;
        let what = format!("{order:?} {element:?}");
        for (k, x) in mesh.nodes.iter().enumerate() {
            assert!((u[2 * k] - slope * x[0]).abs() < 1e-12 * slope.abs(), "{what}: u_r at {x:?}: {}", u[2 * k]);
            assert!(u[2 * k + 1].abs() < 1e-12 * slope.abs(), "{what}: u_z at {x:?}: {}", u[2 * k + 1]);
            if x[0] == 0.0 {
                assert_eq!(u[2 * k], 0.0, "{what}: axis node {k}");
            }
        }
        let (nodal, hoop) = nodal_stress(&mesh, &m, element, &u);
        for (k, x) in mesh.nodes.iter().enumerate() {
            let (s, h) = (nodal[k], hoop[k]);
            assert!(s.iter().all(|v| v.is_finite()) && h.is_finite(), "{what}: stress at {x:?}: {s:?} {h}");
            let expected = [-q, -2.0 * m.poisson * q, 0.0];
            for i in 0..3 {
                assert!(
                    (s[i] - expected[i]).abs() < 1e-9 * q,
                    "{what}: stress {i} at {x:?}: {} vs {}",
                    s[i],
                    expected[i]
                );
            }
            assert!((h + q).abs() < 1e-9 * q, "{what}: hoop stress at {x:?}: {h}");
        }
    }
}

/// The library's axisymmetric energy norms (`fem::postprocess`) equal this file's independent
/// one on Lamé's cylinder; the plane-only `energy_error` refuses (NaN) rather than drop the hoop
/// term; the nodal stresses of `fem::postprocess` match those of `mixed_pressure` (hoop strain in
/// σrr and σzz).
#[test]
fn axisymmetric_library_norms_match_the_independent_ones() {
    use signorini::fem::postprocess;
    let mesh = meridian(Grid::new(6, Order::P2).distorted(Distortion::Smooth(0.03)), INNER, OUTER - INNER, 0.5);
    let m = material(0.3);
    let mut c = Constraints::new(2 * mesh.num_nodes());
    c.fix_group(&mesh, BOTTOM, 1, |_| 0.0);
    c.fix_group(&mesh, TOP, 1, |_| 0.0);
    let loads =
        Loads { body_force: None, edge_loads: vec![EdgeLoad { group: LEFT, traction: Traction::Pressure(PRESSURE) }] };
    let u = solve_banded(&mesh, &assemble_with(&mesh, &m, Element::Lagrange, &c, &loads, 0..2 * mesh.num_nodes()));
    let exact = lame(&m);
    let ours = energy_error(&mesh, &m, &u, &exact);
    let library = postprocess::energy_error_with_displacement(&mesh, &m, &u, |x| {
        let t = exact(x);
        ([t[0], 0.0], [[t[1], 0.0], [0.0, t[2]]])
    });
    assert!((library - ours).abs() <= 1e-10 * ours, "library {library:e}, independent {ours:e}");
    let zero = vec![0.0; u.len()];
    let norm = energy_error(&mesh, &m, &u, |_| [0.0; 3]);
    let library_norm = postprocess::energy_norm(&mesh, &m, &u);
    assert!((library_norm - norm).abs() <= 1e-10 * norm, "library {library_norm:e}, independent {norm:e}");
    assert!(postprocess::energy_error(&mesh, &m, &zero, |_| [[0.0; 2]; 2]).is_nan());
    let (mixed, _) = nodal_stress(&mesh, &m, Element::Lagrange, &u);
    let plain = postprocess::nodal_stress(&mesh, &m, &u);
    for (a, b) in mixed.iter().zip(&plain) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= 1e-9 * PRESSURE, "{a:?} against {b:?}");
        }
    }
}
