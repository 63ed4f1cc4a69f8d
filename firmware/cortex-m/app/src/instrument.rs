//! The instrument: one sample through the pipeline, roll and pitch on the dials.
//!
//! [`Instrument::step`] is the whole per-sample work of the firmware: the
//! sample goes through `clino_core::Pipeline` (calibrate → lever arm →
//! filter → tilt; the `dynamic` filter unless told otherwise) and the
//! aerospace roll and pitch of the new attitude turn the two dials. While the
//! host sends dial angles (protocol SET_DIALS, at least one every
//! [`HOST_DIALS_TIMEOUT_S`]) the dials show those instead.
//! [`live_step`] is the loop body of a board: poll the MPU6050, read, step,
//! send the SAMPLE frame.

use crate::dials::Dial;
use crate::serial::{Frame, send_frame};
use crate::source::{MicrosClock, Mpu6050Source, Reading};
use clino_core::filter::FilterSpec;
use clino_core::pipeline::{Output, Pipeline, SensorRange};
use clino_core::{ImuSample, tilt::RollPitch};
use embedded_hal::i2c::I2c;
use embedded_hal::pwm::SetDutyCycle;

/// How long host dial angles hold without a new one, s (protocol: "at least one every 2 s").
pub const HOST_DIALS_TIMEOUT_S: f64 = 2.0;

/// Pipeline and dials.
#[derive(Debug)]
pub struct Instrument<R, P> {
    pipeline: Pipeline,
    roll: Dial<R>,
    pitch: Dial<P>,
    host: Option<(f64, f64, f64)>,
    dial_faults: u32,
}

impl<R: SetDutyCycle, P: SetDutyCycle> Instrument<R, P> {
    /// An instrument running `pipeline`, roll on `roll`, pitch on `pitch`.
    pub fn new(pipeline: Pipeline, roll: Dial<R>, pitch: Dial<P>) -> Self {
        Instrument {
            pipeline,
            roll,
            pitch,
            host: None,
            dial_faults: 0,
        }
    }

    /// The source instrument's set-up with clino's filter: the `dynamic`
    /// filter at its defaults, no calibration, no lever arm. The board
    /// stamps each sample with its own timer as it reads it: the stamps are
    /// the sampling's own, so each step is taken from them
    /// (`Pipeline::with_sample_clock(false)`; the sample clock recovers
    /// stamps a host made, and would cost the board time for nothing).
    pub fn dynamic(roll: Dial<R>, pitch: Dial<P>) -> Self {
        Self::new(
            Pipeline::new(FilterSpec::default()).with_sample_clock(false),
            roll,
            pitch,
        )
    }

    /// [`Instrument::dynamic`] for an MPU6050 read at `config`'s full-scale
    /// ranges: a reading at a range is clipped, counted, and the filter is
    /// told (`Pipeline::with_sensor_range`; the power-on ±250 °/s and ±2 g
    /// are exceeded by a brisk hand).
    pub fn dynamic_at(config: &clino_mpu6050::Config, roll: Dial<R>, pitch: Dial<P>) -> Self {
        let range = SensorRange::from_full_scale(
            f64::from(config.accel_range.g()),
            f64::from(config.gyro_range.dps()),
        );
        Self::new(
            Pipeline::new(FilterSpec::default())
                .with_sensor_range(range)
                .with_sample_clock(false),
            roll,
            pitch,
        )
    }

    /// The pipeline (its counts, attitude, tilt).
    pub fn pipeline(&self) -> &Pipeline {
        &self.pipeline
    }

    /// The roll dial.
    pub fn roll_dial(&self) -> &Dial<R> {
        &self.roll
    }

    /// The pitch dial.
    pub fn pitch_dial(&self) -> &Dial<P> {
        &self.pitch
    }

    /// Times a PWM channel refused a duty cycle (the sample was still processed).
    pub fn dial_faults(&self) -> u32 {
        self.dial_faults
    }

    /// Angles from the host (SET_DIALS), received at sample time `t_s`.
    pub fn set_host_dials(&mut self, roll_rad: f64, pitch_rad: f64, t_s: f64) {
        self.host = Some((roll_rad, pitch_rad, t_s));
    }

    /// Process one sample: the pipeline, then the dials.
    pub fn step(&mut self, sample: &ImuSample) -> Output {
        let out = self.pipeline.update(sample);
        let shown = match self.host {
            Some((r, p, t)) if sample.t_s - t <= HOST_DIALS_TIMEOUT_S => Some((r, p)),
            _ => out.attitude.as_ref().map(|q| {
                let rp = RollPitch::from_attitude(q);
                (rp.roll, rp.pitch)
            }),
        };
        if let Some((r, p)) = shown {
            if self.roll.show(r).is_err() {
                self.dial_faults += 1;
            }
            if self.pitch.show(p).is_err() {
                self.dial_faults += 1;
            }
        }
        out
    }
}

/// What one pass of a board's loop did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LiveStep {
    /// No new sample in the sensor yet.
    NotReady,
    /// A sample was read and processed; `sent` tells whether its frame went out.
    Sample {
        /// The reading.
        reading: Reading,
        /// The pipeline's output.
        output: Output,
        /// True when the SAMPLE frame was written.
        sent: bool,
    },
}

/// One pass of a board's main loop: if the MPU6050 has a new sample, read
/// it, run the instrument and send the SAMPLE frame numbered `*seq` (then
/// advanced, wrapping). An I²C error is returned as is (the caller counts it
/// and goes on); a failed serial write is returned as `Err(Right)`.
#[allow(clippy::type_complexity)]
pub fn live_step<I2C, C, R, P, W>(
    source: &mut Mpu6050Source<I2C, C>,
    instrument: &mut Instrument<R, P>,
    tx: &mut W,
    seq: &mut u16,
) -> Result<LiveStep, LiveError<clino_mpu6050::Error<I2C::Error>, W::Error>>
where
    I2C: I2c,
    C: MicrosClock,
    R: SetDutyCycle,
    P: SetDutyCycle,
    W: embedded_io::Write,
{
    if !source.imu().data_ready().map_err(LiveError::Sensor)? {
        return Ok(LiveStep::NotReady);
    }
    let reading = source.read().map_err(LiveError::Sensor)?;
    let output = instrument.step(&reading.sample);
    let frame = Frame::Sample {
        seq: *seq,
        t_us: reading.t_us,
        raw: reading.raw,
    };
    *seq = seq.wrapping_add(1);
    let sent = send_frame(tx, &frame).map_err(LiveError::Serial)?;
    Ok(LiveStep::Sample {
        reading,
        output,
        sent,
    })
}

/// Why [`live_step`] failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LiveError<S, W> {
    /// The sensor (I²C) failed.
    Sensor(S),
    /// The serial link failed.
    Serial(W),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dials::ServoTiming;
    use clino_core::pipeline::Status;
    use clino_core::{G0, Vec3};
    use clino_mpu6050::{Address, Mpu6050, RawSample};
    use embedded_hal_mock::eh1::i2c::{Mock as I2cMock, Transaction as T};
    extern crate std;
    use std::vec;
    use std::vec::Vec;

    /// A PWM channel that keeps its duty (max 20 000: one count per µs).
    #[derive(Debug, Default)]
    struct Pwm(u16);
    impl embedded_hal::pwm::ErrorType for Pwm {
        type Error = core::convert::Infallible;
    }
    impl SetDutyCycle for Pwm {
        fn max_duty_cycle(&self) -> u16 {
            20_000
        }
        fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
            self.0 = duty;
            Ok(())
        }
    }

    fn instrument() -> Instrument<Pwm, Pwm> {
        let t = ServoTiming::default();
        Instrument::dynamic(Dial::new(Pwm(0), t), Dial::new(Pwm(0), t))
    }

    #[test]
    fn a_still_tilted_sensor_turns_the_dials_to_its_roll_and_pitch() {
        // at rest with roll 30°, pitch −20° (aerospace z-y-x): specific force
        // f_b = g·(−sin θ, sin φ cos θ, cos φ cos θ)
        let (r, p) = (30f64.to_radians(), -20f64.to_radians());
        let f = Vec3::new(-p.sin(), r.sin() * p.cos(), r.cos() * p.cos()) * G0;
        let mut ins = instrument();
        for k in 0..50 {
            let out = ins.step(&ImuSample::new(k as f64 * 0.01, Vec3::zeros(), f));
            assert_eq!(
                out.status,
                if k == 0 {
                    Status::Initialised
                } else {
                    Status::Fused
                }
            );
        }
        let t = ServoTiming::default();
        assert_eq!(ins.roll_dial().pulse_us(), t.pulse_us(r));
        assert_eq!(ins.pitch_dial().pulse_us(), t.pulse_us(p));
        // 30° → 1781 µs, −20° → 544 + 70/180·1856 = 1265.8 → 1266 µs
        assert_eq!(ins.roll_dial().pulse_us(), Some(1781));
        assert_eq!(ins.pitch_dial().pulse_us(), Some(1266));

        // host angles take over for 2 s, then the filter again
        ins.set_host_dials(0.0, 0.0, 0.5);
        ins.step(&ImuSample::new(0.51, Vec3::zeros(), f));
        assert_eq!(ins.roll_dial().pulse_us(), Some(1472));
        ins.step(&ImuSample::new(2.6, Vec3::zeros(), f));
        assert_eq!(ins.roll_dial().pulse_us(), Some(1781));
    }

    #[test]
    fn a_reading_at_the_configured_range_is_counted_as_clipped() {
        // ±2 g, ±250 °/s: the gyro's rail (32767 counts at 131 LSB/(°/s)) is
        // clipped; the same reading at ±2000 °/s is not
        let t = ServoTiming::default();
        let rail = (32767.0f64 / 131.0).to_radians();
        for (gyro_range, clipped) in [
            (clino_mpu6050::GyroRange::Dps250, 1),
            (clino_mpu6050::GyroRange::Dps2000, 0),
        ] {
            let config = clino_mpu6050::Config {
                gyro_range,
                ..Default::default()
            };
            let mut ins =
                Instrument::dynamic_at(&config, Dial::new(Pwm(0), t), Dial::new(Pwm(0), t));
            let f = Vec3::new(0.0, 0.0, G0);
            ins.step(&ImuSample::new(0.0, Vec3::zeros(), f));
            let out = ins.step(&ImuSample::new(0.01, Vec3::new(rail, 0.0, 0.0), f));
            assert_eq!(out.status, Status::Fused);
            assert_eq!(ins.pipeline().counts().gyro_clipped, clipped);
        }
    }

    #[test]
    fn no_dial_moves_before_the_filter_has_an_attitude() {
        let mut ins = instrument();
        let out = ins.step(&ImuSample::new(0.0, Vec3::zeros(), Vec3::zeros()));
        assert_eq!(out.status, Status::Waiting);
        assert_eq!(ins.roll_dial().pulse_us(), None);
    }

    struct Clock(u32);
    impl MicrosClock for Clock {
        fn now_us(&mut self) -> u32 {
            self.0 += 10_000;
            self.0
        }
    }

    /// A UART that keeps what is written.
    #[derive(Default)]
    struct Wire {
        bytes: Vec<u8>,
    }

    impl embedded_io::ErrorType for Wire {
        type Error = core::convert::Infallible;
    }

    impl embedded_io::Write for Wire {
        fn write(&mut self, b: &[u8]) -> Result<usize, Self::Error> {
            self.bytes.extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> Result<(), Self::Error> {
            Ok(())
        }
    }

    #[test]
    fn live_step_polls_reads_steps_and_numbers_frames() {
        let level = RawSample {
            accel: [0, 0, 16384],
            temp: 0,
            gyro: [0, 0, 0],
        }
        .to_be_bytes()
        .to_vec();
        let nack = embedded_hal::i2c::ErrorKind::NoAcknowledge(
            embedded_hal::i2c::NoAcknowledgeSource::Data,
        );
        let bus = I2cMock::new(&[
            T::write_read(0x68, vec![0x3A], vec![0]),
            T::write_read(0x68, vec![0x3A], vec![1]),
            T::write_read(0x68, vec![0x3B], level.clone()),
            T::write_read(0x68, vec![0x3A], vec![1]),
            T::write_read(0x68, vec![0x3B], level).with_error(nack),
        ]);
        let mut src = Mpu6050Source::new(Mpu6050::new(bus.clone(), Address::Ad0Low), Clock(0));
        let mut ins = instrument();
        let mut tx = Wire::default();
        let mut seq = u16::MAX;
        assert_eq!(
            live_step(&mut src, &mut ins, &mut tx, &mut seq),
            Ok(LiveStep::NotReady)
        );
        let Ok(LiveStep::Sample {
            reading,
            output,
            sent,
        }) = live_step(&mut src, &mut ins, &mut tx, &mut seq)
        else {
            panic!("no sample")
        };
        assert_eq!(reading.t_us, 10_000);
        assert_eq!(output.status, Status::Initialised);
        // the SAMPLE frame went out as the protocol encodes it
        assert!(sent);
        let mut frames = Vec::new();
        clino_core::protocol::Decoder::default().feed(&tx.bytes, |d| frames.push(d.result));
        match frames.as_slice() {
            [Ok(clino_core::protocol::Frame::Sample(s))] => {
                assert_eq!((s.seq, s.t_us, s.acc), (u16::MAX, 10_000, [0, 0, 16384]));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(seq, 0); // wrapped
        assert_eq!(ins.roll_dial().pulse_us(), Some(1472)); // level
        assert_eq!(
            live_step(&mut src, &mut ins, &mut tx, &mut seq),
            Err(LiveError::Sensor(clino_mpu6050::Error::I2c(nack)))
        );
        assert_eq!(seq, 0); // no frame for a failed read
        bus.clone().done();
    }
}
