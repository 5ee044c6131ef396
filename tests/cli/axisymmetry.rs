//! `signorini run` on bodies of revolution (`plane = "axisymmetric"`): what it refuses and how it
//! says so (a mesh across the axis, a radial displacement prescribed on the axis, a body free to
//! slide along the axis, the dual formulation, the estimate, mesh adaptation, interface laws),
//! and that the summary and `report.json` say the forces are for the full revolution.

use crate::{bin, report, run_err, run_ok, scratch};

/// A thick tube `r ∈ [r0, r0 + 1]`, `z ∈ [0, 0.25]`, pressed inside; `extra` is appended.
fn tube(dir: &std::path::Path, r0: f64, extra: &str) -> std::path::PathBuf {
    let file = dir.join("tube.toml");
    std::fs::write(
        &file,
        format!(
            "title = \"tube\"\n[mesh]\nshape = \"rectangle\"\norigin = [{r0:?}, 0.0]\nsize = [1.0, 0.25]\ncell_size = 0.125\n\
             [material]\nyoung = 2e11\npoisson = 0.3\nplane = \"axisymmetric\"\n\
             [[dirichlet]]\npart = \"bottom\"\nuy = 0.0\n[[traction]]\npart = \"left\"\npressure = 1e8\n{extra}"
        ),
    )
    .unwrap();
    file
}

/// The Lamé tube of the smoke check: `u_r(a)` is the closed form, forces are for the whole
/// circumference (the inner pressure's resultant is `p 2π a h` in r), the summary says so.
#[test]
fn axisymmetric_forces_are_for_the_full_revolution() {
    let dir = scratch("axi-forces");
    let file = tube(&dir, 1.0, "[[dirichlet]]\npart = \"top\"\nuy = 0.0\n[discretization]\norder = 2\n");
    let out = run_ok(bin().arg("run").arg(&file).arg("--out").arg(dir.join("out")));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("plane axisymmetric"), "{stdout}");
    assert!(stdout.contains("axial forces (N, full revolution): applied 0, reactions bottom"), "{stdout}");
    let r = report(&dir.join("out"));
    assert_eq!(r["plane"], "axisymmetric");
    assert_eq!(r["forces"], "full revolution");
    let applied = r["results"]["applied_force"][0].as_f64().unwrap();
    let expected = 1e8 * 2.0 * std::f64::consts::PI * 1.0 * 0.25;
    assert!((applied - expected).abs() < 1e-9 * expected, "applied {applied:e}, expected {expected:e}");
    // Lamé, ε_z = 0: u_r(a) = A a + B / a (see docs/validation.md).
    let (e, nu, p, a, b) = (2e11, 0.3, 1e8, 1.0f64, 2.0f64);
    let big_a = p * a * a * (1.0 + nu) * (1.0 - 2.0 * nu) / (e * (b * b - a * a));
    let big_b = p * a * a * b * b * (1.0 + nu) / (e * (b * b - a * a));
    let max_u = r["results"]["max_displacement"].as_f64().unwrap();
    let exact = big_a * a + big_b / a;
    assert!((max_u - exact).abs() < 1e-3 * exact, "u_r(a) = {max_u:e}, Lamé {exact:e}");
}

/// A node at r < 0: `Error::Mesh` naming the node and what to do, nothing written.
#[test]
fn axisymmetric_mesh_across_the_axis_is_refused() {
    let dir = scratch("axi-negative-r");
    let file = tube(&dir, -0.5, "");
    let err = run_err(bin().arg("run").arg(&file).arg("--out").arg(dir.join("out")), 1);
    for word in ["node", "r = x", "< 0", "meridian half-plane", "x >= 0"] {
        assert!(err.contains(word), "`{word}` missing from: {err}");
    }
    assert!(!dir.join("out").join("report.json").exists());
}

/// A nonzero radial displacement prescribed on the axis would tear it open.
#[test]
fn axisymmetric_radial_displacement_on_the_axis_is_refused() {
    let dir = scratch("axi-ux-axis");
    let file = tube(&dir, 0.0, "[[dirichlet]]\npart = \"left\"\nux = 1e-3\n");
    let err = run_err(bin().arg("run").arg(&file).arg("--out").arg(dir.join("out")), 1);
    for word in ["on the axis", "ux = 1e-3", "cannot move radially", "remove ux"] {
        assert!(err.contains(word), "`{word}` missing from: {err}");
    }
}

/// Without any uy fixed, a body of revolution slides along its axis: the one rigid motion.
#[test]
fn axisymmetric_body_free_along_the_axis_is_refused() {
    let dir = scratch("axi-free-z");
    let file = dir.join("free.toml");
    std::fs::write(
        &file,
        "[mesh]\nshape = \"rectangle\"\norigin = [0.0, 0.0]\nsize = [1.0, 1.0]\ncell_size = 0.25\n\
         [material]\nyoung = 2e11\npoisson = 0.3\nplane = \"axisymmetric\"\n\
         [[dirichlet]]\npart = \"right\"\nux = 0.0\n",
    )
    .unwrap();
    let err = run_err(bin().arg("run").arg(&file).arg("--out").arg(dir.join("out")), 1);
    for word in ["1 rigid motion free", "translation in z", "fix uy"] {
        assert!(err.contains(word), "`{word}` missing from: {err}");
    }
}

/// The dual formulation, the estimate and mesh adaptation stop before any work, saying why.
#[test]
fn axisymmetric_refuses_the_dual_the_estimate_and_adaptation() {
    let dir = scratch("axi-refusals");
    let file = tube(&dir, 1.0, "");
    for flags in [&["--estimate"][..], &["--formulation", "dual"][..]] {
        let err = run_err(bin().arg("run").arg(&file).args(flags).args(["--quiet", "--out"]).arg(dir.join("out")), 1);
        for word in
            ["body of revolution", "Airy stress function", "plane equilibrium", "tube.toml", "without --estimate"]
        {
            assert!(err.contains(word), "{flags:?}: `{word}` missing from: {err}");
        }
        assert!(!dir.join("out").join("report.json").exists(), "{flags:?}: nothing is written");
    }
    let err =
        run_err(bin().arg("adapt").arg(&file).args(["--target", "5", "--quiet", "--out"]).arg(dir.join("adapt")), 1);
    assert!(err.contains("mesh adaptation") && err.contains("body of revolution"), "{err}");
}

/// An interface law on an axisymmetric scene is refused by name.
#[test]
fn axisymmetric_refuses_interface_laws() {
    let dir = scratch("axi-interface");
    let file = tube(
        &dir,
        1.0,
        "[contact]\npart = \"right\"\nobstacle = \"line\"\npoint = [2.01, 0.0]\nnormal = [-1.0, 0.0]\nfriction = \"none\"\n\
         [contact.interface]\nlaw = \"thin_layer\"\nyoung = 1e9\npoisson = 0.3\nthickness = 1e-3\nbonded = false\n",
    );
    let err = run_err(bin().arg("run").arg(&file).args(["--quiet", "--out"]).arg(dir.join("out")), 1);
    for word in ["thin_layer", "plane interfaces", "axisymmetric", "tube.toml:"] {
        assert!(err.contains(word), "`{word}` missing from: {err}");
    }
}

/// A solid cylinder held along its axis by friction on a rigid plane only, pressed and then
/// squeezed radially along a load path: the axial contact resultant is the press `q π R²` at
/// every increment, `history.csv` names its columns in N and J, the summary gives the axial
/// resultant only.
#[test]
fn axisymmetric_load_path_on_a_body_held_by_the_contact() {
    let dir = scratch("axi-path");
    let file = dir.join("path.toml");
    std::fs::write(
        &file,
        "[mesh]\nshape = \"rectangle\"\nsize = [0.02, 0.04]\ncell_size = 2.5e-3\nmesher = \"structured\"\n\
         [material]\nyoung = 1.3e11\npoisson = 0.2\nplane = \"axisymmetric\"\n\
         [[traction]]\npart = \"top\"\npressure = 5e7\nname = \"press\"\n\
         [[traction]]\npart = \"right\"\npressure = 1.5e8\nname = \"push\"\n\
         [contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
         friction = \"coulomb\"\nmu = 0.3\nsolver = \"newton\"\n\
         [evolution]\nsteps = 8\n[evolution.factor]\npress = [[0, 0], [1, 1], [2, 1]]\npush = [[0, 0], [1, 0], [2, 1]]\n",
    )
    .unwrap();
    let out = run_ok(bin().arg("run").arg(&file).arg("--out").arg(dir.join("out")));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("axial resultant 6.2832e4 N, full revolution"), "{stdout}");
    let csv = std::fs::read_to_string(dir.join("out").join("history.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    assert!(header.contains(&"contact_y_N") && header.contains(&"work_J"), "{header:?}");
    assert!(!header.iter().any(|h| h.contains("per_m")), "{header:?}");
    let column = header.iter().position(|h| *h == "contact_y_N").unwrap();
    let press = 5e7 * std::f64::consts::PI * 0.02 * 0.02;
    for (k, line) in csv.lines().skip(1).enumerate() {
        let fy: f64 = line.split(',').nth(column).unwrap().parse().unwrap();
        let expected = press * ((k + 1) as f64 / 4.0).min(1.0);
        assert!((fy - expected).abs() < 1e-9 * press, "increment {}: {fy:e} against {expected:e}", k + 1);
    }
}

/// A tube (no node on the axis) pressed on a frictionless rigid plane, held along z by the
/// contact alone: the floating-body handling of every route that has one gives the exact
/// uniaxial state, `σzz = −q` everywhere (von Mises `q`), the contact resultant `q π (r1² − r0²)`.
#[test]
fn axisymmetric_floating_tube_is_uniaxial_on_every_route() {
    let dir = scratch("axi-floating-tube");
    let file = dir.join("tube.toml");
    std::fs::write(
        &file,
        "[mesh]\nshape = \"rectangle\"\norigin = [0.01, 0.0]\nsize = [0.01, 0.04]\ncell_size = 2.5e-3\nmesher = \"structured\"\n\
         [material]\nyoung = 1.3e11\npoisson = 0.2\nplane = \"axisymmetric\"\n\
         [[traction]]\npart = \"top\"\npressure = 5e7\n\
         [contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\nfriction = \"none\"\n",
    )
    .unwrap();
    let load = 5e7 * std::f64::consts::PI * (0.02 * 0.02 - 0.01 * 0.01);
    for solver in ["newton_full", "newton", "snes_vi"] {
        let out = dir.join(solver);
        run_ok(bin().arg("run").arg(&file).args(["--quiet", "--contact-solver", solver, "--out"]).arg(&out));
        let r = report(&out);
        let von_mises = r["results"]["max_von_mises"].as_f64().unwrap();
        assert!((von_mises - 5e7).abs() < 1e-6 * 5e7, "{solver}: max von Mises {von_mises:e}");
        let axial = r["contact"]["resultant"][1].as_f64().unwrap();
        assert!((axial - load).abs() < 1e-9 * load, "{solver}: axial resultant {axial:e} against {load:e}");
    }
}
