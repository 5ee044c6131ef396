//! The full-space semi-smooth Newton for several bodies (mortar contact rows): the same answer
//! as the condensed route, in few Newton steps, the contact patch test exact.
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::{ContactSolverSpec, Scene};

use super::bodies_blocks::patch_text;
use super::contact::example;
use super::{ensure, manifest};

/// Solve `text` with the default contact solver, or with the condensed semi-smooth Newton.
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

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Full space (the default) against condensed on one scene: the route taken, its Newton steps
/// (at most `max_steps`), and the displacements and contact forces within `1e-8` relative.
/// Returns the full-space problem.
fn agree<'s>(
    s: &'s Session,
    name: &str,
    text: &str,
    path: &std::path::Path,
    max_steps: usize,
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
    ensure(fo.report.solver.starts_with("full-space"), || format!("{name}: solved by {}", fo.report.solver))?;
    ensure(fo.report.iterations <= max_steps, || {
        format!("{name}: {} full-space Newton steps (at most {max_steps} expected)", fo.report.iterations)
    })?;
    ensure(du <= 1e-8 && df <= 1e-8, || format!("{name}: routes differ: displacement {du:e}, forces {df:e}"))?;
    Ok(full)
}

/// The non-matching contact patch test (frictionless, the upper body held vertically by the
/// contact alone), P1 and P2: the full space agrees with the condensed route, and its nodal
/// pressures equal the applied one to 1e-12.
pub fn bodies_full_space_patch_test(s: &Session) -> Result<(), String> {
    for order in [1, 2] {
        let path = manifest("two_body_patch.toml");
        let p = agree(s, &format!("patch P{order}"), &patch_text(order), &path, 10)?;
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
/// block held vertically by the contact alone).
pub fn bodies_full_space_block_on_block(s: &Session) -> Result<(), String> {
    let (text, path) = example("block_on_block.toml");
    agree(s, "block on block (Coulomb)", &text, &path, 10).map(|_| ())
}
