//! `signorini run` on the axisymmetric Hertz sphere (`examples/scenes/hertz_sphere.toml`): the
//! example as shipped meets Hertz's closed form, and `mpirun -n 2` gives the serial answer.

use crate::mpi::serial_and_two_ranks;
use crate::{bin, relative_difference, report, run_ok, scene, scratch};

/// Hertz's sphere on a rigid plane (K. L. Johnson, Contact Mechanics, 1985, §4.2.1) for the
/// example's numbers: `(a, p0)` with `a = (3PR/4E*)^(1/3)`, `p0 = 3P/(2πa²)`, `P = q π R²`.
fn hertz_sphere() -> (f64, f64) {
    let (young, poisson, radius, q) = (210e9_f64, 0.3_f64, 0.1_f64, 1.2e7_f64);
    let estar = young / (1.0 - poisson * poisson);
    let load = q * std::f64::consts::PI * radius * radius;
    let a = (3.0 * load * radius / (4.0 * estar)).cbrt();
    (a, 3.0 * load / (2.0 * std::f64::consts::PI * a * a))
}

/// `(x, pressure, status)` of every row of a run's contact.csv.
fn contact_rows(dir: &std::path::Path) -> Vec<(f64, f64, String)> {
    let text = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (x, p, s) = (col("x"), col("pressure"), col("status"));
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[x].parse().unwrap(), f[p].parse().unwrap(), f[s].to_string())
        })
        .collect()
}

/// The example as shipped (4.3e3 dofs, cells a/10 at the pole): the pole's pressure within 1 %
/// of p0 (measured −0.27 %), the last loaded point within a cell of a (measured 4.962e-3 m
/// against 4.967e-3 m), the contact resultant equal to P and the independent check clean.
#[test]
fn example_hertz_sphere_meets_hertz() {
    let out = scratch("hertz-sphere-example");
    run_ok(bin().arg("run").arg(scene("examples/scenes/hertz_sphere.toml")).args(["--quiet", "--out"]).arg(&out));
    let (a, p0) = hertz_sphere();
    let rows = contact_rows(&out);
    let pole = rows.iter().find(|r| r.0 == 0.0).expect("the pole is a contact point");
    assert!((pole.1 / p0 - 1.0).abs() < 0.01, "pole pressure {:e} against p0 = {p0:e}", pole.1);
    let edge = rows.iter().filter(|r| r.1 > 1e-6 * p0).map(|r| r.0).fold(0.0, f64::max);
    assert!((edge - a).abs() < 1e-3 * 0.6, "last loaded point at r = {edge:e}, a = {a:e} (cells 5e-4 m)");
    let r = report(&out);
    let load = 1.2e7 * std::f64::consts::PI * 0.01;
    let resultant = r["contact"]["resultant"][1].as_f64().unwrap();
    assert!((resultant - load).abs() < 1e-9 * load, "contact resultant {resultant:e} against P = {load:e}");
    assert_eq!(r["plane"], "axisymmetric", "{}", r["plane"]);
}

/// `mpirun -n 2` on the example: the displacement field and the contact pressures equal the
/// serial ones (the P2 axis vertex, its extrapolated pressure and the floating body's
/// stabilisation are handled the same way on every rank).
#[test]
fn mpirun_two_ranks_hertz_sphere_equals_serial() {
    let file = scene("examples/scenes/hertz_sphere.toml");
    let (serial, parallel) = serial_and_two_ranks("hertz-sphere", "run", &file, &[]);
    assert_eq!(report(&parallel)["mpi_ranks"], 2);
    let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
    assert!(d < 1e-9, "MPI displacement differs from serial by {d:e}");
    let (a, b) = (contact_rows(&serial), contact_rows(&parallel));
    assert_eq!(a.len(), b.len());
    let peak = a.iter().map(|r| r.1).fold(0.0, f64::max);
    for (s, p) in a.iter().zip(&b) {
        assert_eq!(s.0, p.0);
        assert!((s.1 - p.1).abs() < 1e-9 * peak, "r = {:e}: pressure {:e} serial, {:e} on 2 ranks", s.0, s.1, p.1);
    }
}
