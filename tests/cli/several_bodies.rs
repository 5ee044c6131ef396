//! Scenes with several bodies: `run` solves them and reports every body, the contact solver
//! option reaches every pair, the commands that cannot solve them refuse.

use crate::edit::Edit;

use crate::{bin, report, run_err, run_ok, scene, scratch};

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
        .edit("origin = [0.0, 0.0]", "origin = [0.0, -0.005]");
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
        run_err(bin().arg("run").arg(&path).args(["--quiet", "--contact-solver", "snes_vi", "--out"]).arg(&out), 2);
    assert!(stderr.contains("snes_vi"), "{stderr}");
    let stderr =
        run_err(bin().arg("run").arg(&path).args(["--quiet", "--contact-solver", "tao", "--out"]).arg(&out), 2);
    assert!(stderr.contains("Tresca"), "{stderr}");
    assert!(!out.join("report.json").exists());
}
