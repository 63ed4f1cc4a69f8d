//! `clino testbench conical|orbit|static|analyze`: the dynamic test bench.

use super::{GapsArg, OutputArgs, SensorArg, print_result};
use clap::ValueEnum;
use clino::report::text::testbench as text;
use clino::sim::motion::ConeAxis;
use clino::sim::stewart::{Geometry, ServoLegs};
use clino::testbench::conical::{ConicalConfig, PlatformSpec, run_conical};
use clino::testbench::orbit::{OrbitConfig, run_orbit};
use clino::testbench::recording::{Excitation, Table, analyze};
use clino::testbench::static_record::read_static_record;
use clino::testbench::{plots, static_test};
use std::io::IsTerminal;
use std::path::PathBuf;

/// Arguments of `clino testbench`.
#[derive(clap::Args)]
pub struct Args {
    #[command(subcommand)]
    cmd: Cmd,
}

#[derive(clap::Subcommand)]
enum Cmd {
    /// Simulated conical motion about z: sensitivities (dB) per frequency.
    Conical(ConicalArgs),
    /// Simulated positional orbits: cross-coupling (degrees p-p) per frequency.
    Orbit(OrbitArgs),
    /// Static test: drift and noise of a filter's tilt at rest (recording or simulation).
    Static(StaticArgs),
    /// Analyse a lab recording (inclinometer outputs with encoder legs or a reference attitude).
    Analyze(AnalyzeArgs),
    /// Write a simulated lab recording (platform encoders, IMU, inclinometer quaternion) to CSV.
    Record(RecordArgs),
}

/// The simulated Stewart platform (conical and orbit tests).
#[derive(clap::Args)]
struct PlatformArgs {
    /// Carry the sensor on a simulated servo-driven Stewart platform (typical geometry): the
    /// sensor rides the actual motion of the servo legs, and the reference (cone angle, orbit
    /// amplitude, the platform's own tilt) comes from the actual legs by forward kinematics.
    #[arg(long)]
    platform: bool,
    /// Natural frequency of the platform's servo legs, Hz (needs --platform).
    #[arg(long, default_value_t = ServoLegs::default().natural_hz, requires = "platform")]
    servo_hz: f64,
    /// Damping ratio of the servo legs (needs --platform).
    #[arg(long, default_value_t = ServoLegs::default().damping, requires = "platform")]
    servo_damping: f64,
}

impl PlatformArgs {
    fn spec(&self) -> Option<PlatformSpec> {
        self.platform.then(|| PlatformSpec {
            geometry: Geometry::typical(),
            servo: ServoLegs {
                natural_hz: self.servo_hz,
                damping: self.servo_damping,
            },
        })
    }
}

/// The servo legs of the platform a lab recording is simulated on.
#[derive(clap::Args)]
struct ServoArgs {
    /// Natural frequency of the platform's servo legs, Hz.
    #[arg(long, default_value_t = ServoLegs::default().natural_hz)]
    servo_hz: f64,
    /// Damping ratio of the servo legs.
    #[arg(long, default_value_t = ServoLegs::default().damping)]
    servo_damping: f64,
}

impl ServoArgs {
    fn legs(&self) -> ServoLegs {
        ServoLegs {
            natural_hz: self.servo_hz,
            damping: self.servo_damping,
        }
    }
}

#[derive(clap::Args)]
struct RecordArgs {
    /// Output CSV file.
    out: PathBuf,
    /// What the platform does.
    #[arg(long, value_enum, default_value = "conical")]
    excitation: ExcitationArg,
    /// Cone angle, degrees (conical).
    #[arg(long, default_value_t = 5.0)]
    alpha_deg: f64,
    /// Orbit amplitude on x, y, z, mm (orbit).
    #[arg(long, default_value_t = 20.0)]
    amplitude_mm: f64,
    /// Frequency, Hz.
    #[arg(long, default_value_t = 1.0)]
    freq_hz: f64,
    /// Duration, s.
    #[arg(long, default_value_t = 30.0)]
    duration_s: f64,
    /// Sensor preset.
    #[arg(long, value_enum, default_value = "mpu6050", ignore_case = true)]
    sensor: SensorArg,
    /// Override the sensor bandwidth with a first-order low-pass at this cut-off, Hz.
    #[arg(long)]
    bandwidth_hz: Option<f64>,
    /// Attitude filter giving the recorded inclinometer quaternion.
    #[arg(long, default_value = clino::testbench::filters::BEST_FILTER)]
    filter: String,
    /// Sample rate, Hz.
    #[arg(long, default_value_t = 200.0)]
    rate_hz: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    servo: ServoArgs,
}

/// What the platform does.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum ExcitationArg {
    /// Conical motion about z (frequency response).
    Conical,
    /// Positional orbit (cross-coupling).
    Orbit,
}

impl From<ExcitationArg> for Excitation {
    fn from(e: ExcitationArg) -> Self {
        match e {
            ExcitationArg::Conical => Excitation::Conical,
            ExcitationArg::Orbit => Excitation::Orbit,
        }
    }
}

/// The axis a cone is drawn about.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum AxisArg {
    /// x (gyro z sensitivity).
    X,
    /// y (gyro z sensitivity).
    Y,
    /// z (the full test).
    Z,
}

impl From<AxisArg> for ConeAxis {
    fn from(a: AxisArg) -> Self {
        match a {
            AxisArg::X => ConeAxis::X,
            AxisArg::Y => ConeAxis::Y,
            AxisArg::Z => ConeAxis::Z,
        }
    }
}

#[derive(clap::Args)]
struct Common {
    /// Sensor preset.
    #[arg(long, value_enum, default_value = "mpu6050", ignore_case = true)]
    sensor: SensorArg,
    /// Override the sensor bandwidth with a first-order low-pass at this cut-off, Hz.
    #[arg(long)]
    bandwidth_hz: Option<f64>,
    /// Attitude filter, e.g. mahony, complementary:tau=10, madgwick:beta=0.01, poisson, dynamic:bandwidth=0.15.
    #[arg(long, default_value = clino::testbench::filters::BEST_FILTER)]
    filter: String,
    /// Sample rate, Hz.
    #[arg(long, default_value_t = 200.0)]
    rate_hz: f64,
    /// Random seed.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    #[command(flatten)]
    output: OutputArgs,
}

impl Common {
    fn sensor(&self) -> anyhow::Result<clino::sim::ImuModel> {
        self.sensor.model(self.bandwidth_hz)
    }
}

#[derive(clap::Args)]
struct ConicalArgs {
    /// Cone angle, degrees.
    #[arg(long, default_value_t = 5.0)]
    alpha_deg: f64,
    /// Frequencies, Hz (comma separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.1,0.2,0.5,1,2,3.15,5,10"
    )]
    freq_hz: Vec<f64>,
    /// Cone axis: z (the full test) or x, y (gyro z sensitivity).
    #[arg(long, value_enum, default_value = "z", ignore_case = true)]
    axis: AxisArg,
    #[command(flatten)]
    platform: PlatformArgs,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct OrbitArgs {
    /// Orbit amplitude on each of x, y, z, mm.
    #[arg(long, default_value_t = 20.0)]
    amplitude_mm: f64,
    /// Frequencies, Hz (comma separated).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "0.1,0.2,0.3,0.4,0.5,0.6,0.7,0.8"
    )]
    freq_hz: Vec<f64>,
    #[command(flatten)]
    platform: PlatformArgs,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct StaticArgs {
    /// Recording at rest (CSV: t_s, gyr_*_rad_s|deg_s, acc_*_m_s2|g; read as by `clino allan`); omit to simulate the sensor.
    recording: Option<PathBuf>,
    /// Simulated duration, s (the source's test lasts 10 minutes).
    #[arg(long, default_value_t = 600.0)]
    duration_s: f64,
    /// Start of the record excluded from the statistics (filter settling), s.
    #[arg(long, default_value_t = 10.0)]
    settle_s: f64,
    /// What to do with a gap in a recording's time stamps.
    #[arg(long, value_enum, default_value = "refuse")]
    gaps: GapsArg,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct AnalyzeArgs {
    /// Lab recording (CSV; see `clino::testbench::recording` for the columns).
    recording: PathBuf,
    /// What the platform did.
    #[arg(long, value_enum, default_value = "conical")]
    excitation: ExcitationArg,
    /// Excitation frequency, Hz (default: fitted from the reference).
    #[arg(long)]
    freq_hz: Option<f64>,
    /// Start of the record to skip, s.
    #[arg(long, default_value_t = 0.0)]
    skip_s: f64,
    /// Print JSON to stdout.
    #[arg(long)]
    json: bool,
}

fn progress(n: usize) -> indicatif::ProgressBar {
    if std::io::stderr().is_terminal() {
        indicatif::ProgressBar::new(n as u64)
    } else {
        indicatif::ProgressBar::hidden()
    }
}

/// Run `clino testbench`.
pub fn run(a: Args) -> anyhow::Result<()> {
    match a.cmd {
        Cmd::Conical(c) => conical(c),
        Cmd::Orbit(o) => orbit(o),
        Cmd::Static(s) => static_cmd(s),
        Cmd::Analyze(a) => lab_analysis(a),
        Cmd::Record(r) => record(r),
    }
}

fn conical(c: ConicalArgs) -> anyhow::Result<()> {
    let mut cfg = ConicalConfig::new(
        c.alpha_deg.to_radians(),
        c.freq_hz,
        c.common.sensor()?,
        &c.common.filter,
    );
    cfg.rate_hz = c.common.rate_hz;
    cfg.seed = c.common.seed;
    cfg.platform = c.platform.spec();
    cfg.axis = c.axis.into();
    let pb = progress(cfg.freqs_hz.len());
    let pts = run_conical(&cfg, &mut |d, _| pb.set_position(d as u64))?;
    pb.finish_and_clear();
    if let Some(p) = &c.common.output.plot {
        plots::conical_plot(p, &pts)?;
    }
    print_result(c.common.output.json, &pts, || text::conical(&pts))
}

fn orbit(o: OrbitArgs) -> anyhow::Result<()> {
    let mut cfg = OrbitConfig::new(
        o.amplitude_mm * 1e-3,
        o.freq_hz,
        o.common.sensor()?,
        &o.common.filter,
    );
    cfg.rate_hz = o.common.rate_hz;
    cfg.seed = o.common.seed;
    cfg.platform = o.platform.spec();
    let pb = progress(cfg.freqs_hz.len());
    let pts = run_orbit(&cfg, &mut |d, _| pb.set_position(d as u64))?;
    pb.finish_and_clear();
    if let Some(p) = &o.common.output.plot {
        plots::orbit_plot(p, &pts)?;
    }
    let on_platform = cfg.platform.is_some();
    print_result(o.common.output.json, &pts, || {
        text::orbit(&pts, on_platform)
    })
}

fn static_cmd(s: StaticArgs) -> anyhow::Result<()> {
    let r = match &s.recording {
        Some(path) => {
            // the rules of `clino allan` too: comments, unused columns, gaps, dropouts
            let rec = read_static_record(path, s.gaps.into())?;
            for n in &rec.notes {
                eprintln!("warning: {n}");
            }
            static_test::static_test_record(&rec, &s.common.filter, s.settle_s)?
        }
        None => static_test::static_test_simulated(
            &s.common.sensor()?,
            s.common.rate_hz,
            s.duration_s,
            s.common.seed,
            &s.common.filter,
            s.settle_s,
        )?,
    };
    if let Some(p) = &s.common.output.plot {
        plots::static_plot(p, &r)?;
    }
    print_result(s.common.output.json, &r, || text::static_test(&r))
}

fn lab_analysis(a: AnalyzeArgs) -> anyhow::Result<()> {
    let exc = a.excitation.into();
    let t = Table::read(&a.recording)?;
    let r = analyze(&t, exc, &Geometry::typical(), a.freq_hz, a.skip_s)?;
    print_result(a.json, &r, || text::lab_analysis(&r, exc))
}

fn record(r: RecordArgs) -> anyhow::Result<()> {
    let exc: Excitation = r.excitation.into();
    let amp = match exc {
        Excitation::Conical => r.alpha_deg.to_radians(),
        Excitation::Orbit => r.amplitude_mm * 1e-3,
    };
    clino::testbench::recording::simulate_lab_recording(
        &r.out,
        exc,
        amp,
        r.freq_hz,
        &r.servo.legs(),
        &r.sensor.model(r.bandwidth_hz)?,
        &r.filter,
        r.rate_hz,
        r.duration_s,
        r.seed,
    )?;
    eprintln!("wrote {}", r.out.display());
    Ok(())
}
