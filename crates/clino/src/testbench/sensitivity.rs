//! Sensitivities under the conical motion about z, and their dB values.
//!
//! Source: Liu, Cai, Yang, Zhang, "Testing of a MEMS Dynamic Inclinometer
//! Using the Stewart Platform", Sensors 2019. Y is the fitted amplitude of
//! the instrument's output at the cone frequency ([`super::sinefit`]), α the
//! cone angle, ω = 2πf its angular frequency. A perfect instrument has S = 1
//! (0 dB); `20·log10 S` is the amplitude-frequency curve.

/// Gyro x or y sensitivity S = Y/(ω·sin α) (eq 6; the rate amplitude of eq 2).
pub fn gyro(y_rad_s: f64, omega_rad_s: f64, alpha_rad: f64) -> f64 {
    y_rad_s / (omega_rad_s * alpha_rad.sin())
}

/// Accelerometer x or y sensitivity S = Y/(g·sin α) (eq 7; the specific-force amplitude of eq 3).
pub fn accel(y_m_s2: f64, g_m_s2: f64, alpha_rad: f64) -> f64 {
    y_m_s2 / (g_m_s2 * alpha_rad.sin())
}

/// Tilt sensitivity from the quaternion components (x or y of
/// [`clino_core::tilt::QuatTilt`]): S = Y/sin(α/2) (eq 8).
pub fn quat_tilt(y: f64, alpha_rad: f64) -> f64 {
    y / (0.5 * alpha_rad).sin()
}

/// Tilt sensitivity of the sin φ output of the z-x-y set
/// ([`clino_core::tilt::ZxyTilt::sin_phi`]): S = Y/sin α (eqs 10–11).
pub fn sin_phi(y: f64, alpha_rad: f64) -> f64 {
    y / alpha_rad.sin()
}

/// Tilt sensitivity of the tan θ output of the z-x-y set
/// ([`clino_core::tilt::ZxyTilt::tan_theta`]): S = Y/tan α (eqs 10–11).
pub fn tan_theta(y: f64, alpha_rad: f64) -> f64 {
    y / alpha_rad.tan()
}

/// A sensitivity in decibels: 20·log10 S.
pub fn db(s: f64) -> f64 {
    20.0 * s.log10()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Motion;
    use crate::sim::motion::Conical;
    use clino_core::tilt::{QuatTilt, ZxyTilt};

    #[test]
    fn truth_of_a_cone_has_unit_sensitivity() {
        // independent values: the truth's own extreme values over one period
        let (a, f) = (5f64.to_radians(), 0.7);
        let c = Conical::about_z(a, f);
        let w = 2.0 * std::f64::consts::PI * f;
        let mut mx = [0.0f64; 5];
        for k in 0..10000 {
            let tr = c.truth(k as f64 / (10000.0 * f));
            let up = tr.specific_force(9.8);
            let q = QuatTilt::from_attitude(&tr.attitude);
            let z = ZxyTilt::from_attitude(&tr.attitude);
            for (m, v) in mx
                .iter_mut()
                .zip([tr.gyr_rad_s.x, up.y, q.x, z.sin_phi(), z.tan_theta()])
            {
                *m = m.max(v.abs());
            }
        }
        assert!((gyro(mx[0], w, a) - 1.0).abs() < 1e-6);
        assert!((accel(mx[1], 9.8, a) - 1.0).abs() < 1e-6);
        assert!((quat_tilt(mx[2], a) - 1.0).abs() < 1e-6);
        assert!((sin_phi(mx[3], a) - 1.0).abs() < 1e-6);
        assert!((tan_theta(mx[4], a) - 1.0).abs() < 1e-6);
        assert!((db(0.66) + 3.609).abs() < 1e-3); // the paper's "66 % … 3.6 dB"
    }
}
