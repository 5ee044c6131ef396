//! `examples/scenes/pellet_cladding.toml` end to end (issue 27): the contact pressure of the
//! shrink fit against Lamé's closed form, the cladding's hoop stress (tensile) and the pellet's
//! (compressive) read back from the VTK files, and `mpirun -n 2` equal to the serial run.

use crate::mpi::serial_and_two_ranks;
use crate::{bin, python, relative_difference, report, run_ok, scene, scratch};

/// The shrink-fit pressure on the tube's bore (b = 4.18 mm, c = 4.75 mm, Zircaloy) pressed by
/// the pellet (b' = 4.19 mm, UO2, solid), `ε_z = 0`, each cylinder in its own geometry, equal
/// ring forces (tests/petsc_cases/axisymmetric_bodies.rs derives it): 3.13582e7 Pa.
fn shrink_fit_pressure() -> f64 {
    let (b, bp, c) = (4.18e-3f64, 4.19e-3f64, 4.75e-3f64);
    let ((ec, nc), (ep, np)) = ((9.9e10, 0.37), (2e11, 0.3));
    let tube = b * (1.0 + nc) / ec * ((1.0 - 2.0 * nc) * b * b + c * c) / (c * c - b * b);
    let pellet = (b / bp) * bp * (1.0 + np) * (1.0 - 2.0 * np) / ep;
    (bp - b) / (tube + pellet)
}

/// Every contact point's pressure in contact.csv within 0.1 % of the closed form (measured
/// 3.8e-4); the cladding's hoop stress (VTK `stress` ZZ, σθθ in axisymmetry) positive
/// everywhere and Lamé's `p (b² + c²)/(c² − b²)` = 246.6 MPa at the bore within 1 %; the
/// pellet's hoop stress `−p b/b'` everywhere within 1 % (its axis included: no NaN at r = 0).
#[test]
fn example_pellet_cladding_is_a_shrink_fit() {
    let out = scratch("pellet-cladding");
    run_ok(bin().arg("run").arg(scene("examples/scenes/pellet_cladding.toml")).args(["--quiet", "--out"]).arg(&out));
    let p = shrink_fit_pressure();
    assert!((p / 3.13582e7 - 1.0).abs() < 1e-5, "closed form {p:e}");
    let csv = std::fs::read_to_string(out.join("contact.csv")).unwrap();
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header.iter().position(|&h| h == "pressure").unwrap();
    let pressures: Vec<f64> = lines.map(|l| l.split(',').nth(column).unwrap().parse().unwrap()).collect();
    assert!(pressures.len() > 10, "{csv}");
    for q in &pressures {
        assert!((q / p - 1.0).abs() < 1e-3, "contact pressure {q:e} against the shrink fit's {p:e}");
    }
    let (b, bp, c) = (4.18e-3f64, 4.19e-3f64, 4.75e-3f64);
    let hoop_bore = p * (b * b + c * c) / (c * c - b * b);
    let s = python(&format!(
        "t = meshio.read(r'{}')\nh = t.point_data['stress'][:, 2]\nbore = np.abs(t.points[:, 0] - {b:?}) < 1e-9\n\
         pellet = meshio.read(r'{}').point_data['stress'][:, 2]\n\
         print(float(h.min()), float(np.max(np.abs(h[bore] / {hoop_bore:?} - 1))), bool(np.all(np.isfinite(pellet))), \
         float(np.max(np.abs(pellet / {:?} + 1))))",
        out.join("cladding.vtu").display(),
        out.join("pellet.vtu").display(),
        p * b / bp
    ));
    let v: Vec<&str> = s.split_whitespace().collect();
    let (min_hoop, bore, finite, pellet): (f64, f64, &str, f64) =
        (v[0].parse().unwrap(), v[1].parse().unwrap(), v[2], v[3].parse().unwrap());
    assert!(min_hoop > 0.0, "the cladding's hoop stress must be tensile everywhere: min {min_hoop:e}");
    assert!(bore < 1e-2, "hoop stress at the bore {bore:e} from Lamé's {hoop_bore:e}");
    assert!(finite == "True" && pellet < 1e-2, "pellet hoop stress: finite {finite}, deviation {pellet:e}");
}

/// `mpirun -n 2` on the example: the same displacement field and contact pressures as serial.
#[test]
fn mpirun_two_ranks_pellet_cladding_equals_serial() {
    let file = scene("examples/scenes/pellet_cladding.toml");
    let (serial, parallel) = serial_and_two_ranks("pellet-cladding", "run", &file, &[]);
    assert_eq!(report(&parallel)["mpi_ranks"], 2);
    let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
    assert!(d < 1e-10, "displacements differ by {d:e}");
    let pressures = |dir: &std::path::Path| -> Vec<f64> {
        let csv = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
        csv.lines().skip(1).map(|l| l.split(',').nth(3).unwrap().parse().unwrap()).collect()
    };
    let (a, b) = (pressures(&serial), pressures(&parallel));
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-9 * x.abs(), "pressures {x:e} and {y:e}");
    }
}
