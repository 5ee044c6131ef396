//! `examples/scenes/thin_layer.toml`: a plinth on a thin bonded pad (`law = "thin_layer"`) runs,
//! and its interface answer satisfies checks computed here from the scene's data alone.

use crate::edit::Edit;
use crate::{bin, run_ok, scene, scratch};

/// The rows of `contact.csv`: `(x, pressure, tangential traction, gap, tangential slip, status)`.
fn contact_rows(dir: &std::path::Path) -> Vec<(f64, f64, f64, f64, f64, String)> {
    let text = std::fs::read_to_string(dir.join("contact.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no {name} in {header:?}"));
    let (x, p, t, g, s, st) =
        (col("x"), col("pressure"), col("tangential_traction"), col("gap"), col("tangential_slip"), col("status"));
    lines
        .map(|l| {
            let v: Vec<&str> = l.split(',').collect();
            let f = |k: usize| v[k].parse::<f64>().unwrap();
            (f(x), f(p), f(t), f(g), f(s), v[st].to_string())
        })
        .collect()
}

/// The bonded pad: at every point the springs' law with K_N = E(1 − ν)/((1 + ν)(1 − 2ν) e) and
/// K_T = E/(2(1 + ν) e) computed here (pressure = −K_N · gap, traction = −K_T · slip, to 1e-9 of
/// the peak); the trapezoidal sums of the tractions (the consistent weights of a uniform P1
/// side) give the applied loads (1.2 MN/m down, 0.8 MN/m along x) and the mean slip T/(K_T L)
/// (any body on uniform springs); the heel in tension; the base pressure within 2 % of the peak
/// of the rigid block's linear distribution N/L ∓ 6M/L² (the plinth's plane modulus is 10 times
/// the pad's K_N L: measured 1.05 %). The cut pad (bonded = false, Coulomb 0.8): the heel
/// lifts off, no point pulls.
#[test]
fn thin_layer_example_pad_answers() {
    let path = scene("examples/scenes/thin_layer.toml");
    let dir = scratch("thin-layer-example");
    run_ok(bin().arg("run").arg(&path).args(["--quiet", "--out"]).arg(&dir));
    let rows = contact_rows(&dir);
    let (young, nu, e, width, height) = (50e6_f64, 0.4_f64, 0.02_f64, 0.6_f64, 0.4_f64);
    let k_n = young * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * e);
    let k_t = young / (2.0 * (1.0 + nu) * e);
    let (n_load, t_load) = (2e6 * width, 2e6 * height);
    let moment = t_load * height / 2.0;
    let peak = n_load / width + 6.0 * moment / (width * width);
    assert_eq!(rows.len(), 61);
    let h = width / 60.0;
    let (mut n_sum, mut t_sum, mut slip_sum) = (0.0, 0.0, 0.0);
    for (i, (x, p, t, g, s, _)) in rows.iter().enumerate() {
        assert!((p + k_n * g).abs() <= 1e-9 * peak, "x = {x}: pressure {p:e}, gap {g:e}, K_N {k_n:e}");
        assert!((t + k_t * s).abs() <= 1e-9 * peak, "x = {x}: traction {t:e}, slip {s:e}, K_T {k_t:e}");
        let w = if i == 0 || i == rows.len() - 1 { h / 2.0 } else { h };
        n_sum += w * p;
        t_sum += w * t;
        slip_sum += w * s;
        let rigid = n_load / width + 12.0 * moment * x / width.powi(3);
        assert!((p - rigid).abs() <= 0.02 * peak, "x = {x}: pressure {p:e}, rigid block {rigid:e}");
    }
    assert!((n_sum - n_load).abs() <= 1e-9 * n_load, "normal resultant {n_sum:e}");
    assert!((t_sum + t_load).abs() <= 1e-9 * t_load, "tangential resultant {t_sum:e}");
    let mean_slip = t_load / (k_t * width);
    assert!(
        (slip_sum / width - mean_slip).abs() <= 1e-9 * mean_slip,
        "mean slip {:e}, {mean_slip:e}",
        slip_sum / width
    );
    let heel = rows.iter().min_by(|a, b| a.0.total_cmp(&b.0)).unwrap();
    assert!(heel.1 < -0.2 * n_load / width, "heel pressure {:e}: no tension", heel.1);

    // The cut pad: the heel lifts off.
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .edit("bonded = true", "bonded = false")
        .edit("normal = [0.0, 1.0]\n", "normal = [0.0, 1.0]\nfriction = \"coulomb\"\nmu = 0.8\n");
    let cut = dir.join("cut.toml");
    std::fs::write(&cut, text).unwrap();
    let out = dir.join("cut");
    run_ok(bin().arg("run").arg(&cut).args(["--quiet", "--out"]).arg(&out));
    let rows = contact_rows(&out);
    let open: Vec<f64> = rows.iter().filter(|r| r.5 == "open").map(|r| r.0).collect();
    assert!(!open.is_empty() && open.iter().all(|&x| x < -0.1), "open points at {open:?}");
    assert!(rows.iter().all(|r| r.1 >= 0.0), "a cut pad does not pull");
    assert!(rows.iter().filter(|r| r.5 == "open").all(|r| r.1 == 0.0 && r.3 > 0.0), "open points carry nothing");
}
