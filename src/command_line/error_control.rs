//! `signorini adapt` and `signorini study`: the CLI side (arguments, terminal lines, exit);
//! the work is in the library ([`signorini::adapt`]).
use std::path::PathBuf;

use signorini::adapt::{self, report, AdaptOptions, StudyOptions};
use signorini::petsc::Session;
use signorini::scene::Scene;
use signorini::Error;

use crate::RunArgs;

fn output_dir(args: &RunArgs, scene: &Scene) -> PathBuf {
    args.out.clone().or_else(|| scene.output_dir.clone()).unwrap_or_else(|| PathBuf::from("out"))
}

/// `adapt SCENE --target PERCENT`: exit status 0 when the loop ran (reached or not: a target
/// not reached is a warning line, and `status` in adapt.json), 1 on an error.
pub fn adapt_command(session: &Session, args: RunArgs) -> Result<(), Error> {
    let loud = session.rank() == 0 && !args.quiet;
    let path = args.scene.clone().ok_or_else(|| Error::Usage("adapt needs a scene file".into()))?;
    let scene = Scene::from_file(&path)?;
    // Several bodies: checked, then refused (adaptation and its dual estimate take one body).
    signorini::problem::refuse_several_bodies(&scene)?;
    let out = output_dir(&args, &scene);
    let mut options = AdaptOptions::new(&scene, args.target);
    options.max_steps = args.max_steps;
    options.max_elements = args.max_elements;
    if let Some(rate) = args.contact_rate {
        if scene.contact.is_none() {
            return Err(Error::Usage(format!(
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
        eprintln!(
            "signorini {} adapt — {} ({}): target {:.3} %, at most {} step(s)",
            env!("CARGO_PKG_VERSION"),
            scene.title.as_deref().unwrap_or("untitled scene"),
            scene.source.display(),
            options.target_percent,
            options.max_steps
        );
    }
    let outcome = adapt::adapt(session, &scene, &options, &out, &mut |s| {
        if loud {
            let t = &s.seconds;
            eprintln!(
                "  step {:<3} {:>8} elements {:>8} nodes {:>9} dofs  error {:>8.3} %{}  [mesh {:.2}, solve {:.2}, dual {:.2}, \
                 estimate {:.2}, remesh {:.2} s; run {:.2} s]",
                s.step,
                s.elements,
                s.nodes,
                s.dofs,
                s.error_percent,
                if s.error_grew { " (grew)" } else { "" },
                t.mesh,
                t.solve,
                t.dual,
                t.estimate,
                t.remesh,
                s.cumulative_seconds
            );
        }
    })?;
    let written = if session.rank() == 0 { report::write_adapt_outputs(&outcome, &out)? } else { Vec::new() };
    if session.rank() == 0 {
        // The outcome and the warnings are said even with --quiet.
        eprintln!("  {}", report::status_line(&outcome));
        for w in &outcome.warnings {
            eprintln!("  warning   {w}");
        }
        if loud {
            let files: Vec<String> =
                written.iter().chain(&outcome.mesh_picture).map(|p| p.display().to_string()).collect();
            eprintln!("  wrote     {} and step_0 .. step_{}/solution.vtu", files.join(", "), outcome.steps.len() - 1);
        }
    }
    // A failed step: the files of the steps before it are written; the run's error is its.
    if let Some(error) = outcome.error {
        return Err(std::sync::Arc::try_unwrap(error).unwrap_or_else(|shared| Error::Usage(shared.to_string())));
    }
    Ok(())
}

/// `study SCENE --levels N`.
pub fn study_command(session: &Session, args: RunArgs) -> Result<(), Error> {
    let loud = session.rank() == 0 && !args.quiet;
    let path = args.scene.clone().ok_or_else(|| Error::Usage("study needs a scene file".into()))?;
    let scene = Scene::from_file(&path)?;
    // Several bodies: checked, then refused (the study's levels and its dual take one body).
    signorini::problem::refuse_several_bodies(&scene)?;
    let out = output_dir(&args, &scene);
    adapt::driver::mesh_request(&scene, "study")?;
    if loud {
        eprintln!(
            "signorini {} study — {} ({}): {} level(s), reference {} halving(s) finer, P2",
            env!("CARGO_PKG_VERSION"),
            scene.title.as_deref().unwrap_or("untitled scene"),
            scene.source.display(),
            args.levels,
            args.reference_halvings
        );
    }
    let options = StudyOptions { levels: args.levels, reference_halvings: args.reference_halvings };
    let outcome = adapt::study(session, &scene, options, &mut |level, r| {
        if !loud {
            return;
        }
        match level {
            None => eprintln!(
                "  reference {} elements, {} dofs, ‖σ_ref‖ = {:.6e} [{:.2} s]",
                r.elements, r.dofs, r.energy_norm, r.seconds
            ),
            Some(l) => eprintln!(
                "  level {:<2} h {:.3e}: {:>7} elements  ‖Δu‖ {:.4e}  ‖Δσ‖ {:.4e}  ε ref {:.3} %  estimate {:.3} %  \
                 effectivity {:.3} [{:.2} s]",
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
            eprintln!(
                "  rates     ‖Δu‖ {}, ‖Δσ‖ {}, true {}, estimate {}",
                f(r.displacement),
                f(r.stress),
                f(r.true_error),
                f(r.estimate)
            );
            let files: Vec<String> = written.iter().map(|p| p.display().to_string()).collect();
            eprintln!("  wrote     {}", files.join(", "));
        }
    }
    Ok(())
}
