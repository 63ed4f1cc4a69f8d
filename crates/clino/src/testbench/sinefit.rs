//! Sine fitting (IEEE Std 1057-2017, §4.1.3: three-parameter fit at a known
//! frequency, four-parameter fit when the frequency is unknown), with a
//! polynomial trend removed in the same least-squares problem.
//!
//! Model: y(t) = A·cos ωt + B·sin ωt + Σ_{k=0..p} c_k·τ^k, with τ = (t − t_mid)/(T/2)
//! the centred, scaled time (k = 0 is the offset C of the standard; p ≥ 1 adds
//! the trend that integration drift leaves in a dynamic inclinometer's
//! output, as the Stewart-platform paper removes before its eq 11). The
//! amplitude is Y = √(A² + B²) and y ≈ Y·sin(ωt + φ) with φ = atan2(A, B).

use crate::{Error, ErrorKind, Result};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::PI;

/// Result of a sine fit.
#[derive(Clone, Debug, PartialEq)]
pub struct SineFit {
    /// Frequency, Hz (given, or estimated by the four-parameter fit).
    pub freq_hz: f64,
    /// Amplitude Y = √(A² + B²) (units of y).
    pub amplitude: f64,
    /// Phase φ of Y·sin(ωt + φ), rad.
    pub phase_rad: f64,
    /// Cosine coefficient A.
    pub a: f64,
    /// Sine coefficient B.
    pub b: f64,
    /// Trend polynomial c_0…c_p in the scaled time τ (c_0 is the offset).
    pub trend: Vec<f64>,
    /// RMS of the residual.
    pub rms_residual: f64,
    /// Iterations of the four-parameter fit (0 for the three-parameter fit).
    pub iterations: usize,
}

impl SineFit {
    /// The fitted sine without the trend at time `t_s`.
    pub fn sine_at(&self, t_s: f64) -> f64 {
        let w = 2.0 * PI * self.freq_hz;
        self.a * (w * t_s).cos() + self.b * (w * t_s).sin()
    }
    /// Twice the amplitude: the peak-to-peak of the fitted sine.
    pub fn peak_to_peak(&self) -> f64 {
        2.0 * self.amplitude
    }
}

fn check(t: &[f64], y: &[f64], trend_order: usize) -> Result<()> {
    if t.len() != y.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("sine fit: {} times but {} values", t.len(), y.len()),
        ));
    }
    if t.len() < 4 + trend_order + 1 {
        return Err(Error::new(
            ErrorKind::Empty,
            format!("sine fit: only {} samples", t.len()),
        ));
    }
    if let Some(i) = t
        .iter()
        .zip(y)
        .position(|(a, b)| !a.is_finite() || !b.is_finite())
    {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("sine fit: sample {i} is not finite"),
        ));
    }
    Ok(())
}

/// Three-parameter sine fit at the known frequency `freq_hz` (IEEE Std 1057
/// §4.1.3.1) plus a polynomial trend of order `trend_order` (0: offset only).
pub fn fit3(t: &[f64], y: &[f64], freq_hz: f64, trend_order: usize) -> Result<SineFit> {
    check(t, y, trend_order)?;
    if !(freq_hz.is_finite() && freq_hz > 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("sine fit: frequency {freq_hz} Hz"),
        ));
    }
    let (sol, rms) = solve(t, y, freq_hz, trend_order, None)?;
    Ok(make(freq_hz, &sol, trend_order, rms, 0))
}

/// Four-parameter sine fit (IEEE Std 1057 §4.1.3.3): the frequency is
/// estimated too, by Gauss–Newton on the linearised model with the extra
/// column ∂y/∂ω = t·(−A·sin ωt + B·cos ωt). Starts from `freq_guess_hz`, or
/// when `None` from the zero-crossing rate of the detrended signal refined by a
/// grid of three-parameter fits.
pub fn fit4(
    t: &[f64],
    y: &[f64],
    freq_guess_hz: Option<f64>,
    trend_order: usize,
) -> Result<SineFit> {
    check(t, y, trend_order)?;
    let span = t[t.len() - 1] - t[0];
    if span.is_nan() || span <= 0.0 {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "sine fit: time does not advance",
        ));
    }
    let f0 = match freq_guess_hz {
        Some(f) if f.is_finite() && f > 0.0 => f,
        Some(f) => {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("sine fit: frequency guess {f} Hz"),
            ));
        }
        None => crossing_freq(t, y, trend_order, span)?,
    };
    let mut f = grid_refine(t, y, f0, trend_order, span)?;
    let mut it = 0;
    loop {
        it += 1;
        let (sol, _) = solve(t, y, f, trend_order, None)?;
        let (a, b) = (sol[0], sol[1]);
        let (sol4, _) = solve(t, y, f, trend_order, Some((a, b)))?;
        let dw = sol4[2 + trend_order + 1];
        let df = dw / (2.0 * PI);
        f += df;
        if !(f > 0.0 && f.is_finite()) {
            return Err(Error::new(
                ErrorKind::NotConverged,
                "four-parameter sine fit: frequency diverged",
            ));
        }
        if df.abs() < 1e-12 * f.max(1.0) || it >= 50 {
            let (sol, rms) = solve(t, y, f, trend_order, None)?;
            if it >= 50 && df.abs() > 1e-6 * f {
                return Err(Error::new(
                    ErrorKind::NotConverged,
                    "four-parameter sine fit did not converge",
                ));
            }
            return Ok(make(f, &sol, trend_order, rms, it));
        }
    }
}

/// Best three-parameter fit on a grid of ±1/T (steps of 0.05/T) around `f0`.
fn grid_refine(t: &[f64], y: &[f64], f0: f64, trend_order: usize, span: f64) -> Result<f64> {
    let mut best = (f64::INFINITY, f0);
    for k in -20..=20 {
        let f = f0 + k as f64 * 0.05 / span;
        if f <= 0.0 {
            continue;
        }
        let (_, rms) = solve(t, y, f, trend_order, None)?;
        if rms < best.0 {
            best = (rms, f);
        }
    }
    Ok(best.1)
}

/// Frequency from the zero-crossing rate of the detrended record.
fn crossing_freq(t: &[f64], y: &[f64], trend_order: usize, span: f64) -> Result<f64> {
    // detrend by the polynomial alone
    let n = t.len();
    let (t_mid, half) = (0.5 * (t[0] + t[n - 1]), 0.5 * span);
    let p = trend_order + 1;
    let m = DMatrix::from_fn(n, p, |i, k| ((t[i] - t_mid) / half).powi(k as i32));
    let c = m
        .clone()
        .svd(true, true)
        .solve(&DVector::from_column_slice(y), 1e-12)
        .map_err(|e| Error::new(ErrorKind::Degenerate, e.to_string()))?;
    let r = DVector::from_column_slice(y) - m * c;
    // zero crossings with hysteresis at ±0.3 RMS, so noise near zero does not count
    let rms = (r.norm_squared() / n as f64).sqrt();
    let h = 0.3 * rms;
    let mut state = 0i8;
    let mut crossings = 0usize;
    for &v in r.iter() {
        let s = if v > h {
            1
        } else if v < -h {
            -1
        } else {
            0
        };
        if s != 0 {
            if state != 0 && s != state {
                crossings += 1;
            }
            state = s;
        }
    }
    if crossings < 2 {
        return Err(Error::new(
            ErrorKind::Degenerate,
            "four-parameter sine fit: fewer than one period in the record",
        ));
    }
    Ok(crossings as f64 / (2.0 * span))
}

/// Least squares on [cos, sin, τ^0…τ^p, (optional ∂/∂ω column)].
fn solve(
    t: &[f64],
    y: &[f64],
    f: f64,
    p: usize,
    dw: Option<(f64, f64)>,
) -> Result<(DVector<f64>, f64)> {
    let n = t.len();
    let w = 2.0 * PI * f;
    let (t0, t1) = (t[0], t[n - 1]);
    let t_mid = 0.5 * (t0 + t1);
    let half = (0.5 * (t1 - t0)).max(f64::MIN_POSITIVE);
    let cols = 2 + p + 1 + usize::from(dw.is_some());
    let m = DMatrix::from_fn(n, cols, |i, k| {
        let ti = t[i];
        match k {
            0 => (w * ti).cos(),
            1 => (w * ti).sin(),
            k if k < 3 + p => ((ti - t_mid) / half).powi((k - 2) as i32),
            _ => {
                let (a, b) = dw.unwrap_or((0.0, 0.0));
                ti * (-a * (w * ti).sin() + b * (w * ti).cos())
            }
        }
    });
    let yv = DVector::from_column_slice(y);
    let sol = m
        .clone()
        .svd(true, true)
        .solve(&yv, 1e-13)
        .map_err(|e| Error::new(ErrorKind::Degenerate, format!("sine fit: {e}")))?;
    let r = yv - &m * &sol;
    let rms = (r.norm_squared() / n as f64).sqrt();
    Ok((sol, rms))
}

fn make(f: f64, sol: &DVector<f64>, p: usize, rms: f64, iterations: usize) -> SineFit {
    let (a, b) = (sol[0], sol[1]);
    SineFit {
        freq_hz: f,
        amplitude: (a * a + b * b).sqrt(),
        phase_rad: a.atan2(b),
        a,
        b,
        trend: (0..=p).map(|k| sol[2 + k]).collect(),
        rms_residual: rms,
        iterations,
    }
}

/// Peak-to-peak (max − min) of a series; 0 for an empty one. NaNs are an error.
pub fn peak_to_peak(y: &[f64]) -> Result<f64> {
    if y.iter().any(|v| !v.is_finite()) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "peak-to-peak: non-finite value",
        ));
    }
    let mx = y.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mn = y.iter().copied().fold(f64::INFINITY, f64::min);
    Ok(if y.is_empty() { 0.0 } else { mx - mn })
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::SeedableRng;
    use rand_distr::{Distribution, Normal};

    fn signal(f: f64, amp: f64, ph: f64, noise: f64) -> (Vec<f64>, Vec<f64>) {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        let nd = Normal::new(0.0, noise.max(1e-300)).unwrap();
        let t: Vec<f64> = (0..2000).map(|k| 3.0 + k as f64 * 0.01).collect();
        let y = t
            .iter()
            .map(|&t| {
                amp * (2.0 * PI * f * t + ph).sin() + 0.3 + 0.02 * t - 0.001 * t * t
                    + if noise > 0.0 {
                        nd.sample(&mut rng)
                    } else {
                        0.0
                    }
            })
            .collect();
        (t, y)
    }

    #[test]
    fn three_parameter_recovers_amplitude_phase_with_trend() {
        let (t, y) = signal(1.7, 0.8, 0.4, 0.0);
        let s = fit3(&t, &y, 1.7, 2).unwrap();
        assert!((s.amplitude - 0.8).abs() < 1e-10, "{}", s.amplitude);
        assert!((s.phase_rad - 0.4).abs() < 1e-10);
        assert!(s.rms_residual < 1e-10);
        // without trend removal the amplitude is biased by the ramp
        let s0 = fit3(&t, &y, 1.7, 0).unwrap();
        assert!((s0.amplitude - 0.8).abs() > 1e-4);
    }

    #[test]
    fn four_parameter_finds_frequency() {
        let (t, y) = signal(2.345, 0.5, -1.0, 0.01);
        let s = fit4(&t, &y, None, 2).map_err(|e| e.to_string()).unwrap();
        assert!((s.freq_hz - 2.345).abs() < 1e-4, "{}", s.freq_hz);
        assert!((s.amplitude - 0.5).abs() < 2e-3);
        assert!((s.rms_residual - 0.01).abs() < 1e-3);
        let s2 = fit4(&t, &y, Some(2.3), 2).unwrap();
        assert!((s2.freq_hz - s.freq_hz).abs() < 1e-9);
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(fit3(&[0.0, 1.0], &[0.0, 1.0], 1.0, 0).is_err());
        let (t, mut y) = signal(1.0, 1.0, 0.0, 0.0);
        y[7] = f64::NAN;
        assert_eq!(
            fit3(&t, &y, 1.0, 1).unwrap_err().kind,
            ErrorKind::InvalidInput
        );
        assert!(peak_to_peak(&[1.0, f64::NAN]).is_err());
        assert_eq!(peak_to_peak(&[1.0, -2.0, 0.5]).unwrap(), 3.0);
    }
}
