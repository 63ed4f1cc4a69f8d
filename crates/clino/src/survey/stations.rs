//! Survey station files (CSV, by header name).
//!
//! Columns: `md_m` (measured depth, m), `acc_x_m_s2`, `acc_y_m_s2`,
//! `acc_z_m_s2` (specific force in the tool frame, z down the hole: a vertical
//! tool at rest reads (0, 0, −g)), and optionally `mag_x_uT`, `mag_y_uT`,
//! `mag_z_uT` (field in the tool frame) and `temp_c` (°C, for temperature
//! calibration models). Rows with the same `md_m` are a roll test. Errors name
//! file, line and column.

use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use std::path::Path;

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

/// Read stations from CSV text.
pub fn parse_stations<R: std::io::Read>(rd: R) -> Result<Vec<StationReading>> {
    let mut rdr = csv::ReaderBuilder::new().has_headers(true).from_reader(rd);
    let headers: Vec<String> = rdr
        .headers()
        .map_err(|e| Error::new(ErrorKind::Parse, format!("bad header: {e}")).at_line(1))?
        .iter()
        .map(|s| s.trim().to_string())
        .collect();
    let col = |n: &str| headers.iter().position(|h| h == n);
    let need = |n: &str| {
        col(n).ok_or_else(|| {
            Error::new(ErrorKind::MissingColumn, "survey stations need this column")
                .at_line(1)
                .at_column(n)
        })
    };
    let md = need("md_m")?;
    let acc = [
        need("acc_x_m_s2")?,
        need("acc_y_m_s2")?,
        need("acc_z_m_s2")?,
    ];
    let mag = match (col("mag_x_uT"), col("mag_y_uT"), col("mag_z_uT")) {
        (Some(a), Some(b), Some(c)) => Some([a, b, c]),
        (None, None, None) => None,
        _ => {
            return Err(Error::new(
                ErrorKind::MissingColumn,
                "the magnetometer needs all of mag_x_uT, mag_y_uT, mag_z_uT",
            )
            .at_line(1)
            .at_column("mag_x_uT"));
        }
    };
    let temp = col("temp_c");
    let mut out = Vec::new();
    for rec in rdr.records() {
        let rec = rec.map_err(|e| {
            Error::new(ErrorKind::Parse, format!("malformed row: {e}"))
                .at_line(e.position().map(|p| p.line()).unwrap_or(0))
        })?;
        let line = rec.position().map(|p| p.line()).unwrap_or(0);
        let num = |i: usize| -> Result<f64> {
            let s = rec.get(i).unwrap_or("").trim();
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| {
                    Error::new(ErrorKind::Parse, format!("not a finite number: '{s}'"))
                        .at_line(line)
                        .at_column(headers[i].clone())
                })
        };
        let f = Vec3::new(num(acc[0])?, num(acc[1])?, num(acc[2])?);
        if f.norm() == 0.0 {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "zero specific force: no gravity to survey with",
            )
            .at_line(line)
            .at_column("acc_x_m_s2"));
        }
        let h = match mag {
            Some(m) => Some(Vec3::new(num(m[0])?, num(m[1])?, num(m[2])?)),
            None => None,
        };
        let temp_c = match temp {
            Some(i) => Some(num(i)?),
            None => None,
        };
        out.push(StationReading {
            md_m: num(md)?,
            line,
            acc_m_s2: f,
            mag_ut: h,
            temp_c,
        });
    }
    if out.is_empty() {
        return Err(Error::new(
            ErrorKind::Empty,
            "the station file has no data rows",
        ));
    }
    Ok(out)
}

/// Read stations from a CSV file.
pub fn read_stations(path: &Path) -> Result<Vec<StationReading>> {
    let f = std::fs::File::open(path)
        .map_err(|e| Error::new(ErrorKind::Io, format!("cannot open: {e}")).in_file(path))?;
    parse_stations(f).map_err(|e| e.in_file(path))
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
}
