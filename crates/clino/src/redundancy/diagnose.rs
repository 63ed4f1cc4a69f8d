//! Fault diagnosis: residuals, noise-derived thresholds and the smallest
//! set of chains that explains them (Li Chenggang et al., "Fault Diagnosis
//! in a Gyroscope-Based Six-Axis Accelerometer", section 3.1).
//!
//! ## Residuals
//!
//! The record is cut into blocks of `L` samples (`block_len`). Per block, the
//! six base residuals are
//!
//! * compatibility (10 a–c): the trapezoid mean over the block of
//!   `k̄·(Σ fᵢ/kᵢ)`, in N (`k̄` is the mean stiffness, a scale only);
//! * gyro (11 d–f ≡ 12 g–i): `(trapz(G·f)·h − c·(ω*_end − ω*_start))/T`, in N,
//!   with `G·f = (−f2+f4, f3−f7, −f6+f8)`, `c = 2mn/3` and `T` the block
//!   duration: eq 11 over the block, i.e. eq 12 with the block-mean `ε*`.
//!
//! No gyro differentiation is needed, and a fault `e(t)` on the chains `F`
//! moves the block residual by exactly `P_F·ē` (`ē` its block mean). The
//! per-sample forms of each family are in [`super::equations`]
//! ([`super::equations::gyro_integral_residuals`] from the first sample on,
//! [`super::equations::gyro_derivative_residuals`],
//! [`super::equations::closed_form_residuals`]).
//!
//! ## Noise model and thresholds
//!
//! Chain forces carry white noise `σ_f` (N) and the gyro white noise `σ_ω`
//! (rad/s) per sample ([`NoiseModel`]). The block residual covariance is then
//! `R = Σw²·σ_f²·P̃P̃ᵀ + diag(0, 0, 0, 2c²σ_ω²/T²·I₃)` with `Σw²` the sum of the
//! squared trapezoid weights and `P̃` the scaled parity matrix. Residuals are
//! whitened with `R`'s Cholesky factor, so a fault-free window of `M` blocks
//! (`window_blocks`) gives chi-square statistics, and every threshold is the
//! chi-square quantile at the configured false-alarm probability `α` per test
//! (`false_alarm_prob`, Wilson–Hilferty approximation).
//!
//! ## General scheme (smallest explaining set)
//!
//! For a candidate set `S`, project the whitened residuals of the window onto
//! the complement of the fault directions `R^{-1/2}·P_S` and sum the squares:
//! `J_S ~ χ²(M·(6 − rank P_S))` if the faults lie in `S`. The diagnosis is the
//! smallest `S` (sizes 0, 1, …, `max_faults`) whose `J_S` passes its threshold;
//! among several of that size, the smallest `J_S` (maximum likelihood).
//! `S = ∅` passing means no fault.
//!
//! ## The source's scheme (pattern of violated relations)
//!
//! Each of the 24 relations of [`source_relations`] is tested on its own,
//! `Σ_b (λ·r_b)²/(λᵀRλ) ~ χ²(M)`. The violated pattern is matched against the
//! pattern each fault set predicts (the relations whose chains it touches);
//! the smallest matching set is the diagnosis — the source's "Descartes
//! coordinate systems" enumerate exactly these patterns. Several matching
//! sets of the smallest size make the verdict ambiguous, none unexplained.
//!
//! Both schemes agree wherever the source's scheme isolates the set (see
//! [`super::analysis`]) and the fault is large enough to violate every
//! relation it touches; the general scheme also isolates the rest. In the
//! 165-set sweep (`clino redundancy sweep`) the source's scheme named the
//! injected set in all 131 runs it can isolate for stuck, bias and drift
//! faults (126 for zero-mean noise faults, whose weaker relations sometimes
//! stay below threshold) and never named a wrong set: it answers
//! "unexplained" or "ambiguous" instead.

use super::equations::{Relation, source_relations};
use super::fault_set::FaultSet;
use super::model::{Forces, SixAxisAccelerometer};
use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use nalgebra::{DMatrix, SMatrix, SVector};

/// White noise on the measurements, per sample.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct NoiseModel {
    /// Standard deviation of each chain force, N.
    pub force_sigma_n: f64,
    /// Standard deviation of each gyro axis, rad/s.
    pub gyro_sigma_rad_s: f64,
}

impl NoiseModel {
    /// Realistic noise for the reference device at 1 kHz: 0.2 mN per chain
    /// (2·10⁻⁴ of the 1 N weight of the cube) and 2 mrad/s per gyro axis
    /// (0.11 °/s, a tactical MEMS gyro's white noise at that rate).
    pub fn reference() -> Self {
        Self {
            force_sigma_n: 2.0e-4,
            gyro_sigma_rad_s: 2.0e-3,
        }
    }
}

/// Settings of the diagnosis; every default is documented with its unit.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct DiagnosisConfig {
    /// Samples per residual block (≥ 2); default 10 (10 ms at 1 kHz).
    pub block_len: usize,
    /// Blocks per decision window (≥ 1); default 10 (100 ms at 1 kHz).
    pub window_blocks: usize,
    /// False-alarm probability per chi-square test; default 10⁻⁶.
    pub false_alarm_prob: f64,
    /// Largest fault set considered (1–5); default 4.
    pub max_faults: usize,
}

impl Default for DiagnosisConfig {
    fn default() -> Self {
        Self {
            block_len: 10,
            window_blocks: 10,
            false_alarm_prob: 1e-6,
            max_faults: 4,
        }
    }
}

/// Outcome of one decision.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    /// All relations hold.
    NoFault,
    /// The smallest set explaining the residuals.
    Faulty(FaultSet),
    /// Several smallest sets explain the residuals equally (source scheme).
    Ambiguous(Vec<FaultSet>),
    /// No set of at most `max_faults` chains explains the residuals.
    Unexplained,
}

impl Verdict {
    /// The diagnosed set, if there is exactly one.
    pub fn set(&self) -> Option<FaultSet> {
        match self {
            Verdict::Faulty(s) => Some(*s),
            _ => None,
        }
    }
    /// True for anything but [`Verdict::NoFault`].
    pub fn alarm(&self) -> bool {
        !matches!(self, Verdict::NoFault)
    }
    /// Short text: "none", "239", "ambiguous(1234|1237)", "unexplained".
    pub fn label(&self) -> String {
        match self {
            Verdict::NoFault => "none".into(),
            Verdict::Faulty(s) => s.to_string(),
            Verdict::Ambiguous(v) => {
                format!(
                    "ambiguous({})",
                    v.iter()
                        .map(|s| s.to_string())
                        .collect::<Vec<_>>()
                        .join("|")
                )
            }
            Verdict::Unexplained => "unexplained".into(),
        }
    }
}

/// The decision for one window of blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct WindowDiagnosis {
    /// Start of the window's first block, s.
    pub t_start_s: f64,
    /// End of the window's last block (when the decision is available), s.
    pub t_end_s: f64,
    /// General scheme.
    pub general: Verdict,
    /// The source's scheme.
    pub source: Verdict,
    /// Fault-free statistic over its threshold (`J_∅ / τ`; > 1 is an alarm).
    pub detection_ratio: f64,
    /// Names of the source relations judged violated.
    pub violated: Vec<String>,
}

struct Candidate {
    set: FaultSet,
    perp: SMatrix<f64, 6, 6>,
    dof_per_block: usize,
    threshold: f64,
}

/// Upper quantile of the standard normal distribution: `z` with
/// `P(Z > z) = p` (Acklam's rational approximation, |error| < 1.2·10⁻⁹).
pub fn normal_upper_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969683028665376e1,
        2.209460984245205e2,
        -2.759285104469687e2,
        1.383_577_518_672_69e2,
        -3.066479806614716e1,
        2.506628277459239,
    ];
    const B: [f64; 5] = [
        -5.447609879822406e1,
        1.615858368580409e2,
        -1.556989798598866e2,
        6.680131188771972e1,
        -1.328068155288572e1,
    ];
    const C: [f64; 6] = [
        -7.784894002430293e-3,
        -3.223964580411365e-1,
        -2.400758277161838,
        -2.549732539343734,
        4.374664141464968,
        2.938163982698783,
    ];
    const D: [f64; 4] = [
        7.784695709041462e-3,
        3.224671290700398e-1,
        2.445134137142996,
        3.754408661907416,
    ];
    // Acklam's algorithm gives the lower quantile x(q), P(Z < x) = q; z = −x(p)
    let lower = |q: f64| -> f64 {
        let plow = 0.02425;
        let tail = |r: f64| {
            (((((C[0] * r + C[1]) * r + C[2]) * r + C[3]) * r + C[4]) * r + C[5])
                / ((((D[0] * r + D[1]) * r + D[2]) * r + D[3]) * r + 1.0)
        };
        if q < plow {
            tail((-2.0 * q.ln()).sqrt())
        } else if q > 1.0 - plow {
            -tail((-2.0 * (1.0 - q).ln()).sqrt())
        } else {
            let u = q - 0.5;
            let r = u * u;
            (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * u
                / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
        }
    };
    -lower(p)
}

/// Chi-square threshold exceeded with probability `p` at `dof` degrees of
/// freedom (Wilson–Hilferty: `k·(1 − 2/(9k) + z·√(2/(9k)))³`).
pub fn chi2_upper_quantile(dof: usize, p: f64) -> f64 {
    let k = dof as f64;
    let z = normal_upper_quantile(p);
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3)
}

/// A configured diagnoser for one device, noise level and sample step.
pub struct Diagnoser {
    acc: SixAxisAccelerometer,
    cfg: DiagnosisConfig,
    /// Scaled parity matrix (compatibility rows × k̄, in N).
    p: SMatrix<f64, 6, 9>,
    r_cov: SMatrix<f64, 6, 6>,
    whiten: SMatrix<f64, 6, 6>,
    candidates: Vec<Candidate>,
    relations: Vec<Relation>,
    rel_lambda: Vec<SVector<f64, 6>>,
    rel_var: Vec<f64>,
    rel_threshold: f64,
    signatures: Vec<(FaultSet, u32)>,
    empty_threshold: f64,
}

impl Diagnoser {
    /// Set up the residual covariance, the candidate projections and the
    /// thresholds for samples `step_s` apart.
    pub fn new(
        acc: &SixAxisAccelerometer,
        noise: &NoiseModel,
        cfg: &DiagnosisConfig,
        step_s: f64,
    ) -> Result<Self> {
        let bad = |m: String| Err(Error::new(ErrorKind::InvalidInput, m));
        if cfg.block_len < 2 {
            return bad(format!(
                "block length must be at least 2 samples, got {}",
                cfg.block_len
            ));
        }
        if cfg.window_blocks < 1 {
            return bad("window must hold at least one block".into());
        }
        if !(cfg.false_alarm_prob > 0.0 && cfg.false_alarm_prob < 0.5) {
            return bad(format!(
                "false-alarm probability must be in (0, 0.5), got {}",
                cfg.false_alarm_prob
            ));
        }
        if !(1..=5).contains(&cfg.max_faults) {
            return bad(format!("max faults must be 1–5, got {}", cfg.max_faults));
        }
        if !(noise.force_sigma_n > 0.0 && noise.gyro_sigma_rad_s > 0.0) {
            return bad("noise levels must be positive".into());
        }
        if !(step_s > 0.0 && step_s.is_finite()) {
            return bad(format!("sample step must be positive, got {step_s} s"));
        }
        let kbar = acc.stiffness_n_m.iter().sum::<f64>() / 9.0;
        let mut p = acc.parity();
        for r in 0..3 {
            for c in 0..9 {
                p[(r, c)] *= kbar;
            }
        }
        let l = cfg.block_len as f64;
        let t_block = (l - 1.0) * step_s;
        let sum_w2 = (l - 1.5) / ((l - 1.0) * (l - 1.0));
        let c = acc.pair_coefficient();
        let mut r_cov = p * p.transpose() * (sum_w2 * noise.force_sigma_n.powi(2));
        for i in 3..6 {
            r_cov[(i, i)] += 2.0 * (c * noise.gyro_sigma_rad_s / t_block).powi(2);
        }
        let chol = r_cov.cholesky().ok_or_else(|| {
            Error::new(
                ErrorKind::Degenerate,
                "residual covariance is not positive definite",
            )
        })?;
        let whiten = chol
            .l()
            .try_inverse()
            .ok_or_else(|| Error::new(ErrorKind::Degenerate, "singular covariance"))?;
        let m = cfg.window_blocks;
        let alpha = cfg.false_alarm_prob;
        let mut candidates = Vec::new();
        for k in 1..=cfg.max_faults {
            for set in FaultSet::all_of_size(k) {
                let idx = set.indices();
                let d = DMatrix::from_fn(6, idx.len(), |r, j| {
                    (0..6).map(|q| whiten[(r, q)] * p[(q, idx[j])]).sum::<f64>()
                });
                let svd = d.svd(true, false);
                let u = svd.u.expect("u requested");
                let smax = svd.singular_values.iter().fold(0.0f64, |a, &b| a.max(b));
                let mut perp = SMatrix::<f64, 6, 6>::identity();
                let mut rank = 0;
                for (j, &s) in svd.singular_values.iter().enumerate() {
                    if s > 1e-9 * smax {
                        let col = SVector::<f64, 6>::from_fn(|r, _| u[(r, j)]);
                        perp -= col * col.transpose();
                        rank += 1;
                    }
                }
                let dof_per_block = 6 - rank;
                let threshold = chi2_upper_quantile(m * dof_per_block, alpha);
                candidates.push(Candidate {
                    set,
                    perp,
                    dof_per_block,
                    threshold,
                });
            }
        }
        let relations = source_relations(acc);
        // relation coefficients over the scaled residuals
        let rel_lambda: Vec<SVector<f64, 6>> = relations
            .iter()
            .map(|r| {
                let mut l = r.lambda;
                for i in 0..3 {
                    l[i] /= kbar;
                }
                l
            })
            .collect();
        let rel_var = rel_lambda
            .iter()
            .map(|l| (l.transpose() * r_cov * l)[0])
            .collect();
        let mut signatures = Vec::new();
        for k in 1..=cfg.max_faults {
            for set in FaultSet::all_of_size(k) {
                signatures.push((set, super::analysis::signature(&relations, set)));
            }
        }
        Ok(Self {
            acc: acc.clone(),
            cfg: *cfg,
            p,
            r_cov,
            whiten,
            candidates,
            relations,
            rel_lambda,
            rel_var,
            rel_threshold: chi2_upper_quantile(m, alpha),
            signatures,
            empty_threshold: chi2_upper_quantile(6 * m, alpha),
        })
    }

    /// The configuration in use.
    pub fn config(&self) -> &DiagnosisConfig {
        &self.cfg
    }

    /// Covariance of the fault-free block residual (N²).
    pub fn residual_covariance(&self) -> &SMatrix<f64, 6, 6> {
        &self.r_cov
    }

    /// Base residuals of one block (see the module doc), N. The slices hold
    /// the block's samples: times (s), chain forces (N), gyro (rad/s).
    pub fn block_residual(&self, t_s: &[f64], forces: &[Forces], gyr: &[Vec3]) -> SVector<f64, 6> {
        let n = t_s.len();
        let t_total = t_s[n - 1] - t_s[0];
        let mut mean = Forces::zeros();
        for i in 0..n - 1 {
            let h = t_s[i + 1] - t_s[i];
            mean += (forces[i] + forces[i + 1]) * (0.5 * h / t_total);
        }
        let mut r = self.p * mean;
        let c = self.acc.pair_coefficient();
        let dw = gyr[n - 1] - gyr[0];
        for i in 0..3 {
            r[3 + i] -= c * dw[i] / t_total;
        }
        r
    }

    /// Decide on a window of block residuals (both schemes).
    pub fn decide(
        &self,
        blocks: &[SVector<f64, 6>],
        t_start_s: f64,
        t_end_s: f64,
    ) -> WindowDiagnosis {
        let mut scatter = SMatrix::<f64, 6, 6>::zeros();
        for r in blocks {
            let w = self.whiten * r;
            scatter += w * w.transpose();
        }
        let m = blocks.len();
        // thresholds are precomputed for full windows; a shorter one gets its own
        let thr = |full: f64, dof_per_block: usize| {
            if m == self.cfg.window_blocks {
                full
            } else {
                chi2_upper_quantile(dof_per_block * m, self.cfg.false_alarm_prob)
            }
        };
        let j_empty = scatter.trace();
        let thr_empty = thr(self.empty_threshold, 6);
        let general = if j_empty <= thr_empty {
            Verdict::NoFault
        } else {
            let mut verdict = Verdict::Unexplained;
            for k in 1..=self.cfg.max_faults {
                let best = self
                    .candidates
                    .iter()
                    .filter(|c| c.set.len() == k)
                    .map(|c| ((c.perp * scatter).trace(), c))
                    .filter(|(j, c)| *j <= thr(c.threshold, c.dof_per_block))
                    .min_by(|a, b| a.0.total_cmp(&b.0));
                if let Some((_, c)) = best {
                    verdict = Verdict::Faulty(c.set);
                    break;
                }
            }
            verdict
        };
        // source scheme
        let thr_rel = thr(self.rel_threshold, 1);
        let mut sig = 0u32;
        let mut violated = Vec::new();
        for (i, l) in self.rel_lambda.iter().enumerate() {
            let stat: f64 = blocks.iter().map(|r| l.dot(r).powi(2)).sum::<f64>() / self.rel_var[i];
            if stat > thr_rel {
                sig |= 1 << i;
                violated.push(self.relations[i].name.clone());
            }
        }
        let source = if sig == 0 {
            Verdict::NoFault
        } else {
            let mut v = Verdict::Unexplained;
            for k in 1..=self.cfg.max_faults {
                let m: Vec<FaultSet> = self
                    .signatures
                    .iter()
                    .filter(|(s, g)| s.len() == k && *g == sig)
                    .map(|(s, _)| *s)
                    .collect();
                match m.len() {
                    0 => continue,
                    1 => v = Verdict::Faulty(m[0]),
                    _ => v = Verdict::Ambiguous(m),
                }
                break;
            }
            v
        };
        WindowDiagnosis {
            t_start_s,
            t_end_s,
            general,
            source,
            detection_ratio: j_empty / thr_empty,
            violated,
        }
    }
}

/// Check that time increases and the step is nearly uniform (the noise
/// model assumes one step); returns the median step, s. Errors name the
/// 0-based sample index as `line` offset by `first_line`.
pub fn uniform_step(t_s: &[f64], first_line: u64) -> Result<f64> {
    if t_s.len() < 2 {
        return Err(Error::new(ErrorKind::Empty, "need at least two samples"));
    }
    let mut steps: Vec<f64> = Vec::with_capacity(t_s.len() - 1);
    for (i, w) in t_s.windows(2).enumerate() {
        let h = w[1] - w[0];
        if h.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
            return Err(Error::new(
                ErrorKind::TimeNotIncreasing,
                format!("time does not increase: {} s after {} s", w[1], w[0]),
            )
            .at_line(first_line + i as u64 + 1)
            .at_column("t_s"));
        }
        steps.push(h);
    }
    let mut sorted = steps.clone();
    sorted.sort_by(f64::total_cmp);
    let med = sorted[sorted.len() / 2];
    if let Some(i) = steps.iter().position(|&h| (h - med).abs() > 0.2 * med) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "sample step {} s differs from the median {} s by more than 20% (gap or jitter)",
                steps[i], med
            ),
        )
        .at_line(first_line + i as u64 + 1)
        .at_column("t_s"));
    }
    Ok(med)
}

/// Diagnose a whole record: blocks of `block_len` samples, a decision at
/// every block over the last `window_blocks` blocks (one decision per block
/// once the window is full).
pub fn diagnose_record(
    diag: &Diagnoser,
    t_s: &[f64],
    forces: &[Forces],
    gyr: &[Vec3],
) -> Result<Vec<WindowDiagnosis>> {
    if t_s.len() != forces.len() || t_s.len() != gyr.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "times, forces and gyro differ in length",
        ));
    }
    let l = diag.cfg.block_len;
    let nb = t_s.len() / l;
    let m = diag.cfg.window_blocks;
    if nb < m {
        return Err(Error::new(
            ErrorKind::Empty,
            format!(
                "record too short: {} samples, a decision needs {} ({} blocks of {})",
                t_s.len(),
                m * l,
                m,
                l
            ),
        ));
    }
    let blocks: Vec<SVector<f64, 6>> = (0..nb)
        .map(|b| {
            let r = b * l..(b + 1) * l;
            diag.block_residual(&t_s[r.clone()], &forces[r.clone()], &gyr[r])
        })
        .collect();
    Ok((m..=nb)
        .map(|e| {
            let s = e - m;
            diag.decide(&blocks[s..e], t_s[s * l], t_s[e * l - 1])
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn quantiles_match_tables() {
        assert_relative_eq!(normal_upper_quantile(0.025), 1.959964, epsilon = 1e-6);
        assert_relative_eq!(normal_upper_quantile(1e-6), 4.753424, epsilon = 1e-5);
        assert_relative_eq!(normal_upper_quantile(0.5), 0.0, epsilon = 1e-12);
        assert_relative_eq!(normal_upper_quantile(0.975), -1.959964, epsilon = 1e-6);
        // chi-square tables: χ²_0.95(10) = 18.307, χ²_0.99(30) = 50.892
        assert_relative_eq!(chi2_upper_quantile(10, 0.05), 18.307, max_relative = 2e-3);
        assert_relative_eq!(chi2_upper_quantile(30, 0.01), 50.892, max_relative = 2e-3);
    }

    #[test]
    fn uniform_step_reports_the_line() {
        let e = uniform_step(&[0.0, 0.001, 0.002, 0.0015], 2).unwrap_err();
        assert_eq!(e.kind, ErrorKind::TimeNotIncreasing);
        assert_eq!(e.line, Some(5));
        let e = uniform_step(&[0.0, 0.001, 0.002, 0.010, 0.011], 2).unwrap_err();
        assert_eq!(e.line, Some(5));
        assert_relative_eq!(
            uniform_step(&[0.0, 0.001, 0.002], 2).unwrap(),
            0.001,
            epsilon = 1e-15
        );
    }
}
