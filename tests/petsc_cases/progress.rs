//! The library's progress events (`problem::Progress`): a recording observer gets the phases
//! in order, each started then finished, and the contact Newton steps with their residuals.
use std::sync::{Arc, Mutex};

use signorini::petsc::Session;
use signorini::problem::{ElasticityProblem, Phase, Progress};
use signorini::scene::Scene;

#[derive(Debug, Clone, PartialEq)]
enum Event {
    Started(Phase),
    Finished(Phase),
    Iteration(Phase, usize, f64),
}

#[derive(Clone, Default)]
struct Recorder(Arc<Mutex<Vec<Event>>>, Arc<Mutex<Vec<(Phase, f64)>>>);

impl Progress for Recorder {
    fn phase_started(&self, phase: Phase) {
        self.0.lock().unwrap().push(Event::Started(phase));
    }
    fn phase_finished(&self, phase: Phase, seconds: f64) {
        self.1.lock().unwrap().push((phase, seconds));
        self.0.lock().unwrap().push(Event::Finished(phase));
    }
    fn iteration(&self, phase: Phase, step: usize, residual: f64) {
        self.0.lock().unwrap().push(Event::Iteration(phase, step, residual));
    }
}

pub fn progress_events_in_order(s: &Session) -> Result<(), String> {
    let recorder = Recorder::default();
    let scene = Scene::default_scene();
    let mut p = ElasticityProblem::setup_system_with_progress(s, scene, Box::new(recorder.clone()))
        .map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    p.solve().map_err(|e| e.to_string())?;
    p.postprocess().map_err(|e| e.to_string())?;
    let dir = std::env::temp_dir().join(format!("signorini-progress-{}", std::process::id()));
    p.write_output(&dir).map_err(|e| e.to_string())?;
    let _ = std::fs::remove_dir_all(&dir);
    let events = recorder.0.lock().unwrap().clone();
    let phases: Vec<Event> = events.iter().filter(|e| !matches!(e, Event::Iteration(..))).cloned().collect();
    let mut expected = Vec::new();
    for phase in [Phase::Mesh, Phase::Assemble, Phase::Solve, Phase::Postprocess, Phase::Output] {
        expected.push(Event::Started(phase));
        expected.push(Event::Finished(phase));
    }
    if phases != expected {
        return Err(format!("phases {phases:?}, expected {expected:?}"));
    }
    // Every phase does work: its time is positive.
    let seconds = recorder.1.lock().unwrap().clone();
    if seconds.len() != 5 || !seconds.iter().all(|(_, t)| *t > 0.0) {
        return Err(format!("phase times {seconds:?}"));
    }
    // The Newton steps come between the start and the end of the solve, numbered from 1, one
    // per iteration of the report, with its residual history.
    let steps: Vec<(usize, usize, f64)> = events
        .iter()
        .enumerate()
        .filter_map(|(k, e)| match e {
            Event::Iteration(Phase::Solve, step, r) => Some((k, *step, *r)),
            _ => None,
        })
        .collect();
    let solve_start = events.iter().position(|e| *e == Event::Started(Phase::Solve)).unwrap();
    let solve_end = events.iter().position(|e| *e == Event::Finished(Phase::Solve)).unwrap();
    let report = &p.contact_outcome.as_ref().ok_or("no contact outcome")?.report;
    if steps.len() != report.iterations || steps.is_empty() {
        return Err(format!("{} iteration events for {} iterations", steps.len(), report.iterations));
    }
    for (n, (k, step, r)) in steps.iter().enumerate() {
        if !(solve_start < *k && *k < solve_end) || *step != n + 1 || *r != report.residual_history[n] {
            return Err(format!("iteration event {n}: at {k}, step {step}, residual {r}: {events:?}"));
        }
    }
    // Without an observer nothing changes: the default is the no-op one, and the answer is the
    // observed run's, bit for bit, after the same Newton steps.
    let mut q = ElasticityProblem::setup_system(s, Scene::default_scene()).map_err(|e| e.to_string())?;
    q.assemble().map_err(|e| e.to_string())?;
    q.solve().map_err(|e| e.to_string())?;
    let unobserved = &q.contact_outcome.as_ref().ok_or("no contact outcome without an observer")?.report;
    if q.displacement != p.displacement || p.displacement.is_none() {
        return Err("the displacement differs without an observer".into());
    }
    if unobserved.iterations != report.iterations || unobserved.residual_history != report.residual_history {
        return Err(format!(
            "without an observer: {} steps {:?}, with: {} steps {:?}",
            unobserved.iterations, unobserved.residual_history, report.iterations, report.residual_history
        ));
    }
    Ok(())
}
