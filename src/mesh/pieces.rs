//! Connected pieces of a mesh: cells that share a node belong to the same piece.
use super::Mesh;

/// The piece of every node (`0 .. count`), numbered in order of their lowest node, and the
/// number of pieces. Nodes of no cell (which a valid mesh has none of) get their own piece.
pub fn node_pieces(mesh: &Mesh) -> (Vec<usize>, usize) {
    let n = mesh.num_nodes();
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut k: usize) -> usize {
        while parent[k] != k {
            parent[k] = parent[parent[k]];
            k = parent[k];
        }
        k
    }
    for c in 0..mesh.num_cells() {
        let cell = mesh.cell(c);
        let first = root(&mut parent, cell[0]);
        for &k in &cell[1..] {
            let r = root(&mut parent, k);
            if r != first {
                let (lo, hi) = (r.min(first), r.max(first));
                parent[hi] = lo;
            }
        }
    }
    let mut label = vec![usize::MAX; n];
    let mut pieces = vec![0; n];
    let mut count = 0;
    for (k, piece) in pieces.iter_mut().enumerate() {
        let r = root(&mut parent, k);
        if label[r] == usize::MAX {
            label[r] = count;
            count += 1;
        }
        *piece = label[r];
    }
    (pieces, count)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{structured, Order};

    #[test]
    fn two_separate_squares_are_two_pieces() {
        let a = structured::rectangle([0.0, 0.0], [1.0, 1.0], 2, 2, Order::P1).unwrap();
        let (pieces, count) = node_pieces(&a);
        assert_eq!(count, 1);
        assert!(pieces.iter().all(|&p| p == 0));
        // Append a shifted copy: nodes and cells renumbered, no shared node.
        let mut b = a.clone();
        let offset = a.num_nodes();
        b.nodes.extend(a.nodes.iter().map(|p| [p[0] + 5.0, p[1]]));
        b.cells.extend(a.cells.iter().map(|&k| k + offset));
        b.cell_group.extend(a.cell_group.iter().copied());
        let (pieces, count) = node_pieces(&b);
        assert_eq!(count, 2);
        assert!(pieces[..offset].iter().all(|&p| p == 0) && pieces[offset..].iter().all(|&p| p == 1));
    }
}
