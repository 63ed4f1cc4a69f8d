//! A slewing machine: chassis on a slope, upper structure turning about the
//! chassis z axis, inclinometer off the axis.
//!
//! This is the rotating platform of "inclination sensing on a rotating
//! platform, with tangential and radial acceleration errors removed using a
//! rate gyro" (the patent behind [`clino_core::compensate`]), made concrete
//! as an excavator or crane:
//!
//! * the chassis stands still on a slope: attitude q_c (roll, pitch, heading);
//! * the upper structure slews about the chassis z axis by β(t), with a
//!   jerk-limited rate profile (smooth-step ramps between rest, ±ω_max
//!   cruises and dwells), so ω̇ and the jerk are bounded;
//! * the inclinometer is fixed to the upper structure at lever arm **p**
//!   (metres, upper-structure frame, from a point on the slew axis); its body
//!   frame is the upper structure's;
//! * the engine shakes the sensor: a small linear vibration of the sensor point
//!   (amplitude in m/s², frequency in Hz) and a small angular vibration about
//!   the body x axis.
//!
//! Truth: q(t) = q_c ⊗ q_z(β(t)) ⊗ q_x(ν(t)), ν the angular vibration of the
//! rigid upper structure about the reference point on the slew axis; the
//! sensor point is at q(t)·p, plus the engine's small linear vibration. The
//! tilt of the upper structure is the chassis tilt (it turns about its own
//! z axis), but its direction in the body frame turns with β.

use super::{Motion, Truth};
use crate::fusion::{FilterKind, FilterSpec, Pipeline};
use clino_core::{Attitude, Vec3};
use nalgebra::{UnitQuaternion, Vector3};
use std::f64::consts::PI;

/// Parameters of the slewing machine. Angles in radians, lengths in metres.
#[derive(Clone, Debug, PartialEq)]
pub struct SlewingPlatform {
    /// Chassis roll on the slope, rad (z-y-x).
    pub chassis_roll: f64,
    /// Chassis pitch on the slope, rad (z-y-x).
    pub chassis_pitch: f64,
    /// Chassis heading, rad.
    pub chassis_heading: f64,
    /// Lever arm of the sensor from the slew axis, m (upper-structure frame).
    pub lever_arm_m: Vec3,
    /// Largest slew rate, rad/s.
    pub max_rate_rad_s: f64,
    /// Duration of one smooth-step ramp between rates, s. The peak angular
    /// acceleration of a ramp of Δω is 1.5·Δω/T and its jerk 6·Δω/T².
    pub ramp_s: f64,
    /// Time at constant slew rate in each move, s.
    pub cruise_s: f64,
    /// Time at rest between moves, s.
    pub dwell_s: f64,
    /// Rest before the first move, s.
    pub initial_rest_s: f64,
    /// Amplitude of the engine's linear vibration of the sensor point, m/s² (body x and z).
    pub vibration_m_s2: f64,
    /// Amplitude of the engine's angular vibration about body x, rad/s.
    pub vibration_rate_rad_s: f64,
    /// Engine vibration frequency, Hz.
    pub vibration_hz: f64,
}

impl Default for SlewingPlatform {
    /// An excavator on a 6° slope (roll 4°, pitch −4.5°), sensor 2.5 m from the
    /// slew axis at 30° from the upper structure's x axis and 1.2 m up; slews
    /// of ±1 rad/s with 1.5-s ramps (peak 1 rad/s², jerk ≤ 2.7 rad/s³), 4-s
    /// cruises, 3-s dwells; engine at 30 Hz shaking the sensor by 0.5 m/s² and
    /// 0.5°/s.
    fn default() -> Self {
        Self {
            chassis_roll: 4f64.to_radians(),
            chassis_pitch: (-4.5f64).to_radians(),
            chassis_heading: 0.7,
            lever_arm_m: Vector3::new(2.5 * (PI / 6.0).cos(), 2.5 * (PI / 6.0).sin(), 1.2),
            max_rate_rad_s: 1.0,
            ramp_s: 1.5,
            cruise_s: 4.0,
            dwell_s: 3.0,
            initial_rest_s: 10.0,
            vibration_m_s2: 0.5,
            vibration_rate_rad_s: 0.5f64.to_radians(),
            vibration_hz: 30.0,
        }
    }
}

/// Smooth step s(x) = 3x² − 2x³ on [0, 1] and its first two derivatives.
fn smoothstep(x: f64) -> (f64, f64, f64) {
    if x <= 0.0 {
        (0.0, 0.0, 0.0)
    } else if x >= 1.0 {
        (1.0, 0.0, 0.0)
    } else {
        (x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x), 6.0 - 12.0 * x)
    }
}

impl SlewingPlatform {
    /// The chassis attitude q_c.
    pub fn chassis(&self) -> Attitude {
        UnitQuaternion::from_euler_angles(
            self.chassis_roll,
            self.chassis_pitch,
            self.chassis_heading,
        )
    }

    /// Inclination of the upper structure (= of the chassis), rad.
    pub fn inclination(&self) -> f64 {
        clino_core::tilt::inclination(&self.chassis())
    }

    /// Duration of one cycle (a move out and a move back), s.
    pub fn cycle_s(&self) -> f64 {
        2.0 * (2.0 * self.ramp_s + self.cruise_s + self.dwell_s)
    }

    /// Slew angle β, rate ω and acceleration ω̇ at time t (rad, rad/s, rad/s²).
    ///
    /// Each move: ramp up to ±ω_max (smooth step over `ramp_s`), cruise, ramp
    /// down, dwell; moves alternate in direction, so β stays bounded.
    pub fn slew(&self, t: f64) -> (f64, f64, f64) {
        let t = t - self.initial_rest_s;
        if t <= 0.0 {
            return (0.0, 0.0, 0.0);
        }
        let (tr, tc, td, w) = (
            self.ramp_s,
            self.cruise_s,
            self.dwell_s,
            self.max_rate_rad_s,
        );
        let move_len = 2.0 * tr + tc + td;
        let travel = w * (tr + tc); // angle of one move (a smooth-step ramp covers w·T/2)
        let k = (t / move_len).floor();
        let tm = t - k * move_len;
        let dir = if (k as i64) % 2 == 0 { 1.0 } else { -1.0 };
        // moves alternate: the angle after an even number of moves is 0, after an odd number `travel`
        let base = if (k as i64) % 2 == 0 { 0.0 } else { travel };
        let (rate, acc, angle);
        if tm < tr {
            let (s, ds, _) = smoothstep(tm / tr);
            let (_, _, _) = (s, ds, 0.0);
            rate = w * s;
            acc = w * ds / tr;
            // ∫ s = tr·(x³ − x⁴/2)
            let x = tm / tr;
            angle = w * tr * (x * x * x - 0.5 * x * x * x * x);
        } else if tm < tr + tc {
            rate = w;
            acc = 0.0;
            angle = w * tr * 0.5 + w * (tm - tr);
        } else if tm < 2.0 * tr + tc {
            let x = (tm - tr - tc) / tr;
            let (s, ds, _) = smoothstep(x);
            rate = w * (1.0 - s);
            acc = -w * ds / tr;
            angle = w * tr * 0.5 + w * tc + w * tr * (x - (x * x * x - 0.5 * x * x * x * x));
        } else {
            rate = 0.0;
            acc = 0.0;
            angle = travel;
        }
        (base + dir * angle, dir * rate, dir * acc)
    }
}

impl Motion for SlewingPlatform {
    fn truth(&self, t: f64) -> Truth {
        let (beta, w, w_dot) = self.slew(t);
        let omega_v = 2.0 * PI * self.vibration_hz;
        // angular vibration about body x: rate r·sin(Ωt), angle −r/Ω·cos(Ωt) + r/Ω
        let nu_rate = self.vibration_rate_rad_s * (omega_v * t).sin();
        let nu_acc = self.vibration_rate_rad_s * omega_v * (omega_v * t).cos();
        let nu = self.vibration_rate_rad_s / omega_v * (1.0 - (omega_v * t).cos());
        let qc = self.chassis();
        let qz = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), beta);
        let qx = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), nu);
        let attitude = qc * qz * qx;
        // body rate: the slew rate about upper z, seen in the body (after q_x), plus the vibration about x
        let ez_b = qx.inverse_transform_vector(&Vector3::z());
        let gyr = ez_b * w + Vector3::new(nu_rate, 0.0, 0.0);
        // d/dt of ez_b·w: ez_b turns with −ν̇ about x: d(ez_b)/dt = ez_b × (ν̇ e_x)
        let ang_acc = ez_b * w_dot
            + ez_b.cross(&Vector3::new(nu_rate, 0.0, 0.0)) * w
            + Vector3::new(nu_acc, 0.0, 0.0);
        // The upper structure is rigid and turns (slew and angular vibration) about the
        // reference point on the slew axis, so the sensor point at body lever arm p has
        // nav position A·p, velocity A·(ω × p) and acceleration A·(ω̇ × p + ω × (ω × p)),
        // A = attitude. The engine's linear vibration adds a·sin(Ωt + 0.3) along a
        // fixed body direction (its displacement, ≈ 10 µm, is left out of the position).
        let p = self.lever_arm_m;
        let la = clino_core::compensate::lever_arm_acceleration(&gyr, &ang_acc, &p);
        let vib_dir = Vector3::new(1.0, 0.0, 1.0) / 2f64.sqrt();
        let phase = omega_v * t + 0.3;
        let vib_b_acc = vib_dir * (self.vibration_m_s2 * phase.sin());
        let vib_b_vel = vib_dir * (-self.vibration_m_s2 / omega_v * phase.cos());
        let pos_m = attitude * p;
        let vel_m_s = attitude * (gyr.cross(&p) + vib_b_vel);
        let acc_m_s2 = attitude * (la + vib_b_acc);
        Truth {
            t_s: t,
            attitude,
            gyr_rad_s: gyr,
            ang_acc_rad_s2: ang_acc,
            pos_m,
            vel_m_s,
            acc_m_s2,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn slew_profile_is_consistent_and_limited() {
        let m = SlewingPlatform::default();
        let h = 1e-5;
        let mut max_a: f64 = 0.0;
        let mut max_w: f64 = 0.0;
        let mut t = 0.0;
        while t < 2.0 * m.cycle_s() + 12.0 {
            let (b0, w0, a0) = m.slew(t);
            let (b1, w1, _) = m.slew(t + h);
            let (bm, wm, _) = m.slew(t - h);
            // rate is the derivative of angle, acceleration of rate (central differences)
            assert!(((b1 - bm) / (2.0 * h) - w0).abs() < 1e-6, "t {t}");
            assert!(((w1 - wm) / (2.0 * h) - a0).abs() < 1e-4, "t {t}");
            assert!(b0.abs() < 20.0);
            max_a = max_a.max(a0.abs());
            max_w = max_w.max(w0.abs());
            t += 0.0137;
        }
        assert!(max_w <= 1.0 + 1e-12 && max_w > 0.99);
        assert!(max_a <= 1.0 + 1e-9 && max_a > 0.95, "peak ω̇ {max_a}");
    }

    #[test]
    fn truth_is_self_consistent() {
        let m = SlewingPlatform::default();
        for &t in &[0.0, 11.0, 12.3, 15.7, 21.0, 33.3] {
            let tr = m.truth(t);
            let h = 1e-6;
            let (a, b) = (m.truth(t - h), m.truth(t + h));
            // body rate from the attitude's central difference
            let w_fd = (a.attitude.inverse() * b.attitude).scaled_axis() / (2.0 * h);
            assert_relative_eq!(w_fd, tr.gyr_rad_s, epsilon = 1e-6);
            let wd_fd = (b.gyr_rad_s - a.gyr_rad_s) / (2.0 * h);
            assert_relative_eq!(wd_fd, tr.ang_acc_rad_s2, epsilon = 1e-4);
            // inclination is the chassis'
            let inc = clino_core::tilt::inclination(&tr.attitude);
            assert!((inc - m.inclination()).abs() < 1e-3);
        }
    }

    #[test]
    fn specific_force_is_lever_arm_plus_gravity_without_vibration() {
        let m = SlewingPlatform {
            vibration_m_s2: 0.0,
            vibration_rate_rad_s: 0.0,
            ..Default::default()
        };
        for &t in &[10.5, 11.0, 13.0, 17.2] {
            let tr = m.truth(t);
            let f = tr.specific_force(clino_core::G0);
            let la = clino_core::compensate::lever_arm_acceleration(
                &tr.gyr_rad_s,
                &tr.ang_acc_rad_s2,
                &m.lever_arm_m,
            );
            let g_b = tr
                .attitude
                .inverse_transform_vector(&Vector3::new(0.0, 0.0, clino_core::G0));
            assert_relative_eq!(f, la + g_b, epsilon = 1e-9);
        }
    }
}

/// The inclinometer of the slewing-machine scenario: the `mpu6050` preset
/// (datasheet noise, bandwidth, quantisation, bias instability and random
/// walk; gyro bias residual of a power-on average) with both triads
/// calibrated as the MPU6050 inclinometer source does (multi-position for the
/// accelerometer, rate table for the gyro): bias, scale and cross-axis a
/// tenth of the preset's (accelerometer 0.5/−0.4/0.8 mg, ≤ 0.03 %, 0.02 %;
/// gyro ≤ 0.03 % scale, 0.02 % cross-axis).
///
/// Why calibrated: an accelerometer bias b leaves a tilt error of b/g at rest
/// whatever the filter (1 mg is 0.057°), and a gyro cross-axis error c turns
/// a slew at ω into a tilt drift c·ω (0.2 % at 1 rad/s is 0.11°/s), so with
/// the preset's residuals no filter shows a dynamic error below 0.2–0.3°;
/// this scenario measures the dynamics. [`evaluate`] takes any model, the
/// preset included (BENCHMARKS.md lists both).
pub fn sensor() -> super::ImuModel {
    let mut m = super::ImuModel::mpu6050();
    m.name = "mpu6050 (accelerometer calibrated)".into();
    m.accel.bias *= 0.1;
    m.accel.scale *= 0.1;
    m.accel.cross_axis *= 0.1;
    m.gyro.scale *= 0.1;
    m.gyro.cross_axis *= 0.1;
    m
}

/// Inclination error of one filter on a simulated slewing machine.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SlewingScore {
    /// Filter name.
    pub filter: String,
    /// Inclination RMSE without lever-arm compensation, degrees.
    pub uncompensated_deg: f64,
    /// Inclination RMSE with lever-arm compensation, degrees.
    pub compensated_deg: f64,
    /// Largest inclination error with compensation, degrees.
    pub compensated_max_deg: f64,
}

/// Simulate `duration_s` of the machine through `model` at `rate_hz` (seed
/// `seed`) and score each filter with and without compensation, each run
/// through the one [`Pipeline`]. Errors (BROAD's inclination error,
/// [`crate::eval::inclination_error`]) are scored after the initial rest
/// (while the machine slews and dwells); a non-finite estimate makes the
/// score NaN.
pub fn evaluate(
    platform: &SlewingPlatform,
    model: &super::ImuModel,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
    filters: &[FilterSpec],
) -> crate::Result<Vec<SlewingScore>> {
    use crate::eval::{Rms, inclination_error};
    let samples = model.simulate(platform, rate_hz, duration_s, seed);
    let truth: Vec<Attitude> = (0..samples.len())
        .map(|k| platform.truth(samples[k].t_s).attitude)
        .collect();
    let score = |mut p: Pipeline| {
        let (mut rms, mut max) = (Rms::default(), 0.0f64);
        for (smp, q) in samples.iter().zip(&truth) {
            let est = p.update(smp).attitude.unwrap_or_else(Attitude::identity);
            if smp.t_s > platform.initial_rest_s {
                let e = inclination_error(&est, q);
                rms.push(e);
                max = max.max(e);
            }
        }
        (rms.value().to_degrees(), max.to_degrees())
    };
    filters
        .iter()
        .map(|spec| {
            // as `clino fuse` runs them, with and without `--lever-arm` (with the
            // dynamic filter, the lever arm also turns on the bias estimate)
            let config = crate::fusion::FilterConfig::from_spec(*spec);
            let arm = config.with_lever_arm(Some(platform.lever_arm_m));
            let (unc, _) = score(config.pipeline()?);
            let (com, max) = score(arm.pipeline()?);
            Ok(SlewingScore {
                filter: crate::fusion::spec_text(spec),
                uncompensated_deg: unc,
                compensated_deg: com,
                compensated_max_deg: max,
            })
        })
        .collect()
}

#[cfg(test)]
mod eval_tests {
    use super::*;

    #[test]
    fn compensation_makes_the_dynamic_filter_exact_on_a_slewing_excavator() {
        let m = SlewingPlatform::default();
        let model = sensor();
        let r = evaluate(
            &m,
            &model,
            200.0,
            100.0,
            1,
            &[FilterKind::Dynamic, FilterKind::Mahony].map(FilterSpec::default_for),
        )
        .unwrap();
        let (d, mh) = (&r[0], &r[1]);
        assert!(d.compensated_deg <= 0.1, "{d:?}");
        assert!(d.compensated_deg * 5.0 <= d.uncompensated_deg, "{d:?}");
        // compensation helps any filter (Mahony also suffers from the engine vibration)
        assert!(mh.compensated_deg < mh.uncompensated_deg / 2.0, "{mh:?}");
        assert!(d.compensated_deg < mh.compensated_deg, "{d:?} vs {mh:?}");
    }
}

/// The `clino demo` section: a slewing excavator on a slope, every filter with
/// and without lever-arm compensation (100 s at 200 Hz, seed 1).
pub fn demo_summary() -> crate::Result<String> {
    use std::fmt::Write;
    let m = SlewingPlatform::default();
    let model = sensor();
    let scores = evaluate(
        &m,
        &model,
        200.0,
        100.0,
        1,
        &[
            FilterKind::Dynamic,
            FilterKind::Mahony,
            FilterKind::Madgwick,
            FilterKind::Complementary,
        ]
        .map(FilterSpec::default_for),
    )?;
    let mut s = String::new();
    let p = m.lever_arm_m;
    let _ = writeln!(
        s,
        "Slewing excavator: chassis on a {:.1}° slope, upper structure slewing ±{:.1} rad/s \
         (peak {:.1} rad/s², jerk-limited), sensor at r = {:.2} m from the slew axis \
         (lever arm {:.2}, {:.2}, {:.2} m), engine vibration {:.1} m/s² at {:.0} Hz; {}, 200 Hz, 100 s.",
        m.inclination().to_degrees(),
        m.max_rate_rad_s,
        1.5 * m.max_rate_rad_s / m.ramp_s,
        (p.x * p.x + p.y * p.y).sqrt(),
        p.x,
        p.y,
        p.z,
        m.vibration_m_s2,
        m.vibration_hz,
        model.name
    );
    let _ = writeln!(
        s,
        "  inclination RMSE       without compensation   with --lever-arm"
    );
    for sc in &scores {
        let _ = writeln!(
            s,
            "  {:<14} {:>20.3}° {:>17.3}°",
            sc.filter, sc.uncompensated_deg, sc.compensated_deg
        );
    }
    Ok(s)
}

/// A slewing machine's digging: its whole body translated on an ellipse of
/// 0.3 m/s² (0.15 vertically) at 0.7 Hz from `start_s` (ramped in over
/// 2 s), to be added to a [`SlewingPlatform`] with
/// [`super::motion::Sum`]. The low-passed specific force then swings by
/// more than the rest detector's 0.2 m/s², so the dwells never pass for
/// rest, and a 0.5-s block mean keeps sinc²(0.7·0.25) ≈ 0.9 of it.
pub fn digging(start_s: f64) -> super::motion::Orbit {
    let w = 2.0 * PI * 0.7;
    super::motion::Orbit {
        amplitude_m: Vector3::new(0.3, 0.3, 0.15) / (w * w),
        phase_rad: Vector3::new(0.0, 1.0, 2.0),
        omega_rad_s: w,
        attitude: Attitude::identity(),
        start_s,
        ramp_s: 2.0,
    }
}

#[cfg(test)]
mod mount_tests {
    use super::*;
    use crate::eval::{Rms, inclination_error};
    use clino_core::compensate::MountOptions;
    use clino_core::pipeline::Pipeline as CorePipeline;

    const MG: f64 = 1e-3 * clino_core::G0;

    /// RMSE (degrees) after the initial rest, and the final estimator.
    fn run(
        motion: &dyn Motion,
        samples: &[clino_core::ImuSample],
        from: f64,
        mut p: CorePipeline,
    ) -> (f64, CorePipeline) {
        let mut rms = Rms::default();
        for s in samples {
            let q = p.update(s).attitude.unwrap_or_else(Attitude::identity);
            if s.t_s > from {
                rms.push(inclination_error(&q, &motion.truth(s.t_s).attitude));
            }
        }
        (rms.value().to_degrees(), p)
    }

    fn uncalibrated_bias() -> (super::super::ImuModel, Vec3) {
        let mut model = sensor();
        let b = Vec3::new(7.0, -10.0, 5.0) * MG;
        model.accel.bias = b;
        (model, b)
    }

    /// The pipeline of `--lever-arm auto`: the arm estimated from the
    /// recording (the accelerometer bias with it).
    fn lever_auto() -> CorePipeline {
        CorePipeline::new(FilterSpec::default()).with_mount_estimator(Some(MountOptions {
            estimate_lever: true,
            ..Default::default()
        }))
    }

    /// The pipeline of `--lever-arm` with the arm of `m` given (the
    /// accelerometer bias estimated online).
    fn lever_given(m: &SlewingPlatform) -> CorePipeline {
        let opts = MountOptions {
            lever_arm_m: m.lever_arm_m,
            ..Default::default()
        };
        CorePipeline::new(FilterSpec::default()).with_mount_estimator(Some(opts))
    }

    /// The machine sampled at 50 Hz for `seconds` (seed 1), its engine at
    /// 17.5 Hz (0.35 of the rate, as on the grid), the accelerometer
    /// uncalibrated ([`uncalibrated_bias`]) behind a 20-Hz anti-alias filter.
    fn at_50_hz(seconds: f64) -> (SlewingPlatform, Vec<clino_core::ImuSample>) {
        let m = SlewingPlatform {
            vibration_hz: 17.5,
            ..Default::default()
        };
        let (model, _) = uncalibrated_bias();
        let s = model.with_bandwidth(20.0).simulate(&m, 50.0, seconds, 1);
        (m, s)
    }

    /// The machine (default) shaken from `start_s` on by its digging: its
    /// body translated on an ellipse of 0.3 m/s² (0.15 vertically) at
    /// 0.7 Hz, ramped in over 2 s. Its dwells then never pass for rest
    /// (the low-passed specific force swings by more than 0.2 m/s²), and
    /// the bias estimator's blocks keep most of it (0.17 m/s² learnt).
    fn digging_machine(
        start_s: f64,
    ) -> (
        SlewingPlatform,
        crate::sim::motion::Sum<SlewingPlatform, crate::sim::motion::Orbit>,
    ) {
        let base = SlewingPlatform::default();
        let m = crate::sim::motion::Sum {
            a: base.clone(),
            b: digging(start_s),
        };
        (base, m)
    }

    /// The machine digging from the start at 50 Hz (as `at_50_hz`: the
    /// engine at 17.5 Hz behind a 20-Hz anti-alias filter; the sensor
    /// calibrated), seed 1: the machine, its motion, the sensor's model and
    /// its samples.
    #[allow(clippy::type_complexity)]
    fn digging_at_50_hz() -> (
        SlewingPlatform,
        crate::sim::motion::Sum<SlewingPlatform, crate::sim::motion::Orbit>,
        crate::sim::ImuModel,
        Vec<clino_core::ImuSample>,
    ) {
        let (base, mut m) = digging_machine(0.0);
        m.a.vibration_hz = 17.5;
        let model = sensor().with_bandwidth(20.0);
        let s = model.simulate(&m, 50.0, 120.0, 1);
        (base, m, model, s)
    }

    /// The machine with its boom swaying at `hz` (`acc` m/s², 1°/s) instead
    /// of its engine's 30 Hz.
    fn swaying(hz: f64, acc: f64) -> SlewingPlatform {
        SlewingPlatform {
            vibration_hz: hz,
            vibration_m_s2: acc,
            vibration_rate_rad_s: 1f64.to_radians(),
            ..Default::default()
        }
    }

    #[test]
    fn slewing_makes_the_horizontal_accelerometer_bias_observable() {
        // 10 mg of bias is 0.5° of tilt whatever the filter (issue 13); the slew
        // turns it in the navigation frame while the tilt error does not
        let m = SlewingPlatform::default();
        let (model, b) = uncalibrated_bias();
        let s = model.simulate(&m, 200.0, 120.0, 1);
        let spec = FilterSpec::default();
        // the filter alone, its own rest-to-rest bias learning off: the bias stays
        let mut alone = spec;
        alone.set("accel_bias_sigma", "0").unwrap();
        let (plain, _) = run(
            &m,
            &s,
            m.initial_rest_s,
            CorePipeline::new(alone).with_lever_arm(Some(m.lever_arm_m)),
        );
        let opts = MountOptions {
            lever_arm_m: m.lever_arm_m,
            ..Default::default()
        };
        let (est, p) = run(
            &m,
            &s,
            m.initial_rest_s,
            CorePipeline::new(spec).with_mount_estimator(Some(opts)),
        );
        let e = p.mount_estimator().unwrap();
        let (db, sb) = (e.accel_bias() - b, e.accel_bias_sigma());
        // measured: 0.52° without, 0.17° with (the filter re-converges within
        // ≈ 10 s of the first slew), bias within 0.1 mg on x and y
        assert!(plain > 0.4, "{plain}");
        assert!(est < 0.2 && est < plain / 2.5, "{est} vs {plain}");
        for i in 0..2 {
            assert!(db[i].abs() < 1.0 * MG, "bias error {db:?}");
            assert!(db[i].abs() < 4.0 * sb[i] + 0.2 * MG, "{db:?} vs 1σ {sb:?}");
            assert!(sb[i] < 1.0 * MG, "{sb:?}");
        }
    }

    /// Issue 13: the slewing machine at 50 Hz, its engine at 17.5 Hz (8.75
    /// periods in a 0.5-s block), the accelerometer biased by 10 mg. The
    /// bias is only observable once the first slew has turned it; how soon
    /// it is learnt is the tilt error of the first seconds of that slew,
    /// most of the whole recording's. Equally weighted 0.5-s blocks kept
    /// 1/32 of the engine (0.04 m/s², learnt as the blocks' noise: the first
    /// turn taught the bias slowly); the overlapping triangles keep 1/188,
    /// and the noise's starting guess weighs 2 s of blocks, not 20.
    #[test]
    fn at_50_hz_the_first_slew_teaches_the_bias_quickly() {
        let (m, s) = at_50_hz(16.0);
        let mut p = lever_given(&m);
        let mut rms = Rms::default();
        for smp in &s {
            let q = p.update(smp).attitude.unwrap_or_else(Attitude::identity);
            // the first slew starts at 10 s: its ramp, then a second at full rate
            if (11.0..13.5).contains(&smp.t_s) {
                rms.push(inclination_error(&q, &m.truth(smp.t_s).attitude));
            }
        }
        let e = rms.value().to_degrees();
        std::println!("{e}°");
        // measured: 0.36° with the equal blocks, 0.22° now (0.7° before any turn)
        assert!(e < 0.3, "{e}°");
    }

    #[test]
    fn a_swaying_boom_does_not_hide_the_bias() {
        // The boom sways at 3 Hz (its first mode) instead of the engine's
        // 30 Hz: 1.5 m/s² and 1°/s. Behind the rest detector's low-pass the
        // sway is above the thresholds, so no stop was a rest (the plain
        // filter's gyro bias went unlearnt: 0.6–0.8° on some seeds), and a
        // 0.5-s block mean of the bias estimator kept up to a/(π·f·T) =
        // 0.3 m/s² of it, more than the 0.12 m/s² bias it is to find. The
        // sway is now notched out of the rest detector's input, and the
        // estimator's blocks span whole periods of it.
        // Measured on this seed: 0.61° before, 0.37° with the notch alone,
        // 0.12° with the blocks too (0.09° without the sway).
        let m = swaying(3.0, 1.5);
        let (model, b) = uncalibrated_bias();
        let s = model.simulate(&m, 200.0, 120.0, 1);
        let (tilt, p) = run(&m, &s, m.initial_rest_s, lever_given(&m));
        let db = p.mount_estimator().unwrap().accel_bias() - b;
        std::println!("{tilt}°, bias error {db:?}");
        assert!(tilt < 0.15, "{tilt}°");
        assert!(db.xy().norm() < 1.0 * MG, "bias error {db:?}");
    }

    #[test]
    fn lever_arm_compensation_noise_is_not_a_sway() {
        // The lever-arm compensation differentiates the gyro: its noise,
        // times the 2.5-m arm, reaches the rest detector as 0.09 m/s² (RMS,
        // behind its low-pass) at power-on, half the rest threshold — but
        // spread over the band, where a structure's sway is one line
        // (p₀·p₂/p₁² ≈ 50–160 for it, 2–3 for a boom swaying at 2.2 Hz).
        // Taken for a sway (before the band test: 0.7–3.6 s of this run),
        // it set the bias estimator's blocks to its "periods".
        let m = SlewingPlatform::default();
        let (model, _) = uncalibrated_bias();
        let s = model.simulate(&m, 200.0, 60.0, 1);
        let mut p = lever_given(&m);
        for smp in &s {
            p.update(smp);
            let d = p.filter().as_dynamic().unwrap();
            assert_eq!(d.sway_hz(), None, "at {} s", smp.t_s);
        }
        // and a boom's sway is one
        let m = swaying(2.2, 1.0);
        let s = model.simulate(&m, 200.0, 10.0, 1);
        let mut p = lever_given(&m);
        for smp in &s {
            p.update(smp);
        }
        let f = p.filter().as_dynamic().unwrap().sway_hz();
        let f = f.expect("the boom's sway is found");
        assert!((f - 2.2).abs() < 0.15, "{f} Hz");
    }

    #[test]
    fn a_new_accelerometer_bias_estimate_reaches_the_tilt_at_once() {
        // Issue 13, the slewing machine with an uncalibrated accelerometer and
        // the lever arm given: the bias is found within a few seconds of the
        // first slew (t = 10 s), but the filter's attitude had been pulled to
        // the biased gravity direction (≈ b_h/g = 0.7°) and, with the estimate
        // only removed from the samples to come, took ≈ 10 s more to follow
        // it through its loop. Fed back into the state at once
        // (`Dynamic::shift_accel_input`), the tilt is right as soon as the
        // estimate is. Measured on this seed, 3–13 s after the first slew
        // began: 0.327° with the shift disabled (checked by removing the
        // `shift_accel_input` call in the pipeline), 0.051° with it; over the
        // whole run 0.17° before the fix (the test above), 0.108° after, and
        // 0.097° since the whole estimate (the Kalman filter's posterior mean)
        // is applied instead of a share 1 − σ²/σ₀² of it (a second shrinkage
        // towards zero on top of the one the prior already makes).
        let m = SlewingPlatform::default();
        let (model, _) = uncalibrated_bias();
        let s = model.simulate(&m, 200.0, 120.0, 1);
        let mut p = lever_given(&m);
        let (mut all, mut early) = (Rms::default(), Rms::default());
        for smp in &s {
            let q = p.update(smp).attitude.unwrap_or_else(Attitude::identity);
            let e = inclination_error(&q, &m.truth(smp.t_s).attitude);
            if smp.t_s > m.initial_rest_s {
                all.push(e);
            }
            if smp.t_s > m.initial_rest_s + 3.0 && smp.t_s < m.initial_rest_s + 13.0 {
                early.push(e);
            }
        }
        let (all, early) = (all.value().to_degrees(), early.value().to_degrees());
        assert!(early < 0.15, "3–13 s after the first slew began: {early}°");
        assert!(all < 0.1, "{all}°");
    }

    #[test]
    fn lever_arm_auto_finds_the_arm_from_the_recording() {
        let m = SlewingPlatform::default();
        let (model, _) = uncalibrated_bias();
        let s = model.simulate(&m, 200.0, 120.0, 3);
        let (tilt, p) = run(&m, &s, m.initial_rest_s, lever_auto());
        let e = p.mount_estimator().unwrap();
        let dr = e.lever_arm() - m.lever_arm_m;
        // the component along the slew axis makes no acceleration: only x, y
        assert!(dr.xy().norm() < 0.05, "arm error {dr:?}");
        assert!(e.lever_arm_sigma().xy().norm() < 0.05);
        // the height only turns with the engine's vibration about x, of which
        // a block keeps what its triangle leaves; its 1σ says so: −0.56 m at
        // 0.25 m (2.2σ), where ω̇ from the lever stage's differentiator
        // (0.31 of a 30-Hz vibration at 200 Hz, turned by −167°) gave
        // −2.16 m at 0.38 m (5.7σ)
        let sz = e.lever_arm_sigma().z;
        assert!(
            dr.z.abs() < 3.0 * sz && sz < 0.5,
            "height {} ± {sz} m off",
            dr.z
        );
        // a rigid body about a fixed axis: the arm predicts all but the noise
        let f = e.lever_explains().unwrap();
        assert!(e.lever_model_holds() && f > 0.98, "{f}");
        assert_eq!(e.applied_lever_arm(), e.lever_arm());
        // measured 0.080° on this seed (0.081° before 8 Dec 2026; issue 13
        // asks ≤ 0.15°): the filter's state is moved with each new pair of
        // estimates (bias and arm) as had they been removed from the start
        // (`Dynamic::shift_arm_input`); without that feedback it was 0.117°
        // when the feedback came (0.12–0.17° over seeds 1–3)
        assert!(tilt < 0.11, "{tilt}");
    }

    #[test]
    fn lever_arm_auto_on_a_hand_fits_no_arm_and_applies_none() {
        // A sensor moved by hand (rests, turns of tens of degrees, its own
        // translation unrelated to the turns): no point of it stays still,
        // so no lever arm exists. Before the blocks were weighed again
        // (NOISE_REWEIGH_RATIO) its first second of motion, weighed at the
        // rest's noise, fixed the arm at (−0.08, −0.34, 0.05) m ± (0.015,
        // 0.006, 0.020) m (55σ from zero on y); applied, with the whole
        // bias estimate, it took the tilt from 0.18° to 1.0° (a shaken
        // sensor's from 0.15° to 7.7°). Weighed again but applied whatever
        // it predicts (no LEVER_EXPLAINS): (−0.02, −0.02, −0.00) m, 0.19°.
        let hand = crate::sim::hand::HandMotion::new(crate::sim::hand::HandParams::by_hand(), 1);
        let s = sensor().simulate(&hand, 100.0, 120.0, 1);
        let spec = FilterSpec::default();
        let (plain, _) = run(&hand, &s, 0.0, CorePipeline::new(spec));
        let (auto, p) = run(&hand, &s, 0.0, lever_auto());
        let e = p.mount_estimator().unwrap();
        let (r, sr) = (e.lever_arm(), e.lever_arm_sigma());
        println!(
            "arm {r:?} ± {sr:?}, explains {:?}: {auto}° against {plain}°",
            e.lever_explains()
        );
        // an honest 1σ: the estimate is noise about zero
        for i in 0..3 {
            assert!(r[i].abs() < 4.0 * sr[i], "{r:?} ± {sr:?}");
        }
        assert!(!e.lever_model_holds(), "{:?}", e.lever_explains());
        assert!(e.lever_explains().unwrap() < 0.25);
        assert_eq!(e.applied_lever_arm(), Vec3::zeros());
        assert_eq!(p.applied_accel_bias(), Vec3::zeros());
        assert!(auto < 1.1 * plain, "{auto}° against {plain}°");
    }

    #[test]
    fn lever_arm_auto_never_applies_an_arm_fitted_to_a_hands_first_turns() {
        // A hand has no point that stays still, so no lever arm. Its first
        // block of motion, weighed at the rest's noise, sets an arm to a
        // centimetre (its variance shrinks from the 2-m prior in two
        // blocks). Before the share weighed each prediction by how much its
        // arm knew, a hand turning three times as fast (up to ±2000 °/s,
        // tens to hundreds of rad/s² of dω/dt) had its second block of
        // motion predicted to 94 % by the arm fitted to the rest's noise
        // (1.8 m of 1σ), the share jumped to 0.64 while the noise was still
        // the rest's, and the chance arm was applied for 0.2 s: the tilt
        // 10° (`generalise`: the mean 0.612° → 0.648°, worst 0.97 → 1.35×
        // VQF; 4 seeds of 8 at 100 Hz). Weighed, with the share asked to
        // reach a half, a hand at 25 or 100 Hz still had an arm fitted to two
        // blocks predict 70 % of the next (seed 5: 0.25 s applied); at three
        // quarters none does.
        for (speed, rate) in [(1.0, 25.0), (1.0, 100.0), (3.0, 100.0)] {
            let mut params = crate::sim::hand::HandParams::by_hand();
            params.band_hz = (speed * params.band_hz.0, speed * params.band_hz.1);
            let mut model = sensor().with_bandwidth((0.4f64 * rate).min(98.0));
            model.gyro.range = 2000f64.to_radians();
            for seed in 1..=8 {
                let hand = crate::sim::hand::HandMotion::new(params, seed);
                let s = model.simulate(&hand, rate, 30.0, seed);
                let mut p = lever_auto();
                let mut applied = 0;
                for x in &s {
                    p.update(x);
                    if p.mount_estimator().unwrap().lever_model_holds() {
                        applied += 1;
                    }
                }
                let f = p.mount_estimator().unwrap().lever_explains();
                println!(
                    "{speed}× at {rate} Hz, seed {seed}: applied on {applied} samples, share {f:?}"
                );
                assert_eq!(applied, 0, "{speed}× at {rate} Hz, seed {seed}");
            }
        }
    }

    #[test]
    fn lever_arm_auto_on_a_swaying_boom_at_25_hz_applies_the_arm_in_its_first_slew() {
        // `generalise`'s swaying boom at 25 Hz (its chassis heading and sway
        // frequency by seed, the sensor's anti-alias filter at 10 Hz): the
        // 10-s rest's sway sets an arm whose component along the slew's
        // regressor is still at its 2-m prior, and the first slew's blocks
        // come mispredicted. Counted in full (before the share weighed each
        // prediction by how much its arm knew) they held the share under a
        // half for 3.2 s of the first slew on seed 5 (1.77 Hz), with 2.5
        // m/s² of centripetal acceleration uncompensated: 0.175° over the
        // run (the issue asks ≤ 0.15° of `--lever-arm auto`); the other
        // seeds 0.084–0.114°.
        let (model, _) = uncalibrated_bias();
        let model = model.with_bandwidth(10.0);
        for seed in 1..=8u64 {
            let m = SlewingPlatform {
                chassis_heading: 0.7 + seed as f64,
                ..swaying(1.5 + 3.0 * (seed as f64 * 0.618_033_988_75).fract(), 1.0)
            };
            let s = model.simulate(&m, 25.0, 120.0, seed);
            let (tilt, p) = run(&m, &s, m.initial_rest_s, lever_auto());
            let e = p.mount_estimator().unwrap();
            println!("seed {seed}, sway {:.2} Hz: {tilt:.3}°", m.vibration_hz);
            assert!(e.lever_model_holds(), "seed {seed}");
            assert!(tilt < 0.15, "seed {seed}: {tilt}°");
        }
    }

    #[test]
    fn a_mount_that_does_not_turn_keeps_its_tilt() {
        // tilted 20°, translated by ±0.2 m at 0.5 Hz (no rotation), 8 mg of
        // bias: the bias is a tilt here, indistinguishable; the estimate must
        // stay at zero and the tilt as it is without the estimator
        use crate::sim::motion::{Orbit, Sum};
        let base =
            crate::sim::motion::Static::new(UnitQuaternion::from_euler_angles(0.3, -0.2, 0.5));
        let orbit = Orbit::spatial(0.2, 0.5).with_start(5.0, 2.0);
        let m = Sum { a: base, b: orbit };
        let mut model = sensor();
        model.accel.bias = Vec3::new(8.0, -6.0, 3.0) * MG;
        let s = model.simulate(&m, 100.0, 90.0, 2);
        let spec = FilterSpec::default();
        let (plain, _) = run(&m, &s, 5.0, CorePipeline::new(spec));
        let (est, p) = run(
            &m,
            &s,
            5.0,
            CorePipeline::new(spec).with_mount_estimator(Some(MountOptions::default())),
        );
        let b = p.mount_estimator().unwrap().accel_bias();
        assert!(b.norm() < 0.5 * MG, "{b:?}");
        assert!((est - plain).abs() < 0.01, "{est} vs {plain}");
    }

    /// Issue 13, offline: `clino fuse --offline --lever-arm X` removes the
    /// accelerometer bias the real-time pass's estimator ended with from
    /// every sample before its passes ([`crate::fusion::FilterConfig`]), so
    /// the first second of the first slew, which holds most of the real-time
    /// error (the whole bias, before any turn has told it from the tilt),
    /// is right too. Calling the smoother without that pass (what the
    /// generalisation harness did until 7 Dec 2026) left the bias to the
    /// rest pairs. Measured at 50 Hz, seed 1: real time 0.085°, offline
    /// 0.035°, offline without the estimator 0.102°.
    #[test]
    fn offline_the_estimated_bias_is_removed_from_the_first_sample() {
        use crate::fusion::FilterConfig;
        let (m, s) = at_50_hz(120.0);
        let score = |q: &[Option<Attitude>]| {
            let mut rms = Rms::default();
            for (smp, q) in s.iter().zip(q) {
                if smp.t_s > m.initial_rest_s {
                    let q = q.unwrap_or_else(Attitude::identity);
                    rms.push(inclination_error(&q, &m.truth(smp.t_s).attitude));
                }
            }
            rms.value().to_degrees()
        };
        let given =
            FilterConfig::from_spec(FilterSpec::default()).with_lever_arm(Some(m.lever_arm_m));
        let (real_time, _) = run(&m, &s, m.initial_rest_s, lever_given(&m));
        let offline = score(&given.with_offline(true).smooth_samples(&s).unwrap());
        let without = score(
            &given
                .with_accel_bias(false)
                .with_offline(true)
                .smooth_samples(&s)
                .unwrap(),
        );
        std::println!(
            "real time {real_time}°, offline {offline}°, without the estimate {without}°"
        );
        assert!(offline < 0.05, "{offline}°");
        assert!(offline < 0.5 * real_time, "{offline}° against {real_time}°");
        assert!(offline < 0.5 * without, "{offline}° against {without}°");
    }

    /// Issue 13: an arm given says the axis does not move, and the bias the
    /// estimator reads is believed only while the arm's terms leave at most
    /// 0.1 m/s² of the block-mean specific force unexplained
    /// ([`clino_core::compensate::LEVER_FIXED_AXIS_M_S2`]). A segment turned
    /// by hand about a joint 0.25 m away, the joint itself carried by the
    /// hand (`clino fuse --lever-arm 0.25,0.05,0`): its blocks leave
    /// 0.4–1 m/s², and the bias read from them had been applied. Measured on
    /// this seed at 100 Hz (0.43 m/s² left): 0.118° with the arm's
    /// compensation alone, 0.203° with that bias applied (the gate as it
    /// was), 0.118° with the gate.
    #[test]
    fn a_given_arm_on_a_joint_that_moves_applies_no_bias() {
        use crate::sim::hand::{HandMotion, HandParams};
        use crate::sim::motion::Offset;
        let hand = HandMotion::new(HandParams::by_hand(), 2);
        let r = Vec3::new(0.25, 0.05, 0.0);
        let m = Offset {
            motion: hand,
            r_body_m: r,
        };
        let s = sensor().with_bandwidth(40.0).simulate(&m, 100.0, 90.0, 2);
        let from = hand.params.initial_rest_s;
        let (alone, _) = run(
            &m,
            &s,
            from,
            CorePipeline::new(FilterSpec::default()).with_lever_arm(Some(r)),
        );
        let opts = MountOptions {
            lever_arm_m: r,
            ..Default::default()
        };
        let (with, p) = run(
            &m,
            &s,
            from,
            CorePipeline::new(FilterSpec::default()).with_mount_estimator(Some(opts)),
        );
        let e = p.mount_estimator().unwrap();
        std::println!(
            "{alone}° alone, {with}° with the estimator; noise {} m/s²",
            e.noise_sigma()
        );
        assert!(e.noise_sigma() > 0.3, "{}", e.noise_sigma());
        assert!(!e.lever_model_holds());
        assert_eq!(p.applied_accel_bias(), Vec3::zeros());
        assert!(with < 1.05 * alone, "{with}° against {alone}°");
    }

    /// Issue 13: a given arm stays believed once its model has held while
    /// the turns pinned the bias down. The slewing machine, clean for its
    /// first slews, then shaken from 40 s on by 0.3 m/s² at 0.7 Hz (digging,
    /// travel): its blocks leave 0.17 m/s², over the fixed-axis bar, yet the
    /// bias was learnt where the arm held. Measured on this seed: 0.088°
    /// with the bias kept, 0.453° had it been dropped when the noise rose
    /// (the gate without the vouching).
    #[test]
    fn a_given_arm_that_held_keeps_its_bias_when_the_machine_is_shaken() {
        let (base, m) = digging_machine(40.0);
        let (model, _) = uncalibrated_bias();
        let s = model.simulate(&m, 100.0, 120.0, 1);
        let (e, p) = run(&m, &s, base.initial_rest_s, lever_given(&base));
        let est = p.mount_estimator().unwrap();
        std::println!("{e}°, noise {} m/s²", est.noise_sigma());
        let bar = clino_core::compensate::LEVER_FIXED_AXIS_M_S2;
        assert!(est.noise_sigma() > bar, "{}", est.noise_sigma());
        assert!(est.lever_model_holds());
        assert!(e < 0.15, "{e}°");
    }

    /// Issue 13: the digging machine of the test below run without its
    /// lever arm (a user who never measured it; VQF, too, reads the slews'
    /// tangential and centripetal accelerations). Its dwells never pass for
    /// rest, so no rest proper ever ended the filter's start-up: its loop
    /// ran at the start-up's 3-s time constant for the whole two minutes
    /// instead of the design's 6.7 s, and the slews' accelerations, fixed
    /// in the body while the machine turns, passed into the tilt and were
    /// learnt as gyro bias. Measured on this seed: 6.13° so, where VQF
    /// gives 2.59° (`generalise`, `slewing+rock@50Hz cal`, seed 1); with the
    /// floor the running mean's 1/t since the alignment was lost (the
    /// design loop takes over 6.7 s in) 2.21°.
    #[test]
    fn a_slewing_machine_that_never_rests_leaves_the_start_up_bandwidth() {
        let (base, m, _, s) = digging_at_50_hz();
        let p = CorePipeline::new(FilterSpec::default());
        let (e, _) = run(&m, &s, base.initial_rest_s, p);
        std::println!("{e}°");
        assert!(e < 2.59, "{e}°");
    }

    /// Issue 13: a machine that never rests. Digging from the start, its
    /// dwells never pass the rest detector, so the gyro bias was never read
    /// from a still gyro, and the loop's motion learning alone followed the
    /// accelerometer's errors into it: in a slew faster than the loop, a
    /// body-fixed accelerometer error is a body-fixed innovation whichever
    /// way the machine turns, while the tilt a gyro bias makes changes sign
    /// with the slew, so alternate slews never undo what it learnt. The
    /// gyro is still in each dwell (the rocking is a translation) and the
    /// bias is now read from it there (the turn-free stillness). Measured
    /// on this seed, the accelerometer calibrated, the arm given without
    /// the bias estimator: 0.061° and the bias within 0.010 °/s of the
    /// truth; without the turn-free stillness (a throw-away build) 0.135°
    /// and 0.056 °/s. With a 10-mg accelerometer bias the gyro bias was
    /// 0.49 °/s off after 120 s (1.13°). Since the loop that no rest has
    /// aligned falls to its design bandwidth (the test above), 0.044° and
    /// 0.0099 °/s.
    #[test]
    fn a_slewing_machine_that_never_rests_reads_its_gyro_bias_in_the_dwells() {
        use clino_core::AttitudeFilter;
        let (base, m, model, s) = digging_at_50_hz();
        let p = CorePipeline::new(FilterSpec::default()).with_lever_arm(Some(base.lever_arm_m));
        let (e, p) = run(&m, &s, base.initial_rest_s, p);
        let b = (p.filter().gyro_bias() - model.gyro.bias)
            .norm()
            .to_degrees();
        std::println!("{e}°, gyro bias off by {b} °/s");
        assert!(e < 0.08, "{e}°");
        assert!(b < 0.015, "{b} °/s");
    }
}
