//! # clino-fw — the instrument on a Cortex-M4F
//!
//! The per-sample loop of clino's dynamic inclinometer as firmware, `no_std`
//! and allocation-free, generic over the embedded-hal 1.0 traits so the same
//! code runs on any board (and on the host, in the tests):
//!
//! * [`source`] — where samples come from: the MPU6050 over I²C
//!   ([`source::Mpu6050Source`], the `clino-mpu6050` driver and a microsecond
//!   clock), or a replay of recorded samples ([`samples`], the compact binary
//!   the QEMU build embeds);
//! * [`instrument`] — one sample through `clino_core::Pipeline` (the
//!   `dynamic` filter by default) and roll and pitch onto the two dials;
//! * [`dials`] — a hobby servo on a PWM channel
//!   ([`embedded_hal::pwm::SetDutyCycle`]) showing an angle;
//! * [`serial`] — the one function that sends the wire protocol's frames
//!   (encoded by `clino_core::protocol`);
//! * [`results`] — the record the QEMU build writes per sample, so the host
//!   can compare it with its own pipeline.
#![no_std]
#![deny(missing_docs)]

pub mod dials;
pub mod instrument;
pub mod results;
pub mod samples;
pub mod serial;
pub mod source;

/// FNV-1a, 64 bit (Fowler–Noll–Vo; offset basis 0xcbf29ce484222325, prime
/// 0x100000001b3): the firmware and the host print it over the samples and
/// the results to show they saw the same bytes.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    fnv1a64_extend(0xcbf2_9ce4_8422_2325, bytes)
}

/// Continue an FNV-1a hash `h` over more `bytes` (streaming form of [`fnv1a64`]).
pub fn fnv1a64_extend(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

#[cfg(test)]
mod tests {
    #[test]
    fn fnv1a64_reference_values() {
        // published test vectors of FNV-1a 64
        assert_eq!(super::fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(super::fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(super::fnv1a64(b"foobar"), 0x8594_4171_f739_67e8);
        let h = super::fnv1a64_extend(super::fnv1a64(b"foo"), b"bar");
        assert_eq!(h, super::fnv1a64(b"foobar"));
    }
}
