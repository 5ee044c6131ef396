//! `-pc_type ict`: our threshold incomplete Cholesky as a PETSc preconditioner (PCSHELL).
use signorini::fem::assembly::{Constraints, EdgeLoad, Loads, Traction};
use signorini::mesh::{structured, Mesh, Order};
use signorini::petsc::{LinearSolver, Matrix, Session, SolveStats};
use signorini::Error;

use super::{ensure, set_options, solve, steel};

/// A clamped P2 cantilever 4 × 1 on an nx × nx/4 grid (nx = 32: about 4 300 dofs), tip load
/// downwards.
fn cantilever(nx: usize) -> (Mesh, Constraints) {
    let mesh = structured::rectangle([0.0, 0.0], [4.0, 1.0], nx, nx / 4, Order::P2).unwrap();
    let mut c = Constraints::new(2 * mesh.num_nodes());
    let left = mesh.require_group("left", 1).unwrap();
    c.fix_group(&mesh, left, 0, |_| 0.0);
    c.fix_group(&mesh, left, 1, |_| 0.0);
    (mesh, c)
}

fn run(s: &Session, prefix: &str, options: &[(&str, Option<&str>)]) -> Result<(Vec<f64>, SolveStats), Error> {
    run_on(s, 32, prefix, options)
}

fn run_on(
    s: &Session,
    nx: usize,
    prefix: &str,
    options: &[(&str, Option<&str>)],
) -> Result<(Vec<f64>, SolveStats), Error> {
    let (mesh, c) = cantilever(nx);
    set_options(s, prefix, options);
    let right = mesh.require_group("right", 1).unwrap();
    let loads = Loads {
        body_force: None,
        edge_loads: vec![EdgeLoad { group: right, traction: Traction::Constant([0.0, -1e6]) }],
    };
    solve(s, &mesh, &steel(), &c, &loads, prefix)
}

fn max_relative_difference(u: &[f64], v: &[f64]) -> f64 {
    let scale = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    u.iter().zip(v).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

/// CG + ICT (no -ksp_type: CG is chosen) solves the cantilever: the solve's independent
/// residual check passes, the answer agrees with MUMPS, and the report says ict with its τ.
pub fn ict_cg_solves_the_cantilever(s: &Session) -> Result<(), String> {
    let (reference, _) = run(s, "ictref_", &[]).map_err(|e| e.to_string())?;
    let (u, stats) = run(s, "ict1_", &[("pc_type", Some("ict")), ("pc_ict_drop_tolerance", Some("1e-3"))])
        .map_err(|e| e.to_string())?;
    println!("    CG + ICT(1e-3): {} iterations, {:.3} s, {}", stats.iterations, stats.seconds, stats.pc_type);
    ensure(stats.ksp_type == "cg", || format!("KSP {} instead of cg", stats.ksp_type))?;
    ensure(stats.pc_type.starts_with("ict (drop tolerance 1e-3"), || format!("pc_type {}", stats.pc_type))?;
    ensure(stats.relative_residual <= 1e-8, || format!("true residual {:e}", stats.relative_residual))?;
    let d = max_relative_difference(&u, &reference);
    ensure(d < 1e-6, || format!("relative difference {d:e} from MUMPS"))?;
    ensure(stats.pc_type.contains("RCM order"), || format!("RCM is the default: {}", stats.pc_type))?;
    // The natural order works too (more iterations on a structured grid numbered row by row
    // is not guaranteed, so only the answer and the report are checked).
    let (un, natural) = run(
        s,
        "ictnat_",
        &[("pc_type", Some("ict")), ("pc_ict_drop_tolerance", Some("1e-3")), ("pc_ict_ordering", Some("natural"))],
    )
    .map_err(|e| e.to_string())?;
    println!("    CG + ICT(1e-3, natural): {} iterations, {}", natural.iterations, natural.pc_type);
    ensure(!natural.pc_type.contains("RCM"), || natural.pc_type.clone())?;
    let d = max_relative_difference(&un, &reference);
    ensure(d < 1e-6, || format!("natural order: relative difference {d:e} from MUMPS"))?;
    // The option stays "ict" in the database: a second solver with the prefix works too.
    let (_, again) = run(s, "ict1_", &[]).map_err(|e| e.to_string())?;
    ensure(again.iterations == stats.iterations && again.pc_type.starts_with("ict"), || format!("{again:?}"))
}

/// τ → 0 keeps (nearly) the exact factor: CG converges in 1–2 iterations (on a 16 × 4 grid:
/// the exact factor in natural order is dense in its band); a fill limit is reported and
/// still converges.
pub fn ict_tiny_tolerance_is_a_direct_solve(s: &Session) -> Result<(), String> {
    let (_, stats) = run_on(s, 16, "ict0_", &[("pc_type", Some("ict")), ("pc_ict_drop_tolerance", Some("1e-14"))])
        .map_err(|e| e.to_string())?;
    println!("    CG + ICT(1e-14): {} iterations, {}", stats.iterations, stats.pc_type);
    ensure(stats.iterations <= 2, || format!("{} iterations with τ = 1e-14", stats.iterations))?;
    let (_, limited) = run(
        s,
        "ictp_",
        &[
            ("ksp_type", Some("cg")),
            ("pc_type", Some("ict")),
            ("pc_ict_drop_tolerance", Some("1e-4")),
            ("pc_ict_fill", Some("10")),
        ],
    )
    .map_err(|e| e.to_string())?;
    println!("    CG + ICT(1e-4, fill 10): {} iterations, {}", limited.iterations, limited.pc_type);
    ensure(limited.pc_type.contains("fill limit 10"), || limited.pc_type.clone())
}

/// Fewer iterations than ICC(0) at τ = 1e-2 and τ = 1e-3, and fewer as τ decreases.
pub fn ict_needs_fewer_iterations_than_icc0(s: &Session) -> Result<(), String> {
    let (_, icc0) =
        run(s, "icc0_", &[("ksp_type", Some("cg")), ("pc_type", Some("icc"))]).map_err(|e| e.to_string())?;
    let mut its = Vec::new();
    for (k, tau) in ["1e-2", "1e-3", "1e-4"].iter().enumerate() {
        let prefix = format!("ictt{k}_");
        let (_, st) = run(s, &prefix, &[("pc_type", Some("ict")), ("pc_ict_drop_tolerance", Some(tau))])
            .map_err(|e| e.to_string())?;
        println!("    CG + ICT({tau}): {} iterations, {:.3} s, {}", st.iterations, st.seconds, st.pc_type);
        its.push(st.iterations);
    }
    println!("    CG + ICC(0): {} iterations, {:.3} s", icc0.iterations, icc0.seconds);
    ensure(its[0] < icc0.iterations && its[1] < icc0.iterations, || {
        format!("ICT iterations {its:?} against ICC(0) {}", icc0.iterations)
    })?;
    ensure(its[0] >= its[1] && its[1] >= its[2], || format!("iterations {its:?} do not fall with τ"))
}

/// Bad values of the ICT options are typed errors naming the option; so are an unsymmetric
/// matrix (found in the shell's setup callback) and a non-positive diagonal.
pub fn ict_bad_options_and_matrices_are_typed_errors(s: &Session) -> Result<(), String> {
    let cases: &[(&str, &str, &str)] = &[
        ("ictbad1_", "pc_ict_drop_tolerance", "-1"),
        ("ictbad2_", "pc_ict_drop_tolerance", "abc"),
        ("ictbad3_", "pc_ict_fill", "abc"),
        ("ictbad4_", "pc_ict_fill", "-3"),
        ("ictbad5_", "pc_ict_drop_tolerance", "nan"),
        ("ictbad6_", "pc_ict_ordering", "amd"),
    ];
    for (prefix, name, value) in cases {
        let full = format!("-{prefix}{name}");
        match run(s, prefix, &[("pc_type", Some("ict")), (name, Some(value))]) {
            Err(Error::PetscOption { option, message }) => {
                ensure(option == full && message.contains(&full) && message.contains(value), || {
                    format!("{full} {value}: option {option}, message {message}")
                })?
            }
            other => return Err(format!("{full} {value}: expected a PetscOption error, got {:?}", other.map(|r| r.1))),
        }
    }
    // The matrix is checked in the setup callback; the typed error comes out of the solve.
    set_options(s, "ictmat_", &[("pc_type", Some("ict"))]);
    let unsym = Matrix::from_csr_rows(s, s.world(), 2, 0, &[0, 2, 4], &[0, 1, 0, 1], &[2.0, -1.0, -0.5, 2.0], 1, false)
        .map_err(|e| e.to_string())?;
    let negative = Matrix::from_csr_rows(s, s.world(), 2, 0, &[0, 1, 2], &[0, 1], &[2.0, -1.0], 1, false)
        .map_err(|e| e.to_string())?;
    for (a, what) in [(&unsym, "not symmetric"), (&negative, "diagonal entry (1, 1) is -1")] {
        let mut b = a.create_vector().map_err(|e| e.to_string())?;
        b.set_owned(&[1.0, 1.0]).map_err(|e| e.to_string())?;
        let mut x = a.create_vector().map_err(|e| e.to_string())?;
        let mut ksp = LinearSolver::new(s, s.world(), "ictmat_").map_err(|e| e.to_string())?;
        ksp.set_operator(a).map_err(|e| e.to_string())?;
        match ksp.solve(a, &b, &mut x) {
            Err(Error::Factorization { message, .. }) => ensure(message.contains(what), || message.clone())?,
            other => return Err(format!("{what}: expected a Factorization error, got {other:?}")),
        }
    }
    Ok(())
}
