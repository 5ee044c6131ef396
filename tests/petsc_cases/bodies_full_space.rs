//! The full-space semi-smooth Newton for several bodies (mortar contact rows): the same answer
//! as the condensed route, in few Newton steps, the contact patch test exact.
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::{ContactSolverSpec, Scene};

use super::bodies_blocks::patch_text;
use super::contact::example;
use super::{ensure, manifest};

/// Solve `text` with the default contact solver (the full-space Newton), or with the condensed
/// semi-smooth Newton.
fn solve<'s>(
    s: &'s Session,
    text: &str,
    path: &std::path::Path,
    condensed: bool,
) -> Result<ElasticityProblem<'s>, String> {
    let scene = Scene::from_str(text, path).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    if condensed {
        p.contact.as_mut().ok_or("no contact")?.spec.solver = ContactSolverSpec::Newton;
    }
    p.assemble().map_err(|e| e.to_string())?;
    p.solve().map_err(|e| e.to_string())?;
    p.postprocess().map_err(|e| e.to_string())?;
    Ok(p)
}

/// The inner solver of a body the contact holds (floating_elimination.rs).
const PINNED: &str = "springs at pinned contact dofs";

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Full space (the default) against condensed on one scene: the route taken (with the inner
/// solver `inner`), its Newton steps (at most `max_steps`), and the displacements and contact
/// forces within `tol` relative. Returns the full-space problem.
fn agree<'s>(
    s: &'s Session,
    name: &str,
    text: &str,
    path: &std::path::Path,
    max_steps: usize,
    inner: &str,
    tol: f64,
) -> Result<ElasticityProblem<'s>, String> {
    let full = solve(s, text, path, false).map_err(|e| format!("{name}, full space: {e}"))?;
    let condensed = solve(s, text, path, true).map_err(|e| format!("{name}, condensed: {e}"))?;
    let fo = full.contact_outcome.as_ref().ok_or("no contact outcome")?;
    let co = condensed.contact_outcome.as_ref().ok_or("no contact outcome")?;
    let (uf, uc) = (full.displacement.as_ref().unwrap(), condensed.displacement.as_ref().unwrap());
    let du = max_diff(uf, uc) / max_abs(uc);
    let df = max_diff(&fo.force, &co.force) / max_abs(&co.force);
    eprintln!(
        "    {name}: full space {} Newton steps ({}), condensed {} iterations; differences: displacement {du:.2e}, \
         contact forces {df:.2e}",
        fo.report.iterations, fo.report.solver, co.report.iterations
    );
    ensure(fo.report.solver.starts_with("full-space") && fo.report.solver.contains(inner), || {
        format!("{name}: solved by {} (inner solver with '{inner}' expected)", fo.report.solver)
    })?;
    ensure(fo.report.iterations <= max_steps, || {
        format!("{name}: {} full-space Newton steps (at most {max_steps} expected)", fo.report.iterations)
    })?;
    ensure(du <= tol && df <= tol, || format!("{name}: routes differ: displacement {du:e}, forces {df:e}"))?;
    Ok(full)
}

/// The non-matching contact patch test (frictionless, the upper body held vertically by the
/// contact alone), P1 and P2: the full space agrees with the condensed route, and its nodal
/// pressures equal the applied one to 1e-12.
pub fn bodies_full_space_patch_test(s: &Session) -> Result<(), String> {
    for order in [1, 2] {
        let path = manifest("two_body_patch.toml");
        // The docs: 1 Newton step; the condensed route's proximal steps leave 4e-12 (measured
        // 2.8e-12 in the displacements, 1.4e-12 in the forces).
        let p = agree(s, &format!("patch P{order}"), &patch_text(order), &path, 1, PINNED, 1e-11)?;
        let c = p.contact.as_ref().unwrap();
        let o = p.contact_outcome.as_ref().unwrap();
        let (pressure, _) = c.boundary.tractions(&o.force);
        let pr = 1e6_f64;
        let perr = pressure.iter().map(|q| (q - pr).abs() / pr).fold(0.0, f64::max);
        eprintln!("    patch P{order}: full-space pressure error {perr:.2e}");
        ensure(perr <= 1e-12, || format!("P{order}: full-space pressure off by {perr:e}"))?;
    }
    Ok(())
}

/// The square block on an elastic foundation with Coulomb friction (block_on_block.toml; the
/// block held vertically by the contact alone): the default run takes the full-space Newton
/// with pins on the block (floating_elimination.rs), and agrees with SNES's LU of the whole
/// mixed Jacobian (`-contact_full_space_lu`) to round-off.
pub fn bodies_full_space_block_on_block(s: &Session) -> Result<(), String> {
    let (text, path) = example("block_on_block.toml");
    // The docs: 6 Newton steps (measured: 6 with the pins, 6 with the LU).
    let pinned = agree(s, "block on block (Coulomb)", &text, &path, 6, PINNED, 1e-11)?;
    s.set_option("-contact_full_space_lu", None).map_err(|e| e.to_string())?;
    let lu = solve(s, &text, &path, false);
    s.clear_option("-contact_full_space_lu").map_err(|e| e.to_string())?;
    let lu = lu.map_err(|e| format!("LU of the mixed Jacobian: {e}"))?;
    let (po, lo) = (pinned.contact_outcome.as_ref().unwrap(), lu.contact_outcome.as_ref().unwrap());
    let df = max_diff(&po.force, &lo.force) / max_abs(&lo.force);
    let du = max_diff(pinned.displacement.as_ref().unwrap(), lu.displacement.as_ref().unwrap())
        / max_abs(lu.displacement.as_ref().unwrap());
    eprintln!(
        "    block on block: pinned elimination {} steps, LU {} steps ({}); displacement {du:.2e}, forces {df:.2e}",
        po.report.iterations, lo.report.iterations, lo.report.solver
    );
    ensure(!lo.report.solver.contains(PINNED) && lo.report.solver.starts_with("full-space"), || {
        format!("with -contact_full_space_lu: solved by {}", lo.report.solver)
    })?;
    ensure(po.report.iterations == 6 && lo.report.iterations == 6, || {
        format!("{} (pins) and {} (LU) Newton steps, 6 expected", po.report.iterations, lo.report.iterations)
    })?;
    // Round-off: the docs said 8e-14; measured 2.3e-14 in the displacements, 1.6e-13 in the
    // forces (relative to the largest).
    ensure(du <= 1e-12 && df <= 1e-12, || {
        format!("pinned elimination and LU differ: displacement {du:e}, forces {df:e}")
    })
}

/// Every body held by its Dirichlet conditions (the block of block_on_block.toml pressed by a
/// prescribed displacement of its top instead of a pressure): the full-space Newton with the
/// block elimination (one MUMPS factorisation, Schur complement on every dof a mortar row
/// touches) agrees with the condensed route, in few steps, with no option.
pub fn bodies_full_space_block_elimination(s: &Session) -> Result<(), String> {
    let (text, path) = example("block_on_block.toml");
    let loads = "[[body.traction]]\npart = \"top\"\npressure = 5e7\n";
    ensure(text.contains(loads), || "test bug: block_on_block.toml's top load changed".into())?;
    let text = text.replacen(loads, "[[body.dirichlet]]\npart = \"top\"\nuy = -2e-5\n", 1);
    let full = super::contact::solve_text(s, &text, &path).map_err(|e| format!("full space: {e}"))?;
    let p = solve(s, &text, &path, true).map_err(|e| format!("condensed: {e}"))?;
    let (fo, co) = (full.contact_outcome.as_ref().unwrap(), p.contact_outcome.as_ref().unwrap());
    let (uf, uc) = (full.displacement.as_ref().unwrap(), p.displacement.as_ref().unwrap());
    let du = max_diff(uf, uc) / max_abs(uc);
    let df = max_diff(&fo.force, &co.force) / max_abs(&co.force);
    let stats = full.stats.as_ref().ok_or("no stats")?;
    eprintln!(
        "    held block: {} ({} steps, inner {}), condensed {} iterations; displacement {du:.2e}, forces {df:.2e}",
        fo.report.solver,
        fo.report.iterations,
        format!("{} + {}", stats.ksp_type, stats.pc_type),
        co.report.iterations
    );
    // The docs said 8 steps and 5e-14 in the forces; measured 7 steps, forces 2.9e-14 and
    // displacements 9e-16 (relative to the largest).
    ensure(fo.report.solver.starts_with("full-space") && fo.report.iterations == 7, || {
        format!("solved by {} in {} steps (7 measured)", fo.report.solver, fo.report.iterations)
    })?;
    let inner = format!("{} + {}", stats.ksp_type, stats.pc_type);
    ensure(inner.contains("block elimination"), || format!("inner solver {inner}"))?;
    ensure(du <= 1e-13 && df <= 1e-13, || format!("routes differ: displacement {du:e}, forces {df:e}"))
}
