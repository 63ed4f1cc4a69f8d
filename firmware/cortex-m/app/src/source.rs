//! Samples from the MPU6050: one burst read, time-stamped by a microsecond clock.

use clino_core::{ImuSample, Vec3};
use clino_mpu6050::{Error, Mpu6050, RawSample};
use embedded_hal::i2c::I2c;

/// A free-running microsecond counter that wraps at 2³² (a timer on the board).
pub trait MicrosClock {
    /// Microseconds since boot, modulo 2³².
    fn now_us(&mut self) -> u32;
}

/// One reading: the raw counts (what a SAMPLE frame carries), the board time
/// stamp, and the sample in SI units for the pipeline.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// The 14 data registers.
    pub raw: RawSample,
    /// Board time, µs, wrapping (the SAMPLE frame's `t_us`).
    pub t_us: u32,
    /// The sample in SI units; `t_s` is the unwrapped time · 1e-6 (as the host computes it).
    pub sample: ImuSample,
}

/// The MPU6050 as a sample source.
#[derive(Debug)]
pub struct Mpu6050Source<I2C, C> {
    imu: Mpu6050<I2C>,
    clock: C,
    last_us: Option<u32>,
    total_us: u64,
}

impl<I2C: I2c, C: MicrosClock> Mpu6050Source<I2C, C> {
    /// Samples from `imu` (initialised) stamped by `clock`.
    pub fn new(imu: Mpu6050<I2C>, clock: C) -> Self {
        Mpu6050Source {
            imu,
            clock,
            last_us: None,
            total_us: 0,
        }
    }

    /// The driver (to reconfigure it, or poll its data-ready flag).
    pub fn imu(&mut self) -> &mut Mpu6050<I2C> {
        &mut self.imu
    }

    /// Read one sample: the clock, then the burst of 14 registers, converted
    /// at the driver's configured ranges. Time is unwrapped across the clock's
    /// 2³² µs (71.6 min) wrap: t = t_prev + (now − now_prev) mod 2³².
    pub fn read(&mut self) -> Result<Reading, Error<I2C::Error>> {
        let t_us = self.clock.now_us();
        let raw = self.imu.read_raw()?;
        if let Some(prev) = self.last_us {
            self.total_us += u64::from(t_us.wrapping_sub(prev));
        } else {
            self.total_us = u64::from(t_us);
        }
        self.last_us = Some(t_us);
        let m = raw.to_si(self.imu.config());
        let [gx, gy, gz] = m.gyr_rad_s;
        let [ax, ay, az] = m.acc_m_s2;
        let mut sample = ImuSample::new(
            self.total_us as f64 * 1e-6,
            Vec3::new(gx, gy, gz),
            Vec3::new(ax, ay, az),
        );
        sample.temp_c = Some(m.temp_c);
        Ok(Reading { raw, t_us, sample })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clino_mpu6050::{Address, G0};
    use embedded_hal_mock::eh1::i2c::{Mock, Transaction as T};
    extern crate std;
    use std::vec;

    struct Script(&'static [u32], usize);
    impl MicrosClock for Script {
        fn now_us(&mut self) -> u32 {
            self.1 += 1;
            self.0[self.1 - 1]
        }
    }

    #[test]
    fn time_unwraps_across_the_32_bit_wrap_and_counts_convert() {
        let level = RawSample {
            accel: [0, 0, 16384],
            temp: 340,
            gyro: [131, 0, 0],
        }
        .to_be_bytes();
        let bus = Mock::new(&[
            T::write_read(0x68, vec![0x3B], level.to_vec()),
            T::write_read(0x68, vec![0x3B], level.to_vec()),
            T::write_read(0x68, vec![0x3B], level.to_vec()),
        ]);
        let clock = Script(&[u32::MAX - 4_999, 5_000, 15_000], 0);
        let mut src = Mpu6050Source::new(Mpu6050::new(bus.clone(), Address::Ad0Low), clock);
        let a = src.read().unwrap();
        let b = src.read().unwrap();
        let c = src.read().unwrap();
        assert_eq!(a.t_us, u32::MAX - 4_999);
        assert_eq!(b.t_us, 5_000);
        // 4 294 962 296 µs, then +10 000 across the wrap, then +10 000
        assert_eq!(a.sample.t_s, 4_294_962_296.0 * 1e-6);
        assert_eq!(b.sample.t_s, 4_294_972_296.0 * 1e-6);
        assert_eq!(c.sample.t_s, 4_294_982_296.0 * 1e-6);
        assert_eq!(a.sample.acc_m_s2, Vec3::new(0.0, 0.0, G0));
        assert!((a.sample.gyr_rad_s.x - 1f64.to_radians()).abs() < 1e-15);
        assert!((a.sample.temp_c.unwrap() - 37.53).abs() < 1e-12); // 340/340 + 36.53
        src.imu.release().done();
    }
}
