//! The dual formulation with contact inside the driver:
//!
//! ```text
//! ElasticityProblem::solve_dual        with a [contact] section:
//!     contact_side                     the contact part and the obstacle's frame and gap
//!     dual::contact::condense          assemble (z, r), MUMPS with the Schur complement on r
//!                                      (or the talk's other condensations and storages of W:
//!                                      -dual_contact_condensation, -dual_contact_storage;
//!                                      under MPI the columns on the distributed A_zz, the
//!                                      condensed problem solved by every rank)
//!     CondensedDual::solve             the scene's condensed solver (+ equilibrium of r)
//!     verify_dual_contact              independent check: forces recomputed from σ_h,
//!                                      displacements from the assembled matrix
//!                ::estimate            + the Γc terms of the error in the constitutive relation
//! ```
//!
//! The independent check does not trust the solver's bookkeeping: the contact forces are
//! recomputed from the stress field itself (`σ_h n` at both ends of every contact edge, by
//! linear extrapolation of two interior samples of the edge's piece, exact for the linear
//! HCT traction), the contact displacements from the assembled sparse matrix (`(A x − b)_r`,
//! not `W`), and the equilibrium conditions from the forces. Sign, friction cone and
//! complementarity are then those of [`crate::contact::ContactResiduals`].
use super::ElasticityProblem;
use crate::contact::obstacle::Obstacle;
use crate::contact::{FrictionLaw, PointStatus};
use crate::contact_routes::condensed_route::{condensed_solver, tao_box_qp};
use crate::dual::condensation::{Condensation, Storage, STORAGE_OPTION};
use crate::dual::contact::{condense, contact_points, DualContactPoint};
use crate::dual::{DualData, DualSystem};
use crate::error::{Error, Result};
use crate::estimate::{ContactLawTerm, ContactSample, ContactTerms};
use crate::fem::quadrature;
use crate::petsc::SolveStats;
use crate::report::contact::ContactReport;
use crate::report::contact_zones::{ClosedZone, PeakPressure};
use crate::scene::{ContactSolverSpec, FrictionSpec};

/// The dual contact solution (forces per edge end, in the contact frames).
pub struct DualContactOutcome {
    pub points: Vec<DualContactPoint>,
    pub force: Vec<f64>,
    pub displacement: Vec<f64>,
    pub status: Vec<PointStatus>,
    pub report: ContactReport,
}

/// The contact part of a scene for the dual: its group and the obstacle.
pub(super) struct DualContactSide {
    pub group: usize,
    pub obstacle: Obstacle,
    pub extra_gap: f64,
}

impl DualContactSide {
    /// The body's contact direction `n = −ν` (ν the obstacle normal towards the body).
    pub fn normal(&self, x: [f64; 2]) -> [f64; 2] {
        let p = self.obstacle.project(x);
        [-p.normal[0], -p.normal[1]]
    }
    pub fn gap(&self, x: [f64; 2]) -> f64 {
        self.obstacle.project(x).signed_distance + self.extra_gap
    }
}

impl ElasticityProblem<'_> {
    pub(super) fn dual_contact_side(&self) -> Result<Option<DualContactSide>> {
        let Some(spec) = &self.scene.contact else { return Ok(None) };
        if spec.solver == ContactSolverSpec::SnesVi {
            return Err(Error::Formulation {
                message: "dual formulation: solver = \"snes_vi\" works on the primal displacements only".into(),
                hint: "use a condensed solver (newton, relaxation, dpana, uzawa, tresca_fixed_point, tao) or the \
                       default"
                    .into(),
            });
        }
        Ok(Some(DualContactSide {
            group: self.mesh.require_group(&spec.part, 1)?,
            obstacle: crate::contact_routes::condensed_route::obstacle_of(&spec.obstacle)?,
            extra_gap: spec.gap,
        }))
    }

    /// Solve the dual problem with contact: returns φ and the solver statistics.
    pub(super) fn solve_dual_contact(
        &self,
        system: &DualSystem,
        side: &DualContactSide,
        prefix: &str,
    ) -> Result<(Vec<f64>, SolveStats, DualContactOutcome)> {
        let spec = self.scene.contact.as_ref().expect("contact side without [contact]");
        let points = contact_points(system, &self.mesh, &|x| side.gap(x));
        let friction = match spec.friction {
            FrictionSpec::None => FrictionLaw::None,
            FrictionSpec::Coulomb { mu } => FrictionLaw::Coulomb { mu: vec![mu; points.len()] },
            FrictionSpec::Tresca { threshold } => {
                FrictionLaw::Tresca { threshold: points.iter().map(|p| threshold * p.weight).collect() }
            }
        };
        let storage = Storage::from_options(self.session)?;
        if storage == Storage::Implicit {
            implicit_storage_accepts(&spec.solver)?;
        }
        let condensation = Condensation::from_options(self.session, prefix, storage)?;
        let progress = self.progress();
        let mut note_columns = |done: usize, total: usize| {
            progress.note(&format!("condensing: {done} / {total} flexibility columns"));
        };
        let mut condensed = condense(
            self.session,
            system,
            &self.mesh,
            &points,
            friction,
            condensation,
            storage,
            prefix,
            &mut note_columns,
        )?;
        // Within a load path: the law acts on the increment (`ContactShift`), each point's
        // shift weighted like its gap, (2 v_end + v_other)/3, in the end's frame.
        let shift = self.contact_shift.as_ref().map(|c| {
            let at = |k: usize| {
                let p = &points[k];
                c.at(c.previous_at_node(p.node), p.tangent)
            };
            let mut values = vec![0.0; 2 * points.len()];
            for (k, p) in points.iter().enumerate() {
                // The other end of the edge is the neighbouring point (ends are stored in pairs).
                let other = if p.end == 0 { k + 1 } else { k - 1 };
                let (v, w) = (at(k), at(other));
                let v = [(2.0 * v[0] + w[0]) / 3.0, (2.0 * v[1] + w[1]) / 3.0];
                values[2 * k] = v[0] * p.normal[0] + v[1] * p.normal[1];
                values[2 * k + 1] = v[0] * p.tangent[0] + v[1] * p.tangent[1];
            }
            values
        });
        if let Some(shift) = &shift {
            condensed.problem = condensed.problem.shifted(shift)?;
        }
        let settings = crate::contact_routes::condensation::solver_settings(spec);
        let start = std::time::Instant::now();
        let tao = |p: &crate::contact::CondensedProblem| tao_box_qp(self.session, p);
        let answer = match condensed_solver(&spec.solver) {
            Some(solver) => condensed.solve(system, &solver, &settings, None)?,
            None => condensed.solve(system, &crate::contact::ContactSolver::SemismoothNewton, &settings, Some(&tao))?,
        };
        let contact_seconds = start.elapsed().as_secs_f64();
        // Independent check.
        let field = system.field(&self.mesh, &answer.phi);
        let force_check = forces_from_field(system, &field, &points);
        let scale = answer.solution.force.iter().chain(&force_check).fold(0.0f64, |m, v| m.max(v.abs()));
        let force_mismatch =
            answer.solution.force.iter().zip(&force_check).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
                / scale.max(f64::MIN_POSITIVE);
        let law_displacement: Vec<f64> = match &shift {
            Some(shift) => answer.displacement_check.iter().zip(shift).map(|(u, s)| u - s).collect(),
            None => answer.displacement_check.clone(),
        };
        let residuals = condensed.problem.residuals_at(&force_check, &law_displacement)?;
        let equilibrium = condensed.equilibrium.relative_residual(&force_check);
        // The displacements are recomputed as a residual of the assembled HCT system, which
        // carries its round-off (measured up to 1e-7 of the displacement scale on the 32 × 32
        // square block): a margin of 1000 over the solver's tolerance, never more than the
        // scene asked for.
        let accepted = (1e3 * settings.tolerance.max(1e-10)).min(spec.tolerance.unwrap_or(f64::INFINITY));
        if force_mismatch > 1e-8 || equilibrium > 1e-8 || !residuals.is_acceptable(accepted) {
            return Err(Error::SolverDiverged {
                solver: format!("dual formulation: {}", answer.solution.solver),
                reason: format!(
                    "its answer fails the independent check: forces recomputed from the stress field differ by \
                     {force_mismatch:.2e} (relative), equilibrium of the contact forces {equilibrium:.2e}, {residuals}"
                ),
                iterations: answer.solution.iterations,
                residual: residuals.worst().max(force_mismatch).max(equilibrium),
                tried: answer.solution.notes.join("; "),
            });
        }
        let status = condensed.problem.status_at(&force_check, &law_displacement)?;
        let mut notes = answer.solution.notes.clone();
        if let (Condensation::Schur, Some(reason)) = (condensation, &system.local_fallback) {
            notes.push(local_fallback_note(reason));
        }
        notes.push(format!(
            "forces recomputed from the stress field agree to {force_mismatch:.1e}; equilibrium of the contact forces \
             {equilibrium:.1e}"
        ));
        let report = self.dual_contact_report(&points, &force_check, &status, &residuals, &answer.solution, notes);
        let stats = condensed.linear_stats(contact_seconds, answer.outer_iterations);
        let outcome =
            DualContactOutcome { points, force: force_check, displacement: answer.displacement_check, status, report };
        Ok((answer.phi, stats, outcome))
    }

    fn dual_contact_report(
        &self,
        points: &[DualContactPoint],
        force: &[f64],
        status: &[PointStatus],
        residuals: &crate::contact::ContactResiduals,
        solution: &crate::contact::ContactSolution,
        notes: Vec<String>,
    ) -> ContactReport {
        let spec = self.scene.contact.as_ref().expect("report without [contact]");
        let mut resultant = [0.0f64; 2];
        let (mut normal_resultant, mut tangential_resultant) = (0.0, 0.0);
        for (i, p) in points.iter().enumerate() {
            let (rn, rt) = (force[2 * i], force[2 * i + 1]);
            for c in 0..2 {
                resultant[c] += rn * p.normal[c] + rt * p.tangent[c];
            }
            normal_resultant += rn;
            tangential_resultant += rt;
        }
        let frictional = spec.friction != FrictionSpec::None;
        let counts = crate::report::contact::StateCounts::of(status.iter().map(|&s| (s, frictional)));
        let (peak_pressure, zones) = peak_and_zones(points, force, status);
        ContactReport {
            part: spec.part.clone(),
            friction: spec.friction.into(),
            solver: solution.solver.clone(),
            route: "dual".into(),
            route_reason: "the dual formulation: the Airy stress problem condensed onto the contact forces".into(),
            iterations: solution.iterations,
            status_changes: solution.history.iter().map(|h| h.status_changes).collect(),
            residual_history: solution.history.iter().map(|h| h.residual).collect(),
            notes,
            points: points.len(),
            open: counts.open,
            closed: counts.closed,
            stick: counts.stick,
            slip: counts.slip,
            resultant,
            normal_resultant,
            tangential_resultant,
            peak_pressure,
            zones,
            residuals: residuals.into(),
            stabilisation_force: [0.0; 2],
            stabilisation_iterations: 0,
            stabilisation_step_iterations: Vec::new(),
            linear_solves: 2,
        }
    }

    /// The Γc terms of the estimate: samples along every contact edge of the dual (the primal
    /// displacement, the dual traction, the obstacle's direction and gap at each sample).
    pub(super) fn dual_contact_terms(
        &self,
        u: &[f64],
        system: &DualSystem,
        phi: &[f64],
    ) -> Result<Option<(ContactTerms, bool)>> {
        let (Some(side), Some(spec)) = (self.dual_contact_side()?, &self.scene.contact) else { return Ok(None) };
        let law = match spec.friction {
            FrictionSpec::None => ContactLawTerm::Frictionless,
            FrictionSpec::Tresca { threshold } => ContactLawTerm::Tresca { threshold },
            FrictionSpec::Coulomb { mu } => ContactLawTerm::Coulomb { mu },
        };
        let field = system.field(&self.mesh, phi);
        let cells = edge_cells(system);
        let rule = quadrature::gauss_legendre(6);
        let mut terms = ContactTerms::new(self.mesh.num_cells());
        for e in system.edges.iter().filter(|e| e.contact.is_some()) {
            let (pa, pb) = (self.mesh.nodes[e.a], self.mesh.nodes[e.b]);
            let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            let outward = [(pb[1] - pa[1]) / len, -(pb[0] - pa[0]) / len];
            let cell = cells[e.edge];
            let samples: Vec<ContactSample> = rule
                .points
                .iter()
                .zip(&rule.weights)
                .map(|(&s, &w)| {
                    let x = [pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])];
                    let sigma = field.stress_at(cell, x);
                    ContactSample {
                        weight: w * len,
                        traction: [
                            sigma[0] * outward[0] + sigma[2] * outward[1],
                            sigma[2] * outward[0] + sigma[1] * outward[1],
                        ],
                        displacement: {
                            let u_x =
                                crate::estimate::constitutive_relation::displacement_at_point(&self.mesh, u, cell, x);
                            // Within a load path, the increment's (`ContactShift`).
                            match &self.contact_shift {
                                Some(c) => {
                                    let n = side.normal(x);
                                    let previous = crate::estimate::constitutive_relation::displacement_at_point(
                                        &self.mesh,
                                        &c.previous_displacement,
                                        cell,
                                        x,
                                    );
                                    let v = c.at(previous, [-n[1], n[0]]);
                                    [u_x[0] - v[0], u_x[1] - v[1]]
                                }
                                None => u_x,
                            }
                        },
                        normal: side.normal(x),
                        gap: side.gap(x),
                    }
                })
                .collect();
            terms.add_edge(cell, samples, law);
        }
        // Round-off of the two solves (each to 1e-9 of its own scales): 1e-6 of the largest term.
        let admissible = terms.all_nonnegative(1e-6);
        Ok(Some((terms, admissible)))
    }
}

/// The note of a Schur condensation that could not take the local parametrisation of the
/// contact part (`reason`: [`DualSystem::local_fallback`]).
fn local_fallback_note(reason: &str) -> String {
    format!(
        "local parametrisation of the contact part not used ({}): the contact forces are unknowns instead, \
         a dense boundary block (slower assembly and factorisation); the answer is unaffected",
        reason.strip_prefix("dual formulation: ").unwrap_or(reason)
    )
}

/// With the implicit storage of `W` only the solvers that need products work: Uzawa (Uzawa on
/// the full dual system), the semi-smooth Newton method (Krylov solves on products) and the
/// fixed point on Tresca thresholds around it; the others need the entries of `W`.
fn implicit_storage_accepts(solver: &ContactSolverSpec) -> Result<()> {
    match solver {
        ContactSolverSpec::Relaxation { .. } | ContactSolverSpec::DPana | ContactSolverSpec::Tao => {
            Err(Error::Usage(format!(
                "{STORAGE_OPTION} implicit gives the flexibility W by products only, and solver = \"{}\" needs its \
                 entries: with implicit storage use solver = \"uzawa\" (Uzawa on the full dual system), \"newton\" \
                 (semi-smooth Newton, Krylov solves on products) or \"tresca_fixed_point\"; or {STORAGE_OPTION} dense",
                solver.scene_name()
            )))
        }
        _ => Ok(()),
    }
}

/// The cell of every HCT edge on the boundary (the only cell that has it).
fn edge_cells(system: &DualSystem) -> Vec<usize> {
    let mut cells = vec![usize::MAX; system.dofs.edges.len()];
    for (c, edges) in system.dofs.cell_edges.iter().enumerate() {
        for &e in edges {
            cells[e] = c;
        }
    }
    cells
}

/// The contact forces carried by the stress field: `σ_h n` at both ends of each contact edge
/// (linear extrapolation of the samples at ¼ and ¾ of the edge, exact for the linear HCT
/// traction), in the point's frame, times `w`.
fn forces_from_field(system: &DualSystem, field: &crate::dual::DualField, points: &[DualContactPoint]) -> Vec<f64> {
    let cells = edge_cells(system);
    let mesh = field.mesh;
    let mut out = vec![0.0; 2 * points.len()];
    for (i, p) in points.iter().enumerate() {
        let e = &system.edges[p.edge];
        let (pa, pb) = (mesh.nodes[e.a], mesh.nodes[e.b]);
        let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
        let outward = [(pb[1] - pa[1]) / len, -(pb[0] - pa[0]) / len];
        let at = |s: f64| {
            let x = [pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])];
            let sigma = field.stress_at(cells[e.edge], x);
            [sigma[0] * outward[0] + sigma[2] * outward[1], sigma[2] * outward[0] + sigma[1] * outward[1]]
        };
        let (near, far) = if p.end == 0 { (at(0.25), at(0.75)) } else { (at(0.75), at(0.25)) };
        let t = [1.5 * near[0] - 0.5 * far[0], 1.5 * near[1] - 0.5 * far[1]];
        out[2 * i] = p.weight * (t[0] * p.normal[0] + t[1] * p.normal[1]);
        out[2 * i + 1] = p.weight * (t[0] * p.tangent[0] + t[1] * p.tangent[1]);
    }
    out
}

/// The arc length of every contact point along the contact part: points follow the boundary
/// loop, an edge's two ends share the arc length of their nodes (a chain that is not connected
/// to the previous one starts at the previous one's end).
fn arc_lengths(points: &[DualContactPoint]) -> Vec<f64> {
    let mut s = vec![0.0; points.len()];
    for i in 1..points.len() {
        let (a, b) = (points[i - 1].position, points[i].position);
        let connected = points[i - 1].node == points[i].node || points[i].end == 1;
        s[i] = s[i - 1] + if connected { (b[0] - a[0]).hypot(b[1] - a[1]) } else { 0.0 };
    }
    s
}

/// The dual contact answer point by point along the contact part, for `contact.csv` and
/// `contact.svg`: two points per contact edge (its ends, where the linear traction is
/// discontinuous across a node), pressure `−rN / w`, tangential traction `rT / w`, and the
/// dual contact displacement (the multiplier of the force constraints: a weighted mean of the
/// displacement near the edge end) with the gap `g̃ − uN` it closes.
pub(crate) fn dual_contact_curve(outcome: &DualContactOutcome) -> Vec<super::ContactCurvePoint> {
    let s = arc_lengths(&outcome.points);
    let frictional = outcome.report.friction.is_frictional();
    outcome
        .points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (rn, rt) = (outcome.force[2 * i], outcome.force[2 * i + 1]);
            let (un, ut) = (outcome.displacement[2 * i], outcome.displacement[2 * i + 1]);
            super::ContactCurvePoint {
                s: s[i],
                position: p.position,
                pressure: -rn / p.weight + 0.0, // never -0
                tangential_traction: rt / p.weight + 0.0,
                gap: p.gap - un,
                normal_displacement: un,
                tangential_slip: ut,
                status: crate::report::contact::ContactState::of(outcome.status[i], frictional),
            }
        })
        .collect()
}

/// The peak pressure (−rN / w) and the closed zones along the contact part: points follow
/// the boundary loop, an edge's two ends share the arc length of their nodes.
fn peak_and_zones(
    points: &[DualContactPoint],
    force: &[f64],
    status: &[PointStatus],
) -> (Option<PeakPressure>, Vec<ClosedZone>) {
    let s = arc_lengths(points);
    let mut peak: Option<PeakPressure> = None;
    for (i, p) in points.iter().enumerate() {
        let pressure = -force[2 * i] / p.weight;
        if pressure > 0.0 && peak.as_ref().is_none_or(|q| pressure > q.pressure) {
            peak = Some(PeakPressure { pressure, node: p.node, position: p.position, s: s[i] });
        }
    }
    let mut zones: Vec<ClosedZone> = Vec::new();
    let mut current: Option<(usize, usize)> = None;
    let close = |(a, b): (usize, usize)| ClosedZone {
        extent: [s[a], s[b]],
        start: points[a].position,
        end: points[b].position,
        points: b - a + 1,
    };
    for i in 0..points.len() {
        let chained = i > 0 && (points[i - 1].node == points[i].node || points[i].end == 1);
        match (status[i] != PointStatus::Open, current) {
            (true, Some((a, _))) if chained => current = Some((a, i)),
            (true, c) => {
                if let Some(z) = c {
                    zones.push(close(z));
                }
                current = Some((i, i));
            }
            (false, Some(z)) => {
                zones.push(close(z));
                current = None;
            }
            (false, None) => {}
        }
    }
    if let Some(z) = current {
        zones.push(close(z));
    }
    (peak, zones)
}

/// The data of a contact side for [`DualData`].
pub(super) fn dual_data_with_contact<'a>(
    data: DualData<'a>,
    group: usize,
    normal: &'a (dyn Fn([f64; 2]) -> [f64; 2] + Sync),
) -> DualData<'a> {
    DualData { contact: Some(crate::dual::ContactSide { group, normal }), ..data }
}

/// Nodal contact pressure, friction traction and status (0 open, 1 stick, 2 slip, 3 closed
/// without friction: [`crate::report::contact::ContactState::code`]) of the dual solution for
/// `solution.vtu`: the mean of the edge ends at each node (the worst status).
pub(crate) fn nodal_contact_fields(num_nodes: usize, outcome: &DualContactOutcome) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let (mut pressure, mut friction, mut status, mut count) =
        (vec![0.0; num_nodes], vec![0.0; num_nodes], vec![-1.0f64; num_nodes], vec![0usize; num_nodes]);
    let frictional = outcome.report.friction.is_frictional();
    for (i, p) in outcome.points.iter().enumerate() {
        pressure[p.node] += -outcome.force[2 * i] / p.weight;
        friction[p.node] += outcome.force[2 * i + 1] / p.weight;
        count[p.node] += 1;
        let code = crate::report::contact::ContactState::of(outcome.status[i], frictional).code();
        status[p.node] = status[p.node].max(code);
    }
    for k in 0..num_nodes {
        if count[k] > 0 {
            pressure[k] /= count[k] as f64;
            friction[k] /= count[k] as f64;
        }
    }
    (pressure, friction, status)
}
