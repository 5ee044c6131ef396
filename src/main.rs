//! The `signorini` command-line program. The library never prints; this file does.
use std::path::PathBuf;
use std::process::ExitCode;

mod command_line;

use clap::Parser as _;
use command_line::arguments::{self as cli, Bench, CaseArgs, Cli, Command, ExportArgs, RunArgs};
use command_line::{bench_runner, error_control, summary, terminal_progress};
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;
use signorini::{bench, Error};

/// The output directory whose previous results this run removed (said after an error).
static REMOVED_BEFORE_RUN: std::sync::Mutex<Option<PathBuf>> = std::sync::Mutex::new(None);

/// Why a command failed: a mistake on its command line (exit status 2, as clap's own) or an
/// error of the work (exit status 1).
enum Failure {
    CommandLine(Error),
    Run(Error),
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Failure::Run(e)
    }
}

impl Failure {
    fn error(&self) -> &Error {
        match self {
            Failure::CommandLine(e) | Failure::Run(e) => e,
        }
    }
}

/// A command-line mistake found after parsing (a flag that does not fit the scene).
fn mistake(message: String) -> Failure {
    Failure::CommandLine(Error::Usage(message))
}

/// The exit status of a command-line mistake.
const USAGE_EXIT: u8 = 2;

fn main() -> ExitCode {
    // A write past `ulimit -f` then fails with EFBIG (its partial file removed, the error said)
    // instead of killing the program with a temporary file left behind.
    signorini::petsc::ignore_file_size_signal();
    let args: Vec<String> = std::env::args().collect();
    let program = args.first().cloned().unwrap_or_else(|| "signorini".into());
    let (ours, petsc) = cli::split_petsc_options(args.get(1..).unwrap_or(&[]));
    let parsed = match Cli::try_parse_from(std::iter::once(program.clone()).chain(ours)) {
        Ok(c) => c,
        Err(e) => {
            // Help and version go to stdout with exit 0; mistakes to stderr with exit 2.
            let _ = e.print();
            return ExitCode::from(if e.use_stderr() { USAGE_EXIT } else { 0 });
        }
    };
    let session = |job: &dyn Fn(&Session) -> Result<(), Failure>| with_session(&program, &petsc, job);
    match parsed.command {
        Command::Run(r) => {
            if r.no_mesh_cache {
                // Still one thread: MPI and PETSc start later.
                std::env::set_var("SIGNORINI_NO_MESH_CACHE", "1");
            }
            session(&|s| run(s, &r))
        }
        Command::Adapt(a) => session(&|s| error_control::adapt_command(s, &a)),
        Command::Study(a) => session(&|s| error_control::study_command(s, &a)),
        Command::Export(e) => session(&|s| export_command(s, &e)),
        Command::Bench { which } => {
            // A benchmark's driver runs on one process: refused under mpirun -n N (N > 1).
            if let Some(Err(code)) = which.driver_name().map(bench_runner::refuse_several_processes) {
                return code;
            }
            match which {
                Bench::Elasticity(o) => bench_runner::bench_elasticity(&o, &petsc),
                Bench::Contact(o) => bench_runner::bench_contact(&o, &petsc),
                Bench::Dual(o) => bench_runner::bench_dual(&o, &petsc),
                Bench::DualContact(o) => bench_runner::bench_dual_contact(&o, &petsc),
                Bench::Held(o) => bench_runner::bench_held(&o, &petsc),
                Bench::Evolution(o) => bench_runner::bench_evolution(&o, &petsc),
                Bench::Accuracy(o) => bench_runner::bench_accuracy(&o, &petsc),
                Bench::Scale(o) => bench_runner::bench_scale(&o, &petsc),
                Bench::Startup(o) => bench_runner::bench_startup(o.runs as usize, o.skip_half_disc, o.out),
                Bench::ElasticityCase(c) => session(&|s| bench_elasticity_case(s, &c)),
                Bench::ContactCase(c) => session(&|s| bench_contact_case(s, &c)),
                Bench::AccuracyCase(c) => session(&|s| bench_accuracy_case(s, &c)),
                Bench::DualCase(c) => session(&|s| bench_dual_case(s, &c)),
                Bench::DualContactCase(c) => session(&|s| bench_dual_contact_case(s, &c)),
                Bench::HeldCase(c) => session(&|s| bench_held_case(s, &c)),
                Bench::EvolutionCase(c) => session(&|s| bench_evolution_case(s, &c)),
                Bench::ScaleCase(c) => session(&|s| bench_scale_case(s, &c)),
            }
        }
    }
}

/// Start PETSc with the command line's PETSc options, run `job`, say why it failed (exit 2 for
/// a command-line mistake, a PETSc option without its value included; 1 otherwise).
fn with_session(program: &str, petsc: &[String], job: &dyn Fn(&Session) -> Result<(), Failure>) -> ExitCode {
    let mut petsc_argv = vec![program.to_string()];
    petsc_argv.extend(petsc.iter().cloned());
    let session = match Session::init(&petsc_argv) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            // The options checked here are the command line's own.
            let usage = matches!(e, Error::PetscOption { .. });
            return if usage { ExitCode::from(USAGE_EXIT) } else { ExitCode::FAILURE };
        }
    };
    let rank = session.rank();
    let result = job(&session);
    // Under MPI, rank 0 says why the run failed, and so does the lowest rank whose failure was
    // its own when rank 0's was not (rank 0 then has Error::OtherRank, naming that rank). An
    // error every rank met alike (a scene mistake) is printed once. Every rank gets here: the
    // steps whose failure can differ between ranks are agreed (Session::agree).
    let own_failure = matches!(&result, Err(f) if !matches!(f.error(), Error::OtherRank { .. }));
    let reporter = session.world().first_failure(own_failure).ok().flatten();
    if let Err(failure) = &result {
        let e = failure.error();
        if rank != 0 {
            if reporter == Some(rank) {
                eprintln!("error (MPI rank {rank}): {e}");
            }
        } else {
            eprintln!("error: {e}");
            if let Some(dir) = REMOVED_BEFORE_RUN.lock().unwrap_or_else(|p| p.into_inner()).as_ref() {
                eprintln!("note: the previous results in {} were removed; no result was written", dir.display());
            }
        }
    }
    // No rank leaves before the messages above are written: mpirun aborts the job at the first
    // non-zero exit status, which cut rank 0 off before its message when another rank exited
    // first (one more reduction, reached by every rank like the one above).
    let _ = session.world().min(&[0.0]);
    drop(session); // PetscFinalize before exit
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::CommandLine(_)) => ExitCode::from(USAGE_EXIT),
        Err(Failure::Run(_)) => ExitCode::FAILURE,
    }
}

fn run(session: &Session, args: &RunArgs) -> Result<(), Failure> {
    // Nothing stale after a failure: the previous results go before anything is read or solved
    // (with --out known now; else once the scene says where its results go).
    // Rank 0 alone clears: the ranks agree on its outcome before they go on together.
    let clear = |out: &std::path::Path| -> Result<(), Failure> {
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
    let force_unit = if signorini::problem::axisymmetry::is_axisymmetric(&scene) { "N" } else { "N/m" };
    let progress = Box::new(terminal_progress::TerminalProgress::new(show_progress).with_force_unit(force_unit));
    let dual = match args.formulation.as_deref() {
        Some("dual") => true,
        Some(_) => false,
        None => scene.formulation == signorini::scene::Formulation::Dual,
    };
    let estimate = args.estimate || scene.estimate;
    if dual || estimate {
        let what = if dual { "the dual formulation" } else { "the estimate (--estimate)" };
        signorini::interface_law::refuse_dual(&scene, what)?;
        signorini::problem::axisymmetry::refuse_in_axisymmetry(&scene, what)?;
    }
    // What of the dual contact cannot run on several ranks is refused before any work starts.
    if (dual || estimate) && scene.contact.is_some() {
        signorini::dual::condensation::refuse_undistributable(session)?;
    }
    let mut problem = ElasticityProblem::setup_system_with_progress(session, scene, progress)?;
    match args.dual_constraints.as_deref() {
        Some("multipliers") => problem.scene.dual_constraints = signorini::scene::DualConstraints::Multipliers,
        Some(_) => problem.scene.dual_constraints = signorini::scene::DualConstraints::Eliminated,
        None => {}
    }
    let load_path = signorini::evolution::LoadPath::of_scene(&problem.scene)?;
    if let Some(path) = &load_path {
        if dual {
            return Err(Failure::Run(Error::Formulation {
                message: "a load path ([evolution]) is solved in the primal formulation (with --estimate: the dual \
                          at every increment)"
                    .into(),
                hint: "remove --formulation dual / formulation = \"dual\" (or the [evolution] table)".into(),
            }));
        }
        problem.assemble()?;
        let each = if estimate {
            signorini::evolution::EachIncrement::Estimate
        } else {
            signorini::evolution::EachIncrement::Postprocess
        };
        let steps_dir = out.clone();
        let solved = problem
            .solve_load_path(path, each, &mut |p, record| p.write_step_output(&steps_dir, record.step).map(|_| ()));
        if let Err(e) = solved {
            // No increments left behind by a path that did not finish.
            if session.rank() == 0 {
                let _ = signorini::output::pvd::clear_step_files(&out);
            }
            return Err(e.into());
        }
    } else if !dual || estimate {
        problem.assemble()?;
        problem.solve()?;
        problem.postprocess()?;
    }
    // With --estimate the primal solution stands on its own: when the dual formulation cannot
    // take the scene (a point support that carries a force, a hole, ...) the primal results are
    // written all the same, and the run then fails with the dual's reason.
    let mut refused = None;
    // A load path estimated every increment already (the last one's stays in the report).
    if (dual || estimate) && load_path.is_none() {
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
            Err(Failure::Run(e))
        }
        None => Ok(()),
    }
}

/// `signorini export SCENE [--out FILE] [--solve]`: the condensed contact problem in the FCLIB
/// format (and our solution of it with `--solve`); one line on stdout says what was written.
fn export_command(session: &Session, args: &ExportArgs) -> Result<(), Failure> {
    use signorini::contact::FrictionLaw;
    use signorini::export::{check_friction, write_fclib, FclibInfo};
    let path = &args.scene;
    let scene = Scene::from_file(path)?;
    // Several bodies: checked, then refused (their first body's [contact] is not the scene's).
    signorini::problem::refuse_several_bodies(&scene)?;
    if scene.contact.is_none() {
        // A scene the command cannot take, as a Tresca or several-body scene: not a mistake on
        // the command line (exit 1).
        return Err(Failure::Run(Error::Usage(format!(
            "signorini export: the scene {} has no [contact] section: there is no contact problem to export",
            path.display()
        ))));
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
         towards the body); q = gap - B K^-1 f. u are displacements (m), r nodal forces ({}).",
        env!("CARGO_PKG_VERSION"),
        option_env!("SIGNORINI_COMMIT").unwrap_or("unknown"),
        path.display(),
        condensed.points(),
        problem.mesh.num_cells(),
        problem.mesh.num_nodes(),
        problem.material.plane.name(),
        problem.material.young,
        problem.material.poisson,
        if problem.mesh.measure.is_axisymmetric() { "N, for the full revolution" } else { "N per unit thickness" },
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
fn override_contact_solver(scene: &mut Scene, name: &str) -> Result<(), Failure> {
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
        mistake(format!(
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
        return Err(mistake(format!(
            "--contact-solver {name}: the scene {} has no [contact] section (nor, with [[body]] tables, a \
             [[contact_pair]] or a [body.contact])",
            scene.source.display()
        )));
    }
    if solver == S::SnesVi && frictions.iter().any(|f| *f != FrictionSpec::None) {
        return Err(mistake("--contact-solver snes_vi handles frictionless contact only: use newton_full".into()));
    }
    if solver == S::Tao && !frictions.iter().all(|f| matches!(f, FrictionSpec::Tresca { .. })) {
        return Err(mistake("--contact-solver tao solves the Tresca problem only: use newton_full".into()));
    }
    let several_bodies = scene.has_body_tables();
    match scene.contact.as_mut().filter(|_| !several_bodies) {
        Some(contact) => contact.solver = solver,
        None => scene.contact_solver = Some(solver),
    }
    Ok(())
}

/// `bench elasticity-case --case DOFS,SOLVER`: one case, its row as JSON on stdout.
fn bench_elasticity_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let solver = bench::SOLVERS.get(index).ok_or_else(|| mistake(format!("no benchmark solver {index}")))?;
    let scratch = args.out.clone().unwrap_or_else(std::env::temp_dir);
    let row = bench::elasticity_case(session, dofs, solver, &scratch)?;
    print_case_row(session, &row)
}

/// A benchmark case's result: its JSON row on stdout, for the parent process (rank 0 only).
fn print_case_row(session: &Session, row: &impl serde::Serialize) -> Result<(), Failure> {
    if session.rank() == 0 {
        println!("{}", serde_json::to_string(row).map_err(|e| Error::Usage(e.to_string()))?);
    }
    Ok(())
}

fn bench_contact_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let solver = bench::CONTACT_SOLVERS.get(index).ok_or_else(|| mistake(format!("no contact solver {index}")))?;
    let row = bench::contact_case(session, dofs, solver)?;
    print_case_row(session, &row)
}

fn bench_dual_contact_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let row = bench::dual_contact::dual_contact_case(session, dofs, index)?;
    print_case_row(session, &row)
}

fn bench_held_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let row = bench::held::held_case(session, dofs, index)?;
    print_case_row(session, &row)
}

fn bench_evolution_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let row = bench::evolution::evolution_case(session, dofs, index)?;
    print_case_row(session, &row)
}

/// `bench scale-case --case DOFS,INDEX`: one case of `bench scale` (under mpirun for its
/// scaling parts), its row as JSON on stdout (rank 0).
fn bench_scale_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let row = bench::scale::scale_case(session, dofs, index)?;
    print_case_row(session, &row)
}

/// `bench accuracy-case --case DOFS,INDEX --out SCRATCH`: case INDEX of SCRATCH/plan.json.
fn bench_accuracy_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (_, index) = args.case;
    let scratch = args.out.clone().ok_or_else(|| mistake("bench accuracy-case needs --out SCRATCH".into()))?;
    let result = bench::accuracy::accuracy_case(session, &scratch, index)?;
    print_case_row(session, &result)
}

fn bench_dual_case(session: &Session, args: &CaseArgs) -> Result<(), Failure> {
    let (dofs, index) = args.case;
    let solvers = bench::dual::dual_solvers();
    let solver = solvers.get(index).ok_or_else(|| mistake(format!("no dual benchmark solver {index}")))?;
    let row = bench::dual::dual_case(session, dofs, solver)?;
    print_case_row(session, &row)
}
