//! The scaling benchmark (`signorini bench scale`), in three parts.
//!
//! **Contact points** (`--part contact-points`): a strip of height 1 and length `L`, P1 on a
//! structured mesh, pressed on its top face by a uniform pressure onto a frictionless rigid
//! line (its only support besides a pin `ux = 0` at its top-left corner: the contact holds it),
//! and the same strip on a second deformable strip (a contact pair; the lower strip on rollers),
//! with `m` = 100 → 20 000 contact points ([`POINT_CASES`]; `m` = 4001 is the 1000 × 1 strip of
//! cells 0.25, 40 010 dofs; `m` = 20 000 also with 24 cells across the height, 1e6 dofs). For
//! each `m`, each contact route ([`ROUTES`]) and one linear solve of the same mesh (MUMPS
//! Cholesky of K with the stabilisation springs the condensed route adds at pinned contact
//! dofs: K alone is singular) run in a process of their own: the contact solve's wall time
//! (the better of two), the process's peak resident memory (VmHWM), the Newton steps and the
//! route the program reports it took. The dense Schur route is skipped where it is predicted to
//! take more than [`MAX_PREDICTED_SECONDS`] or [`MAX_PREDICTED_BYTES`]: its cost grows like
//! `s³` in time and `s²` in memory in the number `s` of dofs the contact rows touch (`2m` on
//! one body, `4m` on two), calibrated on the measured 52 s and 3.2 GB of the strip with 4001
//! points (issue 24).
//!
//! **Strong scaling** (`--part strong`): one size (`--max-dofs`), `mpirun -n 1, 2, ...` up to
//! the cores present, for plane elasticity alone, the square block (Coulomb, one body), the
//! block on its elastic foundation (two bodies, a contact pair) and the primal + dual +
//! estimate of the elastic square: the wall time of the solve (the better of two; assembly
//! excluded), the speedup `t₁/tₙ` and the parallel efficiency `t₁/(n tₙ)`.
//!
//! **Weak scaling** (`--part weak`): the same scenes at about [`WEAK_DOFS_PER_RANK`] dofs per
//! rank (less when `--max-dofs` caps the largest), efficiency `t₁/tₙ`.
use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::provenance::BenchRecord;
use crate::error::{Error, Result};
use crate::output::{self, plot};
use crate::petsc::Session;
use crate::problem::ElasticityProblem;
use crate::resources;

/// One contact route of the benchmark: its name and the PETSc options that ask for it.
pub struct ScaleRoute {
    /// The route's name (as `-contact_route` and `report.json` → `contact.route` write it).
    pub name: &'static str,
    /// Its PETSc options (name, value).
    pub options: &'static [(&'static str, Option<&'static str>)],
}

/// The contact routes compared, in table order. Before `-contact_route` existed the default was
/// the dense Schur route and `-contact_full_space_lu` the sparse LU one (no `auto`).
pub static ROUTES: &[ScaleRoute] = &[
    ScaleRoute { name: "dense_schur", options: &[("-contact_route", Some("dense_schur"))] },
    ScaleRoute { name: "sparse_lu", options: &[("-contact_route", Some("sparse_lu"))] },
    ScaleRoute { name: "auto", options: &[("-contact_route", Some("auto"))] },
];

/// The name of the linear reference in the tables.
pub const LINEAR: &str = "one linear solve (MUMPS)";

/// Contact points and cells across the height of the strips: `m − 1` cells of `1/cells` along
/// a strip of length `(m − 1)/cells`; `2 m (cells + 1)` dofs per strip.
pub static POINT_CASES: &[(usize, usize)] =
    &[(100, 4), (400, 4), (1_000, 4), (4_001, 4), (10_000, 4), (20_000, 4), (20_000, 24)];

/// The strip scenes: one body on a rigid line, two bodies (a contact pair).
pub static STRIPS: &[&str] = &["one body", "two bodies"];

/// The scenes of the scaling parts, in table order.
pub static SCALING_SCENES: &[&str] = &[
    "elasticity",
    "contact, one body (square block)",
    "contact, two bodies (block on block)",
    "primal + dual + estimate",
];

/// Dense route skipped above these predictions.
pub const MAX_PREDICTED_SECONDS: f64 = 60.0;
/// See [`MAX_PREDICTED_SECONDS`]: 8 GB.
pub const MAX_PREDICTED_BYTES: f64 = 8e9;
/// Weak scaling: about this many dofs per rank, at most `--max-dofs / ranks`.
pub const WEAK_DOFS_PER_RANK: usize = 500_000;

/// Case indices: contact-point cases below `STRONG_BASE`, strong scaling from it, weak from
/// `WEAK_BASE`; a scaling case is `base + 100 ranks + scene`.
const STRONG_BASE: usize = 10_000;
const WEAK_BASE: usize = 20_000;

/// Which parts to run (`--part`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// Time and memory against the number of contact points, per route.
    ContactPoints,
    /// Strong scaling.
    Strong,
    /// Weak scaling.
    Weak,
}

impl Part {
    /// The name in `--part` and in the rows.
    pub fn name(self) -> &'static str {
        match self {
            Part::ContactPoints => "contact-points",
            Part::Strong => "strong",
            Part::Weak => "weak",
        }
    }
}

#[derive(Debug, Clone, Serialize, Deserialize)]
/// One case of the scaling benchmark.
pub struct ScaleRow {
    /// `contact-points`, `strong` or `weak`.
    pub part: String,
    /// The scene (a strip scene or a scaling scene).
    pub scene: String,
    /// The contact route asked for, or [`LINEAR`] (contact points); empty in the scaling parts.
    pub route: String,
    /// MPI ranks.
    pub ranks: usize,
    /// Displacement unknowns.
    pub dofs: usize,
    /// Contact points (0 without contact).
    pub contact_points: usize,
    /// Seconds: the contact solve, the linear solve, or the scaling scene's solve.
    pub seconds: f64,
    /// Peak resident memory of the process (rank 0), MB.
    pub peak_memory_mb: f64,
    /// Newton steps of the contact solve (0 without one).
    pub newton_steps: usize,
    /// The route the program reports it took (`report.json` → `contact.route`), when it says.
    pub route_taken: Option<String>,
    /// Why (`contact.route_reason`).
    pub route_reason: Option<String>,
    /// Why the case was not run (its predicted cost), when skipped.
    pub skipped: Option<String>,
}

/// The strip's cell size and length for `m` points and `cells` cells across.
fn strip_geometry(m: usize, cells: usize) -> (f64, f64) {
    let h = 1.0 / cells as f64;
    (h, (m - 1) as f64 * h)
}

/// Dofs of the strip scene (`two` strips or one).
pub fn strip_dofs(m: usize, cells: usize, two: bool) -> usize {
    2 * m * (cells + 1) * if two { 2 } else { 1 }
}

/// Predicted seconds and bytes of the dense Schur route on a strip scene with `m` points:
/// `s = 2m` (one body) or `4m` (two: the master's nodes too), scaled from the strip with 4001
/// points (52 s, 3.2 GB for `s` = 8002) as `s³` and `s²`.
pub fn dense_prediction(m: usize, two: bool) -> (f64, f64) {
    let s = (if two { 4 } else { 2 } * m) as f64 / 8002.0;
    (52.0 * s.powi(3), 3.2e9 * s.powi(2))
}

/// The strip scene's text: the issue's slender strip, frictionless (see the module doc).
fn strip_scene(m: usize, cells: usize, two: bool) -> String {
    let (h, length) = strip_geometry(m, cells);
    let material = "young = 1e9, poisson = 0.3, plane = \"strain\"";
    if two {
        let body = |name: &str, y0: f64| {
            format!(
                "[[body]]\nname = \"{name}\"\nmesh = {{ shape = \"rectangle\", origin = [0.0, {y0:?}], \
                 size = [{length:?}, 1.0], cell_size = {h:e}, mesher = \"structured\" }}\n\
                 material = {{ {material} }}\ndiscretization = {{ order = 1 }}\n"
            )
        };
        format!(
            "title = \"two strips\"\n{}[[body.traction]]\npart = \"top\"\npressure = 1e6\n[[body.dirichlet]]\n\
             point = [0.0, 1.0]\nux = 0.0\n{}[[body.dirichlet]]\npart = \"bottom\"\nuy = 0.0\n[[body.dirichlet]]\n\
             point = [0.0, -1.0]\nux = 0.0\n[[contact_pair]]\nslave = \"upper.bottom\"\nmaster = \"lower.top\"\n\
             friction = \"none\"\n",
            body("upper", 0.0),
            body("lower", -1.0)
        )
    } else {
        format!(
            "title = \"strip\"\n[mesh]\nshape = \"rectangle\"\nsize = [{length:?}, 1.0]\ncell_size = {h:e}\n\
             mesher = \"structured\"\n[discretization]\norder = 1\n[material]\nyoung = 1e9\npoisson = 0.3\n\
             plane = \"strain\"\n[[traction]]\npart = \"top\"\npressure = 1e6\n[[dirichlet]]\npoint = [0.0, 1.0]\n\
             ux = 0.0\n[contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
             friction = \"none\"\n"
        )
    }
}

/// The elastic square of the scaling parts (clamped on its left side, loaded on its right
/// side), about `target_dofs` P1 dofs.
fn elastic_square(target_dofs: usize) -> String {
    let cells = ((((target_dofs / 2) as f64).sqrt()).round() as usize).max(3) - 1;
    format!(
        "title = \"elastic square\"\n[mesh]\nshape = \"rectangle\"\nsize = [1.0, 1.0]\ncell_size = {:e}\n\
         mesher = \"structured\"\n[discretization]\norder = 1\n[material]\nyoung = 2e11\npoisson = 0.3\n\
         plane = \"strain\"\n[[traction]]\npart = \"right\"\ntraction = [0.0, -1e6]\n[[dirichlet]]\npart = \"left\"\n\
         ux = 0.0\nuy = 0.0\n",
        1.0 / cells as f64
    )
}

/// Slots per (point case, strip): the linear solve, then each route.
fn slots() -> usize {
    1 + ROUTES.len()
}

/// The cases of the chosen parts up to `max_dofs`, on up to `max_ranks` ranks:
/// `(dofs, index, name)`.
pub fn scale_cases(parts: &[Part], max_dofs: usize, max_ranks: usize) -> Vec<(usize, usize, String)> {
    let mut cases = Vec::new();
    if parts.contains(&Part::ContactPoints) {
        for (p, &(m, cells)) in POINT_CASES.iter().enumerate() {
            for (s, strip) in STRIPS.iter().enumerate() {
                let dofs = strip_dofs(m, cells, s == 1);
                if dofs > max_dofs {
                    continue;
                }
                for slot in 0..slots() {
                    let what = if slot == 0 { LINEAR } else { ROUTES[slot - 1].name };
                    let index = (p * STRIPS.len() + s) * slots() + slot;
                    cases.push((dofs, index, format!("m = {m}, {strip}: {what}")));
                }
            }
        }
    }
    for (part, base) in [(Part::Strong, STRONG_BASE), (Part::Weak, WEAK_BASE)] {
        if !parts.contains(&part) {
            continue;
        }
        for (k, scene) in SCALING_SCENES.iter().enumerate() {
            for ranks in 1..=max_ranks.max(1) {
                let dofs = match part {
                    Part::Strong => max_dofs,
                    _ => ranks * WEAK_DOFS_PER_RANK.min(max_dofs / max_ranks.max(1)).max(1_000),
                };
                cases.push((dofs, base + 100 * ranks + k, format!("{} n = {ranks}: {scene}", part.name())));
            }
        }
    }
    cases
}

/// The ranks a case runs on: 1 for the contact-point cases.
pub fn case_ranks(index: usize) -> usize {
    if index >= STRONG_BASE {
        (index % STRONG_BASE) / 100
    } else {
        1
    }
}

/// One case (see [`scale_cases`]), in this process (under `mpirun` for the scaling parts).
pub fn scale_case(session: &Session, dofs: usize, index: usize) -> Result<ScaleRow> {
    if index < STRONG_BASE {
        return point_case(session, index);
    }
    let part = if index >= WEAK_BASE { Part::Weak } else { Part::Strong };
    let ranks = case_ranks(index);
    if ranks != session.size() {
        return Err(Error::Usage(format!(
            "bench scale-case {index} runs on {ranks} rank(s), this run has {}: launch it with mpirun -n {ranks}",
            session.size()
        )));
    }
    scaling_case(session, part, index % 100, dofs)
}

fn mb(b: Option<u64>) -> f64 {
    b.map_or(f64::NAN, |b| b as f64 / 1e6)
}

/// A contact-point case: the linear solve or one route on one strip scene.
fn point_case(session: &Session, index: usize) -> Result<ScaleRow> {
    let slot = index % slots();
    let s = (index / slots()) % STRIPS.len();
    let p = index / slots() / STRIPS.len();
    let &(m, cells) = POINT_CASES.get(p).ok_or_else(|| Error::Usage(format!("no contact-point case {index}")))?;
    let two = s == 1;
    let route = if slot == 0 { None } else { Some(&ROUTES[slot - 1]) };
    let mut row = ScaleRow {
        part: Part::ContactPoints.name().into(),
        scene: STRIPS[s].into(),
        route: route.map_or(LINEAR, |r| r.name).into(),
        ranks: session.size(),
        dofs: strip_dofs(m, cells, two),
        contact_points: m,
        // Zero until measured (NaN is no JSON number): a skipped case keeps them.
        seconds: 0.0,
        peak_memory_mb: 0.0,
        newton_steps: 0,
        route_taken: None,
        route_reason: None,
        skipped: None,
    };
    if route.is_some_and(|r| r.name == "dense_schur") {
        let (seconds, bytes) = dense_prediction(m, two);
        if seconds > MAX_PREDICTED_SECONDS || bytes > MAX_PREDICTED_BYTES {
            row.skipped = Some(format!("predicted {seconds:.0} s, {:.1} GB", bytes / 1e9));
            return Ok(row);
        }
    }
    if let Some(r) = route {
        for (name, value) in r.options {
            session.set_option(name, *value)?;
        }
    }
    let scene = crate::scene::Scene::from_str(&strip_scene(m, cells, two), Path::new("bench-scale-strip.toml"))?;
    let mut problem = ElasticityProblem::setup_system(session, scene)?;
    problem.assemble()?;
    row.dofs = problem.num_dofs();
    if route.is_none() {
        row.seconds = problem.linear_solve_seconds()?.min(problem.linear_solve_seconds()?);
    } else {
        row.seconds = super::best_of_two_solves(&mut problem)?;
        let o = problem.contact_outcome.as_ref().ok_or_else(|| Error::Usage("no contact outcome".into()))?;
        row.contact_points = o.report.points;
        row.newton_steps = o.report.iterations;
        // `route` and `route_reason` are in the report of programs that choose routes.
        let report = serde_json::to_value(&o.report).unwrap_or_default();
        let text = |key: &str| report.get(key).and_then(|v| v.as_str()).map(str::to_string);
        row.route_taken = text("route");
        row.route_reason = text("route_reason");
    }
    row.peak_memory_mb = mb(resources::peak_memory_bytes());
    Ok(row)
}

/// A scaling case: scene `scene` at about `dofs` dofs on this run's ranks.
fn scaling_case(session: &Session, part: Part, scene: usize, dofs: usize) -> Result<ScaleRow> {
    let name = *SCALING_SCENES.get(scene).ok_or_else(|| Error::Usage(format!("no scaling scene {scene}")))?;
    let text = match scene {
        1 => super::square_block_at(crate::scene::DEFAULT_SCENE_TOML, dofs, |_| None),
        2 => super::block_on_block_at(dofs),
        _ => elastic_square(dofs),
    };
    let parsed = crate::scene::Scene::from_str(&text, Path::new("bench-scale.toml"))?;
    let mut problem = ElasticityProblem::setup_system(session, parsed)?;
    problem.assemble()?;
    let mut seconds = f64::INFINITY;
    for _ in 0..2 {
        let t = Instant::now();
        problem.solve()?;
        if scene == 3 {
            problem.postprocess()?;
            problem.solve_dual()?;
            problem.estimate()?;
        }
        seconds = seconds.min(t.elapsed().as_secs_f64());
    }
    let (points, steps) = problem.contact_outcome.as_ref().map_or((0, 0), |o| (o.report.points, o.report.iterations));
    Ok(ScaleRow {
        part: part.name().into(),
        scene: name.into(),
        route: String::new(),
        ranks: session.size(),
        dofs: problem.num_dofs(),
        contact_points: points,
        seconds,
        peak_memory_mb: mb(resources::peak_memory_bytes()),
        newton_steps: steps,
        route_taken: None,
        route_reason: None,
        skipped: None,
    })
}

/// A route asked for by name that the program reports it did not take (a fallback): the
/// row is kept and this is its failed-case reason.
pub fn route_mismatch(row: &ScaleRow) -> Option<String> {
    let taken = row.route_taken.as_deref()?;
    (row.route != "auto" && row.route != LINEAR && taken != row.route).then(|| {
        format!(
            "asked for {}, the program took {taken} ({})",
            row.route,
            row.route_reason.as_deref().unwrap_or("no reason given")
        )
    })
}

/// The progress line of a finished case.
pub fn describe(row: &ScaleRow) -> String {
    match &row.skipped {
        Some(why) => format!("skipped ({why})"),
        None => format!(
            "{:>8.3} s, {:>6.0} MB{}",
            row.seconds,
            row.peak_memory_mb,
            if row.newton_steps > 0 { format!(", {} Newton steps", row.newton_steps) } else { String::new() }
        ),
    }
}

/// The contact-point table: per (strip, m) the linear solve, then each route with its time and
/// memory ratios to it, then what `auto` chose and its time over the best route's.
pub fn points_table(rows: &[ScaleRow]) -> String {
    let mut s = String::from(
        "| scene | contact points | dofs | route | solve (s) | / linear | peak memory (MB) | / linear | Newton steps | route taken |\n\
         |---|---:|---:|---|---:|---:|---:|---:|---:|---|\n",
    );
    let mut summary = String::from(
        "| scene | contact points | dofs | auto took | why | chosen / best | best route | auto's own run / best |\n\
         |---|---:|---:|---|---|---:|---|---:|\n",
    );
    let points = rows.iter().filter(|r| r.part == Part::ContactPoints.name());
    let mut groups: Vec<(&str, usize, usize)> = Vec::new();
    for r in points.clone() {
        if !groups.iter().any(|g| g.0 == r.scene && g.1 == r.contact_points && g.2 == r.dofs) {
            groups.push((&r.scene, r.contact_points, r.dofs));
        }
    }
    for (scene, m, dofs) in groups {
        let group: Vec<&ScaleRow> =
            points.clone().filter(|r| r.scene == scene && r.contact_points == m && r.dofs == dofs).collect();
        let linear = group.iter().find(|r| r.route == LINEAR);
        for r in &group {
            if let Some(why) = &r.skipped {
                s.push_str(&format!("| {scene} | {m} | {dofs} | {} | skipped ({why}) | | | | | |\n", r.route));
                continue;
            }
            let ratio = |x: f64, y: Option<f64>| match y {
                Some(y) if r.route != LINEAR => format!("{:.2}", x / y),
                _ => String::new(),
            };
            s.push_str(&format!(
                "| {scene} | {m} | {dofs} | {} | {:.3} | {} | {:.0} | {} | {} | {} |\n",
                r.route,
                r.seconds,
                ratio(r.seconds, linear.map(|l| l.seconds)),
                r.peak_memory_mb,
                ratio(r.peak_memory_mb, linear.map(|l| l.peak_memory_mb)),
                if r.route == LINEAR { String::new() } else { r.newton_steps.to_string() },
                r.route_taken.as_deref().unwrap_or(if r.route == LINEAR { "" } else { "–" }),
            ));
        }
        let best = group
            .iter()
            .filter(|r| r.route != LINEAR && r.route != "auto" && r.skipped.is_none())
            .min_by(|a, b| a.seconds.total_cmp(&b.seconds));
        if let Some(auto) = group.iter().find(|r| r.route == "auto" && r.skipped.is_none()) {
            // The chosen route's time as run by name (auto's own run differs from it by the
            // noise between two processes only), else auto's own.
            let chosen = auto
                .route_taken
                .as_deref()
                .and_then(|t| group.iter().find(|r| r.route == t && r.skipped.is_none()))
                .map_or(auto.seconds, |r| r.seconds);
            let over_best = |t: f64| best.map_or(String::new(), |b| format!("{:.2}", t / b.seconds));
            summary.push_str(&format!(
                "| {scene} | {m} | {dofs} | {} | {} | {} | {} | {} |\n",
                auto.route_taken.as_deref().unwrap_or("– (not reported)"),
                auto.route_reason.as_deref().map_or(String::new(), |w| w.replace('|', "\\|")),
                over_best(chosen),
                best.map_or("", |b| b.route.as_str()),
                over_best(auto.seconds),
            ));
        }
    }
    format!(
        "{s}\nThe route `auto` took, and the time of that route (run by name) over the fastest route run by \
         name at the same size: 1 is the right choice. Auto's own run over the same is the noise between \
         two processes (each time the better of two solves):\n\n{summary}"
    )
}

/// The strong or weak scaling table: per scene and ranks, the time, the speedup and the
/// efficiency against one rank.
pub fn scaling_table(rows: &[ScaleRow], part: Part) -> String {
    let mut s = String::from(match part {
        Part::Weak => {
            "| scene | ranks | dofs | solve (s) | efficiency t1/tn | Newton steps | peak memory, rank 0 (MB) |\n\
             |---|---:|---:|---:|---:|---:|---:|\n"
        }
        _ => {
            "| scene | ranks | dofs | solve (s) | speedup t1/tn | efficiency t1/(n tn) | Newton steps | peak memory, rank 0 (MB) |\n\
             |---|---:|---:|---:|---:|---:|---:|---:|\n"
        }
    });
    for r in rows.iter().filter(|r| r.part == part.name()) {
        let one = rows.iter().find(|q| q.part == r.part && q.scene == r.scene && q.ranks == 1).map(|q| q.seconds);
        let speedup = one.map_or(String::new(), |t| format!("{:.2}", t / r.seconds));
        let efficiency = one.map_or(String::new(), |t| format!("{:.2}", t / (r.ranks as f64 * r.seconds)));
        let steps = if r.newton_steps > 0 { r.newton_steps.to_string() } else { String::new() };
        s.push_str(&match part {
            Part::Weak => format!(
                "| {} | {} | {} | {:.3} | {speedup} | {steps} | {:.0} |\n",
                r.scene, r.ranks, r.dofs, r.seconds, r.peak_memory_mb
            ),
            _ => format!(
                "| {} | {} | {} | {:.3} | {speedup} | {efficiency} | {steps} | {:.0} |\n",
                r.scene, r.ranks, r.dofs, r.seconds, r.peak_memory_mb
            ),
        });
    }
    s
}

/// Every table of the run (the parts that have rows), with headings.
pub fn scale_table(rows: &[ScaleRow]) -> String {
    let mut s = String::new();
    for (part, heading) in [
        (Part::ContactPoints, "Contact points: each route against one linear solve of the same mesh"),
        (Part::Strong, "Strong scaling: one size, 1 to n ranks"),
        (Part::Weak, "Weak scaling: dofs proportional to the ranks"),
    ] {
        if !rows.iter().any(|r| r.part == part.name()) {
            continue;
        }
        let table = match part {
            Part::ContactPoints => points_table(rows),
            _ => scaling_table(rows, part),
        };
        s.push_str(&format!("## {heading}\n\n{table}\n"));
    }
    s
}

/// `bench_scale.md` (every table, provenance, failed cases), `bench_scale_points.svg` (solve
/// time against contact points per route and strip, with the linear solve) and
/// `bench_scale_speedup.svg` (strong-scaling speedup against ranks, with the ideal line), the
/// plots when they have points. `note` is a line added under the tables (mpirun missing).
pub fn write_scale_outputs(rows: &[ScaleRow], record: &BenchRecord, dir: &Path, note: &str) -> Result<Vec<PathBuf>> {
    let md = dir.join("bench_scale.md");
    let mut tables = scale_table(rows);
    if !note.is_empty() {
        tables.push_str(&format!("{note}\n"));
    }
    let text = record.markdown("Benchmark: scaling in contact points and in MPI ranks", &tables);
    output::write_atomically(&md, |w| w.write_all(text.as_bytes()))?;
    let mut paths = vec![md];

    let mut series = Vec::new();
    for strip in STRIPS {
        for route in ROUTES.iter().map(|r| r.name).chain([LINEAR]) {
            let points: Vec<(f64, f64)> = rows
                .iter()
                .filter(|r| {
                    r.part == Part::ContactPoints.name() && r.scene == *strip && r.route == route && r.skipped.is_none()
                })
                .map(|r| (r.contact_points as f64, r.seconds))
                .collect();
            if !points.is_empty() {
                series.push(plot::Series { label: format!("{strip}: {route}"), points });
            }
        }
    }
    let svg = dir.join("bench_scale_points.svg");
    if series.is_empty() {
        let _ = std::fs::remove_file(&svg);
    } else {
        plot::write_loglog_svg(
            &svg,
            "Strip on a line / on a strip: solve time against contact points",
            "contact points",
            "seconds",
            &series,
        )?;
        paths.push(svg);
    }

    let mut series = Vec::new();
    let mut most_ranks = 1;
    for scene in SCALING_SCENES {
        let strong: Vec<&ScaleRow> =
            rows.iter().filter(|r| r.part == Part::Strong.name() && r.scene == *scene).collect();
        if let Some(one) = strong.iter().find(|r| r.ranks == 1) {
            let points: Vec<(f64, f64)> = strong.iter().map(|r| (r.ranks as f64, one.seconds / r.seconds)).collect();
            most_ranks = most_ranks.max(strong.iter().map(|r| r.ranks).max().unwrap_or(1));
            series.push(plot::Series { label: scene.to_string(), points });
        }
    }
    let svg = dir.join("bench_scale_speedup.svg");
    if series.is_empty() {
        let _ = std::fs::remove_file(&svg);
    } else {
        let ideal = (1..=most_ranks).map(|n| (n as f64, n as f64)).collect();
        series.push(plot::Series { label: "ideal".into(), points: ideal });
        plot::write_loglog_svg(
            &svg,
            "Strong scaling: speedup against MPI ranks",
            "MPI ranks",
            "speedup t1/tn",
            &series,
        )?;
        paths.push(svg);
    }
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_issue_strip_is_a_case_and_the_prediction_matches_its_measure() {
        // The issue's strip: 1000 × 1, cells 0.25, 40 010 dofs, 4001 contact points.
        assert_eq!(strip_geometry(4_001, 4), (0.25, 1000.0));
        assert_eq!(strip_dofs(4_001, 4, false), 40_010);
        assert_eq!(strip_dofs(20_000, 24, false), 1_000_000);
        let (seconds, bytes) = dense_prediction(4_001, false);
        assert!((seconds - 52.0).abs() < 0.1 && (bytes - 3.2e9).abs() < 1e7);
        assert!(dense_prediction(10_000, false).0 > MAX_PREDICTED_SECONDS);
        assert!(dense_prediction(1_000, true).0 < MAX_PREDICTED_SECONDS);
    }

    /// A skipped case is a row the parent can read back (its times are numbers, not NaN, which
    /// JSON cannot carry), and the table says why it was skipped.
    #[test]
    fn a_skipped_row_goes_through_json_and_into_the_table() {
        let row = ScaleRow {
            part: Part::ContactPoints.name().into(),
            scene: STRIPS[0].into(),
            route: "dense_schur".into(),
            ranks: 1,
            dofs: 100_000,
            contact_points: 10_000,
            seconds: 0.0,
            peak_memory_mb: 0.0,
            newton_steps: 0,
            route_taken: None,
            route_reason: None,
            skipped: Some("predicted 813 s, 20.0 GB".into()),
        };
        let back: ScaleRow = serde_json::from_str(&serde_json::to_string(&row).unwrap()).unwrap();
        let table = points_table(&[back]);
        assert!(
            table.contains("| one body | 10000 | 100000 | dense_schur | skipped (predicted 813 s, 20.0 GB) |"),
            "{table}"
        );
    }

    #[test]
    fn cases_decode_to_their_part_ranks_and_scene() {
        let cases = scale_cases(&[Part::ContactPoints, Part::Strong, Part::Weak], 200_000, 2);
        // Contact points: 6 one-body and 5 two-body sizes up to 2e5 dofs, linear + routes each.
        assert_eq!(cases.iter().filter(|c| c.1 < STRONG_BASE).count(), 11 * slots());
        assert!(cases.iter().all(|c| c.0 <= 200_000));
        let strong: Vec<_> = cases.iter().filter(|c| (STRONG_BASE..WEAK_BASE).contains(&c.1)).collect();
        assert_eq!(strong.len(), 2 * SCALING_SCENES.len());
        assert!(strong.iter().all(|c| c.0 == 200_000 && c.2.contains(SCALING_SCENES[c.1 % 100])));
        let weak: Vec<_> = cases.iter().filter(|c| c.1 >= WEAK_BASE).collect();
        assert!(weak.iter().all(|c| c.0 == case_ranks(c.1) * 100_000), "{weak:?}");
        assert_eq!(cases.iter().filter(|c| case_ranks(c.1) == 2).count(), 2 * SCALING_SCENES.len());
    }
}
