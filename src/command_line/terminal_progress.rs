//! Progress on the terminal: an `indicatif` spinner on stderr for work that lasts more than
//! [`DELAY`] (meshing, factorisation and solve, the contact Newton steps with their residuals,
//! benchmark cases). Drawn only when stderr is a terminal and `--quiet` is not given, so piped
//! output and report files never hold escape codes; cleared when its work ends. The delay can
//! be set in milliseconds with the environment variable `SIGNORINI_PROGRESS_DELAY_MS` (the
//! tests use 0).
use std::io::IsTerminal as _;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use signorini::evolution::StepRecord;
use signorini::problem::{Phase, Progress};

/// Work shorter than this shows no spinner (unless `SIGNORINI_PROGRESS_DELAY_MS` says else).
const DELAY: Duration = Duration::from_millis(1000);

fn delay() -> Duration {
    std::env::var("SIGNORINI_PROGRESS_DELAY_MS")
        .ok()
        .and_then(|v| v.trim().parse().ok())
        .map_or(DELAY, Duration::from_millis)
}
/// Redraw period of a visible spinner.
const TICK: Duration = Duration::from_millis(100);

/// May progress be drawn? Only on a terminal, and not with `--quiet`.
pub fn wanted(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

struct Current {
    bar: ProgressBar,
    since: Instant,
    shown: bool,
}

type Shared = Arc<Mutex<Option<Current>>>;

/// A spinner on stderr that appears once its task has lasted [`DELAY`]. Does nothing when
/// disabled.
pub struct Spinner {
    current: Option<Shared>,
    stop: Arc<AtomicBool>,
    ticker: Option<JoinHandle<()>>,
}

impl Spinner {
    pub fn new(enabled: bool) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        if !enabled {
            return Spinner { current: None, stop, ticker: None };
        }
        let current: Shared = Arc::new(Mutex::new(None));
        let (shared, halt, delay) = (current.clone(), stop.clone(), delay());
        let ticker = std::thread::spawn(move || {
            while !halt.load(Ordering::Relaxed) {
                std::thread::sleep(TICK);
                let mut guard = shared.lock().unwrap_or_else(PoisonError::into_inner);
                if let Some(c) = guard.as_mut() {
                    if !c.shown && c.since.elapsed() >= delay {
                        c.bar.set_draw_target(ProgressDrawTarget::stderr());
                        c.shown = true;
                    }
                    if c.shown {
                        c.bar.tick();
                    }
                }
            }
        });
        Spinner { current: Some(current), stop, ticker: Some(ticker) }
    }

    fn with<T>(&self, f: impl FnOnce(&mut Option<Current>) -> T) -> Option<T> {
        self.current.as_ref().map(|c| f(&mut c.lock().unwrap_or_else(PoisonError::into_inner)))
    }

    /// A new task (the previous one, if any, is cleared).
    pub fn start(&self, message: String) {
        self.with(|current| {
            if let Some(old) = current.take() {
                old.bar.finish_and_clear();
            }
            let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden());
            if let Ok(style) = ProgressStyle::with_template("{spinner} [{elapsed}] {wide_msg}") {
                bar.set_style(style);
            }
            bar.set_message(message);
            *current = Some(Current { bar, since: Instant::now(), shown: false });
        });
    }

    /// What the current task is doing now.
    pub fn set_message(&self, message: String) {
        self.with(|current| {
            if let Some(c) = current.as_ref() {
                c.bar.set_message(message);
            }
        });
    }

    /// Print `line` on stderr above the spinner (which is redrawn after it); nothing when
    /// disabled.
    pub fn print_line(&self, line: &str) {
        self.with(|current| match current.as_ref() {
            Some(c) if c.shown => c.bar.suspend(|| eprintln!("{line}")),
            _ => eprintln!("{line}"),
        });
    }

    /// The current task ended: its spinner disappears.
    pub fn finish(&self) {
        self.with(|current| {
            if let Some(c) = current.take() {
                c.bar.finish_and_clear();
            }
        });
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        self.finish();
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.ticker.take() {
            let _ = t.join();
        }
    }
}

/// The library's progress events drawn as a spinner: the phase, the contact solver's remarks
/// and each Newton step with its residual.
pub struct TerminalProgress {
    spinner: Spinner,
    phase: Mutex<Option<Phase>>,
    /// The unit of forces in the increment lines: "N/m" (plane) or "N" (axisymmetric).
    force_unit: &'static str,
}

impl TerminalProgress {
    pub fn new(enabled: bool) -> Self {
        TerminalProgress { spinner: Spinner::new(enabled), phase: Mutex::new(None), force_unit: "N/m" }
    }

    /// The same, with forces in `unit` ("N" for a body of revolution).
    pub fn with_force_unit(self, unit: &'static str) -> Self {
        TerminalProgress { force_unit: unit, ..self }
    }

    fn phase_name(&self) -> &'static str {
        self.phase.lock().unwrap_or_else(PoisonError::into_inner).map_or("", Phase::name)
    }
}

fn describe(phase: Phase) -> &'static str {
    match phase {
        Phase::Mesh => "meshing",
        Phase::Assemble => "assembling",
        Phase::Solve => "solving (factorisation and solve)",
        Phase::Postprocess => "stresses, reactions and checks",
        Phase::Dual => "dual solve",
        Phase::Estimate => "error estimate",
        Phase::Output => "writing results",
    }
}

impl Progress for TerminalProgress {
    fn phase_started(&self, phase: Phase) {
        *self.phase.lock().unwrap_or_else(PoisonError::into_inner) = Some(phase);
        self.spinner.start(describe(phase).to_string());
    }

    fn phase_finished(&self, _phase: Phase, _seconds: f64) {
        self.spinner.finish();
    }

    fn iteration(&self, _phase: Phase, step: usize, residual: f64) {
        self.spinner.set_message(format!("contact iteration {step}, residual {residual:.2e}"));
    }

    fn note(&self, text: &str) {
        self.spinner.set_message(format!("{}: {}", self.phase_name(), text.trim()));
    }

    fn increment_finished(&self, step: &StepRecord, total: usize) {
        self.spinner.print_line(&increment_line(step, total, self.force_unit));
    }
}

/// Decimal digits of `n`.
fn digits(n: usize) -> usize {
    n.max(1).ilog10() as usize + 1
}

/// A time with 6 significant digits at most and no trailing zeros (`0.075`, not
/// `0.07500000000000001`), e-notation outside `[1e-4, 1e6)`.
fn short_time(t: f64) -> String {
    let rounded: f64 = format!("{t:.5e}").parse().unwrap_or(t);
    if rounded == 0.0 || (1e-4..1e6).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// The line of a converged increment, its columns aligned from one increment of the path to
/// the next: `increment  3/40  t = 0.075     Q = -1.234e3 N/m  stick/slip/open 12/ 4/30 …`
/// (`unit`: "N/m", or "N" for a body of revolution).
/// The counts are `closed/open` where closed points have no friction, and all four where both
/// kinds are closed; cut increments say how many times they were halved.
pub fn increment_line(step: &StepRecord, total: usize, unit: &str) -> String {
    let width = digits(total.max(step.step));
    let points = digits(step.open + step.stick + step.slip + step.closed);
    let (names, counts) = match (step.closed > 0, step.stick + step.slip > 0) {
        (false, _) => ("stick/slip/open", vec![step.stick, step.slip, step.open]),
        (true, false) => ("closed/open", vec![step.closed, step.open]),
        (true, true) => ("stick/slip/closed/open", vec![step.stick, step.slip, step.closed, step.open]),
    };
    let counts: Vec<String> = counts.iter().map(|c| format!("{c:>points$}")).collect();
    let mut line = format!(
        "increment {:>width$}/{total}  t = {:<9}  Q = {:>9} {unit:<3}  {names} {}  {:>3} iterations  residual {:<8}  {:>7.2} s",
        step.step,
        short_time(step.time),
        format!("{:.3e}", step.tangential_resultant),
        counts.join("/"),
        step.iterations,
        format!("{:.1e}", step.worst_residual),
        step.seconds,
    );
    match step.halvings {
        0 => {}
        1 => line.push_str("  (halved once)"),
        n => line.push_str(&format!("  (halved {n} times)")),
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(step: usize, stick: usize, slip: usize, closed: usize, open: usize) -> StepRecord {
        StepRecord {
            step,
            time: step as f64 * 0.025,
            halvings: 0,
            contact_resultant: [0.0, 0.0],
            normal_resultant: -2e6,
            tangential_resultant: if step.is_multiple_of(2) { -1234.5 } else { 5.0e5 },
            open,
            stick,
            slip,
            closed,
            iterations: step % 12 + 1,
            worst_residual: 3.2e-11 * 10f64.powi(step as i32 % 3),
            dissipation: 0.0,
            total_dissipation: 0.0,
            work: 0.0,
            stored_energy: 0.0,
            monitor_displacement: 0.0,
            estimate_percent: None,
            seconds: 0.08 * step as f64,
        }
    }

    #[test]
    fn increment_lines_say_what_converged() {
        let line = increment_line(&record(3, 12, 4, 0, 30), 40, "N/m");
        assert_eq!(
            line,
            "increment  3/40  t = 0.075      Q =   5.000e5 N/m  stick/slip/open 12/ 4/30    4 iterations  residual \
             3.2e-11      0.24 s"
        );
        let mut cut = record(7, 0, 0, 20, 26);
        cut.halvings = 2;
        let line = increment_line(&cut, 9, "N/m");
        assert!(line.contains("closed/open 20/26"), "{line}");
        assert!(line.ends_with("  (halved 2 times)"), "{line}");
        let mixed = increment_line(&record(1, 3, 2, 5, 0), 1, "N/m");
        assert!(mixed.contains("stick/slip/closed/open  3/ 2/ 5/ 0"), "{mixed}");
        assert!(!line.contains('\u{1b}') && !mixed.contains('\u{1b}'), "no escape codes");
    }

    #[test]
    fn increment_lines_are_aligned() {
        // Steps of 1 to 3 digits, counts of 1 and 2 digits, residuals of both exponent widths.
        let lines: Vec<String> = [1, 2, 9, 10, 99, 100, 120]
            .iter()
            .map(|&k| increment_line(&record(k, k % 17, 3, 0, 60 - k % 17 - 3), 120, "N/m"))
            .collect();
        for marker in ["t = ", "Q = ", "stick/slip/open", "iterations", "residual", " s"] {
            let columns: Vec<usize> = lines.iter().map(|l| l.find(marker).unwrap()).collect();
            assert!(columns.iter().all(|c| *c == columns[0]), "{marker:?} at {columns:?}:\n{}", lines.join("\n"));
        }
        assert!(lines.iter().all(|l| l.len() == lines[0].len()), "{}", lines.join("\n"));
    }

    #[test]
    fn times_are_short() {
        assert_eq!(short_time(0.07500000000000001), "0.075");
        assert_eq!(short_time(1.0), "1");
        assert_eq!(short_time(2.5e-7), "2.5e-7");
    }
}
