//! One body of revolution (`plane = "axisymmetric"`) against rigid obstacles: the Hertz sphere
//! and the Boussinesq flat punch against their closed forms, every contact route on one small
//! sphere, and the routes' refusals.

use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;

use super::contact::{example, fit_half_width_and_peak, set_line, solve_text};
use super::ensure;

use std::f64::consts::PI;

/// The example's sphere: E = 210 GPa, ν = 0.3, R = 0.1 m, pressure q = 1.2e7 Pa on the flat top.
const SPHERE: (f64, f64, f64, f64) = (210e9, 0.3, 0.1, 1.2e7);

/// Hertz's sphere on a rigid plane (K. L. Johnson, Contact Mechanics, Cambridge 1985, §4.2.1,
/// E* = E/(1 − ν²)): `(P, a, p0)` with `P = q π R²` (the full-revolution force),
/// `a = (3PR/(4E*))^(1/3)`, `p0 = 3P/(2πa²)`.
fn hertz_sphere(q: f64) -> (f64, f64, f64) {
    let (e, nu, r, _) = SPHERE;
    let estar = e / (1.0 - nu * nu);
    let load = q * PI * r * r;
    let a = (3.0 * load * r / (4.0 * estar)).cbrt();
    (load, a, 3.0 * load / (2.0 * PI * a * a))
}

/// `(r, p)` of the contact points whose pressure is a real fraction of the peak, by radius
/// (the axis point's pressure is `AxisPressure`'s extrapolation).
fn loaded_points(p: &ElasticityProblem) -> Vec<(f64, f64)> {
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, _) = c.boundary.tractions(&o.force);
    let peak = pressure.iter().cloned().fold(0.0, f64::max);
    let mut pts: Vec<(f64, f64)> = c
        .boundary
        .nodes
        .iter()
        .zip(&pressure)
        .filter(|(_, &pr)| pr > 1e-6 * peak)
        .map(|(&n, &pr)| (p.mesh.nodes[n][0], pr))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

fn refined_sphere(fine: f64, radius: f64) -> (String, std::path::PathBuf) {
    let (text, path) = example("hertz_sphere.toml");
    let t = set_line(
        &text,
        "refine",
        &format!("refine = {{ point = [0.0, 0.0], cell_size = {fine:e}, radius = {radius:e} }}"),
    );
    (t, path)
}

/// The Hertz sphere (examples/scenes/hertz_sphere.toml, a/R = 0.05) with cells of a/20 within
/// 3a of the pole (2.8e4 dofs): `a` and `p0` fitted to the closed points as the plane Hertz
/// test does (p² linear in r² on the inner 80 % of the zone) within 0.5 % of Hertz (measured
/// +0.08 %, −0.17 %; with cells of a/40, 1.1e5 dofs: +0.08 %, −0.17 %: what is left is the
/// hemisphere's finite size, (a/R)² = 0.25 %), the pressure profile p0 √(1 − r²/a²) within 1 %
/// RMS of p0 over the closed points (measured 0.27 %), the axis point's extrapolated pressure
/// within 0.5 % of p0 (measured −0.20 %), and the contact resultant equal to P.
pub fn axisymmetric_hertz_sphere(s: &Session) -> Result<(), String> {
    let (load, a_exact, p0_exact) = hertz_sphere(SPHERE.3);
    let (text, path) = refined_sphere(2.5e-4, 0.015);
    let p = solve_text(s, &text, &path).map_err(|e| format!("hertz sphere: {e}"))?;
    let dofs = 2 * p.mesh.num_nodes();
    ensure(dofs <= 100_000, || format!("{dofs} dofs: the test is for at most 1e5"))?;
    let pts = loaded_points(&p);
    let (a, p0) = fit_half_width_and_peak(&pts);
    let (ea, ep) = (a / a_exact - 1.0, p0 / p0_exact - 1.0);
    let rms = (pts
        .iter()
        .map(|&(r, pr)| (pr - p0_exact * (1.0 - (r / a_exact).powi(2)).max(0.0).sqrt()).powi(2))
        .sum::<f64>()
        / pts.len() as f64)
        .sqrt()
        / p0_exact;
    let axis = pts.first().filter(|q| q.0 == 0.0).ok_or("the pole is not a loaded contact point")?.1;
    let ex = axis / p0_exact - 1.0;
    println!(
        "    hertz sphere, {dofs} dofs: a {a:.5e} ({:+.3} %), p0 {p0:.5e} ({:+.3} %), RMS {:.3} % of p0, axis {:+.3} %, {} closed points",
        100.0 * ea,
        100.0 * ep,
        100.0 * rms,
        100.0 * ex,
        pts.len()
    );
    ensure(ea.abs() < 0.005 && ep.abs() < 0.005, || {
        format!("a {a:e} against {a_exact:e} ({ea:+.4}), p0 {p0:e} against {p0_exact:e} ({ep:+.4})")
    })?;
    ensure(rms < 0.01, || format!("pressure profile: RMS error {rms:.4} of p0"))?;
    ensure(ex.abs() < 0.005, || format!("axis pressure {axis:e} against p0 = {p0_exact:e} ({ex:+.4})"))?;
    let o = p.contact_outcome.as_ref().unwrap();
    let resultant = o.report.resultant[1];
    ensure((resultant - load).abs() < 1e-9 * load, || format!("contact resultant {resultant:e}, P = {load:e}"))
}

/// Boussinesq's rigid flat-ended cylindrical punch of radius a on an elastic half-space
/// (K. L. Johnson, Contact Mechanics, §3.8, eq. 3.35; Sneddon 1946): `p(r) = P / (2π a √(a² − r²))`
/// for `r < a`, `P = 2 a E* d`. The half-space is a cylinder of radius and depth 20a (E = 1
/// GPa, ν = 0.3, P2, cells a/50 within 1.2a of the punch's edge), pushed by its base (uz = d =
/// 1e-3 a) into the punch, the polyline (a, a) → (a, 0) → (−a, 0), frictionless. The
/// pressure is compared with Boussinesq's for the computed P: within 1 % for r ≤ a/2
/// (measured +0.50 % to +0.56 %), the pressure at the axis point (extrapolated) included; the
/// computed P is within 5 % of 2aE*d (measured +3.1 %: the finite cylinder with its base held
/// is stiffer than the half-space).
pub fn axisymmetric_boussinesq_flat_punch(s: &Session) -> Result<(), String> {
    let (a, e, nu, d) = (1.0_f64, 1e9_f64, 0.3_f64, 1e-3_f64);
    let text = format!(
        r#"title = "Boussinesq flat punch"
[mesh]
shape = "rectangle"
origin = [0.0, {depth}]
size = [{size}, {size}]
cell_size = {coarse}
mesher = "gmsh"
refine = {{ point = [{a}, -0.01], cell_size = {fine}, radius = {zone} }}
[discretization]
order = 2
[material]
young = {e:e}
poisson = {nu}
plane = "axisymmetric"
[[dirichlet]]
part = "bottom"
uy = {d:e}
[contact]
part = "top"
obstacle = "polyline"
points = [[{a}, {a}], [{a}, 0.0], [-{a}, 0.0]]
friction = "none"
"#,
        depth = -20.0 * a,
        size = 20.0 * a,
        coarse = 2.0 * a,
        fine = a / 50.0,
        zone = 1.2 * a,
    );
    let path = super::manifest("boussinesq_punch.toml");
    let p = solve_text(s, &text, &path).map_err(|e| format!("Boussinesq punch: {e}"))?;
    let o = p.contact_outcome.as_ref().unwrap();
    let load = o.report.resultant[1].abs();
    let boussinesq = 2.0 * a * e / (1.0 - nu * nu) * d;
    let pts = loaded_points(&p);
    let inner: Vec<&(f64, f64)> = pts.iter().filter(|q| q.0 <= 0.5 * a).collect();
    ensure(inner.len() >= 20 && inner[0].0 == 0.0, || {
        format!("{} points in r <= a/2, from r = {:e}", inner.len(), inner[0].0)
    })?;
    let worst = inner
        .iter()
        .map(|&&(r, pr)| pr / (load / (2.0 * PI * a * (a * a - r * r).sqrt())) - 1.0)
        .fold(0.0f64, |m, x| if x.abs() > m.abs() { x } else { m });
    println!(
        "    Boussinesq punch, {} dofs: P = {load:.5e} N ({:+.2} % of 2aE*d), worst pressure error for r <= a/2 {:+.3} % over {} points",
        2 * p.mesh.num_nodes(),
        100.0 * (load / boussinesq - 1.0),
        100.0 * worst,
        inner.len()
    );
    ensure(worst.abs() < 0.01, || format!("pressure for r <= a/2 off Boussinesq's by {worst:+.4}"))?;
    ensure((load / boussinesq - 1.0).abs() < 0.05, || format!("P = {load:e} against 2aE*d = {boussinesq:e}"))
}

/// The relative difference of two vectors.
fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt() / n
}

/// Every contact route on one small axisymmetric sphere (the example, cells 1e-3 m at the
/// pole): frictionless (full-space and condensed Newton, relaxation, Uzawa, D-PANA, PETSc
/// SNESVI), Tresca (those, and PETSc TAO) and Coulomb μ = 0.3 (the condensed Newton, the
/// full-space Newton, relaxation, Uzawa, D-PANA, the Tresca fixed point) give the same
/// displacements (within 1e-6, the iterative solvers' tolerance; measured below 2e-9) and
/// contact forces (measured below 3e-8), each passing its independent check.
pub fn axisymmetric_contact_routes_agree(s: &Session) -> Result<(), String> {
    let (base, path) = refined_sphere(1e-3, 0.01);
    let families: &[(&str, &str, &[&str])] = &[
        ("none", "friction = \"none\"", &["newton_full", "newton", "relaxation", "uzawa", "dpana", "snes_vi"]),
        (
            "tresca",
            "friction = \"tresca\"\nthreshold = 1e9",
            &["newton_full", "newton", "relaxation", "uzawa", "dpana", "tao"],
        ),
        (
            "coulomb",
            "friction = \"coulomb\"\nmu = 0.3",
            &["newton_full", "newton", "relaxation", "uzawa", "dpana", "tresca_fixed_point"],
        ),
    ];
    for (friction, lines, solvers) in families {
        let mut reference: Option<(Vec<f64>, Vec<f64>)> = None;
        for solver in *solvers {
            let text = set_line(&base, "friction", &format!("{lines}\nsolver = \"{solver}\""));
            let p = solve_text(s, &text, &path).map_err(|e| format!("{friction}/{solver}: {e}"))?;
            let u = p.displacement.clone().unwrap();
            let o = p.contact_outcome.as_ref().unwrap();
            let worst = o.report.residuals.worst();
            ensure(worst < 1e-6, || format!("{friction}/{solver}: independent check {worst:e}"))?;
            if *friction == "none" {
                // The pole's pressure (a P2 vertex on the axis, on a curved edge: its weight is
                // a small number of either sign) is AxisPressure's extrapolation, within 1 % of
                // p0 at cells of a/5 (measured −0.59 %; dividing by the weight gave 3.4e12 Pa).
                let (_, _, p0) = hertz_sphere(SPHERE.3);
                let pole = loaded_points(&p).first().filter(|q| q.0 == 0.0).ok_or("no pressure at the pole")?.1;
                ensure((pole / p0 - 1.0).abs() < 0.01, || format!("{solver}: pole pressure {pole:e}, p0 = {p0:e}"))?;
            }
            match &reference {
                None => reference = Some((u, o.force.clone())),
                Some((ru, rf)) => {
                    let (du, df) = (relative_difference(ru, &u), relative_difference(rf, &o.force));
                    println!("    {friction}/{solver}: differs from {} by {du:.1e} (u), {df:.1e} (r)", solvers[0]);
                    ensure(du < 1e-6 && df < 1e-6, || {
                        format!("{friction}: {solver} differs from {} by {du:e} (u), {df:e} (r)", solvers[0])
                    })?;
                }
            }
        }
    }
    Ok(())
}

/// SNESVI bounds a contact point with a prescribed component (the axis node: u_r = 0) on its
/// free Cartesian dof, its normal row `B_N = (n·d) dᵀ` (it used to refuse such a point). On a
/// cone under the pole (a "line" obstacle of normal (0.05, 1): n·d = 0.9988 at the axis node)
/// it gives the full-space Newton's answer (measured 3e-10 in u).
pub fn axisymmetric_snes_vi_on_a_cone_equals_newton_full(s: &Session) -> Result<(), String> {
    let (base, path) = refined_sphere(1e-3, 0.01);
    let tilted = set_line(&base, "normal", "normal = [0.05, 1.0]");
    let mut answers = Vec::new();
    for solver in ["newton_full", "snes_vi"] {
        let text = set_line(&tilted, "friction", &format!("friction = \"none\"\nsolver = \"{solver}\""));
        let p = solve_text(s, &text, &path).map_err(|e| format!("{solver} on the cone: {e}"))?;
        let o = p.contact_outcome.as_ref().unwrap();
        let worst = o.report.residuals.worst();
        ensure(worst < 1e-6, || format!("{solver} on the cone: independent check {worst:e}"))?;
        answers.push((p.displacement.clone().unwrap(), o.force.clone()));
    }
    let (du, df) =
        (relative_difference(&answers[0].0, &answers[1].0), relative_difference(&answers[0].1, &answers[1].1));
    println!("    cone: snes_vi differs from newton_full by {du:.1e} (u), {df:.1e} (r)");
    ensure(du < 1e-6 && df < 1e-6, || format!("cone: snes_vi differs from newton_full by {du:e} (u), {df:e} (r)"))
}
