//! The IEEE Std 952 noise model, the covariance of overlapping Allan variance
//! estimates under it, their equivalent degrees of freedom, and chi-squared
//! confidence factors.
//!
//! **Model** (IEEE Std 952-1997, Annex C, eq. C.2–C.7, terms adding in variance):
//!
//! σ²(τ) = 3Q²/τ² + N²/τ + (2 ln 2/π)·B² + K²·τ/3 + R²·τ²/2,
//!
//! quantisation Q (u·s), white noise N (u/√Hz), bias instability B (u),
//! rate random walk K (u/√s) and rate ramp R (u/s), for a rate u (rad/s or m/s²).
//!
//! **Covariance.** The overlapping estimator at cluster size m averages the
//! squares of the second differences d_i = θ_{i+2m} − 2θ_{i+m} + θ_i of the
//! integrated record θ. For Gaussian noise, Cov(d₁ᵢ², d₂ⱼ²) = 2·Cov(d₁ᵢ, d₂ⱼ)², and
//! Cov(d₁ᵢ, d₂ⱼ) = Σ_{p,q} c_p c_q G(τ₀·(j − i + q·m₂ − p·m₁)) with c = (1, −2, 1)
//! and G the generalised autocovariance of θ (polynomials of degree ≤ 2 cancel
//! in a second difference, so G is defined up to them):
//!
//! | noise | G(s) |
//! |---|---|
//! | white N (θ a random walk) | −N²·\|s\|/2 |
//! | flicker B | (B²/2π)·s²·ln\|s\| |
//! | random walk K (sampled: the rate is a discrete random walk) | K²·(\|s\|³ − τ₀²·\|s\|)/12 |
//! | quantisation Q (θ white) | Q² at s = 0, else 0 |
//!
//! Each row reproduces its σ²(τ) term exactly (tested). A rate ramp adds the
//! constant μ = R·τ² to every d, hence 4·μ₁μ₂·Cov(d₁, d₂) to Cov(d₁², d₂²).
//! This is the construction of C. A. Greenhall and W. J. Riley, "Uncertainty of
//! stability variances based on finite differences", Proc. 35th PTTI, 2003
//! (their sz/BasicSum), written for a mixture of noises; for one power-law
//! noise it reproduces their equivalent degrees of freedom (tested against
//! values of their algorithm and their Table 2 asymptotes).

use statrs::function::gamma::checked_gamma_lr;

/// IEEE 952 factor of the bias-instability floor: σ_floor = √(2 ln 2/π)·B ≈ 0.664·B.
pub const B_FLOOR: f64 = 0.664_282_470_267_960_1;

/// Coefficient of B² in σ²: 2·ln 2/π (= [`B_FLOOR`]²).
pub const B_COEF: f64 = 2.0 * std::f64::consts::LN_2 / std::f64::consts::PI;

/// Names of the five model terms, in the order of [`basis`].
pub const TERM_NAMES: [&str; 5] = ["q", "n", "b", "k", "r"];

/// The IEEE Std 952 noise coefficients of one axis (0 for a term that is absent).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct NoiseModel {
    /// Quantisation noise Q, u·s (σ = √3·Q/τ).
    pub q: f64,
    /// White noise N (angle / velocity random walk), u/√Hz (σ = N/√τ).
    pub n: f64,
    /// Bias instability B, u (floor σ = 0.664·B).
    pub b: f64,
    /// Rate random walk K, u/√s (σ = K·√(τ/3)).
    pub k: f64,
    /// Rate ramp R, u/s (σ = R·τ/√2).
    pub r: f64,
}

/// σ²(τ) of a unit coefficient of each term: [3/τ², 1/τ, 2 ln 2/π, τ/3, τ²/2].
pub fn basis(tau: f64) -> [f64; 5] {
    [
        3.0 / (tau * tau),
        1.0 / tau,
        B_COEF,
        tau / 3.0,
        tau * tau / 2.0,
    ]
}

impl NoiseModel {
    /// From the squared coefficients (Q², N², B², K², R²), negative ones taken as 0.
    pub fn from_squares(c: [f64; 5]) -> Self {
        let s = |v: f64| v.max(0.0).sqrt();
        Self {
            q: s(c[0]),
            n: s(c[1]),
            b: s(c[2]),
            k: s(c[3]),
            r: s(c[4]),
        }
    }

    /// The squared coefficients (Q², N², B², K², R²).
    pub fn squares(&self) -> [f64; 5] {
        [self.q, self.n, self.b, self.k, self.r].map(|v| v * v)
    }

    /// Allan variance σ²(τ) of the model.
    pub fn avar(&self, tau: f64) -> f64 {
        basis(tau)
            .iter()
            .zip(self.squares())
            .map(|(b, c)| b * c)
            .sum()
    }

    /// Generalised autocovariance of the integrated record θ at lag `s` seconds
    /// (sample interval `tau0`), without the quantisation spike at s = 0.
    fn g(&self, s: f64, tau0: f64) -> f64 {
        let a = s.abs();
        if a == 0.0 {
            return 0.0;
        }
        let mut g = -0.5 * self.n * self.n * a;
        if self.b > 0.0 {
            g += self.b * self.b / (2.0 * std::f64::consts::PI) * s * s * a.ln();
        }
        if self.k > 0.0 {
            g += self.k * self.k * (a * a * a - tau0 * tau0 * a) / 12.0;
        }
        g
    }
}

const C: [f64; 3] = [1.0, -2.0, 1.0];

/// Sampling of the lag sum: at most this many lags per pair of cluster sizes
/// (a Riemann sum of a piecewise-smooth function; exact while the step is 1).
const LAG_SAMPLES: f64 = 160.0;

/// Covariance of the overlapping Allan variance estimates at cluster sizes
/// `m1` and `m2` of a record of `n` rate samples at interval `tau0`, under `model`.
pub fn avar_cov(model: &NoiseModel, tau0: f64, n: usize, m1: usize, m2: usize) -> f64 {
    let (len1, len2) = (n as i64 + 1 - 2 * m1 as i64, n as i64 + 1 - 2 * m2 as i64);
    if len1 < 1 || len2 < 1 {
        return f64::NAN;
    }
    let (mi, mj) = (m1 as f64, m2 as f64);
    let cd = |h: f64| -> f64 {
        let mut v = 0.0;
        for (p, cp) in C.iter().enumerate() {
            for (q, cq) in C.iter().enumerate() {
                v += cp * cq * model.g(tau0 * (h + q as f64 * mj - p as f64 * mi), tau0);
            }
        }
        v
    };
    // number of pairs (i, j), i < len1, j < len2, with j − i = h
    let count = |h: i64| -> f64 { ((len1.min(len2 - h)) - 0i64.max(-h)).max(0) as f64 };
    let (t1, t2) = (mi * tau0, mj * tau0);
    let (mu1, mu2) = (model.r * t1 * t1, model.r * t2 * t2);
    // support of Cov(d1_i, d2_{i+h}): (−2·m2, 2·m1) for the polynomial kernels;
    // flicker leaves a tail falling as 1/h², taken over a few supports more
    let ext = if model.b > 0.0 {
        4 * (m1 + m2) as i64
    } else {
        0
    };
    let h_lo = (-2 * m2 as i64 - ext).max(-(len1 - 1));
    let h_hi = (2 * m1 as i64 + ext).min(len2 - 1);
    let span = (h_hi - h_lo + 1) as f64;
    let step = (span / LAG_SAMPLES).floor().max(1.0) as i64;
    let mut sum = 0.0;
    let mut h = h_lo;
    while h <= h_hi {
        let c = cd(h as f64);
        sum += step as f64 * count(h) * (2.0 * c * c + 4.0 * mu1 * mu2 * c);
        h += step;
    }
    // quantisation: θ white, a spike of Q² where two phase samples coincide
    if model.q > 0.0 {
        let q2 = model.q * model.q;
        let mut lags: Vec<(i64, f64)> = Vec::with_capacity(9);
        for (p, cp) in C.iter().enumerate() {
            for (q, cq) in C.iter().enumerate() {
                let lag = p as i64 * m1 as i64 - q as i64 * m2 as i64;
                match lags.iter_mut().find(|(l, _)| *l == lag) {
                    Some((_, w)) => *w += cp * cq * q2,
                    None => lags.push((lag, cp * cq * q2)),
                }
            }
        }
        for (lag, cq) in lags {
            if lag < -(len1 - 1) || lag > len2 - 1 {
                continue;
            }
            let c = cd(lag as f64);
            sum += count(lag) * (2.0 * ((c + cq).powi(2) - c * c) + 4.0 * mu1 * mu2 * cq);
        }
    }
    sum / (4.0 * t1 * t1 * t2 * t2 * len1 as f64 * len2 as f64)
}

/// Covariance matrix of the estimates at all `ms` (see [`avar_cov`]).
pub fn avar_cov_matrix(model: &NoiseModel, tau0: f64, n: usize, ms: &[usize]) -> Vec<Vec<f64>> {
    let k = ms.len();
    let mut c = vec![vec![0.0; k]; k];
    for i in 0..k {
        for j in i..k {
            let v = avar_cov(model, tau0, n, ms[i], ms[j]);
            c[i][j] = v;
            c[j][i] = v;
        }
    }
    c
}

/// Equivalent degrees of freedom 2·σ⁴/Var(σ̂²) of the overlapping Allan variance
/// at cluster size `m` of `n` samples under `model` (at least 1).
pub fn edf(model: &NoiseModel, tau0: f64, n: usize, m: usize) -> f64 {
    let v = avar_cov(model, tau0, n, m, m);
    let a = model.avar(m as f64 * tau0);
    if !(v > 0.0 && a > 0.0) {
        return 1.0;
    }
    (2.0 * a * a / v).max(1.0)
}

/// Equivalent degrees of freedom of the overlapping Allan variance for white
/// rate noise: (3(N−1)/(2m) − 2(N−2)/N)·4m²/(4m² + 5), N the number of phase
/// samples (Howe, Allan & Barnes, "Properties of signal sources and
/// measurement methods", 35th Frequency Control Symposium, 1981). Used only
/// before a noise model is known.
pub fn edf_white(n_samples: usize, m: usize) -> f64 {
    let (n, m) = (n_samples as f64 + 1.0, m as f64);
    ((3.0 * (n - 1.0) / (2.0 * m) - 2.0 * (n - 2.0) / n) * 4.0 * m * m / (4.0 * m * m + 5.0))
        .max(1.0)
}

/// Confidence level of every interval here.
pub const CONFIDENCE: f64 = 0.99;

/// Two-sided standard-normal quantile of [`CONFIDENCE`] (z_{0.995}).
pub const Z99: f64 = 2.575_829_303_548_901;

/// Quantile of the chi-squared distribution with `dof` degrees of freedom:
/// the root of P(dof/2, x/2) = p, with P the regularised lower incomplete
/// gamma function of statrs (`gamma_lr`), found by bisection on ln x (statrs'
/// own `inverse_cdf` fails for the 0.005 quantile of one degree of freedom).
/// Above 10⁴ degrees of freedom the Wilson–Hilferty cube
/// k·(1 − 2/(9k) + z_p·√(2/(9k)))³ is used; it agrees to 1e-6 there (tested).
pub fn chi2_quantile(dof: f64, p: f64) -> f64 {
    if !(dof > 0.0 && p > 0.0 && p < 1.0) {
        return f64::NAN;
    }
    if dof > 1e4 {
        let z = normal_quantile(p);
        let a = 2.0 / (9.0 * dof);
        return dof * (1.0 - a + z * a.sqrt()).powi(3);
    }
    chi2_quantile_exact(dof, p)
}

fn chi2_quantile_exact(dof: f64, p: f64) -> f64 {
    let cdf = |x: f64| checked_gamma_lr(dof / 2.0, x / 2.0).unwrap_or(f64::NAN);
    let (mut lo, mut hi) = ((1e-300f64).ln(), (dof + 100.0 * dof.sqrt() + 1000.0).ln());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if cdf(mid.exp()) < p {
            lo = mid;
        } else {
            hi = mid;
        }
        if hi - lo < 1e-13 {
            break;
        }
    }
    (0.5 * (lo + hi)).exp()
}

/// Standard-normal quantile: −√2·erfc⁻¹(2p) (statrs).
fn normal_quantile(p: f64) -> f64 {
    -std::f64::consts::SQRT_2 * statrs::function::erf::erfc_inv(2.0 * p)
}

/// Factors (lo, hi) of the [`CONFIDENCE`] interval of a variance estimated
/// with `edf` degrees of freedom: σ² ∈ [σ̂²·lo, σ̂²·hi] with
/// lo = edf/χ²_{0.995}(edf), hi = edf/χ²_{0.005}(edf).
pub fn chi2_factors(edf: f64) -> (f64, f64) {
    let a = (1.0 - CONFIDENCE) / 2.0;
    let edf = edf.max(0.1);
    (
        edf / chi2_quantile(edf, 1.0 - a),
        edf / chi2_quantile(edf, a).max(1e-300),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_factor_is_ieee_952s_0664() {
        assert!((B_FLOOR * B_FLOOR - B_COEF).abs() < 1e-15);
        assert_eq!((B_FLOOR * 1000.0).round(), 664.0);
    }

    #[test]
    fn chi2_quantiles_match_published_tables() {
        // NIST/SEMATECH e-Handbook of Statistical Methods, table 1.3.6.7.4
        for (k, lo, hi) in [
            (1.0, 0.0000393, 7.879),
            (5.0, 0.412, 16.750),
            (10.0, 2.156, 25.188),
            (30.0, 13.787, 53.672),
            (100.0, 67.328, 140.169),
        ] {
            let (l, h) = (chi2_quantile(k, 0.005), chi2_quantile(k, 0.995));
            assert!((l / lo - 1.0).abs() < 2e-3, "k {k}: {l} vs {lo}");
            assert!((h / hi - 1.0).abs() < 1e-4, "k {k}: {h} vs {hi}");
        }
        // large dof: the Wilson–Hilferty cube agrees with the exact root at 10⁴ and beyond
        for k in [1e4f64, 1e5] {
            for p in [0.005, 0.995] {
                let z = normal_quantile(p);
                let wh = k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3);
                let exact = chi2_quantile_exact(k, p);
                assert!((exact / wh - 1.0).abs() < 1e-6, "{k} {p}: {exact} vs {wh}");
            }
        }
        assert!((normal_quantile(0.995) - Z99).abs() < 1e-9);
    }

    /// Mean of the estimator: the kernels of the table give back σ²(τ).
    fn avar_from_kernel(model: &NoiseModel, tau0: f64, m: usize) -> f64 {
        let t = m as f64 * tau0;
        let mut v = 0.0;
        for (p, cp) in C.iter().enumerate() {
            for (q, cq) in C.iter().enumerate() {
                let s = (q as f64 - p as f64) * t;
                v += cp * cq * model.g(s, tau0);
                if p == q {
                    v += cp * cq * model.q * model.q;
                }
            }
        }
        v / (2.0 * t * t)
    }

    #[test]
    fn kernels_reproduce_each_term_of_the_model() {
        let tau0 = 0.01;
        for (i, name) in TERM_NAMES.iter().enumerate().take(4) {
            let mut c = [0.0; 5];
            c[i] = 4e-6;
            let model = NoiseModel::from_squares(c);
            for m in [1usize, 3, 10, 100] {
                let t = m as f64 * tau0;
                let mut expect = model.avar(t);
                if *name == "k" {
                    // the sampled random walk adds K²τ₀²/(6τ): σ²(τ₀) = K²τ₀/2
                    expect += model.k * model.k * tau0 * tau0 / (6.0 * t);
                }
                let got = avar_from_kernel(&model, tau0, m);
                assert!(
                    (got / expect - 1.0).abs() < 1e-9,
                    "{name} m {m}: {got} vs {expect}"
                );
            }
        }
    }

    fn one(term: usize) -> NoiseModel {
        let mut c = [0.0; 5];
        c[term] = 1.0;
        NoiseModel::from_squares(c)
    }

    #[test]
    fn edf_of_one_noise_matches_greenhall() {
        // values of Greenhall & Riley's algorithm (allantools 2024.06,
        // edf_greenhall(alpha, d=2, m, N+1, overlapping=True)) for N rate samples
        let cases = [
            // (term, m, N, edf)
            (1, 50, 10_000, 297.78),
            (1, 300, 10_000, 47.767),
            (1, 1000, 100_000, 147.755),
            (1, 3000, 1_000_000, 497.75),
            (2, 50, 10_000, 232.94),
            (2, 300, 10_000, 37.304),
            (2, 1000, 100_000, 115.54),
            (2, 3000, 1_000_000, 389.41),
            (3, 50, 10_000, 183.84),
            (3, 300, 10_000, 29.362),
            (3, 1000, 100_000, 91.143),
            (3, 3000, 1_000_000, 307.39),
            (0, 10, 100_000, 51_421.4),
            (0, 1000, 100_000, 50_666.4),
        ];
        for (term, m, n, expect) in cases {
            let e = edf(&one(term), 0.01, n, m);
            // Greenhall's table values for flicker are fits to ~1 %
            let tol = if term == 2 { 0.02 } else { 0.01 };
            assert!(
                (e / expect - 1.0).abs() < tol,
                "{} m {m} N {n}: {e} vs {expect}",
                TERM_NAMES[term]
            );
        }
    }

    #[test]
    fn white_noise_edf_is_exact_at_short_tau() {
        // m = 1: d_i = τ₀(y_{i+1} − y_i), lag-one correlation −1/2, M = N − 1:
        // edf = M / (1 + 2·(1/4)·(1 − 1/M))
        let n = 1000usize;
        let mm = (n - 1) as f64;
        let expect = mm / (1.0 + 0.5 * (1.0 - 1.0 / mm));
        let e = edf(&one(1), 0.01, n, 1);
        assert!((e / expect - 1.0).abs() < 1e-12, "{e} vs {expect}");
        // and the Howe–Allan–Barnes formula agrees with the general one at m ≥ 2
        for m in [2usize, 5, 20, 100] {
            let (a, b) = (edf(&one(1), 0.01, n, m), edf_white(n, m));
            assert!((a / b - 1.0).abs() < 0.03, "m {m}: {a} vs {b}");
        }
    }

    #[test]
    fn sampled_lag_sum_agrees_with_the_exact_one() {
        // with m large the lag sum is sampled; compare with the same m at step 1
        let model = NoiseModel {
            q: 0.0,
            n: 1e-3,
            b: 2e-4,
            k: 3e-5,
            r: 0.0,
        };
        let exact = |m1: usize, m2: usize| {
            let (mi, mj) = (m1 as f64, m2 as f64);
            let n = 20_000usize;
            let tau0 = 0.1;
            let (len1, len2) = (n as i64 + 1 - 2 * m1 as i64, n as i64 + 1 - 2 * m2 as i64);
            let mut sum = 0.0;
            for h in -(len1 - 1)..len2 {
                let mut c = 0.0;
                for (p, cp) in C.iter().enumerate() {
                    for (q, cq) in C.iter().enumerate() {
                        c += cp
                            * cq
                            * model.g(tau0 * (h as f64 + q as f64 * mj - p as f64 * mi), tau0);
                    }
                }
                let cnt = ((len1.min(len2 - h)) - 0i64.max(-h)).max(0) as f64;
                sum += cnt * 2.0 * c * c;
            }
            let (t1, t2) = (mi * tau0, mj * tau0);
            sum / (4.0 * t1 * t1 * t2 * t2 * len1 as f64 * len2 as f64)
        };
        for (m1, m2) in [(40, 40), (100, 160), (300, 300), (200, 1000)] {
            let a = avar_cov(&model, 0.1, 20_000, m1, m2);
            let e = exact(m1, m2);
            assert!((a / e - 1.0).abs() < 0.02, "({m1}, {m2}): {a} vs {e}");
        }
    }
}
