//! Choosing an attitude filter by name for the test bench.
//!
//! One function, [`filter_factory`], maps a name (optionally with parameters)
//! to a factory that builds fresh filters; every test-bench run goes through
//! it. The filters themselves come from the shared registry
//! [`crate::fusion::FilterConfig`]: this module only parses the bench's
//! `name:key=value,…` spec into a [`FilterConfig`] (kind and [`Gains`]).
//!
//! Names: `poisson` (exact strapdown integration), `poisson-rect` (the
//! paper's rectangle rule), `complementary`, `mahony`, `madgwick`, `dynamic`
//! (clino's own filter, [`clino_core::filter::Dynamic`]). Parameters follow a
//! colon, comma separated: `complementary:tau=10` (time constant, s) or
//! `complementary:k=0.05` (blend per sample; default 0.05 at the run's rate),
//! `mahony:kp=0.1,ki=0.0005` (rad/s, rad/s²), `madgwick:beta=0.01` (rad/s),
//! `dynamic:bandwidth=0.15` (base loop bandwidth p₀, rad/s). Unnamed
//! parameters keep the registry's defaults ([`Gains::default`]).

use crate::fusion::{FilterConfig, FilterKind, Gains};
use crate::{Error, ErrorKind, Result};
use clino_core::filter::{Complementary, Integrator};
use clino_core::{Attitude, AttitudeFilter, ImuSample};

/// Builds a fresh, uninitialised filter.
pub type FilterFactory = Box<dyn Fn() -> Box<dyn AttitudeFilter> + Send + Sync>;

/// Filter names accepted by [`filter_factory`].
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
/// within 0.05 dB from 0.1 to 10 Hz and the fitted cross-coupling of 20 mm
/// orbits at 0.01–0.02° p-p from 0.1 to 0.8 Hz (BENCHMARKS.md). At 100 Hz the
/// 10-Hz cone shows +0.1 dB: one rate sample per integration step misses
/// (ωh)²/24 of the coning rotation, a property of rate-sampled strapdown
/// integration shared by every filter here.
pub const BEST_FILTER: &str = "dynamic";

/// Run a fresh filter from `factory` over `samples`, returning its attitude
/// after each sample (identity until initialised). The first step uses the
/// nominal period `1/rate_hz`, later ones the time-stamp differences.
pub fn run_filter(factory: &FilterFactory, samples: &[ImuSample], rate_hz: f64) -> Vec<Attitude> {
    let mut f = factory();
    let mut prev = None;
    samples
        .iter()
        .map(|s| {
            let dt = prev.map_or(1.0 / rate_hz, |p| s.t_s - p);
            prev = Some(s.t_s);
            f.update(s.gyr_rad_s, s.acc_m_s2, dt);
            f.attitude()
        })
        .collect()
}

/// A factory for the filter named by `spec` (see the module doc), for samples at `rate_hz`.
pub fn filter_factory(spec: &str, rate_hz: f64) -> Result<FilterFactory> {
    let bad = |m: String| Error::new(ErrorKind::InvalidInput, m);
    let (name, rest) = match spec.split_once(':') {
        Some((n, r)) => (n.trim().to_ascii_lowercase(), r),
        None => (spec.trim().to_ascii_lowercase(), ""),
    };
    let mut params = Vec::new();
    for kv in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (k, v) = kv.split_once('=').ok_or_else(|| {
            bad(format!(
                "filter '{spec}': parameter '{kv}' is not key=value"
            ))
        })?;
        let v: f64 = v
            .trim()
            .parse()
            .map_err(|_| bad(format!("filter '{spec}': '{v}' is not a number")))?;
        if !(v.is_finite() && v >= 0.0) {
            return Err(bad(format!(
                "filter '{spec}': {k} must be finite and non-negative"
            )));
        }
        params.push((k.trim().to_ascii_lowercase(), v));
    }
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(bad(format!("sample rate {rate_hz} Hz")));
    }
    let (kind, integrator) = match name.as_str() {
        "poisson-rect" => (FilterKind::Poisson, Some(Integrator::Rectangle)),
        n => (
            n.parse::<FilterKind>().map_err(|_| {
                bad(format!(
                    "unknown filter '{n}' (known: {})",
                    FILTER_NAMES.join(", ")
                ))
            })?,
            None,
        ),
    };
    let allowed: &[&str] = match kind {
        FilterKind::Complementary => &["tau", "k"],
        FilterKind::Mahony => &["kp", "ki"],
        FilterKind::Madgwick => &["beta"],
        FilterKind::Dynamic => &["bandwidth"],
        _ => &[],
    };
    let mut gains = Gains {
        integrator,
        ..Gains::default()
    };
    for (k, v) in &params {
        let v = *v;
        match (kind, k.as_str()) {
            (FilterKind::Complementary, "tau") => {
                if v <= 0.0 {
                    return Err(bad("complementary: tau must be positive".into()));
                }
                gains.complementary_k = Complementary::k_for(v, 1.0 / rate_hz);
            }
            (FilterKind::Complementary, "k") => gains.complementary_k = v,
            (FilterKind::Mahony, "kp") => gains.mahony_kp = v,
            (FilterKind::Mahony, "ki") => gains.mahony_ki = v,
            (FilterKind::Madgwick, "beta") => gains.madgwick_beta = v,
            (FilterKind::Dynamic, "bandwidth") => gains.dynamic_bandwidth_rad_s = v,
            _ => {
                return Err(bad(format!(
                    "filter '{name}' has no parameter '{k}' (has: {})",
                    if allowed.is_empty() {
                        "none".to_string()
                    } else {
                        allowed.join(", ")
                    }
                )));
            }
        }
    }
    if kind == FilterKind::Complementary
        && params.iter().any(|(k, _)| k == "tau")
        && params.iter().any(|(k, _)| k == "k")
    {
        return Err(bad(format!(
            "filter '{spec}': give complementary either tau or k, not both"
        )));
    }
    let config = FilterConfig::new(kind).with_gains(gains);
    // Checks every gain once here, so building a fresh filter below cannot fail.
    config
        .validate()
        .map_err(|e| bad(format!("filter '{spec}': {}", e.message)))?;
    Ok(Box::new(move || -> Box<dyn AttitudeFilter> {
        config.build().expect("gains validated by filter_factory")
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_parameters() {
        for n in FILTER_NAMES {
            let f = filter_factory(n, 100.0).unwrap();
            assert_eq!(f().name().split('-').next(), n.split('-').next());
        }
        assert!(filter_factory(BEST_FILTER, 200.0).is_ok());
        assert!(filter_factory("mahony:kp=0.5", 100.0).is_ok());
        assert_eq!(
            filter_factory("kalman", 100.0).err().unwrap().kind,
            ErrorKind::InvalidInput
        );
        assert!(filter_factory("mahony:beta=1", 100.0).is_err());
        assert!(filter_factory("mahony:kp=x", 100.0).is_err());
        assert!(filter_factory("complementary:tau=0", 100.0).is_err());
        assert!(filter_factory("complementary:tau=1,k=0.1", 100.0).is_err());
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
