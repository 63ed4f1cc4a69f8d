//! One time-stamped IMU reading.

use crate::Vec3;

/// One IMU reading in SI units, body frame.
///
/// * `t_s` — time stamp, s (monotonic within a recording);
/// * `gyr_rad_s` — angular rate, rad/s;
/// * `acc_m_s2` — specific force, m/s² (a sensor at rest and level reads (0, 0, +g));
/// * `mag_ut` — magnetic flux density, µT, when the sensor has a magnetometer;
/// * `temp_c` — sensor temperature, °C, when known.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSample {
    /// Time stamp, s.
    pub t_s: f64,
    /// Body angular rate, rad/s.
    pub gyr_rad_s: Vec3,
    /// Specific force, m/s².
    pub acc_m_s2: Vec3,
    /// Magnetic flux density, µT.
    pub mag_ut: Option<Vec3>,
    /// Temperature, °C.
    pub temp_c: Option<f64>,
}

impl ImuSample {
    /// A 6-D sample (gyro and accelerometer only).
    pub fn new(t_s: f64, gyr_rad_s: Vec3, acc_m_s2: Vec3) -> Self {
        Self {
            t_s,
            gyr_rad_s,
            acc_m_s2,
            mag_ut: None,
            temp_c: None,
        }
    }

    /// True when time, gyro and accelerometer are all finite (the magnetometer
    /// and temperature, being optional, are not checked).
    pub fn is_finite(&self) -> bool {
        self.t_s.is_finite()
            && self.gyr_rad_s.iter().all(|v| v.is_finite())
            && self.acc_m_s2.iter().all(|v| v.is_finite())
    }
}
