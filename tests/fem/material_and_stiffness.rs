//! Hooke's law in plane strain and plane stress, and the element stiffness.

use crate::{curved_p2_triangle, steel};
use nalgebra::{DMatrix, DVector};
use signorini::fem::{element_stiffness, Material, PlaneModel};
use signorini::mesh::Order;

// ---------------------------------------------------------------------------------------------
// Material.
// ---------------------------------------------------------------------------------------------

#[test]
fn hooke_law_plane_strain_and_plane_stress() {
    let (e, nu) = (210.0e9, 0.3);
    let strain = Material::new(e, nu, PlaneModel::Strain);
    let stress = Material::new(e, nu, PlaneModel::Stress);
    let f = e / ((1.0 + nu) * (1.0 - 2.0 * nu));
    let cs = strain.elasticity();
    let expect = [[f * (1.0 - nu), f * nu, 0.0], [f * nu, f * (1.0 - nu), 0.0], [0.0, 0.0, f * (1.0 - 2.0 * nu) / 2.0]];
    let g = e / (1.0 - nu * nu);
    let cp = stress.elasticity();
    let expect_p = [[g, g * nu, 0.0], [g * nu, g, 0.0], [0.0, 0.0, g * (1.0 - nu) / 2.0]];
    for i in 0..3 {
        for j in 0..3 {
            assert!((cs[i][j] - expect[i][j]).abs() <= 1e-15 * f);
            assert!((cp[i][j] - expect_p[i][j]).abs() <= 1e-15 * g);
        }
    }
    for m in [strain, stress] {
        let (c, s) = (m.elasticity(), m.compliance());
        for i in 0..3 {
            for j in 0..3 {
                let p: f64 = (0..3).map(|k| c[i][k] * s[k][j]).sum();
                assert!((p - if i == j { 1.0 } else { 0.0 }).abs() < 1e-14, "C C^-1 != I for {:?}", m.plane);
            }
        }
        // w*(C e) = w(e) = ½ e·C e.
        let eps = [1e-3, -4e-4, 6e-4];
        let sig = m.stress(eps);
        let w = m.strain_energy_density(eps);
        assert!((m.complementary_energy_density(sig) - w).abs() < 1e-12 * w);
        let half_s_cinv_s: f64 =
            0.5 * (0..3).map(|i| (0..3).map(|j| sig[i] * s[i][j] * sig[j]).sum::<f64>()).sum::<f64>();
        assert!((m.complementary_energy_density(sig) - half_s_cinv_s).abs() < 1e-12 * w);
    }
    // σzz and von Mises.
    let s = [100.0, 40.0, 30.0];
    assert!((strain.sigma_zz(s) - 42.0).abs() < 1e-12);
    assert_eq!(stress.sigma_zz(s), 0.0);
    assert!((stress.von_mises([100.0, 0.0, 0.0]) - 100.0).abs() < 1e-12);
    assert!((stress.von_mises([0.0, 0.0, 50.0]) - 50.0 * 3f64.sqrt()).abs() < 1e-12);
    // Plane strain, equibiaxial: σzz = 2νσ, σ_vm = |σ − σzz|.
    assert!((strain.von_mises([10.0, 10.0, 0.0]) - 10.0 * (1.0 - 2.0 * nu)).abs() < 1e-12);
    let szz = strain.sigma_zz(s);
    let vm = (0.5 * ((s[0] - s[1]).powi(2) + (s[1] - szz).powi(2) + (szz - s[0]).powi(2)) + 3.0 * s[2] * s[2]).sqrt();
    assert!((strain.von_mises(s) - vm).abs() < 1e-12);
    // Complementary energy ½ σ : C⁻¹ σ, written out.
    let ws = (1.0 + nu) / (2.0 * e)
        * ((1.0 - nu) * (s[0] * s[0] + s[1] * s[1]) - 2.0 * nu * s[0] * s[1] + 2.0 * s[2] * s[2]);
    assert!((strain.complementary_energy_density(s) - ws).abs() < 1e-14 * ws);
    let wp = (s[0] * s[0] + s[1] * s[1] - 2.0 * nu * s[0] * s[1] + 2.0 * (1.0 + nu) * s[2] * s[2]) / (2.0 * e);
    assert!((stress.complementary_energy_density(s) - wp).abs() < 1e-14 * wp);
}

#[test]
fn material_check_rejects_bad_constants() {
    assert!(steel(PlaneModel::Strain).check().is_ok());
    assert!(Material::new(1.0, -0.99, PlaneModel::Stress).check().is_ok());
    for (e, nu, word) in [
        (0.0, 0.3, "Young"),
        (-1.0, 0.3, "Young"),
        (f64::NAN, 0.3, "Young"),
        (f64::INFINITY, 0.3, "Young"),
        (1.0, 0.5, "Poisson"),
        (1.0, -1.0, "Poisson"),
        (1.0, f64::NAN, "Poisson"),
    ] {
        let err = Material::new(e, nu, PlaneModel::Strain).check().expect_err("must be rejected");
        assert!(err.contains(word), "message for E={e}, nu={nu} should mention {word}: {err}");
    }
}

// ---------------------------------------------------------------------------------------------
// Element stiffness.
// ---------------------------------------------------------------------------------------------

fn check_element_stiffness(order: Order, x: &[[f64; 2]], what: &str) {
    let m = steel(PlaneModel::Strain);
    let n = 2 * order.nodes_per_cell();
    let k = DMatrix::from_row_slice(n, n, &element_stiffness(order, x, &m));
    let scale = k.amax();
    assert!((&k - k.transpose()).amax() <= 1e-14 * scale, "{what}: not symmetric");
    let mut eig: Vec<f64> = k.clone().symmetric_eigen().eigenvalues.iter().copied().collect();
    eig.sort_by(f64::total_cmp);
    let zero = 1e-10 * eig[n - 1];
    assert!(eig[0] > -zero, "{what}: negative eigenvalue {}", eig[0]);
    assert!(eig[..3].iter().all(|l| l.abs() < zero), "{what}: eigenvalues {eig:?}");
    assert!(eig[3] > 1e-4 * eig[n - 1], "{what}: more than 3 zero-energy modes: {eig:?}");
    // The rigid motions are in the kernel.
    for r in [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] {
        let v = DVector::from_iterator(n, x.iter().flat_map(|p| [r[0] - r[2] * p[1], r[1] + r[2] * p[0]]));
        assert!((&k * v).amax() < 1e-12 * scale, "{what}: rigid motion {r:?} has energy");
    }
}

#[test]
fn element_stiffness_is_symmetric_psd_with_three_rigid_modes() {
    check_element_stiffness(Order::P1, &[[0.1, 0.0], [1.3, 0.2], [0.4, 0.9]], "P1");
    let v = [[0.1, 0.0], [1.3, 0.2], [0.4, 0.9]];
    let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    let straight = [v[0], v[1], v[2], mid(v[0], v[1]), mid(v[1], v[2]), mid(v[2], v[0])];
    check_element_stiffness(Order::P2, &straight, "P2 straight");
    check_element_stiffness(Order::P2, &curved_p2_triangle(0.25), "P2 curved");
    // P1 against the closed form for the unit right triangle in plane stress, E = 1, ν = 0:
    // K = ½ [B^T C B] with C = diag(1, 1, ½).
    let m = Material::new(1.0, 0.0, PlaneModel::Stress);
    let k = element_stiffness(Order::P1, &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &m);
    #[rustfmt::skip]
    let expect = [
        0.75, 0.25, -0.5, -0.25, -0.25, 0.0,
        0.25, 0.75, 0.0, -0.25, -0.25, -0.5,
        -0.5, 0.0, 0.5, 0.0, 0.0, 0.0,
        -0.25, -0.25, 0.0, 0.25, 0.25, 0.0,
        -0.25, -0.25, 0.0, 0.25, 0.25, 0.0,
        0.0, -0.5, 0.0, 0.0, 0.0, 0.5,
    ];
    for i in 0..36 {
        assert!((k[i] - expect[i]).abs() < 1e-15, "entry {i}: {} vs {}", k[i], expect[i]);
    }
}
