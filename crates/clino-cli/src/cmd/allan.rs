//! `clino allan`: Allan deviation, IEEE Std 952 readings and fitted noise terms of a static recording.

use clino::sim::ImuModel;
use clino::testbench::allan::{AxisAllan, ChannelStatus, Reading, allan_imu};
use clino::testbench::plots;
use clino::testbench::static_record::{GapPolicy, StaticRecord, read_static_record};
use serde::Serialize;
use std::path::PathBuf;

/// Arguments of `clino allan`.
#[derive(clap::Args)]
pub struct Args {
    /// Static recording (CSV: t_s, gyr_*_rad_s|deg_s, acc_*_m_s2|g; `#` comment lines; other columns ignored); omit with --simulate.
    recording: Option<PathBuf>,
    /// What to do with a gap in the time stamps: refuse (an error naming the line), or longest (analyse the longest gap-free segment).
    #[arg(long, default_value = "refuse")]
    gaps: String,
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

#[derive(Serialize)]
struct Output<'a> {
    file: Option<String>,
    rate_hz: f64,
    samples: usize,
    duration_s: f64,
    confidence: f64,
    record: Option<&'a StaticRecord>,
    warnings: Vec<String>,
    axes: &'a [AxisAllan],
}

/// Run `clino allan`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let policy: GapPolicy = a.gaps.parse()?;
    let (record, samples, rate) = match (&a.recording, &a.simulate) {
        (Some(p), None) => {
            let r = read_static_record(p, policy)?;
            r.require(clino::testbench::allan::MIN_SAMPLES, "an Allan analysis")?;
            let (s, rate) = (r.samples.clone(), r.rate_hz);
            (Some(r), s, rate)
        }
        (None, Some(name)) => {
            let m = ImuModel::preset(name)?;
            m.validate()?;
            (
                None,
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
    let axes = allan_imu(&samples, rate).map_err(|e| match &record {
        Some(r) if e.file.is_none() => e.in_file(&r.file),
        _ => e,
    })?;
    let mut warnings: Vec<String> = record.iter().flat_map(|r| r.notes.clone()).collect();
    for ax in &axes {
        if ax.status != ChannelStatus::Ok {
            warnings.push(format!(
                "{}: {}",
                ax.axis,
                ax.reason.clone().unwrap_or_default()
            ));
        }
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    if let Some(p) = &a.plot {
        plots::allan_plot(p, &axes)?;
    }
    let duration_s = samples.len() as f64 / rate;
    if a.json {
        let out = Output {
            file: record.as_ref().map(|r| r.file.display().to_string()),
            rate_hz: rate,
            samples: samples.len(),
            duration_s,
            confidence: clino::testbench::allan::CONFIDENCE,
            record: record.as_ref(),
            warnings,
            axes: &axes,
        };
        println!("{}", serde_json::to_string_pretty(&out)?);
        return Ok(());
    }
    println!(
        "{} samples at {rate:.3} Hz ({duration_s:.1} s); 99 % intervals [lo, hi]",
        samples.len()
    );
    let f = |r: &Reading| {
        r.estimate.map_or("-".to_string(), |e| {
            format!("{:.3e} [{:.3e}, {:.3e}]", e.value, e.lo, e.hi)
        })
    };
    println!(
        "\nIEEE 952 readings: N from the -1/2 line at 1 s, B = min/0.664, K from the +1/2 line at 3 s"
    );
    println!(
        "axis   unit    N (u/sqrt(Hz))                       B (u)                                at tau (s)  K (u/sqrt(s))"
    );
    let mut notes = Vec::new();
    for ax in &axes {
        let r = &ax.ieee952;
        println!(
            "{:<6} {:<7} {:<36} {:<36} {:<11} {}",
            ax.axis,
            ax.unit,
            f(&r.n),
            f(&r.b),
            r.b_tau_s.map_or("-".into(), |t| format!("{t:.3}")),
            f(&r.k)
        );
        if ax.status == ChannelStatus::Ok {
            for (name, t) in [("N", &r.n), ("B", &r.b), ("K", &r.k)] {
                if let Some(why) = &t.reason {
                    notes.push(format!("{} reading {name}: {why}", ax.axis));
                }
            }
        }
    }
    println!(
        "\nfitted model sigma^2 = 3Q^2/tau^2 + N^2/tau + 0.664^2 B^2 + K^2 tau/3 + R^2 tau^2/2"
    );
    println!(
        "axis   tau range (s)     N (u/sqrt(Hz))                       B (u)                                K (u/sqrt(s))                        other"
    );
    for ax in &axes {
        let Some(fit) = &ax.fit else {
            println!("{:<6} -", ax.axis);
            continue;
        };
        let mut other = Vec::new();
        for (name, t) in [("Q", &fit.terms[0]), ("R", &fit.terms[4])] {
            if let Some(e) = t.estimate {
                other.push(format!(
                    "{name} {:.3e} [{:.3e}, {:.3e}]",
                    e.value, e.lo, e.hi
                ));
            }
        }
        if fit.inflation > 1.0 {
            other.push(format!(
                "intervals x{:.2} (model misses the curve)",
                fit.inflation
            ));
        }
        println!(
            "{:<6} {:<17} {:<36} {:<36} {:<36} {}",
            ax.axis,
            format!("{:.3}-{:.4}", fit.tau_from_s, fit.tau_to_s),
            f(&fit.terms[1]),
            f(&fit.terms[2]),
            f(&fit.terms[3]),
            other.join("; ")
        );
        if let Some(x) = &fit.excluded {
            notes.push(format!("{} fit: excluded {x}", ax.axis));
        }
    }
    if !notes.is_empty() {
        println!("\nnotes:");
        for n in notes {
            println!("  {n}");
        }
    }
    Ok(())
}
