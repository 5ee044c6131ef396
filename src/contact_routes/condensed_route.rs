//! Contact with a rigid obstacle in the primal formulation: the driver's part for the
//! condensed solvers (`solver = "newton"`, `"relaxation"`, ...), SNESVI and TAO. The default,
//! the full-space semi-smooth Newton (`"newton_full"`), is in `full_space/`; it falls back
//! to the condensed route here.
//!
//! ```text
//! setup     contact points on the scene's part (ContactBoundary: nodes, frames n/t, gaps,
//!           consistent weights); nodes with a Dirichlet component are left out
//! assemble  K (+ a stabilisation spring at the contact nodes only when Dirichlet conditions
//!           leave a rigid motion free, see below), f
//! condense  u_free = B K⁻¹ f;  W = B K⁻¹ Bᵀ — on one process with the default linear
//!           solver from one MUMPS factorisation with the Schur complement S on the contact
//!           dofs, (K⁻¹)_cc = S⁻¹ (`petsc::schur`); otherwise (MPI, any -ksp_type/-pc_type, or
//!           `-contact_condense_schur false`) by one solve per contact unknown with the
//!           configured KSP (2m solves; m without friction: the tangential block is not
//!           computed)
//! solve     the condensed problem with the scene's solver
//! recover   u = K⁻¹ (f + Bᵀ r) by one more solve
//! verify    residuals of (r, B u) — u from the field solve, not from W — and equilibrium
//! ```
//!
//! ## Bodies held by contact
//! A body held only by the obstacle (Hertz, force-driven; the stick patch test held sideways by
//! friction alone) has a singular K. When the Dirichlet conditions leave a rigid motion free,
//! springs `S = k I` are added at the contact nodes, with `k = 1e-3 · max diag(K) / m` (derived
//! from the matrix, not a user parameter), and anchored at the previous iterate: proximal-point
//! iterations `(K + S) u⁺ = f + S u + Bᵀ r⁺` with the contact law on `r⁺`. `W` and the
//! factorisation do not change (two solves per iteration); at convergence the spring force
//! `−S (u⁺ − u)` vanishes and `u` solves the original problem exactly (Rockafellar's proximal
//! point method; the error in the free rigid motions contracts by `S/(S + K_contact)` per
//! iteration). A body with no static equilibrium — lifting off, or sliding because friction
//! cannot hold the tangential load — never converges: its spring force stays, the run stops
//! and says why (`stabilisation_force` in the report).
use nalgebra::DMatrix;

use crate::contact::boundary::ContactBoundary;
use crate::contact::obstacle::Obstacle;
use crate::contact::{self, CondensedProblem, Delassus, FrictionLaw, PointStatus, SolverSettings};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::petsc::schur::SchurFactor;
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats, Vector};
use crate::scene::{ContactSolverSpec, ContactSpec, FrictionSpec, ObstacleSpec};

pub(crate) use super::condensation::{condensed_solver, tao_box_qp, Factorised};
use super::condensation::{flexibility_from_schur, schur_dofs};
pub use crate::report::contact::{ContactOutcome, ContactReport};

/// Total stiffness of the stabilisation springs relative to the largest diagonal entry of K
/// (shared among the contact nodes). Small enough that the proximal iterations converge fast,
/// large enough that K + S stays well conditioned.
pub const STABILISATION: f64 = 1e-3;
/// A stabilisation force above this fraction of the applied load means no static equilibrium.
pub const EQUILIBRIUM_TOLERANCE: f64 = 1e-6;

/// The contact of a problem before its solve: the scene's contact and its contact points.
pub struct ContactSetup {
    /// The scene's `[contact]` (with several bodies, the first contact part's, see `parts`).
    pub spec: ContactSpec,
    /// The contact points: nodes, normals, weights and initial gaps.
    pub boundary: ContactBoundary,
    /// Stiffness of the stabilisation springs, when a rigid motion is not held by Dirichlet.
    pub spring: Option<f64>,
    /// Which rigid motions Dirichlet leaves free (the Unconstrained message), if any.
    pub free_motions: Option<String>,
    /// The dofs the stabilisation springs act on: the free dofs of the nodes `B` touches.
    pub spring_dofs: Vec<usize>,
    /// With several bodies: the contact parts (pairs and rigid obstacles) the points come from,
    /// each with its friction law; `None` for one body (its friction is `spec.friction`).
    pub parts: Option<crate::problem::bodies::ContactParts>,
    /// The interface laws of the contact's points, when the scene has some
    /// ([`crate::interface_law::staggered`]).
    pub interface: Option<crate::interface_law::staggered::InterfaceLaws>,
}

pub fn obstacle_of(spec: &ObstacleSpec) -> Result<Obstacle> {
    Ok(match spec {
        ObstacleSpec::Line { point, normal } => Obstacle::new_line(*point, *normal)?,
        ObstacleSpec::Circle { center, radius } => Obstacle::new_circle(*center, *radius)?,
        ObstacleSpec::Polyline { points } => Obstacle::new_polyline(points.clone())?,
    })
}

/// The obstacle in words, for messages: the line's point and normal, the disc, the polyline.
pub fn obstacle_text(spec: &ObstacleSpec) -> String {
    match spec {
        ObstacleSpec::Line { point, normal } => format!(
            "the line through ({}, {}) with normal ({}, {})",
            number(point[0]),
            number(point[1]),
            number(normal[0]),
            number(normal[1])
        ),
        ObstacleSpec::Circle { center, radius } => {
            format!(
                "the rigid disc of centre ({}, {}) and radius {}",
                number(center[0]),
                number(center[1]),
                number(*radius)
            )
        }
        ObstacleSpec::Polyline { points } => {
            format!("the polyline of {} points from ({}, {})", points.len(), number(points[0][0]), number(points[0][1]))
        }
    }
}

/// A number for a message: shortest form, no negative zero.
fn number(x: f64) -> String {
    format!("{}", x + 0.0)
}

/// Does the body (its node positions `nodes`) lie inside the obstacle's rigid region? When
/// more than half of its nodes are inside it by more than 1e-6 of the body's size: what is
/// wrong and what to do (a normal pointing the wrong way puts the body there while its contact
/// part still touches the line).
pub fn wrong_side(spec: &ObstacleSpec, nodes: &[[f64; 2]]) -> Option<(String, String)> {
    let obstacle = obstacle_of(spec).ok()?;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in nodes {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    let size = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let depths: Vec<f64> =
        nodes.iter().map(|&p| -obstacle.project(p).signed_distance).filter(|&d| d > 1e-6 * size).collect();
    if nodes.is_empty() || 2 * depths.len() <= nodes.len() {
        return None;
    }
    let deepest = depths.iter().cloned().fold(0.0, f64::max);
    let (where_, hint) = match spec {
        ObstacleSpec::Line { normal, .. } => (
            "behind the line, in the obstacle's half-plane",
            format!(
                "the normal points from the obstacle towards the body: reverse it (normal = [{}, {}])",
                number(-normal[0]),
                number(-normal[1])
            ),
        ),
        ObstacleSpec::Circle { .. } => (
            "inside the rigid disc",
            "a circle obstacle is a rigid disc with the body outside it: move the disc or the body".to_string(),
        ),
        ObstacleSpec::Polyline { .. } => (
            "on the right of the polyline, in the obstacle",
            "the body must lie on the left of the polyline's direction of travel: reverse the order of its points"
                .to_string(),
        ),
    };
    let what = format!(
        "the body lies {where_} ({} of its {} nodes are inside it, up to {deepest:.3e} deep)",
        depths.len(),
        nodes.len()
    );
    Some((what, hint))
}

impl ContactSetup {
    /// The contact points of `spec` on `mesh`; `prescribed(node)` gives the Dirichlet values of a
    /// node (a node with both prescribed is left out); `free_motions` are the rigid motions
    /// Dirichlet leaves free, if any.
    pub fn new(
        mesh: &Mesh,
        spec: &ContactSpec,
        prescribed: &dyn Fn(usize) -> [Option<f64>; 2],
        free_motions: Option<String>,
    ) -> Result<Self> {
        let group = mesh.require_group(&spec.part, 1)?;
        let obstacle = obstacle_of(&spec.obstacle)?;
        let boundary = ContactBoundary::with_prescribed(mesh, group, &obstacle, spec.gap, prescribed)?;
        let spring_dofs = spring_dofs(&boundary, prescribed);
        Ok(ContactSetup {
            spec: spec.clone(),
            boundary,
            spring: None,
            free_motions,
            spring_dofs,
            parts: None,
            interface: None,
        })
    }

    /// Why a body that the contact should hold has no closed point, when its position says
    /// why: it lies inside the obstacle ([`wrong_side`]). Only for one body on one obstacle
    /// (`mesh` is then the body's).
    pub(super) fn wrong_side_of(&self, mesh: &Mesh) -> Option<(String, String)> {
        let one_obstacle = match &self.parts {
            None => true,
            Some(parts) => parts.parts.len() == 1 && parts.parts[0].master.is_none(),
        };
        if !one_obstacle {
            return None;
        }
        wrong_side(&self.spec.obstacle, &mesh.nodes)
    }

    /// The error of a body that lifts off with nothing else to hold it (`free`: the rigid
    /// motions the Dirichlet conditions leave free); when the body lies inside the obstacle,
    /// that is what the error says (a scene whose geometry contradicts it).
    pub(crate) fn lift_off(&self, mesh: &Mesh, free: &str) -> Error {
        let part = &self.spec.part;
        match self.wrong_side_of(mesh) {
            Some((what, hint)) => Error::Formulation {
                message: format!(
                    "no contact point of '{part}' closes and nothing else holds the body: {what}, against {}",
                    obstacle_text(&self.spec.obstacle)
                ),
                hint,
            },
            None => Error::Unconstrained(format!(
                "the body lifts off the obstacle (no contact point of '{part}' is closed) and nothing else holds it: \
                 {free}; add a Dirichlet condition or change the loads"
            )),
        }
    }

    /// The friction law of point `i`.
    fn point_friction(&self, i: usize) -> FrictionSpec {
        match &self.parts {
            Some(parts) => parts.friction_of_point(i),
            None => self.spec.friction,
        }
    }

    /// Has point `i` a friction law (else its closed state is `closed`, not stick or slip)?
    pub fn frictional_points(&self) -> Vec<bool> {
        (0..self.boundary.points()).map(|i| self.point_friction(i) != FrictionSpec::None).collect()
    }

    /// The friction law of every point, for the contact solvers.
    pub fn friction_law(&self) -> FrictionLaw {
        let m = self.boundary.points();
        // The law of the whole problem: Coulomb or Tresca if some point has it (several bodies
        // mix them only with frictionless parts, ContactParts checks that), else none.
        let laws: Vec<FrictionSpec> = (0..m).map(|i| self.point_friction(i)).collect();
        let coulomb = laws.iter().any(|l| matches!(l, FrictionSpec::Coulomb { .. }));
        let tresca = laws.iter().any(|l| matches!(l, FrictionSpec::Tresca { .. }));
        // A point with a prescribed component gets no friction: its support carries the
        // tangential force (ContactBoundary module documentation).
        let free = |i: usize| self.boundary.prescribed[i].is_none();
        if coulomb {
            FrictionLaw::Coulomb {
                mu: (0..m)
                    .map(|i| match laws[i] {
                        FrictionSpec::Coulomb { mu } if free(i) => mu,
                        _ => 0.0,
                    })
                    .collect(),
            }
        } else if tresca {
            // The threshold is a traction (Pa = N/m²); the per-point force threshold is g·w_i (N/m).
            FrictionLaw::Tresca {
                threshold: (0..m)
                    .map(|i| match laws[i] {
                        FrictionSpec::Tresca { threshold } if free(i) => threshold * self.boundary.weight[i],
                        _ => 0.0,
                    })
                    .collect(),
            }
        } else {
            FrictionLaw::None
        }
    }

    /// The threshold the independent check accepts an answer with: a margin of 100 over the
    /// solver's stopping tolerance `tolerance` (the check measures on its own scales), but never
    /// more than the tolerance the scene asked for.
    pub(crate) fn acceptance(&self, tolerance: f64) -> f64 {
        (100.0 * tolerance.max(1e-10)).min(self.spec.tolerance.unwrap_or(f64::INFINITY))
    }

    /// The friction law(s) for the report: the contact's, or every part's.
    pub(crate) fn friction_report(&self) -> crate::report::contact::FrictionReport {
        match &self.parts {
            Some(parts) => parts.friction_report(),
            None => self.spec.friction.into(),
        }
    }

    /// The owned load `f + S anchor`: the springs pull towards the previous iterate.
    fn anchored_load(&self, f: &[f64], anchor: &[f64], rows: std::ops::Range<usize>) -> Vec<f64> {
        let mut load = f.to_vec();
        if let Some(k) = self.spring {
            for &dof in self.spring_dofs.iter().filter(|d| rows.contains(d)) {
                load[dof - rows.start] += k * anchor[dof];
            }
        }
        load
    }

    /// Add the stabilisation springs to the owned diagonal entries (CSR rows `first_row..`).
    pub fn add_springs(
        &mut self,
        session: &Session,
        first_row: usize,
        indptr: &[usize],
        indices: &[usize],
        values: &mut [f64],
    ) -> Result<()> {
        if self.free_motions.is_none() {
            return Ok(());
        }
        let max_diag = (0..indptr.len() - 1)
            .filter_map(|r| {
                indices[indptr[r]..indptr[r + 1]].binary_search(&(first_row + r)).ok().map(|k| values[indptr[r] + k])
            })
            .fold(0.0f64, |a, v| a.max(v.abs()));
        // The same k on every rank: the largest diagonal over all ranks.
        let max_diag = session.world().max(&[max_diag])?[0];
        self.set_stabilisation(max_diag);
        match self.spring {
            Some(k) => self.add_spring_values(k, first_row, indptr, indices, values),
            None => Ok(()),
        }
    }

    /// Choose the stabilisation spring stiffness from the largest diagonal entry of K (only
    /// when the Dirichlet conditions leave a rigid motion free): `k = STABILISATION · max_diag / m`.
    pub fn set_stabilisation(&mut self, max_diag: f64) {
        if self.free_motions.is_some() {
            self.spring = Some(STABILISATION * max_diag / self.boundary.points().max(1) as f64);
        }
    }

    /// Add springs of stiffness `k` at the contact nodes to the owned diagonal entries.
    pub fn add_spring_values(
        &self,
        k: f64,
        first_row: usize,
        indptr: &[usize],
        indices: &[usize],
        values: &mut [f64],
    ) -> Result<()> {
        // A prescribed dof keeps its Dirichlet row: spring_dofs holds free dofs only.
        for &row in &self.spring_dofs {
            if row < first_row || row >= first_row + indptr.len() - 1 {
                continue;
            }
            let r = row - first_row;
            let cols = &indices[indptr[r]..indptr[r + 1]];
            let k_pos =
                cols.binary_search(&row).map_err(|_| Error::PetscUsage(format!("no diagonal entry in row {row}")))?;
            values[indptr[r] + k_pos] += k;
        }
        Ok(())
    }

    /// SNESVI route: rotate the 2×2 node blocks of the contact nodes into their (n, t) frames,
    /// `K' = Rᵀ K R`, `f' = Rᵀ f`, so that the non-penetration `uN ≤ g0` becomes an upper bound
    /// on one unknown. A contact point with a prescribed component (`aligned_normal`:
    /// a roller or pin on the contact part, the axis node of a body of revolution, u_r = 0) is
    /// not rotated: its row `B_N` acts on its free Cartesian dof alone, so the bound goes on
    /// that dof and its fixed row (a lone diagonal, whose pattern a rotation would need to
    /// widen) stays as it is.
    pub fn rotate_to_frames(
        &self,
        num_nodes: usize,
        first_row: usize,
        indptr: &[usize],
        indices: &[usize],
        values: &mut [f64],
        rhs: &mut [f64],
    ) -> Result<()> {
        // A point with a prescribed component has its normal row on the free dof alone
        // (`aligned_normal`): it is bounded in Cartesian components, its Dirichlet row kept.
        // A prescribed point without a free normal component is left out of the points by
        // `ContactBoundary`; this guards the invariant.
        let b = &self.boundary;
        if let Some(i) = (0..b.points()).find(|&i| b.prescribed[i].is_some() && self.aligned_normal(i).is_none()) {
            return Err(Error::Usage(format!(
                "solver \"snes_vi\": contact node {} has a prescribed displacement component and no free normal \
                 component, which its bounds cannot take; use solver = \"newton_full\" (the default)",
                b.nodes[i]
            )));
        }
        let mut frame: Vec<Option<[[f64; 2]; 2]>> = vec![None; num_nodes];
        for (i, &node) in self.boundary.nodes.iter().enumerate() {
            if self.aligned_normal(i).is_some() {
                continue;
            }
            let (n, t) = (self.boundary.normal[i], self.boundary.tangent[i]);
            frame[node] = Some([[n[0], t[0]], [n[1], t[1]]]); // R = [n t]
        }
        let nrows = indptr.len() - 1;
        // Right multiplication by R_b on every owned row.
        for r in 0..nrows {
            let (a, b) = (indptr[r], indptr[r + 1]);
            let mut k = a;
            while k < b {
                let col = indices[k];
                let node = col / 2;
                if let Some(rb) = frame[node] {
                    if !col.is_multiple_of(2) || k + 1 >= b || indices[k + 1] != col + 1 {
                        return Err(Error::PetscUsage(format!(
                            "row {}: contact node {node} lacks a full 2×2 block",
                            first_row + r
                        )));
                    }
                    let (kx, ky) = (values[k], values[k + 1]);
                    values[k] = kx * rb[0][0] + ky * rb[1][0];
                    values[k + 1] = kx * rb[0][1] + ky * rb[1][1];
                    k += 2;
                } else {
                    k += 1;
                }
            }
        }
        // Left multiplication by R_aᵀ on the rows of contact nodes (rows 2a, 2a+1 share a pattern).
        for r in (0..nrows).filter(|r| (first_row + r).is_multiple_of(2)) {
            let node = (first_row + r) / 2;
            let Some(ra) = frame[node] else { continue };
            if r + 1 >= nrows || indptr[r + 1] - indptr[r] != indptr[r + 2] - indptr[r + 1] {
                return Err(Error::PetscUsage(format!("contact node {node}: rows differ in pattern")));
            }
            let len = indptr[r + 1] - indptr[r];
            for k in 0..len {
                let (i0, i1) = (indptr[r] + k, indptr[r + 1] + k);
                let (kx, ky) = (values[i0], values[i1]);
                values[i0] = ra[0][0] * kx + ra[1][0] * ky;
                values[i1] = ra[0][1] * kx + ra[1][1] * ky;
            }
            let (fx, fy) = (rhs[r], rhs[r + 1]);
            rhs[r] = ra[0][0] * fx + ra[1][0] * fy;
            rhs[r + 1] = ra[0][1] * fx + ra[1][1] * fy;
        }
        Ok(())
    }

    /// The SNESVI route's unrotated points: a contact point with a prescribed component `k`
    /// has its row `B_N = (n·d) dᵀ` on the free dof `c = 1 − k` alone (module doc of
    /// [`crate::contact::boundary`]: `n_k = 0` in [`ContactBoundary::normal`]); then `(c, n_c)`,
    /// and its condition `B_N u = n_c u_c ≤ g0` is a bound on the Cartesian dof `c`.
    fn aligned_normal(&self, i: usize) -> Option<(usize, f64)> {
        let (k, _) = self.boundary.prescribed[i]?;
        let n = self.boundary.normal[i];
        (n[k] == 0.0 && n[1 - k] != 0.0).then_some((1 - k, n[1 - k]))
    }

    /// Of the residual `K v − f` at the node of point `i` in the SNESVI route's unknowns: the
    /// normal contact force `rN` (`(K v − f)_N = rN` on a rotated node, `(K v − f)_c = n_c rN`
    /// on an [`Self::aligned_normal`] one) and the residual of the row that must vanish (the
    /// rotated tangential row; the prescribed dof's row, which is its Dirichlet row).
    fn normal_force_and_free_residual(&self, i: usize, reaction: [f64; 2]) -> (f64, f64) {
        match self.aligned_normal(i) {
            None => (reaction[0], reaction[1]),
            Some((c, nc)) => (reaction[c] / nc, reaction[1 - c]),
        }
    }

    /// `(B_N u, B_T u)` of point `i` from its node block `v` in the SNESVI route's unknowns.
    fn frame_components(&self, i: usize, v: [f64; 2]) -> [f64; 2] {
        if self.aligned_normal(i).is_none() {
            return v;
        }
        let (n, t) = (self.boundary.normal[i], self.boundary.tangent[i]);
        [n[0] * v[0] + n[1] * v[1], t[0] * v[0] + t[1] * v[1]]
    }

    /// Frictionless contact on the full system with PETSc SNESVI: `v_N ≤ g0` at the contact
    /// nodes of the rotated system (see [`Self::rotate_to_frames`]).
    pub fn solve_vi<'s>(
        &self,
        session: &'s Session,
        matrix: &Matrix<'s>,
        rhs: &Vector<'s>,
    ) -> Result<(Vec<f64>, ContactOutcome)> {
        let b = &self.boundary;
        let m = b.points();
        let rows = matrix.owned_rows();
        let inf = f64::INFINITY;
        let (mut lower, mut upper) = (vec![-inf; rows.len()], vec![inf; rows.len()]);
        for (i, &node) in b.nodes.iter().enumerate() {
            match self.aligned_normal(i) {
                None if rows.contains(&(2 * node)) => upper[2 * node - rows.start] = b.gap[i],
                // n_c u_c <= g0 with n_c = ±1.
                Some((c, nc)) if rows.contains(&(2 * node + c)) => {
                    let bound = b.gap[i] / nc;
                    if nc > 0.0 {
                        upper[2 * node + c - rows.start] = bound;
                    } else {
                        lower[2 * node + c - rows.start] = bound;
                    }
                }
                _ => {}
            }
        }
        let f = rhs.owned_values()?;
        // SNESVI's absolute tolerance: VI_ROUND_OFF of the load |f| (not of the anchored load
        // of the proximal iterations, whose spring part would loosen it).
        let absolute = VI_ROUND_OFF * rhs.norm2()?;
        let mut v = matrix.create_vector()?;
        let mut rk_vec = matrix.create_vector()?;
        let mut anchor = vec![0.0; matrix.global_size()];
        let mut history: Vec<f64> = Vec::new();
        let mut newton_steps = 0;
        let (run, force, uc, v_all, reaction, spring) = loop {
            // Proximal iterations on the stabilisation springs, as in `solve` (S = k I is the
            // same in the rotated frames).
            let rk = self.anchored_load(&f, &anchor, rows.clone());
            rk_vec.set_owned(&rk)?;
            let run = crate::petsc::bounded::solve_vi(
                session,
                matrix,
                &rk_vec,
                (&lower, &upper),
                &mut v,
                absolute,
                "contact_",
            )?;
            newton_steps += run.iterations;
            // Contact forces: the residual K'v − f' on the normal unknowns (tangential: 0).
            let mut residual = matrix.create_vector()?;
            matrix.multiply(&v, &mut residual)?;
            residual.axpy(-1.0, &rk_vec)?;
            let reaction = residual.gather_all()?;
            let v_all = v.gather_all()?;
            let mut force = vec![0.0; 2 * m];
            let mut uc = vec![0.0; 2 * m];
            for (i, &node) in b.nodes.iter().enumerate() {
                let [vn, vt] = self.frame_components(i, [v_all[2 * node], v_all[2 * node + 1]]);
                force[2 * i] = self.normal_force_and_free_residual(i, [reaction[2 * node], reaction[2 * node + 1]]).0;
                uc[2 * i] = vn;
                uc[2 * i + 1] = vt;
            }
            let Some(k) = self.spring else { break (run, force, uc, v_all, reaction, [0.0; 2]) };
            let (mut spring_rotated, mut largest) = (vec![[0.0f64; 2]; m], 0.0f64);
            let mut spring = [0.0f64; 2];
            for (i, &node) in b.nodes.iter().enumerate() {
                let moved = [0, 1].map(|c| -k * (v_all[2 * node + c] - anchor[2 * node + c]));
                largest = largest.max(moved[0].abs()).max(moved[1].abs());
                if self.aligned_normal(i).is_some() {
                    // Cartesian unknowns: the spring force as it is.
                    spring[0] += moved[0];
                    spring[1] += moved[1];
                } else {
                    spring_rotated[i] = moved;
                }
            }
            for (i, sr) in spring_rotated.iter().enumerate() {
                for (c, total) in spring.iter_mut().enumerate() {
                    *total += sr[0] * b.normal[i][c] + sr[1] * b.tangent[i][c];
                }
            }
            history.push(largest);
            let scale = force.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            let all_open = force.iter().step_by(2).all(|&r| r >= 0.0);
            if proximal_iterations_done(&history, scale, all_open) {
                break (run, force, uc, v_all, reaction, spring);
            }
            anchor = v_all;
        };
        // Back to Cartesian components: u = R v at the contact nodes.
        let mut u = v_all;
        for (i, &node) in b.nodes.iter().enumerate() {
            if self.aligned_normal(i).is_some() {
                continue;
            }
            let (n, t) = (b.normal[i], b.tangent[i]);
            let (vn, vt) = (u[2 * node], u[2 * node + 1]);
            u[2 * node] = n[0] * vn + t[0] * vt;
            u[2 * node + 1] = n[1] * vn + t[1] * vt;
        }
        // Independent check (no W here): residuals of (r, B u) with the law itself.
        let scale = contact::ResidualScale::from_field(&force, &u, &b.gap);
        let force_scale = scale.force;
        // Residual of the reduced (tangential) rows: must vanish for a frictionless solution.
        let tangential: f64 = b
            .nodes
            .iter()
            .enumerate()
            .map(|(i, &node)| {
                self.normal_force_and_free_residual(i, [reaction[2 * node], reaction[2 * node + 1]]).1.abs()
            })
            .fold(0.0, f64::max);
        let residuals = contact::evaluate_residuals(&force, &uc, &b.gap, &|_, _| 0.0, scale);
        let tolerance = self.spec.tolerance.unwrap_or(1e-9);
        if !residuals.is_acceptable(self.acceptance(tolerance)) || tangential > 1e-6 * force_scale {
            return Err(Error::SolverDiverged {
                solver: run.method.clone(),
                reason: format!(
                    "PETSc reported {} but the answer fails the independent check: {residuals}; tangential residual {tangential:.3e}",
                    run.converged_reason
                ),
                iterations: run.iterations,
                residual: residuals.worst(),
                tried: "reduced-space active set Newton; use solver = \"newton\" (condensed semi-smooth Newton)".into(),
            });
        }
        let status: Vec<PointStatus> = (0..m)
            .map(|i| if force[2 * i] < -1e-12 * force_scale { PointStatus::Slip } else { PointStatus::Open })
            .collect();
        let solution = contact::ContactSolution {
            force: force.clone(),
            displacement: uc,
            iterations: run.iterations,
            history: Vec::new(),
            status: status.clone(),
            residuals,
            solver: run.method.clone(),
            notes: vec![format!("{} ({} linear iterations)", run.converged_reason, run.linear_iterations)],
        };
        let mut report = self.report(&force, &status, &u, &residuals, history.len().max(1), &solution);
        report.iterations = newton_steps;
        report.stabilisation_force = spring;
        report.stabilisation_iterations = history.len();
        Ok((u, ContactOutcome { force, status, report }))
    }

    /// Condense, solve, recover and verify. `ksp` is set up on `matrix`; `rhs` is f.
    pub fn solve<'s>(
        &self,
        session: &'s Session,
        matrix: &Matrix<'s>,
        rhs: &Vector<'s>,
        ksp: &mut LinearSolver<'s>,
        progress: &dyn crate::problem::Progress,
    ) -> Result<(Vec<f64>, ContactOutcome, Option<SolveStats>)> {
        let mut operator = self.condense(session, matrix, ksp, progress)?;
        let f = rhs.owned_values()?;
        let (u, outcome) =
            self.solve_condensed_load(session, &mut operator, matrix, &f, &Increment::default(), progress)?;
        Ok((u, outcome, operator.linear.stats()))
    }

    /// The condensed operator of this contact: `W = B K⁻¹ Bᵀ` and the factorised K, computed once
    /// and reused by every load solved on it ([`ContactSetup::solve_condensed_load`]).
    pub(crate) fn condense<'a, 's>(
        &self,
        session: &'s Session,
        matrix: &Matrix<'s>,
        ksp: &'a mut LinearSolver<'s>,
        progress: &dyn crate::problem::Progress,
    ) -> Result<CondensedOperator<'a, 's>> {
        let m = self.boundary.points();
        // An interface law's springs and compliances act on the tangential unknowns too.
        let frictional = !matches!(self.friction_law(), FrictionLaw::None) || self.interface.is_some();
        let (mut w, linear, solves) = self.flexibility(session, matrix, ksp, frictional, progress)?;
        if !frictional {
            // Tangential block never used (rT stays 0): keep W symmetric positive definite.
            for i in 0..m {
                for j in 0..m {
                    w[(2 * i + 1, 2 * j)] = 0.0;
                    w[(2 * i, 2 * j + 1)] = 0.0;
                    w[(2 * i + 1, 2 * j + 1)] = if i == j { w[(2 * i, 2 * i)] } else { 0.0 };
                }
            }
        }
        let b = &self.boundary;
        let problem = CondensedProblem::new(
            Delassus::Dense(w),
            vec![0.0; 2 * m],
            b.gap.clone(),
            self.friction_law(),
            Some(b.weight.clone()),
        )?;
        Ok(CondensedOperator { problem, linear, solves })
    }

    /// Solve the contact problem for the owned load `f` on a condensed operator: the
    /// proximal iterations on the stabilisation springs around the condensed solves, the
    /// recovery `u = K⁻¹ (f + Bᵀ r)` and the independent check. `increment` says what the
    /// contact law sees beyond the static problem (an increment of a load path: the law acts
    /// on `B u − shift`) and where to start.
    pub(crate) fn solve_condensed_load<'s>(
        &self,
        session: &'s Session,
        operator: &mut CondensedOperator<'_, 's>,
        matrix: &Matrix<'s>,
        f: &[f64],
        increment: &Increment,
        progress: &dyn crate::problem::Progress,
    ) -> Result<(Vec<f64>, ContactOutcome)> {
        let b = &self.boundary;
        let m = b.points();
        let n = matrix.global_size();
        let rows = matrix.owned_rows();
        let mut x = matrix.create_vector()?;
        let mut e = matrix.create_vector()?;
        let zero_shift = vec![0.0; 2 * m];
        let shift = increment.shift.as_deref().unwrap_or(&zero_shift);
        let mut settings = super::condensation::solver_settings(&self.spec);
        // Proximal iterations on the stabilisation springs (see the module doc): the springs
        // are anchored at the previous displacement, so their force vanishes at convergence.
        let mut anchor = increment.start_displacement.clone().unwrap_or_else(|| vec![0.0; n]);
        let mut history: Vec<f64> = Vec::new();
        let mut interface_base_force = increment.start_force.clone();
        // With interface laws the solver's unknown is the contact force r' (all points), not r.
        let mut initial_force: Option<Vec<f64>> = match &increment.interface {
            Some(i) => i.last_contact_force.clone(),
            None => increment.start_force.clone(),
        };
        let (mut total_iterations, mut all_changes, mut all_residuals) = (0usize, Vec::new(), Vec::<f64>::new());
        let base_tolerance = settings.tolerance;
        let mut step_iterations = Vec::new();
        loop {
            let rk = self.anchored_load(f, &anchor, rows.clone());
            // With interface laws on a body held by the stabilisation springs: the free
            // displacement under f + Bᵀ r_prev (the last total force), so that it stays of the
            // size of the answer instead of the weak springs' (interface_law::condensed,
            // "base force": the parallel springs' cancellation is then small).
            let base_force = match (&increment.interface, self.spring) {
                (Some(_), Some(_)) => interface_base_force.clone(),
                _ => None,
            };
            let mut u_free = match (&increment.free_field, self.spring) {
                (Some(field), None) => {
                    operator.solves += 1;
                    b.gather(field)
                }
                _ => {
                    let mut load_k = rk.clone();
                    if let Some(r) = &base_force {
                        let mut load = vec![0.0; n];
                        b.scatter_add(r, &mut load);
                        for (t, l) in load_k.iter_mut().zip(&load[rows.clone()]) {
                            *t += l;
                        }
                    }
                    e.set_owned(&load_k)?;
                    operator.linear.solve(matrix, &e, &mut x)?;
                    operator.solves += 2;
                    b.gather(&x.gather_all()?)
                }
            };
            for (v, s) in u_free.iter_mut().zip(shift) {
                *v -= s;
            }
            let problem = operator.problem.with_free_displacement(u_free)?;
            let modified = match &increment.interface {
                Some(i) => Some(crate::interface_law::condensed::ModifiedProblem::with_base_force(
                    &problem,
                    &i.modifications,
                    i.last_contact_force.as_deref(),
                    base_force.as_deref(),
                )?),
                None => None,
            };
            settings.initial_force = initial_force.clone();
            // A warm-started solve accepts the previous force as it is when its residual is
            // below the tolerance: the force then stays frozen, the springs take up its error
            // at every iteration and the proximal iterations stall at the solver's tolerance
            // (1e-10 of the load on the two-body patch test) instead of converging. Ask the
            // later solves for what the previous one reached (×100), at most 1e3 × tighter.
            if initial_force.is_some() {
                if let Some(&reached) = all_residuals.last() {
                    settings.tolerance = base_tolerance.min((100.0 * reached).max(1e-3 * base_tolerance));
                }
            }
            let (solution, contact_force) = if let Some(md) = &modified {
                let (solution, contact_force) = self.solve_modified(md, &settings, progress)?;
                (solution, Some(contact_force))
            } else if self.spec.solver == ContactSolverSpec::Tao {
                progress.note(&format!("contact: {m} points, solver PETSc TAO (box-constrained QP)"));
                (self.solve_with_tao(session, &problem)?, None)
            } else {
                (self.solve_condensed(&problem, &settings, progress)?, None)
            };
            // The independent check accepts what the scene's tolerance accepts.
            let check = SolverSettings { tolerance: base_tolerance, ..settings.clone() };
            let solves = operator.solves;
            let (u, mut outcome) = self.recover_and_verify(
                matrix,
                &rk,
                &mut operator.linear,
                (&problem, modified.as_ref()),
                solution,
                &check,
                solves,
                shift,
            )?;
            total_iterations += outcome.report.iterations;
            step_iterations.push(outcome.report.iterations);
            all_changes.extend(outcome.report.status_changes.iter().copied());
            all_residuals.extend(outcome.report.residual_history.iter().copied());
            outcome.report.residual_history = all_residuals.clone();
            outcome.report.iterations = total_iterations;
            outcome.report.status_changes = all_changes.clone();
            let Some(k) = self.spring else { return Ok((u, outcome)) };
            let (mut spring, mut largest) = ([0.0f64; 2], 0.0f64);
            for &dof in &self.spring_dofs {
                let fc = -k * (u[dof] - anchor[dof]);
                spring[dof % 2] += fc;
                largest = largest.max(fc.abs());
            }
            let scale = outcome.force.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            history.push(largest);
            outcome.report.stabilisation_force = spring;
            outcome.report.stabilisation_iterations = history.len();
            outcome.report.stabilisation_step_iterations = step_iterations.clone();
            if proximal_iterations_done(&history, scale, outcome.report.open == outcome.report.points) {
                return Ok((u, outcome));
            }
            anchor = u;
            if contact_force.is_some() {
                interface_base_force = Some(outcome.force.clone());
            }
            initial_force = Some(contact_force.unwrap_or(outcome.force));
        }
    }

    /// The flexibility `W = B K⁻¹ Bᵀ` (`2m × 2m`, local frames), the factorised stiffness it was
    /// computed with (for the later solves), and the number of linear solves it took.
    ///
    /// On one process with the default linear solver: from one MUMPS factorisation with the
    /// Schur complement on the contact dofs (`S⁻¹ = (K⁻¹)_cc`, every block at once); else, or
    /// with `-contact_condense_schur false`, one solve per contact unknown with the configured
    /// KSP (any options, any number of ranks): all `2m` columns when `all_columns`, only the
    /// normal ones otherwise (the tangential columns are left zero).
    fn flexibility<'a, 's>(
        &self,
        session: &'s Session,
        matrix: &Matrix<'s>,
        ksp: &'a mut LinearSolver<'s>,
        all_columns: bool,
        progress: &dyn crate::problem::Progress,
    ) -> Result<(DMatrix<f64>, Factorised<'a, 's>, usize)> {
        let b = &self.boundary;
        let m = b.points();
        let rows = matrix.owned_rows();
        let mut w = DMatrix::<f64>::zeros(2 * m, 2 * m);
        let schur_rows = schur_dofs(b);
        let default_solver = !session.has_option("-ksp_type")? && !session.has_option("-pc_type")?;
        let applicable = session.size() == 1 && default_solver;
        let wants_schur = match session.flag("-contact_condense_schur")? {
            None => applicable,
            Some(false) => false,
            Some(true) => {
                if !applicable {
                    return Err(Error::Usage(
                        "-contact_condense_schur needs one process and the default linear solver (no -ksp_type/-pc_type)"
                            .into(),
                    ));
                }
                true
            }
        };
        let start = std::time::Instant::now();
        let mut linear = if wants_schur {
            let factor = SchurFactor::new(session, matrix, &schur_rows)?;
            w = flexibility_from_schur(&factor, b)?;
            Factorised::Schur(factor, start.elapsed().as_secs_f64())
        } else {
            Factorised::Krylov(ksp)
        };
        let columns: Vec<usize> = match linear {
            Factorised::Schur(..) => Vec::new(),
            Factorised::Krylov(_) if all_columns => (0..2 * m).collect(),
            Factorised::Krylov(_) => (0..m).map(|i| 2 * i).collect(),
        };
        let mut x = matrix.create_vector()?;
        let mut e = matrix.create_vector()?;
        let mut unit = vec![0.0; 2 * m];
        let mut load = vec![0.0; matrix.global_size()];
        for (count, &j) in columns.iter().enumerate() {
            unit[j] = 1.0;
            load.iter_mut().for_each(|v| *v = 0.0);
            b.scatter_add(&unit, &mut load);
            unit[j] = 0.0;
            e.set_owned(&load[rows.clone()])?;
            linear.solve(matrix, &e, &mut x)?;
            let col = b.gather(&x.gather_all()?);
            for (i, v) in col.iter().enumerate() {
                w[(i, j)] = *v;
            }
            if count % 50 == 49 {
                progress.note(&format!("condensing: {} / {} flexibility columns", count + 1, columns.len()));
            }
        }
        Ok((w, linear, columns.len()))
    }

    /// The condensed problem itself, for solvers elsewhere (the FCLIB export): the whole
    /// flexibility `W = B K⁻¹ Bᵀ` (every column, also without friction), `u_free = B K⁻¹ f`,
    /// the gaps, the friction law and the weights. `matrix` is K without springs, `rhs` f.
    ///
    /// A body held by the contact alone (Dirichlet conditions leave a rigid motion free) has a
    /// singular K and no flexibility: [`Error::Unconstrained`] (the solver's stabilised
    /// iterations have no single condensed problem to give).
    pub fn condensed_problem<'s>(
        &self,
        session: &'s Session,
        matrix: &Matrix<'s>,
        rhs: &Vector<'s>,
        ksp: &mut LinearSolver<'s>,
        progress: &dyn crate::problem::Progress,
    ) -> Result<CondensedProblem<'static>> {
        if let Some(free) = &self.free_motions {
            return Err(Error::Unconstrained(format!(
                "the body is held by the contact on '{}' alone ({free}): its stiffness is singular, so there is no \
                 flexibility W = B K^-1 B^T and no condensed contact problem; hold the rigid motions with Dirichlet \
                 conditions",
                self.spec.part
            )));
        }
        let (w, mut linear, _) = self.flexibility(session, matrix, ksp, true, progress)?;
        let mut x = matrix.create_vector()?;
        linear.solve(matrix, rhs, &mut x)?;
        let b = &self.boundary;
        CondensedProblem::new(
            Delassus::Dense(w),
            b.gather(&x.gather_all()?),
            b.gap.clone(),
            self.friction_law(),
            Some(b.weight.clone()),
        )
    }

    fn solve_with_tao(&self, session: &Session, problem: &CondensedProblem) -> Result<contact::ContactSolution> {
        tao_box_qp(session, problem)
    }

    fn solve_condensed(
        &self,
        problem: &CondensedProblem,
        settings: &SolverSettings,
        progress: &dyn crate::problem::Progress,
    ) -> Result<contact::ContactSolution> {
        let m = problem.points();
        let solver = condensed_solver(&self.spec.solver).ok_or_else(|| {
            Error::Usage(format!(
                "contact solver {:?} runs on the full system, not on the condensed problem",
                self.spec.solver
            ))
        })?;
        progress.note(&format!("contact: {m} points, solver {}", solver.name()));
        let solution = contact::solve(problem, &solver, settings)?;
        for (k, h) in solution.history.iter().enumerate() {
            progress.iteration(crate::problem::Phase::Solve, k + 1, h.residual);
        }
        Ok(solution)
    }

    /// K u = f + Bᵀ r by one more solve, then the independent check of (r, B u).
    #[allow(clippy::too_many_arguments)]
    fn recover_and_verify<'s>(
        &self,
        matrix: &Matrix<'s>,
        rhs: &[f64],
        linear: &mut Factorised<'_, 's>,
        (problem, modified): (&CondensedProblem, Option<&crate::interface_law::condensed::ModifiedProblem>),
        solution: contact::ContactSolution,
        settings: &SolverSettings,
        linear_solves: usize,
        shift: &[f64],
    ) -> Result<(Vec<f64>, ContactOutcome)> {
        let b = &self.boundary;
        let rows = matrix.owned_rows();
        let mut load = vec![0.0; matrix.global_size()];
        let mut e = matrix.create_vector()?;
        let mut x = matrix.create_vector()?;
        // Recover the field with the contact forces applied: K u = f + Bᵀ r.
        let mut total = rhs.to_vec();
        load.iter_mut().for_each(|v| *v = 0.0);
        b.scatter_add(&solution.force, &mut load);
        for (t, l) in total.iter_mut().zip(&load[rows.clone()]) {
            *t += l;
        }
        e.set_owned(&total)?;
        linear.solve(matrix, &e, &mut x)?;
        let u = x.gather_all()?;
        // Independent check on (r, B u − shift).
        let mut uc = b.gather(&u);
        for (v, s) in uc.iter_mut().zip(shift) {
            *v -= s;
        }
        let accepted = self.acceptance(settings.tolerance);
        // With interface laws: the contact law on (r', u') recomputed from (r, B u) and the
        // springs' residual (`interface_law::condensed`).
        let (residuals, status, failed) = match modified {
            Some(md) => {
                let checked = md.residuals_at(&solution.force, &uc)?;
                let failed = (!checked.is_acceptable(accepted)).then(|| (checked.to_string(), checked.worst()));
                (checked.contact, md.status_at(&solution.force, &uc)?, failed)
            }
            None => {
                let residuals = problem.residuals_at(&solution.force, &uc)?;
                let failed = (!residuals.is_acceptable(accepted)).then(|| (residuals.to_string(), residuals.worst()));
                (residuals, problem.status_at(&solution.force, &uc)?, failed)
            }
        };
        if let Some((residuals_text, worst)) = failed {
            return Err(Error::SolverDiverged {
                solver: solution.solver.clone(),
                reason: format!(
                    "its answer fails the independent check on the recomputed displacement field: {residuals_text}"
                ),
                iterations: solution.iterations,
                residual: worst,
                tried: solution.notes.join("; "),
            });
        }
        let report = self.report(&solution.force, &status, &u, &residuals, linear_solves, &solution);
        Ok((u, ContactOutcome { force: solution.force, status, report }))
    }

    #[allow(clippy::too_many_arguments)]
    pub(crate) fn report(
        &self,
        force: &[f64],
        status: &[PointStatus],
        u: &[f64],
        residuals: &contact::ContactResiduals,
        linear_solves: usize,
        solution: &contact::ContactSolution,
    ) -> ContactReport {
        let b = &self.boundary;
        let m = b.points();
        let solution_force = force;
        let mut resultant = [0.0f64; 2];
        let (mut normal_resultant, mut tangential_resultant) = (0.0, 0.0);
        for i in 0..m {
            let (rn, rt) = (solution_force[2 * i], solution_force[2 * i + 1]);
            // Along the obstacle's whole frame: at a point with a prescribed component the
            // support takes the rest of the node's force (`ContactBoundary::point_force`).
            for (r, w) in resultant.iter_mut().zip(b.point_force(i, solution_force)) {
                *r += w;
            }
            normal_resultant += rn;
            tangential_resultant += rt;
        }
        let stabilisation_force = [0.0f64; 2];
        let _ = u;
        let friction = self.friction_report();
        let counts = crate::report::contact::StateCounts::of(status.iter().copied().zip(self.frictional_points()));
        ContactReport {
            part: self.spec.part.clone(),
            friction,
            solver: solution.solver.clone(),
            route: "condensed".into(),
            route_reason: format!(
                "solver = \"{}\" (the condensed route: the contact problem on W = B K⁻¹ Bᵀ)",
                self.spec.solver.scene_name()
            ),
            iterations: solution.iterations,
            status_changes: solution.history.iter().map(|h| h.status_changes).collect(),
            residual_history: solution.history.iter().map(|h| h.residual).collect(),
            notes: solution.notes.clone(),
            points: m,
            open: counts.open,
            closed: counts.closed,
            stick: counts.stick,
            slip: counts.slip,
            resultant,
            normal_resultant,
            tangential_resultant,
            peak_pressure: None,
            zones: Vec::new(),
            residuals: residuals.into(),
            stabilisation_force,
            stabilisation_iterations: 0,
            stabilisation_step_iterations: Vec::new(),
            linear_solves,
        }
    }
}

/// The condensed operator of a contact, computed once ([`ContactSetup::condense`]): the
/// flexibility `W = B K⁻¹ Bᵀ` in the contact frames (its tangential block zero without
/// friction) and the factorised stiffness, with the number of linear solves so far.
pub(crate) struct CondensedOperator<'a, 's> {
    /// The contact problem on `W` with a zero free displacement (validated once; every load
    /// solved on the operator replaces the free displacement).
    pub(crate) problem: CondensedProblem<'static>,
    pub(crate) linear: Factorised<'a, 's>,
    pub(crate) solves: usize,
}

/// What one solve of a load path adds to the static contact problem
/// ([`ContactSetup::solve_condensed_load`]); the default is the static problem from rest.
#[derive(Debug, Clone, Default)]
pub(crate) struct Increment {
    /// Subtracted from the relative displacement `B u` (2m entries, the contact frames) before
    /// the contact law sees it: the obstacle's motion along the normal, and along the tangent
    /// the obstacle's motion plus the slip of the last converged state, so that friction acts
    /// on the slip increment. `None`: zero.
    pub(crate) shift: Option<Vec<f64>>,
    /// Where the springs are anchored first (the last converged displacement); zero if `None`.
    pub(crate) start_displacement: Option<Vec<f64>>,
    /// The force the contact solver starts from (the last converged one); zero if `None`.
    pub(crate) start_force: Option<Vec<f64>>,
    /// `K⁻¹ f` (the whole vector), when the caller has it (a load path combines its load
    /// cases' fields): the free displacement then costs no solve. Ignored with stabilisation
    /// springs (their anchored load changes at every proximal iteration).
    pub(crate) free_field: Option<Vec<f64>>,
    /// With interface laws: the modification of every point (the staggered loop's current
    /// iterate, [`crate::interface_law::staggered`]); `None`: plain contact.
    pub(crate) interface: Option<InterfaceIncrement>,
}

/// What the interface laws change in a solve ([`Increment::interface`]).
#[derive(Debug, Clone, Default)]
pub(crate) struct InterfaceIncrement {
    /// One per contact point.
    pub(crate) modifications: Vec<crate::interface_law::PointModification>,
    /// The last iterate's contact force `r'` (2m): where the solver starts (zero if `None`), and
    /// the thresholds of Coulomb points mixed with Tresca points
    /// ([`crate::interface_law::condensed::unify_friction`]).
    pub(crate) last_contact_force: Option<Vec<f64>>,
}

/// The SNESVI route's absolute residual tolerance, relative to the load `|f|`: above the
/// round-off floor of `|K v − f|` on stiff bodies (1.8e-12 of `|f|` on the Hertz sphere at
/// E = 210 GPa, where PETSc's relative 1e-12 was out of reach and its line search failed).
const VI_ROUND_OFF: f64 = 1e-11;

/// The free dofs of the nodes some row of `B` touches (the contact nodes, and between two
/// bodies the coupled nodes of the other side), increasing: where the stabilisation springs act.
pub(crate) fn spring_dofs(boundary: &ContactBoundary, prescribed: &dyn Fn(usize) -> [Option<f64>; 2]) -> Vec<usize> {
    boundary
        .support_nodes()
        .into_iter()
        .flat_map(|k| {
            let fixed = prescribed(k);
            (0..2).filter(move |&c| fixed[c].is_none()).map(move |c| 2 * k + c)
        })
        .collect()
}

/// Stop the proximal iterations on the stabilisation springs? `history` holds the largest
/// spring force of each iteration so far (the last is the current one), `scale` the largest
/// contact force. Stop when the spring force is negligible (converged, or below 1e-8 of the
/// contact forces and no longer halving: its round-off floor), when no point is in
/// contact after three iterations (the body lifts off), when the force no longer halves over
/// five iterations (the body slides), or after 200 iterations; the caller's equilibrium check
/// tells these apart.
fn proximal_iterations_done(history: &[f64], scale: f64, all_open: bool) -> bool {
    let n = history.len();
    let largest = history[n - 1];
    // Converged, or at the round-off floor of the spring force (it stops decreasing once
    // u − anchor is round-off in u: more iterations change nothing).
    let floor = n >= 3 && largest <= 1e-8 * scale && largest > 0.5 * history[n - 2];
    let converged = largest <= 1e-12 * scale || floor;
    let lifted = all_open && n >= 3;
    let stalled = n > 10 && largest > 0.5 * history[n - 6];
    converged || lifted || stalled || n >= 200
}
