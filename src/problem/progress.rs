//! Progress of a run, for whoever shows it. The library never prints: the driver tells an
//! observer when each phase starts and finishes and, during iterative phases (the contact
//! Newton steps), each iteration and its residual. The default observer ([`NoProgress`]) does
//! nothing; the `signorini` binary draws a spinner on a terminal.
//!
//! Observers take `&self` (a phase can report while other parts of the driver hold the
//! observer too); one that records keeps its state behind a `Mutex` or a `RefCell`.
//!
//! Order of the events of a primal run: `Mesh`, `Assemble`, `Solve` (with `iteration` events
//! while the contact iterates), `Postprocess`, then `Dual` and `Estimate` when asked for,
//! and `Output`; each `phase_started` is followed by its `phase_finished` (not after a failure).
//! A load path (`crate::evolution`) also sends `increment_finished` after each converged
//! increment.

/// A phase of a run, named as in the report's `timings`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Phase {
    /// Mesh generation or reading, and the checks of the scene against it.
    Mesh,
    /// Stiffness and load assembly.
    Assemble,
    /// The linear solve (factorisation included) or the contact iteration.
    Solve,
    /// Stresses, reactions and the independent checks.
    Postprocess,
    /// The dual (stress-function) solve.
    Dual,
    /// The error estimate.
    Estimate,
    /// Writing the result files.
    Output,
}

impl Phase {
    /// The phase's name in `timings` of `report.json`.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Mesh => "mesh",
            Phase::Assemble => "assemble",
            Phase::Solve => "solve",
            Phase::Postprocess => "postprocess",
            Phase::Dual => "dual",
            Phase::Estimate => "estimate",
            Phase::Output => "output",
        }
    }
}

/// Receives the progress of a run. Every method has an empty default.
pub trait Progress {
    /// `phase` begins.
    fn phase_started(&self, _phase: Phase) {}
    /// `phase` ended successfully after `seconds`.
    fn phase_finished(&self, _phase: Phase, _seconds: f64) {}
    /// Iteration `step` (from 1) of `phase` ended with relative residual `residual`.
    fn iteration(&self, _phase: Phase, _step: usize, _residual: f64) {}
    /// A remark on what the current phase is doing (e.g. "factorising K").
    fn note(&self, _text: &str) {}
    /// Increment `step.step` of a load path of `total` increments has converged, with the
    /// record `step` (what `history.csv` writes of it).
    fn increment_finished(&self, _step: &crate::evolution::StepRecord, _total: usize) {}
}

/// The observer that ignores everything (the default).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}

/// Run `f` as `phase`: started, then finished with its duration when `f` succeeds.
pub(crate) fn in_phase<T, E>(
    progress: &dyn Progress,
    phase: Phase,
    f: impl FnOnce() -> std::result::Result<T, E>,
) -> std::result::Result<T, E> {
    progress.phase_started(phase);
    let start = std::time::Instant::now();
    let value = f()?;
    progress.phase_finished(phase, start.elapsed().as_secs_f64());
    Ok(value)
}
