//! `signorini run` on a scene with `[evolution]`: the increments' files, the history and its
//! plots, the report's steps, the estimate at every increment, refusals, and `mpirun -n 2`.

use crate::{bin, mpirun_two, python, relative_difference, report, run_err, run_ok, scene, scratch};

/// The press-then-push square block, its mesh coarsened (16 cells a side) for speed.
fn press_then_push(dir: &std::path::Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(scene("examples/scenes/square_block_press_then_push.toml")).unwrap();
    assert!(text.contains("cell_size = 1.25e-3"), "test bug: the example's cell size changed");
    let path = dir.join("press_then_push.toml");
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(&path, text.replace("cell_size = 1.25e-3", "cell_size = 2.5e-3")).unwrap();
    path
}

#[test]
fn load_path_writes_increments_history_and_plots() {
    let dir = scratch("load-path-run");
    let scene_file = press_then_push(&dir.join("scene"));
    let out = dir.join("out");
    let run = run_ok(bin().arg("run").arg(&scene_file).arg("--out").arg(&out));
    let stdout = String::from_utf8_lossy(&run.stdout);
    // Every increment is a file, listed in solution.pvd with its time, and reads back in meshio.
    let pvd = std::fs::read_to_string(out.join("solution.pvd")).unwrap();
    for k in 1..=8 {
        let name = format!("steps/solution_{k:04}.vtu");
        assert!(out.join(&name).exists() && pvd.contains(&name), "{name} missing:\n{pvd}");
    }
    let read = python(&format!(
        "m = meshio.read(r'{}')\nprint(m.point_data['displacement'].shape[0] == len(m.points))",
        out.join("steps/solution_0008.vtu").display()
    ));
    assert_eq!(read.trim(), "True");
    // report.json: one step per increment, with its time, counts, residual and dissipation.
    let r = report(&out);
    let steps = r["steps"].as_array().expect("steps");
    assert_eq!(steps.len(), 8);
    assert_eq!(steps[3]["time"], 1.0);
    for s in steps {
        assert!(s["worst_residual"].as_f64().unwrap() < 1e-6, "{s}");
        assert!(s["dissipation"].as_f64().unwrap() >= -1e-9, "{s}");
    }
    // Friction has memory: nothing slips while only pressed... then the push makes it slip.
    assert!(steps[7]["slip"].as_u64().unwrap() > 0, "{}", steps[7]);
    assert!(r["load_path"]["energy"]["relative_residual"].as_f64().unwrap() < 1e-8, "{}", r["load_path"]);
    // history.csv: a header and one row per increment; the plots.
    let csv = std::fs::read_to_string(out.join("history.csv")).unwrap();
    assert_eq!(csv.lines().count(), 9, "{csv}");
    for plot in ["hysteresis.svg", "contact_profiles.svg"] {
        assert!(std::fs::read_to_string(out.join(plot)).unwrap().contains("<svg"), "{plot}");
    }
    // The summary names the path.
    assert!(stdout.contains("increments"), "{stdout}");
    // A second run into the same directory first removes the increments of the first.
    std::fs::write(out.join("steps/solution_0099.vtu"), "stale").unwrap();
    run_ok(bin().arg("run").arg(&scene_file).args(["--quiet", "--out"]).arg(&out));
    assert!(!out.join("steps/solution_0099.vtu").exists(), "a stale increment survived");
}

#[test]
fn load_path_estimate_at_every_increment() {
    let dir = scratch("load-path-estimate");
    let scene_file = press_then_push(&dir.join("scene"));
    // The corner point support carries force: the dual refuses it. Without it (as in
    // square_block_tresca.toml) the estimate runs at every increment.
    let text = std::fs::read_to_string(&scene_file).unwrap();
    let corner = "[[dirichlet]]\npoint = [0.04, 0.0]      # the lower-right corner\nux = 0.0\nuy = 0.0\n";
    assert!(text.contains(corner), "test bug: the corner support changed");
    std::fs::write(&scene_file, text.replace(corner, "")).unwrap();
    let out = dir.join("out");
    run_ok(bin().arg("run").arg(&scene_file).args(["--quiet", "--estimate", "--out"]).arg(&out));
    let r = report(&out);
    let steps = r["steps"].as_array().unwrap();
    assert!(steps.iter().all(|s| s["estimate_percent"].as_f64().is_some_and(|e| e > 0.0 && e < 50.0)), "{steps:?}");
    assert!(r["estimate"]["relative_percent"].as_f64().is_some(), "the last increment's estimate");
}

#[test]
fn load_path_refusals_name_what_to_do() {
    let dir = scratch("load-path-refusals");
    let scene_file = press_then_push(&dir.join("scene"));
    let err = run_err(
        bin().arg("run").arg(&scene_file).args(["--quiet", "--formulation", "dual", "--out"]).arg(dir.join("a")),
        1,
    );
    assert!(err.contains("load path") && err.contains("primal"), "{err}");
    let text = std::fs::read_to_string(&scene_file).unwrap().replace("solver = \"newton\"", "solver = \"snes_vi\"");
    let vi = dir.join("vi.toml");
    std::fs::write(&vi, text.replace("friction = \"coulomb\"\nmu = 1.0", "friction = \"none\"")).unwrap();
    let err = run_err(bin().arg("run").arg(&vi).args(["--quiet", "--out"]).arg(dir.join("b")), 1);
    assert!(err.contains("snes_vi") && err.contains("newton"), "{err}");
    // A moving rigid obstacle of one of several bodies.
    let base = std::fs::read_to_string(scene("examples/scenes/block_on_block.toml")).unwrap();
    let at = base.find("[[contact_pair]]").expect("block_on_block.toml has a pair");
    let moving = format!(
        "{}[body.contact]\npart = \"left\"\nobstacle = \"line\"\npoint = [-0.03, 0.0]\nnormal = [1.0, 0.0]\n\
         motion = [1e-5, 0.0]\nname = \"slide\"\n\n{}\n[evolution]\nsteps = 2\n[evolution.factor]\nslide = [[0, 0], [1, 1]]\n",
        &base[..at],
        &base[at..]
    );
    let bodies = dir.join("moving_obstacle.toml");
    std::fs::write(&bodies, moving).unwrap();
    let err = run_err(bin().arg("run").arg(&bodies).args(["--quiet", "--out"]).arg(dir.join("c")), 1);
    assert!(err.contains("moves (`motion`)") && err.contains("one body"), "{err}");
}

#[test]
fn mpirun_two_ranks_load_path_equals_serial() {
    let dir = scratch("mpi-load-path");
    let scene_file = press_then_push(&dir.join("scene"));
    let serial = dir.join("serial");
    run_ok(bin().arg("run").arg(&scene_file).args(["--quiet", "--out"]).arg(&serial));
    let parallel = dir.join("parallel");
    let out =
        mpirun_two().arg("run").arg(&scene_file).args(["--quiet", "--out"]).arg(&parallel).output().expect("mpirun");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    for k in [4, 8] {
        let name = format!("steps/solution_{k:04}.vtu");
        let d = relative_difference(&serial.join(&name), &parallel.join(&name));
        assert!(d < 1e-10, "increment {k}: MPI differs from serial by {d:e}");
    }
    let (a, b) = (report(&serial), report(&parallel));
    assert_eq!(b["mpi_ranks"], 2);
    let total = a["steps"][7]["total_dissipation"].as_f64().unwrap();
    assert!(total > 0.0, "the push dissipates");
    for k in 0..8 {
        assert_eq!(a["steps"][k]["stick"], b["steps"][k]["stick"], "increment {}", k + 1);
        let (da, db) = (a["steps"][k]["dissipation"].as_f64().unwrap(), b["steps"][k]["dissipation"].as_f64().unwrap());
        assert!((da - db).abs() <= 1e-10 * total, "increment {}: dissipation {da} / {db}", k + 1);
    }
}

/// `examples/scenes/fretting_cylinder.toml` as shipped: the tangential load goes through its
/// cycle (Q at the two positive peaks equal, at the negative one opposite, within 1 %), the
/// cycle dissipates, and the loop and the profiles are drawn.
#[test]
fn example_fretting_cylinder_runs_its_cycle() {
    let out = scratch("fretting-example");
    run_ok(bin().arg("run").arg(scene("examples/scenes/fretting_cylinder.toml")).args(["--quiet", "--out"]).arg(&out));
    let r = report(&out);
    let steps = r["steps"].as_array().unwrap();
    let q = |t: f64| {
        let s = steps.iter().find(|s| (s["time"].as_f64().unwrap() - t).abs() < 1e-12).expect("a peak increment");
        s["tangential_resultant"].as_f64().unwrap()
    };
    let (first, reversed, again) = (q(2.0), q(4.0), q(6.0));
    assert!(first.abs() > 0.0 && ((again - first) / first).abs() < 0.01, "Q* {first}, again {again}");
    assert!(((reversed + first) / first).abs() < 0.01, "Q* {first}, reversed {reversed}");
    assert!(steps.last().unwrap()["total_dissipation"].as_f64().unwrap() > 0.0);
    let svg = std::fs::read_to_string(out.join("hysteresis.svg")).unwrap();
    assert!(svg.contains("<svg"), "hysteresis.svg");
    let profiles = std::fs::read_to_string(out.join("contact_profiles.svg")).unwrap();
    for t in ["t = 2", "t = 3", "t = 4", "t = 6"] {
        assert!(profiles.contains(t), "profile {t} missing");
    }
}
