//! Load paths (issue 25): increments with friction memory on the condensed route, checked
//! against static solves, closed forms and finer references.
use super::contact::{example, set_line, solve_text};
use signorini::evolution::LoadPath;
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

/// Solve `text` along `path`, every increment post-processed; the problem after the path and
/// the displacement of every increment.
fn solve_path<'s>(
    s: &'s Session,
    text: &str,
    file: &std::path::Path,
    path: &LoadPath,
) -> Result<(ElasticityProblem<'s>, Vec<Vec<f64>>), String> {
    let scene = Scene::from_str(text, file).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    let mut fields = Vec::new();
    p.solve_load_path(path, signorini::evolution::EachIncrement::Postprocess, &mut |q, _| {
        fields.push(q.displacement.clone().expect("a step has a displacement"));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    Ok((p, fields))
}

fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt() / n
}

/// Proportional loading in N increments equals the static solve at every increment's load
/// where the law allows it: the square block (no initial gap, loads growing monotonically, slip
/// zones growing and never reversing) with Coulomb, Tresca and no friction. The slip of a
/// point that keeps slipping in one direction sums to the static slip (each increment's slip
/// opposes the same force), so each increment's answer is the static answer at its load. The
/// static answers come from the default full-space route at the scaled loads, the path from
/// the condensed route with the increments' memory.
pub fn load_path_proportional_equals_static(s: &Session) -> Result<(), String> {
    let (base, file) = example("square_block.toml");
    let cases = [
        ("coulomb", base.clone()),
        (
            "tresca",
            set_line(&base, "mu = 1.0", "threshold = 2e7").replace("friction = \"coulomb\"", "friction = \"tresca\""),
        ),
        ("frictionless", set_line(&base, "mu = 1.0", "").replace("friction = \"coulomb\"", "friction = \"none\"")),
    ];
    for (name, text) in cases {
        let text = text.replace("solver = \"newton_full\"", "solver = \"newton_full\"\ntolerance = 1e-12");
        let path = LoadPath::proportional(4).unwrap();
        let (p, fields) = solve_path(s, &text, &file, &path).map_err(|e| format!("{name}, path: {e}"))?;
        let mut worst = 0.0f64;
        for (k, u) in fields.iter().enumerate() {
            let t = path.times[k];
            assert!(
                text.contains("pressure = 5e7") && text.contains("pressure = 1.5e8"),
                "test bug: square_block.toml's loads changed"
            );
            let scaled = text
                .replace("pressure = 5e7", &format!("pressure = {:e}", 5e7 * t))
                .replace("pressure = 1.5e8", &format!("pressure = {:e}", 1.5e8 * t));
            let reference = solve_text(s, &scaled, &file).map_err(|e| format!("{name}, static at t = {t}: {e}"))?;
            worst = worst.max(relative_difference(reference.displacement.as_ref().unwrap(), u));
        }
        let report = p.load_path.as_ref().unwrap();
        eprintln!(
            "    {name}: worst |u(t_k) − u_static(t_k)| / |u_static(t_k)| = {worst:.2e} over {} increments; energy balance {:.2e}, dissipation {:.4e} J/m",
            fields.len(),
            report.energy.relative_residual,
            report.energy.dissipation
        );
        ensure(fields.len() == 4, || format!("{name}: {} increments", fields.len()))?;
        ensure(worst < 1e-10, || format!("{name}: the path differs from the static answers by {worst:.2e}"))?;
        ensure(report.energy.relative_residual < 1e-8, || format!("{name}: energy balance {:?}", report.energy))?;
        ensure(report.steps.iter().all(|r| r.dissipation >= -1e-12 * r.work.abs()), || {
            format!("{name}: negative dissipation {:?}", report.steps.iter().map(|r| r.dissipation).collect::<Vec<_>>())
        })?;
    }
    Ok(())
}

const STEEL_E: f64 = 210e9;
const STEEL_NU: f64 = 0.3;
const RADIUS: f64 = 0.1;
const MU: f64 = 0.3;

/// The two steel cylinders of `two_cylinders.toml` (identical bodies: Dundurs β = 0, so the
/// normal and tangential problems uncouple and Mindlin–Deresiewicz holds), cells of `fine`
/// near the contact, Coulomb μ = 0.3. The upper flat side is moved: pressed down by 1e-3 m
/// (`press`, t from 0 to 1), then sheared by ±2.5e-4 m through a full cycle
/// (`shear`: 0 → δ* at t = 2 → −δ* at t = 4 → δ* at t = 6); the lower flat side is clamped.
/// `per_unit` increments per unit of pseudo-time in the shear phase, 2 in the press phase.
fn fretting_text(fine: &str, per_unit: usize) -> (String, std::path::PathBuf) {
    let (text, path) = example("two_cylinders.toml");
    let text = text.replacen("cell_size = 2.5e-4", &format!("cell_size = {fine}"), 2);
    let loads = "[[body.traction]]\npart = \"flat\"\npressure = 2.25e8        # resultant P = 2.25e8 * 0.2 = \
                 4.5e7 N/m downwards\n\n[[body.dirichlet]]\npoint = [0.0, 0.1]       # the middle of the flat \
                 side\nux = 0.0\n";
    assert!(text.contains(loads), "test bug: two_cylinders.toml's upper loads changed");
    let moved = "[[body.dirichlet]]\npart = \"flat\"\nuy = -1e-3\nname = \"press\"\n\n[[body.dirichlet]]\npart = \
                 \"flat\"\nux = 2.5e-4\nname = \"shear\"\n";
    let text = text.replacen(loads, moved, 1);
    let text = set_line(&text, "friction", &format!("friction = \"coulomb\"\nmu = {MU}"));
    let mut times = vec![0.5, 1.0];
    for k in 1..=5 * per_unit {
        times.push(1.0 + k as f64 / per_unit as f64);
    }
    let times: Vec<String> = times.iter().map(|t| format!("{t}")).collect();
    let evolution = format!(
        "\n[evolution]\ntimes = [{}]\nmonitor = \"upper.flat\"\n\n[evolution.factor]\npress = [[0, 0], [1, 1], [6, 1]]\nshear = [[0, 0], [1, 0], \
         [2, 1], [4, -1], [6, 1]]\n",
        times.join(", ")
    );
    (text + &evolution, path)
}

/// What the fretting test reads of one increment: P and Q (the contact loads, Q signed as Σ rT
/// on the slave side) and the slave points `(x, pressure, friction traction, status)` by x.
struct Snapshot {
    time: f64,
    load: f64,
    shear: f64,
    points: Vec<(f64, f64, f64, signorini::contact::PointStatus)>,
}

fn snapshot(p: &ElasticityProblem, time: f64) -> Snapshot {
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, friction) = c.boundary.tractions(&o.force);
    let mut points: Vec<_> = (0..c.boundary.points())
        .map(|i| (p.mesh.nodes[c.boundary.nodes[i]][0], pressure[i], friction[i], o.status[i]))
        .collect();
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let load = -o.force.iter().step_by(2).sum::<f64>();
    let shear = o.force.iter().skip(1).step_by(2).sum::<f64>();
    Snapshot { time, load, shear, points }
}

/// Hertz for the two cylinders: a = √(4PR/(πE*)), p0 = 2P/(πa), R = R1 R2/(R1 + R2),
/// 1/E* = 2 (1 − ν²)/E (Johnson §4.2).
fn hertz(load: f64) -> (f64, f64) {
    let estar = STEEL_E / (2.0 * (1.0 - STEEL_NU * STEEL_NU));
    let a = (4.0 * load * (RADIUS / 2.0) / (std::f64::consts::PI * estar)).sqrt();
    (a, 2.0 * load / (std::f64::consts::PI * a))
}

/// `√(1 − x²/c²)` inside `|x| < c`, 0 outside.
fn ellipse(x: f64, c: f64) -> f64 {
    if c > 0.0 {
        (1.0 - x * x / (c * c)).max(0.0).sqrt()
    } else {
        0.0
    }
}

/// The half-width of the stick zone of a snapshot (its ends halfway between the last stick and
/// the first slip point) and the contact-node spacing at the centre.
fn stick_half_width(s: &Snapshot) -> Result<(f64, f64), String> {
    use signorini::contact::PointStatus;
    let pts = &s.points;
    let centre = pts.iter().position(|q| q.0 >= 0.0).ok_or("no contact point at x >= 0")?;
    let spacing = pts[centre + 1].0 - pts[centre].0;
    let stick: Vec<usize> = (0..pts.len()).filter(|&i| pts[i].3 == PointStatus::Stick).collect();
    let (Some(&first), Some(&last)) = (stick.first(), stick.last()) else {
        return Ok((0.0, spacing));
    };
    ensure(stick.len() == last - first + 1, || format!("t = {}: the stick points are not one zone", s.time))?;
    ensure(first > 0 && last + 1 < pts.len(), || format!("t = {}: the stick zone reaches the end", s.time))?;
    let left = 0.5 * (pts[first - 1].0 + pts[first].0);
    let right = 0.5 * (pts[last].0 + pts[last + 1].0);
    Ok((0.5 * (right - left), spacing))
}

/// Mindlin–Deresiewicz for two identical cylinders through a full tangential cycle at fixed
/// normal load (Johnson, Contact Mechanics, §7.2; SCIENCE.md §10), with a, p0 from Hertz and P,
/// Q from the contact forces of each increment (signs: s = sign of Q at the first peak, q and Q
/// multiplied by s):
///
/// ```text
///   loading 0 → Q*:      q = μp0 [√(1 − x²/a²) − (c/a) √(1 − x²/c²)],   c/a = √(1 − Q/μP)
///   unloading Q* → Q:    q = μp0 [−√(1 − x²/a²) + 2 (c′/a) √(1 − x²/c′²) − (c*/a) √(1 − x²/c*²)],
///                        c′/a = √(1 − (Q* − Q)/(2μP))
///   reloading −Q* → Q:   the same, mirrored
/// ```
///
/// Checked at the peak Q*, at every increment of the unloading and of the reloading: the stick
/// zone (the points that did not slip in the increment) against c and c′ within one node
/// spacing, and the friction traction over |x| < a against the closed form, RMS within 2.5 %
/// of μp0. Over the cycle: the energy balance (work = stored + dissipation, 1e-8) and each
/// increment's dissipation ≥ 0. The loop (Q against the imposed δ) is compared with a mesh
/// twice as fine: its unloading compliance within 2 % and its area (the dissipation per cycle)
/// within 3 %.
pub fn mindlin_deresiewicz_fretting_cycle(s: &Session) -> Result<(), String> {
    let coarse = fretting_cycle(s, "2.5e-4", 4)?;
    let fine = fretting_cycle(s, "1.25e-4", 4)?;
    let line = format!(
        "loop: compliance {:.5e} m/(N/m) (finer mesh {:.5e}, {:+.2} %), area {:.5e} J/m (finer {:.5e}, {:+.2} %)",
        coarse.0,
        fine.0,
        100.0 * (coarse.0 / fine.0 - 1.0),
        coarse.1,
        fine.1,
        100.0 * (coarse.1 / fine.1 - 1.0)
    );
    eprintln!("    {line}");
    ensure((coarse.0 / fine.0 - 1.0).abs() < 0.02, || format!("{line}: compliance"))?;
    ensure((coarse.1 / fine.1 - 1.0).abs() < 0.03, || format!("{line}: area"))?;
    Ok(())
}

/// One fretting cycle on cells of `fine` (see [`mindlin_deresiewicz_fretting_cycle`]): the
/// closed-form checks; returns the loop's unloading compliance and its area.
fn fretting_cycle(s: &Session, fine: &str, per_unit: usize) -> Result<(f64, f64), String> {
    let (text, file) = fretting_text(fine, per_unit);
    let scene = Scene::from_str(&text, &file).map_err(|e| e.to_string())?;
    let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("the scene has no load path")?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    let mut snaps = Vec::new();
    p.solve_load_path(&path, signorini::evolution::EachIncrement::Solve, &mut |q, record| {
        snaps.push(snapshot(q, record.time));
        Ok(())
    })
    .map_err(|e| format!("cells {fine}: {e}"))?;
    let report = p.load_path.clone().unwrap();
    let at = |t: f64| snaps.iter().position(|x| (x.time - t).abs() < 1e-9).expect("a time of the path");
    let peak = &snaps[at(2.0)];
    let sign = peak.shear.signum();
    let q_star = sign * peak.shear;
    let load = peak.load;
    let (a, p0) = hertz(load);
    let ratio = q_star / (MU * load);
    ensure((0.3..0.8).contains(&ratio), || format!("test setup: Q*/μP = {ratio}"))?;
    let c_star = a * (1.0 - ratio).sqrt();
    let mut worst_c: f64 = 0.0;
    let mut worst_rms: f64 = 0.0;
    for snap in &snaps[at(2.0)..] {
        let (a, p0) = hertz(snap.load);
        let q = sign * snap.shear;
        // Which branch: loading to the first peak, unloading to −Q*, reloading to Q*.
        let (c_expected, profile): (f64, Box<dyn Fn(f64) -> f64>) = if snap.time <= 2.0 + 1e-9 {
            let c = a * (1.0 - q / (MU * snap.load)).max(0.0).sqrt();
            (c, Box::new(move |x: f64| ellipse(x, a) - (c / a) * ellipse(x, c)))
        } else {
            // Unloading from +Q* (t ≤ 4) or reloading from −Q* (mirrored).
            let mirror = if snap.time <= 4.0 + 1e-9 { 1.0 } else { -1.0 };
            let travelled = (q_star - mirror * q).max(0.0);
            let c1 = a * (1.0 - travelled / (2.0 * MU * snap.load)).max(0.0).sqrt();
            let cs = c_star;
            (
                c1,
                Box::new(move |x: f64| {
                    mirror * (-ellipse(x, a) + 2.0 * (c1 / a) * ellipse(x, c1) - (cs / a) * ellipse(x, cs))
                }),
            )
        };
        let (c, spacing) = stick_half_width(snap)?;
        let errors: Vec<f64> =
            snap.points.iter().filter(|x| x.0.abs() < a).map(|x| sign * x.2 / (MU * p0) - profile(x.0)).collect();
        let rms = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len() as f64).sqrt();
        worst_c = worst_c.max((c - c_expected).abs() / spacing);
        worst_rms = worst_rms.max(rms);
        ensure((c - c_expected).abs() <= spacing, || {
            format!(
                "cells {fine}, t = {}: stick half-width {c:.4e}, Mindlin–Deresiewicz {c_expected:.4e} (spacing {spacing:.3e})",
                snap.time
            )
        })?;
        ensure(rms < 0.025, || format!("cells {fine}, t = {}: traction RMS {rms:.4} of μp0", snap.time))?;
    }
    let _ = p0;
    // The loop: Q against the imposed δ (the monitor's mean ux is δ, the flat side's).
    let cycle: Vec<&signorini::evolution::StepRecord> = report.steps.iter().filter(|r| r.time >= 2.0 - 1e-9).collect();
    let first = cycle[0];
    let next = cycle[1];
    let compliance = (next.monitor_displacement - first.monitor_displacement).abs()
        / (next.tangential_resultant - first.tangential_resultant).abs();
    let area: f64 = cycle[1..].iter().map(|r| r.dissipation).sum();
    let trapezoid = report.energy.dissipation;
    eprintln!(
        "    cells {fine}: dissipation over the path: the law's {:.6e} J/m, trapezoidal {trapezoid:.6e} J/m ({:+.2e} relative)",
        report.energy.law_dissipation,
        report.energy.law_dissipation / trapezoid - 1.0
    );
    eprintln!(
        "    cells {fine}: {} increments, Q*/μP = {ratio:.4}, c*/a = {:.4}; worst |c − c_MD| = {worst_c:.2} spacings, worst traction RMS {worst_rms:.4} of μp0; energy balance {:.2e}",
        report.steps.len(),
        c_star / a,
        report.energy.relative_residual
    );
    ensure(report.energy.relative_residual < 1e-8, || format!("energy balance {:?}", report.energy))?;
    ensure(report.steps.iter().all(|r| r.dissipation >= -1e-12 * r.work.abs().max(1e-30)), || {
        format!(
            "an increment with negative dissipation: {:?}",
            report.steps.iter().map(|r| (r.time, r.dissipation, r.work)).collect::<Vec<_>>()
        )
    })?;
    Ok((compliance, area))
}

/// The square block with its two loads on a path, `per_unit` increments per unit of time,
/// `cells` squares along each side, the contact solver's tolerance 1e-12:
/// `press-then-push` (the top pressure to full load on t ∈ [0, 1], then the side pressure on
/// t ∈ [1, 2]), `push-then-press` (the other way round) or `proportional` (both together on
/// [0, 2]).
fn square_block_path(history: &str, cells: usize, per_unit: usize) -> (String, std::path::PathBuf) {
    let (text, file) = example("square_block.toml");
    assert!(
        text.contains("pressure = 5e7\n") && text.contains("pressure = 1.5e8"),
        "test bug: square_block.toml changed"
    );
    let text = text
        .replace("pressure = 5e7\n", "pressure = 5e7\nname = \"press\"\n")
        .replace("pressure = 1.5e8", "name = \"push\"\npressure = 1.5e8")
        .replace("cell_size = 1.25e-3", &format!("cell_size = {:e}", 0.04 / cells as f64))
        .replace("solver = \"newton_full\"", "solver = \"newton\"\ntolerance = 1e-12");
    let (first, second, together) = ("[[0, 0], [1, 1], [2, 1]]", "[[0, 0], [1, 0], [2, 1]]", "[[0, 0], [2, 1]]");
    let (press, push) = match history {
        "press-then-push" => (first, second),
        "push-then-press" => (second, first),
        _ => (together, together),
    };
    let evolution =
        format!("\n[evolution]\nsteps = {}\n\n[evolution.factor]\npress = {press}\npush = {push}\n", 2 * per_unit);
    (text + &evolution, file)
}

/// ux along the contact side (y = 0) at the abscissae `xs`, linearly interpolated between the
/// nodes of the side.
fn bottom_ux(p: &ElasticityProblem, xs: &[f64]) -> Vec<f64> {
    let u = p.displacement.as_ref().unwrap();
    let mut side: Vec<(f64, f64)> =
        p.mesh.nodes.iter().enumerate().filter(|(_, x)| x[1].abs() < 1e-12).map(|(k, x)| (x[0], u[2 * k])).collect();
    side.sort_by(|a, b| a.0.total_cmp(&b.0));
    xs.iter()
        .map(|&x| {
            let k = side.partition_point(|q| q.0 <= x).clamp(1, side.len() - 1);
            let (a, b) = (side[k - 1], side[k]);
            a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
        })
        .collect()
}

/// Path dependence on the square block (Raous, Chabrand & Lebon; Coulomb μ = 1; the same final
/// loads on three histories), ux along the contact side:
/// - pressed, then pushed: pressing alone makes every point stick (the record says so), so
///   nothing slips before the push, which then slips every point one way: the answer is the
///   proportional one (to 1e-12 of the largest ux), and ux(0) is the benchmark's 2.86e-5 m;
/// - pushed, then pressed: the push slides the unpressed contact side freely, and the pressure
///   then locks that slip in: the answer differs from the proportional one by more than 10 %
///   of the largest ux;
/// - each history matches its own reference on a mesh 4× finer: the coarse–fine difference is
///   at most 3 % of the largest ux, and at most a fifth of the difference between the two
///   histories that differ.
pub fn square_block_path_dependence(s: &Session) -> Result<(), String> {
    let xs: Vec<f64> = (0..32).map(|k| k as f64 * 0.04 / 32.0).collect();
    let mut runs = Vec::new();
    for history in ["press-then-push", "proportional", "push-then-press"] {
        for cells in [32usize, 128] {
            let (text, file) = square_block_path(history, cells, 4);
            let scene = Scene::from_str(&text, &file).map_err(|e| e.to_string())?;
            let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
            let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
            p.assemble().map_err(|e| e.to_string())?;
            p.solve_load_path(&path, signorini::evolution::EachIncrement::Solve, &mut |_, _| Ok(()))
                .map_err(|e| format!("{history}, {cells}: {e}"))?;
            let report = p.load_path.as_ref().unwrap();
            ensure(report.energy.relative_residual < 1e-8, || format!("{history}: energy {:?}", report.energy))?;
            if history == "press-then-push" {
                let pressed = report.steps.iter().find(|r| (r.time - 1.0).abs() < 1e-12).unwrap();
                ensure(pressed.slip == 0 && pressed.stick == pressed.closed, || {
                    format!("{history}, {cells}: not every point sticks when pressed: {pressed:?}")
                })?;
            }
            runs.push(bottom_ux(&p, &xs));
        }
    }
    let norm = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let largest = runs.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let same = norm(&runs[0], &runs[2]);
    let between = norm(&runs[4], &runs[2]);
    let errors = [norm(&runs[0], &runs[1]), norm(&runs[2], &runs[3]), norm(&runs[4], &runs[5])];
    let line = format!(
        "square block: max |ux| {largest:.4e} m; press-then-push − proportional {same:.2e}; push-then-press − \
         proportional {between:.3e}; coarse − 4× finer: {:.3e}, {:.3e}, {:.3e}; ux(0) pressed then pushed {:.4e} \
         (benchmark 2.86e-5), pushed then pressed {:.4e}",
        errors[0], errors[1], errors[2], runs[1][0], runs[5][0]
    );
    eprintln!("    {line}");
    ensure(same <= 1e-12 * largest, || format!("{line}: pressing then pushing differs from proportional"))?;
    ensure(between >= 0.1 * largest, || format!("{line}: pushing then pressing is not path dependent"))?;
    ensure(errors.iter().all(|&e| e <= 0.03 * largest && e <= between / 5.0), || {
        format!("{line}: a history differs from its finer reference beyond the discretisation error")
    })?;
    Ok(())
}

/// The stick patch on a path: a block (2 m × 1 m, E = 90 GPa, ν = 0.2, P`order`) on a rigid
/// plane, Coulomb μ = 0.5, no support in x (held sideways by friction alone). Pressed by
/// p = 1 MPa (with the side pressures νp/(1 − ν) that make the stress uniform) on t ∈ [0, 1],
/// then sheared by a uniform q(t) = 0.3 p φ(t) on the top and the sides, φ: 0 → 1 → −1 → 0 on
/// t ∈ [1, 4]. Every point sticks (|q| < μp), the stress is uniform and the displacement
/// u = (2(1 + ν) q y / E, −(1 + ν)(1 − 2ν) p y /(E(1 − ν))) exactly, at every increment.
fn stick_patch_path_text(order: u32) -> String {
    let (p, nu) = (1e6_f64, 0.2_f64);
    let side = nu * p / (1.0 - nu);
    let q = 0.3 * p;
    format!(
        r#"
title = "stick patch on a path"
[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.3
mesher = "gmsh"
[discretization]
order = {order}
[material]
young = 90e9
poisson = 0.2
[[traction]]
part = "top"
traction = [0.0, {mp:e}]
name = "press"
[[traction]]
part = "right"
traction = [{ms:e}, 0.0]
name = "press"
[[traction]]
part = "left"
traction = [{side:e}, 0.0]
name = "press"
[[traction]]
part = "top"
traction = [{q:e}, 0.0]
name = "shear"
[[traction]]
part = "right"
traction = [0.0, {q:e}]
name = "shear"
[[traction]]
part = "left"
traction = [0.0, {mq:e}]
name = "shear"
[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = 0.5
solver = "newton"
[evolution]
steps = 8
[evolution.factor]
press = [[0, 0], [1, 1], [4, 1]]
shear = [[0, 0], [1, 0], [2, 1], [3, -1], [4, 0]]
"#,
        mp = -p,
        ms = -side,
        mq = -q,
    )
}

/// The stick patch on a path ([`stick_patch_path_text`]) is exact at every increment, P1 and
/// P2: the displacement within 1e-12 of the slope, every point sticking, and the friction
/// resultant equal to the applied shear.
pub fn stick_patch_exact_at_every_increment(s: &Session) -> Result<(), String> {
    let (e, nu, p) = (90e9_f64, 0.2_f64, 1e6_f64);
    for order in [1, 2] {
        let text = stick_patch_path_text(order);
        let file = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("stick_patch_path.toml");
        let scene = Scene::from_str(&text, &file).map_err(|e| e.to_string())?;
        let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
        let mut pr = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
        pr.assemble().map_err(|e| e.to_string())?;
        let mut worst = 0.0f64;
        let mut problems = Vec::new();
        let mut count = 0;
        pr.solve_load_path(&path, signorini::evolution::EachIncrement::Postprocess, &mut |q, record| {
            count += 1;
            let t = record.time;
            let press = path.factor(Some("press"), t);
            let shear = 0.3 * p * path.factor(Some("shear"), t);
            let k = -(1.0 + nu) * (1.0 - 2.0 * nu) * p * press / (e * (1.0 - nu));
            let kx = 2.0 * (1.0 + nu) * shear / e;
            let u = q.displacement.as_ref().unwrap();
            let err = q
                .mesh
                .nodes
                .iter()
                .enumerate()
                .map(|(i, x)| (u[2 * i] - kx * x[1]).abs().max((u[2 * i + 1] - k * x[1]).abs()))
                .fold(0.0, f64::max);
            worst = worst.max(err / k.abs().max(1e-300));
            let o = q.contact_outcome.as_ref().unwrap();
            if o.report.stick != o.report.points {
                problems.push(format!("t = {t}: {} of {} points stick", o.report.stick, o.report.points));
            }
            if (o.report.resultant[0] + 2.0 * shear).abs() > 1e-10 * p {
                problems.push(format!(
                    "t = {t}: friction resultant {:?}, applied shear {}",
                    o.report.resultant,
                    2.0 * shear
                ));
            }
            let r = &q.results.as_ref().unwrap().report;
            if r.equilibrium_residual > 1e-9 {
                problems.push(format!("t = {t}: equilibrium residual {}", r.equilibrium_residual));
            }
            Ok(())
        })
        .map_err(|e| format!("P{order}: {e}"))?;
        eprintln!("    P{order}: {count} increments, worst displacement error {worst:.2e} of the slope");
        ensure(problems.is_empty(), || format!("P{order}: {}", problems.join("; ")))?;
        ensure(count == 8 && worst <= 1e-12, || format!("P{order}: {count} increments, error {worst:e}"))?;
    }
    Ok(())
}

/// The estimate at every increment (`EachIncrement::Estimate`) on the square block without its
/// corner point (`square_block_tresca.toml`, refined to 14 cells a side):
/// - frictionless, loads ramped in 3 increments: each increment's estimate equals the static
///   estimate at its loads (frictionless steps are independent of the path), to 1e-8, with a
///   body force so that the answer is not a uniform stress (exact in P1, estimate zero);
/// - Tresca, pressed, pushed, then half unpushed (the side pressure back to one half: the slip
///   reverses near the pushed side): at every increment the dual passes its independent check
///   with the law on the slip increment, the contact terms of the estimate are nonnegative (an
///   admissible pair for the increment's problem: the estimator refuses otherwise), and the
///   estimate stays of the size of the static one at full load (between 0.5× and 2×).
pub fn estimate_at_every_increment(s: &Session) -> Result<(), String> {
    use signorini::evolution::EachIncrement;
    let (base, file) = example("square_block_tresca.toml");
    let base = base
        .replace("cell_size = 6e-3", "cell_size = 2.857142857142857e-3")
        .replace("solver = \"newton\"", "tolerance = 1e-11\nsolver = \"newton\"");
    // Frictionless: path against static.
    // A body force makes the answer other than a uniform stress (which P1 would get exactly).
    let frictionless = set_line(&base, "threshold", "").replace("friction = \"tresca\"", "friction = \"none\"")
        + "\n[loads]\nbody_force = [0.0, -1e9]\n";
    let path = LoadPath::proportional(3).unwrap();
    let scene = Scene::from_str(&frictionless, &file).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    let mut along = Vec::new();
    p.solve_load_path(&path, EachIncrement::Estimate, &mut |_, record| {
        along.push(record.estimate_percent.expect("an estimate per increment"));
        Ok(())
    })
    .map_err(|e| format!("frictionless path: {e}"))?;
    for (k, &t) in path.times.iter().enumerate() {
        let scaled = frictionless
            .replace("pressure = 5e7", &format!("pressure = {:e}", 5e7 * t))
            .replace("pressure = 1.5e8", &format!("pressure = {:e}", 1.5e8 * t))
            .replace("body_force = [0.0, -1e9]", &format!("body_force = [0.0, {:e}]", -1e9 * t));
        let mut q = solve_text(s, &scaled, &file).map_err(|e| format!("static at t = {t}: {e}"))?;
        q.solve_dual().and_then(|()| q.estimate()).map_err(|e| format!("static estimate at t = {t}: {e}"))?;
        let reference = q.estimate.as_ref().unwrap().estimate.relative_percent;
        eprintln!("    frictionless, t = {t:.4}: estimate {:.6} % (static {reference:.6} %)", along[k]);
        ensure((along[k] - reference).abs() <= 1e-8 * reference, || {
            format!("frictionless t = {t}: estimate {} % on the path, {reference} % static", along[k])
        })?;
    }
    // Tresca with a reversal.
    let text = base
        .replace("pressure = 5e7\n", "pressure = 5e7\nname = \"press\"\n")
        .replace("pressure = 1.5e8", "name = \"push\"\npressure = 1.5e8")
        + "\n[evolution]\nsteps = 6\n[evolution.factor]\npress = [[0, 0], [1, 1], [3, 1]]\npush = [[0, 0], [1, 0], [2, 1], [3, 0.5]]\n";
    let scene = Scene::from_str(&text, &file).map_err(|e| e.to_string())?;
    let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    let mut lines = Vec::new();
    let mut estimates = Vec::new();
    p.solve_load_path(&path, EachIncrement::Estimate, &mut |q, record| {
        let e = q.estimate.as_ref().expect("an estimate");
        lines.push(format!(
            "t = {:.2}: {:.4} % (contact {:.3e}, min contact integrand {:.2e}), stick/slip/open {}/{}/{}",
            record.time,
            e.estimate.relative_percent,
            e.estimate.contact,
            e.estimate.min_contact_integrand,
            record.stick,
            record.slip,
            record.open
        ));
        estimates.push(e.estimate.relative_percent);
        Ok(())
    })
    .map_err(|e| format!("Tresca path: {e}\n{}", lines.join("\n")))?;
    for l in &lines {
        eprintln!("    Tresca path, {l}");
    }
    let mut q = solve_text(s, &base, &file).map_err(|e| format!("static: {e}"))?;
    q.solve_dual().and_then(|()| q.estimate()).map_err(|e| format!("static estimate: {e}"))?;
    let reference = q.estimate.as_ref().unwrap().estimate.relative_percent;
    let at_full = estimates[path.times.iter().position(|&t| (t - 2.0).abs() < 1e-12).unwrap()];
    ensure(estimates.len() == path.times.len(), || format!("{} estimates", estimates.len()))?;
    ensure((0.5 * reference..2.0 * reference).contains(&at_full), || {
        format!("estimate at full load {at_full} % on the path, {reference} % static")
    })?;
    Ok(())
}

/// An increment that does not converge is cut in two (at most `MAX_HALVINGS` times each): the
/// square block pressed then pushed in one increment per phase, the Newton iterations limited
/// to 2. The path converges through halvings (the report counts them, the notes say where),
/// and its answer is the answer of the same increments listed from the start with no limit
/// (the same discrete path, to 1e-10). With 1 iteration even 5 halvings are not enough: the
/// error says so.
pub fn load_path_halves_failed_increments(s: &Session) -> Result<(), String> {
    use signorini::evolution::EachIncrement;
    let (text, file) = square_block_path("press-then-push", 16, 1);
    let limited = |n: usize| text.replace("tolerance = 1e-12", &format!("tolerance = 1e-12\nmax_iterations = {n}"));
    let run = |text: &str| -> Result<ElasticityProblem<'_>, String> {
        let scene = Scene::from_str(text, &file).map_err(|e| e.to_string())?;
        let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
        let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
        p.assemble().map_err(|e| e.to_string())?;
        p.solve_load_path(&path, EachIncrement::Solve, &mut |_, _| Ok(())).map_err(|e| e.to_string())?;
        Ok(p)
    };
    let halved = run(&limited(2))?;
    let report = halved.load_path.as_ref().unwrap();
    let times: Vec<f64> = report.steps.iter().map(|r| r.time).collect();
    eprintln!(
        "    2 Newton steps at most: {} halvings, increments at {times:?}, depths {:?}",
        report.halvings,
        report.steps.iter().map(|r| r.halvings).collect::<Vec<_>>()
    );
    ensure(report.halvings > 0 && times.len() > 2, || format!("no halving: {times:?}"))?;
    ensure(report.notes.iter().any(|n| n.contains("cut in two at t =")), || format!("notes {:?}", report.notes))?;
    // The same increments, listed, without the limit.
    let listed: Vec<String> = times.iter().map(|t| format!("{t:e}")).collect();
    let steps_line = "steps = 2\n";
    ensure(text.contains(steps_line), || "test bug: the path's steps line".into())?;
    let reference = run(&text.replace(steps_line, &format!("times = [{}]\n", listed.join(", "))))?;
    let d = relative_difference(reference.displacement.as_ref().unwrap(), halved.displacement.as_ref().unwrap());
    eprintln!("    against the same increments listed: {d:.2e}");
    ensure(d < 1e-10, || format!("the halved path differs from its increments listed by {d:e}"))?;
    match run(&limited(1)) {
        Err(e) => ensure(e.contains("even cut in two 5 times"), || format!("wrong error: {e}")),
        Ok(_) => Err("one Newton step per increment converged: the limit is not exercised".into()),
    }
}
