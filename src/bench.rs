//! Benchmarks (`signorini bench ...`): timings and memory measured in one run, reported as
//! ratios so that noisy machines still compare. Never run as timed tests.
//!
//! `elasticity`: a plane-strain square clamped on its left side and loaded on its right side,
//! P1 on structured meshes of 1e4 → 1e6 dofs. For each size: mesh generation, assembly
//! (pattern + values + PETSc matrix), `.vtu` output, and for each linear solver the
//! factorisation/setup + solve time (PETSc's `KSPSolve`), iterations, and the peak memory the
//! solve added. The overhead ratio is (mesh + assembly + output) / MUMPS solve time.
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::Result;
use crate::fem::assembly::{self, Constraints, EdgeLoad, Loads, Traction};
use crate::fem::material::{Material, PlaneModel};
use crate::mesh::{structured, Order};
use crate::output::{self, plot, vtu};
use crate::petsc::{LinearSolver, Matrix, Session};
use crate::resources;

/// One linear solver of the benchmark: a name, its options (under its own prefix) and the
/// largest problem it is run on (slow preconditioners are skipped on the largest meshes).
pub struct BenchSolver {
    pub name: &'static str,
    pub prefix: &'static str,
    pub options: &'static [(&'static str, Option<&'static str>)],
    pub max_dofs: usize,
}

pub const SOLVERS: &[BenchSolver] = &[
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

#[derive(Debug, Clone, serde::Serialize)]
pub struct BenchRow {
    pub dofs: usize,
    pub mesh_seconds: f64,
    pub assemble_seconds: f64,
    pub output_seconds: f64,
    pub solver: String,
    pub solve_seconds: f64,
    pub iterations: usize,
    /// Resident memory added by the solve (peak during solve minus before), MB.
    pub solve_memory_mb: f64,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
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

fn reset_peak_memory() {
    // Linux: writing 5 to clear_refs resets VmHWM to the current RSS (best effort).
    let _ = std::fs::write("/proc/self/clear_refs", "5");
}

fn mb(b: Option<u64>) -> f64 {
    b.map_or(f64::NAN, |b| b as f64 / 1e6)
}

pub fn elasticity(session: &Session, max_dofs: usize, progress: &mut dyn FnMut(&str)) -> Result<Vec<BenchRow>> {
    let material = Material { young: 2.0e11, poisson: 0.3, plane: PlaneModel::Strain };
    let scratch = std::env::temp_dir().join(format!("signorini-bench-{}", std::process::id()));
    for solver in SOLVERS {
        for (k, v) in solver.options {
            session.set_option(&format!("-{}{k}", solver.prefix), *v)?;
        }
    }
    let mut rows = Vec::new();
    for target in sizes(max_dofs) {
        let n = (((target / 2) as f64).sqrt().round() as usize).max(2); // nodes per side
        let t = Instant::now();
        let mesh = structured::rectangle([0.0, 0.0], [1.0, 1.0], n - 1, n - 1, Order::P1)?;
        let mesh_seconds = t.elapsed().as_secs_f64();
        let dofs = 2 * mesh.num_nodes();
        progress(&format!("bench elasticity: {dofs} dofs ({} triangles), mesh {mesh_seconds:.3} s", mesh.num_cells()));

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
        let matrix = Matrix::from_csr_rows(
            session,
            session.world(),
            dofs,
            m.first_row,
            &m.indptr,
            &m.indices,
            &m.values,
            2,
            true,
        )?;
        let mut rhs = matrix.create_vector()?;
        rhs.set_owned(&system.rhs)?;
        drop(system);
        let assemble_seconds = t.elapsed().as_secs_f64();
        progress(&format!("  assemble {assemble_seconds:.3} s"));

        let mut solution = None;
        let mut size_rows = Vec::new();
        for solver in SOLVERS.iter().filter(|s| dofs <= s.max_dofs) {
            let before = resources::current_memory_bytes();
            reset_peak_memory();
            let mut ksp = LinearSolver::new(session, session.world(), solver.prefix)?;
            let t = Instant::now();
            ksp.set_operator(&matrix)?;
            let mut x = matrix.create_vector()?;
            let stats = ksp.solve(&matrix, &rhs, &mut x);
            let solve_seconds = t.elapsed().as_secs_f64();
            let peak = resources::peak_memory_bytes();
            let stats = match stats {
                Ok(s) => s,
                Err(e) => {
                    progress(&format!("  {:<26} failed: {e}", solver.name));
                    continue;
                }
            };
            if solution.is_none() {
                solution = Some(x.gather_all()?);
            }
            progress(&format!(
                "  {:<26} {:>8.3} s, {:>5} iterations, residual {:.1e}",
                solver.name, solve_seconds, stats.iterations, stats.relative_residual
            ));
            size_rows.push(BenchRow {
                dofs,
                mesh_seconds,
                assemble_seconds,
                output_seconds: 0.0,
                solver: solver.name.to_string(),
                solve_seconds,
                iterations: stats.iterations,
                solve_memory_mb: mb(peak) - mb(before),
                peak_memory_mb: mb(peak),
                relative_residual: stats.relative_residual,
            });
        }
        // Output cost: the solution file a run would write.
        let t = Instant::now();
        if let (Some(u), 0) = (&solution, rank) {
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
        progress(&format!("  output {output_seconds:.3} s"));
        for r in &mut size_rows {
            r.output_seconds = output_seconds;
        }
        rows.extend(size_rows);
    }
    let _ = std::fs::remove_dir_all(&scratch);
    Ok(rows)
}

/// The results as a Markdown table (one row per size × solver) plus the overhead ratios.
pub fn elasticity_table(rows: &[BenchRow]) -> String {
    let mut s = String::from(
        "| dofs | solver | solve (s) | iterations | solve memory (MB) | assembly (s) | mesh (s) | output (s) | overhead / MUMPS solve | total / KSPSolve |\n\
         |---:|---|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let mumps = rows
            .iter()
            .find(|m| m.dofs == r.dofs && m.solver.starts_with("MUMPS"))
            .map_or(f64::NAN, |m| m.solve_seconds);
        let overhead = r.mesh_seconds + r.assemble_seconds + r.output_seconds;
        s.push_str(&format!(
            "| {} | {} | {:.3} | {} | {:.0} | {:.3} | {:.3} | {:.3} | {:.2} | {:.2} |\n",
            r.dofs,
            r.solver,
            r.solve_seconds,
            r.iterations,
            r.solve_memory_mb,
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
pub fn write_elasticity_outputs(rows: &[BenchRow], dir: &Path) -> Result<(PathBuf, PathBuf)> {
    let md = dir.join("bench_elasticity.md");
    let table = elasticity_table(rows);
    output::write_atomically(&md, |w| w.write_all(table.as_bytes()))?;
    let mut series: Vec<plot::Series> = Vec::new();
    for solver in SOLVERS {
        let points: Vec<(f64, f64)> =
            rows.iter().filter(|r| r.solver == solver.name).map(|r| (r.dofs as f64, r.solve_seconds)).collect();
        if !points.is_empty() {
            series.push(plot::Series { label: format!("solve: {}", solver.name), points });
        }
    }
    let mut assembly: Vec<(f64, f64)> = Vec::new();
    for r in rows {
        if !assembly.iter().any(|p| p.0 == r.dofs as f64) {
            assembly.push((r.dofs as f64, r.assemble_seconds));
        }
    }
    series.push(plot::Series { label: "assembly".into(), points: assembly });
    let svg = dir.join("bench_elasticity.svg");
    plot::write_loglog_svg(
        &svg,
        "Plane elasticity, P1: wall time against size",
        "degrees of freedom",
        "seconds",
        &series,
    )?;
    Ok((md, svg))
}
