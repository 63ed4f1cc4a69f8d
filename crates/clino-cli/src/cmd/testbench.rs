//! `clino testbench conical|orbit|static|analyze`: the dynamic test bench.

use clino::sim::ImuModel;
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
    /// What the platform does: conical or orbit.
    #[arg(long, default_value = "conical")]
    excitation: String,
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
    /// Sensor preset: ideal, mpu6050, mpu6050-raw.
    #[arg(long, default_value = "mpu6050")]
    sensor: String,
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

fn excitation(name: &str) -> anyhow::Result<Excitation> {
    match name {
        "conical" => Ok(Excitation::Conical),
        "orbit" => Ok(Excitation::Orbit),
        other => anyhow::bail!("unknown excitation '{other}' (conical or orbit)"),
    }
}

#[derive(clap::Args)]
struct Common {
    /// Sensor preset: ideal, mpu6050, mpu6050-raw.
    #[arg(long, default_value = "mpu6050")]
    sensor: String,
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
    /// Print JSON to stdout.
    #[arg(long)]
    json: bool,
    /// Write a plot (.svg or .png).
    #[arg(long)]
    plot: Option<PathBuf>,
}

fn sensor(name: &str, bandwidth_hz: Option<f64>) -> anyhow::Result<ImuModel> {
    let m = ImuModel::preset(name)?;
    Ok(match bandwidth_hz {
        Some(b) => m.with_bandwidth(b),
        None => m,
    })
}

impl Common {
    fn sensor(&self) -> anyhow::Result<ImuModel> {
        sensor(&self.sensor, self.bandwidth_hz)
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
    #[arg(long, default_value = "z")]
    axis: String,
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
    /// What to do with a gap in a recording's time stamps: refuse, or longest (the longest gap-free segment).
    #[arg(long, default_value = "refuse")]
    gaps: String,
    #[command(flatten)]
    common: Common,
}

#[derive(clap::Args)]
struct AnalyzeArgs {
    /// Lab recording (CSV; see `clino::testbench::recording` for the columns).
    recording: PathBuf,
    /// What the platform did: conical or orbit.
    #[arg(long, default_value = "conical")]
    excitation: String,
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

fn opt(v: Option<f64>) -> String {
    v.map_or("-".into(), |v| format!("{v:+.3}"))
}

/// Run `clino testbench`.
pub fn run(a: Args) -> anyhow::Result<()> {
    match a.cmd {
        Cmd::Conical(c) => {
            let mut cfg = ConicalConfig::new(
                c.alpha_deg.to_radians(),
                c.freq_hz,
                c.common.sensor()?,
                &c.common.filter,
            );
            cfg.rate_hz = c.common.rate_hz;
            cfg.seed = c.common.seed;
            cfg.platform = c.platform.spec();
            cfg.axis = match c.axis.as_str() {
                "x" => ConeAxis::X,
                "y" => ConeAxis::Y,
                "z" => ConeAxis::Z,
                other => anyhow::bail!("unknown cone axis '{other}' (x, y or z)"),
            };
            let pb = progress(cfg.freqs_hz.len());
            let pts = run_conical(&cfg, &mut |d, _| pb.set_position(d as u64))?;
            pb.finish_and_clear();
            if let Some(p) = &c.common.plot {
                plots::conical_plot(p, &pts)?;
            }
            if c.common.json {
                println!("{}", serde_json::to_string_pretty(&pts)?);
            } else {
                println!(
                    "freq_hz  alpha_deg gyro_x_db gyro_y_db gyro_z_db accel_x_db accel_y_db tilt_x_db tilt_y_db sin_phi_db tan_theta_db"
                );
                for p in &pts {
                    println!(
                        "{:7.3}  {:9.3} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>9} {:>10} {:>12}",
                        p.freq_hz,
                        p.alpha_deg,
                        opt(p.gyro_x_db),
                        opt(p.gyro_y_db),
                        opt(p.gyro_z_db),
                        opt(p.accel_x_db),
                        opt(p.accel_y_db),
                        opt(p.tilt_x_db),
                        opt(p.tilt_y_db),
                        opt(p.sin_phi_db),
                        opt(p.tan_theta_db)
                    );
                }
            }
        }
        Cmd::Orbit(o) => {
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
            if let Some(p) = &o.common.plot {
                plots::orbit_plot(p, &pts)?;
            }
            if o.common.json {
                println!("{}", serde_json::to_string_pretty(&pts)?);
            } else {
                println!(
                    "# tilt error under the orbit, degrees: *_pp = max − min, *_fit_pp = 2 × sine fitted at the orbit frequency"
                );
                if cfg.platform.is_some() {
                    println!(
                        "# on the simulated platform: orbit_*_mm = amplitude actually made, ref_*_pp_deg = the platform's own tilt (from forward kinematics of the legs)"
                    );
                }
                println!(
                    "freq_hz  roll_pp_deg pitch_pp_deg roll_fit_pp_deg pitch_fit_pp_deg  orbit_x_mm orbit_y_mm orbit_z_mm  ref_roll_pp_deg ref_pitch_pp_deg"
                );
                for p in &pts {
                    let [ax, ay, az] = p.orbit_amplitude_mm.unwrap_or([f64::NAN; 3]);
                    let [rr, rp] = p.reference_tilt_pp_deg.unwrap_or([f64::NAN; 2]);
                    println!(
                        "{:7.3}  {:11.4} {:12.4} {:15.4} {:16.4}  {:10.3} {:10.3} {:10.3}  {:15.2e} {:16.2e}",
                        p.freq_hz,
                        p.roll_pp_deg,
                        p.pitch_pp_deg,
                        p.roll_fit_pp_deg,
                        p.pitch_fit_pp_deg,
                        ax,
                        ay,
                        az,
                        rr,
                        rp
                    );
                }
            }
        }
        Cmd::Static(s) => {
            let r = match &s.recording {
                Some(path) => {
                    // the rules of `clino allan` too: comments, unused columns, gaps, dropouts
                    let rec = read_static_record(path, s.gaps.parse()?)?;
                    for n in &rec.notes {
                        eprintln!("warning: {n}");
                    }
                    rec.require(3, "a static test")?;
                    static_test::static_test(&rec.samples, &s.common.filter, s.settle_s)?
                }
                None => {
                    let m = s.common.sensor()?;
                    m.validate()?;
                    let smp = m.simulate(
                        &clino::sim::motion::Static::level(),
                        s.common.rate_hz,
                        s.duration_s,
                        s.common.seed,
                    );
                    static_test::static_test(&smp, &s.common.filter, s.settle_s)?
                }
            };
            if let Some(p) = &s.common.plot {
                plots::static_plot(p, &r)?;
            }
            if s.common.json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                println!(
                    "static test: filter {}, {:.1} s, {} samples",
                    r.filter, r.duration_s, r.samples
                );
                println!("angle  mean_deg   drift_deg  drift_rate_deg_s  noise_std_deg  pp_deg");
                for (n, d) in [("roll", r.roll), ("pitch", r.pitch)] {
                    println!(
                        "{n:<5}  {:+9.4}  {:+10.3e}  {:+16.3e}  {:13.3e}  {:9.3e}",
                        d.mean_deg, d.drift_deg, d.drift_rate_deg_s, d.noise_std_deg, d.pp_deg
                    );
                }
            }
        }
        Cmd::Analyze(a) => {
            let exc = excitation(&a.excitation)?;
            let t = Table::read(&a.recording)?;
            let r = analyze(&t, exc, &Geometry::typical(), a.freq_hz, a.skip_s).map_err(|e| {
                if e.file.is_none() {
                    e.in_file(&a.recording)
                } else {
                    e
                }
            })?;
            if a.json {
                println!("{}", serde_json::to_string_pretty(&r)?);
            } else {
                println!(
                    "reference: {:.4} Hz, amplitude {:.4} ({})",
                    r.freq_hz,
                    r.reference_amplitude,
                    match exc {
                        Excitation::Conical => "cone angle, deg",
                        Excitation::Orbit => "x orbit, mm",
                    }
                );
                if let Some(n) = r.fk_max_iterations {
                    println!("forward kinematics: at most {n} iterations per row");
                }
                if let Some(p) = &r.conical {
                    println!(
                        "gyro_x_db {} gyro_y_db {} accel_x_db {} accel_y_db {} tilt_x_db {} tilt_y_db {} sin_phi_db {} tan_theta_db {}",
                        opt(p.gyro_x_db),
                        opt(p.gyro_y_db),
                        opt(p.accel_x_db),
                        opt(p.accel_y_db),
                        opt(p.tilt_x_db),
                        opt(p.tilt_y_db),
                        opt(p.sin_phi_db),
                        opt(p.tan_theta_db)
                    );
                }
                if let Some(p) = &r.orbit {
                    println!(
                        "roll_pp_deg {:.4} pitch_pp_deg {:.4} roll_fit_pp_deg {:.4} pitch_fit_pp_deg {:.4}",
                        p.roll_pp_deg, p.pitch_pp_deg, p.roll_fit_pp_deg, p.pitch_fit_pp_deg
                    );
                }
            }
        }
        Cmd::Record(r) => {
            let exc = excitation(&r.excitation)?;
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
                &sensor(&r.sensor, r.bandwidth_hz)?,
                &r.filter,
                r.rate_hz,
                r.duration_s,
                r.seed,
            )?;
            eprintln!("wrote {}", r.out.display());
        }
    }
    Ok(())
}
