//! Every reader of the library over arbitrary bytes: shared by the
//! property-based test (`tests/reader_bytes.rs`, in CI) and the cargo-fuzz
//! target (`fuzz/fuzz_targets/readers.rs`, run by hand for minutes).
//!
//! The invariant: no panic; every error names the file it came from and
//! quotes at most a short piece of the input.

use clino::io::{ImuCsvReader, ReadOptions};
use clino::testbench::static_record::{GapPolicy, static_record_from_bytes};
use std::path::Path;

/// Longest error message accepted, bytes (a header listed in full is the longest part).
const MAX_MESSAGE: usize = 600;

fn check(e: &clino::Error, input_len: usize) {
    assert!(e.file.is_some(), "an error without its file: {e}");
    let m = e.to_string();
    assert!(
        m.len() <= MAX_MESSAGE + input_len.min(MAX_MESSAGE),
        "a {}-byte message for {input_len} bytes of input",
        m.len()
    );
}

/// Run every reader over `bytes`.
pub fn read_everything(bytes: &[u8]) {
    let name = Path::new("fuzz.csv");
    let n = bytes.len();
    let options = [
        ReadOptions::default(),
        ReadOptions {
            rate_hz: Some(100.0),
            ..ReadOptions::default()
        },
        ReadOptions {
            imu_only: true,
            ..ReadOptions::default()
        },
    ];
    for opts in &options {
        match ImuCsvReader::new(bytes, name, opts) {
            Ok(mut r) => loop {
                match r.next_row() {
                    Ok(Some(row)) => {
                        assert!(row.sample.t_s.is_finite(), "a non-finite time stamp passed");
                    }
                    Ok(None) => break,
                    Err(e) => {
                        check(&e, n);
                        break;
                    }
                }
            },
            Err(e) => check(&e, n),
        }
    }
    if let Err(e) = clino::calib::recording::Recording::from_reader(bytes) {
        check(&e, n);
    }
    if let Err(e) = clino::survey::stations::parse_stations(bytes) {
        check(&e, n);
    }
    if let Err(e) = clino::redundancy::recording::read_csv_from(bytes, name) {
        check(&e, n);
    }
    match clino::testbench::recording::Table::from_reader(bytes, name) {
        Ok(t) => {
            let _ = t.channels();
            if let Err(e) = t.imu_samples() {
                check(&e, n);
            }
        }
        Err(e) => check(&e, n),
    }
    for policy in [GapPolicy::Refuse, GapPolicy::Longest] {
        if let Err(e) = static_record_from_bytes(bytes, name, policy) {
            check(&e, n);
        }
    }
}
