//! The held-by-contact benchmark: a P2 half disc (radius 0.1 m, steel, Coulomb μ = 0.3) on a
//! rigid plane, driven two ways on the same mesh — by a prescribed displacement of its flat
//! side (the Dirichlet conditions hold the body) and by a traction on it with no support at all
//! (the contact alone holds the body, sideways by friction) — with the full-space Newton. The
//! ratio of the two contact solve times, per size, is the target (at most 2 at 8.6e4 dofs).
use std::path::Path;

use crate::error::{Error, Result};
use crate::petsc::Session;
use crate::resources;

/// The two ways of driving the disc (case index 0, 1).
pub static DRIVES: &[&str] = &["displacement", "force"];

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
/// One row of the held-body benchmark: a body held by its contact, driven by displacement or force.
pub struct HeldBenchRow {
    /// Displacement unknowns.
    pub dofs: usize,
    /// Contact points.
    pub contact_points: usize,
    /// `"displacement"` or `"force"`.
    pub drive: String,
    /// Contact solver iterations.
    pub iterations: usize,
    /// Seconds of the contact solve.
    pub contact_seconds: f64,
    /// One linear solve of the same mesh (displacement-driven only: without supports K is
    /// singular).
    pub linear_seconds: Option<f64>,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
    /// The contact solver as reported.
    pub solver: String,
}

/// Sizes: 1e4, 8.6e4 (the size of the target), 3e5 dofs.
pub fn held_cases(max_dofs: usize) -> Vec<(usize, usize, String)> {
    let mut cases = Vec::new();
    for n in [10_000, 86_000, 300_000].into_iter().filter(|&n| n <= max_dofs) {
        for (k, d) in DRIVES.iter().enumerate() {
            cases.push((n, k, format!("{d}-driven")));
        }
    }
    cases
}

/// The scene text: cells of `fine` within 0.02 m of the initial contact point, `coarse` away.
fn scene(drive: &str, coarse: f64, fine: f64) -> String {
    let load = if drive == "force" {
        "[[traction]]\npart = \"flat\"\ntraction = [1.0e6, -2.25e8]\n"
    } else {
        "[[dirichlet]]\npart = \"flat\"\nux = 1.0e-6\nuy = -1.0e-4\n"
    };
    format!(
        "title = \"half disc, {drive}-driven, Coulomb\"\n\
         [mesh]\nshape = \"half_disc\"\ncenter = [0.0, 0.1]\nradius = 0.1\ncell_size = {coarse:e}\n\
         refine = {{ point = [0.0, 0.0], cell_size = {fine:e}, radius = 0.02 }}\n\
         [discretization]\norder = 2\n\
         [material]\nyoung = 210e9\npoisson = 0.3\nplane = \"strain\"\n\
         {load}\
         [contact]\npart = \"arc\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
         friction = \"coulomb\"\nmu = 0.3\n"
    )
}

/// One case: the disc at about `target_dofs` dofs, driven as `DRIVES[index]`. The better of two
/// contact solves and of two linear solves (see `contact_case`).
pub fn held_case(session: &Session, target_dofs: usize, index: usize) -> Result<HeldBenchRow> {
    let drive = *DRIVES.get(index).ok_or_else(|| Error::Usage(format!("no drive {index}")))?;
    // 77 574 dofs at (0.005, 3e-4); the dofs grow as the inverse square of the sizes.
    let scale = (77_574.0 / target_dofs as f64).sqrt();
    let text = scene(drive, 0.005 * scale, 3e-4 * scale);
    let scene = crate::scene::Scene::from_str(&text, Path::new("bench-held.toml"))?;
    let mut problem = crate::problem::ElasticityProblem::setup_system(session, scene)?;
    problem.assemble()?;
    let linear_seconds = if drive == "displacement" {
        Some(problem.linear_solve_seconds()?.min(problem.linear_solve_seconds()?))
    } else {
        None
    };
    let contact_seconds = super::best_of_two_solves(&mut problem)?;
    let o = problem.contact_outcome.as_ref().ok_or_else(|| Error::Usage("no contact outcome".into()))?;
    Ok(HeldBenchRow {
        dofs: problem.num_dofs(),
        contact_points: o.report.points,
        drive: drive.to_string(),
        iterations: o.report.iterations,
        contact_seconds,
        linear_seconds,
        peak_memory_mb: resources::peak_memory_bytes().map_or(f64::NAN, |b| b as f64 / 1048576.0),
        solver: o.report.solver.clone(),
    })
}

/// The table: one row per case, with the force-driven time over the displacement-driven one of
/// the same size.
pub fn held_table(rows: &[HeldBenchRow]) -> String {
    let mut s = String::from(
        "| dofs | contact points | drive | Newton steps | contact solve (s) | one linear solve (s) | force / displacement | peak memory (MB) |\n\
         |---:|---:|---|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let reference = rows.iter().find(|q| q.dofs == r.dofs && q.drive == "displacement");
        let ratio = match (r.drive.as_str(), reference) {
            ("force", Some(d)) => format!("{:.2}", r.contact_seconds / d.contact_seconds),
            _ => String::new(),
        };
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.3} | {} | {} | {:.0} |\n",
            r.dofs,
            r.contact_points,
            r.drive,
            r.iterations,
            r.contact_seconds,
            r.linear_seconds.map_or(String::new(), |t| format!("{t:.3}")),
            ratio,
            r.peak_memory_mb
        ));
    }
    s
}
