//! Restoration: faulty chains replaced from the healthy ones and the gyro
//! (Li Chenggang et al., "Fault Diagnosis in a Gyroscope-Based Six-Axis
//! Accelerometer", section 3.2, eq 14).
//!
//! Two forms:
//!
//! * [`restore_exact`] solves the six relations `P·f = (0, c·ε*)` for the
//!   faulty chains (least squares over the six, exact for consistent data);
//!   eq 14 is this solution for chains 2, 3, 9 using three of the relations
//!   ([`super::equations::restore_eq14`]).
//! * [`Restorer`] is the minimum-variance form: it estimates the
//!   six-dimensional acceleration `x = (F/m, ε*)` by weighted least squares
//!   from the healthy chains (noise `σ_f`) and the gyro's `ε*` (noise
//!   `σ_ε`), then sets `f̂_F = H_F·x̂` ([`SixAxisAccelerometer::sensitivity`]).
//!   It equals the exact form without noise and weights the noisy gyro
//!   derivative down when the healthy chains already determine `x`.
//!
//! The gyro's `ε*` comes from [`gyro_derivative`]: the slope of a local
//! least-squares line through `2K+1` samples (a Savitzky–Golay first
//! derivative; the source suggests numerical differentiation or a tracking
//! differentiator). For uniform steps `h` its white-noise level is
//! `σ_ε = σ_ω / (h·√(K(K+1)(2K+1)/3))`.

use super::analysis::restorable;
use super::diagnose::NoiseModel;
use super::fault_set::FaultSet;
use super::model::{Forces, SixAxisAccelerometer};
use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use nalgebra::{DMatrix, DVector};

/// Local-line derivative of the gyro over `2·half_window + 1` samples
/// (shortened at the ends), rad/s².
pub fn gyro_derivative(t_s: &[f64], gyr: &[Vec3], half_window: usize) -> Vec<Vec3> {
    let n = t_s.len().min(gyr.len());
    (0..n)
        .map(|i| {
            let a = i.saturating_sub(half_window);
            let b = (i + half_window).min(n - 1);
            let cnt = (b - a + 1) as f64;
            if b == a {
                return Vec3::zeros();
            }
            let tm = t_s[a..=b].iter().sum::<f64>() / cnt;
            let wm = gyr[a..=b].iter().sum::<Vec3>() / cnt;
            let mut num = Vec3::zeros();
            let mut den = 0.0;
            for j in a..=b {
                let dt = t_s[j] - tm;
                num += (gyr[j] - wm) * dt;
                den += dt * dt;
            }
            num / den
        })
        .collect()
}

/// White-noise level of [`gyro_derivative`] for uniform steps, rad/s².
pub fn gyro_derivative_sigma(gyro_sigma_rad_s: f64, step_s: f64, half_window: usize) -> f64 {
    let k = half_window as f64;
    gyro_sigma_rad_s / (step_s * (k * (k + 1.0) * (2.0 * k + 1.0) / 3.0).sqrt())
}

/// Replace the chains of `fault` by the least-squares solution of the six
/// relations `P·f = (0, c·ε*)` (eqs 10, 12) given the other chains.
pub fn restore_exact(
    acc: &SixAxisAccelerometer,
    f: &Forces,
    eps: &Vec3,
    fault: FaultSet,
) -> Result<Forces> {
    if !restorable(acc, fault) {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!("chains {fault} cannot be restored"),
        ));
    }
    let p = acc.parity();
    let kbar = acc.stiffness_n_m.iter().sum::<f64>() / 9.0;
    let scale = |r: usize| if r < 3 { kbar } else { 1.0 };
    let bad = fault.indices();
    let c = acc.pair_coefficient();
    let a = DMatrix::from_fn(6, bad.len(), |r, j| p[(r, bad[j])] * scale(r));
    let rhs = DVector::from_fn(6, |r, _| {
        let target = if r >= 3 { c * eps[r - 3] } else { 0.0 };
        let known: f64 = fault
            .complement_indices()
            .iter()
            .map(|&i| p[(r, i)] * f[i])
            .sum();
        (target - known) * scale(r)
    });
    let sol = a
        .svd(true, true)
        .solve(&rhs, 1e-12)
        .map_err(|e| Error::new(ErrorKind::Degenerate, e.to_string()))?;
    let mut g = *f;
    for (j, &i) in bad.iter().enumerate() {
        g[i] = sol[j];
    }
    Ok(g)
}

/// Minimum-variance restoration of a known fault set (see the module doc).
#[derive(Clone, Debug)]
pub struct Restorer {
    fault: FaultSet,
    healthy: Vec<usize>,
    /// |F| × (healthy + 3) gain from (healthy forces, gyro ε*) to restored forces.
    gain: DMatrix<f64>,
}

impl Restorer {
    /// Prepare the restoration of `fault` with force noise from `noise` and
    /// gyro-derivative noise `eps_sigma_rad_s2`.
    pub fn new(
        acc: &SixAxisAccelerometer,
        noise: &NoiseModel,
        eps_sigma_rad_s2: f64,
        fault: FaultSet,
    ) -> Result<Self> {
        if !restorable(acc, fault) {
            return Err(Error::new(
                ErrorKind::Degenerate,
                format!("chains {fault} cannot be restored"),
            ));
        }
        let h = acc.sensitivity();
        let healthy = fault.complement_indices();
        let nh = healthy.len();
        // rows: healthy chains (weight 1/σ_f), gyro ε* (weight 1/σ_ε)
        let a = DMatrix::from_fn(nh + 3, 6, |r, c| {
            if r < nh {
                h[(healthy[r], c)] / noise.force_sigma_n
            } else if c == 3 + (r - nh) {
                1.0 / eps_sigma_rad_s2
            } else {
                0.0
            }
        });
        let w = DMatrix::from_fn(nh + 3, nh + 3, |r, c| {
            if r != c {
                0.0
            } else if r < nh {
                1.0 / noise.force_sigma_n
            } else {
                1.0 / eps_sigma_rad_s2
            }
        });
        let ata = a.transpose() * &a;
        let inv = ata
            .try_inverse()
            .ok_or_else(|| Error::new(ErrorKind::Degenerate, "singular restoration"))?;
        let est = inv * a.transpose() * w; // x̂ = est · (f_H, ε*)
        let bad = fault.indices();
        let hf = DMatrix::from_fn(bad.len(), 6, |r, c| h[(bad[r], c)]);
        Ok(Self {
            fault,
            healthy,
            gain: hf * est,
        })
    }

    /// The fault set this restorer replaces.
    pub fn fault(&self) -> FaultSet {
        self.fault
    }

    /// Forces with the faulty chains replaced, N.
    pub fn restore(&self, f: &Forces, eps_gyro: &Vec3) -> Forces {
        let nh = self.healthy.len();
        let y = DVector::from_fn(nh + 3, |r, _| {
            if r < nh {
                f[self.healthy[r]]
            } else {
                eps_gyro[r - nh]
            }
        });
        let est = &self.gain * y;
        let mut g = *f;
        for (j, i) in self.fault.indices().into_iter().enumerate() {
            g[i] = est[j];
        }
        g
    }
}

#[cfg(test)]
mod tests {
    use super::super::equations::restore_eq14;
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::SVector;

    /// The six-dimensional state `(F/m, ε*)` of some forces.
    fn state(acc: &SixAxisAccelerometer, f: &Forces) -> SVector<f64, 6> {
        let sf = acc.specific_force(f);
        let e = acc.angular_acceleration(f);
        SVector::<f64, 6>::new(sf.x, sf.y, sf.z, e.x, e.y, e.z)
    }

    fn case() -> (SixAxisAccelerometer, Forces, Vec3) {
        let k: [f64; 9] = std::array::from_fn(|i| 2.0e7 * (1.0 + 0.04 * i as f64));
        let acc = SixAxisAccelerometer::new(0.1, 0.012, k).unwrap();
        let eps = Vec3::new(15.0, -40.0, 8.0);
        let f = acc.forces(&Vec3::new(3.0, -2.0, 9.0), &eps);
        (acc, f, eps)
    }

    #[test]
    fn exact_restoration_of_every_restorable_set() {
        let (acc, truth, eps) = case();
        for k in 1..=4 {
            for s in FaultSet::all_of_size(k) {
                let mut bad = truth;
                for i in s.indices() {
                    bad[i] = 5.0 * (i as f64 + 1.0);
                }
                let g = restore_exact(&acc, &bad, &eps, s).unwrap();
                assert_relative_eq!(g, truth, max_relative = 1e-7, epsilon = 1e-9);
            }
        }
    }

    #[test]
    fn eq14_is_the_exact_restoration_of_239() {
        let (acc, truth, eps) = case();
        let s = FaultSet::from_label("239").unwrap();
        let mut bad = truth;
        bad[1] = 0.0;
        bad[2] = 1.0;
        bad[8] = -1.0;
        let a = restore_eq14(&acc, &bad, &eps);
        let b = restore_exact(&acc, &bad, &eps, s).unwrap();
        assert_relative_eq!(a, b, max_relative = 1e-7, epsilon = 1e-9);
    }

    #[test]
    fn weighted_restoration_recovers_the_state() {
        let (acc, truth, eps) = case();
        let noise = NoiseModel::reference();
        for set in ["239", "2468", "1", "159"] {
            let s = FaultSet::from_label(set).unwrap();
            let r = Restorer::new(&acc, &noise, 0.1, s).unwrap();
            let mut bad = truth;
            for i in s.indices() {
                bad[i] += 0.7;
            }
            let g = r.restore(&bad, &eps);
            assert_relative_eq!(
                state(&acc, &g),
                state(&acc, &truth),
                max_relative = 1e-7,
                epsilon = 1e-7
            );
        }
    }

    #[test]
    fn derivative_of_a_quadratic_is_exact_and_noise_formula_holds() {
        let t: Vec<f64> = (0..50).map(|i| i as f64 * 0.002).collect();
        let w: Vec<Vec3> = t.iter().map(|&t| Vec3::new(3.0 * t * t, -t, 1.0)).collect();
        let d = gyro_derivative(&t, &w, 5);
        assert_relative_eq!(d[20], Vec3::new(6.0 * t[20], -1.0, 0.0), epsilon = 1e-9);
        // σ_ε = σ_ω / (h √(Σ k²)), Σ_{k=−K}^{K} k² = K(K+1)(2K+1)/3
        let sum_k2: f64 = (-5i32..=5).map(|k| (k * k) as f64).sum();
        assert_relative_eq!(
            gyro_derivative_sigma(1.0, 0.002, 5),
            1.0 / (0.002 * sum_k2.sqrt()),
            max_relative = 1e-12
        );
    }

    proptest::proptest! {
        /// Any set of up to four chains, any motion, any fault values:
        /// the exact restoration returns the true forces (case count from
        /// PROPTEST_CASES).
        #[test]
        fn restores_any_set_of_up_to_four(
            mask in 1u16..512,
            sf in proptest::array::uniform3(-30.0f64..30.0),
            eps in proptest::array::uniform3(-200.0f64..200.0),
            err in proptest::array::uniform9(-2.0f64..2.0),
        ) {
            let s = FaultSet(mask);
            proptest::prop_assume!(s.len() <= 4);
            let acc = SixAxisAccelerometer::reference();
            let eps = Vec3::from(eps);
            let truth = acc.forces(&Vec3::from(sf), &eps);
            let mut bad = truth;
            for i in s.indices() {
                bad[i] += err[i] + 0.1;
            }
            let g = restore_exact(&acc, &bad, &eps, s).unwrap();
            proptest::prop_assert!((g - truth).norm() < 1e-7 * (1.0 + truth.norm()), "{s}: {}", (g - truth).norm());
        }
    }
}
