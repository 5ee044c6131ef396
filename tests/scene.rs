//! The scene format: the example scenes parse to what they say, and every mistake is an
//! `Error::Scene` at the right line, naming the key or value, never a panic.
use signorini::error::{Error, Location};
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use signorini::scene::{
    DirichletSpec, Load, MaterialSpec, MeshSpec, Mesher, PlaneSpec, RefineSpec, Scene, DEFAULT_SCENE_SOURCE,
    DEFAULT_SCENE_TOML,
};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

fn parse(text: &str) -> signorini::Result<Scene> {
    Scene::from_str(text, Path::new("test.toml"))
}

/// A valid scene; tests replace one line (or append) to make one mistake.
const BASE: &str = r#"title = "base"

[mesh]
shape = "rectangle"
size = [1.0, 0.2]
cell_size = 0.1

[discretization]
order = 1

[material]
young = 210e9
poisson = 0.3

[[dirichlet]]
part = "left"
ux = 0.0
uy = 0.0

[[traction]]
part = "right"
traction = [0.0, -1e6]
"#;

/// BASE with the first occurrence of `from` replaced by `to` (which must change the text).
fn base_with(from: &str, to: &str) -> String {
    assert!(BASE.contains(from), "test bug: {from:?} not in BASE");
    BASE.replacen(from, to, 1)
}

struct SceneError {
    line: usize,
    column: usize,
    message: String,
    hint: String,
}

#[track_caller]
fn scene_error(text: &str) -> SceneError {
    match parse(text) {
        Err(Error::Scene { location: Location { file, line, column }, message, hint }) => {
            assert_eq!(file, Path::new("test.toml"));
            SceneError { line, column, message, hint }
        }
        other => panic!("expected Error::Scene, got {other:?}\nfor scene:\n{text}"),
    }
}

/// 1-based line of the first line of `text` containing `needle`.
fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).expect("needle in text") + 1
}

#[test]
fn base_scene_is_valid() {
    let s = parse(BASE).unwrap();
    assert_eq!(s.title.as_deref(), Some("base"));
    assert_eq!(s.order, Order::P1);
    assert_eq!(s.source, Path::new("test.toml"));
    assert_eq!(s.petsc_options, Vec::<String>::new());
    assert_eq!(s.output_dir, None);
    assert_eq!(s.body_force, [0.0, 0.0]);
}

// ---- examples --------------------------------------------------------------------------------

#[test]
fn default_scene_parses_and_matches_its_file() {
    let s = Scene::default_scene();
    assert_eq!(s.source, Path::new(DEFAULT_SCENE_SOURCE));
    assert_eq!(
        s.mesh,
        MeshSpec::Rectangle {
            origin: [0.0, 0.0],
            size: [1.0, 0.2],
            cell_size: 0.02,
            mesher: Mesher::Structured,
            refine: None
        }
    );
    assert_eq!(s.order, Order::P2);
    assert_eq!(s.material, MaterialSpec { young: 210e9, poisson: 0.3, plane: PlaneSpec::Strain });
    assert_eq!(s.dirichlet.len(), 1);
    assert_eq!((s.dirichlet[0].part.as_str(), s.dirichlet[0].ux, s.dirichlet[0].uy), ("left", Some(0.0), Some(0.0)));
    assert_eq!(s.tractions.len(), 1);
    assert_eq!(s.tractions[0].part, "right");
    assert_eq!(s.tractions[0].load, Load::Traction([0.0, -1e6]));
    // a few thousand dofs: (2·50+1)·(2·10+1) P2 nodes, 2 dofs each
    if let MeshSpec::Rectangle { size, cell_size, .. } = s.mesh {
        let (nx, ny) = ((size[0] / cell_size).round() as usize, (size[1] / cell_size).round() as usize);
        let dofs = 2 * (2 * nx + 1) * (2 * ny + 1);
        assert!((2000..10000).contains(&dofs), "{dofs} dofs");
    }

    let from_disk = Scene::from_file(&examples().join("default.toml")).unwrap();
    assert_eq!(from_disk.tractions[0].at.file, examples().join("default.toml"));
    assert_eq!(s.tractions[0].at.file, Path::new(DEFAULT_SCENE_SOURCE));
    let mut same = from_disk.clone();
    same.source = s.source.clone();
    same.tractions[0].at = s.tractions[0].at.clone();
    same.dirichlet[0].at = s.dirichlet[0].at.clone();
    assert_eq!(same, s);
    assert_eq!(std::fs::read_to_string(examples().join("default.toml")).unwrap(), DEFAULT_SCENE_TOML);
}

#[test]
fn cantilever_example_parses() {
    let s = Scene::from_file(&examples().join("cantilever.toml")).unwrap();
    assert_eq!(
        s.mesh,
        MeshSpec::Rectangle {
            origin: [0.0, 0.0],
            size: [2.0, 0.2],
            cell_size: 0.025,
            mesher: Mesher::Gmsh,
            refine: Some(RefineSpec { point: [0.0, 0.0], cell_size: 0.005, radius: 0.05 })
        }
    );
    assert_eq!(s.order, Order::P1);
    assert_eq!(s.body_force, [0.0, -7.7e4]);
    assert_eq!(s.petsc_options, ["-ksp_type", "cg", "-pc_type", "gamg"]);
    assert_eq!(s.output_dir.as_deref(), Some(Path::new("out/cantilever")));
    assert!(s.tractions.is_empty());
}

#[test]
fn patch_test_example_parses() {
    let path = examples().join("patch_test.toml");
    let s = Scene::from_file(&path).unwrap();
    let (young, nu, p) = (s.material.young, s.material.poisson, 1e6);
    assert_eq!(s.material.plane, PlaneSpec::Strain);
    let side = nu * p / (1.0 - nu);
    let loads: Vec<(&str, Load)> = s.tractions.iter().map(|t| (t.part.as_str(), t.load)).collect();
    assert_eq!(loads, [("top", Load::Pressure(p)), ("right", Load::Pressure(side)), ("left", Load::Pressure(side))]);
    let fixed: Vec<(&str, Option<f64>, Option<f64>)> =
        s.dirichlet.iter().map(|d| (d.part.as_str(), d.ux, d.uy)).collect();
    assert_eq!(fixed, [("bottom", None, Some(0.0)), ("left", Some(0.0), None)]);
    // the comment's exact solution: uy = -1e-5 y
    let slope = -(1.0 + nu) * (1.0 - 2.0 * nu) * p / (young * (1.0 - nu));
    assert!((slope + 1e-5).abs() < 1e-20, "{slope}");
    // the locations of `part = ...` are recorded
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(s.dirichlet[0].at.line, line_of(&text, "part = \"bottom\""));
    assert_eq!(s.dirichlet[0].at.column, "part = ".len() + 1);
    assert_eq!(s.dirichlet[0].at.file, path);
}

#[test]
fn missing_scene_file_is_an_io_error() {
    match Scene::from_file(Path::new("/nonexistent/scene.toml")) {
        Err(Error::Io { path, .. }) => assert_eq!(path, Path::new("/nonexistent/scene.toml")),
        other => panic!("{other:?}"),
    }
}

// ---- TOML-level mistakes ---------------------------------------------------------------------

#[test]
fn toml_syntax_error() {
    let text = base_with("size = [1.0, 0.2]", "size = [1.0, 0.2");
    let e = scene_error(&text);
    assert!(e.message.starts_with("TOML syntax error"), "{}", e.message);
    assert!(e.hint.contains("toml.io"), "{}", e.hint);
    assert!(e.line == line_of(&text, "size =") || e.line == line_of(&text, "size =") + 1, "line {}", e.line);

    let text = base_with("poisson = 0.3", "poisson = 0.3 0.4");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "poisson"));
    assert!(e.message.starts_with("TOML syntax error"), "{}", e.message);
}

#[test]
fn duplicate_key() {
    let text = base_with("poisson = 0.3", "poisson = 0.3\npoisson = 0.25");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "poisson = 0.25"));
    assert!(e.message.contains("poisson"), "{}", e.message);
    assert!(e.hint.contains("only once"), "{}", e.hint);
}

#[test]
fn unknown_key_close_to_a_known_one() {
    let text = base_with("size = [1.0, 0.2]", "size = [1.0, 0.2]\nradus = 1.0");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "radus"), 1));
    assert!(e.message.contains("`radus`") && e.message.contains("[mesh]"), "{}", e.message);
    assert!(e.hint.contains("did you mean `radius`?"), "{}", e.hint);
}

#[test]
fn unknown_key_lists_the_allowed_keys() {
    let text = base_with("poisson = 0.3", "poisson = 0.3\ndensity = 7850");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "density"));
    assert!(e.message.contains("`density`") && e.message.contains("[material]"), "{}", e.message);
    assert!(!e.hint.contains("did you mean"), "{}", e.hint);
    assert!(e.hint.contains("young, poisson, plane"), "{}", e.hint);
}

#[test]
fn unknown_top_level_table() {
    let text = BASE.replace("[material]", "[materials]");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[materials]"), 2));
    assert!(e.message.contains("`materials`") && e.message.contains("top level"), "{}", e.message);
    assert!(e.hint.contains("did you mean `material`?"), "{}", e.hint);

    let text = format!("{BASE}\n[contact]\nfriction = 0.3\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[contact]"));
    assert!(e.hint.contains("not supported yet"), "{}", e.hint);
}

/// Every table names itself in unknown-key errors (the key lists in the parser match its
/// structs).
#[test]
fn unknown_key_in_every_table_names_the_table() {
    let cases: &[(&str, &str, &str)] = &[
        ("title = \"base\"", "title = \"base\"\nbogus_key = 1", "top level"),
        ("shape = \"rectangle\"", "shape = \"rectangle\"\nbogus_key = 1", "[mesh]"),
        ("order = 1", "order = 1\nbogus_key = 1", "[discretization]"),
        ("poisson = 0.3", "poisson = 0.3\nbogus_key = 1", "[material]"),
        ("uy = 0.0", "uy = 0.0\nbogus_key = 1", "[[dirichlet]]"),
        ("traction = [0.0, -1e6]", "traction = [0.0, -1e6]\nbogus_key = 1", "[[traction]]"),
    ];
    for (from, to, table) in cases {
        let text = base_with(from, to);
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "bogus_key"), "{table}");
        assert!(e.message.contains("`bogus_key`") && e.message.contains(table), "{table}: {}", e.message);
    }
    let appended: &[(&str, &str)] = &[
        ("[loads]\nbogus_key = 1\n", "[loads]"),
        ("[solver]\nbogus_key = 1\n", "[solver]"),
        ("[output]\nbogus_key = 1\n", "[output]"),
    ];
    for (tail, table) in appended {
        let text = format!("{BASE}\n{tail}");
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "bogus_key"), "{table}");
        assert!(e.message.contains("`bogus_key`") && e.message.contains(table), "{table}: {}", e.message);
    }
    let text = base_with(
        "mesh]\nshape = \"rectangle\"",
        "mesh]\nshape = \"rectangle\"\nmesher = \"gmsh\"\nrefine = { point = [0, 0], cell_size = 0.01, radius = 0.1, bogus_key = 1 }",
    );
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "bogus_key"));
    assert!(e.message.contains("mesh.refine"), "{}", e.message);
    assert!(e.hint.contains("point, cell_size, radius"), "{}", e.hint);
}

#[test]
fn wrong_type_of_a_value() {
    let text = base_with("young = 210e9", "young = \"steel\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "steel"), "young = ".len() + 1));
    assert!(e.message.contains("`young`") && e.message.contains("\"steel\""), "{}", e.message);
    assert!(e.hint.contains("number"), "{}", e.hint);

    let text = base_with("title = \"base\"", "title = 3");
    let e = scene_error(&text);
    assert_eq!(e.line, 1);
    assert!(e.message.contains("`title`") && e.message.contains("integer 3"), "{}", e.message);
}

#[test]
fn wrong_type_of_a_table() {
    let text = format!("mesh = 3\n{}", &BASE[BASE.find("[discretization]").unwrap()..]);
    let e = scene_error(&text);
    assert_eq!(e.line, 1);
    assert!(e.message.contains("`mesh`") && e.message.contains("[mesh] table"), "{}", e.message);
}

#[test]
fn vectors_need_exactly_two_numbers() {
    let text = base_with("size = [1.0, 0.2]", "size = [1.0, 0.2, 0.3]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "size"));
    assert!(e.message.contains("`size`") && e.message.contains("3 items"), "{}", e.message);

    let text = base_with("traction = [0.0, -1e6]", "traction = [0.0, \"down\"]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "down"));
    assert!(e.message.contains("`traction`") && e.message.contains("\"down\""), "{}", e.message);

    let text = format!("{BASE}\n[loads]\nbody_force = -9.81\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "body_force"));
    assert!(e.message.contains("`body_force`") && e.message.contains("-9.81"), "{}", e.message);
}

// ---- missing keys point at their table -------------------------------------------------------

#[test]
fn missing_material_table() {
    let start = BASE.find("[material]").unwrap();
    let end = BASE.find("[[dirichlet]]").unwrap();
    let text = format!("{}{}", &BASE[..start], &BASE[end..]);
    let e = scene_error(&text);
    assert_eq!(e.line, 1);
    assert!(e.message.contains("[material]"), "{}", e.message);
    assert!(e.hint.contains("young") && e.hint.contains("poisson"), "{}", e.hint);
}

#[test]
fn missing_mesh_table() {
    let start = BASE.find("[mesh]").unwrap();
    let end = BASE.find("[discretization]").unwrap();
    let text = format!("{}{}", &BASE[..start], &BASE[end..]);
    let e = scene_error(&text);
    assert!(e.message.contains("[mesh]"), "{}", e.message);
}

#[test]
fn missing_key_points_at_the_table_header() {
    let text = base_with("young = 210e9\n", "");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[material]"), 1));
    assert!(e.message.contains("[material]") && e.message.contains("`young`"), "{}", e.message);
    assert!(e.hint.contains("young ="), "{}", e.hint);

    let text = base_with("size = [1.0, 0.2]\n", "");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[mesh]"));
    assert!(e.message.contains("`size`") && e.message.contains("rectangle"), "{}", e.message);

    let text = base_with("shape = \"rectangle\"\n", "");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[mesh]"));
    assert!(e.message.contains("`shape`"), "{}", e.message);

    let text = base_with("cell_size = 0.1\n", "");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[mesh]"));
    assert!(e.message.contains("`cell_size`"), "{}", e.message);

    // the second [[traction]] table lacks its part
    let text = format!("{BASE}\n[[traction]]\npressure = 1.0\n");
    let e = scene_error(&text);
    assert_eq!(e.line, text.lines().collect::<Vec<_>>().iter().rposition(|l| *l == "[[traction]]").unwrap() + 1);
    assert!(e.message.contains("[[traction]]") && e.message.contains("`part`"), "{}", e.message);
}

#[test]
fn missing_key_in_a_table_written_with_dotted_keys() {
    // no [mesh] header: the table is located by its first key
    let start = BASE.find("[mesh]").unwrap();
    let end = BASE.find("[discretization]").unwrap();
    let text = format!("{}mesh.shape = \"disc\"\nmesh.cell_size = 0.1\n\n{}", &BASE[..start], &BASE[end..]);
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mesh.shape"));
    assert!(e.message.contains("`radius`") && e.message.contains("disc"), "{}", e.message);
}

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
    assert!(e.hint.contains("\"rectangle\", \"disc\", \"half_disc\", \"file\""), "{}", e.hint);

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
    let sub = parse(&text.replace("mesher = \"structured\"", "mesher = \"gmsh\"")).unwrap();
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
        DirichletSpec { part: "left".into(), ux: None, uy: Some(0.0), at: s.dirichlet[0].at.clone() }
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

// ---- mesh files ------------------------------------------------------------------------------

fn file_scene(file: &str) -> String {
    base_with(
        "shape = \"rectangle\"\nsize = [1.0, 0.2]\ncell_size = 0.1",
        &format!("shape = \"file\"\nfile = \"{file}\""),
    )
}

#[test]
fn mesh_file_that_does_not_exist() {
    let text = file_scene("no_such_part.msh");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "file ="), "file = ".len() + 1));
    assert!(e.message.contains("no_such_part.msh") && e.message.contains("does not exist"), "{}", e.message);
    assert!(e.hint.contains("scene file's directory"), "{}", e.hint);
}

#[test]
fn mesh_file_is_resolved_against_the_scene_directory() {
    let dir = std::env::temp_dir().join(format!("signorini-scene-test-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/part.msh"), "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n").unwrap();
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, file_scene("meshes/part.msh")).unwrap();
    let s = Scene::from_file(&scene_path);
    // the same name read from another directory is missing
    let elsewhere = Scene::from_str(&file_scene("meshes/part.msh"), Path::new("/nonexistent/scene.toml"));
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(s.unwrap().mesh, MeshSpec::File { path: dir.join("meshes/part.msh") });
    assert!(matches!(elsewhere, Err(Error::Scene { .. })), "{elsewhere:?}");
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

// ---- robustness ------------------------------------------------------------------------------

/// Every prefix of a valid scene, and the scene with any one line removed, gives a scene or an
/// `Error::Scene` whose location is inside the text: never a panic.
#[test]
fn no_input_panics() {
    let text = std::fs::read_to_string(examples().join("cantilever.toml")).unwrap();
    let lines = text.lines().count() + 1;
    let check = |t: &str| match parse(t) {
        Ok(_) => {}
        Err(Error::Scene { location, .. }) => {
            assert!(location.line >= 1 && location.line <= lines, "{location}")
        }
        Err(other) => panic!("{other:?}"),
    };
    for (cut, _) in text.char_indices() {
        check(&text[..cut]);
    }
    let all: Vec<&str> = text.lines().collect();
    for skip in 0..all.len() {
        let t: Vec<&str> = all.iter().enumerate().filter(|(i, _)| *i != skip).map(|(_, l)| *l).collect();
        check(&t.join("\n"));
    }
    for weird in ["", "\u{feff}", "[[mesh]]\nshape = 1\n", "mesh = []", "[mesh.refine]\npoint = 3\n", "é = 1"] {
        check(weird);
    }
}

// ---- boundary parts against a mesh -----------------------------------------------------------

/// The unit square split along its diagonal, boundary parts bottom/right/top/left and a region.
///
/// ```text
///   3 ---- 2
///   |    / |
///   |  /   |
///   0 ---- 1
/// ```
fn two_triangles() -> Mesh {
    let group = |name: &str, tag, dim| PhysicalGroup { name: name.into(), tag, dim };
    Mesh {
        order: Order::P1,
        nodes: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        cells: vec![0, 1, 2, 0, 2, 3],
        cell_group: vec![4, 4],
        edges: vec![0, 1, 1, 2, 2, 3, 3, 0],
        edge_group: vec![0, 1, 2, 3],
        groups: vec![
            group("bottom", 1, 1),
            group("right", 2, 1),
            group("top", 3, 1),
            group("left", 4, 1),
            group("domain", 5, 2),
        ],
    }
}

#[test]
fn check_against_mesh_accepts_known_parts() {
    let mesh = two_triangles();
    assert_ne!(mesh.cell_group[0], NO_GROUP);
    parse(BASE).unwrap().check_against_mesh(&mesh).unwrap();
    Scene::from_file(&examples().join("patch_test.toml")).unwrap().check_against_mesh(&mesh).unwrap();
}

#[test]
fn check_against_mesh_reports_an_unknown_part() {
    let text = base_with("part = \"right\"", "part = \"rigth\"");
    let scene = parse(&text).unwrap();
    match scene.check_against_mesh(&two_triangles()) {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!(location.file, Path::new("test.toml"));
            assert_eq!((location.line, location.column), (line_of(&text, "rigth"), "part = ".len() + 1));
            assert!(message.contains("`rigth`"), "{message}");
            assert!(hint.contains("did you mean `right`?"), "{hint}");
            assert!(hint.contains("bottom, right, top, left"), "{hint}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn check_against_mesh_rejects_a_region_name() {
    let text = base_with("part = \"left\"", "part = \"domain\"");
    let scene = parse(&text).unwrap();
    match scene.check_against_mesh(&two_triangles()) {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!(location.line, line_of(&text, "domain"));
            assert!(message.contains("`domain`") && message.contains("region"), "{message}");
            assert!(hint.contains("bottom, right, top, left"), "{hint}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn check_against_mesh_without_boundary_names() {
    let mut mesh = two_triangles();
    mesh.groups.truncate(0);
    mesh.groups.push(PhysicalGroup { name: "domain".into(), tag: 5, dim: 2 });
    mesh.cell_group = vec![0, 0];
    let e = parse(BASE).unwrap().check_against_mesh(&mesh).unwrap_err();
    let Error::Scene { hint, .. } = e else { panic!("{e:?}") };
    assert!(hint.contains("no named boundary parts"), "{hint}");
}
