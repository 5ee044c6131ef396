//! # The local parametrisation of the contact part (no dense block)
//!
//! With the contact forces `r` as unknowns ([`super::boundary::eliminate`]) the Airy function's
//! boundary values are the tractions integrated along the boundary from a starting point
//! (`d(φ,y)/ds = t_x`, `d(φ,x)/ds = −t_y`, F. Lebon's talk "Formulation en contraintes"): at
//! the k-th vertex of a contact run `∇φ` and `φ` depend on every force upstream in the run, and
//! every boundary dof downstream of the run on all of them. The reduced matrix then has dense
//! columns coupling every contact force to the whole rest of the boundary, which the assembly
//! and the factorisation with the Schur complement on `r` pay for.
//!
//! Passing a force changes `φ` downstream by an affine function (the jump of `∇φ` is the
//! force turned by a right angle, the jump of `φ` adds its moment):
//!
//! ```text
//!   upstream ─ v0 ─── v1 ─── v2 ─── … ─── vM ─ downstream (known tractions)
//!              │ contact run: forces r_1 … r_M (4 per edge)  │
//!   φ = base + ξ on the run,  base(x) = φ(v0) + ∇φ(v0)·(x − x0)   (affine: no traction)
//!   downstream: integrated from vM's (φ, ∇φ) = base(vM) + ξ_M   → local in ξ
//! ```
//!
//! So the unknowns of the run are taken to be the deviations `ξ` of the run's own dofs from
//! the affine base of its first vertex (per edge `a → b`: `∇φ(b)`, `φ(b)` and the midpoint
//! `φ,n`, four unknowns, as many as the edge's forces). The base satisfies the four traction
//! conditions of an edge with zero force (an affine φ has no stress), so those conditions,
//! linear, hold for the deviations alone:
//!
//! ```text
//!   M_e [ξ_b; ξ_a] + D_e r_e = 0   ⇒   r_e = −D_e⁻¹ M_e [ξ_b; ξ_a] = R_e [ξ_b; ξ_a]
//! ```
//!
//! (`ξ_a = 0` at `v0`; `D_e` is invertible when the contact frame is, `M_e`'s own block when
//! the normal and the tangent of the edge are independent). Every dof is then an affine
//! function of the free HCT dofs `z` and of `ξ` with a bounded number of terms: the reduced
//! matrix has rows whose length does not grow with the number of contact points, the
//! three columns of the base being the only long ones (as without contact).
//!
//! The admissible set of `(φ, r)` is unchanged, and `r = B ξ` with `B` block lower bidiagonal
//! (4 × 4 diagonal blocks `R_e`'s own part, invertible). The complementary energy in `(z, ξ)`,
//! minimised over `z`, is `½ ξᵀ S ξ − (b_ξ + ℓ_ξ)ᵀ ξ` (`S` the Schur complement on `ξ`, `ℓ_ξ`
//! the load condensed onto them), so with `ξ = B⁻¹ r` the condensed problem on the forces is
//!
//! ```text
//!   W = B⁻ᵀ S B⁻¹,      u_free = −B⁻ᵀ (b_ξ + ℓ_ξ),
//! ```
//!
//! the same `W` and `u_free` as with the forces as unknowns (a change of variables of the
//! Schur block and a shift of `z`), each product with `B⁻¹` or `B⁻ᵀ` one block substitution
//! along the runs. The contact displacement (the multiplier of the forces) is recovered from
//! the assembled matrix as `B⁻ᵀ (A x − b)_ξ`.
//!
//! The boundary walk starts where a contact run starts when no edge has a prescribed
//! displacement component, so no contact edge closes it and the parametrisation applies to every
//! scene the dual accepts (a contact part that is the whole boundary is refused). Should it still
//! fail ([`super::DualSystem::local_fallback`] keeps why), or with `-dual_contact_local false`, the
//! Schur route keeps the contact forces as unknowns, with their dense boundary block (slower, the
//! same answer), and the report's contact notes say so.
use nalgebra::{DMatrix, Matrix4};

use super::boundary::{AffineDofs, EdgeForceMap};
use crate::error::{Error, Result};

/// The local parametrisation of a dual problem with contact: the affine map from `(z, ξ)` to
/// the HCT dofs, and the block bidiagonal map `B` from `ξ` to the contact forces.
#[derive(Debug, Clone)]
pub struct LocalContact {
    /// The reduced unknowns are the free HCT dofs, then the deviations `ξ` (`num_contact`,
    /// as many as the forces; slot `first + k` of an edge's [`EdgeForceMap`]).
    pub affine: AffineDofs,
    /// The contact edges in walk order (a run's edges follow each other).
    edges: Vec<EdgeForceMap>,
    /// The inverse of each edge's own 4 × 4 block of `B`.
    own_inverse: Vec<Matrix4<f64>>,
}

impl LocalContact {
    /// The parametrisation from the affine map and the contact edges' force maps; an error if an
    /// edge's own block of `B` is singular.
    pub fn new(affine: AffineDofs, edges: Vec<EdgeForceMap>) -> Result<Self> {
        let own_inverse = edges
            .iter()
            .map(|e| {
                e.map.fixed_columns::<4>(0).into_owned().try_inverse().ok_or_else(|| Error::Formulation {
                    message: "dual formulation: a contact edge's forces do not determine its Airy dofs".into(),
                    hint: "report this mesh: it should not happen".into(),
                })
            })
            .collect::<Result<Vec<_>>>()?;
        if edges.len() * 4 != affine.num_contact {
            return Err(Error::Formulation {
                message: format!(
                    "dual formulation: {} contact edges for {} contact unknowns",
                    edges.len(),
                    affine.num_contact
                ),
                hint: "report this mesh: it should not happen".into(),
            });
        }
        Ok(LocalContact { affine, edges, own_inverse })
    }

    /// Number of contact unknowns (forces, deviations).
    pub fn len(&self) -> usize {
        self.affine.num_contact
    }

    /// Whether there are no contact unknowns.
    pub fn is_empty(&self) -> bool {
        self.affine.num_contact == 0
    }

    /// Correct the deviations `ξ` by the least change that makes them meet the closure
    /// conditions of the boundary integration in this parametrisation exactly (to round-off):
    /// `ξ ← ξ − Cᵀ (C Cᵀ)⁻¹ (C ξ − c)`, `C ξ = c` the rows of `affine.contact_equilibrium`.
    /// Returns the largest relative closure residual before and after (relative to
    /// `|c_i| + Σ_j |C_ij ξ_j|`).
    ///
    /// Why: the forces balance the loads (`E r = e`, [`super::equilibrium`]), but `ξ = B⁻¹ r`
    /// is a substitution along the whole contact run, whose round-off the field's closure meets
    /// on the one edge where the boundary integration closes, as a traction error of the moment
    /// residual over `h²`: 4.8e-9 of the pressure on the contact patch at 1.05e5 unknowns
    /// (h = 0.0115, a moment residual of 3e-14), growing as the mesh is refined. The correction
    /// is of that round-off's size.
    pub fn balance(&self, xi: &mut [f64]) -> (f64, f64) {
        let rows = &self.affine.contact_equilibrium;
        let relative = |xi: &[f64]| {
            let (mut worst, mut scale) = (0.0f64, 0.0f64);
            for (terms, c) in rows {
                let value: f64 = terms.iter().map(|&(j, a)| a * xi[j]).sum::<f64>() - c;
                scale = scale.max(c.abs() + terms.iter().map(|&(j, a)| (a * xi[j]).abs()).sum::<f64>());
                worst = worst.max(value.abs());
            }
            worst / scale.max(f64::MIN_POSITIVE)
        };
        let before = relative(xi);
        let k = rows.len();
        if k == 0 {
            return (before, before);
        }
        let mut columns: Vec<usize> = rows.iter().flat_map(|(terms, _)| terms.iter().map(|t| t.0)).collect();
        columns.sort_unstable();
        columns.dedup();
        let c = nalgebra::DMatrix::from_fn(k, columns.len(), |i, a| {
            rows[i].0.iter().filter(|t| t.0 == columns[a]).map(|t| t.1).sum::<f64>()
        });
        let residual = nalgebra::DVector::from_iterator(
            k,
            rows.iter().map(|(terms, c)| terms.iter().map(|&(j, a)| a * xi[j]).sum::<f64>() - c),
        );
        let Some(cholesky) = (&c * c.transpose()).cholesky() else { return (before, before) };
        let correction = c.transpose() * cholesky.solve(&residual);
        let mut corrected = xi.to_vec();
        for (a, &j) in columns.iter().enumerate() {
            corrected[j] -= correction[a];
        }
        let after = relative(&corrected);
        if after < before {
            xi.copy_from_slice(&corrected);
            return (before, after);
        }
        (before, before)
    }

    /// `r = B ξ`.
    pub fn forces(&self, xi: &[f64]) -> Vec<f64> {
        let mut r = vec![0.0; self.len()];
        for e in &self.edges {
            let local = self.gather(e, xi);
            for (i, ri) in r[e.first..e.first + 4].iter_mut().enumerate() {
                *ri = (0..7).map(|j| e.map[(i, j)] * local[j]).sum();
            }
        }
        r
    }

    /// `ξ = B⁻¹ r`: forward substitution along the runs.
    pub fn deviations(&self, r: &[f64]) -> Vec<f64> {
        let mut xi = vec![0.0; self.len()];
        for (e, inverse) in self.edges.iter().zip(&self.own_inverse) {
            let mut rhs = [0.0; 4];
            for (i, v) in rhs.iter_mut().enumerate() {
                *v = r[e.first + i];
                if let Some(p) = e.prev {
                    *v -= (0..3).map(|j| e.map[(i, 4 + j)] * xi[p + j]).sum::<f64>();
                }
            }
            for i in 0..4 {
                xi[e.first + i] = (0..4).map(|j| inverse[(i, j)] * rhs[j]).sum();
            }
        }
        xi
    }

    /// `y = B⁻ᵀ v`: backward substitution along the runs.
    pub fn transpose_solve(&self, v: &[f64]) -> Vec<f64> {
        let mut acc = v.to_vec();
        let mut y = vec![0.0; self.len()];
        for (e, inverse) in self.edges.iter().zip(&self.own_inverse).rev() {
            let own: [f64; 4] = std::array::from_fn(|i| acc[e.first + i]);
            for i in 0..4 {
                y[e.first + i] = (0..4).map(|j| inverse[(j, i)] * own[j]).sum();
            }
            if let Some(p) = e.prev {
                for j in 0..3 {
                    acc[p + j] -= (0..4).map(|i| e.map[(i, 4 + j)] * y[e.first + i]).sum::<f64>();
                }
            }
        }
        y
    }

    /// `W = B⁻ᵀ S B⁻¹` for a symmetric `S` (symmetrised).
    pub fn congruence(&self, s: &DMatrix<f64>) -> DMatrix<f64> {
        let m = self.len();
        // Y = B⁻ᵀ S, column by column; then W = B⁻ᵀ Yᵀ (S symmetric: Yᵀ = S B⁻¹).
        let mut y = DMatrix::<f64>::zeros(m, m);
        for j in 0..m {
            let column: Vec<f64> = s.column(j).iter().copied().collect();
            y.set_column(j, &nalgebra::DVector::from_vec(self.transpose_solve(&column)));
        }
        let mut w = DMatrix::<f64>::zeros(m, m);
        for i in 0..m {
            let row: Vec<f64> = y.row(i).iter().copied().collect();
            w.set_column(i, &nalgebra::DVector::from_vec(self.transpose_solve(&row)));
        }
        DMatrix::from_fn(m, m, |i, j| 0.5 * (w[(i, j)] + w[(j, i)]))
    }

    fn gather(&self, e: &EdgeForceMap, xi: &[f64]) -> [f64; 7] {
        let mut local = [0.0; 7];
        local[..4].copy_from_slice(&xi[e.first..e.first + 4]);
        if let Some(p) = e.prev {
            local[4..].copy_from_slice(&xi[p..p + 3]);
        }
        local
    }
}

#[cfg(test)]
mod tests {
    use super::super::system::{BodyLoad, ContactSide, DualData, DualSystem};
    use crate::fem::assembly::{EdgeLoad, Traction};
    use crate::fem::material::{Material, PlaneModel};
    use crate::mesh::{structured, Mesh, Order};

    /// The square block of the benchmark (pressure on top and left, `ux = 0` on the right,
    /// contact at the bottom), `n × n` cells.
    fn block(n: usize) -> (Mesh, DualSystem) {
        let mesh = structured::rectangle([0.0, 0.0], [0.04, 0.04], n, n, Order::P1).expect("mesh");
        let group = |name: &str| mesh.require_group(name, 1).expect("group");
        let loads = [
            EdgeLoad { group: group("top"), traction: Traction::Pressure(5e7) },
            EdgeLoad { group: group("left"), traction: Traction::Pressure(1.5e8) },
        ];
        let prescribed = [(group("right"), [Some(0.0), None])];
        let normal = |_: [f64; 2]| [0.0, -1.0];
        let data = DualData {
            body_force: BodyLoad::Constant([0.0, 0.0]),
            edge_loads: &loads,
            prescribed: &prescribed,
            contact: Some(ContactSide { group: group("bottom"), normal: &normal }),
        };
        let system = DualSystem::new(&mesh, &Material::new(1.3e11, 0.2, PlaneModel::Strain), &data).expect("system");
        (mesh, system)
    }

    /// A block held by the contact alone (pressures on the other three sides, no Dirichlet part)
    /// with the contact on side `contact` ("all": the whole boundary, one group).
    fn floating(contact: &str) -> crate::error::Result<DualSystem> {
        let mut mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 6, 3, Order::P1).expect("mesh");
        if contact == "all" {
            let bottom = mesh.require_group("bottom", 1).expect("group");
            mesh.edge_group.fill(bottom);
        }
        let side = if contact == "all" { "bottom" } else { contact };
        let group = |name: &str| mesh.require_group(name, 1).expect("group");
        let loads: Vec<EdgeLoad> = ["bottom", "right", "top", "left"]
            .into_iter()
            .filter(|&s| s != side && contact != "all")
            .map(|s| EdgeLoad { group: group(s), traction: Traction::Pressure(1e6) })
            .collect();
        let normal = |_: [f64; 2]| [0.0, -1.0];
        let data = DualData {
            body_force: BodyLoad::Constant([0.0, -7.7e4]),
            edge_loads: &loads,
            prescribed: &[],
            contact: Some(ContactSide { group: group(side), normal: &normal }),
        };
        DualSystem::new(&mesh, &Material::new(9e10, 0.2, PlaneModel::Strain), &data)
    }

    /// Without any Dirichlet part the boundary loop starts at the lowest-numbered boundary node,
    /// (0, 0) on the structured mesh, and the left side, walked downwards, ends there. The walk
    /// starts where the contact run starts, wherever the loop does: the contact on the left
    /// gets its local parametrisation like the one at the bottom (until 2026-11-26 the walk
    /// started with the loop, the left contact closed it and fell back to the forces as unknowns,
    /// where its last edge's forces had a zero flexibility).
    #[test]
    fn a_contact_run_at_the_end_of_the_loop_gets_its_local_parametrisation() {
        for side in ["bottom", "left", "top"] {
            let system = floating(side).expect("system");
            assert!(system.local.is_some() && system.local_fallback.is_none(), "{side}: {:?}", system.local_fallback);
            assert_eq!(system.local.as_ref().map(|l| l.len()), Some(4 * if side == "left" { 3 } else { 6 }));
        }
    }

    /// A contact part that is the whole boundary is refused with its reason (the walk would close
    /// through a contact edge whichever edge it starts at).
    #[test]
    fn a_contact_part_on_the_whole_boundary_is_refused() {
        let error = floating("all").err().expect("refused");
        let text = error.to_string();
        assert!(text.contains("the contact part is the whole boundary") && text.contains("hint:"), "{text}");
    }

    fn row_lengths(indptr: &[usize]) -> Vec<usize> {
        indptr.windows(2).map(|w| w[1] - w[0]).collect()
    }

    /// The structure the local parametrisation is for: the rows of the contact unknowns and all
    /// but a few rows (the affine base's dofs, long also without contact) stay short whatever
    /// the number of contact points, while with the forces as unknowns every force row couples
    /// to all the forces upstream and to the whole boundary downstream.
    #[test]
    fn local_rows_do_not_grow_with_the_contact_points() {
        let mut longest_contact_rows = Vec::new();
        for n in [8, 32] {
            let (mesh, system) = block(n);
            let local = system.local.as_ref().expect("the block has a local parametrisation");
            let nm = local.affine.num_unknowns();
            let nz = local.affine.num_masters;
            assert_eq!(nm, system.num_unknowns());
            assert_eq!(local.len(), 4 * n);
            let rows = system.assemble_in(&local.affine, &mesh, 0..nm);
            let lengths = row_lengths(&rows.indptr);
            let longest = *lengths[nz..].iter().max().expect("contact rows");
            longest_contact_rows.push(longest);
            assert!(longest <= 40, "{n} cells: a contact row has {longest} entries");
            let long = lengths.iter().filter(|&&l| l > 60).count();
            assert!(long <= 6, "{n} cells: {long} rows longer than 60");
            // With the forces as unknowns the last force row sees every other force.
            let forces = system.assemble(&mesh, 0..nm);
            let force_rows = row_lengths(&forces.indptr);
            assert!(*force_rows[nz..].iter().max().expect("force rows") >= 4 * n);
            assert!(forces.indices.len() > rows.indices.len());
        }
        assert_eq!(longest_contact_rows[0], longest_contact_rows[1]);
    }

    /// `B⁻¹` and `B⁻ᵀ` invert `B` and its transpose.
    #[test]
    fn force_map_substitutions_invert_it() {
        let (_, system) = block(6);
        let local = system.local.as_ref().expect("local parametrisation");
        let m = local.len();
        let r: Vec<f64> = (0..m).map(|k| ((k * 7919) % 13) as f64 - 6.0).collect();
        let xi = local.deviations(&r);
        let back = local.forces(&xi);
        let scale = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(r.iter().zip(&back).all(|(a, b)| (a - b).abs() <= 1e-12 * scale));
        // ⟨B⁻ᵀ v, r⟩ = ⟨v, B⁻¹ r⟩.
        let v: Vec<f64> = (0..m).map(|k| ((k * 104729) % 17) as f64 - 8.0).collect();
        let y = local.transpose_solve(&v);
        let left: f64 = y.iter().zip(&r).map(|(a, b)| a * b).sum();
        let right: f64 = v.iter().zip(&xi).map(|(a, b)| a * b).sum();
        assert!((left - right).abs() <= 1e-10 * left.abs().max(right.abs()), "{left} against {right}");
        // W = B⁻ᵀ S B⁻¹ on the identity: (B Bᵀ)⁻¹, symmetric.
        let w = local.congruence(&nalgebra::DMatrix::identity(m, m));
        let bbt_w = {
            let b = nalgebra::DMatrix::from_fn(m, m, |i, j| {
                let mut e = vec![0.0; m];
                e[j] = 1.0;
                local.forces(&e)[i]
            });
            &b * b.transpose() * &w
        };
        assert!((bbt_w - nalgebra::DMatrix::<f64>::identity(m, m)).amax() < 1e-8);
    }
}
