//! Plots for people: SVG or PNG, chosen by the file extension.
//!
//! Plots use plotters without its `ttf` feature (which needs system font
//! libraries a fresh machine lacks); text is drawn with the bundled
//! `ab_glyph` renderer and a font shipped in this crate.

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
    let ((x0, x1), (y0, y1)) = bounds(series, spec.log_x, spec.log_y);
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
        let dir = std::env::temp_dir().join(format!("clino-report-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
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
}
