//! The motion a sensor on a servo-driven Stewart platform actually makes.
//!
//! Source: Liu, Cai, Yang, Zhang, "Testing of a MEMS Dynamic Inclinometer
//! Using the Stewart Platform", Sensors 2019, figure 2: the commanded pose
//! becomes leg lengths (inverse kinematics), the servo legs follow them with
//! attenuation and lag, and the platform — and the sensor on it — moves with
//! the *actual* legs. [`PlatformMotion`] makes that actual motion a
//! [`Motion`], so a simulated inclinometer feels exactly what the encoders
//! report.
//!
//! The servo legs ([`ServoLegs`]) are integrated by RK4 on a 1 ms grid,
//! starting at rest on the first commanded lengths. Between grid points leg
//! lengths and rates are cubic-Hermite interpolated and leg accelerations
//! (from the servo equation) linearly. From the legs (l, l̇, l̈):
//!
//! * the pose (t, R) by forward kinematics, warm-started from the nearest
//!   grid pose (all grid poses are solved, and checked, at construction);
//! * the twist from J·[ṫ; ω] = l̇, with J the analytic Jacobian (rows
//!   [nᵢ, rᵢ × nᵢ], rᵢ = R·pᵢ);
//! * the accelerations from J·[ẗ; α] = l̈ − ṅᵢ·v̇ᵢ − nᵢ·(ω × (ω × rᵢ)),
//!   with v̇ᵢ = ṫ + ω × rᵢ and ṅᵢ = (v̇ᵢ − nᵢ(nᵢ·v̇ᵢ))/lᵢ (differentiating
//!   lᵢ = |t + R·pᵢ − bᵢ| twice).
//!
//! ω and α come out in the base (navigation) frame and are rotated into the
//! body frame (α_b = Rᵀα, since ω_b × ω_b = 0). Position is relative to the
//! home pose.

use super::stewart::{Geometry, Pose, ServoLegs};
use super::{Motion, Truth};
use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use nalgebra::SVector;

/// Grid step of the servo integration, s.
const H: f64 = 1e-3;

/// The actual motion of a servo-driven platform following a commanded motion.
#[derive(Clone, Debug)]
pub struct PlatformMotion {
    geometry: Geometry,
    x: Vec<[f64; 6]>,
    v: Vec<[f64; 6]>,
    a: Vec<[f64; 6]>,
    poses: Vec<Pose>,
    max_fk_iterations: usize,
}

impl PlatformMotion {
    /// Drive `geometry` with `servo` legs along `command` (attitude, and
    /// position about the home point) for `duration_s` (≥ 0). Fails when a
    /// commanded pose leaves the workspace or forward kinematics fails.
    pub fn new<M: Motion + ?Sized>(
        geometry: &Geometry,
        servo: &ServoLegs,
        command: &M,
        duration_s: f64,
    ) -> Result<Self> {
        if !(duration_s.is_finite() && duration_s >= 0.0) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("duration {duration_s} s"),
            ));
        }
        if !(servo.natural_hz.is_finite()
            && servo.natural_hz > 0.0
            && servo.damping.is_finite()
            && servo.damping >= 0.0)
        {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "servo natural frequency must be positive and damping non-negative",
            ));
        }
        let n = (duration_s / H).ceil() as usize + 2;
        let wn = 2.0 * std::f64::consts::PI * servo.natural_hz;
        let z = servo.damping;
        let home = geometry.home();
        let cmd_len = |t: f64| {
            let tr = command.truth(t);
            geometry.inverse(&Pose {
                pos_m: home.pos_m + tr.pos_m,
                attitude: tr.attitude,
            })
        };
        let acc = |u: f64, x: f64, v: f64| wn * wn * (u - x) - 2.0 * z * wn * v;
        let mut xs = Vec::with_capacity(n);
        let mut vs = Vec::with_capacity(n);
        let mut as_ = Vec::with_capacity(n);
        let mut x = cmd_len(0.0)?;
        let mut v = [0.0; 6];
        let mut u = x;
        for k in 0..n {
            xs.push(x);
            vs.push(v);
            as_.push(core::array::from_fn(|i| acc(u[i], x[i], v[i])));
            let ta = k as f64 * H;
            let (um, ub) = (cmd_len(ta + 0.5 * H)?, cmd_len(ta + H)?);
            for i in 0..6 {
                let (x0, v0) = (x[i], v[i]);
                let k1v = acc(u[i], x0, v0);
                let k2x = v0 + 0.5 * H * k1v;
                let k2v = acc(um[i], x0 + 0.5 * H * v0, k2x);
                let k3x = v0 + 0.5 * H * k2v;
                let k3v = acc(um[i], x0 + 0.5 * H * k2x, k3x);
                let k4x = v0 + H * k3v;
                let k4v = acc(ub[i], x0 + H * k3x, k4x);
                x[i] = x0 + H / 6.0 * (v0 + 2.0 * k2x + 2.0 * k3x + k4x);
                v[i] = v0 + H / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
            }
            u = ub;
        }
        let mut poses = Vec::with_capacity(n);
        let mut guess = home;
        let mut max_it = 0;
        for (k, l) in xs.iter().enumerate() {
            let fk = geometry.forward(l, &guess).map_err(|e| {
                let msg = format!("platform at t = {:.4} s: {}", k as f64 * H, e.message);
                Error::new(e.kind, msg)
            })?;
            max_it = max_it.max(fk.iterations);
            guess = fk.pose;
            poses.push(fk.pose);
        }
        Ok(Self {
            geometry: geometry.clone(),
            x: xs,
            v: vs,
            a: as_,
            poses,
            max_fk_iterations: max_it,
        })
    }

    /// Largest forward-kinematics iteration count over the grid.
    pub fn max_fk_iterations(&self) -> usize {
        self.max_fk_iterations
    }

    /// Last time covered, s (later times hold the final state).
    pub fn end_s(&self) -> f64 {
        (self.x.len() - 2) as f64 * H
    }

    /// Leg lengths, rates and accelerations at `t_s` (clamped to the covered span).
    pub fn legs(&self, t_s: f64) -> ([f64; 6], [f64; 6], [f64; 6]) {
        let tc = t_s.clamp(0.0, self.end_s());
        let k = ((tc / H).floor() as usize).min(self.x.len() - 2);
        let s = (tc - k as f64 * H) / H;
        let (h00, h10, h01, h11) = (
            2.0 * s.powi(3) - 3.0 * s * s + 1.0,
            s.powi(3) - 2.0 * s * s + s,
            -2.0 * s.powi(3) + 3.0 * s * s,
            s.powi(3) - s * s,
        );
        let (d00, d10, d01, d11) = (
            6.0 * s * s - 6.0 * s,
            3.0 * s * s - 4.0 * s + 1.0,
            -6.0 * s * s + 6.0 * s,
            3.0 * s * s - 2.0 * s,
        );
        let (x0, x1, v0, v1) = (self.x[k], self.x[k + 1], self.v[k], self.v[k + 1]);
        let l =
            core::array::from_fn(|i| h00 * x0[i] + h10 * H * v0[i] + h01 * x1[i] + h11 * H * v1[i]);
        let ld = core::array::from_fn(|i| {
            (d00 * x0[i] + d10 * H * v0[i] + d01 * x1[i] + d11 * H * v1[i]) / H
        });
        let ldd = core::array::from_fn(|i| (1.0 - s) * self.a[k][i] + s * self.a[k + 1][i]);
        (l, ld, ldd)
    }

    /// Actual pose at `t_s` (forward kinematics of the interpolated legs).
    pub fn pose(&self, t_s: f64) -> Pose {
        let tc = t_s.clamp(0.0, self.end_s());
        let k = ((tc / H).round() as usize).min(self.poses.len() - 1);
        let (l, _, _) = self.legs(tc);
        // the grid pose (solved and checked by the full forward kinematics at
        // construction) is at most half a step away: plain Newton steps with
        // the analytic Jacobian converge from it quadratically; the full solver
        // (with its conditioning checks) only if they did not
        let target = SVector::<f64, 6>::from_column_slice(&l);
        let mut pose = self.poses[k];
        for _ in 0..4 {
            let r =
                target - SVector::<f64, 6>::from_column_slice(&self.geometry.leg_lengths(&pose));
            if r.amax() < 1e-13 {
                return pose;
            }
            let Some(dx) = self.geometry.jacobian(&pose).lu().solve(&r) else {
                break;
            };
            pose.pos_m += Vec3::new(dx[0], dx[1], dx[2]);
            pose.attitude = clino_core::Attitude::from_scaled_axis(Vec3::new(dx[3], dx[4], dx[5]))
                * pose.attitude;
        }
        // if it ever did not converge, the grid pose itself is the best available answer
        self.geometry
            .forward(&l, &self.poses[k])
            .map_or(self.poses[k], |f| f.pose)
    }
}

impl Motion for PlatformMotion {
    fn truth(&self, t_s: f64) -> Truth {
        let pose = self.pose(t_s);
        let (l, ld, ldd) = self.legs(t_s);
        let g = &self.geometry;
        let j = g.jacobian(&pose);
        let lu = j.lu();
        let sol = |b: SVector<f64, 6>| lu.solve(&b).unwrap_or_else(SVector::<f64, 6>::zeros);
        let tw = sol(SVector::<f64, 6>::from_column_slice(&ld));
        let (tdot, w) = (
            Vec3::new(tw[0], tw[1], tw[2]),
            Vec3::new(tw[3], tw[4], tw[5]),
        );
        let mut rhs = SVector::<f64, 6>::zeros();
        for i in 0..6 {
            let r = pose.attitude.transform_vector(&g.platform_m[i]);
            let vvec = pose.pos_m + r - g.base_m[i];
            let n = vvec / l[i];
            let vd = tdot + w.cross(&r);
            let nd = (vd - n * n.dot(&vd)) / l[i];
            rhs[i] = ldd[i] - nd.dot(&vd) - n.dot(&w.cross(&w.cross(&r)));
        }
        let ac = sol(rhs);
        let (tdd, alpha) = (
            Vec3::new(ac[0], ac[1], ac[2]),
            Vec3::new(ac[3], ac[4], ac[5]),
        );
        Truth {
            t_s,
            attitude: pose.attitude,
            gyr_rad_s: pose.attitude.inverse_transform_vector(&w),
            ang_acc_rad_s2: pose.attitude.inverse_transform_vector(&alpha),
            pos_m: pose.pos_m - g.home().pos_m,
            vel_m_s: tdot,
            acc_m_s2: tdd,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::motion::{Conical, Orbit};
    use approx::assert_relative_eq;

    #[test]
    fn fast_servo_follows_the_command() {
        let g = Geometry::typical();
        let cone = Conical::about_z(3f64.to_radians(), 0.5);
        let servo = ServoLegs {
            natural_hz: 200.0,
            damping: 0.9,
        };
        let pm = PlatformMotion::new(&g, &servo, &cone, 4.0).unwrap();
        // for f ≪ f_n the legs lag by the group delay 2ζ/ω_n
        let delay = 2.0 * servo.damping / (2.0 * std::f64::consts::PI * servo.natural_hz);
        let (a, b) = (pm.truth(3.0), cone.truth(3.0 - delay));
        assert!(
            a.attitude.angle_to(&b.attitude) < 2e-5,
            "{}",
            a.attitude.angle_to(&b.attitude)
        );
        assert!((a.gyr_rad_s - b.gyr_rad_s).norm() < 1e-3 * b.gyr_rad_s.norm());
        assert!(a.attitude.angle_to(&cone.truth(3.0).attitude) > 1e-4);
        assert!(pm.max_fk_iterations() <= 5);
    }

    #[test]
    fn rates_and_accelerations_match_finite_differences_of_the_pose() {
        let g = Geometry::typical();
        let servo = ServoLegs {
            natural_hz: 6.0,
            damping: 0.5,
        };
        let m = crate::sim::motion::Sum {
            a: Conical::about_z(4f64.to_radians(), 1.3),
            b: Orbit::spatial(0.02, 0.9),
        };
        let pm = PlatformMotion::new(&g, &servo, &m, 3.0).unwrap();
        let h = 1e-4;
        for k in 0..8 {
            let t = 1.0 + 0.237 * k as f64;
            let tr = pm.truth(t);
            let (qp, qm) = (pm.truth(t + h).attitude, pm.truth(t - h).attitude);
            let dq = (qp.into_inner() - qm.into_inner()) / (2.0 * h);
            let w_fd = (tr.attitude.into_inner().conjugate() * dq).vector() * 2.0;
            assert_relative_eq!(w_fd, tr.gyr_rad_s, epsilon = 1e-5);
            let a_fd = (pm.truth(t + h).gyr_rad_s - pm.truth(t - h).gyr_rad_s) / (2.0 * h);
            assert_relative_eq!(a_fd, tr.ang_acc_rad_s2, epsilon = 2e-3);
            let v_fd = (pm.truth(t + h).pos_m - pm.truth(t - h).pos_m) / (2.0 * h);
            assert_relative_eq!(v_fd, tr.vel_m_s, epsilon = 1e-7);
            let acc_fd = (pm.truth(t + h).vel_m_s - pm.truth(t - h).vel_m_s) / (2.0 * h);
            assert_relative_eq!(acc_fd, tr.acc_m_s2, epsilon = 2e-3);
        }
    }

    #[test]
    fn bad_input_is_an_error() {
        let g = Geometry::typical();
        let cone = Conical::about_z(0.05, 1.0);
        assert!(PlatformMotion::new(&g, &ServoLegs::default(), &cone, f64::NAN).is_err());
        let huge = Conical::about_z(1.0, 1.0);
        assert!(PlatformMotion::new(&g, &ServoLegs::default(), &huge, 1.0).is_err());
    }
}
