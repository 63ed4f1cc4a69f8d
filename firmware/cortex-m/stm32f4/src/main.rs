//! clino-fw on an STM32F411 (Cortex-M4F): the board binding, and nothing else.
//!
//! Everything the instrument does is in `clino-fw` (generic over
//! embedded-hal 1.0); this file only hands it the board's peripherals:
//!
//! | what | peripheral | pins (Nucleo-F411RE header) |
//! |---|---|---|
//! | MPU6050, 400 kHz | I2C1 | PB8 SCL (D15), PB9 SDA (D14) |
//! | roll dial servo, 50 Hz | TIM3 CH1 | PA6 (D12) |
//! | pitch dial servo, 50 Hz | TIM3 CH2 | PA7 (D11) |
//! | frames to the host, 115200 8N1 | USART2 TX | PA2 (the ST-LINK's virtual COM port) |
//! | time stamps, 1 µs, wraps at 2³² | TIM5 (32-bit) | — |
//!
//! Build: `cargo build --release -p clino-fw-stm32f4` in `firmware/cortex-m`;
//! flash with `probe-rs run --chip STM32F411RETx` (or `st-flash` after
//! `rust-objcopy -O binary`).
#![no_std]
#![no_main]

use clino_fw::dials::{Dial, ServoTiming};
use clino_fw::instrument::{Instrument, LiveStep, live_step};
use clino_fw::serial::{Frame, send_frame};
use clino_fw::source::{MicrosClock, Mpu6050Source};
use clino_mpu6050::{Address, Config, Mpu6050};
use cortex_m_rt::entry;
use panic_halt as _;
use stm32f4xx_hal::i2c::{DutyCycle, I2c, Mode};
use stm32f4xx_hal::timer::CounterUs;
use stm32f4xx_hal::{pac, prelude::*, rcc};

/// TIM5 as the board's microsecond clock (free-running over the full 2³²).
struct Tim5Clock(CounterUs<pac::TIM5>);

impl MicrosClock for Tim5Clock {
    fn now_us(&mut self) -> u32 {
        self.0.now().ticks()
    }
}

#[entry]
fn main() -> ! {
    let (Some(dp), Some(cp)) = (pac::Peripherals::take(), cortex_m::Peripherals::take()) else {
        panic!("peripherals taken twice")
    };
    let mut rcc = dp.RCC.freeze(rcc::Config::hsi().sysclk(84.MHz()));
    let gpioa = dp.GPIOA.split(&mut rcc);
    let gpiob = dp.GPIOB.split(&mut rcc);

    let i2c = I2c::new(
        dp.I2C1,
        (gpiob.pb8, gpiob.pb9),
        Mode::fast(400.kHz(), DutyCycle::Ratio2to1),
        &mut rcc,
    );
    // 20 ms period at 1 MHz: one duty count per microsecond of pulse
    let (_pwm, (ch1, ch2, ..)) = dp.TIM3.pwm_us(20_000.micros(), &mut rcc);
    let mut roll = ch1.with(gpioa.pa6);
    let mut pitch = ch2.with(gpioa.pa7);
    roll.enable();
    pitch.enable();
    let Ok(mut tx) = dp.USART2.tx(gpioa.pa2, 115_200.bps(), &mut rcc) else {
        panic!("USART2 configuration")
    };
    let mut clock = dp.TIM5.counter_us(&mut rcc);
    // the largest period `start` takes (ARR = 2³² − 2); then ARR = 2³² − 1 so the
    // counter wraps at 2³², as MicrosClock promises
    let _ = clock.start(u32::MAX.micros());
    // SAFETY: TIM5 is owned by `clock`; only its auto-reload value is written.
    unsafe { (*pac::TIM5::ptr()).arr().write(|w| w.bits(u32::MAX)) };
    let mut delay = cp.SYST.delay(&rcc.clocks);

    let config = Config::default(); // ±2 g, ±250 °/s, 44 Hz DLPF, 100 Hz
    let mut imu = Mpu6050::new(i2c, Address::Ad0Low);
    // no sensor, or not an MPU6050: retry once a second (the dials stay put)
    while imu.init(&config, &mut delay).is_err() {
        delay.delay_ms(1000);
    }
    let timing = ServoTiming::default();
    let mut instrument =
        Instrument::dynamic_at(&config, Dial::new(roll, timing), Dial::new(pitch, timing));
    let _ = send_frame(
        &mut tx,
        &Frame::Config {
            config,
            streaming: true,
        },
    );
    let mut source = Mpu6050Source::new(imu, Tim5Clock(clock));
    let mut seq = 0u16;
    let mut faults = 0u32;
    loop {
        match live_step(&mut source, &mut instrument, &mut tx, &mut seq) {
            Ok(LiveStep::NotReady | LiveStep::Sample { .. }) => {}
            // a bus or link error loses this sample only; counted (for a future STATUS frame)
            Err(_) => faults = faults.wrapping_add(1),
        }
    }
}
