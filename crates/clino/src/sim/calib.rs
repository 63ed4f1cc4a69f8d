//! A small, seeded generator of calibration recordings (for tests and the demo).
//!
//! A *true* sensor model maps raw readings to true values; the generator
//! inverts it: from the true specific force, rate and field at each instant it
//! makes the raw readings a miscalibrated IMU would report, adds white noise
//! (rand_chacha, seeded, so every run is identical) and a temperature that
//! swings between two values (the MWD paper calibrates over about 25–80 °C).
//!
//! The motion is a sequence of static poses joined by rotations about a fixed
//! body axis with a smooth (1 − cos) angle profile, so the true body rate is
//! exact; the rotation is about the sensor's origin (no lever-arm acceleration)
//! and the Earth's rotation is ignored (the gyro reads only its bias at rest).
//! Frames are clino's: ENU navigation, body z up when level, specific force
//! (0, 0, +g) when level.
//!
//! This is deliberately smaller than `clino::sim` (trajectories, full IMU error
//! model): it makes exactly the data a calibration needs, with truth attached.

use crate::calib::fit::Observation;
use crate::calib::recording::Recording;
use clino_core::sensor::{MatrixModel, MwdModel};
use clino_core::{Attitude, ImuSample, Vec3, tilt};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Settings of the generator.
#[derive(Clone, Debug)]
pub struct SynthOptions {
    /// True accelerometer model (raw → true).
    pub accel: MwdModel,
    /// True gyro model (raw → true).
    pub gyro: MatrixModel,
    /// True magnetometer model (raw → true): hard iron in `bias`, soft iron in `matrix`.
    pub mag: MatrixModel,
    /// Earth's field in ENU, µT.
    pub field_enu_ut: Vec3,
    /// Gravity, m/s².
    pub g: f64,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Time held still in each pose, s.
    pub static_s: f64,
    /// Time of each rotation between poses, s.
    pub move_s: f64,
    /// White noise 1σ per sample: accelerometer m/s², gyro rad/s, magnetometer µT.
    pub noise: [f64; 3],
    /// Temperature swings between these, °C.
    pub temp_range_c: [f64; 2],
    /// Period of the temperature swing, s.
    pub temp_period_s: f64,
    /// Seed of the noise.
    pub seed: u64,
}

impl Default for SynthOptions {
    fn default() -> Self {
        Self {
            accel: poorly_calibrated_accel(),
            gyro: MatrixModel {
                bias: [0.01, -0.02, 0.015],
                matrix: [
                    [1.02, 0.003, -0.004],
                    [-0.002, 0.985, 0.006],
                    [0.005, -0.003, 1.01],
                ],
            },
            mag: MatrixModel {
                bias: [12.0, -7.0, 20.0],
                matrix: [[1.05, 0.03, -0.02], [0.03, 0.93, 0.04], [-0.02, 0.04, 1.1]],
            },
            field_enu_ut: Vec3::new(0.0, 22.0, -42.0),
            g: clino_core::G0,
            rate_hz: 20.0,
            static_s: 4.0,
            move_s: 2.0,
            noise: [0.003, 0.001, 0.05],
            temp_range_c: [25.0, 80.0],
            temp_period_s: 504.0,
            seed: 7,
        }
    }
}

/// A poorly calibrated accelerometer triad with the magnitudes of the MWD
/// paper's Table 1 (JA5M36: scale ±5 %, bias ≤ 10 mg, alignment ≤ 2 mrad,
/// scale tempco ≤ 180 ppm/°C, bias tempco ≤ 100 µg/°C), plus small second- and
/// third-order temperature terms. Raw readings are nominally in m/s² (SF ≈ 1).
/// The misalignment is lower triangular (the convention the fit uses without
/// a reference inclination), so the truth is what the fit can recover.
pub fn poorly_calibrated_accel() -> MwdModel {
    MwdModel {
        tc_c: 30.0,
        scale: [
            [1.031, 1.5e-4, -1.2e-6, 1.5e-8],
            [0.962, -1.1e-4, 8.0e-7, -1.0e-8],
            [1.018, 1.7e-4, 1.0e-6, 2.0e-8],
        ],
        bias: [
            [0.085, 9.0e-4, -1.0e-5, 1.0e-7],
            [-0.060, -7.0e-4, 1.2e-5, -1.5e-7],
            [0.045, 1.0e-3, 8.0e-6, 8.0e-8],
        ],
        m: [[0.0, 0.0, 0.0], [0.0018, 0.0, 0.0], [-0.0015, 0.0012, 0.0]],
    }
}

/// The 26 "up" directions of a cube (6 faces, 12 edges, 8 corners), unit vectors in the body frame.
pub fn cube_directions() -> Vec<Vec3> {
    let mut v = Vec::new();
    for x in -1i32..=1 {
        for y in -1i32..=1 {
            for z in -1i32..=1 {
                if (x, y, z) != (0, 0, 0) {
                    v.push(Vec3::new(x as f64, y as f64, z as f64).normalize());
                }
            }
        }
    }
    v
}

/// The pose schedule of the generated calibration recordings: the 14 face and
/// corner directions of a cube, six times over (84 poses). With the default
/// timing (4 s still, 2 s moving) the recording lasts 504 s, one period of the
/// default temperature swing, so every orientation is seen at low, middle and
/// high temperatures (a temperature model cannot otherwise be separated from
/// the orientation).
pub fn calibration_schedule() -> Vec<Attitude> {
    let dirs: Vec<Vec3> = cube_directions()
        .into_iter()
        .filter(|d| d.iter().filter(|c| c.abs() > 1e-9).count() != 2)
        .collect();
    let mut ups = Vec::new();
    for _ in 0..6 {
        ups.extend(dirs.iter().copied());
    }
    attitudes_from_ups(&ups)
}

/// Attitudes (body → ENU) whose up vector in the body frame is each of `ups`,
/// with headings spread by the golden angle so a magnetometer sees them all.
pub fn attitudes_from_ups(ups: &[Vec3]) -> Vec<Attitude> {
    ups.iter()
        .enumerate()
        .map(|(k, u)| {
            let q = tilt::attitude_from_up(u).unwrap_or_else(Attitude::identity);
            let psi = k as f64 * 2.399_963_229_728_653;
            Attitude::from_axis_angle(&nalgebra::Vector3::z_axis(), psi) * q
        })
        .collect()
}

/// A simulated recording with its truth.
#[derive(Clone, Debug)]
pub struct SynthRecording {
    /// Raw samples (what the miscalibrated IMU reports), with temperature and field.
    pub samples: Vec<ImuSample>,
    /// Reference inclination of the housing, deg, while static (NaN while moving).
    pub ref_inclination_deg: Vec<f64>,
    /// True specific force, m/s².
    pub true_acc: Vec<Vec3>,
    /// True body rate, rad/s.
    pub true_gyr: Vec<Vec3>,
    /// True field in the body frame, µT.
    pub true_mag: Vec<Vec3>,
    /// True attitude.
    pub attitude: Vec<Attitude>,
}

impl SynthRecording {
    /// As a [`Recording`] (CSV-shaped, with `temp_c` and `ref_inclination_deg`).
    pub fn recording(&self) -> Recording {
        Recording::from_samples(&self.samples, Some(&self.ref_inclination_deg))
    }
}

fn temperature(opt: &SynthOptions, t: f64) -> f64 {
    let [lo, hi] = opt.temp_range_c;
    0.5 * (lo + hi) - 0.5 * (hi - lo) * (2.0 * std::f64::consts::PI * t / opt.temp_period_s).cos()
}

fn raw_matrix(m: &MatrixModel, y: Vec3) -> Vec3 {
    let mm = nalgebra::Matrix3::from_fn(|i, j| m.matrix[i][j]);
    let inv = mm.try_inverse().unwrap_or_else(nalgebra::Matrix3::identity);
    inv * y + Vec3::from(m.bias)
}

/// Make a continuous recording through `attitudes` (static, move, static, …).
pub fn recording(opt: &SynthOptions, attitudes: &[Attitude]) -> SynthRecording {
    let mut rng = ChaCha8Rng::seed_from_u64(opt.seed);
    let n = |s: f64| {
        Normal::new(0.0, s.max(0.0))
            .unwrap_or_else(|_| Normal::new(0.0, 0.0).expect("σ = 0 is valid"))
    };
    let (na, ng, nm) = (n(opt.noise[0]), n(opt.noise[1]), n(opt.noise[2]));
    let dt = 1.0 / opt.rate_hz;
    let mut out = SynthRecording {
        samples: Vec::new(),
        ref_inclination_deg: Vec::new(),
        true_acc: Vec::new(),
        true_gyr: Vec::new(),
        true_mag: Vec::new(),
        attitude: Vec::new(),
    };
    let mut t = 0.0;
    let push = |out: &mut SynthRecording,
                rng: &mut ChaCha8Rng,
                t: f64,
                q: Attitude,
                w: Vec3,
                still: bool| {
        let f = q.inverse_transform_vector(&Vec3::new(0.0, 0.0, opt.g));
        let h = q.inverse_transform_vector(&opt.field_enu_ut);
        let temp = temperature(opt, t);
        let noise3 = |rng: &mut ChaCha8Rng, d: &Normal<f64>| {
            Vec3::new(d.sample(rng), d.sample(rng), d.sample(rng))
        };
        let acc = opt.accel.invert(f, temp).unwrap_or(f) + noise3(rng, &na);
        let gyr = raw_matrix(&opt.gyro, w) + noise3(rng, &ng);
        let mag = raw_matrix(&opt.mag, h) + noise3(rng, &nm);
        out.samples.push(ImuSample {
            t_s: t,
            gyr_rad_s: gyr,
            acc_m_s2: acc,
            mag_ut: Some(mag),
            temp_c: Some(temp),
        });
        out.ref_inclination_deg.push(if still {
            tilt::inclination(&q).to_degrees()
        } else {
            f64::NAN
        });
        out.true_acc.push(f);
        out.true_gyr.push(w);
        out.true_mag.push(h);
        out.attitude.push(q);
    };
    let ns = (opt.static_s * opt.rate_hz).round() as usize;
    let nmv = (opt.move_s * opt.rate_hz).round() as usize;
    for (k, q) in attitudes.iter().enumerate() {
        for _ in 0..ns {
            push(&mut out, &mut rng, t, *q, Vec3::zeros(), true);
            t += dt;
        }
        if let Some(q1) = attitudes.get(k + 1) {
            let d = q.inverse() * q1;
            let (axis, angle) = d
                .axis_angle()
                .map(|(a, th)| (a.into_inner(), th))
                .unwrap_or((Vec3::x(), 0.0));
            let tm = opt.move_s;
            for i in 0..nmv {
                let s = i as f64 * dt;
                let frac = 0.5 * (1.0 - (std::f64::consts::PI * s / tm).cos());
                let rate =
                    angle * 0.5 * std::f64::consts::PI / tm * (std::f64::consts::PI * s / tm).sin();
                let qi = q * Attitude::from_scaled_axis(axis * angle * frac);
                push(&mut out, &mut rng, t, qi, axis * rate, false);
                t += dt;
            }
        }
    }
    out
}

/// Pose means directly (no continuous recording): the raw accelerometer
/// observation at each attitude and temperature, with the noise of a mean of
/// `n_avg` samples, and the true specific force. Fast, for fits in tests.
pub fn accel_pose_observations(
    opt: &SynthOptions,
    attitudes: &[Attitude],
    temps_c: &[f64],
    n_avg: usize,
) -> Vec<(Observation, Vec3)> {
    let mut rng = ChaCha8Rng::seed_from_u64(opt.seed ^ 0x5eed);
    let d = Normal::new(0.0, opt.noise[0] / (n_avg.max(1) as f64).sqrt())
        .unwrap_or_else(|_| Normal::new(0.0, 0.0).expect("valid"));
    attitudes
        .iter()
        .zip(temps_c)
        .map(|(q, &temp)| {
            let f = q.inverse_transform_vector(&Vec3::new(0.0, 0.0, opt.g));
            let raw = opt.accel.invert(f, temp).unwrap_or(f)
                + Vec3::new(d.sample(&mut rng), d.sample(&mut rng), d.sample(&mut rng));
            (
                Observation {
                    raw,
                    temp_c: Some(temp),
                    ref_inclination: Some(tilt::inclination(q)),
                    ref_vector: None,
                },
                f,
            )
        })
        .collect()
}

/// `n` temperatures spread over `range` in a shuffled (golden-ratio) order, so
/// that temperature and orientation are not correlated.
pub fn spread_temperatures(range: [f64; 2], n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| {
            let f = (k as f64 * 0.618_033_988_749_895).fract();
            range[0] + (range[1] - range[0]) * f
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn raw_readings_calibrate_back_to_truth() {
        let opt = SynthOptions {
            noise: [0.0; 3],
            rate_hz: 200.0,
            ..Default::default()
        };
        let att = attitudes_from_ups(&cube_directions()[..5]);
        let r = recording(&opt, &att);
        for i in (0..r.samples.len()).step_by(7) {
            let s = &r.samples[i];
            assert_relative_eq!(
                opt.accel.apply(s.acc_m_s2, s.temp_c),
                r.true_acc[i],
                epsilon = 1e-9
            );
            assert_relative_eq!(opt.gyro.apply(s.gyr_rad_s), r.true_gyr[i], epsilon = 1e-9);
            assert_relative_eq!(
                opt.mag.apply(s.mag_ut.unwrap()),
                r.true_mag[i],
                epsilon = 1e-9
            );
            assert!((25.0..=80.0).contains(&s.temp_c.unwrap()));
        }
        // the gyro's true rate integrates to the attitude change
        let mut q = r.attitude[0];
        let dt = 1.0 / opt.rate_hz;
        for i in 0..r.samples.len() - 1 {
            let w = 0.5 * (r.true_gyr[i] + r.true_gyr[i + 1]);
            q *= Attitude::from_scaled_axis(w * dt);
        }
        assert!(
            q.angle_to(r.attitude.last().unwrap()) < 1e-4,
            "{}",
            q.angle_to(r.attitude.last().unwrap())
        );
    }
}
