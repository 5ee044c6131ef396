//! Tests of the mesh module: structured rectangles, P1 -> P2, validation, MSH 4.1 input and
//! Gmsh-generated meshes (the `gmsh` binary must be installed).
use std::path::{Path, PathBuf};
use std::process::Command;

use signorini::mesh::gmsh::{generate, generate_from_geo, gmsh_version, MeshRequest, Refinement, Shape};
use signorini::mesh::msh::read_msh;
use signorini::mesh::structured::{cells_for_size, rectangle};
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use signorini::Error;

// ---------------------------------------------------------------------------------------------
// Helpers
// ---------------------------------------------------------------------------------------------

/// A directory of its own for one test, removed when dropped.
struct Scratch(PathBuf);

impl Scratch {
    fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("signorini-mesh-tests-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        Scratch(dir)
    }
    fn path(&self, file: &str) -> PathBuf {
        self.0.join(file)
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// The path an inline file `name` is written to by [`read_inline`].
fn inline_path(name: &str) -> PathBuf {
    std::env::temp_dir().join(format!("signorini-mesh-tests-{}-{name}", std::process::id())).join(format!("{name}.msh"))
}

/// Write `text` to `<name>.msh` in a scratch directory, read it, remove it.
fn read_inline(name: &str, text: &str) -> signorini::Result<Mesh> {
    let dir = Scratch::new(name);
    let path = dir.path(&format!("{name}.msh"));
    assert_eq!(path, inline_path(name));
    std::fs::write(&path, text).unwrap();
    read_msh(&path)
}

fn signed_area(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
}

fn vertex_area(mesh: &Mesh, c: usize) -> f64 {
    let v = mesh.cell(c);
    signed_area(mesh.nodes[v[0]], mesh.nodes[v[1]], mesh.nodes[v[2]])
}

/// Area of the (possibly curved) cell: integral of det J of the isoparametric map. For P2,
/// det J is quadratic and the edge-midpoint rule (weights 1/6) integrates it exactly.
fn cell_area(mesh: &Mesh, c: usize) -> f64 {
    match mesh.order {
        Order::P1 => vertex_area(mesh, c),
        Order::P2 => {
            let v = mesh.cell(c);
            let x: Vec<[f64; 2]> = v.iter().map(|&n| mesh.nodes[n]).collect();
            let det = |xi: f64, eta: f64| {
                let l0 = 1.0 - xi - eta;
                let dxi = [1.0 - 4.0 * l0, 4.0 * xi - 1.0, 0.0, 4.0 * (l0 - xi), 4.0 * eta, -4.0 * eta];
                let deta = [1.0 - 4.0 * l0, 0.0, 4.0 * eta - 1.0, -4.0 * xi, 4.0 * xi, 4.0 * (l0 - eta)];
                let mut j = [0.0; 4];
                for i in 0..6 {
                    j[0] += dxi[i] * x[i][0];
                    j[1] += deta[i] * x[i][0];
                    j[2] += dxi[i] * x[i][1];
                    j[3] += deta[i] * x[i][1];
                }
                j[0] * j[3] - j[1] * j[2]
            };
            (det(0.5, 0.0) + det(0.5, 0.5) + det(0.0, 0.5)) / 6.0
        }
    }
}

fn total_area(mesh: &Mesh) -> f64 {
    (0..mesh.num_cells()).map(|c| cell_area(mesh, c)).sum()
}

fn group_length(mesh: &Mesh, name: &str) -> f64 {
    let g = mesh.require_group(name, 1).unwrap();
    mesh.edges_in_group(g).map(|e| mesh.edge_normal(e).1).sum()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1.0)
}

fn dist(p: [f64; 2], q: [f64; 2]) -> f64 {
    ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
}

/// Every boundary edge's outward normal points away from the cell it bounds.
fn assert_outward_normals(mesh: &Mesh) {
    for e in 0..mesh.num_edges() {
        let ed = mesh.edge(e);
        let (n, _) = mesh.edge_normal(e);
        let c = (0..mesh.num_cells())
            .find(|&c| {
                let v = mesh.cell(c);
                v[..3].contains(&ed[0]) && v[..3].contains(&ed[1])
            })
            .expect("boundary edge on a triangle");
        let v = mesh.cell(c);
        let opposite = *v[..3].iter().find(|&&x| x != ed[0] && x != ed[1]).unwrap();
        let (a, o) = (mesh.nodes[ed[0]], mesh.nodes[opposite]);
        let inward = [o[0] - a[0], o[1] - a[1]];
        assert!(n[0] * inward[0] + n[1] * inward[1] < 0.0, "edge {e} normal {n:?} points inwards");
    }
}

fn assert_counter_clockwise(mesh: &Mesh) {
    for c in 0..mesh.num_cells() {
        assert!(vertex_area(mesh, c) > 0.0, "triangle {c} is not counter-clockwise");
    }
}

fn mesh_error_text(result: signorini::Result<Mesh>) -> (Error, String) {
    let e = result.expect_err("expected an error");
    let text = e.to_string();
    (e, text)
}

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

// ---------------------------------------------------------------------------------------------
// Validation of hand-built meshes
// ---------------------------------------------------------------------------------------------

/// Unit square, two triangles (0,1,2) and (0,2,3), with boundary group "wall" on all sides.
fn square(order: Order) -> Mesh {
    let mut nodes = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let groups = vec![
        PhysicalGroup { name: "wall".into(), tag: 1, dim: 1 },
        PhysicalGroup { name: "domain".into(), tag: 2, dim: 2 },
    ];
    match order {
        Order::P1 => Mesh {
            order,
            nodes,
            cells: vec![0, 1, 2, 0, 2, 3],
            cell_group: vec![1, 1],
            edges: vec![0, 1, 1, 2, 2, 3, 3, 0],
            edge_group: vec![0; 4],
            groups,
        },
        Order::P2 => {
            // mids: 4 (0-1), 5 (1-2), 6 (2-3), 7 (3-0), 8 (0-2)
            nodes.extend([[0.5, 0.0], [1.0, 0.5], [0.5, 1.0], [0.0, 0.5], [0.5, 0.5]]);
            Mesh {
                order,
                nodes,
                cells: vec![0, 1, 2, 4, 5, 8, 0, 2, 3, 8, 6, 7],
                cell_group: vec![1, 1],
                edges: vec![0, 1, 4, 1, 2, 5, 2, 3, 6, 3, 0, 7],
                edge_group: vec![0; 4],
                groups,
            }
        }
    }
}

#[test]
fn validate_accepts_and_orients() {
    for order in [Order::P1, Order::P2] {
        let mut mesh = square(order);
        // Reverse the boundary edges: validate turns them back.
        let npe = order.nodes_per_edge();
        for e in mesh.edges.chunks_exact_mut(npe) {
            e.swap(0, 1);
        }
        mesh.validate().unwrap();
        assert_eq!(&mesh.edges[..2], &[0, 1]);
        assert_outward_normals(&mesh);
    }
}

#[test]
fn validate_flips_an_all_clockwise_mesh() {
    let mut mesh = square(Order::P2);
    // Clockwise: (0,2,1 | m02, m21, m10) and (0,3,2 | m03, m32, m20).
    mesh.cells = vec![0, 2, 1, 8, 5, 4, 0, 3, 2, 7, 6, 8];
    mesh.validate().unwrap();
    assert_eq!(mesh.cells, vec![0, 1, 2, 4, 5, 8, 0, 2, 3, 8, 6, 7]);
    assert_counter_clockwise(&mesh);
    assert!(close(total_area(&mesh), 1.0, 1e-15));
}

#[test]
fn validate_rejects_mixed_orientation() {
    // Three triangles of a fan, the middle one clockwise.
    let mut mesh = Mesh {
        order: Order::P1,
        nodes: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [-1.0, 1.0]],
        cells: vec![0, 1, 2, 0, 3, 2, 0, 3, 4],
        cell_group: vec![NO_GROUP; 3],
        edges: vec![],
        edge_group: vec![],
        groups: vec![],
    };
    let e = mesh.validate().unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, Error::Mesh { .. }));
    assert!(text.contains("triangle 1 (nodes 0, 3, 2)") && text.contains("inverted"), "{text}");
}

#[test]
fn validate_rejects_degenerate_triangle() {
    let mut mesh = square(Order::P1);
    mesh.nodes[2] = [2.0, 0.0]; // collinear with 0 and 1
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("triangle 0 (nodes 0, 1, 2)") && e.contains("degenerate"), "{e}");
}

#[test]
fn validate_rejects_unreferenced_node() {
    let mut mesh = square(Order::P1);
    mesh.nodes.push([0.5, 0.25]);
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("node 4 at (0.5, 0.25)") && e.contains("no triangle uses"), "{e}");
}

#[test]
fn validate_rejects_boundary_edge_off_the_triangles() {
    let mut mesh = square(Order::P1);
    mesh.edges.extend([1, 3]); // the other diagonal
    mesh.edge_group.push(0);
    let e = mesh.validate().unwrap_err().to_string();
    assert!(
        e.contains("boundary edge 4 of group 'wall' (nodes 1, 3)") && e.contains("not a side of any triangle"),
        "{e}"
    );
    // An interior side is not a boundary edge either.
    let mut mesh = square(Order::P1);
    mesh.edges.extend([0, 2]);
    mesh.edge_group.push(0);
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("boundary edge 4") && e.contains("2 triangles"), "{e}");
}

#[test]
fn validate_rejects_other_defects() {
    // Index out of range.
    let mut mesh = square(Order::P1);
    mesh.cells[4] = 9;
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("triangle 1 (nodes 0, 9, 3)") && e.contains("4 nodes"), "{e}");
    // Non-finite coordinate.
    let mut mesh = square(Order::P1);
    mesh.nodes[3] = [f64::NAN, 1.0];
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("node 3 at (NaN, 1)"), "{e}");
    // Edge in a surface group.
    let mut mesh = square(Order::P1);
    mesh.edge_group[2] = 1;
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("boundary edge 2 of group 'domain'") && e.contains("dimension 2"), "{e}");
    // Cell in a curve group.
    let mut mesh = square(Order::P1);
    mesh.cell_group[0] = 0;
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("triangle 0") && e.contains("'wall'"), "{e}");
    // Duplicated boundary edge in the same group.
    let mut mesh = square(Order::P1);
    mesh.edges.extend([1, 0]);
    mesh.edge_group.push(0);
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("boundary edge 4") && e.contains("repeats boundary edge 0"), "{e}");
    // P2 boundary edge with the wrong mid node.
    let mut mesh = square(Order::P2);
    mesh.edges[2] = 5;
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("boundary edge 0") && e.contains("mid node 5"), "{e}");
    // P2 mid node pushed across the cell: negative Jacobian.
    let mut mesh = square(Order::P2);
    mesh.nodes[4] = [0.5, 0.9];
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("triangle 0") && e.contains("Jacobian"), "{e}");
    // P2 neighbours disagreeing on the shared mid node.
    let mut mesh = square(Order::P2);
    mesh.nodes.push([0.5, 0.5]);
    mesh.cells[9] = 9;
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("triangle 1") && e.contains("share their mid nodes"), "{e}");
    // Empty mesh.
    let mut mesh = square(Order::P1);
    mesh.cells.clear();
    mesh.cell_group.clear();
    let e = mesh.validate().unwrap_err().to_string();
    assert!(e.contains("no triangles"), "{e}");
}

#[test]
fn require_group_names_the_known_groups() {
    let mesh = rectangle([0.0, 0.0], [1.0, 1.0], 1, 1, Order::P1).unwrap();
    let e = mesh.require_group("contact", 1).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, Error::Mesh { .. }));
    assert!(text.contains("physical group 'contact'") && text.contains("bottom, right, top, left"), "{text}");
}

// ---------------------------------------------------------------------------------------------
// MSH 4.1 files written inline
// ---------------------------------------------------------------------------------------------

/// An element block: (entity dim, entity tag, element type, [(element tag, node tags)]).
type Block = (i32, i32, i32, Vec<(u64, Vec<u64>)>);

/// A small MSH 4.1 ASCII file.
struct MshText {
    format: &'static str,
    names: Vec<(u8, i32, &'static str)>,
    /// (tag, physical tags) of curves and surfaces.
    curves: Vec<(i32, Vec<i32>)>,
    surfaces: Vec<(i32, Vec<i32>)>,
    nodes: Vec<(u64, [f64; 3])>,
    blocks: Vec<Block>,
}

impl MshText {
    /// Unit square with node tags 10, 20, 30, 40 (+ unused 99), triangles (10,20,30), (10,30,40),
    /// boundary lines on curve 1 (group "bottom side") and curve 2 (group 7, unnamed).
    fn square() -> Self {
        MshText {
            format: "4.1 0 8",
            names: vec![(1, 5, "bottom side"), (2, 6, "domain"), (1, 8, "unused \"quoted\" name")],
            curves: vec![(1, vec![5]), (2, vec![7]), (3, vec![])],
            surfaces: vec![(1, vec![6])],
            nodes: vec![
                (10, [0.0, 0.0, 0.0]),
                (20, [1.0, 0.0, 0.0]),
                (99, [5.0, 5.0, 0.0]),
                (30, [1.0, 1.0, 0.0]),
                (40, [0.0, 1.0, 0.0]),
            ],
            blocks: vec![
                (2, 1, 2, vec![(1, vec![10, 20, 30]), (2, vec![10, 30, 40])]),
                (1, 1, 1, vec![(3, vec![10, 20])]),
                (1, 2, 1, vec![(4, vec![30, 20])]),
                (1, 3, 1, vec![(5, vec![30, 40])]),
            ],
        }
    }

    fn text(&self) -> String {
        let mut s = format!("$MeshFormat\n{}\n$EndMeshFormat\n", self.format);
        if !self.names.is_empty() {
            s += &format!("$PhysicalNames\n{}\n", self.names.len());
            for (d, t, n) in &self.names {
                s += &format!("{d} {t} \"{n}\"\n");
            }
            s += "$EndPhysicalNames\n";
        }
        s += &format!("$Entities\n0 {} {} 0\n", self.curves.len(), self.surfaces.len());
        let tags = |t: &Vec<i32>| {
            let mut s = t.len().to_string();
            for x in t {
                s += &format!(" {x}");
            }
            s
        };
        for (tag, phys) in self.curves.iter().chain(self.surfaces.iter()) {
            s += &format!("{tag} 0 0 0 1 1 0 {} 0\n", tags(phys));
        }
        s += "$EndEntities\n";
        let (min, max) = self.nodes.iter().fold((u64::MAX, 0), |(a, b), n| (a.min(n.0), b.max(n.0)));
        s += &format!("$Nodes\n1 {} {min} {max}\n2 1 0 {}\n", self.nodes.len(), self.nodes.len());
        for (t, _) in &self.nodes {
            s += &format!("{t}\n");
        }
        for (_, p) in &self.nodes {
            s += &format!("{:?} {:?} {:?}\n", p[0], p[1], p[2]);
        }
        s += "$EndNodes\n";
        let all: Vec<u64> = self.blocks.iter().flat_map(|b| b.3.iter().map(|e| e.0)).collect();
        s += &format!(
            "$Elements\n{} {} {} {}\n",
            self.blocks.len(),
            all.len(),
            all.iter().min().unwrap(),
            all.iter().max().unwrap()
        );
        for (dim, ent, ty, elements) in &self.blocks {
            s += &format!("{dim} {ent} {ty} {}\n", elements.len());
            for (tag, nodes) in elements {
                s += &tag.to_string();
                for n in nodes {
                    s += &format!(" {n}");
                }
                s += "\n";
            }
        }
        s += "$EndElements\n";
        s
    }
}

#[test]
fn msh_inline_square_is_read_compacted_and_oriented() {
    let mesh = read_inline("square", &MshText::square().text()).unwrap();
    assert_eq!(mesh.order, Order::P1);
    assert_eq!(mesh.num_nodes(), 4, "the unused node 99 is dropped");
    assert_eq!(mesh.nodes, vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    assert_eq!(mesh.cells, vec![0, 1, 2, 0, 2, 3]);
    assert_eq!(mesh.num_edges(), 2, "lines without a physical group are ignored");
    let bottom = mesh.require_group("bottom side", 1).unwrap();
    let unnamed = mesh.require_group("7", 1).unwrap();
    assert!(mesh.group_index("unused \"quoted\" name", 1).is_some());
    assert_eq!(mesh.groups[bottom].tag, 5);
    assert_eq!(mesh.edges_in_group(bottom).collect::<Vec<_>>(), vec![0]);
    // The line 30 -> 20 was reversed so the domain is on its left.
    let e = mesh.edges_in_group(unnamed).next().unwrap();
    assert_eq!(mesh.edge(e), &[1, 2]);
    assert_eq!(mesh.edge_normal(e).0, [1.0, 0.0]);
    let domain = mesh.require_group("domain", 2).unwrap();
    assert_eq!(mesh.cell_group, vec![domain, domain]);
}

#[test]
fn msh_inline_variants() {
    // Clockwise triangles are flipped; no physical surface: triangles kept with NO_GROUP;
    // a line in two physical curves gives two edges.
    let mut m = MshText::square();
    m.blocks[0].3 = vec![(1, vec![10, 30, 20]), (2, vec![10, 40, 30])];
    m.surfaces = vec![(1, vec![])];
    m.curves[0].1 = vec![5, 7];
    let mesh = read_inline("variants", &m.text()).unwrap();
    assert_eq!(mesh.cell_group, vec![NO_GROUP; 2]);
    assert_counter_clockwise(&mesh);
    assert_eq!(mesh.num_edges(), 3);
    assert_eq!(mesh.edge(0), mesh.edge(1));
    assert_ne!(mesh.edge_group[0], mesh.edge_group[1]);
    // Triangles outside physical surfaces are dropped when there are physical surfaces.
    let mut m = MshText::square();
    m.surfaces = vec![(1, vec![6]), (2, vec![])];
    m.nodes.push((50, [2.0, 0.0, 0.0]));
    m.blocks.push((2, 2, 2, vec![(9, vec![20, 50, 30])]));
    let mesh = read_inline("dropped", &m.text()).unwrap();
    assert_eq!((mesh.num_cells(), mesh.num_nodes()), (2, 4));
}

#[test]
fn msh_p2_inline() {
    let mut m = MshText::square();
    m.nodes.extend([
        (11, [0.5, 0.0, 0.0]),
        (12, [1.0, 0.5, 0.0]),
        (13, [0.5, 1.0, 0.0]),
        (14, [0.0, 0.5, 0.0]),
        (15, [0.5, 0.5, 0.0]),
    ]);
    m.blocks = vec![
        (2, 1, 9, vec![(1, vec![10, 20, 30, 11, 12, 15]), (2, vec![10, 30, 40, 15, 13, 14])]),
        (1, 1, 8, vec![(3, vec![10, 20, 11])]),
        (1, 2, 8, vec![(4, vec![30, 20, 12])]),
    ];
    let mesh = read_inline("p2", &m.text()).unwrap();
    assert_eq!(mesh.order, Order::P2);
    assert_eq!(mesh.num_nodes(), 9);
    assert_eq!(mesh.num_edges(), 2);
    assert!(close(total_area(&mesh), 1.0, 1e-15));
    // Mixed orders are refused.
    m.blocks.push((1, 3, 1, vec![(5, vec![30, 40])]));
    let (e, text) = mesh_error_text(read_inline("mixed", &m.text()));
    assert!(matches!(e, Error::MeshFile { .. }));
    assert!(text.contains("mixes linear and quadratic") && text.contains("element 5"), "{text}");
}

#[test]
fn msh_error_version_2() {
    let mut m = MshText::square();
    m.format = "2.2 0 8";
    let (e, text) = mesh_error_text(read_inline("v22", &m.text()));
    let path = inline_path("v22");
    assert!(matches!(e, Error::MeshFile { line: Some(2), .. }), "{e:?}");
    assert!(text.contains(&path.display().to_string()), "{text}");
    assert!(
        text.contains(
            "MSH 2.2 is not supported: re-export as MSH 4.1 (gmsh -format msh41, or Mesh.MshFileVersion = 4.1)"
        ),
        "{text}"
    );
}

#[test]
fn msh_error_unsupported_element() {
    let mut m = MshText::square();
    m.blocks[0] = (2, 1, 3, vec![(17, vec![10, 20, 30, 40])]);
    let (e, text) = mesh_error_text(read_inline("quad", &m.text()));
    assert!(matches!(e, Error::MeshFile { .. }));
    assert!(text.contains("element 17") && text.contains("type 3") && text.contains("quadrangle"), "{text}");
    assert!(text.contains("quad.msh"), "{text}");
}

#[test]
fn msh_error_truncated() {
    let text = MshText::square().text();
    let cut = text.find("$EndNodes").unwrap() - 12;
    let (e, msg) = mesh_error_text(read_inline("truncated", &text[..cut]));
    let Error::MeshFile { line, .. } = &e else { panic!("{e:?}") };
    assert!(line.is_some(), "{e:?}");
    assert!(msg.contains("truncated.msh") && msg.contains("ends early"), "{msg}");
    // Truncated in the elements: mshio's error, with a line.
    let cut = text.find("$EndElements").unwrap() - 4;
    let (e, msg) = mesh_error_text(read_inline("truncated2", &text[..cut]));
    assert!(matches!(e, Error::MeshFile { line: Some(_), .. }), "{e:?}");
    assert!(msg.contains("truncated2.msh") && msg.contains("truncated?"), "{msg}");
    // Garbage in place of a number.
    let bad = text.replacen("0.0 1.0 0.0", "0.0 x1.0 0.0", 1);
    let (e, msg) = mesh_error_text(read_inline("garbage", &bad));
    let expected_line = bad[..bad.find("x1.0").unwrap()].lines().count();
    assert!(matches!(e, Error::MeshFile { line: Some(l), .. } if l == expected_line), "{e:?} (line {expected_line})");
    assert!(msg.contains("garbage.msh"), "{msg}");
}

#[test]
fn msh_error_non_planar() {
    let mut m = MshText::square();
    m.nodes[3].1[2] = 0.5;
    let (e, text) = mesh_error_text(read_inline("nonplanar", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(text.contains("node tag 30 at (1, 1, 0.5)") && text.contains("not a planar mesh"), "{text}");
    assert!(text.contains("nonplanar.msh"), "{text}");
    // Rounding noise in z is accepted.
    let mut m = MshText::square();
    m.nodes[3].1[2] = 1e-14;
    read_inline("almost_planar", &m.text()).unwrap();
}

#[test]
fn msh_error_degenerate_triangle() {
    let mut m = MshText::square();
    m.nodes[3].1 = [2.0, 0.0, 0.0]; // node 30 on the line through 10 and 20
    let (e, text) = mesh_error_text(read_inline("degenerate", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(
        text.contains("degenerate.msh") && text.contains("triangle 0 (nodes 0, 1, 2)") && text.contains("degenerate"),
        "{text}"
    );
}

#[test]
fn msh_error_inverted_triangle() {
    let mut m = MshText::square();
    m.nodes.push((50, [2.0, 0.0, 0.0]));
    m.blocks[0].3.push((3, vec![20, 30, 50])); // clockwise, the other two counter-clockwise
    let (e, text) = mesh_error_text(read_inline("inverted", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(text.contains("triangle 2 (nodes 1, 2, 4)") && text.contains("inverted"), "{text}");
}

#[test]
fn msh_error_boundary_edge_off_the_mesh() {
    let mut m = MshText::square();
    m.blocks[1].3.push((6, vec![20, 40])); // the diagonal not used by the triangles
    let (e, text) = mesh_error_text(read_inline("offedge", &m.text()));
    assert!(matches!(e, Error::Mesh { source_file: Some(_), .. }));
    assert!(
        text.contains("boundary edge 1 of group 'bottom side'") && text.contains("not a side of any triangle"),
        "{text}"
    );
}

#[test]
fn msh_error_unknown_node_and_missing_file() {
    let mut m = MshText::square();
    m.blocks[0].3[1].1[2] = 77;
    let (e, text) = mesh_error_text(read_inline("unknown_node", &m.text()));
    assert!(matches!(e, Error::MeshFile { .. }));
    assert!(text.contains("element 2 refers to node 77"), "{text}");

    let dir = Scratch::new("missing");
    let path = dir.path("does-not-exist.msh");
    let (e, text) = mesh_error_text(read_msh(&path));
    assert!(matches!(e, Error::Io { .. }), "{e:?}");
    assert!(text.contains("does-not-exist.msh"), "{text}");
}

#[test]
fn msh_error_not_an_msh_file() {
    let (e, text) = mesh_error_text(read_inline("notmsh", "hello\n"));
    assert!(matches!(e, Error::MeshFile { line: Some(1), .. }));
    assert!(text.contains("$MeshFormat"), "{text}");
    let bad_names = MshText::square().text().replace("2 6 \"domain\"", "2 six \"domain\"");
    let (e, text) = mesh_error_text(read_inline("badnames", &bad_names));
    assert!(matches!(e, Error::MeshFile { line: Some(7), .. }), "{e:?}");
    assert!(text.contains("PhysicalNames"), "{text}");
}

// ---------------------------------------------------------------------------------------------
// Gmsh
// ---------------------------------------------------------------------------------------------

#[test]
fn gmsh_reports_its_version() {
    let v = gmsh_version().unwrap();
    assert!(v.split('.').count() >= 2 && v.chars().next().unwrap().is_ascii_digit(), "{v}");
}

#[test]
fn gmsh_rectangle() {
    for order in [Order::P1, Order::P2] {
        let mesh = generate(&MeshRequest {
            shape: Shape::Rectangle { origin: [0.5, -1.0], size: [2.0, 1.0] },
            cell_size: 0.25,
            refinement: None,
            order,
        })
        .unwrap();
        assert_eq!(mesh.order, order);
        assert!(close(total_area(&mesh), 2.0, 1e-13), "{order:?}: {}", total_area(&mesh));
        for (name, len) in [("bottom", 2.0), ("right", 1.0), ("top", 2.0), ("left", 1.0)] {
            assert!(close(group_length(&mesh, name), len, 1e-13), "{name}");
        }
        mesh.require_group("domain", 2).unwrap();
        assert_counter_clockwise(&mesh);
        assert_outward_normals(&mesh);
        let (_, hmax) = mesh.size_range();
        assert!(hmax < 0.25 * 1.6, "hmax {hmax}");
    }
}

fn disc(order: Order, h: f64) -> Mesh {
    generate(&MeshRequest {
        shape: Shape::Disc { center: [1.0, 2.0], radius: 0.5 },
        cell_size: h,
        refinement: None,
        order,
    })
    .unwrap()
}

#[test]
fn gmsh_disc_area_converges() {
    let exact = std::f64::consts::PI * 0.25;
    let err = |m: &Mesh| (total_area(m) - exact).abs();
    let (coarse, fine) = (disc(Order::P1, 0.1), disc(Order::P1, 0.05));
    let (e1, e2) = (err(&coarse), err(&fine));
    // The P1 mesh is the inscribed polygon: area below pi R^2, error O(h^2).
    assert!(total_area(&coarse) < exact);
    let rate = (e1 / e2).log2();
    assert!((1.7..2.3).contains(&rate), "P1 rate {rate} ({e1:e}, {e2:e})");
    // P2 with mid nodes on the circle: much closer, and a higher rate.
    let (q1, q2) = (disc(Order::P2, 0.1), disc(Order::P2, 0.05));
    let (p1, p2) = (err(&q1), err(&q2));
    assert!(p1 < e1 / 100.0, "P2 {p1:e} vs P1 {e1:e}");
    let rate2 = (p1 / p2).log2();
    assert!(rate2 > 3.5, "P2 rate {rate2} ({p1:e}, {p2:e})");
    // Boundary nodes, mid nodes included, lie on the circle.
    let circle = q1.require_group("circle", 1).unwrap();
    assert_eq!(q1.edges_in_group(circle).count(), q1.num_edges());
    for e in 0..q1.num_edges() {
        for &n in q1.edge(e) {
            assert!((dist(q1.nodes[n], [1.0, 2.0]) - 0.5).abs() < 1e-12);
        }
    }
    q1.require_group("domain", 2).unwrap();
    assert_outward_normals(&q1);
}

#[test]
fn gmsh_half_disc() {
    let (c, r) = ([0.0, 1.0], 1.0);
    for order in [Order::P1, Order::P2] {
        let mesh = generate(&MeshRequest {
            shape: Shape::HalfDisc { center: c, radius: r },
            cell_size: 0.1,
            refinement: None,
            order,
        })
        .unwrap();
        let bottom = [c[0], c[1] - r];
        assert!(mesh.nodes.contains(&bottom), "{order:?}: (cx, cy - R) is not a node");
        let half = 0.5 * std::f64::consts::PI;
        assert!(close(total_area(&mesh), half, if order == Order::P1 { 1e-2 } else { 1e-5 }));
        let (arc, flat) = (mesh.require_group("arc", 1).unwrap(), mesh.require_group("flat", 1).unwrap());
        mesh.require_group("domain", 2).unwrap();
        assert!(close(group_length(&mesh, "flat"), 2.0, 1e-13));
        for e in mesh.edges_in_group(flat) {
            assert_eq!(mesh.edge_normal(e).0, [0.0, 1.0]);
            assert!(mesh.edge(e).iter().all(|&n| mesh.nodes[n][1] == c[1]));
        }
        for e in mesh.edges_in_group(arc) {
            let (n, _) = mesh.edge_normal(e);
            let p = mesh.nodes[mesh.edge(e)[0]];
            assert!(n[0] * (p[0] - c[0]) + n[1] * (p[1] - c[1]) > 0.0);
            assert!(mesh.edge(e).iter().all(|&k| mesh.nodes[k][1] <= c[1] + 1e-15));
        }
        assert_outward_normals(&mesh);
    }
}

#[test]
fn gmsh_refinement_makes_cells_smaller_near_the_point() {
    let point = [0.0, -1.0];
    let mesh = generate(&MeshRequest {
        shape: Shape::HalfDisc { center: [0.0, 0.0], radius: 1.0 },
        cell_size: 0.2,
        refinement: Some(Refinement { point, cell_size: 0.02, radius: 0.1 }),
        order: Order::P1,
    })
    .unwrap();
    let longest = |c: usize| {
        let v = mesh.cell(c);
        (0..3).map(|k| dist(mesh.nodes[v[k]], mesh.nodes[v[(k + 1) % 3]])).fold(0.0, f64::max)
    };
    let centroid = |c: usize| {
        let v = mesh.cell(c);
        let p: Vec<[f64; 2]> = v.iter().map(|&n| mesh.nodes[n]).collect();
        [(p[0][0] + p[1][0] + p[2][0]) / 3.0, (p[0][1] + p[1][1] + p[2][1]) / 3.0]
    };
    let (mut near, mut far) = (Vec::new(), Vec::new());
    for c in 0..mesh.num_cells() {
        let d = dist(centroid(c), point);
        if d < 0.1 {
            near.push(longest(c));
        } else if d > 0.5 {
            far.push(longest(c));
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    assert!(near.len() > 20, "{} cells near the point", near.len());
    assert!(mean(&near) < 0.04, "near {}", mean(&near));
    assert!(mean(&far) > 0.15, "far {}", mean(&far));
}

#[test]
fn gmsh_bad_requests_and_failures() {
    let (e, text) = mesh_error_text(generate(&MeshRequest {
        shape: Shape::Disc { center: [0.0, 0.0], radius: -1.0 },
        cell_size: 0.1,
        refinement: None,
        order: Order::P1,
    }));
    assert!(matches!(e, Error::Mesh { .. }));
    assert!(text.contains("radius = -1"), "{text}");
    let (_, text) = mesh_error_text(generate(&MeshRequest {
        shape: Shape::Rectangle { origin: [0.0, 0.0], size: [1.0, 1.0] },
        cell_size: 0.0,
        refinement: None,
        order: Order::P1,
    }));
    assert!(text.contains("cell_size = 0"), "{text}");
    let (_, text) = mesh_error_text(generate(&MeshRequest {
        shape: Shape::Rectangle { origin: [0.0, 0.0], size: [1.0, 1.0] },
        cell_size: 1e-5,
        refinement: None,
        order: Order::P1,
    }));
    assert!(text.contains("larger cell size"), "{text}");
    // A script Gmsh cannot parse.
    let (e, text) = mesh_error_text(generate_from_geo("Point(1) = {0, 0, 0, 0.1};\nBogus(2) = {1};\n", Order::P1));
    let Error::Gmsh { stderr, .. } = &e else { panic!("{e:?}") };
    assert!(stderr.contains("syntax error"), "{stderr}");
    assert!(text.contains("gmsh failed") && text.contains("line 2"), "{text}");
}

// ---------------------------------------------------------------------------------------------
// MSH files written by Gmsh: ASCII and binary read back the same
// ---------------------------------------------------------------------------------------------

fn gmsh_to_file(geo: &str, dir: &Path, name: &str, extra: &[&str]) -> PathBuf {
    let geo_path = dir.join(format!("{name}.geo"));
    std::fs::write(&geo_path, geo).unwrap();
    let out = dir.join(format!("{name}.msh"));
    let status = Command::new("gmsh")
        .arg(&geo_path)
        .args(["-2", "-format", "msh41", "-v", "1", "-o"])
        .arg(&out)
        .args(extra)
        .status()
        .unwrap();
    assert!(status.success());
    out
}

#[test]
fn msh_ascii_and_binary_from_gmsh_agree() {
    let geo = "Point(1) = {0, 0, 0, 0.15};\nPoint(2) = {1, 0, 0, 0.15};\nPoint(3) = {0, 1, 0, 0.15};\n\
               Point(4) = {0.3, 0.4, 0, 0.15};\n\
               Line(1) = {1, 2};\nCircle(2) = {2, 1, 3};\nLine(3) = {3, 1};\n\
               Curve Loop(1) = {1, 2, 3};\nPlane Surface(1) = {1};\n\
               Physical Curve(\"bottom edge\") = {1};\nPhysical Curve(\"arc\") = {2};\n\
               Physical Surface(\"solid body\") = {1};\n";
    let scratch = Scratch::new("gmsh-files");
    let dir = scratch.0.as_path();
    for (order, extra) in [(Order::P1, vec![]), (Order::P2, vec!["-order", "2"])] {
        let ascii = read_msh(&gmsh_to_file(geo, dir, "ascii", &extra)).unwrap();
        let mut bin_args = extra.clone();
        bin_args.push("-bin");
        let binary_path = gmsh_to_file(geo, dir, "binary", &bin_args);
        assert!(std::fs::read(&binary_path).unwrap().starts_with(b"$MeshFormat\n4.1 1 8\n"));
        let bytes = std::fs::read(&binary_path).unwrap();
        let binary = read_msh(&binary_path).unwrap();
        // Truncated binary files: the file is named, and the line of the section the parser
        // stopped in (binary data has no lines of its own).
        for cut in [bytes.len() / 2, bytes.len() - 20] {
            let path = dir.join("cut.msh");
            std::fs::write(&path, &bytes[..cut]).unwrap();
            let e = read_msh(&path).unwrap_err();
            assert!(matches!(e, Error::MeshFile { line: Some(_), .. }), "{e:?}");
            assert!(e.to_string().contains("cut.msh") && e.to_string().contains("truncated?"), "{e}");
        }
        assert_eq!(ascii.order, order);
        assert_eq!(binary.order, order);
        assert_eq!(ascii.cells, binary.cells);
        assert_eq!(ascii.edges, binary.edges);
        assert_eq!(ascii.edge_group, binary.edge_group);
        assert_eq!(ascii.groups, binary.groups);
        for (a, b) in ascii.nodes.iter().zip(&binary.nodes) {
            assert!(dist(*a, *b) < 1e-15, "{a:?} {b:?}");
        }
        // Physical names with spaces; the unattached point 4 is not in the mesh.
        ascii.require_group("bottom edge", 1).unwrap();
        ascii.require_group("solid body", 2).unwrap();
        assert!(!ascii.nodes.contains(&[0.3, 0.4]));
        // Quarter disc of radius 1.
        let quarter = std::f64::consts::FRAC_PI_4;
        let tol = if order == Order::P1 { 1e-2 } else { 1e-5 };
        assert!(close(total_area(&ascii), quarter, tol), "{order:?}: {}", total_area(&ascii));
    }
}

// ---------------------------------------------------------------------------------------------
// P2 mid nodes on the arcs, and the mesh cache
// ---------------------------------------------------------------------------------------------

fn half_disc_request(cell_size: f64, order: Order) -> MeshRequest {
    MeshRequest {
        shape: Shape::HalfDisc { center: [0.0, 0.1], radius: 0.1 },
        cell_size,
        refinement: Some(Refinement { point: [0.0, 0.0], cell_size: cell_size / 8.0, radius: 0.015 }),
        order,
    }
}

/// The same mesh to the bit: every array and group.
fn assert_identical(a: &Mesh, b: &Mesh) {
    assert_eq!(a.order, b.order);
    let bits = |m: &Mesh| m.nodes.iter().flat_map(|p| [p[0].to_bits(), p[1].to_bits()]).collect::<Vec<u64>>();
    assert!(bits(a) == bits(b), "node coordinates differ");
    assert_eq!(a.cells, b.cells);
    assert_eq!(a.cell_group, b.cell_group);
    assert_eq!(a.edges, b.edges);
    assert_eq!(a.edge_group, b.edge_group);
    assert_eq!(a.groups, b.groups);
}

#[test]
fn gmsh_half_disc_p2_nodes_lie_on_the_circle_where_gmsh_puts_them() {
    // The chosen algorithm (Frontal-Delaunay) and our P2 mid nodes: every node of the arc,
    // vertices and mid nodes, on the circle to 1e-12 relative.
    let request = half_disc_request(0.02, Order::P2);
    let mesh = generate(&request).unwrap();
    let (c, r) = ([0.0, 0.1], 0.1);
    let arc = mesh.require_group("arc", 1).unwrap();
    let mut ours: Vec<[f64; 2]> = Vec::new();
    for e in mesh.edges_in_group(arc) {
        for &n in mesh.edge(e) {
            assert!((dist(mesh.nodes[n], c) - r).abs() <= 1e-12 * r, "node {n} at {:?}", mesh.nodes[n]);
        }
        ours.push(mesh.nodes[mesh.edge(e)[2]]);
    }
    // Gmsh's own second-order mesh of the same script puts them at the same points, to 1e-9
    // relative (both on the circle; Gmsh's are off the exact half angle by ~1e-10 rad).
    let mut geo = String::new();
    let p1 = generate(&MeshRequest { order: Order::P1, ..request.clone() }).unwrap();
    assert_eq!(p1.num_cells(), mesh.num_cells());
    for line in [
        "Point(1) = {-0.1, 0.1, 0, 0.02};",
        "Point(2) = {0.0, 0.0, 0, 0.02};",
        "Point(3) = {0.1, 0.1, 0, 0.02};",
        "Point(4) = {0.0, 0.1, 0, 0.02};",
        "Circle(1) = {1, 4, 2};\nCircle(2) = {2, 4, 3};\nLine(3) = {3, 1};",
        "Curve Loop(1) = {1, 2, 3};\nPlane Surface(1) = {1};",
        "Physical Curve(\"arc\") = {1, 2};\nPhysical Curve(\"flat\") = {3};\nPhysical Surface(\"domain\") = {1};",
        "Point(100) = {0.0, 0.0, 0, 0.0025};",
        "Field[1] = Distance;\nField[1].PointsList = {100};\nField[2] = Threshold;\nField[2].InField = 1;",
        "Field[2].SizeMin = 0.0025;\nField[2].SizeMax = 0.02;\nField[2].DistMin = 0.015;\nField[2].DistMax = 0.03;",
        "Background Field = 2;\nMesh.MeshSizeExtendFromBoundary = 0;\nMesh.MeshSizeFromPoints = 0;",
        "Mesh.MeshSizeFromCurvature = 0;\nMesh.Algorithm = 6;\nMesh.SecondOrderLinear = 0;",
    ] {
        geo.push_str(line);
        geo.push('\n');
    }
    let theirs_mesh = generate_from_geo(&geo, Order::P2).unwrap();
    assert_eq!(theirs_mesh.num_nodes(), mesh.num_nodes());
    let arc = theirs_mesh.require_group("arc", 1).unwrap();
    let mut theirs: Vec<[f64; 2]> =
        theirs_mesh.edges_in_group(arc).map(|e| theirs_mesh.nodes[theirs_mesh.edge(e)[2]]).collect();
    let by_x = |a: &[f64; 2], b: &[f64; 2]| a[0].total_cmp(&b[0]);
    ours.sort_by(by_x);
    theirs.sort_by(by_x);
    assert_eq!(ours.len(), theirs.len());
    for (a, b) in ours.iter().zip(&theirs) {
        assert!(dist(*a, *b) <= 1e-9 * r, "mid node {a:?} against Gmsh's {b:?}");
    }
}

mod cache {
    use super::*;
    use signorini::mesh::cache::{CacheStatus, MeshCache};
    use signorini::mesh::gmsh::generate_cached;

    fn entries(cache: &MeshCache) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(cache.entries_dir())
            .map(|d| d.map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|x| x == "mesh")).collect())
            .unwrap_or_default();
        v.sort();
        v
    }

    #[test]
    fn a_hit_is_the_same_mesh_to_the_bit_and_disabled_meshes_alike() {
        let scratch = Scratch::new("cache-hit");
        let cache = MeshCache::at(&scratch.0);
        let request = half_disc_request(0.02, Order::P2);
        let (made, first) = generate_cached(&request, Some(&cache)).unwrap();
        assert_eq!((first.status, first.problem.as_deref()), (CacheStatus::Miss, None));
        assert_eq!(entries(&cache).len(), 1);
        let (cached, second) = generate_cached(&request, Some(&cache)).unwrap();
        assert_eq!((second.status, second.problem.as_deref()), (CacheStatus::Hit, None));
        assert_identical(&made, &cached);
        // Without a cache: made by Gmsh again, the same mesh (Gmsh is deterministic), nothing
        // stored.
        let (fresh, off) = generate_cached(&request, None).unwrap();
        assert_eq!(off.status, CacheStatus::Disabled);
        assert_identical(&made, &fresh);
        assert_identical(&made, &generate(&request).unwrap());
        assert_eq!(entries(&cache).len(), 1);
    }

    #[test]
    fn corrupt_or_truncated_entries_are_detected_remeshed_and_replaced() {
        let scratch = Scratch::new("cache-corrupt");
        let cache = MeshCache::at(&scratch.0);
        let request = half_disc_request(0.03, Order::P2);
        let (made, _) = generate_cached(&request, Some(&cache)).unwrap();
        let path = entries(&cache).pop().unwrap();
        let good = std::fs::read(&path).unwrap();
        let mut flipped = good.clone();
        let middle = flipped.len() / 2;
        flipped[middle] ^= 0x10; // one bit of a node coordinate or an index
        let damages: [(&str, Vec<u8>); 4] = [
            ("a flipped bit", flipped),
            ("truncation", good[..good.len() - 100].to_vec()),
            ("an empty file", Vec::new()),
            ("another file", b"not a mesh at all".to_vec()),
        ];
        for (what, bytes) in damages {
            std::fs::write(&path, &bytes).unwrap();
            let (mesh, report) = generate_cached(&request, Some(&cache)).unwrap();
            assert_eq!(report.status, CacheStatus::Miss, "{what}");
            let problem = report.problem.unwrap_or_else(|| panic!("{what}: not reported"));
            assert!(problem.contains("unusable entry") && problem.contains("replaced"), "{what}: {problem}");
            assert_identical(&made, &mesh);
            // Replaced: the entry is whole again and the next run hits.
            assert_eq!(std::fs::read(&path).unwrap(), good, "{what}");
            assert_eq!(generate_cached(&request, Some(&cache)).unwrap().1.status, CacheStatus::Hit, "{what}");
        }
    }

    #[test]
    fn any_change_of_the_input_misses() {
        let scratch = Scratch::new("cache-inputs");
        let cache = MeshCache::at(&scratch.0);
        let base = half_disc_request(0.03, Order::P1);
        let variants = [
            base.clone(),
            MeshRequest { cell_size: 0.029, ..base.clone() },
            MeshRequest { order: Order::P2, ..base.clone() },
            MeshRequest { shape: Shape::HalfDisc { center: [0.0, 0.1], radius: 0.11 }, ..base.clone() },
            MeshRequest { shape: Shape::HalfDisc { center: [0.001, 0.1], radius: 0.1 }, ..base.clone() },
            MeshRequest { shape: Shape::Disc { center: [0.0, 0.1], radius: 0.1 }, ..base.clone() },
            MeshRequest { refinement: None, ..base.clone() },
            MeshRequest {
                refinement: Some(Refinement { point: [0.0, 0.0], cell_size: 0.03 / 8.0, radius: 0.016 }),
                ..base.clone()
            },
        ];
        for (k, request) in variants.iter().enumerate() {
            let (_, report) = generate_cached(request, Some(&cache)).unwrap();
            assert_eq!(report.status, CacheStatus::Miss, "variant {k}: {request:?}");
            assert_eq!(entries(&cache).len(), k + 1);
        }
        for (k, request) in variants.iter().enumerate() {
            let (mesh, report) = generate_cached(request, Some(&cache)).unwrap();
            assert_eq!(report.status, CacheStatus::Hit, "variant {k}");
            assert_eq!(mesh.order, request.order);
        }
    }

    #[test]
    fn the_cache_keeps_to_its_size_bound_newest_first() {
        let scratch = Scratch::new("cache-bound");
        // Room for about one entry: each store removes the older ones, never itself.
        let cache = MeshCache::at(&scratch.0).with_max_bytes(1);
        for h in [0.05, 0.04] {
            let (_, report) = generate_cached(&half_disc_request(h, Order::P1), Some(&cache)).unwrap();
            assert_eq!(report.status, CacheStatus::Miss);
            assert_eq!(entries(&cache).len(), 1);
        }
        assert_eq!(
            generate_cached(&half_disc_request(0.04, Order::P1), Some(&cache)).unwrap().1.status,
            CacheStatus::Hit
        );
        assert_eq!(
            generate_cached(&half_disc_request(0.05, Order::P1), Some(&cache)).unwrap().1.status,
            CacheStatus::Miss
        );
    }

    #[test]
    fn an_unwritable_cache_still_meshes_and_says_so() {
        let scratch = Scratch::new("cache-unwritable");
        let file = scratch.path("not-a-directory");
        std::fs::write(&file, b"x").unwrap();
        let cache = MeshCache::at(&file);
        let (mesh, report) = generate_cached(&half_disc_request(0.05, Order::P1), Some(&cache)).unwrap();
        assert!(mesh.num_cells() > 0);
        assert_eq!(report.status, CacheStatus::Miss);
        assert!(report.problem.is_some_and(|p| p.contains("not stored")));
    }
}
