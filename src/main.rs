//! The `signorini` command-line program. The library never prints; this file does.
use std::path::PathBuf;
use std::process::ExitCode;

use signorini::petsc::Session;
use signorini::problem::{ElasticityProblem, Report};
use signorini::scene::Scene;
use signorini::{bench, Error};

const USAGE: &str = "\
signorini — 2D frictional contact in linear elasticity, on PETSc

usage:
  signorini run [SCENE] [--out DIR] [--quiet] [--contact-solver NAME] [PETSc options...]
      Solve the scene (a TOML file; without one, the embedded default scene) and write
      DIR/solution.vtu and DIR/report.json (DIR: --out, else the scene's [output] dir, else ./out).
      --contact-solver overrides the scene's [contact] solver: newton_full (default), newton, relaxation, dpana, uzawa,
      tresca_fixed_point, snes_vi (frictionless), tao (Tresca).
      SCENE must come before the PETSc options. Examples:
        signorini run examples/scenes/cantilever.toml -ksp_type cg -pc_type icc -pc_factor_levels 2 -ksp_monitor
        mpirun -n 2 signorini run examples/scenes/cantilever.toml
  signorini bench elasticity [--max-dofs N] [--out DIR] [PETSc options...]
      Assembly and solve times, peak memory and overhead ratios from 1e4 up to N dofs
      (default 1e6); writes DIR/bench_elasticity.md and DIR/bench_elasticity.svg (DIR default ./bench).
  signorini bench contact [--max-dofs N] [--out DIR] [PETSc options...]
      The square block (Coulomb) from 1e3 dofs up to N (default 1e5) for each contact solver:
      iterations, time, memory, and the ratio to one linear solve of the same mesh; writes
      DIR/bench_contact.md and DIR/bench_contact.svg.
  signorini --help | --version

PETSc options: any option PETSc knows (-ksp_type, -pc_type, -pc_factor_levels, -ksp_monitor,
-ksp_view, -log_view, ...) applies to the main linear solver; scene [solver] petsc_options are
defaults that the command line overrides.";

struct RunArgs {
    scene: Option<PathBuf>,
    out: Option<PathBuf>,
    quiet: bool,
    max_dofs: usize,
    /// bench elasticity-case: the size and the solver index.
    case: Option<(usize, usize)>,
    /// run: override of the scene's [contact] solver.
    contact_solver: Option<String>,
    petsc: Vec<String>,
}

fn parse(args: &[String], allow_scene: bool) -> Result<RunArgs, Error> {
    let mut r = RunArgs {
        scene: None,
        out: None,
        quiet: false,
        max_dofs: 1_000_000,
        case: None,
        contact_solver: None,
        petsc: Vec::new(),
    };
    let mut i = 0;
    while i < args.len() {
        let a = &args[i];
        match a.as_str() {
            "--contact-solver" => {
                let v = args.get(i + 1).filter(|v| !v.starts_with('-')).ok_or_else(|| {
                    Error::Usage("--contact-solver needs a solver name (see signorini --help)".into())
                })?;
                r.contact_solver = Some(v.clone());
                i += 2;
            }
            "--out" | "--max-dofs" => {
                let v = args
                    .get(i + 1)
                    .filter(|v| !v.starts_with('-'))
                    .ok_or_else(|| Error::Usage(format!("{a} needs a value (see signorini --help)")))?;
                if a == "--out" {
                    r.out = Some(PathBuf::from(v));
                } else {
                    r.max_dofs = v
                        .parse::<f64>()
                        .ok()
                        .filter(|x| *x >= 1.0 && x.is_finite())
                        .ok_or_else(|| Error::Usage(format!("--max-dofs expects a positive number, got {v:?}")))?
                        as usize;
                }
                i += 2;
            }
            "--case" => {
                let parse_case = |v: &str| -> Option<(usize, usize)> {
                    let (d, k) = v.split_once(',')?;
                    Some((d.parse().ok()?, k.parse().ok()?))
                };
                r.case = Some(
                    args.get(i + 1)
                        .and_then(|v| parse_case(v))
                        .ok_or_else(|| Error::Usage("--case needs DOFS,SOLVER_INDEX".into()))?,
                );
                i += 2;
            }
            "--quiet" => {
                r.quiet = true;
                i += 1;
            }
            s if s.starts_with("--") => {
                return Err(Error::Usage(format!(
                    "unknown flag {s} (PETSc options take one dash; see signorini --help)"
                )))
            }
            s if s.starts_with('-') => {
                r.petsc.push(s.to_string());
                i += 1;
                // The option's value, if any, follows: anything that is not another option name.
                if let Some(v) = args.get(i) {
                    let is_name =
                        v.starts_with('-') && v[1..].starts_with(|c: char| c.is_ascii_alphabetic() || c == '_');
                    if !is_name && v.ends_with(".toml") {
                        return Err(Error::Usage(format!(
                            "{v:?} follows the PETSc option {a}: the scene file comes first, before PETSc options"
                        )));
                    }
                    if !is_name {
                        r.petsc.push(v.clone());
                        i += 1;
                    }
                }
            }
            s => {
                if allow_scene && r.scene.is_none() && r.petsc.is_empty() {
                    r.scene = Some(PathBuf::from(s));
                    i += 1;
                } else {
                    return Err(Error::Usage(format!(
                        "unexpected argument {s:?}: the scene file comes first, before PETSc options (see signorini --help)"
                    )));
                }
            }
        }
    }
    Ok(r)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().collect();
    let program = args.first().cloned().unwrap_or_else(|| "signorini".into());
    match args.get(1).map(String::as_str) {
        None | Some("--help") | Some("-h") | Some("help") => {
            println!("{USAGE}");
            ExitCode::SUCCESS
        }
        Some("--version") | Some("-V") => {
            println!("signorini {}", env!("CARGO_PKG_VERSION"));
            ExitCode::SUCCESS
        }
        Some("run") => with_session(&program, &args[2..], true, run),
        Some("bench") => match args.get(2).map(String::as_str) {
            Some("elasticity") => bench_elasticity(&args[3..]),
            Some("elasticity-case") => with_session(&program, &args[3..], false, bench_elasticity_case),
            Some("contact") => bench_contact(&args[3..]),
            Some("contact-case") => with_session(&program, &args[3..], false, bench_contact_case),
            other => usage_error(&format!(
                "bench needs a benchmark name: `signorini bench elasticity` or `signorini bench contact` (got {})",
                other.map(|o| format!("{o:?}")).unwrap_or_else(|| "nothing".into())
            )),
        },
        Some(other) => {
            usage_error(&format!("unknown command {other:?}: use `signorini run` or `signorini bench` (see --help)"))
        }
    }
}

fn usage_error(message: &str) -> ExitCode {
    eprintln!("error: {message}");
    ExitCode::from(2)
}

fn with_session(
    program: &str,
    args: &[String],
    allow_scene: bool,
    job: fn(&Session, RunArgs) -> Result<(), Error>,
) -> ExitCode {
    let parsed = match parse(args, allow_scene) {
        Ok(p) => p,
        Err(e) => return usage_error(&e.to_string()),
    };
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
    let scene = match &args.scene {
        Some(path) => Scene::from_file(path)?,
        None => Scene::default_scene(),
    };
    let mut scene = scene;
    if let Some(name) = &args.contact_solver {
        override_contact_solver(&mut scene, name)?;
    }
    let out = args.out.clone().or_else(|| scene.output_dir.clone()).unwrap_or_else(|| PathBuf::from("out"));
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
    problem.assemble()?;
    say(&format!("  assemble  [{:.2} s]", problem.timings.get("assemble").unwrap_or(0.0)));
    problem.solve()?;
    problem.postprocess()?;
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
    let candidates =
        [S::Newton, S::Relaxation { omega: 1.0 }, S::DPana, S::Uzawa, S::TrescaFixedPoint, S::SnesVi, S::Tao];
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
    eprintln!(
        "  result    max |u| = {:.4e}, max von Mises = {:.4e}",
        r.results.max_displacement, r.results.max_von_mises
    );
    let reactions: Vec<String> =
        r.results.reactions.iter().map(|(k, v)| format!("{k} ({:.4e}, {:.4e})", v[0], v[1])).collect();
    eprintln!(
        "  check     applied force ({:.4e}, {:.4e}), reactions {}, equilibrium residual {:.1e}",
        r.results.applied_force[0],
        r.results.applied_force[1],
        reactions.join(", "),
        r.results.equilibrium_residual
    );
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
    for u in &r.solver.unused_options {
        eprintln!("  warning   PETSc option {u} was never used (a typo?)");
    }
    let files: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
    eprintln!("  wrote     {}", files.join(", "));
}

/// `bench elasticity`: runs every (size, solver) case in a child process of its own (so that
/// each reports its own memory) and collects their rows.
fn bench_elasticity(args: &[String]) -> ExitCode {
    let parsed = match parse(args, false) {
        Ok(p) => p,
        Err(e) => return usage_error(&e.to_string()),
    };
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

/// `bench contact`: each (size, solver) case in a child process.
fn bench_contact(args: &[String]) -> ExitCode {
    let mut parsed = match parse(args, false) {
        Ok(p) => p,
        Err(e) => return usage_error(&e.to_string()),
    };
    if !args.iter().any(|a| a == "--max-dofs") {
        parsed.max_dofs = 100_000;
    }
    let out = parsed.out.clone().unwrap_or_else(|| PathBuf::from("bench"));
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the signorini executable to run the cases: {e}");
            return ExitCode::FAILURE;
        }
    };
    let scratch = std::env::temp_dir().join(format!("signorini-bench-contact-{}", std::process::id()));
    let cases = bench::contact_cases(parsed.max_dofs);
    let mut rows: Vec<bench::ContactBenchRow> = Vec::new();
    for (k, (dofs, solver)) in cases.iter().enumerate() {
        let index = bench::CONTACT_SOLVERS.iter().position(|s| s == solver).unwrap_or(0);
        eprint!("[{}/{}] ~{dofs} dofs, {:<20} ", k + 1, cases.len(), solver);
        match run_case::<bench::ContactBenchRow>(&exe, "contact", *dofs, index, &scratch, &parsed.petsc) {
            Ok(row) => {
                eprintln!(
                    "{:>8.3} s, {:>4} iterations, {:>6.1} x one linear solve, residual {:.1e}",
                    row.contact_seconds,
                    row.iterations,
                    row.contact_seconds / row.linear_seconds,
                    row.worst_residual
                );
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
    match bench::write_contact_outputs(&rows, &out) {
        Ok((md, svg)) => {
            println!("{}", bench::contact_table(&rows));
            eprintln!("wrote {}, {}", md.display(), svg.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
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
