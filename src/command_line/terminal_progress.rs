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
}

impl TerminalProgress {
    pub fn new(enabled: bool) -> Self {
        TerminalProgress { spinner: Spinner::new(enabled), phase: Mutex::new(None) }
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
}
