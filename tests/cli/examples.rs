//! The example programs (built by `cargo test`) run with small settings.

use crate::scratch;
use std::path::PathBuf;
use std::process::Command;

/// The examples, built by `cargo test`, run with small settings.
fn example_binary(name: &str) -> PathBuf {
    let deps = std::env::current_exe().unwrap().parent().unwrap().to_path_buf();
    let path = deps.parent().unwrap().join("examples").join(name);
    assert!(path.exists(), "example {name} not built at {}", path.display());
    path
}

#[test]
fn example_hertz_contact_runs_small() {
    let plot = scratch("hertz-plot").join("hertz.svg");
    let out = Command::new(example_binary("hertz_contact")).arg("--small").arg("--plot").arg(&plot).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}\n{}", String::from_utf8_lossy(&out.stderr));
    // The coarse mesh is still within a few per cent of Hertz on the peak pressure.
    let line = stdout.lines().find(|l| l.contains("peak pressure")).unwrap();
    let percent: f64 = line.rsplit('(').next().unwrap().trim_end_matches(" %)").trim().parse().unwrap();
    assert!(percent.abs() < 10.0, "{stdout}");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.contains("<svg") && svg.contains("Hertz") && svg.contains("P2 nodes"), "plot");
}

#[test]
fn example_assembly_timing_runs_small() {
    let m = 60_usize;
    let out = Command::new(example_binary("assembly_timing")).arg(m.to_string()).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    // The m × m node grid, two triangles per square.
    let size = format!("{} nodes, {} triangles, {} dofs", m * m, 2 * (m - 1) * (m - 1), 2 * m * m);
    assert!(text.lines().next() == Some(size.as_str()), "expected {size:?}:\n{text}");
    // Each phase prints its wall and CPU times and the matrix size; both assemblies build the
    // same matrix, and the two row blocks together hold exactly its entries.
    let nnz = |line: &str| -> Vec<usize> {
        let tail = line.rsplit("nnz = ").next().unwrap();
        tail.split(" + ").map(|n| n.trim().parse().unwrap()).collect()
    };
    let lines: Vec<&str> = text.lines().skip(1).collect();
    assert_eq!(lines.len(), 3, "{text}");
    for (line, start) in lines.iter().zip([
        "assemble (no loads): wall ",
        "assemble (body force + pressure): wall ",
        "two row blocks: wall ",
    ]) {
        assert!(line.starts_with(start) && line.contains(" s, cpu ") && line.contains("nnz = "), "{line}");
    }
    let (whole, with_loads, blocks) = (nnz(lines[0]), nnz(lines[1]), nnz(lines[2]));
    assert_eq!(whole, with_loads, "{text}");
    assert_eq!(blocks.len(), 2, "{text}");
    assert_eq!(blocks[0] + blocks[1], whole[0], "the row blocks hold the whole matrix: {text}");
    // At most 2 × 2 entries per pair of nodes sharing an edge (both ways) and per node.
    let edges = 2 * m * (m - 1) + (m - 1) * (m - 1);
    assert!(whole[0] <= 4 * (m * m + 2 * edges) && whole[0] > 4 * m * m, "{text}");
}

#[test]
fn example_contact_builder_runs() {
    let out = Command::new(example_binary("contact_builder")).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    // Held sideways by friction alone: the shear 2e5 × 2 is carried by the contact.
    assert!(text.contains("contact:") && text.contains("tangential -4.0000e5"), "{text}");
}

#[test]
fn example_two_bodies_runs() {
    let out = Command::new(example_binary("two_bodies")).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    // The block's vertical load 5e6 N/m crosses the interface: the base receives it.
    assert!(text.contains("body base:") && text.contains("-5.0000e6), equilibrium residual"), "{text}");
    let residual = |line: &str| -> f64 { line.rsplit(' ').next().unwrap_or("1").parse().unwrap_or(1.0) };
    for line in text.lines().filter(|l| l.contains("residual")) {
        assert!(residual(line) < 1e-9, "{line}");
    }
}

/// `examples/scenes/adhesive_shear.toml` as shipped (RCCM adhesion): the tangential resultant on
/// the base peaks above twice the friction plateau while the bond holds, and ends on Coulomb's
/// μ P = 0.5 × 1e4 Pa × 0.02 m = 100 N/m (β ≈ 0.0025 left) within 1 %.
#[test]
fn example_adhesive_shear_debonds_then_slides() {
    let out = scratch("adhesive-shear-example");
    crate::run_ok(
        crate::bin()
            .arg("run")
            .arg(crate::scene("examples/scenes/adhesive_shear.toml"))
            .args(["--quiet", "--out"])
            .arg(&out),
    );
    let r = crate::report(&out);
    let steps = r["steps"].as_array().unwrap();
    let shear: Vec<f64> = steps.iter().map(|s| s["tangential_resultant"].as_f64().unwrap()).collect();
    let plateau = 0.5 * 1e4 * 0.02;
    let peak = shear.iter().fold(0.0f64, |m, q| m.max(q.abs()));
    let end = *shear.last().unwrap();
    assert!(peak > 2.0 * plateau, "peak {peak} against the plateau {plateau}");
    assert!((end.abs() - plateau).abs() < 0.01 * plateau, "end {end} against the plateau {plateau}");
}
