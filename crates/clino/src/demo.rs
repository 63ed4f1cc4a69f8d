//! The built-in demonstration behind `clino demo`: no files, no hardware, no
//! downloads. Each module contributes a section (its `demo_summary`);
//! [`summary`] puts them together.

use crate::Result;

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
    (
        "1. Dynamic inclination on real data",
        crate::fusion::demo_summary,
    ),
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
        crate::bench::demo_summary,
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
