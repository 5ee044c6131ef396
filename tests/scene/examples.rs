//! The example scenes and the TOML blocks of docs/scene-format.md parse to what they say.

use crate::{examples, line_of, parse, part, BASE};
use signorini::error::Error;
use signorini::mesh::structured::cells_for_size;
use signorini::mesh::Order;
use signorini::scene::{
    nearest_node, ContactSolverSpec, DirichletTarget, FrictionSpec, Load, MaterialSpec, MeshSpec, Mesher, ObstacleSpec,
    PlaneSpec, RefineSpec, Scene, DEFAULT_SCENE_SOURCE, DEFAULT_SCENE_TOML,
};
use std::path::{Path, PathBuf};

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
            MeshSpec::QuarterDisc { .. } => &["arc", "flat", "axis"],
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
