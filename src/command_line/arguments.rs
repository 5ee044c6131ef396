//! The command line: the program's own flags through clap, PETSc's options passed through.
//!
//! PETSc options are single-dash words (`-ksp_type cg`, `-ksp_monitor`), which clap cannot
//! tell from short flags, so the arguments are split first ([`split_petsc_options`]): every
//! `-word` (a dash then a letter or `_`) and the value that follows it, if any, go to PETSc
//! untouched; everything else — subcommands, the scene, `--flags` with their values, `-h` —
//! goes to clap. The program's flags may therefore stand anywhere, before or after PETSc
//! options (`signorini run -ksp_monitor --out dir scene.toml` works).
use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};

/// Solver names `--contact-solver` accepts (the scene's `[contact] solver` names).
pub const CONTACT_SOLVERS: [&str; 8] =
    ["newton_full", "newton", "relaxation", "dpana", "uzawa", "tresca_fixed_point", "snes_vi", "tao"];

const PETSC_HELP: &str = "\
PETSc options: any option PETSc knows (-ksp_type, -pc_type, -pc_factor_levels, -ksp_monitor,
-ksp_view, -log_view, ...), anywhere on the line, applies to the main linear solver; the
contact solver's SNES/KSP take the prefix contact_ (-contact_snes_monitor). Scene [solver]
petsc_options are defaults that the command line overrides. Examples:
  signorini run examples/scenes/cantilever.toml -ksp_type cg -pc_type icc -pc_factor_levels 2 -ksp_monitor
  mpirun -n 2 signorini run examples/scenes/cantilever.toml";

/// The widest `--help` line: the terminal's width, at most this.
pub const HELP_WIDTH: usize = 100;

#[derive(Debug, Parser)]
#[command(
    name = "signorini",
    version,
    about = "2D frictional contact in linear elasticity with certified error control, on PETSc",
    after_help = PETSC_HELP,
    max_term_width = HELP_WIDTH
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Solve a scene and write DIR/solution.vtu and DIR/report.json (with contact also
    /// DIR/contact.csv, DIR/contact.svg and DIR/convergence.svg); the summary goes to stdout.
    #[command(after_help = PETSC_HELP)]
    Run(RunArgs),
    /// Adapt the mesh to a target error: solve primal and dual, estimate the error in the
    /// constitutive relation, remesh the scene's geometry with the optimal size map (refines
    /// and coarsens), repeat until the relative error is at most --target. Writes
    /// DIR/step_K/solution.vtu (cell data error, target_size), DIR/adapt.json, adapt.md and
    /// adapt.svg. A target not reached within --max-steps is a warning (exit status 0; the
    /// status is in adapt.json).
    #[command(after_help = PETSC_HELP)]
    Adapt(AdaptArgs),
    /// Convergence study: uniform refinements (the scene's cell size halved per level) against
    /// a P2 reference on a finer mesh: true errors of the primal and the dual, the estimate,
    /// effectivity and observed rates; writes DIR/study.json, study.md and study.svg.
    #[command(after_help = PETSC_HELP)]
    Study(StudyArgs),
    /// Write the scene's condensed contact problem as an FCLIB local problem (HDF5): W, q (the
    /// gaps minus the free displacements) and mu, in FCLIB's sign convention (normal force and
    /// gap >= 0), for Siconos and the other FCLIB readers to solve the same discrete problem.
    /// With --solve, our solution (u, r) too. Tresca friction has no FCLIB form.
    #[command(after_help = PETSC_HELP)]
    Export(ExportArgs),
    /// Benchmarks: tables (markdown) and plots (SVG) of times, iterations and memory.
    #[command(arg_required_else_help = false, subcommand_required = true)]
    Bench {
        #[command(subcommand)]
        which: Bench,
    },
}

#[derive(Debug, Args)]
pub struct RunArgs {
    /// The scene (a TOML file); without one, the embedded default scene (the square block of
    /// Raous–Chabrand–Lebon with Coulomb friction).
    pub scene: Option<PathBuf>,
    /// Output directory (default: the scene's [output] dir, else ./out).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print nothing but errors (no summary, no progress spinner).
    #[arg(long, short)]
    pub quiet: bool,
    /// Override the scene's [contact] solver.
    #[arg(long, value_name = "NAME", value_parser = CONTACT_SOLVERS)]
    pub contact_solver: Option<String>,
    /// Solve for displacements (primal, the default) or for stresses (dual: the Airy stress
    /// function on HCT elements); overrides [discretization] formulation.
    #[arg(long, value_name = "NAME", value_parser = ["primal", "dual"])]
    pub formulation: Option<String>,
    /// How the dual formulation imposes its boundary constraints: eliminated (a symmetric
    /// positive definite system, the default) or multipliers (a symmetric indefinite saddle
    /// point: MUMPS LDLᵀ, or -ksp_type symmlq -pc_type jacobi); overrides
    /// [discretization] dual_constraints.
    #[arg(long, value_name = "HOW", value_parser = ["eliminated", "multipliers"])]
    pub dual_constraints: Option<String>,
    /// Solve both formulations on the same mesh and report the error in the constitutive
    /// relation, per element and in total (as [estimate] in a scene).
    #[arg(long)]
    pub estimate: bool,
    /// Mesh with Gmsh even if the mesh cache has this mesh, and do not store it (as
    /// SIGNORINI_NO_MESH_CACHE=1).
    #[arg(long)]
    pub no_mesh_cache: bool,
}

#[derive(Debug, Args)]
pub struct ExportArgs {
    /// The scene (a TOML file with a [contact] section, Coulomb or no friction).
    pub scene: PathBuf,
    /// The file to write (default: DIR/problem.hdf5, DIR the scene's [output] dir, else ./out).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Also solve the condensed problem with the scene's contact solver and write our solution
    /// in the file (/solution: u and r, FCLIB's convention), for comparison.
    #[arg(long)]
    pub solve: bool,
}

#[derive(Debug, Args)]
pub struct AdaptArgs {
    /// The scene (a TOML file with a geometry: shape rectangle, disc, half_disc or quarter_disc).
    pub scene: PathBuf,
    /// The target relative error, percent of the energy norm (0 < PERCENT < 100).
    #[arg(long, value_name = "PERCENT", value_parser = parse_percent, allow_hyphen_values = true)]
    pub target: f64,
    /// The most meshes solved, the scene's own mesh included.
    #[arg(long, value_name = "N", default_value_t = 8, value_parser = clap::value_parser!(u32).range(1..=100))]
    pub max_steps: u32,
    /// Stop rather than remesh to more elements than this (predicted by the size map).
    #[arg(long, value_name = "N", default_value = "2e6", value_parser = parse_dofs)]
    pub max_elements: usize,
    /// The a priori rate p of the cells on the contact part (default 0.5, the talk's dual
    /// Tresca rate; the element degree makes them like the volume's).
    #[arg(long, value_name = "P", value_parser = parse_rate)]
    pub contact_rate: Option<f64>,
    /// Output directory (default: the scene's [output] dir, else ./out).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print nothing but errors and warnings.
    #[arg(long, short)]
    pub quiet: bool,
}

#[derive(Debug, Args)]
pub struct StudyArgs {
    /// The scene (a TOML file with a geometry: shape rectangle, disc, half_disc or quarter_disc).
    pub scene: PathBuf,
    /// Number of levels: cell sizes h, h/2, ..., h/2^(N-1) (h the scene's).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10))]
    pub levels: u32,
    /// The P2 reference is this many halvings (1 or 2) finer than the last level.
    #[arg(long, value_name = "M", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=2))]
    pub reference_halvings: u32,
    /// Output directory (default: the scene's [output] dir, else ./out).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Print nothing but errors.
    #[arg(long, short)]
    pub quiet: bool,
}

fn parse_rate(v: &str) -> Result<f64, String> {
    v.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x > 0.0 && *x <= 4.0)
        .ok_or_else(|| format!("expects an a priori rate in (0, 4], such as 0.5, got {v:?}"))
}

fn parse_percent(v: &str) -> Result<f64, String> {
    v.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite() && *x > 0.0 && *x < 100.0)
        .ok_or_else(|| format!("expects a percentage between 0 and 100 (exclusive), such as 5, got {v:?}"))
}

#[derive(Debug, Subcommand)]
pub enum Bench {
    /// Plane elasticity: assembly and solve times, peak memory and overhead ratios per linear
    /// solver, from 1e4 dofs up to --max-dofs (default 1e6).
    Elasticity(BenchArgs),
    /// The square block (Coulomb) for each contact solver: iterations, time, memory and the
    /// ratio to one linear solve of the same mesh, from 1e3 dofs up to --max-dofs (default 1e5).
    Contact(BenchArgs),
    /// The dual formulation (Airy/HCT) per linear solver against the primal P2 solve of the same
    /// mesh, with the estimate, from 1e4 dual dofs up to --max-dofs (default 1e5).
    Dual(BenchArgs),
    /// Contact in the dual formulation: the square block without its corner point (Tresca) in
    /// the dual and in the primal, with the estimate, from 1e3 to --max-dofs (default 1e5).
    DualContact(BenchArgs),
    /// A body held by the contact: the P2 half disc (Coulomb) driven by a prescribed
    /// displacement and by a traction with no support, full-space Newton, the ratio of the two
    /// solve times, at 1e4, 8.6e4 and 3e5 dofs up to --max-dofs (default 1e5).
    Held(BenchArgs),
    /// Load paths: the square block pressed then pushed (20 increments) and two cylinders
    /// through a fretting cycle (40 increments), at 1e4 and 1e5 dofs up to --max-dofs (default
    /// 1e5): the whole path against one linear solve and one static contact solve of the same
    /// mesh, with the targets (1 + 0.3 N linear solves; 10 static contact solves).
    Evolution(BenchArgs),
    /// Start-up and meshing: the wall and CPU time of a 1e3-dof `run` against
    /// `signorini --version`, and the mesh / contact-solve time ratio of the 8.6e4-dof P2 half
    /// disc on a first run and from the mesh cache.
    Startup(StartupArgs),
    /// The work-precision diagram of a contact scene: relative error (the estimate, and the
    /// true error against a P2 reference) against wall time for uniform P1 and P2 meshes, the
    /// adaptive loop in P1 and P2, and every contact solver on one mesh; one SVG plot and a
    /// markdown table. Default scene: the square block without its corner point, Tresca
    /// friction (examples/scenes/square_block_tresca.toml).
    Accuracy(AccuracyArgs),
    /// Scaling: (contact points) a strip pressed onto a rigid line and onto a second strip, with
    /// 100 to 20 000 contact points: time, peak memory and Newton steps of each contact route
    /// (dense_schur, sparse_lu, auto) against one linear solve of the same mesh, the route auto
    /// took and its time over the best route's (dense_schur skipped where predicted above 60 s
    /// or 8 GB); (strong) elasticity, one-body and two-body contact and primal + dual +
    /// estimate at --max-dofs on mpirun -n 1, 2, ... up to the cores present: time, speedup,
    /// efficiency; (weak) the same scenes at about 5e5 dofs per rank (at most --max-dofs in
    /// all): efficiency t1/tn. Writes bench_scale.md, bench_scale_points.svg and
    /// bench_scale_speedup.svg.
    Scale(ScaleArgs),
    /// One elasticity case (used by `bench elasticity`, one process per case).
    #[command(hide = true)]
    ElasticityCase(CaseArgs),
    /// One accuracy case (used by `bench accuracy`).
    #[command(hide = true)]
    AccuracyCase(CaseArgs),
    /// One contact case (used by `bench contact`).
    #[command(hide = true)]
    ContactCase(CaseArgs),
    /// One dual case (used by `bench dual`).
    #[command(hide = true)]
    DualCase(CaseArgs),
    /// One dual contact case (used by `bench dual-contact`).
    #[command(hide = true)]
    DualContactCase(CaseArgs),
    /// One held-by-contact case (used by `bench held`).
    #[command(hide = true)]
    HeldCase(CaseArgs),
    /// One load-path case (used by `bench evolution`).
    #[command(hide = true)]
    EvolutionCase(CaseArgs),
    /// One scaling case (used by `bench scale`, under mpirun for the scaling parts).
    #[command(hide = true)]
    ScaleCase(CaseArgs),
}

impl Bench {
    /// The name of a benchmark that runs its cases in child processes of its own (`None` for
    /// a case, which is such a child): it runs on one process.
    pub fn driver_name(&self) -> Option<&'static str> {
        match self {
            Bench::Elasticity(_) => Some("elasticity"),
            Bench::Contact(_) => Some("contact"),
            Bench::Dual(_) => Some("dual"),
            Bench::DualContact(_) => Some("dual-contact"),
            Bench::Held(_) => Some("held"),
            Bench::Evolution(_) => Some("evolution"),
            Bench::Startup(_) => Some("startup"),
            Bench::Accuracy(_) => Some("accuracy"),
            Bench::Scale(_) => Some("scale"),
            Bench::ElasticityCase(_)
            | Bench::AccuracyCase(_)
            | Bench::ContactCase(_)
            | Bench::DualCase(_)
            | Bench::DualContactCase(_)
            | Bench::HeldCase(_)
            | Bench::EvolutionCase(_)
            | Bench::ScaleCase(_) => None,
        }
    }
}

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Largest problem size, in degrees of freedom.
    #[arg(long, value_name = "N", value_parser = parse_dofs)]
    pub max_dofs: Option<usize>,
    /// Where the table and the plot go (default ./bench).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Run only these solvers (strategies, drives), comma-separated: each NAME is a solver's
    /// name as the table writes it (any case), or else a part of the names it selects (`mumps`,
    /// `icc`); a NAME that matches none is refused with the list of names.
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    pub solvers: Option<Vec<String>>,
}

#[derive(Debug, Args)]
pub struct ScaleArgs {
    /// Which part: contact-points, strong or weak (default: all three).
    #[arg(long, value_name = "PART", value_parser = ["contact-points", "strong", "weak", "all"])]
    pub part: Option<String>,
    /// Largest problem size, in degrees of freedom (default 2e5): the contact-point cases up to
    /// it, the strong-scaling size, and the weak-scaling size on the most ranks (the docs' runs
    /// use 1e6).
    #[arg(long, value_name = "N", value_parser = parse_dofs)]
    pub max_dofs: Option<usize>,
    /// Where the tables and the plots go (default ./bench).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct StartupArgs {
    /// Start-up runs of each command.
    #[arg(long, value_name = "N", default_value_t = 20, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub runs: u32,
    /// Only the start-up part (not the half disc, which takes two contact solves of 8.6e4 dofs).
    #[arg(long)]
    pub skip_half_disc: bool,
    /// Where the table goes (default ./bench).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// The scene (a TOML file with a geometry); default: the square block without its corner
    /// point, Tresca friction.
    pub scene: Option<PathBuf>,
    /// Largest uniform mesh, in degrees of freedom (default 2e4); the adaptive loops stop
    /// before meshes above it, the P2 reference is about 16 times larger.
    #[arg(long, value_name = "N", value_parser = parse_dofs)]
    pub max_dofs: Option<usize>,
    /// The adaptive loops' target error, percent (default 1).
    #[arg(long, value_name = "PERCENT", value_parser = parse_percent, allow_hyphen_values = true)]
    pub target: Option<f64>,
    /// Where the table and the plot go (default ./bench).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Run only these series and solvers, comma-separated (as for the other benchmarks).
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    pub solvers: Option<Vec<String>>,
}

#[derive(Debug, Args)]
pub struct CaseArgs {
    /// DOFS,SOLVER_INDEX
    #[arg(long, value_parser = parse_case)]
    pub case: (usize, usize),
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

fn parse_dofs(v: &str) -> Result<usize, String> {
    v.parse::<f64>()
        .ok()
        .filter(|x| *x >= 1.0 && x.is_finite())
        .map(|x| x as usize)
        .ok_or_else(|| format!("expects a positive number of dofs such as 1e5, got {v:?}"))
}

fn parse_case(v: &str) -> Result<(usize, usize), String> {
    let (d, k) = v.split_once(',').ok_or("expects DOFS,SOLVER_INDEX")?;
    Ok((d.parse().map_err(|_| "bad DOFS")?, k.parse().map_err(|_| "bad SOLVER_INDEX")?))
}

/// Our flags that take a value (the next argument, unless written `--flag=value`).
const VALUE_FLAGS: [&str; 15] = [
    "--out",
    "--part",
    "--runs",
    "--max-dofs",
    "--case",
    "--contact-solver",
    "--formulation",
    "--dual-constraints",
    "--target",
    "--max-steps",
    "--max-elements",
    "--levels",
    "--reference-halvings",
    "--contact-rate",
    "--solvers",
];

/// A PETSc option name: a dash then a letter or an underscore (`-ksp_type`, `-_x`), never
/// `-h` alone (ours) nor a negative number (a value).
fn is_petsc_name(a: &str) -> bool {
    a.len() > 2 && a.starts_with('-') && a[1..].starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
}

/// Split the arguments (without the program name) into ours and PETSc's.
pub fn split_petsc_options(args: &[String]) -> (Vec<String>, Vec<String>) {
    let (mut ours, mut petsc) = (Vec::new(), Vec::new());
    let mut i = 0;
    while i < args.len() {
        let a = &args[i];
        if a.starts_with("--") {
            ours.push(a.clone());
            if VALUE_FLAGS.contains(&a.as_str()) {
                if let Some(v) = args.get(i + 1) {
                    ours.push(v.clone());
                    i += 1;
                }
            }
        } else if is_petsc_name(a) {
            petsc.push(a.clone());
            // Its value, if any: the next argument unless it is an option or flag of its own,
            // or a scene file.
            if let Some(v) = args.get(i + 1) {
                if !v.starts_with("--") && !is_petsc_name(v) && !v.ends_with(".toml") && v != "-h" {
                    petsc.push(v.clone());
                    i += 1;
                }
            }
        } else {
            ours.push(a.clone());
        }
        i += 1;
    }
    (ours, petsc)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn split(line: &str) -> (Vec<String>, Vec<String>) {
        let args: Vec<String> = line.split_whitespace().map(String::from).collect();
        split_petsc_options(&args)
    }

    #[test]
    fn petsc_options_and_our_flags_mix_in_any_order() {
        let (ours, petsc) = split("run -ksp_monitor --out dir s.toml -ksp_type cg -pc_factor_levels 2 -q");
        assert_eq!(ours, ["run", "--out", "dir", "s.toml", "-q"]);
        assert_eq!(petsc, ["-ksp_monitor", "-ksp_type", "cg", "-pc_factor_levels", "2"]);
        let (ours, petsc) = split("run -mat_mumps_icntl_14 -1 --out=d -h");
        assert_eq!(ours, ["run", "--out=d", "-h"]);
        assert_eq!(petsc, ["-mat_mumps_icntl_14", "-1"]);
    }

    #[test]
    fn adapt_and_study_flags_take_their_values_even_negative_ones() {
        let (ours, petsc) = split("adapt s.toml --target -5 --max-steps 3 -ksp_type cg");
        assert_eq!(ours, ["adapt", "s.toml", "--target", "-5", "--max-steps", "3"]);
        assert_eq!(petsc, ["-ksp_type", "cg"]);
        let parse = |line: &str| {
            let (ours, _) = split(line);
            Cli::try_parse_from(std::iter::once("signorini".to_string()).chain(ours))
        };
        assert!(parse("adapt s.toml --target -5").is_err());
        assert!(parse("adapt s.toml --target 0").is_err());
        assert!(parse("adapt s.toml --target 100").is_err());
        assert!(parse("adapt s.toml --target 5 --max-steps 0").is_err());
        assert!(parse("study s.toml --levels 0").is_err());
        assert!(parse("study s.toml --levels 2 --reference-halvings 3").is_err());
        match parse("adapt s.toml --target 2.5").unwrap().command {
            Command::Adapt(a) => assert_eq!((a.target, a.max_steps), (2.5, 8)),
            other => panic!("{other:?}"),
        }
        match parse("export s.toml --out p.hdf5 --solve -ksp_type cg").unwrap().command {
            Command::Export(a) => {
                assert_eq!(
                    (a.scene.to_str(), a.out.as_deref().and_then(|p| p.to_str()), a.solve),
                    (Some("s.toml"), Some("p.hdf5"), true)
                )
            }
            other => panic!("{other:?}"),
        }
        assert!(parse("export").is_err());
        match parse("study s.toml --levels 3 --out d").unwrap().command {
            Command::Study(a) => assert_eq!((a.levels, a.reference_halvings), (3, 1)),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn clap_reads_our_part() {
        let (ours, _) = split("run s.toml --contact-solver newton_full --out d");
        let cli = Cli::try_parse_from(std::iter::once("signorini".to_string()).chain(ours)).unwrap();
        match cli.command {
            Command::Run(r) => {
                assert_eq!(r.scene.unwrap().to_str(), Some("s.toml"));
                assert_eq!(r.contact_solver.as_deref(), Some("newton_full"));
                assert_eq!(r.out.unwrap().to_str(), Some("d"));
            }
            other => panic!("{other:?}"),
        }
    }
}
