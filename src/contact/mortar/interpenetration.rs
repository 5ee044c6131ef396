//! Pointwise interpenetration of the two sides of a pair, measured after the solve from the
//! displacement field alone.
//!
//! The mortar constraint holds in the weak sense at the slave nodes the pairing kept
//! (`uN_i ≤ g0_i`, tested against the dual basis). It says nothing, pointwise, about
//!
//! * slave nodes that are not contact points (their normal line misses the master side, or meets
//!   it farther than the pairing distance: they are assumed never to touch), and
//! * master nodes, which may push into the slave side between two slave nodes (a master corner
//!   on a coarse slave face).
//!
//! This check takes every node `q` of one side and the other side's boundary as the polyline
//! through its nodes (a P2 edge `v0, mid, v1` as two chords), in the reference configuration:
//!
//! ```text
//!        q  (node of this side)
//!        |  d0 = (x_q − x_p)·ν        ν: outward normal of the other body at p
//!   a ---p-------- b                  (the chord's, or at a vertex the mean of the two chords')
//!   ////////////////  other body      u_p = (1 − t) u_a + t u_b
//!
//!   d      = d0 + ν·(u_q − u_p)                      linearized gap after the solve (small sliding)
//!   excess = (min(d0, 0) − d)₊                       penetration beyond the reference overlap
//! ```
//!
//! `p` is the closest point of the polyline to `x_q`. The gap is measured along the contact
//! direction of the constraint ([`super`], "Contact direction"): the bisector of the two
//! sides' normals, `ν = (ν_p − n_q)/|ν_p − n_q|` with `ν_p` the other side's outward normal at
//! `p` (its chord's, or at a vertex the mean of the two chords') and `n_q` the node's own nodal
//! normal (outward of its body), for a slave and a master node alike. Measured along one side's
//! normal instead, a relative tangential slip `δ` would add `δ sin θ` (`θ` the angle between
//! the two sides' normals, `2x/R` on two cylinders) that the small-sliding model does not see.
//! Nodes whose closest point is an end of
//! the other side (beyond its extent) or farther than `max_distance` are not measured. The
//! reference overlap `min(d0, 0)` is discounted: two discrete curves of one circle cross by
//! up to their chords' sagitta (`h²/8R`), and the solve is not asked to separate them.
//!
//! What the excess means: a solver error or a node the pairing left out shows as a penetration
//! of the order of the displacements. On a converged weak solution the chords of the other
//! side are only an interpolation of its deformed boundary, so the excess is a discretisation
//! quantity (`O(h² |u''|)` near the edge of a contact zone, zero in the patch test, where the
//! relative displacement is linear along a straight interface).
use super::MortarSide;

/// The worst node of one side against the other.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NodePenetration {
    /// The node (global id).
    pub node: usize,
    /// `d0`: its signed distance to the other side in the reference configuration (negative
    /// inside the other body).
    pub initial_gap: f64,
    /// `d`: the linearized gap after the solve.
    pub gap: f64,
    /// `(min(d0, 0) − d)₊`.
    pub excess: f64,
    /// The other side's nodes at the ends of the chord it was measured against.
    pub facing: [usize; 2],
}

/// What [`MortarSide::penetration_into`] measured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Interpenetration {
    /// Nodes measured (facing the other side within the distance).
    pub measured: usize,
    /// The node with the largest excess (`None` when no node was measured).
    pub worst: Option<NodePenetration>,
}

impl Interpenetration {
    /// The largest excess (0 when nothing was measured).
    pub fn excess(&self) -> f64 {
        self.worst.map_or(0.0, |w| w.excess)
    }

    /// The worse of two measurements.
    pub fn max(self, other: Interpenetration) -> Interpenetration {
        let worst = match (self.worst, other.worst) {
            (Some(a), Some(b)) => Some(if b.excess > a.excess { b } else { a }),
            (a, b) => a.or(b),
        };
        Interpenetration { measured: self.measured + other.measured, worst }
    }
}

/// A chord of the other side: end nodes, end positions, outward unit normal.
struct Chord {
    nodes: [usize; 2],
    x: [[f64; 2]; 2],
    normal: [f64; 2],
}

impl MortarSide {
    /// The chords of the side: `v0 → v1` (P1) or `v0 → mid → v1` (P2), body on the left.
    fn chords(&self) -> Vec<Chord> {
        let mut out = Vec::new();
        for ids in self.edges() {
            let path: Vec<usize> = if ids.len() == 3 { vec![ids[0], ids[2], ids[1]] } else { ids.clone() };
            for w in path.windows(2) {
                let (Some(a), Some(b)) = (self.position(w[0]), self.position(w[1])) else { continue };
                let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
                let length = dx.hypot(dy);
                if length > 0.0 {
                    out.push(Chord { nodes: [w[0], w[1]], x: [a, b], normal: [dy / length, -dx / length] });
                }
            }
        }
        out
    }

    /// Every node of this side against `other`'s boundary, with the displacement field `u`
    /// (`dof = 2·node + component`; both sides' node ids index it): see the module
    /// documentation. Nodes farther than `max_distance` from
    /// `other`, or beyond its ends, or for which `measure` is false, are not measured.
    ///
    /// Errors: those of [`MortarSide::nodal_normals`] (this side's).
    pub fn penetration_into(
        &self,
        other: &MortarSide,
        u: &[f64],
        max_distance: f64,
        measure: impl Fn(usize) -> bool,
    ) -> crate::error::Result<Interpenetration> {
        let own_normals = self.nodal_normals()?;
        let chords = other.chords();
        // How many chords meet at each node of the other side: an end of the side has one.
        let mut valence = vec![0usize; other.nodes().len()];
        for c in &chords {
            for k in c.nodes {
                if let Ok(i) = other.nodes().binary_search(&k) {
                    valence[i] += 1;
                }
            }
        }
        let displacement = |k: usize| [u[2 * k], u[2 * k + 1]];
        let mut result = Interpenetration::default();
        for (index, &q) in self.nodes().iter().enumerate() {
            let Some(xq) = self.position(q).filter(|_| measure(q)) else { continue };
            // The closest point over the chords; at a shared vertex the normals are averaged.
            let mut best: Option<(f64, usize, f64)> = None; // (distance², chord, t)
            for (c, chord) in chords.iter().enumerate() {
                let d = [chord.x[1][0] - chord.x[0][0], chord.x[1][1] - chord.x[0][1]];
                let r = [xq[0] - chord.x[0][0], xq[1] - chord.x[0][1]];
                let t = ((r[0] * d[0] + r[1] * d[1]) / (d[0] * d[0] + d[1] * d[1])).clamp(0.0, 1.0);
                let p = [chord.x[0][0] + t * d[0], chord.x[0][1] + t * d[1]];
                let dist2 = (xq[0] - p[0]).powi(2) + (xq[1] - p[1]).powi(2);
                if best.is_none_or(|b| dist2 < b.0) {
                    best = Some((dist2, c, t));
                }
            }
            let Some((dist2, c, t)) = best else { continue };
            if dist2.sqrt() > max_distance {
                continue;
            }
            let chord = &chords[c];
            let mut normal = chord.normal;
            let end = if t <= 0.0 {
                Some(chord.nodes[0])
            } else if t >= 1.0 {
                Some(chord.nodes[1])
            } else {
                None
            };
            if let Some(vertex) = end {
                let at = other.nodes().binary_search(&vertex).map_or(0, |i| valence[i]);
                if at < 2 {
                    continue; // beyond the end of the other side
                }
                let mut sum = [0.0; 2];
                for other_chord in chords.iter().filter(|o| o.nodes.contains(&vertex)) {
                    sum[0] += other_chord.normal[0];
                    sum[1] += other_chord.normal[1];
                }
                let length = sum[0].hypot(sum[1]);
                if length == 0.0 {
                    continue;
                }
                normal = [sum[0] / length, sum[1] / length];
            }
            let own = own_normals[index];
            let bisector = [normal[0] - own[0], normal[1] - own[1]];
            let length = bisector[0].hypot(bisector[1]);
            if length > 0.5 {
                normal = [bisector[0] / length, bisector[1] / length];
            }
            let p = [
                chord.x[0][0] + t * (chord.x[1][0] - chord.x[0][0]),
                chord.x[0][1] + t * (chord.x[1][1] - chord.x[0][1]),
            ];
            let (ua, ub, uq) = (displacement(chord.nodes[0]), displacement(chord.nodes[1]), displacement(q));
            let up = [(1.0 - t) * ua[0] + t * ub[0], (1.0 - t) * ua[1] + t * ub[1]];
            let initial_gap = (xq[0] - p[0]) * normal[0] + (xq[1] - p[1]) * normal[1];
            let gap = initial_gap + normal[0] * (uq[0] - up[0]) + normal[1] * (uq[1] - up[1]);
            let excess = (initial_gap.min(0.0) - gap).max(0.0);
            result.measured += 1;
            if result.worst.is_none_or(|w| excess > w.excess) {
                result.worst = Some(NodePenetration { node: q, initial_gap, gap, excess, facing: chord.nodes });
            }
        }
        Ok(result)
    }
}

#[cfg(test)]
mod tests {
    use super::MortarSide;
    use crate::mesh::Order;
    const ALL: fn(usize) -> bool = |_| true;

    /// A lower body's top side `y = 0` (body below: edges run right to left) and an upper
    /// body's bottom side `y = gap` (edges left to right), non-matching.
    fn sides(gap: f64) -> (MortarSide, MortarSide, Vec<[f64; 2]>) {
        let mut positions = Vec::new();
        let lower_x = [0.0, 0.3, 0.55, 1.0];
        let upper_x = [0.1, 0.4, 0.9];
        for &x in &lower_x {
            positions.push([x, 0.0]);
        }
        for &x in &upper_x {
            positions.push([x, gap]);
        }
        let lower = MortarSide::new("lower", Order::P1, vec![vec![3, 2], vec![2, 1], vec![1, 0]], &positions).unwrap();
        let upper = MortarSide::new("upper", Order::P1, vec![vec![4, 5], vec![5, 6]], &positions).unwrap();
        (lower, upper, positions)
    }

    #[test]
    fn rigid_motions_and_separation_penetrate_nothing() {
        let (lower, upper, positions) = sides(0.0);
        // Both sides moved together: no excess; every upper node measured (they face the lower side).
        let u: Vec<f64> = positions.iter().flat_map(|_| [0.2, -0.1]).collect();
        let m = upper.penetration_into(&lower, &u, 1.0, ALL).unwrap();
        assert_eq!(m.measured, 3);
        assert_eq!(m.excess(), 0.0);
        // The upper body lifted by 0.01: gaps 0.01, no excess.
        let u: Vec<f64> = (0..positions.len()).flat_map(|k| [0.0, if k >= 4 { 0.01 } else { 0.0 }]).collect();
        let m = upper.penetration_into(&lower, &u, 1.0, ALL).unwrap();
        assert!((m.worst.unwrap().gap - 0.01).abs() < 1e-15);
        assert_eq!(m.excess(), 0.0);
        // Lower nodes against the upper side: only those facing it (x = 0.3, 0.55) are measured.
        let m = lower.penetration_into(&upper, &u, 1.0, ALL).unwrap();
        assert_eq!(m.measured, 2);
        assert_eq!(m.excess(), 0.0);
    }

    #[test]
    fn a_pushed_node_penetrates_by_its_displacement() {
        let (lower, upper, positions) = sides(0.0);
        // Upper node 5 (x = 0.4) pushed 1e-3 into the lower body.
        let mut u = vec![0.0; 2 * positions.len()];
        u[2 * 5 + 1] = -1e-3;
        let m = upper.penetration_into(&lower, &u, 1.0, ALL).unwrap();
        let w = m.worst.unwrap();
        assert_eq!(w.node, 5);
        assert!((w.excess - 1e-3).abs() < 1e-15, "{w:?}");
        // Seen from the lower side: node 1 (x = 0.3) lies 2/3 of the way along the upper chord
        // 0.1 → 0.4 and node 2 (x = 0.55) 3/10 of the way along 0.4 → 0.9, chords whose shared
        // end went down by 1e-3: they are 2/3·1e-3 and 7/10·1e-3 inside.
        let m = lower.penetration_into(&upper, &u, 1.0, ALL).unwrap();
        let w = m.worst.unwrap();
        assert_eq!((m.measured, w.node), (2, 2));
        assert!((w.excess - 0.7e-3).abs() < 1e-15, "{w:?}");
    }

    #[test]
    fn reference_overlap_is_discounted_and_distance_limits() {
        // Upper side 1e-4 inside the lower body from the start: that overlap is not an excess,
        // but a further 1e-5 is.
        let (lower, upper, positions) = sides(-1e-4);
        let mut u = vec![0.0; 2 * positions.len()];
        assert_eq!(upper.penetration_into(&lower, &u, 1.0, ALL).unwrap().excess(), 0.0);
        u[2 * 4 + 1] = -1e-5;
        let w = upper.penetration_into(&lower, &u, 1.0, ALL).unwrap().worst.unwrap();
        assert!((w.initial_gap + 1e-4).abs() < 1e-15 && (w.excess - 1e-5).abs() < 1e-15, "{w:?}");
        // Farther than the distance: nothing measured.
        let (lower, upper, positions) = sides(0.5);
        let u = vec![0.0; 2 * positions.len()];
        assert_eq!(upper.penetration_into(&lower, &u, 0.1, ALL).unwrap().measured, 0);
    }

    #[test]
    fn gaps_follow_the_bisector_of_the_two_normals() {
        // The lower side tilted by 0.1 rad, the upper one horizontal above it: sliding the upper
        // node along x by 1e-2 changes its gap along the bisector (tilted by 0.05 rad) by
        // 1e-2 sin(0.05), half of what the lower side's own normal would give.
        let positions = vec![[1.0, 0.1], [0.0, 0.0], [0.4, 0.5], [0.6, 0.5]];
        let lower = MortarSide::new("lower", Order::P1, vec![vec![0, 1]], &positions).unwrap();
        let upper = MortarSide::new("upper", Order::P1, vec![vec![2, 3]], &positions).unwrap();
        let mut u = vec![0.0; 8];
        u[2 * 2] = 1e-2;
        u[2 * 3] = 1e-2;
        let w = upper.penetration_into(&lower, &u, 1.0, ALL).unwrap().worst.unwrap();
        let tilt = 0.5 * 0.1f64.atan();
        assert!((w.initial_gap - w.gap - 1e-2 * tilt.sin()).abs() < 1e-12, "{w:?}");
    }
}
