//! The per-sample result record the QEMU build writes (and the host compares):
//! the pipeline's status as one byte (its index in `Status::ALL`) and the
//! attitude quaternion w, x, y, z as four little-endian `f64` (all NaN
//! before initialisation) — 33 bytes; a file starts with `CLQ1` and `n: u32`.

use clino_core::pipeline::{Output, Status};

/// First four bytes of a result file.
pub const MAGIC: [u8; 4] = *b"CLQ1";
/// Bytes per record.
pub const RECORD: usize = 33;

/// The record of one output.
pub fn record(out: &Output) -> [u8; RECORD] {
    let status = Status::ALL
        .iter()
        .position(|s| *s == out.status)
        .unwrap_or(usize::MAX) as u8;
    let q = match &out.attitude {
        Some(a) => [a.w, a.i, a.j, a.k],
        None => [f64::NAN; 4],
    };
    let mut r = [0u8; RECORD];
    r[0] = status;
    for (k, x) in q.iter().enumerate() {
        r[1 + 8 * k..9 + 8 * k].copy_from_slice(&x.to_le_bytes());
    }
    r
}

/// One decoded record: the status (`None` for an unknown byte) and w, x, y, z.
pub fn decode(r: &[u8; RECORD]) -> (Option<Status>, [f64; 4]) {
    let mut q = [0.0; 4];
    for (k, x) in q.iter_mut().enumerate() {
        let mut b = [0u8; 8];
        b.copy_from_slice(&r[1 + 8 * k..9 + 8 * k]);
        *x = f64::from_le_bytes(b);
    }
    (Status::ALL.get(usize::from(r[0])).copied(), q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clino_core::Attitude;

    #[test]
    fn round_trip() {
        let a = Attitude::from_euler_angles(0.1, -0.2, 0.3);
        let o = Output {
            status: Status::Fused,
            attitude: Some(a),
        };
        let (s, q) = decode(&record(&o));
        assert_eq!(s, Some(Status::Fused));
        assert_eq!(q, [a.w, a.i, a.j, a.k]);
        let w = Output {
            status: Status::Waiting,
            attitude: None,
        };
        let (s, q) = decode(&record(&w));
        assert_eq!(s, Some(Status::Waiting));
        assert!(q.iter().all(|x| x.is_nan()));
        let mut bad = record(&w);
        bad[0] = 200;
        assert_eq!(decode(&bad).0, None);
    }
}
