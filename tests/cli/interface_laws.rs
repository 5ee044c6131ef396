//! `signorini run` on scenes with interface laws: `mpirun -n 2` gives the serial answer (the
//! staggered loop and its laws run the same on every rank), the estimate and the dual
//! formulation are refused by name, and the masonry joint example softens from its peak to
//! residual friction.

use crate::{bin, mpirun_two, python, report, run_err, run_ok, scene, scratch};

/// The largest difference between two interface files' fields, relative to each field's size.
fn interface_difference(a: &std::path::Path, b: &std::path::Path, fields: &[&str]) -> f64 {
    let s = python(&format!(
        "a = meshio.read(r'{}')\nb = meshio.read(r'{}')\nworst = 0.0\nfor f in {:?}:\n    x, y = a.point_data[f], b.point_data[f]\n    worst = max(worst, float(np.max(np.abs(x - y)) / max(np.max(np.abs(x)), 1e-300)))\nprint(worst)",
        a.display(),
        b.display(),
        fields
    ));
    s.trim().parse().unwrap()
}

/// The RCCM example (adhesion, its debonding, then friction) and the masonry joint (softening)
/// on 2 ranks: every increment's interface equals the serial one.
#[test]
fn mpirun_two_ranks_interface_laws_equal_serial() {
    for (example, fields, increments) in [
        ("adhesive_shear", &["opening", "slip", "traction_normal", "traction_tangential", "adhesion"][..], 40),
        ("masonry_joint", &["opening", "slip", "traction_normal", "traction_tangential", "damage"][..], 22),
    ] {
        let dir = scratch(&format!("mpi-interface-{example}"));
        let file = scene(&format!("examples/scenes/{example}.toml"));
        let serial = dir.join("serial");
        run_ok(bin().arg("run").arg(&file).args(["--quiet", "--out"]).arg(&serial));
        let parallel = dir.join("parallel");
        let out =
            mpirun_two().arg("run").arg(&file).args(["--quiet", "--out"]).arg(&parallel).output().expect("mpirun");
        assert!(out.status.success(), "{example}: {}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(report(&parallel)["mpi_ranks"], 2);
        for k in [increments / 2, increments] {
            let name = format!("steps/interface_{k:04}.vtu");
            let d = interface_difference(&serial.join(&name), &parallel.join(&name), fields);
            assert!(d < 1e-8, "{example}, increment {k}: MPI differs from serial by {d:e}");
        }
    }
}

/// `--estimate` and `--formulation dual` with an interface law stop before any work, naming the
/// contact, the law and where it is declared.
#[test]
fn interface_law_refuses_the_estimate_and_the_dual() {
    let dir = scratch("interface-refusals");
    let file = scene("examples/scenes/thin_layer.toml");
    for flags in [&["--estimate"][..], &["--formulation", "dual"][..]] {
        let err = run_err(bin().arg("run").arg(&file).args(flags).args(["--quiet", "--out"]).arg(dir.join("out")), 1);
        for word in ["not implemented", "`bottom`", "thin_layer", "thin_layer.toml:", "without --estimate"] {
            assert!(err.contains(word), "{flags:?}: `{word}` missing from: {err}");
        }
        assert!(!dir.join("out").join("report.json").exists(), "{flags:?}: nothing is written");
    }
}

/// `examples/scenes/masonry_joint.toml` as shipped: the joint sticks while it is pressed,
/// yields in the first shear increment, and its shear force softens towards residual friction
/// μσL (within 1 % at the end), monotonically, with the damage growing to nearly 1.
#[test]
fn example_masonry_joint_softens_to_friction() {
    let out = scratch("masonry-example");
    run_ok(bin().arg("run").arg(scene("examples/scenes/masonry_joint.toml")).args(["--quiet", "--out"]).arg(&out));
    let r = report(&out);
    let steps = r["steps"].as_array().unwrap();
    let q: Vec<f64> = steps.iter().map(|s| s["tangential_resultant"].as_f64().unwrap().abs()).collect();
    let (mu, sigma, length, c0) = (0.75, 0.6e6, 0.21, 0.8e6);
    let residual = mu * sigma * length;
    assert!(q[1] < 1e-6 * residual, "pressed only: the joint carries no shear ({})", q[1]);
    assert!(q[2] > residual && q[2] <= (c0 + mu * sigma) * length * (1.0 + 1e-9), "first shear increment: {}", q[2]);
    for k in 3..q.len() {
        assert!(q[k] <= q[k - 1] * (1.0 + 1e-9), "softening is monotone: {} then {}", q[k - 1], q[k]);
    }
    let last = *q.last().unwrap();
    assert!((last - residual).abs() < 0.01 * residual, "end {last}, residual friction {residual}");
    let csv = std::fs::read_to_string(out.join("history.csv")).unwrap();
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let column = header.iter().position(|h| *h == "interface_max_damage").expect("a damage column");
    let damage: f64 = csv.lines().last().unwrap().split(',').nth(column).unwrap().parse().unwrap();
    assert!(damage > 0.99 && damage <= 1.0, "damage at the end {damage}");
    assert!(out.join("interface_tau_delta.svg").exists());
}
