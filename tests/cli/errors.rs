//! Usage errors, help, and bad input: clear, typed errors (naming the file and line) and no
//! partial or stale output.

use crate::edit::Edit;

use crate::{bin, block, run_err, run_ok, scene, scratch};
use std::process::Command;

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
    let text =
        std::fs::read_to_string(scene("examples/scenes/block.toml")).unwrap().edit("young = 210e9", "young = -210e9");
    let line = text.lines().position(|l| l.contains("young = -210e9")).unwrap() + 1;
    std::fs::write(&path, text).unwrap();
    let msg = run_err(bin().arg("run").arg(&path), 1);
    assert!(msg.contains(&format!("s.toml:{line}:")) && msg.contains("young"), "{msg}");
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

/// Every mistake on the command line exits 2, also those found after parsing: a PETSc option
/// without its value, a contact solver the scene's friction does not allow or a scene without
/// contact, a flag for a part the scene lacks, a benchmark solver that does not exist. A scene
/// that a command cannot take (export of a scene without contact) is not one (exit 1).
#[test]
fn every_command_line_mistake_exits_2() {
    let msg = run_err(bin().args(["run", "--quiet", "-pc_factor_levels"]), 2);
    assert!(msg.contains("-pc_factor_levels") && msg.contains("needs a value"), "{msg}");
    let msg = run_err(bin().args(["run", "--quiet", "--contact-solver", "snes_vi"]), 2);
    assert!(msg.contains("frictionless"), "{msg}");
    let msg = run_err(bin().arg("run").arg(block()).args(["--quiet", "--contact-solver", "newton"]), 2);
    assert!(msg.contains("no [contact] section"), "{msg}");
    let dir = scratch("export-usage");
    let msg = run_err(bin().arg("export").arg(block()).arg("--out").arg(dir.join("p.hdf5")), 1);
    assert!(msg.contains("no [contact] section"), "{msg}");
    let msg = run_err(
        bin().arg("adapt").arg(scene("examples/scenes/clamped_block.toml")).args([
            "--target",
            "5",
            "--contact-rate",
            "1",
        ]),
        2,
    );
    assert!(msg.contains("--contact-rate"), "{msg}");
    let msg =
        run_err(bin().args(["bench", "dual", "--max-dofs", "1e4", "--solvers", "mumps,nosuch", "--out"]).arg(&dir), 2);
    assert!(msg.contains("nosuch") && msg.contains("MUMPS Cholesky (default)"), "{msg}");
    assert!(!dir.join("bench_dual.md").exists(), "a refused benchmark ran");
    // A scene mistake is not a command-line one.
    run_err(bin().args(["run", "--quiet", "/nonexistent/scene.toml", "--out"]).arg(dir.join("o")), 1);
}

/// `--help` fits the terminal: at most 100 columns where the width is not known (a pipe), and
/// the terminal's width from COLUMNS when it is smaller.
#[test]
fn help_is_wrapped_to_the_terminal() {
    for args in
        [&["--help"][..], &["run", "--help"], &["adapt", "--help"], &["bench", "--help"], &["bench", "dual", "--help"]]
    {
        for (columns, limit) in [(None, 100), (Some("72"), 72)] {
            let mut cmd = bin();
            cmd.args(args);
            match columns {
                Some(c) => cmd.env("COLUMNS", c),
                None => cmd.env_remove("COLUMNS"),
            };
            let out = cmd.output().unwrap();
            let text = String::from_utf8_lossy(&out.stdout);
            assert!(out.status.success() && text.contains("Usage: signorini"), "{args:?}: {text}");
            for line in text.lines() {
                assert!(
                    line.chars().count() <= limit,
                    "{args:?}, {columns:?}: {} columns: {line}",
                    line.chars().count()
                );
            }
        }
    }
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
fn unwritable_output_leaves_nothing_half_written() {
    let dir = scratch("unwritable");
    let blocker = dir.join("file");
    std::fs::write(&blocker, "not a directory").unwrap();
    let msg = run_err(bin().args(["run", "--quiet", "--out"]).arg(blocker.join("out")), 1);
    // The typed error names the path it could not write and why.
    let target = blocker.join("out");
    assert!(
        msg.contains("cannot write output")
            && msg.contains(&target.display().to_string())
            && msg.contains("nothing was written"),
        "{msg}"
    );
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "stray files: {names:?}");
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
    // SIGXFSZ is ignored: the write fails with EFBIG, the program says so, exits 1 and removes
    // its partial file itself (it is not killed with a temporary file left behind).
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("File too large") && stderr.contains("solution.vtu"), "{stderr}");
    let names: Vec<String> =
        std::fs::read_dir(&small).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "a temporary file stayed: {names:?}");
    // The next run (without the limit) cleans whatever temporary file was left.
    run_ok(bin().arg("run").arg(scene("examples/scenes/cantilever.toml")).args(["--quiet", "--out"]).arg(&small));
    let names: Vec<String> =
        std::fs::read_dir(&small).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}

/// Results are all or nothing: when a previous result cannot be removed (here report.json is a
/// directory), every other previous result is removed, and the error names what is stale.
#[test]
fn previous_results_that_cannot_be_removed_are_named_stale() {
    let dir = scratch("stale-named");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    std::fs::remove_file(dir.join("report.json")).unwrap();
    std::fs::create_dir(dir.join("report.json")).unwrap();
    let msg = run_err(bin().args(["run", "--quiet", "--out"]).arg(&dir), 1);
    assert!(msg.contains("report.json") && msg.contains("stale") && msg.contains("earlier run"), "{msg}");
    for f in ["solution.vtu", "contact.csv", "contact.svg", "convergence.svg"] {
        assert!(!dir.join(f).exists(), "{f} of the earlier run is still there: {msg}");
    }
}

/// A run after a two-body run in the same directory leaves no body file of the earlier run.
#[test]
fn a_run_clears_the_body_files_of_an_earlier_two_body_run() {
    let dir = scratch("bodies-cleared");
    run_ok(bin().arg("run").arg(scene("examples/scenes/block_on_block.toml")).args(["--quiet", "--out"]).arg(&dir));
    let pvd = std::fs::read_to_string(dir.join("solution.pvd")).unwrap();
    let bodies: Vec<String> = pvd.split("file=\"").skip(1).map(|r| r.split('"').next().unwrap().to_string()).collect();
    assert!(bodies.len() == 2 && bodies.iter().all(|b| dir.join(b).is_file()), "{pvd}");
    let user_file = dir.join("notes.vtu");
    std::fs::write(&user_file, "not ours").unwrap();
    run_ok(bin().arg("run").arg(block()).args(["--quiet", "--out"]).arg(&dir));
    assert!(!dir.join("solution.pvd").exists());
    for b in &bodies {
        assert!(!dir.join(b).exists(), "stale {b}");
    }
    assert!(user_file.exists(), "a file the runs did not write was removed");
}
