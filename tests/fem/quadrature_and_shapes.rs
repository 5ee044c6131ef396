//! Quadrature rules, Lagrange shape functions and the isoparametric map of curved cells.

use crate::{curved_p2_triangle, monomial_integral, Random};
use signorini::fem::{lagrange, quadrature};
use signorini::mesh::Order;

// ---------------------------------------------------------------------------------------------
// Quadrature.
// ---------------------------------------------------------------------------------------------

#[test]
fn triangle_rules_integrate_monomials_exactly() {
    for degree in 0..=10 {
        let rule = quadrature::triangle(degree);
        assert!(rule.degree >= degree, "rule for degree {degree} claims only {}", rule.degree);
        assert!(rule.weights.iter().all(|&w| w > 0.0), "degree {degree}: a weight is not positive");
        assert!(
            rule.points.iter().all(|p| p[0] >= 0.0 && p[1] >= 0.0 && p[0] + p[1] <= 1.0),
            "degree {degree}: a point lies outside the reference triangle"
        );
        for total in 0..=rule.degree as u32 {
            for a in 0..=total {
                let b = total - a;
                let q: f64 = rule
                    .points
                    .iter()
                    .zip(&rule.weights)
                    .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32))
                    .sum();
                let exact = monomial_integral(a, b);
                assert!((q - exact).abs() <= 1e-14 * exact, "degree {degree} rule: x^{a} y^{b}: {q} vs {exact}");
            }
        }
    }
    // The tabled rules are not exact one degree higher (so the test above can fail).
    for (degree, points) in [(1, 1), (2, 3), (4, 6), (5, 7)] {
        let rule = quadrature::triangle(degree);
        assert_eq!(rule.len(), points);
        let d = rule.degree as u32 + 1;
        let worst = (0..=d)
            .map(|a| {
                let q: f64 = rule
                    .points
                    .iter()
                    .zip(&rule.weights)
                    .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi((d - a) as i32))
                    .sum();
                (q - monomial_integral(a, d - a)).abs()
            })
            .fold(0.0, f64::max);
        assert!(worst > 1e-6, "degree {degree} rule is unexpectedly exact for degree {d}");
    }
}

#[test]
fn gauss_legendre_integrates_monomials_exactly() {
    for n in 1..=8 {
        let rule = quadrature::gauss_legendre(n);
        assert_eq!(rule.len(), n);
        assert_eq!(rule.degree, 2 * n - 1);
        assert!(rule.weights.iter().all(|&w| w > 0.0));
        assert!(rule.points.windows(2).all(|p| p[0] < p[1]));
        for k in 0..=2 * n as i32 {
            let q: f64 = rule.points.iter().zip(&rule.weights).map(|(x, w)| w * x.powi(k)).sum();
            let exact = 1.0 / (k as f64 + 1.0);
            if k < 2 * n as i32 {
                assert!((q - exact).abs() <= 1e-15, "{n} points, x^{k}: {q} vs {exact}");
            } else {
                assert!((q - exact).abs() > 1e-12, "{n} points exact for x^{k}?");
            }
        }
    }
    // Known values: 2 points at 1/2 ± 1/(2√3).
    let r = quadrature::gauss_legendre(2);
    assert!((r.points[0] - (0.5 - 0.5 / 3f64.sqrt())).abs() < 1e-16);
    assert_eq!(quadrature::line(5).len(), 3);
}

// ---------------------------------------------------------------------------------------------
// Lagrange elements and the isoparametric map.
// ---------------------------------------------------------------------------------------------

#[test]
fn shape_functions_are_nodal_and_complete() {
    for order in [Order::P1, Order::P2] {
        let n = order.nodes_per_cell();
        let nodes = lagrange::reference_nodes(order);
        for (i, &xi) in nodes.iter().enumerate() {
            let v = lagrange::shape_values(order, xi);
            for j in 0..n {
                assert!((v[j] - if i == j { 1.0 } else { 0.0 }).abs() < 1e-15, "{order:?}: N{j} at node {i}");
            }
        }
        let mut rng = Random(42);
        for _ in 0..20 {
            let (a, b) = (0.5 * (rng.next() + 1.0), 0.5 * (rng.next() + 1.0));
            let xi = if a + b <= 1.0 { [a, b] } else { [1.0 - a, 1.0 - b] };
            let v = lagrange::shape_values(order, xi);
            let g = lagrange::shape_gradients(order, xi);
            assert!((v[..n].iter().sum::<f64>() - 1.0).abs() < 1e-15);
            // Reproduce ξ, η (and ξη, ξ² for P2) and compare gradients with finite differences.
            let fns: Vec<Box<dyn Fn([f64; 2]) -> f64>> = match order {
                Order::P1 => vec![Box::new(|p: [f64; 2]| p[0]), Box::new(|p: [f64; 2]| 2.0 * p[1] - p[0] + 1.0)],
                Order::P2 => vec![
                    Box::new(|p: [f64; 2]| p[0] * p[1]),
                    Box::new(|p: [f64; 2]| p[0] * p[0] - 3.0 * p[1] * p[1] + p[1]),
                ],
            };
            for f in &fns {
                let interp: f64 = (0..n).map(|k| v[k] * f(nodes[k])).sum();
                assert!((interp - f(xi)).abs() < 1e-14);
            }
            for k in 0..n {
                let eps = 1e-6;
                for d in 0..2 {
                    let (mut p, mut m) = (xi, xi);
                    p[d] += eps;
                    m[d] -= eps;
                    let fd = (lagrange::shape_values(order, p)[k] - lagrange::shape_values(order, m)[k]) / (2.0 * eps);
                    assert!((fd - g[k][d]).abs() < 1e-8, "{order:?}: dN{k}/dξ{d}: {fd} vs {}", g[k][d]);
                }
            }
        }
    }
}

#[test]
fn isoparametric_map_of_a_curved_triangle() {
    let delta = 0.2;
    let x = curved_p2_triangle(delta);
    assert!(!lagrange::is_affine(&x));
    assert!(lagrange::is_affine(&curved_p2_triangle(0.0)));
    // Area: straight triangle + parabolic segment (2/3 · chord · sagitta); det J is quadratic.
    let rule = quadrature::triangle(2);
    let area: f64 =
        rule.points.iter().zip(&rule.weights).map(|(&p, w)| w * lagrange::map_cell_point(Order::P2, &x, p).det).sum();
    let exact = 1.0 + 2.0 / 3.0 * 2.0 * delta;
    assert!((area - exact).abs() < 1e-14, "area {area} vs {exact}");
    // The physical gradients of the coordinate functions are exact: Σ x_k ∇N_k = (1, 0).
    let mut rng = Random(7);
    for _ in 0..10 {
        let (a, b) = (0.5 * (rng.next() + 1.0), 0.5 * (rng.next() + 1.0));
        let xi = if a + b <= 1.0 { [a, b] } else { [1.0 - a, 1.0 - b] };
        let p = lagrange::map_cell_point(Order::P2, &x, xi);
        let mut gx = [0.0; 2];
        let mut gy = [0.0; 2];
        for k in 0..6 {
            for d in 0..2 {
                gx[d] += x[k][0] * p.gradients[k][d];
                gy[d] += x[k][1] * p.gradients[k][d];
            }
        }
        assert!(
            (gx[0] - 1.0).abs() < 1e-14 && gx[1].abs() < 1e-14 && gy[0].abs() < 1e-14 && (gy[1] - 1.0).abs() < 1e-14
        );
        let v = lagrange::shape_values(Order::P2, xi);
        assert_eq!(p.x, lagrange::map_point(&x, &v[..6]));
    }
}

#[test]
fn edge_maps_integrate_curved_edges() {
    // Parabolic edge from (0,0) to (L,0) through (L/2, −δ): ∫ n ds = (Δy, −Δx) exactly, and the
    // length has a closed form.
    let (l, delta) = (2.0, 0.3);
    let edge = [[0.0, 0.0], [l, 0.0], [0.5 * l, -delta]];
    let rule = quadrature::gauss_legendre(3);
    let mut n_ds = [0.0; 2];
    for (&t, &w) in rule.points.iter().zip(&rule.weights) {
        let p = lagrange::map_edge_point(&edge, t);
        n_ds[0] += w * p.length_element * p.normal[0];
        n_ds[1] += w * p.length_element * p.normal[1];
    }
    assert!(n_ds[0].abs() < 1e-15 && (n_ds[1] + l).abs() < 1e-15, "∫ n ds = {n_ds:?}");
    let k = 4.0 * delta;
    let exact_length = 0.5 * ((l * l + k * k).sqrt() + l * l / k * (k / l).asinh());
    let fine = quadrature::gauss_legendre(30);
    let length: f64 = fine
        .points
        .iter()
        .zip(&fine.weights)
        .map(|(&t, &w)| w * lagrange::map_edge_point(&edge, t).length_element)
        .sum();
    assert!((length - exact_length).abs() < 1e-13, "{length} vs {exact_length}");
    // Outward normal at the middle of the bulge points down (domain on the left of 0 -> 1).
    let mid = lagrange::map_edge_point(&edge, 0.5);
    assert!((mid.normal[0]).abs() < 1e-15 && (mid.normal[1] + 1.0).abs() < 1e-15);
    assert_eq!(mid.x, [0.5 * l, -delta]);
    // Straight 2-node edge.
    let p = lagrange::map_edge_point(&[[1.0, 1.0], [1.0, 3.0]], 0.25);
    assert_eq!(p.x, [1.0, 1.5]);
    assert_eq!(p.length_element, 2.0);
    assert_eq!(p.normal, [1.0, 0.0]);
}
