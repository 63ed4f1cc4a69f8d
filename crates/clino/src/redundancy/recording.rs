//! Recordings of the nine chain forces and the gyro, and their diagnosis.
//!
//! ## CSV format
//!
//! One header row, then one row per sample, comma separated; lines starting
//! with `#` are comments. Columns are found by header name (any order,
//! case-insensitive); all thirteen are required:
//!
//! | column | meaning | unit |
//! |---|---|---|
//! | `t_s` | time, strictly increasing, nearly uniform step (±20 %) | s |
//! | `f1_N` … `f9_N` | force of branch chain 1 … 9 (source numbering, sign as in eq 1) | N |
//! | `gyr_x_rad_s`, `gyr_y_rad_s`, `gyr_z_rad_s` | body angular rate `ω*` | rad/s |
//!
//! Other columns are reported in [`Recording::ignored_columns`]. An empty or
//! non-numeric cell, NaN or infinity is an error naming the file, line and
//! column; nothing is skipped.

use super::diagnose::{
    Diagnoser, DiagnosisConfig, NoiseModel, WindowDiagnosis, diagnose_record, uniform_step,
};
use super::fault_set::FaultSet;
use super::model::{Forces, N_CHAINS, SixAxisAccelerometer};
use super::restore::{Restorer, gyro_derivative, gyro_derivative_sigma};
use crate::io::TableReader;
use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use std::io::{Read, Write};
use std::path::Path;

/// The required column names, in the order written by [`write_csv`].
pub const COLUMNS: [&str; 13] = [
    "t_s",
    "f1_N",
    "f2_N",
    "f3_N",
    "f4_N",
    "f5_N",
    "f6_N",
    "f7_N",
    "f8_N",
    "f9_N",
    "gyr_x_rad_s",
    "gyr_y_rad_s",
    "gyr_z_rad_s",
];

/// A recording of forces and gyro.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Recording {
    /// Time, s.
    pub t_s: Vec<f64>,
    /// Chain forces, N.
    pub forces: Vec<Forces>,
    /// Body angular rate, rad/s.
    pub gyr_rad_s: Vec<Vec3>,
    /// File line of the first data row (1-based), for error messages.
    pub first_data_line: u64,
    /// Header names that were not used.
    pub ignored_columns: Vec<String>,
}

/// Read a recording from a CSV file (format in the module doc; [`TableReader`]'s rules).
pub fn read_csv(path: &Path) -> Result<Recording> {
    read_table(TableReader::open(path)?)
}

/// Read a recording from any reader; `name` is used in error messages.
pub fn read_csv_from<R: Read>(reader: R, name: &Path) -> Result<Recording> {
    read_table(TableReader::new(reader, name)?)
}

/// Read a recording from a table whose header has been read.
pub fn read_table<R: Read>(mut tb: TableReader<R>) -> Result<Recording> {
    let name = tb.file().to_path_buf();
    let mut idx = [0usize; 13];
    for (k, col) in COLUMNS.iter().enumerate() {
        idx[k] = tb.find(&[col]).ok_or_else(|| tb.missing(col, "required"))?;
    }
    let ignored = tb
        .header()
        .iter()
        .filter(|n| !COLUMNS.iter().any(|c| n.eq_ignore_ascii_case(c)))
        .cloned()
        .collect();
    let mut rec = Recording {
        ignored_columns: ignored,
        ..Default::default()
    };
    while tb.next_record()? {
        let line = tb.line();
        if rec.t_s.is_empty() {
            rec.first_data_line = line;
        }
        let mut v = [0.0f64; 13];
        for (k, i) in idx.iter().enumerate() {
            v[k] = tb.finite(*i)?;
        }
        rec.t_s.push(v[0]);
        rec.forces.push(Forces::from_fn(|i, _| v[1 + i]));
        rec.gyr_rad_s.push(Vec3::new(v[10], v[11], v[12]));
    }
    uniform_step(&rec.t_s, rec.first_data_line).map_err(|e| e.in_file(name))?;
    Ok(rec)
}

/// Write a recording as CSV (the columns of [`COLUMNS`]).
pub fn write_csv<W: Write>(out: W, rec: &Recording) -> Result<()> {
    let mut w = csv::Writer::from_writer(out);
    let io = |e: csv::Error| Error::new(ErrorKind::Io, e.to_string());
    w.write_record(COLUMNS).map_err(io)?;
    for i in 0..rec.t_s.len() {
        let mut row: Vec<String> = vec![format!("{}", rec.t_s[i])];
        row.extend((0..N_CHAINS).map(|c| format!("{}", rec.forces[i][c])));
        row.extend((0..3).map(|c| format!("{}", rec.gyr_rad_s[i][c])));
        w.write_record(&row).map_err(io)?;
    }
    w.flush()?;
    Ok(())
}

/// A stretch of consecutive windows with the same verdicts.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Segment {
    /// Decision time of the first window in the stretch (its end), s.
    pub from_s: f64,
    /// Decision time of the last window in the stretch, s.
    pub to_s: f64,
    /// General-scheme verdict ("none", "239", "unexplained").
    pub general: String,
    /// Source-scheme verdict.
    pub source: String,
    /// Source relations violated in the first window of the stretch.
    pub violated: Vec<String>,
}

/// The diagnosis of a recording.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RecordingDiagnosis {
    /// Samples read.
    pub samples: usize,
    /// Sample step (median), s.
    pub step_s: f64,
    /// Decisions made (one per block once the window is full).
    pub windows: usize,
    /// Decision time of the first alarm, s.
    pub first_alarm_s: Option<f64>,
    /// Start of the first alarming window (restoration starts here), s.
    pub restore_from_s: Option<f64>,
    /// Most frequent alarming general verdict ("none" if no alarm).
    pub diagnosed: String,
    /// Most frequent alarming source-scheme verdict.
    pub diagnosed_source: String,
    /// Stretches of equal verdicts, in time order.
    pub segments: Vec<Segment>,
    /// The diagnosis settings used.
    pub config: DiagnosisConfig,
    /// The noise model used.
    pub noise: NoiseModel,
}

/// Diagnose a recording with both schemes.
pub fn diagnose_recording(
    acc: &SixAxisAccelerometer,
    noise: &NoiseModel,
    cfg: &DiagnosisConfig,
    rec: &Recording,
) -> Result<RecordingDiagnosis> {
    let step = uniform_step(&rec.t_s, rec.first_data_line)?;
    let diag = Diagnoser::new(acc, noise, cfg, step)?;
    let w = diagnose_record(&diag, &rec.t_s, &rec.forces, &rec.gyr_rad_s)?;
    Ok(summarize(rec.t_s.len(), step, &w, cfg, noise))
}

fn summarize(
    samples: usize,
    step_s: f64,
    w: &[WindowDiagnosis],
    cfg: &DiagnosisConfig,
    noise: &NoiseModel,
) -> RecordingDiagnosis {
    let mut segments: Vec<Segment> = Vec::new();
    for x in w {
        let (g, s) = (x.general.label(), x.source.label());
        match segments.last_mut() {
            Some(seg) if seg.general == g && seg.source == s => seg.to_s = x.t_end_s,
            _ => segments.push(Segment {
                from_s: x.t_end_s,
                to_s: x.t_end_s,
                general: g,
                source: s,
                violated: x.violated.clone(),
            }),
        }
    }
    let most = |labels: Vec<String>| {
        let mut v: Vec<(String, usize)> = Vec::new();
        for l in labels {
            match v.iter_mut().find(|(k, _)| *k == l) {
                Some((_, c)) => *c += 1,
                None => v.push((l, 1)),
            }
        }
        v.into_iter()
            .max_by_key(|(_, c)| *c)
            .map_or("none".to_string(), |(l, _)| l)
    };
    RecordingDiagnosis {
        samples,
        step_s,
        windows: w.len(),
        first_alarm_s: w.iter().find(|x| x.general.alarm()).map(|x| x.t_end_s),
        restore_from_s: w.iter().find(|x| x.general.alarm()).map(|x| x.t_start_s),
        diagnosed: most(
            w.iter()
                .filter(|x| x.general.alarm())
                .map(|x| x.general.label())
                .collect(),
        ),
        diagnosed_source: most(
            w.iter()
                .filter(|x| x.source.alarm())
                .map(|x| x.source.label())
                .collect(),
        ),
        segments,
        config: *cfg,
        noise: *noise,
    }
}

/// One restored sample: forces and the body-frame six-dimensional acceleration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestoredSample {
    /// Time, s.
    pub t_s: f64,
    /// Chain forces with the diagnosed chains replaced (from `restore_from_s` on), N.
    pub forces: Forces,
    /// Body specific force `F/m` of the restored forces, m/s² (eq 3, body frame).
    pub specific_force_m_s2: Vec3,
    /// Body angular acceleration `ε*` of the restored forces, rad/s² (eq 4).
    pub ang_acc_rad_s2: Vec3,
}

/// Restore a diagnosed recording: from the start of the first alarming
/// window on, the diagnosed chains are replaced by the minimum-variance
/// restoration ([`Restorer`], gyro differentiated over `2K+1` samples with
/// `K = half_window`). Without a single diagnosed set the forces are kept.
/// Body-frame outputs only: a recording does not carry the initial attitude
/// that the navigation-frame acceleration (eq 3) would need.
pub fn restore_recording(
    acc: &SixAxisAccelerometer,
    noise: &NoiseModel,
    rec: &Recording,
    diagnosis: &RecordingDiagnosis,
    half_window: usize,
) -> Result<Vec<RestoredSample>> {
    let set = FaultSet::from_label(&diagnosis.diagnosed).ok();
    let restorer = match (set, diagnosis.restore_from_s) {
        (Some(s), Some(_)) => {
            let sigma =
                gyro_derivative_sigma(noise.gyro_sigma_rad_s, diagnosis.step_s, half_window.max(1));
            Some(Restorer::new(acc, noise, sigma, s)?)
        }
        _ => None,
    };
    let eps = gyro_derivative(&rec.t_s, &rec.gyr_rad_s, half_window.max(1));
    let from = diagnosis.restore_from_s.unwrap_or(f64::INFINITY);
    Ok((0..rec.t_s.len())
        .map(|i| {
            let f = match &restorer {
                Some(r) if rec.t_s[i] >= from => r.restore(&rec.forces[i], &eps[i]),
                _ => rec.forces[i],
            };
            RestoredSample {
                t_s: rec.t_s[i],
                forces: f,
                specific_force_m_s2: acc.specific_force(&f),
                ang_acc_rad_s2: acc.angular_acceleration(&f),
            }
        })
        .collect())
}

/// Write restored samples as CSV: `t_s, f1_N..f9_N, sf_x_m_s2, sf_y_m_s2,
/// sf_z_m_s2, eps_x_rad_s2, eps_y_rad_s2, eps_z_rad_s2`.
pub fn write_restored_csv<W: Write>(out: W, samples: &[RestoredSample]) -> Result<()> {
    let mut w = csv::Writer::from_writer(out);
    let io = |e: csv::Error| Error::new(ErrorKind::Io, e.to_string());
    let mut header: Vec<&str> = COLUMNS[..10].to_vec();
    header.extend([
        "sf_x_m_s2",
        "sf_y_m_s2",
        "sf_z_m_s2",
        "eps_x_rad_s2",
        "eps_y_rad_s2",
        "eps_z_rad_s2",
    ]);
    w.write_record(&header).map_err(io)?;
    for s in samples {
        let mut row: Vec<String> = vec![format!("{}", s.t_s)];
        row.extend((0..N_CHAINS).map(|c| format!("{}", s.forces[c])));
        row.extend((0..3).map(|c| format!("{}", s.specific_force_m_s2[c])));
        row.extend((0..3).map(|c| format!("{}", s.ang_acc_rad_s2[c])));
        w.write_record(&row).map_err(io)?;
    }
    w.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_csv(rows: &[&str]) -> String {
        let mut s = COLUMNS.join(",") + "\n";
        for r in rows {
            s += r;
            s += "\n";
        }
        s
    }

    #[test]
    fn bad_cell_names_line_and_column() {
        let text = sample_csv(&["0,1,2,3,4,5,6,7,8,9,0,0,0", "0.001,1,2,x,4,5,6,7,8,9,0,0,0"]);
        let e = read_csv_from(text.as_bytes(), Path::new("rec.csv")).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Parse);
        assert_eq!(e.line, Some(3));
        assert_eq!(e.column.as_deref(), Some("f3_N"));
        assert_eq!(e.file.as_deref(), Some(Path::new("rec.csv")));
        let text = sample_csv(&["0,1,2,3,4,5,6,7,8,9,0,0,NaN"]);
        let e = read_csv_from(text.as_bytes(), Path::new("r.csv")).unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(2), Some("gyr_z_rad_s"))
        );
    }

    #[test]
    fn missing_column_and_empty_file() {
        let text = "t_s,f1_N\n0,1\n";
        let e = read_csv_from(text.as_bytes(), Path::new("r.csv")).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingColumn);
        let e = read_csv_from(sample_csv(&[]).as_bytes(), Path::new("r.csv")).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Empty);
        let text = sample_csv(&["0,1,2,3,4,5,6,7,8,9,0,0,0", "0,1,2,3,4,5,6,7,8,9,0,0,0"]);
        let e = read_csv_from(text.as_bytes(), Path::new("r.csv")).unwrap_err();
        assert_eq!((e.kind, e.line), (ErrorKind::TimeNotIncreasing, Some(3)));
    }

    #[test]
    fn simulated_recording_round_trip_and_diagnosis() {
        use super::super::fault_set::FaultSet;
        use super::super::simulate::ShakeMotion;
        use crate::sim::Motion;
        let acc = SixAxisAccelerometer::reference();
        let m = ShakeMotion::default();
        let mut rec = Recording::default();
        // deterministic pseudo-noise keeps this test independent of the simulator
        let mut x = 0.5f64;
        let mut noise = || {
            x = (x * 9301.0 + 0.49297).fract();
            (x - 0.5) * 2.0e-4 * 12f64.sqrt()
        };
        for i in 0..400 {
            let t = i as f64 * 1e-3;
            let s = m.truth(t);
            let mut f = acc.forces(&s.specific_force(clino_core::G0), &s.ang_acc_rad_s2);
            for c in 0..9 {
                f[c] += noise();
            }
            if t >= 0.2 {
                f[4] -= 0.018;
                f[7] += 0.017;
            }
            rec.t_s.push(t);
            rec.forces.push(f);
            rec.gyr_rad_s.push(s.gyr_rad_s);
        }
        let mut buf = Vec::new();
        write_csv(&mut buf, &rec).unwrap();
        let back = read_csv_from(buf.as_slice(), Path::new("mem.csv")).unwrap();
        assert_eq!(back.t_s.len(), 400);
        assert!((back.forces[123] - rec.forces[123]).norm() < 1e-12);
        let d = diagnose_recording(
            &acc,
            &NoiseModel::reference(),
            &DiagnosisConfig::default(),
            &back,
        )
        .unwrap();
        assert_eq!(d.diagnosed, FaultSet::from_label("58").unwrap().to_string());
        assert!(d.first_alarm_s.unwrap() >= 0.2 && d.first_alarm_s.unwrap() < 0.3);
        assert_eq!(d.segments[0].general, "none");
        let restored = restore_recording(&acc, &NoiseModel::reference(), &back, &d, 10).unwrap();
        let mut worst = 0.0f64;
        for (i, r) in restored.iter().enumerate().skip(250).take(100) {
            let s = m.truth(back.t_s[i]);
            worst = worst.max((r.specific_force_m_s2 - s.specific_force(clino_core::G0)).norm());
        }
        // the 18 mN and 17 mN biases would be ≈ 0.3 m/s² unrestored
        assert!(worst < 0.03, "restored specific-force error {worst} m/s²");
        let mut out = Vec::new();
        write_restored_csv(&mut out, &restored).unwrap();
        assert!(String::from_utf8(out).unwrap().starts_with("t_s,f1_N"));
    }
}
