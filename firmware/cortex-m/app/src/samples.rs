//! The compact sample file the QEMU build embeds: no CSV parsing on the device.
//!
//! Layout (little-endian): the magic `CLS1`, the number of records `n: u32`,
//! then `n` records of seven `f64` — `t_s, gyr_x, gyr_y, gyr_z` (rad/s),
//! `acc_x, acc_y, acc_z` (m/s²) — 56 bytes each. The QEMU crate's `build.rs`
//! writes it from a recording CSV; the host's checker reads the same bytes.

use clino_core::{ImuSample, Vec3};

/// First four bytes of a sample file.
pub const MAGIC: [u8; 4] = *b"CLS1";
/// Bytes per record: seven `f64`.
pub const RECORD: usize = 56;
/// Bytes before the first record.
pub const HEADER: usize = 8;

/// Why a byte string is not a sample file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FormatError {
    /// Shorter than the header or without the magic.
    NotASampleFile,
    /// The header's count does not match the length (count, bytes of records found).
    Length {
        /// Records the header announces.
        count: u32,
        /// Bytes after the header.
        bytes: usize,
    },
}

/// A sample file, borrowed (in flash on the device).
#[derive(Clone, Copy, Debug)]
pub struct Samples<'a> {
    records: &'a [u8],
}

impl<'a> Samples<'a> {
    /// Check the header and the length.
    pub fn parse(bytes: &'a [u8]) -> Result<Self, FormatError> {
        if bytes.len() < HEADER || bytes[..4] != MAGIC {
            return Err(FormatError::NotASampleFile);
        }
        let count = u32::from_le_bytes([bytes[4], bytes[5], bytes[6], bytes[7]]);
        let records = &bytes[HEADER..];
        if records.len() as u64 != u64::from(count) * RECORD as u64 {
            return Err(FormatError::Length {
                count,
                bytes: records.len(),
            });
        }
        Ok(Samples { records })
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.records.len() / RECORD
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Sample `i`, `None` past the end.
    pub fn get(&self, i: usize) -> Option<ImuSample> {
        let r = self.records.get(i * RECORD..(i + 1) * RECORD)?;
        let f = |k: usize| {
            let mut b = [0u8; 8];
            b.copy_from_slice(&r[8 * k..8 * k + 8]);
            f64::from_le_bytes(b)
        };
        Some(ImuSample::new(
            f(0),
            Vec3::new(f(1), f(2), f(3)),
            Vec3::new(f(4), f(5), f(6)),
        ))
    }

    /// Every sample in order.
    pub fn iter(&self) -> impl Iterator<Item = ImuSample> + '_ {
        (0..self.len()).filter_map(|i| self.get(i))
    }
}

/// The header of a file of `n` records.
pub fn header(n: u32) -> [u8; HEADER] {
    let c = n.to_le_bytes();
    [
        MAGIC[0], MAGIC[1], MAGIC[2], MAGIC[3], c[0], c[1], c[2], c[3],
    ]
}

/// The record of one sample (magnetometer and temperature are not stored).
pub fn record(s: &ImuSample) -> [u8; RECORD] {
    let v = [
        s.t_s,
        s.gyr_rad_s.x,
        s.gyr_rad_s.y,
        s.gyr_rad_s.z,
        s.acc_m_s2.x,
        s.acc_m_s2.y,
        s.acc_m_s2.z,
    ];
    let mut out = [0u8; RECORD];
    for (k, x) in v.iter().enumerate() {
        out[8 * k..8 * k + 8].copy_from_slice(&x.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;
    use std::vec::Vec;

    #[test]
    fn round_trip_is_bit_exact_and_lengths_are_checked() {
        let a = ImuSample::new(
            0.1,
            Vec3::new(1e-300, -0.0, f64::NAN),
            Vec3::new(9.80665, 1.0 / 3.0, -7.5),
        );
        let b = ImuSample::new(0.2, Vec3::new(1.0, 2.0, 3.0), Vec3::new(4.0, 5.0, 6.0));
        let mut f: Vec<u8> = header(2).to_vec();
        f.extend_from_slice(&record(&a));
        f.extend_from_slice(&record(&b));
        let s = Samples::parse(&f).unwrap();
        assert_eq!(s.len(), 2);
        let a2 = s.get(0).unwrap();
        assert_eq!(record(&a2), record(&a)); // NaN and −0 bit for bit
        assert_eq!(s.get(1).unwrap(), b);
        assert_eq!(s.get(2), None);
        assert_eq!(s.iter().count(), 2);

        assert_eq!(
            Samples::parse(&f[..f.len() - 1]).unwrap_err(),
            FormatError::Length {
                count: 2,
                bytes: 111
            }
        );
        assert_eq!(
            Samples::parse(b"CLS2\0\0\0\0").unwrap_err(),
            FormatError::NotASampleFile
        );
        assert_eq!(
            Samples::parse(b"CLS").unwrap_err(),
            FormatError::NotASampleFile
        );
    }
}
