//! One filter specification: which filter, with every one of its parameters.
//!
//! [`FilterSpec`] is the single typed value every way of choosing a filter
//! ends in: the command line's `--filter NAME` with its gain flags, the
//! `name:key=value,…` form of the test bench and of `clino eval`, the Python
//! keyword arguments, and the microcontroller's constants. Defaults live here
//! and nowhere else ([`FilterSpec::default_for`], and [`DynamicParams::default`]
//! for the dynamic filter). [`FilterSpec::params`] lists each filter's
//! parameters with their unit and meaning ([`ParamInfo`]); [`FilterSpec::set`]
//! changes one by key and checks its range, so no parameter can be set to a
//! value its filter cannot use, and no key can be given to a filter that
//! does not read it.
//!
//! ```
//! use clino_core::filter::{FilterKind, FilterSpec};
//! let mut s = FilterSpec::default_for(FilterKind::Mahony);
//! s.set("kp", "0.5").unwrap();
//! assert_eq!(s, FilterSpec::Mahony { kp: 0.5, ki: 0.02 });
//! assert!(s.set("beta", "0.1").is_err()); // Madgwick's, not Mahony's
//! assert!(s.set("kp", "-1").is_err());
//! ```

use super::{
    AttitudeFilter, Complementary, Dynamic, DynamicParams, Integrator, Madgwick, Mahony, Poisson,
    Step,
};
use crate::{Attitude, Vec3};

/// The attitude filters, by the name used on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FilterKind {
    /// Gyro-only strapdown integration of the Poisson equation ([`Poisson`]).
    Poisson,
    /// The DCM complementary filter of the MPU6050 + Arduino inclinometer ([`Complementary`]).
    Complementary,
    /// Mahony's proportional-integral filter ([`Mahony`]).
    Mahony,
    /// Madgwick's gradient-descent filter ([`Madgwick`]).
    Madgwick,
    /// clino's dynamic inclinometer filter ([`Dynamic`]).
    Dynamic,
}

impl FilterKind {
    /// Every filter, in the order tables list them.
    pub const ALL: [FilterKind; 5] = [
        FilterKind::Poisson,
        FilterKind::Complementary,
        FilterKind::Mahony,
        FilterKind::Madgwick,
        FilterKind::Dynamic,
    ];

    /// The command-line name.
    pub const fn name(self) -> &'static str {
        match self {
            FilterKind::Poisson => "poisson",
            FilterKind::Complementary => "complementary",
            FilterKind::Mahony => "mahony",
            FilterKind::Madgwick => "madgwick",
            FilterKind::Dynamic => "dynamic",
        }
    }

    /// The kind named `name` (ASCII case ignored), `None` when unknown.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
    }
}

impl core::fmt::Display for FilterKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

/// How the complementary filter's accelerometer blend is given.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Blend {
    /// Weight k per sample, in [0, 1] (the paper's form; its time constant
    /// τ = −T_s/ln(1 − k) depends on the sample period T_s).
    PerSample(f64),
    /// Time constant τ, s: k = 1 − exp(−dt/τ) is formed from each sample's dt,
    /// so the filter behaves the same at any rate.
    TimeConstant(f64),
}

/// Which filter, with every parameter it reads (SI units). The defaults of
/// every filter are those of [`FilterSpec::default_for`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterSpec {
    /// [`Poisson`]: gyro-only strapdown integration.
    Poisson {
        /// Integration rule (default exact).
        integrator: Integrator,
    },
    /// [`Complementary`]: C = (1 − k)·C_gyro + k·C_acc.
    Complementary {
        /// Accelerometer blend (default k = 0.05 per sample, the paper's value).
        blend: Blend,
        /// Integration rule of C_gyro (default rectangle, as in the paper).
        integrator: Integrator,
    },
    /// [`Mahony`]: proportional-integral rate correction.
    Mahony {
        /// Proportional gain, rad/s per unit of error (default 1).
        kp: f64,
        /// Integral gain, rad/s² per unit of error (default 0.02).
        ki: f64,
    },
    /// [`Madgwick`]: gradient-descent step.
    Madgwick {
        /// Gradient step β, rad/s (default 0.1).
        beta: f64,
    },
    /// [`Dynamic`]: clino's own filter; every parameter is documented on [`DynamicParams`].
    Dynamic(DynamicParams),
}

impl Default for FilterSpec {
    /// The dynamic filter at its defaults.
    fn default() -> Self {
        Self::default_for(FilterKind::Dynamic)
    }
}

/// What kind of value a parameter takes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParamType {
    /// A number in `[min, max]` (`min` excluded when `min_exclusive`).
    Number {
        /// Smallest value.
        min: f64,
        /// Largest value.
        max: f64,
        /// True when `min` itself is not allowed.
        min_exclusive: bool,
    },
    /// `true`/`false` (or `1`/`0`).
    Bool,
    /// `exact` or `rectangle` ([`Integrator`]).
    Integrator,
}

// Number(min, max, min_exclusive) as a const expression
const fn num(min: f64, max: f64, min_exclusive: bool) -> ParamType {
    ParamType::Number {
        min,
        max,
        min_exclusive,
    }
}
const POSITIVE: ParamType = num(0.0, 1e9, true);
const NON_NEGATIVE: ParamType = num(0.0, 1e9, false);

/// One parameter of one filter: its key, unit and meaning.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParamInfo {
    /// Key, as written after `name:` (`bandwidth_rad_s`); the part before the
    /// unit suffix is accepted too (`bandwidth`).
    pub key: &'static str,
    /// Unit (`rad/s`, `s`, `1` for a plain number, `-` for a choice).
    pub unit: &'static str,
    /// The value it takes.
    pub ty: ParamType,
    /// One line on its meaning.
    pub doc: &'static str,
}

const fn p(key: &'static str, unit: &'static str, ty: ParamType, doc: &'static str) -> ParamInfo {
    ParamInfo { key, unit, ty, doc }
}

const POISSON_PARAMS: [ParamInfo; 1] = [p(
    "integrator",
    "-",
    ParamType::Integrator,
    "gyro step: exact (Rodrigues) or rectangle (the paper's first-order rule)",
)];
const COMPLEMENTARY_PARAMS: [ParamInfo; 3] = [
    p(
        "k",
        "1",
        num(0.0, 1.0, false),
        "accelerometer blend per sample (τ = −T_s/ln(1 − k))",
    ),
    p(
        "tau_s",
        "s",
        POSITIVE,
        "blend time constant instead of k: k = 1 − exp(−dt/τ) at every sample",
    ),
    p(
        "integrator",
        "-",
        ParamType::Integrator,
        "gyro step: rectangle (the paper's) or exact",
    ),
];
const MAHONY_PARAMS: [ParamInfo; 2] = [
    p(
        "kp",
        "rad/s",
        NON_NEGATIVE,
        "proportional gain per unit of error",
    ),
    p("ki", "rad/s²", NON_NEGATIVE, "integral (gyro-bias) gain"),
];
const MADGWICK_PARAMS: [ParamInfo; 1] = [p(
    "beta",
    "rad/s",
    NON_NEGATIVE,
    "gradient step (gyro error it corrects)",
)];
const DYNAMIC_PARAMS: [ParamInfo; 27] = [
    p(
        "bandwidth_rad_s",
        "rad/s",
        num(0.0, 100.0, true),
        "base loop bandwidth p₀ (1/p₀: time the accelerometer takes to correct tilt)",
    ),
    p(
        "velocity_damping",
        "1",
        POSITIVE,
        "velocity-leak factor a (k_u = a·p)",
    ),
    p(
        "tilt_gain",
        "1",
        POSITIVE,
        "tilt-gain factor b (k_θ = b·p²)",
    ),
    p(
        "bias_gain",
        "1",
        NON_NEGATIVE,
        "bias-gain factor c (k_b = c·p₀²·p)",
    ),
    p(
        "scale_rate_rad_s",
        "rad/s",
        POSITIVE,
        "rate where gyro scale drift equals bias drift: bandwidth √2·p₀; motion learning half to each",
    ),
    p(
        "rest_gyr_rad_s",
        "rad/s",
        POSITIVE,
        "rest threshold on the low-passed rate",
    ),
    p(
        "rest_gyr_initial_rad_s",
        "rad/s",
        POSITIVE,
        "rest threshold until the bias has been learnt",
    ),
    p(
        "rest_acc_m_s2",
        "m/s²",
        POSITIVE,
        "rest threshold on the low-passed specific force",
    ),
    p(
        "rest_time_s",
        "s",
        NON_NEGATIVE,
        "time the rest thresholds must hold",
    ),
    p(
        "rest_bias_tau_s",
        "s",
        POSITIVE,
        "time constant of bias learning at rest",
    ),
    p(
        "bias_memory_s",
        "s",
        POSITIVE,
        "memory of the rest bias estimate while moving",
    ),
    p(
        "lowpass_tau_s",
        "s",
        POSITIVE,
        "low-pass of |ω| for the bandwidth adaptation",
    ),
    p(
        "rest_lowpass_tau_s",
        "s",
        POSITIVE,
        "low-pass rest detection compares the rate with",
    ),
    p(
        "rest_window_s",
        "s",
        POSITIVE,
        "longest memory of the stillness means rest compares with",
    ),
    p(
        "vibration_tau_s",
        "s",
        POSITIVE,
        "vibration low-pass before rest detection",
    ),
    p(
        "bias_max_rad_s",
        "rad/s",
        NON_NEGATIVE,
        "largest gyro bias believed, per axis",
    ),
    p(
        "start_bandwidth_rad_s",
        "rad/s",
        POSITIVE,
        "bandwidth at start-up",
    ),
    p(
        "start_time_s",
        "s",
        NON_NEGATIVE,
        "time over which the start-up bandwidth falls to p₀",
    ),
    p(
        "alignment_s",
        "s",
        NON_NEGATIVE,
        "rest time after power-on during which tilt is also aligned",
    ),
    p(
        "rest_pull_rad_s",
        "rad/s",
        NON_NEGATIVE,
        "pull of the tilt to the accelerometer at later rests (0: off, where slow translations pass for rest)",
    ),
    p(
        "gyro_scale_sigma",
        "1",
        num(0.0, 1.0, false),
        "prior 1σ of the gyro scale errors learnt from rest to rest (0: off)",
    ),
    p(
        "accel_scale_sigma",
        "1",
        num(0.0, 1.0, false),
        "prior 1σ of the accelerometer scale errors learnt from rest to rest (0: off)",
    ),
    p(
        "accel_bias_sigma",
        "m/s²",
        num(0.0, 10.0, false),
        "prior 1σ of the accelerometer bias learnt from rest to rest (0: off)",
    ),
    p(
        "sensor_delay_periods",
        "periods",
        num(0.0, 100.0, false),
        "the sensor's delay of its samples behind their time stamps (its anti-alias filter; the gyro's where the two triads differ, gyro_lag_s), in sample periods; the output is carried over it",
    ),
    p(
        "gyro_lag_s",
        "s",
        num(-0.1, 0.1, false),
        "how much later the gyro's samples stand for than the accelerometer's (0.00098 for an MPU6050 at DLPF_CFG 0)",
    ),
    p(
        "gravity_m_s2",
        "m/s²",
        num(0.0, 100.0, true),
        "local gravity",
    ),
    p(
        "learn_bias",
        "-",
        ParamType::Bool,
        "learn the gyro bias (at rest and in motion)",
    ),
];

/// Why [`FilterSpec::set`] refused a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamError {
    /// The filter has no parameter of that key.
    UnknownKey,
    /// The value does not parse as the parameter's type.
    NotAValue,
    /// The value is outside the parameter's range.
    OutOfRange,
}

impl core::fmt::Display for ParamError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            ParamError::UnknownKey => "no such parameter for this filter",
            ParamError::NotAValue => "not a value of the parameter's type",
            ParamError::OutOfRange => "out of the parameter's range",
        })
    }
}

impl ParamInfo {
    /// True when `key` names this parameter (in full, or without its unit suffix).
    pub fn matches(&self, key: &str) -> bool {
        let key = key.trim();
        if self.key.eq_ignore_ascii_case(key) {
            return true;
        }
        for suffix in ["_rad_s", "_m_s2", "_s", "_periods"] {
            if let Some(stem) = self.key.strip_suffix(suffix)
                && stem.eq_ignore_ascii_case(key)
            {
                return true;
            }
        }
        false
    }

    fn parse(&self, value: &str) -> Result<Value, ParamError> {
        let v = value.trim();
        match self.ty {
            ParamType::Number {
                min,
                max,
                min_exclusive,
            } => {
                let x: f64 = v.parse().map_err(|_| ParamError::NotAValue)?;
                let low_ok = if min_exclusive { x > min } else { x >= min };
                if x.is_finite() && low_ok && x <= max {
                    Ok(Value::Number(x))
                } else {
                    Err(ParamError::OutOfRange)
                }
            }
            ParamType::Bool => match v {
                "1" => Ok(Value::Bool(true)),
                "0" => Ok(Value::Bool(false)),
                _ if v.eq_ignore_ascii_case("true") => Ok(Value::Bool(true)),
                _ if v.eq_ignore_ascii_case("false") => Ok(Value::Bool(false)),
                _ => Err(ParamError::NotAValue),
            },
            ParamType::Integrator => {
                if v.eq_ignore_ascii_case("exact") {
                    Ok(Value::Integrator(Integrator::Exact))
                } else if v.eq_ignore_ascii_case("rectangle") || v.eq_ignore_ascii_case("rect") {
                    Ok(Value::Integrator(Integrator::Rectangle))
                } else {
                    Err(ParamError::NotAValue)
                }
            }
        }
    }
}

/// The value of one parameter ([`FilterSpec::get`]); `Display` writes the
/// text form that [`FilterSpec::set`] reads back.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Value {
    /// A number, in the parameter's unit.
    Number(f64),
    /// A switch.
    Bool(bool),
    /// An integration rule.
    Integrator(Integrator),
}

impl core::fmt::Display for Value {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Value::Number(x) => write!(f, "{x}"),
            Value::Bool(b) => write!(f, "{b}"),
            Value::Integrator(Integrator::Exact) => f.write_str("exact"),
            Value::Integrator(Integrator::Rectangle) => f.write_str("rectangle"),
        }
    }
}

impl Value {
    fn num(&self) -> f64 {
        match self {
            Value::Number(x) => *x,
            _ => f64::NAN,
        }
    }
}

impl FilterSpec {
    /// The filter `kind` at its defaults: Poisson exact; complementary
    /// k = 0.05 per sample with the rectangle rule (Sapegin & Strokach);
    /// Mahony kp = 1 rad/s, ki = 0.02 rad/s²; Madgwick β = 0.1 rad/s;
    /// dynamic [`DynamicParams::default`].
    pub fn default_for(kind: FilterKind) -> Self {
        match kind {
            FilterKind::Poisson => FilterSpec::Poisson {
                integrator: Integrator::Exact,
            },
            FilterKind::Complementary => FilterSpec::Complementary {
                blend: Blend::PerSample(0.05),
                integrator: Integrator::Rectangle,
            },
            FilterKind::Mahony => FilterSpec::Mahony { kp: 1.0, ki: 0.02 },
            FilterKind::Madgwick => FilterSpec::Madgwick { beta: 0.1 },
            FilterKind::Dynamic => FilterSpec::Dynamic(DynamicParams::default()),
        }
    }

    /// Which filter.
    pub fn kind(&self) -> FilterKind {
        match self {
            FilterSpec::Poisson { .. } => FilterKind::Poisson,
            FilterSpec::Complementary { .. } => FilterKind::Complementary,
            FilterSpec::Mahony { .. } => FilterKind::Mahony,
            FilterSpec::Madgwick { .. } => FilterKind::Madgwick,
            FilterSpec::Dynamic(_) => FilterKind::Dynamic,
        }
    }

    /// The parameters of filter `kind`, with units and meaning.
    pub fn params(kind: FilterKind) -> &'static [ParamInfo] {
        match kind {
            FilterKind::Poisson => &POISSON_PARAMS,
            FilterKind::Complementary => &COMPLEMENTARY_PARAMS,
            FilterKind::Mahony => &MAHONY_PARAMS,
            FilterKind::Madgwick => &MADGWICK_PARAMS,
            FilterKind::Dynamic => &DYNAMIC_PARAMS,
        }
    }

    /// The parameter of this filter named `key` (full key or without its unit suffix).
    pub fn param(&self, key: &str) -> Option<&'static ParamInfo> {
        Self::params(self.kind()).iter().find(|p| p.matches(key))
    }

    /// Set one parameter from its text form, checking its type and range.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), ParamError> {
        let info = self.param(key).ok_or(ParamError::UnknownKey)?;
        let v = info.parse(value)?;
        let k = info.key;
        match self {
            FilterSpec::Poisson { integrator } => {
                if let Value::Integrator(i) = v {
                    *integrator = i;
                }
            }
            FilterSpec::Complementary { blend, integrator } => match (k, v) {
                ("k", v) => *blend = Blend::PerSample(v.num()),
                ("tau_s", v) => *blend = Blend::TimeConstant(v.num()),
                (_, Value::Integrator(i)) => *integrator = i,
                _ => return Err(ParamError::UnknownKey),
            },
            FilterSpec::Mahony { kp, ki } => match k {
                "kp" => *kp = v.num(),
                _ => *ki = v.num(),
            },
            FilterSpec::Madgwick { beta } => *beta = v.num(),
            FilterSpec::Dynamic(d) => {
                if let Value::Bool(b) = v {
                    d.learn_bias = b;
                    return Ok(());
                }
                let x = v.num();
                let slot = match k {
                    "bandwidth_rad_s" => &mut d.bandwidth_rad_s,
                    "velocity_damping" => &mut d.velocity_damping,
                    "tilt_gain" => &mut d.tilt_gain,
                    "bias_gain" => &mut d.bias_gain,
                    "scale_rate_rad_s" => &mut d.scale_rate_rad_s,
                    "rest_gyr_rad_s" => &mut d.rest_gyr_rad_s,
                    "rest_gyr_initial_rad_s" => &mut d.rest_gyr_initial_rad_s,
                    "rest_acc_m_s2" => &mut d.rest_acc_m_s2,
                    "rest_time_s" => &mut d.rest_time_s,
                    "rest_bias_tau_s" => &mut d.rest_bias_tau_s,
                    "bias_memory_s" => &mut d.bias_memory_s,
                    "lowpass_tau_s" => &mut d.lowpass_tau_s,
                    "rest_window_s" => &mut d.rest_window_s,
                    "rest_lowpass_tau_s" => &mut d.rest_lowpass_tau_s,
                    "vibration_tau_s" => &mut d.vibration_tau_s,
                    "bias_max_rad_s" => &mut d.bias_max_rad_s,
                    "start_bandwidth_rad_s" => &mut d.start_bandwidth_rad_s,
                    "start_time_s" => &mut d.start_time_s,
                    "alignment_s" => &mut d.alignment_s,
                    "rest_pull_rad_s" => &mut d.rest_pull_rad_s,
                    "gyro_scale_sigma" => &mut d.gyro_scale_sigma,
                    "accel_scale_sigma" => &mut d.accel_scale_sigma,
                    "accel_bias_sigma" => &mut d.accel_bias_sigma,
                    "sensor_delay_periods" => &mut d.sensor_delay_periods,
                    "gyro_lag_s" => &mut d.gyro_lag_s,
                    "gravity_m_s2" => &mut d.gravity_m_s2,
                    _ => return Err(ParamError::UnknownKey),
                };
                *slot = x;
            }
        }
        Ok(())
    }

    /// The value of the parameter named `key` (`None` when this filter has no
    /// such parameter, or for the blend form not in use: `k` of a
    /// complementary filter given by `tau_s`, and the reverse).
    pub fn get(&self, key: &str) -> Option<Value> {
        let info = self.param(key)?;
        let n = Value::Number;
        Some(match (self, info.key) {
            (FilterSpec::Poisson { integrator }, _) => Value::Integrator(*integrator),
            (FilterSpec::Complementary { blend, .. }, "k") => match blend {
                Blend::PerSample(k) => n(*k),
                Blend::TimeConstant(_) => return None,
            },
            (FilterSpec::Complementary { blend, .. }, "tau_s") => match blend {
                Blend::TimeConstant(t) => n(*t),
                Blend::PerSample(_) => return None,
            },
            (FilterSpec::Complementary { integrator, .. }, _) => Value::Integrator(*integrator),
            (FilterSpec::Mahony { kp, .. }, "kp") => n(*kp),
            (FilterSpec::Mahony { ki, .. }, _) => n(*ki),
            (FilterSpec::Madgwick { beta }, _) => n(*beta),
            (FilterSpec::Dynamic(d), k) => match k {
                "learn_bias" => Value::Bool(d.learn_bias),
                "bandwidth_rad_s" => n(d.bandwidth_rad_s),
                "velocity_damping" => n(d.velocity_damping),
                "tilt_gain" => n(d.tilt_gain),
                "bias_gain" => n(d.bias_gain),
                "scale_rate_rad_s" => n(d.scale_rate_rad_s),
                "rest_gyr_rad_s" => n(d.rest_gyr_rad_s),
                "rest_gyr_initial_rad_s" => n(d.rest_gyr_initial_rad_s),
                "rest_acc_m_s2" => n(d.rest_acc_m_s2),
                "rest_time_s" => n(d.rest_time_s),
                "rest_bias_tau_s" => n(d.rest_bias_tau_s),
                "bias_memory_s" => n(d.bias_memory_s),
                "lowpass_tau_s" => n(d.lowpass_tau_s),
                "rest_window_s" => n(d.rest_window_s),
                "rest_lowpass_tau_s" => n(d.rest_lowpass_tau_s),
                "vibration_tau_s" => n(d.vibration_tau_s),
                "bias_max_rad_s" => n(d.bias_max_rad_s),
                "start_bandwidth_rad_s" => n(d.start_bandwidth_rad_s),
                "start_time_s" => n(d.start_time_s),
                "alignment_s" => n(d.alignment_s),
                "rest_pull_rad_s" => n(d.rest_pull_rad_s),
                "gyro_scale_sigma" => n(d.gyro_scale_sigma),
                "accel_scale_sigma" => n(d.accel_scale_sigma),
                "accel_bias_sigma" => n(d.accel_bias_sigma),
                "sensor_delay_periods" => n(d.sensor_delay_periods),
                "gyro_lag_s" => n(d.gyro_lag_s),
                "gravity_m_s2" => n(d.gravity_m_s2),
                _ => return None,
            },
        })
    }

    /// Check every parameter against its range (what [`FilterSpec::set`]
    /// guarantees, for a spec built field by field).
    pub fn validate(&self) -> Result<(), (&'static str, ParamError)> {
        let check = |key: &'static str, x: f64| -> Result<(), (&'static str, ParamError)> {
            let info = Self::params(self.kind())
                .iter()
                .find(|p| p.key == key)
                .ok_or((key, ParamError::UnknownKey))?;
            if let ParamType::Number {
                min,
                max,
                min_exclusive,
            } = info.ty
            {
                let low_ok = if min_exclusive { x > min } else { x >= min };
                if !(x.is_finite() && low_ok && x <= max) {
                    return Err((key, ParamError::OutOfRange));
                }
            }
            Ok(())
        };
        match self {
            FilterSpec::Poisson { .. } => Ok(()),
            FilterSpec::Complementary { blend, .. } => match blend {
                Blend::PerSample(k) => check("k", *k),
                Blend::TimeConstant(t) => check("tau_s", *t),
            },
            FilterSpec::Mahony { kp, ki } => {
                check("kp", *kp)?;
                check("ki", *ki)
            }
            FilterSpec::Madgwick { beta } => check("beta", *beta),
            FilterSpec::Dynamic(d) => {
                let all = [
                    ("bandwidth_rad_s", d.bandwidth_rad_s),
                    ("velocity_damping", d.velocity_damping),
                    ("tilt_gain", d.tilt_gain),
                    ("bias_gain", d.bias_gain),
                    ("scale_rate_rad_s", d.scale_rate_rad_s),
                    ("rest_gyr_rad_s", d.rest_gyr_rad_s),
                    ("rest_gyr_initial_rad_s", d.rest_gyr_initial_rad_s),
                    ("rest_acc_m_s2", d.rest_acc_m_s2),
                    ("rest_time_s", d.rest_time_s),
                    ("rest_bias_tau_s", d.rest_bias_tau_s),
                    ("bias_memory_s", d.bias_memory_s),
                    ("lowpass_tau_s", d.lowpass_tau_s),
                    ("rest_window_s", d.rest_window_s),
                    ("rest_lowpass_tau_s", d.rest_lowpass_tau_s),
                    ("vibration_tau_s", d.vibration_tau_s),
                    ("bias_max_rad_s", d.bias_max_rad_s),
                    ("start_bandwidth_rad_s", d.start_bandwidth_rad_s),
                    ("start_time_s", d.start_time_s),
                    ("alignment_s", d.alignment_s),
                    ("rest_pull_rad_s", d.rest_pull_rad_s),
                    ("gyro_scale_sigma", d.gyro_scale_sigma),
                    ("accel_scale_sigma", d.accel_scale_sigma),
                    ("accel_bias_sigma", d.accel_bias_sigma),
                    ("sensor_delay_periods", d.sensor_delay_periods),
                    ("gyro_lag_s", d.gyro_lag_s),
                    ("gravity_m_s2", d.gravity_m_s2),
                ];
                for (k, x) in all {
                    check(k, x)?;
                }
                Ok(())
            }
        }
    }

    /// A fresh, uninitialised filter of this specification.
    pub fn build(&self) -> AnyFilter {
        match *self {
            FilterSpec::Poisson { integrator } => AnyFilter::Poisson(Poisson::new(integrator)),
            FilterSpec::Complementary { blend, integrator } => {
                let (k, tau) = match blend {
                    Blend::PerSample(k) => (k, None),
                    Blend::TimeConstant(t) => (0.05, Some(t)),
                };
                AnyFilter::Complementary(Complementary::with_integrator(k, integrator), tau)
            }
            FilterSpec::Mahony { kp, ki } => AnyFilter::Mahony(Mahony::new(kp, ki)),
            FilterSpec::Madgwick { beta } => AnyFilter::Madgwick(Madgwick::new(beta)),
            FilterSpec::Dynamic(p) => AnyFilter::Dynamic(Dynamic::new(p)),
        }
    }
}

/// Any of the five filters, by value (no allocation, no dynamic dispatch):
/// what [`FilterSpec::build`] makes and [`crate::pipeline::Pipeline`] runs.
#[derive(Clone, Debug)]
// the core allocates nothing: the filter is held by value, not boxed
#[allow(clippy::large_enum_variant)]
pub enum AnyFilter {
    /// [`Poisson`].
    Poisson(Poisson),
    /// [`Complementary`], with its blend time constant (s) when k follows dt.
    Complementary(Complementary, Option<f64>),
    /// [`Mahony`].
    Mahony(Mahony),
    /// [`Madgwick`].
    Madgwick(Madgwick),
    /// [`Dynamic`].
    Dynamic(Dynamic),
}

impl AnyFilter {
    /// The dynamic filter inside, when this is one (the offline smoother
    /// imposes its bias trajectory through it).
    pub fn as_dynamic_mut(&mut self) -> Option<&mut Dynamic> {
        match self {
            AnyFilter::Dynamic(d) => Some(d),
            _ => None,
        }
    }

    /// The dynamic filter inside, when this is one.
    pub fn as_dynamic(&self) -> Option<&Dynamic> {
        match self {
            AnyFilter::Dynamic(d) => Some(d),
            _ => None,
        }
    }
}

macro_rules! each {
    ($self:expr, $f:ident => $e:expr) => {
        match $self {
            AnyFilter::Poisson($f) => $e,
            AnyFilter::Complementary($f, _) => $e,
            AnyFilter::Mahony($f) => $e,
            AnyFilter::Madgwick($f) => $e,
            AnyFilter::Dynamic($f) => $e,
        }
    };
}

impl AttitudeFilter for AnyFilter {
    fn name(&self) -> &'static str {
        each!(self, f => f.name())
    }
    #[inline]
    fn update(&mut self, gyr: Vec3, acc: Vec3, dt: f64) -> Step {
        if let AnyFilter::Complementary(c, Some(tau)) = self
            && dt.is_finite()
            && dt > 0.0
        {
            c.k = Complementary::k_for(*tau, dt);
        }
        each!(self, f => f.update(gyr, acc, dt))
    }
    #[inline]
    fn attitude(&self) -> Attitude {
        each!(self, f => f.attitude())
    }
    #[inline]
    fn is_initialised(&self) -> bool {
        each!(self, f => f.is_initialised())
    }
    fn reset(&mut self) {
        each!(self, f => f.reset())
    }
    fn gyro_bias(&self) -> Vec3 {
        each!(self, f => f.gyro_bias())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_of_every_filter_can_be_set_and_reads_back() {
        for kind in FilterKind::ALL {
            for info in FilterSpec::params(kind) {
                let mut s = FilterSpec::default_for(kind);
                let value = match info.ty {
                    ParamType::Number { min, max, .. } => {
                        if max <= 0.1 {
                            "0.05"
                        } else if max <= 1.0 {
                            "0.5"
                        } else if min >= 0.0 {
                            "1.25"
                        } else {
                            "0"
                        }
                    }
                    ParamType::Bool => "false",
                    // the other rule than the filter's default
                    ParamType::Integrator if kind == FilterKind::Complementary => "exact",
                    ParamType::Integrator => "rectangle",
                };
                s.set(info.key, value).unwrap();
                assert_ne!(
                    s,
                    FilterSpec::default_for(kind),
                    "{kind}:{} did not change the spec",
                    info.key
                );
                assert!(s.validate().is_ok(), "{kind}:{}", info.key);
                // get writes the text form set reads back
                let mut again = FilterSpec::default_for(kind);
                let text = std::format!("{}", s.get(info.key).unwrap());
                again.set(info.key, &text).unwrap();
                assert_eq!(again, s, "{kind}:{}", info.key);
                // the short key (without unit suffix) names the same parameter
                let short = info
                    .key
                    .trim_end_matches("_rad_s")
                    .trim_end_matches("_m_s2")
                    .trim_end_matches("_periods")
                    .trim_end_matches("_s");
                assert!(info.matches(short), "{}", info.key);
            }
        }
    }

    #[test]
    fn wrong_key_type_and_range_are_refused() {
        let mut s = FilterSpec::default_for(FilterKind::Dynamic);
        assert_eq!(s.set("kp", "1"), Err(ParamError::UnknownKey));
        assert_eq!(s.set("bandwidth", "x"), Err(ParamError::NotAValue));
        assert_eq!(s.set("bandwidth", "0"), Err(ParamError::OutOfRange));
        assert_eq!(s.set("bandwidth", "NaN"), Err(ParamError::OutOfRange));
        assert_eq!(s.set("learn_bias", "2"), Err(ParamError::NotAValue));
        let mut c = FilterSpec::default_for(FilterKind::Complementary);
        assert_eq!(c.set("k", "1.5"), Err(ParamError::OutOfRange));
        c.set("tau", "0.2").unwrap();
        assert_eq!(
            c,
            FilterSpec::Complementary {
                blend: Blend::TimeConstant(0.2),
                integrator: Integrator::Rectangle
            }
        );
        let bad = FilterSpec::Madgwick { beta: -1.0 };
        assert_eq!(bad.validate(), Err(("beta", ParamError::OutOfRange)));
    }

    #[test]
    fn time_constant_blend_gives_the_same_filter_at_any_rate() {
        // k from tau at 100 Hz equals Complementary::k_for; the built filter uses it per dt.
        let spec = FilterSpec::Complementary {
            blend: Blend::TimeConstant(0.195),
            integrator: Integrator::Rectangle,
        };
        let mut f = spec.build();
        let acc = Vec3::new(0.0, 0.0, 9.81);
        f.update(Vec3::zeros(), acc, 0.01);
        f.update(Vec3::zeros(), acc, 0.01);
        match &f {
            AnyFilter::Complementary(c, _) => {
                let want = 1.0 - libm::exp(-0.01 / 0.195);
                assert!((c.k - want).abs() < 1e-15, "{} vs {want}", c.k);
            }
            _ => unreachable!(),
        }
    }
}
