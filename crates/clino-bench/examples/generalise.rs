//! The generalisation harness (issue 13): every filter over a grid of
//! simulated conditions — sample rate × motion × vibration × sensor errors —
//! and over the real BROAD recordings, each scored against VQF (the pure-Rust
//! `vqf-rs` port, real time, 6-D, its defaults) on the same samples.
//!
//! ```text
//! cargo run --release -p clino-bench --example generalise -- [--seeds N] [--first-seed S]
//!     [--draw-errors] [--only TEXT]
//!     [--dynamic SPEC] [--broad DIR] [--no-broad] [--export DIR]
//! ```
//!
//! For each condition it prints VQF's mean inclination RMSE (BROAD's metric,
//! [`clino::eval::inclination_error`]) over the seeds, and for every filter
//! its mean RMSE, the ratio of its mean to VQF's and its worst per-recording
//! ratio. Besides the filters, `dyn+bias` is `dynamic` with the online
//! accelerometer-bias estimator (the lever arm given where the condition
//! has one), and `dyn+auto` with the lever arm estimated as well
//! (`--lever-arm auto`): on a mount with no rotation axis the arm must not
//! be applied and the tilt must stay `dynamic`'s. `--dynamic SPEC` replaces the dynamic filter's parameters (the
//! `name:key=value` form of `clino fuse -f`), so a default can be tried on the
//! whole grid before it is changed.
//!
//! The motions: a segment moved by hand (with 1-s rests, with poses held in
//! the hand, with the sensor 0.25 m from the joint), a slow robot arm with and
//! without a vibrating base (an engine's 8.75–30 Hz, a structure swaying
//! at 1.5–5 Hz, below the rest detector's vibration low-pass, and a base
//! rocking at 1.5–5 Hz with no linear sway), a sensor shaken to and fro
//! with little rotation (BROAD's fast translations), a drum turning
//! one way about its horizontal axis in runs and stops, and the slewing
//! excavator (also digging from the start, which keeps every rest out; with
//! its lever arm given, and without it, as a user who never measured it
//! runs `clino fuse`), and a
//! base precessing slowly on a cone (0.31°/s, under the rest detector's
//! threshold), quiet or digging. The sensors: calibrated, or with one kind of error each
//! (accelerometer scale and bias, gyro scale and bias, cross-axis terms of
//! both triads or of either alone, a
//! board warming up, a wide gyro range, a gyro 1 ms behind its
//! accelerometer), or mounted on its side or upside
//! down on the moving body ([`Mounted`]).
//!
//! Simulated recordings are scored from the end of their initial rest on
//! (motion and the rests between moves); BROAD on its `movement` samples.
//! A non-finite estimate makes a score NaN (never dropped).
//!
//! A second table scores VQF and `dynamic` at rest only: the simulated
//! motion's own rests after its first move (the carrying motion still; the
//! vibration riding on it goes on), and BROAD's non-movement samples after
//! its first movement. A steady offset the loop leaves at rest (the unseen
//! chain's failure mode) shows there, where the whole-run RMSE averages it away.
//!
//! For each BROAD recording it also prints a score that needs no optical
//! reference: the seconds from 1.5 s before each rest to 1 s into it, against
//! the gyro carried back from the accelerometer's mean in that rest
//! (`before_rest`). The end of a move is where the unseen chain's offset and
//! BROAD trial 21's error began; there the optical reference's own
//! misalignment and latency are as large as the differences between filters.
//!
//! Then the slewing machine with an uncalibrated accelerometer (its engine
//! vibrating at 30 Hz, then its boom swaying at 1.5–4.5 Hz): the tilt with
//! the lever arm given, without and with the bias estimator, and with
//! `--lever-arm auto`, the estimates against the truth, and offline with
//! the arm given and estimated.
//!
//! Every offline score is the smoother as `clino fuse --offline` runs it
//! ([`clino::fusion::FilterConfig`]): on a recording with a lever arm that
//! includes the real-time pass whose mount estimator's accelerometer bias is
//! removed before the passes, which `--lever-arm` switches on (calling
//! [`clino::smooth::smooth`] directly skipped it, and the grid's slewing rows
//! read 0.104° offline where the command gives 0.03°).
//!
//! Last, `dynamic` and VQF on the hand at 40 Hz with samples lost on the way
//! (a radio link's dropouts): `dynamic` given the samples received, VQF,
//! whose sample period is fixed, each lost sample replaced by the next one.
//!
//! And both on sensors switched on already moving (no initial rest).
//!
//! And time stamps not made by the sensor's clock (`--only stamps`): the
//! hand at 100 Hz and the slow arm on a vibrating base at 125 Hz stamped as
//! a host receives them (±30 % or ±45 % of a period, late by 0–8 ms, 16-ms
//! USB packets), some with 2 % of the samples lost; `dynamic` with the sample
//! clock recovered (the default) and with the stamps as given, VQF with its
//! fixed period.
//!
//! And the sensor's delay: the hand at 40 Hz and the drum, their reference
//! re-timed so that the samples lag it by 0 (time stamps re-timed to the
//! samples), 0.4 (the simulator's own anti-alias filter, the grid's) and
//! 1.2 periods (BROAD's sensor, `clino eval --delay`): VQF, `dynamic` with
//! its default `sensor_delay_periods` (0.5) and with the delay given.
//!
//! And the rest pairs' learner (`--only learner`): `dynamic` as given, with
//! the accelerometer scale's prior halved, without accelerometer learning
//! and without any learning from rest pairs, on the sensors it is for and on
//! calibrated ones, where it can only fit the pairs' noise.
//!
//! `--slewing-rates HZ[,HZ…]` runs the slewing machine's two tables at those
//! sample rates instead of 200 Hz (its engine at 0.35 of the rate, at most
//! 30 Hz, as on the grid's rows).
//!
//! `--export DIR` also writes every simulated recording but the slewing
//! machine's with its lever arm given (an arm VQF cannot compensate
//! offline; the rows without it are written) as a BROAD-format
//! CSV (`t_s`, rate, specific force, `ref_q*` = the truth, `movement` = the
//! scored samples, `rest`), bit-exact (shortest round-trip floats), and
//! `DIR/index.csv` with this harness's scores of each: what
//! `scripts/offline_vqf_grid.py DIR` puts beside PyPI `vqf`'s offline
//! smoother (which `vqf-rs` does not have), condition by condition.

use clino::core::compensate::{LeverArm, MountOptions};
use clino::core::filter::DynamicParams;
use clino::core::{Attitude, AttitudeFilter, ImuSample, Vec3};
use clino::eval::inclination_error;
use clino::fusion::{FilterKind, FilterSpec, Pipeline, SensorRange, parse_spec};
use clino::io::{CsvLineWriter, ImuCsvReader, ReadOptions};
use clino::sim::hand::{HandMotion, HandParams, duty_clock};
use clino::sim::motion::{Drum, Mounted, Offset, Static, Sum, vibration};
use clino::sim::slewing::{self, SlewingPlatform};
use clino::sim::{ImuModel, Motion};
use nalgebra::Matrix3;
use std::path::PathBuf;

/// One recording: samples, truth (or reference), which samples are scored.
struct Rec {
    samples: Vec<ImuSample>,
    truth: Vec<Option<Attitude>>,
    scored: Vec<bool>,
    /// Which scored samples are at rest (the motion's own rests after the
    /// first motion; none on the slewing machine, whose engine never stops).
    rest: Vec<bool>,
    /// Lever arm to compensate (slewing machine), m.
    lever: Option<Vec3>,
    /// The sensor's full-scale ranges, as its user knows them (simulated:
    /// the model's; BROAD: not known). VQF is not told.
    range: SensorRange,
}

fn rmse(rec: &Rec, est: &[Attitude]) -> f64 {
    rmse_over(rec, est, &rec.scored)
}

/// RMSE over the samples `mask` marks (NaN when none).
fn rmse_over(rec: &Rec, est: &[Attitude], mask: &[bool]) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for (k, q) in est.iter().enumerate() {
        if let (true, Some(t)) = (mask[k], rec.truth[k]) {
            let e = inclination_error(q, &t);
            s += e * e;
            n += 1;
        }
    }
    if n == 0 {
        return f64::NAN;
    }
    (s / n as f64).sqrt().to_degrees()
}

fn nominal_dt(rec: &Rec) -> f64 {
    let mut d: Vec<f64> = rec
        .samples
        .windows(2)
        .map(|w| w[1].t_s - w[0].t_s)
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    d.sort_by(|a, b| a.total_cmp(b));
    d.get(d.len() / 2).copied().unwrap_or(0.01)
}

fn run_vqf(rec: &Rec) -> Vec<Attitude> {
    let ts = nominal_dt(rec);
    let mut v = vqf_rs::VQF::new(ts, None, None, None);
    // VQF has no lever-arm stage: it gets the same compensated specific force
    // as clino's filters (the real-time differentiator, the true rate's bias 0)
    let mut lever = rec.lever.map(LeverArm::new);
    let mut last_t: Option<f64> = None;
    rec.samples
        .iter()
        .map(|s| {
            let mut a = s.acc_m_s2;
            if let (Some(l), Some(t0)) = (&mut lever, last_t) {
                a = l.compensate(&s.gyr_rad_s, &a, &Vec3::zeros(), s.t_s - t0);
            }
            last_t = Some(s.t_s);
            let g = s.gyr_rad_s;
            v.update([g.x, g.y, g.z], [a.x, a.y, a.z], None);
            let q = v.quat_6d();
            Attitude::from_quaternion(nalgebra::Quaternion::new(q.0, q.1, q.2, q.3))
        })
        .collect()
}

fn run_clino(rec: &Rec, spec: &FilterSpec) -> Vec<Attitude> {
    run_pipeline(
        rec,
        Pipeline::new(*spec)
            .with_lever_arm(rec.lever)
            .with_sensor_range(rec.range),
    )
    .0
}

/// The dynamic filter with the online accelerometer-bias estimator (and the
/// lever arm given, or estimated when `auto`); also the final estimates.
fn run_mount(rec: &Rec, spec: &FilterSpec, auto: bool) -> (Vec<Attitude>, Option<(Vec3, Vec3)>) {
    let opts = MountOptions {
        estimate_lever: auto,
        lever_arm_m: if auto {
            Vec3::zeros()
        } else {
            rec.lever.unwrap_or_else(Vec3::zeros)
        },
        ..Default::default()
    };
    run_pipeline(
        rec,
        Pipeline::new(*spec)
            .with_mount_estimator(Some(opts))
            .with_sensor_range(rec.range),
    )
}

fn run_pipeline(rec: &Rec, mut p: Pipeline) -> (Vec<Attitude>, Option<(Vec3, Vec3)>) {
    let est = rec
        .samples
        .iter()
        .map(|s| p.update(s).attitude.unwrap_or_else(Attitude::identity))
        .collect();
    let m = p.mount_estimator().map(|m| (m.accel_bias(), m.lever_arm()));
    (est, m)
}

/// The offline smoother as `clino fuse --offline` runs it
/// ([`clino::fusion::FilterConfig`]): the steps from the sample clock
/// recovered over the whole recording and, where the recording has a lever
/// arm, the accelerometer bias the real-time pass's mount estimator found
/// removed before the passes (`--lever-arm` switches that estimate on with
/// the dynamic filter), the arm given or, with `auto`, estimated
/// (`--lever-arm auto`).
fn run_offline(rec: &Rec, spec: &FilterSpec) -> Vec<Attitude> {
    run_offline_as(rec, spec, false)
}

/// [`run_offline`], the lever arm given (`auto` false) or estimated.
fn run_offline_as(rec: &Rec, spec: &FilterSpec, auto: bool) -> Vec<Attitude> {
    let cfg = clino::fusion::FilterConfig::from_spec(*spec).with_sensor_range(rec.range);
    let cfg = if auto {
        cfg.with_lever_auto(rec.lever.is_some())
    } else {
        cfg.with_lever_arm(rec.lever)
    };
    match cfg.with_offline(true).smooth_samples(&rec.samples) {
        // (a row the smoother could not use has no attitude: identity, and
        // scored as the error it is)
        Ok(q) => q
            .into_iter()
            .map(|q| q.unwrap_or_else(Attitude::identity))
            .collect(),
        // (scored NaN, never as a number that looks right)
        Err(e) => {
            eprintln!("offline smoothing refused: {e}");
            let nan = nalgebra::Quaternion::new(f64::NAN, f64::NAN, f64::NAN, f64::NAN);
            vec![Attitude::new_unchecked(nan); rec.samples.len()]
        }
    }
}

/// A simulated recording of `motion` through `model`, the sensor turned on
/// the body by `mount` ([`Mounted`]; its truth is the sensor's attitude).
#[allow(clippy::too_many_arguments)]
fn simulate(
    motion: &dyn Motion,
    model: &ImuModel,
    rate: f64,
    seconds: f64,
    seed: u64,
    score_from: f64,
    lever: Option<Vec3>,
    mount: Attitude,
) -> Rec {
    let mounted = Mounted { motion, mount };
    let motion: &dyn Motion = &mounted;
    let samples = model.simulate(motion, rate, seconds, seed);
    let truth = samples
        .iter()
        .map(|s| Some(motion.truth(s.t_s).attitude))
        .collect();
    let scored: Vec<bool> = samples.iter().map(|s| s.t_s >= score_from).collect();
    let rest = vec![false; samples.len()];
    Rec {
        samples,
        truth,
        scored,
        rest,
        lever,
        range: SensorRange::from_full_scale(
            model.accel.range / clino::core::G0,
            model.gyro.range.to_degrees(),
        ),
    }
}

/// `rec` with its rests marked: the scored samples at which the hand motion
/// (the carrying motion, without the vibration riding on it) is at rest
/// ([`HandMotion::at_rest`]: stopped, or for a held hand creeping on).
fn with_rests(mut rec: Rec, motion: &HandMotion) -> Rec {
    for (k, s) in rec.samples.iter().enumerate() {
        rec.rest[k] = rec.scored[k] && motion.at_rest(s.t_s);
    }
    rec
}

/// The sensor of a condition.
#[derive(Clone, Copy, Debug)]
enum Sensor {
    /// MPU6050 noise, bandwidth and bias processes, both triads calibrated
    /// ([`slewing::sensor`]: accelerometer bias ≤ 0.8 mg, scale ≤ 0.03 %).
    Calibrated,
    /// The calibrated sensor with the accelerometer reading 4 % low on every axis.
    ScaleLow,
    /// The calibrated sensor with accelerometer scale errors (+5, −5, +3) %.
    ScaleMixed,
    /// The calibrated sensor with an uncalibrated accelerometer bias (7, −10, 5) mg.
    Bias,
    /// The calibrated sensor with gyro scale errors (+2, −1.5, +1) % (an
    /// MPU6050's sensitivity tolerance is ±3 %): fast turns leave a tilt
    /// error the loop must remove at the next rest.
    GyroScale,
    /// Both triads' scale errors at once: gyro (+2, −1.5, +1) % and
    /// accelerometer (+5, −5, +3) % (an MPU6050 out of the box, less its biases).
    ScaleBoth,
    /// Cross-axis sensitivity of both triads, up to 1.5 % (an MPU6050's
    /// datasheet gives ±2 %): an error no diagonal scale or bias model holds,
    /// what a calibration of scale and bias alone leaves behind.
    CrossAxis,
    /// The gyro's cross-axis terms of [`Sensor::CrossAxis`] alone (0.5–1.2 %,
    /// a misalignment and a non-orthogonality), the accelerometer calibrated:
    /// a turn about one axis reads partly about the others, so the gyro
    /// propagates a tilt error of about the cross term times the swing
    /// while the mount moves, which no per-axis scale holds.
    GyroCross,
    /// The accelerometer's cross-axis terms of [`Sensor::CrossAxis`] alone
    /// (0.4–1.5 %), the gyro calibrated: gravity read at rest is turned by
    /// about the terms (level, by 0.97°), which no per-axis scale or bias
    /// holds; the rest-to-rest learner sees only how that turn changes
    /// with the pose.
    AccCross,
    /// The calibrated sensor with its gyro at ±2000 °/s (its accelerometer
    /// stays at ±2 g).
    WideGyro,
    /// A board warming up after power-on, 3 °C a minute throughout: the
    /// biases drift with the MPU6050's temperature coefficients (gyro
    /// 0.08 °/s, accelerometer 0.5–0.86 mg per °C), 0.48 °/s and 3–5 mg
    /// over the two minutes.
    WarmUp,
    /// A gyro never zeroed: biases of (3, −2, 1.5) °/s, within an
    /// MPU6050's zero-rate output tolerance of ±20 °/s (what a hobby board
    /// reads at power-on before anyone holds it still to calibrate).
    GyroBias,
    /// The calibrated sensor mounted on its side (turned 90° about its x
    /// axis: its z axis horizontal), as on a wall, a boom's flank or one
    /// segment of a chain; the truth is the sensor's own attitude.
    Sideways,
    /// The calibrated sensor mounted upside down (turned 180° about x).
    UpsideDown,
    /// The calibrated sensor with its gyro 1 ms behind its accelerometer
    /// (its anti-alias low-pass's delay 1/(2πf_c) 1 ms longer): an
    /// MPU6050 with DLPF_CFG = 0 (the 1-kHz rate) has the accelerometer at
    /// 0 ms and the gyro at 0.98 ms (datasheet), a period at 1 kHz; parts
    /// that filter each triad separately can be further apart. No filter
    /// is told.
    GyroLag,
}

impl Sensor {
    fn name(self) -> &'static str {
        match self {
            Sensor::Calibrated => "cal",
            Sensor::ScaleLow => "acc-4%",
            Sensor::ScaleMixed => "acc±5%",
            Sensor::Bias => "acc-bias10mg",
            Sensor::GyroScale => "gyro±2%",
            Sensor::ScaleBoth => "gyro±2%+acc±5%",
            Sensor::CrossAxis => "xaxis1.5%",
            Sensor::GyroCross => "gyro-xaxis",
            Sensor::AccCross => "acc-xaxis",
            Sensor::WarmUp => "warm-up",
            Sensor::WideGyro => "gyro2000dps",
            Sensor::GyroBias => "gyro-bias3dps",
            Sensor::Sideways => "sideways",
            Sensor::UpsideDown => "upside-down",
            Sensor::GyroLag => "gyro-lag1ms",
        }
    }

    /// How the sensor is turned on the moving body (its frame against the
    /// body's whose motion the simulation describes).
    fn mount(self) -> Attitude {
        let about_x = |a: f64| Attitude::from_scaled_axis(Vec3::new(a, 0.0, 0.0));
        match self {
            Sensor::Sideways => about_x(std::f64::consts::FRAC_PI_2),
            Sensor::UpsideDown => about_x(std::f64::consts::PI),
            _ => Attitude::identity(),
        }
    }
    /// The sensor model at `rate`. With `draw` (a seed, `--draw-errors`),
    /// each error's vector or matrix is drawn for that seed: its entries'
    /// axes and signs shuffled, their sizes kept, so a user's sensor, whose
    /// errors point wherever they point, is scored as well as the one
    /// vector the defaults were looked at on.
    fn model(self, rate: f64, draw: Option<u64>) -> ImuModel {
        let v = |salt: u64, e: Vec3| draw.map_or(e, |seed| signed_permutation(e, seed, salt));
        let x =
            |salt: u64, e: Matrix3<f64>| draw.map_or(e, |seed| shuffled_cross_axis(e, seed, salt));
        let mut m = slewing::sensor();
        // the sensor's anti-alias filter follows its output rate (DLPF ≤ 0.4·f_s)
        m = m.with_bandwidth((0.4 * rate).min(98.0));
        let mg = 1e-3 * clino::core::G0;
        match self {
            Sensor::Calibrated => {}
            Sensor::ScaleLow => m.accel.scale = Vec3::repeat(-0.04),
            Sensor::ScaleMixed => m.accel.scale = v(1, Vec3::new(0.05, -0.05, 0.03)),
            Sensor::Bias => m.accel.bias = v(2, Vec3::new(7.0, -10.0, 5.0) * mg),
            Sensor::GyroScale => m.gyro.scale = v(3, Vec3::new(0.02, -0.015, 0.01)),
            Sensor::ScaleBoth => {
                m.gyro.scale = v(3, Vec3::new(0.02, -0.015, 0.01));
                m.accel.scale = v(1, Vec3::new(0.05, -0.05, 0.03));
            }
            Sensor::WarmUp => m.temperature.rate_c_per_s = 0.05,
            Sensor::GyroBias => m.gyro.bias = v(4, Vec3::new(3.0, -2.0, 1.5).map(f64::to_radians)),
            Sensor::Sideways | Sensor::UpsideDown => {}
            Sensor::GyroLag => {
                let tau = 1.0 / (std::f64::consts::TAU * (0.4 * rate).min(98.0)) + 1e-3;
                m.gyro.bandwidth = clino::sim::imu::Bandwidth::FirstOrder {
                    cutoff_hz: 1.0 / (std::f64::consts::TAU * tau),
                };
            }
            Sensor::WideGyro => m.gyro.range = 2000f64.to_radians(),
            Sensor::GyroCross => m.gyro.cross_axis = x(5, gyro_cross_axis()),
            Sensor::AccCross => m.accel.cross_axis = x(6, accel_cross_axis()),
            Sensor::CrossAxis => {
                m.accel.cross_axis = x(6, accel_cross_axis());
                m.gyro.cross_axis = x(5, gyro_cross_axis());
            }
        }
        m
    }
}

/// `x` with its entries moved to other axes and their signs flipped, drawn
/// for `seed` (and `salt`, one per kind of error): the same sizes, another
/// direction.
fn signed_permutation(x: Vec3, seed: u64, salt: u64) -> Vec3 {
    let mut i = [0usize, 1, 2];
    shuffle(&mut i, seed, salt);
    Vec3::from_fn(|k, _| sign(seed, 16 * salt + 8 + k as u64) * x[i[k]])
}

/// The off-diagonal terms of `m` shuffled among themselves and their signs
/// flipped, drawn for `seed` and `salt` (see [`signed_permutation`]).
fn shuffled_cross_axis(m: Matrix3<f64>, seed: u64, salt: u64) -> Matrix3<f64> {
    let off = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];
    let mut i = [0usize, 1, 2, 3, 4, 5];
    shuffle(&mut i, seed, salt);
    let mut out = Matrix3::zeros();
    for (k, &(r, c)) in off.iter().enumerate() {
        let (fr, fc) = off[i[k]];
        out[(r, c)] = sign(seed, 16 * salt + 8 + k as u64) * m[(fr, fc)];
    }
    out
}

/// A Fisher–Yates shuffle of `i` drawn for `seed` and `salt`.
fn shuffle(i: &mut [usize], seed: u64, salt: u64) {
    for k in (1..i.len()).rev() {
        let j = (unit(seed, 16 * salt + k as u64) * (k + 1) as f64) as usize;
        i.swap(k, j.min(k));
    }
}

/// ±1 drawn for `seed` and stream `k`.
fn sign(seed: u64, k: u64) -> f64 {
    if unit(seed, k) < 0.5 { -1.0 } else { 1.0 }
}

/// The accelerometer cross-axis terms of [`Sensor::CrossAxis`] and
/// [`Sensor::AccCross`]: asymmetric, a misalignment (antisymmetric part)
/// and a non-orthogonality (symmetric part) at once.
fn accel_cross_axis() -> Matrix3<f64> {
    Matrix3::new(
        0.0, 0.012, -0.008, //
        -0.004, 0.0, 0.015, //
        0.010, -0.013, 0.0,
    )
}

/// The gyro cross-axis terms of [`Sensor::CrossAxis`] and
/// [`Sensor::GyroCross`]: asymmetric, a misalignment (antisymmetric part)
/// and a non-orthogonality (symmetric part) at once.
fn gyro_cross_axis() -> Matrix3<f64> {
    Matrix3::new(
        0.0, -0.010, 0.006, //
        0.008, 0.0, -0.012, //
        -0.005, 0.009, 0.0,
    )
}

/// The motion of a condition.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// A segment moved by hand with rests ([`HandParams::by_hand`]).
    Hand,
    /// Slow robot-like motion under 0.35 rad/s with 2-s rests ([`HandParams::slow`]).
    Slow,
    /// The slow motion with vibration (linear 1.5 m/s², angular 2°/s).
    SlowVib,
    /// The slow motion on a structure swaying at its first mode, 1.5–5 Hz
    /// by seed (a boom, a mast), with the same 1.5 m/s² and 2°/s: below
    /// the vibration low-pass's reach, where the engines of `SlowVib` are
    /// above it.
    SlowBoom,
    /// The slow motion on a base rocking at 1.5–5 Hz by seed with the boom's
    /// 2°/s of angular sway and no linear sway (a vehicle on its suspension,
    /// a sensor near the pivot of a structure's mode): the specific force
    /// hardly moves, the rate passes the rest detector's low-pass.
    SlowRock,
    /// The hand motion with 1-s rests.
    ShortRests,
    /// The hand motion with its rests held in the hand, not set down
    /// ([`HandParams::held`]: the pose creeps on at 1 % of the motion's
    /// speed) and a physiological tremor throughout (9 Hz, 0.1 m/s²,
    /// 1°/s).
    Held,
    /// The hand motion at twice its speed (peaks of 4–8 rad/s, 2 g): an
    /// MPU6050 at its power-on ranges (±250 °/s, ±2 g) clips its gyro in
    /// the fast turns.
    Hand2x,
    /// The hand motion at three times its speed (peaks of 6–13 rad/s, 4 g).
    Hand3x,
    /// A sensor shaken to and fro by hand with little rotation (BROAD's
    /// fast translations): ±0.1 m at 1–3 Hz (about 1 g at the peaks), tilt
    /// and yaw within ±8° on the same clock, moves of 8 s, rests of 3 s.
    Shake,
    /// The hand motion turning a segment about a joint 0.25 m from the
    /// sensor (a chain of segments moved by hand, a sensor on an arm): the
    /// sensor's tangential and centripetal accelerations turn with it
    /// ([`Offset`]), no lever arm given to any filter.
    Arm,
    /// [`Kind::Arm`] with the arm given, as a user who measured it runs
    /// `clino fuse --lever-arm` (the `dyn+bias` column: the bias estimator
    /// that flag switches on): the joint is carried by the hand, so the
    /// arm's terms leave the hand's own accelerations.
    ArmGiven,
    /// A drum turning one way about its horizontal x axis at 2 ± 1 rad/s
    /// (swing 0.1 Hz) in runs of 20 s with stops of 4 s ([`Drum`]): a gyro
    /// scale error drifts the tilt at a rate with a mean while it turns.
    Drum,
    /// The slewing excavator with the lever arm given.
    Slewing,
    /// The slewing excavator whose boom sways at 1.5–4.5 Hz by seed (1 m/s²,
    /// 1°/s) instead of its engine's 30 Hz.
    SlewingSway,
    /// The slewing excavator rocked from the start by its digging (its
    /// whole body translated on an ellipse of 0.3 m/s² at 0.7 Hz,
    /// [`slewing::digging`]): its dwells never pass for rest.
    SlewingRock,
    /// [`Kind::Slewing`] with no lever arm given to any filter: a user who
    /// has not measured it runs `clino fuse` as it is. VQF, too, reads the
    /// tangential and centripetal accelerations.
    SlewingBare,
    /// [`Kind::SlewingRock`] with no lever arm given: the machine never
    /// rests, and nothing tells the loop the slew's centripetal
    /// acceleration from a tilt.
    SlewingRockBare,
    /// A base precessing on a 2° cone at 0.025 Hz: a steady turn of
    /// 0.31°/s, under the rest detector's 0.5°/s and slower than any hand
    /// (a hull's slow list, a structure drifting, a tilt table creeping),
    /// tilted 3° and never still.
    Cone,
    /// [`Kind::Cone`] on a machine digging ([`slewing::digging`]): no
    /// stillness passes for rest, and the specific force cannot tell the
    /// slow turn within a few seconds.
    ConeDig,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::Hand => "hand",
            Kind::Slow => "slow",
            Kind::SlowVib => "slow+vib",
            Kind::SlowBoom => "slow+boom",
            Kind::SlowRock => "slow+rock",
            Kind::ShortRests => "hand,rests1s",
            Kind::Held => "hand,held",
            Kind::Arm => "hand,arm0.25m",
            Kind::ArmGiven => "hand,arm0.25m+lever",
            Kind::Hand2x => "hand,2x",
            Kind::Hand3x => "hand,3x",
            Kind::Shake => "shake",
            Kind::Drum => "drum",
            Kind::Slewing => "slewing+lever",
            Kind::SlewingSway => "slewing+sway+lever",
            Kind::SlewingRock => "slewing+rock+lever",
            Kind::SlewingBare => "slewing",
            Kind::SlewingRockBare => "slewing+rock",
            Kind::Cone => "cone",
            Kind::ConeDig => "cone+dig",
        }
    }
}

struct Condition {
    name: String,
    kind: Kind,
    sensor: Sensor,
    rate: f64,
}

/// A structure's sway frequency in [lo, hi) Hz for `seed`, spread over the
/// seeds in golden-ratio steps.
fn sway_hz(seed: u64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * (seed as f64 * 0.618_033_988_75).fract()
}

fn make(c: &Condition, seed: u64, draw: bool) -> Rec {
    let model = c.sensor.model(c.rate, draw.then_some(seed));
    let seconds = 120.0;
    // the condition's sensor, rate and mount; scored from `from` on
    let sim = |m: &dyn Motion, from: f64| {
        simulate(
            m,
            &model,
            c.rate,
            seconds,
            seed,
            from,
            None,
            c.sensor.mount(),
        )
    };
    match c.kind {
        Kind::Slewing
        | Kind::SlewingSway
        | Kind::SlewingRock
        | Kind::SlewingBare
        | Kind::SlewingRockBare => {
            let mut m = SlewingPlatform {
                chassis_heading: 0.7 + seed as f64,
                vibration_hz: (0.35 * c.rate).min(30.0),
                ..Default::default()
            };
            if let Kind::SlewingSway = c.kind {
                m.vibration_hz = sway_hz(seed, 1.5, 4.5);
                m.vibration_m_s2 = 1.0;
                m.vibration_rate_rad_s = 1f64.to_radians();
            }
            let rocked = Sum {
                a: m.clone(),
                b: slewing::digging(0.0),
            };
            let bare = matches!(c.kind, Kind::SlewingBare | Kind::SlewingRockBare);
            let motion: &dyn Motion = if let Kind::SlewingRock | Kind::SlewingRockBare = c.kind {
                &rocked
            } else {
                &m
            };
            simulate(
                motion,
                &model,
                c.rate,
                seconds,
                seed,
                m.initial_rest_s,
                (!bare).then_some(m.lever_arm_m),
                // (the lever arm is in the machine's frame: upright only)
                Attitude::identity(),
            )
        }
        Kind::Cone | Kind::ConeDig => {
            let (hz, angle) = (0.025, 2f64.to_radians());
            let w = 2.0 * std::f64::consts::PI * hz;
            let base = Sum {
                a: Static::new(Attitude::from_euler_angles(0.05, -0.03, 0.7 + seed as f64)),
                b: vibration(hz, w * angle, Vec3::zeros()),
            };
            let mut dig = slewing::digging(0.0);
            if let Kind::Cone = c.kind {
                dig.amplitude_m = Vec3::zeros();
            }
            sim(&Sum { a: base, b: dig }, 10.0)
        }
        Kind::Drum => {
            let duty = HandParams {
                move_s: 20.0,
                rest_s: 4.0,
                ramp_s: 1.0,
                initial_rest_s: 5.0,
                ..HandParams::by_hand()
            };
            let m = Drum {
                duty,
                rate_rad_s: 2.0,
                swing_rad_s: 1.0,
                swing_hz: 0.1,
                heading_rad: 0.7 + seed as f64,
            };
            let mut rec = sim(&m, duty.initial_rest_s);
            for (k, s) in rec.samples.iter().enumerate() {
                rec.rest[k] = rec.scored[k] && duty_clock(&duty, s.t_s).1 == 0.0;
            }
            rec
        }
        Kind::Arm | Kind::ArmGiven => {
            let hand = HandMotion::new(HandParams::by_hand(), seed);
            let m = Offset {
                motion: hand,
                r_body_m: Vec3::new(0.25, 0.05, 0.0),
            };
            let from = hand.params.initial_rest_s;
            let mut rec = with_rests(sim(&m, from), &hand);
            if let Kind::ArmGiven = c.kind {
                rec.lever = Some(m.r_body_m);
            }
            rec
        }
        Kind::Hand
        | Kind::Hand2x
        | Kind::Hand3x
        | Kind::Shake
        | Kind::Slow
        | Kind::SlowVib
        | Kind::SlowBoom
        | Kind::SlowRock
        | Kind::ShortRests
        | Kind::Held => {
            let mut p = match c.kind {
                Kind::Slow | Kind::SlowVib | Kind::SlowBoom | Kind::SlowRock => HandParams::slow(),
                Kind::Held => HandParams::held(),
                _ => HandParams::by_hand(),
            };
            let speed = match c.kind {
                Kind::Hand2x => 2.0,
                Kind::Hand3x => 3.0,
                _ => 1.0,
            };
            p.band_hz = (p.band_hz.0 * speed, p.band_hz.1 * speed);
            if let Kind::ShortRests = c.kind {
                p.rest_s = 1.0;
            }
            if let Kind::Shake = c.kind {
                p.tilt_amplitude_rad = 8f64.to_radians();
                p.yaw_amplitude_rad = 8f64.to_radians();
                p.position_amplitude_m = 0.1;
                p.band_hz = (1.0, 3.0);
            }
            let hand = HandMotion::new(p, seed);
            let from = p.initial_rest_s;
            if let Kind::Held = c.kind {
                // physiological tremor, 8–12 Hz: about 0.1 m/s² and 1°/s
                let m = Sum {
                    a: hand,
                    b: vibration(9.0, 1f64.to_radians(), Vec3::new(0.1, 0.08, 0.06)),
                };
                let rec = sim(&m, from);
                return with_rests(rec, &hand);
            }
            if let Kind::SlowVib | Kind::SlowBoom | Kind::SlowRock = c.kind {
                let f = if let Kind::SlowBoom | Kind::SlowRock = c.kind {
                    sway_hz(seed, 1.5, 5.0)
                } else {
                    (0.35 * c.rate).min(30.0)
                };
                let linear = if let Kind::SlowRock = c.kind {
                    Vec3::zeros()
                } else {
                    Vec3::new(1.5, 1.0, 1.2)
                };
                let m = Sum {
                    a: hand,
                    b: vibration(f, 2f64.to_radians(), linear),
                };
                with_rests(sim(&m, from), &hand)
            } else {
                with_rests(sim(&hand, from), &hand)
            }
        }
    }
}

/// The slewing machine with an uncalibrated accelerometer: the tilt with the
/// lever arm given (without and with the bias estimator) and with
/// `--lever-arm auto`, and the final estimates against the truth; with its
/// engine's 30-Hz vibration, then with its boom swaying at 1.5–4.5 Hz.
fn slewing_estimates(seeds: Seeds, dynamic: &FilterSpec, rates: &[f64]) {
    for &rate in rates {
        for kind in [Kind::Slewing, Kind::SlewingSway] {
            slewing_table(seeds, dynamic, kind, rate);
        }
    }
}

/// [`slewing_estimates`] on one slewing machine.
fn slewing_table(seeds: Seeds, dynamic: &FilterSpec, kind: Kind, rate: f64) {
    println!(
        "\nslewing machine{}, accelerometer bias {}, {rate} Hz, 120 s: inclination RMSE, final estimates",
        if let Kind::SlewingSway = kind {
            " with its boom swaying at 1.5-4.5 Hz (1 m/s², 1°/s)"
        } else {
            ""
        },
        if seeds.draw {
            "of the sizes of (7, -10, 5) mg, on axes and with signs drawn per seed"
        } else {
            "(7, -10, 5) mg"
        }
    );
    println!(
        "{:<6}{:>10}{:>11}{:>10}{:>12}{:>14}{:>14}{:>11}{:>11}",
        "seed",
        "lever °",
        "+bias °",
        "auto °",
        "|Δb_xy| mg",
        "|Δr_xy| cm",
        "|Δr| cm",
        "offline °",
        "off auto °"
    );
    let c = Condition {
        name: String::new(),
        kind,
        sensor: Sensor::Bias,
        rate,
    };
    let b_true = |seed: u64| {
        Sensor::Bias
            .model(rate, seeds.draw.then_some(seed))
            .accel
            .bias
    };
    let r_true = SlewingPlatform::default().lever_arm_m;
    let mut worst = [0.0f64; 5];
    for seed in seeds.range() {
        let rec = seeds.make(&c, seed);
        let lever = rmse(&rec, &run_clino(&rec, dynamic));
        let (q, _) = run_mount(&rec, dynamic, false);
        let bias = rmse(&rec, &q);
        let (q, m) = run_mount(&rec, dynamic, true);
        let auto = rmse(&rec, &q);
        let (b, r) = m.unwrap_or((Vec3::repeat(f64::NAN), Vec3::repeat(f64::NAN)));
        let db = (b - b_true(seed)).xy().norm() / (1e-3 * clino::core::G0);
        let dr = (r - r_true).xy().norm() * 100.0;
        let dr3 = (r - r_true).norm() * 100.0;
        // offline as `clino fuse --offline --lever-arm X` and `… auto`
        let off = rmse(&rec, &run_offline_as(&rec, dynamic, false));
        let off_auto = rmse(&rec, &run_offline_as(&rec, dynamic, true));
        for (w, v) in worst.iter_mut().zip([lever, bias, auto, off, off_auto]) {
            // (a NaN stays: f64::max would drop it, and a failed seed is
            // never the best)
            *w = if v.is_nan() || w.is_nan() {
                f64::NAN
            } else {
                w.max(v)
            };
        }
        println!(
            "{seed:<6}{lever:>10.3}{bias:>11.3}{auto:>10.3}{db:>12.2}{dr:>14.1}{dr3:>14.1}{off:>11.3}{off_auto:>11.3}"
        );
    }
    println!(
        "{:<6}{:>10.3}{:>11.3}{:>10.3}{:>40.3}{:>11.3}",
        "worst", worst[0], worst[1], worst[2], worst[3], worst[4]
    );
}

/// Which samples a link that loses a share `p` of them, in bursts of
/// `burst`, delivers (seeded, deterministic); the first always.
fn received(n: usize, p: f64, burst: usize, seed: u64) -> Vec<bool> {
    let mut x = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut keep = vec![true; n];
    let mut k = 1;
    while k < n {
        // xorshift64*
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        let u = (x.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64;
        if u < p / burst as f64 {
            for kk in keep.iter_mut().skip(k).take(burst) {
                *kk = false;
            }
            k += burst;
        } else {
            k += 1;
        }
    }
    keep
}

/// `rec` as received: only the samples `keep` marks.
fn received_part(rec: &Rec, keep: &[bool]) -> Rec {
    let pick = |k: &usize| keep[*k];
    let n = rec.samples.len();
    Rec {
        samples: (0..n).filter(pick).map(|k| rec.samples[k]).collect(),
        truth: (0..n).filter(pick).map(|k| rec.truth[k]).collect(),
        scored: (0..n).filter(pick).map(|k| rec.scored[k]).collect(),
        rest: (0..n).filter(pick).map(|k| rec.rest[k]).collect(),
        lever: rec.lever,
        range: rec.range,
    }
}

/// `rec` as a filter with a fixed sample period (VQF) takes it when the
/// samples `keep` does not mark were lost: each replaced by the next one
/// received, scored on the samples received.
fn held_over(rec: &Rec, keep: &[bool]) -> Rec {
    let n = rec.samples.len();
    let mut filled = rec.samples.clone();
    for k in (0..n.saturating_sub(1)).rev() {
        if !keep[k] {
            filled[k] = ImuSample {
                t_s: rec.samples[k].t_s,
                ..filled[k + 1]
            };
        }
    }
    Rec {
        samples: filled,
        truth: rec.truth.clone(),
        scored: (0..n).map(|k| rec.scored[k] && keep[k]).collect(),
        rest: rec.rest.clone(),
        lever: rec.lever,
        range: rec.range,
    }
}

/// `rec` scored against its truth re-timed by `x` sample periods: row k
/// against the truth at t_k + x·h, slerped between the neighbouring rows'
/// truths (the motions are smooth over a period). The rows beyond the ends
/// keep the end's truth.
fn retimed(rec: &Rec, x: f64) -> Rec {
    let n = rec.truth.len().max(1);
    let (j, f) = (x.floor() as isize, x - x.floor());
    let at = |k: isize| rec.truth[k.clamp(0, n as isize - 1) as usize];
    let truth = (0..rec.truth.len() as isize)
        .map(|k| match (at(k + j), at(k + j + 1)) {
            (Some(a), Some(b)) => Some(a.slerp(&b, f)),
            (a, _) => a,
        })
        .collect();
    Rec {
        samples: rec.samples.clone(),
        truth,
        scored: rec.scored.clone(),
        rest: rec.rest.clone(),
        lever: rec.lever,
        range: rec.range,
    }
}

/// The sensor's delay behind the reference ([`retimed`]): VQF, `dynamic` as
/// given and `dynamic` with `sensor_delay_periods` set to the delay.
fn delay_table(seeds: Seeds, dynamic: &FilterSpec) {
    // the simulator's first-order anti-alias filter at 0.4·f_s delays by
    // 1/(2π·0.4) = 0.40 periods
    const SIMULATED: f64 = 0.4;
    println!("\nthe sensor's delay behind the reference: inclination RMSE (mean over the seeds)");
    println!(
        "{:<22}{:>8}{:>9}{:>10}{:>7}{:>14}{:>7}",
        "condition", "delay", "vqf °", "dynamic", "ratio", "delay given", "ratio"
    );
    for (name, kind, rate) in [
        ("hand@40Hz cal", Kind::Hand, 40.0),
        ("drum@100Hz cal", Kind::Drum, 100.0),
    ] {
        let c = Condition {
            name: name.into(),
            kind,
            sensor: Sensor::Calibrated,
            rate,
        };
        let recs: Vec<Rec> = seeds.range().map(|seed| seeds.make(&c, seed)).collect();
        for delay in [0.0, SIMULATED, 1.2] {
            let mut given = *dynamic;
            if let FilterSpec::Dynamic(p) = &mut given {
                p.sensor_delay_periods = delay;
            }
            let (mut v, mut d, mut g) = (0.0, 0.0, 0.0);
            for rec in &recs {
                let r = retimed(rec, delay - SIMULATED);
                v += rmse(&r, &run_vqf(&r));
                d += rmse(&r, &run_clino(&r, dynamic));
                g += rmse(&r, &run_clino(&r, &given));
            }
            let k = seeds.n as f64;
            println!(
                "{name:<22}{delay:>8.1}{:>9.3}{:>10.3}{:>7.2}{:>14.3}{:>7.2}",
                v / k,
                d / k,
                d / v,
                g / k,
                g / v
            );
        }
    }
}

/// A gyro 1 ms behind its accelerometer (the grid's `gyro-lag1ms`, an
/// MPU6050 at DLPF_CFG = 0): VQF; `dynamic` as given; with the sensor's
/// delay told (`sensor_delay_periods`, the gyro's: the simulator's
/// first-order low-pass, 1/(2π·min(0.4·rate, 98 Hz)) and the 1 ms); and with
/// `gyro_lag_s` told as well, and told the wrong way round (−1 ms), over
/// the motion and at rest; the offline smoother as given and told both.
fn lag_table(seeds: Seeds, dynamic: &FilterSpec) {
    let FilterSpec::Dynamic(base) = dynamic else {
        return;
    };
    const LAG_S: f64 = 1e-3;
    println!(
        "\na gyro 1 ms behind its accelerometer: inclination RMSE (mean over the seeds), ratio to VQF's"
    );
    println!(
        "{:<26}{:>7}{:>8}{:>14}{:>14}{:>14}{:>14}{:>14}{:>14}{:>14}{:>10}{:>10}",
        "condition",
        "delay",
        "vqf °",
        "dynamic",
        "delay told",
        "+ lag told",
        "lag -1 ms",
        "at rest",
        "rest, delay",
        "rest, + lag",
        "offline",
        "both told"
    );
    for (kind, rate) in [
        (Kind::Hand, 1000.0),
        (Kind::Shake, 100.0),
        (Kind::Drum, 100.0),
        (Kind::Drum, 1000.0),
    ] {
        let c = Condition {
            name: format!("{}@{rate}Hz gyro-lag1ms", kind.name()),
            kind,
            sensor: Sensor::GyroLag,
            rate,
        };
        // the gyro's delay in periods (the sensor's model in `make`)
        let delay = (1.0 / (std::f64::consts::TAU * (0.4 * rate).min(98.0)) + LAG_S) * rate;
        let told = |lag: f64| {
            FilterSpec::Dynamic(DynamicParams {
                sensor_delay_periods: delay,
                gyro_lag_s: lag,
                ..*base
            })
        };
        let (delay_only, both, wrong) = (told(0.0), told(LAG_S), told(-LAG_S));
        // means: VQF, dynamic, delay, both, wrong; at rest: VQF, dynamic,
        // delay, both; offline: as given, both told
        let mut m = [0.0f64; 11];
        for seed in seeds.range() {
            let rec = seeds.make(&c, seed);
            let est = [
                run_vqf(&rec),
                run_clino(&rec, dynamic),
                run_clino(&rec, &delay_only),
                run_clino(&rec, &both),
                run_clino(&rec, &wrong),
            ];
            let mut row: Vec<f64> = est.iter().map(|q| rmse(&rec, q)).collect();
            row.extend(est[..4].iter().map(|q| rmse_over(&rec, q, &rec.rest)));
            row.push(rmse(&rec, &run_offline(&rec, dynamic)));
            row.push(rmse(&rec, &run_offline(&rec, &both)));
            for (a, x) in m.iter_mut().zip(row) {
                *a += x / seeds.n as f64;
            }
        }
        let cell = |x: f64, vqf: f64| format!("{x:.3} {:>5.2}", x / vqf);
        println!(
            "{:<26}{delay:>7.2}{:>8.3}{:>14}{:>14}{:>14}{:>14}{:>14}{:>14}{:>14}{:>10.3}{:>10.3}",
            c.name,
            m[0],
            cell(m[1], m[0]),
            cell(m[2], m[0]),
            cell(m[3], m[0]),
            cell(m[4], m[0]),
            cell(m[6], m[5]),
            cell(m[7], m[5]),
            cell(m[8], m[5]),
            m[9],
            m[10]
        );
    }
}

/// What the rest pairs' learner buys and costs: `dynamic` as given, with the
/// accelerometer scale's prior halved (1.5 %: the MPU6050's ±3 % read as a
/// two-sigma band), with the accelerometer's scale and bias not learnt, and
/// with no learning from rest pairs at all; each against VQF (mean ratio,
/// worst recording) on the sensors the learner is for (per-axis scale
/// errors, cross-axis sensitivity, a gyro scale error, an accelerometer
/// bias) and on calibrated ones, where all it can do is fit the pairs'
/// noise (the slow arm, whose long segments carry the gyro bias error's
/// drift; on a swaying base a single pair in two minutes).
fn learner_table(seeds: Seeds, dynamic: &FilterSpec) {
    let FilterSpec::Dynamic(base) = dynamic else {
        return;
    };
    let with = |f: &dyn Fn(&mut DynamicParams)| {
        let mut p = *base;
        f(&mut p);
        FilterSpec::Dynamic(p)
    };
    let variants = [
        ("as given", *dynamic),
        (
            "acc scale 1.5 %",
            with(&|p| p.accel_scale_sigma = base.accel_scale_sigma.min(0.015)),
        ),
        (
            "no acc learning",
            with(&|p| (p.accel_scale_sigma, p.accel_bias_sigma) = (0.0, 0.0)),
        ),
        (
            "no learning",
            with(&|p| {
                (p.gyro_scale_sigma, p.accel_scale_sigma, p.accel_bias_sigma) = (0.0, 0.0, 0.0)
            }),
        ),
    ];
    println!(
        "
the rest pairs' learner: inclination RMSE ratio to VQF, mean (worst recording)"
    );
    print!("{:<28}{:>8}", "condition (seeds)", "vqf °");
    for (name, _) in &variants {
        print!("{name:>18}");
    }
    println!();
    for (kind, sensor, rate) in [
        (Kind::Hand, Sensor::Calibrated, 40.0),
        (Kind::Hand, Sensor::ScaleMixed, 40.0),
        (Kind::Hand, Sensor::GyroScale, 40.0),
        (Kind::Hand, Sensor::CrossAxis, 40.0),
        (Kind::SlowVib, Sensor::Calibrated, 100.0),
        (Kind::SlowVib, Sensor::Bias, 100.0),
        (Kind::SlowVib, Sensor::ScaleLow, 125.0),
        (Kind::SlowBoom, Sensor::Calibrated, 125.0),
    ] {
        let c = Condition {
            name: format!("{}@{rate}Hz {}", kind.name(), sensor.name()),
            kind,
            sensor,
            rate,
        };
        let recs: Vec<Rec> = seeds.range().map(|seed| seeds.make(&c, seed)).collect();
        let v: Vec<f64> = recs.iter().map(|r| rmse(r, &run_vqf(r))).collect();
        let v_mean = v.iter().sum::<f64>() / seeds.n as f64;
        print!("{:<28}{v_mean:>8.3}", format!("{} ({seeds})", c.name));
        for (_, spec) in &variants {
            let d: Vec<f64> = recs.iter().map(|r| rmse(r, &run_clino(r, spec))).collect();
            let mean = d.iter().sum::<f64>() / seeds.n as f64;
            let worst = d
                .iter()
                .zip(&v)
                .map(|(d, v)| d / v)
                .fold(f64::NAN, f64::max);
            print!("{:>11.2} ({worst:.2})", mean / v_mean);
        }
        println!();
    }
}

/// Samples lost on the way (a radio link's dropouts): the calibrated hand at
/// 40 Hz, `dynamic` given the samples received (each step as long as the
/// time since the last one, as the pipeline gives it), VQF (a fixed sample
/// period) the recording with each lost sample replaced by the next one
/// received; both scored on the samples received, and `dynamic` offline
/// ([`clino::smooth`]) on the samples received.
fn lost_samples(seeds: Seeds, dynamic: &FilterSpec) {
    println!("\nlost samples, hand @40 Hz calibrated: inclination RMSE on the samples received");
    println!(
        "{:<24}{:>10}{:>10}{:>8}{:>10}",
        "samples lost", "vqf °", "dynamic", "ratio", "offline"
    );
    let c = Condition {
        name: String::new(),
        kind: Kind::Hand,
        sensor: Sensor::Calibrated,
        rate: 40.0,
    };
    for (name, p, burst) in [
        ("none", 0.0, 1),
        ("5 %, one at a time", 0.05, 1),
        ("5 %, bursts of 5", 0.05, 5),
        ("20 %, one at a time", 0.2, 1),
    ] {
        let (mut v, mut d, mut o) = (0.0, 0.0, 0.0);
        for seed in seeds.range() {
            let rec = seeds.make(&c, seed);
            let n = rec.samples.len();
            let keep = received(n, p, burst, seed);
            let sub = received_part(&rec, &keep);
            d += rmse(&sub, &run_clino(&sub, dynamic));
            o += rmse(&sub, &run_offline(&sub, dynamic));
            let full = held_over(&rec, &keep);
            v += rmse(&full, &run_vqf(&full));
        }
        let k = seeds.n as f64;
        println!(
            "{name:<24}{:>10.3}{:>10.3}{:>8.2}{:>10.3}",
            v / k,
            d / k,
            d / v,
            o / k
        );
    }
}

/// A uniform number in [0, 1) for `k` under `seed` (splitmix64: seeded,
/// deterministic).
fn unit(seed: u64, k: u64) -> f64 {
    let mut z = seed
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(k.wrapping_mul(0xBF58_476D_1CE4_E5B9));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

/// How a recording's time stamps were made.
#[derive(Clone, Copy, Debug)]
enum Stamps {
    /// The sensor's own sample clock.
    Sensor,
    /// Each stamp off by up to ±`x` of a period, uniformly (a host's clock
    /// read at each sample, to either side).
    Uniform(f64),
    /// The host's receive times: each sample late by 0–`x` s (exponential,
    /// mean x/4, cut at x), never before the one before (an operating
    /// system's scheduling).
    Late(f64),
    /// The host's receive times through a USB serial bridge that sends what
    /// it holds every `x` s (an FTDI chip's latency timer, 16 ms by
    /// default): every sample of a packet stamped at its arrival, 0–1 ms
    /// after the packet, 20 µs apart.
    Packets(f64),
}

impl Stamps {
    fn name(self) -> String {
        match self {
            Stamps::Sensor => "the sensor's clock".into(),
            Stamps::Uniform(x) => format!("±{:.0} % of a period", 100.0 * x),
            Stamps::Late(x) => format!("late by 0–{:.0} ms", 1e3 * x),
            Stamps::Packets(x) => format!("USB packets every {:.0} ms", 1e3 * x),
        }
    }

    /// The stamps of the sample times `t`.
    fn apply(self, t: &[f64], seed: u64) -> Vec<f64> {
        let h = if t.len() > 1 {
            (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64
        } else {
            0.01
        };
        let mut out: Vec<f64> = Vec::with_capacity(t.len());
        let (mut last_packet, mut within) = (f64::NAN, 0.0);
        for (k, &tk) in t.iter().enumerate() {
            let u = unit(seed, k as u64);
            let s = match self {
                Stamps::Sensor => tk,
                Stamps::Uniform(x) => tk + x * h * (2.0 * u - 1.0),
                Stamps::Late(x) => tk + (-(x / 4.0) * (1.0 - u).ln()).min(x),
                Stamps::Packets(x) => {
                    let packet = (tk / x).floor() + 1.0;
                    within = if packet == last_packet {
                        within + 1.0
                    } else {
                        0.0
                    };
                    last_packet = packet;
                    packet * x + 1e-3 * unit(seed ^ 0x5A5A, packet as u64) + 20e-6 * within
                }
            };
            let floor = out.last().map_or(f64::MIN, |p| p + 1e-6);
            out.push(s.max(floor));
        }
        out
    }
}

/// Time stamps that are not the sensor's: the calibrated hand at 100 Hz
/// and the slow arm on a vibrating base at 125 Hz, `dynamic` (real time and
/// offline) given the stamps as a host made them, VQF its fixed sample
/// period (the rate a user knows); all scored against the truth at the
/// sensor's sample times.
fn stamps_table(seeds: Seeds, dynamic: &FilterSpec) {
    println!(
        "\ntime stamps not made by the sensor's clock: inclination RMSE (on the samples received)"
    );
    println!(
        "{:<20}{:<36}{:>8}{:>10}{:>8}{:>10}{:>10}",
        "condition", "stamps", "vqf °", "dynamic", "ratio", "as given", "offline"
    );
    for (kind, rate) in [(Kind::Hand, 100.0), (Kind::SlowVib, 125.0)] {
        let c = Condition {
            name: format!("{}@{rate:.0}Hz cal", kind.name()),
            kind,
            sensor: Sensor::Calibrated,
            rate,
        };
        for (stamps, lost) in [
            (Stamps::Sensor, false),
            (Stamps::Uniform(0.3), false),
            (Stamps::Uniform(0.45), false),
            (Stamps::Late(0.008), false),
            (Stamps::Packets(0.016), false),
            (Stamps::Sensor, true),
            (Stamps::Uniform(0.3), true),
            (Stamps::Late(0.008), true),
        ] {
            let (mut v, mut d, mut g, mut o) = (0.0, 0.0, 0.0, 0.0);
            for seed in seeds.range() {
                let rec = seeds.make(&c, seed);
                let n = rec.samples.len();
                // 2 % of the samples lost, one at a time (seeded)
                let keep: Vec<bool> = if lost {
                    received(n, 0.02, 1, seed)
                } else {
                    vec![true; n]
                };
                let mut host = received_part(&rec, &keep);
                let t: Vec<f64> = host.samples.iter().map(|s| s.t_s).collect();
                for (s, ts) in host.samples.iter_mut().zip(stamps.apply(&t, seed)) {
                    s.t_s = ts;
                }
                d += rmse(&host, &run_clino(&host, dynamic));
                let given = Pipeline::new(*dynamic)
                    .with_sensor_range(host.range)
                    .with_sample_clock(false);
                g += rmse(&host, &run_pipeline(&host, given).0);
                o += rmse(&host, &run_offline(&host, dynamic));
                // VQF, whose period is fixed
                let full = held_over(&rec, &keep);
                v += rmse(&full, &run_vqf(&full));
            }
            let k = seeds.n as f64;
            let name = if lost {
                format!("{}, 2 % lost", stamps.name())
            } else {
                stamps.name()
            };
            println!(
                "{:<20}{:<36}{:>8.3}{:>10.3}{:>8.2}{:>10.3}{:>10.3}",
                c.name,
                name,
                v / k,
                d / k,
                d / v,
                g / k,
                o / k
            );
        }
    }
}

/// Sensors switched on already moving (no initial rest): the calibrated
/// hand at 40 Hz and the slow arm at 100 Hz, scored from the first sample
/// (the first 20 s, and the whole 120 s).
fn started_in_motion(seeds: Seeds, dynamic: &FilterSpec) {
    println!("\nswitched on in motion (no initial rest): inclination RMSE from the first sample");
    println!(
        "{:<24}{:>10}{:>10}{:>8}{:>12}{:>10}{:>8}",
        "motion", "vqf 20 s", "dynamic", "ratio", "vqf 120 s", "dynamic", "ratio"
    );
    for (name, slow, rate) in [
        ("hand @40 Hz", false, 40.0),
        ("slow arm @100 Hz", true, 100.0),
    ] {
        let mut r = [0.0; 4];
        for seed in seeds.range() {
            let p = HandParams {
                initial_rest_s: 0.0,
                ..if slow {
                    HandParams::slow()
                } else {
                    HandParams::by_hand()
                }
            };
            let hand = HandMotion::new(p, seed);
            let model = Sensor::Calibrated.model(rate, None);
            let mut rec = simulate(
                &hand,
                &model,
                rate,
                120.0,
                seed,
                0.0,
                None,
                Attitude::identity(),
            );
            let (v, d) = (run_vqf(&rec), run_clino(&rec, dynamic));
            r[2] += rmse(&rec, &v);
            r[3] += rmse(&rec, &d);
            for (k, s) in rec.samples.iter().enumerate() {
                rec.scored[k] = s.t_s < 20.0;
            }
            r[0] += rmse(&rec, &v);
            r[1] += rmse(&rec, &d);
        }
        let k = seeds.n as f64;
        println!(
            "{name:<24}{:>10.3}{:>10.3}{:>8.2}{:>12.3}{:>10.3}{:>8.2}",
            r[0] / k,
            r[1] / k,
            r[1] / r[0],
            r[2] / k,
            r[3] / k,
            r[3] / r[2]
        );
    }
}

fn load_broad(path: &PathBuf) -> clino::Result<Rec> {
    let mut r = ImuCsvReader::from_path(path, &ReadOptions::default())?;
    let mut rec = Rec {
        samples: vec![],
        truth: vec![],
        scored: vec![],
        rest: vec![],
        lever: None,
        range: SensorRange::default(),
    };
    let mut moved = false;
    while let Some(row) = r.next_row()? {
        rec.samples.push(row.sample);
        rec.truth.push(row.ref_q);
        let m = row.movement.unwrap_or(false);
        moved |= m;
        rec.scored.push(m);
        // BROAD's own rests after its first motion (not the initial one)
        rec.rest.push(moved && row.movement == Some(false));
    }
    Ok(rec)
}

/// How far before a rest the rest-anchored score reaches, s.
const BEFORE_REST_S: f64 = 1.5;

/// The seconds into each of a BROAD recording's rests (after movement,
/// lasting 2 s or more) and the [`BEFORE_REST_S`] before it, scored without
/// the optical reference: the truth is the gyro (less the bias `dynamic`
/// learnt at that rest) carried back from the accelerometer's mean over
/// 0.5–1.5 s into the rest, with `dynamic`'s heading there. The reference's
/// own misalignment and latency drop out, and so does the accelerometer's
/// error at rest, which both filters are scored against alike; what is left
/// is the gyro's error over those 2.5 s (its scale times the angle turned).
/// RMSE of VQF and `dynamic`, degrees; `None` without such a rest.
fn before_rest(rec: &Rec, vqf: &[Attitude], dynamic: &FilterSpec) -> Option<(f64, f64)> {
    let mut p = Pipeline::new(*dynamic);
    let (mut qd, mut bias) = (Vec::new(), Vec::new());
    for s in &rec.samples {
        qd.push(p.update(s).attitude.unwrap_or_else(Attitude::identity));
        bias.push(p.filter().gyro_bias());
    }
    let t = |k: usize| rec.samples[k].t_s;
    let n = rec.samples.len();
    let (mut sd, mut sv, mut m) = (0.0, 0.0, 0usize);
    let mut k = 1;
    while k < n {
        if !rec.scored[k - 1] || rec.scored[k] {
            k += 1;
            continue;
        }
        let start = k;
        let mut end = k;
        while end < n && !rec.scored[end] {
            end += 1;
        }
        k = end;
        if t(end - 1) - t(start) < 2.0 {
            continue;
        }
        let ta = t(start) + 1.0;
        let Some(ka) = (start..end).find(|&i| t(i) >= ta) else {
            continue;
        };
        let (mut am, mut c) = (Vec3::zeros(), 0.0);
        for i in start..end {
            if (t(i) - ta).abs() <= 0.5 {
                am += rec.samples[i].acc_m_s2;
                c += 1.0;
            }
        }
        let up = qd[ka].inverse_transform_vector(&Vec3::z());
        let Some(turn) = nalgebra::UnitQuaternion::rotation_between(&(am / c), &up) else {
            continue;
        };
        let b = bias[end - 1];
        let mut q = qd[ka] * turn;
        let mut i = ka;
        while i > 0 && t(i) > t(start) - BEFORE_REST_S {
            let step = (rec.samples[i].gyr_rad_s - b) * (t(i) - t(i - 1));
            q *= nalgebra::UnitQuaternion::from_scaled_axis(step).inverse();
            i -= 1;
            sd += inclination_error(&qd[i], &q).powi(2);
            sv += inclination_error(&vqf[i], &q).powi(2);
            m += 1;
        }
    }
    (m > 0).then(|| {
        let f = |s: f64| (s / m as f64).sqrt().to_degrees();
        (f(sv), f(sd))
    })
}

/// Scores of one recording: VQF, then each of `filters`, then offline
/// dynamic, then dynamic with the mount estimator (the lever arm given, or
/// none), then with the lever arm estimated (`--lever-arm auto`: on a mount
/// with no rotation axis it must leave the tilt as it was); then at rest
/// ([`Rec::rest`]) VQF and the first of `filters`.
fn score(rec: &Rec, filters: &[FilterSpec], dynamic: &FilterSpec) -> Vec<f64> {
    let vqf = run_vqf(rec);
    let mut out = vec![rmse(rec, &vqf)];
    let mut first_rest = f64::NAN;
    for (i, f) in filters.iter().enumerate() {
        let est = run_clino(rec, f);
        out.push(rmse(rec, &est));
        if i == 0 {
            first_rest = rmse_over(rec, &est, &rec.rest);
        }
    }
    out.push(rmse(rec, &run_offline(rec, dynamic)));
    out.push(rmse(rec, &run_mount(rec, dynamic, false).0));
    out.push(rmse(rec, &run_mount(rec, dynamic, true).0));
    out.push(rmse_over(rec, &vqf, &rec.rest));
    out.push(first_rest);
    out
}

/// The error at rest of VQF and of `dynamic` (the last two scores of each
/// row): a steady offset the loop leaves at rest shows here.
fn print_rest_table(rows: &[(String, Vec<Vec<f64>>)]) {
    println!("\nat rest (the motion's own rests after the first motion): inclination RMSE");
    println!(
        "{:<40}{:>8}{:>9}{:>7}{:>7}",
        "condition (seeds)", "vqf °", "dynamic", "ratio", "worst"
    );
    for (label, r) in rows {
        let (n, k) = (r.len(), r[0].len());
        let vm = r.iter().map(|x| x[k - 2]).sum::<f64>() / n as f64;
        let dm = r.iter().map(|x| x[k - 1]).sum::<f64>() / n as f64;
        if !vm.is_finite() {
            continue;
        }
        let worst = r
            .iter()
            .map(|x| x[k - 1] / x[k - 2])
            .fold(f64::NAN, f64::max);
        println!("{label:<40}{vm:>8.3}{dm:>9.3}{:>7.2}{worst:>7.2}", dm / vm);
    }
}

/// Write `rec` as a BROAD-format CSV at `path` (`--export`).
fn export_recording(path: &std::path::Path, rec: &Rec) -> clino::Result<()> {
    let io =
        |e: std::io::Error| clino::Error::new(clino::ErrorKind::Io, e.to_string()).in_file(path);
    let f = std::fs::File::create(path).map_err(io)?;
    let mut w = CsvLineWriter::new(f);
    // the raw columns as `clino stream --record` writes them (less `temp_c`),
    // then the reference and the masks
    let mut head: Vec<&str> = clino::stream::RAW_HEADER[..7].to_vec();
    head.extend(["ref_qw", "ref_qx", "ref_qy", "ref_qz", "movement", "rest"]);
    w.header(&head).map_err(io)?;
    for (k, s) in rec.samples.iter().enumerate() {
        w.f64(s.t_s);
        for v in s.gyr_rad_s.iter().chain(s.acc_m_s2.iter()) {
            w.f64(*v);
        }
        let q = rec.truth[k].map_or([f64::NAN; 4], |t| {
            let q = t.quaternion();
            [q.w, q.i, q.j, q.k]
        });
        for v in q {
            w.f64(v);
        }
        w.str(if rec.scored[k] { "1" } else { "0" });
        w.str(if rec.rest[k] { "1" } else { "0" });
        w.end_row().map_err(io)?;
    }
    w.finish().map(drop).map_err(io)
}

/// The file name of a condition's recording: its name with every character
/// that is not a letter, digit, `.` or `-` replaced by `_`.
fn export_name(condition: &str, seed: u64) -> String {
    let slug: String = condition
        .chars()
        .map(|c| match c {
            '±' => "pm".to_string(),
            '%' => "pc".to_string(),
            c if c.is_ascii_alphanumeric() || c == '.' || c == '-' => c.to_string(),
            _ => "_".to_string(),
        })
        .collect();
    format!("{slug}_s{seed}.csv")
}

/// `--slewing-rates`: positive sample rates in Hz, comma-separated.
fn parse_rates(v: &str) -> clino::Result<Vec<f64>> {
    v.split(',')
        .map(|x| x.trim().parse::<f64>())
        .collect::<Result<Vec<_>, _>>()
        .ok()
        .filter(|r| !r.is_empty() && r.iter().all(|f| f.is_finite() && *f > 0.0))
        .ok_or_else(|| {
            clino::Error::new(
                clino::ErrorKind::InvalidInput,
                format!("--slewing-rates: positive sample rates in Hz, comma-separated, not '{v}'"),
            )
        })
}

/// The seeds every condition runs on: `n` of them from `first` (`--seeds`,
/// `--first-seed`). The defaults were chosen on seeds 1–8; a run from another
/// first seed (say 101) scores them on motions, noise and sensor errors they
/// were never looked at on.
#[derive(Clone, Copy)]
struct Seeds {
    first: u64,
    n: u64,
    /// Each seed draws its sensor's errors ([`Sensor::model`]).
    draw: bool,
}

impl Seeds {
    fn make(self, c: &Condition, seed: u64) -> Rec {
        make(c, seed, self.draw)
    }

    fn range(self) -> std::ops::RangeInclusive<u64> {
        self.first..=self.first + (self.n - 1)
    }
}

impl std::fmt::Display for Seeds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}", self.n)
    }
}

fn main() -> clino::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut seeds = Seeds {
        first: 1,
        n: 3,
        draw: false,
    };
    let mut only: Option<String> = None;
    let mut dynamic = FilterSpec::default();
    let mut broad = clino_bench::broad_dir();
    let mut export: Option<PathBuf> = None;
    let mut slewing_rates = vec![200.0];
    let mut i = 0;
    while i < args.len() {
        let val = || {
            args.get(i + 1).cloned().ok_or_else(|| {
                clino::Error::new(
                    clino::ErrorKind::InvalidInput,
                    format!("{} needs a value", args[i]),
                )
            })
        };
        match args[i].as_str() {
            "--seeds" => {
                seeds.n = val()?.parse().ok().filter(|&n| n > 0).ok_or_else(|| {
                    clino::Error::new(clino::ErrorKind::InvalidInput, "--seeds: a positive number")
                })?;
                i += 1;
            }
            "--draw-errors" => seeds.draw = true,
            "--first-seed" => {
                seeds.first = val()?.parse().map_err(|_| {
                    clino::Error::new(clino::ErrorKind::InvalidInput, "--first-seed: a number")
                })?;
                i += 1;
            }
            "--only" => {
                only = Some(val()?);
                i += 1;
            }
            "--dynamic" => {
                dynamic = parse_spec(&val()?)?;
                i += 1;
            }
            "--broad" => {
                broad = Some(PathBuf::from(val()?));
                i += 1;
            }
            "--no-broad" => broad = None,
            "--slewing-rates" => {
                slewing_rates = parse_rates(&val()?)?;
                i += 1;
            }
            "--export" => {
                export = Some(PathBuf::from(val()?));
                i += 1;
            }
            other => {
                return Err(clino::Error::new(
                    clino::ErrorKind::InvalidInput,
                    format!("unknown argument {other}"),
                ));
            }
        }
        i += 1;
    }
    if seeds.first.checked_add(seeds.n - 1).is_none() {
        return Err(clino::Error::new(
            clino::ErrorKind::InvalidInput,
            "--first-seed: the last seed would be past 2^64 - 1",
        ));
    }
    let mut filters: Vec<FilterSpec> = vec![dynamic];
    for k in [
        FilterKind::Mahony,
        FilterKind::Madgwick,
        FilterKind::Complementary,
    ] {
        filters.push(FilterSpec::default_for(k));
    }
    let names = [
        "dynamic", "mahony", "madgwick", "complem.", "offline", "dyn+bias", "dyn+auto",
    ];
    let mut conditions = Vec::new();
    for &rate in &[25.0, 100.0, 1000.0] {
        for kind in [Kind::Hand, Kind::SlowVib, Kind::ShortRests, Kind::Held] {
            for sensor in [Sensor::Calibrated, Sensor::ScaleLow, Sensor::Bias] {
                conditions.push(Condition {
                    name: format!("{}@{rate}Hz {}", kind.name(), sensor.name()),
                    kind,
                    sensor,
                    rate,
                });
            }
        }
    }
    for (kind, sensor, rate) in [
        (Kind::Hand, Sensor::Calibrated, 40.0),
        (Kind::Hand, Sensor::ScaleMixed, 40.0),
        (Kind::Hand, Sensor::GyroScale, 40.0),
        (Kind::Hand, Sensor::GyroScale, 100.0),
        (Kind::Hand, Sensor::ScaleMixed, 100.0),
        (Kind::Hand, Sensor::ScaleBoth, 40.0),
        (Kind::Arm, Sensor::Calibrated, 40.0),
        (Kind::Arm, Sensor::Calibrated, 100.0),
        (Kind::Arm, Sensor::Bias, 40.0),
        (Kind::ArmGiven, Sensor::Calibrated, 40.0),
        (Kind::ArmGiven, Sensor::Calibrated, 100.0),
        (Kind::Hand, Sensor::CrossAxis, 40.0),
        (Kind::Hand, Sensor::CrossAxis, 100.0),
        (Kind::Hand, Sensor::GyroCross, 40.0),
        (Kind::Hand, Sensor::GyroCross, 100.0),
        (Kind::SlowVib, Sensor::GyroCross, 125.0),
        (Kind::Shake, Sensor::GyroCross, 100.0),
        (Kind::Hand, Sensor::AccCross, 40.0),
        (Kind::Hand, Sensor::AccCross, 100.0),
        (Kind::SlowVib, Sensor::AccCross, 125.0),
        (Kind::SlowVib, Sensor::CrossAxis, 125.0),
        (Kind::Hand, Sensor::WarmUp, 40.0),
        (Kind::ShortRests, Sensor::WarmUp, 40.0),
        (Kind::Held, Sensor::WarmUp, 40.0),
        (Kind::SlowVib, Sensor::WarmUp, 125.0),
        (Kind::SlowVib, Sensor::ScaleMixed, 125.0),
        (Kind::Slow, Sensor::ScaleLow, 125.0),
        (Kind::SlowVib, Sensor::ScaleLow, 125.0),
        (Kind::SlowBoom, Sensor::Calibrated, 125.0),
        (Kind::SlowBoom, Sensor::ScaleLow, 125.0),
        (Kind::SlowBoom, Sensor::GyroScale, 125.0),
        (Kind::SlowBoom, Sensor::WarmUp, 125.0),
        (Kind::SlowBoom, Sensor::Calibrated, 25.0),
        (Kind::SlowBoom, Sensor::GyroScale, 25.0),
        (Kind::SlowBoom, Sensor::Calibrated, 1000.0),
        (Kind::SlowBoom, Sensor::GyroScale, 1000.0),
        (Kind::SlowVib, Sensor::GyroScale, 125.0),
        (Kind::SlowVib, Sensor::CrossAxis, 25.0),
        (Kind::Hand2x, Sensor::Calibrated, 40.0),
        (Kind::Hand2x, Sensor::Calibrated, 100.0),
        (Kind::Hand3x, Sensor::WideGyro, 100.0),
        (Kind::Shake, Sensor::Calibrated, 40.0),
        (Kind::Shake, Sensor::Calibrated, 100.0),
        (Kind::Shake, Sensor::GyroScale, 100.0),
        (Kind::Drum, Sensor::Calibrated, 100.0),
        (Kind::Drum, Sensor::GyroScale, 100.0),
        (Kind::Drum, Sensor::GyroScale, 25.0),
        (Kind::Hand, Sensor::GyroBias, 40.0),
        (Kind::Held, Sensor::GyroBias, 100.0),
        (Kind::SlowVib, Sensor::GyroBias, 125.0),
        (Kind::Hand, Sensor::Sideways, 40.0),
        (Kind::Hand, Sensor::UpsideDown, 40.0),
        (Kind::SlowVib, Sensor::Sideways, 125.0),
        (Kind::SlowBoom, Sensor::UpsideDown, 125.0),
        (Kind::Hand, Sensor::GyroLag, 1000.0),
        (Kind::Shake, Sensor::GyroLag, 100.0),
        (Kind::Drum, Sensor::GyroLag, 100.0),
        (Kind::Drum, Sensor::GyroLag, 1000.0),
        (Kind::SlowRock, Sensor::Calibrated, 125.0),
        (Kind::SlowRock, Sensor::GyroScale, 125.0),
        (Kind::SlowRock, Sensor::Calibrated, 25.0),
        (Kind::Slewing, Sensor::Calibrated, 200.0),
        (Kind::Slewing, Sensor::Bias, 200.0),
        (Kind::Slewing, Sensor::Bias, 50.0),
        (Kind::Slewing, Sensor::Calibrated, 50.0),
        (Kind::Slewing, Sensor::Calibrated, 25.0),
        (Kind::SlewingRock, Sensor::Calibrated, 50.0),
        (Kind::SlewingRock, Sensor::Bias, 50.0),
        (Kind::SlewingRock, Sensor::Bias, 200.0),
        (Kind::SlewingBare, Sensor::Calibrated, 50.0),
        (Kind::SlewingRockBare, Sensor::Calibrated, 50.0),
        (Kind::Cone, Sensor::Calibrated, 100.0),
        (Kind::Cone, Sensor::Calibrated, 25.0),
        (Kind::Cone, Sensor::Bias, 100.0),
        (Kind::ConeDig, Sensor::Calibrated, 100.0),
    ] {
        conditions.push(Condition {
            name: format!("{}@{rate}Hz {}", kind.name(), sensor.name()),
            kind,
            sensor,
            rate,
        });
    }
    println!("dynamic: {}", clino::fusion::spec_text(&dynamic));
    println!(
        "seeds: {}–{}{}",
        seeds.first,
        seeds.first + (seeds.n - 1),
        if seeds.draw {
            ", each drawing its sensor's errors"
        } else {
            ""
        }
    );
    print!("{:<32}{:>8}", "condition (seeds)", "vqf °");
    for n in names {
        print!("{n:>20}");
    }
    println!();
    println!("{:<40}{}", "", "   mean° ratio worst".repeat(names.len()));
    let mut all_ratio: Vec<Vec<f64>> = vec![vec![]; names.len()];
    let print_row = |label: &str, rows: &[Vec<f64>], all: &mut Vec<Vec<f64>>| {
        let n = rows.len() as f64;
        let mean = |j: usize| rows.iter().map(|r| r[j]).sum::<f64>() / n;
        let v = mean(0);
        print!("{label:<32}{v:>8.3}");
        for j in 1..=names.len() {
            let m = mean(j);
            let worst = rows.iter().map(|r| r[j] / r[0]).fold(f64::NAN, f64::max);
            all[j - 1].push(m / v);
            print!("{m:>8.3}{:>6.2}{worst:>6.2}", m / v);
        }
        println!();
    };
    let mut rest_rows: Vec<(String, Vec<Vec<f64>>)> = Vec::new();
    let mut index = match &export {
        Some(d) => {
            let io = |e: std::io::Error| {
                clino::Error::new(clino::ErrorKind::Io, e.to_string()).in_file(d)
            };
            std::fs::create_dir_all(d).map_err(io)?;
            let f = std::fs::File::create(d.join("index.csv")).map_err(io)?;
            let mut w = CsvLineWriter::new(f);
            w.header(&[
                "file",
                "condition",
                "seed",
                "vqf_rs_deg",
                "dynamic_deg",
                "offline_deg",
                "vqf_rs_rest_deg",
                "dynamic_rest_deg",
            ])
            .map_err(io)?;
            Some(w)
        }
        None => None,
    };
    for c in &conditions {
        if let Some(o) = &only
            && !c.name.contains(o.as_str())
        {
            continue;
        }
        let mut rows: Vec<Vec<f64>> = Vec::new();
        for seed in seeds.range() {
            let rec = seeds.make(c, seed);
            let r = score(&rec, &filters, &dynamic);
            if let (Some(d), Some(w), false) = (&export, &mut index, rec.lever.is_some()) {
                let name = export_name(&c.name, seed);
                export_recording(&d.join(&name), &rec)?;
                let k = r.len();
                w.str(&name);
                // quoted: condition names hold commas ("hand,held@…")
                w.str(&format!("\"{}\"", c.name));
                w.f64(seed as f64);
                for v in [r[0], r[1], r[5], r[k - 2], r[k - 1]] {
                    w.f64(v);
                }
                w.end_row().map_err(|e| {
                    clino::Error::new(clino::ErrorKind::Io, e.to_string()).in_file(d)
                })?;
            }
            rows.push(r);
        }
        let label = format!("{} ({seeds})", c.name);
        print_row(&label, &rows, &mut all_ratio);
        rest_rows.push((label, rows));
    }
    if let Some(d) = broad
        && only.as_deref().is_none_or(|o| "broad".contains(o))
    {
        let paths = clino::eval::expand_paths(&[d])?;
        let mut before = Vec::new();
        let rows: Vec<Vec<f64>> = paths
            .iter()
            .map(|p| {
                load_broad(p).map(|r| {
                    before.push(before_rest(&r, &run_vqf(&r), &dynamic));
                    score(&r, &filters, &dynamic)
                })
            })
            .collect::<clino::Result<_>>()?;
        for ((p, r), b) in paths.iter().zip(&rows).zip(&before) {
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().to_string())
                .unwrap_or_default();
            let k = r.len();
            let into = b.map_or_else(
                || "-".to_string(),
                |(v, d)| format!("vqf {v:.3} dynamic {d:.3} ({:.2})", d / v),
            );
            println!(
                "  {name:<44}vqf {:.3}  dynamic {:.3} ({:.2})  offline {:.3}  at rest: vqf {:.3} dynamic {:.3}  into rests (rest-anchored): {into}",
                r[0],
                r[1],
                r[1] / r[0],
                r[5],
                r[k - 2],
                r[k - 1]
            );
        }
        let some: Vec<(f64, f64)> = before.iter().flatten().copied().collect();
        if !some.is_empty() {
            let k = some.len() as f64;
            let (v, d) = some
                .iter()
                .fold((0.0, 0.0), |(a, b), (v, d)| (a + v / k, b + d / k));
            println!(
                "  into rests, rest-anchored ({} recordings, {BEFORE_REST_S} s before each rest to 1 s into it): vqf {v:.3}  dynamic {d:.3} ({:.2})",
                some.len(),
                d / v
            );
        }
        let label = format!("BROAD ({})", rows.len());
        print_row(&label, &rows, &mut all_ratio);
        rest_rows.push((label, rows));
    }
    if let (Some(d), Some(w)) = (&export, index) {
        w.finish()
            .map_err(|e| clino::Error::new(clino::ErrorKind::Io, e.to_string()).in_file(d))?;
    }
    if !rest_rows.is_empty() {
        print_rest_table(&rest_rows);
    }
    if only.as_deref().is_none_or(|o| "slewing".contains(o)) {
        slewing_estimates(seeds, &dynamic, &slewing_rates);
    }
    if only.as_deref().is_none_or(|o| "lost".contains(o)) {
        lost_samples(seeds, &dynamic);
    }
    if only.as_deref().is_none_or(|o| "stamps".contains(o)) {
        stamps_table(seeds, &dynamic);
    }
    if only.as_deref().is_none_or(|o| "started".contains(o)) {
        started_in_motion(seeds, &dynamic);
    }
    if only.as_deref().is_none_or(|o| "delay".contains(o)) {
        delay_table(seeds, &dynamic);
    }
    if only.as_deref().is_none_or(|o| "lag".contains(o)) {
        lag_table(seeds, &dynamic);
    }
    if only.as_deref().is_none_or(|o| "learner".contains(o)) {
        learner_table(seeds, &dynamic);
    }
    if all_ratio.iter().any(|r| !r.is_empty()) {
        print!("{:<40}", "largest mean ratio over the conditions");
        for r in &all_ratio {
            print!("{:>20.2}", r.iter().copied().fold(f64::NAN, f64::max));
        }
        println!();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_seeds_flags_change_the_recordings() {
        // --first-seed: the seeds from it; --draw-errors: the same seed's
        // recording with its sensor's errors drawn reads differently
        let s = Seeds {
            first: 101,
            n: 3,
            draw: false,
        };
        assert_eq!(s.range().collect::<Vec<_>>(), vec![101, 102, 103]);
        let c = Condition {
            name: "hand@40Hz acc-bias10mg".into(),
            kind: Kind::Hand,
            sensor: Sensor::Bias,
            rate: 40.0,
        };
        let plain = s.make(&c, 101);
        let drawn = Seeds { draw: true, ..s }.make(&c, 101);
        assert_eq!(plain.samples.len(), drawn.samples.len());
        assert_eq!(plain.truth, drawn.truth, "the same motion");
        let differs = plain
            .samples
            .iter()
            .zip(&drawn.samples)
            .any(|(a, b)| a.acc_m_s2 != b.acc_m_s2);
        assert!(differs, "the drawn bias is not in the readings");
        // another seed, another motion
        assert_ne!(s.make(&c, 102).truth, plain.truth);
    }

    #[test]
    fn drawn_sensor_errors_keep_their_sizes_and_change_their_directions() {
        // without a draw, the one vector the defaults were looked at on
        let fixed = Sensor::Bias.model(100.0, None).accel.bias;
        let mg = 1e-3 * clino::core::G0;
        assert_eq!(fixed, Vec3::new(7.0, -10.0, 5.0) * mg);
        let sorted = |v: &[f64]| {
            let mut a: Vec<f64> = v.iter().map(|x| x.abs()).collect();
            a.sort_by(f64::total_cmp);
            a
        };
        let mut seen = std::collections::HashSet::new();
        for seed in 101..=108 {
            // a bias: the same sizes on the axes, in another order and signs
            let b = Sensor::Bias.model(100.0, Some(seed)).accel.bias;
            assert_eq!(
                sorted(b.as_slice()),
                sorted(fixed.as_slice()),
                "seed {seed}"
            );
            seen.insert(b.map(|x| (x / mg).round() as i64).as_slice().to_vec());
            // cross-axis terms: still none on the diagonal, the same six sizes
            let m = Sensor::GyroCross.model(100.0, Some(seed)).gyro.cross_axis;
            let off = |m: &Matrix3<f64>| {
                let mut v = vec![];
                for r in 0..3 {
                    for c in 0..3 {
                        if r == c {
                            assert_eq!(m[(r, c)], 0.0);
                        } else {
                            v.push(m[(r, c)]);
                        }
                    }
                }
                v
            };
            assert_eq!(
                sorted(&off(&m)),
                sorted(&off(&gyro_cross_axis())),
                "seed {seed}"
            );
            // the same seed draws the same errors
            assert_eq!(
                m,
                Sensor::GyroCross.model(100.0, Some(seed)).gyro.cross_axis
            );
        }
        // eight seeds point the bias in more than a few directions
        assert!(seen.len() >= 5, "{seen:?}");
    }

    #[test]
    fn slewing_rates_are_parsed_and_change_the_machine() {
        assert_eq!(parse_rates("25, 50,200").unwrap(), vec![25.0, 50.0, 200.0]);
        for bad in ["", "50,", "x", "-3", "0", "NaN", "inf", "25;50"] {
            assert!(parse_rates(bad).is_err(), "'{bad}'");
        }
        // the table's recording at each rate: its sample period, and its
        // engine at 0.35 of the rate (at most 30 Hz) shaking the gyro
        for rate in [25.0, 200.0] {
            let c = Condition {
                name: String::new(),
                kind: Kind::Slewing,
                sensor: Sensor::Bias,
                rate,
            };
            let rec = make(&c, 1, false);
            assert_eq!(rec.samples.len(), (120.0 * rate) as usize);
            let dt = rec.samples[1].t_s - rec.samples[0].t_s;
            assert!((dt - 1.0 / rate).abs() < 1e-9, "{rate} Hz: {dt}");
            assert!(rec.lever.is_some());
        }
    }

    #[test]
    fn a_bare_slewing_machine_is_the_same_recording_with_no_arm_given() {
        // the rows without the arm differ from theirs with it in what the
        // filters are told, not in what the sensor read
        for (given, bare) in [
            (Kind::Slewing, Kind::SlewingBare),
            (Kind::SlewingRock, Kind::SlewingRockBare),
        ] {
            let c = |kind| Condition {
                name: String::new(),
                kind,
                sensor: Sensor::Calibrated,
                rate: 25.0,
            };
            let (a, b) = (make(&c(given), 2, false), make(&c(bare), 2, false));
            assert!(a.lever.is_some() && b.lever.is_none());
            assert_eq!(a.samples.len(), b.samples.len());
            assert!(a.samples.iter().zip(&b.samples).all(|(x, y)| x == y));
        }
    }
}
