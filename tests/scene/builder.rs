//! `SceneBuilder` and `BodiesBuilder`: every call gives the scene its scene-file key gives
//! (the oracle is hand-written scene text read by `Scene::from_str`), the calls may come in any
//! order, a call that would be ignored is refused, and a mistake names the builder call.
use super::*;
use signorini::fem::Element;
use signorini::scene::{
    BodiesBuilder, ContactSolverSpec, DualConstraints, Formulation, FrictionSpec, MeshSpec, Mesher, ObstacleSpec,
    PlaneSpec, SceneBuilder, BUILT_IN_RUST,
};

/// The built scene is the scene of `text`: the same scene text, and (the oracle's own reading)
/// the same mesh, material and contact.
#[track_caller]
fn same_scene(built: signorini::Result<Scene>, text: &str) -> Scene {
    let built = built.unwrap_or_else(|e| panic!("the builder refused a valid scene: {e}"));
    let read = parse(text).unwrap_or_else(|e| panic!("test bug, the text is not a valid scene: {e}\n{text}"));
    assert_eq!(built.to_toml(), read.to_toml());
    assert_eq!(built.mesh, read.mesh);
    assert_eq!(built.material, read.material);
    assert_eq!(
        built.contact.as_ref().map(|c| (&c.obstacle, c.gap, c.friction, c.solver)),
        read.contact.as_ref().map(|c| (&c.obstacle, c.gap, c.friction, c.solver))
    );
    assert_eq!(built.source, Path::new(BUILT_IN_RUST));
    built
}

#[test]
fn rectangle_calls_give_the_keys_of_a_file() {
    let built = SceneBuilder::rectangle([1.0, -1.0], [2.0, 0.5], 0.1)
        .title("all the single-body keys")
        .gmsh()
        .refine([2.0, -1.0], 0.02, 0.3)
        .material(70e9, 0.25)
        .plane_stress()
        .body_force([0.0, -2.7e4])
        .traction("right", [1e5, 0.0])
        .pressure("top", 2e6)
        .traction("top", [0.0, -1.0])
        .dirichlet("left", Some(0.0), None)
        .dirichlet_point([1.0, -1.0], None, Some(0.0))
        .formulation(Formulation::Dual)
        .dual_constraints(DualConstraints::Multipliers)
        .estimate()
        .petsc_options("-ksp_type cg")
        .petsc_options("-pc_type gamg")
        .output_dir("out/rect")
        .build();
    let text = r#"
title = "all the single-body keys"
[mesh]
shape = "rectangle"
origin = [1.0, -1.0]
size = [2.0, 0.5]
cell_size = 0.1
mesher = "gmsh"
refine = { point = [2.0, -1.0], cell_size = 0.02, radius = 0.3 }
[discretization]
formulation = "dual"
dual_constraints = "multipliers"
[material]
young = 70e9
poisson = 0.25
plane = "stress"
[loads]
body_force = [0.0, -2.7e4]
[[traction]]
part = "right"
traction = [1e5, 0.0]
[[traction]]
part = "top"
pressure = 2e6
[[traction]]
part = "top"
traction = [0.0, -1.0]
[[dirichlet]]
part = "left"
ux = 0.0
[[dirichlet]]
point = [1.0, -1.0]
uy = 0.0
[estimate]
[solver]
petsc_options = "-ksp_type cg -pc_type gamg"
[output]
dir = "out/rect"
"#;
    let s = same_scene(built, text);
    assert!(matches!(s.mesh, MeshSpec::Rectangle { mesher: Mesher::Gmsh, refine: Some(_), .. }));
    assert_eq!(s.material.plane, PlaneSpec::Stress);
    assert_eq!(
        (s.formulation, s.dual_constraints, s.estimate),
        (Formulation::Dual, DualConstraints::Multipliers, true)
    );
    assert_eq!(s.petsc_options, ["-ksp_type", "cg", "-pc_type", "gamg"]);
    assert_eq!(s.tractions.len(), 3);
    assert_eq!(s.dirichlet.len(), 2);
}

#[test]
fn disc_half_disc_and_obstacle_calls_give_the_keys_of_a_file() {
    // A disc on a rigid roller: P2–P0, Coulomb, the condensed Newton with its tolerances.
    let built = SceneBuilder::disc([0.0, 1.0], 1.0, 0.2)
        .refine([0.0, 0.0], 0.05, 0.3)
        .quadratic()
        .p2p0()
        .material(1e7, 0.4999)
        .pressure("circle", 1e4)
        .dirichlet_point([0.0, 2.0], Some(0.0), None)
        .contact_circle("circle", [0.0, -2.0], 2.0)
        .gap(-1e-4)
        .coulomb(0.4)
        .contact_solver(ContactSolverSpec::Newton)
        .contact_tolerance(1e-10)
        .contact_max_iterations(50)
        .build();
    let text = r#"
[mesh]
shape = "disc"
center = [0.0, 1.0]
radius = 1.0
cell_size = 0.2
refine = { point = [0.0, 0.0], cell_size = 0.05, radius = 0.3 }
[discretization]
order = 2
element = "p2p0"
[material]
young = 1e7
poisson = 0.4999
[[traction]]
part = "circle"
pressure = 1e4
[[dirichlet]]
point = [0.0, 2.0]
ux = 0.0
[contact]
part = "circle"
obstacle = "circle"
center = [0.0, -2.0]
radius = 2.0
gap = -1e-4
friction = "coulomb"
mu = 0.4
solver = "newton"
tolerance = 1e-10
max_iterations = 50
"#;
    let s = same_scene(built, text);
    assert_eq!((s.order, s.element), (Order::P2, Element::P2P0));
    let c = s.contact.unwrap();
    assert_eq!((c.tolerance, c.max_iterations), (Some(1e-10), Some(50)));

    // A half disc on a line, Tresca, relaxation with its ω.
    let built = SceneBuilder::half_disc([0.0, 0.5], 0.5, 0.1)
        .material(210e9, 0.3)
        .pressure("flat", 1e6)
        .contact_line("arc", [0.0, 0.0], [0.0, 2.0])
        .tresca(5e5)
        .contact_solver(ContactSolverSpec::Relaxation { omega: 1.3 })
        .build();
    let text = r#"
[mesh]
shape = "half_disc"
center = [0.0, 0.5]
radius = 0.5
cell_size = 0.1
[material]
young = 210e9
poisson = 0.3
[[traction]]
part = "flat"
pressure = 1e6
[contact]
part = "arc"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 2.0]
friction = "tresca"
threshold = 5e5
solver = "relaxation"
omega = 1.3
"#;
    let s = same_scene(built, text);
    assert_eq!(s.contact.unwrap().solver, ContactSolverSpec::Relaxation { omega: 1.3 });

    // A quarter disc (the meridian section of a hemisphere) on a line, axisymmetric.
    let built = SceneBuilder::quarter_disc([0.0, 0.5], 0.5, 0.1)
        .refine([0.0, 0.0], 0.02, 0.1)
        .material(210e9, 0.3)
        .axisymmetric()
        .pressure("flat", 1e6)
        .contact_line("arc", [0.0, 0.0], [0.0, 1.0])
        .build();
    let text = r#"
[mesh]
shape = "quarter_disc"
center = [0.0, 0.5]
radius = 0.5
cell_size = 0.1
refine = { point = [0.0, 0.0], cell_size = 0.02, radius = 0.1 }
[material]
young = 210e9
poisson = 0.3
plane = "axisymmetric"
[[traction]]
part = "flat"
pressure = 1e6
[contact]
part = "arc"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
"#;
    let s = same_scene(built, text);
    assert!(matches!(s.mesh, MeshSpec::QuarterDisc { radius: 0.5, refine: Some(_), .. }), "{:?}", s.mesh);

    // A rectangle on a polyline valley, frictionless (Coulomb with μ = 0 too, as in a file).
    let valley = [[-1.0, 0.0], [0.5, -0.1], [2.0, 0.0]];
    let text = r#"
[mesh]
shape = "rectangle"
size = [1.0, 0.2]
cell_size = 0.1
[material]
young = 1e9
poisson = 0.3
[[traction]]
part = "top"
pressure = 1e5
[[dirichlet]]
part = "left"
ux = 0.0
[contact]
part = "bottom"
obstacle = "polyline"
points = [[-1.0, 0.0], [0.5, -0.1], [2.0, 0.0]]
solver = "snes_vi"
"#;
    let polyline = || {
        SceneBuilder::rectangle([0.0, 0.0], [1.0, 0.2], 0.1)
            .material(1e9, 0.3)
            .pressure("top", 1e5)
            .dirichlet("left", Some(0.0), None)
            .contact_polyline("bottom", &valley)
            .contact_solver(ContactSolverSpec::SnesVi)
    };
    let s = same_scene(polyline().build(), text);
    assert!(matches!(&s.contact.unwrap().obstacle, ObstacleSpec::Polyline { points } if points.len() == 3));
    same_scene(polyline().coulomb(0.0).build(), text);
}

#[test]
fn mesh_file_calls_give_the_keys_of_a_file() {
    let dir = std::env::temp_dir().join(format!("signorini-builder-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (msh, geo) = (dir.join("part.msh"), dir.join("part.geo"));
    std::fs::write(&msh, "not read by the scene reader").unwrap();
    std::fs::write(&geo, "// not read either").unwrap();
    let text = format!(
        "[mesh]\nshape = \"file\"\nfile = {:?}\ngeometry = {:?}\n[material]\nyoung = 1e9\npoisson = 0.3\n",
        msh.display().to_string(),
        geo.display().to_string()
    );
    same_scene(SceneBuilder::mesh_file_with_geometry(&msh, &geo).material(1e9, 0.3).build(), &text);
    // gmsh() and refine() would be ignored on a file: refused, named.
    for (call, builder) in [
        ("SceneBuilder::gmsh", SceneBuilder::mesh_file(&msh).material(1e9, 0.3).gmsh()),
        ("SceneBuilder::refine", SceneBuilder::mesh_file(&msh).refine([0.0, 0.0], 0.1, 1.0).material(1e9, 0.3)),
    ] {
        let e = builder.build().unwrap_err();
        assert!(
            matches!(&e, Error::Scene { message, .. } if message.starts_with(call) && message.contains("ignored")),
            "{e}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The calls of one scene, each a step; applied in any order they give the same scene.
type Step = fn(SceneBuilder) -> SceneBuilder;

#[test]
fn the_calls_may_come_in_any_order() {
    let steps: Vec<Step> = vec![
        |b| b.coulomb(0.3),
        |b| b.gap(1e-5),
        |b| b.contact_solver(ContactSolverSpec::Uzawa),
        |b| b.contact_tolerance(1e-8),
        |b| b.contact_max_iterations(300),
        |b| b.contact_line("bottom", [0.0, 0.0], [0.0, 1.0]),
        |b| b.refine([0.5, 0.0], 0.02, 0.1),
        |b| b.gmsh(),
        |b| b.quadratic(),
        |b| b.material(1e9, 0.3),
        |b| b.title("order"),
        |b| b.pressure("top", 1e6),
        |b| b.dirichlet_point([0.0, 1.0], Some(0.0), None),
    ];
    let build = |order: &[usize]| {
        let start = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1);
        order.iter().fold(start, |b, &i| steps[i](b)).build().unwrap().to_toml()
    };
    let forward: Vec<usize> = (0..steps.len()).collect();
    let reference = build(&forward);
    // The friction is there, whatever came first (the newcomer's friction #5).
    assert!(reference.contains("friction = \"coulomb\"\nmu = 0.3"), "{reference}");
    let backward: Vec<usize> = forward.iter().rev().copied().collect();
    assert_eq!(build(&backward), reference);
    for shift in 1..steps.len() {
        let rotated: Vec<usize> = (0..steps.len()).map(|i| (i + shift) % steps.len()).collect();
        assert_eq!(build(&rotated), reference, "rotated by {shift}");
    }
}

/// `build()`'s error for a scene built in Rust: at `<scene built in Rust>` without a line.
#[track_caller]
fn builder_error(built: signorini::Result<Scene>) -> (String, String) {
    match built {
        Err(e @ Error::Scene { .. }) => {
            let shown = e.to_string();
            let Error::Scene { location, message, hint } = e else { unreachable!() };
            assert_eq!(location.file, Path::new(BUILT_IN_RUST));
            assert_eq!(location.line, 0);
            assert!(shown.starts_with(&format!("{BUILT_IN_RUST}: {message}")), "{shown}");
            (message, hint)
        }
        other => panic!("expected Error::Scene, got {other:?}"),
    }
}

#[test]
fn a_call_that_would_be_ignored_is_refused() {
    let block = || SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.3);
    // Contact settings without a contact (friction, gap, solver, tolerances): each named.
    for (call, b) in [
        ("SceneBuilder::coulomb", block().coulomb(0.3)),
        ("SceneBuilder::tresca", block().tresca(1e5)),
        ("SceneBuilder::gap", block().gap(0.1)),
        ("SceneBuilder::contact_solver", block().contact_solver(ContactSolverSpec::Newton)),
        ("SceneBuilder::contact_tolerance", block().contact_tolerance(1e-8)),
        ("SceneBuilder::contact_max_iterations", block().contact_max_iterations(5)),
    ] {
        let (message, hint) = builder_error(b.build());
        assert!(message.starts_with(call) && message.contains("no contact"), "{message}");
        assert!(hint.contains("contact_line"), "{hint}");
    }
    // A second call of a setter would replace the first: refused, naming the second.
    for (call, b) in [
        ("SceneBuilder::material", block().material(2e9, 0.3)),
        (
            "SceneBuilder::contact_circle",
            block().contact_line("bottom", [0.0, 0.0], [0.0, 1.0]).contact_circle("bottom", [0.0, -1.0], 1.0),
        ),
        ("SceneBuilder::tresca", block().contact_line("bottom", [0.0, 0.0], [0.0, 1.0]).coulomb(0.3).tresca(1e5)),
        ("SceneBuilder::quadratic", block().quadratic().quadratic()),
        ("SceneBuilder::title", block().title("a").title("b")),
        ("SceneBuilder::axisymmetric", block().plane_stress().axisymmetric()),
    ] {
        let (message, _) = builder_error(b.build());
        assert!(message.starts_with(call) && message.contains("set twice (by SceneBuilder::"), "{call}: {message}");
    }
    // No material at all (it has no default).
    let (message, hint) = builder_error(SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).build());
    assert!(message.contains("SceneBuilder::material was not called") && hint.contains(".material("), "{message}");
}

#[test]
fn a_mistake_names_the_builder_call_and_key() {
    let block = || SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.3);
    // The scene reader's message, after the call and the key, and not a line of generated text.
    let from_file = scene_error(&base_with("poisson = 0.3", "poisson = 0.6"));
    let (message, hint) =
        builder_error(SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.6).build());
    assert_eq!(message, format!("SceneBuilder::material (`poisson = 0.6`): {}", from_file.message));
    assert_eq!(hint, from_file.hint);
    let line = SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.1).material(1e9, 0.6).build().unwrap_err().to_string();
    assert!(line.starts_with("<scene built in Rust>: SceneBuilder::material"), "{line}");
    let contact = || block().contact_line("bottom", [0.0, 0.0], [0.0, 1.0]);
    for (expected, b) in [
        (
            "SceneBuilder::rectangle (`cell_size = -0.1`)",
            SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], -0.1).material(1e9, 0.3),
        ),
        ("SceneBuilder::disc (`radius = 0.0`)", SceneBuilder::disc([0.0, 0.0], 0.0, 0.1).material(1e9, 0.3)),
        (
            "SceneBuilder::quarter_disc (`radius = 0.0`)",
            SceneBuilder::quarter_disc([0.0, 0.0], 0.0, 0.1).material(1e9, 0.3),
        ),
        ("SceneBuilder::refine (`refine = ", block().refine([0.0, 0.0], 0.01, 0.1)),
        ("SceneBuilder::p2p0 (`element = \"p2p0\"`)", block().p2p0()),
        ("SceneBuilder::pressure(\"top\", ..) (`pressure = nan`)", block().pressure("top", f64::NAN)),
        ("SceneBuilder::dirichlet(\"left\", ..)", block().dirichlet("left", None, None)),
        ("SceneBuilder::coulomb (`mu = -0.5`)", contact().coulomb(-0.5)),
        ("SceneBuilder::tresca (`threshold = -1.0`)", contact().tresca(-1.0)),
        ("SceneBuilder::gap (`gap = inf`)", contact().gap(f64::INFINITY)),
        ("SceneBuilder::contact_circle (`radius = -1.0`)", block().contact_circle("bottom", [0.0, -1.0], -1.0)),
        ("SceneBuilder::contact_polyline (`points = [[0.0, 0.0]]`)", block().contact_polyline("bottom", &[[0.0, 0.0]])),
        (
            "SceneBuilder::contact_solver (`omega = 3.0`)",
            contact().contact_solver(ContactSolverSpec::Relaxation { omega: 3.0 }),
        ),
        ("SceneBuilder::contact_solver (`solver = \"tao\"`)", contact().contact_solver(ContactSolverSpec::Tao)),
        ("SceneBuilder::contact_tolerance (`tolerance = 0.5`)", contact().contact_tolerance(0.5)),
        ("SceneBuilder::contact_max_iterations (`max_iterations = 0`)", contact().contact_max_iterations(0)),
        ("SceneBuilder::contact_line (`part = \"\"`)", block().contact_line("", [0.0, 0.0], [0.0, 1.0])),
    ] {
        let (message, _) = builder_error(b.build());
        assert!(message.starts_with(expected), "expected {expected}, got: {message}");
    }
}

#[test]
fn bodies_builder_names_its_calls_and_refuses_what_it_would_ignore() {
    let body = || SceneBuilder::rectangle([0.0, 0.0], [1.0, 1.0], 0.25).material(1e9, 0.3);
    let base = || {
        SceneBuilder::rectangle([0.0, -1.0], [1.0, 1.0], 0.25).material(1e9, 0.3).dirichlet(
            "bottom",
            Some(0.0),
            Some(0.0),
        )
    };
    // The pair with its overlap, the scene-wide settings: the keys of a file.
    let built = BodiesBuilder::new("two")
        .body("top", body().build().unwrap())
        .body("base", base().build().unwrap())
        .pair_with_overlap("top.bottom", "base.top", FrictionSpec::Tresca { threshold: 1e5 }, 1e-3)
        .petsc_options("-contact_snes_monitor")
        .output_dir("out/two")
        .contact_solver(ContactSolverSpec::Newton)
        .build()
        .unwrap();
    let text = r#"
title = "two"
[[body]]
name = "top"
[body.mesh]
shape = "rectangle"
size = [1.0, 1.0]
cell_size = 0.25
[body.material]
young = 1e9
poisson = 0.3
[[body]]
name = "base"
[body.mesh]
shape = "rectangle"
origin = [0.0, -1.0]
size = [1.0, 1.0]
cell_size = 0.25
[body.material]
young = 1e9
poisson = 0.3
[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0
[[contact_pair]]
slave = "top.bottom"
master = "base.top"
friction = "tresca"
threshold = 1e5
max_initial_overlap = 1e-3
[solver]
petsc_options = "-contact_snes_monitor"
[output]
dir = "out/two"
"#;
    assert_eq!(built.to_toml(), parse(text).unwrap().to_toml());
    assert_eq!(built.contact_solver, Some(ContactSolverSpec::Newton));
    // Mistakes name the call.
    let two =
        |name: &str| BodiesBuilder::new("t").body(name, body().build().unwrap()).body("base", base().build().unwrap());
    let (message, _) = builder_error(two("top").pair("top.bottom", "nobody.top", FrictionSpec::None).build());
    assert!(message.starts_with("BodiesBuilder::pair(\"top.bottom\", \"nobody.top\", ..)"), "{message}");
    let (message, _) =
        builder_error(two("top").pair_with_overlap("top.bottom", "base.top", FrictionSpec::None, -1.0).build());
    assert!(message.starts_with("BodiesBuilder::pair_with_overlap(\"top.bottom\", \"base.top\", ..)"), "{message}");
    let (message, _) = builder_error(two("a b").build());
    assert!(message.starts_with("BodiesBuilder::body(\"a b\", ..)"), "{message}");
    // A body's scene-wide setting would be ignored: refused, naming the body and the setting.
    for (what, scene) in [
        ("PETSc options", body().petsc_options("-ksp_type cg").build().unwrap()),
        ("a title", body().title("mine").build().unwrap()),
        ("an output directory", body().output_dir("x").build().unwrap()),
        ("the estimate", body().estimate().build().unwrap()),
        ("several bodies", BodiesBuilder::new("inner").body("x", body().build().unwrap()).build().unwrap()),
    ] {
        let (message, hint) =
            builder_error(BodiesBuilder::new("t").body("top", scene).body("base", base().build().unwrap()).build());
        assert!(message.starts_with("BodiesBuilder::body(\"top\", ..)") && message.contains(what), "{message}");
        assert!(hint.contains("BodiesBuilder"), "{hint}");
    }
}

#[test]
fn axisymmetric_call_gives_the_plane_key() {
    let built = SceneBuilder::rectangle([0.0, 0.0], [1.0, 2.0], 0.5)
        .material(2e11, 0.3)
        .axisymmetric()
        .dirichlet("bottom", None, Some(0.0))
        .build();
    let text = r#"
[mesh]
shape = "rectangle"
origin = [0.0, 0.0]
size = [1.0, 2.0]
cell_size = 0.5
[material]
young = 2e11
poisson = 0.3
plane = "axisymmetric"
[[dirichlet]]
part = "bottom"
uy = 0.0
"#;
    let s = same_scene(built, text);
    assert_eq!(s.material.plane, PlaneSpec::Axisymmetric);
}
