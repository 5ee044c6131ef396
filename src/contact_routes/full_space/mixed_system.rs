//! The full-space mixed system of one rank for the SNES wrapper: the Alart–Curnier quantities
//! of the contact points, the residual, the generalized Jacobian, the convergence test, the
//! line search, and the rigid-motion checks (see the parent module's documentation).
use nalgebra::{DMatrix, DVector, Dyn, Matrix3, SymmetricEigen, Vector3};

use super::*;
use crate::contact_routes::block_elimination::{BlockElimination, ContactRow};
use crate::contact_routes::floating_elimination::FloatingElimination;

/// The Alart–Curnier quantities of one point at `(u_k, λ)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PointEval {
    pub(crate) tau_n: f64,
    pub(crate) tau_t: f64,
    pub(crate) threshold: f64,
    pub(crate) c_n: f64,
    pub(crate) c_t: f64,
}

/// The friction law as the mixed system sees it.
#[derive(Debug, Clone)]
pub(crate) enum Law {
    None,
    Tresca(Vec<f64>),
    Coulomb(Vec<f64>),
}

impl Law {
    pub(crate) fn of(friction: FrictionLaw) -> Self {
        match friction {
            FrictionLaw::Tresca { threshold } if threshold.iter().any(|&s| s > 0.0) => Law::Tresca(threshold),
            FrictionLaw::Coulomb { mu } if mu.iter().any(|&v| v > 0.0) => Law::Coulomb(mu),
            _ => Law::None,
        }
    }
    pub(crate) fn frictional(&self) -> bool {
        !matches!(self, Law::None)
    }
    /// Threshold of point `i` for the independent check (Coulomb: from the force itself).
    pub(crate) fn threshold(&self, i: usize, normal_force: f64) -> f64 {
        match self {
            Law::None => 0.0,
            Law::Tresca(s) => s[i],
            Law::Coulomb(mu) => mu[i] * (-normal_force).max(0.0),
        }
    }
    pub(crate) fn name(&self) -> &'static str {
        match self {
            Law::None => "frictionless",
            Law::Tresca(_) => "Tresca",
            Law::Coulomb(_) => "Coulomb",
        }
    }
}

/// Evaluate point `i` (augmentation `rho`, gap `gap`) at contact displacements `(uN, uT)` and
/// forces `(λN, λT)`.
pub(crate) fn evaluate(law: &Law, i: usize, rho: [f64; 2], gap: f64, u: [f64; 2], lambda: [f64; 2]) -> PointEval {
    let tau_n = lambda[0] - rho[0] * (u[0] - gap);
    let c_n = (lambda[0] - tau_n.min(0.0)) / rho[0];
    let (tau_t, threshold, c_t) = match law {
        Law::None => (0.0, 0.0, 0.0),
        _ => {
            let s = match law {
                Law::Tresca(s) => s[i],
                Law::Coulomb(mu) => mu[i] * (-tau_n).max(0.0),
                Law::None => 0.0,
            };
            let tau_t = lambda[1] - rho[1] * u[1];
            (tau_t, s, (lambda[1] - tau_t.clamp(-s, s)) / rho[1])
        }
    };
    PointEval { tau_n, tau_t, threshold, c_n, c_t }
}

/// The piece of the generalized Jacobian at a point (see the module documentation).
pub(crate) fn classify(law: &Law, e: &PointEval, bonded_start: bool) -> PointState {
    let contact = e.tau_n <= 0.0;
    let tangential = if !law.frictional() {
        TangentialState::Free
    } else if e.threshold > 0.0 {
        if e.tau_t.abs() < e.threshold {
            TangentialState::Stick
        } else {
            TangentialState::Slip { positive: e.tau_t > 0.0 }
        }
    } else if bonded_start && contact && e.tau_t == 0.0 {
        TangentialState::Stick
    } else {
        TangentialState::Free
    };
    PointState { contact, tangential }
}

/// The status reported for a point: open unless it carries a normal force or sits on the
/// obstacle under compression (`τN < 0`).
pub(crate) fn status_of(law: &Law, e: &PointEval) -> PointStatus {
    if e.tau_n >= 0.0 {
        return PointStatus::Open;
    }
    match classify(law, e, false).tangential {
        TangentialState::Stick => PointStatus::Stick,
        _ => PointStatus::Slip,
    }
}

/// A contact point owned by this rank, with the positions of its unknowns.
#[derive(Debug, Clone)]
pub(crate) struct OwnedPoint {
    pub(crate) index: usize,
    /// The coefficients of the point's normal and tangential rows of `B` on each dof they
    /// touch (the point's node; with a contact pair also the master nodes), by increasing dof.
    pub(crate) coefficients: Vec<[f64; 2]>,
    /// The positions of those dofs in the ghosted iterate.
    pub(crate) positions: Vec<usize>,
    /// Where each entry of a contact row sits among the row's stored entries (increasing
    /// global columns): entry `e < coefficients.len()` is the dof of `coefficients[e]`, then the
    /// multipliers λN (λT). The identity on one process; under MPI a master dof owned by a
    /// later rank is stored after this rank's multipliers.
    pub(crate) slots: Vec<usize>,
    /// The normal and the tangential row applied to the rigid motions (3 per body).
    pub(crate) rigid: [DVector<f64>; 2],
    pub(crate) gap: f64,
    pub(crate) rho: [f64; 2],
    /// Position of λN (λT follows) in the ghosted iterate.
    pub(crate) lambda: usize,
    /// Position in the owned residual of the normal row (the tangential row follows).
    pub(crate) row: usize,
    /// Pattern position of the first entry of the normal row (each contact row has one entry
    /// per dof of `coefficients` and `per_point` multiplier entries, placed as `slots` says).
    pub(crate) start: usize,
}

/// Rigid motions left free by the Dirichlet conditions: the Gram matrix of their rows, on the
/// rigid motions of every body (3 each).
#[derive(Debug, Clone)]
pub(crate) struct RigidCheck {
    pub(crate) dirichlet: DMatrix<f64>,
}

fn rigid_row(direction: [f64; 2], scaled: [f64; 2]) -> Vector3<f64> {
    Vector3::new(direction[0], direction[1], direction[1] * scaled[0] - direction[0] * scaled[1])
}

/// The rigid-motion row of one dof (`2·node + component`) at its node's scaled position.
pub(crate) fn dof_rigid_row(dof: usize, scaled: [f64; 2]) -> Vector3<f64> {
    rigid_row(if dof.is_multiple_of(2) { [1.0, 0.0] } else { [0.0, 1.0] }, scaled)
}

/// Dofs to pin with springs so that, with the Dirichlet rows (`dirichlet`: their Gram matrix of
/// rigid-motion rows, 3 per body), every rigid motion is blocked, chosen among `candidates`
/// (the dofs the contact rows touch, increasing) that are not prescribed. Per body that the
/// Dirichlet rows do not hold: the free dofs of its candidate node farthest from their centre,
/// then of the node farthest from that one, then of the others by decreasing distance from the
/// first, until that body's rigid motions are blocked. `None` if even every candidate leaves a
/// rigid motion free.
pub(crate) fn choose_pins(
    candidates: &[usize],
    mesh: &Mesh,
    piece_of: &[usize],
    is_fixed: &dyn Fn(usize) -> bool,
    scaled: &dyn Fn([f64; 2]) -> [f64; 2],
    dirichlet: &DMatrix<f64>,
) -> Option<Vec<usize>> {
    let mut nodes: Vec<usize> = candidates.iter().map(|&dof| dof / 2).collect();
    nodes.dedup();
    let pieces = dirichlet.nrows() / 3;
    let distance = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]);
    let mut pins = Vec::new();
    for piece in 0..pieces {
        let mut gram: Matrix3<f64> = dirichlet.fixed_view::<3, 3>(3 * piece, 3 * piece).into_owned();
        if full_rank(&gram) {
            continue;
        }
        let own: Vec<usize> = nodes.iter().copied().filter(|&k| piece_of[k] == piece).collect();
        if own.is_empty() {
            return None;
        }
        let position = |k: usize| mesh.nodes[k];
        let mut centre = [0.0; 2];
        for &k in &own {
            centre[0] += position(k)[0] / own.len() as f64;
            centre[1] += position(k)[1] / own.len() as f64;
        }
        let first =
            *own.iter().max_by(|&&i, &&j| distance(position(i), centre).total_cmp(&distance(position(j), centre)))?;
        let mut order: Vec<usize> = own.iter().copied().filter(|&k| k != first).collect();
        order.sort_by(|&i, &j| {
            distance(position(j), position(first)).total_cmp(&distance(position(i), position(first)))
        });
        order.insert(0, first);
        let mut held = false;
        for k in order {
            for c in 0..2 {
                if is_fixed(2 * k + c) || candidates.binary_search(&(2 * k + c)).is_err() {
                    continue;
                }
                let r = dof_rigid_row(2 * k + c, scaled(position(k)));
                gram += r * r.transpose();
                pins.push(2 * k + c);
            }
            if full_rank(&gram) {
                held = true;
                break;
            }
        }
        if !held {
            return None;
        }
    }
    pins.sort_unstable();
    Some(pins)
}

/// An orthonormal basis of the null space of a symmetric Gram matrix (eigenvalues at or below
/// 1e-10 of the largest, as [`full_rank`]); `None` when it has full rank.
pub(crate) fn null_space(gram: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let eigen = SymmetricEigen::<f64, Dyn>::new(gram.clone());
    let largest = eigen.eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
    let free: Vec<usize> = (0..gram.nrows()).filter(|&j| !blocks(eigen.eigenvalues[j], largest)).collect();
    if free.is_empty() {
        return None;
    }
    Some(DMatrix::from_fn(gram.nrows(), free.len(), |r, c| eigen.eigenvectors[(r, free[c])]))
}

pub(crate) fn full_rank(gram: &Matrix3<f64>) -> bool {
    full_rank_of(SymmetricEigen::new(*gram).eigenvalues.as_slice().to_vec())
}

fn full_rank_of(eigenvalues: Vec<f64>) -> bool {
    let largest = eigenvalues.iter().fold(0.0f64, |m, &l| m.max(l.abs()));
    eigenvalues.iter().all(|&l| blocks(l, largest))
}

/// Does an eigenvalue `l` of a Gram matrix whose largest is `largest` count (above 1e-10 of it)?
fn blocks(l: f64, largest: f64) -> bool {
    largest > 0.0 && l > 1e-10 * largest
}

/// What the failure of a body that nothing holds looks like.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Floating {
    pub(crate) closed: usize,
    pub(crate) imbalance: [f64; 2],
}

/// The mixed system of this rank, for the SNES wrapper.
pub(crate) struct MixedSystem<'s, 'p> {
    pub(crate) comm: Comm,
    /// Told each Newton step and its residual.
    pub(crate) progress: &'p dyn crate::problem::Progress,
    /// Exact Jacobian solves by block elimination with one factor of K, when they apply.
    pub(crate) elimination: Option<BlockElimination<'s>>,
    /// The same for a body its Dirichlet conditions do not hold (iterating in `(u, λ)`).
    pub(crate) held_by_contact: Option<FloatingElimination<'s>>,
    /// How SNES's LU keeps its factorisation across steps (the sparse LU route).
    pub(crate) reuse: Option<FactorisationReuse>,
    pub(crate) law: Law,
    pub(crate) per_point: usize,
    /// Owned displacement rows (they come first in the owned block) and their first dof.
    pub(crate) num_u: usize,
    pub(crate) first_dof: usize,
    pub(crate) indptr: Vec<usize>,
    pub(crate) local_columns: Vec<usize>,
    /// Values of the force rows' entries (K and −Bᵀ); the contact rows' entries are 0 here.
    pub(crate) base: Vec<f64>,
    /// With an elimination iterating in `(v, λ)` (one process): `K`'s rows, from which the
    /// force rows `K v − f` are evaluated; the pattern then holds their diagonal alone.
    pub(crate) stiffness: Option<&'p crate::fem::assembly::CsrRows>,
    pub(crate) rhs: Vec<f64>,
    pub(crate) fixed_row: Vec<bool>,
    pub(crate) points: Vec<OwnedPoint>,
    /// Spring stiffness and the pattern positions of the contact nodes' diagonal entries.
    pub(crate) spring: Option<(f64, Vec<usize>)>,
    pub(crate) rigid: Option<RigidCheck>,
    pub(crate) gap_scale: f64,
    pub(crate) tight: f64,
    pub(crate) tolerance: f64,
    // ---- iteration state
    pub(crate) step_states: Option<Vec<PointState>>,
    pub(crate) previous: Option<Vec<PointState>>,
    /// Status sets met since the last cycle, with the merit then.
    pub(crate) seen: Vec<(Vec<PointState>, f64)>,
    pub(crate) history: Vec<IterationRecord>,
    pub(crate) notes: Vec<String>,
    pub(crate) cycles: usize,
    pub(crate) step_cap: f64,
    pub(crate) last_step_scale: f64,
    pub(crate) regularized: bool,
    pub(crate) regularized_steps: usize,
    pub(crate) floating_steps: usize,
    pub(crate) previous_equilibrium: f64,
    pub(crate) floating: Option<Floating>,
    pub(crate) equilibrium: f64,
    pub(crate) contact_residual: f64,
    /// The force rows' scale `max_r (Σ_c |K_rc x_c| + |f_r|)` at the current iterate.
    pub(crate) force_terms: f64,
    /// Scale of the force rows in the merit (the largest diagonal entry of K).
    pub(crate) force_scale: f64,
    /// `½ ‖F_u / k_ref‖²` and the whole merit at the current iterate.
    pub(crate) force_merit: f64,
    pub(crate) merit: f64,
    pub(crate) monotone: bool,
    pub(crate) line_search_failed: bool,
    pub(crate) shortened_steps: usize,
    pub(crate) best_merit: f64,
    pub(crate) best_at: usize,
}

impl MixedSystem<'_, '_> {
    /// The contact displacements `B u` of the owned points in their frames: read from `u` in
    /// the unknowns `(u, λ)`, or `B v + W λ` in the eliminations' `(v, λ)`
    /// (`block_elimination.rs`, `floating_elimination.rs`). Linear in `x`.
    pub(crate) fn contact_displacements(&self, x: &[f64]) -> Vec<[f64; 2]> {
        let frame = |p: &OwnedPoint| {
            let mut bu = [0.0; 2];
            for (&at, c) in p.positions.iter().zip(&p.coefficients) {
                bu[0] += c[0] * x[at];
                bu[1] += c[1] * x[at];
            }
            bu
        };
        let response = match (&self.elimination, &self.held_by_contact) {
            (Some(elimination), _) => Some(elimination.flexibility_times(&self.multipliers(x))),
            (None, Some(floating)) if floating.in_v => Some(floating.flexibility_times(&self.multipliers(x))),
            _ => None,
        };
        match response {
            None => self.points.iter().map(frame).collect(),
            Some(response) => {
                // One process: every point is owned, in boundary order.
                self.points
                    .iter()
                    .map(|p| {
                        let bv = frame(p);
                        [bv[0] + response[2 * p.index], bv[1] + response[2 * p.index + 1]]
                    })
                    .collect()
            }
        }
    }

    /// The multipliers of the owned points in `W`'s numbering (`2i`: normal, `2i + 1`: tangential).
    pub(crate) fn multipliers(&self, x: &[f64]) -> Vec<f64> {
        let mut lambda = vec![0.0; 2 * self.points.len()];
        for p in &self.points {
            lambda[2 * p.index] = x[p.lambda];
            if self.per_point == 2 {
                lambda[2 * p.index + 1] = x[p.lambda + 1];
            }
        }
        lambda
    }

    /// Evaluate the points at `x`.
    pub(crate) fn evaluations(&self, x: &[f64]) -> Vec<PointEval> {
        self.contact_displacements(x).into_iter().zip(&self.points).map(|(u, p)| self.eval_at(p, u, x)).collect()
    }

    /// Evaluate a point from its contact displacements (frame) and its multipliers in `x`.
    pub(crate) fn eval_at(&self, p: &OwnedPoint, u: [f64; 2], x: &[f64]) -> PointEval {
        let lambda = [x[p.lambda], if self.per_point == 2 { x[p.lambda + 1] } else { 0.0 }];
        evaluate(&self.law, p.index, p.rho, p.gap, u, lambda)
    }

    /// Do the unknowns read `(v, λ)` (an elimination's change of unknowns) rather than `(u, λ)`?
    pub(crate) fn in_v(&self) -> bool {
        self.elimination.is_some() || self.held_by_contact.as_ref().is_some_and(|f| f.in_v)
    }

    /// Is `c` a displacement column of the force rows' stiffness part? In `(v, λ)` the force
    /// rows are `K v − f` (and the floating elimination's pinned terms): their `−Bᵀ` entries
    /// drop out.
    pub(crate) fn in_force_rows(&self, c: usize) -> bool {
        !self.in_v() || c < self.num_u
    }

    /// The merit `Θ = ½ (‖C‖² + ‖F_u / k_ref‖²)` at `x − t d` (every rank; see `step_length`).
    pub(crate) fn merit_at(&self, x: &[f64], d: &[f64], t: f64) -> Result<f64> {
        let trial: Vec<f64> = x.iter().zip(d).map(|(a, b)| a - t * b).collect();
        let mut sum = 0.0;
        for e in self.evaluations(&trial) {
            sum += e.c_n * e.c_n + e.c_t * e.c_t;
        }
        let contact = self.comm.sum(&[sum])?[0];
        Ok(0.5 * contact + (1.0 - t) * (1.0 - t) * self.force_merit)
    }

    pub(crate) fn states(&self, x: &[f64]) -> Vec<PointState> {
        self.evaluations(x).iter().map(|e| classify(&self.law, e, self.rigid.is_some())).collect()
    }

    /// The rigid motions the Dirichlet rows and the closed/sticking rows of `states` leave
    /// free: an orthonormal basis (columns over the rigid-motion coordinates, 3 per body) of
    /// the null space of their Gram matrix; `None` when they block every rigid motion.
    pub(crate) fn free_motions(&self, states: &[PointState]) -> Result<Option<DMatrix<f64>>> {
        let Some(rigid) = &self.rigid else { return Ok(None) };
        let size = rigid.dirichlet.nrows();
        let mut gram = DMatrix::<f64>::zeros(size, size);
        for (p, s) in self.points.iter().zip(states) {
            if s.contact {
                gram += &p.rigid[0] * p.rigid[0].transpose();
            }
            if s.tangential == TangentialState::Stick {
                gram += &p.rigid[1] * p.rigid[1].transpose();
            }
        }
        let summed = self.comm.sum(gram.as_slice())?;
        Ok(null_space(&(&rigid.dirichlet + DMatrix::from_column_slice(size, size, &summed))))
    }
}

impl NonlinearSystem for MixedSystem<'_, '_> {
    fn residual(&mut self, x: &[f64], f: &mut [f64]) -> Result<()> {
        for (r, fr) in f.iter_mut().enumerate().take(self.num_u) {
            if let Some(k) = self.stiffness {
                // One process: the iterate's first entries are the dofs in their own order.
                let (cols, vals) = k.row(self.first_dof + r);
                *fr = cols.iter().zip(vals).map(|(&c, v)| v * x[c]).sum::<f64>() - self.rhs[r];
                continue;
            }
            let span = self.indptr[r]..self.indptr[r + 1];
            *fr = self.base[span.clone()]
                .iter()
                .zip(&self.local_columns[span])
                .filter(|(_, &c)| self.in_force_rows(c))
                .map(|(v, &c)| v * x[c])
                .sum::<f64>()
                - self.rhs[r];
        }
        if let Some(floating) = self.held_by_contact.as_ref().filter(|f| f.in_v) {
            // In (v, λ) the pinned rows keep a part of the contact forces (floating_elimination.rs).
            for (dof, v) in floating.pinned_forces(&self.multipliers(x)) {
                f[dof - self.first_dof] += v;
            }
        }
        for (p, e) in self.points.iter().zip(self.evaluations(x)) {
            f[p.row] = e.c_n;
            if self.per_point == 2 {
                f[p.row + 1] = e.c_t;
            }
        }
        Ok(())
    }

    fn jacobian(&mut self, x: &[f64], values: &mut [f64]) -> Result<()> {
        // With the block elimination the assembled Jacobian is never used (its solves take the
        // pieces below): no copy of K's values, which would cost more than the step itself.
        let own_solve = self.elimination.is_some() || self.held_by_contact.is_some();
        if !own_solve {
            values.copy_from_slice(&self.base);
        }
        let mut states = self.states(x);
        // A slip point whose slip direction reverses sticks for this step.
        if let Some(before) = &self.step_states {
            contact::stick_reversed_slips(&mut states, before);
        }
        let free = self.free_motions(&states)?;
        let held = free.is_none();
        self.regularized = !held;
        if !held && !own_solve {
            if let Some((k, positions)) = &self.spring {
                for &pos in positions {
                    values[pos] += k;
                }
            }
        }
        let coulomb = match &self.law {
            Law::Coulomb(mu) => Some(mu),
            _ => None,
        };
        let mut rows = Vec::with_capacity(if own_solve { self.per_point * states.len() } else { 0 });
        for (p, s) in self.points.iter().zip(&states) {
            let nd = p.coefficients.len();
            let w = nd + self.per_point;
            let row_n = &mut values[p.start..p.start + w];
            let at = &p.slots;
            if s.contact {
                for (&e, c) in at.iter().zip(&p.coefficients) {
                    row_n[e] = c[0];
                }
                rows.push(ContactRow::Displacement);
            } else {
                row_n[at[nd]] = 1.0 / p.rho[0];
                rows.push(ContactRow::Force { rho: p.rho[0] });
            }
            if self.per_point == 2 {
                let row_t = &mut values[p.start + w..p.start + 2 * w];
                match (s.tangential, coulomb) {
                    (TangentialState::Stick, _) => {
                        for (&e, c) in at.iter().zip(&p.coefficients) {
                            row_t[e] = c[1];
                        }
                        rows.push(ContactRow::Displacement);
                    }
                    (TangentialState::Slip { positive }, Some(mu)) if s.contact => {
                        let sigma = if positive { 1.0 } else { -1.0 };
                        let a = -sigma * mu[p.index] * p.rho[0] / p.rho[1];
                        for (&e, c) in at.iter().zip(&p.coefficients) {
                            row_t[e] = a * c[0];
                        }
                        let (b, c) = (sigma * mu[p.index] / p.rho[1], 1.0 / p.rho[1]);
                        row_t[at[nd]] = b;
                        row_t[at[nd + 1]] = c;
                        rows.push(ContactRow::CoulombSlip { a, b, c });
                    }
                    _ => {
                        row_t[at[nd + 1]] = 1.0 / p.rho[1];
                        rows.push(ContactRow::Force { rho: p.rho[1] });
                    }
                }
            }
        }
        if let Some(floating) = &mut self.held_by_contact {
            floating.set_rows(rows, free.as_ref())?;
        } else if let Some(elimination) = &mut self.elimination {
            elimination.set_rows(rows)?;
        }
        self.step_states = Some(states);
        Ok(())
    }

    fn converged(&mut self, iteration: usize, x: &[f64], f: &[f64]) -> Result<Convergence> {
        // Backward error of the force rows, contact rows relative to the displacement scale.
        let (mut eq_num, mut eq_den, mut umax) = (0.0f64, 0.0f64, 0.0f64);
        let mut imbalance = [0.0f64; 2];
        for r in 0..self.num_u {
            let terms: f64 = match self.stiffness {
                Some(k) => {
                    let (cols, vals) = k.row(self.first_dof + r);
                    cols.iter().zip(vals).map(|(&c, v)| (v * x[c]).abs()).sum()
                }
                None => {
                    let span = self.indptr[r]..self.indptr[r + 1];
                    self.base[span.clone()]
                        .iter()
                        .zip(&self.local_columns[span])
                        .filter(|(_, &c)| self.in_force_rows(c))
                        .map(|(v, &c)| (v * x[c]).abs())
                        .sum()
                }
            };
            eq_num = eq_num.max(f[r].abs());
            eq_den = eq_den.max(terms + self.rhs[r].abs());
            umax = umax.max(x[r].abs());
            if !self.fixed_row[r] {
                imbalance[(self.first_dof + r) % 2] += f[r];
            }
        }
        if self.in_v() {
            // In (v, λ) the displacement scale also takes the contact displacements B v + W λ.
            for u in self.contact_displacements(x) {
                umax = umax.max(u[0].abs()).max(u[1].abs());
            }
        }
        let mut c_max = 0.0f64;
        let (mut c_sq, mut f_sq) = (0.0f64, 0.0f64);
        for p in &self.points {
            c_max = c_max.max(f[p.row].abs());
            c_sq += f[p.row] * f[p.row];
            if self.per_point == 2 {
                c_max = c_max.max(f[p.row + 1].abs());
                c_sq += f[p.row + 1] * f[p.row + 1];
            }
        }
        for fr in f.iter().take(self.num_u) {
            f_sq += (fr / self.force_scale).powi(2);
        }
        let states = self.states(x);
        let changes = self.previous.as_ref().map_or(0, |prev| contact::count_changes(prev, &states));
        let off_piece = self.step_states.as_ref().map_or(states.len(), |s| contact::count_changes(s, &states));
        let closed = states.iter().filter(|s| s.contact).count();
        // Cycle detection: the status set equals one met two or more iterations before.
        let local_equal: Vec<f64> = self
            .seen
            .iter()
            .take(self.seen.len().saturating_sub(1))
            .map(|(earlier, _)| if *earlier == states { 1.0 } else { 0.0 })
            .collect();
        let maxima = self.comm.max(&[eq_num, eq_den, c_max, umax])?;
        let sums = self.comm.sum(&[
            changes as f64,
            off_piece as f64,
            closed as f64,
            imbalance[0],
            imbalance[1],
            c_sq,
            f_sq,
        ])?;
        self.force_merit = 0.5 * sums[6];
        self.merit = 0.5 * (sums[5] + sums[6]);
        let equal = if local_equal.is_empty() { Vec::new() } else { self.comm.min(&local_equal)? };
        let equilibrium = if maxima[1] > 0.0 { maxima[0] / maxima[1] } else { maxima[0] };
        self.force_terms = maxima[1];
        let u_scale = if maxima[3].max(self.gap_scale) > 0.0 { maxima[3].max(self.gap_scale) } else { 1.0 };
        let contact_residual = maxima[2] / u_scale;
        let (changes, off_piece, closed) = (sums[0] as usize, sums[1] as usize, sums[2] as usize);
        self.equilibrium = equilibrium;
        self.contact_residual = contact_residual;
        if iteration > 0 {
            self.history.push(IterationRecord { residual: equilibrium.max(contact_residual), status_changes: changes });
            self.progress.iteration(crate::problem::Phase::Solve, iteration, equilibrium.max(contact_residual));
        }
        self.previous = Some(states.clone());
        let exact_step = iteration > 0 && !self.regularized && self.last_step_scale == 1.0 && off_piece == 0;
        let within = |tol: f64| equilibrium <= tol && contact_residual <= tol;
        if within(self.tight) || (exact_step && within(self.tolerance)) {
            return Ok(Convergence::Converged(format!(
                "converged after {iteration} Newton steps: equilibrium {equilibrium:.2e}, contact {contact_residual:.2e}"
            )));
        }
        if !(equilibrium.is_finite() && contact_residual.is_finite()) {
            return Ok(Convergence::Diverged("the iterate became non-finite".into()));
        }
        if self.line_search_failed {
            return Ok(Convergence::Diverged(format!("the line search failed at Newton step {iteration}")));
        }
        if self.merit < 0.5 * self.best_merit {
            self.best_merit = self.merit;
            self.best_at = iteration;
        }
        if !self.regularized && iteration >= self.best_at + STEPS_WITHOUT_PROGRESS {
            if self.monotone {
                return Ok(Convergence::Diverged(format!(
                    "no progress in {STEPS_WITHOUT_PROGRESS} Newton steps (the merit did not halve)"
                )));
            }
            // Wandering without a cycle: damp as after a cycle, give it another round.
            self.monotone = true;
            self.best_at = iteration;
            self.notes.push(format!(
                "no progress in {STEPS_WITHOUT_PROGRESS} full Newton steps: monotone line search from step {iteration}"
            ));
        }
        if iteration > 0 && changes == 0 {
            self.step_cap = 1.0;
        }
        // A status set met again without the merit having halved since: a cycle (with
        // shortened steps a set may come back while the iterate progresses).
        let merit = self.merit;
        if equal.iter().zip(&self.seen).any(|(&e, (_, then))| e == 1.0 && merit > 0.5 * then) {
            self.cycles += 1;
            let what = format!(
                "active-set cycle at Newton step {iteration}: the status set of {} points repeats an earlier one",
                closed
            );
            if self.cycles >= CYCLES_BEFORE_FALLBACK {
                self.notes.push(what);
                return Ok(Convergence::Diverged(format!(
                    "{CYCLES_BEFORE_FALLBACK} active-set cycles despite damping"
                )));
            }
            self.step_cap = 0.5f64.powi(self.cycles as i32);
            self.monotone = true;
            self.notes.push(format!(
                "{what}; steps capped at {} until the statuses settle, monotone line search",
                self.step_cap
            ));
            self.seen.clear();
        }
        self.seen.push((states, self.merit));
        // A body that nothing holds: regularised steps that do not reduce the imbalance.
        if iteration > 0 && self.regularized {
            self.regularized_steps += 1;
            let stalled = equilibrium > 0.5 * self.previous_equilibrium;
            self.floating_steps = if stalled { self.floating_steps + 1 } else { 0 };
            self.floating = Some(Floating { closed, imbalance: [sums[3], sums[4]] });
            if self.floating_steps >= FLOATING_STEPS {
                return Ok(Convergence::Diverged(format!(
                    "the closed contact points do not hold the body ({closed} closed) and the equilibrium residual \
                     stays at {equilibrium:.2e}"
                )));
            }
        } else {
            self.floating_steps = 0;
            self.floating = None;
        }
        self.previous_equilibrium = equilibrium;
        Ok(Convergence::Iterating)
    }

    fn factorisation_reuse(&self) -> Option<FactorisationReuse> {
        self.reuse.clone()
    }

    fn jacobian_solver(&self) -> Option<String> {
        if self.held_by_contact.is_some() {
            return Some(FLOATING_ELIMINATION_NAME.to_string());
        }
        self.elimination.as_ref().map(|_| ELIMINATION_NAME.to_string())
    }

    fn solve_jacobian(&mut self, r: &[f64], d: &mut [f64]) -> Result<()> {
        // Force residuals at the round-off of the force rows' terms: no solve (the rows are linear).
        let negligible = ROUND_OFF * self.force_terms;
        if let Some(floating) = &mut self.held_by_contact {
            return floating.solve(r, d, negligible);
        }
        match &mut self.elimination {
            Some(elimination) => elimination.solve(r, d, negligible),
            None => Err(Error::PetscUsage("no block elimination set up".into())),
        }
    }

    /// Full semi-smooth Newton steps (the primal–dual active set method: on piecewise-linear
    /// equations they land on the solution of the current piece), capped after active-set
    /// cycles; once a cycle has been seen, a monotone Armijo backtracking on the merit
    /// `Θ = ½ (‖C‖² + ‖F_u / k_ref‖²)` (both parts in displacement units; the force rows are
    /// linear, so along an exact Newton direction `F_u(x − t d) = (1 − t) F_u(x)`), halving
    /// from the cap down to 10⁻⁶. (A non-monotone Armijo search from the start, as in the
    /// condensed method, shortened useful steps and lost the hard cases: μ ≥ 2 on fine P2
    /// meshes took more steps or failed.) Regularised steps are taken as they are.
    fn step_length(&mut self, x: &[f64], d: &[f64]) -> Result<f64> {
        let cap = self.step_cap;
        if self.regularized || !self.monotone {
            self.last_step_scale = cap;
            return Ok(cap);
        }
        let reference = self.merit;
        let mut t = cap;
        loop {
            let trial = self.merit_at(x, d, t)?;
            if trial <= (1.0 - ARMIJO * t) * reference {
                break;
            }
            t *= 0.5;
            if t < SMALLEST_STEP {
                self.line_search_failed = true;
                t = SMALLEST_STEP;
                break;
            }
        }
        if t < cap {
            self.shortened_steps += 1;
        }
        self.last_step_scale = t;
        Ok(t)
    }
}
