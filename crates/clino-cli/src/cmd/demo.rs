//! `clino demo`: the embedded default.

/// Arguments of `clino demo`.
#[derive(clap::Args)]
pub struct Args {}

/// Run the demo: print the library's demo text.
pub fn run(_a: Args) -> anyhow::Result<()> {
    println!("clino demo — built-in data, no files, no hardware\n");
    print!("{}", clino::demo::summary()?);
    Ok(())
}
