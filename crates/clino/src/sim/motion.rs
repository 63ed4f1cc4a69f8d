//! Analytic truth trajectories: static, conical motion, positional orbits, and sums.
//!
//! Source of the conical motion and the orbits: Liu, Cai, Yang, Zhang,
//! "Testing of a MEMS Dynamic Inclinometer Using the Stewart Platform",
//! Sensors 2019 (eq 1: q(t); eq 2: body rate; eq 3: specific force; eq 4:
//! positional vibrations S_i(t) = Ŝ_i·sin(ωt + φ_i)).
//!
//! Every motion gives the exact attitude, body rate, body angular
//! acceleration, position, velocity and acceleration (no numerical
//! differentiation), so a simulated sensor sees exactly the physics.

use super::{Motion, Truth};
use clino_core::{Attitude, Vec3};
use nalgebra::Quaternion;

/// A sensor at rest: constant attitude and position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Static {
    /// Attitude (body to ENU).
    pub attitude: Attitude,
    /// Position, m (navigation frame).
    pub pos_m: Vec3,
}

impl Static {
    /// Level and at the origin.
    pub fn level() -> Self {
        Self::new(Attitude::identity())
    }
    /// At rest with the given attitude, at the origin.
    pub fn new(attitude: Attitude) -> Self {
        Self {
            attitude,
            pos_m: Vec3::zeros(),
        }
    }
}

impl Motion for Static {
    fn truth(&self, t_s: f64) -> Truth {
        Truth {
            t_s,
            attitude: self.attitude,
            gyr_rad_s: Vec3::zeros(),
            ang_acc_rad_s2: Vec3::zeros(),
            pos_m: self.pos_m,
            vel_m_s: Vec3::zeros(),
            acc_m_s2: Vec3::zeros(),
        }
    }
}

/// The body axis a conical motion turns about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeAxis {
    /// Cone about x: q = (cos α/2, 0, sin α/2·cos ωt, sin α/2·sin ωt).
    X,
    /// Cone about y: q = (cos α/2, sin α/2·sin ωt, 0, sin α/2·cos ωt).
    Y,
    /// Cone about z (the paper's eq 1): q = (cos α/2, sin α/2·cos ωt, sin α/2·sin ωt, 0).
    Z,
}

/// Conical motion: a rotation by the fixed angle α about an axis OL that turns
/// at the constant rate ω in the plane normal to the cone axis.
///
/// About z (Liu et al., Sensors 2019, eq 1), with θ = ωt + φ₀:
/// q(t) = (cos α/2, sin α/2·cos θ, sin α/2·sin θ, 0). The body rate is
/// ω_b = 2·vec(q* ⊗ q̇) = (−ω·sin α·sin θ, ω·sin α·cos θ, −2ω·sin²(α/2)) (eq 2),
/// the angular acceleration dω_b/dt = (−ω²·sin α·cos θ, −ω²·sin α·sin θ, 0), and
/// the up vector in the body frame (−sin α·sin θ, sin α·cos θ, cos α) (eq 3).
/// The cones about x and y are the cyclic permutations (x→y→z→x) of this one,
/// which preserve the quaternion algebra. The sensor sits at the cone's apex
/// (position `pos_m`, no linear motion).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conical {
    /// Cone axis.
    pub axis: ConeAxis,
    /// Cone (rotation) angle α, rad.
    pub alpha_rad: f64,
    /// Angular rate ω of the axis OL, rad/s (2π·f).
    pub omega_rad_s: f64,
    /// Phase φ₀ at t = 0, rad.
    pub phase_rad: f64,
    /// Position of the apex, m.
    pub pos_m: Vec3,
}

impl Conical {
    /// Cone about z of angle `alpha_rad` at frequency `freq_hz`, phase 0, at the origin.
    pub fn about_z(alpha_rad: f64, freq_hz: f64) -> Self {
        Self::new(ConeAxis::Z, alpha_rad, freq_hz)
    }
    /// Cone about `axis` of angle `alpha_rad` at frequency `freq_hz`, phase 0, at the origin.
    pub fn new(axis: ConeAxis, alpha_rad: f64, freq_hz: f64) -> Self {
        Self {
            axis,
            alpha_rad,
            omega_rad_s: 2.0 * std::f64::consts::PI * freq_hz,
            phase_rad: 0.0,
            pos_m: Vec3::zeros(),
        }
    }
    /// Frequency f = ω/2π, Hz.
    pub fn freq_hz(&self) -> f64 {
        self.omega_rad_s / (2.0 * std::f64::consts::PI)
    }
    /// Map a vector written for the z cone into this cone's axes (cyclic permutation).
    fn perm(&self, v: Vec3) -> Vec3 {
        match self.axis {
            ConeAxis::Z => v,
            // z-case (a, b, c) → about x: (c, a, b)
            ConeAxis::X => Vec3::new(v.z, v.x, v.y),
            // about y: (b, c, a)
            ConeAxis::Y => Vec3::new(v.y, v.z, v.x),
        }
    }
}

impl Motion for Conical {
    fn truth(&self, t_s: f64) -> Truth {
        let a = self.alpha_rad;
        let w = self.omega_rad_s;
        let th = w * t_s + self.phase_rad;
        let (s_th, c_th) = th.sin_cos();
        let (sh, ch) = (0.5 * a).sin_cos();
        let v = self.perm(Vec3::new(sh * c_th, sh * s_th, 0.0));
        let attitude = Attitude::new_unchecked(Quaternion::new(ch, v.x, v.y, v.z));
        let sa = a.sin();
        let gyr = self.perm(Vec3::new(-w * sa * s_th, w * sa * c_th, -2.0 * w * sh * sh));
        let acc = self.perm(Vec3::new(-w * w * sa * c_th, -w * w * sa * s_th, 0.0));
        Truth {
            t_s,
            attitude,
            gyr_rad_s: gyr,
            ang_acc_rad_s2: acc,
            pos_m: self.pos_m,
            vel_m_s: Vec3::zeros(),
            acc_m_s2: Vec3::zeros(),
        }
    }
}

/// Positional orbit: three harmonic vibrations of one frequency,
/// S_i(t) = e(t)·Ŝ_i·sin(ωt + φ_i), i ∈ {x, y, z} (Liu et al., Sensors 2019, eq 4),
/// with a constant attitude.
///
/// e(t) is a start envelope, as a platform starts an orbit from rest: e = 0
/// before `start_s`, the quintic smooth step e = 10x³ − 15x⁴ + 6x⁵,
/// x = (t − start)/ramp, over `ramp_s` (so position, velocity and acceleration
/// are continuous), then 1 (with `ramp_s` = 0 and `start_s` = 0 the plain eq 4).
/// Velocity and acceleration are the exact derivatives,
/// v = e'·S + e·ω·Ŝ·cos(ωt + φ), a = e''·S + 2e'·ω·Ŝ·cos(ωt + φ) − e·ω²·Ŝ·sin(ωt + φ).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    /// Amplitudes Ŝ_i, m (navigation frame).
    pub amplitude_m: Vec3,
    /// Phases φ_i, rad.
    pub phase_rad: Vec3,
    /// Angular frequency ω, rad/s.
    pub omega_rad_s: f64,
    /// Constant attitude.
    pub attitude: Attitude,
    /// Time the orbit starts (rest before), s; −∞ (the default) for always on.
    pub start_s: f64,
    /// Duration of the smooth-step start ramp, s (0: none).
    pub ramp_s: f64,
}

impl Orbit {
    /// This orbit starting from rest at `start_s` with a smooth-step amplitude ramp of `ramp_s`.
    pub fn with_start(mut self, start_s: f64, ramp_s: f64) -> Self {
        self.start_s = start_s;
        self.ramp_s = ramp_s;
        self
    }

    /// The envelope e(t) and its first two derivatives.
    fn envelope(&self, t: f64) -> (f64, f64, f64) {
        if t < self.start_s {
            return (0.0, 0.0, 0.0);
        }
        if self.ramp_s <= 0.0 || t >= self.start_s + self.ramp_s {
            return (1.0, 0.0, 0.0);
        }
        let r = self.ramp_s;
        let x = (t - self.start_s) / r;
        let (x2, x3) = (x * x, x * x * x);
        (
            x3 * (10.0 - 15.0 * x + 6.0 * x2),
            30.0 * x2 * (1.0 - x).powi(2) / r,
            60.0 * x * (1.0 - 3.0 * x + 2.0 * x2) / (r * r),
        )
    }

    /// Default phases of [`Orbit::spatial`]: (0°, 120°, 240°), so that the three
    /// vibrations trace a genuinely spatial ellipse (the paper does not give its phases).
    pub const DEFAULT_PHASES_RAD: [f64; 3] = [
        0.0,
        2.0 * std::f64::consts::FRAC_PI_3,
        4.0 * std::f64::consts::FRAC_PI_3,
    ];

    /// Equal amplitude `amplitude_m` on x, y and z at `freq_hz`, phases
    /// [`Orbit::DEFAULT_PHASES_RAD`], level attitude.
    pub fn spatial(amplitude_m: f64, freq_hz: f64) -> Self {
        let p = Self::DEFAULT_PHASES_RAD;
        Self {
            amplitude_m: Vec3::repeat(amplitude_m),
            phase_rad: Vec3::new(p[0], p[1], p[2]),
            omega_rad_s: 2.0 * std::f64::consts::PI * freq_hz,
            attitude: Attitude::identity(),
            start_s: f64::NEG_INFINITY,
            ramp_s: 0.0,
        }
    }
}

impl Motion for Orbit {
    fn truth(&self, t_s: f64) -> Truth {
        let w = self.omega_rad_s;
        let (e, e1, e2) = self.envelope(t_s);
        let mut pos = Vec3::zeros();
        let mut vel = Vec3::zeros();
        let mut acc = Vec3::zeros();
        for i in 0..3 {
            let (s, c) = (w * t_s + self.phase_rad[i]).sin_cos();
            let a = self.amplitude_m[i];
            pos[i] = e * a * s;
            vel[i] = e1 * a * s + e * w * a * c;
            acc[i] = e2 * a * s + 2.0 * e1 * w * a * c - e * w * w * a * s;
        }
        Truth {
            t_s,
            attitude: self.attitude,
            gyr_rad_s: Vec3::zeros(),
            ang_acc_rad_s2: Vec3::zeros(),
            pos_m: pos,
            vel_m_s: vel,
            acc_m_s2: acc,
        }
    }
}

/// The superposition of two motions: `b` rides on `a`.
///
/// Attitude q = q_a ⊗ q_b (b's rotation expressed in a's body frame);
/// body rate ω = C_bᵀ·ω_a + ω_b; angular acceleration
/// dω/dt = C_bᵀ·dω_a/dt − ω_b × (C_bᵀ·ω_a) + dω_b/dt (from dC_b/dt = C_b·[ω_b×]).
/// Positions, velocities and accelerations add in the navigation frame (the
/// sensor stays at the centre of rotation, as on a Stewart platform whose
/// rotation centre is the sensor). Example: a conical motion plus an orbit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sum<A, B> {
    /// The carrying motion.
    pub a: A,
    /// The motion riding on it.
    pub b: B,
}

impl<A: Motion, B: Motion> Motion for Sum<A, B> {
    fn truth(&self, t_s: f64) -> Truth {
        let ta = self.a.truth(t_s);
        let tb = self.b.truth(t_s);
        let wa_b = tb.attitude.inverse_transform_vector(&ta.gyr_rad_s);
        let aa_b = tb.attitude.inverse_transform_vector(&ta.ang_acc_rad_s2);
        Truth {
            t_s,
            attitude: ta.attitude * tb.attitude,
            gyr_rad_s: wa_b + tb.gyr_rad_s,
            ang_acc_rad_s2: aa_b - tb.gyr_rad_s.cross(&wa_b) + tb.ang_acc_rad_s2,
            pos_m: ta.pos_m + tb.pos_m,
            vel_m_s: ta.vel_m_s + tb.vel_m_s,
            acc_m_s2: ta.acc_m_s2 + tb.acc_m_s2,
        }
    }
}

/// `motion` seen by a sensor mounted at `r_body_m` (body frame) from the
/// point the motion describes: a segment turned about a joint, a sensor on
/// an arm. Attitude and rates are the motion's; the sensor's point is
/// p + C·r, its velocity v + C·(ω × r) and its acceleration
/// a + C·(dω/dt × r + ω × (ω × r)) — the tangential and centripetal terms of
/// the lever arm ([`clino_core::compensate::lever_arm_acceleration`]), which
/// turn with the body and so do not average out as a free translation does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Offset<M> {
    /// The motion of the pivot (the joint).
    pub motion: M,
    /// The sensor's position from the pivot, m (body frame).
    pub r_body_m: Vec3,
}

impl<M: Motion> Motion for Offset<M> {
    fn truth(&self, t_s: f64) -> Truth {
        let t = self.motion.truth(t_s);
        let (w, wd, r) = (t.gyr_rad_s, t.ang_acc_rad_s2, self.r_body_m);
        let c = t.attitude;
        Truth {
            pos_m: t.pos_m + c * r,
            vel_m_s: t.vel_m_s + c * w.cross(&r),
            acc_m_s2: t.acc_m_s2 + c * clino_core::compensate::lever_arm_acceleration(&w, &wd, &r),
            ..t
        }
    }
}

/// A sensor fixed to the moving body turned by `mount` (sensor frame to
/// body frame): on its side on a wall or a boom's flank, upside down under
/// a plate, or however one segment of a chain carries it. The sensor's
/// point moves as the body's (put [`Offset`] inside for a lever arm); its
/// attitude is the body's times the mount, q·m, and its rates are the
/// body's seen in its own frame, m*·ω and m*·dω/dt.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mounted<M> {
    /// The body's motion.
    pub motion: M,
    /// The sensor's frame against the body's.
    pub mount: Attitude,
}

impl<M: Motion> Motion for Mounted<M> {
    fn truth(&self, t_s: f64) -> Truth {
        let t = self.motion.truth(t_s);
        let back = self.mount.inverse();
        Truth {
            attitude: t.attitude * self.mount,
            gyr_rad_s: back * t.gyr_rad_s,
            ang_acc_rad_s2: back * t.ang_acc_rad_s2,
            ..t
        }
    }
}

/// A drum: the sensor turning one way about its own x axis, which stays
/// horizontal at heading `heading_rad` (a tumbler or mixer drum, a rolling
/// pipe, a wheel, a drill string laid down), in runs and stops: the rate is
/// ω = e(t)·(ω₀ + ω₁·sin(Ω·τ)), with τ, e the moves-and-rests clock of
/// `duty` ([`super::hand::duty_clock`]) and Ω = 2π·`swing_hz`. The angle
/// turned is θ = ω₀·τ + (ω₁/Ω)·(1 − cos Ω·τ), so q = R_z(heading)·R_x(θ),
/// ω_b = (θ̇, 0, 0) and dω_b/dt = (θ̈, 0, 0) in closed form, with
/// θ̇ = (ω₀ + ω₁·sin Ωτ)·e and θ̈ = ω₁·Ω·cos(Ωτ)·e² + (ω₀ + ω₁·sin Ωτ)·e'.
/// The sensor sits on the axis (no linear motion; [`Offset`] puts it off).
/// A gyro scale error then drifts the tilt at a rate with a mean, which a
/// filter that takes all it learns in motion for bias keeps when the drum
/// stops.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drum {
    /// Runs and stops: only `move_s`, `rest_s`, `ramp_s` and `initial_rest_s` are read.
    pub duty: super::hand::HandParams,
    /// Mean rate ω₀ while turning, rad/s.
    pub rate_rad_s: f64,
    /// Swing ω₁ of the rate about its mean, rad/s.
    pub swing_rad_s: f64,
    /// Frequency of that swing (of the motion clock), Hz.
    pub swing_hz: f64,
    /// Heading of the axis, rad.
    pub heading_rad: f64,
}

impl Motion for Drum {
    fn truth(&self, t_s: f64) -> Truth {
        let (tau, e, e1) = super::hand::duty_clock(&self.duty, t_s);
        let (w0, w1) = (self.rate_rad_s, self.swing_rad_s);
        let big = 2.0 * std::f64::consts::PI * self.swing_hz;
        let (s, c) = (big * tau).sin_cos();
        let theta = if big > 0.0 {
            w0 * tau + w1 / big * (1.0 - c)
        } else {
            w0 * tau
        };
        let d1 = w0 + w1 * s;
        let rate = d1 * e;
        let acc = w1 * big * c * e * e + d1 * e1;
        let attitude = Attitude::from_axis_angle(&Vec3::z_axis(), self.heading_rad)
            * Attitude::from_axis_angle(&Vec3::x_axis(), theta);
        Truth {
            t_s,
            attitude,
            gyr_rad_s: Vec3::new(rate, 0.0, 0.0),
            ang_acc_rad_s2: Vec3::new(acc, 0.0, 0.0),
            pos_m: Vec3::zeros(),
            vel_m_s: Vec3::zeros(),
            acc_m_s2: Vec3::zeros(),
        }
    }
}

/// A vibrating base (an engine, a robot's drives) at `freq_hz`: linear
/// vibration of acceleration amplitude `acc_m_s2` per navigation axis (an
/// [`Orbit`] of amplitude a/ω², phases 0, 1, 2 rad) and angular vibration of
/// rate amplitude `rate_rad_s` (a [`Conical`] motion about z of angle
/// rate/ω). Ride it on a motion with [`Sum`]: `Sum { a: motion, b: vibration(..) }`.
pub fn vibration(freq_hz: f64, rate_rad_s: f64, acc_m_s2: Vec3) -> Sum<Orbit, Conical> {
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    Sum {
        a: Orbit {
            amplitude_m: acc_m_s2 / (w * w),
            phase_rad: Vec3::new(0.0, 1.0, 2.0),
            omega_rad_s: w,
            attitude: Attitude::identity(),
            start_s: f64::NEG_INFINITY,
            ramp_s: 0.0,
        },
        b: Conical::new(ConeAxis::Z, rate_rad_s / w, freq_hz),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    /// Body rate from central finite differences of the attitude: ω ≈ 2·vec(q* ⊗ dq/dt).
    fn fd_rate(m: &dyn Motion, t: f64) -> Vec3 {
        let h = 1e-5;
        let q0 = m.truth(t).attitude;
        let qp = m.truth(t + h).attitude.into_inner();
        let qm = m.truth(t - h).attitude.into_inner();
        let dq = (qp - qm) / (2.0 * h);
        (q0.into_inner().conjugate() * dq).vector() * 2.0
    }

    fn check_derivatives(m: &dyn Motion) {
        for k in 0..20 {
            let t = 0.137 * k as f64;
            let tr = m.truth(t);
            assert_relative_eq!(fd_rate(m, t), tr.gyr_rad_s, epsilon = 1e-7);
            let h = 1e-5;
            let da = (m.truth(t + h).gyr_rad_s - m.truth(t - h).gyr_rad_s) / (2.0 * h);
            assert_relative_eq!(da, tr.ang_acc_rad_s2, epsilon = 1e-6);
            let dv = (m.truth(t + h).pos_m - m.truth(t - h).pos_m) / (2.0 * h);
            assert_relative_eq!(dv, tr.vel_m_s, epsilon = 1e-8);
            let dacc = (m.truth(t + h).vel_m_s - m.truth(t - h).vel_m_s) / (2.0 * h);
            assert_relative_eq!(dacc, tr.acc_m_s2, epsilon = 1e-7);
        }
    }

    #[test]
    fn a_mounted_sensor_reads_the_body_s_motion_in_its_own_frame() {
        // the rates still match the attitude's finite differences, and the
        // specific force is the body's rotated into the sensor: on its side
        // (90° about x) the body's z reading is the sensor's y, upside down
        // its z reversed
        let body = Conical::new(ConeAxis::X, 20f64.to_radians(), 0.7);
        let side = Mounted {
            motion: body,
            mount: Attitude::from_scaled_axis(Vec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0)),
        };
        check_derivatives(&side);
        let down = Mounted {
            motion: Static::level(),
            mount: Attitude::from_scaled_axis(Vec3::new(std::f64::consts::PI, 0.0, 0.0)),
        };
        let (f_body, f_side) = (
            body.truth(1.3).specific_force(9.8),
            side.truth(1.3).specific_force(9.8),
        );
        assert_relative_eq!(
            f_side,
            Vec3::new(f_body.x, f_body.z, -f_body.y),
            epsilon = 1e-12
        );
        assert_relative_eq!(
            down.truth(0.5).specific_force(9.8),
            Vec3::new(0.0, 0.0, -9.8),
            epsilon = 1e-12
        );
    }

    #[test]
    fn cones_match_finite_differences() {
        for axis in [ConeAxis::X, ConeAxis::Y, ConeAxis::Z] {
            let mut c = Conical::new(axis, 5f64.to_radians(), 1.3);
            c.phase_rad = 0.4;
            check_derivatives(&c);
            let big = Conical::new(axis, 40f64.to_radians(), 0.7);
            check_derivatives(&big);
        }
    }

    #[test]
    fn cone_about_z_matches_paper_eqs_2_and_3() {
        let (a, f) = (5f64.to_radians(), 0.5);
        let c = Conical::about_z(a, f);
        let w = 2.0 * std::f64::consts::PI * f;
        for k in 0..10 {
            let t = 0.21 * k as f64;
            let tr = c.truth(t);
            let (s, co) = (w * t).sin_cos();
            assert_relative_eq!(
                tr.gyr_rad_s,
                Vec3::new(
                    -w * a.sin() * s,
                    w * a.sin() * co,
                    -2.0 * w * (a / 2.0).sin().powi(2)
                ),
                epsilon = 1e-12
            );
            let f_b = tr.specific_force(1.0);
            assert_relative_eq!(
                f_b,
                Vec3::new(-a.sin() * s, a.sin() * co, a.cos()),
                epsilon = 1e-12
            );
        }
    }

    #[test]
    fn cone_about_x_tilts_the_x_axis() {
        // the cone about x keeps body x at angle α from navigation x
        let a = 7f64.to_radians();
        let c = Conical::new(ConeAxis::X, a, 0.9);
        for k in 0..10 {
            let tr = c.truth(0.3 * k as f64);
            let x_n = tr.attitude.transform_vector(&Vec3::x());
            assert_relative_eq!(x_n.x, a.cos(), epsilon = 1e-12);
        }
    }

    #[test]
    fn a_drum_turns_about_its_horizontal_x_axis() {
        let d = Drum {
            duty: crate::sim::hand::HandParams {
                move_s: 1.0,
                rest_s: 0.6,
                ramp_s: 0.4,
                initial_rest_s: 0.3,
                ..crate::sim::hand::HandParams::by_hand()
            },
            rate_rad_s: 2.0,
            swing_rad_s: 1.0,
            swing_hz: 0.7,
            heading_rad: 0.5,
        };
        // through the initial rest, ramps, the run and the stop
        check_derivatives(&d);
        for k in 0..40 {
            let tr = d.truth(0.1 * k as f64);
            // body x stays horizontal at the heading
            let x_n = tr.attitude.transform_vector(&Vec3::x());
            assert_relative_eq!(
                x_n,
                Vec3::new(0.5f64.cos(), 0.5f64.sin(), 0.0),
                epsilon = 1e-12
            );
            assert!(tr.gyr_rad_s.x >= 0.0 && tr.gyr_rad_s.x <= 3.0 + 1e-12);
        }
        // at rest before the first run and in the stop after it
        assert_eq!(d.truth(0.2).gyr_rad_s, Vec3::zeros());
        assert_eq!(d.truth(2.5).gyr_rad_s, Vec3::zeros());
        assert_eq!(d.truth(2.5).attitude, d.truth(2.6).attitude);
    }

    #[test]
    fn orbit_and_sums_match_finite_differences() {
        let o = Orbit::spatial(0.02, 0.8);
        check_derivatives(&o);
        // inside the start ramp (0.5 … 1.5 s) and after it
        check_derivatives(&Orbit::spatial(0.02, 0.8).with_start(0.5, 1.0));
        assert_eq!(
            Orbit::spatial(0.02, 0.8)
                .with_start(0.5, 1.0)
                .truth(0.3)
                .pos_m,
            Vec3::zeros()
        );
        let s = Sum {
            a: Conical::new(ConeAxis::Z, 10f64.to_radians(), 0.6),
            b: Conical::new(ConeAxis::X, 4f64.to_radians(), 1.7),
        };
        check_derivatives(&s);
        let s2 = Sum {
            a: Conical::about_z(0.1, 1.0),
            b: o,
        };
        check_derivatives(&s2);
        assert_relative_eq!(s2.truth(0.3).pos_m, o.truth(0.3).pos_m, epsilon = 1e-15);
    }

    #[test]
    fn vibration_has_the_amplitudes_asked_for() {
        check_derivatives(&vibration(3.0, 0.035, Vec3::new(1.5, 1.0, 1.2)));
        let v = vibration(30.0, 0.035, Vec3::new(1.5, 1.0, 1.2));
        let (mut w_max, mut a_max) = (0.0f64, Vec3::zeros());
        for k in 0..1000 {
            let tr = v.truth(k as f64 * 1e-4);
            w_max = w_max.max(tr.gyr_rad_s.xy().norm());
            a_max = a_max.sup(&tr.acc_m_s2.abs());
        }
        // the cone's rate across its axis is ω·sin α (α = rate/ω)
        assert_relative_eq!(w_max, 0.035, max_relative = 1e-6);
        assert_relative_eq!(a_max, Vec3::new(1.5, 1.0, 1.2), max_relative = 1e-3);
    }

    #[test]
    fn an_offset_sensor_moves_as_a_point_of_the_body() {
        // derivatives by finite differences, on a turning, translating motion
        let m = Offset {
            motion: Sum {
                a: Conical::about_z(0.3, 0.7),
                b: Orbit::spatial(0.1, 0.4),
            },
            r_body_m: Vec3::new(0.3, -0.1, 0.2),
        };
        check_derivatives(&m);
        // the point's position is the pivot's plus the rotated arm
        let (tr, tp) = (m.truth(1.3), m.motion.truth(1.3));
        assert_relative_eq!(
            tr.pos_m,
            tp.pos_m + tp.attitude * m.r_body_m,
            epsilon = 1e-12
        );
    }

    #[test]
    fn static_reads_gravity_only() {
        let s = Static::level();
        let tr = s.truth(3.0);
        assert_eq!(tr.specific_force(9.8), Vec3::new(0.0, 0.0, 9.8));
        assert_eq!(tr.gyr_rad_s, Vec3::zeros());
    }
}
