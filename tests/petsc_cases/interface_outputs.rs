//! The interface's files of a run, written by `ElasticityProblem::write_output` and
//! `write_step_output` from interface snapshots set by hand (the snapshot the interface laws'
//! solves leave in `ElasticityProblem::interface`): a static run's `interface.vtu` and report
//! entry, a load path's `steps/interface_NNNN.vtu`, `interface.pvd`, history columns and τ–δ
//! plot.
use super::contact::{example, set_line};
use signorini::interface_law::{InterfacePointState, InterfaceSnapshot};
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;

fn ensure(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(message())
    }
}

/// Five points along the block's bottom; the slip grows with `k`, the opening with the point.
fn snapshot(k: usize) -> InterfaceSnapshot {
    let points = (0..5)
        .map(|i| InterfacePointState {
            x: [0.01 * i as f64, 0.0],
            opening: 1e-8 * i as f64,
            slip: 1e-6 * (k * i) as f64,
            traction_normal: -1e7,
            traction_tangential: 1e6 * k as f64,
            adhesion: Some(1.0 - 0.1 * k as f64),
            damage: None,
            law_residual: 1e-14 * k as f64,
        })
        .collect();
    InterfaceSnapshot { time: k as f64, laws: vec!["rccm".into()], points, iterations: 3 }
}

fn scratch(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-interface-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

fn report_json(dir: &std::path::Path) -> Result<serde_json::Value, String> {
    let text = std::fs::read_to_string(dir.join("report.json")).map_err(|e| e.to_string())?;
    serde_json::from_str(&text).map_err(|e| e.to_string())
}

pub fn interface_files_of_a_static_run(s: &Session) -> Result<(), String> {
    let (text, file) = example("square_block.toml");
    let text = set_line(&text, "cell_size", "cell_size = 5e-3");
    let scene = Scene::from_str(&text, &file).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    p.solve().map_err(|e| e.to_string())?;
    p.postprocess().map_err(|e| e.to_string())?;
    let dir = scratch("static");
    // Without an interface: no interface file, no report entry.
    let (report, written) = p.write_output(&dir).map_err(|e| e.to_string())?;
    ensure(report.interface.is_none() && !dir.join("interface.vtu").exists(), || {
        "an interface file without a law".into()
    })?;
    ensure(!written.iter().any(|w| w.ends_with("interface.vtu")), || format!("{written:?}"))?;
    p.interface = Some(snapshot(2));
    let (report, written) = p.write_output(&dir).map_err(|e| e.to_string())?;
    ensure(written.contains(&dir.join("interface.vtu")), || format!("interface.vtu not written: {written:?}"))?;
    let entry = report.interface.as_ref().ok_or("no interface entry in the report")?;
    ensure(entry.laws == ["rccm"] && entry.last.points == 5, || format!("{entry:?}"))?;
    ensure(entry.last.min_adhesion == Some(0.8) && entry.worst_law_residual == 2e-14, || format!("{entry:?}"))?;
    ensure(entry.traced_points.is_empty(), || "a static run traces nothing".into())?;
    let json = report_json(&dir)?;
    ensure(json["interface"]["final"]["max_slip"] == 8e-6, || format!("{}", json["interface"]))?;
    ensure(json["interface"]["worst_law_residual"] == 2e-14, || format!("{}", json["interface"]))?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

pub fn interface_files_of_a_load_path(s: &Session) -> Result<(), String> {
    let (text, file) = example("square_block.toml");
    let text = format!("{}\n[evolution]\nsteps = 3\n", set_line(&text, "cell_size", "cell_size = 5e-3"));
    let scene = Scene::from_str(&text, &file).map_err(|e| e.to_string())?;
    let path = signorini::evolution::LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no path")?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    let dir = scratch("path");
    p.solve_load_path(&path, signorini::evolution::EachIncrement::Postprocess, &mut |_, _| Ok(()))
        .map_err(|e| e.to_string())?;
    // The increments' interface, as the laws' solves would leave it, then each increment's files.
    for k in 1..=3 {
        p.interface = Some(snapshot(k));
        p.write_step_output(&dir, k).map_err(|e| e.to_string())?;
    }
    let (report, written) = p.write_output(&dir).map_err(|e| e.to_string())?;
    for name in ["interface.vtu", "interface.pvd", "interface_tau_delta.svg", "history.csv"] {
        ensure(written.contains(&dir.join(name)), || format!("{name} not written: {written:?}"))?;
    }
    for k in 1..=3 {
        let step = dir.join(format!("steps/interface_{k:04}.vtu"));
        ensure(step.exists(), || format!("{} missing", step.display()))?;
    }
    let pvd = std::fs::read_to_string(dir.join("interface.pvd")).map_err(|e| e.to_string())?;
    ensure(pvd.matches("<DataSet").count() == 3 && pvd.contains("file=\"steps/interface_0003.vtu\""), || pvd.clone())?;
    let csv = std::fs::read_to_string(dir.join("history.csv")).map_err(|e| e.to_string())?;
    let lines: Vec<&str> = csv.lines().collect();
    ensure(
        lines.len() == 4 && lines[0].ends_with(signorini::evolution::history::HISTORY_CSV_INTERFACE_COLUMNS),
        || csv.clone(),
    )?;
    // increment 2: min β 0.8, no damage, max opening 4e-8, max slip 8e-6, residual 2e-14
    ensure(lines[2].ends_with(",8e-1,,4e-8,8e-6,2e-14"), || lines[2].to_string())?;
    let entry = report.interface.as_ref().ok_or("no interface entry")?;
    // the default traced points: the first, middle and last
    ensure(entry.traced_points == [[0.0, 0.0], [0.02, 0.0], [0.04, 0.0]], || format!("{entry:?}"))?;
    ensure(entry.worst_law_residual == 3e-14, || format!("{entry:?}"))?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}
