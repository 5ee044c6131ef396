//! What a run reports of its interface law: the `interface` entry of `report.json`
//! ([`InterfaceReport`]), the history of a load path's interface
//! ([`crate::output::interface::InterfaceHistory`], recorded increment by increment with
//! [`ElasticityProblem::record_interface_step`]) and the points its τ–δ plot traces (the
//! scene's `trace` of every interface table).
use serde::Serialize;

use crate::output::interface::{InterfaceHistory, InterfaceSummary};
use crate::problem::ElasticityProblem;

/// `report.json` → `interface`: the laws, the final interface's summary, the worst law
/// residual of the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InterfaceReport {
    /// The law of each contact part (`thin_layer`, `rccm`, `cohesive_joint`).
    pub laws: Vec<String>,
    /// The interface at the end of the run (the last increment's on a load path).
    #[serde(rename = "final")]
    pub last: InterfaceSummary,
    /// The largest law residual of the run: of the final solve, and of every increment of a
    /// load path.
    pub worst_law_residual: f64,
    /// The contact points traced in `interface_tau_delta.svg` (their positions, m); empty for
    /// a static run.
    pub traced_points: Vec<[f64; 2]>,
}

impl ElasticityProblem<'_> {
    /// The `trace` points of every interface table of the scene (`[contact.interface]`, each
    /// body's, each pair's), in that order; empty: the default points.
    pub fn interface_trace_spec(&self) -> Vec<[f64; 2]> {
        let scene = &self.scene;
        let rigid = scene.contact.iter().chain(scene.bodies.iter().filter_map(|b| b.contact.as_ref()));
        let interfaces = rigid
            .filter_map(|c| c.interface.as_ref())
            .chain(scene.contact_pairs.iter().filter_map(|p| p.interface.as_ref()));
        interfaces.flat_map(|i| i.trace.iter().copied()).collect()
    }

    /// Record the current interface ([`ElasticityProblem::interface`]) as increment `step` of
    /// the load path's interface history (nothing without an interface). Recording a step again
    /// replaces its sample, so the driver and a caller may both record it.
    pub fn record_interface_step(&self, step: usize) {
        let Some(snapshot) = &self.interface else { return };
        let mut history = self.interface_history.borrow_mut();
        let history = history.get_or_insert_with(|| InterfaceHistory::new(snapshot, &self.interface_trace_spec()));
        history.record(step, snapshot);
    }

    /// The load path's interface history so far (`None`: no increment recorded).
    pub fn interface_history(&self) -> Option<InterfaceHistory> {
        self.interface_history.borrow().clone()
    }

    /// The `interface` entry of the report; `None` without an interface snapshot.
    pub(crate) fn interface_report(&self) -> Option<InterfaceReport> {
        let snapshot = self.interface.as_ref()?;
        let last = InterfaceSummary::of(snapshot);
        let history = self.interface_history.borrow();
        let path_worst = history.iter().flat_map(|h| &h.steps).map(|s| s.summary.worst_law_residual);
        let worst_law_residual = path_worst.fold(last.worst_law_residual, f64::max);
        let traced_points = match (&*history, &self.load_path) {
            (Some(h), Some(_)) => h.trace_points.iter().filter_map(|&i| snapshot.points.get(i)).map(|p| p.x).collect(),
            _ => Vec::new(),
        };
        Some(InterfaceReport { laws: snapshot.laws.clone(), last, worst_law_residual, traced_points })
    }
}
