//! Two MPI ranks give the serial answer; acceptance never exceeds the tolerance asked for.

use crate::{answer, assert_same_answer, assert_uniform_pressure, scratch, Block, SQUARE_BLOCK};
use serde_json::Value;
use std::path::PathBuf;
use std::process::Command;

/// Run a scene on two MPI ranks; its report.
pub(crate) fn mpi_answer(name: &str, scene: &str, args: &[&str]) -> (PathBuf, Value) {
    let dir = scratch(name);
    let file = dir.join("scene.toml");
    std::fs::write(&file, scene).unwrap();
    let out_dir = dir.join("out");
    let out = Command::new("mpirun")
        .args(["--allow-run-as-root", "--oversubscribe", "-n", "2"])
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .arg(env!("CARGO_BIN_EXE_signorini"))
        .arg("run")
        .arg(&file)
        .arg("--quiet")
        .arg("--out")
        .arg(&out_dir)
        .args(args)
        .output()
        .expect("mpirun (./setup.sh installs openmpi-bin)");
    assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    let report = serde_json::from_str(&std::fs::read_to_string(out_dir.join("report.json")).unwrap()).unwrap();
    (out_dir, report)
}

#[test]
fn mpi_symmetry_plane_through_a_contact_node_is_exact() {
    let b = Block { left: false, extra: "[[dirichlet]]\npart = \"left\"\nux = 0.0\n".into(), ..Default::default() };
    let (dir, r) = mpi_answer("mpi_symmetry", &b.toml(), &[]);
    assert_eq!(r["mpi_ranks"], 2);
    assert_uniform_pressure("mpi_symmetry", &dir, b.p, 1e-8);
    let umax = r["results"]["max_displacement"].as_f64().unwrap();
    assert!((umax - b.top_displacement()).abs() <= 1e-7 * umax);
}

#[test]
fn mpi_dual_formulation_equals_serial() {
    // The patch test's tractions, a roller on the bottom: the dual on 1 and 2 ranks.
    let scene = r#"[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.2
mesher = "gmsh"

[discretization]
formulation = "dual"

[material]
young = 90e9
poisson = 0.3

[[traction]]
part = "top"
pressure = 1e6

[[traction]]
part = "right"
traction = [0.0, 2e5]

[[dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0
"#;
    let (_, serial) = answer("dual_serial", scene, &[]);
    let (_, parallel) = mpi_answer("dual_mpi", scene, &[]);
    assert_eq!(parallel["formulation"], "dual");
    let (a, b) = (
        serial["dual"]["check"]["complementary_energy"].as_f64().unwrap(),
        parallel["dual"]["check"]["complementary_energy"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-10 * a.abs(), "complementary energy serial {a} vs 2 ranks {b}");
    let (a, b) =
        (serial["dual"]["max_von_mises"].as_f64().unwrap(), parallel["dual"]["max_von_mises"].as_f64().unwrap());
    assert!((a - b).abs() <= 1e-9 * a, "max von Mises serial {a} vs 2 ranks {b}");
}

#[test]
fn acceptance_never_exceeds_the_tolerance_asked_for() {
    // With tolerance = 1e-7 the independent check accepts nothing worse than 1e-7 (the default
    // margin of 100 over the solver's tolerance is capped by what the scene asked for).
    for solver in ["relaxation", "newton", "newton_full"] {
        let b = Block {
            contact: format!("friction = \"coulomb\"\nmu = 0.3\nsolver = \"{solver}\"\ntolerance = 1e-7"),
            ..Default::default()
        };
        let (_, r) = answer(&format!("accept_{solver}"), &b.toml(), &[]);
        let res = &r["contact"]["residuals"];
        for key in [
            "max_penetration",
            "max_wrong_sign_pressure",
            "max_cone_violation",
            "normal_complementarity",
            "tangential_complementarity",
        ] {
            let v = res[key].as_f64().unwrap();
            assert!(v <= 1e-7, "{solver}: {key} = {v} above the tolerance asked for");
        }
    }
}

#[test]
fn mpi_fallback_after_snes_iteration_limit() {
    let (dir, r) = mpi_answer("mpi_fallback", SQUARE_BLOCK, &["-contact_snes_max_it", "1"]);
    let notes = r["contact"]["notes"].to_string().to_lowercase();
    assert!(notes.contains("fell back") && notes.contains("diverged_max_it"), "{notes}");
    assert!(r["contact"]["solver"].as_str().unwrap().contains("fallback"));
    // The fallback's answer on two ranks is the serial default run's.
    let (serial_dir, serial) = answer("mpi_fallback_serial", SQUARE_BLOCK, &[]);
    assert_same_answer("mpi_fallback", (&dir, &r), (&serial_dir, &serial), 1e-8);
}
