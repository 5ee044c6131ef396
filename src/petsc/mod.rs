//! The safe PETSc layer: the only module that touches `signorini-sys`.
//!
//! - [`Session`]: one process-wide PETSc session (`PetscInitialize` with the program's argv, so
//!   every PETSc option works from the command line; `PetscFinalize` on drop). A second session
//!   in the same process is refused with [`Error::PetscUsage`] (initialising MPI twice aborts).
//! - [`Vector`], [`Matrix`], [`LinearSolver`]: owning handles. They are moved, never copied;
//!   they borrow the session so they cannot outlive `PetscFinalize`; `Drop` destroys them and
//!   never panics.
//! - [`nonlinear::NonlinearSolver`]: SNES on a system whose residual, Jacobian values and
//!   convergence test are Rust code ([`nonlinear::NonlinearSystem`]); [`bounded`]: SNESVI and
//!   TAO for bound-constrained problems. Callbacks catch panics and never unwind into C.
//! - Every PETSc call goes through `check`: a nonzero code becomes [`Error::Petsc`] with
//!   PETSc's own message (captured by an error handler we install, so PETSc prints nothing),
//!   the call's name and the Rust file and line.
//! - Debian's PETSc is built without debugging checks, so indices and sizes are checked here
//!   before every call that takes them.
//! - Under MPI an error returned by one rank alone, while the others go on into a collective
//!   call (matrix or vector creation and assembly, scatters, solves, reductions, finalisation),
//!   would leave them waiting forever. [`Comm::agree`] (and [`Session::agree`]) settles a
//!   step's outcome over the ranks with one reduction before the next collective: the failing
//!   rank returns its own error, the others [`Error::OtherRank`]. The SNES callbacks agree the
//!   same way ([`nonlinear`]); the drivers agree after every step whose failure can depend on a
//!   rank's own data (mesh generation and files, rank 0's output, the owned rows).
use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::marker::PhantomData;
use std::sync::atomic::{AtomicU8, Ordering};
use std::sync::Mutex;

use crate::error::{Error, Result};
use signorini_sys as sys;

pub mod bounded;
pub mod dense_lu;
mod ict;
pub mod inverse_block;
mod linear_solver;
mod matrix;
pub mod nonlinear;
pub mod schur;
mod vector;

pub use ict::{DEFAULT_DROP_TOLERANCE as ICT_DEFAULT_DROP_TOLERANCE, NAME as ICT_NAME};
pub use linear_solver::{LinearSolver, SolveStats};
pub use matrix::Matrix;
pub use vector::Vector;

/// The message of the last PETSc error, captured by our error handler.
static LAST_ERROR: Mutex<Option<String>> = Mutex::new(None);

/// 0: never initialised, 1: a session is alive, 2: finalised (cannot come back: MPI is gone).
static SESSION_STATE: AtomicU8 = AtomicU8::new(0);

/// Is a session alive (PETSc initialised and not finalised)?
fn session_alive() -> bool {
    SESSION_STATE.load(Ordering::SeqCst) == 1
}

unsafe extern "C" fn capture_error(
    _comm: sys::MPI_Comm,
    line: c_int,
    func: *const c_char,
    file: *const c_char,
    code: sys::PetscErrorCode,
    kind: sys::PetscErrorType,
    message: *const c_char,
    _ctx: *mut c_void,
) -> sys::PetscErrorCode {
    let result = std::panic::catch_unwind(|| {
        let text = |p: *const c_char| {
            if p.is_null() {
                String::new()
            } else {
                // SAFETY: PETSc passes NUL-terminated strings (or NULL, handled above).
                unsafe { CStr::from_ptr(p) }.to_string_lossy().trim().to_string()
            }
        };
        if kind == sys::PetscErrorType::PETSC_ERROR_INITIAL {
            let msg = format!("{} [in {}() at {}:{}]", text(message), text(func), text(file), line);
            if let Ok(mut last) = LAST_ERROR.lock() {
                *last = Some(msg);
            }
        }
    });
    let _ = result;
    code
}

/// Turn a PETSc return code into a `Result`, with PETSc's message and where we called it.
#[track_caller]
pub(crate) fn check(code: sys::PetscErrorCode, call: &'static str) -> Result<()> {
    if code == 0 {
        return Ok(());
    }
    let caller = std::panic::Location::caller();
    let detail = LAST_ERROR.lock().ok().and_then(|mut m| m.take());
    let mut generic: *const c_char = std::ptr::null();
    // SAFETY: PetscErrorMessage only writes a pointer to a static string.
    unsafe { sys::PetscErrorMessage(code, &mut generic, std::ptr::null_mut()) };
    let generic = if generic.is_null() {
        String::new()
    } else {
        // SAFETY: static NUL-terminated string owned by PETSc.
        unsafe { CStr::from_ptr(generic) }.to_string_lossy().into_owned()
    };
    let message = match detail {
        Some(d) if !d.is_empty() => format!("{generic}: {d}"),
        _ => generic,
    };
    Err(Error::Petsc { code, call, message, rust_file: caller.file(), rust_line: caller.line() })
}

/// Call a PETSc function and check its code: `petsc!(VecAssemblyBegin(v))`.
macro_rules! petsc {
    ($f:ident ( $($arg:expr),* $(,)? )) => {
        $crate::petsc::check(
            // SAFETY: every call site passes handles owned by a live wrapper and buffers whose
            // sizes were checked against the object's sizes just before.
            unsafe { signorini_sys::$f($($arg),*) },
            stringify!($f),
        )
    };
}
pub(crate) use petsc;

pub(crate) fn cstring(s: &str) -> Result<CString> {
    CString::new(s).map_err(|_| Error::PetscUsage(format!("string {s:?} contains a NUL byte")))
}

pub(crate) fn from_c(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: PETSc strings are NUL-terminated.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

/// An MPI communicator handle (borrowed from PETSc: never freed by us).
#[derive(Clone, Copy, Debug)]
pub struct Comm {
    raw: sys::MPI_Comm,
}

impl Comm {
    pub(crate) fn raw(self) -> sys::MPI_Comm {
        self.raw
    }
    /// This process's rank in the communicator.
    pub fn rank(self) -> Result<usize> {
        let mut r: c_int = 0;
        mpi_check(unsafe { sys::signorini_comm_rank(self.raw, &mut r) }, "MPI_Comm_rank")?;
        Ok(r as usize)
    }
    /// The number of processes in the communicator.
    pub fn size(self) -> Result<usize> {
        let mut s: c_int = 0;
        mpi_check(unsafe { sys::signorini_comm_size(self.raw, &mut s) }, "MPI_Comm_size")?;
        Ok(s as usize)
    }
    fn allreduce(self, values: &[f64], op: c_int) -> Result<Vec<f64>> {
        let mut out = vec![0.0; values.len()];
        let n = c_int::try_from(values.len()).map_err(|_| Error::PetscUsage("allreduce too large".into()))?;
        // SAFETY: both buffers hold n doubles.
        mpi_check(
            unsafe { sys::signorini_allreduce_f64(self.raw, values.as_ptr(), out.as_mut_ptr(), n, op) },
            "MPI_Allreduce",
        )?;
        Ok(out)
    }
    /// Element-wise sum over all ranks.
    pub fn sum(self, values: &[f64]) -> Result<Vec<f64>> {
        self.allreduce(values, 0)
    }
    /// Element-wise maximum over all ranks.
    pub fn max(self, values: &[f64]) -> Result<Vec<f64>> {
        self.allreduce(values, 1)
    }
    /// Element-wise minimum over all ranks.
    pub fn min(self, values: &[f64]) -> Result<Vec<f64>> {
        self.allreduce(values, 2)
    }

    /// Rank 0's `bytes` on every rank (collective: every rank calls it at the same point; the
    /// other ranks' `bytes` are not read). The length goes first, then the bytes in pieces of
    /// at most `i32::MAX` (MPI counts are `int`). Nothing on a single rank.
    pub fn broadcast_from_rank_0(self, bytes: Vec<u8>) -> Result<Vec<u8>> {
        self.broadcast_from(0, bytes)
    }

    /// [`Comm::broadcast_from_rank_0`] for a message rank 0 sends after a long piece of work
    /// of its own: the other ranks wait for its length without spinning (they test for it
    /// every millisecond and sleep in between, instead of keeping a core busy), then receive
    /// the bytes.
    pub fn broadcast_from_rank_0_sleeping(self, bytes: Vec<u8>) -> Result<Vec<u8>> {
        if self.size()? == 1 {
            return Ok(bytes);
        }
        let mut length = (bytes.len() as u64).to_le_bytes();
        // SAFETY: the buffer holds the 8 bytes broadcast.
        mpi_check(
            unsafe { sys::signorini_bcast_bytes_sleeping(self.raw, length.as_mut_ptr().cast(), 8, 0, 1000) },
            "MPI_Ibcast",
        )?;
        let length = usize::try_from(u64::from_le_bytes(length))
            .map_err(|_| Error::PetscUsage("MPI_Bcast: rank 0's message is too long for this rank".into()))?;
        let mut buffer = if self.rank()? == 0 { bytes } else { vec![0u8; length] };
        for piece in buffer.chunks_mut(i32::MAX as usize) {
            // SAFETY: `piece` holds `piece.len()` (≤ i32::MAX) bytes, the same count on every rank.
            mpi_check(
                unsafe { sys::signorini_bcast_bytes(self.raw, piece.as_mut_ptr().cast(), piece.len() as c_int, 0) },
                "MPI_Bcast",
            )?;
        }
        Ok(buffer)
    }

    /// Every rank's `bytes` on rank 0, in rank order (collective; the other ranks get an empty
    /// list). One broadcast per rank other than 0, so a rank also receives the messages of the
    /// ranks after it: meant for a few ranks.
    pub fn gather_bytes_to_rank_0(self, bytes: Vec<u8>) -> Result<Vec<Vec<u8>>> {
        let (size, rank) = (self.size()?, self.rank()?);
        let mut mine = Some(bytes);
        let mut all = Vec::with_capacity(if rank == 0 { size } else { 0 });
        if rank == 0 {
            all.push(mine.take().unwrap_or_default());
        }
        for root in 1..size {
            let sent = if root == rank { mine.take().unwrap_or_default() } else { Vec::new() };
            let received = self.broadcast_from(root, sent)?;
            if rank == 0 {
                all.push(received);
            }
        }
        Ok(all)
    }

    /// Rank `root`'s `bytes` on every rank (as [`Comm::broadcast_from_rank_0`]).
    pub fn broadcast_from(self, root: usize, bytes: Vec<u8>) -> Result<Vec<u8>> {
        if self.size()? == 1 {
            return Ok(bytes);
        }
        let root_rank = c_int::try_from(root).map_err(|_| Error::PetscUsage(format!("MPI_Bcast: no rank {root}")))?;
        let is_root = self.rank()? == root;
        let mut length = (bytes.len() as u64).to_le_bytes();
        // SAFETY: the buffer holds the 8 bytes broadcast.
        mpi_check(
            unsafe { sys::signorini_bcast_bytes(self.raw, length.as_mut_ptr().cast(), 8, root_rank) },
            "MPI_Bcast",
        )?;
        let length = usize::try_from(u64::from_le_bytes(length))
            .map_err(|_| Error::PetscUsage("MPI_Bcast: rank 0's message is too long for this rank".into()))?;
        let mut buffer = if is_root { bytes } else { vec![0u8; length] };
        for piece in buffer.chunks_mut(i32::MAX as usize) {
            // SAFETY: `piece` holds `piece.len()` (≤ i32::MAX) bytes, the same count on every rank.
            mpi_check(
                unsafe {
                    sys::signorini_bcast_bytes(self.raw, piece.as_mut_ptr().cast(), piece.len() as c_int, root_rank)
                },
                "MPI_Bcast",
            )?;
        }
        Ok(buffer)
    }

    /// The lowest rank on which `failed` is true, the same on every rank (one reduction;
    /// collective); `None` when no rank failed.
    pub fn first_failure(self, failed: bool) -> Result<Option<usize>> {
        let mine = if failed { self.rank()? as f64 } else { f64::INFINITY };
        let first = self.min(&[mine])?[0];
        Ok(first.is_finite().then_some(first as usize))
    }

    /// Agree on the outcome of a step over the ranks, before the next collective operation
    /// (collective: every rank must call it at the same point). A rank whose `outcome` is an
    /// error returns it; when another rank failed, a rank that succeeded returns
    /// [`Error::OtherRank`] (naming the lowest failing rank and `during`) instead of its value.
    /// So an error that depends on a rank's own data (its rows, a file only rank 0 writes, a
    /// mesh generated by each rank) stops every rank, instead of leaving the others waiting
    /// forever in the next collective call. One reduction; nothing on a single rank.
    pub fn agree<T>(self, outcome: Result<T>, during: &'static str) -> Result<T> {
        if self.size()? == 1 {
            return outcome;
        }
        let first = match self.first_failure(outcome.is_err()) {
            Ok(first) => first,
            // The reduction itself failed: the rank's own error, if it has one, says more.
            Err(e) => return outcome.and(Err(e)),
        };
        match (outcome, first) {
            (Ok(_), Some(rank)) => Err(Error::OtherRank { rank, during }),
            (outcome, _) => outcome,
        }
    }
}

fn mpi_check(code: c_int, call: &'static str) -> Result<()> {
    if code == 0 {
        Ok(())
    } else {
        let caller = std::panic::Location::caller();
        Err(Error::Petsc {
            code,
            call,
            message: "MPI error".into(),
            rust_file: caller.file(),
            rust_line: caller.line(),
        })
    }
}

/// The process-wide PETSc session. Create it once, early (it owns MPI too); every PETSc object
/// borrows it.
pub struct Session {
    /// argv strings handed to PetscInitialize: PETSc keeps pointers into them until finalise.
    _args: Vec<CString>,
    _argv: Vec<*mut c_char>,
    /// The communicator of every driver: `PETSC_COMM_WORLD`, or `PETSC_COMM_SELF` inside
    /// [`Session::alone`] (with `rank` 0 and `size` 1 then).
    world: std::cell::Cell<Comm>,
    rank: std::cell::Cell<usize>,
    size: std::cell::Cell<usize>,
    /// PETSc is not thread safe in this build: keep the session on its thread.
    _not_send: PhantomData<*const ()>,
    /// Options the program set as its own defaults (not the user's choices).
    program_options: std::cell::RefCell<std::collections::HashSet<String>>,
}

/// Open MPI settings that let a process started without `mpirun` (a "singleton") initialise
/// MPI in ~0.02 s instead of ~0.4 s: without them Open MPI forks its `orted` daemon and probes
/// the psm/ofi network transports, which a single process never uses. Measured on a 1e3-dof
/// contact run: 0.48–0.57 s → 0.14–0.19 s, the same answer to the bit.
///
/// The hwloc settings keep Open MPI's topology discovery (hwloc 2.9) to the CPUs and memory:
/// no PCI devices (`linuxio` and `pci` read every device's configuration space, 1.2 ms a read
/// in a virtual machine) and no loading of the `gl` (tries to reach X displays :0 to :9),
/// `opencl`, `pci` and `xml_libxml` (loads libxml2 and ICU) plugins. A single process binds to
/// nothing and talks to no network device, so it needs none of them: MPI initialisation
/// takes about 15 ms less CPU and 25 ms less wall time (1e3-dof run, `signorini bench
/// startup`), with a bit-identical answer.
const SINGLETON_SETTINGS: &[(&str, &str)] = &[
    ("OMPI_MCA_ess_singleton_isolated", "1"),
    ("OMPI_MCA_pml", "ob1"),
    ("OMPI_MCA_mtl", "^psm,ofi,psm2"),
    ("OMPI_MCA_btl", "self,vader"),
    ("HWLOC_COMPONENTS", "-linuxio,-pci"),
    ("HWLOC_PLUGINS_BLACKLIST", "hwloc_gl,hwloc_opencl,hwloc_pci,hwloc_xml_libxml"),
];

/// Variables a launcher (`mpirun`/`mpiexec`, PMIx or PMI launchers such as `srun`) sets in
/// every process it starts.
const LAUNCHER_VARIABLES: &[&str] = &["OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"];

/// The [`SINGLETON_SETTINGS`] to apply, given which environment variables are set: none under
/// an MPI launcher, and never one the user set.
fn singleton_settings_to_apply(is_set: impl Fn(&str) -> bool) -> Vec<(&'static str, &'static str)> {
    if LAUNCHER_VARIABLES.iter().any(|v| is_set(v)) {
        return Vec::new();
    }
    SINGLETON_SETTINGS.iter().copied().filter(|(name, _)| !is_set(name)).collect()
}

/// Remove the session directories of earlier runs that were killed before they could (their
/// process no longer exists; Linux `/proc`, nothing is removed elsewhere).
fn remove_stale_session_directories() {
    if !std::path::Path::new("/proc/self").exists() {
        return;
    }
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else { return };
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().to_string();
        if let Some(pid) = name.strip_prefix("signorini-mpi-").and_then(|p| p.parse::<u32>().ok()) {
            if pid != std::process::id() && !std::path::Path::new(&format!("/proc/{pid}")).exists() {
                let _ = std::fs::remove_dir_all(entry.path());
            }
        }
    }
}

/// Open MPI's session directory base of this process, when the program chose it (removed after
/// MPI is finalised).
static SESSION_DIRECTORY: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();

/// Apply the singleton settings to this process's environment (before MPI is initialised: it
/// reads them once). Also give the process a session directory of its own
/// (`OMPI_MCA_orte_tmpdir_base` = `$TMPDIR/signorini-mpi-PID`): isolated singletons all take job
/// family 0, so concurrent runs shared `/tmp/ompi.HOST.UID/jf.0`, and one run's clean-up removed
/// it under another, which then failed in MPI_Init ("A call to mkdir was unable to create the
/// desired directory"). Not under a launcher, and not when the user set the variable.
fn prefer_fast_singleton_start() {
    let is_set = |v: &str| std::env::var_os(v).is_some();
    for (name, value) in singleton_settings_to_apply(is_set) {
        std::env::set_var(name, value);
    }
    let launched = LAUNCHER_VARIABLES.iter().any(|v| is_set(v));
    if !launched && !is_set("OMPI_MCA_orte_tmpdir_base") {
        remove_stale_session_directories();
        let dir = std::env::temp_dir().join(format!("signorini-mpi-{}", std::process::id()));
        if std::fs::create_dir_all(&dir).is_ok() {
            std::env::set_var("OMPI_MCA_orte_tmpdir_base", &dir);
            let _ = SESSION_DIRECTORY.set(dir);
        }
    }
}

impl Session {
    /// Initialise PETSc (and MPI) with these arguments (`args[0]` is the program name). All
    /// `-option value` pairs in them go into PETSc's options database. A process that no MPI
    /// launcher started gets Open MPI's fast singleton settings first (see
    /// `SINGLETON_SETTINGS` in `petsc/mod.rs`; variables the user set are left alone).
    pub fn init(args: &[String]) -> Result<Session> {
        match SESSION_STATE.compare_exchange(0, 1, Ordering::SeqCst, Ordering::SeqCst) {
            Ok(_) => {}
            Err(1) => {
                return Err(Error::PetscUsage(
                    "a PETSc session is already alive in this process: create one Session and share it".into(),
                ))
            }
            Err(_) => {
                return Err(Error::PetscUsage(
                    "PETSc was finalised in this process and cannot be initialised again (MPI allows one \
                     initialisation per process): run each session in its own process"
                        .into(),
                ))
            }
        }
        if let Err(e) = check_option_values(args.get(1..).unwrap_or(&[]), "command line") {
            SESSION_STATE.store(0, Ordering::SeqCst);
            return Err(e);
        }
        prefer_fast_singleton_start();
        let program = args.first().cloned().unwrap_or_else(|| "signorini".to_string());
        let mut c_args = Vec::with_capacity(args.len().max(1));
        c_args.push(cstring(&program)?);
        for a in args.iter().skip(1) {
            c_args.push(cstring(a)?);
        }
        let mut argv: Vec<*mut c_char> = c_args.iter().map(|c| c.as_ptr() as *mut c_char).collect();
        argv.push(std::ptr::null_mut());
        let mut argc = c_args.len() as c_int;
        let mut argv_ptr = argv.as_mut_ptr();
        // SAFETY: argc/argv describe NUL-terminated strings that live in `Session` until
        // PetscFinalize (PETSc keeps pointers to them).
        let code = unsafe { sys::PetscInitialize(&mut argc, &mut argv_ptr, std::ptr::null(), std::ptr::null()) };
        if code != 0 {
            SESSION_STATE.store(2, Ordering::SeqCst);
            return check(code, "PetscInitialize").map(|_| unreachable!());
        }
        // From now on PETSc reports errors to us instead of printing them.
        petsc!(PetscPushErrorHandler(Some(capture_error), std::ptr::null_mut()))?;
        // SAFETY: valid after PetscInitialize.
        let world = Comm { raw: unsafe { sys::signorini_comm_world() } };
        let rank = world.rank()?;
        let size = world.size()?;
        Ok(Session {
            _args: c_args,
            _argv: argv,
            world: std::cell::Cell::new(world),
            rank: std::cell::Cell::new(rank),
            size: std::cell::Cell::new(size),
            _not_send: PhantomData,
            program_options: Default::default(),
        })
    }

    /// `PETSC_COMM_WORLD` (`PETSC_COMM_SELF` inside [`Session::alone`]).
    pub fn world(&self) -> Comm {
        self.world.get()
    }

    /// Run `work` as if this process were alone: inside it [`Session::world`] is
    /// `PETSC_COMM_SELF`, [`Session::rank`] 0 and [`Session::size`] 1, so every object it
    /// creates and every agreement it makes stays on this process (no other rank takes part,
    /// whatever each does). The options database is the same. Restored afterwards, also if
    /// `work` panics.
    pub fn alone<R>(&self, work: impl FnOnce(&Session) -> R) -> R {
        struct Restore<'a> {
            session: &'a Session,
            saved: (Comm, usize, usize),
        }
        impl Drop for Restore<'_> {
            fn drop(&mut self) {
                let (world, rank, size) = self.saved;
                self.session.world.set(world);
                self.session.rank.set(rank);
                self.session.size.set(size);
            }
        }
        let _restore = Restore { session: self, saved: (self.world.get(), self.rank.get(), self.size.get()) };
        self.world.set(self.self_comm());
        self.rank.set(0);
        self.size.set(1);
        work(self)
    }
    /// `PETSC_COMM_SELF`.
    pub fn self_comm(&self) -> Comm {
        // SAFETY: valid after PetscInitialize.
        Comm { raw: unsafe { sys::signorini_comm_self() } }
    }
    /// This process's MPI rank (0 without MPI).
    pub fn rank(&self) -> usize {
        self.rank.get()
    }
    /// The number of MPI processes (1 without MPI).
    pub fn size(&self) -> usize {
        self.size.get()
    }

    /// [`Comm::agree`] over `PETSC_COMM_WORLD`, the communicator of every driver: collective.
    pub fn agree<T>(&self, outcome: Result<T>, during: &'static str) -> Result<T> {
        if self.size() == 1 {
            return outcome;
        }
        self.world().agree(outcome, during)
    }

    /// Is `-name` (with its leading dash) in the options database?
    pub fn has_option(&self, name: &str) -> Result<bool> {
        let n = cstring(name)?;
        let mut set = sys::PetscBool::PETSC_FALSE;
        petsc!(PetscOptionsHasName(std::ptr::null_mut(), std::ptr::null(), n.as_ptr(), &mut set))?;
        Ok(set == sys::PetscBool::PETSC_TRUE)
    }

    /// MUMPS's AMF ordering (`-<prefix>mat_mumps_icntl_7 2`) unless the options already choose
    /// one: about twice as fast as Debian's default PORD (its MUMPS has no METIS).
    pub fn prefer_amf_ordering(&self, prefix: &str) -> Result<()> {
        self.prefer_mumps_ordering(prefix, 2)
    }

    /// Use MUMPS ordering `icntl_7` for the solvers under `prefix` unless the user chose one
    /// (an ordering the program itself set earlier, for another solver, is not the user's).
    pub fn prefer_mumps_ordering(&self, prefix: &str, icntl_7: i32) -> Result<()> {
        self.prefer_option(format!("-{prefix}mat_mumps_icntl_7"), icntl_7)
    }

    /// Set `name` to `value` unless the user set it (a value the program itself set earlier,
    /// for another solver, is not the user's).
    fn prefer_option(&self, name: String, value: i32) -> Result<()> {
        let ours = self.program_options.borrow().contains(&name);
        if ours || !self.has_option(&name)? {
            self.set_option(&name, Some(&value.to_string()))?;
            self.program_options.borrow_mut().insert(name);
        }
        Ok(())
    }

    /// MUMPS's workspace margin (`-<prefix>mat_mumps_icntl_14`, percent above its estimate)
    /// unless the options choose one. The LU of an indefinite mixed system pivots off the
    /// diagonal more than the analysis foresees: a 1000 × 1 slab on its contact (1001 points)
    /// stopped with INFOG(1) = −9 (workspace too small) at MUMPS's 20 %, and ran at 50 %.
    pub fn prefer_mumps_workspace(&self, prefix: &str, percent: i32) -> Result<()> {
        self.prefer_option(format!("-{prefix}mat_mumps_icntl_14"), percent)
    }

    /// On more than one process: refuse, before any work, a main linear solver (no prefix) that
    /// PETSc 3.18 runs on one process only, as [`Error::SingleProcess`] naming the option. PETSc
    /// would refuse it in the first solve, after the mesh and the assembly ("Could not locate a
    /// solver type for factorization type ICC and matrix type mpiaij"). Such solvers are
    /// `-pc_type icc`, `ilu` and our `ict`, and the factorisation packages of one process
    /// (`-pc_factor_mat_solver_type petsc`, `superlu`, `umfpack`, `cholmod`, `klu`,
    /// `mkl_pardiso`) when the preconditioner factorises (`lu`, `cholesky`, or unset: the
    /// default MUMPS Cholesky). The command line's options come first, then `scene_defaults`
    /// (a scene's `[solver] petsc_options`, which the command line overrides).
    pub fn refuse_one_process_solver(&self, scene_defaults: &[String]) -> Result<()> {
        if self.size() == 1 {
            return Ok(());
        }
        let value = |name: &str| -> Result<Option<String>> {
            if let Some(v) = self.option(name)? {
                return Ok(Some(v));
            }
            Ok(scene_defaults.windows(2).rev().find(|w| w[0] == name).map(|w| w[1].clone()))
        };
        let pc = value("-pc_type")?;
        let (option, reason) = match pc.as_deref() {
            Some(p @ ("icc" | "ilu" | ict::NAME)) => (
                format!("-pc_type {p}"),
                format!(
                    "{} factorisation of the whole matrix; in parallel use -pc_type bjacobi -sub_pc_type {}, or -pc_type \
                     hypre",
                    if p == "ilu" { "an incomplete LU" } else { "an incomplete Cholesky" },
                    if p == "ilu" { "ilu" } else { "icc" }
                ),
            ),
            None | Some("lu" | "cholesky") => {
                let package = value("-pc_factor_mat_solver_type")?;
                match package.as_deref() {
                    Some(s @ ("petsc" | "superlu" | "umfpack" | "cholmod" | "klu" | "mkl_pardiso")) => (
                        format!("-pc_factor_mat_solver_type {s}"),
                        "a direct solver package of one process; in parallel use mumps (the default) or superlu_dist"
                            .to_string(),
                    ),
                    _ => return Ok(()),
                }
            }
            Some(_) => return Ok(()),
        };
        Err(Error::SingleProcess {
            feature: option,
            reason: format!("started on {} MPI processes: {reason}", self.size()),
        })
    }

    /// A true/false option: `None` if absent; present without a value, `1`, `true` or `yes`
    /// is true; `0`, `false` or `no` false; anything else is [`Error::Usage`] naming it.
    pub fn flag(&self, name: &str) -> Result<Option<bool>> {
        match self.option(name)?.as_deref() {
            None => Ok(None),
            Some("" | "1" | "true" | "yes") => Ok(Some(true)),
            Some("0" | "false" | "no") => Ok(Some(false)),
            Some(other) => Err(Error::Usage(format!("{name} takes true or false (got \"{other}\")"))),
        }
    }

    /// The value of `-name`: `None` if absent, `Some("")` if present without a value.
    pub fn option(&self, name: &str) -> Result<Option<String>> {
        let n = cstring(name)?;
        let mut buf = vec![0 as c_char; 4096];
        let mut set = sys::PetscBool::PETSC_FALSE;
        petsc!(PetscOptionsGetString(
            std::ptr::null_mut(),
            std::ptr::null(),
            n.as_ptr(),
            buf.as_mut_ptr(),
            buf.len(),
            &mut set
        ))?;
        if set != sys::PetscBool::PETSC_TRUE {
            return Ok(None);
        }
        Ok(Some(from_c(buf.as_ptr())))
    }

    /// Set `-name [value]`, replacing any earlier value.
    pub fn set_option(&self, name: &str, value: Option<&str>) -> Result<()> {
        let n = cstring(name)?;
        let v = value.map(cstring).transpose()?;
        petsc!(PetscOptionsSetValue(
            std::ptr::null_mut(),
            n.as_ptr(),
            v.as_ref().map_or(std::ptr::null(), |v| v.as_ptr())
        ))
    }

    /// Remove `-name` from the options database.
    pub fn clear_option(&self, name: &str) -> Result<()> {
        let n = cstring(name)?;
        petsc!(PetscOptionsClearValue(std::ptr::null_mut(), n.as_ptr()))
    }

    /// Insert options given as tokens (`["-ksp_type", "cg", "-ksp_monitor"]`) as *defaults*: an
    /// option already in the database (from the command line) wins. Returns the options it set.
    pub fn insert_default_options(&self, tokens: &[String]) -> Result<Vec<String>> {
        check_option_values(tokens, "scene [solver] petsc_options")?;
        let mut inserted = Vec::new();
        let mut i = 0;
        while i < tokens.len() {
            let name = &tokens[i];
            if !name.starts_with('-') || name.len() < 2 {
                return Err(Error::PetscUsage(format!(
                    "PETSc option list: expected an option starting with '-', found {name:?}"
                )));
            }
            let value = tokens.get(i + 1).filter(|v| !is_option_name(v));
            if !self.has_option(name)? {
                self.set_option(name, value.map(|s| s.as_str()))?;
                inserted.push(name.clone());
            }
            i += if value.is_some() { 2 } else { 1 };
        }
        Ok(inserted)
    }

    /// Options given but never queried by any PETSc object: usually a typo. (`-options_left`
    /// style check, returned rather than printed.)
    pub fn unused_options(&self) -> Result<Vec<String>> {
        let mut n: sys::PetscInt = 0;
        let mut names: *mut *mut c_char = std::ptr::null_mut();
        let mut values: *mut *mut c_char = std::ptr::null_mut();
        petsc!(PetscOptionsLeftGet(std::ptr::null_mut(), &mut n, &mut names, &mut values))?;
        let mut out = Vec::with_capacity(n.max(0) as usize);
        for k in 0..n.max(0) as usize {
            // SAFETY: PETSc returned n entries in each array.
            let name = from_c(unsafe { *names.add(k) });
            let value = from_c(unsafe { *values.add(k) });
            out.push(if value.is_empty() { format!("-{name}") } else { format!("-{name} {value}") });
        }
        petsc!(PetscOptionsLeftRestore(std::ptr::null_mut(), &mut n, &mut names, &mut values))?;
        Ok(out)
    }
}

/// Suffixes of PETSc options that always take a value. PETSc 3.18 silently ignores an integer,
/// real or string option given without its value (`-pc_factor_levels` alone leaves the default
/// in place), so such a token is refused here instead of giving a silently different solver.
const VALUE_SUFFIXES: &[&str] = &[
    "_type",
    "_levels",
    "_rtol",
    "_atol",
    "_dtol",
    "_divtol",
    "_max_it",
    "_maxit",
    "_max_iter",
    "_omega",
    "_its",
    "_lits",
    "_fill",
    "_restart",
    "_tol",
    "_threshold",
    "_ordering",
    "_shift_amount",
    "_max_funcs",
    "_gatol",
    "_grtol",
    "_gttol",
    "_agg_nsmooths",
    "_max_levels",
    "_coarse_eq_limit",
    "_blocks",
    "_local_blocks",
];

/// Does this option name need a value (see [`VALUE_SUFFIXES`]; also `..._icntl_N`, `..._cntl_N`)?
fn needs_value(name: &str) -> bool {
    let bare = name.trim_start_matches('-');
    if VALUE_SUFFIXES.iter().any(|s| bare.ends_with(s)) {
        return true;
    }
    match bare.rsplit_once('_') {
        Some((head, num)) if num.chars().all(|c| c.is_ascii_digit()) && !num.is_empty() => {
            head.ends_with("_icntl") || head.ends_with("_cntl")
        }
        _ => false,
    }
}

/// Check a PETSc option token list (`["-ksp_type", "cg", "-ksp_monitor"]`): every option that
/// needs a value has one. `source` says where the list came from (for the message).
pub fn check_option_values(tokens: &[String], source: &str) -> Result<()> {
    for (i, t) in tokens.iter().enumerate() {
        if is_option_name(t) && needs_value(t) {
            let has_value = tokens.get(i + 1).is_some_and(|v| !is_option_name(v));
            if !has_value {
                return Err(Error::PetscOption {
                    option: t.clone(),
                    message: format!(
                        "{source}: PETSc option {t} needs a value (PETSc would silently ignore it), e.g. {}",
                        example_value(t)
                    ),
                });
            }
        }
    }
    Ok(())
}

fn example_value(name: &str) -> String {
    let v = if name.ends_with("_type") {
        "cg"
    } else if name.ends_with("tol") {
        "1e-8"
    } else {
        "2"
    };
    format!("{name} {v}")
}

/// `-ksp_type` is an option name; `-1e-3` and `-5` are values.
fn is_option_name(token: &str) -> bool {
    token.starts_with('-') && token[1..].chars().next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
}

impl Drop for Session {
    fn drop(&mut self) {
        // SAFETY: every PETSc object borrows the session, so all were destroyed before this.
        let _ = unsafe { sys::PetscFinalize() };
        SESSION_STATE.store(2, Ordering::SeqCst);
        // Best effort: Open MPI has removed its own session files by now.
        if let Some(dir) = SESSION_DIRECTORY.get() {
            let _ = std::fs::remove_dir_all(dir);
        }
    }
}

/// Give freed heap memory back to the operating system (glibc `malloc_trim`), so that the
/// resident memory measured for a later phase (a benchmark's solve) is not hidden by memory an
/// earlier phase (assembly) freed but the allocator kept. It needs FFI, hence lives here.
pub fn release_free_memory() {
    // SAFETY: malloc_trim has no preconditions.
    unsafe { sys::signorini_release_free_memory() };
}

/// Ignore the signal SIGXFSZ (a file grew past the file-size limit, `ulimit -f`), whose default
/// action kills the process in the middle of a write and leaves its temporary file behind:
/// ignored, the write fails with `EFBIG` ("File too large"), and the writer removes its
/// temporary and reports an [`Error::Output`]. Process-wide and inherited by child processes
/// (Gmsh then fails the same way); for programs, not for a library to call on its own. It
/// needs FFI, hence lives here. Returns false if the disposition could not be changed.
pub fn ignore_file_size_signal() -> bool {
    // SAFETY: signal(2) with SIG_IGN installs no handler code; it has no preconditions.
    unsafe { sys::signorini_ignore_file_size_signal() == 0 }
}

/// Convert a `usize` index to PETSc's 32-bit `PetscInt`, or explain why not.
pub(crate) fn to_petsc_int(value: usize, what: &str) -> Result<sys::PetscInt> {
    sys::PetscInt::try_from(value).map_err(|_| {
        Error::PetscUsage(format!(
            "{what} = {value} does not fit Debian's 32-bit PetscInt (max {}): the problem is too large for this PETSc build",
            sys::PetscInt::MAX
        ))
    })
}

/// The message of a panic caught at a PETSc callback boundary (`catch_unwind`'s payload).
fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<String>()
        .cloned()
        .or_else(|| payload.downcast_ref::<&str>().map(|s| s.to_string()))
        .unwrap_or_else(|| "unknown panic".into())
}

#[cfg(test)]
mod tests {
    #[test]
    fn singleton_settings_respect_launchers_and_user_choices() {
        let all = super::singleton_settings_to_apply(|_| false);
        assert_eq!(all.len(), super::SINGLETON_SETTINGS.len());
        // Under mpirun (or any PMI/PMIx launcher) nothing is touched.
        for launcher in super::LAUNCHER_VARIABLES {
            assert!(super::singleton_settings_to_apply(|v| v == *launcher).is_empty());
        }
        // A setting the user gave is left alone; the others are applied.
        let some = super::singleton_settings_to_apply(|v| v == "OMPI_MCA_btl");
        assert_eq!(some.len(), super::SINGLETON_SETTINGS.len() - 1);
        assert!(some.iter().all(|(name, _)| *name != "OMPI_MCA_btl"));
    }

    use super::is_option_name;
    #[test]
    fn options_that_need_values() {
        use super::{check_option_values, needs_value};
        assert!(needs_value("-pc_factor_levels") && needs_value("-ksp_type") && needs_value("-mat_mumps_icntl_7"));
        assert!(!needs_value("-ksp_monitor") && !needs_value("-pc_sor_symmetric") && !needs_value("-log_view"));
        let t = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        assert!(check_option_values(&t(&["-pc_factor_levels", "2", "-ksp_monitor"]), "x").is_ok());
        assert!(check_option_values(&t(&["-ksp_rtol", "-ksp_monitor"]), "x").is_err());
        assert!(check_option_values(&t(&["-ksp_monitor", "-pc_factor_levels"]), "x").is_err());
    }

    #[test]
    fn option_names_versus_negative_values() {
        assert!(is_option_name("-ksp_type"));
        assert!(is_option_name("-_x"));
        assert!(!is_option_name("-1e-3"));
        assert!(!is_option_name("-5"));
        assert!(!is_option_name("cg"));
    }
}
