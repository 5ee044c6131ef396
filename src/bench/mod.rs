//! Benchmarks (`signorini bench ...`): timings and memory measured in one run, reported as
//! ratios so that noisy machines still compare. Never run as timed tests.
//!
//! `elasticity`: a plane-strain square clamped on its left side and loaded on its right side,
//! P1 on structured meshes of 1e4 → 1e6 dofs. For each size: mesh generation, assembly
//! (pattern + values + PETSc matrix), `.vtu` output, and for each linear solver the
//! factorisation/setup + solve time (PETSc's `KSPSolve`), iterations, and the memory the
//! solve added — each (size, solver) case in a process of its own (the CLI spawns them), so
//! memory freed by one solver cannot hide another's. The overhead ratio is (mesh + assembly + output) / MUMPS solve time.
pub mod accuracy;
pub mod dual;
pub mod dual_contact;
pub mod evolution;
pub mod held;
pub mod provenance;
pub mod scale;
pub mod startup;

pub use provenance::{BenchRecord, FailedCase};

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::{Error, Result};
use crate::fem::assembly::{self, Constraints, EdgeLoad, Loads, Traction};
use crate::fem::material::{Material, PlaneModel};
use crate::mesh::{structured, Order};
use crate::output::{self, plot, vtu};
use crate::petsc::{LinearSolver, Matrix, Session};
use crate::resources;

/// One linear solver of the benchmark: a name, its options (under its own prefix) and the
/// largest problem it is run on (slow preconditioners are skipped on the largest meshes).
pub struct BenchSolver {
    /// The solver's name in the tables.
    pub name: &'static str,
    /// The PETSc options prefix of its KSP (`b_mumps_`).
    pub prefix: &'static str,
    /// Its PETSc options (name, value), set under `prefix`.
    pub options: &'static [(&'static str, Option<&'static str>)],
    /// The largest size (dofs) it is run at.
    pub max_dofs: usize,
}

/// The linear solvers of `signorini bench`, in table order.
pub static SOLVERS: &[BenchSolver] = &[
    BenchSolver { name: "MUMPS Cholesky (default)", prefix: "b_mumps_", options: &[], max_dofs: usize::MAX },
    BenchSolver {
        name: "CG + ICC(0)",
        prefix: "b_icc0_",
        options: &[("ksp_type", Some("cg")), ("pc_type", Some("icc"))],
        max_dofs: usize::MAX,
    },
    BenchSolver {
        name: "CG + ICC(2)",
        prefix: "b_icc2_",
        options: &[("ksp_type", Some("cg")), ("pc_type", Some("icc")), ("pc_factor_levels", Some("2"))],
        max_dofs: usize::MAX,
    },
    BenchSolver {
        name: "CG + BoomerAMG",
        prefix: "b_amg_",
        options: &[("ksp_type", Some("cg")), ("pc_type", Some("hypre")), ("pc_hypre_type", Some("boomeramg"))],
        max_dofs: usize::MAX,
    },
    BenchSolver {
        name: "SYMMLQ + SSOR",
        prefix: "b_ssor_",
        options: &[("ksp_type", Some("symmlq")), ("pc_type", Some("sor")), ("pc_sor_symmetric", None)],
        max_dofs: 200_000,
    },
];

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
/// One row of the linear-solver benchmark: one solver at one size.
pub struct BenchRow {
    /// Displacement unknowns.
    pub dofs: usize,
    /// Seconds to make the mesh.
    pub mesh_seconds: f64,
    /// Seconds to assemble the system.
    pub assemble_seconds: f64,
    /// Seconds to write the outputs.
    pub output_seconds: f64,
    /// The solver's name.
    pub solver: String,
    /// Seconds of the solve (factorisation included).
    pub solve_seconds: f64,
    /// Krylov iterations (1 for a direct solve).
    pub iterations: usize,
    /// Resident memory added by the solve (peak during solve minus before), MB.
    pub solve_memory_mb: f64,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
    /// ‖b − Ax‖ / ‖b‖ after the solve.
    pub relative_residual: f64,
}

/// Sizes in dofs: 1e4, 1e5, 1e6 ... up to `max_dofs` (and at least the smallest).
pub fn sizes(max_dofs: usize) -> Vec<usize> {
    let mut s: Vec<usize> = [10_000, 100_000, 1_000_000, 4_000_000].into_iter().filter(|&n| n <= max_dofs).collect();
    if s.is_empty() {
        s.push(max_dofs.max(50));
    }
    s
}

fn mb(b: Option<u64>) -> f64 {
    b.map_or(f64::NAN, |b| b as f64 / 1e6)
}

/// One benchmark case — one size, one solver — meant to run in a process of its own, so that
/// the memory it reports is its own (freed heap of an earlier solver would hide it otherwise).
/// `scratch` receives the solution file whose writing is timed.
pub fn elasticity_case(
    session: &Session,
    target_dofs: usize,
    solver: &BenchSolver,
    scratch: &Path,
) -> Result<BenchRow> {
    let material = Material { young: 2.0e11, poisson: 0.3, plane: PlaneModel::Strain };
    for (k, v) in solver.options {
        session.set_option(&format!("-{}{k}", solver.prefix), *v)?;
    }
    let n = (((target_dofs / 2) as f64).sqrt().round() as usize).max(2); // nodes per side
    let t = Instant::now();
    let mesh = structured::rectangle([0.0, 0.0], [1.0, 1.0], n - 1, n - 1, Order::P1)?;
    let mesh_seconds = t.elapsed().as_secs_f64();
    let dofs = 2 * mesh.num_nodes();

    let t = Instant::now();
    let mut constraints = Constraints::new(dofs);
    let left = mesh.require_group("left", 1)?;
    constraints.fix_group(&mesh, left, 0, |_| 0.0);
    constraints.fix_group(&mesh, left, 1, |_| 0.0);
    let loads = Loads {
        body_force: None,
        edge_loads: vec![EdgeLoad {
            group: mesh.require_group("right", 1)?,
            traction: Traction::Constant([0.0, -1.0e6]),
        }],
    };
    let (size, rank) = (session.size(), session.rank());
    let nn = mesh.num_nodes();
    let rows_range = 2 * (nn * rank / size)..2 * (nn * (rank + 1) / size);
    let system = assembly::assemble(&mesh, &material, &constraints, &loads, rows_range);
    let m = &system.matrix;
    let matrix =
        Matrix::from_csr_rows(session, session.world(), dofs, m.first_row, &m.indptr, &m.indices, &m.values, 2, true)?;
    let mut rhs = matrix.create_vector()?;
    rhs.set_owned(&system.rhs)?;
    drop(system);
    let assemble_seconds = t.elapsed().as_secs_f64();

    // Memory of the solve alone: reset the peak (VmHWM) to the current resident size first,
    // or a solve smaller than the memory freed after assembly would not show.
    crate::petsc::release_free_memory();
    resources::reset_peak_memory();
    let before = resources::current_memory_bytes();
    let mut ksp = LinearSolver::new(session, session.world(), solver.prefix)?;
    let t = Instant::now();
    ksp.set_operator(&matrix)?;
    let mut x = matrix.create_vector()?;
    let stats = ksp.solve(&matrix, &rhs, &mut x)?;
    let solve_seconds = t.elapsed().as_secs_f64();
    let peak = resources::peak_memory_bytes();
    let u = x.gather_all()?;

    let t = Instant::now();
    if rank == 0 {
        let disp3: Vec<f64> = u.chunks(2).flat_map(|d| [d[0], d[1], 0.0]).collect();
        vtu::write_vtu(
            &scratch.join("solution.vtu"),
            &mesh,
            &[vtu::Field { name: "displacement", components: 3, values: &disp3 }],
            &[],
            true,
        )?;
    }
    let output_seconds = t.elapsed().as_secs_f64();
    Ok(BenchRow {
        dofs,
        mesh_seconds,
        assemble_seconds,
        output_seconds,
        solver: solver.name.to_string(),
        solve_seconds,
        iterations: stats.iterations,
        solve_memory_mb: mb(peak) - mb(before),
        peak_memory_mb: mb(peak),
        relative_residual: stats.relative_residual,
    })
}

/// The (size, solver) cases of the benchmark up to `max_dofs`.
pub fn elasticity_cases(max_dofs: usize) -> Vec<(usize, &'static BenchSolver)> {
    let mut cases = Vec::new();
    for target in sizes(max_dofs) {
        for solver in SOLVERS.iter().filter(|s| target <= s.max_dofs) {
            cases.push((target, solver));
        }
    }
    cases
}

/// The results as a Markdown table (one row per size × solver) plus the overhead ratios.
pub fn elasticity_table(rows: &[BenchRow]) -> String {
    let mut s = String::from(
        "| dofs | solver | solve (s) | iterations | solve memory (MB) | peak memory (MB) | assembly (s) | mesh (s) | output (s) | overhead / MUMPS solve | total / KSPSolve |\n\
         |---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let mumps = rows
            .iter()
            .find(|m| m.dofs == r.dofs && m.solver.starts_with("MUMPS"))
            .map_or(f64::NAN, |m| m.solve_seconds);
        let overhead = r.mesh_seconds + r.assemble_seconds + r.output_seconds;
        s.push_str(&format!(
            "| {} | {} | {:.3} | {} | {:.0} | {:.0} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} |\n",
            r.dofs,
            r.solver,
            r.solve_seconds,
            r.iterations,
            r.solve_memory_mb,
            r.peak_memory_mb,
            r.assemble_seconds,
            r.mesh_seconds,
            r.output_seconds,
            overhead / mumps,
            (overhead + r.solve_seconds) / r.solve_seconds,
        ));
    }
    s
}

/// Write `bench_elasticity.md` (table) and `bench_elasticity.svg` (solve time against dofs, one
/// line per solver, plus assembly) into `dir`.
pub fn write_elasticity_outputs(rows: &[BenchRow], record: &BenchRecord, dir: &Path) -> Result<Vec<PathBuf>> {
    let solvers = SOLVERS
        .iter()
        .map(|solver| {
            let points = rows.iter().filter(|r| r.solver == solver.name).map(|r| (r.dofs as f64, r.solve_seconds));
            (format!("solve: {}", solver.name), points.collect())
        })
        .collect();
    let assembly = once_per_size(rows.iter().map(|r| (r.dofs as f64, r.assemble_seconds)));
    write_table_and_plot(
        dir,
        "bench_elasticity",
        record,
        ("Benchmark: plane elasticity, P1", &elasticity_table(rows)),
        "Plane elasticity, P1: wall time against size",
        solvers,
        plot::Series { label: "assembly".into(), points: assembly },
    )
}

// ------------------------------------------------------------------------------------------
// Contact benchmark: the square block of Raous–Chabrand–Lebon (Coulomb, μ = 1) on structured
// P1 meshes of growing size, one process per (size, solver) case.

/// The contact solvers compared (scene names).
/// `two_bodies` is not a solver: the square block on an elastic foundation
/// (`examples/scenes/block_on_block.toml`, non-matching meshes, mortar coupling), solved with its
/// default (the full-space semi-smooth Newton with the floating elimination: the block is held
/// vertically by the contact alone).
pub static CONTACT_SOLVERS: &[&str] =
    &["newton_full", "newton", "relaxation", "uzawa", "tresca_fixed_point", "dpana", "two_bodies"];

/// Largest size (dofs) each solver is run at: condensation costs one solve per contact unknown,
/// so the condensed routes stop early; the full-space Newton goes to 1e6 dofs.
pub fn contact_max_dofs(solver: &str) -> usize {
    match solver {
        "newton_full" => usize::MAX,
        "newton" => 200_000,
        "two_bodies" => usize::MAX,
        _ => 20_000,
    }
}

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
/// One row of the contact benchmark: one contact solver on one case.
pub struct ContactBenchRow {
    /// Displacement unknowns.
    pub dofs: usize,
    /// Contact points.
    pub contact_points: usize,
    /// The contact solver's name.
    pub solver: String,
    /// Contact solver iterations.
    pub iterations: usize,
    /// Proximal iterations on the stabilisation springs (a body held by the contact alone; 0
    /// otherwise): `iterations` counts the contact solver's iterations over all of them.
    #[serde(default)]
    pub proximal_iterations: usize,
    /// The most iterations one proximal iteration took (= `iterations` without them).
    #[serde(default)]
    pub most_in_one_proximal: usize,
    /// Seconds of the contact solve.
    pub contact_seconds: f64,
    /// Seconds of one linear solve of the same mesh, for comparison.
    pub linear_seconds: f64,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
    /// The largest residual of the independent check.
    pub worst_residual: f64,
    /// Sticking points.
    pub stick: usize,
    /// Slipping points.
    pub slip: usize,
}

/// Sizes of the contact benchmark: 1e3 → 1e6 dofs.
pub fn contact_sizes(max_dofs: usize) -> Vec<usize> {
    [1_000, 10_000, 100_000, 1_000_000].into_iter().filter(|&n| n <= max_dofs).collect()
}

/// The contact benchmark's cases up to `max_dofs`: (target dofs, contact solver name).
pub fn contact_cases(max_dofs: usize) -> Vec<(usize, &'static str)> {
    let mut cases = Vec::new();
    for n in contact_sizes(max_dofs) {
        for s in CONTACT_SOLVERS.iter().filter(|s| n <= contact_max_dofs(s)) {
            cases.push((n, *s));
        }
    }
    cases
}

/// The square block of `text` (the default scene or a variant) on a structured mesh of about
/// `target_dofs` P1 dofs; `edit` may replace any other line (given trimmed).
pub(crate) fn square_block_at(text: &str, target_dofs: usize, edit: impl Fn(&str) -> Option<String>) -> String {
    let cells = ((((target_dofs / 2) as f64).sqrt()).round() as usize).max(3) - 1;
    text.lines()
        .map(|l| {
            let t = l.trim_start();
            if t.starts_with("cell_size") {
                format!("cell_size = {:e}", 0.04 / cells as f64)
            } else {
                edit(t).unwrap_or_else(|| l.to_string())
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// `examples/scenes/block_on_block.toml` with cells of `h` in the block and `2h` in the
/// foundation, `h` chosen for about `target_dofs` dofs: `0.04²/h² + 0.08·0.02/(2h)²` nodes.
pub(crate) fn block_on_block_at(target_dofs: usize) -> String {
    let h = (0.004 / target_dofs as f64).sqrt();
    let mut sizes = [h, 2.0 * h].into_iter();
    BLOCK_ON_BLOCK_TOML
        .lines()
        .map(|l| match l.find("cell_size = ") {
            Some(at) => {
                let rest = &l[at + "cell_size = ".len()..];
                let end = rest.find([' ', '}']).unwrap_or(rest.len());
                format!("{}cell_size = {:e}{}", &l[..at], sizes.next().unwrap_or(h), &rest[end..])
            }
            None => l.to_string(),
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The two-body example scene, for the contact benchmark.
const BLOCK_ON_BLOCK_TOML: &str = include_str!("../../examples/scenes/block_on_block.toml");

/// The better of two contact solves of `problem` (assembled), in seconds (see `contact_case`).
pub(crate) fn best_of_two_solves(problem: &mut crate::problem::ElasticityProblem<'_>) -> Result<f64> {
    let mut seconds = f64::INFINITY;
    for _ in 0..2 {
        let t = Instant::now();
        problem.solve()?;
        seconds = seconds.min(t.elapsed().as_secs_f64());
    }
    Ok(seconds)
}

/// One contact case (square block, `target_dofs` dofs, the named contact solver).
pub fn contact_case(session: &Session, target_dofs: usize, solver: &str) -> Result<ContactBenchRow> {
    let text = match solver {
        "two_bodies" => block_on_block_at(target_dofs),
        _ => square_block_at(crate::scene::DEFAULT_SCENE_TOML, target_dofs, |t| {
            t.starts_with("solver").then(|| format!("solver = \"{solver}\""))
        }),
    };
    let scene = crate::scene::Scene::from_str(&text, Path::new("bench-contact.toml"))?;
    let mut problem = crate::problem::ElasticityProblem::setup_system(session, scene)?;
    problem.assemble()?;
    // The better of two runs for both times, so that both are measured in the same state of the
    // process's memory: the first run that touches a fresh gigabyte of memory pays for it (on
    // the machine behind the README's tables, 233 000 page faults made the first 1e6-dof linear
    // solve 6.5–7.3 s against 3.2–3.7 s for the second, in the same process, which reused the
    // memory); a cold contact solve against a warm linear one would charge that to the contact.
    let linear_seconds = problem.linear_solve_seconds()?.min(problem.linear_solve_seconds()?);
    let contact_seconds = best_of_two_solves(&mut problem)?;
    let o = problem.contact_outcome.as_ref().ok_or_else(|| Error::Usage("no contact outcome".into()))?;
    let r = &o.report.residuals;
    Ok(ContactBenchRow {
        dofs: problem.num_dofs(),
        contact_points: o.report.points,
        solver: solver.to_string(),
        iterations: o.report.iterations,
        proximal_iterations: o.report.stabilisation_iterations,
        most_in_one_proximal: o
            .report
            .stabilisation_step_iterations
            .iter()
            .copied()
            .max()
            .unwrap_or(o.report.iterations),
        contact_seconds,
        linear_seconds,
        peak_memory_mb: mb(resources::peak_memory_bytes()),
        worst_residual: r.worst(),
        stick: o.report.stick,
        slip: o.report.slip,
    })
}

/// The contact benchmark's rows as a Markdown table.
pub fn contact_table(rows: &[ContactBenchRow]) -> String {
    let mut s = String::from(
        "| dofs | contact points | solver | iterations (proximal) | contact solve (s) | one linear solve (s) | ratio | peak memory (MB) | worst residual | stick / slip |\n\
         |---:|---:|---|---:|---:|---:|---:|---:|---:|---|\n",
    );
    for r in rows {
        let proximal = if r.proximal_iterations > 0 {
            format!(" ({} proximal, at most {} in one)", r.proximal_iterations, r.most_in_one_proximal)
        } else {
            String::new()
        };
        let near_resolution = r.contact_seconds.min(r.linear_seconds) < NOISE_SECONDS;
        s.push_str(&format!(
            "| {} | {} | {} | {}{proximal} | {:.3} | {:.3} | {:.1}{} | {:.0} | {:.1e} | {} / {} |\n",
            r.dofs,
            r.contact_points,
            r.solver,
            r.iterations,
            r.contact_seconds,
            r.linear_seconds,
            r.contact_seconds / r.linear_seconds,
            if near_resolution { " †" } else { "" },
            r.peak_memory_mb,
            r.worst_residual,
            r.stick,
            r.slip
        ));
    }
    if rows.iter().any(|r| r.contact_seconds.min(r.linear_seconds) < NOISE_SECONDS) {
        s.push_str(&format!(
            "\n† a time below {:.0} ms: as short as the scheduling noise of a shared machine (and a few \
             timer ticks of the process start-up work that remains), so its ratio says little.\n",
            NOISE_SECONDS * 1e3
        ));
    }
    s
}

/// Times below this (seconds) are marked in the tables: the ratio of two such times is mostly
/// noise (scheduling on a loaded machine, not the clock's nanosecond resolution).
const NOISE_SECONDS: f64 = 0.01;

/// `bench_contact.md` and `bench_contact.svg` (contact solve time against dofs, per solver).
pub fn write_contact_outputs(rows: &[ContactBenchRow], record: &BenchRecord, dir: &Path) -> Result<Vec<PathBuf>> {
    let solvers = CONTACT_SOLVERS
        .iter()
        .map(|solver| {
            let points = rows.iter().filter(|r| r.solver == *solver).map(|r| (r.dofs as f64, r.contact_seconds));
            (format!("contact: {solver}"), points.collect())
        })
        .collect();
    // One linear-solve series per scene: the two-body meshes are not the square block's.
    let linear_of = |two_bodies: bool| {
        once_per_size(
            rows.iter().filter(|r| (r.solver == "two_bodies") == two_bodies).map(|r| (r.dofs as f64, r.linear_seconds)),
        )
    };
    let mut solvers: Vec<(String, Vec<(f64, f64)>)> = solvers;
    solvers.push(("one linear solve, two bodies (MUMPS)".into(), linear_of(true)));
    write_table_and_plot(
        dir,
        "bench_contact",
        record,
        ("Benchmark: frictional contact (square block, Coulomb)", &contact_table(rows)),
        "Square block, Coulomb friction: wall time against size",
        solvers,
        plot::Series { label: "one linear solve, square block (MUMPS)".into(), points: linear_of(false) },
    )
}

/// `bench_dual_contact.md` and `bench_dual_contact.svg` (dual contact solve per strategy and the
/// primal contact solve against the primal dofs).
pub fn write_dual_contact_outputs(
    rows: &[dual_contact::DualContactBenchRow],
    record: &BenchRecord,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let mut strategies: Vec<(String, Vec<(f64, f64)>)> = dual_contact::STRATEGIES
        .iter()
        .map(|st| {
            let points = rows.iter().filter(|r| r.strategy == st.name).map(|r| (r.primal_dofs as f64, r.dual_seconds));
            (format!("dual: {}", st.name), points.collect())
        })
        .collect();
    let p2 = rows.iter().filter_map(|r| r.primal_p2_seconds.map(|t| (r.primal_dofs as f64, t)));
    strategies.push(("primal P2, same mesh".into(), p2.collect()));
    let primal = once_per_size(rows.iter().map(|r| (r.primal_dofs as f64, r.primal_seconds)));
    write_table_and_plot(
        dir,
        "bench_dual_contact",
        record,
        ("Benchmark: contact in the dual formulation against the primal", &dual_contact::dual_contact_table(rows)),
        "Square block (Tresca), dual contact against primal contact",
        strategies,
        plot::Series { label: "primal P1, full-space Newton".into(), points: primal },
    )
}

/// `bench_held.md` and `bench_held.svg` (contact solve time against dofs, per drive).
pub fn write_held_outputs(rows: &[held::HeldBenchRow], record: &BenchRecord, dir: &Path) -> Result<Vec<PathBuf>> {
    let drives = held::DRIVES
        .iter()
        .map(|d| {
            let points = rows.iter().filter(|r| r.drive == *d).map(|r| (r.dofs as f64, r.contact_seconds));
            (format!("full-space Newton, {d}-driven"), points.collect())
        })
        .collect();
    let linear = once_per_size(rows.iter().filter_map(|r| r.linear_seconds.map(|t| (r.dofs as f64, t))));
    write_table_and_plot(
        dir,
        "bench_held",
        record,
        ("Benchmark: a body held by the contact (half disc, Coulomb)", &held::held_table(rows)),
        "Half disc, Coulomb: displacement- against force-driven",
        drives,
        plot::Series { label: "one linear solve (MUMPS)".into(), points: linear },
    )
}

/// `bench_evolution.md` and `bench_evolution.svg` (path time against dofs, per path, with one
/// linear solve of the same mesh).
pub fn write_evolution_outputs(
    rows: &[evolution::EvolutionBenchRow],
    record: &BenchRecord,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    let paths = evolution::PATHS
        .iter()
        .map(|name| {
            let points = rows.iter().filter(|r| r.path == *name).map(|r| (r.dofs as f64, r.path_seconds));
            (
                format!(
                    "{name} path ({} increments)",
                    rows.iter().find(|r| r.path == *name).map_or(0, |r| r.increments)
                ),
                points.collect(),
            )
        })
        .collect();
    let linear = rows.iter().map(|r| (r.dofs as f64, r.linear_seconds)).collect();
    write_table_and_plot(
        dir,
        "bench_evolution",
        record,
        ("Benchmark: load paths (increments with friction memory)", &evolution::evolution_table(rows)),
        "Load paths: the whole path against one linear solve",
        paths,
        plot::Series { label: "one linear solve (MUMPS)".into(), points: linear },
    )
}

/// The first point of each size (x), in order: per-size quantities repeated on every row.
fn once_per_size(points: impl Iterator<Item = (f64, f64)>) -> Vec<(f64, f64)> {
    let mut out: Vec<(f64, f64)> = Vec::new();
    for p in points {
        if !out.iter().any(|q| q.0 == p.0) {
            out.push(p);
        }
    }
    out
}

/// Write `bench_dual.md` and `bench_dual.svg` (dual solve per solver and the primal P2 solve
/// against the dual dofs) into `dir`.
pub fn write_dual_outputs(rows: &[dual::DualBenchRow], record: &BenchRecord, dir: &Path) -> Result<Vec<PathBuf>> {
    let solvers = SOLVERS
        .iter()
        .map(|solver| {
            let points = rows
                .iter()
                .filter(|r| r.solver == solver.name)
                .map(|r| (r.dual_dofs as f64, r.setup_seconds + r.solve_seconds));
            (format!("dual: {}", solver.name), points.collect())
        })
        .collect();
    let primal = once_per_size(rows.iter().map(|r| (r.dual_dofs as f64, r.primal_seconds)));
    write_table_and_plot(
        dir,
        "bench_dual",
        record,
        ("Benchmark: dual (Airy/HCT) against primal P2", &dual::dual_table(rows)),
        "Dual (Airy/HCT) solve against the primal P2 solve of the same mesh",
        solvers,
        plot::Series { label: "primal P2 (MUMPS)".into(), points: primal },
    )
}

/// Write `<stem>.md` (provenance, the table and the failed cases) and, when a case succeeded,
/// `<stem>.svg` (time against dofs: one line per solver that has points, then the reference
/// line) into `dir`. Their paths.
fn write_table_and_plot(
    dir: &Path,
    stem: &str,
    record: &BenchRecord,
    (heading, table): (&str, &str),
    title: &str,
    solvers: Vec<(String, Vec<(f64, f64)>)>,
    reference: plot::Series,
) -> Result<Vec<PathBuf>> {
    let md = dir.join(format!("{stem}.md"));
    let text = record.markdown(heading, table);
    output::write_atomically(&md, |w| w.write_all(text.as_bytes()))?;
    if reference.points.is_empty() && solvers.iter().all(|(_, points)| points.is_empty()) {
        // No case succeeded: nothing to draw.
        let svg = dir.join(format!("{stem}.svg"));
        let _ = std::fs::remove_file(&svg);
        return Ok(vec![md]);
    }
    let mut series: Vec<plot::Series> = solvers
        .into_iter()
        .filter(|(_, points)| !points.is_empty())
        .map(|(label, points)| plot::Series { label, points })
        .collect();
    if !reference.points.is_empty() {
        series.push(reference);
    }
    let svg = dir.join(format!("{stem}.svg"));
    plot::write_loglog_svg(&svg, title, "degrees of freedom", "seconds", &series)?;
    Ok(vec![md, svg])
}
