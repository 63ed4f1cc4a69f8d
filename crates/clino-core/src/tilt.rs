//! Tilt outputs and their conventions, all in one place.
//!
//! Tilt is the attitude's deviation from level; heading does not enter.
//! Everything here is computed from the **up vector in the body frame**,
//! u_b = Cᵀ·e_z (the third row of the body-to-navigation matrix C), which is
//! also the direction of the specific force a resting accelerometer reads.
//! The conventions of the field, named (never guessed):
//!
//! | name | angles | up vector u_b |
//! |---|---|---|
//! | [`RollPitch`] (aerospace z-y-x, C = R_z(ψ)·R_y(θ)·R_x(φ)) | roll φ, pitch θ | (−sinθ, cosθ·sinφ, cosθ·cosφ) |
//! | [`ZxyTilt`] (z-x-y, C = R_z(ψ)·R_x(φ)·R_y(θ)) | φ, θ; outputs sinφ, tanθ | (−cosφ·sinθ, sinφ, cosφ·cosθ) |
//! | [`QuatTilt`] (order-free) | x, y of the heading-free tilt quaternion | — |
//! | [`inclination`] | angle of body z from vertical | acos(u_z) |
//! | [`gravity_toolface`] | direction of the high side in the body x–y plane | atan2(u_y, u_x) |
//!
//! Source of the z-x-y set and of the quaternion-component outputs: Liu, Cai
//! et al., "Testing of a MEMS Dynamic Inclinometer Using the Stewart
//! Platform", Sensors 2019 (its sensitivities of eqs 8 and 11).

use crate::math::{asin, atan2, clamp1, sqrt};
use crate::{Attitude, Vec3};

/// Up direction (navigation +z) expressed in the body frame: u_b = Cᵀ·e_z.
///
/// For q = (w, x, y, z): u_b = (2(xz − wy), 2(yz + wx), w² − x² − y² + z²).
#[inline]
pub fn up_in_body(q: &Attitude) -> Vec3 {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    Vec3::new(
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        w * w - x * x - y * y + z * z,
    )
}

/// Aerospace roll and pitch (z-y-x Euler sequence), radians.
///
/// C = R_z(ψ)·R_y(θ)·R_x(φ); the up vector in the body frame is
/// (−sinθ, cosθ·sinφ, cosθ·cosφ), so φ = atan2(u_y, u_z) and
/// θ = atan2(−u_x, √(u_y² + u_z²)). Roll is in (−π, π], pitch in [−π/2, π/2];
/// at pitch ±90° roll is undefined and reported as atan2 of the rounding residue.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollPitch {
    /// Roll φ about body x, rad.
    pub roll: f64,
    /// Pitch θ about body y, rad.
    pub pitch: f64,
}

impl RollPitch {
    /// From an up vector in the body frame (need not be normalised).
    pub fn from_up(u: &Vec3) -> Self {
        Self {
            roll: atan2(u.y, u.z),
            pitch: atan2(-u.x, sqrt(u.y * u.y + u.z * u.z)),
        }
    }
    /// From an attitude.
    pub fn from_attitude(q: &Attitude) -> Self {
        Self::from_up(&up_in_body(q))
    }
    /// The unit up vector (−sinθ, cosθ·sinφ, cosθ·cosφ).
    pub fn up(&self) -> Vec3 {
        let (sp, cp) = (crate::math::sin(self.pitch), crate::math::cos(self.pitch));
        let (sr, cr) = (crate::math::sin(self.roll), crate::math::cos(self.roll));
        Vec3::new(-sp, cp * sr, cp * cr)
    }
}

/// The z-x-y tilt set, radians: C = R_z(ψ)·R_x(φ)·R_y(θ), up vector
/// (−cosφ·sinθ, sinφ, cosφ·cosθ).
///
/// φ = asin(u_y) ∈ [−π/2, π/2], θ = atan2(−u_x, u_z) ∈ (−π, π]. The
/// dynamic-inclinometer outputs of the Stewart-platform paper are sinφ and
/// tanθ ([`ZxyTilt::sin_phi`], [`ZxyTilt::tan_theta`]); at θ = ±90° tanθ is
/// infinite and returned as such.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ZxyTilt {
    /// φ, rotation about body x (applied second), rad.
    pub phi: f64,
    /// θ, rotation about body y (applied last), rad.
    pub theta: f64,
}

impl ZxyTilt {
    /// From an up vector in the body frame (normalised here).
    pub fn from_up(u: &Vec3) -> Self {
        let n = u.norm();
        Self {
            phi: asin(clamp1(u.y / n)),
            theta: atan2(-u.x, u.z),
        }
    }
    /// From an attitude.
    pub fn from_attitude(q: &Attitude) -> Self {
        Self::from_up(&up_in_body(q))
    }
    /// sinφ = u_y.
    pub fn sin_phi(&self) -> f64 {
        crate::math::sin(self.phi)
    }
    /// tanθ = −u_x/u_z.
    pub fn tan_theta(&self) -> f64 {
        crate::math::tan(self.theta)
    }
    /// The unit up vector (−cosφ·sinθ, sinφ, cosφ·cosθ).
    pub fn up(&self) -> Vec3 {
        let (sf, cf) = (crate::math::sin(self.phi), crate::math::cos(self.phi));
        let (st, ct) = (crate::math::sin(self.theta), crate::math::cos(self.theta));
        Vec3::new(-cf * st, sf, cf * ct)
    }
}

/// Order-free tilt: the x and y components of the heading-free tilt quaternion.
///
/// Any attitude splits as q = q_ψ ⊗ q_t, with q_ψ = (cos ψ/2, 0, 0, sin ψ/2) a
/// rotation about navigation z and q_t = (n, x_t, y_t, 0) with no z part. With
/// q = (w, x, y, z) and n = √(w² + z²): x_t = (w·x + z·y)/n, y_t = (w·y − z·x)/n.
/// For the conical motion q(t) = (cos α/2, sin α/2·cos ωt, sin α/2·sin ωt, 0)
/// of the Stewart-platform paper, (x_t, y_t) are its second and third
/// components, of amplitude sin(α/2). The inclination is 2·acos(n).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuatTilt {
    /// x component of the tilt quaternion.
    pub x: f64,
    /// y component of the tilt quaternion.
    pub y: f64,
}

impl QuatTilt {
    /// From an attitude. At inclination 180° (n = 0) the split is not unique
    /// and the tilt axis is reported as the one of q itself.
    pub fn from_attitude(q: &Attitude) -> Self {
        let (w, x, y, z) = (q.w, q.i, q.j, q.k);
        let n = sqrt(w * w + z * z);
        if n < 1e-12 {
            return Self { x, y };
        }
        Self {
            x: (w * x + z * y) / n,
            y: (w * y - z * x) / n,
        }
    }
    /// The tilt quaternion q_t = (√(1 − x² − y²), x, y, 0).
    pub fn quaternion(&self) -> Attitude {
        let w = sqrt((1.0 - self.x * self.x - self.y * self.y).max(0.0));
        Attitude::new_unchecked(nalgebra::Quaternion::new(w, self.x, self.y, 0.0))
    }
}

/// Inclination: the angle between body z and the vertical, rad, in [0, π].
///
/// acos(u_z), evaluated as atan2(√(u_x² + u_y²), u_z) to stay accurate near 0
/// and π. Equals 2·acos(√(w² + z²)) of the attitude quaternion (BROAD's
/// inclination error uses that form).
#[inline]
pub fn inclination(q: &Attitude) -> f64 {
    inclination_from_up(&up_in_body(q))
}

/// Inclination of an up vector (or of a resting accelerometer's specific force), rad.
#[inline]
pub fn inclination_from_up(u: &Vec3) -> f64 {
    atan2(sqrt(u.x * u.x + u.y * u.y), u.z)
}

/// Gravity toolface, rad in (−π, π]: the direction of the high side (the
/// horizontal projection of "up") in the body x–y plane, measured from body x
/// towards body y: atan2(u_y, u_x). Undefined (returned as 0) when the body z
/// axis is vertical.
///
/// This is the toolface of a body whose z axis points *up* the instrument. The
/// drilling convention (tool z down the hole) lives in `clino::survey`.
#[inline]
pub fn gravity_toolface(q: &Attitude) -> f64 {
    let u = up_in_body(q);
    if u.x == 0.0 && u.y == 0.0 {
        0.0
    } else {
        atan2(u.y, u.x)
    }
}

/// The heading-free attitude whose up vector is `u` (body frame), if `u` is
/// finite and non-zero: the shortest rotation taking û to navigation z,
/// q = normalise(1 + û_z, û_y, −û_x, 0). Upside down (û = −e_z) it is the
/// half turn about body x.
pub fn attitude_from_up(u: &Vec3) -> Option<Attitude> {
    let n = u.norm();
    if !(n.is_finite() && n > 0.0) {
        return None;
    }
    let a = u / n;
    // 1 + a_z, without cancellation when a_z ≈ −1: (a_x² + a_y²)/(1 − a_z)
    let w = if a.z >= 0.0 {
        1.0 + a.z
    } else {
        (a.x * a.x + a.y * a.y) / (1.0 - a.z)
    };
    let q = if w == 0.0 {
        nalgebra::Quaternion::new(0.0, 1.0, 0.0, 0.0)
    } else {
        let s = sqrt(2.0 * w);
        nalgebra::Quaternion::new(w / s, a.y / s, -a.x / s, 0.0)
    };
    Some(Attitude::new_unchecked(q))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use core::f64::consts::{FRAC_PI_2, PI};
    use nalgebra::{UnitQuaternion, Vector3};

    fn zyx(roll: f64, pitch: f64, yaw: f64) -> Attitude {
        // nalgebra's from_euler_angles is the z-y-x sequence: R_z(yaw)·R_y(pitch)·R_x(roll).
        UnitQuaternion::from_euler_angles(roll, pitch, yaw)
    }
    fn zxy(phi: f64, theta: f64, yaw: f64) -> Attitude {
        UnitQuaternion::from_axis_angle(&Vector3::z_axis(), yaw)
            * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), phi)
            * UnitQuaternion::from_axis_angle(&Vector3::y_axis(), theta)
    }

    #[test]
    fn up_vector_is_third_row_of_dcm() {
        let q = zyx(0.3, -0.7, 2.1);
        let c = q.to_rotation_matrix();
        let row = c.matrix().row(2).transpose();
        assert_relative_eq!(up_in_body(&q), row, epsilon = 1e-15);
    }

    #[test]
    fn roll_pitch_closed_form_any_heading() {
        for &(r, p, y) in &[
            (0.1, 0.2, 0.0),
            (-2.5, 1.2, 1.0),
            (3.0, -1.4, -2.9),
            (0.0, 0.0, 0.5),
        ] {
            let t = RollPitch::from_attitude(&zyx(r, p, y));
            assert_relative_eq!(t.roll, r, epsilon = 1e-12);
            assert_relative_eq!(t.pitch, p, epsilon = 1e-12);
            let u = Vector3::new(-p.sin(), p.cos() * r.sin(), p.cos() * r.cos());
            assert_relative_eq!(t.up(), u, epsilon = 1e-12);
        }
    }

    #[test]
    fn roll_pitch_near_vertical_pitch() {
        // 1e-6 rad short of +90°: pitch still exact, roll still recovered.
        let p = FRAC_PI_2 - 1e-6;
        let t = RollPitch::from_attitude(&zyx(0.4, p, 0.3));
        assert_relative_eq!(t.pitch, p, epsilon = 1e-12);
        assert_relative_eq!(t.roll, 0.4, epsilon = 1e-6);
        // exactly -90°: pitch is -90° whatever roll was
        let t = RollPitch::from_up(&Vector3::new(1.0, 0.0, 0.0));
        assert_relative_eq!(t.pitch, -FRAC_PI_2, epsilon = 1e-15);
        assert!(t.roll.is_finite());
    }

    #[test]
    fn zxy_closed_form_and_outputs() {
        for &(f, t, y) in &[(0.1, 0.2, 0.0), (-1.2, 2.5, 1.0), (1.4, -3.0, -2.0)] {
            let z = ZxyTilt::from_attitude(&zxy(f, t, y));
            assert_relative_eq!(z.phi, f, epsilon = 1e-12);
            assert_relative_eq!(z.theta, t, epsilon = 1e-12);
            assert_relative_eq!(z.sin_phi(), f.sin(), epsilon = 1e-12);
            assert_relative_eq!(z.tan_theta(), t.tan(), epsilon = 1e-9);
            let u = Vector3::new(-f.cos() * t.sin(), f.sin(), f.cos() * t.cos());
            assert_relative_eq!(up_in_body(&zxy(f, t, y)), u, epsilon = 1e-12);
        }
        // near theta = 90°: tan θ large but right
        let th = FRAC_PI_2 - 1e-5;
        let z = ZxyTilt::from_attitude(&zxy(0.2, th, 0.0));
        assert_relative_eq!(z.tan_theta(), th.tan(), max_relative = 1e-6);
    }

    #[test]
    fn quaternion_components_of_conical_motion() {
        let alpha = 5f64.to_radians();
        for k in 0..16 {
            let wt = k as f64 * 0.4;
            let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                (alpha / 2.0).cos(),
                (alpha / 2.0).sin() * wt.cos(),
                (alpha / 2.0).sin() * wt.sin(),
                0.0,
            ));
            let qt = QuatTilt::from_attitude(&q);
            assert_relative_eq!(qt.x, (alpha / 2.0).sin() * wt.cos(), epsilon = 1e-15);
            assert_relative_eq!(qt.y, (alpha / 2.0).sin() * wt.sin(), epsilon = 1e-15);
            // heading does not change the components' magnitude and inclination
            let h = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.1) * q;
            let qh = QuatTilt::from_attitude(&h);
            assert_relative_eq!(qh.x.hypot(qh.y), (alpha / 2.0).sin(), epsilon = 1e-15);
            assert_relative_eq!(inclination(&h), alpha, epsilon = 1e-12);
            // the split reproduces q: q = q_psi * q_t
            let n = (h.w * h.w + h.k * h.k).sqrt();
            let qpsi = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
                h.w / n,
                0.0,
                0.0,
                h.k / n,
            ));
            assert!((qpsi * qh.quaternion()).angle_to(&h) < 1e-12);
        }
    }

    #[test]
    fn inclination_matches_both_closed_forms() {
        for &(r, p) in &[
            (0.0, 0.0),
            (0.3, 0.4),
            (1.5, -0.2),
            (3.0, 0.1),
            (0.0, FRAC_PI_2),
        ] {
            let q = zyx(r, p, 0.7);
            let direct = (r.cos() * p.cos()).clamp(-1.0, 1.0).acos();
            assert_relative_eq!(inclination(&q), direct, epsilon = 1e-12);
            let broad = 2.0 * (q.w * q.w + q.k * q.k).sqrt().min(1.0).acos();
            assert_relative_eq!(inclination(&q), broad, epsilon = 1e-7);
        }
        // small angles stay accurate (acos would lose them)
        let q = zyx(1e-9, 0.0, 0.0);
        assert_relative_eq!(inclination(&q), 1e-9, max_relative = 1e-6);
        assert_relative_eq!(inclination(&zyx(PI, 0.0, 0.0)), PI, epsilon = 1e-12);
    }

    #[test]
    fn toolface_points_to_high_side() {
        // tilt about body x by +20° (roll): up vector has +y component → toolface 90°
        let q = zyx(20f64.to_radians(), 0.0, 0.4);
        assert_relative_eq!(gravity_toolface(&q), FRAC_PI_2, epsilon = 1e-12);
        // nose down (pitch +): up has -x component → toolface 180°
        let q = zyx(0.0, 0.3, 0.0);
        assert_relative_eq!(gravity_toolface(&q).abs(), PI, epsilon = 1e-12);
        assert_eq!(gravity_toolface(&Attitude::identity()), 0.0);
    }

    #[test]
    fn attitude_from_up_round_trip() {
        for u in [
            Vector3::new(0.0, 0.0, 1.0),
            Vector3::new(0.3, -0.2, 0.9),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.0, 0.0, -2.0),
            Vector3::new(1e-3, 0.0, -1.0),
        ] {
            let q = attitude_from_up(&u).unwrap();
            assert_relative_eq!(up_in_body(&q), u.normalize(), epsilon = 1e-12);
            assert!(q.k.abs() < 1e-15, "heading-free: no z component");
        }
        assert!(attitude_from_up(&Vector3::zeros()).is_none());
        assert!(attitude_from_up(&Vector3::new(f64::NAN, 0.0, 1.0)).is_none());
    }
}
