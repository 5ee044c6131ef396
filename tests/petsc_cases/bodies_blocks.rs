//! Several bodies in contact (issue 13): the contact patch test on non-matching irregular
//! meshes, the square block on a very stiff elastic foundation against the rigid obstacle, a
//! stack of three blocks, and the errors of scenes with several bodies.

use super::edit::Edit;
use std::path::Path;

use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::Error;

use super::contact::{example, set_line, solve_text};
use super::{ensure, manifest};

/// The line (1-based) of the first line of `text` that starts with `start` after `after`
/// (a line number, 0 for the whole text).
fn line_of(text: &str, start: &str, after: usize) -> usize {
    text.lines()
        .enumerate()
        .skip(after)
        .find(|(_, l)| l.trim_start().starts_with(start))
        .map(|(i, _)| i + 1)
        .unwrap_or_else(|| panic!("test bug: no line starting with {start}"))
}

/// Contact force on the slave side of each point, summed: `Σ n_i rN_i + t_i rT_i`.
fn slave_resultant(p: &ElasticityProblem) -> [f64; 2] {
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let b = &c.boundary;
    let mut s = [0.0; 2];
    for i in 0..b.points() {
        for (k, sk) in s.iter_mut().enumerate() {
            *sk += b.normal[i][k] * o.force[2 * i] + b.tangent[i][k] * o.force[2 * i + 1];
        }
    }
    s
}

// ------------------------------------------------------------------ patch test

/// Two rectangles of the same width stacked: `lower` [0, 2] × [−1, 0] (E = 70 GPa, ν = 0.3,
/// bottom uy = 0, its lower-left corner ux = 0) and `upper` [0, 2] × [0, 1] (E = 210 GPa,
/// ν = 0.25, pressure P on its top, its upper-left corner ux = 0, held vertically by the
/// contact alone), frictionless. Both are gmsh meshes refined at different places of the
/// interface (upper near x = 0.5, lower near x = 1.4), so the interface nodes of the two sides
/// are irregular and never match (apart from the two end corners). The two sides have the same
/// extent: every slave node is fully covered by the master side.
pub(super) fn patch_text(order: u32) -> String {
    format!(
        r#"title = "two-body contact patch test on non-matching meshes"

[[body]]
name = "lower"
mesh = {{ shape = "rectangle", origin = [0.0, -1.0], size = [2.0, 1.0], cell_size = 0.25, mesher = "gmsh", refine = {{ point = [1.4, 0.0], cell_size = 0.07, radius = 0.3 }} }}
material = {{ young = 70e9, poisson = 0.3 }}
discretization = {{ order = {order} }}

[[body.dirichlet]]
part = "bottom"
uy = 0.0

[[body.dirichlet]]
point = [0.0, -1.0]
ux = 0.0

[[body]]
name = "upper"
mesh = {{ shape = "rectangle", origin = [0.0, 0.0], size = [2.0, 1.0], cell_size = 0.2, mesher = "gmsh", refine = {{ point = [0.5, 0.0], cell_size = 0.045, radius = 0.25 }} }}
material = {{ young = 210e9, poisson = 0.25 }}
discretization = {{ order = {order} }}

[[body.traction]]
part = "top"
pressure = 1e6

[[body.dirichlet]]
point = [0.0, 1.0]
ux = 0.0

[[contact_pair]]
slave = "upper.bottom"
master = "lower.top"
"#
    )
}

/// Exact to round-off: the issue's 1e-12 of the pressure and of the displacement, on the
/// default route (the full-space Newton with the floating elimination, the upper body held by
/// the contact alone; measured 1.1e-13 (P1) and 7.1e-13 (P2) in the pressure, 4e-14 in the
/// displacement). The condensed route's proximal iterations leave about 4e-12
/// (`bodies_full_space_patch_test` compares the two).
///
/// Uniform stress σyy = −P, σxx = 0 in both bodies (plane strain): each has
/// εxx = ν(1+ν)P/E, εyy = −(1−ν²)P/E; `ux = εxx x`, `uy = εyy,lower (y + 1)` below and
/// `uy = εyy,lower + εyy,upper y` above (the interface slides, frictionless).
fn patch_nonmatching(s: &Session, order: u32) -> Result<(), String> {
    let text = patch_text(order);
    let path = manifest("two_body_patch.toml");
    let p = solve_text(s, &text, &path).map_err(|e| format!("P{order}: {e}"))?;
    let pr = 1e6_f64;
    let strains = |e: f64, nu: f64| (nu * (1.0 + nu) * pr / e, -(1.0 - nu * nu) * pr / e);
    let (exx_lo, eyy_lo) = strains(70e9, 0.3);
    let (exx_up, eyy_up) = strains(210e9, 0.25);
    let model = p.bodies.as_ref().ok_or("no bodies model")?;
    let u = p.displacement.as_ref().unwrap();
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for (k, x) in p.mesh.nodes.iter().enumerate() {
        let exact = match model.layout.node_body(k) {
            Some(0) => [exx_lo * x[0], eyy_lo * (x[1] + 1.0)],
            Some(1) => [exx_up * x[0], eyy_lo + eyy_up * x[1]],
            other => return Err(format!("node {k} in body {other:?}")),
        };
        err = err.max((u[2 * k] - exact[0]).abs()).max((u[2 * k + 1] - exact[1]).abs());
        size = size.max(exact[0].hypot(exact[1]));
    }
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    // The interface really is non-matching: slave nodes that are not master nodes.
    let master_nodes: Vec<[f64; 2]> = (0..p.mesh.num_nodes())
        .filter(|&k| model.layout.node_body(k) == Some(0) && p.mesh.nodes[k][1].abs() < 1e-12)
        .map(|k| p.mesh.nodes[k])
        .collect();
    let unmatched = c
        .boundary
        .nodes
        .iter()
        .filter(|&&k| !master_nodes.iter().any(|m| (m[0] - p.mesh.nodes[k][0]).abs() < 1e-9))
        .count();
    ensure(unmatched + 2 >= c.boundary.points() && c.boundary.points() > master_nodes.len(), || {
        format!(
            "P{order}: the meshes match at {} of {} slave nodes",
            c.boundary.points() - unmatched,
            c.boundary.points()
        )
    })?;
    let (pressure, friction) = c.boundary.tractions(&o.force);
    let perr = pressure.iter().map(|q| (q - pr).abs() / pr).fold(0.0, f64::max);
    let terr = friction.iter().map(|q| q.abs() / pr).fold(0.0, f64::max);
    let r = p.bodies_report.as_ref().ok_or("no bodies report")?;
    let eq: Vec<f64> = r.bodies.iter().map(|b| b.equilibrium_residual).collect();
    let ar = r.contacts[0].action_reaction_residual.ok_or("no action-reaction residual")?;
    let resultant = r.contacts[0].slave_resultant;
    let np = r.contacts[0].node_penetration.as_ref().ok_or("no node_penetration")?;
    eprintln!(
        "    P{order}: {} slave points ({} master nodes), pressure error {perr:.2e}, friction {terr:.1e}, displacement \
         error {:.2e} (relative), equilibrium residuals {eq:?}, action-reaction {ar:.1e}, slave resultant {resultant:?}, \
         pointwise penetration {:.1e} ({} nodes)",
        c.boundary.points(),
        master_nodes.len(),
        err / size,
        np.max_penetration,
        np.measured_nodes
    );
    // Every master node but the two ends (level with the slave side's ends) faces the slave
    // side and is measured; the interface stays straight, so no node enters the other body.
    ensure(np.measured_nodes + 2 >= master_nodes.len() && np.max_penetration <= 1e-12, || {
        format!("P{order}: pointwise penetration {np:?}")
    })?;
    ensure(o.report.solver.starts_with("full-space"), || format!("P{order}: solved by {}", o.report.solver))?;
    // The docs' claim: the full-space route solves the non-matching patch in 1 Newton step.
    ensure(o.report.iterations == 1, || {
        format!("P{order}: {} full-space Newton steps, 1 expected", o.report.iterations)
    })?;
    ensure(o.report.open == 0, || format!("P{order}: {} open points", o.report.open))?;
    ensure(perr <= 1e-12 && terr == 0.0, || {
        format!("P{order}: contact pressure off by {perr:e} of the applied {pr:e} (friction {terr:e})")
    })?;
    ensure(err <= 1e-12 * size, || format!("P{order}: displacement error {:e} of {size:e}", err / size))?;
    ensure(eq.iter().all(|&e| e <= 1e-12), || format!("P{order}: equilibrium residuals {eq:?}"))?;
    ensure(ar <= 1e-13, || format!("P{order}: action-reaction residual {ar:e}"))?;
    ensure((resultant[1] - 2.0 * pr).abs() <= 1e-11 * 2.0 * pr && resultant[0].abs() <= 1e-12 * pr, || {
        format!("P{order}: contact resultant on the upper body {resultant:?}, applied (0, {:e})", 2.0 * pr)
    })
}

pub fn two_body_patch_nonmatching_p1(s: &Session) -> Result<(), String> {
    patch_nonmatching(s, 1)
}

pub fn two_body_patch_nonmatching_p2(s: &Session) -> Result<(), String> {
    patch_nonmatching(s, 2)
}

// ------------------------------------------------------------------ square block

/// The square block of square_block.toml (same mesh, loads, supports with the fixed corner,
/// Coulomb μ = 1) on a foundation of E × 1e4 clamped at its bottom, against the rigid
/// obstacle: the tangential displacements of the block's bottom and the contact resultant
/// within 1 %.
pub fn square_block_on_stiff_foundation(s: &Session) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let rigid_text = set_line(&text, "solver", "solver = \"newton\"");
    let rigid = solve_text(s, &rigid_text, &path).map_err(|e| format!("rigid obstacle: {e}"))?;
    let two_text = r#"title = "square block on a very stiff foundation"

[[body]]
name = "block"
mesh = { shape = "rectangle", origin = [0.0, 0.0], size = [0.04, 0.04], cell_size = 1.25e-3, mesher = "structured" }
material = { young = 1.3e11, poisson = 0.2, plane = "strain" }
discretization = { order = 1 }

[[body.traction]]
part = "top"
pressure = 5e7

[[body.traction]]
part = "left"
pressure = 1.5e8

[[body.dirichlet]]
part = "right"
ux = 0.0

[[body.dirichlet]]
point = [0.04, 0.0]
ux = 0.0
uy = 0.0

[[body]]
name = "foundation"
mesh = { shape = "rectangle", origin = [-0.02, -0.02], size = [0.08, 0.02], cell_size = 2.5e-3 }
material = { young = 1.3e15, poisson = 0.2, plane = "strain" }
discretization = { order = 1 }

[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0

[[contact_pair]]
slave = "block.bottom"
master = "foundation.top"
friction = "coulomb"
mu = 1.0
"#;
    let two = solve_text(s, two_text, &manifest("stiff_foundation.toml")).map_err(|e| format!("two bodies: {e}"))?;
    let model = two.bodies.as_ref().unwrap();
    let (ur, ut) = (rigid.displacement.as_ref().unwrap(), two.displacement.as_ref().unwrap());
    let (mut diff, mut size, mut count) = (0.0f64, 0.0f64, 0usize);
    for (k, x) in rigid.mesh.nodes.iter().enumerate().filter(|(_, x)| x[1].abs() < 1e-12) {
        let j = (0..two.mesh.num_nodes())
            .find(|&j| {
                model.layout.node_body(j) == Some(0)
                    && (two.mesh.nodes[j][0] - x[0]).abs() < 1e-12
                    && two.mesh.nodes[j][1].abs() < 1e-12
            })
            .ok_or_else(|| format!("no block node at ({}, 0)", x[0]))?;
        diff = diff.max((ur[2 * k] - ut[2 * j]).abs());
        size = size.max(ur[2 * k].abs());
        count += 1;
    }
    let (rr, rt) = (slave_resultant(&rigid), slave_resultant(&two));
    let rdiff = (rr[0] - rt[0]).hypot(rr[1] - rt[1]) / rr[0].hypot(rr[1]);
    let report = two.bodies_report.as_ref().unwrap();
    let eq: Vec<f64> = report.bodies.iter().map(|b| b.equilibrium_residual).collect();
    let ar = report.contacts[0].action_reaction_residual.unwrap();
    let (o_r, o_t) = (&rigid.contact_outcome.as_ref().unwrap().report, &two.contact_outcome.as_ref().unwrap().report);
    eprintln!(
        "    {count} bottom nodes: max |ux difference| {:.2e} of max ux {size:.3e}; resultant rigid {rr:?}, two bodies \
         {rt:?} ({rdiff:.2e}); stick/slip rigid {}/{}, two bodies {}/{}; equilibrium {eq:?}, action-reaction {ar:.1e}",
        diff / size,
        o_r.stick,
        o_r.slip,
        o_t.stick,
        o_t.slip
    );
    ensure(count == 33, || format!("{count} bottom nodes"))?;
    // The target is 1 %; the docs claim 4.0e-5 and 5.0e-5 (measured 4.02e-5 and 4.99e-5),
    // asserted to 1e-4, and the same stick/slip counts as on the rigid obstacle.
    ensure(diff <= 1e-4 * size, || format!("tangential displacement differs by {:.3e} of {size:e}", diff / size))?;
    ensure(rdiff <= 1e-4, || format!("contact resultant {rt:?} against the rigid {rr:?}: {rdiff:.3e}"))?;
    // (The open counts differ by the fixed corner (0.04, 0): left out of the rigid obstacle's
    // contact set, an open slave point of the pair; measured 3 and 4.)
    ensure((o_r.stick, o_r.slip) == (o_t.stick, o_t.slip) && o_t.open == o_r.open + 1, || {
        format!(
            "open/stick/slip: rigid {:?}, two bodies {:?}",
            (o_r.open, o_r.stick, o_r.slip),
            (o_t.open, o_t.stick, o_t.slip)
        )
    })?;
    ensure(eq.iter().all(|&e| e <= 1e-9) && ar <= 1e-12, || format!("equilibrium {eq:?}, action-reaction {ar:e}"))
}

// ------------------------------------------------------------------ three blocks

/// Three blocks, each narrower than the one below, their meshes not matching across either
/// interface: `base` [0, 3] × [−1, 0] clamped at its bottom; `middle` [0.5, 2.5] × [0, 1]
/// (gmsh) and `top` [1, 2] × [1, 1.6], pressed by P = 1e6 on the top, each with one point
/// ux = 0 and held vertically by the contact alone. Coulomb μ = 0.3 under the middle block,
/// frictionless under the top one.
pub(super) fn stack_text() -> String {
    r#"title = "three blocks stacked"

[[body]]
name = "base"
mesh = { shape = "rectangle", origin = [0.0, -1.0], size = [3.0, 1.0], cell_size = 0.23 }
material = { young = 70e9, poisson = 0.3 }

[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0

[[body]]
name = "middle"
mesh = { shape = "rectangle", origin = [0.5, 0.0], size = [2.0, 1.0], cell_size = 0.19, mesher = "gmsh" }
material = { young = 210e9, poisson = 0.3 }

[[body.dirichlet]]
point = [0.5, 1.0]
ux = 0.0

[[body]]
name = "top"
mesh = { shape = "rectangle", origin = [1.0, 1.0], size = [1.0, 0.6], cell_size = 0.07 }
material = { young = 110e9, poisson = 0.34 }

[[body.traction]]
part = "top"
pressure = 1e6

[[body.dirichlet]]
point = [1.0, 1.6]
ux = 0.0

[[contact_pair]]
slave = "middle.bottom"
master = "base.top"
friction = "coulomb"
mu = 0.3

[[contact_pair]]
slave = "top.bottom"
master = "middle.top"
"#
    .to_string()
}

pub fn three_block_stack(s: &Session) -> Result<(), String> {
    let p = solve_text(s, &stack_text(), &manifest("three_blocks.toml")).map_err(|e| e.to_string())?;
    let force = 1e6 * 1.0;
    let r = p.bodies_report.as_ref().ok_or("no bodies report")?;
    let names: Vec<&str> = r.bodies.iter().map(|b| b.name.as_str()).collect();
    ensure(names == ["base", "middle", "top"], || format!("bodies {names:?}"))?;
    ensure(r.contacts.len() == 2, || format!("{} contact parts", r.contacts.len()))?;
    for body in &r.bodies {
        eprintln!(
            "    body {}: applied {:?}, reaction {:?}, contact {:?}, equilibrium residual {:.1e}",
            body.name, body.applied_force, body.reaction, body.contact_force, body.equilibrium_residual
        );
        ensure(body.equilibrium_residual <= 1e-9, || format!("body {}: {}", body.name, body.equilibrium_residual))?;
    }
    for (c, mu) in r.contacts.iter().zip([0.3, 0.0]) {
        let (sr, mr) = (c.slave_resultant, c.master_resultant.unwrap());
        let ar = c.action_reaction_residual.unwrap();
        eprintln!(
            "    pair {}: {} points ({} open, {} stick, {} slip), slave {sr:?}, master {mr:?}, vertical error \
             {:.1e}, action-reaction {ar:.1e}",
            c.name,
            c.points,
            c.open,
            c.stick,
            c.slip,
            (sr[1] - force).abs() / force
        );
        ensure((sr[1] - force).abs() <= 1e-8 * force, || {
            format!("{}: vertical resultant {} of {force}", c.name, sr[1])
        })?;
        ensure(sr[0].abs() <= mu * sr[1] + 1e-8 * force, || format!("{}: horizontal resultant {}", c.name, sr[0]))?;
        ensure(ar <= 1e-12, || format!("{}: action-reaction residual {ar:e}", c.name))?;
        ensure(c.open < c.points, || format!("{}: no closed point", c.name))?;
    }
    // The frictionless interface transmits no horizontal force, the top block's point support
    // none either; the base carries the whole load.
    let base = &r.bodies[0];
    ensure((base.reaction[1] - force).abs() <= 1e-8 * force, || format!("base reaction {:?}", base.reaction))
}

// ------------------------------------------------------------------ errors

fn scene_error(result: Result<ElasticityProblem, Error>, what: &str) -> Result<(usize, String), String> {
    match result {
        Err(Error::Scene { location, message, .. }) => Ok((location.line, message)),
        Err(e) => Err(format!("{what}: wrong error: {e}")),
        Ok(_) => Err(format!("{what}: solved")),
    }
}

pub fn bodies_errors_name_what_is_wrong(s: &Session) -> Result<(), String> {
    let path = manifest("bodies_errors.toml");
    let path: &Path = &path;
    // A Tresca pair and a Coulomb pair: one friction law per run, at the Tresca pair.
    let text = stack_text().edit(
        "slave = \"top.bottom\"\nmaster = \"middle.top\"\n",
        "slave = \"top.bottom\"\nmaster = \"middle.top\"\nfriction = \"tresca\"\nthreshold = 1e5\n",
    );
    let (line, message) = scene_error(solve_text(s, &text, path), "Tresca and Coulomb")?;
    let tresca_pair = line_of(&text, "[[contact_pair]]", line_of(&text, "[[contact_pair]]", 0));
    ensure(line == tresca_pair && message.contains("Tresca") && message.contains("Coulomb"), || {
        format!("Tresca and Coulomb: line {line} (the pair is at {tresca_pair}): {message}")
    })?;
    ensure(message.contains("top.bottom") && message.contains("middle.bottom"), || {
        format!("Tresca and Coulomb: {message}")
    })?;

    // A body held by nothing.
    let (base, _) = example("block_on_block.toml");
    let text = format!(
        "{base}\n[[body]]\nname = \"loose\"\nmesh = {{ shape = \"rectangle\", origin = [1.0, 1.0], size = [0.1, 0.1], \
         cell_size = 0.02 }}\nmaterial = {{ young = 7e10, poisson = 0.3 }}\n"
    );
    match solve_text(s, &text, path) {
        Err(Error::Unconstrained(m)) => {
            ensure(m.contains("body `loose`") && m.contains("held by nothing"), || format!("loose body: {m}"))?
        }
        Err(e) => return Err(format!("loose body: wrong error: {e}")),
        Ok(_) => return Err("loose body: solved".into()),
    }

    // snes_vi in a body's [contact] while a pair is present.
    let at = base.find("[[contact_pair]]").unwrap();
    let text = format!(
        "{}[body.contact]\npart = \"left\"\nobstacle = \"line\"\npoint = [-0.03, 0.0]\nnormal = [1.0, 0.0]\nsolver = \
         \"snes_vi\"\n\n{}",
        &base[..at],
        &base[at..]
    );
    let (line, message) = scene_error(solve_text(s, &text, path), "snes_vi")?;
    let table = line_of(&text, "[body.contact]", 0);
    ensure(line > table && line <= table + 5 && message.contains("snes_vi"), || {
        format!("snes_vi: line {line} ([body.contact] at {table}): {message}")
    })?;

    // Pair parts that do not face each other: the block moved off the foundation.
    let text = base.replacen("origin = [0.0, 0.0]", "origin = [0.2, 0.0]", 1);
    let (line, message) = scene_error(solve_text(s, &text, path), "not facing")?;
    let pair = line_of(&text, "[[contact_pair]]", 0);
    ensure(line == pair && message.contains("block.bottom") && message.contains("foundation.top"), || {
        format!("not facing: line {line} (pair at {pair}): {message}")
    })?;

    // A body pulled away from the one it rests on, held by the contact alone: an error, with
    // and without friction.
    let lifted = base.replacen("pressure = 5e7", "pressure = -5e7", 1);
    for text in [lifted.clone(), set_line(&set_line(&lifted, "friction", "friction = \"none\""), "mu", "")] {
        match solve_text(s, &text, path) {
            Err(Error::Unconstrained(m)) => {
                ensure(m.contains("lifts off") && m.contains("body `block`"), || format!("lift-off: {m}"))?
            }
            Err(e) => return Err(format!("lift-off: wrong error: {e}")),
            Ok(p) => {
                return Err(format!(
                    "lift-off: a body pulled away got an answer: {:?}",
                    p.contact_outcome.map(|o| o.report.stabilisation_force)
                ))
            }
        }
    }
    Ok(())
}

/// A point condition of one body where another body has a node at the same place: the
/// foundation of block_on_block.toml held in x at (0.04, 0), the block's bottom-right corner
/// too. The condition takes the foundation's node, and so does its reaction in the report (it
/// used to be looked up on the union mesh, which found the block's node first: its reaction
/// went missing). That node is also a master node of the pair with a prescribed component:
/// its entry leaves the contact rows (it used to stay, on a fixed dof, and the run failed its
/// global equilibrium check), and its share of the contact force goes to the support. The
/// reactions of every condition then balance the loads — the foundation's bottom and point
/// reactions equal the block's loads and right-side reaction, reversed — and the pair's
/// action–reaction and both bodies' equilibrium hold.
pub fn point_condition_at_a_shared_place_is_its_bodys(s: &Session) -> Result<(), String> {
    let (base, path) = example("block_on_block.toml");
    let anchor = "[[contact_pair]]";
    let at = base.find(anchor).ok_or("test bug: no contact pair in block_on_block.toml")?;
    let text = format!("{}[[body.dirichlet]]\npoint = [0.04, 0.0]\nux = 0.0\n\n{}", &base[..at], &base[at..]);
    let p = solve_text(s, &text, &path).map_err(|e| format!("solve: {e}"))?;
    let report = p.report().map_err(|e| e.to_string())?;
    let results = report.results.ok_or("no results")?;
    let reaction = |key: &str| {
        results.reactions.iter().find(|(k, _)| k.contains(key)).map(|(_, r)| *r).ok_or(format!("no reaction {key}"))
    };
    let point = reaction("0.04")?;
    let (bottom, right) = (reaction("foundation.bottom")?, reaction("block.right")?);
    eprintln!(
        "    point reaction {point:?}, foundation bottom {bottom:?}, block right {right:?}, applied {:?}, equilibrium {:.1e}",
        results.applied_force, results.equilibrium_residual
    );
    let scale = results.applied_force[0].hypot(results.applied_force[1]);
    ensure(point[0].abs() > 1e-3 * scale && point[1] == 0.0, || format!("point reaction {point:?}"))?;
    ensure(results.equilibrium_residual < 1e-10, || format!("equilibrium {:e}", results.equilibrium_residual))?;
    // The foundation's supports carry what the contact gives it: the block's loads plus the
    // block's own support reaction.
    let block = [results.applied_force[0] + right[0], results.applied_force[1] + right[1]];
    let foundation = [bottom[0] + point[0], bottom[1] + point[1]];
    ensure((block[0] + foundation[0]).hypot(block[1] + foundation[1]) <= 1e-9 * scale, || {
        format!("foundation reactions {foundation:?} against the block's loads and reaction {block:?}")
    })?;
    let bodies = p.bodies_report.as_ref().ok_or("no bodies report")?;
    let ar = bodies.contacts[0].action_reaction_residual.ok_or("no action-reaction residual")?;
    let eq: Vec<f64> = bodies.bodies.iter().map(|b| b.equilibrium_residual).collect();
    ensure(ar < 1e-12 && eq.iter().all(|&e| e < 1e-10), || format!("action-reaction {ar:e}, equilibrium {eq:?}"))
}
