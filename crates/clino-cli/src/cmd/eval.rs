//! `clino eval`: score filters against a reference orientation (BROAD's inclination error).

use std::path::PathBuf;

use clino::eval::evaluate;
use clino::fusion::{FilterConfig, FilterKind};

use super::{GainArgs, ReadArgs};

/// Arguments of `clino eval`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Recordings with ref_qw..ref_qz and movement columns; a directory means every *.csv inside, sorted.
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// Filters to score, comma-separated (poisson,complementary,mahony,madgwick) or `all`.
    #[arg(long, short = 'f', default_value = "all")]
    pub filter: String,
    /// Print machine-readable JSON to stdout instead of the table.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub read: ReadArgs,
    #[command(flatten)]
    pub gains: GainArgs,
}

/// Run `clino eval`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let opts = a.read.options()?;
    let gains = a.gains.gains()?;
    let configs: Vec<FilterConfig> = FilterKind::parse_list(&a.filter)?
        .into_iter()
        .map(|k| FilterConfig::new(k).with_gains(gains))
        .collect();
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
