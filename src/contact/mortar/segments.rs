//! Segment-to-segment integration of one slave edge against the master edges: projections
//! along the slave normal field, the segmentation of the slave parameter interval, the dual
//! basis of the edge and the mortar integrals (see the parent module's documentation).
use crate::fem::lagrange::{edge_shape_derivatives, edge_shape_values, map_edge_point, EdgePoint};
use crate::fem::quadrature::gauss_legendre;
use crate::mesh::Measure;
use nalgebra::DMatrix;

/// Gauss–Legendre points per segment (exact to degree 15; P2 × P2 on straight edges is degree 4).
pub(super) const SEGMENT_POINTS: usize = 8;
/// Tolerance on edge parameters (`s`, `η ∈ [0, 1]`) for coverage and segment ends.
pub(super) const PARAMETER_TOLERANCE: f64 = 1e-9;
/// Local parameters of the edge nodes `v0, v1, mid`.
pub(super) const NODE_PARAMETER: [f64; 3] = [0.0, 1.0, 0.5];
/// Newton iterations of a projection, and the parameter range beyond which it gives up.
const NEWTON_ITERATIONS: usize = 50;
const PARAMETER_RANGE: f64 = 10.0;

pub(super) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
pub(super) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}

/// One edge of a side: node ids and coordinates (`len` = 2 for P1, 3 for P2: `v0, v1, mid`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Edge {
    pub len: usize,
    pub nodes: [usize; 3],
    pub x: [[f64; 2]; 3],
}

impl Edge {
    pub fn at(&self, s: f64) -> EdgePoint {
        map_edge_point(&self.x[..self.len], s)
    }

    /// A box containing the whole edge: a P2 edge is a parabolic arc, inside the triangle of
    /// its end points and its Bézier control point `2 mid − (v0 + v1)/2`.
    fn bounding_box(&self) -> [[f64; 2]; 2] {
        let mut points = vec![self.x[0], self.x[1]];
        if self.len == 3 {
            let m = self.x[2];
            points.push([
                2.0 * m[0] - 0.5 * (self.x[0][0] + self.x[1][0]),
                2.0 * m[1] - 0.5 * (self.x[0][1] + self.x[1][1]),
            ]);
        }
        let mut b = [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]];
        for p in points {
            for c in 0..2 {
                b[0][c] = b[0][c].min(p[c]);
                b[1][c] = b[1][c].max(p[c]);
            }
        }
        b
    }
}

/// A slave edge with the nodal normals of its nodes (the normal field `n(s) = Σ_a φ_a(s) n_a`).
#[derive(Debug, Clone, Copy)]
pub(super) struct SlaveEdge {
    pub edge: Edge,
    pub normals: [[f64; 2]; 3],
    /// Plane (`ds`) or axisymmetric (`2π r ds`): the measure of every integral over the edge.
    pub measure: Measure,
}

impl SlaveEdge {
    /// `(Σ φ_a n_a, Σ φ_a' n_a)` at `s`: the interpolated normal (not normalized) and its derivative.
    fn normal_field(&self, s: f64) -> ([f64; 2], [f64; 2]) {
        let (v, d) = (edge_shape_values(self.edge.len, s), edge_shape_derivatives(self.edge.len, s));
        let (mut n, mut dn) = ([0.0; 2], [0.0; 2]);
        for a in 0..self.edge.len {
            for c in 0..2 {
                n[c] += v[a] * self.normals[a][c];
                dn[c] += d[a] * self.normals[a][c];
            }
        }
        (n, dn)
    }

    fn unit_normal(&self, s: f64) -> [f64; 2] {
        let (n, _) = self.normal_field(s);
        let l = norm(n);
        [n[0] / l, n[1] / l]
    }

    /// The parameter `s` whose normal line `x(s) + t n(s)` passes through `q` (a master vertex):
    /// the root of `F(s) = (q − x(s)) × n(s)`, by Newton from the projection on the chord.
    fn foot(&self, q: [f64; 2]) -> Option<f64> {
        let chord = sub(self.edge.x[1], self.edge.x[0]);
        let s0 = dot(sub(q, self.edge.x[0]), chord) / dot(chord, chord);
        newton(s0, |s| {
            let p = self.edge.at(s);
            let (n, dn) = self.normal_field(s);
            let r = sub(q, p.x);
            (cross(r, n), cross(r, dn) - cross(p.tangent, n), (norm(q) + magnitude(&self.edge, s)) * norm(n))
        })
    }
}

/// Newton's method on a scalar function given as `s -> (f(s), f'(s), scale)`, `scale` the size
/// of the terms of `f` (its round-off is a few `ε · scale`). Converged when `|f|` is at
/// round-off or the step below `1e-13`; `None` if it leaves `[−10, 10]`, meets a zero slope or
/// does not converge. (On a short edge far from the origin the parameter cannot be resolved
/// beyond `ε |x| / h`, so a criterion on the step alone could stall.)
fn newton(mut s: f64, f: impl Fn(f64) -> (f64, f64, f64)) -> Option<f64> {
    for _ in 0..NEWTON_ITERATIONS {
        let (value, slope, scale) = f(s);
        if value.abs() <= 16.0 * f64::EPSILON * scale {
            return Some(s);
        }
        if !(slope.abs() > 0.0 && value.is_finite()) {
            return None;
        }
        let step = value / slope;
        s -= step;
        if !s.is_finite() || s.abs() > PARAMETER_RANGE {
            return None;
        }
        // Quadratic convergence: after a step of 1e-13 the error is at round-off.
        if step.abs() <= 1e-13 {
            return Some(s);
        }
    }
    None
}

/// `Σ_a |φ_a(s)| |x_a|`: the size of the terms of `x(s)`, for round-off estimates.
fn magnitude(edge: &Edge, s: f64) -> f64 {
    let phi = edge_shape_values(edge.len, s);
    (0..edge.len).map(|a| phi[a].abs() * norm(edge.x[a])).sum()
}

/// The parameter `η` of the point of `edge` on the line `p + t n`: the root of
/// `(x(η) − p) × n = 0`, exact for a P1 edge, by Newton from the chord's intersection for P2.
fn intersect(edge: &Edge, p: [f64; 2], n: [f64; 2]) -> Option<f64> {
    let chord = sub(edge.x[1], edge.x[0]);
    let den = cross(chord, n);
    if den.is_nan() || den.abs() <= 1e-12 * norm(chord) * norm(n) {
        return None;
    }
    let eta = cross(sub(p, edge.x[0]), n) / den;
    if edge.len == 2 {
        return Some(eta);
    }
    newton(eta, |eta| {
        let q = edge.at(eta);
        (cross(sub(q.x, p), n), cross(q.tangent, n), (norm(p) + magnitude(edge, eta)) * norm(n))
    })
}

/// What the slave point at `s` is paired with on a master edge.
struct Pairing {
    /// Master shape function values at the paired point.
    values: [f64; 3],
    /// `(x_master − x_slave)·n(s)`, `n(s)` the unit slave normal.
    gap: f64,
}

/// The pairing of the slave point at `s` with `master` along the slave normal field, if the
/// normal line meets the edge (`η ∈ [0, 1]` up to the tolerance). With `checked`, the master
/// edge must also face the slave (`n_master·n < 0`) and lie within `max_distance`.
fn pair(slave: &SlaveEdge, s: f64, master: &Edge, max_distance: f64, checked: bool) -> Option<Pairing> {
    let (q, gap) = meet(slave.edge.at(s).x, slave.unit_normal(s), master, max_distance, checked)?;
    Some(Pairing { values: q.values, gap })
}

/// Where the line `p + τ n` (`n` a unit normal) meets `master` (`η ∈ [0, 1]` up to the
/// tolerance): the master point and the gap `(x_master − p)·n`; with `checked`, only if the
/// edge faces the line (`n_master·n < 0`) within `max_distance`.
fn meet(p: [f64; 2], n: [f64; 2], master: &Edge, max_distance: f64, checked: bool) -> Option<(EdgePoint, f64)> {
    let eta = intersect(master, p, n)?;
    if !(-PARAMETER_TOLERANCE..=1.0 + PARAMETER_TOLERANCE).contains(&eta) {
        return None;
    }
    let q = master.at(eta);
    let gap = dot(sub(q.x, p), n);
    if checked && (dot(q.normal, n) >= 0.0 || gap.abs() > max_distance) {
        return None;
    }
    Some((q, gap))
}

/// The master side's unit normal where the line `p + t n` (a slave node and its normal) meets
/// it: on the nearest master edge that the line meets within `max_distance` and that faces the
/// slave (`n_master·n < 0`), the master nodal normals `normals[f]` of edge `f` interpolated by
/// its shape functions. `None` when no edge is met.
pub(super) fn master_normal_at(
    p: [f64; 2],
    n: [f64; 2],
    masters: &[Edge],
    normals: &[[[f64; 2]; 3]],
    max_distance: f64,
) -> Option<[f64; 2]> {
    let mut best: Option<(f64, [f64; 2])> = None;
    for (f, master) in masters.iter().enumerate() {
        let Some((q, gap)) = meet(p, n, master, max_distance, true) else { continue };
        if best.is_some_and(|b| b.0 <= gap.abs()) {
            continue;
        }
        if let Some(m) = interpolated_normal(&q, &normals[f], master.len) {
            best = Some((gap.abs(), m));
        }
    }
    best.map(|b| b.1)
}

/// The master's nodal normals `normals` (of an edge of `len` nodes) interpolated at the edge
/// point `q` and normalised; `None` where they cancel.
fn interpolated_normal(q: &EdgePoint, normals: &[[f64; 2]; 3], len: usize) -> Option<[f64; 2]> {
    let mut m = [0.0; 2];
    for (v, nm) in q.values.iter().zip(normals).take(len) {
        m[0] += v * nm[0];
        m[1] += v * nm[1];
    }
    let l = norm(m);
    (l > 0.0).then(|| [m[0] / l, m[1] / l])
}

/// A node-to-segment row: `(master node j, φ_j^m(η))` by increasing node, the gap
/// `(x_m − p)·n` and the master's unit normal at the paired point.
pub(super) type NodeToSegment = (Vec<(usize, f64)>, f64, [f64; 2]);

/// The node-to-segment row of a slave node at `p` with unit normal `n`: on the nearest master
/// edge that the line `p + τ n` meets within `max_distance` and that faces the slave, the master
/// shape function values `(node j, φ_j^m(η))` by increasing node, the gap `(x_m − p)·n` and the
/// master normal there (its nodal normals `normals[f]` interpolated). `None` when no edge is met.
pub(super) fn node_to_segment(
    p: [f64; 2],
    n: [f64; 2],
    masters: &[Edge],
    normals: &[[[f64; 2]; 3]],
    max_distance: f64,
) -> Option<NodeToSegment> {
    let mut best: Option<(usize, EdgePoint, f64)> = None;
    for (f, master) in masters.iter().enumerate() {
        let Some((q, gap)) = meet(p, n, master, max_distance, true) else { continue };
        if best.as_ref().is_some_and(|b| b.2.abs() <= gap.abs()) {
            continue;
        }
        best = Some((f, q, gap));
    }
    let (f, q, gap) = best?;
    let master = &masters[f];
    let mut row: Vec<(usize, f64)> = (0..master.len).map(|a| (master.nodes[a], q.values[a])).collect();
    row.sort_by_key(|&(j, _)| j);
    let m = interpolated_normal(&q, &normals[f], master.len).unwrap_or(q.normal);
    Some((row, gap, m))
}

/// The part `[lo, hi]` of the slave parameter interval `[0, 1]` that master edge `master` faces.
struct Candidate {
    master: usize,
    lo: f64,
    hi: f64,
}

/// The integrals of one slave edge (local nodes `a` of the edge).
#[derive(Debug, Clone)]
pub(super) struct EdgeIntegrals {
    /// `∫_e φ_a ds` (the edge's part of `D_i`; `ds` stands for `2π r ds` in axisymmetry, here
    /// and below). It is 0 exactly for a P2 vertex on the axis (see [`EdgeIntegrals::axis`]).
    pub weight: [f64; 3],
    /// `∫_e ψ_a g ds`, `g = (x_master − x_slave)·n(s)` on the covered segments.
    pub gap: [f64; 3],
    /// `(master node j, ∫_e ψ_a φ_j ds)`.
    pub mortar: [Vec<(usize, f64)>; 3],
    /// Whether the normal line of node `a` meets the master side.
    pub covered: [bool; 3],
    /// Parameter length of the segments of the edge that no master edge faces (beyond the
    /// tolerance).
    pub uncovered_length: f64,
    /// In axisymmetry: whether local node `a` is a P2 vertex on the axis, whose weight
    /// `∫ φ_a 2π r ds` vanishes (`∫₀¹ (1 − s)(1 − 2s) s ds = 0`) and whose dual function is then
    /// `ψ_a ≡ 0` (row `a` of `A = D_e M_e⁻¹` is zero).
    pub axis: [bool; 3],
}

/// Segment the slave edge against `masters` and integrate (parent module documentation).
/// Errors (messages): a dual basis that cannot be built, or a Gauss point whose normal misses
/// the master edge its segment was paired with (an edge too curved for its size).
pub(super) fn integrate(slave: &SlaveEdge, masters: &[Edge], max_distance: f64) -> Result<EdgeIntegrals, String> {
    let n = slave.edge.len;
    let candidates = candidates(slave, masters, max_distance);

    // Node coverage: the node's own normal line (n(s_a) = n_a) meets a facing master edge.
    let mut covered = [false; 3];
    for (a, cov) in covered.iter_mut().enumerate().take(n) {
        let s = NODE_PARAMETER[a];
        *cov = candidates.iter().any(|c| {
            c.lo - PARAMETER_TOLERANCE <= s
                && s <= c.hi + PARAMETER_TOLERANCE
                && pair(slave, s, &masters[c.master], max_distance, true).is_some()
        });
    }

    // Segments: between consecutive break points, paired with the nearest facing candidate.
    let mut breaks = vec![0.0, 1.0];
    for c in &candidates {
        breaks.extend([c.lo, c.hi].into_iter().filter(|&s| s > 0.0 && s < 1.0));
    }
    breaks.sort_by(f64::total_cmp);
    breaks.dedup();
    let mut segments: Vec<(f64, f64, Option<usize>)> = Vec::with_capacity(breaks.len());
    let mut uncovered_length = 0.0;
    for w in breaks.windows(2) {
        let (l, r) = (w[0], w[1]);
        let mid = 0.5 * (l + r);
        let best = candidates
            .iter()
            .filter(|c| c.lo <= mid && mid <= c.hi)
            .filter_map(|c| pair(slave, mid, &masters[c.master], max_distance, true).map(|p| (c.master, p.gap.abs())))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(f, _)| f);
        if best.is_none() && r - l > PARAMETER_TOLERANCE {
            uncovered_length += r - l;
        }
        segments.push((l, r, best));
    }

    // The composite rule over all segments, covered or not: the dual basis is built with the
    // very rule the mortar integrals use, so biorthogonality holds to round-off on curved edges.
    let rule = gauss_legendre(SEGMENT_POINTS);
    let mut points = Vec::with_capacity(segments.len() * SEGMENT_POINTS);
    for &(l, r, master) in &segments {
        for (t, w) in rule.points.iter().zip(&rule.weights) {
            let s = l + (r - l) * t;
            let p = slave.edge.at(s);
            points.push((s, (r - l) * w * p.length_element * slave.measure.factor(p.x), master));
        }
    }
    let mut mass = DMatrix::<f64>::zeros(n, n);
    let mut weight = [0.0; 3];
    for &(s, w, _) in &points {
        let phi = edge_shape_values(n, s);
        for a in 0..n {
            weight[a] += w * phi[a];
            for b in 0..n {
                mass[(a, b)] += w * phi[a] * phi[b];
            }
        }
    }
    // A P2 vertex on the axis (r snapped to 0 exactly by the setup) has weight 0 on a straight
    // edge (`∫ (1 − s)(1 − 2s) s ds = 0`) and a weight of relative size `θ²` on an arc of angle
    // `θ`: either way it is set to 0 exactly, so that its dual function vanishes and the node
    // gets a node-to-segment row instead (parent module, "Axisymmetry").
    let mut axis = [false; 3];
    for a in 0..n {
        if slave.measure.is_axisymmetric() && n == 3 && a < 2 && slave.edge.x[a][0] == 0.0 {
            axis[a] = true;
            weight[a] = 0.0;
        }
    }
    if let Some(a) = (0..n).find(|&a| !(axis[a] || weight[a] > 0.0 && weight[a].is_finite())) {
        return Err(format!(
            "the consistent weight ∫φ ds of its local node {a} is {:e}, not positive: its P2 mid node is too far \
             from the middle of the edge; remesh the side",
            weight[a]
        ));
    }
    // ψ_a = Σ_b A_ab φ_b with A = D_e M_e⁻¹.
    let inverse = mass.try_inverse().ok_or("its mass matrix is singular (a degenerate edge)")?;
    let dual = |s: f64| {
        let phi = edge_shape_values(n, s);
        let mut psi = [0.0; 3];
        for (a, p) in psi.iter_mut().enumerate().take(n) {
            *p = weight[a] * (0..n).map(|b| inverse[(a, b)] * phi[b]).sum::<f64>();
        }
        psi
    };

    let mut gap = [0.0; 3];
    let mut mortar: [Vec<(usize, f64)>; 3] = Default::default();
    for &(s, w, master) in &points {
        let Some(f) = master else { continue };
        let Some(pairing) = pair(slave, s, &masters[f], max_distance, false) else {
            return Err(format!(
                "the slave normal at its parameter {s:.6} misses the master edge its segment is paired with \
                 (nodes {:?}): the edges are too curved for their size; refine the sides",
                &masters[f].nodes[..masters[f].len]
            ));
        };
        let psi = dual(s);
        for a in 0..n {
            gap[a] += w * psi[a] * pairing.gap;
            for b in 0..masters[f].len {
                add(&mut mortar[a], masters[f].nodes[b], w * psi[a] * pairing.values[b]);
            }
        }
    }
    Ok(EdgeIntegrals { weight, gap, mortar, covered, uncovered_length, axis })
}

/// `row[j] += v`, for a short sparse row.
pub(super) fn add(row: &mut Vec<(usize, f64)>, j: usize, v: f64) {
    match row.iter_mut().find(|(c, _)| *c == j) {
        Some(entry) => entry.1 += v,
        None => row.push((j, v)),
    }
}

/// The master edges that face part of the slave edge, with the parameter interval they face:
/// the hull of the slave end points whose normal line meets the edge and of the feet of its
/// end vertices that fall on the slave edge. (Feet far outside `[0, 1]`, e.g. of a master edge
/// much longer than the slave edge, are not needed, and not always computable.) Bounding boxes
/// must be within `max_distance` when it is finite.
fn candidates(slave: &SlaveEdge, masters: &[Edge], max_distance: f64) -> Vec<Candidate> {
    let mut reach = slave.edge.bounding_box();
    if max_distance.is_finite() {
        reach[0].iter_mut().for_each(|c| *c -= max_distance);
        reach[1].iter_mut().for_each(|c| *c += max_distance);
    }
    let inside = |t: f64| (-PARAMETER_TOLERANCE..=1.0 + PARAMETER_TOLERANCE).contains(&t);
    let ends = [0.0, 1.0].map(|s| (s, slave.edge.at(s).x, slave.unit_normal(s)));
    let mut out = Vec::new();
    for (f, master) in masters.iter().enumerate() {
        if max_distance.is_finite() {
            let b = master.bounding_box();
            if (0..2).any(|c| b[1][c] < reach[0][c] || b[0][c] > reach[1][c]) {
                continue;
            }
        }
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let ends_in = ends.iter().filter(|(_, p, n)| intersect(master, *p, *n).is_some_and(inside)).map(|e| e.0);
        let feet_in = [master.x[0], master.x[1]].into_iter().filter_map(|q| slave.foot(q)).filter(|&s| inside(s));
        for s in ends_in.chain(feet_in) {
            lo = lo.min(s.clamp(0.0, 1.0));
            hi = hi.max(s.clamp(0.0, 1.0));
        }
        if hi > lo {
            out.push(Candidate { master: f, lo, hi });
        }
    }
    out
}
