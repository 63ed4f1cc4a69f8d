//! The six-position method (for a fixture that points each housing axis up and down).
//!
//! With the housing's axis i up, an ideal triad reads +g along i; down, −g.
//! For readings u = K·a + u₀ (MPU6050 inclinometer paper, eq 1: A = K⁻¹(U_a − U_a0)),
//! the column i of K is (u(+i) − u(−i))/(2g), and u₀ is the mean of the six
//! readings (the ±g terms cancel). The calibration applies M = K⁻¹. Closed form;
//! all twelve parameters are determined because the fixture defines the axes.

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
    })
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
}
