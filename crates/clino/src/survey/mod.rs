//! Drilling surveys: inclination, azimuth, toolface and dip from a tool's
//! accelerometer and magnetometer; roll-test quality checks; the well path by
//! minimum curvature.
//!
//! ## The tool frame (drilling convention)
//! The tool's z axis points **down the hole**; x and y are across it, x being
//! the tool's reference (scribe line); the frame is right-handed. Readings are
//! specific force f (m/s²) and field h (µT) in this frame, so a vertical tool at
//! rest reads f = (0, 0, −g). The gravity vector in the tool frame is G = −f.
//! The navigation frame here is North-East-Down; the tool's attitude is
//! C = R_z(A)·R_y(I)·R_z(θ) (azimuth A, inclination I, gravity toolface θ),
//! which gives G = g·(−sin I·cos θ, sin I·sin θ, cos I).
//!
//! From "Error Analysis in Accelerometers Calibration of Measurement while
//! Drilling Instrument" (eqs 9–12), re-derived for this frame (the printed
//! eq 12 has garbled signs; the form below follows from the physics and is
//! tested against attitudes built from known angles):
//!
//! * G_L = |f| (eq 9), H_L = |h| (eq 10);
//! * inclination I = atan2(√(G_x² + G_y²), G_z) (eq 11), in [0°, 180°];
//! * azimuth A = atan2(G_L·(G_x·H_y − G_y·H_x), H_z·(G_x² + G_y²) − G_z·(G_x·H_x + G_y·H_y)),
//!   from (magnetic) north, clockwise (towards east), in [0°, 360°) (eq 12);
//! * gravity toolface θ = atan2(G_y, −G_x) = atan2(−f_y, f_x): the angle from
//!   the high side of the hole to the tool's x axis, clockwise looking down the hole;
//! * magnetic toolface = atan2(−h_y, h_x): in a vertical hole it equals A + θ;
//! * dip = asin(G·H/(G_L·H_L)), positive when the field points down.
//!
//! Azimuth and gravity toolface are undefined in a vertical hole (reported as
//! `None`); the magnetic toolface stays defined there.

pub mod qc;
pub mod stations;
pub mod trajectory;

pub use qc::{RollTest, RollTestLimits, roll_tests};
pub use stations::{StationReading, calibrate_readings, read_stations};
pub use trajectory::{TrajectoryPoint, minimum_curvature};

use crate::Result;
use clino_core::Vec3;
use serde::Serialize;

/// Settings of a survey computation.
#[derive(Clone, Debug)]
pub struct SurveyOptions {
    /// Magnetic declination added to the azimuth, deg (0: azimuth from magnetic north).
    pub declination_deg: f64,
    /// Roll-test limits (MWD paper eqs 13–15).
    pub limits: RollTestLimits,
}

impl Default for SurveyOptions {
    fn default() -> Self {
        Self {
            declination_deg: 0.0,
            limits: RollTestLimits::default(),
        }
    }
}

/// The survey quantities of one station.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Station {
    /// Measured depth, m.
    pub md_m: f64,
    /// 1-based line of the station in its file (0 when not from a file).
    pub line: u64,
    /// Total gravity G_L, m/s².
    pub g_total_m_s2: f64,
    /// Total gravity in units of standard gravity.
    pub g_total_g: f64,
    /// Total field H_L, µT (with a magnetometer).
    pub h_total_ut: Option<f64>,
    /// Inclination, deg in [0, 180].
    pub inclination_deg: f64,
    /// Azimuth from north, clockwise, deg in [0, 360) (None: vertical hole or no magnetometer).
    pub azimuth_deg: Option<f64>,
    /// Gravity toolface, deg in [0, 360) (None: vertical hole).
    pub gravity_toolface_deg: Option<f64>,
    /// Magnetic toolface, deg in [0, 360) (with a magnetometer).
    pub magnetic_toolface_deg: Option<f64>,
    /// Magnetic dip, deg (with a magnetometer).
    pub dip_deg: Option<f64>,
}

fn wrap360(x: f64) -> f64 {
    let r = x.rem_euclid(360.0);
    if r >= 360.0 || r == 0.0 { 0.0 } else { r }
}

/// Inclination, rad, from the specific force in the tool frame (z down the hole).
pub fn inclination(f: &Vec3) -> f64 {
    f.x.hypot(f.y).atan2(-f.z)
}

/// True when the hole is vertical to within rounding (azimuth and gravity toolface undefined).
fn is_vertical(f: &Vec3) -> bool {
    f.x.hypot(f.y) <= 1e-12 * f.norm()
}

/// Gravity toolface, rad in (−π, π], or None in a vertical hole.
pub fn gravity_toolface(f: &Vec3) -> Option<f64> {
    (!is_vertical(f)).then(|| (-f.y).atan2(f.x))
}

/// Magnetic azimuth, rad in (−π, π], from north clockwise, or None in a vertical hole.
pub fn azimuth(f: &Vec3, h: &Vec3) -> Option<f64> {
    if is_vertical(f) {
        return None;
    }
    let g = -f;
    let gl = g.norm();
    let num = gl * (g.x * h.y - g.y * h.x);
    let den = h.z * (g.x * g.x + g.y * g.y) - g.z * (g.x * h.x + g.y * h.y);
    Some(num.atan2(den))
}

/// Magnetic toolface, rad: atan2(−h_y, h_x).
pub fn magnetic_toolface(h: &Vec3) -> f64 {
    (-h.y).atan2(h.x)
}

/// Dip, rad: asin(G·H/(G_L·H_L)) with G = −f.
pub fn dip(f: &Vec3, h: &Vec3) -> f64 {
    ((-f).dot(h) / (f.norm() * h.norm()))
        .clamp(-1.0, 1.0)
        .asin()
}

/// Compute the survey quantities of one reading.
pub fn station(r: &StationReading, opt: &SurveyOptions) -> Station {
    let f = r.acc_m_s2;
    Station {
        md_m: r.md_m,
        line: r.line,
        g_total_m_s2: f.norm(),
        g_total_g: f.norm() / clino_core::G0,
        h_total_ut: r.mag_ut.map(|h| h.norm()),
        inclination_deg: inclination(&f).to_degrees(),
        azimuth_deg: r
            .mag_ut
            .and_then(|h| azimuth(&f, &h))
            .map(|a| wrap360(a.to_degrees() + opt.declination_deg)),
        gravity_toolface_deg: gravity_toolface(&f).map(|t| wrap360(t.to_degrees())),
        magnetic_toolface_deg: r
            .mag_ut
            .map(|h| wrap360(magnetic_toolface(&h).to_degrees())),
        dip_deg: r.mag_ut.map(|h| dip(&f, &h).to_degrees()),
    }
}

/// A whole survey: stations, roll tests, trajectory.
#[derive(Clone, Debug, Serialize)]
pub struct SurveyReport {
    /// Every reading's survey quantities, in file order.
    pub stations: Vec<Station>,
    /// Roll tests (readings repeated at one depth) with their verdicts.
    pub roll_tests: Vec<RollTest>,
    /// The well path at each distinct depth (repeated readings averaged).
    pub trajectory: Vec<TrajectoryPoint>,
}

impl Station {
    /// Every figure of the station is finite (the optional ones where present).
    fn is_finite(&self) -> bool {
        [
            Some(self.g_total_m_s2),
            Some(self.g_total_g),
            self.h_total_ut,
            Some(self.inclination_deg),
            self.azimuth_deg,
            self.gravity_toolface_deg,
            self.magnetic_toolface_deg,
            self.dip_deg,
        ]
        .iter()
        .flatten()
        .all(|v| v.is_finite())
    }
}

/// [`survey`] of a stations file (CSV or Parquet, [`read_stations`]),
/// calibrated first with `calibration` when one is given
/// ([`calibrate_readings`]): what `clino survey` runs. Every error names the
/// stations file (and the line and column where there is one).
pub fn survey_file(
    path: &std::path::Path,
    calibration: Option<&crate::calib::CalibrationFile>,
    opt: &SurveyOptions,
) -> Result<SurveyReport> {
    let named = |e: crate::Error| e.or_in_file(path);
    let mut readings = read_stations(path)?;
    if let Some(cal) = calibration {
        calibrate_readings(&mut readings, cal).map_err(named)?;
    }
    survey(&readings, opt).map_err(named)
}

/// Compute a survey from readings: stations, roll-test QC and the trajectory.
///
/// Every reading is checked against the physical bounds of a survey station
/// first ([`StationReading::check`]: |f| ≤ 4 g, |h| ≤ 1000 µT, |md| ≤ 100 km;
/// readings calibrated after loading are checked again here), and every
/// derived figure must be finite; errors name the reading's line and column.
pub fn survey(readings: &[StationReading], opt: &SurveyOptions) -> Result<SurveyReport> {
    if !opt.declination_deg.is_finite() || opt.declination_deg.abs() > 180.0 {
        return Err(crate::Error::new(
            crate::ErrorKind::InvalidInput,
            format!(
                "declination {} deg is outside −180 … 180°",
                opt.declination_deg
            ),
        ));
    }
    let mut stations = Vec::with_capacity(readings.len());
    for r in readings {
        r.check()?;
        let s = station(r, opt);
        if !s.is_finite() {
            return Err(crate::Error::new(
                crate::ErrorKind::InvalidInput,
                format!("the reading gives non-finite survey figures: {s:?}"),
            )
            .at_line(r.line));
        }
        stations.push(s);
    }
    let roll = roll_tests(&stations, &opt.limits);
    let trajectory = trajectory::from_stations(&stations)?;
    if let Some(p) = trajectory.iter().find(|p| {
        ![
            p.tvd_m,
            p.north_m,
            p.east_m,
            p.dogleg_deg,
            p.dls_deg_per_30m,
        ]
        .iter()
        .all(|v| v.is_finite())
    }) {
        return Err(crate::Error::new(
            crate::ErrorKind::InvalidInput,
            format!("the trajectory is not finite at md {} m: {p:?}", p.md_m),
        ));
    }
    Ok(SurveyReport {
        stations,
        roll_tests: roll,
        trajectory,
    })
}

/// The `clino demo` section: a simulated build-and-hold well surveyed from
/// tool readings (MPU-class noise), a 12-toolface roll test, and the trajectory.
pub fn demo_summary() -> Result<String> {
    use nalgebra::{Rotation3, Vector3};
    use std::fmt::Write;
    let g = clino_core::G0;
    // Earth field: 50 µT, dip 60° (NED)
    let (ht, dip) = (50.0, 60f64.to_radians());
    let h_ned = Vector3::new(ht * dip.cos(), 0.0, ht * dip.sin());
    // deterministic small noise (accelerometer 0.5 mg, magnetometer 0.05 µT)
    let mut state: u64 = 0x5eed;
    let mut noise = |s: f64| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2.0 * s * 3f64.sqrt()
    };
    let reading = |md: f64, inc: f64, azi: f64, tf: f64, noise: &mut dyn FnMut(f64) -> f64| {
        let c = Rotation3::from_axis_angle(&Vector3::z_axis(), azi.to_radians())
            * Rotation3::from_axis_angle(&Vector3::y_axis(), inc.to_radians())
            * Rotation3::from_axis_angle(&Vector3::z_axis(), tf.to_radians());
        let gt = c.inverse() * Vector3::new(0.0, 0.0, g);
        let h = c.inverse() * h_ned;
        let n = |s: f64, f: &mut dyn FnMut(f64) -> f64| Vector3::new(f(s), f(s), f(s));
        StationReading {
            md_m: md,
            line: 0,
            acc_m_s2: -gt + n(0.5e-3 * g, noise),
            mag_ut: Some(h + n(0.05, noise)),
            temp_c: None,
        }
    };
    // truth: vertical to 300 m, build 3°/30 m to 30°, hold; azimuth 45°
    let mut readings = Vec::new();
    let mut truth = Vec::new();
    for k in 0..=20 {
        let md = 60.0 * k as f64;
        let inc = ((md - 300.0).max(0.0) / 30.0 * 3.0).min(30.0);
        let tf = 37.0 * k as f64 % 360.0;
        readings.push(reading(md, inc, 45.0, tf, &mut noise));
        truth.push((md, inc));
    }
    // roll test at 900 m: 12 toolfaces
    for j in 0..12 {
        readings.push(reading(900.0, 30.0, 45.0, 30.0 * j as f64, &mut noise));
    }
    readings.sort_by(|a, b| a.md_m.total_cmp(&b.md_m));
    let rep = survey(&readings, &SurveyOptions::default())?;
    let mut worst_inc: f64 = 0.0;
    let mut worst_azi: f64 = 0.0;
    for st in &rep.stations {
        let inc_t = truth
            .iter()
            .find(|t| (t.0 - st.md_m).abs() < 1e-9)
            .map_or(30.0, |t| t.1);
        worst_inc = worst_inc.max((st.inclination_deg - inc_t).abs());
        if inc_t > 5.0
            && let Some(a) = st.azimuth_deg
        {
            worst_azi = worst_azi.max((a - 45.0).abs());
        }
    }
    let last = rep.trajectory.last();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Build-and-hold well (vertical to 300 m, 3°/30 m to 30°, azimuth 45°), {} stations read by a tool\n\
         with 0.5 mg accelerometer and 0.05 µT magnetometer noise (field 50 µT, dip 60°):",
        rep.stations.len()
    );
    let _ = writeln!(
        s,
        "  largest inclination error {worst_inc:.3}°, azimuth error {worst_azi:.3}° (stations above 5°)"
    );
    for r in &rep.roll_tests {
        let _ = writeln!(
            s,
            "  roll test at {:.0} m ({} toolfaces): Δinc {:.3}°, Δazi {:.3}°, ΔG_L {:.5} g → {}",
            r.md_m,
            r.n,
            r.inclination_range_deg,
            r.azimuth_range_deg.unwrap_or(f64::NAN),
            r.g_total_range_g,
            if r.pass { "pass" } else { "FAIL" }
        );
    }
    if let Some(p) = last {
        let max_dls = rep
            .trajectory
            .iter()
            .map(|p| p.dls_deg_per_30m)
            .fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "  minimum curvature: MD {:.0} m → TVD {:.1} m, north {:.1} m, east {:.1} m; largest DLS {:.2}°/30 m",
            p.md_m, p.tvd_m, p.north_m, p.east_m, max_dls
        );
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::{Rotation3, Vector3};

    /// Tool readings for known angles, from the attitude C = R_z(A)·R_y(I)·R_z(θ) (NED).
    fn readings(inc_deg: f64, azi_deg: f64, tf_deg: f64, dip_deg: f64) -> (Vec3, Vec3) {
        let (i, a, t, d) = (
            inc_deg.to_radians(),
            azi_deg.to_radians(),
            tf_deg.to_radians(),
            dip_deg.to_radians(),
        );
        let c = Rotation3::from_axis_angle(&Vector3::z_axis(), a)
            * Rotation3::from_axis_angle(&Vector3::y_axis(), i)
            * Rotation3::from_axis_angle(&Vector3::z_axis(), t);
        let g_ned = Vec3::new(0.0, 0.0, clino_core::G0);
        let h_ned = Vec3::new(48.0 * d.cos(), 0.0, 48.0 * d.sin());
        let f = -(c.transpose() * g_ned);
        let h = c.transpose() * h_ned;
        (f, h)
    }

    fn st(inc: f64, azi: f64, tf: f64) -> Station {
        let (f, h) = readings(inc, azi, tf, 60.0);
        station(
            &StationReading {
                md_m: 100.0,
                line: 0,
                acc_m_s2: f,
                mag_ut: Some(h),
                temp_c: None,
            },
            &SurveyOptions::default(),
        )
    }

    fn ang_eq(a: f64, b: f64, tol: f64) {
        let d = (a - b + 180.0).rem_euclid(360.0) - 180.0;
        assert!(d.abs() < tol, "{a} vs {b}");
    }

    #[test]
    fn vertical_tool_at_rest_reads_minus_g_on_z() {
        let (f, _) = readings(0.0, 0.0, 0.0, 60.0);
        assert_relative_eq!(f, Vec3::new(0.0, 0.0, -clino_core::G0), epsilon = 1e-12);
        // horizontal, high side up at toolface 0: x axis points up, so f_x = +g
        let (f, _) = readings(90.0, 0.0, 0.0, 60.0);
        assert_relative_eq!(f, Vec3::new(clino_core::G0, 0.0, 0.0), epsilon = 1e-12);
    }

    #[test]
    fn closed_forms_for_known_orientations_all_quadrants() {
        for &inc in &[0.5, 10.0, 45.0, 89.0, 90.0, 120.0, 179.0] {
            for &azi in &[
                0.0, 30.0, 89.9, 90.0, 135.0, 180.0, 200.0, 270.0, 315.0, 359.5,
            ] {
                for &tf in &[0.0, 45.0, 90.0, 180.0, 250.0, 330.0] {
                    let s = st(inc, azi, tf);
                    assert_relative_eq!(s.inclination_deg, inc, epsilon = 1e-9);
                    ang_eq(s.azimuth_deg.unwrap(), azi, 1e-7);
                    ang_eq(s.gravity_toolface_deg.unwrap(), tf, 1e-7);
                    assert_relative_eq!(s.dip_deg.unwrap(), 60.0, epsilon = 1e-9);
                    assert_relative_eq!(s.g_total_g, 1.0, epsilon = 1e-12);
                    assert_relative_eq!(s.h_total_ut.unwrap(), 48.0, epsilon = 1e-12);
                    assert!((0.0..360.0).contains(&s.azimuth_deg.unwrap()));
                }
            }
        }
    }

    #[test]
    fn json_stations_carry_the_documented_keys() {
        let (f, h) = readings(30.0, 200.0, 40.0, 60.0);
        let r = StationReading {
            md_m: 12.5,
            line: 2,
            acc_m_s2: f,
            mag_ut: Some(h),
            temp_c: None,
        };
        let rep = survey(
            &[r, StationReading { md_m: 40.0, ..r }],
            &SurveyOptions::default(),
        )
        .unwrap();
        let v = serde_json::to_value(&rep).unwrap();
        let s0 = &v["stations"][0];
        assert_eq!(s0["md_m"], 12.5);
        for k in ["inclination_deg", "azimuth_deg", "gravity_toolface_deg"] {
            assert!(s0[k].is_f64(), "{k}: {s0}");
        }
        assert_eq!(v["trajectory"].as_array().unwrap().len(), 2);
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
        #[test]
        fn any_attitude_round_trips(inc in 0.01f64..179.99, azi in 0.0f64..360.0, tf in 0.0f64..360.0, d in -80.0f64..80.0) {
            let (f, h) = readings(inc, azi, tf, d);
            let s = station(&StationReading { md_m: 0.0, line: 0, acc_m_s2: f, mag_ut: Some(h), temp_c: None }, &SurveyOptions::default());
            proptest::prop_assert!((s.inclination_deg - inc).abs() < 1e-8);
            let da = (s.azimuth_deg.unwrap() - azi + 180.0).rem_euclid(360.0) - 180.0;
            let dt = (s.gravity_toolface_deg.unwrap() - tf + 180.0).rem_euclid(360.0) - 180.0;
            proptest::prop_assert!(da.abs() < 1e-6 && dt.abs() < 1e-6, "azi {} tf {}", da, dt);
            proptest::prop_assert!((s.dip_deg.unwrap() - d).abs() < 1e-8);
        }
    }

    #[test]
    fn non_physical_readings_are_errors_not_nan_figures() {
        let (f, h) = readings(30.0, 200.0, 40.0, 60.0);
        let good = StationReading {
            md_m: 10.0,
            line: 2,
            acc_m_s2: f,
            mag_ut: Some(h),
            temp_c: None,
        };
        let bad = StationReading {
            md_m: 20.0,
            line: 3,
            acc_m_s2: Vec3::new(1e308, f.y, f.z),
            ..good
        };
        let e = survey(&[good, bad], &SurveyOptions::default()).unwrap_err();
        assert_eq!((e.line, e.column.as_deref()), (Some(3), Some("acc_x_m_s2")));
        // a field of 1e200 µT would give H_L = inf and a NaN dip
        let bad = StationReading {
            md_m: 20.0,
            line: 3,
            mag_ut: Some(Vec3::new(1e200, 0.0, 0.0)),
            ..good
        };
        let e = survey(&[good, bad], &SurveyOptions::default()).unwrap_err();
        assert_eq!(e.column.as_deref(), Some("mag_x_uT"));
        let opt = SurveyOptions {
            declination_deg: f64::NAN,
            ..Default::default()
        };
        assert!(survey(&[good], &opt).is_err());
        assert!(survey(&[good], &SurveyOptions::default()).is_ok());
    }

    #[test]
    fn vertical_hole_edge_cases() {
        // exactly vertical: azimuth and gravity toolface undefined, magnetic toolface = A + θ
        for &(azi, tf) in &[(0.0, 0.0), (40.0, 30.0), (200.0, 300.0)] {
            let s = st(0.0, azi, tf);
            assert_eq!(s.inclination_deg, 0.0);
            assert!(s.azimuth_deg.is_none() && s.gravity_toolface_deg.is_none());
            ang_eq(s.magnetic_toolface_deg.unwrap(), azi + tf, 1e-9);
        }
        // 0.01° off vertical: everything defined and exact
        let s = st(0.01, 123.0, 77.0);
        ang_eq(s.azimuth_deg.unwrap(), 123.0, 1e-6);
        ang_eq(s.gravity_toolface_deg.unwrap(), 77.0, 1e-6);
        // upside down (180°)
        let s = st(180.0, 0.0, 0.0);
        assert_relative_eq!(s.inclination_deg, 180.0, epsilon = 1e-12);
        assert!(s.azimuth_deg.is_none());
        // declination shifts the azimuth
        let (f, h) = readings(30.0, 350.0, 0.0, 60.0);
        let s = station(
            &StationReading {
                md_m: 0.0,
                line: 0,
                acc_m_s2: f,
                mag_ut: Some(h),
                temp_c: None,
            },
            &SurveyOptions {
                declination_deg: 15.0,
                ..Default::default()
            },
        );
        ang_eq(s.azimuth_deg.unwrap(), 5.0, 1e-9);
        // no magnetometer: inclination and gravity toolface only
        let s = station(
            &StationReading {
                md_m: 0.0,
                line: 0,
                acc_m_s2: f,
                mag_ut: None,
                temp_c: None,
            },
            &SurveyOptions::default(),
        );
        assert!(s.azimuth_deg.is_none() && s.dip_deg.is_none());
        assert!(s.gravity_toolface_deg.is_some());
    }
}
