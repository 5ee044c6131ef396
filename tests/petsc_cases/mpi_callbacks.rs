//! The SNES wrapper under MPI: a callback that fails on one rank only stops the solve on every
//! rank, instead of leaving the others waiting in SNES's next collective operation (a hang).
use signorini::petsc::nonlinear::{Convergence, NonlinearSolver, NonlinearSystem};
use signorini::petsc::Session;
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
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let mut command = std::process::Command::new("timeout");
        // This process is an MPI singleton: its Open MPI/PMIx variables would confuse mpirun.
        for (key, _) in std::env::vars() {
            if key.starts_with("OMPI_") || key.starts_with("PMIX_") || key.starts_with("OPAL_") {
                command.env_remove(key);
            }
        }
        let out = command
            .args(["120", "mpirun", "-n", "2"])
            .arg(&exe)
            .args(["--exact", NAME])
            .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
            .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
            .env("OMPI_MCA_rmaps_base_oversubscribe", "1")
            .output()
            .map_err(|e| format!("mpirun (openmpi-bin, installed by ./setup.sh): {e}"))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        let passed = stdout.matches(&format!("test {NAME} ... ok")).count();
        return ensure(out.status.success() && passed == 2, || {
            format!(
                "two ranks: exit {:?} (124: timed out, a hang), {passed} ranks passed\n{stdout}\n{}",
                out.status.code(),
                String::from_utf8_lossy(&out.stderr)
            )
        });
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
        Err(Error::PetscUsage(m)) => ensure(m.contains("another MPI rank"), || format!("rank {rank}: {m}")),
        other => Err(format!("rank {rank}: expected a callback error, got {other:?}")),
    }
}
