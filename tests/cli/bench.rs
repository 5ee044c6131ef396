//! `bench`: every benchmark writes its table (with provenance and failed cases as rows) and its
//! plot.

use crate::{bin, run_err, run_ok, scratch};

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

#[test]
fn bench_dual_writes_its_table_and_plot() {
    let dir = scratch("bench-dual");
    let out = bin().args(["bench", "dual", "--max-dofs", "2000", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let table = std::fs::read_to_string(dir.join("bench_dual.md")).unwrap();
    assert!(table.contains("MUMPS") && table.contains("primal P2"), "{table}");
    // Every solver of the benchmark is a row or a failed case; the docs' one failed case is
    // SYMMLQ + SSOR (it stalls on the HCT system), every other solver runs: a row of the table,
    // not a failed case (CG + SSOR among them).
    let (rows, failed) = (table_rows(&table), failed_rows(&table));
    let solvers = signorini::bench::dual::dual_solvers();
    assert!(solvers.len() >= 6, "{table}");
    for name in solvers.iter().map(|s| s.solver.name) {
        let cell = format!("| {name} |");
        let (ran, failed_here) = (rows.iter().any(|r| r.contains(&cell)), failed.iter().any(|r| r.contains(&cell)));
        assert!(ran ^ failed_here, "{name}: a row or a failed case, once: {table}");
        if name != "SYMMLQ + SSOR" {
            assert!(ran, "{name} must run (the docs say it does): {table}");
        }
    }
    assert_provenance(&table, "bench dual --max-dofs 2000");
    assert!(std::fs::read_to_string(dir.join("bench_dual.svg")).unwrap().contains("<svg"));
}

/// `--solvers` runs only the solvers it names (an exact name alone, else every name containing
/// it): one MUMPS row at 1e3 dofs, none of the others, no failed case.
#[test]
fn bench_solvers_runs_only_the_named_solvers() {
    let dir = scratch("bench-solvers");
    let out = run_ok(
        bin().args(["bench", "dual", "--max-dofs", "2000", "--solvers", "mumps cholesky (DEFAULT)", "--out"]).arg(&dir),
    );
    let table = std::fs::read_to_string(dir.join("bench_dual.md")).unwrap();
    let rows = table_rows(&table);
    assert_eq!(rows.len(), 1, "{table}");
    assert!(rows[0].contains("| MUMPS Cholesky (default) |"), "{table}");
    assert!(failed_rows(&table).is_empty(), "{table}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("[1/1]"), "one case ran");
    let out = run_ok(bin().args(["bench", "dual", "--max-dofs", "2000", "--solvers", "mumps", "--out"]).arg(&dir));
    let table = std::fs::read_to_string(dir.join("bench_dual.md")).unwrap();
    let names: Vec<&str> = table_rows(&table).iter().map(|r| r.split('|').nth(3).unwrap().trim()).collect();
    assert_eq!(names, ["MUMPS Cholesky (default)", "saddle point, MUMPS LDLᵀ"], "{table}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("[2/2]"));
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
    // Every strategy is a row or a failed case; the docs' failed cases are three-step CG +
    // hypre PILUT and brute SYMMLQ + SSOR, every other strategy runs at 1e3 (a row, not failed).
    let (rows, failed) = (table_rows(&table), failed_rows(&table));
    for name in signorini::bench::dual_contact::STRATEGIES.iter().map(|s| s.name) {
        let cell = format!("| {name} |");
        assert_eq!(rows.iter().chain(&failed).filter(|r| r.contains(&cell)).count(), 1, "{name}: {table}");
        if !["three-step, CG + hypre PILUT", "brute, SYMMLQ + SSOR"].contains(&name) {
            assert!(rows.iter().any(|r| r.contains(&cell)), "{name} must run (the docs say it does): {table}");
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

/// `bench scale`, tiny: every part writes its table (each route and the linear solve a row per
/// strip size; ranks 1 and, with mpirun and two cores, 2 in the scaling tables) and the plots;
/// `--part` keeps one part.
#[test]
fn bench_scale_small_writes_its_tables_and_plots() {
    let dir = scratch("bench-scale");
    let out = bin().args(["bench", "scale", "--max-dofs", "5e3", "--out"]).arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let md = std::fs::read_to_string(dir.join("bench_scale.md")).unwrap();
    assert_provenance(&md, "bench scale --max-dofs 5e3");
    assert!(failed_rows(&md).is_empty(), "{md}");
    let rows = table_rows(&md);
    // Strips of 100 points (one body, two bodies) and 400 (one body) up to 5e3 dofs.
    for (scene, m) in [("one body", 100), ("two bodies", 100), ("one body", 400)] {
        for route in ["one linear solve (MUMPS)", "dense_schur", "sparse_lu", "auto"] {
            let cells = format!("| {scene} | {m} |");
            assert_eq!(
                rows.iter()
                    .filter(|r| r.starts_with(&cells) && r.split('|').nth(4).map(str::trim) == Some(route))
                    .count(),
                1,
                "{scene}, {m} points, {route}: {md}"
            );
        }
    }
    let ranks = std::thread::available_parallelism().map_or(1, |n| n.get());
    for heading in ["## Strong scaling", "## Weak scaling"] {
        let section = &md[md.find(heading).unwrap_or_else(|| panic!("{heading}: {md}"))..];
        let rows = table_rows(section);
        assert_eq!(rows.len(), 4 * ranks, "{heading}: {md}");
        for scene in signorini::bench::scale::SCALING_SCENES {
            assert!(rows.iter().any(|r| r.starts_with(&format!("| {scene} | 1 |"))), "{scene}: {md}");
        }
    }
    for svg in ["bench_scale_points.svg", "bench_scale_speedup.svg"] {
        assert!(std::fs::read_to_string(dir.join(svg)).unwrap().contains("<svg"), "{svg}");
    }

    let dir = scratch("bench-scale-part");
    run_ok(bin().args(["bench", "scale", "--part", "strong", "--max-dofs", "2e3", "--out"]).arg(&dir));
    let md = std::fs::read_to_string(dir.join("bench_scale.md")).unwrap();
    assert!(md.contains("## Strong scaling") && !md.contains("## Weak") && !md.contains("## Contact points"), "{md}");
    assert!(!dir.join("bench_scale_points.svg").exists() && dir.join("bench_scale_speedup.svg").exists());
}
