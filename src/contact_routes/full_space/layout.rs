//! The global numbering of the mixed unknowns `(u, λ)` over the MPI ranks (see the parent
//! module's documentation, "Layout over MPI ranks").
use std::ops::Range;

/// The global numbering of the mixed unknowns (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct MixedLayout {
    blocks: Vec<RankBlock>,
    per_point: usize,
}

#[derive(Debug, Clone, PartialEq)]
struct RankBlock {
    dofs: Range<usize>,
    points: Range<usize>,
    offset: usize,
}

impl MixedLayout {
    /// `dof_ranges[r]`: the displacement dofs rank `r` owns (contiguous, in rank order, each
    /// a whole number of nodes); `contact_nodes`: the node of each contact point, increasing;
    /// `per_point`: contact unknowns per point (1 without friction, 2 with).
    pub fn new(dof_ranges: &[Range<usize>], contact_nodes: &[usize], per_point: usize) -> Self {
        let mut offset = 0;
        let blocks = dof_ranges
            .iter()
            .map(|d| {
                let lo = contact_nodes.partition_point(|&k| 2 * k < d.start);
                let hi = contact_nodes.partition_point(|&k| 2 * k < d.end);
                let block = RankBlock { dofs: d.clone(), points: lo..hi, offset };
                offset += d.len() + per_point * (hi - lo);
                block
            })
            .collect();
        MixedLayout { blocks, per_point }
    }

    /// Number of unknowns of the mixed system.
    pub fn global_size(&self) -> usize {
        self.blocks.last().map_or(0, |b| b.offset + b.dofs.len() + self.per_point * b.points.len())
    }

    /// The unknowns rank `rank` owns.
    pub fn owned(&self, rank: usize) -> Range<usize> {
        let b = &self.blocks[rank];
        b.offset..b.offset + b.dofs.len() + self.per_point * b.points.len()
    }

    /// The contact points rank `rank` owns.
    pub fn points(&self, rank: usize) -> Range<usize> {
        self.blocks[rank].points.clone()
    }

    /// Global index of displacement dof `dof`.
    pub fn u(&self, dof: usize) -> usize {
        let b = &self.blocks[self.blocks.partition_point(|b| b.dofs.end <= dof)];
        b.offset + dof - b.dofs.start
    }

    /// Global index of component `k` (0 normal, 1 tangential) of contact point `i`.
    pub fn lambda(&self, i: usize, k: usize) -> usize {
        let b = &self.blocks[self.blocks.partition_point(|b| b.points.end <= i)];
        b.offset + b.dofs.len() + self.per_point * (i - b.points.start) + k
    }
}

/// The owned displacement dofs of every rank, as the driver partitions the nodes.
pub fn dof_ranges(num_nodes: usize, ranks: usize) -> Vec<Range<usize>> {
    (0..ranks).map(|r| 2 * (num_nodes * r / ranks)..2 * (num_nodes * (r + 1) / ranks)).collect()
}

#[cfg(test)]
mod tests {
    use super::{dof_ranges, MixedLayout};

    #[test]
    fn layout_interleaves_rank_blocks() {
        // 10 nodes on 2 ranks (nodes 0..5 and 5..10); contact nodes 1, 4, 7 with friction.
        let ranges = dof_ranges(10, 2);
        assert_eq!(ranges, vec![0..10, 10..20]);
        let layout = MixedLayout::new(&ranges, &[1, 4, 7], 2);
        assert_eq!(layout.global_size(), 26);
        assert_eq!(layout.owned(0), 0..14);
        assert_eq!(layout.owned(1), 14..26);
        assert_eq!((layout.u(0), layout.u(9), layout.u(10), layout.u(19)), (0, 9, 14, 23));
        assert_eq!((layout.lambda(0, 0), layout.lambda(0, 1), layout.lambda(1, 0)), (10, 11, 12));
        assert_eq!((layout.lambda(2, 0), layout.lambda(2, 1)), (24, 25));
        assert_eq!((layout.points(0), layout.points(1)), (0..2, 2..3));
        // A dof of rank 1 comes after rank 0's multipliers: a mortar row of point 1 touching
        // node 5 is stored λ first (the parent module's `OwnedPoint::slots`).
        assert!(layout.u(10) > layout.lambda(1, 1));
        // Frictionless: one unknown per point; a rank with no contact point.
        let layout = MixedLayout::new(&ranges, &[7, 8], 1);
        assert_eq!((layout.owned(0), layout.owned(1)), (0..10, 10..22));
        assert_eq!((layout.lambda(0, 0), layout.lambda(1, 0)), (20, 21));
        // One rank: [u | λ].
        let layout = MixedLayout::new(&dof_ranges(10, 1), &[1, 4, 7], 1);
        assert_eq!((layout.global_size(), layout.u(19), layout.lambda(2, 0)), (23, 19, 22));
    }
}
