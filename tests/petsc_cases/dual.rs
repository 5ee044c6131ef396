//! The dual (Airy/HCT) formulation: exact stress fields to round-off on irregular meshes,
//! supports per component, body force, and the error in the constitutive relation against the
//! primal solution (Prager–Synge).
use signorini::dual::checks::check;
use signorini::dual::{DualData, DualSystem};
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
        let data = DualData { body_force: [0.0, 0.0], edge_loads: &loads, prescribed: &[], free_groups: &[] };
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
    let data = DualData { body_force: [0.0, 0.0], edge_loads: &loads, prescribed: &[], free_groups: &[] };
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
    let data = DualData { body_force: [0.0, 0.0], edge_loads: &loads, prescribed: &prescribed, free_groups: &[] };
    // With a support the field comes out of a genuine minimisation: the linear solve's
    // round-off shows (measured 7e-11).
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
    let data = DualData { body_force: [0.0, 0.0], edge_loads: &loads, prescribed: &[], free_groups: &[] };
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
    let data = DualData { body_force: [0.0, -rho_g], edge_loads: &bottom, prescribed: &[], free_groups: &[] };
    let (err, check) = solve_and_compare(session, &mesh, &material, &data, exact)?;
    if err > 1e-11 || check.worst() > 1e-11 {
        return Err(format!("weight on tractions: stress error {err:e}, check {check:?}"));
    }
    let material = Material::new(2e11, 0.0, PlaneModel::Stress);
    let prescribed = [(group(&mesh, "bottom"), [None, Some(0.0)])];
    let data = DualData { body_force: [0.0, -rho_g], edge_loads: &[], prescribed: &prescribed, free_groups: &[] };
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
    let data = DualData { body_force: [0.0, 0.0], edge_loads: &loads, prescribed: &[], free_groups: &[] };
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
    let data = DualData { body_force: [0.0, -1.0], edge_loads: &[], prescribed: &prescribed, free_groups: &[] };
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
