//! The extreme-case suite: legal scenes at the edges of what the program accepts (friction from
//! 0 to 100, thresholds from tiny to huge, ν up to 0.4999, moduli from 1e-3 to 1e15, units from
//! µm to km, slender bodies, gaps and overlaps, tilted and nearly tangent obstacles, corners,
//! whole-boundary contact, bodies held only by friction, symmetry planes and pins on contact
//! nodes, every contact solver and fallback, MPI) and illegal ones (disconnected meshes, bodies
//! inside the obstacle, loads that overflow, sliding bodies). Each scene states what it must
//! give: an answer that passes the program's own check AND an independent one here (exact
//! solution, equilibrium, the contact pressure read back from solution.vtu with meshio), or a
//! typed error whose message says what is wrong.
//!
//! Every case spawns the program (one PETSc session per process).
use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::Value;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_signorini"));
    c.env("OMP_NUM_THREADS", "1").env("OPENBLAS_NUM_THREADS", "1");
    c
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("signorini-extreme-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Run `scene` (TOML text) with extra arguments; Ok(report) on exit 0, Err(stderr) otherwise.
fn run(name: &str, scene: &str, args: &[&str]) -> (PathBuf, Result<Value, (Option<i32>, String)>) {
    let dir = scratch(name);
    let file = dir.join("scene.toml");
    std::fs::write(&file, scene).unwrap();
    let out_dir = dir.join("out");
    let out = bin().arg("run").arg(&file).arg("--out").arg(&out_dir).arg("--quiet").args(args).output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).to_string();
    if out.status.success() {
        let text = std::fs::read_to_string(out_dir.join("report.json")).expect("report.json after exit 0");
        (out_dir, Ok(serde_json::from_str(&text).unwrap()))
    } else {
        (out_dir, Err((out.status.code(), stderr)))
    }
}

/// The answer of a scene that must solve, after the program's own check and ours: the contact
/// residuals it reports are small, and the global equilibrium holds.
fn answer(name: &str, scene: &str, args: &[&str]) -> (PathBuf, Value) {
    let (dir, result) = run(name, scene, args);
    let report = match result {
        Ok(r) => r,
        Err((code, stderr)) => panic!("{name}: expected an answer, got exit {code:?}:\n{stderr}"),
    };
    if report.get("results").is_some() {
        let eq = report["results"]["equilibrium_residual"].as_f64().unwrap();
        assert!(eq < 1e-7, "{name}: equilibrium residual {eq}");
    }
    if let Some(c) = report.get("contact") {
        let r = &c["residuals"];
        for key in ["max_penetration", "max_wrong_sign_pressure", "max_cone_violation", "normal_complementarity"] {
            let v = r[key].as_f64().unwrap();
            assert!(v <= 1e-6, "{name}: contact residual {key} = {v}");
        }
    }
    (dir, report)
}

/// A scene that must fail with exit 1 and a message containing every one of `words`
/// (case-insensitive), and leave no result files behind.
fn error(name: &str, scene: &str, args: &[&str], words: &[&str]) -> String {
    let (dir, result) = run(name, scene, args);
    let (code, stderr) = match result {
        Ok(r) => panic!("{name}: expected an error, got an answer: {}", r["results"]),
        Err(e) => e,
    };
    assert_eq!(code, Some(1), "{name}: exit code, stderr: {stderr}");
    assert!(stderr.starts_with("error: "), "{name}: {stderr}");
    let lower = stderr.to_lowercase();
    for w in words {
        assert!(lower.contains(&w.to_lowercase()), "{name}: message lacks {w:?}:\n{stderr}");
    }
    for f in ["solution.vtu", "report.json"] {
        assert!(!dir.join(f).exists(), "{name}: {f} left behind after an error");
    }
    stderr
}

/// Contact pressures of the closed points (pressure > 0) read back from solution.vtu by meshio.
fn closed_pressures(dir: &Path) -> Vec<f64> {
    let script = format!(
        "import meshio, numpy as np\nm = meshio.read(r'{}')\np = m.point_data['contact_pressure']\ns = m.point_data['contact_status']\nfor v in p[s >= 1]: print(repr(float(v)))",
        dir.join("solution.vtu").display()
    );
    let out = Command::new("python3").arg("-c").arg(&script).output().expect("python3 with meshio (./setup.sh)");
    assert!(out.status.success(), "meshio: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).lines().map(|l| l.trim().parse().unwrap()).collect()
}

fn assert_uniform_pressure(name: &str, dir: &Path, p: f64, tol: f64) {
    let pressures = closed_pressures(dir);
    assert!(!pressures.is_empty(), "{name}: no closed contact point");
    for v in &pressures {
        assert!((v - p).abs() <= tol * p, "{name}: pressure {v} instead of {p} (all: {pressures:?})");
    }
}

/// A block `[0, w] × [0, h]` on the rigid plane y = 0, top pressure `p`, sides loaded by the
/// plane-strain lateral pressure νp/(1−ν) (the frictionless patch test) unless
/// `extra` says otherwise, and the horizontal translation removed at the top-left corner.
struct Block<'a> {
    w: f64,
    h: f64,
    cell: f64,
    order: u8,
    young: f64,
    poisson: f64,
    plane: &'a str,
    p: f64,
    /// Lateral pressure νp/(1−ν) on the left face (else a free or constrained face).
    left: bool,
    /// Lateral pressure on the right face.
    right: bool,
    mesher: &'a str,
    contact: String,
    extra: String,
}

impl Default for Block<'_> {
    fn default() -> Self {
        Block {
            w: 2.0,
            h: 1.0,
            cell: 0.25,
            order: 1,
            young: 90e9,
            poisson: 0.2,
            plane: "strain",
            p: 1e6,
            left: true,
            right: true,
            mesher: "gmsh",
            contact: "friction = \"none\"".into(),
            extra: "[[dirichlet]]\npoint = [0.0, {h}]\nux = 0.0\n".into(),
        }
    }
}

impl Block<'_> {
    fn lateral(&self) -> f64 {
        if self.plane == "strain" {
            self.poisson * self.p / (1.0 - self.poisson)
        } else {
            0.0
        }
    }
    fn toml(&self) -> String {
        let mut sides = String::new();
        for (part, on) in [("left", self.left), ("right", self.right)] {
            if on && self.lateral() != 0.0 {
                sides += &format!("[[traction]]\npart = \"{part}\"\npressure = {:e}\n\n", self.lateral());
            }
        }
        format!(
            r#"[mesh]
shape = "rectangle"
size = [{w:e}, {h:e}]
cell_size = {c:e}
mesher = "{mesher}"

[discretization]
order = {o}

[material]
young = {e:e}
poisson = {nu}
plane = "{plane}"

[[traction]]
part = "top"
pressure = {p:e}

{sides}
{extra}
[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
{contact}
"#,
            w = self.w,
            h = self.h,
            c = self.cell,
            mesher = self.mesher,
            o = self.order,
            e = self.young,
            nu = self.poisson,
            plane = self.plane,
            p = self.p,
            extra = self.extra.replace("{h}", &format!("{:e}", self.h)),
            contact = self.contact,
        )
    }
    /// The exact largest |u|: the top's (1+ν)(1−2ν) p h / (E (1−ν)) in plane strain (ux = 0);
    /// in plane stress with free sides uy = p h / E at the top and ux = ν p x / E, largest at
    /// the top-right corner.
    fn top_displacement(&self) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        if self.plane == "strain" {
            (1.0 + nu) * (1.0 - 2.0 * nu) * self.p * self.h / (e * (1.0 - nu))
        } else {
            (self.p * self.h / e).hypot(nu * self.p * self.w / e)
        }
    }
}

/// The patch test must be exact: uniform pressure p on every closed point, the normal resultant
/// −p w, and the exact top displacement.
fn patch(name: &str, b: &Block, args: &[&str]) {
    patch_to(name, b, args, 1e-8);
}

/// The patch test to a relative tolerance `tol` on the pressures (iterative contact solvers
/// stop at their own tolerance).
fn patch_to(name: &str, b: &Block, args: &[&str], tol: f64) {
    let (dir, r) = answer(name, &b.toml(), args);
    assert_uniform_pressure(name, &dir, b.p, tol);
    let n = r["contact"]["normal_resultant"].as_f64().unwrap();
    assert!((n + b.p * b.w).abs() <= 1e-8 * b.p * b.w, "{name}: normal resultant {n}");
    let umax = r["results"]["max_displacement"].as_f64().unwrap();
    let exact = b.top_displacement();
    assert!((umax - exact).abs() <= tol.max(1e-7) * exact, "{name}: max |u| {umax} vs exact {exact}");
}

// ---------------------------------------------------------------- material and units extremes

#[test]
fn patch_nu_zero() {
    patch("nu0", &Block { poisson: 0.0, ..Default::default() }, &[]);
}

#[test]
fn patch_nu_0_49() {
    patch("nu049", &Block { poisson: 0.49, ..Default::default() }, &[]);
}

#[test]
fn patch_nu_0_4999_p2() {
    patch("nu04999", &Block { poisson: 0.4999, order: 2, ..Default::default() }, &[]);
}

#[test]
fn patch_plane_stress() {
    patch("plane_stress", &Block { plane: "stress", ..Default::default() }, &[]);
}

#[test]
fn patch_young_tiny() {
    // E = 1e-3 Pa with a load of 1e-9 Pa: displacements of order 1e-6 m, small strains.
    patch("young_tiny", &Block { young: 1e-3, p: 1e-9, ..Default::default() }, &[]);
}

#[test]
fn patch_young_huge() {
    patch("young_huge", &Block { young: 1e15, ..Default::default() }, &[]);
}

#[test]
fn patch_micrometres() {
    patch("micro", &Block { w: 2e-6, h: 1e-6, cell: 2.5e-7, ..Default::default() }, &[]);
}

#[test]
fn patch_kilometres() {
    patch("km", &Block { w: 2e3, h: 1e3, cell: 250.0, p: 1e9, young: 1e15, ..Default::default() }, &[]);
}

#[test]
fn patch_aspect_ratio_1000() {
    patch("slender", &Block { w: 1000.0, h: 1.0, cell: 1.0, mesher: "structured", ..Default::default() }, &[]);
}

#[test]
fn patch_p2_irregular() {
    patch("p2", &Block { order: 2, ..Default::default() }, &[]);
}

// ---------------------------------------------------------------- every contact solver

fn solver_patch(solver: &str, friction: &str) {
    let b = Block { contact: format!("{friction}\nsolver = \"{solver}\""), ..Default::default() };
    // Relaxation and Uzawa are first-order iterations stopped at their tolerance.
    let tol = if matches!(solver, "relaxation" | "uzawa") { 1e-5 } else { 1e-8 };
    patch_to(&format!("solver_{solver}"), &b, &[], tol);
}

#[test]
fn patch_solver_newton() {
    solver_patch("newton", "friction = \"coulomb\"\nmu = 0.3");
}

#[test]
fn patch_solver_relaxation() {
    solver_patch("relaxation", "friction = \"coulomb\"\nmu = 0.3");
}

#[test]
fn patch_solver_dpana() {
    solver_patch("dpana", "friction = \"coulomb\"\nmu = 0.1");
}

#[test]
fn patch_solver_uzawa() {
    solver_patch("uzawa", "friction = \"none\"");
}

#[test]
fn patch_solver_tresca_fixed_point() {
    solver_patch("tresca_fixed_point", "friction = \"coulomb\"\nmu = 0.3");
}

#[test]
fn patch_solver_tao() {
    solver_patch("tao", "friction = \"tresca\"\nthreshold = 1e5");
}

#[test]
fn patch_solver_snes_vi() {
    solver_patch("snes_vi", "friction = \"none\"");
}

#[test]
fn patch_solver_newton_full_lu() {
    patch("full_space_lu", &Block::default(), &["-contact_full_space_lu"]);
}

// ---------------------------------------------------------------- friction extremes

const SQUARE_BLOCK: &str = include_str!("../examples/scenes/square_block.toml");

fn square_block(friction: &str) -> String {
    let start = SQUARE_BLOCK.find("friction = \"coulomb\"").unwrap();
    let end = SQUARE_BLOCK[start..].find("solver").unwrap() + start;
    format!("{}{friction}\n{}", &SQUARE_BLOCK[..start], &SQUARE_BLOCK[end..])
}

#[test]
fn square_block_mu_zero() {
    let (_, r) = answer("sb_mu0", &square_block("friction = \"coulomb\"\nmu = 0.0"), &[]);
    assert_eq!(r["contact"]["stick"].as_u64(), Some(0));
    assert!(r["contact"]["tangential_resultant"].as_f64().unwrap().abs() < 1e-6);
}

#[test]
fn square_block_mu_0_1() {
    answer("sb_mu01", &square_block("friction = \"coulomb\"\nmu = 0.1"), &[]);
}

#[test]
fn square_block_mu_10() {
    // μ = 10: more points stick than at μ = 1 (8 stick, 21 slip); only the lightly pressed
    // points near the open zone may still slip.
    let (_, r) = answer("sb_mu10", &square_block("friction = \"coulomb\"\nmu = 10.0"), &[]);
    let (stick, slip) = (r["contact"]["stick"].as_u64().unwrap(), r["contact"]["slip"].as_u64().unwrap());
    assert!(stick > 8 && slip < stick, "μ = 10: {}", r["contact"]);
}

#[test]
fn square_block_mu_100() {
    let (_, r) = answer("sb_mu100", &square_block("friction = \"coulomb\"\nmu = 100.0"), &[]);
    let (stick, slip) = (r["contact"]["stick"].as_u64().unwrap(), r["contact"]["slip"].as_u64().unwrap());
    assert!(stick > 8 && slip < stick, "μ = 100: {}", r["contact"]);
}

#[test]
fn square_block_tresca_tiny_threshold() {
    // A threshold of 1e-3 Pa next to pressures of 1e8 Pa: every closed point slips.
    let (_, r) = answer("sb_tresca_tiny", &square_block("friction = \"tresca\"\nthreshold = 1e-3"), &[]);
    assert_eq!(r["contact"]["stick"].as_u64(), Some(0));
}

#[test]
fn square_block_tresca_huge_threshold() {
    let (_, r) = answer("sb_tresca_huge", &square_block("friction = \"tresca\"\nthreshold = 1e20"), &[]);
    assert_eq!(r["contact"]["slip"].as_u64(), Some(0));
}

// ---------------------------------------------------------------- held by friction alone

fn held_by_friction(q_over_mu_p: f64) -> String {
    // The stick patch test with no support in x at all: shear q on the top and
    // the sides, μ = 0.5, held sideways only by friction.
    let (p, mu, nu) = (1e6, 0.5, 0.2);
    let q = q_over_mu_p * mu * p;
    let l = nu * p / (1.0 - nu);
    format!(
        r#"[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.25
mesher = "gmsh"

[material]
young = 90e9
poisson = {nu}

[[traction]]
part = "top"
traction = [{q:e}, {mp:e}]

[[traction]]
part = "right"
traction = [{ml:e}, {q:e}]

[[traction]]
part = "left"
traction = [{l:e}, {mq:e}]

[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = {mu}
"#,
        mp = -p,
        ml = -l,
        mq = -q
    )
}

#[test]
fn held_by_friction_just_below_mu_p() {
    let (dir, r) = answer("friction_below", &held_by_friction(0.95), &[]);
    assert_eq!(r["contact"]["slip"].as_u64(), Some(0), "{}", r["contact"]);
    assert_uniform_pressure("friction_below", &dir, 1e6, 1e-7);
}

#[test]
fn held_by_friction_just_above_mu_p() {
    error("friction_above", &held_by_friction(1.05), &[], &["slide"]);
}

// ---------------------------------------------------------------- gaps and obstacle geometry

#[test]
fn initial_gap_closed_by_a_held_body() {
    // The block hangs 1e-5 above the plane, its top pushed down by 2e-5: the gap closes.
    let b = Block {
        left: false,
        right: false,
        p: 0.0,
        extra: "[[dirichlet]]\npart = \"top\"\nuy = -2e-5\n\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n".into(),
        contact: "friction = \"none\"\ngap = 1e-5".into(),
        ..Default::default()
    };
    let (_, r) = answer("gap", &b.toml(), &[]);
    assert!(r["contact"]["points"].as_u64().unwrap() > 0);
    assert!(r["contact"]["normal_resultant"].as_f64().unwrap() < 0.0, "the gap must close: {}", r["contact"]);
}

#[test]
fn initial_gap_never_closed() {
    // Pushed down by less than the gap: no contact force at all, every point open.
    let b = Block {
        left: false,
        right: false,
        p: 0.0,
        extra: "[[dirichlet]]\npart = \"top\"\nuy = -5e-6\n\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n".into(),
        contact: "friction = \"none\"\ngap = 1e-5".into(),
        ..Default::default()
    };
    let (_, r) = answer("gap_open", &b.toml(), &[]);
    assert_eq!(r["contact"]["normal_resultant"].as_f64(), Some(0.0));
    assert_eq!(r["contact"]["open"], r["contact"]["points"]);
}

#[test]
fn declared_initial_overlap() {
    // gap = −1e-6: the body starts 1 µm inside the plane, which the scene declares; held by
    // its top, the plane pushes it back out.
    let b = Block {
        left: false,
        right: false,
        p: 0.0,
        extra: "[[dirichlet]]\npart = \"top\"\nuy = 0.0\n\n[[dirichlet]]\npoint = [0.0, 1.0]\nux = 0.0\n".into(),
        contact: "friction = \"none\"\ngap = -1e-6".into(),
        ..Default::default()
    };
    let (_, r) = answer("overlap", &b.toml(), &[]);
    assert!(r["contact"]["normal_resultant"].as_f64().unwrap() < 0.0);
}

fn tilted(normal: [f64; 2], push: f64) -> String {
    // A block standing on a tilted line through its lower-left corner (the rest of its bottom
    // above the line), its top clamped and pushed by `push` along −normal.
    let n = normal[0].hypot(normal[1]);
    let d = [-push * normal[0] / n, -push * normal[1] / n];
    format!(
        r#"[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.25
mesher = "gmsh"

[material]
young = 90e9
poisson = 0.3

[[dirichlet]]
part = "top"
ux = {dx:e}
uy = {dy:e}

[contact]
part = "bottom"
obstacle = "line"
point = [0.0, 0.0]
normal = [{nx:e}, {ny:e}]
friction = "coulomb"
mu = 0.3
"#,
        dx = d[0],
        dy = d[1],
        nx = normal[0],
        ny = normal[1]
    )
}

#[test]
fn tilted_obstacle() {
    let (_, r) = answer("tilted", &tilted([5e-4, 1.0], 2e-3), &[]);
    assert!(r["contact"]["open"].as_u64().unwrap() < r["contact"]["points"].as_u64().unwrap());
}

#[test]
fn nearly_tangent_obstacle_normal() {
    let (_, r) = answer("near_tangent", &tilted([1e-9, 1.0], 1e-5), &[]);
    assert_eq!(r["contact"]["open"].as_u64(), Some(0), "{}", r["contact"]);
}

#[test]
fn polyline_corner_under_the_body() {
    let b = Block { contact: "friction = \"none\"".into(), ..Default::default() };
    // A shallow valley whose corner lies under the middle of the block (0.5 mm below its
    // bottom corners' level at x = 0 and 2): the block sinks onto the two slopes.
    let scene = b.toml().replace(
        "obstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]",
        "obstacle = \"polyline\"\npoints = [[-1.0, 0.0], [1.0, -1e-3], [3.0, 0.0]]",
    );
    let (_, r) = answer("polyline", &scene, &[]);
    assert!(r["contact"]["normal_resultant"].as_f64().unwrap() < 0.0);
}

// ---------------------------------------------------------------- constrained contact nodes

#[test]
fn symmetry_plane_through_a_contact_node() {
    // The frictionless patch test with its left face on a symmetry plane (ux = 0) instead of
    // the lateral pressure: the same exact solution (ux = 0 everywhere), and the corner node
    // (0, 0) has ux prescribed and must stay a contact node.
    let b = Block { left: false, extra: "[[dirichlet]]\npart = \"left\"\nux = 0.0\n".into(), ..Default::default() };
    patch("symmetry_plane", &b, &[]);
}

#[test]
fn symmetry_plane_through_a_contact_node_p2_friction() {
    let b = Block {
        left: false,
        order: 2,
        extra: "[[dirichlet]]\npart = \"left\"\nux = 0.0\n".into(),
        contact: "friction = \"coulomb\"\nmu = 0.3".into(),
        ..Default::default()
    };
    patch("symmetry_plane_p2", &b, &[]);
}

#[test]
fn pin_at_a_contact_node() {
    // ux = 0 at the contact node (0, 0) instead of the top-left corner.
    let b = Block { extra: "[[dirichlet]]\npoint = [0.0, 0.0]\nux = 0.0\n".into(), ..Default::default() };
    patch("pin_contact_node", &b, &[]);
}

#[test]
fn whole_boundary_contact_part() {
    // A disc whose whole boundary may touch, resting on a plane under its weight, held
    // sideways by friction only.
    let scene = r#"[mesh]
shape = "disc"
center = [0.0, 0.1]
radius = 0.1
cell_size = 0.01

[material]
young = 210e9
poisson = 0.3

[loads]
body_force = [0.0, -7.7e4]

[contact]
part = "circle"
obstacle = "line"
point = [0.0, 0.0]
normal = [0.0, 1.0]
friction = "coulomb"
mu = 0.3
"#;
    let (_, r) = answer("disc_whole_boundary", scene, &[]);
    // The weight of the meshed (polygonal) disc.
    let weight = -r["results"]["applied_force"][1].as_f64().unwrap();
    assert!((weight - 7.7e4 * std::f64::consts::PI * 0.01).abs() < 1e-2 * weight);
    let n = r["contact"]["normal_resultant"].as_f64().unwrap();
    assert!((n + weight).abs() < 1e-7 * weight, "normal resultant {n} vs weight {weight}");
}

// ---------------------------------------------------------------- fallbacks and options

#[test]
fn fallback_after_snes_iteration_limit() {
    let (_, r) = answer("fallback_max_it", SQUARE_BLOCK, &["-contact_snes_max_it", "1"]);
    let notes = r["contact"]["notes"].to_string().to_lowercase();
    assert!(
        notes.contains("fell back") && notes.contains("diverged_max_it"),
        "the failure and the fallback must be in the notes: {notes}"
    );
}

#[test]
fn fallback_after_iterative_inner_solver() {
    answer("fallback_gmres_ilu", SQUARE_BLOCK, &["-contact_ksp_type", "gmres", "-contact_pc_type", "ilu"]);
}

#[test]
fn line_search_the_messages_recommend() {
    answer("linesearch_bt", SQUARE_BLOCK, &["-contact_snes_linesearch_type", "bt"]);
}

#[test]
fn advice_after_an_iteration_limit_works() {
    // Both the full-space Newton and its condensed fallback stop at 2 steps; the error's advice
    // (more steps) must produce the answer on the same scene.
    let scene = SQUARE_BLOCK.replace("solver = \"newton_full\"", "solver = \"newton_full\"\nmax_iterations = 2");
    let msg = error("advice", &scene, &[], &["did not converge", "-contact_snes_max_it"]);
    assert!(!msg.contains("linesearch_type bt"), "{msg}");
    answer("advice_followed", &scene, &["-contact_snes_max_it", "50"]);
}

#[test]
fn mpi_two_ranks_square_block() {
    let dir = scratch("mpi");
    let file = dir.join("scene.toml");
    std::fs::write(&file, SQUARE_BLOCK).unwrap();
    let out = Command::new("mpirun")
        .args(["--allow-run-as-root", "--oversubscribe", "-n", "2"])
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .arg(env!("CARGO_BIN_EXE_signorini"))
        .arg("run")
        .arg(&file)
        .arg("--quiet")
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .expect("mpirun (./setup.sh installs openmpi-bin)");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (_, serial) = answer("mpi_serial", SQUARE_BLOCK, &[]);
    let text = std::fs::read_to_string(dir.join("out/report.json")).unwrap();
    let parallel: Value = serde_json::from_str(&text).unwrap();
    let (a, b) = (
        serial["results"]["max_displacement"].as_f64().unwrap(),
        parallel["results"]["max_displacement"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-8 * a, "serial {a} vs 2 ranks {b}");
}

// ---------------------------------------------------------------- illegal scenes: typed errors

#[test]
fn body_inside_a_circle_obstacle() {
    let scene = r#"[mesh]
shape = "half_disc"
center = [0.0, 0.0]
radius = 0.1
cell_size = 0.02

[material]
young = 210e9
poisson = 0.3

[[dirichlet]]
part = "flat"
ux = 0.0
uy = 0.0

[contact]
part = "arc"
obstacle = "circle"      # a rigid disc of radius 0.2 around the whole body
center = [0.0, 0.0]
radius = 0.2
friction = "none"
"#;
    error("inside_circle", scene, &[], &["node", "inside the obstacle", "arc"]);
}

#[test]
fn body_on_the_wrong_side_of_a_line() {
    let b = Block::default();
    // The obstacle is the half-plane y >= -0.5 (normal pointing down): the body is inside it.
    let scene =
        b.toml().replace("point = [0.0, 0.0]\nnormal = [0.0, 1.0]", "point = [0.0, -0.5]\nnormal = [0.0, -1.0]");
    error("wrong_side", &scene, &[], &["node", "inside the obstacle", "bottom"]);
}

#[test]
fn sliding_square_block_without_friction_support() {
    // The square block without friction and without its supports: the left pressure pushes it
    // along the plane and nothing holds it sideways.
    let scene = square_block("friction = \"none\"")
        .replace("[[dirichlet]]\npart = \"right\"\nux = 0.0\n", "")
        .replace("[[dirichlet]]\npoint = [0.04, 0.0]      # the lower-right corner\nux = 0.0\nuy = 0.0\n", "");
    error("sliding", &scene, &[], &["slide"]);
}

#[test]
fn overflowing_load() {
    let b = Block { p: 1e300, ..Default::default() };
    let msg = error("overflow", &b.toml(), &[], &["pressure", "overflow", "units"]);
    assert!(msg.contains("scene.toml:"), "the message names the file and line: {msg}");
}

#[test]
fn coulomb_negative_mu() {
    let b = Block { contact: "friction = \"coulomb\"\nmu = -0.5".into(), ..Default::default() };
    error("mu_negative", &b.toml(), &[], &["mu"]);
}

#[test]
fn poisson_at_the_incompressible_limit() {
    let b = Block { poisson: 0.5, ..Default::default() };
    error("nu_half", &b.toml(), &[], &["poisson"]);
}

#[test]
fn loose_contact_tolerance() {
    let b = Block { contact: "friction = \"none\"\ntolerance = 0.9".into(), ..Default::default() };
    error("tolerance", &b.toml(), &[], &["tolerance"]);
}

#[test]
fn square_block_reactions_per_prescribed_component() {
    // `right` prescribes ux only: its reaction has no y component; the corner point prescribes
    // both and carries the vertical force the old attribution gave to `right`.
    let (_, r) = answer("sb_reactions", SQUARE_BLOCK, &[]);
    let reactions = &r["results"]["reactions"];
    assert_eq!(reactions["right"][1].as_f64(), Some(0.0), "{reactions}");
    let corner = &reactions["point [0.04, 0]"];
    assert!(corner[1].as_f64().unwrap().abs() > 1e3, "the corner carries a vertical force: {reactions}");
    assert!(r["results"]["equilibrium_residual"].as_f64().unwrap() < 1e-12);
}

#[test]
fn disconnected_piece_held_by_nothing() {
    // Two squares, the second touching nothing; only the first is held.
    let dir = scratch("pieces-mesh");
    let geo = dir.join("two.geo");
    std::fs::write(
        &geo,
        "Point(1)={0,0,0,0.25};Point(2)={1,0,0,0.25};Point(3)={1,1,0,0.25};Point(4)={0,1,0,0.25};\n\
         Point(5)={3,0,0,0.25};Point(6)={4,0,0,0.25};Point(7)={4,1,0,0.25};Point(8)={3,1,0,0.25};\n\
         Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};\n\
         Line(5)={5,6};Line(6)={6,7};Line(7)={7,8};Line(8)={8,5};\n\
         Curve Loop(1)={1,2,3,4};Plane Surface(1)={1};Curve Loop(2)={5,6,7,8};Plane Surface(2)={2};\n\
         Physical Curve(\"bottom\")={1};Physical Curve(\"top\")={3,7};Physical Curve(\"other\")={2,4,5,6,8};\n\
         Physical Surface(\"domain\")={1,2};\n",
    )
    .unwrap();
    let msh = dir.join("two.msh");
    let status = Command::new("gmsh").arg(&geo).args(["-2", "-format", "msh41", "-v", "0", "-o"]).arg(&msh).status();
    assert!(status.expect("gmsh (./setup.sh installs it)").success());
    let scene = format!(
        "[mesh]\nshape = \"file\"\nfile = \"{}\"\n\n[material]\nyoung = 1e9\npoisson = 0.3\n\n[[traction]]\npart = \"top\"\npressure = 1e5\n\n[[dirichlet]]\npart = \"bottom\"\nux = 0.0\nuy = 0.0\n",
        msh.display()
    );
    error("pieces", &scene, &[], &["2 separate pieces", "held", "float"]);
}

/// Run a scene on two MPI ranks; its report.
fn mpi_answer(name: &str, scene: &str, args: &[&str]) -> (PathBuf, Value) {
    let dir = scratch(name);
    let file = dir.join("scene.toml");
    std::fs::write(&file, scene).unwrap();
    let out_dir = dir.join("out");
    let out = Command::new("mpirun")
        .args(["--allow-run-as-root", "--oversubscribe", "-n", "2"])
        .env("OMP_NUM_THREADS", "1")
        .env("OPENBLAS_NUM_THREADS", "1")
        .arg(env!("CARGO_BIN_EXE_signorini"))
        .arg("run")
        .arg(&file)
        .arg("--quiet")
        .arg("--out")
        .arg(&out_dir)
        .args(args)
        .output()
        .expect("mpirun (./setup.sh installs openmpi-bin)");
    assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
    let report = serde_json::from_str(&std::fs::read_to_string(out_dir.join("report.json")).unwrap()).unwrap();
    (out_dir, report)
}

#[test]
fn mpi_symmetry_plane_through_a_contact_node_is_exact() {
    let b = Block { left: false, extra: "[[dirichlet]]\npart = \"left\"\nux = 0.0\n".into(), ..Default::default() };
    let (dir, r) = mpi_answer("mpi_symmetry", &b.toml(), &[]);
    assert_eq!(r["mpi_ranks"], 2);
    assert_uniform_pressure("mpi_symmetry", &dir, b.p, 1e-8);
    let umax = r["results"]["max_displacement"].as_f64().unwrap();
    assert!((umax - b.top_displacement()).abs() <= 1e-7 * umax);
}

#[test]
fn mpi_dual_formulation_equals_serial() {
    // The patch test's tractions, a roller on the bottom: the dual on 1 and 2 ranks.
    let scene = r#"[mesh]
shape = "rectangle"
size = [2.0, 1.0]
cell_size = 0.2
mesher = "gmsh"

[discretization]
formulation = "dual"

[material]
young = 90e9
poisson = 0.3

[[traction]]
part = "top"
pressure = 1e6

[[traction]]
part = "right"
traction = [0.0, 2e5]

[[dirichlet]]
part = "bottom"
ux = 0.0
uy = 0.0
"#;
    let (_, serial) = answer("dual_serial", scene, &[]);
    let (_, parallel) = mpi_answer("dual_mpi", scene, &[]);
    assert_eq!(parallel["formulation"], "dual");
    let (a, b) = (
        serial["dual"]["check"]["complementary_energy"].as_f64().unwrap(),
        parallel["dual"]["check"]["complementary_energy"].as_f64().unwrap(),
    );
    assert!((a - b).abs() <= 1e-10 * a.abs(), "complementary energy serial {a} vs 2 ranks {b}");
    let (a, b) =
        (serial["dual"]["max_von_mises"].as_f64().unwrap(), parallel["dual"]["max_von_mises"].as_f64().unwrap());
    assert!((a - b).abs() <= 1e-9 * a, "max von Mises serial {a} vs 2 ranks {b}");
}

#[test]
fn acceptance_never_exceeds_the_tolerance_asked_for() {
    // With tolerance = 1e-7 the independent check accepts nothing worse than 1e-7 (the default
    // margin of 100 over the solver's tolerance is capped by what the scene asked for).
    for solver in ["relaxation", "newton", "newton_full"] {
        let b = Block {
            contact: format!("friction = \"coulomb\"\nmu = 0.3\nsolver = \"{solver}\"\ntolerance = 1e-7"),
            ..Default::default()
        };
        let (_, r) = answer(&format!("accept_{solver}"), &b.toml(), &[]);
        let res = &r["contact"]["residuals"];
        for key in [
            "max_penetration",
            "max_wrong_sign_pressure",
            "max_cone_violation",
            "normal_complementarity",
            "tangential_complementarity",
        ] {
            let v = res[key].as_f64().unwrap();
            assert!(v <= 1e-7, "{solver}: {key} = {v} above the tolerance asked for");
        }
    }
}

#[test]
fn mpi_fallback_after_snes_iteration_limit() {
    let (_, r) = mpi_answer("mpi_fallback", SQUARE_BLOCK, &["-contact_snes_max_it", "1"]);
    let notes = r["contact"]["notes"].to_string().to_lowercase();
    assert!(notes.contains("fell back") && notes.contains("diverged_max_it"), "{notes}");
    assert!(r["contact"]["solver"].as_str().unwrap().contains("fallback"));
}

#[test]
fn contact_closed_in_two_places_gives_two_zones_and_the_peak() {
    // The block on a plane with a 2 cm deep dip under its middle: it touches on both sides.
    let b = Block { contact: "friction = \"none\"".into(), mesher: "structured", cell: 0.1, ..Default::default() };
    let scene = b.toml().replace(
        "obstacle = \"line\"\npoint = [0.0, 0.0]\nnormal = [0.0, 1.0]",
        "obstacle = \"polyline\"\npoints = [[-1.0, 0.0], [0.75, 0.0], [0.85, -0.02], [1.15, -0.02], [1.25, 0.0], [3.0, 0.0]]",
    );
    let (_, r) = answer("two_zones", &scene, &[]);
    let zones = r["contact"]["zones"].as_array().unwrap();
    assert_eq!(zones.len(), 2, "{}", r["contact"]["zones"]);
    let (a, c) = (&zones[0], &zones[1]);
    assert!(a["end"][0].as_f64().unwrap() <= 0.8 && c["start"][0].as_f64().unwrap() >= 1.2, "{zones:?}");
    assert!(a["extent"][1].as_f64().unwrap() < c["extent"][0].as_f64().unwrap());
    let peak = &r["contact"]["peak_pressure"];
    assert!(peak["pressure"].as_f64().unwrap() > 1e6, "the supports beside the dip carry more: {peak}");
}

#[test]
fn hertz_zone_is_the_contact_width_along_the_arc() {
    let scene =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/hertz.toml")).unwrap();
    let (_, r) = answer("hertz_zone", &scene, &[]);
    let (radius, young, nu, load) = (0.1f64, 210e9f64, 0.3f64, 4.5e7f64);
    let a = (4.0 * load * radius / (std::f64::consts::PI * young / (1.0 - nu * nu))).sqrt();
    let zones = r["contact"]["zones"].as_array().unwrap();
    assert_eq!(zones.len(), 1);
    let width = zones[0]["extent"][1].as_f64().unwrap() - zones[0]["extent"][0].as_f64().unwrap();
    assert!((width - 2.0 * a).abs() < 0.03 * 2.0 * a, "zone width {width} vs 2a = {}", 2.0 * a);
    let peak = &r["contact"]["peak_pressure"];
    let p0 = 2.0 * load / (std::f64::consts::PI * a);
    assert!(
        (peak["pressure"].as_f64().unwrap() - p0).abs() < 0.01 * p0
            && peak["position"][0].as_f64().unwrap().abs() < 0.1 * a
    );
}
