//! `signorini adapt` and `signorini study`: the CLI side (arguments, terminal lines, exit);
//! the work is in the library ([`signorini::adapt`]). As `run`: the summary on stdout, within
//! [`summary::WIDTH`] columns (a table row per step or level), warnings and errors on stderr.
use std::path::PathBuf;

use signorini::adapt::{self, report, AdaptOptions, StudyOptions};
use signorini::petsc::Session;
use signorini::scene::Scene;
use signorini::Error;

use super::arguments::{AdaptArgs, StudyArgs};
use super::summary::{self, Lines};
use crate::{mistake, Failure};

fn output_dir(out: &Option<PathBuf>, scene: &Scene) -> PathBuf {
    out.clone().or_else(|| scene.output_dir.clone()).unwrap_or_else(|| PathBuf::from("out"))
}

/// Print wrapped lines on stdout.
fn print(lines: Lines) {
    for line in lines.into_lines() {
        println!("{line}");
    }
}

/// The header of the step table and one row (at most [`summary::WIDTH`] columns).
const STEP_HEADER: &str =
    "  step  elements     nodes       dofs  error (%)  mesh (s)  solve  dual  estimate  remesh  run (s)";

fn step_row(s: &adapt::AdaptStep) -> String {
    let t = &s.seconds;
    format!(
        "  {:>4}  {:>8}  {:>8}  {:>9}  {:>9.3}{} {:>8.2}  {:>5.2}  {:>4.2}  {:>8.2}  {:>6.2}  {:>7.2}",
        s.step,
        s.elements,
        s.nodes,
        s.dofs,
        s.error_percent,
        if s.error_grew { "↑" } else { " " },
        t.mesh,
        t.solve,
        t.dual,
        t.estimate,
        t.remesh,
        s.cumulative_seconds
    )
}

/// The header of the study table (its row: in `study_command`).
const LEVEL_HEADER: &str =
    "  level  h (m)     elements  ‖Δu‖ref    ‖Δσ‖ref    true (%)  estimate (%)  effectivity  time (s)";

/// `adapt SCENE --target PERCENT`: exit status 0 when the loop ran (reached or not: a target
/// not reached is a warning line, and `status` in adapt.json), 1 on an error.
pub fn adapt_command(session: &Session, args: &AdaptArgs) -> Result<(), Failure> {
    let loud = session.rank() == 0 && !args.quiet;
    let scene = Scene::from_file(&args.scene)?;
    // Several bodies: checked, then refused (adaptation and its dual estimate take one body).
    signorini::problem::refuse_several_bodies(&scene)?;
    let out = output_dir(&args.out, &scene);
    let mut options = AdaptOptions::new(&scene, args.target);
    options.max_steps = args.max_steps as usize;
    options.max_elements = args.max_elements;
    if let Some(rate) = args.contact_rate {
        if scene.contact.is_none() {
            return Err(mistake(format!(
                "adapt: --contact-rate applies to the contact part, and {} has no [contact] section",
                scene.source.display()
            )));
        }
        for (_, p) in options.rates.parts.iter_mut() {
            *p = rate;
        }
    }
    // Checked before anything is removed or solved.
    adapt::driver::mesh_request(&scene, "adapt")?;
    // Rank 0 alone clears; agreed before the ranks go on together.
    let cleared = if session.rank() == 0 { adapt::driver::clear_previous_adapt(&out).map(|_| ()) } else { Ok(()) };
    session.agree(cleared, "clearing the previous adaptation")?;
    if loud {
        let mut head = Lines::default();
        head.add("adapt", &summary::program_and_scene(scene.title.as_deref(), &scene.source.display().to_string()));
        head.add(
            "",
            &format!(
                "target {:.3} %, at most {} step(s); ↑: the error grew",
                options.target_percent, options.max_steps
            ),
        );
        print(head);
        println!("{STEP_HEADER}");
    }
    let outcome = adapt::adapt(session, &scene, &options, &out, &mut |s| {
        if loud {
            println!("{}", step_row(s));
        }
    })?;
    let written = if session.rank() == 0 { report::write_adapt_outputs(&outcome, &out)? } else { Vec::new() };
    if session.rank() == 0 {
        // The outcome (stdout) and the warnings (stderr) are said even with --quiet.
        let mut lines = Lines::default();
        lines.add("status", &report::status_line(&outcome));
        if loud {
            let files: Vec<String> =
                written.iter().chain(&outcome.mesh_picture).map(|p| p.display().to_string()).collect();
            lines.add(
                "wrote",
                &format!("{} and step_0 .. step_{}/solution.vtu", files.join(", "), outcome.steps.len() - 1),
            );
        }
        print(lines);
        let mut warnings = Lines::default();
        for w in &outcome.warnings {
            warnings.add("warning", w);
        }
        for line in warnings.into_lines() {
            eprintln!("{line}");
        }
    }
    // A failed step: the files of the steps before it are written; the run's error is its.
    if let Some(error) = outcome.error {
        let error = std::sync::Arc::try_unwrap(error).unwrap_or_else(|shared| Error::Usage(shared.to_string()));
        return Err(Failure::Run(error));
    }
    Ok(())
}

/// `study SCENE --levels N`.
pub fn study_command(session: &Session, args: &StudyArgs) -> Result<(), Failure> {
    let loud = session.rank() == 0 && !args.quiet;
    let scene = Scene::from_file(&args.scene)?;
    // Several bodies: checked, then refused (the study's levels and its dual take one body).
    signorini::problem::refuse_several_bodies(&scene)?;
    let out = output_dir(&args.out, &scene);
    adapt::driver::mesh_request(&scene, "study")?;
    if loud {
        let mut head = Lines::default();
        head.add("study", &summary::program_and_scene(scene.title.as_deref(), &scene.source.display().to_string()));
        head.add(
            "",
            &format!(
                "{} level(s), P2 reference {} halving(s) finer than the last",
                args.levels, args.reference_halvings
            ),
        );
        print(head);
    }
    let options = StudyOptions { levels: args.levels as usize, reference_halvings: args.reference_halvings as usize };
    let outcome = adapt::study(session, &scene, options, &mut |level, r| {
        if !loud {
            return;
        }
        match level {
            None => {
                let mut lines = Lines::default();
                lines.add(
                    "reference",
                    &format!(
                        "{} elements, {} dofs, ‖σ_ref‖ = {:.6e} [{:.2} s]",
                        r.elements, r.dofs, r.energy_norm, r.seconds
                    ),
                );
                print(lines);
                println!("{LEVEL_HEADER}");
            }
            Some(l) => println!(
                "  {:>5}  {:.3e}  {:>8}  {:.4e}  {:.4e}  {:>8.3}  {:>12.3}  {:>11.3}  {:>8.2}",
                l.level,
                l.cell_size,
                l.elements,
                l.error_displacement,
                l.error_stress,
                l.true_percent,
                l.estimate_percent,
                l.effectivity,
                l.seconds
            ),
        }
    })?;
    if session.rank() == 0 {
        let written = report::write_study_outputs(&outcome, &out)?;
        if loud {
            let r = &outcome.rates;
            let f = |x: Option<f64>| x.map_or_else(|| "–".to_string(), |x| format!("{x:.2}"));
            let mut lines = Lines::default();
            lines.add(
                "rates",
                &format!(
                    "‖Δu‖ {}, ‖Δσ‖ {}, true {}, estimate {}",
                    f(r.displacement),
                    f(r.stress),
                    f(r.true_error),
                    f(r.estimate)
                ),
            );
            let files: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
            lines.add("wrote", &files.join(", "));
            print(lines);
        }
    }
    Ok(())
}
