//! The dual contact benchmark: the square block of Raous–Chabrand–Lebon without its corner
//! point (the contact holds it vertically), Tresca friction (threshold 2e7 Pa), P1, solved in
//! the primal (full-space Newton, the default) and in the dual (the Airy/HCT problem condensed
//! onto the contact forces by one MUMPS factorisation with the Schur complement, semi-smooth
//! Newton on the condensed problem), with the error in the constitutive relation of the pair and
//! its contact terms; the first strategy's case also times the P2 primal on the same mesh (the
//! cubic HCT dual has about 3 unknowns per vertex, P1 2 and P2 8). Targets: the dual contact
//! solve at most 2× the primal contact solve at 1e5 dofs and above; the estimate at most 10 %
//! of the two solves.
//!
//! The strategies ([`STRATEGIES`]) are the source talk's: the condensation by MUMPS with the
//! Schur complement, the three-step condensation ([`crate::dual::condensation`]) with a direct
//! or an iterative solver of the interior (incomplete Cholesky by fill level and by drop
//! tolerance, SSOR, hypre's PILUT; SYMMLQ for the talk's "brute" condensation), and the condensed contact solvers
//! (semi-smooth Newton, projected relaxation, D-PANA, Uzawa) on the same flexibility, and the
//! implicit storage of the flexibility (`-dual_contact_storage implicit`: products by one
//! interior MUMPS solve each, `W` never formed) with Uzawa — Uzawa on the full dual system —
//! and with the semi-smooth Newton method (Krylov on products); these two run up to 1e4 (one
//! interior solve per Uzawa iteration: thousands). The iterative interior solvers need
//! thousands of iterations on the HCT system: they run at 1e3 only.
use std::path::Path;
use std::time::Instant;

use crate::error::{Error, Result};
use crate::petsc::Session;
use crate::resources;

/// One strategy of the dual contact solve: its name, the PETSc options of the dual (set with
/// the `dual_` prefix of a dual solve after a primal one, except the condensation's own
/// option), the scene's contact solver and the largest size it runs at.
pub struct DualContactStrategy {
    /// The strategy's name in the table.
    pub name: &'static str,
    /// Its PETSc options (name, value).
    pub options: &'static [(&'static str, Option<&'static str>)],
    /// The scene's contact `solver`.
    pub contact_solver: &'static str,
    /// The largest size it runs at (dofs).
    pub max_dofs: usize,
}

const SMALL: usize = 2_000;

/// The strategies of the dual contact solve (case index).
pub static STRATEGIES: &[DualContactStrategy] = &[
    DualContactStrategy {
        name: "MUMPS Schur + semi-smooth Newton",
        options: &[],
        contact_solver: "newton",
        max_dofs: usize::MAX,
    },
    DualContactStrategy {
        name: "MUMPS Schur + projected relaxation",
        options: &[],
        contact_solver: "relaxation",
        max_dofs: 20_000,
    },
    DualContactStrategy { name: "MUMPS Schur + D-PANA", options: &[], contact_solver: "dpana", max_dofs: 20_000 },
    DualContactStrategy { name: "MUMPS Schur + Uzawa", options: &[], contact_solver: "uzawa", max_dofs: 20_000 },
    DualContactStrategy {
        name: "implicit W, MUMPS interior + Uzawa (full dual system)",
        options: &[("-dual_contact_storage", Some("implicit"))],
        contact_solver: "uzawa",
        max_dofs: 20_000,
    },
    DualContactStrategy {
        name: "implicit W, MUMPS interior + semi-smooth Newton (Krylov)",
        options: &[("-dual_contact_storage", Some("implicit"))],
        contact_solver: "newton",
        max_dofs: 20_000,
    },
    DualContactStrategy {
        name: "three-step, MUMPS + semi-smooth Newton",
        options: &[("-dual_contact_condensation", Some("columns"))],
        contact_solver: "newton",
        max_dofs: 20_000,
    },
    DualContactStrategy {
        name: "three-step, CG + ICC(0)",
        options: &[("-dual_ksp_type", Some("cg")), ("-dual_pc_type", Some("icc"))],
        contact_solver: "newton",
        max_dofs: SMALL,
    },
    DualContactStrategy {
        name: "three-step, CG + SSOR",
        options: &[("-dual_ksp_type", Some("cg")), ("-dual_pc_type", Some("sor")), ("-dual_pc_sor_symmetric", None)],
        contact_solver: "newton",
        max_dofs: SMALL,
    },
    DualContactStrategy {
        name: "three-step, CG + ICT(1e-3)",
        options: &[
            ("-dual_ksp_type", Some("cg")),
            ("-dual_pc_type", Some("ict")),
            ("-dual_pc_ict_drop_tolerance", Some("1e-3")),
        ],
        contact_solver: "newton",
        max_dofs: SMALL,
    },
    DualContactStrategy {
        name: "three-step, CG + hypre PILUT",
        options: &[
            ("-dual_ksp_type", Some("cg")),
            ("-dual_pc_type", Some("hypre")),
            ("-dual_pc_hypre_type", Some("pilut")),
        ],
        contact_solver: "newton",
        max_dofs: SMALL,
    },
    DualContactStrategy {
        name: "brute, SYMMLQ + SSOR",
        options: &[
            ("-dual_ksp_type", Some("symmlq")),
            ("-dual_pc_type", Some("sor")),
            ("-dual_pc_sor_symmetric", None),
            ("-dual_ksp_rtol", Some("1e-13")),
        ],
        contact_solver: "newton",
        max_dofs: SMALL,
    },
];

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
/// One row of the dual contact benchmark: one strategy at one size.
pub struct DualContactBenchRow {
    /// Displacement unknowns of the P1 primal.
    pub primal_dofs: usize,
    /// Unknowns of the dual.
    pub dual_unknowns: usize,
    /// Contact points.
    pub contact_points: usize,
    /// The strategy's name.
    pub strategy: String,
    /// Assembly, full-space Newton and postprocessing of the primal (P1), the better of two.
    pub primal_seconds: f64,
    /// The same for the P2 primal on the same mesh (the first strategy's case only; None in the
    /// others), the order whose cost the cubic HCT dual compares with.
    pub primal_p2_seconds: Option<f64>,
    /// Setup, condensation, contact solve and checks of the dual, the better of two (timed in
    /// turn with the primal ones).
    pub dual_seconds: f64,
    /// Seconds of the estimate.
    pub estimate_seconds: f64,
    /// The relative estimate (%).
    pub relative_percent: f64,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
}

/// Sizes (primal P1 dofs): 1e3, 1e4, 1e5, up to `max_dofs`.
pub fn dual_contact_cases(max_dofs: usize) -> Vec<(usize, usize, String)> {
    let mut cases = Vec::new();
    for n in [1_000, 10_000, 100_000].into_iter().filter(|&n| n <= max_dofs) {
        for (k, s) in STRATEGIES.iter().enumerate().filter(|(_, s)| n <= s.max_dofs) {
            cases.push((n, k, s.name.to_string()));
        }
    }
    cases
}

/// One case: the block at about `target_dofs` primal dofs.
pub fn dual_contact_case(session: &Session, target_dofs: usize, index: usize) -> Result<DualContactBenchRow> {
    let strategy = STRATEGIES.get(index).ok_or_else(|| Error::Usage(format!("no dual contact strategy {index}")))?;
    for (k, v) in strategy.options {
        session.set_option(k, *v)?;
    }
    let corner = "[[dirichlet]]\npoint = [0.04, 0.0]      # the lower-right corner\nux = 0.0\nuy = 0.0\n";
    let text = crate::scene::DEFAULT_SCENE_TOML.replace(corner, "");
    if text.contains("point = [0.04") {
        return Err(Error::Usage("bench dual-contact: the default scene's corner point was not found".into()));
    }
    let text = super::square_block_at(&text, target_dofs, |t| {
        if t.starts_with("friction") {
            Some("friction = \"tresca\"".to_string())
        } else if t.starts_with("mu ") {
            Some("threshold = 2e7".to_string())
        } else {
            t.starts_with("solver").then(String::new)
        }
    });
    let scene = crate::scene::Scene::from_str(&text, Path::new("bench-dual-contact.toml"))?;
    let mut problem = crate::problem::ElasticityProblem::setup_system(session, scene)?;
    let mut p2 = if index == 0 {
        let p2 = text.lines().map(|l| if l.trim_start().starts_with("order") { "order = 2" } else { l });
        let p2 = p2.collect::<Vec<_>>().join("\n");
        let scene = crate::scene::Scene::from_str(&p2, Path::new("bench-dual-contact-p2.toml"))?;
        Some(crate::problem::ElasticityProblem::setup_system(session, scene)?)
    } else {
        None
    };
    // The primal keeps its default (full-space Newton); the dual gets the strategy's solver.
    let solver = crate::scene::ContactSolverSpec::from_scene_name(strategy.contact_solver)
        .ok_or_else(|| Error::Usage(format!("bench dual-contact: no contact solver {}", strategy.contact_solver)))?;
    if let Some(contact) = problem.scene.contact.as_mut() {
        contact.solver = solver;
    }
    // Each side timed twice in turn in this process (P1 primal, P2 primal, dual; again), the
    // better of two kept for each, as the contact benchmark does: none pays alone for the first
    // touch of its memory or gains from coming last. The windows: the primal's assembly,
    // contact solve and postprocessing (stresses, the independent contact check); the dual's
    // setup, condensation, contact solve and its own checks (`solve_dual`).
    let (mut primal_seconds, mut primal_p2_seconds, mut dual_seconds) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    for _ in 0..2 {
        primal_seconds = primal_seconds.min(timed_primal(&mut problem)?);
        if let Some(p2) = p2.as_mut() {
            primal_p2_seconds = primal_p2_seconds.min(timed_primal(p2)?);
        }
        let t = Instant::now();
        problem.solve_dual()?;
        dual_seconds = dual_seconds.min(t.elapsed().as_secs_f64());
    }
    let primal_p2_seconds = p2.is_some().then_some(primal_p2_seconds);
    drop(p2);
    let t = Instant::now();
    problem.estimate()?;
    let estimate_seconds = t.elapsed().as_secs_f64();
    let dual = problem.dual.as_ref().ok_or_else(|| Error::Usage("no dual outcome".into()))?;
    let estimate = problem.estimate.as_ref().ok_or_else(|| Error::Usage("no estimate".into()))?;
    Ok(DualContactBenchRow {
        primal_dofs: problem.num_dofs(),
        dual_unknowns: dual.report.unknowns,
        contact_points: dual.report.contact.as_ref().map_or(0, |c| c.points),
        strategy: strategy.name.to_string(),
        primal_seconds,
        primal_p2_seconds,
        dual_seconds,
        estimate_seconds,
        relative_percent: estimate.estimate.relative_percent,
        peak_memory_mb: resources::peak_memory_bytes().map_or(f64::NAN, |b| b as f64 / 1048576.0),
    })
}

/// Assembly, contact solve and postprocessing of a primal problem, in seconds.
fn timed_primal(problem: &mut crate::problem::ElasticityProblem<'_>) -> Result<f64> {
    let t = Instant::now();
    problem.assemble()?;
    problem.solve()?;
    problem.postprocess()?;
    Ok(t.elapsed().as_secs_f64())
}

/// The dual contact benchmark's rows as a Markdown table.
pub fn dual_contact_table(rows: &[DualContactBenchRow]) -> String {
    let mut s = String::from(
        "| primal dofs | dual unknowns | contact points | strategy | primal P1 contact (s) | primal P2 contact (s) | \
         dual contact (s) | dual / P1 | dual / P2 | estimate (s) | estimate / solves | error (%) | peak memory (MB) |\n\
         |---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    let or_dash = |v: Option<f64>, digits: usize| v.map_or_else(|| "–".to_string(), |v| format!("{v:.digits$}"));
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {:.3} | {} | {:.3} | {:.2} | {} | {:.3} | {:.3} | {:.3} | {:.0} |\n",
            r.primal_dofs,
            r.dual_unknowns,
            r.contact_points,
            r.strategy,
            r.primal_seconds,
            or_dash(r.primal_p2_seconds, 3),
            r.dual_seconds,
            r.dual_seconds / r.primal_seconds,
            or_dash(r.primal_p2_seconds.map(|p2| r.dual_seconds / p2), 2),
            r.estimate_seconds,
            r.estimate_seconds / (r.primal_seconds + r.dual_seconds),
            r.relative_percent,
            r.peak_memory_mb
        ));
    }
    s
}
