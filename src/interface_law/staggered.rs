//! # The staggered loop: a solve with interface laws
//!
//! One static solve, or one increment of a load path, with the laws of
//! [`crate::interface_law`] at the contact points:
//!
//! ```text
//!   trial := committed (the internal variables at the start of the increment)
//!   repeat
//!     modification_i = law.modification(point_i, friction_i, trial_i, last_i)     every point
//!     solve the modified condensed problem (interface_law::condensed), warm-started
//!       from the last contact force r'; recover u = K⁻¹ (f + Bᵀ r) with the TOTAL force r;
//!       check (r', u') recomputed from (r, B u) and the springs' residual
//!     solution_i from (r, B u − shift)                                            every point
//!     trial_i' = law.update(point_i, committed_i, solution_i, dt)
//!   until trial' = trial, the next modifications equal these and (Tresca and Coulomb points
//!         mixed) the thresholds from r' equal those solved with, all to 1e-10 relative;
//!         at most MAX_STAGGERED times, else Error::SolverDiverged (a load path then halves)
//!   law.residual at every point ≤ the check's acceptance; commit
//! ```
//!
//! A memoryless law whose modification does not depend on the last solution (the thin layer)
//! converges in one iteration. `dt` is the increment's duration (1 for a static run). The
//! internal variables are committed by the caller only when the increment converges (a halved
//! increment restarts from the committed ones).
//!
//! ## Which law at which point
//!
//! One body: the `[contact]`'s `interface` at every point. Several bodies: each point's contact
//! part ([`crate::problem::bodies::ContactParts`]) and that part's `interface` (a pair's or a
//! body's rigid obstacle's); points of parts without one are plain Signorini with their
//! friction ([`PointModification::plain`]).
//!
//! ## Slip on a load path
//!
//! The whole tangential jump at a point is `s = (B u)_T − d·t` (the obstacle's motion removed);
//! the law sees its increment: the shift along `t` is `d·t + s_before + c_T r_T,before`, the slip
//! so far measured on `u' = u + c r` (a cut layer's elastic shear `−c_T r_T` is not slip). The
//! springs' offset along `t` is the whole jump before the increment (`InterfacePoint::slip_before`).
//!
//! ## Routing
//!
//! A contact with an interface law runs on the condensed route: the default solver
//! (`newton_full`) becomes the condensed semi-smooth Newton (`newton`) with a note, as on load
//! paths; `snes_vi` and `tao`, which solve plain Signorini only, are refused, and so are the dual
//! formulation and the estimate ([`super::refuse_dual`]). A law with memory needs a load path
//! (`[evolution]`): a static run refuses it.
use super::condensed::{mixed_friction, unify_friction};
use super::{
    law_of, InterfaceLaw, InterfacePoint, InterfacePointState, InterfaceSnapshot, PointFriction, PointModification,
    PointSolution,
};
use crate::contact::FrictionLaw;
use crate::contact_routes::condensed_route::{
    CondensedOperator, ContactOutcome, ContactSetup, Increment, InterfaceIncrement,
};
use crate::error::{Error, Result};
use crate::fem::material::PlaneModel;
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats, Vector};
use crate::scene::{ContactSolverSpec, InterfaceSpec};

/// Most solve → update iterations of one increment.
pub const MAX_STAGGERED: usize = 200;
/// Relative change under which the staggered iterations stop.
pub const STAGGERED_TOLERANCE: f64 = 1e-10;

/// The interface laws of a contact's points.
#[derive(Debug)]
pub struct InterfaceLaws {
    /// One law per contact part that has one.
    laws: Vec<Box<dyn InterfaceLaw>>,
    /// The contact (part or pair) of each law, for messages.
    law_contacts: Vec<String>,
    /// The law of each point (`None`: plain Signorini).
    law_of_point: Vec<Option<usize>>,
    /// The law's name of each contact part (`"signorini"` without one), in the parts' order.
    part_laws: Vec<String>,
    /// Each point's weight and gap (`slip_before` set per increment).
    points: Vec<InterfacePoint>,
    /// The scene's friction of each point (force units).
    friction: Vec<PointFriction>,
    /// What the routing changed (for the report's notes).
    pub notes: Vec<String>,
}

/// The interface's state between increments.
#[derive(Debug, Clone, PartialEq)]
pub struct InterfaceState {
    /// The committed internal variables of each point.
    pub committed: Vec<Vec<f64>>,
    /// The whole tangential jump at each point (`slip_before` of the next increment).
    pub jump: Vec<f64>,
    /// The slip so far measured on `u' = u + c r` (the load path's tangential shift).
    pub shift_slip: Vec<f64>,
    /// Each point's last solution (`None` before the first solve).
    pub last: Option<Vec<PointSolution>>,
    /// The last contact force `r'` (2m).
    pub last_contact_force: Option<Vec<f64>>,
}

/// A converged solve with interface laws.
#[derive(Debug, Clone)]
pub struct InterfaceStep {
    /// The state to commit.
    pub state: InterfaceState,
    /// Each point's solution.
    pub solutions: Vec<PointSolution>,
    /// Each point's [`InterfaceLaw::residual`].
    pub law_residuals: Vec<f64>,
    /// Staggered iterations (solve → update).
    pub iterations: usize,
}

impl InterfaceLaws {
    /// The laws of `m` points: `laws` with the contact each belongs to (for messages), the law
    /// of each point (`None`: plain Signorini), the law's name of each contact part (for the
    /// snapshot), each point's weight and gap, and its friction (force units).
    pub fn new(
        laws: Vec<(Box<dyn InterfaceLaw>, String)>,
        law_of_point: Vec<Option<usize>>,
        part_laws: Vec<String>,
        points: Vec<InterfacePoint>,
        friction: Vec<PointFriction>,
    ) -> Result<Self> {
        let m = points.len();
        if law_of_point.len() != m || friction.len() != m || law_of_point.iter().flatten().any(|&l| l >= laws.len()) {
            return Err(Error::Usage(format!(
                "interface laws: {m} points, {} point laws and {} frictions (each point's law among the {} laws)",
                law_of_point.len(),
                friction.len(),
                laws.len()
            )));
        }
        let (laws, law_contacts) = laws.into_iter().unzip();
        Ok(InterfaceLaws { laws, law_contacts, law_of_point, part_laws, points, friction, notes: Vec::new() })
    }

    /// Whether some law has internal variables.
    pub fn has_memory(&self) -> bool {
        self.laws.iter().any(|l| l.has_memory())
    }

    /// The state before the path starts.
    pub fn initial_state(&self) -> InterfaceState {
        let m = self.points.len();
        InterfaceState {
            committed: self.law_of_point.iter().map(|l| l.map_or_else(Vec::new, |l| self.laws[l].initial())).collect(),
            jump: vec![0.0; m],
            shift_slip: vec![0.0; m],
            last: None,
            last_contact_force: None,
        }
    }

    fn modifications(
        &self,
        points: &[InterfacePoint],
        trial: &[Vec<f64>],
        last: Option<&[PointSolution]>,
    ) -> Vec<PointModification> {
        (0..points.len())
            .map(|i| match self.law_of_point[i] {
                Some(l) => self.laws[l].modification(&points[i], self.friction[i], &trial[i], last.map(|s| &s[i])),
                None => PointModification::plain(self.friction[i]),
            })
            .collect()
    }

    /// The interface at the end of a converged solve, for the outputs.
    pub fn snapshot(&self, positions: &[[f64; 2]], step: &InterfaceStep, time: f64) -> InterfaceSnapshot {
        let points = (0..self.points.len())
            .map(|i| {
                let s = &step.solutions[i];
                let w = self.points[i].weight;
                let outputs = self.law_of_point[i].map(|l| self.laws[l].outputs(&step.state.committed[i]));
                InterfacePointState {
                    x: positions[i],
                    opening: s.opening,
                    slip: s.slip,
                    traction_normal: s.force[0] / w,
                    traction_tangential: s.force[1] / w,
                    adhesion: outputs.and_then(|o| o.adhesion),
                    damage: outputs.and_then(|o| o.damage),
                    law_residual: step.law_residuals[i],
                }
            })
            .collect();
        InterfaceSnapshot { time, laws: self.part_laws.clone(), points, iterations: step.iterations }
    }
}

/// The friction of each point from the contact's law (force units).
fn point_frictions(law: &FrictionLaw, m: usize) -> Vec<PointFriction> {
    (0..m)
        .map(|i| match law {
            FrictionLaw::None => PointFriction::None,
            FrictionLaw::Tresca { threshold } => PointFriction::Tresca(threshold[i]),
            FrictionLaw::Coulomb { mu } => PointFriction::Coulomb(mu[i]),
        })
        .collect()
}

/// `|a − b| ≤ tol · scale` entry by entry, `scale` the largest magnitude of both.
fn close(a: &[f64], b: &[f64]) -> bool {
    if a.len() != b.len() {
        return false;
    }
    let scale = a.iter().chain(b).fold(0.0f64, |s, x| s.max(x.abs()));
    a.iter().zip(b).all(|(x, y)| (x - y).abs() <= STAGGERED_TOLERANCE * scale)
}

fn friction_value(f: PointFriction) -> (u8, f64) {
    match f {
        PointFriction::None => (0, 0.0),
        PointFriction::Tresca(s) => (1, s),
        PointFriction::Coulomb(mu) => (2, mu),
    }
}

/// Two lists of modifications equal to [`STAGGERED_TOLERANCE`] (each quantity relative to its
/// largest magnitude over the points).
fn same_modifications(a: &[PointModification], b: &[PointModification]) -> bool {
    let field =
        |f: fn(&PointModification) -> [f64; 2], m: &[PointModification]| -> Vec<f64> { m.iter().flat_map(f).collect() };
    let fields: [fn(&PointModification) -> [f64; 2]; 5] = [
        |m| m.compliance,
        |m| m.stiffness,
        |m| m.spring_offset,
        |m| m.force_offset,
        |m| [friction_value(m.friction).1, 0.0],
    ];
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.contact == y.contact && friction_value(x.friction).0 == friction_value(y.friction).0)
        && fields.iter().all(|f| close(&field(*f, a), &field(*f, b)))
}

/// The thresholds of the unified friction law (empty unless Tresca).
fn thresholds(law: &FrictionLaw) -> Vec<f64> {
    match law {
        FrictionLaw::Tresca { threshold } => threshold.clone(),
        _ => Vec::new(),
    }
}

impl ContactSetup {
    /// The interface laws of the scene's contact (its `[contact]`, or each contact part's), and
    /// the routing they need (module documentation). Nothing without an interface table.
    pub(crate) fn attach_interface(&mut self, plane: PlaneModel) -> Result<()> {
        let m = self.boundary.points();
        let (specs, part_of): (Vec<(String, Option<InterfaceSpec>)>, Vec<usize>) = match &self.parts {
            None => (vec![(self.spec.part.clone(), self.spec.interface.clone())], vec![0; m]),
            Some(p) => (p.parts.iter().map(|q| (q.name.clone(), q.interface.clone())).collect(), p.part_of.clone()),
        };
        let Some((contact, first)) = specs.iter().find_map(|(n, s)| s.as_ref().map(|s| (n.clone(), s.clone()))) else {
            return Ok(());
        };
        let law = super::law_name(&first.law);
        let where_ = format!("{}:{}", first.at.file.display(), first.at.line);
        let mut notes = Vec::new();
        match self.spec.solver {
            ContactSolverSpec::SnesVi | ContactSolverSpec::Tao => {
                return Err(Error::Formulation {
                    message: format!(
                        "the contact on `{contact}` has the interface law `{law}` ({where_}), which runs on the \
                         condensed route, and solver \"{}\" solves plain Signorini contact only",
                        self.spec.solver.scene_name()
                    ),
                    hint: "leave out `solver` (the condensed semi-smooth Newton is then used) or choose a condensed \
                           solver (\"newton\", \"relaxation\", ...)"
                        .into(),
                });
            }
            ContactSolverSpec::FullSpaceNewton => {
                self.spec.solver = ContactSolverSpec::Newton;
                notes.push(format!(
                    "interface law `{law}` on `{contact}`: the contact runs on the condensed route (semi-smooth Newton \
                     on the modified W = B K⁻¹ Bᵀ)"
                ));
            }
            _ => {}
        }
        let mut laws: Vec<Box<dyn InterfaceLaw>> = Vec::new();
        let mut law_contacts = Vec::new();
        let mut law_of_part = Vec::new();
        let mut part_laws = Vec::new();
        for (name, spec) in &specs {
            match spec {
                Some(s) => {
                    law_of_part.push(Some(laws.len()));
                    laws.push(law_of(&s.law, plane));
                    law_contacts.push(name.clone());
                    part_laws.push(super::law_name(&s.law).to_string());
                }
                None => {
                    law_of_part.push(None);
                    part_laws.push("signorini".to_string());
                }
            }
        }
        let b = &self.boundary;
        self.interface = Some(InterfaceLaws {
            laws,
            law_contacts,
            law_of_point: part_of.iter().map(|&p| law_of_part[p]).collect(),
            part_laws,
            points: (0..m)
                .map(|i| InterfacePoint {
                    weight: b.weight[i],
                    gap: b.gap[i],
                    slip_before: 0.0,
                    traction_scale: 0.0,
                    displacement_scale: 0.0,
                })
                .collect(),
            friction: point_frictions(&self.friction_law(), m),
            notes,
        });
        Ok(())
    }

    /// A static solve with interface laws: condense, the staggered loop (dt = 1). A law with
    /// memory is refused (it needs a load path).
    pub(crate) fn solve_with_interface<'s>(
        &self,
        session: &'s Session,
        matrix: &Matrix<'s>,
        rhs: &Vector<'s>,
        ksp: &mut LinearSolver<'s>,
        progress: &dyn crate::problem::Progress,
    ) -> Result<(Vec<f64>, ContactOutcome, Option<SolveStats>, InterfaceStep)> {
        let laws = self
            .interface
            .as_ref()
            .ok_or(Error::CallOrder { call: "solve_with_interface()", needs: "a contact with an interface law" })?;
        self.refuse_memory_in_static_run()?;
        let mut operator = self.condense(session, matrix, ksp, progress)?;
        let f = rhs.owned_values()?;
        let state = laws.initial_state();
        let (u, outcome, step) =
            self.solve_staggered(session, &mut operator, matrix, &f, &Increment::default(), &state, 1.0, progress)?;
        Ok((u, outcome, operator.linear.stats(), step))
    }

    /// A law with memory in a static run: refused (`[evolution]` needed).
    pub(crate) fn refuse_memory_in_static_run(&self) -> Result<()> {
        let Some(laws) = &self.interface else { return Ok(()) };
        match laws.laws.iter().position(|l| l.has_memory()) {
            None => Ok(()),
            Some(k) => Err(Error::Formulation {
                message: format!(
                    "the interface law `{}` of the contact on `{}` has internal variables that evolve with the load \
                     (it has memory): a static run has no load history to integrate them on",
                    laws.laws[k].name(),
                    laws.law_contacts[k]
                ),
                hint: "add an [evolution] table (a load path from rest to the loads) to the scene".into(),
            }),
        }
    }

    /// The staggered loop of one solve (module documentation) from the committed `state`, the
    /// increment `base` (shift, start, free field) and its duration `dt`. The state is not
    /// changed: the caller commits [`InterfaceStep::state`] when the increment is accepted.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve_staggered<'s>(
        &self,
        session: &'s Session,
        operator: &mut CondensedOperator<'_, 's>,
        matrix: &Matrix<'s>,
        f: &[f64],
        base: &Increment,
        state: &InterfaceState,
        dt: f64,
        progress: &dyn crate::problem::Progress,
    ) -> Result<(Vec<f64>, ContactOutcome, InterfaceStep)> {
        let laws = self
            .interface
            .as_ref()
            .ok_or(Error::CallOrder { call: "solve_staggered()", needs: "a contact with an interface law" })?;
        let b = &self.boundary;
        let m = b.points();
        let shift = base.shift.clone().unwrap_or_else(|| vec![0.0; 2 * m]);
        let tolerance = crate::contact_routes::condensation::solver_settings(&self.spec).tolerance;
        let mut solver_iterations = 0;
        let ((u, mut outcome), step) =
            // The law's residual settles at the staggered loop's own tolerance: never ask less of it.
            staggered(laws, state, dt, self.acceptance(tolerance).max(100.0 * STAGGERED_TOLERANCE), |modifications, last| {
                let increment = Increment {
                    interface: Some(InterfaceIncrement {
                        modifications: modifications.to_vec(),
                        last_contact_force: last.map(<[f64]>::to_vec),
                    }),
                    ..base.clone()
                };
                let (u, outcome) = self.solve_condensed_load(session, operator, matrix, f, &increment, progress)?;
                solver_iterations += outcome.report.iterations;
                let mut uc = b.gather(&u);
                for (v, s) in uc.iter_mut().zip(&shift) {
                    *v -= s;
                }
                Ok((outcome.force.clone(), uc, (u, outcome)))
            })?;
        outcome.report.iterations = solver_iterations;
        outcome.report.notes.extend(laws.notes.iter().cloned());
        let worst = step.law_residuals.iter().copied().fold(0.0, f64::max);
        outcome.report.notes.push(format!(
            "interface laws ({}): {} staggered iteration(s) (solve → update of the internal variables); largest law \
             residual {worst:.2e}",
            laws.part_laws.join(", "),
            step.iterations
        ));
        Ok((u, outcome, step))
    }

    /// The modified problem's solve ([`super::condensed::ModifiedProblem`]): the scene's condensed
    /// solver on the points with contact (none: `r' = 0`), the answer as the total force and
    /// its displacement; also `r'` (all points).
    pub(crate) fn solve_modified(
        &self,
        modified: &super::condensed::ModifiedProblem,
        settings: &crate::contact::SolverSettings,
        progress: &dyn crate::problem::Progress,
    ) -> Result<(crate::contact::ContactSolution, Vec<f64>)> {
        match modified.problem() {
            Some(problem) => {
                let mut settings = settings.clone();
                settings.initial_force = settings.initial_force.as_deref().map(|r| modified.restrict(r));
                let solver =
                    crate::contact_routes::condensation::condensed_solver(&self.spec.solver).ok_or_else(|| {
                        Error::Usage(format!(
                            "contact solver {:?} runs on the full system, not on the condensed problem",
                            self.spec.solver
                        ))
                    })?;
                progress.note(&format!(
                    "contact: {} points with a unilateral contact (of {}), interface laws, solver {}",
                    problem.points(),
                    self.boundary.points(),
                    solver.name()
                ));
                let solution = crate::contact::solve(problem, &solver, &settings)?;
                for (k, h) in solution.history.iter().enumerate() {
                    progress.iteration(crate::problem::Phase::Solve, k + 1, h.residual);
                }
                let contact_force = modified.expand(&solution.force);
                let answer = modified.answer(&contact_force);
                Ok((
                    crate::contact::ContactSolution {
                        force: answer.force,
                        displacement: answer.displacement,
                        ..solution
                    },
                    contact_force,
                ))
            }
            None => {
                let m = self.boundary.points();
                let contact_force = vec![0.0; 2 * m];
                let answer = modified.answer(&contact_force);
                let residuals = crate::contact::ContactResiduals {
                    max_penetration: 0.0,
                    max_wrong_sign_pressure: 0.0,
                    max_cone_violation: 0.0,
                    normal_complementarity: 0.0,
                    tangential_complementarity: 0.0,
                    scale: crate::contact::ResidualScale { force: 1.0, displacement: 1.0 },
                    worst_point: 0,
                };
                Ok((
                    crate::contact::ContactSolution {
                        force: answer.force,
                        displacement: answer.displacement,
                        iterations: 0,
                        history: Vec::new(),
                        status: vec![crate::contact::PointStatus::Stick; m],
                        residuals,
                        solver: "none: no point has a unilateral contact (the interface's springs only)".into(),
                        notes: Vec::new(),
                    },
                    contact_force,
                ))
            }
        }
    }
}

/// The staggered loop (module documentation) around `solve`, which solves the modified problem
/// of the given modifications (`last`: the last contact force `r'`, for the warm start and the
/// thresholds of mixed Tresca/Coulomb points) and returns the total force `r`, the relative
/// displacement the law sees `B u − shift` (2m each, recomputed from the field) and what the
/// caller keeps of the last solve. `accepted`: the largest law residual accepted.
pub fn staggered<T>(
    laws: &InterfaceLaws,
    state: &InterfaceState,
    dt: f64,
    accepted: f64,
    mut solve: impl FnMut(&[PointModification], Option<&[f64]>) -> Result<(Vec<f64>, Vec<f64>, T)>,
) -> Result<(T, InterfaceStep)> {
    let m = laws.points.len();
    let points: Vec<InterfacePoint> =
        (0..m).map(|i| InterfacePoint { slip_before: state.jump[i], ..laws.points[i] }).collect();
    let mut trial = state.committed.clone();
    let mut last_contact_force = state.last_contact_force.clone();
    let mut modifications = laws.modifications(&points, &trial, state.last.as_deref());
    let mut modifications_settled = false;
    for iteration in 1..=MAX_STAGGERED {
        let frictions: Vec<PointFriction> = modifications.iter().map(|md| md.friction).collect();
        let mixed = mixed_friction(&frictions);
        let used = thresholds(&unify_friction(&frictions, last_contact_force.as_deref()));
        let (force, uc, kept) = solve(&modifications, last_contact_force.as_deref())?;
        let mut contact_force = vec![0.0; 2 * m];
        let solutions: Vec<PointSolution> = (0..m)
            .map(|i| {
                let md = &modifications[i];
                let r = [force[2 * i], force[2 * i + 1]];
                let gap = [points[i].gap, 0.0];
                for k in 0..2 {
                    contact_force[2 * i + k] =
                        r[k] - md.force_offset[k] + md.stiffness[k] * (uc[2 * i + k] - gap[k] + md.spring_offset[k]);
                }
                let slip = uc[2 * i + 1] + state.shift_slip[i];
                PointSolution {
                    opening: points[i].gap - uc[2 * i],
                    slip,
                    slip_increment: slip - state.jump[i],
                    force: r,
                    contact_force: [contact_force[2 * i], contact_force[2 * i + 1]],
                }
            })
            .collect();
        let updated: Vec<Vec<f64>> = (0..m)
            .map(|i| match laws.law_of_point[i] {
                Some(l) => laws.laws[l].update(&points[i], &state.committed[i], &solutions[i], dt),
                None => state.committed[i].clone(),
            })
            .collect();
        let next = laws.modifications(&points, &updated, Some(&solutions));
        let next_frictions: Vec<PointFriction> = next.iter().map(|md| md.friction).collect();
        let thresholds_now = thresholds(&unify_friction(&next_frictions, Some(&contact_force)));
        // The variables relative to their largest magnitude over the points.
        let same_variables = trial.iter().zip(&updated).all(|(a, b)| a.len() == b.len()) && {
            let all_old: Vec<f64> = trial.iter().flatten().copied().collect();
            let all_new: Vec<f64> = updated.iter().flatten().copied().collect();
            close(&all_old, &all_new)
        };
        // Variables that only move at round-off (an opening of 1e-19 m feeding a joint's largest
        // opening) never settle relative to themselves: once the modifications they give have not
        // changed over two iterations, the solve no longer depends on them.
        let same_now = same_modifications(&modifications, &next) && (!mixed || close(&used, &thresholds_now));
        let converged = same_now && (same_variables || modifications_settled);
        modifications_settled = same_now;
        if !converged {
            trial = updated;
            modifications = next;
            last_contact_force = Some(contact_force);
            continue;
        }
        // The interface's largest traction: the stress scale of the residual at points that
        // carry little.
        let traction_scale = (0..m)
            .map(|i| solutions[i].force[0].hypot(solutions[i].force[1]) / points[i].weight)
            .fold(0.0f64, f64::max);
        let displacement_scale = (0..m)
            .map(|i| (solutions[i].opening - points[i].gap).abs().max(solutions[i].slip.abs()))
            .fold(0.0f64, f64::max);
        let law_residuals: Vec<f64> = (0..m)
            .map(|i| match laws.law_of_point[i] {
                Some(l) => {
                    let point = InterfacePoint { traction_scale, displacement_scale, ..points[i] };
                    laws.laws[l].residual(&point, &state.committed[i], &updated[i], &solutions[i], dt)
                }
                None => 0.0,
            })
            .collect();
        let (worst_point, worst) = law_residuals.iter().copied().enumerate().fold((0, 0.0f64), |a, (i, r)| {
            let r = if r.is_nan() { f64::INFINITY } else { r };
            if r > a.1 {
                (i, r)
            } else {
                a
            }
        });
        if worst > accepted {
            let l = laws.law_of_point[worst_point].unwrap_or(0);
            return Err(Error::SolverDiverged {
                solver: format!("interface law `{}` on `{}`", laws.laws[l].name(), laws.law_contacts[l]),
                reason: format!(
                    "the law's own residual at contact point {worst_point} is {worst:.3e} after the staggered \
                     iterations converged (accepted: {accepted:.1e})"
                ),
                iterations: iteration,
                residual: worst,
                tried: format!("{iteration} staggered iterations (solve → update)"),
            });
        }
        let shift_slip =
            (0..m).map(|i| solutions[i].slip + modifications[i].compliance[1] * solutions[i].force[1]).collect();
        let state = InterfaceState {
            committed: updated,
            jump: solutions.iter().map(|s| s.slip).collect(),
            shift_slip,
            last: Some(solutions.clone()),
            last_contact_force: Some(contact_force),
        };
        return Ok((kept, InterfaceStep { state, solutions, law_residuals, iterations: iteration }));
    }
    Err(Error::SolverDiverged {
        solver: "interface laws (staggered solve → update)".into(),
        reason: format!(
            "the internal variables and the modified contact problem still change after {MAX_STAGGERED} iterations \
             (relative tolerance {STAGGERED_TOLERANCE:e})"
        ),
        iterations: MAX_STAGGERED,
        residual: f64::NAN,
        tried: format!("{MAX_STAGGERED} staggered iterations"),
    })
}
