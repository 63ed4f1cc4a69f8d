//! # clino-core — the part of clino that runs on the device
//!
//! `clino-core` is `#![no_std]` and allocates nothing. It holds what a
//! gyro-aided dynamic inclinometer computes sample by sample:
//!
//! * [`sample`] — one time-stamped IMU reading ([`ImuSample`]);
//! * [`filter`] — attitude filters behind one trait ([`AttitudeFilter`]):
//!   strapdown integration of the Poisson equation, the complementary filter
//!   of the MPU6050 + Arduino inclinometer, Mahony, Madgwick, and clino's own
//!   [`filter::Dynamic`] (bounded-velocity tilt loop with bias, rest and rate adaptation);
//! * [`clock`] — the sensor's sample clock recovered from time stamps a host
//!   made ([`clock::SampleClock`]);
//! * [`compensate`] — lever-arm (tangential r·dω/dt and centripetal ω×(ω×r))
//!   correction of the accelerometer before fusion;
//! * [`tilt`] — every tilt convention of the field in one place;
//! * [`protocol`] — the serial wire protocol of clino's boards (COBS frames
//!   with a CRC, a streaming decoder, counts → SI);
//! * [`pipeline`] — calibrate → compensate → filter → tilt per sample
//!   ([`Pipeline`]): the only loop that runs a filter, on a device or a laptop.
//!
//! ## Conventions (fixed for all of clino)
//!
//! * SI units inside: s, rad, rad/s, m/s², µT, °C. Degrees only at the edges.
//! * Navigation frame East-North-Up (z up). Body frame right-handed, z up when
//!   the sensor lies level.
//! * Accelerometers measure **specific force**: at rest and level they read
//!   (0, 0, +g). Gyroscopes read the body angular rate in rad/s.
//! * Quaternions are Hamilton, scalar first (w, x, y, z), and rotate body
//!   vectors into the navigation frame: v_n = q ⊗ v_b ⊗ q*. The type is
//!   [`Attitude`] (nalgebra's `UnitQuaternion<f64>`).
//! * Standard gravity [`G0`] = 9.80665 m/s² unless the user gives local g.
//! * Arithmetic is `f64`: on Cortex-M4F class parts this is software floating
//!   point, which still runs well above 1 kHz sample rates; on desktop it
//!   removes any doubt that rounding affects a benchmark.
//!
//! ## Example
//!
//! ```
//! use clino_core::{AttitudeFilter, filter::Mahony, tilt, G0};
//! use nalgebra::Vector3;
//!
//! // A sensor resting with 10° roll: specific force is g·(0, sin 10°, cos 10°).
//! let roll = 10f64.to_radians();
//! let acc = Vector3::new(0.0, G0 * roll.sin(), G0 * roll.cos());
//! let gyr = Vector3::zeros();
//! let mut f = Mahony::default();
//! for _ in 0..200 {
//!     f.update(gyr, acc, 0.01);
//! }
//! let t = tilt::RollPitch::from_attitude(&f.attitude());
//! assert!((t.roll - roll).abs() < 1e-9);
//! assert!(t.pitch.abs() < 1e-9);
//! ```
#![no_std]
#![deny(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

pub mod clock;
pub mod compensate;
pub mod filter;
pub(crate) mod math;
pub mod pipeline;
pub mod protocol;
pub mod sample;
pub mod sensor;
pub mod tilt;

pub use filter::{AttitudeFilter, FilterKind, FilterSpec, Step};
pub use pipeline::Pipeline;
pub use sample::ImuSample;

/// An attitude: the unit quaternion that rotates body vectors into the
/// East-North-Up navigation frame (Hamilton, scalar first).
pub type Attitude = nalgebra::UnitQuaternion<f64>;

/// Three-vector of `f64` (body or navigation frame; the name of the binding says which).
pub type Vec3 = nalgebra::Vector3<f64>;

/// Standard gravity, m/s² (CGPM 1901; ISO 80000-3).
pub const G0: f64 = 9.806_65;
