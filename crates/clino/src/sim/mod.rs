//! Simulation: truth trajectories ([`Motion`]) and, from them, sensor readings.
//!
//! A [`Motion`] gives the exact kinematics at any time ([`Truth`]); an IMU
//! error model ([`ImuModel`]) turns truth into [`clino_core::ImuSample`]s.
//!
//! * [`motion`] — analytic motions: static, conical (about x, y, z), positional
//!   orbits, and sums of them;
//! * [`imu`] — the IMU error model, its presets (`ideal`, `mpu6050`,
//!   `mpu6050-raw`) and the seeded simulator ([`ImuModel::simulate`],
//!   [`ImuModel::stream`]);
//! * [`platform`] — the actual (servo-filtered) motion of a platform, as a [`Motion`];
//! * [`calib`] — a seeded generator of miscalibrated recordings (accelerometer, gyro,
//!   magnetometer poses and rate-table runs) with their truth;
//! * [`stewart`] — 6-UPS Stewart platform: geometry, inverse and forward
//!   kinematics, servo legs.
//!
//! ```
//! use clino::sim::{ImuModel, motion::Conical};
//! let cone = Conical::about_z(5f64.to_radians(), 1.0);
//! let imu = ImuModel::preset("mpu6050").unwrap();
//! let samples = imu.simulate(&cone, 200.0, 2.0, 1);
//! assert_eq!(samples.len(), 400);
//! ```

pub mod slewing;

use clino_core::{Attitude, Vec3};

pub mod calib;
pub mod hand;
pub mod imu;
pub mod motion;
pub mod platform;
pub mod stewart;

pub use imu::{Bandwidth, ImuModel, ImuStream, TempProfile, TriadErrors};

/// Exact kinematics of the sensor at one instant.
///
/// Frames: `attitude` rotates body vectors into ENU navigation; rates and
/// angular acceleration are in the body frame; position, velocity and
/// acceleration are of the sensor's own point, in the navigation frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Truth {
    /// Time, s.
    pub t_s: f64,
    /// Body-to-navigation attitude.
    pub attitude: Attitude,
    /// Body angular rate ω, rad/s (body frame).
    pub gyr_rad_s: Vec3,
    /// Body angular acceleration dω/dt, rad/s² (body frame).
    pub ang_acc_rad_s2: Vec3,
    /// Position of the sensor point, m (navigation frame).
    pub pos_m: Vec3,
    /// Velocity of the sensor point, m/s (navigation frame).
    pub vel_m_s: Vec3,
    /// Acceleration of the sensor point, m/s² (navigation frame).
    pub acc_m_s2: Vec3,
}

impl Truth {
    /// Specific force in the body frame for local gravity `g` (m/s², positive):
    /// f_b = Cᵀ·(a_n + g·e_z).
    pub fn specific_force(&self, g: f64) -> Vec3 {
        self.attitude
            .inverse_transform_vector(&(self.acc_m_s2 + Vec3::new(0.0, 0.0, g)))
    }
}

/// A truth trajectory: kinematics as a function of time.
pub trait Motion {
    /// The truth at time `t_s`.
    fn truth(&self, t_s: f64) -> Truth;
}

impl<M: Motion + ?Sized> Motion for &M {
    fn truth(&self, t_s: f64) -> Truth {
        (**self).truth(t_s)
    }
}

impl<M: Motion + ?Sized> Motion for Box<M> {
    fn truth(&self, t_s: f64) -> Truth {
        (**self).truth(t_s)
    }
}
