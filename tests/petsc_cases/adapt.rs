//! Mesh adaptation and the convergence study, end to end (PETSc solves, Gmsh remeshing).

use super::edit::Edit;
use std::path::{Path, PathBuf};

use signorini::adapt::{adapt, study, AdaptOptions, AdaptStatus, StudyOptions};
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;
use signorini::Error;

use super::{ensure, manifest};

/// The clamped block of examples/scenes/clamped_block.toml at another cell size.
fn clamped_block(cell_size: f64) -> Scene {
    let path = manifest("examples/scenes/clamped_block.toml");
    let text = std::fs::read_to_string(&path).unwrap().edit("cell_size = 0.25", &format!("cell_size = {cell_size}"));
    Scene::from_str(&text, &path).unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-petsc-adapt-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The relative estimate of one solve of `scene` on its own mesh, and its element count.
fn uniform_estimate(session: &Session, scene: Scene) -> Result<(f64, usize), Error> {
    let mut p = ElasticityProblem::setup_system(session, scene)?;
    p.assemble()?;
    p.solve()?;
    p.postprocess()?;
    p.solve_dual()?;
    p.estimate()?;
    Ok((p.estimate.as_ref().map_or(f64::NAN, |e| e.estimate.relative_percent), p.mesh.num_cells()))
}

/// The clamped block meshed finely (cell size 0.015) in a disc in the middle of the body,
/// where the error is small, and at 0.1 elsewhere: the error is concentrated at the two
/// singular corners, far from the fine zone. The optimal map coarsens the fine zone (most of
/// the elements) and refines the corners: the element count drops from step 0 to step 1.
pub fn adapt_coarsens_where_the_error_is_small(session: &Session) -> Result<(), String> {
    let path = manifest("examples/scenes/clamped_block.toml");
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .edit("cell_size = 0.25", "cell_size = 0.1\nrefine = { point = [1.0, 0.5], cell_size = 0.015, radius = 0.2 }");
    let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let mut options = AdaptOptions::new(&scene, 8.0);
    options.max_steps = 3;
    let out = scratch("coarsen");
    let outcome = adapt(session, &scene, &options, &out, &mut |_| {}).map_err(|e| e.to_string())?;
    let s = &outcome.steps;
    if std::env::var_os("SIGNORINI_PRINT_RATES").is_some() {
        eprintln!("coarsen: {:?}", s.iter().map(|s| (s.elements, s.error_percent)).collect::<Vec<_>>());
    }
    ensure(s.len() >= 2, || format!("one step only: {:?}", s.iter().map(|s| s.error_percent).collect::<Vec<_>>()))?;
    ensure(s[0].size_map.coarsened > s[0].elements / 2, || {
        format!("map coarsens only {} cells", s[0].size_map.coarsened)
    })?;
    ensure(s[1].elements < s[0].elements, || {
        format!("no coarsening: {} -> {} elements", s[0].elements, s[1].elements)
    })?;
    ensure(outcome.status == AdaptStatus::Reached, || format!("{:?}: {:?}", outcome.status, outcome.warnings))?;
    ensure(out.join("step_1/solution.vtu").is_file() && out.join("step_1/report.json").is_file(), || {
        "step files missing".into()
    })?;
    let _ = std::fs::remove_dir_all(&out);
    Ok(())
}

/// On the block with two corner singularities the adaptive loop's error falls step after step
/// to the target, and the adapted mesh beats a uniform mesh with more elements.
pub fn adapt_error_decreases_at_corner_singularities(session: &Session) -> Result<(), String> {
    let scene = clamped_block(0.25);
    let mut options = AdaptOptions::new(&scene, 4.0);
    options.max_steps = 6;
    let out = scratch("corners");
    let outcome = adapt(session, &scene, &options, &out, &mut |_| {}).map_err(|e| e.to_string())?;
    let errors: Vec<f64> = outcome.steps.iter().map(|s| s.error_percent).collect();
    let elements: Vec<usize> = outcome.steps.iter().map(|s| s.elements).collect();
    if std::env::var_os("SIGNORINI_PRINT_RATES").is_some() {
        eprintln!("adapt: errors {errors:?}, elements {elements:?}");
    }
    ensure(errors.len() >= 2 && errors[1] < 0.5 * errors[0], || format!("errors {errors:?}"))?;
    // The error falls at every step to the target.
    ensure(errors.windows(2).all(|w| w[1] < w[0]), || format!("the error grew at a step: {errors:?}"))?;
    ensure(outcome.reached && *errors.last().unwrap() <= 4.0, || {
        format!("not reached: {errors:?} {:?}", outcome.warnings)
    })?;
    // A uniform mesh with at least as many elements stays well above the adapted error: the
    // corner singularities slow it down.
    let last = outcome.steps.last().unwrap();
    let h = (2.0 / (last.elements as f64 * 3f64.sqrt() / 4.0)).sqrt() * 0.9;
    let (uniform, n) = uniform_estimate(session, clamped_block(h)).map_err(|e| e.to_string())?;
    ensure(n >= last.elements && uniform > 1.15 * last.error_percent, || {
        format!("uniform {uniform:.3} % on {n} elements vs adapted {:.3} % on {}", last.error_percent, last.elements)
    })?;
    let _ = std::fs::remove_dir_all(&out);
    Ok(())
}

/// A target the steps cannot reach is reported as such (status, warning), not as an error.
pub fn adapt_target_not_reached_is_reported(session: &Session) -> Result<(), String> {
    let scene = clamped_block(0.25);
    let mut options = AdaptOptions::new(&scene, 0.5);
    options.max_steps = 2;
    let out = scratch("unreached");
    let outcome = adapt(session, &scene, &options, &out, &mut |_| {}).map_err(|e| e.to_string())?;
    ensure(outcome.status == AdaptStatus::MaxSteps && !outcome.reached, || format!("{:?}", outcome.status))?;
    ensure(outcome.steps.len() == 2, || format!("{} steps", outcome.steps.len()))?;
    ensure(outcome.warnings.iter().any(|w| w.contains("not reached")), || format!("{:?}", outcome.warnings))?;
    // Bad options are refused before anything is solved.
    for (target, steps) in [(0.0, 3), (-1.0, 3), (f64::NAN, 3), (5.0, 0)] {
        let mut bad = AdaptOptions::new(&scene, target);
        bad.max_steps = steps;
        match adapt(session, &scene, &bad, &out, &mut |_| {}) {
            Err(Error::Usage(m)) => ensure(!m.is_empty(), String::new)?,
            other => return Err(format!("target {target}, {steps} steps: {:?}", other.map(|o| o.status))),
        }
    }
    let _ = std::fs::remove_dir_all(&out);
    Ok(())
}

/// P1 on a smooth problem (the clamped square under its weight): the true energy error falls
/// as h (fitted rate within 0.85–1.15) and the estimate matches it (Prager–Synge).
pub fn study_p1_rate_is_one_on_a_smooth_problem(session: &Session) -> Result<(), String> {
    let scene = Scene::from_file(&manifest("examples/scenes/smooth_square.toml")).map_err(|e| e.to_string())?;
    let options = StudyOptions { levels: 3, reference_halvings: 1 };
    let outcome = study(session, &scene, options, &mut |_, _| {}).map_err(|e| e.to_string())?;
    let rate = outcome.rates.displacement.unwrap_or(f64::NAN);
    ensure((0.85..=1.15).contains(&rate), || format!("P1 energy rate {rate:.3}: {:?}", outcome.levels))?;
    let rate = outcome.rates.estimate.unwrap_or(f64::NAN);
    ensure((0.85..=1.15).contains(&rate), || format!("estimate rate {rate:.3}"))?;
    for l in &outcome.levels {
        ensure((0.97..1.1).contains(&l.effectivity), || format!("level {}: effectivity {}", l.level, l.effectivity))?;
        ensure(l.error_stress > 0.0 && l.error_stress < l.error_displacement, || format!("{l:?}"))?;
    }
    ensure(outcome.levels[1].elements == 4 * outcome.levels[0].elements, || "not halved".into())?;
    // Levels 0 and a mesh file are refused.
    let zero = StudyOptions { levels: 0, reference_halvings: 1 };
    ensure(matches!(study(session, &scene, zero, &mut |_, _| {}), Err(Error::Usage(_))), || "levels 0".into())?;
    Ok(())
}

/// A scene whose mesh is a file has no geometry to remesh: NeedsGeometry, for adapt and study.
pub fn adapt_and_study_refuse_mesh_files(session: &Session) -> Result<(), String> {
    let dir = scratch("file");
    std::fs::create_dir_all(&dir).unwrap();
    let scene_path = write_file_scene(&dir);
    let scene = Scene::from_file(&scene_path).map_err(|e| e.to_string())?;
    let options = AdaptOptions::new(&scene, 5.0);
    match adapt(session, &scene, &options, &dir, &mut |_| {}) {
        Err(e @ Error::NeedsGeometry { command: "adapt", .. }) => {
            let m = e.to_string();
            ensure(m.contains("shape = \"file\"") && m.contains("hint"), || m.clone())?;
        }
        other => return Err(format!("adapt on a mesh file: {:?}", other.map(|o| o.status))),
    }
    let options = StudyOptions { levels: 2, reference_halvings: 1 };
    ensure(
        matches!(study(session, &scene, options, &mut |_, _| {}), Err(Error::NeedsGeometry { command: "study", .. })),
        || "study on a mesh file".into(),
    )?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// A mesh file with the Gmsh script it was made from (`geometry = "…"`): adapt remeshes the
/// script's geometry with the size map, P2, and the mid nodes of the new boundary edges lie on
/// the script's circle arc (a quarter disc of radius 1 clamped on one straight side, pulled on
/// the other); a script without one of the scene's parts stops the loop at the first remesh
/// with the steps before it kept (status Failed, the error naming the part); study still
/// refuses the file.
pub fn adapt_remeshes_a_mesh_file_from_its_geometry_script(session: &Session) -> Result<(), String> {
    let dir = scratch("file-geometry");
    std::fs::create_dir_all(&dir).unwrap();
    let script = "SetFactory(\"Built-in\");\nPoint(1) = {0, 0, 0, 0.3};\nPoint(2) = {1, 0, 0, 0.3};\n\
                  Point(3) = {0, 1, 0, 0.3};\nLine(1) = {1, 2};\nCircle(2) = {2, 1, 3};\nLine(3) = {3, 1};\n\
                  Curve Loop(1) = {1, 2, 3};\nPlane Surface(1) = {1};\nPhysical Curve(\"base\") = {1};\n\
                  Physical Curve(\"arc\") = {2};\nPhysical Curve(\"side\") = {3};\nPhysical Surface(\"domain\") = {1};\n";
    std::fs::write(dir.join("quarter.geo"), script).unwrap();
    let status = std::process::Command::new("gmsh")
        .arg(dir.join("quarter.geo"))
        .args(["-2", "-order", "2", "-format", "msh41", "-v", "0", "-o"])
        .arg(dir.join("quarter.msh"))
        .status()
        .unwrap();
    ensure(status.success(), || "gmsh failed on the quarter disc".into())?;
    let scene_text = "[mesh]\nshape = \"file\"\nfile = \"quarter.msh\"\ngeometry = \"quarter.geo\"\n\n\
                      [discretization]\norder = 2\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n\
                      [[dirichlet]]\npart = \"base\"\nux = 0.0\nuy = 0.0\n\n\
                      [[traction]]\npart = \"side\"\ntraction = [-1e6, 0.0]\n";
    std::fs::write(dir.join("quarter.toml"), scene_text).unwrap();
    let scene = Scene::from_file(&dir.join("quarter.toml")).map_err(|e| e.to_string())?;
    let mut options = AdaptOptions::new(&scene, 0.5);
    options.max_steps = 3;
    let out = dir.join("out");
    let mut checked = Vec::new();
    let arc = |mesh: &signorini::mesh::Mesh| mesh.group_index("arc", 1);
    let outcome = signorini::adapt::adapt_inspecting(session, &scene, &options, &out, &mut |_| {}, &mut |k, p| {
        let mesh = &p.mesh;
        let group = arc(mesh).ok_or_else(|| signorini::Error::Usage(format!("step {k}: no arc group")))?;
        let mut worst = 0.0f64;
        let mut nodes = 0;
        for e in 0..mesh.num_edges() {
            if mesh.edge_group[e] != group {
                continue;
            }
            for &n in mesh.edge(e) {
                worst = worst.max((mesh.nodes[n][0].hypot(mesh.nodes[n][1]) - 1.0).abs());
                nodes += 1;
            }
        }
        checked.push((k, mesh.num_cells(), nodes, worst));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    ensure(outcome.steps.len() >= 2, || format!("one step only: {checked:?}"))?;
    ensure(checked[1].1 != checked[0].1, || format!("step 1 is the file's mesh again: {checked:?}"))?;
    // Gmsh places the arc's nodes on the circle to its own tolerance (parametric evaluation).
    ensure(checked.iter().all(|&(_, _, nodes, worst)| nodes > 0 && worst <= 1e-12), || format!("{checked:?}"))?;
    let errors: Vec<f64> = outcome.steps.iter().map(|s| s.error_percent).collect();
    ensure(errors[1] < errors[0], || format!("errors {errors:?}"))?;
    let options = StudyOptions { levels: 2, reference_halvings: 1 };
    ensure(
        matches!(study(session, &scene, options, &mut |_, _| {}), Err(Error::NeedsGeometry { command: "study", .. })),
        || "study on a mesh file with its geometry".into(),
    )?;
    // A script that lacks one of the scene's parts.
    std::fs::write(dir.join("quarter.geo"), script.edit("Physical Curve(\"side\") = {3};\n", "")).unwrap();
    let scene = Scene::from_file(&dir.join("quarter.toml")).map_err(|e| e.to_string())?;
    // Step 0 (the file's mesh) is kept; step 1's mesh lacks the part: status Failed, the
    // error kept for the caller.
    let outcome =
        adapt(session, &scene, &AdaptOptions::new(&scene, 0.5), &out, &mut |_| {}).map_err(|e| e.to_string())?;
    ensure(
        outcome.status == AdaptStatus::Failed
            && outcome.steps.len() == 1
            && outcome.failure.as_deref().is_some_and(|f| f.starts_with("step 1 failed") && f.contains("`side`"))
            && outcome.error.as_deref().is_some_and(|e| matches!(e, Error::Mesh { .. } | Error::Scene { .. })),
        || format!("{:?} {:?} {:?}", outcome.status, outcome.failure, outcome.error),
    )?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// A scene reading `square.msh` (a Gmsh unit square) beside it.
pub(crate) fn write_file_scene(dir: &Path) -> PathBuf {
    let geo = dir.join("square.geo");
    std::fs::write(
        &geo,
        "Point(1) = {0, 0, 0, 0.5};\nPoint(2) = {1, 0, 0, 0.5};\nPoint(3) = {1, 1, 0, 0.5};\nPoint(4) = {0, 1, 0, 0.5};\n\
         Line(1) = {1, 2};\nLine(2) = {2, 3};\nLine(3) = {3, 4};\nLine(4) = {4, 1};\nCurve Loop(1) = {1, 2, 3, 4};\n\
         Plane Surface(1) = {1};\nPhysical Curve(\"bottom\") = {1};\nPhysical Curve(\"top\") = {3};\n\
         Physical Surface(\"domain\") = {1};\n",
    )
    .unwrap();
    let status = std::process::Command::new("gmsh")
        .arg(&geo)
        .args(["-2", "-format", "msh41", "-v", "0", "-o"])
        .arg(dir.join("square.msh"))
        .status()
        .unwrap();
    assert!(status.success());
    let scene = dir.join("file.toml");
    std::fs::write(
        &scene,
        "[mesh]\nshape = \"file\"\nfile = \"square.msh\"\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n\
         [[dirichlet]]\npart = \"bottom\"\nux = 0.0\nuy = 0.0\n\n[[traction]]\npart = \"top\"\npressure = 1e6\n",
    )
    .unwrap();
    scene
}

/// The flat punch (examples/scenes/flat_punch.toml: an elastic block sticking on a rigid flat,
/// the stress singular at the punch edges, uniform meshes converging as h^0.69): from the
/// scene's 118 elements the loop's error falls at every step to the 1 % target, and the
/// adapted mesh beats a uniform mesh with more elements by over a factor 2 (measured: 7.22,
/// 1.52, 1.06, 0.94 % on 118, 2839, 2127, 2416 elements; uniform cells of 0.025: 2.22 % on
/// 3714 elements). Tresca on a straight obstacle: every estimate is a guaranteed bound.
pub fn adapt_error_decreases_on_the_flat_punch(session: &Session) -> Result<(), String> {
    let path = manifest("examples/scenes/flat_punch.toml");
    let scene = Scene::from_file(&path).map_err(|e| e.to_string())?;
    let mut options = AdaptOptions::new(&scene, 1.0);
    options.max_steps = 6;
    let out = scratch("punch");
    let outcome = adapt(session, &scene, &options, &out, &mut |_| {}).map_err(|e| e.to_string())?;
    let errors: Vec<f64> = outcome.steps.iter().map(|s| s.error_percent).collect();
    let elements: Vec<usize> = outcome.steps.iter().map(|s| s.elements).collect();
    if std::env::var_os("SIGNORINI_PRINT_RATES").is_some() {
        eprintln!("punch: errors {errors:?}, elements {elements:?}");
    }
    ensure(errors.len() >= 2 && errors.windows(2).all(|w| w[1] < w[0]), || format!("errors {errors:?}"))?;
    ensure(errors[1] < 0.5 * errors[0], || format!("errors {errors:?}"))?;
    ensure(outcome.reached, || format!("not reached: {errors:?} {:?}", outcome.warnings))?;
    ensure(outcome.steps.iter().all(|s| s.kind == signorini::estimate::EstimateKind::GuaranteedBound), || {
        "Tresca: the estimate must be a guaranteed bound".into()
    })?;
    let last = outcome.steps.last().unwrap();
    let text = std::fs::read_to_string(&path).unwrap().edit("cell_size = 0.15", "cell_size = 0.025");
    let uniform = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let (error, n) = uniform_estimate(session, uniform).map_err(|e| e.to_string())?;
    ensure(2 * n >= 3 * last.elements && error > 2.0 * last.error_percent, || {
        format!("uniform {error:.3} % on {n} elements vs adapted {:.3} % on {}", last.error_percent, last.elements)
    })?;
    let _ = std::fs::remove_dir_all(&out);
    Ok(())
}

/// Every mesh of the loop keeps its curved boundary exact: on a P2 disc (clamped, under its own
/// weight), every boundary node of every step, vertices and mid-edge nodes, lies on the circle
/// to round-off, and the remeshed steps are other meshes than the first.
pub fn adapt_keeps_curved_boundaries_exact(session: &Session) -> Result<(), String> {
    let text = "[mesh]\nshape = \"disc\"\ncenter = [0.3, -0.2]\nradius = 0.5\ncell_size = 0.15\n\n\
                [discretization]\norder = 2\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n\
                [loads]\nbody_force = [0.0, -1e4]\n\n[[dirichlet]]\npart = \"circle\"\nux = 0.0\nuy = 0.0\n";
    let scene = Scene::from_str(text, &manifest("disc.toml")).map_err(|e| e.to_string())?;
    let mut options = AdaptOptions::new(&scene, 0.05);
    options.max_steps = 3;
    let out = scratch("disc");
    let mut checked = Vec::new();
    let outcome = signorini::adapt::adapt_inspecting(session, &scene, &options, &out, &mut |_| {}, &mut |k, p| {
        let mesh = &p.mesh;
        let mut worst = 0.0f64;
        let mut nodes = 0;
        for e in 0..mesh.num_edges() {
            for &n in mesh.edge(e) {
                let x = mesh.nodes[n];
                worst = worst.max(((x[0] - 0.3).hypot(x[1] + 0.2) - 0.5).abs());
                nodes += 1;
            }
        }
        checked.push((k, mesh.num_cells(), nodes, worst));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    ensure(outcome.steps.len() >= 2, || format!("one step only: {checked:?}"))?;
    ensure(checked.iter().all(|&(_, _, nodes, worst)| nodes > 0 && worst <= 1e-12 * 0.5), || format!("{checked:?}"))?;
    ensure(checked[1].1 != checked[0].1, || format!("step 1 is the first mesh again: {checked:?}"))?;
    let _ = std::fs::remove_dir_all(&out);
    Ok(())
}
