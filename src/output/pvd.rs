//! `solution.pvd` of a load path: a ParaView collection with one `.vtu` per increment, so that
//! ParaView's time slider steps through the increments.
//!
//! ```text
//!   <?xml version="1.0"?>
//!   <VTKFile type="Collection" version="0.1" byte_order="LittleEndian">
//!     <Collection>
//!       <DataSet timestep="2.5e-2" group="" part="0" file="steps/solution_0001.vtu"/>
//!       <DataSet timestep="5e-2" group="" part="0" file="steps/solution_0002.vtu"/>
//!     </Collection>
//!   </VTKFile>
//! ```
//!
//! The format is VTK's XML collection (`vtkPVDReader`, ParaView's "PVD" reader; VTK File
//! Formats, "Parallel File Formats"): `timestep` is the time ParaView shows for the data set,
//! `file` its path relative to the `.pvd` file. Times are written with `{:e}` (the shortest
//! decimal that reads back to the same `f64`), file names as given, escaped for an XML
//! attribute. (meshio reads time series from XDMF only, not from `.pvd`; the tests parse the
//! collection with an XML parser instead.)
use std::path::{Component, Path, PathBuf};

use crate::error::{Error, Result};
use crate::output::vtu::escape_attribute;
use crate::output::write_atomically;

/// The `.vtu` file of increment `step` (from 1), relative to the output directory:
/// `steps/solution_0001.vtu`, the number zero-padded to 4 digits (wider from 10000 on, so that
/// the names of a path of fewer than 10000 increments sort in order).
pub fn step_file_name(step: usize) -> String {
    format!("{STEPS_DIR}/solution_{step:04}.vtu")
}

/// The interface's `.vtu` file of increment `step` (from 1), relative to the output directory:
/// `steps/interface_0001.vtu`, numbered as [`step_file_name`] (listed in `interface.pvd`).
pub fn interface_step_file_name(step: usize) -> String {
    format!("{STEPS_DIR}/interface_{step:04}.vtu")
}

/// The directory of the step files, inside the output directory.
pub const STEPS_DIR: &str = "steps";

/// Is `name` (in [`STEPS_DIR`]) a step file of [`step_file_name`] or
/// [`interface_step_file_name`], `solution_NNNN.vtu` or `interface_NNNN.vtu` with at least 4
/// digits?
fn is_step_file(name: &str) -> bool {
    name.strip_prefix("solution_")
        .or_else(|| name.strip_prefix("interface_"))
        .and_then(|n| n.strip_suffix(".vtu"))
        .is_some_and(|digits| digits.len() >= 4 && digits.bytes().all(|b| b.is_ascii_digit()))
}

/// Remove a previous load path's step files from `dir/steps` (the names of [`step_file_name`]
/// and the temporaries a killed writer left of them), then `dir/steps` itself if nothing else
/// is in it; returns the paths removed, sorted. Other files are left alone. (The run files of
/// [`crate::output::clear_previous_run`] are plain names in `dir`: it does not look into
/// `steps/`.) If a step file cannot be removed, [`Error::Output`] names each one still there.
pub fn clear_step_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let steps = dir.join(STEPS_DIR);
    let mut removed = Vec::new();
    let Ok(entries) = std::fs::read_dir(&steps) else {
        return Ok(removed); // no steps directory: nothing to clear
    };
    let names: Vec<String> = entries.flatten().map(|e| e.file_name().to_string_lossy().to_string()).collect();
    let (gone, stale) = crate::output::remove_each(
        names.iter().filter(|n| is_step_file(n) || is_step_temporary(n)).map(|n| steps.join(n)),
    );
    removed.extend(gone);
    if let Some((first, reason)) = stale.first() {
        let names: Vec<String> = stale.iter().map(|(p, _)| p.display().to_string()).collect();
        return Err(Error::Output {
            path: first.clone(),
            message: format!(
                "removing the previous load path's step files failed ({reason}): {} still there, from an earlier \
                 run, not results of this one; remove them and run again",
                names.join(", ")
            ),
        });
    }
    // Best effort: a directory holding other files stays.
    let _ = std::fs::remove_dir(&steps);
    Ok(removed)
}

/// Is `name` the temporary file of a step file (`.solution_0003.vtu.PID.N.tmp`, see
/// [`crate::output::write_atomically`]), whether that step file exists or not?
fn is_step_temporary(name: &str) -> bool {
    name.strip_prefix('.').and_then(|n| n.split_once(".vtu.")).is_some_and(|(stem, _)| {
        is_step_file(&format!("{stem}.vtu")) && crate::output::is_temporary_of(name, &[format!("{stem}.vtu")])
    })
}

/// Write the collection `path` listing `entries` (time, file relative to `path`'s directory),
/// one data set each, in the order given, atomically (inside [`crate::output::all_or_nothing`]
/// it is part of the batch).
///
/// Refused with [`Error::Output`] naming `path` (nothing written): no entry, a non-finite
/// time, times not increasing, an empty or absolute file name or one with `..` (a collection
/// moved with its directory must still find its files).
pub fn write_pvd(path: &Path, entries: &[(f64, String)]) -> Result<()> {
    let refuse = |message: String| Error::Output {
        path: path.to_path_buf(),
        message: format!("{message} (nothing was written; an existing file at this path is unchanged)"),
    };
    if entries.is_empty() {
        return Err(refuse("a collection needs at least one data set, none was given".into()));
    }
    for (k, (time, file)) in entries.iter().enumerate() {
        if !time.is_finite() {
            return Err(refuse(format!("data set {} ({file}) has the time {time}: times must be finite", k + 1)));
        }
        if k > 0 && *time <= entries[k - 1].0 {
            return Err(refuse(format!(
                "data set {} ({file}) has the time {time:e}, not after the previous one's {:e}: times must \
                 increase",
                k + 1,
                entries[k - 1].0
            )));
        }
        let relative = Path::new(file);
        let inside = relative.components().all(|c| matches!(c, Component::Normal(_) | Component::CurDir));
        if file.is_empty() || !inside {
            return Err(refuse(format!(
                "data set {} has the file name {file:?}: give a path relative to the collection's directory, \
                 without `..`",
                k + 1
            )));
        }
    }
    write_atomically(path, |w| {
        writeln!(w, "<?xml version=\"1.0\"?>")?;
        writeln!(w, "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">")?;
        writeln!(w, "  <Collection>")?;
        for (time, file) in entries {
            writeln!(
                w,
                "    <DataSet timestep=\"{time:e}\" group=\"\" part=\"0\" file=\"{}\"/>",
                escape_attribute(file)
            )?;
        }
        writeln!(w, "  </Collection>")?;
        writeln!(w, "</VTKFile>")
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(test: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("signorini-pvd-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    /// The `(timestep, file)` attributes of the `<DataSet>` elements, by plain text scanning.
    fn data_sets(text: &str) -> Vec<(String, String)> {
        let attribute = |element: &str, name: &str| {
            let start = element.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
            element[start..].split('"').next().unwrap().to_string()
        };
        text.split("<DataSet").skip(1).map(|e| (attribute(e, "timestep"), attribute(e, "file"))).collect()
    }

    #[test]
    fn step_file_names_are_padded_to_four_digits_then_widen() {
        assert_eq!(step_file_name(1), "steps/solution_0001.vtu");
        assert_eq!(step_file_name(42), "steps/solution_0042.vtu");
        assert_eq!(step_file_name(9999), "steps/solution_9999.vtu");
        assert_eq!(step_file_name(10000), "steps/solution_10000.vtu");
        assert_eq!(interface_step_file_name(3), "steps/interface_0003.vtu");
        assert_eq!(interface_step_file_name(10000), "steps/interface_10000.vtu");
        let mut names: Vec<String> = (1..=9999).rev().map(step_file_name).collect();
        names.sort();
        assert_eq!(names[0], step_file_name(1));
        assert_eq!(names[9998], step_file_name(9999));
    }

    #[test]
    fn collection_lists_every_step_with_its_exact_time() {
        let dir = scratch("list");
        let path = dir.join("solution.pvd");
        let times = [1e-300, 0.1, 0.2, 0.30000000000000004, 1.0 / 3.0, 7.0, 1e300];
        let entries: Vec<(f64, String)> = times.iter().enumerate().map(|(k, &t)| (t, step_file_name(k + 1))).collect();
        write_pvd(&path, &entries).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let read = data_sets(&text);
        assert_eq!(read.len(), times.len());
        for (k, (time, file)) in read.iter().enumerate() {
            assert_eq!(time.parse::<f64>().unwrap().to_bits(), times[k].to_bits(), "{time}");
            assert_eq!(file, &format!("steps/solution_{:04}.vtu", k + 1));
        }
        assert!(text.starts_with("<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\""), "{text}");
        assert!(text.trim_end().ends_with("</Collection>\n</VTKFile>"), "{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn file_names_are_escaped() {
        let dir = scratch("escape");
        let path = dir.join("a.pvd");
        write_pvd(&path, &[(0.5, "r&d/\"x\"<1>.vtu".into())]).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains("file=\"r&amp;d/&quot;x&quot;&lt;1&gt;.vtu\""), "{text}");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_previous_runs_step_files_are_cleared_and_nothing_else() {
        let dir = scratch("clear");
        assert!(clear_step_files(&dir).unwrap().is_empty(), "no directory: nothing to do");
        let steps = dir.join(STEPS_DIR);
        std::fs::create_dir_all(&steps).unwrap();
        let ours = [
            "solution_0001.vtu",
            "solution_0002.vtu",
            "solution_12345.vtu",
            ".solution_0003.vtu.4711.2.tmp",
            "interface_0001.vtu",
            ".interface_0002.vtu.4711.3.tmp",
        ];
        let theirs =
            ["notes.txt", "solution_01.vtu", "solution_0001.vtu.bak", ".solution_0003.vtu.x.2.tmp", "interface_7.vtu"];
        for name in ours.iter().chain(&theirs) {
            std::fs::write(steps.join(name), "x").unwrap();
        }
        let removed = clear_step_files(&dir).unwrap();
        let mut expected: Vec<PathBuf> = ours.iter().map(|n| steps.join(n)).collect();
        expected.sort();
        assert_eq!(removed, expected);
        let mut left: Vec<String> =
            std::fs::read_dir(&steps).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect();
        left.sort();
        let mut theirs: Vec<String> = theirs.iter().map(|s| s.to_string()).collect();
        theirs.sort();
        assert_eq!(left, theirs);
        // Only step files: the directory goes too.
        for name in &theirs {
            std::fs::remove_file(steps.join(name)).unwrap();
        }
        std::fs::write(steps.join(step_file_name(1).trim_start_matches("steps/")), "x").unwrap();
        assert_eq!(clear_step_files(&dir).unwrap(), [dir.join(step_file_name(1))]);
        assert!(!steps.exists());

        // A step file that cannot be removed (here a directory of that name) is named as stale;
        // the others are removed all the same.
        std::fs::create_dir_all(steps.join("solution_0009.vtu")).unwrap();
        std::fs::write(steps.join("solution_0002.vtu"), "x").unwrap();
        match clear_step_files(&dir) {
            Err(Error::Output { path, message }) => {
                assert_eq!(path, steps.join("solution_0009.vtu"));
                assert!(message.contains("solution_0009.vtu still there, from an earlier run"), "{message}");
            }
            other => panic!("expected an output error, got {other:?}"),
        }
        assert!(!steps.join("solution_0002.vtu").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn bad_entries_are_refused_and_nothing_is_written() {
        let dir = scratch("refuse");
        let path = dir.join("solution.pvd");
        let ok = |t: f64, f: &str| (t, f.to_string());
        let cases: Vec<(Vec<(f64, String)>, &str)> = vec![
            (vec![], "at least one data set"),
            (vec![ok(0.1, "a.vtu"), ok(f64::NAN, "b.vtu")], "data set 2 (b.vtu) has the time NaN"),
            (vec![ok(f64::INFINITY, "a.vtu")], "data set 1 (a.vtu) has the time inf"),
            (vec![ok(0.2, "a.vtu"), ok(0.2, "b.vtu")], "not after the previous one's 2e-1"),
            (vec![ok(0.2, "/tmp/a.vtu")], "data set 1 has the file name \"/tmp/a.vtu\""),
            (vec![ok(0.2, "../a.vtu")], "without `..`"),
            (vec![ok(0.2, "")], "data set 1 has the file name \"\""),
        ];
        for (entries, expected) in cases {
            match write_pvd(&path, &entries) {
                Err(Error::Output { path: p, message }) => {
                    assert_eq!(p, path);
                    assert!(message.contains(expected), "{message:?} lacks {expected:?}");
                }
                other => panic!("{entries:?}: expected an output error, got {other:?}"),
            }
            assert!(!dir.exists() || std::fs::read_dir(&dir).unwrap().next().is_none());
        }
    }
}
