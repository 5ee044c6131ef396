//! The scene's condensed contact problem on its own, for other solvers (`signorini export`
//! writes it in the FCLIB format):
//!
//! ```text
//! condensed_contact_problem   K, f assembled as for a plain solve (no stabilisation springs,
//!                             whatever the scene's contact solver), then W = B K⁻¹ Bᵀ (every
//!                             column, also without friction) and u_free = B K⁻¹ f
//!                             (ContactSetup::condensed_problem), the gaps, the friction law
//! solve_condensed_contact_problem
//!                             our answer to exactly that problem: the scene's solver on the
//!                             condensed problem, checked by contact::solve
//! ```
use super::ElasticityProblem;
use crate::contact::{self, CondensedProblem, ContactSolution, ContactSolver};
use crate::contact_routes::condensed_route::{condensed_solver, tao_box_qp};
use crate::error::{Error, Result};
use crate::fem::assembly;
use crate::petsc::LinearSolver;
use crate::scene::ContactSolverSpec;

impl<'s> ElasticityProblem<'s> {
    /// The condensed contact problem of the scene (collective over the MPI ranks).
    ///
    /// Errors: [`Error::Usage`] for a scene without `[contact]`, [`Error::Unconstrained`] for a
    /// body held by the contact alone (its stiffness is singular: no flexibility), and the
    /// errors of the linear solves.
    pub fn condensed_contact_problem(&mut self) -> Result<CondensedProblem<'static>> {
        let contact = self.contact.as_ref().ok_or_else(|| {
            Error::Usage(format!(
                "the scene {} has no [contact] section: there is no contact problem to condense",
                self.scene.source.display()
            ))
        })?;
        let start = std::time::Instant::now();
        let system = self.with_loads(|loads| {
            assembly::assemble_cells(
                &self.mesh,
                &self.cell_materials,
                self.scene.element,
                &self.constraints,
                loads,
                self.rows.clone(),
            )
        })?;
        let (matrix, rhs) = self.to_petsc(&system)?;
        let mut ksp = LinearSolver::new(self.session, self.session.world(), "")?;
        ksp.set_operator(&matrix)?;
        let problem = contact.condensed_problem(self.session, &matrix, &rhs, &mut ksp, &*self.progress)?;
        self.timings.add("condense", start.elapsed().as_secs_f64());
        Ok(problem)
    }

    /// Solve `problem` (from [`Self::condensed_contact_problem`]) with the scene's contact
    /// solver on the condensed problem — the semi-smooth Newton method for `newton_full` and
    /// `snes_vi`, which run on the full system, TAO for `tao` — with the scene's tolerance and
    /// iteration limit. The answer has passed [`contact::solve`]'s independent check.
    pub fn solve_condensed_contact_problem(&self, problem: &CondensedProblem) -> Result<ContactSolution> {
        let spec = &self
            .contact
            .as_ref()
            .ok_or_else(|| Error::Usage("the scene has no [contact] section: no contact solver".into()))?
            .spec;
        if spec.solver == ContactSolverSpec::Tao {
            return tao_box_qp(self.session, problem);
        }
        let solver = condensed_solver(&spec.solver).unwrap_or(ContactSolver::SemismoothNewton);
        let settings = crate::contact_routes::condensation::solver_settings(spec);
        contact::solve(problem, &solver, &settings)
    }
}
