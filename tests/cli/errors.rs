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
    // The next run (without the limit) cleans whatever temporary file was left.
    run_ok(bin().arg("run").arg(scene("examples/scenes/cantilever.toml")).args(["--quiet", "--out"]).arg(&small));
    let names: Vec<String> =
        std::fs::read_dir(&small).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
    assert!(names.iter().all(|n| !n.ends_with(".tmp")), "{names:?}");
}
