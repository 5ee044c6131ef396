//! The discrete dual problem: assemble, solve with PETSc, evaluate and check the stress field.
//!
//! Unknowns: the reduced HCT dofs `z` (masters of [`super::boundary::eliminate`]), with all
//! dofs `φ = T z + φ0`. The complementary energy of `σ = σ(φ) + σp` (σp the particular field of
//! the body force) is
//!
//! ```text
//!   J*(φ) = ½ b(σ(φ) + σp, σ(φ) + σp) − l(σ(φ) + σp),     b(σ, τ) = ∫ σ : C⁻¹ τ,
//! ```
//!
//! so the reduced system is `Tᵀ S T z = Tᵀ (l − S φ0 − b_p)` with `S = Σ_E S_E`
//! ([`HctElement::compliance_stiffness`]), `l` the prescribed-displacement functional and
//! `b_p[i] = b(σp, σ(ψ_i))`. It is symmetric positive definite (the affine kernel is fixed), and
//! solved by PETSc's KSP with the options database (MUMPS Cholesky by default), on one or
//! several MPI ranks (contiguous row blocks; every rank assembles its own rows).
use std::ops::Range;
use std::sync::Arc;

use nalgebra::{DMatrix, SMatrix};

use super::boundary::{self, AffineDofs, BoundaryEdge, ContactEdge, DofRole, TractionComponent};
use super::dofs::HctDofs;
use super::local_contact::LocalContact;
use crate::error::{Error, Result};
use crate::estimate::StressField;
use crate::fem::assembly::EdgeLoad;
use crate::fem::csr_assembly::CsrAssembler;
use crate::fem::hct::{HctElement, HCT_DOFS};
use crate::fem::material::Material;
use crate::fem::quadrature;
use crate::mesh::Mesh;
use crate::petsc::{LinearSolver, Matrix, Session, SolveStats};
use crate::scene::DualConstraints;

/// `x -> (F(x), σp(x))`: a variable body force and its particular stress field.
pub type BodyField = Arc<dyn Fn([f64; 2]) -> ([f64; 2], [f64; 3]) + Send + Sync>;

/// A body force and its particular stress field `σp` (`div σp + F = 0`).
#[derive(Clone)]
pub enum BodyLoad {
    /// A constant force F (N/m³), with `σp = diag(−Fx x, −Fy y)`.
    Constant([f64; 2]),
    /// `x -> (F(x), σp(x))` for a variable force, σp given by the caller.
    Field(BodyField),
}

impl BodyLoad {
    /// The body force F (N/m³) at `x`.
    pub fn force(&self, x: [f64; 2]) -> [f64; 2] {
        match self {
            BodyLoad::Constant(f) => *f,
            BodyLoad::Field(g) => g(x).0,
        }
    }
    /// A particular stress `σp` (Pa) with `div σp + F = 0`, `[σxx, σyy, σxy]` at `x`.
    pub fn particular(&self, x: [f64; 2]) -> [f64; 3] {
        match self {
            BodyLoad::Constant(f) => particular_stress(*f, x),
            BodyLoad::Field(g) => g(x).1,
        }
    }
    fn is_zero(&self) -> bool {
        matches!(self, BodyLoad::Constant([0.0, 0.0]))
    }
}

/// The data of a dual problem besides the mesh and the material.
pub struct DualData<'a> {
    /// The body force.
    pub body_force: BodyLoad,
    /// Tractions on boundary groups (several on one group add up).
    pub edge_loads: &'a [EdgeLoad<'a>],
    /// Prescribed displacement components `(group, [ux, uy])` on boundary groups.
    pub prescribed: &'a [(usize, [Option<f64>; 2])],
    /// The contact part, whose tractions are the contact forces.
    pub contact: Option<ContactSide<'a>>,
}

/// The contact part of a dual problem: a boundary group whose traction is unknown, linear on
/// each edge, with its end values as contact forces ([`super::boundary::ContactEdge`]).
#[derive(Clone, Copy)]
pub struct ContactSide<'a> {
    /// The contact part's boundary group (index into `mesh.groups`).
    pub group: usize,
    /// The body's unit contact direction `n` at a point; the frame is `(n, t)` with `t` = `n`
    /// turned by +90° (the convention of [`crate::contact::boundary`]).
    pub normal: &'a (dyn Fn([f64; 2]) -> [f64; 2] + Sync),
}

/// The particular stress field of a constant body force F: `σp = diag(−Fx x, −Fy y)`,
/// `div σp + F = 0`.
pub fn particular_stress(f: [f64; 2], x: [f64; 2]) -> [f64; 3] {
    [-f[0] * x[0], -f[1] * x[1], 0.0]
}

/// The assembled dual problem.
pub struct DualSystem {
    /// The HCT dofs of the mesh: φ, φ,x, φ,y per vertex, a normal derivative per edge.
    pub dofs: HctDofs,
    /// Each cell's HCT element (its local basis on the macro-triangle).
    pub elements: Vec<HctElement>,
    /// The boundary edges with their tractions or contact unknowns.
    pub edges: Vec<BoundaryEdge>,
    /// The map from the reduced unknowns to all HCT dofs (boundary data and the affine kernel
    /// eliminated).
    pub affine: AffineDofs,
    /// With contact: the local parametrisation of the contact part ([`super::local_contact`]).
    pub local: Option<LocalContact>,
    /// With contact and no [`Self::local`]: why the local parametrisation was not used (the
    /// routes that take it then keep the contact forces as unknowns, a dense boundary block).
    pub local_fallback: Option<String>,
    /// The material (the compliance `C⁻¹` of the dual energy).
    pub material: Material,
    /// The body force.
    pub body_force: BodyLoad,
}

/// Why the local parametrisation's affine base cannot stand in for that of the contact forces
/// as unknowns (the same free HCT dofs and the same anchor are needed for the two to share the
/// reduced numbering): `None` when it can.
fn base_difference(local: &AffineDofs, forces: &AffineDofs) -> Option<String> {
    let mut differences = Vec::new();
    if local.num_masters != forces.num_masters {
        differences.push(format!("{} free HCT dofs against {}", local.num_masters, forces.num_masters));
    }
    if local.anchor != forces.anchor {
        differences.push(format!("the affine part of φ fixed at node {} against node {}", local.anchor, forces.anchor));
    }
    (!differences.is_empty()).then(|| {
        format!(
            "dual formulation: the local parametrisation's affine base differs from that of the contact forces as \
             unknowns ({}); report this mesh: it should not happen",
            differences.join(", ")
        )
    })
}

/// The terms `(unknown, coefficient)` of a dof's expansion: one for a master, a list for a slave.
#[derive(Clone, Copy)]
struct Terms<'a> {
    one: Option<(usize, f64)>,
    many: &'a [(usize, f64)],
}

impl Terms<'_> {
    fn iter(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.one.into_iter().chain(self.many.iter().copied())
    }
}

/// The reduced rows `rows` of the system, CSR with global column indices.
pub struct ReducedRows {
    /// Global index of the first row held.
    pub first_row: usize,
    /// Start of each row in `indices` and `values` (length rows + 1).
    pub indptr: Vec<usize>,
    /// Global column index of each stored entry.
    pub indices: Vec<usize>,
    /// Value of each stored entry.
    pub values: Vec<f64>,
    /// Right-hand side of the rows held.
    pub rhs: Vec<f64>,
}

impl DualSystem {
    /// Number the dofs, build the elements, impose the boundary data.
    pub fn new(mesh: &Mesh, material: &Material, data: &DualData) -> Result<Self> {
        let dofs = HctDofs::new(mesh);
        let elements = (0..mesh.num_cells()).map(|c| dofs.element(mesh, c)).collect::<Result<Vec<_>>>()?;
        let order = boundary::boundary_loop(mesh)?;
        let mut edges = Vec::with_capacity(order.len());
        let mut num_contact_edges = 0;
        for &e in &order {
            let ed = mesh.edge(e);
            let (a, b) = (ed[0], ed[1]);
            let (pa, pb) = (mesh.nodes[a], mesh.nodes[b]);
            let len = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            let n = [(pb[1] - pa[1]) / len, -(pb[0] - pa[0]) / len];
            let group = mesh.edge_group[e];
            // The traction left for σ(φ) (the loads minus the particular field's σp n), projected
            // in L2 onto linear functions along the edge: exact for linear tractions, and it keeps
            // the edge's force and moment, so equilibrium is kept (HCT tractions are linear on an
            // edge). Values at the start, the midpoint and the end.
            let rule = quadrature::gauss_legendre(5);
            let (mut mean, mut slope) = ([0.0; 2], [0.0; 2]);
            for (&s, &w) in rule.points.iter().zip(&rule.weights) {
                let x = [pa[0] + s * (pb[0] - pa[0]), pa[1] + s * (pb[1] - pa[1])];
                let mut v = [0.0; 2];
                for load in data.edge_loads.iter().filter(|l| l.group == group) {
                    let ti = load.traction.at(x, n);
                    v[0] += ti[0];
                    v[1] += ti[1];
                }
                let sp = data.body_force.particular(x);
                let left = [v[0] - (sp[0] * n[0] + sp[2] * n[1]), v[1] - (sp[2] * n[0] + sp[1] * n[1])];
                for k in 0..2 {
                    mean[k] += w * left[k];
                    slope[k] += 12.0 * w * (s - 0.5) * left[k];
                }
            }
            let t = [0, 1].map(|k| [mean[k] - 0.5 * slope[k], mean[k], mean[k] + 0.5 * slope[k]]);
            let mut components = [TractionComponent::Known(t[0]), TractionComponent::Known(t[1])];
            let mut contact = None;
            if let Some(side) = data.contact.filter(|c| c.group == group) {
                components = [TractionComponent::Free, TractionComponent::Free];
                let frames = [pa, pb].map(|x| {
                    let n = (side.normal)(x);
                    [n, [-n[1], n[0]]]
                });
                contact = Some(ContactEdge { first: 4 * num_contact_edges, frames });
                num_contact_edges += 1;
            }
            for (g, values) in data.prescribed {
                if *g == group {
                    for k in 0..2 {
                        if let Some(u0) = values[k] {
                            if !matches!(components[k], TractionComponent::Prescribed(_)) {
                                components[k] = TractionComponent::Prescribed(u0);
                            }
                        }
                    }
                }
            }
            let edge = dofs.edge_between(a, b).ok_or_else(|| {
                boundary::formulation_error(
                    format!("boundary edge {a} -> {b} is not an edge of any triangle"),
                    "check the mesh",
                )
            })?;
            edges.push(BoundaryEdge { mesh_edge: e, a, b, edge, components, contact });
        }
        if num_contact_edges == edges.len() {
            // The walk then closes through a contact edge: the global equilibrium conditions
            // take that edge's forces, and no dof depends on them (a zero flexibility).
            return Err(boundary::formulation_error(
                "the contact part is the whole boundary: the dual needs part of the boundary with known tractions \
                 (zero on a free side) or a Dirichlet condition"
                    .into(),
                "make the contact part only the side that may touch the obstacle, or use the primal formulation",
            ));
        }
        let affine = boundary::eliminate(mesh, &dofs, &edges)?;
        let (local, local_fallback) = if num_contact_edges > 0 {
            match boundary::eliminate_local(mesh, &dofs, &edges).and_then(|(a, maps)| LocalContact::new(a, maps)) {
                Ok(l) => match base_difference(&l.affine, &affine) {
                    None => (Some(l), None),
                    Some(why) => (None, Some(why)),
                },
                Err(Error::Formulation { message, hint }) => (None, Some(format!("{message}; {hint}"))),
                Err(e) => (None, Some(e.to_string())),
            }
        } else {
            (None, None)
        };
        Ok(DualSystem {
            dofs,
            elements,
            edges,
            affine,
            local,
            local_fallback,
            material: *material,
            body_force: data.body_force.clone(),
        })
    }

    /// The reduced unknowns: free HCT dofs, then the contact forces (if any).
    pub fn num_unknowns(&self) -> usize {
        self.affine.num_unknowns()
    }

    /// The prescribed-displacement functional `l` on all dofs (vertex gradient dofs only).
    pub(super) fn load_functional(&self) -> Vec<f64> {
        let mut l = vec![0.0; self.dofs.len()];
        for e in &self.edges {
            let (gxa, gya) = (self.dofs.node_dof(e.a, 1), self.dofs.node_dof(e.a, 2));
            let (gxb, gyb) = (self.dofs.node_dof(e.b, 1), self.dofs.node_dof(e.b, 2));
            if let TractionComponent::Prescribed(u0x) = e.components[0] {
                l[gyb] += u0x;
                l[gya] -= u0x;
            }
            if let TractionComponent::Prescribed(u0y) = e.components[1] {
                l[gxb] -= u0y;
                l[gxa] += u0y;
            }
        }
        l
    }

    /// `b_p[i] = ∫_E σp : C⁻¹ σ(ψ_i)` of each element.
    pub(super) fn particular_cross_term(&self, element: &HctElement) -> [f64; HCT_DOFS] {
        let mut out = [0.0; HCT_DOFS];
        if self.body_force.is_zero() {
            return out;
        }
        let compliance = self.material.compliance();
        // Degree 2 is exact for a constant force (σp linear); a variable one gets a finer rule.
        let rule = quadrature::triangle(if matches!(self.body_force, BodyLoad::Constant(_)) { 2 } else { 8 });
        for (piece, triangle) in element.pieces().into_iter().enumerate() {
            for (x, w) in quadrature::on_triangle(&rule, triangle) {
                let sp = self.body_force.particular(x);
                let ep: Vec<f64> = (0..3).map(|r| (0..3).map(|q| compliance[r][q] * sp[q]).sum()).collect();
                for (o, s) in out.iter_mut().zip(element.stresses(piece, x)) {
                    *o += w * (s[0] * ep[0] + s[1] * ep[1] + s[2] * ep[2]);
                }
            }
        }
        out
    }

    /// The expansion of dof `d` in the reduced unknowns of `affine`: its terms and its constant.
    fn expansion<'a>(affine: &'a AffineDofs, d: usize) -> (Terms<'a>, f64) {
        match &affine.role[d] {
            DofRole::Master(k) => (Terms { one: Some((*k, 1.0)), many: &[] }, 0.0),
            DofRole::Slave(t, c) => (Terms { one: None, many: t }, *c),
            DofRole::Fixed(v) => (Terms { one: None, many: &[] }, *v),
        }
    }

    /// The reduced rows `rows` (every rank computes every element and keeps its rows).
    pub fn assemble(&self, mesh: &Mesh, rows: Range<usize>) -> ReducedRows {
        self.assemble_in(&self.affine, mesh, rows)
    }

    /// The reduced rows `rows` in the reduced unknowns of `affine` (this system's, or its
    /// [`LocalContact::affine`]).
    pub fn assemble_in(&self, affine: &AffineDofs, mesh: &Mesh, rows: Range<usize>) -> ReducedRows {
        /// Elements whose twelve expansions have more terms than this in all take the dense
        /// product (the plain loop costs their square, with a search per entry).
        const LONG_EXPANSIONS: usize = 64;
        let l = self.load_functional();
        let nm = affine.num_unknowns();
        let mut rhs = vec![0.0; rows.len()];
        // The load functional: l lives on vertex dofs.
        for (d, &ld) in l.iter().enumerate() {
            if ld != 0.0 {
                for (k, a) in Self::expansion(affine, d).0.iter() {
                    if rows.contains(&k) {
                        rhs[k - rows.start] += a * ld;
                    }
                }
            }
        }
        // Each element couples the reduced unknowns of its dofs' expansions.
        let mut group_ptr = Vec::with_capacity(self.elements.len() + 1);
        group_ptr.push(0);
        let mut group_indices = Vec::with_capacity(13 * self.elements.len());
        for c in 0..self.elements.len() {
            let start = group_indices.len();
            for d in self.dofs.cell_dofs(mesh, c) {
                group_indices.extend(Self::expansion(affine, d).0.iter().map(|(k, _)| k));
            }
            group_indices[start..].sort_unstable();
            let mut kept = start;
            for i in start..group_indices.len() {
                if i == start || group_indices[i] != group_indices[kept - 1] {
                    group_indices[kept] = group_indices[i];
                    kept += 1;
                }
            }
            group_indices.truncate(kept);
            group_ptr.push(group_indices.len());
        }
        let mut matrix = CsrAssembler::new(rows.clone(), nm, &group_ptr, &group_indices);
        drop((group_ptr, group_indices));
        for (c, element) in self.elements.iter().enumerate() {
            let cell_dofs = self.dofs.cell_dofs(mesh, c);
            let exp: Vec<(Terms<'_>, f64)> = cell_dofs.iter().map(|&d| Self::expansion(affine, d)).collect();
            // Elements whose expanded unknowns are all elsewhere contribute nothing here.
            if !exp.iter().any(|(t, _)| t.iter().any(|(k, _)| rows.contains(&k))) {
                continue;
            }
            let s: SMatrix<f64, HCT_DOFS, HCT_DOFS> = element.compliance_stiffness(&self.material);
            let bp = self.particular_cross_term(element);
            // S φ0 restricted to the element (constants of the expansions).
            let mut s_phi0 = [0.0; HCT_DOFS];
            for i in 0..HCT_DOFS {
                s_phi0[i] = (0..HCT_DOFS).map(|j| s[(i, j)] * exp[j].1).sum();
            }
            let long = exp.iter().map(|(t, _)| t.iter().count()).sum::<usize>() > LONG_EXPANSIONS;
            if long {
                // Expansions through a contact part (every boundary unknown downstream depends
                // on all its forces): the element matrix in the union of the unknowns as one
                // dense product Tᵀ S T, added row by row.
                let mut group: Vec<usize> = exp.iter().flat_map(|(t, _)| t.iter().map(|(k, _)| k)).collect();
                group.sort_unstable();
                group.dedup();
                let mut t = DMatrix::<f64>::zeros(HCT_DOFS, group.len());
                for (i, (terms, _)) in exp.iter().enumerate() {
                    for (k, a) in terms.iter() {
                        if let Ok(p) = group.binary_search(&k) {
                            t[(i, p)] += a;
                        }
                    }
                }
                let s_dyn = DMatrix::from_fn(HCT_DOFS, HCT_DOFS, |i, j| s[(i, j)]);
                let st = &s_dyn * &t;
                let mut row_values = vec![0.0; group.len()];
                for (p, &kp) in group.iter().enumerate() {
                    if !rows.contains(&kp) {
                        continue;
                    }
                    let mut load = 0.0;
                    for i in 0..HCT_DOFS {
                        load += t[(i, p)] * (s_phi0[i] + bp[i]);
                    }
                    rhs[kp - rows.start] -= load;
                    for (q, value) in row_values.iter_mut().enumerate() {
                        *value = t.column(p).dot(&st.column(q));
                    }
                    matrix.add_sorted(kp, &group, &row_values);
                }
                continue;
            }
            for i in 0..HCT_DOFS {
                for (ki, ai) in exp[i].0.iter() {
                    if !rows.contains(&ki) {
                        continue;
                    }
                    rhs[ki - rows.start] -= ai * (s_phi0[i] + bp[i]);
                    for j in 0..HCT_DOFS {
                        let sij = s[(i, j)];
                        if sij == 0.0 {
                            continue;
                        }
                        for (kj, aj) in exp[j].0.iter() {
                            matrix.add(ki, kj, ai * sij * aj);
                        }
                    }
                }
            }
        }
        let (indptr, indices, values) = matrix.into_parts();
        ReducedRows { first_row: rows.start, indptr, indices, values, rhs }
    }

    /// Assemble and solve with the main KSP (PETSc options without prefix); all HCT dofs, on
    /// every rank.
    pub fn solve(&self, session: &Session, mesh: &Mesh) -> Result<(Vec<f64>, SolveStats)> {
        self.solve_with_prefix(session, mesh, "")
    }

    /// As [`DualSystem::solve`], the KSP reading its options under `prefix`.
    pub fn solve_with_prefix(&self, session: &Session, mesh: &Mesh, prefix: &str) -> Result<(Vec<f64>, SolveStats)> {
        let nm = self.num_unknowns();
        let (size, rank) = (session.size(), session.rank());
        let rows = (rank * nm / size)..((rank + 1) * nm / size);
        let r = self.assemble(mesh, rows);
        let matrix = Matrix::from_csr_rows(
            session,
            session.world(),
            nm,
            r.first_row,
            &r.indptr,
            &r.indices,
            &r.values,
            1,
            true,
        )?;
        let mut b = matrix.create_vector()?;
        b.set_owned(&r.rhs)?;
        let mut x = matrix.create_vector()?;
        let mut ksp = LinearSolver::new(session, session.world(), prefix)?;
        // MUMPS orders the HCT system much better with PORD than with the AMF default of the
        // primal (1e5 dual dofs: factorisation 0.87 s against 1.78 s, measured): the user's
        // -mat_mumps_icntl_7 still wins.
        ksp.prefer_ordering(4);
        ksp.set_operator(&matrix)?;
        let stats = ksp.solve(&matrix, &b, &mut x)?;
        let z = x.gather_all()?;
        Ok((self.affine.expand(&z), stats))
    }

    /// Solve with the constraints `constraints` imposed as asked: eliminated
    /// ([`DualSystem::solve_with_prefix`]) or by multipliers
    /// ([`DualSystem::solve_saddle_point`]).
    pub fn solve_with(
        &self,
        session: &Session,
        mesh: &Mesh,
        prefix: &str,
        constraints: DualConstraints,
    ) -> Result<(Vec<f64>, SolveStats)> {
        match constraints {
            DualConstraints::Eliminated => self.solve_with_prefix(session, mesh, prefix),
            DualConstraints::Multipliers => self.solve_saddle_point(session, mesh, prefix),
        }
    }

    /// The stress field of the dofs `phi`.
    pub fn field<'a>(&'a self, mesh: &'a Mesh, phi: &'a [f64]) -> DualField<'a> {
        DualField { system: self, mesh, phi }
    }
}

/// A solved dual stress field, cell by cell.
pub struct DualField<'a> {
    /// The dual system the dofs belong to.
    pub system: &'a DualSystem,
    /// The mesh.
    pub mesh: &'a Mesh,
    /// All HCT dofs of the Airy stress function φ.
    pub phi: &'a [f64],
}

impl DualField<'_> {
    fn local(&self, cell: usize) -> [f64; HCT_DOFS] {
        self.system.dofs.cell_dofs(self.mesh, cell).map(|d| self.phi[d])
    }

    /// The cell's dofs minus those of the affine function `a` that matches φ and ∇φ at its first
    /// vertex (an affine function has no stress, so the stress is unchanged).
    ///
    /// Why: φ grows as `σ L²` over the body, its gradient as `σ L`, while the stress is a
    /// second derivative over cells of size `h`: from the dofs themselves the evaluation sums
    /// terms of size `|φ| / h²` to a stress `σ`, losing `ε (L/h)²` (relative). The deviations
    /// are differences of neighbouring values, `φ_k − φ_0 ~ σ L h` and `∇φ_k − ∇φ_0 ~ σ h`,
    /// computed without cancellation: the loss falls to `ε L/h`. Measured on the contact patch
    /// with a Gmsh zone refined to h = 0.002 in a body of size 2: the interior equilibrium and
    /// stress jumps of the check fell from 2.3e-8 and 1.1e-8 of the stress (refused) to
    /// round-off.
    fn local_deviation(&self, cell: usize) -> [f64; HCT_DOFS] {
        let mut local = self.local(cell);
        let v = self.mesh.cell(cell);
        let x0 = self.mesh.nodes[v[0]];
        let g = [local[1], local[2]];
        let phi0 = local[0];
        for k in 0..3 {
            let x = self.mesh.nodes[v[k]];
            let d = [x[0] - x0[0], x[1] - x0[1]];
            local[3 * k] = (local[3 * k] - phi0) - (g[0] * d[0] + g[1] * d[1]);
            local[3 * k + 1] -= g[0];
            local[3 * k + 2] -= g[1];
        }
        let sign = self.system.dofs.edge_signs(self.mesh, cell);
        for k in 0..3 {
            let (p, q) = (self.mesh.nodes[v[k]], self.mesh.nodes[v[(k + 1) % 3]]);
            let d = [q[0] - p[0], q[1] - p[1]];
            let len = d[0].hypot(d[1]);
            let n = [sign[k] * d[1] / len, -sign[k] * d[0] / len];
            local[9 + k] -= n[0] * g[0] + n[1] * g[1];
        }
        local
    }

    /// φ, φ,x, φ,y at `x` in cell `cell`.
    pub fn airy(&self, cell: usize, x: [f64; 2]) -> [f64; 3] {
        let e = &self.system.elements[cell];
        let piece = e.locate(x);
        let local = self.local(cell);
        let v = e.values(piece, x);
        let g = e.gradients(piece, x);
        [
            v.iter().zip(&local).map(|(a, b)| a * b).sum(),
            g.iter().zip(&local).map(|(a, b)| a[0] * b).sum(),
            g.iter().zip(&local).map(|(a, b)| a[1] * b).sum(),
        ]
    }

    /// The stress at `x` of cell `cell` (the piece containing it).
    pub fn stress_at(&self, cell: usize, x: [f64; 2]) -> [f64; 3] {
        self.stress(cell, self.system.elements[cell].locate(x), x)
    }

    /// Stress at every mesh node: the average over the cells around it.
    pub fn nodal_stress(&self) -> Vec<[f64; 3]> {
        let n = self.mesh.num_nodes();
        let (mut sum, mut count) = (vec![[0.0; 3]; n], vec![0usize; n]);
        for c in 0..self.mesh.num_cells() {
            for &node in self.mesh.cell(c) {
                let s = self.stress_at(c, self.mesh.nodes[node]);
                for k in 0..3 {
                    sum[node][k] += s[k];
                }
                count[node] += 1;
            }
        }
        for (s, &k) in sum.iter_mut().zip(&count) {
            if k > 0 {
                s.iter_mut().for_each(|v| *v /= k as f64);
            }
        }
        sum
    }

    /// φ at every mesh node (mid-edge nodes evaluated in a cell around them).
    pub fn nodal_airy(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.mesh.num_nodes()];
        for c in 0..self.mesh.num_cells() {
            for &node in self.mesh.cell(c) {
                out[node] = self.airy(c, self.mesh.nodes[node])[0];
            }
        }
        out
    }
}

impl StressField for DualField<'_> {
    fn pieces(&self, cell: usize) -> Vec<[[f64; 2]; 3]> {
        self.system.elements[cell].pieces().to_vec()
    }
    fn stress(&self, cell: usize, piece: usize, x: [f64; 2]) -> [f64; 3] {
        let local = self.local_deviation(cell);
        let mut s = self.system.body_force.particular(x);
        for (b, v) in self.system.elements[cell].stresses(piece, x).iter().zip(&local) {
            for k in 0..3 {
                s[k] += b[k] * v;
            }
        }
        s
    }
}
