//! # The condensed contact problem in the FCLIB format
//!
//! FCLIB is the exchange format of discrete frictional contact problems (V. Acary, M. Brémond,
//! T. Koziol, F. Pérignon, *FCLIB: a collection of discrete 3D frictional contact problems*,
//! Inria technical report RT-0444, 2014; reference implementation `src/fclib.h` of the
//! FrictionalContactLibrary/fclib repository, whose `fclib_write_local`,
//! `fclib_write_solution` and `fclib_read_local` fix the layout below). Its *local* problem:
//! given `W` (symmetric positive semi-definite), `q` and one friction coefficient per contact,
//! find `u` and `r` with
//!
//! ```text
//!   u = W r + q,     û = u + (μ ‖u_T‖, 0) per contact,     K*_μ ∋ û ⊥ r ∈ K_μ,
//!   K_μ = { r : ‖r_T‖ ≤ μ r_N }   (the Coulomb cone),   K*_μ its dual cone,
//! ```
//!
//! that is (De Saxcé's form of Signorini + Coulomb): `r_N ≥ 0`, `u_N ≥ 0`, `r_N u_N = 0`,
//! `‖r_T‖ ≤ μ r_N`, sticking (`u_T = 0`) inside the cone and sliding opposite to `r_T` on its
//! boundary. Each contact has a block of `spacedim` components, the normal one first; here
//! `spacedim = 2` (normal, tangential).
//!
//! ## File layout (HDF5; "int" is the native 32-bit integer, "double" the native float64)
//!
//! ```text
//!   /fclib_local/spacedim          int[1]        2
//!   /fclib_local/W/nzmax           int[1]        number of stored entries
//!   /fclib_local/W/m, W/n          int[1]        2 × contacts (rows, columns)
//!   /fclib_local/W/nz              int[1]        −1: compressed sparse columns (−2 would be rows,
//!                                                ≥ 0 triplets)
//!   /fclib_local/W/p               int[n+1]      column pointers, 0-based (p[0] = 0, p[n] = nzmax)
//!   /fclib_local/W/i               int[nzmax]    row indices, 0-based, increasing in each column
//!   /fclib_local/W/x               double[nzmax] the entries
//!   /fclib_local/vectors/q         double[2 × contacts]
//!   /fclib_local/vectors/mu        double[contacts]
//!   /fclib_local/info/title        \
//!   /fclib_local/info/description   > scalar fixed-length null-terminated ASCII strings
//!   /fclib_local/info/math_info    /   (what H5LTmake_dataset_string writes)
//!   /solution/u, /solution/r       double[2 × contacts]   (optional: our solution)
//! ```
//!
//! `W` is dense (the flexibility couples every pair of contact points); every nonzero entry is
//! stored, so the file's `W` is ours entry for entry. No `V`, `R`, `s` (no equality
//! constraints) and no `/guesses`.
//!
//! ## From our convention to FCLIB's
//!
//! ```text
//!   ours (crate::contact)                     FCLIB
//!   u = W r + u_free                          u' = W' r' + q
//!   uN − g0 ≤ 0,  rN ≤ 0 (compression)        u'_N ≥ 0,  r'_N ≥ 0
//!   frame (n, t), n towards the obstacle      frame (−n, −t): the obstacle's normal, towards
//!                                             the body (the same frame turned by 180°,
//!                                             still right-handed)
//!
//!   r' = −r,   u' = g̃ − u   (g̃ = (g0_0, 0, g0_1, 0, ...)),   hence   W' = W,   q = g̃ − u_free
//! ```
//!
//! so `u'_N = g0 − uN` is the gap after deformation and `r'_N = −rN` the compressive normal
//! force, both `≥ 0`; the tangential pair changes sign together, so friction opposing the slip
//! (`uT = −λ rT`) carries over unchanged, and so does the cone `|rT| ≤ μ (−rN) = μ r'_N`.
//! Coulomb friction gives `mu`; no friction is `mu = 0` (the cone is the normal ray). Tresca
//! friction (a given threshold, not proportional to the normal force) has no FCLIB form and is
//! refused ([`Error::Formulation`]).
use std::io;
use std::path::Path;

use hdf5::types::{FixedAscii, TypeDescriptor};
use nalgebra::DMatrix;

use crate::contact::{CondensedProblem, Delassus, FrictionLaw};
use crate::error::{Error, Result};
use crate::output::write_atomically_by_name;

/// FCLIB's `spacedim`: components per contact (normal, tangential).
pub const SPACE_DIMENSION: usize = 2;

/// Longest info string written (bytes, the terminating null excluded); longer ones are cut.
const STRING_CAPACITY: usize = 4095;

/// The local problem in FCLIB's convention: `u = W r + q`, one `mu` per contact.
#[derive(Debug, Clone, PartialEq)]
pub struct FclibLocal {
    /// `W` (`2m × 2m`), equal to our Delassus operator (its entries; an implicit operator is
    /// applied to the unit vectors and symmetrised).
    pub w: DMatrix<f64>,
    /// `q = g̃ − u_free`, ordered `(N_0, T_0, N_1, T_1, ...)`.
    pub q: Vec<f64>,
    /// One friction coefficient per contact (0: frictionless).
    pub mu: Vec<f64>,
}

/// A solution in FCLIB's convention (`/solution/u`, `/solution/r`).
#[derive(Debug, Clone, PartialEq)]
pub struct FclibSolution {
    /// `u' = W r' + q` (gap after deformation, then the tangential displacement along `−t`).
    pub u: Vec<f64>,
    /// `r' = −r` (compressive normal force ≥ 0, then the tangential force along `−t`).
    pub r: Vec<f64>,
}

/// The problem's description in `/fclib_local/info` (ASCII; other characters are replaced).
#[derive(Debug, Clone, PartialEq)]
pub struct FclibInfo {
    /// A short title.
    pub title: String,
    /// What the problem is (scene, mesh, material).
    pub description: String,
    /// The mathematical formulation stored.
    pub math_info: String,
}

/// What [`write_fclib`] wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct FclibSummary {
    /// Number of contacts (`W` is `2 contacts × 2 contacts`).
    pub contacts: usize,
    /// `spacedim` (always [`SPACE_DIMENSION`]).
    pub dimension: usize,
    /// Entries stored in `W` (`nzmax`).
    pub nonzeros: usize,
    /// Whether `/solution` was written.
    pub solution: bool,
}

/// `W` in compressed sparse columns, as the file stores it.
#[derive(Debug, Clone, PartialEq)]
pub struct CompressedColumns {
    /// Column pointers (`n + 1`).
    pub p: Vec<i32>,
    /// Row index of each entry.
    pub i: Vec<i32>,
    /// The entries.
    pub x: Vec<f64>,
}

/// The error for a friction law FCLIB cannot hold.
fn tresca_refused() -> Error {
    Error::Formulation {
        message: "the FCLIB format has no Tresca friction: its local problem is Coulomb friction only (a \
                  threshold mu r_N proportional to the normal force), so a given Tresca threshold cannot be \
                  written"
            .into(),
        hint: "export the scene with friction = \"coulomb\" (and its mu) or friction = \"none\"".into(),
    }
}

/// `g̃ − v`: the gap on the normal entries minus `v` (the change of convention of the module
/// documentation, for `u_free` and for `u`).
fn gap_minus(problem: &CondensedProblem, v: &[f64]) -> Vec<f64> {
    let mut out = negated(v);
    for (i, g) in problem.gap().iter().enumerate() {
        out[2 * i] += g;
    }
    out
}

/// `−v`, with `+0.0` for zeros (no `-0` in the file).
fn negated(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| 0.0 - x).collect()
}

/// The entries of `W`: copied, or (implicit operator) its products with the unit vectors,
/// symmetrised.
fn dense_delassus(delassus: &Delassus) -> DMatrix<f64> {
    match delassus {
        Delassus::Dense(w) => w.clone(),
        Delassus::Operator { .. } => {
            let n = delassus.size();
            let mut w = DMatrix::<f64>::zeros(n, n);
            let (mut e, mut column) = (vec![0.0; n], vec![0.0; n]);
            for j in 0..n {
                e[j] = 1.0;
                delassus.apply(&e, &mut column);
                e[j] = 0.0;
                w.column_mut(j).copy_from_slice(&column);
            }
            (&w + w.transpose()) * 0.5
        }
    }
}

/// Can a problem with this friction law be written? [`Error::Formulation`] for Tresca: the
/// check to make before the (costly) condensation.
pub fn check_friction(friction: &FrictionLaw) -> Result<()> {
    match friction {
        // All-zero thresholds are no friction (as `CondensedProblem::new` stores them).
        FrictionLaw::Tresca { threshold } if threshold.iter().any(|&s| s != 0.0) => Err(tresca_refused()),
        _ => Ok(()),
    }
}

impl FclibLocal {
    /// Our condensed problem in FCLIB's convention; [`Error::Formulation`] for Tresca friction.
    pub fn from_condensed(problem: &CondensedProblem) -> Result<Self> {
        check_friction(problem.friction())?;
        let mu = match problem.friction() {
            FrictionLaw::Coulomb { mu } => mu.clone(),
            _ => vec![0.0; problem.points()],
        };
        Ok(FclibLocal { w: dense_delassus(problem.delassus()), q: gap_minus(problem, problem.free_displacement()), mu })
    }

    /// Number of contacts.
    pub fn contacts(&self) -> usize {
        self.mu.len()
    }

    /// `W`'s nonzero entries in compressed sparse columns (exact zeros are not stored);
    /// [`Error::Usage`] for a `W` beyond FCLIB's 32-bit sizes and indices.
    pub fn compressed_columns(&self) -> Result<CompressedColumns> {
        let n = self.w.ncols();
        let too_large = || {
            Error::Usage(format!("FCLIB stores matrix sizes and indices as 32-bit integers: W ({n}×{n}) is too large"))
        };
        let index = |k: usize| i32::try_from(k).map_err(|_| too_large());
        let mut columns = CompressedColumns { p: Vec::with_capacity(n + 1), i: Vec::new(), x: Vec::new() };
        columns.p.push(0);
        for j in 0..n {
            for (row, &value) in self.w.column(j).iter().enumerate() {
                if value != 0.0 {
                    columns.i.push(index(row)?);
                    columns.x.push(value);
                }
            }
            columns.p.push(index(columns.x.len())?);
        }
        Ok(columns)
    }
}

impl FclibSolution {
    /// Our contact force `r` (with `u = W r + u_free`) in FCLIB's convention.
    pub fn from_force(problem: &CondensedProblem, force: &[f64]) -> Result<Self> {
        let u = problem.displacement(force)?;
        Ok(FclibSolution { u: gap_minus(problem, &u), r: negated(force) })
    }
}

impl FclibInfo {
    /// A title and a description of the problem's origin, and `math_info` said from the
    /// problem itself (friction, conventions, what is known of existence and uniqueness).
    pub fn new(title: impl Into<String>, description: impl Into<String>, problem: &CondensedProblem) -> Self {
        let m = problem.points();
        let friction = match problem.friction() {
            FrictionLaw::Coulomb { mu } => {
                let (lo, hi) = mu.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| (a.min(v), b.max(v)));
                if lo == hi {
                    format!("Coulomb friction, mu = {hi}")
                } else {
                    format!("Coulomb friction, mu from {lo} to {hi}")
                }
            }
            _ => "frictionless (mu = 0)".into(),
        };
        let existence = match problem.friction() {
            FrictionLaw::Coulomb { .. } => {
                "W is symmetric positive definite, so a solution exists for every mu and is unique for small mu"
            }
            _ => "W is symmetric positive definite, so the solution exists and is unique (a convex quadratic program)",
        };
        FclibInfo {
            title: title.into(),
            description: description.into(),
            math_info: format!(
                "2D quasi-static frictional contact, {m} contacts, {friction}. spacedim = 2: per contact the normal \
                 component, then the tangential one. u = W r + q with r_N >= 0 the compressive normal force, u_N >= 0 \
                 the gap after deformation, r_N u_N = 0, |r_T| <= mu r_N, sliding opposite to r_T. {existence}."
            ),
        }
    }
}

/// Write the condensed contact problem (and, given our contact force `force` in our
/// convention, the solution it makes) to `path` as an FCLIB local problem, all at once: the
/// file is written under a hidden temporary name in the same directory and renamed over
/// `path` when complete ([`write_atomically_by_name`]); on failure nothing is left and an
/// existing `path` is unchanged.
///
/// Errors: [`Error::Formulation`] for Tresca friction (before any file is touched),
/// [`Error::Usage`] for a force of the wrong size, [`Error::Output`] when writing fails.
pub fn write_fclib(
    path: &Path,
    problem: &CondensedProblem,
    force: Option<&[f64]>,
    info: &FclibInfo,
) -> Result<FclibSummary> {
    let local = FclibLocal::from_condensed(problem)?;
    let solution = force.map(|f| FclibSolution::from_force(problem, f)).transpose()?;
    let columns = local.compressed_columns()?;
    write_atomically_by_name(path, |temporary| {
        write_hdf5(temporary, &local, &columns, solution.as_ref(), info)
            .map_err(|e| io::Error::other(format!("HDF5: {e}")))
    })?;
    Ok(FclibSummary {
        contacts: local.contacts(),
        dimension: SPACE_DIMENSION,
        nonzeros: columns.x.len(),
        solution: solution.is_some(),
    })
}

fn write_hdf5(
    path: &Path,
    local: &FclibLocal,
    columns: &CompressedColumns,
    solution: Option<&FclibSolution>,
    info: &FclibInfo,
) -> hdf5::Result<()> {
    let size = i32::try_from(local.w.nrows()).map_err(|_| "W is too large for 32-bit sizes")?;
    let nonzeros = i32::try_from(columns.x.len()).map_err(|_| "W has too many entries for 32-bit sizes")?;
    let file = hdf5::File::create(path)?;
    {
        let root = file.create_group("fclib_local")?;
        ints(&root, "spacedim", &[SPACE_DIMENSION as i32])?;
        let w = root.create_group("W")?;
        ints(&w, "nzmax", &[nonzeros])?;
        ints(&w, "m", &[size])?;
        ints(&w, "n", &[size])?;
        ints(&w, "nz", &[-1])?;
        ints(&w, "p", &columns.p)?;
        ints(&w, "i", &columns.i)?;
        doubles(&w, "x", &columns.x)?;
        let vectors = root.create_group("vectors")?;
        doubles(&vectors, "q", &local.q)?;
        doubles(&vectors, "mu", &local.mu)?;
        let about = root.create_group("info")?;
        string(&about, "title", &info.title)?;
        string(&about, "description", &info.description)?;
        string(&about, "math_info", &info.math_info)?;
        if let Some(s) = solution {
            let group = file.create_group("solution")?;
            doubles(&group, "u", &s.u)?;
            doubles(&group, "r", &s.r)?;
        }
    }
    file.close()
}

/// A 1-D dataset of native ints (a one-element one for a scalar, as FCLIB writes them).
fn ints(group: &hdf5::Group, name: &str, values: &[i32]) -> hdf5::Result<()> {
    group.new_dataset_builder().with_data(values).create(name).map(|_| ())
}

fn doubles(group: &hdf5::Group, name: &str, values: &[f64]) -> hdf5::Result<()> {
    group.new_dataset_builder().with_data(values).create(name).map(|_| ())
}

/// A scalar dataset of a fixed-length string of exactly `len + 1` bytes, null-terminated: what
/// FCLIB's reader expects (it allocates the stored size and reads the bytes as a C string).
fn string(group: &hdf5::Group, name: &str, text: &str) -> hdf5::Result<()> {
    let text = ascii(text);
    let value = FixedAscii::<{ STRING_CAPACITY + 1 }>::from_ascii(text.as_bytes()).map_err(|e| e.to_string())?;
    let dataset =
        group.new_dataset_builder().empty_as(TypeDescriptor::FixedAscii(text.len() + 1)).shape(()).create(name)?;
    dataset.write_scalar(&value)
}

/// `text` in printable ASCII: common typography transliterated, anything else `?`, cut to
/// [`STRING_CAPACITY`] bytes.
fn ascii(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            c if c.is_ascii() && c != '\0' => out.push(c),
            '\u{2010}'..='\u{2015}' | '\u{2212}' => out.push('-'),
            '\u{2018}' | '\u{2019}' => out.push('\''),
            '\u{201c}' | '\u{201d}' => out.push('"'),
            'μ' | 'µ' => out.push_str("mu"),
            '×' => out.push('x'),
            '≤' => out.push_str("<="),
            '≥' => out.push_str(">="),
            '\0' => {}
            _ => out.push('?'),
        }
    }
    if out.len() > STRING_CAPACITY {
        out.truncate(STRING_CAPACITY - 3);
        out.push_str("...");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two points: the first pressed into the obstacle (closed), the second lifted off (open).
    fn two_points(friction: FrictionLaw) -> CondensedProblem<'static> {
        let w = DMatrix::from_row_slice(
            4,
            4,
            &[4.0, 0.5, 1.0, 0.2, 0.5, 3.0, 0.1, 0.4, 1.0, 0.1, 5.0, 0.3, 0.2, 0.4, 0.3, 2.0],
        );
        CondensedProblem::new(Delassus::Dense(w), vec![2.0, 0.5, -1.0, 0.1], vec![1.0, 0.5], friction, None).unwrap()
    }

    #[test]
    fn conversion_flips_signs_and_folds_the_gap_into_q() {
        let p = two_points(FrictionLaw::Coulomb { mu: vec![0.3, 0.3] });
        let local = FclibLocal::from_condensed(&p).unwrap();
        assert_eq!(local.w, *p.delassus().as_dense().unwrap());
        assert_eq!(local.q, vec![1.0 - 2.0, -0.5, 0.5 + 1.0, -0.1]);
        assert_eq!(local.mu, vec![0.3, 0.3]);
        // Our solution, in FCLIB's convention, satisfies FCLIB's conditions.
        let ours = crate::contact::solve(
            &p,
            &crate::contact::ContactSolver::SemismoothNewton,
            &crate::contact::SolverSettings::default(),
        )
        .unwrap();
        assert!(ours.force[0] < 0.0, "point 0 is closed: {:?}", ours.force);
        let s = FclibSolution::from_force(&p, &ours.force).unwrap();
        let wr = &local.w * nalgebra::DVector::from_column_slice(&s.r);
        for k in 0..4 {
            assert!((s.u[k] - wr[k] - local.q[k]).abs() < 1e-12, "u = W r + q");
        }
        for i in 0..2 {
            let (un, rn, rt) = (s.u[2 * i], s.r[2 * i], s.r[2 * i + 1]);
            assert!(un >= -1e-9 && rn >= -1e-12 && (un * rn).abs() < 1e-9, "point {i}: {un} {rn}");
            assert!(rt.abs() <= local.mu[i] * rn + 1e-12);
        }
        assert!(s.r[0] > 0.0 && s.u[0].abs() < 1e-9, "point 0 closed: r_N > 0, u_N = 0");
        assert!(s.r[2].abs() < 1e-12 && s.u[2] > 0.0, "point 1 open: r_N = 0, u_N > 0");
        // Frictionless is mu = 0; Tresca is refused with the typed error.
        let none = FclibLocal::from_condensed(&two_points(FrictionLaw::None)).unwrap();
        assert_eq!(none.mu, vec![0.0, 0.0]);
        match FclibLocal::from_condensed(&two_points(FrictionLaw::Tresca { threshold: vec![1.0, 1.0] })) {
            Err(Error::Formulation { message, hint }) => {
                assert!(message.contains("Tresca") && hint.contains("coulomb"), "{message} / {hint}")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn compressed_columns_skip_exact_zeros_and_match_w() {
        let mut local = FclibLocal::from_condensed(&two_points(FrictionLaw::None)).unwrap();
        local.w[(3, 0)] = 0.0;
        local.w[(0, 3)] = 0.0;
        let c = local.compressed_columns().unwrap();
        assert_eq!(c.p, vec![0, 3, 7, 11, 14]);
        assert_eq!(c.i[..3], [0, 1, 2]);
        let mut back = DMatrix::<f64>::zeros(4, 4);
        for j in 0..4 {
            for k in c.p[j] as usize..c.p[j + 1] as usize {
                back[(c.i[k] as usize, j)] = c.x[k];
            }
        }
        assert_eq!(back, local.w);
    }

    #[test]
    fn info_strings_are_ascii_and_bounded() {
        assert_eq!(ascii("Raous–Chabrand — μ ≤ 1 × 2’s"), "Raous-Chabrand - mu <= 1 x 2's");
        assert_eq!(ascii("a\0b√"), "ab?");
        let long = "x".repeat(10_000);
        assert_eq!(ascii(&long).len(), STRING_CAPACITY);
    }
}
