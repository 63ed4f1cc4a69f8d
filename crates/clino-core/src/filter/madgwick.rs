//! Madgwick's gradient-descent orientation filter (6-D).

use super::{Admit, AttitudeFilter, Step, admit, renormalise};
use crate::math::sqrt;
use crate::{Attitude, Vec3};
use nalgebra::Quaternion;

/// Madgwick's gradient-descent filter, IMU (6-D) form.
///
/// Source: S. Madgwick, A. Harrison, R. Vaidyanathan, "Estimation of IMU and
/// MARG orientation using a gradient descent algorithm", ICORR 2011, eqs 25–33:
/// with q = (w, x, y, z) and â the unit specific force, the objective
/// f(q) = v̂(q) − â, v̂ = (2(xz − wy), 2(wx + yz), 2(½ − x² − y²)), its gradient
/// ∇ = Jᵀ·f, and the update q̇ = ½·q ⊗ (0, ω) − β·∇/|∇|, q ← normalise(q + q̇·dt).
///
/// β (rad/s) is the rate at which the accelerometer pulls the attitude, and
/// the paper's guide β = √(3/4)·ω̃ takes it from the gyro's expected error ω̃
/// (rad/s). The default 0.1 rad/s is the reference implementation's (and the
/// Rust `ahrs` crate's): it corrects up to 5.7°/s of gyro error, so a tilt
/// error of 10° takes about 2 s to remove. There is no bias state: a constant
/// gyro bias b leaves a steady tilt offset of about |b|/β·… (the correction
/// saturates at β, so biases above β/√(3/4) are not held at all).
#[derive(Clone, Debug)]
pub struct Madgwick {
    /// Gradient-descent rate β, rad/s.
    pub beta: f64,
    q: Attitude,
    initialised: bool,
}

impl Default for Madgwick {
    fn default() -> Self {
        Self::new(0.1)
    }
}

impl Madgwick {
    /// A new filter with rate β (rad/s).
    pub fn new(beta: f64) -> Self {
        Self {
            beta,
            q: Attitude::identity(),
            initialised: false,
        }
    }

    /// Start from a known attitude.
    pub fn set_attitude(&mut self, q: Attitude) {
        self.q = q;
        self.initialised = true;
    }
}

impl AttitudeFilter for Madgwick {
    fn name(&self) -> &'static str {
        "madgwick"
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
        let q = self.q.quaternion();
        let mut qdot = q * Quaternion::new(0.0, gyr.x, gyr.y, gyr.z) * 0.5;
        let n2 = acc.norm_squared();
        let step = if n2 > 0.0 {
            let a = acc / sqrt(n2);
            let (w, x, y, z) = (q.w, q.i, q.j, q.k);
            // objective f = v̂(q) − â
            let f1 = 2.0 * (x * z - w * y) - a.x;
            let f2 = 2.0 * (w * x + y * z) - a.y;
            let f3 = 2.0 * (0.5 - x * x - y * y) - a.z;
            // ∇ = Jᵀ f
            let gw = -2.0 * y * f1 + 2.0 * x * f2;
            let gx = 2.0 * z * f1 + 2.0 * w * f2 - 4.0 * x * f3;
            let gy = -2.0 * w * f1 + 2.0 * z * f2 - 4.0 * y * f3;
            let gz = 2.0 * x * f1 + 2.0 * y * f2;
            let gn = sqrt(gw * gw + gx * gx + gy * gy + gz * gz);
            if gn > 0.0 {
                let s = self.beta / gn;
                qdot -= Quaternion::new(gw, gx, gy, gz) * s;
            }
            Step::Fused
        } else {
            Step::GyroOnly
        };
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
        self.initialised = false;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tilt::{inclination, up_in_body};
    use nalgebra::{UnitQuaternion, Vector3};

    #[test]
    fn gradient_matches_finite_difference() {
        // ∇ of ½|f|² by central differences against the closed form used above.
        let q0 = Quaternion::new(0.9, 0.2, -0.3, 0.1).normalize();
        let a = Vector3::new(0.1, 0.3, 0.95).normalize();
        let cost = |q: Quaternion<f64>| {
            let (w, x, y, z) = (q.w, q.i, q.j, q.k);
            let f = Vector3::new(
                2.0 * (x * z - w * y) - a.x,
                2.0 * (w * x + y * z) - a.y,
                2.0 * (0.5 - x * x - y * y) - a.z,
            );
            0.5 * f.norm_squared()
        };
        let (w, x, y, z) = (q0.w, q0.i, q0.j, q0.k);
        let f1 = 2.0 * (x * z - w * y) - a.x;
        let f2 = 2.0 * (w * x + y * z) - a.y;
        let f3 = 2.0 * (0.5 - x * x - y * y) - a.z;
        let g = [
            -2.0 * y * f1 + 2.0 * x * f2,
            2.0 * z * f1 + 2.0 * w * f2 - 4.0 * x * f3,
            -2.0 * w * f1 + 2.0 * z * f2 - 4.0 * y * f3,
            2.0 * x * f1 + 2.0 * y * f2,
        ];
        let h = 1e-6;
        for (i, gi) in g.iter().enumerate() {
            let mut d = Quaternion::new(0.0, 0.0, 0.0, 0.0);
            d.coords[(i + 3) % 4] = h; // coords are (x, y, z, w)
            let num = (cost(q0 + d) - cost(q0 - d)) / (2.0 * h);
            assert!((num - gi).abs() < 1e-7, "component {i}: {num} vs {gi}");
        }
    }

    #[test]
    fn converges_to_static_tilt() {
        let truth = UnitQuaternion::from_euler_angles(-0.4, 0.25, 0.0);
        let acc = up_in_body(&truth) * 9.81;
        let mut f = Madgwick::default();
        f.update(Vector3::zeros(), Vector3::new(0.0, 0.0, 9.81), 0.01);
        for _ in 0..3000 {
            f.update(Vector3::zeros(), acc, 0.01);
        }
        // the normalised gradient step keeps a limit cycle of size β·dt around the optimum
        assert!((inclination(&f.attitude()) - inclination(&truth)).abs() < 0.1 * 0.01);
    }
}
