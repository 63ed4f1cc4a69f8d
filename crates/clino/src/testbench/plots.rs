//! Plots of test-bench results (SVG or PNG by extension, via [`crate::report`]).

use super::allan::AxisAllan;
use super::conical::ConicalPoint;
use super::orbit::OrbitPoint;
use super::static_test::StaticResult;
use crate::Result;
use crate::report::{PlotSpec, Series, line_plot};
use std::path::Path;

/// Amplitude-frequency curves (dB against log frequency) of a conical sweep.
pub fn conical_plot(path: &Path, pts: &[ConicalPoint]) -> Result<()> {
    let col = |name: &str, f: &dyn Fn(&ConicalPoint) -> Option<f64>| {
        Series::line(
            name,
            pts.iter()
                .filter_map(|p| f(p).map(|v| (p.freq_hz, v)))
                .collect(),
        )
    };
    let series: Vec<Series> = vec![
        col("gyro x", &|p| p.gyro_x_db),
        col("gyro y", &|p| p.gyro_y_db),
        col("gyro z", &|p| p.gyro_z_db),
        col("accel x", &|p| p.accel_x_db),
        col("accel y", &|p| p.accel_y_db),
        col("tilt x (quaternion)", &|p| p.tilt_x_db),
        col("tilt y (quaternion)", &|p| p.tilt_y_db),
        col("sin phi", &|p| p.sin_phi_db),
        col("tan theta", &|p| p.tan_theta_db),
    ]
    .into_iter()
    .filter(|s| !s.points.is_empty())
    .collect();
    let spec = PlotSpec {
        title: "Sensitivity under conical motion about z".into(),
        x_label: "frequency (Hz)".into(),
        y_label: "sensitivity (dB)".into(),
        log_x: true,
        log_y: false,
    };
    line_plot(path, &spec, &series)
}

/// Cross-coupling (peak-to-peak and fitted) against frequency.
pub fn orbit_plot(path: &Path, pts: &[OrbitPoint]) -> Result<()> {
    let col = |name: &str, f: &dyn Fn(&OrbitPoint) -> f64| {
        Series::line(name, pts.iter().map(|p| (p.freq_hz, f(p))).collect())
    };
    let series = vec![
        col("roll p-p", &|p| p.roll_pp_deg),
        col("pitch p-p", &|p| p.pitch_pp_deg),
        col("roll fitted p-p", &|p| p.roll_fit_pp_deg),
        col("pitch fitted p-p", &|p| p.pitch_fit_pp_deg),
    ];
    let spec = PlotSpec {
        title: "Cross-coupling under positional orbits".into(),
        x_label: "frequency (Hz)".into(),
        y_label: "tilt peak-to-peak (deg)".into(),
        log_x: false,
        log_y: false,
    };
    line_plot(path, &spec, &series)
}

/// Allan deviation of every axis, log-log.
pub fn allan_plot(path: &Path, axes: &[AxisAllan]) -> Result<()> {
    let series: Vec<Series> = axes
        .iter()
        .map(|a| {
            Series::line(
                format!("{} ({})", a.axis, a.unit),
                a.points.iter().map(|p| (p.tau_s, p.adev)).collect(),
            )
        })
        .collect();
    let spec = PlotSpec {
        title: "Allan deviation (overlapping)".into(),
        x_label: "averaging time tau (s)".into(),
        y_label: "Allan deviation (rad/s or m/s^2)".into(),
        log_x: true,
        log_y: true,
    };
    line_plot(path, &spec, &series)
}

/// Roll and pitch over a static test.
pub fn static_plot(path: &Path, r: &StaticResult) -> Result<()> {
    let series = vec![
        Series::line("roll", r.trace.iter().map(|p| (p[0], p[1])).collect()),
        Series::line("pitch", r.trace.iter().map(|p| (p[0], p[2])).collect()),
    ];
    let spec = PlotSpec {
        title: format!("Static test, filter {}", r.filter),
        x_label: "time (s)".into(),
        y_label: "tilt (deg)".into(),
        log_x: false,
        log_y: false,
    };
    line_plot(path, &spec, &series)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ImuModel;
    use crate::testbench::conical::{ConicalConfig, run_conical};

    #[test]
    fn writes_a_conical_svg() {
        let cfg = ConicalConfig::new(0.1, vec![0.5, 2.0], ImuModel::ideal(), "poisson");
        let pts = run_conical(&cfg, &mut |_, _| {}).unwrap();
        let dir = tempfile::Builder::new()
            .prefix("clino-tbplot-")
            .tempdir()
            .unwrap();
        let p = dir.path().join("c.svg");
        conical_plot(&p, &pts).unwrap();
        assert!(std::fs::read_to_string(&p).unwrap().contains("<svg"));
    }
}
