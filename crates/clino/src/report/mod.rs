//! Plots for people: SVG or PNG, chosen by the file extension.
//!
//! Plots use plotters without its `ttf` feature (which needs system font
//! libraries a fresh machine lacks); text is drawn with the bundled
//! `ab_glyph` renderer and a font shipped in this crate.

pub mod text;

use crate::{Error, ErrorKind, Result};
use plotters::prelude::*;
use std::path::Path;

/// One line (or set of markers) on a plot.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend label.
    pub label: String,
    /// (x, y) points; non-finite points are skipped when drawing.
    pub points: Vec<(f64, f64)>,
    /// Draw markers instead of a line.
    pub markers: bool,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            markers: false,
        }
    }
    /// A marker series.
    pub fn markers(label: impl Into<String>, points: Vec<(f64, f64)>) -> Self {
        Self {
            label: label.into(),
            points,
            markers: true,
        }
    }
}

/// Axes and titles of a plot.
#[derive(Clone, Debug, Default)]
pub struct PlotSpec {
    /// Title over the plot.
    pub title: String,
    /// Label of the x axis, with its unit.
    pub x_label: String,
    /// Label of the y axis, with its unit.
    pub y_label: String,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
}

const FONT: &[u8] = include_bytes!("DejaVuSans.ttf");

fn register_font() {
    use std::sync::Once;
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // registering can only fail for an invalid font, which is bundled and tested
        let _ = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT);
    });
}

/// Check, before any work is done, that `path` can name a plot: it ends in
/// `.svg` or `.png` and its directory exists.
pub fn check_plot_path(path: &Path) -> Result<()> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    if ext != "svg" && ext != "png" {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "plot file must end in .svg or .png",
        )
        .in_file(path));
    }
    let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
    if let Some(d) = dir
        && !d.is_dir()
    {
        return Err(Error::new(
            ErrorKind::Io,
            format!("plot: directory {} does not exist", d.display()),
        )
        .in_file(path));
    }
    Ok(())
}

/// Draw `series` to `path` (`.svg` or `.png`, 1000×650 px).
pub fn line_plot(path: &Path, spec: &PlotSpec, series: &[Series]) -> Result<()> {
    register_font();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(|e| e.to_ascii_lowercase())
        .unwrap_or_default();
    let err = |e: String| Error::new(ErrorKind::Io, format!("plot: {e}")).in_file(path);
    match ext.as_str() {
        "svg" => {
            let root = SVGBackend::new(path, (1000, 650)).into_drawing_area();
            draw(root, spec, series).map_err(err)
        }
        "png" => {
            let root = BitMapBackend::new(path, (1000, 650)).into_drawing_area();
            draw(root, spec, series).map_err(err)
        }
        _ => Err(Error::new(
            ErrorKind::InvalidInput,
            "plot file must end in .svg or .png",
        )
        .in_file(path)),
    }
}

fn bounds(series: &[Series], log_x: bool, log_y: bool) -> ((f64, f64), (f64, f64)) {
    let ok = |v: f64, log: bool| v.is_finite() && (!log || v > 0.0);
    let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
    let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
    for s in series {
        for &(x, y) in &s.points {
            if ok(x, log_x) && ok(y, log_y) {
                xr = (xr.0.min(x), xr.1.max(x));
                yr = (yr.0.min(y), yr.1.max(y));
            }
        }
    }
    let fix = |r: (f64, f64), log: bool| {
        if !r.0.is_finite() {
            return if log { (0.1, 10.0) } else { (0.0, 1.0) };
        }
        if log {
            if r.1 <= r.0 {
                (r.0 / 2.0, r.0 * 2.0)
            } else {
                (r.0 / 1.2, r.1 * 1.2)
            }
        } else {
            let span = r.1 - r.0;
            let pad = if span > 0.0 {
                0.05 * span
            } else {
                0.5 * r.0.abs().max(1.0)
            };
            (r.0 - pad, r.1 + pad)
        }
    };
    (fix(xr, log_x), fix(yr, log_y))
}

/// A corner of the plotting area.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Corner {
    UpperRight,
    UpperLeft,
    LowerRight,
    LowerLeft,
}

impl Corner {
    fn position(self) -> SeriesLabelPosition {
        match self {
            Corner::UpperRight => SeriesLabelPosition::UpperRight,
            Corner::UpperLeft => SeriesLabelPosition::UpperLeft,
            Corner::LowerRight => SeriesLabelPosition::LowerRight,
            Corner::LowerLeft => SeriesLabelPosition::LowerLeft,
        }
    }
}

/// Plotting area of a 1000×650 plot, px (the margins, axis label areas and caption taken off).
const AREA_PX: (f64, f64) = (900.0, 540.0);

/// Where the legend goes so that it covers no data: the corner of the
/// plotting area with the fewest points (lines sampled along their
/// segments) under the legend's box, preferring upper right, upper left,
/// lower right, lower left. When every corner holds data, the y range is
/// raised at the top by the legend's height, so the legend sits in the
/// upper right above all data. Returns the corner and the (possibly
/// raised) y range.
pub(crate) fn legend_place(
    series: &[Series],
    spec: &PlotSpec,
    x: (f64, f64),
    y: (f64, f64),
) -> (Corner, (f64, f64)) {
    let labelled: Vec<&Series> = series.iter().filter(|s| !s.label.is_empty()).collect();
    if labelled.is_empty() {
        return (Corner::UpperRight, y);
    }
    // legend box in px (14 px font: about 8 px a character, 18 px a line;
    // 30 px sample, 5 px margins, 5 px from the edge), as fractions of the area
    let chars = labelled
        .iter()
        .map(|s| s.label.chars().count())
        .max()
        .unwrap_or(0);
    let w = ((8 * chars + 50) as f64 / AREA_PX.0).min(0.9);
    let h = ((18 * labelled.len() + 20) as f64 / AREA_PX.1).min(0.9);
    let norm = |v: f64, (a, b): (f64, f64), log: bool| {
        if log {
            (v.ln() - a.ln()) / (b.ln() - a.ln())
        } else {
            (v - a) / (b - a)
        }
    };
    let mut counts = [0usize; 4];
    let corners = [
        Corner::UpperRight,
        Corner::UpperLeft,
        Corner::LowerRight,
        Corner::LowerLeft,
    ];
    let mut count = |u: f64, v: f64| {
        for (k, c) in corners.iter().enumerate() {
            let in_x = match c {
                Corner::UpperRight | Corner::LowerRight => u >= 1.0 - w,
                _ => u <= w,
            };
            let in_y = match c {
                Corner::UpperRight | Corner::UpperLeft => v >= 1.0 - h,
                _ => v <= h,
            };
            if in_x && in_y && (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v) {
                counts[k] += 1;
            }
        }
    };
    for s in series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .filter(|p| {
                p.0.is_finite()
                    && p.1.is_finite()
                    && (!spec.log_x || p.0 > 0.0)
                    && (!spec.log_y || p.1 > 0.0)
            })
            .map(|p| (norm(p.0, x, spec.log_x), norm(p.1, y, spec.log_y)))
            .collect();
        for (i, &(u, v)) in pts.iter().enumerate() {
            count(u, v);
            // a line covers the space between its points: sample each segment
            // every 1 % of the area (dense traces are covered by their points)
            if !s.markers && pts.len() < 5000 && i + 1 < pts.len() {
                let (u1, v1) = pts[i + 1];
                let n = ((u1 - u).abs().max((v1 - v).abs()) / 0.01)
                    .ceil()
                    .min(200.0) as usize;
                for j in 1..n {
                    let t = j as f64 / n as f64;
                    count(u + t * (u1 - u), v + t * (v1 - v));
                }
            }
        }
    }
    let best = (0..4).min_by_key(|&k| counts[k]).unwrap_or(0);
    if counts[best] == 0 {
        return (corners[best], y);
    }
    // every corner covers data: raise the top so the data stays below the legend
    let f = 1.0 / (1.0 - h - 0.02);
    let y1 = if spec.log_y {
        (y.0.ln() + (y.1.ln() - y.0.ln()) * f).exp()
    } else {
        y.0 + (y.1 - y.0) * f
    };
    (Corner::UpperRight, (y.0, y1))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    spec: &PlotSpec,
    series: &[Series],
) -> std::result::Result<(), String>
where
    DB::ErrorType: 'static,
{
    let e = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let ((x0, x1), y_range) = bounds(series, spec.log_x, spec.log_y);
    let (corner, (y0, y1)) = legend_place(series, spec, (x0, x1), y_range);
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(&spec.title, ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70);
    macro_rules! body {
        ($chart:expr) => {{
            let mut chart = $chart;
            chart
                .configure_mesh()
                .x_desc(spec.x_label.as_str())
                .y_desc(spec.y_label.as_str())
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(|x| e(&x))?;
            for (i, s) in series.iter().enumerate() {
                let color = Palette99::pick(i).to_rgba();
                let pts: Vec<(f64, f64)> = s
                    .points
                    .iter()
                    .copied()
                    .filter(|p| {
                        p.0.is_finite()
                            && p.1.is_finite()
                            && (!spec.log_x || p.0 > 0.0)
                            && (!spec.log_y || p.1 > 0.0)
                    })
                    .collect();
                if s.markers {
                    chart
                        .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                        .map_err(|x| e(&x))?
                        .label(s.label.as_str())
                        .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
                } else {
                    chart
                        .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                        .map_err(|x| e(&x))?
                        .label(s.label.as_str())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                        });
                }
            }
            chart
                .configure_series_labels()
                .position(corner.position())
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .label_font(("sans-serif", 14))
                .draw()
                .map_err(|x| e(&x))?;
        }};
    }
    match (spec.log_x, spec.log_y) {
        (false, false) => body!(
            builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(|x| e(&x))?
        ),
        (true, false) => body!(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), y0..y1)
                .map_err(|x| e(&x))?
        ),
        (false, true) => body!(
            builder
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                .map_err(|x| e(&x))?
        ),
        (true, true) => body!(
            builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(|x| e(&x))?
        ),
    }
    root.present().map_err(|x| e(&x))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn writes_svg_and_png_with_log_axes() {
        let tmp = tempfile::Builder::new()
            .prefix("clino-report-")
            .tempdir()
            .unwrap();
        let dir = tmp.path();
        let s = vec![
            Series::line(
                "a",
                (1..50).map(|i| (i as f64, (i as f64).powf(-0.5))).collect(),
            ),
            Series::markers("b", vec![(2.0, 0.3), (5.0, f64::NAN)]),
        ];
        for (name, log) in [("p.svg", false), ("p.png", true)] {
            let path = dir.join(name);
            let spec = PlotSpec {
                title: "t".into(),
                x_label: "τ (s)".into(),
                y_label: "σ".into(),
                log_x: log,
                log_y: log,
            };
            line_plot(&path, &spec, &s).unwrap();
            assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        }
        let bad = line_plot(&dir.join("p.txt"), &PlotSpec::default(), &s).unwrap_err();
        assert_eq!(bad.kind, ErrorKind::InvalidInput);
    }

    fn place(series: &[Series]) -> (Corner, (f64, f64)) {
        let spec = PlotSpec::default();
        let (x, y) = bounds(series, false, false);
        legend_place(series, &spec, x, y)
    }

    #[test]
    fn legend_goes_to_an_empty_corner() {
        // a rising line runs through the lower-left and upper-right corners
        let rising = [Series::line(
            "rising",
            (0..=10).map(|i| (i as f64, i as f64)).collect(),
        )];
        let (c, y) = place(&rising);
        assert_eq!(c, Corner::UpperLeft);
        assert_eq!(
            y,
            bounds(&rising, false, false).1,
            "the range is not changed"
        );
        // a falling line leaves the upper right empty
        let falling = [Series::line(
            "falling",
            (0..=10).map(|i| (i as f64, -(i as f64))).collect(),
        )];
        assert_eq!(place(&falling).0, Corner::UpperRight);
        // a line with two points only: its segment is sampled, not just its ends
        let two = [
            Series::line("two", vec![(0.0, 0.0), (1.0, 1.0)]),
            Series::markers("m", vec![(0.0, 1.0)]),
        ];
        assert_eq!(place(&two).0, Corner::LowerRight);
    }

    #[test]
    fn legend_raises_the_top_when_every_corner_has_data() {
        // a fast sine fills the whole area: the top is raised by the legend's height
        let sine = [Series::line(
            "sine",
            (0..2000)
                .map(|i| (i as f64, (i as f64 * 0.3).sin()))
                .collect(),
        )];
        let (_, y) = bounds(&sine, false, false);
        let (c, y2) = place(&sine);
        assert_eq!(c, Corner::UpperRight);
        assert_eq!(y2.0, y.0);
        let h = (18.0 + 20.0) / AREA_PX.1;
        // the data's top (1.0 + 5 % pad) now lies below the legend box
        assert!(((y.1 - y2.0) / (y2.1 - y2.0)) <= 1.0 - h, "{y:?} {y2:?}");
        // and the raised range puts nothing under the legend
        let spec = PlotSpec::default();
        let (again, y3) = legend_place(&sine, &spec, bounds(&sine, false, false).0, y2);
        assert_eq!((again, y3), (Corner::UpperRight, y2));
    }
}
