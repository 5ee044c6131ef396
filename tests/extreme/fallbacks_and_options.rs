//! Solver fallbacks, the options the messages recommend, and two MPI ranks.

use crate::{answer, error, SQUARE_BLOCK};

// ---------------------------------------------------------------- fallbacks and options

#[test]
fn fallback_after_snes_iteration_limit() {
    let (_, r) = answer("fallback_max_it", SQUARE_BLOCK, &["-contact_snes_max_it", "1"]);
    let notes = r["contact"]["notes"].to_string().to_lowercase();
    assert!(
        notes.contains("fell back") && notes.contains("diverged_max_it"),
        "the failure and the fallback must be in the notes: {notes}"
    );
}

#[test]
fn fallback_after_iterative_inner_solver() {
    answer("fallback_gmres_ilu", SQUARE_BLOCK, &["-contact_ksp_type", "gmres", "-contact_pc_type", "ilu"]);
}

#[test]
fn line_search_the_messages_recommend() {
    answer("linesearch_bt", SQUARE_BLOCK, &["-contact_snes_linesearch_type", "bt"]);
}

#[test]
fn advice_after_an_iteration_limit_works() {
    // Both the full-space Newton and its condensed fallback stop at 2 steps; the error's advice
    // (more steps) must produce the answer on the same scene.
    let scene = SQUARE_BLOCK.replace("solver = \"newton_full\"", "solver = \"newton_full\"\nmax_iterations = 2");
    let msg = error("advice", &scene, &[], &["did not converge", "-contact_snes_max_it"]);
    assert!(!msg.contains("linesearch_type bt"), "{msg}");
    answer("advice_followed", &scene, &["-contact_snes_max_it", "50"]);
}

#[test]
fn mpi_two_ranks_square_block() {
    let (_, parallel) = crate::mpi::mpi_answer("mpi", SQUARE_BLOCK, &[]);
    let (_, serial) = answer("mpi_serial", SQUARE_BLOCK, &[]);
    let (a, b) = (
        serial["results"]["max_displacement"].as_f64().unwrap(),
        parallel["results"]["max_displacement"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-8 * a, "serial {a} vs 2 ranks {b}");
}
