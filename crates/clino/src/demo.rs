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

/// The whole demo text: every section, separated by blank lines.
pub fn summary() -> Result<String> {
    let sections = [crate::fusion::demo_summary()?];
    Ok(sections.join("\n"))
}
