//! The load-path benchmark (`signorini bench evolution`): what a path of increments costs
//! against one linear solve and one static contact solve of the same mesh.
//!
//! - `press-then-push`: the square block (P1, Coulomb μ = 1) pressed, then pushed, in 20
//!   increments. Target: the whole path (its load cases, the factorisation, W, every increment,
//!   no output) within one linear solve plus 0.3 linear solves per increment.
//! - `fretting`: two identical P2 cylinders pressed, then sheared through a full cycle
//!   (`tests/petsc_cases/evolution.rs`), 40 increments. Target: under 10 static contact solves
//!   of the same scene at its peak load (the default route).
//!
//! Each case runs in a child process; times are the better of two runs of each part.
use std::path::Path;

use crate::error::{Error, Result};
use crate::evolution::LoadPath;
use crate::petsc::Session;
use crate::problem::ElasticityProblem;
use crate::resources;
use crate::scene::Scene;

/// The two paths (case index 0, 1).
pub static PATHS: &[&str] = &["press-then-push", "fretting"];

/// Increments of each path.
pub const INCREMENTS: [usize; 2] = [20, 40];

/// One row of the load-path benchmark.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct EvolutionBenchRow {
    /// Displacement unknowns.
    pub dofs: usize,
    /// Contact points.
    pub contact_points: usize,
    /// `"press-then-push"` or `"fretting"`.
    pub path: String,
    /// Converged increments.
    pub increments: usize,
    /// Contact solver iterations over the path.
    pub iterations: usize,
    /// Seconds of the whole path (load cases, factorisation, W, increments; no output).
    pub path_seconds: f64,
    /// One linear solve of the same mesh (factorisation and solve).
    pub linear_seconds: f64,
    /// One static contact solve of the scene at its final loads (the default route).
    pub static_contact_seconds: f64,
    /// The path's energy balance residual (relative to the work).
    pub energy_residual: f64,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
}

/// Sizes 1e4 and 1e5 dofs (up to `max_dofs`), both paths.
pub fn evolution_cases(max_dofs: usize) -> Vec<(usize, usize, String)> {
    let mut cases = Vec::new();
    for n in [10_000, 100_000].into_iter().filter(|&n| n <= max_dofs) {
        for (k, p) in PATHS.iter().enumerate() {
            cases.push((n, k, p.to_string()));
        }
    }
    cases
}

/// The square block, `cells` squares per side, its two pressures named; the path's
/// `[evolution]` when `increments` is given.
fn square_block(cells: usize, increments: Option<usize>) -> String {
    let mut text = format!(
        "title = \"square block, pressed then pushed\"\n\
         [mesh]\nshape = \"rectangle\"\nsize = [0.04, 0.04]\ncell_size = {:e}\nmesher = \"structured\"\n\
         [discretization]\norder = 1\n\
         [material]\nyoung = 1.3e11\npoisson = 0.2\nplane = \"strain\"\n\
         [[traction]]\npart = \"top\"\npressure = 5e7\nname = \"press\"\n\
         [[traction]]\npart = \"left\"\npressure = 1.5e8\nname = \"push\"\n\
         [[dirichlet]]\npart = \"right\"\nux = 0.0\n\
         [[dirichlet]]\npoint = [0.04, 0.0]\nux = 0.0\nuy = 0.0\n\
         [contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
         friction = \"coulomb\"\nmu = 1.0\n",
        0.04 / cells as f64
    );
    if let Some(n) = increments {
        text.push_str(&format!(
            "[evolution]\nsteps = {n}\n[evolution.factor]\npress = [[0, 0], [1, 1], [2, 1]]\npush = [[0, 0], [1, 0], [2, 1]]\n"
        ));
    }
    text
}

/// Two identical P2 steel cylinders (radius 0.1 m), cells of `fine` within 0.015 m of the
/// contact and `coarse` away; the upper flat side pressed by 1e-3 m and sheared by 2.5e-4 m;
/// with `increments`, the fretting path (press on t ∈ [0, 1], shear 0 → 1 → −1 → 1 on [1, 6]).
fn fretting(coarse: f64, fine: f64, increments: Option<usize>) -> String {
    let body = |name: &str, placement: &str, center: f64, refine_y: f64, loads: &str| {
        format!(
            "[[body]]\nname = \"{name}\"\n{placement}\
             [body.mesh]\nshape = \"half_disc\"\ncenter = [0.0, {center}]\nradius = 0.1\ncell_size = {coarse:e}\n\
             refine = {{ point = [0.0, {refine_y}], cell_size = {fine:e}, radius = 0.015 }}\n\
             [body.discretization]\norder = 2\n\
             [body.material]\nyoung = 210e9\npoisson = 0.3\nplane = \"strain\"\n{loads}"
        )
    };
    let upper = body(
        "upper",
        "",
        0.1,
        0.0,
        "[[body.dirichlet]]\npart = \"flat\"\nuy = -1e-3\nname = \"press\"\n\
         [[body.dirichlet]]\npart = \"flat\"\nux = 2.5e-4\nname = \"shear\"\n",
    );
    let lower = body(
        "lower",
        "rotate = 180.0\ntranslate = [0.0, -0.1]\n",
        0.0,
        -0.1,
        "[[body.dirichlet]]\npart = \"flat\"\nux = 0.0\nuy = 0.0\n",
    );
    let mut text = format!(
        "title = \"two cylinders, fretting\"\n{upper}{lower}\
         [[contact_pair]]\nslave = \"upper.arc\"\nmaster = \"lower.arc\"\nfriction = \"coulomb\"\nmu = 0.3\n"
    );
    if let Some(n) = increments {
        text.push_str(&format!(
            "[evolution]\nsteps = {n}\n[evolution.factor]\npress = [[0, 0], [1, 1], [6, 1]]\n\
             shear = [[0, 0], [1, 0], [2, 1], [4, -1], [6, 1]]\n"
        ));
    }
    text
}

/// The scene of case `index` at about `target_dofs` dofs, with or without its path.
fn scene_text(index: usize, target_dofs: usize, with_path: bool) -> Result<String> {
    let increments = with_path.then(|| INCREMENTS[index]);
    match index {
        // 2 (c + 1)² dofs for c cells per side.
        0 => Ok(square_block(((target_dofs as f64 / 2.0).sqrt() as usize).max(8) - 1, increments)),
        // At (0.005, 1.25e-4) scaled by s, about 4.5e5 / s² dofs.
        1 => {
            let scale = (452_000.0 / target_dofs as f64).sqrt();
            Ok(fretting(0.005 * scale, 1.25e-4 * scale, increments))
        }
        _ => Err(Error::Usage(format!("no load path case {index}"))),
    }
}

/// One case: path `PATHS[index]` at about `target_dofs` dofs.
pub fn evolution_case(session: &Session, target_dofs: usize, index: usize) -> Result<EvolutionBenchRow> {
    let name = *PATHS.get(index).ok_or_else(|| Error::Usage(format!("no load path case {index}")))?;
    let file = Path::new("bench-evolution.toml");
    // The static contact solve of the same scene at its final loads (default route).
    let static_scene = Scene::from_str(&scene_text(index, target_dofs, false)?, file)?;
    let mut problem = ElasticityProblem::setup_system(session, static_scene)?;
    problem.assemble()?;
    let linear_seconds = problem.linear_solve_seconds()?.min(problem.linear_solve_seconds()?);
    let static_contact_seconds = super::best_of_two_solves(&mut problem)?;
    // The path, twice: the better time.
    let mut best: Option<(f64, ElasticityProblem)> = None;
    for _ in 0..2 {
        let scene = Scene::from_str(&scene_text(index, target_dofs, true)?, file)?;
        let path = LoadPath::of_scene(&scene)?.ok_or_else(|| Error::Usage("the bench scene has no path".into()))?;
        let mut p = ElasticityProblem::setup_system(session, scene)?;
        p.assemble()?;
        let start = std::time::Instant::now();
        p.solve_load_path(&path, crate::evolution::EachIncrement::Solve, &mut |_, _| Ok(()))?;
        let seconds = start.elapsed().as_secs_f64();
        if best.as_ref().is_none_or(|b| seconds < b.0) {
            best = Some((seconds, p));
        }
    }
    let (path_seconds, p) = best.expect("two runs");
    let report = p.load_path.as_ref().ok_or_else(|| Error::Usage("no load path report".into()))?;
    Ok(EvolutionBenchRow {
        dofs: p.num_dofs(),
        contact_points: p.contact.as_ref().map_or(0, |c| c.boundary.points()),
        path: name.to_string(),
        increments: report.steps.len(),
        iterations: report.steps.iter().map(|s| s.iterations).sum(),
        path_seconds,
        linear_seconds,
        static_contact_seconds,
        energy_residual: report.energy.relative_residual,
        peak_memory_mb: resources::peak_memory_bytes().map_or(f64::NAN, |b| b as f64 / 1048576.0),
    })
}

/// The table: the path against its targets (press-then-push: path / linear solve against
/// 1 + 0.3 N; fretting: path / static contact solve against 10).
pub fn evolution_table(rows: &[EvolutionBenchRow]) -> String {
    let mut s = String::from(
        "| path | dofs | contact points | increments | contact iterations | path (s) | one linear solve (s) | \
         one static contact solve (s) | path / linear | path / static contact | target | energy balance | peak memory (MB) |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---:|---:|\n",
    );
    for r in rows {
        let to_linear = r.path_seconds / r.linear_seconds;
        let to_static = r.path_seconds / r.static_contact_seconds;
        let target = match r.path.as_str() {
            "fretting" => format!("≤ 10 static: {}", if to_static <= 10.0 { "met" } else { "not met" }),
            _ => {
                let bound = 1.0 + 0.3 * r.increments as f64;
                format!("≤ {bound:.1} linear: {}", if to_linear <= bound { "met" } else { "not met" })
            }
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} | {} | {:.1e} | {:.0} |\n",
            r.path,
            r.dofs,
            r.contact_points,
            r.increments,
            r.iterations,
            r.path_seconds,
            r.linear_seconds,
            r.static_contact_seconds,
            to_linear,
            to_static,
            target,
            r.energy_residual,
            r.peak_memory_mb
        ));
    }
    s
}
