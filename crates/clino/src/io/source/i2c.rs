//! An MPU6050 on an I²C bus as a [`SampleSource`] ([`I2cSource`]).

use std::time::{Duration, Instant};

use clino_core::protocol::{self, Scales};
use clino_mpu6050::{AccelRange, Address, Config, Dlpf, GyroRange, Mpu6050};
use embedded_hal::delay::DelayNs;
use embedded_hal::i2c::{ErrorKind as BusError, I2c, NoAcknowledgeSource};

use super::{SampleSource, SourceEvent, SourceNotice};
use crate::{Error, ErrorKind, Result};

/// The longest a poll blocks, s.
const MAX_WAIT_S: f64 = 0.05;

/// The pause before a failed read is tried again.
const RETRY_PAUSE: Duration = Duration::from_millis(1);

/// The sensor's internal sample rate, Hz (see the module doc).
const SENSOR_RATE_HZ: u16 = 1000;

/// The host's clock as an [`I2cSource`] sees it: a trait, so that the tests
/// run on a virtual clock (no timed assertions) and a board could bring its own.
pub trait HostClock: Send {
    /// Time since a fixed origin (monotonic).
    fn now(&self) -> Duration;
    /// Wait for `d`.
    fn sleep(&mut self, d: Duration);
}

/// The host's monotonic clock ([`Instant`]) and [`std::thread::sleep`].
#[derive(Clone, Copy, Debug)]
pub struct StdClock {
    origin: Instant,
}

impl StdClock {
    /// A clock whose origin is now.
    pub fn new() -> Self {
        Self {
            origin: Instant::now(),
        }
    }
}

impl Default for StdClock {
    fn default() -> Self {
        Self::new()
    }
}

impl HostClock for StdClock {
    fn now(&self) -> Duration {
        self.origin.elapsed()
    }
    fn sleep(&mut self, d: Duration) {
        std::thread::sleep(d);
    }
}

/// A [`HostClock`] as the driver's delay (the 100 ms after the reset).
struct Delay<'a, C>(&'a mut C);

impl<C: HostClock> DelayNs for Delay<'_, C> {
    fn delay_ns(&mut self, ns: u32) {
        self.0.sleep(Duration::from_nanos(u64::from(ns)));
    }
}

/// Options of an [`I2cSource`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct I2cOptions {
    /// Host read rate, Hz: 0 < rate ≤ 1000 (the sensor's internal rate).
    /// Default 100 Hz, the rate of clino's board firmware.
    pub rate_hz: f64,
    /// Accelerometer full scale. Default ±2 g (16384 LSB/g): tilt at rest and
    /// slow machines; ±4 g or more where vibration or shocks saturate it.
    pub accel_range: AccelRange,
    /// Gyroscope full scale. Default ±250 °/s (131 LSB/(°/s)).
    pub gyro_range: GyroRange,
    /// Digital low-pass filter, the anti-aliasing filter of the host rate.
    /// Default 44 Hz (accelerometer; 42 Hz gyroscope), below the 50 Hz
    /// Nyquist frequency of 100 Hz.
    pub dlpf: Dlpf,
    /// Times a failed read is tried again before the stream fails. Default 3.
    pub retries: u32,
}

impl Default for I2cOptions {
    fn default() -> Self {
        Self {
            rate_hz: 100.0,
            accel_range: AccelRange::G2,
            gyro_range: GyroRange::Dps250,
            dlpf: Dlpf::Bw44Hz,
            retries: 3,
        }
    }
}

impl I2cOptions {
    /// The options of the command line's numbers: rate in Hz, accelerometer
    /// full scale in g (2, 4, 8, 16), gyroscope full scale in °/s (250, 500,
    /// 1000, 2000), low-pass bandwidth in Hz (260, 184, 94, 44, 21, 10, 5,
    /// the accelerometer's); the other fields their defaults.
    pub fn from_numbers(rate_hz: f64, accel_g: u8, gyro_dps: u16, dlpf_hz: u16) -> Result<Self> {
        let bad = |what: String| Error::new(ErrorKind::InvalidInput, what);
        let accel_range = AccelRange::from_g(accel_g).ok_or_else(|| {
            bad(format!(
                "accelerometer range must be 2, 4, 8 or 16 g, got {accel_g}"
            ))
        })?;
        let gyro_range = GyroRange::from_dps(gyro_dps).ok_or_else(|| {
            bad(format!(
                "gyroscope range must be 250, 500, 1000 or 2000 °/s, got {gyro_dps}"
            ))
        })?;
        let dlpf = (0..7)
            .filter_map(Dlpf::from_cfg)
            .find(|d| d.accel_bandwidth_hz() == dlpf_hz)
            .ok_or_else(|| {
                bad(format!(
                    "low-pass bandwidth must be 260, 184, 94, 44, 21, 10 or 5 Hz, got {dlpf_hz}"
                ))
            })?;
        let opts = Self {
            rate_hz,
            accel_range,
            gyro_range,
            dlpf,
            ..Self::default()
        };
        opts.validate()?;
        Ok(opts)
    }

    /// Check the rate (finite, 0 < rate ≤ 1000 Hz).
    pub fn validate(&self) -> Result<()> {
        if !(self.rate_hz > 0.0 && self.rate_hz <= f64::from(SENSOR_RATE_HZ)) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "the I2C read rate must be above 0 and at most {SENSOR_RATE_HZ} Hz (the sensor's rate), got {}",
                    self.rate_hz
                ),
            ));
        }
        Ok(())
    }

    /// The chip's configuration: these ranges and filter, internal rate 1 kHz.
    pub fn sensor_config(&self) -> Config {
        let mut c = Config {
            accel_range: self.accel_range,
            gyro_range: self.gyro_range,
            dlpf: self.dlpf,
            sample_rate_divider: 0,
        };
        // 1 kHz from the 1 kHz (filter on) or 8 kHz (filter off) gyroscope output rate
        c.sample_rate_divider = c.divider_for(SENSOR_RATE_HZ).unwrap_or(0);
        c
    }
}

/// The address of a command line: `0x68`, `0x69` (hex) or `104`, `105` (decimal).
pub fn parse_address(text: &str) -> Result<Address> {
    let t = text.trim();
    let n = match t.strip_prefix("0x").or_else(|| t.strip_prefix("0X")) {
        Some(hex) => u8::from_str_radix(hex, 16).ok(),
        None => t.parse::<u8>().ok(),
    };
    n.and_then(Address::from_addr).ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidInput,
            format!(
                "an MPU6050 answers at 0x68 (AD0 low) or 0x69 (AD0 high), got '{text}' \
                 (write it as 0x68 or 104)"
            ),
        )
    })
}

/// What a bus error was, in words, with the HAL's own description.
fn describe<E: embedded_hal::i2c::Error>(e: &E) -> String {
    let what = match e.kind() {
        BusError::NoAcknowledge(NoAcknowledgeSource::Address) => {
            "no acknowledge of the address (nothing answers there)"
        }
        BusError::NoAcknowledge(NoAcknowledgeSource::Data) => "no acknowledge of a data byte",
        BusError::NoAcknowledge(_) => "no acknowledge",
        BusError::ArbitrationLoss => "arbitration lost",
        BusError::Bus => "bus error (a misplaced START or STOP)",
        BusError::Overrun => "overrun",
        _ => "transfer failed",
    };
    format!("I2C {what} ({e:?})")
}

/// WHO_AM_I must read 0x68: an `Io` error when nothing answers, `InvalidInput` for another chip.
fn check_who_am_i<I: I2c>(dev: &mut Mpu6050<I>, name: &str) -> Result<()> {
    let id = dev.who_am_i().map_err(|e| {
        let why = match e {
            clino_mpu6050::Error::I2c(e) => describe(&e),
            clino_mpu6050::Error::WrongDevice(id) => format!("WHO_AM_I {id:#04x}"),
        };
        Error::new(
            ErrorKind::Io,
            format!(
                "no MPU6050 answers: {why}; check the wiring (SDA, SCL, GND, 3.3 V), \
                 the bus number and the address (0x68, or 0x69 with AD0 high; \
                 `i2cdetect -y N` lists what answers on bus N)"
            ),
        )
        .in_file(name)
    })?;
    if id != clino_mpu6050::WHO_AM_I_MPU6050 {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "WHO_AM_I reads {id:#04x}, expected {:#04x}: not an MPU6050 \
                 (an MPU6500 reads 0x70, an MPU9250 0x71, 0x00 or 0xff a bus fault)",
                clino_mpu6050::WHO_AM_I_MPU6050
            ),
        )
        .in_file(name));
    }
    Ok(())
}

/// An MPU6050 on an I²C bus as a [`SampleSource`]: set up through
/// [`clino_mpu6050`], read on a fixed-rate schedule of the host's clock.
///
/// * **Set-up** ([`I2cSource::new`]): WHO_AM_I must read 0x68 — nothing
///   answering is an error of kind [`ErrorKind::Io`] (check the wiring and
///   the address), another value one of kind [`ErrorKind::InvalidInput`]
///   (another chip) — then the chip is reset and configured
///   ([`clino_mpu6050::Mpu6050::init`]) with the ranges and low-pass filter of
///   [`I2cOptions`]. Its internal sample rate is set to 1 kHz (the gyroscope
///   output rate with the filter on, SMPLRT_DIV = 0; 8 kHz / 8 with it off),
///   above any host rate, so that every read gets a sample at most 1 ms old
///   and the two clocks' drift never makes the host read one sample twice.
///   The low-pass filter ([`I2cOptions::dlpf`]) is the anti-aliasing filter
///   of the host's rate: keep its bandwidth below half of it.
/// * **Schedule** ([`SampleSource::poll`]): sample k is due at
///   `t_k = t_0 + k / rate` on the host clock, `t_0` being the first poll;
///   its time stamp is `k / rate` s (from the start, without the read's
///   jitter). The schedule never drifts: waking late does not move it. When a
///   read comes more than one period after its due time (the host was busy,
///   the bus slow), the `m = ⌊lateness · rate⌋` sample times that passed are
///   skipped and reported ([`SourceNotice::Late`]) instead of read in a
///   burst of stale samples. A poll blocks at most 50 ms.
/// * **Reads**: one 14-byte burst (accelerometer, temperature, gyroscope of
///   one sampling instant), converted with [`Scales`] (counts / LSB per g ·
///   g₀, counts / LSB per °/s · π/180) and the temperature formula
///   ([`protocol::temp_c`]).
/// * **Bus errors**: a failed read is tried again [`I2cOptions::retries`]
///   times (each reported, [`SourceNotice::BusRetry`], 1 ms apart: a NACK or
///   a lost arbitration from a glitch on a long cable passes) before it
///   becomes an `Err` of kind [`ErrorKind::Io`] naming the device
///   (`/dev/i2c-1 @0x68: …`). Every kind of bus error is retried the same
///   way: a sensor that is really gone fails after the retries, a few ms late.
/// * **Commands**: a bare sensor has no dials; [`SampleSource::send`] refuses.
///
/// Generic over the bus (`linux_embedded_hal::I2cdev` on `/dev/i2c-N`, any
/// embedded-hal 1.0 bus, a mock in the tests) and the clock ([`HostClock`]).
pub struct I2cSource<I: I2c, C: HostClock = StdClock> {
    dev: Mpu6050<I>,
    clock: C,
    name: String,
    description: String,
    scales: Scales,
    opts: I2cOptions,
    start: Option<f64>,
    k: u64,
}

impl<I: I2c> I2cSource<I, StdClock> {
    /// Set up the MPU6050 at `address` on `bus` (called `device` in messages,
    /// e.g. `/dev/i2c-1`), read on the host's clock.
    pub fn new(bus: I, device: &str, address: Address, opts: I2cOptions) -> Result<Self> {
        Self::with_clock(bus, device, address, opts, StdClock::new())
    }
}

impl<I: I2c, C: HostClock> I2cSource<I, C> {
    /// [`I2cSource::new`] on the clock `clock`.
    pub fn with_clock(
        bus: I,
        device: &str,
        address: Address,
        opts: I2cOptions,
        mut clock: C,
    ) -> Result<Self> {
        opts.validate()?;
        let name = format!("{device} @{:#04x}", address.addr());
        let mut dev = Mpu6050::new(bus, address);
        check_who_am_i(&mut dev, &name)?;
        let config = opts.sensor_config();
        dev.init(&config, &mut Delay(&mut clock)).map_err(|e| {
            let why = match e {
                clino_mpu6050::Error::I2c(e) => describe(&e),
                e @ clino_mpu6050::Error::WrongDevice(_) => e.to_string(),
            };
            Error::new(
                ErrorKind::Io,
                format!("setting the MPU6050 up failed: {why}"),
            )
            .in_file(&name)
        })?;
        let scales = Scales::from_ranges(opts.accel_range.g(), opts.gyro_range.dps())
            .map_err(|e| Error::new(ErrorKind::InvalidInput, format!("{e:?}")))?;
        let description = format!(
            "{name} (MPU6050: read at {} Hz, sensor at {} Hz, ±{} g, ±{} °/s, low-pass {} Hz)",
            opts.rate_hz,
            config.sample_rate_hz(),
            opts.accel_range.g(),
            opts.gyro_range.dps(),
            opts.dlpf.accel_bandwidth_hz()
        );
        Ok(Self {
            dev,
            clock,
            name,
            description,
            scales,
            opts,
            start: None,
            k: 0,
        })
    }

    /// The chip's configuration as written.
    pub fn config(&self) -> &Config {
        self.dev.config()
    }

    /// The bus and the clock back.
    pub fn release(self) -> (I, C) {
        (self.dev.release(), self.clock)
    }

    /// Time of sample `k` from the start, s.
    fn t_of(&self, k: u64) -> f64 {
        k as f64 / self.opts.rate_hz
    }

    /// The burst read, tried again after a bus error (each retry a notice).
    fn read_raw(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<clino_mpu6050::RawSample> {
        let mut attempt = 0;
        loop {
            let error = match self.dev.read_raw() {
                Ok(raw) => return Ok(raw),
                Err(clino_mpu6050::Error::I2c(e)) => describe(&e),
                Err(e) => e.to_string(),
            };
            if attempt >= self.opts.retries {
                let tries = attempt + 1;
                return Err(Error::new(
                    ErrorKind::Io,
                    format!(
                        "reading the MPU6050 failed ({tries} attempt{}): {error}",
                        if tries == 1 { "" } else { "s" }
                    ),
                )
                .in_file(&self.name));
            }
            attempt += 1;
            emit(SourceEvent::Notice(SourceNotice::BusRetry {
                error,
                attempt,
                of: self.opts.retries,
            }));
            self.clock.sleep(RETRY_PAUSE);
        }
    }
}

impl<I: I2c, C: HostClock> SampleSource for I2cSource<I, C> {
    fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
        let now = self.clock.now().as_secs_f64();
        let t0 = match self.start {
            Some(t0) => t0,
            None => {
                emit(SourceEvent::Notice(SourceNotice::Connected {
                    device: self.description.clone(),
                }));
                *self.start.insert(now)
            }
        };
        let due = t0 + self.t_of(self.k);
        if due > now {
            let wait = due - now;
            if wait > MAX_WAIT_S {
                self.clock.sleep(Duration::from_secs_f64(MAX_WAIT_S));
                return Ok(true);
            }
            self.clock.sleep(Duration::from_secs_f64(wait));
        }
        let late = self.clock.now().as_secs_f64() - due;
        let missed = (late * self.opts.rate_hz).floor();
        if missed >= 1.0 {
            // whole periods passed: skip their sample times (a float → u64 `as` saturates)
            let missed = missed as u64;
            self.k = self.k.saturating_add(missed);
            emit(SourceEvent::Notice(SourceNotice::Late { missed }));
        }
        let raw = self.read_raw(emit)?;
        let wire = protocol::Sample {
            seq: 0,
            t_us: 0,
            acc: raw.accel,
            temp: raw.temp,
            gyr: raw.gyro,
        };
        emit(SourceEvent::Sample(
            wire.to_si(&self.scales, self.t_of(self.k)),
        ));
        self.k += 1;
        Ok(true)
    }

    fn name(&self) -> &str {
        &self.name
    }

    fn send(&mut self, _frame: &protocol::Frame) -> Result<()> {
        Err(Error::new(
            ErrorKind::InvalidInput,
            "a bare MPU6050 takes no commands (no dials): --dials needs a board running \
             clino firmware (--port)",
        )
        .in_file(&self.name))
    }
}
