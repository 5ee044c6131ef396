//! The `signorini` program end to end: each test spawns it (one PETSc session per process),
//! then checks exit codes, messages and the files it wrote — `solution.vtu` read back with
//! Python meshio, the independent reader (installed by ./setup.sh).
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

#[test]
fn default_scene_writes_report_and_solution() {
    let dir = scratch("default");
    let out = run_ok(bin().args(["run", "--out"]).arg(&dir));
    // The summary is the program's answer: on stdout.
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("wrote") && stdout.contains("equilibrium residual"), "{stdout}");
    let r = report(&dir);
    for key in ["nodes", "elements", "dofs", "formulation", "timings", "solver", "memory", "results"] {
        assert!(r.get(key).is_some(), "report.json lacks {key}: {r}");
    }
    assert_eq!(r["dofs"], 2 * r["nodes"].as_u64().unwrap());
    assert_eq!(r["formulation"], "primal");
    // The default scene runs the full-space semi-smooth Newton (SNES), its Jacobians solved by
    // block elimination with one MUMPS factor of K.
    assert!(r["solver"]["ksp_type"].as_str().unwrap().contains("preonly"), "{}", r["solver"]);
    assert!(r["solver"]["pc_type"].as_str().unwrap().contains("block elimination"), "{}", r["solver"]);
    assert!(r["solver"]["factor_package"].as_str().unwrap().starts_with("mumps"), "{}", r["solver"]);
    // The default scene is a frictional contact problem, checked independently.
    let c = &r["contact"];
    assert!(
        c["points"].as_u64().unwrap() > 0 && c["stick"].as_u64().unwrap() > 0 && c["slip"].as_u64().unwrap() > 0,
        "{c}"
    );
    for k in [
        "max_penetration",
        "max_wrong_sign_pressure",
        "max_cone_violation",
        "normal_complementarity",
        "tangential_complementarity",
    ] {
        assert!(c["residuals"][k].as_f64().unwrap() < 1e-7, "contact residual {k}: {c}");
    }
    assert!(stdout.contains("independent check"), "{stdout}");
    assert!(r["solver"]["relative_residual"].as_f64().unwrap() < 1e-8);
    for phase in ["mesh", "assemble", "solve", "output", "total"] {
        assert!(r["timings"][phase].as_f64().unwrap() >= 0.0, "timings.{phase}");
    }
    assert!(r["memory"]["peak_bytes"].as_u64().unwrap() > 1_000_000);
    assert!(r["results"]["equilibrium_residual"].as_f64().unwrap() < 1e-9);
    // No temporary files left next to the outputs.
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(names.len(), 5, "solution.vtu, report.json and the three contact files: {names:?}");
}

/// The plane-elasticity block (no contact): its linear solver is the main KSP.
fn block() -> PathBuf {
    scene("examples/scenes/block.toml")
}

#[test]
fn petsc_options_on_the_command_line_select_the_solver() {
    let reference = scratch("opts-ref");
    run_ok(bin().arg("run").arg(block()).args(["--quiet", "--out"]).arg(&reference));
    let cases: &[(&str, &[&str], &str)] = &[
        ("icc2", &["-ksp_type", "cg", "-pc_type", "icc", "-pc_factor_levels", "2"], "icc"),
        ("amg", &["-ksp_type", "cg", "-pc_type", "hypre", "-pc_hypre_type", "boomeramg"], "hypre"),
        ("ssor", &["-ksp_type", "symmlq", "-pc_type", "sor", "-pc_sor_symmetric", "-ksp_max_it", "50000"], "sor"),
    ];
    for (name, options, pc) in cases {
        let dir = scratch(&format!("opts-{name}"));
        run_ok(bin().arg("run").arg(block()).args(["--quiet", "--out"]).arg(&dir).args(*options));
        let r = report(&dir);
        assert_eq!(r["solver"]["pc_type"], *pc, "{name}");
        assert!(r["solver"]["iterations"].as_u64().unwrap() > 1, "{name}: {r}");
        let d = relative_difference(&reference.join("solution.vtu"), &dir.join("solution.vtu"));
        assert!(d < 1e-6, "{name}: relative difference {d:e} from MUMPS");
    }
}

#[test]
fn scene_petsc_options_are_defaults_the_command_line_overrides() {
    let dir = scratch("scene-opts");
    let text =
        std::fs::read_to_string(block()).unwrap() + "\n[solver]\npetsc_options = \"-ksp_type cg -pc_type jacobi\"\n";
    let path = dir.join("s.toml");
    std::fs::write(&path, text).unwrap();
    run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(dir.join("a")));
    assert_eq!(report(&dir.join("a"))["solver"]["pc_type"], "jacobi");
    run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(dir.join("b")).args(["-pc_type", "icc"]));
    assert_eq!(report(&dir.join("b"))["solver"]["pc_type"], "icc");
}

#[test]
fn mpirun_two_ranks_equals_serial() {
    let serial = scratch("mpi-serial");
    let cantilever = scene("examples/scenes/cantilever.toml");
    run_ok(bin().arg("run").arg(&cantilever).args(["--quiet", "--out"]).arg(&serial));
    for (name, extra) in [
        ("direct", &[][..]),
        ("cg-bjacobi-icc", &["-ksp_type", "cg", "-pc_type", "bjacobi", "-sub_pc_type", "icc"][..]),
    ] {
        let parallel = scratch(&format!("mpi-{name}"));
        let out = mpirun_two()
            .arg("run")
            .arg(&cantilever)
            .args(["--quiet", "--out"])
            .arg(&parallel)
            .args(extra)
            .output()
            .expect("mpirun (openmpi-bin, installed by ./setup.sh)");
        assert!(out.status.success(), "mpirun failed: {}", String::from_utf8_lossy(&out.stderr));
        let r = report(&parallel);
        assert_eq!(r["mpi_ranks"], 2);
        assert_eq!(r["dofs"], report(&serial)["dofs"]);
        let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
        assert!(d < 1e-8, "{name}: MPI answer differs from serial by {d:e}");
    }
}

#[test]
fn mpirun_two_ranks_contact_equals_serial() {
    // Frictional contact (square block) and a body held by contact alone (patch test).
    for name in ["square_block", "contact_patch"] {
        let path = scene(&format!("examples/scenes/{name}.toml"));
        let serial = scratch(&format!("mpi-contact-serial-{name}"));
        run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&serial));
        let parallel = scratch(&format!("mpi-contact-{name}"));
        let out =
            mpirun_two().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&parallel).output().expect("mpirun");
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
        assert!(d < 1e-8, "{name}: MPI differs from serial by {d:e}");
        assert_eq!(report(&parallel)["contact"]["stick"], report(&serial)["contact"]["stick"]);
    }
}

/// A failure on rank 0 alone stops every rank with an error, within a timeout, instead of
/// leaving rank 1 waiting in the next collective operation: clearing the previous results
/// fails (a directory named solution.vtu in the output directory), or writing them fails (the
/// output directory is a file). Without the agreement both runs hang until the timeout.
#[test]
fn mpirun_two_ranks_failure_on_rank_0_stops_every_rank() {
    let path = scene("examples/scenes/square_block.toml");
    let blocked = scratch("mpi-clear-fails");
    std::fs::create_dir_all(blocked.join("solution.vtu")).unwrap();
    let file = scratch("mpi-write-fails").join("a-file");
    std::fs::write(&file, "not a directory").unwrap();
    for (out_dir, expected) in [(&blocked, "removing the previous run's file"), (&file, "creating directory")] {
        let mut timed = Command::new("timeout");
        let mpirun = mpirun_two();
        timed.arg("120").arg(mpirun.get_program()).args(mpirun.get_args());
        for (key, value) in mpirun.get_envs() {
            if let Some(value) = value {
                timed.env(key, value);
            }
        }
        let started = std::time::Instant::now();
        let out = timed.arg("run").arg(&path).args(["--quiet", "--out"]).arg(out_dir).output().expect("mpirun");
        let seconds = started.elapsed().as_secs_f64();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_ne!(out.status.code(), Some(124), "{expected}: timed out after {seconds:.0} s (a hang)\n{stderr}");
        assert!(!out.status.success(), "{expected}: the run succeeded");
        // Rank 0 reports its own error once; rank 1 stopped without an error of its own.
        assert_eq!(stderr.matches(expected).count(), 1, "{expected}:\n{stderr}");
        assert!(!stderr.contains("MPI rank 1"), "{expected}:\n{stderr}");
    }
}

/// A block pushed sideways against a wall body, every body held by its Dirichlet conditions:
/// the slave face (the block's right side) runs across the ranks' node blocks, and so do the
/// master nodes.
const SIDEWAYS_PAIR: &str = r#"title = "Block pushed against a wall body"

[[body]]
name = "block"
mesh = { shape = "rectangle", origin = [0.0, 0.0], size = [0.04, 0.04], cell_size = 1.25e-3 }
material = { young = 1.3e11, poisson = 0.2, plane = "strain" }

[[body.dirichlet]]
part = "left"
ux = 2e-5

[[body.dirichlet]]
part = "bottom"
uy = 0.0

[[body.traction]]
part = "top"
pressure = 5e7

[[body]]
name = "wall"
mesh = { shape = "rectangle", origin = [0.04, -0.02], size = [0.02, 0.08], cell_size = 2.5e-3 }
material = { young = 7e10, poisson = 0.3, plane = "strain" }

[[body.dirichlet]]
part = "right"
ux = 0.0
uy = 0.0

[[contact_pair]]
slave = "block.right"
master = "wall.left"
friction = "coulomb"
mu = 0.3
"#;

#[test]
fn mpirun_two_ranks_bodies_equal_serial() {
    // Two bodies (mortar contact pair, Coulomb): the same answer on two processes as on one,
    // on the full-space Newton (its mortar rows read master dofs of the other rank) and on the
    // condensed route.
    let dir = scratch("mpi-bodies-scenes");
    let block_on_block = scene("examples/scenes/block_on_block.toml");
    // Every body held by its Dirichlet conditions: the block pressed by a prescribed
    // displacement of its top (its slave points on rank 0, the master nodes on rank 1).
    let text = std::fs::read_to_string(&block_on_block).unwrap();
    let loads = "[[body.traction]]\npart = \"top\"\npressure = 5e7\n";
    assert!(text.contains(loads), "test bug: block_on_block.toml's top load changed");
    let held = dir.join("block_on_block_held.toml");
    std::fs::write(&held, text.replacen(loads, "[[body.dirichlet]]\npart = \"top\"\nuy = -2e-5\n", 1)).unwrap();
    let sideways = dir.join("sideways.toml");
    std::fs::write(&sideways, SIDEWAYS_PAIR).unwrap();
    for (name, path, options, full_space) in [
        ("held", &held, &[][..], true),
        ("sideways", &sideways, &[][..], true),
        // The block held vertically by the contact alone: the full-space Newton (the floating
        // elimination in serial, SNES's LU of the mixed Jacobian on two ranks), and the
        // condensed route when asked for.
        ("floating", &block_on_block, &[][..], true),
        ("condensed", &block_on_block, &["--contact-solver", "newton"][..], false),
    ] {
        let serial = scratch(&format!("mpi-bodies-serial-{name}"));
        run_ok(bin().arg("run").arg(path).args(["--quiet", "--out"]).arg(&serial).args(options));
        let parallel = scratch(&format!("mpi-bodies-{name}"));
        let out = mpirun_two()
            .arg("run")
            .arg(path)
            .args(["--quiet", "--out"])
            .arg(&parallel)
            .args(options)
            .output()
            .expect("mpirun");
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        let (rs, rp) = (report(&serial), report(&parallel));
        assert_eq!(rp["mpi_ranks"], 2);
        for r in [&rs, &rp] {
            let solver = r["contact"]["solver"].as_str().unwrap();
            assert_eq!(solver.starts_with("full-space"), full_space, "{name}: {solver}, {}", r["contact"]["notes"]);
        }
        if full_space {
            // The same Newton steps (the same generalized Jacobians, solved exactly).
            assert_eq!(rp["contact"]["iterations"], rs["contact"]["iterations"], "{name}");
        }
        let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
        assert!(d < 1e-10, "{name}: MPI displacement differs from serial by {d:e}");
        let resultant = |r: &serde_json::Value| -> Vec<f64> {
            r["bodies"]["contacts"][0]["slave_resultant"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap())
                .collect()
        };
        let (a, b) = (resultant(&rs), resultant(&rp));
        let size = a[0].hypot(a[1]);
        assert!(size > 1e6, "{name}: {rs}");
        assert!((a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-10 * size, "{name}: contact resultant serial {a:?}, MPI {b:?}");
        assert_eq!(rp["bodies"]["bodies"].as_array().map(|b| b.len()), Some(2), "{name}: {rp}");
        assert_eq!(rp["bodies"]["contacts"][0]["stick"], rs["bodies"]["contacts"][0]["stick"], "{name}");
    }
}

#[test]
fn contact_solver_from_the_command_line() {
    let reference = scratch("cs-ref");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&reference));
    let dir = scratch("cs-relax");
    run_ok(bin().args(["run", "--quiet", "--contact-solver", "relaxation", "--out"]).arg(&dir));
    let r = report(&dir);
    assert!(r["contact"]["solver"].as_str().unwrap().contains("relaxation"), "{r}");
    let d = relative_difference(&reference.join("solution.vtu"), &dir.join("solution.vtu"));
    assert!(d < 1e-6, "relaxation differs from Newton by {d:e}");
    let msg = run_err(bin().args(["run", "--quiet", "--contact-solver", "snes_vi"]), 1);
    assert!(msg.contains("frictionless"), "{msg}");
    // An unknown name is a usage error that lists the names.
    let msg = run_err(bin().args(["run", "--quiet", "--contact-solver", "magic"]), 2);
    assert!(msg.contains("magic") && msg.contains("newton_full") && msg.contains("tao"), "{msg}");
    // The default solver can be named too.
    let dir = scratch("cs-full");
    run_ok(bin().args(["run", "--quiet", "--contact-solver", "newton_full", "--out"]).arg(&dir));
    assert!(report(&dir)["contact"]["solver"].as_str().unwrap().contains("full-space"));
}

#[test]
fn schur_condensation_needs_the_default_linear_solver() {
    let msg = run_err(
        bin().args(["run", "--quiet", "--contact-solver", "newton", "-contact_condense_schur", "-ksp_type", "cg"]),
        1,
    );
    assert!(msg.contains("-contact_condense_schur needs"), "{msg}");
    let msg =
        run_err(bin().args(["run", "--quiet", "--contact-solver", "newton", "-contact_condense_schur", "maybe"]), 1);
    assert!(msg.contains("-contact_condense_schur takes true or false"), "{msg}");
    // The default on one process: W from the Schur complement; `false` turns it off.
    let dir = scratch("schur-ok");
    run_ok(bin().args(["run", "--quiet", "--contact-solver", "newton", "--out"]).arg(&dir));
    assert!(report(&dir)["solver"]["factor_package"].as_str().unwrap().contains("Schur"));
    let dir = scratch("schur-off");
    run_ok(
        bin()
            .args(["run", "--quiet", "--contact-solver", "newton", "--out"])
            .arg(&dir)
            .args(["-contact_condense_schur", "false"]),
    );
    assert!(!report(&dir)["solver"]["factor_package"].as_str().unwrap().contains("Schur"));
}

#[test]
fn contact_fields_read_back_in_meshio() {
    let dir = scratch("contact-fields");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    let r = report(&dir);
    let out = python(&format!(
        r#"
m = meshio.read(r'{}')
p, t, s = m.point_data['contact_pressure'], m.point_data['friction_traction'], m.point_data['contact_status']
pts = m.points
bottom = np.abs(pts[:, 1]) < 1e-12
print(int((s == 0).sum()), int((s == 1).sum()), int((s == 2).sum()), int((s == -1).sum()), float(p[bottom].min()), float(np.abs(t[~bottom]).max()), float((np.abs(t[bottom]) - 1.0 * p[bottom]).max()))
"#,
        dir.join("solution.vtu").display()
    ));
    let v: Vec<f64> = out.split_whitespace().map(|x| x.parse().unwrap()).collect();
    let c = &r["contact"];
    assert_eq!(v[0] as u64, c["open"].as_u64().unwrap(), "{out}");
    assert_eq!(v[1] as u64, c["stick"].as_u64().unwrap(), "{out}");
    assert_eq!(v[2] as u64, c["slip"].as_u64().unwrap(), "{out}");
    assert_eq!((v[0] + v[1] + v[2] + v[3]) as u64, r["nodes"].as_u64().unwrap());
    assert!(v[4] >= 0.0, "negative contact pressure on the bottom: {out}");
    assert_eq!(v[5], 0.0, "friction traction off the contact part: {out}");
    assert!(v[6] <= 1e-6 * 1.5e8, "friction traction above mu * pressure: {out}");
}

#[test]
fn solution_vtu_reads_back_in_meshio_with_exact_patch_values() {
    // The patch test: uniform stress, exact for P1 and P2; check the file, not our memory.
    for order in [1, 2] {
        let dir = scratch(&format!("meshio-p{order}"));
        let text = std::fs::read_to_string(scene("examples/scenes/patch_test.toml"))
            .unwrap()
            .replace("order = 1", &format!("order = {order}"));
        let path = dir.join("patch.toml");
        std::fs::write(&path, text).unwrap();
        run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&dir));
        let r = report(&dir);
        let (e, nu, p) = (90e9_f64, 0.2_f64, 1e6_f64);
        let k = -(1.0 + nu) * (1.0 - 2.0 * nu) * p / (e * (1.0 - nu));
        let sxx = -nu * p / (1.0 - nu);
        let tri = if order == 1 { "triangle" } else { "triangle6" };
        let line = if order == 1 { "line" } else { "line3" };
        let out = python(&format!(
            r#"
m = meshio.read(r'{vtu}')
pts, u, s = m.points, m.point_data['displacement'], m.point_data['stress']
types = [c.type for c in m.cells]
assert types == ['{tri}', '{line}'], types
assert len(pts) == {nodes}, len(pts)
assert m.cells[0].data.shape == ({elements}, {npc}), m.cells[0].data.shape
assert len(m.cells[1].data) == {edges}
err_u = max(np.abs(u[:, 0]).max(), np.abs(u[:, 1] - {k:e} * pts[:, 1]).max(), np.abs(u[:, 2]).max())
err_s = max(np.abs(s[:, 0] - {sxx:e}).max(), np.abs(s[:, 1] + {p:e}).max(), np.abs(s[:, 3]).max())
zz = {nu:e} * ({sxx:e} - {p:e})
err_s = max(err_s, np.abs(s[:, 2] - zz).max())
ids = set(int(v) for block in m.cell_data['part_id'] for v in np.asarray(block).ravel())
print(err_u / abs({k:e}), err_s / {p:e}, sorted(ids))
"#,
            vtu = dir.join("solution.vtu").display(),
            nodes = r["nodes"],
            elements = r["elements"],
            edges = r["boundary_edges"],
            npc = if order == 1 { 3 } else { 6 },
        ));
        let fields: Vec<&str> = out.split_whitespace().collect();
        let err_u: f64 = fields[0].parse().unwrap();
        let err_s: f64 = fields[1].parse().unwrap();
        assert!(err_u < 1e-10, "P{order}: displacement error {err_u:e} (relative to the slope)");
        assert!(err_s < 1e-8, "P{order}: stress error {err_s:e}");
        let parts = r["parts"].as_object().unwrap();
        for name in ["bottom", "right", "top", "left", "domain"] {
            let tag = parts[name].as_i64().unwrap();
            assert!(out.contains(&tag.to_string()), "part_id lacks {name} ({tag}): {out}");
        }
    }
}

/// The data rows of the first Markdown table of a benchmark file (after its header and
/// separator lines).
fn table_rows(md: &str) -> Vec<&str> {
    md.lines().skip_while(|l| !l.starts_with('|')).skip(2).take_while(|l| l.starts_with('|')).collect()
}

/// The rows of the failed-cases table (`| dofs | solver | failed: reason |`).
fn failed_rows(md: &str) -> Vec<&str> {
    md.lines()
        .skip_while(|l| !l.starts_with("| dofs | solver | failed: reason |"))
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .collect()
}

/// Every benchmark file says when, by what and how it was run.
fn assert_provenance(md: &str, command: &str) {
    assert!(md.starts_with("# Benchmark"), "{md}");
    let date = md.lines().find_map(|l| l.strip_prefix("- date: ")).expect("a date line");
    assert!(date.len() == 23 && date.ends_with(" UTC") && date.starts_with("20"), "date {date}");
    let program = md.lines().find_map(|l| l.strip_prefix("- program: ")).expect("a program line");
    assert!(program.starts_with(&format!("signorini {} (commit ", env!("CARGO_PKG_VERSION"))), "{program}");
    let commit = program.rsplit("commit ").next().unwrap().trim_end_matches(')');
    assert!(commit == "unknown" || commit.chars().take(7).all(|c| c.is_ascii_hexdigit()), "commit {commit}");
    assert!(md.contains(&format!("- command: `signorini {command}")), "{md}");
}

#[test]
fn bench_elasticity_small_writes_table_and_plot() {
    let dir = scratch("bench");
    let out = run_ok(bin().args(["bench", "elasticity", "--max-dofs", "3000", "--out"]).arg(&dir));
    let table = std::fs::read_to_string(dir.join("bench_elasticity.md")).unwrap();
    assert!(table.contains("MUMPS") && table.contains("SYMMLQ + SSOR") && table.contains("BoomerAMG"), "{table}");
    assert_provenance(&table, "bench elasticity --max-dofs 3000 --out");
    assert!(failed_rows(&table).is_empty() && !table.contains("Failed cases"), "{table}");
    // Each row its own solver, iterative ones iterating.
    let rows = table_rows(&table);
    assert_eq!(rows.len(), 5, "{table}");
    let iterations: Vec<u64> = rows.iter().map(|r| r.split('|').nth(4).unwrap().trim().parse().unwrap()).collect();
    assert!(iterations[0] == 1 && iterations[1..].iter().all(|&i| i > 1), "{table}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("| dofs |"));
    let svg = std::fs::read_to_string(dir.join("bench_elasticity.svg")).unwrap();
    assert!(svg.starts_with("<?xml") || svg.starts_with("<svg"), "not an SVG");
}

#[test]
fn bench_contact_small_writes_table_and_plot() {
    let dir = scratch("bench-contact");
    run_ok(bin().args(["bench", "contact", "--max-dofs", "1000", "--out"]).arg(&dir));
    let table = std::fs::read_to_string(dir.join("bench_contact.md")).unwrap();
    assert_provenance(&table, "bench contact --max-dofs 1000");
    let rows = table_rows(&table);
    assert_eq!(rows.len(), 7, "one row per contact solver and the two-body scene: {table}");
    for solver in ["newton_full", "newton", "relaxation", "uzawa", "tresca_fixed_point", "dpana", "two_bodies"] {
        assert!(rows.iter().any(|r| r.contains(&format!("| {solver} |"))), "{solver} missing: {table}");
    }
    assert!(std::fs::read_to_string(dir.join("bench_contact.svg")).unwrap().contains("<svg"));
}

/// The work-precision diagram on the default scene (square block without its corner point,
/// Tresca), tiny: a reference, uniform P1 and P2 levels with their true errors, the adaptive
/// loops, every contact solver on one mesh; one SVG with estimates and true errors.
#[test]
fn bench_accuracy_small_writes_the_diagram_and_its_table() {
    let dir = scratch("bench-accuracy");
    let out = run_ok(bin().args(["bench", "accuracy", "--max-dofs", "500", "--out"]).arg(&dir));
    let md = std::fs::read_to_string(dir.join("bench_accuracy.md")).unwrap();
    assert_provenance(&md, "bench accuracy --max-dofs 500");
    assert!(md.contains("(examples/scenes/square_block_tresca.toml)") && md.contains("Reference: P2"), "{md}");
    let rows = table_rows(&md);
    let series = |s: &str| rows.iter().filter(|r| r.starts_with(&format!("| {s} |"))).count();
    assert_eq!((series("uniform P1"), series("uniform P2")), (2, 1), "{md}");
    assert!(series("adaptive P1") >= 1 && series("adaptive P2") >= 1, "{md}");
    for solver in ["newton_full", "newton", "dpana", "uzawa", "tao"] {
        assert!(rows.iter().any(|r| r.starts_with(&format!("| solver | {solver} |"))), "{solver}: {md}");
    }
    // Uniform levels: the estimate and the true error agree (Tresca: a guaranteed bound, the
    // effectivity near 1) and fall from the first level to the second.
    let cells = |r: &str| r.split('|').map(|c| c.trim().to_string()).collect::<Vec<String>>();
    let p1: Vec<Vec<String>> = rows.iter().filter(|r| r.starts_with("| uniform P1 |")).map(|r| cells(r)).collect();
    let (e0, e1): (f64, f64) = (p1[0][12].parse().unwrap(), p1[1][12].parse().unwrap());
    let (t0, t1): (f64, f64) = (p1[0][13].parse().unwrap(), p1[1][13].parse().unwrap());
    assert!(e1 < 0.7 * e0 && t1 < 0.7 * t0, "{md}");
    let effectivity: f64 = p1[1][14].parse().unwrap();
    assert!((0.95..1.1).contains(&effectivity), "{md}");
    assert!(md.contains("Observed rates") && md.contains("adaptive P1:"), "{md}");
    let svg = std::fs::read_to_string(dir.join("bench_accuracy.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("uniform P2: true error") && svg.contains("contact solvers"));
    assert!(String::from_utf8_lossy(&out.stdout).contains("| series |"));
    // A scene without geometry is refused before any case runs.
    let file_dir = scratch("bench-accuracy-file");
    std::fs::write(
        file_dir.join("m.toml"),
        "[mesh]\nshape = \"file\"\nfile = \"m.msh\"\n\n[material]\nyoung = 1e9\npoisson = 0.3\n",
    )
    .unwrap();
    std::fs::write(file_dir.join("m.msh"), "").unwrap();
    let msg = run_err(bin().args(["bench", "accuracy"]).arg(file_dir.join("m.toml")).arg("--out").arg(&file_dir), 1);
    assert!(msg.contains("bench accuracy") && !file_dir.join("bench_accuracy.md").exists(), "{msg}");
}

// ------------------------------------------------------------------ errors: clear, typed, no partial output

#[test]
fn missing_scene_file_names_the_file() {
    let msg = run_err(bin().args(["run", "/nonexistent/scene.toml"]), 1);
    assert!(msg.contains("/nonexistent/scene.toml"), "{msg}");
}

#[test]
fn scene_syntax_error_names_file_and_line() {
    let dir = scratch("syntax");
    let path = dir.join("bad.toml");
    std::fs::write(&path, "[mesh]\nshape = \"rectangle\"\nsize = [1.0, 1.0]\ncell_size = 0.1 0.2\n").unwrap();
    let msg = run_err(bin().arg("run").arg(&path).arg("--out").arg(dir.join("out")), 1);
    assert!(msg.contains("bad.toml:4:"), "{msg}");
    assert!(!dir.join("out").exists(), "output written despite the error");
}

#[test]
fn negative_young_modulus_names_the_line() {
    let dir = scratch("young");
    let path = dir.join("s.toml");
    let text = std::fs::read_to_string(scene("examples/scenes/block.toml"))
        .unwrap()
        .replace("young = 210e9", "young = -210e9");
    let line = text.lines().position(|l| l.contains("young = -210e9")).unwrap() + 1;
    std::fs::write(&path, text).unwrap();
    let msg = run_err(bin().arg("run").arg(&path), 1);
    assert!(msg.contains(&format!("s.toml:{line}:")) && msg.contains("young"), "{msg}");
}

#[test]
fn missing_petsc_option_value_is_refused() {
    let msg = run_err(bin().args(["run", "--quiet", "-ksp_type", "cg", "-pc_type", "icc", "-pc_factor_levels"]), 1);
    assert!(msg.contains("-pc_factor_levels") && msg.contains("needs a value"), "{msg}");
}

#[test]
fn unknown_petsc_type_reports_petsc_message() {
    let msg = run_err(bin().arg("run").arg(block()).args(["--quiet", "-ksp_type", "no_such_method"]), 1);
    assert!(msg.contains("PETSc error") && msg.contains("no_such_method"), "{msg}");
}

#[test]
fn diverging_solver_says_what_it_tried() {
    let msg = run_err(
        bin().arg("run").arg(block()).args(["--quiet", "-ksp_type", "cg", "-pc_type", "none", "-ksp_max_it", "5"]),
        1,
    );
    assert!(msg.contains("did not converge") && msg.contains("DIVERGED_ITS") && msg.contains("tried"), "{msg}");
}

#[test]
fn usage_errors_exit_2() {
    let msg = run_err(bin().args(["run", "--bogus"]), 2);
    assert!(msg.contains("--bogus"), "{msg}");
    let msg = run_err(bin().args(["frobnicate"]), 2);
    assert!(msg.contains("frobnicate"), "{msg}");
    let msg = run_err(bin().args(["run", "--out"]), 2);
    assert!(msg.contains("--out") && msg.contains("value"), "{msg}");
    let msg = run_err(bin().args(["run", "a.toml", "b.toml"]), 2);
    assert!(msg.contains("b.toml"), "{msg}");
    let msg = run_err(bin().args(["bench", "contact", "--max-dofs", "lots"]), 2);
    assert!(msg.contains("lots") && msg.contains("--max-dofs"), "{msg}");
    let msg = run_err(bin().args(["bench"]), 2);
    assert!(msg.contains("elasticity") && msg.contains("contact"), "{msg}");
}

#[test]
fn help_on_every_subcommand() {
    for args in [
        &["--help"][..],
        &["-h"],
        &["run", "--help"],
        &["run", "-h"],
        &["bench", "--help"],
        &["bench", "contact", "-h"],
    ] {
        let out = bin().args(args).output().unwrap();
        assert!(out.status.success(), "{args:?}: {:?}", out.status);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("Usage: signorini"), "{args:?}: {text}");
    }
    // -h never runs anything: no output directory appears.
    let dir = scratch("help-no-run");
    let out = bin().current_dir(&dir).args(["run", "-h"]).output().unwrap();
    assert!(out.status.success() && !dir.join("out").exists());
    let out = bin().arg("--version").output().unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("signorini "));
}

#[test]
fn own_flags_and_petsc_options_in_any_order() {
    // --out after PETSc options, the scene after them, a value-less PETSc option just before
    // our flag: all the same run.
    let dir = scratch("any-order");
    run_ok(
        bin()
            .args(["run", "-ksp_type", "cg", "-pc_type", "icc", "-ksp_converged_reason", "--quiet", "--out"])
            .arg(&dir)
            .arg(block()),
    );
    let r = report(&dir);
    assert_eq!(r["solver"]["ksp_type"], "cg", "{}", r["solver"]);
    assert_eq!(r["solver"]["pc_type"], "icc");
}

#[test]
fn unwritable_output_leaves_nothing_half_written() {
    let dir = scratch("unwritable");
    let blocker = dir.join("file");
    std::fs::write(&blocker, "not a directory").unwrap();
    let msg = run_err(bin().args(["run", "--quiet", "--out"]).arg(blocker.join("out")), 1);
    assert!(msg.contains("cannot write output") || msg.contains("failed"), "{msg}");
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "stray files: {names:?}");
}

#[test]
fn unused_petsc_option_is_reported_as_a_warning() {
    let dir = scratch("unused");
    let out = run_ok(bin().args(["run", "--out"]).arg(&dir).args(["-ksp_tyep", "cg"]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("-ksp_tyep") && stderr.contains("never used"), "{stderr}");
    let r = report(&dir);
    assert!(r["solver"]["unused_options"].to_string().contains("ksp_tyep"), "{r}");
}

/// The examples, built by `cargo test`, run with small settings.
fn example_binary(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    let path = deps.parent().unwrap().join("examples").join(name);
    assert!(path.exists(), "example {name} not built at {}", path.display());
    path
}

#[test]
fn example_hertz_contact_runs_small() {
    let plot = scratch("hertz-plot").join("hertz.svg");
    let out = Command::new(example_binary("hertz_contact")).arg("--small").arg("--plot").arg(&plot).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    // The coarse mesh is still within a few per cent of Hertz on the peak pressure.
    let line = stdout.lines().find(|l| l.contains("peak pressure")).unwrap();
    let percent: f64 = line.rsplit('(').next().unwrap().trim_end_matches(" %)").trim().parse().unwrap();
    assert!(percent.abs() < 10.0, "{stdout}");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Hertz") && svg.contains("P2 nodes"), "plot");
}

#[test]
fn example_assembly_timing_runs_small() {
    let out = Command::new(example_binary("assembly_timing")).arg("60").output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

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
        .replace("order = 1", "order = 2\nelement = \"p2p0\"")
        .replace("poisson = 0.2", &format!("poisson = {nu}"))
        .replace("pressure = 2.5e5", &format!("pressure = {side:e}"));
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
    assert!(e["estimate_seconds"].as_f64().unwrap() >= 0.0);
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
    let report = std::fs::read_to_string(dir.join("report.json")).unwrap();
    assert!(report.contains("\"formulation\": \"dual\"") && report.contains("\"peak_pressure\""), "{report}");
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

#[test]
fn a_failed_run_leaves_no_stale_results() {
    let dir = scratch("stale");
    run_ok(bin().arg("run").arg(block()).args(["--quiet", "--out"]).arg(&dir));
    assert!(dir.join("solution.vtu").exists() && dir.join("report.json").exists());
    // A temporary file a killed writer left behind (SIGXFSZ, SIGINT) is cleaned by the next run.
    let leftover = dir.join(".solution.vtu.12345.0.tmp");
    std::fs::write(&leftover, "half a file").unwrap();
    let msg = run_err(bin().args(["run", "/nonexistent/scene.toml", "--quiet", "--out"]).arg(&dir), 1);
    assert!(msg.contains("previous results") && msg.contains("removed"), "{msg}");
    for f in ["solution.vtu", "report.json"] {
        assert!(!dir.join(f).exists(), "stale {f} after a failed run");
    }
    assert!(!leftover.exists(), "the leftover temporary file was not cleaned");
    // Under a file-size limit the writer is stopped: no half-written file stays behind.
    let small = scratch("ulimit");
    let out = Command::new("bash")
        .arg("-c")
        .arg(format!(
            "ulimit -f 20; exec {} run {} --quiet --out {}",
            env!("CARGO_BIN_EXE_signorini"),
            scene("examples/scenes/cantilever.toml").display(),
            small.display()
        ))
        .env("PMIX_MCA_gds", "hash")
        .output()
        .unwrap();
    assert!(!out.status.success(), "a 10 kB file-size limit cannot hold solution.vtu");
    for f in ["solution.vtu", "report.json"] {
        assert!(!small.join(f).exists(), "{f} written under the file-size limit");
    }
    // The next run (without the limit) cleans whatever temporary file was left.
    run_ok(bin().arg("run").arg(scene("examples/scenes/cantilever.toml")).args(["--quiet", "--out"]).arg(&small));
    let names: Vec<String> =
        std::fs::read_dir(&small).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}

#[test]
fn physics_warnings_in_the_report_and_the_terminal() {
    let dir = scratch("no-warning");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    assert_eq!(report(&dir)["warnings"], serde_json::json!([]), "the default scene warns about nothing");
    let base = std::fs::read_to_string(scene("examples/scenes/patch_test.toml")).unwrap();
    for (name, from, to, kind) in [
        ("locking", "poisson = 0.2", "poisson = 0.4999", "locking"),
        ("large", "young = 90e9", "young = 1e7", "large_displacement"),
    ] {
        let dir = scratch(name);
        let path = dir.join("s.toml");
        assert!(base.contains(from));
        std::fs::write(&path, base.replacen(from, to, 1)).unwrap();
        let out = run_ok(bin().arg("run").arg(&path).arg("--out").arg(dir.join("out")));
        let kinds: Vec<String> = report(&dir.join("out"))["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .map(|w| w["kind"].as_str().unwrap().to_string())
            .collect();
        assert!(kinds.iter().any(|k| k == kind), "{name}: {kinds:?}");
        assert!(String::from_utf8_lossy(&out.stderr).contains(&format!("warning   {kind}")), "{name}");
    }
}

#[test]
fn example_contact_builder_runs() {
    let out = Command::new(example_binary("contact_builder")).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    // Held sideways by friction alone: the shear 2e5 × 2 is carried by the contact.
    assert!(text.contains("contact:") && text.contains("tangential -4.0000e5"), "{text}");
}

#[test]
fn example_two_bodies_runs() {
    let out = Command::new(example_binary("two_bodies")).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    // The block's vertical load 5e6 N/m crosses the interface: the base receives it.
    assert!(text.contains("body base:") && text.contains("-5.0000e6), equilibrium residual"), "{text}");
    let residual = |line: &str| -> f64 { line.rsplit(' ').next().unwrap_or("1").parse().unwrap_or(1.0) };
    for line in text.lines().filter(|l| l.contains("residual")) {
        assert!(residual(line) < 1e-9, "{line}");
    }
}

#[test]
fn a_factorisation_out_of_memory_is_named_and_the_advice_works() {
    let msg = run_err(bin().arg("run").arg(block()).args(["--quiet", "-mat_mumps_icntl_23", "1"]), 1);
    assert!(msg.contains("out of memory") && msg.contains("INFOG(1)") && msg.contains("-pc_type hypre"), "{msg}");
    // The advice: an iterative solver instead of the factorisation.
    let dir = scratch("oom-advice");
    run_ok(
        bin()
            .arg("run")
            .arg(block())
            .args(["--quiet", "-mat_mumps_icntl_23", "1", "-ksp_type", "cg", "-pc_type", "hypre", "--out"])
            .arg(&dir),
    );
}

#[test]
fn bench_dual_writes_its_table_and_plot() {
    let dir = scratch("bench-dual");
    let out = bin().args(["bench", "dual", "--max-dofs", "2000", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = std::fs::read_to_string(dir.join("bench_dual.md")).unwrap();
    assert!(table.contains("MUMPS") && table.contains("primal P2"), "{table}");
    // CG + SSOR converges on the HCT system (a row of the table, not a failed case).
    assert!(table.lines().any(|l| l.contains("| CG + SSOR |") && !l.contains("exit")), "{table}");
    assert_provenance(&table, "bench dual --max-dofs 2000");
    assert!(std::fs::read_to_string(dir.join("bench_dual.svg")).unwrap().contains("<svg"));
}

/// Concurrent runs on one machine: each process gets an Open MPI session directory of its own
/// (isolated singletons all take job family 0, and one run's clean-up used to remove the shared
/// directory under another, which then failed in MPI_Init); none is left behind.
#[test]
fn concurrent_runs_do_not_share_the_mpi_session_directory() {
    let dir = scratch("concurrent-runs");
    let tmp = dir.join("tmp");
    std::fs::create_dir_all(&tmp).unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/square_block_1k.toml");
    let children: Vec<_> = (0..8)
        .map(|k| {
            bin()
                .arg("run")
                .arg(&scene)
                .args(["--quiet", "--out"])
                .arg(dir.join(format!("out{k}")))
                .env("TMPDIR", &tmp)
                .spawn()
                .unwrap()
        })
        .collect();
    for mut child in children {
        assert!(child.wait().unwrap().success());
    }
    let left: Vec<_> = std::fs::read_dir(&tmp).unwrap().flatten().map(|e| e.file_name()).collect();
    assert!(left.is_empty(), "left in TMPDIR: {left:?}");
}

/// `bench held`: both drives of the half disc at 1e4 dofs, the force-driven row with its ratio
/// to the displacement-driven one, no failed case (the force-driven disc has no supports).
#[test]
fn bench_held_writes_both_drives_and_their_ratio() {
    let dir = scratch("bench-held");
    let out = bin().args(["bench", "held", "--max-dofs", "20000", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = std::fs::read_to_string(dir.join("bench_held.md")).unwrap();
    assert_provenance(&table, "bench held --max-dofs 20000");
    assert!(failed_rows(&table).is_empty(), "{table}");
    let rows = table_rows(&table);
    assert_eq!(rows.len(), 2, "{table}");
    let force = rows.iter().find(|r| r.contains("| force |")).expect("a force-driven row");
    let ratio: f64 = force.split('|').nth(7).unwrap().trim().parse().expect("a ratio");
    assert!(ratio > 0.0 && ratio.is_finite(), "{table}");
    assert!(std::fs::read_to_string(dir.join("bench_held.svg")).unwrap().contains("<svg"));
}

/// `bench dual-contact`: the block without its corner in the dual and the primal, with the
/// estimate, at 1e3 dofs, every strategy (the iterative interior solvers take about 10 s).
#[test]
fn bench_dual_contact_writes_its_table() {
    let dir = scratch("bench-dual-contact");
    let out = bin().args(["bench", "dual-contact", "--max-dofs", "2000", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = std::fs::read_to_string(dir.join("bench_dual_contact.md")).unwrap();
    assert_provenance(&table, "bench dual-contact --max-dofs 2000");
    // Every strategy is a row or a failed case; the direct ones succeed.
    let (rows, failed) = (table_rows(&table), failed_rows(&table));
    for name in signorini::bench::dual_contact::STRATEGIES.iter().map(|s| s.name) {
        let cell = format!("| {name} |");
        assert_eq!(rows.iter().chain(&failed).filter(|r| r.contains(&cell)).count(), 1, "{name}: {table}");
        if name.contains("MUMPS") {
            assert!(rows.iter().any(|r| r.contains(&cell)), "{name} failed: {table}");
        }
    }
    assert!(std::fs::read_to_string(dir.join("bench_dual_contact.svg")).unwrap().contains("<svg"));
}

/// A case that fails is a row of the file with its reason, never dropped; when every case
/// fails the file is still written (with no plot) and the run fails.
#[test]
fn bench_failed_cases_are_rows_with_their_reason() {
    let dir = scratch("bench-failed");
    let out = run_ok(
        bin().args(["bench", "elasticity", "--max-dofs", "3000", "--out"]).arg(&dir).args(["-b_ssor_ksp_max_it", "2"]),
    );
    let md = std::fs::read_to_string(dir.join("bench_elasticity.md")).unwrap();
    assert_provenance(&md, "bench elasticity --max-dofs 3000 --out");
    assert!(md.contains("-b_ssor_ksp_max_it 2`"), "the whole command line: {md}");
    assert_eq!(table_rows(&md).len(), 4, "{md}");
    let failed = failed_rows(&md);
    assert_eq!(failed.len(), 1, "{md}");
    assert!(
        failed[0].starts_with("| 3000 | SYMMLQ + SSOR | exit 1: error: ") && failed[0].contains("DIVERGED_ITS"),
        "{md}"
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("SYMMLQ + SSOR | exit 1"));
    assert!(dir.join("bench_elasticity.svg").exists());

    let out = bin()
        .args(["bench", "elasticity", "--max-dofs", "3000", "--out"])
        .arg(&dir)
        .args(["-b_mumps_pc_type", "bogus", "-b_icc0_ksp_max_it", "1", "-b_icc2_ksp_max_it", "1"])
        .args(["-b_amg_ksp_max_it", "1", "-b_ssor_ksp_max_it", "1"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no benchmark case succeeded"));
    let md = std::fs::read_to_string(dir.join("bench_elasticity.md")).unwrap();
    assert_eq!(failed_rows(&md).len(), 5, "every case a row: {md}");
    assert!(table_rows(&md).is_empty() && md.contains("Failed cases (5)"), "{md}");
    assert!(!dir.join("bench_elasticity.svg").exists(), "no plot of nothing (and no stale one)");
}

/// The terminal summary of a contact run: within 100 columns, the solver said once, every
/// quantity an engineer looks for; piped output holds no progress escape codes.
#[test]
fn the_summary_fits_100_columns_and_says_each_thing_once() {
    for (name, scene_file) in [("summary-default", None), ("summary-hertz", Some("examples/scenes/hertz.toml"))] {
        let dir = scratch(name);
        let mut cmd = bin();
        cmd.arg("run");
        if let Some(f) = scene_file {
            cmd.arg(scene(f));
        }
        let out = run_ok(cmd.arg("--out").arg(&dir));
        let stdout = String::from_utf8_lossy(&out.stdout);
        let stderr = String::from_utf8_lossy(&out.stderr);
        for line in stdout.lines().chain(stderr.lines()) {
            assert!(line.chars().count() <= 100, "{name}: a line of {} characters: {line}", line.chars().count());
        }
        // Output that is not a terminal: no escape codes, no carriage returns.
        assert!(!stdout.contains('\u{1b}') && !stderr.contains('\u{1b}'), "{name}: escape codes");
        assert!(!stdout.contains('\r') && !stderr.contains('\r'), "{name}: carriage returns");
        let r = report(&dir);
        let solver = r["contact"]["solver"].as_str().unwrap();
        // The solver description is wrapped like any text: compare without line breaks.
        let flat = stdout.lines().map(|l| l.get(10..).unwrap_or("").trim()).collect::<Vec<_>>().join(" ");
        assert_eq!(flat.matches(solver).count(), 1, "{name}: the solver once: {stdout}");
        for label in ["problem", "solver", "time", "contact", "wrote"] {
            let n = stdout.lines().filter(|l| l.starts_with(&format!("{label:<10}"))).count();
            assert_eq!(n, 1, "{name}: one '{label}' line: {stdout}");
        }
        for what in
            ["peak pressure", "closed zone 1: s in [", "stick", "slip", "open", "resultant", "independent check"]
        {
            assert!(flat.contains(what), "{name}: no '{what}': {stdout}");
        }
        for phase in ["mesh", "assemble", "solve", "output", "total"] {
            assert!(flat.contains(&format!("{phase} ")), "{name}: time of {phase}: {stdout}");
        }
        let peak = r["contact"]["peak_pressure"]["pressure"].as_f64().unwrap();
        assert!(flat.contains(&format!("peak pressure {peak:.4e}")), "{name}: {stdout}");
        assert!(r["contact"]["zones"].as_array().is_some_and(|z| !z.is_empty()), "{name}");
    }
}

/// Is `path` well-formed XML with an `<svg>` root? (Python's parser, which the tests need anyway.)
fn svg_is_well_formed(path: &Path) -> bool {
    let out = python(&format!(
        "import xml.etree.ElementTree as E\nr = E.parse({:?}).getroot()\nprint(r.tag.endswith('svg'), len(r.findall('.//{{http://www.w3.org/2000/svg}}text')) > 0)",
        path.display().to_string()
    ));
    out.trim() == "True True"
}

/// Every contact run writes contact.csv (one row per contact point, in order of arc length,
/// the report's peak among its pressures), contact.svg and convergence.svg (well-formed SVG
/// with text); a run without contact removes them; a failed run leaves none.
#[test]
fn contact_runs_write_the_curve_as_csv_and_pictures() {
    let dir = scratch("contact-files");
    let stdout = String::from_utf8_lossy(
        &run_ok(bin().arg("run").arg(scene("examples/scenes/hertz.toml")).arg("--out").arg(&dir)).stdout,
    )
    .to_string();
    let r = report(&dir);
    let c = &r["contact"];
    let text = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "s,x,y,pressure,tangential_traction,gap,normal_displacement,tangential_slip,status"
    );
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(str::to_string).collect()).collect();
    assert_eq!(rows.len() as u64, c["points"].as_u64().unwrap(), "one row per contact point");
    let num = |row: &[String], k: usize| row[k].parse::<f64>().unwrap();
    let s: Vec<f64> = rows.iter().map(|r| num(r, 0)).collect();
    assert!(s.windows(2).all(|w| w[1] >= w[0]), "rows in order of arc length");
    let peak = rows.iter().map(|r| num(r, 3)).fold(f64::NEG_INFINITY, f64::max);
    let reported = c["peak_pressure"]["pressure"].as_f64().unwrap();
    assert!((peak - reported).abs() <= 1e-12 * reported.abs(), "csv peak {peak} against report {reported}");
    let peak_row = rows.iter().find(|r| num(r, 3) == peak).unwrap();
    assert!((num(peak_row, 0) - c["peak_pressure"]["s"].as_f64().unwrap()).abs() < 1e-12);
    for (status, key) in [("open", "open"), ("stick", "stick"), ("slip", "slip")] {
        let n = rows.iter().filter(|r| r[8] == status).count() as u64;
        assert_eq!(n, c[key].as_u64().unwrap(), "{status} rows");
    }
    for row in &rows {
        if row[8] == "open" {
            assert!(num(row, 3).abs() <= 1e-12 * reported, "an open point carries no pressure: {row:?}");
            assert!(num(row, 5) >= -1e-12, "an open point has a gap: {row:?}");
        } else {
            assert!(num(row, 5).abs() < 1e-9, "a closed point has no gap: {row:?}");
        }
    }
    assert_eq!(c["residual_history"].as_array().unwrap().len() as u64, c["iterations"].as_u64().unwrap());
    for f in ["contact.svg", "convergence.svg"] {
        assert!(svg_is_well_formed(&dir.join(f)), "{f} is not well-formed SVG with text");
        assert!(stdout.contains(f), "the summary names {f}");
    }
    // The next run rewrites them; a run without contact removes them.
    let before = std::fs::metadata(dir.join("contact.csv")).unwrap().modified().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(20));
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    assert!(std::fs::metadata(dir.join("contact.csv")).unwrap().modified().unwrap() > before, "rewritten");
    let rows = std::fs::read_to_string(dir.join("contact.csv")).unwrap().lines().count() - 1;
    assert_eq!(rows as u64, report(&dir)["contact"]["points"].as_u64().unwrap());
    run_ok(bin().arg("run").arg(block()).args(["--quiet", "--out"]).arg(&dir));
    for f in ["contact.csv", "contact.svg", "convergence.svg"] {
        assert!(!dir.join(f).exists(), "{f} left from the previous contact run");
    }
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    run_err(bin().args(["run", "/nonexistent/scene.toml", "--quiet", "--out"]).arg(&dir), 1);
    let left: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
    assert!(left.is_empty(), "stale results after a failed run: {left:?}");
}

/// On a terminal (a pseudo-terminal made by `script`) the progress spinner is drawn on stderr,
/// with the contact Newton steps; `--quiet` draws nothing. Skipped without `script`.
#[test]
fn progress_is_drawn_on_a_terminal_only() {
    if Command::new("script").arg("--version").output().is_err() {
        eprintln!("skipped: no `script` to make a terminal");
        return;
    }
    let dir = scratch("tty");
    let run = |extra: &str| {
        let log = dir.join(format!("typescript{}", extra.trim()));
        let inner = format!(
            "{} run {} --out {} {extra} >/dev/null",
            env!("CARGO_BIN_EXE_signorini"),
            scene("examples/scenes/hertz.toml").display(),
            dir.join("out").display()
        );
        let out = Command::new("script")
            .args(["-qec", &inner])
            .arg(&log)
            .env("SIGNORINI_PROGRESS_DELAY_MS", "0")
            .env("PMIX_MCA_gds", "hash")
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&std::fs::read(&log).unwrap()).to_string();
        // `script` adds a header line and a footer line of its own.
        text.lines().filter(|l| !l.starts_with("Script ")).collect::<Vec<_>>().join("\n")
    };
    let shown = run("");
    assert!(shown.contains('\u{1b}') && shown.contains("contact iteration"), "{shown}");
    let quiet = run("--quiet");
    assert!(!quiet.contains('\u{1b}') && !quiet.contains("contact iteration"), "{quiet}");
}

#[test]
fn gmsh_meshes_come_from_the_mesh_cache_the_second_time() {
    let dir = scratch("mesh-cache");
    let cache = dir.join("cache");
    let path = scene("examples/scenes/cantilever.toml");
    let run = |out: &str, extra: &[&str], env: Option<(&str, &str)>| {
        let mut c = bin();
        c.arg("run").arg(&path).args(extra).arg("--out").arg(dir.join(out)).env("SIGNORINI_CACHE_DIR", &cache);
        if let Some((k, v)) = env {
            c.env(k, v);
        }
        let o = run_ok(&mut c);
        let r = report(&dir.join(out));
        (String::from_utf8_lossy(&o.stdout).to_string(), String::from_utf8_lossy(&o.stderr).to_string(), r)
    };
    let (first, _, r1) = run("first", &[], None);
    assert_eq!(r1["mesh_cache"]["status"], "miss", "{r1}");
    assert!(!first.contains("(cached)"), "{first}");
    let (second, _, r2) = run("second", &[], None);
    assert_eq!(r2["mesh_cache"]["status"], "hit", "{r2}");
    assert!(second.contains("mesh ") && second.contains(" s (cached)"), "{second}");
    // The same mesh, so the same answer to the bit.
    let solution = |out: &str| std::fs::read(dir.join(out).join("solution.vtu")).unwrap();
    assert!(solution("first") == solution("second"), "the cached mesh gave another solution");
    // Off by the flag or the variable: meshed by Gmsh, nothing read.
    let (_, _, r3) = run("flag", &["--no-mesh-cache"], None);
    assert_eq!(r3["mesh_cache"]["status"], "disabled", "{r3}");
    let (_, _, r4) = run("variable", &[], Some(("SIGNORINI_NO_MESH_CACHE", "1")));
    assert_eq!(r4["mesh_cache"]["status"], "disabled", "{r4}");
    // A damaged entry: a note on stderr, meshed again, and the next run hits.
    let entries: Vec<PathBuf> = std::fs::read_dir(cache.join("meshes")).unwrap().map(|e| e.unwrap().path()).collect();
    assert_eq!(entries.len(), 1, "{entries:?}");
    let bytes = std::fs::read(&entries[0]).unwrap();
    std::fs::write(&entries[0], &bytes[..bytes.len() / 3]).unwrap();
    let (_, stderr, r5) = run("damaged", &[], None);
    assert_eq!(r5["mesh_cache"]["status"], "miss", "{r5}");
    assert!(stderr.contains("mesh cache: unusable entry"), "{stderr}");
    assert!(solution("damaged") == solution("first"));
    let (_, _, r6) = run("again", &[], None);
    assert_eq!(r6["mesh_cache"]["status"], "hit", "{r6}");
}

#[test]
fn several_bodies_run_and_other_commands_refuse() {
    // `run` solves both example scenes with [[body]] tables and reports every body.
    for name in ["block_on_block", "two_cylinders"] {
        let dir = scratch(&format!("bodies-{name}"));
        let path = scene(&format!("examples/scenes/{name}.toml"));
        run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&dir));
        let r = report(&dir);
        let bodies = r["bodies"]["bodies"].as_array().unwrap_or_else(|| panic!("{name}: no bodies in {r}"));
        assert_eq!(bodies.len(), 2, "{name}: {r}");
        assert_eq!(r["bodies"]["contacts"].as_array().map(|c| c.len()), Some(1), "{name}: {r}");
        assert!(dir.join("solution.vtu").exists(), "{name}");
        // The other commands that solve still refuse, without an answer.
        let stderr = run_err(bin().arg("export").arg(&path).arg("--out").arg(dir.join("p.hdf5")), 1);
        assert!(stderr.contains("several bodies are parsed and checked but not solved yet"), "{stderr}");
        assert!(!dir.join("p.hdf5").exists());
    }
    for command in [&["adapt", "--target", "5", "--quiet"][..], &["study", "--levels", "2", "--quiet"][..]] {
        let stderr = run_err(
            bin()
                .args(command)
                .arg(scene("examples/scenes/block_on_block.toml"))
                .arg("--out")
                .arg(scratch(&format!("bodies-{}", command[0]))),
            1,
        );
        assert!(stderr.contains("several bodies are parsed and checked but not solved yet"), "{command:?}: {stderr}");
    }
    // A mistake found once the meshes exist comes first, with its file and line.
    let dir = scratch("bodies-overlap");
    let text = std::fs::read_to_string(scene("examples/scenes/block_on_block.toml"))
        .unwrap()
        .replace("origin = [0.0, 0.0]", "origin = [0.0, -0.005]");
    let path = dir.join("overlap.toml");
    std::fs::write(&path, &text).unwrap();
    let stderr = run_err(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(dir.join("out")), 1);
    let line = text.lines().position(|l| l.starts_with("[[contact_pair]]")).unwrap() + 1;
    assert!(
        stderr.contains(&format!("{}:{line}:1: bodies `block` and `foundation` overlap", path.display())),
        "{stderr}"
    );
}

#[test]
fn ict_preconditioner_from_the_command_line() {
    let cantilever = scene("examples/scenes/cantilever.toml");
    let reference = scratch("ict-ref");
    run_ok(bin().arg("run").arg(&cantilever).args(["--quiet", "--out"]).arg(&reference));
    let dir = scratch("ict");
    run_ok(bin().arg("run").arg(&cantilever).args(["--quiet", "--out"]).arg(&dir).args([
        "-ksp_type",
        "cg",
        "-pc_type",
        "ict",
        "-pc_ict_drop_tolerance",
        "1e-3",
    ]));
    let r = report(&dir);
    let pc = r["solver"]["pc_type"].as_str().unwrap_or_default();
    assert!(pc.starts_with("ict (drop tolerance 1e-3"), "pc_type {pc}");
    assert_eq!(r["solver"]["ksp_type"], "cg");
    assert!(r["solver"]["iterations"].as_u64().unwrap() > 1, "{r}");
    let d = relative_difference(&reference.join("solution.vtu"), &dir.join("solution.vtu"));
    assert!(d < 1e-6, "relative difference {d:e} from the scene's solver");
    // A bad value names the option.
    let err = run_err(
        bin().arg("run").arg(&cantilever).args(["--quiet", "--out"]).arg(scratch("ict-bad")).args([
            "-pc_type",
            "ict",
            "-pc_ict_drop_tolerance",
            "abc",
        ]),
        1,
    );
    assert!(err.contains("-pc_ict_drop_tolerance abc"), "{err}");
    // On two processes: a typed error naming the parallel alternatives.
    let out = mpirun_two()
        .arg("run")
        .arg(&cantilever)
        .args(["--quiet", "--out"])
        .arg(scratch("ict-mpi"))
        .args(["-pc_type", "ict"])
        .output()
        .expect("mpirun (openmpi-bin, installed by ./setup.sh)");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("-pc_type ict runs on one process"), "{stderr}");
}

#[test]
fn contact_solver_option_reaches_every_contact_of_several_bodies() {
    // block_on_block.toml has one [[contact_pair]] and no [contact] table: the command line's
    // solver applies to the pair.
    let path = scene("examples/scenes/block_on_block.toml");
    let dir = scratch("bodies-contact-solver");
    run_ok(bin().arg("run").arg(&path).args(["--quiet", "--contact-solver", "relaxation", "--out"]).arg(&dir));
    let r = report(&dir);
    let solver = r["contact"]["solver"].as_str().unwrap_or_default().to_lowercase();
    assert!(solver.contains("relaxation"), "solver: {solver}");
    // snes_vi cannot take a pair, tao only Tresca: usage errors, nothing written.
    let out = scratch("bodies-contact-solver-bad");
    let stderr =
        run_err(bin().arg("run").arg(&path).args(["--quiet", "--contact-solver", "snes_vi", "--out"]).arg(&out), 1);
    assert!(stderr.contains("snes_vi"), "{stderr}");
    let stderr =
        run_err(bin().arg("run").arg(&path).args(["--quiet", "--contact-solver", "tao", "--out"]).arg(&out), 1);
    assert!(stderr.contains("Tresca"), "{stderr}");
    assert!(!out.join("report.json").exists());
}
