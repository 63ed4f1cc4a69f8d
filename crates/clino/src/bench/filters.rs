//! Choosing an attitude filter by name for the test bench.
//!
//! One function, [`filter_factory`], maps a name (optionally with parameters)
//! to a factory that builds fresh filters; every test-bench run goes through
//! it, so swapping in a shared registry later changes only this file.
//!
//! Names: `poisson` (exact strapdown integration), `poisson-rect` (the
//! paper's rectangle rule), `complementary`, `mahony`, `madgwick`. Parameters
//! follow a colon, comma separated: `complementary:tau=10` (time constant, s;
//! default: the paper's k = 0.05 per sample at the run's rate), `mahony:kp=0.1,ki=0.0005`
//! (rad/s, rad/s²), `madgwick:beta=0.01` (rad/s).

use crate::{Error, ErrorKind, Result};
use clino_core::filter::{Complementary, Integrator, Madgwick, Mahony, Poisson};
use clino_core::{Attitude, AttitudeFilter, ImuSample};

/// Builds a fresh, uninitialised filter.
pub type FilterFactory = Box<dyn Fn() -> Box<dyn AttitudeFilter> + Send + Sync>;

/// Filter names accepted by [`filter_factory`].
pub const FILTER_NAMES: [&str; 5] = [
    "poisson",
    "poisson-rect",
    "complementary",
    "mahony",
    "madgwick",
];

/// The best of the current filters on the test bench (see the testbench note):
/// Mahony with k_p = 0.1 rad/s (a 10 s accelerometer time constant, which
/// rejects the orbits' linear accelerations) and k_i = 5e-4 rad/s².
pub const BEST_FILTER: &str = "mahony:kp=0.1,ki=0.0005";

fn param(params: &[(String, f64)], key: &str, default: f64) -> f64 {
    params
        .iter()
        .find(|(k, _)| k == key)
        .map_or(default, |(_, v)| *v)
}

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
    let allowed: &[&str] = match name.as_str() {
        "poisson" | "poisson-rect" => &[],
        "complementary" => &["tau", "k"],
        "mahony" => &["kp", "ki"],
        "madgwick" => &["beta"],
        _ => {
            return Err(bad(format!(
                "unknown filter '{name}' (known: {})",
                FILTER_NAMES.join(", ")
            )));
        }
    };
    if let Some((k, _)) = params.iter().find(|(k, _)| !allowed.contains(&k.as_str())) {
        return Err(bad(format!(
            "filter '{name}' has no parameter '{k}' (has: {})",
            allowed.join(", ")
        )));
    }
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(bad(format!("sample rate {rate_hz} Hz")));
    }
    let f: FilterFactory = match name.as_str() {
        "poisson" => Box::new(|| Box::new(Poisson::new(Integrator::Exact))),
        "poisson-rect" => Box::new(|| Box::new(Poisson::new(Integrator::Rectangle))),
        "complementary" => {
            let k = if params.iter().any(|(k, _)| k == "tau") {
                let tau = param(&params, "tau", 0.0);
                if tau <= 0.0 {
                    return Err(bad("complementary: tau must be positive".into()));
                }
                Complementary::k_for(tau, 1.0 / rate_hz)
            } else {
                param(&params, "k", 0.05)
            };
            Box::new(move || Box::new(Complementary::new(k)))
        }
        "mahony" => {
            let d = Mahony::default();
            let kp = param(&params, "kp", d.kp);
            let ki = param(&params, "ki", d.ki);
            Box::new(move || Box::new(Mahony::new(kp, ki)))
        }
        _ => {
            let beta = param(&params, "beta", Madgwick::default().beta);
            Box::new(move || Box::new(Madgwick::new(beta)))
        }
    };
    Ok(f)
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
    }
}
