//! `signorini export`: the condensed contact problem in the FCLIB format, read back by Python
//! h5py (the independent reader, installed by ./setup.sh) by FCLIB's names and types alone,
//! and the scenes it refuses.
#[path = "common/edit.rs"]
mod edit;
use edit::Edit;
use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_signorini"));
    c.env("OMP_NUM_THREADS", "1").env("OPENBLAS_NUM_THREADS", "1");
    c
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("signorini-cli-export-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The square block of Raous–Chabrand–Lebon on an 8 × 8 mesh (8 contact points), with the
/// `[contact]` lines `replace`d, written into `dir`.
fn small_block(dir: &Path, replace: &[(&str, &str)]) -> PathBuf {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/square_block.toml");
    let mut text = std::fs::read_to_string(path).unwrap().edit("cell_size = 1.25e-3", "cell_size = 5e-3");
    for (from, to) in replace {
        assert!(text.contains(from), "{from}");
        text = text.edit(from, to);
    }
    let scene = dir.join("block.toml");
    std::fs::write(&scene, text).unwrap();
    scene
}

/// Read an FCLIB local problem and its solution with h5py; the checks' numbers as JSON.
const READER: &str = r#"
import sys, json
try:
    import h5py, numpy as np
except BaseException as e:
    print('NO H5PY', e); sys.exit(3)
f = h5py.File(sys.argv[1], 'r')
L = f['fclib_local']
W = L['W']
ints = [L['spacedim']] + [W[k] for k in ('nzmax', 'm', 'n', 'nz', 'p', 'i')]
doubles = [W['x'], L['vectors/q'], L['vectors/mu'], f['solution/u'], f['solution/r']]
types_ok = all(d.dtype == np.int32 for d in ints) and all(d.dtype == np.float64 for d in doubles)
m, n, nz, nzmax = (int(W[k][0]) for k in ('m', 'n', 'nz', 'nzmax'))
p, i, x = W['p'][()], W['i'][()], W['x'][()]
A = np.zeros((m, n))
for j in range(n):
    A[i[p[j]:p[j + 1]], j] = x[p[j]:p[j + 1]]
q, mu = L['vectors/q'][()], L['vectors/mu'][()]
u, r = f['solution/u'][()], f['solution/r'][()]
un, ut, rn, rt = u[0::2], u[1::2], r[0::2], r[1::2]
us, rs = np.abs(np.concatenate([u, q])).max(), np.abs(r).max()
eig = np.linalg.eigvalsh((A + A.T) / 2)
info = {k: L['info'][k][()].decode('ascii') for k in ('title', 'description', 'math_info')}
print(json.dumps({
    'types_ok': bool(types_ok), 'spacedim': int(L['spacedim'][0]), 'm': m, 'n': n, 'nz': nz, 'nzmax': nzmax,
    'p_len': len(p), 'i_len': len(i), 'q_len': len(q), 'contacts': len(mu), 'mu': mu.tolist(),
    'asymmetry': float(np.abs(A - A.T).max() / np.abs(A).max()),
    'min_eig': float(eig.min() / eig.max()),
    'u_eq': float(np.abs(A @ r + q - u).max() / us),
    'min_un': float(un.min() / us), 'min_rn': float(rn.min() / rs),
    'complementarity': float(np.abs(un * rn).max() / (us * rs)),
    'cone': float((np.abs(rt) - mu * rn).max() / rs),
    'slip_work': float((rt * ut).max() / (us * rs)),
    'closed': int((rn > 1e-9 * rs).sum()),
    'sum_rn': float(rn.sum()), 'sum_rt': float(rt.sum()),
    'info': info, 'groups': sorted(f.keys()),
}))
"#;

fn read_back(file: &Path) -> serde_json::Value {
    let out =
        Command::new("python3").arg("-c").arg(READER).arg(file).output().expect("python3 is needed (run ./setup.sh)");
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        out.status.success(),
        "h5py failed (installed? run ./setup.sh): {stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&stdout).unwrap()
}

/// Export the small square block with `--solve` to the default file (./out/problem.hdf5, the
/// scene having no [output] dir), read it back with h5py: FCLIB's types and sizes, W symmetric
/// positive definite, our solution satisfying FCLIB's conditions in the file (u = W r + q,
/// u_N ≥ 0, r_N ≥ 0, u_N r_N = 0, |r_T| ≤ μ r_N, sliding opposite to r_T) and carrying the
/// contact resultants of `signorini run` on the same scene (with its sign flipped).
#[test]
fn export_square_block_reads_back_in_h5py() {
    let dir = scratch("block");
    let scene = small_block(&dir, &[]);
    let out = bin().current_dir(&dir).arg("export").arg(&scene).arg("--solve").output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "stdout: {stdout}\nstderr: {}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(stdout.lines().count(), 1, "one line: {stdout}");
    assert!(
        stdout.starts_with("wrote out/problem.hdf5: FCLIB local problem, 8 contacts in dimension 2 (W 16x16")
            && stdout.contains("Coulomb mu = 1")
            && stdout.contains("with our solution"),
        "{stdout}"
    );
    let v = read_back(&dir.join("out/problem.hdf5"));
    assert_eq!(v["types_ok"], true, "{v}");
    assert_eq!(
        (v["spacedim"].as_i64(), v["m"].as_i64(), v["n"].as_i64(), v["nz"].as_i64()),
        (Some(2), Some(16), Some(16), Some(-1))
    );
    let nzmax = v["nzmax"].as_u64().unwrap();
    assert!(nzmax > 16 && v["i_len"].as_u64() == Some(nzmax) && v["p_len"].as_u64() == Some(17), "{v}");
    assert_eq!((v["q_len"].as_u64(), v["contacts"].as_u64()), (Some(16), Some(8)));
    assert!(v["mu"].as_array().unwrap().iter().all(|m| m.as_f64() == Some(1.0)), "{v}");
    let num = |k: &str| v[k].as_f64().unwrap();
    assert!(num("asymmetry") == 0.0, "W symmetric: {v}");
    assert!(num("min_eig") > 0.0, "W positive definite: {v}");
    assert!(num("u_eq") < 1e-12, "u = W r + q: {v}");
    assert!(num("min_un") > -1e-9 && num("min_rn") > -1e-9, "u_N >= 0, r_N >= 0: {v}");
    assert!(num("complementarity") < 1e-9 && num("cone") < 1e-9 && num("slip_work") < 1e-9, "{v}");
    assert!(v["closed"].as_u64().unwrap() >= 4, "{v}");
    assert_eq!(v["groups"], serde_json::json!(["fclib_local", "solution"]));
    assert!(v["info"]["title"].as_str().unwrap().starts_with("Square block on a rigid foundation"), "{v}");
    assert!(v["info"]["math_info"].as_str().unwrap().contains("r_N >= 0"), "{v}");
    assert!(v["info"]["description"].as_str().unwrap().contains("8 contact points"), "{v}");

    // The same problem as `signorini run` solves: the resultants of its contact forces.
    let run_dir = dir.join("run");
    let run =
        bin().arg("run").arg(&scene).arg("--out").arg(&run_dir).arg("--contact-solver").arg("newton").output().unwrap();
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run_dir.join("report.json")).unwrap()).unwrap();
    let (normal, tangential) = (
        report["contact"]["normal_resultant"].as_f64().unwrap(),
        report["contact"]["tangential_resultant"].as_f64().unwrap(),
    );
    assert!((num("sum_rn") + normal).abs() <= 1e-8 * normal.abs(), "{} vs run {normal}", num("sum_rn"));
    assert!((num("sum_rt") + tangential).abs() <= 1e-8 * normal.abs(), "{} vs run {tangential}", num("sum_rt"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without `--solve`: no /solution; `--out` names the file. A scene without [contact] and a
/// Tresca scene are refused (exit 1, `error:` and what to do), leaving no file.
#[test]
fn export_without_solution_and_refused_scenes() {
    let dir = scratch("refused");
    let scene = small_block(&dir, &[("friction = \"coulomb\"", "friction = \"none\""), ("mu = 1.0", "")]);
    let file = dir.join("frictionless.hdf5");
    let out = bin().arg("export").arg(&scene).arg("--out").arg(&file).output().unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout.contains("8 contacts in dimension 2") && stdout.contains("frictionless"), "{stdout}");
    assert!(!stdout.contains("solution"), "{stdout}");
    let script = "import h5py, sys\nf = h5py.File(sys.argv[1], 'r')\nprint(sorted(f.keys()), f['fclib_local/vectors/mu'][()].max())";
    let py = Command::new("python3").arg("-c").arg(script).arg(&file).output().expect("python3");
    assert_eq!(
        String::from_utf8_lossy(&py.stdout).trim(),
        "['fclib_local'] 0.0",
        "{}",
        String::from_utf8_lossy(&py.stderr)
    );

    let refused = |scene: &Path, file: &Path| -> String {
        let out = bin().arg("export").arg(scene).arg("--out").arg(file).output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr).to_string();
        assert_eq!(out.status.code(), Some(1), "stderr: {stderr}");
        assert!(stderr.starts_with("error: "), "{stderr}");
        assert!(!file.exists(), "{} written", file.display());
        stderr
    };
    // Help, and a missing scene (a usage mistake: exit 2).
    let help = bin().args(["export", "-h"]).output().unwrap();
    assert!(help.status.success() && String::from_utf8_lossy(&help.stdout).contains("Usage: signorini export"));
    assert_eq!(bin().arg("export").output().unwrap().status.code(), Some(2));
    let no_contact = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes/block.toml");
    let stderr = refused(&no_contact, &dir.join("none.hdf5"));
    assert!(stderr.contains("has no [contact] section"), "{stderr}");
    let tresca_dir = dir.join("tresca");
    std::fs::create_dir_all(&tresca_dir).unwrap();
    let tresca = small_block(
        &tresca_dir,
        &[("friction = \"coulomb\"", "friction = \"tresca\""), ("mu = 1.0", "threshold = 1e7")],
    );
    let stderr = refused(&tresca, &tresca_dir.join("tresca.hdf5"));
    assert!(
        stderr.contains("no Tresca friction") && stderr.contains("hint: export the scene with friction = \"coulomb\""),
        "{stderr}"
    );
    assert_eq!(std::fs::read_dir(&tresca_dir).unwrap().count(), 1, "only the scene in {}", tresca_dir.display());
    let _ = std::fs::remove_dir_all(&dir);
}
