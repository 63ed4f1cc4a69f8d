//! Simulation: a shaken, rocking cube; noisy chain forces and gyro; faults
//! injected; diagnosis, restoration and their errors measured against truth.
//!
//! The motion ([`ShakeMotion`]) is exact and analytic; the forces come from
//! the forward model (eqs 1–4, 10), so the only errors are the simulated
//! noise ([`NoiseModel`]) and the injected faults ([`FaultKind`]).
//!
//! Measures (one run, [`SimReport`]): a *false alarm* is a window ending
//! before the fault onset that raises an alarm; the *detection delay* is the
//! end of the first alarming window minus the onset; the *diagnosed* set is
//! the most frequent verdict among windows that start after the onset; the
//! *restored linear acceleration error* is `max_t |â(t) − a(t)| / max_t |a(t)|`
//! with `a` the true ENU linear acceleration and `â` decoupled (eq 3, gyro
//! rates) from the forces restored with the diagnosed set from the start of
//! the first alarming window on (offline restoration after diagnosis).

use super::decouple::{RateSource, decouple};
use super::diagnose::{
    Diagnoser, DiagnosisConfig, NoiseModel, Verdict, WindowDiagnosis, diagnose_record,
};
use super::fault_set::FaultSet;
use super::model::{Forces, SixAxisAccelerometer};
use super::recording::Recording;
use super::restore::{Restorer, gyro_derivative, gyro_derivative_sigma};
use crate::report::{PlotSpec, Series, line_plot};
use crate::sim::{Motion, Truth};
use crate::{Error, ErrorKind, Result};
use clino_core::{Attitude, G0, Vec3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};
use std::collections::BTreeMap;
use std::f64::consts::TAU;
use std::path::Path;

/// A cube rocking about a fixed body axis while its housing shakes:
/// `A(t) = A₀·R(axis, Φ·sin(2π f_r t))`, position `p(t) = d·sin(2π f_l t)`
/// (ENU), like the source's crank-slider test platform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShakeMotion {
    /// Attitude at the rocking centre.
    pub initial: Attitude,
    /// Rocking axis in the body frame (unit).
    pub axis: Vec3,
    /// Rocking amplitude Φ, rad.
    pub amplitude_rad: f64,
    /// Rocking frequency, Hz.
    pub rock_hz: f64,
    /// Shaking amplitude per ENU axis, m.
    pub shake_m: Vec3,
    /// Shaking frequency, Hz.
    pub shake_hz: f64,
}

impl Default for ShakeMotion {
    /// Tilted 10° in roll and 5° in pitch, rocking ±20° at 2 Hz about a
    /// skew axis, shaken (4, 3, 2) mm at 5 Hz (linear acceleration up to
    /// ≈ 5.3 m/s², angular acceleration up to ≈ 55 rad/s²).
    fn default() -> Self {
        Self {
            initial: Attitude::from_euler_angles(10f64.to_radians(), 5f64.to_radians(), 0.0),
            axis: Vec3::new(0.3, 1.0, 0.2).normalize(),
            amplitude_rad: 20f64.to_radians(),
            rock_hz: 2.0,
            shake_m: Vec3::new(0.004, 0.003, 0.002),
            shake_hz: 5.0,
        }
    }
}

impl Motion for ShakeMotion {
    fn truth(&self, t_s: f64) -> Truth {
        let wr = TAU * self.rock_hz;
        let wl = TAU * self.shake_hz;
        let phi = self.amplitude_rad * (wr * t_s).sin();
        let dphi = self.amplitude_rad * wr * (wr * t_s).cos();
        let ddphi = -self.amplitude_rad * wr * wr * (wr * t_s).sin();
        let axis = nalgebra::Unit::new_normalize(self.axis);
        Truth {
            t_s,
            attitude: self.initial * Attitude::from_axis_angle(&axis, phi),
            gyr_rad_s: axis.into_inner() * dphi,
            ang_acc_rad_s2: axis.into_inner() * ddphi,
            pos_m: self.shake_m * (wl * t_s).sin(),
            vel_m_s: self.shake_m * (wl * (wl * t_s).cos()),
            acc_m_s2: self.shake_m * (-wl * wl * (wl * t_s).sin()),
        }
    }
}

/// How a faulty chain misbehaves from the onset on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FaultKind {
    /// Output frozen at its value at the onset.
    Stuck,
    /// Constant offset (magnitude in N).
    Bias,
    /// Offset growing linearly (magnitude in N/s).
    Drift,
    /// Extra white noise (magnitude: its standard deviation, N).
    Noise,
}

impl FaultKind {
    /// Every kind.
    pub const ALL: [FaultKind; 4] = [
        FaultKind::Stuck,
        FaultKind::Bias,
        FaultKind::Drift,
        FaultKind::Noise,
    ];

    /// Parse "stuck", "bias", "drift" or "noise".
    pub fn parse(s: &str) -> Result<Self> {
        match s.to_ascii_lowercase().as_str() {
            "stuck" => Ok(FaultKind::Stuck),
            "bias" => Ok(FaultKind::Bias),
            "drift" => Ok(FaultKind::Drift),
            "noise" => Ok(FaultKind::Noise),
            _ => Err(Error::new(
                ErrorKind::InvalidInput,
                format!("unknown fault kind '{s}' (stuck, bias, drift, noise)"),
            )),
        }
    }

    /// Default magnitude: bias 20 mN (2 % of the cube's weight, 100 σ_f),
    /// drift 0.2 N/s, noise 4 mN (20 σ_f); stuck has none.
    pub fn default_magnitude(self) -> f64 {
        match self {
            FaultKind::Stuck => 0.0,
            FaultKind::Bias => 0.02,
            FaultKind::Drift => 0.2,
            FaultKind::Noise => 0.004,
        }
    }

    /// Lower-case name.
    pub fn name(self) -> &'static str {
        match self {
            FaultKind::Stuck => "stuck",
            FaultKind::Bias => "bias",
            FaultKind::Drift => "drift",
            FaultKind::Noise => "noise",
        }
    }
}

/// Per-chain factors on the fault magnitude: distinct values and signs,
/// chosen by a random search over the validation sets so that faults do not
/// cancel: in every relation of the source's scheme a touched relation sees
/// at least 0.035 of the magnitude (normalised), and the fault direction
/// keeps at least 2.4 % of its length outside every other set's fault space.
/// (Equal magnitudes cancel exactly, e.g. b3 = b6 puts a 368 bias inside the
/// fault space of 789.)
const CHAIN_FACTOR: [f64; 9] = [1.1, 1.5, -1.4, -0.9, -1.0, 0.8, -0.7, 1.2, 1.3];

/// Settings of a simulated run.
#[derive(Clone, Debug, PartialEq)]
pub struct SimConfig {
    /// Record length, s.
    pub duration_s: f64,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Fault onset, s.
    pub onset_s: f64,
    /// Measurement noise.
    pub noise: NoiseModel,
    /// Diagnosis settings.
    pub diagnosis: DiagnosisConfig,
    /// Fault magnitude (see [`FaultKind::default_magnitude`]); `None` for the default.
    pub magnitude: Option<f64>,
    /// Half window `K` of the gyro differentiator used in restoration, samples.
    pub derivative_half_window: usize,
    /// Random seed.
    pub seed: u64,
    /// The motion.
    pub motion: ShakeMotion,
}

impl Default for SimConfig {
    /// 1 s at 1 kHz, fault at 0.4 s, reference noise, default diagnosis, K = 10.
    fn default() -> Self {
        Self {
            duration_s: 1.0,
            rate_hz: 1000.0,
            onset_s: 0.4,
            noise: NoiseModel::reference(),
            diagnosis: DiagnosisConfig::default(),
            magnitude: None,
            derivative_half_window: 10,
            seed: 7,
            motion: ShakeMotion::default(),
        }
    }
}

/// Results of one simulated run.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SimReport {
    /// Injected fault set, e.g. "239".
    pub faults: String,
    /// Fault kind.
    pub fault_kind: FaultKind,
    /// Fault magnitude used (N, N/s or N; 0 for stuck).
    pub fault_magnitude: f64,
    /// Fault onset, s.
    pub onset_s: f64,
    /// Diagnosed set by the general scheme, e.g. "239" ("none", "unexplained").
    pub diagnosed: String,
    /// Verdict of the source's scheme (most frequent label).
    pub diagnosed_source: String,
    /// The general diagnosis equals the injected set.
    pub correct: bool,
    /// The source's scheme names the injected set.
    pub source_correct: bool,
    /// An alarm was raised after the onset.
    pub detected: bool,
    /// End of the first alarming window minus the onset, s.
    pub detection_delay_s: Option<f64>,
    /// End of the first window diagnosing the injected set minus the onset, s.
    pub isolation_delay_s: Option<f64>,
    /// Windows ending before the onset that raised an alarm.
    pub false_alarm_windows: usize,
    /// Windows ending before the onset.
    pub pre_onset_windows: usize,
    /// Restored linear acceleration: max error / max truth (see the module doc).
    pub restored_linear_acc_max_rel_error: Option<f64>,
    /// The same without restoration (faulty forces decoupled).
    pub faulty_linear_acc_max_rel_error: f64,
    /// The same for the fault-free noisy forces (noise floor).
    pub fault_free_linear_acc_max_rel_error: f64,
    /// What the scheme can do about the injected set (restorable, isolable,
    /// the sets it cannot be told from), from [`super::analysis::Capability`].
    pub capability: super::analysis::Capability,
    /// The set the restoration used (the diagnosed one, label), if it ran.
    pub restored_with: Option<String>,
    /// What a reader must know before trusting the numbers: a set the
    /// diagnosis cannot locate, a restoration with chains other than the
    /// faulty ones, a restoration worse than none. Empty when all is well.
    pub warnings: Vec<String>,
}

/// One run with its time series (for plots).
#[derive(Clone, Debug)]
pub struct SimOutcome {
    /// The numbers.
    pub report: SimReport,
    /// Time, s.
    pub t_s: Vec<f64>,
    /// True ENU linear acceleration, m/s².
    pub truth_acc: Vec<Vec3>,
    /// Decoupled from the faulty forces, m/s².
    pub faulty_acc: Vec<Vec3>,
    /// Decoupled from the restored forces, m/s².
    pub restored_acc: Vec<Vec3>,
    /// Every window's decision.
    pub windows: Vec<WindowDiagnosis>,
    /// The simulated measurements (faulty forces, noisy gyro), e.g. to write
    /// as CSV for `clino redundancy diagnose`.
    pub recording: Recording,
}

impl SimOutcome {
    /// Plot the x linear acceleration: truth, faulty and restored (like the
    /// source's Fig. 4), to `.svg` or `.png`.
    pub fn plot(&self, path: &Path) -> Result<()> {
        let s = |v: &[Vec3]| {
            self.t_s
                .iter()
                .zip(v)
                .map(|(t, a)| (*t, a.x))
                .collect::<Vec<_>>()
        };
        let err: Vec<(f64, f64)> = self
            .t_s
            .iter()
            .zip(self.restored_acc.iter().zip(&self.truth_acc))
            .map(|(t, (r, a))| (*t, r.x - a.x))
            .collect();
        line_plot(
            path,
            &PlotSpec {
                title: format!(
                    "faults {} ({}), diagnosed {}: x linear acceleration",
                    self.report.faults,
                    self.report.fault_kind.name(),
                    self.report.diagnosed
                ),
                x_label: "time (s)".into(),
                y_label: "a_x (m/s²)".into(),
                ..Default::default()
            },
            &[
                Series::line("faulty", s(&self.faulty_acc)),
                Series::line("truth", s(&self.truth_acc)),
                Series::line("restored", s(&self.restored_acc)),
                Series::line("restored − truth", err),
            ],
        )
    }
}

/// A simulator: one device, one configuration, a diagnoser built once.
pub struct Simulator {
    acc: SixAxisAccelerometer,
    cfg: SimConfig,
    diag: Diagnoser,
}

fn max_rel_error(est: &[Vec3], truth: &[Vec3]) -> f64 {
    let den = truth.iter().map(|a| a.norm()).fold(0.0, f64::max);
    let num = est
        .iter()
        .zip(truth)
        .map(|(e, a)| (e - a).norm())
        .fold(0.0, f64::max);
    num / den
}

fn most_frequent(labels: impl Iterator<Item = String>) -> Option<String> {
    let mut count: BTreeMap<String, usize> = BTreeMap::new();
    for l in labels {
        *count.entry(l).or_default() += 1;
    }
    count.into_iter().max_by_key(|(_, c)| *c).map(|(l, _)| l)
}

impl Simulator {
    /// Validate the configuration and build the diagnoser.
    pub fn new(acc: &SixAxisAccelerometer, cfg: &SimConfig) -> Result<Self> {
        let bad = |m: String| Err(Error::new(ErrorKind::InvalidInput, m));
        if !(cfg.rate_hz > 0.0 && cfg.rate_hz.is_finite()) {
            return bad(format!(
                "sample rate must be positive, got {} Hz",
                cfg.rate_hz
            ));
        }
        if !(cfg.duration_s > 0.0 && cfg.onset_s >= 0.0 && cfg.onset_s < cfg.duration_s) {
            return bad(format!(
                "need 0 ≤ onset < duration, got onset {} s, duration {} s",
                cfg.onset_s, cfg.duration_s
            ));
        }
        let diag = Diagnoser::new(acc, &cfg.noise, &cfg.diagnosis, 1.0 / cfg.rate_hz)?;
        Ok(Self {
            acc: acc.clone(),
            cfg: cfg.clone(),
            diag,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    /// Simulate one run with `faults` of `kind`, noise seeded by `seed`.
    pub fn run(&self, faults: FaultSet, kind: FaultKind, seed: u64) -> Result<SimOutcome> {
        let cfg = &self.cfg;
        let acc = &self.acc;
        let h = 1.0 / cfg.rate_hz;
        let n = (cfg.duration_s * cfg.rate_hz).round() as usize + 1;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * h).collect();
        let truth: Vec<Truth> = t.iter().map(|&t| cfg.motion.truth(t)).collect();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let nf = Normal::new(0.0, cfg.noise.force_sigma_n)
            .map_err(|e| Error::new(ErrorKind::InvalidInput, e.to_string()))?;
        let ng = Normal::new(0.0, cfg.noise.gyro_sigma_rad_s)
            .map_err(|e| Error::new(ErrorKind::InvalidInput, e.to_string()))?;
        let magnitude = match kind {
            FaultKind::Stuck => 0.0,
            _ => cfg.magnitude.unwrap_or(kind.default_magnitude()),
        };
        let nx = Normal::new(
            0.0,
            if kind == FaultKind::Noise {
                magnitude.abs().max(1e-300)
            } else {
                1.0
            },
        )
        .map_err(|e| Error::new(ErrorKind::InvalidInput, e.to_string()))?;
        let mut clean = Vec::with_capacity(n);
        let mut faulty = Vec::with_capacity(n);
        let mut gyr = Vec::with_capacity(n);
        let mut stuck: Option<Forces> = None;
        for (i, s) in truth.iter().enumerate() {
            let f = acc.forces(&s.specific_force(G0), &s.ang_acc_rad_s2)
                + Forces::from_fn(|_, _| nf.sample(&mut rng));
            gyr.push(s.gyr_rad_s + Vec3::from_fn(|_, _| ng.sample(&mut rng)));
            let mut g = f;
            if t[i] >= cfg.onset_s {
                let held = *stuck.get_or_insert(f);
                for c in faults.indices() {
                    g[c] = match kind {
                        FaultKind::Stuck => held[c],
                        FaultKind::Bias => f[c] + magnitude * CHAIN_FACTOR[c],
                        FaultKind::Drift => {
                            f[c] + magnitude * CHAIN_FACTOR[c] * (t[i] - cfg.onset_s)
                        }
                        FaultKind::Noise => f[c] + CHAIN_FACTOR[c].abs() * nx.sample(&mut rng),
                    };
                }
            }
            clean.push(f);
            faulty.push(g);
        }
        let windows = diagnose_record(&self.diag, &t, &faulty, &gyr)?;
        let onset = cfg.onset_s;
        let pre: Vec<_> = windows.iter().filter(|w| w.t_end_s < onset).collect();
        let false_alarms = pre.iter().filter(|w| w.general.alarm()).count();
        let first_alarm = windows
            .iter()
            .find(|w| w.t_end_s >= onset && w.general.alarm());
        let first_iso = windows
            .iter()
            .find(|w| w.t_end_s >= onset && w.general.set() == Some(faults));
        let after: Vec<_> = windows.iter().filter(|w| w.t_start_s >= onset).collect();
        let diagnosed =
            most_frequent(after.iter().map(|w| w.general.label())).unwrap_or_else(|| "none".into());
        let diagnosed_source =
            most_frequent(after.iter().map(|w| w.source.label())).unwrap_or_else(|| "none".into());
        let diagnosed_set = after
            .iter()
            .filter_map(|w| match &w.general {
                Verdict::Faulty(s) if s.to_string() == diagnosed => Some(*s),
                _ => None,
            })
            .next();

        // restoration from the first alarming window on, with the diagnosed set
        let mut restored = faulty.clone();
        let mut restored_ok = false;
        if let (Some(set), Some(alarm)) = (diagnosed_set, first_alarm) {
            let k = cfg.derivative_half_window;
            let eps_sigma = gyro_derivative_sigma(cfg.noise.gyro_sigma_rad_s, h, k.max(1));
            if let Ok(r) = Restorer::new(acc, &cfg.noise, eps_sigma, set) {
                let eps = gyro_derivative(&t, &gyr, k);
                for i in 0..n {
                    if t[i] >= alarm.t_start_s {
                        restored[i] = r.restore(&faulty[i], &eps[i]);
                    }
                }
                restored_ok = true;
            }
        }
        let a_true: Vec<Vec3> = truth.iter().map(|s| s.acc_m_s2).collect();
        let dec = |f: &[Forces]| -> Result<Vec<Vec3>> {
            Ok(decouple(
                acc,
                &t,
                f,
                RateSource::Gyro(&gyr),
                truth[0].attitude,
                Vec3::zeros(),
                G0,
            )?
            .into_iter()
            .map(|d| d.lin_acc_nav_m_s2)
            .collect())
        };
        let a_faulty = dec(&faulty)?;
        let a_clean = dec(&clean)?;
        let a_rest = dec(&restored)?;
        let capability = super::analysis::Capability::of(acc, faults);
        let restored_err = restored_ok.then(|| max_rel_error(&a_rest, &a_true));
        let faulty_err = max_rel_error(&a_faulty, &a_true);
        let mut warnings: Vec<String> = capability.warning(faults).into_iter().collect();
        if let Some(set) = diagnosed_set.filter(|&s| restored_ok && s != faults) {
            warnings.push(format!(
                "the diagnosis named chains {}, not the faulty {}: the restoration replaced the wrong chains",
                set.to_list(),
                faults.to_list()
            ));
        }
        if let Some(e) = restored_err.filter(|&e| e > faulty_err) {
            warnings.push(format!(
                "the restored linear acceleration is worse than the unrestored one ({:.3} % against {:.3} %)",
                100.0 * e,
                100.0 * faulty_err
            ));
        }
        let report = SimReport {
            faults: faults.to_string(),
            fault_kind: kind,
            fault_magnitude: magnitude,
            onset_s: onset,
            correct: diagnosed == faults.to_string(),
            source_correct: diagnosed_source == faults.to_string(),
            diagnosed,
            diagnosed_source,
            detected: first_alarm.is_some(),
            detection_delay_s: first_alarm.map(|w| w.t_end_s - onset),
            isolation_delay_s: first_iso.map(|w| w.t_end_s - onset),
            false_alarm_windows: false_alarms,
            pre_onset_windows: pre.len(),
            restored_linear_acc_max_rel_error: restored_err,
            faulty_linear_acc_max_rel_error: faulty_err,
            fault_free_linear_acc_max_rel_error: max_rel_error(&a_clean, &a_true),
            capability,
            restored_with: diagnosed_set.filter(|_| restored_ok).map(|s| s.to_string()),
            warnings,
        };
        let recording = Recording {
            t_s: t.clone(),
            forces: faulty,
            gyr_rad_s: gyr,
            first_data_line: 2,
            ignored_columns: vec![],
        };
        Ok(SimOutcome {
            report,
            t_s: t,
            truth_acc: a_true,
            faulty_acc: a_faulty,
            restored_acc: a_rest,
            windows,
            recording,
        })
    }
}

/// Summary of a sweep over many fault sets.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SweepSummary {
    /// Fault kind.
    pub fault_kind: FaultKind,
    /// Runs.
    pub runs: usize,
    /// Fraction of runs with an alarm after the onset.
    pub detection_rate: f64,
    /// Alarming windows before the onset over all windows before the onset.
    pub false_alarm_rate: f64,
    /// Windows before the onset, all runs.
    pub pre_onset_windows: usize,
    /// Mean detection delay over detected runs, s.
    pub mean_detection_delay_s: f64,
    /// Largest detection delay, s.
    pub max_detection_delay_s: f64,
    /// Mean isolation delay over runs isolated at some window, s.
    pub mean_isolation_delay_s: f64,
    /// Runs whose general diagnosis equals the injected set.
    pub isolated: usize,
    /// Runs whose source-scheme diagnosis equals the injected set.
    pub isolated_source: usize,
    /// Runs where both schemes name the injected set.
    pub agree: usize,
    /// Runs where the source's scheme names a wrong set (rather than
    /// "unexplained" or "ambiguous").
    pub source_wrong_set: usize,
    /// Largest restored linear-acceleration relative error.
    pub max_restored_linear_acc_rel_error: f64,
    /// The set with that largest error.
    pub worst_restored_set: String,
    /// Injected sets the general scheme got wrong, with the verdict ("1234→1237").
    pub misdiagnosed: Vec<String>,
}

/// Run every set in `sets` with `kind` (seed `cfg.seed + index`), calling
/// `progress(done, total)` after each run.
pub fn sweep(
    sim: &Simulator,
    sets: &[FaultSet],
    kind: FaultKind,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<(SweepSummary, Vec<SimReport>)> {
    let mut reports = Vec::with_capacity(sets.len());
    for (i, &s) in sets.iter().enumerate() {
        reports.push(
            sim.run(s, kind, sim.cfg.seed.wrapping_add(i as u64))?
                .report,
        );
        progress(i + 1, sets.len());
    }
    Ok((summarize(kind, &reports), reports))
}

/// [`sweep`] for each of `kinds` in turn: one summary per kind, in order;
/// `progress(done, total)` counts the runs of the kind in progress.
pub fn sweep_kinds(
    sim: &Simulator,
    sets: &[FaultSet],
    kinds: &[FaultKind],
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<SweepSummary>> {
    kinds
        .iter()
        .map(|&k| sweep(sim, sets, k, progress).map(|(s, _)| s))
        .collect()
}

fn summarize(kind: FaultKind, r: &[SimReport]) -> SweepSummary {
    let mean = |v: &[f64]| {
        if v.is_empty() {
            f64::NAN
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    };
    let delays: Vec<f64> = r.iter().filter_map(|x| x.detection_delay_s).collect();
    let iso: Vec<f64> = r.iter().filter_map(|x| x.isolation_delay_s).collect();
    let pre: usize = r.iter().map(|x| x.pre_onset_windows).sum();
    let fa: usize = r.iter().map(|x| x.false_alarm_windows).sum();
    SweepSummary {
        fault_kind: kind,
        runs: r.len(),
        detection_rate: r.iter().filter(|x| x.detected).count() as f64 / r.len().max(1) as f64,
        false_alarm_rate: if pre == 0 {
            0.0
        } else {
            fa as f64 / pre as f64
        },
        pre_onset_windows: pre,
        mean_detection_delay_s: mean(&delays),
        max_detection_delay_s: delays.iter().copied().fold(0.0, f64::max),
        mean_isolation_delay_s: mean(&iso),
        isolated: r.iter().filter(|x| x.correct).count(),
        isolated_source: r.iter().filter(|x| x.source_correct).count(),
        agree: r.iter().filter(|x| x.correct && x.source_correct).count(),
        source_wrong_set: r
            .iter()
            .filter(|x| !x.source_correct && x.diagnosed_source.chars().all(|c| c.is_ascii_digit()))
            .count(),
        max_restored_linear_acc_rel_error: r
            .iter()
            .filter_map(|x| x.restored_linear_acc_max_rel_error)
            .fold(0.0, f64::max),
        worst_restored_set: r
            .iter()
            .filter_map(|x| {
                x.restored_linear_acc_max_rel_error
                    .map(|e| (e, x.faults.clone()))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .map_or_else(String::new, |(_, s)| s),
        misdiagnosed: r
            .iter()
            .filter(|x| !x.correct)
            .map(|x| format!("{}→{}", x.faults, x.diagnosed))
            .collect(),
    }
}

/// The source's validation set: all single, double and triple faults and
/// the Table 1 quadruples (165 sets).
pub fn validation_sets() -> Vec<FaultSet> {
    let mut v: Vec<FaultSet> = (1..=3).flat_map(FaultSet::all_of_size).collect();
    v.extend(
        super::analysis::TABLE1
            .iter()
            .map(|s| FaultSet::from_label(s).expect("table entries are labels")),
    );
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn short() -> SimConfig {
        SimConfig {
            duration_s: 0.3,
            onset_s: 0.1,
            ..SimConfig::default()
        }
    }

    #[test]
    fn motion_derivatives_by_finite_differences() {
        let m = ShakeMotion::default();
        let (t, d) = (0.137, 1e-5);
        let a = m.truth(t - d);
        let b = m.truth(t + d);
        let c = m.truth(t);
        let fd_acc = (b.vel_m_s - a.vel_m_s) / (2.0 * d);
        assert!((fd_acc - c.acc_m_s2).norm() < 1e-5);
        let fd_eps = (b.gyr_rad_s - a.gyr_rad_s) / (2.0 * d);
        assert!((fd_eps - c.ang_acc_rad_s2).norm() < 1e-4);
        // body rate from the attitude: q̇ = q ⊗ (0, ω/2)
        let dq = a.attitude.inverse() * b.attitude;
        let w = dq.scaled_axis() / (2.0 * d);
        assert!((w - c.gyr_rad_s).norm() < 1e-6);
    }

    #[test]
    fn source_example_239_restores_within_one_percent() {
        let sim =
            Simulator::new(&SixAxisAccelerometer::reference(), &SimConfig::default()).unwrap();
        let s = FaultSet::from_label("239").unwrap();
        for kind in FaultKind::ALL {
            let r = sim.run(s, kind, 11).unwrap().report;
            assert_eq!(r.diagnosed, "239", "{kind:?}: {r:?}");
            let e = r.restored_linear_acc_max_rel_error.unwrap();
            assert!(e < 0.01, "{kind:?}: restored error {e}");
            assert!(r.faulty_linear_acc_max_rel_error > e, "{kind:?}");
            assert_eq!(r.false_alarm_windows, 0);
        }
    }

    #[test]
    fn a_set_that_cannot_be_isolated_is_reported_with_warnings() {
        // 1234 shares its fault directions with 1237: the diagnosis may name
        // another set, and a restoration with it is no restoration
        let sim =
            Simulator::new(&SixAxisAccelerometer::reference(), &SimConfig::default()).unwrap();
        let r = sim
            .run(FaultSet::parse("1,2,3,4").unwrap(), FaultKind::Bias, 7)
            .unwrap()
            .report;
        assert!(!r.capability.isolable && r.capability.restorable, "{r:?}");
        assert!(r.warnings[0].contains("not isolable"), "{:?}", r.warnings);
        if r.restored_with.as_deref().is_some_and(|s| s != "1234") {
            assert!(
                r.warnings.iter().any(|w| w.contains("wrong chains")),
                "{:?}",
                r.warnings
            );
        }
        if r.restored_linear_acc_max_rel_error.unwrap_or(0.0) > r.faulty_linear_acc_max_rel_error {
            assert!(
                r.warnings.iter().any(|w| w.contains("worse")),
                "{:?}",
                r.warnings
            );
        }
        // the source's example: no warning
        let r = sim
            .run(FaultSet::from_label("239").unwrap(), FaultKind::Bias, 7)
            .unwrap()
            .report;
        assert!(r.warnings.is_empty() && r.capability.isolable, "{r:?}");
        assert_eq!(r.restored_with.as_deref(), Some("239"));
    }

    #[test]
    fn all_165_sets_isolated_and_restored_for_every_fault_kind() {
        let sim = Simulator::new(&SixAxisAccelerometer::reference(), &short()).unwrap();
        let sets = validation_sets();
        assert_eq!(sets.len(), 165);
        let a = super::super::analysis::analyze(&SixAxisAccelerometer::reference(), 4);
        for kind in FaultKind::ALL {
            let (s, reports) = sweep(&sim, &sets, kind, &mut |_, _| {}).unwrap();
            assert!(s.misdiagnosed.is_empty(), "{kind:?}: {:?}", s.misdiagnosed);
            assert_eq!(s.detection_rate, 1.0);
            assert!(
                s.max_restored_linear_acc_rel_error < 0.01,
                "{kind:?}: {}",
                s.max_restored_linear_acc_rel_error
            );
            assert_eq!(s.false_alarm_rate, 0.0);
            // the source's scheme agrees wherever it can isolate the set (its
            // per-relation tests are weaker for zero-mean noise faults)
            for r in &reports {
                let k = r.faults.len().to_string();
                if a.source_isolable[&k].contains(&r.faults) && kind != FaultKind::Noise {
                    assert!(
                        r.source_correct,
                        "{kind:?} {}: source said {}",
                        r.faults, r.diagnosed_source
                    );
                }
            }
        }
    }

    #[test]
    fn false_alarm_rate_matches_the_configured_probability() {
        // fault-free: with α = 1 % per test the fault-free statistic alarms in ≈1 % of windows
        let cfg = SimConfig {
            duration_s: 2.0,
            onset_s: 1.999,
            diagnosis: DiagnosisConfig {
                false_alarm_prob: 0.01,
                window_blocks: 1,
                ..DiagnosisConfig::default()
            },
            ..SimConfig::default()
        };
        let sim = Simulator::new(&SixAxisAccelerometer::reference(), &cfg).unwrap();
        let mut fa = 0;
        let mut n = 0;
        for seed in 0..5 {
            let r = sim
                .run(FaultSet::from_label("1").unwrap(), FaultKind::Bias, seed)
                .unwrap()
                .report;
            fa += r.false_alarm_windows;
            n += r.pre_onset_windows;
        }
        let rate = fa as f64 / n as f64;
        assert!(
            n > 900 && (0.002..0.03).contains(&rate),
            "false-alarm rate {rate} over {n}"
        );
    }
}
