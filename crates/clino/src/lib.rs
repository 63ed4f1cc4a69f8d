//! # clino — the std layer of the clino inclinometer toolkit
//!
//! Everything that needs files, allocation or solvers, on top of
//! [`clino_core`] (re-exported as [`core`]):
//!
//! * [`io`] — recordings in (CSV, columns found by header name) and results out;
//! * [`fusion`] — the fusion stage: filter registry, streaming CSV → CSV run;
//! * [`batch`] — recordings held as arrays (NumPy) through the one pipeline, per-recording summaries;
//! * [`eval`] — scoring attitude estimates against a reference (BROAD's inclination error);
//! * [`demo`] — the built-in demonstration (embedded data, no files);
//! * [`error`] — one error type that names the file, line and column;
//! * [`report`] — plots (SVG/PNG);
//! * [`sim`] — truth trajectories, simulated sensors, Stewart platform;
//! * [`mod@testbench`] — dynamic and static test analysis (sine fits, sensitivities,
//!   cross-coupling, Allan deviation);
//! * [`smooth`] — offline (forward–backward) tilt for whole recordings;
//! * [`calib`] — estimating sensor calibrations (static poses, multi-position fits, calibration files);
//! * [`survey`] — drilling surveys: inclination, azimuth, toolface, roll-test QC, minimum curvature;
//! * [`redundancy`] — nine-chain six-axis accelerometer with a gyro: decoupling, fault diagnosis, restoration.
//!
//! Conventions are those of [`clino_core`]: SI units inside, ENU navigation
//! frame, Hamilton scalar-first quaternions rotating body to navigation,
//! accelerometers reading specific force.
#![deny(missing_docs)]

pub use clino_core as core;
/// The MPU6050 driver of the I²C source ([`io::source::I2cSource`]): ranges, filter, address.
pub use clino_mpu6050 as mpu6050;

pub mod batch;
pub mod calib;
pub mod demo;
pub mod error;
pub mod eval;
pub mod fusion;
pub mod io;
pub mod redundancy;
pub mod report;
pub mod sim;
pub mod smooth;
pub mod stream;
pub mod survey;
pub mod testbench;

pub use error::{Error, ErrorKind, Result};
