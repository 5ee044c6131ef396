//! Interface laws (issue 26), the core: the thin layer on the condensed route, static and on a
//! load path, against closed forms (uniform stress: every point's jump is σ/K), the Signorini
//! limit of a stiff cut layer, and the refusals. Scenes are written in TOML without the
//! interface table (parsed by another lane) and given their law in Rust.
use std::path::PathBuf;

use super::contact::{example, set_line};
use signorini::error::Location;
use signorini::evolution::{EachIncrement, LoadPath};
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::{InterfaceLawSpec, InterfaceSpec, RccmSpec, Scene, ThinLayerSpec};
use signorini::Error;

fn ensure(ok: bool, message: impl FnOnce() -> String) -> Result<(), String> {
    if ok {
        Ok(())
    } else {
        Err(message())
    }
}

fn file(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(name)
}

fn at() -> Location {
    Location { file: file("interface.toml"), line: 1, column: 1 }
}

/// The layer of the tests: E = 1 GPa, ν = 0.3, 1 mm thick.
const LAYER: ThinLayerSpec = ThinLayerSpec { young: 1e9, poisson: 0.3, thickness: 1e-3, bonded: true };

fn layer(spec: ThinLayerSpec) -> Option<InterfaceSpec> {
    Some(InterfaceSpec { law: InterfaceLawSpec::ThinLayer(spec), trace: Vec::new(), at: at() })
}

/// `(K_N, K_T)` of a layer in plane strain (independent of the code: the Lamé constants).
fn stiffness(spec: &ThinLayerSpec) -> (f64, f64) {
    let (e, nu, h) = (spec.young, spec.poisson, spec.thickness);
    let mu = e / (2.0 * (1.0 + nu));
    let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
    ((lambda + 2.0 * mu) / h, mu / h)
}

/// Body E = 90 GPa, ν = 0.2, [−1, 1] × [0, 1] on the line y = 0, no support (held by the
/// interface alone), pressed by p = 1 MPa on top with the side pressures νp/(1 − ν) and sheared
/// by q = 0.3 p on the top and the sides: a uniform stress σyy = −p, σxy = q (plane strain).
/// With `path`, the keys `press` and `shear` and the `[evolution]` table `path`.
fn patch_text(friction: &str, path: Option<&str>) -> String {
    let (p, nu) = (1e6_f64, 0.2_f64);
    let side = nu * p / (1.0 - nu);
    let q = 0.3 * p;
    let (press, shear) = if path.is_some() { ("name = \"press\"", "name = \"shear\"") } else { ("", "") };
    format!(
        r#"
title = "thin layer patch"
[mesh]
shape = "rectangle"
origin = [-1.0, 0.0]
size = [2.0, 1.0]
cell_size = 0.25
mesher = "structured"
[material]
young = 90e9
poisson = 0.2
[[traction]]
part = "top"
traction = [0.0, {mp:e}]
{press}
[[traction]]
part = "right"
traction = [{ms:e}, 0.0]
{press}
[[traction]]
part = "left"
traction = [{side:e}, 0.0]
{press}
[[traction]]
part = "top"
traction = [{q:e}, 0.0]
{shear}
[[traction]]
part = "right"
traction = [0.0, {q:e}]
{shear}
[[traction]]
part = "left"
traction = [0.0, {mq:e}]
{shear}
[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
{friction}
{path}
"#,
        mp = -p,
        ms = -side,
        mq = -q,
        path = path.unwrap_or(""),
    )
}

fn scene_with(text: &str, interface: Option<InterfaceSpec>) -> Result<Scene, String> {
    let mut scene = Scene::from_str(text, &file("interface_patch.toml")).map_err(|e| e.to_string())?;
    scene.contact.as_mut().ok_or("no contact")?.interface = interface;
    Ok(scene)
}

fn solve_scene(s: &Session, scene: Scene) -> Result<ElasticityProblem<'_>, Error> {
    let mut p = ElasticityProblem::setup_system(s, scene)?;
    p.assemble()?;
    p.solve()?;
    p.postprocess()?;
    Ok(p)
}

/// The patch's exact answer at loads `press · p` and `shear · q`: the largest difference of
/// the displacement from `u = (q/K_T + 2(1+ν) q y/E, −p/K_N − (1+ν)(1−2ν) p y/(E(1−ν)))`
/// relative to its largest value, and of every point's tractions and jumps (the snapshot) from
/// `t = (−p, −q t_x)`, opening `= t_N / K_N`, slip `= −t_T / K_T`, relative to p and p/K_N.
fn patch_errors(p: &ElasticityProblem, press: f64, shear: f64, layer: &ThinLayerSpec) -> Result<(f64, f64), String> {
    let (e, nu) = (90e9_f64, 0.2_f64);
    let (pr, q) = (1e6 * press, 0.3e6 * shear);
    let (kn, kt) = stiffness(layer);
    let u = p.displacement.as_ref().ok_or("no displacement")?;
    let exact = |x: [f64; 2]| {
        [
            q / kt + 2.0 * (1.0 + nu) * q * x[1] / e,
            -pr / kn - (1.0 + nu) * (1.0 - 2.0 * nu) * pr * x[1] / (e * (1.0 - nu)),
        ]
    };
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for (k, x) in p.mesh.nodes.iter().enumerate() {
        let ex = exact(*x);
        err = err.max((u[2 * k] - ex[0]).abs()).max((u[2 * k + 1] - ex[1]).abs());
        size = size.max(ex[0].abs()).max(ex[1].abs());
    }
    let snapshot = p.interface.as_ref().ok_or("no interface snapshot")?;
    let c = p.contact.as_ref().ok_or("no contact")?;
    ensure(snapshot.points.len() == c.boundary.points(), || "a snapshot point per contact point".into())?;
    let mut jump_err = 0.0f64;
    for (i, point) in snapshot.points.iter().enumerate() {
        let tx = c.boundary.tangent[i][0];
        let (tn, tt) = (-pr, -q * tx);
        let scale_t = 1e6;
        let scale_u = 1e6 / kn;
        jump_err = jump_err
            .max((point.traction_normal - tn).abs() / scale_t)
            .max((point.traction_tangential - tt).abs() / scale_t)
            .max((point.opening - tn / kn).abs() / scale_u)
            .max((point.slip + tt / kt).abs() / scale_u);
        let x = p.mesh.nodes[c.boundary.nodes[i]];
        ensure(point.x == x, || format!("point {i} at {:?}, its node at {x:?}", point.x))?;
    }
    Ok((err / size.max(1e-300), jump_err))
}

/// A block on a bonded thin layer on a rigid line, under uniform pressure and shear: every
/// point's jump is σ/K_N and τ/K_T and the field is the closed form, to round-off.
pub fn thin_layer_bonded_patch(s: &Session) -> Result<(), String> {
    let p = solve_scene(s, scene_with(&patch_text("", None), layer(LAYER))?).map_err(|e| e.to_string())?;
    let (field, jumps) = patch_errors(&p, 1.0, 1.0, &LAYER)?;
    let o = p.contact_outcome.as_ref().unwrap();
    let snapshot = p.interface.as_ref().unwrap();
    eprintln!(
        "    bonded layer: stabilisation {} iterations, force {:?}; displacement error {field:.2e}, tractions/jumps error {jumps:.2e}, {} staggered \
         iteration(s), solver {}, notes {:?}",
        o.report.stabilisation_iterations,
        o.report.stabilisation_force,
        snapshot.iterations,
        o.report.solver,
        o.report.notes
    );
    ensure(
        snapshot.laws == vec!["thin_layer".to_string()] && snapshot.time == 1.0 && snapshot.iterations == 1,
        || format!("snapshot {:?} at {}, {} iterations", snapshot.laws, snapshot.time, snapshot.iterations),
    )?;
    ensure(o.report.notes.iter().any(|n| n.contains("condensed route")), || format!("notes {:?}", o.report.notes))?;
    ensure(snapshot.points.iter().all(|q| q.law_residual <= 1e-9), || "law residuals".into())?;
    ensure(field <= 1e-9 && jumps <= 1e-9, || format!("displacement error {field:e}, jumps {jumps:e}"))?;
    Ok(())
}

/// The same patch with a cut layer (unilateral contact, Coulomb μ = 0.5 > q/p: every point
/// pressed and sticking) equals the bonded layer.
pub fn thin_layer_cut_in_compression_equals_bonded(s: &Session) -> Result<(), String> {
    let cut = ThinLayerSpec { bonded: false, ..LAYER };
    let text = patch_text("friction = \"coulomb\"\nmu = 0.5", None);
    let pc = solve_scene(s, scene_with(&text, layer(cut))?).map_err(|e| e.to_string())?;
    // A bonded layer has no friction (the scene refuses one beside it).
    let pb = solve_scene(s, scene_with(&patch_text("", None), layer(LAYER))?).map_err(|e| e.to_string())?;
    let (uc, ub) = (pc.displacement.as_ref().unwrap(), pb.displacement.as_ref().unwrap());
    let size = ub.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let diff = uc.iter().zip(ub).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / size;
    let (field, jumps) = patch_errors(&pc, 1.0, 1.0, &cut)?;
    let o = pc.contact_outcome.as_ref().unwrap();
    eprintln!(
        "    cut layer in compression: {} stick of {} points, difference from the bonded layer {diff:.2e}, \
         displacement error {field:.2e}, jumps {jumps:.2e}",
        o.report.stick, o.report.points
    );
    ensure(o.report.stick == o.report.points, || format!("{} of {} points stick", o.report.stick, o.report.points))?;
    ensure(diff <= 1e-9 && field <= 1e-9 && jumps <= 1e-9, || {
        format!("cut vs bonded {diff:e}, field {field:e}, jumps {jumps:e}")
    })
}

/// A cut layer with K → ∞ is Signorini–Coulomb: the square block (Raous; 16 cells a side),
/// with open, sticking and slipping points, solved by the condensed Newton without a layer and
/// with cut layers of growing stiffness. The difference decreases like 1/K and ends below 1e-8.
pub fn thin_layer_stiff_limit_is_signorini(s: &Session) -> Result<(), String> {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "cell_size", "cell_size = 2.5e-3");
    let text = set_line(&text, "solver", "solver = \"newton\"");
    let text =
        set_line(&text, "pressure = 5e7", "pressure = 5e7\n[[traction]]\npart = \"top\"\ntraction = [-2e7, 0.0]");
    let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let plain = solve_scene(s, scene.clone()).map_err(|e| e.to_string())?;
    let o = plain.contact_outcome.as_ref().unwrap();
    let (open, stick, slip) = (o.report.open, o.report.stick, o.report.slip);
    ensure(open > 0 && stick > 0 && slip > 0, || format!("open {open}, stick {stick}, slip {slip}: not a mixed case"))?;
    let up = plain.displacement.clone().unwrap();
    let rp = o.force.clone();
    let mut differences = Vec::new();
    for young in [1e18, 1e20] {
        let mut scene = scene.clone();
        let spec = ThinLayerSpec { young, poisson: 0.3, thickness: 1e-3, bonded: false };
        scene.contact.as_mut().unwrap().interface = layer(spec);
        let p = solve_scene(s, scene).map_err(|e| format!("E = {young:e}: {e}"))?;
        let u = p.displacement.as_ref().unwrap();
        let r = &p.contact_outcome.as_ref().unwrap().force;
        let size = up.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let force = rp.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let du = u.iter().zip(&up).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / size;
        let dr = r.iter().zip(&rp).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / force;
        let q = p.contact_outcome.as_ref().unwrap();
        ensure(q.status == o.status, || format!("E = {young:e}: the statuses differ from Signorini's"))?;
        differences.push(du.max(dr));
    }
    eprintln!(
        "    stiff cut layer: {open} open, {stick} stick, {slip} slip points; difference from Signorini–Coulomb \
         {} (layer E = 1e18, 1e20 Pa)",
        differences.iter().map(|d| format!("{d:.2e}")).collect::<Vec<_>>().join(", ")
    );
    ensure(differences[1] <= 1e-8, || format!("differences {differences:?}"))?;
    ensure(differences[1] < 0.1 * differences[0], || format!("no decrease with K: {differences:?}"))
}

/// Two bodies glued by a bonded layer under uniform compression: the jump is σ/K_N.
/// The non-matching two-body patch of `bodies_blocks` with one material in both bodies (so that
/// the interface has no tangential jump): `u_upper − u_lower = −P/K_N` along y at the interface.
pub fn thin_layer_glues_two_bodies(s: &Session) -> Result<(), String> {
    let text =
        super::bodies_blocks::patch_text(1).replace("young = 210e9, poisson = 0.25", "young = 70e9, poisson = 0.3");
    let mut scene = Scene::from_str(&text, &file("two_body_layer.toml")).map_err(|e| e.to_string())?;
    scene.contact_pairs[0].interface = layer(LAYER);
    let p = solve_scene(s, scene).map_err(|e| e.to_string())?;
    let (kn, _) = stiffness(&LAYER);
    let pr = 1e6_f64;
    let (e, nu) = (70e9_f64, 0.3_f64);
    let (exx, eyy) = (nu * (1.0 + nu) * pr / e, -(1.0 - nu * nu) * pr / e);
    let model = p.bodies.as_ref().ok_or("no bodies model")?;
    let u = p.displacement.as_ref().unwrap();
    let (mut err, mut size) = (0.0f64, 0.0f64);
    for (k, x) in p.mesh.nodes.iter().enumerate() {
        let exact = match model.layout.node_body(k) {
            Some(0) => [exx * x[0], eyy * (x[1] + 1.0)],
            Some(1) => [exx * x[0], eyy * (x[1] + 1.0) - pr / kn],
            other => return Err(format!("node {k} in body {other:?}")),
        };
        err = err.max((u[2 * k] - exact[0]).abs()).max((u[2 * k + 1] - exact[1]).abs());
        size = size.max(exact[0].hypot(exact[1]));
    }
    let snapshot = p.interface.as_ref().ok_or("no snapshot")?;
    let jump = snapshot
        .points
        .iter()
        .map(|q| ((q.opening + pr / kn).abs() / (pr / kn)).max((q.traction_normal + pr).abs() / pr))
        .fold(0.0, f64::max);
    eprintln!(
        "    two bodies glued by a bonded layer: displacement error {:.2e}, jump/traction error {jump:.2e}, laws {:?}",
        err / size,
        snapshot.laws
    );
    ensure(snapshot.laws == vec!["thin_layer".to_string()], || format!("laws {:?}", snapshot.laws))?;
    ensure(err <= 1e-9 * size && jump <= 1e-9, || format!("displacement error {:e}, jump {jump:e}", err / size))
}

/// A thin-layer load path: pressed on t ∈ [0, 1], then sheared forth and back (q: 0 → 1 → −1 →
/// 0 on [1, 4]), bonded and cut (Coulomb μ = 0.5: every point sticks). At every increment the
/// snapshot is the increment's (time, tractions and jumps σ/K) and the field is the closed
/// form: for the cut layer this needs the slip so far measured on u' = u + c r (the layer's
/// shear is not slip: measured on u, the sticking points would be pulled back by c r_T at the
/// next increment).
pub fn thin_layer_load_path(s: &Session) -> Result<(), String> {
    let evolution = "[evolution]\nsteps = 8\n[evolution.factor]\npress = [[0, 0], [1, 1], [4, 1]]\nshear = [[0, 0], \
                     [1, 0], [2, 1], [3, -1], [4, 0]]";
    for spec in [LAYER, ThinLayerSpec { bonded: false, ..LAYER }] {
        let name = if spec.bonded { "bonded" } else { "cut" };
        let friction = if spec.bonded { "" } else { "friction = \"coulomb\"\nmu = 0.5" };
        let text = patch_text(friction, Some(evolution));
        let scene = scene_with(&text, layer(spec))?;
        let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
        let mut pr = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
        pr.assemble().map_err(|e| e.to_string())?;
        let (mut worst_field, mut worst_jump, mut count) = (0.0f64, 0.0f64, 0);
        let mut problems = Vec::new();
        pr.solve_load_path(&path, EachIncrement::Postprocess, &mut |q, record| {
            count += 1;
            let t = record.time;
            let (press, shear) = (path.factor(Some("press"), t), path.factor(Some("shear"), t));
            match patch_errors(q, press, shear, &spec) {
                Ok((field, jump)) => {
                    worst_field = worst_field.max(field);
                    worst_jump = worst_jump.max(jump);
                }
                Err(e) => problems.push(format!("t = {t}: {e}")),
            }
            let snapshot = q.interface.as_ref().expect("a snapshot");
            if snapshot.time != t {
                problems.push(format!("t = {t}: snapshot at {}", snapshot.time));
            }
            Ok(())
        })
        .map_err(|e| format!("{name}: {e}"))?;
        eprintln!(
            "    {name} layer on a path: {count} increments, worst displacement error {worst_field:.2e}, worst \
             traction/jump error {worst_jump:.2e}"
        );
        ensure(problems.is_empty(), || format!("{name}: {}", problems.join("; ")))?;
        // The cut layer's increments are held by friction: the contact solve's stopping
        // tolerance (1e-9) shows (measured: 4.5e-10 in the field, 6.5e-9 of p/K_N in the jumps
        // at t = 1; 1e-12 elsewhere); the bonded layer has no contact solve (1e-12).
        let tolerance = if spec.bonded { 1e-10 } else { 1e-8 };
        ensure(count == 8 && worst_field <= tolerance && worst_jump <= tolerance, || {
            format!("{name}: {count} increments, field {worst_field:e}, jumps {worst_jump:e}")
        })?;
    }
    Ok(())
}

fn formulation_error(result: Result<impl Sized, Error>, what: &str, expect: &[&str]) -> Result<(), String> {
    match result {
        Err(e @ Error::Formulation { .. }) => {
            let text = e.to_string();
            ensure(expect.iter().all(|w| text.contains(w)), || format!("{what}: {text}"))
        }
        Err(other) => Err(format!("{what}: expected a formulation error, got {other}")),
        Ok(_) => Err(format!("{what}: accepted")),
    }
}

/// What an interface law cannot run with is refused, naming the contact and what to do:
/// snes_vi and tao (plain Signorini only), the dual formulation and the estimate, and a law
/// with memory in a static run.
pub fn interface_law_refusals(s: &Session) -> Result<(), String> {
    let text = patch_text("", None);
    for solver in ["snes_vi", "tao"] {
        let friction = if solver == "tao" { "friction = \"tresca\"\nthreshold = 1e5" } else { "" };
        // Tresca needs a cut layer (a bonded one has no friction).
        let spec = if solver == "tao" { ThinLayerSpec { bonded: false, ..LAYER } } else { LAYER };
        let mut scene = scene_with(&patch_text(friction, None), layer(spec))?;
        scene.contact.as_mut().unwrap().solver = match solver {
            "snes_vi" => signorini::scene::ContactSolverSpec::SnesVi,
            _ => signorini::scene::ContactSolverSpec::Tao,
        };
        formulation_error(
            ElasticityProblem::setup_system(s, scene).map(|_| ()),
            solver,
            &["`bottom`", "thin_layer", solver, "leave out `solver`"],
        )?;
    }
    let scene = scene_with(&text, layer(LAYER))?;
    formulation_error(
        signorini::interface_law::refuse_dual(&scene, "the estimate (--estimate)"),
        "refuse_dual",
        &["the error in the constitutive relation with an interface law is not implemented", "`bottom`"],
    )?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    formulation_error(p.solve_dual(), "solve_dual", &["not implemented", "thin_layer"])?;
    formulation_error(p.estimate(), "estimate", &["not implemented"])?;
    let rccm = RccmSpec {
        normal_stiffness: 1e15,
        tangential_stiffness: 1e15,
        adhesion_energy: 1.0,
        viscosity: 0.0,
        mu: 0.3,
        initial_adhesion: 1.0,
    };
    let scene =
        scene_with(&text, Some(InterfaceSpec { law: InterfaceLawSpec::Rccm(rccm), trace: Vec::new(), at: at() }))?;
    // A scene built in Rust is checked like a file when the problem is set up: the scene's own
    // error (at the law's line) comes first.
    match solve_scene(s, scene) {
        Err(e @ Error::Scene { .. }) => {
            let text = e.to_string();
            ensure(["rccm", "memory", "[evolution]"].iter().all(|w| text.contains(w)), || {
                format!("rccm static: {text}")
            })
        }
        Err(other) => Err(format!("rccm static: expected a scene error, got {other}")),
        Ok(_) => Err("rccm static: accepted".into()),
    }
}

/// Per-part laws: the three-block stack of `bodies_blocks` with the top pair glued by a bonded
/// layer and the lower pair plain Coulomb. Each top-pair point follows the layer's law
/// (`t_N = K_N (opening − g0)`, `t_T = −K_T slip`), each lower-pair point has no law, every
/// body is in equilibrium and each pair carries the top load.
pub fn thin_layer_on_one_pair_of_three_bodies(s: &Session) -> Result<(), String> {
    let mut scene =
        Scene::from_str(&super::bodies_blocks::stack_text(), &file("three_blocks.toml")).map_err(|e| e.to_string())?;
    scene.contact_pairs[1].interface = layer(LAYER);
    let p = solve_scene(s, scene).map_err(|e| e.to_string())?;
    let (kn, kt) = stiffness(&LAYER);
    let c = p.contact.as_ref().unwrap();
    let parts = c.parts.as_ref().ok_or("no contact parts")?;
    let snapshot = p.interface.as_ref().ok_or("no snapshot")?;
    ensure(snapshot.laws == ["signorini", "thin_layer"], || format!("laws {:?}", snapshot.laws))?;
    let force = 1e6;
    let (mut worst, mut layer_points, mut layer_force) = (0.0f64, 0, 0.0);
    for (i, q) in snapshot.points.iter().enumerate() {
        if parts.part_of[i] == 1 {
            layer_points += 1;
            layer_force += q.traction_normal * c.boundary.weight[i];
            let tn = kn * (q.opening - c.boundary.gap[i]);
            let tt = -kt * q.slip;
            worst = worst.max((q.traction_normal - tn).abs() / force).max((q.traction_tangential - tt).abs() / force);
        } else if q.law_residual != 0.0 {
            return Err(format!("point {i} of the plain pair has a law residual {}", q.law_residual));
        }
    }
    let r = p.bodies_report.as_ref().ok_or("no bodies report")?;
    let equilibrium = r.bodies.iter().map(|b| b.equilibrium_residual).fold(0.0, f64::max);
    let vertical: Vec<f64> = r.contacts.iter().map(|c| (c.slave_resultant[1] - force).abs() / force).collect();
    eprintln!(
        "    layer on one pair of three: {layer_points} layer points, law error {worst:.2e}, layer resultant {:.6e}, \
         equilibrium {equilibrium:.1e}, vertical resultant errors {vertical:?}",
        -layer_force
    );
    ensure(layer_points > 0 && layer_points < snapshot.points.len(), || format!("{layer_points} layer points"))?;
    ensure(worst <= 1e-9, || format!("layer law error {worst:e}"))?;
    ensure((layer_force + force).abs() <= 1e-8 * force, || format!("layer resultant {layer_force}"))?;
    ensure(equilibrium <= 1e-9 && vertical.iter().all(|&v| v <= 1e-8), || {
        format!("equilibrium {equilibrium:e}, vertical {vertical:?}")
    })
}

/// RCCM between two deformable bodies (a mortar pair): two blocks glued by the adhesive, the
/// lower one held at its base, the upper one pulled off by its top (ν = 0: the fields are
/// uniform) past the adhesive's peak to three times its critical opening. At every increment
/// and every point the traction and β lie on the closed form of the rate-independent law
/// (b = 0, monotone opening u): β = min(1, w/(C_N u²)), σ = C_N β² u — C_N u up to
/// u_c = √(w/C_N), then w²/(C_N u³) — whatever the blocks' stretch takes of the pull.
pub fn rccm_glues_two_bodies_until_they_pull_off(s: &Session) -> Result<(), String> {
    let (cn, w) = (1e10_f64, 1.0_f64);
    let text = format!(
        r#"title = "two blocks glued by RCCM, pulled apart"

[[body]]
name = "base"
mesh = {{ shape = "rectangle", origin = [0.0, -0.01], size = [0.02, 0.01], cell_size = 0.0025 }}
material = {{ young = 1e10, poisson = 0.0 }}

[[body.dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0

[[body]]
name = "top"
mesh = {{ shape = "rectangle", origin = [0.0, 0.0], size = [0.02, 0.01], cell_size = 0.002 }}
material = {{ young = 1e10, poisson = 0.0 }}

[[body.dirichlet]]
part = "top"
ux = 0.0
uy = 3e-5
name = "pull"

[[contact_pair]]
slave = "top.bottom"
master = "base.top"
interface = {{ law = "rccm", normal_stiffness = {cn:e}, tangential_stiffness = {cn:e}, adhesion_energy = {w:e} }}

[evolution]
steps = 30

[evolution.factor]
pull = [[0, 0], [1, 1]]
"#
    );
    let scene = Scene::from_str(&text, &file("rccm_pair.toml")).map_err(|e| e.to_string())?;
    let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
    let mut pr = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    pr.assemble().map_err(|e| e.to_string())?;
    let uc = (w / cn).sqrt();
    let peak = (cn * w).sqrt();
    let (mut worst_traction, mut worst_beta, mut largest_opening, mut count) = (0.0f64, 0.0f64, 0.0f64, 0);
    let mut laws = Vec::new();
    pr.solve_load_path(&path, EachIncrement::Postprocess, &mut |q, _| {
        count += 1;
        let snapshot = q.interface.as_ref().expect("a snapshot");
        laws = snapshot.laws.clone();
        for point in &snapshot.points {
            let u = point.opening;
            let beta = if u <= 0.0 { 1.0 } else { (w / (cn * u * u)).min(1.0) };
            worst_traction = worst_traction.max((point.traction_normal - cn * beta * beta * u).abs() / peak);
            worst_beta = worst_beta.max((point.adhesion.unwrap_or(f64::NAN) - beta).abs());
            largest_opening = largest_opening.max(u);
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    eprintln!(
        "    RCCM pair pulled off: {count} increments, largest opening {:.2} u_c, traction off the closed form \
         {worst_traction:.2e} of the peak, β off {worst_beta:.2e}, laws {laws:?}",
        largest_opening / uc
    );
    ensure(laws == vec!["rccm".to_string()], || format!("laws {laws:?}"))?;
    ensure(count == 30 && largest_opening > 2.5 * uc, || format!("{count} increments, opening {largest_opening:e}"))?;
    ensure(worst_traction <= 1e-8 && worst_beta <= 1e-8, || {
        format!("traction off by {worst_traction:e} of the peak, β by {worst_beta:e}")
    })
}
