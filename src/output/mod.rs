//! Result files: `.vtu` meshes with fields ([`vtu`]), log-log SVG plots ([`plot`]), JSON reports.
//!
//! Every file goes through [`write_atomically`], so a reader (ParaView, a script polling a run
//! directory, the next run of the program) never sees a half-written file:
//!
//! ```text
//!   out/report.json            target (old version, if any, stays readable throughout)
//!   out/.report.json.4711.0.tmp  1. created next to the target (same file system), written,
//!                                  flushed and fsync'ed
//!                                2. renamed over the target: rename(2) replaces the directory
//!                                   entry in one step (POSIX.1-2017, `rename`), so readers see
//!                                   either the old file or the complete new one
//!                                3. on any failure (or a panic in the writer) it is removed
//! ```
//!
//! The temporary name is hidden (leading dot) and unique per process (pid) and per call (a
//! process-wide counter), so concurrent writers of the same target never share a temporary.
pub mod contact_plots;
pub mod mesh_plot;
pub mod plot;
pub mod vtu;

use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

/// Distinguishes the temporaries of successive calls within one process.
static TEMPORARY_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Buffer between the writer closure and the temporary file.
const WRITE_BUFFER_BYTES: usize = 1 << 20;

/// Removes the temporary file when dropped, unless it has been renamed into place. Covers every
/// early return and a panic inside the writer closure.
struct TemporaryFile {
    path: PathBuf,
    renamed: bool,
}

impl Drop for TemporaryFile {
    fn drop(&mut self) {
        if !self.renamed {
            // Best effort: the file may not exist if its creation failed.
            let _ = fs::remove_file(&self.path);
        }
    }
}

fn output_error(path: &Path, step: &str, err: impl std::fmt::Display) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: format!("{step}: {err} (nothing was written; an existing file at this path is unchanged)"),
    }
}

/// Write a file all at once or not at all.
///
/// `write` receives a buffered writer into a hidden temporary file in the target's directory
/// (missing parent directories are created). When `write` returns `Ok`, the data are flushed,
/// fsync'ed, and the temporary is renamed over `path`. When anything fails — directory creation,
/// the closure, the flush, the sync or the rename — the temporary is removed and the previous
/// contents of `path` (if any) are left untouched; the error is [`Error::Output`] naming `path`
/// and the step that failed.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
    let file_name = path
        .file_name()
        .ok_or_else(|| output_error(path, "choosing the file name", "the path does not end in a file name"))?;
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    fs::create_dir_all(&parent)
        .map_err(|e| output_error(path, &format!("creating directory {}", parent.display()), e))?;

    let counter = TEMPORARY_COUNTER.fetch_add(1, Ordering::Relaxed);
    let mut temporary_name = std::ffi::OsString::from(".");
    temporary_name.push(file_name);
    temporary_name.push(format!(".{}.{}.tmp", std::process::id(), counter));
    let mut temporary = TemporaryFile { path: parent.join(temporary_name), renamed: false };

    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temporary.path)
        .map_err(|e| output_error(path, &format!("creating temporary file {}", temporary.path.display()), e))?;
    let mut buffered = BufWriter::with_capacity(WRITE_BUFFER_BYTES, file);
    write(&mut buffered).map_err(|e| output_error(path, "writing", e))?;
    let file: File = buffered.into_inner().map_err(|e| output_error(path, "flushing", e.error()))?;
    file.sync_all().map_err(|e| output_error(path, "syncing to disk", e))?;
    drop(file);
    fs::rename(&temporary.path, path).map_err(|e| {
        output_error(path, &format!("renaming temporary file {} over the target", temporary.path.display()), e)
    })?;
    temporary.renamed = true;
    // Make the rename itself durable. Best effort: not every platform can open a directory.
    if let Ok(dir) = File::open(&parent) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// The result files of a run in its output directory (the last three for contact runs).
pub const RUN_FILES: [&str; 5] = ["solution.vtu", "report.json", "contact.csv", "contact.svg", "convergence.svg"];

/// Remove the previous run's result files from `dir`, and the temporary files that a writer
/// killed before its rename left there (`.solution.vtu.PID.N.tmp`, by a signal or a file-size
/// limit), so that after a failed run nothing stale remains. Returns the paths removed.
pub fn clear_previous_run(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut removed = Vec::new();
    let Ok(entries) = fs::read_dir(dir) else {
        return Ok(removed); // no directory yet: nothing to clear
    };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        let result = RUN_FILES.contains(&name.as_str());
        let temporary = name.ends_with(".tmp") && RUN_FILES.iter().any(|f| name.starts_with(&format!(".{f}.")));
        if result || temporary {
            let path = entry.path();
            fs::remove_file(&path).map_err(|e| output_error(&path, "removing the previous run's file", e))?;
            removed.push(path);
        }
    }
    removed.sort();
    Ok(removed)
}

/// Write `value` as pretty-printed JSON (two-space indent, trailing newline), atomically.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    write_atomically(path, |w| {
        serde_json::to_writer_pretty(&mut *w, value).map_err(io::Error::from)?;
        w.write_all(b"\n")
    })
}
