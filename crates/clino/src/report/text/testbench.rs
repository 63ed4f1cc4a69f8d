//! Text of `clino testbench conical|orbit|static|analyze`.

use super::opt3 as opt;
use crate::testbench::conical::ConicalPoint;
use crate::testbench::orbit::OrbitPoint;
use crate::testbench::recording::{Analysis, Excitation};
use crate::testbench::static_test::StaticResult;
use std::fmt::Write;

/// The frequency-response table of a conical run: one row per frequency,
/// sensitivities in dB (`-` where the record lacks the channel).
pub fn conical(pts: &[ConicalPoint]) -> String {
    let mut s = String::from(
        "freq_hz  alpha_deg gyro_x_db gyro_y_db gyro_z_db accel_x_db accel_y_db tilt_x_db tilt_y_db sin_phi_db tan_theta_db\n",
    );
    for p in pts {
        let _ = writeln!(
            s,
            "{:7.3}  {:9.3} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9} {:>10} {:>12}",
            p.freq_hz,
            p.alpha_deg,
            opt(p.gyro_x_db),
            opt(p.gyro_y_db),
            opt(p.gyro_z_db),
            opt(p.accel_x_db),
            opt(p.accel_y_db),
            opt(p.tilt_x_db),
            opt(p.tilt_y_db),
            opt(p.sin_phi_db),
            opt(p.tan_theta_db)
        );
    }
    s
}

/// The cross-coupling table of an orbit run, with the legend of its two
/// forms (max − min and fitted); `on_platform` adds the legend of the
/// platform's columns (orbit made, the platform's own tilt).
pub fn orbit(pts: &[OrbitPoint], on_platform: bool) -> String {
    let mut s = String::from(
        "# tilt error under the orbit, degrees: *_pp = max − min, *_fit_pp = 2 × sine fitted at the orbit frequency\n",
    );
    if on_platform {
        s += "# on the simulated platform: orbit_*_mm = amplitude actually made, ref_*_pp_deg = the platform's own tilt (from forward kinematics of the legs)\n";
    }
    s += "freq_hz  roll_pp_deg pitch_pp_deg roll_fit_pp_deg pitch_fit_pp_deg  orbit_x_mm orbit_y_mm orbit_z_mm  ref_roll_pp_deg ref_pitch_pp_deg\n";
    for p in pts {
        let [ax, ay, az] = p.orbit_amplitude_mm.unwrap_or([f64::NAN; 3]);
        let [rr, rp] = p.reference_tilt_pp_deg.unwrap_or([f64::NAN; 2]);
        let _ = writeln!(
            s,
            "{:7.3}  {:11.4} {:12.4} {:15.4} {:16.4}  {:10.3} {:10.3} {:10.3}  {:15.2e} {:16.2e}",
            p.freq_hz,
            p.roll_pp_deg,
            p.pitch_pp_deg,
            p.roll_fit_pp_deg,
            p.pitch_fit_pp_deg,
            ax,
            ay,
            az,
            rr,
            rp
        );
    }
    s
}

/// The static test: filter, span, and the drift and noise of roll and pitch.
pub fn static_test(r: &StaticResult) -> String {
    let mut s = format!(
        "static test: filter {}, {:.1} s, {} samples\n",
        r.filter, r.duration_s, r.samples
    );
    s += "angle  mean_deg   drift_deg  drift_rate_deg_s  noise_std_deg  pp_deg\n";
    for (n, d) in [("roll", r.roll), ("pitch", r.pitch)] {
        let _ = writeln!(
            s,
            "{n:<5}  {:+9.4}  {:+10.3e}  {:+16.3e}  {:13.3e}  {:9.3e}",
            d.mean_deg, d.drift_deg, d.drift_rate_deg_s, d.noise_std_deg, d.pp_deg
        );
    }
    s
}

/// The analysis of a lab recording made under `exc`: the reference found,
/// the forward-kinematics effort, and the sensitivities or cross-coupling.
pub fn lab_analysis(r: &Analysis, exc: Excitation) -> String {
    let mut s = format!(
        "reference: {:.4} Hz, amplitude {:.4} ({})\n",
        r.freq_hz,
        r.reference_amplitude,
        match exc {
            Excitation::Conical => "cone angle, deg",
            Excitation::Orbit => "x orbit, mm",
        }
    );
    if let Some(n) = r.fk_max_iterations {
        let _ = writeln!(s, "forward kinematics: at most {n} iterations per row");
    }
    if let Some(p) = &r.conical {
        let _ = writeln!(
            s,
            "gyro_x_db {} gyro_y_db {} accel_x_db {} accel_y_db {} tilt_x_db {} tilt_y_db {} sin_phi_db {} tan_theta_db {}",
            opt(p.gyro_x_db),
            opt(p.gyro_y_db),
            opt(p.accel_x_db),
            opt(p.accel_y_db),
            opt(p.tilt_x_db),
            opt(p.tilt_y_db),
            opt(p.sin_phi_db),
            opt(p.tan_theta_db)
        );
    }
    if let Some(p) = &r.orbit {
        let _ = writeln!(
            s,
            "roll_pp_deg {:.4} pitch_pp_deg {:.4} roll_fit_pp_deg {:.4} pitch_fit_pp_deg {:.4}",
            p.roll_pp_deg, p.pitch_pp_deg, p.roll_fit_pp_deg, p.pitch_fit_pp_deg
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testbench::static_test::AngleDrift;

    fn point(f: f64) -> ConicalPoint {
        ConicalPoint {
            freq_hz: f,
            alpha_deg: 5.0,
            gyro_x_db: Some(-0.0123),
            gyro_y_db: Some(0.25),
            gyro_z_db: None,
            accel_x_db: Some(-1.5),
            accel_y_db: Some(-1.25),
            tilt_x_db: Some(-3.0),
            tilt_y_db: Some(-3.125),
            sin_phi_db: None,
            tan_theta_db: Some(12.0),
        }
    }

    #[test]
    fn conical_rows_come_from_the_points() {
        let s = conical(&[point(0.5), point(3.15)]);
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 3);
        assert!(lines[0].starts_with("freq_hz  alpha_deg gyro_x_db"));
        assert_eq!(
            lines[1],
            "  0.500      5.000    -0.012    +0.250         -     -1.500     -1.250    -3.000    -3.125          -      +12.000"
        );
        assert!(lines[2].starts_with("  3.150 "));
    }

    #[test]
    fn orbit_without_reference_prints_nan_and_one_legend() {
        let p = OrbitPoint {
            freq_hz: 0.5,
            roll_pp_deg: 0.0512,
            pitch_pp_deg: 0.1,
            roll_fit_pp_deg: 0.02,
            pitch_fit_pp_deg: 0.03,
            orbit_amplitude_mm: None,
            reference_tilt_pp_deg: None,
        };
        let s = orbit(std::slice::from_ref(&p), false);
        assert_eq!(s.lines().filter(|l| l.starts_with('#')).count(), 1);
        assert_eq!(
            s.lines().last().unwrap(),
            "  0.500       0.0512       0.1000          0.0200           0.0300         NaN        NaN        NaN              NaN              NaN"
        );
        assert_eq!(
            orbit(&[p], true)
                .lines()
                .filter(|l| l.starts_with('#'))
                .count(),
            2
        );
    }

    #[test]
    fn static_rows() {
        let d = AngleDrift {
            mean_deg: 0.5,
            drift_deg: -1e-3,
            drift_rate_deg_s: 2e-6,
            noise_std_deg: 3e-3,
            pp_deg: 0.02,
        };
        let r = StaticResult {
            filter: "dynamic".into(),
            duration_s: 590.0,
            samples: 118000,
            roll: d,
            pitch: d,
            trace: vec![],
        };
        assert_eq!(
            static_test(&r),
            "static test: filter dynamic, 590.0 s, 118000 samples\n\
             angle  mean_deg   drift_deg  drift_rate_deg_s  noise_std_deg  pp_deg\n\
             roll     +0.5000   -1.000e-3         +2.000e-6       3.000e-3   2.000e-2\n\
             pitch    +0.5000   -1.000e-3         +2.000e-6       3.000e-3   2.000e-2\n"
        );
    }

    #[test]
    fn lab_analysis_names_the_amplitude() {
        let r = Analysis {
            freq_hz: 1.0,
            reference_amplitude: 20.0,
            fk_max_iterations: Some(4),
            conical: None,
            orbit: None,
        };
        assert_eq!(
            lab_analysis(&r, Excitation::Orbit),
            "reference: 1.0000 Hz, amplitude 20.0000 (x orbit, mm)\nforward kinematics: at most 4 iterations per row\n"
        );
    }
}
