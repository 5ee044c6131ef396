//! The `[contact]` table: obstacles, friction laws, solvers and the checks on each key.

use crate::edit::Edit;

use crate::{line_contact, line_of, parse, scene_error, two_triangles, with_contact, BASE};
use signorini::error::Error;
use signorini::scene::{ContactSolverSpec, FrictionSpec, ObstacleSpec};
use std::path::Path;

// ---- [contact] -------------------------------------------------------------------------------

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
    let text = line_contact("").edit("normal = [0.0, 1.0]", "normal = [3, -4]");
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
    let text = line_contact("").edit("obstacle = \"line\"", "obstacle = \"plane\"");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "obstacle"), "obstacle = ".len() + 1));
    assert!(e.message.contains("obstacle") && e.message.contains("\"plane\""), "{}", e.message);
    assert!(e.hint.contains("\"line\", \"circle\", \"polyline\""), "{}", e.hint);
    let e = scene_error(&line_contact("").edit("obstacle = \"line\"", "obstacle = \"circel\""));
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
    let text = line_contact("").edit("part = \"bottom\"\n", "");
    let e = scene_error(&text);
    assert_eq!((e.line, e.column), (line_of(&text, "[contact]"), 1));
    assert!(e.message.contains("[contact]") && e.message.contains("`part`"), "{}", e.message);
    assert!(e.hint.contains("part = \"bottom\""), "{}", e.hint);

    let text = with_contact("part = \"bottom\"\n");
    let e = scene_error(&text);
    assert_eq!(e.line, line_of(&text, "[contact]"));
    assert!(e.message.contains("`obstacle`"), "{}", e.message);
    assert!(e.hint.contains("obstacle = \"line\""), "{}", e.hint);

    let text = line_contact("").edit("normal = [0.0, 1.0]\n", "");
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
        let text = line_contact("").edit("normal = [0.0, 1.0]", &format!("normal = {bad}"));
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
    let text = line_contact("").edit("part = \"bottom\"\nobstacle", "part = \"left\"\nobstacle");
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
    let text = line_contact("").edit("part = \"bottom\"", "part = \"botom\"");
    let scene = parse(&text).unwrap();
    match scene.check_against_mesh(&two_triangles()) {
        Err(Error::Scene { location, message, hint }) => {
            assert_eq!((location.line, location.column), (line_of(&text, "botom"), "part = ".len() + 1));
            assert!(message.contains("`botom`"), "{message}");
            assert!(hint.contains("did you mean `bottom`?"), "{hint}");
        }
        other => panic!("{other:?}"),
    }
    let text = line_contact("").edit("part = \"bottom\"", "part = \"domain\"");
    let e = parse(&text).unwrap().check_against_mesh(&two_triangles()).unwrap_err();
    let Error::Scene { location, message, .. } = e else { panic!("{e:?}") };
    assert_eq!(location.line, line_of(&text, "domain"));
    assert!(message.contains("region"), "{message}");
    parse(&line_contact("")).unwrap().check_against_mesh(&two_triangles()).unwrap();
}
