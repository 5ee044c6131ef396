//! The driver's post-processing: nodal stresses and von Mises, the reactions of every Dirichlet
//! condition (`K u − f` on its fixed dofs, less the contact share a support receives), and the
//! independent checks of the answer that need the whole field — global equilibrium of loads,
//! reactions and contact forces, the nodes left out of the contact points, and, with several
//! bodies, each body and each pair (`report/bodies.rs`).
use super::*;

impl ElasticityProblem<'_> {
    /// Stresses, von Mises, reactions per Dirichlet part, global equilibrium.
    pub fn postprocess(&mut self) -> Result<()> {
        self.progress.phase_started(Phase::Postprocess);
        let start = std::time::Instant::now();
        let u = self.displacement.as_ref().ok_or(Error::CallOrder { call: "postprocess()", needs: "solve()" })?;
        let (nodal_stress, sigma_zz) =
            mixed_pressure::nodal_stress_cells(&self.mesh, &self.cell_materials, self.scene.element, u);
        let von_mises: Vec<f64> =
            nodal_stress.iter().zip(&sigma_zz).map(|(s, zz)| mixed_pressure::von_mises(*s, *zz)).collect();
        let max_displacement = u.chunks(2).map(|d| d[0].hypot(d[1])).fold(0.0, f64::max);
        let max_von_mises = von_mises.iter().cloned().fold(0.0, f64::max);

        // Reactions: r = K u − f on the fixed dofs, from unconstrained operators.
        let f = self.with_loads(|loads| assembly::load_vector(&self.mesh, loads))?;
        let ku = assembly::residual_forces_cells(&self.mesh, &self.cell_materials, self.scene.element, u);
        let applied_force = [f.iter().step_by(2).sum::<f64>(), f.iter().skip(1).step_by(2).sum::<f64>()];
        // Reactions per prescribed component: a condition's reaction holds only the components it
        // prescribes (a node listed by two conditions gives each its own components; a
        // component prescribed twice counts for the first condition that prescribes it).
        let mut reactions = std::collections::BTreeMap::new();
        let mut total_reaction = [0.0f64; 2];
        // Σ of the magnitudes of the forces involved: the scale of the equilibrium residual.
        let mut magnitude = applied_force[0].hypot(applied_force[1]);
        let mut counted = vec![false; f.len()];
        // A contact point's share on a prescribed dof of its node (a pin on the contact part,
        // against an obstacle or another body) goes to the support: it is taken out of that
        // dof's reaction and counted with the contact forces below (`point_force`).
        let mut on_supports = vec![0.0; f.len()];
        if let (Some(c), Some(outcome)) = (&self.contact, &self.contact_outcome) {
            c.boundary.add_forces_on_supports(&outcome.force, &mut on_supports);
        }
        // Several bodies: each condition on its own body's nodes (not the union mesh's nearest).
        let body_nodes = match &self.bodies {
            Some(model) => Some(bodies::dirichlet_nodes(model)?),
            None => None,
        };
        for (k, d) in self.scene.dirichlet.iter().enumerate() {
            let mut r = [0.0f64; 2];
            let components = [d.ux.is_some(), d.uy.is_some()];
            let nodes = match &body_nodes {
                Some(all) => all[k].clone(),
                None => d.nodes(&self.mesh)?,
            };
            for node in nodes {
                for comp in (0..2).filter(|&c| components[c]) {
                    let dof = 2 * node + comp;
                    if self.constraints.value(dof).is_some() && !counted[dof] {
                        counted[dof] = true;
                        r[comp] += ku[dof] - f[dof] - on_supports[dof];
                    }
                }
            }
            total_reaction[0] += r[0];
            total_reaction[1] += r[1];
            magnitude += r[0].hypot(r[1]);
            reactions
                .entry(d.target.to_string())
                .and_modify(|s: &mut [f64; 2]| {
                    s[0] += r[0];
                    s[1] += r[1];
                })
                .or_insert(r);
        }
        // Independent equilibrium check: the applied loads must balance the reactions and the
        // contact forces, relative to the magnitudes of those forces (never to their sum, which
        // vanishes when the answer is right).
        // The contact forces enter as Bᵀ r: between two bodies both sides count (they cancel).
        if let (Some(c), Some(outcome)) = (&self.contact, &self.contact_outcome) {
            let mut on_dofs = on_supports.clone();
            c.boundary.scatter_add(&outcome.force, &mut on_dofs);
            total_reaction[0] += on_dofs.iter().step_by(2).sum::<f64>();
            total_reaction[1] += on_dofs.iter().skip(1).step_by(2).sum::<f64>();
            magnitude += outcome.report.resultant[0].hypot(outcome.report.resultant[1]);
        }
        // With no load and no contact force (a body moved rigidly, a gap that stays open) every
        // force is round-off: the stiffness times the displacement is then the force scale.
        // In axisymmetry forces are for the full revolution (2π r ds): the stiffness scale is
        // E u 2π r_max, and the radial components of ring forces do not add up to a balance (a
        // ring pulled outwards all round is in equilibrium): only the axial resultant is checked,
        // the radial equilibrium being node by node in the solver's residual.
        let magnitude = magnitude.max(self.material.plane_modulus() * max_displacement * self.mesh.force_length());
        let imbalance =
            self.mesh.measure.imbalance([applied_force[0] + total_reaction[0], applied_force[1] + total_reaction[1]]);
        let equilibrium_residual = if magnitude > 0.0 { imbalance / magnitude } else { 0.0 };
        if equilibrium_residual > EQUILIBRIUM_CHECK {
            return Err(Error::SolverDiverged {
                solver: "the independent check of the answer".into(),
                reason: format!(
                    "global equilibrium fails: loads ({:.4e}, {:.4e}) + reactions and contact forces ({:.4e}, {:.4e}) \
                     leave {imbalance:.3e} against forces of {magnitude:.3e}",
                    applied_force[0], applied_force[1], total_reaction[0], total_reaction[1]
                ),
                iterations: self.stats.as_ref().map_or(0, |s| s.iterations),
                residual: equilibrium_residual,
                tried: self.stats.as_ref().map_or_else(String::new, |s| format!("{} + {}", s.ksp_type, s.pc_type)),
            });
        }
        // The peak pressure and the closed zones along the part.
        if let (Some(c), Some(outcome)) = (&self.contact, &mut self.contact_outcome) {
            let (pressure, _) = c.boundary.tractions(&outcome.force);
            let (peak, zones) =
                crate::report::contact_zones::zones(&self.mesh, &c.boundary, &pressure, &outcome.status);
            outcome.report.peak_pressure = peak;
            outcome.report.zones = zones;
        }
        // Nodes of the contact part left out of the contact points (prescribed in both
        // components) must not penetrate either.
        if let (Some(c), Some(outcome)) = (&self.contact, &mut self.contact_outcome) {
            let (penetration, node) = c.boundary.left_out_penetration(u);
            let scale = outcome.report.residuals.displacement_scale.max(f64::MIN_POSITIVE);
            let relative = penetration / scale;
            outcome.report.residuals.max_penetration = outcome.report.residuals.max_penetration.max(relative);
            if relative > EQUILIBRIUM_CHECK {
                let node = node.unwrap_or(0);
                return Err(Error::SolverDiverged {
                    solver: "the independent check of the answer".into(),
                    reason: format!(
                        "node {node} of contact part '{}' (left out of the contact points: its displacement is \
                         prescribed) penetrates the obstacle by {penetration:.4e} ({relative:.1e} of the \
                         displacement scale): the prescribed displacement pushes it through the obstacle",
                        c.spec.part
                    ),
                    iterations: 0,
                    residual: relative,
                    tried: "check the prescribed displacements of the contact part".into(),
                });
            }
        }
        let bodies_report = self.check_bodies(u, &f, &ku, &on_supports)?;
        self.bodies_report = bodies_report;
        self.warnings.extend(crate::report::warnings::after_solving(&self.mesh, u));
        let open = self.contact_open_warnings();
        self.warnings.extend(open);
        self.results = Some(Results {
            nodal_stress,
            sigma_zz,
            von_mises,
            report: ResultsReport { max_displacement, max_von_mises, applied_force, reactions, equilibrium_residual },
        });
        self.timings.add("postprocess", start.elapsed().as_secs_f64());
        self.progress.phase_finished(Phase::Postprocess, start.elapsed().as_secs_f64());
        Ok(())
    }

    /// A `contact_open` warning for each contact part whose points all stayed open.
    fn contact_open_warnings(&self) -> Vec<Warning> {
        use crate::contact_routes::condensed_route::{obstacle_text, wrong_side};
        let (Some(c), Some(outcome)) = (&self.contact, &self.contact_outcome) else { return Vec::new() };
        let status = &outcome.status;
        // Each part: its name, its points and, against a rigid obstacle, the obstacle and the
        // nodes of the body that touches it.
        let parts: Vec<(&str, Vec<usize>, Option<(&scene::ObstacleSpec, &[[f64; 2]])>)> = match (&c.parts, &self.bodies)
        {
            (Some(parts), Some(model)) => parts
                .parts
                .iter()
                .enumerate()
                .map(|(p, part)| {
                    let points = (0..status.len()).filter(|&i| parts.part_of[i] == p).collect();
                    let spec =
                        if part.master.is_none() { model.bodies[part.slave_body].contact.as_ref() } else { None };
                    let nodes = &self.mesh.nodes[model.layout.bodies[part.slave_body].nodes.clone()];
                    (part.name.as_str(), points, spec.map(|s| (&s.obstacle, nodes)))
                })
                .collect(),
            _ => vec![(
                c.spec.part.as_str(),
                (0..status.len()).collect(),
                Some((&c.spec.obstacle, &self.mesh.nodes[..])),
            )],
        };
        parts
            .into_iter()
            .filter(|(_, points, _)| {
                !points.is_empty() && points.iter().all(|&i| status[i] == crate::contact::PointStatus::Open)
            })
            .map(|(name, points, obstacle)| {
                let wrong = obstacle.and_then(|(o, nodes)| wrong_side(o, nodes)).map(|(w, h)| format!("{w}; {h}"));
                let text = obstacle.map(|(o, _)| obstacle_text(o));
                crate::report::warnings::contact_open(name, points.len(), text.as_deref(), wrong.as_deref())
            })
            .collect()
    }
}
