//! The FCLIB export of the condensed contact problem (`signorini::export::fclib`), read back
//! with the HDF5 library through the `hdf5` crate, by the file's names and types alone: the
//! layout of FCLIB's reference reader (`fclib_read_local`, `fclib_read_solution`), the data
//! equal to ours, our solution satisfying FCLIB's conditions; and the problems it refuses.
use std::path::PathBuf;

use hdf5::types::{FloatSize, IntSize, TypeDescriptor};
use nalgebra::{DMatrix, DVector};
use signorini::contact::FrictionLaw;
use signorini::export::{write_fclib, FclibInfo};
use signorini::petsc::Session;
use signorini::problem::ElasticityProblem;
use signorini::scene::Scene;
use signorini::Error;

use super::contact::{example, set_line, solve_text};
use super::ensure;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("signorini-petsc-export-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The square block of Raous–Chabrand–Lebon on an 8 × 8 mesh: 8 contact points (the corner
/// (40 mm, 0) is fixed, so left out).
fn small_block(friction: &str) -> (String, PathBuf) {
    let (text, path) = example("square_block.toml");
    let text = set_line(&text, "cell_size", "cell_size = 5e-3");
    let text = set_line(&text, "solver", "solver = \"newton\"");
    let text = match friction {
        "coulomb" => text,
        "tresca" => set_line(&set_line(&text, "friction", "friction = \"tresca\""), "mu", "threshold = 1e7"),
        _ => set_line(&set_line(&text, "friction", "friction = \"none\""), "mu", ""),
    };
    (text, path)
}

/// A dataset's values, checking FCLIB's type: native 32-bit ints or float64.
fn ints(file: &hdf5::File, name: &str) -> Result<Vec<i32>, String> {
    let d = file.dataset(name).map_err(|e| format!("{name}: {e}"))?;
    let t = d.dtype().and_then(|t| t.to_descriptor()).map_err(|e| e.to_string())?;
    ensure(t == TypeDescriptor::Integer(IntSize::U4), || format!("{name}: type {t:?}, FCLIB reads native int"))?;
    d.read_raw::<i32>().map_err(|e| e.to_string())
}

fn doubles(file: &hdf5::File, name: &str) -> Result<Vec<f64>, String> {
    let d = file.dataset(name).map_err(|e| format!("{name}: {e}"))?;
    let t = d.dtype().and_then(|t| t.to_descriptor()).map_err(|e| e.to_string())?;
    ensure(t == TypeDescriptor::Float(FloatSize::U8), || format!("{name}: type {t:?}, FCLIB reads double"))?;
    d.read_raw::<f64>().map_err(|e| e.to_string())
}

/// The exported square block (Coulomb μ = 1 and frictionless) read back: every dataset of the
/// layout with FCLIB's types and sizes; W (compressed columns) equal to our Delassus matrix
/// entry for entry; q = g̃ − u_free; mu; our solution, in FCLIB's convention, solving the file's
/// problem (u = W r + q, u_N ≥ 0, r_N ≥ 0, u_N r_N = 0, |r_T| ≤ μ r_N, sliding opposite to
/// r_T) and being the answer the program's own condensed route gives; no temporary left.
pub fn fclib_export_square_block_reads_back(s: &Session) -> Result<(), String> {
    let dir = scratch("block");
    let mut coulomb_w: Option<DMatrix<f64>> = None;
    for friction in ["coulomb", "none"] {
        let (text, path) = small_block(friction);
        let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
        let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
        let problem = p.condensed_contact_problem().map_err(|e| format!("{friction}: {e}"))?;
        let ours = p.solve_condensed_contact_problem(&problem).map_err(|e| format!("{friction}: {e}"))?;
        let file = dir.join(friction).join("nested/problem.hdf5");
        let info = FclibInfo::new("square block", "the PETSc suite's export test", &problem);
        let summary = write_fclib(&file, &problem, Some(&ours.force), &info).map_err(|e| e.to_string())?;
        let m = problem.points();
        ensure(m == 8 && summary.contacts == 8 && summary.dimension == 2 && summary.solution, || {
            format!("{friction}: {m} points, summary {summary:?}")
        })?;
        let names: Vec<String> = std::fs::read_dir(file.parent().unwrap())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
            .collect();
        ensure(names == ["problem.hdf5"], || format!("left in the directory: {names:?}"))?;

        let h = hdf5::File::open(&file).map_err(|e| e.to_string())?;
        let n = 2 * m;
        ensure(ints(&h, "fclib_local/spacedim")? == [2], || "spacedim".into())?;
        let (m_, n_, nz, nzmax) = (
            ints(&h, "fclib_local/W/m")?,
            ints(&h, "fclib_local/W/n")?,
            ints(&h, "fclib_local/W/nz")?,
            ints(&h, "fclib_local/W/nzmax")?,
        );
        ensure(m_ == [n as i32] && n_ == [n as i32] && nz == [-1], || format!("W header {m_:?} {n_:?} {nz:?}"))?;
        let (pp, ii, xx) =
            (ints(&h, "fclib_local/W/p")?, ints(&h, "fclib_local/W/i")?, doubles(&h, "fclib_local/W/x")?);
        ensure(pp.len() == n + 1 && pp[0] == 0 && pp[n] == nzmax[0], || format!("column pointers {pp:?}"))?;
        ensure(ii.len() == nzmax[0] as usize && xx.len() == ii.len(), || "i, x sizes".into())?;
        let mut w = DMatrix::<f64>::zeros(n, n);
        for j in 0..n {
            ensure(pp[j] <= pp[j + 1], || format!("column pointers decrease at {j}"))?;
            let rows = &ii[pp[j] as usize..pp[j + 1] as usize];
            ensure(rows.windows(2).all(|r| r[0] < r[1]), || format!("rows of column {j} not increasing"))?;
            for k in pp[j] as usize..pp[j + 1] as usize {
                w[(ii[k] as usize, j)] = xx[k];
            }
        }
        let ours_w = problem.delassus().as_dense().unwrap();
        ensure(w == *ours_w, || format!("{friction}: the file's W differs from ours"))?;
        ensure(w == w.transpose(), || "W is not symmetric".into())?;
        // Without friction the whole flexibility is exported (the tangential block included):
        // the same W as with Coulomb friction.
        match &coulomb_w {
            None => coulomb_w = Some(w.clone()),
            Some(c) => ensure(*c == w, || "frictionless W differs from the Coulomb one".into())?,
        }
        let q = doubles(&h, "fclib_local/vectors/q")?;
        let mu = doubles(&h, "fclib_local/vectors/mu")?;
        for i in 0..m {
            let (g, uf) = (problem.gap()[i], problem.free_displacement());
            ensure(q[2 * i] == g - uf[2 * i] && q[2 * i + 1] == 0.0 - uf[2 * i + 1], || format!("q at point {i}"))?;
        }
        let expected_mu = if friction == "coulomb" { 1.0 } else { 0.0 };
        ensure(mu.len() == m && mu.iter().all(|&v| v == expected_mu), || format!("mu {mu:?}"))?;
        for key in ["title", "description", "math_info"] {
            let d = h.dataset(&format!("fclib_local/info/{key}")).map_err(|e| e.to_string())?;
            let t = d.dtype().and_then(|t| t.to_descriptor()).map_err(|e| e.to_string())?;
            ensure(d.shape().is_empty() && matches!(t, TypeDescriptor::FixedAscii(k) if k > 1), || {
                format!("info/{key}: shape {:?}, type {t:?}: FCLIB reads a scalar fixed-length string", d.shape())
            })?;
        }
        ensure(!h.link_exists("guesses") && !h.link_exists("fclib_local/R"), || "unexpected groups".into())?;

        // Our solution solves the file's problem in FCLIB's convention.
        let (u, r) = (doubles(&h, "solution/u")?, doubles(&h, "solution/r")?);
        let wr = &w * DVector::from_column_slice(&r);
        let (force_scale, disp_scale) =
            (r.iter().fold(0.0f64, |a, v| a.max(v.abs())), u.iter().chain(&q).fold(0.0f64, |a, v| a.max(v.abs())));
        let mut closed = 0;
        for k in 0..n {
            ensure((u[k] - wr[k] - q[k]).abs() <= 1e-12 * disp_scale, || format!("u = W r + q fails at {k}"))?;
        }
        for i in 0..m {
            let (un, ut, rn, rt) = (u[2 * i], u[2 * i + 1], r[2 * i], r[2 * i + 1]);
            ensure(un >= -1e-9 * disp_scale && rn >= -1e-9 * force_scale, || format!("point {i}: u_N {un}, r_N {rn}"))?;
            ensure((un * rn).abs() <= 1e-9 * disp_scale * force_scale, || format!("point {i}: u_N r_N = {}", un * rn))?;
            ensure(rt.abs() <= mu[i] * rn + 1e-9 * force_scale, || format!("point {i}: |r_T| {rt} > mu r_N {rn}"))?;
            ensure(rt * ut <= 1e-9 * force_scale * disp_scale, || {
                format!("point {i}: r_T {rt} does not oppose u_T {ut}")
            })?;
            if rn > 1e-9 * force_scale {
                closed += 1;
            }
        }
        ensure(closed >= m / 2, || format!("{friction}: only {closed} of {m} points closed"))?;

        // It is the problem the program solves: the condensed route of `run` gives this force.
        let run = solve_text(s, &text, &path).map_err(|e| e.to_string())?;
        let force = &run.contact_outcome.as_ref().unwrap().force;
        let diff = force.iter().zip(&r).map(|(a, b)| (a + b).abs()).fold(0.0f64, f64::max);
        ensure(diff <= 1e-8 * force_scale, || {
            format!("{friction}: run's force differs from the file's r by {diff:e}")
        })?;
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// What FCLIB cannot hold is refused with a typed error, and no file is left: Tresca friction
/// (`Error::Formulation`, from the writer and from `check_friction`), a scene without contact
/// (`Error::Usage`), a body held by the contact alone (`Error::Unconstrained`: no flexibility).
pub fn fclib_export_refuses_what_it_cannot_hold(s: &Session) -> Result<(), String> {
    let dir = scratch("refused");
    let file = dir.join("problem.hdf5");
    // Tresca: the condensed problem exists, FCLIB has no form for it.
    let (text, path) = small_block("tresca");
    let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    let early = signorini::export::check_friction(&p.contact.as_ref().unwrap().friction_law());
    ensure(matches!(early, Err(Error::Formulation { .. })), || format!("check_friction: {early:?}"))?;
    let problem = p.condensed_contact_problem().map_err(|e| e.to_string())?;
    ensure(matches!(problem.friction(), FrictionLaw::Tresca { .. }), || "not Tresca".into())?;
    let info = FclibInfo::new("t", "d", &problem);
    match write_fclib(&file, &problem, None, &info) {
        Err(Error::Formulation { message, hint }) => {
            ensure(message.contains("Tresca") && hint.contains("coulomb"), || format!("{message} / {hint}"))?
        }
        other => return Err(format!("Tresca export: {other:?}")),
    }
    ensure(!dir.exists(), || "the refused export created files".into())?;
    // No [contact].
    let (text, path) = example("block.toml");
    let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    match p.condensed_contact_problem() {
        Err(Error::Usage(m)) => ensure(m.contains("no [contact] section"), || m.clone())?,
        other => return Err(format!("no contact: {:?}", other.map(|c| c.points()))),
    }
    // Held by the contact alone: the patch test's block is free to move vertically.
    let (text, path) = example("contact_patch.toml");
    let scene = Scene::from_str(&text, &path).map_err(|e| e.to_string())?;
    let mut p = ElasticityProblem::setup_system(s, scene).map_err(|e| e.to_string())?;
    match p.condensed_contact_problem() {
        Err(Error::Unconstrained(m)) => {
            ensure(m.contains("held by the contact") && m.contains("Dirichlet"), || m.clone())?
        }
        other => return Err(format!("held by contact: {:?}", other.map(|c| c.points()))),
    }
    Ok(())
}
