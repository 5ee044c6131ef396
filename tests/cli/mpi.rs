//! `mpirun -n 2`: two ranks give the serial answer (elasticity, contact, several bodies), a
//! failure on one rank stops every rank, and concurrent runs keep their MPI session directories
//! apart.

use crate::{bin, mpirun_two, relative_difference, report, run_ok, scene, scratch};
use std::path::Path;
use std::process::Command;

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

/// Under `mpirun -n 2` the cost model takes the gathered dense route on the square block (K
/// gathered on rank 0, which runs the one-process dense Schur route and sends the answer), as does
/// `-contact_route dense_schur`; the distributed sparse LU stays available by name. All three
/// give the serial answer: displacements, contact forces and Newton steps.
#[test]
fn mpirun_two_ranks_gathered_dense_route_equals_serial() {
    let path = scene("examples/scenes/square_block.toml");
    let serial = scratch("mpi-gathered-serial");
    run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&serial));
    let s = report(&serial);
    assert_eq!(s["contact"]["route"], "dense_schur", "{}", s["contact"]["route_reason"]);
    for (name, extra, route) in [
        ("auto", &[][..], "dense_schur_gathered"),
        ("named-dense", &["-contact_route", "dense_schur"][..], "dense_schur_gathered"),
        ("named-sparse", &["-contact_route", "sparse_lu"][..], "sparse_lu"),
    ] {
        let parallel = scratch(&format!("mpi-gathered-{name}"));
        let out = mpirun_two()
            .arg("run")
            .arg(&path)
            .args(["--quiet", "--out"])
            .arg(&parallel)
            .args(extra)
            .output()
            .expect("mpirun");
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        let p = report(&parallel);
        assert_eq!(p["mpi_ranks"], 2);
        assert_eq!(p["contact"]["route"], route, "{name}: {}", p["contact"]["route_reason"]);
        let reason = p["contact"]["route_reason"].as_str().unwrap();
        if route == "dense_schur_gathered" {
            assert!(reason.contains("2 MPI ranks") && reason.contains("on rank 0 alone: "), "{name}: {reason}");
        } else {
            assert!(reason.contains("asked for (-contact_route sparse_lu)"), "{name}: {reason}");
        }
        let d = relative_difference(&serial.join("solution.vtu"), &parallel.join("solution.vtu"));
        assert!(d < 1e-10, "{name}: MPI differs from serial by {d:e}");
        for key in ["resultant"] {
            for c in 0..2 {
                let (a, b) = (s["contact"][key][c].as_f64().unwrap(), p["contact"][key][c].as_f64().unwrap());
                assert!((a - b).abs() <= 1e-10 * a.abs().max(1.0), "{name}: {key}[{c}] {a} against {b}");
            }
        }
        for key in ["stick", "slip", "open"] {
            assert_eq!(p["contact"][key], s["contact"][key], "{name}: {key}");
        }
        let steps = |r: &serde_json::Value| r["contact"]["iterations"].as_i64().unwrap();
        assert!((steps(&p) - steps(&s)).abs() <= 1, "{name}: {} Newton steps against {}", steps(&p), steps(&s));
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
    for (out_dir, expected) in [(&blocked, "removing the previous run's results failed"), (&file, "creating directory")]
    {
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
    // on the full-space Newton (gathered on rank 0, or distributed: its mortar rows read master
    // dofs of the other rank) and on the condensed route.
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
        // elimination, on rank 0 alone under the gathered route on two ranks), and the
        // condensed route when asked for.
        ("floating", &block_on_block, &[][..], true),
        ("condensed", &block_on_block, &["--contact-solver", "newton"][..], false),
        // SNES's LU of the mixed Jacobian distributed over both ranks, by name (the cost
        // model takes the gathered route on these scenes).
        ("held-distributed", &held, &["-contact_route", "sparse_lu"][..], true),
        ("floating-distributed", &block_on_block, &["-contact_route", "sparse_lu"][..], true),
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

// ---- adapt, study, several bodies and the refusals under `mpirun -n 2` ----

/// `signorini SUBCOMMAND SCENE ARGS --quiet --out DIR` once on one process and once under
/// `mpirun -n 2`: the two output directories (serial, two ranks), both runs successful.
pub(crate) fn serial_and_two_ranks(
    name: &str,
    subcommand: &str,
    scene: &Path,
    args: &[&str],
) -> (std::path::PathBuf, std::path::PathBuf) {
    let serial = scratch(&format!("mpi-{name}-serial"));
    run_ok(bin().arg(subcommand).arg(scene).args(args).args(["--quiet", "--out"]).arg(&serial));
    let parallel = scratch(&format!("mpi-{name}-two-ranks"));
    let out = mpirun_two()
        .arg(subcommand)
        .arg(scene)
        .args(args)
        .args(["--quiet", "--out"])
        .arg(&parallel)
        .env("SIGNORINI_CACHE_DIR", Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh-cache"))
        .output()
        .expect("mpirun");
    assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    (serial, parallel)
}

fn json_file(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))).unwrap()
}

/// `|a − b| ≤ 1e-10 |a|` for the number at `key` of two JSON objects.
fn assert_close(what: &str, key: &str, a: &serde_json::Value, b: &serde_json::Value) {
    let (x, y) = (a[key].as_f64().unwrap_or_else(|| panic!("{what}: no {key}: {a}")), b[key].as_f64().unwrap());
    assert!((x - y).abs() <= 1e-10 * x.abs(), "{what}: {key} serial {x:e}, two ranks {y:e}");
}

/// Two solution.vtu files of meshes made alike: whether their cells are the same (connectivity
/// and counts), the largest node shift relative to the mesh's diagonal, and the relative
/// difference of the displacement (point data) and of the square of each named cell field (the
/// per-cell error: its square is the cell's share of the estimate, summed over ranks in another
/// order; where a cell's contact term is round-off, its square root amplifies that round-off).
fn mesh_and_fields(a: &Path, b: &Path, cell_fields: &[&str]) -> (bool, f64, Vec<f64>) {
    let out = crate::python(&format!(
        r#"a, b = meshio.read(r'{}'), meshio.read(r'{}')
same = len(a.points) == len(b.points) and all(np.array_equal(x.data, y.data) for x, y in zip(a.cells, b.cells))
diag = np.linalg.norm(a.points.max(axis=0) - a.points.min(axis=0))
shift = np.abs(a.points - b.points).max() / diag if same else float('inf')
rel = lambda x, y: np.linalg.norm(x - y) / np.linalg.norm(x)
fields = [rel(a.point_data['displacement'], b.point_data['displacement'])] if same else []
fields += [rel(np.concatenate(a.cell_data[k]) ** 2, np.concatenate(b.cell_data[k]) ** 2) for k in {:?}] if same else []
print(same, shift, ' '.join(repr(float(f)) for f in fields))"#,
        a.display(),
        b.display(),
        cell_fields
    ));
    let mut words = out.split_whitespace();
    let same = words.next() == Some("True");
    let shift = words.next().unwrap().parse().unwrap();
    (same, shift, words.map(|w| w.parse().unwrap()).collect())
}

/// The adaptive loop on two ranks gives the serial loop: the same steps (element, node and dof
/// counts), each step's estimate, displacement and per-cell error to 1e-10, and meshes with the
/// same cells whose nodes agree to 1e-10 of the diagonal. Rank 0 alone remeshes (Gmsh) and
/// sends the mesh to rank 1; the size map it meshes from is computed from the two ranks'
/// estimate, which differs from the serial one in round-off (1e-13), hence nodes equal to
/// round-off and not bit for bit. Three steps, two Gmsh remeshings.
#[test]
fn mpirun_two_ranks_adapt_equals_serial() {
    let scene = scene("examples/scenes/clamped_block.toml");
    adapt_agreement("adapt", &scene, &["--target", "8"], 3);
}

fn adapt_agreement(name: &str, scene: &Path, args: &[&str], steps: usize) {
    let (serial, parallel) = serial_and_two_ranks(name, "adapt", scene, args);
    let (a, b) = (json_file(&serial.join("adapt.json")), json_file(&parallel.join("adapt.json")));
    assert_eq!(a["status"], "reached", "{name}: {a}");
    assert_eq!(b["status"], a["status"], "{name}");
    let (sa, sb) = (a["steps"].as_array().unwrap(), b["steps"].as_array().unwrap());
    assert_eq!(sa.len(), steps, "{name}: test bug, the loop took another number of steps: {a}");
    assert_eq!(sb.len(), sa.len(), "{name}: steps");
    for (k, (x, y)) in sa.iter().zip(sb).enumerate() {
        let what = format!("{name}: step {k}");
        for key in ["elements", "nodes", "dofs"] {
            assert_eq!(x[key], y[key], "{what}: {key}");
        }
        for key in ["error", "error_percent", "reference_norm"] {
            assert_close(&what, key, x, y);
        }
        let dir = |root: &Path| root.join(format!("step_{k}"));
        let (ra, rb) = (json_file(&dir(&serial).join("report.json")), json_file(&dir(&parallel).join("report.json")));
        assert_eq!(rb["mpi_ranks"], 2, "{what}");
        assert_close(&what, "relative_percent", &ra["estimate"], &rb["estimate"]);
        let (same, shift, fields) =
            mesh_and_fields(&dir(&serial).join("solution.vtu"), &dir(&parallel).join("solution.vtu"), &["error"]);
        assert!(same, "{what}: the meshes have different cells");
        assert!(shift <= 1e-10, "{what}: nodes moved by {shift:e} of the diagonal");
        // The per-cell error of the contact scene (the dual's contact terms, condensed by the
        // distributed solver whose round-off differs from run to run) agrees to 1e-10–2e-10 of
        // its norm: 1e-9 for the cells, 1e-10 for the displacement and the total estimate.
        assert!(fields[0] <= 1e-10, "{what}: displacement differs by {:e}", fields[0]);
        assert!(fields.iter().all(|d| *d <= 1e-9), "{what}: displacement, error² differ by {fields:?}");
    }
}

/// The convergence study on two ranks gives the serial study: the P2 reference, every level's
/// true errors, estimate and effectivity to 1e-10, the same meshes (Gmsh, made by rank 0).
#[test]
fn mpirun_two_ranks_study_equals_serial() {
    let scene = scene("examples/scenes/clamped_block.toml");
    study_agreement("study", &scene);
}

fn study_agreement(name: &str, scene: &Path) {
    let (serial, parallel) = serial_and_two_ranks(name, "study", scene, &["--levels", "2"]);
    let (a, b) = (json_file(&serial.join("study.json")), json_file(&parallel.join("study.json")));
    for key in ["elements", "nodes", "dofs"] {
        assert_eq!(a["reference"][key], b["reference"][key], "{name}: reference {key}");
    }
    assert_close(name, "energy_norm", &a["reference"], &b["reference"]);
    let (la, lb) = (a["levels"].as_array().unwrap(), b["levels"].as_array().unwrap());
    assert_eq!((la.len(), lb.len()), (2, 2), "{name}");
    for (k, (x, y)) in la.iter().zip(lb).enumerate() {
        let what = format!("{name}: level {k}");
        for key in ["elements", "nodes", "dofs"] {
            assert_eq!(x[key], y[key], "{what}: {key}");
        }
        for key in ["error_displacement", "error_stress", "estimate", "estimate_percent", "effectivity"] {
            assert_close(&what, key, x, y);
        }
    }
}

/// Adaptation and the study of a contact scene (Tresca, the dual's contact terms in the
/// estimate) on two ranks: as the elasticity ones above. Both runs condense the dual contact by
/// columns (the route under MPI; the serial default, the Schur complement, gives the same
/// estimate to 5e-10 only: the two condensations' round-off on these meshes).
#[test]
fn mpirun_two_ranks_adapt_and_study_of_contact_equal_serial() {
    let scene = scene("examples/scenes/square_block_tresca.toml");
    let columns = ["--target", "8", "--max-steps", "3", "-dual_contact_condensation", "columns"];
    adapt_agreement("adapt-contact", &scene, &columns, 2);
    study_agreement("study-contact", &scene);
}

/// Two elastic cylinders pressed together (a mortar contact pair, frictionless; the upper one
/// held sideways at its centre only, vertically by the contact), meshed coarser than
/// examples/scenes/two_cylinders.toml: on two ranks the full-space Newton runs (SNES's LU of
/// the mixed Jacobian, asked for with `-contact_route sparse_lu`, and the cost model's gathered
/// route, rank 0 running the floating elimination as in serial), never the condensed route, and
/// each gives the serial answer: the same Newton steps, the contact resultant to 1e-10, each body's
/// displacement to 1e-10 once its rigid motion is taken out, and to 1e-9 with it. Frictionless
/// contact leaves the upper cylinder's rotation about its centre free (every arc point moves
/// along the arc): the two routes fix that mode differently in round-off (measured: a rotation
/// of 6e-13 rad, 8e-11 of the displacement; on the scene's own mesh 1.4e-11 rad, 2e-9).
#[test]
fn mpirun_two_ranks_bodies_full_space_route() {
    let text = std::fs::read_to_string(scene("examples/scenes/two_cylinders.toml")).unwrap();
    let coarse = text
        .replace("cell_size = 0.01\n", "cell_size = 0.02\n")
        .replace("cell_size = 2.5e-4, radius = 0.015", "cell_size = 1e-3, radius = 0.02");
    assert_eq!(coarse.matches("cell_size = 0.02\n").count(), 2, "test bug: two_cylinders.toml's cell sizes changed");
    assert_eq!(coarse.matches("cell_size = 1e-3").count(), 2, "test bug: two_cylinders.toml's refinements changed");
    let dir = scratch("mpi-two-cylinders-scene");
    let path = dir.join("two_cylinders_coarse.toml");
    std::fs::write(&path, coarse).unwrap();
    let (serial, gathered) = serial_and_two_ranks("two-cylinders", "run", &path, &[]);
    // The distributed route by name: SNES's LU of the mixed Jacobian over both ranks, whose
    // mortar rows read master dofs of the other rank.
    let distributed = scratch("mpi-two-cylinders-two-ranks-sparse-lu");
    let out = mpirun_two()
        .arg("run")
        .arg(&path)
        .args(["-contact_route", "sparse_lu", "--quiet", "--out"])
        .arg(&distributed)
        .env("SIGNORINI_CACHE_DIR", Path::new(env!("CARGO_TARGET_TMPDIR")).join("mesh-cache"))
        .output()
        .expect("mpirun");
    assert!(out.status.success(), "sparse_lu: {}", String::from_utf8_lossy(&out.stderr));
    for (parallel, route) in [(&gathered, "dense_schur_gathered"), (&distributed, "sparse_lu")] {
        let rp = report(parallel);
        assert_eq!(rp["contact"]["route"], route, "{}", rp["contact"]["route_reason"]);
        two_cylinders_agree(&serial, parallel);
    }
}

/// The two-rank run in `parallel` gives the serial answer of `serial` (see
/// [`mpirun_two_ranks_bodies_full_space_route`]).
fn two_cylinders_agree(serial: &Path, parallel: &Path) {
    let (rs, rp) = (report(serial), report(parallel));
    assert_eq!(rp["mpi_ranks"], 2);
    for r in [&rs, &rp] {
        let solver = r["contact"]["solver"].as_str().unwrap();
        assert!(solver.starts_with("full-space semi-smooth Newton"), "{solver}: {}", r["contact"]["notes"]);
    }
    assert_eq!(rp["contact"]["iterations"], rs["contact"]["iterations"]);
    let resultant = |r: &serde_json::Value| -> Vec<f64> {
        let v = r["bodies"]["contacts"][0]["slave_resultant"].as_array().unwrap();
        v.iter().map(|x| x.as_f64().unwrap()).collect()
    };
    let (a, b) = (resultant(&rs), resultant(&rp));
    assert!(a[1] > 4e7, "the resultant carries the load (4.5e7 N/m): {a:?}");
    assert!((a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-10 * a[1], "resultant serial {a:?}, two ranks {b:?}");
    for body in ["upper", "lower"] {
        let out = crate::python(&format!(
            r#"a, b = meshio.read(r'{}'), meshio.read(r'{}')
x, u = a.points[:, :2], a.point_data['displacement'][:, :2]
d = u - b.point_data['displacement'][:, :2]
R = np.zeros((2 * len(x), 3)); R[0::2, 0] = 1; R[1::2, 1] = 1; R[0::2, 2] = -x[:, 1]; R[1::2, 2] = x[:, 0]
c = np.linalg.lstsq(R, d.ravel(), rcond=None)[0]
print(np.linalg.norm(d) / np.linalg.norm(u), np.linalg.norm(d.ravel() - R @ c) / np.linalg.norm(u))"#,
            serial.join(format!("{body}.vtu")).display(),
            parallel.join(format!("{body}.vtu")).display()
        ));
        let v: Vec<f64> = out.split_whitespace().map(|w| w.parse().unwrap()).collect();
        assert!(v[1] <= 1e-10, "{body}: the deformation differs by {:e}", v[1]);
        // The raw field also carries the rigid rotation that frictionless contact leaves free
        // (fixed by round-off: 8e-11 to 3e-9 between routes and runs).
        assert!(v[0] <= 1e-8, "{body}: the displacement differs by {:e}", v[0]);
    }
}

/// A benchmark's driver under `mpirun -n 2` is refused by name before any case runs: exit 2,
/// said once, and its output directory never made. (Without the refusal each rank runs every
/// case in child processes that inherit the launcher's environment, and both write the table.)
#[test]
fn mpirun_two_ranks_bench_is_refused_by_name() {
    let out_dir = scratch("mpi-bench-refused").join("bench");
    let out = mpirun_two()
        .args(["bench", "elasticity", "--max-dofs", "1e4", "--solvers", "mumps", "--out"])
        .arg(&out_dir)
        .output()
        .expect("mpirun");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    let message = "error: signorini bench elasticity runs on one process only (it was started on 2 MPI processes";
    assert_eq!(stderr.matches(message).count(), 1, "{stderr}");
    assert!(stderr.contains("hint: run it without mpirun"), "{stderr}");
    assert!(!out_dir.exists(), "the benchmark started: {} exists", out_dir.display());
}

/// A main linear solver of one process (PETSc 3.18's ICC, ILU, our ICT, the factorisation
/// packages of one process) under `mpirun -n 2` is refused by name before the mesh is read:
/// the scene's mesh file is not a mesh, and the error is the solver's, said once. From the
/// command line and from the scene's [solver] petsc_options alike; on one process the same
/// runs go on to read the mesh (and fail there). Without the check PETSc refused them in the
/// first solve ("Could not locate a solver type for factorization type ICC and matrix type
/// mpiaij"), after the mesh and the assembly.
#[test]
fn mpirun_two_ranks_one_process_solver_is_refused_by_name() {
    let dir = scratch("mpi-one-process-solver");
    std::fs::write(dir.join("not_a_mesh.msh"), "not a mesh\n").unwrap();
    let scene_text = |solver: &str| {
        format!(
            "[mesh]\nshape = \"file\"\nfile = \"not_a_mesh.msh\"\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n\
             [[dirichlet]]\npart = \"left\"\nux = 0.0\nuy = 0.0\n{solver}"
        )
    };
    let plain = dir.join("plain.toml");
    std::fs::write(&plain, scene_text("")).unwrap();
    let with_ilu = dir.join("ilu.toml");
    std::fs::write(&with_ilu, scene_text("\n[solver]\npetsc_options = \"-ksp_type cg -pc_type ilu\"\n")).unwrap();
    for (path, options, named) in [
        (&plain, &["-ksp_type", "cg", "-pc_type", "icc"][..], "-pc_type icc"),
        (&plain, &["-ksp_type", "cg", "-pc_type", "ict"][..], "-pc_type ict"),
        (&plain, &["-pc_factor_mat_solver_type", "petsc"][..], "-pc_factor_mat_solver_type petsc"),
        (&with_ilu, &[][..], "-pc_type ilu"),
    ] {
        let out = mpirun_two()
            .arg("run")
            .arg(path)
            .args(["--quiet", "--out"])
            .arg(dir.join("out"))
            .args(options)
            .output()
            .expect("mpirun");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{named}: {stderr}");
        let message = format!("error: {named} runs on one process only (started on 2 MPI processes");
        assert_eq!(stderr.matches(&message).count(), 1, "{named}: {stderr}");
        assert!(stderr.contains("hint: run it without mpirun"), "{named}: {stderr}");
        assert!(!stderr.contains("not a Gmsh MSH file"), "{named}: the mesh was read first: {stderr}");
        // One process: no refusal, the mesh is read (and is not one).
        let serial = bin().arg("run").arg(path).args(["--quiet", "--out"]).arg(dir.join("out")).args(options).output();
        let stderr = String::from_utf8_lossy(&serial.unwrap().stderr).to_string();
        assert!(stderr.contains("not a Gmsh MSH file") && !stderr.contains("one process"), "{named}: {stderr}");
    }
}

/// `signorini export --solve` on two ranks writes the serial FCLIB problem: W, q and mu, and
/// our solution (u, r), to 1e-10 of each array's largest entry, read back with h5py; the
/// sparsity of W identical.
#[test]
fn mpirun_two_ranks_export_equals_serial() {
    let scene = scene("examples/scenes/square_block.toml");
    let (serial, parallel) = (scratch("mpi-export-serial"), scratch("mpi-export-two-ranks"));
    let (a, b) = (serial.join("problem.hdf5"), parallel.join("problem.hdf5"));
    run_ok(bin().arg("export").arg(&scene).arg("--solve").arg("--out").arg(&a));
    let out = mpirun_two().arg("export").arg(&scene).arg("--solve").arg("--out").arg(&b).output().expect("mpirun");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    // One line on stdout, from rank 0 alone.
    assert_eq!(String::from_utf8_lossy(&out.stdout).matches("wrote ").count(), 1);
    let script = format!(
        r#"import sys, h5py, numpy as np
a, b = h5py.File(r'{}', 'r'), h5py.File(r'{}', 'r')
worst = 0.0
for name in ['fclib_local/W/x', 'fclib_local/vectors/q', 'fclib_local/vectors/mu', 'solution/u', 'solution/r']:
    x, y = np.array(a[name]), np.array(b[name])
    assert x.shape == y.shape and x.size > 0, name
    worst = max(worst, np.abs(x - y).max() / np.abs(x).max())
for name in ['fclib_local/W/i', 'fclib_local/W/p', 'fclib_local/W/m', 'fclib_local/W/n']:
    assert np.array_equal(np.array(a[name]), np.array(b[name])), name
print(worst)"#,
        a.display(),
        b.display()
    );
    let run = Command::new("python3").arg("-c").arg(&script).output().expect("python3 (run ./setup.sh)");
    assert!(run.status.success(), "h5py: {}", String::from_utf8_lossy(&run.stderr));
    let worst: f64 = String::from_utf8_lossy(&run.stdout).trim().parse().unwrap();
    assert!(worst <= 1e-10, "the exported problem differs by {worst:e}");
}

/// `signorini run SCENE OPTIONS` on one process and under `mpirun -n 2` (dual contact and
/// `--estimate` tests); the two output directories.
fn dual_serial_and_two_ranks(name: &str, path: &Path, options: &[&str]) -> (std::path::PathBuf, std::path::PathBuf) {
    let serial = scratch(&format!("mpi-dual-serial-{name}"));
    run_ok(bin().arg("run").arg(path).args(["--quiet", "--out"]).arg(&serial).args(options));
    let parallel = scratch(&format!("mpi-dual-{name}"));
    let out = mpirun_two().arg("run").arg(path).args(["--quiet", "--out"]).arg(&parallel).args(options).output();
    let out = out.expect("mpirun");
    assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(report(&parallel)["mpi_ranks"], 2, "{name}");
    (serial, parallel)
}

/// `max |a − b| / max |a|` over the point data `fields` of two `solution.vtu` files (each field
/// relative to its own size).
fn worst_point_data_difference(a: &Path, b: &Path, fields: &[&str]) -> f64 {
    let script = format!(
        "a = meshio.read(r'{}').point_data\nb = meshio.read(r'{}').point_data\nprint(max(np.abs(a[k] - b[k]).max() \
         / np.abs(a[k]).max() for k in {fields:?}))",
        a.join("solution.vtu").display(),
        b.join("solution.vtu").display()
    );
    crate::python(&script).trim().parse().unwrap()
}

/// The numeric columns and the statuses of `contact.csv`.
fn contact_table(dir: &Path) -> (Vec<Vec<f64>>, Vec<String>) {
    let text = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (mut columns, mut status) = (vec![Vec::new(); header.len() - 1], Vec::new());
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        for (k, c) in cells[..header.len() - 1].iter().enumerate() {
            columns[k].push(c.parse::<f64>().unwrap());
        }
        status.push(cells[header.len() - 1].to_string());
    }
    assert_eq!(header[3..8], ["pressure", "tangential_traction", "gap", "normal_displacement", "tangential_slip"]);
    (columns, status)
}

/// The dual formulation with contact on two ranks (the three-step condensation with MUMPS on
/// the distributed interior block, the condensed problem solved on every rank) gives the serial
/// answer (the Schur complement of one sequential factorisation, in the local parametrisation)
/// to 1e-10: stresses, Airy function, contact forces and displacements, statuses, resultant.
/// Tresca friction on the square block (7 × 7), the patch test held by the contact alone
/// (equilibrium conditions on the forces), and the implicit storage of W (products by
/// distributed interior solves).
#[test]
fn mpirun_two_ranks_dual_contact_equals_serial() {
    let tresca = scene("examples/scenes/square_block_tresca.toml");
    let patch = scene("examples/scenes/contact_patch.toml");
    for (name, path, options) in [
        ("tresca", &tresca, &["--formulation", "dual"][..]),
        ("patch", &patch, &["--formulation", "dual"][..]),
        ("implicit", &tresca, &["--formulation", "dual", "-dual_contact_storage", "implicit"][..]),
    ] {
        let (serial, parallel) = dual_serial_and_two_ranks(name, path, options);
        let (rs, rp) = (report(&serial), report(&parallel));
        assert_eq!(rp["formulation"], "dual", "{name}");
        assert!(rs["contact"]["closed"].as_u64().unwrap() > 0, "{name}: nothing in contact: {}", rs["contact"]);
        let solver = rp["dual"]["solver"]["converged_reason"].as_str().unwrap();
        assert!(solver.contains("solves with A_zz"), "{name}: not the three-step condensation: {solver}");
        let d = worst_point_data_difference(&serial, &parallel, &["stress", "airy_stress", "contact_pressure"]);
        assert!(d < 1e-10, "{name}: MPI stress differs from serial by {d:e}");
        let ((cs, ss), (cp, sp)) = (contact_table(&serial), contact_table(&parallel));
        assert_eq!(ss, sp, "{name}: contact statuses");
        // Forces (pressure, tangential traction) relative to the largest force, displacements
        // (normal displacement, slip) relative to the largest one or the report's displacement
        // scale (the patch's are zero to round-off: every point closed and sticking).
        let displacement_scale = rs["contact"]["residuals"]["displacement_scale"].as_f64().unwrap();
        for (group, floor) in [([3, 4], 0.0), ([6, 7], displacement_scale)] {
            let scale = group.iter().flat_map(|&k| cs[k].iter()).fold(floor, |m, v| m.max(v.abs()));
            assert!(scale > 0.0, "{name}: columns {group:?} are zero");
            for k in group {
                let worst = cs[k].iter().zip(&cp[k]).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                assert!(worst <= 1e-10 * scale, "{name}: contact.csv column {k} differs by {:e}", worst / scale);
            }
        }
        let resultant = |r: &serde_json::Value| -> Vec<f64> {
            r["contact"]["resultant"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect()
        };
        let (a, b) = (resultant(&rs), resultant(&rp));
        assert!((a[0] - b[0]).hypot(a[1] - b[1]) <= 1e-10 * a[0].hypot(a[1]), "{name}: resultant {a:?} against {b:?}");
    }
}

/// `run --estimate` with contact on two ranks (the primal's full-space Newton, the dual's
/// distributed condensation, the estimate per element on every rank) gives the serial global
/// estimate, its volume and contact parts, and every element's error, to 1e-10 (an element's
/// squared error relative to the global squared error: where the contact term is round-off,
/// its square root is not comparable).
#[test]
fn mpirun_two_ranks_estimate_equals_serial() {
    let tresca = scene("examples/scenes/square_block_tresca.toml");
    let (serial, parallel) = dual_serial_and_two_ranks("estimate", &tresca, &["--estimate"]);
    let (es, ep) = (&report(&serial)["estimate"], &report(&parallel)["estimate"]);
    let error = es["error"].as_f64().unwrap();
    assert!(error > 0.0 && es["contact"].as_f64().unwrap() > 0.0, "{es}");
    for key in ["error", "relative_percent", "volume", "contact"] {
        let (a, b) = (es[key].as_f64().unwrap(), ep[key].as_f64().unwrap());
        assert!((a - b).abs() <= 1e-10 * a.abs(), "estimate.{key}: serial {a:e}, MPI {b:e}");
    }
    let script = format!(
        "a = meshio.read(r'{}').cell_data\nb = meshio.read(r'{}').cell_data\nprint(max(np.abs(np.concatenate(a[k]) \
         ** 2 - np.concatenate(b[k]) ** 2).max() for k in ['error', 'error_contact']))",
        serial.join("solution.vtu").display(),
        parallel.join("solution.vtu").display()
    );
    let worst: f64 = crate::python(&script).trim().parse().unwrap();
    assert!(worst <= 1e-10 * error * error, "per-element squared error differs by {:e} of e²", worst / (error * error));
    let d = worst_point_data_difference(&serial, &parallel, &["displacement", "dual_stress"]);
    assert!(d < 1e-10, "MPI fields differ from serial by {d:e}");
}

/// What of the dual contact cannot be distributed is refused by name before any work: the
/// Schur condensation asked for under `mpirun -n 2`. The scene names a contact part the mesh
/// lacks, an error found only after meshing: the refusal comes first.
#[test]
fn mpirun_two_ranks_refuse_dual_schur_condensation_before_meshing() {
    let dir = scratch("mpi-dual-refused");
    let text = std::fs::read_to_string(scene("examples/scenes/square_block_tresca.toml")).unwrap();
    let contact = "[contact]\npart = \"bottom\"";
    assert!(text.contains(contact), "test bug: square_block_tresca.toml's contact part changed");
    let path = dir.join("nowhere.toml");
    std::fs::write(&path, text.replacen(contact, "[contact]\npart = \"nowhere\"", 1)).unwrap();
    // One process: the missing part is found (after meshing).
    let serial =
        crate::run_err(bin().arg("run").arg(&path).args(["--estimate", "--quiet", "--out"]).arg(dir.join("s")), 1);
    assert!(serial.contains("no boundary part named `nowhere`"), "{serial}");
    for mode in ["--estimate", "--formulation"] {
        let mut cmd = mpirun_two();
        cmd.arg("run").arg(&path).args(["--quiet", "--out"]).arg(dir.join("p")).arg(mode);
        if mode == "--formulation" {
            cmd.arg("dual");
        }
        let out = cmd.args(["-dual_contact_condensation", "schur"]).output().expect("mpirun");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{mode}: {stderr}");
        assert!(
            stderr.contains("-dual_contact_condensation schur")
                && stderr.contains("runs on one process only (started on 2 MPI processes"),
            "{mode}: {stderr}"
        );
        assert!(!stderr.contains("nowhere"), "{mode}: the refusal came after meshing: {stderr}");
        assert!(!dir.join("p").join("report.json").exists());
    }
}
