//! `clino calibrate`: estimate sensor calibrations from recordings, or apply one.

use super::OutputArgs;
use anyhow::{Context, Result};
use clap::ValueEnum;
use clino::calib::{
    self, CalibOptions, CalibrationFile, Method, ModelKind, Recording, StaticOptions,
};
use clino::core::sensor::TriadKind;
use clino::report::text::calib as text;
use std::path::{Path, PathBuf};

/// Arguments of `clino calibrate`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    what: What,
}

#[derive(clap::Subcommand)]
enum What {
    /// Accelerometer: static poses (held still by hand or on a fixture), multi-position fit or six-position method.
    Accel(AccelArgs),
    /// Gyro: rate-table runs (ref_gyr_*_rad_s columns) or rotations between static poses.
    Gyro(GyroArgs),
    /// Magnetometer: hard/soft iron by ellipsoid fit over all samples.
    Mag(MagArgs),
    /// Apply a calibration file to a recording (same columns, calibrated).
    Apply(Apply),
}

/// A calibration model fitted to a recording.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum ModelArg {
    /// Bias and a full scale/misalignment matrix.
    Matrix,
    /// MWD model, 12 parameters (nominal temperature).
    Mwd12,
    /// MWD model, 30 parameters (cubic in temperature).
    Mwd30,
}

impl From<ModelArg> for ModelKind {
    fn from(m: ModelArg) -> Self {
        match m {
            ModelArg::Matrix => ModelKind::Matrix,
            ModelArg::Mwd12 => ModelKind::Mwd12,
            ModelArg::Mwd30 => ModelKind::Mwd30,
        }
    }
}

/// How the accelerometer is calibrated.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum AccelModelArg {
    /// Bias and a full scale/misalignment matrix (multi-position fit).
    Matrix,
    /// MWD model, 12 parameters (multi-position fit).
    Mwd12,
    /// MWD model, 30 parameters, cubic in temperature (multi-position fit).
    Mwd30,
    /// Six-position method: each housing axis up and down on a fixture.
    Six,
}

impl From<AccelModelArg> for Method {
    fn from(m: AccelModelArg) -> Self {
        match m {
            AccelModelArg::Matrix => Method::Fit(ModelKind::Matrix),
            AccelModelArg::Mwd12 => Method::Fit(ModelKind::Mwd12),
            AccelModelArg::Mwd30 => Method::Fit(ModelKind::Mwd30),
            AccelModelArg::Six => Method::SixPosition,
        }
    }
}

/// What every calibration reads and writes.
#[derive(clap::Args)]
struct Common {
    /// Recording (CSV or Parquet: t_s and the triad's columns, e.g. acc_*_m_s2, gyr_*_rad_s, mag_*_uT; temp_c).
    recording: PathBuf,
    /// Output calibration file (TOML).
    #[arg(short, long)]
    output: PathBuf,
    /// Add to an existing calibration file instead of replacing it.
    #[arg(long)]
    update: bool,
    // Print the result as JSON; --plot draws the residuals before/after.
    #[command(flatten)]
    out: OutputArgs,
}

/// Static-pose detection.
#[derive(clap::Args)]
struct StaticArgs {
    /// Static detection window, s.
    #[arg(long, default_value_t = 0.5)]
    window_s: f64,
    /// Shortest static pose, s.
    #[arg(long, default_value_t = 1.0)]
    min_pose_s: f64,
}

impl StaticArgs {
    fn options(&self) -> StaticOptions {
        StaticOptions {
            window_s: self.window_s,
            min_duration_s: self.min_pose_s,
            ..Default::default()
        }
    }
}

#[derive(clap::Args)]
struct AccelArgs {
    #[command(flatten)]
    common: Common,
    /// Model (multi-position fit) or the six-position method. The recording may carry ref_inclination_deg.
    #[arg(long, value_enum, default_value = "mwd12")]
    model: AccelModelArg,
    /// Local gravity, m/s².
    #[arg(long, default_value_t = clino::core::G0)]
    g_m_s2: f64,
    #[command(flatten)]
    statics: StaticArgs,
}

#[derive(clap::Args)]
struct GyroArgs {
    #[command(flatten)]
    common: Common,
    /// Model (rotations between static poses: matrix only).
    #[arg(long, value_enum, default_value = "mwd12")]
    model: ModelArg,
    #[command(flatten)]
    statics: StaticArgs,
    /// Accelerometer calibration giving the gravity directions (rotations between poses; default: the accel entry of the file given with --update).
    #[arg(long)]
    accel_calibration: Option<PathBuf>,
}

#[derive(clap::Args)]
struct MagArgs {
    #[command(flatten)]
    common: Common,
    /// Model.
    #[arg(long, value_enum, default_value = "mwd12")]
    model: ModelArg,
    /// Local field magnitude, µT (default: mean raw magnitude).
    #[arg(long)]
    field_ut: Option<f64>,
}

#[derive(clap::Args)]
struct Apply {
    /// Calibration file (TOML).
    calibration: PathBuf,
    /// Recording (CSV, or Parquet by the `.parquet` extension).
    recording: PathBuf,
    /// Output recording, same columns: CSV, or Parquet when the name ends in `.parquet`
    /// (written under a temporary name and renamed: a failed run leaves nothing half-written).
    #[arg(short, long)]
    output: PathBuf,
    /// Apply models outside their valid temperature range.
    #[arg(long)]
    extrapolate: bool,
}

/// Run `clino calibrate`.
pub fn run(a: Args) -> Result<()> {
    match a.what {
        What::Accel(f) => {
            let opts = CalibOptions {
                statics: f.statics.options(),
                g_m_s2: f.g_m_s2,
                ..CalibOptions::default()
            };
            fit(TriadKind::Accel, f.model.into(), &f.common, opts)
        }
        What::Gyro(f) => {
            let accel = match &f.accel_calibration {
                Some(p) => CalibrationFile::load(p)?.accel.map(|e| e.calibration()),
                None => existing(&f.common)?.accel.map(|e| e.calibration()),
            };
            let opts = CalibOptions {
                statics: f.statics.options(),
                accel,
                ..CalibOptions::default()
            };
            fit(
                TriadKind::Gyro,
                Method::Fit(f.model.into()),
                &f.common,
                opts,
            )
        }
        What::Mag(f) => {
            let opts = CalibOptions {
                field_ut: f.field_ut,
                ..CalibOptions::default()
            };
            fit(TriadKind::Mag, Method::Fit(f.model.into()), &f.common, opts)
        }
        What::Apply(p) => apply(p),
    }
}

fn apply(p: Apply) -> Result<()> {
    let mut cal = CalibrationFile::load(&p.calibration)?;
    cal.extrapolate = p.extrapolate;
    let mut rec = Recording::load(&p.recording)?;
    cal.apply_recording(&mut rec)?;
    rec.save(&p.output, &[&p.recording, &p.calibration])?;
    eprintln!("wrote {} rows to {}", rec.len(), p.output.display());
    Ok(())
}

/// The calibration file updated (`--update` of an existing file) or a new one.
fn existing(c: &Common) -> Result<CalibrationFile> {
    Ok(if c.update && c.output.exists() {
        CalibrationFile::load(&c.output)?
    } else {
        CalibrationFile::default()
    })
}

/// Fit, save the calibration, print it, then plot. A plot name that cannot
/// be a plot (extension, directory) is refused before the fit; a plot that
/// still cannot be written is an error (non-zero exit) after the
/// calibration is saved and printed.
fn fit(kind: TriadKind, method: Method, c: &Common, opts: CalibOptions) -> Result<()> {
    if let Some(p) = &c.out.plot {
        clino::report::check_plot_path(p)?;
    }
    let rec = Recording::load(&c.recording)?;
    let mut file = existing(c)?;
    let name = c.recording.display().to_string();
    let cal = calib::calibrate(kind, method, &rec, &name, &opts)?;
    for n in &cal.notes {
        eprintln!("clino: note: {n}");
    }
    file.set(kind, cal.entry.clone());
    file.save(&c.output)?;
    if c.out.json {
        println!("{}", serde_json::to_string_pretty(&cal.to_json())?);
    } else {
        print!("{}", text::calibration(&cal));
        println!("wrote {}", c.output.display());
    }
    if let Some(p) = &c.out.plot {
        plot(&cal, p, &c.output)?;
    }
    Ok(())
}

fn plot(cal: &calib::Calibration, p: &Path, saved: &Path) -> Result<()> {
    cal.plot(p).with_context(|| {
        format!(
            "the calibration was saved to {}, but the plot could not be written",
            saved.display()
        )
    })?;
    Ok(())
}
