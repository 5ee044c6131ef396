//! # Rigid obstacles and the closest-point projection
//!
//! A rigid obstacle is described by its boundary curve and the side the body is on. For a point
//! `x` of the body, [`Obstacle::project`] returns the closest point `p` of the obstacle's
//! boundary, the unit normal `ν` of the obstacle at `p` pointing towards the body side, and the
//! signed distance `d` (positive on the body side, negative inside the obstacle):
//!
//! ```text
//!            x  (body side, d > 0)
//!            |
//!            | d = (x − p)·ν
//!            |
//!   ---------p--------->   obstacle boundary, ν = unit normal at p, towards the body
//!   //////// obstacle ////
//! ```
//!
//! In every case `x = p + d ν` (the projection is orthogonal), which is what the contact
//! boundary ([`super::boundary`]) uses: the body's contact direction is `n = −ν` and the initial
//! gap `g0 = d`, so that the linearized non-penetration `(x + u − p)·ν ≥ 0` reads `u·n ≤ g0`
//! (Wriggers, *Computational Contact Mechanics*, 2nd ed., Springer 2006, ch. 4, contact
//! kinematics: the normal gap from the closest-point projection).
//!
//! ## The three shapes
//!
//! - **Line** `{ y : (y − point)·normal = 0 }`, body on the side `normal` points to:
//!   `d = (x − point)·ν`, `p = x − d ν`, `ν = normal / |normal|`.
//! - **Circle** (centre `c`, radius `R`, body outside): `d = |x − c| − R`,
//!   `ν = (x − c)/|x − c|`, `p = c + R ν`. At `x = c` every boundary point is closest; we return
//!   `ν = (0, −1)` (a body sitting on top of the circle's centre would be pushed down), `d = −R`.
//! - **Polyline** `P_0, P_1, …, P_{n−1}` (`n ≥ 2`), body on the **left** of the direction of
//!   travel, so the normal of segment `P_k → P_{k+1}` is its tangent rotated by +90°,
//!   `ν_k = (−τ_y, τ_x)`. The curve is continued beyond its ends: the first segment extends
//!   backwards from `P_0` and the last one forwards from `P_{n−1}` as half-lines, so the obstacle
//!   is the whole region on the right of an unbounded simple curve and every point of the plane
//!   has a well-defined side (a single segment is an infinite line).
//!
//! ```text
//!               body (on the left of the direction of travel)
//!                                                       .
//!   . . . P0 ---------- P1                            .      dots: the half-line extensions
//!                         \                         P4
//!                          \                       /
//!                           P2 ---------------- P3
//!               obstacle (on the right)
//!
//!   right turn at P1 (cross(P1 − P0, P2 − P1) < 0): convex obstacle corner, poking into the body;
//!   left turns at P2, P3: concave obstacle corners.
//! ```
//!
//! Projection onto a polyline: the closest point over the pieces (segments, end half-lines) and
//! interior vertices. When the closest point is the interior of a piece, `ν` is that piece's
//! normal and `d = (x − p)·ν_k`. When it is an interior vertex `V` (this happens on the body
//! side of a convex obstacle corner, where `x` lies in the cone between the two adjacent normals,
//! and inside the obstacle at a concave corner), `ν` is the direction from `V` to `x` on the
//! body side (from `x` to `V` inside the obstacle), and the side is decided by the sign of
//! `(x − V)·(ν_{k−1} + ν_k)`: `x − V` lies in the cone spanned by `ν_{k−1}, ν_k` (body side of
//! a convex corner) or by `−ν_{k−1}, −ν_k` (inside a concave corner), so its product with the sum
//! of the normals has the sign of the side; this is the 2D analogue of the angle-weighted
//! pseudonormal test of Bærentzen & Aanæs, "Signed distance computation using the angle weighted pseudonormal", IEEE TVCG 11
//! (2005) 243–253. A point exactly on a vertex gets `ν = (ν_{k−1} + ν_k)/|ν_{k−1} + ν_k|`.
//!
//! ## Validation
//!
//! The variants are plain data, so a caller may build one directly; [`Obstacle::validate`]
//! checks it (the `new_*` constructors call it): finite coordinates, unit line normal,
//! positive radius, at least two polyline points, no zero-length segment, no U-turn between
//! consecutive segments and no intersection between non-adjacent pieces (end half-lines
//! included). Degenerate input is an [`Error::Usage`] naming the obstacle and the point or
//! segment at fault. [`Obstacle::project`] never panics, even on an unvalidated obstacle
//! (a zero-length polyline segment is skipped, a line normal is normalized).
use crate::error::{Error, Result};

/// A rigid obstacle. See the module documentation for the conventions.
#[derive(Debug, Clone, PartialEq)]
pub enum Obstacle {
    /// The straight line through `point`; `normal` is unit and points from the obstacle towards
    /// the body.
    Line {
        /// A point of the line.
        point: [f64; 2],
        /// Unit normal towards the body.
        normal: [f64; 2],
    },
    /// A rigid disc; the body is outside it.
    Circle {
        /// Centre of the rigid disc.
        center: [f64; 2],
        /// Its radius, > 0.
        radius: f64,
    },
    /// An open polyline continued by half-lines at both ends; the body is on the left of the
    /// direction of travel `points[0] → points[1] → …`.
    Polyline {
        /// The vertices, the body on the left of the direction of travel.
        points: Vec<[f64; 2]>,
    },
}

/// The closest point of an obstacle to a point `x`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Projection {
    /// Closest point of the obstacle's boundary.
    pub point: [f64; 2],
    /// Unit normal of the obstacle at `point`, pointing towards the body side.
    pub normal: [f64; 2],
    /// `(x − point)·normal`: positive on the body side, negative inside the obstacle.
    pub signed_distance: f64,
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}
fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
fn norm(a: [f64; 2]) -> f64 {
    a[0].hypot(a[1])
}
fn finite(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}
/// Unit left normal of the direction `d` (`d` rotated by +90°), or zero for `d = 0`.
fn left_normal(d: [f64; 2]) -> [f64; 2] {
    let l = norm(d);
    if l > 0.0 {
        [-d[1] / l, d[0] / l]
    } else {
        [0.0, 0.0]
    }
}

/// One piece of a polyline: `a + s (b − a)` for `s` in `[s_min, s_max]` (infinite for the end
/// half-lines).
struct Piece {
    a: [f64; 2],
    b: [f64; 2],
    s_min: f64,
    s_max: f64,
}

fn pieces(points: &[[f64; 2]]) -> Vec<Piece> {
    let n = points.len();
    (0..n.saturating_sub(1))
        .map(|k| Piece {
            a: points[k],
            b: points[k + 1],
            s_min: if k == 0 { f64::NEG_INFINITY } else { 0.0 },
            s_max: if k + 2 == n { f64::INFINITY } else { 1.0 },
        })
        .collect()
}

/// Whether two pieces share a point (collinear overlaps included). `tol` is an absolute length.
fn pieces_intersect(p: &Piece, q: &Piece, tol: f64) -> bool {
    let d = sub(p.b, p.a);
    let e = sub(q.b, q.a);
    let w = sub(q.a, p.a);
    let denom = cross(d, e);
    let (ld, le) = (norm(d), norm(e));
    if denom.abs() > 1e-12 * ld * le {
        // a + s d = q.a + t e  →  s = (w × e)/(d × e), t = (w × d)/(d × e).
        let s = cross(w, e) / denom;
        let t = cross(w, d) / denom;
        let (ts, te) = (tol / ld, tol / le);
        s >= p.s_min - ts && s <= p.s_max + ts && t >= q.s_min - te && t <= q.s_max + te
    } else {
        // Parallel: they meet only if collinear (distance of q.a from p's line within tol) and
        // their parameter ranges, expressed on p, overlap.
        if (cross(d, w) / ld).abs() > tol {
            return false;
        }
        let along = |x: [f64; 2]| dot(sub(x, p.a), d) / (ld * ld);
        let (s0, s1) = (along(q.a), along(q.b));
        // q's range [t_min, t_max] maps to s = s0 + t (s1 − s0).
        let map = |t: f64| if t.is_infinite() { t * (s1 - s0).signum() } else { s0 + t * (s1 - s0) };
        let (u, v) = (map(q.s_min), map(q.s_max));
        let (lo, hi) = if u <= v { (u, v) } else { (v, u) };
        let ts = tol / ld;
        lo <= p.s_max + ts && hi >= p.s_min - ts
    }
}

impl Obstacle {
    /// The line through `point` with normal `normal` (any nonzero length: it is normalized),
    /// pointing from the obstacle towards the body.
    pub fn new_line(point: [f64; 2], normal: [f64; 2]) -> Result<Self> {
        let l = norm(normal);
        let unit = if l > 0.0 && l.is_finite() { [normal[0] / l, normal[1] / l] } else { normal };
        let obstacle = Obstacle::Line { point, normal: unit };
        obstacle.validate()?;
        Ok(obstacle)
    }

    /// A rigid disc of centre `center` and radius `radius > 0`, the body outside it.
    pub fn new_circle(center: [f64; 2], radius: f64) -> Result<Self> {
        let obstacle = Obstacle::Circle { center, radius };
        obstacle.validate()?;
        Ok(obstacle)
    }

    /// A polyline (at least two points), the body on the left of the direction of travel.
    pub fn new_polyline(points: Vec<[f64; 2]>) -> Result<Self> {
        let obstacle = Obstacle::Polyline { points };
        obstacle.validate()?;
        Ok(obstacle)
    }

    /// A short description for messages, e.g. "line obstacle through (0, -0.1)".
    pub fn describe(&self) -> String {
        match self {
            Obstacle::Line { point, normal } => {
                format!("line obstacle through ({}, {}) with normal ({}, {})", point[0], point[1], normal[0], normal[1])
            }
            Obstacle::Circle { center, radius } => {
                format!("circle obstacle of centre ({}, {}) and radius {radius}", center[0], center[1])
            }
            Obstacle::Polyline { points } => format!("polyline obstacle of {} points", points.len()),
        }
    }

    /// Checks the obstacle (see the module documentation); errors are [`Error::Usage`] naming
    /// the obstacle and the point or segment at fault.
    pub fn validate(&self) -> Result<()> {
        let fail = |what: String| Err(Error::Usage(format!("{}: {what}", self.describe())));
        match self {
            Obstacle::Line { point, normal } => {
                if !finite(*point) {
                    return fail("the point must have finite coordinates".to_string());
                }
                let l = norm(*normal);
                if !(finite(*normal) && l > 0.0) {
                    return fail("the normal must be a nonzero finite vector".to_string());
                }
                if (l - 1.0).abs() > 1e-12 {
                    return fail(format!(
                        "the normal has length {l}, it must be a unit vector (Obstacle::new_line normalizes it)"
                    ));
                }
            }
            Obstacle::Circle { center, radius } => {
                if !finite(*center) {
                    return fail("the centre must have finite coordinates".to_string());
                }
                if !(radius.is_finite() && *radius > 0.0) {
                    return fail(format!("the radius is {radius}, it must be positive and finite"));
                }
            }
            Obstacle::Polyline { points } => {
                if points.len() < 2 {
                    return fail("a polyline needs at least two points".to_string());
                }
                if let Some(k) = points.iter().position(|p| !finite(*p)) {
                    return fail(format!("point {k} ({}, {}) is not finite", points[k][0], points[k][1]));
                }
                // Length scale for the intersection tolerance.
                let extent = points.iter().map(|p| p[0].abs().max(p[1].abs())).fold(0.0, f64::max).max(1e-300);
                let tol = 1e-12 * extent;
                for k in 0..points.len() - 1 {
                    if norm(sub(points[k + 1], points[k])) <= tol {
                        return fail(format!(
                            "segment {k} (points {k} and {}) has zero length: remove the repeated point",
                            k + 1
                        ));
                    }
                }
                for k in 1..points.len() - 1 {
                    let d0 = sub(points[k], points[k - 1]);
                    let d1 = sub(points[k + 1], points[k]);
                    if cross(d0, d1).abs() <= 1e-12 * norm(d0) * norm(d1) && dot(d0, d1) < 0.0 {
                        return fail(format!(
                            "the polyline turns back on itself at point {k} ({}, {}): segments {} and {k} overlap",
                            points[k][0],
                            points[k][1],
                            k - 1
                        ));
                    }
                }
                let ps = pieces(points);
                for i in 0..ps.len() {
                    for j in i + 2..ps.len() {
                        if pieces_intersect(&ps[i], &ps[j], tol) {
                            let name = |k: usize| {
                                let mut s = format!("segment {k}");
                                if k == 0 {
                                    s.push_str(" (with its half-line before point 0)");
                                }
                                if k + 1 == ps.len() {
                                    s.push_str(&format!(" (with its half-line after point {})", k + 1));
                                }
                                s
                            };
                            return fail(format!(
                                "{} and {} intersect: the polyline must not cross itself",
                                name(i),
                                name(j)
                            ));
                        }
                    }
                }
            }
        }
        Ok(())
    }

    /// The closest point of the obstacle to `x`, the obstacle's normal there (towards the body)
    /// and the signed distance (positive on the body side).
    pub fn project(&self, x: [f64; 2]) -> Projection {
        match self {
            Obstacle::Line { point, normal } => {
                let l = norm(*normal);
                let nu = if l > 0.0 { [normal[0] / l, normal[1] / l] } else { [0.0, 1.0] };
                let d = dot(sub(x, *point), nu);
                Projection { point: [x[0] - d * nu[0], x[1] - d * nu[1]], normal: nu, signed_distance: d }
            }
            Obstacle::Circle { center, radius } => {
                let r = sub(x, *center);
                let dist = norm(r);
                let nu = if dist > 0.0 { [r[0] / dist, r[1] / dist] } else { [0.0, -1.0] };
                Projection {
                    point: [center[0] + radius * nu[0], center[1] + radius * nu[1]],
                    normal: nu,
                    signed_distance: dist - radius,
                }
            }
            Obstacle::Polyline { points } => project_polyline(points, x),
        }
    }
}

fn project_polyline(points: &[[f64; 2]], x: [f64; 2]) -> Projection {
    let ps = pieces(points);
    // Best candidate: (squared distance, closest point, Some(piece) or None for a vertex, vertex).
    let mut best: Option<(f64, [f64; 2], Option<usize>, usize)> = None;
    for (k, piece) in ps.iter().enumerate() {
        let d = sub(piece.b, piece.a);
        let l2 = dot(d, d);
        if l2 == 0.0 {
            continue;
        }
        let s = dot(sub(x, piece.a), d) / l2;
        if s < piece.s_min || s > piece.s_max {
            continue;
        }
        let p = [piece.a[0] + s * d[0], piece.a[1] + s * d[1]];
        let r = sub(x, p);
        let dist2 = dot(r, r);
        if best.is_none_or(|b| dist2 < b.0) {
            best = Some((dist2, p, Some(k), 0));
        }
    }
    // Interior vertices (the ends P_0, P_{n−1} lie inside the extended end pieces). On a tie the
    // piece is kept (then x − V is along the piece's normal and both rules agree), except for x
    // on the vertex itself, which gets the vertex's normal.
    let interior = points.len().saturating_sub(1);
    for (v, &vertex) in points.iter().enumerate().take(interior).skip(1) {
        let r = sub(x, vertex);
        let dist2 = dot(r, r);
        if dist2 == 0.0 || best.is_none_or(|b| dist2 < b.0) {
            best = Some((dist2, vertex, None, v));
        }
    }
    let Some((dist2, p, piece, vertex)) = best else {
        // Unvalidated degenerate polyline (fewer than two distinct points): the distance to the
        // first point, with an arbitrary normal.
        let p = points.first().copied().unwrap_or([0.0, 0.0]);
        let r = sub(x, p);
        let d = norm(r);
        let nu = if d > 0.0 { [r[0] / d, r[1] / d] } else { [0.0, 1.0] };
        return Projection { point: p, normal: nu, signed_distance: d };
    };
    let r = sub(x, p);
    match piece {
        Some(k) => {
            let nu = left_normal(sub(ps[k].b, ps[k].a));
            Projection { point: p, normal: nu, signed_distance: dot(r, nu) }
        }
        None => {
            let n_before = left_normal(sub(points[vertex], points[vertex - 1]));
            let n_after = left_normal(sub(points[vertex + 1], points[vertex]));
            let pseudo = [n_before[0] + n_after[0], n_before[1] + n_after[1]];
            let dist = dist2.sqrt();
            if dist == 0.0 {
                let l = norm(pseudo);
                let nu = if l > 0.0 { [pseudo[0] / l, pseudo[1] / l] } else { n_before };
                return Projection { point: p, normal: nu, signed_distance: 0.0 };
            }
            let sign = if dot(r, pseudo) >= 0.0 { 1.0 } else { -1.0 };
            Projection { point: p, normal: [sign * r[0] / dist, sign * r[1] / dist], signed_distance: sign * dist }
        }
    }
}
