//! Friction from 0 to 100, Tresca thresholds from tiny to huge, bodies held by friction alone.

use crate::{answer, assert_same_answer, assert_uniform_pressure, counts, error, square_block};

// ---------------------------------------------------------------- friction extremes

#[test]
fn square_block_mu_zero() {
    let (_, r) = answer("sb_mu0", &square_block("friction = \"coulomb\"\nmu = 0.0"), &[]);
    assert_eq!(r["contact"]["stick"].as_u64(), Some(0));
    assert!(r["contact"]["tangential_resultant"].as_f64().unwrap().abs() < 1e-6);
}

#[test]
fn square_block_mu_0_1() {
    // μ = 0.1 cannot hold the lateral push where the block touches: every closed point slips,
    // so the tangential resultant is exactly μ times the normal one, against the motion (+x),
    // and the condensed Newton gives the same answer as the full-space one.
    let scene = square_block("friction = \"coulomb\"\nmu = 0.1");
    let (dir, r) = answer("sb_mu01", &scene, &[]);
    let [open, stick, slip] = counts(&r);
    assert!(stick == 0 && slip > 0 && open + slip == r["contact"]["points"].as_u64().unwrap(), "{}", r["contact"]);
    let (n, t) =
        (r["contact"]["normal_resultant"].as_f64().unwrap(), r["contact"]["tangential_resultant"].as_f64().unwrap());
    assert!(t < 0.0 && (t.abs() - 0.1 * n.abs()).abs() <= 1e-12 * n.abs(), "tangential {t} vs μ N = {}", 0.1 * n.abs());
    let (newton_dir, newton) = answer("sb_mu01_newton", &scene, &["--contact-solver", "newton"]);
    assert_same_answer("sb_mu01", (&dir, &r), (&newton_dir, &newton), 1e-8);
}

#[test]
fn square_block_mu_10() {
    // μ = 10: more points stick than at μ = 1 (8 stick, 21 slip); only the lightly pressed
    // points near the open zone may still slip.
    let (_, r) = answer("sb_mu10", &square_block("friction = \"coulomb\"\nmu = 10.0"), &[]);
    let (stick, slip) = (r["contact"]["stick"].as_u64().unwrap(), r["contact"]["slip"].as_u64().unwrap());
    assert!(stick > 8 && slip < stick, "μ = 10: {}", r["contact"]);
}

#[test]
fn square_block_mu_100() {
    let (_, r) = answer("sb_mu100", &square_block("friction = \"coulomb\"\nmu = 100.0"), &[]);
    let (stick, slip) = (r["contact"]["stick"].as_u64().unwrap(), r["contact"]["slip"].as_u64().unwrap());
    assert!(stick > 8 && slip < stick, "μ = 100: {}", r["contact"]);
}

#[test]
fn square_block_tresca_tiny_threshold() {
    // A threshold of 1e-3 Pa next to pressures of 1e8 Pa: every closed point slips.
    let (_, r) = answer("sb_tresca_tiny", &square_block("friction = \"tresca\"\nthreshold = 1e-3"), &[]);
    assert_eq!(r["contact"]["stick"].as_u64(), Some(0));
}

#[test]
fn square_block_tresca_huge_threshold() {
    let (_, r) = answer("sb_tresca_huge", &square_block("friction = \"tresca\"\nthreshold = 1e20"), &[]);
    assert_eq!(r["contact"]["slip"].as_u64(), Some(0));
}

// ---------------------------------------------------------------- held by friction alone

fn held_by_friction(q_over_mu_p: f64) -> String {
    // The stick patch test with no support in x at all: shear q on the top and
    // the sides, μ = 0.5, held sideways only by friction.
    let (p, mu, nu) = (1e6, 0.5, 0.2);
    let q = q_over_mu_p * mu * p;
    let l = nu * p / (1.0 - nu);
    format!(
        r#"[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.25
mesher = "gmsh"

[material]
young = 90e9
poisson = {nu}

[[traction]]
part = "top"
traction = [{q:e}, {mp:e}]

[[traction]]
part = "right"
traction = [{ml:e}, {q:e}]

[[traction]]
part = "left"
traction = [{l:e}, {mq:e}]

[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = {mu}
"#,
        mp = -p,
        ml = -l,
        mq = -q
    )
}

#[test]
fn held_by_friction_just_below_mu_p() {
    let (dir, r) = answer("friction_below", &held_by_friction(0.95), &[]);
    assert_eq!(r["contact"]["slip"].as_u64(), Some(0), "{}", r["contact"]);
    assert_uniform_pressure("friction_below", &dir, 1e6, 1e-7);
}

#[test]
fn held_by_friction_just_above_mu_p() {
    error("friction_above", &held_by_friction(1.05), &[], &["slide"]);
}
