//! Text renderings of typed results: the tables and summaries the `clino`
//! commands print. Each is a pure function of a result (nothing is
//! re-computed here), so a test can pin what a user reads.

pub mod allan;
pub mod calib;
pub mod redundancy;
pub mod stewart;
pub mod survey;
pub mod testbench;

/// A signed value with three decimals, or `-` when it is not available.
pub(crate) fn opt3(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:+.3}"))
}
