//! `clino fuse`: run one attitude filter over a recording, CSV in, CSV out.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};

use clino::fusion::{
    FUSE_HEADER, FilterConfig, FuseOptions, FuseReport, TiltTrace, fuse_into, fuse_traced,
};
use clino::io::{AtomicFile, ImuCsvReader, ParquetRowWriter};

use super::{GainArgs, ReadArgs, StageArgs};

/// Arguments of `clino fuse`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input recording: CSV (`#` lines are comments; columns found by header name) or Parquet
    /// (`.parquet`, the same column names). `-` reads CSV from stdin.
    pub input: PathBuf,
    /// Filter: poisson, complementary, mahony, madgwick or dynamic (clino's own), with any
    /// parameter as NAME:KEY=VALUE,… (`clino fuse --help` lists them all with units).
    #[arg(long, short = 'f', default_value = "dynamic", long_help = clino::fusion::filter_help())]
    pub filter: String,
    /// Output (t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status): CSV, or Parquet when the
    /// name ends in `.parquet`; `-` or absent: CSV on stdout.
    /// A file is written under a temporary name and renamed at the end: a failed run leaves nothing half-written.
    #[arg(long, short = 'o')]
    pub output: Option<PathBuf>,
    /// Also plot roll, pitch and inclination (degrees) against time to this SVG or PNG file
    /// (at most 20 000 evenly spaced rows are kept for it, whatever the length of the input).
    #[arg(long, value_name = "FILE.svg|png")]
    pub plot: Option<PathBuf>,
    /// Stop with an error at the first NaN or out-of-bounds gyro or accelerometer value instead of holding the attitude.
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

/// Fuse into the output the arguments name: a CSV or Parquet file (written
/// atomically), or CSV on stdout.
fn write_out<R: std::io::Read>(
    a: &Args,
    reader: &mut ImuCsvReader<R>,
    config: &FilterConfig,
    opts: &FuseOptions,
    trace: Option<&mut TiltTrace>,
) -> anyhow::Result<FuseReport> {
    let Some(p) = a.output.as_ref().filter(|p| p.as_os_str() != "-") else {
        let out: Box<dyn Write> = Box::new(std::io::stdout().lock());
        return Ok(fuse_traced(reader, out, config, opts, trace)?);
    };
    let mut inputs: Vec<&Path> = vec![&a.input];
    inputs.extend(a.calibration.as_deref());
    let mut file = AtomicFile::create(p, &inputs)?;
    let rep = if clino::io::is_parquet(p) {
        let mut w = ParquetRowWriter::new(&mut file, &FUSE_HEADER, &["status"])?;
        let rep = fuse_into(reader, &mut w, config, opts, trace)?;
        w.finish().map_err(|e| clino::Error::from(e).in_file(p))?;
        rep
    } else {
        fuse_traced(reader, &mut file, config, opts, trace)?
    };
    file.commit()?;
    Ok(rep)
}

/// The mount estimate (accelerometer bias, lever arm) on stderr.
fn mount_summary(m: &clino::fusion::MountReport, lever_auto: bool) -> String {
    let mg = 1e3 / clino::core::G0;
    let (b, sb) = (m.accel_bias_m_s2, m.accel_bias_sigma_m_s2);
    let mut s = format!(
        "clino fuse: accelerometer bias ({:.2}, {:.2}, {:.2}) mg ± ({:.2}, {:.2}, {:.2}) mg (1σ)",
        b[0] * mg,
        b[1] * mg,
        b[2] * mg,
        sb[0] * mg,
        sb[1] * mg,
        sb[2] * mg
    );
    if !lever_auto && !m.bias_applied {
        s.push_str(&format!(
            "\nclino fuse: the bias estimate NOT applied: the given arm's terms leave {:.3} m/s² of the block-mean acceleration a block (1σ), where a rigid body turning about a fixed axis leaves at most {} m/s²; the point on the axis moves, and the tilt is the filter's own with the arm's terms removed",
            m.noise_sigma_m_s2,
            clino::core::compensate::LEVER_FIXED_AXIS_M_S2
        ));
    }
    if lever_auto {
        let (r, sr) = (m.lever_arm_m, m.lever_arm_sigma_m);
        s.push_str(&format!(
            "\nclino fuse: lever arm ({:.3}, {:.3}, {:.3}) m ± ({:.3}, {:.3}, {:.3}) m (1σ; a component along the rotation axis causes no acceleration and keeps its prior)",
            r[0], r[1], r[2], sr[0], sr[1], sr[2]
        ));
        if let Some(f) = m.lever_explains {
            let a = m.lever_arm_applied_m;
            if m.lever_applied {
                s.push_str(&format!(
                    "\nclino fuse: applied: its tangential and centripetal terms predict {:.1} % of the block-mean acceleration and leave {:.3} m/s² a block (1σ)",
                    100.0 * f,
                    m.noise_sigma_m_s2
                ));
            } else {
                s.push_str(&format!(
                    "\nclino fuse: NOT applied, nor the bias estimate (the samples were compensated with ({:.3}, {:.3}, {:.3}) m): its terms predict {:.1} % of the block-mean acceleration and leave {:.3} m/s² a block (1σ), where a rigid body turning about a fixed axis has them predict at least {:.0} % and leave at most {} m/s²; this mount moves in ways a lever arm does not model",
                    a[0],
                    a[1],
                    a[2],
                    100.0 * f,
                    m.noise_sigma_m_s2,
                    100.0 * clino::core::compensate::LEVER_EXPLAINS,
                    clino::core::compensate::LEVER_FIXED_AXIS_M_S2
                ));
            }
        }
    }
    s
}

/// What the dynamic filter learnt from rest to rest, on stderr.
fn sensor_error_summary(e: &clino::fusion::SensorErrorReport) -> String {
    let mg = 1e3 / clino::core::G0;
    let three = |v: [f64; 3], sd: [f64; 3], k: f64| {
        format!(
            "({:+.2}, {:+.2}, {:+.2}) ± ({:.2}, {:.2}, {:.2})",
            v[0] * k,
            v[1] * k,
            v[2] * k,
            sd[0] * k,
            sd[1] * k,
            sd[2] * k
        )
    };
    let p = e.probability;
    let m = e.motion_gyro_scale;
    format!(
        "clino fuse: learnt from {} rest pairs (1σ; probability that the error is there at all): gyro scale {} % ({:.2}), accelerometer scale {} % ({:.2}), accelerometer bias {} mg ({:.2}); and in motion by the loop, gyro scale ({:+.2}, {:+.2}, {:+.2}) % more",
        e.rest_pairs,
        three(e.gyro_scale, e.gyro_scale_sigma, 100.0),
        p[0],
        three(e.accel_scale, e.accel_scale_sigma, 100.0),
        p[1],
        three(e.accel_bias_m_s2, e.accel_bias_sigma_m_s2, mg),
        p[2],
        m[0] * 100.0,
        m[1] * 100.0,
        m[2] * 100.0
    )
}

/// The one-line summary on stderr.
fn summary(rep: &FuseReport, label: &str) -> String {
    format!(
        "clino fuse: {} rows with {label}: {} initialised, {} fused, {} gyro only, {} waiting for a usable accelerometer, {} with NaN gyro/accelerometer, {} beyond the physical bounds (attitude held{}){}{}",
        rep.counts.samples,
        rep.counts.initialised,
        rep.counts.fused,
        rep.counts.gyro_only,
        rep.counts.waiting,
        rep.counts.dropouts,
        rep.counts.saturated,
        rep.first_dropout_line
            .map(|l| format!(", first at line {l}"))
            .unwrap_or_default(),
        clipped(rep),
        stamps(rep)
    )
}

/// The steps taken from the sample clock recovered from the stamps, when any were.
fn stamps(rep: &FuseReport) -> String {
    match rep.stamp_jitter_s {
        Some(j) if rep.counts.retimed > 0 => format!(
            "; time stamps off the sensor's clock by {:.2} ms RMS (a host's receive times?): {} rows took their step from the clock recovered from them (`--stamps as-given`: from the stamps)",
            1e3 * j,
            rep.counts.retimed
        ),
        _ => String::new(),
    }
}

/// A hint, when a triad whose range was not given repeats its largest
/// reading ([`clino::fusion::Rails::suspected`]): it was most likely clipped.
fn rail_hint(rep: &FuseReport, range: &clino::fusion::SensorRange) -> Option<String> {
    let (g, a) = rep.rails.suspected();
    let mut said = Vec::new();
    if let (Some(v), false) = (g, range.gyro_rad_s.is_finite()) {
        said.push(format!(
            "the gyro's largest reading, {:.1} °/s, is on {} rows: clipped at its range? `--gyro-range {:.0}` tells the filter",
            v.to_degrees(),
            rep.rails.gyro_rows,
            v.to_degrees()
        ));
    }
    if let (Some(v), false) = (a, range.acc_m_s2.is_finite()) {
        said.push(format!(
            "the accelerometer's largest reading, {:.2} g, is on {} rows: clipped at its range? `--acc-range {:.0}` tells the filter",
            v / clino::core::G0,
            rep.rails.acc_rows,
            v / clino::core::G0
        ));
    }
    (!said.is_empty()).then(|| format!("clino fuse: {}", said.join("; ")))
}

/// The clipped readings, when the sensor's ranges were given and any were.
fn clipped(rep: &FuseReport) -> String {
    let c = &rep.counts;
    if c.gyro_clipped + c.acc_clipped == 0 {
        return String::new();
    }
    format!(
        "; clipped at the sensor's range: {} gyro, {} accelerometer{}",
        c.gyro_clipped,
        c.acc_clipped,
        rep.first_clipped_line
            .map(|l| format!(" (first at line {l})"))
            .unwrap_or_default()
    )
}

/// Run `clino fuse`.
pub fn run(a: Args) -> anyhow::Result<()> {
    // fuse uses time, gyro and accelerometer only (and temperature for a calibration)
    let opts = clino::io::ReadOptions {
        imu_only: a.calibration.is_none(),
        ..a.read.options()?
    };
    // the parameters are checked before any file is touched
    let config = super::filter_config(&a.filter, &a.gains, &a.stages)?;
    let calibration = match &a.calibration {
        Some(p) => Some(clino::calib::CalibrationFile::load(p)?),
        None => None,
    };
    let stdin = a.input.as_os_str() == "-";
    let to_file = a.output.as_ref().filter(|p| p.as_os_str() != "-");
    let bar = super::progress_spinner("fuse");
    let show = |p| super::show_fuse_progress(&bar, p);
    let fuse_opts = FuseOptions {
        progress: Some(&show),
        strict: a.strict,
        calibration: calibration.as_ref(),
        // a live source or a person watching: every row as soon as it is known
        flush_rows: stdin || (to_file.is_none() && std::io::stdout().is_terminal()),
    };
    let mut trace = a.plot.as_ref().map(|_| TiltTrace::new(20_000));
    let (rep, gaps) = if stdin {
        let input: Box<dyn std::io::Read> = Box::new(std::io::stdin().lock());
        let mut reader = ImuCsvReader::new(input, "<stdin>", &opts)?;
        let rep = write_out(&a, &mut reader, &config, &fuse_opts, trace.as_mut())?;
        (rep, reader.gaps().describe())
    } else {
        // CSV or Parquet, by the extension
        let mut reader = ImuCsvReader::from_path(&a.input, &opts)?;
        let rep = write_out(&a, &mut reader, &config, &fuse_opts, trace.as_mut())?;
        (rep, reader.gaps().describe())
    };
    bar.finish_and_clear();
    if let Some(g) = gaps {
        eprintln!("clino fuse: warning: {}: {g}", a.input.display());
    }
    if let Some(t) = &rep.timing {
        eprintln!(
            "clino fuse: the sensor's timing as the recording notes it (clino stream): {} (a --filter that names sensor_delay_periods or gyro_lag_s overrides it)",
            t.note_text()
        );
    }
    if rep.bad_timing_note {
        eprintln!(
            "clino fuse: warning: {}: its clino.sensor_timing note does not read as sensor_delay_periods=…,gyro_lag_s=… (numbers in the filter's ranges) and was not taken",
            a.input.display()
        );
    }
    if rep.late_note {
        eprintln!(
            "clino fuse: warning: {}: a clino.* note after the first sample row (a sensor reset to other settings mid-recording?) was not taken",
            a.input.display()
        );
    }
    if let (Some(path), Some(trace)) = (&a.plot, &trace) {
        let title = format!("{} — {}", a.input.display(), config.label());
        trace.plot(path, &title)?;
        eprintln!("clino fuse: plot written to {}", path.display());
    }
    if let Some(m) = &rep.mount {
        eprintln!("{}", mount_summary(m, config.lever_auto));
    }
    if let Some(e) = &rep.sensor_errors
        && e.rest_pairs > 0
    {
        eprintln!("{}", sensor_error_summary(e));
    }
    eprintln!("{}", summary(&rep, &config.label()));
    if let Some(hint) = rail_hint(&rep, &config.sensor_range) {
        eprintln!("{hint}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A given arm whose model does not hold (the point on the axis moves):
    /// the bias estimate printed was not removed, and the summary says so,
    /// where it had printed the estimate as if it had been.
    #[test]
    fn a_given_arm_whose_bias_was_not_applied_says_so() {
        let m = clino::fusion::MountReport {
            noise_sigma_m_s2: 0.43,
            lever_applied: true,
            bias_applied: false,
            ..Default::default()
        };
        let s = mount_summary(&m, false);
        assert!(s.contains("bias estimate NOT applied"), "{s}");
        assert!(s.contains("leave 0.430 m/s²"), "{s}");
        let applied = clino::fusion::MountReport {
            bias_applied: true,
            ..m
        };
        assert!(!mount_summary(&applied, false).contains("NOT applied"));
    }
}
