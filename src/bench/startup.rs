//! `signorini bench startup`: what a run costs besides its solve, measured in one run of the
//! benchmark so that a busy machine still compares.
//!
//! - Start-up: `signorini run --quiet` of the 1e3-dof square block
//!   (`examples/scenes/square_block_1k.toml`), `--runs` times, alternating with
//!   `signorini --version` (which only loads the program and its libraries: the floor of any
//!   run). Wall time per process (min and median) and mean CPU time (the children's user +
//!   system time, from `/proc/self/stat`). Target: the run under 0.15 s.
//! - Meshing: the 8.6e4-dof P2 half disc with Coulomb friction
//!   (`examples/scenes/half_disc_86k.toml`) run twice against a fresh mesh cache: the first run
//!   meshes with Gmsh, the second takes the mesh from the cache. The ratio mesh / contact
//!   solve time of each, from the runs' own reports. Targets: at most 0.25 on the first run,
//!   near zero cached.
//!
//! Every measurement is a child process of the benchmark (the program under test is the
//! benchmark's own executable), run in a scratch directory that is removed at the end.
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use crate::error::{Error, Result};

/// The 1e3-dof start-up scene.
pub const SMALL_SCENE: &str = include_str!("../../examples/scenes/square_block_1k.toml");
/// The 8.6e4-dof P2 half disc.
pub const HALF_DISC_SCENE: &str = include_str!("../../examples/scenes/half_disc_86k.toml");

/// Wall times of repeated runs of one command, and their mean CPU time.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Timing {
    /// Runs timed.
    pub runs: usize,
    /// Fastest wall time (s).
    pub min_seconds: f64,
    /// Median wall time (s).
    pub median_seconds: f64,
    /// Mean user + system time per run (resolution 0.01 s / runs).
    pub mean_cpu_seconds: f64,
}

/// One run of the half disc, from its report.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct MeshRun {
    /// Displacement unknowns.
    pub dofs: usize,
    /// Seconds to get the mesh.
    pub mesh_seconds: f64,
    /// Seconds of the solve.
    pub solve_seconds: f64,
    /// `hit`, `miss` or `disabled`, as the run reported it.
    pub cache: String,
}

impl MeshRun {
    /// Mesh time over solve time.
    pub fn ratio(&self) -> f64 {
        self.mesh_seconds / self.solve_seconds
    }
}

#[derive(Debug, Clone, PartialEq, serde::Serialize)]
/// The start-up benchmark: a bare command, a small run, and the half disc meshed then cached.
pub struct StartupBench {
    /// Displacement unknowns of the small run.
    pub small_dofs: usize,
    /// `signorini --version`.
    pub bare: Timing,
    /// A small scene solved.
    pub small_run: Timing,
    /// The half disc with an empty mesh cache.
    pub first: Option<MeshRun>,
    /// The half disc again, its mesh from the cache.
    pub cached: Option<MeshRun>,
}

/// The children's CPU time so far (user + system of waited-for children), seconds.
fn children_cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    // Fields after the command name (which may hold spaces): state is field 3, cutime 16,
    // cstime 17; clock ticks of 1/100 s (USER_HZ on Linux).
    let fields: Vec<&str> = stat.rsplit_once(')').map_or("", |(_, rest)| rest).split_whitespace().collect();
    let ticks = |k: usize| fields.get(k - 3).and_then(|v| v.parse::<f64>().ok()).unwrap_or(0.0);
    (ticks(16) + ticks(17)) / 100.0
}

fn run(command: &mut Command) -> Result<f64> {
    let start = Instant::now();
    let out = command.output().map_err(|e| Error::Usage(format!("cannot start {command:?}: {e}")))?;
    let seconds = start.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(Error::Usage(format!(
            "{command:?} failed ({}): {}",
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        )));
    }
    Ok(seconds)
}

fn timing(mut walls: Vec<f64>, cpu: f64) -> Timing {
    walls.sort_by(f64::total_cmp);
    let n = walls.len();
    let median = if n % 2 == 1 { walls[n / 2] } else { 0.5 * (walls[n / 2 - 1] + walls[n / 2]) };
    Timing { runs: n, min_seconds: walls[0], median_seconds: median, mean_cpu_seconds: cpu / n as f64 }
}

fn report_json(dir: &Path) -> Result<serde_json::Value> {
    let path = dir.join("report.json");
    let text = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, "reading the run's report", e))?;
    serde_json::from_str(&text).map_err(|e| Error::Usage(format!("{}: {e}", path.display())))
}

/// Run the benchmark with the program `exe`, `runs` start-up runs, the half disc unless
/// `skip_half_disc`, in `scratch` (created, and removed at the end).
pub fn startup_bench(exe: &Path, runs: usize, skip_half_disc: bool, scratch: &Path) -> Result<StartupBench> {
    std::fs::create_dir_all(scratch).map_err(|e| Error::io(scratch, "creating the scratch directory", e))?;
    let result = measure(exe, runs.max(1), skip_half_disc, scratch);
    let _ = std::fs::remove_dir_all(scratch);
    result
}

fn measure(exe: &Path, runs: usize, skip_half_disc: bool, scratch: &Path) -> Result<StartupBench> {
    let write = |name: &str, text: &str| -> Result<PathBuf> {
        let path = scratch.join(name);
        std::fs::write(&path, text).map_err(|e| Error::io(&path, "writing a benchmark scene", e))?;
        Ok(path)
    };
    let small = write("square_block_1k.toml", SMALL_SCENE)?;
    let out = scratch.join("out");
    let bare = || {
        let mut c = Command::new(exe);
        c.arg("--version");
        c
    };
    let small_run = || {
        let mut c = Command::new(exe);
        c.arg("run").arg(&small).arg("--quiet").arg("--out").arg(&out);
        c
    };
    // One of each first, not counted: the files in the page cache.
    run(&mut bare())?;
    run(&mut small_run())?;
    let small_dofs = report_json(&out)?["dofs"].as_u64().unwrap_or(0) as usize;
    let (mut bare_walls, mut run_walls, mut bare_cpu, mut run_cpu) = (Vec::new(), Vec::new(), 0.0, 0.0);
    for _ in 0..runs {
        let cpu = children_cpu_seconds();
        bare_walls.push(run(&mut bare())?);
        let mid = children_cpu_seconds();
        run_walls.push(run(&mut small_run())?);
        bare_cpu += mid - cpu;
        run_cpu += children_cpu_seconds() - mid;
    }
    let (mut first, mut cached) = (None, None);
    if !skip_half_disc {
        let scene = write("half_disc_86k.toml", HALF_DISC_SCENE)?;
        let cache = scratch.join("mesh-cache");
        let half_disc = |into: &mut Option<MeshRun>| -> Result<()> {
            run(Command::new(exe)
                .arg("run")
                .arg(&scene)
                .arg("--quiet")
                .arg("--out")
                .arg(&out)
                .env("SIGNORINI_CACHE_DIR", &cache)
                .env_remove("SIGNORINI_NO_MESH_CACHE"))?;
            let r = report_json(&out)?;
            let seconds = |phase: &str| r["timings"][phase].as_f64().unwrap_or(f64::NAN);
            *into = Some(MeshRun {
                dofs: r["dofs"].as_u64().unwrap_or(0) as usize,
                mesh_seconds: seconds("mesh"),
                solve_seconds: seconds("solve"),
                cache: r["mesh_cache"]["status"].as_str().unwrap_or("none").to_string(),
            });
            Ok(())
        };
        half_disc(&mut first)?;
        half_disc(&mut cached)?;
    }
    Ok(StartupBench {
        small_dofs,
        bare: timing(bare_walls, bare_cpu),
        small_run: timing(run_walls, run_cpu),
        first,
        cached,
    })
}

/// The Markdown table of the results.
pub fn startup_table(b: &StartupBench) -> String {
    let t = |t: &Timing| format!("{:.3} | {:.3} | {:.3}", t.min_seconds, t.median_seconds, t.mean_cpu_seconds);
    let mut s = format!(
        "| start-up ({} runs each) | wall min (s) | wall median (s) | CPU mean (s) |\n|---|---:|---:|---:|\n\
         | `signorini --version` (loads the libraries) | {} |\n\
         | `signorini run --quiet`, {} dofs | {} |\n\
         | run − `--version` (medians) | | {:.3} | {:.3} |\n\n\
         Target: the run under 0.15 s.\n",
        b.bare.runs,
        t(&b.bare),
        b.small_dofs,
        t(&b.small_run),
        b.small_run.median_seconds - b.bare.median_seconds,
        b.small_run.mean_cpu_seconds - b.bare.mean_cpu_seconds,
    );
    let rows: Vec<(&str, &MeshRun)> = [("first run", b.first.as_ref()), ("second run", b.cached.as_ref())]
        .into_iter()
        .filter_map(|(n, r)| Some((n, r?)))
        .collect();
    if !rows.is_empty() {
        s.push_str(
            "\n| P2 half disc, Coulomb | dofs | mesh cache | mesh (s) | contact solve (s) | mesh / solve |\n\
             |---|---:|---|---:|---:|---:|\n",
        );
        for (name, r) in rows {
            s.push_str(&format!(
                "| {name} | {} | {} | {:.3} | {:.3} | {:.4} |\n",
                r.dofs,
                r.cache,
                r.mesh_seconds,
                r.solve_seconds,
                r.ratio()
            ));
        }
        s.push_str("\nTargets: mesh / solve at most 0.25 on the first run, near zero when cached.\n");
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_and_the_table() {
        let t = timing(vec![0.3, 0.1, 0.2, 0.4], 0.8);
        assert_eq!((t.min_seconds, t.median_seconds, t.mean_cpu_seconds), (0.1, 0.25, 0.2));
        let run = MeshRun { dofs: 85834, mesh_seconds: 1.0, solve_seconds: 8.0, cache: "miss".into() };
        let b = StartupBench { small_dofs: 1058, bare: t.clone(), small_run: t, first: Some(run), cached: None };
        let table = startup_table(&b);
        assert!(table.contains("| first run | 85834 | miss | 1.000 | 8.000 | 0.1250 |"), "{table}");
        assert!(!table.contains("second run"), "{table}");
    }

    /// The children's CPU time is read (not the 0 of an unreadable /proc/self/stat): a child
    /// that computes for about 0.2 s of CPU adds at least one clock tick.
    #[test]
    fn children_cpu_time_counts_a_waited_for_child() {
        let before = children_cpu_seconds();
        let busy = "i=0; while [ $i -lt 200000 ]; do i=$((i+1)); done";
        assert!(Command::new("sh").args(["-c", busy]).status().unwrap().success());
        let after = children_cpu_seconds();
        assert!(after > before && after - before >= 0.01, "children's CPU {before} s then {after} s");
    }
}
