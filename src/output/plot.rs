//! Dependency-free SVG line plots: log-log, for benchmark results (time or error against size),
//! and linear ([`write_linear_styled_svg`]), for fields along a line and load paths (a
//! hysteresis loop: the line joins the points in the order given, never sorted).
//!
//! A value `v > 0` is placed on an axis spanning the decades `10^lo .. 10^hi` at
//!
//! ```text
//!   pixel(v) = start + (log10(v) - lo) / (hi - lo) * length
//! ```
//!
//! (the y axis runs upwards, so its pixel is measured from the bottom). `lo` and `hi` are whole
//! decades enclosing every plotted point, so each axis has at least two labelled decade ticks;
//! minor ticks mark 2..9 × 10^k when there are few decades. Points with a non-positive or
//! non-finite coordinate cannot be placed on a log axis: they are skipped and break the
//! series' line there.
//!
//! ```text
//!          title
//!   10^2 ┤ ○──○                ┌──────────┐   legend in the plot corner
//!        │     ╲               │ ○─ serie │   that covers the fewest data
//!   10^1 ┤      ○──○           └──────────┘
//!        └────┬─────────┬────
//!           10^1      10^2
//!                x label
//! ```
//!
//! Output is SVG 1.1 (W3C Recommendation, 2011): only `line`, `path`, `circle`, `rect`, `text`
//! and `tspan`, so any viewer (browsers, librsvg, Inkscape) renders it.
use std::fmt::Write as _;
use std::path::Path;

use crate::error::Result;
use crate::output::write_atomically;

/// One line of the plot: a label for the legend and its `(x, y)` points, in drawing order.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The legend's label.
    pub label: String,
    /// The points `(x, y)`.
    pub points: Vec<(f64, f64)>,
}

const WIDTH: f64 = 800.0;
const HEIGHT: f64 = 560.0;
const LEFT: f64 = 90.0;
const RIGHT: f64 = 775.0;
const TOP: f64 = 50.0;
const BOTTOM: f64 = 480.0;
const FONT: f64 = 14.0;

/// Okabe & Ito's colour-blind-safe palette (Okabe, Ito, "Color Universal Design", 2008), without
/// the yellow that is unreadable on white.
const COLOURS: [&str; 7] = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"];

/// The line style of series `i`: solid for the first round of [`COLOURS`], dashed after, so
/// that no two series of one plot look alike.
fn dash(i: usize) -> &'static str {
    if i < COLOURS.len() {
        ""
    } else {
        r#" stroke-dasharray="8 4""#
    }
}

#[derive(Debug, Clone, Copy)]
enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
    Cross,
}

const MARKERS: [Marker; 6] =
    [Marker::Circle, Marker::Square, Marker::TriangleUp, Marker::Diamond, Marker::TriangleDown, Marker::Cross];

/// A log10 axis over whole decades.
#[derive(Debug, Clone, Copy)]
struct LogAxis {
    lo: i32,
    hi: i32,
}

impl LogAxis {
    /// Smallest whole-decade range containing `[min, max]` (both > 0); at least one decade wide.
    fn enclosing(min: f64, max: f64) -> Self {
        let lo = min.log10().floor();
        let hi = max.log10().ceil();
        // Clamp so that extreme but finite inputs cannot overflow the integer conversion.
        let (mut lo, mut hi) = (lo.clamp(-400.0, 400.0) as i32, hi.clamp(-400.0, 400.0) as i32);
        if lo == hi {
            lo -= 1;
            hi += 1;
        }
        LogAxis { lo, hi }
    }

    /// Position of `v` in [0, 1] along the axis.
    fn fraction(&self, v: f64) -> f64 {
        (v.log10() - self.lo as f64) / (self.hi - self.lo) as f64
    }

    fn decades(&self) -> i32 {
        self.hi - self.lo
    }

    /// Label every `step`-th decade so that at most 8 labels are written.
    fn label_step(&self) -> i32 {
        (self.decades() + 7) / 8
    }
}

fn x_pixel(axis: &LogAxis, v: f64) -> f64 {
    LEFT + axis.fraction(v) * (RIGHT - LEFT)
}

fn y_pixel(axis: &LogAxis, v: f64) -> f64 {
    BOTTOM - axis.fraction(v) * (BOTTOM - TOP)
}

fn plottable(p: &(f64, f64)) -> bool {
    p.0 > 0.0 && p.1 > 0.0 && p.0.is_finite() && p.1.is_finite()
}

/// Escape text content for XML.
fn escape_text(s: &str) -> String {
    crate::output::vtu::escape_attribute(s)
}

/// Write a log-log plot of `series` as an 800×560 SVG file, atomically.
///
/// Each series gets its own colour and marker; the legend goes in the corner of the plot area
/// that overlaps the fewest data. Points with a coordinate `<= 0`, NaN or infinite are skipped
/// (a log axis cannot show them); if no point is left the axes span 1..10 and the plot says so.
pub fn write_loglog_svg(path: &Path, title: &str, x_label: &str, y_label: &str, series: &[Series]) -> Result<()> {
    let svg = render(title, x_label, y_label, series);
    write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

/// The SVG document as a string (`write!` into a `String` cannot fail, hence the `let _`).
fn render(title: &str, x_label: &str, y_label: &str, series: &[Series]) -> String {
    let valid = || series.iter().flat_map(|s| s.points.iter()).filter(|p| plottable(p));
    let any_data = valid().next().is_some();
    let (x_axis, y_axis) = if any_data {
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::INFINITY, 0.0f64, f64::INFINITY, 0.0f64);
        for &(x, y) in valid() {
            xmin = xmin.min(x);
            xmax = xmax.max(x);
            ymin = ymin.min(y);
            ymax = ymax.max(y);
        }
        (LogAxis::enclosing(xmin, xmax), LogAxis::enclosing(ymin, ymax))
    } else {
        (LogAxis { lo: 0, hi: 1 }, LogAxis { lo: 0, hi: 1 })
    };

    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif" font-size="{FONT}">
<rect x="0" y="0" width="{WIDTH}" height="{HEIGHT}" fill="white"/>"#
    );

    // Grid and ticks.
    let _ = writeln!(s, r#"<g stroke-width="1">"#);
    for (axis, is_x) in [(&x_axis, true), (&y_axis, false)] {
        let minor = axis.decades() <= 6;
        for k in axis.lo..=axis.hi {
            let decade = 10f64.powi(k);
            draw_tick(&mut s, axis, is_x, decade, true);
            if minor && k < axis.hi {
                for m in 2..=9 {
                    draw_tick(&mut s, axis, is_x, m as f64 * decade, false);
                }
            }
        }
    }
    let _ = writeln!(s, "</g>");
    let _ = writeln!(
        s,
        r#"<rect x="{LEFT}" y="{TOP}" width="{}" height="{}" fill="none" stroke="black" stroke-width="1.2"/>"#,
        RIGHT - LEFT,
        BOTTOM - TOP
    );

    // Decade labels: 10 with a raised exponent.
    for (axis, is_x) in [(&x_axis, true), (&y_axis, false)] {
        let step = axis.label_step();
        for k in (axis.lo..=axis.hi).filter(|k| (k - axis.lo) % step == 0) {
            let v = 10f64.powi(k);
            let (x, y, anchor) = if is_x {
                (x_pixel(axis, v), BOTTOM + 24.0, "middle")
            } else {
                (LEFT - 8.0, y_pixel(axis, v) + 5.0, "end")
            };
            let _ = writeln!(
                s,
                r#"<text x="{x:.2}" y="{y:.2}" text-anchor="{anchor}">10<tspan dy="-7" font-size="{:.1}">{}</tspan></text>"#,
                FONT * 0.75,
                k.to_string().replace('-', "\u{2212}")
            );
        }
    }

    // On an axis of one or two decades, also label 2 and 5 × 10^k, so it has enough numbers.
    for (axis, is_x) in [(&x_axis, true), (&y_axis, false)] {
        if axis.decades() > 2 {
            continue;
        }
        for k in axis.lo..axis.hi {
            for m in [2u32, 5] {
                let v = m as f64 * 10f64.powi(k);
                let (x, y, anchor) = if is_x {
                    (x_pixel(axis, v), BOTTOM + 24.0, "middle")
                } else {
                    (LEFT - 8.0, y_pixel(axis, v) + 5.0, "end")
                };
                let _ = writeln!(
                    s,
                    r#"<text x="{x:.2}" y="{y:.2}" text-anchor="{anchor}" font-size="{:.1}">{}</text>"#,
                    FONT * 0.85,
                    mantissa_times_decade(m, k)
                );
            }
        }
    }

    // Title and axis labels.
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="30" text-anchor="middle" font-size="18" font-weight="bold">{}</text>"#,
        (LEFT + RIGHT) / 2.0,
        escape_text(title)
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" text-anchor="middle" font-size="15">{}</text>"#,
        (LEFT + RIGHT) / 2.0,
        BOTTOM + 56.0,
        escape_text(x_label)
    );
    let (ylx, yly) = (26.0, (TOP + BOTTOM) / 2.0);
    let _ = writeln!(
        s,
        r#"<text x="{ylx}" y="{yly:.2}" text-anchor="middle" font-size="15" transform="rotate(-90 {ylx} {yly:.2})">{}</text>"#,
        escape_text(y_label)
    );
    if !any_data {
        let _ = writeln!(
            s,
            r##"<text x="{:.2}" y="{:.2}" text-anchor="middle" fill="#666">no positive data to plot</text>"##,
            (LEFT + RIGHT) / 2.0,
            (TOP + BOTTOM) / 2.0
        );
    }

    // Series: lines broken at unplottable points, then markers on top.
    let pixels: Vec<Vec<Option<(f64, f64)>>> = series
        .iter()
        .map(|se| {
            se.points.iter().map(|p| plottable(p).then(|| (x_pixel(&x_axis, p.0), y_pixel(&y_axis, p.1)))).collect()
        })
        .collect();
    for (i, pts) in pixels.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let mut d = String::new();
        let mut pen_down = false;
        for p in pts {
            match p {
                Some((x, y)) => {
                    let _ = write!(d, "{}{x:.2} {y:.2} ", if pen_down { "L" } else { "M" });
                    pen_down = true;
                }
                None => pen_down = false,
            }
        }
        let _ = writeln!(s, r#"<g fill="{colour}" stroke="{colour}">"#);
        if !d.is_empty() {
            let _ = writeln!(
                s,
                r#"<path d="{}" fill="none" stroke-width="2" stroke-linejoin="round"{}/>"#,
                d.trim_end(),
                dash(i)
            );
        }
        for &(x, y) in pts.iter().flatten() {
            draw_marker(&mut s, MARKERS[i % MARKERS.len()], x, y);
        }
        let _ = writeln!(s, "</g>");
    }

    if !series.is_empty() {
        draw_legend(&mut s, series, &pixels);
    }
    let _ = writeln!(s, "</svg>");
    s
}

/// `m × 10^k` as a plain decimal (`0.002`, `50`) for moderate `k`, else as `m×10^k` text.
fn mantissa_times_decade(m: u32, k: i32) -> String {
    match k {
        0..=4 => format!("{}", m as u64 * 10u64.pow(k as u32)),
        -4..=-1 => format!("{}{m}", "0.".to_string() + &"0".repeat((-k - 1) as usize)),
        _ => format!(
            r#"{m}×10<tspan dy="-6" font-size="{:.1}">{}</tspan>"#,
            FONT * 0.65,
            k.to_string().replace('-', "\u{2212}")
        ),
    }
}

fn draw_tick(s: &mut String, axis: &LogAxis, is_x: bool, v: f64, major: bool) {
    let (grid, tick) = if major { ("#d0d0d0", 7.0) } else { ("#eeeeee", 4.0) };
    if is_x {
        let x = x_pixel(axis, v);
        let _ = writeln!(s, r#"<line x1="{x:.2}" y1="{TOP}" x2="{x:.2}" y2="{BOTTOM}" stroke="{grid}"/>"#);
        let _ =
            writeln!(s, r#"<line x1="{x:.2}" y1="{BOTTOM}" x2="{x:.2}" y2="{:.2}" stroke="black"/>"#, BOTTOM - tick);
    } else {
        let y = y_pixel(axis, v);
        let _ = writeln!(s, r#"<line x1="{LEFT}" y1="{y:.2}" x2="{RIGHT}" y2="{y:.2}" stroke="{grid}"/>"#);
        let _ = writeln!(s, r#"<line x1="{LEFT}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="black"/>"#, LEFT + tick);
    }
}

fn draw_marker(s: &mut String, marker: Marker, x: f64, y: f64) {
    const R: f64 = 4.5;
    let _ = match marker {
        Marker::Circle => writeln!(s, r#"<circle cx="{x:.2}" cy="{y:.2}" r="{R}"/>"#),
        Marker::Square => {
            let a = R * 0.85;
            writeln!(s, r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}"/>"#, x - a, y - a, 2.0 * a, 2.0 * a)
        }
        Marker::TriangleUp => writeln!(
            s,
            r#"<path d="M{x:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z"/>"#,
            y - 1.2 * R,
            x + 1.1 * R,
            y + 0.8 * R,
            x - 1.1 * R,
            y + 0.8 * R
        ),
        Marker::TriangleDown => writeln!(
            s,
            r#"<path d="M{x:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z"/>"#,
            y + 1.2 * R,
            x + 1.1 * R,
            y - 0.8 * R,
            x - 1.1 * R,
            y - 0.8 * R
        ),
        Marker::Diamond => writeln!(
            s,
            r#"<path d="M{x:.2} {:.2} L{:.2} {y:.2} L{x:.2} {:.2} L{:.2} {y:.2} Z"/>"#,
            y - 1.2 * R,
            x + 1.2 * R,
            y + 1.2 * R,
            x - 1.2 * R
        ),
        Marker::Cross => writeln!(
            s,
            r#"<path d="M{:.2} {:.2} L{:.2} {:.2} M{:.2} {:.2} L{:.2} {:.2}" fill="none" stroke-width="2.5"/>"#,
            x - R,
            y - R,
            x + R,
            y + R,
            x - R,
            y + R,
            x + R,
            y - R
        ),
    };
}

/// Legend box in the plot corner covering the fewest line samples and markers (tie order:
/// upper right, upper left, lower left, lower right).
fn draw_legend(s: &mut String, series: &[Series], pixels: &[Vec<Option<(f64, f64)>>]) {
    const ROW: f64 = 20.0;
    const PAD: f64 = 10.0;
    let longest = series.iter().map(|se| se.label.chars().count()).max().unwrap_or(0) as f64;
    let width = 52.0 + longest * FONT * 0.6 + PAD;
    let height = series.len() as f64 * ROW + PAD;

    // Points along every drawn segment, to measure how much of the data a box would hide.
    let mut samples = Vec::new();
    for pts in pixels {
        for w in pts.windows(2) {
            if let [Some(a), Some(b)] = w {
                for t in 0..=10 {
                    let t = t as f64 / 10.0;
                    samples.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
                }
            }
        }
        samples.extend(pts.iter().flatten().copied());
    }
    let corners = [
        (RIGHT - PAD - width, TOP + PAD),
        (LEFT + PAD, TOP + PAD),
        (LEFT + PAD, BOTTOM - PAD - height),
        (RIGHT - PAD - width, BOTTOM - PAD - height),
    ];
    let margin = 6.0;
    let covered = |&(x0, y0): &(f64, f64)| {
        samples
            .iter()
            .filter(|&&(x, y)| {
                x >= x0 - margin && x <= x0 + width + margin && y >= y0 - margin && y <= y0 + height + margin
            })
            .count()
    };
    let mut best = corners[0];
    let mut best_count = covered(&best);
    for c in &corners[1..] {
        let n = covered(c);
        if n < best_count {
            best = *c;
            best_count = n;
        }
    }
    let (x0, y0) = best;
    let _ = writeln!(
        s,
        r##"<rect x="{x0:.2}" y="{y0:.2}" width="{width:.2}" height="{height:.2}" fill="white" fill-opacity="0.9" stroke="#888"/>"##
    );
    for (i, se) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let y = y0 + PAD / 2.0 + (i as f64 + 0.5) * ROW;
        let _ = writeln!(s, r#"<g fill="{colour}" stroke="{colour}">"#);
        let _ = writeln!(
            s,
            r#"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke-width="2"{}/>"#,
            x0 + 8.0,
            x0 + 40.0,
            dash(i)
        );
        draw_marker(s, MARKERS[i % MARKERS.len()], x0 + 24.0, y);
        let _ = writeln!(s, "</g>");
        let _ = writeln!(s, r#"<text x="{:.2}" y="{:.2}">{}</text>"#, x0 + 48.0, y + 5.0, escape_text(&se.label));
    }
}

// ------------------------------------------------------------------------------------------
// Linear axes, for fields along a line (e.g. a contact pressure against position).

/// A linear axis from `lo` to `hi` with ticks every `step` (1, 2 or 5 × 10^k, about 6 ticks).
#[derive(Debug, Clone, Copy)]
struct LinearAxis {
    lo: f64,
    hi: f64,
    step: f64,
}

impl LinearAxis {
    fn enclosing(min: f64, max: f64) -> Self {
        let (min, max) = if max > min { (min, max) } else { (min - 1.0, min + 1.0) };
        let raw = (max - min) / 6.0;
        let magnitude = 10f64.powf(raw.log10().floor());
        let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * magnitude).find(|s| *s >= raw).unwrap_or(10.0 * magnitude);
        LinearAxis { lo: (min / step).floor() * step, hi: (max / step).ceil() * step, step }
    }
    fn fraction(&self, v: f64) -> f64 {
        (v - self.lo) / (self.hi - self.lo)
    }
}

/// One log-log plot of a multi-panel figure ([`write_loglog_panels_svg`]).
pub struct Panel<'a> {
    /// The panel's title.
    pub title: &'a str,
    /// Label of the x axis.
    pub x_label: &'a str,
    /// Label of the y axis.
    pub y_label: &'a str,
    /// The lines drawn.
    pub series: &'a [Series],
}

/// Write log-log plots side by side in one SVG file (each 800×560, as
/// [`write_loglog_svg`] draws it), atomically.
pub fn write_loglog_panels_svg(path: &Path, panels: &[Panel]) -> Result<()> {
    let svg = side_by_side(panels.iter().map(|p| render(p.title, p.x_label, p.y_label, p.series)).collect());
    write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

/// One SVG document holding `plots` (each a whole 800×560 document) side by side.
fn side_by_side(plots: Vec<String>) -> String {
    let mut svg = String::new();
    let width = WIDTH * plots.len().max(1) as f64;
    let _ = writeln!(
        svg,
        r#"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{width}" height="{HEIGHT}" viewBox="0 0 {width} {HEIGHT}">"#
    );
    for (k, one) in plots.iter().enumerate() {
        // Drop the XML declaration and place the panel's own <svg> at its offset.
        let body = one.split_once("?>").map_or(one.as_str(), |(_, rest)| rest).trim_start();
        let placed = body.replacen("<svg ", &format!("<svg x=\"{}\" y=\"0\" ", k as f64 * WIDTH), 1);
        svg.push_str(&placed);
    }
    svg.push_str("</svg>\n");
    svg
}

/// How a linear plot draws a series ([`write_linear_styled_svg`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Style {
    /// A line through the points in the order given, never sorted (a loop stays a loop).
    Line,
    /// A marker at each point, no line (measured or computed samples).
    Markers,
    /// The line of [`Style::Line`] and a marker at each point on top of it.
    LineAndMarkers,
}

/// Write a plot with linear axes. `lines[i]` says whether series `i` is drawn as a line (true)
/// or as markers only (false: measured or computed samples).
pub fn write_linear_svg(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    lines: &[bool],
) -> Result<()> {
    let styles: Vec<Style> = (0..series.len())
        .map(|i| if lines.get(i).copied().unwrap_or(true) { Style::Line } else { Style::Markers })
        .collect();
    write_linear_styled_svg(path, title, x_label, y_label, series, &styles)
}

/// Write a plot with linear axes (800×560), atomically; series `i` is drawn as `styles[i]`
/// says ([`Style::Line`] where `styles` has no entry). Lines join the points in the order
/// given, so a path that goes back and forth in x (a hysteresis loop) is drawn as it went;
/// a non-finite point is skipped and breaks the line there.
pub fn write_linear_styled_svg(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    styles: &[Style],
) -> Result<()> {
    let text = render_linear(title, x_label, y_label, series, styles);
    write_atomically(path, |w| w.write_all(text.as_bytes()))
}

/// Write linear plots side by side in one SVG file (each 800×560, as
/// [`write_linear_styled_svg`] draws it, every series as `style`), atomically.
pub fn write_linear_panels_svg(path: &Path, panels: &[Panel], style: Style) -> Result<()> {
    let svg = side_by_side(
        panels
            .iter()
            .map(|p| render_linear(p.title, p.x_label, p.y_label, p.series, &vec![style; p.series.len()]))
            .collect(),
    );
    write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

fn render_linear(title: &str, x_label: &str, y_label: &str, series: &[Series], styles: &[Style]) -> String {
    let finite = || series.iter().flat_map(|s| s.points.iter()).filter(|p| p.0.is_finite() && p.1.is_finite());
    let bounds = finite().fold((f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY), |b, p| {
        (b.0.min(p.0), b.1.max(p.0), b.2.min(p.1), b.3.max(p.1))
    });
    let (x_axis, y_axis) = if bounds.0.is_finite() {
        (LinearAxis::enclosing(bounds.0, bounds.1), LinearAxis::enclosing(bounds.2, bounds.3))
    } else {
        (LinearAxis::enclosing(0.0, 1.0), LinearAxis::enclosing(0.0, 1.0))
    };
    let px = |v: f64| LEFT + x_axis.fraction(v) * (RIGHT - LEFT);
    let py = |v: f64| BOTTOM - y_axis.fraction(v) * (BOTTOM - TOP);
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{WIDTH}" height="{HEIGHT}" viewBox="0 0 {WIDTH} {HEIGHT}" font-family="DejaVu Sans, Helvetica, Arial, sans-serif" font-size="{FONT}">
<rect x="0" y="0" width="{WIDTH}" height="{HEIGHT}" fill="white"/>"#
    );
    for (axis, is_x) in [(&x_axis, true), (&y_axis, false)] {
        let n = ((axis.hi - axis.lo) / axis.step).round() as i64;
        for k in 0..=n {
            let v = axis.lo + k as f64 * axis.step;
            let label = format!("{:.4}", v).trim_end_matches('0').trim_end_matches('.').to_string();
            let label = if v.abs() >= 1e4 || (v != 0.0 && v.abs() < 1e-3) { format!("{v:.3e}") } else { label };
            if is_x {
                let x = px(v);
                let _ = writeln!(s, r##"<line x1="{x:.2}" y1="{TOP}" x2="{x:.2}" y2="{BOTTOM}" stroke="#e6e6e6"/>"##);
                let _ = writeln!(
                    s,
                    r#"<text x="{x:.2}" y="{}" text-anchor="middle">{}</text>"#,
                    BOTTOM + 20.0,
                    escape_text(&label)
                );
            } else {
                let y = py(v);
                let _ = writeln!(s, r##"<line x1="{LEFT}" y1="{y:.2}" x2="{RIGHT}" y2="{y:.2}" stroke="#e6e6e6"/>"##);
                let _ = writeln!(
                    s,
                    r#"<text x="{}" y="{:.2}" text-anchor="end">{}</text>"#,
                    LEFT - 8.0,
                    y + 5.0,
                    escape_text(&label)
                );
            }
        }
    }
    let _ = writeln!(
        s,
        r#"<rect x="{LEFT}" y="{TOP}" width="{}" height="{}" fill="none" stroke="black" stroke-width="1.2"/>"#,
        RIGHT - LEFT,
        BOTTOM - TOP
    );
    let mut pixels: Vec<Vec<Option<(f64, f64)>>> = Vec::new();
    for (i, se) in series.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let pts: Vec<Option<(f64, f64)>> = se
            .points
            .iter()
            .map(|p| if p.0.is_finite() && p.1.is_finite() { Some((px(p.0), py(p.1))) } else { None })
            .collect();
        let _ = writeln!(s, r#"<g fill="{colour}" stroke="{colour}">"#);
        let style = styles.get(i).copied().unwrap_or(Style::Line);
        if style != Style::Markers {
            let mut d = String::new();
            let mut pen_down = false;
            for p in &pts {
                match p {
                    Some((x, y)) => {
                        let _ = write!(d, "{}{x:.2},{y:.2} ", if pen_down { "L" } else { "M" });
                        pen_down = true;
                    }
                    None => pen_down = false,
                }
            }
            let _ = writeln!(s, r#"<path d="{}" fill="none" stroke-width="2"/>"#, d.trim_end());
        }
        if style != Style::Line {
            for (x, y) in pts.iter().flatten() {
                draw_marker(&mut s, MARKERS[i % MARKERS.len()], *x, *y);
            }
        }
        let _ = writeln!(s, "</g>");
        pixels.push(pts);
    }
    draw_legend(&mut s, series, &pixels);
    let _ = writeln!(
        s,
        r#"<text x="{}" y="28" text-anchor="middle" font-size="{}" font-weight="bold">{}</text>"#,
        (LEFT + RIGHT) / 2.0,
        FONT + 3.0,
        escape_text(title)
    );
    let _ = writeln!(
        s,
        r#"<text x="{}" y="{}" text-anchor="middle">{}</text>"#,
        (LEFT + RIGHT) / 2.0,
        HEIGHT - 30.0,
        escape_text(x_label)
    );
    let _ = writeln!(
        s,
        r#"<text x="22" y="{:.2}" text-anchor="middle" transform="rotate(-90 22 {:.2})">{}</text>"#,
        (TOP + BOTTOM) / 2.0,
        (TOP + BOTTOM) / 2.0,
        escape_text(y_label)
    );
    let _ = writeln!(s, "</svg>");
    s
}
