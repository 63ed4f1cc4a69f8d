//! Write the protocol's conformance vector, `firmware/protocol/frames.bin`
//! (one CONFIG and 2000 SAMPLE frames, the bytes a board sends) and
//! `frames.csv` (the same samples decoded, SI units), from the embedded
//! BROAD excerpt: `cargo run -p clino --example protocol_vector [DIR]`.
//! The test `stream_vector_is_reproducible` checks the shipped files equal
//! what this writes.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args().nth(1).map_or_else(
        || std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../firmware/protocol"),
        std::path::PathBuf::from,
    );
    let (bin, csv) = clino::stream::reference_vector()?;
    std::fs::create_dir_all(&dir)?;
    std::fs::write(dir.join("frames.bin"), &bin)?;
    std::fs::write(dir.join("frames.csv"), &csv)?;
    println!(
        "{} bytes, {} samples written to {}",
        bin.len(),
        csv.lines().count() - 1,
        dir.display()
    );
    Ok(())
}
