//! `clino stream`: a board on a serial port, an MPU6050 on an I²C bus (Linux),
//! or a recording replayed, through the pipeline live: a terminal view, fused
//! CSV rows, a recording.

use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clino::io::source::{
    FileSource, ReplaySource, SampleSource, SerialOptions, SerialSource, SourceNotice,
};
use clino::mpu6050::Address;
use clino::stream::{
    FusedCsv, LiveStatus, Recorder, StreamConfig, StreamCounts, StreamObserver, StreamOutputs,
};

use super::{GainArgs, ReadArgs, StageArgs};

/// Arguments of `clino stream`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Serial port of a board running clino firmware (e.g. /dev/ttyACM0, /dev/ttyUSB0).
    // one source of --port, --i2c, --replay. The flags of one source are
    // checked by `check_flags`: clap takes a `requires` as met when the
    // required flag conflicts with one that is present (or is required
    // unless one is), so `requires = "port"` would let `--i2c … --dials` through.
    #[arg(
        long,
        value_name = "DEVICE",
        required_unless_present_any = ["i2c", "replay"],
        conflicts_with_all = ["i2c", "replay"]
    )]
    pub port: Option<String>,
    /// Baud rate of the port (8N1).
    #[arg(long, default_value_t = 115_200, value_name = "N")]
    pub baud: u32,
    /// An MPU6050 on this I²C bus, read by the host (Linux: /dev/i2c-1 on a Raspberry Pi).
    #[arg(long, value_name = "/dev/i2c-N", conflicts_with = "replay")]
    pub i2c: Option<String>,
    /// I²C address of the MPU6050: 0x68 (AD0 low, the default) or 0x69 (AD0 high); hex or decimal.
    #[arg(long, value_name = "ADDR", value_parser = parse_address)]
    pub address: Option<Address>,
    /// Read rate of the I²C sensor, Hz (default 100, at most 1000; the time stamps are k / rate).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
    /// Accelerometer full scale of the I²C sensor, ±g: 2 (default), 4, 8 or 16.
    #[arg(long, value_name = "G")]
    pub accel_fs: Option<u8>,
    /// Gyroscope full scale of the I²C sensor, ±°/s: 250 (default), 500, 1000 or 2000.
    #[arg(long, value_name = "DPS")]
    pub gyro_fs: Option<u16>,
    /// Low-pass filter of the I²C sensor, Hz: 260, 184, 94, 44 (default), 21, 10 or 5
    /// (keep it below half the rate).
    #[arg(long, value_name = "HZ")]
    pub dlpf: Option<u16>,
    /// Replay a recording (CSV or Parquet, as `clino fuse` reads) on its own clock.
    #[arg(long, value_name = "FILE")]
    pub replay: Option<PathBuf>,
    /// Replay speed, × real time (`inf`: as fast as the pipeline takes it).
    /// Default 1; only with `--replay`.
    #[arg(long, value_name = "X")]
    pub speed: Option<f64>,
    /// Filter: poisson, complementary, mahony, madgwick or dynamic, with any
    /// parameter as NAME:KEY=VALUE,… (as `clino fuse`).
    #[arg(long, short = 'f', default_value = "dynamic", long_help = clino::fusion::filter_help())]
    pub filter: String,
    #[command(flatten)]
    pub gains: GainArgs,
    #[command(flatten)]
    pub stages: StageArgs,
    #[command(flatten)]
    pub read: ReadArgs,
    /// Calibrate every sample with this calibration file (from `clino calibrate`) before fusion.
    #[arg(long, value_name = "CAL.toml")]
    pub calibration: Option<PathBuf>,
    /// Write fused rows to stdout, with the columns of `clino fuse`, one flushed line per sample.
    #[arg(long)]
    pub csv: bool,
    /// Record the raw samples (SI units; CSV, or Parquet by the extension) for `clino fuse`;
    /// flushed every second, complete after Ctrl-C.
    #[arg(long, value_name = "FILE.csv|parquet")]
    pub record: Option<PathBuf>,
    /// Send the filter's roll and pitch to the board's dials (10 times a second; a board on
    /// --port: a bare I²C sensor has none).
    #[arg(long)]
    pub dials: bool,
    /// Report when no valid frame has arrived for this many seconds (wrong baud rate, wrong port).
    #[arg(long, default_value_t = 3.0, value_name = "SECONDS")]
    pub silence: f64,
    /// Samples the buffer between the reader and the filter holds (a slow consumer drops beyond it).
    #[arg(long, default_value_t = 4096, value_name = "N")]
    pub buffer: usize,
}

fn parse_address(text: &str) -> Result<Address, String> {
    clino::io::source::parse_address(text).map_err(|e| e.message)
}

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_sigint(_: libc::c_int) {
    STOP.store(true, Ordering::Relaxed);
}

/// Ctrl-C (and SIGTERM) end the stream cleanly: outputs finished, summary printed.
fn catch_interrupt() {
    // SAFETY: the handler only stores to an atomic (async-signal-safe); the
    // sigaction struct is fully initialised by zeroing and the fields set.
    unsafe {
        let mut sa: libc::sigaction = std::mem::zeroed();
        sa.sa_sigaction = on_sigint as extern "C" fn(libc::c_int) as libc::sighandler_t;
        libc::sigemptyset(&mut sa.sa_mask);
        libc::sigaction(libc::SIGINT, &sa, std::ptr::null_mut());
        libc::sigaction(libc::SIGTERM, &sa, std::ptr::null_mut());
    }
}

/// What a person sees: each fault on stderr when it happens (a burst of one
/// kind at most once a second, with the number held back), and the live line.
struct Terminal {
    view: bool,
    last: Vec<(String, Instant, u64)>,
}

impl Terminal {
    fn say(&mut self, key: &str, text: &str) {
        let now = Instant::now();
        let slot = match self.last.iter().position(|(k, _, _)| k == key) {
            Some(i) => i,
            None => {
                self.last
                    .push((key.to_string(), now - Duration::from_secs(2), 0));
                self.last.len() - 1
            }
        };
        let (_, at, held) = &mut self.last[slot];
        if now.duration_since(*at) < Duration::from_secs(1) {
            *held += 1;
            return;
        }
        let more = std::mem::take(held);
        *at = now;
        match more {
            0 => self.say_now(text),
            n => self.say_now(&format!("{text} (and {n} more since the last report)")),
        }
    }

    fn say_now(&self, text: &str) {
        if self.view {
            print!("\r\x1b[2K");
            let _ = std::io::stdout().flush();
        }
        eprintln!("clino stream: {text}");
    }
}

impl StreamObserver for Terminal {
    fn notice(&mut self, n: &SourceNotice, _: &StreamCounts) {
        use clino_core::protocol::Notice;
        // the kinds that come in bursts are held to one line a second; the rest always print
        let key = match n {
            SourceNotice::BadFrame(e) => e.kind_name(),
            SourceNotice::Garbage { .. } => "garbage",
            SourceNotice::Link(Notice::Gap { .. }) => "gap",
            SourceNotice::Link(Notice::Repeated { .. }) => "repeated",
            SourceNotice::Link(Notice::NoConfig) => "no config",
            SourceNotice::Late { .. } => "late",
            SourceNotice::BusRetry { .. } => "bus retry",
            _ => {
                self.say_now(&n.to_string());
                return;
            }
        };
        self.say(key, &n.to_string());
    }
    fn message(&mut self, text: &str) {
        self.say_now(text);
    }
    fn tick(&mut self, live: &LiveStatus) {
        if self.view {
            print!("\r\x1b[2K{}", live.line());
            let _ = std::io::stdout().flush();
        }
    }
}

fn open_serial(a: &Args, port: &str) -> anyhow::Result<Box<dyn SampleSource + Send>> {
    anyhow::ensure!(
        a.silence > 0.0,
        "--silence wants a positive number of seconds"
    );
    let opts = SerialOptions {
        baud: a.baud,
        silence: Duration::from_secs_f64(a.silence),
        ..SerialOptions::default()
    };
    Ok(Box::new(SerialSource::open(port, opts)?))
}

/// The MPU6050 on the kernel's I²C device `path` (Linux's `/dev/i2c-N`).
#[cfg(target_os = "linux")]
fn open_i2c(a: &Args, path: &str) -> anyhow::Result<Box<dyn SampleSource + Send>> {
    use clino::io::source::I2cSource;
    let opts = i2c_options(a)?;
    let io = |m: String| clino::Error::new(clino::ErrorKind::Io, m).in_file(path);
    if !Path::new(path).exists() {
        return Err(io(
            "no such I2C bus (is I2C enabled? `ls /dev/i2c-*` lists the buses; \
             on a Raspberry Pi: raspi-config, Interface Options, I2C)"
                .into(),
        )
        .into());
    }
    let bus = linux_embedded_hal::I2cdev::new(path)
        .map_err(|e| io(format!("cannot open the I2C bus: {e}{}", i2c_open_hint(&e))))?;
    Ok(Box::new(I2cSource::new(
        bus,
        path,
        a.address.unwrap_or_default(),
        opts,
    )?))
}

/// The I²C sensor's options from the flags.
fn i2c_options(a: &Args) -> anyhow::Result<clino::io::source::I2cOptions> {
    use clino::io::source::I2cOptions;
    let d = I2cOptions::default();
    Ok(I2cOptions::from_numbers(
        a.rate.unwrap_or(d.rate_hz),
        a.accel_fs.unwrap_or(d.accel_range.g()),
        a.gyro_fs.unwrap_or(d.gyro_range.dps()),
        a.dlpf.unwrap_or(d.dlpf.accel_bandwidth_hz()),
    )?)
}

/// The likely cause of an error opening an I²C bus.
#[cfg(target_os = "linux")]
fn i2c_open_hint(e: &linux_embedded_hal::i2cdev::linux::LinuxI2CError) -> &'static str {
    use linux_embedded_hal::i2cdev::linux::LinuxI2CError;
    let errno = match e {
        LinuxI2CError::Errno(n) => Some(*n),
        LinuxI2CError::Io(e) => e.raw_os_error(),
    };
    match errno {
        Some(libc::EACCES) | Some(libc::EPERM) => {
            " (add the user to the i2c group, or run as root)"
        }
        Some(libc::ENOTTY) => " (not an I2C bus: give its /dev/i2c-N device)",
        _ => "",
    }
}

#[cfg(not(target_os = "linux"))]
fn open_i2c(a: &Args, path: &str) -> anyhow::Result<Box<dyn SampleSource + Send>> {
    let _ = a;
    anyhow::bail!(
        "{path}: --i2c reads /dev/i2c-N and works on Linux only (use --port with a board running clino firmware)"
    )
}

/// The flags that belong to one source are given with it.
fn check_flags(a: &Args) -> anyhow::Result<()> {
    anyhow::ensure!(
        !a.dials || a.port.is_some(),
        "--dials needs a board running clino firmware on --port (a bare I2C sensor or a replay has no dials)"
    );
    anyhow::ensure!(
        a.speed.is_none() || a.replay.is_some(),
        "--speed is the replay speed: it needs --replay (a live source runs on its own clock)"
    );
    let i2c_only = [
        ("--address", a.address.is_some()),
        ("--rate", a.rate.is_some()),
        ("--accel-fs", a.accel_fs.is_some()),
        ("--gyro-fs", a.gyro_fs.is_some()),
        ("--dlpf", a.dlpf.is_some()),
    ];
    if a.i2c.is_none()
        && let Some((flag, _)) = i2c_only.iter().find(|(_, given)| *given)
    {
        anyhow::bail!("{flag} is an option of the I2C sensor: it needs --i2c");
    }
    Ok(())
}

fn open_source(a: &Args) -> anyhow::Result<Box<dyn SampleSource + Send>> {
    check_flags(a)?;
    if let Some(port) = &a.port {
        return open_serial(a, port);
    }
    if let Some(path) = &a.i2c {
        return open_i2c(a, path);
    }
    let path = a.replay.as_deref().unwrap_or(Path::new("-"));
    let opts = clino::io::ReadOptions {
        imu_only: a.calibration.is_none(),
        ..a.read.options()?
    };
    Ok(Box::new(ReplaySource::new(
        FileSource::open(path, &opts)?,
        a.speed.unwrap_or(1.0),
    )?))
}

/// Run `clino stream`.
pub fn run(a: Args) -> anyhow::Result<()> {
    let mut filter = super::filter_config(&a.filter, &a.gains, &a.stages)?;
    // an MPU6050 on I²C is read at the ranges set here: a reading at one is
    // clipped (a board over serial names its own in its CONFIG)
    if a.i2c.is_some() && filter.sensor_range == clino::fusion::SensorRange::default() {
        let d = clino::io::source::I2cOptions::default();
        filter = filter.with_sensor_range(clino::fusion::SensorRange::from_full_scale(
            f64::from(a.accel_fs.unwrap_or(d.accel_range.g())),
            f64::from(a.gyro_fs.unwrap_or(d.gyro_range.dps())),
        ));
    }
    // the sensor's timing, where the user did not give it: an MPU6050 on
    // I²C from the flags here, a board from its CONFIG (clino::stream)
    let timing_given = clino::fusion::names_timing(&a.filter);
    let mut timing_note = None;
    if a.i2c.is_some()
        && !timing_given
        && let clino::fusion::FilterSpec::Dynamic(p) = &mut filter.spec
    {
        let o = i2c_options(&a)?;
        let t = clino::stream::SensorTiming::mpu6050(&o.sensor_config(), false, o.rate_hz);
        t.apply(p);
        let text = t.notice(
            &format!(
                "the sensor's settings ({} Hz filter, read at {} Hz)",
                o.dlpf.accel_bandwidth_hz(),
                o.rate_hz
            ),
            o.rate_hz,
        );
        eprintln!("clino stream: {text}");
        timing_note = Some((t, text));
    }
    // a replayed recording's own note of its sensor's timing, as `clino
    // fuse` takes it (not from stdin, which cannot be read twice)
    if let (Some(path), false) = (&a.replay, timing_given)
        && path != Path::new("-")
        && let clino::fusion::FilterSpec::Dynamic(p) = &mut filter.spec
    {
        let opts = clino::io::ReadOptions {
            imu_only: true,
            ..a.read.options()?
        };
        let mut r = clino::io::ImuCsvReader::from_path(path, &opts)?;
        r.next_row()?;
        if let Some(t) = clino::stream::SensorTiming::from_notes(r.notes().0) {
            t.apply(p);
            eprintln!(
                "clino stream: the sensor's timing as the recording notes it: {} (a --filter that names sensor_delay_periods or gyro_lag_s overrides it)",
                t.note_text()
            );
            timing_note = Some((
                t,
                format!(
                    "replayed with the timing its recording notes: {}",
                    t.note_text()
                ),
            ));
        }
    }
    let calibration = match &a.calibration {
        Some(p) => Some(clino::calib::CalibrationFile::load(p)?),
        None => None,
    };
    let mut cfg = StreamConfig::new(filter);
    cfg.calibration = calibration.as_ref();
    cfg.capacity = a.buffer;
    cfg.dials = a.dials;
    cfg.board_timing = !timing_given;
    let source = open_source(&a)?;
    let mut outputs = StreamOutputs::default();
    if a.csv {
        outputs.csv = Some(FusedCsv::new(
            Box::new(std::io::stdout()) as Box<dyn Write + Send>
        )?);
    }
    if let Some(p) = &a.record {
        let inputs: Vec<&Path> = a.replay.iter().map(|p| p.as_path()).collect();
        let mut r = Recorder::create(p, &inputs)?;
        if let Some((t, text)) = &timing_note {
            r.comment(&format!("clino stream: {text}"))?;
            r.note_timing(t)?;
        }
        outputs.record = Some(r);
    }
    let mut term = Terminal {
        view: !a.csv && std::io::stdout().is_terminal(),
        last: Vec::new(),
    };
    catch_interrupt();
    eprintln!(
        "clino stream: {} through {} (Ctrl-C ends)",
        source.name(),
        filter.label()
    );
    let result = clino::stream::run(source, &cfg, &mut outputs, &mut term, &STOP);
    if term.view {
        println!();
    }
    let recorded = outputs.record.take().map(Recorder::finish).transpose();
    let counts = result?;
    if let (Some(p), Some(n)) = (&a.record, recorded?) {
        eprintln!("clino stream: {n} samples recorded to {}", p.display());
    }
    eprintln!("clino stream: summary");
    for line in counts.summary() {
        eprintln!("  {line}");
    }
    Ok(())
}
