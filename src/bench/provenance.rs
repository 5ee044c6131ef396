//! What every benchmark file says about itself: when it was run (UTC), by which program
//! (version and git commit, "unknown" outside a git checkout), with which command line, and
//! each case that failed with its reason, so that no case is ever dropped silently.
use std::time::{SystemTime, UNIX_EPOCH};

/// A benchmark case that did not produce a row.
#[derive(Debug, Clone, PartialEq)]
pub struct FailedCase {
    /// The size asked for (dofs).
    pub dofs: usize,
    /// The solver or strategy.
    pub solver: String,
    /// Why it produced no row.
    pub reason: String,
}

/// The provenance of a benchmark run and its failed cases.
#[derive(Debug, Clone, PartialEq)]
pub struct BenchRecord {
    /// `YYYY-MM-DD HH:MM:SS UTC` of the start of the run.
    pub date: String,
    /// The program's version.
    pub version: String,
    /// `git rev-parse --short HEAD` at build time (`-modified` with uncommitted changes).
    pub commit: String,
    /// The command line of the run.
    pub command_line: String,
    /// The cases that produced no row.
    pub failures: Vec<FailedCase>,
}

impl BenchRecord {
    /// A record dated now, for this program, run as `command_line`.
    pub fn new(command_line: String) -> Self {
        let seconds = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
        BenchRecord {
            date: utc_date_time(seconds),
            version: env!("CARGO_PKG_VERSION").to_string(),
            commit: env!("SIGNORINI_COMMIT").to_string(),
            command_line,
            failures: Vec::new(),
        }
    }

    /// The Markdown file: title, provenance, the table, then the failed cases (if any).
    pub fn markdown(&self, title: &str, table: &str) -> String {
        let mut s = format!(
            "# {title}\n\n- date: {}\n- program: signorini {} (commit {})\n- command: `{}`\n\n{table}",
            self.date,
            self.version,
            self.commit,
            self.command_line.replace('`', "'")
        );
        if !self.failures.is_empty() {
            s.push_str(&format!("\nFailed cases ({}):\n\n", self.failures.len()));
            s.push_str(&self.failures_table());
        }
        s
    }

    /// One row per failed case: `| dofs | solver | reason |`.
    pub fn failures_table(&self) -> String {
        let mut s = String::from("| dofs | solver | failed: reason |\n|---:|---|---|\n");
        for f in &self.failures {
            s.push_str(&format!("| {} | {} | {} |\n", f.dofs, cell(&f.solver), cell(&f.reason)));
        }
        s
    }
}

/// Text as one Markdown table cell: on one line, `|` escaped.
fn cell(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ").replace('|', "\\|")
}

/// `YYYY-MM-DD HH:MM:SS UTC` of a Unix time (the proleptic Gregorian calendar; H. Hinnant's
/// days-to-civil algorithm).
pub fn utc_date_time(unix_seconds: u64) -> String {
    let days = (unix_seconds / 86_400) as i64;
    let rest = unix_seconds % 86_400;
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC", rest / 3600, rest % 3600 / 60, rest % 60)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_of_known_instants() {
        assert_eq!(utc_date_time(0), "1970-01-01 00:00:00 UTC");
        assert_eq!(utc_date_time(951_782_400), "2000-02-29 00:00:00 UTC");
        assert_eq!(utc_date_time(1_700_000_000), "2023-11-14 22:13:20 UTC");
    }

    #[test]
    fn failures_are_rows_on_one_line() {
        let mut r = BenchRecord::new("signorini bench contact".into());
        r.failures.push(FailedCase { dofs: 100, solver: "uzawa".into(), reason: "error: a | b\nmore".into() });
        let md = r.markdown("T", "| a |\n|---|\n| 1 |\n");
        assert!(md.contains("| 100 | uzawa | error: a \\| b more |"), "{md}");
        assert!(md.contains("- command: `signorini bench contact`"));
        assert!(md.contains(&format!("commit {}", env!("SIGNORINI_COMMIT"))));
    }
}
