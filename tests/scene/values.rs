//! Values out of range, names from a fixed set, keys that do not apply, boundary conditions, [solver] and [output].

use crate::edit::Edit;

use crate::{base_with, line_of, parse, part, scene_error, BASE};
use signorini::mesh::Order;
use signorini::scene::{DirichletSpec, Load, MeshSpec, Mesher, PlaneSpec, RefineSpec};
use std::path::Path;

// ---- values out of range ---------------------------------------------------------------------

#[test]
fn young_must_be_positive_and_finite() {
    for bad in ["0.0", "-1e9", "nan", "inf", "-inf"] {
        let text = base_with("young = 210e9", &format!("young = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "young"), "{bad}");
        assert!(e.message.contains("`young`"), "{bad}: {}", e.message);
        assert!(e.message.contains(bad), "{bad}: {}", e.message);
    }
    let e = scene_error(&base_with("young = 210e9", "young = -5"));
    assert!(e.message.contains("positive") && e.message.contains("-5"), "{}", e.message);
    assert!(e.hint.contains("Pa"), "{}", e.hint);
}

#[test]
fn poisson_must_be_in_range() {
    let text = base_with("poisson = 0.3", "poisson = 0.5");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "poisson"), "poisson = ".len() + 1));
    assert!(e.message.contains("`poisson`") && e.message.contains("0.5"), "{}", e.message);
    assert!(
        e.hint.contains("incompressible") && e.hint.contains("0.4999") && e.hint.contains("order = 2"),
        "{}",
        e.hint
    );

    let e = scene_error(&base_with("poisson = 0.3", "poisson = -1"));
    assert!(e.message.contains("`poisson`") && e.message.contains("-1"), "{}", e.message);

    for ok in ["0.4999", "-0.9", "0"] {
        assert!(parse(&base_with("poisson = 0.3", &format!("poisson = {ok}"))).is_ok(), "{ok}");
    }
}

#[test]
fn cell_size_must_be_positive() {
    for bad in ["0.0", "-0.1"] {
        let text = base_with("cell_size = 0.1", &format!("cell_size = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "cell_size"));
        assert!(e.message.contains("`cell_size`") && e.message.contains(bad), "{}", e.message);
    }
}

#[test]
fn cell_size_must_not_make_an_absurd_mesh() {
    let text = base_with("cell_size = 0.1", "cell_size = 1e-5");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "cell_size"));
    assert!(e.message.contains("cell_size") && e.message.contains("triangles"), "{}", e.message);
    assert!(e.hint.contains("larger"), "{}", e.hint);
}

#[test]
fn size_and_radius_must_be_positive() {
    let text = base_with("size = [1.0, 0.2]", "size = [1.0, 0.0]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "size"));
    assert!(e.message.contains("`size`") && e.message.contains("[1.0, 0.0]"), "{}", e.message);

    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"disc\"\nradius = -2.0");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "radius"));
    assert!(e.message.contains("`radius`") && e.message.contains("-2"), "{}", e.message);
}

#[test]
fn order_must_be_1_or_2() {
    for bad in ["3", "0", "2.0", "\"P2\""] {
        let text = base_with("order = 1", &format!("order = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "order"), "{bad}");
        assert!(e.message.contains("`order`") && e.message.contains("1 or 2"), "{bad}: {}", e.message);
    }
    assert_eq!(parse(&base_with("order = 1", "order = 2")).unwrap().order, Order::P2);
    // [discretization] is optional: P1
    let text = base_with("[discretization]\norder = 1\n", "");
    assert_eq!(parse(&text).unwrap().order, Order::P1);
}

// ---- names with a fixed set of choices -------------------------------------------------------

#[test]
fn unknown_shape() {
    let text = base_with("shape = \"rectangle\"", "shape = \"rect\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "shape"), "shape = ".len() + 1));
    assert!(e.message.contains("shape") && e.message.contains("\"rect\""), "{}", e.message);
    assert!(e.hint.contains("\"rectangle\", \"disc\", \"half_disc\", \"quarter_disc\", \"file\""), "{}", e.hint);

    let e = scene_error(&base_with("shape = \"rectangle\"", "shape = \"dsic\""));
    assert!(e.hint.contains("did you mean \"disc\"?"), "{}", e.hint);
}

#[test]
fn unknown_plane_model() {
    let text = base_with("poisson = 0.3", "poisson = 0.3\nplane = \"strian\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "plane"));
    assert!(e.message.contains("plane") && e.message.contains("\"strian\""), "{}", e.message);
    assert!(e.hint.contains("did you mean \"strain\"?") && e.hint.contains("\"stress\""), "{}", e.hint);

    let s = parse(&base_with("poisson = 0.3", "poisson = 0.3\nplane = \"stress\"")).unwrap();
    assert_eq!(s.material.plane, PlaneSpec::Stress);
    let s = parse(&base_with("poisson = 0.3", "poisson = 0.3\nplane = \"axisymmetric\"")).unwrap();
    assert_eq!(s.material.plane, PlaneSpec::Axisymmetric);
    let text = base_with("poisson = 0.3", "poisson = 0.3\nplane = \"axisymetric\"");
    let e = scene_error(&text);
    assert!(e.hint.contains("did you mean \"axisymmetric\"?"), "{}", e.hint);
}

#[test]
fn unknown_mesher() {
    let text = base_with("cell_size = 0.1", "cell_size = 0.1\nmesher = \"delaunay\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mesher"));
    assert!(e.message.contains("mesher") && e.message.contains("\"delaunay\""), "{}", e.message);
    assert!(e.hint.contains("\"structured\", \"gmsh\""), "{}", e.hint);
}

// ---- keys that do not apply ------------------------------------------------------------------

#[test]
fn key_that_does_not_apply_to_the_shape() {
    let text = base_with("cell_size = 0.1", "cell_size = 0.1\nradius = 1.0");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "radius"));
    assert!(e.message.contains("`radius`") && e.message.contains("rectangle"), "{}", e.message);
    assert!(e.hint.contains("remove `radius`") && e.hint.contains("size"), "{}", e.hint);

    let text =
        base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"disc\"\nradius = 1.0\nmesher = \"gmsh\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mesher"));
    assert!(e.message.contains("`mesher`") && e.message.contains("disc"), "{}", e.message);
    assert!(e.hint.contains("always made by gmsh"), "{}", e.hint);

    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"file\"\nfile = \"a.msh\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "cell_size"));
    assert!(e.message.contains("`cell_size`") && e.message.contains("file"), "{}", e.message);
}

#[test]
fn refine_needs_gmsh() {
    let refine = "refine = { point = [0.0, 0.0], cell_size = 0.01, radius = 0.1 }";
    // structured by default
    let text = base_with("cell_size = 0.1", &format!("cell_size = 0.1\n{refine}"));
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "refine"));
    assert!(e.message.contains("`refine`") && e.message.contains("gmsh"), "{}", e.message);
    assert!(e.hint.contains("mesher = \"gmsh\""), "{}", e.hint);
    // explicitly structured, refine as a sub-table
    let text = format!(
        "{}\n[mesh.refine]\npoint = [0.0, 0.0]\ncell_size = 0.01\nradius = 0.1\n",
        base_with("cell_size = 0.1", "cell_size = 0.1\nmesher = \"structured\"")
    );
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[mesh.refine]"));
    // with gmsh both forms are accepted
    let with_gmsh = base_with("cell_size = 0.1", &format!("cell_size = 0.1\nmesher = \"gmsh\"\n{refine}"));
    let s = parse(&with_gmsh).unwrap();
    let sub = parse(&text.edit("mesher = \"structured\"", "mesher = \"gmsh\"")).unwrap();
    assert_eq!(s.mesh, sub.mesh);
    let MeshSpec::Rectangle { refine: Some(r), mesher: Mesher::Gmsh, .. } = s.mesh else { panic!("{:?}", s.mesh) };
    assert_eq!(r, RefineSpec { point: [0.0, 0.0], cell_size: 0.01, radius: 0.1 });
}

#[test]
fn refine_values_are_checked() {
    let gmsh = |refine: &str| base_with("cell_size = 0.1", &format!("cell_size = 0.1\nmesher = \"gmsh\"\n{refine}"));
    let text = gmsh("refine = { point = [0.0, 0.0], cell_size = 0.01 }");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "refine"));
    assert!(e.message.contains("refine") && e.message.contains("`radius`"), "{}", e.message);

    let text = gmsh("refine = { point = [0.0, 0.0], cell_size = 0.5, radius = 0.1 }");
    let e = scene_error(&text);
    assert!(e.message.contains("cell_size") && e.message.contains("0.5"), "{}", e.message);

    let text = gmsh("refine = { point = [0.0, 0.0], cell_size = 0.01, radius = 0 }");
    let e = scene_error(&text);
    assert!(e.message.contains("`radius`") && e.message.contains("positive"), "{}", e.message);
}

// ---- boundary conditions ---------------------------------------------------------------------

#[test]
fn dirichlet_without_components() {
    let text = base_with("ux = 0.0\nuy = 0.0\n", "");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[[dirichlet]]"), 1));
    assert!(e.message.contains("`left`") && e.message.contains("`ux`") && e.message.contains("`uy`"), "{}", e.message);
    assert!(e.hint.contains("ux = 0.0"), "{}", e.hint);

    let s = parse(&base_with("ux = 0.0\n", "")).unwrap();
    assert_eq!(
        s.dirichlet[0],
        DirichletSpec { target: part("left"), ux: None, uy: Some(0.0), name: None, at: s.dirichlet[0].at.clone() }
    );
}

#[test]
fn traction_with_both_or_neither_load() {
    let text = base_with("traction = [0.0, -1e6]", "traction = [0.0, -1e6]\npressure = 1e5");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "pressure"));
    assert!(e.message.contains("`traction`") && e.message.contains("`pressure`"), "{}", e.message);
    assert!(e.message.contains("`right`"), "{}", e.message);

    let text = base_with("traction = [0.0, -1e6]\n", "");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[[traction]]"));
    assert!(e.message.contains("neither") && e.message.contains("`right`"), "{}", e.message);
    assert!(e.hint.contains("pressure = "), "{}", e.hint);

    let s = parse(&base_with("traction = [0.0, -1e6]", "pressure = -2.5")).unwrap();
    assert_eq!(s.tractions[0].load, Load::Pressure(-2.5));
}

#[test]
fn part_must_be_a_nonempty_string() {
    let text = base_with("part = \"left\"", "part = 3");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "part = 3"));
    assert!(e.message.contains("`part`"), "{}", e.message);
    let text = base_with("part = \"left\"", "part = \"\"");
    let e = scene_error(&text);
    assert!(e.message.contains("`part`") && e.message.contains("empty"), "{}", e.message);
}

// ---- solver and output -----------------------------------------------------------------------

#[test]
fn solver_and_output_sections() {
    let text = format!("{BASE}\n[solver]\npetsc_options = \"\"\"  -ksp_type cg\n -pc_type   gamg \"\"\"\n[output]\ndir = \"results/a\"\n");
    let s = parse(&text).unwrap();
    assert_eq!(s.petsc_options, ["-ksp_type", "cg", "-pc_type", "gamg"]);
    assert_eq!(s.output_dir.as_deref(), Some(Path::new("results/a")));

    let text = format!("{BASE}\n[solver]\npetsc_options = \"ksp_type cg\"\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "petsc_options"));
    assert!(e.message.contains("`petsc_options`") && e.message.contains("ksp_type"), "{}", e.message);

    let text = format!("{BASE}\n[output]\ndir = \"\"\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "dir ="));
    assert!(e.message.contains("`dir`"), "{}", e.message);
}

#[test]
fn disc_and_half_disc() {
    let text = base_with(
        "shape = \"rectangle\"\nsize = [1.0, 0.2]",
        "shape = \"half_disc\"\ncenter = [0.0, 1.0]\nradius = 1.0",
    );
    let s = parse(&text).unwrap();
    assert_eq!(s.mesh, MeshSpec::HalfDisc { center: [0.0, 1.0], radius: 1.0, cell_size: 0.1, refine: None });
    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"disc\"\nradius = 2");
    let s = parse(&text).unwrap();
    assert_eq!(s.mesh, MeshSpec::Disc { center: [0.0, 0.0], radius: 2.0, cell_size: 0.1, refine: None });
}

#[test]
fn quarter_disc_and_its_errors_at_their_line() {
    let text = base_with(
        "shape = \"rectangle\"\nsize = [1.0, 0.2]",
        "shape = \"quarter_disc\"\ncenter = [0.0, 1.0]\nradius = 1.0",
    );
    let s = parse(&text).unwrap();
    assert_eq!(s.mesh, MeshSpec::QuarterDisc { center: [0.0, 1.0], radius: 1.0, cell_size: 0.1, refine: None });
    // With a refinement, as half_disc takes one.
    let refined = format!("{text}\n[mesh.refine]\npoint = [0.0, 0.0]\ncell_size = 0.01\nradius = 0.1\n");
    let MeshSpec::QuarterDisc { refine: Some(r), .. } = parse(&refined).unwrap().mesh else { panic!() };
    assert_eq!((r.point, r.cell_size, r.radius), ([0.0, 0.0], 0.01, 0.1));
    // A key of another shape, a missing or negative radius: errors at their line.
    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"quarter_disc\"\nsize = [1.0, 1.0]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "size = [1.0, 1.0]"));
    assert!(e.message.contains("`size` does not apply to shape = \"quarter_disc\""), "{}", e.message);
    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"quarter_disc\"\nradius = -1.0");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "radius = -1.0"));
    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"quarter_disc\"\nmesher = \"gmsh\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mesher ="));
    assert!(e.hint.contains("quarter_disc meshes are always made by gmsh"), "{}", e.hint);
    let text = base_with("shape = \"rectangle\"\nsize = [1.0, 0.2]", "shape = \"quarter_disk\"\nradius = 1.0");
    let e = scene_error(&text);
    assert!(e.hint.contains("quarter_disc"), "{}", e.hint);
}
