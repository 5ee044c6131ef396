//! The parent side of the benchmarks: each (size, solver) case runs in a child process of its
//! own (`signorini bench KIND-case`, so that each reports its own memory); its JSON row is
//! collected, or its failure with the reason. The Markdown file carries the date, the program
//! version and commit, the command line and every failed case as a row.
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use signorini::bench::{self, BenchRecord, FailedCase};
use signorini::Error;

use super::arguments::{AccuracyArgs, BenchArgs, ScaleArgs};
use super::terminal_progress::{self, Spinner};

/// How many processes the MPI launcher started this one among (`mpirun -n N`), and this one's
/// rank, read from the launcher's environment before MPI starts (Open MPI's
/// `OMPI_COMM_WORLD_SIZE` and `OMPI_COMM_WORLD_RANK`, MPICH's and Slurm's `PMI_SIZE` and
/// `PMI_RANK`); `(1, 0)` when no launcher started it.
fn launched_processes() -> (usize, usize) {
    let read = |names: [&str; 2]| names.iter().find_map(|n| std::env::var(n).ok()?.trim().parse::<usize>().ok());
    let size = read(["OMPI_COMM_WORLD_SIZE", "PMI_SIZE"]).unwrap_or(1);
    let rank = read(["OMPI_COMM_WORLD_RANK", "PMI_RANK"]).unwrap_or(0);
    (size, rank)
}

/// `signorini bench NAME` under `mpirun -n N` (N > 1): refused before any case runs, said once
/// (by rank 0), exit status 2. Every process would run every case in child processes of its
/// own (which inherit the launcher's environment) and write the same files.
pub fn refuse_several_processes(name: &str) -> Result<(), ExitCode> {
    let (size, rank) = launched_processes();
    if size <= 1 {
        return Ok(());
    }
    let e = Error::SingleProcess {
        feature: format!("signorini bench {name}"),
        reason: format!(
            "it was started on {size} MPI processes; it runs each case in a child process of its own and measures \
             it there, and every process would run every case and write the same files"
        ),
    };
    if rank == 0 {
        eprintln!("error: {e}");
    }
    Err(ExitCode::from(2))
}

/// The reason of a case on several ranks when there is no `mpirun`.
const MPIRUN_MISSING: &str = "mpirun not found on the PATH (openmpi-bin; ./setup.sh installs it): not run";

/// `mpirun` on the PATH, if any.
fn find_mpirun() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    std::env::split_paths(&path).map(|d| d.join("mpirun")).find(|p| p.is_file())
}

/// Run `exe bench KIND-case --case DOFS,INDEX` (under `mpirun -n RANKS` when `ranks` is given)
/// and parse its JSON row; else the reason.
fn run_case<T: serde::de::DeserializeOwned>(
    exe: &Path,
    kind: &str,
    (dofs, index): (usize, usize),
    ranks: Option<usize>,
    out: &Path,
    petsc: &[String],
) -> Result<T, String> {
    let mpirun = ranks.and_then(|n| find_mpirun().map(|m| (n, m)));
    let mut command = match (ranks, mpirun) {
        // One rank without mpirun: the run is the same, serial.
        (None, _) | (Some(1), None) => std::process::Command::new(exe),
        (Some(_), None) => return Err(MPIRUN_MISSING.to_string()),
        (Some(n), Some((_, mpirun))) => {
            let mut c = std::process::Command::new(mpirun);
            // As the tests run it: more ranks than cores allowed, one thread per rank, and
            // allowed as root (containers).
            c.args(["-n", &n.to_string(), "--oversubscribe"])
                .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
                .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
            for threads in ["OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS"] {
                if std::env::var_os(threads).is_none() {
                    c.env(threads, "1");
                }
            }
            c.arg(exe);
            c
        }
    };
    let o = command
        .args(["bench", &format!("{kind}-case"), "--case", &format!("{dofs},{index}"), "--out"])
        .arg(out)
        .args(petsc)
        .output()
        .map_err(|e| format!("could not start: {e}"))?;
    if !o.status.success() {
        let stderr = String::from_utf8_lossy(&o.stderr);
        let reason = stderr.trim();
        return Err(match o.status.code() {
            Some(code) if !reason.is_empty() => format!("exit {code}: {reason}"),
            Some(code) => format!("exit {code} without a message"),
            None => format!("killed by a signal {}", if reason.is_empty() { "" } else { reason }).trim().to_string(),
        });
    }
    serde_json::from_slice(&o.stdout).map_err(|e| format!("unreadable result: {e}"))
}

/// Writes a benchmark's files (table, then the plot when a case succeeded) into a directory.
type Writer<T> = Box<dyn Fn(&[T], &BenchRecord, &Path) -> Result<Vec<PathBuf>, Error>>;

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
    /// The children's scratch directory (default: a fresh one under the system's temporary
    /// directory), removed at the end.
    scratch: Option<PathBuf>,
    /// A result that is partly a failure (rows kept, the reason a failed-case row).
    failure_of: Option<fn(&T) -> Option<String>>,
    /// The MPI ranks of a case (by its index), launched through `mpirun`; `None`: every case in
    /// one process.
    ranks_of: Option<fn(usize) -> Option<usize>>,
}

/// The command line as typed (the program by its file name), for the benchmark files.
fn command_line() -> String {
    std::env::args()
        .enumerate()
        .map(|(k, a)| {
            let a = if k == 0 {
                Path::new(&a).file_name().map_or(a.clone(), |f| f.to_string_lossy().to_string())
            } else {
                a
            };
            if a.is_empty() || a.contains(char::is_whitespace) {
                format!("'{a}'")
            } else {
                a
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// The cases whose solver `--solvers` names: each NAME selects the solver of that name (any
/// case), or else every solver whose name contains it; a NAME that selects none is a mistake.
pub fn select_cases(
    cases: Vec<(usize, usize, String)>,
    solvers: Option<&[String]>,
) -> Result<Vec<(usize, usize, String)>, String> {
    let Some(wanted) = solvers else { return Ok(cases) };
    let mut names: Vec<String> = Vec::new();
    for (_, _, name) in &cases {
        if !names.contains(name) {
            names.push(name.clone());
        }
    }
    let mut chosen: Vec<String> = Vec::new();
    for item in wanted.iter().map(|w| w.trim()).filter(|w| !w.is_empty()) {
        let item_lower = item.to_lowercase();
        let exact: Vec<String> = names.iter().filter(|n| n.to_lowercase() == item_lower).cloned().collect();
        let matching = if exact.is_empty() {
            names.iter().filter(|n| n.to_lowercase().contains(&item_lower)).cloned().collect()
        } else {
            exact
        };
        if matching.is_empty() {
            return Err(format!(
                "--solvers {item}: no solver of this benchmark (up to its --max-dofs) is named so or has it in its \
                 name; its solvers: {}",
                names.join("; ")
            ));
        }
        chosen.extend(matching);
    }
    if chosen.is_empty() {
        return Err("--solvers: give at least one solver name".into());
    }
    Ok(cases.into_iter().filter(|(_, _, name)| chosen.contains(name)).collect())
}

/// What every benchmark's parent takes from the command line.
struct BenchLine<'a> {
    out: Option<PathBuf>,
    solvers: Option<&'a [String]>,
    petsc: &'a [String],
}

impl<'a> BenchLine<'a> {
    fn of(args: &'a BenchArgs, petsc: &'a [String]) -> Self {
        BenchLine { out: args.out.clone(), solvers: args.solvers.as_deref(), petsc }
    }
}

/// Run every case, print a line per case (a spinner while it runs, on a terminal), write the
/// files. Fails when no case succeeded (the table of failures is written all the same).
fn run_bench<T: serde::de::DeserializeOwned>(line: &BenchLine, mut runner: CaseRunner<T>) -> ExitCode {
    runner.cases = match select_cases(std::mem::take(&mut runner.cases), line.solvers) {
        Ok(cases) => cases,
        Err(message) => {
            if let Some(scratch) = &runner.scratch {
                let _ = std::fs::remove_dir_all(scratch);
            }
            eprintln!("error: {message}");
            return ExitCode::from(crate::USAGE_EXIT);
        }
    };
    let out = line.out.clone().unwrap_or_else(|| PathBuf::from("bench"));
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the signorini executable to run the cases: {e}");
            return ExitCode::FAILURE;
        }
    };
    let mut record = BenchRecord::new(command_line());
    let scratch = runner.scratch.clone().unwrap_or_else(|| {
        std::env::temp_dir().join(format!("signorini-bench-{}-{}", runner.kind, std::process::id()))
    });
    let spinner = Spinner::new(terminal_progress::wanted(false));
    let mut rows: Vec<T> = Vec::new();
    for (k, (dofs, index, name)) in runner.cases.iter().enumerate() {
        let head = format!("[{}/{}] ~{dofs} dofs, {name:<26}", k + 1, runner.cases.len());
        spinner.start(head.clone());
        let ranks = runner.ranks_of.and_then(|f| f(*index));
        let result = run_case::<T>(&exe, runner.kind, (*dofs, *index), ranks, &scratch, line.petsc);
        spinner.finish();
        match result {
            Ok(row) => {
                eprintln!("{head} {}", (runner.describe)(&row));
                if let Some(reason) = runner.failure_of.and_then(|f| f(&row)) {
                    eprintln!("{head} failed: {reason}");
                    record.failures.push(FailedCase { dofs: *dofs, solver: name.clone(), reason });
                }
                rows.push(row);
            }
            Err(reason) => {
                eprintln!("{head} failed: {reason}");
                record.failures.push(FailedCase { dofs: *dofs, solver: name.clone(), reason });
            }
        }
    }
    drop(spinner);
    let _ = std::fs::remove_dir_all(&scratch);
    match (runner.write)(&rows, &record, &out) {
        Ok(paths) => {
            if !rows.is_empty() {
                println!("{}", (runner.table)(&rows));
            }
            if !record.failures.is_empty() {
                println!("Failed cases ({}):\n\n{}", record.failures.len(), record.failures_table());
            }
            let names: Vec<String> = paths.iter().map(|p| p.display().to_string()).collect();
            eprintln!("wrote {}", names.join(", "));
            if rows.is_empty() {
                eprintln!("error: no benchmark case succeeded (each failure is a row of {})", names[0]);
                return ExitCode::FAILURE;
            }
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `bench elasticity`: each (size, solver) case in a child process.
pub fn bench_elasticity(args: &BenchArgs, petsc: &[String]) -> ExitCode {
    let cases = bench::elasticity_cases(args.max_dofs.unwrap_or(1_000_000))
        .into_iter()
        .map(|(dofs, solver)| {
            (dofs, bench::SOLVERS.iter().position(|s| s.name == solver.name).unwrap_or(0), solver.name.to_string())
        })
        .collect();
    run_bench(
        &BenchLine::of(args, petsc),
        CaseRunner::<bench::BenchRow> {
            kind: "elasticity",
            cases,
            describe: |row| {
                format!(
                    "{:>8.3} s, {:>5} iterations, {:>6.0} MB",
                    row.solve_seconds, row.iterations, row.solve_memory_mb
                )
            },
            table: bench::elasticity_table,
            write: Box::new(bench::write_elasticity_outputs),
            scratch: None,
            failure_of: None,
            ranks_of: None,
        },
    )
}

/// `bench contact`: each (size, solver) case in a child process.
pub fn bench_contact(args: &BenchArgs, petsc: &[String]) -> ExitCode {
    let cases = bench::contact_cases(args.max_dofs.unwrap_or(100_000))
        .into_iter()
        .map(|(dofs, solver)| {
            (dofs, bench::CONTACT_SOLVERS.iter().position(|s| *s == solver).unwrap_or(0), solver.to_string())
        })
        .collect();
    run_bench(
        &BenchLine::of(args, petsc),
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
            write: Box::new(bench::write_contact_outputs),
            scratch: None,
            failure_of: None,
            ranks_of: None,
        },
    )
}

/// `bench dual`: each (size, solver) case in a child process.
pub fn bench_dual(args: &BenchArgs, petsc: &[String]) -> ExitCode {
    let cases = bench::dual::dual_cases(args.max_dofs.unwrap_or(100_000));
    run_bench(
        &BenchLine::of(args, petsc),
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
            write: Box::new(bench::write_dual_outputs),
            scratch: None,
            failure_of: None,
            ranks_of: None,
        },
    )
}

/// `bench accuracy [SCENE]`: the plan (levels meshed here to count their dofs) in a scratch
/// directory, then each case in a child process.
pub fn bench_accuracy(args: &AccuracyArgs, petsc: &[String]) -> ExitCode {
    use signorini::bench::accuracy::{self, AccuracyCaseResult};
    use signorini::scene::Scene;
    let scene = match &args.scene {
        Some(path) => Scene::from_file(path),
        None => Scene::from_str(accuracy::DEFAULT_SCENE_TOML, Path::new(accuracy::DEFAULT_SCENE_PATH)),
    };
    let (max_dofs, target) = (args.max_dofs.unwrap_or(20_000), args.target.unwrap_or(1.0));
    let plan = scene.and_then(|s| accuracy::plan(&s, max_dofs, target));
    let plan = match plan {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::from(if matches!(e, Error::Usage(_)) { crate::USAGE_EXIT } else { 1 });
        }
    };
    let scratch = std::env::temp_dir().join(format!("signorini-bench-accuracy-{}", std::process::id()));
    let written = std::fs::create_dir_all(&scratch).map_err(|e| e.to_string()).and_then(|_| {
        let text = serde_json::to_string(&plan).map_err(|e| e.to_string())?;
        std::fs::write(accuracy::plan_path(&scratch), text).map_err(|e| e.to_string())
    });
    if let Err(e) = written {
        eprintln!("error: cannot write the benchmark plan into {}: {e}", scratch.display());
        return ExitCode::FAILURE;
    }
    let cases = plan.cases.iter().enumerate().map(|(k, (dofs, _, name))| (*dofs, k, name.clone())).collect();
    let scene_name = plan.scene_path.display().to_string();
    run_bench(
        &BenchLine { out: args.out.clone(), solvers: args.solvers.as_deref(), petsc },
        CaseRunner::<AccuracyCaseResult> {
            kind: "accuracy",
            cases,
            describe: |r| {
                let last = r.rows.last();
                match last {
                    Some(row) if row.series == "reference" => {
                        format!("{} elements, {} dofs, {:.2} s", row.elements, row.dofs, row.run_seconds)
                    }
                    Some(row) => format!(
                        "{:>3} point(s), last: {:>7} dofs, {:>8.3} s, estimate {:>7.3} %, true {}",
                        r.rows.len(),
                        row.dofs,
                        row.cumulative_seconds,
                        row.estimate_percent,
                        row.true_percent.map_or("–".to_string(), |t| format!("{t:.3} %"))
                    ),
                    None => "no point".into(),
                }
            },
            table: accuracy::accuracy_table,
            write: Box::new(move |rows, record, dir| accuracy::write_accuracy_outputs(rows, record, dir, &scene_name)),
            scratch: Some(scratch),
            failure_of: Some(|r| r.failure.clone()),
            ranks_of: None,
        },
    )
}

/// `bench held`: the half disc driven by displacement and by force, each case in a child process.
pub fn bench_held(args: &BenchArgs, petsc: &[String]) -> ExitCode {
    let cases = bench::held::held_cases(args.max_dofs.unwrap_or(100_000));
    run_bench(
        &BenchLine::of(args, petsc),
        CaseRunner::<bench::held::HeldBenchRow> {
            kind: "held",
            cases,
            describe: |row| format!("{:>8.3} s, {:>3} Newton steps", row.contact_seconds, row.iterations),
            table: bench::held::held_table,
            write: Box::new(bench::write_held_outputs),
            scratch: None,
            failure_of: None,
            ranks_of: None,
        },
    )
}

/// `bench evolution`: each (size, path) case in a child process.
pub fn bench_evolution(args: &BenchArgs, petsc: &[String]) -> ExitCode {
    let cases = bench::evolution::evolution_cases(args.max_dofs.unwrap_or(100_000));
    run_bench(
        &BenchLine::of(args, petsc),
        CaseRunner::<bench::evolution::EvolutionBenchRow> {
            kind: "evolution",
            cases,
            describe: |row| {
                format!(
                    "path {:>7.3} s ({} increments), {:.2} linear solves, {:.2} static contact solves",
                    row.path_seconds,
                    row.increments,
                    row.path_seconds / row.linear_seconds,
                    row.path_seconds / row.static_contact_seconds
                )
            },
            table: bench::evolution::evolution_table,
            write: Box::new(bench::write_evolution_outputs),
            scratch: None,
            failure_of: None,
            ranks_of: None,
        },
    )
}

/// `bench dual-contact`: each (size, strategy) case in a child process.
pub fn bench_dual_contact(args: &BenchArgs, petsc: &[String]) -> ExitCode {
    let cases = bench::dual_contact::dual_contact_cases(args.max_dofs.unwrap_or(100_000));
    run_bench(
        &BenchLine::of(args, petsc),
        CaseRunner::<bench::dual_contact::DualContactBenchRow> {
            kind: "dual-contact",
            cases,
            describe: |row| {
                format!(
                    "primal {:.3} s, dual {:.3} s ({:.2} x), estimate {:.3} s, error {:.2} %",
                    row.primal_seconds,
                    row.dual_seconds,
                    row.dual_seconds / row.primal_seconds,
                    row.estimate_seconds,
                    row.relative_percent
                )
            },
            table: bench::dual_contact::dual_contact_table,
            write: Box::new(bench::write_dual_contact_outputs),
            scratch: None,
            failure_of: None,
            ranks_of: None,
        },
    )
}

/// `bench scale`: the contact-point cases in a child process each, the scaling cases under
/// `mpirun -n 1, 2, ...` up to the cores present.
pub fn bench_scale(args: &ScaleArgs, petsc: &[String]) -> ExitCode {
    use signorini::bench::scale::{self, Part};
    let parts: Vec<Part> = match args.part.as_deref() {
        Some("contact-points") => vec![Part::ContactPoints],
        Some("strong") => vec![Part::Strong],
        Some("weak") => vec![Part::Weak],
        _ => vec![Part::ContactPoints, Part::Strong, Part::Weak],
    };
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let cases = scale::scale_cases(&parts, args.max_dofs.unwrap_or(200_000), cores);
    let scaling = parts.iter().any(|p| *p != Part::ContactPoints);
    let note = if scaling && cores > 1 && find_mpirun().is_none() {
        format!("Runs on more than one rank: not made, {MPIRUN_MISSING}.")
    } else if scaling && cores == 1 {
        "One core present: the scaling parts have one rank only.".to_string()
    } else {
        String::new()
    };
    run_bench(
        &BenchLine { out: args.out.clone(), solvers: None, petsc },
        CaseRunner::<scale::ScaleRow> {
            kind: "scale",
            cases,
            describe: scale::describe,
            table: scale::scale_table,
            write: Box::new(move |rows, record, dir| scale::write_scale_outputs(rows, record, dir, &note)),
            scratch: None,
            failure_of: Some(scale::route_mismatch),
            ranks_of: Some(|index| (index >= 10_000).then(|| scale::case_ranks(index))),
        },
    )
}

/// `bench startup`: every measurement a child process (see [`bench::startup`]); the table on
/// stdout and in DIR/bench_startup.md.
pub fn bench_startup(runs: usize, skip_half_disc: bool, out: Option<PathBuf>) -> ExitCode {
    let out = out.unwrap_or_else(|| PathBuf::from("bench"));
    let record = BenchRecord::new(command_line());
    let result = std::env::current_exe()
        .map_err(|e| Error::Usage(format!("cannot find the signorini executable to run: {e}")))
        .and_then(|exe| {
            let scratch = std::env::temp_dir().join(format!("signorini-bench-startup-{}", std::process::id()));
            eprintln!(
                "measuring start-up ({runs} runs each){}",
                if skip_half_disc { "" } else { ", then the half disc twice" }
            );
            bench::startup::startup_bench(&exe, runs, skip_half_disc, &scratch)
        })
        .and_then(|b| {
            let table = bench::startup::startup_table(&b);
            let md = out.join("bench_startup.md");
            let text = record.markdown("Start-up and meshing", &table);
            signorini::output::write_atomically(&md, |w| w.write_all(text.as_bytes()))?;
            println!("{table}");
            eprintln!("wrote {}", md.display());
            Ok(())
        });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

#[cfg(test)]
mod tests {
    use super::select_cases;

    fn cases() -> Vec<(usize, usize, String)> {
        let names = ["newton_full", "newton", "relaxation", "MUMPS Cholesky (default)", "CG + ICC(0)", "CG + ICC(2)"];
        [1_000, 10_000]
            .iter()
            .flat_map(|&d| names.iter().enumerate().map(move |(k, n)| (d, k, n.to_string())))
            .collect()
    }

    fn chosen(solvers: &[&str]) -> Result<Vec<String>, String> {
        let solvers: Vec<String> = solvers.iter().map(|s| s.to_string()).collect();
        let picked = select_cases(cases(), Some(&solvers))?;
        Ok(picked.into_iter().filter(|c| c.0 == 1_000).map(|c| c.2).collect())
    }

    #[test]
    fn solvers_are_chosen_by_name_or_part_of_it() {
        assert_eq!(select_cases(cases(), None).unwrap().len(), 12);
        // An exact name (any case) selects that solver alone, though others contain it.
        assert_eq!(chosen(&["NEWTON"]).unwrap(), ["newton"]);
        assert_eq!(chosen(&["newton_full", "relaxation"]).unwrap(), ["newton_full", "relaxation"]);
        // Else a part of names selects all of them.
        assert_eq!(chosen(&["icc"]).unwrap(), ["CG + ICC(0)", "CG + ICC(2)"]);
        assert_eq!(chosen(&["mumps"]).unwrap(), ["MUMPS Cholesky (default)"]);
        assert_eq!(select_cases(cases(), Some(&["icc".to_string()])).unwrap().len(), 4, "every size");
        let e = chosen(&["mumps", "amg"]).unwrap_err();
        assert!(e.contains("--solvers amg") && e.contains("CG + ICC(2)"), "{e}");
        assert!(chosen(&[""]).is_err());
    }
}
