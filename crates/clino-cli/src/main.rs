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
    /// Run an attitude filter over a recording: CSV in, attitude and tilt CSV out.
    Fuse(cmd::fuse::Args),
    /// Score filters against a reference orientation: inclination RMSE in degrees.
    Eval(cmd::eval::Args),
}

fn main() -> std::process::ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => cmd::demo::run(a),
        Command::Fuse(a) => cmd::fuse::run(a),
        Command::Eval(a) => cmd::eval::run(a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("clino: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
