//! Result files: `.vtu` meshes with fields ([`vtu`]), ParaView collections of them ([`pvd`]),
//! SVG plots ([`plot`]), JSON reports.
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
//!
//! Several files that belong together (a run's results) go through [`all_or_nothing`]: each is
//! written to its temporary as above, and only when all are written are they fsync'ed — in
//! parallel, which costs about one fsync instead of one per file —, renamed, and their
//! directory fsync'ed once. A failure before that leaves no new file at all.
pub mod contact_plots;
pub mod interface;
pub mod mesh_plot;
pub mod plot;
pub mod pvd;
pub mod vtu;

use std::cell::RefCell;
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

/// A file of an [`all_or_nothing`] batch: written and flushed, not yet synced nor renamed.
struct Pending {
    temporary: TemporaryFile,
    file: File,
    target: PathBuf,
}

thread_local! {
    /// The files of the [`all_or_nothing`] batch running on this thread, if one is.
    static BATCH: RefCell<Option<Vec<Pending>>> = const { RefCell::new(None) };
}

/// Takes the batch away when dropped (its temporaries are then removed), also on a panic.
struct BatchGuard;

impl Drop for BatchGuard {
    fn drop(&mut self) {
        let _ = BATCH.with(|b| b.borrow_mut().take());
    }
}

/// Run `write`, in which every [`write_atomically`] of this thread only writes its temporary
/// file; when `write` succeeds, sync all the temporaries (in parallel), rename each over its
/// target and sync each directory once, so the files appear together, or (on an error or a
/// panic) none of them does. Inside another `all_or_nothing`, runs `write` as part of the
/// outer one.
pub fn all_or_nothing<T>(write: impl FnOnce() -> Result<T>) -> Result<T> {
    if BATCH.with(|b| b.borrow().is_some()) {
        return write();
    }
    BATCH.with(|b| *b.borrow_mut() = Some(Vec::new()));
    let guard = BatchGuard;
    let value = write()?;
    let pending = BATCH.with(|b| b.borrow_mut().take()).unwrap_or_default();
    drop(guard);
    commit(pending)?;
    Ok(value)
}

/// Sync, rename and make durable the files of a batch; on failure none stays.
fn commit(pending: Vec<Pending>) -> Result<()> {
    let synced: Vec<io::Result<()>> = if pending.len() < 2 {
        pending.iter().map(|p| p.file.sync_all()).collect()
    } else {
        std::thread::scope(|scope| {
            let handles: Vec<_> = pending.iter().map(|p| scope.spawn(|| p.file.sync_all())).collect();
            handles.into_iter().map(|h| h.join().unwrap_or_else(|_| Err(io::Error::other("sync panicked")))).collect()
        })
    };
    if let Some((p, Err(e))) = pending.iter().zip(synced).find(|(_, r)| r.is_err()) {
        return Err(output_error(&p.target, "syncing to disk", e));
    }
    let mut renamed: Vec<PathBuf> = Vec::new();
    let mut dirs: Vec<PathBuf> = Vec::new();
    for Pending { mut temporary, file, target } in pending {
        drop(file);
        if let Err(e) = fs::rename(&temporary.path, &target) {
            for path in &renamed {
                let _ = fs::remove_file(path);
            }
            let step = format!("renaming temporary file {} over the target", temporary.path.display());
            return Err(output_error(&target, &step, e));
        }
        temporary.renamed = true;
        let dir = temporary.path.parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf);
        if !dirs.contains(&dir) {
            dirs.push(dir);
        }
        renamed.push(target);
    }
    for dir in dirs {
        // Best effort, as in write_atomically.
        if let Ok(dir) = File::open(&dir) {
            let _ = dir.sync_all();
        }
    }
    Ok(())
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
/// and the step that failed. Inside [`all_or_nothing`], the sync and the rename wait for the
/// rest of the batch.
pub fn write_atomically(path: &Path, write: impl FnOnce(&mut dyn Write) -> io::Result<()>) -> Result<()> {
    let (parent, mut temporary, file) = create_temporary(path)?;
    let mut buffered = BufWriter::with_capacity(WRITE_BUFFER_BYTES, file);
    write(&mut buffered).map_err(|e| output_error(path, "writing", e))?;
    let file: File = buffered.into_inner().map_err(|e| output_error(path, "flushing", e.error()))?;
    if BATCH.with(|b| b.borrow().is_some()) {
        // Inside all_or_nothing: synced and renamed with the rest of the batch.
        let pending = Pending { temporary, file, target: path.to_path_buf() };
        BATCH.with(|b| {
            if let Some(batch) = b.borrow_mut().as_mut() {
                batch.push(pending);
            }
        });
        return Ok(());
    }
    file.sync_all().map_err(|e| output_error(path, "syncing to disk", e))?;
    drop(file);
    install(&mut temporary, path, &parent)
}

/// [`write_atomically`] for writers that open the file by name themselves (an HDF5 library):
/// `write` gets the path of the hidden temporary file (already created, empty; the writer may
/// truncate or replace it) and must have closed it when it returns. Then the temporary is
/// fsync'ed and renamed over `path`; on any failure it is removed and `path` is untouched.
/// Never part of an [`all_or_nothing`] batch.
pub fn write_atomically_by_name(path: &Path, write: impl FnOnce(&Path) -> io::Result<()>) -> Result<()> {
    let (parent, mut temporary, file) = create_temporary(path)?;
    drop(file);
    write(&temporary.path).map_err(|e| output_error(path, "writing", e))?;
    let file = File::open(&temporary.path).map_err(|e| output_error(path, "reopening the written file", e))?;
    file.sync_all().map_err(|e| output_error(path, "syncing to disk", e))?;
    drop(file);
    install(&mut temporary, path, &parent)
}

/// Create the parent directories of `path` and a new hidden temporary file next to it; the
/// parent directory, the temporary (removed when dropped unless installed) and its handle.
fn create_temporary(path: &Path) -> Result<(PathBuf, TemporaryFile, File)> {
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
    let temporary = TemporaryFile { path: parent.join(temporary_name), renamed: false };

    let file = OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temporary.path)
        .map_err(|e| output_error(path, &format!("creating temporary file {}", temporary.path.display()), e))?;
    Ok((parent, temporary, file))
}

/// Rename the complete temporary over `path` and make the rename durable.
fn install(temporary: &mut TemporaryFile, path: &Path, parent: &Path) -> Result<()> {
    fs::rename(&temporary.path, path).map_err(|e| {
        output_error(path, &format!("renaming temporary file {} over the target", temporary.path.display()), e)
    })?;
    temporary.renamed = true;
    // Make the rename itself durable. Best effort: not every platform can open a directory.
    if let Ok(dir) = File::open(parent) {
        let _ = dir.sync_all();
    }
    Ok(())
}

/// The result files of a run in its output directory (`contact.csv` and the plots for contact
/// runs; with several bodies also `solution.pvd` and the `.vtu` file of each body it lists; a
/// load path adds `solution.pvd`, its history and plots, and `steps/solution_NNNN.vtu`; an
/// interface law `interface.vtu`, and on a load path `interface.pvd`, its τ–δ plot and
/// `steps/interface_NNNN.vtu`).
pub const RUN_FILES: [&str; 12] = [
    "solution.vtu",
    "solution.pvd",
    "report.json",
    "contact.csv",
    "contact.svg",
    "convergence.svg",
    "history.csv",
    "hysteresis.svg",
    "contact_profiles.svg",
    interface::INTERFACE_VTU,
    interface::INTERFACE_PVD,
    interface::TAU_DELTA_SVG,
];

/// The `.vtu` files a previous run's `solution.pvd` in `dir` lists (plain names in `dir` only).
fn collection_members(dir: &Path) -> Vec<String> {
    let Ok(text) = fs::read_to_string(dir.join("solution.pvd")) else { return Vec::new() };
    text.split("file=\"")
        .skip(1)
        .filter_map(|rest| rest.split('"').next())
        .filter(|name| name.ends_with(".vtu") && !name.contains(['/', '\\']) && !name.starts_with('.'))
        .map(str::to_string)
        .collect()
}

/// Is `name` the temporary file of [`write_atomically`] for one of `targets`
/// (`.TARGET.PID.N.tmp`)?
pub(crate) fn is_temporary_of(name: &str, targets: &[String]) -> bool {
    let Some(inner) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else { return false };
    targets.iter().any(|t| {
        inner.strip_prefix(t.as_str()).and_then(|r| r.strip_prefix('.')).is_some_and(|r| {
            let mut parts = r.split('.');
            let numeric = |p: Option<&str>| p.is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()));
            numeric(parts.next()) && numeric(parts.next()) && parts.next().is_none()
        })
    })
}

/// Remove the previous run's result files from `dir` ([`RUN_FILES`] and the body files its
/// `solution.pvd` lists), and the temporary files that a writer killed before its rename left
/// there (`.solution.vtu.PID.N.tmp`, by a signal), so that after a failed run nothing stale
/// remains. Returns the paths removed. Every file that can be removed is; if one cannot, the
/// error names each file of the previous run still there (stale), so that nobody takes them
/// for this run's results.
pub fn clear_previous_run(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut removed = Vec::new();
    let Ok(entries) = fs::read_dir(dir) else {
        return Ok(removed); // no directory yet: nothing to clear
    };
    let mut targets: Vec<String> = RUN_FILES.iter().map(|f| f.to_string()).collect();
    targets.extend(collection_members(dir));
    let mut stale: Vec<(PathBuf, String)> = Vec::new();
    // A previous load path's increments (`steps/solution_NNNN.vtu`).
    removed.extend(pvd::clear_step_files(dir)?);
    let previous = entries.flatten().filter_map(|entry| {
        let name = entry.file_name().to_string_lossy().to_string();
        (targets.contains(&name) || is_temporary_of(&name, &targets)).then(|| entry.path())
    });
    let (gone, left) = remove_each(previous);
    removed.extend(gone);
    stale.extend(left);
    removed.sort();
    stale.sort();
    if let Some((first, reason)) = stale.first() {
        let names: Vec<String> = stale.iter().map(|(p, _)| p.display().to_string()).collect();
        return Err(Error::Output {
            path: first.clone(),
            message: format!(
                "removing the previous run's results failed ({reason}): {} {} stale, from an earlier run, not \
                 results of this one; {} removed; remove or rename the stale {} and run again",
                names.join(", "),
                if names.len() == 1 { "is" } else { "are" },
                if removed.is_empty() {
                    "nothing else was".to_string()
                } else {
                    format!("{} other file(s) were", removed.len())
                },
                if names.len() == 1 { "entry" } else { "entries" },
            ),
        });
    }
    Ok(removed)
}

/// Remove every file of `paths`: those removed, and those that could not be with the reason,
/// both sorted.
pub(crate) fn remove_each(paths: impl IntoIterator<Item = PathBuf>) -> (Vec<PathBuf>, Vec<(PathBuf, String)>) {
    let (mut removed, mut stale) = (Vec::new(), Vec::new());
    for path in paths {
        match fs::remove_file(&path) {
            Ok(()) => removed.push(path),
            Err(e) => stale.push((path, e.to_string())),
        }
    }
    removed.sort();
    stale.sort();
    (removed, stale)
}

/// Write `value` as pretty-printed JSON (two-space indent, trailing newline), atomically.
pub fn write_json(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    write_atomically(path, |w| {
        serde_json::to_writer_pretty(&mut *w, value).map_err(io::Error::from)?;
        w.write_all(b"\n")
    })
}
