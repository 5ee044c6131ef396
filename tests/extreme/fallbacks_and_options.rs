//! Solver fallbacks, the options the messages recommend, and two MPI ranks. Every forced
//! fallback is checked against the normal route: the same displacement field (meshio) and the
//! same open/stick/slip counts as the default run of the same scene.

use crate::edit::Edit;

use crate::{answer, assert_same_answer, counts, error, SQUARE_BLOCK};
use serde_json::Value;
use std::path::PathBuf;

/// The square block on the default route (the full-space Newton), which must not fall back.
fn reference(name: &str) -> (PathBuf, Value) {
    let (dir, r) = answer(name, SQUARE_BLOCK, &[]);
    let solver = r["contact"]["solver"].as_str().unwrap();
    assert!(solver.starts_with("full-space") && !solver.contains("fallback"), "{solver}");
    (dir, r)
}

/// A run forced onto the condensed fallback: the note names the full-space failure `reason`,
/// the solver says it is the fallback, and the answer is the default run's.
fn assert_fell_back_to_the_same_answer(name: &str, args: &[&str], reason: &str) {
    let (dir, r) = answer(name, SQUARE_BLOCK, args);
    let notes = r["contact"]["notes"].to_string();
    assert!(
        notes.contains("fell back") && notes.contains(reason),
        "{name}: the failure and the fallback must be in the notes: {notes}"
    );
    let solver = r["contact"]["solver"].as_str().unwrap();
    assert!(solver.contains("condensed") && solver.contains("fallback"), "{name}: {solver}");
    let (ref_dir, reference) = reference(&format!("{name}_reference"));
    assert_same_answer(name, (&dir, &r), (&ref_dir, &reference), 1e-8);
}

// ---------------------------------------------------------------- fallbacks and options

#[test]
fn fallback_after_snes_iteration_limit() {
    assert_fell_back_to_the_same_answer("fallback_max_it", &["-contact_snes_max_it", "1"], "DIVERGED_MAX_IT");
}

#[test]
fn fallback_after_iterative_inner_solver() {
    // GMRES + ILU does not solve the full-space Jacobian (measured: DIVERGED_LINEAR_SOLVE at
    // the first step).
    assert_fell_back_to_the_same_answer(
        "fallback_gmres_ilu",
        &["-contact_ksp_type", "gmres", "-contact_pc_type", "ilu"],
        "DIVERGED_LINEAR_SOLVE",
    );
}

#[test]
fn backtracking_line_search_falls_back_to_the_same_answer() {
    // The messages no longer recommend `-contact_snes_linesearch_type bt` (they say to leave
    // the line search at its default, see below): on the square block it stalls after one
    // step (measured: DIVERGED_LOCAL_MIN after 1 step), and the condensed Newton takes over
    // with the same answer.
    assert_fell_back_to_the_same_answer(
        "linesearch_bt",
        &["-contact_snes_linesearch_type", "bt"],
        "DIVERGED_LOCAL_MIN",
    );
}

#[test]
fn advice_after_an_iteration_limit_works() {
    // Both the full-space Newton and its condensed fallback stop at 2 steps; the error's advice
    // (more steps) must produce the answer on the same scene, on the full-space route itself.
    let scene = SQUARE_BLOCK.edit("solver = \"newton_full\"", "solver = \"newton_full\"\nmax_iterations = 2");
    assert_ne!(scene, SQUARE_BLOCK, "the square block's solver line changed: the edit missed");
    let msg = error("advice", &scene, &[], &["did not converge", "-contact_snes_max_it"]);
    assert!(!msg.contains("linesearch_type bt"), "{msg}");
    let (dir, r) = answer("advice_followed", &scene, &["-contact_snes_max_it", "50"]);
    let solver = r["contact"]["solver"].as_str().unwrap();
    assert!(
        solver.starts_with("full-space") && !solver.contains("fallback"),
        "the advice must work without the fallback: {solver}"
    );
    let (ref_dir, reference) = reference("advice_reference");
    assert_same_answer("advice_followed", (&dir, &r), (&ref_dir, &reference), 1e-8);
}

#[test]
fn mpi_two_ranks_square_block() {
    let (mpi_dir, parallel) = crate::mpi::mpi_answer("mpi", SQUARE_BLOCK, &[]);
    assert_eq!(parallel["mpi_ranks"], 2);
    let (dir, serial) = answer("mpi_serial", SQUARE_BLOCK, &[]);
    assert_same_answer("mpi_two_ranks_square_block", (&mpi_dir, &parallel), (&dir, &serial), 1e-8);
    assert!(counts(&serial)[1] > 0 && counts(&serial)[2] > 0, "stick and slip: {}", serial["contact"]);
}
