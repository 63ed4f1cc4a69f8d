//! Choosing the calibration method for a triad and a recording, and what it
//! produced: the one library call behind `clino calibrate accel|gyro|mag`.
//!
//! * accelerometer: static poses ([`detect_static`](super::detect_static)),
//!   then the multi-position fit of a model ([`fit`](super::fit)) or the
//!   six-position method ([`six`]);
//! * gyro: a rate-table fit when the recording has the `ref_gyr_*_rad_s`
//!   columns ([`gyro::rate_table`]), else rotations between static poses
//!   ([`gyro::from_rotations`], matrix model only);
//! * magnetometer: the hard/soft-iron ellipsoid fit over at most 3000
//!   samples (evenly decimated).

use super::gyro::{self, RotationFit};
use super::six::{self, SixPosition};
use super::{ModelKind, Recording, StaticOptions, StaticReport, TriadEntry, TriadFit};
use crate::{Error, ErrorKind, Result};
use clino_core::sensor::{TriadCalibration, TriadKind};
use std::path::Path;

/// How a triad is calibrated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// A fit of this model (multi-position, rate table or ellipsoid by triad).
    Fit(ModelKind),
    /// The six-position method (accelerometer on a fixture).
    SixPosition,
}

impl Method {
    /// The method by the name `clino calibrate --model` takes: a model of
    /// [`ModelKind::parse`] (`matrix`, `mwd12`, `mwd30`: a fit) or `six`
    /// (the six-position method, accelerometer only).
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "six" => Ok(Method::SixPosition),
            m => ModelKind::parse(m).map(Method::Fit).map_err(|_| {
                Error::new(
                    ErrorKind::InvalidInput,
                    format!(
                        "unknown model '{s}' (matrix, mwd12, mwd30; six: the six-position method)"
                    ),
                )
            }),
        }
    }
}

/// Settings of [`calibrate`] (each used by the triads that need it).
#[derive(Clone, Debug)]
pub struct CalibOptions {
    /// Static-pose detection (accelerometer, gyro from rotations).
    pub statics: StaticOptions,
    /// Local gravity, m/s² (accelerometer).
    pub g_m_s2: f64,
    /// Local field magnitude, µT (magnetometer; `None`: the mean raw magnitude).
    pub field_ut: Option<f64>,
    /// Accelerometer calibration giving the gravity directions (gyro from
    /// rotations; `None`: the raw accelerometer, said in the notes).
    pub accel: Option<TriadCalibration>,
}

impl Default for CalibOptions {
    fn default() -> Self {
        Self {
            statics: StaticOptions::default(),
            g_m_s2: clino_core::G0,
            field_ut: None,
            accel: None,
        }
    }
}

/// What a method produced.
#[derive(Clone, Debug)]
pub enum Outcome {
    /// Six-position method over detected static poses.
    SixPosition {
        /// The poses found.
        statics: StaticReport,
        /// The result.
        six: SixPosition,
        /// Gravity used, m/s².
        g_m_s2: f64,
    },
    /// Accelerometer multi-position fit over detected static poses.
    AccelFit {
        /// The poses found.
        statics: StaticReport,
        /// The fit.
        fit: TriadFit,
    },
    /// Magnetometer ellipsoid fit.
    MagFit {
        /// The fit.
        fit: TriadFit,
    },
    /// Gyro rate-table fit.
    RateTable {
        /// The fit.
        fit: TriadFit,
    },
    /// Gyro from rotations between static poses.
    Rotations {
        /// The poses found.
        statics: StaticReport,
        /// The result.
        rotations: RotationFit,
    },
}

/// A calibration of one triad: what the method found and the file entry.
#[derive(Clone, Debug)]
pub struct Calibration {
    /// The triad.
    pub kind: TriadKind,
    /// What the method found.
    pub outcome: Outcome,
    /// The calibration-file entry (model, valid range, method, 1σ).
    pub entry: TriadEntry,
    /// What a user should know about the result (e.g. raw gravity directions).
    pub notes: Vec<String>,
}

/// Calibrate the triad `kind` from `rec` with `method`; `source` names the
/// recording in the entry's method text.
pub fn calibrate(
    kind: TriadKind,
    method: Method,
    rec: &Recording,
    source: &str,
    opts: &CalibOptions,
) -> Result<Calibration> {
    match (kind, method) {
        (TriadKind::Accel, Method::SixPosition) => six_position(rec, source, opts),
        (_, Method::SixPosition) => Err(Error::new(
            ErrorKind::InvalidInput,
            "the six-position method calibrates the accelerometer only",
        )),
        (TriadKind::Accel, Method::Fit(model)) => accel_fit(rec, model, source, opts),
        (TriadKind::Mag, Method::Fit(model)) => {
            let fit = super::calibrate_mag(rec, model, opts.field_ut)?;
            let what = format!(
                "{} ellipsoid fit, {} samples, {source}",
                model.name(),
                fit.observations
            );
            Ok(from_fit(fit, &what, |fit| Outcome::MagFit { fit }))
        }
        (TriadKind::Gyro, Method::Fit(model)) if rec.ref_gyr.is_some() => {
            let fit = gyro::rate_table(rec, model)?;
            let what = format!(
                "{} rate-table fit, {} segments, {source}",
                model.name(),
                fit.observations
            );
            Ok(from_fit(fit, &what, |fit| Outcome::RateTable { fit }))
        }
        (TriadKind::Gyro, Method::Fit(model)) => rotations(rec, model, source, opts),
    }
}

fn from_fit(fit: TriadFit, method: &str, wrap: impl FnOnce(TriadFit) -> Outcome) -> Calibration {
    Calibration {
        kind: fit.kind,
        entry: super::entry_from_fit(&fit, method),
        outcome: wrap(fit),
        notes: Vec::new(),
    }
}

fn six_position(rec: &Recording, source: &str, opts: &CalibOptions) -> Result<Calibration> {
    let statics = super::detect_static(rec, &opts.statics)?;
    let six = six::six_position(&statics.poses, opts.g_m_s2)?;
    let sigma = six
        .params
        .iter()
        .map(|p| (p.name.clone(), p.sigma))
        .collect();
    let entry = super::entry(
        TriadKind::Accel,
        six.calibration,
        &format!("six-position method, {source}"),
        "the fixture defines the axes: all 12 parameters determined",
        sigma,
    );
    Ok(Calibration {
        kind: TriadKind::Accel,
        outcome: Outcome::SixPosition {
            statics,
            six,
            g_m_s2: opts.g_m_s2,
        },
        entry,
        notes: Vec::new(),
    })
}

fn accel_fit(
    rec: &Recording,
    model: ModelKind,
    source: &str,
    opts: &CalibOptions,
) -> Result<Calibration> {
    let (statics, fit) = super::calibrate_accel(rec, model, &opts.statics, opts.g_m_s2)?;
    let what = format!(
        "{} multi-position fit, {} poses, {source}",
        model.name(),
        fit.observations
    );
    Ok(from_fit(fit, &what, |fit| Outcome::AccelFit {
        statics,
        fit,
    }))
}

fn rotations(
    rec: &Recording,
    model: ModelKind,
    source: &str,
    opts: &CalibOptions,
) -> Result<Calibration> {
    if model != ModelKind::Matrix {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "without a rate table (ref_gyr_*_rad_s columns) the gyro is calibrated from rotations between static poses, with the matrix model only (--model matrix)",
        ));
    }
    let mut notes = Vec::new();
    if opts.accel.is_none() {
        notes.push("gravity directions from the uncalibrated accelerometer; calibrate it first (--accel-calibration CAL.toml) for a better gyro fit".to_string());
    }
    let statics = super::detect_static(rec, &opts.statics)?;
    let r = gyro::from_rotations(rec, &statics.poses, opts.accel.as_ref())?;
    let sigma = r.params.iter().map(|p| (p.name.clone(), p.sigma)).collect();
    let entry = super::entry(
        TriadKind::Gyro,
        r.calibration,
        &format!(
            "rotations between {} static poses, {source}",
            statics.poses.len()
        ),
        "gravity directions fix the frame to the accelerometer's; bias is the mean static reading (Earth rate neglected)",
        sigma,
    );
    Ok(Calibration {
        kind: TriadKind::Gyro,
        outcome: Outcome::Rotations {
            statics,
            rotations: r,
        },
        entry,
        notes,
    })
}

impl Calibration {
    /// The `--json` output: the static poses (when detected) and the result.
    pub fn to_json(&self) -> serde_json::Value {
        use serde_json::json;
        match &self.outcome {
            Outcome::SixPosition { statics, six, .. } => {
                json!({ "static": statics, "six_position": six })
            }
            Outcome::AccelFit { statics, fit } => json!({ "static": statics, "fit": fit }),
            Outcome::MagFit { fit } | Outcome::RateTable { fit } => json!({ "fit": fit }),
            Outcome::Rotations { statics, rotations } => {
                json!({ "static": statics, "rotations": rotations })
            }
        }
    }

    /// Plot the residuals before and after (per pose, segment or move) to `path` (SVG or PNG).
    pub fn plot(&self, path: &Path) -> Result<()> {
        match &self.outcome {
            Outcome::AccelFit { fit, .. }
            | Outcome::MagFit { fit }
            | Outcome::RateTable { fit } => super::plot_residuals(path, fit),
            Outcome::SixPosition {
                statics,
                six,
                g_m_s2,
            } => {
                let g = *g_m_s2;
                let e: Vec<_> = six::pose_norm_errors(&statics.poses, &six.calibration, g)
                    .into_iter()
                    .map(|(i, b, a)| (i, b / g * 1e3, a / g * 1e3))
                    .collect();
                super::plot_before_after(
                    path,
                    "accel calibration (six-position): magnitude error per pose",
                    "magnitude error (mg)",
                    &e,
                )
            }
            Outcome::Rotations { rotations, .. } => {
                let e: Vec<_> = rotations
                    .moves
                    .iter()
                    .enumerate()
                    .map(|(k, m)| (k, m.error_before_deg, m.error_after_deg))
                    .collect();
                super::plot_before_after(
                    path,
                    "gyro calibration (rotations between poses): gravity-direction mismatch per move",
                    "mismatch (deg)",
                    &e,
                )
            }
        }
    }
}
