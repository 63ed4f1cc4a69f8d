//! Fit of the IEEE 952 model to an Allan curve over the τ range it describes.
//!
//! * **Estimator**: non-negative weighted least squares of σ̂²(τ) on the five
//!   basis functions of [`basis`], iterated so that the weights are
//!   1/Var(σ̂²(τ)) of the fitted model itself ([`avar_cov`], not the data's own
//!   σ̂⁴, which would favour the points that came out low).
//! * **Uncertainty**: the estimates are linear in σ̂², c = L·σ̂², so their
//!   covariance is L·Σ·Lᵀ with Σ the full covariance of the correlated
//!   estimates at all τ ([`avar_cov_matrix`]): the points are not independent
//!   and are not treated as such. Each coefficient c_j (a squared term) gets
//!   Satterthwaite's edf_j = 2c_j²/Var(c_j) and a chi-squared interval.
//! * **Terms present**: a term stays in the model only while c_j/sd(c_j) ≥
//!   z_{0.995} = 2.58 (backward elimination, weakest first), else it is
//!   reported absent with that reason.
//! * **Adequacy**: the weighted residual sum Q is compared with its
//!   distribution under the model (mean tr(T), variance 2·tr(T²), T = W^½·P·Σ·Pᵀ·W^½,
//!   P = I − A·L; Satterthwaite). When Q exceeds its 99th percentile the model
//!   does not describe the curve within its scatter and every interval is
//!   widened by √(Q/E(Q)) (a Birge ratio), reported as `inflation`.

use super::model::{
    NoiseModel, TERM_NAMES, Z99, avar_cov, avar_cov_matrix, basis, chi2_factors, chi2_quantile,
    edf_white,
};
use super::{AllanPoint, Estimate, Reading, g3};
use nalgebra::{DMatrix, DVector};

/// The fitted IEEE 952 model of one axis.
#[derive(Clone, Debug, PartialEq)]
pub struct FittedModel {
    /// The point estimates (0 for absent terms).
    pub model: NoiseModel,
    /// Each term (Q, N, B, K, R) with its interval, or the reason it is absent.
    pub terms: [Reading; 5],
    /// Shortest τ of the fitted range, s.
    pub tau_from_s: f64,
    /// Longest τ of the fitted range, s.
    pub tau_to_s: f64,
    /// Curve points fitted.
    pub points: usize,
    /// Why the points below `tau_from_s` were left out, if any were.
    pub excluded: Option<String>,
    /// Weighted residual sum over its expectation under the model (≈ 1 when
    /// the model describes the curve).
    pub chi2_ratio: f64,
    /// Factor applied to every interval's width for a model that misses the curve (1 when it does not).
    pub inflation: f64,
}

/// Weighted non-negative least squares over the columns in `active`: the best
/// all-non-negative solution of every subset (that is the NNLS optimum).
fn nnls(a: &DMatrix<f64>, s: &DVector<f64>, w: &DVector<f64>, active: [bool; 5]) -> [f64; 5] {
    let rows = a.nrows();
    let cols_all: Vec<usize> = (0..5).filter(|&j| active[j]).collect();
    let mut best: Option<(f64, [f64; 5])> = None;
    for mask in 1u32..(1 << cols_all.len()) {
        let cols: Vec<usize> = cols_all
            .iter()
            .enumerate()
            .filter(|(b, _)| mask & (1 << b) != 0)
            .map(|(_, &j)| j)
            .collect();
        // column scaling: the basis spans many decades
        let scale: Vec<f64> = cols
            .iter()
            .map(|&j| {
                (0..rows)
                    .map(|i| (a[(i, j)] * w[i].sqrt()).powi(2))
                    .sum::<f64>()
                    .sqrt()
                    .max(1e-300)
            })
            .collect();
        let aw = DMatrix::from_fn(rows, cols.len(), |i, k| {
            a[(i, cols[k])] * w[i].sqrt() / scale[k]
        });
        let bw = DVector::from_fn(rows, |i, _| s[i] * w[i].sqrt());
        let Ok(x) = aw.clone().svd(true, true).solve(&bw, 1e-14) else {
            continue;
        };
        if x.iter().any(|v| *v < 0.0 || !v.is_finite()) {
            continue;
        }
        let r = (bw - aw * &x).norm_squared();
        let mut c = [0.0; 5];
        for (k, &j) in cols.iter().enumerate() {
            c[j] = x[k] / scale[k];
        }
        if best.is_none_or(|(rb, _)| r < rb) {
            best = Some((r, c));
        }
    }
    best.map_or([0.0; 5], |(_, c)| c)
}

/// Fit the model to `pts[range]` of a record of `n` samples at interval `tau0`
/// (`ms` the cluster sizes of the points).
pub(super) fn fit_model(
    pts: &[AllanPoint],
    ms: &[usize],
    range: std::ops::Range<usize>,
    tau0: f64,
    n: usize,
    excluded: Option<String>,
) -> FittedModel {
    let idx: Vec<usize> = range.collect();
    let rows = idx.len();
    let a = DMatrix::from_fn(rows, 5, |i, j| basis(pts[idx[i]].tau_s)[j]);
    let s = DVector::from_fn(rows, |i, _| pts[idx[i]].adev.powi(2));
    let fit_ms: Vec<usize> = idx.iter().map(|&i| ms[i]).collect();
    let tau_from_s = pts[idx[0]].tau_s;
    let tau_to_s = pts[idx[rows - 1]].tau_s;
    let mut active = [true; 5];
    let mut why: [Option<String>; 5] = Default::default();
    // first weights: white-noise degrees of freedom over the data's own σ̂⁴
    let w0 = DVector::from_fn(rows, |i, _| {
        edf_white(n, fit_ms[i]) / (2.0 * s[i] * s[i]).max(1e-300)
    });
    let mut c = nnls(&a, &s, &w0, active);
    let reweigh = |c: &[f64; 5]| {
        let model = NoiseModel::from_squares(*c);
        DVector::from_fn(rows, |i, _| {
            1.0 / avar_cov(&model, tau0, n, fit_ms[i], fit_ms[i]).max(1e-300)
        })
    };
    let mut w = w0.clone();
    let (mut l, mut cov_c, mut sigma);
    loop {
        for _ in 0..3 {
            if c.iter().all(|v| *v == 0.0) {
                break;
            }
            w = reweigh(&c);
            c = nnls(&a, &s, &w, active);
        }
        let model = NoiseModel::from_squares(c);
        sigma = DMatrix::from_fn(rows, rows, |_, _| 0.0);
        let full = avar_cov_matrix(&model, tau0, n, &fit_ms);
        for i in 0..rows {
            for j in 0..rows {
                sigma[(i, j)] = full[i][j];
            }
        }
        // c = L·s on the positive columns
        let pos: Vec<usize> = (0..5).filter(|&j| c[j] > 0.0).collect();
        l = DMatrix::zeros(5, rows);
        if !pos.is_empty() {
            let ap = DMatrix::from_fn(rows, pos.len(), |i, k| a[(i, pos[k])]);
            let wm = DMatrix::from_diagonal(&w);
            let normal = ap.transpose() * &wm * &ap;
            // scale for the inverse (columns span decades)
            let d: Vec<f64> = (0..pos.len())
                .map(|k| normal[(k, k)].sqrt().max(1e-300))
                .collect();
            let ns = DMatrix::from_fn(pos.len(), pos.len(), |i, j| normal[(i, j)] / (d[i] * d[j]));
            if let Some(inv) = ns.try_inverse() {
                let inv =
                    DMatrix::from_fn(pos.len(), pos.len(), |i, j| inv[(i, j)] / (d[i] * d[j]));
                let lp = inv * ap.transpose() * &wm;
                for (k, &j) in pos.iter().enumerate() {
                    for i in 0..rows {
                        l[(j, i)] = lp[(k, i)];
                    }
                }
            }
        }
        cov_c = &l * &sigma * l.transpose();
        // weakest positive term
        let weakest = pos
            .iter()
            .map(|&j| (j, c[j] / cov_c[(j, j)].max(0.0).sqrt()))
            .min_by(|x, y| x.1.total_cmp(&y.1));
        match weakest {
            Some((j, z)) if z < Z99 && pos.len() > 1 => {
                why[j] = Some(format!(
                    "not significant in the fit: {}² = {:.3e} ± {:.3e} (below 2.58 standard deviations)",
                    TERM_NAMES[j].to_uppercase(),
                    c[j],
                    cov_c[(j, j)].max(0.0).sqrt()
                ));
                active[j] = false;
                c = nnls(&a, &s, &w, active);
            }
            _ => break,
        }
    }
    // adequacy of the model: Q = rᵀWr against its distribution under Σ
    let r = &s - &a * DVector::from_column_slice(&c);
    let q_obs: f64 = (0..rows).map(|i| w[i] * r[i] * r[i]).sum();
    let p = DMatrix::identity(rows, rows) - &a * &l;
    let wh = DMatrix::from_diagonal(&w.map(f64::sqrt));
    let t = &wh * &p * &sigma * p.transpose() * &wh;
    let e_q = t.trace();
    let v_q = 2.0 * (&t * &t).trace();
    let (chi2_ratio, inflation) = if e_q > 0.0 && v_q > 0.0 {
        let dof = 2.0 * e_q * e_q / v_q;
        let limit = e_q * chi2_quantile(dof, 0.99) / dof;
        let ratio = q_obs / e_q;
        (ratio, if q_obs > limit { ratio.sqrt() } else { 1.0 })
    } else {
        (f64::NAN, 1.0)
    };
    let terms = std::array::from_fn(|j| {
        if c[j] > 0.0 {
            let var = cov_c[(j, j)].max(0.0) * inflation * inflation;
            let edf = if var > 0.0 {
                2.0 * c[j] * c[j] / var
            } else {
                f64::INFINITY
            };
            let (lo, hi) = chi2_factors(edf.min(1e9));
            Reading {
                estimate: Some(Estimate {
                    value: c[j].sqrt(),
                    lo: (c[j] * lo).sqrt(),
                    hi: (c[j] * hi).sqrt(),
                    edf,
                }),
                region: None,
                reason: None,
            }
        } else {
            Reading {
                estimate: None,
                region: None,
                reason: Some(why[j].clone().unwrap_or_else(|| {
                    format!(
                        "the fit gives it no weight over τ = {} … {} s",
                        g3(tau_from_s),
                        g3(tau_to_s)
                    )
                })),
            }
        }
    });
    FittedModel {
        model: NoiseModel::from_squares(c),
        terms,
        tau_from_s,
        tau_to_s,
        points: rows,
        excluded,
        chi2_ratio,
        inflation,
    }
}
