//! Survey station files (CSV, by header name).
//!
//! Columns: `md_m` (measured depth, m), `acc_x_m_s2`, `acc_y_m_s2`,
//! `acc_z_m_s2` (specific force in the tool frame, z down the hole: a vertical
//! tool at rest reads (0, 0, −g)), and optionally `mag_x_uT`, `mag_y_uT`,
//! `mag_z_uT` (field in the tool frame) and `temp_c` (°C, for temperature
//! calibration models). Rows with the same `md_m` are a roll test. Errors name
//! file, line and column.
//!
//! ## Physical bounds
//! A survey station is read with the tool at rest, so its specific force is
//! gravity (G_L ≈ 1 g) and its field the Earth's (22–67 µT). A reading beyond
//! the bounds below is a fault, a saturated axis or a unit error, not a
//! station; it is rejected with its line and column instead of turning into
//! an infinite G_L and a NaN dip:
//!
//! * specific force: every axis and |f| at most [`MAX_SPECIFIC_FORCE_M_S2`] (4 g);
//! * field: every axis and |h| at most [`MAX_FIELD_UT`] (1000 µT);
//! * measured depth: |md| at most [`MAX_MEASURED_DEPTH_M`] (100 km; the deepest
//!   borehole is 12.3 km);
//! * temperature: [`TEMP_RANGE_C`] (−100 … 300 °C).

use crate::error::short;
use crate::io::TableReader;
use crate::{Error, ErrorKind, Result};
use clino_core::{G0, Vec3};
use std::path::Path;

/// Largest specific force of a survey station, per axis and in magnitude,
/// m/s²: 4 g (a tool at rest reads 1 g).
pub const MAX_SPECIFIC_FORCE_M_S2: f64 = 4.0 * G0;
/// Largest field of a survey station, per axis and in magnitude, µT (the
/// Earth's field is 22–67 µT).
pub const MAX_FIELD_UT: f64 = 1000.0;
/// Largest |measured depth|, m.
pub const MAX_MEASURED_DEPTH_M: f64 = 1.0e5;
/// Accepted tool temperatures, °C.
pub const TEMP_RANGE_C: (f64, f64) = (-100.0, 300.0);

const ACC_COLS: [&str; 3] = ["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"];
const MAG_COLS: [&str; 3] = ["mag_x_uT", "mag_y_uT", "mag_z_uT"];

/// Check one triad against a bound: the largest axis names the column.
fn check_triad(v: &Vec3, max: f64, cols: [&str; 3], what: &str, bound: &str) -> Result<()> {
    // the axis with the largest (or a non-finite) value names the column
    let k = (0..3)
        .max_by(|&a, &b| {
            let m = |i: usize| {
                if v[i].is_finite() {
                    v[i].abs()
                } else {
                    f64::INFINITY
                }
            };
            m(a).total_cmp(&m(b))
        })
        .unwrap_or(0);
    let norm = v.norm();
    if !(v[k].abs() <= max && norm <= max) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "{what} {} on this axis, magnitude {}: beyond the physical bound of a survey station at rest, {bound}",
                short(v[k]),
                short(norm)
            ),
        )
        .at_column(cols[k]));
    }
    Ok(())
}

impl StationReading {
    /// Check the reading against the physical bounds of a survey station (see
    /// the module doc); the error names the line and the column.
    pub fn check(&self) -> Result<()> {
        let at = |e: Error| e.at_line(self.line);
        if !(self.md_m.is_finite() && self.md_m.abs() <= MAX_MEASURED_DEPTH_M) {
            return Err(at(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "measured depth {} m is beyond ±{MAX_MEASURED_DEPTH_M} m",
                    short(self.md_m)
                ),
            )
            .at_column("md_m")));
        }
        check_triad(
            &self.acc_m_s2,
            MAX_SPECIFIC_FORCE_M_S2,
            ACC_COLS,
            "specific force (m/s²)",
            "39.2 m/s² (4 g)",
        )
        .map_err(at)?;
        if self.acc_m_s2.norm() == 0.0 {
            return Err(at(Error::new(
                ErrorKind::InvalidInput,
                "zero specific force: no gravity to survey with",
            )
            .at_column("acc_x_m_s2")));
        }
        if let Some(h) = &self.mag_ut {
            check_triad(h, MAX_FIELD_UT, MAG_COLS, "field (µT)", "1000 µT").map_err(at)?;
        }
        if let Some(t) = self.temp_c
            && !(TEMP_RANGE_C.0..=TEMP_RANGE_C.1).contains(&t)
        {
            return Err(at(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "temperature {} °C is outside {} … {} °C",
                    short(t),
                    TEMP_RANGE_C.0,
                    TEMP_RANGE_C.1
                ),
            )
            .at_column("temp_c")));
        }
        Ok(())
    }
}

/// One station's readings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StationReading {
    /// Measured depth, m.
    pub md_m: f64,
    /// 1-based line in the file (0 when not from a file).
    pub line: u64,
    /// Specific force in the tool frame, m/s².
    pub acc_m_s2: Vec3,
    /// Field in the tool frame, µT.
    pub mag_ut: Option<Vec3>,
    /// Tool temperature, °C.
    pub temp_c: Option<f64>,
}

/// Read stations from CSV text (errors name `<input>`).
pub fn parse_stations<R: std::io::Read>(rd: R) -> Result<Vec<StationReading>> {
    stations_from(TableReader::new(rd, "<input>")?)
}

/// Read stations from a table whose header has been read ([`TableReader`]'s rules).
pub fn stations_from<R: std::io::Read>(mut tb: TableReader<R>) -> Result<Vec<StationReading>> {
    let need = |n: &str| {
        tb.find(&[n])
            .ok_or_else(|| tb.missing(n, "survey stations need this column"))
    };
    let md = need("md_m")?;
    let acc = [
        need("acc_x_m_s2")?,
        need("acc_y_m_s2")?,
        need("acc_z_m_s2")?,
    ];
    let col = |n: &str| tb.find(&[n]);
    let mag = match (col("mag_x_uT"), col("mag_y_uT"), col("mag_z_uT")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        (None, None, None) => None,
        _ => {
            return Err(tb.missing(
                "mag_x_uT",
                "the magnetometer needs all of mag_x_uT, mag_y_uT, mag_z_uT",
            ));
        }
    };
    let temp = col("temp_c");
    let mut out = Vec::new();
    while tb.next_record()? {
        let num = |i: usize| tb.finite(i);
        let f = Vec3::new(num(acc[0])?, num(acc[1])?, num(acc[2])?);
        let h = match mag {
            Some(m) => Some(Vec3::new(num(m[0])?, num(m[1])?, num(m[2])?)),
            None => None,
        };
        let temp_c = match temp {
            Some(i) => Some(num(i)?),
            None => None,
        };
        let r = StationReading {
            md_m: num(md)?,
            line: tb.line(),
            acc_m_s2: f,
            mag_ut: h,
            temp_c,
        };
        r.check().map_err(|e| e.in_file(tb.file()))?;
        out.push(r);
    }
    Ok(out)
}

/// Read stations from a CSV file.
pub fn read_stations(path: &Path) -> Result<Vec<StationReading>> {
    stations_from(TableReader::open(path)?)
}

/// Calibrate raw station readings with a calibration file (its accelerometer and
/// magnetometer models, at each station's temperature); errors name the line.
pub fn calibrate_readings(
    readings: &mut [StationReading],
    cal: &crate::calib::CalibrationFile,
) -> Result<()> {
    for r in readings.iter_mut() {
        let mut s = clino_core::ImuSample::new(0.0, Vec3::zeros(), r.acc_m_s2);
        s.mag_ut = r.mag_ut;
        s.temp_c = r.temp_c;
        let out = cal.apply(&s).map_err(|e| e.at_line(r.line))?;
        r.acc_m_s2 = out.acc_m_s2;
        r.mag_ut = out.mag_ut;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_and_reports_errors() {
        let s = parse_stations(
            "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n10,0,0,-9.8\n20,1,0,-9.7\n".as_bytes(),
        )
        .unwrap();
        assert_eq!(s.len(), 2);
        assert_eq!(s[1].line, 3);
        assert!(s[0].mag_ut.is_none());
        let e = parse_stations("md_m,acc_x_m_s2,acc_y_m_s2\n".as_bytes()).unwrap_err();
        assert_eq!(e.column.as_deref(), Some("acc_z_m_s2"));
        let e = parse_stations(
            "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT\n10,0,0,-9.8,1,2,x\n"
                .as_bytes(),
        )
        .unwrap_err();
        assert_eq!((e.line, e.column.as_deref()), (Some(2), Some("mag_z_uT")));
        let e = parse_stations("md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n".as_bytes()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Empty);
    }

    #[test]
    fn non_physical_readings_are_rejected_with_line_and_column() {
        let head = "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT\n";
        let ok = "10,0.5,0.2,-9.8,20,1,40\n";
        let case = |row: &str| {
            parse_stations(format!("{head}{ok}{row}").as_bytes())
                .map(|_| ())
                .unwrap_err()
        };
        let e = case("20,1e308,0,-9.8,20,1,40\n");
        assert_eq!(
            (e.kind, e.line, e.column.as_deref()),
            (ErrorKind::InvalidInput, Some(3), Some("acc_x_m_s2")),
            "{e}"
        );
        assert!(e.message.contains("39.2"), "{e}");
        // 4 g per axis passes, but not as a magnitude
        let e = case("20,30,25,-9.8,20,1,40\n");
        assert_eq!(e.column.as_deref(), Some("acc_x_m_s2"), "{e}");
        let e = case("20,0.5,0.2,-9.8,20,1,-2000\n");
        assert_eq!((e.line, e.column.as_deref()), (Some(3), Some("mag_z_uT")));
        let e = case("1e308,0.5,0.2,-9.8,20,1,40\n");
        assert_eq!(e.column.as_deref(), Some("md_m"));
        let e = case("20,0,0,0,20,1,40\n");
        assert_eq!(e.column.as_deref(), Some("acc_x_m_s2"));
        // a 3 g reading (a shock, not a station) is still a reading: QC flags its G_L
        assert!(parse_stations(format!("{head}{ok}20,0,0,-29.4,20,1,40\n").as_bytes()).is_ok());
    }
}
