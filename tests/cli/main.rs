//! The `signorini` program end to end: each test spawns it (one PETSc session per process),
//! then checks exit codes, messages and the files it wrote — `solution.vtu` read back with
//! Python meshio, the independent reader (installed by ./setup.sh).
#[path = "../common/edit.rs"]
mod edit;

mod axisymmetric_bodies;
mod axisymmetry;
mod bench;
mod dual_outputs;
mod errors;
mod examples;
mod formulations;
mod hertz_sphere;
mod interface_laws;
mod interface_outputs;
mod load_paths;
mod mpi;
mod run_output;
mod several_bodies;
mod solver_options;
mod thin_layer;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// `mpirun -n 2 signorini` (as root in containers, one thread per rank).
fn mpirun_two() -> Command {
    let mut c = Command::new("mpirun");
    c.args(["-n", "2", "--oversubscribe"])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .arg(env!("CARGO_BIN_EXE_signorini"));
    c
}

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_signorini"));
    c.env("OMP_NUM_THREADS", "1").env("OPENBLAS_NUM_THREADS", "1");
    // Gmsh meshes cached for the tests, not in the user's cache.
    c.env("SIGNORINI_CACHE_DIR", Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh-cache"));
    c.env_remove("SIGNORINI_NO_MESH_CACHE");
    c
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("signorini-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn scene(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

fn run_ok(cmd: &mut Command) -> Output {
    let out = cmd.output().expect("spawn signorini");
    assert!(
        out.status.success(),
        "signorini failed ({:?}):\nstdout: {}\nstderr: {}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

fn run_err(cmd: &mut Command, code: i32) -> String {
    let out = cmd.output().expect("spawn signorini");
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(code), "expected exit {code}, stderr: {stderr}");
    assert!(stderr.starts_with("error: "), "stderr: {stderr}");
    stderr
}

fn report(dir: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap()
}

/// Run a Python script with meshio; its stdout. Fails (not skips) without python3 or meshio.
fn python(script: &str) -> String {
    let full = format!("import sys\ntry:\n    import meshio, numpy as np\nexcept BaseException as e:\n    print('NO MESHIO', e); sys.exit(3)\n{script}");
    let out = Command::new("python3").arg("-c").arg(&full).output().expect("python3 is needed (run ./setup.sh)");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "python failed (meshio installed? run ./setup.sh): {stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

fn relative_difference(a: &Path, b: &Path) -> f64 {
    let s = python(&format!(
        "a = meshio.read(r'{}').point_data['displacement']\nb = meshio.read(r'{}').point_data['displacement']\nprint(np.linalg.norm(a - b) / np.linalg.norm(a))",
        a.display(),
        b.display()
    ));
    s.trim().parse().unwrap()
}

/// The plane-elasticity block (no contact): its linear solver is the main KSP.
fn block() -> PathBuf {
    scene("examples/scenes/block.toml")
}
