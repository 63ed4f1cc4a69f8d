//! Simulation: truth trajectories ([`Motion`]) and, from them, sensor readings.
//!
//! A [`Motion`] gives the exact kinematics at any time ([`Truth`]); an IMU
//! error model turns truth into [`clino_core::ImuSample`]s.

pub mod slewing;

use clino_core::{Attitude, Vec3};

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
