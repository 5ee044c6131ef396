//! A picture of a mesh with one value per cell (the element error of an adaptive step), drawn
//! with `plotters` (SVG backend; text as SVG `<text>`, no font needed where it is written).
//!
//! Each vertex triangle is filled with the colour of its value on a logarithmic scale (the
//! sizes and errors of an adapted mesh span decades), outlined by a thin line, with equal scales
//! on both axes; an optional second panel zooms on a window (a singular point), and a colour bar
//! on the right gives the scale. Curved P2 cells are drawn by their vertex triangles.
use std::path::Path;

use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Viridis (van der Walt & Smith, matplotlib 2015) sampled at 9 points, dark to light.
const VIRIDIS: [(u8, u8, u8); 9] = [
    (68, 1, 84),
    (71, 44, 122),
    (59, 81, 139),
    (44, 113, 142),
    (33, 144, 141),
    (39, 173, 129),
    (92, 200, 99),
    (170, 220, 50),
    (253, 231, 37),
];

/// The colour at `t` in [0, 1] (clamped), linear between the samples.
pub fn viridis(t: f64) -> RGBColor {
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * (VIRIDIS.len() - 1) as f64;
    let k = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - k as f64;
    let mix = |a: u8, b: u8| (a as f64 + f * (b as f64 - a as f64)).round() as u8;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn plot_error(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::Output { path: path.to_path_buf(), message: format!("drawing the mesh: {e} (nothing was written)") }
}

/// Write `path`: the cells of `mesh` coloured by `values` (one per cell, > 0; others drawn in
/// the lowest colour) on a log scale, with `title` and the colour bar labelled `label`; with
/// `zoom = Some([x0, x1, y0, y1])` a second panel shows that window of the mesh.
pub fn write_mesh_svg(
    path: &Path,
    mesh: &Mesh,
    values: &[f64],
    title: &str,
    label: &str,
    zoom: Option<[f64; 4]>,
) -> Result<()> {
    if values.len() != mesh.num_cells() {
        return Err(Error::Usage(format!("mesh picture: {} values for {} cells", values.len(), mesh.num_cells())));
    }
    let positive = values.iter().copied().filter(|v| v.is_finite() && *v > 0.0);
    let (lo, hi) = positive.fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(v), b.max(v)));
    let (lo, hi) = if lo.is_finite() { (lo.log10(), hi.log10().max(lo.log10() + 1e-12)) } else { (0.0, 1.0) };
    let scale = |v: f64| if v > 0.0 && v.is_finite() { (v.log10() - lo) / (hi - lo) } else { 0.0 };
    let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for p in &mesh.nodes {
        x0 = x0.min(p[0]);
        x1 = x1.max(p[0]);
        y0 = y0.min(p[1]);
        y1 = y1.max(p[1]);
    }
    // The zoom window, moved inside the mesh's bounding box where it sticks out.
    let zoom = zoom.map(|z| {
        let shift = |a: f64, b: f64, lo: f64, hi: f64| {
            let d = if a < lo {
                lo - a
            } else if b > hi {
                hi - b
            } else {
                0.0
            };
            (a + d, b + d)
        };
        let (a, b) = shift(z[0], z[1], x0, x1);
        let (c, d) = shift(z[2], z[3], y0, y1);
        [a, b, c, d]
    });
    let windows: Vec<[f64; 4]> = std::iter::once([x0, x1, y0, y1]).chain(zoom).collect();
    // Equal scales in each panel: one plot height, each panel as wide as its window's aspect
    // ratio asks (around the plot: label areas and margins, in pixels).
    let plot_height = 420.0;
    let aspect = |w: &[f64; 4]| ((w[3] - w[2]) / (w[1] - w[0]).max(f64::MIN_POSITIVE)).clamp(0.2, 3.0);
    let (pad_x, pad_y) = (50.0 + 20.0, 30.0 + 20.0 + 22.0);
    let widths: Vec<u32> = windows.iter().map(|w| (plot_height / aspect(w) + pad_x) as u32).collect();
    let bar_width = 150u32;
    let size = (widths.iter().sum::<u32>() + bar_width, (plot_height + pad_y) as u32 + 40);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        let e = |e: plotters::drawing::DrawingAreaErrorKind<_>| plot_error(path, e);
        root.fill(&WHITE).map_err(e)?;
        let root = root.titled(title, ("sans-serif", 18)).map_err(e)?;
        let (panels, right) = root.split_horizontally(size.0 - bar_width);
        let mut areas = Vec::new();
        let mut rest = panels;
        for &w in &widths[..widths.len() - 1] {
            let (a, b) = rest.split_horizontally(w);
            areas.push(a);
            rest = b;
        }
        areas.push(rest);
        let triangle = |c: usize| -> Vec<(f64, f64)> {
            mesh.cell(c)[..3].iter().map(|&n| (mesh.nodes[n][0], mesh.nodes[n][1])).collect()
        };
        for (k, (area, w)) in areas.iter().zip(&windows).enumerate() {
            // The cells whose bounding box meets the window (the plotting area clips them).
            let inside = |c: usize| {
                let v = &mesh.cell(c)[..3];
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for &n in v {
                    for k in 0..2 {
                        lo[k] = lo[k].min(mesh.nodes[n][k]);
                        hi[k] = hi[k].max(mesh.nodes[n][k]);
                    }
                }
                hi[0] >= w[0] && lo[0] <= w[1] && hi[1] >= w[2] && lo[1] <= w[3]
            };
            let mut chart = ChartBuilder::on(area)
                .caption(if k == 0 { "the whole mesh" } else { "zoom" }, ("sans-serif", 14))
                .margin(10)
                .x_label_area_size(30)
                .y_label_area_size(50)
                .build_cartesian_2d(w[0]..w[1], w[2]..w[3])
                .map_err(e)?;
            chart.configure_mesh().disable_mesh().x_labels(5).y_labels(5).draw().map_err(e)?;
            let cells: Vec<usize> = (0..mesh.num_cells()).filter(|&c| k == 0 || inside(c)).collect();
            let plotting = chart.plotting_area();
            for &c in &cells {
                plotting.draw(&Polygon::new(triangle(c), viridis(scale(values[c])).filled())).map_err(e)?;
            }
            let edge = RGBColor(30, 30, 30).mix(0.45).stroke_width(1);
            for &c in &cells {
                let mut t = triangle(c);
                t.push(t[0]);
                plotting.draw(&PathElement::new(t, edge)).map_err(e)?;
            }
            if k == 0 {
                if let Some(z) = zoom {
                    let frame = vec![(z[0], z[2]), (z[1], z[2]), (z[1], z[3]), (z[0], z[3]), (z[0], z[2])];
                    plotting.draw(&PathElement::new(frame, RED.stroke_width(2))).map_err(e)?;
                }
            }
        }
        // The colour bar: 64 bands from lo to hi, labelled with the values.
        let mut bar = ChartBuilder::on(&right)
            .margin_top(30)
            .margin_bottom(40)
            .margin_left(10)
            .margin_right(5)
            .right_y_label_area_size(70)
            .caption(label, ("sans-serif", 13))
            .build_cartesian_2d(0.0..1.0, lo..hi)
            .map_err(e)?;
        bar.configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_labels(6)
            .y_label_style(("sans-serif", 12))
            .y_label_formatter(&|v| format!("{:.1e}", 10f64.powf(*v)))
            .draw()
            .map_err(e)?;
        let bands = 64;
        bar.draw_series((0..bands).map(|k| {
            let (a, b) = (lo + (hi - lo) * k as f64 / bands as f64, lo + (hi - lo) * (k + 1) as f64 / bands as f64);
            Rectangle::new([(0.0, a), (1.0, b)], viridis((k as f64 + 0.5) / bands as f64).filled())
        }))
        .map_err(e)?;
        root.present().map_err(e)?;
    }
    super::write_atomically(path, |w| w.write_all(svg.as_bytes()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::{structured, Order};

    #[test]
    fn viridis_runs_from_dark_to_light() {
        let (a, b) = (viridis(0.0), viridis(1.0));
        assert_eq!((a.0, a.1, a.2), VIRIDIS[0]);
        assert_eq!((b.0, b.1, b.2), VIRIDIS[8]);
        let lum = |c: RGBColor| 0.3 * c.0 as f64 + 0.59 * c.1 as f64 + 0.11 * c.2 as f64;
        assert!((1..=10).all(|k| lum(viridis(k as f64 / 10.0)) > lum(viridis((k - 1) as f64 / 10.0))));
        assert_eq!(viridis(f64::NAN), viridis(0.0));
    }

    #[test]
    fn every_cell_is_a_filled_polygon_coloured_by_its_value() {
        let mesh = structured::rectangle([0.0, 0.0], [2.0, 1.0], 4, 2, Order::P1).unwrap();
        let values: Vec<f64> = (0..mesh.num_cells()).map(|c| 10f64.powi(c as i32 % 4 - 3)).collect();
        let path = std::env::temp_dir().join(format!("signorini-mesh-plot-{}.svg", std::process::id()));
        write_mesh_svg(&path, &mesh, &values, "test mesh", "element error", None).unwrap();
        let svg = std::fs::read_to_string(&path).unwrap();
        assert_eq!(svg.matches("<polygon").count(), mesh.num_cells(), "one polygon per cell");
        // With a zoom: the cells with a vertex in the window again in a second panel.
        write_mesh_svg(&path, &mesh, &values, "test mesh", "element error", Some([0.0, 0.5, 0.0, 0.5])).unwrap();
        let zoomed = std::fs::read_to_string(&path).unwrap();
        assert!(zoomed.matches("<polygon").count() > mesh.num_cells(), "no zoom panel");
        assert!(zoomed.contains("zoom"));
        // The smallest value gets the darkest colour, the largest the lightest.
        assert!(svg.contains("#440154") || svg.contains("rgb(68,1,84)"), "no darkest colour");
        assert!(svg.contains("#FDE725") || svg.contains("#fde725") || svg.contains("rgb(253,231,37)"), "no lightest");
        assert!(svg.contains("element error") && svg.contains("test mesh"));
        assert!(write_mesh_svg(&path, &mesh, &values[1..], "t", "l", None).is_err());
        let _ = std::fs::remove_file(&path);
    }
}
