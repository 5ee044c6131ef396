//! The full-space Newton's routes (`-contact_route`): every route gives the same answer to
//! 1e-10 in the same Newton steps (±1), on the patch test, Hertz, the square block and a long
//! strip; the cost model's choice is reported; the dense route refuses what does not fit.
use super::contact::{example, set_line, solve_text};
use super::edit::Edit;
use super::{ensure, manifest};
use signorini::petsc::Session;
use signorini::Error;

/// A `length` × 1 strip (structured P1, cells 0.25: `4 length + 1` contact points) pressed by
/// 1 MPa on a frictionless rigid line, pinned sideways at its top-left corner.
pub fn strip_scene(length: f64) -> String {
    format!(
        "title = \"strip\"\n[mesh]\nshape = \"rectangle\"\nsize = [{length:?}, 1.0]\ncell_size = 0.25\n\
         mesher = \"structured\"\n[discretization]\norder = 1\n[material]\nyoung = 1e9\npoisson = 0.3\n\
         plane = \"strain\"\n[[traction]]\npart = \"top\"\npressure = 1e6\n[[dirichlet]]\npoint = [0.0, 1.0]\n\
         ux = 0.0\n[contact]\npart = \"bottom\"\nobstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]\n\
         friction = \"none\"\n"
    )
}

fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.iter().map(|x| x * x).sum::<f64>().sqrt().max(f64::MIN_POSITIVE);
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt() / n
}

struct Run {
    displacement: Vec<f64>,
    force: Vec<f64>,
    iterations: usize,
    route: String,
    reason: String,
    notes: Vec<String>,
}

fn run(s: &Session, text: &str, path: &std::path::Path, options: &[(&str, &str)]) -> Result<Run, String> {
    for (name, value) in options {
        s.set_option(name, Some(value)).unwrap();
    }
    let solved = solve_text(s, text, path);
    for (name, _) in options {
        s.clear_option(name).unwrap();
    }
    let p = solved.map_err(|e| format!("{options:?}: {e}"))?;
    let o = p.contact_outcome.as_ref().ok_or("no contact outcome")?;
    ensure(o.report.solver.starts_with("full-space"), || format!("{options:?}: fell back: {}", o.report.solver))?;
    Ok(Run {
        displacement: p.displacement.clone().unwrap(),
        force: o.force.clone(),
        iterations: o.report.iterations,
        route: o.report.route.clone(),
        reason: o.report.route_reason.clone(),
        notes: o.report.notes.clone(),
    })
}

/// Every route to the same answer (1e-10) in the same Newton steps (±1), and the cost
/// model's choice where the scene makes it clear (the long strip: sparse; the square block:
/// dense).
pub fn contact_routes_agree(s: &Session) -> Result<(), String> {
    let strip_path = manifest("examples/scenes/strip.toml");
    let (patch, patch_path) = example("contact_patch.toml");
    let (hertz, hertz_path) = example("hertz.toml");
    let hertz = set_line(&hertz, "cell_size", "cell_size = 0.02");
    let (block, block_path) = example("square_block.toml");
    let block = set_line(&block, "cell_size", "cell_size = 2.5e-3");
    let tresca = set_line(&block, "mu", "threshold = 2e7").edit("\"coulomb\"", "\"tresca\"");
    let cases: [(&str, String, &std::path::Path, Option<&str>); 5] = [
        ("patch", patch, &patch_path, None),
        ("hertz", hertz, &hertz_path, None),
        ("square block, Coulomb", block, &block_path, Some("dense_schur")),
        ("square block, Tresca", tresca, &block_path, Some("dense_schur")),
        ("strip, 401 points", strip_scene(100.0), &strip_path, Some("sparse_lu")),
    ];
    for (name, text, path, expected) in cases {
        let auto = run(s, &text, path, &[])?;
        if let Some(expected) = expected {
            ensure(auto.route == expected, || {
                format!("{name}: the cost model chose {} ({})", auto.route, auto.reason)
            })?;
        }
        ensure(auto.reason.contains("predicted"), || format!("{name}: route reason {:?}", auto.reason))?;
        let routes = [
            vec![("-contact_route", "dense_schur")],
            vec![("-contact_route", "sparse_lu")],
            vec![("-contact_route", "sparse_lu"), ("-contact_lu_reuse", "false")],
        ];
        for options in routes {
            let other = run(s, &text, path, &options)?;
            ensure(other.route == options[0].1, || format!("{name} {options:?}: route {}", other.route))?;
            let du = relative_difference(&auto.displacement, &other.displacement);
            let df = relative_difference(&auto.force, &other.force);
            ensure(du < 1e-10 && df < 1e-10, || {
                format!("{name} {options:?}: displacements differ by {du:e}, forces by {df:e} from {}", auto.route)
            })?;
            // On the square block the sparse route keeps its factors for a step (3 LUs for 4
            // steps, GMRES on the kept step): that path is the one compared here.
            if name.starts_with("square block") && options.len() == 1 && options[0].1 == "sparse_lu" {
                let kept = other.notes.iter().any(|n| {
                    n.contains("LU factorisation(s) of the mixed Jacobian")
                        && n.split_whitespace().next().and_then(|f| f.parse::<usize>().ok()) < Some(other.iterations)
                });
                ensure(kept, || format!("{name}: no step kept the factors: {:?}", other.notes))?;
            }
            ensure(auto.iterations.abs_diff(other.iterations) <= 1, || {
                format!(
                    "{name} {options:?}: {} Newton steps against {} ({})",
                    other.iterations, auto.iterations, auto.route
                )
            })?;
        }
    }
    Ok(())
}

/// The dense route named on a machine with too little memory for it is refused before any
/// work, naming the route and a cheaper one; unnamed, the cost model avoids it and says why.
pub fn contact_route_out_of_memory_is_named(s: &Session) -> Result<(), String> {
    let path = manifest("examples/scenes/strip.toml");
    let text = strip_scene(100.0);
    // 802 Schur dofs: 3 · 8 · 802² ≈ 15 MB, above a 1 MB limit.
    let refused = run(s, &text, &path, &[("-contact_route", "dense_schur"), ("-contact_memory_limit", "1")]);
    match refused {
        Err(message) => ensure(
            message.contains("dense_schur needs about 15 MB")
                && message.contains("1 MB are available")
                && message.contains("-contact_route sparse_lu"),
            || format!("the refusal says {message}"),
        )?,
        Ok(r) => return Err(format!("the dense route ran in 1 MB: {}", r.route)),
    }
    let scene = signorini::scene::Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let mut p = signorini::problem::ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    s.set_option("-contact_route", Some("dense_schur")).unwrap();
    s.set_option("-contact_memory_limit", Some("1")).unwrap();
    let e = p.solve();
    s.clear_option("-contact_route").unwrap();
    s.clear_option("-contact_memory_limit").unwrap();
    ensure(matches!(e, Err(Error::RouteMemory { .. })), || format!("not a RouteMemory error: {:?}", e.err()))?;
    // The square block's cost model prefers the dense route; with 1 MB it takes the sparse one.
    let (block, block_path) = example("square_block.toml");
    let block = set_line(&block, "cell_size", "cell_size = 2.5e-3");
    let avoided = run(s, &block, &block_path, &[("-contact_memory_limit", "0.01")])?;
    ensure(avoided.route == "sparse_lu" && avoided.reason.contains("MB are available"), || {
        format!("with 0.01 MB: {} ({})", avoided.route, avoided.reason)
    })?;
    // A full-space failure with no memory for the condensed fallback's dense W: the failure
    // is the answer, and it says why there was no fallback.
    let failed = run(s, &block, &block_path, &[("-contact_memory_limit", "0.01"), ("-contact_snes_max_it", "1")]);
    ensure(
        failed.as_ref().is_err_and(|m| {
            m.contains("DIVERGED_MAX_IT")
                && m.contains(
                    "no fallback: the condensed route's dense W on 32 contact unknowns needs about 0.02 MB and 0.01 MB",
                )
        }),
        || format!("{:?}", failed.as_ref().err()),
    )?;
    let bad = run(s, &block, &block_path, &[("-contact_route", "fastest")]);
    ensure(bad.as_ref().is_err_and(|m| m.contains("auto, dense_schur or sparse_lu")), || format!("{:?}", bad.err()))?;
    Ok(())
}
