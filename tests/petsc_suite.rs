//! Tests that touch PETSc, all in ONE process with ONE PETSc session (initialising MPI twice in
//! a process aborts). `harness = false`: this file is its own runner; it prints libtest-style
//! lines and a closing `test result:` line, and exits non-zero on failure.
//! Run one test: `cargo test --release --test petsc_suite -- NAME_SUBSTRING`.
mod petsc_cases;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::Instant;

use signorini::petsc::Session;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "--list") {
        for (name, _) in petsc_cases::TESTS {
            println!("{name}: test");
        }
        return;
    }
    let filters: Vec<&String> = args.iter().filter(|a| !a.starts_with('-')).collect();
    let exact = args.iter().any(|a| a == "--exact");
    let selected: Vec<_> = petsc_cases::TESTS
        .iter()
        .filter(|(name, _)| {
            filters.is_empty() || filters.iter().any(|f| if exact { name == f } else { name.contains(f.as_str()) })
        })
        .collect();
    let session = Session::init(&["petsc_suite".to_string()]).expect("PETSc session");
    println!("\nrunning {} tests", selected.len());
    let start = Instant::now();
    let (mut passed, mut failed) = (0, Vec::new());
    for (name, test) in &selected {
        let t = Instant::now();
        let outcome = catch_unwind(AssertUnwindSafe(|| test(&session)));
        match outcome {
            Ok(Ok(())) => {
                passed += 1;
                println!("test {name} ... ok ({:.2} s)", t.elapsed().as_secs_f64());
            }
            Ok(Err(msg)) => {
                println!("test {name} ... FAILED\n    {msg}");
                failed.push(name.to_string());
            }
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_default();
                println!("test {name} ... FAILED (panicked)\n    {msg}");
                failed.push(name.to_string());
            }
        }
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
