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
    /// Nine-chain six-axis accelerometer with a gyro: restorable sets, fault simulation, diagnosis.
    Redundancy(cmd::redundancy::Args),
    /// Dynamic test bench: conical response, orbit cross-coupling, static test, lab analysis.
    Testbench(cmd::testbench::Args),
    /// Allan deviation and IEEE 952 noise terms of a static recording.
    Allan(cmd::allan::Args),
    /// Stewart-platform kinematics (inverse and forward) of single poses.
    Stewart(cmd::stewart::Args),
    /// Calibrate accelerometer, gyro or magnetometer triads from recordings, or apply a calibration.
    Calibrate(cmd::calibrate::Args),
    /// Drilling survey: inclination, azimuth, toolface, roll-test QC, minimum-curvature trajectory.
    Survey(cmd::survey::Args),
    /// Convert a recording between CSV and Parquet (same column names).
    Convert(cmd::convert::Args),
    /// Live: a board on a serial port (clino's protocol) or a replayed recording through the filter.
    Stream(cmd::stream::Args),
}

fn main() -> std::process::ExitCode {
    // A closed output pipe (`clino eval … --json | head`) ends the process
    // quietly, as for any Unix filter, instead of a write error or panic.
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to its default at start-up, before
    // any thread exists, has no preconditions.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Demo(a) => cmd::demo::run(a),
        Command::Fuse(a) => cmd::fuse::run(a),
        Command::Eval(a) => cmd::eval::run(a),
        Command::Redundancy(a) => cmd::redundancy::run(a),
        Command::Testbench(a) => cmd::testbench::run(a),
        Command::Allan(a) => cmd::allan::run(a),
        Command::Stewart(a) => cmd::stewart::run(a),
        Command::Calibrate(a) => cmd::calibrate::run(a),
        Command::Survey(a) => cmd::survey::run(a),
        Command::Convert(a) => cmd::convert::run(a),
        Command::Stream(a) => cmd::stream::run(a),
    };
    match result {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("clino: error: {e:#}");
            std::process::ExitCode::FAILURE
        }
    }
}
