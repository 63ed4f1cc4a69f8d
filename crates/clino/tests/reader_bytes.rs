//! Every reader over arbitrary and over damaged-but-plausible bytes, property
//! based (a few hundred cases in CI; `fuzz/` runs the same for minutes with
//! cargo-fuzz). See `common/readers.rs` for the invariant.

mod common;

use proptest::prelude::*;

const EXCERPT: &str = include_str!("../data/broad_07_excerpt.csv");

/// The first lines of the excerpt: a real header and real rows to damage.
fn plausible() -> Vec<u8> {
    EXCERPT
        .lines()
        .take(40)
        .collect::<Vec<_>>()
        .join("\n")
        .into_bytes()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(
        std::env::var("PROPTEST_CASES").ok().and_then(|s| s.parse().ok()).unwrap_or(64) * 8
    ))]

    /// Random bytes.
    #[test]
    fn any_bytes(bytes in proptest::collection::vec(any::<u8>(), 0..2048)) {
        common::readers::read_everything(&bytes);
    }

    /// A real recording with bytes overwritten, inserted and cut: the
    /// reader's rules (comments, quotes, BOM, CRLF, numbers) meet damage.
    #[test]
    fn damaged_recording(
        edits in proptest::collection::vec((any::<prop::sample::Index>(), prop_oneof![
            Just(b'\n'), Just(b'\r'), Just(b','), Just(b';'), Just(b'#'), Just(b'"'),
            Just(b'-'), Just(b'e'), Just(b'.'), Just(b'9'), Just(0u8), Just(0xEF), Just(0xFF),
        ], 0u8..3), 1..12),
        cut in any::<prop::sample::Index>(),
    ) {
        let mut b = plausible();
        for (at, byte, op) in edits {
            let i = at.index(b.len() + 1);
            match op {
                0 if i < b.len() => b[i] = byte,
                1 => b.insert(i, byte),
                _ if i < b.len() => { b.remove(i); }
                _ => {}
            }
        }
        let keep = cut.index(b.len() + 1);
        b.truncate(keep.max(b.len() / 2));
        common::readers::read_everything(&b);
    }
}

/// Inputs cargo-fuzz found (`fuzz/`), kept as regressions.
#[test]
fn fuzz_regressions() {
    // a header of 0xFF bytes: each decodes to a 3-byte U+FFFD, and the
    // missing-column message listed 1.2 kB of it
    common::readers::read_everything(include_bytes!("fuzz_regressions/long_binary_header.bin"));
}
