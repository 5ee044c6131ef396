//! The scene format: the example scenes parse to what they say, and every mistake is an
//! `Error::Scene` at the right line, naming the key or value, never a panic.
use signorini::error::{Error, Location};
use signorini::mesh::structured::cells_for_size;
use signorini::mesh::{Mesh, Order, PhysicalGroup, NO_GROUP};
use signorini::scene::{
    nearest_node, point_tolerance, ContactSolverSpec, DirichletSpec, DirichletTarget, FrictionSpec, Load, MaterialSpec,
    MeshSpec, Mesher, ObstacleSpec, PlaneSpec, RefineSpec, Scene, DEFAULT_SCENE_SOURCE, DEFAULT_SCENE_TOML,
    POINT_TOLERANCE,
};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

fn part(name: &str) -> DirichletTarget {
    DirichletTarget::Part(name.to_string())
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
    // The default scene is a frictional contact problem: the square block benchmark.
    let s = Scene::default_scene();
    assert_eq!(s.source, Path::new(DEFAULT_SCENE_SOURCE));
    assert_eq!(
        s.mesh,
        MeshSpec::Rectangle {
            origin: [0.0, 0.0],
            size: [0.04, 0.04],
            cell_size: 1.25e-3,
            mesher: Mesher::Structured,
            refine: None
        }
    );
    assert_eq!(s.order, Order::P1);
    assert_eq!(s.material, MaterialSpec { young: 1.3e11, poisson: 0.2, plane: PlaneSpec::Strain });
    let contact = s.contact.as_ref().expect("the default scene has a [contact] section");
    assert_eq!(contact.part, "bottom");
    assert_eq!(contact.friction, FrictionSpec::Coulomb { mu: 1.0 });
    let block = Scene::from_file(&examples().join("square_block.toml")).unwrap();
    assert_eq!(
        (&s.mesh, &s.tractions.len(), &s.dirichlet.len()),
        (&block.mesh, &block.tractions.len(), &block.dirichlet.len())
    );
    let from_disk = Scene::from_file(&examples().join("default.toml")).unwrap();
    assert_eq!(from_disk.tractions[0].at.file, examples().join("default.toml"));
    assert_eq!(s.tractions[0].at.file, Path::new(DEFAULT_SCENE_SOURCE));
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
    let fixed: Vec<(DirichletTarget, Option<f64>, Option<f64>)> =
        s.dirichlet.iter().map(|d| (d.target.clone(), d.ux, d.uy)).collect();
    assert_eq!(fixed, [(part("bottom"), None, Some(0.0)), (part("left"), Some(0.0), None)]);
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

    let text = BASE.replace("[material]", "[contacts]\n[material]");
    let e = scene_error(&text);
    assert!(e.message.contains("`contacts`") && e.message.contains("top level"), "{}", e.message);
    assert!(e.hint.contains("did you mean `contact`?"), "{}", e.hint);
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
        ("[contact]\npart = \"bottom\"\nbogus_key = 1\n", "[contact]"),
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
        DirichletSpec { target: part("left"), ux: None, uy: Some(0.0), at: s.dirichlet[0].at.clone() }
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
    assert_eq!(s.unwrap().mesh, MeshSpec::File { path: dir.join("meshes/part.msh"), geometry: None });
    assert!(matches!(elsewhere, Err(Error::Scene { .. })), "{elsewhere:?}");
}

#[test]
fn mesh_file_geometry_script_is_resolved_and_checked() {
    let dir = std::env::temp_dir().join(format!("signorini-scene-geometry-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    std::fs::write(dir.join("meshes/part.msh"), "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n").unwrap();
    std::fs::write(dir.join("meshes/part.geo"), "Point(1) = {0, 0, 0, 1};\n").unwrap();
    let with = |geometry: &str| {
        base_with(
            "shape = \"rectangle\"\nsize = [1.0, 0.2]\ncell_size = 0.1",
            &format!("shape = \"file\"\nfile = \"meshes/part.msh\"\ngeometry = \"{geometry}\""),
        )
    };
    let good = Scene::from_str(&with("meshes/part.geo"), &dir.join("scene.toml"));
    let text = with("meshes/missing.geo");
    let bad = Scene::from_str(&text, &dir.join("scene.toml"));
    std::fs::remove_dir_all(&dir).unwrap();
    assert_eq!(
        good.unwrap().mesh,
        MeshSpec::File { path: dir.join("meshes/part.msh"), geometry: Some(dir.join("meshes/part.geo")) }
    );
    let Err(Error::Scene { location: Location { line, .. }, message, hint }) = bad else { panic!("{bad:?}") };
    assert_eq!(line, line_of(&text, "geometry ="));
    assert!(message.contains("missing.geo") && message.contains("does not exist"), "{message}");
    assert!(hint.contains(".geo script"), "{hint}");
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
    for example in ["cantilever.toml", "square_block.toml"] {
        no_input_panics_around(&std::fs::read_to_string(examples().join(example)).unwrap());
    }
    let polyline = "part = \"bottom\"\nobstacle = \"polyline\"\npoints = [[-1, 0], [0, -0.1], [1, 0]]\n";
    no_input_panics_around(&with_contact(polyline));
}

fn no_input_panics_around(text: &str) {
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
    for weird in [
        "",
        "\u{feff}",
        "[[mesh]]\nshape = 1\n",
        "mesh = []",
        "[mesh.refine]\npoint = 3\n",
        "é = 1",
        "contact = []",
        "[contact]\npoints = 3\n",
        "[[contact]]\npart = \"a\"\n",
    ] {
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

// ---- contact examples ------------------------------------------------------------------------

#[test]
fn contact_patch_example_parses() {
    let path = examples().join("contact_patch.toml");
    let s = Scene::from_file(&path).unwrap();
    assert_eq!(
        s.mesh,
        MeshSpec::Rectangle {
            origin: [0.0, 0.0],
            size: [2.0, 1.0],
            cell_size: 0.3,
            mesher: Mesher::Gmsh,
            refine: None
        }
    );
    let (young, nu, p) = (s.material.young, s.material.poisson, 1e6);
    assert_eq!((young, nu, s.material.plane), (90e9, 0.2, PlaneSpec::Strain));
    let side = nu * p / (1.0 - nu);
    let loads: Vec<(&str, Load)> = s.tractions.iter().map(|t| (t.part.as_str(), t.load)).collect();
    assert_eq!(loads, [("top", Load::Pressure(p)), ("right", Load::Pressure(side)), ("left", Load::Pressure(side))]);
    // one point condition, ux only, off the contact part
    assert_eq!(s.dirichlet.len(), 1);
    assert_eq!(
        (&s.dirichlet[0].target, s.dirichlet[0].ux, s.dirichlet[0].uy),
        (&DirichletTarget::Point([0.0, 1.0]), Some(0.0), None)
    );
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(s.dirichlet[0].at.line, line_of(&text, "point = [0.0, 1.0]"));
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.part, "bottom");
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] });
    assert_eq!((c.gap, c.friction, c.solver), (0.0, FrictionSpec::None, ContactSolverSpec::FullSpaceNewton));
    assert_eq!((c.tolerance, c.max_iterations), (None, None));
    assert_eq!((c.at.line, c.at.column), (line_of(&text, "part = \"bottom\""), "part = ".len() + 1));
    // the comment's exact solution: uy = -1e-5 y
    let slope = -(1.0 + nu) * (1.0 - 2.0 * nu) * p / (young * (1.0 - nu));
    assert!((slope + 1e-5).abs() < 1e-20, "{slope}");
}

#[test]
fn hertz_example_parses() {
    let s = Scene::from_file(&examples().join("hertz.toml")).unwrap();
    let r = 0.1;
    let MeshSpec::HalfDisc { center, radius, cell_size, refine: Some(refine) } = s.mesh else { panic!("{:?}", s.mesh) };
    assert_eq!((center, radius, cell_size), ([0.0, r], r, 0.01));
    assert_eq!(s.order, Order::P2);
    assert_eq!(s.material, MaterialSpec { young: 210e9, poisson: 0.3, plane: PlaneSpec::Strain });
    // the comment's numbers: P = pressure · 2R, a = sqrt(4PR/(π E*)), p0 = 2P/(π a)
    assert_eq!(s.tractions.len(), 1);
    assert_eq!(s.tractions[0].part, "flat");
    let Load::Pressure(pressure) = s.tractions[0].load else { panic!("{:?}", s.tractions[0].load) };
    let force = pressure * 2.0 * r;
    assert!((force - 4.5e7).abs() < 1e-6, "{force}");
    let e_star = s.material.young / (1.0 - s.material.poisson.powi(2));
    let a = (4.0 * force * r / (std::f64::consts::PI * e_star)).sqrt();
    let p0 = 2.0 * force / (std::f64::consts::PI * a);
    assert!((a - 4.98e-3).abs() < 5e-6 && (0.04..=0.1).contains(&(a / r)), "a = {a}");
    assert!((p0 - 5.75e9).abs() < 5e6, "p0 = {p0}");
    // refinement: cells of about a/20 within about 3a of the initial contact point
    assert_eq!(refine.point, [0.0, 0.0]);
    assert!((refine.cell_size / (a / 20.0) - 1.0).abs() < 0.01, "{}", refine.cell_size);
    assert!((refine.radius / (3.0 * a) - 1.0).abs() < 0.01, "{}", refine.radius);
    // ux = 0 at the middle of the flat side, and nothing else
    assert_eq!(s.dirichlet.len(), 1);
    assert_eq!(
        (&s.dirichlet[0].target, s.dirichlet[0].ux, s.dirichlet[0].uy),
        (&DirichletTarget::Point([0.0, r]), Some(0.0), None)
    );
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.part, "arc");
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] });
    assert_eq!((c.friction, c.solver), (FrictionSpec::None, ContactSolverSpec::FullSpaceNewton));
}

#[test]
fn square_block_example_parses() {
    let s = Scene::from_file(&examples().join("square_block.toml")).unwrap();
    let MeshSpec::Rectangle { origin, size, cell_size, mesher, refine } = s.mesh else { panic!("{:?}", s.mesh) };
    assert_eq!((origin, size, mesher, refine), ([0.0, 0.0], [0.04, 0.04], Mesher::Structured, None));
    // 32 element edges along the contact side
    assert_eq!(cells_for_size(size, cell_size), (32, 32));
    assert_eq!(s.order, Order::P1);
    assert_eq!(s.material, MaterialSpec { young: 1.3e11, poisson: 0.2, plane: PlaneSpec::Strain });
    let loads: Vec<(&str, Load)> = s.tractions.iter().map(|t| (t.part.as_str(), t.load)).collect();
    assert_eq!(loads, [("top", Load::Pressure(5e7)), ("left", Load::Pressure(1.5e8))]);
    let fixed: Vec<(DirichletTarget, Option<f64>, Option<f64>)> =
        s.dirichlet.iter().map(|d| (d.target.clone(), d.ux, d.uy)).collect();
    assert_eq!(fixed, [(part("right"), Some(0.0), None), (DirichletTarget::Point([0.04, 0.0]), Some(0.0), Some(0.0))]);
    let c = s.contact.as_ref().unwrap();
    assert_eq!(c.part, "bottom");
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] });
    assert_eq!(
        (c.gap, c.friction, c.solver),
        (0.0, FrictionSpec::Coulomb { mu: 1.0 }, ContactSolverSpec::FullSpaceNewton)
    );
    // the mesh has nodes at the reference abscissae and at the fixed corner
    let mesh = signorini::mesh::structured::rectangle(origin, size, 32, 32, Order::P1).unwrap();
    s.check_against_mesh(&mesh).unwrap();
    for x in [0.0, 1.25e-3, 5e-3, 7.5e-3, 11.25e-3] {
        let (_, d) = nearest_node(&mesh, [x, 0.0]).unwrap();
        assert!(d < 1e-15, "x = {x}: {d}");
    }
    assert_eq!(s.dirichlet[1].nodes(&mesh).unwrap(), [32]);
}

#[test]
fn every_example_parses_and_names_only_parts_of_its_shape() {
    let parts_of = |mesh: &MeshSpec| -> &[&str] {
        match mesh {
            MeshSpec::Rectangle { .. } => &["bottom", "right", "top", "left"],
            MeshSpec::Disc { .. } => &["circle"],
            MeshSpec::HalfDisc { .. } => &["arc", "flat"],
            MeshSpec::File { .. } => &[],
        }
    };
    let mut names: Vec<PathBuf> = std::fs::read_dir(examples())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    names.sort();
    assert!(names.len() >= 6, "{names:?}");
    for path in names {
        let s = Scene::from_file(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        // Every body of a scene with [[body]] tables, the one body of the others.
        for body in s.bodies().iter() {
            let known = parts_of(&body.mesh);
            for (p, at) in body.boundary_parts() {
                assert!(known.contains(&p), "{}: {at}: part {p} of a {:?}", path.display(), body.mesh);
            }
        }
        for pair in &s.contact_pairs {
            for side in [&pair.slave, &pair.master] {
                let body = &s.bodies[s.body_index(&side.body).unwrap()];
                assert!(parts_of(&body.mesh).contains(&side.part.as_str()), "{}: {side}", path.display());
            }
        }
    }
}

// ---- [contact] -------------------------------------------------------------------------------

const LINE: &str = "part = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n";

/// BASE with a [contact] table whose keys are `body`.
fn with_contact(body: &str) -> String {
    format!("{BASE}\n[contact]\n{body}")
}

/// BASE with the line obstacle and `extra` keys.
fn line_contact(extra: &str) -> String {
    with_contact(&format!("{LINE}{extra}\n"))
}

#[test]
fn contact_defaults() {
    let text = line_contact("");
    let s = parse(&text).unwrap();
    let c = s.contact.unwrap();
    assert_eq!(c.part, "bottom");
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] });
    assert_eq!(c.gap, 0.0);
    assert_eq!(c.friction, FrictionSpec::None);
    // the default: the full-space semi-smooth Newton
    assert_eq!(c.solver, ContactSolverSpec::FullSpaceNewton);
    assert_eq!((c.tolerance, c.max_iterations), (None, None));
    assert_eq!(
        (c.at.file.as_path(), c.at.line, c.at.column),
        (Path::new("test.toml"), line_of(&text, "part = \"bottom\""), 8)
    );
}

#[test]
fn contact_with_every_option() {
    let text = line_contact(
        "gap = -1e-4\nfriction = \"coulomb\"\nmu = 0.3\nsolver = \"relaxation\"\nomega = 1.5\ntolerance = 1e-8\nmax_iterations = 300",
    );
    let c = parse(&text).unwrap().contact.unwrap();
    assert_eq!(c.gap, -1e-4);
    assert_eq!(c.friction, FrictionSpec::Coulomb { mu: 0.3 });
    assert_eq!(c.solver, ContactSolverSpec::Relaxation { omega: 1.5 });
    assert_eq!((c.tolerance, c.max_iterations), (Some(1e-8), Some(300)));

    let c = parse(&line_contact("friction = \"tresca\"\nthreshold = 1e5\nsolver = \"tao\"")).unwrap().contact.unwrap();
    assert_eq!((c.friction, c.solver), (FrictionSpec::Tresca { threshold: 1e5 }, ContactSolverSpec::Tao));
    let c = parse(&line_contact("solver = \"relaxation\"")).unwrap().contact.unwrap();
    assert_eq!(c.solver, ContactSolverSpec::Relaxation { omega: 1.0 });
    for (name, solver) in [
        ("newton", ContactSolverSpec::Newton),
        ("newton_full", ContactSolverSpec::FullSpaceNewton),
        ("dpana", ContactSolverSpec::DPana),
        ("uzawa", ContactSolverSpec::Uzawa),
        ("tresca_fixed_point", ContactSolverSpec::TrescaFixedPoint),
        ("snes_vi", ContactSolverSpec::SnesVi),
    ] {
        let c = parse(&line_contact(&format!("solver = \"{name}\""))).unwrap().contact.unwrap();
        assert_eq!(c.solver, solver);
        assert_eq!(solver.scene_name(), name);
    }
    // a table written inline at the top level works too
    let text =
        format!("contact = {{ part = \"bottom\", obstacle = \"circle\", center = [0.5, -1], radius = 1 }}\n{BASE}");
    let c = parse(&text).unwrap().contact.unwrap();
    assert_eq!(c.obstacle, ObstacleSpec::Circle { center: [0.5, -1.0], radius: 1.0 });
    assert_eq!(c.at.line, 1);
}

#[test]
fn contact_normal_is_normalised() {
    let text = line_contact("").replace("normal = [0.0, 1.0]", "normal = [3, -4]");
    let c = parse(&text).unwrap().contact.unwrap();
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.6, -0.8] });
}

#[test]
fn contact_polyline_parses() {
    let text =
        with_contact("part = \"bottom\"\nobstacle = \"polyline\"\npoints = [[-1, 0], [0.0, -0.1], [1.0, 0.0]]\n");
    let c = parse(&text).unwrap().contact.unwrap();
    assert_eq!(c.obstacle, ObstacleSpec::Polyline { points: vec![[-1.0, 0.0], [0.0, -0.1], [1.0, 0.0]] });
}

#[test]
fn contact_unknown_obstacle_kind() {
    let text = line_contact("").replace("obstacle = \"line\"", "obstacle = \"plane\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "obstacle"), "obstacle = ".len() + 1));
    assert!(e.message.contains("obstacle") && e.message.contains("\"plane\""), "{}", e.message);
    assert!(e.hint.contains("\"line\", \"circle\", \"polyline\""), "{}", e.hint);
    let e = scene_error(&line_contact("").replace("obstacle = \"line\"", "obstacle = \"circel\""));
    assert!(e.hint.contains("did you mean \"circle\"?"), "{}", e.hint);
}

#[test]
fn contact_obstacle_key_that_does_not_apply() {
    let text = line_contact("radius = 1.0");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "radius"));
    assert!(e.message.contains("`radius`") && e.message.contains("obstacle = \"line\""), "{}", e.message);
    assert!(e.hint.contains("remove `radius`") && e.hint.contains("point, normal"), "{}", e.hint);

    let text =
        with_contact("part = \"bottom\"\nobstacle = \"circle\"\ncenter = [0, -1]\nradius = 1\nnormal = [0, 1]\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "normal"));
    assert!(e.hint.contains("center, radius"), "{}", e.hint);
}

#[test]
fn contact_missing_keys_point_at_the_table() {
    let text = line_contact("").replace("part = \"bottom\"\n", "");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[contact]"), 1));
    assert!(e.message.contains("[contact]") && e.message.contains("`part`"), "{}", e.message);
    assert!(e.hint.contains("part = \"bottom\""), "{}", e.hint);

    let text = with_contact("part = \"bottom\"\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[contact]"));
    assert!(e.message.contains("`obstacle`"), "{}", e.message);
    assert!(e.hint.contains("obstacle = \"line\""), "{}", e.hint);

    let text = line_contact("").replace("normal = [0.0, 1.0]\n", "");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[contact]"));
    assert!(e.message.contains("`normal`") && e.message.contains("obstacle = \"line\""), "{}", e.message);

    let text = with_contact("part = \"bottom\"\nobstacle = \"circle\"\ncenter = [0, -1]\n");
    let e = scene_error(&text);
    assert!(e.message.contains("`radius`") && e.message.contains("circle"), "{}", e.message);

    let text = with_contact("part = \"bottom\"\nobstacle = \"polyline\"\n");
    let e = scene_error(&text);
    assert!(e.message.contains("`points`") && e.message.contains("polyline"), "{}", e.message);
}

#[test]
fn contact_zero_normal() {
    for bad in ["[0.0, 0.0]", "[0, 0]", "[-0.0, 0.0]"] {
        let text = line_contact("").replace("normal = [0.0, 1.0]", &format!("normal = {bad}"));
        let e = scene_error(&text);
        assert_eq!((e.line, e.column), (line_of(&text, "normal"), "normal = ".len() + 1), "{bad}");
        assert!(
            e.message.contains("`normal`") && e.message.contains("zero") && e.message.contains(bad),
            "{}",
            e.message
        );
        assert!(e.hint.contains("from the obstacle towards the body"), "{}", e.hint);
    }
}

#[test]
fn contact_circle_radius_must_be_positive() {
    for bad in ["0.0", "-1"] {
        let text =
            with_contact(&format!("part = \"bottom\"\nobstacle = \"circle\"\ncenter = [0, -2]\nradius = {bad}\n"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "radius ="), "{bad}");
        assert!(
            e.message.contains("`radius`") && e.message.contains("positive") && e.message.contains(bad),
            "{}",
            e.message
        );
    }
}

fn polyline(points: &str) -> String {
    with_contact(&format!("part = \"bottom\"\nobstacle = \"polyline\"\npoints = {points}\n"))
}

#[test]
fn contact_polyline_needs_two_points() {
    for bad in ["[]", "[[0.0, 0.0]]"] {
        let text = polyline(bad);
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "points ="), "{bad}");
        assert!(e.message.contains("at least 2 points"), "{}", e.message);
        assert!(e.hint.contains("left of the direction of travel"), "{}", e.hint);
    }
}

#[test]
fn contact_polyline_repeated_point() {
    let text = polyline("[[-1.0, 0.0], [0.0, -0.1], [0.0, -0.1], [1.0, 0.0]]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "points ="));
    assert!(e.message.contains("points[1] and points[2]") && e.message.contains("[0, -0.1]"), "{}", e.message);
    assert!(e.hint.contains("repeated point"), "{}", e.hint);
}

#[test]
fn contact_polyline_turning_back() {
    let text = polyline("[[-1.0, 0.0], [1.0, 0.0], [0.0, 0.0]]");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "points ="));
    assert!(e.message.contains("turns back") && e.message.contains("points[1]"), "{}", e.message);
}

#[test]
fn contact_polyline_points_have_two_numbers() {
    for (bad, found) in [
        ("[[0.0, 0.0], [1.0]]", "points[1]"),
        ("[[0.0, 0.0], \"a\"]", "points[1]"),
        ("3", "integer 3"),
        ("[[0, nan], [1, 0]]", "points[0]"),
    ] {
        let text = polyline(bad);
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "points ="), "{bad}");
        assert!(e.message.contains("`points") && e.message.contains(found), "{bad}: {}", e.message);
    }
}

#[test]
fn contact_mu_must_be_nonnegative_and_finite() {
    for bad in ["-0.1", "nan", "inf", "-inf"] {
        let text = line_contact(&format!("friction = \"coulomb\"\nmu = {bad}"));
        let e = scene_error(&text);
        assert_eq!((e.line, e.column), (line_of(&text, "mu ="), "mu = ".len() + 1), "{bad}");
        assert!(e.message.contains("`mu`") && e.message.contains(bad), "{bad}: {}", e.message);
    }
    let e = scene_error(&line_contact("friction = \"coulomb\"\nmu = -0.1"));
    assert!(e.message.contains("negative") && e.hint.contains("≥ 0"), "{} / {}", e.message, e.hint);
    let e = scene_error(&line_contact("friction = \"coulomb\"\nmu = \"high\""));
    assert!(e.message.contains("`mu`") && e.message.contains("number"), "{}", e.message);
}

#[test]
fn contact_coulomb_with_mu_zero_is_frictionless() {
    let c = parse(&line_contact("friction = \"coulomb\"\nmu = 0.0")).unwrap().contact.unwrap();
    assert_eq!(c.friction, FrictionSpec::None);
    let c = parse(&line_contact("friction = \"coulomb\"\nmu = 0")).unwrap().contact.unwrap();
    assert_eq!(c.friction, FrictionSpec::None);
    // and so SNESVI accepts it
    let c = parse(&line_contact("friction = \"coulomb\"\nmu = 0\nsolver = \"snes_vi\"")).unwrap().contact.unwrap();
    assert_eq!((c.friction, c.solver), (FrictionSpec::None, ContactSolverSpec::SnesVi));
}

#[test]
fn contact_mu_without_coulomb() {
    let text = line_contact("friction = \"tresca\"\nthreshold = 1e5\nmu = 0.3");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mu ="));
    assert!(e.message.contains("`mu`") && e.message.contains("friction = \"tresca\""), "{}", e.message);
    assert!(e.hint.contains("threshold") && e.hint.contains("friction = \"coulomb\""), "{}", e.hint);

    let text = line_contact("friction = \"none\"\nmu = 0.3");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mu ="));
    assert!(e.message.contains("`mu`") && e.message.contains("friction = \"none\""), "{}", e.message);
    assert!(e.hint.contains("add friction = \"coulomb\""), "{}", e.hint);

    // friction not written: the default is none
    let text = line_contact("mu = 0.3");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "mu ="));
    assert!(e.message.contains("`mu`") && e.message.contains("default"), "{}", e.message);
    assert!(e.hint.contains("add friction = \"coulomb\""), "{}", e.hint);
}

#[test]
fn contact_threshold_must_be_positive() {
    for bad in ["0.0", "-1e5"] {
        let text = line_contact(&format!("friction = \"tresca\"\nthreshold = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "threshold ="), "{bad}");
        assert!(
            e.message.contains("`threshold`") && e.message.contains("positive") && e.message.contains(bad),
            "{}",
            e.message
        );
    }
}

#[test]
fn contact_threshold_without_tresca() {
    let text = line_contact("friction = \"coulomb\"\nmu = 0.3\nthreshold = 1e5");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "threshold ="));
    assert!(e.message.contains("`threshold`") && e.message.contains("friction = \"coulomb\""), "{}", e.message);
    assert!(e.hint.contains("`mu`") && e.hint.contains("friction = \"tresca\""), "{}", e.hint);

    let text = line_contact("threshold = 1e5");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "threshold ="));
    assert!(e.hint.contains("add friction = \"tresca\""), "{}", e.hint);
}

#[test]
fn contact_coulomb_without_mu() {
    let text = line_contact("friction = \"coulomb\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "friction"), "friction = ".len() + 1));
    assert!(e.message.contains("coulomb") && e.message.contains("`mu`"), "{}", e.message);
    assert!(e.hint.contains("mu = 0.3"), "{}", e.hint);
}

#[test]
fn contact_tresca_without_threshold() {
    let text = line_contact("friction = \"tresca\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "friction"));
    assert!(e.message.contains("tresca") && e.message.contains("`threshold`"), "{}", e.message);
    assert!(e.hint.contains("threshold = "), "{}", e.hint);
}

#[test]
fn contact_unknown_friction() {
    let text = line_contact("friction = \"coulom\"\nmu = 0.3");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "friction"));
    assert!(
        e.hint.contains("did you mean \"coulomb\"?") && e.hint.contains("\"none\", \"tresca\", \"coulomb\""),
        "{}",
        e.hint
    );
}

#[test]
fn contact_unknown_solver() {
    let text = line_contact("solver = \"gauss_seidel\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "solver"), "solver = ".len() + 1));
    assert!(e.message.contains("solver") && e.message.contains("\"gauss_seidel\""), "{}", e.message);
    for name in ["newton", "newton_full", "relaxation", "dpana", "uzawa", "tresca_fixed_point", "snes_vi", "tao"] {
        assert!(e.hint.contains(&format!("\"{name}\"")), "{name}: {}", e.hint);
    }
    let e = scene_error(&line_contact("solver = \"newtn\""));
    assert!(e.hint.contains("did you mean \"newton\"?"), "{}", e.hint);
    let e = scene_error(&line_contact("solver = \"newton_ful\""));
    assert!(e.hint.contains("did you mean \"newton_full\"?"), "{}", e.hint);
}

#[test]
fn contact_omega_out_of_range() {
    for bad in ["0.0", "2.0", "-0.5", "2.5", "nan"] {
        let text = line_contact(&format!("solver = \"relaxation\"\nomega = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "omega"), "{bad}");
        assert!(e.message.contains("`omega`") && e.message.contains(bad), "{bad}: {}", e.message);
    }
    let e = scene_error(&line_contact("solver = \"relaxation\"\nomega = 2"));
    assert!(e.message.contains("(0, 2)"), "{}", e.message);
    assert!(e.hint.contains("Gauss–Seidel"), "{}", e.hint);
}

#[test]
fn contact_omega_for_another_solver() {
    let text = line_contact("solver = \"uzawa\"\nomega = 1.2");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "omega"));
    assert!(e.message.contains("`omega`") && e.message.contains("solver = \"uzawa\""), "{}", e.message);
    assert!(e.hint.contains("solver = \"relaxation\""), "{}", e.hint);
    let e = scene_error(&line_contact("omega = 1.2"));
    assert!(e.message.contains("default solver") && e.message.contains("newton_full"), "{}", e.message);
}

#[test]
fn contact_snes_vi_needs_frictionless() {
    for friction in ["friction = \"coulomb\"\nmu = 0.3", "friction = \"tresca\"\nthreshold = 1e5"] {
        let text = line_contact(&format!("{friction}\nsolver = \"snes_vi\""));
        let e = scene_error(&text);
        assert_eq!((e.line, e.column), (line_of(&text, "solver"), "solver = ".len() + 1), "{friction}");
        assert!(e.message.contains("snes_vi") && e.message.contains("friction = \""), "{}", e.message);
        assert!(
            e.hint.contains("SNESVI") && e.hint.contains("frictionless") && e.hint.contains("newton"),
            "{}",
            e.hint
        );
    }
    let c = parse(&line_contact("solver = \"snes_vi\"")).unwrap().contact.unwrap();
    assert_eq!(c.solver, ContactSolverSpec::SnesVi);
}

#[test]
fn contact_tao_needs_tresca() {
    for (friction, named) in [
        ("friction = \"coulomb\"\nmu = 0.3", "friction = \"coulomb\""),
        ("", "frictionless"),
        ("friction = \"coulomb\"\nmu = 0.0", "mu = 0"),
    ] {
        let text = line_contact(&format!("{friction}\nsolver = \"tao\""));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "solver"), "{friction}");
        assert!(
            e.message.contains("tao") && e.message.contains("tresca") && e.message.contains(named),
            "{}",
            e.message
        );
        assert!(e.hint.contains("TAO") && e.hint.contains("Tresca"), "{}", e.hint);
    }
}

#[test]
fn contact_tolerance_and_iterations_are_checked() {
    for bad in ["0.0", "-1e-9", "1.0", "5"] {
        let text = line_contact(&format!("tolerance = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "tolerance"), "{bad}");
        assert!(e.message.contains("`tolerance`") && e.message.contains(bad), "{bad}: {}", e.message);
    }
    for (bad, what) in
        [("0", "at least 1"), ("-3", "at least 1"), ("10.5", "whole number"), ("\"many\"", "whole number")]
    {
        let text = line_contact(&format!("max_iterations = {bad}"));
        let e = scene_error(&text);
        assert_eq!(e.line, line_of(&text, "max_iterations"), "{bad}");
        assert!(e.message.contains("`max_iterations`") && e.message.contains(what), "{bad}: {}", e.message);
    }
}

#[test]
fn contact_gap_must_be_a_number() {
    let text = line_contact("gap = \"small\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "gap"));
    assert!(e.message.contains("`gap`"), "{}", e.message);
}

#[test]
fn contact_part_must_not_be_clamped() {
    // BASE clamps "left" (ux and uy)
    let text = line_contact("").replace("part = \"bottom\"\nobstacle", "part = \"left\"\nobstacle");
    let e = scene_error(&text);
    let contact_line = text.lines().collect::<Vec<_>>().iter().rposition(|l| *l == "part = \"left\"").unwrap() + 1;
    assert_eq!((e.line, e.column), (contact_line, "part = ".len() + 1));
    assert!(e.message.contains("`left`") && e.message.contains("clamped"), "{}", e.message);
    assert!(e.message.contains(&format!("line {}", line_of(&text, "part = \"left\""))), "{}", e.message);
    assert!(e.hint.contains("a clamped part cannot come into contact"), "{}", e.hint);

    // clamped by two tables, one component each
    let text = format!(
        "{}\n[[dirichlet]]\npart = \"bottom\"\nux = 0.0\n\n[[dirichlet]]\npart = \"bottom\"\nuy = 0.0\n",
        line_contact("")
    );
    let e = scene_error(&text);
    assert!(e.message.contains("`bottom`") && e.message.contains("lines "), "{}", e.message);

    // one component is allowed
    let text = format!("{}\n[[dirichlet]]\npart = \"bottom\"\nux = 0.0\n", line_contact(""));
    assert!(parse(&text).is_ok());
    // a point condition with both components on a node of the contact part is allowed (that
    // node leaves the contact set)
    let text = format!("{}\n[[dirichlet]]\npoint = [1.0, 0.0]\nux = 0.0\nuy = 0.0\n", line_contact(""));
    assert!(parse(&text).is_ok());
}

#[test]
fn check_against_mesh_checks_the_contact_part() {
    let text = line_contact("").replace("part = \"bottom\"", "part = \"botom\"");
    let scene = parse(&text).unwrap();
    match scene.check_against_mesh(&two_triangles()) {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!((location.line, location.column), (line_of(&text, "botom"), "part = ".len() + 1));
            assert!(message.contains("`botom`"), "{message}");
            assert!(hint.contains("did you mean `bottom`?"), "{hint}");
        }
        other => panic!("{other:?}"),
    }
    let text = line_contact("").replace("part = \"bottom\"", "part = \"domain\"");
    let e = parse(&text).unwrap().check_against_mesh(&two_triangles()).unwrap_err();
    let Error::Scene { location, message, .. } = e else { panic!("{e:?}") };
    assert_eq!(location.line, line_of(&text, "domain"));
    assert!(message.contains("region"), "{message}");
    parse(&line_contact("")).unwrap().check_against_mesh(&two_triangles()).unwrap();
}

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
    let text = line_contact("").replace("normal = [0.0, 1.0]", "normal = [0.0, 1e-320]");
    let c = parse(&text).unwrap().contact.unwrap();
    assert_eq!(c.obstacle, ObstacleSpec::Line { point: [0.0, 0.0], normal: [0.0, 1.0] });
}

/// The TOML blocks of docs/scene-format.md parse: whole scenes as they are, `[contact]` and
/// `[[dirichlet]]` snippets appended to a valid scene.
#[test]
fn documentation_examples_parse() {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-format.md")).unwrap();
    let blocks: Vec<&str> = doc.split("```toml\n").skip(1).map(|b| b.split("```").next().unwrap()).collect();
    let mut contacts = 0;
    for block in &blocks {
        let text = if block.contains("[mesh]") { block.to_string() } else { format!("{BASE}\n{block}") };
        let s = parse(&text).unwrap_or_else(|e| panic!("{e}\nin the block\n{block}"));
        contacts += usize::from(s.contact.is_some());
    }
    assert!(blocks.len() >= 5 && contacts >= 3, "{} blocks, {contacts} with [contact]", blocks.len());
}

#[test]
fn element_p2p0_needs_order_2_and_plane_strain() {
    use signorini::fem::Element;
    // Default and explicit Lagrange.
    assert_eq!(parse(BASE).unwrap().element, Element::Lagrange);
    let text = base_with("order = 1", "order = 1\nelement = \"lagrange\"");
    assert_eq!(parse(&text).unwrap().element, Element::Lagrange);
    let text = base_with("order = 1", "order = 2\nelement = \"p2p0\"");
    assert_eq!(parse(&text).unwrap().element, Element::P2P0);
    // Unknown name: the choices are listed.
    let text = base_with("order = 1", "order = 2\nelement = \"p2p1\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "element"), "element = ".len() + 1));
    assert!(e.message.contains("p2p1") && e.hint.contains("\"p2p0\""), "{} / {}", e.message, e.hint);
    // P1 cells: the element would be P1 itself.
    let text = base_with("order = 1", "order = 1\nelement = \"p2p0\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "element"), "element = ".len() + 1));
    assert!(e.message.contains("order = 1") && e.hint.contains("order = 2"), "{} / {}", e.message, e.hint);
    // Without `order` the default is P1: same error.
    let text = base_with("order = 1", "element = \"p2p0\"");
    assert!(scene_error(&text).hint.contains("order = 2"));
    // Plane stress does not lock.
    let text = base_with("order = 1", "order = 2\nelement = \"p2p0\"");
    let text = text.replacen("poisson = 0.3", "poisson = 0.3\nplane = \"stress\"", 1);
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "element"));
    assert!(e.message.contains("plane strain") && e.hint.contains("does not lock"), "{} / {}", e.message, e.hint);
}

#[test]
fn formulation_and_estimate_keys() {
    use signorini::scene::Formulation;
    let s = parse(&base_with("order = 1", "order = 1\nformulation = \"dual\"")).unwrap();
    assert_eq!(s.formulation, Formulation::Dual);
    assert!(!s.estimate);
    let s = parse(&format!("{BASE}\n[estimate]\n")).unwrap();
    assert!(s.estimate && s.formulation == Formulation::Primal);
    let s = parse(&format!("{BASE}\n[estimate]\nenabled = false\n")).unwrap();
    assert!(!s.estimate);
    let text = base_with("order = 1", "order = 1\nformulation = \"dula\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "dula"));
    assert!(e.message.contains("formulation") && e.hint.contains("dual"), "{} / {}", e.message, e.hint);
    let text = format!("{BASE}\n[estimate]\nenabled = \"yes\"\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "enabled"));
    assert!(e.message.contains("true or false"), "{}", e.message);
}

#[test]
fn dual_constraints_key() {
    use signorini::scene::DualConstraints;
    assert_eq!(parse(BASE).unwrap().dual_constraints, DualConstraints::Eliminated);
    let s = parse(&base_with("order = 1", "order = 1\ndual_constraints = \"multipliers\"")).unwrap();
    assert_eq!(s.dual_constraints, DualConstraints::Multipliers);
    // It survives the round trip through the scene text.
    assert_eq!(parse(&s.to_toml()).unwrap().dual_constraints, DualConstraints::Multipliers);
    let text = base_with("order = 1", "order = 1\ndual_constraints = \"lagrange\"");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "lagrange"));
    assert!(e.message.contains("dual_constraints") && e.hint.contains("multipliers"), "{} / {}", e.message, e.hint);
}

#[test]
fn scenes_built_in_rust_get_the_checks_of_a_file() {
    use signorini::scene::{SceneBuilder, BUILT_IN_RUST};
    // ν = 0.6 and μ = −0.5: the same messages as in a file.
    let from_file = scene_error(&base_with("poisson = 0.3", "poisson = 0.6"));
    let built = SceneBuilder::rectangle([0.0, 0.0], [1.0, 0.2], 0.1)
        .material(210e9, 0.6)
        .dirichlet("left", Some(0.0), Some(0.0))
        .build();
    match built {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!(location.file, Path::new(BUILT_IN_RUST));
            assert!(
                message.contains("poisson = 0.6") && message.ends_with(&from_file.message),
                "{message} / {}",
                from_file.message
            );
            assert_eq!(hint, from_file.hint);
        }
        other => panic!("{other:?}"),
    }
    let built = SceneBuilder::rectangle([0.0, 0.0], [1.0, 0.2], 0.1)
        .material(210e9, 0.3)
        .contact_line("bottom", [0.0, 0.0], [0.0, 1.0])
        .coulomb(-0.5)
        .build();
    match built {
        Err(Error::Scene { message, .. }) => assert!(message.contains("mu"), "{message}"),
        other => panic!("mu = -0.5 accepted: {other:?}"),
    }
    // A scene changed field by field after reading is checked again (as the driver does).
    let mut scene = parse(BASE).unwrap();
    scene.material.poisson = 0.6;
    assert!(matches!(scene.validated(), Err(Error::Scene { .. })));
    // Every example scene survives the round trip through to_toml unchanged.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = Scene::from_file(&path).unwrap();
            let again = Scene::from_str(&scene.to_toml(), &path).unwrap();
            assert_eq!(again.to_toml(), scene.to_toml(), "{}", path.display());
            assert_eq!(again.material, scene.material);
            assert_eq!(again.contact.as_ref().map(|c| c.friction), scene.contact.as_ref().map(|c| c.friction));
        }
    }
}
