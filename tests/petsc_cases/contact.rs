//! Contact validation cases (the source talk's reference cases): patch tests exact to round-off, Hertz, the square
//! block of Raous–Chabrand–Lebon, solver agreement, Newton iteration counts, robustness.

use super::edit::Edit;
use std::path::Path;

use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;
use signorini::Error;

use super::{ensure, manifest};

pub fn example(name: &str) -> (String, std::path::PathBuf) {
    let path = manifest(&format!("examples/scenes/{name}"));
    (std::fs::read_to_string(&path).unwrap(), path)
}

/// Replace one line that starts with `key` (after trimming) by `line`.
pub fn set_line(text: &str, key: &str, line: &str) -> String {
    let mut done = false;
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if !done && l.trim_start().starts_with(key) {
                done = true;
                line.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    assert!(done, "no line starting with {key}");
    out.join("\n") + "\n"
}

pub fn solve_text<'s>(s: &'s Session, text: &str, path: &Path) -> Result<ElasticityProblem<'s>, Error> {
    let scene = Scene::from_str(text, path)?;
    let mut p = ElasticityProblem::setup_system(s, scene)?;
    p.assemble()?;
    p.solve()?;
    p.postprocess()?;
    Ok(p)
}

fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt() / n
}

// ------------------------------------------------------------------ patch tests

fn patch(s: &Session, order: u32, solver: &str) -> Result<(), String> {
    let (text, path) = example("contact_patch.toml");
    let text = set_line(&text, "order", &format!("order = {order}"));
    let text = set_line(&text, "solver", &format!("solver = \"{solver}\""));
    let p = solve_text(s, &text, &path).map_err(|e| format!("P{order} {solver}: {e}"))?;
    let (e, nu, pr) = (90e9_f64, 0.2_f64, 1e6_f64);
    let k = -(1.0 + nu) * (1.0 - 2.0 * nu) * pr / (e * (1.0 - nu));
    let u = p.displacement.as_ref().unwrap();
    let scale = k.abs();
    let err = p
        .mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, x)| u[2 * i].abs().max((u[2 * i + 1] - k * x[1]).abs()))
        .fold(0.0, f64::max);
    // Exact to round-off (the docs' claim): measured at most 1.4e-13 of the slope in the
    // displacements and 7.7e-13 of p in the pressures (P2, condensed Newton).
    ensure(err <= 1e-12 * scale, || format!("P{order} {solver}: displacement error {err:e} (slope {scale:e})"))?;
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, friction) = c.boundary.tractions(&o.force);
    for (i, (pi, ti)) in pressure.iter().zip(&friction).enumerate() {
        ensure((pi - pr).abs() <= 1e-12 * pr && ti.abs() <= 1e-12 * pr, || {
            format!("P{order} {solver}: point {i}: pressure {pi}, friction {ti} (exact {pr}, 0)")
        })?;
    }
    ensure(o.report.open == 0, || format!("{} open points", o.report.open))?;
    let r = &p.results.as_ref().unwrap().report;
    ensure(r.equilibrium_residual < 1e-9, || format!("equilibrium residual {}", r.equilibrium_residual))
}

pub fn contact_patch_frictionless_exact(s: &Session) -> Result<(), String> {
    for order in [1, 2] {
        patch(s, order, "newton")?;
        patch(s, order, "snes_vi")?;
    }
    Ok(())
}

pub fn full_space_patch_frictionless_exact(s: &Session) -> Result<(), String> {
    for order in [1, 2] {
        patch(s, order, "newton_full")?;
    }
    Ok(())
}

/// The stick patch test (the frictional patch test: q ≤ μp sticks everywhere): uniform shear q on top of the compressed block, no
/// support at all in x: the body is held sideways only by friction.
fn stick_patch_text(q_over_p: f64, mu: f64, order: u32, solver: &str) -> (String, std::path::PathBuf) {
    let (e, nu, p) = (90e9_f64, 0.2_f64, 1e6_f64);
    let _ = e;
    let side = nu * p / (1.0 - nu);
    let q = q_over_p * p;
    let text = format!(
        r#"
title = "stick patch"
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
traction = [{q:e}, {mp:e}]
[[traction]]
part = "right"
traction = [{ms:e}, {q:e}]
[[traction]]
part = "left"
traction = [{side:e}, {mq:e}]
[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = {mu}
solver = "{solver}"
"#,
        mp = -p,
        ms = -side,
        mq = -q,
    );
    (text, manifest("stick_patch.toml"))
}

pub fn contact_stick_patch_exact_held_by_friction(s: &Session) -> Result<(), String> {
    stick_patch(s, "newton")
}

pub fn full_space_stick_patch_exact_held_by_friction(s: &Session) -> Result<(), String> {
    stick_patch(s, "newton_full")
}

fn stick_patch(s: &Session, solver: &str) -> Result<(), String> {
    let (e, nu, p) = (90e9_f64, 0.2_f64, 1e6_f64);
    let q = 0.3 * p;
    for order in [1, 2] {
        let (text, path) = stick_patch_text(0.3, 0.5, order, solver);
        let pr = solve_text(s, &text, &path).map_err(|e| format!("P{order}: {e}"))?;
        let u = pr.displacement.as_ref().unwrap();
        let k = -(1.0 + nu) * (1.0 - 2.0 * nu) * p / (e * (1.0 - nu));
        let kx = 2.0 * (1.0 + nu) * q / e;
        let err = pr
            .mesh
            .nodes
            .iter()
            .enumerate()
            .map(|(i, x)| (u[2 * i] - kx * x[1]).abs().max((u[2 * i + 1] - k * x[1]).abs()))
            .fold(0.0, f64::max);
        // Exact to round-off (the docs' claim): measured at most 3e-13 of the slope.
        ensure(err <= 1e-12 * k.abs(), || format!("P{order}: displacement error {err:e}"))?;
        let o = pr.contact_outcome.as_ref().unwrap();
        ensure(o.report.stick == o.report.points, || format!("P{order}: not all stick: {:?}", o.report))?;
        ensure((o.report.resultant[0] + q * 2.0).abs() < 1e-12 * q, || {
            format!("friction resultant {:?}", o.report.resultant)
        })?;
    }
    Ok(())
}

pub fn contact_stick_patch_sliding_has_no_static_solution(s: &Session) -> Result<(), String> {
    for solver in ["newton", "newton_full"] {
        let (text, path) = stick_patch_text(0.6, 0.5, 1, solver);
        match solve_text(s, &text, &path) {
            Err(Error::NoEquilibrium(m)) => ensure(m.contains("slides"), || format!("{solver}: {m}"))?,
            Err(e) => return Err(format!("{solver}: wrong error: {e}")),
            Ok(p) => {
                return Err(format!(
                    "{solver}: a sliding body got a static answer: {:?}",
                    p.contact_outcome.map(|o| o.report)
                ))
            }
        }
    }
    Ok(())
}

pub fn contact_lift_off_is_an_error(s: &Session) -> Result<(), String> {
    for solver in ["newton", "newton_full"] {
        let (text, path) = example("contact_patch.toml");
        // Pull the block up: it leaves the plane and nothing holds it.
        let text = text.replacen("pressure = 1e6", "pressure = -1e6", 1);
        let text = set_line(&text, "solver", &format!("solver = \"{solver}\""));
        match solve_text(s, &text, &path) {
            Err(Error::Unconstrained(m)) => ensure(m.contains("lifts off"), || format!("{solver}: {m}"))?,
            Err(e) => return Err(format!("{solver}: wrong error: {e}")),
            Ok(_) => return Err(format!("{solver}: a body lifting off got an answer")),
        }
    }
    Ok(())
}

// ------------------------------------------------------------------ Hertz

/// Fit p(x) = p0 sqrt(1 − x²/a²) to the closed nodes: p² is linear in x².
fn hertz_fit(p: &ElasticityProblem) -> (f64, f64, Vec<(f64, f64)>) {
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, _) = c.boundary.tractions(&o.force);
    // Open points may carry round-off pressures (1e-78 of the peak seen with OpenBLAS, exact
    // zeros with the reference BLAS): the zone is where the pressure is a real fraction of the peak.
    let peak = pressure.iter().cloned().fold(0.0, f64::max);
    let mut pts: Vec<(f64, f64)> = c
        .boundary
        .nodes
        .iter()
        .zip(&pressure)
        .filter(|(_, &pr)| pr > 1e-6 * peak)
        .map(|(&n, &pr)| (p.mesh.nodes[n][0], pr))
        .collect();
    pts.sort_by(|a, b| a.0.partial_cmp(&b.0).unwrap());
    let (a, p0) = fit_half_width_and_peak(&pts);
    (a, p0, pts)
}

/// `(a, p0)` of p(x) = p0 sqrt(1 − x²/a²) fitted to closed points `(x, p)`: least squares of
/// y = α + β x² with y = p², on the inner 80 % of the zone (the edge is where the nodal
/// resolution errs).
pub fn fit_half_width_and_peak(closed: &[(f64, f64)]) -> (f64, f64) {
    let xmax = closed.iter().map(|q| q.0.abs()).fold(0.0, f64::max);
    let inner: Vec<&(f64, f64)> = closed.iter().filter(|q| q.0.abs() <= 0.8 * xmax).collect();
    let n = inner.len() as f64;
    let (sx, sy, sxx, sxy) = inner.iter().fold((0.0, 0.0, 0.0, 0.0), |(a, b, c, d), q| {
        let (x2, y) = (q.0 * q.0, q.1 * q.1);
        (a + x2, b + y, c + x2 * x2, d + x2 * y)
    });
    let beta = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let alpha = (sy - beta * sx) / n;
    ((-alpha / beta).sqrt(), alpha.sqrt())
}

pub fn hertz_cylinder(s: &Session) -> Result<(), String> {
    hertz(s, "newton")
}

pub fn full_space_hertz_cylinder(s: &Session) -> Result<(), String> {
    hertz(s, "newton_full")
}

fn hertz(s: &Session, solver: &str) -> Result<(), String> {
    let (text, path) = example("hertz.toml");
    let text = format!("{text}solver = \"{solver}\"\n");
    let (r, e, nu) = (0.1, 210e9, 0.3);
    let load = 2.25e8 * 2.0 * r;
    let estar = e / (1.0 - nu * nu);
    let a_exact = (4.0 * load * r / (std::f64::consts::PI * estar)).sqrt();
    let p0_exact = 2.0 * load / (std::f64::consts::PI * a_exact);
    let mut errors = Vec::new();
    for (cell, fine) in [("1e-3", "1e-3"), ("5e-4", "5e-4"), ("2.5e-4", "2.5e-4")] {
        let t = set_line(
            &text,
            "refine",
            &format!("refine = {{ point = [0.0, 0.0], cell_size = {fine}, radius = 0.015 }}"),
        );
        let _ = cell;
        let p = solve_text(s, &t, &path).map_err(|e| format!("hertz {fine}: {e}"))?;
        let (a, p0, pts) = hertz_fit(&p);
        let (ea, ep) = ((a - a_exact).abs() / a_exact, (p0 - p0_exact).abs() / p0_exact);
        errors.push((fine, ea, ep));
        // P2: no checkerboard between vertex and mid-edge nodes inside the zone.
        let inner: Vec<&(f64, f64)> = pts.iter().filter(|q| q.0.abs() < 0.7 * a).collect();
        for w in inner.windows(3) {
            let wiggle = (w[1].1 - 0.5 * (w[0].1 + w[2].1)).abs() / p0_exact;
            ensure(wiggle < 0.02, || format!("hertz {fine}: pressure oscillates at x = {:.3e}: {wiggle:.3}", w[1].0))?;
        }
    }
    let (_, ea, ep) = errors[errors.len() - 1];
    ensure(ea < 0.01 && ep < 0.01, || {
        format!("Hertz: half-width and peak errors {errors:?} (a = {a_exact:e}, p0 = {p0_exact:e})")
    })?;
    // Converging under refinement: the larger of the two errors falls at every level.
    ensure(errors.windows(2).all(|w| w[1].1.max(w[1].2) < w[0].1.max(w[0].2)), || {
        format!("no convergence under refinement: {errors:?}")
    })
}

/// The Hertz half cylinder pinned at its lowest point (ux = 0 on a node of the contact part,
/// instead of the middle of its flat side): the pinned node stays a contact point and the
/// pressure matches Hertz as the unpinned one does (it was 35 % high when that node was dropped).
pub fn hertz_pinned_at_a_contact_node(s: &Session) -> Result<(), String> {
    let (text, path) = example("hertz.toml");
    let text = text.edit("point = [0.0, 0.1]       # the middle of the flat side", "point = [0.0, 0.0]");
    if !text.contains("point = [0.0, 0.0]\nux = 0.0") {
        return Err("test bug: hertz.toml's point condition was not moved".into());
    }
    let t = set_line(&text, "refine", "refine = { point = [0.0, 0.0], cell_size = 2.5e-4, radius = 0.015 }");
    let p = solve_text(s, &t, &path).map_err(|e| format!("pinned hertz: {e}"))?;
    let pinned = p.mesh.nodes.iter().position(|x| x[0] == 0.0 && x[1] == 0.0).ok_or("no node at the origin")?;
    let c = p.contact.as_ref().unwrap();
    ensure(c.boundary.nodes.contains(&pinned), || {
        format!("the pinned node {pinned} was dropped from the contact points")
    })?;
    let (r, e, nu) = (0.1, 210e9, 0.3);
    let load = 2.25e8 * 2.0 * r;
    let estar = e / (1.0 - nu * nu);
    let a_exact = (4.0 * load * r / (std::f64::consts::PI * estar)).sqrt();
    let p0_exact = 2.0 * load / (std::f64::consts::PI * a_exact);
    let (a, p0, _) = hertz_fit(&p);
    let (ea, ep) = ((a - a_exact).abs() / a_exact, (p0 - p0_exact).abs() / p0_exact);
    ensure(ea < 0.01 && ep < 0.01, || format!("pinned Hertz: half-width error {ea:.4}, peak error {ep:.4}"))
}

/// The frictionless patch test of `contact_patch.toml` turned by an angle `a` (body and
/// obstacle together), held in its tangential direction by a pin on a contact node: `ux = 0`
/// (or `uy = 0`) at a corner of the contact face. The exact field is the unrotated one turned
/// by `a`, `u = k y' ν` with `ν = (−sin a, cos a)` the obstacle's normal and `y'` the distance
/// from the contact face (the contact nodes do not move, so the pin holds only what the exact
/// field already satisfies): every pressure `p`, the contact resultant `2p ν` (no tangential
/// part) and the pin's reaction zero.
fn rotated_patch(s: &Session, angle: f64, order: u32, pin: &str, corner: f64, lu: bool) -> Result<(), String> {
    let what = format!("rotated patch {angle}°, P{order}, pin {pin} at the corner x' = {corner}, lu = {lu}");
    let a = angle.to_radians();
    let normal = [-a.sin(), a.cos()];
    let at = [corner * a.cos(), corner * a.sin()];
    let text = format!(
        r#"title = "rotated contact patch"
[[body]]
name = "block"
rotate = {angle}
[body.mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.3
mesher = "gmsh"
[body.discretization]
order = {order}
[body.material]
young = 90e9
poisson = 0.2
plane = "strain"
[[body.traction]]
part = "top"
pressure = 1e6
[[body.traction]]
part = "right"
pressure = 2.5e5
[[body.traction]]
part = "left"
pressure = 2.5e5
[[body.dirichlet]]
point = [{:?}, {:?}]
{pin} = 0.0
[body.contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [{:?}, {:?}]
friction = "none"
"#,
        at[0], at[1], normal[0], normal[1]
    );
    if lu {
        s.set_option("-contact_full_space_lu", None).unwrap();
    }
    let solved = solve_text(s, &text, &manifest("examples/scenes/rotated_patch.toml"));
    if lu {
        s.clear_option("-contact_full_space_lu").unwrap();
    }
    let p = solved.map_err(|e| format!("{what}: {e}"))?;
    let (e, nu, pr) = (90e9_f64, 0.2_f64, 1e6_f64);
    let k = -(1.0 + nu) * (1.0 - 2.0 * nu) * pr / (e * (1.0 - nu));
    let u = p.displacement.as_ref().unwrap();
    let err = p
        .mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, x)| {
            let y = normal[0] * x[0] + normal[1] * x[1];
            (u[2 * i] - k * y * normal[0]).abs().max((u[2 * i + 1] - k * y * normal[1]).abs())
        })
        .fold(0.0, f64::max);
    ensure(err <= 1e-10 * k.abs(), || format!("{what}: displacement error {err:e} (slope {:e})", k.abs()))?;
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    ensure(c.boundary.prescribed.iter().any(|q| q.is_some()), || format!("{what}: the pin is not on a contact point"))?;
    // Pointwise pressures to 1e-9: the closed rows hold n·u = g0 to round-off of u (1e-16 m
    // here, u ~ 1e-5 m), which the stiffness K_ii ~ E turns into 1e-10 of a P2 vertex's force
    // p w_i (SNES's LU of the mixed Jacobian gives the same 7e-11 at 45°); the nodal forces to
    // 1e-10 of the load.
    let total = 2.0 * pr;
    let (pressure, _) = c.boundary.tractions(&o.force);
    let worst = pressure.iter().map(|pi| (pi - pr).abs()).fold(0.0, f64::max);
    ensure(worst <= 1e-9 * pr, || format!("{what}: pressure off by {worst:e} (exact {pr})"))?;
    let force_error =
        (0..c.boundary.points()).map(|i| (o.force[2 * i] + pr * c.boundary.weight[i]).abs()).fold(0.0, f64::max);
    ensure(force_error <= 1e-10 * total, || format!("{what}: a nodal contact force off by {force_error:e}"))?;
    let r = o.report.resultant;
    let off = (r[0] - total * normal[0]).hypot(r[1] - total * normal[1]);
    ensure(off <= 1e-10 * total, || {
        format!("{what}: contact resultant {r:?}, exact {:?}", [total * normal[0], total * normal[1]])
    })?;
    let results = &p.results.as_ref().unwrap().report;
    let reaction = results.reactions.values().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
    ensure(reaction <= 1e-10 * total, || format!("{what}: pin reaction {:?}, exact 0", results.reactions))?;
    ensure(results.equilibrium_residual < 1e-12, || {
        format!("{what}: equilibrium residual {}", results.equilibrium_residual)
    })
}

/// Rotated patch tests (issue 23, 1a): angles 30°, 45°, 135°, 210° and −60°, P1 and P2, a pin
/// `ux = 0` or `uy = 0` on either corner of the contact face, the default route and SNES's LU
/// of the mixed Jacobian.
pub fn rotated_contact_patches_exact(s: &Session) -> Result<(), String> {
    for (angle, pin, corner) in
        [(45.0, "ux", 0.0), (30.0, "uy", 2.0), (135.0, "ux", 2.0), (210.0, "uy", 0.0), (-60.0, "ux", 0.0)]
    {
        for order in [1, 2] {
            rotated_patch(s, angle, order, pin, corner, false)?;
        }
    }
    rotated_patch(s, 45.0, 2, "ux", 0.0, true)?;
    rotated_patch(s, 210.0, 1, "uy", 2.0, true)
}

/// A 250 × 1 strip (P1, cells 0.5) pressed by `p` on its top face and held only by
/// frictionless contact on its bottom face, with a pin `ux = 0` at the top-left corner; with
/// `two_bodies`, the obstacle is a second strip of the same material below it, its bottom on
/// rollers (`uy = 0`) and pinned `ux = 0` at its bottom-left corner. The exact field is uniform
/// stress `σyy = −p` in each strip (`ux = ν(1 + ν) p x / E`, `uy = −(1 − ν²) p y / E` from the
/// contact face), the pressure is `p` everywhere and the pins carry nothing.
fn slender_strip<'s>(
    s: &'s Session,
    two_bodies: bool,
    refine: bool,
    route: &str,
) -> Result<ElasticityProblem<'s>, String> {
    let what = format!("250 x 1 strip, two bodies {two_bodies}, refinement {refine}, route {route}");
    let body = |name: &str, y0: f64| {
        format!(
            "[[body]]\nname = \"{name}\"\nmesh = {{ shape = \"rectangle\", origin = [0.0, {y0:?}], size = [250.0, 1.0], \
             cell_size = 0.5 }}\nmaterial = {{ young = 1e9, poisson = 0.3, plane = \"strain\" }}\n\
             discretization = {{ order = 1 }}\n"
        )
    };
    let text = if two_bodies {
        format!(
            "title = \"two-body strip\"\n{}[[body.traction]]\npart = \"top\"\npressure = 1e6\n[[body.dirichlet]]\n\
             point = [0.0, 1.0]\nux = 0.0\n{}[[body.dirichlet]]\npart = \"bottom\"\nuy = 0.0\n[[body.dirichlet]]\n\
             point = [0.0, -1.0]\nux = 0.0\n[[contact_pair]]\nslave = \"upper.bottom\"\nmaster = \"lower.top\"\n\
             friction = \"none\"\n",
            body("upper", 0.0),
            body("lower", -1.0)
        )
    } else {
        "title = \"strip\"\n[mesh]\nshape = \"rectangle\"\nsize = [250.0, 1.0]\ncell_size = 0.5\n[discretization]\n\
         order = 1\n[material]\nyoung = 1e9\npoisson = 0.3\nplane = \"strain\"\n[[traction]]\npart = \"top\"\n\
         pressure = 1e6\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n[contact]\npart = \"bottom\"\n\
         obstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\nfriction = \"none\"\n"
            .to_string()
    };
    if !refine {
        s.set_option("-contact_full_space_refine", Some("false")).unwrap();
    }
    s.set_option("-contact_route", Some(route)).unwrap();
    let solved = solve_text(s, &text, &manifest("examples/scenes/strip.toml"));
    s.clear_option("-contact_route").unwrap();
    if !refine {
        s.clear_option("-contact_full_space_refine").unwrap();
    }
    let p = solved.map_err(|e| format!("{what}: {e}"))?;
    let (e, nu, pr) = (1e9_f64, 0.3_f64, 1e6_f64);
    let (ex, ey) = (nu * (1.0 + nu) * pr / e, -(1.0 - nu * nu) * pr / e);
    let u = p.displacement.as_ref().unwrap();
    let scale = ex * 250.0;
    let err = p
        .mesh
        .nodes
        .iter()
        .enumerate()
        .map(|(i, x)| {
            // Both strips stretch from their pinned left ends; they shorten from the rigid
            // obstacle (y = 0), or from the lower strip's rollers (y = −1).
            let y = if two_bodies { x[1] + 1.0 } else { x[1] };
            (u[2 * i] - ex * x[0]).abs().max((u[2 * i + 1] - ey * y).abs())
        })
        .fold(0.0, f64::max);
    ensure(err <= 1e-10 * scale, || format!("{what}: displacement off by {err:e} (scale {scale:e})"))?;
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, _) = c.boundary.tractions(&o.force);
    let worst = pressure.iter().map(|pi| (pi - pr).abs()).fold(0.0, f64::max);
    ensure(worst <= 1e-10 * pr, || format!("{what}: contact pressure uniform to {:e} only", worst / pr))?;
    let load = 250.0 * pr;
    let results = &p.results.as_ref().unwrap().report;
    for (name, r) in &results.reactions {
        if name.starts_with("point") {
            ensure(r[0].hypot(r[1]) <= 1e-10 * load, || format!("{what}: pin {name} carries {r:?}, exact 0"))?;
        }
    }
    ensure(o.report.residuals.max_penetration <= 1e-12, || {
        format!("{what}: penetration {:e} of the displacement scale", o.report.residuals.max_penetration)
    })?;
    Ok(p)
}

/// Issue 23, 1d: a slender strip held by the contact, one body and two. The cost model's
/// route (sparse LU) is exact; the dense route (floating elimination, refined against K) gives the exact pressure to 1e-10 (3e-6 before
/// the refinement); without the refinement (`-contact_full_space_refine false`) the (v, λ)
/// answer, penetrating by 3e-8 of the displacement scale, is refused by the independent check
/// (which accepted it at 100 × the tolerance) and the run iterates again in (u, λ).
pub fn slender_strip_held_by_contact_exact(s: &Session) -> Result<(), String> {
    for two_bodies in [false, true] {
        // The cost model's route for 501 points (the sparse LU of the mixed Jacobian): exact too.
        let p = slender_strip(s, two_bodies, true, "auto")?;
        let report = &p.contact_outcome.as_ref().unwrap().report;
        ensure(report.route == "sparse_lu", || format!("two bodies {two_bodies}: route {}", report.route))?;
        let p = slender_strip(s, two_bodies, true, "dense_schur")?;
        let notes = &p.contact_outcome.as_ref().unwrap().report.notes;
        ensure(notes.iter().any(|n| n.contains("iterative refinement against K")), || {
            format!("two bodies {two_bodies}: no refinement step: {notes:?}")
        })?;
        ensure(!notes.iter().any(|n| n.contains("fails the independent check")), || {
            format!("two bodies {two_bodies}: the refined answer was refused: {notes:?}")
        })?;
        let p = slender_strip(s, two_bodies, false, "dense_schur")?;
        let notes = &p.contact_outcome.as_ref().unwrap().report.notes;
        ensure(notes.iter().any(|n| n.contains("fails the independent check")), || {
            format!("two bodies {two_bodies}: the unrefined (v, λ) answer passed the check: {notes:?}")
        })?;
    }
    Ok(())
}

// ------------------------------------------------------------------ square block

pub fn square_block_raous(s: &Session) -> Result<(), String> {
    raous(s, "newton")
}

pub fn full_space_square_block_raous(s: &Session) -> Result<(), String> {
    raous(s, "newton_full")
}

fn raous(s: &Session, solver: &str) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "solver", &format!("solver = \"{solver}\""));
    let p = solve_text(s, &text, &path).map_err(|e| e.to_string())?;
    let u = p.displacement.as_ref().unwrap();
    let reference = [(0.0, 2.86e-5), (1.25e-3, 2.72e-5), (5e-3, 2.28e-5), (7.5e-3, 1.98e-5), (11.25e-3, 1.50e-5)];
    let mut report = Vec::new();
    for (x, ux_ref) in reference {
        let node = (0..p.mesh.num_nodes())
            .find(|&n| (p.mesh.nodes[n][0] - x).abs() < 1e-9 && p.mesh.nodes[n][1].abs() < 1e-12)
            .ok_or_else(|| format!("no node at ({x}, 0)"))?;
        let ux = u[2 * node];
        report.push((x, ux, ux_ref));
        ensure((ux - ux_ref).abs() <= 0.05 * ux_ref, || {
            format!("ux({x}) = {ux:e}, reference {ux_ref:e} ±5 %; all: {report:?}")
        })?;
    }
    let o = p.contact_outcome.as_ref().unwrap();
    ensure(o.report.slip > 0 && o.report.stick > 0, || format!("expected a stick and a slip zone: {:?}", o.report))
}

// ------------------------------------------------------------------ solvers

fn small_block(friction: &str, solver: &str) -> (String, std::path::PathBuf) {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "cell_size", "cell_size = 5e-3");
    let text = set_line(&text, "solver", &format!("solver = \"{solver}\""));
    let text = match friction {
        "coulomb" => set_line(&text, "mu", "mu = 0.2"),
        "tresca" => set_line(&set_line(&text, "friction", "friction = \"tresca\""), "mu", "threshold = 1e7"),
        _ => set_line(&set_line(&text, "friction", "friction = \"none\""), "mu", ""),
    };
    (text, path)
}

pub fn contact_solvers_agree(s: &Session) -> Result<(), String> {
    let families: &[(&str, &[&str])] = &[
        ("coulomb", &["newton", "relaxation", "uzawa", "tresca_fixed_point", "dpana"]),
        ("tresca", &["newton", "relaxation", "uzawa", "dpana", "tao"]),
        ("none", &["newton", "relaxation", "uzawa", "snes_vi"]),
    ];
    for (friction, solvers) in families {
        let mut reference: Option<Vec<f64>> = None;
        for solver in *solvers {
            let (text, path) = small_block(friction, solver);
            let p = solve_text(s, &text, &path).map_err(|e| format!("{friction}/{solver}: {e}"))?;
            let u = p.displacement.clone().unwrap();
            match &reference {
                None => reference = Some(u),
                Some(r) => {
                    let d = relative_difference(r, &u);
                    ensure(d < 1e-6, || format!("{friction}: {solver} differs from newton by {d:e}"))?;
                }
            }
        }
    }
    Ok(())
}

/// The condensed semi-smooth Newton on the square block from 4 to 64 cells per side: its step
/// count is NOT mesh-independent (measured 2, 2, 4, 7, 9; the full-space Newton's are 3, 3, 4,
/// 4, 5, see below), but it grows slowly: by at most 3 per halving of the cells, never falls,
/// and stays within 10 at 64 cells per side.
pub fn condensed_newton_iterations_under_refinement(s: &Session) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "solver", "solver = \"newton\"");
    let mut its = Vec::new();
    for cell in ["1e-2", "5e-3", "2.5e-3", "1.25e-3", "6.25e-4"] {
        let t = set_line(&text, "cell_size", &format!("cell_size = {cell}"));
        let p = solve_text(s, &t, &path).map_err(|e| format!("{cell}: {e}"))?;
        its.push(p.contact_outcome.as_ref().unwrap().report.iterations);
    }
    ensure(
        its.iter().all(|&n| (1..=10).contains(&n)) && its.windows(2).all(|w| w[0] <= w[1] && w[1] <= w[0] + 3),
        || format!("condensed Newton iterations from coarse to fine: {its:?} (measured 2, 2, 4, 7, 9)"),
    )
}

/// The full-space Newton on the square block from 4 to 64 cells per side: the same narrow
/// range of Newton steps at every size, and no fallback to the condensed method.
pub fn full_space_iterations_mesh_independent(s: &Session) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "solver", "solver = \"newton_full\"");
    let mut its = Vec::new();
    for cell in ["1e-2", "5e-3", "2.5e-3", "1.25e-3", "6.25e-4"] {
        let t = set_line(&text, "cell_size", &format!("cell_size = {cell}"));
        let p = solve_text(s, &t, &path).map_err(|e| format!("{cell}: {e}"))?;
        let r = &p.contact_outcome.as_ref().unwrap().report;
        ensure(r.solver.starts_with("full-space"), || format!("{cell}: fell back: {:?}", r.notes))?;
        its.push(r.iterations);
    }
    // The issue's target: at most 10 semi-smooth Newton steps at every size (3, 3, 4, 4, 5
    // measured; 4, 5, 8, 10 from 1e3 to 1e6 dofs in `signorini bench contact`).
    ensure(its.iter().all(|&n| (1..=10).contains(&n)) && its.windows(2).all(|w| w[1] <= w[0] + 2), || {
        format!("full-space Newton steps from coarse to fine: {its:?}")
    })
}

/// The full-space and the condensed semi-smooth Newton methods give the same displacements on
/// the small square block (Coulomb, Tresca, frictionless).
pub fn full_space_agrees_with_condensed(s: &Session) -> Result<(), String> {
    for friction in ["coulomb", "tresca", "none"] {
        let mut fields = Vec::new();
        for solver in ["newton", "newton_full"] {
            let (text, path) = small_block(friction, solver);
            let p = solve_text(s, &text, &path).map_err(|e| format!("{friction}/{solver}: {e}"))?;
            let r = &p.contact_outcome.as_ref().unwrap().report;
            ensure(solver == "newton" || r.solver.starts_with("full-space"), || {
                format!("{friction}: the full-space run fell back: {:?}", r.notes)
            })?;
            fields.push(p.displacement.clone().unwrap());
        }
        let d = relative_difference(&fields[0], &fields[1]);
        ensure(d < 1e-6, || format!("{friction}: newton_full differs from newton by {d:e}"))?;
    }
    Ok(())
}

/// The block elimination (one factor of K, the default on one process) and the MUMPS LU of the
/// whole mixed Jacobian (`-contact_full_space_lu`) take the same Newton steps to the same
/// solution, for every friction law; without block elimination the report says LU.
pub fn full_space_block_elimination_matches_lu(s: &Session) -> Result<(), String> {
    for friction in ["coulomb", "tresca", "none"] {
        let (text, path) = example("square_block.toml");
        let text = set_line(&text, "cell_size", "cell_size = 2.5e-3");
        let text = match friction {
            "coulomb" => text,
            "tresca" => set_line(&text, "mu", "threshold = 2e7").edit("\"coulomb\"", "\"tresca\""),
            _ => set_line(&text, "mu", "").edit("\"coulomb\"", "\"none\""),
        };
        let mut runs = Vec::new();
        for lu in [false, true] {
            if lu {
                s.set_option("-contact_full_space_lu", None).unwrap();
            }
            let solved = solve_text(s, &text, &path);
            if lu {
                s.clear_option("-contact_full_space_lu").unwrap();
            }
            let p = solved.map_err(|e| format!("{friction}, lu = {lu}: {e}"))?;
            let r = p.contact_outcome.as_ref().unwrap().report.clone();
            ensure(r.solver.contains("block elimination") != lu, || format!("{friction}, lu = {lu}: {}", r.solver))?;
            runs.push((p.displacement.clone().unwrap(), p.contact_outcome.as_ref().unwrap().force.clone(), r));
        }
        let (a, b) = (&runs[0], &runs[1]);
        ensure(a.2.status_changes == b.2.status_changes, || {
            format!(
                "{friction}: status changes {:?} (elimination) and {:?} (LU)",
                a.2.status_changes, b.2.status_changes
            )
        })?;
        let (du, df) = (relative_difference(&a.0, &b.0), relative_difference(&a.1, &b.1));
        ensure(du < 1e-9 && df < 1e-9, || format!("{friction}: displacements differ by {du:e}, forces by {df:e}"))?;
    }
    Ok(())
}

pub fn friction_coefficient_sweep_0_to_10(s: &Session) -> Result<(), String> {
    for solver in ["newton", "newton_full"] {
        let (text, path) = example("square_block.toml");
        let text = set_line(&text, "cell_size", "cell_size = 5e-3");
        let text = set_line(&text, "solver", &format!("solver = \"{solver}\""));
        let (mut stick, mut slip) = (Vec::new(), Vec::new());
        for mu in [0.0, 0.05, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0] {
            let t = set_line(&text, "mu", &format!("mu = {mu}"));
            let p = solve_text(s, &t, &path).map_err(|e| format!("{solver}, mu = {mu}: {e}"))?;
            let o = p.contact_outcome.as_ref().unwrap();
            stick.push(o.report.stick);
            slip.push(o.report.slip);
            if mu == 0.0 {
                ensure(o.force.iter().skip(1).step_by(2).all(|&t| t == 0.0), || {
                    format!("{solver}: mu = 0 produced friction forces")
                })?;
            }
            ensure(solver == "newton" || o.report.solver.starts_with("full-space"), || {
                format!("mu = {mu}: the full-space Newton fell back: {:?}", o.report.notes)
            })?;
        }
        // Stick counts grow with μ, from none at μ = 0 to every closed point at μ = 10.
        ensure(stick.windows(2).all(|w| w[0] <= w[1]) && stick[0] == 0 && stick[7] > stick[1] && slip[7] == 0, || {
            format!("{solver}: stick counts {stick:?}, slip counts {slip:?} for mu = 0, 0.05, ..., 10")
        })?;
    }
    Ok(())
}

/// The default contact solver is the full-space Newton, and its report says what it did.
pub fn full_space_is_the_default_and_reports(s: &Session) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "solver", "");
    let p = solve_text(s, &text, &path).map_err(|e| e.to_string())?;
    let r = &p.contact_outcome.as_ref().unwrap().report;
    ensure(
        r.solver.starts_with("full-space semi-smooth Newton")
            && r.solver.contains("block elimination")
            && r.solver.to_lowercase().contains("mumps"),
        || format!("default solver: {}", r.solver),
    )?;
    ensure(r.status_changes.len() == r.iterations && r.status_changes.last() == Some(&0), || {
        format!("status changes {:?} over {} iterations", r.status_changes, r.iterations)
    })?;
    ensure(r.linear_solves == r.iterations, || format!("{} linear solves, {} steps", r.linear_solves, r.iterations))?;
    let stats = p.stats.as_ref().unwrap();
    ensure(stats.ksp_type.contains("snes newtonls") && stats.iterations == r.iterations, || format!("{stats:?}"))
}

/// A full-space run that cannot finish hands over to the condensed Newton; when that fails too,
/// the error says what both tried.
pub fn full_space_failure_falls_back_and_says_so(s: &Session) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "solver", "solver = \"newton_full\"\nmax_iterations = 3");
    match solve_text(s, &text, &path) {
        Err(Error::SolverDiverged { solver, tried, .. }) => ensure(
            solver.contains("fallback from the full-space")
                && tried.contains("first the full-space semi-smooth Newton")
                && tried.contains("DIVERGED_MAX_IT")
                && tried.contains("-contact_snes_monitor"),
            || format!("{solver} / {tried}"),
        ),
        Err(e) => Err(format!("wrong error: {e}")),
        Ok(p) => Err(format!("3 Newton steps were enough? {:?}", p.contact_outcome.map(|o| o.report))),
    }?;
    // A full-space run stopped after one step, the condensed Newton then converging: the
    // fallback's answer is the full-space one (displacements and forces to 1e-8, the same
    // stick/slip counts), and its note says what happened.
    let (text, path) = example("square_block.toml");
    let normal = solve_text(s, &text, &path).map_err(|e| format!("default: {e}"))?;
    s.set_option("-contact_snes_max_it", Some("1")).map_err(|e| e.to_string())?;
    let forced = solve_text(s, &text, &path);
    s.clear_option("-contact_snes_max_it").map_err(|e| e.to_string())?;
    let forced = forced.map_err(|e| format!("forced fallback: {e}"))?;
    let (a, b) = (normal.contact_outcome.as_ref().unwrap(), forced.contact_outcome.as_ref().unwrap());
    ensure(a.report.solver.starts_with("full-space") && !a.report.solver.contains("fallback"), || {
        a.report.solver.clone()
    })?;
    ensure(b.report.solver.contains("fallback") && b.report.notes.iter().any(|n| n.contains("fell back")), || {
        format!("{}: {:?}", b.report.solver, b.report.notes)
    })?;
    let du = relative_difference(normal.displacement.as_ref().unwrap(), forced.displacement.as_ref().unwrap());
    let df = relative_difference(&a.force, &b.force);
    ensure(du < 1e-8 && df < 1e-8, || format!("fallback differs: displacements {du:e}, forces {df:e}"))?;
    ensure((a.report.open, a.report.stick, a.report.slip) == (b.report.open, b.report.stick, b.report.slip), || {
        format!(
            "counts {:?} vs {:?}",
            (a.report.open, a.report.stick, a.report.slip),
            (b.report.open, b.report.stick, b.report.slip)
        )
    })
}

/// The default condensation on one process, W from one MUMPS factorisation with the Schur
/// complement, gives the solve-per-column answer of `-contact_condense_schur false` (square
/// block, Coulomb; Hertz small, frictionless).
pub fn condensation_by_schur_complement_agrees(s: &Session) -> Result<(), String> {
    let cases = [("square_block.toml", "1.25e-3"), ("hertz.toml", "1e-3")];
    for (name, cell) in cases {
        let (text, path) = example(name);
        let text = if name == "hertz.toml" {
            set_line(&text, "refine", &format!("refine = {{ point = [0.0, 0.0], cell_size = {cell}, radius = 0.015 }}"))
        } else {
            text
        };
        let text = if text.lines().any(|l| l.trim_start().starts_with("solver")) {
            set_line(&text, "solver", "solver = \"newton\"")
        } else {
            text.edit("[contact]\n", "[contact]\nsolver = \"newton\"\n")
        };
        s.set_option("-contact_condense_schur", Some("false")).unwrap();
        let columns = solve_text(s, &text, &path);
        s.clear_option("-contact_condense_schur").unwrap();
        let columns = columns.map_err(|e| format!("{name} (columns): {e}"))?;
        let schur = solve_text(s, &text, &path).map_err(|e| format!("{name} (Schur): {e}"))?;
        let d = relative_difference(columns.displacement.as_ref().unwrap(), schur.displacement.as_ref().unwrap());
        // Measured: 7e-15 (square block), 4e-12 (Hertz, a body held by contact: springs).
        ensure(d < 1e-10, || format!("{name}: Schur condensation differs by {d:e}"))?;
        let (by_schur, by_columns) = (schur.stats.as_ref().unwrap(), columns.stats.as_ref().unwrap());
        ensure(by_schur.factor_package.as_deref().unwrap_or("").contains("Schur"), || format!("{by_schur:?}"))?;
        ensure(!by_columns.factor_package.as_deref().unwrap_or("").contains("Schur"), || format!("{by_columns:?}"))?;
    }
    Ok(())
}

/// Bodies the Dirichlet conditions do not hold (Hertz, pinned in x only; a half disc with a
/// sheared flat side and no support at all, held sideways by Coulomb friction alone): the
/// block elimination with springs at pinned contact dofs, removed in every step (the default
/// on one process), gives the answer of the MUMPS LU of the whole mixed Jacobian.
pub fn held_by_contact_elimination_matches_lu(s: &Session) -> Result<(), String> {
    let (hertz, path) = example("hertz.toml");
    let hertz = hertz.edit("cell_size = 2.5e-4, radius = 0.015", "cell_size = 1e-3, radius = 0.015");
    let hertz = set_line(&hertz, "cell_size", "cell_size = 0.02");
    let sheared = hertz
        .edit("pressure = 2.25e8", "traction = [1.0e7, -2.25e8]")
        .edit("[[dirichlet]]\npoint = [0.0, 0.1]       # the middle of the flat side\nux = 0.0\n", "")
        .edit("friction = \"none\"", "friction = \"coulomb\"\nmu = 0.3");
    ensure(!sheared.contains("[[dirichlet]]") && sheared.contains("mu = 0.3"), || {
        "the sheared scene was not built".into()
    })?;
    for (name, text) in [("hertz", &hertz), ("sheared, coulomb", &sheared)] {
        let mut runs = Vec::new();
        for lu in [false, true] {
            if lu {
                s.set_option("-contact_full_space_lu", None).unwrap();
            }
            let solved = solve_text(s, text, &path);
            if lu {
                s.clear_option("-contact_full_space_lu").unwrap();
            }
            let p = solved.map_err(|e| format!("{name}, lu = {lu}: {e}"))?;
            let r = p.contact_outcome.as_ref().unwrap().report.clone();
            ensure(r.solver.contains("springs at pinned contact dofs") != lu, || {
                format!("{name}, lu = {lu}: {}", r.solver)
            })?;
            ensure(r.solver.starts_with("full-space"), || format!("{name}, lu = {lu}: fell back: {:?}", r.notes))?;
            runs.push((p.displacement.clone().unwrap(), p.contact_outcome.as_ref().unwrap().force.clone(), r));
        }
        let (a, b) = (&runs[0], &runs[1]);
        let (du, df) = (relative_difference(&a.0, &b.0), relative_difference(&a.1, &b.1));
        ensure(du < 1e-8 && df < 1e-8, || format!("{name}: displacements differ by {du:e}, forces by {df:e}"))?;
        ensure(a.2.iterations <= b.2.iterations + 2, || {
            format!("{name}: {} Newton steps with the elimination, {} with LU", a.2.iterations, b.2.iterations)
        })?;
    }
    Ok(())
}
