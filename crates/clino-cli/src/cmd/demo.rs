//! `clino demo`: the embedded default.

/// Arguments of `clino demo`.
#[derive(clap::Args)]
pub struct Args {
    /// Print JSON: the fusion scores as numbers and every section's text, line by line.
    #[arg(long)]
    json: bool,
}

/// Run the demo: print the library's demo text (or its JSON form).
pub fn run(a: Args) -> anyhow::Result<()> {
    if a.json {
        println!("{}", serde_json::to_string_pretty(&clino::demo::report()?)?);
        return Ok(());
    }
    println!("clino demo — built-in data, no files, no hardware\n");
    print!("{}", clino::demo::summary()?);
    Ok(())
}
