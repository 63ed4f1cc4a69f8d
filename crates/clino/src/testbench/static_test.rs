//! The static test: drift and noise of a filter's tilt output at rest.
//!
//! Source: Sapegin & Strokach, "Micromechanical inclinometer" (MPU6050 +
//! Arduino), section "experiment results": the instrument lies at rest on a
//! table for 10 minutes and the drift of pitch and roll over the run, and its
//! rate (drift / duration), are reported. Here the drift is the change of
//! the least-squares line through the tilt over the analysed span (robust to
//! noise, unlike last − first), the drift rate its slope, and the noise the
//! standard deviation about that line. A recording reaches it through
//! [`super::static_record`], the rules `clino allan` applies too.

use super::filters::{filter_factory, run_filter};
use crate::sim::ImuModel;
use crate::sim::motion::Static;
use crate::{Error, ErrorKind, Result};
use clino_core::ImuSample;
use clino_core::tilt::RollPitch;
use serde::Serialize;

/// Drift and noise of one tilt angle at rest.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AngleDrift {
    /// Mean, degrees.
    pub mean_deg: f64,
    /// Drift over the span (slope × span), degrees.
    pub drift_deg: f64,
    /// Drift rate (slope of the fitted line), degrees per second.
    pub drift_rate_deg_s: f64,
    /// Standard deviation about the fitted line, degrees.
    pub noise_std_deg: f64,
    /// Peak-to-peak, degrees.
    pub pp_deg: f64,
}

/// Result of a static test.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StaticResult {
    /// Filter used.
    pub filter: String,
    /// Analysed span, s (after the settling time).
    pub duration_s: f64,
    /// Samples analysed.
    pub samples: usize,
    /// Aerospace roll.
    pub roll: AngleDrift,
    /// Aerospace pitch.
    pub pitch: AngleDrift,
    /// The analysed tilt trace: (t_s, roll_deg, pitch_deg) per sample (not serialised).
    #[serde(skip)]
    pub trace: Vec<[f64; 3]>,
}

fn drift(t: &[f64], y_rad: &[f64]) -> AngleDrift {
    let n = t.len() as f64;
    let tm = t.iter().sum::<f64>() / n;
    let ym = y_rad.iter().sum::<f64>() / n;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (a, b) in t.iter().zip(y_rad) {
        sxy += (a - tm) * (b - ym);
        sxx += (a - tm) * (a - tm);
    }
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let var = t
        .iter()
        .zip(y_rad)
        .map(|(a, b)| (b - ym - slope * (a - tm)).powi(2))
        .sum::<f64>()
        / n;
    let mx = y_rad.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mn = y_rad.iter().copied().fold(f64::INFINITY, f64::min);
    let span = t[t.len() - 1] - t[0];
    AngleDrift {
        mean_deg: ym.to_degrees(),
        drift_deg: (slope * span).to_degrees(),
        drift_rate_deg_s: slope.to_degrees(),
        noise_std_deg: var.sqrt().to_degrees(),
        pp_deg: (mx - mn).to_degrees(),
    }
}

/// Static test of a recording read by
/// [`read_static_record`](crate::testbench::static_record::read_static_record)
/// (at least 3 samples; errors name the file).
pub fn static_test_record(
    rec: &crate::testbench::static_record::StaticRecord,
    filter: &str,
    settle_s: f64,
) -> Result<StaticResult> {
    rec.require(3, "a static test")?;
    static_test(&rec.samples, filter, settle_s)
}

/// Static test of the sensor `model` simulated level at rest for
/// `duration_s` at `rate_hz` (noise seed `seed`).
pub fn static_test_simulated(
    model: &crate::sim::ImuModel,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
    filter: &str,
    settle_s: f64,
) -> Result<StaticResult> {
    model.validate()?;
    let smp = model.simulate(
        &crate::sim::motion::Static::level(),
        rate_hz,
        duration_s,
        seed,
    );
    static_test(&smp, filter, settle_s)
}

/// Static test of `filter` on a recording at rest: the filter runs over all
/// samples; the first `settle_s` seconds are excluded from the statistics.
pub fn static_test(samples: &[ImuSample], filter: &str, settle_s: f64) -> Result<StaticResult> {
    if samples.len() < 3 {
        return Err(Error::new(
            ErrorKind::Empty,
            "static test: fewer than 3 samples",
        ));
    }
    if let Some(i) = samples.iter().position(|s| !s.is_finite()) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("static test: sample {i} is not finite"),
        ));
    }
    if let Some(i) = samples
        .windows(2)
        .position(|w| !crate::testbench::allan::increasing(w[0].t_s, w[1].t_s))
    {
        return Err(Error::new(
            ErrorKind::TimeNotIncreasing,
            format!("time does not increase after sample {i}"),
        ));
    }
    let span = samples[samples.len() - 1].t_s - samples[0].t_s;
    let rate = (samples.len() - 1) as f64 / span;
    let factory = filter_factory(filter, rate)?;
    let att = run_filter(&factory, samples, rate);
    let t0 = samples[0].t_s + settle_s;
    let (mut t, mut roll, mut pitch) = (Vec::new(), Vec::new(), Vec::new());
    for (s, a) in samples.iter().zip(&att) {
        if s.t_s >= t0 {
            let rp = RollPitch::from_attitude(a);
            t.push(s.t_s);
            roll.push(rp.roll);
            pitch.push(rp.pitch);
        }
    }
    if t.len() < 3 {
        return Err(Error::new(
            ErrorKind::Empty,
            "static test: the settling time leaves fewer than 3 samples",
        ));
    }
    Ok(StaticResult {
        filter: filter.to_string(),
        duration_s: t[t.len() - 1] - t[0],
        samples: t.len(),
        roll: drift(&t, &roll),
        pitch: drift(&t, &pitch),
        trace: (0..t.len())
            .map(|i| [t[i], roll[i].to_degrees(), pitch[i].to_degrees()])
            .collect(),
    })
}

/// The paper's 10-minute static test on a simulated sensor lying level.
pub fn simulate_static(
    sensor: &ImuModel,
    filter: &str,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
) -> Result<StaticResult> {
    sensor.validate()?;
    let s = sensor.simulate(&Static::level(), rate_hz, duration_s, seed);
    static_test(&s, filter, 10.0f64.min(duration_s / 10.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clino_core::Vec3;

    #[test]
    fn gyro_bias_makes_the_gyro_only_tilt_drift_at_its_rate() {
        let mut m = ImuModel::ideal();
        m.gyro.bias = Vec3::new(1e-4, 0.0, 0.0);
        let r = simulate_static(&m, "poisson", 100.0, 600.0, 0).unwrap();
        // roll drifts at the bias rate about body x
        assert!(
            (r.roll.drift_rate_deg_s - 1e-4f64.to_degrees()).abs() < 1e-8,
            "{r:?}"
        );
        assert!(r.pitch.drift_rate_deg_s.abs() < 1e-6);
        // the complementary filter holds it: steady offset b·τ, no drift
        let c = simulate_static(&m, "complementary", 100.0, 600.0, 0).unwrap();
        assert!(c.roll.drift_rate_deg_s.abs() < 1e-7, "{c:?}");
    }

    #[test]
    fn bad_records_are_errors() {
        let s = ImuModel::ideal().simulate(&Static::level(), 10.0, 1.0, 0);
        let mut bad = s.clone();
        bad[4].t_s = bad[3].t_s;
        assert_eq!(
            static_test(&bad, "mahony", 0.0).unwrap_err().kind,
            ErrorKind::TimeNotIncreasing
        );
        assert!(static_test(&s, "unknown", 0.0).is_err());
        assert!(static_test(&s[..2], "mahony", 0.0).is_err());
    }
}
