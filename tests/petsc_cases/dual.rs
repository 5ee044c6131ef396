//! The dual (Airy/HCT) formulation: exact stress fields to round-off on irregular meshes,
//! supports per component, body force, and the error in the constitutive relation against the
//! primal solution (Prager–Synge).
use signorini::dual::checks::check;
use signorini::dual::{BodyLoad, DualData, DualSystem};
use signorini::estimate::{volume_terms, ExactStress, StressField};
use signorini::fem::assembly::{Constraints, Loads};
use signorini::fem::assembly::{EdgeLoad, Traction};
use signorini::fem::material::{Material, PlaneModel};
use signorini::mesh::{gmsh, Mesh, Order};
use signorini::petsc::Session;

fn block(cell: f64, order: Order) -> Mesh {
    let request = gmsh::MeshRequest {
        shape: gmsh::Shape::Rectangle { origin: [0.0, 0.0], size: [2.0, 1.0] },
        cell_size: cell,
        refinement: None,
        order,
    };
    gmsh::generate(&request).expect("gmsh")
}

fn group(mesh: &Mesh, name: &str) -> usize {
    mesh.group_index(name, 1).unwrap()
}

/// Solve the dual problem and compare its stresses with `exact` at the Gauss points of every
/// piece; the worst relative difference and the check.
fn solve_and_compare(
    session: &Session,
    mesh: &Mesh,
    material: &Material,
    data: &DualData,
    exact: impl Fn([f64; 2]) -> [f64; 3],
) -> Result<(f64, signorini::dual::DualCheck), String> {
    let system = DualSystem::new(mesh, material, data).map_err(|e| e.to_string())?;
    let (phi, _) = system.solve(session, mesh).map_err(|e| e.to_string())?;
    let field = system.field(mesh, &phi);
    // Pointwise at every node of every cell.
    let mut worst = 0.0f64;
    let mut scale = 0.0f64;
    for c in 0..mesh.num_cells() {
        for &n in mesh.cell(c) {
            let x = mesh.nodes[n];
            let (s, e) = (field.stress_at(c, x), exact(x));
            for k in 0..3 {
                worst = worst.max((s[k] - e[k]).abs());
                scale = scale.max(e[k].abs());
            }
        }
    }
    Ok((worst / scale, check(&field, data)))
}

/// The frictionless patch test with tractions on the whole boundary: σ = diag(−νp/(1−ν), −p).
pub fn dual_patch_test_all_tractions_exact(session: &Session) -> Result<(), String> {
    let (p, nu) = (1e6, 0.2);
    let lateral = nu * p / (1.0 - nu);
    for order in [Order::P1, Order::P2] {
        let mesh = block(0.3, order);
        let material = Material::new(90e9, nu, PlaneModel::Strain);
        let loads = [
            EdgeLoad { group: group(&mesh, "top"), traction: Traction::Pressure(p) },
            EdgeLoad { group: group(&mesh, "bottom"), traction: Traction::Pressure(p) },
            EdgeLoad { group: group(&mesh, "left"), traction: Traction::Pressure(lateral) },
            EdgeLoad { group: group(&mesh, "right"), traction: Traction::Pressure(lateral) },
        ];
        let data =
            DualData { body_force: BodyLoad::Constant([0.0, 0.0]), edge_loads: &loads, prescribed: &[], contact: None };
        let (err, check) = solve_and_compare(session, &mesh, &material, &data, |_| [-lateral, -p, 0.0])?;
        if err > 1e-11 || check.worst() > 1e-11 {
            return Err(format!("{order:?}: stress error {err:e}, check {check:?}"));
        }
    }
    Ok(())
}

/// The stick patch test's stress field with shear q, and the same with a roller support on the
/// bottom (uy = 0: the normal traction is unknown there, the shear known).
pub fn dual_stick_patch_and_roller_support_exact(session: &Session) -> Result<(), String> {
    let (p, q, nu) = (1e6, 3e5, 0.3);
    let lateral = nu * p / (1.0 - nu);
    let mesh = block(0.25, Order::P1);
    let material = Material::new(2e11, nu, PlaneModel::Strain);
    let exact = |_: [f64; 2]| [-lateral, -p, q];
    let loads = [
        EdgeLoad { group: group(&mesh, "top"), traction: Traction::Constant([q, -p]) },
        EdgeLoad { group: group(&mesh, "bottom"), traction: Traction::Constant([-q, p]) },
        EdgeLoad { group: group(&mesh, "left"), traction: Traction::Constant([lateral, -q]) },
        EdgeLoad { group: group(&mesh, "right"), traction: Traction::Constant([-lateral, q]) },
    ];
    let data =
        DualData { body_force: BodyLoad::Constant([0.0, 0.0]), edge_loads: &loads, prescribed: &[], contact: None };
    let (err, check) = solve_and_compare(session, &mesh, &material, &data, exact)?;
    if err > 1e-11 || check.worst() > 1e-11 {
        return Err(format!("stick patch: stress error {err:e}, check {check:?}"));
    }
    // Roller on the bottom: uy = 0 prescribed, the shear traction −q still given there.
    let (p2, nu2) = (1e6, 0.3);
    let lateral2 = nu2 * p2 / (1.0 - nu2);
    let loads = [
        EdgeLoad { group: group(&mesh, "top"), traction: Traction::Pressure(p2) },
        EdgeLoad { group: group(&mesh, "left"), traction: Traction::Pressure(lateral2) },
        EdgeLoad { group: group(&mesh, "right"), traction: Traction::Pressure(lateral2) },
    ];
    let prescribed = [(group(&mesh, "bottom"), [None, Some(0.0)])];
    let data = DualData {
        body_force: BodyLoad::Constant([0.0, 0.0]),
        edge_loads: &loads,
        prescribed: &prescribed,
        contact: None,
    };
    // With a support the field comes out of a genuine minimisation: the linear solve's
    // round-off shows (measured 2.3e-10 on 2026-11-26; the docs' "1e-11 with a roller" does
    // not hold here, only the check values do).
    let (err, check) = solve_and_compare(session, &mesh, &material, &data, |_| [-lateral2, -p2, 0.0])?;
    if err > 1e-9 || check.worst() > 1e-11 {
        return Err(format!("roller: stress error {err:e}, check {check:?}"));
    }
    Ok(())
}

/// Pure bending of a beam (φ cubic: σxx = k y) and a body force (σyy linear): exact.
pub fn dual_cubic_airy_and_body_force_exact(session: &Session) -> Result<(), String> {
    let mesh = {
        let request = gmsh::MeshRequest {
            shape: gmsh::Shape::Rectangle { origin: [0.0, -0.5], size: [4.0, 1.0] },
            cell_size: 0.3,
            refinement: None,
            order: Order::P1,
        };
        gmsh::generate(&request).map_err(|e| e.to_string())?
    };
    let material = Material::new(2e11, 0.3, PlaneModel::Stress);
    let k = 1e7;
    let left = |x: [f64; 2], _n: [f64; 2]| [-k * x[1], 0.0];
    let right = |x: [f64; 2], _n: [f64; 2]| [k * x[1], 0.0];
    let loads = [
        EdgeLoad { group: group(&mesh, "left"), traction: Traction::Field(&left) },
        EdgeLoad { group: group(&mesh, "right"), traction: Traction::Field(&right) },
    ];
    let data =
        DualData { body_force: BodyLoad::Constant([0.0, 0.0]), edge_loads: &loads, prescribed: &[], contact: None };
    let (err, check) = solve_and_compare(session, &mesh, &material, &data, |x| [k * x[1], 0.0, 0.0])?;
    if err > 1e-11 || check.worst() > 1e-11 {
        return Err(format!("bending: stress error {err:e}, check {check:?}"));
    }
    // A block under its weight ρg held by tractions on its bottom (σyy = ρg (y − 1)), and the
    // same on a roller support, whose exact solution this is when ν = 0 (otherwise the roller
    // would have to bend the bottom into a parabola).
    let mesh = block(0.25, Order::P1);
    let rho_g = 7.7e4;
    let exact = |x: [f64; 2]| [0.0, rho_g * (x[1] - 1.0), 0.0];
    let bottom = [EdgeLoad { group: group(&mesh, "bottom"), traction: Traction::Constant([0.0, rho_g]) }];
    let data =
        DualData { body_force: BodyLoad::Constant([0.0, -rho_g]), edge_loads: &bottom, prescribed: &[], contact: None };
    let (err, check) = solve_and_compare(session, &mesh, &material, &data, exact)?;
    if err > 1e-11 || check.worst() > 1e-11 {
        return Err(format!("weight on tractions: stress error {err:e}, check {check:?}"));
    }
    let material = Material::new(2e11, 0.0, PlaneModel::Stress);
    let prescribed = [(group(&mesh, "bottom"), [None, Some(0.0)])];
    let data = DualData {
        body_force: BodyLoad::Constant([0.0, -rho_g]),
        edge_loads: &[],
        prescribed: &prescribed,
        contact: None,
    };
    // Measured 6.7e-11 (2026-11-26): above the docs' 1e-11, as for the roller above.
    let (err, check) = solve_and_compare(session, &mesh, &material, &data, exact)?;
    if err > 1e-9 || check.worst() > 1e-11 {
        return Err(format!("weight on a roller: stress error {err:e}, check {check:?}"));
    }
    Ok(())
}

/// Loads that are not in equilibrium on a boundary loaded by tractions only are refused, and
/// a domain with a hole is refused with the Michell explanation.
pub fn dual_refuses_unbalanced_loads_and_holes(session: &Session) -> Result<(), String> {
    let _ = session;
    let mesh = block(0.5, Order::P1);
    let material = Material::new(2e11, 0.3, PlaneModel::Strain);
    let loads = [EdgeLoad { group: group(&mesh, "top"), traction: Traction::Pressure(1e6) }];
    let data =
        DualData { body_force: BodyLoad::Constant([0.0, 0.0]), edge_loads: &loads, prescribed: &[], contact: None };
    match DualSystem::new(&mesh, &material, &data) {
        Err(e @ signorini::Error::NoEquilibrium(_)) => {
            let m = e.to_string();
            if !m.contains("not in equilibrium") {
                return Err(m);
            }
        }
        other => return Err(format!("unbalanced loads accepted: {:?}", other.err())),
    }
    // A square with a square hole.
    let geo = "Point(1)={0,0,0,0.3};Point(2)={3,0,0,0.3};Point(3)={3,3,0,0.3};Point(4)={0,3,0,0.3};\
               Point(5)={1,1,0,0.3};Point(6)={2,1,0,0.3};Point(7)={2,2,0,0.3};Point(8)={1,2,0,0.3};\
               Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};\
               Line(5)={5,8};Line(6)={8,7};Line(7)={7,6};Line(8)={6,5};\
               Curve Loop(1)={1,2,3,4};Curve Loop(2)={5,6,7,8};Plane Surface(1)={1,2};\
               Physical Curve(\"outer\")={1,2,3,4};Physical Curve(\"hole\")={5,6,7,8};Physical Surface(\"domain\")={1};";
    let holed = gmsh::generate_from_geo(geo, Order::P1).map_err(|e| e.to_string())?;
    let prescribed = [(group(&holed, "outer"), [Some(0.0), Some(0.0)])];
    let data = DualData {
        body_force: BodyLoad::Constant([0.0, -1.0]),
        edge_loads: &[],
        prescribed: &prescribed,
        contact: None,
    };
    match DualSystem::new(&holed, &material, &data) {
        Err(e @ signorini::Error::Formulation { .. }) => {
            let m = e.to_string();
            if !(m.contains("hole") && m.contains("Michell") && m.contains("hint")) {
                return Err(m);
            }
        }
        other => return Err(format!("a domain with a hole accepted: {:?}", other.err())),
    }
    Ok(())
}

// ---------------------------------------------------------------- against the primal

/// Timoshenko's cantilever [0, 4] × [−½, ½] loaded by a shear force P at x = 0 and balanced at
/// x = 4 (tractions on the whole boundary; S. Timoshenko, J. N. Goodier, *Theory of
/// Elasticity*, §21): σxx = −P x y / I, σxy = −P (c² − y²) / (2I), σyy = 0, I = 2c³/3. Its Airy
/// function is quartic, so no mesh reproduces it; the in-plane stresses hold for any ν in
/// plane strain and plane stress (a traction problem on a simply connected domain).
const P: f64 = 1e6;
const C: f64 = 0.5;
const I: f64 = 2.0 * C * C * C / 3.0;

fn cantilever_stress(x: [f64; 2]) -> [f64; 3] {
    [-P * x[0] * x[1] / I, 0.0, -P * (C * C - x[1] * x[1]) / (2.0 * I)]
}

fn cantilever_mesh(h: f64, order: Order) -> Mesh {
    let request = gmsh::MeshRequest {
        shape: gmsh::Shape::Rectangle { origin: [0.0, -C], size: [4.0, 2.0 * C] },
        cell_size: h,
        refinement: None,
        order,
    };
    gmsh::generate(&request).expect("gmsh")
}

/// `σ_h − σ`: the dual field minus the exact one, on the dual pieces.
struct Difference<'a> {
    dual: &'a signorini::dual::DualField<'a>,
}

impl StressField for Difference<'_> {
    fn pieces(&self, cell: usize) -> Vec<[[f64; 2]; 3]> {
        self.dual.pieces(cell)
    }
    fn stress(&self, cell: usize, piece: usize, x: [f64; 2]) -> [f64; 3] {
        let (a, b) = (self.dual.stress(cell, piece, x), cantilever_stress(x));
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
}

/// (‖σ_h − Cε(u_h)‖², ‖σ − σ_h‖², ‖σ − Cε(u_h)‖², ‖σ‖²) on one mesh.
fn cantilever_errors(session: &Session, mesh: &Mesh, material: &Material) -> Result<[f64; 4], String> {
    let left = |x: [f64; 2], _n: [f64; 2]| {
        let s = cantilever_stress(x);
        [-s[0], -s[2]]
    };
    let right = |x: [f64; 2], _n: [f64; 2]| {
        let s = cantilever_stress(x);
        [s[0], s[2]]
    };
    let loads = [
        EdgeLoad { group: group(mesh, "left"), traction: Traction::Field(&left) },
        EdgeLoad { group: group(mesh, "right"), traction: Traction::Field(&right) },
    ];
    // Primal: the same tractions, rigid motions removed at two corners (their reactions vanish:
    // the loads balance).
    let corner = |p: [f64; 2]| {
        (0..mesh.num_nodes())
            .min_by(|&a, &b| {
                let d = |n: usize| (mesh.nodes[n][0] - p[0]).hypot(mesh.nodes[n][1] - p[1]);
                d(a).total_cmp(&d(b))
            })
            .unwrap()
    };
    let mut constraints = Constraints::new(2 * mesh.num_nodes());
    let (a, b) = (corner([0.0, -C]), corner([4.0, -C]));
    constraints.fix(2 * a, 0.0);
    constraints.fix(2 * a + 1, 0.0);
    constraints.fix(2 * b + 1, 0.0);
    let primal_loads = Loads { body_force: None, edge_loads: loads.to_vec() };
    let (u, _) = super::solve(session, mesh, material, &constraints, &primal_loads, "").map_err(|e| e.to_string())?;
    let data =
        DualData { body_force: BodyLoad::Constant([0.0, 0.0]), edge_loads: &loads, prescribed: &[], contact: None };
    let system = DualSystem::new(mesh, material, &data).map_err(|e| e.to_string())?;
    let (phi, _) = system.solve(session, mesh).map_err(|e| e.to_string())?;
    let field = system.field(mesh, &phi);
    let zero = vec![0.0; u.len()];
    let sum = |t: signorini::estimate::VolumeTerms| t.element_squared.iter().sum::<f64>();
    let cre = sum(volume_terms(mesh, material, &u, &field, 5));
    let dual = sum(volume_terms(mesh, material, &zero, &Difference { dual: &field }, 5));
    let exact = ExactStress { mesh, stress: cantilever_stress };
    let primal = sum(volume_terms(mesh, material, &u, &exact, 5));
    let norm = sum(volume_terms(mesh, material, &zero, &exact, 5));
    Ok([cre, dual, primal, norm])
}

/// The least-squares slope of log e against log h.
fn fitted_rate(h: &[f64], e: &[f64]) -> f64 {
    let (x, y): (Vec<f64>, Vec<f64>) = h.iter().zip(e).map(|(h, e)| (h.ln(), e.ln())).unzip();
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

/// The mean cell size `(area / cells)^½` of a mesh of area 4.
fn mean_size(mesh: &Mesh) -> f64 {
    (4.0 / mesh.num_cells() as f64).sqrt()
}

/// The observed rates on the cantilever: dual h² (full HCT, smooth solution), primal P1 h,
/// P2 h²; the estimate is above both errors.
pub fn dual_cantilever_rates(session: &Session) -> Result<(), String> {
    let material = Material::new(2e11, 0.3, PlaneModel::Stress);
    let hs = [0.4, 0.2, 0.1, 0.05];
    for (order, primal_rate) in [(Order::P1, 0.9), (Order::P2, 1.8)] {
        let (mut sizes, mut dual, mut primal) = (Vec::new(), Vec::new(), Vec::new());
        for &h in &hs {
            let mesh = cantilever_mesh(h, order);
            // The end shear is quadratic along the edges; the dual imposes its linear L2
            // projection (HCT tractions are linear per edge), so the hypercircle identity holds
            // here up to that data term only (it is tested exactly on the manufactured problem).
            let [cre, d, p, norm] = cantilever_errors(session, &mesh, &material)?;
            if cre.sqrt() < d.sqrt().max(p.sqrt()) {
                return Err(format!("{order:?} h = {h}: the estimate {} is below an error", cre.sqrt()));
            }
            sizes.push(mean_size(&mesh));
            dual.push((d / norm).sqrt());
            primal.push((p / norm).sqrt());
        }
        let (rd, rp) = (fitted_rate(&sizes, &dual), fitted_rate(&sizes, &primal));
        if std::env::var_os("SIGNORINI_PRINT_RATES").is_some() {
            eprintln!("{order:?}: sizes {sizes:?}\n  dual {dual:?} rate {rd:.2}\n  primal {primal:?} rate {rp:.2}");
        }
        if rd < 1.8 || rp < primal_rate {
            return Err(format!(
                "{order:?}: fitted rates dual {rd:.2} (errors {dual:?}), primal {rp:.2} (errors {primal:?}), expected 1.8 and {primal_rate}"
            ));
        }
    }
    Ok(())
}

/// Near incompressibility (plane strain, ν = 0.4999): the dual stresses converge as at ν = 0.3
/// (no locking), the P1 primal ones do not.
pub fn dual_does_not_lock(session: &Session) -> Result<(), String> {
    let hs = [0.2, 0.1, 0.05];
    let mut dual = [Vec::new(), Vec::new()];
    let mut primal = [Vec::new(), Vec::new()];
    for (k, nu) in [0.3, 0.4999].into_iter().enumerate() {
        let material = Material::new(2e11, nu, PlaneModel::Strain);
        for &h in &hs {
            let mesh = cantilever_mesh(h, Order::P1);
            let [_, d, p, norm] = cantilever_errors(session, &mesh, &material)?;
            dual[k].push((d / norm).sqrt());
            primal[k].push((p / norm).sqrt());
        }
    }
    let (r3, r5) = (vec![fitted_rate(&hs, &dual[0])], vec![fitted_rate(&hs, &dual[1])]);
    for k in 0..hs.len() {
        let ratio = dual[1][k] / dual[0][k];
        if !(0.5..2.0).contains(&ratio) {
            return Err(format!("dual at ν = 0.4999 vs 0.3: {:?} vs {:?}", dual[1], dual[0]));
        }
    }
    if r5.iter().zip(&r3).any(|(a, b)| (a - b).abs() > 0.3) || r5.iter().any(|&r| r < 1.8) {
        return Err(format!("dual rates ν = 0.3 {r3:?}, ν = 0.4999 {r5:?}"));
    }
    // P1 locks: at ν = 0.4999 its error is several times the ν = 0.3 one on every mesh.
    if primal[1].iter().zip(&primal[0]).any(|(a, b)| a < &(3.0 * b)) {
        return Err(format!("P1 did not lock?! ν = 0.4999 {:?} vs ν = 0.3 {:?}", primal[1], primal[0]));
    }
    Ok(())
}

/// The manufactured solution u = (s, s), s = sin πx sin πy on the unit square, clamped all
/// round (u = 0 there, so every u_h of the primal is kinematically admissible), with the body
/// force F = −div σ(u) and the particular field σp = (−∫₀ˣ Fx dx, −∫₀ʸ Fy dy, 0).
pub fn dual_prager_synge_identity_manufactured(session: &Session) -> Result<(), String> {
    use std::f64::consts::PI;
    use std::sync::Arc;
    let material = Material::new(210e9, 0.3, PlaneModel::Strain);
    let (lambda, mu) = material.lame();
    let force = move |x: [f64; 2]| {
        let sv = (PI * x[0]).sin() * (PI * x[1]).sin();
        let cc = (PI * x[0]).cos() * (PI * x[1]).cos();
        let f = PI * PI * ((3.0 * mu + lambda) * sv - (lambda + mu) * cc);
        [f, f]
    };
    let particular = move |x: [f64; 2]| {
        let (sx, cx, sy, cy) = ((PI * x[0]).sin(), (PI * x[0]).cos(), (PI * x[1]).sin(), (PI * x[1]).cos());
        let ix = PI * ((3.0 * mu + lambda) * sy * (1.0 - cx) - (lambda + mu) * cy * sx);
        let iy = PI * ((3.0 * mu + lambda) * sx * (1.0 - cy) - (lambda + mu) * cx * sy);
        [-ix, -iy, 0.0]
    };
    let exact = move |x: [f64; 2]| {
        let dx = PI * (PI * x[0]).cos() * (PI * x[1]).sin();
        let dy = PI * (PI * x[0]).sin() * (PI * x[1]).cos();
        material.stress([dx, dy, dx + dy])
    };
    for order in [Order::P1, Order::P2] {
        for h in [0.2, 0.1] {
            let mesh = gmsh::generate(&gmsh::MeshRequest {
                shape: gmsh::Shape::Rectangle { origin: [0.0, 0.0], size: [1.0, 1.0] },
                cell_size: h,
                refinement: None,
                order,
            })
            .map_err(|e| e.to_string())?;
            let mut constraints = Constraints::new(2 * mesh.num_nodes());
            let mut prescribed = Vec::new();
            for side in ["bottom", "right", "top", "left"] {
                let g = group(&mesh, side);
                constraints.fix_group(&mesh, g, 0, |_| 0.0);
                constraints.fix_group(&mesh, g, 1, |_| 0.0);
                prescribed.push((g, [Some(0.0), Some(0.0)]));
            }
            let loads = Loads { body_force: Some(&force), edge_loads: vec![] };
            let (u, _) =
                super::solve(session, &mesh, &material, &constraints, &loads, "").map_err(|e| e.to_string())?;
            let data = DualData {
                body_force: BodyLoad::Field(Arc::new(move |x| (force(x), particular(x)))),
                edge_loads: &[],
                prescribed: &prescribed,
                contact: None,
            };
            let system = DualSystem::new(&mesh, &material, &data).map_err(|e| e.to_string())?;
            let (phi, _) = system.solve(session, &mesh).map_err(|e| e.to_string())?;
            let field = system.field(&mesh, &phi);
            let c = check(&field, &data);
            if c.interior_equilibrium > 1e-6 || c.stress_jump > 1e-11 {
                return Err(format!("{order:?} h = {h}: not admissible: {c:?}"));
            }
            let sum = |t: signorini::estimate::VolumeTerms| t.element_squared.iter().sum::<f64>();
            let zero = vec![0.0; u.len()];
            let cre = sum(volume_terms(&mesh, &material, &u, &field, 10));
            let difference = Shifted { dual: &field, exact: &exact };
            let dual = sum(volume_terms(&mesh, &material, &zero, &difference, 10));
            let sigma = ExactStress { mesh: &mesh, stress: exact };
            let primal = sum(volume_terms(&mesh, &material, &u, &sigma, 10));
            let identity = (cre - dual - primal).abs() / cre;
            if identity > 1e-10 {
                return Err(format!(
                    "{order:?} h = {h}: Prager-Synge off by {identity:e} ({cre:e} vs {dual:e} + {primal:e})"
                ));
            }
        }
    }
    Ok(())
}

/// `σ_h − σ` for any exact σ.
struct Shifted<'a> {
    dual: &'a signorini::dual::DualField<'a>,
    exact: &'a dyn Fn([f64; 2]) -> [f64; 3],
}

impl StressField for Shifted<'_> {
    fn pieces(&self, cell: usize) -> Vec<[[f64; 2]; 3]> {
        self.dual.pieces(cell)
    }
    fn stress(&self, cell: usize, piece: usize, x: [f64; 2]) -> [f64; 3] {
        let (a, b) = (self.dual.stress(cell, piece, x), (self.exact)(x));
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
}

/// The saddle point with the constraints as multipliers gives the eliminated solution: with
/// MUMPS LDLᵀ to round-off, with SYMMLQ + Jacobi to its tolerance, and exactly admissible in
/// both cases (the constraints are restored after the solve).
pub fn dual_saddle_point_agrees_with_elimination(session: &Session) -> Result<(), String> {
    use signorini::scene::DualConstraints;
    let mesh = block(0.15, Order::P1);
    let material = Material::new(2e11, 0.3, PlaneModel::Strain);
    let right = [EdgeLoad { group: group(&mesh, "right"), traction: Traction::Constant([1e6, -3e6]) }];
    let prescribed = [(group(&mesh, "left"), [Some(0.0), Some(0.0)]), (group(&mesh, "bottom"), [None, Some(0.0)])];
    let data = DualData {
        body_force: BodyLoad::Constant([0.0, -7.7e4]),
        edge_loads: &right,
        prescribed: &prescribed,
        contact: None,
    };
    let system = DualSystem::new(&mesh, &material, &data).map_err(|e| e.to_string())?;
    if system.saddle_point_size() != 2 * system.dofs.len() - system.num_unknowns() {
        return Err("saddle-point size".into());
    }
    let (reference, _) = system.solve(session, &mesh).map_err(|e| e.to_string())?;
    let reference_field = system.field(&mesh, &reference);
    let difference = |phi: &[f64]| {
        let field = system.field(&mesh, phi);
        let (mut worst, mut scale) = (0.0f64, 0.0f64);
        for c in 0..mesh.num_cells() {
            for &n in mesh.cell(c) {
                let x = mesh.nodes[n];
                let (a, b) = (field.stress_at(c, x), reference_field.stress_at(c, x));
                for k in 0..3 {
                    worst = worst.max((a[k] - b[k]).abs());
                    scale = scale.max(b[k].abs());
                }
            }
        }
        (worst / scale, check(&field, &data))
    };
    let (phi, stats) =
        system.solve_with(session, &mesh, "kkt_direct_", DualConstraints::Multipliers).map_err(|e| e.to_string())?;
    let (err, chk) = difference(&phi);
    if stats.factor_package.as_deref() != Some("mumps") || err > 1e-9 || chk.worst() > 1e-11 {
        return Err(format!("saddle point, MUMPS: {stats:?}, stress difference {err:e}, check {chk:?}"));
    }
    for (k, v) in [("ksp_type", "symmlq"), ("pc_type", "jacobi"), ("ksp_max_it", "200000")] {
        session.set_option(&format!("-kkt_symmlq_{k}"), Some(v)).map_err(|e| e.to_string())?;
    }
    let (phi, stats) =
        system.solve_with(session, &mesh, "kkt_symmlq_", DualConstraints::Multipliers).map_err(|e| e.to_string())?;
    let (err, chk) = difference(&phi);
    // The operator is fourth order (condition ~h⁻⁴): a residual of 1e-8 leaves pointwise
    // stresses right to ~1e-3 and the energy, quadratic, to ~1e-7.
    let energy = check(&reference_field, &data).complementary_energy;
    let energy_error = (chk.complementary_energy - energy).abs() / energy.abs();
    if stats.ksp_type != "symmlq" || stats.iterations < 10 || err > 2e-3 || energy_error > 1e-7 || chk.worst() > 1e-11 {
        return Err(format!(
            "saddle point, SYMMLQ: {stats:?}, stress difference {err:e}, energy difference {energy_error:e}, check {chk:?}"
        ));
    }
    // Without -ksp_type, a non-direct preconditioner gets SYMMLQ on the saddle point (CG would
    // break down on the indefinite matrix).
    for (k, v) in [("pc_type", "jacobi"), ("ksp_max_it", "200000")] {
        session.set_option(&format!("-kkt_auto_{k}"), Some(v)).map_err(|e| e.to_string())?;
    }
    let (_, stats) =
        system.solve_with(session, &mesh, "kkt_auto_", DualConstraints::Multipliers).map_err(|e| e.to_string())?;
    if stats.ksp_type != "symmlq" {
        return Err(format!("default Krylov method on the saddle point: {}", stats.ksp_type));
    }
    Ok(())
}
