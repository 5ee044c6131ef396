//! The outputs of an interface law ([`crate::interface_law`]): what a run writes of the
//! interface's state at its contact points.
//!
//! - `interface.vtu` ([`INTERFACE_VTU`], [`write_interface_vtu`]): the contact points as VTK
//!   vertex cells (`VTK_VERTEX`, type 1, one per point: the points of different contact parts
//!   are not joined), at `(x, y, 0)`, with the point data
//!
//!   | array | unit | meaning |
//!   |---|---|---|
//!   | `opening` | m | the distance between the faces along the normal, > 0 separated |
//!   | `slip` | m | the tangential jump since the start of the path |
//!   | `traction_normal` | Pa | `rN / w`, < 0 compression |
//!   | `traction_tangential` | Pa | `rT / w` |
//!   | `adhesion` | – | β in [0, 1] (RCCM), only when a law has it |
//!   | `damage` | – | in [0, 1] (cohesive joint), only when a law has it |
//!   | `law_residual` | – | the law's own residual at the point (0 exact) |
//!
//!   With laws of several kinds in one run (a pair glued, another cohesive), `adhesion` and
//!   `damage` hold NaN at the points whose law lacks them (NaN: no value, not a number to read).
//! - on a load path, `steps/interface_NNNN.vtu` per increment
//!   ([`crate::output::pvd::interface_step_file_name`]) and `interface.pvd` ([`INTERFACE_PVD`])
//!   listing them with their times;
//! - `interface_tau_delta.svg` ([`TAU_DELTA_SVG`], [`write_tau_delta_svg`]): for the traced
//!   points ([`trace_points`]), the tangential traction against the slip (left panel) and the
//!   normal traction against the opening (right panel), one line per point through the
//!   increments in their order;
//! - the interface's columns of `history.csv` ([`InterfaceSummary`], one per increment, see
//!   [`crate::evolution::history`]) and its entry in `report.json`.
//!
//! A non-finite value is refused before anything is written, naming the point and the array.
use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::interface_law::{InterfacePointState, InterfaceSnapshot};
use crate::output::plot::{write_linear_panels_svg, Panel, Series, Style};
use crate::output::vtu::{begin_piece, end_piece, write_array, write_f64_array};
use crate::output::write_atomically;

/// The interface's state at the end of a static run (or of a load path), in the output
/// directory.
pub const INTERFACE_VTU: &str = "interface.vtu";
/// The collection of a load path's interface files.
pub const INTERFACE_PVD: &str = "interface.pvd";
/// The τ–δ plot of the traced points.
pub const TAU_DELTA_SVG: &str = "interface_tau_delta.svg";

const VTK_VERTEX: u8 = 1;

/// [`Error::Output`] for `path`: nothing was written.
fn refused(path: &Path, message: String) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: format!("{message} (nothing was written; an existing file at this path is unchanged)"),
    }
}

/// The arrays of a point that every law has, named as in the file.
fn required(p: &InterfacePointState) -> [(&'static str, f64); 5] {
    [
        ("opening", p.opening),
        ("slip", p.slip),
        ("traction_normal", p.traction_normal),
        ("traction_tangential", p.traction_tangential),
        ("law_residual", p.law_residual),
    ]
}

/// Every position and value of `snapshot` finite (the optional ones where present), at least
/// one point; else [`Error::Output`] naming the point and the array.
fn check_snapshot(path: &Path, snapshot: &InterfaceSnapshot) -> Result<()> {
    if snapshot.points.is_empty() {
        return Err(refused(path, "the interface has no contact point".into()));
    }
    if !snapshot.time.is_finite() {
        return Err(refused(path, format!("the snapshot's time is {}, not a finite number", snapshot.time)));
    }
    for (i, p) in snapshot.points.iter().enumerate() {
        let optional = [("adhesion", p.adhesion), ("damage", p.damage)];
        let values = required(p)
            .into_iter()
            .chain([("x", p.x[0]), ("y", p.x[1])])
            .chain(optional.into_iter().filter_map(|(k, v)| v.map(|v| (k, v))));
        for (name, v) in values {
            if !v.is_finite() {
                return Err(refused(
                    path,
                    format!("contact point {i} at ({:e}, {:e}): {name} is {v}, not a finite number", p.x[0], p.x[1]),
                ));
            }
        }
    }
    Ok(())
}

/// Write `snapshot` as a `.vtu` file (module documentation), atomically. Refused with
/// [`Error::Output`] naming `path` (nothing written): no point, a non-finite value.
pub fn write_interface_vtu(path: &Path, snapshot: &InterfaceSnapshot) -> Result<()> {
    check_snapshot(path, snapshot)?;
    let points = &snapshot.points;
    let n = points.len();
    let mut arrays: Vec<(&str, Vec<f64>)> = ["opening", "slip", "traction_normal", "traction_tangential"]
        .iter()
        .enumerate()
        .map(|(k, name)| (*name, points.iter().map(|p| required(p)[k].1).collect()))
        .collect();
    if points.iter().any(|p| p.adhesion.is_some()) {
        arrays.push(("adhesion", points.iter().map(|p| p.adhesion.unwrap_or(f64::NAN)).collect()));
    }
    if points.iter().any(|p| p.damage.is_some()) {
        arrays.push(("damage", points.iter().map(|p| p.damage.unwrap_or(f64::NAN)).collect()));
    }
    arrays.push(("law_residual", points.iter().map(|p| p.law_residual).collect()));
    write_atomically(path, |w| {
        begin_piece(w, n, n)?;
        writeln!(w, "      <PointData>")?;
        for (name, values) in &arrays {
            write_f64_array(w, Some(name), 1, n, values.iter().copied())?;
        }
        writeln!(w, "      </PointData>")?;
        writeln!(w, "      <Points>")?;
        write_f64_array(w, None, 3, 3 * n, points.iter().flat_map(|p| [p.x[0], p.x[1], 0.0]))?;
        writeln!(w, "      </Points>")?;
        writeln!(w, "      <Cells>")?;
        write_array(w, "Int64", Some("connectivity"), 1, n, (0..n).map(|i| (i as i64).to_le_bytes()))?;
        write_array(w, "Int64", Some("offsets"), 1, n, (1..=n).map(|i| (i as i64).to_le_bytes()))?;
        write_array(w, "UInt8", Some("types"), 1, n, std::iter::repeat_n([VTK_VERTEX], n))?;
        writeln!(w, "      </Cells>")?;
        end_piece(w)
    })
}

/// The interface at the end of one solve in a few numbers (`history.csv`, `report.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InterfaceSummary {
    /// The path's time (1 for a static run).
    pub time: f64,
    /// The law of each contact part.
    pub laws: Vec<String>,
    /// Contact points.
    pub points: usize,
    /// Staggered iterations (solve → update) of the solve.
    pub iterations: usize,
    /// The smallest adhesion β over the points that have one (`None`: no law has it).
    pub min_adhesion: Option<f64>,
    /// The largest damage over the points that have one (`None`: no law has it).
    pub max_damage: Option<f64>,
    /// The largest opening (m; negative when a bonded layer is compressed everywhere).
    pub max_opening: f64,
    /// The largest |slip| (m).
    pub max_slip: f64,
    /// The largest law residual.
    pub worst_law_residual: f64,
}

impl InterfaceSummary {
    /// The summary of `snapshot` (0 for the extremes of a snapshot without points).
    pub fn of(snapshot: &InterfaceSnapshot) -> Self {
        let points = &snapshot.points;
        let fold_some =
            |values: Vec<f64>, min: bool| values.into_iter().reduce(|a, b| if min { a.min(b) } else { a.max(b) });
        InterfaceSummary {
            time: snapshot.time,
            laws: snapshot.laws.clone(),
            points: points.len(),
            iterations: snapshot.iterations,
            min_adhesion: fold_some(points.iter().filter_map(|p| p.adhesion).collect(), true),
            max_damage: fold_some(points.iter().filter_map(|p| p.damage).collect(), false),
            // The largest opening, negative when every point is compressed into a bonded layer.
            max_opening: points.iter().map(|p| p.opening).reduce(f64::max).unwrap_or(0.0),
            max_slip: points.iter().map(|p| p.slip.abs()).fold(0.0, f64::max),
            worst_law_residual: points.iter().map(|p| p.law_residual).fold(0.0, f64::max),
        }
    }
}

/// The contact points traced in the τ–δ plot: for each point of `trace` the index of the
/// contact point nearest to it (the first on a tie); without `trace`, the first, middle
/// (`n / 2`) and last contact points. Each index once, in the order found.
pub fn trace_points(points: &[InterfacePointState], trace: &[[f64; 2]]) -> Vec<usize> {
    let n = points.len();
    if n == 0 {
        return Vec::new();
    }
    let chosen: Vec<usize> = if trace.is_empty() {
        vec![0, n / 2, n - 1]
    } else {
        trace
            .iter()
            .map(|t| {
                let distance = |p: &InterfacePointState| (p.x[0] - t[0]).hypot(p.x[1] - t[1]);
                (0..n).fold(0, |best, i| if distance(&points[i]) < distance(&points[best]) { i } else { best })
            })
            .collect()
    };
    let mut unique = Vec::with_capacity(chosen.len());
    for i in chosen {
        if !unique.contains(&i) {
            unique.push(i);
        }
    }
    unique
}

/// The interface at one increment of a load path: its summary and its traced points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InterfaceStepSample {
    /// The increment (from 1, as [`crate::evolution::StepRecord::step`]).
    pub step: usize,
    /// The interface's summary at its end.
    pub summary: InterfaceSummary,
    /// The traced points' states, in the order of [`InterfaceHistory::trace_points`].
    pub trace: Vec<InterfacePointState>,
}

/// The interface along a load path: the points traced and every increment's sample.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InterfaceHistory {
    /// The traced contact points' indices ([`trace_points`], chosen at the first increment).
    pub trace_points: Vec<usize>,
    /// One sample per increment, in increasing order of the increments.
    pub steps: Vec<InterfaceStepSample>,
}

impl InterfaceHistory {
    /// An empty history tracing, among the points of `snapshot`, those nearest `trace`
    /// ([`trace_points`]).
    pub fn new(snapshot: &InterfaceSnapshot, trace: &[[f64; 2]]) -> Self {
        InterfaceHistory { trace_points: trace_points(&snapshot.points, trace), steps: Vec::new() }
    }

    /// Record `snapshot` as increment `step`; a second record of the same step replaces the
    /// first (so that recording twice, by the driver and by a caller, keeps one sample).
    pub fn record(&mut self, step: usize, snapshot: &InterfaceSnapshot) {
        let trace = self.trace_points.iter().filter_map(|&i| snapshot.points.get(i).cloned()).collect();
        let sample = InterfaceStepSample { step, summary: InterfaceSummary::of(snapshot), trace };
        match self.steps.iter().position(|s| s.step >= step) {
            Some(k) if self.steps[k].step == step => self.steps[k] = sample,
            Some(k) => self.steps.insert(k, sample),
            None => self.steps.push(sample),
        }
    }

    /// The sample of increment `step`, if recorded.
    pub fn at(&self, step: usize) -> Option<&InterfaceStepSample> {
        self.steps.iter().find(|s| s.step == step)
    }
}

/// Write `interface_tau_delta.svg`: two linear panels side by side (1600×560), the tangential
/// traction (Pa) against the slip (m) and the normal traction (Pa) against the opening (m), one
/// line with markers per traced point through the increments in their order (never sorted: a
/// loading cycle draws its loop), labelled with the point's position, atomically. Errors: no
/// increment or no traced point ([`Error::Usage`]); a non-finite value ([`Error::Output`]
/// naming the increment and the point).
pub fn write_tau_delta_svg(path: &Path, title: &str, history: &InterfaceHistory) -> Result<()> {
    if history.steps.is_empty() || history.trace_points.is_empty() {
        return Err(Error::Usage(format!(
            "{}: a τ–δ plot needs at least one increment and one traced point (nothing was written)",
            path.display()
        )));
    }
    for s in &history.steps {
        for (k, p) in s.trace.iter().enumerate() {
            let values = [p.slip, p.opening, p.traction_normal, p.traction_tangential];
            if values.iter().any(|v| !v.is_finite()) {
                return Err(refused(
                    path,
                    format!("increment {}: traced point {k} has a value that is not a finite number", s.step),
                ));
            }
        }
    }
    let label = |k: usize| {
        let first = history.steps.iter().find_map(|s| s.trace.get(k));
        match first {
            Some(p) => format!("point {} at ({:.4e}, {:.4e})", history.trace_points[k], p.x[0], p.x[1]),
            None => format!("point {}", history.trace_points[k]),
        }
    };
    let series = |xy: fn(&InterfacePointState) -> (f64, f64)| -> Vec<Series> {
        (0..history.trace_points.len())
            .map(|k| Series {
                label: label(k),
                points: history.steps.iter().filter_map(|s| s.trace.get(k)).map(xy).collect(),
            })
            .collect()
    };
    let tangential = series(|p| (p.slip, p.traction_tangential));
    let normal = series(|p| (p.opening, p.traction_normal));
    let (left, right) =
        (format!("{title}: shear traction against slip"), format!("{title}: normal traction against opening"));
    let panels = [
        Panel { title: &left, x_label: "slip (m)", y_label: "tangential traction (Pa)", series: &tangential },
        Panel {
            title: &right,
            x_label: "opening (m)",
            y_label: "normal traction (Pa, < 0 compression)",
            series: &normal,
        },
    ];
    write_linear_panels_svg(path, &panels, Style::LineAndMarkers)
}
