//! The serial link: the wire protocol's board → host frames.
//!
//! [`Frame`] holds exactly the fields of the protocol's CONFIG (0x01) and
//! SAMPLE (0x02) payloads (protocol v1, `firmware/protocol/PROTOCOL.md`).
//! [`send_frame`] is the one place where they become bytes on the UART.

use clino_core::protocol;
use clino_mpu6050::{Config, RawSample};

/// The protocol's board identifier of this firmware (2 = Cortex-M4F example).
pub const BOARD_ID: u8 = 2;
/// Protocol version spoken.
pub const PROTO_VERSION: u8 = 1;

/// A board → host frame, by its fields.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Frame {
    /// CONFIG: what the board measures with.
    Config {
        /// The sensor configuration (ranges, DLPF, rate).
        config: Config,
        /// True while samples are streamed.
        streaming: bool,
    },
    /// SAMPLE: one reading as raw counts.
    Sample {
        /// Sequence number (0 at start, +1 per sample, wraps).
        seq: u16,
        /// Board time, µs, wrapping.
        t_us: u32,
        /// The MPU6050's registers.
        raw: RawSample,
    },
}

/// The CONFIG frame's `rate_hz`: the sensor's sample rate rounded to whole hertz.
pub fn rate_hz(config: &Config) -> u16 {
    (config.sample_rate_hz() + 0.5) as u16
}

/// Firmware version (major, minor, patch) from the crate's version.
pub fn fw_version() -> (u8, u8, u8) {
    let p = |s: &str| s.parse::<u8>().unwrap_or(0);
    (
        p(env!("CARGO_PKG_VERSION_MAJOR")),
        p(env!("CARGO_PKG_VERSION_MINOR")),
        p(env!("CARGO_PKG_VERSION_PATCH")),
    )
}

/// The frame in the protocol's own type (`clino_core::protocol::Frame`).
pub fn to_protocol(frame: &Frame) -> protocol::Frame {
    match *frame {
        Frame::Config { config, streaming } => {
            let (major, minor, patch) = fw_version();
            protocol::Frame::Config(protocol::Config {
                proto_version: PROTO_VERSION,
                firmware: [major, minor, patch],
                board: BOARD_ID,
                rate_hz: rate_hz(&config),
                accel_fs_g: config.accel_range.g(),
                gyro_fs_dps: config.gyro_range.dps(),
                dlpf_cfg: config.dlpf.cfg(),
                streaming: u8::from(streaming),
            })
        }
        Frame::Sample { seq, t_us, raw } => protocol::Frame::Sample(protocol::Sample {
            seq,
            t_us,
            acc: raw.accel,
            temp: raw.temp,
            gyr: raw.gyro,
        }),
    }
}

/// Send one frame on the serial link: encoded by `clino_core::protocol`
/// (type byte, payload, CRC-16/CCITT-FALSE, COBS, 0x00 delimiter) and
/// written whole. Returns `Ok(true)` once the bytes are written.
pub fn send_frame<W: embedded_io::Write>(tx: &mut W, frame: &Frame) -> Result<bool, W::Error> {
    let mut buf = [0u8; protocol::MAX_FRAME];
    // a CONFIG or SAMPLE always fits MAX_FRAME (the protocol's own bound)
    let Ok(n) = protocol::encode(&to_protocol(frame), &mut buf) else {
        return Ok(false);
    };
    tx.write_all(&buf[..n])?;
    Ok(true)
}
