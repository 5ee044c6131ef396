//! Elements and formulations: the P2–P0 element, the dual (HCT) formulation and its
//! saddle-point route, and the error estimate.

use crate::edit::Edit;

use crate::{bin, mpirun_two, python, relative_difference, report, run_err, run_ok, scene, scratch};

#[test]
fn p2p0_element_reported_exact_on_the_patch_and_equal_under_mpi() {
    // The patch test at ν = 0.4999 with the locking-free P2–P0 element: report.json names the
    // element, solution.vtu holds the exact uniform stress (σzz = −ν/(1−ν) p from the cell
    // pressures), and two MPI ranks give the serial answer.
    let (nu, p) = (0.4999_f64, 1e6_f64);
    let side = nu / (1.0 - nu) * p;
    let dir = scratch("p2p0");
    let text = std::fs::read_to_string(scene("examples/scenes/patch_test.toml"))
        .unwrap()
        .edit("order = 1", "order = 2\nelement = \"p2p0\"")
        .edit("poisson = 0.2", &format!("poisson = {nu}"))
        .edit("pressure = 2.5e5", &format!("pressure = {side:e}"));
    let path = dir.join("patch.toml");
    std::fs::write(&path, text).unwrap();
    let serial = dir.join("serial");
    run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&serial));
    assert_eq!(report(&serial)["element"], "P2-P0");
    let out = python(&format!(
        "s = meshio.read(r'{}').point_data['stress']\nprint(max(np.abs(s[:, 0] + {side:e}).max(), np.abs(s[:, 1] + {p:e}).max(), np.abs(s[:, 2] + {side:e}).max(), np.abs(s[:, 3]).max()) / {p:e})",
        serial.join("solution.vtu").display()
    ));
    let err: f64 = out.trim().parse().unwrap();
    assert!(err < 1e-6, "P2-P0 patch stress error {err:e} (relative to p)");
    let parallel = dir.join("parallel");
    let out = mpirun_two()
        .arg("run")
        .arg(&path)
        .args(["--quiet", "--out"])
        .arg(&parallel)
        .output()
        .expect("mpirun (openmpi-bin, installed by ./setup.sh)");
    assert!(out.status.success(), "mpirun failed: {}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(report(&parallel)["element"], "P2-P0");
    let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
    assert!(d < 1e-8, "P2-P0: MPI answer differs from serial by {d:e}");
}

#[test]
fn dual_formulation_run_writes_stresses_and_its_check() {
    let dir = scratch("dual");
    run_ok(
        bin()
            .arg("run")
            .arg(scene("examples/scenes/patch_test.toml"))
            .args(["--quiet", "--formulation", "dual", "--out"])
            .arg(&dir),
    );
    let r = report(&dir);
    assert_eq!(r["formulation"], "dual");
    assert_eq!(r["element"], "HCT");
    assert!(r.get("results").is_none(), "a dual-only run has no displacement results: {r}");
    let d = &r["dual"];
    for key in ["traction_residual", "interior_equilibrium", "stress_jump"] {
        assert!(d["check"][key].as_f64().unwrap() < 1e-10, "{key}: {d}");
    }
    // The patch test's exact stresses, read back by meshio.
    let out = python(&format!(
        "m = meshio.read(r'{}')\ns = m.point_data['stress']\nprint(np.abs(s[:, 0] + 2.5e5).max() / 1e6, np.abs(s[:, 1] + 1e6).max() / 1e6, np.abs(s[:, 3]).max() / 1e6)",
        dir.join("solution.vtu").display()
    ));
    for v in out.split_whitespace() {
        assert!(v.parse::<f64>().unwrap() < 1e-11, "stress error {out}");
    }
}

#[test]
fn dual_saddle_point_route_serial_mpi_and_its_own_options() {
    let cantilever = scene("examples/scenes/cantilever.toml");
    let eliminated = scratch("kkt-eliminated");
    run_ok(bin().arg("run").arg(&cantilever).args(["--quiet", "--estimate", "--out"]).arg(&eliminated));
    let reference = report(&eliminated)["estimate"]["relative_percent"].as_f64().unwrap();
    assert_eq!(report(&eliminated)["dual"]["constraints"], "eliminated");
    // Multipliers with MUMPS LDLᵀ: the same estimate; the scene's primal options (cg + gamg)
    // do not reach the dual, which reads -dual_*.
    let kkt = scratch("kkt-serial");
    run_ok(
        bin()
            .arg("run")
            .arg(&cantilever)
            .args(["--quiet", "--estimate", "--dual-constraints", "multipliers", "--out"])
            .arg(&kkt),
    );
    let r = report(&kkt);
    assert_eq!(r["dual"]["constraints"], "multipliers");
    assert!(r["dual"]["saddle_point_size"].as_u64().unwrap() > r["dual"]["unknowns"].as_u64().unwrap());
    assert_eq!(r["dual"]["solver"]["factor_package"], "mumps", "{}", r["dual"]["solver"]);
    let e = r["estimate"]["relative_percent"].as_f64().unwrap();
    assert!((e - reference).abs() < 1e-9 * reference, "{e} vs {reference}");
    // SYMMLQ + Jacobi through the dual's own prefix, the primal untouched.
    let symmlq = scratch("kkt-symmlq");
    run_ok(
        bin()
            .arg("run")
            .arg(&cantilever)
            .args(["--quiet", "--estimate", "--dual-constraints", "multipliers", "--out"])
            .arg(&symmlq)
            .args(["-dual_ksp_type", "symmlq", "-dual_pc_type", "jacobi", "-dual_ksp_max_it", "100000"]),
    );
    let r = report(&symmlq);
    assert_eq!(r["dual"]["solver"]["ksp_type"], "symmlq");
    assert_eq!(r["solver"]["pc_type"], "gamg");
    let e = r["estimate"]["relative_percent"].as_f64().unwrap();
    assert!((e - reference).abs() < 1e-6 * reference, "{e} vs {reference}");
    // Two MPI ranks: the same estimate.
    let parallel = scratch("kkt-mpi");
    let out = mpirun_two()
        .arg("run")
        .arg(&cantilever)
        .args(["--quiet", "--estimate", "--dual-constraints", "multipliers", "--out"])
        .arg(&parallel)
        .output()
        .expect("mpirun (openmpi-bin, installed by ./setup.sh)");
    assert!(out.status.success(), "mpirun failed: {}", String::from_utf8_lossy(&out.stderr));
    let e = report(&parallel)["estimate"]["relative_percent"].as_f64().unwrap();
    assert!((e - reference).abs() < 1e-8 * reference, "MPI {e} vs serial {reference}");
    // A wrong value is a usage error naming the choices.
    let msg = run_err(bin().arg("run").arg(&cantilever).args(["--dual-constraints", "lagrange"]), 2);
    assert!(msg.contains("eliminated") && msg.contains("multipliers"), "{msg}");
}

#[test]
fn estimate_reports_the_error_per_cell_and_in_total() {
    let dir = scratch("estimate");
    run_ok(
        bin()
            .arg("run")
            .arg(scene("examples/scenes/cantilever.toml"))
            .args(["--quiet", "--estimate", "--out"])
            .arg(&dir),
    );
    let r = report(&dir);
    let e = &r["estimate"];
    let (error, relative) = (e["error"].as_f64().unwrap(), e["relative_percent"].as_f64().unwrap());
    assert!(error > 0.0 && relative > 1.0 && relative < 50.0, "{e}");
    assert_eq!(e["kind"], "guaranteed_bound");
    // The dual solve and the estimate do work: their times are positive, the ones of the
    // run's timings, and the run's phases add up to its total.
    for (key, phase) in [("primal_seconds", "solve"), ("dual_seconds", "dual"), ("estimate_seconds", "estimate")] {
        let seconds = e[key].as_f64().unwrap();
        assert!(seconds > 0.0 && seconds == r["timings"][phase].as_f64().unwrap(), "{key}: {e} vs {}", r["timings"]);
    }
    let timings = r["timings"].as_object().unwrap();
    let sum: f64 = timings.iter().filter(|(k, _)| *k != "total").map(|(_, v)| v.as_f64().unwrap()).sum();
    let total = timings["total"].as_f64().unwrap();
    assert!((sum - total).abs() <= 1e-9 * total, "phases add up to {sum}, total {total}");
    // The cell data `error` squares up to the total.
    let out = python(&format!(
        "m = meshio.read(r'{}')\ne = np.concatenate([np.asarray(c, dtype=float) for c in m.cell_data['error']])\nprint(np.sqrt((e ** 2).sum()))",
        dir.join("solution.vtu").display()
    ));
    let total: f64 = out.trim().parse().unwrap();
    assert!((total - error).abs() <= 1e-9 * error, "{total} vs {error}");
    // Without --estimate no dual solve runs.
    let dir = scratch("no-estimate");
    run_ok(bin().arg("run").arg(scene("examples/scenes/cantilever.toml")).args(["--quiet", "--out"]).arg(&dir));
    let r = report(&dir);
    assert!(r.get("estimate").is_none() && r.get("dual").is_none() && r["timings"].get("dual").is_none(), "{r}");
}

#[test]
fn dual_solves_contact_scenes_and_refuses_point_supports_that_carry_force() {
    // The default scene (the square block) in the dual: its corner point is dropped with a
    // note, the contact is solved and reported under `contact`.
    let dir = scratch("dual-contact");
    run_ok(bin().args(["run", "--quiet", "--formulation", "dual", "--out"]).arg(&dir));
    let r = report(&dir);
    assert_eq!(r["formulation"], "dual");
    let notes = r["dual"]["notes"].to_string();
    assert!(notes.contains("point support at (0.04, 0) dropped"), "{notes}");
    // The stress field is statically admissible (the dual's own check, to round-off) ...
    for key in ["interior_equilibrium", "stress_jump"] {
        assert!(r["dual"]["check"][key].as_f64().unwrap() < 1e-10, "{key}: {}", r["dual"]["check"]);
    }
    // (measured 2.4e-10 on the square block: the traction residual on 64 loaded edges)
    assert!(r["dual"]["check"]["traction_residual"].as_f64().unwrap() < 1e-9, "{}", r["dual"]["check"]);
    // ... and the contact carries the whole vertical load, 5e7 Pa on the 0.04 m top (the
    // dropped corner support carries nothing in the dual).
    let c = &r["contact"];
    let n = c["normal_resultant"].as_f64().unwrap();
    assert!((n + 5e7 * 0.04).abs() <= 1e-9 * 5e7 * 0.04, "normal resultant {n} vs the top load 2e6");
    assert!(c["peak_pressure"]["pressure"].as_f64().unwrap() > 0.0, "{c}");
    assert!(c["stick"].as_u64().unwrap() > 0 && c["slip"].as_u64().unwrap() > 0, "{c}");
    // A point support that carries a force: the estimate refuses to compare different problems.
    let dir = scratch("point-force");
    let path = dir.join("s.toml");
    std::fs::write(
        &path,
        "[mesh]\nshape = \"rectangle\"\nsize = [2.0, 1.0]\ncell_size = 0.25\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n\
         [[traction]]\npart = \"top\"\ntraction = [0.0, -1e5]\n\n[[dirichlet]]\npart = \"left\"\nux = 0.0\n\n\
         [[dirichlet]]\npoint = [0.0, 0.0]\nuy = 0.0\n",
    )
    .unwrap();
    let msg = run_err(bin().arg("run").arg(&path).args(["--quiet", "--estimate", "--out"]).arg(dir.join("out")), 1);
    assert!(msg.contains("point support") && msg.contains("hint"), "{msg}");
}
