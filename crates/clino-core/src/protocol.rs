//! The serial wire protocol v1 between a clino board (Arduino UNO, Cortex-M)
//! and the host: frames, CRC, COBS, an encoder, a streaming decoder, and the
//! conversion of raw MPU6050 counts to SI.
//!
//! The byte-level specification is `firmware/protocol/PROTOCOL.md`; the
//! conformance vector beside it (`frames.bin`, `frames.csv`) is what this
//! module's tests and every other implementation are checked against.
//!
//! * Framing: `COBS(body) ++ 0x00` (Cheshire & Baker, "Consistent Overhead
//!   Byte Stuffing", IEEE/ACM Trans. Networking 7(2), 1999), body =
//!   `type ++ payload ++ crc16_le(type ++ payload)`, at most [`MAX_BODY`] bytes;
//! * CRC-16/CCITT-FALSE ([`crc16`]): polynomial 0x1021, init 0xFFFF, no
//!   reflection, no final XOR (check value of `"123456789"` = 0x29B1);
//! * [`Frame`] holds every frame type; [`encode`] writes one into a caller's
//!   buffer; [`Decoder`] takes bytes one at a time (or slices) and yields
//!   frames or typed [`FrameError`]s, resynchronising at every 0x00;
//! * [`Scales`] and [`Sample::to_si`] convert counts to SI (MPU6050 register
//!   map rev 4.2 / product specification rev 3.4: LSB per g and per °/s of
//!   each full-scale range; temperature °C = raw/340 + 36.53);
//! * [`Link`] follows one board's stream: it unwraps the 32-bit microsecond
//!   clock ([`TimeUnwrap`]) and notices sequence gaps, repeated frames and
//!   board resets.
//!
//! Nothing here allocates or panics, whatever bytes arrive.
//!
//! ```
//! use clino_core::protocol::{encode, Decoder, Frame, MAX_FRAME};
//! let mut wire = [0u8; MAX_FRAME];
//! let n = encode(&Frame::SetDials { roll_cdeg: -1250, pitch_cdeg: 300 }, &mut wire).unwrap();
//! let mut dec = Decoder::new();
//! let mut got = None;
//! for &b in &wire[..n] {
//!     if let Some(d) = dec.push(b) {
//!         got = Some(d.result);
//!     }
//! }
//! assert_eq!(got, Some(Ok(Frame::SetDials { roll_cdeg: -1250, pitch_cdeg: 300 })));
//! ```

use crate::{G0, ImuSample, Vec3};

/// Protocol version carried in [`Config::proto_version`].
pub const PROTO_VERSION: u8 = 1;
/// Largest body (type + payload + CRC), bytes.
pub const MAX_BODY: usize = 64;
/// Largest COBS-encoded body (one overhead byte for bodies under 255 bytes).
pub const MAX_ENCODED: usize = MAX_BODY + 1;
/// Largest frame on the wire, with its 0x00 delimiter.
pub const MAX_FRAME: usize = MAX_ENCODED + 1;

/// Frame type bytes.
pub mod ty {
    /// Board → host: configuration.
    pub const CONFIG: u8 = 0x01;
    /// Board → host: one raw sample.
    pub const SAMPLE: u8 = 0x02;
    /// Board → host: answer to a command.
    pub const ACK: u8 = 0x03;
    /// Host → board: send a CONFIG.
    pub const REQUEST_CONFIG: u8 = 0x10;
    /// Host → board: set the sample rate.
    pub const SET_RATE: u8 = 0x11;
    /// Host → board: set full-scale ranges and low-pass.
    pub const SET_RANGES: u8 = 0x12;
    /// Host → board: start streaming.
    pub const START: u8 = 0x13;
    /// Host → board: stop streaming.
    pub const STOP: u8 = 0x14;
    /// Host → board: show these angles on the dials.
    pub const SET_DIALS: u8 = 0x15;
}

/// ACK status bytes.
pub mod ack {
    /// Accepted.
    pub const OK: u8 = 0;
    /// A value out of range (or a rate the link cannot carry).
    pub const OUT_OF_RANGE: u8 = 1;
    /// Unknown command type.
    pub const UNKNOWN_COMMAND: u8 = 2;
    /// The command frame was bad (CRC, length).
    pub const BAD_FRAME: u8 = 3;
}

/// The payload length of a frame type, `None` for an unknown type.
pub const fn payload_len(ty: u8) -> Option<usize> {
    match ty {
        ty::CONFIG => Some(12),
        ty::SAMPLE => Some(20),
        ty::ACK => Some(2),
        ty::REQUEST_CONFIG | ty::START | ty::STOP => Some(0),
        ty::SET_RATE => Some(2),
        ty::SET_RANGES => Some(4),
        ty::SET_DIALS => Some(4),
        _ => None,
    }
}

/// The board's configuration (CONFIG, type 0x01, 12-byte payload).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// Protocol version (= [`PROTO_VERSION`]).
    pub proto_version: u8,
    /// Firmware version: major, minor, patch.
    pub firmware: [u8; 3],
    /// Board: 1 Arduino UNO (ATmega328P), 2 Cortex-M4F example, 3 host simulator.
    pub board: u8,
    /// Sample rate, Hz.
    pub rate_hz: u16,
    /// Accelerometer full scale, ±g (2, 4, 8, 16).
    pub accel_fs_g: u8,
    /// Gyro full scale, ±°/s (250, 500, 1000, 2000).
    pub gyro_fs_dps: u16,
    /// MPU6050 CONFIG register DLPF_CFG, 0..=6.
    pub dlpf_cfg: u8,
    /// 0 stopped, 1 streaming.
    pub streaming: u8,
}

/// One raw sample (SAMPLE, type 0x02, 20-byte payload): the MPU6050's
/// registers ACCEL_XOUT_H … GYRO_ZOUT_L as signed counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Sample {
    /// Sequence number: 0 at boot or START, +1 per sample, wraps.
    pub seq: u16,
    /// Board time, µs since boot, wraps at 2³².
    pub t_us: u32,
    /// Accelerometer counts x, y, z.
    pub acc: [i16; 3],
    /// Temperature counts.
    pub temp: i16,
    /// Gyro counts x, y, z.
    pub gyr: [i16; 3],
}

/// The answer to a command (ACK, type 0x03).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Ack {
    /// The type byte of the command answered.
    pub command: u8,
    /// Status, one of [`ack`].
    pub status: u8,
}

/// Every frame of protocol v1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Frame {
    /// Board → host: configuration.
    Config(Config),
    /// Board → host: a raw sample.
    Sample(Sample),
    /// Board → host: answer to a command.
    Ack(Ack),
    /// Host → board: send a CONFIG.
    RequestConfig,
    /// Host → board: sample rate, Hz (1..=1000).
    SetRate {
        /// Requested rate, Hz.
        rate_hz: u16,
    },
    /// Host → board: ranges and digital low-pass.
    SetRanges {
        /// ±g: 2, 4, 8 or 16.
        accel_fs_g: u8,
        /// ±°/s: 250, 500, 1000 or 2000.
        gyro_fs_dps: u16,
        /// DLPF_CFG 0..=6.
        dlpf_cfg: u8,
    },
    /// Host → board: start streaming.
    Start,
    /// Host → board: stop streaming.
    Stop,
    /// Host → board: dial angles, centidegrees (−9000..=9000).
    SetDials {
        /// Roll, 0.01°.
        roll_cdeg: i16,
        /// Pitch, 0.01°.
        pitch_cdeg: i16,
    },
}

fn le16(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes([b[i], b[i + 1]])
}
fn lei16(b: &[u8], i: usize) -> i16 {
    i16::from_le_bytes([b[i], b[i + 1]])
}

impl Frame {
    /// The type byte.
    pub const fn ty(&self) -> u8 {
        match self {
            Frame::Config(_) => ty::CONFIG,
            Frame::Sample(_) => ty::SAMPLE,
            Frame::Ack(_) => ty::ACK,
            Frame::RequestConfig => ty::REQUEST_CONFIG,
            Frame::SetRate { .. } => ty::SET_RATE,
            Frame::SetRanges { .. } => ty::SET_RANGES,
            Frame::Start => ty::START,
            Frame::Stop => ty::STOP,
            Frame::SetDials { .. } => ty::SET_DIALS,
        }
    }

    /// Write `type ++ payload` into `out` (at least 21 bytes); returns its length.
    fn write_data(&self, out: &mut [u8; MAX_BODY]) -> usize {
        out[0] = self.ty();
        let p = &mut out[1..];
        let put16 = |p: &mut [u8], i: usize, v: [u8; 2]| {
            p[i] = v[0];
            p[i + 1] = v[1];
        };
        match *self {
            Frame::Config(c) => {
                p[0] = c.proto_version;
                p[1..4].copy_from_slice(&c.firmware);
                p[4] = c.board;
                put16(p, 5, c.rate_hz.to_le_bytes());
                p[7] = c.accel_fs_g;
                put16(p, 8, c.gyro_fs_dps.to_le_bytes());
                p[10] = c.dlpf_cfg;
                p[11] = c.streaming;
            }
            Frame::Sample(s) => {
                put16(p, 0, s.seq.to_le_bytes());
                p[2..6].copy_from_slice(&s.t_us.to_le_bytes());
                let vals = [
                    s.acc[0], s.acc[1], s.acc[2], s.temp, s.gyr[0], s.gyr[1], s.gyr[2],
                ];
                for (k, v) in vals.iter().enumerate() {
                    put16(p, 6 + 2 * k, v.to_le_bytes());
                }
            }
            Frame::Ack(a) => {
                p[0] = a.command;
                p[1] = a.status;
            }
            Frame::RequestConfig | Frame::Start | Frame::Stop => {}
            Frame::SetRate { rate_hz } => put16(p, 0, rate_hz.to_le_bytes()),
            Frame::SetRanges {
                accel_fs_g,
                gyro_fs_dps,
                dlpf_cfg,
            } => {
                p[0] = accel_fs_g;
                put16(p, 1, gyro_fs_dps.to_le_bytes());
                p[3] = dlpf_cfg;
            }
            Frame::SetDials {
                roll_cdeg,
                pitch_cdeg,
            } => {
                put16(p, 0, roll_cdeg.to_le_bytes());
                put16(p, 2, pitch_cdeg.to_le_bytes());
            }
        }
        // every type has a known payload length
        1 + payload_len(self.ty()).unwrap_or(0)
    }

    /// The body: `type ++ payload ++ crc16_le`, into `out`; returns its length.
    pub fn write_body(&self, out: &mut [u8; MAX_BODY]) -> usize {
        let n = self.write_data(out);
        let crc = crc16(&out[..n]).to_le_bytes();
        out[n] = crc[0];
        out[n + 1] = crc[1];
        n + 2
    }

    /// Parse a decoded body (`type ++ payload ++ crc16_le`). The CRC is
    /// checked first, so an unknown type or a wrong length is reported only
    /// for a body that arrived intact.
    pub fn parse_body(body: &[u8]) -> Result<Frame, FrameError> {
        if body.len() > MAX_BODY {
            return Err(FrameError::Overlong { bytes: body.len() });
        }
        if body.len() < 3 {
            return Err(FrameError::TooShort { len: body.len() });
        }
        let (data, crc) = body.split_at(body.len() - 2);
        let found = le16(crc, 0);
        let expected = crc16(data);
        if found != expected {
            return Err(FrameError::BadCrc { expected, found });
        }
        let t = data[0];
        let p = &data[1..];
        match payload_len(t) {
            None => return Err(FrameError::UnknownType(t)),
            Some(n) if n != p.len() => {
                return Err(FrameError::BadLength {
                    ty: t,
                    len: p.len(),
                });
            }
            Some(_) => {}
        }
        Ok(match t {
            ty::CONFIG => Frame::Config(Config {
                proto_version: p[0],
                firmware: [p[1], p[2], p[3]],
                board: p[4],
                rate_hz: le16(p, 5),
                accel_fs_g: p[7],
                gyro_fs_dps: le16(p, 8),
                dlpf_cfg: p[10],
                streaming: p[11],
            }),
            ty::SAMPLE => Frame::Sample(Sample {
                seq: le16(p, 0),
                t_us: u32::from_le_bytes([p[2], p[3], p[4], p[5]]),
                acc: [lei16(p, 6), lei16(p, 8), lei16(p, 10)],
                temp: lei16(p, 12),
                gyr: [lei16(p, 14), lei16(p, 16), lei16(p, 18)],
            }),
            ty::ACK => Frame::Ack(Ack {
                command: p[0],
                status: p[1],
            }),
            ty::REQUEST_CONFIG => Frame::RequestConfig,
            ty::SET_RATE => Frame::SetRate {
                rate_hz: le16(p, 0),
            },
            ty::SET_RANGES => Frame::SetRanges {
                accel_fs_g: p[0],
                gyro_fs_dps: le16(p, 1),
                dlpf_cfg: p[3],
            },
            ty::START => Frame::Start,
            ty::STOP => Frame::Stop,
            _ => Frame::SetDials {
                roll_cdeg: lei16(p, 0),
                pitch_cdeg: lei16(p, 2),
            },
        })
    }
}

/// CRC-16/CCITT-FALSE lookup table (MSB first, polynomial 0x1021).
const CRC_TABLE: [u16; 256] = {
    let mut t = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut c = (i as u16) << 8;
        let mut k = 0;
        while k < 8 {
            c = if c & 0x8000 != 0 {
                (c << 1) ^ 0x1021
            } else {
                c << 1
            };
            k += 1;
        }
        t[i] = c;
        i += 1;
    }
    t
};

/// Continue a CRC-16/CCITT-FALSE over more bytes (start from 0xFFFF).
pub fn crc16_update(mut crc: u16, data: &[u8]) -> u16 {
    for &b in data {
        crc = (crc << 8) ^ CRC_TABLE[((crc >> 8) as u8 ^ b) as usize];
    }
    crc
}

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, not reflected, xorout 0):
/// `crc16(b"123456789") == 0x29B1` (the catalogue's check value).
pub fn crc16(data: &[u8]) -> u16 {
    crc16_update(0xFFFF, data)
}

/// The output buffer is too small.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BufferTooSmall {
    /// Bytes needed.
    pub needed: usize,
}

/// Why a COBS block could not be decoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CobsError {
    /// A 0x00 inside the encoded data.
    ZeroByte,
    /// A code byte points past the end of the data.
    Truncated,
    /// The decoded data does not fit the output buffer.
    Overflow,
}

/// Largest encoded length of `n` bytes of data (one code byte per started
/// 254-byte block).
pub const fn cobs_max_encoded(n: usize) -> usize {
    n + n / 254 + 1
}

/// COBS-encode `src` into `dst` (no delimiter); returns the encoded length.
/// A final block of 254 non-zero bytes gets no trailing `0x01` (as in the
/// paper and the usual test vectors).
pub fn cobs_encode(src: &[u8], dst: &mut [u8]) -> Result<usize, BufferTooSmall> {
    let needed = cobs_max_encoded(src.len());
    if dst.len() < needed {
        return Err(BufferTooSmall { needed });
    }
    let mut code_at = 0;
    let mut out = 1;
    let mut code: u8 = 1;
    for (i, &b) in src.iter().enumerate() {
        if b == 0 {
            dst[code_at] = code;
            code_at = out;
            out += 1;
            code = 1;
        } else {
            dst[out] = b;
            out += 1;
            code += 1;
            if code == 0xFF && i + 1 < src.len() {
                dst[code_at] = code;
                code_at = out;
                out += 1;
                code = 1;
            }
        }
    }
    dst[code_at] = code;
    Ok(out)
}

/// Decode one COBS block (without its delimiter) into `dst`; returns the
/// decoded length. Empty input decodes to nothing.
pub fn cobs_decode(src: &[u8], dst: &mut [u8]) -> Result<usize, CobsError> {
    let mut i = 0;
    let mut out = 0;
    while i < src.len() {
        let code = src[i];
        if code == 0 {
            return Err(CobsError::ZeroByte);
        }
        i += 1;
        let n = code as usize - 1;
        if i + n > src.len() {
            return Err(CobsError::Truncated);
        }
        if out + n > dst.len() {
            return Err(CobsError::Overflow);
        }
        for k in 0..n {
            let b = src[i + k];
            if b == 0 {
                return Err(CobsError::ZeroByte);
            }
            dst[out + k] = b;
        }
        i += n;
        out += n;
        if code != 0xFF && i < src.len() {
            if out >= dst.len() {
                return Err(CobsError::Overflow);
            }
            dst[out] = 0;
            out += 1;
        }
    }
    Ok(out)
}

/// Encode a frame for the wire, `COBS(body) ++ 0x00`, into `out` (at least
/// [`MAX_FRAME`] bytes is always enough); returns the number of bytes.
pub fn encode(frame: &Frame, out: &mut [u8]) -> Result<usize, BufferTooSmall> {
    let mut body = [0u8; MAX_BODY];
    let n = frame.write_body(&mut body);
    let needed = cobs_max_encoded(n) + 1;
    if out.len() < needed {
        return Err(BufferTooSmall { needed });
    }
    let m = cobs_encode(&body[..n], out)?;
    out[m] = 0;
    Ok(m + 1)
}

/// Why the bytes between two delimiters were not a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameError {
    /// Not valid COBS.
    Cobs(CobsError),
    /// A body shorter than type + CRC (3 bytes).
    TooShort {
        /// Decoded length.
        len: usize,
    },
    /// The CRC does not match.
    BadCrc {
        /// CRC computed over the received type and payload.
        expected: u16,
        /// CRC received.
        found: u16,
    },
    /// An intact body of a type this version does not know.
    UnknownType(u8),
    /// An intact body whose payload length is wrong for its type.
    BadLength {
        /// The type byte.
        ty: u8,
        /// Payload length received.
        len: usize,
    },
    /// More bytes than the longest frame before a delimiter.
    Overlong {
        /// Bytes discarded.
        bytes: usize,
    },
}

impl FrameError {
    /// A short name of the kind of error (for counts).
    pub const fn kind_name(&self) -> &'static str {
        match self {
            FrameError::Cobs(_) => "cobs",
            FrameError::TooShort { .. } => "too short",
            FrameError::BadCrc { .. } => "bad crc",
            FrameError::UnknownType(_) => "unknown type",
            FrameError::BadLength { .. } => "bad length",
            FrameError::Overlong { .. } => "overlong",
        }
    }
}

impl core::fmt::Display for FrameError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            FrameError::Cobs(e) => write!(f, "not valid COBS ({e:?})"),
            FrameError::TooShort { len } => write!(f, "body of {len} bytes (at least 3)"),
            FrameError::BadCrc { expected, found } => {
                write!(f, "CRC 0x{found:04X} received, 0x{expected:04X} computed")
            }
            FrameError::UnknownType(t) => write!(f, "unknown frame type 0x{t:02X}"),
            FrameError::BadLength { ty, len } => write!(
                f,
                "payload of {len} bytes for type 0x{ty:02X} (expected {})",
                payload_len(*ty).unwrap_or(0)
            ),
            FrameError::Overlong { bytes } => {
                write!(f, "{bytes} bytes without a delimiter (at most {MAX_FRAME})")
            }
        }
    }
}

/// What the decoder made of the bytes up to one delimiter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decoded {
    /// The frame, or why the bytes were not one.
    pub result: Result<Frame, FrameError>,
    /// Bytes discarded before the frame (garbage before it since the last
    /// delimiter); 0 for an error, whose bytes are all in the error.
    pub garbage: usize,
}

/// Streaming frame decoder: push bytes one at a time ([`Decoder::push`]) or
/// a slice at a time ([`Decoder::feed`]).
///
/// The bytes between two 0x00 delimiters are one candidate. If they decode
/// (COBS, CRC, type and length) they are a frame. If not, the decoder looks
/// for a valid frame at their *tail*, longest first: garbage that arrived
/// after a delimiter (line noise, a half-sent frame at connect, another
/// program's text) would otherwise take the next good frame with it. A
/// recovered frame reports how many bytes before it were discarded
/// ([`Decoded::garbage`]); a false recovery needs a 16-bit CRC match and a
/// valid type and length, odds below 2⁻¹⁶ per discarded candidate. Empty
/// candidates (0x00 0x00) are ignored. At most [`MAX_ENCODED`] bytes are kept;
/// a longer run is an [`FrameError::Overlong`] unless its tail is a frame.
#[derive(Clone, Debug)]
pub struct Decoder {
    buf: [u8; MAX_ENCODED],
    len: usize,
    /// bytes shifted out of the front of an overlong candidate
    shed: usize,
}

impl Default for Decoder {
    fn default() -> Self {
        Self::new()
    }
}

impl Decoder {
    /// An empty decoder (as after a delimiter).
    pub const fn new() -> Self {
        Self {
            buf: [0; MAX_ENCODED],
            len: 0,
            shed: 0,
        }
    }

    /// Bytes held since the last delimiter.
    pub fn pending(&self) -> usize {
        self.len + self.shed
    }

    /// Forget the bytes since the last delimiter (e.g. after reconnecting).
    pub fn clear(&mut self) {
        self.len = 0;
        self.shed = 0;
    }

    /// Take one byte; at a delimiter, what the bytes before it were.
    pub fn push(&mut self, b: u8) -> Option<Decoded> {
        if b != 0 {
            if self.len == MAX_ENCODED {
                self.buf.copy_within(1.., 0);
                self.len -= 1;
                self.shed += 1;
            }
            self.buf[self.len] = b;
            self.len += 1;
            return None;
        }
        let (len, shed) = (self.len, self.shed);
        self.clear();
        if len == 0 && shed == 0 {
            return None;
        }
        let cand = &self.buf[..len];
        let whole = decode_candidate(cand);
        if shed == 0 && whole.is_ok() {
            return Some(Decoded {
                result: whole,
                garbage: 0,
            });
        }
        let first = usize::from(shed == 0);
        for start in first..len {
            if let Ok(f) = decode_candidate(&cand[start..]) {
                return Some(Decoded {
                    result: Ok(f),
                    garbage: shed + start,
                });
            }
        }
        let result = match (shed, whole) {
            (0, r) => r,
            (s, _) => Err(FrameError::Overlong { bytes: s + len }),
        };
        Some(Decoded { result, garbage: 0 })
    }

    /// Take a slice; calls `f` for every delimiter reached.
    pub fn feed(&mut self, bytes: &[u8], mut f: impl FnMut(Decoded)) {
        for &b in bytes {
            if let Some(d) = self.push(b) {
                f(d);
            }
        }
    }
}

fn decode_candidate(enc: &[u8]) -> Result<Frame, FrameError> {
    let mut body = [0u8; MAX_ENCODED];
    let n = cobs_decode(enc, &mut body).map_err(FrameError::Cobs)?;
    Frame::parse_body(&body[..n])
}

/// A full-scale range the MPU6050 does not have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RangeError {
    /// Accelerometer range, ±g (not 2, 4, 8 or 16).
    Accel(u8),
    /// Gyro range, ±°/s (not 250, 500, 1000 or 2000).
    Gyro(u16),
}

impl core::fmt::Display for RangeError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            RangeError::Accel(g) => write!(f, "accelerometer range ±{g} g (not 2, 4, 8 or 16)"),
            RangeError::Gyro(d) => write!(f, "gyro range ±{d} °/s (not 250, 500, 1000 or 2000)"),
        }
    }
}

/// Sensitivities of one configuration: MPU6050 product specification rev
/// 3.4, tables 6.1 and 6.2 (AFS_SEL 0..3: 16384, 8192, 4096, 2048 LSB/g;
/// FS_SEL 0..3: 131, 65.5, 32.8, 16.4 LSB/(°/s)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scales {
    /// Accelerometer counts per g.
    pub acc_lsb_per_g: f64,
    /// Gyro counts per °/s.
    pub gyr_lsb_per_dps: f64,
}

impl Scales {
    /// The sensitivities of these full-scale ranges.
    pub fn from_ranges(accel_fs_g: u8, gyro_fs_dps: u16) -> Result<Self, RangeError> {
        let acc = match accel_fs_g {
            2 => 16384.0,
            4 => 8192.0,
            8 => 4096.0,
            16 => 2048.0,
            g => return Err(RangeError::Accel(g)),
        };
        let gyr = match gyro_fs_dps {
            250 => 131.0,
            500 => 65.5,
            1000 => 32.8,
            2000 => 16.4,
            d => return Err(RangeError::Gyro(d)),
        };
        Ok(Self {
            acc_lsb_per_g: acc,
            gyr_lsb_per_dps: gyr,
        })
    }

    /// Accelerometer counts → m/s²: `(counts / LSB_per_g) · 9.80665`.
    pub fn acc_m_s2(&self, counts: i16) -> f64 {
        counts as f64 / self.acc_lsb_per_g * G0
    }

    /// Gyro counts → rad/s: `(counts / LSB_per_dps) · (π/180)`, the factor
    /// being the `f64` nearest π/180 (as [`f64::to_radians`]).
    pub fn gyr_rad_s(&self, counts: i16) -> f64 {
        counts as f64 / self.gyr_lsb_per_dps * (core::f64::consts::PI / 180.0)
    }

    /// Counts of a specific force (m/s², rounded to nearest, saturating at
    /// the i16 range): the inverse of [`Scales::acc_m_s2`] up to rounding.
    pub fn acc_counts(&self, m_s2: f64) -> i16 {
        saturate(m_s2 / G0 * self.acc_lsb_per_g)
    }

    /// Counts of an angular rate (rad/s, rounded, saturating).
    pub fn gyr_counts(&self, rad_s: f64) -> i16 {
        saturate(rad_s.to_degrees() * self.gyr_lsb_per_dps)
    }
}

fn saturate(x: f64) -> i16 {
    if x.is_nan() {
        0
    } else {
        // `as` saturates; round half away from zero first
        let r = if x >= 0.0 { x + 0.5 } else { x - 0.5 };
        r as i16
    }
}

/// Temperature counts → °C: raw/340 + 36.53 (MPU6050 register map rev 4.2, §4.18).
pub fn temp_c(raw: i16) -> f64 {
    raw as f64 / 340.0 + 36.53
}

impl Config {
    /// The sensitivities of this configuration's ranges.
    pub fn scales(&self) -> Result<Scales, RangeError> {
        Scales::from_ranges(self.accel_fs_g, self.gyro_fs_dps)
    }
}

impl Sample {
    /// The sample in SI at host time `t_s`: gyro rad/s, specific force m/s²,
    /// temperature °C; the axes are the sensor's.
    pub fn to_si(&self, scales: &Scales, t_s: f64) -> ImuSample {
        let g = |k: usize| scales.gyr_rad_s(self.gyr[k]);
        let a = |k: usize| scales.acc_m_s2(self.acc[k]);
        ImuSample {
            t_s,
            gyr_rad_s: Vec3::new(g(0), g(1), g(2)),
            acc_m_s2: Vec3::new(a(0), a(1), a(2)),
            mag_ut: None,
            temp_c: Some(temp_c(self.temp)),
        }
    }
}

/// Board time went backwards (by this many µs, modulo 2³²).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TimeBackwards {
    /// How far back, µs.
    pub by_us: u32,
}

/// Unwraps the board's 32-bit microsecond clock into a 64-bit one: each
/// step is `t.wrapping_sub(last)`, taken as forward when below 2³¹ µs
/// (35.8 min) — so a wrap (every 71.6 min) adds 2³² µs — and as time going
/// backwards otherwise.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TimeUnwrap {
    last: Option<u32>,
    total_us: u64,
}

impl TimeUnwrap {
    /// A clock that has seen nothing.
    pub const fn new() -> Self {
        Self {
            last: None,
            total_us: 0,
        }
    }

    /// Take the next board time; the unwrapped time in µs (the first value
    /// is taken as is).
    pub fn update(&mut self, t_us: u32) -> Result<u64, TimeBackwards> {
        let Some(last) = self.last else {
            self.last = Some(t_us);
            self.total_us = t_us as u64;
            return Ok(self.total_us);
        };
        let d = t_us.wrapping_sub(last);
        if d >= 1 << 31 {
            return Err(TimeBackwards {
                by_us: last.wrapping_sub(t_us),
            });
        }
        self.last = Some(t_us);
        self.total_us += d as u64;
        Ok(self.total_us)
    }

    /// Forget the past (after a board reset).
    pub fn reset(&mut self) {
        *self = Self::new();
    }
}

/// Something a [`Link`] noticed about the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Notice {
    /// A CONFIG arrived (the first, or a changed or repeated one).
    Config(Config),
    /// A CONFIG whose ranges cannot be converted: samples are dropped until a good one.
    BadConfig(RangeError),
    /// A CONFIG of another protocol version (its samples are still decoded).
    Version(u8),
    /// The sequence restarted: a board reset (board time went back) or a
    /// STOP/START (time went on). Host time continues one sample period later.
    Reset {
        /// True when the board's clock restarted too.
        clock_restarted: bool,
    },
    /// Samples missing before this one.
    Gap {
        /// How many.
        missing: u16,
    },
    /// A sample whose sequence number was seen last (or is older): dropped.
    Repeated {
        /// Its sequence number.
        seq: u16,
    },
    /// A sample before any usable CONFIG: dropped (ask the board for one).
    NoConfig,
    /// The board answered a command.
    Ack(Ack),
    /// A host → board frame arrived from the board (an echo, or a loop-back).
    Unexpected(u8),
}

/// What a [`Link`] made of one frame: at most one notice and one sample.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct LinkOutput {
    /// Something to report.
    pub notice: Option<Notice>,
    /// A sample in SI at host time, with its sequence number.
    pub sample: Option<(u16, ImuSample)>,
}

/// One board's stream, frame by frame: the current CONFIG and its scales,
/// the unwrapped clock, the sequence counter.
///
/// Host time is `t_s = t_us · 1e-6` with `t_us` the unwrapped board time
/// (plus an offset after a reset, so host time keeps increasing: the first
/// sample after a reset comes one nominal period, 1/rate, after the last one
/// before it). A reset is a sequence that restarts after a CONFIG (seq 0 or
/// going back), or board time going back (modulo 2³²); after a restart the
/// board's clock is taken as restarted when it reads less than before (a
/// STOP/START keeps the clock running).
#[derive(Clone, Debug, Default)]
pub struct Link {
    config: Option<Config>,
    scales: Option<Scales>,
    clock: TimeUnwrap,
    epoch_us: i64,
    last_host_us: Option<u64>,
    last: Option<(u16, u32)>,
    config_since_sample: bool,
}

impl Link {
    /// A link that has seen nothing.
    pub fn new() -> Self {
        Self::default()
    }

    /// The last CONFIG.
    pub fn config(&self) -> Option<&Config> {
        self.config.as_ref()
    }

    fn period_us(&self) -> u64 {
        match self.config {
            Some(c) if c.rate_hz > 0 => 1_000_000u64.div_ceil(c.rate_hz as u64),
            _ => 10_000,
        }
    }

    /// Take one decoded frame.
    pub fn push(&mut self, frame: &Frame) -> LinkOutput {
        let notice = |n| LinkOutput {
            notice: Some(n),
            sample: None,
        };
        match frame {
            Frame::Config(c) => {
                self.config = Some(*c);
                self.config_since_sample = true;
                match c.scales() {
                    Ok(s) => {
                        self.scales = Some(s);
                        if c.proto_version != PROTO_VERSION {
                            notice(Notice::Version(c.proto_version))
                        } else {
                            notice(Notice::Config(*c))
                        }
                    }
                    Err(e) => {
                        self.scales = None;
                        notice(Notice::BadConfig(e))
                    }
                }
            }
            Frame::Ack(a) => notice(Notice::Ack(*a)),
            Frame::Sample(s) => self.sample(s),
            other => notice(Notice::Unexpected(other.ty())),
        }
    }

    fn sample(&mut self, s: &Sample) -> LinkOutput {
        let Some(scales) = self.scales else {
            return LinkOutput {
                notice: Some(Notice::NoConfig),
                sample: None,
            };
        };
        let mut notice = None;
        if let Some((seq, t)) = self.last {
            let back = s.seq.wrapping_sub(seq) >= 0x8000;
            if s.seq == seq || (back && !self.config_since_sample && s.t_us == t) {
                return LinkOutput {
                    notice: Some(Notice::Repeated { seq: s.seq }),
                    sample: None,
                };
            }
            let restart = self.config_since_sample && (s.seq == 0 || back);
            // a board clock that restarted reads less than before; modulo 2³² that
            // can look forward (a board up for over 35.8 min), so after a restart
            // the plain comparison decides
            let clock_back = s.t_us.wrapping_sub(t) >= 1 << 31 || (restart && s.t_us < t);
            if restart || clock_back {
                notice = Some(Notice::Reset {
                    clock_restarted: clock_back,
                });
                if clock_back {
                    self.clock.reset();
                    let u = self.clock.update(s.t_us).unwrap_or(0);
                    let next = self.last_host_us.unwrap_or(0) + self.period_us();
                    self.epoch_us = next as i64 - u as i64;
                }
            } else if back {
                return LinkOutput {
                    notice: Some(Notice::Repeated { seq: s.seq }),
                    sample: None,
                };
            } else {
                let missing = s.seq.wrapping_sub(seq).wrapping_sub(1);
                if missing > 0 {
                    notice = Some(Notice::Gap { missing });
                }
            }
        }
        // forward time (the clock-back case has been re-based above)
        // (never an error: a step back is a reset, re-based above)
        let u = self.clock.update(s.t_us).unwrap_or(0);
        let host = (self.epoch_us + u as i64).max(0) as u64;
        self.last_host_us = Some(host);
        self.last = Some((s.seq, s.t_us));
        self.config_since_sample = false;
        LinkOutput {
            notice,
            sample: Some((s.seq, s.to_si(&scales, host as f64 * 1e-6))),
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use proptest::prelude::*;
    use std::vec::Vec;

    fn enc(src: &[u8]) -> Vec<u8> {
        let mut out = [0u8; 600];
        let n = cobs_encode(src, &mut out).unwrap();
        out[..n].to_vec()
    }

    #[test]
    fn crc_check_value() {
        assert_eq!(crc16(b"123456789"), 0x29B1);
        assert_eq!(crc16(b""), 0xFFFF);
        // bytewise continuation equals one pass
        assert_eq!(crc16_update(crc16(b"1234"), b"56789"), 0x29B1);
    }

    #[test]
    fn cobs_known_vectors() {
        // Cheshire & Baker 1999; the usual examples (delimiter not included)
        let cases: [(&[u8], &[u8]); 7] = [
            (&[], &[0x01]),
            (&[0x00], &[0x01, 0x01]),
            (&[0x00, 0x00], &[0x01, 0x01, 0x01]),
            (&[0x00, 0x11, 0x00], &[0x01, 0x02, 0x11, 0x01]),
            (&[0x11, 0x22, 0x00, 0x33], &[0x03, 0x11, 0x22, 0x02, 0x33]),
            (&[0x11, 0x22, 0x33, 0x44], &[0x05, 0x11, 0x22, 0x33, 0x44]),
            (&[0x11, 0x00, 0x00, 0x00], &[0x02, 0x11, 0x01, 0x01, 0x01]),
        ];
        for (raw, coded) in cases {
            assert_eq!(enc(raw), coded, "{raw:02X?}");
            let mut d = [0u8; 16];
            let n = cobs_decode(coded, &mut d).unwrap();
            assert_eq!(&d[..n], raw);
        }
        // 01..FE (254 bytes) → FF 01..FE
        let a: Vec<u8> = (1..=0xFEu8).collect();
        let mut want = vec_of(&[0xFF]);
        want.extend_from_slice(&a);
        assert_eq!(enc(&a), want);
        // 00 01..FE → 01 FF 01..FE
        let mut b = vec_of(&[0x00]);
        b.extend_from_slice(&a);
        let mut want = vec_of(&[0x01, 0xFF]);
        want.extend_from_slice(&a);
        assert_eq!(enc(&b), want);
        // 01..FF (255 bytes) → FF 01..FE 02 FF
        let c: Vec<u8> = (1..=0xFFu8).collect();
        let mut want = vec_of(&[0xFF]);
        want.extend_from_slice(&a);
        want.extend_from_slice(&[0x02, 0xFF]);
        assert_eq!(enc(&c), want);
        // 02..FF 00 → FF 02..FF 01 01
        let mut d: Vec<u8> = (2..=0xFFu8).collect();
        d.push(0);
        let mut want = vec_of(&[0xFF]);
        want.extend(2..=0xFFu8);
        want.extend_from_slice(&[0x01, 0x01]);
        assert_eq!(enc(&d), want);
        // 03..FF 00 01 → FE 03..FF 02 01
        let mut e: Vec<u8> = (3..=0xFFu8).collect();
        e.extend_from_slice(&[0, 1]);
        let mut want = vec_of(&[0xFE]);
        want.extend(3..=0xFFu8);
        want.extend_from_slice(&[0x02, 0x01]);
        assert_eq!(enc(&e), want);
        for v in [a, b, c, d, e] {
            let coded = enc(&v);
            let mut out = [0u8; 600];
            let n = cobs_decode(&coded, &mut out).unwrap();
            assert_eq!(&out[..n], &v[..]);
        }
    }

    fn vec_of(b: &[u8]) -> Vec<u8> {
        b.to_vec()
    }

    #[test]
    fn cobs_rejects_bad_input() {
        let mut d = [0u8; 8];
        assert_eq!(
            cobs_decode(&[0x03, 0x11], &mut d),
            Err(CobsError::Truncated)
        );
        assert_eq!(cobs_decode(&[0x02, 0x00], &mut d), Err(CobsError::ZeroByte));
        assert_eq!(
            cobs_decode(&[0x05, 1, 2, 3, 4], &mut [0u8; 3]),
            Err(CobsError::Overflow)
        );
        assert!(cobs_encode(&[1, 2, 3], &mut [0u8; 3]).is_err());
    }

    fn sample(seq: u16, t_us: u32) -> Frame {
        Frame::Sample(Sample {
            seq,
            t_us,
            acc: [100, -200, 4096],
            temp: -1234,
            gyr: [-32768, 0, 32767],
        })
    }

    fn config() -> Config {
        Config {
            proto_version: 1,
            firmware: [0, 1, 0],
            board: 3,
            rate_hz: 100,
            accel_fs_g: 8,
            gyro_fs_dps: 1000,
            dlpf_cfg: 3,
            streaming: 1,
        }
    }

    fn wire(f: &Frame) -> Vec<u8> {
        let mut out = [0u8; MAX_FRAME];
        let n = encode(f, &mut out).unwrap();
        out[..n].to_vec()
    }

    fn decode_all(bytes: &[u8]) -> Vec<Decoded> {
        let mut d = Decoder::new();
        let mut v = Vec::new();
        d.feed(bytes, |x| v.push(x));
        v
    }

    #[test]
    fn every_frame_round_trips_and_has_its_length() {
        let frames = [
            Frame::Config(config()),
            sample(7, 0xDEAD_BEEF),
            Frame::Ack(Ack {
                command: ty::SET_RATE,
                status: ack::OUT_OF_RANGE,
            }),
            Frame::RequestConfig,
            Frame::SetRate { rate_hz: 1000 },
            Frame::SetRanges {
                accel_fs_g: 16,
                gyro_fs_dps: 2000,
                dlpf_cfg: 6,
            },
            Frame::Start,
            Frame::Stop,
            Frame::SetDials {
                roll_cdeg: -9000,
                pitch_cdeg: 9000,
            },
        ];
        for f in frames {
            let w = wire(&f);
            let body = 1 + payload_len(f.ty()).unwrap() + 2;
            assert_eq!(w.len(), body + 2, "{f:?}");
            assert_eq!(w.iter().filter(|&&b| b == 0).count(), 1);
            let got = decode_all(&w);
            assert_eq!(got.len(), 1);
            assert_eq!(got[0].result, Ok(f));
        }
        // a SAMPLE is 25 bytes on the wire (the spec's figure)
        assert_eq!(wire(&sample(0, 0)).len(), 25);
    }

    #[test]
    fn sample_payload_layout_is_little_endian_in_register_order() {
        let mut body = [0u8; MAX_BODY];
        let n = sample(0x0102, 0x0304_0506).write_body(&mut body);
        assert_eq!(n, 23);
        assert_eq!(&body[..7], &[0x02, 0x02, 0x01, 0x06, 0x05, 0x04, 0x03]);
        // ax = 100 = 0x0064, temp = -1234 = 0xFB2E, gx = -32768 = 0x8000
        assert_eq!(&body[7..9], &[0x64, 0x00]);
        assert_eq!(&body[13..15], &[0x2E, 0xFB]);
        assert_eq!(&body[15..17], &[0x00, 0x80]);
        let crc = crc16(&body[..21]);
        assert_eq!(&body[21..23], &crc.to_le_bytes());
    }

    #[test]
    fn typed_errors() {
        let mut body = [0u8; MAX_BODY];
        let n = sample(1, 2).write_body(&mut body);
        // CRC
        let mut b = body;
        b[5] ^= 0x10;
        assert!(matches!(
            Frame::parse_body(&b[..n]),
            Err(FrameError::BadCrc { .. })
        ));
        // unknown type and wrong length, with valid CRCs
        let with_crc = |data: &[u8]| {
            let mut v = data.to_vec();
            v.extend_from_slice(&crc16(data).to_le_bytes());
            v
        };
        assert_eq!(
            Frame::parse_body(&with_crc(&[0x7F, 1, 2])),
            Err(FrameError::UnknownType(0x7F))
        );
        assert_eq!(
            Frame::parse_body(&with_crc(&[ty::SAMPLE, 1, 2])),
            Err(FrameError::BadLength {
                ty: ty::SAMPLE,
                len: 2
            })
        );
        assert_eq!(
            Frame::parse_body(&[1, 2]),
            Err(FrameError::TooShort { len: 2 })
        );
        // overlong: 100 non-zero bytes then a delimiter
        let mut g = [0x55u8; 101];
        g[100] = 0;
        let d = decode_all(&g);
        assert_eq!(d.len(), 1);
        assert_eq!(d[0].result, Err(FrameError::Overlong { bytes: 100 }));
    }

    #[test]
    fn resynchronises_after_flipped_bytes_and_recovers_after_garbage() {
        let frames: Vec<Frame> = (0..10).map(|k| sample(k, k as u32 * 10_000)).collect();
        let mut stream = Vec::new();
        for (k, f) in frames.iter().enumerate() {
            let mut w = wire(f);
            if k == 3 {
                // one bit in a payload byte (not into 0x00, which would split the frame)
                w[6] ^= if w[6] == 0x80 { 0x01 } else { 0x80 };
            }
            if k == 6 {
                // garbage without a zero, right before frame 6
                stream.extend_from_slice(&[0x11, 0x22, 0x33, 0xFF, 0x05]);
            }
            stream.extend_from_slice(&w);
        }
        let d = decode_all(&stream);
        assert_eq!(d.len(), 10);
        for (k, x) in d.iter().enumerate() {
            if k == 3 {
                assert!(x.result.is_err(), "{x:?}");
            } else {
                assert_eq!(x.result, Ok(frames[k]), "frame {k}");
            }
        }
        assert_eq!(d[6].garbage, 5);
        // a frame at the tail of a long run of garbage
        let mut long = vec_of(&[0x42; 300]);
        long.extend_from_slice(&wire(&frames[9]));
        let d = decode_all(&long);
        assert_eq!(d.len(), 1);
        assert_eq!((d[0].result, d[0].garbage), (Ok(frames[9]), 300));
        // repeated delimiters are ignored
        assert!(decode_all(&[0, 0, 0]).is_empty());
    }

    #[test]
    fn conversions_follow_the_datasheet() {
        let s = Scales::from_ranges(8, 1000).unwrap();
        assert_eq!(s.acc_m_s2(4096), G0);
        assert_eq!(s.acc_m_s2(-8192), -2.0 * G0);
        assert!((s.gyr_rad_s(328) - 10f64.to_radians()).abs() < 1e-15);
        assert_eq!(temp_c(0), 36.53);
        assert!((temp_c(-3751) - (36.53 - 3751.0 / 340.0)).abs() < 1e-12);
        assert_eq!(s.acc_counts(G0), 4096);
        assert_eq!(s.acc_counts(1e9), i16::MAX);
        assert_eq!(s.gyr_counts(-1e9), i16::MIN);
        assert_eq!(Scales::from_ranges(3, 1000), Err(RangeError::Accel(3)));
        assert_eq!(Scales::from_ranges(2, 300), Err(RangeError::Gyro(300)));
        for (g, lsb) in [(2, 16384.0), (4, 8192.0), (16, 2048.0)] {
            assert_eq!(Scales::from_ranges(g, 250).unwrap().acc_lsb_per_g, lsb);
        }
    }

    #[test]
    fn time_unwraps_across_the_32_bit_wrap() {
        let mut c = TimeUnwrap::new();
        assert_eq!(c.update(u32::MAX - 4_999), Ok(u32::MAX as u64 - 4_999));
        assert_eq!(c.update(5_000), Ok(u32::MAX as u64 + 5_001));
        assert_eq!(c.update(4_000), Err(TimeBackwards { by_us: 1_000 }));
        assert_eq!(c.update(15_000), Ok(u32::MAX as u64 + 15_001));
    }

    fn link_run(frames: &[Frame]) -> (Vec<Notice>, Vec<(u16, f64)>) {
        let mut l = Link::new();
        let (mut n, mut s) = (Vec::new(), Vec::new());
        for f in frames {
            let o = l.push(f);
            n.extend(o.notice);
            s.extend(o.sample.map(|(q, x)| (q, x.t_s)));
        }
        (n, s)
    }

    #[test]
    fn link_notices_gaps_repeats_and_resets() {
        let c = Frame::Config(config());
        let fr = [
            sample(0, 0), // before any CONFIG
            c,
            sample(65534, 1_000_000),
            sample(65535, 1_010_000),
            sample(0, 1_020_000), // seq wraps: no notice
            sample(0, 1_020_000), // repeated
            sample(3, 1_050_000), // 2 missing
            c,
            sample(0, 500), // board reset: clock back
            sample(1, 10_500),
            c,
            sample(0, 30_500), // STOP/START: seq restarts, clock goes on
        ];
        let (n, s) = link_run(&fr);
        assert_eq!(
            n,
            [
                Notice::NoConfig,
                Notice::Config(config()),
                Notice::Repeated { seq: 0 },
                Notice::Gap { missing: 2 },
                Notice::Config(config()),
                Notice::Reset {
                    clock_restarted: true
                },
                Notice::Config(config()),
                Notice::Reset {
                    clock_restarted: false
                },
            ]
        );
        let t: Vec<f64> = s.iter().map(|x| x.1).collect();
        // host time: 1.05 s, then one period (10 ms) later, then on the board's clock
        let want = [1.0, 1.01, 1.02, 1.05, 1.06, 1.07, 1.09];
        assert_eq!(t.len(), want.len());
        for (a, b) in t.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{t:?}");
        }
        // a board up for 60 min resets: modulo 2³² its new clock looks ahead
        let late = 3_600_000_000u32;
        let (n, s) = link_run(&[c, sample(7, late), c, sample(0, 1_000)]);
        assert_eq!(
            n[2],
            Notice::Reset {
                clock_restarted: true
            }
        );
        assert!((s[1].1 - s[0].1 - 0.01).abs() < 1e-9);
        // a gap together with a CONFIG is a gap, not a reset
        let (n, _) = link_run(&[c, sample(10, 0), c, sample(12, 20_000)]);
        assert_eq!(n[2], Notice::Gap { missing: 1 });
    }

    proptest! {
        #[test]
        fn cobs_round_trips(body in proptest::collection::vec(any::<u8>(), 0..=64)) {
            let coded = enc(&body);
            prop_assert!(coded.len() <= body.len() + 1);
            prop_assert!(!coded.contains(&0));
            let mut out = [0u8; 64];
            let n = cobs_decode(&coded, &mut out).unwrap();
            prop_assert_eq!(&out[..n], &body[..]);
        }

        #[test]
        fn garbage_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..2000)) {
            let mut d = Decoder::new();
            let mut l = Link::new();
            d.feed(&bytes, |x| {
                if let Ok(f) = x.result {
                    let _ = l.push(&f);
                }
            });
            prop_assert!(d.pending() <= bytes.len());
            let _ = Frame::parse_body(&bytes[..bytes.len().min(80)]);
        }

        #[test]
        fn frames_survive_in_any_garbage(
            pre in proptest::collection::vec(any::<u8>(), 0..100),
            seq in any::<u16>(), t in any::<u32>(),
        ) {
            // garbage, a delimiter, then a frame: the frame is always decoded
            let mut s = pre.clone();
            s.push(0);
            let f = sample(seq, t);
            s.extend_from_slice(&wire(&f));
            let d = decode_all(&s);
            prop_assert_eq!(d.last().map(|x| x.result), Some(Ok(f)));
        }
    }
}
