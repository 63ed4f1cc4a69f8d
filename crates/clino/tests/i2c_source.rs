//! The I²C source without hardware: a register-file MPU6050 on a mock
//! embedded-hal bus plays a scripted motion (a constant rotation about x,
//! gravity turning with it, a slowly warming die) on a virtual clock that
//! the source's waits and the bus transfers advance. Nothing here is timed.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use clino::ErrorKind;
use clino::core::protocol::Frame;
use clino::fusion::{FilterConfig, FilterKind, FuseOptions};
use clino::io::source::{
    HostClock, I2cOptions, I2cSource, SampleSource, SourceEvent, SourceNotice, parse_address,
};
use clino::io::{ImuCsvReader, ReadOptions};
use clino::mpu6050::{AccelRange, Address, Dlpf, GyroRange};
use clino::stream::{
    FusedCsv, LiveStatus, Recorder, StreamConfig, StreamCounts, StreamObserver, StreamOutputs,
};
use embedded_hal::i2c::{self, ErrorType, I2c, NoAcknowledgeSource, Operation};

const G0: f64 = 9.806_65;
/// The rotation rate about body x, rad/s (20 °/s).
const OMEGA: f64 = 20.0 * std::f64::consts::PI / 180.0;
/// The constant pitch, rad (10°).
const PITCH: f64 = 10.0 * std::f64::consts::PI / 180.0;

/// Virtual time, ns, shared by the source's clock and the bus.
#[derive(Clone, Default)]
struct VirtualClock(Arc<AtomicU64>);

impl VirtualClock {
    fn advance(&self, d: Duration) {
        self.0.fetch_add(d.as_nanos() as u64, Ordering::SeqCst);
    }
    fn seconds(&self) -> f64 {
        self.0.load(Ordering::SeqCst) as f64 * 1e-9
    }
}

impl HostClock for VirtualClock {
    fn now(&self) -> Duration {
        Duration::from_nanos(self.0.load(Ordering::SeqCst))
    }
    fn sleep(&mut self, d: Duration) {
        self.advance(d);
    }
}

#[derive(Debug)]
struct Nack;

impl i2c::Error for Nack {
    fn kind(&self) -> i2c::ErrorKind {
        i2c::ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
    }
}

/// The truth at virtual time `t`: gyro rad/s, specific force m/s², die °C.
/// A turn about body x at a constant pitch θ: z-y-x roll φ = ω t, and at
/// rest the accelerometer reads (−g sin θ, g sin φ cos θ, g cos φ cos θ).
fn truth(t: f64) -> ([f64; 3], [f64; 3], f64) {
    let phi = OMEGA * t;
    (
        [OMEGA, 0.0, 0.0],
        [
            -G0 * PITCH.sin(),
            G0 * phi.sin() * PITCH.cos(),
            G0 * phi.cos() * PITCH.cos(),
        ],
        25.0 + 0.5 * t,
    )
}

fn round(x: f64) -> i16 {
    x.round().clamp(-32768.0, 32767.0) as i16
}

/// One served data read: virtual time, counts (accel, temp, gyro).
#[derive(Clone, Copy, Debug)]
struct Served {
    t: f64,
    /// Time of the motion (from the first data read: the turn starts there).
    m: f64,
    acc: [i16; 3],
    temp: i16,
    gyr: [i16; 3],
}

/// A register-file MPU6050 at 0x68: writes set the register pointer and
/// auto-increment; a reset clears the registers and puts the chip to sleep;
/// a 14-byte read from ACCEL_XOUT_H serves the truth in counts at the
/// ranges the registers hold (zeros while asleep), at the bus's virtual time.
struct Mpu {
    regs: [u8; 128],
    pointer: u8,
    clock: VirtualClock,
    /// Bus time of one transaction.
    transfer: Duration,
    /// Data-read attempts so far (failed ones too).
    attempts: usize,
    /// Attempts that return this much later: (attempt, extra).
    stall: Option<(usize, Duration)>,
    /// Attempts that are not acknowledged.
    fail: fn(usize) -> bool,
    /// Register writes so far.
    writes: Arc<AtomicU64>,
    served: Arc<Mutex<Vec<Served>>>,
    origin: Option<f64>,
}

impl Mpu {
    fn new(clock: VirtualClock) -> Self {
        let mut regs = [0u8; 128];
        regs[0x75] = 0x68;
        regs[0x6B] = 0x40;
        Self {
            regs,
            pointer: 0,
            clock,
            transfer: Duration::from_micros(200),
            attempts: 0,
            stall: None,
            fail: |_| false,
            writes: Arc::default(),
            served: Arc::default(),
            origin: None,
        }
    }

    fn data(&mut self, buf: &mut [u8]) {
        let asleep = self.regs[0x6B] & 0x40 != 0;
        let lsb_g = 16384.0 / f64::from(1u16 << ((self.regs[0x1C] >> 3) & 3));
        let lsb_dps = [131.0, 65.5, 32.8, 16.4][usize::from((self.regs[0x1B] >> 3) & 3)];
        let t = self.clock.seconds();
        let m = t - *self.origin.get_or_insert(t);
        let (g, a, temp) = truth(m);
        let s = Served {
            t,
            m,
            acc: a.map(|v| round(v / G0 * lsb_g)),
            temp: round((temp - 36.53) * 340.0),
            gyr: g.map(|v| round(v.to_degrees() * lsb_dps)),
        };
        let words = [
            s.acc[0], s.acc[1], s.acc[2], s.temp, s.gyr[0], s.gyr[1], s.gyr[2],
        ];
        for (i, w) in words.iter().enumerate() {
            let b = if asleep { [0, 0] } else { w.to_be_bytes() };
            buf[2 * i..2 * i + 2].copy_from_slice(&b);
        }
        if !asleep {
            self.served.lock().unwrap().push(s);
        }
    }
}

impl ErrorType for Mpu {
    type Error = Nack;
}

impl I2c for Mpu {
    fn transaction(&mut self, address: u8, ops: &mut [Operation<'_>]) -> Result<(), Nack> {
        self.clock.advance(self.transfer);
        if address != 0x68 {
            return Err(Nack);
        }
        for op in ops {
            match op {
                Operation::Write(bytes) => {
                    self.pointer = bytes[0];
                    for &b in &bytes[1..] {
                        self.writes.fetch_add(1, Ordering::SeqCst);
                        if self.pointer == 0x6B && b & 0x80 != 0 {
                            let id = self.regs[0x75];
                            self.regs = [0; 128];
                            self.regs[0x75] = id;
                            self.regs[0x6B] = 0x40;
                        } else {
                            self.regs[usize::from(self.pointer & 0x7F)] = b;
                        }
                        self.pointer = self.pointer.wrapping_add(1);
                    }
                }
                Operation::Read(buf) if self.pointer == 0x3B && buf.len() == 14 => {
                    let n = self.attempts;
                    self.attempts += 1;
                    if (self.fail)(n) {
                        return Err(Nack);
                    }
                    self.data(buf);
                    if let Some((at, extra)) = self.stall
                        && at == n
                    {
                        self.clock.advance(extra);
                    }
                }
                Operation::Read(buf) => {
                    for b in buf.iter_mut() {
                        *b = self.regs[usize::from(self.pointer & 0x7F)];
                        self.pointer = self.pointer.wrapping_add(1);
                    }
                }
            }
        }
        Ok(())
    }
}

fn opts(rate_hz: f64) -> I2cOptions {
    I2cOptions {
        rate_hz,
        ..I2cOptions::default()
    }
}

fn source(mpu: Mpu, clock: &VirtualClock, o: I2cOptions) -> I2cSource<Mpu, VirtualClock> {
    I2cSource::with_clock(mpu, "/dev/i2c-1", Address::Ad0Low, o, clock.clone()).unwrap()
}

/// The events of `polls` polls (stopping at the first error, returned too).
fn run(
    src: &mut impl SampleSource,
    polls: usize,
) -> (Vec<SourceEvent>, Option<clino::Error>, Vec<usize>) {
    let mut events = Vec::new();
    let mut per_poll = Vec::new();
    for _ in 0..polls {
        let before = events.len();
        let r = src.poll(&mut |e| events.push(e));
        per_poll.push(events.len() - before);
        match r {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return (events, Some(e), per_poll),
        }
    }
    (events, None, per_poll)
}

fn samples(events: &[SourceEvent]) -> Vec<clino::core::ImuSample> {
    events
        .iter()
        .filter_map(|e| match e {
            SourceEvent::Sample(s) => Some(*s),
            _ => None,
        })
        .collect()
}

#[test]
fn the_sensor_is_set_up_as_the_options_say() {
    let clock = VirtualClock::default();
    let o = I2cOptions {
        accel_range: AccelRange::G8,
        gyro_range: GyroRange::Dps1000,
        dlpf: Dlpf::Bw21Hz,
        ..opts(100.0)
    };
    let (mpu, _) = source(Mpu::new(clock.clone()), &clock, o).release();
    assert_eq!(mpu.regs[0x6B], 0x01, "awake, PLL clock");
    assert_eq!(mpu.regs[0x19], 0, "SMPLRT_DIV: 1 kHz / (1 + 0)");
    assert_eq!(mpu.regs[0x1A], 4, "DLPF_CFG 4 = 21 Hz");
    assert_eq!(mpu.regs[0x1B], 2 << 3, "FS_SEL 2 = ±1000 °/s");
    assert_eq!(mpu.regs[0x1C], 2 << 3, "AFS_SEL 2 = ±8 g");
    assert_eq!(mpu.regs[0x38], 1, "DATA_RDY_EN");
    // the reset waited its 100 ms on the (virtual) host clock
    assert!(clock.seconds() >= 0.1, "{}", clock.seconds());
    // with the filter off the gyro runs at 8 kHz: divider 7 keeps the sensor at 1 kHz
    let off = I2cOptions {
        dlpf: Dlpf::Bw260Hz,
        ..opts(100.0)
    };
    assert_eq!(off.sensor_config().sample_rate_divider, 7);
    assert_eq!(off.sensor_config().sample_rate_hz(), 1000.0);
}

#[test]
fn samples_are_the_counts_in_si_on_a_fixed_rate_schedule() {
    for (accel_range, gyro_range, lsb_g, lsb_dps) in [
        (AccelRange::G2, GyroRange::Dps250, 16384.0, 131.0),
        (AccelRange::G8, GyroRange::Dps1000, 4096.0, 32.8),
    ] {
        let clock = VirtualClock::default();
        let mpu = Mpu::new(clock.clone());
        let served = mpu.served.clone();
        let o = I2cOptions {
            accel_range,
            gyro_range,
            ..opts(100.0)
        };
        let mut src = source(mpu, &clock, o);
        let t0 = clock.seconds(); // the first poll reads at once
        let (events, err, _) = run(&mut src, 300);
        assert!(err.is_none(), "{err:?}");
        assert!(
            matches!(&events[0], SourceEvent::Notice(SourceNotice::Connected { device })
                if device.starts_with("/dev/i2c-1 @0x68 (MPU6050: read at 100 Hz"))
        );
        assert_eq!(events.len(), 301, "one Connected, then one sample per poll");
        let s = samples(&events);
        let served = served.lock().unwrap();
        assert_eq!((s.len(), served.len()), (300, 300));
        for (k, (s, c)) in s.iter().zip(served.iter()).enumerate() {
            // time stamps on the schedule k / rate, and each read at its due time
            assert_eq!(s.t_s, k as f64 / 100.0);
            let read_at = c.t - t0;
            assert!(
                read_at >= s.t_s - 1e-9 && read_at <= s.t_s + 0.5e-3,
                "sample {k}: read at {read_at} s, due {} s",
                s.t_s
            );
            // SI from the counts with the datasheet's sensitivities
            for i in 0..3 {
                assert_eq!(s.acc_m_s2[i], f64::from(c.acc[i]) / lsb_g * G0);
                assert_eq!(
                    s.gyr_rad_s[i],
                    f64::from(c.gyr[i]) / lsb_dps * (std::f64::consts::PI / 180.0)
                );
            }
            assert_eq!(s.temp_c, Some(f64::from(c.temp) / 340.0 + 36.53));
            // and the truth, to half a count
            let (g, a, temp) = truth(c.m);
            for i in 0..3 {
                assert!((s.acc_m_s2[i] - a[i]).abs() <= 0.5 / lsb_g * G0 + 1e-12);
                assert!((s.gyr_rad_s[i] - g[i]).abs() <= 0.5 / lsb_dps * 0.0175);
            }
            assert!((s.temp_c.unwrap() - temp).abs() <= 0.5 / 340.0 + 1e-12);
        }
    }
}

#[test]
fn a_read_more_than_a_period_late_skips_sample_times_and_says_so() {
    let clock = VirtualClock::default();
    let mut mpu = Mpu::new(clock.clone());
    // the 21st read (sample 20, due at 0.200 s) returns 35 ms late: the next
    // due time 0.210 s is then 25.2 ms behind, two whole periods
    mpu.stall = Some((20, Duration::from_millis(35)));
    let served = mpu.served.clone();
    let mut src = source(mpu, &clock, opts(100.0));
    let t0 = clock.seconds();
    let (events, err, _) = run(&mut src, 40);
    assert!(err.is_none(), "{err:?}");
    let t: Vec<u64> = samples(&events)
        .iter()
        .map(|s| (s.t_s * 100.0).round() as u64)
        .collect();
    let want: Vec<u64> = (0..=20).chain(23..42).collect();
    assert_eq!(t, want);
    let late: Vec<(usize, u64)> = events
        .iter()
        .enumerate()
        .filter_map(|(i, e)| match e {
            SourceEvent::Notice(SourceNotice::Late { missed }) => Some((i, *missed)),
            _ => None,
        })
        .collect();
    // one notice, right before the sample at 0.23 s
    assert_eq!(late.len(), 1, "{late:?}");
    assert_eq!(late[0].1, 2);
    assert!(matches!(&events[late[0].0 + 1], SourceEvent::Sample(s) if s.t_s == 0.23));
    // the schedule did not drift: after the stall every read is within a period of its due time
    for (s, c) in samples(&events).iter().zip(served.lock().unwrap().iter()) {
        let behind = c.t - t0 - s.t_s;
        assert!((-1e-9..0.01).contains(&behind), "{} s: {behind}", s.t_s);
    }
    // less than a period late: no notice, nothing skipped
    let clock = VirtualClock::default();
    let mut mpu = Mpu::new(clock.clone());
    mpu.stall = Some((5, Duration::from_millis(8)));
    let mut src = source(mpu, &clock, opts(100.0));
    let (events, _, _) = run(&mut src, 20);
    let t: Vec<f64> = samples(&events).iter().map(|s| s.t_s).collect();
    assert_eq!(t, (0..20).map(|k| k as f64 / 100.0).collect::<Vec<_>>());
    assert!(
        !events
            .iter()
            .any(|e| matches!(e, SourceEvent::Notice(SourceNotice::Late { .. })))
    );
}

#[test]
fn a_slow_rate_keeps_each_poll_within_50_ms() {
    let clock = VirtualClock::default();
    let mut src = source(Mpu::new(clock.clone()), &clock, opts(4.0));
    let mut last = clock.seconds();
    let mut events = Vec::new();
    for _ in 0..40 {
        src.poll(&mut |e| events.push(e)).unwrap();
        let now = clock.seconds();
        assert!(now - last <= 0.05 + 1e-3, "a poll blocked {} s", now - last);
        last = now;
    }
    let t: Vec<f64> = samples(&events).iter().map(|s| s.t_s).collect();
    // 40 polls of at most 50 ms: samples at 0, 0.25, …; none twice
    assert!(t.len() >= 6, "{t:?}");
    assert_eq!(t, (0..t.len()).map(|k| k as f64 * 0.25).collect::<Vec<_>>());
}

#[test]
fn a_wrong_who_am_i_is_named_and_nothing_is_written() {
    let clock = VirtualClock::default();
    let mut mpu = Mpu::new(clock.clone());
    mpu.regs[0x75] = 0x70; // an MPU6500
    let writes = mpu.writes.clone();
    let e = I2cSource::with_clock(mpu, "/dev/i2c-1", Address::Ad0Low, opts(100.0), clock)
        .err()
        .unwrap();
    assert_eq!(e.kind, ErrorKind::InvalidInput);
    let m = e.to_string();
    assert!(m.starts_with("/dev/i2c-1 @0x68: "), "{m}");
    assert!(m.contains("WHO_AM_I reads 0x70, expected 0x68"), "{m}");
    assert_eq!(writes.load(Ordering::SeqCst), 0);
}

#[test]
fn an_absent_sensor_is_an_io_error_naming_the_address() {
    let clock = VirtualClock::default();
    // the chip answers at 0x68; nothing answers at 0x69
    let e = I2cSource::with_clock(
        Mpu::new(clock.clone()),
        "/dev/i2c-1",
        Address::Ad0High,
        opts(100.0),
        clock,
    )
    .err()
    .unwrap();
    assert_eq!(e.kind, ErrorKind::Io);
    let m = e.to_string();
    assert!(m.starts_with("/dev/i2c-1 @0x69: no MPU6050 answers"), "{m}");
    assert!(m.contains("no acknowledge of the address"), "{m}");
    assert!(m.contains("i2cdetect"), "{m}");
    // the rate is checked before the bus is touched
    let clock = VirtualClock::default();
    let e = I2cSource::with_clock(
        Mpu::new(clock.clone()),
        "/dev/i2c-1",
        Address::Ad0Low,
        opts(2000.0),
        clock.clone(),
    )
    .err()
    .unwrap();
    assert_eq!(e.kind, ErrorKind::InvalidInput);
    assert_eq!(clock.seconds(), 0.0);
}

#[test]
fn a_transient_nack_is_retried_and_the_sample_kept() {
    let clock = VirtualClock::default();
    let mut mpu = Mpu::new(clock.clone());
    mpu.fail = |n| n == 5 || n == 9 || n == 10;
    let mut src = source(mpu, &clock, opts(100.0));
    let (events, err, _) = run(&mut src, 12);
    assert!(err.is_none(), "{err:?}");
    let t: Vec<f64> = samples(&events).iter().map(|s| s.t_s).collect();
    assert_eq!(t, (0..12).map(|k| k as f64 / 100.0).collect::<Vec<_>>());
    let retries: Vec<(u32, u32)> = events
        .iter()
        .filter_map(|e| match e {
            SourceEvent::Notice(SourceNotice::BusRetry { error, attempt, of }) => {
                assert!(error.contains("no acknowledge"), "{error}");
                Some((*attempt, *of))
            }
            _ => None,
        })
        .collect();
    // attempt 5 (sample 5) once; attempts 9 and 10 (sample 8) twice
    assert_eq!(retries, [(1, 3), (1, 3), (2, 3)]);
}

#[test]
fn a_sensor_gone_mid_stream_is_an_io_error_naming_the_device() {
    let clock = VirtualClock::default();
    let mut mpu = Mpu::new(clock.clone());
    mpu.fail = |n| n >= 30;
    let mut src = source(mpu, &clock, opts(100.0));
    let (events, err, _) = run(&mut src, 100);
    let e = err.expect("an error");
    assert_eq!(e.kind, ErrorKind::Io);
    let m = e.to_string();
    assert!(
        m.starts_with(
            "/dev/i2c-1 @0x68: reading the MPU6050 failed (4 attempts): I2C no acknowledge"
        ),
        "{m}"
    );
    assert_eq!(samples(&events).len(), 30);
    let retries = events
        .iter()
        .filter(|e| matches!(e, SourceEvent::Notice(SourceNotice::BusRetry { .. })))
        .count();
    assert_eq!(retries, 3);
    // no retries: the first failure ends it
    let clock = VirtualClock::default();
    let mut mpu = Mpu::new(clock.clone());
    mpu.fail = |n| n >= 2;
    let o = I2cOptions {
        retries: 0,
        ..opts(100.0)
    };
    let mut src = source(mpu, &clock, o);
    let (events, err, _) = run(&mut src, 10);
    assert!(err.unwrap().to_string().contains("(1 attempt)"));
    assert_eq!(samples(&events).len(), 2);
}

#[test]
fn a_bare_sensor_refuses_commands() {
    let clock = VirtualClock::default();
    let mut src = source(Mpu::new(clock.clone()), &clock, opts(100.0));
    let e = src
        .send(&Frame::SetDials {
            roll_cdeg: 0,
            pitch_cdeg: 0,
        })
        .unwrap_err();
    assert_eq!(e.kind, ErrorKind::InvalidInput);
    assert!(e.to_string().contains("no dials"), "{e}");
    assert!(src.is_live());
    assert_eq!(src.name(), "/dev/i2c-1 @0x68");
}

#[test]
fn addresses_and_numbers_of_the_command_line() {
    assert_eq!(parse_address("0x68").unwrap(), Address::Ad0Low);
    assert_eq!(parse_address("0X69").unwrap(), Address::Ad0High);
    assert_eq!(parse_address("104").unwrap(), Address::Ad0Low);
    assert_eq!(parse_address("105").unwrap(), Address::Ad0High);
    for bad in ["0x70", "68", "", "0x", "abc", "0x168", "-1"] {
        let e = parse_address(bad).unwrap_err();
        assert!(e.message.contains("0x68 (AD0 low) or 0x69"), "{bad}: {e}");
    }
    let o = I2cOptions::from_numbers(200.0, 4, 500, 94).unwrap();
    assert_eq!(
        (o.rate_hz, o.accel_range, o.gyro_range, o.dlpf),
        (200.0, AccelRange::G4, GyroRange::Dps500, Dlpf::Bw94Hz)
    );
    assert_eq!(
        I2cOptions::from_numbers(100.0, 2, 250, 44).unwrap(),
        I2cOptions::default()
    );
    for (rate, g, dps, hz, what) in [
        (0.0, 2, 250, 44, "rate"),
        (f64::NAN, 2, 250, 44, "rate"),
        (1000.5, 2, 250, 44, "rate"),
        (100.0, 3, 250, 44, "accelerometer"),
        (100.0, 2, 300, 44, "gyroscope"),
        (100.0, 2, 250, 42, "low-pass"),
    ] {
        let e = I2cOptions::from_numbers(rate, g, dps, hz).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput);
        assert!(e.message.contains(what), "{e}");
    }
}

/// A source that ends after `left` samples.
struct Take<S> {
    inner: S,
    left: usize,
}

impl<S: SampleSource> SampleSource for Take<S> {
    fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> clino::Result<bool> {
        if self.left == 0 {
            return Ok(false);
        }
        let left = &mut self.left;
        self.inner.poll(&mut |e| {
            if matches!(e, SourceEvent::Sample(_)) {
                if *left == 0 {
                    return;
                }
                *left -= 1;
            }
            emit(e)
        })
    }
    fn name(&self) -> &str {
        self.inner.name()
    }
}

/// A `Write` into a shared buffer.
#[derive(Clone, Default)]
struct Shared(Arc<Mutex<Vec<u8>>>);

impl std::io::Write for Shared {
    fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
        self.0.lock().unwrap().extend_from_slice(b);
        Ok(b.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

struct Quiet(Vec<String>);

impl StreamObserver for Quiet {
    fn notice(&mut self, n: &SourceNotice, _: &StreamCounts) {
        self.0.push(n.to_string());
    }
    fn message(&mut self, _: &str) {}
    fn tick(&mut self, _: &LiveStatus) {}
}

fn fuse_file(path: &std::path::Path, filter: &FilterConfig) -> String {
    let mut reader = ImuCsvReader::from_path(path, &ReadOptions::default()).unwrap();
    let mut out = Vec::new();
    clino::fusion::fuse(&mut reader, &mut out, filter, &FuseOptions::default()).unwrap();
    String::from_utf8(out).unwrap()
}

#[test]
fn the_stream_loop_over_the_sensor_writes_what_fuse_writes_on_its_samples() {
    let tmp = tempfile::Builder::new()
        .prefix("clino-i2c-test-")
        .tempdir()
        .unwrap();
    let dir = tmp.path();
    let n = 1500; // 15 s at 100 Hz: the filter initialises and tracks the rotation
    let make = || {
        let clock = VirtualClock::default();
        let mut mpu = Mpu::new(clock.clone());
        // one late read on the way: 35.2 ms behind the next due time, 3 periods
        mpu.stall = Some((700, Duration::from_millis(45)));
        Take {
            inner: source(mpu, &clock, opts(100.0)),
            left: n,
        }
    };
    // the samples, straight from the source, written as a recording by hand
    let (events, err, _) = run(&mut make(), 10 * n);
    assert!(err.is_none());
    let direct = dir.join("direct.csv");
    let mut text = String::from(
        "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,temp_c\n",
    );
    for s in samples(&events) {
        let g = s.gyr_rad_s;
        let a = s.acc_m_s2;
        text.push_str(&format!(
            "{},{},{},{},{},{},{},{}\n",
            s.t_s,
            g[0],
            g[1],
            g[2],
            a[0],
            a[1],
            a[2],
            s.temp_c.unwrap()
        ));
    }
    std::fs::write(&direct, text).unwrap();
    for kind in [FilterKind::Dynamic, FilterKind::Mahony] {
        let filter = FilterConfig::new(kind);
        let mut cfg = StreamConfig::new(filter);
        cfg.capacity = 10 * n; // the virtual clock never waits: no sample may be dropped
        let out = Shared::default();
        let rec = dir.join("rec.csv");
        let mut outputs = StreamOutputs {
            csv: Some(
                FusedCsv::new(Box::new(out.clone()) as Box<dyn std::io::Write + Send>).unwrap(),
            ),
            record: Some(Recorder::create(&rec, &[]).unwrap()),
        };
        let mut obs = Quiet(Vec::new());
        let stop = AtomicBool::new(false);
        let counts =
            clino::stream::run(Box::new(make()), &cfg, &mut outputs, &mut obs, &stop).unwrap();
        assert_eq!(outputs.record.take().unwrap().finish().unwrap(), n as u64);
        assert_eq!((counts.received, counts.dropped), (n as u64, 0));
        assert_eq!((counts.late_reads, counts.skipped), (1, 3), "{counts:?}");
        assert!(
            counts
                .summary()
                .iter()
                .any(|l| l == "sensor: 1 late reads (3 sample times skipped), 0 bus retries")
        );
        assert!(
            obs.0.iter().any(|m| m.contains("3 sample times skipped")),
            "{:?}",
            obs.0
        );
        let streamed = String::from_utf8(out.0.lock().unwrap().clone()).unwrap();
        assert_eq!(streamed.lines().count(), n + 1);
        assert_eq!(streamed, fuse_file(&direct, &filter), "{kind:?}");
        assert_eq!(streamed, fuse_file(&rec, &filter), "{kind:?} (recording)");
        // and the filter follows the turn: roll = ω t (wrapped to ±180°), pitch 10°
        let last: Vec<&str> = streamed.lines().last().unwrap().split(',').collect();
        let t: f64 = last[0].parse().unwrap();
        let (roll, pitch): (f64, f64) = (last[5].parse().unwrap(), last[6].parse().unwrap());
        let want = ((OMEGA * t).to_degrees() + 180.0).rem_euclid(360.0) - 180.0;
        assert!(
            (roll - want).abs() < 0.5,
            "{kind:?}: roll {roll}°, want {want}°"
        );
        assert!((pitch - 10.0).abs() < 0.5, "{kind:?}: pitch {pitch}°");
    }
}
