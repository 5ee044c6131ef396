//! TOML-level mistakes, unknown and missing keys: each an `Error::Scene` at the right line.

use crate::edit::Edit;

use crate::{base_with, line_of, scene_error, BASE};

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
    let text = BASE.edit("[material]", "[materials]");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[materials]"), 2));
    assert!(e.message.contains("`materials`") && e.message.contains("top level"), "{}", e.message);
    assert!(e.hint.contains("did you mean `material`?"), "{}", e.hint);

    let text = BASE.edit("[material]", "[contacts]\n[material]");
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
