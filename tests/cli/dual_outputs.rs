//! What a run of the dual formulation writes and counts, and what `--estimate` writes when the
//! dual cannot take the scene (issue 23, items 5 and 9).
use super::*;

/// A dual contact run writes `contact.csv`, `contact.svg` and `convergence.svg` like a primal
/// one. On the frictionless patch (exact: uniform pressure p = 1e6 Pa, the whole bottom closed)
/// the CSV has both ends of every contact edge, in order of arc length over the bottom face
/// [0, 2], each at pressure p with no tangential traction and a closed gap. The counts of the
/// summary are HCT dofs: 3 per vertex and 1 per edge (Euler: edges = nodes + triangles − 1),
/// and on this body, loaded or in contact on its whole boundary, the boundary conditions set
/// all the boundary dofs (3 per boundary vertex, 1 per boundary edge; the anchor's three
/// included): 4 per boundary edge.
#[test]
fn dual_contact_run_writes_contact_files_and_counts_hct_dofs() {
    let dir = scratch("dual-contact-files");
    let out = run_ok(
        bin()
            .arg("run")
            .arg(scene("examples/scenes/contact_patch.toml"))
            .args(["--formulation", "dual", "--out"])
            .arg(&dir),
    );
    for name in ["solution.vtu", "report.json", "contact.csv", "contact.svg", "convergence.svg"] {
        assert!(dir.join(name).is_file(), "{name} missing");
    }
    for name in ["contact.svg", "convergence.svg"] {
        let text = std::fs::read_to_string(dir.join(name)).unwrap();
        assert!(text.contains("<svg") && text.trim_end().ends_with("</svg>"), "{name}: {text}");
    }
    let r = report(&dir);
    let text = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(signorini::problem::CONTACT_CSV_HEADER));
    let rows: Vec<Vec<String>> = lines.map(|l| l.split(',').map(str::to_string).collect()).collect();
    assert_eq!(rows.len(), r["contact"]["points"].as_u64().unwrap() as usize);
    let bottom_edges = rows.len() / 2;
    assert!(bottom_edges >= 4 && rows.len() == 2 * bottom_edges, "{} rows", rows.len());
    let p = 1e6;
    let mut last_s = 0.0;
    for row in &rows {
        let v = |k: usize| row[k].parse::<f64>().unwrap();
        let (s, y, pressure, traction, gap) = (v(0), v(2), v(3), v(4), v(5));
        assert!(s >= last_s && y == 0.0 && (v(1) - s).abs() < 1e-12, "{row:?}");
        last_s = s;
        assert!((pressure - p).abs() < 1e-8 * p && traction.abs() < 1e-8 * p, "{row:?}");
        // The top moves down by 1e-5 m: closed means a gap at round-off of that.
        assert!(gap.abs() < 1e-12 && row[8] != "open", "{row:?}");
    }
    assert!((last_s - 2.0).abs() < 1e-12, "arc length ends at {last_s}");
    let (nodes, cells, edges) =
        (r["nodes"].as_u64().unwrap(), r["elements"].as_u64().unwrap(), r["boundary_edges"].as_u64().unwrap());
    assert_eq!(r["dofs"].as_u64().unwrap(), 3 * nodes + nodes + cells - 1, "{}", r["dual"]);
    assert_eq!(r["fixed_dofs"].as_u64().unwrap(), 4 * edges, "{}", r["dual"]);
    assert_eq!(r["fixed_dofs"], r["dual"]["fixed_hct_dofs"]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    let counts = format!("{} dofs ({} fixed)", r["dofs"], r["fixed_dofs"]);
    assert!(stdout.replace("\n          ", " ").contains(&counts), "{counts} not in {stdout}");
}

/// `--estimate` on the default scene: its corner point support carries a force, which the
/// dual cannot represent, so the estimate is refused (exit 1) — but the primal results are
/// written (solution, report, contact files; no estimate in the report) and the message names
/// a scene that works, which does.
#[test]
fn estimate_refused_writes_the_primal_results_and_names_a_scene_that_works() {
    let dir = scratch("estimate-refused");
    let out = bin().args(["run", "--estimate", "--out"]).arg(&dir).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("point support at (0.04, 0) carries a force"), "{stderr}");
    assert!(stderr.contains("square_block_tresca.toml"), "{stderr}");
    assert!(stderr.contains("primal results were written") && !stderr.contains("no result was written"), "{stderr}");
    for name in ["solution.vtu", "report.json", "contact.csv", "contact.svg", "convergence.svg"] {
        assert!(dir.join(name).is_file(), "{name} missing");
    }
    let r = report(&dir);
    assert_eq!(r["formulation"], "primal");
    assert!(r.get("estimate").is_none() && r.get("dual").is_none(), "{r}");
    let force = r["results"]["reactions"]["point [0.04, 0]"][1].as_f64().unwrap();
    assert!(force > 1e4, "{}", r["results"]["reactions"]);
    // The scene named works.
    let dir = scratch("estimate-tresca");
    run_ok(
        bin()
            .arg("run")
            .arg(scene("examples/scenes/square_block_tresca.toml"))
            .args(["--quiet", "--estimate", "--out"])
            .arg(&dir),
    );
    let e = &report(&dir)["estimate"];
    assert_eq!(e["kind"], "guaranteed_bound", "{e}");
}
