//! One module per subcommand, and the argument groups they share.
pub mod allan;
pub mod calibrate;
pub mod convert;
pub mod demo;
pub mod eval;
pub mod fuse;
pub mod redundancy;
pub mod stewart;
pub mod stream;
pub mod survey;
pub mod testbench;

use clap::ValueEnum;
use clino::fusion::{FilterConfig, apply_params, parse_spec};
use clino::io::{AccelUnit, GyroUnit, ReadOptions};
use std::path::PathBuf;

/// The output flags every command with a JSON form and a plot shares.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct OutputArgs {
    /// Print JSON to stdout instead of the text table.
    #[arg(long)]
    pub json: bool,
    /// Write a plot to FILE (.svg or .png).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// Print `value` as pretty JSON, or `text` as it is.
pub fn print_result<T: serde::Serialize>(
    json: bool,
    value: &T,
    text: impl FnOnce() -> String,
) -> anyhow::Result<()> {
    if json {
        println!("{}", serde_json::to_string_pretty(value)?);
    } else {
        print!("{}", text());
    }
    Ok(())
}

/// Unit of the gyro columns.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum GyroUnitArg {
    /// rad/s (columns gyr_x_rad_s…).
    #[value(name = "rad/s", alias = "rad_s")]
    RadS,
    /// deg/s (columns gyr_x_deg_s…).
    #[value(name = "deg/s", aliases = ["deg_s", "dps"])]
    DegS,
}

impl From<GyroUnitArg> for GyroUnit {
    fn from(u: GyroUnitArg) -> Self {
        match u {
            GyroUnitArg::RadS => GyroUnit::RadPerS,
            GyroUnitArg::DegS => GyroUnit::DegPerS,
        }
    }
}

/// Unit of the accelerometer columns.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum AccelUnitArg {
    /// m/s² (columns acc_x_m_s2…).
    #[value(name = "m/s2", aliases = ["m_s2", "m/s^2", "m/s²"])]
    MS2,
    /// multiples of g (columns acc_x_g…).
    #[value(name = "g")]
    G,
}

impl From<AccelUnitArg> for AccelUnit {
    fn from(u: AccelUnitArg) -> Self {
        match u {
            AccelUnitArg::MS2 => AccelUnit::MPerS2,
            AccelUnitArg::G => AccelUnit::G,
        }
    }
}

/// Gyro integration step of poisson/complementary.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum IntegratorArg {
    /// The rotation vector (Rodrigues).
    Exact,
    /// First order (the paper's rule).
    Rectangle,
}

/// A simulated sensor preset (clino::sim::ImuModel::preset).
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensorArg {
    /// No noise, no bias, no band limit.
    Ideal,
    /// MPU-6050 as a six-position calibration leaves it (a tenth of the raw errors).
    Mpu6050,
    /// MPU-6050 untrimmed: the datasheet's example errors.
    #[value(name = "mpu6050-raw")]
    Mpu6050Raw,
}

impl SensorArg {
    /// The library model, band-limited to `bandwidth_hz` when given.
    pub fn model(self, bandwidth_hz: Option<f64>) -> anyhow::Result<clino::sim::ImuModel> {
        let name = self
            .to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default();
        let m = clino::sim::ImuModel::preset(&name)?;
        Ok(match bandwidth_hz {
            Some(b) => m.with_bandwidth(b),
            None => m,
        })
    }
}

/// What to do with a gap in a recording's time stamps.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum GapsArg {
    /// An error naming the line.
    #[default]
    Refuse,
    /// Analyse the longest gap-free segment.
    Longest,
}

impl From<GapsArg> for clino::testbench::static_record::GapPolicy {
    fn from(g: GapsArg) -> Self {
        match g {
            GapsArg::Refuse => Self::Refuse,
            GapsArg::Longest => Self::Longest,
        }
    }
}

/// A progress indicator on stderr for a long command. indicatif draws
/// nothing when stderr is not a terminal, so logs and pipes stay clean.
pub fn progress_spinner(what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new_spinner();
    bar.set_message(what.to_string());
    bar
}

/// The fuse progress drawn on `bar`: a spinner while reading, then a bar over
/// the offline smoother's seven stages.
pub fn show_fuse_progress(bar: &indicatif::ProgressBar, p: clino::fusion::FuseProgress) {
    use clino::fusion::FuseProgress;
    match p {
        FuseProgress::Read(rows) => {
            bar.set_message(format!("read {rows} rows"));
            bar.tick();
        }
        FuseProgress::Smooth(stage, k, n) => {
            if bar.length() != Some(clino::smooth::Stage::COUNT * n as u64) {
                bar.set_style(
                    indicatif::ProgressStyle::with_template(
                        "{msg} [{bar:40}] {percent}% ({eta} left)",
                    )
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                );
                bar.set_length(clino::smooth::Stage::COUNT * n as u64);
            }
            bar.set_message(format!("offline smoothing ({stage:?})"));
            bar.set_position(stage.index() * n as u64 + k as u64);
        }
    }
}

/// The pipeline the flags name (`--filter`, the gain flags, `--lever-arm`,
/// `--offline`), checked: shared by `fuse` and `stream`.
pub fn filter_config(
    filter: &str,
    gains: &GainArgs,
    stages: &StageArgs,
) -> anyhow::Result<FilterConfig> {
    let mut spec = [parse_spec(filter)?];
    apply_params(&mut spec, &gains.params())?;
    // `--lever-arm auto`: estimated online from the recording (dynamic filter)
    let auto = stages
        .lever_arm
        .as_deref()
        .is_some_and(|s| s.trim().eq_ignore_ascii_case("auto"));
    let lever = if auto { None } else { stages.lever_arm()? };
    let config = FilterConfig::from_spec(spec[0])
        .with_lever_arm(lever)
        .with_lever_auto(auto)
        .with_offline(stages.offline)
        .with_sensor_range(stages.sensor_range()?)
        .with_sample_clock(stages.stamps.recover())
        .with_timing_given(clino::fusion::names_timing(filter));
    config.validate()?;
    Ok(config)
}

/// How to read a recording (shared by `fuse` and `eval`).
#[derive(clap::Args, Debug)]
pub struct ReadArgs {
    /// Unit of the gyro columns: rad/s (columns gyr_x_rad_s…) or deg/s (gyr_x_deg_s…); bare gyr_x… take this unit.
    #[arg(long, value_enum, default_value = "rad/s", ignore_case = true)]
    pub gyro_unit: GyroUnitArg,
    /// Unit of the accelerometer columns: m/s2 (acc_x_m_s2…) or g (acc_x_g…); bare acc_x… take this unit.
    #[arg(long, value_enum, default_value = "m/s2", ignore_case = true)]
    pub accel_unit: AccelUnitArg,
    /// Sample rate in Hz, for files without a t_s column (time of row k = k / rate).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
}

impl ReadArgs {
    /// The library's read options.
    pub fn options(&self) -> clino::Result<ReadOptions> {
        Ok(ReadOptions {
            gyro_unit: self.gyro_unit.into(),
            accel_unit: self.accel_unit.into(),
            rate_hz: self.rate,
            ..ReadOptions::default()
        })
    }
}

/// Filter parameters given as flags (each applies to the filters that read it;
/// one that no chosen filter reads is an error). Every parameter can also be
/// given in the `--filter NAME:KEY=VALUE,…` form. A negative value is taken
/// as a value (`--k -0.5`), so that its range error names the parameter.
#[derive(clap::Args, Debug)]
pub struct GainArgs {
    /// Complementary filter blend per sample, 0..1 (time constant −Ts/ln(1−k)); default 0.05.
    #[arg(long, allow_hyphen_values = true)]
    pub k: Option<String>,
    /// Mahony proportional gain, rad/s per unit error; default 1.
    #[arg(long, allow_hyphen_values = true)]
    pub kp: Option<String>,
    /// Mahony integral gain, rad/s² per unit error; default 0.02.
    #[arg(long, allow_hyphen_values = true)]
    pub ki: Option<String>,
    /// Madgwick gradient step, rad/s; default 0.1.
    #[arg(long, allow_hyphen_values = true)]
    pub beta: Option<String>,
    /// Gyro integration step of poisson/complementary: exact (rotation vector) or rectangle (first order).
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorArg>,
    /// Dynamic filter: base loop bandwidth, rad/s (1/bandwidth is the accelerometer's time constant in slow motion); default 0.15.
    #[arg(long, value_name = "RAD_S", allow_hyphen_values = true)]
    pub bandwidth: Option<String>,
}

impl GainArgs {
    /// The flags given, as (parameter key, value).
    pub fn params(&self) -> Vec<(&'static str, String)> {
        let integrator = self
            .integrator
            .and_then(|i| i.to_possible_value())
            .map(|v| v.get_name().to_string());
        [
            ("k", &self.k),
            ("kp", &self.kp),
            ("ki", &self.ki),
            ("beta", &self.beta),
            ("integrator", &integrator),
            ("bandwidth_rad_s", &self.bandwidth),
        ]
        .into_iter()
        .filter_map(|(k, v)| v.clone().map(|v| (k, v)))
        .collect()
    }
}

/// Pipeline stages around the filter, shared by `fuse` and `eval`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct StageArgs {
    /// Lever arm of the sensor from a point on the rotation axis, metres, body frame: "X,Y,Z".
    /// Tangential (dω/dt × r) and centripetal (ω × (ω × r)) acceleration are removed before fusion.
    /// `clino fuse --lever-arm auto` estimates it online from the recording (dynamic filter) and
    /// applies it, with the bias, once its terms predict at least three quarters of the
    /// recording's accelerations (a rigid body turning about a fixed axis); on a mount that has no such axis
    /// (a hand, a vehicle) it is reported, not applied. With a lever arm the dynamic filter also
    /// estimates the horizontal accelerometer bias.
    #[arg(long, value_name = "X,Y,Z|auto", allow_hyphen_values = true)]
    pub lever_arm: Option<String>,
    /// Smooth offline over the whole recording (forward–backward passes and a bounded-motion
    /// refinement; dynamic filter only). Holds the recording in memory.
    #[arg(long)]
    pub offline: bool,
    /// The gyro's full-scale range, °/s (an MPU6050 powers on at 250). A rate read at it
    /// is clipped: counted, and the dynamic filter realigns on the accelerometer after it and
    /// learns no scale error from the clipped turn. `clino stream` takes the board's own
    /// ranges when this is not given.
    #[arg(long, value_name = "DEG_S", allow_hyphen_values = true)]
    pub gyro_range: Option<f64>,
    /// The accelerometer's full-scale range, g (an MPU6050 powers on at 2). A specific force
    /// read at it is clipped: counted, and the dynamic filter forgets the part beyond the
    /// range within a second.
    #[arg(long, value_name = "G", allow_hyphen_values = true)]
    pub acc_range: Option<f64>,
    /// Where each step's time comes from. recover: time stamps a host made as each sample
    /// arrived (off by milliseconds: USB packets, scheduling) are put back on the sensor's own
    /// clock, recovered from the stamps; a sensor's own stamps give their steps unchanged.
    /// as-given: the stamps' steps as they are.
    #[arg(long, value_enum, default_value = "recover")]
    pub stamps: StampsArg,
}

/// Where each step's time comes from (`--stamps`).
#[derive(ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StampsArg {
    /// The sensor's sample clock recovered from the stamps.
    #[default]
    Recover,
    /// The stamps as they are.
    #[value(name = "as-given")]
    AsGiven,
}

impl StampsArg {
    /// Whether to recover the sample clock ([`clino::fusion::FilterConfig::sample_clock`]).
    pub fn recover(self) -> bool {
        self == StampsArg::Recover
    }
}

impl StageArgs {
    /// The sensor's ranges the flags give (infinite where not given).
    pub fn sensor_range(&self) -> anyhow::Result<clino::fusion::SensorRange> {
        let mut r = clino::fusion::SensorRange::default();
        for (flag, v, unit, out) in [
            (
                "--gyro-range",
                self.gyro_range,
                1f64.to_radians(),
                &mut r.gyro_rad_s,
            ),
            (
                "--acc-range",
                self.acc_range,
                clino::core::G0,
                &mut r.acc_m_s2,
            ),
        ] {
            if let Some(v) = v {
                if !(v.is_finite() && v > 0.0) {
                    anyhow::bail!("{flag} wants a positive full-scale range, got {v}");
                }
                *out = v * unit;
            }
        }
        Ok(r)
    }

    /// The lever arm in metres, parsed from "X,Y,Z".
    pub fn lever_arm(&self) -> anyhow::Result<Option<nalgebra::Vector3<f64>>> {
        let Some(s) = &self.lever_arm else {
            return Ok(None);
        };
        let v: Vec<f64> = s
            .split(',')
            .map(|x| x.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                anyhow::anyhow!("--lever-arm wants three numbers in metres, \"X,Y,Z\", got '{s}'")
            })?;
        if v.len() != 3 || !v.iter().all(|x| x.is_finite()) {
            anyhow::bail!("--lever-arm wants three finite numbers in metres, \"X,Y,Z\", got '{s}'");
        }
        Ok(Some(nalgebra::Vector3::new(v[0], v[1], v[2])))
    }
}
