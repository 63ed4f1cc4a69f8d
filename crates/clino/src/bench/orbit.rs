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

use super::conical::{check_sweep, window_s};
use super::filters::{filter_factory, run_filter};
use super::sinefit::{fit3, peak_to_peak};
use crate::sim::ImuModel;
use crate::sim::motion::Orbit;
use crate::{Error, ErrorKind, Result};
use clino_core::Attitude;
use clino_core::tilt::RollPitch;
use serde::Serialize;

/// Cross-coupling at one orbit frequency.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrbitPoint {
    /// Orbit frequency, Hz.
    pub freq_hz: f64,
    /// Peak-to-peak of roll over the analysis window, degrees (the paper's measure).
    pub roll_pp_deg: f64,
    /// Peak-to-peak of pitch, degrees.
    pub pitch_pp_deg: f64,
    /// Twice the fitted roll amplitude at the orbit frequency, degrees.
    pub roll_fit_pp_deg: f64,
    /// Twice the fitted pitch amplitude at the orbit frequency, degrees.
    pub pitch_fit_pp_deg: f64,
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
    })
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
    /// Run on a simulated servo platform (`None`: the sensor rides the exact orbit).
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
        let samples = cfg
            .sensor
            .simulate(&orbit, cfg.rate_hz, t0 + win, cfg.seed + i as u64);
        let att = run_filter(&factory, &samples, cfg.rate_hz);
        let (t, a): (Vec<f64>, Vec<Attitude>) = samples
            .iter()
            .zip(att)
            .filter(|(s, _)| s.t_s >= t0)
            .map(|(s, a)| (s.t_s, a))
            .unzip();
        out.push(cross_coupling_of_attitudes(&t, &a, f)?);
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

    #[test]
    fn ideal_gyro_only_has_no_coupling() {
        let mut cfg = OrbitConfig::new(0.02, vec![0.5], ImuModel::ideal(), "poisson");
        cfg.settle_s = 1.0;
        let p = &run_orbit(&cfg, &mut |_, _| {}).unwrap()[0];
        assert!(p.roll_pp_deg < 1e-9 && p.pitch_fit_pp_deg < 1e-9, "{p:?}");
    }
}
