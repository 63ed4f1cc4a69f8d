//! Scoring attitude estimates against a reference orientation, as the BROAD
//! benchmark scores them.
//!
//! Source: D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD — A Benchmark
//! for Robust Inertial Orientation Estimation", Data 6(7), 2021 (section on
//! error metrics). The error quaternion is taken in the navigation frame,
//! q_err = q_est ⊗ q_ref*, and split into a rotation about the vertical
//! (heading) and a rotation about a horizontal axis (inclination); the
//! inclination error is the angle of the latter, 2·acos(√(w² + z²)) of q_err.
//! It does not depend on the heading, so filters without a magnetometer are
//! scored fairly. A recording's score is the RMSE of that error, in degrees,
//! over the samples with `movement` = 1 and a finite reference.

use std::io::Read;
use std::path::{Path, PathBuf};

use clino_core::Attitude;
use serde::Serialize;

use crate::fusion::FilterConfig;
use crate::io::{ImuCsvReader, ReadOptions};
use crate::{Error, ErrorKind, Result};

/// Inclination error between an estimate and a reference, rad, in [0, π].
///
/// q_err = q_est ⊗ q_ref* (navigation frame; both rotate body → ENU), and
/// e = 2·acos(√(w² + z²)) of q_err (BROAD, Laidig et al. 2021). Equal to the
/// angle between the two attitudes' vertical axes; a pure heading difference
/// gives 0.
///
/// ```
/// use clino::eval::inclination_error;
/// use clino::core::Attitude;
/// use nalgebra::Vector3;
/// let r = Attitude::from_euler_angles(0.2, -0.1, 1.0);
/// let tilted = Attitude::from_axis_angle(&Vector3::x_axis(), 0.05) * r;
/// assert!((inclination_error(&tilted, &r) - 0.05).abs() < 1e-12);
/// let turned = Attitude::from_axis_angle(&Vector3::z_axis(), 2.0) * r;
/// assert!(inclination_error(&turned, &r) < 1e-7);
/// ```
///
/// A non-finite estimate gives NaN (never a finite number: `f64::min` would
/// turn √NaN into 1 and the error into 0°), which [`Rms`] counts apart.
pub fn inclination_error(q_est: &Attitude, q_ref: &Attitude) -> f64 {
    let e = q_est.quaternion() * q_ref.quaternion().conjugate();
    let c = (e.w * e.w + e.k * e.k).sqrt();
    // clamp rounding above 1 only; NaN stays NaN
    let c = if c > 1.0 { 1.0 } else { c };
    2.0 * c.acos()
}

/// Root-mean-square accumulator of angles that counts non-finite values
/// apart: one of them makes the whole value NaN (a failed estimate is never
/// scored as a good one).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Rms {
    sum_sq: f64,
    n: u64,
    non_finite: u64,
}

impl Rms {
    /// Add one value.
    #[inline]
    pub fn push(&mut self, x: f64) {
        if x.is_finite() {
            self.sum_sq += x * x;
            self.n += 1;
        } else {
            self.non_finite += 1;
        }
    }
    /// Number of finite values.
    pub fn count(&self) -> u64 {
        self.n
    }
    /// Number of non-finite values pushed.
    pub fn non_finite(&self) -> u64 {
        self.non_finite
    }
    /// √(Σx²/n); NaN when empty or when any value was not finite.
    pub fn value(&self) -> f64 {
        if self.n == 0 || self.non_finite > 0 {
            f64::NAN
        } else {
            (self.sum_sq / self.n as f64).sqrt()
        }
    }
}

/// One filter's score on one recording.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FilterScore {
    /// Filter name.
    pub filter: String,
    /// Inclination RMSE, degrees (NaN → `null` when no sample was scored, or
    /// when the estimate was not finite on a scored sample).
    pub rmse_deg: f64,
    /// Samples scored (movement = 1 and finite reference).
    pub scored: u64,
    /// Scored samples whose estimate was not finite (the filter failed there).
    pub non_finite: u64,
    /// Rows the filter held through (NaN or out-of-bounds gyro or accelerometer).
    pub dropouts: u64,
}

/// Scores of every filter on one recording.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RecordingScore {
    /// The recording.
    pub file: PathBuf,
    /// Data rows read.
    pub rows: u64,
    /// One score per filter, in the order asked.
    pub scores: Vec<FilterScore>,
    /// How far the sensor's samples lag the reference ([`DelayEstimator`];
    /// `null` when the recording does not turn enough to time it).
    pub sensor_delay: Option<SensorDelay>,
    /// The sensor's timing the recording notes (a recording of `clino
    /// stream`) and the dynamic filters took
    /// ([`FilterConfig::for_recording`]); `null` when none was taken.
    pub sensor_timing: Option<crate::stream::SensorTiming>,
    /// A timing note a dynamic filter was to take did not read as one, or
    /// one came after the first data row: not taken (as `clino fuse` says).
    pub timing_note_not_taken: bool,
}

/// How far a sensor's samples lag a reference orientation, from the
/// recording itself ([`DelayEstimator`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SensorDelay {
    /// The delay, s (negative: the reference lags the sensor).
    pub seconds: f64,
    /// The same in sample periods (the median step): the value for the
    /// dynamic filter's `sensor_delay_periods` when the reference's time is
    /// the time wanted.
    pub periods: f64,
}

/// Largest delay [`DelayEstimator`] looks for, in samples either way.
const DELAY_MAX_SAMPLES: usize = 8;

/// The lag of a sensor's rate behind a reference orientation's, streaming,
/// in fixed memory (the last 17 rows).
///
/// The reference's rate at each row is the angle turned between its
/// neighbours over their time (a centred difference, `|ω_ref|`); each
/// sample's gyro rate `|ω|` is compared with the reference's rate j rows
/// earlier, for j = −8…8, and the sum of squared differences over the
/// recording is kept per j. The delay is the minimum of the parabola
/// through the least sum and its two neighbours, in rows, times the median
/// step. Magnitudes, not vectors, so the reference's body frame may be
/// turned against the sensor's; a gyro bias or scale error adds to the
/// sums evenly enough not to move the minimum. Why: the dynamic filter
/// makes up the sensor's delay on its output (`sensor_delay_periods`), and
/// the delay is a property of the sensor and its anti-alias filter setting
/// that one recording against a reference measures for every recording.
/// A recording that barely turns (the sums' curvature under 1 % of their
/// least value's scale) gives no delay.
#[derive(Clone, Debug)]
pub struct DelayEstimator {
    /// The last three reference rows (time, attitude), newest last.
    refs: [(f64, Option<Attitude>); 3],
    /// The last 2·L + 1 rows: (gyro rate, reference rate), NaN where unknown.
    ring: [(f64, f64); 2 * DELAY_MAX_SAMPLES + 1],
    filled: usize,
    /// Rows pushed.
    rows: u64,
    /// The last row's gyro rate (its reference rate needs the next row).
    pending: f64,
    sse: [f64; 2 * DELAY_MAX_SAMPLES + 1],
    count: [u64; 2 * DELAY_MAX_SAMPLES + 1],
    steps: Vec<f64>,
    last_t: f64,
}

impl Default for DelayEstimator {
    fn default() -> Self {
        Self {
            refs: [(f64::NAN, None); 3],
            ring: [(f64::NAN, f64::NAN); 2 * DELAY_MAX_SAMPLES + 1],
            filled: 0,
            rows: 0,
            pending: f64::NAN,
            sse: [0.0; 2 * DELAY_MAX_SAMPLES + 1],
            count: [0; 2 * DELAY_MAX_SAMPLES + 1],
            steps: Vec::new(),
            last_t: f64::NAN,
        }
    }
}

impl DelayEstimator {
    /// One row: its sample and reference (if finite). A gyro rate the
    /// filters would not take (non-finite, beyond the physical bounds:
    /// [`clino_core::pipeline::admission`]) is not compared, as a row without
    /// a reference is not; the rows keep their places.
    pub fn push(&mut self, sample: &clino_core::ImuSample, reference: Option<Attitude>) {
        let t = sample.t_s;
        let h = t - self.last_t;
        if h.is_finite() && h > 0.0 && self.steps.len() < 4097 {
            self.steps.push(h);
        }
        self.last_t = t;
        self.refs = [self.refs[1], self.refs[2], (t, reference)];
        // the previous row's reference rate, now that its next row is here
        let r = match (self.refs[0], self.refs[2]) {
            ((t0, Some(q0)), (t2, Some(q2))) if t2 > t0 => q0.angle_to(&q2) / (t2 - t0),
            _ => f64::NAN,
        };
        if self.rows > 0 {
            self.advance((self.pending, r));
        }
        self.rows += 1;
        self.pending = match clino_core::pipeline::admission(sample) {
            None => sample.gyr_rad_s.norm(),
            Some(_) => f64::NAN,
        };
    }

    fn advance(&mut self, row: (f64, f64)) {
        let n = self.ring.len();
        self.ring.rotate_left(1);
        self.ring[n - 1] = row;
        self.filled = (self.filled + 1).min(n);
        if self.filled < n {
            return;
        }
        // the middle row's gyro against the reference j rows before it
        let (g, _) = self.ring[DELAY_MAX_SAMPLES];
        if g.is_nan() {
            return;
        }
        for (k, (sse, c)) in self.sse.iter_mut().zip(&mut self.count).enumerate() {
            // k = L + j; the reference j rows earlier sits at L − j = 2L − k
            let r = self.ring[2 * DELAY_MAX_SAMPLES - k].1;
            if r.is_finite() {
                *sse += (g - r) * (g - r);
                *c += 1;
            }
        }
    }

    /// The delay, or `None` when there is too little turning to time.
    pub fn finish(&self) -> Option<SensorDelay> {
        let mean: Vec<f64> = self
            .sse
            .iter()
            .zip(&self.count)
            .map(|(s, &c)| if c > 100 { s / c as f64 } else { f64::NAN })
            .collect();
        if mean.iter().any(|m| !m.is_finite()) {
            return None;
        }
        let k = (1..mean.len() - 1).min_by(|&a, &b| mean[a].total_cmp(&mean[b]))?;
        let (a, b, c) = (mean[k - 1], mean[k], mean[k + 1]);
        let curv = a - 2.0 * b + c;
        // a minimum on the edge or a flat bottom is no measurement
        if !(b <= a && b <= c) || curv <= 0.01 * b.max(1e-12) {
            return None;
        }
        let rows = (k as f64 - DELAY_MAX_SAMPLES as f64) + 0.5 * (a - c) / curv;
        let mut st = self.steps.clone();
        st.sort_by(|x, y| x.total_cmp(y));
        let h = *st.get(st.len() / 2)?;
        Some(SensorDelay {
            seconds: rows * h,
            periods: rows,
        })
    }
}

/// Scores of several filters on several recordings, with the mean per filter.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EvalTable {
    /// Filter names (columns).
    pub filters: Vec<String>,
    /// One entry per recording (rows).
    pub recordings: Vec<RecordingScore>,
    /// Mean over recordings of the per-recording RMSE, degrees, per filter
    /// (as BROAD averages trials); recordings with nothing scored are left out.
    pub mean_rmse_deg: Vec<f64>,
}

/// Score one sample into `acc`, BROAD's rule: only a sample with
/// `movement` = 1 and a finite reference (`Some`) is scored; an estimate not
/// initialised yet counts as the identity (level, heading 0), so a filter
/// that starts late is charged for it.
#[inline]
pub fn score_sample(
    acc: &mut Rms,
    estimate: Option<Attitude>,
    reference: Option<Attitude>,
    movement: Option<bool>,
) {
    if movement == Some(true)
        && let Some(r) = reference
    {
        let q = estimate.unwrap_or_else(Attitude::identity);
        acc.push(inclination_error(&q, &r));
    }
}

/// The configurations `clino eval` scores for these specifications: each
/// with the lever arm; with `offline`, the smoothed dynamic filter next to
/// the real-time one (which must then be among them). Every one is checked.
pub fn eval_configs(
    specs: &[crate::fusion::FilterSpec],
    lever_arm_m: Option<clino_core::Vec3>,
    offline: bool,
) -> Result<Vec<FilterConfig>> {
    use crate::fusion::FilterKind;
    if offline && !specs.iter().any(|s| s.kind() == FilterKind::Dynamic) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "offline smoothing is for the dynamic filter: include it among the filters",
        ));
    }
    let mut configs = Vec::new();
    for s in specs {
        let c = FilterConfig::from_spec(*s).with_lever_arm(lever_arm_m);
        configs.push(c);
        if offline && s.kind() == FilterKind::Dynamic {
            configs.push(c.with_offline(true));
        }
    }
    for c in &configs {
        c.validate()?;
    }
    Ok(configs)
}

/// Score filters on one recording, in one pass over it (every filter sees
/// every row). The recording needs `ref_q{w,x,y,z}` and `movement` columns.
pub fn score_reader<R: Read>(
    reader: &mut ImuCsvReader<R>,
    configs: &[FilterConfig],
) -> Result<RecordingScore> {
    for (ok, col) in [
        (reader.has_reference(), "ref_qw"),
        (reader.has_movement(), "movement"),
    ] {
        if !ok {
            return Err(Error::new(
                ErrorKind::MissingColumn,
                format!("scoring needs a reference attitude (ref_qw, ref_qx, ref_qy, ref_qz) and a movement column; '{col}' is missing"),
            )
            .in_file(reader.file())
            .at_line(reader.header_line())
            .at_column(col));
        }
    }
    // the recording's notes (a sensor's timing) are complete once its first
    // row is read ([`FilterConfig::for_recording`])
    let mut first = reader.next_row()?;
    let mut sensor_timing = None;
    let configs: Vec<FilterConfig> = configs
        .iter()
        .map(|c| {
            let (c, t) = c.for_recording(reader.notes().0);
            sensor_timing = sensor_timing.or(t);
            c
        })
        .collect();
    let configs = &configs[..];
    let unread = sensor_timing.is_none()
        && configs.iter().any(FilterConfig::takes_timing_note)
        && crate::stream::SensorTiming::is_noted(reader.notes().0);
    // Real-time filters stream; offline ones need the recording in memory,
    // which is kept only when one of them is asked for.
    let mut pipes = configs
        .iter()
        .map(FilterConfig::pipeline)
        .collect::<Result<Vec<_>>>()?;
    let mut rms = vec![Rms::default(); configs.len()];
    let any_offline = configs.iter().any(|c| c.offline);
    let mut samples = Vec::new();
    let mut refs = Vec::new();
    let mut delay = DelayEstimator::default();
    while let Some(row) = match first.take() {
        Some(row) => Some(row),
        None => reader.next_row()?,
    } {
        delay.push(&row.sample, row.ref_q);
        let scored = row.movement == Some(true);
        for ((p, acc), c) in pipes.iter_mut().zip(rms.iter_mut()).zip(configs) {
            if c.offline {
                continue;
            }
            let o = p.update(&row.sample);
            score_sample(acc, o.attitude, row.ref_q, row.movement);
        }
        if any_offline {
            samples.push(row.sample);
            refs.push(row.ref_q.filter(|_| scored));
        }
    }
    let mut dropouts: Vec<u64> = pipes
        .iter()
        .map(|p| p.counts().dropouts + p.counts().saturated)
        .collect();
    for (i, c) in configs.iter().enumerate().filter(|(_, c)| c.offline) {
        let qs = c.smooth_samples(&samples)?;
        for (r, q) in refs.iter().zip(&qs) {
            score_sample(&mut rms[i], *q, *r, Some(true));
        }
        dropouts[i] = samples
            .iter()
            .filter(|s| clino_core::pipeline::admission(s).is_some())
            .count() as u64;
    }
    Ok(RecordingScore {
        file: reader.file().to_path_buf(),
        rows: reader.rows_read(),
        scores: configs
            .iter()
            .zip(&rms)
            .zip(&dropouts)
            .map(|((c, r), d)| FilterScore {
                filter: c.label(),
                rmse_deg: r.value().to_degrees(),
                scored: r.count(),
                non_finite: r.non_finite(),
                dropouts: *d,
            })
            .collect(),
        sensor_delay: delay.finish(),
        sensor_timing,
        timing_note_not_taken: unread || reader.notes().1,
    })
}

/// The recordings named by `paths`: files as given, directories replaced by
/// the `*.csv` and `*.parquet` files inside them (not recursive), sorted by name.
pub fn expand_paths(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut inside = Vec::new();
            for entry in std::fs::read_dir(p).map_err(|e| Error::from(e).in_file(p))? {
                let path = entry.map_err(|e| Error::from(e).in_file(p))?.path();
                if path.is_file()
                    && path.extension().is_some_and(|e| {
                        e.eq_ignore_ascii_case("csv") || e.eq_ignore_ascii_case("parquet")
                    })
                {
                    inside.push(path);
                }
            }
            if inside.is_empty() {
                return Err(Error::new(
                    ErrorKind::Empty,
                    "directory holds no .csv or .parquet file",
                )
                .in_file(p));
            }
            inside.sort();
            out.extend(inside);
        } else if p.exists() {
            out.push(p.clone());
        } else {
            return Err(Error::new(ErrorKind::Io, "no such file or directory").in_file(p));
        }
    }
    if out.is_empty() {
        return Err(Error::new(ErrorKind::Empty, "no recording given"));
    }
    Ok(out)
}

/// Score filters on recordings (files, or directories of `*.csv` and
/// `*.parquet`), one task per recording on `jobs` threads (rayon; `None`:
/// every core), each streaming its file. `progress(done, n, path)` is called
/// as each recording finishes (from the worker threads).
///
/// The table is in the order of the files whatever the threads do, and so
/// is the error: the first recording (in that order) that fails gives it.
/// Each recording is scored by the same code whether alone or in parallel,
/// so the numbers do not depend on `jobs`.
pub fn evaluate(
    paths: &[PathBuf],
    configs: &[FilterConfig],
    opts: &ReadOptions,
    jobs: Option<usize>,
    progress: impl Fn(usize, usize, &Path) + Sync,
) -> Result<EvalTable> {
    use rayon::prelude::*;
    use std::sync::atomic::{AtomicUsize, Ordering};
    for c in configs {
        c.validate()?;
    }
    let files = expand_paths(paths)?;
    let n = files.len();
    let done = AtomicUsize::new(0);
    let score = |f: &PathBuf| -> Result<RecordingScore> {
        let r = ImuCsvReader::from_path(f, opts).and_then(|mut r| score_reader(&mut r, configs));
        progress(done.fetch_add(1, Ordering::Relaxed) + 1, n, f);
        r
    };
    let run = || files.par_iter().map(score).collect::<Vec<_>>();
    let results = match jobs {
        Some(j) => rayon::ThreadPoolBuilder::new()
            .num_threads(j.max(1))
            .build()
            .map_err(|e| Error::new(ErrorKind::InvalidInput, format!("thread pool: {e}")))?
            .install(run),
        None => run(),
    };
    let recordings = results.into_iter().collect::<Result<Vec<_>>>()?;
    Ok(EvalTable::new(configs, recordings))
}

impl EvalTable {
    /// Assemble the table and its means.
    pub fn new(configs: &[FilterConfig], recordings: Vec<RecordingScore>) -> Self {
        let filters: Vec<String> = configs.iter().map(|c| c.label()).collect();
        let mean_rmse_deg = (0..filters.len())
            .map(|j| {
                // a recording where the filter failed makes the mean fail too;
                // recordings with nothing scored are left out
                if recordings.iter().any(|r| r.scores[j].non_finite > 0) {
                    return f64::NAN;
                }
                let v: Vec<f64> = recordings
                    .iter()
                    .map(|r| r.scores[j].rmse_deg)
                    .filter(|x| x.is_finite())
                    .collect();
                if v.is_empty() {
                    f64::NAN
                } else {
                    v.iter().sum::<f64>() / v.len() as f64
                }
            })
            .collect();
        Self {
            filters,
            recordings,
            mean_rmse_deg,
        }
    }

    /// The recordings' names as the text tables print them (the file stem),
    /// and the width of their column.
    fn row_names(&self) -> (Vec<String>, usize) {
        let names: Vec<String> = self
            .recordings
            .iter()
            .map(|r| {
                r.file
                    .file_stem()
                    .map(|s| s.to_string_lossy().into_owned())
                    .unwrap_or_else(|| r.file.display().to_string())
            })
            .collect();
        let w0 = names.iter().map(|n| n.len()).chain([9]).max().unwrap_or(9);
        (names, w0)
    }

    /// A fixed-width text table: one line per recording, one column per
    /// filter, inclination RMSE in degrees, and the mean.
    pub fn to_text(&self) -> String {
        let (names, w0) = self.row_names();
        let widths: Vec<usize> = self.filters.iter().map(|f| f.len().max(7)).collect();
        let mut s = format!("{:<w0$}", "recording");
        for (f, w) in self.filters.iter().zip(&widths) {
            s.push_str(&format!("  {f:>w$}"));
        }
        s.push('\n');
        let cell = |x: f64, w: usize| {
            if x.is_finite() {
                format!("  {x:>w$.3}")
            } else {
                format!("  {:>w$}", "n/a")
            }
        };
        let mut failed = Vec::new();
        for (n, r) in names.iter().zip(&self.recordings) {
            s.push_str(&format!("{n:<w0$}"));
            for (sc, w) in r.scores.iter().zip(&widths) {
                if sc.non_finite > 0 {
                    s.push_str(&format!("  {:>w$}", "FAILED", w = *w));
                    failed.push(format!(
                        "{n}: {} gave a non-finite attitude on {} scored samples",
                        sc.filter, sc.non_finite
                    ));
                } else {
                    s.push_str(&cell(sc.rmse_deg, *w));
                }
            }
            s.push('\n');
        }
        s.push_str(&format!("{:<w0$}", "mean"));
        for (m, w) in self.mean_rmse_deg.iter().zip(&widths) {
            s.push_str(&cell(*m, *w));
        }
        s.push('\n');
        for f in failed {
            s.push_str(&format!("FAILED {f}\n"));
        }
        s
    }

    /// The sensor's delay behind the reference per recording
    /// ([`RecordingScore::sensor_delay`]), in ms and sample periods, and the
    /// mean of those that could be timed.
    pub fn delay_text(&self) -> String {
        let (names, w0) = self.row_names();
        let mut s = format!(
            "{:<w0$}  {:>9}  {:>8}\n",
            "recording", "delay ms", "periods"
        );
        let mut timed = Vec::new();
        for (n, r) in names.iter().zip(&self.recordings) {
            match r.sensor_delay {
                Some(d) => {
                    s.push_str(&format!(
                        "{n:<w0$}  {:>9.2}  {:>8.2}\n",
                        d.seconds * 1e3,
                        d.periods
                    ));
                    timed.push(d.periods);
                }
                None => s.push_str(&format!("{n:<w0$}  {:>9}  {:>8}\n", "n/a", "n/a")),
            }
        }
        if !timed.is_empty() {
            let m = timed.iter().sum::<f64>() / timed.len() as f64;
            s.push_str(&format!("{:<w0$}  {:>9}  {m:>8.2}\n", "mean", ""));
        }
        s
    }

    /// True when some filter gave a non-finite attitude on a scored sample.
    pub fn any_failed(&self) -> bool {
        self.recordings
            .iter()
            .any(|r| r.scores.iter().any(|s| s.non_finite > 0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fusion::FilterKind;
    use clino_core::tilt::up_in_body;
    use nalgebra::{Unit, Vector3};
    use proptest::prelude::*;

    #[test]
    fn known_tilt_error_gives_that_angle_about_any_horizontal_axis() {
        let r = Attitude::from_euler_angles(0.4, 0.3, -2.0);
        for (ax, ang) in [
            (Vector3::x(), 0.1),
            (Vector3::y(), 0.7),
            (Vector3::new(1.0, 1.0, 0.0), 1.3),
        ] {
            let e = Attitude::from_axis_angle(&Unit::new_normalize(ax), ang);
            assert!((inclination_error(&(e * r), &r) - ang).abs() < 1e-12);
        }
    }

    #[test]
    fn pure_heading_error_gives_zero_and_sign_of_quaternion_does_not_matter() {
        let r = Attitude::from_euler_angles(-0.5, 0.2, 0.3);
        let yaw = Attitude::from_axis_angle(&Vector3::z_axis(), 3.0);
        assert!(inclination_error(&(yaw * r), &r) < 1e-7);
        let neg = Attitude::new_unchecked(-*(yaw * r).quaternion());
        assert!(inclination_error(&neg, &r) < 1e-7);
        // A tilt then a heading change: only the tilt counts.
        let tilt = Attitude::from_axis_angle(&Vector3::y_axis(), 0.25);
        assert!((inclination_error(&(yaw * tilt * r), &r) - 0.25).abs() < 1e-12);
    }

    proptest! {
        #[test]
        fn equals_angle_between_vertical_axes(
            a in -3.0f64..3.0, b in -1.5f64..1.5, c in -3.0f64..3.0,
            d in -3.0f64..3.0, e in -1.5f64..1.5, f in -3.0f64..3.0,
        ) {
            let q1 = Attitude::from_euler_angles(a, b, c);
            let q2 = Attitude::from_euler_angles(d, e, f);
            let u1 = up_in_body(&q1);
            let u2 = up_in_body(&q2);
            let angle = u1.cross(&u2).norm().atan2(u1.dot(&u2));
            prop_assert!((inclination_error(&q1, &q2) - angle).abs() < 1e-6);
        }
    }

    #[test]
    fn a_non_finite_estimate_is_never_scored_as_finite() {
        // issue 15: sqrt(NaN).min(1.0) was 1, so acos gave 0° for a failed filter
        let nan = Attitude::new_unchecked(nalgebra::Quaternion::new(f64::NAN, 0.0, 0.0, 0.0));
        assert!(inclination_error(&nan, &Attitude::identity()).is_nan());
        let mut r = Rms::default();
        r.push(0.1);
        r.push(f64::NAN);
        assert_eq!((r.count(), r.non_finite()), (1, 1));
        assert!(r.value().is_nan());
        let score = |nf| FilterScore {
            filter: "x".into(),
            rmse_deg: if nf > 0 { f64::NAN } else { 1.0 },
            scored: 5,
            non_finite: nf,
            dropouts: 0,
        };
        let rec = |nf| RecordingScore {
            file: "a.csv".into(),
            rows: 5,
            scores: vec![score(nf)],
            sensor_delay: None,
            sensor_timing: None,
            timing_note_not_taken: false,
        };
        let cfg = [FilterConfig::new(crate::fusion::FilterKind::Mahony)];
        let t = EvalTable::new(&cfg, vec![rec(0), rec(3)]);
        assert!(
            t.mean_rmse_deg[0].is_nan(),
            "a failed recording must fail the mean"
        );
        assert!(t.any_failed());
        assert!(t.to_text().contains("FAILED"));
    }

    /// A turn with a rate whose axis and size change (1–3 rad/s), the
    /// reference exact at the time stamps and the gyro `lag` periods behind
    /// them at 100 Hz, with a bias and noise; the reference's body frame
    /// turned 30° against the sensor's.
    fn delay_of(lag: f64, turning: bool) -> Option<SensorDelay> {
        delay_with(lag, turning, |_| None)
    }

    /// [`delay_of`] with the gyro of some rows replaced (`bad(k)`).
    fn delay_with(
        lag: f64,
        turning: bool,
        bad: impl Fn(usize) -> Option<clino_core::Vec3>,
    ) -> Option<SensorDelay> {
        use clino_core::Vec3;
        let h = 0.01;
        let rate = |t: f64| {
            if !turning {
                return Vec3::zeros();
            }
            Vec3::new(
                2.0 * (1.3 * t).sin(),
                1.5 * (0.7 * t).cos(),
                1.0 + 0.5 * (2.1 * t).sin(),
            )
        };
        let mount = Attitude::from_euler_angles(0.5, 0.0, 0.0);
        let mut q = Attitude::identity();
        let mut est = DelayEstimator::default();
        let mut noise = 0.37f64;
        let sub = 20;
        for k in 0..6000 {
            let t = k as f64 * h;
            noise = (noise * 9301.0 + 0.49297).fract();
            let gyr = rate(t - lag * h)
                + Vec3::new(0.01, -0.02, 0.005)
                + Vec3::repeat(0.002 * (noise - 0.5));
            let gyr = bad(k).unwrap_or(gyr);
            let acc = clino_core::Vec3::new(0.0, 0.0, 9.81);
            est.push(&clino_core::ImuSample::new(t, gyr, acc), Some(q * mount));
            for j in 0..sub {
                let tj = t + (j as f64 + 0.5) * h / sub as f64;
                q *= Attitude::from_scaled_axis(rate(tj) * (h / sub as f64));
            }
        }
        est.finish()
    }

    #[test]
    fn the_sensor_delay_is_timed_against_the_reference() {
        for lag in [0.0, 0.5, 1.0, 2.7, -1.3] {
            let d = delay_of(lag, true).expect("a turning recording is timed");
            assert!((d.periods - lag).abs() < 0.05, "{lag}: {d:?}");
            assert!((d.seconds - lag * 0.01).abs() < 0.0005, "{lag}: {d:?}");
        }
        // beyond the window, or nothing turning: no delay rather than a wrong one
        assert_eq!(delay_of(9.5, true), None);
        assert_eq!(delay_of(1.0, false), None);
        // corrupt gyro readings (NaN, 1e308, 1e150: beyond the bounds the
        // filters refuse) are left out, not summed into every shift
        let clean = delay_of(1.0, true).unwrap();
        let bad = |k: usize| match k {
            1000 => Some(clino_core::Vec3::new(f64::NAN, 0.0, 0.0)),
            2000 => Some(clino_core::Vec3::new(1e308, 0.0, 0.0)),
            3000 => Some(clino_core::Vec3::new(0.0, 1e150, 0.0)),
            _ => None,
        };
        let dirty = delay_with(1.0, true, bad).expect("still timed");
        assert!(
            (dirty.periods - clean.periods).abs() < 0.01,
            "{dirty:?} {clean:?}"
        );
    }

    #[test]
    fn rms_of_known_values() {
        let mut r = Rms::default();
        assert!(r.value().is_nan());
        for x in [3.0, 4.0] {
            r.push(x);
        }
        assert!((r.value() - 12.5f64.sqrt()).abs() < 1e-15);
        assert_eq!(r.count(), 2);
    }

    const HEAD: &str = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,ref_qw,ref_qx,ref_qy,ref_qz,movement\n";

    #[test]
    fn scores_only_moving_rows_with_finite_reference() {
        // Sensor level at rest; reference says tilted by 2° about x on the
        // scored rows, 30° on an unscored row, NaN on another scored row.
        let (s, c) = (1f64.to_radians().sin(), 1f64.to_radians().cos());
        let (s30, c30) = (15f64.to_radians().sin(), 15f64.to_radians().cos());
        let mut text = String::from(HEAD);
        for i in 0..10 {
            let t = i as f64 * 0.01;
            let line = match i {
                3 => format!("{t},0,0,0,0,0,9.81,{c30},{s30},0,0,0\n"),
                5 => format!("{t},0,0,0,0,0,9.81,nan,nan,nan,nan,1\n"),
                _ => format!("{t},0,0,0,0,0,9.81,{c},{s},0,0,1\n"),
            };
            text.push_str(&line);
        }
        let mut r = ImuCsvReader::new(text.as_bytes(), "m.csv", &ReadOptions::default()).unwrap();
        let cfg: Vec<FilterConfig> = FilterKind::ALL
            .iter()
            .map(|k| FilterConfig::new(*k))
            .collect();
        let rec = score_reader(&mut r, &cfg).unwrap();
        for sc in &rec.scores {
            assert_eq!(sc.scored, 8, "{}", sc.filter);
            assert!(
                (sc.rmse_deg - 2.0).abs() < 1e-9,
                "{}: {}",
                sc.filter,
                sc.rmse_deg
            );
        }
    }

    #[test]
    fn scoring_needs_reference_and_movement() {
        let text = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,0,0,0,9.8\n";
        let mut r = ImuCsvReader::new(text.as_bytes(), "m.csv", &ReadOptions::default()).unwrap();
        let e = score_reader(&mut r, &[FilterConfig::new(FilterKind::Mahony)]).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingColumn);
        assert_eq!(e.column.as_deref(), Some("ref_qw"));
    }

    #[test]
    fn parallel_evaluation_is_ordered_and_equal_to_one_thread() {
        let tmp = tempfile::Builder::new()
            .prefix("clino-eval-par-")
            .tempdir()
            .unwrap();
        let dir = tmp.path().to_path_buf();
        for (k, tilt) in [3.0f64, 1.0, 2.0, 5.0].iter().enumerate() {
            let (s, c) = (tilt.to_radians().sin(), tilt.to_radians().cos());
            let mut text = String::from(HEAD);
            for i in 0..200 {
                text.push_str(&format!(
                    "{},0,0,0.01,0,0,9.81,{c},{s},0,0,1\n",
                    i as f64 * 0.01
                ));
            }
            std::fs::write(dir.join(format!("r{k}.csv")), text).unwrap();
        }
        let cfg = [FilterConfig::new(FilterKind::Mahony)];
        let opts = ReadOptions::default();
        let one = evaluate(
            std::slice::from_ref(&dir),
            &cfg,
            &opts,
            Some(1),
            |_, _, _| {},
        )
        .unwrap();
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let two = evaluate(
            std::slice::from_ref(&dir),
            &cfg,
            &opts,
            Some(3),
            |_, n, _| {
                assert_eq!(n, 4);
                calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
            },
        )
        .unwrap();
        assert_eq!(one, two);
        assert_eq!(calls.into_inner(), 4);
        let names: Vec<String> = two
            .recordings
            .iter()
            .map(|r| r.file.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["r0.csv", "r1.csv", "r2.csv", "r3.csv"]);
        // the error of the first failing file in order, whatever finishes first
        std::fs::write(dir.join("r1.csv"), "t_s,x\n0,1\n").unwrap();
        std::fs::write(dir.join("r2.csv"), "garbage").unwrap();
        let e = evaluate(
            std::slice::from_ref(&dir),
            &cfg,
            &opts,
            Some(2),
            |_, _, _| {},
        )
        .unwrap_err();
        assert!(e.file.as_ref().unwrap().ends_with("r1.csv"), "{e}");
    }
}
