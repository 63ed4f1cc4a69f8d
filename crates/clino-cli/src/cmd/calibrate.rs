//! `clino calibrate`: estimate sensor calibrations from recordings, or apply one.

use anyhow::{Context, Result};
use clino::calib::{self, CalibrationFile, ModelKind, Recording, StaticOptions, gyro, six};
use clino::core::sensor::TriadKind;
use std::path::PathBuf;

/// Arguments of `clino calibrate`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand)]
enum What {
    /// Accelerometer: static poses (held still by hand or on a fixture), multi-position fit.
    Accel(Fit),
    /// Gyro: rate-table runs (ref_gyr_*_rad_s columns) or rotations between static poses.
    Gyro(Fit),
    /// Magnetometer: hard/soft iron by ellipsoid fit over all samples.
    Mag(Fit),
    /// Apply a calibration file to a recording (same columns, calibrated).
    Apply(Apply),
}

#[derive(clap::Args)]
struct Fit {
    /// Recording (CSV: t_s, acc_*_m_s2, gyr_*_rad_s, mag_*_uT, temp_c, ref_inclination_deg).
    recording: PathBuf,
    /// Model: matrix (bias + scale/misalignment), mwd12, mwd30 (cubic temperature), six (six-position, accel only).
    #[arg(long, default_value = "mwd12")]
    model: String,
    /// Output calibration file (TOML).
    #[arg(short, long)]
    output: PathBuf,
    /// Add to an existing calibration file instead of replacing it.
    #[arg(long)]
    update: bool,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// Plot residuals per pose before/after (SVG or PNG).
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Local gravity, m/s².
    #[arg(long, default_value_t = clino::core::G0)]
    g_m_s2: f64,
    /// Local field magnitude, µT (magnetometer; default: mean raw magnitude).
    #[arg(long)]
    field_ut: Option<f64>,
    /// Static detection window, s.
    #[arg(long, default_value_t = 0.5)]
    window_s: f64,
    /// Shortest static pose, s.
    #[arg(long, default_value_t = 1.0)]
    min_pose_s: f64,
    /// Accelerometer calibration to apply first (gyro from rotations; default: the accel entry of the file given with --update).
    #[arg(long)]
    accel_calibration: Option<PathBuf>,
}

#[derive(clap::Args)]
struct Apply {
    /// Calibration file (TOML).
    calibration: PathBuf,
    /// Recording (CSV).
    recording: PathBuf,
    /// Output recording (CSV, same columns).
    #[arg(short, long)]
    output: PathBuf,
    /// Apply models outside their valid temperature range.
    #[arg(long)]
    extrapolate: bool,
}

/// Run `clino calibrate`.
pub fn run(a: Args) -> Result<()> {
    match a.what {
        What::Accel(f) => fit(TriadKind::Accel, f),
        What::Gyro(f) => fit(TriadKind::Gyro, f),
        What::Mag(f) => fit(TriadKind::Mag, f),
        What::Apply(p) => apply(p),
    }
}

fn apply(p: Apply) -> Result<()> {
    let mut cal = CalibrationFile::load(&p.calibration)?;
    cal.extrapolate = p.extrapolate;
    let mut rec = Recording::load(&p.recording)?;
    cal.apply_recording(&mut rec)?;
    let f = std::fs::File::create(&p.output)
        .with_context(|| format!("cannot create {}", p.output.display()))?;
    rec.write_csv(std::io::BufWriter::new(f))
        .map_err(|e| e.in_file(&p.output))?;
    eprintln!("wrote {} rows to {}", rec.len(), p.output.display());
    Ok(())
}

fn fit(kind: TriadKind, f: Fit) -> Result<()> {
    let rec = Recording::load(&f.recording)?;
    let statics = StaticOptions {
        window_s: f.window_s,
        min_duration_s: f.min_pose_s,
        use_mag: kind == TriadKind::Mag && rec.acc.is_none(),
        ..Default::default()
    };
    let mut file = if f.update && f.output.exists() {
        CalibrationFile::load(&f.output)?
    } else {
        CalibrationFile::default()
    };
    let name = f.recording.display().to_string();
    let (json, text, tri) = match (kind, f.model.as_str()) {
        (TriadKind::Accel, "six") => {
            let report = calib::detect_static(&rec, &statics)?;
            let s = six::six_position(&report.poses, f.g_m_s2)?;
            if let Some(p) = &f.plot {
                let e: Vec<_> = six::pose_norm_errors(&report.poses, &s.calibration, f.g_m_s2)
                    .into_iter()
                    .map(|(i, b, a)| (i, b / f.g_m_s2 * 1e3, a / f.g_m_s2 * 1e3))
                    .collect();
                calib::plot_before_after(
                    p,
                    "accel calibration (six-position): magnitude error per pose",
                    "magnitude error (mg)",
                    &e,
                )?;
            }
            let entry = calib::entry(
                kind,
                s.calibration,
                &format!("six-position method, {name}"),
                "the fixture defines the axes: all 12 parameters determined",
                Default::default(),
            );
            let json = serde_json::json!({ "static": report, "six_position": s });
            let text = format!(
                "{}\nsix-position method: K = {:?}, u0 = {:?}\n",
                report.table(),
                s.k,
                s.bias
            );
            (json, text, entry)
        }
        (TriadKind::Accel, m) => {
            let model = ModelKind::parse(m)?;
            let (report, fit) = calib::calibrate_accel(&rec, model, &statics, f.g_m_s2)?;
            if let Some(p) = &f.plot {
                calib::plot_residuals(p, &fit)?;
            }
            let entry = calib::entry_from_fit(
                &fit,
                &format!(
                    "{} multi-position fit, {} poses, {name}",
                    model.name(),
                    fit.observations
                ),
            );
            (
                serde_json::json!({ "static": report, "fit": fit }),
                format!("{}\n{}", report.table(), fit.summary()),
                entry,
            )
        }
        (TriadKind::Mag, m) => {
            let model = ModelKind::parse(m)?;
            let fit = calib::calibrate_mag(&rec, model, f.field_ut)?;
            if let Some(p) = &f.plot {
                calib::plot_residuals(p, &fit)?;
            }
            let entry = calib::entry_from_fit(
                &fit,
                &format!(
                    "{} ellipsoid fit, {} samples, {name}",
                    model.name(),
                    fit.observations
                ),
            );
            (serde_json::json!({ "fit": fit }), fit.summary(), entry)
        }
        (TriadKind::Gyro, m) => {
            let model = ModelKind::parse(m)?;
            if rec.ref_gyr.is_some() {
                let fit = gyro::rate_table(&rec, model)?;
                if let Some(p) = &f.plot {
                    calib::plot_residuals(p, &fit)?;
                }
                let entry = calib::entry_from_fit(
                    &fit,
                    &format!(
                        "{} rate-table fit, {} segments, {name}",
                        model.name(),
                        fit.observations
                    ),
                );
                (serde_json::json!({ "fit": fit }), fit.summary(), entry)
            } else {
                anyhow::ensure!(
                    model == ModelKind::Matrix,
                    "without a rate table (ref_gyr_*_rad_s columns) the gyro is calibrated from rotations between static poses, with the matrix model only (--model matrix)"
                );
                // gravity directions come from the accelerometer: calibrated by --accel-calibration,
                // else by the accel entry of the file being updated, else raw (said on stderr)
                let accel = match &f.accel_calibration {
                    Some(p) => CalibrationFile::load(p)?.accel.map(|e| e.calibration()),
                    None => file.accel.as_ref().map(|e| e.calibration()),
                };
                if accel.is_none() {
                    eprintln!(
                        "clino: note: gravity directions from the uncalibrated accelerometer; calibrate it first (--accel-calibration CAL.toml) for a better gyro fit"
                    );
                }
                let report = calib::detect_static(&rec, &statics)?;
                let r = gyro::from_rotations(&rec, &report.poses, accel.as_ref())?;
                if let Some(p) = &f.plot {
                    let e: Vec<_> = r
                        .moves
                        .iter()
                        .enumerate()
                        .map(|(k, m)| (k, m.error_before_deg, m.error_after_deg))
                        .collect();
                    calib::plot_before_after(
                        p,
                        "gyro calibration (rotations between poses): gravity-direction mismatch per move",
                        "mismatch (deg)",
                        &e,
                    )?;
                }
                let sigma = r.params.iter().map(|p| (p.name.clone(), p.sigma)).collect();
                let entry = calib::entry(
                    kind,
                    r.calibration,
                    &format!(
                        "rotations between {} static poses, {name}",
                        report.poses.len()
                    ),
                    "gravity directions fix the frame to the accelerometer's; bias is the mean static reading (Earth rate neglected)",
                    sigma,
                );
                let text = format!(
                    "{}\ngyro from rotations: rms gravity-direction mismatch {:.4}° before, {:.4}° after\nbias {:?} rad/s\n{}",
                    report.table(),
                    r.rms_before_deg,
                    r.rms_after_deg,
                    r.bias,
                    r.params
                        .iter()
                        .map(|p| format!("{} = {:.6} ± {:.2e}\n", p.name, p.value, p.sigma))
                        .collect::<String>()
                );
                (
                    serde_json::json!({ "static": report, "rotations": r }),
                    text,
                    entry,
                )
            }
        }
    };
    file.set(kind, tri);
    file.save(&f.output)?;
    if f.json {
        println!("{}", serde_json::to_string_pretty(&json)?);
    } else {
        print!("{text}");
        println!("wrote {}", f.output.display());
    }
    Ok(())
}
