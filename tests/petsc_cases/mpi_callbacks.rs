//! Failures on one MPI rank only: a SNES callback that fails on one rank, or a setup step (a
//! check of a rank's own rows) that fails on one rank, stops every rank, instead of leaving the
//! others waiting in the next collective operation (a hang). Each case re-runs itself on two
//! ranks under `mpirun` and a timeout.
use signorini::petsc::nonlinear::{Convergence, NonlinearSolver, NonlinearSystem};
use signorini::petsc::{Matrix, Session, Vector};
use signorini::Error;

use super::ensure;

/// F_i(x) = x_i − (i + 1), one row per dof, on this rank's rows; the residual fails on rank
/// `failing` at its second evaluation.
struct Diagonal {
    first: usize,
    rank: usize,
    failing: usize,
    evaluations: usize,
}

impl NonlinearSystem for Diagonal {
    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> signorini::Result<()> {
        self.evaluations += 1;
        if self.rank == self.failing && self.evaluations == 2 {
            return Err(Error::PetscUsage("the residual failed on purpose on this rank".into()));
        }
        for (r, fr) in f.iter_mut().enumerate() {
            *fr = x[r] - (self.first + r + 1) as f64;
        }
        Ok(())
    }
    fn jacobian(&mut self, _x: &[f64], values: &mut [f64]) -> signorini::Result<()> {
        values.fill(1.0);
        Ok(())
    }
    fn converged(&mut self, iteration: usize, _x: &[f64], _f: &[f64]) -> signorini::Result<Convergence> {
        // Two steps, so that the second residual evaluation happens.
        Ok(if iteration >= 2 { Convergence::Converged("two steps".into()) } else { Convergence::Iterating })
    }
}

/// On one process: run this case itself on two ranks (`mpirun -n 2`, under a timeout) and
/// expect it to pass there. On two ranks: the residual fails on rank 1 only; both ranks must
/// return an error, rank 0 one that says another rank failed.
pub fn nonlinear_callback_error_on_one_rank(s: &Session) -> Result<(), String> {
    const NAME: &str = "nonlinear_callback_error_on_one_rank";
    if s.size() == 1 {
        return on_two_ranks(NAME);
    }
    let (rank, size) = (s.rank(), s.size());
    let per_rank = 3;
    let n = per_rank * size;
    let first = per_rank * rank;
    let indptr: Vec<usize> = (0..=per_rank).collect();
    let columns: Vec<usize> = (first..first + per_rank).collect();
    let mut solver =
        NonlinearSolver::new(s, s.world(), n, first, &indptr, &columns, "mpi_chain_").map_err(|e| e.to_string())?;
    let mut system = Diagonal { first, rank, failing: 1, evaluations: 0 };
    let mut x = vec![0.0; per_rank];
    match solver.solve(&mut x, &mut system, 10) {
        Err(Error::PetscUsage(m)) if rank == 1 => ensure(m.contains("failed on purpose"), || format!("rank 1: {m}")),
        Err(Error::OtherRank { rank: 1, .. }) => Ok(()),
        other => Err(format!("rank {rank}: expected a callback error, got {other:?}")),
    }
}

/// Run the suite's case `name` alone on two ranks (`mpirun -n 2` under `timeout 120`) and expect
/// it to pass on both.
fn on_two_ranks(name: &str) -> Result<(), String> {
    let exe = std::env::current_exe().map_err(|e| e.to_string())?;
    let mut command = std::process::Command::new("timeout");
    // This process is an MPI singleton: its Open MPI/PMIx variables would confuse mpirun.
    for (key, _) in std::env::vars() {
        if key.starts_with("OMPI_") || key.starts_with("PMIX_") || key.starts_with("OPAL_") {
            command.env_remove(key);
        }
    }
    let started = std::time::Instant::now();
    let out = command
        .args(["120", "mpirun", "-n", "2"])
        .arg(&exe)
        .args(["--exact", name])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .output()
        .map_err(|e| format!("mpirun (openmpi-bin, installed by ./setup.sh): {e}"))?;
    let stdout = String::from_utf8_lossy(&out.stdout);
    let passed = stdout.matches(&format!("test {name} ... ok")).count();
    ensure(out.status.success() && passed == 2, || {
        format!(
            "two ranks: exit {:?} (124: timed out, a hang) after {:.1} s, {passed} ranks passed\n{stdout}\n{}",
            out.status.code(),
            started.elapsed().as_secs_f64(),
            String::from_utf8_lossy(&out.stderr)
        )
    })
}

/// On two ranks: (1) a check that fails on rank 1 only, agreed with `Session::agree` before a
/// collective operation (a gather): both ranks return an error, rank 1 its own, rank 0
/// `Error::OtherRank` naming rank 1, and neither enters the gather; (2) a matrix whose rows are
/// wrong on rank 1 only (a column out of range): `Matrix::from_csr_rows` fails on both ranks
/// instead of leaving rank 0 in MatCreate's collective set-up; (3) the ranks still work together
/// afterwards (a gather). Without the agreements the run hangs until the timeout.
pub fn setup_error_on_one_rank(s: &Session) -> Result<(), String> {
    const NAME: &str = "setup_error_on_one_rank";
    if s.size() == 1 {
        return on_two_ranks(NAME);
    }
    let (rank, size) = (s.rank(), s.size());
    let own_check = if rank == 1 { Err(Error::Usage("rank 1's own data is wrong, on purpose".into())) } else { Ok(()) };
    match s.agree(own_check, "checking this rank's data") {
        Err(Error::Usage(m)) if rank == 1 => ensure(m.contains("on purpose"), || format!("rank 1: {m}"))?,
        Err(Error::OtherRank { rank: 1, during }) if rank == 0 => {
            ensure(during == "checking this rank's data", || format!("rank 0: during {during:?}"))?
        }
        other => return Err(format!("rank {rank}: expected an agreed error, got {other:?}")),
    }
    // Two rows per rank, a diagonal; rank 1's second row names a column past the order.
    let n = 2 * size;
    let first = 2 * rank;
    let bad = if rank == 1 { n } else { first + 1 };
    let indptr = [0, 1, 2];
    let indices = [first, bad];
    match Matrix::from_csr_rows(s, s.world(), n, first, &indptr, &indices, &[1.0, 1.0], 1, false) {
        Err(Error::PetscUsage(m)) if rank == 1 => ensure(m.contains("out of range"), || format!("rank 1: {m}"))?,
        Err(Error::OtherRank { rank: 1, .. }) if rank == 0 => {}
        other => return Err(format!("rank {rank}: expected a matrix error, got {:?}", other.err())),
    }
    // Both ranks are still in step: a collective gather works.
    let mut v = Vector::new(s, s.world(), 2, n).map_err(|e| e.to_string())?;
    v.set_owned(&[rank as f64, rank as f64]).map_err(|e| e.to_string())?;
    let all = v.gather_all().map_err(|e| e.to_string())?;
    let expected: Vec<f64> = (0..size).flat_map(|r| [r as f64; 2]).collect();
    ensure(all == expected, || format!("rank {rank}: gathered {all:?}"))
}

/// On two ranks: [`signorini::mesh::shared::from_rank_0`] runs its maker on rank 0 alone (rank
/// 1's maker fails if called) and every rank gets rank 0's mesh bit for bit (nodes, cells,
/// edges, groups, order) and the order of a mesh file's triangles; when rank 0's maker fails, rank 0 returns that error and rank 1
/// `Error::OtherRank` naming rank 0 and the step, and the ranks still work together afterwards.
pub fn mesh_from_rank_0_on_two_ranks(s: &Session) -> Result<(), String> {
    use signorini::mesh::{shared, structured, Order};
    const NAME: &str = "mesh_from_rank_0_on_two_ranks";
    if s.size() == 1 {
        return on_two_ranks(NAME);
    }
    let rank = s.rank();
    let own = |shift: f64| structured::rectangle([shift, 0.0], [1.0, 0.5], 6, 3, Order::P2).unwrap();
    let made = shared::from_rank_0(s, "building the mesh", || {
        if rank == 0 {
            Ok((own(1.0 / 18.0), Some(Order::P1)))
        } else {
            Err(Error::Usage("the maker ran on rank 1".into()))
        }
    });
    let (mesh, file_order) = made.map_err(|e| format!("rank {rank}: {e}"))?;
    let expected = own(1.0 / 18.0);
    ensure(mesh.nodes == expected.nodes && mesh.cells == expected.cells && mesh.edges == expected.edges, || {
        format!("rank {rank}: the mesh received differs from rank 0's")
    })?;
    ensure(mesh.order == Order::P2 && file_order == Some(Order::P1), || {
        format!("rank {rank}: order {:?}, file order {file_order:?}", mesh.order)
    })?;
    ensure(mesh.groups == expected.groups && mesh.edge_group == expected.edge_group, || {
        format!("rank {rank}: groups")
    })?;
    // Rank 0's maker fails: every rank returns an error, none waits.
    let failed = shared::from_rank_0(s, "remeshing", || Err(Error::Usage(format!("rank {rank}'s maker fails"))));
    match failed {
        Err(Error::Usage(m)) if rank == 0 => ensure(m == "rank 0's maker fails", || m.clone())?,
        Err(Error::OtherRank { rank: 0, during: "remeshing" }) if rank == 1 => {}
        other => return Err(format!("rank {rank}: expected an agreed error, got {:?}", other.map(|_| ()))),
    }
    // Still in step: a collective reduction works.
    let sum = s.world().sum(&[1.0]).map_err(|e| e.to_string())?;
    ensure(sum == [2.0], || format!("rank {rank}: sum {sum:?}"))
}
