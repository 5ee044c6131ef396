//! The `signorini` command-line program. The library never prints; this file does.
use std::path::PathBuf;
use std::process::ExitCode;

mod command_line;

use clap::Parser as _;
use command_line::arguments::{self as cli, Bench, Cli, Command};
use command_line::{bench_runner, error_control, summary, terminal_progress};
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;
use signorini::{bench, Error};

/// The output directory whose previous results this run removed (said after an error).
static REMOVED_BEFORE_RUN: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

struct RunArgs {
    scene: Option<PathBuf>,
    out: Option<PathBuf>,
    quiet: bool,
    max_dofs: usize,
    /// bench elasticity-case: the size and the solver index.
    case: Option<(usize, usize)>,
    /// run: override of the scene's [contact] solver.
    contact_solver: Option<String>,
    /// run: `--formulation`, `--estimate`.
    formulation: Option<String>,
    estimate: bool,
    /// run: `--dual-constraints`.
    dual_constraints: Option<String>,
    /// adapt: `--target`, `--max-steps`, `--max-elements`; study: `--levels`,
    /// `--reference-halvings`.
    target: f64,
    max_steps: usize,
    max_elements: usize,
    /// adapt: `--contact-rate`.
    contact_rate: Option<f64>,
    levels: usize,
    reference_halvings: usize,
    /// export: `--solve`.
    solve: bool,
    petsc: Vec<String>,
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let program = args.first().cloned().unwrap_or_else(|| "signorini".into());
    let (ours, petsc) = cli::split_petsc_options(args.get(1..).unwrap_or(&[]));
    let parsed = match Cli::try_parse_from(std::iter::once(program.clone()).chain(ours)) {
        Ok(c) => c,
        Err(e) => {
            // Help and version go to stdout with exit 0; mistakes to stderr with exit 2.
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
        }
    };
    let args = |scene, out, quiet, contact_solver, max_dofs, case| RunArgs {
        scene,
        out,
        quiet,
        max_dofs,
        case,
        contact_solver,
        formulation: None,
        estimate: false,
        dual_constraints: None,
        target: 0.0,
        max_steps: 0,
        max_elements: 0,
        contact_rate: None,
        levels: 0,
        reference_halvings: 0,
        solve: false,
        petsc: petsc.clone(),
    };
    match parsed.command {
        Command::Run(r) => {
            if r.no_mesh_cache {
                // Still one thread: MPI and PETSc start later.
                std::env::set_var("SIGNORINI_NO_MESH_CACHE", "1");
            }
            let mut a = args(r.scene, r.out, r.quiet, r.contact_solver, 0, None);
            a.formulation = r.formulation;
            a.estimate = r.estimate;
            a.dual_constraints = r.dual_constraints;
            with_session(&program, a, run)
        }
        Command::Adapt(a) => {
            let mut r = args(Some(a.scene), a.out, a.quiet, None, 0, None);
            r.target = a.target;
            r.max_steps = a.max_steps as usize;
            r.max_elements = a.max_elements;
            r.contact_rate = a.contact_rate;
            with_session(&program, r, error_control::adapt_command)
        }
        Command::Study(a) => {
            let mut r = args(Some(a.scene), a.out, a.quiet, None, 0, None);
            r.levels = a.levels as usize;
            r.reference_halvings = a.reference_halvings as usize;
            with_session(&program, r, error_control::study_command)
        }
        Command::Export(e) => {
            let mut r = args(Some(e.scene), e.out, false, None, 0, None);
            r.solve = e.solve;
            with_session(&program, r, export_command)
        }
        Command::Bench { which } => match which {
            Bench::Elasticity(o) => {
                bench_runner::bench_elasticity(args(None, o.out, false, None, o.max_dofs.unwrap_or(1_000_000), None))
            }
            Bench::Contact(o) => {
                bench_runner::bench_contact(args(None, o.out, false, None, o.max_dofs.unwrap_or(100_000), None))
            }
            Bench::Startup(o) => bench_runner::bench_startup(o.runs as usize, o.skip_half_disc, o.out),
            Bench::ElasticityCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_elasticity_case)
            }
            Bench::ContactCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_contact_case)
            }
            Bench::Dual(o) => {
                bench_runner::bench_dual(args(None, o.out, false, None, o.max_dofs.unwrap_or(100_000), None))
            }
            Bench::Accuracy(o) => {
                let mut a = args(o.scene, o.out, false, None, o.max_dofs.unwrap_or(20_000), None);
                a.target = o.target.unwrap_or(1.0);
                bench_runner::bench_accuracy(a)
            }
            Bench::AccuracyCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_accuracy_case)
            }
            Bench::DualCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_dual_case)
            }
            Bench::DualContact(o) => {
                bench_runner::bench_dual_contact(args(None, o.out, false, None, o.max_dofs.unwrap_or(100_000), None))
            }
            Bench::DualContactCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_dual_contact_case)
            }
            Bench::Held(o) => {
                bench_runner::bench_held(args(None, o.out, false, None, o.max_dofs.unwrap_or(100_000), None))
            }
            Bench::HeldCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_held_case)
            }
        },
    }
}

fn with_session(program: &str, parsed: RunArgs, job: fn(&Session, RunArgs) -> Result<(), Error>) -> ExitCode {
    let mut petsc_argv = vec![program.to_string()];
    petsc_argv.extend(parsed.petsc.iter().cloned());
    let session = match Session::init(&petsc_argv) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let rank = session.rank();
    let result = job(&session, parsed);
    // Under MPI, rank 0 says why the run failed, and so does the lowest rank whose failure was
    // its own when rank 0's was not (rank 0 then has Error::OtherRank, naming that rank). An
    // error every rank met alike (a scene mistake) is printed once. Every rank gets here: the
    // steps whose failure can differ between ranks are agreed (Session::agree).
    let own_failure = matches!(&result, Err(e) if !matches!(e, Error::OtherRank { .. }));
    let reporter = session.world().first_failure(own_failure).ok().flatten();
    drop(session); // PetscFinalize before exit
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) if rank != 0 => {
            if reporter == Some(rank) {
                eprintln!("error (MPI rank {rank}): {e}");
            }
            ExitCode::FAILURE
        }
        Err(e) => {
            eprintln!("error: {e}");
            if let Some(dir) = REMOVED_BEFORE_RUN.lock().unwrap_or_else(|p| p.into_inner()).as_ref() {
                eprintln!("note: the previous results in {} were removed; no result was written", dir.display());
            }
            ExitCode::FAILURE
        }
    }
}

fn run(session: &Session, args: RunArgs) -> Result<(), Error> {
    // Nothing stale after a failure: the previous results go before anything is read or solved
    // (with --out known now; else once the scene says where its results go).
    // Rank 0 alone clears: the ranks agree on its outcome before they go on together.
    let clear = |out: &std::path::Path| -> Result<(), Error> {
        let cleared = if session.rank() == 0 { signorini::output::clear_previous_run(out) } else { Ok(Vec::new()) };
        if !session.agree(cleared, "clearing the previous results")?.is_empty() {
            *REMOVED_BEFORE_RUN.lock().unwrap_or_else(|p| p.into_inner()) = Some(out.to_path_buf());
        }
        Ok(())
    };
    if let Some(out) = &args.out {
        clear(out)?;
    }
    let scene = match &args.scene {
        Some(path) => Scene::from_file(path)?,
        None => Scene::default_scene(),
    };
    let mut scene = scene;
    if let Some(name) = &args.contact_solver {
        override_contact_solver(&mut scene, name)?;
    }
    let out = args.out.clone().or_else(|| scene.output_dir.clone()).unwrap_or_else(|| PathBuf::from("out"));
    if args.out.is_none() {
        clear(&out)?;
    }
    let show_progress = session.rank() == 0 && terminal_progress::wanted(args.quiet);
    let progress = Box::new(terminal_progress::TerminalProgress::new(show_progress));
    let mut problem = ElasticityProblem::setup_system_with_progress(session, scene, progress)?;
    let dual = match args.formulation.as_deref() {
        Some("dual") => true,
        Some(_) => false,
        None => problem.scene.formulation == signorini::scene::Formulation::Dual,
    };
    let estimate = args.estimate || problem.scene.estimate;
    match args.dual_constraints.as_deref() {
        Some("multipliers") => problem.scene.dual_constraints = signorini::scene::DualConstraints::Multipliers,
        Some(_) => problem.scene.dual_constraints = signorini::scene::DualConstraints::Eliminated,
        None => {}
    }
    if !dual || estimate {
        problem.assemble()?;
        problem.solve()?;
        problem.postprocess()?;
    }
    // With --estimate the primal solution stands on its own: when the dual formulation cannot
    // take the scene (a point support that carries a force, a hole, ...) the primal results are
    // written all the same, and the run then fails with the dual's reason.
    let mut refused = None;
    if dual || estimate {
        let outcome = problem.solve_dual().and_then(|()| if estimate { problem.estimate() } else { Ok(()) });
        match outcome {
            Err(Error::Formulation { message, hint }) if !dual && problem.results.is_some() => {
                problem.dual = None;
                problem.estimate = None;
                refused = Some(Error::Formulation {
                    message: format!("--estimate: {message}"),
                    hint: format!(
                        "{hint}; the primal results were written to {} (without the estimate)",
                        out.display()
                    ),
                });
            }
            other => other?,
        }
    }
    let (report, written) = problem.write_output(&out)?;
    drop(problem); // clears the spinner
    if session.rank() == 0 && !args.quiet {
        // The summary on stdout, warnings on stderr.
        for line in summary::summary_lines(&report, &written) {
            println!("{line}");
        }
        for line in summary::warning_lines(&report) {
            eprintln!("{line}");
        }
    }
    match refused {
        Some(e) => {
            // Results were written: the failure note must not say otherwise.
            *REMOVED_BEFORE_RUN.lock().unwrap_or_else(|p| p.into_inner()) = None;
            Err(e)
        }
        None => Ok(()),
    }
}

/// `signorini export SCENE [--out FILE] [--solve]`: the condensed contact problem in the FCLIB
/// format (and our solution of it with `--solve`); one line on stdout says what was written.
fn export_command(session: &Session, args: RunArgs) -> Result<(), Error> {
    use signorini::contact::FrictionLaw;
    use signorini::export::{check_friction, write_fclib, FclibInfo};
    let path = args.scene.clone().ok_or_else(|| Error::Usage("signorini export needs a scene".into()))?;
    let scene = Scene::from_file(&path)?;
    // Several bodies: checked, then refused (their first body's [contact] is not the scene's).
    signorini::problem::refuse_several_bodies(&scene)?;
    if scene.contact.is_none() {
        return Err(Error::Usage(format!(
            "signorini export: the scene {} has no [contact] section: there is no contact problem to export",
            path.display()
        )));
    }
    let file = args
        .out
        .clone()
        .unwrap_or_else(|| scene.output_dir.clone().unwrap_or_else(|| PathBuf::from("out")).join("problem.hdf5"));
    let mut problem = ElasticityProblem::setup_system(session, scene)?;
    if let Some(contact) = &problem.contact {
        check_friction(&contact.friction_law())?; // Tresca: refused before the condensation
    }
    let condensed = problem.condensed_contact_problem()?;
    let solution = if args.solve { Some(problem.solve_condensed_contact_problem(&condensed)?) } else { None };
    if session.rank() != 0 {
        return Ok(());
    }
    let contact = problem.contact.as_ref().map(|c| c.spec.part.clone()).unwrap_or_default();
    let description = format!(
        "signorini {} ({}): the condensed contact problem of the scene {}: {} contact points (the nodes of the \
         part '{contact}', {} elements, {} nodes) of a linear elastic body (plane {}, E = {:e} Pa, nu = {}) against a \
         rigid obstacle. W = B K^-1 B^T is the flexibility in the local frames (normal: the obstacle's normal, \
         towards the body); q = gap - B K^-1 f. u are displacements (m), r nodal forces (N per unit thickness).",
        env!("CARGO_PKG_VERSION"),
        option_env!("SIGNORINI_COMMIT").unwrap_or("unknown"),
        path.display(),
        condensed.points(),
        problem.mesh.num_cells(),
        problem.mesh.num_nodes(),
        match problem.material.plane {
            signorini::fem::material::PlaneModel::Strain => "strain",
            signorini::fem::material::PlaneModel::Stress => "stress",
        },
        problem.material.young,
        problem.material.poisson,
    );
    let title = problem.scene.title.clone().unwrap_or_else(|| path.display().to_string());
    let info = FclibInfo::new(title, description, &condensed);
    let written = write_fclib(&file, &condensed, solution.as_ref().map(|s| s.force.as_slice()), &info)?;
    let friction = match condensed.friction() {
        FrictionLaw::Coulomb { mu } => format!("Coulomb mu = {}", mu.iter().cloned().fold(0.0, f64::max)),
        _ => "frictionless".to_string(),
    };
    let ours = match &solution {
        Some(s) => format!(", with our solution ({}, {} iterations)", s.solver, s.iterations),
        None => String::new(),
    };
    println!(
        "wrote {}: FCLIB local problem, {} contacts in dimension {} (W {n}x{n}, {} entries), {friction}{ours}",
        file.display(),
        written.contacts,
        written.dimension,
        written.nonzeros,
        n = written.dimension * written.contacts,
    );
    Ok(())
}

/// `--contact-solver NAME`: replace the scene's contact solver, with the scene's own rules
/// (SNESVI is frictionless only, TAO is for Tresca).
fn override_contact_solver(scene: &mut Scene, name: &str) -> Result<(), Error> {
    use signorini::scene::{ContactSolverSpec as S, FrictionSpec};
    let candidates = [
        S::FullSpaceNewton,
        S::Newton,
        S::Relaxation { omega: 1.0 },
        S::DPana,
        S::Uzawa,
        S::TrescaFixedPoint,
        S::SnesVi,
        S::Tao,
    ];
    let solver = candidates.into_iter().find(|c| c.scene_name() == name).ok_or_else(|| {
        Error::Usage(format!(
            "--contact-solver {name}: unknown solver; choose one of newton_full, newton, relaxation, dpana, uzawa, tresca_fixed_point, snes_vi, tao"
        ))
    })?;
    // The friction law of every contact the solver would take: the [contact] table's, or with
    // several bodies every pair's and every body's (the solver then applies to all of them;
    // snes_vi is refused with a pair by the setup, at the pair's line).
    let frictions: Vec<FrictionSpec> = if scene.has_body_tables() {
        let pairs = scene.contact_pairs.iter().map(|p| p.friction);
        pairs.chain(scene.bodies.iter().filter_map(|b| b.contact.as_ref()).map(|c| c.friction)).collect()
    } else {
        scene.contact.iter().map(|c| c.friction).collect()
    };
    if frictions.is_empty() {
        return Err(Error::Usage(format!(
            "--contact-solver {name}: the scene {} has no [contact] section (nor, with [[body]] tables, a \
             [[contact_pair]] or a [body.contact])",
            scene.source.display()
        )));
    }
    if solver == S::SnesVi && frictions.iter().any(|f| *f != FrictionSpec::None) {
        return Err(Error::Usage("--contact-solver snes_vi handles frictionless contact only: use newton_full".into()));
    }
    if solver == S::Tao && !frictions.iter().all(|f| matches!(f, FrictionSpec::Tresca { .. })) {
        return Err(Error::Usage("--contact-solver tao solves the Tresca problem only: use newton_full".into()));
    }
    let several_bodies = scene.has_body_tables();
    match scene.contact.as_mut().filter(|_| !several_bodies) {
        Some(contact) => contact.solver = solver,
        None => scene.contact_solver = Some(solver),
    }
    Ok(())
}

/// `bench elasticity-case --case DOFS,SOLVER`: one case, its row as JSON on stdout.
fn bench_elasticity_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench elasticity-case needs --case DOFS,SOLVER_INDEX".into()))?;
    let solver = bench::SOLVERS.get(index).ok_or_else(|| Error::Usage(format!("no benchmark solver {index}")))?;
    let scratch = args.out.clone().unwrap_or_else(std::env::temp_dir);
    let row = bench::elasticity_case(session, dofs, solver, &scratch)?;
    print_case_row(session, &row)
}

/// A benchmark case's result: its JSON row on stdout, for the parent process (rank 0 only).
fn print_case_row(session: &Session, row: &impl serde::Serialize) -> Result<(), Error> {
    if session.rank() == 0 {
        println!("{}", serde_json::to_string(row).map_err(|e| Error::Usage(e.to_string()))?);
    }
    Ok(())
}

fn bench_contact_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench contact-case needs --case DOFS,SOLVER_INDEX".into()))?;
    let solver = bench::CONTACT_SOLVERS.get(index).ok_or_else(|| Error::Usage(format!("no contact solver {index}")))?;
    let row = bench::contact_case(session, dofs, solver)?;
    print_case_row(session, &row)
}

fn bench_dual_contact_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench dual-contact-case needs --case DOFS,STRATEGY_INDEX".into()))?;
    let row = bench::dual_contact::dual_contact_case(session, dofs, index)?;
    print_case_row(session, &row)
}

fn bench_held_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench held-case needs --case DOFS,DRIVE_INDEX".into()))?;
    let row = bench::held::held_case(session, dofs, index)?;
    print_case_row(session, &row)
}

/// `bench accuracy-case --case DOFS,INDEX --out SCRATCH`: case INDEX of SCRATCH/plan.json.
fn bench_accuracy_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (_, index) = args.case.ok_or_else(|| Error::Usage("bench accuracy-case needs --case DOFS,INDEX".into()))?;
    let scratch = args.out.clone().ok_or_else(|| Error::Usage("bench accuracy-case needs --out SCRATCH".into()))?;
    let result = bench::accuracy::accuracy_case(session, &scratch, index)?;
    if session.rank() == 0 {
        println!("{}", serde_json::to_string(&result).map_err(|e| Error::Usage(e.to_string()))?);
    }
    Ok(())
}

fn bench_dual_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench dual-case needs --case DOFS,SOLVER_INDEX".into()))?;
    let solvers = bench::dual::dual_solvers();
    let solver = solvers.get(index).ok_or_else(|| Error::Usage(format!("no dual benchmark solver {index}")))?;
    let row = bench::dual::dual_case(session, dofs, solver)?;
    print_case_row(session, &row)
}
