//! clino-fw-check: the host half of the QEMU run.
//!
//! `clino-fw-check SAMPLES.csv RESULTS.bin [QEMU.log]` converts the recording
//! with the same code as the firmware's `build.rs` (so the bytes are the
//! ones embedded — the FNV-1a hash in the QEMU log proves it), runs the
//! host's `clino_core::Pipeline` with the `dynamic` filter over them, and
//! compares every result record (status and quaternion) with the one the
//! firmware wrote. The firmware and this program run the same source
//! (clino-core without `std`, so both use the pure-Rust `libm`) and IEEE 754
//! f64 arithmetic — hardware on x86-64, the compiler's correctly rounded
//! software routines on the Cortex-M4F — so the tolerance is zero: every
//! record must be identical bit for bit. The largest differences are printed
//! either way. Exit status 0 only when everything matches.
//!
//! With the feature `std-libm` the host pipeline uses the platform's libm
//! (glibc's `atan2`, `sin`, … as `clino fuse` does): the results then differ
//! in the last bits and pass within [`TOLERANCE_RAD`] of attitude angle, with
//! every status equal.

use clino_core::Attitude;
use clino_core::filter::FilterSpec;
use clino_core::pipeline::Pipeline;
use clino_fw::samples::Samples;
use clino_fw::{fnv1a64, results};
use std::process::ExitCode;

/// Largest attitude difference accepted, rad: 0 (bit for bit) with the
/// firmware's libm; 1e-9 rad with the platform's (`std-libm`).
const TOLERANCE_RAD: f64 = if cfg!(feature = "std-libm") {
    1e-9
} else {
    0.0
};

#[path = "../../qemu/convert.rs"]
mod convert;

fn main() -> ExitCode {
    match run() {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("clino-fw-check: {e}");
            ExitCode::from(2)
        }
    }
}

/// The hexadecimal word after `key` on the log line starting with `prefix`.
fn log_hash(log: &str, prefix: &str, key: &str) -> Option<u64> {
    let line = log.lines().find(|l| l.starts_with(prefix))?;
    let rest = &line[line.find(key)? + key.len()..];
    let hex: String = rest
        .trim_start()
        .chars()
        .take_while(char::is_ascii_hexdigit)
        .collect();
    u64::from_str_radix(&hex, 16).ok()
}

fn run() -> Result<bool, String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.len() < 2 || args.len() > 3 {
        return Err("usage: clino-fw-check SAMPLES.csv RESULTS.bin [QEMU.log]".into());
    }
    let csv = std::fs::read_to_string(&args[0]).map_err(|e| format!("{}: {e}", args[0]))?;
    let file = convert::csv_to_samples(&args[0], &csv)?;
    let samples = Samples::parse(&file).map_err(|e| format!("{}: {e:?}", args[0]))?;
    let n = samples.len();
    let fw = std::fs::read(&args[1]).map_err(|e| format!("{}: {e}", args[1]))?;
    if fw.len() < 8 || fw[..4] != results::MAGIC {
        return Err(format!("{}: not a clino-fw results file", args[1]));
    }
    let count = u32::from_le_bytes([fw[4], fw[5], fw[6], fw[7]]) as usize;
    if count != n || fw.len() != 8 + n * results::RECORD {
        return Err(format!(
            "{}: {count} records announced, {} bytes of records; the recording has {n} samples",
            args[1],
            fw.len() - 8
        ));
    }
    let mut ok = true;
    if let Some(log_path) = args.get(2) {
        let log = std::fs::read_to_string(log_path).map_err(|e| format!("{log_path}: {e}"))?;
        let fw_samples = log_hash(&log, "samples:", "embedded file");
        let fw_results = log_hash(&log, "results:", "fnv1a64");
        let (hs, hr) = (fnv1a64(&file), fnv1a64(&fw));
        println!(
            "input: host {hs:016x}, firmware {}; results file {hr:016x}, firmware {}",
            fw_samples.map_or("missing".into(), |h| format!("{h:016x}")),
            fw_results.map_or("missing".into(), |h| format!("{h:016x}"))
        );
        if fw_samples != Some(hs) || fw_results != Some(hr) {
            println!("MISMATCH: the firmware's hashes differ from the host's");
            ok = false;
        }
    }

    let mut p = Pipeline::new(FilterSpec::default());
    let (mut identical, mut status_diff) = (0usize, 0usize);
    let (mut max_dq, mut max_angle, mut first_diff) = (0.0f64, 0.0f64, None);
    for (i, s) in samples.iter().enumerate() {
        let host = results::record(&p.update(&s));
        let mut rec = [0u8; results::RECORD];
        rec.copy_from_slice(&fw[8 + i * results::RECORD..8 + (i + 1) * results::RECORD]);
        if rec == host {
            identical += 1;
            continue;
        }
        first_diff.get_or_insert(i);
        let (sf, qf) = results::decode(&rec);
        let (sh, qh) = results::decode(&host);
        if sf != sh {
            status_diff += 1;
        }
        if qf.iter().any(|x| x.is_finite()) != qh.iter().any(|x| x.is_finite()) {
            status_diff += 1; // an attitude on one side only
        } else if qf.iter().chain(&qh).all(|x| x.is_finite()) {
            for k in 0..4 {
                max_dq = max_dq.max((qf[k] - qh[k]).abs());
            }
            let a = Attitude::new_normalize(nalgebra_q(qf));
            let b = Attitude::new_normalize(nalgebra_q(qh));
            max_angle = max_angle.max(a.angle_to(&b));
        }
    }
    let c = p.counts();
    println!(
        "host pipeline (dynamic): {} samples, {} fused; firmware records identical bit for bit: {identical}/{n}",
        c.samples, c.fused
    );
    println!(
        "differences: {} records, {status_diff} statuses or attitudes present on one side only, max |Δq| {max_dq:.3e}, max angle {:.3e} rad (tolerance: {})",
        n - identical,
        max_angle,
        if TOLERANCE_RAD == 0.0 {
            "0, bit for bit".to_string()
        } else {
            format!("{TOLERANCE_RAD:e} rad, statuses equal")
        }
    );
    if let Some(i) = first_diff {
        println!("first difference at sample {i}");
    }
    ok &= if TOLERANCE_RAD == 0.0 {
        identical == n
    } else {
        status_diff == 0 && max_angle <= TOLERANCE_RAD
    };
    println!("{}", if ok { "PASS" } else { "FAIL" });
    Ok(ok)
}

/// w, x, y, z as nalgebra's quaternion (clino-core re-exports no constructor of it).
fn nalgebra_q(q: [f64; 4]) -> <Attitude as core::ops::Deref>::Target {
    <Attitude as core::ops::Deref>::Target::new(q[0], q[1], q[2], q[3])
}
