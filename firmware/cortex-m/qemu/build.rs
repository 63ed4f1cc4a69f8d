//! Embeds the recording: the BROAD excerpt (or `CLINO_FW_SAMPLES`), converted
//! to the compact sample file at build time (no CSV parsing on the device),
//! and puts `memory.x` on the linker's path for cortex-m-rt's `link.x`.

use std::path::PathBuf;

#[path = "convert.rs"]
#[allow(dead_code)]
mod convert;

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").unwrap());
    let out = PathBuf::from(std::env::var("OUT_DIR").unwrap());
    let csv = match std::env::var("CLINO_FW_SAMPLES") {
        Ok(p) => PathBuf::from(p),
        Err(_) => manifest.join("../../../crates/clino/data/broad_07_excerpt.csv"),
    };
    println!("cargo:rerun-if-env-changed=CLINO_FW_SAMPLES");
    println!("cargo:rerun-if-changed={}", csv.display());
    println!("cargo:rerun-if-changed=convert.rs");
    let text = std::fs::read_to_string(&csv)
        .unwrap_or_else(|e| panic!("cannot read the samples {}: {e}", csv.display()));
    let bin = convert::csv_to_samples(&csv.display().to_string(), &text)
        .unwrap_or_else(|e| panic!("{e}"));
    std::fs::write(out.join("samples.bin"), bin).unwrap();

    let memory = manifest.join("../memory.x");
    println!("cargo:rerun-if-changed={}", memory.display());
    std::fs::copy(&memory, out.join("memory.x")).unwrap();
    println!("cargo:rustc-link-search={}", out.display());
}
