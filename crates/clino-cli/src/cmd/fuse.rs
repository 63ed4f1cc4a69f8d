//! `clino fuse`: run one attitude filter over a recording, CSV in, CSV out.

use std::io::Write;
use std::path::PathBuf;

use clino::fusion::{FilterConfig, FilterKind, FuseOptions, TiltTrace, fuse_traced};
use clino::io::ImuCsvReader;

use super::{GainArgs, ReadArgs, StageArgs};

/// Arguments of `clino fuse`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input recording (CSV; `#` lines are comments; columns found by header name). `-` reads stdin.
    pub input: PathBuf,
    /// Filter: poisson, complementary, mahony, madgwick or dynamic (clino's own).
    #[arg(long, short = 'f', default_value = "dynamic")]
    pub filter: String,
    /// Output CSV (t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status); `-` or absent: stdout.
    #[arg(long, short = 'o')]
    pub output: Option<PathBuf>,
    /// Also plot roll, pitch and inclination (degrees) against time to this SVG or PNG file
    /// (at most 20 000 evenly spaced rows are kept for it, whatever the length of the input).
    #[arg(long, value_name = "FILE.svg|png")]
    pub plot: Option<PathBuf>,
    /// Stop with an error at the first NaN gyro or accelerometer value instead of holding the attitude.
    #[arg(long)]
    pub strict: bool,
    #[command(flatten)]
    pub read: ReadArgs,
    #[command(flatten)]
    pub gains: GainArgs,
    #[command(flatten)]
    pub stages: StageArgs,
    /// Calibrate every sample with this calibration file (from `clino calibrate`) before fusion.
    #[arg(long, value_name = "CAL.toml")]
    pub calibration: Option<PathBuf>,
}

/// Run `clino fuse`.
pub fn run(a: Args) -> anyhow::Result<()> {
    // fuse uses time, gyro and accelerometer only: skip parsing the rest.
    // fuse uses time, gyro and accelerometer only (and temperature for a calibration)
    let opts = clino::io::ReadOptions {
        imu_only: a.calibration.is_none(),
        ..a.read.options()?
    };
    let kind: FilterKind = a.filter.parse()?;
    let config = FilterConfig::new(kind)
        .with_gains(a.gains.gains()?)
        .with_lever_arm(a.stages.lever_arm()?)
        .with_offline(a.stages.offline);
    config.build()?; // check the gains before touching any file
    let calibration = match &a.calibration {
        Some(p) => Some(clino::calib::CalibrationFile::load(p)?),
        None => None,
    };
    let fuse_opts = FuseOptions {
        strict: a.strict,
        calibration: calibration.as_ref(),
    };
    let input: Box<dyn std::io::Read> = if a.input.as_os_str() == "-" {
        Box::new(std::io::stdin().lock())
    } else {
        Box::new(
            std::fs::File::open(&a.input).map_err(|e| clino::Error::from(e).in_file(&a.input))?,
        )
    };
    let name = if a.input.as_os_str() == "-" {
        PathBuf::from("<stdin>")
    } else {
        a.input.clone()
    };
    let mut reader = ImuCsvReader::new(input, name, &opts)?;
    let out: Box<dyn Write> = match &a.output {
        Some(p) if p.as_os_str() != "-" => {
            Box::new(std::fs::File::create(p).map_err(|e| clino::Error::from(e).in_file(p))?)
        }
        _ => Box::new(std::io::stdout().lock()),
    };
    let mut trace = a.plot.as_ref().map(|_| TiltTrace::new(20_000));
    let rep = fuse_traced(&mut reader, out, &config, &fuse_opts, trace.as_mut())?;
    if let (Some(path), Some(trace)) = (&a.plot, &trace) {
        let title = format!("{} — {}", a.input.display(), config.label());
        trace.plot(path, &title)?;
        eprintln!("clino fuse: plot written to {}", path.display());
    }
    eprintln!(
        "clino fuse: {} rows with {}: {} initialised, {} fused, {} gyro only, {} waiting for a usable accelerometer, {} with NaN gyro/accelerometer (attitude held{})",
        rep.rows,
        kind,
        rep.initialised,
        rep.fused,
        rep.gyro_only,
        rep.waiting,
        rep.dropouts,
        rep.first_dropout_line
            .map(|l| format!(", first at line {l}"))
            .unwrap_or_default()
    );
    Ok(())
}
