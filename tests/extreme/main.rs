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
#[path = "../common/edit.rs"]
mod edit;

mod constrained_nodes;
mod contact_zones;
mod fallbacks_and_options;
mod friction;
mod gaps_and_obstacles;
mod illegal_scenes;
mod mpi;
mod patch_cases;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

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
/// residuals it reports are small, and the global equilibrium holds. The report sections the
/// scene must produce are required, not looked for: `results` for a primal scene, `dual.check`
/// for a dual one, `contact` when the scene has a `[contact]` table; a report without one of
/// them fails here instead of skipping its checks. Each caller adds its own independent check
/// (exact field, resultant, or comparison with another route).
fn answer(name: &str, scene: &str, args: &[&str]) -> (PathBuf, Value) {
    let (dir, result) = run(name, scene, args);
    let report = match result {
        Ok(r) => r,
        Err((code, stderr)) => panic!("{name}: expected an answer, got exit {code:?}:\n{stderr}"),
    };
    let section = |key: &str| -> &Value {
        report.get(key).unwrap_or_else(|| panic!("{name}: report.json has no `{key}` section: {report}"))
    };
    if scene.contains("formulation = \"dual\"") {
        for key in ["traction_residual", "interior_equilibrium", "stress_jump"] {
            let v = section("dual")["check"][key].as_f64().unwrap_or_else(|| panic!("{name}: no dual.check.{key}"));
            assert!(v < 1e-9, "{name}: dual check {key} = {v}");
        }
    } else {
        let eq = section("results")["equilibrium_residual"].as_f64().expect("results.equilibrium_residual");
        assert!(eq < 1e-7, "{name}: equilibrium residual {eq}");
    }
    if scene.contains("[contact]") {
        let r = &section("contact")["residuals"];
        for key in ["max_penetration", "max_wrong_sign_pressure", "max_cone_violation", "normal_complementarity"] {
            let v = r[key].as_f64().unwrap_or_else(|| panic!("{name}: no contact.residuals.{key}"));
            assert!(v <= 1e-6, "{name}: contact residual {key} = {v}");
        }
    }
    (dir, report)
}

/// (open, stick, slip) point counts of a report's contact section.
fn counts(r: &Value) -> [u64; 3] {
    ["open", "stick", "slip"].map(|k| r["contact"][k].as_u64().unwrap_or_else(|| panic!("contact.{k}: {r}")))
}

/// ‖u_a − u_b‖ / ‖u_a‖ over the nodes, both displacement fields read from solution.vtu by meshio.
fn displacement_difference(a: &Path, b: &Path) -> f64 {
    let script = format!(
        "import meshio, numpy as np\na = meshio.read(r'{}').point_data['displacement']\nb = meshio.read(r'{}').point_data['displacement']\nprint(repr(float(np.linalg.norm(a - b) / np.linalg.norm(a))))",
        a.join("solution.vtu").display(),
        b.join("solution.vtu").display()
    );
    let out = Command::new("python3").arg("-c").arg(&script).output().expect("python3 with meshio (./setup.sh)");
    assert!(out.status.success(), "meshio: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout).trim().parse().unwrap()
}

/// The same answer as a reference run: displacement fields within `tol` (relative) and the
/// same open/stick/slip counts.
fn assert_same_answer(name: &str, (dir, r): (&Path, &Value), (ref_dir, reference): (&Path, &Value), tol: f64) {
    let d = displacement_difference(ref_dir, dir);
    assert!(d <= tol, "{name}: displacement differs from the reference run by {d:e} (relative)");
    assert_eq!(counts(r), counts(reference), "{name}: open/stick/slip counts differ from the reference run");
}

/// Every point of the contact part in solution.vtu (read by meshio): (x, y, pressure, status),
/// status 0 open, 1 stick, 2 slip (points off the contact part, status −1, are left out).
fn contact_points(dir: &Path) -> Vec<[f64; 4]> {
    let script = format!(
        "import meshio, numpy as np\nm = meshio.read(r'{}')\np = m.point_data['contact_pressure']\ns = m.point_data['contact_status']\nfor k in np.nonzero(s >= 0)[0]: print(repr(float(m.points[k, 0])), repr(float(m.points[k, 1])), repr(float(p[k])), repr(float(s[k])))",
        dir.join("solution.vtu").display()
    );
    let out = Command::new("python3").arg("-c").arg(&script).output().expect("python3 with meshio (./setup.sh)");
    assert!(out.status.success(), "meshio: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| {
            let v: Vec<f64> = l.split_whitespace().map(|w| w.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
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
fn patch(name: &str, b: &Block, args: &[&str]) -> PathBuf {
    patch_to(name, b, args, 1e-8)
}

/// The patch test to a relative tolerance `tol` on the pressures (iterative contact solvers
/// stop at their own tolerance).
fn patch_to(name: &str, b: &Block, args: &[&str], tol: f64) -> PathBuf {
    let (dir, r) = answer(name, &b.toml(), args);
    assert_uniform_pressure(name, &dir, b.p, tol);
    let n = r["contact"]["normal_resultant"].as_f64().unwrap();
    assert!((n + b.p * b.w).abs() <= 1e-8 * b.p * b.w, "{name}: normal resultant {n}");
    let umax = r["results"]["max_displacement"].as_f64().unwrap();
    let exact = b.top_displacement();
    assert!((umax - exact).abs() <= tol.max(1e-7) * exact, "{name}: max |u| {umax} vs exact {exact}");
    dir
}

const SQUARE_BLOCK: &str = include_str!("../../examples/scenes/square_block.toml");

fn square_block(friction: &str) -> String {
    let start = SQUARE_BLOCK.find("friction = \"coulomb\"").unwrap();
    let end = SQUARE_BLOCK[start..].find("solver").unwrap() + start;
    format!("{}{friction}\n{}", &SQUARE_BLOCK[..start], &SQUARE_BLOCK[end..])
}
