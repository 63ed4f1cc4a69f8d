//! Streaming reader of IMU recordings in CSV.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use clino_core::{Attitude, G0, ImuSample, Vec3};
use nalgebra::Quaternion;

use super::TableReader;
use crate::{Error, ErrorKind, Result};

/// Unit of the gyroscope columns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GyroUnit {
    /// rad/s (columns `gyr_{x,y,z}_rad_s` or bare `gyr_{x,y,z}`).
    #[default]
    RadPerS,
    /// deg/s (columns `gyr_{x,y,z}_deg_s` or bare `gyr_{x,y,z}`), converted to rad/s on reading.
    DegPerS,
}

impl GyroUnit {
    /// Factor from this unit to rad/s.
    pub fn to_rad_s(self) -> f64 {
        match self {
            GyroUnit::RadPerS => 1.0,
            GyroUnit::DegPerS => core::f64::consts::PI / 180.0,
        }
    }
    fn suffix(self) -> &'static str {
        match self {
            GyroUnit::RadPerS => "rad_s",
            GyroUnit::DegPerS => "deg_s",
        }
    }
}

impl FromStr for GyroUnit {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "rad/s" | "rad_s" => Ok(GyroUnit::RadPerS),
            "deg/s" | "deg_s" | "dps" => Ok(GyroUnit::DegPerS),
            other => Err(Error::new(
                ErrorKind::InvalidInput,
                format!("unknown gyro unit '{other}' (expected rad/s or deg/s)"),
            )),
        }
    }
}

/// Unit of the accelerometer columns.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum AccelUnit {
    /// m/s² (columns `acc_{x,y,z}_m_s2` or bare `acc_{x,y,z}`).
    #[default]
    MPerS2,
    /// Multiples of g (columns `acc_{x,y,z}_g` or bare `acc_{x,y,z}`), converted
    /// to m/s² with [`ReadOptions::g`].
    G,
}

impl AccelUnit {
    fn suffix(self) -> &'static str {
        match self {
            AccelUnit::MPerS2 => "m_s2",
            AccelUnit::G => "g",
        }
    }
}

impl FromStr for AccelUnit {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim().to_ascii_lowercase().as_str() {
            "m/s2" | "m/s^2" | "m/s²" | "m_s2" => Ok(AccelUnit::MPerS2),
            "g" => Ok(AccelUnit::G),
            other => Err(Error::new(
                ErrorKind::InvalidInput,
                format!("unknown accelerometer unit '{other}' (expected m/s2 or g)"),
            )),
        }
    }
}

/// Time of row `k` (0-based) of a recording without a time column, s:
/// `k · (1/rate)`, the rule of [`ReadOptions::rate_hz`] (one rounding of
/// `1/rate`, then one of the product, so every reader of arrays or files
/// gives the same bits).
///
/// ```
/// use clino::io::{ImuCsvReader, ReadOptions, row_time};
/// let text = "gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n\
///             0,0,0,0,0,9.8\n0,0,0,0,0,9.8\n0,0,0,0,0,9.8\n0,0,0,0,0,9.8\n";
/// let opts = ReadOptions { rate_hz: Some(285.714), ..Default::default() };
/// let r = ImuCsvReader::new(text.as_bytes(), "m.csv", &opts).unwrap();
/// for (k, row) in r.enumerate() {
///     assert_eq!(row.unwrap().sample.t_s, row_time(k as u64, 285.714));
/// }
/// ```
pub fn row_time(k: u64, rate_hz: f64) -> f64 {
    k as f64 * (1.0 / rate_hz)
}

/// How to read a recording.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Unit of the gyroscope columns.
    pub gyro_unit: GyroUnit,
    /// Unit of the accelerometer columns.
    pub accel_unit: AccelUnit,
    /// Sample rate, Hz, used only when the file has no `t_s` column
    /// (time of row k is then k / rate).
    pub rate_hz: Option<f64>,
    /// Gravity used to convert [`AccelUnit::G`] to m/s² (default [`G0`]).
    pub g: f64,
    /// Read only time, gyro and accelerometer: magnetometer, temperature,
    /// reference and movement columns are neither parsed nor checked (they
    /// come out as `None`). About halves the parsing work of a BROAD file
    /// for runs that do not need them (`clino fuse`).
    pub imu_only: bool,
}

impl Default for ReadOptions {
    fn default() -> Self {
        Self {
            gyro_unit: GyroUnit::RadPerS,
            accel_unit: AccelUnit::MPerS2,
            rate_hz: None,
            g: G0,
            imu_only: false,
        }
    }
}

/// One row of a recording: the IMU sample and, when the file has them, the
/// reference attitude and the benchmark's movement flag.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuRow {
    /// 1-based line of this row in the file (comment lines counted).
    pub line: u64,
    /// The sample, SI units. Gyro or accelerometer components may be NaN
    /// (sensor dropouts are passed on, see [`ImuRow::has_dropout`]).
    pub sample: ImuSample,
    /// Reference attitude (body → ENU), when the file has `ref_q{w,x,y,z}` and
    /// all four are finite on this row (normalised on reading).
    pub ref_q: Option<Attitude>,
    /// The `movement` flag (non-zero → true), when the file has that column
    /// and the cell is finite.
    pub movement: Option<bool>,
}

impl ImuRow {
    /// True when a gyro or accelerometer value is not finite (a dropout).
    pub fn has_dropout(&self) -> bool {
        let s = &self.sample;
        !(s.gyr_rad_s.iter().all(|v| v.is_finite()) && s.acc_m_s2.iter().all(|v| v.is_finite()))
    }
}

/// Column indices found in the header.
#[derive(Clone, Debug)]
struct Columns {
    t: Option<usize>,
    gyr: [usize; 3],
    acc: [usize; 3],
    /// the units of the columns found (the flag's, or the one the names say)
    gyro_unit: GyroUnit,
    accel_unit: AccelUnit,
    mag: Option<[usize; 3]>,
    temp: Option<usize>,
    ref_q: Option<[usize; 4]>,
    movement: Option<usize>,
}

impl Columns {
    /// Every column index read.
    fn used(&self) -> Vec<usize> {
        let mut v: Vec<usize> = self.t.into_iter().chain(self.gyr).chain(self.acc).collect();
        v.extend(self.mag.into_iter().flatten());
        v.extend(self.temp);
        v.extend(self.ref_q.into_iter().flatten());
        v.extend(self.movement);
        v
    }
}

/// Streaming reader of an IMU recording in CSV (BROAD layout).
///
/// * Lines starting with `#` are comments; blank lines are skipped.
/// * The first other line is the header; columns are found by name:
///   `t_s`, `gyr_{x,y,z}_rad_s` (or `_deg_s`, see [`GyroUnit`]),
///   `acc_{x,y,z}_m_s2` (or `_g`, see [`AccelUnit`]), and optionally
///   `mag_{x,y,z}_uT`, `temp_c`, `ref_q{w,x,y,z}`, `movement`.
///   Names are matched without regard to case; other columns are ignored.
/// * Each row is parsed from one reused [`csv::ByteRecord`]: no allocation per
///   row, memory flat in the length of the file.
/// * Errors name the file, the 1-based line (comment lines counted) and the
///   column: missing columns, non-numeric cells, a row with the wrong number of
///   fields, time not strictly increasing, no data rows.
/// * Empty cells and `nan` in sensor columns are read as NaN and passed on:
///   sensor dropouts are the caller's to handle ([`ImuRow::has_dropout`]).
///
/// ```
/// use clino::io::{ImuCsvReader, ReadOptions};
/// let text = "# a comment\nt_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n\
///             0.00,0,0,0.1,0,0,9.81\n0.01,0,0,0.1,0,0,9.81\n";
/// let mut r = ImuCsvReader::new(text.as_bytes(), "inline.csv", &ReadOptions::default()).unwrap();
/// let row = r.next_row().unwrap().unwrap();
/// assert_eq!(row.line, 3);
/// assert_eq!(row.sample.gyr_rad_s.z, 0.1);
/// assert!(r.next_row().unwrap().is_some());
/// assert!(r.next_row().unwrap().is_none());
/// ```
pub struct ImuCsvReader<R: Read> {
    table: TableReader<R>,
    cols: Columns,
    gyr_scale: f64,
    acc_scale: f64,
    dt_rate: Option<f64>,
    last_t: Option<f64>,
    gaps: TimeGaps,
    failed: bool,
}

/// How many intervals set the nominal sample period of a recording.
const NOMINAL_INTERVALS: usize = 64;

/// An interval this many times the nominal period is a gap in time.
///
/// Five periods: sample-clock jitter and the odd late sample of a USB or
/// serial logger stay well below it; a lost packet of several samples, a
/// paused logger or two recordings joined together lie above it.
pub const GAP_FACTOR: f64 = 5.0;

/// One gap in time: where it ends and how long it is.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct TimeGap {
    /// 1-based line of the row after the gap.
    pub line: u64,
    /// Time of the row before the gap, s.
    pub after_t_s: f64,
    /// Length of the interval, s.
    pub size_s: f64,
}

/// The gaps in time of a recording ([`GAP_FACTOR`] × the nominal period,
/// the median of its first 64 intervals): how many, the first and the largest.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct TimeGaps {
    /// The nominal sample period, s (`None` before three intervals were seen).
    pub nominal_period_s: Option<f64>,
    /// Number of gaps.
    pub count: u64,
    /// The first gap.
    pub first: Option<TimeGap>,
    /// The largest gap.
    pub largest: Option<TimeGap>,
    #[serde(skip)]
    early: Vec<f64>,
}

impl TimeGaps {
    /// Look at the interval `dt` that ends at `line`.
    fn observe(&mut self, line: u64, after_t_s: f64, dt: f64) {
        if self.early.len() < NOMINAL_INTERVALS {
            self.early.push(dt);
            let mut v = self.early.clone();
            v.sort_by(f64::total_cmp);
            self.nominal_period_s = (v.len() >= 3).then(|| v[v.len() / 2]);
        }
        let Some(nominal) = self.nominal_period_s else {
            return;
        };
        if dt > GAP_FACTOR * nominal {
            let g = TimeGap {
                line,
                after_t_s,
                size_s: dt,
            };
            self.count += 1;
            self.first.get_or_insert(g);
            if self.largest.is_none_or(|l| dt > l.size_s) {
                self.largest = Some(g);
            }
        }
    }

    /// A one-line description for a summary, `None` without gaps.
    pub fn describe(&self) -> Option<String> {
        let l = self.largest?;
        Some(format!(
            "{} gap{} in time (more than {GAP_FACTOR} × the {:.4} s period); the largest is {:.4} s after t = {} s, before line {}",
            self.count,
            if self.count == 1 { "" } else { "s" },
            self.nominal_period_s.unwrap_or(f64::NAN),
            l.size_s,
            l.after_t_s,
            l.line
        ))
    }
}

impl ImuCsvReader<File> {
    /// Open a file.
    pub fn from_path(path: impl AsRef<Path>, opts: &ReadOptions) -> Result<Self> {
        Self::from_table(TableReader::open(path)?, opts)
    }
}

impl<R: Read> ImuCsvReader<R> {
    /// Read the header from `source`; `name` is the file name used in errors.
    pub fn new(source: R, name: impl Into<PathBuf>, opts: &ReadOptions) -> Result<Self> {
        Self::from_table(TableReader::new(source, name)?, opts)
    }

    /// The IMU reader over a table whose header has been read.
    pub fn from_table(table: TableReader<R>, opts: &ReadOptions) -> Result<Self> {
        if let Some(rate) = opts.rate_hz
            && !(rate.is_finite() && rate > 0.0)
        {
            return Err(table.err(
                ErrorKind::InvalidInput,
                format!("sample rate must be a positive number of Hz, got {rate}"),
            ));
        }
        if !(opts.g.is_finite() && opts.g > 0.0) {
            return Err(table.err(ErrorKind::InvalidInput, "gravity must be positive"));
        }
        let mut me = Self {
            table,
            cols: Columns {
                t: None,
                gyr: [0; 3],
                acc: [0; 3],
                gyro_unit: opts.gyro_unit,
                accel_unit: opts.accel_unit,
                mag: None,
                temp: None,
                ref_q: None,
                movement: None,
            },
            gyr_scale: opts.gyro_unit.to_rad_s(),
            acc_scale: match opts.accel_unit {
                AccelUnit::MPerS2 => 1.0,
                AccelUnit::G => opts.g,
            },
            dt_rate: opts.rate_hz.map(|r| 1.0 / r),
            last_t: None,
            gaps: TimeGaps::default(),
            failed: false,
        };
        me.cols = me.find_columns(opts)?;
        me.table.project(&me.cols.used());
        me.gyr_scale = me.cols.gyro_unit.to_rad_s();
        me.acc_scale = match me.cols.accel_unit {
            AccelUnit::MPerS2 => 1.0,
            AccelUnit::G => opts.g,
        };
        Ok(me)
    }

    /// The header names, in file order.
    pub fn header(&self) -> &[String] {
        self.table.header()
    }

    /// 1-based line of the header.
    pub fn header_line(&self) -> u64 {
        self.table.header_line()
    }

    /// The file name used in errors.
    pub fn file(&self) -> &Path {
        self.table.file()
    }

    /// The recording's notes before its first data row, and whether one
    /// came after it ([`TableReader::notes`]); complete once the first row
    /// has been read.
    pub fn notes(&self) -> (&[String], bool) {
        self.table.notes()
    }

    /// The gaps in time seen so far ([`TimeGaps`]).
    pub fn gaps(&self) -> &TimeGaps {
        &self.gaps
    }

    /// Number of data rows returned so far.
    pub fn rows_read(&self) -> u64 {
        self.table.rows_read()
    }

    /// True when the file has a reference attitude (`ref_q{w,x,y,z}`).
    pub fn has_reference(&self) -> bool {
        self.cols.ref_q.is_some()
    }

    /// True when the file has a `movement` column.
    pub fn has_movement(&self) -> bool {
        self.cols.movement.is_some()
    }

    /// Header name of the first gyro or accelerometer cell of `row` that the
    /// pipeline cannot use: not finite, or beyond the physical bounds
    /// ([`clino_core::pipeline::MAX_RATE_RAD_S`], [`clino_core::pipeline::MAX_SPECIFIC_FORCE_M_S2`]).
    pub fn unusable_column(&self, row: &ImuRow) -> Option<&str> {
        use clino_core::pipeline::{MAX_RATE_RAD_S, MAX_SPECIFIC_FORCE_M_S2};
        let s = &row.sample;
        let bad = |v: f64, max: f64| v.is_nan() || v.abs() > max;
        (0..3)
            .find(|&k| bad(s.gyr_rad_s[k], MAX_RATE_RAD_S))
            .map(|k| self.cols.gyr[k])
            .or_else(|| {
                (0..3)
                    .find(|&k| bad(s.acc_m_s2[k], MAX_SPECIFIC_FORCE_M_S2))
                    .map(|k| self.cols.acc[k])
            })
            .map(|i| self.table.header()[i].as_str())
    }

    fn err(&self, kind: ErrorKind, msg: impl Into<String>) -> Error {
        self.table.err(kind, msg)
    }

    fn find(&self, names: &[&str]) -> Option<usize> {
        self.table.find(names)
    }

    fn find_columns(&self, opts: &ReadOptions) -> Result<Columns> {
        let missing = |want: &str, hint: String| self.table.missing(want, &hint);
        let t = self.find(&["t_s"]);
        if let (Some(i), Some(_)) = (t, self.dt_rate) {
            // a flag that would silently do nothing is refused
            return Err(self
                .err(
                    ErrorKind::InvalidInput,
                    "the file has a time column, so a sample rate (--rate) would be ignored: drop --rate, or the time column",
                )
                .at_line(self.table.header_line())
                .at_column(self.table.header()[i].clone()));
        }
        if t.is_none() && self.dt_rate.is_none() {
            return Err(missing(
                "t_s",
                "no time column: give the sample rate (--rate HZ)".to_string(),
            ));
        }
        // one triad's columns: `{prefix}_{axis}_{unit}` or bare `{prefix}_{axis}`; when
        // missing, say whether the file has the other unit's column
        // one triad's columns: `{prefix}_{axis}_{unit}` or bare `{prefix}_{axis}` in
        // the flag's unit; else `{prefix}_{axis}_{other}` in the other unit (the
        // column name says it). Returns the columns and whether the other unit is used.
        let triad = |prefix: &str, unit: &str, other: &str| -> Result<([usize; 3], bool)> {
            let find3 = |names: &dyn Fn(&str) -> Vec<String>| -> Option<[usize; 3]> {
                let mut cols = [0; 3];
                for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                    let n = names(axis);
                    let refs: Vec<&str> = n.iter().map(String::as_str).collect();
                    cols[k] = self.find(&refs)?;
                }
                Some(cols)
            };
            if let Some(c) =
                find3(&|a| vec![format!("{prefix}_{a}_{unit}"), format!("{prefix}_{a}")])
            {
                return Ok((c, false));
            }
            if let Some(c) = find3(&|a| vec![format!("{prefix}_{a}_{other}")]) {
                return Ok((c, true));
            }
            let axis = ["x", "y", "z"]
                .into_iter()
                .find(|a| {
                    self.find(&[
                        &format!("{prefix}_{a}_{unit}"),
                        &format!("{prefix}_{a}"),
                        &format!("{prefix}_{a}_{other}"),
                    ])
                    .is_none()
                })
                .unwrap_or("x");
            Err(missing(
                &format!("{prefix}_{axis}_{unit}"),
                format!("or '{prefix}_{axis}_{other}', or bare '{prefix}_{axis}'"),
            ))
        };
        let other_gyro = match opts.gyro_unit {
            GyroUnit::RadPerS => GyroUnit::DegPerS,
            GyroUnit::DegPerS => GyroUnit::RadPerS,
        };
        let other_accel = match opts.accel_unit {
            AccelUnit::MPerS2 => AccelUnit::G,
            AccelUnit::G => AccelUnit::MPerS2,
        };
        let (gyr, g_other) = triad("gyr", opts.gyro_unit.suffix(), other_gyro.suffix())?;
        let (acc, a_other) = triad("acc", opts.accel_unit.suffix(), other_accel.suffix())?;
        let gyro_unit = if g_other { other_gyro } else { opts.gyro_unit };
        let accel_unit = if a_other {
            other_accel
        } else {
            opts.accel_unit
        };
        let mag = match (
            self.find(&["mag_x_uT"]),
            self.find(&["mag_y_uT"]),
            self.find(&["mag_z_uT"]),
        ) {
            (Some(x), Some(y), Some(z)) => Some([x, y, z]),
            _ => None,
        };
        let ref_names = ["ref_qw", "ref_qx", "ref_qy", "ref_qz"];
        let found: Vec<Option<usize>> = ref_names.iter().map(|n| self.find(&[n])).collect();
        let ref_q = if found.iter().all(|f| f.is_some()) {
            Some([
                found[0].unwrap(),
                found[1].unwrap(),
                found[2].unwrap(),
                found[3].unwrap(),
            ])
        } else if let Some(k) = found.iter().position(|f| f.is_some()) {
            let miss = ref_names[found.iter().position(|f| f.is_none()).unwrap()];
            return Err(missing(
                miss,
                format!(
                    "the file has '{}' but not all four reference components",
                    ref_names[k]
                ),
            ));
        } else {
            None
        };
        if opts.imu_only {
            return Ok(Columns {
                t,
                gyr,
                acc,
                gyro_unit,
                accel_unit,
                mag: None,
                temp: None,
                ref_q: None,
                movement: None,
            });
        }
        Ok(Columns {
            t,
            gyr,
            acc,
            gyro_unit,
            accel_unit,
            mag,
            temp: self.find(&["temp_c"]),
            ref_q,
            movement: self.find(&["movement"]),
        })
    }

    fn cell(&self, i: usize) -> Result<f64> {
        self.table.f64(i)
    }

    fn vec3(&self, idx: [usize; 3], scale: f64) -> Result<Vec3> {
        Ok(Vec3::new(self.cell(idx[0])?, self.cell(idx[1])?, self.cell(idx[2])?) * scale)
    }

    /// The next data row, `Ok(None)` at the end of the file.
    ///
    /// A file with a header but no data row is an error ([`ErrorKind::Empty`]),
    /// reported by the first call.
    pub fn next_row(&mut self) -> Result<Option<ImuRow>> {
        if !self.table.next_record()? {
            return Ok(None);
        }
        let t_s = match self.cols.t {
            Some(i) => {
                let t = self.cell(i)?;
                if !t.is_finite() {
                    return Err(self.table.err_at(
                        i,
                        ErrorKind::InvalidInput,
                        format!("time stamp is not a finite number ({t})"),
                    ));
                }
                if let Some(prev) = self.last_t
                    && t <= prev
                {
                    let what = if t == prev {
                        "repeats"
                    } else {
                        "goes backwards"
                    };
                    return Err(self.table.err_at(
                        i,
                        ErrorKind::TimeNotIncreasing,
                        format!("time {what}: {t} s after {prev} s"),
                    ));
                }
                t
            }
            None => (self.table.rows_read() - 1) as f64 * self.dt_rate.unwrap_or(f64::NAN),
        };
        let gyr = self.vec3(self.cols.gyr, self.gyr_scale)?;
        let acc = self.vec3(self.cols.acc, self.acc_scale)?;
        let mag_ut = match self.cols.mag {
            Some(m) => Some(self.vec3(m, 1.0)?),
            None => None,
        };
        let temp_c = match self.cols.temp {
            Some(i) => Some(self.cell(i)?),
            None => None,
        };
        let ref_q = match self.cols.ref_q {
            Some([w, x, y, z]) => {
                let q = Quaternion::new(self.cell(w)?, self.cell(x)?, self.cell(y)?, self.cell(z)?);
                let n = q.norm();
                if n.is_finite() && n > 0.0 {
                    Some(Attitude::new_unchecked(q / n))
                } else {
                    None
                }
            }
            None => None,
        };
        let movement = match self.cols.movement {
            Some(i) => {
                let m = self.cell(i)?;
                if m.is_finite() { Some(m != 0.0) } else { None }
            }
            None => None,
        };
        if let Some(prev) = self.last_t {
            self.gaps.observe(self.table.line(), prev, t_s - prev);
        }
        self.last_t = Some(t_s);
        Ok(Some(ImuRow {
            line: self.table.line(),
            sample: ImuSample {
                t_s,
                gyr_rad_s: gyr,
                acc_m_s2: acc,
                mag_ut,
                temp_c,
            },
            ref_q,
            movement,
        }))
    }
}

impl<R: Read> Iterator for ImuCsvReader<R> {
    type Item = Result<ImuRow>;
    fn next(&mut self) -> Option<Self::Item> {
        if self.failed {
            return None;
        }
        match self.next_row() {
            Ok(Some(r)) => Some(Ok(r)),
            Ok(None) => None,
            Err(e) => {
                self.failed = true;
                Some(Err(e))
            }
        }
    }
}
