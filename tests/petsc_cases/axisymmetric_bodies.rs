//! Two bodies of revolution in contact (issue 27): mortar pairs in axisymmetry against closed
//! forms. Shrink fits of two cylinders (Lamé), the pellet–cladding example, and Hertz between
//! two spheres (non-matching gmsh meshes of two quarter discs, the slave side's pole a P2 vertex
//! on the axis with a node-to-segment row).
//!
//! References: S. P. Timoshenko, J. N. Goodier, Theory of Elasticity, 3rd ed., 1970, §28 (thick
//! cylinder); K. L. Johnson, Contact Mechanics, 1985, §4.2 (Hertz, two spheres).
use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::{ContactSolverSpec, Scene};

use super::contact::{example, fit_half_width_and_peak, solve_text};
use super::ensure;

/// `(young, poisson)`.
type Elastic = (f64, f64);

/// Radial displacement at the inner radius `r1` of a cylinder `[r1, r2]` with `ε_z = 0` under an
/// internal pressure `p` (outer face free), and at the outer radius `r2` under an external
/// pressure `p` (inner face free), from Lamé's `u = A r + B/r`:
/// `u = (1 + ν)/E ((1 − 2ν) C1 r + C2 / r)`, `σ_rr = C1 − C2 / r²`.
fn bore_growth(p: f64, r1: f64, r2: f64, (e, nu): Elastic) -> f64 {
    p * r1 * (1.0 + nu) / e * ((1.0 - 2.0 * nu) * r1 * r1 + r2 * r2) / (r2 * r2 - r1 * r1)
}
fn outer_shrink(p: f64, r1: f64, r2: f64, (e, nu): Elastic) -> f64 {
    p * r2 * (1.0 + nu) / e * ((1.0 - 2.0 * nu) * r2 * r2 + r1 * r1) / (r2 * r2 - r1 * r1)
}

/// The shrink-fit contact pressure on the OUTER cylinder's bore, inner cylinder `[a, b_in]`
/// (`a = 0`: solid), outer `[b_out, c]`, interference `δ = b_in − b_out > 0`, `ε_z = 0` in both:
/// each cylinder is solved in its own geometry (the linear problem the mortar pair poses), the
/// two ring forces equal, so the inner one carries `p b_out / b_in`; `δ = u_out(b_out) −
/// u_in(b_in)`. For equal materials and `b_in = b_out = b` this is
/// `p = E δ (b² − a²)(c² − b²) / (2 (1 − ν²) b³ (c² − a²))`: the plane-stress formula with
/// `E / (1 − ν²)`.
fn shrink_fit_pressure(a: f64, b_in: f64, b_out: f64, c: f64, inner: Elastic, outer: Elastic) -> f64 {
    let delta = b_in - b_out;
    delta / (bore_growth(1.0, b_out, c, outer) + outer_shrink(b_out / b_in, a, b_in, inner))
}

/// The slave side's contact points `(z or r, pressure, tangential traction)` from `tractions()`.
fn points(p: &ElasticityProblem, coordinate: usize) -> Vec<(f64, f64, f64)> {
    let c = p.contact.as_ref().unwrap();
    let o = p.contact_outcome.as_ref().unwrap();
    let (pressure, friction) = c.boundary.tractions(&o.force);
    let mut pts: Vec<_> = (0..c.boundary.points())
        .map(|i| (p.mesh.nodes[c.boundary.nodes[i]][coordinate], pressure[i], friction[i]))
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    pts
}

/// Two cylinders `[a, b_in]` (`inner`) and `[b_out, c]` (`outer`) of height `height`, `u_z = 0`
/// on the top and bottom of both, P2, structured meshes of cells `cells` (non-matching along
/// the interface), the outer cylinder's bore the slave side.
#[allow(clippy::too_many_arguments)]
fn shrink_fit_scene(
    (a, b_in, b_out, c): (f64, f64, f64, f64),
    height: f64,
    inner: Elastic,
    outer: Elastic,
    cells: (f64, f64),
    friction: &str,
) -> String {
    let body = |name: &str, origin: f64, width: f64, (e, nu): Elastic, cell: f64| {
        format!(
            "[[body]]\nname = \"{name}\"\nmesh = {{ shape = \"rectangle\", origin = [{origin:?}, 0.0], size = [{width:?}, \
             {height:?}], cell_size = {cell:?} }}\nmaterial = {{ young = {e:e}, poisson = {nu}, plane = \"axisymmetric\" }}\n\
             discretization = {{ order = 2 }}\n\n[[body.dirichlet]]\npart = \"bottom\"\nuy = 0.0\n\n\
             [[body.dirichlet]]\npart = \"top\"\nuy = 0.0\n\n"
        )
    };
    format!(
        "title = \"shrink fit\"\n\n{}{}[[contact_pair]]\nslave = \"outer.left\"\nmaster = \"inner.right\"\n{friction}\n\
         max_initial_overlap = {:?}\n",
        body("inner", a, b_in - a, inner, cells.0),
        body("outer", b_out, c - b_out, outer, cells.1),
        2.0 * (b_in - b_out)
    )
}

/// Every contact point's pressure against the closed form: the largest relative deviation,
/// and the largest tangential traction relative to the pressure.
fn pressure_deviation(pts: &[(f64, f64, f64)], exact: f64) -> (f64, f64) {
    let worst = pts.iter().map(|q| (q.1 / exact - 1.0).abs()).fold(0.0, f64::max);
    let shear = pts.iter().map(|q| q.2.abs() / exact).fold(0.0, f64::max);
    (worst, shear)
}

/// A hollow steel cylinder `r ∈ [0.5, 1.001]` shrink-fitted in a steel tube `r ∈ [1, 1.5]`
/// (interference 1 mm, `ε_z = 0`), non-matching meshes (cells 0.05 and 0.033 along z),
/// frictionless and with Coulomb friction μ = 0.3: every contact point's pressure is the
/// closed form's within 0.1 % (measured 4.2e-4 frictionless, 4.8e-4 Coulomb; 15 points), no
/// slip (the load is radial and symmetric; |tangential| ≤ 1.3e-4 p), and the two answers
/// agree (5.4e-5 of p apart).
pub fn shrink_fit_hollow_cylinders(s: &Session) -> Result<(), String> {
    let steel = (2e11, 0.3);
    let radii = (0.5, 1.001, 1.0, 1.5);
    let exact = shrink_fit_pressure(radii.0, radii.1, radii.2, radii.3, steel, steel);
    // The textbook form (b_in = b_out): 1e-3 relative apart for this δ/b, the geometric effect.
    let (a, b, c) = (0.5f64, 1.0f64, 1.5f64);
    let textbook = 2e11 * 1e-3 * (b * b - a * a) * (c * c - b * b) / (2.0 * (1.0 - 0.09) * b.powi(3) * (c * c - a * a));
    ensure((exact / textbook - 1.0).abs() < 3e-3, || format!("closed forms {exact:e} and {textbook:e}"))?;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("shrink_fit.toml");
    let mut answers = Vec::new();
    for friction in ["friction = \"none\"", "friction = \"coulomb\"\nmu = 0.3"] {
        let text = shrink_fit_scene(radii, 0.2, steel, steel, (0.05, 0.033), friction);
        let p = solve_text(s, &text, &path).map_err(|e| format!("{friction}: {e}"))?;
        let pts = points(&p, 1);
        let (worst, shear) = pressure_deviation(&pts, exact);
        eprintln!(
            "    shrink fit ({friction:?}): {} points, pressure {exact:.6e} Pa exact, worst deviation {worst:.1e}, \
             |tangential| <= {shear:.1e} p",
            pts.len()
        );
        ensure(pts.len() > 5 && worst < 1e-3, || format!("{friction}: pressures {pts:?} against {exact:e}"))?;
        ensure(shear < 1e-3, || format!("{friction}: tangential tractions {pts:?}"))?;
        answers.push(pts);
    }
    let apart = answers[0].iter().zip(&answers[1]).map(|(f, c)| (f.1 - c.1).abs() / exact).fold(0.0, f64::max);
    eprintln!("    shrink fit: frictionless and Coulomb pressures {apart:.1e} apart");
    ensure(apart < 1e-4, || format!("frictionless and Coulomb pressures {apart:e} apart"))
}

/// `examples/scenes/pellet_cladding.toml`: the UO2 pellet (solid, r ≤ 4.19 mm) in the Zircaloy
/// tube (4.18–4.75 mm), Coulomb μ = 0.5: every contact pressure within 0.1 % of the shrink-fit
/// closed form (31.36 MPa; measured deviation 3.8e-4), the tube's hoop stress tensile and
/// Lamé's at its bore `p (b² + c²)/(c² − b²)` = 246.6 MPa within 1 % (measured 1.4e-4), the
/// pellet's stress uniform `σrr = σθθ = −p b/b'` within 1 % of p (measured 1.8e-5).
pub fn pellet_cladding_example_is_a_shrink_fit(s: &Session) -> Result<(), String> {
    let (text, path) = example("pellet_cladding.toml");
    let (uo2, zircaloy) = ((2e11, 0.3), (9.9e10, 0.37));
    let (bp, b, c) = (4.19e-3, 4.18e-3, 4.75e-3);
    let exact = shrink_fit_pressure(0.0, bp, b, c, uo2, zircaloy);
    let p = solve_text(s, &text, &path).map_err(|e| format!("pellet_cladding.toml: {e}"))?;
    let pts = points(&p, 1);
    let (worst, shear) = pressure_deviation(&pts, exact);
    eprintln!("    pellet-cladding: pressure {exact:.6e} Pa exact, worst deviation {worst:.1e}, |tangential| <= {shear:.1e} p");
    ensure(worst < 1e-3 && shear < 1e-3, || format!("pressures {pts:?} against {exact:e}"))?;
    // Stresses: the hoop stress (sigma_zz holds σθθ in axisymmetry) at the tube's bore, and the
    // pellet's uniform state.
    let results = p.results.as_ref().ok_or("no results")?;
    let hoop_bore = exact * (b * b + c * c) / (c * c - b * b);
    let (mut bore, mut pellet) = (0.0f64, 0.0f64);
    for (k, x) in p.mesh.nodes.iter().enumerate() {
        let (sigma, hoop) = (results.nodal_stress[k], results.sigma_zz[k]);
        if (x[0] - b).abs() < 1e-9 && p.bodies.as_ref().unwrap().layout.bodies[1].nodes.contains(&k) {
            bore = bore.max((hoop / hoop_bore - 1.0).abs());
        }
        if !(sigma.iter().all(|v| v.is_finite()) && hoop.is_finite()) {
            return Err(format!("stress at node {k} ({x:?}): {sigma:?}, hoop {hoop}"));
        }
        if p.bodies.as_ref().unwrap().layout.bodies[0].nodes.contains(&k) {
            let uniform = -exact * b / bp;
            pellet = pellet.max(((sigma[0] - uniform).abs()).max((hoop - uniform).abs()) / exact);
        }
    }
    eprintln!(
        "    pellet-cladding: bore hoop stress {hoop_bore:.4e} Pa (tensile), worst deviation {bore:.1e}; pellet \
         stress deviation {pellet:.1e} p"
    );
    ensure(hoop_bore > 0.0 && bore < 1e-2 && pellet < 1e-2, || format!("hoop at the bore {bore:e}, pellet {pellet:e}"))
}

/// A quarter disc of radius `radius` (the meridian of a hemisphere) with its pole at the
/// origin, above it (`up`) or below it, meshed by gmsh (P2, MSH 4.1) with cells `fine` near the
/// pole and `coarse` away; parts `axis`, `arc`, `flat`. Returns the file's path.
fn hemisphere_mesh(dir: &Path, name: &str, radius: f64, up: bool, fine: f64, coarse: f64) -> Result<PathBuf, String> {
    let zc = if up { radius } else { -radius };
    // Domain on the left of every curve: up, the axis runs down, the arc out, the flat back.
    let (axis, arc, flat, loop_) = if up {
        ("{1, 2}", "{2, 1, 3}", "{3, 1}", "{1, 2, 3}")
    } else {
        ("{2, 1}", "{3, 1, 2}", "{1, 3}", "{1, 3, 2}")
    };
    let geo = format!(
        "R = {radius:?}; h = {coarse:?}; hf = {fine:?};\nPoint(1) = {{0, {zc:?}, 0, h}};\nPoint(2) = {{0, 0, 0, hf}};\n\
         Point(3) = {{R, {zc:?}, 0, h}};\nLine(1) = {axis};\nCircle(2) = {arc};\nLine(3) = {flat};\n\
         Curve Loop(1) = {loop_};\nPlane Surface(1) = {{1}};\nPhysical Curve(\"axis\") = {{1}};\n\
         Physical Curve(\"arc\") = {{2}};\nPhysical Curve(\"flat\") = {{3}};\nPhysical Surface(\"domain\") = {{1}};\n\
         Field[1] = Distance; Field[1].PointsList = {{2}};\nField[2] = Threshold; Field[2].InField = 1; \
         Field[2].SizeMin = hf; Field[2].SizeMax = h; Field[2].DistMin = {:?}; Field[2].DistMax = {:?};\n\
         Background Field = 2;\nMesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0;\n",
        0.1 * radius,
        0.5 * radius
    );
    let (geo_path, msh_path) = (dir.join(format!("{name}.geo")), dir.join(format!("{name}.msh")));
    std::fs::write(&geo_path, geo).map_err(|e| e.to_string())?;
    let out = std::process::Command::new("gmsh")
        .args(["-2", "-order", "2", "-format", "msh41", "-v", "1"])
        .arg(&geo_path)
        .arg("-o")
        .arg(&msh_path)
        .output()
        .map_err(|e| format!("gmsh: {e}"))?;
    ensure(out.status.success(), || format!("gmsh: {}", String::from_utf8_lossy(&out.stderr)))?;
    Ok(msh_path)
}

/// Hertz between two spheres: a steel hemisphere of radius 0.1 m pressed by `q` on its flat
/// face onto an aluminium hemisphere of radius 0.2 m held at its flat face (`u_z = 0`),
/// frictionless, non-matching gmsh meshes (cells 0.5 mm and 0.65 mm at the poles; a = 5 mm).
/// `1/R = 1/R1 + 1/R2`, `1/E* = (1 − ν1²)/E1 + (1 − ν2²)/E2`, `P = q π R1²` (the full
/// revolution's force), `a = (3PR/(4E*))^(1/3)`, `p0 = 3P/(2πa²)`. The fit of `p² = p0² (1 −
/// r²/a²)` to the contact points gives `a` and `p0` within 1 % (measured: a +0.37 %, p0 −0.08 %);
/// the pole (a P2 vertex of the slave side on the axis: node-to-segment row) does not sink into
/// the lower sphere (it stays open by 4.4e-5 of the approach a²/R), its extrapolated pressure
/// is p0's within 2 % (measured −0.17 %); the contact forces' axial resultant is P (1e-9).
pub fn hertz_two_spheres(s: &Session) -> Result<(), String> {
    let dir = std::env::temp_dir().join(format!("signorini-axi-spheres-{}", std::process::id()));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let (r1, r2) = (0.1, 0.2);
    let upper = hemisphere_mesh(&dir, "upper", r1, true, 5e-4, 0.01)?;
    let lower = hemisphere_mesh(&dir, "lower", r2, false, 6.5e-4, 0.02)?;
    let (steel, aluminium) = ((210e9, 0.3), (70e9, 0.33));
    let estar = 1.0 / ((1.0 - 0.09) / steel.0 + (1.0 - 0.33f64 * 0.33) / aluminium.0);
    let radius = r1 * r2 / (r1 + r2);
    let q = 4.66e6;
    let load = q * PI * r1 * r1;
    let a = (3.0 * load * radius / (4.0 * estar)).cbrt();
    let p0 = 3.0 * load / (2.0 * PI * a * a);
    let text = format!(
        "title = \"Hertz: two spheres\"\n\n[[body]]\nname = \"upper\"\nmesh = {{ shape = \"file\", file = {:?} }}\n\
         material = {{ young = {:e}, poisson = {}, plane = \"axisymmetric\" }}\ndiscretization = {{ order = 2 }}\n\n\
         [[body.traction]]\npart = \"flat\"\npressure = {q:e}\n\n[[body]]\nname = \"lower\"\n\
         mesh = {{ shape = \"file\", file = {:?} }}\nmaterial = {{ young = {:e}, poisson = {}, plane = \"axisymmetric\" }}\n\
         discretization = {{ order = 2 }}\n\n[[body.dirichlet]]\npart = \"flat\"\nuy = 0.0\n\n[[contact_pair]]\n\
         slave = \"upper.arc\"\nmaster = \"lower.arc\"\nfriction = \"none\"\n",
        upper.display().to_string(),
        steel.0,
        steel.1,
        lower.display().to_string(),
        aluminium.0,
        aluminium.1
    );
    let p = solve_text(s, &text, &dir.join("spheres.toml")).map_err(|e| format!("two spheres: {e}"))?;
    let pts = points(&p, 0);
    let peak = pts.iter().map(|q| q.1).fold(0.0, f64::max);
    let closed: Vec<(f64, f64)> = pts.iter().filter(|q| q.1 > 1e-6 * peak).map(|q| (q.0, q.1)).collect();
    let (a_fit, p0_fit) = fit_half_width_and_peak(&closed);
    let pole = pts.first().filter(|q| q.0 == 0.0).ok_or("no contact point on the axis")?;
    // The axial resultant of the contact forces on the upper sphere: `Σ (n_z rN + t_z rT)`.
    let c = p.contact.as_ref().unwrap();
    let force = &p.contact_outcome.as_ref().unwrap().force;
    let total: f64 = (0..c.boundary.points())
        .map(|i| c.boundary.normal[i][1] * force[2 * i] + c.boundary.tangent[i][1] * force[2 * i + 1])
        .sum();
    let axis_points = c.boundary.axis_pressure.len();
    eprintln!(
        "    two spheres: a {a_fit:.5e} (Hertz {a:.5e}, {:+.2} %), p0 {p0_fit:.5e} (Hertz {p0:.5e}, {:+.2} %), pole \
         pressure {:.5e} ({:+.2} %), contact force {total:.5e} (P {load:.5e}), {axis_points} axis point(s)",
        100.0 * (a_fit / a - 1.0),
        100.0 * (p0_fit / p0 - 1.0),
        pole.1,
        100.0 * (pole.1 / p0 - 1.0)
    );
    ensure(axis_points == 1, || format!("{axis_points} axis points"))?;
    ensure((a_fit / a - 1.0).abs() < 1e-2 && (p0_fit / p0 - 1.0).abs() < 1e-2, || {
        format!("a {a_fit:e} vs {a:e}, p0 {p0_fit:e} vs {p0:e}: {pts:?}")
    })?;
    ensure((pole.1 / p0 - 1.0).abs() < 2e-2, || format!("pole pressure {} vs p0 {p0:e}", pole.1))?;
    ensure((total / load - 1.0).abs() < 1e-9, || format!("contact force {total:e} vs P {load:e}"))?;
    // The pole (upper sphere, slave) against the lower one's pole (master, the same point): no
    // interpenetration beyond round-off of the approach.
    let u = p.displacement.as_ref().ok_or("no displacement")?;
    let (slave_pole, master_pole) = {
        let bodies = &p.bodies.as_ref().unwrap().layout.bodies;
        let find = |range: &std::ops::Range<usize>| {
            range.clone().find(|&k| p.mesh.nodes[k] == [0.0, 0.0]).ok_or("no pole node".to_string())
        };
        (find(&bodies[0].nodes)?, find(&bodies[1].nodes)?)
    };
    // The condensed routes (no augmentation; the axis point's weight 0 only reports its
    // pressure) give the full-space answer, whose augmentation at the axis point borrows its
    // neighbour's weight; frictionless and with Coulomb friction μ = 0.3 (the axis point has
    // no friction, u_r being prescribed on both poles: its tangential row keeps the slave's
    // unit tangent, mortar/points.rs, or the condensed flexibility would be singular).
    let solve = |text: &str, solver: Option<ContactSolverSpec>| -> Result<Vec<(f64, f64, f64)>, String> {
        let mut scene = Scene::from_str(text, &dir.join("spheres.toml")).map_err(|e| e.to_string())?;
        scene.contact_solver = solver;
        let mut q = ElasticityProblem::setup_system(s, scene).map_err(|e| format!("{solver:?}: {e}"))?;
        q.assemble().and_then(|_| q.solve()).and_then(|_| q.postprocess()).map_err(|e| format!("{solver:?}: {e}"))?;
        Ok(points(&q, 0))
    };
    let coulomb_text = text.replace("friction = \"none\"", "friction = \"coulomb\"\nmu = 0.3");
    let coulomb = solve(&coulomb_text, None)?;
    for solver in [ContactSolverSpec::Newton, ContactSolverSpec::DPana] {
        for (what, text, reference) in [("frictionless", &text, &pts), ("Coulomb", &coulomb_text, &coulomb)] {
            let other = solve(text, Some(solver))?;
            let apart = reference
                .iter()
                .zip(&other)
                .map(|(a, b)| (a.1 - b.1).abs().max((a.2 - b.2).abs()) / p0)
                .fold(0.0, f64::max);
            eprintln!("    two spheres, {what}: {solver:?} tractions {apart:.1e} of p0 from the full-space route's");
            ensure(other.len() == reference.len() && apart < 1e-6, || {
                format!("{what}, {solver:?}: tractions {apart:e} of p0 apart")
            })?;
        }
    }
    let (_, p0_coulomb) =
        fit_half_width_and_peak(&coulomb.iter().filter(|q| q.1 > 1e-6 * peak).map(|q| (q.0, q.1)).collect::<Vec<_>>());
    eprintln!(
        "    two spheres, Coulomb μ = 0.3: p0 {p0_coulomb:.5e} ({:+.2} % from Hertz)",
        100.0 * (p0_coulomb / p0 - 1.0)
    );
    // Touching at the start, the upper pole must stay above the lower one: `u_z,s − u_z,m ≥ 0`.
    let approach = a * a / radius;
    let gap = u[2 * slave_pole + 1] - u[2 * master_pole + 1];
    eprintln!("    two spheres: pole gap after the load {:.2e} of the approach a²/R", gap / approach);
    ensure(gap >= -1e-9 * approach, || format!("the pole sinks in by {:e} (approach {approach:e})", -gap))
}
