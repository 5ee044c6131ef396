//! `run` and what it writes: the default scene, solution.vtu and the contact fields read back
//! with meshio, contact.csv and the pictures, the terminal summary, progress, warnings, and the
//! Gmsh mesh cache.

use crate::edit::Edit;

use crate::{bin, block, python, report, run_err, run_ok, scene, scratch};
use std::path::{Path, PathBuf};
use std::process::Command;

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
    // Each phase that does work takes time, and the phases add up to the total.
    for phase in ["mesh", "assemble", "solve", "output"] {
        assert!(r["timings"][phase].as_f64().unwrap() > 0.0, "timings.{phase}: {}", r["timings"]);
    }
    let timings = r["timings"].as_object().unwrap();
    let sum: f64 = timings.iter().filter(|(k, _)| *k != "total").map(|(_, v)| v.as_f64().unwrap()).sum();
    let total = timings["total"].as_f64().unwrap();
    assert!((sum - total).abs() <= 1e-9 * total, "phases add up to {sum}, total {total}: {}", r["timings"]);
    assert!(r["memory"]["peak_bytes"].as_u64().unwrap() > 1_000_000);
    assert!(r["results"]["equilibrium_residual"].as_f64().unwrap() < 1e-9);
    // No temporary files left next to the outputs.
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().into_string().unwrap()).collect();
    assert_eq!(names.len(), 5, "solution.vtu, report.json and the three contact files: {names:?}");
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
            .edit("order = 1", &format!("order = {order}"));
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
        for what in ["peak pressure", "closed zone 1: s in [", "closed", "open", "resultant", "independent check"] {
            assert!(flat.contains(what), "{name}: no '{what}': {stdout}");
        }
        // Stick and slip with friction (the default scene); Hertz is frictionless: closed only.
        let frictional = scene_file.is_none();
        assert_eq!(flat.contains(" stick, ") && flat.contains(" slip)"), frictional, "{name}: {stdout}");
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

/// The default scene with its `[contact]` friction lines replaced by `friction`.
fn default_scene_with(dir: &Path, friction: &str) -> PathBuf {
    let text = std::fs::read_to_string(scene("examples/scenes/default.toml")).unwrap();
    let text = text.replace("friction = \"coulomb\"\nmu = 1.0", friction);
    assert!(text.contains(friction), "the default scene's friction lines moved");
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// report.json writes the friction law as an object (law and coefficient, no string to parse),
/// and the terminal the Tresca threshold in Pa as the scene gives it (N/m²).
#[test]
fn friction_is_an_object_in_the_report() {
    let dir = scratch("friction-object");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    assert_eq!(report(&dir)["contact"]["friction"], serde_json::json!({"law": "coulomb", "mu": 1.0}));
    assert!(report(&dir)["contact"].get("zone").is_none(), "the projected zone is gone: zones is right");
    let tresca = default_scene_with(&dir, "friction = \"tresca\"\nthreshold = 5e7");
    let out = run_ok(bin().arg("run").arg(&tresca).arg("--out").arg(dir.join("tresca")));
    assert_eq!(
        report(&dir.join("tresca"))["contact"]["friction"],
        serde_json::json!({"law": "tresca", "threshold": 5e7})
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("Tresca, threshold = 5e7 Pa"), "{stdout}");
}

/// Without friction a closed point is "closed" (not "slip") in report.json, on the terminal, in
/// contact.csv and in solution.vtu (contact_status 3); the counts agree with the rows, and the
/// closed rows are exactly those with a pressure.
#[test]
fn frictionless_closed_points_are_closed() {
    let dir = scratch("frictionless");
    let path = default_scene_with(&dir, "friction = \"none\"");
    let out = run_ok(bin().arg("run").arg(&path).arg("--out").arg(&dir));
    let r = report(&dir);
    let c = &r["contact"];
    assert_eq!(c["friction"], serde_json::json!({"law": "none"}));
    let (points, open, closed) =
        (c["points"].as_u64().unwrap(), c["open"].as_u64().unwrap(), c["closed"].as_u64().unwrap());
    assert!(closed > 0 && open + closed == points, "{c}");
    assert_eq!((c["stick"].as_u64(), c["slip"].as_u64()), (Some(0), Some(0)), "{c}");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(&format!("{closed} closed, {open} open")) && !stdout.contains("slip"), "{stdout}");
    let csv = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.iter().filter(|r| r[8] == "closed").count() as u64, closed, "{csv}");
    assert!(rows.iter().all(|r| r[8] == "closed" || r[8] == "open"), "{csv}");
    let peak = c["peak_pressure"]["pressure"].as_f64().unwrap();
    for row in &rows {
        let pressure: f64 = row[3].parse().unwrap();
        assert_eq!(row[8] == "closed", pressure > 1e-12 * peak, "{row:?}");
    }
    let out = python(&format!(
        "m = meshio.read(r'{}')\ns = m.point_data['contact_status']\nprint(int((s == 3).sum()), int((s == 0).sum()), int(((s == 1) | (s == 2)).sum()))",
        dir.join("solution.vtu").display()
    ));
    assert_eq!(out.split_whitespace().collect::<Vec<_>>(), [closed.to_string(), open.to_string(), "0".into()], "{out}");
}

/// A 1 MB scene title: the summary shortens it (an ellipsis), stays within 100 columns and
/// short; report.json keeps it whole. (The wrapping is linear by construction: each character
/// is copied once; no timing is asserted.)
#[test]
fn a_huge_title_is_shortened_in_the_summary() {
    let dir = scratch("huge-title");
    let title = "T".repeat(1 << 20);
    let text = std::fs::read_to_string(scene("examples/scenes/block.toml")).unwrap();
    let start = text.find("title = ").unwrap();
    let end = start + text[start..].find('\n').unwrap();
    let path = dir.join("scene.toml");
    std::fs::write(&path, format!("{}title = \"{title}\"{}", &text[..start], &text[end..])).unwrap();
    let out = run_ok(bin().arg("run").arg(&path).arg("--out").arg(dir.join("out")));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.len() < 4000, "{} bytes of summary", stdout.len());
    assert!(stdout.lines().all(|l| l.chars().count() <= 100), "{stdout}");
    assert!(stdout.contains("T…"), "{stdout}");
    // The title (one word longer than a line: cut over lines) is 199 characters and the ellipsis.
    let joined: String = stdout.lines().map(|l| l.chars().skip(10).collect::<String>()).collect();
    assert!(joined.contains(&format!("{}…", "T".repeat(199))) && !joined.contains(&"T".repeat(200)), "{stdout}");
    assert_eq!(report(&dir.join("out"))["title"].as_str().map(str::len), Some(1 << 20));
}

/// Issue 23, 1c: a contact part that never closes is named in a `contact_open` warning (the
/// run is right for the model, the model is doubtful), with the obstacle; when the body lies
/// inside the obstacle (a reversed normal) the warning, or for a body that only the contact
/// holds the error, says so and how to fix it instead of "lifts off".
#[test]
fn a_contact_that_never_closes_is_named() {
    let base = std::fs::read_to_string(scene("examples/scenes/default.toml")).unwrap();
    let contact_open = |dir: &Path| -> Vec<String> {
        report(dir)["warnings"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|w| w["kind"] == "contact_open")
            .map(|w| w["message"].as_str().unwrap().to_string())
            .collect()
    };
    // The normal reversed: the block lies in the obstacle's half-plane, every point open.
    let reversed = base.replacen("normal = [0.0, 1.0]", "normal = [0.0, -1.0]", 1);
    assert_ne!(reversed, base);
    let dir = scratch("open-reversed");
    std::fs::write(dir.join("s.toml"), &reversed).unwrap();
    let out = run_ok(bin().arg("run").arg(dir.join("s.toml")).arg("--out").arg(dir.join("out")));
    let messages = contact_open(&dir.join("out"));
    assert_eq!(messages.len(), 1, "{messages:?}");
    let m = &messages[0];
    assert!(m.contains("'bottom'") && m.contains("half-plane") && m.contains("reverse it (normal = [0, 1])"), "{m}");
    assert!(String::from_utf8_lossy(&out.stderr).contains("warning   contact_open"));
    // A gap the loads never close: the part and the obstacle, no word of a reversed normal.
    let far = base.replacen("normal = [0.0, 1.0]", "normal = [0.0, 1.0]\ngap = 1e-3", 1);
    let dir = scratch("open-gap");
    std::fs::write(dir.join("s.toml"), &far).unwrap();
    run_ok(bin().arg("run").arg(dir.join("s.toml")).arg("--out").arg(dir.join("out")));
    let messages = contact_open(&dir.join("out"));
    assert_eq!(messages.len(), 1, "{messages:?}");
    assert!(messages[0].contains("'bottom'") && messages[0].contains("the gap") && !messages[0].contains("reverse"));
    // The default scene closes: no such warning.
    let dir = scratch("closed");
    run_ok(bin().args(["run", "--quiet", "--out"]).arg(&dir));
    assert!(contact_open(&dir).is_empty());
    // A body held by the contact alone, normal reversed: the error says why, not "lifts off".
    let patch = std::fs::read_to_string(scene("examples/scenes/contact_patch.toml")).unwrap();
    let dir = scratch("patch-reversed");
    let text = patch.replacen("normal = [0.0, 1.0]", "normal = [0.0, -1.0]", 1);
    assert_ne!(text, patch);
    std::fs::write(dir.join("s.toml"), text).unwrap();
    for route in [None, Some("newton")] {
        let mut cmd = bin();
        cmd.arg("run").arg(dir.join("s.toml")).arg("--out").arg(dir.join("out"));
        if let Some(r) = route {
            cmd.args(["--contact-solver", r]);
        }
        let msg = run_err(&mut cmd, 1);
        assert!(
            msg.contains("lies behind the line")
                && msg.contains("hint: the normal points")
                && !msg.contains("lifts off"),
            "{route:?}: {msg}"
        );
    }
}
