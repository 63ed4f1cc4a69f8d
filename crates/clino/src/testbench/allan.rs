//! Allan deviation and the IEEE Std 952 noise terms, with honest bounds.
//!
//! Source: IEEE Std 952-1997 (R2008), "IEEE Standard Specification Format
//! Guide and Test Procedure for Single-Axis Interferometric Fiber Optic
//! Gyros", Annex C. For a rate record y_k sampled at f_s = 1/τ₀ with
//! integrated angle θ_k = τ₀·Σ_{j<k} y_j, the overlapping Allan variance at
//! τ = m·τ₀ (eq C.8) is
//!
//! σ²(τ) = Σ_{k=0}^{N−2m} (θ_{k+2m} − 2θ_{k+m} + θ_k)² / (2τ²·(N − 2m + 1)).
//!
//! Per axis, [`analyse_axis`] gives
//!
//! 1. the curve on about ten log-spaced τ per decade up to N/9 samples, each
//!    point with its equivalent degrees of freedom and a 99 % chi-squared
//!    interval (degrees of freedom of the overlapping estimator under the
//!    fitted noise model: [`model`]);
//! 2. the conventional graphical readings of IEEE 952, `n`, `b`, `k`, each
//!    `None` with the reason when the curve has no such region ([`readings`]);
//! 3. the model σ² = 3Q²/τ² + N²/τ + 0.664²·B² + K²τ/3 + R²τ²/2 fitted over the
//!    τ range it describes — the shortest τ are left out while they lie
//!    significantly below the −½ line, where internal filtering correlates
//!    consecutive samples — with intervals from the full covariance of the
//!    correlated points ([`fit`]).
//!
//! Before any of it, the channel itself is checked: a constant channel, or one
//! whose noise is below its quantisation step, is reported as such
//! ([`ChannelStatus`]) rather than read.
//!
//! ```
//! use clino::testbench::allan::analyse_axis;
//! use clino::sim::{ImuModel, motion::Static};
//! let mut m = ImuModel::ideal();
//! m.gyro.noise_density = 1e-3; // rad/s/√Hz
//! let s = m.simulate(&Static::level(), 100.0, 600.0, 1);
//! let y: Vec<f64> = s.iter().map(|x| x.gyr_rad_s.x).collect();
//! let ax = analyse_axis("gyr_x", "rad/s", &y, 100.0).unwrap();
//! let n = ax.ieee952.n.estimate.unwrap();
//! assert!(n.lo <= 1e-3 && 1e-3 <= n.hi && (n.value / 1e-3 - 1.0).abs() < 0.03);
//! assert!(ax.ieee952.k.estimate.is_none()); // white noise only: no +1/2 region
//! ```

pub mod fit;
pub mod model;
pub mod readings;
pub mod run;

use crate::{Error, ErrorKind, Result};
use clino_core::ImuSample;
pub use fit::FittedModel;
pub use model::{B_FLOOR, CONFIDENCE, NoiseModel};
use model::{avar_cov_matrix, chi2_factors, edf_white};
pub use run::{AllanReport, allan_record, allan_simulated};
use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};

/// One point of an Allan-deviation curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AllanPoint {
    /// Averaging time τ, s.
    pub tau_s: f64,
    /// Allan deviation σ(τ), units of the input.
    pub adev: f64,
    /// Lower 99 % confidence bound.
    pub adev_lo: f64,
    /// Upper 99 % confidence bound.
    pub adev_hi: f64,
    /// Equivalent degrees of freedom of σ̂²(τ).
    pub edf: f64,
    /// Local log-log slope d ln σ / d ln τ (over ±0.2 decade).
    pub slope: f64,
    /// Standard error of `slope`.
    pub slope_se: f64,
}

/// An estimate with its 99 % interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Estimate {
    /// Estimate.
    pub value: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// Equivalent degrees of freedom of the squared estimate.
    pub edf: f64,
}

impl Estimate {
    /// True when `v` lies within [lo, hi].
    pub fn contains(&self, v: f64) -> bool {
        v >= self.lo && v <= self.hi
    }
}

/// A τ range of the curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Region {
    /// Shortest τ, s.
    pub tau_from_s: f64,
    /// Longest τ, s.
    pub tau_to_s: f64,
    /// Curve points in it.
    pub points: usize,
}

/// A reading or fitted term: an estimate and the region it comes from, or the reason there is none.
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    /// The estimate (`None` when the record has no such term).
    pub estimate: Option<Estimate>,
    /// Region of the curve it was read from.
    pub region: Option<Region>,
    /// Why there is no estimate.
    pub reason: Option<String>,
}

impl Reading {
    fn absent(reason: String) -> Self {
        Self {
            estimate: None,
            region: None,
            reason: Some(reason),
        }
    }

    /// The value, if any.
    pub fn value(&self) -> Option<f64> {
        self.estimate.map(|e| e.value)
    }

    /// Write `name`, `name_lo`, `name_hi`, `name_edf`, `name_region_s`, `name_reason`.
    fn write<M: SerializeMap>(
        &self,
        map: &mut M,
        name: &str,
        region: bool,
    ) -> Result<(), M::Error> {
        let e = self.estimate;
        map.serialize_entry(name, &e.map(|e| e.value))?;
        map.serialize_entry(&format!("{name}_lo"), &e.map(|e| e.lo))?;
        map.serialize_entry(&format!("{name}_hi"), &e.map(|e| e.hi))?;
        map.serialize_entry(
            &format!("{name}_edf"),
            &e.map(|e| e.edf).filter(|v| v.is_finite()),
        )?;
        if region {
            map.serialize_entry(
                &format!("{name}_region_s"),
                &self.region.map(|r| [r.tau_from_s, r.tau_to_s]),
            )?;
        }
        map.serialize_entry(&format!("{name}_reason"), &self.reason)
    }
}

/// The IEEE 952 graphical readings of one axis (see [`readings`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Ieee952 {
    /// White noise N, u/√Hz: the −½ line read at τ = 1 s.
    pub n: Reading,
    /// Bias instability B, u: minimum of the curve / 0.664.
    pub b: Reading,
    /// τ of the minimum, s.
    pub b_tau_s: Option<f64>,
    /// Rate random walk K, u/√s: the +½ line read at τ = 3 s.
    pub k: Reading,
}

impl Serialize for Ieee952 {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(None)?;
        self.n.write(&mut map, "n", true)?;
        self.b.write(&mut map, "b", true)?;
        map.serialize_entry("b_tau_s", &self.b_tau_s)?;
        self.k.write(&mut map, "k", true)?;
        map.end()
    }
}

impl Serialize for FittedModel {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(None)?;
        for (name, t) in model::TERM_NAMES.iter().zip(&self.terms) {
            t.write(&mut map, name, false)?;
        }
        map.serialize_entry("tau_from_s", &self.tau_from_s)?;
        map.serialize_entry("tau_to_s", &self.tau_to_s)?;
        map.serialize_entry("points", &self.points)?;
        map.serialize_entry("excluded", &self.excluded)?;
        map.serialize_entry(
            "chi2_ratio",
            &Some(self.chi2_ratio).filter(|v| v.is_finite()),
        )?;
        map.serialize_entry("inflation", &self.inflation)?;
        map.end()
    }
}

/// What the channel holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ChannelStatus {
    /// Noise to analyse.
    Ok,
    /// Every sample has the same value.
    Constant,
    /// The noise is below the quantisation step: the record shows the quantiser.
    QuantisedFlat,
}

/// Units of the coefficients of an axis whose rate is in `unit`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TermUnits {
    /// Of Q.
    pub q: String,
    /// Of N.
    pub n: String,
    /// Of B.
    pub b: String,
    /// Of K.
    pub k: String,
    /// Of R.
    pub r: String,
}

impl TermUnits {
    fn of(unit: &str) -> Self {
        let (q, r) = match unit {
            "rad/s" => ("rad".to_string(), "rad/s^2".to_string()),
            "m/s^2" => ("m/s".to_string(), "m/s^3".to_string()),
            u => (format!("{u}*s"), format!("{u}/s")),
        };
        Self {
            q,
            n: format!("{unit}/sqrt(Hz)"),
            b: unit.to_string(),
            k: format!("{unit}/sqrt(s)"),
            r,
        }
    }
}

/// Allan analysis of one axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AxisAllan {
    /// Axis name (`gyr_x` … `acc_z`).
    pub axis: String,
    /// Unit of the rate (`rad/s` or `m/s^2`).
    pub unit: String,
    /// Units of the coefficients.
    pub units: TermUnits,
    /// What the channel holds.
    pub status: ChannelStatus,
    /// Why the channel is not analysed (status other than `ok`).
    pub reason: Option<String>,
    /// The Allan curve.
    pub points: Vec<AllanPoint>,
    /// The IEEE 952 graphical readings.
    pub ieee952: Ieee952,
    /// The fitted model (`None` for a channel that is not analysed).
    pub fit: Option<FittedModel>,
}

/// Samples needed for an analysis: ten Allan points, the longest with nine clusters.
pub const MIN_SAMPLES: usize = 100;

fn cluster_sizes(n: usize, per_decade: usize) -> Vec<usize> {
    let m_max = n / 9;
    let mut ms: Vec<usize> = Vec::new();
    let per_decade = per_decade.max(1) as f64;
    let mut k = 0.0;
    loop {
        let m = 10f64.powf(k / per_decade).round() as usize;
        if m > m_max {
            break;
        }
        if ms.last() != Some(&m) {
            ms.push(m);
        }
        k += 1.0;
    }
    ms
}

fn check_rate(rate_hz: f64) -> Result<()> {
    if rate_hz.is_finite() && rate_hz > 0.0 {
        Ok(())
    } else {
        Err(Error::new(
            ErrorKind::InvalidInput,
            format!("sample rate {rate_hz} Hz"),
        ))
    }
}

/// Overlapping Allan variance at each cluster size `ms` (σ², not σ).
fn avar_at(y: &[f64], tau0: f64, ms: &[usize]) -> Vec<f64> {
    let n = y.len();
    // integrated angle, with the mean removed (it cancels in the second difference
    // but keeps the cumulative sum well conditioned)
    let mean = y.iter().sum::<f64>() / n as f64;
    let mut theta = Vec::with_capacity(n + 1);
    theta.push(0.0);
    let mut acc = 0.0;
    for v in y {
        acc += (v - mean) * tau0;
        theta.push(acc);
    }
    ms.iter()
        .map(|&m| {
            let tau = m as f64 * tau0;
            let cnt = n + 1 - 2 * m;
            let s: f64 = (0..cnt)
                .map(|i| {
                    let d = theta[i + 2 * m] - 2.0 * theta[i + m] + theta[i];
                    d * d
                })
                .sum();
            s / (2.0 * tau * tau * cnt as f64)
        })
        .collect()
}

fn check_finite(y: &[f64]) -> Result<()> {
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("Allan deviation: sample {i} is not finite"),
        ));
    }
    Ok(())
}

/// Overlapping Allan deviation of the rate record `y` sampled at `rate_hz`, on
/// about `per_decade` log-spaced cluster sizes m from 1 up to N/9 (so every
/// point has at least 9 independent clusters). The intervals here assume white
/// noise (the Howe–Allan–Barnes degrees of freedom, [`model::edf_white`]);
/// [`analyse_axis`] replaces them by those of the fitted noise model.
pub fn allan_deviation(y: &[f64], rate_hz: f64, per_decade: usize) -> Result<Vec<AllanPoint>> {
    check_rate(rate_hz)?;
    check_finite(y)?;
    let n = y.len();
    if n < 18 {
        return Err(Error::new(
            ErrorKind::Empty,
            format!("Allan deviation needs at least 18 samples, got {n}"),
        ));
    }
    let tau0 = 1.0 / rate_hz;
    let ms = cluster_sizes(n, per_decade);
    let av = avar_at(y, tau0, &ms);
    let edf: Vec<f64> = ms.iter().map(|&m| edf_white(n, m)).collect();
    let mut pts = points(&ms, &av, &edf, tau0);
    // slopes with the white-noise variances (no correlation between points)
    let cov: Vec<Vec<f64>> = (0..ms.len())
        .map(|i| {
            (0..ms.len())
                .map(|j| {
                    if i == j {
                        2.0 * av[i] * av[i] / edf[i]
                    } else {
                        0.0
                    }
                })
                .collect()
        })
        .collect();
    set_slopes(&mut pts, &cov, &av);
    Ok(pts)
}

fn points(ms: &[usize], av: &[f64], edf: &[f64], tau0: f64) -> Vec<AllanPoint> {
    ms.iter()
        .zip(av)
        .zip(edf)
        .map(|((&m, &a), &e)| {
            let (lo, hi) = chi2_factors(e);
            let adev = a.sqrt();
            AllanPoint {
                tau_s: m as f64 * tau0,
                adev,
                adev_lo: adev * lo.sqrt(),
                adev_hi: adev * hi.sqrt(),
                edf: e,
                slope: f64::NAN,
                slope_se: f64::NAN,
            }
        })
        .collect()
}

fn set_slopes(pts: &mut [AllanPoint], cov: &[Vec<f64>], avar: &[f64]) {
    let sl = readings::local_slopes(pts, cov, avar);
    for (p, (s, se)) in pts.iter_mut().zip(sl) {
        p.slope = s;
        p.slope_se = se;
    }
}

/// What a channel holds: constant, quantised flat (one value in ≥ 90 % of the
/// samples), or noise; with the explanation.
pub fn channel_status(y: &[f64], unit: &str) -> (ChannelStatus, Option<String>) {
    let mut v: Vec<f64> = y.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return (ChannelStatus::Constant, Some("no samples".into()));
    }
    v.sort_by(f64::total_cmp);
    if v[0] == v[v.len() - 1] {
        return (
            ChannelStatus::Constant,
            Some(format!(
                "constant channel: every one of the {} samples reads {:e} {unit} (a disconnected, \
                 stuck or saturated axis?); there is no noise to analyse",
                v.len(),
                v[0]
            )),
        );
    }
    let (mut best, mut run, mut step) = (1usize, 1usize, f64::INFINITY);
    for w in v.windows(2) {
        if w[1] == w[0] {
            run += 1;
        } else {
            step = step.min(w[1] - w[0]);
            run = 1;
        }
        best = best.max(run);
    }
    let frac = best as f64 / v.len() as f64;
    if frac >= 0.9 {
        return (
            ChannelStatus::QuantisedFlat,
            Some(format!(
                "quantised flat: {:.1} % of the samples read one value (step {step:.3e} {unit}); the \
                 noise is below the quantisation step, so the Allan curve shows the quantiser, not \
                 the sensor: no terms are read",
                100.0 * frac
            )),
        );
    }
    (ChannelStatus::Ok, None)
}

/// The full analysis of one axis: curve, IEEE 952 readings and fitted model
/// (see the module documentation). `y` is the rate record at `rate_hz`.
pub fn analyse_axis(axis: &str, unit: &str, y: &[f64], rate_hz: f64) -> Result<AxisAllan> {
    check_rate(rate_hz)?;
    check_finite(y)?;
    let n = y.len();
    if n < MIN_SAMPLES {
        return Err(Error::new(
            ErrorKind::Empty,
            format!(
                "{n} samples: an Allan analysis needs at least {MIN_SAMPLES} (ten τ points, nine clusters at the longest)"
            ),
        ));
    }
    let (status, reason) = channel_status(y, unit);
    let absent = |r: &str| Reading::absent(r.to_string());
    let mut pts = allan_deviation(y, rate_hz, 10)?;
    if status != ChannelStatus::Ok {
        let r = reason.clone().unwrap_or_default();
        if status == ChannelStatus::Constant {
            pts.clear();
        }
        return Ok(AxisAllan {
            axis: axis.into(),
            unit: unit.into(),
            units: TermUnits::of(unit),
            status,
            reason,
            points: pts,
            ieee952: Ieee952 {
                n: absent(&r),
                b: absent(&r),
                b_tau_s: None,
                k: absent(&r),
            },
            fit: None,
        });
    }
    let tau0 = 1.0 / rate_hz;
    let ms = cluster_sizes(n, 10);
    let av: Vec<f64> = pts.iter().map(|p| p.adev * p.adev).collect();
    // 1. white region and the fit's lower end, with white-noise statistics
    let slopes0: Vec<(f64, f64)> = pts.iter().map(|p| (p.slope, p.slope_se)).collect();
    let white = readings::white_region(&pts, &slopes0);
    let (fit_from, excluded) = match &white {
        Some(r) => {
            let c2: f64 = r
                .clone()
                .map(|j| pts[j].edf * av[j] * pts[j].tau_s)
                .sum::<f64>()
                / r.clone().map(|j| pts[j].edf).sum::<f64>();
            // include shorter τ down to the first point significantly below the line
            let mut from = r.start;
            while from > 0 && !readings::below_line(&pts[from - 1], c2, -0.5) {
                from -= 1;
            }
            let excluded = (from > 0).then(|| {
                format!(
                    "τ < {} s: the curve lies below the −1/2 line (consecutive samples are correlated, \
                     e.g. by internal filtering)",
                    g3(pts[from].tau_s)
                )
            });
            (from, excluded)
        }
        None => (0, None),
    };
    // 2. the model over that range
    let fit = fit::fit_model(&pts, &ms, fit_from..pts.len(), tau0, n, excluded);
    // 3. the covariance of the whole curve under the model: intervals, slopes, readings
    let model = fit.model;
    let cov = if model.squares().iter().any(|c| *c > 0.0) {
        avar_cov_matrix(&model, tau0, n, &ms)
    } else {
        (0..ms.len())
            .map(|i| {
                (0..ms.len())
                    .map(|j| {
                        if i == j {
                            2.0 * av[i] * av[i] / pts[i].edf
                        } else {
                            0.0
                        }
                    })
                    .collect()
            })
            .collect()
    };
    let expect: Vec<f64> = (0..ms.len())
        .map(|i| {
            let a = model.avar(pts[i].tau_s);
            if a > 0.0 { a } else { av[i] }
        })
        .collect();
    let edf: Vec<f64> = (0..ms.len())
        .map(|i| (2.0 * expect[i] * expect[i] / cov[i][i]).max(1.0))
        .collect();
    pts = points(&ms, &av, &edf, tau0);
    set_slopes(&mut pts, &cov, &expect);
    let slopes: Vec<(f64, f64)> = pts.iter().map(|p| (p.slope, p.slope_se)).collect();
    let (b, b_tau_s) = readings::read_b(&pts, &slopes, &cov);
    let ieee952 = Ieee952 {
        n: readings::read_n(&pts, white, &cov),
        b,
        b_tau_s,
        k: readings::read_k(&pts, &slopes, &cov),
    };
    Ok(AxisAllan {
        axis: axis.into(),
        unit: unit.into(),
        units: TermUnits::of(unit),
        status,
        reason,
        points: pts,
        ieee952,
        fit: Some(fit),
    })
}

/// `x` with three significant digits (fixed notation from 1e-3 to 1e5).
pub(crate) fn g3(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{x}");
    }
    if (1e-3..1e5).contains(&a) {
        let d = (2 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.d$}")
    } else {
        format!("{x:.2e}")
    }
}

/// True when `b` is strictly after `a` (false when either is NaN).
pub fn increasing(a: f64, b: f64) -> bool {
    matches!(b.partial_cmp(&a), Some(std::cmp::Ordering::Greater))
}

/// Names of the six axes, in [`allan_imu`]'s order.
pub const AXES: [&str; 6] = ["gyr_x", "gyr_y", "gyr_z", "acc_x", "acc_y", "acc_z"];

/// Allan analysis of the six axes of a static IMU record at `rate_hz`
/// (uniform sampling is the caller's to ensure: see
/// [`crate::testbench::static_record`]; time stamps are checked to increase).
pub fn allan_imu(samples: &[ImuSample], rate_hz: f64) -> Result<Vec<AxisAllan>> {
    if let Some(i) = samples
        .windows(2)
        .position(|w| !increasing(w[0].t_s, w[1].t_s))
    {
        return Err(Error::new(
            ErrorKind::TimeNotIncreasing,
            format!("time does not increase after sample {i}"),
        ));
    }
    AXES.iter()
        .enumerate()
        .map(|(k, name)| {
            let y: Vec<f64> = samples
                .iter()
                .map(|s| {
                    if k < 3 {
                        s.gyr_rad_s[k]
                    } else {
                        s.acc_m_s2[k - 3]
                    }
                })
                .collect();
            analyse_axis(name, if k < 3 { "rad/s" } else { "m/s^2" }, &y, rate_hz)
        })
        .collect()
}

#[cfg(test)]
mod tests;
