//! The element, formulation, estimate and dual-constraint keys, and scenes built in Rust checked like files.

use crate::{base_with, line_of, parse, scene_error, BASE};
use signorini::error::Error;
use signorini::scene::Scene;
use std::path::Path;

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
