//! Recordings held in memory as arrays (NumPy, a column store), and
//! per-recording summaries for fleets of recordings.
//!
//! * [`ImuArrays`] borrows time, gyro and accelerometer columns as they lie
//!   in memory — row-major (`C`) or column-major (`Fortran`) `(N, 3)`
//!   blocks, described by their strides ([`Strided`]) — so a caller's arrays
//!   are read in place, never copied into a second layout. Its rules are
//!   those of [`crate::io::ImuCsvReader`]: a time column that is finite and
//!   strictly increasing, or a sample rate (the time of row k is
//!   [`crate::io::row_time`]); an error names the row (0-based, as the
//!   caller indexes it) and the column.
//! * [`run_arrays`] feeds them through a [`Pipeline`] in chunks with
//!   [`Pipeline::update_batch`] (the one loop); [`fuse_arrays`] adds the
//!   calibration and the offline stage exactly as [`crate::fusion::fuse`]
//!   does, so arrays and files give the same numbers to the last bit.
//! * [`summarize_reader`] streams one recording through [`fuse_into`] into a
//!   [`TiltSummary`] (mean, standard deviation, extremes of roll, pitch and
//!   inclination): one table row per recording, in constant memory.
//!
//! ```
//! use clino::batch::{ImuArrays, Strided, fuse_arrays};
//! use clino::fusion::{FilterConfig, FilterKind, Output, Status};
//! // 20° roll at rest, 100 Hz, row-major (N, 3) blocks
//! let n = 50;
//! let r = 20f64.to_radians();
//! let gyr = vec![0.0; 3 * n];
//! let acc: Vec<f64> = (0..n).flat_map(|_| [0.0, 9.81 * r.sin(), 9.81 * r.cos()]).collect();
//! let a = ImuArrays::new(None, Some(100.0), Strided::rows(&gyr, n), Strided::rows(&acc, n));
//! let mut out = vec![Output { status: Status::Waiting, attitude: None }; n];
//! let rep = fuse_arrays(&a, &FilterConfig::new(FilterKind::Mahony), None, &mut out)?;
//! assert_eq!(rep.counts.samples, 50);
//! let tilt = out[49].tilt().unwrap();
//! assert!((tilt.roll_rad - r).abs() < 1e-9);
//! # Ok::<(), clino::Error>(())
//! ```

use std::io::Read;
use std::path::PathBuf;

use clino_core::pipeline::TiltOutput;
use clino_core::{ImuSample, Vec3};
use serde::Serialize;

use crate::calib::CalibrationFile;
use crate::fusion::{
    FilterConfig, FuseOptions, FuseReport, Output, Pipeline, Status, fuse_into,
    offline_outputs_stamped,
};
use crate::io::{ImuCsvReader, RowSink, row_time};
use crate::{Error, ErrorKind, Result};

fn invalid(msg: impl Into<String>) -> Error {
    Error::new(ErrorKind::InvalidInput, msg)
}

/// A `(rows, 3)` block of numbers where it lies in memory: element (k, j)
/// is `data[k·row_stride + j·col_stride]`.
#[derive(Clone, Copy, Debug)]
pub struct Strided<'a> {
    data: &'a [f64],
    rows: usize,
    row_stride: usize,
    col_stride: usize,
}

impl<'a> Strided<'a> {
    /// Row-major (C order): `x0 y0 z0 x1 y1 z1 …`.
    pub fn rows(data: &'a [f64], rows: usize) -> Self {
        Self {
            data,
            rows,
            row_stride: 3,
            col_stride: 1,
        }
    }

    /// Column-major (Fortran order): `x0 x1 … y0 y1 … z0 z1 …`.
    pub fn columns(data: &'a [f64], rows: usize) -> Self {
        Self {
            data,
            rows,
            row_stride: 1,
            col_stride: rows,
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.rows
    }

    /// True when there is no row.
    pub fn is_empty(&self) -> bool {
        self.rows == 0
    }

    /// True when every element lies inside `data`.
    fn fits(&self) -> bool {
        self.rows == 0 || (self.rows - 1) * self.row_stride + 2 * self.col_stride < self.data.len()
    }

    /// Row `k` as a vector.
    #[inline]
    pub fn row(&self, k: usize) -> Vec3 {
        let b = k * self.row_stride;
        Vec3::new(
            self.data[b],
            self.data[b + self.col_stride],
            self.data[b + 2 * self.col_stride],
        )
    }
}

/// Time, gyro (rad/s) and accelerometer (m/s²) columns of a recording, and
/// optionally its temperature (°C), borrowed where they lie.
#[derive(Clone, Copy, Debug)]
pub struct ImuArrays<'a> {
    /// Time stamps, s; `None` when the rate gives them.
    pub t_s: Option<&'a [f64]>,
    /// Sample rate, Hz, used when there is no time column.
    pub rate_hz: Option<f64>,
    /// Body angular rate, rad/s.
    pub gyr_rad_s: Strided<'a>,
    /// Specific force, m/s².
    pub acc_m_s2: Strided<'a>,
    /// Sensor temperature, °C (for a temperature-dependent calibration).
    pub temp_c: Option<&'a [f64]>,
    /// Index of the first row in the whole stream, when these arrays are one
    /// batch of a longer one: rate-given times continue from it and errors
    /// name rows of the whole stream.
    pub first_row: u64,
    /// Time of the row before the first one (the previous batch's last), so
    /// that time must keep increasing across batches.
    pub prev_t_s: Option<f64>,
}

impl<'a> ImuArrays<'a> {
    /// Arrays with a time column or a rate (exactly one of the two), no
    /// temperature, starting a stream.
    pub fn new(
        t_s: Option<&'a [f64]>,
        rate_hz: Option<f64>,
        gyr_rad_s: Strided<'a>,
        acc_m_s2: Strided<'a>,
    ) -> Self {
        Self {
            t_s,
            rate_hz,
            gyr_rad_s,
            acc_m_s2,
            temp_c: None,
            first_row: 0,
            prev_t_s: None,
        }
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.gyr_rad_s.len()
    }

    /// True when there is no row.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Check the shapes, the rate and every time stamp (finite, strictly
    /// increasing), with the reader's messages; the error names the row.
    pub fn validate(&self) -> Result<()> {
        let n = self.len();
        if self.acc_m_s2.len() != n {
            return Err(invalid(format!(
                "gyr has {n} rows but acc has {}",
                self.acc_m_s2.len()
            ))
            .at_column("acc"));
        }
        if !self.gyr_rad_s.fits() || !self.acc_m_s2.fits() {
            return Err(invalid("an array's strides reach past its memory"));
        }
        if let Some(tc) = self.temp_c
            && tc.len() != n
        {
            return Err(
                invalid(format!("temp_c has {} rows, gyr {n}", tc.len())).at_column("temp_c")
            );
        }
        match (self.t_s, self.rate_hz) {
            (Some(_), Some(_)) => Err(invalid("give the time stamps (t) or the rate, not both")),
            (None, None) => Err(invalid(
                "give the time stamps (t, s) or the sample rate (rate, Hz)",
            )),
            (None, Some(r)) if !(r.is_finite() && r > 0.0) => Err(invalid(format!(
                "sample rate must be a positive number of Hz, got {r}"
            ))),
            (None, Some(_)) => Ok(()),
            (Some(t), None) => {
                if t.len() != n {
                    return Err(
                        invalid(format!("t has {} rows, gyr {n}", t.len())).at_column("t_s")
                    );
                }
                let mut prev = self.prev_t_s;
                for (k, &x) in t.iter().enumerate() {
                    let row = self.first_row + k as u64;
                    if !x.is_finite() {
                        return Err(invalid(format!(
                            "row {row}: time stamp is not a finite number ({x})"
                        ))
                        .at_column("t_s"));
                    }
                    if let Some(p) = prev
                        && x <= p
                    {
                        let what = if x == p { "repeats" } else { "goes backwards" };
                        return Err(Error::new(
                            ErrorKind::TimeNotIncreasing,
                            format!("row {row}: time {what}: {x} s after {p} s"),
                        )
                        .at_column("t_s"));
                    }
                    prev = Some(x);
                }
                Ok(())
            }
        }
    }

    /// Time of row `k` of these arrays, s.
    #[inline]
    pub fn time(&self, k: usize) -> f64 {
        match (self.t_s, self.rate_hz) {
            (Some(t), _) => t[k],
            (None, Some(r)) => row_time(self.first_row + k as u64, r),
            (None, None) => f64::NAN,
        }
    }

    /// Row `k` as a sample (SI units).
    #[inline]
    pub fn sample(&self, k: usize) -> ImuSample {
        let mut s = ImuSample::new(self.time(k), self.gyr_rad_s.row(k), self.acc_m_s2.row(k));
        s.temp_c = self.temp_c.map(|t| t[k]);
        s
    }
}

/// Rows handed to [`Pipeline::update_batch`] at a time by callers that
/// stage samples in a buffer (a few kB of samples: they stay in cache).
/// [`run_arrays`] and [`run_arrays_into`] no longer stage: they read each
/// row where it lies and hand it to [`Pipeline::update`] directly.
pub const CHUNK: usize = 1024;

/// The code of a status: its index in [`Status::ALL`] (the `status_code`
/// column of the Python package).
#[inline]
pub const fn status_code(s: Status) -> u8 {
    match s {
        Status::Waiting => 0,
        Status::Initialised => 1,
        Status::Fused => 2,
        Status::GyroOnly => 3,
        Status::Dropout => 4,
        Status::Saturated => 5,
    }
}

/// Per-row outputs written straight into a caller's buffers (the memory of
/// NumPy arrays), with no [`Output`] array in between: row k of the input
/// fills element k of each buffer.
///
/// * `quat`: the attitude w, x, y, z (body → ENU); NaN before initialisation;
/// * `tilt_deg` (optional): aerospace roll, pitch and the inclination,
///   degrees — the `roll_deg`, `pitch_deg`, `inclination_deg` columns of
///   `clino fuse`, by the same functions; NaN before initialisation;
/// * `status` (optional): [`status_code`] of each row.
///
/// Each buffer must be at least as long as the input; elements past it are
/// untouched.
#[derive(Debug)]
pub struct OutputColumns<'a> {
    /// w, x, y, z per row.
    pub quat: &'a mut [[f64; 4]],
    /// Roll, pitch, inclination per row, degrees.
    pub tilt_deg: Option<&'a mut [[f64; 3]]>,
    /// Status code per row.
    pub status: Option<&'a mut [u8]>,
}

impl<'a> OutputColumns<'a> {
    /// Quaternions only.
    pub fn quat(quat: &'a mut [[f64; 4]]) -> Self {
        Self {
            quat,
            tilt_deg: None,
            status: None,
        }
    }

    /// Error unless every buffer holds at least `n` rows.
    fn check(&self, n: usize) -> Result<()> {
        let short = self.quat.len() < n
            || self.tilt_deg.as_ref().is_some_and(|d| d.len() < n)
            || self.status.as_ref().is_some_and(|s| s.len() < n);
        if short {
            return Err(invalid("output shorter than the input"));
        }
        Ok(())
    }

    /// Write row `k` from `o`.
    #[inline]
    pub fn put(&mut self, k: usize, o: &Output) {
        match &o.attitude {
            Some(a) => {
                self.quat[k] = [a.w, a.i, a.j, a.k];
                if let Some(d) = self.tilt_deg.as_deref_mut() {
                    let t = TiltOutput::from_attitude(a);
                    d[k] = [
                        t.roll_rad.to_degrees(),
                        t.pitch_rad.to_degrees(),
                        t.inclination_rad.to_degrees(),
                    ];
                }
            }
            None => {
                self.quat[k] = [f64::NAN; 4];
                if let Some(d) = self.tilt_deg.as_deref_mut() {
                    d[k] = [f64::NAN; 3];
                }
            }
        }
        if let Some(s) = self.status.as_deref_mut() {
            s[k] = status_code(o.status);
        }
    }
}

/// The one loop over arrays: row k (read where it lies) through
/// [`Pipeline::update`], its output handed to `put(k, &output)`. The
/// arrays must have been validated.
#[inline]
fn run_rows(pipeline: &mut Pipeline, arrays: &ImuArrays, mut put: impl FnMut(usize, &Output)) {
    for k in 0..arrays.len() {
        let o = pipeline.update(&arrays.sample(k));
        put(k, &o);
    }
}

/// Feed `arrays` through `pipeline` ([`Pipeline::update`] row by row, the
/// code of [`Pipeline::update_batch`]), one [`Output`] per row into `out`
/// (at least as long). The arrays are checked first ([`ImuArrays::validate`]).
pub fn run_arrays(pipeline: &mut Pipeline, arrays: &ImuArrays, out: &mut [Output]) -> Result<()> {
    arrays.validate()?;
    if out.len() < arrays.len() {
        return Err(invalid("output shorter than the input"));
    }
    run_rows(pipeline, arrays, |k, o| out[k] = *o);
    Ok(())
}

/// [`run_arrays`] writing each row's outputs straight into `out`'s buffers
/// ([`OutputColumns::put`]): the same loop, so the numbers are equal to the
/// bit, without an [`Output`] per row in memory.
pub fn run_arrays_into(
    pipeline: &mut Pipeline,
    arrays: &ImuArrays,
    out: &mut OutputColumns,
) -> Result<()> {
    arrays.validate()?;
    out.check(arrays.len())?;
    run_rows(pipeline, arrays, |k, o| out.put(k, o));
    Ok(())
}

/// The temperature check of a calibration for one row, naming it (the
/// calibration's range rules of [`CalibrationFile::check_temp`]).
fn check_row(cal: &CalibrationFile, s: &ImuSample, row: u64) -> Result<()> {
    if !finite_imu(s) {
        return Ok(());
    }
    cal.check_temp(s.temp_c).map_err(|e| Error {
        message: format!("row {row}: {}", e.message),
        ..e
    })
}

/// Fuse a whole recording held in arrays: [`FilterConfig::pipeline`] with the
/// calibration, then [`run_arrays`]; or, when `config.offline`, the offline
/// smoother over the calibrated samples ([`crate::fusion::offline_outputs`]). The same
/// stages, in the same order, as [`crate::fusion::fuse`] on a file: the
/// outputs are equal to the bit.
pub fn fuse_arrays(
    arrays: &ImuArrays,
    config: &FilterConfig,
    calibration: Option<&CalibrationFile>,
    out: &mut [Output],
) -> Result<FuseReport> {
    arrays.validate()?;
    if out.len() < arrays.len() {
        return Err(invalid("output shorter than the input"));
    }
    fuse_rows(arrays, config, calibration, |k, o| out[k] = *o)
}

/// [`fuse_arrays`] writing each row's outputs straight into `out`'s buffers
/// ([`OutputColumns::put`]): the same stages and loop, so the numbers are
/// equal to the bit (and to `clino fuse` on the same recording), with
/// nothing allocated per row (the offline smoother keeps the recording, as
/// it must).
pub fn fuse_arrays_into(
    arrays: &ImuArrays,
    config: &FilterConfig,
    calibration: Option<&CalibrationFile>,
    out: &mut OutputColumns,
) -> Result<FuseReport> {
    arrays.validate()?;
    out.check(arrays.len())?;
    fuse_rows(arrays, config, calibration, |k, o| out.put(k, o))
}

/// The stages of [`fuse_arrays`] over validated arrays, each row's output
/// handed to `put(k, &output)` in order.
fn fuse_rows(
    arrays: &ImuArrays,
    config: &FilterConfig,
    calibration: Option<&CalibrationFile>,
    mut put: impl FnMut(usize, &Output),
) -> Result<FuseReport> {
    let n = arrays.len();
    if let Some(cal) = calibration {
        for k in 0..n {
            check_row(cal, &arrays.sample(k), arrays.first_row + k as u64)?;
        }
    }
    let mut report = FuseReport::default();
    if config.offline {
        // counted as `fuse_into` counts them: the raw readings of usable rows
        for k in 0..n {
            let s = arrays.sample(k);
            if clino_core::pipeline::admission(&s).is_none() {
                report
                    .counts
                    .record_clipping(&config.sensor_range, &s, k as u64 + 1);
            }
        }
    }
    let mut put = |k: usize, o: &Output| {
        report.counts.record(o.status);
        if matches!(o.status, Status::Dropout | Status::Saturated) {
            report
                .first_dropout_line
                .get_or_insert(arrays.first_row + k as u64);
        }
        put(k, o);
    };
    if config.offline {
        let samples: Vec<ImuSample> = (0..n)
            .map(|k| {
                let s = arrays.sample(k);
                match calibration {
                    Some(c) if finite_imu(&s) => c.calibration().apply(&s),
                    _ => s,
                }
            })
            .collect();
        let (outs, retimed, jitter) =
            offline_outputs_stamped(config, &samples, calibration.is_some())?;
        for (k, o) in outs.iter().enumerate() {
            put(k, o);
        }
        report.counts.retimed = retimed;
        report.stamp_jitter_s = jitter;
    } else {
        let mut p = config
            .pipeline()?
            .with_calibration(calibration.map(CalibrationFile::calibration));
        run_rows(&mut p, arrays, put);
        // what `clino fuse` reports of a real-time run, from the same pipeline
        report.take_real_time(&p);
    }
    report.first_clipped_line = report
        .counts
        .first_clipped
        .map(|n| arrays.first_row + n - 1);
    for k in 0..n {
        let s = arrays.sample(k);
        if clino_core::pipeline::admission(&s).is_none() {
            report.rails.push(&s);
        }
    }
    Ok(report)
}

fn finite_imu(s: &ImuSample) -> bool {
    s.gyr_rad_s.iter().all(|v| v.is_finite()) && s.acc_m_s2.iter().all(|v| v.is_finite())
}

/// Running mean, standard deviation and extremes of one angle, degrees
/// (Welford's update: B. P. Welford, "Note on a method for calculating
/// corrected sums of squares and products", Technometrics 4(3), 1962).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct AngleStats {
    /// Values seen.
    pub n: u64,
    /// Mean, degrees (NaN when none).
    pub mean_deg: f64,
    /// Sample standard deviation (n − 1), degrees (NaN below two values).
    pub std_deg: f64,
    /// Smallest value, degrees.
    pub min_deg: f64,
    /// Largest value, degrees.
    pub max_deg: f64,
    #[serde(skip)]
    m2: f64,
}

impl Default for AngleStats {
    fn default() -> Self {
        Self {
            n: 0,
            mean_deg: f64::NAN,
            std_deg: f64::NAN,
            min_deg: f64::NAN,
            max_deg: f64::NAN,
            m2: 0.0,
        }
    }
}

impl AngleStats {
    /// Add one finite value (non-finite values are not angles: ignored).
    pub fn push(&mut self, x: f64) {
        if !x.is_finite() {
            return;
        }
        if self.n == 0 {
            self.mean_deg = 0.0;
            self.min_deg = x;
            self.max_deg = x;
        }
        self.n += 1;
        let d = x - self.mean_deg;
        self.mean_deg += d / self.n as f64;
        self.m2 += d * (x - self.mean_deg);
        self.min_deg = self.min_deg.min(x);
        self.max_deg = self.max_deg.max(x);
        self.std_deg = if self.n > 1 {
            (self.m2 / (self.n - 1) as f64).sqrt()
        } else {
            f64::NAN
        };
    }
}

/// Statistics of the tilt a run produced: a [`RowSink`] that takes the rows
/// of [`fuse_into`] (`t_s, qw, qx, qy, qz, roll_deg, pitch_deg,
/// inclination_deg, status`) and keeps only running statistics of the three
/// angles (rows with an attitude).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct TiltSummary {
    /// Aerospace roll, degrees.
    pub roll: AngleStats,
    /// Aerospace pitch, degrees.
    pub pitch: AngleStats,
    /// Inclination (body z from the vertical), degrees.
    pub inclination: AngleStats,
    /// Rows seen.
    pub rows: u64,
    /// Time of the first row, s.
    pub t_first_s: f64,
    /// Time of the last row, s.
    pub t_last_s: f64,
    #[serde(skip)]
    col: usize,
}

impl RowSink for TiltSummary {
    fn f64(&mut self, x: f64) {
        match self.col {
            0 => {
                if self.rows == 0 {
                    self.t_first_s = x;
                }
                self.rows += 1;
                self.t_last_s = x;
            }
            5 => self.roll.push(x),
            6 => self.pitch.push(x),
            7 => self.inclination.push(x),
            _ => {}
        }
        self.col += 1;
    }
    fn str(&mut self, _s: &str) {
        self.col += 1;
    }
    fn end_row(&mut self) -> std::io::Result<()> {
        self.col = 0;
        Ok(())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// One recording's summary: its counts and tilt statistics.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RecordingSummary {
    /// The recording.
    pub file: PathBuf,
    /// The filter configuration ([`FilterConfig::label`]).
    pub filter: String,
    /// What the pipeline did with the rows.
    pub report: FuseReport,
    /// Roll, pitch and inclination statistics.
    pub tilt: TiltSummary,
}

/// Stream one recording through [`fuse_into`] (the run of `clino fuse`)
/// into a [`TiltSummary`]: memory flat in the recording's length (unless
/// `config.offline`).
pub fn summarize_reader<R: Read>(
    reader: &mut ImuCsvReader<R>,
    config: &FilterConfig,
    opts: &FuseOptions,
) -> Result<RecordingSummary> {
    let mut tilt = TiltSummary {
        t_first_s: f64::NAN,
        t_last_s: f64::NAN,
        ..Default::default()
    };
    let report = fuse_into(reader, &mut tilt, config, opts, None)?;
    Ok(RecordingSummary {
        file: reader.file().to_path_buf(),
        filter: config.label(),
        report,
        tilt,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fusion::{FilterKind, FuseOptions, fuse};
    use crate::io::ReadOptions;

    fn text(n: usize) -> (String, Vec<f64>, Vec<f64>, Vec<f64>) {
        let mut s = String::from(
            "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n",
        );
        let (mut t, mut g, mut a) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..n {
            let tk = k as f64 * 0.01;
            let w = [0.3 * (tk * 2.0).sin(), -0.2 * tk.cos(), 0.1];
            let f = [0.5 * tk.sin(), 1.0, 9.7];
            let (w, f) = if k == 37 {
                ([f64::NAN, w[1], w[2]], f)
            } else {
                (w, f)
            };
            s.push_str(&format!(
                "{tk},{},{},{},{},{},{}\n",
                w[0], w[1], w[2], f[0], f[1], f[2]
            ));
            t.push(tk);
            g.extend(w);
            a.extend(f);
        }
        (s, t, g, a)
    }

    fn csv_rows(text: &str, cfg: &FilterConfig) -> Vec<Vec<String>> {
        let mut r = ImuCsvReader::new(text.as_bytes(), "m.csv", &ReadOptions::default()).unwrap();
        let mut out = Vec::new();
        fuse(&mut r, &mut out, cfg, &FuseOptions::default()).unwrap();
        String::from_utf8(out)
            .unwrap()
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    }

    #[test]
    fn arrays_equal_the_file_run_to_the_bit_in_both_layouts_and_offline() {
        let n = 2500;
        let (s, t, g, a) = text(n);
        // the same numbers column-major
        let tr = |v: &[f64]| -> Vec<f64> {
            (0..3)
                .flat_map(|j| (0..n).map(move |k| v[3 * k + j]))
                .collect()
        };
        let (gf, af) = (tr(&g), tr(&a));
        for cfg in [
            FilterConfig::new(FilterKind::Dynamic),
            FilterConfig::new(FilterKind::Mahony).with_lever_arm(Some(Vec3::new(0.1, 0.0, 0.0))),
            FilterConfig::new(FilterKind::Dynamic).with_offline(true),
        ] {
            let rows = csv_rows(&s, &cfg);
            for arr in [
                ImuArrays::new(Some(&t), None, Strided::rows(&g, n), Strided::rows(&a, n)),
                ImuArrays::new(
                    Some(&t),
                    None,
                    Strided::columns(&gf, n),
                    Strided::columns(&af, n),
                ),
            ] {
                let mut out = vec![
                    Output {
                        status: Status::Waiting,
                        attitude: None
                    };
                    n
                ];
                let rep = fuse_arrays(&arr, &cfg, None, &mut out).unwrap();
                assert_eq!(rep.counts.dropouts, 1);
                // the learnt sensor errors of a real-time dynamic run, as `clino fuse` reports them
                assert_eq!(
                    rep.sensor_errors.is_some(),
                    cfg.kind() == FilterKind::Dynamic && !cfg.offline,
                    "{}",
                    cfg.label()
                );
                assert_eq!(rep.first_dropout_line, Some(37));
                for (o, r) in out.iter().zip(&rows) {
                    let q = o.attitude.unwrap();
                    let w: f64 = r[1].parse().unwrap();
                    let z: f64 = r[4].parse().unwrap();
                    assert_eq!((q.w, q.k), (w, z), "{}", cfg.label());
                    assert_eq!(o.status.as_str(), r[8]);
                }
            }
        }
    }

    #[test]
    fn arrays_report_the_recovered_clock_as_the_file_run_does() {
        // 60 s at 100 Hz, each row stamped late by 0–8 ms (a host's receive
        // times): both paths recover the clock on the same rows, real time
        // and offline
        let n = 6000;
        let (mut s, mut t, mut g, mut a) = (
            String::from("t_s,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z\n"),
            Vec::new(),
            Vec::new(),
            Vec::new(),
        );
        let mut last = f64::MIN;
        for k in 0..n {
            let tk = k as f64 * 0.01;
            let u =
                ((k as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> 11) as f64 / (1u64 << 53) as f64;
            let stamp = (tk + (-0.002 * (1.0 - u).ln()).min(0.008)).max(last + 1e-6);
            last = stamp;
            let w = [0.3 * (tk * 2.0).sin(), -0.2 * tk.cos(), 0.1];
            let f = [0.5 * tk.sin(), 1.0, 9.7];
            s.push_str(&format!(
                "{stamp},{},{},{},{},{},{}\n",
                w[0], w[1], w[2], f[0], f[1], f[2]
            ));
            // the arrays hold what the file's text reads back
            t.push(format!("{stamp}").parse::<f64>().unwrap());
            g.extend(w);
            a.extend(f);
        }
        for cfg in [
            FilterConfig::new(FilterKind::Dynamic),
            FilterConfig::new(FilterKind::Dynamic).with_offline(true),
        ] {
            let mut r = ImuCsvReader::new(s.as_bytes(), "m.csv", &ReadOptions::default()).unwrap();
            let file = fuse(&mut r, &mut Vec::new(), &cfg, &FuseOptions::default()).unwrap();
            let arr = ImuArrays::new(Some(&t), None, Strided::rows(&g, n), Strided::rows(&a, n));
            let mut out = vec![
                Output {
                    status: Status::Waiting,
                    attitude: None
                };
                n
            ];
            let rep = fuse_arrays(&arr, &cfg, None, &mut out).unwrap();
            assert!(
                rep.counts.retimed > 4000,
                "{}: {}",
                cfg.label(),
                rep.counts.retimed
            );
            assert_eq!(rep.counts.retimed, file.counts.retimed, "{}", cfg.label());
            assert_eq!(rep.stamp_jitter_s, file.stamp_jitter_s, "{}", cfg.label());
            let j = rep.stamp_jitter_s.unwrap();
            // the exponential's standard deviation, 2 ms (capped at 8 ms)
            assert!((1.5e-3..2.5e-3).contains(&j), "{j}");
        }
    }

    #[test]
    fn columns_equal_the_file_run_to_the_bit_with_tilt_and_status() {
        let n = 1500;
        let (s, t, g, a) = text(n);
        for cfg in [
            FilterConfig::new(FilterKind::Dynamic),
            FilterConfig::new(FilterKind::Madgwick).with_lever_arm(Some(Vec3::new(0.0, 0.05, 0.0))),
            FilterConfig::new(FilterKind::Dynamic).with_offline(true),
        ] {
            let rows = csv_rows(&s, &cfg);
            let arr = ImuArrays::new(Some(&t), None, Strided::rows(&g, n), Strided::rows(&a, n));
            // one row longer than the input: the extra row must stay untouched
            let mut q = vec![[7.0; 4]; n + 1];
            let mut d = vec![[7.0; 3]; n + 1];
            let mut st = vec![99u8; n + 1];
            let mut cols = OutputColumns {
                quat: &mut q,
                tilt_deg: Some(&mut d),
                status: Some(&mut st),
            };
            let rep = fuse_arrays_into(&arr, &cfg, None, &mut cols).unwrap();
            assert_eq!(rep.counts.samples, n as u64);
            assert_eq!(rep.counts.dropouts, 1);
            assert_eq!(rep.first_dropout_line, Some(37));
            for k in 0..n {
                let r = &rows[k];
                let num = |j: usize| -> f64 { r[j].parse().unwrap() };
                assert_eq!(
                    q[k],
                    [num(1), num(2), num(3), num(4)],
                    "{} row {k}",
                    cfg.label()
                );
                assert_eq!(d[k], [num(5), num(6), num(7)], "{} row {k}", cfg.label());
                assert_eq!(Status::ALL[st[k] as usize].as_str(), r[8]);
            }
            assert_eq!((q[n], d[n], st[n]), ([7.0; 4], [7.0; 3], 99));
            // quaternions only: the same numbers
            let mut q2 = vec![[0.0; 4]; n];
            fuse_arrays_into(&arr, &cfg, None, &mut OutputColumns::quat(&mut q2)).unwrap();
            assert_eq!(q2[..], q[..n]);
        }
    }

    #[test]
    fn columns_before_initialisation_are_nan_and_short_buffers_are_refused() {
        // zero specific force: the filter cannot take tilt, no attitude yet
        let g = vec![0.0; 6];
        let a = vec![0.0; 6];
        let arr = ImuArrays::new(
            None,
            Some(100.0),
            Strided::rows(&g, 2),
            Strided::rows(&a, 2),
        );
        let mut p = FilterConfig::new(FilterKind::Dynamic).pipeline().unwrap();
        let (mut q, mut d, mut st) = (vec![[0.0; 4]; 2], vec![[0.0; 3]; 2], vec![9u8; 2]);
        let mut cols = OutputColumns {
            quat: &mut q,
            tilt_deg: Some(&mut d),
            status: Some(&mut st),
        };
        run_arrays_into(&mut p, &arr, &mut cols).unwrap();
        assert!(
            q.iter()
                .flatten()
                .chain(d.iter().flatten())
                .all(|x| x.is_nan())
        );
        assert_eq!(st, [status_code(Status::Waiting); 2]);
        let mut short = vec![[0.0; 4]; 1];
        let e = run_arrays_into(&mut p, &arr, &mut OutputColumns::quat(&mut short)).unwrap_err();
        assert!(e.message.contains("shorter"), "{}", e.message);
        let mut q3 = vec![[0.0; 4]; 2];
        let mut st1 = vec![0u8; 1];
        let mut cols = OutputColumns {
            quat: &mut q3,
            tilt_deg: None,
            status: Some(&mut st1),
        };
        assert!(
            fuse_arrays_into(
                &arr,
                &FilterConfig::new(FilterKind::Dynamic),
                None,
                &mut cols
            )
            .is_err()
        );
    }

    #[test]
    fn status_codes_are_the_positions_in_all() {
        for (i, s) in Status::ALL.iter().enumerate() {
            assert_eq!(status_code(*s) as usize, i, "{}", s.as_str());
        }
    }

    #[test]
    fn rate_times_continue_across_batches_and_bad_time_names_the_row() {
        let g = vec![0.0; 30];
        let a: Vec<f64> = (0..10).flat_map(|_| [0.0, 0.0, 9.81]).collect();
        let mut arr = ImuArrays::new(
            None,
            Some(200.0),
            Strided::rows(&g, 10),
            Strided::rows(&a, 10),
        );
        arr.first_row = 10;
        assert_eq!(arr.time(0), row_time(10, 200.0));
        assert_eq!(arr.time(3), 13.0 * (1.0 / 200.0));
        let t = [0.0, 0.1, 0.1, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9];
        let arr = ImuArrays::new(Some(&t), None, Strided::rows(&g, 10), Strided::rows(&a, 10));
        let e = arr.validate().unwrap_err();
        assert_eq!(e.kind, ErrorKind::TimeNotIncreasing);
        assert!(
            e.message.contains("row 2") && e.message.contains("repeats"),
            "{}",
            e.message
        );
        let mut arr = ImuArrays::new(
            Some(&t[3..]),
            None,
            Strided::rows(&g, 7),
            Strided::rows(&a, 7),
        );
        arr.prev_t_s = Some(0.3);
        arr.first_row = 3;
        let e = arr.validate().unwrap_err();
        assert!(e.message.contains("row 3"), "{}", e.message);
        let both = ImuArrays::new(
            Some(&t),
            Some(1.0),
            Strided::rows(&g, 10),
            Strided::rows(&a, 10),
        );
        assert!(both.validate().is_err());
        let short = ImuArrays::new(
            None,
            Some(1.0),
            Strided::rows(&g, 10),
            Strided::rows(&a[..27], 9),
        );
        assert!(short.validate().unwrap_err().message.contains("acc has 9"));
    }

    #[test]
    fn angle_stats_match_two_pass_values() {
        let xs = [1.0, 2.5, -0.5, 4.0, 3.0];
        let mut s = AngleStats::default();
        for x in xs {
            s.push(x);
        }
        s.push(f64::NAN);
        let m = xs.iter().sum::<f64>() / 5.0;
        let v = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / 4.0;
        assert_eq!(s.n, 5);
        assert!((s.mean_deg - m).abs() < 1e-15);
        assert!((s.std_deg - v.sqrt()).abs() < 1e-14);
        assert_eq!((s.min_deg, s.max_deg), (-0.5, 4.0));
    }

    #[test]
    fn summary_equals_statistics_of_the_fuse_output() {
        let (s, ..) = text(800);
        let cfg = FilterConfig::new(FilterKind::Dynamic);
        let rows = csv_rows(&s, &cfg);
        let mut r = ImuCsvReader::new(s.as_bytes(), "m.csv", &ReadOptions::default()).unwrap();
        let sum = summarize_reader(&mut r, &cfg, &FuseOptions::default()).unwrap();
        let mut inc = AngleStats::default();
        for row in &rows {
            inc.push(row[7].parse().unwrap());
        }
        assert_eq!(sum.tilt.inclination, inc);
        assert_eq!(sum.report.counts.samples, 800);
        assert_eq!(sum.tilt.t_first_s, 0.0);
        assert_eq!(sum.tilt.t_last_s, 7.99);
    }
}
