//! The contact pictures of a run, drawn with `plotters` (its SVG backend only: text is written
//! as SVG `<text>` with a generic font family and laid out by the viewer, so no font is needed
//! on the machine that writes them).
//!
//! - `contact.svg`: normal pressure and tangential traction against arc length along the
//!   contact part;
//! - `convergence.svg`: the contact solver's residual after each iteration, on a log scale.
use std::path::Path;

use plotters::prelude::*;

use crate::error::{Error, Result};

/// Picture size in pixels.
const SIZE: (u32, u32) = (900, 520);

fn plot_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output { path: path.to_path_buf(), message: format!("drawing the plot: {e} (nothing was written)") }
}

/// A tick label with at most three significant digits and no trailing zeros: `5e-3`,
/// `1.25e7`, `0`.
fn tick(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let text = format!("{v:.2e}");
    match text.split_once('e') {
        Some((mantissa, exponent)) if mantissa.contains('.') => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            if exponent == "0" {
                mantissa.to_string()
            } else {
                format!("{mantissa}e{exponent}")
            }
        }
        _ => text,
    }
}

/// Part of the plot's height left above the data for the legend, so that it covers no point.
const LEGEND_BAND: f64 = 0.25;

/// `[lo, hi]` widened by 5 % (and made non-empty).
fn padded(lo: f64, hi: f64) -> (f64, f64) {
    let (lo, hi) = if lo.is_finite() && hi.is_finite() { (lo, hi) } else { (0.0, 1.0) };
    let span = if hi > lo { hi - lo } else { lo.abs().max(1.0) };
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// Draw into an SVG string with `draw`, then write it atomically.
fn write_svg(
    path: &Path,
    draw: impl FnOnce(&DrawingArea<SVGBackend, plotters::coord::Shift>) -> std::result::Result<(), String>,
) -> Result<()> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(|e| plot_error(path, e))?;
        draw(&root).map_err(|e| plot_error(path, e))?;
        root.present().map_err(|e| plot_error(path, e))?;
    }
    super::write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

/// `contact.svg`: pressure and tangential traction (Pa: force per unit length of the part and
/// unit thickness) against arc length `s` (m), one point per contact point; `zoomed` says the
/// points are a window of the part (the axis label says so). The legend sits in a band above
/// the data.
pub fn write_contact_svg(
    path: &Path,
    title: &str,
    s: &[f64],
    pressure: &[f64],
    traction: &[f64],
    zoomed: bool,
) -> Result<()> {
    let (x0, x1) =
        padded(s.iter().copied().fold(f64::INFINITY, f64::min), s.iter().copied().fold(f64::NEG_INFINITY, f64::max));
    let values = pressure.iter().chain(traction).copied().filter(|v| v.is_finite());
    let (y0, y1) = padded(values.clone().fold(0.0, f64::min), values.fold(0.0, f64::max));
    let y1 = y1 + LEGEND_BAND / (1.0 - LEGEND_BAND) * (y1 - y0);
    write_svg(path, |root| {
        let e = |e: plotters::drawing::DrawingAreaErrorKind<_>| e.to_string();
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(85)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(if zoomed {
                "arc length s along the contact part, m (around the closed zones)"
            } else {
                "arc length s along the contact part, m"
            })
            .y_desc("traction, Pa")
            .y_label_formatter(&|v| tick(*v))
            .x_label_formatter(&|v| tick(*v))
            .draw()
            .map_err(e)?;
        let series = [("normal pressure", pressure, BLUE), ("tangential traction", traction, RED)];
        for (name, values, colour) in series {
            let points: Vec<(f64, f64)> = s.iter().copied().zip(values.iter().copied()).collect();
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
                .map_err(e)?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            chart.draw_series(points.into_iter().map(|p| Circle::new(p, 2, colour.filled()))).map_err(e)?;
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;
        Ok(())
    })
}

/// `convergence.svg`: the residual after each iteration (from 1) on a log scale. Zero
/// residuals (an exact final step) are drawn at the bottom of the scale. The legend sits in a
/// band above the data (the scale runs a decade higher than the largest residual needs).
pub fn write_convergence_svg(path: &Path, title: &str, residuals: &[f64]) -> Result<()> {
    let positive: Vec<f64> = residuals.iter().copied().filter(|r| r.is_finite() && *r > 0.0).collect();
    let lo = positive.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = positive.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let (lo, hi) = if lo.is_finite() { (lo / 3.0, hi * 3.0) } else { (1e-16, 1.0) };
    let hi = hi * (hi / lo).powf(LEGEND_BAND / (1.0 - LEGEND_BAND));
    let floor = lo;
    let n = residuals.len().max(1);
    write_svg(path, |root| {
        let e = |e: plotters::drawing::DrawingAreaErrorKind<_>| e.to_string();
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(85)
            .build_cartesian_2d(0..(n as i64 + 1), (lo..hi).log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("iteration")
            .y_desc("relative residual (log scale)")
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .x_labels((n + 2).min(12))
            .draw()
            .map_err(e)?;
        let points: Vec<(i64, f64)> =
            residuals.iter().enumerate().map(|(k, r)| (k as i64 + 1, if *r > 0.0 { *r } else { floor })).collect();
        chart
            .draw_series(LineSeries::new(points.clone(), BLUE.stroke_width(2)))
            .map_err(e)?
            .label("contact solver residual")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLUE.stroke_width(2)));
        chart.draw_series(points.into_iter().map(|p| Circle::new(p, 3, BLUE.filled()))).map_err(e)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(e)?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::tick;

    #[test]
    fn ticks_have_no_trailing_zeros() {
        assert_eq!(tick(5.0e-3), "5e-3");
        assert_eq!(tick(1.25e7), "1.25e7");
        assert_eq!(tick(-2.5e8), "-2.5e8");
        assert_eq!(tick(3.0), "3");
        assert_eq!(tick(0.0), "0");
    }
}
