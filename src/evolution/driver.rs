//! The increments of a load path on the condensed contact route, with K factorised and
//! `W = B K⁻¹ Bᵀ` formed once for the whole path.
//!
//! ```text
//! setup        load cases: one right-hand side per load key (a name, or the ramped loads),
//!              each with its own part of the Dirichlet values: f(t) = Σ_k φ_k(t) f_k
//! factorise    K (+ springs), W once (ContactSetup::condense)
//! increment n  f(t_n); the obstacle at d(t_n) = φ(t_n) d; the law sees B u − shift with
//!                shift_N = d·n,  shift_T = d·t + s^(n−1)   (s = (B u)_T − d·t, the slip so far)
//!              u_free from the load cases' fields K⁻¹ f_k (computed once: no solve), the
//!              condensed solve warm-started from (u, r)^(n−1), recovery (one solve), independent check
//!              on the increment; failed: cut in two (at most MAX_HALVINGS times)
//! record       counts, resultants, energies (below), the profile at the asked times
//! ```
//!
//! With the shift, the tangential relative displacement the solvers see is the slip increment
//! `Δs = s^n − s^(n−1)`: Coulomb and Tresca in rates discretised by backward Euler (SCIENCE.md
//! §10; Klarbring, Mikelić and Shillor 1988; Andersson 1991 for existence of the incremental
//! problem), while the normal law stays on the total gap.
//!
//! # Energies (trapezoidal, exact for an increment in which u and r vary linearly)
//!
//! With `F` the non-contact external nodal forces (the loads, and at the prescribed dofs
//! `F = K u − Bᵀ r`, the supports' reactions), `E = ½ uᵀ K u`, `Δ` the change over increment n
//! and `r̄ = ½ (r^n + r^(n−1))`:
//!
//! ```text
//!   work      W += ½ (F^n + F^(n−1))·Δu  +  r̄·Δ(d-frame)      (loads, supports, moving obstacle)
//!   friction  D^n = −Σ_i r̄T_i Δs_i                            (dissipation, SCIENCE.md §10)
//!   normal    N^n = −Σ_i r̄N_i Δg̃_i ≥ 0,   g̃ = (B u)_N − d·n     (zero while the contact set is fixed)
//!   balance   W = E + Σ D + Σ N   (equilibrium K u = F + Bᵀ r at every increment)
//! ```
//!
//! `N` is the energy the discrete normal law loses when points close or open within an
//! increment (it vanishes with the increment). Each increment's record reports the friction
//! law's own dissipation `−Σ rT^n·Δs = Σ λ |rT^n|² ≥ 0` (backward Euler: the slip increment
//! opposes the end force); `D^n` equals it while a point slips one way at a steady threshold and
//! differs where points start, stop or reverse their slip within the increment (the trapezoid
//! then spreads a slip that happened at the end force over the whole increment; on the
//! Mindlin–Deresiewicz cycle `D^n` is −7e-5 J/m at the reversal increments, 1e-6 of the cycle's
//! dissipation). Both sums converge to the dissipation of the continuous path. The balance's residual is reported relative to
//! the work.
use serde::Serialize;

use super::load_path::LoadPath;
use super::record::{ContactProfile, StepRecord};
use crate::contact_routes::condensed_route::{ContactOutcome, Increment};
use crate::error::{Error, Result};
use crate::fem::assembly::{self, Constraints};
use crate::petsc::LinearSolver;
use crate::problem::ElasticityProblem;
use crate::report::contact::{ContactState, StateCounts};
use crate::scene::{ContactSolverSpec, Formulation};

/// What is done at every increment beyond its solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EachIncrement {
    /// The solve, its check and its record only.
    Solve,
    /// Also [`ElasticityProblem::postprocess`] (stresses, reactions, the equilibrium check):
    /// what the output files of an increment need.
    Postprocess,
    /// Also the dual solve and the estimate of the increment's problem (the contact terms on
    /// the increment: the law on the slip increment, the obstacle where it is at `t_n`).
    Estimate,
}

/// Most times one increment is cut in two before the path stops.
pub const MAX_HALVINGS: usize = 5;

/// The factors the scene's loads are multiplied by at one increment.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadFactors {
    /// One per `[[traction]]` of the scene (in order).
    pub traction: Vec<f64>,
    /// The body force's.
    pub body_force: f64,
    /// One per `[[dirichlet]]` of the scene (in order): its prescribed values' factor (the
    /// primal takes them from its load cases; the dual reads these).
    pub dirichlet: Vec<f64>,
}

/// What the contact law of an increment subtracts from the displacement at a point `x` of the
/// contact part with tangent `t`: `d + ((u^(n−1)(x) − d^(n−1))·t) t` — the obstacle's
/// displacement, and the slip so far along the tangent (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactShift {
    /// The obstacle's displacement at this increment.
    pub obstacle: [f64; 2],
    /// At the last converged increment.
    pub previous_obstacle: [f64; 2],
    /// The last converged displacement (whole vector).
    pub previous_displacement: Vec<f64>,
}

impl ContactShift {
    /// The shift vector at a point whose last displacement was `previous`, tangent `t`.
    pub fn at(&self, previous: [f64; 2], t: [f64; 2]) -> [f64; 2] {
        let slip = (previous[0] - self.previous_obstacle[0]) * t[0] + (previous[1] - self.previous_obstacle[1]) * t[1];
        [self.obstacle[0] + slip * t[0], self.obstacle[1] + slip * t[1]]
    }

    /// The last converged displacement of node `k`.
    pub fn previous_at_node(&self, k: usize) -> [f64; 2] {
        [self.previous_displacement[2 * k], self.previous_displacement[2 * k + 1]]
    }
}

/// What a load path reports (`report.json` → `load_path`, and `steps`).
#[derive(Debug, Clone, Serialize)]
pub struct LoadPathReport {
    /// Every converged increment.
    pub steps: Vec<StepRecord>,
    /// The contact profiles kept (at the asked times).
    pub profiles: Vec<ContactProfile>,
    /// Increments cut in two, over the path.
    pub halvings: usize,
    /// The energy balance at the end of the path.
    pub energy: EnergyBalance,
    /// How the increments were solved.
    pub route: String,
    /// What happened on the way.
    pub notes: Vec<String>,
}

/// A load path in `report.json` → `load_path` (its increments are in `steps`).
#[derive(Debug, Clone, Serialize)]
pub struct LoadPathSummary {
    /// Converged increments.
    pub increments: usize,
    /// Increments cut in two, over the path.
    pub halvings: usize,
    /// The energy balance at the end of the path.
    pub energy: EnergyBalance,
    /// How the increments were solved.
    pub route: String,
    /// What happened on the way.
    pub notes: Vec<String>,
}

impl LoadPathSummary {
    /// The summary of a path's report.
    pub fn of(report: &LoadPathReport) -> Self {
        LoadPathSummary {
            increments: report.steps.len(),
            halvings: report.halvings,
            energy: report.energy,
            route: report.route.clone(),
            notes: report.notes.clone(),
        }
    }
}

/// The energy balance of a path (J/m; see the module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct EnergyBalance {
    /// Work of the loads, the supports and the moving obstacle.
    pub work: f64,
    /// Elastic energy at the end.
    pub stored_energy: f64,
    /// Frictional dissipation in the balance: the trapezoidal `Σ D^n` (module documentation).
    pub dissipation: f64,
    /// The friction law's dissipation, `Σ −rT^n·Δs ≥ 0` summed over the increments (what each
    /// increment's record reports); it differs from `dissipation` by the trapezoidal rule's
    /// error at increments where points start, stop or reverse their slip, and both converge
    /// to the same value as the increments shrink.
    pub law_dissipation: f64,
    /// Energy lost by the discrete normal law (points closing or opening within increments).
    pub normal_contact_loss: f64,
    /// `|W − E − D − N| / max(|W|, E)`.
    pub relative_residual: f64,
}

/// One load key (a name, or `None` for the ramped loads) and its part of the loads.
struct LoadCase {
    key: Option<String>,
    /// Owned rows of the right-hand side (Dirichlet values of this key lifted).
    rhs: Vec<f64>,
    /// Owned rows of the unconstrained load vector.
    load: Vec<f64>,
}

/// The state the next increment starts from.
struct State {
    time: f64,
    u: Vec<f64>,
    force: Vec<f64>,
    /// `B u` in the contact frames.
    relative: Vec<f64>,
    /// The obstacle's displacement.
    obstacle: [f64; 2],
    /// Non-contact external forces `F` (owned rows).
    external: Vec<f64>,
}

/// The key of the loads of a `[[traction]]`, of the body force, of a `[[dirichlet]]` and of
/// the obstacle's motion: their `name` (`None`: ramped).
fn traction_key(t: &crate::scene::TractionSpec) -> Option<&str> {
    t.name.as_deref()
}
fn body_force_key(scene: &crate::scene::Scene) -> Option<&str> {
    scene.body_force_name.as_deref()
}
fn dirichlet_key(d: &crate::scene::DirichletSpec) -> Option<&str> {
    d.name.as_deref()
}
fn motion_of(spec: &crate::scene::ContactSpec) -> Option<([f64; 2], Option<&str>)> {
    spec.motion.map(|d| (d, spec.name.as_deref()))
}

impl<'s> ElasticityProblem<'s> {
    /// Solve the increments of `path` (module documentation), calling `on_step` after each
    /// converged one with the problem holding that increment's displacement and contact
    /// outcome (and what `each` asks for). The path's report is left in
    /// [`ElasticityProblem::load_path`].
    pub fn solve_load_path(
        &mut self,
        path: &LoadPath,
        each: EachIncrement,
        on_step: &mut dyn FnMut(&ElasticityProblem<'s>, &StepRecord) -> Result<()>,
    ) -> Result<()> {
        let mut notes = Vec::new();
        self.refuse_on_load_path()?;
        if let Some(c) = self.contact.as_mut() {
            if c.spec.solver == ContactSolverSpec::FullSpaceNewton {
                c.spec.solver = ContactSolverSpec::Newton;
                notes.push(
                    "the increments run on the condensed route (semi-smooth Newton on W = B K⁻¹ Bᵀ, formed once)"
                        .into(),
                );
            }
        }
        if self.system.is_none() {
            self.assemble()?;
        }
        let (cases, stiffness) = self.load_cases()?;
        let (matrix, rhs) =
            self.system.take().ok_or(Error::CallOrder { call: "solve_load_path()", needs: "assemble()" })?;
        let outcome = self.run_increments(path, &cases, &stiffness, &matrix, &mut notes, each, on_step);
        self.system = Some((matrix, rhs));
        outcome
    }

    /// Refuse what a load path cannot do, before any work.
    fn refuse_on_load_path(&self) -> Result<()> {
        if self.scene.formulation == Formulation::Dual {
            return Err(Error::Formulation {
                message: "a load path is solved in the primal formulation only".into(),
                hint: "remove `formulation = \"dual\"` (or the [evolution] table)".into(),
            });
        }
        if let Some(model) = &self.bodies {
            if let Some(body) = model.bodies.iter().find(|b| b.contact.as_ref().is_some_and(|c| c.motion.is_some())) {
                return Err(Error::Formulation {
                    message: format!(
                        "the rigid obstacle of body `{}` moves (`motion`): on a load path an obstacle moves only in \
                         a scene of one body",
                        body.name
                    ),
                    hint: "hold the obstacle still on the path (remove `motion`), or move the body through its \
                           supports (a named [[body.dirichlet]] with a table)"
                        .into(),
                });
            }
        }
        if let Some(c) = &self.contact {
            if c.spec.solver == ContactSolverSpec::SnesVi {
                return Err(Error::Formulation {
                    message: "contact solver snes_vi solves one static problem on the whole system; a load path needs \
                              the condensed route"
                        .into(),
                    hint: "use solver = \"newton\" (or any condensed solver) with [evolution]".into(),
                });
            }
        }
        Ok(())
    }

    /// One right-hand side per load key, with that key's loads at factor 1, the others at 0,
    /// and the Dirichlet values of that key's conditions (the others' at 0).
    fn load_cases(&mut self) -> Result<(Vec<LoadCase>, assembly::CsrRows)> {
        let mut keys: Vec<Option<String>> = Vec::new();
        let mut add = |k: Option<&str>| {
            let k = k.map(str::to_string);
            if !keys.contains(&k) {
                keys.push(k);
            }
        };
        for t in &self.scene.tractions {
            add(traction_key(t));
        }
        if self.scene.body_force != [0.0, 0.0] {
            add(body_force_key(&self.scene));
        }
        let dirichlet = self.dirichlet_with_nodes()?;
        for (d, _) in &dirichlet {
            if d.ux.is_some_and(|v| v != 0.0) || d.uy.is_some_and(|v| v != 0.0) {
                add(dirichlet_key(d));
            }
        }
        if keys.is_empty() {
            keys.push(None);
        }
        // Which condition gives each fixed dof its value: the last one listing it.
        let mut owner: Vec<Option<(Option<String>, f64)>> = vec![None; self.num_dofs()];
        for (d, nodes) in &dirichlet {
            for &node in nodes {
                for (c, v) in [d.ux, d.uy].into_iter().enumerate() {
                    if let Some(v) = v {
                        owner[2 * node + c] = Some((dirichlet_key(d).map(str::to_string), v));
                    }
                }
            }
        }
        let saved = self.load_factors.take();
        let mut cases = Vec::new();
        let mut stiffness = None;
        for key in keys {
            let mut constraints = Constraints::new(self.num_dofs());
            for (dof, o) in owner.iter().enumerate() {
                if let Some((k, v)) = o {
                    constraints.fix(dof, if *k == key { *v } else { 0.0 });
                }
            }
            // Factor 1 for the loads of this key, 0 for the others.
            let of_key = |k: Option<&str>| if k == key.as_deref() { 1.0 } else { 0.0 };
            let bf = of_key(body_force_key(&self.scene));
            let traction = self.scene.tractions.iter().map(|t| of_key(traction_key(t))).collect();
            let dirichlet = self.scene.dirichlet.iter().map(|d| of_key(dirichlet_key(d))).collect();
            self.load_factors = Some(LoadFactors { traction, body_force: bf, dirichlet });
            let first = stiffness.is_none();
            let (rhs, load, unconstrained) = self.with_loads(|loads| {
                let system = assembly::assemble_cells(
                    &self.mesh,
                    &self.cell_materials,
                    self.scene.element,
                    &constraints,
                    loads,
                    self.rows.clone(),
                );
                // K without constraints (the energies), once.
                let unconstrained = first.then(|| {
                    assembly::assemble_cells(
                        &self.mesh,
                        &self.cell_materials,
                        self.scene.element,
                        &Constraints::new(self.num_dofs()),
                        loads,
                        self.rows.clone(),
                    )
                    .matrix
                });
                (system.rhs, assembly::load_vector(&self.mesh, loads)[self.rows.clone()].to_vec(), unconstrained)
            })?;
            if let Some(k) = unconstrained {
                stiffness = Some(k);
            }
            cases.push(LoadCase { key, rhs, load });
        }
        self.load_factors = saved;
        Ok((cases, stiffness.expect("at least one load case")))
    }

    /// Every Dirichlet condition of the scene with the nodes it fixes (with several bodies,
    /// each on its own body's nodes).
    fn dirichlet_with_nodes(&self) -> Result<Vec<(crate::scene::DirichletSpec, Vec<usize>)>> {
        let nodes = match &self.bodies {
            Some(model) => crate::problem::bodies::dirichlet_nodes(model)?,
            None => self.scene.dirichlet.iter().map(|d| d.nodes(&self.mesh)).collect::<Result<Vec<_>>>()?,
        };
        Ok(self.scene.dirichlet.iter().cloned().zip(nodes).collect())
    }

    #[allow(clippy::too_many_arguments)]
    fn run_increments(
        &mut self,
        path: &LoadPath,
        cases: &[LoadCase],
        stiffness: &assembly::CsrRows,
        matrix: &crate::petsc::Matrix<'s>,
        notes: &mut Vec<String>,
        each: EachIncrement,
        on_step: &mut dyn FnMut(&ElasticityProblem<'s>, &StepRecord) -> Result<()>,
    ) -> Result<()> {
        let session = self.session;
        let n = self.num_dofs();
        let mut ksp = LinearSolver::new(session, session.world(), "")?;
        ksp.set_operator(matrix)?;
        // Without contact: the increments' linear solves (the KSP keeps its factorisation).
        let mut plain = match self.contact {
            Some(_) => None,
            None => {
                let mut k = LinearSolver::new(session, session.world(), "")?;
                k.set_operator(matrix)?;
                Some(k)
            }
        };
        let start = std::time::Instant::now();
        let contact = self.contact.as_ref();
        let m = contact.map_or(0, |c| c.boundary.points());
        let motion = contact.and_then(|c| motion_of(&c.spec)).map(|(d, k)| (d, k.map(str::to_string)));
        let mut operator = match contact {
            Some(c) => Some(c.condense(session, matrix, &mut ksp, &*self.progress)?),
            None => None,
        };
        // Each load case's field K⁻¹ f_k, once: an increment's free displacement is their
        // combination (no solve), its recovery one solve.
        let mut fields = Vec::new();
        if let Some(op) = operator.as_mut() {
            let (mut x, mut e) = (matrix.create_vector()?, matrix.create_vector()?);
            for case in cases {
                e.set_owned(&case.rhs)?;
                op.linear.solve(matrix, &e, &mut x)?;
                fields.push(x.gather_all()?);
            }
        }
        self.timings.add("condense", start.elapsed().as_secs_f64());
        let tangent = contact.map_or([1.0, 0.0], |c| c.boundary.tangent.first().copied().unwrap_or([1.0, 0.0]));
        let monitor = self.monitor_nodes(path)?;
        let obstacle_at = |t: f64| match &motion {
            Some((d, k)) => {
                let f = path.factor(k.as_deref(), t);
                [f * d[0], f * d[1]]
            }
            None => [0.0, 0.0],
        };
        let mut state = State {
            time: path.start,
            u: vec![0.0; n],
            force: vec![0.0; 2 * m],
            relative: vec![0.0; 2 * m],
            obstacle: obstacle_at(path.start),
            external: vec![0.0; self.rows.len()],
        };
        // Interface laws: the committed internal variables and slips (interface_law::staggered).
        let mut interface_state = contact.and_then(|c| c.interface.as_ref()).map(|laws| laws.initial_state());
        let mut energy = EnergyBalance::default();
        let mut steps: Vec<StepRecord> = Vec::new();
        let mut profiles = Vec::new();
        let mut halvings_total = 0;
        let profile_times = path.profiles.clone();
        let mut x = matrix.create_vector()?;
        let mut e = matrix.create_vector()?;
        // Targets still to reach, the next last; each with how often it was halved.
        let mut pending: Vec<(f64, usize)> = path.times.iter().rev().map(|&t| (t, 0)).collect();
        while let Some((t, depth)) = pending.pop() {
            let step_start = std::time::Instant::now();
            let factor = |k: &Option<String>| path.factor(k.as_deref(), t);
            let mut f = vec![0.0; self.rows.len()];
            let mut load = vec![0.0; self.rows.len()];
            for case in cases {
                let phi = factor(&case.key);
                if phi != 0.0 {
                    f.iter_mut().zip(&case.rhs).for_each(|(a, b)| *a += phi * b);
                    load.iter_mut().zip(&case.load).for_each(|(a, b)| *a += phi * b);
                }
            }
            self.load_factors = Some(LoadFactors {
                traction: self.scene.tractions.iter().map(|tr| path.factor(traction_key(tr), t)).collect(),
                body_force: path.factor(body_force_key(&self.scene), t),
                dirichlet: self.scene.dirichlet.iter().map(|d| path.factor(dirichlet_key(d), t)).collect(),
            });
            let d = obstacle_at(t);
            let mut interface_step = None;
            let attempt: Result<(Vec<f64>, Option<ContactOutcome>)> = match (self.contact.as_ref(), operator.as_mut()) {
                (Some(c), Some(op)) => {
                    let b = &c.boundary;
                    let mut shift = vec![0.0; 2 * m];
                    for i in 0..m {
                        let (nn, tt) = (b.normal[i], b.tangent[i]);
                        // With interface laws: the slip so far measured on u' = u + c r.
                        let slip_so_far = match &interface_state {
                            Some(s) => s.shift_slip[i],
                            None => state.relative[2 * i + 1] - dot(state.obstacle, tt),
                        };
                        shift[2 * i] = dot(d, nn);
                        shift[2 * i + 1] = dot(d, tt) + slip_so_far;
                    }
                    let mut free_field = vec![0.0; n];
                    for (case, field) in cases.iter().zip(&fields) {
                        let phi = factor(&case.key);
                        if phi != 0.0 {
                            free_field.iter_mut().zip(field).for_each(|(a, b)| *a += phi * b);
                        }
                    }
                    let increment = Increment {
                        shift: Some(shift),
                        start_displacement: Some(state.u.clone()),
                        start_force: Some(state.force.clone()),
                        free_field: Some(free_field),
                        interface: None,
                    };
                    match &interface_state {
                        Some(committed) => c
                            .solve_staggered(
                                session,
                                op,
                                matrix,
                                &f,
                                &increment,
                                committed,
                                t - state.time,
                                &*self.progress,
                            )
                            .map(|(u, outcome, step)| {
                                interface_step = Some(step);
                                (u, Some(outcome))
                            }),
                        None => c
                            .solve_condensed_load(session, op, matrix, &f, &increment, &*self.progress)
                            .map(|(u, outcome)| (u, Some(outcome))),
                    }
                }
                _ => (|| {
                    let plain = plain.as_mut().expect("a linear solver without contact");
                    e.set_owned(&f)?;
                    plain.solve(matrix, &e, &mut x)?;
                    Ok((x.gather_all()?, None))
                })(),
            };
            let (u, outcome) = match attempt {
                Ok(v) => v,
                Err(err @ Error::SolverDiverged { .. }) => {
                    if depth >= MAX_HALVINGS {
                        return Err(Error::SolverDiverged {
                            solver: "load path".into(),
                            reason: format!(
                                "the increment from t = {} to t = {t} did not converge, even cut in two {MAX_HALVINGS} times: {err}",
                                state.time
                            ),
                            iterations: steps.len(),
                            residual: f64::NAN,
                            tried: format!("{MAX_HALVINGS} halvings of the increment"),
                        });
                    }
                    let middle = 0.5 * (state.time + t);
                    notes.push(format!(
                        "the increment to t = {t} failed ({}); cut in two at t = {middle}",
                        first_line(&err.to_string())
                    ));
                    halvings_total += 1;
                    pending.push((t, depth + 1));
                    pending.push((middle, depth + 1));
                    continue;
                }
                Err(other) => return Err(other),
            };
            if let Some(o) = &outcome {
                self.check_contact_equilibrium(o)?;
            }
            // Energies and the record.
            let rows = self.rows.clone();
            let ku: Vec<f64> = (0..rows.len())
                .map(|r| {
                    let span = stiffness.indptr[r]..stiffness.indptr[r + 1];
                    stiffness.indices[span.clone()].iter().zip(&stiffness.values[span]).map(|(&c, v)| v * u[c]).sum()
                })
                .collect();
            let force = outcome.as_ref().map_or_else(|| vec![0.0; 2 * m], |o| o.force.clone());
            let mut btr = vec![0.0; n];
            let relative = match self.contact.as_ref() {
                Some(c) => {
                    c.boundary.scatter_add(&force, &mut btr);
                    c.boundary.gather(&u)
                }
                None => Vec::new(),
            };
            let mut external = load;
            for (dof, _) in self.constraints.fixed().filter(|(dof, _)| rows.contains(dof)) {
                external[dof - rows.start] = ku[dof - rows.start] - btr[dof];
            }
            let mut own = [0.0, 0.0]; // this rank's work of F and ½ uᵀ K u
            for (r, dof) in rows.clone().enumerate() {
                own[0] += 0.5 * (external[r] + state.external[r]) * (u[dof] - state.u[dof]);
                own[1] += 0.5 * u[dof] * ku[r];
            }
            let [mut work, stored] = <[f64; 2]>::try_from(session.world().sum(&own)?).expect("two sums");
            let (mut dissipation, mut law_dissipation, mut normal_loss) = (0.0, 0.0, 0.0);
            if let Some(c) = self.contact.as_ref() {
                let b = &c.boundary;
                let moved = [d[0] - state.obstacle[0], d[1] - state.obstacle[1]];
                for i in 0..m {
                    let (nn, tt) = (b.normal[i], b.tangent[i]);
                    let (rn, rt) =
                        (0.5 * (force[2 * i] + state.force[2 * i]), 0.5 * (force[2 * i + 1] + state.force[2 * i + 1]));
                    let dgap = (relative[2 * i] - dot(d, nn)) - (state.relative[2 * i] - dot(state.obstacle, nn));
                    let dslip =
                        (relative[2 * i + 1] - dot(d, tt)) - (state.relative[2 * i + 1] - dot(state.obstacle, tt));
                    dissipation -= rt * dslip;
                    law_dissipation -= force[2 * i + 1] * dslip;
                    normal_loss -= rn * dgap;
                    // The moving obstacle's work on the body.
                    work += rn * dot(moved, nn) + rt * dot(moved, tt);
                }
            }
            energy.work += work;
            energy.dissipation += dissipation;
            energy.law_dissipation += law_dissipation;
            energy.normal_contact_loss += normal_loss;
            energy.stored_energy = stored;
            let monitor_displacement = if monitor.is_empty() {
                0.0
            } else {
                monitor.iter().map(|&k| u[2 * k] * tangent[0] + u[2 * k + 1] * tangent[1]).sum::<f64>()
                    / monitor.len() as f64
            };
            let mut record = match &outcome {
                Some(o) => {
                    let r = &o.report;
                    let counts = StateCounts::of(
                        o.status
                            .iter()
                            .copied()
                            .zip(self.contact.as_ref().map(|c| c.frictional_points()).unwrap_or_default()),
                    );
                    StepRecord {
                        step: steps.len() + 1,
                        time: t,
                        halvings: depth,
                        contact_resultant: r.resultant,
                        normal_resultant: r.normal_resultant,
                        tangential_resultant: r.tangential_resultant,
                        open: counts.open,
                        stick: counts.stick,
                        slip: counts.slip,
                        closed: counts.closed,
                        iterations: r.iterations,
                        worst_residual: r.residuals.worst(),
                        dissipation: law_dissipation,
                        total_dissipation: energy.law_dissipation,
                        work: energy.work,
                        stored_energy: stored,
                        monitor_displacement,
                        estimate_percent: None,
                        seconds: step_start.elapsed().as_secs_f64(),
                    }
                }
                None => StepRecord {
                    step: steps.len() + 1,
                    time: t,
                    halvings: depth,
                    contact_resultant: [0.0; 2],
                    normal_resultant: 0.0,
                    tangential_resultant: 0.0,
                    open: 0,
                    stick: 0,
                    slip: 0,
                    closed: 0,
                    iterations: 0,
                    worst_residual: 0.0,
                    dissipation: 0.0,
                    total_dissipation: 0.0,
                    work: energy.work,
                    stored_energy: stored,
                    monitor_displacement,
                    estimate_percent: None,
                    seconds: step_start.elapsed().as_secs_f64(),
                },
            };
            if let (Some(c), Some(o)) = (self.contact.as_ref(), &outcome) {
                if profile_times.iter().any(|&p| (p - t).abs() <= 1e-12 * t.abs().max(1.0)) {
                    profiles.push(profile_of(c, o, &self.mesh, record.step, t, tangent));
                }
            }
            if let (Some(step), Some(c)) = (interface_step, self.contact.as_ref()) {
                // The increment converged: commit the interface's variables.
                if let Some(laws) = c.interface.as_ref() {
                    let positions: Vec<[f64; 2]> = c.boundary.nodes.iter().map(|&k| self.mesh.nodes[k]).collect();
                    self.interface = Some(laws.snapshot(&positions, &step, t));
                }
                interface_state = Some(step.state);
            }
            let shift = ContactShift { obstacle: d, previous_obstacle: state.obstacle, previous_displacement: state.u };
            state = State { time: t, u: u.clone(), force, relative, obstacle: d, external };
            self.displacement = Some(u);
            self.contact_outcome = outcome;
            self.stats = match &operator {
                Some(op) => op.linear.stats(),
                None => plain.as_ref().and_then(|k| k.last_stats()),
            };
            if each != EachIncrement::Solve {
                self.postprocess()?;
            }
            if each == EachIncrement::Estimate {
                self.contact_shift = Some(shift);
                let estimated = self.solve_dual().and_then(|()| self.estimate());
                self.contact_shift = None;
                estimated?;
                record.estimate_percent = self.estimate.as_ref().map(|e| e.estimate.relative_percent);
            }
            self.progress.increment_finished(&record, path.times.len());
            on_step(self, &record)?;
            steps.push(record);
        }
        self.timings.add("increments", steps.iter().map(|r| r.seconds).sum());
        let scale = energy.work.abs().max(energy.stored_energy).max(f64::MIN_POSITIVE);
        energy.relative_residual =
            (energy.work - energy.stored_energy - energy.dissipation - energy.normal_contact_loss).abs() / scale;
        let route = match &self.contact {
            Some(c) => format!(
                "condensed route, solver {} (K factorised and W formed once; each increment: one solve, two per proximal iteration for a body held by the contact alone)",
                c.spec.solver.scene_name()
            ),
            None => "linear: K factorised once, one solve per increment".into(),
        };
        self.load_path =
            Some(LoadPathReport { steps, profiles, halvings: halvings_total, energy, route, notes: notes.clone() });
        Ok(())
    }

    /// The nodes of the monitored part: the path's `monitor`, else the contact points' nodes
    /// (the slave sides between bodies); empty without either.
    fn monitor_nodes(&self, path: &LoadPath) -> Result<Vec<usize>> {
        let part = match (&path.monitor, &self.contact) {
            (Some(p), _) => p.clone(),
            (None, Some(c)) => {
                let mut nodes = c.boundary.nodes.clone();
                nodes.sort_unstable();
                nodes.dedup();
                return Ok(nodes);
            }
            (None, None) => return Ok(Vec::new()),
        };
        // A monitor asked for by name must exist (the error names the parts there are).
        let group = self.mesh.require_group(&part, 1)?;
        Ok(self.mesh.group_nodes(group))
    }
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn first_line(s: &str) -> &str {
    s.lines().next().unwrap_or(s)
}

/// The contact tractions along the contact part, sorted by their position along `tangent`.
fn profile_of(
    c: &crate::contact_routes::condensed_route::ContactSetup,
    o: &ContactOutcome,
    mesh: &crate::mesh::Mesh,
    step: usize,
    time: f64,
    tangent: [f64; 2],
) -> ContactProfile {
    let b = &c.boundary;
    let (pressure, traction) = b.tractions(&o.force);
    let frictional = c.frictional_points();
    let mut order: Vec<usize> = (0..b.points()).collect();
    let along = |i: usize| dot(mesh.nodes[b.nodes[i]], tangent);
    order.sort_by(|&i, &j| along(i).total_cmp(&along(j)));
    ContactProfile {
        step,
        time,
        abscissa: order.iter().map(|&i| along(i)).collect(),
        pressure: order.iter().map(|&i| pressure[i]).collect(),
        traction: order.iter().map(|&i| traction[i]).collect(),
        state: order.iter().map(|&i| ContactState::of(o.status[i], frictional[i])).collect(),
    }
}
