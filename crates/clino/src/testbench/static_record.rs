//! A recording at rest, read under the rules both `clino allan` and
//! `clino testbench static` apply before any analysis.
//!
//! * The file is read by [`crate::io::ImuCsvReader`] (lines starting with `#`
//!   are comments; columns by header name; other columns, such as the `ref_q*`
//!   and `mag_*` of a BROAD file, are neither parsed nor checked, so NaN there
//!   is harmless). Gyro columns in `_rad_s` or `_deg_s`, accelerometer columns
//!   in `_m_s2` or `_g`, chosen from the header.
//! * Every gyro and accelerometer cell must be a finite number: a dropout is an
//!   error naming the file, line and column.
//! * Time must increase (the reader's rule) and be uniform: an interval longer
//!   than 1.5 times the median interval is a gap. [`GapPolicy::Refuse`] makes
//!   the first gap an error naming the file, the line after it and its size;
//!   [`GapPolicy::Longest`] keeps the longest gap-free segment and says so in
//!   [`StaticRecord::notes`]. (A gap cannot pass silently: the rate from the
//!   time stamps would be wrong, and every cluster straddling the gap would mix
//!   two records.)
//! * The sample rate is that of the kept segment: (samples − 1)/span.

use crate::io::{ImuCsvReader, ReadOptions};
use crate::{Error, ErrorKind, Result};
use clino_core::ImuSample;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// What to do with a gap in the time stamps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GapPolicy {
    /// A gap is an error (the default).
    #[default]
    Refuse,
    /// Analyse the longest gap-free segment.
    Longest,
}

impl std::str::FromStr for GapPolicy {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self> {
        match s {
            "refuse" => Ok(Self::Refuse),
            "longest" => Ok(Self::Longest),
            o => Err(Error::new(
                ErrorKind::InvalidInput,
                format!("unknown gap policy '{o}' (refuse or longest)"),
            )),
        }
    }
}

/// A gap in the time stamps.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Gap {
    /// 1-based line of the first row after the gap.
    pub line: u64,
    /// Time of the row before the gap, s.
    pub t_before_s: f64,
    /// Time of the row after the gap, s.
    pub t_after_s: f64,
    /// Interval, s.
    pub interval_s: f64,
    /// Samples missing at the median interval.
    pub missing_samples: f64,
}

/// A gap-free stretch of the record.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Segment {
    /// 1-based lines of its first and last rows.
    pub lines: [u64; 2],
    /// Times of its first and last rows, s.
    pub t_s: [f64; 2],
    /// Rows.
    pub samples: usize,
}

/// A static record that passed the rules.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StaticRecord {
    /// The file read.
    pub file: PathBuf,
    /// The samples kept (the whole record, or its longest segment).
    #[serde(skip)]
    pub samples: Vec<ImuSample>,
    /// Sample rate of the kept samples, Hz.
    pub rate_hz: f64,
    /// Median interval of the time stamps, s.
    pub median_interval_s: f64,
    /// Gaps found.
    pub gaps: Vec<Gap>,
    /// Gap-free segments.
    pub segments: Vec<Segment>,
    /// Index in `segments` of the one kept.
    pub used_segment: usize,
    /// What the rules did (one sentence each), for the user.
    pub notes: Vec<String>,
}

impl StaticRecord {
    /// An error unless the kept record has at least `min` samples (`what` needs them).
    pub fn require(&self, min: usize, what: &str) -> Result<()> {
        let n = self.samples.len();
        if n < min {
            let seg = if self.segments.len() > 1 {
                " in its longest gap-free segment"
            } else {
                ""
            };
            return Err(Error::new(
                ErrorKind::Empty,
                format!("{n} samples{seg}: {what} needs at least {min}"),
            )
            .in_file(&self.file));
        }
        Ok(())
    }
}

/// Units of the gyro and accelerometer columns, from the header line of `path`.
/// Read `path` under the rules of the module.
pub fn read_static_record(path: &Path, policy: GapPolicy) -> Result<StaticRecord> {
    // the units come from the column names (the reader's rule)
    let opts = ReadOptions {
        imu_only: true,
        ..ReadOptions::default()
    };
    let rdr = ImuCsvReader::from_path(path, &opts)?;
    from_rows(rdr, path, policy)
}

/// Read CSV text under the rules of the module, naming `name` in errors.
pub fn static_record_from_bytes(
    text: &[u8],
    name: &Path,
    policy: GapPolicy,
) -> Result<StaticRecord> {
    let opts = ReadOptions {
        imu_only: true,
        ..ReadOptions::default()
    };
    let rdr = ImuCsvReader::new(text, name, &opts)?;
    from_rows(rdr, name, policy)
}

fn from_rows<R: std::io::Read>(
    mut rdr: ImuCsvReader<R>,
    file: &Path,
    policy: GapPolicy,
) -> Result<StaticRecord> {
    let mut samples = Vec::new();
    let mut lines = Vec::new();
    while let Some(row) = rdr.next_row()? {
        if row.has_dropout() {
            let col = rdr.unusable_column(&row).unwrap_or("?").to_string();
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "not a finite number (a dropout): a static analysis needs every sample",
            )
            .in_file(file)
            .at_line(row.line)
            .at_column(col));
        }
        samples.push(row.sample);
        lines.push(row.line);
    }
    split(samples, &lines, file, policy)
}

fn split(
    samples: Vec<ImuSample>,
    lines: &[u64],
    file: &Path,
    policy: GapPolicy,
) -> Result<StaticRecord> {
    let n = samples.len();
    if n < 2 {
        return Err(Error::new(
            ErrorKind::Empty,
            format!("{n} sample: a static analysis needs at least two"),
        )
        .in_file(file));
    }
    let mut dts: Vec<f64> = samples.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
    let gap_dts = dts.clone();
    dts.sort_by(f64::total_cmp);
    let median = dts[dts.len() / 2];
    let mut gaps = Vec::new();
    let mut segments = Vec::new();
    let mut start = 0usize;
    for (i, &dt) in gap_dts.iter().enumerate() {
        if dt > 1.5 * median {
            gaps.push(Gap {
                line: lines[i + 1],
                t_before_s: samples[i].t_s,
                t_after_s: samples[i + 1].t_s,
                interval_s: dt,
                missing_samples: dt / median - 1.0,
            });
            segments.push(start..i + 1);
            start = i + 1;
        }
    }
    segments.push(start..n);
    let seg_info: Vec<Segment> = segments
        .iter()
        .map(|r| Segment {
            lines: [lines[r.start], lines[r.end - 1]],
            t_s: [samples[r.start].t_s, samples[r.end - 1].t_s],
            samples: r.len(),
        })
        .collect();
    let mut notes = Vec::new();
    let used = if let Some(g) = gaps.first() {
        let summary = format!(
            "time gap of {:.6} s (about {:.0} missing samples at the median interval {:.6} s) between \
             t = {} s and t = {} s",
            g.interval_s, g.missing_samples, median, g.t_before_s, g.t_after_s
        );
        match policy {
            GapPolicy::Refuse => {
                return Err(Error::new(
                    ErrorKind::InvalidInput,
                    format!(
                        "{summary} ({} gaps in all): the analysis needs uniform sampling; split the \
                         record, or analyse its longest gap-free segment (`--gaps longest`)",
                        gaps.len()
                    ),
                )
                .in_file(file)
                .at_line(g.line)
                .at_column("t_s"));
            }
            GapPolicy::Longest => {
                let (k, r) = segments
                    .iter()
                    .enumerate()
                    .max_by_key(|(_, r)| r.len())
                    .expect("at least one segment");
                notes.push(format!(
                    "{} time gaps (the first: {summary}, line {}): {} gap-free segments; analysing the \
                     longest, lines {}–{} (t = {} … {} s, {} samples)",
                    gaps.len(),
                    g.line,
                    segments.len(),
                    lines[r.start],
                    lines[r.end - 1],
                    samples[r.start].t_s,
                    samples[r.end - 1].t_s,
                    r.len()
                ));
                k
            }
        }
    } else {
        0
    };
    let r = segments[used].clone();
    let kept: Vec<ImuSample> = samples[r.clone()].to_vec();
    let span = kept[kept.len().max(1) - 1].t_s - kept[0].t_s;
    let rate_hz = if kept.len() >= 2 && span > 0.0 {
        (kept.len() - 1) as f64 / span
    } else {
        1.0 / median
    };
    Ok(StaticRecord {
        file: file.to_path_buf(),
        samples: kept,
        rate_hz,
        median_interval_s: median,
        gaps,
        segments: seg_info,
        used_segment: used,
        notes,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n";

    fn rows(ts: &[f64]) -> String {
        let mut s = String::from("# a comment\n# another\n");
        s.push_str(HEAD);
        for (i, t) in ts.iter().enumerate() {
            s.push_str(&format!("{t},{},0,0,0,0,9.8\n", (i % 7) as f64 * 1e-3));
        }
        s
    }

    #[test]
    fn a_gap_is_refused_with_file_line_and_size() {
        let mut ts: Vec<f64> = (0..50).map(|i| i as f64 * 0.01).collect();
        ts.extend((0..80).map(|i| 100.5 + i as f64 * 0.01));
        let text = rows(&ts);
        let e = static_record_from_bytes(text.as_bytes(), Path::new("rec.csv"), GapPolicy::Refuse)
            .unwrap_err();
        // 3 header lines, then the 51st data row follows the gap
        assert_eq!(e.line, Some(3 + 51));
        assert_eq!(e.column.as_deref(), Some("t_s"));
        let msg = e.to_string();
        assert!(
            msg.starts_with("rec.csv:54: column 't_s': time gap of 100.01"),
            "{msg}"
        );
        assert!(msg.contains("10000 missing samples"), "{msg}");
        // or the longest segment, said so
        let r = static_record_from_bytes(text.as_bytes(), Path::new("rec.csv"), GapPolicy::Longest)
            .unwrap();
        assert_eq!(r.samples.len(), 80);
        assert_eq!(r.segments.len(), 2);
        assert_eq!(r.used_segment, 1);
        assert!((r.rate_hz - 100.0).abs() < 1e-6, "{}", r.rate_hz);
        assert!(r.notes[0].contains("lines 54–133"), "{:?}", r.notes);
    }

    #[test]
    fn unused_columns_may_hold_nan_and_comments_are_read() {
        // the shipped BROAD excerpt: '#' lines, NaN in ref_q*
        let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/broad_07_excerpt.csv");
        let r = read_static_record(&p, GapPolicy::Refuse).unwrap();
        assert!(r.samples.len() > 1000);
        assert!((r.rate_hz - 285.714).abs() < 0.1, "{}", r.rate_hz);
        assert!(r.gaps.is_empty());
    }

    #[test]
    fn dropouts_and_units() {
        let text = format!("{HEAD}0,0,0,0,0,0,9.8\n0.01,0,,0,0,0,9.8\n");
        let e = static_record_from_bytes(text.as_bytes(), Path::new("d.csv"), GapPolicy::Refuse)
            .unwrap_err();
        assert_eq!(
            (e.line, e.column.as_deref()),
            (Some(3), Some("gyr_y_rad_s"))
        );
        let text = "t_s,gyr_x_deg_s,gyr_y_deg_s,gyr_z_deg_s,acc_x_g,acc_y_g,acc_z_g\n0,1,0,0,0,0,1\n0.1,1,0,0,0,0,1\n";
        let r = static_record_from_bytes(text.as_bytes(), Path::new("u.csv"), GapPolicy::Refuse)
            .unwrap();
        assert!((r.samples[0].gyr_rad_s.x - 1f64.to_radians()).abs() < 1e-15);
        assert!((r.samples[0].acc_m_s2.z - clino_core::G0).abs() < 1e-12);
        let e = r.require(100, "an Allan analysis").unwrap_err();
        assert_eq!(
            e.to_string(),
            "u.csv: 2 samples: an Allan analysis needs at least 100"
        );
    }
}
