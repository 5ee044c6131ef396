//! Point location in a triangle mesh: which cell holds a point.
//!
//! A uniform grid of buckets over the mesh's bounding box (about one cell per bucket); each
//! cell is registered in the buckets its bounding box (of all its nodes, so curved P2 cells are
//! covered) overlaps. A query tests the cells of the point's bucket with the barycentric
//! coordinates `λ` of the vertex triangle and returns the first with `min λ ≥ −tol`. Meshes of the
//! same domain at different sizes are nested only approximately (curved boundaries: a fine
//! point may lie just outside every coarse cell), so when no cell holds the point the one with
//! the largest `min λ` among the bucket's and its neighbours' cells is returned: the coarse
//! fields are then extrapolated over a sliver of width O(h²).
use crate::mesh::Mesh;

/// Finds the cell of a mesh holding a point (a bucket grid over the cells), for transferring fields
/// between meshes.
pub struct Locator<'m> {
    mesh: &'m Mesh,
    lo: [f64; 2],
    cell: [f64; 2],
    n: [usize; 2],
    buckets: Vec<Vec<usize>>,
}

fn barycentric(t: &[[f64; 2]; 3], x: [f64; 2]) -> [f64; 3] {
    let det = (t[1][0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (t[1][1] - t[0][1]);
    let l1 = ((x[0] - t[0][0]) * (t[2][1] - t[0][1]) - (t[2][0] - t[0][0]) * (x[1] - t[0][1])) / det;
    let l2 = ((t[1][0] - t[0][0]) * (x[1] - t[0][1]) - (x[0] - t[0][0]) * (t[1][1] - t[0][1])) / det;
    [1.0 - l1 - l2, l1, l2]
}

impl<'m> Locator<'m> {
    /// The locator of `mesh`'s cells.
    pub fn new(mesh: &'m Mesh) -> Self {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in &mesh.nodes {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let cells = mesh.num_cells().max(1) as f64;
        let span = [(hi[0] - lo[0]).max(f64::MIN_POSITIVE), (hi[1] - lo[1]).max(f64::MIN_POSITIVE)];
        let side = (span[0] * span[1] / cells).sqrt().max(1e-300);
        let n = [((span[0] / side).ceil() as usize).clamp(1, 4096), ((span[1] / side).ceil() as usize).clamp(1, 4096)];
        let cell = [span[0] / n[0] as f64, span[1] / n[1] as f64];
        let mut locator = Locator { mesh, lo, cell, n, buckets: vec![Vec::new(); n[0] * n[1]] };
        for c in 0..mesh.num_cells() {
            let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for &v in mesh.cell(c) {
                for k in 0..2 {
                    a[k] = a[k].min(mesh.nodes[v][k]);
                    b[k] = b[k].max(mesh.nodes[v][k]);
                }
            }
            let (i0, j0) = locator.bucket(a);
            let (i1, j1) = locator.bucket(b);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    locator.buckets[j * n[0] + i].push(c);
                }
            }
        }
        locator
    }

    fn bucket(&self, x: [f64; 2]) -> (usize, usize) {
        let idx = |k: usize| (((x[k] - self.lo[k]) / self.cell[k]).floor().max(0.0) as usize).min(self.n[k] - 1);
        (idx(0), idx(1))
    }

    fn vertices(&self, c: usize) -> [[f64; 2]; 3] {
        let v = self.mesh.cell(c);
        [self.mesh.nodes[v[0]], self.mesh.nodes[v[1]], self.mesh.nodes[v[2]]]
    }

    /// Test cell `c` for `x`: true when it holds `x`; else keep it in `best` if it is the
    /// nearest to holding it so far.
    fn test(&self, c: usize, x: [f64; 2], best: &mut Option<(usize, f64)>) -> bool {
        let l = barycentric(&self.vertices(c), x);
        let m = l[0].min(l[1]).min(l[2]);
        if m >= -1e-12 {
            *best = Some((c, m));
            return true;
        }
        if best.is_none_or(|(_, b)| m > b) {
            *best = Some((c, m));
        }
        false
    }

    /// The cell holding `x` (or the nearest to holding it); `None` only for an empty mesh.
    pub fn locate(&self, x: [f64; 2]) -> Option<usize> {
        let (i, j) = self.bucket(x);
        let mut best: Option<(usize, f64)> = None;
        for &c in &self.buckets[j * self.n[0] + i] {
            if self.test(c, x, &mut best) {
                return Some(c);
            }
        }
        // Outside every cell of the bucket: widen the search ring by ring, until some cell was
        // seen and one more ring has been searched.
        let mut extra = 1;
        for ring in 1..=self.n[0].max(self.n[1]) {
            let (i0, i1) = (i.saturating_sub(ring), (i + ring).min(self.n[0] - 1));
            let (j0, j1) = (j.saturating_sub(ring), (j + ring).min(self.n[1] - 1));
            for jj in j0..=j1 {
                for ii in i0..=i1 {
                    if ii.abs_diff(i) != ring && jj.abs_diff(j) != ring {
                        continue;
                    }
                    for &c in &self.buckets[jj * self.n[0] + ii] {
                        if self.test(c, x, &mut best) {
                            return Some(c);
                        }
                    }
                }
            }
            if best.is_some() {
                if extra == 0 {
                    break;
                }
                extra -= 1;
            }
        }
        best.map(|(c, _)| c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{structured, Order};

    #[test]
    fn every_centroid_is_found_in_its_own_cell_and_outside_points_near_the_boundary() {
        let mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 7, 5, Order::P2).unwrap();
        let locator = Locator::new(&mesh);
        for c in 0..mesh.num_cells() {
            let t = locator.vertices(c);
            let g = [(t[0][0] + t[1][0] + t[2][0]) / 3.0, (t[0][1] + t[1][1] + t[2][1]) / 3.0];
            assert_eq!(locator.locate(g), Some(c));
        }
        // Just outside the right edge: a cell touching it.
        let c = locator.locate([2.0 + 1e-6, 0.5]).unwrap();
        assert!(locator.vertices(c).iter().any(|v| (v[0] - 2.0).abs() < 1e-12));
    }
}
