//! Offline (non-causal) tilt estimation for recordings: the dynamic filter run
//! forwards and backwards in time, combined.
//!
//! A causal filter lags: the accelerometer's evidence about the tilt at time t
//! arrives over the following seconds. With the whole recording at hand the
//! same evidence can be used from both sides. This is the two-filter form of
//! fixed-interval smoothing (Fraser & Potter, 1969): a forward and a backward
//! run of the same filter, combined. Here:
//!
//! 1. a forward pass of [`clino_core::filter::Dynamic`] over the recording learns the gyro bias at
//!    the end;
//! 2. a backward pass runs on the time-reversed recording (rates negated: the
//!    reversed body turns the other way; sample k's interval is the one ending
//!    at sample k + 1), starting from the end state, and learns the bias at the start;
//! 3. a second forward pass starts from the start state;
//! 4. two more passes, forwards and backwards, run with the bias imposed as the
//!    mean of the backward and second forward estimates at each sample (a
//!    smoothed bias trajectory), each pass starting where the previous ended,
//!    and with the accelerometer's scale errors and bias that the second
//!    forward pass learnt from rest to rest over the whole record imposed from
//!    the first sample ([`clino_core::filter::Dynamic::set_sensor_errors`]);
//!    where the bias drifts, passes 1–3 learnt at eight times the real-time
//!    loop's bias gain give the trajectory instead (*drift*, below); and
//!    with the gyro scale factors the learner found, or those fitted to the
//!    two passes' disagreement, imposed where that brings the two passes
//!    together (*scale*, below);
//! 5. at every sample the tilt is the mean of the two up vectors of those passes
//!    (equal weights — their errors are alike and nearly independent); the
//!    heading is the forward pass's;
//! 6. a whole-record refinement uses the mount's bounded velocity and
//!    position (from the specific force corrected as in 4):
//!    [`refine_bounded_motion`], a Kalman/Rauch–Tung–Striebel smoother on
//!    the remaining tilt error (skip it for travelling mounts), under two
//!    models of how that error evolves, whose smoothed corrections are
//!    averaged: the passes' tilt corrections are right and what remains is
//!    a slow Gauss–Markov error (the residual model), or the gyro is right
//!    (its rate less the smoothed bias, with the gyro scale factors the
//!    second forward pass learnt) up to a slow random walk, so that every
//!    correction the passes made beyond the gyro is itself an error unless
//!    the bounded motion confirms it (the gyro model); the gyro model's
//!    weight is 1 − d/2, d the learner's doubt in the gyro's propagation
//!    ([`clino_core::filter::Dynamic::gyro_doubt`], [`BoundedMotion::gyro_weight`]).
//!
//! *Drift.* The real-time loop learns the bias in motion with a time
//! constant of about 75 s (made for a bias that holds for minutes and
//! that rests keep told; a third of that while none has), so a
//! board warming up (3 °C a minute: 0.004 °/s each second) is lagged by
//! about 0.3 °/s, forwards and backwards alike: their mean misses a drift
//! that the passes never caught up with (a hand holding poses without
//! setting the sensor down: 0.39° offline against offline VQF's 0.28°).
//! So passes 1–3 are also run with the bias gain eight times larger
//! (`DRIFT_BIAS_GAIN`), and that trajectory, with what its learner made of
//! the rest pairs, is taken when it drifts by at least 0.1 °/s a minute
//! (`DRIFT_RATE_DEG_S_PER_MIN`) and removes at least half of the mean
//! square disagreement between the forward and backward tilt passes
//! (`DRIFT_EXPLAINS`): a bias error turns the two passes' tilts apart in
//! opposite directions, and a trajectory that is right brings them
//! together. Elsewhere the result is the steady passes', to the bit.
//!
//! *Scale.* The tilt passes do not learn, so a gyro scale error the
//! learning passes found from rest to rest acts on them unless imposed: the
//! forward and backward passes then drift apart in opposite directions by
//! the scale error times the angle turned. The learnt scale is imposed where
//! it removes at least half of their mean-square disagreement (the same
//! `DRIFT_EXPLAINS`): a gyro with ±2 % scale errors moved by hand at 100 Hz,
//! 0.105° → 0.079° offline (a drum turning one way 0.452° → 0.142°), while on
//! BROAD trial 31, where unmodelled errors of a real gyro are learnt as
//! −0.47 % of z scale, it removes 36 % and is not imposed.
//!
//! Where no rest pair taught the scale (a boom's sway is notched and no
//! pair forms; pairs the prior holds back), the disagreement itself tells
//! it: it is linear in the scale errors, so three more pairs of passes,
//! each with one axis's scale stepped by 1 %, give its response, and one
//! Gauss–Newton step with the learner's prior (`scale_fit`) the scale that
//! explains it best. That scale is taken where it removes at least 75 % of
//! the disagreement (`SCALE_FIT_EXPLAINS`: a fit always removes some), and
//! half of what the learnt scale leaves if that was taken. Whichever scale
//! is taken, the learning passes had taken part of the scale error in
//! their rest pairs for the accelerometer's errors, which are imposed from
//! the first sample (a steady offset), so the whole smoothing runs again
//! on the rates the scale corrects (not where the gyro clipped: a
//! corrected rate no longer reads at the range; the scale is then imposed
//! as it is; with the learnt scale too since 6 Dec 2026, when held poses'
//! pairs came to teach it well enough that no fit was taken after it: the
//! slow arm on a vibrating base, 8 seeds, offline 0.064° → 0.061°, the
//! drum 0.142° → 0.130°). The slow arm with (+2, −1.5, +1) % errors,
//! 8 seeds: on a boom swaying at 1.5–5 Hz 0.126° → 0.061° offline, 0.050°
//! since the bar is 75 % (offline VQF 0.096°); on a base vibrating at
//! 30 Hz 0.118° → 0.065° (0.095°; 0.090° with the scale imposed but nothing
//! learnt again); on a base rocking at 1.5–5 Hz, where few rest pairs form,
//! 0.098° at 85 %, 0.073° at 75 % (0.095°); BROAD unchanged (its calibrated
//! IMUs' fits remove 7–72 %).
//!
//! *Clipping.* Given the sensor's ranges ([`SmoothOptions::sensor_range`]),
//! every pass is told of a clipped gyro or accelerometer as the real-time
//! filter is ([`Pipeline::with_sensor_range`]), and where the gyro clipped
//! the forward and backward up vectors are weighted by how settled each pass
//! is, 1 − exp(−t/τ), t the time since the pass last crossed a clipped rate
//! and τ = 1/`bandwidth_rad_s` (the loop's memory): after a fast turn the
//! pass that comes from the quiet side counts most. The refinement's gyro
//! model (the gyro right up to a slow random walk) is wrong at a clipped
//! rate: there its walk takes the variance of a shortfall as large as the
//! range itself, (range·h)² over a step h. A hand at twice its speed
//! through ±250 °/s at 40 Hz (8.5 % of samples clipped, 8 seeds): 2.23° not
//! told; told, 2.25° with equal weights and no added variance, 2.17°
//! weighted, **1.51°** with the variance (offline VQF 2.02°; the variance at
//! 0.1, 0.3 and 3 times the range: 1.58, 1.45 and 2.43°; BENCHMARKS.md).
//!
//! Gaps of lost samples (steps beyond 1.5 typical steps) are filled before
//! the passes, rate and specific force interpolated linearly across them,
//! and only the attitudes of the samples given are returned.
//!
//! Lever-arm compensation, when asked for, is done once before the passes,
//! with a centred (zero-lag) derivative of the rate ([`compensate_centred`]).
//!
//! Memory: the recording (56 bytes a sample: rate, specific force, interval)
//! and at most 88 bytes a sample of working state (at 20 Hz and above; 112
//! where a gyro scale is taken) beyond the 32-byte
//! attitudes returned ([`smooth_in_place`]), unlike the streaming real-time
//! path, which holds nothing.

use clino_core::filter::dynamic::STEPS_ALIKE;
use clino_core::filter::{DynamicParams, FilterSpec};
use clino_core::pipeline::{Pipeline, SensorRange};
use clino_core::tilt::up_in_body;
use clino_core::{Attitude, AttitudeFilter, ImuSample, Vec3};
use nalgebra::UnitQuaternion;

/// Options of the offline smoother.
#[derive(Clone, Debug)]
pub struct SmoothOptions {
    /// Parameters of the dynamic filter used in every pass.
    pub params: DynamicParams,
    /// Lever arm of the sensor from the rotation axis, m (body frame).
    pub lever_arm_m: Option<Vec3>,
    /// The final whole-record refinement ([`refine_bounded_motion`]); `None` skips it
    /// (for mounts that travel, e.g. vehicles).
    pub refine: Option<BoundedMotion>,
    /// Also learn the gyro bias as a drift (a board warming up) and take
    /// that trajectory where the record shows one (see the [module
    /// docs](self)). Default on; off saves three to seven passes.
    pub drift: bool,
    /// Impose the gyro scale factors the rest pairs taught, or those fitted
    /// to the forward and backward passes' disagreement, in the tilt passes
    /// where that brings them together (see the [module docs](self)).
    /// Default on; off saves eight to twelve passes (and, where a scale is
    /// taken, the whole smoothing again).
    pub scale: bool,
    /// The sensor's full-scale ranges, as the rates given read them
    /// ([`SensorRange`]): where the gyro clipped, the forward and backward
    /// passes are weighted by how long ago each last crossed a clipped rate
    /// (see the [module docs](self)). Default: not known.
    pub sensor_range: SensorRange,
}

impl Default for SmoothOptions {
    fn default() -> Self {
        Self {
            params: DynamicParams::default(),
            lever_arm_m: None,
            refine: Some(BoundedMotion::default()),
            drift: true,
            scale: true,
            sensor_range: SensorRange::default(),
        }
    }
}

/// What the offline refinement assumes about the mount's motion: it works in
/// place (a hand, a machine arm, a test platform, an excavator or crane that
/// does not travel), so over the record its horizontal velocity and its
/// displacement from where it started stay within about these sizes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoundedMotion {
    /// Typical horizontal speed, m/s. Default 1 m/s.
    pub speed_m_s: f64,
    /// Typical horizontal excursion from the start, m. Default 1 m.
    pub range_m: f64,
    /// How far the smoothed tilt may still be wrong, rad (1σ). Default 0.5°.
    pub tilt_sigma_rad: f64,
    /// Correlation time of that tilt error, s. Default 10 s.
    pub tilt_tau_s: f64,
    /// Rate at which the velocity and position bounds are imposed, Hz. Default 10 Hz
    /// (about the inverse correlation time of hand and machine motion).
    pub constraint_rate_hz: f64,
    /// Random walk of the tilt the gyro alone carries, rad/√s, in the gyro
    /// model: what the smoothed bias and the learnt scale factors leave of
    /// the gyro's error. Default 1e-3 rad/√s (0.057°/√s, 0.18° over 10 s):
    /// an MPU6050-class gyro's residual bias after rest-to-rest smoothing,
    /// ≈ 0.01°/s over the ≈ 10 s between rests, (1.7e-4 rad/s)²·10 s =
    /// 3e-7 rad²/s, its white noise (0.005°/s/√Hz: 8e-9 rad²/s) and the
    /// cross-axis and g-sensitivity terms no model here holds. Measured
    /// (BENCHMARKS.md): 1e-7 to 1e-5 rad²/s move the simulated grid and
    /// BROAD by less than 0.01°.
    pub gyro_walk_rad_sqrt_s: f64,
    /// Weight of the gyro model in the refinement, 0–1 (the residual model
    /// has the rest); `None`, the default, takes it from the evidence the
    /// second forward pass gathered on the gyro: 1 − d/2, with d the
    /// learner's doubt in the gyro's propagation
    /// ([`clino_core::filter::Dynamic::gyro_doubt`]). Without evidence (no
    /// rest pair, or pairs that miss as much as an unmodelled sensor would)
    /// the weight is 1/2, an equal pool: each model is right on some sensors,
    /// the gyro model on a well-calibrated gyro (simulated hand motion,
    /// offline error 0.126° → 0.069° alone, where the passes' loop
    /// corrections are mostly the mount's acceleration), the residual model
    /// on a gyro shaken at 5 g with no rest to learn from (BROAD trial 15:
    /// 0.45° against 0.55°) or one whose pairs show errors the learner does
    /// not model (trial 31, IMU D: 0.84° against 0.92°). Where rest pairs
    /// have pinned the gyro's scale down and they fit, the gyro model takes
    /// up to the whole weight (simulated calibrated hand motion: w ≈ 0.88).
    /// The bounded-motion likelihood of the two models was measured to pick
    /// the better one no more often than not, so it does not choose.
    /// `Some(0.0)` gives the residual model alone (the refinement before
    /// 4 Dec 2026), `Some(1.0)` the gyro model alone.
    pub gyro_weight: Option<f64>,
}

impl Default for BoundedMotion {
    fn default() -> Self {
        Self {
            speed_m_s: 1.0,
            range_m: 1.0,
            tilt_sigma_rad: 0.5f64.to_radians(),
            tilt_tau_s: 10.0,
            constraint_rate_hz: 10.0,
            gyro_walk_rad_sqrt_s: 1e-3,
            gyro_weight: None,
        }
    }
}

/// A pipeline running the dynamic filter of `opts` (without lever arm: the
/// compensation is done once, before the passes, see [`compensate_centred`]),
/// resumed from `start` (attitude and bias) when given.
///
/// With `delayed` the sensor's delay stays in the filter for its rest pairs
/// (a forward pass that learns: their rotation between two rests is read at
/// the true motion's instants, the samples the delay later;
/// [`DynamicParams::sensor_delay_periods`]). Otherwise the pass works at the
/// samples' instants, forwards or backwards, and the delay is made up once,
/// on the result; the attitudes the passes hand on are the states
/// ([`state`]) either way. `bias_gain` multiplies the filter's
/// [`DynamicParams::bias_gain`] (`DRIFT_BIAS_GAIN` for the drift candidate).
fn make(
    opts: &SmoothOptions,
    start: Option<(Attitude, Vec3)>,
    learn: bool,
    delayed: bool,
    bias_gain: f64,
) -> Pipeline {
    let mut params = opts.params;
    params.learn_bias = learn;
    params.bias_gain *= bias_gain;
    if !delayed {
        params.sensor_delay_periods = 0.0;
    }
    let mut p = Pipeline::new(FilterSpec::Dynamic(params)).with_sensor_range(opts.sensor_range);
    if let Some((q, b)) = start
        && let Some(f) = p.filter_mut().as_dynamic_mut()
    {
        f.resume(q, b);
    }
    p
}

/// A pass's attitude at the samples' instant (a dynamic filter's state, not
/// carried over the sensor's delay).
fn state(f: &Pipeline) -> Attitude {
    f.filter()
        .as_dynamic()
        .map_or_else(|| f.filter().attitude(), |d| d.sampled_attitude())
}

/// Half-width of the centred differentiator window, s (window 50 ms, as the
/// real-time differentiator's, but centred: zero lag and a quarter of its noise).
/// Never less than [`GAP_PERIODS`] sample periods, so that the window holds a
/// neighbour on each side at any rate (at 25 Hz the 3-point central
/// difference; [`centred_half_window`]).
const CENTRED_HALF_WINDOW_S: f64 = 0.025;

/// The centred differentiator's half-width for a recording stepped by `dt`:
/// [`CENTRED_HALF_WINDOW_S`], widened to [`GAP_PERIODS`] typical steps where
/// the sampling is slower than one step in 25 ms / 1.5 (≈ 60 Hz). Without
/// the widening a ±25 ms window held the sample alone at 25 Hz (and at
/// 40 Hz whenever a step rounded above 25 ms): ω̇ read zero and the
/// tangential term r·ω̇ was left in (the slewing machine offline at 25 Hz
/// 2.17° against 0.05° in real time).
fn centred_half_window(dt: &[f64]) -> f64 {
    typical_step(dt).map_or(CENTRED_HALF_WINDOW_S, |h| {
        CENTRED_HALF_WINDOW_S.max(GAP_PERIODS * h)
    })
}

/// A stage of the offline smoother, reported to a progress callback with the
/// number of samples it has done (of `n`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Lever-arm compensation (a real-time pass for the bias, then the centred derivative).
    Compensate,
    /// One of the five filter passes (1 to 5, see the [module docs](self)).
    Pass(u8),
    /// The drift candidate: its three learning passes and its two tilt
    /// passes (1 to 5, reported as one stage; see the [module docs](self)).
    Drift(u8),
    /// The tilt passes with a gyro scale imposed (1 to 10, reported as one
    /// stage): the learnt one's pair, the three steps of the fit and the
    /// fitted one's (see the [module docs](self)).
    Scale(u8),
    /// The whole-record refinement ([`refine_bounded_motion`]).
    Refine,
}

impl Stage {
    /// How many stages there are (for a progress bar).
    pub const COUNT: u64 = 9;

    /// The stage's place among the [`Stage::COUNT`], 0-based (for a
    /// progress bar).
    pub fn index(self) -> u64 {
        match self {
            Stage::Compensate => 0,
            Stage::Pass(k) => u64::from(k),
            Stage::Drift(_) => 6,
            Stage::Scale(_) => 7,
            Stage::Refine => 8,
        }
    }
}

/// The progress callback: called every [`PROGRESS_EVERY`] samples of a stage
/// and at its end, with the stage, the samples done and the samples in all.
pub type Progress<'a> = &'a mut dyn FnMut(Stage, usize, usize);

/// How often (in samples) the smoother reports progress.
pub const PROGRESS_EVERY: usize = 1 << 16;

fn tick(progress: &mut Option<Progress<'_>>, stage: Stage, k: usize, n: usize) {
    if let Some(p) = progress
        && (k % PROGRESS_EVERY == 0 || k == n)
    {
        p(stage, k, n);
    }
}

/// Whether a reading is one the real-time pipeline would use: finite and
/// within the physical bounds ([`clino_core::pipeline::admission`]). The
/// passes skip the others as the pipeline does; the lever-arm
/// differentiator, the gap filling and the refinement skip them too (a
/// finite 1e308 taken as specific force swamped the refinement's velocity).
fn usable(gyr: &Vec3, acc: &Vec3) -> bool {
    clino_core::pipeline::admission(&ImuSample::new(0.0, *gyr, *acc)).is_none()
}

/// The running time of the passes: the sum of the usable intervals of `dt`.
fn running_time(dt: &[f64]) -> Vec<f64> {
    let mut now = 0.0;
    dt.iter()
        .map(|&h| {
            now += if h.is_finite() && h > 0.0 { h } else { 0.0 };
            now
        })
        .collect()
}

/// Lever-arm compensation for a whole recording with a centred derivative.
///
/// ω̇ at sample k is the slope of a least-squares line through the rates of
/// the samples within ±25 ms (actual time stamps; at least the neighbours on
/// each side below 60 Hz, `centred_half_window`): the centred form of the
/// local polynomial fit, exact for quadratics, with no lag (which the
/// real-time path cannot have) and a noise gain of about 0.06·σ/h for 15
/// samples. At the recording's ends and beside lost samples the line takes
/// the samples there are (two make a one-sided difference). The bias used
/// for ω is `bias` (from a first pass).
pub fn compensate_centred(
    gyr: &[Vec3],
    acc: &[Vec3],
    dt: &[f64],
    lever_arm_m: &Vec3,
    bias: &Vec3,
) -> Vec<Vec3> {
    let mut out = acc.to_vec();
    compensate_centred_in_place(gyr, &mut out, dt, lever_arm_m, bias);
    out
}

/// [`compensate_centred`] writing over `acc` (sample k's result needs only
/// the rates around k and its own specific force).
pub fn compensate_centred_in_place(
    gyr: &[Vec3],
    acc: &mut [Vec3],
    dt: &[f64],
    lever_arm_m: &Vec3,
    bias: &Vec3,
) {
    let n = gyr.len().min(acc.len()).min(dt.len());
    let t = running_time(&dt[..n]);
    let half = centred_half_window(&dt[..n]);
    // (the derivative's window reads the rate alone)
    let good = |k: usize| usable(&gyr[k], &Vec3::zeros());
    for k in 0..n {
        if !good(k) || !usable(&Vec3::zeros(), &acc[k]) {
            continue;
        }
        let (mut lo, mut hi) = (k, k);
        while lo > 0 && t[k] - t[lo - 1] <= half {
            lo -= 1;
        }
        while hi + 1 < n && t[hi + 1] - t[k] <= half {
            hi += 1;
        }
        let idx = || (lo..=hi).filter(|&i| good(i));
        let m = idx().count();
        let w = gyr[k] - bias;
        let w_dot = if m >= 2 {
            let tm = idx().map(|i| t[i]).sum::<f64>() / m as f64;
            let ym = idx().map(|i| gyr[i]).sum::<Vec3>() / m as f64;
            let sxx: f64 = idx().map(|i| (t[i] - tm).powi(2)).sum();
            let sxy: Vec3 = idx().map(|i| (gyr[i] - ym) * (t[i] - tm)).sum();
            if sxx > 0.0 { sxy / sxx } else { Vec3::zeros() }
        } else {
            Vec3::zeros()
        };
        acc[k] -= clino_core::compensate::lever_arm_acceleration(&w, &w_dot, lever_arm_m);
    }
}

/// One pass over the recording, through the [`Pipeline`] (its rules for
/// dropouts apply), calling `each(i, pipeline)` after sample i. With `bias`
/// given, the filter's bias is imposed at every sample instead of learnt.
/// `t` is the running time ([`running_time`]) and `dt[k]` the interval that
/// ends at sample k.
///
/// The time stamps the pipeline sees are `t` (forwards) or its negation
/// (backwards, where going from sample i+1 back to sample i undoes the
/// rotation of interval i+1 with the rate negated). A pass that starts from a
/// resumed state is given the time of the sample before its first.
#[allow(clippy::too_many_arguments)]
fn pass(
    gyr: &[Vec3],
    acc: &[Vec3],
    t: &[f64],
    dt: &[f64],
    reverse: bool,
    f: &mut Pipeline,
    bias: Option<&[Vec3]>,
    mut each: impl FnMut(usize, &Pipeline),
) {
    let n = gyr.len();
    let sign = if reverse { -1.0 } else { 1.0 };
    if f.filter().is_initialised() {
        let t0 = if reverse {
            -(t[n - 1] + dt[n - 1])
        } else {
            t[0] - dt[0]
        };
        f.set_last_time(t0);
    }
    for k in 0..n {
        let i = if reverse { n - 1 - k } else { k };
        if let (Some(b), Some(d)) = (bias, f.filter_mut().as_dynamic_mut()) {
            d.set_gyro_bias(b[i] * sign);
        }
        let sample = if reverse {
            ImuSample::new(-t[i], -gyr[i], acc[i])
        } else {
            ImuSample::new(t[i], gyr[i], acc[i])
        };
        f.update(&sample);
        each(i, f);
    }
}

/// Offline tilt of a whole recording (see the [module docs](self)).
///
/// `gyr` (rad/s), `acc` (m/s²) and `dt` (s, the interval ending at each sample;
/// the first one is the nominal period) have one entry per sample. Samples
/// the filter rejects (non-finite values, dt ≤ 0) keep the state, as in the
/// real-time path. Returns one attitude per sample.
pub fn smooth(gyr: &[Vec3], acc: &[Vec3], dt: &[f64], opts: &SmoothOptions) -> Vec<Attitude> {
    if let Some((acc, opts)) = at_gyro_instants(acc, dt, opts) {
        return smooth(gyr, &acc, dt, &opts);
    }
    match opts.lever_arm_m {
        Some(_) => {
            let mut acc = acc.to_vec();
            smooth_in_place(gyr, &mut acc, dt, opts, None)
        }
        None => smooth_compensated(gyr, acc, dt, opts, None),
    }
}

/// [`smooth`] for long recordings: the lever-arm compensation (if any) is
/// written over `acc`, and `progress` (if given) hears of every stage.
///
/// Memory beyond the inputs: at most 88 bytes a sample (8 of running time,
/// 48 of the steady and the drift candidate's smoothed bias and 12 of up
/// vectors during the passes, and the scale fit's 48 bytes every 0.1 s, 16
/// a sample at 25 Hz; 72 of refinement state and 16 of the two axes'
/// results during the refinement), and the 32-byte attitudes returned.
/// Below 20 Hz the scale fit keeps every sample: up to 116 bytes. Where a
/// gyro scale is taken, the smoothing runs again on a corrected copy
/// of the rates: 24 bytes a sample more.
pub fn smooth_in_place(
    gyr: &[Vec3],
    acc: &mut [Vec3],
    dt: &[f64],
    opts: &SmoothOptions,
    mut progress: Option<Progress<'_>>,
) -> Vec<Attitude> {
    if let Some((moved, opts)) = at_gyro_instants(acc, dt, opts) {
        acc[..moved.len()].copy_from_slice(&moved);
        return smooth_in_place(gyr, acc, dt, &opts, progress);
    }
    let n = gyr.len().min(acc.len()).min(dt.len());
    if let (Some(p), true) = (opts.lever_arm_m, n > 0) {
        // a first real-time (compensated) pass learns the bias used for ω
        let mut f0 = Pipeline::new(FilterSpec::Dynamic(opts.params)).with_lever_arm(Some(p));
        let mut now = 0.0;
        for k in 0..n {
            now += if dt[k].is_finite() && dt[k] > 0.0 {
                dt[k]
            } else {
                0.0
            };
            f0.update(&ImuSample::new(now, gyr[k], acc[k]));
            tick(&mut progress, Stage::Compensate, k, n);
        }
        compensate_centred_in_place(gyr, &mut acc[..n], dt, &p, &f0.filter().gyro_bias());
        tick(&mut progress, Stage::Compensate, n, n);
    }
    smooth_compensated(gyr, acc, dt, opts, progress)
}

/// A gyro behind its accelerometer ([`DynamicParams::gyro_lag_s`]) made
/// up before anything else: the specific force read at the gyro's
/// instants, each sample the one `gyro_lag_s` earlier in the record
/// ([`read_at`]: linear between the two samples around that time, the
/// nearer of them where the other is one the filter refuses, the first
/// sample's before the start; a sample it refuses stays as it is; a
/// negative lag reads later), and the options with no lag left. The
/// passes' states then stand for the gyro's instants, as the real-time
/// filter's do, and the sensor's delay carries them to the time stamps as
/// before. The real-time filter turns each accelerometer sample back over
/// the lag by the rate it has; offline the sample at the right time is in
/// the record, linear acceleration and all. `None` where there is no lag.
/// Memory: a copy of the specific force, 24 bytes a sample.
fn at_gyro_instants(
    acc: &[Vec3],
    dt: &[f64],
    opts: &SmoothOptions,
) -> Option<(Vec<Vec3>, SmoothOptions)> {
    let lag = opts.params.gyro_lag_s;
    if lag == 0.0 || !lag.is_finite() {
        return None;
    }
    let mut opts = opts.clone();
    opts.params.gyro_lag_s = 0.0;
    // a specific force the filter would refuse (non-finite, beyond the
    // physical bounds) is neither read nor made readable
    let good = |a: &Vec3| usable(&Vec3::zeros(), a);
    Some((read_at(acc, dt, -lag, good), opts))
}

/// The series `x` read `by` seconds after each sample's time (the running
/// time of `dt`): linear between the two samples around that time, the
/// nearer of them where the other is not `good`, the end sample's beyond
/// either end. A sample that is not `good` itself stays as it is (a bad
/// reading is not replaced by its neighbours', nor spread into them).
fn read_at(x: &[Vec3], dt: &[f64], by: f64, good: impl Fn(&Vec3) -> bool) -> Vec<Vec3> {
    let n = x.len().min(dt.len());
    let t = running_time(&dt[..n]);
    let mut j = 0;
    (0..n)
        .map(|k| {
            let want = t[k] + by;
            // j: the last sample at or before `want` (or the first), j1 the next
            while j + 1 < n && t[j + 1] <= want {
                j += 1;
            }
            while j > 0 && t[j] > want {
                j -= 1;
            }
            let j1 = (j + 1).min(n - 1);
            let span = t[j1] - t[j];
            let f = if span > 0.0 {
                ((want - t[j]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            match (good(&x[k]), good(&x[j]), good(&x[j1])) {
                (false, _, _) | (true, false, false) => x[k],
                (true, true, true) => x[j] + (x[j1] - x[j]) * f,
                (true, true, false) => x[j],
                (true, false, true) => x[j1],
            }
        })
        .collect()
}

/// What a learning pass took from the rate at sample i, as a bias in the
/// forward sense (`sign` −1 for a backward pass, whose filter sees −ω and
/// learns −b): its bias b plus what its motion's gyro scale took,
/// s_m·(ω − b) ([`clino_core::filter::Dynamic::motion_gyro_scale`]). The
/// passes that impose the trajectory then subtract all of it as a bias.
fn rate_correction(f: &Pipeline, gyr: &Vec3, sign: f64) -> Vec3 {
    let b = f.filter().gyro_bias() * sign;
    match f.filter().as_dynamic() {
        Some(d) => {
            let c = b + d.motion_gyro_scale().component_mul(&(gyr - b));
            if c.iter().all(|v| v.is_finite()) {
                c
            } else {
                b
            }
        }
        None => b,
    }
}

/// A step longer than this many sample periods (the median step) bridges
/// lost samples; as [`clino_core::filter::Dynamic`]'s strapdown step takes
/// it (one lost sample makes two periods; jittered time stamps are not gaps).
const GAP_PERIODS: f64 = 1.5;

/// The median of up to 4097 of the positive steps, evenly spread over the
/// recording (a fixed amount of memory however long it is); `None` without one.
fn typical_step(dt: &[f64]) -> Option<f64> {
    let stride = (dt.len() / 4096).max(1);
    let mut d: Vec<f64> = dt
        .iter()
        .step_by(stride)
        .copied()
        .filter(|h| h.is_finite() && *h > 0.0)
        .collect();
    d.sort_by(|a, b| a.total_cmp(b));
    d.get(d.len() / 2).copied()
}

/// The five passes, the combination and the refinement, on a recording
/// already compensated for the lever arm. Gaps of lost samples (steps
/// longer than [`GAP_PERIODS`] typical steps, between two usable samples)
/// are first filled at the typical step with rate and specific force
/// interpolated linearly between the samples around them, and the passes
/// run on the filled recording; the attitudes of the samples given are
/// returned. Every pass interpolates the rate across a gap in its own step
/// (the rate linear between samples), but the refinement's models are
/// sampled at the typical step, so the recording they all see has none
/// (hand @40 Hz, 5 % of samples lost in bursts of five: 1.24° against 0.16°
/// without loss before the fill, when the steps still held one end's rate;
/// BENCHMARKS.md). Memory: only with gaps, a filled copy of the inputs.
fn smooth_compensated(
    gyr: &[Vec3],
    acc: &[Vec3],
    dt: &[f64],
    opts: &SmoothOptions,
    progress: Option<Progress<'_>>,
) -> Vec<Attitude> {
    let n = gyr.len().min(acc.len()).min(dt.len());
    let (gyr, acc, dt) = (&gyr[..n], &acc[..n], &dt[..n]);
    let good = |k: usize| usable(&gyr[k], &acc[k]);
    let fills = |h: f64, k: usize| -> usize {
        if k == 0 || dt[k].is_nan() || dt[k] <= GAP_PERIODS * h || !good(k) || !good(k - 1) {
            return 0;
        }
        let m = (dt[k] / h).round() - 1.0;
        if m.is_finite() && m >= 1.0 {
            (m as usize).min(1 << 20)
        } else {
            0
        }
    };
    let Some(h) = typical_step(dt) else {
        return smooth_regular(gyr, acc, dt, opts, progress);
    };
    if (0..n).all(|k| fills(h, k) == 0) {
        return smooth_regular(gyr, acc, dt, opts, progress);
    }
    let (mut g2, mut a2, mut d2, mut at) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..n {
        let m = fills(h, k);
        let step = dt[k] / (m + 1) as f64;
        for j in 1..=m {
            let x = j as f64 / (m + 1) as f64;
            g2.push(gyr[k - 1] + (gyr[k] - gyr[k - 1]) * x);
            a2.push(acc[k - 1] + (acc[k] - acc[k - 1]) * x);
            d2.push(step);
        }
        at.push(g2.len());
        g2.push(gyr[k]);
        a2.push(acc[k]);
        d2.push(if m > 0 { step } else { dt[k] });
    }
    let q = smooth_regular(&g2, &a2, &d2, opts, progress);
    at.iter().map(|&i| q[i]).collect()
}

/// How much faster than in real time the drift candidate's learning passes
/// learn the gyro bias through the loop (their `bias_gain`, ×8): the loop's
/// bias then follows a drift with a time constant of about 9 s instead of
/// about 75 s. A board warming up at 3 °C a minute drifts by 0.004 °/s each
/// second (0.08 °/s per °C, the MPU6050 model's gyro coefficient): the
/// real-time loop lags it by about 0.3 °/s, the drift candidate by about
/// 0.04 °/s (the held hand of the generalisation grid, BENCHMARKS.md).
const DRIFT_BIAS_GAIN: f64 = 8.0;

/// Share of the forward and backward passes' disagreement (its mean square)
/// a candidate must remove to be taken: the drift candidate's bias
/// trajectory here, the learnt gyro scale imposed likewise (its shares in
/// the `gyro_scale` comment of `smooth_regular`). For the drift: a faster
/// bias lets both passes follow the accelerometer more closely, so some of
/// the disagreement goes with it on any record; a drifting bias, which
/// turns the two passes' tilts apart in opposite directions, is what
/// removes most of it. Half: on the grid's warming boards the drift
/// candidate removed 77–96 % (held in the hand) and 19–84 % (rests of a
/// second); where nothing warms, at most 48 % (a gyro with ±2 % scale
/// errors, whose errors the faster bias partly follows) but for one held
/// hand (63 %, and worse against the truth: the reason for
/// `DRIFT_RATE_DEG_S_PER_MIN` as well), on BROAD at most 60 %
/// (BENCHMARKS.md).
const DRIFT_EXPLAINS: f64 = 0.5;

/// Least drift of the drift candidate's bias, °/s per minute (the norm of
/// its least-squares slopes over the record), for it to be considered: a
/// board warming by more than about a degree a minute (the MPU6050's
/// 0.08 °/s per °C). A sensor that does not warm drifts by its bias
/// instability (0.005 °/s for an MPU6050): the drift candidate's bias, which
/// follows more of the motion's errors, then wanders by 0.002–0.04 °/s a
/// minute (the generalisation grid's calibrated and miscalibrated sensors)
/// and up to 0.07 on BROAD, and on warming boards (3 °C a minute) by
/// 0.2–0.41 (BENCHMARKS.md).
const DRIFT_RATE_DEG_S_PER_MIN: f64 = 0.1;

/// The passes of the gyro scale stage ([`Stage::Scale`]): five pairs.
const SCALE_PASSES: usize = 10;

/// How often the forward and backward passes' disagreement is kept for the
/// scale fit, s: it changes over the loop's memory (1/`bandwidth_rad_s`,
/// 6.7 s by default), so 0.1 s keeps all of it, in 48 bytes (four `f32`
/// vectors) every 0.1 s.
const SCALE_FIT_EVERY_S: f64 = 0.1;

/// The step of each axis's gyro scale by which the scale fit measures the
/// disagreement's response, 1: 1 %, the size of the errors to find (an
/// uncalibrated MEMS gyro's are 1–3 %), in the range where the passes
/// respond linearly (a scale error of s turns a pass by s times the angle
/// turned, before its loop pulls it back).
const SCALE_FIT_STEP: f64 = 0.01;

/// Share of the forward and backward passes' disagreement (its mean square)
/// the gyro scale fitted to it ([`scale_fit`]) must remove to be imposed.
/// A scale fitted to the disagreement always removes some of it: by chance
/// alone three of the record's independent stretches (its length over the
/// loop's memory, 18 on two minutes; for noise that share is Beta(3/2,
/// 15/2)-distributed, above 50 % once in 75 records), more where errors no
/// model here holds turn with the motion (the rate's discretisation at
/// 25 Hz, the accelerometer's scale errors, a real gyro's cross-axis
/// terms); a gyro whose scale is off explains most of it.
///
/// Measured (8 seeds each, 6 Dec 2026): the grid's gyros with (+2, −1.5,
/// +1) % errors 77–100 % removed where the motion turns them (the slow arm
/// on a rocking base 77–96 %, on a swaying boom 84–97 %, on a vibrating
/// base 88–97 %, the hand 89–99 %, the drum 98–100 %; the sensor shaken
/// within ±8°, where the scale costs little, 1–73 %); calibrated gyros up
/// to 82 % (the hand with 1-s rests at 25 Hz 1–82 %, the sensor shaken at
/// 40 Hz 1–78 %, the slow arm with accelerometer errors ±5 % 18–79 %);
/// BROAD's calibrated IMUs 7–72 %.
///
/// The two mistakes do not cost alike: a fit taken where the gyro's scale
/// is right cost those calibrated rows at most 0.002° (mean over the
/// seeds; the shaken sensor gained 0.002°), one not taken where the scale
/// is off left a rocking base's seed at 0.238° against 0.052°. So the bar
/// is 75 %, not above every calibrated gyro's fit (85 % until 6 Dec 2026:
/// the rocking base with gyro scale errors 0.098° → 0.073° offline, the
/// swaying boom 0.061° → 0.050°; at 60 % the calibrated hand at 25 Hz
/// gains 0.003–0.008° more and one row loses 0.005°). Holding half the
/// record out of the fit as a check (alternate stretches of the loop's
/// memory) does not tell the two apart: what the calibrated gyros' fits
/// explain they explain out of sample as well (82 → 80 %, 78 → 73 %,
/// against 77 → 73 % on the rocking base's seed). The learnt scale, which
/// the rest pairs found independently of the passes, needs only
/// [`DRIFT_EXPLAINS`].
const SCALE_FIT_EXPLAINS: f64 = 0.75;

/// The gyro scale errors that best explain the forward and backward tilt
/// passes' disagreement: one Gauss–Newton step from no scale, with a prior.
///
/// `gap` is the disagreement (forward minus backward up vector, body frame)
/// at the kept samples with no scale imposed (NaN where left out),
/// `columns[j]` the same with a
/// scale error `step` imposed on axis j. A scale error s turns the two
/// passes apart in opposite directions, by s times the angle turned, so the
/// disagreement is linear in it, g(s) ≈ g₀ + J·s with J's columns
/// (gⱼ − g₀)/step; the fit minimises |g₀ + J·s|²/σ² + |s|²/σₛ², with σ²
/// all of the disagreement's mean square (whatever the scale does not
/// explain is noise to it) counted over `independent` samples (the record
/// over the loop's memory: the kept samples are that much correlated), and
/// σₛ = `prior_sigma` (the filter's [`DynamicParams::gyro_scale_sigma`]).
/// An axis the motion did not turn about leaves its column at zero and its
/// scale at zero. `None` if the inputs are empty, mismatched or not finite.
fn scale_fit(
    gap: &[[f32; 3]],
    columns: [&[[f32; 3]]; 3],
    step: f64,
    independent: f64,
    prior_sigma: f64,
) -> Option<Vec3> {
    let m = gap.len();
    if m == 0 || columns.iter().any(|c| c.len() != m) || !(step > 0.0 && prior_sigma > 0.0) {
        return None;
    }
    let v = |g: &[f32; 3]| Vec3::from(g.map(f64::from));
    let finite = |g: &[f32; 3]| g.iter().all(|x| x.is_finite());
    let used: Vec<usize> = (0..m)
        .filter(|&k| finite(&gap[k]) && columns.iter().all(|c| finite(&c[k])))
        .collect();
    if used.is_empty() {
        return None;
    }
    let noise = used.iter().map(|&k| v(&gap[k]).norm_squared()).sum::<f64>() / used.len() as f64;
    if !(noise.is_finite() && noise > 0.0) {
        return None;
    }
    // (the samples left out take their share of the independent ones)
    let independent = independent * used.len() as f64 / m as f64;
    let weight = independent.min(used.len() as f64) / used.len() as f64 / noise;
    let mut a = nalgebra::Matrix3::identity() / (prior_sigma * prior_sigma);
    let mut b = Vec3::zeros();
    for &k in &used {
        let g = v(&gap[k]);
        let j = nalgebra::Matrix3::from_columns(&[
            (v(&columns[0][k]) - g) / step,
            (v(&columns[1][k]) - g) / step,
            (v(&columns[2][k]) - g) / step,
        ]);
        a += j.transpose() * j * weight;
        b -= j.transpose() * g * weight;
    }
    let s = a.cholesky()?.solve(&b);
    s.iter().all(|v| v.is_finite()).then_some(s)
}

/// The rate at which a bias trajectory drifts over the record, rad/s per
/// second: the norm of the least-squares slopes of its three axes against
/// the running time `t`.
fn drift_rate(bias: &[Vec3], t: &[f64]) -> f64 {
    let n = bias.len().min(t.len());
    if n < 2 {
        return 0.0;
    }
    let tm = t[..n].iter().sum::<f64>() / n as f64;
    let bm = bias[..n].iter().sum::<Vec3>() / n as f64;
    let (mut sxy, mut sxx) = (Vec3::zeros(), 0.0);
    for k in 0..n {
        sxy += (bias[k] - bm) * (t[k] - tm);
        sxx += (t[k] - tm) * (t[k] - tm);
    }
    let r = (sxy / sxx).norm();
    if r.is_finite() { r } else { 0.0 }
}

/// What the learning passes (1–3) hand on: the smoothed bias trajectory,
/// the states the tilt passes start from, and what the second forward pass
/// learnt.
struct Learnt {
    bias: Vec<Vec3>,
    start_fwd: Attitude,
    start_bwd: Attitude,
    acc_errs: Option<(Vec3, Vec3)>,
    gyro_scale: Vec3,
    doubt: f64,
}

/// [`smooth_compensated`] on a recording without gaps to fill.
fn smooth_regular(
    gyr: &[Vec3],
    acc: &[Vec3],
    dt: &[f64],
    opts: &SmoothOptions,
    mut progress: Option<Progress<'_>>,
) -> Vec<Attitude> {
    let n = gyr.len().min(acc.len()).min(dt.len());
    let (gyr, acc, dt) = (&gyr[..n], &acc[..n], &dt[..n]);
    if n == 0 {
        return Vec::new();
    }
    let t = running_time(dt);
    // the drift candidate's five passes are reported as one stage, the
    // scaled tilt's two as another
    let drift_passes = 5;
    let mut run = |stage: Stage,
                   reverse: bool,
                   f: &mut Pipeline,
                   bias: Option<&[Vec3]>,
                   each: &mut dyn FnMut(usize, &Pipeline)| {
        let (mut done, of) = match stage {
            Stage::Drift(k) => (usize::from(k - 1) * n, drift_passes),
            Stage::Scale(k) => (usize::from(k - 1) * n, SCALE_PASSES),
            _ => (0, 1),
        };
        pass(gyr, acc, &t, dt, reverse, f, bias, |i, f| {
            each(i, f);
            done += 1;
            tick(&mut progress, stage, done / of, n);
        });
    };
    // 1–3: learn the bias forwards, backwards (from the end's bias) and
    // forwards again (from the start's bias); each pass starts where the
    // previous one ended (attitude and bias), so no pass starts cold in the
    // middle of motion. Once at the real-time filter's bias gain, once at
    // the drift candidate's
    let mut learn = |gain: f64, stage: &dyn Fn(u8) -> Stage| {
        let mut fa = make(opts, None, true, true, gain);
        run(stage(1), false, &mut fa, None, &mut |_, _| {});
        let (qa, ba) = (state(&fa), fa.filter().gyro_bias());
        let mut fb = make(opts, Some((qa, -ba)), true, false, gain);
        // the smoothed bias trajectory, built in place: first the backward
        // pass's estimate, then its mean with the second forward pass's
        let mut bs = vec![Vec3::zeros(); n];
        run(stage(2), true, &mut fb, None, &mut |i, f| {
            bs[i] = rate_correction(f, &gyr[i], -1.0)
        });
        let qb = state(&fb);
        let mut fc = make(opts, Some((qb, bs[0])), true, true, gain);
        run(stage(3), false, &mut fc, None, &mut |i, f| {
            bs[i] = (bs[i] + rate_correction(f, &gyr[i], 1.0)) * 0.5
        });
        let d = fc.filter().as_dynamic();
        Learnt {
            start_fwd: qb,
            start_bwd: state(&fc),
            // what the second forward pass learnt of the accelerometer's
            // scale errors and bias over the whole record (rest to rest),
            // imposed from the first sample on in the passes that follow,
            // which do not learn
            acc_errs: d.map(|d| (d.accel_scale(), d.accel_bias())),
            // the gyro scale factors it learnt: for the refinement's gyro
            // model (where it is one of two models pooled,
            // [`BoundedMotion::gyro_weight`]), and imposed in the tilt
            // passes only where that brings them together (`scale`). Not
            // always: on BROAD trial 31 (IMU D) the −0.47 % of z scale
            // learnt there (probability 0.999) made the offline tilt worse,
            // 0.729° → 0.749°, while in real time it is neutral: something
            // on real sensors (gyro cross-axis terms, unmodelled) is taken
            // for scale, and there it removes 36 % of the passes'
            // disagreement; on the grid's gyros with ±2 % scale errors 30 %
            // to 99 %, with calibrated or cross-axis errors −6 to 17 %
            // (BENCHMARKS.md)
            gyro_scale: d.map_or_else(Vec3::zeros, |d| d.gyro_scale()),
            doubt: d.map_or(1.0, |d| d.gyro_doubt()),
            bias: bs,
        }
    };
    let steady = learn(1.0, &Stage::Pass);
    let drift = opts
        .drift
        .then(|| learn(DRIFT_BIAS_GAIN, &|k| Stage::Drift(k)));
    // 4–5: tilt forwards and backwards with the bias trajectory imposed; the
    // backward pass combines as it goes (when `merge`), over the forward
    // attitudes, and measures the two passes' disagreement (RMS angle
    // between their up vectors)
    let mut q = vec![Attitude::identity(); n];
    // where the gyro clipped: per sample the time since the forward pass
    // last crossed a clipped rate (infinite before the first), s
    let clipped = |k: usize| {
        opts.sensor_range
            .clipped(&ImuSample::new(0.0, gyr[k], Vec3::zeros()))
            .0
    };
    let since: Option<Vec<f32>> = (0..n).any(clipped).then(|| {
        let mut t = f64::INFINITY;
        (0..n)
            .map(|k| {
                t = if clipped(k) { 0.0 } else { t + dt[k] };
                t as f32
            })
            .collect()
    });
    let memory_s = 1.0 / opts.params.bandwidth_rad_s;
    // the passes' disagreement is kept every `stride` samples (about 50 ms:
    // it changes over the loop's memory, seconds) for the scale fit
    let stride = typical_step(dt).map_or(1, |h| (SCALE_FIT_EVERY_S / h).round().max(1.0) as usize);
    let mut ups: Vec<[f32; 3]> = Vec::new();
    let mut tilt = |l: &Learnt,
                    merge: bool,
                    stages: (Stage, Stage),
                    scale: Option<Vec3>,
                    mut gap: Option<&mut Vec<[f32; 3]>>|
     -> f64 {
        let with_errs = |mut p: Pipeline| {
            if let (Some((d, b)), Some(f)) = (l.acc_errs, p.filter_mut().as_dynamic_mut()) {
                f.set_sensor_errors(scale.unwrap_or_else(Vec3::zeros), d, b);
            }
            p
        };
        if let Some(g) = gap.as_deref_mut() {
            g.clear();
        }
        // a pass that only measures keeps the forward up vectors aside
        // (12 bytes a sample) and leaves the attitudes as they are
        if !merge && ups.len() != n {
            ups = vec![[0.0f32; 3]; n];
        }
        let bs = &l.bias;
        let mut fd = with_errs(make(opts, Some((l.start_fwd, bs[0])), false, false, 1.0));
        run(stages.0, false, &mut fd, Some(bs), &mut |i, f| {
            if merge {
                q[i] = f.filter().attitude();
            } else {
                let u = up_in_body(&f.filter().attitude());
                ups[i] = [u.x as f32, u.y as f32, u.z as f32];
            }
        });
        let mut fe = with_errs(make(
            opts,
            Some((l.start_bwd, -bs[n - 1])),
            false,
            false,
            1.0,
        ));
        let (mut sq, mut m) = (0.0, 0.0);
        // the time until the backward pass's next clipped rate (after i)
        let mut until = f64::INFINITY;
        let settled = |t: f64| 1.0 - (-t / memory_s).exp();
        run(stages.1, true, &mut fe, Some(bs), &mut |i, f| {
            let qb = f.filter().attitude();
            let uf = if merge {
                up_in_body(&q[i])
            } else {
                Vec3::from(ups[i].map(f64::from))
            };
            let ub = up_in_body(&qb);
            let a = uf.angle(&ub);
            if a.is_finite() {
                sq += a * a;
                m += 1.0;
            }
            // (sf, sb): how settled each pass is since a clipped rate
            let (sf, sb) = match &since {
                None => (1.0, 1.0),
                Some(tf) => {
                    until = if clipped(i) {
                        0.0
                    } else if i + 1 < n {
                        until + dt[i + 1]
                    } else {
                        f64::INFINITY
                    };
                    (settled(f64::from(tf[i])), settled(until))
                }
            };
            // the scale fit leaves out the loop's memory around a clipped
            // rate, where the passes part for want of the rate, not its scale
            if let (Some(g), 0) = (gap.as_deref_mut(), i % stride) {
                let clear = sf.min(sb) >= settled(memory_s);
                let d = uf - ub;
                g.push(if clear {
                    [d.x as f32, d.y as f32, d.z as f32]
                } else {
                    [f32::NAN; 3]
                });
            }
            if merge {
                q[i] = match &since {
                    None => combine(&q[i], &qb),
                    Some(_) => {
                        let w = if sf + sb > 0.0 { sf / (sf + sb) } else { 0.5 };
                        combine_weighted(&q[i], &qb, w)
                    }
                };
            }
        });
        if m > 0.0 { sq / m } else { 0.0 }
    };
    // the drift candidate is taken where its bias drifts
    // (DRIFT_RATE_DEG_S_PER_MIN) and its trajectory removes at least half of
    // the forward and backward passes' disagreement (DRIFT_EXPLAINS); then
    // a gyro scale, below
    let drift =
        drift.filter(|d| drift_rate(&d.bias, &t) >= DRIFT_RATE_DEG_S_PER_MIN.to_radians() / 60.0);
    let d_drift = drift.as_ref().map_or(f64::INFINITY, |d| {
        tilt(d, false, (Stage::Drift(4), Stage::Drift(5)), None, None)
    });
    let mut gap = Vec::new();
    let d_steady = tilt(
        &steady,
        true,
        (Stage::Pass(4), Stage::Pass(5)),
        None,
        Some(&mut gap),
    );
    // (the other candidate dropped here: its bias is not held through the
    // refinement)
    let (mut chosen, d_chosen) = match drift {
        Some(d) if d_drift < (1.0 - DRIFT_EXPLAINS) * d_steady => {
            drop(steady);
            tilt(
                &d,
                true,
                (Stage::Pass(4), Stage::Pass(5)),
                None,
                Some(&mut gap),
            );
            (d, d_drift)
        }
        other => {
            drop(other);
            (steady, d_steady)
        }
    };
    // the gyro scale: the learnt one, imposed where it removes at least
    // half of the passes' disagreement (DRIFT_EXPLAINS), then the one fitted
    // to that disagreement, where it removes at least SCALE_FIT_EXPLAINS of
    // it and, if the learnt one was taken, half of what that leaves: the
    // rest pairs' scale is evidence from outside the passes, the fit only
    // the passes' own (a drum turning one way at one rate, where scale and
    // bias are one, is fitted at 1.68 % and learnt at 1.77 % of the 2 %:
    // the fit removes a quarter of what the learnt scale leaves, and would
    // make the tilt worse, 0.142° → 0.171°). The common case, neither,
    // leaves the passes' result as it is.
    //
    // (Reported as one stage of SCALE_PASSES passes: the learnt scale's
    // pair, the fit's three steps and the fitted scale's pair.)
    let scale_stages = |pair: u8| (Stage::Scale(2 * pair - 1), Stage::Scale(2 * pair));
    // (the scale, the disagreement it leaves, and whether it is the fit)
    let mut best: Option<(Vec3, f64, bool)> = None;
    let consider =
        |best: &mut Option<(Vec3, f64, bool)>, s: Vec3, d: f64, explains: f64, fit: bool| {
            if d < (1.0 - explains) * d_chosen
                && best.is_none_or(|(_, b, _)| d < (1.0 - DRIFT_EXPLAINS) * b)
            {
                *best = Some((s, d, fit));
            }
        };
    if opts.scale && chosen.gyro_scale != Vec3::zeros() {
        let s = chosen.gyro_scale;
        let d = tilt(&chosen, false, scale_stages(1), Some(s), None);
        consider(&mut best, s, d, DRIFT_EXPLAINS, false);
    }
    if opts.scale && gap.iter().any(|g| g.iter().all(|v| v.is_finite())) {
        // the disagreement's response to each axis's scale, by a step of
        // SCALE_FIT_STEP
        let columns: Vec<Vec<[f32; 3]>> = (0..3)
            .map(|j| {
                let mut g = Vec::new();
                let mut s = Vec3::zeros();
                s[j] = SCALE_FIT_STEP;
                tilt(
                    &chosen,
                    false,
                    scale_stages(2 + j as u8),
                    Some(s),
                    Some(&mut g),
                );
                g
            })
            .collect();
        let span_s = t[n - 1] - t[0] + dt[0];
        let fit = scale_fit(
            &gap,
            [&columns[0], &columns[1], &columns[2]],
            SCALE_FIT_STEP,
            span_s / memory_s,
            opts.params.gyro_scale_sigma,
        );
        if let Some(s) = fit {
            let d = tilt(&chosen, false, scale_stages(5), Some(s), None);
            consider(&mut best, s, d, SCALE_FIT_EXPLAINS, true);
        }
    }
    // the learning passes took the scale error in their rest pairs for the
    // accelerometer's errors too, which are imposed from the first sample
    // (the slow arm on a vibrating base with (+2, −1.5, +1) %: (−1.0, 1.5,
    // −0.8) mg and (0.32, −0.05, −0.27) % learnt against (0.5, −0.4, 0.8) mg
    // and 0.03 %, a steady 0.25° offset); with the scale known, everything
    // runs again on the rates it corrects. Not where the gyro clipped: a
    // corrected rate would no longer read at the range, and the passes
    // would not be told (the scale is then imposed as it is)
    if let (Some((s, _, _)), None) = (best, &since) {
        drop((t, ups, gap, q, chosen));
        let one_less = Vec3::repeat(1.0) - s;
        let corrected: Vec<Vec3> = gyr.iter().map(|w| w.component_mul(&one_less)).collect();
        let again = SmoothOptions {
            scale: false,
            ..opts.clone()
        };
        return smooth_regular(&corrected, acc, dt, &again, progress);
    }
    if let Some((s, _, _)) = best {
        tilt(
            &chosen,
            true,
            (Stage::Pass(4), Stage::Pass(5)),
            Some(s),
            None,
        );
        // the refinement's gyro model turns the gyro as the passes did
        chosen.gyro_scale = s;
    }
    // (the passes are done: their scratch goes before the refinement's)
    drop((t, ups, gap));
    // the gyro model's weight: as given, or from the learner's doubt in the
    // gyro's propagation over the whole record
    let gyro_weight = opts.refine.as_ref().map_or(0.0, |b| {
        b.gyro_weight
            .unwrap_or(1.0 - 0.5 * chosen.doubt)
            .clamp(0.0, 1.0)
    });
    let beyond = match &opts.refine {
        Some(_) if gyro_weight > 0.0 => Some(beyond_gyro(
            &q,
            gyr,
            acc,
            &chosen.bias,
            &chosen.gyro_scale,
            dt,
        )),
        _ => None,
    };
    let acc_errs = chosen.acc_errs;
    drop(chosen);
    if let Some(b) = &opts.refine {
        refine_in_place(
            &mut q,
            acc,
            acc_errs,
            beyond.as_deref().map(|u| (u, gyro_weight)),
            since.as_deref().map(|c| (c, opts.sensor_range.gyro_rad_s)),
            dt,
            b,
            opts.params.gravity_m_s2,
            progress,
        );
    }
    carry_over_delay(&mut q, dt, opts.params.sensor_delay_periods);
    q
}

/// The sensor's delay made up on a whole record's attitudes, in place: each
/// attitude, which stands for its sample's instant, carried on over
/// `periods` typical steps to its time stamp, as the real-time filter
/// reports it ([`DynamicParams::sensor_delay_periods`]). The rate is the
/// attitudes' own centred difference (the corrected rate the passes
/// integrated, and no memory beyond the attitudes); the first and the last
/// sample take the one-sided one.
fn carry_over_delay(q: &mut [Attitude], dt: &[f64], periods: f64) {
    let n = q.len().min(dt.len());
    let lead_s = periods * typical_step(&dt[..n]).unwrap_or(0.0);
    if lead_s.is_nan() || lead_s <= 0.0 || n < 2 {
        return;
    }
    let mut before = q[0];
    for i in 0..n {
        let after = if i + 1 < n { q[i + 1] } else { q[i] };
        let span = if i > 0 { dt[i] } else { 0.0 } + if i + 1 < n { dt[i + 1] } else { 0.0 };
        let turn = (before.inverse() * after).scaled_axis() * (lead_s / span);
        before = q[i];
        if span > 0.0 && turn.iter().all(|v| v.is_finite()) {
            q[i] *= UnitQuaternion::from_scaled_axis(turn);
        }
    }
}

/// The tilt corrections an attitude sequence `q` made beyond the gyro, per
/// sample, in the form [`rts_axis`] takes them: for e_k, the rotation vector
/// of q_k ⊗ (q_{k−1} ⊗ Δq_k)*, where Δq_k is the gyro's step over the
/// interval ending at sample k (the rate (ω − b)·(1 − s) cubic through
/// samples k−2 … k+1 where their steps are alike, its mean over the step
/// (−ω₋₂ + 13·ω₋₁ + 13·ω₀ − ω₊₁)/24, else linear between samples k−1 and
/// k; with the two-sample coning term, as in the filter: a rate linear
/// between samples keeps 1 − (Ωh)²/12 of a turn's amplitude at angular
/// frequency Ω, which the refinement would pull the passes back to,
/// [`clino_core::filter::Dynamic`]'s strapdown step),
/// the entries (−e_N, e_E): the steps of the tilt
/// error states (δ_N, −δ_E) of the refinement when the gyro is right.
/// Samples the passes' pipeline did not use (a NaN, a reading beyond the
/// physical bounds: [`clino_core::pipeline::admission`]; dt ≤ 0) contribute
/// nothing. Stored as `f32` (a step is below 0.1 rad; 7 digits are far below
/// any sensor's).
fn beyond_gyro(
    q: &[Attitude],
    gyr: &[Vec3],
    acc: &[Vec3],
    bias: &[Vec3],
    scale: &Vec3,
    dt: &[f64],
) -> Vec<[f32; 2]> {
    let n = q
        .len()
        .min(gyr.len())
        .min(acc.len())
        .min(bias.len())
        .min(dt.len());
    let one_s = Vec3::repeat(1.0) - scale;
    let mut out = vec![[0.0f32; 2]; n];
    // the corrected rate of each sample the passes used
    let rate = |k: usize| -> Option<Vec3> {
        let used = usable(&gyr[k], &acc[k]) && dt[k].is_finite() && dt[k] > 0.0;
        let w = (gyr[k] - bias[k]).component_mul(&one_s);
        (used && w.iter().all(|v| v.is_finite())).then_some(w)
    };
    // (one sample clock's steps, as the filter's strapdown step asks)
    let alike = |a: f64, b: f64| (a - b).abs() < STEPS_ALIKE * b;
    let mut w_prev: Option<Vec3> = None;
    for k in 0..n {
        let Some(w) = rate(k) else {
            continue;
        };
        if let (Some(wp), true) = (w_prev, k > 0) {
            // the cubic through k−2 … k+1, over equal steps
            let cubic = (k >= 2 && k + 1 < n)
                .then(|| (rate(k - 2), rate(k - 1), rate(k + 1)))
                .and_then(|(a, b, c)| Some((a?, b?, c?)))
                .filter(|_| alike(dt[k - 1], dt[k]) && alike(dt[k + 1], dt[k]))
                .map(|(wpp, _, wn)| (wp + w) * (13.0 / 24.0) - (wpp + wn) * (1.0 / 24.0));
            let mean = cubic.unwrap_or((w + wp) * 0.5);
            let phi = (mean + wp.cross(&w) * (dt[k] / 12.0)) * dt[k];
            let pred = q[k - 1] * UnitQuaternion::from_scaled_axis(phi);
            let e = (q[k] * pred.inverse()).scaled_axis();
            if e.iter().all(|v| v.is_finite()) {
                out[k] = [-e.y as f32, e.x as f32];
            }
        }
        w_prev = Some(w);
    }
    out
}

/// The forward attitude turned (in the body) so that its up vector becomes
/// the weighted mean of the forward (weight `w`) and backward up vectors.
fn combine_weighted(qf: &Attitude, qb: &Attitude, w: f64) -> Attitude {
    let (uf, ub) = (up_in_body(qf), up_in_body(qb));
    let um = uf * w + ub * (1.0 - w);
    // (opposite up vectors: no mean direction)
    if um.norm_squared().is_nan() || um.norm_squared() < 0.25e-12 {
        return *qf;
    }
    let corr = UnitQuaternion::rotation_between(&um, &uf).unwrap_or_else(UnitQuaternion::identity);
    qf * corr
}

/// The forward attitude turned (in the body) so that its up vector becomes
/// the mean of the forward and backward up vectors (equal weights).
fn combine(qf: &Attitude, qb: &Attitude) -> Attitude {
    combine_weighted(qf, qb, 0.5)
}

/// Whole-record refinement of a tilt estimate from bounded motion, under the
/// residual model alone ([`BoundedMotion::gyro_weight`] is not read here: the
/// gyro model needs the rates and the smoothed bias, which only [`smooth`] has).
///
/// With the attitude estimate q̂, the horizontal specific force in the
/// navigation frame, f̂ = (q̂ ⊗ f ⊗ q̂*)_EN, is the mount's horizontal
/// acceleration plus g times the remaining tilt error δ = (δ_E, δ_N)
/// (true = exp(δ) ⊗ q̂): a_E = f̂_E + g·δ_N, a_N = f̂_N − g·δ_E. Integrated
/// once and twice it gives velocity and position, which for a mount working
/// in place must stay near zero. Per horizontal axis this is a linear
/// Gauss–Markov model with state (d, v, p):
///
/// ```text
/// d_{k+1} = φ·d_k + w,   φ = exp(−h/τ),  Var w = σ_d²·(1 − φ²)
/// v_{k+1} = v_k + (f̂_k + g·d_k)·h
/// p_{k+1} = p_k + v_k·h
/// 0 = v + n_v (σ = speed),  0 = p + n_p (σ = range), at `constraint_rate_hz`
/// ```
///
/// solved exactly by a Kalman filter and a Rauch–Tung–Striebel smoother
/// (Rauch, Tung, Striebel, AIAA J. 3(8), 1965); the smoothed d is applied as
/// the navigation-frame correction exp(δ) ⊗ q̂. O(n) time and memory (72
/// bytes a sample: the filtered state and the upper triangle of its covariance;
/// the predictions are recomputed in the backward pass).
pub fn refine_bounded_motion(
    q: &[Attitude],
    acc: &[Vec3],
    dt: &[f64],
    b: &BoundedMotion,
    g: f64,
) -> Vec<Attitude> {
    let mut out = q.to_vec();
    refine_in_place(&mut out, acc, None, None, None, dt, b, g, None);
    out
}

/// [`refine_bounded_motion`] writing over `q`; with `fix` = (d, b) the
/// specific force used is f·(1 − d) − b (the accelerometer's learnt scale
/// errors and bias, [`clino_core::filter::Dynamic::set_sensor_errors`]); with
/// `gyro` = (the steps from [`beyond_gyro`], w) the gyro model is pooled with
/// the residual model at weight w ([`BoundedMotion::gyro_weight`]); with
/// `clipped` = (per sample the time since the gyro last clipped, the gyro's
/// range) the gyro model's walk takes (range·h)² more at each clipped step.
#[allow(clippy::too_many_arguments)]
fn refine_in_place(
    q: &mut [Attitude],
    acc: &[Vec3],
    fix: Option<(Vec3, Vec3)>,
    gyro: Option<(&[[f32; 2]], f64)>,
    clipped: Option<(&[f32], f64)>,
    dt: &[f64],
    b: &BoundedMotion,
    g: f64,
    mut progress: Option<Progress<'_>>,
) {
    let n = q.len().min(acc.len()).min(dt.len());
    if n < 2 {
        return;
    }
    let q = &mut q[..n];
    let h = |k: usize| {
        if dt[k].is_finite() && dt[k] > 0.0 {
            dt[k]
        } else {
            0.0
        }
    };
    // horizontal specific force in ENU; unusable samples (not finite, or
    // beyond the physical bounds) contribute nothing
    let force = |q: &[Attitude], k: usize, axis: usize| {
        if !usable(&Vec3::zeros(), &acc[k]) {
            return 0.0;
        }
        let a = match &fix {
            Some((d, b)) => clino_core::filter::correct_specific_force(&acc[k], d, b),
            None => acc[k],
        };
        let f = q[k] * a;
        if f.iter().all(|v| v.is_finite()) {
            f[axis]
        } else {
            0.0
        }
    };
    // E velocity sees +g·δ_N; N velocity sees −g·δ_E = +g·(−δ_E): the
    // smoothed (δ_N, −δ_E), pooled over the models ([`BoundedMotion::gyro_weight`])
    let (beyond, w) = match gyro {
        Some((u, w)) if u.len() >= n => (Some(u), w.clamp(0.0, 1.0)),
        _ => (None, 0.0),
    };
    let mut d = vec![[0.0f32; 2]; n];
    for axis in 0..2 {
        if w < 1.0 {
            rts_axis(
                n,
                |k| force(q, k, axis),
                h,
                b,
                g,
                TiltModel::Residual,
                |k, v| d[k][axis] += ((1.0 - w) * v) as f32,
            );
        }
        if let (Some(u), true) = (beyond, w > 0.0) {
            rts_axis(
                n,
                |k| force(q, k, axis),
                h,
                b,
                g,
                TiltModel::Gyro(&|k| {
                    // a clipped rate: the gyro fell short by up to about its
                    // range over the step
                    let extra = match clipped {
                        Some((c, range)) if c[k] == 0.0 => (range * h(k)).powi(2),
                        _ => 0.0,
                    };
                    (f64::from(u[k][axis]), extra)
                }),
                |k, v| d[k][axis] += (w * v) as f32,
            );
        }
        tick(&mut progress, Stage::Refine, n * (axis + 1) / 2, n);
    }
    for k in 0..n {
        let c = Vec3::new(-f64::from(d[k][1]), f64::from(d[k][0]), 0.0);
        if c.iter().all(|v| v.is_finite()) {
            q[k] = UnitQuaternion::from_scaled_axis(c) * q[k];
        }
    }
}

/// How the remaining tilt error d of one axis evolves in [`rts_axis`].
#[derive(Clone, Copy)]
enum TiltModel<'a> {
    /// The residual model: d is a Gauss–Markov process of 1σ
    /// [`BoundedMotion::tilt_sigma_rad`] and correlation time
    /// [`BoundedMotion::tilt_tau_s`] (the estimate's own tilt corrections
    /// are right).
    Residual,
    /// The gyro model: d_k = d_{k−1} + u_k + w_k with u_k the estimate's
    /// step beyond the gyro ([`beyond_gyro`]) and Var w_k =
    /// [`BoundedMotion::gyro_walk_rad_sqrt_s`]²·h_k plus what the closure
    /// adds (a clipped rate); d starts with 1σ [`BoundedMotion::tilt_sigma_rad`].
    /// The closure gives (u_k, the added variance).
    Gyro(&'a dyn Fn(usize) -> (f64, f64)),
}

/// The state transition of [`rts_axis`] over the interval `hk` ending at
/// sample k: the matrix, the known input and the tilt state's process noise.
fn transition(
    k: usize,
    hk: f64,
    b: &BoundedMotion,
    g: f64,
    model: TiltModel<'_>,
    fk: f64,
) -> (nalgebra::Matrix3<f64>, nalgebra::Vector3<f64>, f64) {
    let (phi, input, var) = match model {
        TiltModel::Residual => {
            let phi = (-hk / b.tilt_tau_s).exp();
            let sd2 = b.tilt_sigma_rad * b.tilt_sigma_rad;
            (phi, 0.0, sd2 * (1.0 - phi * phi))
        }
        TiltModel::Gyro(u) => {
            let (uk, extra) = u(k);
            let walk = b.gyro_walk_rad_sqrt_s * b.gyro_walk_rad_sqrt_s * hk + extra;
            (1.0, if uk.is_finite() { uk } else { 0.0 }, walk)
        }
    };
    let fm = nalgebra::Matrix3::new(phi, 0.0, 0.0, g * hk, 1.0, 0.0, 0.0, hk, 1.0);
    (fm, nalgebra::Vector3::new(input, fk * hk, 0.0), var)
}

/// Kalman filter + RTS smoother of one horizontal axis of [`refine_bounded_motion`];
/// `f(k)` is the horizontal specific force and `h(k)` the interval ending at
/// sample k; `emit(k, d)` hears the smoothed tilt-error state d of every
/// sample (last to first).
///
/// The forward pass stores only the filtered state and the upper triangle of
/// its (symmetrised) covariance; the backward pass recomputes each prediction
/// from them, which is the same arithmetic as the forward pass's.
fn rts_axis(
    n: usize,
    f: impl Fn(usize) -> f64,
    h: impl Fn(usize) -> f64,
    b: &BoundedMotion,
    g: f64,
    model: TiltModel<'_>,
    mut emit: impl FnMut(usize, f64),
) {
    use nalgebra::{Matrix3, Vector3 as V3};
    if n == 0 {
        return;
    }
    let sd2 = b.tilt_sigma_rad * b.tilt_sigma_rad;
    let (rv, rp) = (b.speed_m_s * b.speed_m_s, b.range_m * b.range_m);
    let noise = |var: f64| {
        let mut q = Matrix3::zeros();
        q[(0, 0)] = var;
        q
    };
    let pack = |x: &V3<f64>, p: &Matrix3<f64>| {
        [
            x[0],
            x[1],
            x[2],
            p[(0, 0)],
            p[(0, 1)],
            p[(0, 2)],
            p[(1, 1)],
            p[(1, 2)],
            p[(2, 2)],
        ]
    };
    let unpack = |s: &[f64; 9]| {
        let x = V3::new(s[0], s[1], s[2]);
        let p = Matrix3::new(s[3], s[4], s[5], s[4], s[6], s[7], s[5], s[7], s[8]);
        (x, p)
    };
    let mut x = V3::new(0.0, 0.0, 0.0);
    let mut p = Matrix3::from_diagonal(&V3::new(sd2, rv, rp));
    let mut filtered: Vec<[f64; 9]> = Vec::with_capacity(n);
    let mut since = 0.0;
    let period = 1.0 / b.constraint_rate_hz;
    for k in 0..n {
        // predict over the interval ending at sample k
        let hk = h(k);
        let (fm, input, var) = transition(k, hk, b, g, model, f(k));
        x = fm * x + input;
        p = fm * p * fm.transpose() + noise(var);
        // velocity and position bounds at the constraint rate
        since += hk;
        if since >= period {
            since -= period;
            for (i, r) in [(1usize, rv), (2usize, rp)] {
                let s = p[(i, i)] + r;
                let kgain = p.column(i) / s;
                let innov = -x[i];
                x += kgain * innov;
                p -= kgain * p.row(i);
            }
        }
        p = (p + p.transpose()) * 0.5;
        filtered.push(pack(&x, &p));
    }
    // Rauch–Tung–Striebel backward pass
    let (mut xsm, _) = unpack(&filtered[n - 1]);
    emit(n - 1, xsm[0]);
    for k in (0..n - 1).rev() {
        let (xk, pk) = unpack(&filtered[k]);
        let (fm, input, var) = transition(k + 1, h(k + 1), b, g, model, f(k + 1));
        let x_pred = fm * xk + input;
        let pp = fm * pk * fm.transpose() + noise(var);
        let c = match pp.try_inverse() {
            Some(inv) => pk * fm.transpose() * inv,
            None => Matrix3::zeros(),
        };
        xsm = xk + c * (xsm - x_pred);
        emit(k, xsm[0]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Motion, slewing::SlewingPlatform};
    use clino_core::tilt::up_in_body;

    fn tilt_err(a: &Attitude, b: &Attitude) -> f64 {
        let e = a * b.inverse();
        2.0 * (e.w * e.w + e.k * e.k).sqrt().min(1.0).acos()
    }

    #[test]
    fn a_rocking_base_teaches_a_calibrated_sensor_no_error_from_its_held_poses() {
        // The slow arm on a base rocking at 1.5–5 Hz (2°/s, no linear sway:
        // never a rest) with a calibrated sensor, as the smoother's later
        // passes run it: the bias given, so the arm's stops, held poses,
        // end rest pairs. A held pose's pair compared the specific force
        // 0.1 s late (its low-pass) with the attitude of one instant, which
        // the rocking turns by up to 0.2°: the pairs taught accelerometer
        // bias and gyro scale (RMS over eight seeds 0.77 mg, 0.115 %), which
        // the smoother imposes on its tilt passes from the first sample
        // (offline 1.19× offline VQF's error on the grid). With the held
        // pose's means (the attitude's shifted by the low-pass's delay)
        // 0.45 mg, 0.065 %.
        let rate = 125.0;
        let model = crate::sim::slewing::sensor().with_bandwidth(50.0);
        let (mut b2, mut s2) = (0.0, 0.0);
        let seeds = 8;
        for seed in 1..=seeds {
            let (m, _) = arm_on_base(seed, rock_hz(seed), Vec3::zeros());
            let samples = model.simulate(&m, rate, 120.0, seed);
            let mut f = clino_core::filter::Dynamic::default();
            f.set_gyro_bias(model.gyro.bias);
            for s in &samples {
                f.update(s.gyr_rad_s, s.acc_m_s2, 1.0 / rate);
            }
            assert!(f.rest_pairs() >= 5, "seed {seed}: {} pairs", f.rest_pairs());
            b2 += f.accel_bias().norm_squared();
            s2 += f.gyro_scale().norm_squared();
        }
        let b = (b2 / seeds as f64).sqrt() / (1e-3 * clino_core::G0);
        let s = (s2 / seeds as f64).sqrt() * 100.0;
        eprintln!(
            "learnt on a calibrated sensor: accelerometer bias {b:.2} mg, gyro scale {s:.3} % (RMS)"
        );
        assert!(b < 0.6, "{b} mg");
        assert!(s < 0.09, "{s} %");
    }

    #[test]
    fn lost_samples_are_filled_before_the_passes() {
        // the hand at 40 Hz with five samples lost every two seconds (6 %):
        // the offline tilt on the samples received, against the offline
        // tilt of the whole recording on the same samples
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::by_hand(), 1);
        let model = crate::sim::slewing::sensor().with_bandwidth(16.0);
        let s = model.simulate(&hand, 40.0, 60.0, 1);
        let lost = |k: usize| k > 200 && k % 80 >= 40 && k % 80 < 45;
        let score = |keep: &dyn Fn(usize) -> bool| {
            let idx: Vec<usize> = (0..s.len()).filter(|&k| keep(k)).collect();
            let gyr: Vec<Vec3> = idx.iter().map(|&k| s[k].gyr_rad_s).collect();
            let acc: Vec<Vec3> = idx.iter().map(|&k| s[k].acc_m_s2).collect();
            let dt: Vec<f64> = (0..idx.len())
                .map(|j| {
                    if j == 0 {
                        0.025
                    } else {
                        s[idx[j]].t_s - s[idx[j - 1]].t_s
                    }
                })
                .collect();
            let q = smooth(&gyr, &acc, &dt, &SmoothOptions::default());
            let (mut s2, mut n) = (0.0, 0.0);
            for (j, &k) in idx.iter().enumerate() {
                if !lost(k) && k > 200 {
                    let e = tilt_err(&q[j], &hand.truth(s[k].t_s).attitude);
                    s2 += e * e;
                    n += 1.0;
                }
            }
            (s2 / n).sqrt().to_degrees()
        };
        let full = score(&|_| true);
        let received = score(&|k| !lost(k));
        // 0.18° against 0.13°; the passes on the gaps as they are: 0.94°
        assert!(received < 2.0 * full, "{received}° against {full}°");
    }

    /// A drum turning about its horizontal body x axis (5 s still, a 1-s
    /// ramp to 2 rad/s, 20 s turning, a 1-s ramp down, 8 s still) read by a
    /// perfect sensor whose samples lag their time stamps by one period at
    /// 100 Hz; the offline RMS tilt error against the truth at the time
    /// stamps over the turn and the stop (from 6 s), degrees.
    fn delayed_drum_offline(sensor_delay_periods: f64) -> f64 {
        lagged_drum_offline(sensor_delay_periods, 0.0, 0.0)
    }

    /// [`delayed_drum_offline`] with the gyro's samples `gyro_lag` periods
    /// further behind, and the filter told `gyro_lag_s`.
    fn lagged_drum_offline(sensor_delay_periods: f64, gyro_lag: f64, gyro_lag_s: f64) -> f64 {
        let h = 0.01;
        let w = |t: f64| 2.0 * ((t - 5.0).clamp(0.0, 1.0) - (t - 26.0).clamp(0.0, 1.0));
        let angle = |t: f64| {
            let up = |x: f64| {
                let x = x.max(0.0);
                if x < 1.0 { x * x } else { 2.0 * x - 1.0 }
            };
            up(t - 5.0) - up(t - 26.0)
        };
        let truth = |t: f64| Attitude::from_axis_angle(&Vec3::x_axis(), angle(t));
        let n = (35.0 / h) as usize;
        let (mut g, mut a) = (Vec::new(), Vec::new());
        for k in 0..n {
            let ts = k as f64 * h - h;
            g.push(Vec3::new(w(ts - gyro_lag * h), 0.0, 0.0));
            a.push(truth(ts).inverse_transform_vector(&Vec3::new(0.0, 0.0, clino_core::G0)));
        }
        let mut opts = SmoothOptions::default();
        opts.params.sensor_delay_periods = sensor_delay_periods;
        opts.params.gyro_lag_s = gyro_lag_s;
        let q = smooth(&g, &a, &vec![h; n], &opts);
        let from = (6.0 / h) as usize;
        let s: f64 = (from..n)
            .map(|k| tilt_err(&q[k], &truth(k as f64 * h)).powi(2))
            .sum();
        (s / (n - from) as f64).sqrt().to_degrees()
    }

    #[test]
    fn the_smoother_makes_up_the_sensors_delay() {
        // the passes at the samples' instants, then carried on over the delay:
        // with the sensor's own delay given the turn is followed to within
        // the steps' error; without, the attitude lags by ω·h = 1.15° while
        // turning (0.96° RMS over the turn and the stop; 0.007° made up)
        let made_up = delayed_drum_offline(1.0);
        let not = delayed_drum_offline(0.0);
        assert!(made_up < 0.02, "{made_up}°");
        assert!(not > 0.8, "{not}°");
    }

    #[test]
    fn the_smoother_reads_the_accelerometer_at_the_gyros_instants() {
        // the accelerometer a period behind its stamps, the gyro two: the
        // sensor's (the gyro's) delay two periods, the lag one. Told:
        // 0.005° RMS over the turn and the stop; not told, 0.92° (the
        // passes meet the accelerometer a period early, ω·h = 1.15°); told
        // the wrong way round, 1.83°
        let told = lagged_drum_offline(2.0, 1.0, 0.01);
        let not = lagged_drum_offline(2.0, 1.0, 0.0);
        let wrong = lagged_drum_offline(2.0, 1.0, -0.01);
        assert!(told < 0.02, "{told}°");
        assert!(not > 0.7, "{not}°");
        assert!(wrong > 1.5 * not, "{wrong}° against {not}°");
    }

    #[test]
    fn read_at_is_the_series_at_the_shifted_time() {
        // a ramp read 1.5 steps later and 0.25 earlier: the ramp there, the
        // end samples beyond the ends; a NaN takes its neighbour
        let dt = [0.1; 6];
        let x: Vec<Vec3> = (0..6)
            .map(|k| Vec3::new(k as f64, 0.0, -2.0 * k as f64))
            .collect();
        let ok = |v: &Vec3| v.iter().all(|c| c.is_finite() && c.abs() < 1e6);
        let later = read_at(&x, &dt, 0.15, ok);
        for (k, v) in later.iter().enumerate() {
            let want = (k as f64 + 1.5).min(5.0);
            assert!(
                (v.x - want).abs() < 1e-12 && (v.z + 2.0 * want).abs() < 1e-12,
                "{k}: {v}"
            );
        }
        let earlier = read_at(&x, &dt, -0.025, ok);
        for (k, v) in earlier.iter().enumerate() {
            let want = (k as f64 - 0.25).max(0.0);
            assert!((v.x - want).abs() < 1e-12, "{k}: {v}");
        }
        // a bad reading (NaN, 1e308) is not read, not spread and not
        // replaced: its own sample stays bad, its neighbours take the good one
        for bad in [Vec3::repeat(f64::NAN), Vec3::new(1e308, 0.0, 0.0)] {
            let mut y = x.clone();
            y[3] = bad;
            let r = read_at(&y, &dt, 0.05, ok);
            assert_eq!(r[2], x[2], "the good one of samples 2 and 3");
            assert!(!ok(&r[3]), "sample 3 stays as it was: {}", r[3]);
            assert!((r[4].x - 4.5).abs() < 1e-12);
            assert!(r.iter().enumerate().all(|(k, v)| k == 3 || ok(v)));
        }
        // no lag: no copy
        assert!(at_gyro_instants(&x, &dt, &SmoothOptions::default()).is_none());
    }

    /// Simulated slewing machine with a constant gyro bias and no lever-arm knowledge
    /// in the filter: a hard case for a causal filter (centripetal acceleration).
    fn recording() -> (Vec<Vec3>, Vec<Vec3>, Vec<f64>, Vec<Attitude>) {
        let m = SlewingPlatform::default();
        let rate = 200.0;
        let n = (90.0 * rate) as usize;
        let bias = Vec3::new(0.3, -0.2, 0.1).map(f64::to_radians);
        let (mut g, mut a, mut d, mut q) = (vec![], vec![], vec![], vec![]);
        for k in 0..n {
            let tr = m.truth(k as f64 / rate);
            g.push(tr.gyr_rad_s + bias);
            a.push(tr.specific_force(clino_core::G0));
            d.push(1.0 / rate);
            let _ = &tr;
            q.push(tr.attitude);
        }
        (g, a, d, q)
    }

    #[test]
    fn smoother_beats_causal_filter_and_reversal_is_consistent() {
        let (g, a, d, q) = recording();
        let opts = SmoothOptions::default();
        let off = smooth(&g, &a, &d, &opts);
        let mut f = make(&SmoothOptions::default(), None, true, false, 1.0);
        let mut on = vec![Attitude::identity(); g.len()];
        pass(
            &g,
            &a,
            &running_time(&d),
            &d,
            false,
            &mut f,
            None,
            |i, f| on[i] = f.filter().attitude(),
        );
        let rms = |e: &[Attitude]| {
            // scored after the machine's initial 10-s rest
            let skip = 2000;
            let s: f64 = e
                .iter()
                .zip(&q)
                .skip(skip)
                .map(|(x, y)| tilt_err(x, y).powi(2))
                .sum();
            (s / (e.len() - skip) as f64).sqrt().to_degrees()
        };
        let (e_on, e_off) = (rms(&on), rms(&off));
        assert!(e_off < e_on, "offline {e_off}° vs online {e_on}°");
        // with the lever arm known, both become small
        let opts_la = SmoothOptions {
            lever_arm_m: Some(SlewingPlatform::default().lever_arm_m),
            ..Default::default()
        };
        let e_off_la = rms(&smooth(&g, &a, &d, &opts_la));
        assert!(
            e_off_la < 0.1 && e_off_la < e_off / 5.0,
            "compensated offline {e_off_la}°"
        );
        // up vectors of the output are unit and finite
        assert!(
            off.iter()
                .all(|x| (up_in_body(x).norm() - 1.0).abs() < 1e-9)
        );
    }

    /// The centred lever-arm compensation at low rates, against the truth: the
    /// slewing machine without its engine, whose specific force at the sensor
    /// is gravity plus the lever arm's tangential and centripetal terms. At
    /// 25 Hz (and at 40 Hz, whose 25-ms steps round either side of the old
    /// ±25-ms window) the window held the sample alone and ω̇ read zero: the
    /// tangential term r·ω̇ (up to 2.5 m/s²) was left in.
    #[test]
    fn the_centred_compensation_takes_the_tangential_term_at_low_rates() {
        let m = SlewingPlatform {
            vibration_m_s2: 0.0,
            vibration_rate_rad_s: 0.0,
            ..Default::default()
        };
        for rate in [25.0, 40.0, 50.0, 200.0] {
            let n = (40.0 * rate) as usize;
            // steps a hair either side of the nominal period, as stamps give them
            let dt: Vec<f64> = (0..n)
                .map(|k| (1.0 + 1e-9 * if k % 2 == 0 { 1.0 } else { -1.0 }) / rate)
                .collect();
            let t = running_time(&dt);
            let truth: Vec<_> = t.iter().map(|&tk| m.truth(tk)).collect();
            let g: Vec<Vec3> = truth.iter().map(|tr| tr.gyr_rad_s).collect();
            let a: Vec<Vec3> = truth
                .iter()
                .map(|tr| tr.specific_force(clino_core::G0))
                .collect();
            let out = compensate_centred(&g, &a, &dt, &m.lever_arm_m, &Vec3::zeros());
            let (mut worst, mut left_in) = (0.0f64, 0.0f64);
            for (k, tr) in truth.iter().enumerate().skip(1).take(n - 2) {
                let up = tr
                    .attitude
                    .inverse_transform_vector(&Vec3::new(0.0, 0.0, clino_core::G0));
                worst = worst.max((out[k] - up).norm());
                left_in = left_in.max((a[k] - up).norm());
            }
            // the slews' ramps reach 1 rad/s² at 2.5 m: what was there to remove
            assert!(left_in > 2.0, "{rate} Hz: {left_in}");
            // a centred line's error at the ramps' corners, where ω̈ jumps by
            // J = 2.7 rad/s³: J·T/4 for the 3-point difference of half-width
            // T, 3·J·T/16 for a dense window; at 2.5 m, with a margin of 1.5
            // (0.063 m/s² at 200 Hz, 0.10 at 25 Hz)
            let bound = 1.5 * 2.5 * 2.7 * centred_half_window(&dt) / 4.0;
            assert!(worst < bound, "{rate} Hz: {worst} m/s² (bound {bound})");
        }
    }

    /// The Kalman/RTS pass of [`rts_axis`] against the same linear-Gaussian
    /// model solved in one piece, for both tilt models: every state is a
    /// linear function of the independent Gaussians z = (x₋₁, w₀ … w_{n−1})
    /// plus a known part c_k (the specific force, and in the gyro model the
    /// steps u_k), the bounds are observations 0 = v_k + n_v, 0 = p_k + n_p,
    /// and the posterior mean is z̄ = Σ Hᵀ (H Σ Hᵀ + R)⁻¹ (0 − c). The
    /// smoothed mean of a linear-Gaussian model is unique, so the recursion
    /// must give the same d at every sample.
    #[test]
    fn rts_pass_equals_the_batch_gaussian_solution() {
        use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
        let n = 40;
        let b = BoundedMotion {
            // tight bounds, so that they pull the tilt error well away from 0
            speed_m_s: 0.02,
            range_m: 0.005,
            tilt_sigma_rad: 0.01,
            tilt_tau_s: 0.05,
            // above the sample rate: a bound at every sample
            constraint_rate_hz: 1000.0,
            gyro_walk_rad_sqrt_s: 0.05,
            gyro_weight: None,
        };
        let g = 9.81;
        // uneven steps, an arbitrary horizontal force and gyro-model steps
        let hs: Vec<f64> = (0..n)
            .map(|k| 0.004 + 0.002 * ((k * 7 % 5) as f64) / 4.0)
            .collect();
        let fs: Vec<f64> = (0..n)
            .map(|k| 0.3 * (0.37 * k as f64).sin() + 0.05)
            .collect();
        let us: Vec<f64> = (0..n).map(|k| 1e-3 * (0.9 * k as f64).cos()).collect();
        let u = |k: usize| (us[k], 0.0);
        for gyro in [false, true] {
            let model = if gyro {
                TiltModel::Gyro(&u)
            } else {
                TiltModel::Residual
            };
            let mut got = vec![f64::NAN; n];
            rts_axis(n, |k| fs[k], |k| hs[k], &b, g, model, |k, d| got[k] = d);

            // x_k = A_k z + c_k
            let m = 3 + n;
            let sd2 = b.tilt_sigma_rad * b.tilt_sigma_rad;
            let mut prior = DVector::zeros(m);
            prior[0] = sd2;
            prior[1] = b.speed_m_s * b.speed_m_s;
            prior[2] = b.range_m * b.range_m;
            let mut a = DMatrix::<f64>::zeros(3, m);
            a[(0, 0)] = 1.0;
            a[(1, 1)] = 1.0;
            a[(2, 2)] = 1.0;
            let mut c = Vector3::<f64>::zeros();
            let (mut rows_a, mut rows_c) = (Vec::new(), Vec::new());
            for k in 0..n {
                let h = hs[k];
                let (phi, var, input) = if gyro {
                    (1.0, b.gyro_walk_rad_sqrt_s.powi(2) * h, us[k])
                } else {
                    let phi = (-h / b.tilt_tau_s).exp();
                    (phi, sd2 * (1.0 - phi * phi), 0.0)
                };
                let f = Matrix3::new(phi, 0.0, 0.0, g * h, 1.0, 0.0, 0.0, h, 1.0);
                let f_d = DMatrix::from_fn(3, 3, |i, j| f[(i, j)]);
                a = &f_d * &a;
                a[(0, 3 + k)] += 1.0;
                prior[3 + k] = var;
                c = f * c + Vector3::new(input, fs[k] * h, 0.0);
                rows_a.push(a.clone());
                rows_c.push(c);
            }
            // observations 0 = v_k + n_v and 0 = p_k + n_p at every k
            let mut hm = DMatrix::<f64>::zeros(2 * n, m);
            let mut y = DVector::<f64>::zeros(2 * n);
            let mut r = DVector::<f64>::zeros(2 * n);
            for k in 0..n {
                for (j, (i, var)) in [(1usize, b.speed_m_s.powi(2)), (2, b.range_m.powi(2))]
                    .into_iter()
                    .enumerate()
                {
                    hm.row_mut(2 * k + j).copy_from(&rows_a[k].row(i));
                    y[2 * k + j] = -rows_c[k][i];
                    r[2 * k + j] = var;
                }
            }
            let sigma = DMatrix::from_diagonal(&prior);
            let s = &hm * &sigma * hm.transpose() + DMatrix::from_diagonal(&r);
            let zbar = &sigma * hm.transpose() * s.lu().solve(&y).unwrap();
            for k in 0..n {
                let want = (rows_a[k].row(0) * &zbar)[0] + rows_c[k][0];
                assert!(
                    (got[k] - want).abs() < 1e-9 * (1.0 + want.abs()),
                    "gyro model {gyro}, sample {k}: RTS {} against batch {want}",
                    got[k]
                );
            }
            // and the bounds pulled the tilt error away from zero: the test sees something
            assert!(got.iter().any(|d| d.abs() > 1e-3), "{got:?}");
        }
    }

    /// [`beyond_gyro`] by round trip: an attitude sequence that is the
    /// gyro's own propagation (rates with scale errors s, the estimate given
    /// the rate (ω − b)·(1 − s)) has no step beyond it; a navigation-frame
    /// tilt c applied from sample j on shows as (−c_N, c_E) at j alone.
    #[test]
    fn beyond_gyro_is_what_an_estimate_did_that_the_gyro_did_not() {
        let n = 400;
        let dt = vec![0.01; n];
        let s = Vec3::new(0.02, -0.015, 0.01);
        let bias = vec![Vec3::new(0.01, -0.02, 0.005); n];
        // a turn whose axis turns (coning), as the true rate
        let rate = |k: usize| {
            let t = k as f64 * 0.01;
            Vec3::new(1.5 * (2.0 * t).sin(), 1.2 * (2.0 * t).cos(), 0.4)
        };
        // the gyro reads ω/(1 − s) + b, so that (ω_meas − b)·(1 − s) = ω
        let gyr: Vec<Vec3> = (0..n)
            .map(|k| rate(k).component_div(&(Vec3::repeat(1.0) - s)) + bias[k])
            .collect();
        let mut q = vec![Attitude::identity(); n];
        q[0] = UnitQuaternion::from_euler_angles(0.2, -0.3, 1.0);
        for k in 1..n {
            let (wp, w) = (rate(k - 1), rate(k));
            let phi = ((w + wp) * 0.5 + wp.cross(&w) * (0.01 / 12.0)) * 0.01;
            q[k] = q[k - 1] * UnitQuaternion::from_scaled_axis(phi);
        }
        let acc = vec![Vec3::new(0.0, 0.0, 9.81); n];
        let u = beyond_gyro(&q, &gyr, &acc, &bias, &s, &dt);
        let largest = u.iter().flatten().fold(0.0f32, |m, v| m.max(v.abs()));
        assert!(largest < 1e-6, "{largest}");
        let (j, c) = (150, Vec3::new(0.01, -0.02, 0.005));
        for x in q.iter_mut().skip(j) {
            *x = UnitQuaternion::from_scaled_axis(c) * *x;
        }
        let u = beyond_gyro(&q, &gyr, &acc, &bias, &s, &dt);
        let want = [-c.y as f32, c.x as f32];
        for (k, v) in u.iter().enumerate() {
            let expect = if k == j { want } else { [0.0; 2] };
            for i in 0..2 {
                assert!(
                    (v[i] - expect[i]).abs() < 2e-4 * c.norm() as f32 + 1e-6,
                    "sample {k}: {v:?} against {expect:?}"
                );
            }
        }
    }

    #[test]
    fn empty_and_nan_input() {
        assert!(smooth(&[], &[], &[], &SmoothOptions::default()).is_empty());
        let g = vec![Vec3::zeros(); 10];
        let mut a = vec![Vec3::new(0.0, 0.0, 9.81); 10];
        a[5] = Vec3::new(f64::NAN, 0.0, 9.81);
        let out = smooth(&g, &a, &[0.01; 10], &SmoothOptions::default());
        assert_eq!(out.len(), 10);
        assert!(out.iter().all(|q| q.w.is_finite()));
        // a NaN or absurd rate, and a zero interval, on a longer still record
        // with the gyro model weighted in: every output finite, and level
        let n = 3000;
        let mut g = vec![Vec3::zeros(); n];
        let a = vec![Vec3::new(0.0, 0.0, 9.81); n];
        let mut dt = vec![0.01; n];
        g[700] = Vec3::new(f64::NAN, 0.0, 0.0);
        g[1400] = Vec3::new(1e308, 0.0, 0.0);
        dt[2100] = 0.0;
        for w in [None, Some(1.0)] {
            let opts = SmoothOptions {
                refine: Some(BoundedMotion {
                    gyro_weight: w,
                    ..Default::default()
                }),
                ..Default::default()
            };
            let out = smooth(&g, &a, &dt, &opts);
            assert_eq!(out.len(), n);
            for (k, q) in out.iter().enumerate() {
                let tilt = up_in_body(q).z.clamp(-1.0, 1.0).acos();
                assert!(
                    tilt.is_finite() && tilt < 1e-3,
                    "{w:?}, sample {k}: {tilt} rad"
                );
            }
        }
    }

    /// The offline tilt RMSE (°, after `from_s`) of `motion` simulated
    /// through `model` at `rate` Hz for 120 s, smoothed with `options(true)`
    /// and `options(false)`; and whether the two results are the same to the
    /// bit.
    fn offline_on_and_off(
        motion: &dyn Motion,
        model: &crate::sim::ImuModel,
        rate: f64,
        seed: u64,
        from_s: f64,
        options: impl Fn(bool) -> SmoothOptions,
    ) -> (f64, f64, bool) {
        let s = model.simulate(motion, rate, 120.0, seed);
        let g: Vec<Vec3> = s.iter().map(|x| x.gyr_rad_s).collect();
        let a: Vec<Vec3> = s.iter().map(|x| x.acc_m_s2).collect();
        let dt = vec![1.0 / rate; s.len()];
        let (on, off) = (
            smooth(&g, &a, &dt, &options(true)),
            smooth(&g, &a, &dt, &options(false)),
        );
        let rms = |q: &[Attitude]| {
            let mut e = crate::eval::Rms::default();
            for (k, x) in s.iter().enumerate() {
                if x.t_s > from_s {
                    e.push(crate::eval::inclination_error(
                        &q[k],
                        &motion.truth(x.t_s).attitude,
                    ));
                }
            }
            e.value().to_degrees()
        };
        (rms(&on), rms(&off), on == off)
    }

    #[test]
    fn the_weighted_combination_is_the_weighted_mean_of_the_up_vectors() {
        // forward tilted 10° about x, backward 4° about y: weight 1 keeps the
        // forward up vector, 0 takes the backward one, ½ is `combine`, and
        // 0.3 points along the normalised 0.3·u_f + 0.7·u_b
        let qf = Attitude::from_scaled_axis(Vec3::new(10f64.to_radians(), 0.0, 0.3));
        let qb = Attitude::from_scaled_axis(Vec3::new(0.0, 4f64.to_radians(), 0.3));
        let (uf, ub) = (up_in_body(&qf), up_in_body(&qb));
        let up = |w: f64| up_in_body(&combine_weighted(&qf, &qb, w));
        assert!((up(1.0) - uf).norm() < 1e-12);
        assert!((up(0.0) - ub).norm() < 1e-12);
        assert_eq!(combine(&qf, &qb), combine_weighted(&qf, &qb, 0.5));
        let want = (uf * 0.3 + ub * 0.7).normalize();
        assert!((up(0.3) - want).norm() < 1e-12, "{:?} {want:?}", up(0.3));
        // opposite up vectors have no mean: the forward attitude
        let across = uf.cross(&Vec3::x()).normalize();
        let flip = qf * Attitude::from_scaled_axis(across * core::f64::consts::PI);
        assert!((up_in_body(&flip) + uf).norm() < 1e-12);
        assert_eq!(combine_weighted(&qf, &flip, 0.5), qf);
    }

    #[test]
    fn a_clipped_gyro_is_smoothed_from_the_quiet_side_and_jumps_in_the_refinement() {
        // The hand at twice its speed through an MPU6050 at its power-on
        // ±250 °/s, 40 Hz, seeds 1–8. Told of the clipped rates, the passes
        // realign after them, the one that comes from the quiet side counts
        // most, and the refinement's gyro model lets the tilt jump where the
        // gyro clipped: 2.233° → 1.512° over the eight (offline VQF 2.018°),
        // every seed that clips better (3.16 → 2.77° the least). Seed 1 never
        // reaches the range: the same to the bit.
        use crate::sim::hand::{HandMotion, HandParams};
        let mut p = HandParams::by_hand();
        p.band_hz = (p.band_hz.0 * 2.0, p.band_hz.1 * 2.0);
        let model = crate::sim::slewing::sensor().with_bandwidth(16.0);
        let range = SensorRange::from_full_scale(2.0, 250.0);
        let (mut told, mut blind) = (0.0, 0.0);
        for seed in 1..=8 {
            let hand = HandMotion::new(p, seed);
            let (t, b, same) =
                offline_on_and_off(&hand, &model, 40.0, seed, p.initial_rest_s, |on| {
                    SmoothOptions {
                        sensor_range: if on { range } else { SensorRange::default() },
                        ..Default::default()
                    }
                });
            assert_eq!(same, seed == 1, "seed {seed}: {t}° told, {b}° not");
            assert!(same || t < 0.9 * b, "seed {seed}: {t}° told, {b}° not");
            (told, blind) = (told + t, blind + b);
        }
        assert!(told < 0.75 * blind, "{told}° told, {blind}° not (sums)");
    }

    /// [`offline_on_and_off`] of a hand holding poses (creeping on, a 9-Hz
    /// tremor, never set down after the first rest) at 40 Hz through the
    /// calibrated MPU6050 model warming by `c_per_s`, with and without the
    /// drift candidate.
    fn held_hand_offline(c_per_s: f64, seed: u64) -> (f64, f64, bool) {
        use crate::sim::hand::{HandMotion, HandParams};
        use crate::sim::motion::{Sum, vibration};
        let hand = HandMotion::new(HandParams::held(), seed);
        let m = Sum {
            a: hand,
            b: vibration(9.0, 1f64.to_radians(), Vec3::new(0.1, 0.08, 0.06)),
        };
        let mut model = crate::sim::slewing::sensor().with_bandwidth(16.0);
        model.temperature.rate_c_per_s = c_per_s;
        offline_on_and_off(
            &m,
            &model,
            40.0,
            seed,
            hand.params.initial_rest_s,
            |drift| SmoothOptions {
                drift,
                ..Default::default()
            },
        )
    }

    #[test]
    fn a_warming_board_is_followed_by_the_drift_candidate() {
        // 3 °C a minute: the gyro bias drifts by 0.004 °/s each second
        // (0.48 °/s over the record), which the steady passes lag by about
        // 0.3 °/s. Measured without the drift candidate → with it: seed 1
        // 0.341° → 0.224°, seed 5 0.406° → 0.232° (offline VQF, PyPI `vqf`,
        // 0.28° over eight such recordings, BENCHMARKS.md)
        for seed in [1, 5] {
            let (on, off, same) = held_hand_offline(0.05, seed);
            println!("seed {seed}: with {on}°, without {off}°");
            assert!(
                !same && on < 0.75 * off,
                "seed {seed}: {on}° against {off}°"
            );
        }
    }

    #[test]
    fn a_board_that_does_not_warm_keeps_the_steady_passes_to_the_bit() {
        // the drift candidate's bias wanders by 0.005–0.03 °/s a minute
        // here, under DRIFT_RATE_DEG_S_PER_MIN: the steady passes' result
        for seed in [1, 2] {
            let (on, off, same) = held_hand_offline(0.0, seed);
            assert!(same, "seed {seed}: {on}° against {off}°");
        }
    }

    /// [`offline_on_and_off`] of a hand moved at 100 Hz through the
    /// calibrated MPU6050 model with gyro scale errors `scale`, with and
    /// without the learnt scale imposed in the tilt passes.
    fn hand_offline_by_scale(scale: Vec3, seed: u64) -> (f64, f64, bool) {
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::by_hand(), seed);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        model.gyro.scale = scale;
        offline_on_and_off(
            &hand,
            &model,
            100.0,
            seed,
            hand.params.initial_rest_s,
            |scale| SmoothOptions {
                scale,
                ..Default::default()
            },
        )
    }

    #[test]
    fn a_gyro_scale_error_is_imposed_where_it_brings_the_passes_together() {
        // (+2, −1.5, +1) %, the grid's: the learnt scale removes most of the
        // passes' disagreement (88–99 % on the grid's hand at 40 Hz).
        // Measured without → with: seed 1 0.115° → 0.080°, seed 2 0.087° →
        // 0.067°
        for seed in [1, 2] {
            let (on, off, same) = hand_offline_by_scale(Vec3::new(0.02, -0.015, 0.01), seed);
            println!("seed {seed}: with {on}°, without {off}°");
            assert!(!same && on < 0.9 * off, "seed {seed}: {on}° against {off}°");
        }
    }

    #[test]
    fn a_calibrated_gyro_keeps_the_tilt_passes_unscaled_to_the_bit() {
        for seed in [1, 2] {
            let (on, off, same) = hand_offline_by_scale(Vec3::zeros(), seed);
            assert!(same, "seed {seed}: {on}° against {off}°");
        }
    }

    /// The offline error of the slow arm (moves of 12 s under 0.36 rad/s,
    /// rests of 2 s) at 125 Hz on a boom swaying at 3 Hz (1.5 m/s², 2°/s),
    /// through the calibrated MPU6050 model with gyro scale errors `scale`,
    /// with and without the gyro scale imposed in the tilt passes.
    fn boom_offline_by_scale(scale: Vec3, seed: u64) -> (f64, f64, bool) {
        arm_offline_by_scale(scale, seed, 3.0)
    }

    /// [`boom_offline_by_scale`] with the base moving at `hz` (30 Hz: an
    /// engine's vibration).
    fn arm_offline_by_scale(scale: Vec3, seed: u64, hz: f64) -> (f64, f64, bool) {
        arm_on_base_offline_by_scale(scale, seed, hz, Vec3::new(1.5, 1.0, 1.2))
    }

    /// The slow arm (moves of 12 s under 0.36 rad/s, rests of 2 s) on a
    /// base moving at `hz` with 2°/s of angular and `linear` m/s² of linear
    /// amplitude (`generalise`'s slow arm on a vibrating, swaying or rocking
    /// base), and the time its first rest ends, s.
    fn arm_on_base(
        seed: u64,
        hz: f64,
        linear: Vec3,
    ) -> (
        crate::sim::motion::Sum<crate::sim::hand::HandMotion, impl crate::sim::Motion>,
        f64,
    ) {
        use crate::sim::hand::{HandMotion, HandParams};
        let arm = HandMotion::new(HandParams::slow(), seed);
        let from = arm.params.initial_rest_s;
        let base = crate::sim::motion::vibration(hz, 2f64.to_radians(), linear);
        (crate::sim::motion::Sum { a: arm, b: base }, from)
    }

    /// The frequency a base rocks at on `seed`, 1.5–5 Hz (`generalise`'s
    /// slow+rock: the golden ratio's multiples spread the seeds).
    fn rock_hz(seed: u64) -> f64 {
        1.5 + 3.5 * (seed as f64 * 0.618_033_988_75).fract()
    }

    /// The slow arm on a base moving at `hz` with 2°/s of angular and
    /// `linear` m/s² of linear amplitude: [`smooth`] with and without the
    /// gyro scale (its RMS inclination errors, °, and whether they are the
    /// same to the bit).
    fn arm_on_base_offline_by_scale(
        scale: Vec3,
        seed: u64,
        hz: f64,
        linear: Vec3,
    ) -> (f64, f64, bool) {
        let (boom, from) = arm_on_base(seed, hz, linear);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(50.0);
        model.gyro.scale = scale;
        offline_on_and_off(&boom, &model, 125.0, seed, from, |scale| SmoothOptions {
            scale,
            ..Default::default()
        })
    }

    #[test]
    fn a_gyro_scale_no_rest_pair_taught_is_fitted_to_the_passes_disagreement() {
        // On a swaying boom no rest pair is formed (a sway is notched), so
        // nothing is learnt of the gyro's (+2, −1.5, +1) % scale errors: the
        // forward and backward passes turn apart by them, and the scale
        // fitted to their disagreement is imposed. Measured without → with:
        // seed 1 0.072° → 0.039°, seed 2 0.119° → 0.043° (before the fit,
        // on == off)
        for seed in [1, 2] {
            let (on, off, same) = boom_offline_by_scale(Vec3::new(0.02, -0.015, 0.01), seed);
            println!("seed {seed}: with {on}°, without {off}°");
            assert!(!same && on < 0.6 * off, "seed {seed}: {on}° against {off}°");
        }
    }

    #[test]
    fn with_a_gyro_scale_imposed_the_accelerometer_errors_are_learnt_again() {
        // on a base vibrating at 30 Hz the rest pairs form, and the learning
        // passes take part of the gyro's (+2, −1.5, +1) % scale errors for
        // the accelerometer's, imposed from the first sample: a steady
        // offset the scale alone does not remove
        // Measured, with → with the scale imposed but not learnt again →
        // without a scale: seed 1 0.046° → 0.087° → 0.102°, seed 4 0.070° →
        // 0.129° → 0.199° (the fitted scale taken). Since the held poses'
        // pairs end at their means (6 Dec 2026) the learnt scale is taken
        // on seed 1, and no fit after it: 0.067° not learnt again (at
        // 2d0bb51); learnt again 0.043°, 0.071° without a scale; seed 4
        // 0.060° and 0.190°. Since the pairs' magnitudes (7 Dec 2026), which
        // the gyro has no part in, the learning passes take less of the scale
        // for the accelerometer's errors: seed 1 0.035° and 0.049° without a
        // scale, seed 4 0.061° and 0.189°; the bounds are under the scale
        // imposed but not learnt again (0.067°, 0.129°)
        for (seed, most) in [(1, 0.045), (4, 0.08)] {
            let (on, off, _) = arm_offline_by_scale(Vec3::new(0.02, -0.015, 0.01), seed, 30.0);
            println!("seed {seed}: {on}°, without a scale {off}°");
            assert!(
                on < 0.8 * off && on < most,
                "seed {seed}: {on}° against {off}°"
            );
        }
    }

    #[test]
    fn a_rocking_base_with_gyro_scale_errors_takes_the_fitted_scale() {
        // the slow arm on a base rocking at 1.5–5 Hz (2°/s, no linear sway:
        // `generalise`'s slow+rock): few rest pairs, so the (+2, −1.5, +1) %
        // scale errors are left to the fit, which removes 77–96 % of the
        // passes' disagreement over the grid's 8 seeds. Measured, with →
        // without: seed 2 0.042° → 0.120°, seed 4 0.119° → 0.238° (with the
        // bar at 85 % seed 2's fit was not taken: 0.120° either way)
        for seed in [2, 4] {
            let hz = rock_hz(seed);
            let (on, off, same) = arm_on_base_offline_by_scale(
                Vec3::new(0.02, -0.015, 0.01),
                seed,
                hz,
                Vec3::zeros(),
            );
            println!("seed {seed} ({hz:.2} Hz): with {on}°, without {off}°");
            assert!(!same && on < 0.6 * off, "seed {seed}: {on}° against {off}°");
        }
    }

    #[test]
    fn a_calibrated_gyro_on_a_boom_keeps_the_tilt_passes_unscaled_to_the_bit() {
        for seed in [1, 2] {
            let (on, off, same) = boom_offline_by_scale(Vec3::zeros(), seed);
            assert!(same, "seed {seed}: {on}° against {off}°");
        }
    }

    #[test]
    fn the_scale_fit_is_the_regularised_least_squares_solution() {
        // a disagreement made of known responses: g₀ = −J·s with J's
        // columns the responses per unit scale (x and y turned, z never),
        // plus a wiggle orthogonal to all of them: the fit recovers s on x
        // and y, keeps z at zero, and with a prior shrinks it by the
        // closed-form factor (to the f32 records' 7 digits)
        let m = 400;
        let jx = |k: usize| Vec3::new((k as f64 * 0.05).sin(), 0.0, 0.0);
        let jy = |k: usize| Vec3::new(0.0, (k as f64 * 0.031).cos(), 0.0);
        let response = |j: usize, k: usize| match j {
            0 => jx(k),
            1 => jy(k),
            _ => Vec3::zeros(),
        };
        let s = Vec3::new(0.02, -0.015, 0.0);
        let wiggle = |k: usize| Vec3::new(0.0, 0.0, 1e-3 * (k as f64 * 0.7).sin());
        let step = 0.01;
        let f32s = |v: Vec3| [v.x as f32, v.y as f32, v.z as f32];
        let g0 = |k: usize| -(jx(k) * s.x + jy(k) * s.y) + wiggle(k);
        let gap: Vec<[f32; 3]> = (0..m).map(|k| f32s(g0(k))).collect();
        let cols: Vec<Vec<[f32; 3]>> = (0..3)
            .map(|j| {
                (0..m)
                    .map(|k| f32s(g0(k) + response(j, k) * step))
                    .collect()
            })
            .collect();
        let cols = [&cols[0][..], &cols[1][..], &cols[2][..]];
        // a vague prior: s itself
        let fit = scale_fit(&gap, cols, step, m as f64, 1e3).unwrap();
        assert!((fit - s).norm() < 1e-6 * s.norm(), "{fit:?}");
        // a prior σ and 4 independent samples of the 400: per axis
        // s·a/(a + 1/σ²), a = w·Σ J², w = (4/400)/mean|g₀|²
        let sigma = 0.01;
        let fit = scale_fit(&gap, cols, step, 4.0, sigma).unwrap();
        let noise = (0..m).map(|k| g0(k).norm_squared()).sum::<f64>() / m as f64;
        let w = 4.0 / m as f64 / noise;
        let ax: f64 = (0..m).map(|k| jx(k).x.powi(2)).sum::<f64>() * w;
        let ay: f64 = (0..m).map(|k| jy(k).y.powi(2)).sum::<f64>() * w;
        let want = Vec3::new(
            s.x * ax / (ax + 1.0 / (sigma * sigma)),
            s.y * ay / (ay + 1.0 / (sigma * sigma)),
            0.0,
        );
        assert!(
            (fit - want).norm() < 1e-6 * want.norm(),
            "{fit:?} against {want:?}"
        );
        assert!(
            want.x < 0.7 * s.x,
            "the prior is to shrink the fit here: {want:?}"
        );
        // a sample left out (a clipped rate's memory) is not used; with all
        // left out, or nothing to fit, there is no fit
        let mut holed = gap.clone();
        holed[7] = [f32::NAN; 3];
        let fit = scale_fit(&holed, cols, step, m as f64, 1e3).unwrap();
        assert!((fit - s).norm() < 1e-6 * s.norm(), "{fit:?}");
        let none = vec![[f32::NAN; 3]; m];
        assert!(scale_fit(&none, cols, step, m as f64, sigma).is_none());
        assert!(scale_fit(&[], [&[], &[], &[]], step, 1.0, sigma).is_none());
        assert!(scale_fit(&gap, [cols[0], cols[1], &cols[2][1..]], step, 1.0, sigma).is_none());
    }

    #[test]
    fn progress_stays_within_each_stage() {
        // every report names a stage among the COUNT and a count within the
        // record (a stage of several passes, the scale's ten among them,
        // reports its share of each), and every stage run reports its end
        let n = PROGRESS_EVERY + 1000;
        let rate = 200.0;
        let g: Vec<Vec3> = (0..n)
            .map(|k| {
                let t = k as f64 / rate;
                Vec3::new(0.3 * (0.7 * t).sin(), 0.2 * (1.1 * t).cos(), 0.1)
            })
            .collect();
        let mut a: Vec<Vec3> = (0..n)
            .map(|k| Vec3::new(0.2 * (k as f64 * 1e-3).sin(), 0.1, 9.8))
            .collect();
        let dt = vec![1.0 / rate; n];
        let mut seen: Vec<(Stage, usize)> = Vec::new();
        let mut report = |stage: Stage, k: usize, of: usize| {
            assert_eq!(of, n);
            assert!(k <= n && stage.index() < Stage::COUNT, "{stage:?} {k}");
            seen.push((stage, k));
        };
        let opts = SmoothOptions {
            lever_arm_m: Some(Vec3::new(0.5, 0.0, 0.0)),
            ..Default::default()
        };
        smooth_in_place(&g, &mut a, &dt, &opts, Some(&mut report));
        for stage in [
            Stage::Compensate,
            Stage::Pass(1),
            Stage::Scale(10),
            Stage::Refine,
        ] {
            assert!(
                seen.contains(&(stage, n)),
                "{stage:?} never ended: {seen:?}"
            );
        }
    }

    #[test]
    fn drift_rate_is_the_least_squares_slope() {
        // a ramp on each axis (with an offset): the norm of the slopes,
        // exactly; about a mean the slope of a symmetric wiggle is zero
        let t: Vec<f64> = (0..101).map(|k| 0.5 * f64::from(k)).collect();
        let slope = Vec3::new(3e-5, -4e-5, 1.2e-4);
        let ramp: Vec<Vec3> = t
            .iter()
            .map(|&x| Vec3::new(0.1, -0.2, 0.05) + slope * x)
            .collect();
        assert!((drift_rate(&ramp, &t) - slope.norm()).abs() < 1e-15);
        let wiggle: Vec<Vec3> = t
            .iter()
            .map(|&x| Vec3::repeat((x - 25.0).powi(2) * 1e-4))
            .collect();
        assert!(drift_rate(&wiggle, &t) < 1e-15);
        // too short, or not finite: no drift
        assert_eq!(drift_rate(&ramp[..1], &t[..1]), 0.0);
        let mut bad = ramp.clone();
        bad[7].x = f64::NAN;
        assert_eq!(drift_rate(&bad, &t), 0.0);
        assert_eq!(drift_rate(&ramp, &vec![3.0; 101]), 0.0);
    }

    #[test]
    fn bad_samples_in_a_warming_record_change_the_offline_tilt_by_little() {
        // the held hand warming (the drift candidate taken) with gyro scale
        // errors (the scale imposed): a NaN rate, an absurd specific force
        // and a zero interval change the tilt by little, and every output is
        // finite. The finite 1e308 alone, taken by the refinement as
        // specific force, made it 0.527° against the clean 0.440° (0.788°
        // against 0.502° without the two candidates) until the refinement
        // skipped what the pipeline skips (`usable`). Since the specific
        // force confirms a stillness's turn (`TurnConfirm`, 7 Dec 2026) the
        // absurd specific force here moves the tilt from 0.267° to 0.298°
        // (11 %), so the bound is 15 %. That is this record's sensitivity to
        // sample 2000, not the bad value: the sample replaced by the mean of
        // its neighbours gives 0.294°, the sample removed (its interval
        // joined to the next) 0.294°, scaled by 1.0001 0.267° (at samples
        // 1500, 2500 or 3500 the 1e308 moves it by 0.3 % at most). Checked
        // below: the absurd value is handled as a sample that is not there
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::held(), 5);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(16.0);
        model.temperature.rate_c_per_s = 0.05;
        model.gyro.scale = Vec3::new(0.02, -0.015, 0.01);
        let s = model.simulate(&hand, 40.0, 120.0, 5);
        let mut g: Vec<Vec3> = s.iter().map(|x| x.gyr_rad_s).collect();
        let mut a: Vec<Vec3> = s.iter().map(|x| x.acc_m_s2).collect();
        let mut dt = vec![1.0 / 40.0; s.len()];
        let rms = |q: &[Attitude]| {
            let mut e = crate::eval::Rms::default();
            for (k, x) in s.iter().enumerate() {
                if x.t_s > hand.params.initial_rest_s {
                    e.push(crate::eval::inclination_error(
                        &q[k],
                        &hand.truth(x.t_s).attitude,
                    ));
                }
            }
            e.value().to_degrees()
        };
        let clean = rms(&smooth(&g, &a, &dt, &SmoothOptions::default()));
        g[1000] = Vec3::new(f64::NAN, 0.0, 0.0);
        a[2000] = Vec3::new(1e308, 0.0, 0.0);
        dt[3000] = 0.0;
        let out = smooth(&g, &a, &dt, &SmoothOptions::default());
        assert_eq!(out.len(), s.len());
        assert!(out.iter().all(|q| q.coords.iter().all(|v| v.is_finite())));
        let bad = rms(&out);
        println!("clean {clean}°, with the bad samples {bad}°");
        assert!(
            (bad - clean).abs() < 0.15 * clean,
            "{bad}° against {clean}°"
        );
        // the 1e308 alone against the same sample replaced by the mean of
        // its neighbours: a usable value there, where the absurd one is not
        let (g, mut a) = (
            s.iter().map(|x| x.gyr_rad_s).collect::<Vec<_>>(),
            s.iter().map(|x| x.acc_m_s2).collect::<Vec<_>>(),
        );
        let dt = vec![1.0 / 40.0; s.len()];
        a[2000] = (a[1999] + a[2001]) * 0.5;
        let mean = rms(&smooth(&g, &a, &dt, &SmoothOptions::default()));
        a[2000] = Vec3::new(1e308, 0.0, 0.0);
        let absurd = rms(&smooth(&g, &a, &dt, &SmoothOptions::default()));
        println!("sample 2000 as its neighbours' mean {mean}°, as 1e308 {absurd}°");
        assert!(
            (absurd - mean).abs() < 0.02 * mean,
            "{absurd}° against {mean}°"
        );
    }
}
