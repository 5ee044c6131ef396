//! Output: `.vtu` files read back by an independent reader (Python meshio), atomic writes,
//! SVG plots, timings and memory.
//!
//! The `.vtu` round trip needs `python3` with `meshio` (`pip install meshio`); without them the
//! tests fail with a message saying so.
use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;
use signorini::error::Error;
use signorini::evolution::history::{write_load_path_outputs, CONTACT_PROFILES_SVG, HISTORY_CSV, HYSTERESIS_SVG};
use signorini::evolution::{ContactProfile, StepRecord};
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use signorini::output::plot::{write_linear_styled_svg, write_linear_svg, write_loglog_svg, Series, Style};
use signorini::output::pvd::{step_file_name, write_pvd};
use signorini::output::vtu::{write_vtu, Field};
use signorini::output::{all_or_nothing, write_atomically, write_atomically_by_name, write_json};
use signorini::report::contact::ContactState;
use signorini::resources::{current_memory_bytes, peak_memory_bytes, Timings};

/// A fresh, empty directory for one test.
fn scratch_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-output-{}-{test}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).unwrap();
    dir
}

fn dir_entries(dir: &Path) -> BTreeSet<String> {
    fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect()
}

fn groups() -> Vec<PhysicalGroup> {
    vec![
        PhysicalGroup { name: "body".into(), tag: 7, dim: 2 },
        PhysicalGroup { name: "bottom".into(), tag: 3, dim: 1 },
        PhysicalGroup { name: "top".into(), tag: 11, dim: 1 },
    ]
}

/// Unit-ish square with awkward coordinates, two P1 triangles, three boundary edges.
///
/// ```text
///   3 ----- 2
///   | \  1  |
///   |  0 \  |
///   0 ----- 1
/// ```
fn p1_mesh() -> Mesh {
    Mesh {
        order: Order::P1,
        nodes: vec![[0.0, -0.0], [1.0 / 3.0, 1e-300], [0.1 + 0.2, 2.0f64.sqrt()], [-7.25e-8, 1.0]],
        cells: vec![0, 1, 3, 1, 2, 3],
        cell_group: vec![0, NO_GROUP],
        edges: vec![0, 1, 2, 3, 3, 0],
        edge_group: vec![1, 2, 1],
        groups: groups(),
        measure: Default::default(),
    }
}

/// The same square as P2: vertices 0-3, edge midpoints 4-8.
///
/// ```text
///   3 --7-- 2
///   | \     |
///   8  6    5
///   |     \ |
///   0 --4-- 1
/// ```
fn p2_mesh() -> Mesh {
    let v = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let mid = |a: usize, b: usize| [(v[a][0] + v[b][0]) / 2.0, (v[a][1] + v[b][1]) / 2.0 + 1e-3 * a as f64];
    let mut nodes = v.to_vec();
    nodes.extend([mid(0, 1), mid(1, 2), mid(1, 3), mid(2, 3), mid(3, 0)]);
    Mesh {
        order: Order::P2,
        nodes,
        // (v0 v1 v2 | m01 m12 m20)
        cells: vec![0, 1, 3, 4, 6, 8, 1, 2, 3, 5, 7, 6],
        cell_group: vec![NO_GROUP, 0],
        // (v0 v1 | mid)
        edges: vec![0, 1, 4, 2, 3, 7, 1, 2, 5],
        edge_group: vec![1, 2, 2],
        groups: groups(),
        measure: Default::default(),
    }
}

/// Deterministic, bit-varied values (negative, tiny, huge, subnormal, non-terminating).
fn values(n: usize, seed: f64) -> Vec<f64> {
    (0..n)
        .map(|i| {
            let x = (i as f64 + seed).sin() * 10f64.powi((i % 9) as i32 - 4) / 3.0;
            match i % 11 {
                7 => 5e-324,
                10 => -1.7976931348623157e308,
                _ => x,
            }
        })
        .collect()
}

/// Run meshio on `file`; returns its view of the mesh as JSON, floats as their IEEE bit patterns
/// (so the comparison is exact and independent of any decimal round trip).
fn read_with_meshio(file: &Path) -> Value {
    const SCRIPT: &str = r#"
import json, struct, sys
try:
    import meshio
    import numpy as np
except BaseException as e:
    print("IMPORT-ERROR: " + repr(e))
    sys.exit(3)
def bits(a):
    a = np.asarray(a, dtype=np.float64)
    return [struct.unpack("<Q", struct.pack("<d", float(x)))[0] for x in a.ravel()]
try:
    m = meshio.read(sys.argv[1])
    out = {
        "points_shape": list(m.points.shape),
        "points": bits(m.points),
        "cells": [{"type": b.type, "shape": list(b.data.shape),
                   "data": [int(x) for x in np.asarray(b.data).ravel()]} for b in m.cells],
        "point_data": {k: {"shape": list(np.asarray(v).shape), "dtype": str(np.asarray(v).dtype), "bits": bits(v)}
                       for k, v in m.point_data.items()},
        "cell_data": {k: [{"shape": list(np.asarray(b).shape), "dtype": str(np.asarray(b).dtype),
                           "bits": bits(b)} for b in v]
                      for k, v in m.cell_data.items()},
    }
    print(json.dumps(out))
except BaseException as e:
    print("READ-ERROR: " + repr(e))
    sys.exit(4)
"#;
    let out = Command::new("python3").arg("-c").arg(SCRIPT).arg(file).output().unwrap_or_else(|e| {
        panic!("cannot run python3 ({e}): the .vtu tests need python3 with meshio (pip install meshio)")
    });
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "meshio could not read {}: exit {:?}\n{stdout}\n{stderr}\n(the .vtu tests need python3 with meshio: pip install meshio)",
        file.display(),
        out.status.code()
    );
    serde_json::from_str(&stdout).unwrap_or_else(|e| panic!("bad JSON from the meshio script ({e}): {stdout}"))
}

fn as_u64s(v: &Value) -> Vec<u64> {
    v.as_array().unwrap().iter().map(|x| x.as_u64().unwrap()).collect()
}

fn bits_of(values: &[f64]) -> Vec<u64> {
    values.iter().map(|v| v.to_bits()).collect()
}

/// A meshio cell block: type name, nodes per cell, flat connectivity.
type Block = (&'static str, usize, Vec<u64>);

/// Expected cell blocks and per-cell physical tags.
fn expected_blocks(mesh: &Mesh, with_edges: bool) -> (Vec<Block>, Vec<i32>) {
    let (tri, line) = match mesh.order {
        Order::P1 => ("triangle", "line"),
        Order::P2 => ("triangle6", "line3"),
    };
    let tag = |g: usize| {
        if g == NO_GROUP {
            -1
        } else {
            mesh.groups[g].tag
        }
    };
    let mut blocks = vec![(tri, mesh.order.nodes_per_cell(), mesh.cells.iter().map(|&n| n as u64).collect())];
    let mut tags: Vec<i32> = mesh.cell_group.iter().map(|&g| tag(g)).collect();
    if with_edges {
        blocks.push((line, mesh.order.nodes_per_edge(), mesh.edges.iter().map(|&n| n as u64).collect()));
        tags.extend(mesh.edge_group.iter().map(|&g| tag(g)));
    }
    (blocks, tags)
}

/// Write `mesh` with a 3-component point field and two cell fields, read it back with meshio,
/// compare everything bit for bit.
fn round_trip(mesh: &Mesh, with_edges: bool, test: &str) {
    let dir = scratch_dir(test);
    let file = dir.join("result.vtu");
    let n_cells = mesh.num_cells() + if with_edges { mesh.num_edges() } else { 0 };
    let displacement = values(3 * mesh.num_nodes(), 0.5);
    let temperature = values(mesh.num_nodes(), 2.0);
    let stress = values(3 * n_cells, 1.25);
    let weird_name = "von Mises <σ> & \"q\"";
    let von_mises = values(n_cells, 9.0);
    write_vtu(
        &file,
        mesh,
        &[
            Field { name: "displacement", components: 3, values: &displacement },
            Field { name: "temperature", components: 1, values: &temperature },
        ],
        &[
            Field { name: "stress", components: 3, values: &stress },
            Field { name: weird_name, components: 1, values: &von_mises },
        ],
        with_edges,
    )
    .unwrap();
    assert_eq!(dir_entries(&dir), BTreeSet::from(["result.vtu".to_string()]), "temporary left behind");

    let m = read_with_meshio(&file);

    // Points: (x, y, 0), bit for bit (including -0.0 and 1e-300).
    assert_eq!(as_u64s(&m["points_shape"]), vec![mesh.num_nodes() as u64, 3]);
    let expected_points: Vec<f64> = mesh.nodes.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
    assert_eq!(as_u64s(&m["points"]), bits_of(&expected_points));

    // Cells: types, shapes and connectivity in order.
    let (blocks, tags) = expected_blocks(mesh, with_edges);
    let cells = m["cells"].as_array().unwrap();
    assert_eq!(cells.len(), blocks.len(), "cell blocks: {cells:?}");
    for (got, (ty, per, data)) in cells.iter().zip(&blocks) {
        assert_eq!(got["type"], *ty);
        assert_eq!(as_u64s(&got["shape"]), vec![(data.len() / per) as u64, *per as u64]);
        assert_eq!(&as_u64s(&got["data"]), data, "{ty} connectivity");
    }

    // Point data.
    let pd = m["point_data"].as_object().unwrap();
    assert_eq!(pd.len(), 2, "point data: {:?}", pd.keys().collect::<Vec<_>>());
    assert_eq!(as_u64s(&pd["displacement"]["shape"]), vec![mesh.num_nodes() as u64, 3]);
    assert_eq!(as_u64s(&pd["displacement"]["bits"]), bits_of(&displacement));
    assert_eq!(as_u64s(&pd["temperature"]["shape"]), vec![mesh.num_nodes() as u64]);
    assert_eq!(as_u64s(&pd["temperature"]["bits"]), bits_of(&temperature));

    // Cell data: split by meshio into the triangle block and the edge block.
    let cd = m["cell_data"].as_object().unwrap();
    assert_eq!(cd.len(), 3, "cell data: {:?}", cd.keys().collect::<Vec<_>>());
    let joined = |name: &str, components: usize| -> Vec<u64> {
        let per_block = cd[name].as_array().unwrap();
        assert_eq!(per_block.len(), blocks.len(), "{name} blocks");
        let mut all = Vec::new();
        for (b, (_, per, data)) in per_block.iter().zip(&blocks) {
            let n = (data.len() / per) as u64;
            let shape = if components == 1 { vec![n] } else { vec![n, components as u64] };
            assert_eq!(as_u64s(&b["shape"]), shape, "{name} shape");
            all.extend(as_u64s(&b["bits"]));
        }
        all
    };
    assert_eq!(joined("stress", 3), bits_of(&stress));
    assert_eq!(joined(weird_name, 1), bits_of(&von_mises));
    let part_ids: Vec<f64> = tags.iter().map(|&t| t as f64).collect();
    assert_eq!(joined("part_id", 1), bits_of(&part_ids));
    assert_eq!(cd["part_id"][0]["dtype"], "int32");
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn p1_vtu_with_edges_reads_back_exactly_in_meshio() {
    round_trip(&p1_mesh(), true, "p1-edges");
}

#[test]
fn p1_vtu_without_edges_reads_back_exactly_in_meshio() {
    round_trip(&p1_mesh(), false, "p1-no-edges");
}

#[test]
fn p2_vtu_with_edges_reads_back_exactly_in_meshio() {
    round_trip(&p2_mesh(), true, "p2-edges");
}

#[test]
fn p2_vtu_without_edges_reads_back_exactly_in_meshio() {
    round_trip(&p2_mesh(), false, "p2-no-edges");
}

#[test]
fn vtu_of_a_larger_mesh_reads_back_in_meshio() {
    // A 60×40 structured P1 grid: arrays span several base64 chunks.
    let (nx, ny) = (60, 40);
    let mut nodes = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            nodes.push([i as f64 / nx as f64, j as f64 / ny as f64 * 0.7]);
        }
    }
    let id = |i: usize, j: usize| j * (nx + 1) + i;
    let mut cells = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            cells.extend([id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    let mut edges = Vec::new();
    for i in 0..nx {
        edges.extend([id(i, 0), id(i + 1, 0)]);
    }
    let mesh = Mesh {
        order: Order::P1,
        cell_group: vec![0; cells.len() / 3],
        edge_group: vec![1; edges.len() / 2],
        nodes,
        cells,
        edges,
        groups: groups(),
        measure: Default::default(),
    };
    round_trip(&mesh, true, "grid");
}

fn output_message(err: Error) -> (PathBuf, String) {
    match err {
        Error::Output { path, message } => (path, message),
        other => panic!("expected Error::Output, got {other:?}"),
    }
}

#[test]
fn field_length_mismatch_names_the_field_and_writes_nothing() {
    let dir = scratch_dir("mismatch");
    let file = dir.join("bad.vtu");
    let mesh = p1_mesh(); // 4 nodes, 2 triangles, 3 edges
    let ok = vec![0.0; 12];
    let short = vec![0.0; 11];

    let err = write_vtu(&file, &mesh, &[Field { name: "displacement", components: 3, values: &short }], &[], true)
        .unwrap_err();
    let (path, message) = output_message(err);
    assert_eq!(path, file);
    assert!(message.contains("point field 'displacement'"), "{message}");
    assert!(message.contains("11 values, expected 12"), "{message}");

    // Cell data covers triangles + edges (5 cells) with edges, triangles only (2) without.
    let five = vec![0.0; 5];
    let two = vec![0.0; 2];
    let err = write_vtu(
        &file,
        &mesh,
        &[Field { name: "u", components: 3, values: &ok }],
        &[Field { name: "gap", components: 1, values: &two }],
        true,
    )
    .unwrap_err();
    let (_, message) = output_message(err);
    assert!(message.contains("cell field 'gap'") && message.contains("2 values, expected 5"), "{message}");
    assert!(message.contains("2 triangles + 3 boundary edges"), "{message}");
    let err = write_vtu(&file, &mesh, &[], &[Field { name: "gap", components: 1, values: &five }], false).unwrap_err();
    let (_, message) = output_message(err);
    assert!(message.contains("cell field 'gap'") && message.contains("5 values, expected 2"), "{message}");

    let err =
        write_vtu(&file, &mesh, &[], &[Field { name: "part_id", components: 1, values: &five }], true).unwrap_err();
    assert!(output_message(err).1.contains("'part_id'"));
    let err = write_vtu(
        &file,
        &mesh,
        &[Field { name: "u", components: 3, values: &ok }, Field { name: "u", components: 3, values: &ok }],
        &[],
        true,
    )
    .unwrap_err();
    assert!(output_message(err).1.contains("point field 'u': given twice"));
    let err = write_vtu(&file, &mesh, &[Field { name: "empty", components: 0, values: &[] }], &[], true).unwrap_err();
    assert!(output_message(err).1.contains("point field 'empty': 0 components"));

    // Inconsistent meshes name the entity.
    let mut bad = p1_mesh();
    bad.cells[4] = 9;
    let err = write_vtu(&file, &bad, &[], &[], true).unwrap_err();
    assert!(output_message(err).1.contains("triangle 1 uses node 9"));
    let mut bad = p1_mesh();
    bad.edge_group[2] = 5;
    let err = write_vtu(&file, &bad, &[], &[], true).unwrap_err();
    assert!(output_message(err).1.contains("boundary edge 2 is in group 5"));

    assert!(dir_entries(&dir).is_empty(), "files left: {:?}", dir_entries(&dir));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn uncreatable_path_is_an_error_and_leaves_nothing() {
    let dir = scratch_dir("uncreatable");
    let blocker = dir.join("a-file");
    fs::write(&blocker, "not a directory").unwrap();

    // Parent "directory" is a file: creating it fails.
    let target = blocker.join("sub").join("out.vtu");
    let err = write_vtu(&target, &p1_mesh(), &[], &[], true).unwrap_err();
    let (path, message) = output_message(err);
    assert_eq!(path, target);
    assert!(message.contains("creating directory"), "{message}");

    // Target is an existing directory: the temporary is created and written, the rename fails,
    // the temporary must be gone.
    let target = dir.join("a-directory");
    fs::create_dir(&target).unwrap();
    fs::write(target.join("inside"), "x").unwrap();
    let err = write_json(&target, &vec![1, 2, 3]).unwrap_err();
    assert!(output_message(err).1.contains("renaming"));
    assert_eq!(dir_entries(&dir), BTreeSet::from(["a-file".to_string(), "a-directory".to_string()]));
    assert_eq!(fs::read_to_string(&blocker).unwrap(), "not a directory");
    assert_eq!(fs::read_to_string(target.join("inside")).unwrap(), "x");

    // A path without a file name.
    assert!(matches!(write_json(Path::new("/"), &1), Err(Error::Output { .. })));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn failed_writer_leaves_the_old_file_intact() {
    let dir = scratch_dir("atomic");
    let file = dir.join("report.json");
    fs::write(&file, "old contents\n").unwrap();

    // The closure writes more than the buffer holds (so bytes reach the temporary), then fails.
    let err = write_atomically(&file, |w| {
        w.write_all(&vec![b'x'; 3 << 20])?;
        Err(std::io::Error::other("simulated failure after 3 MiB"))
    })
    .unwrap_err();
    let (path, message) = output_message(err);
    assert_eq!(path, file);
    assert!(message.contains("simulated failure after 3 MiB"), "{message}");
    assert_eq!(fs::read_to_string(&file).unwrap(), "old contents\n");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["report.json".to_string()]));

    // A panicking writer also leaves the old file and no temporary.
    let result = std::panic::catch_unwind(|| {
        let _ = write_atomically(&file, |w| {
            w.write_all(b"partial")?;
            panic!("writer panicked");
        });
    });
    assert!(result.is_err());
    assert_eq!(fs::read_to_string(&file).unwrap(), "old contents\n");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["report.json".to_string()]));

    // Success replaces the contents; missing parents are created.
    write_atomically(&file, |w| w.write_all(b"new")).unwrap();
    assert_eq!(fs::read_to_string(&file).unwrap(), "new");
    let nested = dir.join("a/b/c.json");
    write_json(&nested, &serde_json::json!({"k": [1.5, 2]})).unwrap();
    assert_eq!(fs::read_to_string(&nested).unwrap(), "{\n  \"k\": [\n    1.5,\n    2\n  ]\n}\n");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["a".to_string(), "report.json".to_string()]));
    fs::remove_dir_all(&dir).unwrap();
}

/// The by-name writer (the FCLIB export's, whose HDF5 library opens the file itself): the
/// closure gets a hidden temporary next to the target; a failure or a panic leaves the old file
/// and no temporary; success replaces the target.
#[test]
fn failed_writer_by_name_leaves_the_old_file_intact() {
    let dir = scratch_dir("atomic-by-name");
    let file = dir.join("problem.hdf5");
    fs::write(&file, "old contents\n").unwrap();
    let err = write_atomically_by_name(&file, |temporary| {
        assert_eq!(temporary.parent(), Some(dir.as_path()));
        assert!(temporary.file_name().unwrap().to_string_lossy().starts_with(".problem.hdf5."));
        fs::write(temporary, "half written")?;
        Err(std::io::Error::other("simulated HDF5 failure"))
    })
    .unwrap_err();
    let (path, message) = output_message(err);
    assert_eq!(path, file);
    assert!(message.contains("simulated HDF5 failure"), "{message}");
    assert_eq!(fs::read_to_string(&file).unwrap(), "old contents\n");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["problem.hdf5".to_string()]));
    let result = std::panic::catch_unwind(|| {
        let _ = write_atomically_by_name(&file, |temporary| {
            fs::write(temporary, "partial")?;
            panic!("writer panicked");
        });
    });
    assert!(result.is_err());
    assert_eq!(fs::read_to_string(&file).unwrap(), "old contents\n");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["problem.hdf5".to_string()]));
    // The writer may replace the temporary (as HDF5's truncating create does).
    write_atomically_by_name(&file, |temporary| {
        fs::remove_file(temporary)?;
        fs::write(temporary, "new")
    })
    .unwrap();
    assert_eq!(fs::read_to_string(&file).unwrap(), "new");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["problem.hdf5".to_string()]));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn files_written_all_or_nothing_appear_together_or_not_at_all() {
    let dir = scratch_dir("batch");
    let (a, b, c) = (dir.join("a.txt"), dir.join("b.txt"), dir.join("sub/c.txt"));
    fs::write(&a, "old a").unwrap();
    // A failure after some files were written: none of them appears, the old file stays, no
    // temporary is left.
    let err = all_or_nothing(|| {
        write_atomically(&a, |w| w.write_all(b"new a"))?;
        write_atomically(&b, |w| w.write_all(b"new b"))?;
        Err::<(), _>(Error::Usage("simulated failure".into()))
    })
    .unwrap_err();
    assert!(err.to_string().contains("simulated failure"));
    assert_eq!(fs::read_to_string(&a).unwrap(), "old a");
    assert_eq!(dir_entries(&dir), BTreeSet::from(["a.txt".to_string()]));
    // A panic likewise.
    let result = std::panic::catch_unwind(|| {
        let _ = all_or_nothing(|| -> signorini::Result<()> {
            write_atomically(&b, |w| w.write_all(b"new b"))?;
            panic!("writer panicked");
        });
    });
    assert!(result.is_err());
    assert_eq!(dir_entries(&dir), BTreeSet::from(["a.txt".to_string()]));
    // Inside the batch nothing is visible yet; after it, everything (nested batches join the
    // outer one).
    let seen = all_or_nothing(|| {
        write_atomically(&a, |w| w.write_all(b"new a"))?;
        all_or_nothing(|| write_atomically(&b, |w| w.write_all(b"new b")))?;
        write_atomically(&c, |w| w.write_all(b"new c"))?;
        Ok((fs::read_to_string(&a).unwrap(), b.exists(), c.exists()))
    })
    .unwrap();
    assert_eq!(seen, ("old a".to_string(), false, false));
    for (path, text) in [(&a, "new a"), (&b, "new b"), (&c, "new c")] {
        assert_eq!(fs::read_to_string(path).unwrap(), text);
    }
    assert_eq!(dir_entries(&dir), BTreeSet::from(["a.txt".into(), "b.txt".into(), "sub".into()]));
    assert_eq!(dir_entries(&dir.join("sub")), BTreeSet::from(["c.txt".to_string()]));
    fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn timings_keep_order_accumulate_and_serialize() {
    let mut t = Timings::new();
    assert_eq!(t.total(), 0.0);
    assert_eq!(serde_json::to_string(&t).unwrap(), r#"{"total":0.0}"#);
    let value = t.time("mesh", || {
        std::thread::sleep(std::time::Duration::from_millis(20));
        42
    });
    assert_eq!(value, 42);
    let mesh_time = t.get("mesh").unwrap();
    assert!((0.02..5.0).contains(&mesh_time), "{mesh_time}");

    let mut t = Timings::new();
    t.add("solve", 1.5);
    t.add("assemble", 0.25);
    t.add("solve", 0.5);
    t.add("write", 0.125);
    assert_eq!(t.get("solve"), Some(2.0));
    assert_eq!(t.get("nothing"), None);
    assert_eq!(t.total(), 2.375);
    let names: Vec<&str> = t.phases().iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["solve", "assemble", "write"]);
    assert_eq!(serde_json::to_string(&t).unwrap(), r#"{"solve":2.0,"assemble":0.25,"write":0.125,"total":2.375}"#);
}

#[test]
fn memory_is_reported_in_bytes() {
    let before = peak_memory_bytes().expect("VmHWM in /proc/self/status");
    // Touch 64 MiB so that it is resident.
    let block = vec![1u8; 64 << 20];
    let sum: u64 = block.iter().step_by(4096).map(|&b| b as u64).sum();
    assert_eq!(sum, (64 << 20) / 4096);
    let current = current_memory_bytes().expect("VmRSS in /proc/self/status");
    let peak = peak_memory_bytes().unwrap();
    assert!(current >= 64 << 20, "current {current}");
    assert!(peak >= current && peak >= before, "peak {peak}, current {current}, before {before}");
    assert!(peak < 1 << 40, "peak {peak}: kB not converted once?");
    drop(block);
}

/// Parse with Python's XML parser; returns (root tag, number of <path>, texts).
fn parse_svg(file: &Path) -> (String, usize, Vec<String>) {
    const SCRIPT: &str = r#"
import json, sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
ns = "{http://www.w3.org/2000/svg}"
print(json.dumps({"root": root.tag, "paths": len(root.findall(".//" + ns + "path")),
                  "texts": ["".join(t.itertext()) for t in root.iter(ns + "text")],
                  "width": root.get("width"), "height": root.get("height")}))
"#;
    let out = Command::new("python3")
        .arg("-c")
        .arg(SCRIPT)
        .arg(file)
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3 ({e}): needed to check the SVG"));
    assert!(out.status.success(), "SVG is not well-formed XML: {}", String::from_utf8_lossy(&out.stderr));
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["width"], "800");
    assert_eq!(v["height"], "560");
    let texts = v["texts"].as_array().unwrap().iter().map(|t| t.as_str().unwrap().to_string()).collect();
    (v["root"].as_str().unwrap().to_string(), v["paths"].as_u64().unwrap() as usize, texts)
}

#[test]
fn loglog_svg_is_well_formed_with_labels_and_legend() {
    let dir = scratch_dir("svg");
    let file = dir.join("plots/time.svg");
    let sizes: [f64; 6] = [1e3, 4e3, 1.6e4, 6.4e4, 2.56e5, 1.024e6];
    let series = vec![
        Series { label: "MUMPS <LU> & co".into(), points: sizes.iter().map(|&n| (n, 2e-6 * n.powf(1.3))).collect() },
        Series { label: "CG + AMG".into(), points: sizes.iter().map(|&n| (n, 1e-6 * n)).collect() },
        // A zero and a NaN are skipped and split the line into two paths.
        Series {
            label: "with gaps".into(),
            points: vec![(1e3, 0.5), (4e3, 0.0), (1.6e4, 0.7), (6.4e4, 0.9), (f64::NAN, 1.0), (1e6, 3.0)],
        },
    ];
    write_loglog_svg(&file, "Solve time", "unknowns", "seconds", &series).unwrap();
    let svg = fs::read_to_string(&file).unwrap();
    let (root, _, texts) = parse_svg(&file);
    assert_eq!(root, "{http://www.w3.org/2000/svg}svg");
    for expected in ["Solve time", "unknowns", "seconds", "MUMPS <LU> & co", "CG + AMG", "with gaps"] {
        assert!(texts.iter().any(|t| t == expected), "missing text {expected:?} in {texts:?}");
    }
    // x spans 10^3..10^7 (1.024e6 > 10^6), y spans 10^-3..10^2 (2e-6·(1.024e6)^1.3 ≈ 13.7).
    for decade in ["103", "104", "105", "106", "107", "10\u{2212}3", "100", "101", "102"] {
        assert!(texts.iter().any(|t| t == decade), "missing tick label {decade:?} in {texts:?}");
    }
    assert!(!texts.iter().any(|t| t == "108" || t == "10\u{2212}4"), "{texts:?}");
    // One line per series; the third is broken into "M .. M .." with its NaN/zero points dropped.
    let line_paths: Vec<&str> = svg.lines().filter(|l| l.contains("stroke-linejoin")).collect();
    assert_eq!(line_paths.len(), 3);
    assert_eq!(line_paths[2].matches('M').count(), 3, "{}", line_paths[2]);
    assert!(!svg.contains("NaN") && !svg.contains("inf"));
    assert_eq!(dir_entries(&dir.join("plots")), BTreeSet::from(["time.svg".to_string()]));

    // One decade on each axis: 2 and 5 × 10^k are labelled too.
    let narrow = dir.join("narrow.svg");
    let points = vec![(2e-3, 3e-6), (3e-3, 4e-6), (5e-3, 4.5e-6)];
    write_loglog_svg(&narrow, "narrow", "x", "y", &[Series { label: "s".into(), points }]).unwrap();
    let (_, _, texts) = parse_svg(&narrow);
    for label in ["0.002", "0.005", "10\u{2212}3", "10\u{2212}2", "2×10\u{2212}6", "5×10\u{2212}6"] {
        assert!(texts.iter().any(|t| t == label), "missing tick label {label:?} in {texts:?}");
    }

    // No plottable data at all still gives a valid file.
    let empty = dir.join("empty.svg");
    write_loglog_svg(&empty, "nothing", "x", "y", &[Series { label: "zeros".into(), points: vec![(0.0, 1.0)] }])
        .unwrap();
    let (_, _, texts) = parse_svg(&empty);
    assert!(texts.iter().any(|t| t == "no positive data to plot"));
    write_loglog_svg(&empty, "", "", "", &[]).unwrap();
    parse_svg(&empty);
    fs::remove_dir_all(&dir).unwrap();
}

/// Parse `file` with Python's XML parser; returns the root's tag, its attributes and the texts
/// of its `<text>` elements (SVG) or the attributes of its `<DataSet>` elements (a collection).
fn parse_xml(file: &Path) -> Value {
    const SCRIPT: &str = r#"
import json, sys
import xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
ns = "{http://www.w3.org/2000/svg}"
print(json.dumps({"root": root.tag, "attributes": dict(root.attrib),
                  "texts": ["".join(t.itertext()) for t in root.iter(ns + "text")],
                  "data_sets": [dict(d.attrib) for d in root.iter("DataSet")],
                  "collections": len(root.findall("Collection"))}))
"#;
    let out = Command::new("python3")
        .arg("-c")
        .arg(SCRIPT)
        .arg(file)
        .output()
        .unwrap_or_else(|e| panic!("cannot run python3 ({e}): needed to parse {}", file.display()));
    assert!(
        out.status.success(),
        "{} is not well-formed XML: {}",
        file.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

/// A load path's `solution.pvd`: an XML collection (Python's parser reads it) with one data set
/// per increment, its exact time and the relative name of a `.vtu` file that exists and that
/// meshio reads with that increment's field (meshio has no `.pvd` reader: it reads time series
/// from XDMF only).
#[test]
fn load_path_collection_lists_each_increment_and_its_file() {
    let dir = scratch_dir("pvd");
    let mesh = p1_mesh();
    let times = [0.025, 0.05, 0.1 + 0.2, 1.0 / 3.0, 2.0];
    let fields: Vec<Vec<f64>> = times.iter().map(|t| values(3 * mesh.num_nodes(), *t)).collect();
    let collection = dir.join("solution.pvd");
    all_or_nothing(|| {
        let mut entries = Vec::new();
        for (k, (t, u)) in times.iter().zip(&fields).enumerate() {
            let name = step_file_name(k + 1);
            write_vtu(
                &dir.join(&name),
                &mesh,
                &[Field { name: "displacement", components: 3, values: u }],
                &[],
                false,
            )?;
            entries.push((*t, name));
        }
        write_pvd(&collection, &entries)
    })
    .unwrap();
    assert_eq!(dir_entries(&dir), BTreeSet::from(["solution.pvd".to_string(), "steps".to_string()]));

    let parsed = parse_xml(&collection);
    assert_eq!(parsed["root"], "VTKFile");
    assert_eq!(parsed["attributes"]["type"], "Collection");
    assert_eq!(parsed["collections"], 1);
    let sets = parsed["data_sets"].as_array().unwrap();
    assert_eq!(sets.len(), times.len());
    for (k, set) in sets.iter().enumerate() {
        let time: f64 = set["timestep"].as_str().unwrap().parse().unwrap();
        assert_eq!(time.to_bits(), times[k].to_bits(), "{set}");
        let file = set["file"].as_str().unwrap();
        assert_eq!(file, format!("steps/solution_{:04}.vtu", k + 1));
        assert_eq!(set["part"], "0");
        let m = read_with_meshio(&dir.join(file));
        assert_eq!(as_u64s(&m["point_data"]["displacement"]["bits"]), bits_of(&fields[k]), "{file}");
    }
    assert_eq!(dir_entries(&dir.join("steps")).len(), times.len(), "a temporary left behind");
    fs::remove_dir_all(&dir).unwrap();
}

/// The history files of a load path are well-formed (Python's parser) and say what they show.
#[test]
fn load_path_history_files_parse_and_carry_their_labels() {
    let dir = scratch_dir("history");
    let steps: Vec<StepRecord> = (1..=6)
        .map(|k| {
            let phase = k as f64 * std::f64::consts::FRAC_PI_3;
            StepRecord {
                step: k,
                time: k as f64 / 6.0,
                halvings: 0,
                contact_resultant: [1e5 * phase.sin(), -2e6],
                normal_resultant: -2e6,
                tangential_resultant: 1e5 * phase.sin(),
                open: 4,
                stick: 3,
                slip: 1,
                closed: 0,
                iterations: 4,
                worst_residual: 1e-12,
                dissipation: 0.5,
                total_dissipation: 0.5 * k as f64,
                work: 2.0 * k as f64,
                stored_energy: 1.0,
                monitor_displacement: 1e-6 * (phase - 0.3).sin(),
                estimate_percent: None,
                seconds: 0.01,
            }
        })
        .collect();
    let abscissa = vec![0.0, 0.5, 1.0];
    let profiles = [2, 5].map(|k| ContactProfile {
        step: k,
        time: k as f64 / 6.0,
        abscissa: abscissa.clone(),
        pressure: vec![1e6, 2e6, 1e6],
        traction: vec![-1e5, 0.0, 1e5 * k as f64],
        state: vec![ContactState::Slip, ContactState::Stick, ContactState::Slip],
    });
    let written = write_load_path_outputs(&dir, &steps, &profiles, "cycle & <load>").unwrap();
    assert_eq!(written, [dir.join(HISTORY_CSV), dir.join(HYSTERESIS_SVG), dir.join(CONTACT_PROFILES_SVG)]);
    assert_eq!(fs::read_to_string(&written[0]).unwrap().lines().count(), 1 + steps.len());

    let hysteresis = parse_xml(&written[1]);
    assert_eq!(hysteresis["root"], "{http://www.w3.org/2000/svg}svg");
    let texts: Vec<&str> = hysteresis["texts"].as_array().unwrap().iter().map(|t| t.as_str().unwrap()).collect();
    for expected in [
        "cycle & <load>: tangential load against displacement",
        "increments 1 to 6, in order",
        "tangential contact force (N/m)",
    ] {
        assert!(texts.contains(&expected), "missing {expected:?} in {texts:?}");
    }
    let profiles_svg = parse_xml(&written[2]);
    assert_eq!(profiles_svg["attributes"]["width"], "1600");
    let texts: Vec<&str> = profiles_svg["texts"].as_array().unwrap().iter().map(|t| t.as_str().unwrap()).collect();
    for expected in [
        "cycle & <load>: contact pressure",
        "cycle & <load>: tangential traction",
        "t = 0.333333 (increment 2)",
        "t = 0.833333 (increment 5)",
    ] {
        assert!(texts.contains(&expected), "missing {expected:?} in {texts:?}");
    }
    fs::remove_dir_all(&dir).unwrap();
}

/// `write_linear_svg` draws lines or markers as before; the styled variant also draws both, and
/// neither sorts the points (a path back and forth in x is drawn as given).
#[test]
fn linear_svg_keeps_the_point_order_and_its_styles() {
    let dir = scratch_dir("linear");
    let back_and_forth = vec![(0.0, 0.0), (2.0, 1.0), (1.0, 2.0), (3.0, 3.0)];
    let series = [
        Series { label: "line".into(), points: back_and_forth.clone() },
        Series { label: "samples".into(), points: back_and_forth.clone() },
    ];
    // The groups of the two series, in order (the legend's groups come after them).
    let groups = |svg: &str| -> Vec<String> {
        svg.split("<g fill=").skip(1).take(2).map(|g| g.split("</g>").next().unwrap().to_string()).collect()
    };
    let xs = |group: &str| -> Vec<f64> {
        let d = group.split("<path d=\"").nth(1).unwrap().split('"').next().unwrap();
        d.split(['M', 'L'])
            .filter(|p| !p.trim().is_empty())
            .map(|p| p.split(',').next().unwrap().parse().unwrap())
            .collect()
    };
    let plain = dir.join("plain.svg");
    write_linear_svg(&plain, "t", "x", "y", &series, &[true, false]).unwrap();
    let svg = fs::read_to_string(&plain).unwrap();
    let g = groups(&svg);
    assert_eq!((g[0].matches("<path").count(), g[0].matches("<circle").count()), (1, 0), "{}", g[0]);
    assert_eq!((g[1].matches("<path").count(), g[1].matches("<rect").count()), (0, 4), "{}", g[1]);
    let x = xs(&g[0]);
    assert!(x[0] < x[2] && x[2] < x[1] && x[1] < x[3], "points reordered: {x:?}");

    let styled = dir.join("styled.svg");
    write_linear_styled_svg(&styled, "t", "x", "y", &series, &[Style::LineAndMarkers, Style::Markers]).unwrap();
    let svg = fs::read_to_string(&styled).unwrap();
    let g = groups(&svg);
    assert_eq!((g[0].matches("<path").count(), g[0].matches("<circle").count()), (1, 4), "{}", g[0]);
    assert_eq!((g[1].matches("<path").count(), g[1].matches("<rect").count()), (0, 4), "{}", g[1]);
    assert_eq!(xs(&g[0]), x);
    parse_xml(&plain);
    parse_xml(&styled);
    fs::remove_dir_all(&dir).unwrap();
}
