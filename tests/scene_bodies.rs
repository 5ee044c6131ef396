//! Scenes with several bodies: `[[body]]` and `[[contact_pair]]` parse to what they say, every
//! mistake is an `Error::Scene` at the right line, and the bodies' model (placed meshes, their
//! union, the overlap check) is right. Single-body scenes are tested in tests/scene.rs.
#[path = "common/edit.rs"]
mod edit;
use edit::Edit;
use signorini::error::{Error, Location};
use signorini::mesh::Order;
use signorini::scene::{
    BodiesModel, DirichletTarget, FrictionSpec, Load, MeshSpec, Mesher, Placement, PlaneSpec, Scene, SINGLE_BODY_NAME,
};
use std::path::{Path, PathBuf};

fn examples() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes")
}

fn parse(text: &str) -> signorini::Result<Scene> {
    Scene::from_str(text, Path::new("test.toml"))
}

/// Two structured blocks, `top` resting on `bottom`, a Coulomb pair between them.
const TWO: &str = r#"title = "two blocks"

[[body]]
name = "top"

[body.mesh]
shape = "rectangle"
origin = [0.0, 1.0]
size = [1.0, 0.5]
cell_size = 0.25

[body.material]
young = 1e9
poisson = 0.3

[[body.traction]]
part = "top"
pressure = 1e6

[[body.dirichlet]]
part = "left"
ux = 0.0

[[body]]
name = "bottom"
mesh = { shape = "rectangle", size = [2.0, 1.0], cell_size = 0.5 }
material = { young = 2e9, poisson = 0.25 }

[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0

[[contact_pair]]
slave = "top.bottom"
master = "bottom.top"
friction = "coulomb"
mu = 0.3
"#;

fn two_with(from: &str, to: &str) -> String {
    assert!(TWO.contains(from), "test bug: {from:?} not in TWO");
    TWO.replacen(from, to, 1)
}

/// 1-based line of the first line of `text` containing `needle` (at or after line `after`).
fn line_of(text: &str, needle: &str) -> usize {
    nth_line_of(text, needle, 0)
}
/// 1-based line of the `n`-th (0-based) line of `text` containing `needle`.
fn nth_line_of(text: &str, needle: &str, n: usize) -> usize {
    text.lines().enumerate().filter(|(_, l)| l.contains(needle)).nth(n).expect("needle in text").0 + 1
}

/// The error of `result`: a scene error in test.toml, as (line, message, hint).
#[track_caller]
fn scene_error<T: std::fmt::Debug>(result: signorini::Result<T>) -> (usize, String, String) {
    match result {
        Err(Error::Scene { location: Location { file, line, .. }, message, hint }) => {
            assert_eq!(file, Path::new("test.toml"));
            (line, message, hint)
        }
        other => panic!("expected Error::Scene, got {other:?}"),
    }
}

// ---- parsing -----------------------------------------------------------------------------------

#[test]
fn two_blocks_parse_with_their_own_tables() {
    let s = parse(TWO).unwrap();
    assert!(s.has_body_tables());
    assert_eq!(s.bodies.len(), 2);
    let (top, bottom) = (&s.bodies[0], &s.bodies[1]);
    assert_eq!((top.name.as_str(), top.at.line), ("top", line_of(TWO, "name = \"top\"")));
    assert_eq!(top.placement, Placement::default());
    assert_eq!(
        top.mesh,
        MeshSpec::Rectangle {
            origin: [0.0, 1.0],
            size: [1.0, 0.5],
            cell_size: 0.25,
            mesher: Mesher::Structured,
            refine: None
        }
    );
    assert_eq!(top.tractions.len(), 1);
    assert_eq!(top.tractions[0].load, Load::Pressure(1e6));
    assert_eq!(top.tractions[0].at.line, line_of(TWO, "part = \"top\""));
    assert_eq!(top.dirichlet[0].target, DirichletTarget::Part("left".into()));
    assert_eq!(bottom.material.young, 2e9);
    assert_eq!(bottom.dirichlet[0].ux, Some(0.0));
    assert!(bottom.tractions.is_empty() && bottom.contact.is_none());
    // The single-body fields hold the first body.
    assert_eq!(s.mesh, top.mesh);
    assert_eq!(s.material, top.material);
    assert_eq!(s.tractions, top.tractions);
    let pair = &s.contact_pairs[0];
    assert_eq!((pair.slave.body.as_str(), pair.slave.part.as_str()), ("top", "bottom"));
    assert_eq!(pair.master.to_string(), "bottom.top");
    assert_eq!(pair.friction, FrictionSpec::Coulomb { mu: 0.3 });
    assert_eq!(pair.max_initial_overlap, None);
    assert_eq!(pair.at.line, line_of(TWO, "[[contact_pair]]"));
    assert_eq!(pair.slave.at.line, line_of(TWO, "slave ="));
    assert_eq!(s.body_index("bottom"), Some(1));
}

#[test]
fn a_single_body_scene_is_one_body_named_body() {
    let s = Scene::from_file(&examples().join("square_block.toml")).unwrap();
    assert!(!s.has_body_tables() && s.contact_pairs.is_empty());
    let bodies = s.bodies();
    assert_eq!(bodies.len(), 1);
    assert_eq!(bodies[0].name, SINGLE_BODY_NAME);
    assert_eq!(bodies[0].mesh, s.mesh);
    assert_eq!(bodies[0].dirichlet, s.dirichlet);
    assert_eq!(bodies[0].contact, s.contact);
    assert_eq!(bodies[0].placement, Placement::default());
}

#[test]
fn the_example_scenes_parse() {
    let s = Scene::from_file(&examples().join("two_cylinders.toml")).unwrap();
    let names: Vec<&str> = s.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["upper", "lower"]);
    assert_eq!(s.bodies[1].placement, Placement { rotate: 180.0, translate: [0.0, -0.1] });
    assert!(s.bodies.iter().all(|b| b.order == Order::P2 && b.material.plane == PlaneSpec::Strain));
    assert!(matches!(s.bodies[0].mesh, MeshSpec::HalfDisc { radius: 0.1, .. }));
    assert_eq!(s.contact_pairs.len(), 1);
    assert_eq!(s.contact_pairs[0].friction, FrictionSpec::None);
    assert_eq!(
        (s.contact_pairs[0].slave.to_string(), s.contact_pairs[0].master.to_string()),
        ("upper.arc".into(), "lower.arc".into())
    );

    let s = Scene::from_file(&examples().join("block_on_block.toml")).unwrap();
    let names: Vec<&str> = s.bodies.iter().map(|b| b.name.as_str()).collect();
    assert_eq!(names, ["block", "foundation"]);
    assert_eq!(s.bodies[1].material.young, 7e10);
    assert_eq!(s.bodies[0].tractions.len(), 2);
    assert_eq!(s.contact_pairs[0].friction, FrictionSpec::Coulomb { mu: 1.0 });
}

#[test]
fn multibody_scenes_survive_the_round_trip_through_to_toml() {
    for text in [
        TWO.to_string(),
        two_with(
            "friction = \"coulomb\"\nmu = 0.3",
            "friction = \"tresca\"\nthreshold = 1e5\nmax_initial_overlap = 1e-3",
        ),
    ] {
        let s = parse(&text).unwrap();
        let again = parse(&s.to_toml()).unwrap();
        assert_eq!(again.to_toml(), s.to_toml());
        assert_eq!(again.contact_pairs.len(), 1);
        assert_eq!(again.contact_pairs[0].friction, s.contact_pairs[0].friction);
        assert_eq!(again.contact_pairs[0].max_initial_overlap, s.contact_pairs[0].max_initial_overlap);
        assert_eq!(again.bodies.len(), 2);
        assert_eq!(again.bodies[1].material, s.bodies[1].material);
        assert_eq!(again.bodies[1].dirichlet.len(), 1);
        // validated() keeps the scene (and its own locations).
        assert_eq!(s.validated().unwrap().bodies, s.bodies);
    }
    let s = Scene::from_file(&examples().join("two_cylinders.toml")).unwrap();
    let again = Scene::from_str(&s.to_toml(), &examples().join("two_cylinders.toml")).unwrap();
    assert_eq!(again.bodies[1].placement, s.bodies[1].placement);
    assert_eq!(again.bodies[1].mesh, s.bodies[1].mesh);
}

#[test]
fn tresca_pairs_and_stated_overlaps_parse() {
    let s = parse(&two_with(
        "friction = \"coulomb\"\nmu = 0.3",
        "friction = \"tresca\"\nthreshold = 2e5\nmax_initial_overlap = 0.0",
    ))
    .unwrap();
    assert_eq!(s.contact_pairs[0].friction, FrictionSpec::Tresca { threshold: 2e5 });
    assert_eq!(s.contact_pairs[0].max_initial_overlap, Some(0.0));
    let s = parse(&two_with("friction = \"coulomb\"\nmu = 0.3", "")).unwrap();
    assert_eq!(s.contact_pairs[0].friction, FrictionSpec::None);
    let s = parse(&two_with("mu = 0.3", "mu = 0")).unwrap();
    assert_eq!(s.contact_pairs[0].friction, FrictionSpec::None);
}

// ---- mistakes, each at its line ------------------------------------------------------------------

#[test]
fn top_level_body_tables_cannot_be_mixed_with_bodies() {
    let text = format!("{TWO}\n[mesh]\nshape = \"rectangle\"\nsize = [1.0, 1.0]\ncell_size = 0.5\n");
    let (line, message, hint) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "[mesh]"));
    assert!(message.contains("[mesh] at the top level cannot be combined with [[body]]"), "{message}");
    assert!(hint.contains("[body.mesh]"), "{hint}");
    let text = format!("{TWO}\n[[dirichlet]]\npart = \"left\"\nux = 0.0\n");
    let (line, message, hint) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "[[dirichlet]]"));
    assert!(message.contains("[[dirichlet]] at the top level"), "{message}");
    assert!(hint.contains("[[body.dirichlet]]"), "{hint}");
    let text = format!("material = {{ young = 1e9, poisson = 0.3 }}\n{TWO}");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!((line, message.contains("[material]")), (1, true), "{message}");
    let text = format!("{TWO}\n[estimate]\n");
    let (line, message, hint) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "[estimate]"));
    assert!(message.contains("[estimate]") && hint.contains("single body"), "{message} / {hint}");
}

#[test]
fn body_names_are_required_unique_and_without_dots() {
    let text = two_with("name = \"bottom\"\n", "");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, nth_line_of(&text, "[[body]]", 1));
    assert!(message.contains("[[body]] number 2 has no `name`"), "{message}");

    let text = two_with("name = \"bottom\"", "name = \"top\"");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, nth_line_of(&text, "name = \"top\"", 1));
    assert!(message.contains("two bodies are named `top` (the first on line 4)"), "{message}");

    let text = two_with("name = \"bottom\"", "name = \"base.plate\"");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "base.plate"));
    assert!(message.contains("contains `.`"), "{message}");
}

#[test]
fn a_body_without_mesh_or_material_is_located_at_its_header() {
    let text = two_with("mesh = { shape = \"rectangle\", size = [2.0, 1.0], cell_size = 0.5 }\n", "");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!((line, message.as_str()), (nth_line_of(&text, "[[body]]", 1), "body `bottom` has no mesh"));
    let text = two_with("[body.material]\nyoung = 1e9\npoisson = 0.3\n", "");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!((line, message.as_str()), (line_of(&text, "[[body]]"), "body `top` has no material"));
}

#[test]
fn mistakes_inside_a_body_are_located_in_that_body() {
    // A missing key is reported at the header of this body's table, not the first body's.
    let text = format!("{TWO}\n[[body]]\nname = \"third\"\n[body.mesh]\nshape = \"disc\"\nradius = 1.0\n");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "shape = \"disc\"") - 1);
    assert_eq!(message, "[body.mesh] of body `third` with shape = \"disc\" is missing `cell_size`");
    let text = two_with("poisson = 0.25", "poisson = 0.5");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "poisson = 0.5"));
    assert!(message.contains("poisson"), "{message}");
    // An unknown key of a [[body]] table.
    let text = two_with("name = \"bottom\"", "name = \"bottom\"\nrotat = 90.0");
    let (line, message, hint) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "rotat ="));
    assert!(message.contains("unknown key `rotat` in [[body]]"), "{message}");
    assert!(hint.contains("did you mean `rotate`?"), "{hint}");
    // Scene-wide keys do not belong to one body.
    let text = two_with(
        "[body.material]\nyoung = 1e9",
        "[body.discretization]\nformulation = \"dual\"\n\n[body.material]\nyoung = 1e9",
    );
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!((line, message.as_str()), (line_of(&text, "formulation"), "`formulation` does not apply to one body"));
    let text = two_with("name = \"bottom\"", "name = \"bottom\"\ntranslate = [1.0]");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "translate"));
    assert!(message.contains("`translate` must be an array of two numbers"), "{message}");
}

#[test]
fn bodies_share_their_order_and_plane_model() {
    let text = two_with("mesh = { shape", "discretization = { order = 2 }\nmesh = { shape");
    let (line, message, hint) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "order = 2"));
    assert_eq!(message, "body `bottom` has order = 2, but body `top` (line 4) has order = 1");
    assert!(hint.contains("same order"), "{hint}");
    let text = two_with("poisson = 0.25 }", "poisson = 0.25, plane = \"stress\" }");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, line_of(&text, "plane = \"stress\""));
    assert_eq!(message, "body `bottom` is in plane = \"stress\", but body `top` (line 4) is in plane = \"strain\"");
    let text = two_with("poisson = 0.25 }", "poisson = 0.25, plane = \"axisymmetric\" }");
    let (_, message, hint) = scene_error(parse(&text));
    assert_eq!(
        message,
        "body `bottom` is in plane = \"axisymmetric\", but body `top` (line 4) is in plane = \"strain\""
    );
    assert!(hint.contains("axisymmetric: bodies of revolution"), "{hint}");
}

#[test]
fn contact_pair_mistakes_are_located() {
    let cases: &[(&str, &str, &str, &str)] = &[
        ("slave = \"top.bottom\"", "slave = \"tpo.bottom\"", "tpo.bottom", "`slave` names an unknown body `tpo`"),
        (
            "slave = \"top.bottom\"",
            "slave = \"top\"",
            "slave = \"top\"",
            "`slave` must name a body and one of its boundary parts as \"body.part\", found \"top\"",
        ),
        (
            "master = \"bottom.top\"",
            "master = \"top.bottom\"",
            "master = \"top.bottom\"",
            "`slave` and `master` are the same part `top.bottom`",
        ),
        (
            "master = \"bottom.top\"",
            "master = \"top.top\"",
            "master = \"top.top\"",
            "`slave` `top.bottom` and `master` `top.top` are parts of the same body `top`",
        ),
        ("mu = 0.3", "threshold = 1e5", "threshold", "`threshold` does not apply to friction = \"coulomb\""),
        ("mu = 0.3", "", "friction = \"coulomb\"", "friction = \"coulomb\" needs `mu`"),
        (
            "mu = 0.3",
            "mu = 0.3\nmax_initial_overlap = -1e-3",
            "max_initial_overlap",
            "`max_initial_overlap` must not be negative, found -1e-3",
        ),
        ("slave = \"top.bottom\"\n", "", "[[contact_pair]]", "this [[contact_pair]] table is missing `slave`"),
        ("mu = 0.3", "mu = 0.3\nmaster_part = \"x\"", "master_part", "unknown key `master_part` in [[contact_pair]]"),
    ];
    for (from, to, at, expected) in cases {
        let text = two_with(from, to);
        let (line, message, _) = scene_error(parse(&text));
        assert_eq!(message, *expected, "{to}");
        assert_eq!(line, line_of(&text, at), "{to}: {message}");
    }
    // The unknown body's hint suggests the closest name.
    let (_, _, hint) = scene_error(parse(&two_with("slave = \"top.bottom\"", "slave = \"tpo.bottom\"")));
    assert_eq!(hint, "did you mean `top`? the bodies are: top, bottom");
    // The same pair twice (either way round).
    let text = format!("{TWO}\n[[contact_pair]]\nslave = \"bottom.top\"\nmaster = \"top.bottom\"\n");
    let (line, message, _) = scene_error(parse(&text));
    assert_eq!(line, nth_line_of(&text, "[[contact_pair]]", 1));
    let first = line_of(&text, "[[contact_pair]]");
    assert_eq!(
        message,
        format!("this pair of `bottom.top` and `top.bottom` repeats the [[contact_pair]] of line {first}")
    );
    // Pairs need bodies.
    let text =
        "[mesh]\nshape = \"rectangle\"\nsize = [1.0, 1.0]\ncell_size = 0.5\n[material]\nyoung = 1e9\npoisson = 0.3\n\
                [[contact_pair]]\nslave = \"a.b\"\nmaster = \"c.d\"\n";
    let (line, message, _) = scene_error(parse(text));
    assert_eq!((line, message.as_str()), (8, "a [[contact_pair]] needs bodies, but the scene has no [[body]] tables"));
}

// ---- the model: meshes, parts, union, overlaps ---------------------------------------------------

#[test]
fn the_union_of_two_blocks_keeps_each_body_apart() {
    let s = parse(TWO).unwrap();
    let model = BodiesModel::build(&s).unwrap();
    // top: 4 x 2 cells of 0.25, bottom: 4 x 2 cells of 0.5, two triangles per cell.
    assert_eq!(model.body_meshes[0].num_cells(), 16);
    assert_eq!(model.body_meshes[1].num_cells(), 16);
    assert_eq!(model.mesh.num_nodes(), 15 + 15);
    assert_eq!(model.mesh.num_cells(), 32);
    let (top, bottom) = (&model.layout.bodies[0], &model.layout.bodies[1]);
    assert_eq!((top.nodes.clone(), bottom.nodes.clone()), (0..15, 15..30));
    assert_eq!(bottom.dofs(), 30..60);
    assert_eq!((top.cells.clone(), bottom.cells.clone()), (0..16, 16..32));
    assert_eq!(model.layout.cell_body[15..17], [0, 1]);
    assert_eq!(model.material_of_cell(20).young, 2e9);
    assert_eq!(model.material_of_cell(3).young, 1e9);
    for name in ["top.bottom", "top.top", "top.left", "top.right", "bottom.top", "bottom.bottom", "top.domain"] {
        assert!(model.mesh.groups.iter().any(|g| g.name == name), "{name}");
    }
    let slave = model.part_group(&s.contact_pairs[0].slave).unwrap();
    let edges: Vec<usize> = model.mesh.edges_in_group(slave).collect();
    assert_eq!(edges.len(), 4);
    assert!(edges.iter().all(|&e| top.edges.contains(&e)));
    assert!(model.mesh.edges_in_group(slave).all(|e| model
        .mesh
        .edge(e)
        .iter()
        .all(|&k| model.mesh.nodes[k][1] == 1.0)));
    let master = model.part_group(&s.contact_pairs[0].master).unwrap();
    assert!(model.mesh.edges_in_group(master).all(|e| model.mesh.edge(e).iter().all(|&k| bottom.nodes.contains(&k))));
}

#[test]
fn a_placed_body_is_rotated_then_translated() {
    // The bottom block turned a quarter turn about (0, 0) then moved: [-1, 0] x [0, 2] -> [1, 2] x [-1, 1].
    let text = two_with("name = \"bottom\"", "name = \"bottom\"\nrotate = 90.0\ntranslate = [2.0, -1.0]");
    let text = text.edit("origin = [0.0, 1.0]", "origin = [1.0, 1.0]");
    let model = BodiesModel::build(&parse(&text).unwrap()).unwrap();
    let m = &model.body_meshes[1];
    let (lo, hi) = m.nodes.iter().fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), p| {
        ([lo[0].min(p[0]), lo[1].min(p[1])], [hi[0].max(p[0]), hi[1].max(p[1])])
    });
    assert_eq!((lo, hi), ([1.0, -1.0], [2.0, 1.0]));
    // Still counter-clockwise, with the body on the left of its boundary edges.
    let mut union = model.mesh.clone();
    union.validate().unwrap();
    // The mesh's part "top" (y = 1 before) is now the face x = 1.
    let top = union.group_index("bottom.top", 1).unwrap();
    assert!(union.edges_in_group(top).all(|e| union.edge(e).iter().all(|&k| union.nodes[k][0] == 1.0)));
}

#[test]
fn unknown_parts_are_found_once_the_meshes_exist() {
    let text = two_with("master = \"bottom.top\"", "master = \"bottom.circle\"");
    let s = parse(&text).unwrap();
    let (line, message, hint) = scene_error(BodiesModel::build(&s));
    assert_eq!(line, line_of(&text, "bottom.circle"));
    assert_eq!(message, "the mesh of body `bottom` has no boundary part named `circle`");
    assert!(hint.contains("body `bottom`'s boundary parts are: bottom, right, top, left"), "{hint}");
    // A body's own load on a part its mesh lacks.
    let text = two_with("part = \"top\"\npressure", "part = \"arc\"\npressure");
    let (line, message, _) = scene_error(BodiesModel::build(&parse(&text).unwrap()));
    assert_eq!(
        (line, message.as_str()),
        (line_of(&text, "part = \"arc\""), "the mesh has no boundary part named `arc`")
    );
    // A point condition is checked on the placed mesh.
    let text = two_with("part = \"left\"\nux", "point = [0.1, 1.0]\nux");
    let (line, message, _) = scene_error(BodiesModel::build(&parse(&text).unwrap()));
    assert_eq!(line, line_of(&text, "point = [0.1, 1.0]"));
    assert!(message.starts_with("the mesh has no node at point [0.1, 1]"), "{message}");
    // [1, 2] x [0, 0.5] moved to [0, 1] x [1, 1.5]: its corner (0, 1) is a node once placed.
    let text = two_with("part = \"left\"\nux", "point = [0.0, 1.0]\nux")
        .edit("origin = [0.0, 1.0]", "origin = [1.0, 0.0]")
        .edit("name = \"top\"", "name = \"top\"\ntranslate = [-1.0, 1.0]");
    BodiesModel::build(&parse(&text).unwrap()).unwrap();
}

#[test]
fn overlapping_blocks_are_refused_unless_the_overlap_is_stated() {
    // The top block 0.1 into the bottom one.
    let text = two_with("origin = [0.0, 1.0]", "origin = [0.0, 0.9]");
    let (line, message, hint) = scene_error(BodiesModel::build(&parse(&text).unwrap()));
    assert_eq!(line, line_of(&text, "[[contact_pair]]"));
    assert!(message.starts_with("bodies `top` and `bottom` overlap: the node of "), "{message}");
    assert!(message.contains("is 1.000e-1 inside"), "{message}");
    assert!(hint.contains("max_initial_overlap"), "{hint}");
    let stated = text.edit("mu = 0.3", "mu = 0.3\nmax_initial_overlap = 0.1");
    BodiesModel::build(&parse(&stated).unwrap()).unwrap();
    let too_small = text.edit("mu = 0.3", "mu = 0.3\nmax_initial_overlap = 0.05");
    let (_, message, _) = scene_error(BodiesModel::build(&parse(&too_small).unwrap()));
    assert!(message.contains("more than the accepted initial overlap of this [[contact_pair]], 5.000e-2"), "{message}");
    // Bodies joined by no pair get the default tolerance, located at the later body.
    let unpaired = text[..text.find("[[contact_pair]]").unwrap()].to_string();
    let (line, message, _) = scene_error(BodiesModel::build(&parse(&unpaired).unwrap()));
    assert_eq!(line, line_of(&unpaired, "name = \"bottom\""));
    assert!(message.contains("the default accepted overlap (no [[contact_pair]] joins them)"), "{message}");
}

/// Two discs of radius 1 at distance `d` between centres, a frictionless pair.
fn two_discs(d: f64, extra: &str) -> String {
    format!(
        "[[body]]\nname = \"left\"\nmesh = {{ shape = \"disc\", center = [0.0, 0.0], radius = 1.0, cell_size = 0.25 }}\n\
         material = {{ young = 1e9, poisson = 0.3 }}\n\
         [[body]]\nname = \"right\"\nmesh = {{ shape = \"disc\", center = [{d}, 0.0], radius = 1.0, cell_size = 0.25 }}\n\
         material = {{ young = 1e9, poisson = 0.3 }}\n\
         [[contact_pair]]\nslave = \"left.circle\"\nmaster = \"right.circle\"\n{extra}"
    )
}

#[test]
fn overlapping_discs_are_found_and_touching_ones_pass() {
    let text = two_discs(1.5, "");
    let (line, message, _) = scene_error(BodiesModel::build(&parse(&text).unwrap()));
    assert_eq!(line, line_of(&text, "[[contact_pair]]"));
    // The deepest node is the tip of a diameter: (1, 0) in `right`, or (0.5, 0) in `left`, 0.5 deep.
    assert!(message.starts_with("bodies `left` and `right` overlap: the node of `"), "{message}");
    // The deepest node is the tip of a diameter: (1, 0) in `right` or (0.5, 0) in `left`, about
    // 0.5 deep (the polygon of the meshed disc is a little inside the circle).
    assert!(message.contains("` at [1, 0] is 4.9") || message.contains("` at [0.5, 0] is 4.9"), "{message}");
    // Touching at (1, 0): both discs have a node there; their polygons only touch.
    let model = BodiesModel::build(&parse(&two_discs(2.0, "")).unwrap()).unwrap();
    assert_eq!(model.layout.bodies.len(), 2);
    assert_eq!(model.mesh.num_nodes(), model.body_meshes[0].num_nodes() + model.body_meshes[1].num_nodes());
    assert!(model.mesh.group_index("right.circle", 1).is_some());
}

/// Two bars of width 0.1 crossing like a plus sign, 2 cells along each (cells of 1.1 x 0.1):
/// no node of one is inside the other, only their sides cross. `up_origin_y` moves the
/// vertical bar (−1: centred on the horizontal one; 0.05: standing on it, a T).
fn plus_sign(order: u8, up_origin_y: f64) -> String {
    format!(
        "[[body]]\nname = \"across\"\nmesh = {{ shape = \"rectangle\", origin = [-1.0, -0.05], size = [2.2, 0.1], cell_size = 1.1 }}\n\
         discretization = {{ order = {order} }}\nmaterial = {{ young = 1e9, poisson = 0.3 }}\n\
         [[body.dirichlet]]\npart = \"left\"\nux = 0.0\nuy = 0.0\n\
         [[body]]\nname = \"up\"\nmesh = {{ shape = \"rectangle\", origin = [-0.05, {up_origin_y}], size = [0.1, 2.2], cell_size = 1.1 }}\n\
         discretization = {{ order = {order} }}\nmaterial = {{ young = 1e9, poisson = 0.3 }}\n\
         [[body.dirichlet]]\npart = \"top\"\nux = 0.0\nuy = 0.0\n"
    )
}

#[test]
fn bars_crossing_like_a_plus_sign_are_refused_and_a_t_passes() {
    for order in [1, 2] {
        let text = plus_sign(order, -1.0);
        let s = parse(&text).unwrap();
        // No node of either bar is inside the other: the meshes of the bars apart (`up` 6
        // higher), each node against the other bar's rectangle where the scene puts it.
        let apart = BodiesModel::build(&parse(&plus_sign(order, 5.0)).unwrap()).unwrap();
        let in_box =
            |p: [f64; 2], lo: [f64; 2], hi: [f64; 2]| p[0] > lo[0] && p[0] < hi[0] && p[1] > lo[1] && p[1] < hi[1];
        assert!(apart.body_meshes[0].nodes.iter().all(|&p| !in_box(p, [-0.05, -1.0], [0.05, 1.2])));
        assert!(apart.body_meshes[1].nodes.iter().all(|&p| !in_box([p[0], p[1] - 6.0], [-1.0, -0.05], [1.2, 0.05])));
        let (line, message, hint) = scene_error(BodiesModel::build(&s));
        assert_eq!(line, line_of(&text, "name = \"up\""), "P{order}");
        assert!(message.starts_with("bodies `across` and `up` overlap: their boundaries cross at ["), "{message}");
        // The deepest point of a side inside the other bar: its middle, 0.05 from the other's sides.
        assert!(message.contains("is 5.000e-2 inside"), "{message}");
        assert!(message.contains("more than the default accepted overlap"), "{message}");
        assert!(hint.contains("max_initial_overlap"), "{hint}");
        // Standing on it (a T): touching along the top side, accepted.
        BodiesModel::build(&parse(&plus_sign(order, 0.05)).unwrap()).unwrap();
    }
}

#[test]
fn the_example_scenes_make_non_overlapping_unions() {
    let s = Scene::from_file(&examples().join("block_on_block.toml")).unwrap();
    let model = BodiesModel::build(&s).unwrap();
    // block: 32 x 32 cells, foundation: 32 x 8 cells.
    assert_eq!(model.layout.bodies[0].nodes.len(), 33 * 33);
    assert_eq!(model.layout.bodies[1].nodes.len(), 33 * 9);
    assert_eq!(model.mesh.num_cells(), 2 * 32 * 32 + 2 * 32 * 8);
    assert_eq!(model.layout.cell_body.iter().filter(|&&b| b == 1).count(), 2 * 32 * 8);
    assert!(
        model.mesh.group_index("foundation.top", 1).is_some() && model.mesh.group_index("block.bottom", 1).is_some()
    );

    let s = Scene::from_file(&examples().join("two_cylinders.toml")).unwrap();
    let model = BodiesModel::build(&s).unwrap();
    assert_eq!(model.mesh.order, Order::P2);
    let (upper, lower) = (&model.layout.bodies[0], &model.layout.bodies[1]);
    assert!(model.mesh.nodes[upper.nodes.clone()].iter().all(|p| p[1] >= -1e-12));
    assert!(model.mesh.nodes[lower.nodes.clone()].iter().all(|p| p[1] <= 1e-12 && p[1] >= -0.1 - 1e-12));
    // Both arcs have a node at the initial contact point; the lower flat side is at y = -0.1.
    for body in [upper, lower] {
        assert!(model.mesh.nodes[body.nodes.clone()].iter().any(|p| p[0].abs() < 1e-12 && p[1].abs() < 1e-12));
    }
    let flat = model.mesh.group_index("lower.flat", 1).unwrap();
    assert!(model.mesh.edges_in_group(flat).all(|e| model
        .mesh
        .edge(e)
        .iter()
        .all(|&k| (model.mesh.nodes[k][1] + 0.1).abs() < 1e-12)));
    let mut union = model.mesh.clone();
    union.validate().unwrap();
}

#[test]
fn the_documented_example_is_valid() {
    let doc = std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/scene-format.md")).unwrap();
    let section = &doc[doc.find("## Several bodies").unwrap()..];
    let start = section.find("```toml\n").unwrap() + "```toml\n".len();
    let text = &section[start..start + section[start..].find("```").unwrap()];
    let s = parse(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(s.bodies.len(), 2);
    assert_eq!(s.bodies[0].body_force, [0.0, -7.7e4]);
    assert_eq!(s.contact_pairs[0].max_initial_overlap, Some(1e-9));
    let model = BodiesModel::build(&s).unwrap();
    assert_eq!(model.layout.bodies[1].name, "foundation");
}

#[test]
fn each_body_gets_the_single_body_checks_of_its_loads() {
    // A traction whose energy overflows, on the second body, is refused at its line.
    let text = two_with(
        "[[body.dirichlet]]\npart = \"bottom\"",
        "[[body.traction]]\npart = \"right\"\ntraction = [1e200, 0.0]\n\n[[body.dirichlet]]\npart = \"bottom\"",
    );
    let (line, message, _) = scene_error(BodiesModel::build(&parse(&text).unwrap()));
    assert_eq!(line, line_of(&text, "part = \"right\""));
    assert!(message.contains("would overflow"), "{message}");
}

#[test]
fn the_not_solved_error_says_how_many_bodies_and_pairs() {
    let e = Error::SeveralBodiesNotSolved { scene: "s.toml".into(), bodies: 1, pairs: 0 };
    let shown = e.to_string();
    assert!(
        shown.starts_with(
            "s.toml: this scene has 1 body and 0 contact pairs: several bodies are parsed and checked but not solved \
             yet in this version by this command or formulation (export, adapt, study, the dual formulation and the \
             estimate take one body)\n  hint: "
        ),
        "{shown}"
    );
    assert!(shown.contains("`signorini run` solves it"), "{shown}");
}

// ---------------------------------------------------------------------------------------------
// Several bodies built in Rust, and materials per cell.
// ---------------------------------------------------------------------------------------------

#[test]
fn bodies_builder_gives_the_scene_a_file_gives() {
    use signorini::scene::{BodiesBuilder, SceneBuilder};
    let top = SceneBuilder::rectangle([0.0, 1.0], [1.0, 0.5], 0.25)
        .material(1e9, 0.3)
        .pressure("top", 1e6)
        .dirichlet_point([0.0, 1.5], Some(0.0), None)
        .build()
        .unwrap();
    let bottom = SceneBuilder::rectangle([-0.5, 0.0], [2.0, 1.0], 0.3)
        .material(2e9, 0.25)
        .dirichlet("bottom", Some(0.0), Some(0.0))
        .build()
        .unwrap();
    let scene = BodiesBuilder::new("two blocks in Rust")
        .body("top", top)
        .body("bottom", bottom)
        .pair("top.bottom", "bottom.top", FrictionSpec::Coulomb { mu: 0.3 })
        .build()
        .unwrap();
    // The same scene written as a file: the same scene (compared through its complete TOML
    // serialisation, which both parse back to).
    let file = parse(
        r#"title = "two blocks in Rust"

[[body]]
name = "top"
mesh = { shape = "rectangle", origin = [0.0, 1.0], size = [1.0, 0.5], cell_size = 0.25 }
material = { young = 1e9, poisson = 0.3 }

[[body.traction]]
part = "top"
pressure = 1e6

[[body.dirichlet]]
point = [0.0, 1.5]
ux = 0.0

[[body]]
name = "bottom"
mesh = { shape = "rectangle", origin = [-0.5, 0.0], size = [2.0, 1.0], cell_size = 0.3 }
material = { young = 2e9, poisson = 0.25 }

[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0

[[contact_pair]]
slave = "top.bottom"
master = "bottom.top"
friction = "coulomb"
mu = 0.3
"#,
    )
    .unwrap();
    assert_eq!(scene.to_toml(), file.to_toml());
    assert_eq!(parse(&scene.to_toml()).unwrap().to_toml(), file.to_toml());
    assert_eq!(scene.bodies.len(), 2);
    assert_eq!(scene.bodies[1].name, "bottom");
    assert_eq!(scene.bodies[1].material.young, 2e9);
    assert_eq!(scene.contact_pairs[0].slave.to_string(), "top.bottom");
    assert_eq!(scene.contact_pairs[0].friction, FrictionSpec::Coulomb { mu: 0.3 });
    let model = BodiesModel::build(&scene).unwrap();
    assert!(model.part_group(&scene.contact_pairs[0].master).is_some());
    // A mistake is reported as in a file, at the scene built in Rust.
    let err = BodiesBuilder::new("bad")
        .body("top", SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.5).material(1e9, 0.3).build().unwrap())
        .body("other", SceneBuilder::rectangle([0.0, 2.0], [1.0, 1.0], 0.5).material(1e9, 0.3).build().unwrap())
        .pair("top.bottom", "nobody.top", FrictionSpec::None)
        .build()
        .unwrap_err();
    assert!(matches!(&err, Error::Scene { message, .. } if message.contains("nobody")), "{err}");
    // No body at all.
    let err = BodiesBuilder::new("empty").build().unwrap_err();
    assert!(matches!(&err, Error::Usage(m) if m.contains("no body")), "{err}");
}

#[test]
fn materials_per_cell_are_checked_and_assemble_per_body() {
    use signorini::fem::assembly::{assemble_cells, Constraints, Loads};
    use signorini::fem::{CellMaterials, Element, Material, PlaneModel};
    let soft = Material::new(1e9, 0.3, PlaneModel::Strain);
    let hard = Material::new(5e9, 0.3, PlaneModel::Strain);
    assert!(matches!(CellMaterials::per_cell(vec![], vec![]), Err(Error::Usage(_))));
    assert!(matches!(CellMaterials::per_cell(vec![soft], vec![0, 1]), Err(Error::Usage(m)) if m.contains("cell 1")));
    // Two identical blocks side by side but apart: with materials (soft, hard), each body's
    // stiffness is its material's, so the hard block's entries are 5 times the soft one's.
    let scene = parse(TWO).unwrap();
    let model = BodiesModel::build(&scene).unwrap();
    let cells = model.layout.cell_body.clone();
    let materials = CellMaterials::per_cell(vec![soft, hard], cells).unwrap();
    let uniform = CellMaterials::uniform(soft);
    let loads = Loads { body_force: None, edge_loads: Vec::new() };
    let free = Constraints::new(2 * model.mesh.num_nodes());
    let all = 0..2 * model.mesh.num_nodes();
    let a = assemble_cells(&model.mesh, &materials, Element::Lagrange, &free, &loads, all.clone());
    let b = assemble_cells(&model.mesh, &uniform, Element::Lagrange, &free, &loads, all);
    let second = model.layout.bodies[1].dofs();
    for row in 0..2 * model.mesh.num_nodes() {
        let ratio = if second.contains(&row) { 5.0 } else { 1.0 };
        let (cols, va) = a.matrix.row(row);
        let (_, vb) = b.matrix.row(row);
        for k in 0..cols.len() {
            assert!((va[k] - ratio * vb[k]).abs() <= 1e-9 * vb[k].abs().max(1.0), "row {row}");
        }
    }
}
