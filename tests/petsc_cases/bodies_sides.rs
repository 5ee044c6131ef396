//! Which side of a pair is the slave, and pairs whose sides are out of the pairing range
//! (issue 23, item 6): the pointwise check after the solve names the right cause, and two
//! bodies too far apart to be paired solve without contact force, with a warning.
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::Error;

use super::contact::{example, solve_text};
use super::{ensure, manifest};

/// `examples/scenes/block_on_block.toml` with the block (0.04 wide, its bottom the shorter
/// side, lying within the foundation's top) moved to x = `x0`, cells of `block_cell` in the
/// block and `foundation_cell` in the foundation, and the pair's slave side the block's bottom
/// (`block_is_slave`) or the foundation's top.
fn blocks(x0: f64, block_cell: &str, foundation_cell: &str, block_is_slave: bool) -> (String, std::path::PathBuf) {
    let (text, path) = example("block_on_block.toml");
    let edits = [
        (
            "origin = [0.0, 0.0], size = [0.04, 0.04], cell_size = 1.25e-3",
            format!("origin = [{x0:?}, 0.0], size = [0.04, 0.04], cell_size = {block_cell}"),
        ),
        (
            "origin = [-0.02, -0.02], size = [0.08, 0.02], cell_size = 2.5e-3",
            format!("origin = [-0.02, -0.02], size = [0.08, 0.02], cell_size = {foundation_cell}"),
        ),
    ];
    let mut text = text;
    for (from, to) in edits {
        assert!(text.contains(from), "test bug: block_on_block.toml changed ({from})");
        text = text.replacen(from, &to, 1);
    }
    if !block_is_slave {
        let pair = "slave = \"block.bottom\"   # body.part\nmaster = \"foundation.top\"";
        assert!(text.contains(pair), "test bug: block_on_block.toml's pair changed");
        text = text.replacen(pair, "slave = \"foundation.top\"\nmaster = \"block.bottom\"", 1);
    }
    (text, path)
}

/// The pair's pointwise penetration (relative to the displacement scale), from report.json.
fn node_penetration(p: &ElasticityProblem, what: &str) -> Result<f64, String> {
    let report = p.report().map_err(|e| format!("{what}: report: {e}"))?;
    let bodies = report.bodies.ok_or_else(|| format!("{what}: no `bodies` in the report"))?;
    let np = bodies.contacts[0].node_penetration.as_ref().ok_or_else(|| format!("{what}: no node_penetration"))?;
    Ok(np.max_penetration)
}

/// The pointwise check's error: `(reason, tried)`.
fn check_error(result: Result<ElasticityProblem, Error>, what: &str) -> Result<(String, String), String> {
    match result {
        Err(Error::SolverDiverged { solver, reason, tried, .. }) if solver.contains("independent check") => {
            Ok((reason, tried))
        }
        Err(e) => Err(format!("{what}: wrong error: {e}")),
        Ok(_) => Err(format!("{what}: passed the pointwise check")),
    }
}

/// A block on a foundation twice as fine, pressed and pushed sideways (the example's loads,
/// Coulomb μ = 1), with the foundation's top as the slave side: the block's bottom, the master
/// side, ends inside the slave side.
///
/// - The block's corner on a slave node (x0 = 0): every slave node facing the block's bottom is
///   a contact point, the last one faced on half its support. Its row used to weigh the
///   master's displacement by the faced half of `∫φ`, `u_i − ½ ū_master ≤ 0`: the corner sank
///   into the foundation by 8.5 % of the displacement scale and the run was refused as "the
///   slave side is coarser" (it is twice as fine). Weighed by the faced part of `∫ψ`
///   (`contact/mortar/mod.rs`, "Coverage"), a rigid translation transfers exactly and the
///   corner stays out: measured 1.1e-15 of the displacement scale.
/// - The block moved by 0.6 mm (its corner 0.48 of a slave edge past the last contact point):
///   the next slave node faces no master edge, nothing holds the corner between the two, and it
///   goes in by 3.4e-2 of the displacement scale (1.5e-2 with cells 4 times finer: a finer
///   slave side does not cure it). The error now says so: the master side ends inside the slave
///   side; swap the sides. Swapped (the block's bottom, which lies within the foundation's top,
///   the slave side), the same scene passes (6e-5).
/// - A slave side coarser than the master side (the block's bottom with cells of 5 mm on the
///   foundation's top with 1.25 mm, the block moved by 0.6 mm): a foundation node between two
///   slave nodes goes in by 6.4e-3, and the error says the slave side is coarser, with both
///   spacings.
pub fn which_side_is_slave_decides_the_pointwise_check(s: &Session) -> Result<(), String> {
    // The corner on a slave node: passes, exactly.
    let (text, path) = blocks(0.0, "2.5e-3", "1.25e-3", false);
    let p = solve_text(s, &text, &path).map_err(|e| format!("corner on a slave node: {e}"))?;
    let exact = node_penetration(&p, "corner on a slave node")?;
    eprintln!("    master side ending on a slave node: pointwise penetration {exact:.1e}");
    ensure(exact < 1e-12, || format!("corner on a slave node: pointwise penetration {exact:e}"))?;

    // The corner between two slave nodes: refused, saying that the master side ends inside the
    // slave side and to swap the sides.
    let (text, path) = blocks(6e-4, "2.5e-3", "1.25e-3", false);
    let (reason, tried) = check_error(solve_text(s, &text, &path), "corner between slave nodes")?;
    eprintln!("    master side ending between slave nodes: {reason}");
    ensure(
        reason.contains("of body `block` on contact `foundation.top / block.bottom`")
            && tried.contains("at the end of the master side `block.bottom`, which ends inside the slave side")
            && tried.contains("swap `slave` and `master`")
            && !tried.contains("coarser"),
        || format!("corner between slave nodes: {reason}; {tried}"),
    )?;
    // Swapped: the block's bottom (within the foundation's top, and finer) is the slave side.
    let (text, path) = blocks(6e-4, "1.25e-3", "2.5e-3", true);
    let p = solve_text(s, &text, &path).map_err(|e| format!("swapped: {e}"))?;
    let swapped = node_penetration(&p, "swapped")?;
    eprintln!("    the block's bottom as the slave side: pointwise penetration {swapped:.1e}");
    ensure(swapped < 3e-4, || format!("swapped: pointwise penetration {swapped:e}"))?;

    // A coarser slave side: the message says so, with the two spacings.
    let (text, path) = blocks(6e-4, "5e-3", "1.25e-3", true);
    let (reason, tried) = check_error(solve_text(s, &text, &path), "coarse slave")?;
    eprintln!("    coarse slave side: {reason}");
    ensure(
        reason.contains("of body `foundation`")
            && tried.contains("between two slave nodes 5.000e-3 apart, where the master nodes are 1.250e-3 apart")
            && tried.contains("the slave side is coarser"),
        || format!("coarse slave: {reason}; {tried}"),
    )
}

/// Two blocks 0.5 m apart, each held by its supports, joined by a contact pair: the two sides
/// face each other, farther than the pairing distance (a tenth of the smaller side's extent,
/// 0.1 m). They used to be refused ("no slave node faces the master side"); now the run solves
/// them with no contact force and a `contact_pair_out_of_range` warning naming both distances,
/// and the answer is the one without the pair (the same displacement field to round-off). The
/// pointwise check still measures the two sides: pressed 60 times harder, the upper block goes
/// through the lower one and the run is refused.
pub fn bodies_out_of_pairing_range_solve_without_contact_force(s: &Session) -> Result<(), String> {
    let text = |pressure: &str, pair: bool| {
        let mut t = format!(
            "[[body]]\nname = \"top\"\n\
             mesh = {{ shape = \"rectangle\", origin = [0.0, 1.5], size = [1.0, 0.5], cell_size = 0.25 }}\n\
             material = {{ young = 1e9, poisson = 0.3 }}\n\
             [[body.traction]]\npart = \"top\"\npressure = {pressure}\n\
             [[body.dirichlet]]\npart = \"left\"\nux = 0.0\nuy = 0.0\n\n\
             [[body]]\nname = \"bottom\"\n\
             mesh = {{ shape = \"rectangle\", size = [2.0, 1.0], cell_size = 0.5 }}\n\
             material = {{ young = 2e9, poisson = 0.25 }}\n\
             [[body.dirichlet]]\npart = \"bottom\"\nux = 0.0\nuy = 0.0\n"
        );
        if pair {
            t += "\n[[contact_pair]]\nslave = \"top.bottom\"\nmaster = \"bottom.top\"\nfriction = \"coulomb\"\nmu = 0.3\n";
        }
        t
    };
    let path = manifest("apart.toml");
    let p = solve_text(s, &text("1e6", true), &path).map_err(|e| format!("0.5 m apart: {e}"))?;
    let free = solve_text(s, &text("1e6", false), &path).map_err(|e| format!("without the pair: {e}"))?;
    let warning = p.warnings.iter().find(|w| w.kind == "contact_pair_out_of_range");
    let message = warning.map(|w| w.message.as_str()).unwrap_or("");
    eprintln!("    0.5 m apart: {message}");
    ensure(
        message.contains("`top.bottom` / `bottom.top` (")
            && message.contains("5.000e-1 apart")
            && message.contains("pairing distance 1.000e-1")
            && message.contains("carries no force"),
        || format!("0.5 m apart: warnings {:?}", p.warnings),
    )?;
    ensure(p.contact.is_none() && free.warnings.iter().all(|w| w.kind != "contact_pair_out_of_range"), || {
        "0.5 m apart: contact points were made".into()
    })?;
    let (u, v) = (p.displacement.as_ref().ok_or("no displacement")?, free.displacement.as_ref().ok_or("no u")?);
    let size = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let difference = u.iter().zip(v).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    ensure(u.len() == v.len() && size > 1e-3 && difference <= 1e-12 * size, || {
        format!("0.5 m apart: the field differs from the one without the pair by {difference:e} (max |u| {size:e})")
    })?;
    let report = p.report().map_err(|e| e.to_string())?;
    let pair = &report.bodies.as_ref().ok_or("no bodies report")?.contacts;
    ensure(pair.len() == 1 && pair[0].points == 0 && pair[0].slave_resultant == [0.0; 2], || format!("{pair:?}"))?;

    // Pressed 0.57 m down: through the lower block, refused by the pointwise check.
    let (reason, tried) = check_error(solve_text(s, &text("6e7", true), &path), "pressed through")?;
    ensure(
        reason.contains("of body `top` on contact `top.bottom / bottom.top` penetrates the other side")
            && tried.contains("slave node that is not a contact point")
            && tried.contains("pairing distance 1.000e-1"),
        || format!("pressed through: {reason}; {tried}"),
    )
}
