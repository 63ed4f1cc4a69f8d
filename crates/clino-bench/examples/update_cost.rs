//! Deterministic cost of one filter update on the host: runs one filter
//! over the samples of BROAD trial 07 a given number of times, so that
//! valgrind (or `perf stat -e instructions:u` where the machine has counters)
//! counts instructions instead of timing a shared, loaded machine. Reading
//! the file is counted too and removed with a 0-pass run.
//!
//! ```text
//! cargo build --release -p clino-bench --example update_cost
//! for f in dynamic "dynamic:gyro_scale_sigma=0,accel_scale_sigma=0" vqf_rs; do
//!   for n in 0 3; do
//!     valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!       target/release/examples/update_cost "$f" $n 2>&1 | grep Collected
//! done; done
//! ```
//!
//! (instructions of the 3-pass run − those of the 0-pass run) / (3 × 52 518)
//! is the filter's instructions per update. The first argument is any filter
//! of `clino eval --filters` (`name:key=value,…`) or `vqf_rs`.

use std::hint::black_box;

use clino::core::AttitudeFilter;
use clino::fusion::parse_spec;
use clino::io::{ImuCsvReader, ReadOptions};
use clino_bench as common;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "dynamic".into());
    let passes: usize = args.next().unwrap_or_else(|| "20".into()).parse()?;
    let (text, what) = common::trial_07_text();
    let mut data = Vec::new();
    for r in ImuCsvReader::new(text.as_bytes(), "trial_07.csv", &ReadOptions::default())? {
        let r = r?;
        data.push((r.sample.gyr_rad_s, r.sample.acc_m_s2));
    }
    let dt = 1.0 / 285.714_286;
    let mut out = 0.0;
    for _ in 0..passes {
        if which == "vqf_rs" {
            let mut v = vqf_rs::VQF::new(dt, None, None, None);
            for (g, a) in black_box(&data) {
                v.update([g.x, g.y, g.z], [a.x, a.y, a.z], None);
            }
            out += v.quat_6d().0;
        } else {
            let mut f = parse_spec(&which)?.build();
            for (g, a) in black_box(&data) {
                f.update(*g, *a, dt);
            }
            out += f.attitude().w;
        }
    }
    eprintln!(
        "{which}: {passes} passes over {what} ({} rows), checksum {out:.6}",
        data.len()
    );
    Ok(())
}
