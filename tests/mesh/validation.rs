//! Validation of hand-built meshes: orientation, defects, group names.

use crate::{assert_counter_clockwise, assert_outward_normals, close, total_area};
use signorini::mesh::structured::rectangle;
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use signorini::Error;

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
            measure: Default::default(),
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
                measure: Default::default(),
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
        measure: Default::default(),
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
