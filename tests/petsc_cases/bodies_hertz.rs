//! Two elastic bodies in contact against the analytic solutions (issue 13, item 6): Hertz
//! between two cylinders (identical, and steel on aluminium), and Cattaneo–Mindlin partial slip
//! between two identical cylinders; the per-body and per-pair checks of `report.json` → `bodies`.
//!
//! All cases use `examples/scenes/two_cylinders.toml` (two half discs of radius 0.1 m, P2,
//! refined near the initial contact point) with text edits. Reference: K. L. Johnson, Contact
//! Mechanics, Cambridge 1985, §4.2 (Hertz, two cylinders), §7.1 (Cattaneo–Mindlin).

use super::edit::Edit;
use std::f64::consts::PI;

use signorini::contact::PointStatus;
use signorini::error::Error;
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;

use super::contact::{example, set_line, solve_text};
use super::ensure;

/// Radius of each cylinder: 1/R = 1/R1 + 1/R2.
const RADIUS: f64 = 0.1;
const STEEL: (f64, f64) = (210e9, 0.3);
const ALUMINIUM: (f64, f64) = (70e9, 0.33);

/// 1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2 (plane strain).
fn effective_modulus((e1, nu1): (f64, f64), (e2, nu2): (f64, f64)) -> f64 {
    1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2)
}

/// Hertz half-width and peak pressure of two cylinders of radius [`RADIUS`] pressed by `load`
/// (N/m): a = √(4PR/(πE*)), p0 = 2P/(πa), R = R1 R2 / (R1 + R2).
fn hertz_exact(load: f64, estar: f64) -> (f64, f64) {
    let r = RADIUS / 2.0;
    let a = (4.0 * load * r / (PI * estar)).sqrt();
    (a, 2.0 * load / (PI * a))
}

/// The two cylinders' scene with the refined cell size `fine` near the contact point, each
/// body's material `(young, poisson)`, the pressure on the upper flat side; frictionless.
fn hertz_scene(fine: &str, upper: (f64, f64), lower: (f64, f64), pressure: f64) -> (String, std::path::PathBuf) {
    let (text, path) = example("two_cylinders.toml");
    let text = text.edit("cell_size = 2.5e-4", &format!("cell_size = {fine}"));
    let materials = format!("young = {:e}\npoisson = {}\nplane = \"strain\"\n\n[[body.traction]]", upper.0, upper.1);
    let text = text.replacen("young = 210e9\npoisson = 0.3\nplane = \"strain\"\n\n[[body.traction]]", &materials, 1);
    let text = text.replacen(
        "young = 210e9\npoisson = 0.3\nplane = \"strain\"\n\n[[body.dirichlet]]\npart = \"flat\"",
        &format!(
            "young = {:e}\npoisson = {}\nplane = \"strain\"\n\n[[body.dirichlet]]\npart = \"flat\"",
            lower.0, lower.1
        ),
        1,
    );
    let text = set_line(&text, "pressure", &format!("pressure = {pressure:e}"));
    assert!(
        !text.contains("young = 210e9") && text.contains(&format!("cell_size = {fine}, radius")),
        "test bug: two_cylinders.toml was not edited as expected"
    );
    (text, path)
}

/// The slave side's contact points: (x, pressure, friction traction, status), sorted by x,
/// pressures from `tractions()` (the nodal values −rN/w).
fn contact_points(p: &ElasticityProblem) -> Vec<(f64, f64, f64, PointStatus)> {
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, friction) = c.boundary.tractions(&o.force);
    let mut pts: Vec<_> = (0..c.boundary.points())
        .map(|i| (p.mesh.nodes[c.boundary.nodes[i]][0], pressure[i], friction[i], o.status[i]))
        .collect();
    pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    pts
}

/// Fit p(x) = p0 √(1 − x²/a²) to the points carrying a real fraction of the peak pressure: p²
/// is linear in x² (`contact::fit_half_width_and_peak`).
fn hertz_fit(pts: &[(f64, f64, f64, PointStatus)]) -> (f64, f64) {
    let peak = pts.iter().map(|q| q.1).fold(0.0, f64::max);
    let closed: Vec<(f64, f64)> = pts.iter().filter(|q| q.1 > 1e-6 * peak).map(|q| (q.0, q.1)).collect();
    super::contact::fit_half_width_and_peak(&closed)
}

/// The normal load P (the sum of the slave side's normal contact forces, −Σ rN) and the
/// tangential one Q (Σ rT).
fn contact_loads(p: &ElasticityProblem) -> (f64, f64) {
    let f = &p.contact_outcome.as_ref().unwrap().force;
    let normal: f64 = f.iter().step_by(2).sum();
    let tangential: f64 = f.iter().skip(1).step_by(2).sum();
    (-normal, tangential)
}

/// `report()` → `bodies`: each body's equilibrium residual below 1e-6 and the pair's
/// action–reaction residual below `action_reaction` (also present in the JSON form).
fn check_bodies_report(p: &ElasticityProblem, what: &str, action_reaction: f64) -> Result<(f64, f64), String> {
    let report = p.report().map_err(|e| format!("{what}: report: {e}"))?;
    let bodies = report.bodies.as_ref().ok_or_else(|| format!("{what}: report has no `bodies`"))?;
    let names: Vec<&str> = bodies.bodies.iter().map(|b| b.name.as_str()).collect();
    ensure(names == ["upper", "lower"], || format!("{what}: bodies {names:?}"))?;
    let mut worst_equilibrium = 0.0f64;
    for b in &bodies.bodies {
        ensure(b.equilibrium_residual < 1e-6, || {
            format!("{what}: body `{}`: equilibrium residual {:e} ({b:?})", b.name, b.equilibrium_residual)
        })?;
        worst_equilibrium = worst_equilibrium.max(b.equilibrium_residual);
    }
    ensure(bodies.contacts.len() == 1, || format!("{what}: {} contact parts", bodies.contacts.len()))?;
    let pair = &bodies.contacts[0];
    let residual = pair.action_reaction_residual.ok_or_else(|| format!("{what}: no action_reaction_residual"))?;
    ensure(residual < action_reaction && pair.master_resultant.is_some(), || {
        format!("{what}: action-reaction residual {residual:e} ({pair:?})")
    })?;
    // The pointwise check of the two sides' nodes: made, and below its limit (1e-3) by more
    // than a factor 3 (measured: 2e-6 to 7e-5 of the displacement scale).
    let np = pair.node_penetration.as_ref().ok_or_else(|| format!("{what}: no node_penetration"))?;
    eprintln!(
        "    {what}: pointwise penetration {:.1e} of the displacement scale ({} nodes)",
        np.max_penetration, np.measured_nodes
    );
    ensure(np.measured_nodes > 10 && np.max_penetration < 3e-4, || format!("{what}: pointwise penetration {np:?}"))?;
    // The same fields in report.json.
    let json = serde_json::to_value(&report).map_err(|e| e.to_string())?;
    let listed = &json["bodies"]["bodies"];
    ensure(
        listed.as_array().map_or(0, |a| a.len()) == 2
            && listed[0]["equilibrium_residual"].is_number()
            && listed[1]["equilibrium_residual"].is_number()
            && json["bodies"]["contacts"][0]["action_reaction_residual"].is_number()
            && json["bodies"]["contacts"][0]["node_penetration"]["max_penetration"].is_number(),
        || format!("{what}: report.json's `bodies` lacks fields: {}", json["bodies"]),
    )?;
    Ok((worst_equilibrium, residual))
}

/// Hertz between two cylinders: fit half-width and peak pressure, compare within `tolerance`.
fn hertz_case(
    s: &Session,
    fine: &str,
    upper: (f64, f64),
    lower: (f64, f64),
    pressure: f64,
    tolerance: f64,
) -> Result<String, String> {
    let what = format!("Hertz {fine}, E = {:e} on {:e}", upper.0, lower.0);
    let (text, path) = hertz_scene(fine, upper, lower, pressure);
    let p = solve_text(s, &text, &path).map_err(|e| format!("{what}: {e}"))?;
    let load = pressure * 2.0 * RADIUS;
    let estar = effective_modulus(upper, lower);
    let (a_exact, p0_exact) = hertz_exact(load, estar);
    let pts = contact_points(&p);
    let (a, p0) = hertz_fit(&pts);
    let (ea, ep) = ((a - a_exact).abs() / a_exact, (p0 - p0_exact).abs() / p0_exact);
    // The normal load the contact carries is the applied one (the upper body is held by it).
    let (normal, _) = contact_loads(&p);
    ensure((normal - load).abs() < 1e-3 * load, || format!("{what}: contact carries {normal:e}, load {load:e}"))?;
    let (eq, ar) = check_bodies_report(&p, &what, 1e-10)?;
    // The default route: the full-space Newton, the upper cylinder held by the contact alone
    // (floating elimination) and free to turn about its centre on frictionless contact (springs
    // on that motion only): no hand-over to the condensed route.
    let o = p.contact_outcome.as_ref().ok_or("no contact outcome")?;
    let notes = o.report.notes.join("; ");
    ensure(o.report.solver.starts_with("full-space") && !notes.contains("fell back"), || {
        format!("{what}: solved by {} ({notes})", o.report.solver)
    })?;
    ensure(o.report.iterations <= 20 && eq < 1e-10, || {
        format!("{what}: {} Newton steps, equilibrium {eq:e}", o.report.iterations)
    })?;
    let line = format!(
        "{what}: a = {a:.5e} (Hertz {a_exact:.5e}, {:+.3} %), p0 = {p0:.5e} (Hertz {p0_exact:.5e}, {:+.3} %); \
         equilibrium {eq:.1e}, action-reaction {ar:.1e}, {} Newton steps",
        100.0 * (a - a_exact) / a_exact,
        100.0 * (p0 - p0_exact) / p0_exact,
        o.report.iterations
    );
    eprintln!("    {line}");
    ensure(ea < tolerance && ep < tolerance, || format!("{line}: beyond {} %", 100.0 * tolerance))?;
    Ok(line)
}

/// Hertz, two identical steel cylinders (the example scene as it is: cells of a/20 near the
/// contact): a and p0 within 0.2 % (the issue asks 1 %; measured +0.078 % and +0.023 %).
pub fn hertz_two_cylinders(s: &Session) -> Result<(), String> {
    hertz_case(s, "2.5e-4", STEEL, STEEL, 2.25e8, 0.002).map(|_| ())
}

/// Hertz, steel on aluminium (E* from both bodies), the load scaled so that a is the same as
/// for two steel cylinders: a and p0 within 1 %; and aluminium on steel (the softer body the
/// slave side), the same E*. Cells of a/10 near the contact. Measured: a +0.046 % and +0.058 %,
/// p0 +0.017 % and +0.005 %; the test asks 0.2 %. (With the rows along the slave normal
/// instead of the two sides' bisector, p0 was 0.2 % high whatever the mesh.)
pub fn hertz_two_cylinders_steel_on_aluminium(s: &Session) -> Result<(), String> {
    let ratio = effective_modulus(STEEL, ALUMINIUM) / effective_modulus(STEEL, STEEL);
    hertz_case(s, "5e-4", STEEL, ALUMINIUM, 2.25e8 * ratio, 0.002)?;
    hertz_case(s, "5e-4", ALUMINIUM, STEEL, 2.25e8 * ratio, 0.002).map(|_| ())
}

/// The two cylinders with the upper flat side moved by (`ux`, `uy`) (the lower one clamped),
/// Coulomb friction `mu`, cells of `fine` near the contact.
fn cattaneo_scene(fine: &str, ux: f64, uy: f64, mu: f64) -> (String, std::path::PathBuf) {
    let (text, path) = example("two_cylinders.toml");
    let text = text.edit("cell_size = 2.5e-4", &format!("cell_size = {fine}"));
    let loads = "[[body.traction]]\npart = \"flat\"\npressure = 2.25e8        # resultant P = 2.25e8 * 0.2 = \
                 4.5e7 N/m downwards\n\n[[body.dirichlet]]\npoint = [0.0, 0.1]       # the middle of the flat \
                 side\nux = 0.0\n";
    assert!(text.contains(loads), "test bug: two_cylinders.toml's upper loads changed");
    let text = text.replacen(loads, &format!("[[body.dirichlet]]\npart = \"flat\"\nux = {ux:e}\nuy = {uy:e}\n"), 1);
    let text = set_line(&text, "friction", &format!("friction = \"coulomb\"\nmu = {mu}"));
    (text, path)
}

/// Cattaneo–Mindlin between two identical cylinders (Johnson §7.1): the normal load P and a
/// tangential load Q < μP, frictional contact (Coulomb μ = 0.3).
///
/// Identical bodies (Dundurs β = 0): the normal pressure makes no relative tangential
/// displacement and the tangential traction no relative normal one, so the static solve with
/// both loads at once is the answer of "pressed, then sheared" (no slip while pressing, slip
/// zones growing with Q in one direction while shearing). Supports: the lower flat side
/// clamped, the upper one moved rigidly by (δx, −δy): it can neither rotate (a pressure and a
/// shear traction on it would tip it over, the moment Q·R acting on it) nor shear differently
/// from the lower side, so the two bodies are each other's 180° rotation — the symmetric
/// configuration in which β = 0 decouples the two problems. P and Q are then reactions, read
/// from the contact forces; δ = (2.5e-4, 1e-3) m gives P = 4.93e7 N/m and Q/μP = 0.507.
///
/// Checks: c/a = √(1 − Q/μP) within one contact-node spacing (c: half the stick zone, its ends
/// halfway between the last stick and the first slip point); the stick zone centred on x = 0
/// within half a spacing; the tangential traction in the stick zone
/// q(x) = μp0 (√(1 − x²/a²) − (c/a) √(1 − (x − e)²/c²)) within 2 % of μp0 on its inner 80 %,
/// e its centre. Measured: c/a 0.6997 against 0.7003, e/a below 1e-4, traction within 0.3 %.
///
/// The centre: with the rows along the slave side's normal it was shifted by e/a = 0.107
/// whatever the mesh, flipping with the slave and master sides swapped, scaling as
/// 0.65 (a/R)/μ — the master carried a tangential traction ≈ 2p x/R from the two sides'
/// normals differing by 2x/R. The rows now follow the bisector of the two normals
/// (`contact/mortar/mod.rs`, "Contact direction"), which removed it.
pub fn cattaneo_mindlin_two_cylinders(s: &Session) -> Result<(), String> {
    let mu = 0.3;
    let (text, path) = cattaneo_scene("2.5e-4", 2.5e-4, -1e-3, mu);
    let p = solve_text(s, &text, &path).map_err(|e| format!("Cattaneo: {e}"))?;
    let (load, shear) = contact_loads(&p);
    let q_over_mu_p = shear.abs() / (mu * load);
    ensure((0.4..0.6).contains(&q_over_mu_p), || {
        format!("test setup: Q/μP = {q_over_mu_p} (P {load:e}, Q {shear:e})")
    })?;
    let (a, p0) = hertz_exact(load, effective_modulus(STEEL, STEEL));
    let c_exact = a * (1.0 - q_over_mu_p).sqrt();
    let pts = contact_points(&p);
    // Contact-node spacing near the centre.
    let centre = pts.iter().position(|q| q.0 >= 0.0).ok_or("no contact point at x >= 0")?;
    let spacing = pts[centre + 1].0 - pts[centre].0;
    let stick: Vec<usize> = (0..pts.len()).filter(|&i| pts[i].3 == PointStatus::Stick).collect();
    let (first, last) = (*stick.first().ok_or("no stick point")?, *stick.last().unwrap());
    ensure(stick.len() == last - first + 1, || format!("the stick points are not one zone: {stick:?}"))?;
    ensure(pts[first - 1].3 == PointStatus::Slip && pts[last + 1].3 == PointStatus::Slip, || {
        "the stick zone is not bordered by slip points".into()
    })?;
    let left = 0.5 * (pts[first - 1].0 + pts[first].0);
    let right = 0.5 * (pts[last].0 + pts[last + 1].0);
    let (c, e) = (0.5 * (right - left), 0.5 * (right + left));
    // The tangential traction against Cattaneo's, with the stick zone centred where it is.
    let sign = shear.signum(); // the sign of the friction tractions on the slave points (Q = Σ rT)
    let mut worst = 0.0f64;
    let mut at_centre = f64::NAN;
    for &i in &stick {
        let (x, _, q, _) = pts[i];
        let cattaneo = mu
            * p0
            * ((1.0 - x * x / (a * a)).max(0.0).sqrt()
                - (c_exact / a) * (1.0 - (x - e).powi(2) / (c_exact * c_exact)).max(0.0).sqrt());
        if (x - e).abs() <= 0.8 * c {
            worst = worst.max((sign * q - cattaneo).abs() / (mu * p0));
        }
        if (x - e).abs() < 0.5 * spacing {
            at_centre = sign * q / (mu * p0);
        }
    }
    let line = format!(
        "Cattaneo: P = {load:.4e}, Q/μP = {q_over_mu_p:.4}, c/a = {:.4} (Cattaneo {:.4}; {:+.2} spacings of {spacing:.3e}), \
         stick zone centre e/a = {:+.4} (half a spacing: {:.4}), q(e)/μp0 = {at_centre:.4} (Cattaneo {:.4}), \
         worst |q − q_Cattaneo|/μp0 on the inner 80 % = {worst:.4}",
        c / a,
        c_exact / a,
        (c - c_exact) / spacing,
        e / a,
        0.5 * spacing / a,
        1.0 - c_exact / a,
    );
    eprintln!("    {line}");
    ensure((c - c_exact).abs() <= spacing, || format!("{line}: c beyond one spacing"))?;
    ensure(e.abs() <= 0.5 * spacing, || format!("{line}: the stick zone is not centred"))?;
    ensure(worst < 0.02, || format!("{line}: tangential traction off Cattaneo's"))?;
    // The whole profile, slip zones included: measured 0.87 % of μp0 RMS.
    let rms = cattaneo_rms(&p, mu, effective_modulus(STEEL, STEEL));
    eprintln!("    Cattaneo, ν = 0.3: RMS |q − q_Cattaneo|/μp0 over |x| < a = {rms:.4}");
    ensure(rms < 0.02, || format!("Cattaneo, ν = 0.3: RMS {rms:.4} of μp0"))?;
    check_bodies_report(&p, "Cattaneo", 1e-10).map(|_| ())
}

/// The tangential traction of the slave points against Cattaneo–Mindlin's closed form over the
/// whole contact zone `|x| < a`: RMS of `(q − q_C)/μp0`, where
/// `q_C = μp0 (√(1 − x²/a²) − (c/a) √(1 − x²/c²)₊)` (the slip zones `|x| > c` follow the Coulomb
/// limit `μp`), `c/a = √(1 − Q/μP)`, and P, Q (the contact loads) and a, p0 (Hertz, from P and
/// `estar`) from the solution's contact forces.
fn cattaneo_rms(p: &ElasticityProblem, mu: f64, estar: f64) -> f64 {
    let (load, shear) = contact_loads(p);
    let (a, p0) = hertz_exact(load, estar);
    let c = a * (1.0 - shear.abs() / (mu * load)).max(0.0).sqrt();
    let sign = shear.signum();
    let errors: Vec<f64> = contact_points(p)
        .iter()
        .filter(|q| q.0.abs() < a)
        .map(|&(x, _, q, _)| {
            let exact = (1.0 - x * x / (a * a)).max(0.0).sqrt() - (c / a) * (1.0 - x * x / (c * c)).max(0.0).sqrt();
            sign * q / (mu * p0) - exact
        })
        .collect();
    (errors.iter().map(|e| e * e).sum::<f64>() / errors.len().max(1) as f64).sqrt()
}

/// Cattaneo–Mindlin near incompressibility (issue 23, item 4): the two cylinders of
/// [`cattaneo_mindlin_two_cylinders`] at ν = 0.4999 with P2–P0 elements (`element = "p2p0"`),
/// the same supports and imposed motion. Identical bodies keep the normal and tangential
/// problems uncoupled at any ν (Dundurs β = 0), so the closed form holds with
/// E* = E/(2(1 − ν²)). The tangential traction over the whole contact zone, RMS of μp0: at
/// most 2 % (measured 0.68 %; 0.73 % at ν = 0.49, 0.87 % at ν = 0.3). With P2 elements alone
/// (which lock) it is 11.4 % at ν = 0.4999 (1.5 % at ν = 0.49): the test tells the two apart.
///
/// The 6.9 % RMS reported in the issue is one cylinder on the rigid plane
/// (`examples/scenes/hertz_incompressible.toml` with Coulomb friction and a tangential motion of
/// its flat side), a single-body route: there the profile is right but the stick zone is
/// shifted by e/a ≈ −0.10 at a/R = 0.055 (the same, −0.103, with cells half as large; −0.05
/// at a/R = 0.025), so the comparison with the closed form centred at 0 gives 8.5 % RMS, and
/// 1.4 % once centred where the stick zone is.
/// The shift scales with a/R: it is the curved body's own response (a vertical pressure on
/// a surface tilted by x/R), which the half-space theory leaves out and which two identical
/// cylinders cancel by symmetry. At ν = 0.49 the Dundurs coupling of an elastic body on a
/// rigid one (β ≈ 0.02) shifts it the other way, which is why that profile looked better.
pub fn cattaneo_mindlin_two_cylinders_near_incompressible(s: &Session) -> Result<(), String> {
    let mu = 0.3;
    let nu = 0.4999;
    let estar = effective_modulus((STEEL.0, nu), (STEEL.0, nu));
    let (text, path) = cattaneo_scene("2.5e-4", 2.5e-4, -1e-3, mu);
    ensure(text.matches("poisson = 0.3\n").count() == 2 && text.matches("order = 2\n").count() == 2, || {
        "test bug: two_cylinders.toml's materials or orders changed".into()
    })?;
    let text = text.replace("poisson = 0.3\n", &format!("poisson = {nu}\n"));
    let mut rms = Vec::new();
    for element in ["p2p0", "lagrange"] {
        let text = text.replace("order = 2\n", &format!("order = 2\nelement = \"{element}\"\n"));
        let p = solve_text(s, &text, &path).map_err(|e| format!("Cattaneo, ν = {nu}, {element}: {e}"))?;
        let (load, shear) = contact_loads(&p);
        let value = cattaneo_rms(&p, mu, estar);
        eprintln!(
            "    Cattaneo, ν = {nu}, {element}: P = {load:.4e}, Q/μP = {:.4}, RMS |q − q_Cattaneo|/μp0 over |x| < a \
             = {value:.4}",
            shear.abs() / (mu * load)
        );
        if element == "p2p0" {
            check_bodies_report(&p, "Cattaneo near incompressibility", 1e-10)?;
        }
        rms.push(value);
    }
    ensure(rms[0] <= 0.02, || format!("P2–P0 at ν = {nu}: RMS {:.4} of μp0 (at most 0.02)", rms[0]))?;
    ensure(rms[1] > 0.05, || format!("P2 at ν = {nu}: RMS {:.4} of μp0, expected the locking's > 0.05", rms[1]))
}

/// report.json → `bodies`, on a coarse mesh (cells of 1e-3 near the contact): both bodies'
/// equilibrium residual below 1e-6 and the pair's action–reaction residual below 1e-10, with the
/// upper body held by the contact alone vertically (the example's supports: the proximal
/// springs' residual force enters the upper body's balance) and with both bodies held by their
/// supports and Coulomb friction.
pub fn two_bodies_report_equilibrium_and_action_reaction(s: &Session) -> Result<(), String> {
    let (text, path) = hertz_scene("1e-3", STEEL, ALUMINIUM, 2.25e8);
    let p = solve_text(s, &text, &path).map_err(|e| format!("held by contact: {e}"))?;
    let (eq, ar) = check_bodies_report(&p, "held by contact", 1e-10)?;
    eprintln!("    held by contact (frictionless): equilibrium {eq:.2e}, action-reaction {ar:.2e}");
    let (text, path) = cattaneo_scene("1e-3", 2.5e-4, -1e-3, 0.3);
    let p = solve_text(s, &text, &path).map_err(|e| format!("supported, Coulomb: {e}"))?;
    let (eq, ar) = check_bodies_report(&p, "supported, Coulomb", 1e-10)?;
    eprintln!("    supported (Coulomb): equilibrium {eq:.2e}, action-reaction {ar:.2e}");
    Ok(())
}

/// The pointwise check catches what the pairing cannot see: the upper cylinder pushed down by
/// 3 cm (0.3 of its radius; the run warns of large displacements) brings arc nodes into
/// contact that lay, in the reference configuration, farther than the pairing distance
/// (0.1 × the arc's extent, 2.2 cm) from the lower arc. They are not contact points, so the
/// weak constraint says nothing about them, and the two arcs go through each other there (by
/// 2.5 % of the displacements; the linearised constraint at the last paired nodes, tilted by
/// 30°, is off as much): before this check the run passed every residual and exited 0. Now
/// it is an error that names the node, its body, the pair and the small-sliding limit.
pub fn two_cylinders_beyond_small_sliding_fail_the_check(s: &Session) -> Result<(), String> {
    let (text, path) = cattaneo_scene("2e-3", 0.0, -0.03, 0.3);
    match solve_text(s, &text, &path) {
        Err(Error::SolverDiverged { solver, reason, tried, .. }) => ensure(
            solver.contains("independent check")
                && (reason.contains("of body `upper`") || reason.contains("of body `lower`"))
                && reason.contains("upper.arc / lower.arc")
                && reason.contains("penetrates the other side")
                && tried.contains("small sliding"),
            || format!("wrong message: {reason}; {tried}"),
        ),
        Err(e) => Err(format!("wrong error: {e}")),
        Ok(_) => Err("the cylinders pressed 2 cm into each other passed the check".into()),
    }
}
