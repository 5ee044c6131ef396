//! The accuracy benchmark (`signorini bench accuracy [SCENE]`): the work–precision diagram of
//! one scene, relative error against wall time (log–log), one curve per way of computing it:
//!
//! ```text
//!   uniform P1, uniform P2     the scene's cell size h, h/2, h/4, … (each level a mesh of its own)
//!   adaptive P1, adaptive P2   the steps of the adaptive loop (crate::adapt::driver) from the
//!                              scene's mesh, towards the target error
//!   contact solvers            every condensed contact solver on one uniform P1 mesh
//! ```
//!
//! Each point is the relative error in the constitutive relation (the estimate, % of the energy
//! norm) and, where a reference is computed, the true error against it, `(‖Δu‖² + ‖Δσ‖²)^½ /
//! ‖σ_ref‖` as in [`crate::adapt::study()`] (the reference is P2, one halving finer than the finest
//! uniform P1 level, solved by the full-space Newton). The time of a uniform or solver point is
//! that mesh's run: meshing, primal solve, dual solve and estimate; the time of an adaptive step
//! is the cumulative run time of the loop up to its estimate (every earlier step, remeshing and
//! step output included), i.e. what it costs to get there.
//!
//! Each case (the reference, one uniform level, one adaptive loop, one solver) runs in a child
//! process of its own ([`crate::bench`]'s runner); the plan of the cases is written by the parent
//! as `plan.json` into the children's scratch directory, and the reference as `reference.bin`
//! ([`ReferenceField::to_bytes`]). A case that fails is a row of the failed-cases table; an
//! adaptive loop that fails at a step keeps the rows of the steps before it.
use std::path::{Path, PathBuf};
use std::time::Instant;

use plotters::prelude::*;

use super::BenchRecord;
use crate::adapt::study::{cell_size, fitted_rate, scaled};
use crate::adapt::{adapt_inspecting, AdaptOptions, ReferenceField};
use crate::error::{Error, Result};
use crate::mesh::Order;
use crate::output;
use crate::petsc::Session;
use crate::problem::ElasticityProblem;
use crate::scene::{ContactSolverSpec, FrictionSpec, Scene};

/// The default scene: the square block without its corner point, Tresca friction.
pub const DEFAULT_SCENE_TOML: &str = include_str!("../../examples/scenes/square_block_tresca.toml");
/// Its path in the repository (how the benchmark files name it).
pub const DEFAULT_SCENE_PATH: &str = "examples/scenes/square_block_tresca.toml";

/// One case of the benchmark.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum AccuracyCase {
    /// The P2 reference at this cell size (primal only).
    Reference {
        /// The reference mesh's cell size.
        cell_size: f64,
    },
    /// One uniform level: the scene at `cell_size`, elements of degree `order`.
    Uniform {
        /// Polynomial degree, 1 or 2.
        order: u8,
        /// Level, 0 the coarsest.
        level: usize,
        /// The level's cell size.
        cell_size: f64,
    },
    /// The adaptive loop from the scene's mesh at degree `order`.
    Adaptive {
        /// Polynomial degree, 1 or 2.
        order: u8,
        /// The loop's element budget.
        max_elements: usize,
    },
    /// The named contact solver on the uniform P1 mesh of `cell_size`.
    Solver {
        /// The contact solver's scene name.
        name: String,
        /// The mesh's cell size.
        cell_size: f64,
    },
}

/// What the children need: the scene (as TOML) and the cases.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct AccuracyPlan {
    /// The scene's text.
    pub scene_toml: String,
    /// The scene's file (for relative paths and reports).
    pub scene_path: PathBuf,
    /// The adaptive loops' target (%).
    pub target_percent: f64,
    /// The largest size run (dofs).
    pub max_dofs: usize,
    /// `(estimated dofs, case, name)`.
    pub cases: Vec<(usize, AccuracyCase, String)>,
}

/// One point of the diagram.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct AccuracyRow {
    /// "reference", "uniform P1", "uniform P2", "adaptive P1", "adaptive P2" or "solver".
    pub series: String,
    /// The level's cell size, the step, or the solver's name.
    pub label: String,
    /// Mesh triangles.
    pub elements: usize,
    /// Displacement unknowns.
    pub dofs: usize,
    /// Contact points of the primal (0 without contact).
    pub contact_points: usize,
    /// Seconds to make the mesh.
    pub mesh_seconds: f64,
    /// Assembly, solve and post-processing of the primal (the contact solve included).
    pub primal_seconds: f64,
    /// Seconds of the dual solve.
    pub dual_seconds: f64,
    /// Seconds of the estimate.
    pub estimate_seconds: f64,
    /// Adaptive steps: the size map and Gmsh remeshing that made the next mesh.
    pub remesh_seconds: f64,
    /// This mesh: mesh + primal + dual + estimate.
    pub run_seconds: f64,
    /// Adaptive steps: from the start of the loop to this step's estimate; else `run_seconds`.
    pub cumulative_seconds: f64,
    /// The estimate, % (0 for the reference, which has none).
    pub estimate_percent: f64,
    /// The true error against the reference, % of ‖σ_ref‖ (None without a reference).
    pub true_percent: Option<f64>,
    /// Reference: ‖σ_ref‖.
    pub energy_norm: Option<f64>,
}

/// The rows of one case, why it stopped early (an adaptive loop that failed at a step) and,
/// for an adaptive loop, how it ended (the target, or the budget of elements or steps).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct AccuracyCaseResult {
    /// The points of the case's curve.
    pub rows: Vec<AccuracyRow>,
    /// Why the case stopped early, if it did.
    pub failure: Option<String>,
    #[serde(default)]
    /// How an adaptive loop ended.
    pub note: Option<String>,
}

/// The contact solvers compared for a friction law (those the dual formulation takes too).
pub fn solvers_for(friction: Option<&FrictionSpec>) -> Vec<&'static str> {
    match friction {
        None => Vec::new(),
        Some(FrictionSpec::Tresca { .. }) => {
            vec!["newton_full", "newton", "relaxation", "dpana", "uzawa", "tresca_fixed_point", "tao"]
        }
        Some(_) => vec!["newton_full", "newton", "relaxation", "dpana", "uzawa", "tresca_fixed_point"],
    }
}

fn order_of(degree: u8) -> Order {
    if degree == 2 {
        Order::P2
    } else {
        Order::P1
    }
}

/// The dofs of the scene meshed at `factor` × its cell size and degree `order` (the mesh is
/// built, not estimated: Gmsh's node counts depend on the shape).
fn dofs_at(scene: &Scene, factor: f64, order: Order) -> Result<usize> {
    let (mesh, _, _) = crate::problem::build_mesh(&scaled(scene, factor, order))?;
    Ok(2 * mesh.num_nodes())
}

/// The cases for `scene` up to `max_dofs`: uniform P1 and P2 levels while their dofs stay at
/// most `max_dofs`, the P2 reference one halving below the finest P1 level, the two adaptive
/// loops (up to `max_dofs` dofs), and the contact solvers on the third P1 level (or the finest).
pub fn plan(scene: &Scene, max_dofs: usize, target_percent: f64) -> Result<AccuracyPlan> {
    crate::adapt::driver::mesh_request(scene, "bench accuracy")?;
    let h0 = cell_size(scene);
    let mut cases = Vec::new();
    let mut levels = [Vec::new(), Vec::new()];
    for (slot, degree) in [(0usize, 1u8), (1, 2)] {
        for level in 0..10 {
            let factor = 0.5f64.powi(level as i32);
            let dofs = dofs_at(scene, factor, order_of(degree))?;
            if dofs > max_dofs && level > 0 {
                break;
            }
            levels[slot].push((dofs, level, h0 * factor));
            if dofs > max_dofs {
                break;
            }
        }
    }
    let finest = levels[0].last().map_or(0, |l| l.1);
    let reference_factor = 0.5f64.powi(finest as i32 + 1);
    let reference_dofs = dofs_at(scene, reference_factor, Order::P2)?;
    cases.push((reference_dofs, AccuracyCase::Reference { cell_size: h0 * reference_factor }, "reference P2".into()));
    for (slot, degree) in [(0usize, 1u8), (1, 2)] {
        for &(dofs, level, cell_size) in &levels[slot] {
            cases.push((dofs, AccuracyCase::Uniform { order: degree, level, cell_size }, format!("uniform P{degree}")));
        }
    }
    for degree in [1u8, 2] {
        // P1: about one triangle per dof; P2: four dofs per triangle.
        let max_elements = if degree == 1 { max_dofs } else { max_dofs / 4 };
        cases.push((max_dofs, AccuracyCase::Adaptive { order: degree, max_elements }, format!("adaptive P{degree}")));
    }
    if let Some(&(dofs, _, cell_size)) = levels[0].get(2).or(levels[0].last()) {
        for name in solvers_for(scene.contact.as_ref().map(|c| &c.friction)) {
            cases.push((dofs, AccuracyCase::Solver { name: name.to_string(), cell_size }, format!("solver {name}")));
        }
    }
    Ok(AccuracyPlan { scene_toml: scene.to_toml(), scene_path: scene.source.clone(), target_percent, max_dofs, cases })
}

/// The plan file in the scratch directory.
pub fn plan_path(scratch: &Path) -> PathBuf {
    scratch.join("plan.json")
}

fn reference_path(scratch: &Path) -> PathBuf {
    scratch.join("reference.bin")
}

/// The reference field and its energy norm, when the reference case has written them.
fn read_reference(scratch: &Path) -> Option<(ReferenceField, f64)> {
    let bytes = std::fs::read(reference_path(scratch)).ok()?;
    let norm = f64::from_le_bytes(bytes.get(..8)?.try_into().ok()?);
    Some((ReferenceField::from_bytes(&bytes[8..])?, norm))
}

/// Solve the primal, the dual and the estimate of `scene` on its mesh (or on `mesh`), timed.
fn solve_pair<'s>(session: &'s Session, scene: Scene) -> Result<(ElasticityProblem<'s>, [f64; 4])> {
    let t = Instant::now();
    let mut p = ElasticityProblem::setup_system(session, scene)?;
    let mesh = t.elapsed().as_secs_f64();
    let t = Instant::now();
    p.assemble()?;
    p.solve()?;
    p.postprocess()?;
    let primal = t.elapsed().as_secs_f64();
    let t = Instant::now();
    p.solve_dual()?;
    let dual = t.elapsed().as_secs_f64();
    let t = Instant::now();
    p.estimate()?;
    let estimate = t.elapsed().as_secs_f64();
    Ok((p, [mesh, primal, dual, estimate]))
}

fn contact_points(p: &ElasticityProblem) -> usize {
    p.contact_outcome.as_ref().map_or(0, |o| o.report.points)
}

fn true_percent(reference: &Option<(ReferenceField, f64)>, p: &ElasticityProblem) -> Result<Option<f64>> {
    match reference {
        Some((field, norm)) if *norm > 0.0 => Ok(Some(100.0 * field.true_errors(p)?.combined() / norm)),
        _ => Ok(None),
    }
}

fn pair_row(
    series: &str,
    label: String,
    p: &ElasticityProblem,
    t: [f64; 4],
    reference: &Option<(ReferenceField, f64)>,
) -> Result<AccuracyRow> {
    let run = t.iter().sum();
    Ok(AccuracyRow {
        series: series.to_string(),
        label,
        elements: p.mesh.num_cells(),
        dofs: p.num_dofs(),
        contact_points: contact_points(p),
        mesh_seconds: t[0],
        primal_seconds: t[1],
        dual_seconds: t[2],
        estimate_seconds: t[3],
        remesh_seconds: 0.0,
        run_seconds: run,
        cumulative_seconds: run,
        estimate_percent: p.estimate.as_ref().map_or(f64::NAN, |e| e.estimate.relative_percent),
        true_percent: true_percent(reference, p)?,
        energy_norm: None,
    })
}

/// Run case `index` of the plan in `scratch` (a child process of `bench accuracy`).
pub fn accuracy_case(session: &Session, scratch: &Path, index: usize) -> Result<AccuracyCaseResult> {
    let path = plan_path(scratch);
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, "reading the benchmark plan", e))?;
    let plan: AccuracyPlan = serde_json::from_str(&text)
        .map_err(|e| Error::Usage(format!("bench accuracy: unreadable plan {}: {e}", path.display())))?;
    let (_, case, _) =
        plan.cases.get(index).ok_or_else(|| Error::Usage(format!("bench accuracy: no case {index}")))?.clone();
    let scene = Scene::from_str(&plan.scene_toml, &plan.scene_path)?;
    match case {
        AccuracyCase::Reference { cell_size } => {
            let t = Instant::now();
            let mut s = scaled(&scene, cell_size / self::cell_size(&scene), Order::P2);
            if let Some(c) = s.contact.as_mut() {
                c.solver = ContactSolverSpec::FullSpaceNewton;
            }
            let mut p = ElasticityProblem::setup_system(session, s)?;
            p.assemble()?;
            p.solve()?;
            p.postprocess()?;
            let u = p.displacement.as_ref().ok_or_else(|| Error::PetscUsage("reference not solved".into()))?;
            let field = ReferenceField::new(&p.mesh, u);
            let norm = field.energy_norm(&p.material);
            if session.rank() == 0 {
                let mut bytes = norm.to_le_bytes().to_vec();
                bytes.extend(field.to_bytes());
                output::write_atomically(&reference_path(scratch), |w| w.write_all(&bytes))?;
            }
            let seconds = t.elapsed().as_secs_f64();
            let row = AccuracyRow {
                series: "reference".into(),
                label: format!("P2, h = {cell_size:.4e}"),
                elements: p.mesh.num_cells(),
                dofs: p.num_dofs(),
                contact_points: contact_points(&p),
                mesh_seconds: 0.0,
                primal_seconds: seconds,
                dual_seconds: 0.0,
                estimate_seconds: 0.0,
                remesh_seconds: 0.0,
                run_seconds: seconds,
                cumulative_seconds: seconds,
                estimate_percent: 0.0,
                true_percent: None,
                energy_norm: Some(norm),
            };
            Ok(AccuracyCaseResult { rows: vec![row], failure: None, note: None })
        }
        AccuracyCase::Uniform { order, cell_size, .. } => {
            let reference = read_reference(scratch);
            let s = scaled(&scene, cell_size / self::cell_size(&scene), order_of(order));
            let (p, t) = solve_pair(session, s)?;
            let row = pair_row(&format!("uniform P{order}"), format!("h = {cell_size:.4e}"), &p, t, &reference)?;
            Ok(AccuracyCaseResult { rows: vec![row], failure: None, note: None })
        }
        AccuracyCase::Solver { name, cell_size } => {
            let reference = read_reference(scratch);
            let mut s = scaled(&scene, cell_size / self::cell_size(&scene), Order::P1);
            let contact = s.contact.as_mut().ok_or_else(|| Error::Usage("bench accuracy: no contact".into()))?;
            contact.solver = ContactSolverSpec::from_scene_name(&name)
                .ok_or_else(|| Error::Usage(format!("bench accuracy: unknown contact solver {name}")))?;
            let (p, t) = solve_pair(session, s)?;
            let row = pair_row("solver", name, &p, t, &reference)?;
            Ok(AccuracyCaseResult { rows: vec![row], failure: None, note: None })
        }
        AccuracyCase::Adaptive { order, max_elements } => {
            let reference = read_reference(scratch);
            let s = scaled(&scene, 1.0, order_of(order));
            let mut options = AdaptOptions::new(&s, plan.target_percent);
            options.max_elements = max_elements.max(1);
            let out = scratch.join(format!("adapt_p{order}"));
            // Per step: (contact points, true error) from the solved problem, then the row.
            let measured: std::cell::RefCell<Vec<(usize, Option<f64>)>> = Default::default();
            let mut rows = Vec::new();
            let series = format!("adaptive P{order}");
            let outcome = adapt_inspecting(
                session,
                &s,
                &options,
                &out,
                &mut |step| {
                    let (points, truth) = measured.borrow().last().copied().unwrap_or((0, None));
                    let t = &step.seconds;
                    rows.push(AccuracyRow {
                        series: series.clone(),
                        label: format!("step {}", step.step),
                        elements: step.elements,
                        dofs: step.dofs,
                        contact_points: points,
                        mesh_seconds: t.mesh,
                        primal_seconds: t.solve,
                        dual_seconds: t.dual,
                        estimate_seconds: t.estimate,
                        remesh_seconds: t.remesh,
                        run_seconds: t.mesh + t.solve + t.dual + t.estimate,
                        cumulative_seconds: step.cumulative_seconds,
                        estimate_percent: step.error_percent,
                        true_percent: truth,
                        energy_norm: None,
                    });
                },
                &mut |_, p| {
                    let truth = true_percent(&reference, p)?;
                    measured.borrow_mut().push((contact_points(p), truth));
                    Ok(())
                },
            );
            let _ = std::fs::remove_dir_all(&out);
            // A stop at the element limit or the step limit is the benchmark's budget, not a
            // failure: the table's notes say it.
            let (failure, note) = match outcome {
                Ok(o) => (None, Some(crate::adapt::report::status_line(&o))),
                Err(e) => (Some(format!("step {}: {e}", rows.len())), None),
            };
            Ok(AccuracyCaseResult { rows, failure, note })
        }
    }
}

fn cell(v: Option<f64>, digits: usize) -> String {
    match v {
        Some(v) if v.is_finite() => format!("{v:.digits$}"),
        _ => "–".into(),
    }
}

/// The reference row, if its case succeeded.
fn reference_row(rows: &[AccuracyRow]) -> Option<&AccuracyRow> {
    rows.iter().find(|r| r.series == "reference")
}

/// The rate of a series' estimate against its dofs (`error ∝ dofs^(−rate)`), least squares.
fn dof_rate(rows: &[AccuracyRow], series: &str) -> Option<f64> {
    let pts: Vec<&AccuracyRow> = rows.iter().filter(|r| r.series == series).collect();
    let x: Vec<f64> = pts.iter().map(|r| r.dofs as f64).collect();
    let y: Vec<f64> = pts.iter().map(|r| r.estimate_percent).collect();
    fitted_rate(&x, &y).map(|r| -r)
}

/// The markdown: what was run, the table (one row per point), the rates and the notes.
pub fn accuracy_table(results: &[AccuracyCaseResult]) -> String {
    let rows: Vec<AccuracyRow> = results.iter().flat_map(|r| r.rows.iter().cloned()).collect();
    let mut s = String::new();
    if let Some(r) = reference_row(&rows) {
        s.push_str(&format!(
            "Reference: {} ({} elements, {} dofs, ‖σ_ref‖ = {:.6e}, {:.1} s), the primal by the full-space Newton. \
             True error ε = (‖Δu‖² + ‖Δσ‖²)^½ / ‖σ_ref‖; estimate = error in the constitutive relation / \
             ‖½(σ_h + Cε(u_h))‖. Time: mesh + primal + dual + estimate of the point's mesh; adaptive steps: \
             cumulative from the loop's start (remeshing and step output included).\n\n",
            r.label,
            r.elements,
            r.dofs,
            r.energy_norm.unwrap_or(f64::NAN),
            r.run_seconds
        ));
    } else {
        s.push_str("No reference (its case failed): estimates only.\n\n");
    }
    s.push_str(
        "| series | mesh | elements | dofs | contact points | primal (s) | dual (s) | estimate (s) | remesh (s) | \
         time (s) | cumulative (s) | estimate (%) | true error (%) | effectivity |\n\
         |---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows.iter().filter(|r| r.series != "reference") {
        let effectivity = r.true_percent.map(|t| r.estimate_percent / t);
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {} |\n",
            r.series,
            r.label,
            r.elements,
            r.dofs,
            r.contact_points,
            r.primal_seconds,
            r.dual_seconds,
            r.estimate_seconds,
            r.remesh_seconds,
            r.run_seconds,
            r.cumulative_seconds,
            r.estimate_percent,
            cell(r.true_percent, 3),
            cell(effectivity, 2),
        ));
    }
    let rates: Vec<String> = ["uniform P1", "uniform P2"]
        .iter()
        .filter_map(|series| dof_rate(&rows, series).map(|r| format!("{series} {r:.2}")))
        .collect();
    if !rates.is_empty() {
        s.push_str(&format!(
            "\nObserved rates of the estimate against the dofs (error ∝ dofs^−rate; h^(2 rate) in the cell size): {}.\n",
            rates.join(", ")
        ));
    }
    // The reference's own error, extrapolated from the uniform P2 estimates.
    if let (Some(r), Some(rate)) = (reference_row(&rows), dof_rate(&rows, "uniform P2")) {
        if let Some(last) = rows.iter().rfind(|x| x.series == "uniform P2") {
            let own = last.estimate_percent * (r.dofs as f64 / last.dofs as f64).powf(-rate);
            s.push_str(&format!(
                "The reference's own error, extrapolated from the uniform P2 estimates at that rate: about {own:.3} %; \
                 true errors near it mean little (the reference is then no better than the mesh it measures).\n"
            ));
        }
    }
    for result in results {
        let Some(r) = result.rows.first() else { continue };
        if let Some(f) = &result.failure {
            s.push_str(&format!("\n{} failed after {} step(s): {f}\n", r.series, result.rows.len()));
        }
        if let Some(n) = &result.note {
            s.push_str(&format!("\n{}: {n}\n", r.series));
        }
    }
    s
}

/// The values 1, 2, 5 × 10^k within `[lo, hi]` (the labelled ticks of a log axis).
fn one_two_five(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    if !(lo > 0.0 && hi > lo && lo.is_finite() && hi.is_finite()) {
        return out;
    }
    for k in (lo.log10().floor() as i32)..=(hi.log10().ceil() as i32) {
        for m in [1.0, 2.0, 5.0] {
            let v = m * 10f64.powi(k);
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
    }
    out
}

/// A tick label with as many digits as it needs (0.05, 0.5, 5, 50).
fn short_number(v: f64) -> String {
    let digits = if v >= 1.0 { 1 } else { ((-v.log10().floor()) as usize + 1).min(12) };
    let s = format!("{v:.digits$}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

const SERIES: [(&str, RGBColor); 4] = [
    ("uniform P1", RGBColor(0x00, 0x72, 0xB2)),
    ("uniform P2", RGBColor(0xD5, 0x5E, 0x00)),
    ("adaptive P1", RGBColor(0x00, 0x9E, 0x73)),
    ("adaptive P2", RGBColor(0xCC, 0x79, 0xA7)),
];

fn plot_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output { path: path.to_path_buf(), message: format!("drawing the plot: {e} (nothing was written)") }
}

/// `bench_accuracy.svg`: relative error against wall time, log–log; per series the estimate
/// (solid line, filled markers) and the true error (dashed line, hollow markers) in one colour;
/// the contact solvers as labelled black triangles (estimate).
pub fn write_accuracy_svg(path: &Path, title: &str, rows: &[AccuracyRow]) -> Result<()> {
    let plotted: Vec<&AccuracyRow> = rows.iter().filter(|r| r.series != "reference").collect();
    let xs = plotted.iter().map(|r| r.cumulative_seconds).filter(|v| v.is_finite() && *v > 0.0);
    let ys = plotted
        .iter()
        .flat_map(|r| [Some(r.estimate_percent), r.true_percent])
        .flatten()
        .filter(|v| v.is_finite() && *v > 0.0);
    let (x0, x1) = xs.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (y0, y1) = ys.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (x0, x1) = if x0.is_finite() { (x0 / 1.5, x1 * 1.5) } else { (0.01, 1.0) };
    let (y0, y1) = if y0.is_finite() { (y0 / 1.5, y1 * 1.5) } else { (0.1, 100.0) };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (960, 640)).into_drawing_area();
        let e = |e: plotters::drawing::DrawingAreaErrorKind<_>| plot_error(path, e);
        root.fill(&WHITE).map_err(e)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (x0..x1).log_scale().with_key_points(one_two_five(x0, x1)),
                (y0..y1).log_scale().with_key_points(one_two_five(y0, y1)),
            )
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("wall time (s): the mesh's run; adaptive: cumulative")
            .y_desc("relative error (%)")
            .x_label_formatter(&|v| short_number(*v))
            .y_label_formatter(&|v| short_number(*v))
            .light_line_style(RGBColor(0xEE, 0xEE, 0xEE))
            .draw()
            .map_err(e)?;
        let positive = |p: &(f64, f64)| p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite();
        for (series, colour) in SERIES {
            let mine: Vec<&&AccuracyRow> = plotted.iter().filter(|r| r.series == series).collect();
            let est: Vec<(f64, f64)> =
                mine.iter().map(|r| (r.cumulative_seconds, r.estimate_percent)).filter(positive).collect();
            if !est.is_empty() {
                chart
                    .draw_series(LineSeries::new(est.clone(), colour.stroke_width(2)))
                    .map_err(e)?
                    .label(format!("{series}: estimate"))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
                chart.draw_series(est.iter().map(|p| Circle::new(*p, 4, colour.filled()))).map_err(e)?;
            }
            let truth: Vec<(f64, f64)> = mine
                .iter()
                .filter_map(|r| r.true_percent.map(|t| (r.cumulative_seconds, t)))
                .filter(positive)
                .collect();
            if !truth.is_empty() {
                chart
                    .draw_series(DashedLineSeries::new(truth.clone(), 6, 4, colour.stroke_width(2)))
                    .map_err(e)?
                    .label(format!("{series}: true error"))
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 8, y)], colour.stroke_width(2)));
                chart.draw_series(truth.iter().map(|p| Circle::new(*p, 4, colour.stroke_width(2)))).map_err(e)?;
            }
        }
        let solvers: Vec<(f64, f64, String)> = plotted
            .iter()
            .filter(|r| r.series == "solver")
            .map(|r| (r.cumulative_seconds, r.estimate_percent, r.label.clone()))
            .filter(|(x, y, _)| positive(&(*x, *y)))
            .collect();
        if !solvers.is_empty() {
            chart
                .draw_series(solvers.iter().map(|(x, y, _)| TriangleMarker::new((*x, *y), 6, BLACK.filled())))
                .map_err(e)?
                .label("contact solvers on one P1 mesh: estimate (key below)")
                .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLACK.filled()));
            // The points share one error: numbered (staggered above the points), with a key in
            // the lower left corner, where a work-precision diagram has no data.
            for (k, (x, y, _)) in solvers.iter().enumerate() {
                let dy = -18 - 12 * (k as i32 % 3);
                chart
                    .draw_series(std::iter::once(
                        EmptyElement::at((*x, *y)) + Text::new(format!("{}", k + 1), (-3, dy), ("sans-serif", 12)),
                    ))
                    .map_err(e)?;
            }
            let key: Vec<String> = solvers.iter().enumerate().map(|(k, (_, _, n))| format!("{} {n}", k + 1)).collect();
            for (line, text) in key.chunks(4).rev().enumerate() {
                chart
                    .draw_series(std::iter::once(
                        EmptyElement::at((x0, y0))
                            + Text::new(text.join(", "), (8, -14 - 16 * line as i32), ("sans-serif", 12)),
                    ))
                    .map_err(e)?;
            }
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;
        root.present().map_err(e)?;
    }
    output::write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

/// Write `bench_accuracy.md` and (when a point was measured) `bench_accuracy.svg` into `dir`.
pub fn write_accuracy_outputs(
    results: &[AccuracyCaseResult],
    record: &BenchRecord,
    dir: &Path,
    scene_name: &str,
) -> Result<Vec<PathBuf>> {
    let md = dir.join("bench_accuracy.md");
    let heading = format!("Benchmark: error against run time ({scene_name})");
    let text = record.markdown(&heading, &accuracy_table(results));
    output::write_atomically(&md, |w| w.write_all(text.as_bytes()))?;
    let rows: Vec<AccuracyRow> = results.iter().flat_map(|r| r.rows.iter().cloned()).collect();
    let svg = dir.join("bench_accuracy.svg");
    if !rows.iter().any(|r| r.series != "reference") {
        let _ = std::fs::remove_file(&svg);
        return Ok(vec![md]);
    }
    write_accuracy_svg(&svg, &format!("Error against run time: {scene_name}"), &rows)?;
    Ok(vec![md, svg])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(series: &str, label: &str, dofs: usize, time: f64, estimate: f64, truth: Option<f64>) -> AccuracyRow {
        AccuracyRow {
            series: series.into(),
            label: label.into(),
            elements: dofs,
            dofs,
            contact_points: 8,
            mesh_seconds: 0.0,
            primal_seconds: time / 2.0,
            dual_seconds: time / 2.0,
            estimate_seconds: 0.0,
            remesh_seconds: 0.0,
            run_seconds: time,
            cumulative_seconds: time,
            estimate_percent: estimate,
            true_percent: truth,
            energy_norm: None,
        }
    }

    fn one(row: AccuracyRow) -> AccuracyCaseResult {
        AccuracyCaseResult { rows: vec![row], failure: None, note: None }
    }

    fn results() -> Vec<AccuracyCaseResult> {
        let mut reference = row("reference", "P2, h = 1e-3", 40_000, 3.0, 0.0, None);
        reference.energy_norm = Some(2.5);
        vec![
            one(reference),
            one(row("uniform P1", "h = 4e-3", 100, 0.1, 20.0, Some(19.0))),
            one(row("uniform P1", "h = 2e-3", 400, 0.3, 10.0, Some(9.5))),
            one(row("uniform P2", "h = 4e-3", 400, 0.2, 8.0, Some(7.9))),
            one(row("uniform P2", "h = 2e-3", 1600, 0.5, 4.0, Some(3.9))),
            AccuracyCaseResult {
                rows: vec![
                    row("adaptive P1", "step 0", 100, 0.1, 20.0, None),
                    row("adaptive P1", "step 1", 300, 0.6, 6.0, None),
                ],
                failure: Some("step 2: the dual failed".into()),
                note: None,
            },
            AccuracyCaseResult {
                rows: vec![row("adaptive P2", "step 0", 400, 0.2, 8.0, None)],
                failure: None,
                note: Some("target 1.000 % NOT reached: 8.000 % on 400 elements".into()),
            },
            one(row("solver", "uzawa", 400, 0.4, 10.0, Some(9.5))),
        ]
    }

    #[test]
    fn the_table_has_one_row_per_point_the_rates_and_the_failures() {
        let t = accuracy_table(&results());
        let body: Vec<&str> = t.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| series")).collect();
        assert_eq!(body.len(), 8, "{t}");
        assert!(t.contains("Reference: P2, h = 1e-3 (40000 elements"), "{t}");
        assert!(t.contains("| uniform P1 | h = 2e-3 | 400 | 400 | 8 |"), "{t}");
        assert!(t.contains("| 20.000 | – | – |"), "adaptive step without a true error: {t}");
        // 20 % -> 10 % for 4x the dofs: rate 0.5.
        assert!(t.contains("uniform P1 0.50") && t.contains("uniform P2 0.50"), "{t}");
        // The reference (40000 dofs) from P2's 4 % at 1600 dofs at rate 0.5: 0.8 %.
        assert!(t.contains("about 0.800 %"), "{t}");
        assert!(t.contains("adaptive P1 failed after 2 step(s): step 2: the dual failed"), "{t}");
        assert!(t.contains("adaptive P2: target 1.000 % NOT reached"), "{t}");
    }

    #[test]
    fn the_plot_draws_every_series_in_one_svg() {
        let dir = std::env::temp_dir().join(format!("signorini-bench-accuracy-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let record = BenchRecord::new("signorini bench accuracy".into());
        let written = write_accuracy_outputs(&results(), &record, &dir, "test scene").unwrap();
        assert_eq!(written.len(), 2);
        let svg = std::fs::read_to_string(dir.join("bench_accuracy.svg")).unwrap();
        for label in
            ["uniform P1: estimate", "uniform P1: true error", "adaptive P1: estimate", "uzawa", "contact solvers"]
        {
            assert!(svg.contains(label), "{label} missing");
        }
        // A dashed line is one <polyline> per dash: without the true errors, far fewer.
        let mut no_truth = results();
        no_truth.iter_mut().flat_map(|r| r.rows.iter_mut()).for_each(|r| r.true_percent = None);
        write_accuracy_outputs(&no_truth, &record, &dir, "test scene").unwrap();
        let plain = std::fs::read_to_string(dir.join("bench_accuracy.svg")).unwrap();
        assert!(!plain.contains("true error"));
        assert!(svg.matches("<polyline").count() > plain.matches("<polyline").count() + 10, "no dashed line");
        let md = std::fs::read_to_string(dir.join("bench_accuracy.md")).unwrap();
        assert!(md.starts_with("# Benchmark: error against run time (test scene)") && md.contains("- date: "));
        // No point at all: the table alone.
        let none = vec![AccuracyCaseResult { rows: Vec::new(), failure: None, note: None }];
        assert_eq!(write_accuracy_outputs(&none, &record, &dir, "x").unwrap().len(), 1);
        assert!(!dir.join("bench_accuracy.svg").exists());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn log_ticks_are_one_two_five() {
        assert_eq!(one_two_five(0.15, 12.0), vec![0.2, 0.5, 1.0, 2.0, 5.0, 10.0]);
        assert!(one_two_five(0.0, 1.0).is_empty());
        assert_eq!(short_number(0.05), "0.05");
        assert_eq!(short_number(0.2), "0.2");
        assert_eq!(short_number(5.0), "5");
        assert_eq!(short_number(2.5), "2.5");
        assert_eq!(short_number(20.0), "20");
    }

    #[test]
    fn solvers_follow_the_friction_law() {
        assert!(solvers_for(None).is_empty());
        assert!(solvers_for(Some(&FrictionSpec::Tresca { threshold: 1.0 })).contains(&"tao"));
        assert!(!solvers_for(Some(&FrictionSpec::Coulomb { mu: 0.3 })).contains(&"tao"));
    }
}
