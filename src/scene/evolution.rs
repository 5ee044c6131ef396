//! The `[evolution]` table: a load path, every load multiplied by a piecewise-linear function of
//! a pseudo-time `t`, solved at a list of increments (the driver is [`crate::evolution`]).
//!
//! # Factors
//!
//! A load is a `[[traction]]`, a `[[dirichlet]]` (its prescribed components), the body force of
//! `[loads]`, or the obstacle's `motion` of `[contact]`; each may carry a `name`. At pseudo-time
//! `t` a load of the scene is applied as `factor(t) · load`, with
//!
//! ```text
//!   named load `x`:   factor(t) = the table x = [[t0, f0], [t1, f1], ..., [tk, fk]] of [evolution.factor],
//!                     linear between its rows:  f(t) = f_i + (f_{i+1} − f_i) (t − t_i)/(t_{i+1} − t_i),
//!                     t_i ≤ t ≤ t_{i+1}, and constant outside: f0 before t0, fk after tk
//!   unnamed load:     factor(t) = t / t_end     (the proportional ramp)
//! ```
//!
//! `t_end` ([`EvolutionSpec::ramp_end`]) is the latest last time of the tables, or 1 without
//! tables; so `[evolution] steps = N` without tables applies the loads at `t = k/N`,
//! `k = 1..N`, with factor `k/N`. A load meant to stay constant needs a name and a constant
//! table. Several loads may share a name (one table multiplies them all). The obstacle moves by
//! `factor(t) · motion`.
//!
//! # The increments
//!
//! The path starts at `start` (default: the earliest first time of the tables, or 0 without
//! tables; the state there is the unloaded, undeformed body without slip history) and its
//! increments end at the times `t_1 < ... < t_N`:
//!
//! - `times = [t_1, ..., t_N]` as written (strictly increasing, all after `start`);
//! - `steps = N`: `N` equal increments over `[start, t_end]`, `t_start + k (t_end − t_start)/N`,
//!   and every table time strictly inside `(start, t_end)` inserted (a generated time within
//!   `1e-9 (t_end − t_start)` of a table time is replaced by it), so that peaks and reversals
//!   of the factors are increments.
//!
//! Every increment time lies within the tables' span, from the earliest first time to the latest
//! last time (within `[0, 1]` without tables).
use super::convert::Scope;
use super::diagnostic::{closest, describe, Source};
use super::raw::{Leaf, RawEvolution, RawScene};
use crate::error::{Location, Result};
use std::ops::Range;
use toml::{Spanned, Value};

/// The largest number of generated increments (`steps`): a mistyped count should be an error,
/// not an exhausted memory.
pub const MAX_STEPS: usize = 1_000_000;

/// Two increment times closer than this fraction of the path's span are one time: a generated
/// time is replaced by a table time this close, and a `profiles` time this close to an increment
/// time is that increment.
pub const TIME_TOLERANCE: f64 = 1e-9;

/// A load path (`[evolution]`): the increments and the factor of every named load.
#[derive(Debug, Clone, PartialEq)]
pub struct EvolutionSpec {
    /// The pseudo-time of the initial state (`start`): the unloaded, undeformed body.
    pub start: f64,
    /// The increments' end times, strictly increasing, all after `start` (`times`, or generated
    /// from `steps` with the tables' times inserted: see the module documentation).
    pub times: Vec<f64>,
    /// The tables of `[evolution.factor]`, in file order, one per load name.
    pub factors: Vec<LoadFunction>,
    /// `monitor`: the boundary part whose mean displacement the history records (`"body.part"`
    /// with `[[body]]` tables); `None`: the driver's default (the contact part).
    pub monitor: Option<String>,
    /// Where `monitor` is written (for the check against the mesh).
    pub monitor_at: Option<Location>,
    /// `profiles`: the increment times at which the contact profiles are plotted, increasing
    /// and each one of [`Self::times`] (default: the end of the path; empty: none).
    pub profiles: Vec<f64>,
    /// Where the `[evolution]` table is written.
    pub at: Location,
}

/// The factor of one named load (a table of `[evolution.factor]`): piecewise linear through
/// `points`, constant outside them.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadFunction {
    /// The load name (the `name` of one or more loads).
    pub name: String,
    /// The rows `[t, factor]`: at least 2, times strictly increasing, finite.
    pub points: Vec<[f64; 2]>,
    /// Where the table is written.
    pub at: Location,
}

impl LoadFunction {
    /// The factor at `t`: linear interpolation between the rows, the first (last) factor before
    /// the first (after the last) time. NaN for a table without rows (never read from a scene).
    pub fn value(&self, t: f64) -> f64 {
        piecewise_linear(&self.points, t)
    }

    /// The first time of the table (NaN without rows).
    pub fn first_time(&self) -> f64 {
        self.points.first().map_or(f64::NAN, |p| p[0])
    }

    /// The last time of the table (NaN without rows).
    pub fn last_time(&self) -> f64 {
        self.points.last().map_or(f64::NAN, |p| p[0])
    }
}

impl EvolutionSpec {
    /// The factor of a load at pseudo-time `t`: its table's [`LoadFunction::value`] for a named
    /// load, `t / t_end` ([`Self::ramp_end`]) for an unnamed one (`None`). A name without a
    /// table (impossible in a checked scene) gets the ramp too.
    pub fn factor(&self, name: Option<&str>, t: f64) -> f64 {
        match name.and_then(|n| self.function(n)) {
            Some(f) => f.value(t),
            None => t / self.ramp_end(),
        }
    }

    /// The table of the load named `name`.
    pub fn function(&self, name: &str) -> Option<&LoadFunction> {
        self.factors.iter().find(|f| f.name == name)
    }

    /// The pseudo-time of the initial state ([`Self::start`]).
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The end of the path: the last increment time.
    pub fn end(&self) -> f64 {
        self.times.last().copied().unwrap_or(self.start)
    }

    /// `t_end` of the unnamed loads' ramp `t / t_end`: the latest last time of the tables, or
    /// 1 without tables.
    pub fn ramp_end(&self) -> f64 {
        ramp_end(&self.factors)
    }
}

/// The piecewise-linear interpolation of `rows` (`[t, value]`, t increasing) at `t`, constant
/// beyond the first and last rows (NaN without rows).
pub fn piecewise_linear(rows: &[[f64; 2]], t: f64) -> f64 {
    let (Some(&first), Some(&last)) = (rows.first(), rows.last()) else { return f64::NAN };
    if t <= first[0] {
        return first[1];
    }
    if t >= last[0] {
        return last[1];
    }
    // The row i with t_i ≤ t < t_{i+1}.
    let i = rows.partition_point(|q| q[0] <= t) - 1;
    let ([t0, f0], [t1, f1]) = (rows[i], rows[i + 1]);
    if t == t0 {
        return f0;
    }
    f0 + (f1 - f0) * ((t - t0) / (t1 - t0))
}

fn ramp_end(factors: &[LoadFunction]) -> f64 {
    factors.iter().map(LoadFunction::last_time).reduce(f64::max).unwrap_or(1.0)
}

// ---- conversion -------------------------------------------------------------------------------

/// Every load name of the scene with the span of its value, in file order: `name` of
/// `[[traction]]`, `[[dirichlet]]`, `[loads]` and `[contact]`, at the top level and in every
/// `[[body]]` (already checked to be non-empty strings by the conversion of the body tables).
pub(super) fn load_names(raw: &RawScene) -> Vec<(String, Range<usize>)> {
    let mut leaves: Vec<&Leaf> = Vec::new();
    leaves.extend(raw.traction.iter().map(|t| &t.name));
    leaves.extend(raw.dirichlet.iter().map(|d| &d.name));
    leaves.extend(raw.loads.iter().map(|l| &l.name));
    leaves.extend(raw.contact.iter().map(|c| &c.name));
    for b in &raw.body {
        leaves.extend(b.traction.iter().map(|t| &t.name));
        leaves.extend(b.dirichlet.iter().map(|d| &d.name));
        leaves.extend(b.loads.iter().map(|l| &l.name));
        leaves.extend(b.contact.iter().map(|c| &c.name));
    }
    let mut names: Vec<(String, Range<usize>)> = leaves
        .into_iter()
        .filter_map(|l| l.as_ref())
        .filter_map(|v| v.get_ref().as_str().map(|s| (s.to_string(), v.span())))
        .collect();
    names.sort_by_key(|(_, s)| s.start);
    names
}

/// A `name` of a load: a non-empty string.
pub(super) fn load_name(src: &Source, leaf: &Leaf) -> Result<Option<String>> {
    leaf.as_ref().map(|v| src.nonempty_string(v, "name").map(str::to_string)).transpose()
}

/// Convert and check `[evolution]` against the scene's load names (`names`, from
/// [`load_names`]) and body names (`bodies`: empty for a single-body scene).
pub(super) fn evolution_spec(
    src: &Source,
    e: &RawEvolution,
    names: &[(String, Range<usize>)],
    bodies: &[&str],
) -> Result<EvolutionSpec> {
    let first = super::raw::first_span(&[&e.steps, &e.times, &e.start, &e.monitor, &e.profiles]);
    // Located by its header, else its first key, else the [evolution.factor] header.
    let first = first.or_else(|| src.table_header("evolution.factor", false, 0));
    let table = Scope::top_level(src.text).table(src, "evolution", false, 0, first);
    let at = src.location(table.span.start);

    // The tables, in file order.
    let mut raw_tables: Vec<(&String, &Spanned<Value>)> = e.factor.iter().flatten().collect();
    raw_tables.sort_by_key(|(_, v)| v.span().start);
    let factors =
        raw_tables.iter().map(|(name, v)| load_function(src, name, v)).collect::<Result<Vec<LoadFunction>>>()?;
    check_names(src, &raw_tables, names)?;

    // The span of the tables and the ramp's end.
    let span_start = factors.iter().map(LoadFunction::first_time).reduce(f64::min);
    let t_end = ramp_end(&factors);
    let (lo, hi) = (span_start.unwrap_or(0.0), t_end);
    let span_text = |t: f64| match factors.is_empty() {
        true => format!(
            "without tables in [evolution.factor] the path runs over [0, 1] (the loads follow t); {t} is outside it"
        ),
        false => {
            let last = factors.iter().max_by(|a, b| a.last_time().total_cmp(&b.last_time())).expect("tables");
            let first = factors.iter().min_by(|a, b| a.first_time().total_cmp(&b.first_time())).expect("tables");
            format!(
                "the tables of [evolution.factor] span [{lo}, {hi}] (`{}` on line {} starts first, `{}` on line {} ends last); {t} is outside it",
                first.name, first.at.line, last.name, last.at.line
            )
        }
    };
    if !factors.is_empty() && t_end <= 0.0 {
        let last = factors.iter().max_by(|a, b| a.last_time().total_cmp(&b.last_time())).expect("tables");
        return Err(src.error(
            &span_of_name(&raw_tables, &last.name),
            format!("the tables of [evolution.factor] end at t = {t_end}, but a load path must end after t = 0"),
            "unnamed loads follow t / t_end, the end being the latest last time of the tables: let the tables \
             run to a positive time",
        ));
    }

    let start = match &e.start {
        Some(v) => {
            let s = src.number(v, "start")?;
            if s < lo || s >= hi {
                let message = match s < lo {
                    true => format!("`start` = {} is before the beginning of the load path, {lo}", src.written(v)),
                    false => format!("`start` = {} is not before the end of the load path, {hi}", src.written(v)),
                };
                return Err(src.error(&v.span(), message, format!("give a start in [{lo}, {hi}): {}", span_text(s))));
            }
            s
        }
        None => lo,
    };

    let times = match (&e.steps, &e.times) {
        (Some(s), Some(t)) => {
            let later = if s.span().start > t.span().start { s } else { t };
            return Err(src.error(
                &later.span(),
                "[evolution] gives both `steps` and `times`",
                "keep one: steps = N for N equal increments (the tables' times inserted), or times = [...] for \
                 the increments' end times",
            ));
        }
        (None, None) => {
            return Err(src.error(
                &table.span,
                "[evolution] has neither `steps` nor `times`",
                "add steps = 20 (equal increments over the path) or times = [0.5, 1.0] (the increments' end times)",
            ));
        }
        (Some(v), None) => {
            let n = steps(src, v)?;
            generated_times(start, t_end, n, &factors)
        }
        (None, Some(v)) => listed_times(src, v, start, hi, &span_text)?,
    };

    let (monitor, monitor_at) = match &e.monitor {
        Some(v) => {
            let part = src.nonempty_string(v, "monitor")?;
            if !bodies.is_empty() {
                monitor_body(src, v, part, bodies)?;
            }
            (Some(part.to_string()), Some(src.location(v.span().start)))
        }
        None => (None, None),
    };

    let profiles = match &e.profiles {
        Some(v) => profile_times(src, v, &times, start)?,
        None => times.last().copied().into_iter().collect(),
    };

    Ok(EvolutionSpec { start, times, factors, monitor, monitor_at, profiles, at })
}

fn span_of_name(tables: &[(&String, &Spanned<Value>)], name: &str) -> Range<usize> {
    tables.iter().find(|(n, _)| n.as_str() == name).map_or(0..0, |(_, v)| v.span())
}

/// A number of a table row (an integer or a finite float).
fn row_number(x: &Value) -> Option<f64> {
    match x {
        Value::Float(x) if x.is_finite() => Some(*x),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    }
}

fn load_function(src: &Source, name: &str, v: &Spanned<Value>) -> Result<LoadFunction> {
    let example = format!("`{name} = [[0.0, 0.0], [1.0, 1.0]]` (rows [t, factor])");
    let Value::Array(rows) = v.get_ref() else {
        return Err(src.error(
            &v.span(),
            format!("the factor table `{name}` must be an array of rows [t, factor], found {}", describe(v.get_ref())),
            format!("write e.g. {example}"),
        ));
    };
    let mut points: Vec<[f64; 2]> = Vec::with_capacity(rows.len());
    for (i, row) in rows.iter().enumerate() {
        let point = match row {
            Value::Array(xy) if xy.len() == 2 => row_number(&xy[0]).zip(row_number(&xy[1])).map(|(t, f)| [t, f]),
            _ => None,
        };
        let Some(p) = point else {
            return Err(src.error(
                &v.span(),
                format!(
                    "row {} of the factor table `{name}` must be [t, factor], two finite numbers, found {}",
                    i + 1,
                    describe(row)
                ),
                format!("write each row as two numbers in brackets, e.g. {example}"),
            ));
        };
        if let Some(previous) = points.last() {
            if p[0] <= previous[0] {
                return Err(src.error(
                    &v.span(),
                    format!(
                        "row {} of the factor table `{name}` has t = {}, not after row {}'s t = {}",
                        i + 1,
                        p[0],
                        i,
                        previous[0]
                    ),
                    "the times of a factor table must increase strictly from row to row (a jump is two rows \
                     close in time)",
                ));
            }
        }
        points.push(p);
    }
    if points.len() < 2 {
        return Err(src.error(
            &v.span(),
            format!("the factor table `{name}` has {} row{}: it needs at least 2", points.len(), plural(points.len())),
            format!("give the factor at two times at least, e.g. {example}"),
        ));
    }
    Ok(LoadFunction { name: name.to_string(), points, at: src.location(v.span().start) })
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// Every table names a load, every named load has a table.
fn check_names(src: &Source, tables: &[(&String, &Spanned<Value>)], names: &[(String, Range<usize>)]) -> Result<()> {
    let mut distinct: Vec<&str> = Vec::new();
    for (n, _) in names {
        if !distinct.contains(&n.as_str()) {
            distinct.push(n);
        }
    }
    for (name, v) in tables {
        if distinct.contains(&name.as_str()) {
            continue;
        }
        let list = match distinct.is_empty() {
            true => "no load of the scene has a name: add name = \"...\" to the [[traction]], [[dirichlet]], [loads] \
                     or [contact] (its motion) this table should multiply"
                .to_string(),
            false => format!("the loads are named {}", distinct.join(", ")),
        };
        let hint = match closest(name, &distinct) {
            Some(guess) => format!("did you mean `{guess}`? {list}"),
            None => list,
        };
        return Err(src.error(&v.span(), format!("a table for an unknown load `{name}`"), hint));
    }
    for (name, span) in names {
        if tables.iter().any(|(n, _)| n == &name) {
            continue;
        }
        let written: Vec<&str> = tables.iter().map(|(n, _)| n.as_str()).collect();
        let hint = match closest(name, &written) {
            Some(guess) => format!(
                "did you mean `{guess}`, which has a table? Otherwise add `{name} = [[0.0, 0.0], [1.0, 1.0]]` to \
                 [evolution.factor], or remove the name to ramp the load proportionally (t / t_end)"
            ),
            None => format!(
                "add `{name} = [[0.0, 0.0], [1.0, 1.0]]` (rows [t, factor]) to [evolution.factor], or remove the \
                 name to ramp the load proportionally (t / t_end)"
            ),
        };
        return Err(src.error(span, format!("no table for load `{name}` in [evolution.factor]"), hint));
    }
    Ok(())
}

fn steps(src: &Source, v: &Spanned<Value>) -> Result<usize> {
    let hint = "give the number of equal increments, a whole number ≥ 1, e.g. steps = 20 (or list the increments' \
                end times: times = [...])";
    match v.get_ref() {
        Value::Integer(n) if *n >= 1 && (*n as u64) <= MAX_STEPS as u64 => Ok(*n as usize),
        Value::Integer(n) if *n >= 1 => Err(src.error(
            &v.span(),
            format!("`steps` = {n} is more than {MAX_STEPS} increments"),
            "give fewer steps (each increment is a contact solve)",
        )),
        Value::Integer(n) => Err(src.error(&v.span(), format!("`steps` must be at least 1, found {n}"), hint)),
        other => Err(src.error(&v.span(), format!("`steps` must be a whole number, found {}", describe(other)), hint)),
    }
}

/// `n` equal increments over `[start, end]`, every table time inside `(start, end)` inserted.
fn generated_times(start: f64, end: f64, n: usize, factors: &[LoadFunction]) -> Vec<f64> {
    let length = end - start;
    let tolerance = TIME_TOLERANCE * length;
    let mut times: Vec<f64> =
        (1..=n).map(|k| if k == n { end } else { start + length * (k as f64 / n as f64) }).collect();
    let mut breakpoints: Vec<f64> = factors
        .iter()
        .flat_map(|f| f.points.iter().map(|p| p[0]))
        .filter(|&t| t > start + tolerance && t < end - tolerance)
        .collect();
    breakpoints.sort_by(f64::total_cmp);
    breakpoints.dedup();
    for b in breakpoints {
        let i = times.partition_point(|&t| t < b);
        let near = |j: usize| times.get(j).is_some_and(|&t| (t - b).abs() <= tolerance);
        match (i > 0 && near(i - 1), near(i)) {
            (true, _) => times[i - 1] = b,
            (_, true) => times[i] = b,
            _ => times.insert(i, b),
        }
    }
    times.dedup();
    times
}

fn listed_times(
    src: &Source,
    v: &Spanned<Value>,
    start: f64,
    end: f64,
    span_text: &dyn Fn(f64) -> String,
) -> Result<Vec<f64>> {
    let hint_list = "list the increments' end times in increasing order, all after `start`, e.g. times = [0.5, 1.0]";
    let Value::Array(items) = v.get_ref() else {
        return Err(src.error(
            &v.span(),
            format!("`times` must be an array of numbers, found {}", describe(v.get_ref())),
            hint_list,
        ));
    };
    if items.is_empty() {
        return Err(src.error(&v.span(), "`times` is empty: the path has no increment", hint_list));
    }
    let mut times = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let Some(t) = row_number(item) else {
            return Err(src.error(
                &v.span(),
                format!("`times[{i}]` must be a finite number, found {}", describe(item)),
                hint_list,
            ));
        };
        if let Some(&previous) = times.last() {
            if t <= previous {
                return Err(src.error(
                    &v.span(),
                    format!(
                        "`times` must increase strictly: times[{i}] = {t} is not after times[{}] = {previous}",
                        i - 1
                    ),
                    hint_list,
                ));
            }
        } else if t <= start {
            return Err(src.error(
                &v.span(),
                format!("`times[0]` = {t} is not after the start of the path, {start}"),
                "every increment ends after `start` (the initial state): drop it, or give an earlier `start`",
            ));
        }
        if t > end {
            return Err(src.error(
                &v.span(),
                format!("`times[{i}]` = {t} is after the end of the load path, {end}"),
                format!("every increment time lies where the factors are given: {}", span_text(t)),
            ));
        }
        times.push(t);
    }
    Ok(times)
}

/// `monitor = "body.part"` of a scene with `[[body]]` tables names a body (its part is checked
/// once the mesh exists).
fn monitor_body(src: &Source, v: &Spanned<Value>, text: &str, bodies: &[&str]) -> Result<()> {
    let Some((body, _)) = text.split_once('.').filter(|(b, p)| !b.is_empty() && !p.is_empty()) else {
        return Err(src.error(
            &v.span(),
            format!("`monitor` must name a body and one of its boundary parts as \"body.part\", found \"{text}\""),
            format!("write e.g. `monitor = \"{}.top\"`; the bodies are: {}", bodies[0], bodies.join(", ")),
        ));
    };
    if bodies.contains(&body) {
        return Ok(());
    }
    let known = format!("the bodies are: {}", bodies.join(", "));
    let hint = match closest(body, bodies) {
        Some(guess) => format!("did you mean `{guess}`? {known}"),
        None => known,
    };
    Err(src.error(&v.span(), format!("`monitor` names an unknown body `{body}`"), hint))
}

/// `profiles`: increment times (each snapped to the increment it matches), sorted, distinct.
fn profile_times(src: &Source, v: &Spanned<Value>, times: &[f64], start: f64) -> Result<Vec<f64>> {
    let hint = "give increment times, e.g. profiles = [1.0, 2.0] (or leave `profiles` out for the end of the path)";
    let Value::Array(items) = v.get_ref() else {
        return Err(src.error(
            &v.span(),
            format!("`profiles` must be an array of numbers, found {}", describe(v.get_ref())),
            hint,
        ));
    };
    let end = times.last().copied().unwrap_or(start);
    let tolerance = TIME_TOLERANCE * (end - start);
    let mut out = Vec::with_capacity(items.len());
    for (i, item) in items.iter().enumerate() {
        let Some(t) = row_number(item) else {
            return Err(src.error(
                &v.span(),
                format!("`profiles[{i}]` must be a finite number, found {}", describe(item)),
                hint,
            ));
        };
        let nearest = times.iter().copied().min_by(|a, b| (a - t).abs().total_cmp(&(b - t).abs())).unwrap_or(end);
        if (nearest - t).abs() > tolerance {
            return Err(src.error(
                &v.span(),
                format!("`profiles[{i}]` = {t} is not an increment time of the path"),
                format!(
                    "profiles are plotted at the end of increments: the nearest is t = {nearest} (the increments \
                     end at {})",
                    shown_times(times)
                ),
            ));
        }
        out.push(nearest);
    }
    out.sort_by(f64::total_cmp);
    out.dedup();
    Ok(out)
}

/// The times of a path for a message: all of them if few, else the first and last three.
fn shown_times(times: &[f64]) -> String {
    let text = |ts: &[f64]| ts.iter().map(|t| t.to_string()).collect::<Vec<_>>().join(", ");
    match times.len() > 8 {
        true => format!("{}, ..., {}", text(&times[..3]), text(&times[times.len() - 3..])),
        false => text(times),
    }
}
