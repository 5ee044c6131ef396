//! Load paths (issue 25): increments with friction memory on the condensed route, checked
//! against static solves, closed forms and finer references.
use super::contact::{example, set_line, solve_text};
use signorini::evolution::LoadPath;
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;

fn ensure(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(message())
    }
}

/// Solve `text` along `path`, every increment post-processed; the problem after the path and
/// the displacement of every increment.
fn solve_path<'s>(
    s: &'s Session,
    text: &str,
    file: &std::path::Path,
    path: &LoadPath,
) -> Result<(ElasticityProblem<'s>, Vec<Vec<f64>>), String> {
    let scene = Scene::from_str(text, file).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    p.assemble().map_err(|e| e.to_string())?;
    let mut fields = Vec::new();
    p.solve_load_path(path, true, &mut |q, _| {
        fields.push(q.displacement.clone().expect("a step has a displacement"));
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    Ok((p, fields))
}

fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
    a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt() / n
}

/// Proportional loading in N increments equals the static solve at every increment's load
/// where the law allows it: the square block (no initial gap, loads growing monotonically, slip
/// zones growing and never reversing) with Coulomb, Tresca and no friction. The slip of a
/// point that keeps slipping in one direction sums to the static slip (each increment's slip
/// opposes the same force), so each increment's answer is the static answer at its load. The
/// static answers come from the default full-space route at the scaled loads, the path from
/// the condensed route with the increments' memory.
pub fn load_path_proportional_equals_static(s: &Session) -> Result<(), String> {
    let (base, file) = example("square_block.toml");
    let cases = [
        ("coulomb", base.clone()),
        (
            "tresca",
            set_line(&base, "mu = 1.0", "threshold = 2e7").replace("friction = \"coulomb\"", "friction = \"tresca\""),
        ),
        ("frictionless", set_line(&base, "mu = 1.0", "").replace("friction = \"coulomb\"", "friction = \"none\"")),
    ];
    for (name, text) in cases {
        let text = text.replace("solver = \"newton_full\"", "solver = \"newton_full\"\ntolerance = 1e-12");
        let path = LoadPath::proportional(4).unwrap();
        let (p, fields) = solve_path(s, &text, &file, &path).map_err(|e| format!("{name}, path: {e}"))?;
        let mut worst = 0.0f64;
        for (k, u) in fields.iter().enumerate() {
            let t = path.times[k];
            assert!(
                text.contains("pressure = 5e7") && text.contains("pressure = 1.5e8"),
                "test bug: square_block.toml's loads changed"
            );
            let scaled = text
                .replace("pressure = 5e7", &format!("pressure = {:e}", 5e7 * t))
                .replace("pressure = 1.5e8", &format!("pressure = {:e}", 1.5e8 * t));
            let reference = solve_text(s, &scaled, &file).map_err(|e| format!("{name}, static at t = {t}: {e}"))?;
            worst = worst.max(relative_difference(reference.displacement.as_ref().unwrap(), u));
        }
        let report = p.load_path.as_ref().unwrap();
        eprintln!(
            "    {name}: worst |u(t_k) − u_static(t_k)| / |u_static(t_k)| = {worst:.2e} over {} increments; energy balance {:.2e}, dissipation {:.4e} J/m",
            fields.len(),
            report.energy.relative_residual,
            report.energy.dissipation
        );
        ensure(fields.len() == 4, || format!("{name}: {} increments", fields.len()))?;
        ensure(worst < 1e-10, || format!("{name}: the path differs from the static answers by {worst:.2e}"))?;
        ensure(report.energy.relative_residual < 1e-8, || format!("{name}: energy balance {:?}", report.energy))?;
        ensure(report.steps.iter().all(|r| r.dissipation >= -1e-12 * r.work.abs()), || {
            format!("{name}: negative dissipation {:?}", report.steps.iter().map(|r| r.dissipation).collect::<Vec<_>>())
        })?;
    }
    Ok(())
}
