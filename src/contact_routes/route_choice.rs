//! Which linear algebra solves the full-space Newton steps: a cost model over the number of
//! contact unknowns, the dofs and the ranks, or the user's `-contact_route`.
//!
//! ## The routes
//!
//! ```text
//!   dense_schur   one MUMPS Cholesky of K with the Schur complement S on the s dofs the contact
//!                 rows touch (s = 2 m against a rigid obstacle), S⁻¹ dense; each Newton step a
//!                 dense LU of the (c m)×(c m) contact system (c = 1 frictionless, 2 with
//!                 friction). One process.            time ≈ ½ T_LU(n) + a s³ + f · a (c m)³/3
//!                                                    memory ≈ M_K(n) + 3 · 8 s² bytes
//!   sparse_lu     MUMPS LU of the whole mixed Jacobian (n + c m unknowns), kept from one step to
//!                 the next while few rows change (GMRES on the new Jacobian, preconditioned by
//!                 the kept factors); any number of ranks.
//!                                                    time ≈ f · T_LU(n + c m)
//!                                                    memory ≈ 2 M_K(n) + GMRES basis
//!   dense_schur_gathered   under MPI (p ranks): K and the load gathered on rank 0, which
//!                 runs dense_schur alone on the whole problem and sends the answer
//!                 (`full_space/gathered.rs`).        time ≈ dense_schur + g · 14 n (the gather)
//!                                                    memory ≈ that of dense_schur, on rank 0
//! ```
//!
//! Under MPI the sparse route's factorisations are distributed: its time is divided by
//! `1.3^{log₂ p}` (`p e(p)` with the parallel efficiency `e(2) = 0.65` of `docs/scaling.md`; the
//! mixed LU measured here gained 0.7–1.25× on two shared cores). The dense route cannot be
//! distributed through PETSc 3.18 (it computes MUMPS's Schur complement on one process only,
//! and the centralised Schur complement on two ranks took 2× the serial time at 2e5 dofs,
//! more than 20× at 1e6: `petsc/inverse_block.rs`), so it runs whole on rank 0. Before
//! this route, two ranks took the square block at 2e5 dofs from 1.0–1.9 s (dense_schur, one
//! rank) to 4.4–9.9 s (8 distributed LUs); the distributed LU's statistics are those of the
//! serial one (`full_space/gathered.rs`), so the loss was the route, not MUMPS.
//!
//! `T_LU(n) = γ n^{3/2}` is the nested-dissection cost of a 2D mesh's factorisation (A. George,
//! "Nested dissection of a regular finite element mesh", SIAM J. Numer. Anal. 10 (1973)
//! 345–363: `O(n^{3/2})` operations), an upper bound for slender meshes whose separators are
//! shorter; the dense terms are the LAPACK operation counts (`s³` for forming and inverting `S`,
//! `(c m)³/3` per LU). `f` is the number of factorisations the sparse route makes: the first
//! step's, and one for each step where more than [`MAX_CHANGED_ROWS`] rows of the Jacobian
//! changed since the last one (GMRES on the new Jacobian with the kept factors then needs about
//! as many iterations as rows changed, and each costs a MUMPS solve).
//!
//! Measured on the project's machine (2 cores, OpenBLAS, MUMPS 5.5; `-log_view`): the square
//! block at 2e5 dofs (Coulomb, 320 points, 8 Newton steps) factorises its mixed Jacobian in
//! 0.62 s and solves with the factors in 0.078 s: a kept step with `r` changed rows costs
//! `(r + 1) · 0.078 s`, cheaper than a factorisation only for `r ≤ 7`. The square block's steps
//! change 320, 66, 16, 22, 25, 28, 29 rows: GMRES with factors kept from the third step took
//! 9.6 s against 5.0 s for one LU per step, so rows are kept only up to [`MAX_CHANGED_ROWS`] = 4
//! and in 2D the reuse saves little (the late steps of a converging active set). That is why
//! the route stays a sparse LU per step and the choice matters: `γ = 6.9e-9 s` (0.62 s at
//! 2e5), `a = 1e-10 s` (the strip with 4001 points: 52 s for `s = 8002`), `f` = the expected
//! Newton steps (3 without friction, 8 with). The model only has to order the routes: where
//! the two predictions differ by ten or more (the strip: 52 s against 0.2 s; the square block
//! at 2e5 dofs: 0.9 s against 5.0 s) it is right by a wide margin, and where they are close
//! either route costs about the same. On a square-shaped body with contact along one side
//! `s ≈ 1.4 √n`, so `a s³ ≈ 2.8e-10 n^{3/2}` stays far below `γ n^{3/2}`: the dense route wins
//! at every size; on a strip `s` grows like `n` and the sparse route wins from a few hundred
//! points on.
//!
//! The dense route also needs its memory: when `3 · 8 s²` bytes exceed what the machine has
//! available (`MemAvailable` in `/proc/meminfo`, or `-contact_memory_limit <MB>`), it is not
//! taken; asked for by name, it is refused with [`Error::RouteMemory`] before any work.
use crate::error::{Error, Result};
use crate::petsc::Session;

/// The sparse LU route's gain from doubling the ranks (`p e(p)` at `p = 2`; `e(p) = e(2)^{log₂ p}`
/// for more, as in `docs/scaling.md`). Measured on this project's machine, the square block at
/// 2e5 dofs, 8 MUMPS LUs of the mixed Jacobian: 4.4–4.8 s on one rank, 3.6–6.8 s on two
/// (MUMPS's statistics are the same on both: see the module documentation).
const SPARSE_SPEEDUP_PER_DOUBLING: f64 = 1.3;
/// Seconds per stored entry of `K` gathered on rank 0 (one broadcast per other rank of its
/// rows, 16 bytes an entry, encoded and decoded): 0.81 s for the 1.4e7 entries of the square
/// block at 1e6 dofs on two ranks.
const GATHER_SECONDS: f64 = 6e-8;
/// Stored entries of `K` per displacement dof (P1 triangles on a structured mesh: 7 nodes a
/// row, 2 components).
const ENTRIES_PER_DOF: f64 = 14.0;

/// The option naming the route (`auto`, `dense_schur`, `sparse_lu`).
pub const ROUTE_OPTION: &str = "-contact_route";
/// The option capping the memory a route may plan for, in MB (default: the memory available).
pub const MEMORY_LIMIT_OPTION: &str = "-contact_memory_limit";
/// The sparse LU route refactorises when more rows than this changed since its last
/// factorisation (each kept step costs at most that many GMRES iterations plus a few).
pub const MAX_CHANGED_ROWS: usize = 4;
/// `γ` in `T_LU(n) = γ n^{3/2}` (seconds).
const LU_SECONDS: f64 = 6.9e-9;
/// `a`: seconds per dense operation (forming and inverting `S`, the per-step LU).
const DENSE_SECONDS: f64 = 1e-10;
/// Newton steps expected without and with friction: the sparse route's factorisations (`f`
/// in the module doc) and the dense route's per-step LUs.
const EXPECTED_STEPS: [f64; 2] = [3.0, 8.0];
/// Bytes per entry of a dense matrix, and the number of such `s × s` matrices the dense route
/// holds at once (`S` from MUMPS, its inverse, the per-step system).
const DENSE_COPIES: f64 = 3.0 * 8.0;

/// How the full-space Newton steps are solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Route {
    /// One Cholesky of K with the dense Schur complement on the contact dofs (one process).
    DenseSchur,
    /// MUMPS LU of the mixed Jacobian, kept across steps while few rows change.
    SparseLu,
    /// Under MPI: `K` and the load gathered on rank 0, which runs the one-process route (the
    /// dense Schur route) alone on the whole problem and sends the answer to the other ranks.
    DenseSchurGathered,
    /// The inner solver the options name (`-contact_ksp_type`, `-contact_pc_type`).
    FromOptions,
}

impl Route {
    /// The route's name in reports and in `-contact_route`.
    pub fn name(self) -> &'static str {
        match self {
            Route::DenseSchur => "dense_schur",
            Route::SparseLu => "sparse_lu",
            Route::DenseSchurGathered => "dense_schur_gathered",
            Route::FromOptions => "options",
        }
    }
}

/// The route taken and why, for the report (`contact.route`, `contact.route_reason`).
#[derive(Debug, Clone, PartialEq)]
pub struct RouteChoice {
    /// The route.
    pub route: Route,
    /// Why, in words (the predictions compared, or the option that asked for it).
    pub reason: String,
}

/// What the cost model looks at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RouteInputs {
    /// Displacement dofs (all ranks).
    pub dofs: usize,
    /// Contact points.
    pub points: usize,
    /// Contact unknowns per point (1 frictionless, 2 with friction).
    pub per_point: usize,
    /// Dofs the contact rows touch (the dense route's Schur complement).
    pub schur_size: usize,
    /// MPI ranks.
    pub ranks: usize,
    /// Bytes the dense route may plan for (`None`: no limit known).
    pub memory_limit: Option<f64>,
}

/// Predicted seconds and bytes of the dense Schur route beyond the sparse solve both routes
/// share (see the module documentation).
pub fn dense_prediction(inputs: &RouteInputs) -> (f64, f64) {
    let s = inputs.schur_size as f64;
    let cm = (inputs.per_point * inputs.points) as f64;
    let n = inputs.dofs as f64;
    let steps = expected_steps(inputs);
    let seconds = 0.5 * LU_SECONDS * n.powf(1.5) + DENSE_SECONDS * (s.powi(3) + steps * cm.powi(3) / 3.0);
    (seconds, dense_bytes(inputs.schur_size))
}

/// Bytes of the dense matrices an `s × s` dense Schur complement or flexibility needs (the
/// matrix, its inverse or factors, the per-step system).
pub fn dense_bytes(s: usize) -> f64 {
    DENSE_COPIES * (s as f64).powi(2)
}

/// `bytes` in megabytes, with the digits a small amount needs (`0.027 MB`, `15 MB`).
pub fn megabytes(bytes: f64) -> String {
    let mb = bytes / 1e6;
    if mb >= 10.0 {
        format!("{mb:.0} MB")
    } else {
        format!("{mb:.2} MB")
    }
}

/// Predicted seconds of the sparse LU route (on `inputs.ranks` ranks).
pub fn sparse_prediction(inputs: &RouteInputs) -> f64 {
    let n = (inputs.dofs + inputs.per_point * inputs.points) as f64;
    let speedup = SPARSE_SPEEDUP_PER_DOUBLING.powf((inputs.ranks.max(1) as f64).log2());
    expected_steps(inputs) * LU_SECONDS * n.powf(1.5) / speedup
}

/// Predicted seconds of gathering `K` on rank 0 (the gathered dense route's extra cost).
pub fn gather_prediction(inputs: &RouteInputs) -> f64 {
    if inputs.ranks > 1 {
        GATHER_SECONDS * ENTRIES_PER_DOF * inputs.dofs as f64
    } else {
        0.0
    }
}

fn expected_steps(inputs: &RouteInputs) -> f64 {
    EXPECTED_STEPS[usize::from(inputs.per_point > 1)]
}

/// The route of a scene's full-space Newton steps: the one the options name, else the cost
/// model's (see the module documentation).
pub fn choose(session: &Session, inputs: &RouteInputs) -> Result<RouteChoice> {
    let named = session.option(ROUTE_OPTION)?;
    let legacy_lu = session.has_option(super::full_space::FULL_SPACE_LU_OPTION)?;
    let user_inner = session.has_option("-contact_ksp_type")? || session.has_option("-contact_pc_type")?;
    choose_among(named.as_deref(), legacy_lu, user_inner, inputs)
}

/// [`choose`] on the options' values (`named`: the value of `-contact_route`).
pub fn choose_among(
    named: Option<&str>,
    legacy_lu: bool,
    user_inner: bool,
    inputs: &RouteInputs,
) -> Result<RouteChoice> {
    let (dense_seconds, dense_bytes) = dense_prediction(inputs);
    let sparse_seconds = sparse_prediction(inputs);
    let fits = inputs.memory_limit.is_none_or(|limit| dense_bytes <= limit);
    let memory_words = |limit: f64| {
        format!(
            "the dense Schur complement on {} dofs needs about {} and {} are available",
            inputs.schur_size,
            megabytes(dense_bytes),
            megabytes(limit)
        )
    };
    if user_inner {
        return Ok(RouteChoice {
            route: Route::FromOptions,
            reason: "-contact_ksp_type/-contact_pc_type name the inner solver of the mixed Jacobian".into(),
        });
    }
    let named = match (named, legacy_lu) {
        (None, true) => Some("sparse_lu"),
        (named, _) => named,
    };
    match named {
        None | Some("" | "auto") => {}
        Some("sparse_lu") => {
            return Ok(RouteChoice {
                route: Route::SparseLu,
                reason: format!(
                    "asked for ({}); the cost model predicted {:.2} s for it and {:.2} s for dense_schur",
                    if legacy_lu { super::full_space::FULL_SPACE_LU_OPTION } else { "-contact_route sparse_lu" },
                    sparse_seconds,
                    dense_seconds
                ),
            })
        }
        Some("dense_schur") => {
            if let (false, Some(limit)) = (fits, inputs.memory_limit) {
                return Err(Error::RouteMemory {
                    route: Route::DenseSchur.name().into(),
                    needed_mb: dense_bytes / 1e6,
                    available_mb: limit / 1e6,
                    instead: Route::SparseLu.name().into(),
                });
            }
            if inputs.ranks > 1 {
                return Ok(RouteChoice {
                    route: Route::DenseSchurGathered,
                    reason: format!(
                        "asked for (-contact_route dense_schur) on {} MPI ranks: the Schur complement of MUMPS is \
                         computed on one process, so K is gathered on rank 0, which runs the dense route alone \
                         and sends the answer; the cost model predicted {:.2} s for it and {sparse_seconds:.2} s for sparse_lu \
                         on {} ranks",
                        inputs.ranks,
                        dense_seconds + gather_prediction(inputs),
                        inputs.ranks
                    ),
                });
            }
            return Ok(RouteChoice {
                route: Route::DenseSchur,
                reason: format!(
                    "asked for (-contact_route dense_schur); the cost model predicted {dense_seconds:.2} s for it and \
                     {sparse_seconds:.2} s for sparse_lu"
                ),
            });
        }
        Some(other) => {
            return Err(Error::Usage(format!("{ROUTE_OPTION} takes auto, dense_schur or sparse_lu (got \"{other}\")")))
        }
    }
    let unknowns = inputs.per_point * inputs.points;
    if let (false, Some(limit)) = (fits, inputs.memory_limit) {
        return Ok(RouteChoice { route: Route::SparseLu, reason: memory_words(limit) });
    }
    if inputs.ranks > 1 {
        let gathered_seconds = dense_seconds + gather_prediction(inputs);
        let route = if gathered_seconds <= sparse_seconds { Route::DenseSchurGathered } else { Route::SparseLu };
        return Ok(RouteChoice {
            route,
            reason: format!(
                "{} contact unknowns on {} dofs, {} MPI ranks: predicted {gathered_seconds:.2} s for \
                 dense_schur_gathered (K gathered on rank 0, which runs the one-process dense Schur route \
                 alone and sends the answer: the Schur complement of MUMPS is computed on one process) and {sparse_seconds:.2} s for \
                 sparse_lu (distributed)",
                unknowns, inputs.dofs, inputs.ranks
            ),
        });
    }
    let route = if dense_seconds <= sparse_seconds { Route::DenseSchur } else { Route::SparseLu };
    Ok(RouteChoice {
        route,
        reason: format!(
            "{} contact unknowns on {} dofs: predicted {dense_seconds:.2} s for dense_schur (Schur complement on \
             {} dofs) and {sparse_seconds:.2} s for sparse_lu",
            unknowns, inputs.dofs, inputs.schur_size
        ),
    })
}

/// The memory the machine has available (`MemAvailable`, Linux), in bytes, or the limit the
/// options set (`-contact_memory_limit <MB>`).
pub fn memory_limit(session: &Session) -> Result<Option<f64>> {
    match session.option(MEMORY_LIMIT_OPTION)? {
        Some(text) => match text.trim().parse::<f64>() {
            Ok(mb) if mb > 0.0 && mb.is_finite() => Ok(Some(mb * 1e6)),
            _ => Err(Error::Usage(format!(
                "{MEMORY_LIMIT_OPTION} takes a positive number of megabytes (got \"{text}\")"
            ))),
        },
        None => Ok(crate::resources::available_memory_bytes().map(|b| b as f64)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strip(points: usize) -> RouteInputs {
        // A strip 4 cells high: 5 (points) dofs... 2 × 5 × points dofs, frictionless, held by
        // the contact (both components of each contact node in the Schur complement).
        RouteInputs { dofs: 10 * points, points, per_point: 1, schur_size: 2 * points, ranks: 1, memory_limit: None }
    }

    fn square_block(dofs: usize) -> RouteInputs {
        let points = ((dofs / 2) as f64).sqrt() as usize;
        RouteInputs { dofs, points, per_point: 2, schur_size: 2 * points, ranks: 1, memory_limit: None }
    }

    #[test]
    fn long_interfaces_take_the_sparse_route_and_the_square_block_the_dense_one() {
        for points in [1001, 4001, 20_001] {
            let choice = choose_among(None, false, false, &strip(points)).unwrap();
            assert_eq!(choice.route, Route::SparseLu, "{points}: {}", choice.reason);
        }
        for dofs in [200_000, 1_000_000] {
            let choice = choose_among(None, false, false, &square_block(dofs)).unwrap();
            assert_eq!(choice.route, Route::DenseSchur, "{dofs}: {}", choice.reason);
        }
    }

    #[test]
    fn the_options_name_the_route() {
        let s = square_block(200_000);
        assert_eq!(choose_among(Some("sparse_lu"), false, false, &s).unwrap().route, Route::SparseLu);
        assert_eq!(choose_among(None, true, false, &s).unwrap().route, Route::SparseLu);
        assert_eq!(choose_among(None, false, true, &s).unwrap().route, Route::FromOptions);
        let strip = strip(4001);
        assert_eq!(choose_among(Some("dense_schur"), false, false, &strip).unwrap().route, Route::DenseSchur);
        let e = choose_among(Some("schur"), false, false, &strip).unwrap_err();
        assert!(matches!(&e, Error::Usage(m) if m.contains("auto, dense_schur or sparse_lu")), "{e}");
    }

    #[test]
    fn under_mpi_the_square_block_gathers_k_and_long_interfaces_stay_distributed() {
        for dofs in [200_000, 1_000_000] {
            let s = RouteInputs { ranks: 2, ..square_block(dofs) };
            let choice = choose_among(None, false, false, &s).unwrap();
            assert_eq!(choice.route, Route::DenseSchurGathered, "{dofs}: {}", choice.reason);
            assert!(choice.reason.contains("2 MPI ranks") && choice.reason.contains("gathered"), "{}", choice.reason);
            let named = choose_among(Some("dense_schur"), false, false, &s).unwrap();
            assert_eq!(named.route, Route::DenseSchurGathered, "{}", named.reason);
            assert_eq!(choose_among(Some("sparse_lu"), false, false, &s).unwrap().route, Route::SparseLu);
        }
        for points in [4001, 20_001] {
            let s = RouteInputs { ranks: 2, ..strip(points) };
            let choice = choose_among(None, false, false, &s).unwrap();
            assert_eq!(choice.route, Route::SparseLu, "{points}: {}", choice.reason);
        }
        // The distributed LU's predicted time falls with the ranks, the gathered route's not.
        let one = square_block(1_000_000);
        let four = RouteInputs { ranks: 4, ..one };
        assert!(sparse_prediction(&four) < 0.6 * sparse_prediction(&one));
        assert!(gather_prediction(&four) > 0.0 && gather_prediction(&one) == 0.0);
    }

    #[test]
    fn a_dense_route_that_does_not_fit_is_refused_or_avoided() {
        // The square block's dense route is the cheaper, but needs 3 · 8 · 1412² ≈ 48 MB.
        let s = RouteInputs { memory_limit: Some(10e6), ..square_block(1_000_000) };
        let choice = choose_among(None, false, false, &s).unwrap();
        assert_eq!(choice.route, Route::SparseLu);
        assert!(choice.reason.contains("MB are available"), "{}", choice.reason);
        match choose_among(Some("dense_schur"), false, false, &s).unwrap_err() {
            Error::RouteMemory { route, instead, needed_mb, available_mb } => {
                assert_eq!((route.as_str(), instead.as_str()), ("dense_schur", "sparse_lu"));
                assert!(needed_mb > 40.0 && (available_mb - 10.0).abs() < 1e-9, "{needed_mb} {available_mb}");
            }
            other => panic!("{other}"),
        }
    }
}
