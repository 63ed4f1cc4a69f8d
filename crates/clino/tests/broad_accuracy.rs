//! clino's dynamic filter against VQF on the real BROAD recordings.
//!
//! The VQF figures are PyPI `vqf` 2.x (`VQF(Ts).updateBatch(gyr, acc)['quat6D']`
//! and `offlineVQF`) on the same twelve files with the same scoring, as printed
//! by `scripts/vqf_baseline.py` (and reproduced by `vqf-rs` in
//! `examples/vqf_compare.rs`).
//!
//! The recordings are not in the repository (README, "The BROAD recordings":
//! where they come from and how to convert them). The test is ignored by a
//! plain `cargo test`, which says so in its summary, and runs with
//! `-- --ignored`: `.ci/run` does that whenever the recordings are found,
//! in `$CLINO_BROAD_DIR` or at `<workspace>/../shared/data/broad` (CI keeps
//! a copy of shared/ beside the clone). Run that way without them, it fails
//! and says where it looked.

use std::path::PathBuf;

use clino::eval::evaluate;
use clino::fusion::{FilterConfig, FilterKind};
use clino::io::ReadOptions;

/// (file stem, VQF real-time RMSE °, offline VQF RMSE °)
const VQF: [(&str, f64, f64); 12] = [
    ("02_undisturbed_slow_rotation_B", 0.429, 0.312),
    ("05_undisturbed_slow_rotation_with_breaks_B", 0.353, 0.271),
    ("07_undisturbed_fast_rotation_B", 1.023, 0.959),
    ("09_undisturbed_fast_rotation_with_breaks_B", 0.874, 0.840),
    ("11_undisturbed_slow_translation_B", 0.420, 0.261),
    ("15_undisturbed_fast_translation_A", 0.470, 0.561),
    (
        "18_undisturbed_fast_translation_with_breaks_B",
        0.614,
        0.542,
    ),
    ("21_undisturbed_fast_combined", 1.716, 0.952),
    ("25_disturbed_tapping_B", 0.382, 0.266),
    ("27_disturbed_phone_vibration_B", 0.370, 0.282),
    ("31_disturbed_stationary_magnet_D", 1.141, 0.920),
    ("33_disturbed_attached_magnet_2cm", 0.599, 0.392),
];

/// Where the BROAD recordings are looked for: `$CLINO_BROAD_DIR`, else
/// `<workspace>/../shared/data/broad`.
fn broad_dir() -> PathBuf {
    match std::env::var_os("CLINO_BROAD_DIR") {
        Some(d) => PathBuf::from(d),
        None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/broad"),
    }
}

#[test]
#[ignore = "needs the BROAD recordings (not in the repository): set CLINO_BROAD_DIR or place them at ../shared/data/broad, then run with -- --ignored (.ci/run does when they are there)"]
fn dynamic_beats_vqf_on_broad() {
    let dir = broad_dir();
    assert!(
        dir.is_dir(),
        "BROAD recordings not found at {} (set CLINO_BROAD_DIR; README, \"The BROAD recordings\", says how to get them)",
        dir.display()
    );
    let rt = FilterConfig::new(FilterKind::Dynamic);
    let configs = [rt, rt.with_offline(true)];
    let table = evaluate(
        &[dir],
        &configs,
        &ReadOptions::default(),
        None,
        |_, _, _| {},
    )
    .unwrap();
    assert_eq!(table.recordings.len(), 12, "the twelve BROAD trials");
    let (mut vqf_rt, mut vqf_off) = (0.0, 0.0);
    for rec in &table.recordings {
        let stem = rec.file.file_stem().unwrap().to_string_lossy().to_string();
        let &(_, v_rt, v_off) = VQF.iter().find(|v| v.0 == stem).expect("a known trial");
        vqf_rt += v_rt / 12.0;
        vqf_off += v_off / 12.0;
        let ours = rec.scores[0].rmse_deg;
        // no recording more than 25 % worse than VQF
        assert!(
            ours <= 1.25 * v_rt,
            "{stem}: dynamic {ours:.3}° vs VQF {v_rt:.3}°"
        );
    }
    let (m_rt, m_off) = (table.mean_rmse_deg[0], table.mean_rmse_deg[1]);
    eprintln!(
        "BROAD mean inclination RMSE: dynamic {m_rt:.3}° (VQF {vqf_rt:.3}°), offline {m_off:.3}° (offline VQF {vqf_off:.3}°)"
    );
    assert!(m_rt <= vqf_rt, "dynamic {m_rt:.3}° vs VQF {vqf_rt:.3}°");
    assert!(
        m_off <= vqf_off,
        "offline {m_off:.3}° vs offline VQF {vqf_off:.3}°"
    );
}
