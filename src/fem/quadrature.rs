//! Quadrature rules on the reference triangle and on the unit interval.
//!
//! # Reference triangle
//!
//! ```text
//!   η
//!   (0,1)
//!   |\
//!   | \        T = { (ξ, η) : ξ ≥ 0, η ≥ 0, ξ + η ≤ 1 },  |T| = 1/2
//!   |  \
//!   |   \      ∫_T f ≈ Σ_q w_q f(ξ_q, η_q),  Σ_q w_q = 1/2
//!   (0,0)-(1,0)  ξ
//! ```
//!
//! Every rule below has all its points inside `T` and all its weights positive (so a
//! quadrature of a positive integrand is positive, and element matrices stay semi-definite).
//! Points are given in barycentric coordinates `(λ0, λ1, λ2)` with `(ξ, η) = (λ1, λ2)`.
//!
//! | exact for degree | points | rule | source |
//! |---|---|---|---|
//! | 0, 1 | 1 | centroid, `w = 1/2` | Strang & Fix (1973), Table 4.1 |
//! | 2 | 3 | `(2/3, 1/6, 1/6)` and permutations, `w = 1/6` | Strang & Fix (1973), Table 4.1 |
//! | 3, 4 | 6 | `(1−2a, a, a)`, `a = 0.44594849…`, `w = 0.11169079…`; `(1−2b, b, b)`, `b = 0.09157621…`, `w = 0.05497587…` | Dunavant (1985), degree 4 |
//! | 5 | 7 | centroid `w = 9/80`; `a = (6 − √15)/21`, `w = (155 − √15)/2400`; `b = (6 + √15)/21`, `w = (155 + √15)/2400` | Radon (1948); Stroud (1971) T2:5-1 |
//! | d ≥ 6 | n² | collapsed (Duffy) product of `n = ⌈(d + 2)/2⌉` Gauss–Legendre points | Stroud (1971), §2.7 |
//!
//! For degree 3 we use the 6-point degree-4 rule: the 4-point degree-3 rule of Strang & Fix has a
//! negative weight. The degree-4 constants were recomputed to 20 digits by solving the moment
//! equations (Newton in 40-digit arithmetic).
//!
//! The collapsed rule maps the unit square onto `T` by `(ξ, η) = (u, (1 − u) v)`, whose Jacobian is
//! `1 − u`: a polynomial of degree `d` in `(ξ, η)` becomes degree `d + 1` in `u` and `d` in `v`, so
//! `n` Gauss points per direction (exact to degree `2n − 1`) suffice when `2n − 1 ≥ d + 1`.
//!
//! # Unit interval
//!
//! Gauss–Legendre with `n` points on `[0, 1]` (weights summing to 1) is exact for polynomials of
//! degree `2n − 1`. The points are the roots of the Legendre polynomial `P_n` on `[−1, 1]`, found by
//! Newton's iteration on the three-term recurrence (Abramowitz & Stegun 25.4.29; Press et al.,
//! *Numerical Recipes*, §4.6), then mapped by `x = (1 + t)/2`, `w = w_t / 2`.
//!
//! References: G. Strang, G. Fix, *An Analysis of the Finite Element Method*, Prentice-Hall 1973;
//! D. A. Dunavant, "High degree efficient symmetrical Gaussian quadrature rules for the
//! triangle", Int. J. Numer. Meth. Engng 21 (1985) 1129–1148; J. Radon, Monatsh. Math. 52 (1948)
//! 286–300; A. H. Stroud, *Approximate Calculation of Multiple Integrals*, Prentice-Hall 1971.

/// A quadrature rule on the reference triangle (points `(ξ, η)`, weights summing to 1/2).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleRule {
    /// Points `(ξ, η)` on the reference triangle.
    pub points: Vec<[f64; 2]>,
    /// Weights, one per point.
    pub weights: Vec<f64>,
    /// Highest total polynomial degree integrated exactly.
    pub degree: usize,
}

impl TriangleRule {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// Whether the rule has no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// A quadrature rule on `[0, 1]` (weights summing to 1).
#[derive(Debug, Clone, PartialEq)]
pub struct LineRule {
    /// Points in `[0, 1]`.
    pub points: Vec<f64>,
    /// Weights, one per point.
    pub weights: Vec<f64>,
    /// Highest polynomial degree integrated exactly.
    pub degree: usize,
}

impl LineRule {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.points.len()
    }
    /// Whether the rule has no points.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }
}

/// Push the 3 points of the orbit `(1 − 2a, a, a)` (barycentric) with weight `w`.
fn push_orbit3(rule: &mut TriangleRule, a: f64, w: f64) {
    let c = 1.0 - 2.0 * a;
    // (ξ, η) = (λ1, λ2) of the permutations (c,a,a), (a,c,a), (a,a,c).
    for p in [[a, a], [c, a], [a, c]] {
        rule.points.push(p);
        rule.weights.push(w);
    }
}

/// The cheapest rule of the table above that is exact for polynomials of total degree `degree`.
pub fn triangle(degree: usize) -> TriangleRule {
    let mut rule = TriangleRule { points: Vec::new(), weights: Vec::new(), degree: 0 };
    match degree {
        0 | 1 => {
            rule.points.push([1.0 / 3.0, 1.0 / 3.0]);
            rule.weights.push(0.5);
            rule.degree = 1;
        }
        2 => {
            push_orbit3(&mut rule, 1.0 / 6.0, 1.0 / 6.0);
            rule.degree = 2;
        }
        3 | 4 => {
            push_orbit3(&mut rule, 0.445_948_490_915_964_9, 0.111_690_794_839_005_74);
            push_orbit3(&mut rule, 0.091_576_213_509_770_74, 0.054_975_871_827_660_935);
            rule.degree = 4;
        }
        5 => {
            let s15 = 15.0f64.sqrt();
            rule.points.push([1.0 / 3.0, 1.0 / 3.0]);
            rule.weights.push(9.0 / 80.0);
            push_orbit3(&mut rule, (6.0 - s15) / 21.0, (155.0 - s15) / 2400.0);
            push_orbit3(&mut rule, (6.0 + s15) / 21.0, (155.0 + s15) / 2400.0);
            rule.degree = 5;
        }
        d => {
            let n = (d + 3) / 2;
            let gl = gauss_legendre(n);
            for (&u, &wu) in gl.points.iter().zip(&gl.weights) {
                for (&v, &wv) in gl.points.iter().zip(&gl.weights) {
                    rule.points.push([u, (1.0 - u) * v]);
                    rule.weights.push(wu * wv * (1.0 - u));
                }
            }
            rule.degree = 2 * n - 2;
        }
    }
    rule
}

/// The points of `rule` mapped onto the straight triangle `t` (affinely,
/// `x = t0 + ξ (t1 − t0) + η (t2 − t0)`) with their weights times `|det J|`: the rule for
/// `∫_t f dx` (used piece by piece on the sub-triangles of HCT cells).
pub fn on_triangle(rule: &TriangleRule, t: [[f64; 2]; 3]) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
    let (a, e1, e2) = (t[0], [t[1][0] - t[0][0], t[1][1] - t[0][1]], [t[2][0] - t[0][0], t[2][1] - t[0][1]]);
    let jac = (e1[0] * e2[1] - e1[1] * e2[0]).abs();
    rule.points
        .iter()
        .zip(&rule.weights)
        .map(move |(xi, w)| ([a[0] + xi[0] * e1[0] + xi[1] * e2[0], a[1] + xi[0] * e1[1] + xi[1] * e2[1]], w * jac))
}

/// Gauss–Legendre rule with `n` points on `[0, 1]` (`n = 0` is treated as 1), exact for degree
/// `2n − 1`.
pub fn gauss_legendre(n: usize) -> LineRule {
    let n = n.max(1);
    let mut points = vec![0.0; n];
    let mut weights = vec![0.0; n];
    for i in 0..n.div_ceil(2) {
        // Initial guess for the i-th largest root of P_n (Tricomi's asymptotic form).
        let mut t = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (p, d) = legendre_and_derivative(n, t);
            dp = d;
            let step = p / d;
            t -= step;
            if step.abs() <= 1e-16 * t.abs().max(1.0) {
                let (_, d) = legendre_and_derivative(n, t);
                dp = d;
                break;
            }
        }
        let w = 2.0 / ((1.0 - t * t) * dp * dp);
        // Symmetric pair t, −t on [−1, 1]  ->  (1 ± t)/2 on [0, 1].
        points[i] = 0.5 * (1.0 - t);
        points[n - 1 - i] = 0.5 * (1.0 + t);
        weights[i] = 0.5 * w;
        weights[n - 1 - i] = 0.5 * w;
    }
    if n % 2 == 1 {
        points[n / 2] = 0.5;
    }
    LineRule { points, weights, degree: 2 * n - 1 }
}

/// Gauss–Legendre rule on `[0, 1]` exact for polynomials of degree `degree`.
pub fn line(degree: usize) -> LineRule {
    gauss_legendre(degree / 2 + 1)
}

/// `(P_n(t), P_n'(t))` by the recurrence `k P_k = (2k − 1) t P_{k−1} − (k − 1) P_{k−2}`.
fn legendre_and_derivative(n: usize, t: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, t);
    for k in 2..=n {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * t * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    if n == 0 {
        return (1.0, 0.0);
    }
    // P_n' = n (t P_n − P_{n−1}) / (t² − 1)
    let d = n as f64 * (t * p1 - p0) / (t * t - 1.0);
    (p1, d)
}
