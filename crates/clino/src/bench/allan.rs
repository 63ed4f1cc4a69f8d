//! Allan deviation and the IEEE Std 952 noise terms.
//!
//! Source: IEEE Std 952-1997 (R2008), "IEEE Standard Specification Format
//! Guide and Test Procedure for Single-Axis Interferometric Fiber Optic
//! Gyros", Annex C. For a rate record y_k sampled at f_s = 1/τ₀ with
//! integrated angle θ_k = τ₀·Σ_{j<k} y_j, the overlapping Allan variance at
//! τ = m·τ₀ (eq C.8) is
//!
//! σ²(τ) = Σ_{k=0}^{N−2m} (θ_{k+2m} − 2θ_{k+m} + θ_k)² / (2τ²·(N − 2m + 1)),
//!
//! Its percentage error is about 1/√(2(N/m − 1)) (C.1.6, one sigma); the
//! bounds given here are 99 % chi-square intervals with the equivalent
//! degrees of freedom of the overlapping estimator ([`edf`]). The noise terms add in variance:
//!
//! σ²(τ) = N²/τ + (2 ln 2/π)·B² + K²·τ/3,
//!
//! white noise N (angle or velocity random walk; the −½ slope, read at
//! τ = 1 s), bias instability B (the flat floor 0.664·B), and rate random walk
//! K (the +½ slope, read at τ = 3 s). They are estimated by a weighted,
//! non-negative least-squares fit of that sum to σ² on the log-spaced τ grid.
//! The confidence of each term is propagated from the bound on σ² at the τ
//! where that gives the tightest interval — where the term dominates and σ²
//! is best determined (a conservative bound: the fit uses every τ) — plus the whole share of the other terms there (their
//! shapes are idealised: band-limited flicker is not flat at its band edge),
//! widened by the Birge ratio √(χ²/(n − p)) of the
//! fit when the three-term model does not explain the curve within its
//! intervals (for instance where flicker noise leaves its 1/f band).

use crate::{Error, ErrorKind, Result};
use clino_core::ImuSample;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

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
    /// Local log-log slope d ln σ / d ln τ (0 at the ends).
    pub slope: f64,
}

/// One IEEE 952 noise coefficient with its confidence interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Term {
    /// Estimate.
    pub value: f64,
    /// Lower bound.
    pub lo: f64,
    /// Upper bound.
    pub hi: f64,
    /// τ at which the bound is taken (where it is tightest), s.
    pub tau_s: f64,
}

impl Term {
    /// True when `v` lies within [lo, hi].
    pub fn contains(&self, v: f64) -> bool {
        v >= self.lo && v <= self.hi
    }
}

/// IEEE 952 terms of one axis (`None` when the fit gives the term no weight).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct NoiseTerms {
    /// White noise N (angle / velocity random walk), u/√Hz = u·√s.
    pub white: Option<Term>,
    /// Bias instability B, u.
    pub bias_instability: Option<Term>,
    /// Rate random walk K, u/√s.
    pub random_walk: Option<Term>,
}

/// Overlapping Allan deviation of the rate record `y` sampled at `rate_hz`, on
/// about `per_decade` log-spaced cluster sizes m from 1 up to N/9 (so every
/// point has at least 9 independent clusters).
pub fn allan_deviation(y: &[f64], rate_hz: f64, per_decade: usize) -> Result<Vec<AllanPoint>> {
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("sample rate {rate_hz} Hz"),
        ));
    }
    if let Some(i) = y.iter().position(|v| !v.is_finite()) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("Allan deviation: sample {i} is not finite"),
        ));
    }
    let n = y.len();
    if n < 18 {
        return Err(Error::new(
            ErrorKind::Empty,
            format!("Allan deviation needs at least 18 samples, got {n}"),
        ));
    }
    let tau0 = 1.0 / rate_hz;
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
    let mut pts: Vec<AllanPoint> = ms
        .iter()
        .map(|&m| {
            let tau = m as f64 * tau0;
            let cnt = n + 1 - 2 * m;
            let s: f64 = (0..cnt)
                .map(|i| {
                    let d = theta[i + 2 * m] - 2.0 * theta[i + m] + theta[i];
                    d * d
                })
                .sum();
            let avar = s / (2.0 * tau * tau * cnt as f64);
            let adev = avar.sqrt();
            let (lo, hi) = chi2_bounds(edf(n, m));
            AllanPoint {
                tau_s: tau,
                adev,
                adev_lo: adev * lo.sqrt(),
                adev_hi: adev * hi.sqrt(),
                slope: 0.0,
            }
        })
        .collect();
    for i in 1..pts.len().saturating_sub(1) {
        let (a, b) = (pts[i - 1], pts[i + 1]);
        if a.adev > 0.0 && b.adev > 0.0 {
            pts[i].slope = (b.adev / a.adev).ln() / (b.tau_s / a.tau_s).ln();
        }
    }
    Ok(pts)
}

/// Equivalent degrees of freedom of the overlapping Allan variance of N
/// samples at cluster size m: the smaller of the white-FM and random-walk-FM
/// approximations of Howe, Allan & Barnes, "Properties of signal sources and
/// measurement methods", Proc. 35th Frequency Control Symposium, 1981:
/// edf_W = (3(N−1)/(2m) − 2(N−2)/N)·4m²/(4m² + 5) and
/// edf_RW = (N−2)/m·((N−1)² − 3m(N−1) + 4m²)/(N−3)².
pub fn edf(n: usize, m: usize) -> f64 {
    let (n, m) = (n as f64, m as f64);
    let w = (3.0 * (n - 1.0) / (2.0 * m) - 2.0 * (n - 2.0) / n) * 4.0 * m * m / (4.0 * m * m + 5.0);
    let rw =
        (n - 2.0) / m * ((n - 1.0).powi(2) - 3.0 * m * (n - 1.0) + 4.0 * m * m) / (n - 3.0).powi(2);
    w.min(rw).max(1.0)
}

/// 99 % bounds of σ²/σ̂² for `edf` degrees of freedom: edf/χ²_{0.995} and
/// edf/χ²_{0.005}, with the Wilson–Hilferty approximation
/// χ²_p(k) ≈ k·(1 − 2/(9k) + z_p·√(2/(9k)))³.
pub fn chi2_bounds(edf: f64) -> (f64, f64) {
    let q = |z: f64| {
        let a = 2.0 / (9.0 * edf);
        edf * (1.0 - a + z * a.sqrt()).max(0.0).powi(3)
    };
    (edf / q(2.575_829), edf / q(-2.575_829).max(1e-300))
}

/// Coefficient of B² in σ²: 2·ln 2/π.
const B_COEF: f64 = 2.0 * std::f64::consts::LN_2 / std::f64::consts::PI;

/// The IEEE 952 terms N, B, K of an Allan curve (see the module doc).
pub fn noise_terms(pts: &[AllanPoint]) -> Result<NoiseTerms> {
    if pts.len() < 3 {
        return Err(Error::new(
            ErrorKind::Degenerate,
            "too few Allan points to read the noise terms",
        ));
    }
    // basis functions of σ²(τ) for c = (N², B², K²)
    let basis = |tau: f64| [1.0 / tau, B_COEF, tau / 3.0];
    let rows = pts.len();
    // weights: each row divided by the width of its σ² interval
    let w: Vec<f64> = pts
        .iter()
        .map(|p| 1.0 / (p.adev_hi.powi(2) - p.adev_lo.powi(2)).max(1e-300))
        .collect();
    let mut best: Option<(f64, [f64; 3])> = None;
    for mask in 1u8..8 {
        let cols: Vec<usize> = (0..3).filter(|j| mask & (1 << j) != 0).collect();
        let a = DMatrix::from_fn(rows, cols.len(), |i, j| basis(pts[i].tau_s)[cols[j]] * w[i]);
        let b = DVector::from_fn(rows, |i, _| pts[i].adev * pts[i].adev * w[i]);
        let Ok(x) = a.clone().svd(true, true).solve(&b, 1e-300) else {
            continue;
        };
        if x.iter().any(|v| *v < 0.0 || !v.is_finite()) {
            continue;
        }
        let r = (b - a * &x).norm_squared();
        let mut c = [0.0; 3];
        for (j, &col) in cols.iter().enumerate() {
            c[col] = x[j];
        }
        if best.is_none_or(|(rb, _)| r < rb) {
            best = Some((r, c));
        }
    }
    let (_, c) = best.ok_or_else(|| {
        Error::new(
            ErrorKind::Degenerate,
            "no non-negative noise model fits the Allan curve",
        )
    })?;
    let model = |tau: f64| basis(tau).iter().zip(c).map(|(b, c)| b * c).sum::<f64>();
    // Birge ratio: when the three-term model misses the curve by more than its
    // intervals allow (reduced χ² > 1), widen every interval by √χ²_red
    let k_params = c.iter().filter(|v| **v > 0.0).count();
    let chi2: f64 = pts
        .iter()
        .map(|p| {
            let half = 0.5 * (p.adev_hi.powi(2) - p.adev_lo.powi(2)) / 2.575_829;
            ((p.adev * p.adev - model(p.tau_s)) / half).powi(2)
        })
        .sum();
    let inflate = if rows > k_params {
        (chi2 / (rows - k_params) as f64).sqrt().max(1.0)
    } else {
        1.0
    };
    let term = |j: usize| -> Option<Term> {
        if c[j] <= 0.0 {
            return None;
        }
        // the bound at each τ; keep the tightest (where the term dominates and
        // the Allan variance is best determined)
        let (lo2, hi2, tau) = pts
            .iter()
            .map(|p| {
                let tot = model(p.tau_s);
                let (lo_f, hi_f) = ((p.adev_lo / p.adev).powi(2), (p.adev_hi / p.adev).powi(2));
                let bj = basis(p.tau_s)[j];
                let others = tot - bj * c[j];
                let lo2 = (c[j] - (inflate * tot * (1.0 - lo_f) + others) / bj).max(0.0);
                let hi2 = c[j] + (inflate * tot * (hi_f - 1.0) + others) / bj;
                (lo2, hi2, p.tau_s)
            })
            .min_by(|a, b| (a.1 - a.0).total_cmp(&(b.1 - b.0)))?;
        Some(Term {
            value: c[j].sqrt(),
            lo: lo2.sqrt(),
            hi: hi2.sqrt(),
            tau_s: tau,
        })
    };
    Ok(NoiseTerms {
        white: term(0),
        bias_instability: term(1),
        random_walk: term(2),
    })
}

/// True when `b` is strictly after `a` (false when either is NaN).
pub fn increasing(a: f64, b: f64) -> bool {
    matches!(b.partial_cmp(&a), Some(std::cmp::Ordering::Greater))
}

/// Allan analysis of one axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AxisAllan {
    /// Axis name (`gyr_x` … `acc_z`).
    pub axis: String,
    /// Unit of the coefficients' base quantity (`rad/s` or `m/s^2`).
    pub unit: String,
    /// The Allan curve.
    pub points: Vec<AllanPoint>,
    /// The IEEE 952 terms.
    pub terms: NoiseTerms,
}

/// Allan analysis of the six axes of a static IMU record at `rate_hz`
/// (the sample spacing is assumed uniform; time stamps are checked to increase).
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
    let names = ["gyr_x", "gyr_y", "gyr_z", "acc_x", "acc_y", "acc_z"];
    names
        .iter()
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
            let points = allan_deviation(&y, rate_hz, 10)?;
            let terms = noise_terms(&points)?;
            Ok(AxisAllan {
                axis: name.to_string(),
                unit: if k < 3 { "rad/s" } else { "m/s^2" }.into(),
                points,
                terms,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ImuModel;
    use crate::sim::motion::Static;

    #[test]
    fn white_noise_has_slope_minus_half() {
        let mut m = ImuModel::ideal();
        m.gyro.noise_density = 0.01;
        let s = m.simulate(&Static::level(), 100.0, 600.0, 11);
        let y: Vec<f64> = s.iter().map(|x| x.gyr_rad_s.x).collect();
        let pts = allan_deviation(&y, 100.0, 10).unwrap();
        for p in &pts {
            // σ(τ) = N/√τ within the stated bound
            let expect = 0.01 / p.tau_s.sqrt();
            assert!(
                expect >= p.adev_lo * 0.98 && expect <= p.adev_hi * 1.02,
                "{p:?} {expect}"
            );
        }
        let mid = &pts[pts.len() / 2];
        assert!((mid.slope + 0.5).abs() < 0.15, "{mid:?}");
    }

    #[test]
    fn white_noise_and_random_walk_are_recovered() {
        let (n, k) = (0.002, 0.0004);
        let mut m = ImuModel::ideal();
        m.gyro.noise_density = n;
        m.gyro.random_walk = k;
        m.accel.noise_density = 0.003;
        m.accel.random_walk = 0.0002;
        let s = m.simulate(&Static::level(), 50.0, 4000.0, 5);
        let res = allan_imu(&s, 50.0).unwrap();
        for ax in &res {
            let (n, k) = if ax.axis.starts_with("gyr") {
                (n, k)
            } else {
                (0.003, 0.0002)
            };
            let w = ax.terms.white.unwrap();
            let r = ax.terms.random_walk.unwrap();
            assert!(w.contains(n), "{}: N {w:?} vs {n}", ax.axis);
            assert!(r.contains(k), "{}: K {r:?} vs {k}", ax.axis);
            // and the bounds are informative
            assert!(
                w.hi / w.lo < 1.1 && r.hi / r.lo < 5.0,
                "{}: {w:?} {r:?}",
                ax.axis
            );
        }
    }

    #[test]
    fn mpu6050_preset_returns_its_own_coefficients() {
        let m = ImuModel::mpu6050();
        let rate = 10.0;
        let s = m.simulate(&Static::level(), rate, 6.0 * 3600.0, 9);
        let res = allan_imu(&s, rate).unwrap();
        for ax in &res {
            let e = if ax.axis.starts_with("gyr") {
                &m.gyro
            } else {
                &m.accel
            };
            // rate quantisation adds white noise LSB²/(12·f_s)
            let n_expect = (e.noise_density.powi(2) + e.lsb.powi(2) / (12.0 * rate)).sqrt();
            let w = ax.terms.white.unwrap();
            assert!(w.contains(n_expect), "{}: N {w:?} vs {n_expect}", ax.axis);
            let r = ax.terms.random_walk.unwrap();
            assert!(
                r.contains(e.random_walk),
                "{}: K {r:?} vs {}",
                ax.axis,
                e.random_walk
            );
            eprintln!(
                "{}: N {w:?} (true {n_expect:.4e}); K {r:?} (true {:.4e})",
                ax.axis, e.random_walk
            );
        }
    }

    #[test]
    fn bad_records_are_errors() {
        assert!(allan_deviation(&[1.0; 5], 100.0, 10).is_err());
        let mut y = vec![0.0; 100];
        y[3] = f64::NAN;
        assert_eq!(
            allan_deviation(&y, 100.0, 10).unwrap_err().kind,
            ErrorKind::InvalidInput
        );
    }
}
