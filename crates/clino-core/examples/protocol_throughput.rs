//! Decoder throughput: the conformance vector's frames (one CONFIG, 2000
//! SAMPLEs) decoded and converted to SI over and over; prints frames/s and
//! MB/s. `cargo run --release -p clino-core --example protocol_throughput`.

use std::time::Instant;

use clino_core::protocol::{Decoder, Link};

fn main() {
    let wire: &[u8] = include_bytes!("../../../firmware/protocol/frames.bin");
    let frames = wire.iter().filter(|&&b| b == 0).count();
    let mut best = 0.0f64;
    let mut checksum = 0.0;
    for _ in 0..5 {
        let reps = 200;
        let t = Instant::now();
        for _ in 0..reps {
            let mut dec = Decoder::new();
            let mut link = Link::new();
            dec.feed(wire, |d| {
                if let Ok(f) = d.result
                    && let Some((_, s)) = link.push(&f).sample
                {
                    checksum += s.acc_m_s2.z;
                }
            });
        }
        let s = t.elapsed().as_secs_f64();
        best = best.max((reps * frames) as f64 / s);
    }
    let bytes_per_frame = wire.len() as f64 / frames as f64;
    println!(
        "decode + CRC + link + SI: {:.2} M frames/s ({:.0} MB/s of wire bytes; checksum {checksum:.3})",
        best / 1e6,
        best * bytes_per_frame / 1e6
    );
}
