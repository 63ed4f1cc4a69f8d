//! Lever-arm compensation: remove the tangential and centripetal
//! accelerations that the gyro can explain.
//!
//! An inclinometer at lever arm **p** (metres, body frame) from a point on
//! the rotation axis (a point that does not itself accelerate) measures
//!
//! ```text
//! f = f_true + ω̇ × p + ω × (ω × p)
//! ```
//!
//! the tangential term ω̇ × p and the centripetal (radial) term
//! ω × (ω × p) = (ω·p)·ω − |ω|²·p. Both are known from the gyro rate ω and its
//! derivative ω̇, so they are subtracted before fusion ([`Compensated`]).
//!
//! * [`planar`] is the form of the rotating-platform patent ("inclination
//!   sensing on a rotating platform, with tangential and radial acceleration
//!   errors removed using a rate gyro"): rotation rate w about the platform z
//!   axis, inclinometer at radius r and angle B from the platform x axis.
//! * [`lever_arm_acceleration`] is the general 3-D form for any p and ω.
//! * [`Differentiator`] gives ω̇ from the gyro by a local quadratic
//!   least-squares fit, which does not amplify noise as a finite difference does.

use crate::filter::{AttitudeFilter, Step};
use crate::{Attitude, Vec3};

/// Tangential plus centripetal acceleration of a point at lever arm `p` (m):
/// ω̇ × p + ω × (ω × p), m/s². All vectors in the body frame.
#[inline]
pub fn lever_arm_acceleration(w: &Vec3, w_dot: &Vec3, p: &Vec3) -> Vec3 {
    w_dot.cross(p) + w.cross(&w.cross(p))
}

/// Planar compensation of the rotating-platform patent.
///
/// The platform turns about its z axis at rate `w` (rad/s) with angular
/// acceleration `w_dot` (rad/s²); the inclinometer sits at radius `r` (m) and
/// angle `b` (rad) from the platform x axis and reads `ix`, `iy` (m/s²) along
/// the platform x and y axes. The tangential acceleration r·ẇ has x component
/// −r·ẇ·sin B and y component r·ẇ·cos B; the radial one is −w²·r·(cos B, sin B).
/// Both are subtracted: returns (Ix − (−r·ẇ·sin B − w²·r·cos B),
/// Iy − (r·ẇ·cos B − w²·r·sin B)).
#[inline]
pub fn planar(ix: f64, iy: f64, w: f64, w_dot: f64, r: f64, b: f64) -> (f64, f64) {
    let (sb, cb) = (crate::math::sin(b), crate::math::cos(b));
    let tx = -r * w_dot * sb;
    let ty = r * w_dot * cb;
    let rx = -w * w * r * cb;
    let ry = -w * w * r * sb;
    (ix - tx - rx, iy - ty - ry)
}

/// Capacity of the differentiator's window, samples.
pub const MAX_WINDOW: usize = 32;

/// Derivative of a 3-vector signal by a local quadratic least-squares fit over
/// the last N samples, evaluated at the newest sample (causal, no lag).
///
/// Fit y(t) ≈ c₀ + c₁·(t − tₙ) + c₂·(t − tₙ)² over the window by least squares
/// (actual time stamps, so jitter is handled) and return c₁ = ẏ(tₙ).
///
/// * **Lag:** none for signals that are quadratic over the window; a sinusoid
///   of frequency f is differentiated with a relative error of order
///   (2π·f·T_w)³/12 for window length T_w.
/// * **Noise gain:** for white noise σ at spacing h, the derivative's standard
///   deviation is G·σ/h with G = 1.11, 0.68, 0.47, 0.35, 0.23, 0.14 for
///   N = 5, 7, 9, 11, 15, 21 (a backward difference has √2 = 1.41; a centred
///   fit would have about a quarter of these, at the price of (N − 1)/2
///   samples of lag).
///
/// The default window is 50 ms (15 samples at 285 Hz, 6 at 100 Hz), capped at
/// [`MAX_WINDOW`] samples: long enough to cut MPU6050-class gyro noise by 6×,
/// short enough that jerk-limited slewing (ω̇ changing over ≥ 0.5 s) is
/// followed without bias. Until three samples have arrived the derivative is zero.
#[derive(Clone, Debug)]
pub struct Differentiator {
    window_s: f64,
    n: usize,
    t: [f64; MAX_WINDOW],
    y: [Vec3; MAX_WINDOW],
    len: usize,
    head: usize,
    now: f64,
}

impl Default for Differentiator {
    fn default() -> Self {
        Self::new(0.05)
    }
}

impl Differentiator {
    /// A differentiator whose window spans `window_s` seconds (the sample count
    /// is fixed at the first sample from its dt: N = round(T_w/dt) + 1, 3 ≤ N ≤ 32).
    pub fn new(window_s: f64) -> Self {
        Self {
            window_s: if window_s.is_finite() && window_s > 0.0 {
                window_s
            } else {
                0.05
            },
            n: 0,
            t: [0.0; MAX_WINDOW],
            y: [Vec3::zeros(); MAX_WINDOW],
            len: 0,
            head: 0,
            now: 0.0,
        }
    }

    /// A differentiator over exactly `n` samples (3 ≤ n ≤ 32).
    pub fn with_samples(n: usize) -> Self {
        let mut d = Self::new(1.0);
        d.n = n.clamp(3, MAX_WINDOW);
        d
    }

    /// Window length in samples (0 until the first sample fixed it).
    pub fn samples(&self) -> usize {
        self.n
    }

    /// Forget the history.
    pub fn reset(&mut self) {
        self.len = 0;
        self.head = 0;
        self.now = 0.0;
    }

    /// Push a sample taken `dt` seconds after the previous one; return the
    /// derivative at this sample. Non-finite input is ignored (returns `None`).
    pub fn push(&mut self, dt: f64, y: Vec3) -> Option<Vec3> {
        if !(dt.is_finite() && dt > 0.0 && y.iter().all(|v| v.is_finite())) {
            return None;
        }
        if self.n == 0 {
            let n = libm::round(self.window_s / dt + 1.0);
            self.n = if n.is_finite() {
                (n as usize).clamp(3, MAX_WINDOW)
            } else {
                3
            };
        }
        self.now += dt;
        self.t[self.head] = self.now;
        self.y[self.head] = y;
        self.head = (self.head + 1) % self.n;
        if self.len < self.n {
            self.len += 1;
        }
        Some(self.derivative())
    }

    fn derivative(&self) -> Vec3 {
        if self.len < 3 {
            return Vec3::zeros();
        }
        // sums of x^k and x^k·y with x = t − t_now
        let (mut s1, mut s2, mut s3, mut s4) = (0.0, 0.0, 0.0, 0.0);
        let mut sy = Vec3::zeros();
        let mut sxy = Vec3::zeros();
        let mut sx2y = Vec3::zeros();
        for i in 0..self.len {
            let x = self.t[i] - self.now;
            let x2 = x * x;
            s1 += x;
            s2 += x2;
            s3 += x2 * x;
            s4 += x2 * x2;
            sy += self.y[i];
            sxy += self.y[i] * x;
            sx2y += self.y[i] * x2;
        }
        let s0 = self.len as f64;
        // normal equations [s0 s1 s2; s1 s2 s3; s2 s3 s4]·c = [sy; sxy; sx2y]; c1 by Cramer
        let det = s0 * (s2 * s4 - s3 * s3) - s1 * (s1 * s4 - s3 * s2) + s2 * (s1 * s3 - s2 * s2);
        if det == 0.0 || !det.is_finite() {
            return Vec3::zeros();
        }
        // numerator of c1: replace the second column with the right-hand side
        let m0 = s1 * s4 - s2 * s3; // cofactor terms for sy
        let m1 = s0 * s4 - s2 * s2; // for sxy
        let m2 = s0 * s3 - s1 * s2; // for sx2y
        (-sy * m0 + sxy * m1 - sx2y * m2) / det
    }
}

/// The lever-arm stage on its own: a sensor at `r_m` from a point on the
/// rotation axis, and the differentiator that gives ω̇.
///
/// Each call, ω = ω_meas − b̂ (the filter's bias estimate), ω̇ from the
/// [`Differentiator`], and the specific force f − ω̇ × r − ω × (ω × r) is
/// returned ([`lever_arm_acceleration`]).
#[derive(Clone, Debug)]
pub struct LeverArm {
    /// The lever arm, m, body frame.
    pub r_m: Vec3,
    diff: Differentiator,
}

impl LeverArm {
    /// The stage for lever arm `r_m` (m, body frame) with the default differentiator.
    pub fn new(r_m: Vec3) -> Self {
        Self::with_differentiator(r_m, Differentiator::default())
    }

    /// The stage with a chosen differentiator.
    pub fn with_differentiator(r_m: Vec3, diff: Differentiator) -> Self {
        Self { r_m, diff }
    }

    /// Forget the differentiator's history (the lever arm is kept).
    pub fn reset(&mut self) {
        self.diff.reset();
    }

    /// The compensated specific force of a sample taken `dt` s after the
    /// previous one (`acc` unchanged when the sample cannot be differentiated).
    pub fn compensate(&mut self, gyr: &Vec3, acc: &Vec3, gyro_bias: &Vec3, dt: f64) -> Vec3 {
        match self.rates(gyr, gyro_bias, dt) {
            Some((w, w_dot)) => acc - lever_arm_acceleration(&w, &w_dot, &self.r_m),
            None => *acc,
        }
    }

    /// The rate ω = ω_meas − b̂ and its derivative ω̇ of a sample taken `dt` s
    /// after the previous one (`None` when it cannot be differentiated).
    pub fn rates(&mut self, gyr: &Vec3, gyro_bias: &Vec3, dt: f64) -> Option<(Vec3, Vec3)> {
        let w = gyr - gyro_bias;
        self.diff.push(dt, w).map(|w_dot| (w, w_dot))
    }
}

/// Any attitude filter with lever-arm compensation in front of it.
///
/// Each sample, ω = ω_meas − b̂ (the inner filter's bias estimate), ω̇ from the
/// [`Differentiator`], and the filter receives f − ω̇ × p − ω × (ω × p). The
/// compensated specific force belongs to the same instant as the sample (the
/// causal differentiator has no lag), so timing is preserved.
#[derive(Clone, Debug)]
pub struct Compensated<F> {
    inner: F,
    lever: LeverArm,
}

impl<F: AttitudeFilter> Compensated<F> {
    /// Wrap `inner` with the lever arm `lever_arm_m` (m, body frame, from a
    /// point on the rotation axis to the sensor) and the default differentiator.
    pub fn new(inner: F, lever_arm_m: Vec3) -> Self {
        Self::with_differentiator(inner, lever_arm_m, Differentiator::default())
    }

    /// Wrap with a chosen differentiator.
    pub fn with_differentiator(inner: F, lever_arm_m: Vec3, diff: Differentiator) -> Self {
        Self {
            inner,
            lever: LeverArm::with_differentiator(lever_arm_m, diff),
        }
    }

    /// The wrapped filter.
    pub fn inner(&self) -> &F {
        &self.inner
    }

    /// The wrapped filter, mutably.
    pub fn inner_mut(&mut self) -> &mut F {
        &mut self.inner
    }

    /// The lever arm, m.
    pub fn lever_arm(&self) -> Vec3 {
        self.lever.r_m
    }

    /// The specific force this sample contributes after compensation, or
    /// `None` when the sample is not usable.
    pub fn compensate(&mut self, gyr: &Vec3, acc: &Vec3, dt: f64) -> Option<Vec3> {
        if !(dt.is_finite() && dt > 0.0 && gyr.iter().all(|v| v.is_finite())) {
            return None;
        }
        Some(self.lever.compensate(gyr, acc, &self.inner.gyro_bias(), dt))
    }
}

impl<F: AttitudeFilter> AttitudeFilter for Compensated<F> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn update(&mut self, gyr: Vec3, acc: Vec3, dt: f64) -> Step {
        if !(acc.iter().all(|v| v.is_finite())) {
            return Step::Rejected;
        }
        match self.compensate(&gyr, &acc, dt) {
            Some(f) => self.inner.update(gyr, f, dt),
            None => self.inner.update(gyr, acc, dt),
        }
    }

    fn attitude(&self) -> Attitude {
        self.inner.attitude()
    }

    fn is_initialised(&self) -> bool {
        self.inner.is_initialised()
    }

    fn reset(&mut self) {
        self.inner.reset();
        self.lever.reset();
    }

    fn gyro_bias(&self) -> Vec3 {
        self.inner.gyro_bias()
    }
}

/// Options of [`MountEstimator`]: what it estimates, and the priors and
/// noise it assumes, in physical units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MountOptions {
    /// Estimate the accelerometer bias (body frame). Its horizontal part is
    /// observable while the mount turns about the vertical (rotation
    /// modulation); otherwise it stays at its prior (zero), and the tilt is
    /// what it would have been without the estimator.
    pub estimate_bias: bool,
    /// Estimate the lever arm (`--lever-arm auto`); otherwise it is held at
    /// [`MountOptions::lever_arm_m`].
    pub estimate_lever: bool,
    /// The lever arm, m (body frame): the prior mean when estimated, the
    /// value used otherwise.
    pub lever_arm_m: Vec3,
    /// Prior 1σ of each accelerometer bias component, m/s². Default 0.1 m/s²
    /// (≈ 10 mg: an MPU6050 after a rough calibration).
    pub bias_sigma_m_s2: f64,
    /// Prior 1σ of each lever-arm component when estimated, m. Default 2 m.
    pub lever_sigma_m: f64,
    /// Prior 1σ of the navigation-frame offset (the filter's initial tilt
    /// error times g, and on the vertical the accelerometer's scale error
    /// times g), m/s². Default 10 m/s² (≈ g: diffuse, the initial attitude
    /// may be anything). A narrower prior would hand a share of the initial
    /// error to the bias before any rotation could tell them apart.
    pub offset_sigma_m_s2: f64,
    /// Random walk of that offset, m/s²/√s: a gyro-bias error δb turns the
    /// tilt by δb per second, g·δb of specific force. Default 3e-3 m/s²/√s
    /// (0.02°/s of gyro-bias error followed over ≈ 10 s).
    pub offset_walk_m_s2_sqrt_s: f64,
    /// Gyro scale-factor and misalignment error, 1: while the mount turns at
    /// |ω| the gyro propagation drifts by that fraction of the rate, and the
    /// offset wanders by g·κ·|ω| per √s on top of `offset_walk_m_s2_sqrt_s`.
    /// Default 3e-4 (a calibrated MEMS gyro: 0.03 %, the residual of a
    /// rate-table calibration).
    pub gyro_scale_error: f64,
    /// Length of the blocks over which the model is averaged before each
    /// update, s. Default 0.5 s: the mount's own acceleration averages to
    /// Δv/T over a block, and engine vibration to nearly nothing. Each block
    /// weighs its samples by a triangle (the square of a `block_s`/2 boxcar's
    /// response: an engine at f is left at sinc²(f·`block_s`/2), 1/221 at
    /// 17.5 Hz and 1/153 at 8.75 Hz, where the 0.5-s boxcar left 1/39 and
    /// 1/15; sampled at 50 and 25 Hz, 1/188 and 1/659 against 1/32 and
    /// 1/18); a block starts at the middle of the one before, so every
    /// sample weighs the same and an update comes every `block_s`/2. While
    /// the filter measures a sway of its base (a boom at 1–8 Hz,
    /// [`crate::filter::Dynamic::sway_hz`]), a block is twice the whole
    /// number of its periods nearest to `block_s`/2, which leaves none of it
    /// ([`MountEstimator::set_sway_hz`]). Zero, negative or not finite: the
    /// default.
    pub block_s: f64,
    /// Smallest 1σ of a block's unexplained specific force, m/s². Default
    /// 0.005 m/s² (accelerometer noise averaged over a block is ≈ 10× less).
    pub noise_floor_m_s2: f64,
    /// Time constant over which that 1σ is learnt from the innovations, s.
    /// Default 20 s. Until then it is the mean over the blocks so far with the
    /// pessimistic start (0.05 m/s², a hand) counted as [`NOISE_PRIOR_S`] of
    /// blocks: a few seconds of any motion or rest replace it.
    pub noise_tau_s: f64,
    /// Local gravity, m/s².
    pub gravity_m_s2: f64,
}

impl Default for MountOptions {
    fn default() -> Self {
        Self {
            estimate_bias: true,
            estimate_lever: false,
            lever_arm_m: Vec3::zeros(),
            bias_sigma_m_s2: 0.1,
            lever_sigma_m: 2.0,
            offset_sigma_m_s2: 10.0,
            offset_walk_m_s2_sqrt_s: 3e-3,
            gyro_scale_error: 3e-4,
            block_s: 0.5,
            noise_floor_m_s2: 5e-3,
            noise_tau_s: 20.0,
            gravity_m_s2: crate::G0,
        }
    }
}

/// The weight of the starting noise 1σ of [`MountEstimator`] (0.05 m/s²),
/// as seconds of blocks: it is a guess, worth one block (the default
/// `block_s`), and the blocks measure the noise. The learnt variance is the
/// mean of the guess and the blocks' (an inverse-gamma posterior), so a
/// guess weighed as more lingers: at 2 s, a sixth of the guess's variance
/// was still in it after a slewing machine's 10-s initial rest (the learnt
/// 1σ 0.021 m/s²; 0.0216 in the test below, where the blocks' own is
/// 0.0069), and the first slew, where the bias turns and becomes
/// observable, taught it slowly (at 50 Hz, seed 1: (1.3, −2.4), (3.8, −7.7),
/// (6.8, −8.6) mg 1, 1.5 and 2 s into the slew, truth (7, −10); the first
/// 2 s of slewing hold most of the run's mean-square error). With the
/// 20-s forgetting alone
/// ([`MountOptions::noise_tau_s`]) 60 % of the guess was left. The slewing
/// machine, 8 seeds, lever arm given, 25/50/100/200 Hz, mean: 2 s 0.092/
/// 0.094/0.083/0.085°, 1 s 0.091/0.092/0.081/0.083°, 0.5 s 0.089/0.090/
/// 0.079/0.082°; with `--lever-arm auto` (nine states learnt at once, where
/// a noise too small early takes a block's chance for the arm) 0.098/0.099/
/// 0.090/0.089° at 2 s, 0.098/0.098/0.088/0.090° at 0.5 s, 0.102/0.101/
/// 0.093/0.099° at 0.25 s (BENCHMARKS.md).
pub const NOISE_PRIOR_S: f64 = 0.5;

/// How far the learnt noise of [`MountEstimator`] must rise above the
/// lowest it was since the blocks were last weighed before all the blocks
/// so far are weighed again at the new level, as a ratio of variances.
///
/// A block is weighed by the noise learnt when it comes. Where a quiet
/// stretch (a rest: 0.015 m/s²) is followed by motion the model does not
/// explain (a hand: about 1 m/s² a block), the first blocks of motion come
/// with the rest's noise, and while the arm is still uncertain its prior
/// explains them: a hand's first second fixed the arm at (−0.08, −0.34,
/// 0.05) m ± (0.015, 0.006, 0.020) m, where a least-squares fit over all
/// its blocks gives (−0.02, 0.00, −0.02) m, and it never moved again (the
/// later blocks weighed at their own noise could not outweigh it).
/// Weighing them again at the noise learnt since gives the fit every block
/// would have given at that noise: (−0.02, −0.02, −0.01) m ± (0.024,
/// 0.034, 0.026) m. Twice: the learnt variance is a mean over ≈ 20 s of
/// blocks of three components each, whose own scatter is about 13 % (a
/// χ² of ≈ 120 degrees of freedom); a doubling is a change of the mount's
/// motion, not scatter, and a stationary mount never reweighs. Never the
/// other way: blocks weighed as noisy may have been (a quiet stretch after
/// motion says nothing of the motion's blocks).
pub const NOISE_REWEIGH_RATIO: f64 = 2.0;

/// The share of the block-mean specific force an estimated lever arm must
/// predict ([`MountEstimator::lever_explains`]) before [`MountEstimator`]
/// applies it, and its bias with it ([`MountEstimator::lever_model_holds`]):
/// three quarters, where the arm's terms explain three times what they
/// leave.
///
/// The model holds for a rigid body turning about an axis through a point
/// that does not move, where the arm's terms leave only the noise: the
/// simulated slewing machine predicts 0–0.34 a second into its first slew,
/// 0.95–1.00 five seconds in, 0.996 or more after a minute (8 seeds,
/// 25–200 Hz), and the gate opens 1.2–1.8 s into the slew. On a mount with
/// no such axis the estimate fits chance correlations of the blocks it has
/// seen, and predicts the next no better than no arm: simulated hands (8
/// seeds at 25, 100 and 1000 Hz, twice and three times as fast at 100 Hz)
/// end at −57 % to +5 %; in their first seconds of motion their blocks
/// still correlate with the arm fitted to the blocks before (up to 0.76,
/// and 0.60 from two seconds on). Applied, an arm of a few centimetres
/// times a hand's dω/dt (tens of rad/s²) is metres per second squared of
/// acceleration that is not there (the shaken sensor's tilt 0.15° →
/// 0.38°). At a half, one hand of eight passed in its first second, while
/// its noise was still being learnt ([`LEVER_FIXED_AXIS_M_S2`]: 0.016 →
/// 0.08 m/s²), and had the arm applied for 0.25 s; at three quarters none
/// does, and the slewing machine is as good or better (`generalise
/// --slewing-rates 25,50,100,200`, `--lever-arm auto`, mean °: 0.090,
/// 0.091, 0.078, 0.079 at a half; 0.090, 0.087, 0.077, 0.077 at three
/// quarters; its swaying boom worst 0.135 at both). At 0.9 the first slew
/// waits 2.8–3 s at 100–200 Hz (0.133, 0.147°). Neither this test nor the
/// noise's passes every real mount with no axis: BROAD's arm swings about
/// a moving shoulder are predicted to 77–92 % (trials 15, 18, 21, 31, 33)
/// and leave 0.20–1.08 m/s², its slow rotations leave 0.06–0.08 m/s² and
/// are predicted to −3–18 % (trials 02, 05).
pub const LEVER_EXPLAINS: f64 = 0.75;

/// The largest learnt 1σ of a block's unexplained specific force
/// ([`MountEstimator::noise_sigma`]) with which [`MountEstimator`] applies
/// an estimated lever arm, or the accelerometer bias with an arm given or
/// estimated ([`MountEstimator::lever_model_holds`]), m/s²: 0.1 m/s², a
/// hundredth of g of the mount's own acceleration averaged over a block.
///
/// An arm given says the same as one estimated: that the point on the axis
/// does not move. Until 7 Dec 2026 a given arm was believed whatever the
/// blocks left, and the bias the estimator then read from a moving joint's
/// accelerations was applied: a segment moved by hand, the sensor
/// 0.25 m from its joint, `--lever-arm` given (8 seeds) went from 0.64× VQF's
/// error (the arm's compensation alone) to 0.99× at 40 Hz and 1.23× at
/// 100 Hz (worst recording 1.59×, 1.90×), offline 0.148° → 0.192° and
/// 0.070° → 0.129°. Its blocks leave 0.47–1.05 m/s² unexplained by the
/// end. With the gate it is the compensation alone; the slewing
/// machine's figures are unchanged to the digit (`generalise
/// --slewing-rates 25,50,100,200`).
///
/// The lever-arm model says the point on the axis does not move: what the
/// arm's terms leave is the sensor's noise and what the blocks' triangle
/// leaves of a vibration. The simulated slewing machine leaves 0.007–0.013
/// m/s² (its engine at 30 Hz; its boom's sway notched, under 0.1 at every
/// rate, over 0.05 at some). A sensor carried by hand is swung about the
/// shoulder and elbow, which move: BROAD's fast translations are predicted
/// by an arm of 0.5–0.7 m to 77–92 % ([`LEVER_EXPLAINS`] passes) and leave
/// 0.20–1.08 m/s² a block, and that arm applied (with the share test
/// alone, unweighed then) took the twelve trials' mean from 0.610° to
/// 0.967° (trial 18 0.65° → 3.35°); simulated hands
/// leave 0.9–2.7 m/s². Between the two, 0.1 leaves a factor of 7 to the
/// machine and 2 to the nearest hand; at 0.05 the swaying boom's gate
/// closed in sway (its `--lever-arm auto` 0.10° → 0.16–0.21°).
pub const LEVER_FIXED_AXIS_M_S2: f64 = 0.1;

/// The time over which [`MountEstimator`]'s block noise must have been
/// learnt before a given arm's model can be vouched for, s of blocks: the
/// pessimistic start ([`NOISE_PRIOR_S`]) then weighs at most a fifth, so a
/// quiet start does not pass for a fixed axis before the blocks have shown
/// one ([`MountEstimator::lever_model_holds`]).
pub const VOUCH_SEEN_S: f64 = 2.0;

type M9 = nalgebra::SMatrix<f64, 9, 9>;
type V9 = nalgebra::SVector<f64, 9>;
type M39 = nalgebra::SMatrix<f64, 3, 9>;

/// Online estimate of the accelerometer bias and of the lever arm from the
/// recording itself, observing the [`crate::filter::Dynamic`] filter.
///
/// # Model
///
/// With the filter's attitude q̂ = Q_c ⊗ q̂₀ (body → ENU), where Q_c is the
/// product of the tilt corrections it has applied
/// ([`crate::filter::Dynamic::tilt_correction`]) and q̂₀ the attitude of its
/// gyro propagation alone (rotation matrix R̂₀), the specific force the
/// accelerometer reads, f, rotated into the navigation frame with q̂₀, is
///
/// ```text
/// z = R̂₀·f − g·e_U
///   = m + R̂₀·b + R̂₀·(ω̇× + ω×ω×)·r + a
/// ```
///
/// where m is a constant (the filter's initial tilt error times g on the
/// horizontal, the accelerometer's scale error times g on the vertical,
/// slowly wandering with the gyro-bias error), b the accelerometer bias
/// (body), r the lever arm (body) and a the mount's own acceleration, which
/// averages to Δv/T over a block of length T (all rotated by the constant
/// initial error of q̂₀, which is absorbed in the estimates' frame: it is
/// the filter's own small tilt error). The tangential and centripetal
/// terms are linear in r given ω and ω̇ (the patent's compensation, read
/// backwards), so z is linear in the state x = (m, b, r): a Kalman filter
/// (equivalently, recursive least squares with priors) on block means,
/// H = [I, mean R̂₀, mean R̂₀·(ω̇× + ω×ω×)], gives x and its covariance.
/// The means are weighted by a triangle over each block, and the blocks
/// overlap by half ([`MountOptions::block_s`]): any weighting keeps the
/// model exact (z and H are averaged alike), and the triangle leaves a
/// vibration far less of itself; each block counts as half an independent
/// one in the gain. Each sample enters with its two neighbours: z and R̂₀
/// as their Simpson mean, and for the arm R̂₀·(ω̇× + ω×ω×) = R̈₀ integrated
/// between the neighbours, which is the change of Ṙ₀ = R̂₀·ω× between them:
/// the rate is never differentiated (`Block::add`, private, has the
/// figures).
///
/// # Observability
///
/// On a mount that does not turn, R̂₀ is constant and b is indistinguishable
/// from m (a bias is a tilt): the estimate keeps (nearly) its prior, zero, and the
/// tilt is unchanged. When the mount turns about the vertical, R̂₀·b turns
/// with it while m does not (rotation modulation, as in carouseling): the
/// horizontal bias becomes observable. The lever arm is observable where
/// ω̇ or ω is non-zero, except its component along the rotation axis, which
/// causes no acceleration either. The noise of a block mean is learnt from
/// the innovations (time constant `noise_tau_s`, floor `noise_floor_m_s2`),
/// so a hand's large accelerations weigh little and a machine's small ones much.
#[derive(Clone, Debug)]
pub struct MountEstimator {
    opts: MountOptions,
    x: V9,
    p: M9,
    /// The (up to) two overlapping blocks being summed ([`MountOptions::block_s`]).
    acc: [Block; 2],
    noise_var: f64,
    /// Time the noise has been learnt over, s.
    seen_s: f64,
    blocks: u64,
    /// The frequency of a sway the mount is known to have, Hz
    /// ([`MountEstimator::set_sway_hz`]; 0: none).
    sway_hz: f64,
    /// The lowest learnt noise variance since the blocks were last weighed
    /// ([`NOISE_REWEIGH_RATIO`]).
    noise_low: f64,
    /// Sums over the blocks of their squared innovations without the arm's
    /// terms (the arm at its prior mean) and with those of the arm estimated
    /// before they were seen, each weighed by how much that arm knew,
    /// (m/s²)² ([`MountEstimator::lever_explains`]).
    armless_sq: f64,
    unseen_sq: f64,
    /// The arm estimated before the last block, and its covariance.
    lever_unseen: Vec3,
    lever_unseen_p: nalgebra::Matrix3<f64>,
    /// A given arm's model has held while the bias was learnt
    /// ([`MountEstimator::lever_model_holds`]).
    vouched: bool,
    /// The last sample observed, and the one before it with the step from
    /// it to the last: the blocks sum each sample with its two neighbours
    /// ([`Block::add`]); none after a sample not observed.
    last: Option<Observed>,
    before: Option<(Observed, f64)>,
}

/// One observed sample of [`MountEstimator`]: z = R̂₀·f − g·e_U, R̂₀,
/// R̂₀·ω× (a point at r moves at R̂₀·ω×·r) and |ω|.
#[derive(Clone, Copy, Debug)]
struct Observed {
    z: Vec3,
    r: nalgebra::Matrix3<f64>,
    rv: nalgebra::Matrix3<f64>,
    wn: f64,
}

/// The weighted sums of one block of [`MountEstimator`]: the model's
/// observation and regressors.
#[derive(Clone, Copy, Debug, Default)]
struct Block {
    sz: Vec3,
    sr: nalgebra::Matrix3<f64>,
    /// Σ W·Δ(R̂₀ω×): the arm's regressor from the rate alone ([`Block::add`]).
    srh: nalgebra::Matrix3<f64>,
    /// Sum of weight × dt, s.
    sw: f64,
    /// Time summed so far, s.
    st: f64,
    /// ∫|ω| dt, rad.
    turn: f64,
    /// Length, s (0: not running).
    len: f64,
}

impl Block {
    /// The triangle W of the block at `t` s into it: 0 at both ends, 1 at
    /// its middle, 0 past its end.
    fn triangle(&self, t: f64) -> f64 {
        (1.0 - libm::fabs(2.0 * t / self.len - 1.0)).max(0.0)
    }

    /// Add a sample with its two neighbours, over `dt` s (half the time
    /// between the neighbours), weighted by the triangle at its middle: the
    /// observation `z` and rotation `r` (R̂₀) averaged over the three with
    /// Simpson's weights (1, 4, 1)/6, and `dv` = half the change of R̂₀·ω×
    /// from the first to the third (the velocity of a point at r per metre
    /// of it).
    ///
    /// The arm's regressor is the block mean of R̂₀(ω̇× + ω×ω×) = R̈₀ (Ṙ₀ =
    /// R̂₀·ω×), and between two samples ∫R̈₀ dt is the change of Ṙ₀,
    /// exactly: no derivative of the rate is taken. The specific force's
    /// integral over the same time is its samples' Simpson mean, exact where
    /// the acceleration is a cubic, so a smooth motion's terms match whatever
    /// the weights. A vibration's samples are matched to (2 + cos Ωdt)/3 ÷
    /// sin(Ωdt)/(Ωdt) (dt the step): 1.005 at 30 Hz sampled at 200 Hz, 1.12
    /// at 100 Hz, 1.28 at 2.9 samples a period (17.5 Hz at 50, 8.75 at 25),
    /// where pairs of samples (their mean against the change across them)
    /// matched it to 0.92, 0.68, 0.56.
    ///
    /// Before 8 Dec 2026 the regressor was R̂₀(ω̇× + ω×ω×) at each sample,
    /// ω̇ from the lever stage's differentiator ([`Differentiator`]: 50 ms,
    /// a causal quadratic fit), which passes a 30-Hz engine's angular
    /// vibration sampled at 200 Hz at 0.31 of its size, turned by −167°.
    /// What a block's triangle leaves of that vibration told the arm's
    /// height, with which it turns: on the simulated slewing machine at
    /// 200 Hz (the sensor 1.2 m above the slew axis) the height came out at
    /// −0.7 to −1.2 m, 5.5–6.9 of its own 1σ off (8 seeds with drawn sensor
    /// errors); summed from the rate, 0.50–0.86 m, 1.5–3.2σ (at 50 Hz, its
    /// engine at 17.5 Hz: −0.02 to −0.24 m at 5.2–7.5σ, now 0.03–0.65 m at
    /// 1.7–4.0σ). Still low: something else the blocks keep reads as height.
    fn add(
        &mut self,
        z: &Vec3,
        r: &nalgebra::Matrix3<f64>,
        dv: &nalgebra::Matrix3<f64>,
        w: f64,
        dt: f64,
    ) {
        let wt = self.triangle(self.st + 0.5 * dt);
        self.sz += z * (wt * dt);
        self.sr += r * (wt * dt);
        self.srh += dv * wt;
        self.sw += wt * dt;
        self.st += dt;
        self.turn += w * dt;
    }
}

impl MountOptions {
    /// The prior of [`MountEstimator`]'s state (m, b, r): its mean and the
    /// variance of each component (zero for a state held at its value).
    fn prior(&self) -> (V9, V9) {
        let mean = V9::from_fn(|i, _| if i >= 6 { self.lever_arm_m[i - 6] } else { 0.0 });
        let var = V9::from_fn(|i, _| match i / 3 {
            0 => self.offset_sigma_m_s2 * self.offset_sigma_m_s2,
            1 if self.estimate_bias => self.bias_sigma_m_s2 * self.bias_sigma_m_s2,
            2 if self.estimate_lever => self.lever_sigma_m * self.lever_sigma_m,
            _ => 0.0,
        });
        (mean, var)
    }
}

impl MountEstimator {
    /// An estimator with the priors of `opts`.
    pub fn new(opts: MountOptions) -> Self {
        let (x, var) = opts.prior();
        let p = M9::from_diagonal(&var);
        let floor = opts.noise_floor_m_s2.max(1e-6);
        Self {
            opts,
            x,
            p,
            acc: [Block::default(); 2],
            seen_s: 0.0,
            sway_hz: 0.0,
            // start pessimistic (a hand): the innovations bring it down
            noise_var: (100.0 * floor * floor).max(0.05 * 0.05),
            noise_low: f64::INFINITY,
            blocks: 0,
            armless_sq: 0.0,
            unseen_sq: 0.0,
            lever_unseen: opts.lever_arm_m,
            lever_unseen_p: p.fixed_view::<3, 3>(6, 6).into_owned(),
            vouched: false,
            last: None,
            before: None,
        }
    }

    /// The options.
    pub fn options(&self) -> &MountOptions {
        &self.opts
    }

    /// Accelerometer bias estimate, m/s² (body frame).
    pub fn accel_bias(&self) -> Vec3 {
        Vec3::new(self.x[3], self.x[4], self.x[5])
    }

    /// The part of the bias estimate to remove from the samples, m/s² (body
    /// frame): each component b̂ᵢ weighted by the share of its prior variance
    /// the data have removed, wᵢ = max(0, 1 − σᵢ²/σ₀²) (σ₀ =
    /// [`MountOptions::bias_sigma_m_s2`]). While the mount has turned too
    /// little for the bias to be told from a tilt (σᵢ near σ₀: a component
    /// along the rotation axis never is) the estimate, right on average but
    /// only to within σᵢ, is held back and cannot move the tilt; once a turn
    /// has determined it (σᵢ ≪ σ₀) it is applied in full. Zero when the bias
    /// is not estimated.
    ///
    /// The pipeline applies this share when it models no lever arm (a hand,
    /// a vehicle: accelerations that are not modelled, and that turn with the
    /// mount, leak into the estimate; BROAD 0.655° with the share against
    /// 0.857° with the whole estimate, 0.610° without the estimator), and the
    /// whole estimate [`MountEstimator::accel_bias`], the posterior mean,
    /// when it does (a rigid body turning about an axis, whose accelerations
    /// are the model's: the slewing machine 0.084° (worst 0.090°) against
    /// 0.090° (0.093°) with the share; `generalise`, 8 seeds). With the arm
    /// estimated, the whole estimate while
    /// [`MountEstimator::lever_model_holds`], and none otherwise.
    pub fn applied_accel_bias(&self) -> Vec3 {
        if !self.opts.estimate_bias {
            return Vec3::zeros();
        }
        let s0 = self.opts.bias_sigma_m_s2 * self.opts.bias_sigma_m_s2;
        let b = self.accel_bias();
        Vec3::from_fn(|i, _| {
            let w = 1.0 - self.p[(3 + i, 3 + i)] / s0;
            if w.is_finite() {
                b[i] * w.clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
    }

    /// 1σ of each accelerometer-bias component, m/s².
    pub fn accel_bias_sigma(&self) -> Vec3 {
        Vec3::new(self.p[(3, 3)], self.p[(4, 4)], self.p[(5, 5)]).map(crate::math::sqrt)
    }

    /// Lever-arm estimate (or the given one), m (body frame).
    pub fn lever_arm(&self) -> Vec3 {
        Vec3::new(self.x[6], self.x[7], self.x[8])
    }

    /// 1σ of each lever-arm component, m (zero when not estimated).
    pub fn lever_arm_sigma(&self) -> Vec3 {
        Vec3::new(self.p[(6, 6)], self.p[(7, 7)], self.p[(8, 8)]).map(crate::math::sqrt)
    }

    /// The share of the block-mean specific force the estimated arm
    /// predicts, over the blocks so far: 1 − Σw|u − Hᵣ(r̂′ − r₀)|² / Σw|u|²,
    /// u each block's innovation with the arm at its prior mean r₀, Hᵣ =
    /// R̂₀(ω̇× + ω×ω×) its regressor, and r̂′ the arm estimated before the
    /// block before it, which shares none of its samples (blocks overlap by
    /// half). Out of sample: an arm that fits chance correlations of the
    /// blocks it has seen predicts the next no better than none (zero or
    /// less: a hand, a shaken sensor), while a rigid body's leaves only the
    /// noise (near 1 after the first second of a turn).
    ///
    /// Each block weighs w = σ²/(σ² + tr(Hᵣ P′ Hᵣᵀ)/3), σ² the learnt block
    /// noise and P′ the covariance of r̂′: the share of the prediction's
    /// expected error that is noise rather than the arm's own uncertainty.
    /// A prediction by an arm the blocks had not yet determined is no
    /// evidence either way. Unweighed, such predictions decided the share:
    /// a fast hand's second block of motion, predicted to 94 % by the arm
    /// fitted to the rest's noise (1.8 m of 1σ; such a block now weighs
    /// 10⁻⁷–10⁻⁶), took it to 0.64 and a chance arm was applied (the tilt
    /// 10° for 0.2 s); a
    /// swaying boom's first slew, mispredicted by the arm its sway had set
    /// (the slew's direction of it still at the prior), kept it under a
    /// half 3 s into the slew (0.175° against 0.134°). `None` when the arm
    /// is given or no block has come.
    pub fn lever_explains(&self) -> Option<f64> {
        (self.opts.estimate_lever && self.armless_sq > 0.0)
            .then(|| 1.0 - self.unseen_sq / self.armless_sq)
    }

    /// Whether the mount's accelerations are the lever arm's: the arm's
    /// terms leave at most [`LEVER_FIXED_AXIS_M_S2`] of the block-mean
    /// specific force unexplained (the axis does not move), and the arm is
    /// given or, estimated, predicts at least [`LEVER_EXPLAINS`] of it
    /// ([`MountEstimator::lever_explains`]). Where they are not (a hand, a
    /// vehicle, a segment on a joint that is itself carried),
    /// [`MountEstimator::applied_lever_arm`] is the prior and the
    /// accelerations are the mount's own; the pipeline then applies no
    /// accelerometer bias from the estimator, an arm given or not
    /// ([`crate::pipeline::Pipeline::with_mount_estimator`]).
    ///
    /// A given arm stays believed once its model has held while the turns
    /// pinned the bias down (the noise learnt from [`VOUCH_SEEN_S`] of
    /// blocks, under the bar, and two of the bias's 1σ under half its
    /// prior): the bias was then learnt where the arm holds, and rougher
    /// blocks later (a machine digging or travelling) weigh little in it.
    /// The slewing machine shaken from 40 s on by 0.3 m/s² at 0.7 Hz (3
    /// seeds, 100 Hz): 0.088–0.109° so, 0.45–0.49° had the bias been
    /// dropped when the noise rose (0.17 m/s²).
    pub fn lever_model_holds(&self) -> bool {
        (self.fixed_axis()
            && (!self.opts.estimate_lever
                || self.lever_explains().is_some_and(|f| f >= LEVER_EXPLAINS)))
            || (self.arm_given() && self.vouched)
    }

    /// Whether the blocks' learnt unexplained specific force is under
    /// [`LEVER_FIXED_AXIS_M_S2`]: the point on the axis does not move (false
    /// on a NaN noise).
    fn fixed_axis(&self) -> bool {
        self.noise_var < LEVER_FIXED_AXIS_M_S2 * LEVER_FIXED_AXIS_M_S2
    }

    /// An arm given, not estimated (a zero arm not estimated is no arm: the
    /// pipeline then has no lever stage, [`crate::pipeline::Pipeline::with_mount_estimator`]).
    fn arm_given(&self) -> bool {
        !self.opts.estimate_lever && self.opts.lever_arm_m != Vec3::zeros()
    }

    /// The arm to compensate the samples with, m (body frame): the estimate
    /// where [`MountEstimator::lever_model_holds`], else the prior mean
    /// [`MountOptions::lever_arm_m`].
    pub fn applied_lever_arm(&self) -> Vec3 {
        if self.lever_model_holds() {
            self.lever_arm()
        } else {
            self.opts.lever_arm_m
        }
    }

    /// 1σ of a block's unexplained specific force, as learnt, m/s².
    pub fn noise_sigma(&self) -> f64 {
        crate::math::sqrt(self.noise_var)
    }

    /// Blocks used so far.
    pub fn blocks(&self) -> u64 {
        self.blocks
    }

    /// Drop the partial blocks (the filter re-initialised: C restarts at zero
    /// and the offset m is new); the estimates of b and r are kept and m's
    /// prior restored.
    pub fn restart(&mut self) {
        self.acc = [Block::default(); 2];
        (self.last, self.before) = (None, None);
        let s2 = self.opts.offset_sigma_m_s2 * self.opts.offset_sigma_m_s2;
        for i in 0..3 {
            self.x[i] = 0.0;
            for j in 0..9 {
                self.p[(i, j)] = 0.0;
                self.p[(j, i)] = 0.0;
            }
            self.p[(i, i)] = s2;
        }
    }

    /// A sample not observed (the filter did not fuse it): the samples after
    /// it are not taken as neighbours of those before it.
    pub fn skip(&mut self) {
        (self.last, self.before) = (None, None);
    }

    /// Observe one fused sample: the filter's attitude `q` and its correction
    /// product `corr` after it ([`crate::filter::Dynamic::tilt_correction`]),
    /// the accelerometer reading `f` before any compensation (m/s²), the rate
    /// `w` (the gyro's less its bias), and `dt` since the sample before. The
    /// blocks take the sample before this one with its two neighbours, the
    /// arm's terms from the change of R̂₀·ω× between them (see the type's
    /// model): no derivative of the rate is needed.
    pub fn observe(&mut self, q: &Attitude, corr: &Attitude, f: &Vec3, w: &Vec3, dt: f64) {
        if !(dt.is_finite() && dt > 0.0) {
            (self.last, self.before) = (None, None);
            return;
        }
        let r = (corr.inverse() * q).to_rotation_matrix().into_inner();
        let g = self.opts.gravity_m_s2;
        let z = r * f - Vec3::new(0.0, 0.0, g);
        let rv = r * w.cross_matrix();
        // (a rate near f64::MAX is finite, its norm and R̂₀·ω× need not be)
        if !(z.iter().chain(rv.iter()).all(|v| v.is_finite()) && w.norm().is_finite()) {
            (self.last, self.before) = (None, None);
            return;
        }
        let now = Observed {
            z,
            r,
            rv,
            wn: w.norm(),
        };
        let (last, before) = (self.last.replace(now), self.before);
        self.before = last.map(|l| (l, dt));
        let (Some(mid), Some((first, dt0))) = (last, before) else {
            return;
        };
        // the sample before this one, between its neighbours (Simpson's
        // weights: [`Block::add`]), over half the time between them
        let z = (first.z + mid.z * 4.0 + now.z) / 6.0;
        let r = (first.r + mid.r * 4.0 + now.r) / 6.0;
        let dv = (now.rv - first.rv) * 0.5;
        let (dt, wn) = (0.5 * (dt0 + dt), mid.wn);
        if self.acc.iter().all(|b| b.len == 0.0) {
            self.acc[0] = self.new_block();
        }
        let mut next = false;
        for i in 0..2 {
            let b = &mut self.acc[i];
            if b.len == 0.0 {
                continue;
            }
            let first_half = b.st < 0.5 * b.len;
            b.add(&z, &r, &dv, wn, dt);
            // a triangle starts the next block at its middle
            next |= first_half && b.st >= 0.5 * b.len;
            if b.st >= b.len {
                let b = core::mem::take(b);
                self.update_block(&b);
            }
        }
        if next && let Some(i) = self.acc.iter().position(|b| b.len == 0.0) {
            self.acc[i] = self.new_block();
        }
    }

    /// A sway of the mount at `hz` (a boom at its first mode, measured by
    /// [`crate::filter::Dynamic::sway_hz`]), or none. A block's triangle of
    /// T keeps sinc²(f·T/2) of a sine at f: a sway at 1.5–4 Hz lies in its
    /// main lobe (half of 1.5 m/s² at 2 Hz over 0.5 s, more than the bias it
    /// is to find), and none where f·T/2 is whole. From the next block on,
    /// blocks are twice the whole number of its periods nearest to
    /// `block_s`/2 (at least two periods): the sway and its harmonics fall
    /// on the triangle's double zeros, which a sway measured a few per cent
    /// off still finds nearly at zero.
    pub fn set_sway_hz(&mut self, hz: Option<f64>) {
        self.sway_hz = hz.filter(|f| f.is_finite() && *f > 0.0).unwrap_or(0.0);
    }

    /// The next block: the triangle of `block_s`, or of twice the whole
    /// number of a known sway's periods nearest to `block_s`/2.
    fn new_block(&self) -> Block {
        let t = match self.opts.block_s {
            t if t.is_finite() && t > 0.0 => t,
            _ => MountOptions::default().block_s,
        };
        let len = if self.sway_hz > 0.0 {
            let n = libm::round(0.5 * t * self.sway_hz).max(1.0);
            2.0 * n / self.sway_hz
        } else {
            t
        };
        Block {
            len,
            ..Default::default()
        }
    }

    fn update_block(&mut self, b: &Block) {
        if !(b.sw > 0.0 && b.st > 0.0) {
            return;
        }
        let (z, rb, rh) = (b.sz / b.sw, b.sr / b.sw, b.srh / b.sw);
        let drift = self.opts.gyro_scale_error * self.opts.gravity_m_s2 * b.turn / b.st;
        // the new data a block brings: half of it (they overlap by half)
        let t = 0.5 * b.st;
        // time update: the offset wanders (gyro-bias error, and scale error while turning)
        let walk = self.opts.offset_walk_m_s2_sqrt_s;
        let q = (walk * walk + drift * drift) * t;
        for i in 0..3 {
            self.p[(i, i)] += q;
        }
        let mut hm = M39::zeros();
        for i in 0..3 {
            hm[(i, i)] = 1.0;
            for j in 0..3 {
                hm[(i, 3 + j)] = rb[(i, j)];
                hm[(i, 6 + j)] = rh[(i, j)];
            }
        }
        let nu = z - hm * self.x;
        // the block without the arm's terms (what an arm is to explain), and
        // with the terms of the arm estimated before the block before, which
        // shares none of its samples (blocks overlap by half)
        let r_now = Vec3::from_fn(|i, _| self.x[6 + i]);
        let armless = nu + rh * (r_now - self.opts.lever_arm_m);
        let unseen = armless - rh * (self.lever_unseen - self.opts.lever_arm_m);
        let known = prediction_weight(self.noise_var, &rh, &self.lever_unseen_p);
        self.lever_unseen = r_now;
        self.lever_unseen_p = self.p.fixed_view::<3, 3>(6, 6).into_owned();
        let hph = hm * self.p * hm.transpose();
        // a block whose innovation the state's uncertainty and the learnt noise
        // do not explain (a hand's push, a bump) weighs as little as its own
        // size says
        let e = (nu.norm_squared() - hph.trace()) / 3.0;
        let r = self.noise_var.max(e);
        // blocks overlap by half: a slow residue (a hand's, a vehicle's
        // acceleration) is nearly the same in the two, so each is worth
        // half an independent one
        let s = hph + nalgebra::Matrix3::identity() * (2.0 * r);
        let Some(s_inv) = s.try_inverse() else {
            return;
        };
        let k = self.p * hm.transpose() * s_inv;
        let x = self.x + k * nu;
        let p = self.p - k * s * k.transpose();
        let p = (p + p.transpose()) * 0.5;
        if !(x.iter().all(|v| v.is_finite()) && p.iter().all(|v| v.is_finite())) {
            return;
        }
        self.x = x;
        self.p = p;
        self.blocks += 1;
        if self.opts.estimate_lever {
            self.armless_sq += known * armless.norm_squared();
            self.unseen_sq += known * unseen.norm_squared();
        }
        // the unexplained part of the block mean, learnt from the innovations
        let floor = self.opts.noise_floor_m_s2 * self.opts.noise_floor_m_s2;
        self.seen_s += t;
        let a = (t / self.opts.noise_tau_s.max(t))
            .max(t / (NOISE_PRIOR_S + self.seen_s))
            .min(1.0);
        let before = self.noise_var;
        self.noise_var += a * (e.max(floor) - self.noise_var);
        self.noise_var = self.noise_var.max(floor);
        // a given arm (not none) whose model held (the noise learnt from
        // the blocks themselves, under the fixed-axis bar) while the turns
        // pinned the bias down: the bias was learnt where the arm holds,
        // and later rougher blocks (digging, travel) weigh little in it
        if self.arm_given()
            && self.opts.estimate_bias
            && self.seen_s >= VOUCH_SEEN_S
            && self.fixed_axis()
        {
            let half = 0.5 * self.opts.bias_sigma_m_s2;
            let sb = self.accel_bias_sigma();
            if sb.iter().filter(|&&s| s < half).count() >= 2 {
                self.vouched = true;
            }
        }
        // blocks weighed at a noise since learnt to be larger: weigh them again
        self.noise_low = self.noise_low.min(before);
        if self.noise_var > NOISE_REWEIGH_RATIO * self.noise_low {
            self.reweigh(self.noise_low / self.noise_var);
            self.noise_low = self.noise_var;
        }
    }

    /// Weigh the blocks so far `c` times as much as they were (0 < c ≤ 1),
    /// the priors as they were: in information form, Y = P⁻¹ = Y₀ + D with
    /// Y₀ the prior's, the blocks' D becomes c·D, and Y·x likewise (the
    /// offset's random walk only lowers the offset's share of D). Y₀ + c·D =
    /// (1 − c)·Y₀ + c·Y is positive definite. The states not estimated keep
    /// their zero variance and their values.
    fn reweigh(&mut self, c: f64) {
        if !(c.is_finite() && c > 0.0 && c < 1.0) {
            return;
        }
        let (x0, var) = self.opts.prior();
        // the states held at their values take a unit variance, the same
        // before and after, so the inverses stay those of the others
        let (mut p, mut y0) = (self.p, M9::zeros());
        for i in 0..9 {
            if var[i] > 0.0 {
                y0[(i, i)] = 1.0 / var[i];
            } else {
                p[(i, i)] = 1.0;
                y0[(i, i)] = 1.0;
            }
        }
        let Some(y) = p.cholesky().map(|ch| ch.inverse()) else {
            return;
        };
        let y2 = y0 * (1.0 - c) + y * c;
        let yx2 = y0 * x0 * (1.0 - c) + y * self.x * c;
        let Some(p2) = y2.cholesky().map(|ch| ch.inverse()) else {
            return;
        };
        let x2 = p2 * yx2;
        if !(x2.iter().all(|v| v.is_finite()) && p2.iter().all(|v| v.is_finite())) {
            return;
        }
        for i in 0..9 {
            if var[i] > 0.0 {
                self.x[i] = x2[i];
                for j in 0..9 {
                    self.p[(i, j)] = if var[j] > 0.0 { p2[(i, j)] } else { 0.0 };
                }
            }
        }
        self.p = (self.p + self.p.transpose()) * 0.5;
    }
}

/// How much an arm of covariance `p` knew when it predicted a block of
/// regressor `rh` ([`MountEstimator::lever_explains`]): the share of the
/// prediction's expected error that is the blocks' noise `noise_var`,
/// σ²/(σ² + tr(Hᵣ P Hᵣᵀ)/3), in (0, 1] for a finite P and σ² > 0 (NaN
/// otherwise, which keeps the share, and so the gate, shut).
fn prediction_weight(
    noise_var: f64,
    rh: &nalgebra::Matrix3<f64>,
    p: &nalgebra::Matrix3<f64>,
) -> f64 {
    let spread = (rh * p * rh.transpose()).trace() / 3.0;
    noise_var / (noise_var + spread)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use nalgebra::Vector3;

    #[test]
    fn a_prediction_weighs_by_the_share_of_its_error_that_is_noise() {
        // an arm known to σ_r = 0.1 m per axis, a block turning at ω̇ = 2 rad/s²
        // about z with no rate: Hᵣ = ω̇×, whose rows x and y carry ω̇·σ_r;
        // tr(Hᵣ P Hᵣᵀ) = 2·(2·0.1)², the spread 0.08/3 (m/s²)²
        let rh = Vec3::new(0.0, 0.0, 2.0).cross_matrix();
        let p = nalgebra::Matrix3::identity() * 0.01;
        let sigma2 = 0.02 * 0.02;
        let want = sigma2 / (sigma2 + 0.08 / 3.0);
        assert_relative_eq!(prediction_weight(sigma2, &rh, &p), want, epsilon = 1e-15);
        // an arm known exactly: the whole weight; one not known at all: none
        let zero = nalgebra::Matrix3::zeros();
        assert_eq!(prediction_weight(sigma2, &rh, &zero), 1.0);
        assert!(prediction_weight(sigma2, &rh, &(p * 1e12)) < 1e-9);
        // the spread is a rotation invariant: the same turn about another
        // axis, with an isotropic P, weighs the same
        let q = nalgebra::Rotation3::from_euler_angles(0.4, -1.1, 0.3);
        let turned = q.matrix() * rh * q.matrix().transpose();
        assert_relative_eq!(
            prediction_weight(sigma2, &turned, &p),
            want,
            epsilon = 1e-12
        );
        // no learnt noise or a non-finite covariance: NaN, never a weight
        assert!(prediction_weight(0.0, &rh, &zero).is_nan());
        assert!(prediction_weight(sigma2, &rh, &(p * f64::NAN)).is_nan());
    }

    #[test]
    fn a_sway_makes_blocks_of_whole_periods() {
        // a triangle over an even number of periods leaves none of a sine;
        // the blocks are twice the whole number of sway periods nearest to
        // `block_s`/2, at least one
        let mut e = MountEstimator::new(MountOptions::default());
        assert_relative_eq!(e.new_block().len, 0.5);
        for (hz, len) in [
            (3.0, 2.0 / 3.0),
            (1.5, 2.0 / 1.5),
            (4.5, 2.0 / 4.5),
            (6.5, 4.0 / 6.5),
            (0.5, 4.0),
        ] {
            e.set_sway_hz(Some(hz));
            let mut b = e.new_block();
            assert_relative_eq!(b.len, len, epsilon = 1e-12);
            // and a sine at that frequency (or a harmonic) averages to zero over it
            for (h, phase) in [(1.0, 0.7), (2.0, -0.4), (3.0, 2.0)] {
                let n = 10_000;
                let dt = len / n as f64;
                let m = nalgebra::Matrix3::zeros();
                b.sz = Vec3::zeros();
                (b.sw, b.st) = (0.0, 0.0);
                for k in 0..n {
                    let v = (core::f64::consts::TAU * h * hz * (k as f64 + 0.5) * dt + phase).sin();
                    b.add(&Vec3::new(v, 0.0, 0.0), &m, &m, 0.0, dt);
                }
                let mean = b.sz.x / b.sw;
                assert!(mean.abs() < 1e-6, "{hz} Hz × {h}: {mean}");
            }
        }
        for bad in [None, Some(0.0), Some(f64::NAN), Some(-2.0)] {
            e.set_sway_hz(bad);
            assert_relative_eq!(e.new_block().len, 0.5);
        }
        // a block length that is no length is the default's
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let e = MountEstimator::new(MountOptions {
                block_s: bad,
                ..Default::default()
            });
            assert_relative_eq!(e.new_block().len, 0.5);
        }
    }

    /// A rigid body slewing about z (β = 0.4·t² from a standstill) while an
    /// engine shakes it about x (0.5°/s: the simulated slewing machine's,
    /// at 30 Hz sampled at 200 Hz and at 17.5 Hz sampled at 50 Hz): the
    /// block's sum of the arm's regressor from the rate alone
    /// ([`Block::add`]) against what the accelerometer's samples of a point
    /// on the body sum to (R̈ at the samples by central differences, each
    /// sample's Simpson mean with its neighbours, as the blocks average the
    /// specific force). With the engine alone (no slew) only what the
    /// triangle leaves of the vibration is there, and the differentiator's
    /// form (Σ W·R(ω̇× + ω×ω×)·dt, ω̇ from the lever stage's
    /// [`Differentiator`], against R̈ at the samples alone, as the blocks
    /// summed the specific force before) is off by more than all of it.
    #[test]
    fn a_block_sums_the_arms_terms_from_the_rate() {
        for (fs, hz, amp) in [
            (200.0, 30.0, 0.5),
            (50.0, 17.5, 0.5),
            (50.0, 17.5, 0.0),
            (200.0, 30.0, 0.0),
        ] {
            let (amp, om) = (f64::to_radians(amp), core::f64::consts::TAU * hz);
            for (slew, phase) in [(0.4, 0.0), (0.4, 1.1), (0.0, 0.0), (0.0, 0.7), (0.0, 2.3)] {
                if amp == 0.0 && slew == 0.0 {
                    continue;
                }
                // ν(t) with ν̇ = amp·sin(Ωt + φ)
                let nu = |t: f64| -amp / om * libm::cos(om * t + phase);
                let nu_dot = |t: f64| amp * libm::sin(om * t + phase);
                let rot = |t: f64| {
                    let rz = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), slew * t * t);
                    let rx = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), nu(t));
                    (rz * rx).into_inner()
                };
                let r_dd = |t: f64| {
                    let hh = 1e-4;
                    (rot(t + hh) - rot(t) * 2.0 + rot(t - hh)) / (hh * hh)
                };
                let rate = |t: f64| {
                    let rx = nalgebra::Rotation3::from_axis_angle(&Vector3::x_axis(), nu(t));
                    rx.inverse() * Vec3::z() * (2.0 * slew * t) + Vec3::x() * nu_dot(t)
                };
                // the body rate makes R: Ṙ = R·ω× (central differences)
                let (t0, h) = (0.123, 1e-6);
                let r_dot = (rot(t0 + h) - rot(t0 - h)) / (2.0 * h);
                assert_relative_eq!(r_dot, rot(t0) * rate(t0).cross_matrix(), epsilon = 1e-7);
                let mut b = MountEstimator::new(MountOptions::default()).new_block();
                let (len, dt) = (b.len, 1.0 / fs);
                let n = libm::round(len / dt) as usize;
                // the lever stage's differentiator, its window filled before
                let mut diff = Differentiator::default();
                for k in 0..12 {
                    let _ = diff.push(dt, rate(-(11 - k) as f64 * dt));
                }
                // the sums of the differentiator's form, of R̈'s Simpson means
                // over the samples' neighbours, and of R̈ at the samples alone
                // (as the blocks summed the specific force before)
                let zero = nalgebra::Matrix3::zeros();
                let (mut old, mut sampled, mut point) = (zero, zero, zero);
                // each sample t_k = k·dt, k = 1 … n, with its neighbours
                for k in 1..=n {
                    let (t0, t, t1) = ((k - 1) as f64 * dt, k as f64 * dt, (k + 1) as f64 * dt);
                    let wt = b.triangle(b.st + 0.5 * dt) * dt;
                    let w = rate(t);
                    let w_dot = diff.push(dt, w).unwrap();
                    let wx = w.cross_matrix();
                    old += rot(t) * (w_dot.cross_matrix() + wx * wx) * wt;
                    sampled += (r_dd(t0) + r_dd(t) * 4.0 + r_dd(t1)) * (wt / 6.0);
                    point += r_dd(t) * wt;
                    let dv = (rot(t1) * rate(t1).cross_matrix()
                        - rot(t0) * rate(t0).cross_matrix())
                        * 0.5;
                    let r = (rot(t0) + rot(t) * 4.0 + rot(t1)) / 6.0;
                    b.add(&Vec3::zeros(), &r, &dv, w.norm(), dt);
                }
                let scale = sampled.norm();
                let err = (b.srh - sampled).norm();
                if amp == 0.0 {
                    // a smooth motion: to its curvature
                    assert!(err < 1e-5 * scale, "{fs} Hz: {err} of {scale}");
                } else if slew > 0.0 {
                    // the slew's terms (0.28 rad/s²·s) with the engine's
                    assert!(err < 1e-3 * scale, "{fs} Hz: {err} of {scale}");
                } else if fs == 200.0 {
                    // what the triangle leaves of the vibration alone
                    // (3e-4 to 8e-4 by the phase), matched to 0.5 %; the
                    // differentiator's form is 114–133 % of it off what the
                    // samples sum to
                    assert!(scale > 3e-4 && scale < 2e-3, "{scale}");
                    assert!(err < 0.02 * scale, "{err} of {scale}");
                    let old_err = (old - point).norm();
                    assert!(old_err > point.norm(), "{old_err} of {}", point.norm());
                } else {
                    // at 2.9 samples a period: 22 % (the ratio of the two
                    // sums 1.28)
                    assert!(err < 0.3 * scale, "{err} of {scale}");
                }
            }
        }
    }

    /// A sample the estimator does not see breaks the chain of neighbours:
    /// the samples after it are not differenced with those before it.
    /// Here the rate steps from 0 to 1 rad/s across the gap (the attitude
    /// held, so every three samples on one side have no change of R̂₀·ω×);
    /// without [`MountEstimator::skip`] the step is summed as an arm's term.
    #[test]
    fn a_sample_not_seen_breaks_the_chain_of_neighbours() {
        let q = Attitude::identity();
        let f = Vec3::new(0.0, 0.0, crate::G0);
        let run = |skip: bool| {
            let mut e = MountEstimator::new(MountOptions::default());
            for _ in 0..3 {
                e.observe(&q, &q, &f, &Vec3::zeros(), 0.01);
            }
            if skip {
                e.skip();
            }
            for _ in 0..3 {
                e.observe(&q, &q, &f, &Vec3::z(), 0.01);
            }
            e.acc.iter().map(|b| b.srh.norm()).sum::<f64>()
        };
        assert_eq!(run(true), 0.0);
        assert!(run(false) > 0.05, "{}", run(false));
        // a sample that is no sample (NaN, or a rate whose R̂₀·ω× overflows)
        // breaks the chain as a skipped one does, and leaves the sums finite
        for bad in [Vec3::repeat(f64::NAN), Vec3::new(1e308, 1e308, 1e308)] {
            let mut e = MountEstimator::new(MountOptions::default());
            for k in 0..7 {
                let w = if k == 3 { bad } else { Vec3::zeros() };
                e.observe(&q, &q, &f, &w, 0.01);
            }
            for b in &e.acc {
                assert!(b.srh.iter().chain(b.sz.iter()).all(|v| *v == 0.0), "{bad}");
            }
        }
    }

    /// A block's triangle passes a sine at f by sinc²(f·T/2) (T its length,
    /// sinc x = sin πx/πx): the square of a T/2 boxcar's response. Against
    /// that closed form at an engine's frequencies, and against the 0.5-s
    /// boxcar the blocks were before (sinc(f·T)).
    #[test]
    fn a_triangular_block_passes_an_engine_by_sinc_squared() {
        let sinc = |x: f64| {
            let a = core::f64::consts::PI * x;
            a.sin() / a
        };
        let t = MountOptions::default().block_s;
        for hz in [8.75, 17.5, 30.0, 3.0] {
            let mut worst: f64 = 0.0;
            for j in 0..16 {
                let phase = j as f64 * core::f64::consts::PI / 16.0;
                let mut b = MountEstimator::new(MountOptions::default()).new_block();
                let n = 20_000;
                let dt = t / n as f64;
                let m = nalgebra::Matrix3::zeros();
                for k in 0..n {
                    let v = (core::f64::consts::TAU * hz * (k as f64 + 0.5) * dt + phase).sin();
                    b.add(&Vec3::new(v, 0.0, 0.0), &m, &m, 0.0, dt);
                }
                worst = worst.max((b.sz.x / b.sw).abs());
            }
            let expected = sinc(hz * t / 2.0).powi(2);
            assert_relative_eq!(worst, expected, epsilon = 2e-4 + 0.02 * expected);
            if hz > 5.0 {
                // at least five times below the boxcar's
                assert!(
                    worst < sinc(hz * t).abs().max(1.0 / 39.0) / 5.0,
                    "{hz} Hz: {worst}"
                );
            }
        }
    }

    /// A machine at rest whose engine shakes the sensor at 17.5 Hz (1.5 m/s²
    /// on two axes), sampled at 50 Hz: the blocks' means keep little of it,
    /// so the noise learnt from them nears the floor within a minute and
    /// the first turn can teach the bias. With equally weighted 0.5-s blocks
    /// (8.75 periods) the learnt 1σ stayed at 0.03 m/s².
    #[test]
    fn an_engine_at_rest_leaves_the_learnt_noise_at_its_floor() {
        let mut e = MountEstimator::new(MountOptions::default());
        let (q, dt, a) = (Attitude::identity(), 0.02, 1.5);
        for k in 0..3000 {
            let ph = core::f64::consts::TAU * 17.5 * k as f64 * dt + 0.3;
            let f = Vec3::new(a * ph.sin(), 0.0, crate::G0 + a * ph.cos());
            e.observe(&q, &q, &f, &Vec3::zeros(), dt);
        }
        let floor = MountOptions::default().noise_floor_m_s2;
        assert!(e.noise_sigma() < 2.0 * floor, "{}", e.noise_sigma());
    }

    /// A machine at rest for 10 s (its accelerometer's noise 0.03 m/s² a
    /// sample at 50 Hz, bias (7, −10, 5) mg), then slewing about the
    /// vertical, the rate rising to 1 rad/s over 1.5 s: the bias turns with
    /// it and becomes observable. The noise learnt at rest is the blocks'
    /// own more than the starting guess's, and the first turn teaches the
    /// bias sooner. The blocks' own 1σ is 0.0069 m/s² (0.03 times the root
    /// of a 25-sample triangle's Σw²/(Σw)²); learnt after the rest 0.021 with
    /// the guess (0.05) weighed as 2 s of blocks, 0.013 as 0.5 s. Horizontal
    /// bias error 0.75/1.0/1.25 s into the turn (12.2 mg at its start):
    /// 12.1/10.7/7.1 mg at 2 s, 11.8/8.6/4.6 mg at 0.5 s.
    #[test]
    fn the_first_turn_after_a_rest_teaches_the_bias_sooner() {
        let mut e = MountEstimator::new(MountOptions::default());
        let dt = 0.02;
        let b = Vec3::new(7.0, -10.0, 5.0) * 1e-3 * crate::G0;
        let tilt = Attitude::from_scaled_axis(Vec3::new(0.05, -0.04, 0.0));
        // white noise from a fixed xorshift (sum of 12 uniforms: unit variance)
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut gauss = || {
            let mut s = -6.0;
            for _ in 0..12 {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                s += (x >> 11) as f64 / (1u64 << 53) as f64;
            }
            s
        };
        let (mut psi, mut w) = (0.0, 0.0);
        let mut errors = [f64::NAN; 3];
        let mut noise = f64::NAN;
        for k in 0..(12.0 / dt) as usize {
            let t = k as f64 * dt;
            let w_prev = w;
            w = if t < 10.0 {
                0.0
            } else {
                let u = ((t - 10.0) / 1.5).min(1.0);
                u * u * (3.0 - 2.0 * u)
            };
            psi += 0.5 * (w + w_prev) * dt;
            let q = Attitude::from_scaled_axis(Vec3::new(0.0, 0.0, psi)) * tilt;
            let g_body = q.inverse_transform_vector(&Vec3::new(0.0, 0.0, crate::G0));
            let n = Vec3::new(gauss(), gauss(), gauss()) * 0.03;
            let w_body = q.inverse_transform_vector(&Vec3::new(0.0, 0.0, w));
            e.observe(&q, &Attitude::identity(), &(g_body + b + n), &w_body, dt);
            if (t - 10.0).abs() < 0.5 * dt {
                noise = e.noise_sigma();
            }
            for (i, at) in [10.75, 11.0, 11.25].into_iter().enumerate() {
                if (t - at).abs() < 0.5 * dt {
                    errors[i] = (e.accel_bias() - b).xy().norm() / (1e-3 * crate::G0);
                }
            }
        }
        assert!(noise < 0.015, "learnt 1σ {noise} m/s²");
        assert!(errors[1] < 9.6 && errors[2] < 5.8, "{errors:?} mg");
    }

    #[test]
    fn reweighing_the_blocks_is_running_them_at_the_new_noise() {
        // Two blocks taken at noise v, then weighed at 4v, against the same
        // blocks taken at 4v from the start, in information form (the prior's
        // information plus HᵀH/(2v) a block, as the update's overlap doubles
        // the noise); the bias not estimated keeps its zero variance and value.
        let opts = MountOptions {
            estimate_bias: false,
            estimate_lever: true,
            lever_arm_m: Vec3::new(0.5, -1.0, 0.2),
            ..Default::default()
        };
        let e0 = MountEstimator::new(opts);
        let active = [0, 1, 2, 6, 7, 8];
        let h = |k: f64| {
            nalgebra::SMatrix::<f64, 3, 6>::from_fn(|i, j| {
                if j < 3 {
                    f64::from(u8::from(i == j))
                } else {
                    libm::sin(k * (1.0 + i as f64) + 0.7 * j as f64)
                }
            })
        };
        let z = |k: f64| Vector3::new(libm::cos(k), 0.3 * k, -0.2);
        let sub = |i: usize, j: usize| e0.p[(active[i], active[j])];
        let p0 = nalgebra::SMatrix::<f64, 6, 6>::from_fn(sub);
        let x0 = nalgebra::SVector::<f64, 6>::from_fn(|i, _| e0.x[active[i]]);
        let y0 = p0.try_inverse().unwrap();
        let solve = |v: f64| {
            let mut y = y0;
            let mut yx = y0 * x0;
            for k in [1.0, 2.0] {
                y += h(k).transpose() * h(k) / (2.0 * v);
                yx += h(k).transpose() * z(k) / (2.0 * v);
            }
            let p = y.try_inverse().unwrap();
            (p * yx, p)
        };
        let (xv, pv) = solve(0.01);
        let mut e = e0.clone();
        for i in 0..6 {
            e.x[active[i]] = xv[i];
            for j in 0..6 {
                e.p[(active[i], active[j])] = pv[(i, j)];
            }
        }
        e.reweigh(0.25);
        let (x4, p4) = solve(0.04);
        for i in 0..6 {
            assert_relative_eq!(e.x[active[i]], x4[i], epsilon = 1e-9);
            for j in 0..6 {
                assert_relative_eq!(e.p[(active[i], active[j])], p4[(i, j)], epsilon = 1e-9);
            }
        }
        for i in 3..6 {
            assert_eq!(e.x[i], 0.0);
            assert!((0..9).all(|j| e.p[(i, j)] == 0.0 && e.p[(j, i)] == 0.0));
        }
        // the arm moved back toward its prior mean, its variance grew
        assert!((x4 - xv).norm() > 1e-3 && p4[(3, 3)] > pv[(3, 3)]);
    }

    #[test]
    fn planar_equals_general_form() {
        for &(w, wd, r, b) in &[
            (0.5, 1.0, 2.0, 0.3),
            (-1.0, -0.4, 3.5, 2.5),
            (0.0, 0.7, 1.0, -1.2),
        ] {
            let p = Vector3::new(r * f64::cos(b), r * f64::sin(b), 0.0);
            let a =
                lever_arm_acceleration(&Vector3::new(0.0, 0.0, w), &Vector3::new(0.0, 0.0, wd), &p);
            let (ix, iy) = planar(a.x + 0.1, a.y - 0.2, w, wd, r, b);
            assert_relative_eq!(ix, 0.1, epsilon = 1e-12);
            assert_relative_eq!(iy, -0.2, epsilon = 1e-12);
            // closed forms: tangential magnitude r·|ẇ|, radial w²·r pointing inwards
            let tang = Vector3::new(0.0, 0.0, wd).cross(&p);
            assert_relative_eq!(tang.norm(), r * wd.abs(), epsilon = 1e-12);
            let rad = a - tang;
            assert_relative_eq!(rad, -p * w * w, epsilon = 1e-12);
        }
    }

    #[test]
    fn centripetal_of_constant_rate_is_w2r_inwards() {
        let w = Vector3::new(0.0, 0.0, 1.3);
        let p = Vector3::new(2.0, 0.0, 0.5); // height along the axis does not matter
        let a = lever_arm_acceleration(&w, &Vector3::zeros(), &p);
        assert_relative_eq!(a, Vector3::new(-1.3 * 1.3 * 2.0, 0.0, 0.0), epsilon = 1e-12);
    }

    #[test]
    fn differentiator_is_exact_for_quadratics_with_jitter() {
        let mut d = Differentiator::with_samples(9);
        let f = |t: f64| Vector3::new(1.0 + 2.0 * t - 3.0 * t * t, -0.5 * t, 4.0 * t * t);
        let df = |t: f64| Vector3::new(2.0 - 6.0 * t, -0.5, 8.0 * t);
        let mut t = 0.0;
        let mut last = Vector3::zeros();
        for i in 0..40 {
            let dt = 0.01 + 0.002 * ((i * 7 % 5) as f64 - 2.0) / 2.0;
            t += dt;
            last = d.push(dt, f(t)).unwrap();
        }
        assert_relative_eq!(last, df(t), epsilon = 1e-8);
    }

    #[test]
    fn differentiator_noise_gain_matches_doc() {
        // white noise of unit variance at h = 1: std of the derivative ≈ 0.226 for N = 15
        let mut d = Differentiator::with_samples(15);
        let mut state: u64 = 12345;
        let mut uniform = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut sum2 = 0.0;
        let mut n = 0;
        for i in 0..20000 {
            // Box–Muller
            let (u1, u2) = (uniform().max(1e-300), uniform());
            let g = (-2.0 * u1.ln()).sqrt() * (2.0 * core::f64::consts::PI * u2).cos();
            let v = d.push(1.0, Vector3::new(g, 0.0, 0.0)).unwrap();
            if i > 20 {
                sum2 += v.x * v.x;
                n += 1;
            }
        }
        let sd = (sum2 / n as f64).sqrt();
        assert!((sd - 0.226).abs() < 0.015, "noise gain {sd}");
    }

    #[test]
    fn constant_angular_acceleration_is_removed_exactly() {
        // ω(t) = α·t about z; sensor at p; true specific force (0, 0, g)
        let alpha = 0.8;
        let p = Vector3::new(1.5, -0.4, 0.2);
        let mut c = Compensated::new(crate::filter::Poisson::default(), p);
        let dt = 0.005;
        let mut max_err: f64 = 0.0;
        for k in 1..400 {
            let t = k as f64 * dt;
            let w = Vector3::new(0.0, 0.0, alpha * t);
            let f_true = Vector3::new(0.0, 0.0, 9.81);
            let f = f_true + lever_arm_acceleration(&w, &Vector3::new(0.0, 0.0, alpha), &p);
            let out = c.compensate(&w, &f, dt).unwrap();
            if k > 3 {
                max_err = max_err.max((out - f_true).norm());
            }
        }
        assert!(max_err < 1e-9, "{max_err}");
    }

    #[test]
    fn coning_rate_is_compensated_to_window_error() {
        // ω(t) = Ω·(cos νt, sin νt, 0) + (0, 0, w0): rotating rate vector (coning-like)
        let (big_w, nu, w0) = (0.6, 2.0, 0.5);
        let p = Vector3::new(0.3, 1.2, -0.5);
        let mut d = Differentiator::new(0.05);
        let dt = 0.0035;
        let mut max_err: f64 = 0.0;
        for k in 1..2000 {
            let t = k as f64 * dt;
            let w = Vector3::new(big_w * (nu * t).cos(), big_w * (nu * t).sin(), w0);
            let wd = Vector3::new(
                -big_w * nu * (nu * t).sin(),
                big_w * nu * (nu * t).cos(),
                0.0,
            );
            let est = d.push(dt, w).unwrap();
            if k > 20 {
                let e = (lever_arm_acceleration(&w, &est, &p)
                    - lever_arm_acceleration(&w, &wd, &p))
                .norm();
                max_err = max_err.max(e);
            }
        }
        // truncation of the quadratic fit: of order |p|·Ω·ν³·T_w² (= 0.016 m/s² here);
        // measured far below that, and below 0.3 mg
        let bound = p.norm() * big_w * nu.powi(3) * 0.05f64.powi(2);
        assert!(
            max_err < 0.2 * bound && max_err < 3e-3,
            "{max_err} vs {bound}"
        );
    }
}
