//! The one error type of the library.
//!
//! Every variant carries what a user needs to act: the file and line of a scene mistake, the
//! entity of a mesh defect, PETSc's code and message with the call that failed, or what a
//! solver tried before it gave up. The library never prints or exits; the CLI renders these.
use std::fmt;
use std::path::PathBuf;

/// Where in a text file something is (1-based line and column), shown `file:line:column`.
/// Line 0 means no line (a scene built in Rust, whose errors name the builder call instead):
/// shown as the file alone.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Location {
    /// The file, or a name in angle brackets for a text that is not a file (`<default scene>`,
    /// `<scene built in Rust>`).
    pub file: PathBuf,
    /// 1-based line; 0 for none.
    pub line: usize,
    /// 1-based column, in characters.
    pub column: usize,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            0 => write!(f, "{}", self.file.display()),
            line => write!(f, "{}:{}:{}", self.file.display(), line, self.column),
        }
    }
}

/// Every error of the library: what went wrong, where (file and line, entity, PETSc call),
/// and, for the user's mistakes, what to do. `Display` gives the message the CLI prints.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Reading or writing a file failed at the operating-system level.
    #[error("{path}: {action} failed: {source}")]
    Io {
        /// The file or directory.
        path: PathBuf,
        /// What was being done, e.g. "reading the scene file".
        action: &'static str,
        /// The operating system's error.
        source: std::io::Error,
    },

    /// A mistake in a scene file: where it is, what is wrong, what to do.
    #[error("{location}: {message}\n  hint: {hint}")]
    Scene {
        /// The file, line and column of the value (of the table header for a missing key); for
        /// a scene built in Rust, `<scene built in Rust>` without a line, the message naming
        /// the builder call.
        location: Location,
        /// What is wrong, naming the key and the value found.
        message: String,
        /// What to do about it.
        hint: String,
    },

    /// A mesh file that cannot be parsed (wrong format, truncated, unsupported version...).
    #[error("{file}{}: {message}", line.map(|l| format!(":{l}")).unwrap_or_default())]
    MeshFile {
        /// The mesh file.
        file: PathBuf,
        /// The 1-based line, for a text file.
        line: Option<usize>,
        /// What is wrong.
        message: String,
    },

    /// A mesh that parses but is unusable: names the entity (e.g. "triangle 12", "node 7",
    /// "physical group 'top'").
    #[error("{}invalid mesh: {entity}: {message}", source_file.as_ref().map(|f| format!("{}: ", f.display())).unwrap_or_default())]
    Mesh {
        /// The file the mesh came from, if any.
        source_file: Option<PathBuf>,
        /// The entity at fault, e.g. "triangle 12".
        entity: String,
        /// What is wrong with it.
        message: String,
    },

    /// The Gmsh binary is missing or failed.
    #[error("gmsh failed: {message}")]
    Gmsh {
        /// What failed (the command, the exit status or the missing binary).
        message: String,
        /// Gmsh's standard error output.
        stderr: String,
    },

    /// A PETSc call returned an error code.
    #[error("PETSc error {code} in {call} (at {rust_file}:{rust_line}): {message}")]
    Petsc {
        /// PETSc's error code (`PetscErrorCode`).
        code: i32,
        /// The PETSc function that failed, e.g. "KSPSolve".
        call: &'static str,
        /// PETSc's message for the code.
        message: String,
        /// The Rust source file of the call.
        rust_file: &'static str,
        /// The line of the call in `rust_file`.
        rust_line: u32,
    },

    /// A PETSc option given in a way PETSc would silently ignore (e.g. without its value).
    #[error("{message}")]
    PetscOption {
        /// The option as given, e.g. "-pc_factor_levels".
        option: String,
        /// What is wrong and what to write.
        message: String,
    },

    /// A misuse of the PETSc layer caught before it reached PETSc (which does no checks in
    /// Debian's build): out-of-range index, size mismatch, second session...
    #[error("PETSc layer: {0}")]
    PetscUsage(String),

    /// An iterative or nonlinear solver stopped without converging, or converged to an answer
    /// that fails our independent check.
    #[error(
        "{solver} did not converge: {reason} after {iterations} iterations (residual {residual:.3e}); tried: {tried}"
    )]
    SolverDiverged {
        /// The solver, as the report names it.
        solver: String,
        /// Why it stopped (PETSc's converged reason, or the check that failed).
        reason: String,
        /// Iterations done.
        iterations: usize,
        /// The last residual (relative, as the solver measures it).
        residual: f64,
        /// What was tried before giving up (fallbacks, other settings).
        tried: String,
    },

    /// A contact route asked for by name would need more memory than the machine has (refused
    /// before any work; the cost model avoids it when the route is not named).
    #[error(
        "the contact route {route} needs about {needed_mb:.0} MB and {available_mb:.0} MB are available: use \
         -contact_route {instead} (or auto, which picks the cheaper route)"
    )]
    RouteMemory {
        /// The route named (`dense_schur`).
        route: String,
        /// Its predicted memory, MB.
        needed_mb: f64,
        /// What the machine has available (or `-contact_memory_limit`), MB.
        available_mb: f64,
        /// A route that needs less.
        instead: String,
    },

    /// The loads cannot be balanced: e.g. a tangential load above what friction can hold
    /// (the body slides), or a body pushed away from the only obstacle holding it.
    #[error("{0}")]
    NoEquilibrium(String),

    /// The problem has no unique solution: the boundary conditions leave a rigid motion free.
    #[error("the problem is singular: {0}")]
    Unconstrained(String),

    /// Writing results failed; nothing half-written was left behind.
    #[error("{path}: cannot write output: {message}")]
    Output {
        /// The file or directory that could not be written.
        path: PathBuf,
        /// Why.
        message: String,
    },

    /// A factorisation (e.g. the incomplete Cholesky of `-pc_type ict`) refused its matrix or
    /// broke down: which method, and what is wrong with which row, column or entry.
    #[error("{method}: {message}")]
    Factorization {
        /// The factorisation, e.g. "incomplete Cholesky (ict)".
        method: &'static str,
        /// What is wrong, naming the row, column or entry.
        message: String,
    },

    /// Under MPI: this rank stopped because another rank failed at the same step (before a
    /// collective operation every rank must enter; see `petsc::Comm::agree`). The failing rank
    /// returns its own error, and the CLI prints it.
    #[error("{during} failed on MPI rank {rank} (its error is reported by that rank); every rank stopped")]
    OtherRank {
        /// The rank that failed.
        rank: usize,
        /// The step that failed, e.g. "building the mesh".
        during: &'static str,
    },

    /// Bad command-line usage.
    #[error("{0}")]
    Usage(String),

    /// A step of the solve pipeline ([`crate::problem::ElasticityProblem`]) called before a
    /// step it needs, e.g. `report()` before `solve()`.
    #[error(
        "{call} called before {needs}: call {needs} first (the order: setup_system, assemble, solve, postprocess, \
         then report or write_output; solve_dual after setup_system, estimate after postprocess and solve_dual)"
    )]
    CallOrder {
        /// The step called.
        call: &'static str,
        /// The step it needs first.
        needs: &'static str,
    },

    /// Mesh adaptation or a convergence study needs to remesh the scene's geometry, and the
    /// scene reads its mesh from a file (whose geometry the program does not know).
    #[error(
        "{}: `signorini {command}` remeshes the scene's geometry, but this scene reads its mesh from the file {} \
         (shape = \"file\"), whose geometry is unknown\n  hint: describe the body with shape = \"rectangle\", \
         \"disc\", \"half_disc\" or \"quarter_disc\" and a cell_size in [mesh], or (adapt only) name the Gmsh script the file was \
         made from with geometry = \"part.geo\" in [mesh], or run `signorini run --estimate` on the file's mesh",
        scene.display(),
        file.display()
    )]
    NeedsGeometry {
        /// The scene file.
        scene: PathBuf,
        /// The scene's mesh file.
        file: PathBuf,
        /// The command that needs the geometry: "adapt" or "study".
        command: &'static str,
    },

    /// A scene that cannot be solved as posed: the chosen formulation cannot represent it (the
    /// dual formulation on a domain with holes; an export format without its friction law, as
    /// FCLIB for Tresca), or its geometry contradicts it (a body that starts inside its
    /// obstacle). What and why, and what to do.
    #[error("{message}\n  hint: {hint}")]
    Formulation {
        /// What cannot be solved, and why.
        message: String,
        /// What to do instead.
        hint: String,
    },

    /// A scene written with `[[body]]` tables given to a command or formulation that takes one
    /// body (`export`, `adapt`, `study`, the dual formulation, the estimate): parsed, meshed and
    /// checked, then refused (rather than a wrong answer). `signorini run` solves it.
    #[error(
        "{}: this scene has {bodies} bod{} and {pairs} contact pair{}: several bodies are parsed and checked but \
         not solved yet in this version by this command or formulation (export, adapt, study, the dual formulation \
         and the estimate take one body)\n  hint: the scene is valid: `signorini run` solves it in the primal \
         formulation; for the others, solve one body at a time with a single-body scene",
        scene.display(),
        if *bodies == 1 { "y" } else { "ies" },
        if *pairs == 1 { "" } else { "s" }
    )]
    SeveralBodiesNotSolved {
        /// The scene file.
        scene: std::path::PathBuf,
        /// Its number of `[[body]]` tables.
        bodies: usize,
        /// Its number of `[[contact_pair]]` tables.
        pairs: usize,
    },

    /// A feature that runs on one process, started on several (`mpirun -n N`, N > 1): refused
    /// by name before any work (meshing, assembly, a child process, a file).
    #[error("{feature} runs on one process only ({reason})\n  hint: run it without mpirun")]
    SingleProcess {
        /// The feature, as the user names it (e.g. "signorini bench elasticity").
        feature: String,
        /// Why it cannot be distributed.
        reason: String,
    },
}

/// The library's result type.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// [`Error::Io`]: `action` on `path` failed with `source`.
    pub fn io(path: impl Into<PathBuf>, action: &'static str, source: std::io::Error) -> Self {
        Error::Io { path: path.into(), action, source }
    }

    /// [`Error::Mesh`] about `entity` (e.g. "triangle 12"), without a file (see
    /// [`Error::in_mesh_file`]).
    pub fn mesh(entity: impl Into<String>, message: impl Into<String>) -> Self {
        Error::Mesh { source_file: None, entity: entity.into(), message: message.into() }
    }

    /// Attach the mesh file a mesh error came from, if not already set.
    pub fn in_mesh_file(self, file: impl Into<PathBuf>) -> Self {
        match self {
            Error::Mesh { source_file: None, entity, message } => {
                Error::Mesh { source_file: Some(file.into()), entity, message }
            }
            other => other,
        }
    }
}
