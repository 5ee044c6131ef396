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
