//! The pipeline: calibrate → compensate → filter → tilt, one sample at a time.
//!
//! [`Pipeline`] is the only loop in clino that runs an attitude filter. The
//! same code serves a microcontroller reading a sensor ([`Pipeline::update`]),
//! a live stream on a laptop, whole recordings and NumPy arrays
//! ([`Pipeline::update_batch`], a loop over `update`). It allocates nothing.
//!
//! ## The rules, stated once
//!
//! * **Calibration** (optional): each sample is replaced by
//!   [`Calibration::apply`] before anything else sees it.
//! * **Admission** ([`crate::filter`]'s contract): a sample whose gyro or
//!   accelerometer holds a non-finite value is a *dropout*; one beyond the
//!   physical bounds [`MAX_RATE_RAD_S`] or [`MAX_SPECIFIC_FORCE_M_S2`] is
//!   *saturated*. Neither reaches the filter or the differentiator; the
//!   state is held and the attitude of the sample before is reported.
//! * **Clipping** (optional, [`Pipeline::with_sensor_range`]): a sample the
//!   filter takes whose raw gyro or accelerometer reads within [`CLIP_MARGIN`] of
//!   the sensor's full-scale range is clipped: counted, and the dynamic
//!   filter is told before it takes the sample.
//! * **Time step**: `dt` is the time from the last sample the filter *used*
//!   to this one, so the interval of a dropout is carried into the next
//!   usable sample (the gyro integrates across the gap). A time stamp that is
//!   not finite, or not after the last used one, is refused as a dropout
//!   (readers refuse it earlier, with its line).
//! * **Before initialisation** the filter waits for an accelerometer reading
//!   it can take tilt from (non-zero specific force); those samples have no
//!   attitude ([`Status::Waiting`]). The first usable sample initialises the
//!   attitude (tilt from gravity, heading zero) and needs no `dt`.
//! * **Lever arm** (optional): from the second usable sample on, the
//!   tangential ω̇ × r and centripetal ω × (ω × r) accelerations are removed
//!   from the specific force ([`crate::compensate::LeverArm`]), with ω̇ from
//!   a causal local-quadratic differentiator.
//! * **Outputs**: the attitude (body → ENU) and the tilt set of
//!   [`TiltOutput`] (aerospace roll and pitch, inclination).
//!
//! ```
//! use clino_core::pipeline::{Pipeline, Status};
//! use clino_core::filter::FilterSpec;
//! use clino_core::{ImuSample, Vec3, G0};
//!
//! let mut p = Pipeline::new(FilterSpec::default()); // the dynamic filter
//! let roll = 5f64.to_radians();
//! let acc = Vec3::new(0.0, G0 * roll.sin(), G0 * roll.cos());
//! for k in 0..100 {
//!     let out = p.update(&ImuSample::new(k as f64 * 0.01, Vec3::zeros(), acc));
//!     assert!(k > 0 || out.status == Status::Initialised);
//! }
//! let tilt = p.tilt().unwrap();
//! assert!((tilt.roll_rad - roll).abs() < 1e-9);
//! ```

use crate::clock::SampleClock;
use crate::compensate::{LeverArm, MountEstimator, MountOptions, lever_arm_acceleration};
use crate::filter::{AnyFilter, AttitudeFilter, FilterSpec, Step};
use crate::sensor::Calibration;
use crate::tilt::{RollPitch, inclination};
use crate::{Attitude, ImuSample, Vec3};

/// Largest angular rate a sample may show, rad/s (≈ 57 300 °/s). The widest
/// MEMS gyros read ±4000 °/s (70 rad/s); a larger value is a corrupted
/// reading, and values beyond ~1e150 would overflow the filters' squares.
pub const MAX_RATE_RAD_S: f64 = 1.0e3;

/// Largest specific force a sample may show, m/s² (≈ 1000 g). High-g MEMS
/// accelerometers read ±400 g; a larger value is a corrupted reading.
pub const MAX_SPECIFIC_FORCE_M_S2: f64 = 1.0e4;

/// What the pipeline did with one sample (the `status` column of `clino fuse`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Status {
    /// Not initialised yet (no usable accelerometer reading so far): no attitude.
    Waiting,
    /// The sample initialised the attitude from the accelerometer.
    Initialised,
    /// Gyro propagation and accelerometer correction.
    Fused,
    /// Gyro propagation only (gyro-only filter, or zero accelerometer).
    GyroOnly,
    /// A non-finite gyro or accelerometer value, or a time stamp not after
    /// the last used one: the state is held.
    Dropout,
    /// A reading beyond [`MAX_RATE_RAD_S`] or [`MAX_SPECIFIC_FORCE_M_S2`]: the state is held.
    Saturated,
}

impl Status {
    /// The word written in the `status` column.
    pub const fn as_str(self) -> &'static str {
        match self {
            Status::Waiting => "waiting",
            Status::Initialised => "init",
            Status::Fused => "fused",
            Status::GyroOnly => "gyro_only",
            Status::Dropout => "dropout",
            Status::Saturated => "saturated",
        }
    }

    /// Every status, in the order of [`Counts`].
    pub const ALL: [Status; 6] = [
        Status::Waiting,
        Status::Initialised,
        Status::Fused,
        Status::GyroOnly,
        Status::Dropout,
        Status::Saturated,
    ];

    /// The status named `s` (the inverse of [`Status::as_str`]).
    pub fn from_str_name(s: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.as_str() == s)
    }

    /// True when the filter used the sample.
    pub const fn is_used(self) -> bool {
        matches!(self, Status::Initialised | Status::Fused | Status::GyroOnly)
    }
}

/// Tilt outputs of one attitude, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltOutput {
    /// Aerospace (z-y-x) roll φ.
    pub roll_rad: f64,
    /// Aerospace (z-y-x) pitch θ.
    pub pitch_rad: f64,
    /// Angle of body z from the vertical.
    pub inclination_rad: f64,
}

impl TiltOutput {
    /// The tilt set of attitude `q`.
    pub fn from_attitude(q: &Attitude) -> Self {
        let rp = RollPitch::from_attitude(q);
        Self {
            roll_rad: rp.roll,
            pitch_rad: rp.pitch,
            inclination_rad: inclination(q),
        }
    }
}

/// The pipeline's answer for one sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Output {
    /// What happened to the sample.
    pub status: Status,
    /// The attitude after the sample (body → ENU), `None` before initialisation.
    pub attitude: Option<Attitude>,
}

impl Output {
    /// The tilt set of the attitude, `None` before initialisation.
    pub fn tilt(&self) -> Option<TiltOutput> {
        self.attitude.as_ref().map(TiltOutput::from_attitude)
    }
}

/// Counts of what the pipeline did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Counts {
    /// Samples seen.
    pub samples: u64,
    /// Samples that initialised the attitude.
    pub initialised: u64,
    /// Samples fused (gyro + accelerometer).
    pub fused: u64,
    /// Samples used for the gyro only.
    pub gyro_only: u64,
    /// Samples before the filter could initialise.
    pub waiting: u64,
    /// Dropouts (non-finite values or time not after the last used sample).
    pub dropouts: u64,
    /// Saturated samples (beyond the physical bounds).
    pub saturated: u64,
    /// Samples whose gyro read at its full-scale range
    /// ([`Pipeline::with_sensor_range`]; counted with their status too).
    pub gyro_clipped: u64,
    /// Samples whose accelerometer read at its full-scale range (as
    /// `gyro_clipped`).
    pub acc_clipped: u64,
    /// The first sample with a reading at a range: its number among the
    /// samples counted, from 1.
    pub first_clipped: Option<u64>,
    /// Samples the filter used whose step came from the sample clock
    /// recovered from the stamps ([`Pipeline::with_sample_clock`]), not
    /// from the stamps themselves.
    pub retimed: u64,
}

impl Counts {
    /// Count the readings of `s`, sample `number` (from 1), at the ranges
    /// `range`; whether its gyro and its accelerometer read at them
    /// ([`SensorRange::clipped`]).
    pub fn record_clipping(
        &mut self,
        range: &SensorRange,
        s: &ImuSample,
        number: u64,
    ) -> (bool, bool) {
        let (gyro, acc) = range.clipped(s);
        self.gyro_clipped += u64::from(gyro);
        self.acc_clipped += u64::from(acc);
        if gyro || acc {
            self.first_clipped.get_or_insert(number);
        }
        (gyro, acc)
    }

    /// What `other` counted beyond the statuses, in place of these: the
    /// clipped readings and the steps from the recovered sample clock (a
    /// run's statuses counted apart from the pipeline that counted these).
    pub fn take_pipeline(&mut self, other: &Counts) {
        self.gyro_clipped = other.gyro_clipped;
        self.acc_clipped = other.acc_clipped;
        self.first_clipped = other.first_clipped;
        self.retimed = other.retimed;
    }

    /// Count one sample of status `s`.
    pub fn record(&mut self, s: Status) {
        self.samples += 1;
        match s {
            Status::Waiting => self.waiting += 1,
            Status::Initialised => self.initialised += 1,
            Status::Fused => self.fused += 1,
            Status::GyroOnly => self.gyro_only += 1,
            Status::Dropout => self.dropouts += 1,
            Status::Saturated => self.saturated += 1,
        }
    }
}

/// True when every component is finite.
fn finite(v: &Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// Admission of one (calibrated) sample: `None` when usable, or why not.
pub fn admission(s: &ImuSample) -> Option<Status> {
    if !(finite(&s.gyr_rad_s) && finite(&s.acc_m_s2) && s.t_s.is_finite()) {
        Some(Status::Dropout)
    } else if s.gyr_rad_s.amax() > MAX_RATE_RAD_S || s.acc_m_s2.amax() > MAX_SPECIFIC_FORCE_M_S2 {
        Some(Status::Saturated)
    } else {
        None
    }
}

/// The full-scale ranges of a sensor's two triads: a reading at a range is
/// clipped ([`Pipeline::with_sensor_range`]). Infinite (the default): not
/// known, nothing is taken for clipped.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorRange {
    /// The gyro's range, rad/s (an MPU6050 powers on at ±250 °/s).
    pub gyro_rad_s: f64,
    /// The accelerometer's range, m/s² (an MPU6050 powers on at ±2 g).
    pub acc_m_s2: f64,
}

impl Default for SensorRange {
    fn default() -> Self {
        Self {
            gyro_rad_s: f64::INFINITY,
            acc_m_s2: f64::INFINITY,
        }
    }
}

/// How close to its range a reading counts as clipped, as a fraction of the
/// range: a 16-bit converter's rails are 32767 and −32768 counts (3·10⁻⁵ of
/// the range apart), and a range written in rounded units (250 °/s for
/// 250.0 or 249.99) is within 10⁻³ of the rail it names; a rate 0.25 °/s
/// under a ±250 °/s rail is one that nearly clipped.
pub const CLIP_MARGIN: f64 = 1e-3;

impl SensorRange {
    /// The ranges of a board's configuration: ±`accel_fs_g` g and
    /// ±`gyro_fs_dps` °/s.
    pub fn from_full_scale(accel_fs_g: f64, gyro_fs_dps: f64) -> Self {
        Self {
            gyro_rad_s: gyro_fs_dps.to_radians(),
            acc_m_s2: accel_fs_g * crate::G0,
        }
    }

    /// Whether the gyro and the accelerometer of `s` read at their ranges
    /// (any axis within [`CLIP_MARGIN`] of it).
    pub fn clipped(&self, s: &ImuSample) -> (bool, bool) {
        let at =
            |v: &Vec3, range: f64| range.is_finite() && v.amax() >= range * (1.0 - CLIP_MARGIN);
        (
            at(&s.gyr_rad_s, self.gyro_rad_s),
            at(&s.acc_m_s2, self.acc_m_s2),
        )
    }
}

/// calibrate → compensate → filter → tilt (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Pipeline {
    spec: FilterSpec,
    calibration: Option<Calibration>,
    lever: Option<LeverArm>,
    mount: Option<MountEstimator>,
    /// The accelerometer bias removed from every sample (the mount
    /// estimator's, fed back into the filter's state when it changes).
    applied_bias: Vec3,
    mount_blocks: u64,
    /// The dynamic filter tracks its sensitivity to the lever arm, and each
    /// new arm estimate moves its state (`--lever-arm auto`).
    feeds_back_arm: bool,
    filter: AnyFilter,
    last_t: Option<f64>,
    counts: Counts,
    range: SensorRange,
    /// The sensor's sample clock recovered from the stamps (`None`: the
    /// stamps' own steps), and the recovered time of the samples it took
    /// since the last one the filter used.
    clock: Option<SampleClock>,
    skipped: f64,
}

impl Pipeline {
    /// A pipeline running the filter of `spec`, without calibration or lever arm.
    pub fn new(spec: FilterSpec) -> Self {
        Self {
            filter: spec.build(),
            spec,
            calibration: None,
            lever: None,
            mount: None,
            applied_bias: Vec3::zeros(),
            mount_blocks: 0,
            feeds_back_arm: false,
            last_t: None,
            counts: Counts::default(),
            range: SensorRange::default(),
            clock: Some(SampleClock::new()),
            skipped: 0.0,
        }
    }

    /// The same pipeline taking each step from the sensor's sample clock
    /// recovered from the time stamps (`true`, the default: stamps a host
    /// made when each sample arrived, off by milliseconds, are put back on
    /// the sensor's clock; a sensor's own stamps give their own steps to the
    /// bit, [`crate::clock`]), or from the stamps as they are (`false`).
    pub fn with_sample_clock(mut self, recover: bool) -> Self {
        self.clock = recover.then(SampleClock::new);
        self.skipped = 0.0;
        self
    }

    /// The sample clock recovered from the stamps, when recovering
    /// ([`Pipeline::with_sample_clock`]).
    pub fn sample_clock(&self) -> Option<&SampleClock> {
        self.clock.as_ref()
    }

    /// The same pipeline knowing the sensor's full-scale ranges, so that a
    /// sample read at a range is known to be clipped: the true value was
    /// larger. Each is counted ([`Counts::gyro_clipped`],
    /// [`Counts::acc_clipped`]), and the dynamic filter is told: of a clipped
    /// gyro ([`crate::filter::Dynamic::note_gyro_clipped`]), whose
    /// propagation fell short of the turn, so it realigns on the
    /// accelerometer as at power-on and learns no scale error from the
    /// clipped turn; of a clipped accelerometer
    /// ([`crate::filter::Dynamic::note_acc_clipped`]), whose missing specific
    /// force its velocity residual then forgets within a second.
    pub fn with_sensor_range(mut self, range: SensorRange) -> Self {
        self.range = range;
        self
    }

    /// Change the sensor's full-scale ranges from the next sample on (a
    /// board that reports a new configuration while streaming).
    pub fn set_sensor_range(&mut self, range: SensorRange) {
        self.range = range;
    }

    /// The sensor's full-scale ranges as given ([`Pipeline::with_sensor_range`]).
    pub fn sensor_range(&self) -> SensorRange {
        self.range
    }

    /// The same pipeline with lever-arm compensation: `r_m` is the sensor's
    /// position from a point on the rotation axis, m, body frame.
    pub fn with_lever_arm(mut self, r_m: Option<Vec3>) -> Self {
        self.lever = r_m.map(LeverArm::new);
        self
    }

    /// The same pipeline estimating the accelerometer bias and/or the lever
    /// arm online ([`MountEstimator`]; the dynamic filter only — with any
    /// other filter the estimator stays at its priors). Its current estimates
    /// are removed from every sample before the filter sees it: the bias, and
    /// the tangential and centripetal terms of the estimated (or given) arm.
    /// The bias only while the arm's model holds
    /// ([`MountEstimator::lever_model_holds`]: the axis does not move), given
    /// or estimated; without an arm, the share of it the data pin down.
    /// With `opts.estimate_lever` or a non-zero `opts.lever_arm_m` the lever
    /// stage is switched on.
    pub fn with_mount_estimator(mut self, opts: Option<MountOptions>) -> Self {
        self.mount = opts.map(MountEstimator::new);
        self.track_accel_input();
        if let Some(o) = opts
            && (o.estimate_lever || o.lever_arm_m != Vec3::zeros())
        {
            self.lever = Some(LeverArm::new(o.lever_arm_m));
        }
        self
    }

    /// With the accelerometer bias estimated, the dynamic filter tracks how
    /// its state depends on its accelerometer input, so each new estimate
    /// reaches the tilt at once ([`crate::filter::Dynamic::shift_accel_input`]);
    /// with the lever arm estimated (`--lever-arm auto`), also how it depends
    /// on the arm ([`crate::filter::Dynamic::shift_arm_input`]).
    ///
    /// Both together: until the arm is known the bias estimate is correlated
    /// with its error (the tangential and centripetal terms of a wrong arm
    /// turn with the slew just as the bias does), so moving the tilt by the
    /// new bias alone moved it by half of a consistent change, which was
    /// measured to cost more than it gained (auto 0.18–0.45° against
    /// 0.12–0.17° without feedback); moving it by both, as had the pair
    /// of estimates been removed from the start, gives 0.10–0.11°
    /// (BENCHMARKS.md).
    fn track_accel_input(&mut self) {
        let on = self.feeds_back();
        let observed = self.mount.is_some();
        self.feeds_back_arm = self
            .mount
            .as_ref()
            .is_some_and(|m| m.options().estimate_lever);
        let arm = self.feeds_back_arm;
        if let Some(d) = self.filter.as_dynamic_mut() {
            d.track_accel_input(on);
            d.track_arm_input(arm);
            // the mount estimator observes the gyro-only attitude through it
            d.track_tilt_correction(observed);
        }
        self.hand_over_bias();
    }

    /// While the mount estimator's bias is applied (estimated, and its model
    /// holding: [`MountEstimator::lever_model_holds`]) the filter pulls no
    /// tilt at turns, which make that bias observable and would feed it
    /// into the tilt ([`crate::filter::Dynamic::set_turn_pull`]), and learns
    /// no bias of its own ([`crate::filter::Dynamic::set_accel_bias_owned`]);
    /// otherwise it runs as without the estimator.
    fn hand_over_bias(&mut self) {
        let applied = self.feeds_back()
            && self
                .mount
                .as_ref()
                .is_some_and(MountEstimator::lever_model_holds);
        if let Some(d) = self.filter.as_dynamic_mut() {
            d.set_turn_pull(!applied);
            d.set_accel_bias_owned(applied);
        }
    }

    fn feeds_back(&self) -> bool {
        self.mount
            .as_ref()
            .is_some_and(|m| m.options().estimate_bias)
    }

    /// The accelerometer bias currently removed from every sample, m/s²
    /// (body frame; zero without the online estimator).
    pub fn applied_accel_bias(&self) -> Vec3 {
        self.applied_bias
    }

    /// The online bias and lever-arm estimator, when running.
    pub fn mount_estimator(&self) -> Option<&MountEstimator> {
        self.mount.as_ref()
    }

    /// The same pipeline calibrating every sample first.
    pub fn with_calibration(mut self, calibration: Option<Calibration>) -> Self {
        self.calibration = calibration;
        self
    }

    /// The filter specification.
    pub fn spec(&self) -> &FilterSpec {
        &self.spec
    }

    /// The lever arm, m, when compensating.
    pub fn lever_arm(&self) -> Option<Vec3> {
        self.lever.as_ref().map(|l| l.r_m)
    }

    /// The filter.
    pub fn filter(&self) -> &AnyFilter {
        &self.filter
    }

    /// The filter, mutably (the offline smoother imposes a bias through it).
    pub fn filter_mut(&mut self) -> &mut AnyFilter {
        &mut self.filter
    }

    /// Counts so far.
    pub fn counts(&self) -> &Counts {
        &self.counts
    }

    /// The current attitude, `None` before initialisation.
    #[inline]
    pub fn attitude(&self) -> Option<Attitude> {
        self.filter.is_initialised().then(|| self.filter.attitude())
    }

    /// The current tilt, `None` before initialisation.
    pub fn tilt(&self) -> Option<TiltOutput> {
        self.attitude().as_ref().map(TiltOutput::from_attitude)
    }

    /// Declare `t_s` the time of the last sample the filter used: for a filter
    /// resumed from a saved state ([`Pipeline::filter_mut`]), so that the
    /// next sample's time step is measured from it.
    pub fn set_last_time(&mut self, t_s: f64) {
        self.last_t = Some(t_s);
        self.skipped = 0.0;
        if let Some(c) = &mut self.clock {
            *c = SampleClock::new();
            c.step(t_s);
        }
    }

    /// Back to the state before the first sample (parameters kept).
    pub fn reset(&mut self) {
        self.filter = self.spec.build();
        if let Some(l) = &mut self.lever {
            l.reset();
        }
        if let Some(m) = &mut self.mount {
            *m = MountEstimator::new(*m.options());
        }
        self.applied_bias = Vec3::zeros();
        self.mount_blocks = 0;
        self.track_accel_input();
        self.last_t = None;
        self.counts = Counts::default();
        if let Some(c) = &mut self.clock {
            *c = SampleClock::new();
        }
        self.skipped = 0.0;
    }

    /// Process one sample.
    #[inline]
    pub fn update(&mut self, sample: &ImuSample) -> Output {
        let status = self.step(sample);
        self.counts.record(status);
        Output {
            status,
            attitude: self.attitude(),
        }
    }

    fn step(&mut self, sample: &ImuSample) -> Status {
        // the sample itself when uncalibrated: no copy per sample
        let calibrated;
        let s = match &self.calibration {
            Some(c) => {
                calibrated = c.apply(sample);
                &calibrated
            }
            None => sample,
        };
        if let Some(why) = admission(s) {
            return why;
        }
        let mut retimed = false;
        let dt = match self.last_t {
            Some(t0) => {
                let dt = s.t_s - t0;
                if dt.is_nan() || dt <= 0.0 {
                    return Status::Dropout;
                }
                match &mut self.clock {
                    // the recovered step, plus those of samples taken since
                    // the last one the filter used
                    Some(c) => match c.step(s.t_s) {
                        Some(step) => {
                            retimed = c.recovering();
                            Some(self.skipped + step)
                        }
                        // not after a sample the clock took
                        None => return Status::Dropout,
                    },
                    None => Some(dt),
                }
            }
            None => {
                if let Some(c) = &mut self.clock {
                    *c = SampleClock::new();
                    c.step(s.t_s);
                }
                None
            }
        };
        // a sample the filter takes: the sensor's own reading, before
        // calibration moved its rails
        let number = self.counts.samples + 1;
        let (gyro_clipped, acc_clipped) = self.counts.record_clipping(&self.range, sample, number);
        if let Some(d) = self.filter.as_dynamic_mut() {
            if gyro_clipped {
                d.note_gyro_clipped();
            }
            if acc_clipped {
                d.note_acc_clipped();
            }
        }
        let mut acc = s.acc_m_s2;
        let mut rates = None;
        if let (Some(l), Some(dt)) = (&mut self.lever, dt) {
            rates = l.rates(&s.gyr_rad_s, &self.filter.gyro_bias(), dt);
            if let Some(m) = &self.mount {
                l.r_m = m.applied_lever_arm();
            }
            if let Some((w, w_dot)) = rates {
                acc -= lever_arm_acceleration(&w, &w_dot, &l.r_m);
            }
            if let (true, Some(d)) = (self.feeds_back_arm, self.filter.as_dynamic_mut()) {
                let h = match rates {
                    Some((w, w_dot)) => {
                        let wx = w.cross_matrix();
                        w_dot.cross_matrix() + wx * wx
                    }
                    None => nalgebra::Matrix3::zeros(),
                };
                d.set_arm_input(&h);
            }
        }
        acc -= self.applied_bias;
        // before the first used sample dt is never read (the filter initialises
        // from the accelerometer); any positive value passes the filter's gate
        let step = self
            .filter
            .update(s.gyr_rad_s, acc, dt.unwrap_or(f64::MIN_POSITIVE));
        let status = match step {
            Step::Fused => Status::Fused,
            Step::GyroOnly => Status::GyroOnly,
            Step::Initialised => Status::Initialised,
            Step::Waiting => Status::Waiting,
            Step::Rejected => Status::Dropout,
        };
        if status.is_used() {
            self.last_t = Some(s.t_s);
            self.skipped = 0.0;
            self.counts.retimed += u64::from(retimed);
        } else if let Some(dt) = dt {
            self.skipped = dt;
        }
        let mut new_estimate = false;
        if let Some(m) = &mut self.mount {
            match (status, self.filter.as_dynamic_mut(), dt) {
                (Status::Initialised, _, _) => m.restart(),
                (Status::Fused, Some(d), Some(dt)) => match d.tilt_correction() {
                    Some(qc) => {
                        let w = rates.map_or(s.gyr_rad_s - d.gyro_bias(), |(w, _)| w);
                        m.set_sway_hz(d.sway_hz());
                        m.observe(&d.sampled_attitude(), &qc, &s.acc_m_s2, &w, dt);
                    }
                    // a filter put in through `filter_mut` without the
                    // tracking: its gyro-only reference starts here, as at
                    // initialisation
                    None => {
                        d.track_tilt_correction(true);
                        m.restart();
                    }
                },
                _ => m.skip(),
            }
            if m.blocks() != self.mount_blocks {
                new_estimate = true;
                // a new estimate: remove it from the samples to come, and move
                // the filter's state to where it would be had it been removed
                // from the samples before
                self.mount_blocks = m.blocks();
                let feedback = m.options().estimate_bias;
                // the whole estimate where the mount's accelerations are
                // modelled (a lever arm, given or estimated, about an axis
                // that does not move); none where they are not
                // (MountEstimator::lever_model_holds: a hand, a robot arm,
                // a joint carried by hand, whose own accelerations and gyro
                // errors turn with it as the bias does); the share the data
                // have pinned down where no arm is modelled
                // (MountEstimator::applied_accel_bias)
                let target = if !m.lever_model_holds() {
                    Vec3::zeros()
                } else if self.lever.is_some() {
                    m.accel_bias()
                } else {
                    m.applied_accel_bias()
                };
                let delta = target - self.applied_bias;
                if let (true, Some(d)) = (feedback, self.filter.as_dynamic_mut()) {
                    d.shift_accel_input(-delta);
                }
                self.applied_bias = target;
                if let (true, Some(l)) = (m.options().estimate_lever, &mut self.lever) {
                    let dr = m.applied_lever_arm() - l.r_m;
                    l.r_m = m.applied_lever_arm();
                    if let (true, Some(d)) = (self.feeds_back_arm, self.filter.as_dynamic_mut()) {
                        d.shift_arm_input(-dr);
                    }
                }
            }
        }
        if new_estimate {
            self.hand_over_bias();
        }
        status
    }

    /// Process `samples` in order, writing one [`Output`] per sample into
    /// `out` (which must be at least as long; extra entries are untouched).
    /// The same code as [`Pipeline::update`]. Returns the number processed.
    pub fn update_batch(&mut self, samples: &[ImuSample], out: &mut [Output]) -> usize {
        let n = samples.len().min(out.len());
        for (s, o) in samples[..n].iter().zip(&mut out[..n]) {
            *o = self.update(s);
        }
        n
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::G0;
    use crate::filter::FilterKind;

    fn still(t: f64) -> ImuSample {
        ImuSample::new(t, Vec3::zeros(), Vec3::new(0.0, 0.0, G0))
    }

    #[test]
    fn dropouts_hold_the_state_and_their_interval_carries_over() {
        let mut p = Pipeline::new(FilterSpec::default_for(FilterKind::Poisson));
        let w = Vec3::new(0.0, 0.0, 0.5);
        let s = |t: f64| ImuSample::new(t, w, Vec3::new(0.0, 0.0, G0));
        assert_eq!(p.update(&s(0.0)).status, Status::Initialised);
        p.update(&s(0.01));
        let held = p.attitude();
        let mut bad = s(0.02);
        bad.gyr_rad_s.x = f64::NAN;
        assert_eq!(p.update(&bad).status, Status::Dropout);
        assert_eq!(p.attitude(), held);
        let out = p.update(&s(0.03));
        assert_eq!(out.status, Status::GyroOnly);
        // yaw = 0.5 rad/s over 0.01 + 0.02 s (the gap carried into the step)
        let q = out.attitude.unwrap();
        let yaw = 2.0 * libm::atan2(q.k, q.w);
        assert!((yaw - 0.5 * 0.03).abs() < 1e-12, "{yaw}");
        assert_eq!(p.counts().dropouts, 1);
    }

    #[test]
    fn a_huge_finite_reading_is_saturated_not_poison() {
        for kind in FilterKind::ALL {
            let mut p = Pipeline::new(FilterSpec::default_for(kind));
            for k in 0..10 {
                p.update(&still(k as f64 * 0.01));
            }
            let mut bad = still(0.1);
            bad.acc_m_s2.x = 1e308;
            assert_eq!(p.update(&bad).status, Status::Saturated, "{kind}");
            let mut bad = still(0.11);
            bad.gyr_rad_s.y = -1e200;
            assert_eq!(p.update(&bad).status, Status::Saturated, "{kind}");
            for k in 12..20 {
                let o = p.update(&still(k as f64 * 0.01));
                let q = o.attitude.unwrap();
                assert!(q.w.is_finite() && q.i.is_finite(), "{kind}: {q:?}");
                assert!(o.tilt().unwrap().inclination_rad.abs() < 1e-9, "{kind}");
            }
            assert_eq!(p.counts().saturated, 2);
        }
    }

    #[test]
    fn a_reading_at_its_range_is_clipped_and_counted() {
        // an MPU6050 at ±250 °/s and ±2 g: its rails are 32767/131 = 250.13 °/s
        // and −32768/131, 32767/16384 g; 0.1 % under a range counts, less not
        let r = SensorRange::from_full_scale(2.0, 250.0);
        let at = |w: f64, f: f64| {
            r.clipped(&ImuSample::new(
                0.0,
                Vec3::new(0.0, w, 0.0),
                Vec3::new(0.0, 0.0, f),
            ))
        };
        let dps = |d: f64| d.to_radians();
        assert_eq!(at(dps(32767.0 / 131.0), G0), (true, false));
        assert_eq!(at(dps(-32768.0 / 131.0), G0), (true, false));
        assert_eq!(at(dps(249.76), G0), (true, false));
        assert_eq!(at(dps(249.74), G0), (false, false));
        assert_eq!(at(0.0, -32768.0 / 16384.0 * G0), (false, true));
        assert_eq!(at(0.0, 1.997 * G0), (false, false));
        // not known: nothing is clipped, however large
        let none = SensorRange::default();
        let big = ImuSample::new(0.0, Vec3::repeat(100.0), Vec3::repeat(1e3));
        assert_eq!(none.clipped(&big), (false, false));
        // counted with their status; the attitude goes on
        let mut p = Pipeline::new(FilterSpec::default()).with_sensor_range(r);
        p.update(&still(0.0));
        let mut turn = still(0.01);
        turn.gyr_rad_s.x = dps(250.13);
        assert_eq!(p.update(&turn).status, Status::Fused);
        let mut bump = still(0.02);
        bump.acc_m_s2.z = 2.0 * G0;
        assert_eq!(p.update(&bump).status, Status::Fused);
        let c = p.counts();
        assert_eq!((c.gyro_clipped, c.acc_clipped, c.fused), (1, 1, 2));
        assert_eq!(c.first_clipped, Some(2));
        // a clipped reading the filter does not take (its time goes back) is
        // a dropout and not counted as clipped
        let mut back = turn;
        back.t_s = 0.005;
        assert_eq!(p.update(&back).status, Status::Dropout);
        assert_eq!(p.counts().gyro_clipped, 1);
        // a calibration moves the readings, not the rails: the raw sample is judged
        let mut cal = Pipeline::new(FilterSpec::default())
            .with_sensor_range(r)
            .with_calibration(Some(crate::sensor::Calibration {
                gyro: Some(crate::sensor::TriadCalibration {
                    model: crate::sensor::TriadModel::Matrix(crate::sensor::MatrixModel {
                        bias: [dps(1.0), 0.0, 0.0],
                        ..Default::default()
                    }),
                    valid_temp_c: [-40.0, 85.0],
                }),
                accel: None,
                mag: None,
            }));
        cal.update(&still(0.0));
        cal.update(&turn);
        assert_eq!(cal.counts().gyro_clipped, 1);
    }

    #[test]
    fn time_not_after_the_last_used_sample_is_a_dropout() {
        let mut p = Pipeline::new(FilterSpec::default());
        p.update(&still(1.0));
        assert_eq!(p.update(&still(1.0)).status, Status::Dropout);
        assert_eq!(p.update(&still(0.5)).status, Status::Dropout);
        assert!(p.update(&still(1.01)).status.is_used());
    }

    #[test]
    fn waiting_until_a_usable_accelerometer() {
        let mut p = Pipeline::new(FilterSpec::default_for(FilterKind::Mahony));
        let zero = ImuSample::new(0.0, Vec3::zeros(), Vec3::zeros());
        let o = p.update(&zero);
        assert_eq!(o.status, Status::Waiting);
        assert!(o.attitude.is_none() && o.tilt().is_none());
        assert_eq!(p.update(&still(0.01)).status, Status::Initialised);
    }

    #[test]
    fn batch_equals_per_sample_to_the_bit() {
        let spec = FilterSpec::default();
        let samples: std::vec::Vec<ImuSample> = (0..500)
            .map(|k| {
                let t = k as f64 * 0.005;
                let w = Vec3::new(libm::sin(t), 0.3 * libm::cos(2.0 * t), 0.1);
                ImuSample::new(t, w, Vec3::new(0.5 * libm::sin(t), 0.2, G0))
            })
            .collect();
        let mut a = Pipeline::new(spec).with_lever_arm(Some(Vec3::new(0.5, 0.0, 0.0)));
        let mut b = a.clone();
        let one: std::vec::Vec<Output> = samples.iter().map(|s| a.update(s)).collect();
        let mut many = std::vec![
            Output {
                status: Status::Waiting,
                attitude: None
            };
            samples.len()
        ];
        assert_eq!(b.update_batch(&samples, &mut many), samples.len());
        assert_eq!(one, many);
        assert_eq!(a.counts(), b.counts());
    }

    #[test]
    fn status_names_round_trip() {
        for s in Status::ALL {
            assert_eq!(Status::from_str_name(s.as_str()), Some(s));
        }
    }

    #[test]
    fn reset_and_set_last_time_start_the_sample_clock_afresh() {
        use std::vec::Vec;
        // edge case kept: host stamps (±30 % of a 10-ms period) recovered,
        // then `reset`: the same samples again give the same outputs to the
        // bit (no statistics, period or debt of the clock survive); and
        // `set_last_time` measures the next step from the time given, to the
        // bit, whatever the clock had learnt
        let w = Vec3::new(0.0, 0.0, 0.5);
        let samples: Vec<ImuSample> = (0..1500u64)
            .map(|k| {
                let jitter = 0.003 * (2.0 * ((k * 7919 % 1000) as f64 / 1000.0) - 1.0);
                ImuSample::new(1.7e9 + k as f64 * 0.01 + jitter, w, Vec3::new(0.0, 0.0, G0))
            })
            .collect();
        let mut p = Pipeline::new(FilterSpec::default_for(FilterKind::Poisson));
        let first: Vec<Output> = samples.iter().map(|s| p.update(s)).collect();
        assert!(p.counts().retimed > 0);
        assert!(p.sample_clock().unwrap().recovering());
        let retimed = p.counts().retimed;
        p.reset();
        let again: Vec<Output> = samples.iter().map(|s| p.update(s)).collect();
        assert_eq!(first, again);
        assert_eq!(p.counts().retimed, retimed);
        let before = p.attitude().unwrap();
        let t = samples[samples.len() - 1].t_s + 3.0;
        p.set_last_time(t);
        let out = p.update(&ImuSample::new(t + 0.01, w, Vec3::new(0.0, 0.0, G0)));
        assert!(out.status.is_used());
        let q = out.attitude.unwrap();
        let turned = 2.0 * libm::atan2(q.k, q.w) - 2.0 * libm::atan2(before.k, before.w);
        assert!((turned - 0.5 * (t + 0.01 - t)).abs() < 1e-12, "{turned}");
    }
}
