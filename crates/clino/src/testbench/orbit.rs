//! Cross-coupling under positional orbits.
//!
//! Source: Liu, Cai, Yang, Zhang, "Testing of a MEMS Dynamic Inclinometer
//! Using the Stewart Platform", Sensors 2019, sections 3.2 and 4.2: the
//! platform vibrates along x, y and z at one frequency (eq 4) without
//! rotating; any tilt the inclinometer reports is cross-coupling from the
//! linear acceleration. The paper reports the peak-to-peak of roll and pitch;
//! we also report twice the amplitude of a sine fitted at the orbit frequency
//! (with a quadratic trend removed), which separates the coupling from noise
//! and drift.
//!
//! On the simulated platform ([`OrbitConfig::platform`]) the test runs as the
//! paper's does: the commanded orbit becomes leg lengths, the servo legs
//! follow them with their bandwidth (attenuation and lag), the sensor rides
//! the motion of the *actual* legs ([`PlatformMotion`]), and the reference —
//! the orbit actually made, and the platform's own small rotation — comes from
//! the actual legs by forward kinematics, as from the encoders. The coupling
//! is the inclinometer's tilt minus the platform's actual tilt; the orbit's
//! actual amplitude is reported next to it.

use super::conical::{check_sweep, window_s};
use super::filters::{filter_factory, run_filter};
use super::sinefit::{fit3, peak_to_peak};
use crate::sim::motion::Orbit;
use crate::sim::platform::PlatformMotion;
use crate::sim::stewart::Pose;
use crate::sim::{ImuModel, Motion};
use crate::{Error, ErrorKind, Result};
use clino_core::Attitude;
use clino_core::tilt::RollPitch;
use serde::Serialize;

/// Cross-coupling at one orbit frequency.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrbitPoint {
    /// Orbit frequency, Hz.
    pub freq_hz: f64,
    /// Peak-to-peak (max − min) of the roll error over the analysis window,
    /// degrees (the paper's measure).
    pub roll_pp_deg: f64,
    /// Peak-to-peak (max − min) of the pitch error, degrees.
    pub pitch_pp_deg: f64,
    /// Twice the fitted roll-error amplitude at the orbit frequency, degrees.
    pub roll_fit_pp_deg: f64,
    /// Twice the fitted pitch-error amplitude at the orbit frequency, degrees.
    pub pitch_fit_pp_deg: f64,
    /// Amplitude of the orbit actually made, x, y, z, mm (sine fitted at the
    /// orbit frequency to the reference position); `None` without a reference.
    pub orbit_amplitude_mm: Option<[f64; 3]>,
    /// Peak-to-peak (max − min) of the reference's own roll and pitch,
    /// degrees: the platform's parasitic rotation, taken out of the errors
    /// above; `None` without a reference.
    pub reference_tilt_pp_deg: Option<[f64; 2]>,
}

/// Cross-coupling of a tilt record (aerospace roll and pitch, rad, at times
/// `t_s`) under an orbit at `freq_hz`.
pub fn cross_coupling(
    t_s: &[f64],
    roll_rad: &[f64],
    pitch_rad: &[f64],
    freq_hz: f64,
) -> Result<OrbitPoint> {
    if roll_rad.len() != t_s.len() || pitch_rad.len() != t_s.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "roll, pitch and time have different lengths",
        ));
    }
    let fit = |y: &[f64]| fit3(t_s, y, freq_hz, 2).map(|f| f.peak_to_peak().to_degrees());
    Ok(OrbitPoint {
        freq_hz,
        roll_pp_deg: peak_to_peak(roll_rad)?.to_degrees(),
        pitch_pp_deg: peak_to_peak(pitch_rad)?.to_degrees(),
        roll_fit_pp_deg: fit(roll_rad)?,
        pitch_fit_pp_deg: fit(pitch_rad)?,
        orbit_amplitude_mm: None,
        reference_tilt_pp_deg: None,
    })
}

/// Cross-coupling of filter attitudes `att` against the reference poses
/// `reference` (the platform's actual pose at each time, e.g. from the
/// encoders): the errors roll − roll_ref and pitch − pitch_ref (aerospace
/// z-y-x), and the orbit's actual amplitude from the reference positions
/// (sine fits at `freq_hz` with a linear trend).
pub fn cross_coupling_against(
    t_s: &[f64],
    att: &[Attitude],
    reference: &[Pose],
    freq_hz: f64,
) -> Result<OrbitPoint> {
    if att.len() != t_s.len() || reference.len() != t_s.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "attitudes, reference and time have different lengths",
        ));
    }
    let wrap = |a: f64| {
        (a + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    let rp_ref: Vec<RollPitch> = reference
        .iter()
        .map(|p| RollPitch::from_attitude(&p.attitude))
        .collect();
    let (mut roll, mut pitch) = (Vec::with_capacity(t_s.len()), Vec::with_capacity(t_s.len()));
    for (a, r) in att.iter().zip(&rp_ref) {
        let e = RollPitch::from_attitude(a);
        roll.push(wrap(e.roll - r.roll));
        pitch.push(wrap(e.pitch - r.pitch));
    }
    let mut p = cross_coupling(t_s, &roll, &pitch, freq_hz)?;
    let amp = |k: usize| -> Result<f64> {
        let v: Vec<f64> = reference.iter().map(|p| p.pos_m[k]).collect();
        Ok(fit3(t_s, &v, freq_hz, 1)?.amplitude * 1e3)
    };
    p.orbit_amplitude_mm = Some([amp(0)?, amp(1)?, amp(2)?]);
    let rr: Vec<f64> = rp_ref.iter().map(|r| r.roll).collect();
    let rq: Vec<f64> = rp_ref.iter().map(|r| r.pitch).collect();
    p.reference_tilt_pp_deg = Some([
        peak_to_peak(&rr)?.to_degrees(),
        peak_to_peak(&rq)?.to_degrees(),
    ]);
    Ok(p)
}

/// Cross-coupling from filter attitudes.
pub fn cross_coupling_of_attitudes(
    t_s: &[f64],
    att: &[Attitude],
    freq_hz: f64,
) -> Result<OrbitPoint> {
    let rp: Vec<RollPitch> = att.iter().map(RollPitch::from_attitude).collect();
    let roll: Vec<f64> = rp.iter().map(|r| r.roll).collect();
    let pitch: Vec<f64> = rp.iter().map(|r| r.pitch).collect();
    cross_coupling(t_s, &roll, &pitch, freq_hz)
}

/// A simulated orbit sweep.
#[derive(Clone, Debug)]
pub struct OrbitConfig {
    /// Amplitude Ŝ on each of x, y, z, m.
    pub amplitude_m: f64,
    /// Phases φ_x, φ_y, φ_z, rad.
    pub phases_rad: [f64; 3],
    /// Frequencies, Hz.
    pub freqs_hz: Vec<f64>,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Sensor model.
    pub sensor: ImuModel,
    /// Filter (see [`super::filters::filter_factory`]).
    pub filter: String,
    /// Random seed (frequency i uses seed + i).
    pub seed: u64,
    /// Rest before the orbit starts (the filter initialises at rest), s.
    pub rest_s: f64,
    /// Start ramp, in periods of the orbit (at least 1 s).
    pub ramp_periods: f64,
    /// Time after the ramp discarded before analysis (filter transient), s.
    pub settle_s: f64,
    /// Shortest analysis window, s (rounded up to whole periods).
    pub min_window_s: f64,
    /// Fewest periods in the analysis window.
    pub min_periods: f64,
    /// Run on a simulated servo platform: the sensor rides the actual motion
    /// of the servo legs and the reference is their forward kinematics
    /// (`None`: the sensor rides the exact commanded orbit).
    pub platform: Option<super::conical::PlatformSpec>,
}

impl OrbitConfig {
    /// A sweep with the defaults: phases (0°, 120°, 240°), 200 Hz, seed 1, 2 s rest,
    /// 2-period ramp, 40 s settling, window ≥ 20 s and ≥ 4 periods.
    pub fn new(amplitude_m: f64, freqs_hz: Vec<f64>, sensor: ImuModel, filter: &str) -> Self {
        Self {
            amplitude_m,
            phases_rad: Orbit::DEFAULT_PHASES_RAD,
            freqs_hz,
            rate_hz: 200.0,
            sensor,
            filter: filter.to_string(),
            seed: 1,
            rest_s: 2.0,
            ramp_periods: 2.0,
            settle_s: 40.0,
            min_window_s: 20.0,
            min_periods: 4.0,
            platform: None,
        }
    }
}

/// Run the simulated orbit test at every frequency of `cfg`; `progress(done, total)`
/// is called after each frequency.
pub fn run_orbit(
    cfg: &OrbitConfig,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<OrbitPoint>> {
    check_sweep(&cfg.freqs_hz, cfg.rate_hz)?;
    cfg.sensor.validate()?;
    if !(cfg.amplitude_m.is_finite() && cfg.amplitude_m >= 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("orbit amplitude {} m", cfg.amplitude_m),
        ));
    }
    let factory = filter_factory(&cfg.filter, cfg.rate_hz)?;
    let mut out = Vec::with_capacity(cfg.freqs_hz.len());
    for (i, &f) in cfg.freqs_hz.iter().enumerate() {
        let mut orbit = Orbit::spatial(cfg.amplitude_m, f);
        orbit.phase_rad = cfg.phases_rad.into();
        let ramp = (cfg.ramp_periods / f).max(1.0);
        let orbit = orbit.with_start(cfg.rest_s, ramp);
        let t0 = cfg.rest_s + ramp + cfg.settle_s;
        let win = window_s(f, cfg.min_window_s, cfg.min_periods);
        let total = t0 + win;
        let on_platform;
        let motion: &dyn Motion = match &cfg.platform {
            None => &orbit,
            Some(p) => {
                on_platform = PlatformMotion::new(&p.geometry, &p.servo, &orbit, total + 0.1)?;
                &on_platform
            }
        };
        let samples = cfg
            .sensor
            .simulate(motion, cfg.rate_hz, total, cfg.seed + i as u64);
        let att = run_filter(&factory, &samples, cfg.rate_hz);
        let mut t = Vec::new();
        let mut a = Vec::new();
        let mut reference = Vec::new();
        for (s, q) in samples.iter().zip(att) {
            if s.t_s >= t0 {
                // the actual pose: on the platform, forward kinematics of the actual legs
                let tr = motion.truth(s.t_s);
                t.push(s.t_s);
                a.push(q);
                reference.push(Pose {
                    pos_m: tr.pos_m,
                    attitude: tr.attitude,
                });
            }
        }
        out.push(cross_coupling_against(&t, &a, &reference, f)?);
        progress(i + 1, cfg.freqs_hz.len());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accelerometer_only_tilt_shows_the_acceleration_angle() {
        // a filter that trusts the accelerometer fully (complementary k = 1) reads
        // the tilt of the apparent gravity: for a horizontal acceleration amplitude
        // a = ω²·Ŝ the roll swings by about ±atan(a/g)
        let f = 0.8;
        let mut cfg = OrbitConfig::new(0.02, vec![f], ImuModel::ideal(), "complementary:k=1");
        cfg.settle_s = 2.0;
        let p = &run_orbit(&cfg, &mut |_, _| {}).unwrap()[0];
        let a = (2.0 * std::f64::consts::PI * f).powi(2) * 0.02;
        let g = clino_core::G0;
        // roll = atan2(f_y, f_z) with f = −a_n + g e_z: amplitude ≈ a/g for small a
        let expect_pp = 2.0 * (a / g).to_degrees();
        assert!(
            (p.roll_fit_pp_deg / expect_pp - 1.0).abs() < 0.05,
            "{p:?} vs {expect_pp}"
        );
        assert!((p.pitch_fit_pp_deg / expect_pp - 1.0).abs() < 0.05, "{p:?}");
        assert!(p.roll_pp_deg >= p.roll_fit_pp_deg * 0.95);
    }

    /// The orbit test runs on the platform's actual motion: slow servo legs
    /// attenuate the orbit (|H| of the leg servo at the orbit frequency), the
    /// reference reports the smaller orbit actually made, and an
    /// accelerometer-only tilt couples with the actual acceleration ω²·Ŝ·|H|.
    #[test]
    fn platform_orbit_rides_the_servo_legs_actual_motion() {
        use super::super::conical::PlatformSpec;
        use crate::sim::stewart::{Geometry, ServoLegs};
        let (f, amp) = (0.8, 0.02);
        let run = |servo: Option<ServoLegs>| {
            let mut cfg = OrbitConfig::new(amp, vec![f], ImuModel::ideal(), "complementary:k=1");
            cfg.rate_hz = 100.0;
            cfg.settle_s = 2.0;
            cfg.min_window_s = 5.0;
            cfg.platform = servo.map(|servo| PlatformSpec {
                geometry: Geometry::typical(),
                servo,
            });
            run_orbit(&cfg, &mut |_, _| {}).unwrap()[0].clone()
        };
        let exact = run(None);
        let fast = run(Some(ServoLegs::default()));
        let slow_servo = ServoLegs {
            natural_hz: 1.0,
            damping: 0.7,
        };
        let slow = run(Some(slow_servo));
        let gain = slow_servo.gain(f);
        assert!((gain - 0.85).abs() < 0.01, "{gain}");
        // the orbit actually made
        for (p, h) in [
            (&exact, 1.0),
            (&fast, ServoLegs::default().gain(f)),
            (&slow, gain),
        ] {
            for a in p.orbit_amplitude_mm.unwrap() {
                assert!((a / (20.0 * h) - 1.0).abs() < 0.01, "{a} mm vs {h}: {p:?}");
            }
        }
        // the coupling follows the actual acceleration
        let g = clino_core::G0;
        let expect =
            |h: f64| 2.0 * ((2.0 * std::f64::consts::PI * f).powi(2) * amp * h / g).to_degrees();
        for (p, h) in [(&exact, 1.0), (&slow, gain)] {
            for v in [p.roll_fit_pp_deg, p.pitch_fit_pp_deg] {
                assert!(
                    (v / expect(h) - 1.0).abs() < 0.03,
                    "{v} vs {}: {p:?}",
                    expect(h)
                );
            }
        }
        // --platform changes the result, and the servo bandwidth matters
        assert_ne!(exact, fast);
        assert!(
            slow.roll_fit_pp_deg < 0.9 * fast.roll_fit_pp_deg,
            "{slow:?} {fast:?}"
        );
        // the platform's own rotation is tiny (the paper: < 0.005°) and reported
        let [r, q] = slow.reference_tilt_pp_deg.unwrap();
        assert!(r < 0.01 && q < 0.01, "{slow:?}");
        assert_eq!(exact.reference_tilt_pp_deg, Some([0.0, 0.0]));
    }

    #[test]
    fn ideal_gyro_only_has_no_coupling() {
        let mut cfg = OrbitConfig::new(0.02, vec![0.5], ImuModel::ideal(), "poisson");
        cfg.settle_s = 1.0;
        let p = &run_orbit(&cfg, &mut |_, _| {}).unwrap()[0];
        assert!(p.roll_pp_deg < 1e-9 && p.pitch_fit_pp_deg < 1e-9, "{p:?}");
    }
}
