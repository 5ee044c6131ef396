//! The runner's own command line (tests/petsc_suite.rs): libtest's options keep their libtest
//! meaning, their values are not taken for name filters, and unknown options are refused.
use std::process::Command;

use signorini::petsc::Session;

use crate::{parse_args, Format};

fn parse(args: &[&str]) -> Result<crate::Options, String> {
    parse_args(&args.iter().map(|a| a.to_string()).collect::<Vec<_>>())
}

/// The names `--list` prints when the built runner is started with `args`.
fn listed(args: &[&str]) -> Result<Vec<String>, String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe).arg("--list").args(args).output().map_err(|e| e.to_string())?;
    if !out.status.success() {
        return Err(format!("--list {args:?}: exit {:?}: {}", out.status.code(), String::from_utf8_lossy(&out.stderr)));
    }
    Ok(String::from_utf8_lossy(&out.stdout)
        .lines()
        .filter_map(|l| l.strip_suffix(": test"))
        .map(String::from)
        .collect())
}

pub fn runner_parses_libtest_options(_: &Session) -> Result<(), String> {
    let all: Vec<String> = super::TESTS.iter().map(|(n, _)| n.to_string()).collect();
    // Option values are consumed, never taken for filters.
    for args in [
        &["--test-threads", "1"][..],
        &["--test-threads=1"],
        &["--format", "pretty"],
        &["--color", "never"],
        &["--color=always", "--nocapture", "--show-output", "--include-ignored"],
        &["-Z", "unstable-options"],
        &["-Zunstable-options", "--report-time"],
    ] {
        let o = parse(args)?;
        if !o.filters.is_empty() || !o.skip.is_empty() || !all.iter().all(|n| o.selects(n)) {
            return Err(format!("{args:?} must select every case: {o:?}"));
        }
    }
    let o = parse(&["-q"])?;
    if o.format != Format::Terse || parse(&["--format", "terse"])?.format != Format::Terse {
        return Err(format!("-q / --format terse: {o:?}"));
    }
    if parse(&["--test-threads", "3"])?.test_threads != Some(3) {
        return Err("--test-threads 3 not read".into());
    }
    // --skip leaves out what it names; --exact makes filters and skips whole names.
    let o = parse(&["--skip", "dual"])?;
    let kept: Vec<&String> = all.iter().filter(|n| o.selects(n)).collect();
    if kept.is_empty() || kept.iter().any(|n| n.contains("dual")) || kept.len() == all.len() {
        return Err(format!("--skip dual kept {kept:?}"));
    }
    let o = parse(&["hertz", "--skip", "dual", "--skip=full_space"])?;
    let expected: Vec<&String> =
        all.iter().filter(|n| n.contains("hertz") && !n.contains("dual") && !n.contains("full_space")).collect();
    let kept: Vec<&String> = all.iter().filter(|n| o.selects(n)).collect();
    if kept != expected || kept.is_empty() {
        return Err(format!("hertz --skip dual --skip full_space kept {kept:?}, expected {expected:?}"));
    }
    let o = parse(&["--exact", "hertz_cylinder"])?;
    let kept: Vec<&String> = all.iter().filter(|n| o.selects(n)).collect();
    if kept != [&"hertz_cylinder".to_string()] {
        return Err(format!("--exact hertz_cylinder kept {kept:?}"));
    }
    let o = parse(&["--exact", "--skip", "hertz_cylinder"])?;
    if o.selects("hertz_cylinder") || !o.selects("full_space_hertz_cylinder") {
        return Err(format!("--exact --skip hertz_cylinder: {o:?}"));
    }
    if all.iter().any(|n| parse(&["--ignored"]).unwrap().selects(n)) {
        return Err("--ignored selects nothing (the suite has no ignored case)".into());
    }
    // Refused: unknown options, missing and bad values, options the runner cannot honour.
    for args in [
        &["--no-such-option"][..],
        &["-x"],
        &["--skip"],
        &["--test-threads", "0"],
        &["--test-threads", "many"],
        &["--format", "json"],
        &["--format", "fancy"],
        &["--color", "blue"],
        &["--exact=yes"],
        &["--shuffle"],
    ] {
        if let Ok(o) = parse(args) {
            return Err(format!("{args:?} must be refused, parsed as {o:?}"));
        }
    }
    // The built runner: --list honours filters and --skip, and refuses unknown options.
    let listed_all = listed(&[])?;
    if listed_all != all {
        return Err(format!("--list printed {} names, TESTS has {}", listed_all.len(), all.len()));
    }
    let threads = listed(&["--test-threads", "1"])?;
    if threads != all {
        return Err(format!("--list --test-threads 1 printed {} of {} cases", threads.len(), all.len()));
    }
    let skipped = listed(&["--skip", "dual", "--format", "terse"])?;
    let expected: Vec<String> = all.iter().filter(|n| !n.contains("dual")).cloned().collect();
    if skipped != expected {
        return Err(format!("--list --skip dual printed {skipped:?}"));
    }
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let out = Command::new(exe).args(["--list", "--no-such-option"]).output().map_err(|e| e.to_string())?;
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.success() || !stderr.contains("unknown option") || !stderr.contains("--no-such-option") {
        return Err(format!("an unknown option must be refused: exit {:?}, {stderr}", out.status.code()));
    }
    Ok(())
}
