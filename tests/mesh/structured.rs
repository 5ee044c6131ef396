//! Structured rectangles, the cell count for a size, and P1 -> P2.

use crate::{assert_counter_clockwise, assert_outward_normals, close, dist, group_length, mesh_error_text, total_area};
use signorini::mesh::gmsh::{generate, MeshRequest, Shape};
use signorini::mesh::structured::{cells_for_size, rectangle};
use signorini::mesh::Order;
use signorini::Error;

// ---------------------------------------------------------------------------------------------
// Structured rectangles
// ---------------------------------------------------------------------------------------------

#[test]
fn structured_rectangle_counts_groups_and_area() {
    let (origin, size) = ([-1.5, 0.25], [3.0, 0.7]);
    let mesh = rectangle(origin, size, 5, 3, Order::P1).unwrap();
    assert_eq!(mesh.num_nodes(), 6 * 4);
    assert_eq!(mesh.num_cells(), 2 * 5 * 3);
    assert_eq!(mesh.num_edges(), 2 * (5 + 3));
    let names: Vec<(&str, u8)> = mesh.groups.iter().map(|g| (g.name.as_str(), g.dim)).collect();
    assert_eq!(names, [("bottom", 1), ("right", 1), ("top", 1), ("left", 1), ("domain", 2)]);
    let domain = mesh.require_group("domain", 2).unwrap();
    assert!(mesh.cell_group.iter().all(|&g| g == domain));
    assert!(close(total_area(&mesh), 3.0 * 0.7, 1e-14));
    for (name, len, count) in [("bottom", 3.0, 5), ("top", 3.0, 5), ("left", 0.7, 3), ("right", 0.7, 3)] {
        let g = mesh.require_group(name, 1).unwrap();
        assert_eq!(mesh.edges_in_group(g).count(), count, "{name}");
        assert!(close(group_length(&mesh, name), len, 1e-14), "{name}: {}", group_length(&mesh, name));
    }
    // Corners are exact.
    assert_eq!(mesh.nodes[0], origin);
    assert_eq!(mesh.nodes[mesh.num_nodes() - 1], [origin[0] + size[0], origin[1] + size[1]]);
    assert_counter_clockwise(&mesh);
    assert_outward_normals(&mesh);
    // Outward normals are exactly the axis directions.
    for (name, normal) in [("bottom", [0.0, -1.0]), ("right", [1.0, 0.0]), ("top", [0.0, 1.0]), ("left", [-1.0, 0.0])] {
        let g = mesh.require_group(name, 1).unwrap();
        for e in mesh.edges_in_group(g) {
            assert_eq!(mesh.edge_normal(e).0, normal, "{name} edge {e}");
        }
    }
}

#[test]
fn structured_rectangle_diagonals_alternate() {
    let mesh = rectangle([0.0, 0.0], [1.0, 1.0], 4, 4, Order::P1).unwrap();
    // Count diagonals by slope sign: checkerboard gives as many of each.
    let (mut rising, mut falling) = (0, 0);
    for c in 0..mesh.num_cells() {
        let v = mesh.cell(c);
        for k in 0..3 {
            let (a, b) = (mesh.nodes[v[k]], mesh.nodes[v[(k + 1) % 3]]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            if dx != 0.0 && dy != 0.0 {
                if dx * dy > 0.0 {
                    rising += 1;
                } else {
                    falling += 1;
                }
            }
        }
    }
    // Each cell's diagonal is a side of both its triangles.
    assert_eq!((rising, falling), (16, 16));
}

#[test]
fn structured_rectangle_p2() {
    let (nx, ny) = (4, 3);
    let mesh = rectangle([1.0, 2.0], [2.0, 1.5], nx, ny, Order::P2).unwrap();
    let nv = (nx + 1) * (ny + 1);
    assert_eq!(mesh.num_nodes(), (2 * nx + 1) * (2 * ny + 1));
    assert_eq!(mesh.num_cells(), 2 * nx * ny);
    assert_eq!(mesh.num_edges(), 2 * (nx + ny));
    for c in 0..mesh.num_cells() {
        let v = mesh.cell(c);
        assert!(v[..3].iter().all(|&x| x < nv), "vertices come first");
        for k in 0..3 {
            let (a, b) = (mesh.nodes[v[k]], mesh.nodes[v[(k + 1) % 3]]);
            assert_eq!(mesh.nodes[v[3 + k]], [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
        }
    }
    for e in 0..mesh.num_edges() {
        let ed = mesh.edge(e);
        let (a, b) = (mesh.nodes[ed[0]], mesh.nodes[ed[1]]);
        assert_eq!(mesh.nodes[ed[2]], [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
    }
    assert!(close(total_area(&mesh), 3.0, 1e-14));
    assert!(close(group_length(&mesh, "top"), 2.0, 1e-14));
    assert_counter_clockwise(&mesh);
    assert_outward_normals(&mesh);
    // Same nodes as converting the P1 mesh.
    let converted = rectangle([1.0, 2.0], [2.0, 1.5], nx, ny, Order::P1).unwrap().to_quadratic();
    let mut a = mesh.nodes.clone();
    let mut b = converted.nodes.clone();
    let key = |p: &[f64; 2]| (p[0].to_bits(), p[1].to_bits());
    a.sort_by_key(key);
    b.sort_by_key(key);
    assert_eq!(a, b);
}

#[test]
fn structured_rectangle_rejects_bad_arguments() {
    let (e, text) = mesh_error_text(rectangle([0.0, 0.0], [1.0, 1.0], 0, 3, Order::P1));
    assert!(matches!(e, Error::Mesh { .. }));
    assert!(text.contains("rectangle") && text.contains("nx = 0"), "{text}");
    let (e, text) = mesh_error_text(rectangle([0.0, 0.0], [1.0, -2.0], 2, 3, Order::P1));
    assert!(matches!(e, Error::Mesh { .. }));
    assert!(text.contains("-2"), "{text}");
    let (_, text) = mesh_error_text(rectangle([0.0, 0.0], [1.0, 1.0], usize::MAX, 2, Order::P1));
    assert!(text.contains("more than"), "{text}");
}

#[test]
fn cells_for_size_rounds_up() {
    assert_eq!(cells_for_size([1.0, 0.3], 0.1), (10, 3));
    assert_eq!(cells_for_size([1.05, 0.31], 0.1), (11, 4));
    assert_eq!(cells_for_size([0.01, 2.0], 1.0), (1, 2));
}

/// A size that is a whole number of cells gives that number, also when the floating-point
/// quotient lands just above it (0.07 / 0.01 = 7.000000000000001).
#[test]
fn cells_for_size_ignores_round_off() {
    let quotients = [0.07f64 / 0.01, 0.14 / 0.02, 0.07 / 0.00125];
    assert!(quotients.iter().all(|q| *q > q.round()), "the cases below must exercise round-off: {quotients:?}");
    assert_eq!(cells_for_size([0.07, 0.14], 0.01), (7, 14));
    assert_eq!(cells_for_size([0.14, 0.07], 0.02), (7, 4));
    assert_eq!(cells_for_size([0.07, 0.14], 0.00125), (56, 112));
    // the square block of Raous–Chabrand–Lebon: 32 edges along each side
    assert_eq!(cells_for_size([0.04, 0.04], 0.04 / 32.0), (32, 32));
    assert_eq!(cells_for_size([0.04, 0.04], 1.25e-3), (32, 32));
    // a genuine excess still adds a cell
    assert_eq!(cells_for_size([0.0700001, 1.0], 0.01), (8, 100));
}

// ---------------------------------------------------------------------------------------------
// P1 -> P2
// ---------------------------------------------------------------------------------------------

#[test]
fn to_quadratic_adds_one_node_per_edge_at_the_midpoint() {
    let p1 = rectangle([0.0, 0.0], [1.0, 2.0], 3, 5, Order::P1).unwrap();
    let (v, t) = (p1.num_nodes(), p1.num_cells());
    let e = v + t - 1; // Euler: V - E + T = 1 for a disc
    let mut p2 = p1.to_quadratic();
    assert_eq!(p2.order, Order::P2);
    assert_eq!(p2.num_nodes(), v + e);
    assert_eq!(&p2.nodes[..v], &p1.nodes[..]);
    for c in 0..t {
        let cell = p2.cell(c);
        assert_eq!(&cell[..3], p1.cell(c));
        for k in 0..3 {
            let (a, b) = (p2.nodes[cell[k]], p2.nodes[cell[(k + 1) % 3]]);
            assert!(cell[3 + k] >= v);
            assert_eq!(p2.nodes[cell[3 + k]], [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
        }
    }
    // Every new node is used, interior ones by two triangles.
    let mut uses = vec![0; p2.num_nodes()];
    for c in 0..t {
        for &m in &p2.cell(c)[3..] {
            uses[m] += 1;
        }
    }
    assert!(uses[v..].iter().all(|&u| u == 1 || u == 2));
    assert_eq!(uses[v..].iter().filter(|&&u| u == 1).count(), p1.num_edges());
    assert_eq!(p2.num_edges(), p1.num_edges());
    p2.validate().unwrap();
}

#[test]
fn to_quadratic_with_snaps_boundary_mid_nodes() {
    let p1 = generate(&MeshRequest {
        shape: Shape::Disc { center: [0.5, -0.25], radius: 1.0 },
        cell_size: 0.2,
        refinement: None,
        order: Order::P1,
    })
    .unwrap();
    let circle = p1.require_group("circle", 1).unwrap();
    let c = [0.5, -0.25];
    let mut p2 = p1.to_quadratic_with(|g, p| {
        assert_eq!(g, circle);
        let r = dist(p, c);
        [c[0] + (p[0] - c[0]) / r, c[1] + (p[1] - c[1]) / r]
    });
    p2.validate().unwrap();
    for e in 0..p2.num_edges() {
        assert!((dist(p2.nodes[p2.edge(e)[2]], c) - 1.0).abs() < 1e-14);
    }
    let pi = std::f64::consts::PI;
    let (err1, err2) = ((total_area(&p1) - pi).abs(), (total_area(&p2) - pi).abs());
    assert!(err2 < err1 / 50.0, "P1 area error {err1:e}, snapped P2 {err2:e}");
}
