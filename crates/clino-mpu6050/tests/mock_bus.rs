//! The driver against a scripted I²C bus (`embedded-hal-mock`, eh1): every
//! transaction the driver makes must be the one scripted, in order, and no
//! scripted transaction may be left over (`done()`).

use clino_mpu6050::{
    AccelRange, Address, Config, Dlpf, Error, G0, GyroRange, Mpu6050, RawSample, register,
};
use embedded_hal::i2c::{Error as _, ErrorKind, NoAcknowledgeSource};
use embedded_hal_mock::eh1::delay::NoopDelay;
use embedded_hal_mock::eh1::i2c::{Mock, Transaction as T};

const A: u8 = 0x68;

fn cfg() -> Config {
    Config {
        accel_range: AccelRange::G4,
        gyro_range: GyroRange::Dps500,
        dlpf: Dlpf::Bw44Hz,
        sample_rate_divider: 9,
    }
}

#[test]
fn init_sequence_checks_resets_wakes_configures_and_enables_data_ready() {
    let script = [
        T::write_read(A, vec![0x75], vec![0x68]),
        T::write(A, vec![0x6B, 0x80]),
        T::write(A, vec![0x6B, 0x01]),
        // SMPLRT_DIV=9, CONFIG=3, GYRO_CONFIG=FS_SEL 1<<3, ACCEL_CONFIG=AFS_SEL 1<<3
        T::write(A, vec![0x19, 9, 3, 0x08, 0x08]),
        T::write(A, vec![0x38, 0x01]),
    ];
    let mut bus = Mock::new(&script);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0Low);
    assert_eq!(*imu.config(), Config::POWER_ON);
    imu.init(&cfg(), &mut NoopDelay::new()).unwrap();
    assert_eq!(*imu.config(), cfg());
    assert_eq!(imu.config().sample_rate_hz(), 100.0);
    bus.done();
}

#[test]
fn every_range_lands_in_its_register_bits() {
    let c = Config {
        accel_range: AccelRange::G16,
        gyro_range: GyroRange::Dps2000,
        dlpf: Dlpf::Bw260Hz,
        sample_rate_divider: 7,
    };
    let mut bus = Mock::new(&[T::write(0x69, vec![0x19, 7, 0, 0x18, 0x18])]);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0High);
    imu.configure(&c).unwrap();
    // 8 kHz gyro output with the filter off, / (1 + 7)
    assert_eq!(imu.config().sample_rate_hz(), 1000.0);
    bus.done();
}

/// Registers 59–72 of a known state, big-endian, with signs and extremes.
const BURST: [u8; 14] = [
    0x40, 0x00, // ax = +16384
    0xC0, 0x00, // ay = -16384
    0x7F, 0xFF, // az = +32767
    0xF8, 0x30, // temp = -2000
    0x00, 0x83, // gx = +131
    0xFF, 0x7D, // gy = -131
    0x80, 0x00, // gz = -32768
];

#[test]
fn burst_read_decodes_big_endian_counts_in_register_order() {
    let mut bus = Mock::new(&[T::write_read(
        A,
        vec![register::ACCEL_XOUT_H],
        BURST.to_vec(),
    )]);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0Low);
    let raw = imu.read_raw().unwrap();
    assert_eq!(
        raw,
        RawSample {
            accel: [16384, -16384, 32767],
            temp: -2000,
            gyro: [131, -131, -32768],
        }
    );
    assert_eq!(raw.to_be_bytes(), BURST);
    bus.done();
}

#[test]
fn burst_read_converts_to_si_at_the_configured_ranges() {
    // POWER_ON ranges (±2 g: 16384 LSB/g, ±250 °/s: 131 LSB/(°/s)) until configured
    let mut bus = Mock::new(&[
        T::write_read(A, vec![0x3B], BURST.to_vec()),
        T::write(A, vec![0x19, 9, 3, 0x08, 0x08]),
        T::write_read(A, vec![0x3B], BURST.to_vec()),
    ]);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0Low);
    let m = imu.read().unwrap();
    assert_eq!(m.acc_m_s2[0], G0); // exactly 1 g
    assert_eq!(m.acc_m_s2[1], -G0);
    assert!((m.acc_m_s2[2] - 32767.0 / 16384.0 * 9.80665).abs() < 1e-12);
    assert!((m.gyr_rad_s[0] - 1f64.to_radians()).abs() < 1e-15); // exactly 1 °/s
    assert!((m.gyr_rad_s[1] + 1f64.to_radians()).abs() < 1e-15);
    assert!((m.gyr_rad_s[2] + 32768.0 / 131.0 * core::f64::consts::PI / 180.0).abs() < 1e-12);
    // −2000 / 340 + 36.53 = 36.53 − 5.882 352 9… = 30.647 647 0… °C
    assert!((m.temp_c - 30.647_647_058_823_53).abs() < 1e-9);

    imu.configure(&cfg()).unwrap(); // ±4 g (8192 LSB/g), ±500 °/s (65.5 LSB/(°/s))
    let m = imu.read().unwrap();
    assert_eq!(m.acc_m_s2[0], 2.0 * G0);
    assert!((m.gyr_rad_s[0] - (131.0 / 65.5f64).to_radians()).abs() < 1e-15);
    bus.done();
}

#[test]
fn a_nack_is_the_bus_error_kind_and_leaves_the_config_alone() {
    let nack = ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address);
    let mut bus = Mock::new(&[
        T::write_read(A, vec![0x3B], vec![0; 14]).with_error(nack),
        T::write(A, vec![0x19, 9, 3, 0x08, 0x08]).with_error(nack),
        T::write_read(A, vec![0x75], vec![0]).with_error(nack),
    ]);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0Low);
    let e = imu.read_raw().unwrap_err();
    assert_eq!(e, Error::I2c(nack));
    let Error::I2c(k) = e else { unreachable!() };
    assert_eq!(
        k.kind(),
        ErrorKind::NoAcknowledge(NoAcknowledgeSource::Address)
    );

    assert_eq!(imu.configure(&cfg()), Err(Error::I2c(nack)));
    assert_eq!(*imu.config(), Config::POWER_ON);

    // a chip that does not answer at all stops init at the first transaction
    assert_eq!(
        imu.init(&cfg(), &mut NoopDelay::new()),
        Err(Error::I2c(nack))
    );
    bus.done();
}

#[test]
fn wrong_who_am_i_is_refused_before_anything_is_written() {
    // an MPU6500 answers 0x70: init must stop with it, writing nothing
    let mut bus = Mock::new(&[T::write_read(A, vec![0x75], vec![0x70])]);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0Low);
    let e = imu.init(&cfg(), &mut NoopDelay::new()).unwrap_err();
    assert_eq!(e, Error::WrongDevice(0x70));
    assert_eq!(
        e.to_string(),
        "MPU6050: WHO_AM_I reads 0x70, expected 0x68 (not an MPU6050?)"
    );
    assert_eq!(*imu.config(), Config::POWER_ON);
    bus.done();
}

#[test]
fn data_ready_reads_bit_0_of_int_status() {
    let mut bus = Mock::new(&[
        T::write_read(A, vec![0x3A], vec![0x00]),
        T::write_read(A, vec![0x3A], vec![0x01]),
        T::write_read(A, vec![0x3A], vec![0x10]), // FIFO_OFLOW only
    ]);
    let mut imu = Mpu6050::new(bus.clone(), Address::Ad0Low);
    assert!(!imu.data_ready().unwrap());
    assert!(imu.data_ready().unwrap());
    assert!(!imu.data_ready().unwrap());
    bus.done();
}

#[test]
fn sample_rate_dividers() {
    let c = cfg(); // filter on: 1 kHz gyro output
    assert_eq!(c.divider_for(100), Some(9));
    assert_eq!(c.divider_for(1000), Some(0));
    assert_eq!(c.divider_for(4), Some(249));
    assert_eq!(c.divider_for(300), None); // 1000/300 is not an integer
    assert_eq!(c.divider_for(2), None); // divider 499 > 255
    assert_eq!(c.divider_for(0), None);
    let off = Config {
        dlpf: Dlpf::Bw260Hz,
        ..c
    };
    assert_eq!(off.divider_for(8000), Some(0));
    assert_eq!(off.divider_for(1000), Some(7));
}

#[test]
fn data_delays_are_the_filters_and_half_the_register_period() {
    // register map §4.3: with the filter off the gyro is 0.98 ms behind the
    // accelerometer (0 ms); at 44 Hz / 42 Hz they are 4.9 and 4.8 ms
    let at = |dlpf, hz| {
        let mut c = Config { dlpf, ..cfg() };
        c.sample_rate_divider = c.divider_for(hz).unwrap();
        c
    };
    let close =
        |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
    // read on the data-ready flag: the filters' delays alone
    let d = at(Dlpf::Bw260Hz, 8000).data_delays_s(true);
    assert!(close(d, [0.0, 0.98e-3]), "{d:?}");
    let d = at(Dlpf::Bw44Hz, 100).data_delays_s(true);
    assert!(close(d, [4.9e-3, 4.8e-3]), "{d:?}");
    // read on a clock of its own: half a register period more, the
    // accelerometer's at most its own 1 kHz (8 kHz gyro: 0.0625 ms)
    let d = at(Dlpf::Bw260Hz, 8000).data_delays_s(false);
    assert!(close(d, [0.5e-3, 0.98e-3 + 0.0625e-3]), "{d:?}");
    let d = at(Dlpf::Bw44Hz, 1000).data_delays_s(false);
    assert!(close(d, [5.4e-3, 5.3e-3]), "{d:?}");
    let d = at(Dlpf::Bw5Hz, 100).data_delays_s(false);
    assert!(close(d, [24.0e-3, 23.6e-3]), "{d:?}");
    // every setting: the gyro within 0.4 ms of the accelerometer but at 0
    for k in 1..=6 {
        let f = Dlpf::from_cfg(k).unwrap();
        let lag = f64::from(f.gyro_delay_us()) - f64::from(f.accel_delay_us());
        assert!((-400.0..0.0).contains(&lag), "{k}: {lag} µs");
    }
}

#[test]
fn protocol_values_round_trip() {
    for g in [2, 4, 8, 16] {
        assert_eq!(AccelRange::from_g(g).unwrap().g(), g);
    }
    for d in [250, 500, 1000, 2000] {
        assert_eq!(GyroRange::from_dps(d).unwrap().dps(), d);
    }
    for k in 0..=6 {
        assert_eq!(Dlpf::from_cfg(k).unwrap().cfg(), k);
    }
    assert_eq!(AccelRange::from_g(3), None);
    assert_eq!(GyroRange::from_dps(300), None);
    assert_eq!(Dlpf::from_cfg(7), None);
    assert_eq!(Address::from_addr(0x69), Some(Address::Ad0High));
    assert_eq!(Address::from_addr(0x1E), None);
    // sensitivities: 16384 / 2^AFS_SEL; the gyro's are the datasheet's rounded values
    for r in [
        AccelRange::G2,
        AccelRange::G4,
        AccelRange::G8,
        AccelRange::G16,
    ] {
        assert_eq!(r.lsb_per_g() * f64::from(r.g()), 32768.0);
    }
    assert_eq!(Dlpf::Bw5Hz.accel_bandwidth_hz(), 5);
}
