//! Near incompressibility (ν = 0.4999): frictionless Hertz with the locking-free P2–P0 element
//! against the displacement-only P2 element, which locks.
use signorini::petsc::Session;

use super::contact::{example, set_line, solve_text};
use super::ensure;

/// Hertz measures of a run of `examples/scenes/hertz.toml` with Poisson's ratio `nu` and
/// `element`: (contact pressure at the node x = 0 relative to Hertz's p0, largest node-to-node
/// wiggle |p_i − (p_{i−1} + p_{i+1})/2| / p0 inside |x| < 0.7 a).
fn hertz_run(s: &Session, element: &str, nu: f64) -> Result<(f64, f64), String> {
    let (text, path) = example("hertz.toml");
    let text = set_line(&text, "poisson", &format!("poisson = {nu}"));
    let text = set_line(&text, "order", &format!("order = 2\nelement = \"{element}\""));
    let (r, e) = (0.1, 210e9);
    let load = 2.25e8 * 2.0 * r;
    let estar = e / (1.0 - nu * nu);
    let a = (4.0 * load * r / (std::f64::consts::PI * estar)).sqrt();
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    let p = solve_text(s, &text, &path).map_err(|e| format!("{element}: {e}"))?;
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, _) = c.boundary.tractions(&o.force);
    let mut pts: Vec<(f64, f64)> =
        c.boundary.nodes.iter().zip(&pressure).map(|(&n, &pr)| (p.mesh.nodes[n][0], pr)).collect();
    pts.sort_by(|x, y| x.0.total_cmp(&y.0));
    let centre = pts.iter().min_by(|x, y| x.0.abs().total_cmp(&y.0.abs())).unwrap();
    let peak = centre.1 / p0;
    let inner: Vec<&(f64, f64)> = pts.iter().filter(|q| q.0.abs() < 0.7 * a).collect();
    let wiggle = inner.windows(3).map(|w| (w[1].1 - 0.5 * (w[0].1 + w[2].1)).abs() / p0).fold(0.0, f64::max);
    Ok((peak, wiggle))
}

pub fn hertz_near_incompressible_p2p0_is_locking_free(s: &Session) -> Result<(), String> {
    let (peak, wiggle) = hertz_run(s, "p2p0", 0.4999)?;
    let (peak_p2, wiggle_p2) = hertz_run(s, "lagrange", 0.4999)?;
    let report =
        format!("P2-P0: p(0)/p0 = {peak:.5}, wiggle {wiggle:.4}; P2: p(0)/p0 = {peak_p2:.5}, wiggle {wiggle_p2:.4}");
    // Measured today: P2-P0 p(0)/p0 = 0.9945, wiggle 0.011; P2 0.894, wiggle 0.21 (P2 at
    // ν = 0.3 on the same mesh: 0.9994, wiggle 0.0012). The wiggle bound is that of the ν = 0.3
    // Hertz test (contact::hertz).
    ensure((peak - 1.0).abs() < 0.01, || format!("P2-P0 peak off by more than 1 %: {report}"))?;
    ensure(wiggle < 0.02, || format!("P2-P0 contact pressure not smooth: {report}"))?;
    ensure((peak_p2 - 1.0).abs() > 0.02 && wiggle_p2 > 0.05, || format!("P2 no longer locks (test premise): {report}"))
}
