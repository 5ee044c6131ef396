//! The scene format: the example scenes parse to what they say, and every mistake is an
//! `Error::Scene` at the right line, naming the key or value, never a panic.
#[path = "../common/edit.rs"]
mod edit;

mod builder;
mod contact;
mod element_and_formulation;
mod evolution;
mod examples;
mod interface;
mod mesh_parts;
mod obstacles;
mod point_dirichlet;
mod robustness;
mod syntax_and_keys;
mod values;

use signorini::error::{Error, Location};
use signorini::mesh::{Mesh, Order, PhysicalGroup};
use signorini::scene::{DirichletTarget, Scene};
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
        measure: Default::default(),
    }
}

const LINE: &str = "part = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n";

/// BASE with a [contact] table whose keys are `body`.
fn with_contact(body: &str) -> String {
    format!("{BASE}\n[contact]\n{body}")
}

/// BASE with the line obstacle and `extra` keys.
fn line_contact(extra: &str) -> String {
    with_contact(&format!("{LINE}{extra}\n"))
}
