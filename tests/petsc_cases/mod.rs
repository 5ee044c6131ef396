//! The cases of the PETSc suite (see tests/petsc_suite.rs). Each takes the one session.
#[path = "../common/edit.rs"]
mod edit;
use edit::Edit;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use signorini::fem::assembly::{self, Constraints, EdgeLoad, Loads, Traction};
use signorini::fem::material::{Material, PlaneModel};
use signorini::fem::postprocess;
use signorini::mesh::{gmsh, structured, Mesh, Order};
use signorini::petsc::{LinearSolver, Matrix, Session, SolveStats};
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;
use signorini::Error;

mod adapt;
mod axisymmetric_bodies;
mod axisymmetric_contact;
mod bodies_blocks;
mod bodies_full_space;
mod bodies_hertz;
mod bodies_sides;
mod contact;
mod contact_routes;
mod dual;
mod dual_contact;
mod dual_implicit;
mod evolution;
mod export;
mod ict;
mod interface;
mod interface_joint;
mod interface_outputs;
mod interface_rccm;
mod locking;
mod mpi_callbacks;
mod progress;
mod runner;
mod thin_layer;

type Case = fn(&Session) -> Result<(), String>;

pub const TESTS: &[(&str, Case)] = &[
    ("runner_parses_libtest_options", runner::runner_parses_libtest_options),
    ("thin_layer_bonded_patch", interface::thin_layer_bonded_patch),
    ("thin_layer_cut_in_compression_equals_bonded", interface::thin_layer_cut_in_compression_equals_bonded),
    ("thin_layer_stiff_limit_is_signorini", interface::thin_layer_stiff_limit_is_signorini),
    ("thin_layer_glues_two_bodies", interface::thin_layer_glues_two_bodies),
    ("thin_layer_load_path", interface::thin_layer_load_path),
    ("interface_law_refusals", interface::interface_law_refusals),
    ("thin_layer_on_one_pair_of_three_bodies", interface::thin_layer_on_one_pair_of_three_bodies),
    ("rccm_glues_two_bodies_until_they_pull_off", interface::rccm_glues_two_bodies_until_they_pull_off),
    ("load_path_proportional_equals_static", evolution::load_path_proportional_equals_static),
    ("mindlin_deresiewicz_fretting_cycle", evolution::mindlin_deresiewicz_fretting_cycle),
    ("stick_patch_exact_at_every_increment", evolution::stick_patch_exact_at_every_increment),
    ("estimate_at_every_increment", evolution::estimate_at_every_increment),
    ("load_path_halves_failed_increments", evolution::load_path_halves_failed_increments),
    ("square_block_path_dependence", evolution::square_block_path_dependence),
    ("masonry_joint_shear_patch", interface_joint::masonry_joint_shear_patch),
    ("cohesive_joint_tension_softening_curve", interface_joint::cohesive_joint_tension_softening_curve),
    ("cohesive_joint_without_cohesion_is_coulomb", interface_joint::cohesive_joint_without_cohesion_is_coulomb),
    ("rccm_pull_off_closed_form", interface_rccm::rccm_pull_off_closed_form),
    ("rccm_published_peak_and_separation_energy", interface_rccm::rccm_published_peak_and_separation_energy),
    ("rccm_without_adhesion_is_signorini_coulomb", interface_rccm::rccm_without_adhesion_is_signorini_coulomb),
    ("rccm_adhesive_shear_debonds_then_slides", interface_rccm::rccm_adhesive_shear_debonds_then_slides),
    ("interface_files_of_a_static_run", interface_outputs::interface_files_of_a_static_run),
    ("interface_files_of_a_load_path", interface_outputs::interface_files_of_a_load_path),
    ("second_session_is_refused", second_session_is_refused),
    ("matrix_checks_csr_input", matrix_checks_csr_input),
    ("vector_checks_lengths", vector_checks_lengths),
    ("petsc_error_carries_petsc_message", petsc_error_carries_petsc_message),
    ("missing_petsc_option_value_is_an_error", missing_petsc_option_value_is_an_error),
    ("krylov_divergence_is_reported", krylov_divergence_is_reported),
    ("residual_check_rejects_preonly_with_incomplete_factorisation", residual_check_rejects_preonly_icc),
    ("patch_test_p1_driver_exact", patch_test_p1_driver_exact),
    ("patch_test_p2_driver_exact", patch_test_p2_driver_exact),
    ("manufactured_p1_structured_rates", manufactured_p1_structured_rates),
    ("manufactured_p2_structured_rates", manufactured_p2_structured_rates),
    ("manufactured_p1_gmsh_rates", manufactured_p1_gmsh_rates),
    ("manufactured_p2_gmsh_rates", manufactured_p2_gmsh_rates),
    ("solvers_agree_mumps_icc_hypre_symmlq", solvers_agree),
    ("driver_reports_unconstrained_rigid_motion", driver_reports_unconstrained_rigid_motion),
    ("driver_reports_unknown_boundary_part_with_line", driver_reports_unknown_boundary_part),
    ("driver_elastic_block_equilibrium", driver_default_scene_equilibrium),
    ("driver_pipeline_out_of_order_is_a_call_order_error", driver_pipeline_out_of_order),
    ("mumps_schur_complement_is_the_inverse_block", mumps_schur_complement_is_the_inverse_block),
    ("mumps_selected_inverse_is_the_inverse_block", mumps_selected_inverse_is_the_inverse_block),
    ("dense_lu_solves_and_reports_zero_pivots", dense_lu_solves_and_reports_zero_pivots),
    ("dual_patch_test_all_tractions_exact", dual::dual_patch_test_all_tractions_exact),
    ("dual_contact_patch_tests_exact", dual_contact::dual_contact_patch_tests_exact),
    ("dual_contact_patch_on_a_wall", dual_contact::dual_contact_patch_on_a_wall),
    ("dual_contact_local_fallback_agrees", dual_contact::dual_contact_local_fallback_agrees),
    ("dual_contact_independent_of_young_modulus", dual_contact::dual_contact_independent_of_young_modulus),
    ("estimate_accepts_round_off_point_reactions", dual_contact::estimate_accepts_round_off_point_reactions),
    (
        "dual_contact_patch_refined_and_graded_keeps_its_digits",
        dual_contact::dual_contact_patch_refined_and_graded_keeps_its_digits,
    ),
    ("dual_contact_sliding_has_no_static_solution", dual_contact::dual_contact_sliding_has_no_static_solution),
    ("dual_square_block_raous", dual_contact::dual_square_block_raous),
    ("dual_contact_condensations_agree", dual_contact::dual_contact_condensations_agree),
    ("dual_contact_implicit_storage_agrees", dual_implicit::dual_contact_implicit_storage_agrees),
    ("dual_contact_storage_usage_errors", dual_implicit::dual_contact_storage_usage_errors),
    ("dual_contact_estimate_tresca_and_coulomb", dual_contact::dual_contact_estimate_tresca_and_coulomb),
    ("dual_hertz_cylinder", dual_contact::dual_hertz_cylinder),
    ("dual_contact_effectivity_tresca", dual_contact::dual_contact_effectivity_tresca),
    ("dual_stick_patch_and_roller_support_exact", dual::dual_stick_patch_and_roller_support_exact),
    ("dual_cubic_airy_and_body_force_exact", dual::dual_cubic_airy_and_body_force_exact),
    ("dual_refuses_unbalanced_loads_and_holes", dual::dual_refuses_unbalanced_loads_and_holes),
    ("dual_cantilever_rates", dual::dual_cantilever_rates),
    ("dual_does_not_lock", dual::dual_does_not_lock),
    ("dual_prager_synge_identity_manufactured", dual::dual_prager_synge_identity_manufactured),
    ("dual_saddle_point_agrees_with_elimination", dual::dual_saddle_point_agrees_with_elimination),
    ("contact_patch_frictionless_exact", contact::contact_patch_frictionless_exact),
    ("hertz_pinned_at_a_contact_node", contact::hertz_pinned_at_a_contact_node),
    ("rotated_contact_patches_exact", contact::rotated_contact_patches_exact),
    ("slender_strip_held_by_contact_exact", contact::slender_strip_held_by_contact_exact),
    ("condensation_by_schur_complement_agrees", contact::condensation_by_schur_complement_agrees),
    ("contact_stick_patch_exact_held_by_friction", contact::contact_stick_patch_exact_held_by_friction),
    ("contact_stick_patch_sliding_has_no_static_solution", contact::contact_stick_patch_sliding_has_no_static_solution),
    ("contact_lift_off_is_an_error", contact::contact_lift_off_is_an_error),
    ("hertz_cylinder", contact::hertz_cylinder),
    ("axisymmetric_hertz_sphere", axisymmetric_contact::axisymmetric_hertz_sphere),
    ("axisymmetric_boussinesq_flat_punch", axisymmetric_contact::axisymmetric_boussinesq_flat_punch),
    ("axisymmetric_contact_routes_agree", axisymmetric_contact::axisymmetric_contact_routes_agree),
    (
        "axisymmetric_snes_vi_on_a_cone_equals_newton_full",
        axisymmetric_contact::axisymmetric_snes_vi_on_a_cone_equals_newton_full,
    ),
    ("square_block_raous", contact::square_block_raous),
    ("contact_solvers_agree", contact::contact_solvers_agree),
    ("condensed_newton_iterations_under_refinement", contact::condensed_newton_iterations_under_refinement),
    ("friction_coefficient_sweep_0_to_10", contact::friction_coefficient_sweep_0_to_10),
    ("full_space_patch_frictionless_exact", contact::full_space_patch_frictionless_exact),
    ("full_space_stick_patch_exact_held_by_friction", contact::full_space_stick_patch_exact_held_by_friction),
    ("full_space_agrees_with_condensed", contact::full_space_agrees_with_condensed),
    ("full_space_block_elimination_matches_lu", contact::full_space_block_elimination_matches_lu),
    ("contact_routes_agree", contact_routes::contact_routes_agree),
    ("contact_route_out_of_memory_is_named", contact_routes::contact_route_out_of_memory_is_named),
    ("held_by_contact_elimination_matches_lu", contact::held_by_contact_elimination_matches_lu),
    ("full_space_square_block_raous", contact::full_space_square_block_raous),
    ("full_space_iterations_mesh_independent", contact::full_space_iterations_mesh_independent),
    ("full_space_hertz_cylinder", contact::full_space_hertz_cylinder),
    ("progress_events_in_order", progress::progress_events_in_order),
    ("full_space_is_the_default_and_reports", contact::full_space_is_the_default_and_reports),
    ("full_space_failure_falls_back_and_says_so", contact::full_space_failure_falls_back_and_says_so),
    ("nonlinear_solver_newton_and_callback_errors", nonlinear_solver_newton_and_callback_errors),
    ("nonlinear_callback_error_on_one_rank", mpi_callbacks::nonlinear_callback_error_on_one_rank),
    ("setup_error_on_one_rank", mpi_callbacks::setup_error_on_one_rank),
    ("mesh_from_rank_0_on_two_ranks", mpi_callbacks::mesh_from_rank_0_on_two_ranks),
    ("adapt_coarsens_where_the_error_is_small", adapt::adapt_coarsens_where_the_error_is_small),
    ("adapt_error_decreases_at_corner_singularities", adapt::adapt_error_decreases_at_corner_singularities),
    ("adapt_target_not_reached_is_reported", adapt::adapt_target_not_reached_is_reported),
    ("study_p1_rate_is_one_on_a_smooth_problem", adapt::study_p1_rate_is_one_on_a_smooth_problem),
    ("adapt_and_study_refuse_mesh_files", adapt::adapt_and_study_refuse_mesh_files),
    ("adapt_error_decreases_on_the_flat_punch", adapt::adapt_error_decreases_on_the_flat_punch),
    ("adapt_keeps_curved_boundaries_exact", adapt::adapt_keeps_curved_boundaries_exact),
    ("adapt_remeshes_a_mesh_file_from_its_geometry_script", adapt::adapt_remeshes_a_mesh_file_from_its_geometry_script),
    ("hertz_near_incompressible_p2p0_is_locking_free", locking::hertz_near_incompressible_p2p0_is_locking_free),
    ("contact_patch_near_incompressible_p2p0_exact", locking::contact_patch_near_incompressible_p2p0_exact),
    ("fclib_export_square_block_reads_back", export::fclib_export_square_block_reads_back),
    ("fclib_export_refuses_what_it_cannot_hold", export::fclib_export_refuses_what_it_cannot_hold),
    ("pc_ict_cg_solves_the_cantilever", ict::ict_cg_solves_the_cantilever),
    ("pc_ict_tiny_tolerance_is_a_direct_solve", ict::ict_tiny_tolerance_is_a_direct_solve),
    ("pc_ict_needs_fewer_iterations_than_icc0", ict::ict_needs_fewer_iterations_than_icc0),
    ("pc_ict_bad_options_and_matrices_are_typed_errors", ict::ict_bad_options_and_matrices_are_typed_errors),
    ("axisymmetric_shrink_fit_hollow_cylinders", axisymmetric_bodies::shrink_fit_hollow_cylinders),
    (
        "axisymmetric_pellet_cladding_example_is_a_shrink_fit",
        axisymmetric_bodies::pellet_cladding_example_is_a_shrink_fit,
    ),
    ("axisymmetric_hertz_two_spheres", axisymmetric_bodies::hertz_two_spheres),
    ("hertz_two_cylinders", bodies_hertz::hertz_two_cylinders),
    ("hertz_two_cylinders_steel_on_aluminium", bodies_hertz::hertz_two_cylinders_steel_on_aluminium),
    ("cattaneo_mindlin_two_cylinders", bodies_hertz::cattaneo_mindlin_two_cylinders),
    (
        "cattaneo_mindlin_two_cylinders_near_incompressible",
        bodies_hertz::cattaneo_mindlin_two_cylinders_near_incompressible,
    ),
    (
        "two_bodies_report_equilibrium_and_action_reaction",
        bodies_hertz::two_bodies_report_equilibrium_and_action_reaction,
    ),
    (
        "two_cylinders_beyond_small_sliding_fail_the_check",
        bodies_hertz::two_cylinders_beyond_small_sliding_fail_the_check,
    ),
    ("two_body_patch_nonmatching_p1", bodies_blocks::two_body_patch_nonmatching_p1),
    ("two_body_patch_nonmatching_p2", bodies_blocks::two_body_patch_nonmatching_p2),
    ("square_block_on_stiff_foundation", bodies_blocks::square_block_on_stiff_foundation),
    ("three_block_stack", bodies_blocks::three_block_stack),
    ("thin_layer_against_meshed_layer", thin_layer::thin_layer_against_meshed_layer),
    ("thin_layer_cut_against_meshed_layer_lifting_off", thin_layer::thin_layer_cut_against_meshed_layer_lifting_off),
    ("bodies_errors_name_what_is_wrong", bodies_blocks::bodies_errors_name_what_is_wrong),
    ("point_condition_at_a_shared_place_is_its_bodys", bodies_blocks::point_condition_at_a_shared_place_is_its_bodys),
    ("which_side_is_slave_decides_the_pointwise_check", bodies_sides::which_side_is_slave_decides_the_pointwise_check),
    (
        "bodies_out_of_pairing_range_solve_without_contact_force",
        bodies_sides::bodies_out_of_pairing_range_solve_without_contact_force,
    ),
    ("bodies_full_space_patch_test", bodies_full_space::bodies_full_space_patch_test),
    ("bodies_full_space_block_on_block", bodies_full_space::bodies_full_space_block_on_block),
    ("bodies_full_space_block_elimination", bodies_full_space::bodies_full_space_block_elimination),
];

pub(crate) fn ensure(cond: bool, msg: impl FnOnce() -> String) -> Result<(), String> {
    if cond {
        Ok(())
    } else {
        Err(msg())
    }
}

pub(crate) fn manifest(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// Solve a constrained elasticity system with the KSP configured under `prefix`.
fn solve(
    session: &Session,
    mesh: &Mesh,
    material: &Material,
    constraints: &Constraints,
    loads: &Loads,
    prefix: &str,
) -> Result<(Vec<f64>, SolveStats), Error> {
    let n = 2 * mesh.num_nodes();
    let system = assembly::assemble(mesh, material, constraints, loads, 0..n);
    let m = &system.matrix;
    let a = Matrix::from_csr_rows(session, session.world(), n, 0, &m.indptr, &m.indices, &m.values, 2, true)?;
    let mut b = a.create_vector()?;
    b.set_owned(&system.rhs)?;
    let mut x = a.create_vector()?;
    let mut ksp = LinearSolver::new(session, session.world(), prefix)?;
    ksp.set_operator(&a)?;
    let stats = ksp.solve(&a, &b, &mut x)?;
    Ok((x.owned_values()?, stats))
}

fn set_options(session: &Session, prefix: &str, options: &[(&str, Option<&str>)]) {
    for (k, v) in options {
        session.set_option(&format!("-{prefix}{k}"), *v).unwrap();
    }
}

fn steel() -> Material {
    Material::new(210e9, 0.3, PlaneModel::Strain)
}

fn clamped_cantilever(order: Order) -> (Mesh, Constraints) {
    let mesh = structured::rectangle([0.0, 0.0], [4.0, 1.0], 24, 6, order).unwrap();
    let mut c = Constraints::new(2 * mesh.num_nodes());
    let left = mesh.require_group("left", 1).unwrap();
    c.fix_group(&mesh, left, 0, |_| 0.0);
    c.fix_group(&mesh, left, 1, |_| 0.0);
    (mesh, c)
}

// ---------------------------------------------------------------- PETSc layer

fn second_session_is_refused(_s: &Session) -> Result<(), String> {
    match Session::init(&["again".to_string()]) {
        Err(Error::PetscUsage(m)) => ensure(m.contains("already alive"), || format!("message: {m}")),
        Err(e) => Err(format!("wrong error: {e}")),
        Ok(_) => Err("a second session was created".into()),
    }
}

fn matrix_checks_csr_input(s: &Session) -> Result<(), String> {
    let w = s.world();
    let cases: Vec<(&str, Vec<usize>, Vec<usize>, Vec<f64>)> = vec![
        ("out of range", vec![0, 1, 2], vec![0, 7], vec![1.0, 1.0]),
        ("not strictly increasing", vec![0, 2, 3], vec![1, 0, 1], vec![1.0, 1.0, 1.0]),
        ("disagree", vec![0, 1, 3], vec![0, 1], vec![1.0, 1.0]),
    ];
    for (what, indptr, indices, values) in cases {
        match Matrix::from_csr_rows(s, w, 2, 0, &indptr, &indices, &values, 1, false) {
            Err(Error::PetscUsage(m)) => ensure(m.contains(what), || format!("expected '{what}' in: {m}"))?,
            Err(e) => return Err(format!("{what}: wrong error {e}")),
            Ok(_) => return Err(format!("{what}: accepted")),
        }
    }
    match Matrix::from_csr_rows(s, w, 3, 0, &[0, 1, 2, 3], &[0, 1, 2], &[1.0; 3], 2, false) {
        Err(Error::PetscUsage(m)) => ensure(m.contains("block size"), || m.clone()),
        other => Err(format!("misaligned block accepted or wrong error: {:?}", other.err())),
    }
}

fn vector_checks_lengths(s: &Session) -> Result<(), String> {
    let a = Matrix::from_csr_rows(s, s.world(), 2, 0, &[0, 1, 2], &[0, 1], &[2.0, 4.0], 2, true)
        .map_err(|e| e.to_string())?;
    let mut v = a.create_vector().map_err(|e| e.to_string())?;
    match v.set_owned(&[1.0, 2.0, 3.0]) {
        Err(Error::PetscUsage(m)) => ensure(m.contains("3 values"), || m.clone())?,
        other => return Err(format!("wrong length accepted: {:?}", other.err())),
    }
    v.set_owned(&[1.0, 2.0]).map_err(|e| e.to_string())?;
    ensure(v.gather_all().map_err(|e| e.to_string())? == vec![1.0, 2.0], || "gather".into())
}

fn petsc_error_carries_petsc_message(s: &Session) -> Result<(), String> {
    let (mesh, c) = clamped_cantilever(Order::P1);
    set_options(s, "bad_", &[("ksp_type", Some("no_such_krylov"))]);
    match solve(s, &mesh, &steel(), &c, &Loads::default(), "bad_") {
        Err(Error::Petsc { code, message, call, .. }) => {
            ensure(code != 0 && message.contains("no_such_krylov"), || {
                format!("code {code} call {call} message {message}")
            })
        }
        other => Err(format!("expected a PETSc error, got {:?}", other.map(|_| ()))),
    }
}

fn missing_petsc_option_value_is_an_error(s: &Session) -> Result<(), String> {
    let (mesh, c) = clamped_cantilever(Order::P1);
    // PETSc itself ignores a value-less integer option: the session refuses it (scene options
    // go through the same check as the command line).
    let tokens: Vec<String> =
        ["-miss_ksp_type", "cg", "-miss_pc_factor_levels"].iter().map(|t| t.to_string()).collect();
    match s.insert_default_options(&tokens) {
        Err(Error::PetscOption { option, message }) => {
            ensure(option == "-miss_pc_factor_levels" && message.contains("needs a value"), || {
                format!("{option}: {message}")
            })?
        }
        other => return Err(format!("expected a PetscOption error, got {other:?}")),
    }
    ensure(!s.has_option("-miss_ksp_type").unwrap(), || "options were half-inserted".into())?;
    let _ = (mesh, c);
    Ok(())
}

fn krylov_divergence_is_reported(s: &Session) -> Result<(), String> {
    let (mesh, c) = clamped_cantilever(Order::P1);
    set_options(s, "div_", &[("ksp_type", Some("cg")), ("pc_type", Some("none")), ("ksp_max_it", Some("3"))]);
    let right = mesh.require_group("right", 1).unwrap();
    let loads = Loads {
        body_force: None,
        edge_loads: vec![EdgeLoad { group: right, traction: Traction::Constant([0.0, -1e6]) }],
    };
    match solve(s, &mesh, &steel(), &c, &loads, "div_") {
        Err(Error::SolverDiverged { reason, iterations, tried, .. }) => {
            ensure(reason.contains("DIVERGED_ITS") && iterations == 3 && !tried.is_empty(), || {
                format!("{reason} {iterations} {tried}")
            })
        }
        other => Err(format!("expected SolverDiverged, got {:?}", other.map(|_| ()))),
    }
}

fn residual_check_rejects_preonly_icc(s: &Session) -> Result<(), String> {
    let (mesh, c) = clamped_cantilever(Order::P1);
    set_options(s, "pre_", &[("ksp_type", Some("preonly")), ("pc_type", Some("icc"))]);
    let right = mesh.require_group("right", 1).unwrap();
    let loads = Loads {
        body_force: None,
        edge_loads: vec![EdgeLoad { group: right, traction: Traction::Constant([0.0, -1e6]) }],
    };
    match solve(s, &mesh, &steel(), &c, &loads, "pre_") {
        Err(Error::SolverDiverged { reason, .. }) => {
            ensure(reason.contains("true relative residual"), || format!("reason: {reason}"))
        }
        other => Err(format!("a wrong answer was accepted: {:?}", other.map(|(_, s)| s))),
    }
}

// ---------------------------------------------------------------- patch tests (driver)

fn patch_test(s: &Session, order: u32) -> Result<(), String> {
    let path = manifest("examples/scenes/patch_test.toml");
    let text = std::fs::read_to_string(&path).map_err(|e| e.to_string())?;
    let text = text.edit("order = 1", &format!("order = {order}"));
    let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let (e, nu) = (scene.material.young, scene.material.poisson);
    let p = match scene.tractions.iter().find(|t| t.part == "top").map(|t| &t.load) {
        Some(signorini::scene::Load::Pressure(p)) => *p,
        _ => return Err("patch_test.toml: no top pressure".into()),
    };
    let mut problem = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    problem.assemble().map_err(|e| e.to_string())?;
    problem.solve().map_err(|e| e.to_string())?;
    problem.postprocess().map_err(|e| e.to_string())?;
    let u = problem.displacement.as_ref().unwrap();
    let k = -(1.0 + nu) * (1.0 - 2.0 * nu) * p / (e * (1.0 - nu));
    let scale = problem.mesh.nodes.iter().map(|x| (k * x[1]).abs()).fold(0.0, f64::max);
    let mut err = 0.0f64;
    for (i, x) in problem.mesh.nodes.iter().enumerate() {
        err = err.max(u[2 * i].abs()).max((u[2 * i + 1] - k * x[1]).abs());
    }
    ensure(err <= 1e-12 * scale, || format!("P{order} patch: max displacement error {err:e} (scale {scale:e})"))?;
    let sxx = -nu * p / (1.0 - nu);
    let results = problem.results.as_ref().unwrap();
    for s in &results.nodal_stress {
        let d = (s[0] - sxx).abs().max((s[1] + p).abs()).max(s[2].abs());
        ensure(d <= 1e-9 * p, || format!("P{order} patch: stress {s:?} vs ({sxx}, {}, 0)", -p))?;
    }
    ensure(results.report.equilibrium_residual < 1e-10, || {
        format!("equilibrium residual {}", results.report.equilibrium_residual)
    })
}

fn patch_test_p1_driver_exact(s: &Session) -> Result<(), String> {
    patch_test(s, 1)
}
fn patch_test_p2_driver_exact(s: &Session) -> Result<(), String> {
    patch_test(s, 2)
}

// ---------------------------------------------------------------- manufactured solutions

/// u = (s, s), s = sin πx sin πy on the unit square, u = 0 on the boundary; body force
/// F = −div σ(u) = π² (2μ s − (λ+μ)(cos πx cos πy − s)) (1, 1).
fn manufactured_errors(s: &Session, mesh: &Mesh, prefix: &str) -> Result<(f64, f64), String> {
    let material = steel();
    let (lambda, mu) = material.lame();
    let body = move |x: [f64; 2]| {
        let sv = (PI * x[0]).sin() * (PI * x[1]).sin();
        let cc = (PI * x[0]).cos() * (PI * x[1]).cos();
        let f = PI * PI * (2.0 * mu * sv - (lambda + mu) * (cc - sv));
        [f, f]
    };
    let mut c = Constraints::new(2 * mesh.num_nodes());
    for side in ["bottom", "right", "top", "left"] {
        let g = mesh.require_group(side, 1).map_err(|e| e.to_string())?;
        c.fix_group(mesh, g, 0, |_| 0.0);
        c.fix_group(mesh, g, 1, |_| 0.0);
    }
    let loads = Loads { body_force: Some(&body), edge_loads: vec![] };
    let (u, _) = solve(s, mesh, &material, &c, &loads, prefix).map_err(|e| e.to_string())?;
    let exact = |x: [f64; 2]| {
        let sv = (PI * x[0]).sin() * (PI * x[1]).sin();
        [sv, sv]
    };
    let grad = |x: [f64; 2]| {
        let dx = PI * (PI * x[0]).cos() * (PI * x[1]).sin();
        let dy = PI * (PI * x[0]).sin() * (PI * x[1]).cos();
        [[dx, dy], [dx, dy]]
    };
    Ok((postprocess::energy_error(mesh, &material, &u, grad), postprocess::l2_error(mesh, &u, exact)))
}

fn rates(hs: &[f64], errs: &[f64]) -> Vec<f64> {
    (1..hs.len()).map(|k| (errs[k - 1] / errs[k]).ln() / (hs[k - 1] / hs[k]).ln()).collect()
}

fn check_rates(label: &str, meshes: Vec<Mesh>, energy_min: f64, l2_min: f64, s: &Session) -> Result<(), String> {
    let (mut hs, mut ee, mut el) = (vec![], vec![], vec![]);
    for m in &meshes {
        let (e, l) = manufactured_errors(s, m, "")?;
        hs.push((1.0 / m.num_cells() as f64).sqrt());
        ee.push(e);
        el.push(l);
    }
    let (re, rl) = (rates(&hs, &ee), rates(&hs, &el));
    let last = re.len() - 1;
    ensure(re[last] >= energy_min && rl[last] >= l2_min, || {
        format!("{label}: energy rates {re:?} (need ≥ {energy_min}), L2 rates {rl:?} (need ≥ {l2_min})")
    })
}

fn manufactured_p1_structured_rates(s: &Session) -> Result<(), String> {
    let meshes =
        [8, 16, 32, 64].iter().map(|&n| structured::rectangle([0.0; 2], [1.0; 2], n, n, Order::P1).unwrap()).collect();
    check_rates("P1 structured", meshes, 0.95, 1.9, s)
}

fn manufactured_p2_structured_rates(s: &Session) -> Result<(), String> {
    let meshes =
        [4, 8, 16, 32].iter().map(|&n| structured::rectangle([0.0; 2], [1.0; 2], n, n, Order::P2).unwrap()).collect();
    check_rates("P2 structured", meshes, 1.9, 2.8, s)
}

fn gmsh_square(h: f64, order: Order) -> Mesh {
    gmsh::generate(&gmsh::MeshRequest {
        shape: gmsh::Shape::Rectangle { origin: [0.0, 0.0], size: [1.0, 1.0] },
        cell_size: h,
        refinement: None,
        order,
    })
    .unwrap()
}

fn manufactured_p1_gmsh_rates(s: &Session) -> Result<(), String> {
    let meshes = [0.2, 0.1, 0.05, 0.025].iter().map(|&h| gmsh_square(h, Order::P1)).collect();
    check_rates("P1 gmsh", meshes, 0.9, 1.8, s)
}

fn manufactured_p2_gmsh_rates(s: &Session) -> Result<(), String> {
    let meshes = [0.25, 0.125, 0.0625, 0.03125].iter().map(|&h| gmsh_square(h, Order::P2)).collect();
    check_rates("P2 gmsh", meshes, 1.8, 2.7, s)
}

// ---------------------------------------------------------------- solver agreement

fn solvers_agree(s: &Session) -> Result<(), String> {
    let solvers: &[(&str, &[(&str, Option<&str>)])] = &[
        ("ag_mumps_", &[]),
        ("ag_icc0_", &[("ksp_type", Some("cg")), ("pc_type", Some("icc"))]),
        ("ag_icc2_", &[("ksp_type", Some("cg")), ("pc_type", Some("icc")), ("pc_factor_levels", Some("2"))]),
        ("ag_amg_", &[("ksp_type", Some("cg")), ("pc_type", Some("hypre")), ("pc_hypre_type", Some("boomeramg"))]),
        (
            "ag_ssor_",
            &[
                ("ksp_type", Some("symmlq")),
                ("pc_type", Some("sor")),
                ("pc_sor_symmetric", None),
                ("ksp_max_it", Some("50000")),
            ],
        ),
    ];
    for order in [Order::P1, Order::P2] {
        let (mesh, c) = clamped_cantilever(order);
        let right = mesh.require_group("right", 1).unwrap();
        let loads = Loads {
            body_force: None,
            edge_loads: vec![EdgeLoad { group: right, traction: Traction::Constant([0.0, -1e6]) }],
        };
        let mut reference: Option<Vec<f64>> = None;
        for (prefix, options) in solvers {
            let prefix = format!("{prefix}{}", order.degree());
            set_options(s, &prefix, options);
            let (u, stats) = solve(s, &mesh, &steel(), &c, &loads, &prefix).map_err(|e| format!("{prefix}: {e}"))?;
            match &reference {
                None => {
                    ensure(stats.factor_package.as_deref() == Some("mumps"), || {
                        format!("default is not MUMPS: {stats:?}")
                    })?;
                    reference = Some(u);
                }
                Some(r) => {
                    let norm = r.iter().map(|x| x * x).sum::<f64>().sqrt();
                    let diff = r.iter().zip(&u).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
                    ensure(diff <= 1e-6 * norm, || {
                        format!(
                            "{prefix} ({} + {}): relative difference {:e}",
                            stats.ksp_type,
                            stats.pc_type,
                            diff / norm
                        )
                    })?;
                    ensure(stats.iterations > 1, || format!("{prefix}: not iterative? {stats:?}"))?;
                }
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------- driver errors and checks

fn scene_from(text: &str) -> Scene {
    Scene::from_str(text, Path::new("inline.toml")).unwrap()
}

const FREE_BLOCK: &str = r#"
[mesh]
shape = "rectangle"
size = [1.0, 1.0]
cell_size = 0.25
[material]
young = 1e9
poisson = 0.25
[[traction]]
part = "top"
pressure = 1e6
"#;

fn driver_reports_unconstrained_rigid_motion(s: &Session) -> Result<(), String> {
    match ElasticityProblem::setup_system(s, scene_from(FREE_BLOCK)) {
        Err(Error::Unconstrained(m)) => ensure(m.contains("translation") && m.contains("rotation"), || m.clone()),
        Err(e) => Err(format!("wrong error: {e}")),
        Ok(_) => Err("a free body was accepted".into()),
    }
}

fn driver_reports_unknown_boundary_part(s: &Session) -> Result<(), String> {
    let text = format!("{FREE_BLOCK}\n[[dirichlet]]\npart = \"lefft\"\nux = 0.0\n");
    match ElasticityProblem::setup_system(s, scene_from(&text)) {
        Err(Error::Scene { location, message, hint }) => ensure(
            location.line == text.lines().position(|l| l.contains("lefft")).unwrap() + 1
                && (message.contains("lefft"))
                && hint.contains("left"),
            || format!("{location}: {message} / {hint}"),
        ),
        Err(e) => Err(format!("wrong error: {e}")),
        Ok(_) => Err("unknown part accepted".into()),
    }
}

fn driver_default_scene_equilibrium(s: &Session) -> Result<(), String> {
    let block = manifest("examples/scenes/block.toml");
    let scene = Scene::from_file(&block).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    p.solve().map_err(|e| e.to_string())?;
    p.postprocess().map_err(|e| e.to_string())?;
    let r = &p.results.as_ref().unwrap().report;
    // The elastic block: traction (0, -1e6) on a 0.2 m end: resultant (0, -2e5).
    ensure((r.applied_force[1] + 2e5).abs() < 1e-6 * 2e5 && r.applied_force[0].abs() < 1e-6, || {
        format!("{:?}", r.applied_force)
    })?;
    let left = r.reactions.get("left").ok_or("no reaction on left")?;
    ensure((left[1] - 2e5).abs() < 1e-8 * 2e5 && left[0].abs() < 1e-8 * 2e5, || format!("reaction {left:?}"))?;
    ensure(r.equilibrium_residual < 1e-10, || format!("equilibrium {}", r.equilibrium_residual))
}

/// Each step of the pipeline called before the one it needs: `Error::CallOrder` naming both (not
/// a PETSc-layer error); after the right order the same calls work.
fn driver_pipeline_out_of_order(s: &Session) -> Result<(), String> {
    let scene = Scene::from_file(&manifest("examples/scenes/block.toml")).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    let expect = |result: Result<(), Error>, call: &str, needs: &str| match result {
        Err(e @ Error::CallOrder { .. }) => {
            let text = e.to_string();
            ensure(text.starts_with(&format!("{call} called before {needs}")), || text.clone())
        }
        Err(e) => Err(format!("{call}: wrong error {e:?}")),
        Ok(()) => Err(format!("{call} before {needs} accepted")),
    };
    expect(p.report().map(|_| ()), "report()", "solve()")?;
    expect(p.solve(), "solve()", "assemble()")?;
    expect(p.postprocess(), "postprocess()", "solve()")?;
    expect(p.estimate(), "estimate()", "solve()")?;
    p.assemble().map_err(|e| e.to_string())?;
    p.solve().map_err(|e| e.to_string())?;
    expect(p.report().map(|_| ()), "report()", "postprocess()")?;
    p.postprocess().map_err(|e| e.to_string())?;
    expect(p.estimate(), "estimate()", "solve_dual()")?;
    p.report().map(|_| ()).map_err(|e| e.to_string())
}

// ---------------------------------------------------------------- SNES wrapper

/// F_i(x) = x_i² − (i + 1) + 0.1 (x_{i−1} + x_{i+1}) on a chain: a tridiagonal Jacobian.
struct Chain {
    n: usize,
    first: usize,
    local_columns: Vec<usize>,
    indptr: Vec<usize>,
    columns: Vec<usize>,
    panic_in_residual: bool,
    give_up: bool,
}

impl signorini::petsc::nonlinear::NonlinearSystem for Chain {
    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> signorini::Result<()> {
        if self.panic_in_residual {
            panic!("residual exploded");
        }
        for (r, fr) in f.iter_mut().enumerate() {
            let i = self.first + r;
            let mut v = -((i + 1) as f64);
            for p in self.indptr[r]..self.indptr[r + 1] {
                let xj = x[self.local_columns[p]];
                v += if self.columns[p] == i { xj * xj } else { 0.1 * xj };
            }
            *fr = v;
        }
        Ok(())
    }
    fn jacobian(&mut self, x: &[f64], values: &mut [f64]) -> signorini::Result<()> {
        for r in 0..self.indptr.len() - 1 {
            for p in self.indptr[r]..self.indptr[r + 1] {
                let xj = x[self.local_columns[p]];
                values[p] = if self.columns[p] == self.first + r { 2.0 * xj } else { 0.1 };
            }
        }
        Ok(())
    }
    fn converged(
        &mut self,
        iteration: usize,
        _x: &[f64],
        f: &[f64],
    ) -> signorini::Result<signorini::petsc::nonlinear::Convergence> {
        use signorini::petsc::nonlinear::Convergence;
        let worst = f.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        Ok(if self.give_up && iteration == 2 {
            Convergence::Diverged("the chain gave up on purpose".into())
        } else if worst < 1e-13 * self.n as f64 {
            Convergence::Converged(format!("chain residual {worst:e}"))
        } else {
            Convergence::Iterating
        })
    }
}

fn nonlinear_solver_newton_and_callback_errors(s: &Session) -> Result<(), String> {
    use signorini::petsc::nonlinear::NonlinearSolver;
    let n: usize = 12;
    let (mut indptr, mut columns) = (vec![0], Vec::new());
    for i in 0..n {
        columns.extend((i.saturating_sub(1)..(i + 2).min(n)).collect::<Vec<_>>());
        indptr.push(columns.len());
    }
    let mut solver =
        NonlinearSolver::new(s, s.world(), n, 0, &indptr, &columns, "chain_").map_err(|e| e.to_string())?;
    ensure(solver.ghosts().is_empty(), || "ghosts on one rank".into())?;
    let mut chain = Chain {
        n,
        first: 0,
        local_columns: solver.local_columns().to_vec(),
        indptr: indptr.clone(),
        columns: columns.clone(),
        panic_in_residual: false,
        give_up: false,
    };
    let mut x = vec![1.0; n];
    let run = solver.solve(&mut x, &mut chain, 50).map_err(|e| e.to_string())?;
    // Check the answer against the equations themselves.
    for i in 0..n {
        let left = if i > 0 { x[i - 1] } else { 0.0 };
        let right = if i + 1 < n { x[i + 1] } else { 0.0 };
        let r = x[i] * x[i] - (i + 1) as f64 + 0.1 * (left + right);
        ensure(r.abs() < 1e-11, || format!("equation {i}: residual {r:e} ({run:?})"))?;
    }
    ensure(run.iterations >= 3 && run.iterations <= 8 && run.converged_reason.contains("chain residual"), || {
        format!("{run:?}")
    })?;
    ensure(run.factor_package.as_deref() == Some("mumps") && run.method.contains("newtonls"), || format!("{run:?}"))?;
    // A panic inside a callback is an error, not an abort.
    chain.panic_in_residual = true;
    let mut y = vec![1.0; n];
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {})); // the panic is expected: keep the output clean
    let outcome = solver.solve(&mut y, &mut chain, 50);
    std::panic::set_hook(hook);
    match outcome {
        Err(Error::PetscUsage(m)) => ensure(m.contains("panicked") && m.contains("residual exploded"), || m.clone())?,
        other => return Err(format!("expected a callback error, got {other:?}")),
    }
    // The system's own verdict stops the iteration with its reason.
    chain.panic_in_residual = false;
    chain.give_up = true;
    match solver.solve(&mut y, &mut chain, 50) {
        Err(Error::SolverDiverged { reason, iterations, tried, .. }) => ensure(
            reason.contains("gave up on purpose") && iterations == 2 && tried.contains("-chain_snes_monitor"),
            || format!("{reason} / {iterations} / {tried}"),
        ),
        other => Err(format!("expected SolverDiverged, got {other:?}")),
    }
}

/// S = K_cc − K_ci K_ii⁻¹ K_ic from MUMPS, inverted by PETSc: S⁻¹ must equal (K⁻¹)_cc computed
/// column by column, and the factor (applying the inverted S) must solve full systems like the
/// KSP does.
fn mumps_schur_complement_is_the_inverse_block(s: &Session) -> Result<(), String> {
    use signorini::petsc::schur::SchurFactor;
    let (mesh, c) = clamped_cantilever(Order::P2);
    let n = 2 * mesh.num_nodes();
    let right = mesh.require_group("right", 1).unwrap();
    let loads = Loads {
        body_force: None,
        edge_loads: vec![EdgeLoad { group: right, traction: Traction::Constant([1e5, -1e6]) }],
    };
    let system = assembly::assemble(&mesh, &steel(), &c, &loads, 0..n);
    let m = &system.matrix;
    let a = Matrix::from_csr_rows(s, s.world(), n, 0, &m.indptr, &m.indices, &m.values, 2, true)
        .map_err(|e| e.to_string())?;
    let bottom = mesh.require_group("bottom", 1).unwrap();
    let mut nodes = mesh.group_nodes(bottom);
    nodes.retain(|&k| !c.is_fixed(2 * k));
    let rows: Vec<usize> = nodes.iter().flat_map(|&k| [2 * k, 2 * k + 1]).collect();
    let factor = SchurFactor::new(s, &a, &rows).map_err(|e| e.to_string())?;
    let k = rows.len();
    let inverse = nalgebra::DMatrix::from_row_slice(k, k, factor.inverse_block());
    // (K⁻¹)_cc by solves with the default KSP.
    let mut ksp = LinearSolver::new(s, s.world(), "schur_ref_").map_err(|e| e.to_string())?;
    ksp.set_operator(&a).map_err(|e| e.to_string())?;
    let mut e = a.create_vector().map_err(|e| e.to_string())?;
    let mut x = a.create_vector().map_err(|e| e.to_string())?;
    let mut worst = 0.0f64;
    let scale = inverse.amax();
    for (j, &col) in rows.iter().enumerate() {
        let mut unit = vec![0.0; n];
        unit[col] = 1.0;
        e.set_owned(&unit).map_err(|e| e.to_string())?;
        ksp.solve(&a, &e, &mut x).map_err(|e| e.to_string())?;
        let xv = x.owned_values().map_err(|e| e.to_string())?;
        for (i, &row) in rows.iter().enumerate() {
            worst = worst.max((xv[row] - inverse[(i, j)]).abs());
        }
    }
    ensure(worst <= 1e-8 * scale, || format!("S⁻¹ differs from (K⁻¹)_cc by {worst:e} (scale {scale:e})"))?;
    // Full solves with the factor.
    let mut b = a.create_vector().map_err(|e| e.to_string())?;
    b.set_owned(&system.rhs).map_err(|e| e.to_string())?;
    let mut y = a.create_vector().map_err(|e| e.to_string())?;
    factor.solve(&b, &mut y).map_err(|e| e.to_string())?;
    ksp.solve(&a, &b, &mut x).map_err(|e| e.to_string())?;
    let (yv, xv) = (y.owned_values().unwrap(), x.owned_values().unwrap());
    let norm = xv.iter().map(|v| v * v).sum::<f64>().sqrt();
    let diff = xv.iter().zip(&yv).map(|(p, q)| (p - q).powi(2)).sum::<f64>().sqrt();
    ensure(diff <= 1e-10 * norm, || format!("factor solve differs from KSP by {:e}", diff / norm))
}

/// `petsc::inverse_block`: the block of K⁻¹ from MUMPS's selected inverse entries (ICNTL(30))
/// and from the Schur complement built the parallel way (rows on rank 0 only) must equal
/// (K⁻¹)_cc computed column by column with the KSP, in the caller's order of the rows (given
/// unsorted), and the factor must still solve full systems after the selected inverse (which
/// leaves ICNTL(30) set until the wrapper puts it back).
fn mumps_selected_inverse_is_the_inverse_block(s: &Session) -> Result<(), String> {
    use signorini::petsc::inverse_block::InverseBlockFactor;
    let (mesh, c) = clamped_cantilever(Order::P1);
    let n = 2 * mesh.num_nodes();
    let system = assembly::assemble(&mesh, &steel(), &c, &Loads::default(), 0..n);
    let m = &system.matrix;
    let a = Matrix::from_csr_rows(s, s.world(), n, 0, &m.indptr, &m.indices, &m.values, 2, true)
        .map_err(|e| e.to_string())?;
    let bottom = mesh.require_group("bottom", 1).unwrap();
    let mut nodes = mesh.group_nodes(bottom);
    nodes.retain(|&k| !c.is_fixed(2 * k));
    nodes.reverse();
    let rows: Vec<usize> = nodes.iter().flat_map(|&k| [2 * k + 1, 2 * k]).collect();
    let k = rows.len();
    let mut ksp = LinearSolver::new(s, s.world(), "inverse_ref_").map_err(|e| e.to_string())?;
    ksp.set_operator(&a).map_err(|e| e.to_string())?;
    let mut e = a.create_vector().map_err(|e| e.to_string())?;
    let mut x = a.create_vector().map_err(|e| e.to_string())?;
    let mut reference = nalgebra::DMatrix::<f64>::zeros(k, k);
    for (j, &col) in rows.iter().enumerate() {
        let mut unit = vec![0.0; n];
        unit[col] = 1.0;
        e.set_owned(&unit).map_err(|e| e.to_string())?;
        ksp.solve(&a, &e, &mut x).map_err(|e| e.to_string())?;
        let xv = x.owned_values().map_err(|e| e.to_string())?;
        for (i, &row) in rows.iter().enumerate() {
            reference[(i, j)] = xv[row];
        }
    }
    let scale = reference.amax();
    let selected = InverseBlockFactor::new(s, &a, &rows).map_err(|e| e.to_string())?;
    let schur = InverseBlockFactor::with_schur_complement(s, &a, &rows).map_err(|e| e.to_string())?;
    for (name, f) in [("selected inverse", &selected), ("Schur complement", &schur)] {
        let block = nalgebra::DMatrix::from_row_slice(k, k, f.inverse_block());
        let worst = (&block - &reference).amax();
        ensure(worst <= 1e-10 * scale, || {
            format!("{name}: block differs from (K⁻¹)_cc by {worst:e} (scale {scale:e})")
        })?;
    }
    let mut b = a.create_vector().map_err(|e| e.to_string())?;
    b.set_owned(&system.rhs.iter().enumerate().map(|(i, _)| (i as f64 * 0.37).sin()).collect::<Vec<_>>())
        .map_err(|e| e.to_string())?;
    let mut y = a.create_vector().map_err(|e| e.to_string())?;
    selected.solve(&b, &mut y).map_err(|e| e.to_string())?;
    ksp.solve(&a, &b, &mut x).map_err(|e| e.to_string())?;
    let (yv, xv) = (y.owned_values().unwrap(), x.owned_values().unwrap());
    let norm = xv.iter().map(|v| v * v).sum::<f64>().sqrt();
    let diff = xv.iter().zip(&yv).map(|(p, q)| (p - q).powi(2)).sum::<f64>().sqrt();
    ensure(diff <= 1e-10 * norm, || format!("solve after the selected inverse differs from KSP by {:e}", diff / norm))?;
    ensure(schur.solve(&b, &mut y).is_err(), || "the Schur-complement factor must refuse solves".into())
}

/// LAPACK's LU through PETSc (`petsc::dense_lu`): a nonsymmetric system solved to round-off
/// (against nalgebra's LU and the residual), an exactly singular matrix reported as `None`, and
/// a non-square matrix refused.
fn dense_lu_solves_and_reports_zero_pivots(s: &Session) -> Result<(), String> {
    use nalgebra::{DMatrix, DVector};
    use signorini::petsc::dense_lu::DenseLu;
    for n in [1usize, 3, 40, 300] {
        let a = DMatrix::<f64>::from_fn(n, n, |i, j| {
            let x = ((i * 37 + j * 11) % 23) as f64 / 23.0 - 0.5;
            if i == j {
                x + 4.0
            } else {
                x * (1.0 + (i as f64 - j as f64).abs()).recip() + 0.1 * (i as f64 - 2.0 * j as f64) / n as f64
            }
        });
        let b = DVector::<f64>::from_fn(n, |i, _| (i as f64 * 0.7).sin() + 1.0);
        let lu = DenseLu::new(s, &a).map_err(|e| e.to_string())?.ok_or("a nonsingular matrix reported singular")?;
        let x = DVector::from_vec(lu.solve(b.as_slice()).map_err(|e| e.to_string())?);
        let reference = a.clone().lu().solve(&b).ok_or("nalgebra: singular")?;
        let residual = (&a * &x - &b).amax() / b.amax();
        let difference = (&x - &reference).amax() / reference.amax();
        if residual > 1e-13 || difference > 1e-12 {
            return Err(format!("n = {n}: residual {residual:e}, difference from nalgebra {difference:e}"));
        }
    }
    let mut singular = DMatrix::<f64>::from_fn(4, 4, |i, j| (i + 2 * j) as f64 + 1.0);
    singular[(0, 0)] = 0.0;
    let second = singular.row(1).clone_owned();
    singular.set_row(3, &second);
    if DenseLu::new(s, &singular).map_err(|e| e.to_string())?.is_some() {
        return Err("a matrix with two equal rows was factorised".into());
    }
    // The one-shot solve of the condensed solvers (no session reference, a live session).
    let a = DMatrix::<f64>::from_row_slice(2, 2, &[2.0, 1.0, 1.0, 3.0]);
    let x = signorini::petsc::dense_lu::solve_once(&a, &[3.0, 5.0]).map_err(|e| e.to_string())?.ok_or("singular")?;
    if (x[0] - 0.8).abs() > 1e-15 || (x[1] - 1.4).abs() > 1e-15 {
        return Err(format!("solve_once: {x:?} instead of [0.8, 1.4]"));
    }
    if signorini::petsc::dense_lu::solve_once(&singular, &[1.0; 4]).map_err(|e| e.to_string())?.is_some() {
        return Err("solve_once factorised a singular matrix".into());
    }
    match DenseLu::new(s, &DMatrix::<f64>::zeros(2, 3)) {
        Err(Error::PetscUsage(_)) => Ok(()),
        other => Err(format!("a 2 × 3 matrix gave {:?}", other.map(|o| o.is_some()))),
    }
}
