//! The cohesive–frictional joint (issue 26, `src/interface_law/cohesive_joint.rs`) end to end:
//! uniform patch tests that reproduce the law's τ–δ and tension–opening curves exactly at every
//! increment, and the limit without cohesion against the existing Signorini–Coulomb path.
use super::contact::{example, set_line};
use super::ensure;
use signorini::evolution::{EachIncrement, LoadPath};
use signorini::interface_law::cohesive_joint::CohesiveJoint;
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::{CohesiveJointSpec, Scene};

/// The block of the patch tests: width × height (m), E (Pa), ν, plane strain.
const WIDTH: f64 = 0.2;
const HEIGHT: f64 = 0.1;
const YOUNG: f64 = 10e9;
const POISSON: f64 = 0.2;

/// The joint of the patch tests: c0 = 0.3 MPa, f_t0 = 0.2 MPa, μ = 0.75, G_I = 10 J/m²,
/// G_II = 20 J/m². The block is stiff enough for stable softening: G/H = 4.2e10 Pa/m against
/// c0²/G_II = 4.5e9 (the staggered loop's rate ≤ 0.11), E'/H = 1.1e11 against
/// f_t0²/G_I = 4e9.
fn joint_spec() -> CohesiveJointSpec {
    CohesiveJointSpec {
        cohesion: 0.3e6,
        tensile_strength: 0.2e6,
        mu: 0.75,
        fracture_energy_tension: 10.0,
        fracture_energy_shear: 20.0,
    }
}

/// The `[contact.interface]` table of a joint.
fn interface_table(spec: &CohesiveJointSpec) -> String {
    format!(
        "[contact.interface]\nlaw = \"cohesive_joint\"\ncohesion = {:e}\ntensile_strength = {:e}\nmu = {}\n\
         fracture_energy_tension = {:e}\nfracture_energy_shear = {:e}\n",
        spec.cohesion, spec.tensile_strength, spec.mu, spec.fracture_energy_tension, spec.fracture_energy_shear
    )
}

/// The uniform state of the block at one increment: the joint's normal traction `t_n`
/// (tension positive), its shear stress τ = σ_xy, opening and slip (along +x), and the variables (κ_I, κ_II)
/// the law must reach.
#[derive(Debug, Clone, Copy)]
struct Target {
    t_n: f64,
    tau: f64,
    opening: f64,
    slip: f64,
    kappa: [f64; 2],
}

fn shear_modulus() -> f64 {
    YOUNG / (2.0 * (1.0 + POISSON))
}

/// ε_yy per unit σ_yy when σ_xx = ν/(1 − ν) σ_yy (so that ε_xx = 0, plane strain).
fn vertical_compliance() -> f64 {
    (1.0 + POISSON) * (1.0 - 2.0 * POISSON) / (YOUNG * (1.0 - POISSON))
}

/// The scene of a uniform path: the block on the rigid plane y = 0 (the joint), the top's
/// horizontal displacement prescribed (`δ + τ H / G`), its normal either loaded by the
/// traction `t_n` (`normal_by_traction`) or prescribed (`opening + ε_yy H`), and the sides
/// loaded by the tractions the uniform field needs: `±(σ_xx, τ)`, σ_xx = ν/(1 − ν) t_n
/// (ε_xx = 0). One increment per target at t = 1, 2, …; every table linear between them.
fn uniform_path_text(targets: &[Target], normal_by_traction: bool) -> String {
    let g = shear_modulus();
    let table = |f: &dyn Fn(&Target) -> f64| {
        let rows: Vec<String> = std::iter::once("[0, 0]".to_string())
            .chain(targets.iter().enumerate().map(|(k, t)| format!("[{}, {:e}]", k + 1, f(t))))
            .collect();
        format!("[{}]", rows.join(", "))
    };
    let side_normal = table(&|t| POISSON / (1.0 - POISSON) * t.t_n);
    let side_shear = table(&|t| t.tau);
    let drive_x = table(&|t| t.slip + t.tau * HEIGHT / g);
    let (normal_load, normal_row) = if normal_by_traction {
        (
            "[[traction]]\npart = \"top\"\ntraction = [0.0, 1.0]\nname = \"top_normal\"".to_string(),
            format!("top_normal = {}", table(&|t| t.t_n)),
        )
    } else {
        (
            "[[dirichlet]]\npart = \"top\"\nuy = 1.0\nname = \"drive_y\"".to_string(),
            format!("drive_y = {}", table(&|t| t.opening + vertical_compliance() * t.t_n * HEIGHT)),
        )
    };
    let times: Vec<String> = (1..=targets.len()).map(|k| k.to_string()).collect();
    format!(
        r#"title = "cohesive joint, uniform patch"
[mesh]
shape = "rectangle"
size = [{WIDTH}, {HEIGHT}]
cell_size = 0.025
mesher = "structured"
[material]
young = {YOUNG:e}
poisson = {POISSON}
plane = "strain"
[[traction]]
part = "right"
traction = [1.0, 0.0]
name = "side_normal"
[[traction]]
part = "left"
traction = [-1.0, 0.0]
name = "side_normal"
[[traction]]
part = "right"
traction = [0.0, 1.0]
name = "side_shear"
[[traction]]
part = "left"
traction = [0.0, -1.0]
name = "side_shear"
[[dirichlet]]
part = "top"
ux = 1.0
name = "drive_x"
{normal_load}
[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
solver = "newton"
{interface}
[evolution]
times = [{times}]
[evolution.factor]
{normal_row}
side_normal = {side_normal}
side_shear = {side_shear}
drive_x = {drive_x}
"#,
        times = times.join(", "),
        interface = interface_table(&joint_spec()),
    )
}

/// Run the uniform path and check every point at every increment against its target: the
/// opening, the slip (signed along +x), the tractions, the damage 1 − e^(−ξ(κ)), the law's
/// residual, and the displacement field u = (δ + τ y / G, o + ε_yy y) at every node. Returns
/// the worst relative errors (slip and opening against the law's lengths, tractions against
/// the peak) for the report.
fn run_uniform_path(s: &Session, name: &str, targets: &[Target], normal_by_traction: bool) -> Result<[f64; 3], String> {
    let text = uniform_path_text(targets, normal_by_traction);
    let file = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("{name}.toml"));
    let spec = joint_spec();
    let joint = CohesiveJoint::new(&spec);
    let scene = Scene::from_str(&text, &file).map_err(|e| format!("{name}: {e}"))?;
    let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| format!("{name}: {e}"))?;
    p.assemble().map_err(|e| e.to_string())?;
    let length = (spec.fracture_energy_shear / spec.cohesion).min(spec.fracture_energy_tension / spec.tensile_strength);
    let stress = spec.cohesion + targets.iter().map(|t| t.t_n.abs().max(t.tau.abs())).fold(0.0, f64::max);
    let (g, compliance) = (shear_modulus(), vertical_compliance());
    let mut worst = [0.0f64; 3]; // lengths, tractions, displacement field
    let mut problems = Vec::new();
    let mut orientation = 0.0; // the contact tangent along +x (1) or −x (−1)
    let mut count = 0;
    let mut halved = Vec::new(); // increments the path halved (the targets are at integer times)
    p.solve_load_path(&path, EachIncrement::Postprocess, &mut |q, record| {
        let k = record.time.round() as usize;
        if (record.time - k as f64).abs() > 1e-9 || k == 0 {
            halved.push(record.time);
            return Ok(());
        }
        count += 1;
        let t = targets[k - 1];
        let Some(snapshot) = q.interface.as_ref() else {
            problems.push(format!("t = {k}: no interface snapshot"));
            return Ok(());
        };
        let xi = joint.softening(0.0, &t.kappa);
        let damage = 1.0 - (-xi).exp();
        for point in &snapshot.points {
            if orientation == 0.0 && t.tau.abs() > 0.0 {
                orientation = (point.traction_tangential / -t.tau).signum();
            }
            let o = if orientation == 0.0 { 1.0 } else { orientation };
            let slip_error = (point.slip - o * t.slip).abs().max((point.opening - t.opening).abs()) / length;
            let traction_error =
                (point.traction_normal - t.t_n).abs().max((point.traction_tangential + o * t.tau).abs()) / stress;
            worst[0] = worst[0].max(slip_error);
            worst[1] = worst[1].max(traction_error);
            if slip_error > 1e-7 || traction_error > 1e-7 {
                problems.push(format!(
                    "t = {k}, x = {:?}: opening {:e} (exact {:e}), slip {:e} (exact {:e}), tractions ({:e}, {:e}) (exact ({:e}, {:e}))",
                    point.x,
                    point.opening,
                    t.opening,
                    point.slip,
                    o * t.slip,
                    point.traction_normal,
                    point.traction_tangential,
                    t.t_n,
                    -o * t.tau
                ));
            }
            match point.damage {
                Some(d) if (d - damage).abs() <= 1e-7 => {}
                other => problems.push(format!("t = {k}, x = {:?}: damage {other:?}, exact {damage}", point.x)),
            }
            if point.law_residual > 1e-7 {
                problems.push(format!("t = {k}, x = {:?}: law residual {:e}", point.x, point.law_residual));
            }
        }
        let u = q.displacement.as_ref().expect("a displacement");
        let scale = t.slip.abs() + t.opening.abs() + stress * HEIGHT * (1.0 / g + compliance);
        for (i, x) in q.mesh.nodes.iter().enumerate() {
            let ux = t.slip + t.tau * x[1] / g;
            let uy = t.opening + compliance * t.t_n * x[1];
            worst[2] = worst[2].max((u[2 * i] - ux).abs().max((u[2 * i + 1] - uy).abs()) / scale);
        }
        Ok(())
    })
    .map_err(|e| format!("{name}: {e}"))?;
    if !halved.is_empty() {
        eprintln!("    {name}: the path halved increments, intermediate times {halved:?}");
    }
    ensure(count == targets.len(), || format!("{name}: {count} increments for {} targets", targets.len()))?;
    ensure(problems.is_empty(), || {
        format!("{name}: {}", problems.iter().take(6).cloned().collect::<Vec<_>>().join("; "))
    })?;
    ensure(worst[2] <= 1e-7, || format!("{name}: displacement field off the exact one by {:e}", worst[2]))?;
    Ok(worst)
}

/// The targets of a shear path at constant compression σ: pressed, sheared elastically (the
/// rigid joint sticks) to 95 % of the peak c0 + μσ, slid past the peak on the softening curve
/// τ = c0 e^(−δ/ℓ) + μσ (ℓ = G_II / c0) to 5ℓ, unloaded (sticks, nothing softens), then
/// reversed: τ = −(c(κ) + μσ) with κ = 5ℓ + the reversed slip (the accumulated slip).
fn shear_targets(sigma: f64) -> Vec<Target> {
    let spec = joint_spec();
    let joint = CohesiveJoint::new(&spec);
    let ell = spec.fracture_energy_shear / spec.cohesion;
    let peak = spec.cohesion + spec.mu * sigma;
    let stick = |tau: f64, slip: f64| Target { t_n: -sigma, tau, opening: 0.0, slip, kappa: [0.0, slip] };
    let mut targets = vec![stick(0.0, 0.0), stick(0.5 * peak, 0.0), stick(0.95 * peak, 0.0)];
    for d in [0.1, 0.25, 0.5, 1.0, 1.5, 2.0, 3.0, 5.0] {
        let slip = d * ell;
        targets.push(stick(joint.shear_curve(sigma, slip), slip));
    }
    let reached = joint.shear_curve(sigma, 5.0 * ell);
    targets.push(stick(0.5 * reached, 5.0 * ell));
    targets.push(stick(-0.5 * reached, 5.0 * ell));
    for r in [0.5, 1.0, 2.0] {
        let kappa = (5.0 + r) * ell;
        targets.push(Target {
            t_n: -sigma,
            tau: -joint.shear_curve(sigma, kappa),
            opening: 0.0,
            slip: (5.0 - r) * ell,
            kappa: [0.0, kappa],
        });
    }
    targets
}

/// A single joint under shear at constant normal stress reproduces its τ–δ law exactly at
/// every increment, at σ = 0.1 and 0.6 MPa (the talk's figures): the block's field is uniform
/// (the sides carry the tractions the uniform field needs), so the program must find the
/// exact state: the slip, the tractions and the damage at every contact point, the
/// displacement at every node, to round-off and the staggered loop's tolerance.
pub fn masonry_joint_shear_patch(s: &Session) -> Result<(), String> {
    for sigma in [0.1e6, 0.6e6] {
        let targets = shear_targets(sigma);
        let worst = run_uniform_path(s, &format!("shear_patch_{sigma:e}"), &targets, false)?;
        eprintln!(
            "    σ = {sigma:e} Pa: {} increments, worst slip error {:.1e} ℓ, traction {:.1e} of the peak, displacement {:.1e}",
            targets.len(),
            worst[0],
            worst[1],
            worst[2]
        );
    }
    Ok(())
}

/// The tension test: the joint pulled by the top's displacement, elastically (rigid joint) to
/// 95 % of f_t0, opened on the softening curve f_t = f_t0 e^(−o/ℓ_I) (ℓ_I = G_I / f_t0) to
/// 3ℓ_I, closed again at the constant traction f_t(3ℓ_I) (the opening is recoverable), then
/// compressed (σ = 0.3 MPa) and sheared: the crack that closed under compression slips at
/// c0 e^(−ξ) + μσ, ξ = 3 + δ/ℓ_II (the cohesion lost with the opening: Lourenço–Rots's
/// coupled softening).
pub fn cohesive_joint_tension_softening_curve(s: &Session) -> Result<(), String> {
    let spec = joint_spec();
    let joint = CohesiveJoint::new(&spec);
    let ell_one = spec.fracture_energy_tension / spec.tensile_strength;
    let ell_two = spec.fracture_energy_shear / spec.cohesion;
    let f_t0 = spec.tensile_strength;
    let normal =
        |t_n: f64, opening: f64, kappa_one: f64| Target { t_n, tau: 0.0, opening, slip: 0.0, kappa: [kappa_one, 0.0] };
    let mut targets = vec![normal(0.5 * f_t0, 0.0, 0.0), normal(0.95 * f_t0, 0.0, 0.0)];
    for o in [0.1, 0.5, 1.0, 2.0, 3.0] {
        targets.push(normal(joint.tension_curve(o * ell_one), o * ell_one, o * ell_one));
    }
    let held = joint.tension_curve(3.0 * ell_one);
    for o in [2.0, 1.0, 0.3] {
        targets.push(normal(held, o * ell_one, 3.0 * ell_one));
    }
    targets.push(normal(0.5 * held, 0.0, 3.0 * ell_one));
    let sigma = 0.3e6;
    targets.push(normal(-sigma, 0.0, 3.0 * ell_one));
    let closed_strength = joint.shear_strength(joint.strengths(3.0).0, -sigma);
    targets.push(Target { tau: 0.5 * closed_strength, ..normal(-sigma, 0.0, 3.0 * ell_one) });
    for d in [0.5, 1.0, 2.0] {
        let c = joint.strengths(3.0 + d).0;
        targets.push(Target {
            t_n: -sigma,
            tau: c + spec.mu * sigma,
            opening: 0.0,
            slip: d * ell_two,
            kappa: [3.0 * ell_one, d * ell_two],
        });
    }
    let worst = run_uniform_path(s, "tension_patch", &targets, false)?;
    eprintln!(
        "    tension, closing, shear of the closed crack: {} increments, worst opening/slip error {:.1e} ℓ, traction {:.1e}, displacement {:.1e}",
        targets.len(),
        worst[0],
        worst[1],
        worst[2]
    );
    Ok(())
}

/// Without cohesion and tensile strength (c0 = f_t0 = 0) the joint is Signorini–Coulomb with
/// its μ: the square block pressed then pushed (`square_block_press_then_push.toml`, μ = 1,
/// partial slip) gives the same displacement at every increment as the scene's own Coulomb
/// contact, to 1e-8 (the joint reaches Coulomb as the fixed point on Tresca thresholds).
pub fn cohesive_joint_without_cohesion_is_coulomb(s: &Session) -> Result<(), String> {
    let (text, file) = example("square_block_press_then_push.toml");
    let text = set_line(&text, "solver", "solver = \"newton\"");
    let run = |text: &str| -> Result<Vec<Vec<f64>>, String> {
        let scene = Scene::from_str(text, &file).map_err(|e| e.to_string())?;
        let path = LoadPath::of_scene(&scene).map_err(|e| e.to_string())?.ok_or("no load path")?;
        let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
        p.assemble().map_err(|e| e.to_string())?;
        let mut fields = Vec::new();
        p.solve_load_path(&path, EachIncrement::Solve, &mut |q, _| {
            fields.push(q.displacement.clone().expect("a displacement"));
            Ok(())
        })
        .map_err(|e| e.to_string())?;
        Ok(fields)
    };
    let spec = CohesiveJointSpec {
        cohesion: 0.0,
        tensile_strength: 0.0,
        mu: 1.0,
        fracture_energy_tension: 1.0,
        fracture_energy_shear: 1.0,
    };
    // The joint takes the contact's friction: its `friction` and `mu` move into the table.
    let joint_text = set_line(&set_line(&text, "friction", ""), "mu = 1.0", "")
        .replace("[evolution]", &format!("{}\n[evolution]", interface_table(&spec)));
    let coulomb = run(&text).map_err(|e| format!("plain Coulomb: {e}"))?;
    let joint = run(&joint_text).map_err(|e| format!("joint without cohesion: {e}"))?;
    ensure(coulomb.len() == joint.len() && !joint.is_empty(), || "different increments".into())?;
    let mut worst = 0.0f64;
    for (a, b) in coulomb.iter().zip(&joint) {
        let n = a.iter().map(|x| x * x).sum::<f64>().sqrt();
        let d = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt();
        worst = worst.max(d / n);
    }
    eprintln!("    {} increments: worst |u_joint − u_coulomb| / |u_coulomb| = {worst:.2e}", joint.len());
    ensure(worst <= 1e-8, || format!("the joint without cohesion differs from Coulomb by {worst:e}"))
}
