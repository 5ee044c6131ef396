//! The patch test at material and unit extremes, and with every contact solver.

use crate::{answer, patch, patch_to, Block};

// ---------------------------------------------------------------- material and units extremes

#[test]
fn patch_nu_zero() {
    patch("nu0", &Block { poisson: 0.0, ..Default::default() }, &[]);
}

#[test]
fn patch_nu_0_49() {
    patch("nu049", &Block { poisson: 0.49, ..Default::default() }, &[]);
}

#[test]
fn patch_nu_0_4999_p2() {
    patch("nu04999", &Block { poisson: 0.4999, order: 2, ..Default::default() }, &[]);
}

#[test]
fn patch_plane_stress() {
    patch("plane_stress", &Block { plane: "stress", ..Default::default() }, &[]);
}

#[test]
fn patch_young_tiny() {
    // E = 1e-3 Pa with a load of 1e-9 Pa: displacements of order 1e-6 m, small strains.
    patch("young_tiny", &Block { young: 1e-3, p: 1e-9, ..Default::default() }, &[]);
}

#[test]
fn patch_young_huge() {
    patch("young_huge", &Block { young: 1e15, ..Default::default() }, &[]);
}

#[test]
fn patch_micrometres() {
    patch("micro", &Block { w: 2e-6, h: 1e-6, cell: 2.5e-7, ..Default::default() }, &[]);
}

#[test]
fn patch_kilometres() {
    patch("km", &Block { w: 2e3, h: 1e3, cell: 250.0, p: 1e9, young: 1e15, ..Default::default() }, &[]);
}

#[test]
fn patch_aspect_ratio_1000() {
    let b = Block { w: 1000.0, h: 1.0, cell: 1.0, mesher: "structured", ..Default::default() };
    // 1001 contact points on 4004 dofs: the cost model takes the sparse LU of the mixed
    // Jacobian (its MUMPS workspace margin raised: at 20 % it stopped with INFOG(1) = −9).
    patch("slender", &b, &[]);
    let (_, r) = answer("slender-route", &b.toml(), &[]);
    assert_eq!(r["contact"]["route"], "sparse_lu", "slender: {}", r["contact"]["route_reason"]);
    assert!(r["contact"]["solver"].to_string().starts_with("\"full-space"), "slender: {}", r["contact"]["solver"]);
    // The pinned stiffness of a slab 1000 long is too ill-conditioned for the floating
    // elimination's (v, λ) iteration alone (its residual 4.7e-4 on (u, λ)): the answer is
    // refined against K, and passes the independent check without iterating again.
    let dense = ["-contact_route", "dense_schur"];
    patch("slender-dense", &b, &dense);
    let (_, r) = answer("slender-notes", &b.toml(), &dense);
    let notes = r["contact"]["notes"].to_string();
    assert!(notes.contains("iterative refinement against K"), "slender: notes {notes}");
    assert!(!notes.contains("iterated again in (u, λ)"), "slender: notes {notes}");
    // Without the refinement the (v, λ) answer fails the independent check, and the run
    // iterates again in (u, λ), says so, and gives the same exact answer.
    let unrefined = ["-contact_route", "dense_schur", "-contact_full_space_refine", "false"];
    patch("slender-unrefined", &b, &unrefined);
    let (_, r) = answer("slender-unrefined-notes", &b.toml(), &unrefined);
    let notes = r["contact"]["notes"].to_string();
    assert!(notes.contains("iterated again in (u, λ)"), "slender, unrefined: notes {notes}");
}

#[test]
fn patch_p2_irregular() {
    patch("p2", &Block { order: 2, ..Default::default() }, &[]);
}

// ---------------------------------------------------------------- every contact solver

fn solver_patch(solver: &str, friction: &str) {
    let b = Block { contact: format!("{friction}\nsolver = \"{solver}\""), ..Default::default() };
    // Relaxation and Uzawa are first-order iterations stopped at their tolerance.
    let tol = if matches!(solver, "relaxation" | "uzawa") { 1e-5 } else { 1e-8 };
    patch_to(&format!("solver_{solver}"), &b, &[], tol);
}

#[test]
fn patch_solver_newton() {
    solver_patch("newton", "friction = \"coulomb\"\nmu = 0.3");
}

#[test]
fn patch_solver_relaxation() {
    solver_patch("relaxation", "friction = \"coulomb\"\nmu = 0.3");
}

#[test]
fn patch_solver_dpana() {
    solver_patch("dpana", "friction = \"coulomb\"\nmu = 0.1");
}

#[test]
fn patch_solver_uzawa() {
    solver_patch("uzawa", "friction = \"none\"");
}

#[test]
fn patch_solver_tresca_fixed_point() {
    solver_patch("tresca_fixed_point", "friction = \"coulomb\"\nmu = 0.3");
}

#[test]
fn patch_solver_tao() {
    solver_patch("tao", "friction = \"tresca\"\nthreshold = 1e5");
}

#[test]
fn patch_solver_snes_vi() {
    solver_patch("snes_vi", "friction = \"none\"");
}

#[test]
fn patch_solver_newton_full_lu() {
    patch("full_space_lu", &Block::default(), &["-contact_full_space_lu"]);
}
