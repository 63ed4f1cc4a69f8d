//! Human-like (or slow robot-like) motion with rests: a seeded, smooth,
//! bounded trajectory in attitude and position that stops and restarts.
//!
//! The generalisation harness of issue 13 needs motions of the kinds nobody
//! tuned for: a segment of a chain moved by hand (turns of tens of degrees at
//! a fraction of a hertz, rests of a few seconds at new poses), or a robot arm
//! moving slowly (under 0.35 rad/s) between short rests. Both are made here
//! from one construction:
//!
//! * a **motion clock** τ(t) that runs at rate e(t) ∈ [0, 1]: e = 0 during
//!   rests, 1 while moving, with quintic smooth steps S(x) = 10x³ − 15x⁴ + 6x⁵
//!   of `ramp_s` between them (so rate and acceleration are continuous). Its
//!   integral is closed-form (∫S = 2.5x⁴ − 3x⁵ + x⁶), so τ, τ' = e and
//!   τ'' = e' are exact;
//! * z-y-x Euler angles (roll φ, pitch θ, yaw ψ) and a position, each an
//!   offset plus a sum of three sines of the motion clock, with seeded
//!   frequencies and phases: x(t) = s(τ(t)), ẋ = s'(τ)·e, ẍ = s''(τ)·e² + s'(τ)·e'.
//!   Each rest is therefore at a new pose (the clock stops wherever it is);
//! * the body rate of q = R_z(ψ)·R_y(θ)·R_x(φ) in closed form,
//!   ω_b = (φ̇ − ψ̇·sin θ, θ̇·cos φ + ψ̇·cos θ·sin φ, −θ̇·sin φ + ψ̇·cos θ·cos φ),
//!   and its exact time derivative (product rule on each term).
//!
//! Vibration (an engine, a gearbox, a tool) is added with
//! [`super::motion::Sum`] of this motion and an [`super::motion::Orbit`]
//! (linear) or a small [`super::motion::Conical`] (angular).

use super::{Motion, Truth};
use clino_core::{Attitude, Vec3};
use nalgebra::UnitQuaternion;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::f64::consts::PI;

/// One coordinate: offset + Σ aᵢ·sin(wᵢ·τ + φᵢ).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Sines {
    offset: f64,
    amp: [f64; 3],
    w: [f64; 3],
    phase: [f64; 3],
}

impl Sines {
    /// Value, first and second derivative with respect to τ.
    fn eval(&self, tau: f64) -> (f64, f64, f64) {
        let (mut x, mut d1, mut d2) = (self.offset, 0.0, 0.0);
        for i in 0..3 {
            let (s, c) = (self.w[i] * tau + self.phase[i]).sin_cos();
            x += self.amp[i] * s;
            d1 += self.amp[i] * self.w[i] * c;
            d2 -= self.amp[i] * self.w[i] * self.w[i] * s;
        }
        (x, d1, d2)
    }

    /// Seeded: three frequencies in [f_lo, f_hi] Hz, amplitudes summing to
    /// `amplitude` (so |x − offset| ≤ amplitude).
    fn seeded(rng: &mut ChaCha8Rng, offset: f64, amplitude: f64, f_lo: f64, f_hi: f64) -> Self {
        let mut amp = [0.0; 3];
        let mut w = [0.0; 3];
        let mut phase = [0.0; 3];
        let mut total = 0.0;
        for i in 0..3 {
            amp[i] = rng.random_range(0.3..1.0);
            total += amp[i];
            w[i] = 2.0 * PI * rng.random_range(f_lo..=f_hi);
            phase[i] = rng.random_range(0.0..2.0 * PI);
        }
        for a in &mut amp {
            *a *= amplitude / total;
        }
        Self {
            offset,
            amp,
            w,
            phase,
        }
    }

    /// Largest |ds/dτ|: Σ aᵢ·wᵢ.
    fn peak_rate(&self) -> f64 {
        (0..3).map(|i| self.amp[i] * self.w[i]).sum()
    }
}

/// Parameters of a [`HandMotion`] (angles in radians, lengths in metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandParams {
    /// Largest swing of roll and pitch about their offsets, rad.
    pub tilt_amplitude_rad: f64,
    /// Largest swing of yaw, rad.
    pub yaw_amplitude_rad: f64,
    /// Largest horizontal excursion of the sensor point, m (vertical: half).
    pub position_amplitude_m: f64,
    /// Band of the motion's frequencies (of the motion clock), Hz.
    pub band_hz: (f64, f64),
    /// Time moving between rests, s.
    pub move_s: f64,
    /// Time at rest between moves, s.
    pub rest_s: f64,
    /// Smooth-step ramp between rest and motion, s.
    pub ramp_s: f64,
    /// Rest before the first move, s.
    pub initial_rest_s: f64,
    /// Largest roll and pitch offset of the seeded poses, rad.
    pub pose_tilt_rad: f64,
    /// Fraction of the motion clock's speed kept through the rests after the
    /// first move (0: a true stop). A hand holding a pose is never still: the
    /// pose creeps on along the motion's own path, slowly (see [`Self::held`]).
    pub rest_creep: f64,
}

impl HandParams {
    /// A segment of a chain moved by hand: ±35° tilt and ±60° yaw at
    /// 0.15–0.8 Hz (peak rates of 1–3 rad/s), ±0.25 m, moves of 8 s, rests of 3 s.
    pub fn by_hand() -> Self {
        Self {
            tilt_amplitude_rad: 35f64.to_radians(),
            yaw_amplitude_rad: 60f64.to_radians(),
            position_amplitude_m: 0.25,
            band_hz: (0.15, 0.8),
            move_s: 8.0,
            rest_s: 3.0,
            ramp_s: 0.5,
            initial_rest_s: 5.0,
            pose_tilt_rad: 30f64.to_radians(),
            rest_creep: 0.0,
        }
    }

    /// [`Self::by_hand`] with the rests held in the hand rather than set
    /// down: the pose creeps on at 1 % of the motion's speed (the body rate
    /// 0.01–0.03 rad/s at its peaks, 0.6–1.7°/s, most of the time under the
    /// 0.5°/s a rest detector accepts; the position 1–3 cm/s at most). The
    /// hand's tremor (8–12 Hz) is added apart, as a vibration.
    pub fn held() -> Self {
        Self {
            rest_creep: 0.01,
            ..Self::by_hand()
        }
    }

    /// A robot arm moving slowly: ±20° tilt and ±40° yaw at 0.03–0.1 Hz
    /// (peak rates of about 0.1–0.36 rad/s over seeds, the issue's "under
    /// 0.35 rad/s"), ±0.1 m, moves of 12 s, rests of 2 s.
    pub fn slow() -> Self {
        Self {
            tilt_amplitude_rad: 20f64.to_radians(),
            yaw_amplitude_rad: 40f64.to_radians(),
            position_amplitude_m: 0.1,
            band_hz: (0.03, 0.1),
            move_s: 12.0,
            rest_s: 2.0,
            ramp_s: 0.5,
            initial_rest_s: 3.0,
            pose_tilt_rad: 20f64.to_radians(),
            rest_creep: 0.0,
        }
    }
}

/// A seeded human-like motion with rests (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HandMotion {
    /// The parameters it was made from.
    pub params: HandParams,
    angles: [Sines; 3],
    pos: [Sines; 3],
}

/// Quintic smooth step S(x), S'(x), and ∫₀ˣ S on [0, 1].
fn step5(x: f64) -> (f64, f64, f64) {
    let x = x.clamp(0.0, 1.0);
    let (x2, x3) = (x * x, x * x * x);
    (
        x3 * (10.0 - 15.0 * x + 6.0 * x2),
        30.0 * x2 * (1.0 - x) * (1.0 - x),
        x2 * x2 * (2.5 - 3.0 * x + x2),
    )
}

impl HandMotion {
    /// The motion of `params` with frequencies, phases and poses from `seed`.
    pub fn new(params: HandParams, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x4a4d_4f54);
        let (lo, hi) = params.band_hz;
        let pt = params.pose_tilt_rad;
        let roll0 = rng.random_range(-pt..=pt);
        let pitch0 = rng.random_range(-pt..=pt);
        let yaw0 = rng.random_range(-PI..PI);
        let angles = [
            Sines::seeded(&mut rng, roll0, params.tilt_amplitude_rad, lo, hi),
            Sines::seeded(&mut rng, pitch0, params.tilt_amplitude_rad, lo, hi),
            Sines::seeded(&mut rng, yaw0, params.yaw_amplitude_rad, lo, hi),
        ];
        let a = params.position_amplitude_m;
        let pos = [
            Sines::seeded(&mut rng, 0.0, a, lo, hi),
            Sines::seeded(&mut rng, 0.0, a, lo, hi),
            Sines::seeded(&mut rng, 0.0, 0.5 * a, lo, hi),
        ];
        Self {
            params,
            angles,
            pos,
        }
    }

    /// Upper bound of the body rate, rad/s (Σ of the Euler-rate peaks).
    pub fn peak_rate_bound(&self) -> f64 {
        self.angles.iter().map(|s| s.peak_rate()).sum()
    }

    /// The motion clock τ(t), its rate e(t) and e'(t): the clock of the
    /// moves and rests, [`Self::phase_clock`], with the rests' creep c added
    /// after the initial rest, τ = c·t' + (1 − c)·τ₀, e = c + (1 − c)·e₀.
    pub fn clock(&self, t: f64) -> (f64, f64, f64) {
        let (tau, e, e1) = self.phase_clock(t);
        let c = self.params.rest_creep;
        let t = t - self.params.initial_rest_s;
        if c == 0.0 || t <= 0.0 {
            return (tau, e, e1);
        }
        (c * t + (1.0 - c) * tau, c + (1.0 - c) * e, (1.0 - c) * e1)
    }

    /// The clock of the moves and rests alone: rate 1 while moving, 0 at rest.
    pub fn phase_clock(&self, t: f64) -> (f64, f64, f64) {
        duty_clock(&self.params, t)
    }

    /// True while the mount is at rest (the motion clock stopped, or
    /// creeping at [`HandParams::rest_creep`]).
    pub fn at_rest(&self, t: f64) -> bool {
        self.phase_clock(t).1 == 0.0
    }
}

/// The clock of the moves and rests of `p` ([`HandParams::move_s`],
/// [`HandParams::rest_s`], [`HandParams::ramp_s`] and
/// [`HandParams::initial_rest_s`]): τ(t), its rate e(t) (1 while moving, 0 at
/// rest, quintic steps between) and e'(t), in closed form.
pub fn duty_clock(p: &HandParams, t: f64) -> (f64, f64, f64) {
    let t = t - p.initial_rest_s;
    if t <= 0.0 {
        return (0.0, 0.0, 0.0);
    }
    let r = p.ramp_s.max(1e-9);
    // one cycle: ramp up, move, ramp down, rest
    let cycle = 2.0 * r + p.move_s + p.rest_s;
    let per_cycle = r + p.move_s; // ∫e over a cycle (each ramp gives r/2)
    let k = (t / cycle).floor();
    let u = t - k * cycle;
    let base = k * per_cycle;
    if u < r {
        let (s, ds, is) = step5(u / r);
        (base + r * is, s, ds / r)
    } else if u < r + p.move_s {
        (base + 0.5 * r + (u - r), 1.0, 0.0)
    } else if u < 2.0 * r + p.move_s {
        let x = (u - r - p.move_s) / r;
        let (s, ds, is) = step5(x);
        (base + 0.5 * r + p.move_s + r * (x - is), 1.0 - s, -ds / r)
    } else {
        (base + per_cycle, 0.0, 0.0)
    }
}

impl Motion for HandMotion {
    fn truth(&self, t_s: f64) -> Truth {
        let (tau, e, e1) = self.clock(t_s);
        let chain = |s: &Sines| {
            let (x, d1, d2) = s.eval(tau);
            (x, d1 * e, d2 * e * e + d1 * e1)
        };
        let (phi, dphi, ddphi) = chain(&self.angles[0]);
        let (th, dth, ddth) = chain(&self.angles[1]);
        let (psi, dpsi, ddpsi) = chain(&self.angles[2]);
        let attitude: Attitude = UnitQuaternion::from_euler_angles(phi, th, psi);
        let (sp, cp) = phi.sin_cos();
        let (st, ct) = th.sin_cos();
        let gyr = Vec3::new(
            dphi - dpsi * st,
            dth * cp + dpsi * ct * sp,
            -dth * sp + dpsi * ct * cp,
        );
        let ang_acc = Vec3::new(
            ddphi - ddpsi * st - dpsi * dth * ct,
            ddth * cp - dth * dphi * sp + ddpsi * ct * sp - dpsi * dth * st * sp
                + dpsi * dphi * ct * cp,
            -ddth * sp - dth * dphi * cp + ddpsi * ct * cp
                - dpsi * dth * st * cp
                - dpsi * dphi * ct * sp,
        );
        let mut pos = Vec3::zeros();
        let mut vel = Vec3::zeros();
        let mut acc = Vec3::zeros();
        for i in 0..3 {
            let (x, v, a) = chain(&self.pos[i]);
            pos[i] = x;
            vel[i] = v;
            acc[i] = a;
        }
        Truth {
            t_s,
            attitude,
            gyr_rad_s: gyr,
            ang_acc_rad_s2: ang_acc,
            pos_m: pos,
            vel_m_s: vel,
            acc_m_s2: acc,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn truth_is_the_derivative_of_itself() {
        for params in [
            HandParams::by_hand(),
            HandParams::slow(),
            HandParams::held(),
        ] {
            let m = HandMotion::new(params, 3);
            let h = 1e-6;
            let mut t = 0.0;
            while t < 60.0 {
                let (a, tr, b) = (m.truth(t - h), m.truth(t), m.truth(t + h));
                let w_fd = (a.attitude.inverse() * b.attitude).scaled_axis() / (2.0 * h);
                assert_relative_eq!(w_fd, tr.gyr_rad_s, epsilon = 1e-6);
                let wd_fd = (b.gyr_rad_s - a.gyr_rad_s) / (2.0 * h);
                assert_relative_eq!(wd_fd, tr.ang_acc_rad_s2, epsilon = 1e-4);
                assert_relative_eq!((b.pos_m - a.pos_m) / (2.0 * h), tr.vel_m_s, epsilon = 1e-6);
                assert_relative_eq!(
                    (b.vel_m_s - a.vel_m_s) / (2.0 * h),
                    tr.acc_m_s2,
                    epsilon = 1e-4
                );
                t += 0.173;
            }
        }
    }

    #[test]
    fn rests_are_still_and_at_new_poses() {
        let p = HandParams::by_hand();
        let m = HandMotion::new(p, 9);
        let cycle = 2.0 * p.ramp_s + p.move_s + p.rest_s;
        let mut poses = Vec::new();
        for k in 0..4 {
            // the middle of the k-th rest after the first move
            let t = p.initial_rest_s + (k + 1) as f64 * cycle - 0.5 * p.rest_s;
            assert!(m.at_rest(t));
            let tr = m.truth(t);
            assert_eq!(tr.gyr_rad_s, Vec3::zeros());
            assert_eq!(tr.acc_m_s2, Vec3::zeros());
            poses.push(tr.attitude);
        }
        assert!(poses[0].angle_to(&poses[1]) > 1e-3 && poses[1].angle_to(&poses[2]) > 1e-3);
    }

    #[test]
    fn held_rests_creep_along_the_path() {
        let p = HandParams::held();
        let m = HandMotion::new(p, 4);
        let still = HandMotion::new(HandParams::by_hand(), 4);
        let cycle = 2.0 * p.ramp_s + p.move_s + p.rest_s;
        let mut creep: f64 = 0.0;
        for k in 0..8 {
            let t = p.initial_rest_s + (k + 1) as f64 * cycle - 0.5 * p.rest_s;
            assert!(m.at_rest(t) && still.at_rest(t));
            let w = m.truth(t).gyr_rad_s.norm();
            assert_eq!(still.truth(t).gyr_rad_s.norm(), 0.0);
            assert!(w > 0.0, "a held rest is never still");
            creep = creep.max(w);
        }
        // 1 % of the motion's speed: at most 1 % of the peak-rate bound
        assert!(creep < 0.01 * m.peak_rate_bound() * 1.001, "{creep}");
        // the initial rest is still (set down before the first move)
        assert_eq!(m.truth(0.5 * p.initial_rest_s).gyr_rad_s, Vec3::zeros());
    }

    #[test]
    fn slow_motion_is_slow() {
        for seed in 0..8 {
            let m = HandMotion::new(HandParams::slow(), seed);
            let peak = (0..20000)
                .map(|k| m.truth(k as f64 * 0.01).gyr_rad_s.norm())
                .fold(0.0, f64::max);
            // seed 3 peaks at 0.354 rad/s for an instant
            assert!(peak < 0.36 && peak > 0.05, "seed {seed}: {peak}");
        }
    }
}

#[cfg(test)]
mod filter_tests {
    use super::*;
    use crate::eval::{Rms, inclination_error};
    use crate::sim::motion::{ConeAxis, Conical, Orbit, Sum};
    use clino_core::Vec3;
    use clino_core::filter::FilterSpec;
    use clino_core::pipeline::Pipeline;

    /// Inclination RMSE (°) of `dynamic` over the first 20 s of `params`'
    /// motion at `rate` Hz switched on already moving (no initial rest).
    fn started_in_motion(params: HandParams, rate: f64, seed: u64) -> f64 {
        let p = HandParams {
            initial_rest_s: 0.0,
            ..params
        };
        let hand = HandMotion::new(p, seed);
        let s = crate::sim::slewing::sensor()
            .with_bandwidth(0.4 * rate)
            .simulate(&hand, rate, 20.0, seed);
        let mut f = Pipeline::new(FilterSpec::default());
        let mut rms = Rms::default();
        for smp in &s {
            let q = f.update(smp).attitude.unwrap_or_else(Attitude::identity);
            rms.push(inclination_error(&q, &hand.truth(smp.t_s).attitude));
        }
        rms.value().to_degrees()
    }

    #[test]
    fn a_sensor_switched_on_in_motion_aligns_before_its_first_rest() {
        // Before its first rest the filter's tilt is only as good as the
        // accelerometer over the motion so far. The slow arm at 100 Hz: with
        // the start-up pull on the moving accelerometer and then the 6.7-s
        // loop, the first 20 s were at 0.17–0.26° (mean 0.23°; VQF 0.17°);
        // with the loop at the start-up's 3-s time constant until the first
        // rest, the start-up pull only while slower than the initial rest
        // threshold and the rest pull at the short rests before it,
        // 0.09–0.14°.
        let e: Vec<f64> = (1..=4)
            .map(|s| started_in_motion(HandParams::slow(), 100.0, s))
            .collect();
        let mean = e.iter().sum::<f64>() / 4.0;
        assert!(mean < 0.16, "{e:?}");
        let h: Vec<f64> = (1..=4)
            .map(|s| started_in_motion(HandParams::by_hand(), 40.0, s))
            .collect();
        // the hand at 40 Hz, whose start-up pull followed the hand's first
        // accelerations until the low-passed rate crossed 20 °/s: 1.10–1.65°
        // (mean 1.36°; VQF 1.17°), now with the rate itself 0.83–1.04°
        let mean = h.iter().sum::<f64>() / 4.0;
        assert!(mean < 1.1, "{h:?}");
    }

    #[test]
    fn dynamic_holds_the_tilt_of_a_slow_vibrating_robot_arm() {
        // Issue 13's robot arm: 125 Hz, accelerometer reading 4 % low,
        // motion under 0.35 rad/s between 2-s rests, 1.5 m/s² of linear and
        // 2°/s of angular vibration at 30 Hz. With the rest detection of
        // commit 24815aa the slow motion passed for rest and was learnt as gyro
        // bias: 2.14° here (the generalisation harness, seed 1, before the fix);
        // VQF gives 0.08°; now ≈ 0.1°.
        let hand = HandMotion::new(HandParams::slow(), 1);
        let f = 30.0;
        let w = 2.0 * PI * f;
        let lin = Orbit {
            amplitude_m: Vec3::new(1.5, 1.0, 1.2) / (w * w),
            phase_rad: Vec3::new(0.0, 1.0, 2.0),
            omega_rad_s: w,
            attitude: Attitude::identity(),
            start_s: f64::NEG_INFINITY,
            ramp_s: 0.0,
        };
        let m = Sum {
            a: Sum { a: hand, b: lin },
            b: Conical::new(ConeAxis::Z, 2f64.to_radians() / w, f),
        };
        let mut model = crate::sim::slewing::sensor().with_bandwidth(50.0);
        model.accel.scale = Vec3::repeat(-0.04);
        let s = model.simulate(&m, 125.0, 120.0, 1);
        let mut p = Pipeline::new(FilterSpec::default());
        let mut rms = Rms::default();
        for smp in &s {
            let q = p.update(smp).attitude.unwrap_or_else(Attitude::identity);
            if smp.t_s > hand.params.initial_rest_s {
                rms.push(inclination_error(&q, &m.truth(smp.t_s).attitude));
            }
        }
        let e = rms.value().to_degrees();
        assert!(e < 0.2, "{e}°");
    }

    /// RMSE (°) after the initial rest of the dynamic filter with `params`,
    /// and the filter at the end.
    fn run_hand(
        hand: &HandMotion,
        model: &crate::sim::ImuModel,
        params: clino_core::filter::DynamicParams,
    ) -> (f64, clino_core::filter::Dynamic) {
        run_hand_for(hand, model, params, 120.0)
    }

    /// [`run_hand`] over `seconds` of the motion.
    fn run_hand_for(
        hand: &HandMotion,
        model: &crate::sim::ImuModel,
        params: clino_core::filter::DynamicParams,
        seconds: f64,
    ) -> (f64, clino_core::filter::Dynamic) {
        use clino_core::filter::AttitudeFilter;
        let s = model.simulate(hand, 100.0, seconds, 2);
        let mut d = clino_core::filter::Dynamic::new(params);
        let mut rms = Rms::default();
        for smp in &s {
            d.update(smp.gyr_rad_s, smp.acc_m_s2, 0.01);
            if smp.t_s > hand.params.initial_rest_s {
                rms.push(inclination_error(
                    &d.attitude(),
                    &hand.truth(smp.t_s).attitude,
                ));
            }
        }
        (rms.value().to_degrees(), d)
    }

    #[test]
    fn gyro_scale_errors_are_learnt_from_rest_to_rest() {
        // An uncalibrated gyro, (+2, −1.5, +1) % scale errors, moved by hand
        // between 3-s rests (100 Hz): without the learning the loop takes the
        // scale error for bias, the bias leaves the rest threshold behind and
        // the tilt error is ≈ 1.1° (1.12× VQF, BENCHMARKS.md); learnt from the
        // gravity directions of successive rests the scale comes within a
        // fraction of a percent and the error halves.
        let hand = HandMotion::new(HandParams::by_hand(), 2);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let truth = Vec3::new(0.02, -0.015, 0.01);
        model.gyro.scale = truth;
        let on = clino_core::filter::DynamicParams::default();
        let off = clino_core::filter::DynamicParams {
            gyro_scale_sigma: 0.0,
            ..on
        };
        let (e_on, d_on) = run_hand(&hand, &model, on);
        let (e_off, d_off) = run_hand(&hand, &model, off);
        let s = d_on.gyro_scale();
        println!("learnt {s:?}: {e_on}° against {e_off}° without");
        assert_eq!(d_off.gyro_scale(), Vec3::zeros());
        for i in 0..3 {
            assert!((s[i] - truth[i]).abs() < 0.005, "{s:?}");
        }
        assert!(e_on < 0.6 * e_off, "{e_on}° against {e_off}°");
        // a calibrated gyro learns (nearly) nothing
        let cal = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let (c_on, dc) = run_hand(&hand, &cal, on);
        let (c_off, _) = run_hand(&hand, &cal, off);
        println!(
            "calibrated: learnt {:?}: {c_on}° against {c_off}°",
            dc.gyro_scale()
        );
        // weighted by the evidence that there is any scale error: < 0.01 %
        // (the posterior mean alone, before that weighting: up to 0.09 %)
        assert!(dc.gyro_scale().amax() < 0.0005, "{:?}", dc.gyro_scale());
        assert!(c_on < 1.1 * c_off, "{c_on}° against {c_off}°");
    }

    #[test]
    fn accelerometer_scale_errors_are_learnt_with_the_gyros() {
        // An accelerometer with (+5, −5, +3) % scale errors (an MPU6050 is
        // within ±3 % out of the box), moved by hand between 3-s rests at
        // 100 Hz: each pose's gravity direction is off by P_u·diag(u)·d, up to
        // 2.9° at 45° of tilt, and every filter holds it as an offset (VQF
        // 1.06° on the grid). The gyro carries the direction from rest to
        // rest, and the misses reveal d up to a common scale, which does not
        // turn the direction.
        let hand = HandMotion::new(HandParams::by_hand(), 2);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let truth = Vec3::new(0.05, -0.05, 0.03);
        model.accel.scale = truth;
        let on = clino_core::filter::DynamicParams::default();
        let off = clino_core::filter::DynamicParams {
            accel_scale_sigma: 0.0,
            ..on
        };
        // 300 s: one observation per rest pair (≈ 12 s apart), each seeing the
        // scale errors through poses within ±35° of level, where the direction
        // error is ≈ sin θ·cos θ·(d_x − d_z): about 25 pairs are needed to pin
        // them down (with one evidence for all of the learner's errors: after
        // 120 s 1.09° → 1.02°, after 300 s 1.11° → 0.78°; with each group's
        // own evidence, 300 s: 0.88° → 0.59°, learnt (2.9, −4.9, 2.1) %)
        let (e_on, d_on) = run_hand_for(&hand, &model, on, 300.0);
        let (e_off, d_off) = run_hand_for(&hand, &model, off, 300.0);
        let d = d_on.accel_scale();
        println!(
            "learnt {d:?} (gyro {:?}): {e_on}° against {e_off}° without",
            d_on.gyro_scale()
        );
        assert_eq!(d_off.accel_scale(), Vec3::zeros());
        // the differential part: truth and estimate less their means
        let diff = |v: Vec3| v - Vec3::repeat(v.mean());
        let miss = diff(d) - diff(truth);
        assert!(miss.amax() < 0.02, "{d:?}: {miss:?}");
        assert!(e_on < 0.8 * e_off, "{e_on}° against {e_off}°");
        // the accelerometer's error is not taken for the gyro's
        assert!(d_on.gyro_scale().amax() < 0.005, "{:?}", d_on.gyro_scale());
        // a calibrated accelerometer learns (nearly) nothing
        let cal = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let (c_on, dc) = run_hand(&hand, &cal, on);
        let (c_off, _) = run_hand(&hand, &cal, off);
        println!(
            "calibrated: learnt {:?}: {c_on}° against {c_off}°",
            dc.accel_scale()
        );
        assert!(dc.accel_scale().amax() < 0.002, "{:?}", dc.accel_scale());
        assert!(c_on < 1.05 * c_off, "{c_on}° against {c_off}°");
    }

    /// The hand simulation's sensor (40-Hz bandwidth) with an uncalibrated
    /// accelerometer bias of (7, −10, 5) mg; the bias in m/s²; the default
    /// parameters, and the same without the bias learnt.
    fn biased_accelerometer() -> (
        crate::sim::ImuModel,
        Vec3,
        clino_core::filter::DynamicParams,
        clino_core::filter::DynamicParams,
    ) {
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let truth = Vec3::new(7.0, -10.0, 5.0) * 1e-3 * clino_core::G0;
        model.accel.bias = truth;
        let on = clino_core::filter::DynamicParams::default();
        let off = clino_core::filter::DynamicParams {
            accel_bias_sigma: 0.0,
            ..on
        };
        (model, truth, on, off)
    }

    #[test]
    fn accelerometer_bias_is_learnt_from_turns_between_rests() {
        // An uncalibrated accelerometer bias, (7, −10, 5) mg, moved by hand
        // between 3-s rests (100 Hz): the horizontal part turns the gravity
        // direction by b/g ≈ 0.7° at every pose, and every filter holds it
        // (VQF 0.62° on the grid). A turn between two rests points the
        // body-frame bias another way in the world; the gyro-carried
        // direction then misses the measured one by (C·P_u1 − P_u0)·b/g.
        let hand = HandMotion::new(HandParams::by_hand(), 2);
        let (model, truth, on, off) = biased_accelerometer();
        let (e_on, d_on) = run_hand_for(&hand, &model, on, 300.0);
        let (e_off, d_off) = run_hand_for(&hand, &model, off, 300.0);
        let b = d_on.accel_bias();
        println!(
            "learnt {:?} mg (scale {:?}): {e_on}° against {e_off}° without",
            b / (1e-3 * clino_core::G0),
            d_on.accel_scale()
        );
        assert_eq!(d_off.accel_bias(), Vec3::zeros());
        // One pair's direction miss from 12 mg across gravity is ≈ 0.005 rad.
        // Trusted to the prior 0.02 rad a pair (what an MPU6050's cross-axis
        // sensitivity leaves, not modelled here), 25 pairs took the bias only
        // to about a sixth (|Δb| 0.83 of |b|, 0.95× the tilt error without).
        // The pairs' own residual says this sensor leaves ≈ 0.005 rad, and at
        // that noise they learn it to within a fifth.
        let (bh, th) = (b.xy(), truth.xy());
        let r = d_on.pair_noise_rad();
        println!(
            "pair noise {r} rad, |Δb_xy| {}",
            (bh - th).norm() / th.norm()
        );
        assert!(r < 0.5 * 0.02, "{r} rad");
        assert!((bh - th).norm() < 0.3 * th.norm(), "{bh:?} against {th:?}");
        assert!(e_on < 0.8 * e_off, "{e_on}° against {e_off}°");
        // a calibrated accelerometer learns (nearly) nothing
        let cal = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let (c_on, dc) = run_hand_for(&hand, &cal, on, 300.0);
        let (c_off, _) = run_hand_for(&hand, &cal, off, 300.0);
        println!(
            "calibrated: learnt {:?} mg: {c_on}° against {c_off}°",
            dc.accel_bias() / (1e-3 * clino_core::G0)
        );
        assert!(c_on < 1.05 * c_off, "{c_on}° against {c_off}°");
    }

    /// A pair from (nearly) every rest, the horizontal bias learnt the right
    /// way, and the tilt better for it (`e_on` against `e_off` without the
    /// bias learnt), after `moves` moves.
    fn assert_bias_learnt_from_pairs(
        d_on: &clino_core::filter::Dynamic,
        truth: Vec3,
        moves: f64,
        e_on: f64,
        e_off: f64,
    ) {
        let b = d_on.accel_bias();
        println!(
            "{} pairs in {moves:.0} moves, learnt {:?} mg: {e_on}° against {e_off}° without",
            d_on.rest_pairs(),
            b / (1e-3 * clino_core::G0),
        );
        assert!(
            f64::from(d_on.rest_pairs()) > 0.8 * moves,
            "{} pairs in {moves:.0} moves",
            d_on.rest_pairs()
        );
        let (bh, th) = (b.xy(), truth.xy());
        assert!(
            bh.dot(&th) > 0.1 * th.norm_squared(),
            "{bh:?} against {th:?}"
        );
        assert!(e_on < 0.95 * e_off, "{e_on}° against {e_off}°");
    }

    #[test]
    fn one_second_rests_are_rest_pairs_too() {
        // The accelerometer bias of the test above, (7, −10, 5) mg, but the hand
        // rests 1 s between moves. Rest proper waits for its 0.2-s and 0.25-s
        // low-passes to settle after a fast move (1–1.5 s), then 1.5 s more:
        // a 1-s rest was never declared, no rest pair was formed (0 pairs in
        // 300 s) and the bias stayed in the tilt (0.97× VQF on the grid). The
        // learner's own short-rest detector (a 0.05-s low-pass, 0.5 s under the
        // rest thresholds) forms one pair per rest.
        let params = HandParams {
            rest_s: 1.0,
            ..HandParams::by_hand()
        };
        let hand = HandMotion::new(params, 2);
        let (model, truth, on, off) = biased_accelerometer();
        let (e_on, d_on) = run_hand_for(&hand, &model, on, 300.0);
        let (e_off, _) = run_hand_for(&hand, &model, off, 300.0);
        let moves = (300.0 - params.initial_rest_s) / (params.move_s + params.rest_s);
        assert_bias_learnt_from_pairs(&d_on, truth, moves, e_on, e_off);
    }

    #[test]
    fn rests_in_vibration_are_rest_pairs() {
        // A slow robot arm (moves of 12 s, rests of 2 s, 125 Hz) on a base
        // vibrating at 30 Hz with 2°/s and 1.5 m/s², accelerometer 4 % low.
        // Rest proper is declared 1.5 s after its low-passes settle, so it
        // caught about half the 2-s rests; the short-rest detector's single
        // 0.05-s pole left 0.16 m/s² of the vibration, over the 0.2 m/s²
        // threshold at its peaks, and caught none. Two poles (89 times down
        // at 30 Hz) catch every rest: on the grid this took the arm with
        // ±5 % accelerometer scale errors from 1.00× to 0.89× VQF.
        use crate::sim::motion::{Sum, vibration};
        use clino_core::filter::AttitudeFilter;
        let params = HandParams::slow();
        let (rate, seconds) = (125.0, 240.0);
        let m = Sum {
            a: HandMotion::new(params, 1),
            b: vibration(30.0, 2f64.to_radians(), Vec3::new(1.5, 1.0, 1.2)),
        };
        let mut model = crate::sim::slewing::sensor().with_bandwidth(0.4 * rate);
        model.accel.scale = Vec3::repeat(-0.04);
        let s = model.simulate(&m, rate, seconds, 1);
        let mut d = clino_core::filter::Dynamic::default();
        for smp in &s {
            d.update(smp.gyr_rad_s, smp.acc_m_s2, 1.0 / rate);
        }
        let moves = (seconds - params.initial_rest_s) / (params.move_s + params.rest_s);
        println!(
            "{} pairs in {moves:.0} moves; accelerometer scale learnt {:?}",
            d.rest_pairs(),
            d.accel_scale()
        );
        assert!(
            f64::from(d.rest_pairs()) > 0.8 * moves,
            "{} pairs in {moves:.0} moves",
            d.rest_pairs()
        );
    }

    #[test]
    fn held_poses_are_rests_for_the_tilt_and_the_learner() {
        // The hand of the tests above with its rests held in the air rather
        // than set down (`HandParams::held`: the pose creeps on at 0.6–1.7°/s,
        // over the 0.5°/s rest threshold) and a 9-Hz tremor, 100 Hz, an
        // uncalibrated accelerometer bias of (7, −10, 5) mg. No rest and
        // almost no short rest is declared, so the learner formed no pairs
        // (the generalisation grid: 1.02–1.08× VQF at 25–1000 Hz, 0.94–0.99×
        // with them) and the move's tilt error stayed at the held pose (1000 Hz
        // calibrated: 1.23× VQF's error at rest, 1.07× now). A held pose is
        // the short rest's test with rotation allowed: the low-passed specific
        // force turns only as the gyro says.
        use crate::sim::motion::{Sum, vibration};
        use clino_core::filter::{AttitudeFilter, DynamicParams};
        let params = HandParams::held();
        let (rate, seconds) = (100.0, 300.0);
        let hand = HandMotion::new(params, 2);
        let m = Sum {
            a: hand,
            b: vibration(9.0, 1f64.to_radians(), Vec3::new(0.1, 0.08, 0.06)),
        };
        let (model, truth, on, off) = biased_accelerometer();
        let s = model.simulate(&m, rate, seconds, 3);
        let run = |p: DynamicParams| {
            let mut d = clino_core::filter::Dynamic::new(p);
            let mut rms = Rms::default();
            for smp in &s {
                d.update(smp.gyr_rad_s, smp.acc_m_s2, 1.0 / rate);
                if smp.t_s > params.initial_rest_s {
                    rms.push(inclination_error(&d.attitude(), &m.truth(smp.t_s).attitude));
                }
            }
            (rms.value().to_degrees(), d)
        };
        let (e_on, d_on) = run(on);
        let (e_off, _) = run(off);
        let moves = (seconds - params.initial_rest_s) / (params.move_s + params.rest_s);
        assert_bias_learnt_from_pairs(&d_on, truth, moves, e_on, e_off);
    }

    #[test]
    fn the_offline_smoother_uses_what_the_learner_learnt() {
        // Gyro (+2, −1.5, +1) % and accelerometer (+5, −5, +3) % scale errors,
        // hand motion, 100 Hz, 120 s. The smoother's last two passes do not
        // learn; before they were given the accelerometer scale errors and bias
        // its second pass had learnt (and the refinement the corrected specific force),
        // the offline tilt was worse than the real-time one (here 1.48° against
        // 1.38°); with the accelerometer's (the gyro scale is not imposed,
        // see `smooth`) 0.84°, and 0.61° were the gyro's imposed too.
        use crate::smooth::{SmoothOptions, smooth};
        use clino_core::filter::AttitudeFilter;
        let hand = HandMotion::new(HandParams::by_hand(), 3);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        model.gyro.scale = Vec3::new(0.02, -0.015, 0.01);
        model.accel.scale = Vec3::new(0.05, -0.05, 0.03);
        let s = model.simulate(&hand, 100.0, 120.0, 5);
        let gyr: Vec<Vec3> = s.iter().map(|x| x.gyr_rad_s).collect();
        let acc: Vec<Vec3> = s.iter().map(|x| x.acc_m_s2).collect();
        let dt = vec![0.01; s.len()];
        let off = smooth(&gyr, &acc, &dt, &SmoothOptions::default());
        let mut d = clino_core::filter::Dynamic::default();
        let (mut e_rt, mut e_off) = (Rms::default(), Rms::default());
        for (k, smp) in s.iter().enumerate() {
            d.update(smp.gyr_rad_s, smp.acc_m_s2, 0.01);
            if smp.t_s > hand.params.initial_rest_s {
                let truth = hand.truth(smp.t_s).attitude;
                e_rt.push(inclination_error(&d.attitude(), &truth));
                e_off.push(inclination_error(&off[k], &truth));
            }
        }
        let (rt, of) = (e_rt.value().to_degrees(), e_off.value().to_degrees());
        println!("real time {rt}°, offline {of}°");
        assert!(of < 0.8 * rt, "offline {of}° against real time {rt}°");
    }

    /// Offline tilt RMSE (°, after the initial rest) of `hand` through
    /// `model` at 100 Hz over 120 s, smoothed with the refinement's gyro
    /// model at weight 0 (the residual model alone), 1/2 (the equal pool),
    /// 1 (the gyro model alone) and the default (from the learner's doubt).
    fn offline_errors_by_gyro_weight(
        hand: &HandMotion,
        model: &crate::sim::ImuModel,
    ) -> (f64, f64, f64, f64) {
        use crate::smooth::{BoundedMotion, SmoothOptions, smooth};
        let s = model.simulate(hand, 100.0, 120.0, 7);
        let gyr: Vec<Vec3> = s.iter().map(|x| x.gyr_rad_s).collect();
        let acc: Vec<Vec3> = s.iter().map(|x| x.acc_m_s2).collect();
        let dt = vec![0.01; s.len()];
        let at = |w: Option<f64>| {
            let opts = SmoothOptions {
                refine: Some(BoundedMotion {
                    gyro_weight: w,
                    ..Default::default()
                }),
                ..Default::default()
            };
            let off = smooth(&gyr, &acc, &dt, &opts);
            let mut e = Rms::default();
            for (k, smp) in s.iter().enumerate() {
                if smp.t_s > hand.params.initial_rest_s {
                    e.push(inclination_error(&off[k], &hand.truth(smp.t_s).attitude));
                }
            }
            e.value().to_degrees()
        };
        let (residual, pool, gyro) = (at(Some(0.0)), at(Some(0.5)), at(Some(1.0)));
        let default = at(None);
        println!("residual {residual}°, pool {pool}°, gyro {gyro}°, default {default}°");
        (residual, pool, gyro, default)
    }

    #[test]
    fn the_gyro_model_removes_what_the_loop_took_from_the_motion() {
        // A calibrated gyro, hand motion: what the smoother's passes still get
        // wrong is mostly the mount's acceleration their loop took for tilt,
        // which the gyro does not confirm. The refinement's residual model
        // keeps those corrections (offline 1.2–1.5× offline VQF on the
        // simulated grid); the gyro model undoes them unless bounded motion
        // confirms them. Measured: residual alone ≈ 0.13°, gyro model alone
        // ≈ 0.07°, the default pool of both in between.
        let hand = HandMotion::new(HandParams::by_hand(), 4);
        let model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let (residual, pool, gyro, default) = offline_errors_by_gyro_weight(&hand, &model);
        assert!(gyro < 0.7 * residual, "{gyro}° against {residual}°");
        assert!(pool < 0.85 * residual, "{pool}° against {residual}°");
        assert!(gyro < pool, "{gyro}° against {pool}°");
        // the rest pairs have pinned this gyro down and fit: the default
        // weight leans to the gyro model
        assert!(
            default < pool - 0.5 * (pool - gyro),
            "{default}° against {pool}°, {gyro}°"
        );
    }

    #[test]
    fn the_gyro_model_carries_the_learnt_gyro_scale() {
        // Gyro (+2, −1.5, +1) % scale errors: a gyro model without the scale
        // the passes learnt would undo the corrections that removed them.
        // Measured here, with the learnt scale imposed in the tilt passes too
        // (`SmoothOptions::scale`): the residual model 0.107°, the pool
        // 0.077°, the gyro model alone 0.063°, the default 0.064°; with the
        // gyro model's scale left out, 0.246°, 0.466° and 0.409°.
        let hand = HandMotion::new(HandParams::by_hand(), 5);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        model.gyro.scale = Vec3::new(0.02, -0.015, 0.01);
        let (residual, pool, gyro, default) = offline_errors_by_gyro_weight(&hand, &model);
        assert!(pool < 0.8 * residual, "{pool}° against {residual}°");
        assert!(default < pool, "{default}° against {pool}°");
        // the gyro model alone, which without the learnt scale is worse than
        // the residual model
        assert!(gyro < 0.7 * residual, "{gyro}° against {residual}°");
    }
}
