//! `clino survey`: inclination, azimuth, toolface, QC and trajectory from survey stations.

use anyhow::Result;
use clino::survey::{self, SurveyOptions};
use std::path::PathBuf;

/// Arguments of `clino survey`.
#[derive(clap::Args)]
pub struct Args {
    /// Stations (CSV: md_m, acc_*_m_s2 and optionally mag_*_uT in the tool frame, z down the hole).
    stations: PathBuf,
    /// Magnetic declination added to the azimuth, deg.
    #[arg(long, default_value_t = 0.0)]
    declination_deg: f64,
    /// Calibrate the readings first with this calibration file (accelerometer and magnetometer).
    #[arg(long)]
    calibration: Option<PathBuf>,
    /// Apply the calibration outside its valid temperature range.
    #[arg(long)]
    extrapolate: bool,
    /// Print the result as JSON (stations, roll_tests, trajectory).
    #[arg(long)]
    json: bool,
}

/// Run `clino survey`.
pub fn run(a: Args) -> Result<()> {
    let cal = match &a.calibration {
        Some(p) => {
            let mut cal = clino::calib::CalibrationFile::load(p)?;
            cal.extrapolate = a.extrapolate;
            Some(cal)
        }
        None => None,
    };
    let opts = SurveyOptions {
        declination_deg: a.declination_deg,
        ..Default::default()
    };
    let report = survey::survey_file(&a.stations, cal.as_ref(), &opts)?;
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print!("{}", clino::report::text::survey::survey(&report));
    }
    Ok(())
}
