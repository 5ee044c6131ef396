//! Dirichlet conditions at a point: the nearest node, its tolerance and the checks against a mesh.

use crate::{base_with, line_of, parse, part, scene_error, two_triangles, BASE};
use signorini::error::{Error, Location};
use signorini::mesh::Mesh;
use signorini::scene::{nearest_node, point_tolerance, DirichletSpec, DirichletTarget, POINT_TOLERANCE};

// ---- point Dirichlet conditions --------------------------------------------------------------

#[test]
fn dirichlet_at_a_point() {
    let text = base_with("part = \"left\"", "point = [0, 0.2]");
    let s = parse(&text).unwrap();
    assert_eq!(
        s.dirichlet[0],
        DirichletSpec {
            target: DirichletTarget::Point([0.0, 0.2]),
            ux: Some(0.0),
            uy: Some(0.0),
            name: None,
            at: Location { file: "test.toml".into(), line: line_of(&text, "point ="), column: "point = ".len() + 1 }
        }
    );
    assert_eq!(s.dirichlet[0].target.to_string(), "point [0, 0.2]");
    assert_eq!(part("left").to_string(), "left");
    // a point is not a boundary part
    assert_eq!(s.boundary_parts().map(|(p, _)| p).collect::<Vec<_>>(), ["right"]);
}

#[test]
fn dirichlet_with_both_part_and_point() {
    let text = base_with("part = \"left\"", "part = \"left\"\npoint = [0.0, 0.0]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "point ="));
    assert!(e.message.contains("`part`") && e.message.contains("`point`"), "{}", e.message);
    assert!(e.hint.contains("keep one"), "{}", e.hint);
}

#[test]
fn dirichlet_with_neither_part_nor_point() {
    let text = base_with("part = \"left\"\n", "");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[[dirichlet]]"), 1));
    assert!(e.message.contains("neither `part` nor `point`"), "{}", e.message);
    assert!(e.hint.contains("part = \"left\"") && e.hint.contains("point = [x, y]"), "{}", e.hint);
}

#[test]
fn dirichlet_point_must_be_a_pair_and_fix_something() {
    let text = base_with("part = \"left\"", "point = [0.0]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "point ="));
    assert!(e.message.contains("`point`") && e.message.contains("1 item"), "{}", e.message);

    let text = base_with("part = \"left\"\nux = 0.0\nuy = 0.0\n", "point = [1.0, 0.0]\n");
    let e = scene_error(&text);
    assert!(e.message.contains("at point [1, 0]") && e.message.contains("neither `ux` nor `uy`"), "{}", e.message);
}

#[test]
fn nearest_node_and_tolerance() {
    let mesh = two_triangles();
    assert_eq!(nearest_node(&mesh, [0.9, 0.2]), Some((1, (0.9f64 - 1.0).hypot(0.2))));
    assert_eq!(nearest_node(&mesh, [1.0, 1.0]), Some((2, 0.0)));
    // ties go to the first node
    assert_eq!(nearest_node(&mesh, [0.5, 0.0]).map(|(n, _)| n), Some(0));
    let empty =
        Mesh { nodes: vec![], cells: vec![], cell_group: vec![], edges: vec![], edge_group: vec![], ..mesh.clone() };
    assert_eq!(nearest_node(&empty, [0.0, 0.0]), None);
    assert_eq!(point_tolerance(&mesh), POINT_TOLERANCE * 2f64.sqrt());
    assert_eq!(POINT_TOLERANCE, 1e-8);
}

#[test]
fn dirichlet_nodes_of_parts_and_points() {
    let mesh = two_triangles();
    let text =
        format!("{}\n[[dirichlet]]\npoint = [1.0, 1e-9]\nux = 0.0\n", base_with("part = \"left\"", "part = \"top\""));
    let s = parse(&text).unwrap();
    s.check_against_mesh(&mesh).unwrap();
    assert_eq!(s.dirichlet[0].nodes(&mesh).unwrap(), [2, 3]);
    assert_eq!(s.dirichlet[1].nodes(&mesh).unwrap(), [1]);
}

#[test]
fn check_against_mesh_reports_a_point_without_a_node() {
    let text = format!("{BASE}\n[[dirichlet]]\npoint = [0.5, 0.0]\nux = 0.0\n");
    let s = parse(&text).unwrap();
    for e in [s.check_against_mesh(&two_triangles()).unwrap_err(), s.dirichlet[1].nodes(&two_triangles()).unwrap_err()]
    {
        let Error::Scene { location, message, hint } = e else { panic!("{e:?}") };
        assert_eq!((location.line, location.column), (line_of(&text, "point ="), "point = ".len() + 1));
        assert!(message.contains("no node at point [0.5, 0]") && message.contains("node 0 at [0, 0]"), "{message}");
        assert!(message.contains("5.000e-1"), "{message}");
        assert!(hint.contains("one mesh node") && hint.contains("1.4e-8"), "{hint}");
    }
    // just outside the tolerance
    let text = format!("{BASE}\n[[dirichlet]]\npoint = [1.0, 2e-8]\nux = 0.0\n");
    assert!(parse(&text).unwrap().check_against_mesh(&two_triangles()).is_err());
}

#[test]
fn dirichlet_on_an_unknown_part_is_a_scene_error_from_nodes() {
    let text = base_with("part = \"left\"", "part = \"lefft\"");
    let e = parse(&text).unwrap().dirichlet[0].nodes(&two_triangles()).unwrap_err();
    let Error::Scene { location, hint, .. } = e else { panic!("{e:?}") };
    assert_eq!(location.line, line_of(&text, "lefft"));
    assert!(hint.contains("did you mean `left`?"), "{hint}");
}
