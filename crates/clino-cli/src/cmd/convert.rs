//! `clino convert`: a recording from CSV to Parquet or back.

use std::path::PathBuf;

/// Arguments of `clino convert`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input table: CSV or Parquet (by the `.parquet` extension).
    pub input: PathBuf,
    /// Output table: Parquet when the name ends in `.parquet`, CSV otherwise.
    pub output: PathBuf,
    /// Columns copied as text rather than numbers (comma-separated), e.g. `status`.
    #[arg(long, value_delimiter = ',')]
    pub text: Vec<String>,
}

/// Run `clino convert`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let text: Vec<&str> = a.text.iter().map(String::as_str).collect();
    let rows = clino::io::convert(&a.input, &a.output, &text)?;
    eprintln!(
        "clino convert: {rows} rows from {} to {}",
        a.input.display(),
        a.output.display()
    );
    Ok(())
}
