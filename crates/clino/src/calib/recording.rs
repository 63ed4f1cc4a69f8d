//! The calibration recording: a CSV file read by header name.
//!
//! Columns (the `clino fuse` conventions; any order, extra columns kept):
//!
//! | column | unit | needed |
//! |---|---|---|
//! | `t_s` | s, strictly increasing | always |
//! | `acc_x_m_s2`, `acc_y_m_s2`, `acc_z_m_s2` | m/s² (raw reading) | accelerometer calibration |
//! | `gyr_x_rad_s`, `gyr_y_rad_s`, `gyr_z_rad_s` | rad/s (raw reading) | gyro calibration |
//! | `mag_x_uT`, `mag_y_uT`, `mag_z_uT` | µT (raw reading) | magnetometer calibration |
//! | `temp_c` | °C | temperature models (`mwd30`) |
//! | `ref_inclination_deg` | deg, angle of the housing's z axis from up (empty while moving) | optional, makes the tilt of the triad observable |
//! | `ref_gyr_x_rad_s`, `ref_gyr_y_rad_s`, `ref_gyr_z_rad_s` | rad/s, the rate table's rate in the housing frame | gyro rate-table calibration |
//!
//! A triad's three columns come together or not at all. Every error names the
//! file, the 1-based line and the column.
//!
//! ## Physical bounds
//! A raw reading beyond what any sensor of its kind can report is a logging
//! fault or a unit error. It is rejected here, with its line and column,
//! before it can reach a solver (where a 1e308 turns every residual into
//! infinity): per axis, |acc| ≤ [`MAX_ACC_M_S2`] (100 g), |gyr| and
//! |ref_gyr| ≤ [`MAX_GYR_RAD_S`] (100 rad/s, 5730 °/s), |mag| ≤
//! [`MAX_MAG_UT`] (5000 µT); `temp_c` in [`TEMP_RANGE_C`]; |t_s| ≤
//! [`MAX_TIME_S`].

use crate::io::TableReader;
use crate::{Error, ErrorKind, Result};
use clino_core::{G0, ImuSample, Vec3};
use std::path::{Path, PathBuf};

/// Largest raw accelerometer reading per axis, m/s²: 100 g, beyond the range
/// of inclinometer-class MEMS accelerometers (±16 g at most) and of MWD tools.
pub const MAX_ACC_M_S2: f64 = 100.0 * G0;
/// Largest raw gyro (or rate-table) rate per axis, rad/s: 100 rad/s
/// (5730 °/s; MEMS gyros reach ±4000 °/s).
pub const MAX_GYR_RAD_S: f64 = 100.0;
/// Largest raw magnetometer reading per axis, µT: 5000 µT (MEMS magnetometers
/// reach ±4900 µT; the Earth's field is 22–67 µT).
pub const MAX_MAG_UT: f64 = 5000.0;
/// Accepted temperatures, °C.
pub const TEMP_RANGE_C: (f64, f64) = (-100.0, 300.0);
/// Largest |time stamp|, s (about 317 years).
pub const MAX_TIME_S: f64 = 1.0e10;

/// Column names of the three triads, x, y, z.
pub const ACC_COLS: [&str; 3] = ["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"];
/// Gyro column names.
pub const GYR_COLS: [&str; 3] = ["gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s"];
/// Magnetometer column names.
pub const MAG_COLS: [&str; 3] = ["mag_x_uT", "mag_y_uT", "mag_z_uT"];
/// Rate-table reference rate column names.
pub const REF_GYR_COLS: [&str; 3] = ["ref_gyr_x_rad_s", "ref_gyr_y_rad_s", "ref_gyr_z_rad_s"];

/// A recording in memory: parsed columns plus the raw records (for rewriting).
#[derive(Clone, Debug, Default)]
pub struct Recording {
    /// File it came from, if any.
    pub path: Option<PathBuf>,
    /// Header names in file order.
    pub headers: Vec<String>,
    /// Time stamps, s.
    pub t_s: Vec<f64>,
    /// Raw accelerometer readings, when the columns exist.
    pub acc: Option<Vec<Vec3>>,
    /// Raw gyro readings.
    pub gyr: Option<Vec<Vec3>>,
    /// Raw magnetometer readings.
    pub mag: Option<Vec<Vec3>>,
    /// Temperature, °C.
    pub temp_c: Option<Vec<f64>>,
    /// Reference inclination, deg (NaN where empty).
    pub ref_inclination_deg: Option<Vec<f64>>,
    /// Rate-table reference rate, rad/s.
    pub ref_gyr: Option<Vec<Vec3>>,
    /// 1-based file line of each row.
    pub line: Vec<u64>,
    /// The raw cells of each row, for writing the same columns back.
    pub records: Vec<Vec<String>>,
}

impl Recording {
    /// Read a recording from a CSV file ([`TableReader`]'s rules).
    pub fn load(path: &Path) -> Result<Self> {
        let mut r = Self::from_table(TableReader::open(path)?)?;
        r.path = Some(path.to_path_buf());
        Ok(r)
    }

    /// Read a recording from any reader (CSV with a header row); errors name `<input>`.
    pub fn from_reader<R: std::io::Read>(rd: R) -> Result<Self> {
        Self::from_table(TableReader::new(rd, "<input>")?)
    }

    /// Read a recording from a table whose header has been read.
    pub fn from_table<R: std::io::Read>(mut tb: TableReader<R>) -> Result<Self> {
        let headers: Vec<String> = tb.header().to_vec();
        let t = tb
            .find(&["t_s"])
            .ok_or_else(|| tb.missing("t_s", "the recording needs a time column"))?;
        let triad = |names: [&str; 3]| -> Result<Option<[usize; 3]>> {
            let idx: Vec<Option<usize>> = names.iter().map(|n| tb.find(&[n])).collect();
            match (idx[0], idx[1], idx[2]) {
                (Some(a), Some(b), Some(c)) => Ok(Some([a, b, c])),
                (None, None, None) => Ok(None),
                _ => {
                    let missing = names
                        .iter()
                        .zip(&idx)
                        .find(|(_, i)| i.is_none())
                        .map(|(n, _)| *n)
                        .unwrap_or(names[0]);
                    Err(tb.missing(missing, "a triad needs all three of its columns"))
                }
            }
        };
        let acc_i = triad(ACC_COLS)?;
        let gyr_i = triad(GYR_COLS)?;
        let mag_i = triad(MAG_COLS)?;
        let ref_gyr_i = triad(REF_GYR_COLS)?;
        let temp_i = tb.find(&["temp_c"]);
        let refinc_i = tb.find(&["ref_inclination_deg"]);

        let mut out = Recording {
            path: Some(tb.file().to_path_buf()),
            headers,
            acc: acc_i.map(|_| Vec::new()),
            gyr: gyr_i.map(|_| Vec::new()),
            mag: mag_i.map(|_| Vec::new()),
            temp_c: temp_i.map(|_| Vec::new()),
            ref_inclination_deg: refinc_i.map(|_| Vec::new()),
            ref_gyr: ref_gyr_i.map(|_| Vec::new()),
            ..Default::default()
        };
        while tb.next_record()? {
            let line = tb.line();
            // a finite number within [lo, hi] (the physical bounds of the module doc)
            let bounded = |i: usize, lo: f64, hi: f64, what: &str| -> Result<f64> {
                let v = tb.finite(i)?;
                if (lo..=hi).contains(&v) {
                    Ok(v)
                } else {
                    Err(tb.err_at(
                        i,
                        ErrorKind::InvalidInput,
                        format!(
                            "{} is beyond the physical bound of a raw {what}, {lo} … {hi}",
                            crate::error::short(v)
                        ),
                    ))
                }
            };
            let ts = bounded(t, -MAX_TIME_S, MAX_TIME_S, "time stamp (s)")?;
            if let Some(&prev) = out.t_s.last()
                && ts <= prev
            {
                return Err(tb.err_at(
                    t,
                    ErrorKind::TimeNotIncreasing,
                    format!("time {ts} s does not increase (previous row {prev} s)"),
                ));
            }
            out.t_s.push(ts);
            let v3 = |ix: [usize; 3], max: f64, what: &str| -> Result<Vec3> {
                Ok(Vec3::new(
                    bounded(ix[0], -max, max, what)?,
                    bounded(ix[1], -max, max, what)?,
                    bounded(ix[2], -max, max, what)?,
                ))
            };
            if let (Some(ix), Some(v)) = (acc_i, out.acc.as_mut()) {
                v.push(v3(ix, MAX_ACC_M_S2, "accelerometer reading (m/s², 100 g)")?);
            }
            if let (Some(ix), Some(v)) = (gyr_i, out.gyr.as_mut()) {
                v.push(v3(ix, MAX_GYR_RAD_S, "gyro reading (rad/s)")?);
            }
            if let (Some(ix), Some(v)) = (mag_i, out.mag.as_mut()) {
                v.push(v3(ix, MAX_MAG_UT, "magnetometer reading (µT)")?);
            }
            if let (Some(ix), Some(v)) = (ref_gyr_i, out.ref_gyr.as_mut()) {
                v.push(v3(ix, MAX_GYR_RAD_S, "rate-table rate (rad/s)")?);
            }
            if let (Some(i), Some(v)) = (temp_i, out.temp_c.as_mut()) {
                v.push(bounded(
                    i,
                    TEMP_RANGE_C.0,
                    TEMP_RANGE_C.1,
                    "temperature (°C)",
                )?);
            }
            if let (Some(i), Some(v)) = (refinc_i, out.ref_inclination_deg.as_mut()) {
                // empty while moving
                let x = tb.f64(i)?;
                if x.is_infinite() || (x.is_finite() && !(0.0..=180.0).contains(&x)) {
                    return Err(tb.err_at(
                        i,
                        ErrorKind::InvalidInput,
                        format!("inclination {x}° outside 0–180°"),
                    ));
                }
                v.push(x);
            }
            out.line.push(line);
            out.records.push(tb.texts());
        }
        Ok(out)
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.t_s.len()
    }

    /// True when there are no rows.
    pub fn is_empty(&self) -> bool {
        self.t_s.is_empty()
    }

    /// An error located in this recording's file.
    pub fn error(&self, kind: ErrorKind, msg: impl Into<String>) -> Error {
        let e = Error::new(kind, msg);
        match &self.path {
            Some(p) => e.in_file(p),
            None => e,
        }
    }

    /// Row `i` as an [`ImuSample`] (absent accelerometer or gyro columns read as zero).
    pub fn sample(&self, i: usize) -> ImuSample {
        let z = Vec3::zeros();
        ImuSample {
            t_s: self.t_s[i],
            gyr_rad_s: self.gyr.as_ref().map(|v| v[i]).unwrap_or(z),
            acc_m_s2: self.acc.as_ref().map(|v| v[i]).unwrap_or(z),
            mag_ut: self.mag.as_ref().map(|v| v[i]),
            temp_c: self.temp_c.as_ref().map(|v| v[i]),
        }
    }

    /// Build a recording from samples (for simulated data); reference
    /// inclinations optional.
    pub fn from_samples(samples: &[ImuSample], ref_inclination_deg: Option<&[f64]>) -> Self {
        let mut headers: Vec<String> = vec!["t_s".into()];
        headers.extend(ACC_COLS.iter().map(|s| s.to_string()));
        headers.extend(GYR_COLS.iter().map(|s| s.to_string()));
        let has_mag = samples.iter().all(|s| s.mag_ut.is_some()) && !samples.is_empty();
        let has_temp = samples.iter().all(|s| s.temp_c.is_some()) && !samples.is_empty();
        if has_mag {
            headers.extend(MAG_COLS.iter().map(|s| s.to_string()));
        }
        if has_temp {
            headers.push("temp_c".into());
        }
        if ref_inclination_deg.is_some() {
            headers.push("ref_inclination_deg".into());
        }
        let mut r = Recording {
            headers,
            t_s: samples.iter().map(|s| s.t_s).collect(),
            acc: Some(samples.iter().map(|s| s.acc_m_s2).collect()),
            gyr: Some(samples.iter().map(|s| s.gyr_rad_s).collect()),
            mag: has_mag.then(|| {
                samples
                    .iter()
                    .map(|s| s.mag_ut.unwrap_or_default())
                    .collect()
            }),
            temp_c: has_temp.then(|| {
                samples
                    .iter()
                    .map(|s| s.temp_c.unwrap_or(f64::NAN))
                    .collect()
            }),
            ref_inclination_deg: ref_inclination_deg.map(|r| r.to_vec()),
            line: (2..2 + samples.len() as u64).collect(),
            ..Default::default()
        };
        r.records = (0..samples.len()).map(|i| r.row_cells(i)).collect();
        r
    }

    fn row_cells(&self, i: usize) -> Vec<String> {
        let s = self.sample(i);
        let mut c = vec![format!("{}", s.t_s)];
        c.extend((0..3).map(|k| format!("{}", s.acc_m_s2[k])));
        c.extend((0..3).map(|k| format!("{}", s.gyr_rad_s[k])));
        if let Some(m) = s.mag_ut {
            c.extend((0..3).map(|k| format!("{}", m[k])));
        }
        if let Some(t) = s.temp_c {
            c.push(format!("{t}"));
        }
        if let Some(r) = &self.ref_inclination_deg {
            c.push(if r[i].is_finite() {
                format!("{}", r[i])
            } else {
                String::new()
            });
        }
        c
    }

    /// The rows as written: the original cells, with the triad columns
    /// holding the current values of `acc`, `gyr`, `mag`.
    fn output_rows(&self) -> impl Iterator<Item = Vec<String>> + '_ {
        let idx = |names: [&str; 3]| {
            names.map(|n| self.headers.iter().position(|h| h.eq_ignore_ascii_case(n)))
        };
        let (ai, gi, mi) = (idx(ACC_COLS), idx(GYR_COLS), idx(MAG_COLS));
        self.records.iter().enumerate().map(move |(i, rec)| {
            let mut cells = rec.clone();
            let mut put = |ix: [Option<usize>; 3], v: Option<&Vec<Vec3>>| {
                if let Some(v) = v {
                    for k in 0..3 {
                        if let Some(c) = ix[k]
                            && c < cells.len()
                        {
                            cells[c] = format!("{}", v[i][k]);
                        }
                    }
                }
            };
            put(ai, self.acc.as_ref());
            put(gi, self.gyr.as_ref());
            put(mi, self.mag.as_ref());
            cells
        })
    }

    /// Write the recording as CSV with its original columns; the triad
    /// columns hold the current values of `acc`, `gyr`, `mag`.
    pub fn write_csv<W: std::io::Write>(&self, w: W) -> Result<()> {
        let mut wr = csv::Writer::from_writer(w);
        let io = |e: csv::Error| Error::new(ErrorKind::Io, e.to_string());
        wr.write_record(&self.headers).map_err(io)?;
        for cells in self.output_rows() {
            wr.write_record(&cells).map_err(io)?;
        }
        wr.flush()
            .map_err(|e| Error::new(ErrorKind::Io, e.to_string()))?;
        Ok(())
    }

    /// Write the recording to `path` as [`Recording::write_csv`] does, or as
    /// Parquet when the name ends in `.parquet` (a column whose every cell is
    /// a number is DOUBLE, any other UTF-8 text). The file appears whole or
    /// not at all ([`crate::io::AtomicFile`]; writing over one of `inputs` is
    /// refused); errors name it.
    pub fn save(&self, path: &Path, inputs: &[&Path]) -> Result<()> {
        let named = |e: Error| e.or_in_file(path);
        let mut f = crate::io::AtomicFile::create(path, inputs)?;
        if crate::io::is_parquet(path) {
            let rows: Vec<Vec<String>> = self.output_rows().collect();
            let num = |k: usize| {
                rows.iter().all(|r| {
                    r.get(k)
                        .is_some_and(|c| crate::io::parse_cell(c.as_bytes()).is_some())
                })
            };
            let text: Vec<bool> = (0..self.headers.len()).map(|k| !num(k)).collect();
            let names: Vec<&str> = self.headers.iter().map(String::as_str).collect();
            let text_names: Vec<&str> = names
                .iter()
                .zip(&text)
                .filter(|(_, t)| **t)
                .map(|(n, _)| *n)
                .collect();
            let mut w =
                crate::io::ParquetRowWriter::new(&mut f, &names, &text_names).map_err(named)?;
            let io = |e: std::io::Error| Error::from(e).in_file(path);
            for r in &rows {
                for (k, &t) in text.iter().enumerate() {
                    let c = r.get(k).map_or("", String::as_str);
                    if t {
                        w.str(c);
                    } else {
                        w.f64(crate::io::parse_cell(c.as_bytes()).unwrap_or(f64::NAN));
                    }
                }
                w.end_row().map_err(io)?;
            }
            w.finish().map_err(io)?;
        } else {
            self.write_csv(&mut f).map_err(named)?;
        }
        f.commit()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_by_header_name_and_round_trips() {
        let csv = "temp_c,t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,note,ref_inclination_deg\n\
                   30,0.0,0.1,0.2,9.8,a,0\n31,0.1,0.1,0.2,9.7,b,\n";
        let r = Recording::from_reader(csv.as_bytes()).unwrap();
        assert_eq!(r.len(), 2);
        assert_eq!(r.acc.as_ref().unwrap()[1], Vec3::new(0.1, 0.2, 9.7));
        assert!(r.gyr.is_none());
        assert_eq!(r.temp_c.as_ref().unwrap(), &vec![30.0, 31.0]);
        assert!(r.ref_inclination_deg.as_ref().unwrap()[1].is_nan());
        assert_eq!(r.line, vec![2, 3]);
        let mut out = Vec::new();
        r.write_csv(&mut out).unwrap();
        let back = Recording::from_reader(out.as_slice()).unwrap();
        assert_eq!(back.headers, r.headers);
        assert_eq!(back.acc, r.acc);
        assert_eq!(back.records[0][5], "a");
    }

    #[test]
    fn saves_as_csv_or_parquet_and_reads_back_the_same() {
        let csv = "temp_c,t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,note,ref_inclination_deg\n\
                   30,0.0,0.1,0.2,9.8,a,0\n31,0.1,0.1,0.2,9.7,b,\n";
        let mut r = Recording::from_reader(csv.as_bytes()).unwrap();
        // as `calibrate apply` leaves it: new triad values
        r.acc.as_mut().unwrap()[1] = Vec3::new(0.125, -0.5, 9.80665);
        let d = tempfile::Builder::new()
            .prefix("clino-rec-save-")
            .tempdir()
            .unwrap();
        let (pc, pp) = (d.path().join("out.csv"), d.path().join("out.parquet"));
        r.save(&pc, &[]).unwrap();
        r.save(&pp, &[]).unwrap();
        let (c, p) = (Recording::load(&pc).unwrap(), Recording::load(&pp).unwrap());
        for back in [&c, &p] {
            assert_eq!(back.headers, r.headers);
            assert_eq!(back.acc, r.acc);
            assert_eq!(back.temp_c, r.temp_c);
            assert_eq!(back.records[1][5], "b");
            assert!(back.ref_inclination_deg.as_ref().unwrap()[1].is_nan());
        }
        // writing over an input is refused and leaves it alone
        let e = r.save(&pc, &[&pc]).unwrap_err();
        assert_eq!(e.file.as_deref(), Some(pc.as_path()));
        assert_eq!(Recording::load(&pc).unwrap().acc, r.acc);
    }

    #[test]
    fn errors_name_line_and_column() {
        let csv = "t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,1,2,3\n0.1,1,x,3\n";
        let e = Recording::from_reader(csv.as_bytes()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Parse);
        assert_eq!(e.line, Some(3));
        assert_eq!(e.column.as_deref(), Some("acc_y_m_s2"));

        let csv = "t_s,acc_x_m_s2,acc_z_m_s2\n0,1,3\n";
        let e = Recording::from_reader(csv.as_bytes()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingColumn);
        assert_eq!(e.column.as_deref(), Some("acc_y_m_s2"));

        let csv = "t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,1,2,3\n0,1,2,3\n";
        let e = Recording::from_reader(csv.as_bytes()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::TimeNotIncreasing);
        assert_eq!(e.line, Some(3));

        let e = Recording::from_reader("t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n".as_bytes())
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::Empty);

        let csv = "t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,1,2,NaN\n";
        let e = Recording::from_reader(csv.as_bytes()).unwrap_err();
        assert_eq!(e.column.as_deref(), Some("acc_z_m_s2"));
    }

    #[test]
    fn non_physical_readings_are_rejected_with_line_and_column() {
        let head = "t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,mag_x_uT,mag_y_uT,mag_z_uT,temp_c\n";
        let ok = "0,0.1,0.2,9.8,0,0,0.01,20,0,40,25\n";
        for (row, col) in [
            ("0.1,0.1,1e308,9.8,0,0,0.01,20,0,40,25\n", "acc_y_m_s2"),
            ("0.1,0.1,0.2,9.8,0,-1e200,0.01,20,0,40,25\n", "gyr_y_rad_s"),
            ("0.1,0.1,0.2,9.8,0,0,0.01,20,0,1e6,25\n", "mag_z_uT"),
            ("0.1,0.1,0.2,9.8,0,0,0.01,20,0,40,1e308\n", "temp_c"),
            ("1e300,0.1,0.2,9.8,0,0,0.01,20,0,40,25\n", "t_s"),
        ] {
            let e = Recording::from_reader(format!("{head}{ok}{row}").as_bytes()).unwrap_err();
            assert_eq!(
                (e.kind, e.line, e.column.as_deref()),
                (ErrorKind::InvalidInput, Some(3), Some(col)),
                "{e}"
            );
            assert!(e.message.contains("physical bound"), "{e}");
        }
        // 16 g on one axis (a shock between poses) is a reading
        let r = format!("{head}{ok}0.1,156.9,0.2,9.8,0,0,0.01,20,0,40,25\n");
        assert!(Recording::from_reader(r.as_bytes()).is_ok());
    }
}
