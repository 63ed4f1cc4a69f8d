//! The built-in demonstration behind `clino demo`: no files, no hardware, no
//! downloads. Each module contributes a section (its `demo_summary`);
//! [`summary`] puts them together.

use crate::Result;
use crate::fusion::{FilterConfig, FilterKind, FilterSpec};
use crate::io::{ImuCsvReader, ReadOptions};

/// 22 s of BROAD trial 07 (undisturbed fast rotation; t_s in [22.5, 44.5) s,
/// values unchanged, 285.714 Hz, with optical reference and movement flag).
///
/// Data: BROAD, CC BY 4.0 — D. Laidig, M. Caruso, A. Cereatti, T. Seel,
/// "BROAD — A Benchmark for Robust Inertial Orientation Estimation", Data 6(7), 2021.
pub const BROAD_EXCERPT: &str = include_str!("../data/broad_07_excerpt.csv");

/// The demo's sections, in order: a title and the function that writes it.
pub type Section = (&'static str, fn() -> Result<String>);

/// Every section of the demo, in the order of the pipeline.
pub const SECTIONS: [Section; 6] = [
    ("1. Dynamic inclination on real data", fusion_summary),
    (
        "2. Rotating platform: lever-arm compensation",
        crate::sim::slewing::demo_summary,
    ),
    (
        "3. Calibration of a poorly calibrated triad",
        crate::calib::demo_summary,
    ),
    (
        "4. Dynamic testing on a Stewart platform",
        crate::testbench::demo_summary,
    ),
    (
        "5. Redundant six-axis accelerometer",
        crate::redundancy::demo_summary,
    ),
    ("6. Drilling survey", crate::survey::demo_summary),
];

/// The whole demo text: every section under its title, separated by blank lines.
pub fn summary() -> Result<String> {
    let mut out = String::new();
    for (title, f) in SECTIONS {
        out.push_str(&format!("── {title} ──\n"));
        out.push_str(&f()?);
        if !out.ends_with('\n') {
            out.push('\n');
        }
        out.push('\n');
    }
    Ok(out)
}

/// One section of the demo as `clino demo --json` gives it: its title and
/// its text, line by line.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SectionReport {
    /// The section's title.
    pub title: &'static str,
    /// Its text, one entry per line.
    pub lines: Vec<String>,
}

/// The demo for programs (`clino demo --json`): the headline scores as
/// numbers, and every section's text.
#[derive(Clone, Debug, serde::Serialize)]
pub struct DemoReport {
    /// Section 1 as numbers: every filter at its defaults on the embedded
    /// BROAD excerpt, scored against the optical reference.
    pub fusion: crate::eval::RecordingScore,
    /// Every section, in order.
    pub sections: Vec<SectionReport>,
}

/// The whole demo as data ([`DemoReport`]).
pub fn report() -> Result<DemoReport> {
    let (_, fusion, _) = fusion_scores()?;
    let sections = SECTIONS
        .iter()
        .map(|(title, f)| {
            Ok(SectionReport {
                title,
                lines: f()?.lines().map(str::to_string).collect(),
            })
        })
        .collect::<Result<_>>()?;
    Ok(DemoReport { fusion, sections })
}

/// Every filter at its defaults scored on the embedded BROAD excerpt: the
/// configurations, the scores and the rows read.
fn fusion_scores() -> Result<(Vec<FilterConfig>, crate::eval::RecordingScore, u64)> {
    let mut reader = ImuCsvReader::new(
        BROAD_EXCERPT.as_bytes(),
        "broad_07_excerpt.csv",
        &ReadOptions::default(),
    )?;
    let configs: Vec<FilterConfig> = FilterKind::ALL
        .iter()
        .map(|k| FilterConfig::new(*k))
        .collect();
    let rec = crate::eval::score_reader(&mut reader, &configs)?;
    Ok((configs, rec, reader.rows_read()))
}

/// The fusion section: every filter at its defaults on the embedded BROAD
/// excerpt ([`BROAD_EXCERPT`]), scored with the BROAD inclination error
/// ([`crate::eval`]). Deterministic, well under a second.
pub fn fusion_summary() -> Result<String> {
    let (configs, rec, rows_read) = fusion_scores()?;
    let secs = rows_read as f64 / 285.714;
    let mut s = format!(
        "Attitude filters on {:.0} s of real IMU data (BROAD trial 07, fast rotation, {} rows at 285.7 Hz),\n\
         scored against optical motion capture: inclination RMSE over the {} moving samples.\n\n",
        secs,
        rec.rows,
        rec.scores.first().map_or(0, |s| s.scored)
    );
    s.push_str(&format!(
        "  {:<14} {:>18}  {}\n",
        "filter", "inclination RMSE", "parameters"
    ));
    for (c, sc) in configs.iter().zip(&rec.scores) {
        let params = match c.spec {
            FilterSpec::Poisson { .. } => "gyro only (exact step)".to_string(),
            FilterSpec::Complementary { .. } => "k = 0.05 per sample (the paper's)".to_string(),
            FilterSpec::Mahony { kp, ki } => format!("kp = {kp} rad/s, ki = {ki} rad/s²"),
            FilterSpec::Madgwick { beta } => format!("beta = {beta} rad/s"),
            FilterSpec::Dynamic(p) => {
                format!("bandwidth = {} rad/s (clino's own)", p.bandwidth_rad_s)
            }
        };
        s.push_str(&format!(
            "  {:<14} {:>16.2} °  {}\n",
            sc.filter, sc.rmse_deg, params
        ));
    }
    s.push_str("\nData: BROAD, CC BY 4.0, Laidig, Caruso, Cereatti, Seel, Data 6(7) 2021.\n");
    Ok(s)
}

#[cfg(test)]
mod tests {
    #[test]
    fn fusion_summary_scores_every_filter_and_is_deterministic() {
        let s = super::fusion_summary().unwrap();
        for k in crate::fusion::FilterKind::ALL {
            assert!(s.contains(k.name()), "{s}");
        }
        assert_eq!(s, super::fusion_summary().unwrap());
    }

    #[test]
    fn the_report_holds_the_scores_as_numbers_and_every_section() {
        let r = super::report().unwrap();
        assert_eq!(r.sections.len(), super::SECTIONS.len());
        assert_eq!(r.fusion.scores.len(), crate::fusion::FilterKind::ALL.len());
        // the numbers are those the text shows
        let text = super::fusion_summary().unwrap();
        for sc in &r.fusion.scores {
            assert!(sc.rmse_deg.is_finite() && sc.rmse_deg > 0.0);
            assert!(text.contains(&format!("{:.2} °", sc.rmse_deg)), "{text}");
        }
        assert_eq!(r.sections[0].lines.join("\n") + "\n", text);
    }
}
