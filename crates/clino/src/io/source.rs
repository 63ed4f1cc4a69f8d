//! Sample sources behind one interface: a file, a replay of a file at a
//! chosen speed, a serial port speaking clino's protocol
//! ([`clino_core::protocol`]), an MPU6050 on an I²C bus ([`I2cSource`]).
//!
//! The shape is that of an embedded-hal driver: one trait ([`SampleSource`]),
//! and whatever the transport fails with (a file's parse error, a serial
//! port's I/O error, an I²C bus NACK) comes back as the one [`crate::Error`]
//! (kind [`ErrorKind::Io`] for the bus, with the device's name in
//! `file`). What a source notices without failing — a CONFIG, a sequence gap,
//! a bad frame, the port gone, a late read — is a [`SourceNotice`], reported
//! in order with the samples.
//!
//! The I²C source (MPU6050 on `/dev/i2c-N`, or any embedded-hal 1.0 bus)
//! implements [`SampleSource::poll`] by waiting for its next sample time on
//! a fixed-rate schedule, reading the 14 data registers through the
//! driver ([`clino_mpu6050`]), converting with
//! [`clino_core::protocol::Scales`] and emitting one [`SourceEvent::Sample`];
//! a bus error (after a few retries) is an `Err` of kind `Io`; [`I2cSource`]
//! gives the rules.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use clino_core::ImuSample;
use clino_core::protocol::{self, Decoder, Frame, FrameError, Link, MAX_FRAME, Notice};

use super::{ImuCsvReader, ReadOptions};
use crate::{Error, ErrorKind, Result};

mod i2c;
pub use i2c::{HostClock, I2cOptions, I2cSource, StdClock, parse_address};

/// Something a source reports besides samples.
#[derive(Clone, Debug, PartialEq)]
pub enum SourceNotice {
    /// What the protocol link noticed: CONFIG, reset, gap, repeated frame…
    Link(Notice),
    /// The bytes up to a delimiter were not a frame.
    BadFrame(FrameError),
    /// Bytes discarded before a good frame.
    Garbage {
        /// How many.
        bytes: usize,
    },
    /// The device is open.
    Connected {
        /// Its name.
        device: String,
    },
    /// The device went away (unplugged, closed); the source retries.
    Disconnected {
        /// What the read said.
        reason: String,
    },
    /// No valid frame for a while.
    Silent {
        /// For how long, s.
        seconds: f64,
        /// Bytes that arrived in that time (many bytes and no frame: wrong baud rate).
        bytes: u64,
    },
    /// A sensor read on the host's clock woke more than a sample period
    /// late: the sample times that passed are skipped, not read in a burst.
    Late {
        /// Sample times skipped.
        missed: u64,
    },
    /// A bus transfer failed and is tried again.
    BusRetry {
        /// What the bus said.
        error: String,
        /// This retry, 1-based.
        attempt: u32,
        /// Retries allowed before the stream fails.
        of: u32,
    },
}

impl SourceNotice {
    /// True for what counts as a fault of the link (in the summary).
    pub fn is_fault(&self) -> bool {
        !matches!(
            self,
            SourceNotice::Connected { .. }
                | SourceNotice::Link(Notice::Config(_))
                | SourceNotice::Link(Notice::Ack(protocol::Ack { status: 0, .. }))
        )
    }
}

/// One event of a source.
#[derive(Clone, Debug, PartialEq)]
pub enum SourceEvent {
    /// A sample in SI units, host time.
    Sample(ImuSample),
    /// Something to report.
    Notice(SourceNotice),
}

/// A source of IMU samples (file, replay, serial port, I²C sensor).
pub trait SampleSource {
    /// Emit what is available, blocking at most about 50 ms (so that the
    /// caller can check for Ctrl-C and send commands between calls); `false`
    /// at the end of the stream. Errors of the transport are `Err`.
    fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool>;

    /// The device or file, for messages.
    fn name(&self) -> &str;

    /// True when samples arrive on their own clock (a sensor): a slow
    /// consumer then loses samples. A file or a replay waits for it instead.
    fn is_live(&self) -> bool {
        true
    }

    /// Send a command to the device (the dial angles, a rate). Sources that
    /// take none refuse.
    fn send(&mut self, frame: &Frame) -> Result<()> {
        let _ = frame;
        Err(Error::new(
            ErrorKind::InvalidInput,
            format!("{} takes no commands", self.name()),
        ))
    }
}

/// Every sample of a recording (CSV or Parquet, read by [`ImuCsvReader`]),
/// as fast as the consumer takes them.
pub struct FileSource {
    reader: ImuCsvReader<std::fs::File>,
    name: String,
    peeked: Option<ImuSample>,
}

impl FileSource {
    /// Open a recording (Parquet by the `.parquet` extension).
    pub fn open(path: &Path, opts: &ReadOptions) -> Result<Self> {
        let reader = ImuCsvReader::from_path(path, opts)?;
        Ok(Self {
            reader,
            name: path.display().to_string(),
            peeked: None,
        })
    }

    fn peek(&mut self) -> Result<Option<ImuSample>> {
        if self.peeked.is_none() {
            self.peeked = self.reader.next_row()?.map(|r| r.sample);
        }
        Ok(self.peeked)
    }

    /// The path.
    pub fn path(&self) -> PathBuf {
        self.reader.file().to_path_buf()
    }
}

impl SampleSource for FileSource {
    fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
        for _ in 0..256 {
            match self.peek()? {
                Some(s) => {
                    self.peeked = None;
                    emit(SourceEvent::Sample(s));
                }
                None => return Ok(false),
            }
        }
        Ok(true)
    }
    fn name(&self) -> &str {
        &self.name
    }
    fn is_live(&self) -> bool {
        false
    }
}

/// A recording played back on its own clock: sample k is emitted at
/// `start + (t_k − t_0) / speed` (wall clock), so `speed = 1` is real time
/// and `speed = inf` is as fast as possible.
pub struct ReplaySource {
    file: FileSource,
    speed: f64,
    origin: Option<(Instant, f64)>,
}

impl ReplaySource {
    /// Replay `file` at `speed` × real time (> 0; `inf` for no waiting).
    pub fn new(file: FileSource, speed: f64) -> Result<Self> {
        if speed.is_nan() || speed <= 0.0 {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("replay speed must be a positive number, got {speed}"),
            ));
        }
        Ok(Self {
            file,
            speed,
            origin: None,
        })
    }
}

impl SampleSource for ReplaySource {
    fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
        let slice = Duration::from_millis(50);
        let until = Instant::now() + slice;
        loop {
            let Some(s) = self.file.peek()? else {
                return Ok(false);
            };
            let (t0_wall, t0) = *self.origin.get_or_insert((Instant::now(), s.t_s));
            let due_s = (s.t_s - t0) / self.speed;
            let due = if due_s.is_finite() && due_s > 0.0 {
                t0_wall + Duration::from_secs_f64(due_s.min(1e9))
            } else {
                t0_wall
            };
            let now = Instant::now();
            if due > now {
                if due > until {
                    std::thread::sleep(until.saturating_duration_since(now));
                    return Ok(true);
                }
                std::thread::sleep(due - now);
            }
            self.file.peeked = None;
            emit(SourceEvent::Sample(s));
            if Instant::now() >= until {
                return Ok(true);
            }
        }
    }
    fn name(&self) -> &str {
        self.file.name()
    }
    fn is_live(&self) -> bool {
        false
    }
}

/// Options of a [`SerialSource`].
#[derive(Clone, Debug)]
pub struct SerialOptions {
    /// Baud rate (the UNO firmware's default is 115 200, 8N1).
    pub baud: u32,
    /// No valid frame for this long is reported ([`SourceNotice::Silent`]).
    pub silence: Duration,
    /// Longest wait between reconnection attempts.
    pub max_backoff: Duration,
}

impl Default for SerialOptions {
    fn default() -> Self {
        Self {
            baud: 115_200,
            silence: Duration::from_secs(3),
            max_backoff: Duration::from_secs(2),
        }
    }
}

/// A board on a serial port speaking clino's protocol: frames are decoded
/// ([`Decoder`]), followed ([`Link`]) and converted to SI; every fault is a
/// notice; a port that disappears is reopened with exponential back-off
/// (100 ms doubling to [`SerialOptions::max_backoff`]).
///
/// On connecting it asks for the CONFIG, and sends START when the board
/// says it is stopped. Until a CONFIG arrives samples cannot be converted:
/// they are dropped ([`Notice::NoConfig`]) and the CONFIG is asked for again
/// (at most once a second).
pub struct SerialSource {
    path: String,
    opts: SerialOptions,
    port: Option<Box<dyn serialport::SerialPort>>,
    decoder: Decoder,
    link: Link,
    buf: Vec<u8>,
    backoff: Duration,
    retry_at: Instant,
    last_valid: Instant,
    bytes_since_valid: u64,
    silent_reported: bool,
    config_asked: Option<Instant>,
}

fn open_port(
    path: &str,
    baud: u32,
) -> std::result::Result<Box<dyn serialport::SerialPort>, String> {
    serialport::new(path, baud)
        .timeout(Duration::from_millis(50))
        .open()
        .map_err(|e| e.to_string())
}

impl SerialSource {
    /// Open the port (an error now, naming the device, if it cannot be opened:
    /// a wrong name is not worth retrying; once connected, losing the port is).
    pub fn open(path: &str, opts: SerialOptions) -> Result<Self> {
        let port = open_port(path, opts.baud).map_err(|e| {
            Error::new(ErrorKind::Io, format!("cannot open serial port: {e}")).in_file(path)
        })?;
        let now = Instant::now();
        Ok(Self {
            path: path.to_string(),
            opts,
            port: Some(port),
            decoder: Decoder::new(),
            link: Link::new(),
            buf: vec![0; 4096],
            backoff: Duration::from_millis(100),
            retry_at: now,
            last_valid: now,
            bytes_since_valid: 0,
            silent_reported: false,
            config_asked: None,
        })
    }

    fn write_frame(&mut self, frame: &Frame) -> Result<()> {
        let mut wire = [0u8; MAX_FRAME];
        let n = protocol::encode(frame, &mut wire).unwrap_or(0);
        let Some(port) = self.port.as_mut() else {
            return Ok(()); // not connected: the command is lost, as on a cut wire
        };
        port.write_all(&wire[..n])
            .map_err(|e| Error::new(ErrorKind::Io, e.to_string()).in_file(&self.path))
    }

    fn connected(&mut self, emit: &mut dyn FnMut(SourceEvent)) {
        self.decoder.clear();
        self.backoff = Duration::from_millis(100);
        self.last_valid = Instant::now();
        self.bytes_since_valid = 0;
        emit(SourceEvent::Notice(SourceNotice::Connected {
            device: self.path.clone(),
        }));
        self.config_asked = Some(Instant::now());
        let _ = self.write_frame(&Frame::RequestConfig);
    }

    fn lost(&mut self, reason: String, emit: &mut dyn FnMut(SourceEvent)) {
        self.port = None;
        self.retry_at = Instant::now() + self.backoff;
        emit(SourceEvent::Notice(SourceNotice::Disconnected { reason }));
    }

    fn handle(&mut self, d: protocol::Decoded, emit: &mut dyn FnMut(SourceEvent)) {
        let frame = match d.result {
            Ok(f) => f,
            Err(e) => {
                emit(SourceEvent::Notice(SourceNotice::BadFrame(e)));
                return;
            }
        };
        if d.garbage > 0 {
            emit(SourceEvent::Notice(SourceNotice::Garbage {
                bytes: d.garbage,
            }));
        }
        self.last_valid = Instant::now();
        self.bytes_since_valid = 0;
        self.silent_reported = false;
        let out = self.link.push(&frame);
        match out.notice {
            Some(Notice::Config(c)) if c.streaming == 0 => {
                let _ = self.write_frame(&Frame::Start);
            }
            Some(Notice::NoConfig)
                if self
                    .config_asked
                    .is_none_or(|t| t.elapsed() > Duration::from_secs(1)) =>
            {
                self.config_asked = Some(Instant::now());
                let _ = self.write_frame(&Frame::RequestConfig);
            }
            _ => {}
        }
        if let Some(n) = out.notice {
            emit(SourceEvent::Notice(SourceNotice::Link(n)));
        }
        if let Some((_, s)) = out.sample {
            emit(SourceEvent::Sample(s));
        }
    }

    fn check_silence(&mut self, emit: &mut dyn FnMut(SourceEvent)) {
        let quiet = self.last_valid.elapsed();
        if quiet >= self.opts.silence && !self.silent_reported {
            self.silent_reported = true;
            emit(SourceEvent::Notice(SourceNotice::Silent {
                seconds: quiet.as_secs_f64(),
                bytes: self.bytes_since_valid,
            }));
        }
    }
}

impl SampleSource for SerialSource {
    fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
        if self.port.is_none() {
            let now = Instant::now();
            if now < self.retry_at {
                std::thread::sleep((self.retry_at - now).min(Duration::from_millis(50)));
                return Ok(true);
            }
            match open_port(&self.path, self.opts.baud) {
                Ok(p) => {
                    self.port = Some(p);
                    self.connected(emit);
                }
                Err(_) => {
                    self.backoff = (self.backoff * 2).min(self.opts.max_backoff);
                    self.retry_at = Instant::now() + self.backoff;
                    return Ok(true);
                }
            }
        } else if self.config_asked.is_none() {
            self.connected(emit);
        }
        let Some(port) = self.port.as_mut() else {
            return Ok(true);
        };
        let n = match port.read(&mut self.buf) {
            Ok(0) => {
                self.lost("end of file on the port".into(), emit);
                return Ok(true);
            }
            Ok(n) => n,
            Err(e) if e.kind() == std::io::ErrorKind::TimedOut => 0,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => 0,
            Err(e) => {
                self.lost(e.to_string(), emit);
                return Ok(true);
            }
        };
        self.bytes_since_valid += n as u64;
        let bytes = std::mem::take(&mut self.buf);
        for &b in &bytes[..n] {
            if let Some(d) = self.decoder.push(b) {
                self.handle(d, emit);
            }
        }
        self.buf = bytes;
        self.check_silence(emit);
        Ok(true)
    }

    fn name(&self) -> &str {
        &self.path
    }

    fn send(&mut self, frame: &Frame) -> Result<()> {
        self.write_frame(frame)
    }
}

impl std::fmt::Display for SourceNotice {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SourceNotice::BadFrame(e) => write!(f, "bad frame ({}): {e}", e.kind_name()),
            SourceNotice::Garbage { bytes } => {
                write!(f, "{bytes} garbage bytes discarded before a frame")
            }
            SourceNotice::Connected { device } => write!(f, "connected to {device}"),
            SourceNotice::Disconnected { reason } => {
                write!(
                    f,
                    "the port went away ({reason}): reconnecting with back-off"
                )
            }
            SourceNotice::Silent { seconds, bytes } => f.write_str(&silence_hint(*seconds, *bytes)),
            SourceNotice::Late { missed } => write!(
                f,
                "read late: {missed} sample time{} skipped (the host was busy or the bus slow)",
                if *missed == 1 { "" } else { "s" }
            ),
            SourceNotice::BusRetry { error, attempt, of } => {
                write!(f, "{error}: trying again ({attempt} of {of})")
            }
            SourceNotice::Link(n) => match n {
                Notice::Config(c) => write!(
                    f,
                    "CONFIG: protocol {}, firmware {}.{}.{}, board {}, {} Hz, ±{} g, ±{} °/s, DLPF {}, {}",
                    c.proto_version,
                    c.firmware[0],
                    c.firmware[1],
                    c.firmware[2],
                    match c.board {
                        1 => "Arduino UNO",
                        2 => "Cortex-M4F",
                        3 => "host simulator",
                        _ => "unknown",
                    },
                    c.rate_hz,
                    c.accel_fs_g,
                    c.gyro_fs_dps,
                    c.dlpf_cfg,
                    if c.streaming != 0 {
                        "streaming"
                    } else {
                        "stopped"
                    }
                ),
                Notice::BadConfig(e) => {
                    write!(
                        f,
                        "unusable CONFIG: {e}; samples are dropped until a good one"
                    )
                }
                Notice::Version(v) => write!(
                    f,
                    "CONFIG of protocol version {v} (this host speaks {}): samples decoded as version {}",
                    protocol::PROTO_VERSION,
                    protocol::PROTO_VERSION
                ),
                Notice::Reset {
                    clock_restarted: true,
                } => {
                    write!(
                        f,
                        "board reset: sequence and clock restarted (host time continues)"
                    )
                }
                Notice::Reset {
                    clock_restarted: false,
                } => {
                    write!(f, "sequence restarted (STOP/START): board clock continues")
                }
                Notice::Gap { missing } => write!(f, "sequence gap: {missing} samples missing"),
                Notice::Repeated { seq } => write!(f, "repeated frame (seq {seq}) dropped"),
                Notice::NoConfig => write!(f, "sample before any CONFIG dropped (asked for one)"),
                Notice::Ack(a) => write!(
                    f,
                    "the board answered command 0x{:02X} with status {} ({})",
                    a.command,
                    a.status,
                    match a.status {
                        0 => "ok",
                        1 => "value out of range",
                        2 => "unknown command",
                        3 => "bad frame",
                        _ => "unknown status",
                    }
                ),
                Notice::Unexpected(t) => {
                    write!(
                        f,
                        "a host command (type 0x{t:02X}) came from the board: echo or loop-back?"
                    )
                }
            },
        }
    }
}

/// The message for a [`SourceNotice::Silent`] on a serial port: the likely cause.
pub fn silence_hint(seconds: f64, bytes: u64) -> String {
    if bytes > 0 {
        format!(
            "{bytes} bytes but no valid frame in {seconds:.1} s: the baud rate is probably wrong \
             (clino's UNO firmware sends at 115200 8N1; set it with --baud), \
             or the device is not running clino firmware"
        )
    } else {
        format!(
            "no data in {seconds:.1} s: is the board powered and running clino firmware, \
             and is this its port? (a board that was sent STOP waits for START)"
        )
    }
}
