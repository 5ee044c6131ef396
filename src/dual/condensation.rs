//! # How the dual contact problem is condensed onto the contact forces
//!
//! The reduced dual system, unknowns `x = (z, r)` (free HCT dofs, contact forces),
//!
//! ```text
//!   [ A_zz  A_zr ] [ z ]   [ b_z ]            W = A_rr − A_rz A_zz⁻¹ A_zr      (the talk's D)
//!   [ A_rz  A_rr ] [ r ] = [ b_r ] + u,       u_free = −(b_r + ℓ),  ℓ = −A_rz A_zz⁻¹ b_z
//! ```
//!
//! is condensed onto `r` in one of the source talk's ways ("Résolution numérique duale"):
//!
//! - **`schur`** (the default): one MUMPS factorisation of the whole matrix with the Schur
//!   complement on `r` ([`crate::petsc::schur::SchurFactor`]): `W` comes out of the
//!   factorisation itself.
//! - **`columns`**, the talk's three-step condensation: (1) solve `A_zz X = A_zr` column by
//!   column, (2) form `W = A_rr − A_rz X`, (3) solve the contact problem on `W`. Step (1) uses
//!   the dual's linear solver with every PETSc option: MUMPS (`-ksp_type preonly -pc_type
//!   cholesky`, factorised once, then one pair of triangular solves per column), or a Krylov
//!   method with incomplete Cholesky by fill level (`-ksp_type cg -pc_type icc
//!   -pc_factor_levels k`), by drop tolerance, SSOR (`-pc_type sor -pc_sor_symmetric`), hypre;
//!   with `-ksp_type symmlq` it is the talk's "brute" condensation by SYMMLQ. One solve per
//!   contact force (`2 × points`), then one for `ℓ` and one for the field.
//!
//! `W` is dense in both (the talk's "dense storage of D"). The route is chosen by
//! `-dual_contact_condensation schur|columns`; without it, `columns` when the dual's linear
//! solver is configured (`-ksp_type`/`-pc_type`, under `-dual_` next to a primal solve) or the
//! run has several MPI ranks, else `schur` — as the primal chooses between its Schur
//! factorisation and its KSP.
//!
//! With a direct solver (`preonly` + `cholesky`/`lu`, the default) the columns are solved by
//! blocks of [`BLOCK_COLUMNS`] right-hand sides, one `KSPMatSolve` each (MUMPS's multiple
//! right-hand sides), instead of one `KSPSolve` per column; any other solver goes column by
//! column. On the Hertz scene (42 553 unknowns, 666 contact forces) the dual's time went from
//! 23.6 s to 9.2 s on one process (measured with `signorini run examples/scenes/hertz.toml
//! --estimate -dual_contact_condensation columns`, a machine shared with other jobs).
//!
//! ## Under MPI (`mpirun -n N`)
//!
//! The Schur complement of PETSc 3.18's MUMPS interface is computed on one process, so on
//! several ranks the condensation is `columns`, and `-dual_contact_condensation schur` is
//! refused by name ([`Error::SingleProcess`], by [`refuse_undistributable`], which the CLI
//! calls before meshing). What is distributed and what is held by every rank:
//!
//! - `A_zz` (almost all the unknowns): distributed in contiguous row blocks, factorised and
//!   solved by the distributed solver (MUMPS, or any PETSc KSP and preconditioner).
//! - The block solves' answers `X = A_zz⁻¹ A_zr` stay distributed: each rank forms
//!   `A_rz X` from its own rows of `X` (`A_zr` is held by every rank, sparse), and the parts
//!   are summed over the ranks (one reduction of `m × 64` values per block).
//! - `W` (`m × m`, `m = 2 ×` contact points), `u_free`, the gaps, and everything after: the
//!   condensed contact problem is small and dense, so every rank holds it and solves it
//!   redundantly, with the same data (the reductions and `gather_all` give every rank the same
//!   numbers), hence the same iterations and the same answer; each interior solve for `ℓ`,
//!   `z` and an implicit product is one distributed solve whose answer is gathered on every
//!   rank. The assembly of the reduced rows is redundant too (every rank holds the mesh, as in
//!   [`crate::problem`]), each rank then hands PETSc its own block.
//!
//! Two ranks give the one-process answer to the round-off of the HCT system, whose
//! conditioning grows as `(L/h)⁴` (measured, relative L2 differences): 1e-11 to 1e-12 on the
//! 7 × 7 square block and the contact patch (`tests/cli/mpi.rs`); on the 32 × 32 square block
//! 1.6e-8 in the contact pressure, where the two condensations on one process differ by
//! 1.9e-8; on the Hertz scene the estimate agrees to 1e-11 with the one-process `columns`
//! route and to 8e-8 with the one-process `schur` route, again the gap between the routes.
//!
//! ## Implicit storage of D (`-dual_contact_storage implicit`)
//!
//! The talk's other storage of D: `W` is never formed, each product is one interior solve
//! with the same solver of `A_zz` as the three-step condensation (MUMPS factorised once by
//! default, or any KSP and preconditioner),
//!
//! ```text
//!   y = W x = A_rr x − A_rz (A_zz⁻¹ (A_zr x))          (A_rr, A_zr kept sparse)
//! ```
//!
//! A condensed solver that needs products only then runs on it: projected gradient (Uzawa)
//! and the semi-smooth Newton method (its Newton systems by conjugate gradients or GMRES on
//! products, [`crate::contact`]). Uzawa on this operator is **Uzawa on the full dual system**,
//! the talk's saddle-point route (Arrow, Hurwicz & Uzawa 1958; for contact Glowinski, Lions &
//! Trémolières, "Analyse numérique des inéquations variationnelles", Dunod 1976, and Kikuchi
//! & Oden, "Contact problems in elasticity", SIAM 1988, ch. 6): with the forces `r_k` as data,
//! one solve of the dual system's interior rows `A_zz z_k = b_z − A_zr r_k` gives the contact
//! displacement (the multiplier of the force unknowns)
//! `u_k = A_rz z_k + A_rr r_k − b_r = W r_k + u_free`, and the forces are updated by the
//! projected step `r_{k+1} = P_K(r_k − ρ (u_k − g̃))` ([`crate::contact`]'s Uzawa, `P_K` the
//! projection on `rN ≤ 0`, `|rT| ≤ s`); `ρ = 1/λ̂`, `λ̂` a power-iteration estimate of
//! `λmax(W) = ‖W‖₂` from products (no user parameter). `u_free` itself costs one solve (`ℓ`).
//!
//! The solvers that need entries of `W` (projected relaxation, D-PANA, TAO, the dense Newton
//! factorisations) are refused with implicit storage ([`Error::Usage`]). The diagonal of `W`
//! that the solvers use for scaling (augmentation parameters, Jacobi preconditioner, residual
//! scales) would cost one solve per force, as much as forming `W`: it is replaced by a uniform
//! value, the power-iteration estimate of `λmax(W)` (20 products). The diagonal of `A_rr`, an
//! upper bound of `diag(W)` available for free, was measured useless for this: on the square
//! block it varies by 1000× along the contact side where `diag(W)` varies by 8× (the forces
//! upstream along the boundary load every unknown downstream until `A_zz⁻¹` relaxes them). Every
//! solver stays correct with any positive scaling; the semi-smooth Newton method takes more
//! steps with it (13 against 3 on that block), Uzawa's step does not depend on it.
//!
//! A product that fails (a PETSc error, a Krylov method that does not converge) writes NaN
//! (the solvers stop on a non-finite iterate) and keeps the error, which the caller returns
//! in place of the solver's ([`ColumnCondensation::take_error`]).
use std::cell::{Cell, RefCell};

use nalgebra::DMatrix;

use super::system::ReducedRows;
use crate::error::{Error, Result};
use crate::petsc::{Comm, LinearSolver, Matrix, Session, SolveStats};

/// The option that names the condensation.
pub const CONDENSATION_OPTION: &str = "-dual_contact_condensation";
/// The option that names the storage of `W`.
pub const STORAGE_OPTION: &str = "-dual_contact_storage";

/// The option that turns off the local parametrisation of the contact part (`false`): the Schur
/// route then keeps the contact forces as unknowns, as when the parametrisation does not apply.
pub const LOCAL_OPTION: &str = "-dual_contact_local";

/// `-dual_contact_local true|false`, true without it.
pub fn local_from_options(session: &Session) -> Result<bool> {
    match session.option(LOCAL_OPTION)?.as_deref() {
        None | Some("true") => Ok(true),
        Some("false") => Ok(false),
        Some(other) => Err(Error::Usage(format!("{LOCAL_OPTION} takes true or false (got \"{other}\")"))),
    }
}

/// Right-hand sides per block solve of the flexibility columns (a block of the interior's
/// owned rows, `rows × 64` values, is held at a time).
pub const BLOCK_COLUMNS: usize = 64;

/// Power iterations of the diagonal estimate of the implicit storage.
const POWER_ITERATIONS: usize = 20;

/// The talk's storages of D (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    /// `W` formed, dense (by the condensation).
    Dense,
    /// `W` never formed: products by interior solves.
    Implicit,
}

impl Storage {
    /// The name of `-dual_contact_storage`: `"dense"` or `"implicit"`.
    pub fn name(self) -> &'static str {
        match self {
            Storage::Dense => "dense",
            Storage::Implicit => "implicit",
        }
    }

    /// `-dual_contact_storage dense|implicit`, dense without it.
    pub fn from_options(session: &Session) -> Result<Self> {
        match session.option(STORAGE_OPTION)?.as_deref() {
            None | Some("dense") => Ok(Storage::Dense),
            Some("implicit") => Ok(Storage::Implicit),
            Some(other) => Err(Error::Usage(format!("{STORAGE_OPTION} takes dense or implicit (got \"{other}\")"))),
        }
    }
}

/// The talk's condensation strategies (module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Condensation {
    /// One MUMPS factorisation with the Schur complement on the contact unknowns.
    Schur,
    /// One interior solve per contact unknown (a column of `W`).
    Columns,
}

impl Condensation {
    /// The name of the option value: `"schur"` or `"columns"`.
    pub fn name(self) -> &'static str {
        match self {
            Condensation::Schur => "schur",
            Condensation::Columns => "columns",
        }
    }

    /// The condensation asked for (see the module documentation); `prefix` is the dual's
    /// PETSc options prefix. With implicit storage the interior is solved by the three-step
    /// condensation's solver (`columns`, without forming `W`); `schur` is refused.
    pub fn from_options(session: &Session, prefix: &str, storage: Storage) -> Result<Self> {
        refuse_undistributable(session)?;
        let configured =
            session.has_option(&format!("-{prefix}ksp_type"))? || session.has_option(&format!("-{prefix}pc_type"))?;
        let asked = session.option(CONDENSATION_OPTION)?;
        if storage == Storage::Implicit {
            return match asked.as_deref() {
                None | Some("columns") => Ok(Condensation::Columns),
                Some("schur") => Err(Error::Usage(format!(
                    "{STORAGE_OPTION} implicit never forms W: its products are solves with the interior block \
                     (MUMPS by default, or -{prefix}ksp_type/-{prefix}pc_type), not the Schur complement; drop \
                     {CONDENSATION_OPTION} schur or use {STORAGE_OPTION} dense"
                ))),
                Some(other) => {
                    Err(Error::Usage(format!("{CONDENSATION_OPTION} takes schur or columns (got \"{other}\")")))
                }
            };
        }
        match asked.as_deref() {
            // Under MPI the Schur complement is not available (PETSc 3.18's MUMPS interface
            // computes it on one process): the three-step condensation, distributed.
            None => Ok(if configured || session.size() > 1 { Condensation::Columns } else { Condensation::Schur }),
            Some("schur") if configured => Err(Error::Usage(format!(
                "{CONDENSATION_OPTION} schur factorises with MUMPS and the Schur complement: drop -{prefix}ksp_type and \
                 -{prefix}pc_type, or use {CONDENSATION_OPTION} columns to condense with that solver"
            ))),
            Some("schur") => Ok(Condensation::Schur),
            Some("columns") => Ok(Condensation::Columns),
            Some(other) => Err(Error::Usage(format!("{CONDENSATION_OPTION} takes schur or columns (got \"{other}\")"))),
        }
    }
}

/// Refuse, before any work, what of the dual contact cannot run on several MPI ranks:
/// `-dual_contact_condensation schur` (PETSc 3.18 computes MUMPS Schur complements on one
/// process). On one process, or without that option, nothing is refused.
pub fn refuse_undistributable(session: &Session) -> Result<()> {
    if session.size() > 1 && session.option(CONDENSATION_OPTION)?.as_deref() == Some("schur") {
        return Err(Error::SingleProcess {
            feature: format!("{CONDENSATION_OPTION} schur"),
            reason: format!(
                "started on {} MPI processes: the dual contact's Schur complement on the contact forces is computed \
                 on one process in PETSc 3.18; drop {CONDENSATION_OPTION} (under MPI the default is columns, the \
                 three-step condensation with a distributed solver of the interior block)",
                session.size()
            ),
        });
    }
    Ok(())
}

/// The three-step condensation's pieces: `A_zz` with its solver, the coupling `A_zr` by
/// columns and `A_rr` (sparse). Its solves take `&self` (the solver and the counters are
/// behind cells), so that an implicit `W` can share it ([`ColumnCondensation::product`]).
pub struct ColumnCondensation<'s> {
    interior: Matrix<'s>,
    solver: RefCell<LinearSolver<'s>>,
    /// The ranks over which `A_zz` is distributed (the block solves' partial products are
    /// summed over them).
    comm: Comm,
    /// Column `j` of `A_zr` (rows of `z`), sparse; by symmetry row `j` of `A_rz`.
    coupling: Vec<Vec<(usize, f64)>>,
    /// Row `i` of `A_rr`, sparse (column indices relative to the contact block).
    a_rr: Vec<Vec<(usize, f64)>>,
    num_interior: usize,
    /// Linear solves so far, their iterations and seconds.
    solves: Cell<usize>,
    iterations: Cell<usize>,
    seconds: Cell<f64>,
    /// Block solves so far (each several of the `solves`: [`ColumnCondensation::flexibility`]).
    block_solves: Cell<usize>,
    /// Products `W x` so far (implicit storage).
    products: Cell<usize>,
    /// The first error of a product (module documentation).
    error: RefCell<Option<Error>>,
}

impl<'s> ColumnCondensation<'s> {
    /// Split the assembled rows (all rows, on every rank) at `num_interior` and set up the
    /// solver of `A_zz` with the options under `prefix`. Under MPI `A_zz` is distributed in
    /// contiguous row blocks (rank `k` owns rows `k nz / N .. (k + 1) nz / N`) and solved by
    /// the distributed solver; `A_zr`, `A_rr` and the solves' answers are held by every rank.
    pub fn new(session: &'s Session, rows: &ReducedRows, num_interior: usize, prefix: &str) -> Result<Self> {
        let n = rows.indptr.len() - 1;
        let nz = num_interior;
        let m = n - nz;
        let (mut indptr, mut indices, mut values) = (vec![0usize], Vec::new(), Vec::new());
        let mut coupling = vec![Vec::new(); m];
        let mut a_rr = vec![Vec::new(); m];
        for i in 0..n {
            for k in rows.indptr[i]..rows.indptr[i + 1] {
                let (j, v) = (rows.indices[k], rows.values[k]);
                match (i < nz, j < nz) {
                    (true, true) => {
                        indices.push(j);
                        values.push(v);
                    }
                    (true, false) => coupling[j - nz].push((i, v)),
                    (false, false) => a_rr[i - nz].push((j - nz, v)),
                    (false, true) => {}
                }
            }
            if i < nz {
                indptr.push(indices.len());
            }
        }
        let (size, rank) = (session.size(), session.rank());
        let owned = (rank * nz / size)..((rank + 1) * nz / size);
        let (first, last) = (indptr[owned.start], indptr[owned.end]);
        let owned_indptr: Vec<usize> = indptr[owned.start..=owned.end].iter().map(|k| k - first).collect();
        let interior = Matrix::from_csr_rows(
            session,
            session.world(),
            nz,
            owned.start,
            &owned_indptr,
            &indices[first..last],
            &values[first..last],
            1,
            true,
        )?;
        let mut solver = LinearSolver::new(session, session.world(), prefix)?;
        solver.prefer_ordering(4);
        solver.set_operator(&interior)?;
        Ok(ColumnCondensation {
            interior,
            solver: RefCell::new(solver),
            comm: session.world(),
            coupling,
            a_rr,
            num_interior: nz,
            solves: Cell::new(0),
            iterations: Cell::new(0),
            seconds: Cell::new(0.0),
            block_solves: Cell::new(0),
            products: Cell::new(0),
            error: RefCell::new(None),
        })
    }

    /// Number of contact unknowns.
    pub fn size(&self) -> usize {
        self.coupling.len()
    }

    fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>> {
        let mut b = self.interior.create_vector()?;
        let owned = b.owned_range();
        b.set_owned(&rhs[owned])?;
        let mut x = self.interior.create_vector()?;
        let stats = self.solver.borrow_mut().solve(&self.interior, &b, &mut x)?;
        self.solves.set(self.solves.get() + 1);
        self.iterations.set(self.iterations.get() + stats.iterations);
        self.seconds.set(self.seconds.get() + stats.seconds);
        x.gather_all()
    }

    /// `A_rz y` for `y` on the interior rows.
    fn coupling_transpose(&self, y: &[f64]) -> Vec<f64> {
        self.coupling.iter().map(|col| col.iter().map(|&(i, v)| v * y[i]).sum()).collect()
    }

    /// `A_zr x` on the interior rows.
    fn coupling_times(&self, x: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.num_interior];
        for (col, xj) in self.coupling.iter().zip(x) {
            if *xj != 0.0 {
                for &(i, v) in col {
                    out[i] += v * xj;
                }
            }
        }
        out
    }

    /// `A_rr x`.
    fn a_rr_times(&self, x: &[f64]) -> Vec<f64> {
        self.a_rr.iter().map(|row| row.iter().map(|&(j, v)| v * x[j]).sum()).collect()
    }

    /// `W = A_rr − A_rz A_zz⁻¹ A_zr`, one solve per column (symmetrised), with `progress`
    /// told after every block (every 50 columns column by column). With a direct solver the columns are solved by blocks of
    /// [`BLOCK_COLUMNS`] right-hand sides ([`LinearSolver::solve_block`]): each rank keeps its
    /// own rows of `X = A_zz⁻¹ A_zr`, forms its part of `A_rz X` from them, and the parts are
    /// summed over the ranks (no rank holds all of `X`).
    pub fn flexibility(&self, progress: &mut dyn FnMut(usize, usize)) -> Result<DMatrix<f64>> {
        let m = self.coupling.len();
        let mut w = DMatrix::zeros(m, m);
        for (i, row) in self.a_rr.iter().enumerate() {
            for &(j, v) in row {
                w[(i, j)] += v;
            }
        }
        let owned = self.interior.owned_rows();
        let mut done = 0;
        while done < m {
            let block = (done..(done + BLOCK_COLUMNS).min(m)).collect::<Vec<_>>();
            let mut rhs = vec![0.0; owned.len() * block.len()];
            for (c, &j) in block.iter().enumerate() {
                for &(i, v) in self.coupling[j].iter().filter(|(i, _)| owned.contains(i)) {
                    rhs[c * owned.len() + i - owned.start] = v;
                }
            }
            let start = std::time::Instant::now();
            let solved = self.solver.borrow_mut().solve_block(&self.interior, &rhs, block.len())?;
            let Some(x) = solved else {
                // Not a direct solver: column by column.
                return self.flexibility_by_columns(w, progress);
            };
            self.solves.set(self.solves.get() + block.len());
            self.block_solves.set(self.block_solves.get() + 1);
            self.seconds.set(self.seconds.get() + start.elapsed().as_secs_f64());
            // This rank's part of A_rz X (A_rz = A_zrᵀ), then the sum over the ranks.
            let mut part = vec![0.0; m * block.len()];
            for (c, _) in block.iter().enumerate() {
                let column = &x[c * owned.len()..(c + 1) * owned.len()];
                for (i, coupling) in self.coupling.iter().enumerate() {
                    part[c * m + i] = coupling
                        .iter()
                        .filter(|(r, _)| owned.contains(r))
                        .map(|&(r, v)| v * column[r - owned.start])
                        .sum::<f64>();
                }
            }
            let product = self.comm.sum(&part)?;
            for (c, &j) in block.iter().enumerate() {
                for i in 0..m {
                    w[(i, j)] -= product[c * m + i];
                }
            }
            done += block.len();
            progress(done, m);
        }
        Ok(0.5 * (&w + w.transpose()))
    }

    /// [`ColumnCondensation::flexibility`] by one solve per column (iterative solvers), from
    /// `w` holding `A_rr`.
    fn flexibility_by_columns(
        &self,
        mut w: DMatrix<f64>,
        progress: &mut dyn FnMut(usize, usize),
    ) -> Result<DMatrix<f64>> {
        let m = self.coupling.len();
        let mut rhs = vec![0.0; self.num_interior];
        for j in 0..m {
            rhs.fill(0.0);
            for &(i, v) in &self.coupling[j] {
                rhs[i] = v;
            }
            let x = self.solve(&rhs)?;
            for (i, v) in self.coupling_transpose(&x).into_iter().enumerate() {
                w[(i, j)] -= v;
            }
            if j % 50 == 49 {
                progress(j + 1, m);
            }
        }
        Ok(0.5 * (&w + w.transpose()))
    }

    /// `y = W x = A_rr x − A_rz A_zz⁻¹ A_zr x` by one interior solve (implicit storage). On a
    /// failed solve `y` is NaN and the error is kept ([`ColumnCondensation::take_error`]).
    pub fn product(&self, x: &[f64], y: &mut [f64]) {
        self.products.set(self.products.get() + 1);
        let solved = if x.iter().all(|v| *v == 0.0) {
            Ok(vec![0.0; self.num_interior])
        } else {
            self.solve(&self.coupling_times(x))
        };
        match solved {
            Ok(z) => {
                let a = self.a_rr_times(x);
                for ((yi, ai), ci) in y.iter_mut().zip(a).zip(self.coupling_transpose(&z)) {
                    *yi = ai - ci;
                }
            }
            Err(e) => {
                y.fill(f64::NAN);
                self.error.borrow_mut().get_or_insert(e);
            }
        }
    }

    /// The diagonal the solvers scale with, for the implicit storage (module documentation):
    /// uniform, the Rayleigh quotient `λ̂` of `POWER_ITERATIONS` (20) power iterations on
    /// products (close below `λmax(W)`, which bounds every diagonal entry).
    pub fn diagonal_estimate(&self) -> Result<Vec<f64>> {
        let n = self.size();
        let mut x: Vec<f64> = (0..n).map(|k| 1.0 + 0.1 * ((k % 7) as f64) / 7.0).collect();
        let mut y = vec![0.0; n];
        let mut rayleigh = 0.0f64;
        for _ in 0..POWER_ITERATIONS {
            let norm = x.iter().map(|v| v * v).sum::<f64>().sqrt();
            x.iter_mut().for_each(|v| *v /= norm);
            self.product(&x, &mut y);
            if let Some(e) = self.take_error() {
                return Err(e);
            }
            rayleigh = x.iter().zip(&y).map(|(a, b)| a * b).sum();
            std::mem::swap(&mut x, &mut y);
        }
        Ok(vec![rayleigh; n])
    }

    /// The relative accuracy of the products, measured by their symmetry: for two fixed probes
    /// `x`, `y`, `|xᵀWy − yᵀWx| / (|x| |Wy| + |y| |Wx|)` (zero for exact products of the
    /// symmetric `W`). The cancellation in `A_rr x − A_rz A_zz⁻¹ A_zr x` (`A_rr` is up to 1000×
    /// larger than `W` on the square block) leaves noise of this size in every product.
    pub fn product_accuracy(&self) -> Result<f64> {
        let n = self.size();
        let x: Vec<f64> = (0..n).map(|k| 1.0 + 0.37 * ((k * 7 % 11) as f64)).collect();
        let y: Vec<f64> = (0..n).map(|k| ((k * 5 % 13) as f64) - 6.0).collect();
        let (mut wx, mut wy) = (vec![0.0; n], vec![0.0; n]);
        self.product(&x, &mut wx);
        self.product(&y, &mut wy);
        if let Some(e) = self.take_error() {
            return Err(e);
        }
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(p, q)| p * q).sum::<f64>();
        let norm = |a: &[f64]| dot(a, a).sqrt();
        let scale = norm(&x) * norm(&wy) + norm(&y) * norm(&wx);
        Ok((dot(&x, &wy) - dot(&y, &wx)).abs() / scale.max(f64::MIN_POSITIVE))
    }

    /// The first error of a product since the last call, if any.
    pub fn take_error(&self) -> Option<Error> {
        self.error.borrow_mut().take()
    }

    /// Products `W x` computed so far.
    pub fn products(&self) -> usize {
        self.products.get()
    }

    /// `ℓ = −A_rz A_zz⁻¹ b_z`.
    pub fn condensed_load(&self, b_z: &[f64]) -> Result<Vec<f64>> {
        let x = self.solve(b_z)?;
        Ok(self.coupling_transpose(&x).into_iter().map(|v| -v).collect())
    }

    /// The interior `z = A_zz⁻¹ (b_z − A_zr r)` for the forces `r`.
    pub fn interior(&self, b_z: &[f64], r: &[f64]) -> Result<Vec<f64>> {
        let mut rhs = b_z.to_vec();
        for (a, c) in rhs.iter_mut().zip(self.coupling_times(r)) {
            *a -= c;
        }
        self.solve(&rhs)
    }

    /// What the solves were, for the report.
    pub fn stats(&self, storage: Storage) -> SolveStats {
        let mut s = self.solver.borrow().last_stats().unwrap_or(SolveStats {
            ksp_type: String::new(),
            pc_type: String::new(),
            factor_package: None,
            iterations: 0,
            converged_reason: String::new(),
            relative_residual: 0.0,
            seconds: 0.0,
        });
        s.iterations = self.iterations.get();
        s.seconds = self.seconds.get();
        s.converged_reason = match storage {
            Storage::Dense if self.block_solves.get() > 0 => format!(
                "{} solves with A_zz (three-step condensation; the flexibility columns in {} block solves)",
                self.solves.get(),
                self.block_solves.get()
            ),
            Storage::Dense => format!("{} solves with A_zz (three-step condensation)", self.solves.get()),
            Storage::Implicit => format!(
                "{} solves with A_zz (implicit storage of W: {} products W x, W never formed)",
                self.solves.get(),
                self.products.get()
            ),
        };
        s
    }
}
