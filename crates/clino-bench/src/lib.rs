//! Benchmarks and baseline comparisons of clino, kept out of the test build.
//!
//! `cargo bench -p clino-bench --bench fusion` (criterion) and the examples
//! `vqf_compare` (vqf-rs) and `ahrs_compare` (the ahrs crate) live here, not in
//! `clino`, so that their dependencies — criterion, vqf-rs, ahrs, which also
//! switch on other features of shared crates (nalgebra's `libm-force`, serde's
//! `std`) — are not built by the test command (`cargo test --release` builds
//! the workspace's default members, which leave this crate out) and the tests
//! reuse the release build of the first set-up command as it is.
//!
//! This library holds what they share: where the data is.

use std::path::PathBuf;

/// The BROAD recordings: `$CLINO_BROAD_DIR`, else `<workspace>/../shared/data/broad`, if present.
pub fn broad_dir() -> Option<PathBuf> {
    let d = std::env::var_os("CLINO_BROAD_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/broad")
        });
    d.is_dir().then_some(d)
}

/// The CSV text of BROAD trial 07 if the shared data is there, else the
/// embedded 22 s excerpt repeated (time shifted) to about the same length.
pub fn trial_07_text() -> (String, &'static str) {
    if let Some(d) = broad_dir() {
        let p = d.join("07_undisturbed_fast_rotation_B.csv");
        if let Ok(s) = std::fs::read_to_string(p) {
            return (s, "BROAD trial 07 (52 518 rows)");
        }
    }
    (repeat_excerpt(8), "embedded excerpt x8 (50 288 rows)")
}

/// The embedded excerpt `n` times, time stamps shifted so they keep increasing.
pub fn repeat_excerpt(n: usize) -> String {
    let text = clino::demo::BROAD_EXCERPT;
    let mut out = String::with_capacity(text.len() * n);
    let mut lines = text.lines();
    let mut data = Vec::new();
    for l in lines.by_ref() {
        out.push_str(l);
        out.push('\n');
        if l.starts_with("t_s") {
            break;
        }
    }
    data.extend(lines);
    let span = 22.0;
    for k in 0..n {
        for l in &data {
            let (t, rest) = l.split_once(',').unwrap();
            let t: f64 = t.parse().unwrap();
            out.push_str(&format!("{:.6},{rest}\n", t + span * k as f64));
        }
    }
    out
}
