//! Estimating calibration models from recordings.
//!
//! The models themselves live in [`clino_core::sensor`] (they run on the
//! device); this module finds their numbers:
//!
//! * [`statics`] — static-interval detection in a continuous recording (the
//!   user holds the sensor still in N poses, no fixture), with a report of what
//!   it found;
//! * [`fit`] — multi-position fits by Levenberg–Marquardt of the matrix model
//!   and of the MWD model with 12 (nominal temperature) or 30 (cubic
//!   temperature) parameters, on E = E_g + E_T of "Error Analysis in
//!   Accelerometers Calibration of Measurement while Drilling Instrument"
//!   (eqs 16–20), with parameter uncertainties, residuals per pose and a stated
//!   convention for what the data cannot see; also the magnetometer's
//!   hard/soft-iron ellipsoid fit and the rate-table gyro fit;
//! * [`six`] — the six-position method for fixtures (A = K⁻¹(U_a − U_a0));
//! * [`gyro`] — gyro calibration from rate-table runs and from rotations
//!   between static poses;
//! * [`file`](mod@file) — calibration files (TOML) and applying them to samples
//!   ([`CalibrationFile::load`], [`CalibrationFile::apply`],
//!   [`CalibrationFile::apply_iter`]);
//! * [`recording`] — the CSV recordings these read;
//! * the seeded generator of miscalibrated recordings with truth lives in [`crate::sim::calib`].
//!
//! ## Example: calibrate, save, load, apply
//! ```
//! use clino::sim::calib as synth;
//! use clino::calib::{self, fit::{FitOptions, ModelKind}, CalibrationFile};
//! let opt = synth::SynthOptions::default();
//! let att = synth::attitudes_from_ups(&synth::cube_directions());
//! let temps = vec![30.0; att.len()];
//! let obs: Vec<_> = synth::accel_pose_observations(&opt, &att, &temps, 100).into_iter().map(|(o, _)| o).collect();
//! let fit = calib::fit::fit_triad(&obs, &FitOptions::accel(ModelKind::Mwd12)).unwrap();
//! assert!(fit.rms_norm_after.unwrap() < 1e-3);
//! let mut file = CalibrationFile::default();
//! file.set(fit.kind, calib::entry_from_fit(&fit, "doc example"));
//! let back = CalibrationFile::from_toml(&file.to_toml().unwrap()).unwrap();
//! let mut s = clino::core::ImuSample::new(0.0, Default::default(), obs[0].raw);
//! s.temp_c = Some(30.0);
//! let out = back.apply(&s).unwrap();
//! assert!((out.acc_m_s2.norm() - clino::core::G0).abs() < 1e-3);
//! ```

pub mod file;
pub mod fit;
pub mod gyro;
pub mod method;
pub mod recording;
pub mod six;
pub mod statics;
use crate::sim::calib as synth;

#[cfg(test)]
mod tests;

pub use file::{CalibrationFile, TriadEntry};
pub use fit::{FitOptions, ModelKind, Observation, TriadFit, fit_triad};
pub use method::{CalibOptions, Calibration, Method, Outcome, calibrate};
pub use recording::Recording;
pub use statics::{Pose, StaticOptions, StaticReport, detect_static};

use crate::{ErrorKind, Result};
use clino_core::Vec3;
use clino_core::sensor::{TriadCalibration, TriadKind};

/// The file entry of a fit (units, valid range, convention, 1σ of every parameter).
pub fn entry_from_fit(fit: &TriadFit, method: &str) -> TriadEntry {
    entry(
        fit.kind,
        fit.calibration,
        method,
        &fit.convention,
        fit.params
            .iter()
            .map(|p| (p.name.clone(), p.sigma))
            .collect(),
    )
}

/// A file entry from a calibration.
pub fn entry(
    kind: TriadKind,
    cal: TriadCalibration,
    method: &str,
    convention: &str,
    sigma: std::collections::BTreeMap<String, f64>,
) -> TriadEntry {
    TriadEntry {
        unit: kind.unit().into(),
        raw_unit: format!("{} (raw reading)", kind.unit()),
        valid_temp_c: cal.valid_temp_c,
        method: method.into(),
        convention: convention.into(),
        model: cal.model,
        sigma,
    }
}

/// Accelerometer calibration of a continuous recording: static detection, then
/// the multi-position fit of `model` (using `ref_inclination_deg` when present).
pub fn calibrate_accel(
    rec: &Recording,
    model: ModelKind,
    statics: &StaticOptions,
    g: f64,
) -> Result<(StaticReport, TriadFit)> {
    let report = detect_static(rec, statics)?;
    let obs = fit::observations_from_poses(&report.poses, TriadKind::Accel);
    let fit = fit_triad(
        &obs,
        &FitOptions {
            reference_norm: Some(g),
            ..FitOptions::accel(model)
        },
    )
    .map_err(|e| locate(e, rec))?;
    Ok((report, fit))
}

/// Magnetometer hard/soft-iron calibration by ellipsoid fit over the recording's
/// samples (at most 3000, evenly decimated). `field_ut` is the local field
/// magnitude; when `None` the mean raw magnitude about the centre is used (the
/// scale of a magnetometer is not observable from its own data).
pub fn calibrate_mag(rec: &Recording, model: ModelKind, field_ut: Option<f64>) -> Result<TriadFit> {
    let mag = rec.mag.as_ref().ok_or_else(|| {
        rec.error(
            ErrorKind::MissingColumn,
            "magnetometer calibration needs the magnetometer",
        )
        .at_column("mag_x_uT")
    })?;
    let step = mag.len().div_ceil(3000).max(1);
    let obs: Vec<Observation> = (0..mag.len())
        .step_by(step)
        .map(|i| Observation::new(mag[i], rec.temp_c.as_ref().map(|t| t[i])))
        .collect();
    let field = match field_ut {
        Some(f) => f,
        None => {
            let c = obs.iter().fold(Vec3::zeros(), |s, o| s + o.raw) / obs.len() as f64;
            obs.iter().map(|o| (o.raw - c).norm()).sum::<f64>() / obs.len() as f64
        }
    };
    let opt = FitOptions {
        kind: TriadKind::Mag,
        model,
        reference_norm: Some(field),
        tc_c: 30.0,
        use_ref_inclination: false,
        inclination_weight: 1.0,
    };
    fit_triad(&obs, &opt).map_err(|e| locate(e, rec))
}

fn locate(e: crate::Error, rec: &Recording) -> crate::Error {
    match (&e.file, &rec.path) {
        (None, Some(p)) => e.in_file(p),
        _ => e,
    }
}

/// Tilt error (angle between calibrated and true specific force, rad) and
/// magnitude error (m/s²) of a calibration at one raw reading.
pub fn tilt_and_norm_error(
    cal: &TriadCalibration,
    raw: Vec3,
    temp_c: f64,
    truth: Vec3,
) -> (f64, f64) {
    let y = cal.model.apply(raw, Some(temp_c));
    (y.angle(&truth), y.norm() - truth.norm())
}

/// `clino demo` section: a simulated poorly calibrated accelerometer triad
/// (MWD-paper magnitudes: scale ±4 %, bias ≤ 9 mg, 2 mrad misalignment,
/// ~150 ppm/°C and ~100 µg/°C temperature drift), 78 poses between 25 and 80 °C,
/// fitted with the 12- and 30-parameter models, and the tilt error of 200
/// fresh poses before and after. Deterministic, no files.
pub fn demo_summary() -> Result<String> {
    let opt = synth::SynthOptions::default();
    let mut ups = synth::cube_directions();
    ups.extend(synth::cube_directions());
    ups.extend(synth::cube_directions());
    let att = synth::attitudes_from_ups(&ups);
    let temps = synth::spread_temperatures(opt.temp_range_c, att.len());
    let obs: Vec<Observation> = synth::accel_pose_observations(&opt, &att, &temps, 100)
        .into_iter()
        .map(|(o, _)| o)
        .collect();
    let f12 = fit_triad(&obs, &FitOptions::accel(ModelKind::Mwd12))?;
    let f30 = fit_triad(&obs, &FitOptions::accel(ModelKind::Mwd30))?;
    let val = validation_set(&opt, 200, 99);
    let raw_cal = TriadCalibration {
        model: clino_core::sensor::TriadModel::Matrix(Default::default()),
        valid_temp_c: [0.0, 100.0],
    };
    let stats = |c: &TriadCalibration| {
        let mut tmax: f64 = 0.0;
        let mut gmax: f64 = 0.0;
        for (raw, t, truth) in &val {
            let (te, ge) = tilt_and_norm_error(c, *raw, *t, *truth);
            tmax = tmax.max(te);
            gmax = gmax.max(ge.abs());
        }
        (tmax.to_degrees(), gmax / clino_core::G0 * 1e3)
    };
    let (t0, g0) = stats(&raw_cal);
    let (t12, g12) = stats(&f12.calibration);
    let (t30, g30) = stats(&f30.calibration);
    Ok(format!(
        "Calibration of a poorly calibrated accelerometer triad (simulated, 78 poses, 25–80 °C)\n\
         max over 200 check poses     tilt error     |G| error\n\
         uncalibrated                 {t0:9.4}°   {g0:8.3} mg\n\
         MWD 12 parameters            {t12:9.4}°   {g12:8.3} mg   (temperature drift left)\n\
         MWD 30 parameters            {t30:9.4}°   {g30:8.3} mg   ({} evaluations)\n",
        f30.evaluations
    ))
}

/// Check poses for evaluating calibrations: (raw reading, temperature, true
/// specific force) at random attitudes and temperatures over the range.
pub fn validation_set(opt: &synth::SynthOptions, n: usize, seed: u64) -> Vec<(Vec3, f64, Vec3)> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let u = Vec3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            );
            let u = if u.norm() < 1e-3 {
                Vec3::z()
            } else {
                u.normalize()
            };
            let t = rng.random_range(opt.temp_range_c[0]..=opt.temp_range_c[1]);
            let f = u * opt.g;
            (opt.accel.invert(f, t).unwrap_or(f), t, f)
        })
        .collect()
}

/// Plot a fit's residuals per observation, before and after calibration
/// (magnitude error, or vector error for rate-table fits; with reference
/// inclinations a second file `<stem>_inclination.<ext>` shows the inclination error).
pub(crate) fn plot_residuals(path: &std::path::Path, fit: &TriadFit) -> Result<()> {
    use crate::report::{PlotSpec, Series, line_plot};
    let (scale, unit) = match fit.kind {
        TriadKind::Accel => (1e3 / clino_core::G0, "mg"),
        TriadKind::Gyro => (1.0, "rad/s"),
        TriadKind::Mag => (1.0, "µT"),
    };
    let pts = |f: &dyn Fn(&fit::ObsResidual) -> Option<f64>| -> Vec<(f64, f64)> {
        fit.residuals
            .iter()
            .filter_map(|r| f(r).map(|v| (r.index as f64, v * scale)))
            .collect()
    };
    let vector = fit.rms_vector_after.is_some();
    let (before, after, what) = if vector {
        (
            pts(&|r| r.vector_error_before),
            pts(&|r| r.vector_error_after),
            "vector error",
        )
    } else {
        (
            pts(&|r| r.norm_error_before),
            pts(&|r| r.norm_error_after),
            "magnitude error",
        )
    };
    line_plot(
        path,
        &PlotSpec {
            title: format!(
                "{} calibration ({}): {what} per pose",
                format!("{:?}", fit.kind).to_lowercase(),
                fit.model.name()
            ),
            x_label: "pose".into(),
            y_label: format!("{what} ({unit})"),
            ..Default::default()
        },
        &[
            Series::markers("before", before),
            Series::markers("after", after),
        ],
    )?;
    if fit.rms_inclination_after_deg.is_some() {
        let stem = path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("residuals");
        let ext = path.extension().and_then(|s| s.to_str()).unwrap_or("svg");
        let p2 = path.with_file_name(format!("{stem}_inclination.{ext}"));
        line_plot(
            &p2,
            &PlotSpec {
                title: "inclination error per pose".into(),
                x_label: "pose".into(),
                y_label: "inclination error (deg)".into(),
                ..Default::default()
            },
            &[
                Series::markers(
                    "before",
                    fit.residuals
                        .iter()
                        .filter_map(|r| r.inclination_error_before_deg.map(|v| (r.index as f64, v)))
                        .collect(),
                ),
                Series::markers(
                    "after",
                    fit.residuals
                        .iter()
                        .filter_map(|r| r.inclination_error_after_deg.map(|v| (r.index as f64, v)))
                        .collect(),
                ),
            ],
        )?;
    }
    Ok(())
}

/// Plot per-item errors before and after calibration (x: item number): the
/// six-position method's pose magnitudes, or the gravity-direction mismatch of
/// the gyro's moves between poses.
pub(crate) fn plot_before_after(
    path: &std::path::Path,
    title: &str,
    y_label: &str,
    items: &[(usize, f64, f64)],
) -> Result<()> {
    use crate::report::{PlotSpec, Series, line_plot};
    line_plot(
        path,
        &PlotSpec {
            title: title.into(),
            x_label: "pose / move".into(),
            y_label: y_label.into(),
            ..Default::default()
        },
        &[
            Series::markers(
                "before",
                items.iter().map(|(i, b, _)| (*i as f64, *b)).collect(),
            ),
            Series::markers(
                "after",
                items.iter().map(|(i, _, a)| (*i as f64, *a)).collect(),
            ),
        ],
    )
}

/// Temperature range a calibration is valid for: the calibration data's
/// temperatures widened by 1 °C (a cubic is harmless that far), or
/// [−1e9, 1e9] °C when the data carried no temperature.
pub fn valid_range(temps: &[f64]) -> [f64; 2] {
    let (lo, hi) = temps
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, &t| {
            (a.0.min(t), a.1.max(t))
        });
    if lo.is_finite() && hi.is_finite() {
        [lo - 1.0, hi + 1.0]
    } else {
        [-1e9, 1e9]
    }
}
