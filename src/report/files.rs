//! The result files of a run: `solution.vtu` and `report.json`, and for contact
//! `contact.csv`, `contact.svg` and `convergence.svg` (rank 0, each atomically, all or none).
//! Under MPI the outcome of rank 0's writing is agreed over the ranks before the report, whose
//! making is collective: a failed write stops every rank.
use std::path::{Path, PathBuf};

use super::contact::ContactState;
use super::contact_curve::ContactCurvePoint;
use crate::error::Result;
use crate::output::{self, vtu};
use crate::problem::{ElasticityProblem, Phase, Report};

/// The named arrays `(name, components, values)` of a `.vtu` file, on its points and on its
/// cells, and whether the cell arrays cover the boundary edges too.
pub(crate) struct SolutionFields {
    pub point: Vec<(String, usize, Vec<f64>)>,
    pub cell: Vec<(String, usize, Vec<f64>)>,
    pub with_edges: bool,
}

impl SolutionFields {
    /// Write them with `mesh` to `path` (atomic).
    pub fn write(&self, path: &Path, mesh: &crate::mesh::Mesh) -> Result<()> {
        let points: Vec<vtu::Field> = self.point.iter().map(as_field).collect();
        let cells: Vec<vtu::Field> = self.cell.iter().map(as_field).collect();
        vtu::write_vtu(path, mesh, &points, &cells, self.with_edges)
    }
}

fn as_field((name, k, v): &(String, usize, Vec<f64>)) -> vtu::Field<'_> {
    vtu::Field { name, components: *k, values: v }
}

impl ElasticityProblem<'_> {
    /// `solution.vtu` as [`ElasticityProblem::write_output`] writes it, with extra scalar cell
    /// data (one value per cell each; e.g. the size map `target_size` of mesh adaptation).
    /// Atomic; call it on one rank.
    pub fn write_solution_vtu(&self, path: &Path, extra_cells: &[(&str, &[f64])]) -> Result<()> {
        self.solution_fields(path, extra_cells)?.write(path, &self.mesh)
    }

    /// The data of `solution.vtu`: the primal fields (displacement, stress, von Mises,
    /// contact), the dual ones (stress, von Mises, Airy function; named `dual_...` next to a
    /// primal solution) and the estimate per cell (`error`), whichever were computed, and
    /// `extra_cells`.
    pub(crate) fn solution_fields(&self, path: &Path, extra_cells: &[(&str, &[f64])]) -> Result<SolutionFields> {
        let mut point: Vec<(String, usize, Vec<f64>)> = Vec::new();
        let mut cell: Vec<(String, usize, Vec<f64>)> = Vec::new();
        let tensor = |s: &[f64; 3], zz: f64| [s[0], s[1], zz, s[2], 0.0, 0.0];
        if let (Some(u), Some(results)) = (&self.displacement, &self.results) {
            point.push(("displacement".into(), 3, u.chunks(2).flat_map(|d| [d[0], d[1], 0.0]).collect()));
            // VTK symmetric tensor order: XX, YY, ZZ, XY, YZ, XZ.
            let stress6 =
                results.nodal_stress.iter().zip(&results.sigma_zz).flat_map(|(s, zz)| tensor(s, *zz)).collect();
            point.push(("stress".into(), 6, stress6));
            point.push(("von_mises".into(), 1, results.von_mises.clone()));
            let n = self.mesh.num_nodes();
            if let (Some(c), Some(o)) = (&self.contact, &self.contact_outcome) {
                let (mut pressure, mut friction, mut status) = (vec![0.0; n], vec![0.0; n], vec![-1.0; n]);
                let (p, t) = c.boundary.tractions(&o.force);
                let frictional = c.frictional_points();
                for (i, &node) in c.boundary.nodes.iter().enumerate() {
                    pressure[node] = p[i];
                    friction[node] = t[i];
                    status[node] = ContactState::of(o.status[i], frictional[i]).code();
                }
                self.add_master_contact_fields(&mut pressure, &mut friction, &mut status);
                point.push(("contact_pressure".into(), 1, pressure));
                point.push(("friction_traction".into(), 1, friction));
                point.push(("contact_status".into(), 1, status));
            }
        }
        let mut with_edges = true;
        if let Some(d) = &self.dual {
            let prefix = if self.displacement.is_some() { "dual_" } else { "" };
            let stress6 =
                d.nodal_stress.iter().flat_map(|s| tensor(s, self.material.sigma_zz(*s))).collect::<Vec<f64>>();
            point.push((format!("{prefix}stress"), 6, stress6));
            point.push((format!("{prefix}von_mises"), 1, d.von_mises.clone()));
            point.push(("airy_stress".into(), 1, d.airy.clone()));
            // Per cell: the stress at the centroid (the field is linear on each third of a cell).
            let field = d.system.field(&self.mesh, &d.phi);
            let mut cell_stress = Vec::with_capacity(6 * self.mesh.num_cells());
            let mut cell_vm = Vec::with_capacity(self.mesh.num_cells());
            for c in 0..self.mesh.num_cells() {
                let v = self.mesh.cell(c);
                let x: Vec<[f64; 2]> = v[..3].iter().map(|&k| self.mesh.nodes[k]).collect();
                let g = [(x[0][0] + x[1][0] + x[2][0]) / 3.0, (x[0][1] + x[1][1] + x[2][1]) / 3.0];
                let s = field.stress_at(c, g);
                cell_stress.extend(tensor(&s, self.material.sigma_zz(s)));
                cell_vm.push(self.material.von_mises(s));
            }
            cell.push((format!("{prefix}cell_stress"), 6, cell_stress));
            cell.push((format!("{prefix}cell_von_mises"), 1, cell_vm));
            if let Some(c) = &d.contact {
                let (pressure, friction, status) =
                    crate::problem::dual_contact::nodal_contact_fields(self.mesh.num_nodes(), c);
                point.push((format!("{prefix}contact_pressure"), 1, pressure));
                point.push((format!("{prefix}friction_traction"), 1, friction));
                point.push((format!("{prefix}contact_status"), 1, status));
            }
            with_edges = false;
        }
        if let Some(e) = &self.estimate {
            cell.push(("error".into(), 1, e.estimate.element_error()));
            if self.scene.contact.is_some() {
                let contact: Vec<f64> = e.estimate.element_contact.iter().map(|v| v.max(0.0).sqrt()).collect();
                cell.push(("error_contact".into(), 1, contact));
            }
        }
        for (name, values) in extra_cells {
            if values.len() != self.mesh.num_cells() {
                return Err(crate::error::Error::Output {
                    path: path.to_path_buf(),
                    message: format!(
                        "cell data '{name}' has {} values for {} cells",
                        values.len(),
                        self.mesh.num_cells()
                    ),
                });
            }
            cell.push((name.to_string(), 1, values.to_vec()));
        }
        Ok(SolutionFields { point, cell, with_edges })
    }

    /// The contact answer point by point in order along the contact part (after
    /// [`ElasticityProblem::solve`]); `None` without contact.
    pub fn contact_curve(&self) -> Option<Vec<ContactCurvePoint>> {
        let (c, o, u) = (self.contact.as_ref()?, self.contact_outcome.as_ref()?, self.displacement.as_ref()?);
        Some(super::contact_curve::contact_curve(
            &self.mesh,
            &c.boundary,
            &o.force,
            &o.status,
            u,
            &c.frictional_points(),
        ))
    }

    /// `contact.csv`, `contact.svg` and `convergence.svg` of a contact run into `dir`: the
    /// primal's contact answer, or the dual's in a run of the dual formulation alone.
    fn write_contact_files(&self, dir: &Path, written: &mut Vec<PathBuf>) -> Result<()> {
        let (points, r) = match (self.contact_curve(), &self.contact_outcome) {
            (Some(points), Some(outcome)) => (points, &outcome.report),
            _ => match self.dual.as_ref().and_then(|d| d.contact.as_ref()) {
                Some(outcome) if self.displacement.is_none() => {
                    (crate::problem::dual_contact::dual_contact_curve(outcome), &outcome.report)
                }
                _ => return Ok(()),
            },
        };
        let path = dir.join("contact.csv");
        super::contact_curve::write_contact_csv(&path, &points)?;
        written.push(path);
        // The picture shows the closed zones and a quarter of their span on either side (the
        // whole part when it is mostly closed, or open everywhere); the CSV has every point.
        let (first, last) = (points.first().map_or(0.0, |p| p.s), points.last().map_or(0.0, |p| p.s));
        let closed = r.zones.iter().map(|z| z.extent[0]).fold(f64::INFINITY, f64::min);
        let closed_end = r.zones.iter().map(|z| z.extent[1]).fold(f64::NEG_INFINITY, f64::max);
        let margin = (0.25 * (closed_end - closed)).max(0.02 * (last - first));
        let window = if closed.is_finite() {
            [(closed - margin).max(first), (closed_end + margin).min(last)]
        } else {
            [first, last]
        };
        let shown: Vec<&ContactCurvePoint> = points.iter().filter(|p| p.s >= window[0] && p.s <= window[1]).collect();
        let s: Vec<f64> = shown.iter().map(|p| p.s).collect();
        let pressure: Vec<f64> = shown.iter().map(|p| p.pressure).collect();
        let traction: Vec<f64> = shown.iter().map(|p| p.tangential_traction).collect();
        let path = dir.join("contact.svg");
        let title = format!("Contact tractions on '{}' (friction {})", r.part, r.friction);
        let zoomed = window != [first, last];
        output::contact_plots::write_contact_svg(&path, &title, &s, &pressure, &traction, zoomed)?;
        written.push(path);
        let path = dir.join("convergence.svg");
        let title = format!("Contact solver convergence ({} iterations)", r.residual_history.len());
        output::contact_plots::write_convergence_svg(&path, &title, &r.residual_history)?;
        written.push(path);
        Ok(())
    }

    /// Write the current increment of a load path as `dir/steps/solution_NNNN.vtu` (rank 0;
    /// the problem post-processed at that increment), and with an interface law
    /// `dir/steps/interface_NNNN.vtu`, recording the interface in its history
    /// ([`ElasticityProblem::record_interface_step`]). Returns the path of the solution's file
    /// (on rank 0).
    pub fn write_step_output(&self, dir: &Path, step: usize) -> Result<PathBuf> {
        let path = dir.join(crate::output::pvd::step_file_name(step));
        self.record_interface_step(step);
        let wrote = if self.session.rank() == 0 {
            let steps = dir.join(crate::output::pvd::STEPS_DIR);
            std::fs::create_dir_all(&steps)
                .map_err(|e| crate::Error::io(steps, "creating the directory of the increments", e))
                .and_then(|()| self.solution_fields(&path, &[]))
                .and_then(|fields| fields.write(&path, &self.mesh))
                .and_then(|()| match self.interface.as_ref().filter(|s| !s.points.is_empty()) {
                    Some(snapshot) => {
                        let file = dir.join(crate::output::pvd::interface_step_file_name(step));
                        crate::output::interface::write_interface_vtu(&file, snapshot)
                    }
                    None => Ok(()),
                })
        } else {
            Ok(())
        };
        self.session.agree(wrote, "writing an increment's results")?;
        Ok(path)
    }

    /// Write `solution.vtu`, `report.json` and, with contact, `contact.csv`, `contact.svg` and
    /// `convergence.svg` into `dir` (rank 0 only; all or none of them, synced to disk together:
    /// [`output::all_or_nothing`], so the `output` time in the report leaves out that last
    /// sync). Returns the report and the paths written.
    pub fn write_output(&mut self, dir: &Path) -> Result<(Report, Vec<PathBuf>)> {
        output::all_or_nothing(|| self.write_output_files(dir))
    }

    fn write_output_files(&mut self, dir: &Path) -> Result<(Report, Vec<PathBuf>)> {
        self.progress.phase_started(Phase::Output);
        let start = std::time::Instant::now();
        let mut written = Vec::new();
        let files = |written: &mut Vec<PathBuf>| -> Result<()> {
            if self.session.rank() == 0 {
                let path = dir.join("solution.vtu");
                let fields = self.solution_fields(&path, &[])?;
                fields.write(&path, &self.mesh)?;
                written.push(path);
                match &self.load_path {
                    // A load path: solution.pvd is its time series (the increments' files were
                    // written as they converged), with its history and plots; no body files.
                    Some(path) => {
                        let entries: Vec<(f64, String)> =
                            path.steps.iter().map(|s| (s.time, crate::output::pvd::step_file_name(s.step))).collect();
                        let pvd = dir.join("solution.pvd");
                        crate::output::pvd::write_pvd(&pvd, &entries)?;
                        written.push(pvd);
                        let title = self.scene.title.clone().unwrap_or_else(|| "load path".into());
                        let interface = self.interface_history.borrow();
                        written.extend(crate::evolution::history::write_load_path_outputs_in(
                            dir,
                            &path.steps,
                            &path.profiles,
                            &title,
                            interface.as_ref(),
                            self.mesh.measure,
                        )?);
                        if let Some(history) = interface.as_ref() {
                            // The interface's increments, as written by write_step_output.
                            let entries: Vec<(f64, String)> = path
                                .steps
                                .iter()
                                .filter(|s| history.at(s.step).is_some())
                                .map(|s| (s.time, crate::output::pvd::interface_step_file_name(s.step)))
                                .collect();
                            if !entries.is_empty() {
                                let pvd = dir.join(crate::output::interface::INTERFACE_PVD);
                                crate::output::pvd::write_pvd(&pvd, &entries)?;
                                written.push(pvd);
                            }
                        }
                    }
                    None => self.write_body_files(dir, &fields, written)?,
                }
                if let Some(snapshot) = self.interface.as_ref().filter(|s| !s.points.is_empty()) {
                    let path = dir.join(crate::output::interface::INTERFACE_VTU);
                    crate::output::interface::write_interface_vtu(&path, snapshot)?;
                    written.push(path);
                }
                self.write_contact_files(dir, written)?;
            }
            Ok(())
        };
        // Rank 0 alone writes: agreed before the report (collective), so that its failure stops
        // every rank instead of leaving the others waiting there.
        let wrote = files(&mut written);
        if let Err(e) = self.session.agree(wrote, "writing the results") {
            for path in &written {
                let _ = std::fs::remove_file(path);
            }
            return Err(e);
        }
        self.timings.add("output", start.elapsed().as_secs_f64());
        let finish = |written: &mut Vec<PathBuf>| -> Result<Report> {
            let report = self.report()?;
            if self.session.rank() == 0 {
                let path = dir.join("report.json");
                output::write_json(&path, &report)?;
                written.push(path);
            }
            Ok(report)
        };
        // All or nothing: a failure after some files were written removes them again.
        match finish(&mut written) {
            Ok(report) => {
                self.progress.phase_finished(Phase::Output, start.elapsed().as_secs_f64());
                Ok((report, written))
            }
            Err(e) => {
                for path in &written {
                    let _ = std::fs::remove_file(path);
                }
                Err(e)
            }
        }
    }
}
