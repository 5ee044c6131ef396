//! The dual benchmark: the Airy/HCT solve of a clamped square loaded on one side, per linear
//! solver, against the primal P2 solve of the same mesh (the same vertices), with the error in
//! the constitutive relation of the pair. Sizes are in dual dofs (3 per vertex + 1 per edge,
//! about 6 n² on an n × n grid; the P2 primal of the same mesh has about 8 n²).
use std::time::Instant;

use super::{BenchSolver, SOLVERS};
use crate::dual::{BodyLoad, DualData, DualSystem};
use crate::error::Result;
use crate::estimate::{pair_degree, volume_terms, Estimate, EstimateKind};
use crate::fem::assembly::{self, Constraints, EdgeLoad, Loads, Traction};
use crate::fem::material::{Material, PlaneModel};
use crate::mesh::{structured, Order};
use crate::petsc::{LinearSolver, Matrix, Session};
use crate::resources;
use crate::scene::DualConstraints;

#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
/// One row of the dual benchmark: one solver at one size.
pub struct DualBenchRow {
    /// HCT dofs.
    pub dual_dofs: usize,
    /// Unknowns solved for.
    pub unknowns: usize,
    /// The solver's name.
    pub solver: String,
    /// Elements (HCT bases), numbering and boundary elimination (the better of two).
    pub setup_seconds: f64,
    /// Reduced assembly and solve (the KSP's time, factorisation included; the better of two).
    pub solve_seconds: f64,
    /// Krylov iterations (1 for a direct solve).
    pub iterations: usize,
    /// Seconds of the estimate.
    pub estimate_seconds: f64,
    /// Displacement unknowns of the P2 primal on the same mesh.
    pub primal_p2_dofs: usize,
    /// Assembly and MUMPS Cholesky solve of the P2 primal on the same mesh (the better of two,
    /// timed in turn with the dual's).
    pub primal_seconds: f64,
    /// Peak resident memory of the process so far, MB.
    pub peak_memory_mb: f64,
    /// The relative estimate (%), the same for every solver up to round-off.
    pub relative_percent: f64,
}

/// A linear solver of the dual benchmark and how it imposes the boundary constraints.
pub struct DualBenchSolver {
    /// The linear solver.
    pub solver: &'static BenchSolver,
    /// Eliminated constraints or multipliers.
    pub constraints: DualConstraints,
}

/// Extra solvers of the eliminated system: CG with symmetric SOR (the SSOR of the issue and the
/// talk's preconditioner family; SYMMLQ + SSOR of the elasticity list stalls on the HCT system).
static ELIMINATED_EXTRA_SOLVERS: &[BenchSolver] = &[BenchSolver {
    name: "CG + SSOR",
    prefix: "b_cg_ssor_",
    options: &[
        ("ksp_type", Some("cg")),
        ("pc_type", Some("sor")),
        ("pc_sor_symmetric", None),
        ("ksp_max_it", Some("200000")),
    ],
    max_dofs: 20_000,
}];

static SADDLE_POINT_SOLVERS: &[BenchSolver] = &[
    BenchSolver { name: "saddle point, MUMPS LDLᵀ", prefix: "b_kkt_mumps_", options: &[], max_dofs: usize::MAX },
    BenchSolver {
        name: "saddle point, SYMMLQ + Jacobi",
        prefix: "b_kkt_symmlq_",
        // Thousands of iterations (a fourth-order operator): more than the default limit.
        options: &[("ksp_type", Some("symmlq")), ("pc_type", Some("jacobi")), ("ksp_max_it", Some("200000"))],
        max_dofs: 20_000,
    },
];

/// The solvers of the dual benchmark, in table order: the eliminated (positive definite)
/// system with the elasticity benchmark's solvers but BoomerAMG (the HCT system is not an
/// elliptic second-order one) and CG + SSOR, then the saddle point with multipliers.
pub fn dual_solvers() -> Vec<DualBenchSolver> {
    let eliminated = SOLVERS
        .iter()
        .filter(|s| !s.name.contains("BoomerAMG"))
        .chain(ELIMINATED_EXTRA_SOLVERS)
        .map(|solver| DualBenchSolver { solver, constraints: DualConstraints::Eliminated });
    let saddle =
        SADDLE_POINT_SOLVERS.iter().map(|solver| DualBenchSolver { solver, constraints: DualConstraints::Multipliers });
    eliminated.chain(saddle).collect()
}

/// One size, one solver (the primal reference is solved in the same process).
pub fn dual_case(session: &Session, target_dofs: usize, choice: &DualBenchSolver) -> Result<DualBenchRow> {
    let solver = choice.solver;
    let material = Material { young: 2.0e11, poisson: 0.3, plane: PlaneModel::Strain };
    for (k, v) in solver.options {
        session.set_option(&format!("-{}{k}", solver.prefix), *v)?;
    }
    let n = (((target_dofs as f64) / 6.0).sqrt().round() as usize).max(2);
    let mesh = structured::rectangle([0.0, 0.0], [1.0, 1.0], n, n, Order::P1)?;
    let (left, right) = (mesh.require_group("left", 1)?, mesh.require_group("right", 1)?);
    let loads = [EdgeLoad { group: right, traction: Traction::Constant([0.0, -1.0e6]) }];
    let prescribed = [(left, [Some(0.0), Some(0.0)])];

    // Primal P2 on the same vertices (MUMPS Cholesky, the default), and the dual: each timed
    // twice in turn in this process, the better of the two kept for both, so that neither
    // pays alone for the first touch of its memory (the first run that touches a fresh
    // gigabyte pays about 2x in page faults) nor gains from coming second.
    let p2 = mesh.to_quadratic();
    let dofs = 2 * p2.num_nodes();
    let data = DualData {
        body_force: BodyLoad::Constant([0.0, 0.0]),
        edge_loads: &loads,
        prescribed: &prescribed,
        contact: None,
    };
    let (mut primal_seconds, mut setup_seconds, mut solve_seconds) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut last = None;
    for _ in 0..2 {
        drop(last.take()); // the first round's answers: not held during the second
        let t = Instant::now();
        let u = primal_p2_solve(session, &p2, &material, left, &loads)?;
        primal_seconds = primal_seconds.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let dual = DualSystem::new(&mesh, &material, &data)?;
        setup_seconds = setup_seconds.min(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let (phi, stats) = dual.solve_with(session, &mesh, solver.prefix, choice.constraints)?;
        solve_seconds = solve_seconds.min(t.elapsed().as_secs_f64());
        last = Some((u, dual, phi, stats));
    }
    let (u, dual, phi, stats) = last.ok_or_else(|| crate::error::Error::Usage("bench dual: no round ran".into()))?;

    // The estimate of the pair, on the P2 mesh (its cells are the vertex triangles).
    let t = Instant::now();
    let field = dual.field(&mesh, &phi);
    let volume = volume_terms(&p2, &material, &u, &field, pair_degree(&p2));
    let estimate = Estimate::new(EstimateKind::GuaranteedBound, &volume, None);
    let estimate_seconds = t.elapsed().as_secs_f64();
    Ok(DualBenchRow {
        dual_dofs: dual.dofs.len(),
        unknowns: match choice.constraints {
            DualConstraints::Eliminated => dual.num_unknowns(),
            DualConstraints::Multipliers => dual.saddle_point_size(),
        },
        solver: solver.name.to_string(),
        setup_seconds,
        solve_seconds,
        iterations: stats.iterations,
        estimate_seconds,
        primal_p2_dofs: dofs,
        primal_seconds,
        peak_memory_mb: resources::peak_memory_bytes().map_or(f64::NAN, |b| b as f64 / 1e6),
        relative_percent: estimate.relative_percent,
    })
}

/// Assembly and MUMPS Cholesky solve of the P2 primal of the benchmark's square (clamped on
/// `left`, `loads` on the right): the displacement.
fn primal_p2_solve(
    session: &Session,
    p2: &crate::mesh::Mesh,
    material: &Material,
    left: usize,
    loads: &[EdgeLoad],
) -> Result<Vec<f64>> {
    let mut constraints = Constraints::new(2 * p2.num_nodes());
    constraints.fix_group(p2, left, 0, |_| 0.0);
    constraints.fix_group(p2, left, 1, |_| 0.0);
    let primal_loads = Loads { body_force: None, edge_loads: loads.to_vec() };
    let dofs = 2 * p2.num_nodes();
    let system = assembly::assemble(p2, material, &constraints, &primal_loads, 0..dofs);
    let m = &system.matrix;
    let matrix = Matrix::from_csr_rows(session, session.world(), dofs, 0, &m.indptr, &m.indices, &m.values, 2, true)?;
    let mut rhs = matrix.create_vector()?;
    rhs.set_owned(&system.rhs)?;
    let mut x = matrix.create_vector()?;
    let mut ksp = LinearSolver::new(session, session.world(), "b_mumps_")?;
    ksp.set_operator(&matrix)?;
    ksp.solve(&matrix, &rhs, &mut x)?;
    x.gather_all()
}

/// The (size, index in [`dual_solvers`], name) cases up to `max_dofs` dual dofs; the
/// iterative solvers stop at 2e4 (measured: CG + ICC(0) needs 9252 iterations at 1e4 dual dofs
/// and does not converge in 10000 at 1e5: the HCT system mixes values and derivatives and is
/// badly conditioned for them; SYMMLQ + Jacobi on the saddle point needs ~2000 at 7e3).
pub fn dual_cases(max_dofs: usize) -> Vec<(usize, usize, String)> {
    let solvers = dual_solvers();
    let mut cases = Vec::new();
    for size in super::sizes(max_dofs) {
        for (index, choice) in solvers.iter().enumerate() {
            let solver = choice.solver;
            if size <= solver.max_dofs.min(if solver.name.contains("MUMPS") { usize::MAX } else { 20_000 }) {
                cases.push((size, index, solver.name.to_string()));
            }
        }
    }
    cases
}

/// The markdown table.
pub fn dual_table(rows: &[DualBenchRow]) -> String {
    let mut s = String::from(
        "| dual dofs | unknowns | solver | setup (s) | solve (s) | iterations | estimate (s) | P2 dofs | primal P2 (s) | (setup + solve + estimate) / primal | estimate / dual solve | estimate (%) | peak memory (MB) |\n\
         |---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n",
    );
    for r in rows {
        let dual = r.setup_seconds + r.solve_seconds;
        s.push_str(&format!(
            "| {} | {} | {} | {:.3} | {:.3} | {} | {:.3} | {} | {:.3} | {:.2} | {:.2} | {:.3} | {:.0} |\n",
            r.dual_dofs,
            r.unknowns,
            r.solver,
            r.setup_seconds,
            r.solve_seconds,
            r.iterations,
            r.estimate_seconds,
            r.primal_p2_dofs,
            r.primal_seconds,
            (dual + r.estimate_seconds) / r.primal_seconds,
            r.estimate_seconds / dual,
            r.relative_percent,
            r.peak_memory_mb
        ));
    }
    s
}
