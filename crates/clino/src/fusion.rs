//! The fusion stage of the pipeline: the one filter specification and the
//! streaming run of a recording.
//!
//! * [`parse_spec`] and [`parse_spec_list`] read the `name:key=value,…` form
//!   into a [`FilterSpec`] (every parameter of every filter, checked);
//!   [`apply_params`] applies flags given apart; [`filter_help`] lists them all;
//! * [`FilterConfig`] adds the stages around the filter (lever arm, offline
//!   smoothing) and makes the [`Pipeline`] ([`FilterConfig::pipeline`]), the
//!   only loop that runs a filter (its rules for time steps, dropouts and
//!   initialisation are stated there);
//! * [`fuse`] streams a recording through a filter and writes
//!   `t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status`, one row per
//!   input row, in constant memory.
//!
//! The filters are those of [`clino_core::filter`]; their equations and
//! sources are documented there.
//!
//! ```
//! use clino::fusion::{FilterConfig, FilterKind, FuseOptions, fuse};
//! use clino::io::{ImuCsvReader, ReadOptions};
//!
//! // 22 s of a real recording embedded in the library (BROAD trial 07).
//! let text = clino::demo::BROAD_EXCERPT;
//! let mut reader = ImuCsvReader::new(text.as_bytes(), "excerpt.csv", &ReadOptions::default())?;
//! let mut out = Vec::new();
//! let config = FilterConfig::new(FilterKind::Madgwick);
//! let report = fuse(&mut reader, &mut out, &config, &FuseOptions::default())?;
//! assert_eq!(report.counts.samples, 6286);
//! assert_eq!(report.counts.dropouts, 0);
//! let csv = String::from_utf8(out).unwrap();
//! assert!(csv.starts_with("t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status\n"));
//! assert_eq!(csv.lines().count(), 6287);
//! # Ok::<(), clino::Error>(())
//! ```

use std::io::{Read, Write};

use clino_core::clock::SampleClock;
pub use clino_core::filter::{FilterKind, FilterSpec};
use clino_core::filter::{ParamError, ParamType};
pub use clino_core::pipeline::{Counts, Output, Pipeline, SensorRange, Status};
use clino_core::tilt::{RollPitch, inclination};
use clino_core::{Attitude, ImuSample, Vec3};
use serde::Serialize;

use crate::io::{CsvLineWriter, ImuCsvReader, ImuRow, RowSink};
use crate::{Error, ErrorKind, Result};

fn invalid(msg: impl Into<String>) -> Error {
    Error::new(ErrorKind::InvalidInput, msg)
}

/// The filter named `name` (case ignored), or an error listing the known names.
pub fn parse_kind(name: &str) -> Result<FilterKind> {
    FilterKind::from_name(name).ok_or_else(|| {
        let names: Vec<&str> = FilterKind::ALL.iter().map(|k| k.name()).collect();
        invalid(format!(
            "unknown filter '{}' (known: {})",
            name.trim(),
            names.join(", ")
        ))
    })
}

/// Set one parameter of `spec` from text, with an error that names the
/// filter, the key and what the key accepts.
pub fn set_param(spec: &mut FilterSpec, key: &str, value: &str) -> Result<()> {
    let kind = spec.kind();
    spec.set(key, value).map_err(|e| {
        let keys: Vec<&str> = FilterSpec::params(kind).iter().map(|p| p.key).collect();
        match (e, spec.param(key)) {
            (ParamError::UnknownKey, _) => invalid(format!(
                "the {kind} filter has no parameter '{}' (its parameters: {})",
                key.trim(),
                if keys.is_empty() {
                    "none".to_string()
                } else {
                    keys.join(", ")
                }
            )),
            (_, Some(info)) => invalid(format!(
                "{kind}:{}: '{}' is {} (it takes {})",
                info.key,
                value.trim(),
                e,
                describe(&info.ty, info.unit)
            )),
            (_, None) => invalid(format!("{kind}:{key}: {e}")),
        }
    })
}

fn describe(ty: &ParamType, unit: &str) -> String {
    match ty {
        ParamType::Number {
            min,
            max,
            min_exclusive,
        } => {
            let lo = if *min_exclusive { "(" } else { "[" };
            let hi = if *max >= 1e9 {
                "∞)".to_string()
            } else {
                format!("{max}]")
            };
            // a dimensionless parameter (unit "1") has no unit to print
            let unit = if unit == "1" {
                String::new()
            } else {
                format!(" {unit}")
            };
            format!("a number in {lo}{min}, {hi}{unit}")
        }
        ParamType::Bool => "true or false".to_string(),
        ParamType::Integrator => "exact or rectangle".to_string(),
    }
}

/// Parse one filter specification: `NAME` or `NAME:KEY=VALUE,KEY=VALUE…`
/// (`poisson-rect` is `poisson:integrator=rectangle`). Keys are those of
/// [`FilterSpec::params`], in full (`bandwidth_rad_s`) or without their unit
/// suffix (`bandwidth`); unnamed parameters keep their defaults.
///
/// ```
/// use clino::fusion::{parse_spec, FilterSpec};
/// let s = parse_spec("mahony:kp=0.5, ki=0").unwrap();
/// assert_eq!(s, FilterSpec::Mahony { kp: 0.5, ki: 0.0 });
/// assert!(parse_spec("mahony:beta=1").is_err());
/// ```
pub fn parse_spec(text: &str) -> Result<FilterSpec> {
    let (name, rest) = match text.split_once(':') {
        Some((n, r)) => (n.trim(), r),
        None => (text.trim(), ""),
    };
    let mut spec = if name.eq_ignore_ascii_case("poisson-rect") {
        FilterSpec::Poisson {
            integrator: clino_core::filter::Integrator::Rectangle,
        }
    } else {
        FilterSpec::default_for(parse_kind(name)?)
    };
    let mut given: Vec<&'static str> = Vec::new();
    for kv in rest.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (k, v) = kv
            .split_once('=')
            .ok_or_else(|| invalid(format!("filter '{text}': '{kv}' is not KEY=VALUE")))?;
        set_param(&mut spec, k, v)?;
        let key = spec.param(k).map_or("", |p| p.key);
        if given.contains(&key) {
            return Err(invalid(format!("filter '{text}': {key} is given twice")));
        }
        given.push(key);
    }
    if given.contains(&"k") && given.contains(&"tau_s") {
        return Err(invalid(format!(
            "filter '{text}': give the complementary blend as k or as tau, not both"
        )));
    }
    Ok(spec)
}

/// True when a filter's text (one specification or a list, as
/// [`parse_spec_list`] takes it) names the dynamic filter's timing,
/// `sensor_delay_periods` or `gyro_lag_s` (in full or without the unit):
/// then a recording's own note of it is not taken
/// ([`FilterConfig::timing_given`]).
///
/// ```
/// use clino::fusion::names_timing;
/// assert!(names_timing("dynamic:bandwidth=0.2,sensor_delay=1"));
/// assert!(names_timing("mahony,dynamic:gyro_lag_s=0.001"));
/// assert!(!names_timing("dynamic:bandwidth=0.2,mahony:kp=1"));
/// ```
pub fn names_timing(text: &str) -> bool {
    let dynamic = FilterSpec::default_for(FilterKind::Dynamic);
    text.split(',').any(|item| {
        let kv = item.rsplit(':').next().unwrap_or(item);
        kv.split_once('=').is_some_and(|(k, _)| {
            dynamic
                .param(k)
                .is_some_and(|p| matches!(p.key, "sensor_delay_periods" | "gyro_lag_s"))
        })
    })
}

/// Parse a list of specifications separated by commas, or `all` (every
/// filter at its defaults): `dynamic:bandwidth=0.2,rest_time=2,mahony`. A
/// `KEY=VALUE` item belongs to the filter before it. Repeats are kept once.
pub fn parse_spec_list(text: &str) -> Result<Vec<FilterSpec>> {
    if text.trim().eq_ignore_ascii_case("all") {
        return Ok(FilterKind::ALL
            .iter()
            .map(|k| FilterSpec::default_for(*k))
            .collect());
    }
    let mut items: Vec<String> = Vec::new();
    for part in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        match items.last_mut() {
            Some(last) if part.contains('=') && !part.contains(':') => {
                last.push(if last.contains(':') { ',' } else { ':' });
                last.push_str(part);
            }
            _ if part.contains('=') && !part.contains(':') => {
                return Err(invalid(format!(
                    "'{part}' names no filter: write NAME:{part}"
                )));
            }
            _ => items.push(part.to_string()),
        }
    }
    let mut out: Vec<FilterSpec> = Vec::new();
    for it in &items {
        let s = parse_spec(it)?;
        if !out.contains(&s) {
            out.push(s);
        }
    }
    if out.is_empty() {
        return Err(invalid("no filter named"));
    }
    Ok(out)
}

/// Apply parameters given apart from the specification (the command line's
/// `--kp 0.5`, Python's keyword arguments) to every filter of `specs` that
/// has them. A parameter none of the filters reads is an error, not a flag
/// that silently does nothing.
pub fn apply_params(specs: &mut [FilterSpec], params: &[(&str, String)]) -> Result<()> {
    for (key, value) in params {
        let mut used = false;
        for spec in specs.iter_mut() {
            if spec.param(key).is_some() {
                set_param(spec, key, value)?;
                used = true;
            }
        }
        if !used {
            let names: Vec<&str> = specs.iter().map(|s| s.kind().name()).collect();
            let owners: Vec<&str> = FilterKind::ALL
                .iter()
                .filter(|k| FilterSpec::default_for(**k).param(key).is_some())
                .map(|k| k.name())
                .collect();
            return Err(invalid(format!(
                "'{key}' is a parameter of {}, not of {} (it would do nothing)",
                if owners.is_empty() {
                    "no filter".to_string()
                } else {
                    owners.join(", ")
                },
                names.join(", ")
            )));
        }
    }
    Ok(())
}

/// The specification in the text form [`parse_spec`] reads: the name, then
/// the parameters that differ from the defaults.
pub fn spec_text(spec: &FilterSpec) -> String {
    let base = FilterSpec::default_for(spec.kind());
    let changed: Vec<String> = FilterSpec::params(spec.kind())
        .iter()
        .filter_map(|p| {
            let v = spec.get(p.key)?;
            (base.get(p.key) != Some(v)).then(|| format!("{}={v}", p.key))
        })
        .collect();
    if changed.is_empty() {
        spec.kind().name().to_string()
    } else {
        format!("{}:{}", spec.kind().name(), changed.join(","))
    }
}

/// Every filter and every parameter with its unit, default and meaning (the
/// text of `--help` for `--filter`).
pub fn filter_help() -> String {
    let mut s = String::from(
        "Filter: NAME or NAME:KEY=VALUE,… (keys in full or without their unit suffix).\n",
    );
    for kind in FilterKind::ALL {
        let d = FilterSpec::default_for(kind);
        s.push_str(&format!("  {kind}\n"));
        for p in FilterSpec::params(kind) {
            let def = d
                .get(p.key)
                .map(|v| v.to_string())
                .unwrap_or_else(|| "-".into());
            s.push_str(&format!(
                "    {:<24} {:<7} default {:<9} {}\n",
                p.key, p.unit, def, p.doc
            ));
        }
    }
    s
}

/// Which filter, with which parameters, and the pipeline stages around it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterConfig {
    /// The filter and its parameters.
    pub spec: FilterSpec,
    /// Lever arm of the sensor from a point on the rotation axis, m, body
    /// frame: tangential and centripetal acceleration are removed before
    /// fusion ([`clino_core::compensate::LeverArm`]).
    pub lever_arm_m: Option<Vec3>,
    /// Estimate the lever arm online from the recording (`--lever-arm auto`,
    /// [`clino_core::compensate::MountEstimator`]); dynamic filter only.
    /// `lever_arm_m`, when also given, is the starting value.
    pub lever_auto: bool,
    /// Estimate the horizontal accelerometer bias online where rotation makes
    /// it observable ([`clino_core::compensate::MountEstimator`]); dynamic
    /// filter only. [`FilterConfig::with_lever_arm`] and
    /// [`FilterConfig::with_lever_auto`] switch it on (a mount with a lever
    /// arm turns); on a mount that does not turn it stays at zero.
    pub accel_bias: bool,
    /// Offline smoothing over the whole recording ([`crate::smooth`]); only
    /// for the dynamic filter. [`fuse`] and [`crate::eval`] buffer the
    /// recording when this is set.
    pub offline: bool,
    /// The sensor's full-scale ranges (`--gyro-range`, `--acc-range`):
    /// readings at a range are counted as clipped and the dynamic filter is
    /// told ([`Pipeline::with_sensor_range`]); offline, its passes too, and
    /// they are weighted by how long ago each crossed a clipped rate
    /// ([`crate::smooth::SmoothOptions::sensor_range`]; with a calibration,
    /// which moves the gyro's rails, the passes are not told). Default: not
    /// known.
    pub sensor_range: SensorRange,
    /// Take each step from the sensor's sample clock recovered from the
    /// time stamps (`true`, the default; `--stamps recover`): stamps a host
    /// made as each sample arrived, off by milliseconds, are put back on the
    /// sensor's clock ([`clino_core::clock`]), while a sensor's own stamps
    /// give their own steps to the bit. `false` (`--stamps as-given`): the
    /// stamps' steps as they are, in real time and offline.
    pub sample_clock: bool,
    /// The user named the dynamic filter's timing (`sensor_delay_periods`
    /// or `gyro_lag_s`): a recording's own note of the sensor's timing
    /// ([`crate::stream::Recorder::note_timing`]) is then not taken.
    /// Default false: [`FilterConfig::for_recording`] takes the note.
    pub timing_given: bool,
}

impl FilterConfig {
    /// A filter with default parameters and no extra stage.
    pub fn new(kind: FilterKind) -> Self {
        Self::from_spec(FilterSpec::default_for(kind))
    }

    /// A filter of this specification and no extra stage.
    pub fn from_spec(spec: FilterSpec) -> Self {
        Self {
            spec,
            lever_arm_m: None,
            lever_auto: false,
            accel_bias: false,
            offline: false,
            sensor_range: SensorRange::default(),
            sample_clock: true,
            timing_given: false,
        }
    }

    /// The same filter, told whether the user named its timing
    /// ([`FilterConfig::timing_given`]).
    pub fn with_timing_given(mut self, given: bool) -> Self {
        self.timing_given = given;
        self
    }

    /// True when a recording's note of its sensor's timing is this filter's
    /// to take: a dynamic filter whose timing the user did not name.
    pub fn takes_timing_note(&self) -> bool {
        !self.timing_given && self.spec.kind() == FilterKind::Dynamic
    }

    /// This filter as it runs on a recording whose notes (before its first
    /// data row: [`crate::io::ImuCsvReader::notes`]) are `notes`: a dynamic
    /// filter takes the sensor's timing a recording of `clino stream`
    /// carries ([`crate::stream::SensorTiming::from_notes`]) unless the user
    /// named it; and that timing, when taken.
    pub fn for_recording(
        &self,
        notes: &[String],
    ) -> (FilterConfig, Option<crate::stream::SensorTiming>) {
        let mut c = *self;
        if !self.takes_timing_note() {
            return (c, None);
        }
        let FilterSpec::Dynamic(p) = &mut c.spec else {
            return (c, None);
        };
        match crate::stream::SensorTiming::from_notes(notes) {
            Some(t) => {
                t.apply(p);
                (c, Some(t))
            }
            None => (c, None),
        }
    }

    /// The same filter taking its steps from the sample clock recovered from
    /// the stamps (`true`, the default) or from the stamps as they are
    /// ([`FilterConfig::sample_clock`]).
    pub fn with_sample_clock(mut self, recover: bool) -> Self {
        self.sample_clock = recover;
        self
    }

    /// The same filter knowing the sensor's full-scale ranges.
    pub fn with_sensor_range(mut self, range: SensorRange) -> Self {
        self.sensor_range = range;
        self
    }

    /// Which filter.
    pub fn kind(&self) -> FilterKind {
        self.spec.kind()
    }

    /// The same filter with lever-arm compensation (m, body frame).
    ///
    /// With the dynamic filter this also estimates the accelerometer bias
    /// ([`FilterConfig::accel_bias`]; undo with [`FilterConfig::with_accel_bias`]).
    pub fn with_lever_arm(mut self, lever_arm_m: Option<Vec3>) -> Self {
        self.lever_arm_m = lever_arm_m;
        self.accel_bias = self.wants_accel_bias();
        self
    }

    /// The same filter with the lever arm estimated online (`--lever-arm auto`);
    /// with the dynamic filter also the accelerometer bias.
    pub fn with_lever_auto(mut self, auto: bool) -> Self {
        self.lever_auto = auto;
        self.accel_bias = self.wants_accel_bias();
        self
    }

    /// Switch the online accelerometer-bias estimate on or off.
    pub fn with_accel_bias(mut self, on: bool) -> Self {
        self.accel_bias = on;
        self
    }

    fn wants_accel_bias(&self) -> bool {
        self.kind() == FilterKind::Dynamic && (self.lever_arm_m.is_some() || self.lever_auto)
    }

    /// The options of the online estimator of this configuration, `None` when
    /// it estimates neither bias nor lever arm.
    pub fn mount_options(&self) -> Option<clino_core::compensate::MountOptions> {
        if !(self.lever_auto || self.accel_bias) {
            return None;
        }
        let gravity_m_s2 = match self.spec {
            FilterSpec::Dynamic(p) => p.gravity_m_s2,
            _ => clino_core::G0,
        };
        Some(clino_core::compensate::MountOptions {
            estimate_bias: self.accel_bias,
            estimate_lever: self.lever_auto,
            lever_arm_m: self.lever_arm_m.unwrap_or_else(Vec3::zeros),
            gravity_m_s2,
            ..Default::default()
        })
    }

    /// The same filter, smoothed offline over the whole recording.
    pub fn with_offline(mut self, offline: bool) -> Self {
        self.offline = offline;
        self
    }

    /// The column label of this configuration in tables: the specification
    /// ([`spec_text`]), `+offline` when smoothed, `+lever` when compensated.
    pub fn label(&self) -> String {
        let mut s = spec_text(&self.spec);
        if self.offline {
            s.push_str("+offline");
        }
        if self.lever_auto {
            s.push_str("+lever=auto");
        } else if self.lever_arm_m.is_some() {
            s.push_str("+lever");
        }
        if self.accel_bias {
            s.push_str("+accbias");
        }
        s
    }

    /// Check the parameters, the lever arm and the stages.
    pub fn validate(&self) -> Result<()> {
        if let Err((key, e)) = self.spec.validate() {
            return Err(invalid(format!("{}:{key}: {e}", self.kind())));
        }
        if let Some(p) = self.lever_arm_m
            && !p.iter().all(|v| v.is_finite())
        {
            return Err(invalid("lever arm must be three finite numbers (m)"));
        }
        if (self.lever_auto || self.accel_bias) && self.kind() != FilterKind::Dynamic {
            return Err(invalid(format!(
                "the online lever-arm and accelerometer-bias estimate observes the dynamic filter, not {}",
                self.kind()
            )));
        }
        let r = self.sensor_range;
        if !(r.gyro_rad_s > 0.0 && r.acc_m_s2 > 0.0) {
            return Err(invalid(format!(
                "the sensor's ranges must be positive (gyro {} rad/s, accelerometer {} m/s²)",
                r.gyro_rad_s, r.acc_m_s2
            )));
        }
        if self.offline && self.kind() != FilterKind::Dynamic {
            return Err(invalid(format!(
                "offline smoothing is available for the dynamic filter, not for {}",
                self.kind()
            )));
        }
        Ok(())
    }

    /// The real-time pipeline of this configuration (checked first).
    pub fn pipeline(&self) -> Result<Pipeline> {
        self.validate()?;
        Ok(match self.mount_options() {
            Some(m) => Pipeline::new(self.spec).with_mount_estimator(Some(m)),
            None => Pipeline::new(self.spec).with_lever_arm(self.lever_arm_m),
        }
        .with_sensor_range(self.sensor_range)
        .with_sample_clock(self.sample_clock))
    }

    /// Offline attitudes of a whole recording held in memory (dynamic filter,
    /// [`crate::smooth::smooth`]): one per sample; `None` for samples before the
    /// first usable one. Samples the pipeline would not use (dropouts,
    /// saturation) hold the attitude of the sample before; the smoother sees
    /// only usable samples, with time steps spanning the gaps.
    pub fn smooth_samples(&self, samples: &[ImuSample]) -> Result<Vec<Option<Attitude>>> {
        let mut held = HeldRecording::new(self.sample_clock);
        for s in samples {
            held.push(s);
        }
        let q = self.smooth_held(&mut held, false, None)?;
        Ok(held.expand(&q).collect())
    }

    /// The smoother over a [`HeldRecording`] (its usable samples; the lever-arm
    /// compensation is written over its specific forces). `calibrated`: the
    /// samples held were calibrated, which moved the gyro's rails, so the
    /// passes are not told the sensor's range (its clipped readings are
    /// counted from the raw rows).
    fn smooth_held(
        &self,
        held: &mut HeldRecording,
        calibrated: bool,
        progress: Option<crate::smooth::Progress<'_>>,
    ) -> Result<Vec<Attitude>> {
        self.validate()?;
        let FilterSpec::Dynamic(params) = self.spec else {
            return Err(invalid("offline smoothing needs the dynamic filter"));
        };
        // an online estimate (bias, lever arm) is made by a real-time pass first;
        // the smoother then runs on the bias-corrected readings with that arm
        let mut lever_arm_m = self.lever_arm_m;
        if self.mount_options().is_some() {
            let mut p = self.pipeline()?;
            let usable_t = held
                .t
                .iter()
                .zip(&held.status)
                .filter(|(_, st)| st.is_none());
            for (j, (t, _)) in usable_t.enumerate() {
                p.update(&ImuSample::new(*t, held.gyr[j], held.acc[j]));
            }
            if let Some(m) = p.mount_estimator() {
                if self.lever_auto || self.lever_arm_m.is_some() {
                    lever_arm_m = Some(m.applied_lever_arm());
                }
                // what the real-time pass ended by removing: the whole
                // estimate where the lever arm (given or estimated, about
                // an axis that does not move) models the accelerations,
                // none where it does not (MountEstimator::lever_model_holds)
                let b = p.applied_accel_bias();
                held.acc.iter_mut().for_each(|a| *a -= b);
            }
        }
        let opts = crate::smooth::SmoothOptions {
            params,
            lever_arm_m,
            sensor_range: if calibrated {
                SensorRange::default()
            } else {
                self.sensor_range
            },
            ..Default::default()
        };
        held.finish_intervals();
        Ok(crate::smooth::smooth_in_place(
            &held.gyr,
            &mut held.acc,
            &held.dt,
            &opts,
            progress,
        ))
    }
}

/// A recording held for the offline smoother in compact columns: per row its
/// time and admission (9 bytes), per usable row its rate, specific force and
/// the interval since the usable row before (56 bytes).
#[derive(Debug, Default)]
struct HeldRecording {
    t: Vec<f64>,
    status: Vec<Option<Status>>,
    gyr: Vec<Vec3>,
    acc: Vec<Vec3>,
    dt: Vec<f64>,
    last_usable_t: Option<f64>,
    /// Take the steps from the sample clock recovered from the usable
    /// rows' stamps (`finish_intervals`); the clock, once it has run, and
    /// the rows whose step it gave.
    recover: bool,
    clock: Option<SampleClock>,
    retimed: u64,
}

impl HeldRecording {
    /// Nothing held yet; the steps from the recovered sample clock when
    /// `recover` ([`FilterConfig::sample_clock`]).
    fn new(recover: bool) -> Self {
        Self {
            recover,
            ..Self::default()
        }
    }

    /// Hold one row; returns its admission (`None` when the smoother uses it).
    fn push(&mut self, s: &ImuSample) -> Option<Status> {
        let st = clino_core::pipeline::admission(s);
        self.t.push(s.t_s);
        self.status.push(st);
        if st.is_none() {
            self.gyr.push(s.gyr_rad_s);
            self.acc.push(s.acc_m_s2);
            // the stamps' step (the first set by `finish_intervals`), from
            // the latest stamp: one not after it is unusable (≤ 0)
            self.dt
                .push(self.last_usable_t.map_or(0.0, |t0| s.t_s - t0));
            self.last_usable_t = Some(self.last_usable_t.map_or(s.t_s, |t0| t0.max(s.t_s)));
        }
        st
    }

    /// The rows whose step came from the recovered sample clock, and the
    /// stamps' noise, s, when any did ([`FuseReport::stamp_jitter_s`]).
    fn stamps(&self) -> (u64, Option<f64>) {
        let jitter = (self.retimed > 0)
            .then(|| self.clock.as_ref().map(SampleClock::jitter))
            .flatten();
        (self.retimed, jitter)
    }

    /// The first usable sample's interval: the nominal period (the next
    /// interval), used only to initialise.
    fn finish_intervals(&mut self) {
        // the steps of the sample clock recovered over the whole recording
        // (SampleClock::primed_over: the seconds a clock run once takes to
        // judge the stamps are recovered too); a stamp not after the last
        // keeps its (unusable) step
        if self.recover {
            let usable = || {
                self.t
                    .iter()
                    .zip(&self.status)
                    .filter(|(_, st)| st.is_none())
                    .map(|(t, _)| *t)
            };
            let mut c = SampleClock::primed_over(usable());
            self.retimed = 0;
            for (dt, t) in self.dt.iter_mut().zip(usable()) {
                if let Some(step) = c.step(t) {
                    *dt = step;
                    self.retimed += u64::from(c.recovering());
                }
            }
            self.clock = Some(c);
        }
        match self.dt.len() {
            0 => {}
            1 => self.dt[0] = 0.01,
            _ => self.dt[0] = self.dt[1],
        }
    }

    /// Time and output per row from the usable rows' attitudes `q`: the
    /// pipeline's statuses — `dropout` or `saturated` where
    /// [`clino_core::pipeline::admission`] refused the row (the attitude
    /// held), `waiting` before the first usable one, `fused` elsewhere.
    fn outputs<'a>(&'a self, q: &'a [Attitude]) -> impl Iterator<Item = (f64, Output)> + 'a {
        self.t
            .iter()
            .zip(&self.status)
            .zip(self.expand(q))
            .map(|((t, st), q)| {
                let status = match (st, q) {
                    (Some(st), _) => *st,
                    (None, None) => Status::Waiting,
                    (None, Some(_)) => Status::Fused,
                };
                (
                    *t,
                    Output {
                        status,
                        attitude: q,
                    },
                )
            })
    }

    /// One attitude per row from the usable rows' attitudes `q`: unusable
    /// rows hold the attitude before them (`None` before the first usable).
    fn expand<'a>(&'a self, q: &'a [Attitude]) -> impl Iterator<Item = Option<Attitude>> + 'a {
        let mut j = 0;
        let mut last = None;
        self.status.iter().map(move |st| {
            if st.is_none() {
                last = q.get(j).copied();
                j += 1;
            }
            last
        })
    }
}

/// What a long run of [`fuse`] reports as it goes (for a progress bar).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FuseProgress {
    /// Rows read so far (every [`crate::smooth::PROGRESS_EVERY`] rows).
    Read(u64),
    /// The offline smoother's stage, with samples done and samples in all.
    Smooth(crate::smooth::Stage, usize, usize),
}

/// Counts of a run of [`fuse`]: the pipeline's [`Counts`] (one per row;
/// `samples` = rows read = rows written) and where the first unusable row was.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct FuseReport {
    /// Rows by status.
    pub counts: Counts,
    /// Line of the first dropout or saturated row.
    pub first_dropout_line: Option<u64>,
    /// Line of the first row with a reading at the sensor's range
    /// ([`FilterConfig::sensor_range`]).
    pub first_clipped_line: Option<u64>,
    /// The online accelerometer-bias and lever-arm estimates at the end of
    /// a real-time run, when the configuration makes them.
    pub mount: Option<MountReport>,
    /// What the dynamic filter learnt from rest to rest (real-time runs of
    /// `dynamic` only).
    pub sensor_errors: Option<SensorErrorReport>,
    /// Each triad's largest reading and the rows that read it: a rail, when
    /// it repeats ([`Rails::suspected`]).
    pub rails: Rails,
    /// The time stamps' own noise about the sensor's sample clock, s (RMS),
    /// when the steps were taken from the clock recovered from them
    /// ([`FilterConfig::sample_clock`]; their number is
    /// [`Counts::retimed`]).
    pub stamp_jitter_s: Option<f64>,
    /// The sensor's timing the recording carried and the dynamic filter
    /// took ([`FilterConfig::for_recording`]).
    pub timing: Option<crate::stream::SensorTiming>,
    /// A note came after the first data row, and was not taken (a board
    /// reset to another setting mid-recording).
    pub late_note: bool,
    /// A timing note before the first data row did not read as one
    /// ([`crate::stream::SensorTiming::from_notes`]) and was not taken.
    pub bad_timing_note: bool,
}

/// Each triad's largest reading (the largest magnitude of its three axes)
/// and how many rows read exactly it. A sensor clipped at its range reads
/// its rail again and again; one that is not reaches its largest value on
/// one row, or a few at a peak sampled finely. A recording fused without
/// the sensor's ranges whose rails repeat was most likely clipped
/// ([`FilterConfig::sensor_range`] would tell the filter).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Rails {
    /// The gyro's largest reading, rad/s, and the rows that read it.
    pub gyro_rad_s: f64,
    /// Rows whose gyro read `gyro_rad_s` on some axis.
    pub gyro_rows: u64,
    /// The accelerometer's largest reading, m/s².
    pub acc_m_s2: f64,
    /// Rows whose accelerometer read `acc_m_s2` on some axis.
    pub acc_rows: u64,
}

/// Rows at a triad's largest reading that make it a suspected rail: ten
/// (a peak sampled at 1 kHz stays within one count of its top for a few
/// samples, and noise of a count or more splits them).
pub const RAIL_ROWS: u64 = 10;

impl Rails {
    /// Take one usable sample.
    pub fn push(&mut self, s: &ImuSample) {
        for (v, max, rows) in [
            (&s.gyr_rad_s, &mut self.gyro_rad_s, &mut self.gyro_rows),
            (&s.acc_m_s2, &mut self.acc_m_s2, &mut self.acc_rows),
        ] {
            let m = v.amax();
            if m > *max {
                (*max, *rows) = (m, 1);
            } else if m == *max && m > 0.0 {
                *rows += 1;
            }
        }
    }

    /// The suspected rails (gyro rad/s, accelerometer m/s²): a largest
    /// reading repeated on [`RAIL_ROWS`] rows or more, at least 1.5 rad/s
    /// (86 °/s; the narrowest MEMS gyro range is ±125 °/s) or 1.5 g (the
    /// narrowest accelerometer range is ±2 g): a still sensor repeats its
    /// small largest reading at every count.
    pub fn suspected(&self) -> (Option<f64>, Option<f64>) {
        let at =
            |max: f64, rows: u64, least: f64| (rows >= RAIL_ROWS && max >= least).then_some(max);
        (
            at(self.gyro_rad_s, self.gyro_rows, 1.5),
            at(self.acc_m_s2, self.acc_rows, 1.5 * clino_core::G0),
        )
    }
}

/// The sensor errors the dynamic filter learnt from rest to rest
/// ([`clino_core::filter::Dynamic::gyro_scale`] and its siblings).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct SensorErrorReport {
    /// Rest pairs they were learnt from.
    pub rest_pairs: u32,
    /// Gyro scale-factor errors (fraction per body axis).
    pub gyro_scale: [f64; 3],
    /// Accelerometer scale-factor errors (fraction per body axis).
    pub accel_scale: [f64; 3],
    /// Accelerometer bias, m/s² (body frame).
    pub accel_bias_m_s2: [f64; 3],
    /// 1σ of each of the three above (same units).
    pub gyro_scale_sigma: [f64; 3],
    /// 1σ of the accelerometer scale errors.
    pub accel_scale_sigma: [f64; 3],
    /// 1σ of the accelerometer bias, m/s².
    pub accel_bias_sigma_m_s2: [f64; 3],
    /// Probability that each is present at all: gyro scale, accelerometer
    /// scale, accelerometer bias (prior 1/2; the values above are already
    /// weighted by it).
    pub probability: [f64; 3],
    /// The gyro scale errors the loop learnt in motion on top of
    /// `gyro_scale` (fraction per body axis;
    /// [`clino_core::filter::Dynamic::motion_gyro_scale`]): the rate is
    /// corrected by both.
    pub motion_gyro_scale: [f64; 3],
}

impl SensorErrorReport {
    /// The report of a dynamic filter's current state.
    pub fn of(d: &clino_core::filter::Dynamic) -> Self {
        let a = |v: Vec3| [v.x, v.y, v.z];
        let (ss, sd, sb) = d.sensor_error_sigmas();
        Self {
            gyro_scale_sigma: a(ss),
            accel_scale_sigma: a(sd),
            accel_bias_sigma_m_s2: a(sb),
            rest_pairs: d.rest_pairs(),
            gyro_scale: a(d.gyro_scale()),
            accel_scale: a(d.accel_scale()),
            accel_bias_m_s2: a(d.accel_bias()),
            probability: d.sensor_error_probabilities(),
            motion_gyro_scale: a(d.motion_gyro_scale()),
        }
    }
}

/// Final estimates of [`clino_core::compensate::MountEstimator`] with their 1σ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct MountReport {
    /// Accelerometer bias, m/s² (body frame).
    pub accel_bias_m_s2: [f64; 3],
    /// Its 1σ per axis, m/s².
    pub accel_bias_sigma_m_s2: [f64; 3],
    /// Lever arm, m (body frame): estimated, or the one given.
    pub lever_arm_m: [f64; 3],
    /// Its 1σ per axis, m (zero when given).
    pub lever_arm_sigma_m: [f64; 3],
    /// The share of the block-mean specific force the estimated arm
    /// explains ([`clino_core::compensate::MountEstimator::lever_explains`];
    /// `None` when the arm is given).
    pub lever_explains: Option<f64>,
    /// The learnt 1σ of a block's unexplained specific force, m/s²
    /// ([`clino_core::compensate::MountEstimator::noise_sigma`]): the mount's
    /// own acceleration over half a second, and what the model leaves.
    pub noise_sigma_m_s2: f64,
    /// Whether the arm the samples were compensated with at the end is the
    /// one reported: given, or estimated with its model holding
    /// ([`clino_core::compensate::MountEstimator::lever_model_holds`]).
    pub lever_applied: bool,
    /// Whether the bias estimate was removed from the samples at the end:
    /// estimated, and the arm's model holding, given or estimated (its
    /// terms leave at most
    /// [`clino_core::compensate::LEVER_FIXED_AXIS_M_S2`] of the block-mean
    /// specific force: the axis does not move).
    pub bias_applied: bool,
    /// The arm the samples were compensated with at the end, m: the
    /// estimate where it explains the accelerations, else its prior
    /// ([`clino_core::compensate::MountEstimator::applied_lever_arm`]).
    pub lever_arm_applied_m: [f64; 3],
}

impl MountReport {
    /// The report of an estimator's current state.
    pub fn of(m: &clino_core::compensate::MountEstimator) -> Self {
        let a = |v: Vec3| [v.x, v.y, v.z];
        Self {
            accel_bias_m_s2: a(m.accel_bias()),
            accel_bias_sigma_m_s2: a(m.accel_bias_sigma()),
            lever_arm_m: a(m.lever_arm()),
            lever_arm_sigma_m: a(m.lever_arm_sigma()),
            lever_explains: m.lever_explains(),
            noise_sigma_m_s2: m.noise_sigma(),
            lever_applied: !m.options().estimate_lever || m.lever_model_holds(),
            bias_applied: m.options().estimate_bias && m.lever_model_holds(),
            lever_arm_applied_m: a(m.applied_lever_arm()),
        }
    }
}

impl FuseReport {
    /// What the pipeline of a real-time run counted and estimated beyond
    /// the statuses: the clipped readings, the steps from the recovered
    /// sample clock and the stamps' noise, the mount estimate and the
    /// learnt sensor errors (the one rule for files and arrays).
    pub(crate) fn take_real_time(&mut self, pipeline: &Pipeline) {
        self.counts.take_pipeline(pipeline.counts());
        self.stamp_jitter_s = (self.counts.retimed > 0)
            .then(|| pipeline.sample_clock().map(SampleClock::jitter))
            .flatten();
        self.mount = pipeline.mount_estimator().map(MountReport::of);
        self.sensor_errors = pipeline.filter().as_dynamic().map(SensorErrorReport::of);
    }

    fn add(&mut self, status: Status, line: u64) {
        self.counts.record(status);
        if matches!(status, Status::Dropout | Status::Saturated) {
            self.first_dropout_line.get_or_insert(line);
        }
    }
}

/// Options of a run.
#[derive(Clone, Copy, Default)]
pub struct FuseOptions<'a> {
    /// Make a NaN or out-of-bounds gyro or accelerometer value an error
    /// (naming its line and column).
    pub strict: bool,
    /// Calibrate every sample with this file before fusion (temperature from
    /// the `temp_c` column where the model needs it).
    pub calibration: Option<&'a crate::calib::CalibrationFile>,
    /// Flush the output after every row (for a pipe or a terminal, so each
    /// row is seen when its input row arrives).
    pub flush_rows: bool,
    /// Told how far a long run has got ([`FuseProgress`]).
    pub progress: Option<&'a (dyn Fn(FuseProgress) + Sync)>,
}

impl std::fmt::Debug for FuseOptions<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FuseOptions")
            .field("strict", &self.strict)
            .field("calibration", &self.calibration)
            .field("flush_rows", &self.flush_rows)
            .field("progress", &self.progress.is_some())
            .finish()
    }
}

/// The error for a row the pipeline could not use, under `strict`.
fn dropout_error<R: Read>(reader: &ImuCsvReader<R>, row: &ImuRow, status: Status) -> Error {
    let msg = match status {
        Status::Saturated => format!(
            "a gyro or accelerometer value beyond the physical bounds (|ω| ≤ {} rad/s, |f| ≤ {} m/s²): a corrupted reading; without --strict the filter holds its state",
            clino_core::pipeline::MAX_RATE_RAD_S,
            clino_core::pipeline::MAX_SPECIFIC_FORCE_M_S2
        ),
        _ => "NaN in a gyro or accelerometer column (sensor dropout); without --strict the filter holds its state".to_string(),
    };
    let col = reader.unusable_column(row).unwrap_or("?").to_string();
    Error::new(ErrorKind::InvalidInput, msg)
        .in_file(reader.file())
        .at_line(row.line)
        .at_column(col)
}

/// The output header of [`fuse`].
pub const FUSE_HEADER: [&str; 9] = [
    "t_s",
    "qw",
    "qx",
    "qy",
    "qz",
    "roll_deg",
    "pitch_deg",
    "inclination_deg",
    "status",
];

/// Stream a recording through one filter and write one output row per input
/// row: `t_s,qw,qx,qy,qz,roll_deg,pitch_deg,inclination_deg,status`.
///
/// The quaternion rotates body to ENU (Hamilton, scalar first); roll and pitch
/// are aerospace z-y-x ([`RollPitch`]), inclination the angle of body z from
/// vertical ([`inclination`]). Each row goes through the [`Pipeline`]
/// (its rules for time steps, dropouts and initialisation are documented
/// there, once). Before the filter has initialised the attitude columns are
/// NaN (`status` = `waiting`); on a dropout or saturated row they hold the
/// last attitude, or the run stops with an error when `opts.strict` is set.
///
/// Memory does not depend on the length of the recording (unless `offline`).
pub fn fuse<R: Read, W: Write>(
    reader: &mut ImuCsvReader<R>,
    writer: W,
    config: &FilterConfig,
    opts: &FuseOptions,
) -> Result<FuseReport> {
    fuse_traced(reader, writer, config, opts, None)
}

/// [`fuse`], also keeping a bounded-memory trace of roll, pitch and
/// inclination for a plot ([`TiltTrace`]).
pub fn fuse_traced<R: Read, W: Write>(
    reader: &mut ImuCsvReader<R>,
    writer: W,
    config: &FilterConfig,
    opts: &FuseOptions,
    trace: Option<&mut TiltTrace>,
) -> Result<FuseReport> {
    let mut out = CsvLineWriter::new(writer);
    let io_err = |e: std::io::Error| Error::from(e).in_file("output");
    out.header(&FUSE_HEADER).map_err(io_err)?;
    if opts.flush_rows {
        out.flush().map_err(io_err)?;
    }
    let rep = fuse_into(reader, &mut out, config, opts, trace)?;
    out.finish().map_err(io_err)?;
    Ok(rep)
}

/// [`fuse_traced`] into any [`RowSink`] (CSV or Parquet), which receives the
/// [`FUSE_HEADER`] columns row by row (the caller writes the header and
/// finishes the sink).
pub fn fuse_into<R: Read, S: RowSink>(
    reader: &mut ImuCsvReader<R>,
    out: &mut S,
    config: &FilterConfig,
    opts: &FuseOptions,
    mut trace: Option<&mut TiltTrace>,
) -> Result<FuseReport> {
    // the recording's notes are complete once its first row is read
    let mut first = reader.next_row()?;
    let (config, timing) = config.for_recording(reader.notes().0);
    let config = &config;
    let mut next = |reader: &mut ImuCsvReader<R>| match first.take() {
        Some(row) => Ok(Some(row)),
        None => reader.next_row(),
    };
    let mut pipeline = config.pipeline()?;
    let io_err = |e: std::io::Error| Error::from(e).in_file("output");
    // the calibration file's range checks name the row; the model is applied by the pipeline
    if let Some(cal) = opts.calibration {
        pipeline = pipeline.with_calibration(Some(cal.calibration()));
    }
    let check = |reader: &ImuCsvReader<R>, row: &ImuRow| -> Result<()> {
        if let Some(cal) = opts.calibration
            && !row.has_dropout()
        {
            cal.check_temp(row.sample.temp_c).map_err(|e| Error {
                file: Some(reader.file().to_path_buf()),
                line: Some(row.line),
                ..e
            })?;
        }
        Ok(())
    };
    let mut report = FuseReport {
        timing,
        bad_timing_note: timing.is_none()
            && config.takes_timing_note()
            && crate::stream::SensorTiming::is_noted(reader.notes().0),
        ..FuseReport::default()
    };
    let mut emit = |out: &mut S, row: &ImuRow, q: Option<Attitude>, st: Status| {
        out.f64(row.sample.t_s);
        write_attitude(out, q, row.sample.t_s, trace.as_deref_mut());
        out.str(st.as_str());
        out.end_row()?;
        if opts.flush_rows {
            out.flush()?;
        }
        Ok::<(), std::io::Error>(())
    };
    let progress = |p: FuseProgress| {
        if let Some(f) = opts.progress {
            f(p)
        }
    };
    let mut rows = 0u64;
    let read = |rows: &mut u64| {
        *rows += 1;
        if *rows % crate::smooth::PROGRESS_EVERY as u64 == 0 {
            progress(FuseProgress::Read(*rows));
        }
    };
    if config.offline {
        // the smoother needs the whole recording: it is held in compact columns
        let mut held = HeldRecording::new(config.sample_clock);
        while let Some(row) = next(reader)? {
            check(reader, &row)?;
            read(&mut rows);
            let s = match opts.calibration {
                Some(c) if !row.has_dropout() => c.calibration().apply(&row.sample),
                _ => row.sample,
            };
            if let Some(st) = held.push(&s) {
                if opts.strict {
                    return Err(dropout_error(reader, &row, st));
                }
                report.add(st, row.line);
            } else {
                // a row the smoother takes, judged by its raw reading as the
                // real-time pipeline judges it
                report.rails.push(&row.sample);
                let (g, a) = report
                    .counts
                    .record_clipping(&config.sensor_range, &row.sample, rows);
                if g || a {
                    report.first_clipped_line.get_or_insert(row.line);
                }
            }
        }
        progress(FuseProgress::Read(rows));
        let mut tell = |stage, k, n| progress(FuseProgress::Smooth(stage, k, n));
        let qs = config.smooth_held(&mut held, opts.calibration.is_some(), Some(&mut tell))?;
        (report.counts.retimed, report.stamp_jitter_s) = held.stamps();
        for (t, o) in held.outputs(&qs) {
            // unusable rows were counted as they were read
            if matches!(o.status, Status::Waiting | Status::Fused) {
                report.counts.record(o.status);
            }
            let row = ImuRow {
                line: 0,
                sample: ImuSample::new(t, Vec3::zeros(), Vec3::zeros()),
                ref_q: None,
                movement: None,
            };
            emit(out, &row, o.attitude, o.status).map_err(io_err)?;
        }
        report.late_note = reader.notes().1;
        return Ok(report);
    }
    while let Some(row) = next(reader)? {
        check(reader, &row)?;
        read(&mut rows);
        let o = pipeline.update(&row.sample);
        if opts.strict && matches!(o.status, Status::Dropout | Status::Saturated) {
            return Err(dropout_error(reader, &row, o.status));
        }
        // the rows the pipeline judged for clipping: all it did not refuse
        if !matches!(o.status, Status::Dropout | Status::Saturated) {
            report.rails.push(&row.sample);
        }
        report.add(o.status, row.line);
        if report.first_clipped_line.is_none() && pipeline.counts().first_clipped.is_some() {
            report.first_clipped_line = Some(row.line);
        }
        emit(out, &row, o.attitude, o.status).map_err(io_err)?;
    }
    report.take_real_time(&pipeline);
    report.late_note = reader.notes().1;
    Ok(report)
}

/// The outputs of the offline stage over a whole recording of (already
/// calibrated) samples: the attitudes of [`FilterConfig::smooth_samples`]
/// with the pipeline's statuses — `dropout` or `saturated` where
/// [`clino_core::pipeline::admission`] refuses the sample (the attitude
/// held), `waiting` before the first usable one, `fused` elsewhere. The one
/// rule for files ([`fuse`]) and arrays ([`crate::batch::fuse_arrays`]).
/// `calibrated`: the samples were calibrated (their gyro rails moved: the
/// passes are not told the sensor's range).
pub fn offline_outputs(
    config: &FilterConfig,
    samples: &[ImuSample],
    calibrated: bool,
) -> Result<Vec<Output>> {
    offline_outputs_stamped(config, samples, calibrated).map(|(o, _, _)| o)
}

/// [`offline_outputs`], with the rows whose step came from the sample clock
/// recovered from the stamps and the stamps' own noise, s
/// ([`FuseReport::stamp_jitter_s`]).
pub(crate) fn offline_outputs_stamped(
    config: &FilterConfig,
    samples: &[ImuSample],
    calibrated: bool,
) -> Result<(Vec<Output>, u64, Option<f64>)> {
    let mut held = HeldRecording::new(config.sample_clock);
    for s in samples {
        held.push(s);
    }
    let q = config.smooth_held(&mut held, calibrated, None)?;
    let (retimed, jitter) = held.stamps();
    Ok((held.outputs(&q).map(|(_, o)| o).collect(), retimed, jitter))
}

/// Write the seven attitude columns (NaN before initialisation) and feed the trace.
pub fn write_attitude<S: RowSink>(
    out: &mut S,
    q: Option<Attitude>,
    t_s: f64,
    trace: Option<&mut TiltTrace>,
) {
    match q {
        Some(q) => {
            out.f64(q.w);
            out.f64(q.i);
            out.f64(q.j);
            out.f64(q.k);
            let rp = RollPitch::from_attitude(&q);
            let deg = [
                rp.roll.to_degrees(),
                rp.pitch.to_degrees(),
                inclination(&q).to_degrees(),
            ];
            for d in deg {
                out.f64(d);
            }
            if let Some(t) = trace {
                t.push(t_s, deg);
            }
        }
        None => {
            for _ in 0..7 {
                out.f64(f64::NAN);
            }
        }
    }
}

/// A decimated record of roll, pitch and inclination (degrees) against time,
/// in bounded memory whatever the length of the run: every `stride`-th row is
/// kept; when `capacity` points are held, every other one is dropped and the
/// stride doubles. So between `capacity / 2` and `capacity` evenly spaced
/// rows are kept at the end.
#[derive(Clone, Debug)]
pub struct TiltTrace {
    capacity: usize,
    stride: u64,
    seen: u64,
    points: Vec<(f64, [f64; 3])>,
}

impl TiltTrace {
    /// A trace holding at most `capacity` points (at least 2).
    pub fn new(capacity: usize) -> Self {
        Self {
            capacity: capacity.max(2),
            stride: 1,
            seen: 0,
            points: Vec::new(),
        }
    }

    /// Offer one row: time (s) and [roll, pitch, inclination] (degrees).
    pub fn push(&mut self, t_s: f64, deg: [f64; 3]) {
        if self.seen % self.stride == 0 {
            if self.points.len() == self.capacity {
                let mut k = 0;
                self.points.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
                // keep the phase: this row is kept only if it falls on the new stride
                if self.seen % self.stride != 0 {
                    self.seen += 1;
                    return;
                }
            }
            self.points.push((t_s, deg));
        }
        self.seen += 1;
    }

    /// The points kept: (t_s, [roll_deg, pitch_deg, inclination_deg]).
    pub fn points(&self) -> &[(f64, [f64; 3])] {
        &self.points
    }

    /// Draw roll, pitch and inclination against time to an SVG or PNG file.
    pub fn plot(&self, path: &std::path::Path, title: &str) -> Result<()> {
        let series: Vec<crate::report::Series> = ["roll_deg", "pitch_deg", "inclination_deg"]
            .iter()
            .enumerate()
            .map(|(k, name)| {
                crate::report::Series::line(
                    *name,
                    self.points.iter().map(|(t, d)| (*t, d[k])).collect(),
                )
            })
            .collect();
        let spec = crate::report::PlotSpec {
            title: title.to_string(),
            x_label: "t (s)".into(),
            y_label: "angle (deg)".into(),
            ..Default::default()
        };
        crate::report::line_plot(path, &spec, &series)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::ReadOptions;

    const HEAD: &str = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n";

    fn run(text: &str, kind: FilterKind, strict: bool) -> Result<(FuseReport, String)> {
        let mut r = ImuCsvReader::new(text.as_bytes(), "mem.csv", &ReadOptions::default())?;
        let mut out = Vec::new();
        let rep = fuse(
            &mut r,
            &mut out,
            &FilterConfig::new(kind),
            &FuseOptions {
                strict,
                ..Default::default()
            },
        )?;
        Ok((rep, String::from_utf8(out).unwrap()))
    }

    #[test]
    fn the_learnt_sensor_errors_are_reported() {
        // hand motion between 3-s rests, gyro +2 % on x: the report carries what
        // the filter learnt, with its rest pairs and probability; other filters
        // have none
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::by_hand(), 2);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        model.gyro.scale = Vec3::new(0.02, 0.0, 0.0);
        let mut text = String::from(HEAD);
        for x in model.simulate(&hand, 100.0, 120.0, 2) {
            let (g, a) = (x.gyr_rad_s, x.acc_m_s2);
            text.push_str(&format!(
                "{},{},{},{},{},{},{}\n",
                x.t_s, g.x, g.y, g.z, a.x, a.y, a.z
            ));
        }
        let (rep, _) = run(&text, FilterKind::Dynamic, false).unwrap();
        let e = rep.sensor_errors.unwrap();
        assert!(e.rest_pairs >= 5, "{e:?}");
        assert!((e.gyro_scale[0] - 0.02).abs() < 0.005, "{e:?}");
        assert!(e.probability[0] > 0.9, "{e:?}");
        // the miss is within 3σ, and 1σ is below the prior's 3 % (here 1.2 %: the
        // spread of the mixture, within each model and between the models)
        let sd = e.gyro_scale_sigma[0];
        assert!(
            sd > 0.0 && sd < 0.02 && (e.gyro_scale[0] - 0.02).abs() < 3.0 * sd,
            "{e:?}"
        );
        // the loop's motion scale is reported, the same as the filter's, and
        // small beside the pairs' (a hand turns back and forth)
        assert!(
            e.motion_gyro_scale
                .iter()
                .all(|v| v.is_finite() && v.abs() < 0.005),
            "{e:?}"
        );
        let (rep, _) = run(&text, FilterKind::Mahony, false).unwrap();
        assert!(rep.sensor_errors.is_none());
    }

    #[test]
    fn a_fast_hand_at_25_hz_teaches_a_calibrated_accelerometer_no_bias() {
        // The generalisation grid's hand @25 Hz, seed 3 (turns up to 4 rad/s),
        // on the calibrated sensor behind its anti-alias low-pass at 10 Hz
        // (0.4 periods): its rest pairs' rotation read at the samples' own
        // instants kept the low-pass's cross-coupling of the turning axes as
        // a misfit, which the learner took for a bias (−2.8, −7.4, −1.6) mg
        // off the sensor's own, probability 0.78: a steady 0.45° of tilt
        // (offline, imposed from the first sample, 0.43° over the whole
        // record). Read at the true motion's instants, the sensor's delay
        // later: (−0.9, −1.4, −1.0) mg, 0.31.
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::by_hand(), 3);
        let model = crate::sim::slewing::sensor().with_bandwidth(10.0);
        let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
        for x in model.simulate(&hand, 25.0, 120.0, 3) {
            f.update(&x);
        }
        let d = f.filter().as_dynamic().unwrap();
        let b = (d.accel_bias() - model.accel.bias) / (1e-3 * clino_core::G0);
        let p = d.sensor_error_probabilities()[2];
        assert!(d.rest_pairs() >= 5, "{}", d.rest_pairs());
        assert!(b.norm() < 3.0 && p < 0.5, "{b:?} mg, probability {p}");
    }

    #[test]
    fn a_gyro_with_cross_axis_terms_teaches_a_calibrated_accelerometer_less_bias() {
        // The generalisation grid's hand at 100 Hz with the gyro's cross-axis
        // terms of 0.5–1.2 % (`gyro-xaxis`), the accelerometer calibrated. A
        // turn about one axis reads partly about the others, which the rest
        // pairs' gyro scale cannot hold, and their misfit was taken for an
        // accelerometer bias: 2.7–4.0 mg horizontal over seeds 1–4, mean
        // 3.35 mg (probability 0.33–0.41), a steady 0.2° at rest. The
        // magnitudes of the two rests' specific forces, which the gyro has no
        // part in, tell the learner less bias is there: 0.8–3.4 mg, mean
        // 2.2 mg (0.24–0.37). Not all of it: the directions still show the
        // gyro's misfit (BENCHMARKS.md).
        use crate::sim::hand::{HandMotion, HandParams};
        let mut sum = 0.0;
        for seed in 1..=4 {
            let hand = HandMotion::new(HandParams::by_hand(), seed);
            let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
            model.gyro.cross_axis = nalgebra::Matrix3::new(
                0.0, -0.010, 0.006, //
                0.008, 0.0, -0.012, //
                -0.005, 0.009, 0.0,
            );
            let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
            for x in model.simulate(&hand, 100.0, 120.0, seed) {
                f.update(&x);
            }
            let d = f.filter().as_dynamic().unwrap();
            let b = (d.accel_bias() - model.accel.bias) / (1e-3 * clino_core::G0);
            assert!(d.rest_pairs() >= 5, "{}", d.rest_pairs());
            sum += b.xy().norm();
        }
        assert!(sum / 4.0 < 2.75, "{} mg", sum / 4.0);
    }

    #[test]
    fn a_slow_arm_at_25_hz_on_an_engine_base_forms_its_rest_pairs() {
        // The generalisation grid's slow arm (2-s rests) at 25 Hz on a base
        // vibrating at 8.75 Hz (1.5 m/s², 2°/s: an engine, seen near the
        // Nyquist frequency), with an uncalibrated accelerometer bias of
        // (7, −10, 5) mg. The short rests' cascade, two poles alone, passed the
        // vibration at 1/6 (0.38 m/s² over the 0.2-m/s² threshold): seeds 2
        // and 3 formed 0 and 2 rest pairs in two minutes, learnt no bias and
        // stayed at the bias's tilt, 0.61° and 0.70°. With a zero at the
        // Nyquist frequency in each stage (1/12): 7 pairs each, 0.56° and
        // 0.68°.
        use crate::sim::Motion;
        use crate::sim::hand::{HandMotion, HandParams};
        use crate::sim::motion::{Sum, vibration};
        for seed in [2, 3] {
            let arm = HandMotion::new(HandParams::slow(), seed);
            let base = Sum {
                a: arm,
                b: vibration(8.75, 2f64.to_radians(), Vec3::new(1.5, 1.0, 1.2)),
            };
            let mut model = crate::sim::slewing::sensor().with_bandwidth(10.0);
            model.accel.bias = Vec3::new(7.0, -10.0, 5.0) * (1e-3 * clino_core::G0);
            let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
            let mut err = crate::eval::Rms::default();
            for x in model.simulate(&base, 25.0, 120.0, seed) {
                let q = f.update(&x).attitude;
                if let (Some(q), true) = (q, x.t_s > arm.params.initial_rest_s) {
                    err.push(crate::eval::inclination_error(
                        &q,
                        &base.truth(x.t_s).attitude,
                    ));
                }
            }
            let d = f.filter().as_dynamic().unwrap();
            let e = err.value().to_degrees();
            println!("seed {seed}: {} pairs, {e}°", d.rest_pairs());
            assert!(d.rest_pairs() >= 5, "seed {seed}: {} pairs", d.rest_pairs());
        }
    }

    #[test]
    fn a_base_that_rocks_and_never_rests_has_its_gyro_bias_learnt_in_motion() {
        // The grid's slow arm (2-s rests) on a base rocking at 0.7 Hz (2°/s,
        // no linear sway: a vehicle on its suspension), 125 Hz, a calibrated
        // gyro whose bias is (0.05, −0.04, 0.03)°/s. The rocking keeps every
        // rest out and every rest pair (below the band of sways the rest
        // detector notches, 1–8 Hz, it is motion), so only the loop learns
        // the bias: at its default bias gain (the bias pole at 0.11·p, a
        // minute) the horizontal bias error is still 0.042°/s RMS over the
        // second minute. Raised while no rest has told the bias
        // (UNINFORMED_BIAS_GAIN): 0.020°/s. (Until 7 Dec 2026 this test
        // rocked the base at 2.33 Hz, 0.042 → 0.02°/s, the tilt 1.36× VQF's
        // error before the raise; there the rocking is now notched, held
        // poses end seven rest pairs, and the bias is off by 0.013°/s.)
        use crate::sim::hand::{HandMotion, HandParams};
        use crate::sim::motion::{Sum, vibration};
        use clino_core::AttitudeFilter;
        let seed = 2;
        let arm = HandMotion::new(HandParams::slow(), seed);
        let base = Sum {
            a: arm,
            b: vibration(0.7, 2f64.to_radians(), Vec3::zeros()),
        };
        let model = crate::sim::slewing::sensor().with_bandwidth(50.0);
        let b_true = model.gyro.bias;
        let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
        let (mut e2, mut n, mut rests) = (0.0f64, 0.0f64, 0);
        for x in model.simulate(&base, 125.0, 120.0, seed) {
            f.update(&x);
            let d = f.filter().as_dynamic().unwrap();
            rests += usize::from(d.at_rest());
            if x.t_s > 60.0 {
                e2 += (d.gyro_bias() - b_true).xy().norm_squared();
                n += 1.0;
            }
        }
        let d = f.filter().as_dynamic().unwrap();
        let e = (e2 / n).sqrt().to_degrees();
        println!(
            "{rests} samples at rest, {} pairs, bias error {e}°/s",
            d.rest_pairs()
        );
        // the condition: nothing but the loop teaches the bias
        assert!(
            rests < 125 && d.rest_pairs() == 0,
            "{rests} {}",
            d.rest_pairs()
        );
        assert!(e < 0.03, "{e}°/s");
    }

    #[test]
    fn a_slow_turn_under_the_rest_threshold_is_not_learnt_as_bias() {
        // Issue 13: a base precessing on a 2° cone at 0.025 Hz turns at
        // 0.31°/s, under the rest detector's 0.5°/s: its stillnesses passed
        // for rests and the turn was learnt as gyro bias (1.10°, 8 seeds;
        // VQF 0.59°). The specific force turns with
        // a turn and not with a bias: the share of the residual turn it
        // follows is no longer learnt. Measured on this seed: 0.33°, the
        // bias within 0.02 °/s of the truth; without the test (a throw-away
        // build) 1.07° and 0.26 °/s. Since the rest's pull carries the
        // stillness's mean specific force to the sample's body by the turn
        // it confirms (`a_turn_under_the_rest_threshold_is_not_pulled_behind`),
        // 0.13°; since the share may exceed 1 (`TURN_SHARE_MAX`) and the
        // first rest's alignment carries it too, 0.095°.
        use crate::eval::{Rms, inclination_error};
        use crate::sim::Motion;
        use crate::sim::motion::{Static, Sum, vibration};
        use clino_core::AttitudeFilter;
        let (hz, angle) = (0.025, 2f64.to_radians());
        let w = 2.0 * std::f64::consts::PI * hz;
        let m = Sum {
            a: Static::new(Attitude::from_euler_angles(0.05, -0.03, 0.7)),
            b: vibration(hz, w * angle, Vec3::zeros()),
        };
        let model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
        let mut rms = Rms::default();
        for x in model.simulate(&m, 100.0, 120.0, 1) {
            let q = f.update(&x).attitude.unwrap_or_else(Attitude::identity);
            if x.t_s > 10.0 {
                rms.push(inclination_error(&q, &m.truth(x.t_s).attitude));
            }
        }
        let e = rms.value().to_degrees();
        let b = (f.filter().gyro_bias() - model.gyro.bias)
            .norm()
            .to_degrees();
        println!("{e}°, the gyro bias off by {b} °/s");
        assert!(e < 0.5, "{e}°");
        assert!(b < 0.1, "{b} °/s");
    }

    /// The hand motion at `speed` times its own (turns up to 4 rad/s at 1)
    /// through the slewing machine's sensor with ranges of ±`gyro_dps` °/s
    /// and ±`acc_g` g, 100 Hz, `seed`, run with the ranges given (`told`) or
    /// not: the inclination RMSE over the run and at the hand's rests
    /// (degrees), the largest gyro scale error learnt and the counts.
    fn clipped_hand(
        speed: f64,
        gyro_dps: f64,
        acc_g: f64,
        told: bool,
        seed: u64,
    ) -> (f64, f64, f64, Counts) {
        use crate::sim::Motion;
        use crate::sim::hand::{HandMotion, HandParams};
        let mut p = HandParams::by_hand();
        p.band_hz = (p.band_hz.0 * speed, p.band_hz.1 * speed);
        let hand = HandMotion::new(p, seed);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        model.gyro.range = gyro_dps.to_radians();
        model.accel.range = acc_g * clino_core::G0;
        let range = SensorRange::from_full_scale(acc_g, gyro_dps);
        let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default())
            .with_sensor_range(if told { range } else { SensorRange::default() });
        let (mut all, mut rest) = (crate::eval::Rms::default(), crate::eval::Rms::default());
        for x in model.simulate(&hand, 100.0, 120.0, seed) {
            let q = f.update(&x).attitude;
            if let (Some(q), true) = (q, x.t_s > p.initial_rest_s) {
                let e = crate::eval::inclination_error(&q, &hand.truth(x.t_s).attitude);
                all.push(e);
                if hand.at_rest(x.t_s) {
                    rest.push(e);
                }
            }
        }
        let s = f.filter().as_dynamic().unwrap().gyro_scale().amax();
        let deg = |r: crate::eval::Rms| r.value().to_degrees();
        (deg(all), deg(rest), s, *f.counts())
    }

    #[test]
    fn a_clipped_gyro_teaches_no_scale_and_is_realigned_at_rest() {
        // Turns beyond the gyro's range (twice the hand's speed through
        // ±250 °/s) read as the range: the propagation falls short of them.
        // Unknown to the filter, the rest pairs took the shortfall for a gyro
        // scale error of 5.9 % (the sensor has 0.03 %) and the error at the
        // hand's rests was 4.5°; told of the 1841 clipped samples, the filter
        // learns no scale from those turns and realigns on the accelerometer
        // as at power-on: 2.8° (seeds 1–4: 2.6 → 1.8°, VQF 3.1°,
        // BENCHMARKS.md)
        let (_, blind, s_blind, n_blind) = clipped_hand(2.0, 250.0, 16.0, false, 2);
        let (_, told, s_told, n_told) = clipped_hand(2.0, 250.0, 16.0, true, 2);
        assert_eq!(n_blind.gyro_clipped, 0);
        assert!(n_told.gyro_clipped > 1000, "{n_told:?}");
        assert!(s_blind > 0.02, "scale learnt without the range: {s_blind}");
        assert!(s_told < 0.002, "scale learnt with the range: {s_told}");
        assert!(told < 0.8 * blind, "at rest {told}° told, {blind}° not");
    }

    #[test]
    fn a_clipped_accelerometer_is_forgotten_before_it_becomes_tilt() {
        // Three times the hand's speed through ±2 g (seed 4: 2856 samples
        // clipped): the specific force beyond the range is missing from the
        // velocity residual, which the loop turned into tilt, 1.91° (seeds
        // 1–4 1.15°, VQF, whose 3-s low-pass takes the same step, 1.02°).
        // Told, the residual forgets it within a second: 1.19° (seeds 1–4
        // 0.76°, BENCHMARKS.md)
        let (blind, _, _, n_blind) = clipped_hand(3.0, 2000.0, 2.0, false, 4);
        let (told, _, _, n_told) = clipped_hand(3.0, 2000.0, 2.0, true, 4);
        assert_eq!(n_blind.acc_clipped, 0);
        assert!(
            n_told.acc_clipped > 2000 && n_told.gyro_clipped == 0,
            "{n_told:?}"
        );
        assert!(told < 0.8 * blind, "{told}° told, {blind}° not");
    }

    #[test]
    fn a_repeated_largest_reading_is_a_suspected_rail() {
        // the hand at twice its speed through ±250 °/s and ±2 g, 100 Hz: the
        // gyro's rail repeats; at its own speed at 1 kHz, and still, nothing is
        // suspected (a still sensor repeats a small largest reading)
        use crate::sim::hand::{HandMotion, HandParams};
        let rails = |speed: f64, rate: f64| {
            let mut p = HandParams::by_hand();
            p.band_hz = (p.band_hz.0 * speed, p.band_hz.1 * speed);
            let mut model = crate::sim::slewing::sensor().with_bandwidth(0.4 * rate);
            model.gyro.range = 250f64.to_radians();
            let mut r = Rails::default();
            for x in model.simulate(&HandMotion::new(p, 2), rate, 60.0, 2) {
                r.push(&x);
            }
            r
        };
        let clipped = rails(2.0, 100.0);
        assert_eq!(
            clipped.suspected().0,
            Some(250f64.to_radians()),
            "{clipped:?}"
        );
        let fine = rails(1.0, 1000.0);
        assert_eq!(fine.suspected(), (None, None), "{fine:?}");
        let mut still = Rails::default();
        for k in 0..1000 {
            let w = Vec3::new(0.001 * f64::from(k % 3), 0.0, 0.0);
            still.push(&ImuSample::new(
                k as f64 * 0.01,
                w,
                Vec3::new(0.0, 0.0, 9.81),
            ));
        }
        assert!(still.gyro_rows > RAIL_ROWS, "{still:?}");
        assert_eq!(still.suspected(), (None, None));
    }

    #[test]
    fn a_sensor_that_never_reaches_its_range_runs_as_without_it() {
        // the hand at its own speed (under 240 °/s) through the same sensor:
        // nothing is clipped and every attitude is the same to the bit
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::by_hand(), 1);
        let mut model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        model.gyro.range = 250f64.to_radians();
        let r = SensorRange::from_full_scale(2.0, 250.0);
        let mut a = clino_core::pipeline::Pipeline::new(FilterSpec::default());
        let mut b = a.clone().with_sensor_range(r);
        for x in model.simulate(&hand, 100.0, 60.0, 1) {
            assert_eq!(a.update(&x), b.update(&x));
        }
        assert_eq!((b.counts().gyro_clipped, b.counts().acc_clipped), (0, 0));
    }

    #[test]
    fn host_stamps_are_put_back_on_the_sensors_clock_in_real_time_and_offline() {
        // the hand at 100 Hz, its samples stamped as a host receives them
        // through 16-ms USB packets (every sample of a packet stamped at the
        // packet's arrival): the steps of the recovered clock give what the
        // sensor's own stamps give, the stamps' own steps do not
        use crate::sim::Motion;
        use crate::sim::hand::{HandMotion, HandParams};
        let hand = HandMotion::new(HandParams::by_hand(), 4);
        let model = crate::sim::slewing::sensor().with_bandwidth(40.0);
        let samples = model.simulate(&hand, 100.0, 60.0, 4);
        let mut host = samples.clone();
        let (mut last, mut within) = (f64::NAN, 0.0);
        for s in host.iter_mut() {
            let packet = (s.t_s / 0.016).floor() + 1.0;
            within = if packet == last { within + 1.0 } else { 0.0 };
            last = packet;
            s.t_s = packet * 0.016 + 20e-6 * within;
        }
        // RMS inclination error over [from, to) s
        let over = |out: &[Option<Attitude>], from: f64, to: f64| {
            let mut r = crate::eval::Rms::default();
            for (s, q) in samples.iter().zip(out) {
                if let (Some(q), true) = (q, (from..to).contains(&s.t_s)) {
                    r.push(crate::eval::inclination_error(
                        q,
                        &hand.truth(s.t_s).attitude,
                    ));
                }
            }
            r.value().to_degrees()
        };
        let rms = |out: &[Option<Attitude>]| over(out, 10.0, 60.0);
        let real_time = |c: &FilterConfig, x: &[ImuSample]| {
            let mut p = c.pipeline().unwrap();
            let out: Vec<_> = x.iter().map(|s| p.update(s).attitude).collect();
            (rms(&out), p.counts().retimed)
        };
        let recover = FilterConfig::from_spec(FilterSpec::default());
        let as_given = recover.with_sample_clock(false);
        let (sensor, none) = real_time(&recover, &samples);
        let (recovered, retimed) = real_time(&recover, &host);
        let (given, _) = real_time(&as_given, &host);
        // measured: 0.141°, 0.140° and 0.499°; the clock is recovered after
        // 5.6 s (5444 of 6000 samples retimed)
        assert_eq!(none, 0);
        assert!(retimed > 4000, "{retimed}");
        assert!(recovered < 1.1 * sensor, "{recovered} against {sensor}");
        assert!(given > 2.0 * sensor, "{given} against {sensor}");
        // offline, over the whole minute: the clock is run again from the
        // start primed with what it learnt, so the first seconds are
        // recovered too
        let offline = |c: FilterConfig, x: &[ImuSample]| {
            let out = c.with_offline(true).smooth_samples(x).unwrap();
            (over(&out, 0.0, 10.0), over(&out, 10.0, 60.0))
        };
        let (sensor, recovered, given) = (
            offline(recover, &samples),
            offline(recover, &host),
            offline(as_given, &host),
        );
        // measured, first 10 s and the rest: 0.056°/0.093° with the
        // sensor's stamps, 0.055°/0.092° recovered, 0.30°/0.47° as given
        for (s, r, g) in [
            (sensor.0, recovered.0, given.0),
            (sensor.1, recovered.1, given.1),
        ] {
            assert!(r < 1.2 * s, "{r} against {s}");
            assert!(g > 2.0 * s, "{g} against {s}");
        }
        // a sensor's own stamps: every attitude the same to the bit
        let mut a = recover.pipeline().unwrap();
        let mut b = as_given.pipeline().unwrap();
        for x in &samples {
            assert_eq!(a.update(x), b.update(x));
        }
    }

    /// A motion sampled at `rate` Hz by the slewing machine's sensor behind
    /// an anti-alias low-pass at `bandwidth` Hz, its gyro warming up by 3 °C
    /// a minute (the MPU6050's 0.08 °/s per °C: 0.48 °/s over the two
    /// minutes); the second minute's inclination RMSE and the gyro-bias
    /// error at the end, degrees and °/s.
    fn warming(
        motion: &dyn crate::sim::Motion,
        rate: f64,
        bandwidth: f64,
        seed: u64,
    ) -> (f64, f64) {
        use clino_core::AttitudeFilter;
        let mut model = crate::sim::slewing::sensor().with_bandwidth(bandwidth);
        model.temperature.rate_c_per_s = 0.05;
        let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
        let mut rms = crate::eval::Rms::default();
        for x in model.simulate(motion, rate, 120.0, seed) {
            let q = f.update(&x).attitude;
            if let (Some(q), true) = (q, x.t_s >= 60.0) {
                rms.push(crate::eval::inclination_error(
                    &q,
                    &motion.truth(x.t_s).attitude,
                ));
            }
        }
        let warm = model.temperature.at(120.0) - model.temperature.reference_c;
        let bias = model.gyro.bias + model.gyro.bias_temp_coeff * warm;
        let err = (f.filter().gyro_bias() - bias).norm().to_degrees();
        (rms.value().to_degrees(), err)
    }

    /// [`warming`]: the slow robot arm (moves of 12 s under 0.36 rad/s,
    /// rests of 2 s), at 125 Hz, on a base vibrating at `hz` (an engine at
    /// 30 Hz; a boom's first mode at 1.5–5 Hz, under the rest detector's
    /// vibration low-pass), 1.5 m/s² and 2°/s.
    fn warming_slow_arm(seed: u64, hz: f64) -> (f64, f64) {
        use crate::sim::hand::{HandMotion, HandParams};
        use crate::sim::motion::{Sum, vibration};
        let arm = Sum {
            a: HandMotion::new(HandParams::slow(), seed),
            b: vibration(hz, 2f64.to_radians(), Vec3::new(1.5, 1.0, 1.2)),
        };
        warming(&arm, 125.0, 50.0, seed)
    }

    #[test]
    fn a_warming_gyro_is_followed_through_a_slow_arm_s_short_rests() {
        // The arm's 2-s rests are over before a rest is declared (1.5 s of
        // stillness once the low-passes have settled), so only the learner's
        // short rests see them. While they did not teach the bias, the
        // loop's slow bias pole alone followed the warm-up: 0.54° and 0.82°
        // over the second minute (bias 0.30 and 0.57 °/s off at the end);
        // taught by them, 0.36° and 0.43° (0.30 and 0.27 °/s).
        let tilt: Vec<f64> = [1, 2].map(|seed| warming_slow_arm(seed, 30.0).0).to_vec();
        let mean = tilt.iter().sum::<f64>() / 2.0;
        assert!(mean < 0.5, "{tilt:?} deg");
    }

    #[test]
    fn a_warming_gyro_on_a_swaying_base_is_followed_at_its_short_rests() {
        // The sway passes the short rests' 0.05-s low-passes (at 3 Hz half
        // of 1.5 m/s², over the 0.2-m/s² threshold), so no short rest
        // was seen; the arm's 2-s rests are over before a rest proper is
        // declared, and only the loop's slow bias pole followed the warm-up:
        // 0.75° and 1.08° over the second minute (bias 0.25 and 0.57 °/s off
        // at the end). With the short rests judged on the notched rate and
        // specific force (the rest detector's input): 0.42° and 0.43° (0.30
        // and 0.27 °/s).
        let r: Vec<(f64, f64)> = [(1, 2.4), (2, 3.6)]
            .map(|(seed, hz)| warming_slow_arm(seed, hz))
            .to_vec();
        let mean = (r[0].0 + r[1].0) / 2.0;
        assert!(mean < 0.5, "{r:?} (deg, deg/s)");
    }

    /// What [`boom`] measured: the inclination RMSE after the first rest,
    /// degrees; the amplitude of the tilt error's component at the sway's
    /// frequency, degrees; the gyro scale the rest pairs learnt, and how
    /// many there were.
    struct Boom {
        tilt: f64,
        at_sway: f64,
        scale: Vec3,
        pairs: u32,
    }

    /// The slow robot arm on a boom swaying at `hz` (1.5 m/s², 2°/s), at
    /// 125 Hz, its gyro's scale off by `scale` (`generalise`'s slow+boom
    /// rows: (+2, −1.5, +1) % for gyro±2%, zero calibrated).
    fn boom(seed: u64, hz: f64, scale: Vec3) -> Boom {
        use crate::sim::Motion;
        use crate::sim::hand::{HandMotion, HandParams};
        use crate::sim::motion::{Sum, vibration};
        let p = HandParams::slow();
        let arm = Sum {
            a: HandMotion::new(p, seed),
            b: vibration(hz, 2f64.to_radians(), Vec3::new(1.5, 1.0, 1.2)),
        };
        let mut model = crate::sim::slewing::sensor().with_bandwidth(50.0);
        model.gyro.scale = scale;
        let mut f = clino_core::pipeline::Pipeline::new(FilterSpec::default());
        let mut rms = crate::eval::Rms::default();
        // the error's horizontal components in ENU against e^(−i·2π·hz·t)
        let (mut re, mut im, mut n) = (Vec3::zeros(), Vec3::zeros(), 0.0);
        for x in model.simulate(&arm, 125.0, 120.0, seed) {
            let q = f.update(&x).attitude;
            let truth = arm.truth(x.t_s).attitude;
            if let (Some(q), true) = (q, x.t_s >= p.initial_rest_s) {
                rms.push(crate::eval::inclination_error(&q, &truth));
                let up = |a: &clino_core::Attitude| a.inverse() * Vec3::z();
                let e = truth * up(&q).cross(&up(&truth));
                let ph = std::f64::consts::TAU * hz * x.t_s;
                re += e * ph.cos();
                im -= e * ph.sin();
                n += 1.0;
            }
        }
        let clino_core::filter::AnyFilter::Dynamic(d) = f.filter() else {
            panic!("the default filter is dynamic")
        };
        let amp = |i: usize| 2.0 / n * (re[i] * re[i] + im[i] * im[i]).sqrt();
        Boom {
            tilt: rms.value().to_degrees(),
            at_sway: (amp(0) * amp(0) + amp(1) * amp(1)).sqrt().to_degrees(),
            scale: d.gyro_scale(),
            pairs: d.rest_pairs(),
        }
    }

    #[test]
    fn a_gyro_scale_error_on_a_swaying_boom_is_learnt_at_its_rests() {
        // While a sway was notched no rest ended a rest pair, so a boom's
        // gyro scale error was never learnt, and only the pull at short
        // rests and held poses held the tilt: no pair, 0.215° and 0.234°
        // (generalise, 8 seeds: 0.95× VQF's error). The rests' ends are
        // means that the sway averages out of; with their pairs (10 and 7)
        // the scale error is down from 2.7 % to 0.8 and 1.2 %, and the tilt
        // is 0.172° and 0.177° (generalise, 8 seeds: 0.79×); with the pull
        // on the specific force with the sway notched out
        // (`a_boom_s_sway_is_not_pulled_into_the_tilt_…`), 0.5 and 0.8 %,
        // 0.145° and 0.153°.
        let truth = Vec3::new(0.02, -0.015, 0.01);
        let runs = [(1, 2.4), (2, 3.6)].map(|(seed, hz)| boom(seed, hz, truth));
        for b in &runs {
            let miss = b.scale - truth;
            std::println!(
                "{}°, {} pairs, scale off by {:?} %",
                b.tilt,
                b.pairs,
                miss * 100.0
            );
        }
        for b in &runs {
            assert!(b.pairs >= 5, "{} pairs", b.pairs);
            assert!(
                (b.scale - truth).norm() < 0.6 * truth.norm(),
                "{:?}",
                b.scale
            );
            assert!(b.tilt < 0.19, "{}°", b.tilt);
        }
    }

    #[test]
    fn a_boom_s_sway_is_not_pulled_into_the_tilt_at_short_rests_and_held_poses() {
        // The pull at short rests and held poses acted on each sample's
        // specific force, sway and all: the boom's 1.5 m/s² came through a
        // pull of 0.3 rad/s at up to 0.3/(2πf) of itself, and the tilt error
        // swung at the sway's frequency by 0.108° (1.95 Hz) and 0.135°
        // (1.6 Hz), 0.102° and 0.120° RMS (`generalise --first-seed 101
        // --draw-errors`: seed 107, its boom at 1.95 Hz, 1.41× VQF's error).
        // The pull now acts on the specific force with the sway notched out
        // in the navigation frame: 0.005° and 0.008° at the sway, 0.057° and
        // 0.059° RMS. Notched in the body frame instead, gravity turning with
        // a held pose came through the notch's group delay (0.11 s at 2 Hz):
        // 0.007° at the sway, but 0.224° RMS (seed 1).
        for (seed, hz) in [(1, 1.95), (2, 1.6)] {
            let b = boom(seed, hz, Vec3::zeros());
            std::println!(
                "seed {seed}, {hz} Hz: {}°, {}° at the sway",
                b.tilt,
                b.at_sway
            );
            assert!(b.at_sway < 0.03, "seed {seed}: {}° at the sway", b.at_sway);
            assert!(b.tilt < 0.08, "seed {seed}: {}°", b.tilt);
        }
    }

    /// [`warming`]: the hand of `generalise` (moves of 8 s, rests of 3 s set
    /// down) at 40 Hz.
    fn warming_hand(seed: u64) -> (f64, f64) {
        use crate::sim::hand::{HandMotion, HandParams};
        warming(
            &HandMotion::new(HandParams::by_hand(), seed),
            40.0,
            16.0,
            seed,
        )
    }

    #[test]
    fn a_warming_gyro_set_down_between_moves_is_followed_at_each_rest() {
        // Rests of 3 s set down on a table are quiet (no tremor in the rate,
        // no vibration in the specific force): no creep, so their still rate
        // is the bias and what the bias held before ages as a warming bias
        // does (QUIET_MEMORY_S), not over the minute a held pose's creep needs. Aged over the minute, the
        // bias lagged the warm-up rest after rest: 0.62° and 0.64° over the
        // second minute, the bias 0.34 and 0.36 °/s off at the end; now 0.36°
        // and 0.38° (0.13 and 0.14 °/s).
        let r: Vec<(f64, f64)> = [1, 2].map(warming_hand).to_vec();
        let mean = (r[0].0 + r[1].0) / 2.0;
        assert!(mean < 0.5, "{r:?} (deg, deg/s)");
    }

    #[test]
    fn names_round_trip_and_unknown_is_an_error() {
        for k in FilterKind::ALL {
            assert_eq!(parse_kind(k.name()).unwrap(), k);
            assert_eq!(parse_spec(k.name()).unwrap(), FilterSpec::default_for(k));
        }
        let e = parse_kind("kalman").unwrap_err();
        assert!(e.message.contains("kalman") && e.message.contains("madgwick"));
        let kinds = |s: &str| -> Vec<FilterKind> {
            parse_spec_list(s)
                .unwrap()
                .iter()
                .map(|s| s.kind())
                .collect()
        };
        assert_eq!(
            kinds("mahony, madgwick,mahony"),
            vec![FilterKind::Mahony, FilterKind::Madgwick]
        );
        assert_eq!(kinds("all").len(), 5);
        assert!(parse_spec_list(",").is_err());
        // KEY=VALUE items belong to the filter before them
        let l = parse_spec_list("dynamic:bandwidth=0.2,rest_time=2,mahony,kp=0.5").unwrap();
        let FilterSpec::Dynamic(d) = l[0] else {
            panic!()
        };
        assert_eq!((d.bandwidth_rad_s, d.rest_time_s), (0.2, 2.0));
        assert_eq!(l[1], FilterSpec::Mahony { kp: 0.5, ki: 0.02 });
        assert!(parse_spec_list("kp=0.5,mahony").is_err());
    }

    #[test]
    fn spec_text_round_trips_and_names_only_changes() {
        let s = parse_spec("dynamic:bandwidth=0.25,learn_bias=false").unwrap();
        assert_eq!(
            spec_text(&s),
            "dynamic:bandwidth_rad_s=0.25,learn_bias=false"
        );
        assert_eq!(parse_spec(&spec_text(&s)).unwrap(), s);
        assert_eq!(spec_text(&FilterSpec::default()), "dynamic");
        let h = filter_help();
        for k in FilterKind::ALL {
            for p in FilterSpec::params(k) {
                assert!(h.contains(p.key) && h.contains(p.unit), "{}", p.key);
            }
        }
    }

    #[test]
    fn a_flag_no_chosen_filter_reads_is_an_error() {
        let mut specs = [FilterSpec::default()];
        let e = apply_params(&mut specs, &[("integrator", "rectangle".into())]).unwrap_err();
        assert!(
            e.message.contains("poisson, complementary"),
            "{}",
            e.message
        );
        let mut both = [
            FilterSpec::default(),
            FilterSpec::default_for(FilterKind::Mahony),
        ];
        apply_params(&mut both, &[("kp", "0.3".into())]).unwrap();
        assert_eq!(both[1], FilterSpec::Mahony { kp: 0.3, ki: 0.02 });
        assert_eq!(both[0], FilterSpec::default());
    }

    #[test]
    fn stages_and_bad_gains_are_checked() {
        let c =
            FilterConfig::new(FilterKind::Mahony).with_lever_arm(Some(Vec3::new(0.1, 0.0, 0.0)));
        assert!(c.pipeline().is_ok());
        assert_eq!(c.label(), "mahony+lever");
        let c = FilterConfig::new(FilterKind::Mahony).with_lever_arm(Some(Vec3::new(
            f64::NAN,
            0.0,
            0.0,
        )));
        assert!(c.validate().err().unwrap().message.contains("lever arm"));
        let c = FilterConfig::new(FilterKind::Mahony).with_offline(true);
        assert!(c.validate().err().unwrap().message.contains("offline"));
        let c = FilterConfig::new(FilterKind::Dynamic).with_offline(true);
        assert!(c.validate().is_ok());
        assert_eq!(c.label(), "dynamic+offline");
        let bad = FilterConfig::from_spec(FilterSpec::Madgwick { beta: -0.1 });
        assert!(bad.validate().is_err());
        assert!(parse_spec("dynamic:bandwidth=0").is_err());
        assert!(parse_spec("complementary:k=1.5").is_err());
        assert!(parse_spec("complementary:k=NaN").is_err());
    }

    #[test]
    fn offline_writes_one_row_per_input_row_and_holds_through_dropouts() {
        let r = 15f64.to_radians();
        let (ay, az) = (9.81 * r.sin(), 9.81 * r.cos());
        let mut text = String::from(HEAD);
        for i in 0..400 {
            let g = if i == 200 {
                "nan".to_string()
            } else {
                "0".to_string()
            };
            text.push_str(&format!("{},{g},0,0,0,{ay},{az}\n", i as f64 * 0.01));
        }
        let mut rd =
            ImuCsvReader::new(text.as_bytes(), "mem.csv", &ReadOptions::default()).unwrap();
        let mut out = Vec::new();
        let cfg = FilterConfig::new(FilterKind::Dynamic).with_offline(true);
        let rep = fuse(&mut rd, &mut out, &cfg, &FuseOptions::default()).unwrap();
        let out = String::from_utf8(out).unwrap();
        assert_eq!(rep.counts.samples, 400);
        assert_eq!(rep.counts.dropouts, 1);
        assert_eq!(out.lines().count(), 401);
        let last: Vec<&str> = out.lines().last().unwrap().split(',').collect();
        let incl: f64 = last[7].parse().unwrap();
        assert!((incl - 15.0).abs() < 1e-3, "{incl}");
        assert!(out.lines().nth(201).unwrap().ends_with(",dropout"));
    }

    #[test]
    fn one_output_row_per_input_row_with_static_tilt() {
        // 20° roll at rest: every filter reports 20° inclination and roll.
        let r = 20f64.to_radians();
        let (ay, az) = (9.81 * r.sin(), 9.81 * r.cos());
        let mut text = String::from(HEAD);
        for i in 0..50 {
            text.push_str(&format!("{},0,0,0,0,{ay},{az}\n", i as f64 * 0.01));
        }
        for k in FilterKind::ALL {
            let (rep, out) = run(&text, k, false).unwrap();
            assert_eq!(rep.counts.samples, 50);
            let lines: Vec<&str> = out.lines().collect();
            assert_eq!(lines.len(), 51);
            assert_eq!(lines[0], FUSE_HEADER.join(","));
            let last: Vec<&str> = lines[50].split(',').collect();
            let roll: f64 = last[5].parse().unwrap();
            let incl: f64 = last[7].parse().unwrap();
            // Madgwick normalises its gradient, so at equilibrium rounding noise
            // still moves it by up to β·dt per step (0.1 rad/s · 0.01 s ≈ 0.06°).
            let tol = if k == FilterKind::Madgwick { 0.2 } else { 1e-9 };
            assert!((roll - 20.0).abs() < tol, "{k}: roll {roll}");
            assert!((incl - 20.0).abs() < tol, "{k}: incl {incl}");
            assert!(lines[1].ends_with(",init"));
        }
    }

    #[test]
    fn dropout_rows_hold_state_and_are_counted() {
        let mut text = String::from(HEAD);
        text.push_str("0.00,0,0,0,0,0,9.81\n");
        text.push_str("0.01,0,0,0.5,0,0,9.81\n");
        text.push_str("0.02,nan,0,0.5,0,0,9.81\n");
        text.push_str("0.03,0,0,0.5,0,,9.81\n");
        text.push_str("0.04,0,0,0.5,0,0,9.81\n");
        let (rep, out) = run(&text, FilterKind::Poisson, false).unwrap();
        assert_eq!(rep.counts.dropouts, 2);
        assert_eq!(rep.first_dropout_line, Some(4));
        let rows: Vec<Vec<&str>> = out
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect())
            .collect();
        assert_eq!(rows[2][8], "dropout");
        assert_eq!(rows[3][8], "dropout");
        // Held: same quaternion as the row before.
        assert_eq!(rows[2][1..5], rows[1][1..5]);
        assert_eq!(rows[3][1..5], rows[1][1..5]);
        // After the gap the yaw covers the whole 0.03 s at 0.5 rad/s: 0.01 + 0.03 s in all.
        let qz: f64 = rows[4][4].parse().unwrap();
        let qw: f64 = rows[4][1].parse().unwrap();
        let yaw = 2.0 * qz.atan2(qw);
        assert!((yaw - 0.5 * 0.04).abs() < 1e-12, "yaw {yaw}");
    }

    #[test]
    fn strict_turns_a_dropout_into_an_error_with_line_and_column() {
        let mut text = String::from("# comment\n");
        text.push_str(HEAD);
        text.push_str("0.00,0,0,0,0,0,9.81\n");
        text.push_str("0.01,0,0,0,0,NaN,9.81\n");
        let e = run(&text, FilterKind::Mahony, true).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput);
        assert_eq!(e.line, Some(4));
        assert_eq!(e.column.as_deref(), Some("acc_y_m_s2"));
        assert_eq!(e.file.as_deref(), Some(std::path::Path::new("mem.csv")));
    }

    #[test]
    fn a_huge_finite_cell_is_saturation_not_poison_and_strict_names_it() {
        // issue 15: acc_x = 1e308 on the tenth data row turned every later row into NaN
        let mut text = String::from(HEAD);
        for i in 0..40 {
            let ax = if i == 9 { "1e308" } else { "0" };
            text.push_str(&format!("{},0,0,0.1,{ax},0,9.81\n", i as f64 * 0.01));
        }
        for k in FilterKind::ALL {
            let (rep, out) = run(&text, k, false).unwrap();
            assert_eq!(rep.counts.saturated, 1, "{k}");
            assert_eq!(rep.first_dropout_line, Some(11));
            let rows: Vec<&str> = out.lines().skip(1).collect();
            assert!(rows[9].ends_with(",saturated"), "{k}: {}", rows[9]);
            for r in &rows[10..] {
                assert!(!r.contains("NaN"), "{k}: {r}");
            }
            let e = run(&text, k, true).unwrap_err();
            assert_eq!(
                (e.line, e.column.as_deref()),
                (Some(11), Some("acc_x_m_s2"))
            );
            assert!(e.message.contains("physical bounds"), "{}", e.message);
        }
    }

    #[test]
    fn tilt_trace_is_bounded_and_evenly_spaced() {
        let mut tr = TiltTrace::new(100);
        for i in 0..10_000u64 {
            tr.push(i as f64, [0.0, 0.0, i as f64]);
        }
        let p = tr.points();
        assert!(p.len() <= 100 && p.len() >= 50, "{}", p.len());
        let step = p[1].0 - p[0].0;
        assert_eq!(p[0].0, 0.0);
        assert!(
            p.windows(2).all(|w| w[1].0 - w[0].0 == step),
            "uneven spacing"
        );
        assert_eq!(step, 128.0);
    }

    #[test]
    fn waiting_rows_are_nan_until_a_usable_accelerometer() {
        let mut text = String::from(HEAD);
        text.push_str("0.00,0,0,0,0,0,0\n");
        text.push_str("0.01,0,0,0,0,0,9.81\n");
        let (rep, out) = run(&text, FilterKind::Madgwick, false).unwrap();
        assert_eq!(rep.counts.waiting, 1);
        let first = out.lines().nth(1).unwrap();
        assert_eq!(first, "0.0,NaN,NaN,NaN,NaN,NaN,NaN,NaN,waiting");
    }

    /// A still sensor's sample at `t_s`.
    fn still_at(t_s: f64) -> ImuSample {
        ImuSample::new(t_s, Vec3::zeros(), Vec3::new(0.0, 0.0, clino_core::G0))
    }

    #[test]
    fn a_stamp_between_an_earlier_one_and_the_last_adds_no_time() {
        // 100 Hz, then a stamp 5 ms back (0.195 after 0.20), then one 2 ms
        // after that but still before the last (0.198): the pipeline drops
        // both (not after the last used sample), and so must the smoother
        // (a step measured from the stamp that went back gave 0.198 a
        // positive 3 ms: the running time ran 3 ms past the stamps, 5 ms
        // as given)
        for recover in [true, false] {
            let mut held = HeldRecording::new(recover);
            let mut t: Vec<f64> = (0..=20).map(|k| f64::from(k) * 0.01).collect();
            t.extend([0.195, 0.198, 0.21, 0.22]);
            for &x in &t {
                held.push(&still_at(x));
            }
            held.finish_intervals();
            let running: f64 = held.dt[1..]
                .iter()
                .filter(|d| d.is_finite() && **d > 0.0)
                .sum();
            assert!((running - 0.22).abs() < 1e-9, "{recover}: {running}");
        }
    }

    #[test]
    fn the_stamps_noise_is_reported_after_a_restart_near_the_end() {
        // 100 Hz still, stamps off by ±3 ms (1.7 ms RMS) for 60 s, a 2-s
        // hole, then 1.5 s more: the clock recovered the stamps, the hole
        // started it again, and the last 1.5 s are too few to judge; the
        // stamps' noise reported is the one judged before (it was 0.00 ms)
        let samples: Vec<ImuSample> = (0..6150u32)
            .map(|k| {
                let t = f64::from(k) * 0.01 + if k >= 6000 { 2.0 } else { 0.0 };
                let u = f64::from(k.wrapping_mul(7919) % 1000) / 1000.0;
                still_at(t + 0.003 * (2.0 * u - 1.0))
            })
            .collect();
        let config = FilterConfig::from_spec(FilterSpec::default()).with_offline(true);
        let (outs, retimed, jitter) = offline_outputs_stamped(&config, &samples, false).unwrap();
        assert_eq!(outs.len(), samples.len());
        assert!(retimed > 4000, "{retimed}");
        let j = jitter.unwrap();
        assert!(j > 1e-3 && j < 2.5e-3, "{j}");
    }
}
