//! PETSc options (on the command line and in the scene) and the contact solver chosen on the
//! command line: what they select, their errors and warnings.

use crate::{bin, block, mpirun_two, relative_difference, report, run_err, run_ok, scene, scratch};

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
fn missing_petsc_option_value_is_refused() {
    let msg = run_err(bin().args(["run", "--quiet", "-ksp_type", "cg", "-pc_type", "icc", "-pc_factor_levels"]), 2);
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
fn unused_petsc_option_is_reported_as_a_warning() {
    let dir = scratch("unused");
    let out = run_ok(bin().args(["run", "--out"]).arg(&dir).args(["-ksp_tyep", "cg"]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("-ksp_tyep") && stderr.contains("a typo"), "{stderr}");
    let r = report(&dir);
    assert!(r["solver"]["unused_options"].to_string().contains("ksp_tyep"), "{r}");
    let warnings = r["warnings"].as_array().unwrap();
    assert!(
        warnings
            .iter()
            .any(|w| w["kind"] == "unused_option" && w["message"].as_str().unwrap().contains("-ksp_tyep cg")),
        "{r}"
    );
}

/// `-ksp_type cg -pc_type icc` on the default contact route (newton_full): the warning (on the
/// terminal and in report.json) names the route that ignored them and the prefix that reaches
/// its linear solver; with that prefix nothing is unused, and with --contact-solver newton the
/// options reach the main linear solver (CG + ICC in the report).
#[test]
fn options_the_contact_route_does_not_read_name_the_route_and_the_prefix() {
    let dir = scratch("route-options");
    let out = run_ok(bin().args(["run", "--out"]).arg(&dir).args(["-ksp_type", "cg", "-pc_type", "icc"]));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("newton_full") && stderr.contains("-contact_ksp_type cg"), "{stderr}");
    let r = report(&dir);
    let messages: Vec<&str> = r["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|w| w["kind"] == "unused_option")
        .map(|w| w["message"].as_str().unwrap())
        .collect();
    assert_eq!(messages.len(), 2, "{r}");
    assert!(messages[0].contains("-contact_ksp_type cg") || messages[1].contains("-contact_ksp_type cg"), "{r}");
    assert!(messages.iter().any(|m| m.contains("-contact_pc_type icc")), "{r}");
    // The prefixed options are read (the full-space system is indefinite: GMRES + ILU may fail
    // over to the condensed route, which the report says; either way the options are used).
    let dir = scratch("route-options-prefixed");
    run_ok(bin().args(["run", "--out"]).arg(&dir).args(["-contact_ksp_type", "gmres", "-contact_pc_type", "lu"]));
    let r = report(&dir);
    assert_eq!(r["solver"]["unused_options"].as_array().unwrap().len(), 0, "{r}");
    // The condensed route reads the main solver's options.
    let dir = scratch("route-options-condensed");
    run_ok(bin().args(["run", "--contact-solver", "newton", "--out"]).arg(&dir).args([
        "-ksp_type",
        "cg",
        "-pc_type",
        "icc",
    ]));
    let r = report(&dir);
    assert_eq!(r["solver"]["unused_options"].as_array().unwrap().len(), 0, "{r}");
    assert_eq!((r["solver"]["ksp_type"].as_str(), r["solver"]["pc_type"].as_str()), (Some("cg"), Some("icc")), "{r}");
}

#[test]
fn a_factorisation_out_of_memory_is_named_and_the_advice_works() {
    let msg = run_err(bin().arg("run").arg(block()).args(["--quiet", "-mat_mumps_icntl_23", "1"]), 1);
    assert!(msg.contains("out of memory") && msg.contains("INFOG(1)") && msg.contains("-pc_type hypre"), "{msg}");
    // The advice: an iterative solver instead of the factorisation; it is the one used, and it
    // gives the factorisation's answer.
    let dir = scratch("oom-advice");
    run_ok(
        bin()
            .arg("run")
            .arg(block())
            .args(["--quiet", "-mat_mumps_icntl_23", "1", "-ksp_type", "cg", "-pc_type", "hypre", "--out"])
            .arg(&dir),
    );
    let r = report(&dir);
    assert_eq!(r["solver"]["ksp_type"], "cg", "{}", r["solver"]);
    assert_eq!(r["solver"]["pc_type"], "hypre", "{}", r["solver"]);
    let reference = scratch("oom-advice-ref");
    run_ok(bin().arg("run").arg(block()).args(["--quiet", "--out"]).arg(&reference));
    let d = relative_difference(&reference.join("solution.vtu"), &dir.join("solution.vtu"));
    assert!(d < 1e-6, "CG + hypre differs from MUMPS by {d:e}");
}

/// Issue 23, 6: MUMPS out of memory in the contact route's factorisation (the Schur
/// complement of the block elimination) is named, with advice; the advice (the condensed
/// route with CG) runs.
#[test]
fn the_contact_factorisation_out_of_memory_is_named() {
    let msg = run_err(bin().args(["run", "--quiet", "-mat_mumps_icntl_23", "1"]), 1);
    assert!(msg.contains("out of memory") && msg.contains("INFOG(1)") && msg.contains("Schur complement"), "{msg}");
    assert!(msg.contains("-mat_mumps_icntl_14") && msg.contains("--contact-solver newton -ksp_type cg"), "{msg}");
    assert!(!msg.contains("NaN") && !msg.contains("not finite"), "{msg}");
    let dir = scratch("contact-oom-advice");
    run_ok(
        bin()
            .args(["run", "--quiet", "--contact-solver", "newton", "-ksp_type", "cg", "-pc_type", "hypre", "--out"])
            .arg(&dir),
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
fn contact_solver_from_the_command_line() {
    let reference = scratch("cs-ref");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&reference));
    let dir = scratch("cs-relax");
    run_ok(bin().args(["run", "--quiet", "--contact-solver", "relaxation", "--out"]).arg(&dir));
    let r = report(&dir);
    assert!(r["contact"]["solver"].as_str().unwrap().contains("relaxation"), "{r}");
    let d = relative_difference(&reference.join("solution.vtu"), &dir.join("solution.vtu"));
    assert!(d < 1e-6, "relaxation differs from Newton by {d:e}");
    let msg = run_err(bin().args(["run", "--quiet", "--contact-solver", "snes_vi"]), 2);
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
