//! P2 mid nodes on the arcs, where Gmsh puts them.

use crate::{dist, half_disc_request};
use signorini::mesh::gmsh::{generate, generate_from_geo, MeshRequest};
use signorini::mesh::Order;

// ---------------------------------------------------------------------------------------------
// P2 mid nodes on the arcs, and the mesh cache
// ---------------------------------------------------------------------------------------------

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
