//! Every CSV reader of clino over the fuzzer's bytes (the invariant is in
//! `crates/clino/tests/common/readers.rs`, shared with the CI property test).
#![no_main]

#[path = "../../crates/clino/tests/common/readers.rs"]
mod readers;

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    readers::read_everything(data);
});
