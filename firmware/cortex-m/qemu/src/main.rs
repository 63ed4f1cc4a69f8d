//! clino-fw on QEMU's MPS2 AN386 (Cortex-M4 with FPU), with semihosting.
//!
//! The QEMU machine has no MPU6050 and no PWM timer, so the sample source is
//! the embedded recording (the BROAD excerpt, converted at build time by
//! `build.rs`) and the dials drive a PWM stand-in that keeps its duty; the
//! rest is the firmware's own code ([`clino_fw::instrument::Instrument`]).
//!
//! 1. every sample through `Pipeline::update` (the `dynamic` filter), each
//!    result written to the host file `clino-fw-quats.bin` (format:
//!    `clino_fw::results`), each update timed;
//! 2. every sample again through `Instrument::step` (pipeline + tilt +
//!    dials), timed, its outputs checked against pass 1;
//! 3. the f32/f64 micro-benchmark (`kernel`).
//!
//! Timing: run under `-icount shift=0` QEMU advances virtual time by exactly
//! 1 ns per instruction, and SysTick (on the core clock) counts virtual time;
//! a loop of a known number of instructions calibrates ticks → instructions.
//! These are instruction counts, not cycles (QEMU models no pipeline, no
//! flash wait states, and counts a 14-cycle `vsqrt` as one instruction).
#![no_std]
#![no_main]

mod kernel;

use clino_core::filter::FilterSpec;
use clino_core::pipeline::Pipeline;
use clino_fw::dials::{Dial, ServoTiming};
use clino_fw::instrument::Instrument;
use clino_fw::samples::Samples;
use clino_fw::{fnv1a64, fnv1a64_extend, results};
use cortex_m::peripheral::{SYST, syst::SystClkSource};
use cortex_m_rt::entry;
use cortex_m_semihosting::{debug, hprintln, syscall};
use panic_semihosting as _;

/// The recording, converted at build time (`build.rs`).
static SAMPLES: &[u8] = include_bytes!(concat!(env!("OUT_DIR"), "/samples.bin"));

/// Name of the host file the results go to (semihosting, relative to QEMU's directory).
const RESULTS_FILE: &str = "clino-fw-quats.bin\0";

/// A file on the host, through semihosting SYS_OPEN / SYS_WRITE / SYS_CLOSE.
struct HostFile(usize);

impl HostFile {
    /// Create (truncate) `name` (NUL-terminated) for binary writing.
    fn create(name: &str) -> Option<Self> {
        let b = name.as_bytes();
        // SAFETY: semihosting call with a NUL-terminated name and its length.
        let fd = unsafe {
            syscall!(
                OPEN,
                b.as_ptr(),
                cortex_m_semihosting::nr::open::W_TRUNC_BINARY,
                b.len() - 1
            )
        } as isize;
        (fd >= 0).then_some(HostFile(fd as usize))
    }

    /// Write all of `data`.
    fn write_all(&mut self, mut data: &[u8]) -> bool {
        while !data.is_empty() {
            // SAFETY: semihosting call on a valid buffer; returns the bytes NOT written.
            let left = unsafe { syscall!(WRITE, self.0, data.as_ptr(), data.len()) };
            if left >= data.len() {
                return false;
            }
            data = &data[data.len() - left..];
        }
        true
    }

    fn close(self) -> bool {
        // SAFETY: semihosting call on a handle from SYS_OPEN.
        unsafe { syscall!(CLOSE, self.0) == 0 }
    }
}

/// SysTick as a free-running 24-bit down-counter on the core clock.
fn start_systick(syst: &mut SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(0x00FF_FFFF);
    syst.clear_current();
    syst.enable_counter();
}

/// Ticks from `t0` to `t1` (a down-counter; any interval shorter than one wrap).
#[inline(always)]
fn elapsed(t0: u32, t1: u32) -> u32 {
    t0.wrapping_sub(t1) & 0x00FF_FFFF
}

#[inline(always)]
fn now() -> u32 {
    SYST::get_current()
}

/// `n` iterations of a two-instruction loop (`subs`, `bne`): 2n instructions.
#[inline(never)]
fn known_loop(n: u32) {
    // SAFETY: register-only loop.
    unsafe {
        core::arch::asm!("2:", "subs {n}, {n}, #1", "bne 2b", n = inout(reg) n => _,
                         options(nomem, nostack));
    }
}

/// A PWM channel that keeps its duty: the AN386 has no PWM timer.
struct KeptDuty(u16);

impl embedded_hal::pwm::ErrorType for KeptDuty {
    type Error = core::convert::Infallible;
}

impl embedded_hal::pwm::SetDutyCycle for KeptDuty {
    fn max_duty_cycle(&self) -> u16 {
        20_000
    }
    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
        self.0 = duty;
        Ok(())
    }
}

/// Timing of one pass: total and largest ticks.
#[derive(Default)]
struct Timing {
    ticks: u64,
    max: u32,
    n: u32,
}

impl Timing {
    fn add(&mut self, t: u32) {
        self.ticks += u64::from(t);
        self.max = self.max.max(t);
        self.n += 1;
    }
}

fn fail(msg: &str) -> ! {
    hprintln!("clino-fw FAIL: {}", msg);
    debug::exit(debug::EXIT_FAILURE);
    loop {
        cortex_m::asm::nop();
    }
}

#[entry]
fn main() -> ! {
    let Some(mut cp) = cortex_m::Peripherals::take() else {
        fail("core peripherals taken twice")
    };
    // MVFR0 (0xE000EF40): bits 7:4 single precision, 11:8 double precision support
    // SAFETY: read of a read-only architectural register.
    let mvfr0 = unsafe { core::ptr::read_volatile(0xE000_EF40 as *const u32) };
    hprintln!(
        "clino-fw on QEMU mps2-an386: MVFR0 = {:#010x} (single precision {}, double precision {})",
        mvfr0,
        if (mvfr0 >> 4) & 0xF != 0 {
            "in hardware"
        } else {
            "absent"
        },
        if (mvfr0 >> 8) & 0xF != 0 {
            "in hardware"
        } else {
            "in software"
        }
    );

    start_systick(&mut cp.SYST);
    // the cost of reading the timer twice, and ticks per instruction
    let (a, b) = (now(), now());
    let overhead = elapsed(a, b);
    const CAL_ITER: u32 = 1_000_000;
    let t0 = now();
    known_loop(CAL_ITER);
    let cal_ticks = elapsed(t0, now());
    let cal_insns = 2 * u64::from(CAL_ITER);
    if cal_ticks == 0 {
        fail("SysTick does not count (run QEMU with -icount shift=0)");
    }
    let to_insns = |ticks: u64| ticks * cal_insns / u64::from(cal_ticks);
    hprintln!(
        "timer: {} ticks for {} instructions ({} instructions per tick); read overhead {} ticks",
        cal_ticks,
        cal_insns,
        cal_insns as f64 / f64::from(cal_ticks),
        overhead
    );

    let samples = match Samples::parse(SAMPLES) {
        Ok(s) => s,
        Err(_) => fail("the embedded sample file is malformed"),
    };
    let n = samples.len();
    hprintln!(
        "samples: {} (fnv1a64 of the embedded file {:016x})",
        n,
        fnv1a64(SAMPLES)
    );

    // 1. the pipeline alone, results to the host
    let Some(mut file) = HostFile::create(RESULTS_FILE) else {
        fail("cannot create the results file on the host")
    };
    let mut header = [0u8; 8];
    header[..4].copy_from_slice(&results::MAGIC);
    header[4..].copy_from_slice(&(n as u32).to_le_bytes());
    let mut hash = fnv1a64(&header);
    if !file.write_all(&header) {
        fail("write to the results file");
    }
    let mut buf = [0u8; results::RECORD * 124];
    let mut used = 0;
    let mut pipeline = Pipeline::new(FilterSpec::default());
    let mut update = Timing::default();
    for s in samples.iter() {
        let t0 = now();
        let out = pipeline.update(&s);
        let t1 = now();
        update.add(elapsed(t0, t1).saturating_sub(overhead));
        let r = results::record(&out);
        hash = fnv1a64_extend(hash, &r);
        buf[used..used + results::RECORD].copy_from_slice(&r);
        used += results::RECORD;
        if used == buf.len() {
            if !file.write_all(&buf) {
                fail("write to the results file");
            }
            used = 0;
        }
    }
    if !file.write_all(&buf[..used]) || !file.close() {
        fail("write to the results file");
    }
    let c = pipeline.counts();
    hprintln!(
        "pipeline (dynamic): {} samples: {} init, {} fused, {} gyro-only, {} waiting, {} dropouts, {} saturated",
        c.samples,
        c.initialised,
        c.fused,
        c.gyro_only,
        c.waiting,
        c.dropouts,
        c.saturated
    );
    hprintln!("results: fnv1a64 {:016x}", hash);

    // 2. the instrument: pipeline + tilt + dials, checked against pass 1
    let t = ServoTiming::default();
    let mut ins = Instrument::dynamic(Dial::new(KeptDuty(0), t), Dial::new(KeptDuty(0), t));
    let mut check = Pipeline::new(FilterSpec::default());
    let mut step = Timing::default();
    let mut mismatches = 0u32;
    for s in samples.iter() {
        let t0 = now();
        let out = ins.step(&s);
        let t1 = now();
        step.add(elapsed(t0, t1).saturating_sub(overhead));
        if results::record(&out) != results::record(&check.update(&s)) {
            mismatches += 1;
        }
    }
    let tilt = ins.pipeline().tilt();
    hprintln!(
        "instrument: dials at {:?} µs (roll), {:?} µs (pitch); final roll {:?}, pitch {:?} rad; {} mismatches with pass 1",
        ins.roll_dial().pulse_us(),
        ins.pitch_dial().pulse_us(),
        tilt.map(|t| t.roll_rad),
        tilt.map(|t| t.pitch_rad),
        mismatches
    );

    // 3. f32 against f64, the same arithmetic, inputs from the recording
    let mut k64 = Timing::default();
    let mut k32 = Timing::default();
    let mut k32f = Timing::default();
    let (mut q64, mut q32, mut q32f) = (
        [1.0f64, 0.0, 0.0, 0.0],
        [1.0f32, 0.0, 0.0, 0.0],
        [1.0f32, 0.0, 0.0, 0.0],
    );
    let mut max_dev = 0.0f64;
    let dt = 0.0035;
    for s in samples.iter().take(2000) {
        let w = [s.gyr_rad_s.x, s.gyr_rad_s.y, s.gyr_rad_s.z];
        let a = [s.acc_m_s2.x, s.acc_m_s2.y, s.acc_m_s2.z];
        let (w32, a32) = (w.map(|x| x as f32), a.map(|x| x as f32));
        let t0 = now();
        q64 = kernel::step_f64(q64, w, a, 0.5, dt);
        let t1 = now();
        q32 = kernel::step_f32_libm(q32, w32, a32, 0.5, dt as f32);
        let t2 = now();
        q32f = kernel::step_f32_fpu(q32f, w32, a32, 0.5, dt as f32);
        let t3 = now();
        k64.add(elapsed(t0, t1).saturating_sub(overhead));
        k32.add(elapsed(t1, t2).saturating_sub(overhead));
        k32f.add(elapsed(t2, t3).saturating_sub(overhead));
        for i in 0..4 {
            max_dev = max_dev.max(libm::fabs(f64::from(q32f[i]) - q64[i]));
        }
    }

    let mean = |t: &Timing| to_insns(t.ticks) as f64 / f64::from(t.n.max(1));
    hprintln!(
        "FIGURE pipeline_update_f64 mean {:.0} max {} instructions per update ({} updates)",
        mean(&update),
        to_insns(u64::from(update.max)),
        update.n
    );
    hprintln!(
        "FIGURE instrument_step_f64 mean {:.0} max {} instructions per sample",
        mean(&step),
        to_insns(u64::from(step.max))
    );
    hprintln!(
        "FIGURE kernel_f64 {:.0} kernel_f32_libm_sqrtf {:.0} kernel_f32_vsqrt {:.0} instructions per step ({} steps; f32 vs f64 max |dq| {:.1e})",
        mean(&k64),
        mean(&k32),
        mean(&k32f),
        k64.n,
        max_dev
    );
    if mismatches != 0 {
        fail("the instrument's outputs differ from the pipeline's");
    }
    hprintln!("clino-fw OK");
    debug::exit(debug::EXIT_SUCCESS);
    loop {
        cortex_m::asm::nop();
    }
}
