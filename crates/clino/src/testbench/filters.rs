//! Running a named attitude filter for the test bench.
//!
//! The bench names filters in the one specification form of
//! [`crate::fusion::parse_spec`] (`name:key=value,…`, every parameter of
//! [`clino_core::filter::FilterSpec`]), and runs them through the one
//! per-sample loop, [`clino_core::pipeline::Pipeline`].
//!
//! Names: `poisson` (exact strapdown integration), `poisson-rect` (the
//! paper's rectangle rule), `complementary`, `mahony`, `madgwick`, `dynamic`
//! (clino's own filter). Examples: `complementary:tau=10` (time constant, s)
//! or `complementary:k=0.05` (blend per sample), `mahony:kp=0.1,ki=0.0005`
//! (rad/s, rad/s²), `madgwick:beta=0.01` (rad/s), `dynamic:bandwidth=0.15`.

use crate::Result;
use crate::fusion::{FilterSpec, parse_spec};
use clino_core::pipeline::Pipeline;
use clino_core::{Attitude, ImuSample};

/// Filter names the bench accepts (`poisson-rect` is `poisson:integrator=rectangle`).
pub const FILTER_NAMES: [&str; 6] = [
    "poisson",
    "poisson-rect",
    "complementary",
    "mahony",
    "madgwick",
    "dynamic",
];

/// The filter the test bench demonstrates: clino's own `dynamic` at its
/// defaults. On the `mpu6050` preset at 200 Hz it keeps the tilt of a 5° cone
/// within 0.05 dB from 0.1 to 10 Hz (BENCHMARKS.md). At 100 Hz the
/// 10-Hz cone shows +0.1 dB: one rate sample per integration step misses
/// (ωh)²/24 of the coning rotation, a property of rate-sampled strapdown
/// integration shared by every filter here.
pub const BEST_FILTER: &str = "dynamic";

/// Run a fresh pipeline of `spec` over `samples`, returning its attitude
/// after each sample (identity until initialised). Time steps follow the
/// pipeline's rule (time-stamp differences); `_rate_hz` is kept for callers
/// that pass the nominal rate.
pub fn run_filter(spec: &FilterSpec, samples: &[ImuSample], _rate_hz: f64) -> Vec<Attitude> {
    let mut p = Pipeline::new(*spec);
    samples
        .iter()
        .map(|s| p.update(s).attitude.unwrap_or_else(Attitude::identity))
        .collect()
}

/// The filter named by `spec` (see the module doc), checked. `rate_hz` must be
/// a positive rate (the runs it is for are sampled at it).
pub fn filter_factory(spec: &str, rate_hz: f64) -> Result<FilterSpec> {
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(crate::Error::new(
            crate::ErrorKind::InvalidInput,
            format!("sample rate {rate_hz} Hz"),
        ));
    }
    parse_spec(spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_parameters() {
        for n in FILTER_NAMES {
            let f = filter_factory(n, 100.0).unwrap();
            assert_eq!(f.kind().name(), n.split('-').next().unwrap());
        }
        assert!(filter_factory(BEST_FILTER, 200.0).is_ok());
        assert!(filter_factory("mahony:kp=0.5", 100.0).is_ok());
        assert_eq!(
            filter_factory("kalman", 100.0).err().unwrap().kind,
            crate::ErrorKind::InvalidInput
        );
        assert!(filter_factory("mahony:beta=1", 100.0).is_err());
        assert!(filter_factory("mahony:kp=x", 100.0).is_err());
        assert!(filter_factory("complementary:tau=0", 100.0).is_err());
        assert!(filter_factory("complementary:tau=1,k=0.1", 100.0).is_err());
        assert!(filter_factory("mahony:kp=1,kp=2", 100.0).is_err());
        assert!(filter_factory("complementary:k=1.5", 100.0).is_err());
        assert!(filter_factory("poisson:kp=1", 100.0).is_err());
        assert!(filter_factory("dynamic:bandwidth=0", 100.0).is_err());
        assert!(filter_factory("dynamic:bandwidth=1e3", 100.0).is_err());
        assert!(filter_factory("dynamic:kp=1", 100.0).is_err());
        assert!(filter_factory("mahony", 0.0).is_err());
    }

    /// The spec's parameters reach the filter: feed a tilted, still sensor
    /// to filters started level and compare how far each has turned after
    /// a fixed time; a larger gain must turn further.
    #[test]
    fn parameters_reach_the_filter() {
        let roll = 20f64.to_radians();
        let acc = clino_core::Vec3::new(0.0, 9.80665 * roll.sin(), 9.80665 * roll.cos());
        let level = clino_core::Vec3::new(0.0, 0.0, 9.80665);
        // 1 s level (initialises level), then 1 s tilted; roll reached at the end.
        let samples: Vec<ImuSample> = (0..400)
            .map(|i| {
                let t = i as f64 / 200.0;
                let a = if i < 200 { level } else { acc };
                ImuSample::new(t, clino_core::Vec3::zeros(), a)
            })
            .collect();
        let reached = |spec: &str| {
            let q = *run_filter(&filter_factory(spec, 200.0).unwrap(), &samples, 200.0)
                .last()
                .unwrap();
            clino_core::tilt::RollPitch::from_attitude(&q).roll
        };
        for (lo, hi) in [
            ("complementary:tau=10", "complementary:tau=0.5"),
            ("complementary:k=0.001", "complementary:k=0.05"),
            ("mahony:kp=0.1", "mahony:kp=2"),
            ("madgwick:beta=0.01", "madgwick:beta=0.2"),
            ("dynamic:bandwidth=0.05", "dynamic:bandwidth=0.5"),
        ] {
            let (a, b) = (reached(lo), reached(hi));
            assert!(a.abs() < b.abs(), "{lo}: {a} rad, {hi}: {b} rad");
        }
        // the rectangle rule and the exact step differ under a fast rotation
        let spin: Vec<ImuSample> = (0..200)
            .map(|i| {
                let t = i as f64 / 100.0;
                let w = clino_core::Vec3::new(3.0 * (7.0 * t).cos(), 3.0 * (7.0 * t).sin(), 1.0);
                ImuSample::new(t, w, level)
            })
            .collect();
        let end = |spec: &str| {
            *run_filter(&filter_factory(spec, 100.0).unwrap(), &spin, 100.0)
                .last()
                .unwrap()
        };
        assert!(end("poisson").angle_to(&end("poisson-rect")) > 1e-6);
    }
}
