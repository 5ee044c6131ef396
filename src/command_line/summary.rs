//! The terminal summary of a run (stdout): each quantity once, no line longer than
//! [`WIDTH`] columns. A label in the first [`INDENT`] columns, then the text, wrapped at spaces
//! with continuation lines indented under the text. Warnings go to stderr.
use std::path::PathBuf;

use signorini::problem::Report;

/// The widest line of the summary, in characters.
pub const WIDTH: usize = 100;
/// Where the text after a label starts.
const INDENT: usize = 10;

/// The longest scene title the terminal shows, in characters (longer ones end in `…`).
pub const TITLE_CHARS: usize = 200;

/// Lines of at most [`WIDTH`] characters.
#[derive(Default)]
pub struct Lines(Vec<String>);

impl Lines {
    /// `label` then `text`, wrapped at spaces (a word longer than a line is cut). Linear in the
    /// length of `text`: each character is copied once.
    pub fn add(&mut self, label: &str, text: &str) {
        let room = WIDTH - INDENT;
        let mut current = String::new();
        let mut used = 0; // characters in `current`
        let mut first = true;
        let mut flush = |current: &mut String, used: &mut usize, first: &mut bool| {
            let lead = if *first { format!("{label:<INDENT$}") } else { " ".repeat(INDENT) };
            self.0.push(format!("{lead}{}", current.trim_end()).trim_end().to_string());
            current.clear();
            *used = 0;
            *first = false;
        };
        for word in text.split(' ') {
            let length = word.chars().count();
            if used > 0 && used + 1 + length > room {
                flush(&mut current, &mut used, &mut first);
            }
            if length <= room {
                if used > 0 {
                    current.push(' ');
                    used += 1;
                }
                current.push_str(word);
                used += length;
                continue;
            }
            // A word longer than a line: cut into lines, the rest kept for the next word.
            for c in word.chars() {
                if used == room {
                    flush(&mut current, &mut used, &mut first);
                }
                current.push(c);
                used += 1;
            }
        }
        if used > 0 || first {
            flush(&mut current, &mut used, &mut first);
        }
    }

    pub fn into_lines(self) -> Vec<String> {
        self.0
    }
}

/// `text` cut to `limit` characters, the cut marked by `…`.
pub fn shortened(text: &str, limit: usize) -> String {
    match text.char_indices().nth(limit) {
        Some(_) => {
            let kept: String = text.chars().take(limit.saturating_sub(1)).collect();
            format!("{kept}…")
        }
        None => text.to_string(),
    }
}

/// `signorini VERSION — TITLE (SCENE)`, the title shortened to [`TITLE_CHARS`].
pub fn program_and_scene(title: Option<&str>, scene: &str) -> String {
    format!(
        "signorini {} — {} ({})",
        env!("CARGO_PKG_VERSION"),
        shortened(title.unwrap_or("untitled scene"), TITLE_CHARS),
        shortened(scene, TITLE_CHARS)
    )
}

/// Values this many times the largest of their group, or less, are round-off: printed as 0.
const ROUND_OFF: f64 = 1e-13;

/// `x` in `{:.prec$e}`, or `0` when it is round-off next to `scale`.
fn number(x: f64, scale: f64, prec: usize) -> String {
    if x.abs() <= ROUND_OFF * scale.abs() || x == 0.0 {
        "0".into()
    } else {
        format!("{x:.prec$e}")
    }
}

/// A relative residual with 2 digits: below the machine epsilon it is 0 (the residuals are
/// relative to their problem's scale, so smaller values are round-off of round-off).
fn relative(x: f64) -> String {
    number(x, f64::EPSILON / ROUND_OFF, 1)
}

/// `(x, y)` with 4 significant digits, components below round-off of `scale` as 0.
fn point_in(p: [f64; 2], scale: f64) -> String {
    format!("({}, {})", number(p[0], scale, 4), number(p[1], scale, 4))
}

/// `(x, y)` with 4 significant digits.
fn point(p: [f64; 2]) -> String {
    point_in(p, p[0].abs().max(p[1].abs()))
}

/// How the linear systems were solved, e.g. `preonly + cholesky (mumps)`: said once.
/// With contact, the contact solver, and the linear solver unless the contact solver's name
/// says it already.
pub fn solver_description(r: &Report) -> String {
    let s = &r.solver.stats;
    let pkg = s.factor_package.as_ref().map(|p| format!(" ({p})")).unwrap_or_default();
    let linear = format!("{} + {}{pkg}", s.ksp_type, s.pc_type);
    match &r.contact {
        Some(c) if c.solver.contains(&s.pc_type) => c.solver.clone(),
        Some(c) => format!("{}; linear solves {linear}", c.solver),
        None => linear,
    }
}

/// The interface law's line: the laws, then the final interface's extremes and the worst law
/// residual of the run (`thin_layer: 41 point(s), max opening 1.2e-6 m, ...`).
pub fn interface_line(i: &signorini::report::interface::InterfaceReport) -> String {
    let mut laws: Vec<&str> = Vec::new();
    for law in &i.laws {
        if !laws.contains(&law.as_str()) {
            laws.push(law);
        }
    }
    let l = &i.last;
    let mut parts = vec![
        format!("{} point(s)", l.points),
        format!("max opening {:.4e} m", l.max_opening),
        format!("max |slip| {:.4e} m", l.max_slip),
    ];
    if let Some(b) = l.min_adhesion {
        parts.push(format!("min adhesion {b:.4}"));
    }
    if let Some(d) = l.max_damage {
        parts.push(format!("max damage {d:.4}"));
    }
    parts.push(format!("{} staggered iteration(s)", l.iterations));
    parts.push(format!("worst law residual {}", relative(i.worst_law_residual)));
    format!("{}: {}", laws.join(", "), parts.join(", "))
}

/// The summary's lines.
pub fn summary_lines(r: &Report, written: &[PathBuf]) -> Vec<String> {
    let mut out = Lines::default();
    out.add(
        "run",
        &format!(
            "{} — {} ({})",
            r.program,
            shortened(r.title.as_deref().unwrap_or("untitled scene"), TITLE_CHARS),
            shortened(&r.scene, TITLE_CHARS)
        ),
    );
    out.add(
        "problem",
        &format!(
            "{} element, plane {}, {} formulation: {} nodes, {} triangles, {} dofs ({} fixed), {} rank(s)",
            r.element, r.plane, r.formulation, r.nodes, r.elements, r.dofs, r.fixed_dofs, r.mpi_ranks
        ),
    );
    let s = &r.solver.stats;
    let iterations = match &r.contact {
        Some(c) => format!("{} contact iteration(s), status changes {}", c.iterations, changes_list(&c.status_changes)),
        None => format!("{} iteration(s)", s.iterations),
    };
    out.add(
        "solver",
        &format!(
            "{}: {iterations}, {}, residual {}",
            solver_description(r),
            s.converged_reason,
            relative(s.relative_residual)
        ),
    );
    if let Some(c) = &r.contact {
        out.add("route", &format!("{}: {}", c.route, c.route_reason));
    }
    if let (Some(path), Some(first), Some(last)) = (&r.load_path, r.steps.first(), r.steps.last()) {
        let e = &path.energy;
        out.add(
            "path",
            &format!(
                "{} increments, t = {} to {}, {} halving(s), {} contact iterations in all; dissipation {:.4e} {}, \
                 energy balance {:.1e} of the work; the results below are the last increment's; {}",
                path.increments,
                first.time,
                last.time,
                path.halvings,
                r.steps.iter().map(|s| s.iterations).sum::<usize>(),
                last.total_dissipation,
                if r.forces == "full revolution" { "J" } else { "J/m" },
                e.relative_residual,
                path.route
            ),
        );
    }
    let cached = r.mesh_cache.as_ref().is_some_and(|c| c.status == signorini::mesh::cache::CacheStatus::Hit);
    let phases: Vec<String> = r
        .timings
        .phases()
        .iter()
        .map(|(k, v)| if k == "mesh" && cached { format!("{k} {v:.3} s (cached)") } else { format!("{k} {v:.3} s") })
        .collect();
    out.add(
        "time",
        &format!(
            "{}; total {:.3} s; peak memory {}",
            phases.join(", "),
            r.timings.total(),
            r.memory.peak_bytes.map(|b| format!("{:.1} MB", b as f64 / 1e6)).unwrap_or_else(|| "n/a".into())
        ),
    );
    if let Some(res) = &r.results {
        out.add(
            "result",
            &format!("max |u| = {:.4e} m, max von Mises = {:.4e} Pa", res.max_displacement, res.max_von_mises),
        );
        // Forces below round-off of the largest force of the balance are 0.
        let norm = |p: &[f64; 2]| p[0].hypot(p[1]);
        let scale = res.reactions.values().map(norm).fold(norm(&res.applied_force), f64::max);
        // A body of revolution: ring forces balance along the axis only (their radial sums are
        // not resultants), so the line gives the axial components.
        let revolution = r.forces == "full revolution";
        let shown = |v: &[f64; 2]| if revolution { number(v[1], scale, 4) } else { point_in(*v, scale) };
        let reactions: Vec<String> = res.reactions.iter().map(|(k, v)| format!("{k} {}", shown(v))).collect();
        out.add(
            "balance",
            &format!(
                "{}forces ({}): applied {}, reactions {}; equilibrium residual {}",
                if revolution { "axial " } else { "" },
                force_unit(r),
                shown(&res.applied_force),
                if reactions.is_empty() { "none".into() } else { reactions.join(", ") },
                relative(res.equilibrium_residual)
            ),
        );
    }
    if let Some(c) = &r.contact {
        let closed = if c.friction.is_frictional() {
            format!("{} closed ({} stick, {} slip)", c.closed, c.stick, c.slip)
        } else {
            format!("{} closed", c.closed)
        };
        let scale = c.normal_resultant.abs().max(c.tangential_resultant.abs()).max(norm_of(c.resultant));
        out.add(
            "contact",
            &format!(
                "part '{}', friction {}: {} points: {closed}, {} open; {} {} (normal {}, tangential {})",
                c.part,
                c.friction,
                c.points,
                c.open,
                // A body of revolution: ring forces add up along the axis only.
                if r.forces == "full revolution" {
                    format!("axial resultant {}", number(c.resultant[1], scale, 4))
                } else {
                    format!("resultant {}", point_in(c.resultant, scale))
                },
                force_unit(r),
                number(c.normal_resultant, scale, 4),
                number(c.tangential_resultant, scale, 4)
            ),
        );
        match &c.peak_pressure {
            Some(p) => out.add(
                "",
                &format!("peak pressure {:.4e} Pa at s = {:.4e} m, (x, y) = {}", p.pressure, p.s, point(p.position)),
            ),
            None => out.add("", "peak pressure: no contact point"),
        }
        if c.zones.is_empty() {
            out.add("", "closed zones: none (every point is open)");
        }
        for (k, z) in c.zones.iter().enumerate() {
            out.add(
                "",
                &format!(
                    "closed zone {}: s in [{:.4e}, {:.4e}] m, from {} to {}, {} points",
                    k + 1,
                    z.extent[0],
                    z.extent[1],
                    point(z.start),
                    point(z.end),
                    z.points
                ),
            );
        }
        let worst = [
            c.residuals.max_penetration,
            c.residuals.max_wrong_sign_pressure,
            c.residuals.max_cone_violation,
            c.residuals.normal_complementarity,
            c.residuals.tangential_complementarity,
        ]
        .into_iter()
        .fold(0.0, f64::max);
        out.add(
            "",
            &format!(
                "independent check: penetration {}, pressure sign {}, cone {}, complementarity {} / {} (worst {})",
                relative(c.residuals.max_penetration),
                relative(c.residuals.max_wrong_sign_pressure),
                relative(c.residuals.max_cone_violation),
                relative(c.residuals.normal_complementarity),
                relative(c.residuals.tangential_complementarity),
                relative(worst)
            ),
        );
        if c.stabilisation_iterations > 0 {
            out.add(
                "",
                &format!(
                    "held by contact: {} proximal iteration(s), residual spring force {}",
                    c.stabilisation_iterations,
                    point(c.stabilisation_force)
                ),
            );
        }
    }
    if let Some(i) = &r.interface {
        out.add("interface", &interface_line(i));
    }
    if let Some(d) = &r.dual {
        out.add(
            "dual",
            &format!(
                "HCT, {} unknowns: max von Mises = {:.4e}, complementary energy {:.6e} [{:.2} s]",
                d.unknowns, d.max_von_mises, d.check.complementary_energy, d.solver.seconds
            ),
        );
        out.add(
            "",
            &format!(
                "independent check: traction {}, equilibrium {}, stress jumps {}",
                relative(d.check.traction_residual),
                relative(d.check.interior_equilibrium),
                relative(d.check.stress_jump)
            ),
        );
        for note in &d.notes {
            out.add("", &format!("note: {note}"));
        }
    }
    if let Some(e) = &r.estimate {
        out.add(
            "estimate",
            &format!(
                "error {:.4e} = {:.3} % of the energy norm ({}), in {:.2} s of {:.2} s run time",
                e.estimate.error,
                e.estimate.relative_percent,
                if e.estimate.kind == signorini::estimate::EstimateKind::GuaranteedBound {
                    "a guaranteed bound"
                } else {
                    "an estimator"
                },
                e.estimate_seconds,
                e.run_seconds
            ),
        );
    }
    for (k, path) in written.iter().enumerate() {
        out.add(if k == 0 { "wrote" } else { "" }, &path.display().to_string());
    }
    out.0
}

/// Warning lines (for stderr), wrapped like the summary; PETSc options no solver read are
/// among the report's warnings (kind `unused_option`).
pub fn warning_lines(r: &Report) -> Vec<String> {
    let mut out = Lines::default();
    for w in &r.warnings {
        out.add("warning", &format!("{}: {}", w.kind, w.message));
    }
    if let Some(problem) = r.mesh_cache.as_ref().and_then(|c| c.problem.as_ref()) {
        out.add("note", &format!("mesh cache: {problem}"));
    }
    out.0
}

fn norm_of(p: [f64; 2]) -> f64 {
    p[0].hypot(p[1])
}

/// The status changes per iteration, the first six and the last four when there are more than
/// twelve (all of them are in report.json).
fn changes_list(changes: &[usize]) -> String {
    let join = |v: &[usize]| v.iter().map(|c| c.to_string()).collect::<Vec<_>>().join(", ");
    if changes.len() <= 12 {
        format!("[{}]", join(changes))
    } else {
        format!("[{}, … {} more …, {}]", join(&changes[..6]), changes.len() - 10, join(&changes[changes.len() - 4..]))
    }
}

/// The unit of the summary's forces: N/m (per unit thickness) or N (a body of revolution: the
/// whole circumference, `report.json` → `forces`).
fn force_unit(r: &Report) -> &'static str {
    if r.forces == "full revolution" {
        "N, full revolution"
    } else {
        "N/m"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_interface_line_names_each_law_once_and_the_variables_it_has() {
        use signorini::output::interface::InterfaceSummary;
        use signorini::report::interface::InterfaceReport;
        let last = InterfaceSummary {
            time: 2.0,
            laws: vec!["rccm".into(), "thin_layer".into(), "rccm".into()],
            points: 41,
            iterations: 12,
            min_adhesion: Some(0.25),
            max_damage: None,
            max_opening: 1.5e-6,
            max_slip: 3e-5,
            worst_law_residual: 2e-12,
        };
        let report = InterfaceReport {
            laws: last.laws.clone(),
            last: last.clone(),
            worst_law_residual: 7e-11,
            traced_points: vec![],
        };
        assert_eq!(
            interface_line(&report),
            "rccm, thin_layer: 41 point(s), max opening 1.5000e-6 m, max |slip| 3.0000e-5 m, min adhesion 0.2500, \
             12 staggered iteration(s), worst law residual 7.0e-11"
        );
        let joint = InterfaceReport {
            laws: vec!["cohesive_joint".into()],
            last: InterfaceSummary { min_adhesion: None, max_damage: Some(1.0), ..last },
            worst_law_residual: 0.0,
            traced_points: vec![],
        };
        assert!(interface_line(&joint).contains("max damage 1.0000, 12 staggered iteration(s), worst law residual 0"));
    }

    #[test]
    fn long_text_wraps_within_the_width() {
        let mut l = Lines::default();
        let long = format!("{} {}", "word ".repeat(60), "x".repeat(250));
        l.add("label", &long);
        assert!(l.0.len() > 3);
        assert!(l.0.iter().all(|s| s.chars().count() <= WIDTH), "{:#?}", l.0);
        assert!(l.0[0].starts_with("label     word"));
        let joined: String = l.0.iter().map(|s| s[INDENT..].to_string()).collect::<Vec<_>>().join(" ");
        assert_eq!(joined.matches('x').count(), 250);
    }

    #[test]
    fn a_megabyte_word_is_cut_into_full_lines_once() {
        let mut l = Lines::default();
        let word = "é".repeat(1 << 20); // two bytes per character: cuts fall on characters
        l.add("run", &format!("a {word} b"));
        let room = WIDTH - INDENT;
        // "a" alone (the word does not fit after it), then full lines of the word, then its
        // rest with " b".
        assert_eq!(l.0.len(), 1 + (1 << 20) / room + 1, "{}", l.0.len());
        assert_eq!(l.0[0], "run       a");
        assert!(l.0[1..l.0.len() - 1].iter().all(|s| s.chars().count() == WIDTH));
        assert!(l.0.last().unwrap().ends_with(" b"));
        let joined: String = l.0.iter().map(|s| s.chars().skip(INDENT).collect::<String>()).collect();
        assert_eq!(joined.matches('é').count(), 1 << 20);
    }

    #[test]
    fn titles_are_shortened_with_an_ellipsis() {
        assert_eq!(shortened("short", 10), "short");
        assert_eq!(shortened("exactly 10", 10), "exactly 10");
        assert_eq!(shortened("eleven char", 10), "eleven ch…");
        assert_eq!(shortened("ééééééééééé", 10).chars().count(), 10);
        let line = program_and_scene(Some(&"x".repeat(1 << 20)), "s.toml");
        assert!(line.chars().count() < TITLE_CHARS + 50 && line.contains("x…"), "{line}");
    }

    #[test]
    fn round_off_prints_as_zero() {
        // The applied force of a shear-free load: 1e-25 next to 5e4 is round-off.
        assert_eq!(point_in([1.034e-25, -5.0e4], 5.0e4), "(0, -5.0000e4)");
        assert_eq!(point([0.0, 2.5e-3]), "(0, 2.5000e-3)");
        // A genuine small component stays.
        assert_eq!(point([1.0e-9, 1.0]), "(1.0000e-9, 1.0000e0)");
        // Relative residuals below the machine epsilon are 0; above, two digits.
        assert_eq!(relative(5.2e-97), "0");
        assert_eq!(relative(0.0), "0");
        assert_eq!(relative(8.5e-16), "8.5e-16");
        assert_eq!(relative(1.3e-3), "1.3e-3");
    }

    #[test]
    fn long_status_change_lists_are_shortened() {
        assert_eq!(changes_list(&[3, 1, 0]), "[3, 1, 0]");
        let long: Vec<usize> = (0..111).collect();
        assert_eq!(changes_list(&long), "[0, 1, 2, 3, 4, 5, … 101 more …, 107, 108, 109, 110]");
    }
}
