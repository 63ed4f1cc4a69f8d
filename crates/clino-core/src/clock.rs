//! The sensor's sample clock, recovered from time stamps that are not its own.
//!
//! A sensor samples on its own clock: a crystal or an RC oscillator whose
//! period wanders by parts per million from one sample to the next. The
//! time stamps of a recording are often not that clock's. A host stamps
//! each sample when it arrives — after a USB bridge held it until its
//! latency timer ran out (16 ms on an FTDI chip), after the operating
//! system got round to the reading thread — and a microcontroller's loop
//! stamps it when it gets to it. Such stamps are off by milliseconds, and
//! an attitude filter that integrates the gyro over their steps turns each
//! stamp's error e into an attitude error ω·e, and its loops, rest detector
//! and period estimate see steps that were never taken.
//!
//! Whether the stamps are off the samples, or the samples themselves are
//! irregular and stamped right, shows as white phase noise differs from
//! white frequency noise in a clock. Let z_k be stamp k less its periods
//! counted (lost samples counted), and V_m the variance of z_k − z_{k−m},
//! the stamps' spread over m steps:
//!
//! * **stamps off the samples** (t_k = s_k + v_k, v of variance r, correlated
//!   over fewer than m steps): V_m = 2r whatever m;
//! * **samples really irregular, stamps right** (a loop whose period varies,
//!   s_k = s_{k−1} + T + w_k, w of variance q): V_m = m·q, growing with m.
//!
//! [`SampleClock`] measures V over lags 8–15 and 32–39 (their means V₁, V₂
//! at mean lags m₁ = 11.5, m₂ = 35.5: q = (V₂ − V₁)/(m₂ − m₁), r = (V₁ −
//! m₁·q)/2). Until they are judged ([`STATS_MIN_S`], [`STATS_MIN_SPREADS`])
//! its clock is the straight line through the stamps against the periods
//! counted; from then on a
//! Kalman filter of (the last sample's time, the period) with those noises
//! (q less the part the statistics cannot tell from zero), started from the
//! line with the line's own covariance. Once the part of r the statistics
//! can tell from zero is more than [`ENGAGE_SHARE`] of a period squared,
//! the step it gives is the difference of two recovered times. Where the
//! stamps are the sensor's (every sensor-timed recording: noise below a
//! microsecond), or the samples themselves are irregular, it stays out of
//! the way: the step is the stamps' difference, to the bit.
//!
//! A step's periods are counted on the clock. Where a stamp's standard
//! deviation σ about it is under [`RESOLVE_SHARE`] of a period T, on the odds
//! of a Gaussian against a sample lost with probability [`STEP_LOSS_PRIOR`]:
//! n + 1 rather than n past (n + ½)·T + σ²·ln(1/p)/T (and none, the last step
//! having taken one too many, below ½·T − σ²·ln(1/p)/T). Above it, only a gap
//! past [`LATE_SIGMAS`] counts: a host's late stamps have a long tail, and a
//! stamp off by more than half a period counted as a sample lost would move
//! the clock a period, and the period after it. A period missed or counted
//! too many shows on every stamp after it, a stamp off only on its own: the
//! innovations' running mean finds it where σ is under [`LAG_SHARE`] of a
//! period. Past that, a sample lost cannot be told from stamps late, and it is
//! spread over the steps after it.

//!
//! What the stamps cannot tell: samples whose period repeats a pattern,
//! stamped right (a loop that takes 8 ms and 12 ms in turn, reading the
//! sensor each time round), look like stamps off a regular clock, and are
//! put on one: each step is then off by the pattern's swing (±2 ms there),
//! which does not accumulate. Such a source wants the stamps as given
//! ([`crate::pipeline::Pipeline::with_sample_clock`], `--stamps as-given`);
//! `clino fuse` says on stderr when and how far it moved the stamps.

use crate::math;

/// The stamps' own noise (standard deviation) as a share of the period above
/// which the clock is recovered. A sensor's clock or a microcontroller's
/// timer stamps to a microsecond, under 0.1 % of any period up to 1 kHz; a
/// host's receive times are off by 0.1–16 ms, 1–160 % of a 100-Hz period.
/// At 2 % the stamps' error costs ω·e ≤ 0.6 mrad at 3 rad/s and 100 Hz,
/// below any filter's error: the threshold only decides when the stamps are
/// left exactly as they are.
pub const ENGAGE_SHARE: f64 = 0.02;

/// Below this share (the stamps' noise itself, not its significant part,
/// having fallen: a changed source) the stamps are followed again
/// (hysteresis against [`ENGAGE_SHARE`]).
pub const RELEASE_SHARE: f64 = 0.01;

/// Time over which the stamps' statistics are averaged, s: thousands of
/// steps at 100 Hz, and short against a change of source.
pub const STATS_S: f64 = 10.0;

/// Time before the stamps' noise is judged, s (and at least
/// [`STATS_MIN_SPREADS`] spreads): until then the clock is the line
/// through the stamps, and the steps given are the stamps'.
pub const STATS_MIN_S: f64 = 2.0;

/// Spreads (one a step, from the [`LONG_LAG`] + [`LAGS`]th on) before the
/// stamps' noise is judged: their standard error is then under 40 %.
pub const STATS_MIN_SPREADS: f64 = 100.0;

/// The shorter lag of the stamps' spread, steps: longer than a USB
/// packet's samples are correlated over (16 ms at 400 Hz is 6.4 steps).
/// The first this many steps count one period each.
pub const SHORT_LAG: usize = 8;

/// The longer lag, steps.
pub const LONG_LAG: usize = 32;

/// Each spread is the mean over this many lags from [`SHORT_LAG`] and from
/// [`LONG_LAG`] on: stamps whose error repeats (a 100-Hz sensor through
/// 16-ms USB packets repeats every 8 samples) would make a single lag's
/// spread vanish; eight lags in a row take every phase of a pattern up to
/// eight samples long.
pub const LAGS: usize = 8;

/// Standard errors an estimate of the stamps' noise must stand clear of
/// zero by before it is taken as more than the statistics' own scatter.
pub const SIGNIFICANCE: f64 = 3.0;

/// The stamps resolve a period where the standard deviation of a stamp about
/// the clock is below this share of it: a step's periods are then counted
/// on the odds of a Gaussian (a sample lost with probability
/// [`STEP_LOSS_PRIOR`], or the last step counted a period too many, which
/// the next stamp then shows early), and one missed or counted too many is
/// also found from the innovations' mean ([`LAG_GAIN`]).
/// Above it a host's late stamps, whose tail is long (a scheduler's: an
/// exponential's is past 3σ one time in 50), would be counted as samples
/// lost, and the period would follow: only a gap past [`LATE_SIGMAS`] counts
/// on one step, and a sample lost shows in the innovations' mean
/// ([`LAG_SHARE`]).
pub const RESOLVE_SHARE: f64 = 0.2;

/// See [`RESOLVE_SHARE`].
pub const LATE_SIGMAS: f64 = 6.0;

/// A step longer than this, s, and than [`RESTART_PERIODS`] periods,
/// restarts the clock from the stamps after it: over a dropout that long
/// the periods cannot be counted to one (a sensor clock off by 0.1 % drifts
/// a period in a thousand), and a host's clock may have been set meanwhile.
pub const RESTART_S: f64 = 1.0;

/// See [`RESTART_S`].
pub const RESTART_PERIODS: f64 = 100.0;

/// Innovations past this many standard deviations move the clock only as
/// far as one at it (a Huber filter): a stamp far late, or a period
/// miscounted, which the next count or the innovations' mean
/// ([`LAG_GAIN`]) sets right.
pub const CLIP_SIGMAS: f64 = 3.0;

/// The weight of the newest innovation in their running mean
/// ([`RESOLVE_SHARE`]): a period missed (a sample lost with its stamp late)
/// or counted too many (a stamp far late) is found within three steps.
pub const LAG_GAIN: f64 = 0.25;

/// The innovations' mean finds a period missed or counted too many where
/// the standard deviation of a stamp about the clock is below this share of
/// a period: half a period and three of the mean's own standard deviations
/// (0.38σ at [`LAG_GAIN`]) then stay inside one period. Above it a sample
/// lost is spread over the steps after it.
pub const LAG_SHARE: f64 = 0.4;

/// The prior probability of a sample lost on a step: the clock counts a
/// step's periods with it ([`RESOLVE_SHARE`]), and so do the stamps'
/// statistics, on the step alone (its own odds, Gaussian), kept apart from
/// the clock, whose counts rest on them. Miscounted there, a late stamp adds
/// a period's jump to the spreads and reads as the samples' own period
/// noise: the clock then follows the stamps more closely, never less.
pub const STEP_LOSS_PRIOR: f64 = 0.01;

/// √(LAG_GAIN/(2 − LAG_GAIN)): the innovations' running mean's standard
/// deviation in theirs.
const LAG_SPREAD: f64 = 0.377_964_473_009_227_2;

/// √m₁ and √m₂, the mean lags' roots (the spreads' standard errors).
const SQRT_SHORT: f64 = 3.391_164_991_562_634;
const SQRT_LONG: f64 = 5.958_187_643_906_492;

/// ln(1/[`STEP_LOSS_PRIOR`]), the odds' penalty of a period counted more.
const LN_LOSS_ODDS: f64 = 4.605_170_185_988_092;

/// The sensor's own frequency wander, relative, per √s: an RC oscillator's
/// drift with temperature (an MPU6050's internal clock is good to ±1 % over
/// its temperature range, and moves over minutes). It lets the period follow
/// a drifting sensor clock; a crystal's is a hundredfold smaller.
pub const FREQUENCY_WANDER: f64 = 1e-4;

/// Innovations beyond this many standard deviations while the clock is
/// recovered, or steps of more than one period, this many in a row,
/// restart it from the stamps: they have left the clock (a changed rate, a
/// host's clock stepped).
pub const OUTLIER_SIGMAS: f64 = 6.0;

/// See [`OUTLIER_SIGMAS`].
pub const OUTLIER_RUN: u32 = 5;

/// The sensor's sample clock, recovered from the time stamps (see the
/// [module](self) documentation).
///
/// ```
/// use clino_core::clock::SampleClock;
///
/// // a 100-Hz sensor stamped by a host: each stamp late by 0–8 ms
/// let mut clock = SampleClock::new();
/// let mut worst: f64 = 0.0;
/// for k in 0..3000 {
///     let late = 0.008 * (k as f64 * 0.618_034).fract();
///     let t = k as f64 * 0.01 + late;
///     if let (Some(dt), true) = (clock.step(t), k > 1000) {
///         worst = worst.max((dt - 0.01).abs());
///     }
/// }
/// assert!(clock.recovering());
/// // the stamps' steps are off by up to 8 ms; the recovered ones by 0.1 ms
/// assert!(worst < 1e-4, "{worst}");
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SampleClock {
    /// The last stamp taken (NaN before the first).
    last_t: f64,
    /// Steps so far, and their time.
    steps: f64,
    time: f64,
    /// The clock: the last sample's time and the period.
    phase: f64,
    period: f64,
    /// The line through the stamps until they are judged: the first stamp,
    /// periods counted, and the sums of count, time, count², count·time and
    /// time² (time from the first stamp).
    first: f64,
    count: f64,
    sums: [f64; 5],
    /// Covariance of (phase, period) once tracked: pss, psT, pTT.
    p: [f64; 3],
    /// The steps' running mean, their period (mean over mean periods
    /// counted), their mean square deviation from it (winsorised at half a
    /// period), the mean periods, and the mean square deviation itself.
    stats: [f64; 5],
    /// The stamps' deviation from the steps' periods, z (the last
    /// [`LONG_LAG`] + 1, a ring), and the next slot.
    z: [f64; LONG_LAG + LAGS],
    next: usize,
    /// Running V₁ and V₂ (the mean spreads over lags 8–15 and 32–39).
    v_short: f64,
    v_long: f64,
    /// The steps given are the recovered clock's (not the stamps').
    on: bool,
    /// Innovations beyond [`OUTLIER_SIGMAS`] in a row, and steps of more
    /// than one period in a row.
    outliers: u32,
    lost_run: u32,
    /// Times the stamps left the clock and it started again.
    restarts: u32,
    /// The stamps' noise after the last step ([`SampleClock::noise`]).
    noise: (f64, f64, f64, f64),
    /// √r as judged before the clock last started again (0: never).
    jitter_before: f64,
    /// The innovations' running mean over the last few steps
    /// ([`LAG_GAIN`]).
    lag: f64,
    /// Time the steps given are ahead of the recovered clock, s (≤ 0:
    /// owed by the steps to come).
    owed: f64,
}

impl Default for SampleClock {
    fn default() -> Self {
        Self::new()
    }
}

impl SampleClock {
    /// A clock that has seen no stamp.
    pub const fn new() -> Self {
        Self {
            last_t: f64::NAN,
            steps: 0.0,
            time: 0.0,
            phase: 0.0,
            period: 0.0,
            first: 0.0,
            count: 0.0,
            sums: [0.0; 5],
            p: [0.0; 3],
            stats: [0.0; 5],
            z: [0.0; LONG_LAG + LAGS],
            next: 0,
            v_short: 0.0,
            v_long: 0.0,
            on: false,
            outliers: 0,
            lost_run: 0,
            restarts: 0,
            noise: (0.0, 0.0, 0.0, 0.0),
            jitter_before: 0.0,
            lag: 0.0,
            owed: 0.0,
        }
    }

    /// Take the stamp `t` of the next sample; the step since the last
    /// sample's recovered time, s (the stamps' own step while they are
    /// followed). `None` for the first stamp, and for a stamp not after the
    /// last or not finite (the caller drops that sample: the clock is
    /// unchanged).
    pub fn step(&mut self, t: f64) -> Option<f64> {
        if !t.is_finite() {
            return None;
        }
        if self.last_t.is_nan() {
            self.last_t = t;
            self.phase = t;
            self.first = t;
            return None;
        }
        let (prev, d) = (self.last_t, t - self.last_t);
        if d <= 0.0 {
            return None;
        }
        if d > RESTART_S && self.steps == 0.0 {
            // no period yet (a rate under 1 Hz): the next step is the first
            self.last_t = t;
            self.phase = t;
            self.first = t;
            return Some(d);
        }
        if d > RESTART_S && d > RESTART_PERIODS * self.period {
            // a step this long carries no clock: counted from the stamps
            // after it, afresh (the step itself is the stamps')
            return Some(self.restart(t, d));
        }
        self.last_t = t;
        self.steps += 1.0;
        self.time += d;
        let was_judged = self.judged();
        // the periods since the last sample, and any the clock ran ahead by
        let (n, back) = if self.steps <= SHORT_LAG as f64 {
            (1.0, 0.0)
        } else {
            // σ² the variance of the stamp about the clock's prediction
            let var = if was_judged {
                let (r, _, _, q) = self.noise();
                r + q + self.p[0]
            } else {
                // half a step's spread: a stamp's variance (the line's own
                // residuals would hold every period it missed, a staircase)
                0.5 * self.stats[4]
            };
            let c = self.count_periods(t - self.phase, var);
            if c < 1.0 { (1.0, 1.0 - c) } else { (c, 0.0) }
        };
        let before = self.phase;
        if back > 0.0 {
            // the last step was counted a period too many: undone
            self.phase -= back * self.period;
            if !was_judged {
                self.uncount(prev, back);
            }
        }
        self.lost_run = if n > 1.0 { self.lost_run + 1 } else { 0 };
        if self.lost_run >= OUTLIER_RUN {
            // every step more than one period: the rate was lowered
            return Some(self.restart(t, d));
        }
        self.learn(d);
        if !was_judged {
            self.fit(t, n);
            if self.judged() {
                self.start_tracking();
            }
            return Some(d);
        }
        if !self.track(t, n) {
            return Some(self.restart(t, d));
        }
        // on when the part of r the statistics can tell from zero is past
        // ENGAGE_SHARE of a period, off when r itself falls below
        // RELEASE_SHARE
        let (r, _, r_sig, _) = self.noise();
        let (on_at, off_at) = (ENGAGE_SHARE * self.period, RELEASE_SHARE * self.period);
        if !self.on && r_sig > on_at * on_at {
            self.on = true;
            self.outliers = 0;
            return Some(d);
        }
        if self.on && r < off_at * off_at {
            self.on = false;
            self.owed = 0.0;
        }
        if !self.on {
            return Some(d);
        }
        // a step is at least half a period: time a correction takes back
        // beyond that (a period counted too many) is taken from the steps
        // after it, so that the steps given add up to the recovered time
        let step = self.phase - before + self.owed;
        let least = 0.5 * self.period;
        self.owed = (step - least).min(0.0);
        Some(step.max(least))
    }

    /// Whether the sample times are being recovered (the stamps are off
    /// the sensor's clock by more than [`ENGAGE_SHARE`] of a period).
    pub fn recovering(&self) -> bool {
        self.on
    }

    /// The stamps' own noise, s: the standard deviation of a stamp about
    /// its sample's time, √r (until the stamps are judged: as judged before
    /// the clock last started again, or 0).
    pub fn jitter(&self) -> f64 {
        if self.judged() {
            math::sqrt(self.noise().0)
        } else {
            self.jitter_before
        }
    }

    /// The sample period, s (0 before any step).
    pub fn period(&self) -> f64 {
        self.period
    }

    /// Times the stamps left the recovered clock and it started again from
    /// them (a changed rate, a host's clock stepped).
    pub fn restarts(&self) -> u32 {
        self.restarts
    }

    fn judged(&self) -> bool {
        self.steps >= (LONG_LAG + LAGS) as f64 + STATS_MIN_SPREADS && self.time >= STATS_MIN_S
    }

    /// The stamps' noise as [`SampleClock::compute_noise`] made it after the
    /// last step.
    fn noise(&self) -> (f64, f64, f64, f64) {
        self.noise
    }

    /// The stamps' noise r and the samples' own period noise q, s², from
    /// V₁ and V₂, each also less [`SIGNIFICANCE`] standard errors (the
    /// part the statistics can tell from zero): (r, q, r_sig, q_sig).
    fn compute_noise(&self) -> (f64, f64, f64, f64) {
        if !self.judged() {
            return (0.0, 0.0, 0.0, 0.0);
        }
        // the mean lag of each set
        let mid = 0.5 * (LAGS as f64 - 1.0);
        let (m1, m2) = (SHORT_LAG as f64 + mid, LONG_LAG as f64 + mid);
        let q = ((self.v_long - self.v_short) / (m2 - m1)).max(0.0);
        let r = ((self.v_short - m1 * q) / 2.0).max(0.0);
        // a running variance over n_eff steps of overlapping m-step spreads
        // has a relative standard error of about √(2m/n_eff)
        let n_eff = (self.steps - LONG_LAG as f64).min(2.0 * STATS_S / self.stats[1]);
        let k = math::sqrt(2.0 / n_eff);
        let (a, b) = (self.v_long * k * SQRT_LONG, self.v_short * k * SQRT_SHORT);
        let se_q = math::sqrt(a * a + b * b) / (m2 - m1);
        let se_r = 0.5 * math::sqrt(m1 * m1 * se_q * se_q + b * b);
        (
            r,
            q,
            (r - SIGNIFICANCE * se_r).max(0.0),
            (q - SIGNIFICANCE * se_q).max(0.0),
        )
    }

    /// The stamps' statistics, kept apart from the clock (whose counts rest
    /// on them): the steps' own period (their time over the periods they
    /// count), their spread about it, and the spreads of z over the two
    /// lags. A step's periods are counted on the step alone, as
    /// [`SampleClock::count_periods`] counts on the clock, the step's
    /// variance being the spread.
    fn learn(&mut self, d: f64) {
        let h = self.stats[1];
        let n = if self.steps <= SHORT_LAG as f64 {
            1.0
        } else {
            // n + 1 rather than n past (n + ½)·T + σ²·ln(1/p)/T: the odds of
            // a Gaussian step of variance σ² (the spread) against a sample
            // lost with probability p = STEP_LOSS_PRIOR
            let shift = self.stats[4] * LN_LOSS_ODDS / h;
            libm::round((d - shift) / h).max(1.0)
        };
        let w = (1.0 / self.steps).max(h / STATS_S);
        let [span, _, spread, periods, raw_spread] = &mut self.stats;
        *span += w * (d - *span);
        *periods += w * (n - *periods);
        let h = *span / *periods;
        let e = d - n * h;
        // winsorised at half a period: a period missed counts as half of one
        let c = e.max(-0.5 * h).min(0.5 * h);
        *spread += w * (c * c - *spread);
        *raw_spread += w * (e * e - *raw_spread);
        self.stats[1] = h;
        const RING: usize = LONG_LAG + LAGS;
        let z = self.z[(self.next + RING - 1) % RING] + e;
        self.z[self.next] = z;
        if self.steps >= RING as f64 {
            let w = (1.0 / (self.steps + 1.0 - RING as f64)).max(h / STATS_S);
            let spread = |lag: usize| {
                (lag..lag + LAGS)
                    .map(|m| {
                        let x = z - self.z[(self.next + RING - m) % RING];
                        x * x
                    })
                    .sum::<f64>()
                    / LAGS as f64
            };
            let (short, long) = (spread(SHORT_LAG), spread(LONG_LAG));
            self.v_short += w * (short - self.v_short);
            self.v_long += w * (long - self.v_long);
        }
        self.next = (self.next + 1) % RING;
        self.noise = self.compute_noise();
    }

    /// The periods between the last sample's time on the clock and a stamp
    /// `x` after it, the stamp's variance about the clock being `var` (see
    /// the [module](self) documentation): none where the last step took one
    /// too many.
    fn count_periods(&self, x: f64, var: f64) -> f64 {
        let h = self.period;
        let resolve = RESOLVE_SHARE * h;
        if var >= resolve * resolve {
            // periods cannot be told apart: an obvious gap only
            let sigma = math::sqrt(var);
            return if x > 1.5 * h + LATE_SIGMAS * sigma {
                libm::round((x - LATE_SIGMAS * sigma) / h).max(2.0)
            } else {
                1.0
            };
        }
        let shift = var * LN_LOSS_ODDS / h;
        if x > 1.5 * h + shift {
            libm::round((x - shift) / h).max(2.0)
        } else if x < 0.5 * h - shift {
            0.0
        } else {
            1.0
        }
    }

    /// The last stamp (at `prev`) was counted `back` periods too many: its
    /// point on the line moves back.
    fn uncount(&mut self, prev: f64, back: f64) {
        let (k, tau) = (self.count, prev - self.first);
        let [sk, _, skk, skt, _] = &mut self.sums;
        *sk -= back;
        *skk += (k - back) * (k - back) - k * k;
        *skt -= back * tau;
        self.count -= back;
    }

    /// The least-squares line through the stamps against the periods
    /// counted, the first stamp at count 0: its slope the period, its value
    /// at the last count the phase.
    fn fit(&mut self, t: f64, n: f64) {
        self.count += n;
        let (k, tau) = (self.count, t - self.first);
        let [sk, st, skk, skt, stt] = &mut self.sums;
        *sk += k;
        *st += tau;
        *skk += k * k;
        *skt += k * tau;
        *stt += tau * tau;
        let m = self.steps + 1.0;
        let den = m * *skk - *sk * *sk;
        if den > 0.0 {
            self.period = (m * *skt - *sk * *st) / den;
            let icpt = (*st - self.period * *sk) / m;
            self.phase = self.first + icpt + self.period * k;
        } else {
            self.period = tau / k;
            self.phase = t;
        }
    }

    /// The variance of the stamps about the line, s² (its residuals' sum of
    /// squares over the degrees of freedom; 0 before three stamps).
    fn line_noise(&self) -> f64 {
        let m = self.steps + 1.0;
        if m < 3.0 {
            return 0.0;
        }
        let [sk, st, skk, skt, stt] = self.sums;
        let (kk, kt, tt) = (skk - sk * sk / m, skt - sk * st / m, stt - st * st / m);
        if kk <= 0.0 {
            return 0.0;
        }
        ((tt - kt * kt / kk) / (m - 2.0)).max(0.0)
    }

    /// The Kalman filter starts from the line: its phase at the last count
    /// and its slope, with the line's covariance (residual variance σ², m
    /// stamps over a spread S of counts: the slope's σ²/S, the end's
    /// σ²·(1/m + (k − k̄)²/S), their covariance σ²·(k − k̄)/S).
    fn start_tracking(&mut self) {
        let m = self.steps + 1.0;
        let [sk, _, skk, _, _] = self.sums;
        let spread = skk - sk * sk / m;
        let var = self.line_noise();
        if spread > 0.0 {
            let dk = self.count - sk / m;
            self.p = [
                var * (1.0 / m + dk * dk / spread),
                var * dk / spread,
                var / spread,
            ];
        }
    }

    /// One Kalman step of (phase, period) to the stamp `t`, `n` periods on:
    /// the phase a random walk of the samples' own period noise q, the
    /// period one of [`FREQUENCY_WANDER`], the stamp the phase plus noise of
    /// variance r. False when the stamps left it: [`OUTLIER_RUN`]
    /// innovations in a row beyond [`OUTLIER_SIGMAS`] while recovering.
    fn track(&mut self, t: f64, n: f64) -> bool {
        let (r, _, _, q) = self.noise();
        let h = self.period;
        let q_period = {
            let w = FREQUENCY_WANDER * h;
            w * w * h
        };
        let [pss, pst, ptt] = self.p;
        let pss = pss + 2.0 * n * pst + n * n * ptt + n * q;
        let pst = pst + n * ptt;
        let ptt = ptt + n * q_period;
        let mut predicted = self.phase + n * h;
        let mut innovation = t - predicted;
        let s = pss + r;
        // a period missed or counted too many shows on every stamp after it,
        // a stamp off only on its own: where the stamps resolve a period,
        // the innovations' mean over the last few steps past half a period
        // (and three of its own standard deviations) moves the clock by it
        let (rr, q_all, _, _) = self.noise();
        let var = rr + q_all + pss;
        self.lag += LAG_GAIN * (innovation - self.lag);
        let resolve = LAG_SHARE * h;
        if var < resolve * resolve && self.lag.abs() > 0.5 * h + 3.0 * LAG_SPREAD * math::sqrt(var)
        {
            let periods = libm::round(self.lag / h);
            predicted += periods * h;
            innovation -= periods * h;
            self.lag -= periods * h;
        }
        self.outliers = if self.on && innovation * innovation > OUTLIER_SIGMAS * OUTLIER_SIGMAS * s
        {
            self.outliers + 1
        } else {
            0
        };
        if self.outliers >= OUTLIER_RUN {
            return false;
        }
        let (ks, kt) = if s > 0.0 {
            (pss / s, pst / s)
        } else {
            (1.0, 0.0)
        };
        // an innovation past CLIP_SIGMAS moves the clock only as far as one
        // at it: a stamp far late, or a period miscounted, until the next
        // count or the innovations' mean sets it right
        let bound = CLIP_SIGMAS * math::sqrt(s);
        let innovation = innovation.max(-bound).min(bound);
        self.phase = predicted + ks * innovation;
        self.period = h + kt * innovation;
        self.p = [(1.0 - ks) * pss, (1.0 - ks) * pst, ptt - kt * pst];
        true
    }

    /// The same clock to run over the same stamps again from their start,
    /// for a whole recording held (offline): the stamps' statistics kept,
    /// judged and, if it was recovering, recovering from the first stamp on
    /// (a clock run once recovers only after [`STATS_MIN_S`] and the
    /// statistics' significance, 5–20 s of host stamps). The period and its
    /// variance are the last ones; the first recovered time is the first
    /// stamp, off by the stamps' noise. A clock that started again (its
    /// statistics are of the last stretch only) or never judged its stamps
    /// primes nothing: a new clock, which runs as the first did.
    pub fn primed(&self) -> Self {
        if self.restarts > 0 || !self.judged() {
            // the statistics are of the last stretch only (a changed rate, a
            // host's clock stepped), or there are none: nothing to prime
            return Self::new();
        }
        let (r, ..) = self.noise();
        Self {
            last_t: f64::NAN,
            phase: 0.0,
            first: 0.0,
            count: 0.0,
            sums: [0.0; 5],
            p: [r, 0.0, self.p[2]],
            outliers: 0,
            lost_run: 0,
            lag: 0.0,
            owed: 0.0,
            ..*self
        }
    }

    /// A clock to run over a whole recording's `stamps` (offline): run over
    /// them once, [`SampleClock::primed`] where it recovered them, a new
    /// clock where it did not (its steps are then the stamps', to the bit).
    pub fn primed_over<I: IntoIterator<Item = f64>>(stamps: I) -> Self {
        let mut once = Self::new();
        let mut recovered = false;
        for t in stamps {
            once.step(t);
            recovered |= once.recovering();
        }
        if recovered {
            once.primed()
        } else {
            Self::new()
        }
    }

    /// The stamps left the clock (a changed rate, a host's clock stepped):
    /// follow them from the stamp `t` and judge them afresh; the stamps'
    /// step `d`.
    fn restart(&mut self, t: f64, d: f64) -> f64 {
        *self = Self {
            last_t: t,
            phase: t,
            first: t,
            restarts: self.restarts + 1,
            jitter_before: self.jitter(),
            ..Self::new()
        };
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::vec::Vec;

    /// A uniform number in [0, 1) for `k` (a fixed scrambled sequence).
    fn u(k: u64) -> f64 {
        let mut z = k
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(0x6A09_E667);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Stamps never before the one before (a host's receive times).
    fn monotone(mut v: Vec<f64>) -> Vec<f64> {
        for k in 1..v.len() {
            v[k] = v[k].max(v[k - 1] + 1e-6);
        }
        v
    }

    /// The clock over `stamps` of the samples at `s`: the RMS error of the
    /// stamps and of the recovered times (stamp 0 plus the steps given)
    /// against the samples' times after the first 20 s, each about its mean
    /// (a constant delay changes no step); the share of those steps
    /// recovered; the clock; the steps given.
    fn run(s: &[f64], stamps: &[f64]) -> (f64, f64, f64, SampleClock, Vec<f64>) {
        let mut c = SampleClock::new();
        let mut acc = stamps[0];
        let (mut raw, mut rec, mut on, mut steps) = (Vec::new(), Vec::new(), 0.0, Vec::new());
        for (k, &t) in stamps.iter().enumerate() {
            if let Some(d) = c.step(t) {
                acc += d;
                steps.push(d);
            }
            if s[k] - s[0] > 20.0 {
                raw.push(t - s[k]);
                rec.push(acc - s[k]);
                on += f64::from(u8::from(c.recovering()));
            }
        }
        let rms = |e: &[f64]| {
            let m = e.iter().sum::<f64>() / e.len() as f64;
            (e.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / e.len() as f64).sqrt()
        };
        let share = on / raw.len() as f64;
        (rms(&raw), rms(&rec), share, c, steps)
    }

    /// Sample times at `rate` for 120 s.
    fn times(rate: f64) -> Vec<f64> {
        (0..(120.0 * rate) as usize)
            .map(|k| 5.0 + k as f64 / rate)
            .collect()
    }

    #[test]
    fn the_derived_constants_are_what_they_say() {
        let mid = 0.5 * (LAGS as f64 - 1.0);
        assert_eq!(SQRT_SHORT, (SHORT_LAG as f64 + mid).sqrt());
        assert_eq!(SQRT_LONG, (LONG_LAG as f64 + mid).sqrt());
        assert_eq!(LAG_SPREAD, (LAG_GAIN / (2.0 - LAG_GAIN)).sqrt());
        assert_eq!(LN_LOSS_ODDS, (1.0 / STEP_LOSS_PRIOR).ln());
    }

    #[test]
    fn a_sensors_own_stamps_are_its_steps_to_the_bit() {
        // k/rate at 285.714 Hz (BROAD's), 1 kHz, 25 Hz; time from the epoch
        for (rate, t0) in [(285.714, 3.0), (1000.0, 0.0), (25.0, 1.7e9)] {
            let t: Vec<f64> = (0..(60.0 * rate) as usize)
                .map(|k| t0 + k as f64 / rate)
                .collect();
            let (_, _, on, c, d) = run(&t, &t);
            assert_eq!(on, 0.0, "{rate}");
            assert_eq!(c.restarts(), 0, "{rate}");
            for (k, dk) in d.iter().enumerate() {
                assert_eq!(dk.to_bits(), (t[k + 1] - t[k]).to_bits(), "{rate} {k}");
            }
        }
    }

    /// Host stamps of the samples `s` (rate `rate`), three ways: off by up
    /// to ±45 % of a period; late by 0–8 ms (exponential, mean 2 ms); in
    /// 16-ms USB packets, every sample stamped at its packet's arrival.
    fn host_stamps(s: &[f64], rate: f64) -> [(&'static str, Vec<f64>); 3] {
        let h = 1.0 / rate;
        let n = s.len();
        [
            (
                "±45 %",
                monotone(
                    (0..n)
                        .map(|k| s[k] + 0.45 * h * (2.0 * u(k as u64) - 1.0))
                        .collect(),
                ),
            ),
            (
                "late 0–8 ms",
                monotone(
                    (0..n)
                        .map(|k| s[k] + (-0.002 * (1.0 - u(k as u64)).ln()).min(0.008))
                        .collect(),
                ),
            ),
            (
                "16-ms packets",
                monotone(
                    (0..n)
                        .map(|k| {
                            let packet = (s[k] / 0.016).floor();
                            (packet + 1.0) * 0.016 + 1e-3 * u(packet as u64) + 20e-6 * u(k as u64)
                        })
                        .collect(),
                ),
            ),
        ]
    }

    #[test]
    fn host_stamps_are_put_back_on_the_sensors_clock() {
        // measured: the recovered times are off by 0.07, 0.08 and 0.02 of
        // the stamps' error at 100 Hz, 0.06, 0.07 and 0.01 at 1 kHz; at
        // 25 Hz the late stamps (4 % of a period) are left alone
        for (rate, better) in [(25.0, 1.0), (100.0, 10.0), (1000.0, 10.0)] {
            let s = times(rate);
            for (name, stamps) in host_stamps(&s, rate) {
                let (raw, rec, on, c, d) = run(&s, &stamps);
                assert_eq!(c.restarts(), 0, "{rate} {name}");
                if rate == 25.0 && name.starts_with("late") {
                    assert_eq!(on, 0.0, "{name}");
                    assert!(rec <= raw, "{rate} {name}: {rec} against {raw}");
                    continue;
                }
                assert!(on > 0.95, "{rate} {name}: {on}");
                assert!(
                    (c.period() * rate - 1.0).abs() < 1e-3,
                    "{rate} {name}: {}",
                    c.period()
                );
                // the stamps' noise as identified (√r from the spreads),
                // against the stamps' own RMS about the samples: measured
                // 0.97–1.05
                let j = c.jitter() / raw;
                assert!((j - 1.0).abs() < 0.08, "{rate} {name}: {j}");
                assert!(rec < raw / better, "{rate} {name}: {rec} against {raw}");
                // every step given after the first 20 s is one period, to 5 %
                let worst = d[(25.0 * rate) as usize..]
                    .iter()
                    .map(|dk| (dk * rate - 1.0).abs())
                    .fold(0.0, f64::max);
                assert!(worst < 0.05, "{rate} {name}: {worst}");
            }
        }
    }

    #[test]
    fn stamps_of_really_irregular_samples_are_followed() {
        // a loop whose period varies by ±20 % (independent steps), each
        // sample stamped right: the steps given are the stamps' own
        for rate in [25.0, 100.0, 1000.0] {
            let mut s = std::vec![0.0];
            for k in 1..(120.0 * rate) as u64 {
                let last = s[s.len() - 1];
                s.push(last + (1.0 + 0.4 * (u(k) - 0.5)) / rate);
            }
            let (_, _, on, _, d) = run(&s, &s);
            assert_eq!(on, 0.0, "{rate}");
            for (k, dk) in d.iter().enumerate() {
                assert_eq!(*dk, s[k + 1] - s[k], "{rate} {k}");
            }
        }
    }

    #[test]
    fn samples_lost_between_jittered_stamps_are_counted() {
        // 100 Hz, stamps off by ±10 % of a period (a radio link's receive
        // times), every 50th sample lost
        let h = 0.01;
        let kept: Vec<u64> = (0..12_000).filter(|k| k % 50 != 49).collect();
        let s: Vec<f64> = kept.iter().map(|&k| k as f64 * h).collect();
        let stamps: Vec<f64> = kept
            .iter()
            .map(|&k| k as f64 * h + 0.1 * h * (2.0 * u(k) - 1.0))
            .collect();
        let (raw, rec, on, _, d) = run(&s, &stamps);
        assert!(on > 0.95, "{on}");
        assert!(rec < raw / 5.0, "{rec} against {raw}");
        for (j, dk) in d.iter().enumerate().skip(2000) {
            let periods = (kept[j + 1] - kept[j]) as f64;
            assert!((dk - periods * h).abs() < 0.05 * h, "{j}: {dk}");
        }
    }

    #[test]
    fn stamps_off_and_samples_lost_beyond_telling_apart_do_no_harm() {
        // ±30 % and every 50th sample lost: a stamp a period late and a
        // sample lost look alike on one step, and the lost samples are not
        // counted but spread over the steps after them. At 100 Hz and 1 kHz
        // the recovered times are still closer to the samples than the
        // stamps; at 25 Hz, where the statistics cannot yet tell the losses
        // from the samples' own period noise, they are 1.7 times further off
        // (11.7 ms against 6.9 ms RMS, measured): the limit of what stamps
        // alone can tell.
        for (rate, worse) in [(25.0, 2.0), (100.0, 1.0), (1000.0, 1.0)] {
            let h = 1.0 / rate;
            let kept: Vec<u64> = (0..(120.0 * rate) as u64)
                .filter(|k| k % 50 != 49)
                .collect();
            let s: Vec<f64> = kept.iter().map(|&k| k as f64 * h).collect();
            let stamps = monotone(
                kept.iter()
                    .map(|&k| k as f64 * h + 0.3 * h * (2.0 * u(k) - 1.0))
                    .collect(),
            );
            let (raw, rec, _, _, _) = run(&s, &stamps);
            assert!(rec <= raw * worse, "{rate}: {rec} against {raw}");
        }
    }

    #[test]
    fn a_changed_rate_is_followed() {
        // 100 Hz with jittered stamps for 30 s, then 40 Hz: the clock starts
        // again from the stamps, and the steps are the new period
        let mut stamps = Vec::new();
        for k in 0..3000u64 {
            stamps.push(k as f64 * 0.01 + 0.003 * (2.0 * u(k) - 1.0));
        }
        for k in 1..1200u64 {
            stamps.push(30.0 + k as f64 * 0.025 + 0.003 * (2.0 * u(k + 7777) - 1.0));
        }
        let (_, _, _, c, d) = run(&stamps, &stamps);
        assert!(c.restarts() >= 1);
        assert!((c.period() - 0.025).abs() < 1e-4, "{}", c.period());
        let worst = d[d.len() - 500..]
            .iter()
            .map(|dk| (dk - 0.025).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-3, "{worst}");
    }

    #[test]
    fn a_stamp_not_after_the_last_leaves_the_clock_as_it_was() {
        let mut c = SampleClock::new();
        assert_eq!(c.step(1.0), None);
        assert_eq!(c.step(1.01), Some(1.01 - 1.0));
        let before = c;
        assert_eq!(c.step(1.01), None);
        assert_eq!(c.step(0.5), None);
        assert_eq!(c.step(f64::NAN), None);
        assert_eq!(c.step(f64::INFINITY), None);
        assert_eq!(c, before);
    }

    #[test]
    fn no_kind_of_stamps_at_any_rate_is_made_worse() {
        // host stamps three ways (host_stamps), and stamps off by ±10 %,
        // ±30 % or late by 0–8 ms with every 50th sample lost, at 25, 100,
        // 125, 200 and 1000 Hz: the recovered times are no further off the
        // samples than the stamps (measured: 0.01–0.85 of the stamps' error
        // where recovered, but for one case below; the stamps' own where
        // left alone)
        for rate in [25.0, 100.0, 125.0, 200.0, 1000.0] {
            let s = times(rate);
            let h = 1.0 / rate;
            let mut cases: Vec<(&str, Vec<f64>, Vec<f64>)> = host_stamps(&s, rate)
                .into_iter()
                .map(|(n, v)| (n, s.clone(), v))
                .collect();
            let kept: Vec<u64> = (0..(120.0 * rate) as u64)
                .filter(|k| k % 50 != 49)
                .collect();
            let lossy: Vec<f64> = kept.iter().map(|&k| 5.0 + k as f64 * h).collect();
            for (name, j) in [("±10 %, 2 % lost", 0.1), ("±30 %, 2 % lost", 0.3)] {
                let stamps = kept
                    .iter()
                    .map(|&k| 5.0 + k as f64 * h + j * h * (2.0 * u(k) - 1.0))
                    .collect();
                cases.push((name, lossy.clone(), monotone(stamps)));
            }
            let late = kept
                .iter()
                .map(|&k| 5.0 + k as f64 * h + (-0.002 * (1.0 - u(k)).ln()).min(0.008))
                .collect();
            cases.push(("late 0–8 ms, 2 % lost", lossy.clone(), monotone(late)));
            for (name, s, stamps) in &cases {
                let (raw, rec, _, c, _) = run(s, stamps);
                // late stamps with samples lost at 125 Hz (the late tail a
                // quarter of a period, past what one step resolves): each
                // lost sample is found from the innovations' mean a few steps
                // on, 1.23 times the stamps' error in time (the filter still
                // gains: generalise --only stamps, 0.161° against 0.202°)
                let bound = if rate == 125.0 && name.starts_with("late") && name.ends_with("lost") {
                    1.3
                } else {
                    1.0
                };
                assert!(rec <= raw * bound, "{rate} {name}: {rec} against {raw}");
                assert_eq!(c.restarts(), 0, "{rate} {name}");
            }
        }
    }

    #[test]
    fn a_long_dropout_starts_the_clock_again() {
        // 100 Hz host stamps (±30 %), a 1000-s hole, then the same again
        let mut c = SampleClock::new();
        let mut steps = Vec::new();
        for k in 0..12_000u64 {
            let t = k as f64 * 0.01 + if k >= 6000 { 1000.0 } else { 0.0 };
            steps.push(c.step(t + 0.003 * (2.0 * u(k) - 1.0)));
        }
        assert_eq!(c.restarts(), 1);
        let gap = steps[6000].unwrap();
        assert!((gap - 1000.01).abs() < 0.01, "{gap}");
        // recovered again after the hole
        assert!(c.recovering());
        for d in &steps[9000..] {
            assert!((d.unwrap() - 0.01).abs() < 5e-4, "{d:?}");
        }
    }

    proptest::proptest! {
        #[test]
        fn every_step_given_is_positive_and_finite(
            raw in proptest::collection::vec((1e-6f64..10.0, 0u8..4), 1..600),
        ) {
            // steps of any length, some repeated, some a thousandth
            let mut c = SampleClock::new();
            let mut t = 1.7e9;
            for (d, kind) in raw {
                t += match kind {
                    0 => d,
                    1 => 0.01,
                    2 => 0.01 * (1.0 + 0.4 * (d / 10.0 - 0.5)),
                    _ => d * 1e-3,
                };
                if let Some(step) = c.step(t) {
                    proptest::prop_assert!(step.is_finite() && step > 0.0, "{step}");
                }
            }
        }
    }

    #[test]
    fn a_period_that_repeats_a_pattern_is_the_limit_and_stays_bounded() {
        // a loop taking 8 ms and 12 ms in turn, each sample stamped right:
        // the stamps cannot tell it from a 10-ms clock stamped ±2 ms off,
        // and the steps are put on one; each is off by the swing, and the
        // recovered time never drifts from the samples'
        let mut s = std::vec![0.0];
        for k in 1..12_000 {
            let last = s[s.len() - 1];
            s.push(last + if k % 2 == 0 { 0.008 } else { 0.012 });
        }
        let (raw, rec, on, _, d) = run(&s, &s);
        // measured: recovered throughout, 1.0 ms RMS off the samples' times
        assert_eq!(raw, 0.0);
        assert_eq!(on, 1.0);
        for (k, dk) in d.iter().enumerate().skip(4000) {
            assert!((dk - (s[k + 1] - s[k])).abs() < 2.5e-3, "{k}: {dk}");
        }
        assert!(rec < 1.5e-3, "{rec}");
    }

    #[test]
    fn a_primed_clock_recovers_from_the_first_stamp() {
        // 100 Hz stamped late by 0–8 ms: run once, the clock recovers after
        // some seconds; primed with what it learnt and run again, from the
        // second stamp on, the first 20 s as well as the rest
        let s = times(100.0);
        let [_, (_, late), _] = host_stamps(&s, 100.0);
        let mut once = SampleClock::new();
        let mut first_on = None;
        for (k, &t) in late.iter().enumerate() {
            once.step(t);
            if once.recovering() && first_on.is_none() {
                first_on = Some(k);
            }
        }
        assert!(first_on.unwrap() > 200, "{first_on:?}");
        let mut again = once.primed();
        let mut acc = late[0];
        let (mut e, mut r) = (Vec::new(), Vec::new());
        for (k, &t) in late.iter().enumerate() {
            if let Some(d) = again.step(t) {
                assert!(again.recovering(), "{k}");
                acc += d;
            }
            if s[k] - s[0] < 20.0 {
                e.push(acc - s[k]);
                r.push(t - s[k]);
            }
        }
        let rms = |x: &[f64]| {
            let m = x.iter().sum::<f64>() / x.len() as f64;
            (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / x.len() as f64).sqrt()
        };
        // measured: recovered after 7 s when run once; primed, 0.09 of the
        // stamps' error over the first 20 s (0.08 over the whole recording)
        assert!(rms(&e) < 0.15 * rms(&r), "{} against {}", rms(&e), rms(&r));
        // a sensor's own stamps: primed, still the stamps' steps to the bit
        let mut own = SampleClock::new();
        for &t in &s {
            own.step(t);
        }
        let mut own = own.primed();
        own.step(s[0]);
        for k in 1..s.len() {
            assert_eq!(own.step(s[k]), Some(s[k] - s[k - 1]), "{k}");
        }
    }

    /// The recovered times (stamp 0 plus the steps given) less the samples'
    /// times `s`, both from their first (a constant delay changes no step).
    fn errors(c: &mut SampleClock, s: &[f64], stamps: &[f64]) -> Vec<f64> {
        let mut acc = stamps[0];
        let mut e = Vec::new();
        for (k, &t) in stamps.iter().enumerate() {
            if let Some(d) = c.step(t) {
                assert!(d.is_finite() && d > 0.0, "{k}: {d}");
                acc += d;
            }
            e.push((acc - stamps[0]) - (s[k] - s[0]));
        }
        e
    }

    #[test]
    fn eight_kilohertz_host_stamps_in_epoch_seconds_are_recovered() {
        // edge case kept: a period of 125 µs against stamps whose ulp is
        // 0.24 µs; stamps off by ±30 % are recovered, the period to 1e-3
        let (rate, t0) = (8000.0, 1.7e9);
        let h = 1.0 / rate;
        let s: Vec<f64> = (0..(30.0 * rate) as u64)
            .map(|k| t0 + k as f64 * h)
            .collect();
        let stamps: Vec<f64> = s
            .iter()
            .enumerate()
            .map(|(k, x)| x + 0.3 * h * (2.0 * u(k as u64) - 1.0))
            .collect();
        let mut c = SampleClock::new();
        let e = errors(&mut c, &s, &stamps);
        assert!(c.recovering());
        assert_eq!(c.restarts(), 0);
        assert!((c.period() * rate - 1.0).abs() < 1e-3, "{}", c.period());
        let worst = e[(20.0 * rate) as usize..]
            .iter()
            .map(|x| (x - e[e.len() - 1]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 0.25 * h, "{}", worst / h);
    }

    #[test]
    fn a_rate_under_one_hertz_is_not_a_restart_on_every_step() {
        // a 0.5-Hz logger's own stamps: a step past RESTART_S before any
        // period is known is no restart (once counted one, every stamp of
        // a rate under 1 Hz was one), and the steps are the stamps'
        let mut c = SampleClock::new();
        for k in 0..100 {
            if let Some(d) = c.step(1.7e9 + 2.0 * k as f64) {
                assert_eq!(d, 2.0);
            }
        }
        assert_eq!(c.restarts(), 0);
    }

    #[test]
    fn an_obvious_gap_between_noisy_stamps_is_counted_to_a_period() {
        // 100 Hz, stamps off by ±45 % of a period (σ = 0.26 of one, past
        // RESOLVE_SHARE, under LAG_SHARE), recovered; then 50 samples lost.
        // One step cannot count the gap to a period: it is counted short by
        // the LATE_SIGMAS allowance (two periods here; counting it in full
        // took a host's long-tailed late stamps for gaps at 1 kHz), and the
        // innovations' mean finds the periods missed in the steps after.
        // Measured: one three steps on, the other some 70 steps later; the
        // recovered time is back within a period of the samples' by 100
        // steps after the gap and stays there
        let h = 0.01;
        let kept: Vec<u64> = (0..6000u64)
            .map(|k| if k < 3000 { k } else { k + 50 })
            .collect();
        let s: Vec<f64> = kept.iter().map(|&k| k as f64 * h).collect();
        let stamps: Vec<f64> = kept
            .iter()
            .map(|&k| k as f64 * h + 0.45 * h * (2.0 * u(k) - 1.0))
            .collect();
        let mut c = SampleClock::new();
        let e = errors(&mut c, &s, &stamps);
        assert!(c.recovering());
        assert_eq!(c.restarts(), 0);
        // the recovered time's own offset before the gap
        let before = e[2999];
        assert!(before.abs() < h, "{}", before / h);
        for (k, x) in e.iter().enumerate().skip(3100) {
            assert!((x - before).abs() < h, "{k}: {} periods", (x - before) / h);
        }
    }

    #[test]
    fn a_clock_primed_after_a_changed_rate_keeps_the_start_on_its_own_rate() {
        // 100 Hz for 30 s, then 40 Hz, stamps off by ±30 % of a period. Run
        // once, the recovered times stay within a period of the samples'
        // throughout; primed, the clock must not carry the 40-Hz period and
        // its statistics back to the 100-Hz start (it did: steps of up to
        // 20 ms for 10, 60 ms of time that never was), so a clock that
        // started again primes nothing
        let mut s = Vec::new();
        for k in 0..3000u64 {
            s.push(k as f64 * 0.01);
        }
        for k in 1..1200u64 {
            s.push(30.0 + k as f64 * 0.025);
        }
        let stamps: Vec<f64> = s
            .iter()
            .enumerate()
            .map(|(k, &x)| {
                let h = if x < 30.0 { 0.01 } else { 0.025 };
                x + 0.3 * h * (2.0 * u(k as u64) - 1.0)
            })
            .collect();
        let mut once = SampleClock::new();
        let first = errors(&mut once, &s, &stamps);
        assert!(once.restarts() >= 1);
        let mut primed = once.primed();
        let again = errors(&mut primed, &s, &stamps);
        for (name, e) in [("once", &first), ("primed", &again)] {
            for (k, x) in e[..3000].iter().enumerate() {
                assert!(x.abs() < 0.01, "{name} {k}: {x}");
            }
        }
    }
}
