//! The files of a load path's history, from its [`StepRecord`]s and [`ContactProfile`]s:
//!
//! - `history.csv` ([`HISTORY_CSV`]): one row per increment, the columns of
//!   [`HISTORY_CSV_HEADER`] (units in the names: `_N_per_m` force per metre of thickness,
//!   `_J_per_m` energy per metre of thickness — `_N` and `_J` for the full revolution of a body
//!   of revolution, [`Measure`] — `_m` metres, `seconds` wall clock; `time` is the
//!   load path's pseudo-time), numbers with `{:e}` (the shortest decimal that reads back to the
//!   same `f64`); with an interface law the columns of [`HISTORY_CSV_INTERFACE_COLUMNS`] follow
//!   (the interface's summary at each increment, `crate::output::interface::InterfaceSummary`;
//!   an empty cell where no law of the run has the variable);
//! - `hysteresis.svg` ([`HYSTERESIS_SVG`]): the tangential contact force against the monitored
//!   tangential displacement, one line through the increments in their order (a loading and
//!   unloading cycle draws the loop; the points are never sorted), a marker at each increment;
//! - `contact_profiles.svg` ([`CONTACT_PROFILES_SVG`]): two panels side by side, the contact
//!   pressure (left) and the tangential traction (right) against the abscissa along the contact
//!   part, one line per recorded profile, labelled with its time and increment.
//!
//! A record with a non-finite number is refused before anything is written (a NaN in a csv
//! reads as a number in some tools and as text in others), naming the increment and the field.
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::{ContactProfile, StepRecord};
use crate::error::{Error, Result};
use crate::mesh::Measure;
use crate::output::interface::{write_tau_delta_svg, InterfaceHistory, TAU_DELTA_SVG};
use crate::output::plot::{write_linear_panels_svg, write_linear_styled_svg, Panel, Series, Style};
use crate::output::{all_or_nothing, write_atomically};

/// The history file's name in the output directory.
pub const HISTORY_CSV: &str = "history.csv";
/// The hysteresis plot's name in the output directory.
pub const HYSTERESIS_SVG: &str = "hysteresis.svg";
/// The contact profiles plot's name in the output directory.
pub const CONTACT_PROFILES_SVG: &str = "contact_profiles.svg";

/// The files [`write_load_path_outputs`] may write in the output directory (for clearing a
/// previous run's results).
pub const LOAD_PATH_FILES: [&str; 3] = [HISTORY_CSV, HYSTERESIS_SVG, CONTACT_PROFILES_SVG];

/// The columns of `history.csv`, in order (one per field of [`StepRecord`], the contact
/// resultant split into x and y; `estimate_percent` empty when no estimate was asked for).
pub const HISTORY_CSV_HEADER: &str = "step,time,halvings,contact_x_N_per_m,contact_y_N_per_m,normal_N_per_m,\
tangential_N_per_m,open,stick,slip,closed,iterations,worst_residual,dissipation_J_per_m,total_dissipation_J_per_m,\
work_J_per_m,stored_energy_J_per_m,monitor_displacement_m,estimate_percent,seconds";

/// The columns a run with an interface law adds after [`HISTORY_CSV_HEADER`]'s (the
/// [`InterfaceSummary`](crate::output::interface::InterfaceSummary) of each increment; a cell is empty when no law of the run has the
/// variable: `interface_min_adhesion` without RCCM, `interface_max_damage` without a joint).
pub const HISTORY_CSV_INTERFACE_COLUMNS: &str = "interface_min_adhesion,interface_max_damage,interface_max_opening_m,\
interface_max_slip_m,interface_worst_law_residual";

/// The real-valued fields of a record, named as in [`StepRecord`], in the csv's order.
fn real_fields(s: &StepRecord) -> [(&'static str, f64); 13] {
    [
        ("time", s.time),
        ("contact_resultant[0]", s.contact_resultant[0]),
        ("contact_resultant[1]", s.contact_resultant[1]),
        ("normal_resultant", s.normal_resultant),
        ("tangential_resultant", s.tangential_resultant),
        ("worst_residual", s.worst_residual),
        ("dissipation", s.dissipation),
        ("total_dissipation", s.total_dissipation),
        ("work", s.work),
        ("stored_energy", s.stored_energy),
        ("monitor_displacement", s.monitor_displacement),
        ("estimate_percent", s.estimate_percent.unwrap_or(0.0)),
        ("seconds", s.seconds),
    ]
}

/// [`Error::Output`] for `path`: nothing was written.
fn refused(path: &Path, message: String) -> Error {
    Error::Output {
        path: path.to_path_buf(),
        message: format!("{message} (nothing was written; an existing file at this path is unchanged)"),
    }
}

/// No steps: [`Error::Usage`] naming the file that would have been written.
fn check_some_steps(path: &Path, steps: &[StepRecord]) -> Result<()> {
    if steps.is_empty() {
        return Err(Error::Usage(format!(
            "{}: a load path's history needs at least one increment, none was given (nothing was written)",
            path.display()
        )));
    }
    Ok(())
}

/// Every real number of every record finite, else [`Error::Output`] naming the step and field.
fn check_finite(path: &Path, steps: &[StepRecord]) -> Result<()> {
    check_some_steps(path, steps)?;
    for s in steps {
        if let Some((field, value)) = real_fields(s).into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(refused(
                path,
                format!("step {}: {field} is {value}, not a finite number: the increment's record is invalid", s.step),
            ));
        }
    }
    Ok(())
}

/// Write `history.csv`: the header [`HISTORY_CSV_HEADER`], then one row per step in the order
/// given, atomically. Errors: no step ([`Error::Usage`]); a non-finite number
/// ([`Error::Output`] naming the step and the field); nothing is written then.
pub fn write_history_csv(path: &Path, steps: &[StepRecord]) -> Result<()> {
    write_history_csv_with_interface(path, steps, None)
}

/// [`write_history_csv`] with the interface's columns ([`HISTORY_CSV_INTERFACE_COLUMNS`]) after
/// the others when `interface` is given: each row the sample of its increment (empty cells for
/// an increment without one). A non-finite interface value is refused as a record's is.
pub fn write_history_csv_with_interface(
    path: &Path,
    steps: &[StepRecord],
    interface: Option<&InterfaceHistory>,
) -> Result<()> {
    write_history_csv_in(path, steps, interface, Measure::Plane)
}

/// `header` with the unit suffixes of `measure`: `_N_per_m`, `_J_per_m` per metre of thickness
/// (plane), `_N`, `_J` for the full revolution of a body of revolution.
fn units_of(measure: Measure, header: &str) -> String {
    match measure {
        Measure::Plane => header.to_string(),
        Measure::Axisymmetric => header.replace("_N_per_m", "_N").replace("_J_per_m", "_J"),
    }
}

/// [`write_history_csv_with_interface`] with the column names of `measure` (plane: per metre of
/// thickness; axisymmetric: the full revolution).
pub fn write_history_csv_in(
    path: &Path,
    steps: &[StepRecord],
    interface: Option<&InterfaceHistory>,
    measure: Measure,
) -> Result<()> {
    check_finite(path, steps)?;
    if let Some(history) = interface {
        check_interface_finite(path, history)?;
    }
    let mut text = String::with_capacity(200 * (steps.len() + 1));
    let header = units_of(measure, HISTORY_CSV_HEADER);
    match interface {
        Some(_) => {
            let _ = writeln!(text, "{header},{}", units_of(measure, HISTORY_CSV_INTERFACE_COLUMNS));
        }
        None => {
            let _ = writeln!(text, "{header}");
        }
    }
    for s in steps {
        let _ = write!(
            text,
            "{},{:e},{},{:e},{:e},{:e},{:e},{},{},{},{},{},{:e},{:e},{:e},{:e},{:e},{:e},{},{:e}",
            s.step,
            s.time,
            s.halvings,
            s.contact_resultant[0],
            s.contact_resultant[1],
            s.normal_resultant,
            s.tangential_resultant,
            s.open,
            s.stick,
            s.slip,
            s.closed,
            s.iterations,
            s.worst_residual,
            s.dissipation,
            s.total_dissipation,
            s.work,
            s.stored_energy,
            s.monitor_displacement,
            s.estimate_percent.map_or(String::new(), |e| format!("{e:e}")),
            s.seconds,
        );
        if let Some(history) = interface {
            let cell = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:e}"));
            let summary = history.at(s.step).map(|sample| &sample.summary);
            let _ = write!(
                text,
                ",{},{},{},{},{}",
                cell(summary.and_then(|m| m.min_adhesion)),
                cell(summary.and_then(|m| m.max_damage)),
                cell(summary.map(|m| m.max_opening)),
                cell(summary.map(|m| m.max_slip)),
                cell(summary.map(|m| m.worst_law_residual)),
            );
        }
        text.push('\n');
    }
    write_atomically(path, |w| w.write_all(text.as_bytes()))
}

/// Every number of the interface's samples finite, else [`Error::Output`] naming the increment.
fn check_interface_finite(path: &Path, history: &InterfaceHistory) -> Result<()> {
    for sample in &history.steps {
        let m = &sample.summary;
        let values = [
            ("interface_min_adhesion", m.min_adhesion.unwrap_or(0.0)),
            ("interface_max_damage", m.max_damage.unwrap_or(0.0)),
            ("interface_max_opening_m", m.max_opening),
            ("interface_max_slip_m", m.max_slip),
            ("interface_worst_law_residual", m.worst_law_residual),
        ];
        if let Some((field, value)) = values.into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(refused(
                path,
                format!(
                    "step {}: {field} is {value}, not a finite number: the interface's record is invalid",
                    sample.step
                ),
            ));
        }
    }
    Ok(())
}

/// Write `hysteresis.svg`: the tangential contact force ([`StepRecord::tangential_resultant`],
/// N/m) against the monitored tangential displacement ([`StepRecord::monitor_displacement`], m),
/// linear axes, one line through the steps in the order given (not sorted) with a marker at
/// each, atomically. Errors as [`write_history_csv`].
pub fn write_hysteresis_svg(path: &Path, title: &str, steps: &[StepRecord]) -> Result<()> {
    write_hysteresis_svg_in(path, title, steps, Measure::Plane)
}

/// [`write_hysteresis_svg`] with the force unit of `measure` on its axis.
pub fn write_hysteresis_svg_in(path: &Path, title: &str, steps: &[StepRecord], measure: Measure) -> Result<()> {
    check_finite(path, steps)?;
    let (first, last) = (steps[0].step, steps[steps.len() - 1].step);
    let series = Series {
        label: format!("increments {first} to {last}, in order"),
        points: steps.iter().map(|s| (s.monitor_displacement, s.tangential_resultant)).collect(),
    };
    write_linear_styled_svg(
        path,
        title,
        "tangential displacement of the monitored part (m)",
        &format!("tangential contact force ({})", measure.force_unit()),
        &[series],
        &[Style::LineAndMarkers],
    )
}

/// A time for a legend: 6 significant digits at most, without trailing zeros (`0.3`, not
/// `0.30000000000000004`); e-notation outside `[1e-4, 1e6)`.
fn short_number(v: f64) -> String {
    let rounded: f64 = format!("{v:.5e}").parse().unwrap_or(v);
    if rounded == 0.0 || (1e-4..1e6).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// The legend label of a profile: `t = 0.25 (increment 10)`.
fn profile_label(p: &ContactProfile) -> String {
    format!("t = {} (increment {})", short_number(p.time), p.step)
}

/// Each profile's columns of one length and finite, else [`Error::Output`] naming the profile.
fn check_profiles(path: &Path, profiles: &[ContactProfile]) -> Result<()> {
    if profiles.is_empty() {
        return Err(Error::Usage(format!(
            "{}: no contact profile to plot, none was given (nothing was written)",
            path.display()
        )));
    }
    for p in profiles {
        let n = p.abscissa.len();
        let lengths = [("pressure", p.pressure.len()), ("traction", p.traction.len()), ("state", p.state.len())];
        if let Some((field, len)) = lengths.into_iter().find(|&(_, len)| len != n) {
            return Err(refused(
                path,
                format!("profile of step {}: {field} has {len} values for {n} abscissae", p.step),
            ));
        }
        if !p.time.is_finite() {
            return Err(refused(path, format!("profile of step {}: time is {}, not a finite number", p.step, p.time)));
        }
        let columns = [("abscissa", &p.abscissa), ("pressure", &p.pressure), ("traction", &p.traction)];
        for (field, values) in columns {
            if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(refused(
                    path,
                    format!("profile of step {}: {field}[{i}] is {v}, not a finite number", p.step),
                ));
            }
        }
    }
    Ok(())
}

/// Write `contact_profiles.svg`: two linear plots side by side (1600×560), the contact pressure
/// (Pa, compression positive) and the tangential traction (Pa) against the abscissa along the
/// contact part (m), one line with markers per profile, labelled `t = … (increment …)`,
/// atomically. Errors: no profile ([`Error::Usage`]); columns of different lengths or a
/// non-finite number ([`Error::Output`] naming the profile's step and the field).
pub fn write_profiles_svg(path: &Path, title: &str, profiles: &[ContactProfile]) -> Result<()> {
    check_profiles(path, profiles)?;
    let series = |values: fn(&ContactProfile) -> &Vec<f64>| -> Vec<Series> {
        profiles
            .iter()
            .map(|p| Series {
                label: profile_label(p),
                points: p.abscissa.iter().copied().zip(values(p).iter().copied()).collect(),
            })
            .collect()
    };
    let (pressure, traction) = (series(|p| &p.pressure), series(|p| &p.traction));
    let (pressure_title, traction_title) =
        (format!("{title}: contact pressure"), format!("{title}: tangential traction"));
    let x_label = "abscissa along the contact part (m)";
    let panels = [
        Panel { title: &pressure_title, x_label, y_label: "contact pressure (Pa)", series: &pressure },
        Panel { title: &traction_title, x_label, y_label: "tangential traction (Pa)", series: &traction },
    ];
    write_linear_panels_svg(path, &panels, Style::LineAndMarkers)
}

/// Write the history files of a load path into `dir`: [`HISTORY_CSV`], [`HYSTERESIS_SVG`] and,
/// when `profiles` is not empty, [`CONTACT_PROFILES_SVG`]; all of them or none
/// ([`all_or_nothing`]). Returns the paths written, in that order. `title` heads the plots
/// (the scene's name, say). Errors as [`write_history_csv`] and [`write_profiles_svg`].
pub fn write_load_path_outputs(
    dir: &Path,
    steps: &[StepRecord],
    profiles: &[ContactProfile],
    title: &str,
) -> Result<Vec<PathBuf>> {
    write_load_path_outputs_with_interface(dir, steps, profiles, title, None)
}

/// [`write_load_path_outputs`] with an interface law's history: its columns in
/// [`HISTORY_CSV`] ([`write_history_csv_with_interface`]) and, when it traces points,
/// `interface_tau_delta.svg` ([`crate::output::interface::write_tau_delta_svg`]) after the
/// other files; all of them or none.
pub fn write_load_path_outputs_with_interface(
    dir: &Path,
    steps: &[StepRecord],
    profiles: &[ContactProfile],
    title: &str,
    interface: Option<&InterfaceHistory>,
) -> Result<Vec<PathBuf>> {
    write_load_path_outputs_in(dir, steps, profiles, title, interface, Measure::Plane)
}

/// [`write_load_path_outputs_with_interface`] with the units of `measure` in the column names
/// and axis labels.
pub fn write_load_path_outputs_in(
    dir: &Path,
    steps: &[StepRecord],
    profiles: &[ContactProfile],
    title: &str,
    interface: Option<&InterfaceHistory>,
    measure: Measure,
) -> Result<Vec<PathBuf>> {
    let csv = dir.join(HISTORY_CSV);
    check_finite(&csv, steps)?;
    if let Some(history) = interface {
        check_interface_finite(&csv, history)?;
    }
    if !profiles.is_empty() {
        check_profiles(&dir.join(CONTACT_PROFILES_SVG), profiles)?;
    }
    all_or_nothing(|| {
        let mut written = Vec::with_capacity(4);
        write_history_csv_in(&csv, steps, interface, measure)?;
        written.push(csv.clone());
        let hysteresis = dir.join(HYSTERESIS_SVG);
        write_hysteresis_svg_in(
            &hysteresis,
            &format!("{title}: tangential load against displacement"),
            steps,
            measure,
        )?;
        written.push(hysteresis);
        if !profiles.is_empty() {
            let path = dir.join(CONTACT_PROFILES_SVG);
            write_profiles_svg(&path, title, profiles)?;
            written.push(path);
        }
        if let Some(history) = interface.filter(|h| !h.steps.is_empty() && !h.trace_points.is_empty()) {
            let path = dir.join(TAU_DELTA_SVG);
            write_tau_delta_svg(&path, title, history)?;
            written.push(path);
        }
        Ok(written)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report::contact::ContactState;

    fn scratch(test: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("signorini-history-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = match std::fs::read_dir(dir) {
            Ok(it) => it.map(|e| e.unwrap().file_name().to_string_lossy().to_string()).collect(),
            Err(_) => Vec::new(),
        };
        names.sort();
        names
    }

    /// Increment `k` of a made-up cycle: the displacement goes 0 → 1 → −1 → 1 (in µm), the
    /// force follows with a lag, so x goes back and forth; awkward values in every column.
    fn record(k: usize) -> StepRecord {
        let displacement = [0.0, 0.5, 1.0, 0.5, 0.0, -0.5, -1.0, -0.5, 0.0, 0.5, 1.0];
        let force = [0.0, 300.0, 500.0, 200.0, -100.0, -400.0, -500.0, -200.0, 100.0, 400.0, 500.0];
        let i = k % displacement.len();
        StepRecord {
            step: k + 1,
            time: (k + 1) as f64 / 30.0,
            halvings: k % 3,
            contact_resultant: [force[i] + 1.0 / 3.0, -2.5e6 - k as f64 * 1e-9],
            normal_resultant: -2.5e6 * (1.0 + 1e-16 * k as f64),
            tangential_resultant: force[i],
            open: 30 - k,
            stick: k,
            slip: 2 * k,
            closed: 0,
            iterations: 3 + k,
            worst_residual: 3.2e-11 * (k as f64 + 0.1),
            dissipation: if k == 0 { -0.0 } else { 1e-300 * k as f64 },
            total_dissipation: 0.1 + 0.2 * k as f64,
            work: std::f64::consts::PI * 1e300,
            stored_energy: f64::MIN_POSITIVE,
            monitor_displacement: displacement[i] * 1e-6,
            estimate_percent: (k % 2 == 1).then_some(0.25 + k as f64 * 1e-3),
            seconds: 0.08 + k as f64 * 1e-3,
        }
    }

    fn cycle() -> Vec<StepRecord> {
        (0..11).map(record).collect()
    }

    fn profile(step: usize, time: f64, scale: f64) -> ContactProfile {
        let abscissa: Vec<f64> = (0..9).map(|i| -0.4 + 0.1 * i as f64).collect();
        ContactProfile {
            step,
            time,
            pressure: abscissa.iter().map(|x| scale * (0.16 - x * x).max(0.0)).collect(),
            traction: abscissa.iter().map(|x| scale * 0.3 * x).collect(),
            state: abscissa
                .iter()
                .map(|x| if x.abs() < 0.35 { ContactState::Stick } else { ContactState::Open })
                .collect(),
            abscissa,
        }
    }

    /// The line paths (`fill="none" stroke-width="2"`) of an SVG, each as its points in order.
    fn lines(svg: &str) -> Vec<Vec<(f64, f64)>> {
        svg.lines()
            .filter(|l| l.starts_with("<path d=\"M") && l.ends_with("fill=\"none\" stroke-width=\"2\"/>"))
            .map(|l| {
                let d = l["<path d=\"".len()..].split('"').next().unwrap();
                d.split(['M', 'L'])
                    .filter(|p| !p.trim().is_empty())
                    .map(|p| {
                        let (x, y) = p.trim().split_once(',').unwrap();
                        (x.parse().unwrap(), y.parse().unwrap())
                    })
                    .collect()
            })
            .collect()
    }

    /// `pixels` are `data` through one affine map per axis, x growing to the right and y
    /// upwards (pixel y downwards), to the 0.01 px of the file's two decimals.
    fn assert_affine_image(data: &[(f64, f64)], pixels: &[(f64, f64)]) {
        assert_eq!(data.len(), pixels.len());
        for axis in 0..2 {
            let get = |p: &(f64, f64)| if axis == 0 { p.0 } else { p.1 };
            let (lo, hi) = (0..data.len()).fold((0, 0), |(lo, hi), i| {
                (
                    if get(&data[i]) < get(&data[lo]) { i } else { lo },
                    if get(&data[i]) > get(&data[hi]) { i } else { hi },
                )
            });
            let slope = (get(&pixels[hi]) - get(&pixels[lo])) / (get(&data[hi]) - get(&data[lo]));
            assert!(if axis == 0 { slope > 0.0 } else { slope < 0.0 }, "axis {axis}: slope {slope}");
            for (d, p) in data.iter().zip(pixels) {
                let expected = get(&pixels[lo]) + slope * (get(d) - get(&data[lo]));
                assert!((get(p) - expected).abs() <= 0.02, "axis {axis}: {p:?} for {d:?}, expected {expected}");
            }
        }
    }

    #[test]
    fn history_csv_reads_back_exactly() {
        let dir = scratch("csv");
        let path = dir.join(HISTORY_CSV);
        let steps = cycle();
        write_history_csv(&path, &steps).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        let mut rows = text.lines();
        let header: Vec<&str> = rows.next().unwrap().split(',').collect();
        assert_eq!(header.len(), 20);
        assert_eq!(header[0], "step");
        assert_eq!(header[6], "tangential_N_per_m");
        assert_eq!(header[17], "monitor_displacement_m");
        let rows: Vec<Vec<&str>> = rows.map(|r| r.split(',').collect()).collect();
        assert_eq!(rows.len(), steps.len());
        let real = |s: &str| s.parse::<f64>().unwrap().to_bits();
        let int = |s: &str| s.parse::<usize>().unwrap();
        for (row, s) in rows.iter().zip(&steps) {
            assert_eq!(row.len(), header.len());
            let read = StepRecord {
                step: int(row[0]),
                time: f64::from_bits(real(row[1])),
                halvings: int(row[2]),
                contact_resultant: [f64::from_bits(real(row[3])), f64::from_bits(real(row[4]))],
                normal_resultant: f64::from_bits(real(row[5])),
                tangential_resultant: f64::from_bits(real(row[6])),
                open: int(row[7]),
                stick: int(row[8]),
                slip: int(row[9]),
                closed: int(row[10]),
                iterations: int(row[11]),
                worst_residual: f64::from_bits(real(row[12])),
                dissipation: f64::from_bits(real(row[13])),
                total_dissipation: f64::from_bits(real(row[14])),
                work: f64::from_bits(real(row[15])),
                stored_energy: f64::from_bits(real(row[16])),
                monitor_displacement: f64::from_bits(real(row[17])),
                estimate_percent: (!row[18].is_empty()).then(|| f64::from_bits(real(row[18]))),
                seconds: f64::from_bits(real(row[19])),
            };
            assert_eq!(&read, s);
            // Bit for bit (PartialEq would take −0 for 0).
            let bits = |r: &StepRecord| real_fields(r).map(|(_, v)| v.to_bits());
            assert_eq!(bits(&read), bits(s), "step {}", s.step);
        }
        assert!(rows[0][13] == "-0e0", "{}", rows[0][13]);
        assert_eq!(entries(&dir), [HISTORY_CSV]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn non_finite_numbers_are_refused_naming_step_and_field() {
        let dir = scratch("nan");
        type Spoil = fn(&mut StepRecord);
        let cases: [(usize, Spoil, &str, &str); 4] = [
            (2, |s| s.worst_residual = f64::NAN, "worst_residual", "NaN"),
            (0, |s| s.contact_resultant[1] = f64::INFINITY, "contact_resultant[1]", "inf"),
            (10, |s| s.monitor_displacement = f64::NEG_INFINITY, "monitor_displacement", "-inf"),
            (5, |s| s.time = f64::NAN, "time", "NaN"),
        ];
        for (index, spoil, field, shown) in cases {
            let mut steps = cycle();
            spoil(&mut steps[index]);
            let expected = format!("step {}: {field} is {shown}, not a finite number", index + 1);
            let outcomes = [
                (dir.join(HISTORY_CSV), write_history_csv(&dir.join(HISTORY_CSV), &steps)),
                (dir.join(HYSTERESIS_SVG), write_hysteresis_svg(&dir.join(HYSTERESIS_SVG), "t", &steps)),
                (dir.join(HISTORY_CSV), write_load_path_outputs(&dir, &steps, &[], "t").map(|_| ())),
            ];
            for (target, outcome) in outcomes {
                match outcome {
                    Err(Error::Output { path, message }) => {
                        assert_eq!(path, target);
                        assert!(message.starts_with(&expected), "{message:?} does not start with {expected:?}");
                    }
                    other => panic!("{field}: expected an output error, got {other:?}"),
                }
            }
            assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
        }
    }

    #[test]
    fn no_steps_is_a_usage_error_and_writes_nothing() {
        let dir = scratch("empty");
        let outcomes = [
            write_history_csv(&dir.join(HISTORY_CSV), &[]),
            write_hysteresis_svg(&dir.join(HYSTERESIS_SVG), "t", &[]),
            write_profiles_svg(&dir.join(CONTACT_PROFILES_SVG), "t", &[]),
            write_load_path_outputs(&dir, &[], &[profile(1, 0.5, 1.0)], "t").map(|_| ()),
        ];
        for outcome in outcomes {
            match outcome {
                Err(Error::Usage(message)) => assert!(message.contains("none was given"), "{message}"),
                other => panic!("expected a usage error, got {other:?}"),
            }
        }
        assert!(entries(&dir).is_empty());
    }

    #[test]
    fn hysteresis_is_one_line_through_the_steps_in_order() {
        let dir = scratch("loop");
        let path = dir.join(HYSTERESIS_SVG);
        let steps = cycle();
        write_hysteresis_svg(&path, "Cattaneo–Mindlin <cycle>", &steps).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        let lines = lines(&svg);
        assert_eq!(lines.len(), 1, "{svg}");
        let data: Vec<(f64, f64)> = steps.iter().map(|s| (s.monitor_displacement, s.tangential_resultant)).collect();
        assert_affine_image(&data, &lines[0]);
        // Back and forth in x: the pixels are not sorted (the loop is drawn as it went).
        assert!(lines[0].windows(2).any(|w| w[1].0 < w[0].0) && lines[0].windows(2).any(|w| w[1].0 > w[0].0));
        // A circle at each step, and one in the legend.
        assert_eq!(svg.matches("<circle ").count(), steps.len() + 1);
        for text in [
            "Cattaneo–Mindlin &lt;cycle&gt;",
            "increments 1 to 11, in order",
            "tangential contact force (N/m)",
            "tangential displacement of the monitored part (m)",
        ] {
            assert!(svg.contains(&format!(">{text}</text>")), "missing {text:?}");
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn profiles_are_two_panels_with_one_labelled_line_per_profile() {
        let dir = scratch("profiles");
        let path = dir.join(CONTACT_PROFILES_SVG);
        let profiles = [profile(10, 0.25, 1e6), profile(30, 0.30000000000000004, -2e6)];
        write_profiles_svg(&path, "block", &profiles).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert!(svg.contains("width=\"1600\""));
        let lines = lines(&svg);
        // Left panel: the pressures; right panel: the tractions (same x map, own y map).
        assert_eq!(lines.len(), 4);
        for (k, p) in profiles.iter().enumerate() {
            let pressure: Vec<(f64, f64)> = p.abscissa.iter().copied().zip(p.pressure.iter().copied()).collect();
            let traction: Vec<(f64, f64)> = p.abscissa.iter().copied().zip(p.traction.iter().copied()).collect();
            assert_eq!(lines[k].len(), pressure.len());
            assert_eq!(lines[2 + k].len(), traction.len());
        }
        let both = |data: fn(&ContactProfile) -> &Vec<f64>, first: usize| {
            let d: Vec<(f64, f64)> =
                profiles.iter().flat_map(|p| p.abscissa.iter().copied().zip(data(p).iter().copied())).collect();
            let px: Vec<(f64, f64)> = lines[first].iter().chain(&lines[first + 1]).copied().collect();
            assert_affine_image(&d, &px);
        };
        both(|p| &p.pressure, 0);
        both(|p| &p.traction, 2);
        for text in [
            "t = 0.25 (increment 10)",
            "t = 0.3 (increment 30)",
            "block: contact pressure",
            "block: tangential traction",
        ] {
            assert!(svg.contains(&format!(">{text}</text>")), "missing {text:?}");
        }
        assert_eq!(svg.matches(">t = 0.3 (increment 30)</text>").count(), 2, "a legend in each panel");

        // A profile whose columns disagree, or with a NaN, is refused.
        let mut short = profile(7, 0.5, 1.0);
        short.traction.pop();
        let mut nan = profile(8, 0.5, 1.0);
        nan.pressure[3] = f64::NAN;
        for (bad, expected) in [
            (short, "profile of step 7: traction has 8 values for 9 abscissae"),
            (nan, "profile of step 8: pressure[3] is NaN"),
        ] {
            let target = dir.join("bad.svg");
            match write_profiles_svg(&target, "b", &[profile(1, 0.1, 1.0), bad]) {
                Err(Error::Output { path, message }) => {
                    assert_eq!(path, target);
                    assert!(message.starts_with(expected), "{message}");
                }
                other => panic!("expected an output error, got {other:?}"),
            }
        }
        assert_eq!(entries(&dir), [CONTACT_PROFILES_SVG]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn load_path_outputs_are_written_together_or_not_at_all() {
        let dir = scratch("all");
        let steps = cycle();
        let written = write_load_path_outputs(&dir, &steps, &[profile(3, 0.1, 1e6)], "block").unwrap();
        assert_eq!(written, [dir.join(HISTORY_CSV), dir.join(HYSTERESIS_SVG), dir.join(CONTACT_PROFILES_SVG)]);
        assert_eq!(entries(&dir), [CONTACT_PROFILES_SVG, HISTORY_CSV, HYSTERESIS_SVG]);
        std::fs::remove_dir_all(&dir).unwrap();

        let written = write_load_path_outputs(&dir, &steps, &[], "block").unwrap();
        assert_eq!(written, [dir.join(HISTORY_CSV), dir.join(HYSTERESIS_SVG)]);
        std::fs::remove_dir_all(&dir).unwrap();

        // A bad profile: not even the csv appears.
        let mut bad = profile(3, 0.1, 1e6);
        bad.abscissa[0] = f64::INFINITY;
        match write_load_path_outputs(&dir, &steps, &[bad], "block") {
            Err(Error::Output { path, message }) => {
                assert_eq!(path, dir.join(CONTACT_PROFILES_SVG));
                assert!(message.starts_with("profile of step 3: abscissa[0] is inf"), "{message}");
            }
            other => panic!("expected an output error, got {other:?}"),
        }
        assert!(entries(&dir).is_empty());
    }

    #[test]
    fn legend_times_are_short() {
        assert_eq!(short_number(0.30000000000000004), "0.3");
        assert_eq!(short_number(0.075), "0.075");
        assert_eq!(short_number(1.0), "1");
        assert_eq!(short_number(0.0), "0");
        assert_eq!(short_number(2.5e-7), "2.5e-7");
        assert_eq!(short_number(1.0 / 3.0), "0.333333");
        assert_eq!(short_number(123456789.0), "1.23457e8");
    }
}
