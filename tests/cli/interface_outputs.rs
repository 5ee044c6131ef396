//! `signorini run` with an interface law: a block glued to a rigid floor by a thin elastic
//! layer and pressed uniformly. With ν = 0 for the block the exact answer is uniform: the
//! stress σyy = −p everywhere, no lateral strain, the layer compressed by p / K_N with
//! K_N = E(1 − ν)/((1 + ν)(1 − 2ν) e) (plane strain, the layer's E, ν, e). The files are read
//! back by meshio and the csv parser of the test.
use crate::{bin, python, report, run_ok, scratch};

const P: f64 = 1e6;
const LAYER_E: f64 = 1e7;
const LAYER_NU: f64 = 0.3;
const LAYER_T: f64 = 1e-3;

fn glued_block(dir: &std::path::Path, evolution: &str) -> std::path::PathBuf {
    let text = format!(
        "title = \"glued block\"\n[mesh]\nshape = \"rectangle\"\nsize = [1.0, 0.2]\ncell_size = 0.05\n\
         [material]\nyoung = 1e9\npoisson = 0.0\n[[traction]]\npart = \"top\"\npressure = {P:e}\n\
         [contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
         [contact.interface]\nlaw = \"thin_layer\"\nyoung = {LAYER_E:e}\npoisson = {LAYER_NU}\n\
         thickness = {LAYER_T:e}\ntrace = [[0.5, 0.0]]\n{evolution}"
    );
    std::fs::create_dir_all(dir).unwrap();
    let file = dir.join("glued.toml");
    std::fs::write(&file, text).unwrap();
    file
}

fn normal_stiffness() -> f64 {
    LAYER_E * (1.0 - LAYER_NU) / ((1.0 + LAYER_NU) * (1.0 - 2.0 * LAYER_NU) * LAYER_T)
}

#[test]
fn a_thin_layer_run_writes_its_interface_files() {
    let dir = scratch("interface-static");
    let out = dir.join("out");
    let run = run_ok(bin().arg("run").arg(glued_block(&dir, "")).arg("--out").arg(&out));
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(stdout.contains("interface thin_layer: 21 point(s)"), "{stdout}");
    // interface.vtu: 21 vertices, the exact opening and tractions at every point.
    let check = python(&format!(
        "m = meshio.read(r'{}')\n\
         d = m.point_data\n\
         print(len(m.points), m.cells[0].type, sorted(d.keys()))\n\
         print(max(abs(d['traction_normal'] + {P:e})) / {P:e})\n\
         print(max(abs(d['opening'] - {opening:e})) / {opening_abs:e})\n\
         print(max(abs(d['traction_tangential'])) / {P:e}, max(abs(d['slip'])), max(d['law_residual']))",
        out.join("interface.vtu").display(),
        opening = -P / normal_stiffness(),
        opening_abs = P / normal_stiffness(),
    ));
    let lines: Vec<&str> = check.lines().collect();
    assert_eq!(
        lines[0], "21 vertex ['law_residual', 'opening', 'slip', 'traction_normal', 'traction_tangential']",
        "{check}"
    );
    let numbers = |line: &str| line.split_whitespace().map(|x| x.parse::<f64>().unwrap()).collect::<Vec<f64>>();
    assert!(numbers(lines[1])[0] < 1e-8, "traction error {check}");
    assert!(numbers(lines[2])[0] < 1e-8, "opening error {check}");
    let rest = numbers(lines[3]);
    assert!(rest[0] < 1e-8 && rest[1] < 1e-12 && rest[2] < 1e-8, "{check}");
    // report.json: the interface entry.
    let r = report(&out);
    assert_eq!(r["interface"]["laws"][0], "thin_layer", "{}", r["interface"]);
    assert_eq!(r["interface"]["final"]["points"], 21);
    let max_opening = r["interface"]["final"]["max_opening"].as_f64().unwrap();
    assert!((max_opening * normal_stiffness() / P + 1.0).abs() < 1e-8, "{max_opening}");
    // No load path: no collection, no history, no plot.
    for name in ["interface.pvd", "interface_tau_delta.svg", "history.csv"] {
        assert!(!out.join(name).exists(), "{name}");
    }
}

#[test]
fn a_thin_layer_load_path_writes_its_increments_history_and_plot() {
    let dir = scratch("interface-path");
    let out = dir.join("out");
    let scene = glued_block(&dir, "[evolution]\nsteps = 2\n");
    run_ok(bin().arg("run").arg(&scene).args(["--quiet", "--out"]).arg(&out));
    let pvd = std::fs::read_to_string(out.join("interface.pvd")).unwrap();
    for k in 1..=2 {
        let name = format!("steps/interface_{k:04}.vtu");
        assert!(out.join(&name).exists() && pvd.contains(&name), "{name}:\n{pvd}");
    }
    let read = python(&format!(
        "m = meshio.read(r'{}')\nprint(len(m.points), round(float(m.point_data['traction_normal'].mean()) / {P:e}, 9))",
        out.join("steps/interface_0001.vtu").display()
    ));
    assert_eq!(read.trim(), "21 -0.5", "half the load at the first of two increments");
    // history.csv: the interface's columns after the others; openings −p t/K_N at t = 1/2, 1.
    let csv = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 3, "{csv}");
    let header: Vec<&str> = lines[0].split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("{name}: {csv}"));
    for (k, line) in lines[1..].iter().enumerate() {
        let row: Vec<&str> = line.split(',').collect();
        assert_eq!(row[column("interface_min_adhesion")], "", "a thin layer has no adhesion");
        assert_eq!(row[column("interface_max_damage")], "");
        let opening: f64 = row[column("interface_max_opening_m")].parse().unwrap();
        let exact = -P * (k + 1) as f64 / 2.0 / normal_stiffness();
        assert!((opening / exact - 1.0).abs() < 1e-8, "increment {}: {opening} vs {exact}", k + 1);
    }
    // The τ–δ plot, of the point asked for.
    assert!(std::fs::read_to_string(out.join("interface_tau_delta.svg")).unwrap().contains("<svg"));
    let r = report(&out);
    assert_eq!(r["interface"]["traced_points"], serde_json::json!([[0.5, 0.0]]), "{}", r["interface"]);
    // A static run into the same directory removes the path's interface files.
    run_ok(bin().arg("run").arg(glued_block(&dir, "")).args(["--quiet", "--out"]).arg(&out));
    for name in ["interface.pvd", "interface_tau_delta.svg", "steps/interface_0001.vtu"] {
        assert!(!out.join(name).exists(), "{name} survived");
    }
    assert!(out.join("interface.vtu").exists());
}
