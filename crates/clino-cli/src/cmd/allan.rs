//! `clino allan`: Allan deviation and IEEE Std 952 noise terms of a static recording.

use clino::bench::allan::allan_imu;
use clino::bench::plots;
use clino::bench::recording::Table;
use clino::sim::ImuModel;
use std::path::PathBuf;

/// Arguments of `clino allan`.
#[derive(clap::Args)]
pub struct Args {
    /// Static recording (CSV: t_s, gyr_*_rad_s|deg_s, acc_*_m_s2|g); omit with --simulate.
    recording: Option<PathBuf>,
    /// Simulate this sensor preset at rest instead of reading a recording.
    #[arg(long)]
    simulate: Option<String>,
    /// Simulated duration, s.
    #[arg(long, default_value_t = 3600.0)]
    duration_s: f64,
    /// Simulated sample rate, Hz (a recording's rate comes from its time stamps).
    #[arg(long, default_value_t = 100.0)]
    rate_hz: f64,
    /// Random seed of the simulation.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Print JSON to stdout.
    #[arg(long)]
    json: bool,
    /// Write a log-log plot (.svg or .png).
    #[arg(long)]
    plot: Option<PathBuf>,
}

/// Run `clino allan`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let (samples, rate) = match (&a.recording, &a.simulate) {
        (Some(p), None) => {
            let s = Table::read(p)?.imu_samples()?;
            anyhow::ensure!(
                s.len() >= 18,
                "{}: too few rows for an Allan deviation",
                p.display()
            );
            let rate = (s.len() - 1) as f64 / (s[s.len() - 1].t_s - s[0].t_s);
            (s, rate)
        }
        (None, Some(name)) => {
            let m = ImuModel::preset(name)?;
            m.validate()?;
            (
                m.simulate(
                    &clino::sim::motion::Static::level(),
                    a.rate_hz,
                    a.duration_s,
                    a.seed,
                ),
                a.rate_hz,
            )
        }
        _ => anyhow::bail!("give either a RECORDING or --simulate PRESET"),
    };
    let axes = allan_imu(&samples, rate)?;
    if let Some(p) = &a.plot {
        plots::allan_plot(p, &axes)?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&axes)?);
        return Ok(());
    }
    println!(
        "{} samples at {rate:.3} Hz; terms with 99 % bounds [lo, hi]",
        samples.len()
    );
    println!(
        "axis   unit    white N (u/sqrt(Hz))                 bias instability B (u)              random walk K (u/sqrt(s))"
    );
    for ax in &axes {
        let f = |t: Option<clino::bench::allan::Term>| {
            t.map_or("-".to_string(), |t| {
                format!("{:.3e} [{:.3e}, {:.3e}]", t.value, t.lo, t.hi)
            })
        };
        println!(
            "{:<6} {:<7} {:<36} {:<35} {}",
            ax.axis,
            ax.unit,
            f(ax.terms.white),
            f(ax.terms.bias_instability),
            f(ax.terms.random_walk)
        );
    }
    Ok(())
}
