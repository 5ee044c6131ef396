//! The dual formulation and the error in the constitutive relation inside the driver:
//!
//! ```text
//! ElasticityProblem::solve_dual   the scene's loads and supports as dual data (tractions
//!                                 imposed, prescribed displacements in the complementary
//!                                 energy), HCT assembly, PETSc solve, independent check
//!                 ::estimate      e_E per cell from the primal u_h and the dual σ_h on the
//!                                 same mesh, the global and relative error, timed
//! ```
//!
//! Point supports carry a point force, which no C¹ Airy function can: the dual drops them and
//! says so in its notes; with an estimate, where the primal reaction at the point is known, a
//! point reaction that is not zero (beyond round-off of the reactions) is an error, since the
//! two formulations would then solve different problems.
//!
//! PETSc options: a dual-only run reads the unprefixed options (`-ksp_type ...`), as the primal
//! does; in an estimate run those belong to the primal solve and the dual reads `-dual_ksp_type`,
//! `-dual_pc_type`, ... The boundary constraints are eliminated unless the scene or the command
//! line asks for multipliers (`dual_constraints`, [`crate::dual::saddle_point`]).
use super::dual_contact::{dual_data_with_contact, DualContactOutcome};
use super::ElasticityProblem;
use crate::dual::{check, BodyLoad, DualCheck, DualData, DualSystem};
use crate::error::{Error, Result};
use crate::estimate::{pair_degree, volume_terms, Estimate, EstimateKind};
use crate::fem::assembly::EdgeLoad;
use crate::petsc::SolveStats;
use crate::scene::{DirichletTarget, DualConstraints, FrictionSpec};

/// A point support's primal reaction up to this fraction of [`point_reaction_scale`] is
/// round-off (measured 5e-15 of the load magnitude for a block held by two point supports under
/// self-balanced end pressures): the dual, which drops the support, solves the same problem.
pub const POINT_REACTION_TOLERANCE: f64 = 1e-8;

/// The force scale a point reaction is compared with: the magnitude of the loads (`Σ |f_node|`
/// of the load vector), the resultant of the applied loads and the largest reaction, whichever
/// is largest.
pub fn point_reaction_scale(load_magnitude: f64, results: &super::ResultsReport) -> f64 {
    let resultant = results.applied_force[0].hypot(results.applied_force[1]);
    let reaction = results.reactions.values().map(|r| r[0].hypot(r[1])).fold(0.0, f64::max);
    load_magnitude.max(resultant).max(reaction).max(f64::MIN_POSITIVE)
}

/// The PETSc options prefix of the dual solve when the primal is solved in the same run.
pub const DUAL_OPTIONS_PREFIX: &str = "dual_";

/// What a dual solve reports (`report.json` under `dual`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct DualReport {
    /// HCT degrees of freedom (3 per vertex, 1 per edge) and the unknowns left once the
    /// boundary conditions and the affine kernel are eliminated.
    pub hct_dofs: usize,
    /// Unknowns solved for.
    pub unknowns: usize,
    /// The HCT dofs set by the boundary conditions: by the known tractions, by the contact
    /// forces on the contact part, and the three of the anchor node (φ = φ,x = φ,y = 0); the
    /// others are free unknowns. The `fixed_dofs` of a dual-only run's report.
    pub fixed_hct_dofs: usize,
    /// How the boundary constraints were imposed: "eliminated" (the unknowns above) or
    /// "multipliers" (a saddle point of `saddle_point_size` unknowns).
    pub constraints: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    /// Size of the saddle-point system, with `constraints = "multipliers"`.
    pub saddle_point_size: Option<usize>,
    /// The node where φ, φ,x, φ,y were fixed to zero.
    pub anchor_node: usize,
    /// Largest von Mises stress of the dual solution over the nodes (Pa).
    pub max_von_mises: f64,
    /// The independent check of static admissibility, and the complementary energy.
    pub check: DualCheck,
    /// The dual linear solve's statistics.
    pub solver: SolveStats,
    /// With a `[contact]` section: the dual contact solution and its independent check (forces
    /// at both ends of every contact edge, in the contact frames).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<crate::report::contact::ContactReport>,
    /// What happened on the way, in words.
    pub notes: Vec<String>,
}

/// The solved dual problem.
pub struct DualOutcome {
    /// The dual system: the HCT space, its constraints and matrices.
    pub system: DualSystem,
    /// The Airy stress function's HCT dofs (the solution).
    pub phi: Vec<f64>,
    /// Nodal stresses `[σxx, σyy, σxy]` (Pa) from φ.
    pub nodal_stress: Vec<[f64; 3]>,
    /// Von Mises stress at the nodes (Pa).
    pub von_mises: Vec<f64>,
    /// The Airy stress function φ at the mesh nodes.
    pub airy: Vec<f64>,
    /// The summary written to `report.json`.
    pub report: DualReport,
    /// The dual contact solution, with a `[contact]` table.
    pub contact: Option<DualContactOutcome>,
}

/// The estimate (`report.json` under `estimate`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct EstimateReport {
    #[serde(flatten)]
    /// The error in the constitutive relation: total, relative, per element.
    pub estimate: Estimate,
    /// What `relative_percent` divides by.
    pub norm: &'static str,
    /// What the number means.
    pub meaning: &'static str,
    /// Seconds: the primal solve, the dual solve, the estimate itself, and all of the run.
    pub primal_seconds: f64,
    /// Seconds of the dual solve.
    pub dual_seconds: f64,
    /// Seconds of the estimate itself.
    pub estimate_seconds: f64,
    /// The run time of every phase so far (mesh to output), next to the error it bought.
    pub run_seconds: f64,
}

impl<'s> ElasticityProblem<'s> {
    /// Solve the dual (stress) formulation on the problem's mesh.
    /// The dual formulation and the estimate take one body: [`Error::SeveralBodiesNotSolved`]
    /// for a scene with `[[body]]` tables.
    fn refuse_bodies(&self) -> Result<()> {
        match &self.bodies {
            Some(_) => Err(crate::error::Error::SeveralBodiesNotSolved {
                scene: self.scene.source.clone(),
                bodies: self.scene.bodies.len(),
                pairs: self.scene.contact_pairs.len(),
            }),
            None => Ok(()),
        }
    }

    /// Solve the dual (stress) formulation on the problem's mesh: the Airy stress function on HCT
    /// elements, with its contact when the scene has one; fills [`ElasticityProblem::dual`].
    pub fn solve_dual(&mut self) -> Result<()> {
        self.refuse_bodies()?;
        crate::interface_law::refuse_dual(&self.scene, "the dual formulation")?;
        super::axisymmetry::refuse_in_axisymmetry(&self.scene, "the dual formulation")?;
        self.progress().phase_started(super::Phase::Dual);
        let start = std::time::Instant::now();
        self.solve_dual_unobserved()?;
        self.progress().phase_finished(super::Phase::Dual, start.elapsed().as_secs_f64());
        Ok(())
    }

    fn solve_dual_unobserved(&mut self) -> Result<()> {
        let start = std::time::Instant::now();
        let side = self.dual_contact_side()?;
        if side.is_some() && self.scene.dual_constraints == DualConstraints::Multipliers {
            return Err(Error::Formulation {
                message: "dual formulation: contact with dual_constraints = \"multipliers\" is not available".into(),
                hint: "remove dual_constraints (the constraints are then eliminated, the default)".into(),
            });
        }
        let (body, edge) = self.loads()?;
        let edge_loads: Vec<EdgeLoad> =
            edge.into_iter().map(|(group, traction)| EdgeLoad { group, traction }).collect();
        let mut prescribed = Vec::new();
        let mut notes = Vec::new();
        for (k, d) in self.scene.dirichlet.iter().enumerate() {
            // Within a load path, the increment's values.
            let factor = self.load_factors.as_ref().map_or(1.0, |f| f.dirichlet[k]);
            match &d.target {
                DirichletTarget::Part(part) => prescribed
                    .push((self.mesh.require_group(part, 1)?, [d.ux.map(|v| factor * v), d.uy.map(|v| factor * v)])),
                DirichletTarget::Point(p) => notes.push(format!(
                    "point support at ({}, {}) dropped: a point force cannot be carried by a C1 Airy function; the \
                     answer is that of the problem without it (the same when its reaction is zero, as for a support \
                     that only removes a rigid motion)",
                    p[0], p[1]
                )),
            }
        }
        let normal = |x: [f64; 2]| side.as_ref().map_or([0.0, 0.0], |s| s.normal(x));
        let mut data = DualData {
            body_force: BodyLoad::Constant(body.unwrap_or([0.0, 0.0])),
            edge_loads: &edge_loads,
            prescribed: &prescribed,
            contact: None,
        };
        if let Some(s) = &side {
            data = dual_data_with_contact(data, s.group, &normal);
        }
        let points: Vec<[f64; 2]> = self
            .scene
            .dirichlet
            .iter()
            .filter_map(|d| if let DirichletTarget::Point(p) = d.target { Some(p) } else { None })
            .collect();
        let mut system = DualSystem::new(&self.mesh, &self.material, &data).map_err(|e| match e {
            // Without its point supports the body cannot balance its loads: they carry force.
            Error::NoEquilibrium(m) if !points.is_empty() => Error::Formulation {
                message: format!(
                    "{m}\n  the point support(s) at {points:?} must carry that force, and a point force cannot be \
                     represented by a C1 Airy function"
                ),
                hint: "distribute the support over a boundary part (a [[dirichlet]] with part = ...), or use the \
                       primal formulation"
                    .into(),
            },
            other => other,
        })?;
        if system.local.is_some() && !crate::dual::condensation::local_from_options(self.session)? {
            system.local = None;
            system.local_fallback = Some(format!("{} false", crate::dual::condensation::LOCAL_OPTION));
        }
        let constraints = self.scene.dual_constraints;
        // Alone, the dual solve is the run's main solve and reads the unprefixed PETSc options;
        // after a primal solve (an estimate), those are the primal's, and the dual reads its
        // own under `-dual_` (e.g. -dual_ksp_type symmlq -dual_pc_type jacobi).
        let prefix = if self.displacement.is_some() { DUAL_OPTIONS_PREFIX } else { "" };
        let (phi, stats, contact) = match &side {
            Some(side) => {
                let (phi, stats, outcome) = self.solve_dual_contact(&system, side, prefix)?;
                (phi, stats, Some(outcome))
            }
            None => {
                let (phi, stats) = system.solve_with(self.session, &self.mesh, prefix, constraints)?;
                (phi, stats, None)
            }
        };
        let field = system.field(&self.mesh, &phi);
        let check = check(&field, &data);
        if check.worst() > 1e-8 {
            return Err(Error::SolverDiverged {
                solver: "dual formulation (HCT)".into(),
                reason: format!("the stress field fails its admissibility check: {check:?}"),
                iterations: stats.iterations,
                residual: check.worst(),
                tried: format!("{} + {}", stats.ksp_type, stats.pc_type),
            });
        }
        let nodal_stress = field.nodal_stress();
        let von_mises: Vec<f64> = nodal_stress.iter().map(|s| self.material.von_mises(*s)).collect();
        let airy = field.nodal_airy();
        let report = DualReport {
            hct_dofs: system.dofs.len(),
            unknowns: system.num_unknowns(),
            fixed_hct_dofs: system.dofs.len() - system.affine.num_masters,
            constraints: constraints.name(),
            saddle_point_size: (constraints == DualConstraints::Multipliers).then(|| system.saddle_point_size()),
            anchor_node: system.affine.anchor,
            max_von_mises: von_mises.iter().cloned().fold(0.0, f64::max),
            check,
            solver: stats,
            contact: contact.as_ref().map(|c| c.report.clone()),
            notes,
        };
        self.dual = Some(DualOutcome { system, phi, nodal_stress, von_mises, airy, report, contact });
        self.timings.add("dual", start.elapsed().as_secs_f64());
        Ok(())
    }

    /// `Σ_nodes |f_node|` of the primal load vector (tractions and body force): the size of the
    /// loads, whatever their resultant.
    fn load_magnitude(&self) -> Result<f64> {
        let f = self.with_loads(|loads| crate::fem::assembly::load_vector(&self.mesh, loads))?;
        Ok(f.chunks(2).map(|c| c[0].hypot(c[1])).sum())
    }

    /// The error in the constitutive relation of the primal and dual solutions (both solved).
    pub fn estimate(&mut self) -> Result<()> {
        self.refuse_bodies()?;
        crate::interface_law::refuse_dual(&self.scene, "the estimate")?;
        super::axisymmetry::refuse_in_axisymmetry(&self.scene, "the estimate")?;
        self.progress().phase_started(super::Phase::Estimate);
        let start = std::time::Instant::now();
        self.estimate_unobserved()?;
        self.progress().phase_finished(super::Phase::Estimate, start.elapsed().as_secs_f64());
        Ok(())
    }

    fn estimate_unobserved(&mut self) -> Result<()> {
        let start = std::time::Instant::now();
        let (Some(u), Some(dual)) = (&self.displacement, &self.dual) else {
            let needs = if self.displacement.is_none() { "solve()" } else { "solve_dual()" };
            return Err(Error::CallOrder { call: "estimate()", needs });
        };
        // Point supports are dropped by the dual: their primal reactions must vanish, up to the
        // round-off of the reactions, which is relative to the loads (their magnitudes, not their
        // resultant: self-balanced loads have none, and the round-off is then all there is).
        if let Some(results) = &self.results {
            let scale = point_reaction_scale(self.load_magnitude()?, &results.report);
            for d in &self.scene.dirichlet {
                if let DirichletTarget::Point(p) = &d.target {
                    let r = results.report.reactions.get(&d.target.to_string()).copied().unwrap_or([0.0; 2]);
                    if r[0].hypot(r[1]) > POINT_REACTION_TOLERANCE * scale {
                        return Err(Error::Formulation {
                            message: format!(
                                "dual formulation: the point support at ({}, {}) carries a force ({:.4e}, {:.4e}) in the \
                                 primal solution; a C1 Airy function cannot represent a point force, so the primal and \
                                 dual solutions would not be of the same problem",
                                p[0], p[1], r[0], r[1]
                            ),
                            hint: "distribute the support over a boundary part (a [[dirichlet]] with part = ...), or drop it \
                                   if the other supports hold the body; examples/scenes/square_block_tresca.toml is \
                                   the default scene's square block so changed (no corner point, Tresca friction) and \
                                   runs with the estimate"
                                .into(),
                        });
                    }
                }
            }
        }
        let field = dual.system.field(&self.mesh, &dual.phi);
        let volume = volume_terms(&self.mesh, &self.material, u, &field, pair_degree(&self.mesh));
        let contact = self.dual_contact_terms(u, &dual.system, &dual.phi)?;
        let coulomb = matches!(self.scene.contact.as_ref().map(|c| c.friction), Some(FrictionSpec::Coulomb { .. }));
        let kind = if coulomb { EstimateKind::Estimator } else { EstimateKind::GuaranteedBound };
        let estimate = Estimate::new(kind, &volume, contact.as_ref().map(|c| &c.0));
        let admissible = contact.as_ref().is_none_or(|c| c.1);
        let estimate_seconds = start.elapsed().as_secs_f64();
        self.timings.add("estimate", estimate_seconds);
        self.estimate = Some(EstimateReport {
            estimate,
            norm: "energy norm of the mean field, ‖½(σ_h + Cε(u_h))‖ in the compliance C⁻¹",
            meaning: match (kind, contact.is_some(), admissible) {
                (EstimateKind::Estimator, _, _) => {
                    "an estimator of the error (Coulomb friction is not a minimisation: no guaranteed bound); \
                     error² = volume² + contact², contact² = 2 ∫Γc (σN (uN − g0) + σT·uT + μ|σN||uT|)"
                }
                (_, true, true) => {
                    "a guaranteed upper bound of the error (frictionless or Tresca contact, every contact term ≥ 0): \
                     error² = volume² + contact², contact² = 2 ∫Γc (σN (uN − g0) + σT·uT + g|uT|)"
                }
                (_, true, false) => {
                    "NOT guaranteed: a contact term is negative (see min_contact_integrand), one of the fields is \
                     not admissible on the contact part (e.g. a P2 primal penetrating between nodes)"
                }
                _ => {
                    "a guaranteed upper bound of ‖u − u_h‖_a and of ‖σ − σ_h‖_b (Prager–Synge): \
                     error² = ‖u − u_h‖²_a + ‖σ − σ_h‖²_b"
                }
            },
            primal_seconds: self.timings.get("solve").unwrap_or(0.0),
            dual_seconds: self.timings.get("dual").unwrap_or(0.0),
            estimate_seconds,
            run_seconds: self.timings.total(),
        });
        Ok(())
    }
}
