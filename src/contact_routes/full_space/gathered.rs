//! The gathered dense route under MPI (`dense_schur_gathered`): rank 0 receives the whole
//! constrained stiffness `K` and load, runs the one-process full-space route on them alone
//! (`Session::alone`: its PETSc objects and agreements on `PETSC_COMM_SELF`), and sends the
//! answer to the other ranks, which wait for it without spinning
//! (`Comm::broadcast_from_rank_0_sleeping`: a rank polling in a blocking MPI call keeps a core
//! busy, and on a shared machine that core is the one rank 0 needs).
//!
//! Why (measured on the project's 2-core machine, square block, Coulomb, 2e5 dofs, 8 Newton
//! steps, `OMP_NUM_THREADS=1`): on one process the cost model takes the dense Schur route, one
//! MUMPS Cholesky of `K` with the Schur complement on the contact dofs (1.0–1.1 s of solve).
//! PETSc 3.18 computes MUMPS's Schur complement on one process only, so under `mpirun` the
//! route was the distributed sparse LU of the mixed Jacobian, one LU per Newton step: 8 LUs of
//! 4.4–6.8 s on two ranks against 4.4–4.8 s on one. MUMPS's own statistics of that LU are the
//! same on one and two ranks (`-contact_ksp_view`, first step: estimated flops RINFOG(1) 5.98e9
//! against 6.26e9, factor entries INFOG(3) 21.1e6 against 21.2e6, AMD ordering INFOG(7) = 2 on
//! both, no maximum transversal INFOG(23) = 0 on both, 0 off-diagonal pivots, 714–886 delayed
//! pivots against 743–920), so the distributed LU is not worse-conditioned or fuller: it is
//! eight factorisations against one, and two ranks on two shared cores gain little on each
//! (0.7–1.25×). The route on several ranks that costs what one does: rank 0 runs the
//! one-process route on the gathered problem, so two ranks take the serial Newton steps to the
//! serial answer, at the serial cost plus the gather (one broadcast of each other rank's rows)
//! and the answer's broadcast. Running it on every rank instead (no answer to send) was
//! measured first: on this machine, busy with other work, two ranks then took 2.0–2.4× the
//! time of one (square block, 2e5 and 1e6 dofs), as two separate serial runs side by side do
//! (3.4 s each against 1.5 s alone): the two cores are not two cores' worth of throughput for
//! two factorisations at once.
//!
//! Measured (`mpirun -n 1` and `-n 2 target/release/signorini run`, square block, Coulomb,
//! report.json `timings.solve`, load 2–2.5 from other work): 2e5 dofs 1.16–1.47 s on one rank,
//! 1.34–1.56 s on two (4.4–9.9 s before, 8 distributed LUs); 1e6 dofs 9.2 s on one rank, 10.5–
//! 11.9 s on two, of which the gather took 0.81 s (1.4e7 entries; the issue measured 52 s
//! before). The report's notes say how long the gather and rank 0's run took.
//!
//! Rank 0 holds the whole factor of `K` (the memory of one process). The answer is sent
//! exactly (`f64` bits): the displacements, the contact forces and statuses, the solver's
//! statistics and what the report says of the run (solver, route and why, notes, history,
//! residuals of the independent check); the other ranks rebuild the rest of the report from
//! the forces and statuses with the same function as rank 0 (`ContactSetup::report`). The
//! rows are sent exactly (indices as `u64`, values as `f64` bits), so the gathered `K` is the
//! one a single process assembles, to the round-off of the summation order of the element
//! contributions.
use std::ops::Range;

use crate::contact::{ContactResiduals, PointStatus, ResidualScale};
use crate::error::{Error, Result};
use crate::fem::assembly::{CsrRows, LinearSystem};
use crate::petsc::{Session, SolveStats};
use crate::report::contact::{ContactOutcome, ContactReport, ContactResidualsReport};

/// Every rank's rows (`system`) of the constrained system on rank 0: the whole system (rows
/// `0..n`) there, `None` on the other ranks. Collective.
pub fn gather_system(session: &Session, system: &LinearSystem, n: usize) -> Result<Option<LinearSystem>> {
    let pieces = session.world().gather_bytes_to_rank_0(encode(system))?;
    if session.rank() != 0 {
        return Ok(None);
    }
    let mut matrix = CsrRows { first_row: 0, num_cols: n, indptr: vec![0], indices: Vec::new(), values: Vec::new() };
    let mut rhs = Vec::with_capacity(n);
    for (rank, bytes) in pieces.iter().enumerate() {
        decode(bytes, &mut matrix, &mut rhs).map_err(|why| {
            Error::PetscUsage(format!(
                "gathering the stiffness for the gathered contact route: rank {rank}'s rows: {why}"
            ))
        })?;
    }
    if matrix.num_rows() != n || rhs.len() != n {
        return Err(Error::PetscUsage(format!(
            "gathering the stiffness for the gathered contact route: {} rows and {} loads gathered for {n} dofs",
            matrix.num_rows(),
            rhs.len()
        )));
    }
    Ok(Some(LinearSystem { matrix, rhs }))
}

/// The dof ranges of one process holding every row.
pub fn whole(n: usize) -> Vec<Range<usize>> {
    std::iter::once(0..n).collect()
}

/// What rank 0 sends of the report beyond what the other ranks rebuild from the forces and
/// statuses (see the module documentation).
pub struct ReportPart {
    pub solver: String,
    pub route: String,
    pub route_reason: String,
    pub notes: Vec<String>,
    pub iterations: usize,
    pub status_changes: Vec<usize>,
    pub residual_history: Vec<f64>,
    pub linear_solves: usize,
    pub stabilisation_force: [f64; 2],
    pub stabilisation_iterations: usize,
    pub stabilisation_step_iterations: Vec<usize>,
    pub residuals: ContactResidualsReport,
}

impl ReportPart {
    /// The part of `report` that is sent.
    pub fn of(report: &ContactReport) -> ReportPart {
        ReportPart {
            solver: report.solver.clone(),
            route: report.route.clone(),
            route_reason: report.route_reason.clone(),
            notes: report.notes.clone(),
            iterations: report.iterations,
            status_changes: report.status_changes.clone(),
            residual_history: report.residual_history.clone(),
            linear_solves: report.linear_solves,
            stabilisation_force: report.stabilisation_force,
            stabilisation_iterations: report.stabilisation_iterations,
            stabilisation_step_iterations: report.stabilisation_step_iterations.clone(),
            residuals: report.residuals.clone(),
        }
    }

    /// Put this part into `report` (rebuilt by the receiving rank).
    pub fn apply(self, report: &mut ContactReport) {
        report.solver = self.solver;
        report.route = self.route;
        report.route_reason = self.route_reason;
        report.notes = self.notes;
        report.iterations = self.iterations;
        report.status_changes = self.status_changes;
        report.residual_history = self.residual_history;
        report.linear_solves = self.linear_solves;
        report.stabilisation_force = self.stabilisation_force;
        report.stabilisation_iterations = self.stabilisation_iterations;
        report.stabilisation_step_iterations = self.stabilisation_step_iterations;
        report.residuals = self.residuals;
    }

    /// The residuals of the independent check as the contact module holds them.
    pub fn contact_residuals(&self) -> ContactResiduals {
        let r = &self.residuals;
        ContactResiduals {
            max_penetration: r.max_penetration,
            max_wrong_sign_pressure: r.max_wrong_sign_pressure,
            max_cone_violation: r.max_cone_violation,
            normal_complementarity: r.normal_complementarity,
            tangential_complementarity: r.tangential_complementarity,
            scale: ResidualScale { force: r.force_scale, displacement: r.displacement_scale },
            worst_point: 0,
        }
    }
}

/// Rank 0's answer as the other ranks receive it.
pub struct Answer {
    pub u: Vec<f64>,
    pub force: Vec<f64>,
    pub status: Vec<PointStatus>,
    pub stats: SolveStats,
    pub report: ReportPart,
}

/// Little-endian words: the answer's encoding.
#[derive(Default)]
struct Writer(Vec<u8>);

impl Writer {
    fn int(&mut self, v: usize) {
        self.0.extend_from_slice(&(v as u64).to_le_bytes());
    }
    fn real(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_le_bytes());
    }
    fn reals(&mut self, v: &[f64]) {
        self.int(v.len());
        v.iter().for_each(|&x| self.real(x));
    }
    fn ints(&mut self, v: &[usize]) {
        self.int(v.len());
        v.iter().for_each(|&x| self.int(x));
    }
    fn text(&mut self, t: &str) {
        self.int(t.len());
        self.0.extend_from_slice(t.as_bytes());
    }
    fn texts(&mut self, v: &[String]) {
        self.int(v.len());
        v.iter().for_each(|t| self.text(t));
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8]> {
        if n > self.bytes.len() {
            return Err(Error::PetscUsage("the gathered contact route's answer ends early".into()));
        }
        let (head, tail) = self.bytes.split_at(n);
        self.bytes = tail;
        Ok(head)
    }
    fn word(&mut self) -> Result<[u8; 8]> {
        let mut a = [0u8; 8];
        a.copy_from_slice(self.take(8)?);
        Ok(a)
    }
    fn int(&mut self) -> Result<usize> {
        usize::try_from(u64::from_le_bytes(self.word()?))
            .map_err(|_| Error::PetscUsage("the gathered contact route's answer: a count too large".into()))
    }
    fn real(&mut self) -> Result<f64> {
        Ok(f64::from_le_bytes(self.word()?))
    }
    fn count(&mut self, item: usize) -> Result<usize> {
        let n = self.int()?;
        if n.saturating_mul(item) > self.bytes.len() {
            return Err(Error::PetscUsage("the gathered contact route's answer ends early".into()));
        }
        Ok(n)
    }
    fn reals(&mut self) -> Result<Vec<f64>> {
        let n = self.count(8)?;
        (0..n).map(|_| self.real()).collect()
    }
    fn ints(&mut self) -> Result<Vec<usize>> {
        let n = self.count(8)?;
        (0..n).map(|_| self.int()).collect()
    }
    fn text(&mut self) -> Result<String> {
        let n = self.count(1)?;
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| Error::PetscUsage("the gathered contact route's answer: text not UTF-8".into()))
    }
    fn texts(&mut self) -> Result<Vec<String>> {
        let n = self.count(8)?;
        (0..n).map(|_| self.text()).collect()
    }
}

fn status_code(s: PointStatus) -> usize {
    match s {
        PointStatus::Open => 0,
        PointStatus::Stick => 1,
        PointStatus::Slip => 2,
    }
}

/// Rank 0's answer, to send (see [`decode_answer`]).
pub fn encode_answer(u: &[f64], outcome: &ContactOutcome, stats: &SolveStats) -> Vec<u8> {
    let mut w = Writer::default();
    w.reals(u);
    w.reals(&outcome.force);
    w.ints(&outcome.status.iter().map(|&s| status_code(s)).collect::<Vec<_>>());
    w.text(&stats.ksp_type);
    w.text(&stats.pc_type);
    w.texts(&stats.factor_package.iter().cloned().collect::<Vec<_>>());
    w.int(stats.iterations);
    w.text(&stats.converged_reason);
    w.real(stats.relative_residual);
    w.real(stats.seconds);
    let r = ReportPart::of(&outcome.report);
    w.text(&r.solver);
    w.text(&r.route);
    w.text(&r.route_reason);
    w.texts(&r.notes);
    w.int(r.iterations);
    w.ints(&r.status_changes);
    w.reals(&r.residual_history);
    w.int(r.linear_solves);
    w.reals(&r.stabilisation_force);
    w.int(r.stabilisation_iterations);
    w.ints(&r.stabilisation_step_iterations);
    let c = &r.residuals;
    w.reals(&[
        c.max_penetration,
        c.max_wrong_sign_pressure,
        c.max_cone_violation,
        c.normal_complementarity,
        c.tangential_complementarity,
        c.force_scale,
        c.displacement_scale,
    ]);
    w.0
}

/// The answer [`encode_answer`] wrote.
pub fn decode_answer(bytes: &[u8]) -> Result<Answer> {
    let mut r = Reader { bytes };
    let u = r.reals()?;
    let force = r.reals()?;
    let status = r
        .ints()?
        .into_iter()
        .map(|c| match c {
            0 => Ok(PointStatus::Open),
            1 => Ok(PointStatus::Stick),
            2 => Ok(PointStatus::Slip),
            _ => Err(Error::PetscUsage(format!("the gathered contact route's answer: point status {c}"))),
        })
        .collect::<Result<Vec<_>>>()?;
    let stats = SolveStats {
        ksp_type: r.text()?,
        pc_type: r.text()?,
        factor_package: r.texts()?.into_iter().next(),
        iterations: r.int()?,
        converged_reason: r.text()?,
        relative_residual: r.real()?,
        seconds: r.real()?,
    };
    let (solver, route, route_reason, notes) = (r.text()?, r.text()?, r.text()?, r.texts()?);
    let (iterations, status_changes, residual_history, linear_solves) = (r.int()?, r.ints()?, r.reals()?, r.int()?);
    let spring = r.reals()?;
    let stabilisation_force = [spring.first().copied().unwrap_or(0.0), spring.get(1).copied().unwrap_or(0.0)];
    let (stabilisation_iterations, stabilisation_step_iterations) = (r.int()?, r.ints()?);
    let c = r.reals()?;
    if c.len() != 7 || spring.len() != 2 || !r.bytes.is_empty() {
        return Err(Error::PetscUsage("the gathered contact route's answer does not have its parts".into()));
    }
    let residuals = ContactResidualsReport {
        max_penetration: c[0],
        max_wrong_sign_pressure: c[1],
        max_cone_violation: c[2],
        normal_complementarity: c[3],
        tangential_complementarity: c[4],
        force_scale: c[5],
        displacement_scale: c[6],
    };
    Ok(Answer {
        u,
        force,
        status,
        stats,
        report: ReportPart {
            solver,
            route,
            route_reason,
            notes,
            iterations,
            status_changes,
            residual_history,
            linear_solves,
            stabilisation_force,
            stabilisation_iterations,
            stabilisation_step_iterations,
            residuals,
        },
    })
}

/// `first_row`, rows, entries, then the row lengths, columns, values and loads (little endian).
fn encode(system: &LinearSystem) -> Vec<u8> {
    let k = &system.matrix;
    let rows = k.num_rows();
    let mut out = Vec::with_capacity(24 + 8 * (rows + 2 * k.nnz() + system.rhs.len()));
    for v in [k.first_row, rows, k.nnz()] {
        out.extend_from_slice(&(v as u64).to_le_bytes());
    }
    for r in 0..rows {
        out.extend_from_slice(&((k.indptr[r + 1] - k.indptr[r]) as u64).to_le_bytes());
    }
    for &c in &k.indices[k.indptr[0]..k.indptr[rows]] {
        out.extend_from_slice(&(c as u64).to_le_bytes());
    }
    for &v in &k.values[k.indptr[0]..k.indptr[rows]] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for &b in &system.rhs {
        out.extend_from_slice(&b.to_le_bytes());
    }
    out
}

/// Append one rank's rows (see [`encode`]) to `matrix` and `rhs`; they must follow the rows
/// already there.
fn decode(bytes: &[u8], matrix: &mut CsrRows, rhs: &mut Vec<f64>) -> std::result::Result<(), String> {
    let mut words = bytes.chunks_exact(8).map(|w| {
        let mut a = [0u8; 8];
        a.copy_from_slice(w);
        a
    });
    if !bytes.len().is_multiple_of(8) {
        return Err(format!("{} bytes, not a whole number of words", bytes.len()));
    }
    let mut next = || words.next().ok_or_else(|| "the message ends early".to_string());
    let int = |w: [u8; 8]| usize::try_from(u64::from_le_bytes(w)).map_err(|_| "an index too large".to_string());
    let first_row = int(next()?)?;
    let rows = int(next()?)?;
    let entries = int(next()?)?;
    if first_row != matrix.num_rows() {
        return Err(format!("starts at row {first_row}, after {} rows", matrix.num_rows()));
    }
    let mut end = *matrix.indptr.last().unwrap_or(&0);
    for _ in 0..rows {
        end += int(next()?)?;
        matrix.indptr.push(end);
    }
    for _ in 0..entries {
        let c = int(next()?)?;
        if c >= matrix.num_cols {
            return Err(format!("column {c} beyond {}", matrix.num_cols));
        }
        matrix.indices.push(c);
    }
    for _ in 0..entries {
        matrix.values.push(f64::from_le_bytes(next()?));
    }
    for _ in 0..rows {
        rhs.push(f64::from_le_bytes(next()?));
    }
    if matrix.indices.len() != end || next().is_ok() {
        return Err("row lengths, entries and loads do not match".into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows(
        first_row: usize,
        indptr: Vec<usize>,
        indices: Vec<usize>,
        values: Vec<f64>,
        rhs: Vec<f64>,
    ) -> LinearSystem {
        LinearSystem { matrix: CsrRows { first_row, num_cols: 3, indptr, indices, values }, rhs }
    }

    #[test]
    fn an_answer_decodes_to_what_was_sent() {
        let report = ContactReport {
            part: "bottom".into(),
            friction: crate::report::contact::FrictionReport::None,
            solver: "full-space semi-smooth Newton (Alart–Curnier)".into(),
            route: "dense_schur_gathered".into(),
            route_reason: "2 MPI ranks; on rank 0 alone: …".into(),
            iterations: 4,
            status_changes: vec![3, 1, 0, 0],
            residual_history: vec![1.0, 1e-3, f64::NAN, 1e-16],
            notes: vec!["one".into(), String::new(), "ρ = 2 E' w_i / L".into()],
            points: 3,
            open: 1,
            closed: 2,
            stick: 1,
            slip: 1,
            resultant: [1.5, -2.0],
            normal_resultant: -2.0,
            tangential_resultant: 1.5,
            peak_pressure: None,
            zones: Vec::new(),
            residuals: ContactResidualsReport {
                max_penetration: 1e-15,
                max_wrong_sign_pressure: 0.0,
                max_cone_violation: 2e-16,
                normal_complementarity: 3e-16,
                tangential_complementarity: 4e-16,
                force_scale: 2e6,
                displacement_scale: 3e-5,
            },
            stabilisation_force: [0.25, -0.5],
            stabilisation_iterations: 2,
            stabilisation_step_iterations: vec![3, 1],
            linear_solves: 7,
        };
        let status = vec![PointStatus::Open, PointStatus::Stick, PointStatus::Slip];
        let outcome = ContactOutcome { force: vec![0.0, 0.0, -1.0, 0.5, -1.0, 1.0], status: status.clone(), report };
        let stats = SolveStats {
            ksp_type: "snes newtonls + preonly".into(),
            pc_type: "lu".into(),
            factor_package: Some("mumps".into()),
            iterations: 4,
            converged_reason: "CONVERGED_FNORM_ABS".into(),
            relative_residual: 1e-17,
            seconds: 0.5,
        };
        let u = vec![1e-5, -2e-5, f64::MIN_POSITIVE, 0.1 + 0.2];
        let answer = decode_answer(&encode_answer(&u, &outcome, &stats)).unwrap();
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&answer.u), bits(&u));
        assert_eq!((answer.force, answer.status), (outcome.force.clone(), status));
        assert_eq!(format!("{:?}", answer.stats), format!("{stats:?}"));
        // The report rebuilt from another one with the sent part applied is the sent report.
        let mut rebuilt = outcome.report.clone();
        rebuilt.solver.clear();
        rebuilt.notes.clear();
        rebuilt.residual_history.clear();
        rebuilt.residuals.max_penetration = 1.0;
        assert_eq!(bits(&[answer.report.contact_residuals().scale.displacement]), bits(&[3e-5]));
        answer.report.apply(&mut rebuilt);
        assert_eq!(format!("{rebuilt:?}"), format!("{:?}", outcome.report));
        // Cut short or with bytes left over: refused.
        let bytes = encode_answer(&u, &outcome, &stats);
        assert!(decode_answer(&bytes[..bytes.len() - 3]).is_err());
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode_answer(&longer).is_err());
    }

    #[test]
    fn two_ranks_rows_decode_to_the_whole_system() {
        let top = rows(0, vec![0, 2], vec![0, 1], vec![4.0, -1.0], vec![1.5]);
        let bottom = rows(1, vec![0, 2, 4], vec![0, 1, 1, 2], vec![-1.0, 4.0, -0.5, 2.0], vec![0.25, -3.0]);
        let mut m = CsrRows { first_row: 0, num_cols: 3, indptr: vec![0], indices: vec![], values: vec![] };
        let mut rhs = Vec::new();
        decode(&encode(&top), &mut m, &mut rhs).unwrap();
        decode(&encode(&bottom), &mut m, &mut rhs).unwrap();
        assert_eq!(m.indptr, vec![0, 2, 4, 6]);
        assert_eq!(m.indices, vec![0, 1, 0, 1, 1, 2]);
        assert_eq!(m.values, vec![4.0, -1.0, -1.0, 4.0, -0.5, 2.0]);
        assert_eq!(rhs, vec![1.5, 0.25, -3.0]);
        // Out of order, or cut short: refused.
        let mut m2 = CsrRows { first_row: 0, num_cols: 3, indptr: vec![0], indices: vec![], values: vec![] };
        assert!(decode(&encode(&bottom), &mut m2, &mut Vec::new()).unwrap_err().contains("starts at row 1"));
        let bytes = encode(&top);
        let mut m3 = CsrRows { first_row: 0, num_cols: 3, indptr: vec![0], indices: vec![], values: vec![] };
        assert!(decode(&bytes[..bytes.len() - 8], &mut m3, &mut Vec::new()).unwrap_err().contains("ends early"));
    }
}
