//! The implicit storage of the dual contact flexibility W (`-dual_contact_storage implicit`):
//! products by interior solves, W never formed; Uzawa on it is Uzawa on the full dual system.
//! Same forces as the dense storage; the solvers that need W's entries refused by name.
use signorini::Error;

use super::contact::{example, set_line};
use super::dual_contact::{solve_dual, without_corner_point};
use super::ensure;

/// The square block without its corner point (held vertically by the obstacle only), coarse
/// (8 edges along the contact side), with `friction` (a `[contact]` line pair) and `solver`.
fn block(friction: &str, solver: &str) -> (String, std::path::PathBuf) {
    let (text, path) = example("square_block.toml");
    let text = without_corner_point(&text);
    let text = set_line(&text, "cell_size", "cell_size = 5e-3");
    let text = set_line(&text, "solver", &format!("solver = \"{solver}\""));
    let text = match friction {
        "none" => set_line(&set_line(&text, "friction", "friction = \"none\""), "mu", ""),
        "tresca" => set_line(&set_line(&text, "friction", "friction = \"tresca\""), "mu", "threshold = 1e7"),
        _ => set_line(&text, "mu", "mu = 0.3"),
    };
    (text, path)
}

/// The dual contact forces and the linear solver's description, with `options` set for the
/// solve only.
fn forces(
    s: &signorini::petsc::Session,
    text: &str,
    path: &std::path::Path,
    options: &[(&str, Option<&str>)],
) -> Result<(Vec<f64>, String), Error> {
    for (k, v) in options {
        s.set_option(k, *v)?;
    }
    let result = solve_dual(s, text, path, false);
    for (k, _) in options {
        s.clear_option(k)?;
    }
    let p = result?;
    let dual = p.dual.as_ref().unwrap();
    Ok((dual.contact.as_ref().unwrap().force.clone(), dual.report.solver.converged_reason.clone()))
}

const IMPLICIT: (&str, Option<&str>) = ("-dual_contact_storage", Some("implicit"));

/// Frictionless, Tresca and Coulomb (μ = 0.3): Uzawa on the full dual system and the
/// semi-smooth Newton method on the implicit W give the dense (Schur) storage's forces to 1e-6.
pub fn dual_contact_implicit_storage_agrees(s: &signorini::petsc::Session) -> Result<(), String> {
    for friction in ["none", "tresca", "coulomb"] {
        let (text, path) = block(friction, "newton");
        let (dense, reason) = forces(s, &text, &path, &[]).map_err(|e| format!("{friction}, dense: {e}"))?;
        ensure(!reason.contains("implicit"), || reason.clone())?;
        let scale = dense.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        ensure(scale > 0.0, || format!("{friction}: no contact force"))?;
        for solver in ["uzawa", "newton"] {
            let (text, path) = block(friction, solver);
            let (implicit, reason) =
                forces(s, &text, &path, &[IMPLICIT]).map_err(|e| format!("{friction}, implicit {solver}: {e}"))?;
            ensure(reason.contains("implicit storage of W"), || format!("{friction}, {solver}: {reason}"))?;
            let differ = dense.iter().zip(&implicit).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale;
            ensure(differ < 1e-6, || format!("{friction}, implicit {solver} differs from dense by {differ:e}"))?;
        }
    }
    // The three-step condensation's interior solver also drives the products (CG + SSOR here).
    let (text, path) = block("tresca", "newton");
    let (dense, _) = forces(s, &text, &path, &[]).map_err(|e| format!("dense: {e}"))?;
    let (text, path) = block("tresca", "uzawa");
    let (cg, reason) = forces(
        s,
        &text,
        &path,
        &[IMPLICIT, ("-ksp_type", Some("cg")), ("-pc_type", Some("sor")), ("-pc_sor_symmetric", None)],
    )
    .map_err(|e| format!("implicit CG + SSOR: {e}"))?;
    ensure(reason.contains("implicit storage of W"), || reason.clone())?;
    let scale = dense.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let differ = dense.iter().zip(&cg).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale;
    ensure(differ < 1e-6, || format!("implicit CG + SSOR differs from dense by {differ:e}"))
}

/// A wrong storage, a solver that needs W's entries with implicit storage, and the Schur
/// condensation with implicit storage are usage errors that say what works.
pub fn dual_contact_storage_usage_errors(s: &signorini::petsc::Session) -> Result<(), String> {
    let (text, path) = block("tresca", "uzawa");
    match forces(s, &text, &path, &[("-dual_contact_storage", Some("sparse"))]) {
        Err(Error::Usage(m)) if m.contains("takes dense or implicit") && m.contains("sparse") => {}
        other => return Err(format!("storage sparse: {:?}", other.map(|f| f.1))),
    }
    match forces(s, &text, &path, &[IMPLICIT, ("-dual_contact_condensation", Some("schur"))]) {
        Err(Error::Usage(m)) if m.contains("never forms W") => {}
        other => return Err(format!("implicit + schur: {:?}", other.map(|f| f.1))),
    }
    for solver in ["relaxation", "dpana", "tao"] {
        let (text, path) = block("tresca", solver);
        match forces(s, &text, &path, &[IMPLICIT]) {
            Err(Error::Usage(m))
                if m.contains(&format!("solver = \"{solver}\" needs its entries"))
                    && m.contains("\"uzawa\"")
                    && m.contains("\"newton\"") => {}
            other => return Err(format!("implicit + {solver}: {:?}", other.map(|f| f.1))),
        }
    }
    Ok(())
}
