//! Fuzzing the two readers of user files, the scene (TOML) and the mesh (MSH 4.1), for a fixed
//! number of deterministic mutations of valid files (a seeded xorshift generator: the same
//! inputs on every run). Properties: the readers never panic, and every error they return is
//! located — a scene error carries the file, line and column; a mesh file error the file and a
//! line; a mesh validation error names the entity. `SIGNORINI_FUZZ_CASES=N` runs N mutations
//! per base file instead of the default.
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use signorini::mesh::msh::read_msh;
use signorini::scene::Scene;
use signorini::Error;

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

fn cases(default: usize) -> usize {
    std::env::var("SIGNORINI_FUZZ_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "1e308",
    "1e-320",
    "-0.0",
    "0",
    "-1",
    "99999999999999999999",
    "\"\"",
    "[]",
    "[1.0]",
    "[1.0, 2.0, 3.0]",
    "{}",
    "true",
    "=",
    "[",
    "]",
    "[[traction]]",
    "[mesh]",
    "\n",
    "#",
    "\"disc\"",
    "order = 3",
    "shape = \"file\"",
    "file = \"/nonexistent.msh\"",
    "\u{feff}",
    "é",
    "\t",
    "'",
    "\"\"\"",
];

/// One mutation of `text` (byte level; may break UTF-8).
fn mutate(rng: &mut Rng, bytes: &[u8]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    for _ in 0..1 + rng.below(3) {
        let at = rng.below(out.len() + 1).min(out.len());
        match rng.below(7) {
            0 => {
                if !out.is_empty() {
                    let i = at.min(out.len() - 1);
                    out[i] ^= 1 << rng.below(8);
                }
            }
            1 => out.truncate(at),
            2 => {
                let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
                out.splice(at..at, t.iter().copied());
            }
            3 => {
                let end = (at + rng.below(40)).min(out.len());
                out.drain(at..end);
            }
            4 => {
                // Duplicate a line.
                let start = out[..at].iter().rposition(|&b| b == b'\n').map_or(0, |p| p + 1);
                let end = out[at..].iter().position(|&b| b == b'\n').map_or(out.len(), |p| at + p + 1);
                let line = out[start..end].to_vec();
                out.splice(start..start, line);
            }
            5 => {
                // Replace a number with a token.
                if let Some(p) = out[at..].iter().position(|b| b.is_ascii_digit()) {
                    let s = at + p;
                    let e =
                        out[s..].iter().position(|b| !(b.is_ascii_digit() || *b == b'.')).map_or(out.len(), |q| s + q);
                    let t = TOKENS[rng.below(TOKENS.len())].as_bytes();
                    out.splice(s..e, t.iter().copied());
                }
            }
            _ => out.insert(at, rng.next() as u8),
        }
    }
    out
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("signorini-fuzz-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn scene_reader_never_panics_and_locates_every_error() {
    let dir = scratch("scene");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/scenes");
    let mut bases: Vec<PathBuf> = std::fs::read_dir(&scenes)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    bases.sort();
    assert!(bases.len() >= 5);
    let mut rng = Rng(0x5eed_1234_abcd_ef01);
    let (mut errors, mut oks) = (0, 0);
    for base in &bases {
        let text = std::fs::read(base).unwrap();
        for case in 0..cases(250) {
            let input = mutate(&mut rng, &text);
            let path = dir.join("s.toml");
            std::fs::write(&path, &input).unwrap();
            let result = catch_unwind(AssertUnwindSafe(|| Scene::from_file(&path)));
            let shown = String::from_utf8_lossy(&input);
            match result {
                Err(_) => {
                    panic!("the scene reader panicked on a mutation of {} (case {case}):\n{shown}", base.display())
                }
                Ok(Ok(_)) => oks += 1,
                Ok(Err(Error::Scene { location, .. })) => {
                    assert!(location.line >= 1 && location.column >= 1 && location.file == path, "{location:?}");
                    errors += 1;
                }
                Ok(Err(other)) => panic!("unlocated scene error {other:?} for (case {case}):\n{shown}"),
            }
        }
    }
    assert!(errors > 100 && oks > 10, "the mutations should both break and keep scenes: {errors} errors, {oks} ok");
}

#[test]
fn invalid_utf8_in_a_scene_is_located() {
    let dir = scratch("utf8");
    let path = dir.join("s.toml");
    std::fs::write(&path, b"title = \"ok\"\n[mesh]\nshape = \"rect\xffangle\"\n").unwrap();
    match Scene::from_file(&path) {
        Err(Error::Scene { location, message, .. }) => {
            assert_eq!((location.line, location.column), (3, 14), "{message}");
            assert!(message.contains("UTF-8") && message.contains("0xff"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

fn gmsh_msh(dir: &Path, name: &str, extra: &[&str]) -> Vec<u8> {
    let geo = dir.join("m.geo");
    std::fs::write(
        &geo,
        "Point(1)={0,0,0,0.4};Point(2)={1,0,0,0.4};Point(3)={1,1,0,0.4};Point(4)={0,1,0,0.4};\n\
         Line(1)={1,2};Line(2)={2,3};Line(3)={3,4};Line(4)={4,1};Curve Loop(1)={1,2,3,4};Plane Surface(1)={1};\n\
         Physical Curve(\"bottom\")={1};Physical Curve(\"rest\")={2,3,4};Physical Surface(\"domain\")={1};\n",
    )
    .unwrap();
    let out = dir.join(name);
    let status = std::process::Command::new("gmsh")
        .arg(&geo)
        .args(["-2", "-format", "msh41", "-v", "0"])
        .args(extra)
        .arg("-o")
        .arg(&out)
        .status()
        .expect("gmsh (./setup.sh installs it)");
    assert!(status.success());
    std::fs::read(out).unwrap()
}

#[test]
fn msh_reader_never_panics_and_locates_every_error() {
    let dir = scratch("msh");
    let bases = [
        ("p1_ascii", gmsh_msh(&dir, "a.msh", &[])),
        ("p2_ascii", gmsh_msh(&dir, "b.msh", &["-order", "2"])),
        ("p1_binary", gmsh_msh(&dir, "c.msh", &["-bin"])),
    ];
    let mut rng = Rng(0x0dd_ba11_cafe_f00d);
    let (mut errors, mut oks) = (0, 0);
    for (name, bytes) in &bases {
        assert!(read_msh(&dir.join(match *name {
            "p1_ascii" => "a.msh",
            "p2_ascii" => "b.msh",
            _ => "c.msh",
        }))
        .is_ok());
        for case in 0..cases(300) {
            let input = mutate(&mut rng, bytes);
            let path = dir.join("fuzz.msh");
            std::fs::write(&path, &input).unwrap();
            match catch_unwind(AssertUnwindSafe(|| read_msh(&path))) {
                Err(_) => {
                    let keep = dir.join(format!("panic-{name}-{case}.msh"));
                    std::fs::write(&keep, &input).unwrap();
                    panic!("the MSH reader panicked on a mutation of {name} (case {case}), kept as {}", keep.display());
                }
                Ok(Ok(_)) => oks += 1,
                Ok(Err(Error::MeshFile { line, file, .. })) => {
                    assert!(line.is_some_and(|l| l >= 1) && file == path, "unlocated: {line:?}");
                    errors += 1;
                }
                Ok(Err(Error::Mesh { entity, .. })) => {
                    assert!(!entity.is_empty());
                    errors += 1;
                }
                Ok(Err(other)) => panic!("unexpected error kind for {name} case {case}: {other:?}"),
            }
        }
    }
    assert!(errors > 100, "the mutations should break files: {errors} errors, {oks} ok");
}
