//! Roll-test quality checks (MWD calibration paper, eqs 13–15).
//!
//! The tool is held at a fixed inclination (usually 45°) and turned about its
//! own axis through 12 positions; a good calibration gives the same answer in
//! each: max − min of inclination < 0.1°, of azimuth < 1°, of G_L < 0.003 g.
//! In a station file, readings that share one `md_m` form a roll test.

use super::Station;
use serde::Serialize;

/// The limits of eqs 13–15.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct RollTestLimits {
    /// Inclination spread, deg (eq 13: 0.1).
    pub inclination_deg: f64,
    /// Azimuth spread, deg (eq 14: 1).
    pub azimuth_deg: f64,
    /// G_L spread, in units of standard gravity (eq 15: 0.003).
    pub g_total_g: f64,
}

impl Default for RollTestLimits {
    fn default() -> Self {
        Self {
            inclination_deg: 0.1,
            azimuth_deg: 1.0,
            g_total_g: 0.003,
        }
    }
}

/// The verdict of one roll test.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RollTest {
    /// Depth of the test, m.
    pub md_m: f64,
    /// Number of readings (the paper uses 12).
    pub n: usize,
    /// max − min of inclination, deg.
    pub inclination_range_deg: f64,
    /// Circular max − min of azimuth, deg (None when any reading has none).
    pub azimuth_range_deg: Option<f64>,
    /// max − min of G_L, g.
    pub g_total_range_g: f64,
    /// Eq 13 holds.
    pub inclination_ok: bool,
    /// Eq 14 holds (None: azimuth not available).
    pub azimuth_ok: Option<bool>,
    /// Eq 15 holds.
    pub g_total_ok: bool,
    /// All available checks hold.
    pub pass: bool,
}

/// The smallest arc containing all angles (deg): 360° minus the largest gap.
pub fn circular_range_deg(angles: &[f64]) -> f64 {
    if angles.len() < 2 {
        return 0.0;
    }
    let mut a: Vec<f64> = angles.iter().map(|x| x.rem_euclid(360.0)).collect();
    a.sort_by(|x, y| x.total_cmp(y));
    let mut gap = a[0] + 360.0 - a[a.len() - 1];
    for w in a.windows(2) {
        gap = gap.max(w[1] - w[0]);
    }
    360.0 - gap
}

/// Roll tests: groups of two or more consecutive stations at the same depth.
pub fn roll_tests(stations: &[Station], lim: &RollTestLimits) -> Vec<RollTest> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < stations.len() {
        let mut j = i + 1;
        while j < stations.len() && stations[j].md_m == stations[i].md_m {
            j += 1;
        }
        let g = &stations[i..j];
        if g.len() >= 2 {
            let range = |f: &dyn Fn(&Station) -> f64| {
                let (lo, hi) = g
                    .iter()
                    .map(f)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |a, x| {
                        (a.0.min(x), a.1.max(x))
                    });
                hi - lo
            };
            let inc = range(&|s| s.inclination_deg);
            let gl = range(&|s| s.g_total_g);
            let az: Option<Vec<f64>> = g.iter().map(|s| s.azimuth_deg).collect();
            let azr = az.map(|a| circular_range_deg(&a));
            let inc_ok = inc < lim.inclination_deg;
            let g_ok = gl < lim.g_total_g;
            let az_ok = azr.map(|r| r < lim.azimuth_deg);
            out.push(RollTest {
                md_m: g[0].md_m,
                n: g.len(),
                inclination_range_deg: inc,
                azimuth_range_deg: azr,
                g_total_range_g: gl,
                inclination_ok: inc_ok,
                azimuth_ok: az_ok,
                g_total_ok: g_ok,
                pass: inc_ok && g_ok && az_ok.unwrap_or(true),
            });
        }
        i = j;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::super::{StationReading, SurveyOptions, station};
    use super::*;
    use clino_core::Vec3;
    use clino_core::sensor::MwdModel;
    use nalgebra::{Rotation3, Vector3};

    fn roll(model: Option<&MwdModel>) -> Vec<Station> {
        // 12 rotations at 45° inclination, azimuth 60°
        (0..12)
            .map(|k| {
                let c = Rotation3::from_axis_angle(&Vector3::z_axis(), 60f64.to_radians())
                    * Rotation3::from_axis_angle(&Vector3::y_axis(), 45f64.to_radians())
                    * Rotation3::from_axis_angle(
                        &Vector3::z_axis(),
                        (30.0 * k as f64).to_radians(),
                    );
                let f = -(c.transpose() * Vec3::new(0.0, 0.0, clino_core::G0));
                let h = c.transpose() * Vec3::new(24.0, 0.0, 41.0);
                // a miscalibrated tool reads raw = model⁻¹(f)
                let raw = model.map(|m| m.invert(f, 30.0).unwrap()).unwrap_or(f);
                station(
                    &StationReading {
                        md_m: 500.0,
                        line: k + 2,
                        acc_m_s2: raw,
                        mag_ut: Some(h),
                        temp_c: None,
                    },
                    &SurveyOptions::default(),
                )
            })
            .collect()
    }

    #[test]
    fn calibrated_tool_passes_miscalibrated_fails() {
        let r = roll_tests(&roll(None), &RollTestLimits::default());
        assert_eq!(r.len(), 1);
        assert_eq!(r[0].n, 12);
        assert!(r[0].pass && r[0].inclination_range_deg < 1e-9, "{r:?}");
        let mut m = MwdModel::identity(30.0);
        m.bias[0][0] = 0.05; // 5 mg bias on x
        m.scale[1][0] = 1.01;
        let r = roll_tests(&roll(Some(&m)), &RollTestLimits::default());
        assert!(!r[0].pass, "{r:?}");
        assert!(!r[0].inclination_ok && r[0].inclination_range_deg > 0.1);
    }

    #[test]
    fn circular_range_wraps() {
        assert!((circular_range_deg(&[359.6, 0.2, 359.9]) - 0.6).abs() < 1e-9);
        assert!((circular_range_deg(&[10.0, 20.0]) - 10.0).abs() < 1e-12);
        assert_eq!(circular_range_deg(&[5.0]), 0.0);
    }
}

#[cfg(test)]
mod calibrated_roll_test {
    use super::super::{StationReading, SurveyOptions, calibrate_readings, survey};
    use crate::calib::{self, CalibrationFile, fit};
    use crate::sim::calib as synth;
    use clino_core::Vec3;
    use nalgebra::{Rotation3, Vector3};

    #[test]
    fn calibration_turns_a_failing_roll_test_into_a_pass() {
        // calibrate the simulated poorly calibrated triad (30 parameters, 25–80 °C)
        let opt = synth::SynthOptions::default();
        let mut ups = synth::cube_directions();
        ups.extend(synth::cube_directions());
        ups.extend(synth::cube_directions());
        let att = synth::attitudes_from_ups(&ups);
        let temps = synth::spread_temperatures(opt.temp_range_c, att.len());
        let obs: Vec<_> = synth::accel_pose_observations(&opt, &att, &temps, 100)
            .into_iter()
            .map(|(o, _)| o)
            .collect();
        let f = fit::fit_triad(
            &obs,
            &fit::FitOptions {
                use_ref_inclination: false,
                ..fit::FitOptions::accel(fit::ModelKind::Mwd30)
            },
        )
        .unwrap();
        let mut file = CalibrationFile::default();
        file.set(f.kind, calib::entry_from_fit(&f, "test"));
        // a roll test at 45° inclination, 70 °C, read by that triad
        let mut readings: Vec<StationReading> = (0..12)
            .map(|k| {
                let c = Rotation3::from_axis_angle(&Vector3::z_axis(), 1.0)
                    * Rotation3::from_axis_angle(&Vector3::y_axis(), 45f64.to_radians())
                    * Rotation3::from_axis_angle(
                        &Vector3::z_axis(),
                        (30.0 * k as f64).to_radians(),
                    );
                let truth = -(c.transpose() * Vec3::new(0.0, 0.0, clino_core::G0));
                let h = c.transpose() * Vec3::new(24.0, 0.0, 41.0);
                StationReading {
                    md_m: 800.0,
                    line: k + 2,
                    acc_m_s2: opt.accel.invert(truth, 70.0).unwrap(),
                    mag_ut: Some(h),
                    temp_c: Some(70.0),
                }
            })
            .collect();
        let raw = survey(&readings, &SurveyOptions::default()).unwrap();
        assert!(!raw.roll_tests[0].pass, "{:?}", raw.roll_tests);
        calibrate_readings(&mut readings, &file).unwrap();
        let cal = survey(&readings, &SurveyOptions::default()).unwrap();
        let r = &cal.roll_tests[0];
        assert!(r.pass && r.inclination_range_deg < 0.01, "{r:?}");
    }
}
