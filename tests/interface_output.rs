//! The outputs of an interface law, from synthetic snapshots: `interface.vtu` read back by an
//! independent reader (Python meshio, bit for bit), the interface's columns of `history.csv`,
//! the τ–δ plot (parsed by Python's XML parser), the traced points, the summaries (oracles
//! computed by hand from the snapshot's values), and the clearing of a previous run's files.
//!
//! Needs `python3` with `meshio` (as tests/output.rs).
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;
use signorini::error::Error;
use signorini::evolution::history::{
    write_history_csv_with_interface, write_load_path_outputs_with_interface, HISTORY_CSV, HISTORY_CSV_HEADER,
    HISTORY_CSV_INTERFACE_COLUMNS,
};
use signorini::evolution::StepRecord;
use signorini::interface_law::{InterfacePointState, InterfaceSnapshot};
use signorini::output::interface::{
    trace_points, write_interface_vtu, write_tau_delta_svg, InterfaceHistory, InterfaceSummary, INTERFACE_PVD,
    INTERFACE_VTU, TAU_DELTA_SVG,
};
use signorini::output::pvd::interface_step_file_name;
use signorini::output::{clear_previous_run, RUN_FILES};

fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-interface-output-{}-{test}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

/// Point `i` of `n` along y = 0.1 x, values with awkward bits; adhesion and damage as given.
fn point(i: usize, adhesion: Option<f64>, damage: Option<f64>) -> InterfacePointState {
    let x = i as f64 / 3.0;
    InterfacePointState {
        x: [x, 0.1 * x - 1e-300],
        opening: if i.is_multiple_of(2) { 0.0 } else { 1e-7 * (i as f64).sqrt() },
        slip: -2.5e-6 * (i as f64 - 1.5),
        traction_normal: -1e6 / (1.0 + i as f64) / 3.0,
        traction_tangential: 2e5 * (i as f64 * 0.7).sin(),
        adhesion,
        damage,
        law_residual: 1e-13 * (i + 1) as f64,
    }
}

fn snapshot(time: f64, points: Vec<InterfacePointState>) -> InterfaceSnapshot {
    InterfaceSnapshot { time, laws: vec!["rccm".into()], points, iterations: 7 }
}

/// meshio's view of `file` as JSON, floats as IEEE bit patterns (NaN as its pattern too).
fn read_with_meshio(file: &Path) -> Value {
    const SCRIPT: &str = r#"
import json, struct, sys
import meshio
import numpy as np
def bits(a):
    a = np.asarray(a, dtype=np.float64)
    return [struct.unpack("<Q", struct.pack("<d", float(x)))[0] for x in a.ravel()]
m = meshio.read(sys.argv[1])
print(json.dumps({
    "points": bits(m.points),
    "cells": [{"type": b.type, "data": [int(x) for x in np.asarray(b.data).ravel()]} for b in m.cells],
    "point_data": {k: bits(v) for k, v in m.point_data.items()},
}))
"#;
    let out = Command::new("python3").arg("-c").arg(SCRIPT).arg(file).output().unwrap_or_else(|e| {
        panic!("cannot run python3 ({e}): the .vtu tests need python3 with meshio (pip install meshio)")
    });
    assert!(
        out.status.success(),
        "meshio could not read {}: {}\n(the .vtu tests need python3 with meshio)",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A point's value for one array.
type PointValue = fn(&InterfacePointState) -> f64;

fn as_u64s(v: &Value) -> Vec<u64> {
    v.as_array().unwrap().iter().map(|x| x.as_u64().unwrap()).collect()
}

fn bits(values: impl IntoIterator<Item = f64>) -> Vec<u64> {
    values.into_iter().map(f64::to_bits).collect()
}

#[test]
fn interface_vtu_reads_back_bit_for_bit() {
    let dir = scratch_dir("vtu");
    // Two laws in one run: the first three points have an adhesion, the others not.
    let points: Vec<InterfacePointState> =
        (0..5).map(|i| point(i, (i < 3).then(|| 1.0 - 0.3 * i as f64 / 7.0), None)).collect();
    let file = dir.join(INTERFACE_VTU);
    write_interface_vtu(&file, &snapshot(0.25, points.clone())).unwrap();
    let m = read_with_meshio(&file);
    assert_eq!(as_u64s(&m["points"]), bits(points.iter().flat_map(|p| [p.x[0], p.x[1], 0.0])));
    let cells = m["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 1);
    assert_eq!(cells[0]["type"], "vertex");
    assert_eq!(as_u64s(&cells[0]["data"]), (0..5).collect::<Vec<u64>>());
    let data = m["point_data"].as_object().unwrap();
    let expected: [(&str, PointValue); 6] = [
        ("opening", |p| p.opening),
        ("slip", |p| p.slip),
        ("traction_normal", |p| p.traction_normal),
        ("traction_tangential", |p| p.traction_tangential),
        ("adhesion", |p| p.adhesion.unwrap_or(f64::NAN)),
        ("law_residual", |p| p.law_residual),
    ];
    let mut names: Vec<&String> = data.keys().collect();
    names.sort();
    let mut wanted: Vec<&str> = expected.iter().map(|(n, _)| *n).collect();
    wanted.sort();
    assert_eq!(names, wanted, "no `damage`: no point has one");
    for (name, value) in expected {
        let read = as_u64s(&data[name]);
        if name == "adhesion" {
            // NaN where the law has no adhesion (any NaN pattern), the values elsewhere.
            assert_eq!(read[..3], bits(points[..3].iter().map(value))[..], "{name}");
            assert!(read[3..].iter().all(|&b| f64::from_bits(b).is_nan()), "{name}");
        } else {
            assert_eq!(read, bits(points.iter().map(value)), "{name}");
        }
    }
    // A damage when a law has one.
    let damaged: Vec<InterfacePointState> = (0..2).map(|i| point(i, None, Some(0.5 * i as f64))).collect();
    write_interface_vtu(&file, &snapshot(1.0, damaged)).unwrap();
    let m = read_with_meshio(&file);
    assert_eq!(as_u64s(&m["point_data"]["damage"]), bits([0.0, 0.5]));
    assert!(m["point_data"].get("adhesion").is_none());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_bad_snapshot_is_refused_and_nothing_is_written() {
    let dir = scratch_dir("refuse");
    let file = dir.join(INTERFACE_VTU);
    let mut bad = point(2, None, None);
    bad.traction_tangential = f64::NAN;
    let mut bad_adhesion = point(1, Some(f64::INFINITY), None);
    bad_adhesion.law_residual = 0.0;
    let cases = [
        (snapshot(1.0, vec![]), "no contact point"),
        (snapshot(1.0, vec![point(0, None, None), bad]), "contact point 1 at (6.666666666666666e-1"),
        (snapshot(1.0, vec![bad_adhesion]), "adhesion is inf"),
        (snapshot(f64::NAN, vec![point(0, None, None)]), "time is NaN"),
    ];
    for (s, expected) in cases {
        match write_interface_vtu(&file, &s) {
            Err(Error::Output { path, message }) => {
                assert_eq!(path, file);
                assert!(message.contains(expected), "{message:?} lacks {expected:?}");
                assert!(message.contains("nothing was written"), "{message}");
            }
            other => panic!("expected an output error, got {other:?}"),
        }
        assert!(fs::read_dir(&dir).unwrap().next().is_none(), "nothing in the directory");
    }
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn traced_points_are_the_nearest_or_first_middle_last() {
    let points: Vec<InterfacePointState> = (0..7).map(|i| point(i, None, None)).collect();
    assert_eq!(trace_points(&points, &[]), [0, 3, 6]);
    assert_eq!(trace_points(&points[..2], &[]), [0, 1]);
    assert_eq!(trace_points(&points[..1], &[]), [0]);
    assert!(trace_points(&[], &[[0.0, 0.0]]).is_empty());
    // x = i/3: (1.1, 0) is nearest to point 3 (x = 1), (10, 0) to the last, a repeat counts once
    assert_eq!(trace_points(&points, &[[1.1, 0.0], [10.0, 0.0], [0.95, 0.2]]), [3, 6]);
    // a tie (halfway between points 0 and 1) takes the first
    assert_eq!(trace_points(&points, &[[1.0 / 6.0, 0.1 / 6.0]]), [0]);
}

#[test]
fn the_summary_takes_the_extremes() {
    let points =
        vec![point(0, Some(0.9), None), point(1, Some(0.25), None), point(2, None, None), point(3, None, None)];
    let s = InterfaceSummary::of(&snapshot(0.5, points.clone()));
    assert_eq!(s.time, 0.5);
    assert_eq!(s.points, 4);
    assert_eq!(s.iterations, 7);
    assert_eq!(s.laws, ["rccm"]);
    assert_eq!(s.min_adhesion, Some(0.25));
    assert_eq!(s.max_damage, None);
    // openings 0, 1e-7, 0, 1e-7 √3; slips −2.5e-6 (i − 1.5): largest |.| at i = 0 and 3
    assert_eq!(s.max_opening, 1e-7 * 3f64.sqrt());
    assert_eq!(s.max_slip, 2.5e-6 * 1.5);
    assert_eq!(s.worst_law_residual, 4e-13);
    let damaged = vec![point(0, None, Some(0.1)), point(1, None, Some(0.7))];
    assert_eq!(InterfaceSummary::of(&snapshot(1.0, damaged)).max_damage, Some(0.7));
}

/// Increment `k` (from 1) of a made-up path; the interface follows it.
fn record(k: usize) -> StepRecord {
    StepRecord {
        step: k,
        time: k as f64 / 4.0,
        halvings: 0,
        contact_resultant: [1.0, -2.0],
        normal_resultant: -2.0,
        tangential_resultant: 1.0,
        open: 1,
        stick: 1,
        slip: 1,
        closed: 2,
        iterations: 3,
        worst_residual: 1e-12,
        dissipation: 0.0,
        total_dissipation: 0.0,
        work: 1.0,
        stored_energy: 1.0,
        monitor_displacement: 1e-6 * k as f64,
        estimate_percent: None,
        seconds: 0.01,
    }
}

/// The interface at increment `k`: the adhesion drops with k, the slip grows.
fn snapshot_at(k: usize) -> InterfaceSnapshot {
    let points = (0..5)
        .map(|i| {
            let mut p = point(i, Some(1.0 - 0.1 * (k * (i + 1)) as f64 / 5.0), None);
            p.slip = 1e-6 * (k * i) as f64;
            p.traction_tangential = 1e5 * (k as f64).ln_1p() * (i as f64 + 1.0);
            p
        })
        .collect();
    snapshot(k as f64 / 4.0, points)
}

fn history(steps: &[usize], trace: &[[f64; 2]]) -> InterfaceHistory {
    let mut h = InterfaceHistory::new(&snapshot_at(1), trace);
    for &k in steps {
        h.record(k, &snapshot_at(k));
    }
    h
}

#[test]
fn the_history_keeps_one_sample_per_increment_in_order() {
    let mut h = history(&[2, 1, 3], &[]);
    assert_eq!(h.trace_points, [0, 2, 4]);
    assert_eq!(h.steps.iter().map(|s| s.step).collect::<Vec<_>>(), [1, 2, 3]);
    // recording a step again replaces it
    let mut changed = snapshot_at(2);
    changed.points[2].slip = 42.0;
    h.record(2, &changed);
    assert_eq!(h.steps.len(), 3);
    assert_eq!(h.at(2).unwrap().trace[1].slip, 42.0);
    assert_eq!(h.at(3).unwrap().summary, InterfaceSummary::of(&snapshot_at(3)));
    assert!(h.at(4).is_none());
}

/// A csv line split at commas, the cells as text.
fn cells(line: &str) -> Vec<String> {
    line.split(',').map(str::to_string).collect()
}

#[test]
fn history_csv_gets_the_interface_columns_after_the_others() {
    let dir = scratch_dir("csv");
    let path = dir.join(HISTORY_CSV);
    let steps: Vec<StepRecord> = (1..=4).map(record).collect();
    // increment 3 has no sample: its interface cells are empty
    let h = history(&[1, 2, 4], &[]);
    write_history_csv_with_interface(&path, &steps, Some(&h)).unwrap();
    let text = fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 5);
    assert_eq!(lines[0], format!("{HISTORY_CSV_HEADER},{HISTORY_CSV_INTERFACE_COLUMNS}"));
    let header = cells(lines[0]);
    let column = |name: &str| header.iter().position(|h| h == name).unwrap_or_else(|| panic!("no column {name}"));
    let before = cells(HISTORY_CSV_HEADER).len();
    assert_eq!(column("interface_min_adhesion"), before, "the old columns come first, unchanged");
    for (k, line) in lines[1..].iter().enumerate() {
        let row = cells(line);
        assert_eq!(row.len(), header.len(), "{line}");
        let step = k + 1;
        let get = |name: &str| row[column(name)].clone();
        if step == 3 {
            for name in cells(HISTORY_CSV_INTERFACE_COLUMNS) {
                assert_eq!(get(&name), "", "{name} of increment 3");
            }
            continue;
        }
        let s = snapshot_at(step);
        // min β = 1 − 0.1·5k/5 = 1 − 0.1 k (the last point); max |slip| = 4k µm
        let min_adhesion: f64 = get("interface_min_adhesion").parse().unwrap();
        assert_eq!(min_adhesion, s.points.iter().map(|p| p.adhesion.unwrap()).fold(1.0, f64::min));
        assert!((min_adhesion - (1.0 - 0.1 * step as f64)).abs() < 1e-15);
        assert_eq!(get("interface_max_damage"), "", "rccm has no damage");
        assert_eq!(get("interface_max_slip_m").parse::<f64>().unwrap(), 1e-6 * (4 * step) as f64);
        assert_eq!(get("interface_max_opening_m").parse::<f64>().unwrap(), 1e-7 * 3f64.sqrt());
        assert_eq!(get("interface_worst_law_residual").parse::<f64>().unwrap(), 5e-13);
        assert_eq!(get("step"), step.to_string());
    }
    // Without an interface: the file as before.
    signorini::evolution::history::write_history_csv(&path, &steps).unwrap();
    assert_eq!(fs::read_to_string(&path).unwrap().lines().next().unwrap(), HISTORY_CSV_HEADER);
    // A non-finite interface value is refused, naming the increment, and nothing changes.
    let before = fs::read_to_string(&path).unwrap();
    let mut bad = h.clone();
    bad.steps[1].summary.max_slip = f64::NAN;
    match write_history_csv_with_interface(&path, &steps, Some(&bad)) {
        Err(Error::Output { message, .. }) => {
            assert!(message.contains("step 2: interface_max_slip_m is NaN"), "{message}")
        }
        other => panic!("expected an output error, got {other:?}"),
    }
    assert_eq!(fs::read_to_string(&path).unwrap(), before);
    fs::remove_dir_all(&dir).unwrap();
}

/// The root, the texts and the width of an SVG file, by Python's XML parser.
fn parse_svg(file: &Path) -> (String, Vec<String>, String, usize) {
    const SCRIPT: &str = r#"
import json, sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
ns = "{http://www.w3.org/2000/svg}"
print(json.dumps({"root": root.tag, "texts": ["".join(t.itertext()) for t in root.iter(ns + "text")],
                  "width": root.get("width"), "polylines": len(root.findall(".//" + ns + "polyline")) +
                  len(root.findall(".//" + ns + "path"))}))
"#;
    let out = Command::new("python3").arg("-c").arg(SCRIPT).arg(file).output().expect("python3");
    assert!(out.status.success(), "SVG is not well-formed XML: {}", String::from_utf8_lossy(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    let texts = v["texts"].as_array().unwrap().iter().map(|t| t.as_str().unwrap().to_string()).collect();
    (
        v["root"].as_str().unwrap().to_string(),
        texts,
        v["width"].as_str().unwrap().to_string(),
        v["polylines"].as_u64().unwrap() as usize,
    )
}

#[test]
fn the_tau_delta_plot_has_two_panels_and_a_line_per_traced_point() {
    let dir = scratch_dir("svg");
    let steps: Vec<StepRecord> = (1..=4).map(record).collect();
    let h = history(&[1, 2, 3, 4], &[[0.0, 0.0], [1.4, 0.0]]);
    assert_eq!(h.trace_points, [0, 4]);
    let written = write_load_path_outputs_with_interface(&dir, &steps, &[], "glued & <sheared>", Some(&h)).unwrap();
    let svg = dir.join(TAU_DELTA_SVG);
    assert_eq!(written.last(), Some(&svg));
    let (root, texts, width, _) = parse_svg(&svg);
    assert_eq!(root, "{http://www.w3.org/2000/svg}svg");
    assert_eq!(width, "1600");
    for expected in [
        "glued & <sheared>: shear traction against slip",
        "glued & <sheared>: normal traction against opening",
        "slip (m)",
        "opening (m)",
        "tangential traction (Pa)",
        "point 0 at (0.0000e0, -1.0000e-300)",
        "point 4 at (1.3333e0, 1.3333e-1)",
    ] {
        assert!(texts.iter().any(|t| t == expected), "missing {expected:?} in {texts:?}");
    }
    // No history, or nothing traced: refused as a usage error, nothing written.
    let empty = InterfaceHistory { trace_points: vec![0], steps: vec![] };
    let other = dir.join("other.svg");
    assert!(matches!(write_tau_delta_svg(&other, "t", &empty), Err(Error::Usage(_))));
    assert!(!other.exists());
    // Without an interface: no τ–δ plot.
    fs::remove_file(&svg).unwrap();
    write_load_path_outputs_with_interface(&dir, &steps, &[], "t", None).unwrap();
    assert!(!svg.exists());
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_previous_runs_interface_files_are_cleared() {
    let dir = scratch_dir("clear");
    for name in [INTERFACE_VTU, INTERFACE_PVD, TAU_DELTA_SVG] {
        assert!(RUN_FILES.contains(&name), "{name}");
        fs::write(dir.join(name), "old").unwrap();
    }
    fs::create_dir_all(dir.join("steps")).unwrap();
    fs::write(dir.join(interface_step_file_name(1)), "old").unwrap();
    fs::write(dir.join("keep.txt"), "mine").unwrap();
    let removed = clear_previous_run(&dir).unwrap();
    assert_eq!(removed.len(), 4, "{removed:?}");
    let left: Vec<String> =
        fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into()).collect();
    assert_eq!(left, ["keep.txt"]);
    fs::remove_dir_all(&dir).unwrap();
}
