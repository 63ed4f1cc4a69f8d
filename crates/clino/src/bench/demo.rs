//! The test-bench section of `clino demo`.

use super::conical::{ConicalConfig, run_conical};
use super::filters::BEST_FILTER;
use super::orbit::{OrbitConfig, run_orbit};
use crate::Result;
use crate::sim::ImuModel;
use std::fmt::Write;

/// First-order bandwidth that puts a sensor 3.6 dB down at 3.15 Hz, like the
/// BW-VG527 of the Stewart-platform paper: f_c = 3.15/√(10^0.36 − 1) ≈ 2.77 Hz.
pub fn source_like_bandwidth_hz() -> f64 {
    3.15 / (10f64.powf(0.36) - 1.0).sqrt()
}

/// The filter of the source-like instrument: the complementary filter with the
/// MPU6050 paper's k = 0.05 per sample at 100 Hz, i.e. τ = −0.01/ln 0.95 ≈ 0.195 s
/// (kept as a time constant so it holds at any sample rate).
pub const SOURCE_LIKE_FILTER: &str = "complementary:tau=0.195";

/// Frequency response (5° cone) and cross-coupling (20 mm orbits) of clino's
/// best current filter on the `mpu6050` preset, next to a source-like
/// instrument (the same sensor band-limited to 2.77 Hz, with the short
/// complementary filter). Deterministic (fixed seeds); no files.
pub fn demo_summary() -> Result<String> {
    let cone_f = vec![0.5, 1.0, 2.0, 3.15, 5.0, 10.0];
    let orbit_f = vec![0.1, 0.2, 0.4, 0.5, 0.8];
    let rate = 200.0;
    let best = ImuModel::mpu6050();
    let src = ImuModel::mpu6050().with_bandwidth(source_like_bandwidth_hz());
    let cone = |sensor: &ImuModel, filter: &str| {
        let mut c = ConicalConfig::new(5f64.to_radians(), cone_f.clone(), sensor.clone(), filter);
        c.rate_hz = rate;
        run_conical(&c, &mut |_, _| {})
    };
    let orbit = |sensor: &ImuModel, filter: &str| {
        let mut c = OrbitConfig::new(0.02, orbit_f.clone(), sensor.clone(), filter);
        c.rate_hz = rate;
        run_orbit(&c, &mut |_, _| {})
    };
    let (cb, cs) = (cone(&best, BEST_FILTER)?, cone(&src, SOURCE_LIKE_FILTER)?);
    let (ob, os) = (orbit(&best, BEST_FILTER)?, orbit(&src, SOURCE_LIKE_FILTER)?);
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Dynamic test bench (simulated Stewart platform, {rate} Hz, mpu6050 preset)"
    );
    let _ = writeln!(
        s,
        "  clino: {BEST_FILTER}; source-like: sensor band-limited to {:.2} Hz + {SOURCE_LIKE_FILTER}",
        source_like_bandwidth_hz()
    );
    let _ = writeln!(s, "  tilt sensitivity, 5° cone about z (quaternion x, dB):");
    let _ = writeln!(s, "    freq_hz   clino_db   source_like_db");
    for (b, o) in cb.iter().zip(&cs) {
        let _ = writeln!(
            s,
            "    {:7.2}   {:+8.3}   {:+8.3}",
            b.freq_hz,
            b.tilt_x_db.unwrap_or(f64::NAN),
            o.tilt_x_db.unwrap_or(f64::NAN)
        );
    }
    let _ = writeln!(
        s,
        "  cross-coupling, 20 mm orbits (roll; p-p and fitted p-p, degrees):"
    );
    let _ = writeln!(
        s,
        "    freq_hz   clino_pp  clino_fit   source_pp  source_fit"
    );
    for (b, o) in ob.iter().zip(&os) {
        let _ = writeln!(
            s,
            "    {:7.2}   {:8.3}  {:9.3}   {:9.3}  {:10.3}",
            b.freq_hz, b.roll_pp_deg, b.roll_fit_pp_deg, o.roll_pp_deg, o.roll_fit_pp_deg
        );
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn best_filter_meets_the_issue_targets_on_mpu6050() {
        // tilt attenuation within 0.1 dB up to 10 Hz (5° cone, declining to the gyro range)
        let c = ConicalConfig::new(
            5f64.to_radians(),
            vec![0.1, 3.15, 10.0],
            ImuModel::mpu6050(),
            BEST_FILTER,
        );
        for p in run_conical(&c, &mut |_, _| {}).unwrap() {
            for v in [p.tilt_x_db, p.tilt_y_db].map(Option::unwrap) {
                assert!(v.abs() < 0.1, "{p:?}");
            }
        }
        // fitted cross-coupling below 0.2° p-p for 20 mm orbits, 0.1 … 0.8 Hz
        let o = OrbitConfig::new(0.02, vec![0.1, 0.8], ImuModel::mpu6050(), BEST_FILTER);
        for p in run_orbit(&o, &mut |_, _| {}).unwrap() {
            assert!(p.roll_fit_pp_deg < 0.2 && p.pitch_fit_pp_deg < 0.2, "{p:?}");
        }
    }

    /// clino's `dynamic` filter at its defaults on `mpu6050` (200 Hz): the cone
    /// target holds from 0.2 to 10 Hz and the orbit target at 0.8 Hz, where its
    /// velocity loop works (8× below Mahony's coupling). Below 0.2 Hz (cone)
    /// and 0.8 Hz (orbit) it fails; see the next test and the tb2 note.
    #[test]
    fn dynamic_meets_the_targets_where_it_is_in_motion() {
        let c = ConicalConfig::new(
            5f64.to_radians(),
            vec![0.2, 3.15, 10.0],
            ImuModel::mpu6050(),
            "dynamic",
        );
        for p in run_conical(&c, &mut |_, _| {}).unwrap() {
            for v in [p.tilt_x_db, p.tilt_y_db].map(Option::unwrap) {
                assert!(v.abs() < 0.1, "{p:?}");
            }
        }
        let o = OrbitConfig::new(0.02, vec![0.8], ImuModel::mpu6050(), "dynamic");
        let p = &run_orbit(&o, &mut |_, _| {}).unwrap()[0];
        assert!(
            p.roll_fit_pp_deg < 0.05 && p.pitch_fit_pp_deg < 0.05,
            "{p:?}"
        );
    }

    /// Why `dynamic` misses the orbit target from 0.2 to 0.7 Hz: a pure
    /// translation (zero rate) whose specific force varies by less than the
    /// rest threshold (0.5 m/s² after the 2-Hz low-pass, against the 0.5-s
    /// mean) is taken for rest, and at rest the tilt is pulled to the
    /// accelerometer at p_r = 1 rad/s. The tilt then follows the apparent
    /// gravity through a first-order low-pass: fitted p-p
    /// = 2·(a/g)/√(1 + (ω/p_r)²) with a = ω²·Ŝ.
    #[test]
    fn dynamic_takes_a_slow_orbit_for_rest() {
        let f = 0.5;
        let o = OrbitConfig::new(0.02, vec![f], ImuModel::mpu6050(), "dynamic");
        let p = &run_orbit(&o, &mut |_, _| {}).unwrap()[0];
        let w = 2.0 * std::f64::consts::PI * f;
        let pr = clino_core::filter::DynamicParams::default().rest_bandwidth_rad_s;
        let expect =
            2.0 * (w * w * 0.02 / clino_core::G0).to_degrees() / (1.0 + (w / pr).powi(2)).sqrt();
        for v in [p.roll_fit_pp_deg, p.pitch_fit_pp_deg] {
            assert!((v / expect - 1.0).abs() < 0.05, "{p:?} vs {expect}");
        }
    }

    #[test]
    fn summary_shows_both_instruments() {
        let s = demo_summary().unwrap();
        eprintln!("{s}");
        assert!(s.contains("source-like") && s.contains("3.15"));
    }
    #[test]
    fn source_like_bandwidth_is_3_6_db_down_at_3_15_hz() {
        let g = crate::sim::Bandwidth::FirstOrder {
            cutoff_hz: source_like_bandwidth_hz(),
        }
        .gain(3.15);
        assert!((20.0 * g.log10() + 3.6).abs() < 1e-9);
    }
}
