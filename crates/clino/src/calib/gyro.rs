//! Gyro calibration: from rate-table runs at known rates, and from rotations
//! between static poses.
//!
//! * **Rate table** (MPU6050 inclinometer paper: W = R⁻¹(U − U₀), the table
//!   turning at a constant known rate, several rates per axis): the recording
//!   carries the table's rate in the housing frame (`ref_gyr_*_rad_s`). Rows
//!   with the same reference rate form a segment; each segment's mean raw
//!   reading is an observation with a known vector, fitted by the common engine
//!   ([`super::fit::fit_triad`], vector residuals, all 12 matrix parameters or
//!   the MWD model).
//! * **Rotations between static poses** (no table): the bias is the mean gyro
//!   reading over the static poses (Earth rate neglected); the matrix M is
//!   found so that the integrated calibrated rate rotates the gravity direction
//!   of each pose into that of the next: with R_k = Π exp(M·(u − u₀)·Δt) over
//!   the motion (body frame), the residual is R_kᵀ·a_k − a_{k+1} for unit
//!   gravity directions a. Rotations about each axis are needed; the rotation
//!   about gravity of any one move is invisible, so moves must be varied.

use super::fit::{FitOptions, ModelKind, Observation, TriadFit, covariance, fit_triad};
use super::recording::Recording;
use super::statics::Pose;
use crate::{Error, ErrorKind, Result};
use clino_core::sensor::{MatrixModel, TriadCalibration, TriadKind, TriadModel};
use clino_core::{Attitude, Vec3};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Matrix3, Owned};
use serde::Serialize;

/// Segments of constant reference rate as observations (mean raw, mean temperature, reference).
pub fn rate_table_observations(rec: &Recording) -> Result<Vec<Observation>> {
    let gyr = rec.gyr.as_ref().ok_or_else(|| {
        rec.error(ErrorKind::MissingColumn, "gyro calibration needs the gyro")
            .at_column("gyr_x_rad_s")
    })?;
    let rf = rec.ref_gyr.as_ref().ok_or_else(|| {
        rec.error(
            ErrorKind::MissingColumn,
            "rate-table calibration needs the table's rate",
        )
        .at_column("ref_gyr_x_rad_s")
    })?;
    let mut out = Vec::new();
    let mut a = 0;
    while a < rec.len() {
        let mut b = a + 1;
        while b < rec.len() && (rf[b] - rf[a]).norm() <= 1e-9 * (1.0 + rf[a].norm()) {
            b += 1;
        }
        if b - a >= 5 {
            let k = (b - a) as f64;
            let raw = gyr[a..b].iter().fold(Vec3::zeros(), |s, x| s + x) / k;
            let temp = rec.temp_c.as_ref().map(|t| t[a..b].iter().sum::<f64>() / k);
            out.push(Observation {
                raw,
                temp_c: temp,
                ref_inclination: None,
                ref_vector: Some(rf[a]),
            });
        }
        a = b;
    }
    Ok(out)
}

/// Gyro calibration from rate-table runs. Errors name the axes without a run.
pub fn rate_table(rec: &Recording, model: ModelKind) -> Result<TriadFit> {
    let obs = rate_table_observations(rec)?;
    let mut missing = Vec::new();
    for (i, ax) in ["x", "y", "z"].iter().enumerate() {
        if !obs.iter().any(|o| {
            o.ref_vector
                .is_some_and(|v| v.norm() > 0.0 && v[i].abs() >= 0.5 * v.norm())
        }) {
            missing.push(*ax);
        }
    }
    if !missing.is_empty() {
        return Err(rec.error(
            ErrorKind::Degenerate,
            format!("{} rate-table segments, but no run about the {} axis: turn the table about every axis", obs.len(), missing.join(", ")),
        ));
    }
    let opt = FitOptions {
        kind: TriadKind::Gyro,
        model,
        reference_norm: None,
        tc_c: 30.0,
        use_ref_inclination: false,
        inclination_weight: 1.0,
    };
    fit_triad(&obs, &opt).map_err(|e| match &rec.path {
        Some(p) if e.file.is_none() => e.in_file(p),
        _ => e,
    })
}

/// One move between two static poses.
#[derive(Clone, Debug, Serialize)]
pub struct MoveResidual {
    /// Pose before and after.
    pub poses: [usize; 2],
    /// Rotation angle integrated from the calibrated gyro, deg.
    pub angle_deg: f64,
    /// Gravity-direction mismatch with the raw gyro (bias removed only), deg.
    pub error_before_deg: f64,
    /// Mismatch after calibration, deg.
    pub error_after_deg: f64,
}

/// Result of the rotations-between-poses calibration.
#[derive(Clone, Debug, Serialize)]
pub struct RotationFit {
    /// The calibration (matrix model).
    pub calibration: TriadCalibration,
    /// Bias (mean static gyro reading), rad/s.
    pub bias: [f64; 3],
    /// M entries with 1σ, row-major names `M_xy`.
    pub params: Vec<super::fit::ParamEstimate>,
    /// Residuals per move.
    pub moves: Vec<MoveResidual>,
    /// RMS gravity-direction mismatch before / after, deg.
    pub rms_before_deg: f64,
    /// RMS after, deg.
    pub rms_after_deg: f64,
}

#[derive(Clone)]
struct RotProblem {
    m: Matrix3<f64>,
    /// per move: increments (u − u₀)·Δt (trapezoid), gravity directions before and after
    moves: Vec<(Vec<Vec3>, Vec3, Vec3)>,
}

impl RotProblem {
    fn rotation(&self, inc: &[Vec3]) -> Attitude {
        inc.iter().fold(Attitude::identity(), |r, w| {
            r * Attitude::from_scaled_axis(self.m * w)
        })
    }
    fn predicted(&self, k: usize) -> Vec3 {
        let (inc, a0, _) = &self.moves[k];
        self.rotation(inc).inverse_transform_vector(a0)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for RotProblem {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;
    fn set_params(&mut self, x: &DVector<f64>) {
        for i in 0..3 {
            for j in 0..3 {
                self.m[(i, j)] = x[3 * i + j];
            }
        }
    }
    fn params(&self) -> DVector<f64> {
        DVector::from_fn(9, |k, _| self.m[(k / 3, k % 3)])
    }
    fn residuals(&self) -> Option<DVector<f64>> {
        let mut r = DVector::zeros(3 * self.moves.len());
        for k in 0..self.moves.len() {
            let d = self.predicted(k) - self.moves[k].2;
            r.fixed_rows_mut::<3>(3 * k).copy_from(&d);
        }
        r.iter().all(|v| v.is_finite()).then_some(r)
    }
    fn jacobian(&self) -> Option<DMatrix<f64>> {
        // central differences (the crate's `differentiate_numerically` is meant
        // for tests: it re-evaluates all residuals per entry)
        let x = self.params();
        let mut p = self.clone();
        let mut j = DMatrix::zeros(3 * self.moves.len(), 9);
        let h = 1e-6;
        for c in 0..9 {
            let mut xp = x.clone();
            xp[c] += h;
            p.set_params(&xp);
            let rp = p.residuals()?;
            xp[c] -= 2.0 * h;
            p.set_params(&xp);
            let rm = p.residuals()?;
            j.set_column(c, &((rp - rm) / (2.0 * h)));
        }
        Some(j)
    }
}

/// Gyro scale and misalignment from rotations between static poses (see the
/// module documentation). `poses` are the static poses of `rec` (from
/// [`super::statics::detect_static`]); `accel` optionally calibrates the
/// accelerometer first (the gravity directions are only as good as it).
pub fn from_rotations(
    rec: &Recording,
    poses: &[Pose],
    accel: Option<&TriadCalibration>,
) -> Result<RotationFit> {
    let gyr = rec.gyr.as_ref().ok_or_else(|| {
        rec.error(ErrorKind::MissingColumn, "gyro calibration needs the gyro")
            .at_column("gyr_x_rad_s")
    })?;
    let acc = rec.acc.as_ref().ok_or_else(|| {
        rec.error(
            ErrorKind::MissingColumn,
            "calibrating the gyro from rotations needs the accelerometer",
        )
        .at_column("acc_x_m_s2")
    })?;
    let _ = acc;
    if poses.len() < 4 {
        return Err(rec.error(ErrorKind::Degenerate, format!("{} static poses; calibrating the gyro from rotations needs at least 4 (moves about each axis)", poses.len())));
    }
    let n_static: usize = poses.iter().map(|p| p.n).sum();
    let b = poses
        .iter()
        .fold(Vec3::zeros(), |s, p| s + p.gyr() * p.n as f64)
        / n_static as f64;
    let dir = |p: &Pose| {
        let a = match accel {
            Some(c) => c.model.apply(p.acc(), p.temp_c),
            None => p.acc(),
        };
        a.normalize()
    };
    let mut moves = Vec::new();
    for w in poses.windows(2) {
        let (i0, i1) = (w[0].rows[1], w[1].rows[0]);
        let inc: Vec<Vec3> = (i0..i1)
            .map(|i| ((gyr[i] - b) + (gyr[i + 1] - b)) * 0.5 * (rec.t_s[i + 1] - rec.t_s[i]))
            .collect();
        moves.push((inc, dir(&w[0]), dir(&w[1])));
    }
    // coverage: a substantial rotation about each axis
    let mut missing = Vec::new();
    for (i, ax) in ["x", "y", "z"].iter().enumerate() {
        let seen = moves.iter().any(|(inc, _, _)| {
            let r = inc.iter().fold(Vec3::zeros(), |s, x| s + x);
            r.norm() > 10f64.to_radians() && r[i].abs() >= 0.5 * r.norm()
        });
        if !seen {
            missing.push(*ax);
        }
    }
    if !missing.is_empty() {
        return Err(rec.error(ErrorKind::Degenerate, format!("no rotation of more than 10° about the {} axis between static poses: turn the sensor about every axis", missing.join(", "))));
    }
    let prob = RotProblem {
        m: Matrix3::identity(),
        moves,
    };
    let angle = |p: &RotProblem, k: usize| p.predicted(k).angle(&p.moves[k].2).to_degrees();
    let before: Vec<f64> = (0..prob.moves.len()).map(|k| angle(&prob, k)).collect();
    let (prob, report) = LevenbergMarquardt::new()
        .with_ftol(1e-14)
        .with_xtol(1e-12)
        .with_gtol(1e-14)
        .minimize(prob);
    if !super::fit::solver_succeeded(&report.termination) {
        return Err(super::fit::solver_error(
            "the gyro rotation fit",
            &report.termination,
        ));
    }
    let r = prob
        .residuals()
        .ok_or_else(|| Error::new(ErrorKind::NotConverged, "non-finite residuals"))?;
    let j = prob
        .jacobian()
        .ok_or_else(|| Error::new(ErrorKind::NotConverged, "non-finite Jacobian"))?;
    let (cov, rel, weak) = covariance(&j);
    if rel < 1e-9 {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!(
                "the moves cannot determine M_{}{}: rotate about other axes",
                ["x", "y", "z"][weak / 3],
                ["x", "y", "z"][weak % 3]
            ),
        ));
    }
    let dof = (r.len() as f64 - 9.0).max(1.0);
    let s2 = r.norm_squared() / dof;
    let params = (0..9)
        .map(|k| super::fit::ParamEstimate {
            name: format!("M_{}{}", ["x", "y", "z"][k / 3], ["x", "y", "z"][k % 3]),
            value: prob.m[(k / 3, k % 3)],
            sigma: (s2 * cov[(k, k)]).sqrt(),
            unit: "1".into(),
        })
        .collect();
    let moves: Vec<MoveResidual> = (0..prob.moves.len())
        .map(|k| MoveResidual {
            poses: [poses[k].index, poses[k + 1].index],
            angle_deg: prob.rotation(&prob.moves[k].0).angle().to_degrees(),
            error_before_deg: before[k],
            error_after_deg: angle(&prob, k),
        })
        .collect();
    let rms = |f: &dyn Fn(&MoveResidual) -> f64| {
        (moves.iter().map(|m| f(m).powi(2)).sum::<f64>() / moves.len() as f64).sqrt()
    };
    let temps: Vec<f64> = poses.iter().filter_map(|p| p.temp_c).collect();
    let valid = super::valid_range(&temps);
    Ok(RotationFit {
        calibration: TriadCalibration {
            model: TriadModel::Matrix(MatrixModel {
                bias: [b.x, b.y, b.z],
                matrix: std::array::from_fn(|i| std::array::from_fn(|j| prob.m[(i, j)])),
            }),
            valid_temp_c: valid,
        },
        bias: [b.x, b.y, b.z],
        params,
        rms_before_deg: rms(&|m| m.error_before_deg),
        rms_after_deg: rms(&|m| m.error_after_deg),
        moves,
    })
}
