//! The `signorini` command-line program. The library never prints; this file does.
use std::path::PathBuf;
use std::process::ExitCode;

mod cli;
mod error_control;

use clap::Parser as _;
use cli::{Bench, Cli, Command};
use signorini::petsc::Session;
use signorini::problem::{ElasticityProblem, Report};
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
    levels: usize,
    reference_halvings: usize,
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
        levels: 0,
        reference_halvings: 0,
        petsc: petsc.clone(),
    };
    match parsed.command {
        Command::Run(r) => {
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
            with_session(&program, r, error_control::adapt_command)
        }
        Command::Study(a) => {
            let mut r = args(Some(a.scene), a.out, a.quiet, None, 0, None);
            r.levels = a.levels as usize;
            r.reference_halvings = a.reference_halvings as usize;
            with_session(&program, r, error_control::study_command)
        }
        Command::Bench { which } => match which {
            Bench::Elasticity(o) => {
                bench_elasticity(args(None, o.out, false, None, o.max_dofs.unwrap_or(1_000_000), None))
            }
            Bench::Contact(o) => bench_contact(args(None, o.out, false, None, o.max_dofs.unwrap_or(100_000), None)),
            Bench::ElasticityCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_elasticity_case)
            }
            Bench::ContactCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_contact_case)
            }
            Bench::Dual(o) => bench_dual(args(None, o.out, false, None, o.max_dofs.unwrap_or(100_000), None)),
            Bench::DualCase(c) => {
                with_session(&program, args(None, c.out, true, None, 0, Some(c.case)), bench_dual_case)
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
    drop(session); // PetscFinalize before exit
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            if rank == 0 {
                eprintln!("error: {e}");
                if let Some(dir) = REMOVED_BEFORE_RUN.lock().unwrap_or_else(|p| p.into_inner()).as_ref() {
                    eprintln!("note: the previous results in {} were removed; no result was written", dir.display());
                }
            }
            ExitCode::FAILURE
        }
    }
}

fn run(session: &Session, args: RunArgs) -> Result<(), Error> {
    let say = |s: &str| {
        if session.rank() == 0 && !args.quiet {
            eprintln!("{s}");
        }
    };
    // Nothing stale after a failure: the previous results go before anything is read or solved
    // (with --out known now; else once the scene says where its results go).
    let clear = |out: &std::path::Path| -> Result<(), Error> {
        if session.rank() == 0 && !signorini::output::clear_previous_run(out)?.is_empty() {
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
    say(&format!(
        "signorini {} — {} ({})",
        env!("CARGO_PKG_VERSION"),
        scene.title.as_deref().unwrap_or("untitled scene"),
        scene.source.display()
    ));
    let mut problem = ElasticityProblem::setup_system(session, scene)?;
    say(&format!(
        "  mesh      {} nodes, {} {:?} triangles, {} dofs on {} rank(s) [{:.2} s]",
        problem.mesh.num_nodes(),
        problem.mesh.num_cells(),
        problem.mesh.order,
        problem.num_dofs(),
        session.size(),
        problem.timings.get("mesh").unwrap_or(0.0)
    ));
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
        say(&format!("  assemble  [{:.2} s]", problem.timings.get("assemble").unwrap_or(0.0)));
        problem.solve()?;
        problem.postprocess()?;
    }
    if dual || estimate {
        problem.solve_dual()?;
    }
    if estimate {
        problem.estimate()?;
    }
    let (report, written) = problem.write_output(&out)?;
    if session.rank() == 0 && !args.quiet {
        print_summary(&report, &written);
    }
    Ok(())
}

/// `--contact-solver NAME`: replace the scene's contact solver, with the scene's own rules
/// (SNESVI is frictionless only, TAO is for Tresca).
fn override_contact_solver(scene: &mut Scene, name: &str) -> Result<(), Error> {
    use signorini::scene::{ContactSolverSpec as S, FrictionSpec};
    let contact = scene.contact.as_mut().ok_or_else(|| {
        Error::Usage(format!("--contact-solver {name}: the scene {} has no [contact] section", scene.source.display()))
    })?;
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
    match (&solver, &contact.friction) {
        (S::SnesVi, f) if *f != FrictionSpec::None => {
            Err(Error::Usage("--contact-solver snes_vi handles frictionless contact only: use newton_full".into()))
        }
        (S::Tao, f) if !matches!(f, FrictionSpec::Tresca { .. }) => {
            Err(Error::Usage("--contact-solver tao solves the Tresca problem only: use newton_full".into()))
        }
        _ => {
            contact.solver = solver;
            Ok(())
        }
    }
}

fn print_summary(r: &Report, written: &[PathBuf]) {
    let s = &r.solver.stats;
    let pkg = s.factor_package.as_ref().map(|p| format!(" ({p})")).unwrap_or_default();
    eprintln!(
        "  solve     {} + {}{pkg}: {} iteration(s), {}, true residual {:.1e} [{:.2} s]",
        s.ksp_type, s.pc_type, s.iterations, s.converged_reason, s.relative_residual, s.seconds
    );
    if let Some(res) = &r.results {
        eprintln!("  result    max |u| = {:.4e}, max von Mises = {:.4e}", res.max_displacement, res.max_von_mises);
        let reactions: Vec<String> =
            res.reactions.iter().map(|(k, v)| format!("{k} ({:.4e}, {:.4e})", v[0], v[1])).collect();
        eprintln!(
            "  check     applied force ({:.4e}, {:.4e}), reactions {}, equilibrium residual {:.1e}",
            res.applied_force[0],
            res.applied_force[1],
            reactions.join(", "),
            res.equilibrium_residual
        );
    }
    if let Some(d) = &r.dual {
        eprintln!(
            "  dual      HCT, {} unknowns: max von Mises = {:.4e}, complementary energy {:.6e} [{:.2} s]",
            d.unknowns, d.max_von_mises, d.check.complementary_energy, d.solver.seconds
        );
        eprintln!(
            "            independent check: traction {:.1e}, equilibrium {:.1e}, stress jumps {:.1e}",
            d.check.traction_residual, d.check.interior_equilibrium, d.check.stress_jump
        );
        for note in &d.notes {
            eprintln!("            note: {note}");
        }
    }
    if let Some(e) = &r.estimate {
        eprintln!(
            "  estimate  error {:.4e} = {:.3} % of the energy norm ({}), in {:.2} s of {:.2} s run time",
            e.estimate.error,
            e.estimate.relative_percent,
            if e.estimate.kind == signorini::estimate::EstimateKind::GuaranteedBound {
                "a guaranteed bound"
            } else {
                "an estimator"
            },
            e.estimate_seconds,
            e.run_seconds
        );
    }
    if let Some(c) = &r.contact {
        let worst = [
            c.residuals.max_penetration,
            c.residuals.max_wrong_sign_pressure,
            c.residuals.max_cone_violation,
            c.residuals.normal_complementarity,
            c.residuals.tangential_complementarity,
        ]
        .into_iter()
        .fold(0.0, f64::max);
        eprintln!(
            "  contact   {} on '{}' (friction {}): {} iteration(s), status changes {:?}",
            c.solver, c.part, c.friction, c.iterations, c.status_changes
        );
        eprintln!(
            "            {} points: {} open, {} stick, {} slip; contact force ({:.4e}, {:.4e}); zone {}",
            c.points,
            c.open,
            c.stick,
            c.slip,
            c.resultant[0],
            c.resultant[1],
            c.zone.map(|z| format!("[{:.4e}, {:.4e}]", z[0], z[1])).unwrap_or_else(|| "none".into())
        );
        if let Some(p) = &c.peak_pressure {
            eprintln!(
                "            peak pressure {:.4e} at ({:.4e}, {:.4e}); closed zones (arc length): {}",
                p.pressure,
                p.position[0],
                p.position[1],
                if c.zones.is_empty() {
                    "none".to_string()
                } else {
                    c.zones
                        .iter()
                        .map(|z| format!("[{:.4e}, {:.4e}]", z.extent[0], z.extent[1]))
                        .collect::<Vec<_>>()
                        .join(", ")
                }
            );
        }
        eprintln!(
            "            independent check: penetration {:.1e}, pressure sign {:.1e}, cone {:.1e}, complementarity {:.1e} / {:.1e} (worst {worst:.1e})",
            c.residuals.max_penetration,
            c.residuals.max_wrong_sign_pressure,
            c.residuals.max_cone_violation,
            c.residuals.normal_complementarity,
            c.residuals.tangential_complementarity
        );
        if c.stabilisation_iterations > 0 {
            eprintln!(
                "            held by contact: {} proximal iteration(s), residual spring force ({:.1e}, {:.1e})",
                c.stabilisation_iterations, c.stabilisation_force[0], c.stabilisation_force[1]
            );
        }
    }
    let phases: Vec<String> = r.timings.phases().iter().map(|(k, v)| format!("{k} {v:.3}")).collect();
    eprintln!(
        "  time      {} s; total {:.3} s; peak memory {}",
        phases.join(", "),
        r.timings.total(),
        r.memory.peak_bytes.map(|b| format!("{:.1} MB", b as f64 / 1e6)).unwrap_or_else(|| "n/a".into())
    );
    for w in &r.warnings {
        eprintln!("  warning   {}: {}", w.kind, w.message);
    }
    for u in &r.solver.unused_options {
        eprintln!("  warning   PETSc option {u} was never used (a typo?)");
    }
    let files: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    eprintln!("  wrote     {}", files.join(", "));
}

/// `bench elasticity`: runs every (size, solver) case in a child process of its own (so that
/// each reports its own memory) and collects their rows.
fn bench_elasticity(parsed: RunArgs) -> ExitCode {
    let out = parsed.out.clone().unwrap_or_else(|| PathBuf::from("bench"));
    let scratch = std::env::temp_dir().join(format!("signorini-bench-{}", std::process::id()));
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the signorini executable to run the cases: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut rows: Vec<bench::BenchRow> = Vec::new();
    let cases = bench::elasticity_cases(parsed.max_dofs);
    for (k, (dofs, solver)) in cases.iter().enumerate() {
        let index = bench::SOLVERS.iter().position(|s| s.name == solver.name).unwrap_or(0);
        eprint!("[{}/{}] {dofs} dofs, {:<26} ", k + 1, cases.len(), solver.name);
        let child = std::process::Command::new(&exe)
            .args(["bench", "elasticity-case", "--case", &format!("{dofs},{index}"), "--out"])
            .arg(&scratch)
            .args(&parsed.petsc)
            .output();
        match child {
            Ok(o) if o.status.success() => match serde_json::from_slice::<bench::BenchRow>(&o.stdout) {
                Ok(row) => {
                    eprintln!(
                        "{:>8.3} s, {:>5} iterations, {:>6.0} MB",
                        row.solve_seconds, row.iterations, row.solve_memory_mb
                    );
                    rows.push(row);
                }
                Err(e) => eprintln!("unreadable result: {e}"),
            },
            Ok(o) => eprintln!("failed: {}", String::from_utf8_lossy(&o.stderr).trim()),
            Err(e) => eprintln!("could not start: {e}"),
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    if rows.is_empty() {
        eprintln!("error: no benchmark case succeeded");
        return ExitCode::FAILURE;
    }
    match bench::write_elasticity_outputs(&rows, &out) {
        Ok((md, svg)) => {
            println!("{}", bench::elasticity_table(&rows));
            eprintln!("wrote {}, {}", md.display(), svg.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `bench elasticity-case --case DOFS,SOLVER`: one case, its row as JSON on stdout.
fn bench_elasticity_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench elasticity-case needs --case DOFS,SOLVER_INDEX".into()))?;
    let solver = bench::SOLVERS.get(index).ok_or_else(|| Error::Usage(format!("no benchmark solver {index}")))?;
    let scratch = args.out.clone().unwrap_or_else(std::env::temp_dir);
    let row = bench::elasticity_case(session, dofs, solver, &scratch)?;
    if session.rank() == 0 {
        println!("{}", serde_json::to_string(&row).map_err(|e| Error::Usage(e.to_string()))?);
    }
    Ok(())
}

/// Run `exe bench KIND-case --case DOFS,INDEX` and parse its JSON row.
fn run_case<T: serde::de::DeserializeOwned>(
    exe: &std::path::Path,
    kind: &str,
    dofs: usize,
    index: usize,
    out: &std::path::Path,
    petsc: &[String],
) -> Result<T, String> {
    let o = std::process::Command::new(exe)
        .args(["bench", &format!("{kind}-case"), "--case", &format!("{dofs},{index}"), "--out"])
        .arg(out)
        .args(petsc)
        .output()
        .map_err(|e| format!("could not start: {e}"))?;
    if !o.status.success() {
        return Err(format!("failed: {}", String::from_utf8_lossy(&o.stderr).trim()));
    }
    serde_json::from_slice(&o.stdout).map_err(|e| format!("unreadable result: {e}"))
}

/// Writes a benchmark's table and plot into a directory; their paths.
type Writer<T> = fn(&[T], &std::path::Path) -> Result<(PathBuf, PathBuf), Error>;

/// The parts of a benchmark run in child processes, one per (size, solver) case.
struct CaseRunner<T> {
    /// The child's subcommand is `bench {kind}-case`.
    kind: &'static str,
    /// `(dofs, solver index, solver name)` of each case.
    cases: Vec<(usize, usize, String)>,
    /// The progress line of a finished case.
    describe: fn(&T) -> String,
    table: fn(&[T]) -> String,
    write: Writer<T>,
}

/// Run every case in a child process (each reports its own memory), print progress, write the
/// table and the plot.
fn run_bench<T: serde::de::DeserializeOwned>(parsed: &RunArgs, runner: CaseRunner<T>) -> ExitCode {
    let out = parsed.out.clone().unwrap_or_else(|| PathBuf::from("bench"));
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the signorini executable to run the cases: {e}");
            return ExitCode::FAILURE;
        }
    };
    let scratch = std::env::temp_dir().join(format!("signorini-bench-{}-{}", runner.kind, std::process::id()));
    let mut rows: Vec<T> = Vec::new();
    for (k, (dofs, index, name)) in runner.cases.iter().enumerate() {
        eprint!("[{}/{}] ~{dofs} dofs, {name:<26} ", k + 1, runner.cases.len());
        match run_case::<T>(&exe, runner.kind, *dofs, *index, &scratch, &parsed.petsc) {
            Ok(row) => {
                eprintln!("{}", (runner.describe)(&row));
                rows.push(row);
            }
            Err(e) => eprintln!("{e}"),
        }
    }
    let _ = std::fs::remove_dir_all(&scratch);
    if rows.is_empty() {
        eprintln!("error: no benchmark case succeeded");
        return ExitCode::FAILURE;
    }
    match (runner.write)(&rows, &out) {
        Ok((md, svg)) => {
            println!("{}", (runner.table)(&rows));
            eprintln!("wrote {}, {}", md.display(), svg.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `bench contact`: each (size, solver) case in a child process.
fn bench_contact(parsed: RunArgs) -> ExitCode {
    let cases = bench::contact_cases(parsed.max_dofs)
        .into_iter()
        .map(|(dofs, solver)| {
            (dofs, bench::CONTACT_SOLVERS.iter().position(|s| *s == solver).unwrap_or(0), solver.to_string())
        })
        .collect();
    run_bench(
        &parsed,
        CaseRunner::<bench::ContactBenchRow> {
            kind: "contact",
            cases,
            describe: |row| {
                format!(
                    "{:>8.3} s, {:>4} iterations, {:>6.1} x one linear solve, residual {:.1e}",
                    row.contact_seconds,
                    row.iterations,
                    row.contact_seconds / row.linear_seconds,
                    row.worst_residual
                )
            },
            table: bench::contact_table,
            write: bench::write_contact_outputs,
        },
    )
}

fn bench_contact_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench contact-case needs --case DOFS,SOLVER_INDEX".into()))?;
    let solver = bench::CONTACT_SOLVERS.get(index).ok_or_else(|| Error::Usage(format!("no contact solver {index}")))?;
    let row = bench::contact_case(session, dofs, solver)?;
    if session.rank() == 0 {
        println!("{}", serde_json::to_string(&row).map_err(|e| Error::Usage(e.to_string()))?);
    }
    Ok(())
}

/// `bench dual`: each (size, solver) case in a child process.
fn bench_dual(parsed: RunArgs) -> ExitCode {
    let cases = bench::dual::dual_cases(parsed.max_dofs);
    run_bench(
        &parsed,
        CaseRunner::<bench::dual::DualBenchRow> {
            kind: "dual",
            cases,
            describe: |row| {
                format!(
                    "setup {:.3} s, solve {:.3} s ({} its), estimate {:.3} s; primal P2 {:.3} s",
                    row.setup_seconds, row.solve_seconds, row.iterations, row.estimate_seconds, row.primal_seconds
                )
            },
            table: bench::dual::dual_table,
            write: bench::write_dual_outputs,
        },
    )
}

fn bench_dual_case(session: &Session, args: RunArgs) -> Result<(), Error> {
    let (dofs, index) =
        args.case.ok_or_else(|| Error::Usage("bench dual-case needs --case DOFS,SOLVER_INDEX".into()))?;
    let solvers = bench::dual::dual_solvers();
    let solver = solvers.get(index).ok_or_else(|| Error::Usage(format!("no dual benchmark solver {index}")))?;
    let row = bench::dual::dual_case(session, dofs, solver)?;
    if session.rank() == 0 {
        println!("{}", serde_json::to_string(&row).map_err(|e| Error::Usage(e.to_string()))?);
    }
    Ok(())
}
