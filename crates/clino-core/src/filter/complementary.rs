//! The complementary filter of the MPU6050 + Arduino inclinometer.

use super::poisson::dcm_to_attitude;
use super::{Admit, AttitudeFilter, Integrator, Poisson, Step, admit};
use crate::math::{ln, sqrt};
use crate::{Attitude, Vec3};
use nalgebra::Matrix3;

/// Complementary filter on direction-cosine matrices:
/// C_out = (1 − k)·C_gyro + k·C_acc, re-orthonormalised.
///
/// Source: Sapegin & Strokach, "Micromechanical inclinometer" (MPU6050 +
/// Arduino), eq 5, with the Poisson step of eqs 3–4 for C_gyro. C_acc is built
/// from the accelerometer's roll and pitch (z-y-x set) while keeping the
/// heading ψ of C_gyro: C_acc = R_z(ψ)·R_y(θ_a)·R_x(φ_a), formed from the unit
/// specific force without trigonometry. The output feeds the next gyro step.
///
/// **k is per sample**, so its meaning depends on the sample period T_s: the
/// blend is a first-order low-pass on the accelerometer attitude (high-pass on
/// the gyro) with time constant τ = −T_s / ln(1 − k) ≈ T_s/k. The paper's
/// k = 0.05 at 100 Hz is τ ≈ 0.195 s; at 285.7 Hz (BROAD) τ ≈ 0.068 s. Use
/// [`Complementary::from_time_constant`] to keep τ fixed across rates.
#[derive(Clone, Debug)]
pub struct Complementary {
    /// Blend weight of the accelerometer attitude per sample, in (0, 1].
    pub k: f64,
    gyro: Poisson,
}

impl Default for Complementary {
    /// k = 0.05 (the paper's value) with the paper's rectangle integrator.
    fn default() -> Self {
        Self::new(0.05)
    }
}

impl Complementary {
    /// A filter with blend weight `k` (clamped to [0, 1]) and the rectangle integrator.
    pub fn new(k: f64) -> Self {
        Self::with_integrator(k, Integrator::Rectangle)
    }

    /// A filter with blend weight `k` and a chosen integrator for C_gyro.
    pub fn with_integrator(k: f64, integrator: Integrator) -> Self {
        Self {
            k: if k.is_finite() {
                k.clamp(0.0, 1.0)
            } else {
                0.05
            },
            gyro: Poisson::new(integrator),
        }
    }

    /// The k that gives time constant `tau_s` at sample period `ts_s`: k = 1 − exp(−T_s/τ).
    pub fn k_for(tau_s: f64, ts_s: f64) -> f64 {
        1.0 - crate::math::exp(-ts_s / tau_s)
    }

    /// A filter with time constant `tau_s` at sample period `ts_s`.
    pub fn from_time_constant(tau_s: f64, ts_s: f64) -> Self {
        Self::new(Self::k_for(tau_s, ts_s))
    }

    /// The time constant τ = −T_s / ln(1 − k) of this filter at sample period `ts_s`.
    pub fn time_constant(&self, ts_s: f64) -> f64 {
        -ts_s / ln(1.0 - self.k)
    }

    /// C_acc = R_z(ψ)·R_y(θ_a)·R_x(φ_a): accelerometer tilt with the heading ψ of `c`.
    /// Returns `None` for a zero or non-finite specific force.
    pub fn acc_dcm(c: &Matrix3<f64>, acc: &Vec3) -> Option<Matrix3<f64>> {
        let n = acc.norm();
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let a = acc / n;
        // heading of c (z-y-x): C00 = cψ·cθ, C10 = sψ·cθ
        let h = sqrt(c[(0, 0)] * c[(0, 0)] + c[(1, 0)] * c[(1, 0)]);
        let (cpsi, spsi) = if h > 1e-9 {
            (c[(0, 0)] / h, c[(1, 0)] / h)
        } else {
            (1.0, 0.0)
        };
        // M = R_y(θ)·R_x(φ) from the unit specific force (its third row is â)
        let ct = sqrt(a.y * a.y + a.z * a.z);
        let st = -a.x;
        let (cf, sf) = if ct > 1e-9 {
            (a.z / ct, a.y / ct)
        } else {
            (1.0, 0.0)
        };
        let m = Matrix3::new(ct, st * sf, st * cf, 0.0, cf, -sf, -st, ct * sf, ct * cf);
        let mut out = m;
        for j in 0..3 {
            out[(0, j)] = cpsi * m[(0, j)] - spsi * m[(1, j)];
            out[(1, j)] = spsi * m[(0, j)] + cpsi * m[(1, j)];
        }
        Some(out)
    }
}

impl AttitudeFilter for Complementary {
    fn name(&self) -> &'static str {
        "complementary"
    }

    fn update(&mut self, gyr: Vec3, acc: Vec3, dt: f64) -> Step {
        match admit(&gyr, &acc, dt, self.gyro.is_initialised()) {
            Admit::Run => {}
            Admit::Init(q) => {
                self.gyro = Poisson::with_attitude(self.gyro.integrator, &q);
                return Step::Initialised;
            }
            Admit::Reject => return Step::Rejected,
            Admit::Wait => return Step::Waiting,
        }
        self.gyro.step_raw(gyr * dt);
        let c = *self.gyro.dcm();
        match Self::acc_dcm(&c, &acc) {
            Some(ca) => {
                // The gyro step leaves C off-orthogonal by |φ|²/2 (rectangle) and the
                // blend of two nearby rotations adds about k(1−k)·δ²/2 for an angle δ
                // between them; one pass of the quadratically convergent iteration
                // leaves ≈ 1.5·(that)², and the next sample starts from there, so
                // the error never accumulates.
                let b = (1.0 - self.k) * c + self.k * ca;
                let blended = b + 0.5 * (Matrix3::identity() - b * b.transpose()) * b;
                self.gyro = Poisson::with_dcm(self.gyro.integrator, blended);
                Step::Fused
            }
            None => {
                self.gyro =
                    Poisson::with_dcm(self.gyro.integrator, super::poisson::orthonormalise(&c));
                Step::GyroOnly
            }
        }
    }

    fn attitude(&self) -> Attitude {
        dcm_to_attitude(self.gyro.dcm())
    }

    fn is_initialised(&self) -> bool {
        self.gyro.is_initialised()
    }

    fn reset(&mut self) {
        self.gyro.reset();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tilt::RollPitch;
    use approx::assert_relative_eq;
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn acc_dcm_has_accelerometer_tilt_and_gyro_heading() {
        let truth = UnitQuaternion::from_euler_angles(0.3, -0.5, 1.2);
        let c = *UnitQuaternion::from_euler_angles(0.1, 0.1, 1.2)
            .to_rotation_matrix()
            .matrix();
        let acc = crate::tilt::up_in_body(&truth) * 9.81;
        let ca = Complementary::acc_dcm(&c, &acc).unwrap();
        let expected = truth.to_rotation_matrix();
        assert_relative_eq!(ca, *expected.matrix(), epsilon = 1e-12);
    }

    #[test]
    fn time_constant_round_trip() {
        let ts = 0.01;
        let f = Complementary::from_time_constant(0.5, ts);
        assert_relative_eq!(f.time_constant(ts), 0.5, max_relative = 1e-12);
        assert_relative_eq!(
            Complementary::new(0.05).time_constant(0.01),
            0.194_957,
            max_relative = 1e-5
        );
    }

    #[test]
    fn converges_to_static_tilt_and_removes_gyro_bias_effect_partially() {
        let truth = UnitQuaternion::from_euler_angles(0.2, 0.1, 0.0);
        let acc = crate::tilt::up_in_body(&truth) * 9.81;
        let mut f = Complementary::default();
        f.update(Vector3::zeros(), Vector3::new(0.0, 0.0, 9.81), 0.01);
        let bias = Vector3::new(0.01, 0.0, 0.0);
        for _ in 0..2000 {
            f.update(bias, acc, 0.01);
        }
        let rp = RollPitch::from_attitude(&f.attitude());
        // steady-state error of a first-order loop: bias·T_s·(1−k)/k
        let expected = 0.01 * 0.01 * 0.95 / 0.05;
        assert!((rp.roll - 0.2 - expected).abs() < 2e-4, "roll {}", rp.roll);
        assert!((rp.pitch - 0.1).abs() < 1e-3);
    }
}
