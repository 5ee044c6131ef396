//! # The adaptive loop: solve, estimate, size map, remesh, until the target error
//!
//! After F. Lebon, "Modèles d'interface et formulations pour le contact frottant : résultats et
//! calcul d'erreur" (slides "Adaptation de maillage"), one step on a mesh `T_k` is
//!
//! ```text
//!   1. u_h   primal solution on T_k                       (ElasticityProblem::solve)
//!   2. σ_h   dual (Airy/HCT) solution on T_k              (ElasticityProblem::solve_dual)
//!   3. e_E   error in the constitutive relation per cell  (ElasticityProblem::estimate)
//!            ε_k = e / ‖½(σ_h + Cε(u_h))‖   (relative, in percent)
//!   4. stop when ε_k ≤ ε_0 (the target), or after max_steps meshes
//!   5. r_E   optimal ratios for the absolute target e_0 = ε_0 ‖½(σ_h + Cε(u_h))‖ with the
//!            a priori rates p_E (super::size_map): minimise Σ r_E^{−2} subject to
//!            Σ e_E² r_E^{2p_E} = e_0²,  clamped to [min_ratio, max_ratio]
//!   6. T_k+1 Gmsh remeshes the scene's geometry with the sizes h*_E = r_E h_E as a background
//!            view (super::remesh): refines and coarsens, boundary nodes on the true curves.
//! ```
//!
//! The a priori rates are an input ([`RateModel`]): `p = 1` in the volume for elasticity
//! (primal P1 and dual HCT alike; `p = 2` for P2), and a rate per boundary part for the cells
//! that touch it — for the contact part, `2/3` (primal, Coulomb) or `1/2` (dual, Tresca), the
//! talk's values. The loop
//! consumes only the per-cell errors of the [`crate::estimate::Estimate`]; when the dual
//! formulation gains contact, its contact terms reach the size map through those errors unchanged.
//!
//! The a priori model is asymptotic: near a singularity (a re-entrant corner, the end of a
//! clamped edge) the true local rate is below `p`, the first remeshing under-refines there and
//! more steps are needed; the talk's runs with `p = 1` oscillate around the target (13.80 %,
//! 8.35 %, 7.24 %, 7.51 %, 7.25 % for 6.91 %). A step whose error grows is recorded
//! ([`AdaptStep::error_grew`]), never hidden.
//!
//! **Aiming below the target.** The size map of step `k` predicts an error `ẽ_k+1` (the aim,
//! unless the clamps forbid it); step `k+1` measures `e_k+1`. Their ratio
//! `b = e_k+1 / ẽ_k+1` is the bias of the a priori model on this problem (above 1 near
//! singularities), so step `k+1` aims at `ε_0 / √b` (damped, since the first meshes are
//! pre-asymptotic; `1 ≤ √b ≤ 1.5`) instead of `ε_0`. This choice is ours, not the talk's:
//! without it the loop creeps towards the target from above (8.16 %, 8.02 %, … for 8 % on
//! `examples/scenes/clamped_block.toml` refined in its middle); undamped, it overshoots.
//!
//! The library writes the files of each step (`step_K/solution.vtu` with the cell data `error`
//! and `target_size`, `step_K/report.json`) and reports progress through a callback; it never
//! prints. [`super::report`] writes the summary (`adapt.json`, `adapt.md`, `adapt.svg`).
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::remesh::{element_sizes, remesh};
use super::size_map::{optimal_size_map, SizeMapLimits};
use crate::error::{Error, Result};
use crate::estimate::EstimateKind;
use crate::mesh::gmsh::{MeshRequest, Refinement, Shape};
use crate::mesh::Mesh;
use crate::output;
use crate::petsc::Session;
use crate::problem::ElasticityProblem;
use crate::scene::{MeshSpec, Scene};

/// A priori convergence rates `p_E` of the element errors, `e_E = O(h_E^{p_E})`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct RateModel {
    /// The rate of every cell that touches none of `parts` (1 for elasticity).
    pub volume: f64,
    /// `(boundary part, rate)`: the rate of the cells with an edge on that part (the smallest
    /// applies when a cell touches several).
    pub parts: Vec<(String, f64)>,
}

impl RateModel {
    /// `p = 1` everywhere: elasticity, primal P1 or dual HCT.
    pub fn uniform(p: f64) -> Self {
        RateModel { volume: p, parts: Vec::new() }
    }

    /// The rates for a scene: the element degree in the volume (1 for P1, the talk's value;
    /// 2 for P2, whose primal and HCT dual errors both fall as h² where the solution is
    /// smooth) and, with a `[contact]` section, `1/2` on the cells of the contact part (the
    /// dual Tresca rate, which the talk found the better choice for frictional contact: fewer
    /// steps to the target).
    pub fn for_scene(scene: &Scene) -> Self {
        let mut model = RateModel::uniform(scene.order.degree() as f64);
        if let Some(c) = &scene.contact {
            model.parts.push((c.part.clone(), 0.5));
        }
        model
    }

    /// `p_E` per cell of `mesh`.
    pub fn cell_rates(&self, mesh: &Mesh) -> Result<Vec<f64>> {
        let positive = |p: f64| p.is_finite() && p > 0.0;
        if !positive(self.volume) || self.parts.iter().any(|(_, p)| !positive(*p)) {
            return Err(Error::Usage(format!("a priori rates must be finite and positive, got {self:?}")));
        }
        let mut rates = vec![self.volume; mesh.num_cells()];
        if self.parts.is_empty() {
            return Ok(rates);
        }
        let owner = boundary_edge_cells(mesh);
        for (part, p) in &self.parts {
            let group = mesh.require_group(part, 1)?;
            for e in mesh.edges_in_group(group) {
                if let Some(c) = owner[e] {
                    rates[c] = rates[c].min(*p);
                }
            }
        }
        Ok(rates)
    }
}

/// The cell of each boundary edge (by its end vertices), `None` for an edge no cell has.
pub fn boundary_edge_cells(mesh: &Mesh) -> Vec<Option<usize>> {
    let key = |a: usize, b: usize| if a < b { (a, b) } else { (b, a) };
    let mut by_vertices = std::collections::HashMap::with_capacity(mesh.num_edges());
    for e in 0..mesh.num_edges() {
        let v = mesh.edge(e);
        by_vertices.insert(key(v[0], v[1]), e);
    }
    let mut owner = vec![None; mesh.num_edges()];
    for c in 0..mesh.num_cells() {
        let v = mesh.cell(c);
        for k in 0..3 {
            if let Some(&e) = by_vertices.get(&key(v[k], v[(k + 1) % 3])) {
                owner[e] = Some(c);
            }
        }
    }
    owner
}

/// What the loop aims at and how far it may go.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AdaptOptions {
    /// The target relative error ε_0, percent of the energy norm (> 0).
    pub target_percent: f64,
    /// The most meshes solved, the first included (≥ 1).
    pub max_steps: usize,
    /// Clamps of the reduction ratios per step.
    #[serde(serialize_with = "serialize_limits")]
    pub limits: SizeMapLimits,
    /// The a priori model of the error's decrease with the element size.
    pub rates: RateModel,
    /// The loop stops (status `element_limit`) rather than remesh to more predicted elements.
    pub max_elements: usize,
}

fn serialize_limits<S: serde::Serializer>(l: &SizeMapLimits, s: S) -> std::result::Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let mut m = s.serialize_map(Some(2))?;
    m.serialize_entry("min_ratio", &l.min_ratio)?;
    m.serialize_entry("max_ratio", &l.max_ratio)?;
    m.end()
}

impl AdaptOptions {
    /// The defaults for a scene: 8 steps, ratios in [1/10, 4], the scene's rates, 2e6 elements.
    pub fn new(scene: &Scene, target_percent: f64) -> Self {
        AdaptOptions {
            target_percent,
            max_steps: 8,
            limits: SizeMapLimits::default(),
            rates: RateModel::for_scene(scene),
            max_elements: 2_000_000,
        }
    }

    fn check(&self) -> Result<()> {
        if !(self.target_percent.is_finite() && self.target_percent > 0.0 && self.target_percent < 100.0) {
            return Err(Error::Usage(format!(
                "adapt: the target error must be a percentage between 0 and 100 (exclusive), got {}",
                self.target_percent
            )));
        }
        if self.max_steps == 0 {
            return Err(Error::Usage("adapt: --max-steps must be at least 1 (the first mesh is a step)".into()));
        }
        if self.max_elements == 0 {
            return Err(Error::Usage("adapt: the element limit must be at least 1".into()));
        }
        Ok(())
    }
}

/// Seconds of each phase of one step.
#[derive(Debug, Clone, Copy, Default, serde::Serialize)]
pub struct StepSeconds {
    /// Building the problem on the step's mesh (the first step: meshing the scene too).
    pub mesh: f64,
    /// Primal assembly, solve and post-processing.
    pub solve: f64,
    /// The dual (stress) solve.
    pub dual: f64,
    /// The error estimate.
    pub estimate: f64,
    /// The size map and the Gmsh remeshing that make the next step's mesh (0 on the last).
    pub remesh: f64,
    /// Writing the step's files.
    pub output: f64,
}

impl StepSeconds {
    /// Seconds of the whole step.
    pub fn total(&self) -> f64 {
        self.mesh + self.solve + self.dual + self.estimate + self.remesh + self.output
    }
}

/// The size map computed from a step's estimate.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SizeMapSummary {
    /// The relative error the map aims at: the target, lowered by the bias of the a priori
    /// model measured on the previous remeshing (see the module doc).
    pub aim_percent: f64,
    /// The absolute error `e_0` the map aims at.
    pub target_error: f64,
    /// The error and element count the a priori model predicts on the new mesh.
    pub predicted_error: f64,
    /// Elements the model predicts on the new mesh.
    pub predicted_elements: f64,
    /// Cells to refine (`r_E < 1`) and to coarsen (`r_E > 1`).
    pub refined: usize,
    /// Cells to coarsen.
    pub coarsened: usize,
    /// Smallest reduction ratio `r_E` of the map.
    pub min_ratio: f64,
    /// Largest reduction ratio `r_E`.
    pub max_ratio: f64,
    /// The clamps keep the predicted error above the target: more steps are needed.
    pub target_unreachable: bool,
}

/// One step of the loop.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AdaptStep {
    /// 0 for the scene's own mesh.
    pub step: usize,
    /// Mesh triangles.
    pub elements: usize,
    /// Mesh nodes.
    pub nodes: usize,
    /// Displacement unknowns.
    pub dofs: usize,
    /// `e`, absolute (energy units^½).
    pub error: f64,
    /// `ε = 100 e / ‖½(σ_h + Cε(u_h))‖`.
    pub error_percent: f64,
    /// `‖½(σ_h + Cε(u_h))‖`, the denominator of `error_percent`.
    pub reference_norm: f64,
    /// Guaranteed bound or estimator (Coulomb friction).
    pub kind: EstimateKind,
    /// Seconds of each phase of the step.
    pub seconds: StepSeconds,
    /// Run time from the start of the loop to the end of this step's estimate.
    pub cumulative_seconds: f64,
    /// The error is larger than the previous step's.
    pub error_grew: bool,
    /// The size map made from the step's estimate.
    pub size_map: SizeMapSummary,
    /// The step's directory (`step_K`).
    pub dir: PathBuf,
}

/// Why the loop stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AdaptStatus {
    /// The last step's error is at most the target.
    Reached,
    /// `max_steps` meshes were solved without reaching the target.
    MaxSteps,
    /// The size map asked for more than `max_elements` elements.
    ElementLimit,
    /// A step after the first failed (its solve, the dual's independent check, the estimate,
    /// or the remeshing): the steps before it are kept, `failure` says why.
    Failed,
}

/// The whole run (`adapt.json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct AdaptOutcome {
    /// The program and its version.
    pub program: String,
    /// The scene's source.
    pub scene: String,
    /// The scene's title.
    pub title: Option<String>,
    /// The options of the run.
    pub options: AdaptOptions,
    /// Why the loop stopped.
    pub status: AdaptStatus,
    /// Whether the target error was reached.
    pub reached: bool,
    /// The last step's relative error (percent).
    pub final_error_percent: f64,
    /// Plain statements of what went wrong: a step whose error grew, a target not reached.
    pub warnings: Vec<String>,
    /// Every step, the scene's own mesh first.
    pub steps: Vec<AdaptStep>,
    /// `adapt_mesh.svg`: the last mesh coloured by the element size, with a zoom on the cell of
    /// largest error (not drawn above [`MESH_PICTURE_CELLS`] cells).
    pub mesh_picture: Option<PathBuf>,
    /// With [`AdaptStatus::Failed`]: which step failed and the error's text.
    pub failure: Option<String>,
    /// With [`AdaptStatus::Failed`]: the error itself, for the caller to report (the CLI exits
    /// with it after writing the files of the steps that were done).
    #[serde(skip)]
    pub error: Option<std::sync::Arc<Error>>,
}

/// The largest mesh `adapt_mesh.svg` is drawn for (an SVG of about 150 bytes per cell).
pub const MESH_PICTURE_CELLS: usize = 50_000;

/// The Gmsh request that meshes the scene's geometry (its own cell size and refinement). A
/// scene whose mesh is read from a file has a geometry only with `geometry = "part.geo"`, and
/// only for `adapt` (the remeshing takes its sizes from the size map; `study` needs a cell
/// size to halve).
pub fn mesh_request(scene: &Scene, command: &'static str) -> Result<MeshRequest> {
    let refinement = |r: &Option<crate::scene::RefineSpec>| {
        r.as_ref().map(|r| Refinement { point: r.point, cell_size: r.cell_size, radius: r.radius })
    };
    let (shape, cell_size, refine) = match &scene.mesh {
        MeshSpec::Rectangle { origin, size, cell_size, refine, .. } => {
            (Shape::Rectangle { origin: *origin, size: *size }, *cell_size, refinement(refine))
        }
        MeshSpec::Disc { center, radius, cell_size, refine } => {
            (Shape::Disc { center: *center, radius: *radius }, *cell_size, refinement(refine))
        }
        MeshSpec::HalfDisc { center, radius, cell_size, refine } => {
            (Shape::HalfDisc { center: *center, radius: *radius }, *cell_size, refinement(refine))
        }
        MeshSpec::QuarterDisc { center, radius, cell_size, refine } => {
            (Shape::QuarterDisc { center: *center, radius: *radius }, *cell_size, refinement(refine))
        }
        MeshSpec::File { path, geometry: Some(geometry) } if command == "adapt" => {
            let script =
                std::fs::read_to_string(geometry).map_err(|e| Error::io(geometry, "reading the geometry script", e))?;
            (Shape::Geometry { script, file: geometry.clone() }, f64::NAN, None)
        }
        MeshSpec::File { path, .. } => {
            return Err(Error::NeedsGeometry { scene: scene.source.clone(), file: path.clone(), command })
        }
    };
    Ok(MeshRequest { shape, cell_size, refinement: refine, order: scene.order })
}

/// Remove what an earlier adapt run left in `dir`: `adapt.json`, `adapt.md`, `adapt.svg` and
/// the result files of its `step_K` directories (then the directories, if empty).
pub fn clear_previous_adapt(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut removed = Vec::new();
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(removed);
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        let path = entry.path();
        let is_step =
            name.strip_prefix("step_").is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()));
        if is_step && path.is_dir() {
            removed.extend(output::clear_previous_run(&path)?);
            let _ = std::fs::remove_dir(&path); // only if now empty
        } else if super::report::ADAPT_FILES.contains(&name.as_str()) {
            std::fs::remove_file(&path).map_err(|e| Error::io(&path, "removing the previous adapt run's file", e))?;
            removed.push(path);
        }
    }
    removed.sort();
    Ok(removed)
}

/// Run the adaptive loop on `scene`, writing each step's files under `out` (`step_K/`), and
/// calling `on_step` after each step. The summary files are written by
/// [`super::report::write_adapt_outputs`].
pub fn adapt(
    session: &Session,
    scene: &Scene,
    options: &AdaptOptions,
    out: &Path,
    on_step: &mut dyn FnMut(&AdaptStep),
) -> Result<AdaptOutcome> {
    adapt_inspecting(session, scene, options, out, on_step, &mut |_, _| Ok(()))
}

/// [`adapt`], calling `inspect(k, problem)` on each step's solved problem (primal, dual and
/// estimate done) before its size map; its time is in none of the step's phases (the accuracy
/// benchmark measures true errors there).
pub fn adapt_inspecting(
    session: &Session,
    scene: &Scene,
    options: &AdaptOptions,
    out: &Path,
    on_step: &mut dyn FnMut(&AdaptStep),
    inspect: &mut dyn FnMut(usize, &ElasticityProblem) -> Result<()>,
) -> Result<AdaptOutcome> {
    options.check()?;
    crate::problem::axisymmetry::refuse_in_axisymmetry(scene, "mesh adaptation (signorini adapt)")?;
    let request = mesh_request(scene, "adapt")?;
    let mut steps: Vec<AdaptStep> = Vec::new();
    let mut warnings = Vec::new();
    let mut next_mesh: Option<Mesh> = None;
    let mut cumulative = 0.0;
    let mut status = AdaptStatus::MaxSteps;
    let mut mesh_picture = None;
    let mut failure: Option<(usize, Error)> = None;
    // An error of a step after the first ends the loop with the steps done (status Failed);
    // the first step's error is the run's.
    macro_rules! attempt {
        ($k:expr, $e:expr) => {
            match $e {
                Ok(v) => v,
                Err(e) if steps.is_empty() => return Err(e),
                Err(e) => {
                    failure = Some(($k, e));
                    break;
                }
            }
        };
    }
    for k in 0..options.max_steps {
        let mut seconds = StepSeconds::default();
        let start = Instant::now();
        let mut problem = attempt!(
            k,
            match next_mesh.take() {
                None => ElasticityProblem::setup_system(session, scene.clone()),
                Some(mesh) => ElasticityProblem::setup_with_mesh(session, scene.clone(), mesh),
            }
        );
        seconds.mesh = start.elapsed().as_secs_f64();
        let start = Instant::now();
        attempt!(k, problem.assemble().and_then(|_| problem.solve()).and_then(|_| problem.postprocess()));
        seconds.solve = start.elapsed().as_secs_f64();
        let start = Instant::now();
        attempt!(k, problem.solve_dual());
        seconds.dual = start.elapsed().as_secs_f64();
        let start = Instant::now();
        attempt!(k, problem.estimate());
        seconds.estimate = start.elapsed().as_secs_f64();
        let report = attempt!(
            k,
            problem.estimate.clone().ok_or_else(|| Error::PetscUsage("adapt: the estimate was not computed".into()))
        );
        let estimate = &report.estimate;
        cumulative += seconds.mesh + seconds.solve + seconds.dual + seconds.estimate;
        attempt!(k, inspect(k, &problem));

        // The size map (also on the last step: its target_size field shows the next mesh).
        let start = Instant::now();
        // The a priori model's bias, measured on the last remeshing: it aimed at `predicted`
        // and reached `estimate`; aim lower by the square root of that factor (damped: the
        // first meshes are pre-asymptotic), by at most 1.5.
        let bias = steps.last().map_or(1.0, |p: &AdaptStep| {
            let predicted = 100.0 * p.size_map.predicted_error / p.reference_norm;
            (estimate.relative_percent / predicted).sqrt().clamp(1.0, 1.5)
        });
        let aim_percent = options.target_percent / bias;
        let target_error = aim_percent / 100.0 * estimate.reference_norm;
        let rates = options.rates.cell_rates(&problem.mesh)?;
        let errors = estimate.element_error();
        let map = optimal_size_map(&errors, &rates, target_error.max(f64::MIN_POSITIVE), options.limits)?;
        let h = element_sizes(&problem.mesh);
        let largest = problem.mesh.diagonal() / 4.0;
        let targets: Vec<f64> = h.iter().zip(&map.ratios).map(|(h, r)| (h * r).min(largest.max(*h))).collect();
        let size_map = SizeMapSummary {
            aim_percent,
            target_error,
            predicted_error: map.predicted_error,
            predicted_elements: map.predicted_elements,
            refined: map.ratios.iter().filter(|&&r| r < 1.0).count(),
            coarsened: map.ratios.iter().filter(|&&r| r > 1.0).count(),
            min_ratio: map.ratios.iter().cloned().fold(f64::INFINITY, f64::min),
            max_ratio: map.ratios.iter().cloned().fold(0.0, f64::max),
            target_unreachable: map.target_unreachable,
        };
        let map_seconds = start.elapsed().as_secs_f64();

        let start = Instant::now();
        let dir = out.join(format!("step_{k}"));
        // Rank 0 writes; its outcome is agreed before the report (collective).
        let wrote = if session.rank() == 0 {
            problem.write_solution_vtu(&dir.join("solution.vtu"), &[("target_size", &targets)])
        } else {
            Ok(())
        };
        session.agree(wrote, "writing an adaptation step's solution")?;
        let step_report = problem.report()?; // collective
        if session.rank() == 0 {
            output::write_json(&dir.join("report.json"), &step_report)?;
        }
        seconds.output = start.elapsed().as_secs_f64();

        let previous = steps.last().map(|s: &AdaptStep| s.error_percent);
        let error_grew = previous.is_some_and(|p| estimate.relative_percent > p);
        if let Some(p) = previous.filter(|_| error_grew) {
            warnings.push(format!(
                "step {k}: the error grew from {p:.3} % to {:.3} % (the a priori rates are asymptotic; near a \
                 singularity the first remeshings under-refine)",
                estimate.relative_percent
            ));
        }
        let reached = estimate.relative_percent <= options.target_percent;
        let last = k + 1 == options.max_steps;
        let too_many = map.predicted_elements > options.max_elements as f64;
        if (reached || last || too_many) && session.rank() == 0 && problem.mesh.num_cells() <= MESH_PICTURE_CELLS {
            let path = out.join("adapt_mesh.svg");
            let title = format!(
                "{}: step {k}, {} elements, error {:.3} %",
                scene.title.as_deref().unwrap_or("adapted mesh"),
                problem.mesh.num_cells(),
                estimate.relative_percent
            );
            // Coloured by the element size; the zoom frames the cell with the largest error
            // (where the map refines most), a 75th of the diagonal wide.
            let worst = (0..errors.len()).max_by(|&a, &b| errors[a].total_cmp(&errors[b])).unwrap_or(0);
            let v = problem.mesh.cell(worst);
            let c = problem.mesh.nodes[v[0]];
            let half = problem.mesh.diagonal() / 150.0;
            let zoom = [c[0] - half, c[0] + half, c[1] - half, c[1] + half];
            output::mesh_plot::write_mesh_svg(&path, &problem.mesh, &h, &title, "element size h_E (m)", Some(zoom))?;
            mesh_picture = Some(path);
        }
        let mut next = None;
        let mut remesh_failure = None;
        if !reached && !last && !too_many {
            let start = Instant::now();
            // Rank 0 alone remeshes (Gmsh) and sends the mesh to the other ranks: agreed, so
            // that its failure ends every rank's loop here (status Failed on every rank).
            let remeshed = crate::mesh::shared::from_rank_0(session, "remeshing", || {
                remesh(&problem.mesh, &request, &targets).map(|mesh| (mesh, None))
            });
            match remeshed {
                Ok((mesh, _)) => next = Some(mesh),
                Err(e) => remesh_failure = Some(e),
            }
            seconds.remesh = map_seconds + start.elapsed().as_secs_f64();
        }
        let step = AdaptStep {
            step: k,
            elements: problem.mesh.num_cells(),
            nodes: problem.mesh.num_nodes(),
            dofs: problem.num_dofs(),
            error: estimate.error,
            error_percent: estimate.relative_percent,
            reference_norm: estimate.reference_norm,
            kind: estimate.kind,
            seconds,
            cumulative_seconds: cumulative,
            error_grew,
            size_map,
            dir,
        };
        cumulative += seconds.remesh + seconds.output;
        on_step(&step);
        steps.push(step);
        if let Some(e) = remesh_failure {
            failure = Some((k + 1, e));
            break;
        }
        if reached {
            status = AdaptStatus::Reached;
            break;
        }
        if too_many && !last {
            status = AdaptStatus::ElementLimit;
            warnings.push(format!(
                "target {:.3} % not reached: the size map asks for about {:.3e} elements, above the limit of {}",
                options.target_percent, map.predicted_elements, options.max_elements
            ));
            break;
        }
        next_mesh = next;
    }
    let final_error_percent = steps.last().map_or(f64::NAN, |s| s.error_percent);
    let failure = failure.map(|(k, e)| {
        status = AdaptStatus::Failed;
        let text = format!("step {k} failed: {e}");
        warnings.push(format!(
            "stopped at step {k}: {}; the {} step(s) before it are written",
            e.to_string().lines().next().unwrap_or(""),
            steps.len()
        ));
        (text, std::sync::Arc::new(e))
    });
    if status == AdaptStatus::MaxSteps {
        warnings.push(format!(
            "target {:.3} % not reached in {} step(s): the last error is {final_error_percent:.3} %",
            options.target_percent, options.max_steps
        ));
    }
    Ok(AdaptOutcome {
        program: format!("signorini {} ({})", env!("CARGO_PKG_VERSION"), env!("SIGNORINI_COMMIT")),
        scene: scene.source.display().to_string(),
        title: scene.title.clone(),
        options: options.clone(),
        status,
        reached: status == AdaptStatus::Reached,
        final_error_percent,
        warnings,
        steps,
        mesh_picture,
        failure: failure.as_ref().map(|(text, _)| text.clone()),
        error: failure.map(|(_, e)| e),
    })
}
