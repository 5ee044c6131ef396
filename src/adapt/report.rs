//! The summary files of an adaptive run: `adapt.json` (the [`AdaptOutcome`]), `adapt.md` (the
//! talk's table: step, elements, nodes, dofs, error, and the time of each phase) and `adapt.svg`
//! (the error against the element count and against the cumulative run time, log-log); and
//! those of a convergence study (`study.json`, `study.md`, `study.svg`).
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::driver::{AdaptOutcome, AdaptStatus};
use super::study::{StudyLevel, StudyOutcome};
use crate::error::Result;
use crate::output::plot::{write_loglog_panels_svg, Panel, Series};
use crate::output::{write_atomically, write_json};

/// The summary files, removed before a new run into the same directory.
pub const ADAPT_FILES: [&str; 4] = ["adapt.json", "adapt.md", "adapt.svg", "adapt_mesh.svg"];

/// One line saying how the run ended.
pub fn status_line(outcome: &AdaptOutcome) -> String {
    let target = outcome.options.target_percent;
    let last = outcome.steps.last();
    let (steps, elements) = (outcome.steps.len(), last.map_or(0, |s| s.elements));
    match outcome.status {
        AdaptStatus::Reached => format!(
            "target {target:.3} % reached: {:.3} % after {steps} step(s), {elements} elements",
            outcome.final_error_percent
        ),
        AdaptStatus::MaxSteps => format!(
            "target {target:.3} % NOT reached in {steps} step(s): {:.3} % on {elements} elements (raise --max-steps)",
            outcome.final_error_percent
        ),
        AdaptStatus::ElementLimit => format!(
            "target {target:.3} % NOT reached: {:.3} % on {elements} elements; the next mesh would exceed the \
             element limit",
            outcome.final_error_percent
        ),
        AdaptStatus::Failed => format!(
            "target {target:.3} % NOT reached: {:.3} % on {elements} elements, then {}",
            outcome.final_error_percent,
            outcome.failure.as_deref().and_then(|f| f.lines().next()).unwrap_or("a step failed")
        ),
    }
}

/// The markdown table of the steps.
pub fn adapt_table(outcome: &AdaptOutcome) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Mesh adaptation: {}\n", outcome.title.as_deref().unwrap_or(&outcome.scene));
    let _ = writeln!(
        s,
        "Scene `{}`, target {:.3} % (relative error in the constitutive relation, energy norm); a priori rate \
         p = {} in the volume{}; ratios clamped to [{}, {}] per step.\n",
        outcome.scene,
        outcome.options.target_percent,
        outcome.options.rates.volume,
        outcome.options.rates.parts.iter().map(|(n, p)| format!(", {p} on '{n}'")).collect::<String>(),
        outcome.options.limits.min_ratio,
        outcome.options.limits.max_ratio
    );
    let _ = writeln!(
        s,
        "| step | elements | nodes | dofs | error (%) | mesh (s) | solve (s) | dual (s) | estimate (s) | remesh (s) | \
         cumulative (s) | predicted elements |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for st in &outcome.steps {
        let t = &st.seconds;
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {:.3}{} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.0} |",
            st.step,
            st.elements,
            st.nodes,
            st.dofs,
            st.error_percent,
            if st.error_grew { " (grew)" } else { "" },
            t.mesh,
            t.solve,
            t.dual,
            t.estimate,
            t.remesh,
            st.cumulative_seconds,
            st.size_map.predicted_elements
        );
    }
    let _ = writeln!(s, "\n{}", status_line(outcome));
    for w in &outcome.warnings {
        let _ = writeln!(s, "\nwarning: {w}");
    }
    s
}

/// Write `adapt.json`, `adapt.md` and `adapt.svg` into `dir` (each atomically); their paths.
pub fn write_adapt_outputs(outcome: &AdaptOutcome, dir: &Path) -> Result<Vec<PathBuf>> {
    let json = dir.join("adapt.json");
    write_json(&json, outcome)?;
    let md = dir.join("adapt.md");
    let table = adapt_table(outcome);
    write_atomically(&md, |w| w.write_all(table.as_bytes()))?;
    let svg = dir.join("adapt.svg");
    let by_elements = [Series {
        label: "estimate".into(),
        points: outcome.steps.iter().map(|s| (s.elements as f64, s.error_percent)).collect(),
    }];
    let by_time = [Series {
        label: "estimate".into(),
        points: outcome.steps.iter().map(|s| (s.cumulative_seconds, s.error_percent)).collect(),
    }];
    let target = |xs: &mut dyn Iterator<Item = f64>| {
        let (lo, hi) = xs.fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
        Series {
            label: format!("target {:.3} %", outcome.options.target_percent),
            points: vec![(lo, outcome.options.target_percent), (hi, outcome.options.target_percent)],
        }
    };
    let by_elements = [by_elements[0].clone(), target(&mut outcome.steps.iter().map(|s| s.elements as f64))];
    let by_time = [by_time[0].clone(), target(&mut outcome.steps.iter().map(|s| s.cumulative_seconds))];
    write_loglog_panels_svg(
        &svg,
        &[
            Panel {
                title: "Adaptation: error against elements",
                x_label: "elements",
                y_label: "relative error (%)",
                series: &by_elements,
            },
            Panel {
                title: "Adaptation: error against run time",
                x_label: "cumulative run time (s)",
                y_label: "relative error (%)",
                series: &by_time,
            },
        ],
    )?;
    Ok(vec![json, md, svg])
}

/// The summary files of a convergence study.
pub const STUDY_FILES: [&str; 3] = ["study.json", "study.md", "study.svg"];

fn rate(r: Option<f64>) -> String {
    r.map_or_else(|| "–".to_string(), |r| format!("{r:.2}"))
}

/// The markdown table of a convergence study (the talk's columns, with effectivity and rates).
pub fn study_table(outcome: &StudyOutcome) -> String {
    let mut s = String::new();
    let r = &outcome.reference;
    let _ = writeln!(s, "# Convergence study: {}\n", outcome.title.as_deref().unwrap_or(&outcome.scene));
    let _ = writeln!(
        s,
        "Scene `{}`, P{} levels; reference P{} at cell size {:.4e} ({} nodes, {} elements, {} dofs, \
         ‖σ_ref‖ = {:.6e}, {:.2} s). ‖Δu‖ = ‖u_ref − u_h‖_a (primal), ‖Δσ‖ = ‖σ_ref − σ_h‖_b (dual), \
         ε = (‖Δu‖² + ‖Δσ‖²)^½ / ‖σ_ref‖, effectivity = estimate / (‖Δu‖² + ‖Δσ‖²)^½.\n",
        outcome.scene, outcome.order, r.order, r.cell_size, r.nodes, r.elements, r.dofs, r.energy_norm, r.seconds
    );
    let _ = writeln!(
        s,
        "| h | mean h | ‖Δu‖ref | ‖Δσ‖ref | ε ref (%) | ε estim (%) | effectivity | nodes | elements | time (s) |"
    );
    let _ = writeln!(s, "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for l in &outcome.levels {
        let _ = writeln!(
            s,
            "| {:.4e} | {:.4e} | {:.4e} | {:.4e} | {:.3} | {:.3} | {:.3} | {} | {} | {:.2} |",
            l.cell_size,
            l.mean_size,
            l.error_displacement,
            l.error_stress,
            l.true_percent,
            l.estimate_percent,
            l.effectivity,
            l.nodes,
            l.elements,
            l.seconds
        );
    }
    let rt = &outcome.rates;
    let _ = writeln!(
        s,
        "\nObserved rates (least-squares slope of log error against log mean h): ‖Δu‖ {}, ‖Δσ‖ {}, \
         (‖Δu‖² + ‖Δσ‖²)^½ {}, estimate {}.",
        rate(rt.displacement),
        rate(rt.stress),
        rate(rt.true_error),
        rate(rt.estimate)
    );
    s
}

/// Write `study.json`, `study.md` and `study.svg` into `dir` (each atomically); their paths.
pub fn write_study_outputs(outcome: &StudyOutcome, dir: &Path) -> Result<Vec<PathBuf>> {
    let json = dir.join("study.json");
    write_json(&json, outcome)?;
    let md = dir.join("study.md");
    let table = study_table(outcome);
    write_atomically(&md, |w| w.write_all(table.as_bytes()))?;
    let svg = dir.join("study.svg");
    let series = |label: &str, f: fn(&StudyLevel) -> f64| Series {
        label: label.to_string(),
        points: outcome.levels.iter().map(|l| (l.mean_size, f(l))).collect(),
    };
    let plotted = [
        series("‖Δu‖ (primal, true)", |l| l.error_displacement),
        series("‖Δσ‖ (dual, true)", |l| l.error_stress),
        series("(‖Δu‖² + ‖Δσ‖²)^½ (true)", |l| l.error_true),
        series("estimate e", |l| l.estimate),
    ];
    crate::output::plot::write_loglog_svg(
        &svg,
        "Convergence: true errors and the estimate",
        "mean cell size h (m)",
        "error (energy norm)",
        &plotted,
    )?;
    Ok(vec![json, md, svg])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::adapt::driver::{AdaptOptions, AdaptStep, RateModel, SizeMapSummary, StepSeconds};
    use crate::adapt::SizeMapLimits;
    use crate::estimate::EstimateKind;

    fn step(k: usize, elements: usize, error: f64, grew: bool) -> AdaptStep {
        AdaptStep {
            step: k,
            elements,
            nodes: elements / 2,
            dofs: elements,
            error: error / 100.0,
            error_percent: error,
            reference_norm: 1.0,
            kind: EstimateKind::GuaranteedBound,
            seconds: StepSeconds { mesh: 0.1, solve: 0.2, dual: 0.3, estimate: 0.01, remesh: 0.4, output: 0.0 },
            cumulative_seconds: k as f64,
            error_grew: grew,
            size_map: SizeMapSummary {
                aim_percent: 5.0,
                target_error: 0.05,
                predicted_error: 0.05,
                predicted_elements: 1000.0,
                refined: 1,
                coarsened: 2,
                min_ratio: 0.1,
                max_ratio: 4.0,
                target_unreachable: false,
            },
            dir: PathBuf::from(format!("step_{k}")),
        }
    }

    fn outcome(status: AdaptStatus, steps: Vec<AdaptStep>) -> AdaptOutcome {
        AdaptOutcome {
            program: "signorini test".into(),
            scene: "s.toml".into(),
            title: None,
            options: AdaptOptions {
                target_percent: 5.0,
                max_steps: 3,
                limits: SizeMapLimits::default(),
                rates: RateModel { volume: 1.0, parts: vec![("bottom".into(), 0.5)] },
                max_elements: 10,
            },
            status,
            reached: status == AdaptStatus::Reached,
            final_error_percent: steps.last().unwrap().error_percent,
            warnings: vec!["step 2: the error grew".into()],
            steps,
            mesh_picture: None,
            failure: (status == AdaptStatus::Failed).then(|| "step 1 failed: the dual is refused".to_string()),
            error: None,
        }
    }

    #[test]
    fn table_rows_status_and_warnings_are_plain() {
        let o = outcome(
            AdaptStatus::MaxSteps,
            vec![step(0, 100, 20.0, false), step(1, 900, 6.0, false), step(2, 950, 6.5, true)],
        );
        let t = adapt_table(&o);
        assert_eq!(t.lines().filter(|l| l.starts_with("| ") && !l.starts_with("| step")).count(), 3, "{t}");
        assert!(t.contains("| 2 | 950 | 475 | 950 | 6.500 (grew) |"), "{t}");
        assert!(t.contains("0.5 on 'bottom'"), "{t}");
        assert!(t.contains("NOT reached in 3 step(s)") && t.contains("warning: step 2: the error grew"), "{t}");
        let reached = outcome(AdaptStatus::Reached, vec![step(0, 100, 4.0, false)]);
        assert!(status_line(&reached).starts_with("target 5.000 % reached: 4.000 %"));
        let limit = outcome(AdaptStatus::ElementLimit, vec![step(0, 100, 40.0, false)]);
        assert!(status_line(&limit).contains("element limit"));
        let failed = outcome(AdaptStatus::Failed, vec![step(0, 100, 40.0, false)]);
        assert!(status_line(&failed).ends_with("then step 1 failed: the dual is refused"), "{}", status_line(&failed));
        assert!(adapt_table(&failed).contains("then step 1 failed"));
    }

    #[test]
    fn summary_files_are_written_and_the_plot_has_two_panels() {
        let dir = std::env::temp_dir().join(format!("signorini-adapt-report-{}", std::process::id()));
        let o = outcome(AdaptStatus::Reached, vec![step(0, 100, 20.0, false), step(1, 900, 4.0, false)]);
        let written = write_adapt_outputs(&o, &dir).unwrap();
        assert_eq!(written.len(), 3);
        let svg = std::fs::read_to_string(dir.join("adapt.svg")).unwrap();
        assert_eq!(svg.matches("<svg ").count(), 3, "outer + two panels");
        assert!(svg.contains("x=\"800\""));
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("adapt.json")).unwrap()).unwrap();
        assert_eq!(json["status"], "reached");
        assert_eq!(json["options"]["limits"]["max_ratio"], 4.0);
        let _ = std::fs::remove_dir_all(&dir);
    }
}
