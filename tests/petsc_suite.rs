//! Tests that touch PETSc, all in ONE process with ONE PETSc session (initialising MPI twice in
//! a process aborts). `harness = false`: this file is its own runner; it prints libtest-style
//! lines and a closing `test result:` line, and exits non-zero on failure.
//! Run one test: `cargo test --release --test petsc_suite -- NAME_SUBSTRING`.
//!
//! The runner takes libtest's command line, so that `cargo test -- OPTIONS` means the same here
//! as in the other test crates: positional arguments are name filters (substrings, or whole
//! names with `--exact`), `--skip FILTER` leaves out the matching cases, `--list` lists the
//! selected cases, `-q`/`--format terse` prints one character per case, and the options that
//! take a value (`--test-threads N`, `--color WHEN`, `--format FMT`, `--logfile PATH`, `-Z FLAG`,
//! also as `--option=value`) consume it instead of taking it for a filter. `--test-threads` is
//! accepted and checked, but the cases always run one after the other (one PETSc session).
//! An unknown option, a missing or bad value, or a libtest option this runner cannot honour
//! (`--format json|junit`, `--shuffle`, `--ensure-time`) is refused with exit code 101 (as
//! libtest refuses bad arguments). The case `runner_parses_libtest_options` tests this parser.
mod petsc_cases;

use std::io::Write;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use signorini::petsc::Session;

/// How the runner prints its results (`--format`, `-q`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// One line per case (the default).
    Pretty,
    /// One character per case (`.` passed, `F` failed).
    Terse,
}

/// The runner's command line, with libtest's meaning.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Options {
    /// Positional name filters: a case runs when its name contains one of them (equals one of
    /// them with `exact`); no filter selects every case.
    pub filters: Vec<String>,
    /// `--skip`: cases whose name contains one of these (equals one, with `exact`) are left out.
    pub skip: Vec<String>,
    /// `--exact`: filters and skips match whole names.
    pub exact: bool,
    /// `--list`: print the selected cases and run nothing.
    pub list: bool,
    /// `--ignored` or `--bench`: run only ignored cases or benchmarks, of which the suite has none.
    pub none_selected: bool,
    pub format: Format,
    /// `--test-threads N` (checked; the cases run one after the other in any case).
    pub test_threads: Option<usize>,
    /// `--logfile PATH`: one line `ok NAME` or `failed NAME` per case.
    pub logfile: Option<String>,
    /// `-h`/`--help`.
    pub help: bool,
}

pub const USAGE: &str = "Usage: petsc_suite [OPTIONS] [FILTERS...]\n\
    libtest's options: --skip FILTER, --exact, --list, -q/--quiet, --format pretty|terse,\n\
    --color auto|always|never, --test-threads N (the cases run one at a time), --logfile PATH,\n\
    --nocapture/--no-capture, --show-output, --include-ignored, --ignored, --test, --bench,\n\
    --exclude-should-panic, --force-run-in-process, --report-time, -Z FLAG, -h/--help.";

/// Parse libtest's command line (`args` without the program name).
pub fn parse_args(args: &[String]) -> Result<Options, String> {
    let mut o = Options {
        filters: Vec::new(),
        skip: Vec::new(),
        exact: false,
        list: false,
        none_selected: false,
        format: Format::Pretty,
        test_threads: None,
        logfile: None,
        help: false,
    };
    let mut k = 0;
    while k < args.len() {
        let arg = &args[k];
        k += 1;
        if !arg.starts_with('-') || arg == "-" {
            o.filters.push(arg.clone());
            continue;
        }
        // `--name=value` or `--name value` (and `-Zflag` / `-Z flag`).
        let (name, inline) = match arg.split_once('=') {
            Some((n, v)) if arg.starts_with("--") => (n.to_string(), Some(v.to_string())),
            _ if arg.starts_with("-Z") && arg.len() > 2 => ("-Z".to_string(), Some(arg[2..].to_string())),
            _ => (arg.clone(), None),
        };
        const WITH_VALUE: &[&str] =
            &["--skip", "--test-threads", "--format", "--color", "--logfile", "-Z", "--shuffle-seed"];
        let value = if WITH_VALUE.contains(&name.as_str()) {
            match inline {
                Some(v) => Some(v),
                None if k < args.len() => {
                    k += 1;
                    Some(args[k - 1].clone())
                }
                None => return Err(format!("option {name} needs a value\n{USAGE}")),
            }
        } else if inline.is_some() {
            return Err(format!("option {name} takes no value (got {arg:?})\n{USAGE}"));
        } else {
            None
        };
        match name.as_str() {
            "--skip" => o.skip.extend(value),
            "--exact" => o.exact = true,
            "--list" => o.list = true,
            "-q" | "--quiet" => o.format = Format::Terse,
            "--format" => {
                o.format = match value.as_deref() {
                    Some("pretty") => Format::Pretty,
                    Some("terse") => Format::Terse,
                    Some(v @ ("json" | "junit")) => {
                        return Err(format!("--format {v} is not supported by this runner (pretty or terse)"))
                    }
                    Some(v) => return Err(format!("--format {v}: expected pretty or terse\n{USAGE}")),
                    None => unreachable!(),
                }
            }
            "--color" => match value.as_deref() {
                Some("auto" | "always" | "never") => {} // the runner prints no colour
                Some(v) => return Err(format!("--color {v}: expected auto, always or never\n{USAGE}")),
                None => unreachable!(),
            },
            "--test-threads" => match value.as_deref().map(str::parse::<usize>) {
                Some(Ok(n)) if n > 0 => o.test_threads = Some(n),
                _ => return Err(format!("--test-threads {}: expected a positive integer", value.unwrap_or_default())),
            },
            "--logfile" => o.logfile = value,
            "-Z" => {} // unstable libtest flags: nothing here depends on them
            "--ignored" | "--bench" => o.none_selected = true,
            // Output is never captured; ignored and should-panic cases do not exist; every
            // case already runs in this process and prints its time.
            "--include-ignored"
            | "--test"
            | "--nocapture"
            | "--no-capture"
            | "--show-output"
            | "--exclude-should-panic"
            | "--force-run-in-process"
            | "--report-time" => {}
            "-h" | "--help" => o.help = true,
            "--shuffle" | "--shuffle-seed" | "--ensure-time" => {
                return Err(format!("{name} is not supported by this runner (the cases run in their listed order)"))
            }
            _ => return Err(format!("unknown option {arg:?}\n{USAGE}")),
        }
    }
    Ok(o)
}

impl Options {
    fn matches(&self, name: &str, pattern: &str) -> bool {
        if self.exact {
            name == pattern
        } else {
            name.contains(pattern)
        }
    }

    /// Whether the case `name` runs.
    pub fn selects(&self, name: &str) -> bool {
        !self.none_selected
            && (self.filters.is_empty() || self.filters.iter().any(|f| self.matches(name, f)))
            && !self.skip.iter().any(|s| self.matches(name, s))
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let options = match parse_args(&args) {
        Ok(o) => o,
        Err(msg) => {
            eprintln!("error: {msg}");
            std::process::exit(101);
        }
    };
    if options.help {
        println!("{USAGE}");
        return;
    }
    let selected: Vec<_> = petsc_cases::TESTS.iter().filter(|(name, _)| options.selects(name)).collect();
    if options.list {
        for (name, _) in &selected {
            println!("{name}: test");
        }
        if options.format == Format::Pretty {
            println!("\n{} tests, 0 benchmarks", selected.len());
        }
        return;
    }
    let mut log = options.logfile.as_ref().map(|path| {
        std::fs::File::create(path).unwrap_or_else(|e| {
            eprintln!("error: --logfile {path}: {e}");
            std::process::exit(101);
        })
    });
    let session = Session::init(&["petsc_suite".to_string()]).expect("PETSc session");
    println!("\nrunning {} tests", selected.len());
    let start = Instant::now();
    let (mut passed, mut failed) = (0, Vec::new());
    for (name, test) in &selected {
        let t = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| test(&session)));
        let failure = match outcome {
            Ok(Ok(())) => None,
            Ok(Err(msg)) => Some(format!("FAILED\n    {msg}")),
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                Some(format!("FAILED (panicked)\n    {msg}"))
            }
        };
        if let Some(file) = log.as_mut() {
            let _ = writeln!(file, "{} {name}", if failure.is_none() { "ok" } else { "failed" });
        }
        match (&failure, options.format) {
            (None, Format::Pretty) => println!("test {name} ... ok ({:.2} s)", t.elapsed().as_secs_f64()),
            (None, Format::Terse) => print!("."),
            (Some(msg), Format::Pretty) => println!("test {name} ... {msg}"),
            (Some(msg), Format::Terse) => {
                print!("F");
                eprintln!("\ntest {name} ... {msg}");
            }
        }
        let _ = std::io::stdout().flush();
        match failure {
            None => passed += 1,
            Some(_) => failed.push(name.to_string()),
        }
    }
    if options.format == Format::Terse {
        println!();
    }
    drop(session);
    let filtered = petsc_cases::TESTS.len() - selected.len();
    if !failed.is_empty() {
        println!("\nfailures:");
        for f in &failed {
            println!("    {f}");
        }
    }
    println!(
        "\ntest result: {}. {} passed; {} failed; 0 ignored; 0 measured; {} filtered out; finished in {:.2}s\n",
        if failed.is_empty() { "ok" } else { "FAILED" },
        passed,
        failed.len(),
        filtered,
        start.elapsed().as_secs_f64()
    );
    if !failed.is_empty() {
        std::process::exit(101);
    }
}
