//! `clino allan`: Allan deviation, IEEE Std 952 readings and fitted noise terms of a static recording.

use super::{GapsArg, OutputArgs, SensorArg, print_result};
use clino::report::text::allan as text;
use clino::testbench::allan::{allan_record, allan_simulated};
use clino::testbench::plots;
use clino::testbench::static_record::read_static_record;
use std::path::PathBuf;

/// Arguments of `clino allan`.
#[derive(clap::Args)]
pub struct Args {
    /// Static recording (CSV: t_s, gyr_*_rad_s|deg_s, acc_*_m_s2|g; `#` comment lines; other columns ignored); omit with --simulate.
    recording: Option<PathBuf>,
    /// What to do with a gap in the time stamps: refuse (an error naming the line), or longest (analyse the longest gap-free segment).
    #[arg(long, value_enum, default_value = "refuse")]
    gaps: GapsArg,
    /// Simulate this sensor preset at rest instead of reading a recording.
    #[arg(long, value_enum, ignore_case = true)]
    simulate: Option<SensorArg>,
    /// Simulated duration, s.
    #[arg(long, default_value_t = 3600.0)]
    duration_s: f64,
    /// Simulated sample rate, Hz (a recording's rate comes from its time stamps).
    #[arg(long, default_value_t = 100.0)]
    rate_hz: f64,
    /// Random seed of the simulation.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    // Print JSON; --plot writes a log-log plot.
    #[command(flatten)]
    output: OutputArgs,
}

/// Run `clino allan`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let report = match (&a.recording, a.simulate) {
        (Some(p), None) => allan_record(read_static_record(p, a.gaps.into())?)?,
        (None, Some(s)) => allan_simulated(&s.model(None)?, a.rate_hz, a.duration_s, a.seed)?,
        _ => anyhow::bail!("give either a RECORDING or --simulate PRESET"),
    };
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    if let Some(p) = &a.output.plot {
        plots::allan_plot(p, &report.axes)?;
    }
    print_result(a.output.json, &report, || text::allan(&report))
}
