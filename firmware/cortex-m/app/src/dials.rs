//! A dial: a hobby servo on one PWM channel showing an angle.
//!
//! A hobby servo turns to an angle set by the width of a pulse repeated every
//! 20 ms (50 Hz). The dial angle φ ∈ [−90°, +90°] (the instrument's roll or
//! pitch) maps to the servo angle φ + 90° ∈ [0°, 180°], and that linearly to
//! the pulse width between `min_pulse_us` (0°) and `max_pulse_us` (180°):
//!
//! w = w_min + (φ + 90°)/180° · (w_max − w_min),  duty = w / period · duty_max.
//!
//! Angles beyond ±90° are clamped (the needle stops at the end of the scale);
//! a non-finite angle leaves the dial where it was.

use embedded_hal::pwm::SetDutyCycle;

/// The servo's pulse timing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ServoTiming {
    /// Pulse width at servo angle 0°, µs.
    pub min_pulse_us: u32,
    /// Pulse width at servo angle 180°, µs.
    pub max_pulse_us: u32,
    /// PWM period, µs.
    pub period_us: u32,
}

impl Default for ServoTiming {
    /// 544–2400 µs at 50 Hz: the Arduino `Servo` library's defaults, which
    /// the source instrument's servos (pins 9 and 10) were driven with.
    fn default() -> Self {
        ServoTiming {
            min_pulse_us: 544,
            max_pulse_us: 2400,
            period_us: 20_000,
        }
    }
}

impl ServoTiming {
    /// Pulse width, µs (rounded to the nearest), for dial angle `angle_rad`
    /// (clamped to ±90°); `None` when the angle is not finite.
    pub fn pulse_us(&self, angle_rad: f64) -> Option<u32> {
        if !angle_rad.is_finite() {
            return None;
        }
        let half = core::f64::consts::FRAC_PI_2;
        let frac = (angle_rad.clamp(-half, half) + half) / core::f64::consts::PI;
        let span = f64::from(self.max_pulse_us - self.min_pulse_us);
        // frac·span ∈ [0, span]: adding ½ and truncating rounds to nearest
        Some(self.min_pulse_us + (frac * span + 0.5) as u32)
    }

    /// Duty count, out of `max_duty`, of a pulse `pulse_us` wide (rounded).
    pub fn duty(&self, pulse_us: u32, max_duty: u16) -> u16 {
        let d = (u64::from(pulse_us) * u64::from(max_duty) + u64::from(self.period_us / 2))
            / u64::from(self.period_us);
        d.min(u64::from(max_duty)) as u16
    }
}

/// One dial: a PWM channel and its servo's timing.
#[derive(Debug)]
pub struct Dial<P> {
    pwm: P,
    timing: ServoTiming,
    pulse_us: Option<u32>,
}

impl<P: SetDutyCycle> Dial<P> {
    /// A dial on `pwm` (already running at the servo's period).
    pub fn new(pwm: P, timing: ServoTiming) -> Self {
        Dial {
            pwm,
            timing,
            pulse_us: None,
        }
    }

    /// Turn the needle to `angle_rad` (see the [module docs](self)); a
    /// non-finite angle changes nothing.
    pub fn show(&mut self, angle_rad: f64) -> Result<(), P::Error> {
        let Some(w) = self.timing.pulse_us(angle_rad) else {
            return Ok(());
        };
        let duty = self.timing.duty(w, self.pwm.max_duty_cycle());
        self.pwm.set_duty_cycle(duty)?;
        self.pulse_us = Some(w);
        Ok(())
    }

    /// The pulse width last set, µs.
    pub fn pulse_us(&self) -> Option<u32> {
        self.pulse_us
    }

    /// The PWM channel back.
    pub fn release(self) -> P {
        self.pwm
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use embedded_hal_mock::eh1::pwm::{Mock, Transaction as T};

    #[test]
    fn pulse_widths_at_the_scale_marks() {
        let t = ServoTiming::default();
        assert_eq!(t.pulse_us(-90f64.to_radians()), Some(544));
        assert_eq!(t.pulse_us(0.0), Some(1472)); // (544 + 2400) / 2
        assert_eq!(t.pulse_us(90f64.to_radians()), Some(2400));
        // 30° → 544 + 120/180 · 1856 = 1781.33 → 1781
        assert_eq!(t.pulse_us(30f64.to_radians()), Some(1781));
        assert_eq!(t.pulse_us(3.0), Some(2400)); // clamped
        assert_eq!(t.pulse_us(-3.0), Some(544));
        assert_eq!(t.pulse_us(f64::NAN), None);
        // duty: 1472 µs of 20 000 µs at a 16-bit timer: 0.0736 · 65535 = 4823.4
        assert_eq!(t.duty(1472, 65535), 4823);
        assert_eq!(t.duty(25_000, 1000), 1000);
    }

    #[test]
    fn the_dial_sets_the_duty_and_ignores_nan() {
        // max duty 20 000: one count per µs, so duty = pulse width
        let pwm = Mock::new(&[
            T::max_duty_cycle(20_000),
            T::set_duty_cycle(1472),
            T::max_duty_cycle(20_000),
            T::set_duty_cycle(2400),
        ]);
        let mut d = Dial::new(pwm, ServoTiming::default());
        d.show(0.0).unwrap();
        assert_eq!(d.pulse_us(), Some(1472));
        d.show(f64::NAN).unwrap(); // no transaction
        d.show(2.0).unwrap();
        assert_eq!(d.pulse_us(), Some(2400));
        d.release().done();
    }
}
