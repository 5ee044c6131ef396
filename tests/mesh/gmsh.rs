//! Meshes made by Gmsh, and its ASCII and binary MSH files read back the same.

use crate::{
    assert_counter_clockwise, assert_outward_normals, close, dist, group_length, mesh_error_text, total_area, Scratch,
};
use signorini::mesh::gmsh::{generate, generate_from_geo, gmsh_version, MeshRequest, Refinement, Shape};
use signorini::mesh::msh::read_msh;
use signorini::mesh::{Mesh, Order};
use signorini::Error;
use std::path::{Path, PathBuf};
use std::process::Command;

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
fn gmsh_quarter_disc() {
    let (c, r) = ([0.0, 1.0], 1.0);
    for order in [Order::P1, Order::P2] {
        let mesh = generate(&MeshRequest {
            shape: Shape::QuarterDisc { center: c, radius: r },
            cell_size: 0.1,
            refinement: None,
            order,
        })
        .unwrap();
        for corner in [[c[0], c[1] - r], [c[0] + r, c[1]], c] {
            assert!(mesh.nodes.contains(&corner), "{order:?}: the corner {corner:?} is not a node");
        }
        let quarter = 0.25 * std::f64::consts::PI;
        assert!(close(total_area(&mesh), quarter, if order == Order::P1 { 1e-2 } else { 1e-5 }));
        let arc = mesh.require_group("arc", 1).unwrap();
        let (flat, axis) = (mesh.require_group("flat", 1).unwrap(), mesh.require_group("axis", 1).unwrap());
        mesh.require_group("domain", 2).unwrap();
        assert!(close(group_length(&mesh, "flat"), 1.0, 1e-13));
        assert!(close(group_length(&mesh, "axis"), 1.0, 1e-13));
        for e in mesh.edges_in_group(flat) {
            assert_eq!(mesh.edge_normal(e).0, [0.0, 1.0]);
            assert!(mesh.edge(e).iter().all(|&n| mesh.nodes[n][1] == c[1] && mesh.nodes[n][0] >= c[0]));
        }
        for e in mesh.edges_in_group(axis) {
            assert_eq!(mesh.edge_normal(e).0, [-1.0, 0.0]);
            assert!(mesh.edge(e).iter().all(|&n| mesh.nodes[n][0] == c[0]));
        }
        for e in mesh.edges_in_group(arc) {
            let (n, _) = mesh.edge_normal(e);
            let p = mesh.nodes[mesh.edge(e)[0]];
            assert!(n[0] * (p[0] - c[0]) + n[1] * (p[1] - c[1]) > 0.0);
            assert!(mesh.edge(e).iter().all(|&k| {
                let q = mesh.nodes[k];
                q[1] <= c[1] + 1e-15 && q[0] >= c[0] - 1e-15 && ((q[0] - c[0]).hypot(q[1] - c[1]) - r).abs() < 1e-12
            }));
        }
        // Every node lies in the quarter.
        assert!(mesh.nodes.iter().all(|p| p[0] >= c[0] && p[1] <= c[1]));
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
