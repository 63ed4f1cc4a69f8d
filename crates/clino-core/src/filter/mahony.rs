//! Mahony's explicit complementary filter (proportional-integral, 6-D).

use super::{Admit, AttitudeFilter, Step, admit, renormalise};
use crate::math::sqrt;
use crate::tilt::up_in_body;
use crate::{Attitude, Vec3};
use nalgebra::Quaternion;

/// Mahony's explicit complementary filter with gyro-bias integral.
///
/// Source: R. Mahony, T. Hamel, J.-M. Pflimlin, "Nonlinear complementary
/// filters on the special orthogonal group", IEEE TAC 53(5), 2008, eq 32
/// (explicit complementary filter with bias correction), 6-D form:
///
/// e = â × v̂,  v̂ = Cᵀ·e_z (predicted up in body), â the unit specific force;
/// ∫e ← ∫e + e·dt;  ω' = ω + k_p·e + k_i·∫e;  q̇ = ½·q ⊗ (0, ω').
///
/// The bias estimate is b̂ = −k_i·∫e. Integration is the usual first-order
/// quaternion step followed by normalisation (as in Madgwick's reference C
/// code of both filters), so results compare one-to-one with other libraries.
///
/// Gains and their meaning: linearised about the true attitude, the tilt
/// error obeys a second-order loop with natural frequency ω_n = √k_i and
/// damping ζ = k_p/(2√k_i). k_p (rad/s) is the crossover frequency between
/// gyro and accelerometer, 1/k_p the time constant over which the
/// accelerometer pulls the tilt; k_i (rad/s²) sets how fast bias is learnt.
/// Defaults k_p = 1 rad/s (τ = 1 s: accelerations shorter than a second are
/// mostly rejected, a 1°/s bias leaves ≈1° before the integral takes it) and
/// k_i = 0.02 rad/s² (ζ ≈ 3.5, bias learnt in ≈ k_p/k_i = 50 s).
#[derive(Clone, Debug)]
pub struct Mahony {
    /// Proportional gain k_p, rad/s.
    pub kp: f64,
    /// Integral gain k_i, rad/s².
    pub ki: f64,
    q: Attitude,
    integral: Vec3,
    initialised: bool,
}

impl Default for Mahony {
    fn default() -> Self {
        Self::new(1.0, 0.02)
    }
}

impl Mahony {
    /// A new filter with gains k_p (rad/s) and k_i (rad/s²).
    pub fn new(kp: f64, ki: f64) -> Self {
        Self {
            kp,
            ki,
            q: Attitude::identity(),
            integral: Vec3::zeros(),
            initialised: false,
        }
    }

    /// Start from a known attitude.
    pub fn set_attitude(&mut self, q: Attitude) {
        self.q = q;
        self.initialised = true;
    }
}

impl AttitudeFilter for Mahony {
    fn name(&self) -> &'static str {
        "mahony"
    }

    fn update(&mut self, gyr: Vec3, acc: Vec3, dt: f64) -> Step {
        match admit(&gyr, &acc, dt, self.initialised) {
            Admit::Run => {}
            Admit::Init(q) => {
                self.set_attitude(q);
                return Step::Initialised;
            }
            Admit::Reject => return Step::Rejected,
            Admit::Wait => return Step::Waiting,
        }
        let n2 = acc.norm_squared();
        let mut w = gyr;
        let step = if n2 > 0.0 {
            let a = acc / sqrt(n2);
            let v = up_in_body(&self.q);
            let e = a.cross(&v);
            if self.ki > 0.0 {
                self.integral += e * dt;
                w += self.integral * self.ki;
            }
            w += e * self.kp;
            Step::Fused
        } else {
            if self.ki > 0.0 {
                w += self.integral * self.ki;
            }
            Step::GyroOnly
        };
        let q = self.q.quaternion();
        let qdot = q * Quaternion::new(0.0, w.x, w.y, w.z) * 0.5;
        self.q = renormalise(q + qdot * dt);
        step
    }

    fn attitude(&self) -> Attitude {
        self.q
    }

    fn is_initialised(&self) -> bool {
        self.initialised
    }

    fn reset(&mut self) {
        self.q = Attitude::identity();
        self.integral = Vec3::zeros();
        self.initialised = false;
    }

    fn gyro_bias(&self) -> Vec3 {
        -self.integral * self.ki
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tilt::inclination;
    use approx::assert_relative_eq;
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn learns_gyro_bias_at_rest() {
        let truth = UnitQuaternion::from_euler_angles(0.3, -0.2, 0.0);
        let acc = up_in_body(&truth) * 9.81;
        let bias = Vector3::new(0.02, -0.01, 0.0);
        let mut f = Mahony::default();
        for _ in 0..100_000 {
            f.update(bias, acc, 0.01);
        }
        // the horizontal bias components are observable from gravity; the
        // one along gravity is not. Compare the part perpendicular to up.
        let u = up_in_body(&truth);
        let b = f.gyro_bias();
        let perp = |v: Vector3<f64>| v - u * u.dot(&v);
        assert_relative_eq!(perp(b), perp(bias), epsilon = 1e-6);
        assert!((inclination(&f.attitude()) - inclination(&truth)).abs() < 1e-6);
    }

    #[test]
    fn survives_nan_and_zero_acc() {
        let mut f = Mahony::default();
        assert_eq!(
            f.update(Vector3::zeros(), Vector3::zeros(), 0.01),
            Step::Waiting
        );
        assert_eq!(
            f.update(Vector3::zeros(), Vector3::new(0.0, 1.0, 9.8), 0.01),
            Step::Initialised
        );
        let q = f.attitude();
        assert_eq!(
            f.update(Vector3::new(0.0, f64::NAN, 0.0), Vector3::z(), 0.01),
            Step::Rejected
        );
        assert_eq!(
            f.update(
                Vector3::zeros(),
                Vector3::new(f64::INFINITY, 0.0, 0.0),
                0.01
            ),
            Step::Rejected
        );
        assert_eq!(f.attitude(), q);
        assert_eq!(
            f.update(Vector3::new(0.1, 0.0, 0.0), Vector3::zeros(), 0.01),
            Step::GyroOnly
        );
        assert!(f.attitude().angle_to(&q) > 0.0);
    }
}
