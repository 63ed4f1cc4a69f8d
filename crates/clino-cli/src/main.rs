//! `clino`: the command-line tool. Thin subcommands over the `clino` library.

use clap::{Parser, Subcommand};

mod cmd;

/// clino — gyro-aided dynamic inclinometers: fuse, evaluate, calibrate, survey, test.
#[derive(Parser)]
#[command(name = "clino", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the built-in demonstration (no files, no hardware).
    Demo(cmd::demo::Args),
    /// Nine-chain six-axis accelerometer with a gyro: restorable sets, fault simulation, diagnosis.
    Redundancy(cmd::redundancy::Args),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => cmd::demo::run(a),
        Command::Redundancy(a) => cmd::redundancy::run(a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("clino: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
