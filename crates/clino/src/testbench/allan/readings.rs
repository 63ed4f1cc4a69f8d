//! The conventional graphical readings of IEEE Std 952 (Annex C), taken from
//! the curve where it has the slope of the term:
//!
//! * `n`: the line of slope −½ through the white-noise region, read at τ = 1 s;
//! * `b`: the minimum of the curve divided by √(2 ln 2/π) = 0.664, at `b_tau_s`;
//! * `k`: the line of slope +½ through the random-walk region, read at τ = 3 s.
//!
//! **Regions.** The local slope at each point is the least-squares slope of
//! ln σ on ln τ over the points within ±0.2 decade ([`SLOPE_WINDOW_DECADES`]),
//! with its standard error from the covariance of the estimates. A point
//! belongs to the −½ region when its slope lies in [−½ − [`SLOPE_TOL`], −½ + `SLOPE_TOL`/2]
//! (a run of at least three). The +½ region is a run of points whose slopes
//! lie in [+½ − `SLOPE_TOL`, +½ + max(`SLOPE_TOL`, 2.58·se)], and whose overall rise is significant
//! (the slope of the run, less 2.58 standard errors, is above 0); the floor
//! needs a local slope at the minimum within max(`SLOPE_TOL`, 2.58·se) of 0
//! that is distinguishable from both −½ and +½. Otherwise the reading is
//! `None` with the reason.
//!
//! **Line readings.** Through a region of slope β, c² = Σ w_j σ̂_j²·τ_j^(−2β) / Σ w_j
//! (unbiased in σ²; its variance from the full covariance, so correlated points
//! count as such); the interval is chi-squared with Satterthwaite's
//! edf = 2c⁴/Var(c²). For `n`, w_j are the degrees of freedom of each point
//! (the shortest τ, best determined, are also the least touched by the floor);
//! for `k`, w_j = 1 (the shortest τ of a +½ region are the most touched by it).
//!
//! These are the conventional readings, not the noise terms: each carries the
//! share of the other terms at its τ (`n` and `k` read high where the floor is
//! near, `b` reads high by the white noise and random walk at the minimum, and
//! is only an upper bound of B where white noise meets random walk without a
//! floor). Their intervals are those of the reading; the fitted model
//! ([`super::fit`]) separates the terms.

use super::model::{B_FLOOR, Z99, chi2_factors};
use super::{AllanPoint, Estimate, Reading, Region, g3};

/// Tolerance on a local slope for a region of slope −½ (and the least one for 0 and +½).
pub const SLOPE_TOL: f64 = 0.1;

/// Half-width of the window of the local slope, decades of τ.
pub const SLOPE_WINDOW_DECADES: f64 = 0.2;

/// Local log-log slopes and their standard errors at every point (over the
/// points within ±0.2 decade and at least the neighbours on each side), with `cov`
/// the covariance of σ̂² between points and `avar` the expected σ² at each.
pub fn local_slopes(pts: &[AllanPoint], cov: &[Vec<f64>], avar: &[f64]) -> Vec<(f64, f64)> {
    let k = pts.len();
    (0..k)
        .map(|i| {
            let lt = pts[i].tau_s.log10();
            let win: Vec<usize> = (0..k)
                .filter(|&j| {
                    j + 1 == i
                        || j == i + 1
                        || (pts[j].tau_s.log10() - lt).abs() <= SLOPE_WINDOW_DECADES + 1e-9
                })
                .filter(|&j| pts[j].adev > 0.0)
                .collect();
            if win.len() < 2 {
                return (f64::NAN, f64::INFINITY);
            }
            let x: Vec<f64> = win.iter().map(|&j| pts[j].tau_s.ln()).collect();
            let xm = x.iter().sum::<f64>() / x.len() as f64;
            let sxx: f64 = x.iter().map(|v| (v - xm).powi(2)).sum();
            // slope = Σ a_j ln σ̂_j, a_j = (x_j − x̄)/Sxx; ln σ̂ = ½ ln σ̂²
            let a: Vec<f64> = x.iter().map(|v| (v - xm) / sxx).collect();
            let slope: f64 = win
                .iter()
                .zip(&a)
                .map(|(&j, aj)| aj * pts[j].adev.ln())
                .sum();
            let mut var = 0.0;
            for (p, &jp) in win.iter().enumerate() {
                for (q, &jq) in win.iter().enumerate() {
                    var += a[p] * a[q] * cov[jp][jq] / (avar[jp] * avar[jq]);
                }
            }
            (slope, 0.5 * var.max(0.0).sqrt())
        })
        .collect()
}

/// Line of slope `beta` through `pts[range]`: c² (σ² = c²·τ^{2β}) with its
/// variance.
fn line(
    pts: &[AllanPoint],
    range: &std::ops::Range<usize>,
    beta: f64,
    cov: &[Vec<f64>],
    weighted: bool,
) -> (f64, f64) {
    let w: Vec<f64> = range
        .clone()
        .map(|j| if weighted { pts[j].edf } else { 1.0 })
        .collect();
    let sw: f64 = w.iter().sum();
    let f: Vec<f64> = range
        .clone()
        .map(|j| pts[j].tau_s.powf(-2.0 * beta))
        .collect();
    let c2: f64 = range
        .clone()
        .enumerate()
        .map(|(p, j)| w[p] * f[p] * pts[j].adev.powi(2))
        .sum::<f64>()
        / sw;
    let mut var = 0.0;
    for (p, jp) in range.clone().enumerate() {
        for (q, jq) in range.clone().enumerate() {
            var += w[p] * w[q] * f[p] * f[q] * cov[jp][jq];
        }
    }
    (c2, var / (sw * sw))
}

/// An estimate of a coefficient from its square `c2`, the variance of `c2`,
/// scaled by `scale` (the coefficient is √(scale·c²)).
fn estimate(c2: f64, var: f64, scale: f64) -> Estimate {
    let edf = if var > 0.0 {
        2.0 * c2 * c2 / var
    } else {
        f64::INFINITY
    };
    let (lo, hi) = chi2_factors(edf.min(1e9));
    Estimate {
        value: (scale * c2).sqrt(),
        lo: (scale * c2 * lo).sqrt(),
        hi: (scale * c2 * hi).sqrt(),
        edf,
    }
}

fn region(pts: &[AllanPoint], r: &std::ops::Range<usize>) -> Region {
    Region {
        tau_from_s: pts[r.start].tau_s,
        tau_to_s: pts[r.end - 1].tau_s,
        points: r.len(),
    }
}

/// Runs of consecutive indices where `ok` holds.
fn runs(k: usize, ok: impl Fn(usize) -> bool) -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut start = None;
    for i in 0..=k {
        let inside = i < k && ok(i);
        match (inside, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                out.push(s..i);
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// The white-noise (−½) region: the run of at least three points with slope
/// in [−½ − [`SLOPE_TOL`], −½ + `SLOPE_TOL`/2] holding the most degrees of
/// freedom. (Where internal filtering correlates consecutive samples the
/// curve is flatter than −½ and below the line: those points are not in it.)
pub(super) fn white_region(
    pts: &[AllanPoint],
    slopes: &[(f64, f64)],
) -> Option<std::ops::Range<usize>> {
    runs(pts.len(), |i| {
        let s = slopes[i].0;
        (-0.5 - SLOPE_TOL..=-0.5 + SLOPE_TOL / 2.0).contains(&s)
    })
    .into_iter()
    .filter(|r| r.len() >= 3)
    .max_by(|a, b| {
        let e = |r: &std::ops::Range<usize>| r.clone().map(|j| pts[j].edf).sum::<f64>();
        e(a).total_cmp(&e(b))
    })
}

/// True when the point lies below the line σ² = c²·τ^{2β} by more than its 99 % interval.
pub(super) fn below_line(p: &AllanPoint, c2: f64, beta: f64) -> bool {
    let (_, hi) = chi2_factors(p.edf);
    p.adev.powi(2) * hi < c2 * p.tau_s.powf(2.0 * beta)
}

/// The reading `n` through `region` (from [`white_region`]).
pub(super) fn read_n(
    pts: &[AllanPoint],
    region_w: Option<std::ops::Range<usize>>,
    cov: &[Vec<f64>],
) -> Reading {
    let Some(r) = region_w else {
        return Reading::absent(format!(
            "no white-noise region: no three consecutive points with a local slope within {SLOPE_TOL} of −1/2"
        ));
    };
    let (c2, var) = line(pts, &r, -0.5, cov, true);
    Reading {
        estimate: Some(estimate(c2, var, 1.0)),
        region: Some(region(pts, &r)),
        reason: None,
    }
}

/// The reading `k`: a run of +½ slope whose rise is significant.
pub(super) fn read_k(pts: &[AllanPoint], slopes: &[(f64, f64)], cov: &[Vec<f64>]) -> Reading {
    let k = pts.len();
    let cand = runs(k, |i| {
        let (s, se) = slopes[i];
        (0.5 - SLOPE_TOL..=0.5 + SLOPE_TOL.max(Z99 * se)).contains(&s)
    });
    let last = slopes.iter().rev().find(|s| s.0.is_finite());
    let mut best: Option<(std::ops::Range<usize>, f64, f64)> = None;
    for r in cand {
        // slope of the whole run (with a point on each side for a single-point run)
        let span = if r.len() >= 2 {
            r.clone()
        } else {
            r.start.saturating_sub(1)..(r.end + 1).min(k)
        };
        let sub: Vec<AllanPoint> = span.clone().map(|j| pts[j]).collect();
        let sub_cov: Vec<Vec<f64>> = span
            .clone()
            .map(|a| span.clone().map(|b| cov[a][b]).collect())
            .collect();
        let avar: Vec<f64> = sub.iter().map(|p| p.adev.powi(2)).collect();
        let (s, se) = whole_slope(&sub, &sub_cov, &avar);
        if s - Z99 * se > 0.0 && (s - 0.5).abs() <= SLOPE_TOL.max(Z99 * se) {
            let better = best.as_ref().is_none_or(|b| r.len() > b.0.len());
            if better {
                best = Some((r, s, se));
            }
        }
    }
    let Some((r, _, _)) = best else {
        return Reading::absent(match last {
            Some((s, se)) => format!(
                "no +1/2 (random-walk) region: the curve does not rise significantly with slope +1/2 \
                 (local slope at the longest τ {:.2} ± {:.2})",
                s, se
            ),
            None => "no +1/2 (random-walk) region".to_string(),
        });
    };
    let (c2, var) = line(pts, &r, 0.5, cov, false);
    Reading {
        estimate: Some(estimate(c2, var, 3.0)),
        region: Some(region(pts, &r)),
        reason: None,
    }
}

/// Least-squares slope of ln σ on ln τ over all of `pts`, with its standard error.
fn whole_slope(pts: &[AllanPoint], cov: &[Vec<f64>], avar: &[f64]) -> (f64, f64) {
    let x: Vec<f64> = pts.iter().map(|p| p.tau_s.ln()).collect();
    let xm = x.iter().sum::<f64>() / x.len() as f64;
    let sxx: f64 = x.iter().map(|v| (v - xm).powi(2)).sum();
    let a: Vec<f64> = x.iter().map(|v| (v - xm) / sxx).collect();
    let s: f64 = pts.iter().zip(&a).map(|(p, a)| a * p.adev.ln()).sum();
    let mut var = 0.0;
    for p in 0..pts.len() {
        for q in 0..pts.len() {
            var += a[p] * a[q] * cov[p][q] / (avar[p] * avar[q]);
        }
    }
    (s, 0.5 * var.max(0.0).sqrt())
}

/// The reading `b` (minimum / 0.664) and its τ, when the minimum is a floor.
pub(super) fn read_b(
    pts: &[AllanPoint],
    slopes: &[(f64, f64)],
    cov: &[Vec<f64>],
) -> (Reading, Option<f64>) {
    let Some(i) = (0..pts.len())
        .filter(|&i| pts[i].adev > 0.0)
        .min_by(|&a, &b| pts[a].adev.total_cmp(&pts[b].adev))
    else {
        return (Reading::absent("the curve is zero".to_string()), None);
    };
    let (s, se) = slopes[i];
    let tol = SLOPE_TOL.max(Z99 * se);
    let p = pts[i];
    let upper = p.adev / B_FLOOR;
    let why = if !s.is_finite() {
        Some("too few points around the minimum to read a slope".to_string())
    } else if s.abs() > tol || s - Z99 * se <= -0.5 {
        Some(format!(
            "no bias-instability floor: the minimum σ = {:.3e} at the {} τ = {} s has local slope \
             {:.2} ± {:.2} (not flat, or not distinguishable from −1/2); min/0.664 = {upper:.3e} is \
             only an upper bound of B",
            p.adev,
            if i + 1 == pts.len() { "longest" } else { "" },
            g3(p.tau_s),
            s,
            se
        ))
    } else if s + Z99 * se >= 0.5 {
        Some(format!(
            "no bias-instability floor: the slope at the minimum (τ = {} s, {:.2} ± {:.2}) is not \
             distinguishable from +1/2",
            g3(p.tau_s),
            s,
            se
        ))
    } else {
        None
    };
    if let Some(why) = why {
        return (Reading::absent(why.replace("the  τ", "τ")), None);
    }
    let flat = runs(pts.len(), |j| {
        let (s, se) = slopes[j];
        s.abs() <= SLOPE_TOL.max(Z99 * se)
    })
    .into_iter()
    .find(|r| r.contains(&i))
    .unwrap_or(i..i + 1);
    let var = cov[i][i];
    let c2 = p.adev.powi(2);
    (
        Reading {
            estimate: Some(estimate(c2, var, 1.0 / (B_FLOOR * B_FLOOR))),
            region: Some(region(pts, &flat)),
            reason: None,
        },
        Some(p.tau_s),
    )
}
