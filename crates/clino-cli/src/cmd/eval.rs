//! `clino eval`: score filters against a reference orientation (BROAD's inclination error).

use std::path::PathBuf;

use clino::eval::{eval_configs, evaluate};
use clino::fusion::{FilterKind, apply_params, parse_spec_list};

use super::{GainArgs, ReadArgs, StageArgs};

/// Arguments of `clino eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Recordings with ref_qw..ref_qz and movement columns; a directory means every *.csv inside, sorted.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Filters to score, comma-separated (poisson,complementary,mahony,madgwick,dynamic) or `all`;
    /// each may carry parameters: `dynamic:bandwidth=0.2,rest_time=2,mahony:kp=0.5`.
    #[arg(long, short = 'f', default_value = "all", long_help = clino::fusion::filter_help())]
    pub filter: String,
    /// Print machine-readable JSON to stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    /// Also print how far each recording's sensor samples lag its reference
    /// (its gyro's rate against the reference's, in ms and sample periods):
    /// the value for `dynamic:sensor_delay_periods` where the reference's
    /// time is the time wanted. (The JSON always carries it.)
    #[arg(long)]
    pub delay: bool,
    /// Recordings scored at once, one per thread (default: every core). The
    /// table and the numbers do not depend on it.
    #[arg(long, short = 'j', value_name = "N", value_parser = clap::value_parser!(u16).range(1..))]
    pub jobs: Option<u16>,
    #[command(flatten)]
    pub read: ReadArgs,
    #[command(flatten)]
    pub gains: GainArgs,
    /// --lever-arm applies to every filter; --offline adds the offline (smoothed) dynamic
    /// filter next to the real-time one.
    #[command(flatten)]
    pub stages: StageArgs,
}

/// Run `clino eval`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let opts = a.read.options()?;
    let lever_arm = a.stages.lever_arm()?;
    let mut specs = parse_spec_list(&a.filter)?;
    apply_params(&mut specs, &a.gains.params())?;
    if a.stages.offline && !specs.iter().any(|s| s.kind() == FilterKind::Dynamic) {
        anyhow::bail!("--offline smooths the dynamic filter: include it in --filter");
    }
    let range = a.stages.sensor_range()?;
    let configs: Vec<_> = eval_configs(&specs, lever_arm, a.stages.offline)?
        .into_iter()
        .map(|c| {
            c.with_sensor_range(range)
                .with_sample_clock(a.stages.stamps.recover())
                .with_timing_given(clino::fusion::names_timing(&a.filter))
        })
        .collect();
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(indicatif::ProgressStyle::with_template(
        "{bar:30} {pos}/{len} {msg}",
    )?);
    let jobs = a.jobs.map(usize::from);
    let table = evaluate(&a.paths, &configs, &opts, jobs, |done, n, p| {
        bar.set_length(n as u64);
        bar.set_position(done as u64);
        bar.set_message(p.display().to_string());
    })?;
    bar.finish_and_clear();
    for r in table.recordings.iter().filter(|r| r.timing_note_not_taken) {
        eprintln!(
            "clino eval: warning: {}: a clino.* note after the first sample, or a clino.sensor_timing note that does not read as sensor_delay_periods=…,gyro_lag_s=…, was not taken",
            r.file.display()
        );
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&table)?);
    } else {
        println!("inclination RMSE, degrees (BROAD scoring: movement = 1, finite reference)");
        print!("{}", table.to_text());
        let noted = table
            .recordings
            .iter()
            .filter(|r| r.sensor_timing.is_some())
            .count();
        if noted > 0 {
            println!(
                "({noted} recording(s) noted their sensor's timing, and the dynamic filter took it: `--json` has it per recording)"
            );
        }
        if a.delay {
            println!(
                "\nthe sensor's delay behind the reference (its gyro's rate against the reference's; n/a: too little turning to time)"
            );
            print!("{}", table.delay_text());
        }
    }
    if table.any_failed() {
        anyhow::bail!(
            "a filter gave a non-finite attitude on scored samples (marked FAILED): its score is not a number"
        );
    }
    Ok(())
}
