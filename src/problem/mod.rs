//! The problem driver. Its methods read like the algorithm:
//!
//! ```text
//! ElasticityProblem::setup_system   mesh (generate or read), material, Dirichlet constraints,
//!                                   contact points, rigid-motion check, row partition over MPI ranks
//!                   ::assemble      stiffness rows and load vector of this rank -> PETSc AIJ
//!                                   (kept as Rust CSR rows for the full-space contact route)
//!                   ::solve         KSP (MUMPS Cholesky by default, any PETSc option), checked;
//!                                   with a [contact] section: the full-space semi-smooth Newton
//!                                   on (u, λ) through SNES by default, or the condensed
//!                                   solvers / SNESVI / TAO ([`crate::contact_routes`])
//!                   ::postprocess   stresses, von Mises, reactions, equilibrium residual
//!                   ::write_output  solution.vtu + report.json, and for contact contact.csv,
//!                                   contact.svg, convergence.svg (rank 0, atomic; [`crate::report`])
//!                   ::condensed_contact_problem   instead of assemble/solve: the condensed
//!                                   contact problem alone, for other solvers (condensed.rs;
//!                                   `signorini export` writes it in the FCLIB format)
//! ```
//!
//! Parallel runs (`mpirun -n N`): every rank holds the whole mesh (2D meshes are small next to
//! their matrices; rank 0 alone makes it, with Gmsh, the mesh cache or a file, and sends it to
//! the others: [`crate::mesh::shared`]) and assembles only the rows of the nodes it owns — a contiguous block of
//! node numbers, so PETSc's row layout is our node layout. The solution is gathered on every
//! rank for post-processing; rank 0 writes the files. A step that can fail on one rank alone
//! (building the mesh, checks of the owned rows, rank 0's files) is agreed over the ranks
//! before the next collective operation ([`Session::agree`]): every rank returns an error, the
//! failing one its own and the others [`Error::OtherRank`], instead of waiting forever.
use std::ops::Range;

pub mod axisymmetry;
pub(crate) mod bodies;
mod condensed;
pub(crate) mod dual;
pub(crate) mod dual_contact;
mod postprocess;
mod progress;
pub use crate::contact_routes::condensed_route::ContactSetup;
pub use crate::contact_routes::full_space::{dof_ranges, MixedLayout};
pub use crate::report::bodies::{BodiesReport, BodyReport, ContactPartReport};
pub use crate::report::contact::{ContactOutcome, ContactReport, ContactResidualsReport, ContactState, FrictionReport};
pub use crate::report::contact_curve::{contact_curve, ContactCurvePoint, CONTACT_CSV_HEADER};
pub use crate::report::contact_zones::{ClosedZone, PeakPressure};
pub use crate::report::warnings::Warning;
pub use bodies::{ContactPart, ContactParts, MasterSide};
pub use dual::{DualOutcome, DualReport, EstimateReport};
pub use progress::{NoProgress, Phase, Progress};

use crate::error::{Error, Result};
use crate::fem::assembly::{self, Constraints, EdgeLoad, Loads, Traction};
use crate::fem::material::{CellMaterials, Material};
use crate::fem::mixed_pressure;
use crate::mesh::cache::CacheReport;
use crate::mesh::{self, Mesh, Order};
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats, Vector};
use crate::resources::{self, Timings};
use crate::scene::{self, ContactSolverSpec, Scene};

/// Relative tolerance of the independent checks made after every solve (global equilibrium,
/// penetration of the contact part's left-out nodes).
pub(crate) const EQUILIBRIUM_CHECK: f64 = 1e-6;

/// Everything a run reports (serialised to `report.json`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    /// The program and its version, `signorini 0.1.0 (<git commit>)`.
    pub program: String,
    /// The scene's source: its file, `<default scene>` or `<scene built in Rust>`.
    pub scene: String,
    /// The scene's `title`.
    pub title: Option<String>,
    /// `"primal"` (displacements) or `"dual"` (stresses only).
    pub formulation: &'static str,
    /// The element, e.g. `"P1"`, `"P2"`, `"P2-P0"`, `"HCT"` for a dual-only run.
    pub element: &'static str,
    /// The plane model: `"strain"`, `"stress"` or `"axisymmetric"`.
    pub plane: &'static str,
    /// What the forces (loads, reactions, contact forces, resultants) are per:
    /// `"unit thickness"` (N/m; plane strain and plane stress) or `"full revolution"` (N; a body
    /// of revolution: the ring forces of the whole circumference, `2π r` in every integral).
    pub forces: &'static str,
    /// Mesh nodes (P2 mid nodes included).
    pub nodes: usize,
    /// Mesh triangles.
    pub elements: usize,
    /// Boundary edges of the mesh.
    pub boundary_edges: usize,
    /// The primal dofs (2 per node) and those fixed by the supports; in a dual-only run the HCT
    /// dofs (3 per vertex, 1 per edge) and those set by the boundary conditions (the known
    /// tractions, the contact forces and the anchor: `dual.fixed_hct_dofs`).
    pub dofs: usize,
    /// The dofs fixed (see `dofs`).
    pub fixed_dofs: usize,
    /// MPI processes of the run.
    pub mpi_ranks: usize,
    /// Wall-clock seconds of each phase of the run (mesh, setup, assemble, solve, ...).
    pub timings: Timings,
    /// The mesh cache's part in getting a Gmsh mesh (absent for other meshes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mesh_cache: Option<CacheReport>,
    /// The main linear solver (or the contact route's solve) and the PETSc options.
    pub solver: SolverReport,
    /// Peak resident memory.
    pub memory: MemoryReport,
    /// The primal solution's results (absent for a dual-only run).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub results: Option<ResultsReport>,
    /// Physical group name -> tag (the `part_id` cell data of solution.vtu).
    pub parts: std::collections::BTreeMap<String, i32>,
    /// Contact: solver, iterations, statuses, resultants, the independent residuals.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactReport>,
    /// The dual (stress) solution: size, check, complementary energy.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dual: Option<DualReport>,
    /// The error in the constitutive relation (with `--estimate`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub estimate: Option<EstimateReport>,
    /// Several bodies: each body's equilibrium and each contact part's checks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bodies: Option<BodiesReport>,
    /// A load path: every increment (time, contact resultant, counts, iterations, worst
    /// residual, dissipation, energies); empty for a single static solve.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub steps: Vec<crate::evolution::StepRecord>,
    /// A load path: how it was solved, halvings, the energy balance.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub load_path: Option<crate::evolution::LoadPathSummary>,
    /// An interface law: the laws, the final interface, the worst law residual.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interface: Option<crate::report::interface::InterfaceReport>,
    /// Physics warnings (see `problem::warnings`): the answer is right for the model, the
    /// model may not be.
    pub warnings: Vec<Warning>,
}

#[derive(Debug, Clone, serde::Serialize)]
/// The linear solver's part of a [`Report`].
pub struct SolverReport {
    #[serde(flatten)]
    /// KSP and PC types, iterations, residual, converged reason (PETSc's statistics of the solve).
    pub stats: SolveStats,
    /// PETSc options from the scene that were applied (the command line overrides them).
    pub scene_options: Vec<String>,
    /// Options given but never used by PETSc: usually a typo.
    pub unused_options: Vec<String>,
}

#[derive(Debug, Clone, serde::Serialize)]
/// Peak memory of the run (read from the operating system; `None` where it cannot be read).
pub struct MemoryReport {
    /// Peak resident memory of rank 0, bytes.
    pub peak_bytes: Option<u64>,
    /// Sum over ranks of each rank's peak resident memory, bytes.
    pub peak_bytes_all_ranks: Option<u64>,
}

#[derive(Debug, Clone, serde::Serialize)]
/// The primal solution's summary: extremes, load and reaction resultants, the equilibrium check.
pub struct ResultsReport {
    /// Largest displacement magnitude |u| over the nodes (m).
    pub max_displacement: f64,
    /// Largest von Mises stress over the nodes (Pa).
    pub max_von_mises: f64,
    /// Applied load resultant (body force + tractions), N per unit thickness (N for the full
    /// revolution of a body of revolution: the radial component is then a sum of ring forces, not a balance).
    pub applied_force: [f64; 2],
    /// Reaction resultant on each Dirichlet part.
    pub reactions: std::collections::BTreeMap<String, [f64; 2]>,
    /// |applied + reactions + contact forces| / |applied| (global equilibrium, computed
    /// independently of the solver).
    pub equilibrium_residual: f64,
}

/// One problem being solved: a scene on a PETSc session, taken step by step. Make it with
/// [`ElasticityProblem::setup_system`] (mesh, material, conditions, contact points), then call
/// [`assemble`](Self::assemble), [`solve`](Self::solve), [`postprocess`](Self::postprocess), and
/// read the answer from its fields or [`report`](Self::report), or write the files with
/// [`write_output`](Self::write_output). A step called before the one it needs is an [`Error`] (the
/// state is held in the `Option` fields below, filled as the steps run). The module documentation
/// draws the whole pipeline.
pub struct ElasticityProblem<'s> {
    pub(crate) session: &'s Session,
    /// The scene, as checked by [`Scene::validated`] (for a scene with several bodies, as prepared
    /// for their union mesh).
    pub scene: Scene,
    /// The mesh solved on (for several bodies, their union, each body's nodes a contiguous range).
    pub mesh: Mesh,
    /// The material (the first body's, with several bodies: see `cell_materials`).
    pub material: Material,
    /// The material of every cell (one for a single body; one per body with several).
    pub cell_materials: CellMaterials,
    /// With several bodies: each body's mesh, ranges in [`ElasticityProblem::mesh`] (their
    /// union) and tables.
    pub bodies: Option<scene::BodiesModel>,
    /// The Dirichlet conditions: every fixed dof (2·node + component) and its value (m).
    pub constraints: Constraints,
    /// Global dof rows owned by this rank.
    pub rows: Range<usize>,
    /// Wall-clock seconds of each phase so far.
    pub timings: Timings,
    scene_options: Vec<String>,
    pub(crate) system: Option<(Matrix<'s>, Vector<'s>)>,
    /// The owned rows of K and f, kept in Rust for the full-space contact route (which builds
    /// its own mixed Jacobian instead of a PETSc K).
    full_space_system: Option<assembly::LinearSystem>,
    /// The linear solve's statistics, after [`solve`](Self::solve).
    pub stats: Option<SolveStats>,
    /// The whole displacement vector (dof = 2·node + component), on every rank.
    pub displacement: Option<Vec<f64>>,
    /// Stresses, von Mises and the summary of the solution, after
    /// [`postprocess`](Self::postprocess).
    pub results: Option<Results>,
    /// Several bodies: the checks of each body and contact part ([`ElasticityProblem::postprocess`]).
    pub bodies_report: Option<BodiesReport>,
    /// The contact's setup (contact points, their normals and weights, the obstacle or the pairs),
    /// for a scene with contact.
    pub contact: Option<ContactSetup>,
    /// The contact solution (forces, statuses, the solver's report), after [`solve`](Self::solve).
    pub contact_outcome: Option<ContactOutcome>,
    /// The dual solution, when solved ([`ElasticityProblem::solve_dual`]).
    pub dual: Option<DualOutcome>,
    /// The error estimate, when computed ([`ElasticityProblem::estimate`]).
    pub estimate: Option<EstimateReport>,
    /// Physics warnings so far.
    pub warnings: Vec<Warning>,
    /// The mesh cache's part in getting the mesh, for a Gmsh mesh of the scene.
    pub mesh_cache: Option<CacheReport>,
    /// Who is told the progress of the run ([`NoProgress`] unless set).
    pub(crate) progress: Box<dyn Progress>,
    /// Within a load path: the factors the scene's loads are multiplied by at the current
    /// increment (`None`: the loads as written).
    pub(crate) load_factors: Option<crate::evolution::LoadFactors>,
    /// Within a load path: what the contact law subtracts from the displacement at the current
    /// increment (the obstacle's motion, the slip so far), for the dual and the estimate.
    pub(crate) contact_shift: Option<crate::evolution::ContactShift>,
    /// After a load path: its increments, energies and profiles.
    pub load_path: Option<crate::evolution::LoadPathReport>,
    /// With an interface law: the interface at the end of the last solve (the last increment's
    /// on a load path).
    pub interface: Option<crate::interface_law::InterfaceSnapshot>,
    /// With an interface law on a load path: its summary and traced points at every increment
    /// recorded so far ([`ElasticityProblem::record_interface_step`]; interior mutability, as
    /// the driver's per-increment callback sees the problem by shared reference).
    pub(crate) interface_history: std::cell::RefCell<Option<crate::output::interface::InterfaceHistory>>,
}

/// Post-processed fields.
pub struct Results {
    /// Nodal stresses `[σxx, σyy, σxy]` (Pa), averaged from the cells around each node.
    pub nodal_stress: Vec<[f64; 3]>,
    /// Out-of-plane stress at the nodes (plane strain; 0 in plane stress).
    pub sigma_zz: Vec<f64>,
    /// Von Mises stress at the nodes (Pa), with σzz in plane strain.
    pub von_mises: Vec<f64>,
    /// The summary written to `report.json`.
    pub report: ResultsReport,
}

impl<'s> ElasticityProblem<'s> {
    /// Mesh, material, constraints, partition. Scene PETSc options enter the options database
    /// as defaults (the command line wins).
    pub fn setup_system(session: &'s Session, scene: Scene) -> Result<Self> {
        Self::setup_system_with_progress(session, scene, Box::new(NoProgress))
    }

    /// [`ElasticityProblem::setup_system`], telling `progress` about this and every later
    /// phase of the run.
    pub fn setup_system_with_progress(session: &'s Session, scene: Scene, progress: Box<dyn Progress>) -> Result<Self> {
        // Every scene gets the checks of a scene file, also one built in Rust.
        let scene = moved_obstacles(scene.validated()?);
        // Under MPI, a linear solver of one process is refused before the mesh is made.
        session.refuse_one_process_solver(&scene.petsc_options)?;
        let mut timings = Timings::default();
        // Rank 0 alone builds each mesh (Gmsh, the mesh cache, a file) and sends it to the
        // other ranks (agreed: a failure there stops every rank); with several bodies every
        // rank then places and unites the bodies' meshes (agreed too).
        if scene.has_body_tables() {
            let model = progress::in_phase(&*progress, Phase::Mesh, || {
                timings.time("mesh", || {
                    let meshes = scene
                        .bodies()
                        .iter()
                        .map(|body| {
                            mesh::shared::from_rank_0(session, "building the meshes", || {
                                mesh::build::build(&body.mesh, body.order).map(|(mesh, order, _)| (mesh, order))
                            })
                            .map(|(mesh, _)| mesh)
                        })
                        .collect::<Result<Vec<_>>>()?;
                    session.agree(scene::BodiesModel::on_meshes(&scene, meshes), "building the meshes")
                })
            })?;
            return Self::setup_on_bodies(session, scene, model, timings, progress);
        }
        // Its cache report is rank 0's.
        let mut mesh_cache = None;
        let (mesh, file_order) = progress::in_phase(&*progress, Phase::Mesh, || {
            timings.time("mesh", || {
                mesh::shared::from_rank_0(session, "building the mesh", || {
                    let (mesh, file_order, cache) = build_mesh(&scene)?;
                    mesh_cache = cache;
                    Ok((mesh, file_order))
                })
            })
        })?;
        let mut problem = Self::setup_on_mesh(session, scene, mesh, file_order, timings, progress)?;
        problem.mesh_cache = mesh_cache;
        Ok(problem)
    }

    /// [`ElasticityProblem::setup_system`] on a mesh made elsewhere (a remeshed one, in mesh
    /// adaptation, or a level of a convergence study): the mesh must carry the scene's
    /// boundary parts and be of the scene's order.
    pub fn setup_with_mesh(session: &'s Session, scene: Scene, mesh: Mesh) -> Result<Self> {
        let scene = moved_obstacles(scene.validated()?);
        refuse_several_bodies(&scene)?;
        session.refuse_one_process_solver(&scene.petsc_options)?;
        Self::setup_on_mesh(session, scene, mesh, None, Timings::default(), Box::new(NoProgress))
    }

    fn setup_on_mesh(
        session: &'s Session,
        scene: Scene,
        mesh: Mesh,
        file_order: Option<Order>,
        mut timings: Timings,
        progress: Box<dyn Progress>,
    ) -> Result<Self> {
        let mut mesh = consistent_across_ranks(session, mesh)?;
        let material = bodies::material_of(&scene.material);
        let mesh_file = match &scene.mesh {
            crate::scene::MeshSpec::File { path, .. } => Some(path.clone()),
            _ => None,
        };
        axisymmetry::prepare_mesh(&mut mesh, material.plane, mesh_file.as_deref())?;
        axisymmetry::refuse_interface_laws(&scene)?;
        scene.check_against_mesh(&mesh)?;
        scene.check_magnitudes(&mesh)?;
        let start = std::time::Instant::now();
        let mut constraints = Constraints::new(2 * mesh.num_nodes());
        for d in &scene.dirichlet {
            for node in d.nodes(&mesh)? {
                if let Some(ux) = d.ux {
                    constraints.fix(2 * node, ux);
                }
                if let Some(uy) = d.uy {
                    constraints.fix(2 * node + 1, uy);
                }
            }
        }
        axisymmetry::fix_axis(&mesh, &mut constraints)?;
        check_every_piece_is_held(&mesh, &scene, &constraints)?;
        let free_motions = constraints.check_rigid_motions(&mesh).err();
        let contact = match &scene.contact {
            Some(spec) => {
                let prescribed = |node: usize| [constraints.value(2 * node), constraints.value(2 * node + 1)];
                Some(ContactSetup::new(&mesh, spec, &prescribed, free_motions.map(|e| e.to_string()))?)
            }
            None => match free_motions {
                Some(e) => return Err(e),
                None => None,
            },
        };
        timings.add("setup", start.elapsed().as_secs_f64());
        let cell_materials = CellMaterials::uniform(material);
        Self::from_parts(
            session,
            scene,
            mesh,
            (material, cell_materials, None),
            constraints,
            contact,
            file_order,
            timings,
            progress,
        )
    }

    /// [`ElasticityProblem::setup_system`] for a scene with several bodies, on their model.
    fn setup_on_bodies(
        session: &'s Session,
        scene: Scene,
        model: scene::BodiesModel,
        mut timings: Timings,
        progress: Box<dyn Progress>,
    ) -> Result<Self> {
        let start = std::time::Instant::now();
        let setup = bodies::setup_bodies(scene, model)?;
        let mesh = consistent_across_ranks(session, setup.mesh)?;
        timings.add("setup", start.elapsed().as_secs_f64());
        let mut problem = Self::from_parts(
            session,
            setup.scene,
            mesh,
            (setup.material, setup.cell_materials, Some(setup.model)),
            setup.constraints,
            setup.contact,
            None,
            timings,
            progress,
        )?;
        problem.warnings.extend(setup.warnings);
        Ok(problem)
    }

    #[allow(clippy::too_many_arguments)]
    fn from_parts(
        session: &'s Session,
        scene: Scene,
        mesh: Mesh,
        (material, cell_materials, bodies): (Material, CellMaterials, Option<scene::BodiesModel>),
        constraints: Constraints,
        contact: Option<ContactSetup>,
        file_order: Option<Order>,
        timings: Timings,
        progress: Box<dyn Progress>,
    ) -> Result<Self> {
        let initial_warnings =
            crate::report::warnings::before_solving(&mesh, scene.element, material.poisson, material.plane, file_order);
        let scene_options = session.insert_default_options(&scene.petsc_options)?;
        let rows = dof_ranges(mesh.num_nodes(), session.size())[session.rank()].clone();
        let mut contact = contact;
        if let Some(c) = contact.as_mut() {
            c.attach_interface(material.plane)?;
        }
        Ok(ElasticityProblem {
            session,
            scene,
            mesh,
            material,
            cell_materials,
            bodies,
            constraints,
            rows,
            timings,
            scene_options,
            system: None,
            full_space_system: None,
            stats: None,
            displacement: None,
            results: None,
            bodies_report: None,
            contact,
            contact_outcome: None,
            dual: None,
            estimate: None,
            warnings: initial_warnings,
            mesh_cache: None,
            progress,
            load_factors: None,
            contact_shift: None,
            load_path: None,
            interface: None,
            interface_history: std::cell::RefCell::new(None),
        })
    }

    /// Tell `progress` about the following phases of the run (replaces the observer).
    pub fn set_progress(&mut self, progress: Box<dyn Progress>) {
        self.progress = progress;
    }

    /// The observer of the run's progress.
    pub fn progress(&self) -> &dyn Progress {
        &*self.progress
    }

    /// The number of displacement unknowns: 2 per node.
    pub fn num_dofs(&self) -> usize {
        2 * self.mesh.num_nodes()
    }

    fn loads(&self) -> Result<(Option<[f64; 2]>, Vec<(usize, Traction<'static>)>)> {
        let factors = self.load_factors.as_ref();
        let body_factor = factors.map_or(1.0, |f| f.body_force);
        let body = self.scene.body_force.map(|b| body_factor * b);
        let body = if body == [0.0, 0.0] { None } else { Some(body) };
        let mut edge = Vec::new();
        for (k, t) in self.scene.tractions.iter().enumerate() {
            let g = self.mesh.require_group(&t.part, 1)?;
            let factor = factors.map_or(1.0, |f| f.traction[k]);
            let traction = match t.load {
                scene::Load::Traction(v) => Traction::Constant(v.map(|x| factor * x)),
                scene::Load::Pressure(p) => Traction::Pressure(factor * p),
            };
            edge.push((g, traction));
        }
        Ok((body, edge))
    }

    /// Run `f` with the scene's loads (body force and edge tractions) as `fem` loads.
    pub(crate) fn with_loads<T>(&self, f: impl FnOnce(&Loads) -> T) -> Result<T> {
        let (body, edge) = self.loads()?;
        let body_fn = body.map(|b| move |_x: [f64; 2]| b);
        let loads = Loads {
            body_force: body_fn.as_ref().map(|f| f as &(dyn Fn([f64; 2]) -> [f64; 2] + Sync)),
            edge_loads: edge.into_iter().map(|(group, traction)| EdgeLoad { group, traction }).collect(),
        };
        Ok(f(&loads))
    }

    /// Assemble this rank's rows of the stiffness matrix and load vector into PETSc objects.
    pub fn assemble(&mut self) -> Result<()> {
        self.progress.phase_started(Phase::Assemble);
        let start = std::time::Instant::now();
        let mut system = self.with_loads(|loads| {
            let element = self.scene.element;
            assembly::assemble_cells(
                &self.mesh,
                &self.cell_materials,
                element,
                &self.constraints,
                loads,
                self.rows.clone(),
            )
        })?;
        if let Some(contact) = self.contact.as_mut().filter(|c| c.spec.solver == ContactSolverSpec::FullSpaceNewton) {
            // The full-space route keeps K unmodified (its springs live in the Jacobian only,
            // and only while the contact does not hold the body) and builds its own matrix.
            let m = &system.matrix;
            let max_diag =
                (0..m.num_rows()).map(|r| m.get(m.first_row + r, m.first_row + r).abs()).fold(0.0f64, f64::max);
            contact.set_stabilisation(self.session.world().max(&[max_diag])?[0]);
            self.full_space_system = Some(system);
            self.timings.add("assemble", start.elapsed().as_secs_f64());
            self.progress.phase_finished(Phase::Assemble, start.elapsed().as_secs_f64());
            return Ok(());
        }
        if let Some(contact) = &mut self.contact {
            let m = &mut system.matrix;
            // The springs (after their one reduction) and the rotation check this rank's rows:
            // agreed before the matrix (collective) is built.
            let prepared =
                contact.add_springs(self.session, m.first_row, &m.indptr, &m.indices, &mut m.values).and_then(|()| {
                    if contact.spec.solver != ContactSolverSpec::SnesVi {
                        return Ok(());
                    }
                    let n = self.mesh.num_nodes();
                    contact.rotate_to_frames(n, m.first_row, &m.indptr, &m.indices, &mut m.values, &mut system.rhs)
                });
            self.session.agree(prepared, "preparing the contact rows")?;
        }
        self.system = Some(self.to_petsc(&system)?);
        self.timings.add("assemble", start.elapsed().as_secs_f64());
        self.progress.phase_finished(Phase::Assemble, start.elapsed().as_secs_f64());
        Ok(())
    }

    /// Solve the linear system with the KSP configured by the options database.
    pub fn solve(&mut self) -> Result<()> {
        self.progress.phase_started(Phase::Solve);
        let start = std::time::Instant::now();
        if let (Some(contact), Some(system)) = (&self.contact, &self.full_space_system) {
            let ranges = dof_ranges(self.mesh.num_nodes(), self.session.size());
            let (u, outcome, mut stats) = contact.solve_full_space(
                self.session,
                &self.mesh,
                &self.cell_materials,
                &self.constraints,
                system,
                &ranges,
                &*self.progress,
            )?;
            stats.seconds = start.elapsed().as_secs_f64();
            self.stats = Some(stats);
            self.check_contact_equilibrium(&outcome)?;
            self.displacement = Some(u);
            self.contact_outcome = Some(outcome);
            self.timings.add("solve", start.elapsed().as_secs_f64());
            self.progress.phase_finished(Phase::Solve, start.elapsed().as_secs_f64());
            return Ok(());
        }
        let (matrix, rhs) = self.system.as_ref().ok_or(Error::CallOrder { call: "solve()", needs: "assemble()" })?;
        let mut ksp = LinearSolver::new(self.session, self.session.world(), "")?;
        ksp.set_operator(matrix)?;
        if let Some(contact) = self.contact.as_ref().filter(|c| c.spec.solver == ContactSolverSpec::SnesVi) {
            let (u, outcome) = contact.solve_vi(self.session, matrix, rhs)?;
            self.stats = Some(crate::petsc::SolveStats {
                ksp_type: "snes vinewtonrsls".into(),
                pc_type: "lu".into(),
                factor_package: Some("mumps".into()),
                iterations: outcome.report.iterations,
                converged_reason: outcome.report.notes.join("; "),
                relative_residual: 0.0,
                seconds: start.elapsed().as_secs_f64(),
            });
            self.check_contact_equilibrium(&outcome)?;
            self.displacement = Some(u);
            self.contact_outcome = Some(outcome);
        } else if let Some(contact) = self.contact.as_ref().filter(|c| c.interface.is_some()) {
            let (u, outcome, stats, step) =
                contact.solve_with_interface(self.session, matrix, rhs, &mut ksp, &*self.progress)?;
            self.stats = Some(stats.ok_or_else(|| Error::PetscUsage("no linear solve recorded".into()))?);
            self.check_contact_equilibrium(&outcome)?;
            self.interface = contact.interface.as_ref().map(|laws| {
                let positions: Vec<[f64; 2]> = contact.boundary.nodes.iter().map(|&k| self.mesh.nodes[k]).collect();
                laws.snapshot(&positions, &step, 1.0)
            });
            self.displacement = Some(u);
            self.contact_outcome = Some(outcome);
        } else if let Some(contact) = &self.contact {
            let (u, outcome, stats) = contact.solve(self.session, matrix, rhs, &mut ksp, &*self.progress)?;
            self.stats = Some(stats.ok_or_else(|| Error::PetscUsage("no linear solve recorded".into()))?);
            self.check_contact_equilibrium(&outcome)?;
            self.displacement = Some(u);
            self.contact_outcome = Some(outcome);
        } else {
            let mut x = matrix.create_vector()?;
            let stats = ksp.solve(matrix, rhs, &mut x)?;
            self.displacement = Some(x.gather_all()?);
            self.stats = Some(stats);
        }
        self.timings.add("solve", start.elapsed().as_secs_f64());
        self.progress.phase_finished(Phase::Solve, start.elapsed().as_secs_f64());
        Ok(())
    }

    /// A body held by contact (stabilisation springs added): it must not lift off, and the
    /// springs must carry nothing of the load.
    pub(crate) fn check_contact_equilibrium(&self, outcome: &ContactOutcome) -> Result<()> {
        let contact = match &self.contact {
            Some(c) if c.spring.is_some() => c,
            _ => return Ok(()),
        };
        let free = contact.free_motions.clone().unwrap_or_default();
        if outcome.report.open == outcome.report.points {
            return Err(contact.lift_off(&self.mesh, &free));
        }
        let f = self.with_loads(|loads| assembly::load_vector(&self.mesh, loads))?;
        let applied = [f.iter().step_by(2).sum::<f64>(), f.iter().skip(1).step_by(2).sum::<f64>()];
        let scale = applied[0].hypot(applied[1]).max(outcome.report.resultant[0].hypot(outcome.report.resultant[1]));
        let spring = outcome.report.stabilisation_force;
        if spring[0].hypot(spring[1]) > crate::contact_routes::condensed_route::EQUILIBRIUM_TOLERANCE * scale {
            let r = &outcome.report;
            return Err(Error::NoEquilibrium(format!(
                "no static equilibrium: the loads ({:.4e}, {:.4e}) are not balanced by the contact forces ({:.4e}, {:.4e}) and the supports ({free}); the body slides or moves away (normal contact force {:.4e}, tangential {:.4e}, friction {})",
                applied[0], applied[1], r.resultant[0], r.resultant[1], r.normal_resultant, r.tangential_resultant, r.friction
            )));
        }
        Ok(())
    }

    /// This rank's rows of a CSR system as a PETSc matrix (SPD, block size 2) and vector.
    fn to_petsc(&self, system: &assembly::LinearSystem) -> Result<(Matrix<'s>, Vector<'s>)> {
        let m = &system.matrix;
        let matrix = Matrix::from_csr_rows(
            self.session,
            self.session.world(),
            self.num_dofs(),
            m.first_row,
            &m.indptr,
            &m.indices,
            &m.values,
            2,
            true,
        )?;
        let mut rhs = matrix.create_vector()?;
        rhs.set_owned(&system.rhs)?;
        Ok((matrix, rhs))
    }

    /// Time one plain linear solve of the assembled system with the default-configured KSP
    /// (factorisation included): the yardstick the contact benchmark divides by.
    pub fn linear_solve_seconds(&self) -> Result<f64> {
        // The full-space route keeps K as CSR rows only: build the PETSc matrix for the timing.
        let built;
        let (matrix, rhs) = match (&self.system, &self.full_space_system) {
            (Some((m, b)), _) => (m, b),
            (None, Some(system)) => {
                // A body held by the contact: K with the stabilisation springs, as the
                // condensed route factorises it (K alone is singular).
                let mut system = system.clone();
                if let Some((contact, k)) = self.contact.as_ref().and_then(|c| c.spring.map(|k| (c, k))) {
                    let m = &mut system.matrix;
                    contact.add_spring_values(k, m.first_row, &m.indptr, &m.indices, &mut m.values)?;
                }
                built = self.to_petsc(&system)?;
                (&built.0, &built.1)
            }
            _ => return Err(Error::CallOrder { call: "linear_solve_seconds()", needs: "assemble()" }),
        };
        let start = std::time::Instant::now();
        let mut ksp = LinearSolver::new(self.session, self.session.world(), "")?;
        ksp.set_operator(matrix)?;
        let mut x = matrix.create_vector()?;
        ksp.solve(matrix, rhs, &mut x)?;
        Ok(start.elapsed().as_secs_f64())
    }

    /// Build the report (collective: every rank must call it).
    pub fn report(&self) -> Result<Report> {
        let dual_only = self.displacement.is_none() && self.dual.is_some();
        let stats = match (&self.stats, &self.dual) {
            (Some(s), _) => s.clone(),
            (None, Some(d)) => d.report.solver.clone(),
            (None, None) => return Err(Error::CallOrder { call: "report()", needs: "solve()" }),
        };
        let results = match &self.results {
            Some(r) => Some(r.report.clone()),
            None if dual_only => None,
            None => return Err(Error::CallOrder { call: "report()", needs: "postprocess()" }),
        };
        let peak = resources::peak_memory_bytes();
        let all = self.session.world().sum(&[peak.unwrap_or(0) as f64])?[0];
        let unused_options = self.session.unused_options()?;
        let route = crate::report::option_warnings::OptionRoute {
            contact_solver: self.contact.as_ref().map(|c| c.spec.solver.scene_name()),
            primal: self.displacement.is_some(),
            dual: self.dual.is_some(),
        };
        let mut warnings = self.warnings.clone();
        warnings.extend(crate::report::option_warnings::unused_option_warnings(&unused_options, route));
        let parts = self.mesh.groups.iter().map(|g| (g.name.clone(), g.tag)).collect();
        Ok(Report {
            bodies: self.bodies_report.clone(),
            program: format!("signorini {} ({})", env!("CARGO_PKG_VERSION"), env!("SIGNORINI_COMMIT")),
            scene: self.scene.source.display().to_string(),
            title: self.scene.title.clone(),
            formulation: if dual_only { "dual" } else { "primal" },
            element: if dual_only { "HCT" } else { self.scene.element.report_name(self.mesh.order) },
            plane: self.material.plane.name(),
            forces: self.mesh.measure.forces_per(),
            nodes: self.mesh.num_nodes(),
            elements: self.mesh.num_cells(),
            boundary_edges: self.mesh.num_edges(),
            // A dual-only run counts the HCT dofs, and those the boundary conditions set.
            dofs: if dual_only { self.dual.as_ref().map_or(0, |d| d.report.hct_dofs) } else { self.num_dofs() },
            fixed_dofs: if dual_only {
                self.dual.as_ref().map_or(0, |d| d.report.fixed_hct_dofs)
            } else {
                self.constraints.num_fixed()
            },
            mpi_ranks: self.session.size(),
            timings: self.timings.clone(),
            mesh_cache: self.mesh_cache.clone(),
            solver: SolverReport { stats, scene_options: self.scene_options.clone(), unused_options },
            memory: MemoryReport { peak_bytes: peak, peak_bytes_all_ranks: peak.map(|_| all as u64) },
            results,
            parts,
            // A dual-only run reports its own contact solution here, like the primal's.
            contact: self
                .contact_outcome
                .as_ref()
                .map(|o| o.report.clone())
                .or_else(|| self.dual.as_ref().and_then(|d| d.contact.as_ref()).map(|c| c.report.clone())),
            dual: self.dual.as_ref().map(|d| d.report.clone()),
            // The error next to the whole run's time (output included, as far as it went).
            estimate: self.estimate.clone().map(|mut e| {
                e.run_seconds = self.timings.total();
                e
            }),
            steps: self.load_path.as_ref().map(|l| l.steps.clone()).unwrap_or_default(),
            load_path: self.load_path.as_ref().map(crate::evolution::LoadPathSummary::of),
            interface: self.interface_report(),
            warnings,
        })
    }
}

/// A scene solved once (no `[evolution]`) takes its obstacles where their `motion` puts them
/// (in full); a load path moves them itself, increment by increment.
fn moved_obstacles(mut scene: Scene) -> Scene {
    if scene.evolution.is_some() {
        return scene;
    }
    let mut contacts: Vec<&mut scene::ContactSpec> = scene.contact.iter_mut().collect();
    contacts.extend(scene.bodies.iter_mut().filter_map(|b| b.contact.as_mut()));
    for c in contacts {
        if c.motion.is_some() {
            c.obstacle = c.obstacle_at(1.0);
            c.motion = None;
        }
    }
    scene
}

/// Every connected piece of the mesh must be held by a Dirichlet condition or a contact part:
/// a loose piece would float away (its displacement is undetermined).
fn check_every_piece_is_held(mesh: &Mesh, scene: &Scene, constraints: &Constraints) -> Result<()> {
    let pieces = mesh::pieces::node_pieces(mesh);
    let count = pieces.1;
    if count < 2 {
        return Ok(());
    }
    let group = scene.contact.as_ref().and_then(|c| mesh.group_index(&c.part, 1));
    let contact_nodes =
        group.into_iter().flat_map(|g| mesh.edges_in_group(g).flat_map(|e| mesh.edge(e).iter().copied()));
    if let Some(LoosePiece { piece: p, nodes, first }) = first_loose_piece(mesh, &pieces, constraints, contact_nodes) {
        let x = mesh.nodes[first];
        return Err(Error::Unconstrained(format!(
            "the mesh has {count} separate pieces, and piece {} ({nodes} nodes, e.g. node {first} at ({:?}, {:?})) is held \
             by nothing: no Dirichlet condition and no contact part touches it, so it would float away; hold it with a \
             [[dirichlet]] condition or a contact part, or remove it from the mesh",
            p + 1,
            x[0],
            x[1]
        )));
    }
    Ok(())
}

/// A connected piece of a mesh that nothing holds: its index, its number of nodes, its first node.
pub(super) struct LoosePiece {
    pub piece: usize,
    pub nodes: usize,
    pub first: usize,
}

/// The first connected piece of `mesh` (its `node_pieces`) that has no node with a prescribed
/// component and none among `holding_nodes` (the nodes a contact touches), if any.
pub(super) fn first_loose_piece(
    mesh: &Mesh,
    (pieces, count): &(Vec<usize>, usize),
    constraints: &Constraints,
    holding_nodes: impl Iterator<Item = usize>,
) -> Option<LoosePiece> {
    let mut held = vec![false; *count];
    for k in 0..mesh.num_nodes() {
        if constraints.is_fixed(2 * k) || constraints.is_fixed(2 * k + 1) {
            held[pieces[k]] = true;
        }
    }
    for k in holding_nodes {
        held[pieces[k]] = true;
    }
    let piece = held.iter().position(|h| !h)?;
    let nodes = pieces.iter().filter(|&&q| q == piece).count();
    let first = pieces.iter().position(|&q| q == piece).unwrap_or(0);
    Some(LoosePiece { piece, nodes, first })
}

/// A scene with `[[body]]` tables is meshed and checked (every mistake in it is reported), then
/// refused with [`Error::SeveralBodiesNotSolved`]: the single-body fields the solver reads hold
/// only its first body.
pub fn refuse_several_bodies(scene: &Scene) -> Result<()> {
    if !scene.has_body_tables() {
        return Ok(());
    }
    scene::BodiesModel::build(scene)?;
    Err(Error::SeveralBodiesNotSolved {
        scene: scene.source.clone(),
        bodies: scene.bodies.len(),
        pairs: scene.contact_pairs.len(),
    })
}

/// The scene's mesh: generated (structured or Gmsh) or read from a file, at the scene's order;
/// the order of the file's triangles when it was read from one; and for a Gmsh mesh what the
/// mesh cache did ([`crate::mesh::cache::MeshCache::from_env`]: on unless `SIGNORINI_NO_MESH_CACHE` is set).
pub fn build_mesh(scene: &Scene) -> Result<(Mesh, Option<Order>, Option<CacheReport>)> {
    mesh::build::build(&scene.mesh, scene.order)
}

/// Make sure every rank holds the same mesh (rank 0's, sent by [`mesh::shared::from_rank_0`];
/// with several bodies, the union each rank made of those: a mismatch would give silently
/// wrong answers).
fn consistent_across_ranks(session: &Session, mesh: Mesh) -> Result<Mesh> {
    if session.size() == 1 {
        return Ok(mesh);
    }
    let fingerprint = [
        mesh.num_nodes() as f64,
        mesh.num_cells() as f64,
        mesh.num_edges() as f64,
        mesh.nodes.iter().map(|p| p[0] + 2.0 * p[1]).sum::<f64>(),
    ];
    let lo = session.world().min(&fingerprint)?;
    let hi = session.world().max(&fingerprint)?;
    if lo != hi {
        return Err(Error::mesh(
            "mesh",
            "the MPI ranks built different meshes (node or cell counts differ): use a mesh file so every rank reads the same mesh",
        ));
    }
    Ok(mesh)
}
