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
    /// Calibrate accelerometer, gyro or magnetometer triads from recordings, or apply a calibration.
    Calibrate(cmd::calibrate::Args),
    /// Drilling survey: inclination, azimuth, toolface, roll-test QC, minimum-curvature trajectory.
    Survey(cmd::survey::Args),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => cmd::demo::run(a),
        Command::Calibrate(a) => cmd::calibrate::run(a),
        Command::Survey(a) => cmd::survey::run(a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("clino: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
