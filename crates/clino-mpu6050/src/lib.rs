//! # clino-mpu6050 — the MPU6050 over embedded-hal 1.0
//!
//! A `no_std`, allocation-free driver for the InvenSense MPU6050 (three-axis
//! gyroscope + three-axis accelerometer + temperature), generic over
//! [`embedded_hal::i2c::I2c`], so the same code runs on a microcontroller's
//! I²C peripheral, on Linux `/dev/i2c-N` (`linux-embedded-hal`) and against a
//! scripted mock bus in the tests.
//!
//! * every bus failure is one error kind, [`Error::I2c`], carrying the HAL's
//!   error (whose [`embedded_hal::i2c::Error::kind`] says NACK, arbitration
//!   loss, …); a chip that does not answer `0x68` to WHO_AM_I is
//!   [`Error::WrongDevice`];
//! * the configuration is typed ([`Config`]: [`AccelRange`], [`GyroRange`],
//!   [`Dlpf`], the sample-rate divider) and written in one burst;
//! * one 14-byte burst read ([`Mpu6050::read_raw`]) gives the raw counts of
//!   ACCEL_XOUT…GYRO_ZOUT, all taken at the same sampling instant (the chip
//!   latches its output registers during a burst read; register map §3);
//!   [`RawSample::to_si`] converts them to SI units.
//!
//! Sources: *MPU-6000 and MPU-6050 Product Specification*, PS-MPU-6000A-00
//! rev 3.4 (sensitivities, §6.1–6.2; temperature, §6.4) and *MPU-6000 and
//! MPU-6050 Register Map and Descriptions*, RM-MPU-6000A-00 rev 4.2
//! (registers 25–28, 56, 58, 59–72, 107, 117).
//!
//! ```
//! use clino_mpu6050::{AccelRange, Config, Dlpf, GyroRange, RawSample};
//! let cfg = Config { accel_range: AccelRange::G4, gyro_range: GyroRange::Dps500,
//!                    dlpf: Dlpf::Bw44Hz, sample_rate_divider: 9 };
//! assert_eq!(cfg.sample_rate_hz(), 100.0);
//! // 8192 counts = 1 g at ±4 g; 65.5 counts = 1 °/s at ±500 °/s
//! let raw = RawSample { accel: [0, 0, 8192], temp: 0, gyro: [0, 0, 0] };
//! assert_eq!(raw.to_si(&cfg).acc_m_s2[2], 9.80665);
//! ```
#![no_std]
#![deny(missing_docs)]

use embedded_hal::delay::DelayNs;
use embedded_hal::i2c::I2c;

/// Register addresses (register map rev 4.2, §3).
pub mod register {
    /// SMPLRT_DIV (25): sample rate = gyroscope output rate / (1 + SMPLRT_DIV).
    pub const SMPLRT_DIV: u8 = 0x19;
    /// CONFIG (26): DLPF_CFG in bits 2:0.
    pub const CONFIG: u8 = 0x1A;
    /// GYRO_CONFIG (27): FS_SEL in bits 4:3.
    pub const GYRO_CONFIG: u8 = 0x1B;
    /// ACCEL_CONFIG (28): AFS_SEL in bits 4:3.
    pub const ACCEL_CONFIG: u8 = 0x1C;
    /// INT_ENABLE (56): DATA_RDY_EN in bit 0.
    pub const INT_ENABLE: u8 = 0x38;
    /// INT_STATUS (58): DATA_RDY_INT in bit 0, cleared by reading.
    pub const INT_STATUS: u8 = 0x3A;
    /// ACCEL_XOUT_H (59): first of the 14 data registers (accel x y z, temp, gyro x y z; big-endian).
    pub const ACCEL_XOUT_H: u8 = 0x3B;
    /// PWR_MGMT_1 (107): DEVICE_RESET bit 7, SLEEP bit 6, CLKSEL bits 2:0.
    pub const PWR_MGMT_1: u8 = 0x6B;
    /// WHO_AM_I (117): reads [`super::WHO_AM_I_MPU6050`] whatever the AD0 pin.
    pub const WHO_AM_I: u8 = 0x75;
}

/// What WHO_AM_I reads on an MPU6050 (register map §4.32: bits 6:1 = 0b110100).
pub const WHO_AM_I_MPU6050: u8 = 0x68;

/// Standard gravity, m/s² (the conversion of g to SI, as in `clino_core::G0`).
pub const G0: f64 = 9.806_65;

/// Wait after DEVICE_RESET before the next command, ms (the 100 ms of the
/// register map's reset sequence, §4.28).
pub const RESET_DELAY_MS: u32 = 100;

/// The chip's 7-bit I²C address, set by its AD0 pin (register map §4.32).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub enum Address {
    /// AD0 low: 0x68 (the default on most breakout boards).
    #[default]
    Ad0Low,
    /// AD0 high: 0x69.
    Ad0High,
}

impl Address {
    /// The 7-bit address.
    pub const fn addr(self) -> u8 {
        match self {
            Address::Ad0Low => 0x68,
            Address::Ad0High => 0x69,
        }
    }

    /// The address `a` (0x68 or 0x69), `None` for any other value.
    pub const fn from_addr(a: u8) -> Option<Self> {
        match a {
            0x68 => Some(Address::Ad0Low),
            0x69 => Some(Address::Ad0High),
            _ => None,
        }
    }
}

/// Accelerometer full-scale range (ACCEL_CONFIG.AFS_SEL; product specification §6.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AccelRange {
    /// ±2 g, 16384 LSB/g.
    G2,
    /// ±4 g, 8192 LSB/g.
    G4,
    /// ±8 g, 4096 LSB/g.
    G8,
    /// ±16 g, 2048 LSB/g.
    G16,
}

impl AccelRange {
    /// AFS_SEL, 0..=3.
    pub const fn afs_sel(self) -> u8 {
        match self {
            AccelRange::G2 => 0,
            AccelRange::G4 => 1,
            AccelRange::G8 => 2,
            AccelRange::G16 => 3,
        }
    }

    /// The full scale in g (2, 4, 8 or 16: the wire protocol's `accel_fs_g`).
    pub const fn g(self) -> u8 {
        2 << self.afs_sel()
    }

    /// The range of full scale `g` (2, 4, 8 or 16), `None` otherwise.
    pub const fn from_g(g: u8) -> Option<Self> {
        match g {
            2 => Some(AccelRange::G2),
            4 => Some(AccelRange::G4),
            8 => Some(AccelRange::G8),
            16 => Some(AccelRange::G16),
            _ => None,
        }
    }

    /// Sensitivity, LSB per g: 16384 / 2^AFS_SEL.
    pub const fn lsb_per_g(self) -> f64 {
        match self {
            AccelRange::G2 => 16384.0,
            AccelRange::G4 => 8192.0,
            AccelRange::G8 => 4096.0,
            AccelRange::G16 => 2048.0,
        }
    }
}

/// Gyroscope full-scale range (GYRO_CONFIG.FS_SEL; product specification §6.1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum GyroRange {
    /// ±250 °/s, 131 LSB/(°/s).
    Dps250,
    /// ±500 °/s, 65.5 LSB/(°/s).
    Dps500,
    /// ±1000 °/s, 32.8 LSB/(°/s).
    Dps1000,
    /// ±2000 °/s, 16.4 LSB/(°/s).
    Dps2000,
}

impl GyroRange {
    /// FS_SEL, 0..=3.
    pub const fn fs_sel(self) -> u8 {
        match self {
            GyroRange::Dps250 => 0,
            GyroRange::Dps500 => 1,
            GyroRange::Dps1000 => 2,
            GyroRange::Dps2000 => 3,
        }
    }

    /// The full scale in °/s (250, 500, 1000 or 2000: the wire protocol's `gyro_fs_dps`).
    pub const fn dps(self) -> u16 {
        250 << self.fs_sel()
    }

    /// The range of full scale `dps` (250, 500, 1000 or 2000), `None` otherwise.
    pub const fn from_dps(dps: u16) -> Option<Self> {
        match dps {
            250 => Some(GyroRange::Dps250),
            500 => Some(GyroRange::Dps500),
            1000 => Some(GyroRange::Dps1000),
            2000 => Some(GyroRange::Dps2000),
            _ => None,
        }
    }

    /// Sensitivity, LSB per °/s, as the datasheet states it (131, 65.5, 32.8, 16.4).
    pub const fn lsb_per_dps(self) -> f64 {
        match self {
            GyroRange::Dps250 => 131.0,
            GyroRange::Dps500 => 65.5,
            GyroRange::Dps1000 => 32.8,
            GyroRange::Dps2000 => 16.4,
        }
    }
}

/// Digital low-pass filter (CONFIG.DLPF_CFG, register map §4.3): the
/// accelerometer and gyroscope bandwidths; it also sets the gyroscope output
/// rate (8 kHz for DLPF_CFG = 0, 1 kHz otherwise).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Dlpf {
    /// DLPF_CFG 0: accelerometer 260 Hz, gyroscope 256 Hz, gyro output 8 kHz.
    Bw260Hz,
    /// DLPF_CFG 1: 184 Hz / 188 Hz.
    Bw184Hz,
    /// DLPF_CFG 2: 94 Hz / 98 Hz.
    Bw94Hz,
    /// DLPF_CFG 3: 44 Hz / 42 Hz.
    Bw44Hz,
    /// DLPF_CFG 4: 21 Hz / 20 Hz.
    Bw21Hz,
    /// DLPF_CFG 5: 10 Hz / 10 Hz.
    Bw10Hz,
    /// DLPF_CFG 6: 5 Hz / 5 Hz.
    Bw5Hz,
}

impl Dlpf {
    /// DLPF_CFG, 0..=6 (the wire protocol's `dlpf_cfg`).
    pub const fn cfg(self) -> u8 {
        match self {
            Dlpf::Bw260Hz => 0,
            Dlpf::Bw184Hz => 1,
            Dlpf::Bw94Hz => 2,
            Dlpf::Bw44Hz => 3,
            Dlpf::Bw21Hz => 4,
            Dlpf::Bw10Hz => 5,
            Dlpf::Bw5Hz => 6,
        }
    }

    /// The setting of DLPF_CFG `cfg`, `None` for 7 (reserved) and above.
    pub const fn from_cfg(cfg: u8) -> Option<Self> {
        match cfg {
            0 => Some(Dlpf::Bw260Hz),
            1 => Some(Dlpf::Bw184Hz),
            2 => Some(Dlpf::Bw94Hz),
            3 => Some(Dlpf::Bw44Hz),
            4 => Some(Dlpf::Bw21Hz),
            5 => Some(Dlpf::Bw10Hz),
            6 => Some(Dlpf::Bw5Hz),
            _ => None,
        }
    }

    /// Accelerometer bandwidth, Hz.
    pub const fn accel_bandwidth_hz(self) -> u16 {
        [260, 184, 94, 44, 21, 10, 5][self.cfg() as usize]
    }

    /// The accelerometer filter's delay, µs (register map §4.3, CONFIG's
    /// table): 0, 2.0, 3.0, 4.9, 8.5, 13.8 and 19.0 ms.
    pub const fn accel_delay_us(self) -> u32 {
        [0, 2000, 3000, 4900, 8500, 13_800, 19_000][self.cfg() as usize]
    }

    /// The gyroscope filter's delay, µs (register map §4.3, CONFIG's
    /// table): 0.98, 1.9, 2.8, 4.8, 8.3, 13.4 and 18.6 ms. With the filter
    /// off the gyroscope is 0.98 ms behind the accelerometer; at every
    /// other setting it is 0.1–0.4 ms ahead.
    pub const fn gyro_delay_us(self) -> u32 {
        [980, 1900, 2800, 4800, 8300, 13_400, 18_600][self.cfg() as usize]
    }

    /// Gyroscope output rate, Hz: 8000 with the filter off (DLPF_CFG = 0), else 1000.
    pub const fn gyro_output_rate_hz(self) -> u16 {
        if self.cfg() == 0 { 8000 } else { 1000 }
    }
}

/// The measurement configuration, written to registers 25–28 in one burst.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Config {
    /// Accelerometer full scale.
    pub accel_range: AccelRange,
    /// Gyroscope full scale.
    pub gyro_range: GyroRange,
    /// Digital low-pass filter.
    pub dlpf: Dlpf,
    /// SMPLRT_DIV: sample rate = gyro output rate / (1 + divider).
    pub sample_rate_divider: u8,
}

impl Config {
    /// The registers' values after power-on or reset (all zero: ±2 g, ±250 °/s,
    /// filter off, divider 0 — 8 kHz gyro, the accelerometer at 1 kHz).
    pub const POWER_ON: Config = Config {
        accel_range: AccelRange::G2,
        gyro_range: GyroRange::Dps250,
        dlpf: Dlpf::Bw260Hz,
        sample_rate_divider: 0,
    };

    /// Sample rate, Hz: gyro output rate / (1 + SMPLRT_DIV) (register map §4.2).
    pub fn sample_rate_hz(&self) -> f64 {
        f64::from(self.dlpf.gyro_output_rate_hz()) / (1.0 + f64::from(self.sample_rate_divider))
    }

    /// How far behind the instant they are read the accelerometer's and the
    /// gyroscope's data registers stand, s: each filter's delay
    /// ([`Dlpf::accel_delay_us`], [`Dlpf::gyro_delay_us`]) and, read at
    /// times not tied to the sensor's sample clock, half the period at which
    /// the registers take a new sample (on average that old): the sample
    /// rate's, and for the accelerometer at most its own 1 kHz. Read on the
    /// data-ready flag (`synced`) the registers are fresh.
    pub fn data_delays_s(&self, synced: bool) -> [f64; 2] {
        let fs = self.sample_rate_hz();
        let age = |rate: f64| if synced { 0.0 } else { 0.5 / rate };
        [
            f64::from(self.dlpf.accel_delay_us()) * 1e-6 + age(fs.min(1000.0)),
            f64::from(self.dlpf.gyro_delay_us()) * 1e-6 + age(fs),
        ]
    }

    /// The divider that gives exactly `rate_hz` with this configuration's
    /// filter, `None` when no divider 0..=255 does (e.g. 300 Hz from 1 kHz).
    pub fn divider_for(&self, rate_hz: u16) -> Option<u8> {
        let out = self.dlpf.gyro_output_rate_hz();
        if rate_hz == 0 || out % rate_hz != 0 {
            return None;
        }
        u8::try_from(out / rate_hz - 1).ok()
    }
}

impl Default for Config {
    /// ±2 g, ±250 °/s (the source instrument's ranges), 44 Hz bandwidth, 100 Hz.
    fn default() -> Self {
        Config {
            accel_range: AccelRange::G2,
            gyro_range: GyroRange::Dps250,
            dlpf: Dlpf::Bw44Hz,
            sample_rate_divider: 9,
        }
    }
}

/// The 14 data registers as read: raw counts in register order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
pub struct RawSample {
    /// ACCEL_XOUT, ACCEL_YOUT, ACCEL_ZOUT.
    pub accel: [i16; 3],
    /// TEMP_OUT.
    pub temp: i16,
    /// GYRO_XOUT, GYRO_YOUT, GYRO_ZOUT.
    pub gyro: [i16; 3],
}

impl RawSample {
    /// Decode registers 59–72 (each value big-endian, high byte first).
    pub const fn from_be_bytes(b: &[u8; 14]) -> Self {
        const fn word(b: &[u8; 14], i: usize) -> i16 {
            i16::from_be_bytes([b[2 * i], b[2 * i + 1]])
        }
        RawSample {
            accel: [word(b, 0), word(b, 1), word(b, 2)],
            temp: word(b, 3),
            gyro: [word(b, 4), word(b, 5), word(b, 6)],
        }
    }

    /// The registers' bytes (the inverse of [`RawSample::from_be_bytes`]).
    pub const fn to_be_bytes(&self) -> [u8; 14] {
        let v = [
            self.accel[0],
            self.accel[1],
            self.accel[2],
            self.temp,
            self.gyro[0],
            self.gyro[1],
            self.gyro[2],
        ];
        let mut b = [0u8; 14];
        let mut i = 0;
        while i < 7 {
            let [h, l] = v[i].to_be_bytes();
            b[2 * i] = h;
            b[2 * i + 1] = l;
            i += 1;
        }
        b
    }

    /// SI units at the ranges of `config`:
    /// a = counts / (LSB/g) · g0 (m/s²), ω = counts / (LSB/(°/s)) · π/180 (rad/s),
    /// T = counts / 340 + 36.53 (°C) (product specification §6.1, §6.2, §6.4).
    pub fn to_si(&self, config: &Config) -> Measurement {
        let a = config.accel_range.lsb_per_g();
        let g = config.gyro_range.lsb_per_dps();
        let acc = |c: i16| f64::from(c) / a * G0;
        let gyr = |c: i16| f64::from(c) / g * (core::f64::consts::PI / 180.0);
        Measurement {
            acc_m_s2: self.accel.map(acc),
            gyr_rad_s: self.gyro.map(gyr),
            temp_c: temperature_c(self.temp),
        }
    }
}

/// Die temperature, °C, of TEMP_OUT `raw`: raw / 340 + 36.53 (register map §4.18).
pub fn temperature_c(raw: i16) -> f64 {
    f64::from(raw) / 340.0 + 36.53
}

/// One reading in SI units, sensor axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement {
    /// Specific force, m/s² (level at rest: (0, 0, +g)).
    pub acc_m_s2: [f64; 3],
    /// Angular rate, rad/s.
    pub gyr_rad_s: [f64; 3],
    /// Die temperature, °C.
    pub temp_c: f64,
}

/// What went wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Error<E> {
    /// The I²C bus failed (no acknowledge, arbitration loss, …: the HAL's error says which).
    I2c(E),
    /// WHO_AM_I read this value instead of [`WHO_AM_I_MPU6050`]: another chip
    /// (an MPU6500 reads 0x70, an MPU9250 0x71) or a bus fault.
    WrongDevice(u8),
}

impl<E: core::fmt::Debug> core::fmt::Display for Error<E> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Error::I2c(e) => write!(f, "MPU6050: I2C bus error: {e:?}"),
            Error::WrongDevice(id) => write!(
                f,
                "MPU6050: WHO_AM_I reads {id:#04x}, expected {WHO_AM_I_MPU6050:#04x} (not an MPU6050?)"
            ),
        }
    }
}

impl<E: core::fmt::Debug> core::error::Error for Error<E> {}

/// The driver: an I²C bus, the chip's address and the configuration last written.
#[derive(Debug)]
pub struct Mpu6050<I2C> {
    i2c: I2C,
    address: u8,
    config: Config,
}

impl<I2C: I2c> Mpu6050<I2C> {
    /// A driver for the chip at `address` on `i2c`. Nothing is sent until
    /// [`Mpu6050::init`]; the configuration is assumed to be [`Config::POWER_ON`].
    pub fn new(i2c: I2C, address: Address) -> Self {
        Mpu6050 {
            i2c,
            address: address.addr(),
            config: Config::POWER_ON,
        }
    }

    /// The bus back.
    pub fn release(self) -> I2C {
        self.i2c
    }

    /// The configuration last written successfully.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Read WHO_AM_I.
    pub fn who_am_i(&mut self) -> Result<u8, Error<I2C::Error>> {
        self.read_register(register::WHO_AM_I)
    }

    /// Check the chip, reset it and start it measuring with `config`:
    ///
    /// 1. WHO_AM_I must read 0x68 (else [`Error::WrongDevice`], nothing written);
    /// 2. PWR_MGMT_1 ← 0x80 (DEVICE_RESET), then wait [`RESET_DELAY_MS`];
    /// 3. PWR_MGMT_1 ← 0x01 (awake, clock from the PLL on the X gyro, which
    ///    the register map §4.28 recommends over the internal oscillator);
    /// 4. registers 25–28 ← `config` ([`Mpu6050::configure`]);
    /// 5. INT_ENABLE ← 0x01 (DATA_RDY_EN: the INT pin and [`Mpu6050::data_ready`]).
    pub fn init(
        &mut self,
        config: &Config,
        delay: &mut impl DelayNs,
    ) -> Result<(), Error<I2C::Error>> {
        let id = self.who_am_i()?;
        if id != WHO_AM_I_MPU6050 {
            return Err(Error::WrongDevice(id));
        }
        self.write_register(register::PWR_MGMT_1, 0x80)?;
        self.config = Config::POWER_ON;
        delay.delay_ms(RESET_DELAY_MS);
        self.write_register(register::PWR_MGMT_1, 0x01)?;
        self.configure(config)?;
        self.write_register(register::INT_ENABLE, 0x01)
    }

    /// Write SMPLRT_DIV, CONFIG, GYRO_CONFIG and ACCEL_CONFIG in one burst
    /// (the chip auto-increments the register address). On a bus error the
    /// remembered configuration is left as it was.
    pub fn configure(&mut self, config: &Config) -> Result<(), Error<I2C::Error>> {
        let frame = [
            register::SMPLRT_DIV,
            config.sample_rate_divider,
            config.dlpf.cfg(),
            config.gyro_range.fs_sel() << 3,
            config.accel_range.afs_sel() << 3,
        ];
        self.i2c.write(self.address, &frame).map_err(Error::I2c)?;
        self.config = *config;
        Ok(())
    }

    /// True when a new sample is in the data registers (INT_STATUS.DATA_RDY_INT;
    /// reading clears it).
    pub fn data_ready(&mut self) -> Result<bool, Error<I2C::Error>> {
        Ok(self.read_register(register::INT_STATUS)? & 0x01 != 0)
    }

    /// Burst-read the 14 data registers (one I²C write-read from ACCEL_XOUT_H).
    pub fn read_raw(&mut self) -> Result<RawSample, Error<I2C::Error>> {
        let mut b = [0u8; 14];
        self.i2c
            .write_read(self.address, &[register::ACCEL_XOUT_H], &mut b)
            .map_err(Error::I2c)?;
        Ok(RawSample::from_be_bytes(&b))
    }

    /// [`Mpu6050::read_raw`] converted to SI at the configured ranges.
    pub fn read(&mut self) -> Result<Measurement, Error<I2C::Error>> {
        Ok(self.read_raw()?.to_si(&self.config))
    }

    fn read_register(&mut self, reg: u8) -> Result<u8, Error<I2C::Error>> {
        let mut b = [0u8; 1];
        self.i2c
            .write_read(self.address, &[reg], &mut b)
            .map_err(Error::I2c)?;
        Ok(b[0])
    }

    fn write_register(&mut self, reg: u8, value: u8) -> Result<(), Error<I2C::Error>> {
        self.i2c
            .write(self.address, &[reg, value])
            .map_err(Error::I2c)
    }
}
