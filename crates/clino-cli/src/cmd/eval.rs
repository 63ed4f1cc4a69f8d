//! `clino eval`: score filters against a reference orientation (BROAD's inclination error).

use std::path::PathBuf;

use clino::eval::evaluate;
use clino::fusion::{FilterConfig, FilterKind};

use super::{GainArgs, ReadArgs, StageArgs};

/// Arguments of `clino eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Recordings with ref_qw..ref_qz and movement columns; a directory means every *.csv inside, sorted.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Filters to score, comma-separated (poisson,complementary,mahony,madgwick,dynamic) or `all`.
    #[arg(long, short = 'f', default_value = "all")]
    pub filter: String,
    /// Print machine-readable JSON to stdout instead of the table.
    #[arg(long)]
    pub json: bool,
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
    let gains = a.gains.gains()?;
    let lever_arm = a.stages.lever_arm()?;
    let kinds = FilterKind::parse_list(&a.filter)?;
    if a.stages.offline && !kinds.contains(&FilterKind::Dynamic) {
        anyhow::bail!("--offline smooths the dynamic filter: include it in --filter");
    }
    let mut configs: Vec<FilterConfig> = Vec::new();
    for k in kinds {
        let c = FilterConfig::new(k)
            .with_gains(gains)
            .with_lever_arm(lever_arm);
        configs.push(c);
        if a.stages.offline && k == FilterKind::Dynamic {
            configs.push(c.with_offline(true));
        }
    }
    for c in &configs {
        c.build()?;
    }
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(indicatif::ProgressStyle::with_template(
        "{bar:30} {pos}/{len} {msg}",
    )?);
    let table = evaluate(&a.paths, &configs, &opts, |i, n, p| {
        bar.set_length(n as u64);
        bar.set_position(i as u64);
        bar.set_message(p.display().to_string());
    })?;
    bar.finish_and_clear();
    if a.json {
        println!("{}", serde_json::to_string_pretty(&table)?);
    } else {
        println!("inclination RMSE, degrees (BROAD scoring: movement = 1, finite reference)");
        print!("{}", table.to_text());
    }
    Ok(())
}
