//! One module per subcommand, and the argument groups they share.
pub mod allan;
pub mod calibrate;
pub mod convert;
pub mod demo;
pub mod eval;
pub mod fuse;
pub mod redundancy;
pub mod stewart;
pub mod survey;
pub mod testbench;

use clino::io::{AccelUnit, GyroUnit, ReadOptions};

/// How to read a recording (shared by `fuse` and `eval`).
#[derive(clap::Args, Debug)]
pub struct ReadArgs {
    /// Unit of the gyro columns: rad/s (columns gyr_x_rad_s…) or deg/s (gyr_x_deg_s…); bare gyr_x… take this unit.
    #[arg(long, default_value = "rad/s", value_name = "rad/s|deg/s")]
    pub gyro_unit: String,
    /// Unit of the accelerometer columns: m/s2 (acc_x_m_s2…) or g (acc_x_g…); bare acc_x… take this unit.
    #[arg(long, default_value = "m/s2", value_name = "m/s2|g")]
    pub accel_unit: String,
    /// Sample rate in Hz, for files without a t_s column (time of row k = k / rate).
    #[arg(long, value_name = "HZ")]
    pub rate: Option<f64>,
}

impl ReadArgs {
    /// The library's read options.
    pub fn options(&self) -> clino::Result<ReadOptions> {
        Ok(ReadOptions {
            gyro_unit: self.gyro_unit.parse::<GyroUnit>()?,
            accel_unit: self.accel_unit.parse::<AccelUnit>()?,
            rate_hz: self.rate,
            ..ReadOptions::default()
        })
    }
}

/// Filter parameters given as flags (each applies to the filters that read it;
/// one that no chosen filter reads is an error). Every parameter can also be
/// given in the `--filter NAME:KEY=VALUE,…` form.
#[derive(clap::Args, Debug)]
pub struct GainArgs {
    /// Complementary filter blend per sample, 0..1 (time constant −Ts/ln(1−k)); default 0.05.
    #[arg(long)]
    pub k: Option<String>,
    /// Mahony proportional gain, rad/s per unit error; default 1.
    #[arg(long)]
    pub kp: Option<String>,
    /// Mahony integral gain, rad/s² per unit error; default 0.02.
    #[arg(long)]
    pub ki: Option<String>,
    /// Madgwick gradient step, rad/s; default 0.1.
    #[arg(long)]
    pub beta: Option<String>,
    /// Gyro integration step of poisson/complementary: exact (rotation vector) or rectangle (first order).
    #[arg(long, value_name = "exact|rectangle")]
    pub integrator: Option<String>,
    /// Dynamic filter: base loop bandwidth, rad/s (1/bandwidth is the accelerometer's time constant in slow motion); default 0.15.
    #[arg(long, value_name = "RAD_S")]
    pub bandwidth: Option<String>,
}

impl GainArgs {
    /// The flags given, as (parameter key, value).
    pub fn params(&self) -> Vec<(&'static str, String)> {
        [
            ("k", &self.k),
            ("kp", &self.kp),
            ("ki", &self.ki),
            ("beta", &self.beta),
            ("integrator", &self.integrator),
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
    /// `clino fuse --lever-arm auto` estimates it online from the recording (dynamic filter).
    /// With a lever arm the dynamic filter also estimates the horizontal accelerometer bias.
    #[arg(long, value_name = "X,Y,Z|auto", allow_hyphen_values = true)]
    pub lever_arm: Option<String>,
    /// Smooth offline over the whole recording (forward–backward passes and a bounded-motion
    /// refinement; dynamic filter only). Holds the recording in memory.
    #[arg(long)]
    pub offline: bool,
}

impl StageArgs {
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
