//! `clino demo`: the embedded default.

/// Arguments of `clino demo`.
#[derive(clap::Args)]
pub struct Args {}

/// Run the demo.
pub fn run(_a: Args) -> anyhow::Result<()> {
    println!("clino demo");
    Ok(())
}
