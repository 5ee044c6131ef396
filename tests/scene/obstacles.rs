//! Obstacle geometry: projections onto lines, circles and polylines as the driver builds them.

use crate::edit::Edit;

use crate::{line_contact, parse};
use signorini::scene::ObstacleSpec;

// ---- obstacle geometry -----------------------------------------------------------------------

#[track_caller]
fn assert_close(a: [f64; 2], b: [f64; 2]) {
    assert!((a[0] - b[0]).abs() < 1e-14 && (a[1] - b[1]).abs() < 1e-14, "{a:?} != {b:?}");
}

/// The scene's obstacle as the driver builds it (`contact::obstacle`, the one projection code).
#[derive(Debug)]
struct Projection {
    distance: f64,
    normal: [f64; 2],
    closest: [f64; 2],
}
trait Project {
    fn project(&self, x: [f64; 2]) -> Projection;
}
impl Project for ObstacleSpec {
    fn project(&self, x: [f64; 2]) -> Projection {
        use signorini::contact::obstacle::Obstacle;
        let o = match self {
            ObstacleSpec::Line { point, normal } => Obstacle::new_line(*point, *normal),
            ObstacleSpec::Circle { center, radius } => Obstacle::new_circle(*center, *radius),
            ObstacleSpec::Polyline { points } => Obstacle::new_polyline(points.clone()),
        }
        .unwrap();
        let p = o.project(x);
        Projection { distance: p.signed_distance, normal: p.normal, closest: p.point }
    }
}

#[test]
fn line_obstacle_projection() {
    let line = ObstacleSpec::Line { point: [1.0, 1.0], normal: [0.6, 0.8] };
    let p = line.project([1.0 + 0.6 * 2.0 + 0.8 * 5.0, 1.0 + 0.8 * 2.0 - 0.6 * 5.0]);
    assert!((p.distance - 2.0).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [0.6, 0.8]);
    assert_close(p.closest, [1.0 + 0.8 * 5.0, 1.0 - 0.6 * 5.0]);
    let p = line.project([1.0 - 0.6, 1.0 - 0.8]);
    assert!((p.distance + 1.0).abs() < 1e-14, "{p:?}");
}

#[test]
fn circle_obstacle_projection() {
    let circle = ObstacleSpec::Circle { center: [0.0, -2.0], radius: 1.0 };
    let p = circle.project([0.0, 0.5]);
    assert!((p.distance - 1.5).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [0.0, 1.0]);
    assert_close(p.closest, [0.0, -1.0]);
    let p = circle.project([3.0, 2.0]);
    assert!((p.distance - 4.0).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [0.6, 0.8]);
    // inside: negative distance; at the centre a fixed normal
    let p = circle.project([0.0, -2.5]);
    assert!((p.distance + 0.5).abs() < 1e-14 && p.normal == [0.0, -1.0], "{p:?}");
    let p = circle.project([0.0, -2.0]);
    // at the centre: contact::obstacle's documented convention, normal (0, -1)
    assert_eq!((p.distance, p.normal, p.closest), (-1.0, [0.0, -1.0], [0.0, -3.0]));
}

#[test]
fn polyline_obstacle_projection() {
    // a V-shaped valley: body above (left of travel), the obstacle below
    //
    //   (-1, 1)             (1, 1)
    //        \   body     /
    //         \          /
    //          \ (0, 0) /
    //            obstacle
    let valley = ObstacleSpec::Polyline { points: vec![[-1.0, 1.0], [0.0, 0.0], [1.0, 1.0]] };
    let s = 0.5f64.sqrt();
    // inside a segment
    let p = valley.project([0.5 - s * 0.1, 0.5 + s * 0.1]);
    assert!((p.distance - 0.1).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [-s, s]);
    assert_close(p.closest, [0.5, 0.5]);
    // below the vertex (a concave vertex on the body's side): inside the obstacle
    let p = valley.project([0.0, -0.3]);
    assert!((p.distance + 0.3).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [0.0, 1.0]);
    assert_close(p.closest, [0.0, 0.0]);
    // above the vertex: closest to both segments, outside
    let p = valley.project([0.0, 0.3]);
    assert!((p.distance - 0.3 * s).abs() < 1e-14, "{p:?}");
    // beyond the ends the segments go on
    let p = valley.project([3.0, 2.0]);
    assert!((p.distance + s).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [-s, s]);
    assert_close(p.closest, [2.5, 2.5]);
    let p = valley.project([-3.0, 3.0]);
    assert!(p.distance.abs() < 1e-14, "{p:?}");

    // a ridge (convex vertex on the body's side)
    let ridge = ObstacleSpec::Polyline { points: vec![[-1.0, -1.0], [0.0, 0.0], [1.0, -1.0]] };
    let p = ridge.project([0.0, 0.3]);
    assert!((p.distance - 0.3).abs() < 1e-14, "{p:?}");
    assert_close(p.normal, [0.0, 1.0]);
    let p = ridge.project([0.0, -0.3]);
    assert!((p.distance + 0.3 * s).abs() < 1e-14, "{p:?}");
    // on the vertex itself: the pseudo-normal
    let p = ridge.project([0.0, 0.0]);
    assert_eq!(p.distance, 0.0);
    assert_close(p.normal, [0.0, 1.0]);
    // two points: a line, body on the left
    let two = ObstacleSpec::Polyline { points: vec![[1.0, 0.0], [0.0, 0.0]] };
    let p = two.project([5.0, -2.0]);
    assert!((p.distance - 2.0).abs() < 1e-14 && p.normal == [-0.0, -1.0], "{p:?}");
}

#[test]
fn polyline_signed_distance_matches_brute_force() {
    // a zigzag: compare the sign of the distance with the side found by casting a vertical ray
    // (the polyline is a graph y = f(x), extended by its end segments)
    let points = vec![[-2.0, 0.0], [-1.0, 0.5], [0.0, -0.2], [0.5, 0.3], [1.5, 0.0]];
    let obstacle = ObstacleSpec::Polyline { points: points.clone() };
    let f = |x: f64| {
        let k = points.windows(2).position(|w| x <= w[1][0]).unwrap_or(points.len() - 2);
        let (a, b) = (points[k], points[k + 1]);
        a[1] + (b[1] - a[1]) * (x - a[0]) / (b[0] - a[0])
    };
    for i in 0..60 {
        for j in 0..40 {
            let x = [-3.0 + 0.1 * i as f64 + 0.013, -1.0 + 0.05 * j as f64 + 0.007];
            let p = obstacle.project(x);
            let above = x[1] > f(x[0]);
            assert_eq!(p.distance > 0.0, above, "{x:?}: {p:?}");
            // |distance| is the distance to the closest point, the normal is a unit vector
            let d = (x[0] - p.closest[0]).hypot(x[1] - p.closest[1]);
            assert!((d - p.distance.abs()).abs() < 1e-12, "{x:?}: {p:?}");
            assert!((p.normal[0].hypot(p.normal[1]) - 1.0).abs() < 1e-12, "{x:?}: {p:?}");
        }
    }
}

#[test]
fn contact_tiny_normal_is_still_a_direction() {
    let text = line_contact("").edit("normal = [0.0, 1.0]", "normal = [0.0, 1e-320]");
    let c = parse(&text).unwrap().contact.unwrap();
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] });
}
