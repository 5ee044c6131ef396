//! The mixed system's rows before the iteration: the bodies and their rigid motions, the
//! augmentation of every contact point, the check of the contact nodes' stiffness blocks, each
//! point's rows of `B`, and the pattern of this rank's rows (force rows `K, −Bᵀ`, then the
//! contact rows), see the parent module's documentation ("Unknowns and equations", "The
//! augmentation ρ", "Layout over MPI ranks").
use std::collections::{HashMap, HashSet};
use std::ops::Range;

use nalgebra::DVector;

use super::mixed_system::{dof_rigid_row, OwnedPoint};
use super::{MixedLayout, AUGMENTATION};
use crate::contact::boundary::ContactBoundary;
use crate::error::{Error, Result};
use crate::fem::assembly::CsrRows;
use crate::fem::material::CellMaterials;
use crate::mesh::Mesh;
use crate::petsc::Comm;

/// The bodies for the rigid-motion rows: the centre and size of the whole mesh (positions are
/// scaled by them), and the piece (body) of every node — one piece with a rigid obstacle,
/// each connected piece of the mesh with contact pairs (each body moves on its own).
pub(crate) struct Pieces {
    centre: [f64; 2],
    pub extent: f64,
    pub piece_of: Vec<usize>,
    pub count: usize,
}

impl Pieces {
    pub fn of(mesh: &Mesh, coupled: bool) -> Self {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &mesh.nodes {
            for c in 0..2 {
                lo[c] = lo[c].min(p[c]);
                hi[c] = hi[c].max(p[c]);
            }
        }
        let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        let mut extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        if !(extent.is_finite() && extent > 0.0) {
            extent = 1.0;
        }
        let (piece_of, count) =
            if coupled { crate::mesh::pieces::node_pieces(mesh) } else { (vec![0; mesh.num_nodes()], 1) };
        Pieces { centre, extent, piece_of, count }
    }

    /// A position relative to the mesh's centre, in units of its size.
    pub fn scaled(&self, p: [f64; 2]) -> [f64; 2] {
        [(p[0] - self.centre[0]) / self.extent, (p[1] - self.centre[1]) / self.extent]
    }

    /// Row `k` (0 normal, 1 tangential) of a point's `B` entries applied to the rigid motions
    /// (3 per piece).
    pub fn rigid_row(&self, mesh: &Mesh, entries: &[(usize, [f64; 2])], k: usize) -> DVector<f64> {
        let mut r = DVector::<f64>::zeros(3 * self.count);
        for &(dof, coef) in entries {
            let node = dof / 2;
            let v = coef[k] * dof_rigid_row(dof, self.scaled(mesh.nodes[node]));
            for a in 0..3 {
                r[3 * self.piece_of[node] + a] += v[a];
            }
        }
        r
    }
}

/// The augmentation `ρ_i` of every point: `2 E' w_i / L`, with two bodies those of the point's
/// two sides in series, `2 w_i / (L_s/E'_s + L_m/E'_m)` (every rank knows every weight).
///
/// In axisymmetry a P2 vertex on the axis has `w_i = ∫ φ_i 2π r ds = 0` exactly on a straight
/// edge ([`crate::contact::boundary::AxisPressure`]), which would make `ρ_i = 0` and the point's
/// complementarity function degenerate; it takes the weight of the nearer node its pressure is
/// extrapolated from (any `ρ_i > 0` has the same solution; this one has the scale of its
/// neighbours').
pub(crate) fn augmentation(b: &ContactBoundary, mesh: &Mesh, materials: &CellMaterials, pieces: &Pieces) -> Vec<f64> {
    let (modulus, diameter) =
        piece_moduli_and_diameters(mesh, materials, &pieces.piece_of, pieces.count, pieces.extent);
    let compliance = |node: usize| diameter[pieces.piece_of[node]] / modulus[pieces.piece_of[node]];
    // A P2 vertex on the axis in axisymmetry (weight 0 on a straight edge, a small number of
    // either sign on a curved one) takes the weight of the nearer node its pressure is
    // extrapolated from (the module documentation of `full_space`); any other point of weight 0,
    // the smallest positive weight.
    let smallest = b.weight.iter().copied().filter(|&w| w > 0.0).fold(f64::INFINITY, f64::min);
    let weight = |i: usize| {
        let neighbour = b
            .axis_pressure
            .iter()
            .find(|a| a.node == b.nodes[i])
            .and_then(|a| b.nodes.iter().position(|&k| k == a.from[0].0))
            .map(|j| b.weight[j].max(b.weight[i]))
            .filter(|&w| w > 0.0);
        match neighbour {
            Some(w) => w,
            None if b.weight[i] > 0.0 => b.weight[i],
            None if smallest.is_finite() => smallest,
            None => 0.0,
        }
    };
    (0..b.points())
        .map(|i| {
            let other = b.coupled_to(i).first().map_or(0.0, |c| compliance(c.node));
            AUGMENTATION * weight(i) / (compliance(b.nodes[i]) + other)
        })
        .collect()
}

/// The smallest and the largest `ρ_i / w_i` over the points of positive weight (the notes).
pub(crate) fn augmentation_range(rho: &[f64], weight: &[f64]) -> (f64, f64) {
    rho.iter()
        .zip(weight)
        .filter(|(_, &w)| w > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), (r, w)| (lo.min(r / w), hi.max(r / w)))
}

/// Each piece's (body's) plane modulus (the largest of its cells') and diameter (the larger
/// side of its bounding box; `fallback` for a degenerate one).
fn piece_moduli_and_diameters(
    mesh: &Mesh,
    materials: &CellMaterials,
    piece_of: &[usize],
    pieces: usize,
    fallback: f64,
) -> (Vec<f64>, Vec<f64>) {
    let per_cell = mesh.order.nodes_per_cell();
    let mut modulus = vec![0.0f64; pieces];
    for c in 0..mesh.num_cells() {
        let piece = piece_of[mesh.cells[per_cell * c]];
        modulus[piece] = modulus[piece].max(materials.of(c).plane_modulus());
    }
    let mut lo = vec![[f64::INFINITY; 2]; pieces];
    let mut hi = vec![[f64::NEG_INFINITY; 2]; pieces];
    for (k, p) in mesh.nodes.iter().enumerate() {
        let piece = piece_of[k];
        for c in 0..2 {
            lo[piece][c] = lo[piece][c].min(p[c]);
            hi[piece][c] = hi[piece][c].max(p[c]);
        }
    }
    let diameter = (0..pieces)
        .map(|q| {
            let d = (hi[q][0] - lo[q][0]).max(hi[q][1] - lo[q][1]);
            if d.is_finite() && d > 0.0 {
                d
            } else {
                fallback
            }
        })
        .collect();
    (modulus, diameter)
}

/// The diagonal blocks of `K` at the owned contact nodes must be positive definite (in the
/// points' normal and tangential directions). Every rank takes the same decision (the first
/// bad node of any rank): an error returned by one rank alone would leave the others waiting
/// in the solver's setup.
pub(crate) fn check_contact_blocks(
    comm: Comm,
    k: &CsrRows,
    b: &ContactBoundary,
    my_points: Range<usize>,
    rho: &[f64],
    part: &str,
) -> Result<()> {
    let coupled = b.is_coupled();
    let mut bad_node = f64::INFINITY;
    for i in my_points {
        let node = b.nodes[i];
        let kb = [
            [k.get(2 * node, 2 * node), k.get(2 * node, 2 * node + 1)],
            [k.get(2 * node + 1, 2 * node), k.get(2 * node + 1, 2 * node + 1)],
        ];
        let quad =
            |v: [f64; 2]| v[0] * (kb[0][0] * v[0] + kb[0][1] * v[1]) + v[1] * (kb[1][0] * v[0] + kb[1][1] * v[1]);
        // A mortar point's slave entries are zero in a prescribed component (mortar/points.rs).
        let positive = |v: [f64; 2]| (coupled && v == [0.0, 0.0]) || quad(v) > 0.0;
        if !(positive(b.normal[i]) && positive(b.tangent[i]) && rho[i] > 0.0) {
            bad_node = node as f64;
            break;
        }
    }
    let bad_node = comm.min(&[bad_node])?[0];
    if bad_node.is_finite() {
        return Err(Error::mesh(
            format!("node {bad_node} of contact part '{part}'"),
            "its stiffness diagonal block is not positive definite: the node belongs to no element",
        ));
    }
    Ok(())
}

/// This rank's rows of the mixed system: their pattern (`indptr`, global `indices`), the
/// constant values (`base`: `K` and `−Bᵀ`; the contact rows are refilled at every Jacobian),
/// where the stabilisation springs go, and the owned contact points.
pub(crate) struct Pattern {
    pub indptr: Vec<usize>,
    pub indices: Vec<usize>,
    pub base: Vec<f64>,
    pub spring_positions: Vec<usize>,
    pub points: Vec<OwnedPoint>,
}

/// What [`Pattern::new`] reads besides the stiffness and the contact rows.
pub(crate) struct PatternInput<'a> {
    pub layout: &'a MixedLayout,
    pub owned_dofs: Range<usize>,
    pub per_point: usize,
    pub my_points: Range<usize>,
    /// The first unknown of this rank's block.
    pub block_start: usize,
    pub rho: &'a [f64],
    /// Does a stabilisation spring act at this dof (Jacobian only, while the contact leaves a
    /// rigid motion free)?
    pub spring_at: &'a dyn Fn(usize) -> bool,
    /// The force rows are evaluated from `K`'s own rows, never assembled (an elimination
    /// iterating in `(v, λ)` solves the steps): keep their diagonal entry alone.
    pub lean: bool,
}

impl Pattern {
    pub fn new(
        k: &CsrRows,
        b: &ContactBoundary,
        mesh: &Mesh,
        pieces: &Pieces,
        input: PatternInput<'_>,
    ) -> Result<Self> {
        let PatternInput { layout, owned_dofs, per_point, my_points, block_start, rho, spring_at, lean } = input;
        let m = b.points();
        // Each point's rows of B (every dof they touch: the point's node and, for a contact
        // pair, the master nodes), and for each dof the points whose rows touch it (the −Bᵀ
        // entries of the force rows; none in a lean pattern).
        let b_rows: Vec<Vec<(usize, [f64; 2])>> = (0..m).map(|i| point_row(b, i)).collect();
        let mut touching: HashMap<usize, Vec<(usize, [f64; 2])>> = HashMap::new();
        for (i, entries) in b_rows.iter().enumerate().filter(|_| !lean) {
            for &(dof, coef) in entries {
                touching.entry(dof).or_default().push((i, coef));
            }
        }
        // The force rows (K, −Bᵀ), then the contact rows.
        let mut indptr = vec![0usize];
        let mut indices: Vec<usize> = Vec::new();
        let mut base: Vec<f64> = Vec::new();
        let mut spring_positions = Vec::new();
        let mut row: Vec<(usize, f64)> = Vec::new();
        for dof in owned_dofs {
            let (cols, vals) = k.row(dof);
            row.clear();
            if lean {
                // The diagonal alone (a row with no entry may not be stored); its value is
                // never read (the force rows are evaluated from K, the steps eliminated).
                indices.push(layout.u(dof));
                base.push(0.0);
                indptr.push(indices.len());
                continue;
            }
            row.extend(cols.iter().zip(vals).map(|(&c, &v)| (layout.u(c), v)));
            for &(i, coef) in touching.get(&dof).map_or(&[][..], |v| v.as_slice()) {
                row.push((layout.lambda(i, 0), -coef[0]));
                if per_point == 2 {
                    row.push((layout.lambda(i, 1), -coef[1]));
                }
            }
            row.sort_unstable_by_key(|e| e.0);
            // No spring on a prescribed dof: its Dirichlet row stays as it is.
            if spring_at(dof) {
                let diagonal = layout.u(dof);
                let at = row.iter().position(|e| e.0 == diagonal).ok_or_else(|| {
                    Error::PetscUsage(format!("contact node {}: no diagonal stiffness entry in row {dof}", dof / 2))
                })?;
                spring_positions.push(indices.len() + at);
            }
            indices.extend(row.iter().map(|e| e.0));
            base.extend(row.iter().map(|e| e.1));
            indptr.push(indices.len());
        }
        let mut points = Vec::with_capacity(my_points.len());
        for i in my_points {
            let entries = &b_rows[i];
            // The row's columns in the order the Jacobian fills them (the dofs of `entries`,
            // then the multipliers), and where each sits in the stored, increasing row: under
            // MPI a master dof of a later rank comes after this rank's multipliers.
            let columns: Vec<usize> = entries
                .iter()
                .map(|&(dof, _)| layout.u(dof))
                .chain((0..per_point).map(|c| layout.lambda(i, c)))
                .collect();
            let mut sorted = columns.clone();
            sorted.sort_unstable();
            let slots: Vec<usize> = columns.iter().map(|c| sorted.partition_point(|s| s < c)).collect();
            let start = indices.len();
            for _ in 0..per_point {
                indices.extend(&sorted);
                base.extend(std::iter::repeat_n(0.0, sorted.len()));
                indptr.push(indices.len());
            }
            points.push(OwnedPoint {
                index: i,
                coefficients: entries.iter().map(|e| e.1).collect(),
                positions: Vec::new(),
                slots,
                rigid: [pieces.rigid_row(mesh, entries, 0), pieces.rigid_row(mesh, entries, 1)],
                gap: b.gap[i],
                rho: [rho[i]; 2],
                lambda: layout.lambda(i, 0) - block_start,
                row: layout.lambda(i, 0) - block_start,
                start,
            });
        }
        Ok(Pattern { indptr, indices, base, spring_positions, points })
    }
}

/// The dofs where the stabilisation springs act: the free dofs of the contact nodes, and with
/// contact pairs every free dof `B` touches (either side may be the body the contact holds).
pub(crate) fn spring_dofs_of<'a>(b: &'a ContactBoundary, spring_dofs: &[usize]) -> impl Fn(usize) -> bool + 'a {
    let coupled = b.is_coupled();
    let spring_set: HashSet<usize> = spring_dofs.iter().copied().collect();
    move |dof: usize| -> bool {
        if coupled {
            return spring_set.contains(&dof);
        }
        match b.nodes.binary_search(&(dof / 2)) {
            Ok(i) => b.prescribed[i].is_none_or(|(pc, _)| pc != dof % 2),
            Err(_) => false,
        }
    }
}

/// The entries of point `i`'s rows of `B`: each dof any of them touches, with its coefficients
/// in the normal and the tangential row (duplicates summed), by increasing dof.
fn point_row(b: &ContactBoundary, i: usize) -> Vec<(usize, [f64; 2])> {
    let mut entries: Vec<(usize, [f64; 2])> = Vec::new();
    for k in 0..2 {
        for (dof, v) in b.b_row(2 * i + k) {
            match entries.binary_search_by_key(&dof, |e| e.0) {
                Ok(at) => entries[at].1[k] += v,
                Err(at) => entries.insert(at, (dof, if k == 0 { [v, 0.0] } else { [0.0, v] })),
            }
        }
    }
    entries
}
