//! The fusion stage of the pipeline: a filter registry and a streaming
//! CSV → CSV run.
//!
//! * [`FilterConfig`] names a filter and its gains and builds it
//!   ([`FilterConfig::build`]) as a `Box<dyn AttitudeFilter>`;
//! * [`Fuser`] feeds rows of a recording to one filter, keeping the time step
//!   and handling sensor dropouts (NaN gyro or accelerometer values: the
//!   filter keeps its state through them);
//! * [`fuse`] streams a recording through a filter and writes
//!   `t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status`, one row per
//!   input row, in constant memory.
//!
//! The filters are those of [`clino_core::filter`]; their equations and
//! sources are documented there.
//!
//! ```
//! use clino::fusion::{FilterConfig, FilterKind, FuseOptions, fuse};
//! use clino::io::{ImuCsvReader, ReadOptions};
//!
//! // 22 s of a real recording embedded in the library (BROAD trial 07).
//! let text = clino::demo::BROAD_EXCERPT;
//! let mut reader = ImuCsvReader::new(text.as_bytes(), "excerpt.csv", &ReadOptions::default())?;
//! let mut out = Vec::new();
//! let config = FilterConfig::new(FilterKind::Madgwick);
//! let report = fuse(&mut reader, &mut out, &config, &FuseOptions::default())?;
//! assert_eq!(report.rows, 6286);
//! assert_eq!(report.dropouts, 0);
//! let csv = String::from_utf8(out).unwrap();
//! assert!(csv.starts_with("t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status\n"));
//! assert_eq!(csv.lines().count(), 6287);
//! # Ok::<(), clino::Error>(())
//! ```

use std::io::{Read, Write};
use std::str::FromStr;

use clino_core::compensate::Compensated;
use clino_core::filter::{
    Complementary, Dynamic, DynamicParams, Integrator, Madgwick, Mahony, Poisson,
};
use clino_core::tilt::{RollPitch, inclination};
use clino_core::{Attitude, AttitudeFilter, Step, Vec3};
use serde::Serialize;

use crate::io::{CsvLineWriter, ImuCsvReader, ImuRow};
use crate::{Error, ErrorKind, Result};

/// The attitude filters that can be named on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum FilterKind {
    /// Gyro-only strapdown integration of the Poisson equation ([`Poisson`]).
    Poisson,
    /// The DCM complementary filter of the MPU6050 + Arduino inclinometer ([`Complementary`]).
    Complementary,
    /// Mahony's proportional-integral filter ([`Mahony`]).
    Mahony,
    /// Madgwick's gradient-descent filter ([`Madgwick`]).
    Madgwick,
    /// clino's dynamic inclinometer filter ([`Dynamic`]): bounded-velocity
    /// tilt loop with gyro-bias, rest and rotation-rate adaptation.
    Dynamic,
}

impl FilterKind {
    /// Every filter, in the order tables list them.
    pub const ALL: [FilterKind; 5] = [
        FilterKind::Poisson,
        FilterKind::Complementary,
        FilterKind::Mahony,
        FilterKind::Madgwick,
        FilterKind::Dynamic,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Poisson => "poisson",
            FilterKind::Complementary => "complementary",
            FilterKind::Mahony => "mahony",
            FilterKind::Madgwick => "madgwick",
            FilterKind::Dynamic => "dynamic",
        }
    }

    /// Parse a comma-separated list of names (`"mahony,madgwick"`, or `"all"`).
    pub fn parse_list(s: &str) -> Result<Vec<FilterKind>> {
        if s.trim().eq_ignore_ascii_case("all") {
            return Ok(Self::ALL.to_vec());
        }
        let mut out = Vec::new();
        for name in s.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let k: FilterKind = name.parse()?;
            if !out.contains(&k) {
                out.push(k);
            }
        }
        if out.is_empty() {
            return Err(Error::new(ErrorKind::InvalidInput, "no filter named"));
        }
        Ok(out)
    }
}

impl std::fmt::Display for FilterKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FilterKind {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        let s = s.trim().to_ascii_lowercase();
        Self::ALL
            .into_iter()
            .find(|k| k.name() == s)
            .ok_or_else(|| {
                let names: Vec<&str> = Self::ALL.iter().map(|k| k.name()).collect();
                Error::new(
                    ErrorKind::InvalidInput,
                    format!("unknown filter '{s}' (known: {})", names.join(", ")),
                )
            })
    }
}

/// Gains of every filter (each filter reads its own).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Gains {
    /// Complementary blend k per sample, 0..1 (default 0.05; its time constant
    /// is −Ts/ln(1 − k), about 0.19 s at 100 Hz, 0.068 s at 285.7 Hz).
    pub complementary_k: f64,
    /// Mahony proportional gain kp, rad/s per unit of error (default 1.0).
    pub mahony_kp: f64,
    /// Mahony integral gain ki, rad/s² per unit of error (default 0.02).
    pub mahony_ki: f64,
    /// Madgwick gradient step β, rad/s (default 0.1).
    pub madgwick_beta: f64,
    /// Gyro integration step for `poisson` and `complementary`; `None` keeps each
    /// filter's default (exact for `poisson`, rectangle for `complementary`,
    /// as in the MPU6050 + Arduino inclinometer).
    #[serde(skip)]
    pub integrator: Option<Integrator>,
    /// Base loop bandwidth p₀ of the dynamic filter, rad/s (default 0.15;
    /// see [`DynamicParams::bandwidth_rad_s`] for its meaning).
    pub dynamic_bandwidth_rad_s: f64,
}

impl Default for Gains {
    fn default() -> Self {
        Self {
            complementary_k: 0.05,
            mahony_kp: 1.0,
            mahony_ki: 0.02,
            madgwick_beta: 0.1,
            integrator: None,
            dynamic_bandwidth_rad_s: DynamicParams::default().bandwidth_rad_s,
        }
    }
}

/// Which filter, with which gains, and the pipeline stages around it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterConfig {
    /// The filter.
    pub kind: FilterKind,
    /// Its gains.
    pub gains: Gains,
    /// Lever arm of the sensor from a point on the rotation axis, m, body
    /// frame: tangential and centripetal acceleration are removed before
    /// fusion ([`Compensated`]).
    pub lever_arm_m: Option<Vec3>,
    /// Offline smoothing over the whole recording ([`crate::smooth`]); only
    /// for the dynamic filter. A streaming [`Fuser`] runs the real-time filter;
    /// [`fuse`] and [`crate::eval`] buffer the recording when this is set.
    pub offline: bool,
}

impl FilterConfig {
    /// A filter with default gains and no extra stage.
    pub fn new(kind: FilterKind) -> Self {
        Self {
            kind,
            gains: Gains::default(),
            lever_arm_m: None,
            offline: false,
        }
    }

    /// The same stages with other gains.
    pub fn with_gains(mut self, gains: Gains) -> Self {
        self.gains = gains;
        self
    }

    /// The same filter with lever-arm compensation (m, body frame).
    pub fn with_lever_arm(mut self, lever_arm_m: Option<Vec3>) -> Self {
        self.lever_arm_m = lever_arm_m;
        self
    }

    /// The same filter, smoothed offline over the whole recording.
    pub fn with_offline(mut self, offline: bool) -> Self {
        self.offline = offline;
        self
    }

    /// The column label of this configuration in tables: the filter's name,
    /// `+offline` when smoothed, `+lever` when compensated.
    pub fn label(&self) -> String {
        let mut s = self.kind.name().to_string();
        if self.offline {
            s.push_str("+offline");
        }
        if self.lever_arm_m.is_some() {
            s.push_str("+lever");
        }
        s
    }

    /// The dynamic filter's parameters for these gains.
    pub fn dynamic_params(&self) -> DynamicParams {
        DynamicParams {
            bandwidth_rad_s: self.gains.dynamic_bandwidth_rad_s,
            ..DynamicParams::default()
        }
    }

    /// Check the gains, the lever arm and the stages.
    pub fn validate(&self) -> Result<()> {
        let g = &self.gains;
        let check = |name: &str, v: f64, min_exclusive: bool, max: f64| {
            let lower_ok = if min_exclusive { v > 0.0 } else { v >= 0.0 };
            if v.is_finite() && lower_ok && v <= max {
                Ok(())
            } else {
                Err(Error::new(
                    ErrorKind::InvalidInput,
                    format!("gain {name} must be a number in [0, {max}], got {v}"),
                ))
            }
        };
        // Every gain is checked, whichever filter is built: a bad flag is bad input.
        check("k", g.complementary_k, false, 1.0)?;
        check("kp", g.mahony_kp, false, f64::MAX)?;
        check("ki", g.mahony_ki, false, f64::MAX)?;
        check("beta", g.madgwick_beta, false, f64::MAX)?;
        check("bandwidth", g.dynamic_bandwidth_rad_s, true, 100.0)?;
        if let Some(p) = self.lever_arm_m
            && !p.iter().all(|v| v.is_finite())
        {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "lever arm must be three finite numbers (m)",
            ));
        }
        if self.offline && self.kind != FilterKind::Dynamic {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "offline smoothing is available for the dynamic filter, not for {}",
                    self.kind
                ),
            ));
        }
        Ok(())
    }

    /// Build the real-time filter (with its lever-arm stage), checking the gains.
    pub fn build(&self) -> Result<Box<dyn AttitudeFilter + Send>> {
        self.validate()?;
        let g = &self.gains;
        fn wrap<F: AttitudeFilter + Send + 'static>(
            f: F,
            la: Option<Vec3>,
        ) -> Box<dyn AttitudeFilter + Send> {
            match la {
                Some(p) => Box::new(Compensated::new(f, p)),
                None => Box::new(f),
            }
        }
        let la = self.lever_arm_m;
        Ok(match self.kind {
            FilterKind::Poisson => wrap(Poisson::new(g.integrator.unwrap_or_default()), la),
            FilterKind::Complementary => wrap(
                Complementary::with_integrator(
                    g.complementary_k,
                    g.integrator.unwrap_or(Integrator::Rectangle),
                ),
                la,
            ),
            FilterKind::Mahony => wrap(Mahony::new(g.mahony_kp, g.mahony_ki), la),
            FilterKind::Madgwick => wrap(Madgwick::new(g.madgwick_beta), la),
            FilterKind::Dynamic => wrap(Dynamic::new(self.dynamic_params()), la),
        })
    }

    /// Offline attitudes of a whole recording held in memory (dynamic filter,
    /// [`crate::smooth::smooth`]): one per row; `None` for rows before the first
    /// usable one. Dropout rows (NaN gyro or accelerometer) hold the attitude
    /// of the row before; the smoother sees only usable rows, with time steps
    /// spanning the gaps.
    pub fn smooth_rows(&self, rows: &[ImuRow]) -> Result<Vec<Option<Attitude>>> {
        self.validate()?;
        let usable: Vec<usize> = (0..rows.len())
            .filter(|&k| !rows[k].has_dropout())
            .collect();
        let mut gyr = Vec::with_capacity(usable.len());
        let mut acc = Vec::with_capacity(usable.len());
        let mut dt = Vec::with_capacity(usable.len());
        for (j, &k) in usable.iter().enumerate() {
            gyr.push(rows[k].sample.gyr_rad_s);
            acc.push(rows[k].sample.acc_m_s2);
            dt.push(if j == 0 {
                // nominal period for the first sample (used only to initialise)
                usable
                    .get(1)
                    .map_or(0.01, |&k1| rows[k1].sample.t_s - rows[k].sample.t_s)
            } else {
                rows[k].sample.t_s - rows[usable[j - 1]].sample.t_s
            });
        }
        let opts = crate::smooth::SmoothOptions {
            params: self.dynamic_params(),
            lever_arm_m: self.lever_arm_m,
            ..Default::default()
        };
        let q = crate::smooth::smooth(&gyr, &acc, &dt, &opts);
        let mut out = vec![None; rows.len()];
        let mut last = None;
        let mut j = 0;
        for (k, slot) in out.iter_mut().enumerate() {
            if j < usable.len() && usable[j] == k {
                last = q.get(j).copied();
                j += 1;
            }
            *slot = last;
        }
        Ok(out)
    }
}

/// What happened to one row, as written in the `status` column.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RowStatus {
    /// Not initialised yet (no usable accelerometer reading so far): the attitude is NaN.
    Waiting,
    /// The row initialised the attitude from the accelerometer.
    Initialised,
    /// Gyro propagation and accelerometer correction.
    Fused,
    /// Gyro propagation only (gyro-only filter, or zero accelerometer).
    GyroOnly,
    /// NaN in the gyro or accelerometer: the filter kept its state.
    Dropout,
}

impl RowStatus {
    /// The word written in the `status` column.
    pub fn as_str(self) -> &'static str {
        match self {
            RowStatus::Waiting => "waiting",
            RowStatus::Initialised => "init",
            RowStatus::Fused => "fused",
            RowStatus::GyroOnly => "gyro_only",
            RowStatus::Dropout => "dropout",
        }
    }
}

/// Counts of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FuseReport {
    /// Rows read (= rows written).
    pub rows: u64,
    /// Rows that initialised the attitude (1, or 0 if none could).
    pub initialised: u64,
    /// Rows fused (gyro + accelerometer).
    pub fused: u64,
    /// Rows used for the gyro only.
    pub gyro_only: u64,
    /// Rows before the filter could initialise.
    pub waiting: u64,
    /// Rows with NaN gyro or accelerometer values (the filter kept its state).
    pub dropouts: u64,
    /// Line of the first such row.
    pub first_dropout_line: Option<u64>,
}

/// Options of a run.
#[derive(Clone, Copy, Debug, Default)]
pub struct FuseOptions<'a> {
    /// Make a NaN gyro or accelerometer value an error (naming its line and column).
    pub strict: bool,
    /// Calibrate every sample with this file before fusion (temperature from
    /// the `temp_c` column where the model needs it).
    pub calibration: Option<&'a crate::calib::CalibrationFile>,
}

/// Feeds the rows of one recording to one filter.
pub struct Fuser {
    filter: Box<dyn AttitudeFilter + Send>,
    last_t: Option<f64>,
    report: FuseReport,
}

impl Fuser {
    /// A fuser around a freshly built filter.
    pub fn new(config: &FilterConfig) -> Result<Self> {
        Ok(Self {
            filter: config.build()?,
            last_t: None,
            report: FuseReport::default(),
        })
    }

    /// The filter.
    pub fn filter(&self) -> &dyn AttitudeFilter {
        &*self.filter
    }

    /// Counts so far.
    pub fn report(&self) -> &FuseReport {
        &self.report
    }

    /// Process one row. The time step is the time since the last row the
    /// filter used, so a dropout row's interval is carried into the next one.
    #[inline]
    pub fn step(&mut self, row: &ImuRow) -> RowStatus {
        self.report.rows += 1;
        if row.has_dropout() {
            self.report.dropouts += 1;
            self.report.first_dropout_line.get_or_insert(row.line);
            return RowStatus::Dropout;
        }
        let t = row.sample.t_s;
        // Before the first usable row dt is never used (the filter initialises
        // from the accelerometer); any positive value passes the filter's check.
        let dt = self.last_t.map_or(f64::MIN_POSITIVE, |t0| t - t0);
        let step = self
            .filter
            .update(row.sample.gyr_rad_s, row.sample.acc_m_s2, dt);
        let status = match step {
            Step::Fused => RowStatus::Fused,
            Step::GyroOnly => RowStatus::GyroOnly,
            Step::Initialised => RowStatus::Initialised,
            Step::Waiting => RowStatus::Waiting,
            // Finite input and increasing time: only a filter-specific refusal
            // lands here; the state is unchanged, like a dropout.
            Step::Rejected => RowStatus::Dropout,
        };
        match status {
            RowStatus::Fused => self.report.fused += 1,
            RowStatus::GyroOnly => self.report.gyro_only += 1,
            RowStatus::Waiting => self.report.waiting += 1,
            RowStatus::Dropout => {
                self.report.dropouts += 1;
                self.report.first_dropout_line.get_or_insert(row.line);
            }
            RowStatus::Initialised => self.report.initialised += 1,
        }
        if !matches!(status, RowStatus::Waiting | RowStatus::Dropout) {
            self.last_t = Some(t);
        }
        status
    }

    /// The current attitude, `None` before initialisation.
    #[inline]
    pub fn attitude(&self) -> Option<Attitude> {
        self.filter.is_initialised().then(|| self.filter.attitude())
    }
}

/// The error for a dropout row under `strict`.
fn dropout_error<R: Read>(reader: &ImuCsvReader<R>, row: &ImuRow) -> Error {
    let col = reader.dropout_column(row).unwrap_or("?").to_string();
    Error::new(
        ErrorKind::InvalidInput,
        "NaN in a gyro or accelerometer column (sensor dropout); without --strict the filter holds its state",
    )
    .in_file(reader.file())
    .at_line(row.line)
    .at_column(col)
}

/// The output header of [`fuse`].
pub const FUSE_HEADER: [&str; 9] = [
    "t_s",
    "qw",
    "qx",
    "qy",
    "qz",
    "roll_deg",
    "pitch_deg",
    "inclination_deg",
    "status",
];

/// Stream a recording through one filter and write one output row per input
/// row: `t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status`.
///
/// The quaternion rotates body to ENU (Hamilton, scalar first); roll and pitch
/// are aerospace z-y-x ([`RollPitch`]), inclination the angle of body z from
/// vertical ([`inclination`]). Before the filter has initialised the
/// attitude columns are NaN (`status` = `waiting`); on a dropout row they hold
/// the last attitude (`status` = `dropout`), or the run stops with an error
/// when `opts.strict` is set.
///
/// Memory does not depend on the length of the recording.
pub fn fuse<R: Read, W: Write>(
    reader: &mut ImuCsvReader<R>,
    writer: W,
    config: &FilterConfig,
    opts: &FuseOptions,
) -> Result<FuseReport> {
    fuse_traced(reader, writer, config, opts, None)
}

/// [`fuse`], also keeping a bounded-memory trace of roll, pitch and
/// inclination for a plot ([`TiltTrace`]).
pub fn fuse_traced<R: Read, W: Write>(
    reader: &mut ImuCsvReader<R>,
    writer: W,
    config: &FilterConfig,
    opts: &FuseOptions,
    mut trace: Option<&mut TiltTrace>,
) -> Result<FuseReport> {
    let mut fuser = Fuser::new(config)?;
    let mut out = CsvLineWriter::new(writer);
    let io_err = |e: std::io::Error| Error::from(e).in_file("output");
    out.header(&FUSE_HEADER).map_err(io_err)?;
    let calibrate = |reader: &ImuCsvReader<R>, row: &mut ImuRow| -> Result<()> {
        if let Some(cal) = opts.calibration
            && !row.has_dropout()
        {
            row.sample = cal.apply(&row.sample).map_err(|e| Error {
                file: Some(reader.file().to_path_buf()),
                line: Some(row.line),
                ..e
            })?;
        }
        Ok(())
    };
    if config.offline {
        // the smoother needs the whole recording: rows are held in memory
        let mut rows = Vec::new();
        while let Some(mut row) = reader.next_row()? {
            if row.has_dropout() && opts.strict {
                return Err(dropout_error(reader, &row));
            }
            calibrate(reader, &mut row)?;
            rows.push(row);
        }
        let qs = config.smooth_rows(&rows)?;
        let mut report = FuseReport::default();
        for (row, q) in rows.iter().zip(&qs) {
            report.rows += 1;
            let status = if row.has_dropout() {
                report.dropouts += 1;
                report.first_dropout_line.get_or_insert(row.line);
                RowStatus::Dropout
            } else if q.is_none() {
                report.waiting += 1;
                RowStatus::Waiting
            } else {
                report.fused += 1;
                RowStatus::Fused
            };
            out.f64(row.sample.t_s);
            write_attitude(&mut out, *q, row.sample.t_s, trace.as_deref_mut());
            out.str(status.as_str());
            out.end_row().map_err(io_err)?;
        }
        out.finish().map_err(io_err)?;
        return Ok(report);
    }
    while let Some(mut row) = reader.next_row()? {
        calibrate(reader, &mut row)?;
        let status = fuser.step(&row);
        if status == RowStatus::Dropout && opts.strict {
            return Err(dropout_error(reader, &row));
        }
        out.f64(row.sample.t_s);
        write_attitude(
            &mut out,
            fuser.attitude(),
            row.sample.t_s,
            trace.as_deref_mut(),
        );
        out.str(status.as_str());
        out.end_row().map_err(io_err)?;
    }
    out.finish().map_err(io_err)?;
    Ok(*fuser.report())
}

/// Write the seven attitude columns (NaN before initialisation) and feed the trace.
fn write_attitude<W: Write>(
    out: &mut CsvLineWriter<W>,
    q: Option<Attitude>,
    t_s: f64,
    trace: Option<&mut TiltTrace>,
) {
    match q {
        Some(q) => {
            out.f64(q.w);
            out.f64(q.i);
            out.f64(q.j);
            out.f64(q.k);
            let rp = RollPitch::from_attitude(&q);
            let deg = [
                rp.roll.to_degrees(),
                rp.pitch.to_degrees(),
                inclination(&q).to_degrees(),
            ];
            for d in deg {
                out.f64(d);
            }
            if let Some(t) = trace {
                t.push(t_s, deg);
            }
        }
        None => {
            for _ in 0..7 {
                out.f64(f64::NAN);
            }
        }
    }
}

/// A decimated record of roll, pitch and inclination (degrees) against time,
/// in bounded memory whatever the length of the run: every `stride`-th row is
/// kept; when `capacity` points are held, every other one is dropped and the
/// stride doubles. So between `capacity / 2` and `capacity` evenly spaced
/// rows are kept at the end.
#[derive(Clone, Debug)]
pub struct TiltTrace {
    capacity: usize,
    stride: u64,
    seen: u64,
    points: Vec<(f64, [f64; 3])>,
}

impl TiltTrace {
    /// A trace holding at most `capacity` points (at least 2).
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity: capacity.max(2),
            stride: 1,
            seen: 0,
            points: Vec::new(),
        }
    }

    /// Offer one row: time (s) and [roll, pitch, inclination] (degrees).
    pub fn push(&mut self, t_s: f64, deg: [f64; 3]) {
        if self.seen % self.stride == 0 {
            if self.points.len() == self.capacity {
                let mut k = 0;
                self.points.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
                // keep the phase: this row is kept only if it falls on the new stride
                if self.seen % self.stride != 0 {
                    self.seen += 1;
                    return;
                }
            }
            self.points.push((t_s, deg));
        }
        self.seen += 1;
    }

    /// The points kept: (t_s, [roll_deg, pitch_deg, inclination_deg]).
    pub fn points(&self) -> &[(f64, [f64; 3])] {
        &self.points
    }

    /// Draw roll, pitch and inclination against time to an SVG or PNG file.
    pub fn plot(&self, path: &std::path::Path, title: &str) -> Result<()> {
        let series: Vec<crate::report::Series> = ["roll_deg", "pitch_deg", "inclination_deg"]
            .iter()
            .enumerate()
            .map(|(k, name)| {
                crate::report::Series::line(
                    *name,
                    self.points.iter().map(|(t, d)| (*t, d[k])).collect(),
                )
            })
            .collect();
        let spec = crate::report::PlotSpec {
            title: title.to_string(),
            x_label: "t (s)".into(),
            y_label: "angle (deg)".into(),
            ..Default::default()
        };
        crate::report::line_plot(path, &spec, &series)
    }
}

/// The fusion section of `clino demo`: every filter, default gains, on the
/// embedded BROAD excerpt ([`crate::demo::BROAD_EXCERPT`]), scored with the
/// BROAD inclination error ([`crate::eval`]). Deterministic, well under a second.
pub fn demo_summary() -> Result<String> {
    let mut reader = ImuCsvReader::new(
        crate::demo::BROAD_EXCERPT.as_bytes(),
        "broad_07_excerpt.csv",
        &crate::io::ReadOptions::default(),
    )?;
    let configs: Vec<FilterConfig> = FilterKind::ALL
        .iter()
        .map(|k| FilterConfig::new(*k))
        .collect();
    let rec = crate::eval::score_reader(&mut reader, &configs)?;
    let secs = reader.rows_read() as f64 / 285.714;
    let mut s = format!(
        "Attitude filters on {:.0} s of real IMU data (BROAD trial 07, fast rotation, {} rows at 285.7 Hz),\n\
         scored against optical motion capture: inclination RMSE over the {} moving samples.\n\n",
        secs,
        rec.rows,
        rec.scores.first().map_or(0, |s| s.scored)
    );
    s.push_str(&format!(
        "  {:<14} {:>18}  {}\n",
        "filter", "inclination RMSE", "gains"
    ));
    let g = Gains::default();
    for (c, sc) in configs.iter().zip(&rec.scores) {
        let gains = match c.kind {
            FilterKind::Poisson => "gyro only (exact step)".to_string(),
            FilterKind::Complementary => format!("k = {} per sample", g.complementary_k),
            FilterKind::Mahony => format!("kp = {}, ki = {}", g.mahony_kp, g.mahony_ki),
            FilterKind::Madgwick => format!("beta = {} rad/s", g.madgwick_beta),
            FilterKind::Dynamic => format!(
                "bandwidth = {} rad/s (clino's own)",
                g.dynamic_bandwidth_rad_s
            ),
        };
        s.push_str(&format!(
            "  {:<14} {:>16.2} °  {}\n",
            sc.filter, sc.rmse_deg, gains
        ));
    }
    s.push_str("\nData: BROAD, CC BY 4.0, Laidig, Caruso, Cereatti, Seel, Data 6(7) 2021.\n");
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::ReadOptions;

    const HEAD: &str = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n";

    fn run(text: &str, kind: FilterKind, strict: bool) -> Result<(FuseReport, String)> {
        let mut r = ImuCsvReader::new(text.as_bytes(), "mem.csv", &ReadOptions::default())?;
        let mut out = Vec::new();
        let rep = fuse(
            &mut r,
            &mut out,
            &FilterConfig::new(kind),
            &FuseOptions {
                strict,
                ..Default::default()
            },
        )?;
        Ok((rep, String::from_utf8(out).unwrap()))
    }

    #[test]
    fn names_round_trip_and_unknown_is_an_error() {
        for k in FilterKind::ALL {
            assert_eq!(k.name().parse::<FilterKind>().unwrap(), k);
        }
        let e = "kalman".parse::<FilterKind>().unwrap_err();
        assert!(e.message.contains("kalman") && e.message.contains("madgwick"));
        assert_eq!(
            FilterKind::parse_list("mahony, madgwick,mahony").unwrap(),
            vec![FilterKind::Mahony, FilterKind::Madgwick]
        );
        assert_eq!(FilterKind::parse_list("all").unwrap().len(), 5);
        assert!(FilterKind::parse_list(",").is_err());
    }

    #[test]
    fn stages_and_bad_gains_are_checked() {
        let c =
            FilterConfig::new(FilterKind::Mahony).with_lever_arm(Some(Vec3::new(0.1, 0.0, 0.0)));
        assert!(c.build().is_ok());
        assert_eq!(c.label(), "mahony+lever");
        let c = FilterConfig::new(FilterKind::Mahony).with_lever_arm(Some(Vec3::new(
            f64::NAN,
            0.0,
            0.0,
        )));
        assert!(c.build().err().unwrap().message.contains("lever arm"));
        let c = FilterConfig::new(FilterKind::Mahony).with_offline(true);
        assert!(c.build().err().unwrap().message.contains("offline"));
        let c = FilterConfig::new(FilterKind::Dynamic).with_offline(true);
        assert!(c.build().is_ok());
        assert_eq!(c.label(), "dynamic+offline");
        let mut c = FilterConfig::new(FilterKind::Dynamic);
        c.gains.dynamic_bandwidth_rad_s = 0.0;
        assert!(c.build().is_err());
        let mut c = FilterConfig::new(FilterKind::Complementary);
        c.gains.complementary_k = 1.5;
        assert!(c.build().is_err());
        c.gains.complementary_k = f64::NAN;
        assert!(c.build().is_err());
        let mut c = FilterConfig::new(FilterKind::Madgwick);
        c.gains.madgwick_beta = -0.1;
        assert!(c.build().is_err());
    }

    #[test]
    fn offline_writes_one_row_per_input_row_and_holds_through_dropouts() {
        let r = 15f64.to_radians();
        let (ay, az) = (9.81 * r.sin(), 9.81 * r.cos());
        let mut text = String::from(HEAD);
        for i in 0..400 {
            let g = if i == 200 {
                "nan".to_string()
            } else {
                "0".to_string()
            };
            text.push_str(&format!("{},{g},0,0,0,{ay},{az}\n", i as f64 * 0.01));
        }
        let mut rd =
            ImuCsvReader::new(text.as_bytes(), "mem.csv", &ReadOptions::default()).unwrap();
        let mut out = Vec::new();
        let cfg = FilterConfig::new(FilterKind::Dynamic).with_offline(true);
        let rep = fuse(&mut rd, &mut out, &cfg, &FuseOptions::default()).unwrap();
        let out = String::from_utf8(out).unwrap();
        assert_eq!(rep.rows, 400);
        assert_eq!(rep.dropouts, 1);
        assert_eq!(out.lines().count(), 401);
        let last: Vec<&str> = out.lines().last().unwrap().split(',').collect();
        let incl: f64 = last[7].parse().unwrap();
        assert!((incl - 15.0).abs() < 1e-3, "{incl}");
        assert!(out.lines().nth(201).unwrap().ends_with(",dropout"));
    }

    #[test]
    fn one_output_row_per_input_row_with_static_tilt() {
        // 20° roll at rest: every filter reports 20° inclination and roll.
        let r = 20f64.to_radians();
        let (ay, az) = (9.81 * r.sin(), 9.81 * r.cos());
        let mut text = String::from(HEAD);
        for i in 0..50 {
            text.push_str(&format!("{},0,0,0,0,{ay},{az}\n", i as f64 * 0.01));
        }
        for k in FilterKind::ALL {
            let (rep, out) = run(&text, k, false).unwrap();
            assert_eq!(rep.rows, 50);
            let lines: Vec<&str> = out.lines().collect();
            assert_eq!(lines.len(), 51);
            assert_eq!(lines[0], FUSE_HEADER.join(","));
            let last: Vec<&str> = lines[50].split(',').collect();
            let roll: f64 = last[5].parse().unwrap();
            let incl: f64 = last[7].parse().unwrap();
            // Madgwick normalises its gradient, so at equilibrium rounding noise
            // still moves it by up to β·dt per step (0.1 rad/s · 0.01 s ≈ 0.06°).
            let tol = if k == FilterKind::Madgwick { 0.2 } else { 1e-9 };
            assert!((roll - 20.0).abs() < tol, "{k}: roll {roll}");
            assert!((incl - 20.0).abs() < tol, "{k}: incl {incl}");
            assert!(lines[1].ends_with(",init"));
        }
    }

    #[test]
    fn dropout_rows_hold_state_and_are_counted() {
        let mut text = String::from(HEAD);
        text.push_str("0.00,0,0,0,0,0,9.81\n");
        text.push_str("0.01,0,0,0.5,0,0,9.81\n");
        text.push_str("0.02,nan,0,0.5,0,0,9.81\n");
        text.push_str("0.03,0,0,0.5,0,,9.81\n");
        text.push_str("0.04,0,0,0.5,0,0,9.81\n");
        let (rep, out) = run(&text, FilterKind::Poisson, false).unwrap();
        assert_eq!(rep.dropouts, 2);
        assert_eq!(rep.first_dropout_line, Some(4));
        let rows: Vec<Vec<&str>> = out
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .collect();
        assert_eq!(rows[2][8], "dropout");
        assert_eq!(rows[3][8], "dropout");
        // Held: same quaternion as the row before.
        assert_eq!(rows[2][1..5], rows[1][1..5]);
        assert_eq!(rows[3][1..5], rows[1][1..5]);
        // After the gap the yaw covers the whole 0.03 s at 0.5 rad/s: 0.01 + 0.03 s in all.
        let qz: f64 = rows[4][4].parse().unwrap();
        let qw: f64 = rows[4][1].parse().unwrap();
        let yaw = 2.0 * qz.atan2(qw);
        assert!((yaw - 0.5 * 0.04).abs() < 1e-12, "yaw {yaw}");
    }

    #[test]
    fn strict_turns_a_dropout_into_an_error_with_line_and_column() {
        let mut text = String::from("# comment\n");
        text.push_str(HEAD);
        text.push_str("0.00,0,0,0,0,0,9.81\n");
        text.push_str("0.01,0,0,0,0,NaN,9.81\n");
        let e = run(&text, FilterKind::Mahony, true).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput);
        assert_eq!(e.line, Some(4));
        assert_eq!(e.column.as_deref(), Some("acc_y_m_s2"));
        assert_eq!(e.file.as_deref(), Some(std::path::Path::new("mem.csv")));
    }

    #[test]
    fn demo_summary_scores_every_filter_sensibly() {
        let s = demo_summary().unwrap();
        for k in FilterKind::ALL {
            assert!(s.contains(k.name()), "{s}");
        }
        let again = demo_summary().unwrap();
        assert_eq!(s, again);
    }

    #[test]
    fn tilt_trace_is_bounded_and_evenly_spaced() {
        let mut tr = TiltTrace::new(100);
        for i in 0..10_000u64 {
            tr.push(i as f64, [0.0, 0.0, i as f64]);
        }
        let p = tr.points();
        assert!(p.len() <= 100 && p.len() >= 50, "{}", p.len());
        let step = p[1].0 - p[0].0;
        assert_eq!(p[0].0, 0.0);
        assert!(
            p.windows(2).all(|w| w[1].0 - w[0].0 == step),
            "uneven spacing"
        );
        assert_eq!(step, 128.0);
    }

    #[test]
    fn waiting_rows_are_nan_until_a_usable_accelerometer() {
        let mut text = String::from(HEAD);
        text.push_str("0.00,0,0,0,0,0,0\n");
        text.push_str("0.01,0,0,0,0,0,9.81\n");
        let (rep, out) = run(&text, FilterKind::Madgwick, false).unwrap();
        assert_eq!(rep.waiting, 1);
        let first = out.lines().nth(1).unwrap();
        assert_eq!(first, "0.0,NaN,NaN,NaN,NaN,NaN,NaN,NaN,waiting");
    }
}
