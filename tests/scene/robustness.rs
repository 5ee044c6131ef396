//! No input panics: prefixes, scenes missing a line and odd tables give a scene or an `Error::Scene`.

use crate::{examples, parse, with_contact};
use signorini::error::Error;

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
