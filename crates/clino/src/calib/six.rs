//! The six-position method (for a fixture that points each housing axis up and down).
//!
//! With the housing's axis i up, an ideal triad reads +g along i; down, −g.
//! For readings u = K·a + u₀ (MPU6050 inclinometer paper, eq 1: A = K⁻¹(U_a − U_a0)),
//! the column i of K is (u(+i) − u(−i))/(2g), and u₀ is the mean of the six
//! readings (the ±g terms cancel). The calibration applies M = K⁻¹. Closed form;
//! all twelve parameters are determined because the fixture defines the axes.
//!
//! Uncertainty (1σ): the mean of a pose of n samples whose reading scatters
//! by s (root of the summed variances of the three axes) has, per axis, the
//! variance v = s²/(3n) (white, isotropic noise; a group of G poses averages
//! to Σv/G²). Then var K_ij = (v₊ⱼ + v₋ⱼ)/(2g)², var u0_i = Σ₆ v/36, and
//! for M = K⁻¹ to first order dM = −M·dK·M, so
//! var M_ab = Σ_cd (M_ac·M_db)²·var K_cd (the K entries are independent).

use super::fit::ParamEstimate;
use super::statics::Pose;
use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use clino_core::sensor::{MatrixModel, TriadCalibration, TriadModel};
use nalgebra::Matrix3;
use serde::Serialize;

/// Result of the six-position method.
#[derive(Clone, Debug, Serialize)]
pub struct SixPosition {
    /// The calibration (matrix model, M = K⁻¹).
    pub calibration: TriadCalibration,
    /// K (rows), raw units per m/s².
    pub k: [[f64; 3]; 3],
    /// u₀, raw units.
    pub bias: [f64; 3],
    /// Pose used for +x, −x, +y, −y, +z, −z (averaged when several qualify).
    pub poses: [Vec<usize>; 6],
    /// The applied parameters with 1σ: `M_ij` (M = K⁻¹, 1 SI per raw) and
    /// `u0_i` (raw), named as the multi-position fit names them. See
    /// [`six_position`] for how the 1σ are propagated.
    pub params: Vec<ParamEstimate>,
}

const NAMES: [&str; 6] = ["+x", "-x", "+y", "-y", "+z", "-z"];

/// Estimate the matrix model from static poses that point each housing axis up
/// and down (a pose counts for ±i when its reading is within about 25° of that
/// axis: |u_i| ≥ 0.9·|u|). Errors name the missing positions.
pub fn six_position(poses: &[Pose], g: f64) -> Result<SixPosition> {
    let mut groups: [Vec<usize>; 6] = Default::default();
    for p in poses {
        let u = p.acc();
        let n = u.norm();
        if n <= 0.0 {
            continue;
        }
        for i in 0..3 {
            if u[i] >= 0.9 * n {
                groups[2 * i].push(p.index);
            } else if -u[i] >= 0.9 * n {
                groups[2 * i + 1].push(p.index);
            }
        }
    }
    let missing: Vec<&str> = (0..6)
        .filter(|&k| groups[k].is_empty())
        .map(|k| NAMES[k])
        .collect();
    if !missing.is_empty() {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!(
                "the six-position method needs each housing axis up and down; {} poses found, none with {} up",
                poses.len(),
                missing.join(", ")
            ),
        ));
    }
    let mean = |k: usize| {
        let v = &groups[k];
        v.iter()
            .map(|&i| {
                poses
                    .iter()
                    .find(|p| p.index == i)
                    .map(|p| p.acc())
                    .unwrap_or_default()
            })
            .fold(Vec3::zeros(), |s, x| s + x)
            / v.len() as f64
    };
    let m: Vec<Vec3> = (0..6).map(mean).collect();
    let var: Vec<f64> = (0..6).map(|k| mean_variance(poses, &groups[k])).collect();
    let mut k = Matrix3::zeros();
    for i in 0..3 {
        k.set_column(i, &((m[2 * i] - m[2 * i + 1]) / (2.0 * g)));
    }
    let u0 = m.iter().fold(Vec3::zeros(), |s, x| s + x) / 6.0;
    let kinv = k.try_inverse().ok_or_else(|| {
        Error::new(
            ErrorKind::Degenerate,
            "the six positions give a singular scale matrix K",
        )
    })?;
    let temps: Vec<f64> = poses.iter().filter_map(|p| p.temp_c).collect();
    let valid = super::valid_range(&temps);
    let params = params(&kinv, &u0, &var, g);
    Ok(SixPosition {
        calibration: TriadCalibration {
            model: TriadModel::Matrix(MatrixModel {
                bias: [u0.x, u0.y, u0.z],
                matrix: std::array::from_fn(|i| std::array::from_fn(|j| kinv[(i, j)])),
            }),
            valid_temp_c: valid,
        },
        k: std::array::from_fn(|i| std::array::from_fn(|j| k[(i, j)])),
        bias: [u0.x, u0.y, u0.z],
        poses: groups,
        params,
    })
}

/// Per-axis variance of the mean reading of a group of poses (see the module docs).
fn mean_variance(poses: &[Pose], group: &[usize]) -> f64 {
    let sum: f64 = group
        .iter()
        .map(|&i| {
            poses.iter().find(|p| p.index == i).map_or(f64::NAN, |p| {
                p.acc_std.unwrap_or(f64::NAN).powi(2) / (3.0 * p.n as f64)
            })
        })
        .sum();
    sum / (group.len() * group.len()) as f64
}

/// M and u₀ with their 1σ (module docs), M row-major then u₀.
fn params(m: &Matrix3<f64>, u0: &Vec3, var: &[f64], g: f64) -> Vec<ParamEstimate> {
    const AX: [&str; 3] = ["x", "y", "z"];
    // var K_cd: column d from the ±d groups (isotropic: same for every row c)
    let var_k = |d: usize| (var[2 * d] + var[2 * d + 1]) / (4.0 * g * g);
    let mut out = Vec::with_capacity(12);
    for a in 0..3 {
        for b in 0..3 {
            let v: f64 = (0..3)
                .flat_map(|c| (0..3).map(move |d| (c, d)))
                .map(|(c, d)| (m[(a, c)] * m[(d, b)]).powi(2) * var_k(d))
                .sum();
            out.push(ParamEstimate {
                name: format!("M_{}{}", AX[a], AX[b]),
                value: m[(a, b)],
                sigma: v.sqrt(),
                unit: "1 (SI per raw)".into(),
            });
        }
    }
    let var_u0 = var.iter().sum::<f64>() / 36.0;
    for (i, ax) in AX.iter().enumerate() {
        out.push(ParamEstimate {
            name: format!("u0_{ax}"),
            value: u0[i],
            sigma: var_u0.sqrt(),
            unit: "m/s² (raw)".into(),
        });
    }
    out
}

/// Magnitude error |y| − g of every pose before (raw) and after a calibration:
/// (pose index, before, after), m/s².
pub fn pose_norm_errors(poses: &[Pose], cal: &TriadCalibration, g: f64) -> Vec<(usize, f64, f64)> {
    poses
        .iter()
        .map(|p| {
            (
                p.index,
                p.acc().norm() - g,
                cal.model.apply(p.acc(), p.temp_c).norm() - g,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn pose(i: usize, u: Vec3) -> Pose {
        Pose {
            index: i,
            rows: [0, 0],
            lines: [0, 0],
            start_s: 0.0,
            duration_s: 1.0,
            n: 1,
            acc_mean: Some([u.x, u.y, u.z]),
            acc_std: None,
            gyr_mean: None,
            mag_mean: None,
            temp_c: Some(30.0),
            ref_inclination_deg: None,
        }
    }

    #[test]
    fn recovers_k_and_offset_exactly() {
        let k = Matrix3::new(
            1.02, 0.004, -0.003, -0.002, 0.97, 0.005, 0.006, -0.001, 1.01,
        );
        let u0 = Vec3::new(0.08, -0.05, 0.12);
        let g = 9.80665;
        let dirs = [
            Vec3::x(),
            -Vec3::x(),
            Vec3::y(),
            -Vec3::y(),
            Vec3::z(),
            -Vec3::z(),
        ];
        let poses: Vec<Pose> = dirs
            .iter()
            .enumerate()
            .map(|(i, d)| pose(i, k * (d * g) + u0))
            .collect();
        let s = six_position(&poses, g).unwrap();
        let cal = s.calibration.model;
        for d in dirs {
            assert_relative_eq!(cal.apply(k * (d * g) + u0, None), d * g, epsilon = 1e-12);
        }
        assert_relative_eq!(Vec3::from(s.bias), u0, epsilon = 1e-12);
        // a missing position is named
        let e = six_position(&poses[..5], g).unwrap_err();
        assert!(e.message.contains("-z up"), "{}", e.message);
    }

    #[test]
    fn one_sigma_matches_the_scatter_of_repeated_calibrations() {
        // independent check of the propagation: many noisy repetitions of the
        // six poses; the spread of M and u0 over them is the 1σ reported
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let k = Matrix3::new(1.05, 0.02, -0.03, -0.01, 0.93, 0.04, 0.03, -0.02, 1.1);
        let u0 = Vec3::new(0.08, -0.05, 0.12);
        let g = 9.80665;
        let (s_pose, n) = (0.06, 50usize); // reading scatter, samples per pose
        let per_axis = Normal::new(0.0, s_pose / (3.0 * n as f64).sqrt()).unwrap();
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let dirs = [
            Vec3::x(),
            -Vec3::x(),
            Vec3::y(),
            -Vec3::y(),
            Vec3::z(),
            -Vec3::z(),
        ];
        let trials = 3000;
        let mut sum = [0.0f64; 12];
        let mut sum2 = [0.0f64; 12];
        let mut reported = Vec::new();
        for _ in 0..trials {
            let poses: Vec<Pose> = dirs
                .iter()
                .enumerate()
                .map(|(i, d)| {
                    let noise = Vec3::from_fn(|_, _| per_axis.sample(&mut rng));
                    let mut p = pose(i, k * (d * g) + u0 + noise);
                    p.acc_std = Some(s_pose);
                    p.n = n;
                    p
                })
                .collect();
            let r = six_position(&poses, g).unwrap();
            for (j, p) in r.params.iter().enumerate() {
                sum[j] += p.value;
                sum2[j] += p.value * p.value;
            }
            reported = r.params;
        }
        assert_eq!(reported.len(), 12);
        assert_eq!(reported[1].name, "M_xy");
        assert_eq!(reported[11].name, "u0_z");
        for j in 0..12 {
            let mean = sum[j] / trials as f64;
            let sd = (sum2[j] / trials as f64 - mean * mean).max(0.0).sqrt();
            let ratio = reported[j].sigma / sd;
            // 3000 trials: the spread itself is known to about ±1.3 % (1σ)
            assert!(
                (ratio - 1.0).abs() < 0.06,
                "{}: {} vs {sd}",
                reported[j].name,
                reported[j].sigma
            );
        }
    }
}
