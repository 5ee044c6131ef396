//! Mesh files resolved against the scene's directory, and boundary parts checked against a mesh.

use crate::{base_with, examples, line_of, parse, scene_error, two_triangles, BASE};
use signorini::error::{Error, Location};
use signorini::mesh::{PhysicalGroup, NO_GROUP};
use signorini::scene::{MeshSpec, Scene};
use std::path::Path;

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

// ---- boundary parts against a mesh -----------------------------------------------------------

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
