//! The Parquet path of clino's one reader over the fuzzer's bytes, written to
//! a `.parquet` file (the reader opens files by path): no panic, errors name
//! the file.
#![no_main]

use clino::io::{ImuCsvReader, ReadOptions, TableReader};

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let path = std::env::temp_dir().join(format!("clino-fuzz-{}.parquet", std::process::id()));
    std::fs::write(&path, data).unwrap();
    match TableReader::open(&path) {
        Ok(mut t) => {
            let n = t.header().len();
            loop {
                match t.next_record() {
                    Ok(true) => {
                        for i in 0..n {
                            let _ = t.f64(i);
                            let _ = t.text(i);
                        }
                    }
                    Ok(false) => break,
                    Err(e) => {
                        assert!(e.file.is_some(), "{e}");
                        break;
                    }
                }
            }
        }
        Err(e) => assert!(e.file.is_some(), "{e}"),
    }
    if let Ok(r) = ImuCsvReader::from_path(&path, &ReadOptions::default()) {
        for row in r {
            if let Err(e) = row {
                assert!(e.file.is_some(), "{e}");
                break;
            }
        }
    }
});
