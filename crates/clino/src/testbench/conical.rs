//! Frequency response under the conical motion about z (tracking performance).
//!
//! Source: Liu, Cai, Yang, Zhang, "Testing of a MEMS Dynamic Inclinometer
//! Using the Stewart Platform", Sensors 2019, sections 3 and 4.1: at each
//! frequency the gyro, accelerometer and tilt outputs are fitted by a sine at
//! the cone frequency, turned into sensitivities (eqs 6, 7, 8, 11) and
//! plotted as 20·log10 S against frequency.
//!
//! [`analyze_conical`] works on any record (simulated or from the lab);
//! [`run_conical`] simulates the whole bench: cone → IMU model → filter →
//! analysis, one frequency after another.

use super::filters::{filter_factory, run_filter};
use super::sensitivity as sens;
use super::sinefit::fit3;
use crate::Result;
use crate::sim::ImuModel;
use crate::sim::motion::{ConeAxis, Conical};
use crate::sim::platform::PlatformMotion;
use crate::sim::stewart::{Geometry, ServoLegs};
use crate::{Error, ErrorKind};
use clino_core::tilt::{QuatTilt, ZxyTilt};
use clino_core::{Attitude, ImuSample};
use serde::Serialize;

/// Output channels of an inclinometer under test (any may be missing).
#[derive(Clone, Debug, Default)]
pub struct Channels {
    /// Time stamps, s.
    pub t_s: Vec<f64>,
    /// Gyro x, rad/s.
    pub gyr_x: Option<Vec<f64>>,
    /// Gyro y, rad/s.
    pub gyr_y: Option<Vec<f64>>,
    /// Gyro z, rad/s.
    pub gyr_z: Option<Vec<f64>>,
    /// Accelerometer x, m/s².
    pub acc_x: Option<Vec<f64>>,
    /// Accelerometer y, m/s².
    pub acc_y: Option<Vec<f64>>,
    /// Attitude output (tilt; heading is ignored).
    pub attitude: Option<Vec<Attitude>>,
}

impl Channels {
    /// Channels of IMU samples and the filter attitudes computed from them.
    pub fn from_samples(samples: &[ImuSample], attitude: Option<Vec<Attitude>>) -> Self {
        Self {
            t_s: samples.iter().map(|s| s.t_s).collect(),
            gyr_x: Some(samples.iter().map(|s| s.gyr_rad_s.x).collect()),
            gyr_y: Some(samples.iter().map(|s| s.gyr_rad_s.y).collect()),
            gyr_z: Some(samples.iter().map(|s| s.gyr_rad_s.z).collect()),
            acc_x: Some(samples.iter().map(|s| s.acc_m_s2.x).collect()),
            acc_y: Some(samples.iter().map(|s| s.acc_m_s2.y).collect()),
            attitude,
        }
    }

    /// The channels restricted to samples with `t_s` in [t0, t1).
    pub fn window(&self, t0: f64, t1: f64) -> Self {
        let idx: Vec<usize> = (0..self.t_s.len())
            .filter(|&i| self.t_s[i] >= t0 && self.t_s[i] < t1)
            .collect();
        let pick = |v: &Option<Vec<f64>>| v.as_ref().map(|v| idx.iter().map(|&i| v[i]).collect());
        Self {
            t_s: idx.iter().map(|&i| self.t_s[i]).collect(),
            gyr_x: pick(&self.gyr_x),
            gyr_y: pick(&self.gyr_y),
            gyr_z: pick(&self.gyr_z),
            acc_x: pick(&self.acc_x),
            acc_y: pick(&self.acc_y),
            attitude: self
                .attitude
                .as_ref()
                .map(|v| idx.iter().map(|&i| v[i]).collect()),
        }
    }
}

/// A simulated Stewart platform carrying the sensor: the sensor rides the
/// actual (servo-filtered) motion ([`crate::sim::platform::PlatformMotion`])
/// and the reference cone angle comes from the actual pose, as the paper takes
/// it from the encoders by forward kinematics.
#[derive(Clone, Debug, PartialEq)]
pub struct PlatformSpec {
    /// Joint layout and stroke.
    pub geometry: Geometry,
    /// Servo legs.
    pub servo: ServoLegs,
}

impl Default for PlatformSpec {
    /// [`Geometry::typical`] with the default [`ServoLegs`] (20 Hz, ζ = 0.7).
    fn default() -> Self {
        Self {
            geometry: Geometry::typical(),
            servo: ServoLegs::default(),
        }
    }
}

/// Sensitivities (dB) at one cone frequency; `None` where the record lacks the channel.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ConicalPoint {
    /// Cone frequency, Hz.
    pub freq_hz: f64,
    /// Cone angle the sensitivities refer to (the actual one on a simulated platform), degrees.
    pub alpha_deg: f64,
    /// Gyro x sensitivity, dB (eq 6).
    pub gyro_x_db: Option<f64>,
    /// Gyro y sensitivity, dB (eq 6).
    pub gyro_y_db: Option<f64>,
    /// Gyro z sensitivity, dB (eq 6 under a cone about x or y; the paper's
    /// route to S_z, since the z rate of a cone about z is constant).
    pub gyro_z_db: Option<f64>,
    /// Accelerometer x sensitivity, dB (eq 7).
    pub accel_x_db: Option<f64>,
    /// Accelerometer y sensitivity, dB (eq 7).
    pub accel_y_db: Option<f64>,
    /// Tilt sensitivity from the quaternion x component, dB (eq 8).
    pub tilt_x_db: Option<f64>,
    /// Tilt sensitivity from the quaternion y component, dB (eq 8).
    pub tilt_y_db: Option<f64>,
    /// Tilt sensitivity of the sin φ output (z-x-y set), dB (eq 11).
    pub sin_phi_db: Option<f64>,
    /// Tilt sensitivity of the tan θ output (z-x-y set), dB (eq 11).
    pub tan_theta_db: Option<f64>,
}

/// Trend order removed from tilt outputs before fitting (quadratic: offset, drift, and its change).
pub const TILT_TREND_ORDER: usize = 2;

/// Sensitivities of `ch` under a cone of angle `alpha_rad` at `freq_hz`
/// (three-parameter fits at the known frequency; offset removed from gyro and
/// accelerometer, a quadratic trend from the tilt outputs).
pub fn analyze_conical(
    ch: &Channels,
    alpha_rad: f64,
    freq_hz: f64,
    g_m_s2: f64,
) -> Result<ConicalPoint> {
    if !(alpha_rad > 0.0 && alpha_rad < 1.5 && freq_hz > 0.0 && g_m_s2 > 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "conical analysis: cone angle {alpha_rad} rad, frequency {freq_hz} Hz, g {g_m_s2}"
            ),
        ));
    }
    let t = &ch.t_s;
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    let amp = |y: &Option<Vec<f64>>, p: usize| -> Result<Option<f64>> {
        y.as_ref()
            .map(|y| fit3(t, y, freq_hz, p).map(|f| f.amplitude))
            .transpose()
    };
    let db = |s: Option<f64>| s.map(sens::db);
    let (mut tx, mut ty, mut sp, mut tt) = (None, None, None, None);
    if let Some(att) = &ch.attitude {
        if att.len() != t.len() {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "attitude and time have different lengths",
            ));
        }
        let qt: Vec<QuatTilt> = att.iter().map(QuatTilt::from_attitude).collect();
        let z: Vec<ZxyTilt> = att.iter().map(ZxyTilt::from_attitude).collect();
        let p = TILT_TREND_ORDER;
        tx = Some(sens::quat_tilt(
            fit3(t, &qt.iter().map(|q| q.x).collect::<Vec<_>>(), freq_hz, p)?.amplitude,
            alpha_rad,
        ));
        ty = Some(sens::quat_tilt(
            fit3(t, &qt.iter().map(|q| q.y).collect::<Vec<_>>(), freq_hz, p)?.amplitude,
            alpha_rad,
        ));
        sp = Some(sens::sin_phi(
            fit3(
                t,
                &z.iter().map(|z| z.sin_phi()).collect::<Vec<_>>(),
                freq_hz,
                p,
            )?
            .amplitude,
            alpha_rad,
        ));
        tt = Some(sens::tan_theta(
            fit3(
                t,
                &z.iter().map(|z| z.tan_theta()).collect::<Vec<_>>(),
                freq_hz,
                p,
            )?
            .amplitude,
            alpha_rad,
        ));
    }
    Ok(ConicalPoint {
        freq_hz,
        alpha_deg: alpha_rad.to_degrees(),
        gyro_x_db: db(amp(&ch.gyr_x, 0)?.map(|y| sens::gyro(y, w, alpha_rad))),
        gyro_y_db: db(amp(&ch.gyr_y, 0)?.map(|y| sens::gyro(y, w, alpha_rad))),
        gyro_z_db: None,
        accel_x_db: db(amp(&ch.acc_x, 0)?.map(|y| sens::accel(y, g_m_s2, alpha_rad))),
        accel_y_db: db(amp(&ch.acc_y, 0)?.map(|y| sens::accel(y, g_m_s2, alpha_rad))),
        tilt_x_db: db(tx),
        tilt_y_db: db(ty),
        sin_phi_db: db(sp),
        tan_theta_db: db(tt),
    })
}

/// Gyro sensitivities under a cone about body x or y (eq 6 with the axes
/// permuted): about x the y and z rates are harmonic of amplitude ω·sin α,
/// about y the z and x rates. The accelerometer and tilt outputs are not the
/// paper's harmonic signals under these cones and are not reported. For
/// [`ConeAxis::Z`] this is [`analyze_conical`].
pub fn analyze_cone(
    ch: &Channels,
    axis: ConeAxis,
    alpha_rad: f64,
    freq_hz: f64,
    g_m_s2: f64,
) -> Result<ConicalPoint> {
    if axis == ConeAxis::Z {
        return analyze_conical(ch, alpha_rad, freq_hz, g_m_s2);
    }
    if !(alpha_rad > 0.0 && alpha_rad < 1.5 && freq_hz > 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("conical analysis: cone angle {alpha_rad} rad, frequency {freq_hz} Hz"),
        ));
    }
    let w = 2.0 * std::f64::consts::PI * freq_hz;
    let s = |y: &Option<Vec<f64>>| -> Result<Option<f64>> {
        y.as_ref()
            .map(|y| {
                fit3(&ch.t_s, y, freq_hz, 0)
                    .map(|f| sens::db(sens::gyro(f.amplitude, w, alpha_rad)))
            })
            .transpose()
    };
    let (gx, gy, gz) = match axis {
        ConeAxis::X => (None, s(&ch.gyr_y)?, s(&ch.gyr_z)?),
        _ => (s(&ch.gyr_x)?, None, s(&ch.gyr_z)?),
    };
    Ok(ConicalPoint {
        freq_hz,
        alpha_deg: alpha_rad.to_degrees(),
        gyro_x_db: gx,
        gyro_y_db: gy,
        gyro_z_db: gz,
        accel_x_db: None,
        accel_y_db: None,
        tilt_x_db: None,
        tilt_y_db: None,
        sin_phi_db: None,
        tan_theta_db: None,
    })
}

/// The two harmonic quaternion components of a cone about `axis`
/// (about z: x, y; about x: y, z; about y: z, x), each of amplitude sin(α/2).
fn cone_components(axis: ConeAxis, q: &Attitude) -> (f64, f64) {
    match axis {
        ConeAxis::Z => (q.i, q.j),
        ConeAxis::X => (q.j, q.k),
        ConeAxis::Y => (q.k, q.i),
    }
}

/// A simulated conical-motion sweep.
#[derive(Clone, Debug)]
pub struct ConicalConfig {
    /// Cone axis (z for the paper's full test; x or y for the gyro's z axis).
    pub axis: ConeAxis,
    /// Cone angle α, rad.
    pub alpha_rad: f64,
    /// Frequencies, Hz.
    pub freqs_hz: Vec<f64>,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Sensor model.
    pub sensor: ImuModel,
    /// Filter (see [`super::filters::filter_factory`]).
    pub filter: String,
    /// Random seed (frequency i uses seed + i).
    pub seed: u64,
    /// Time discarded at the start (sensor and filter transients), s.
    pub settle_s: f64,
    /// Shortest analysis window, s (rounded up to whole periods).
    pub min_window_s: f64,
    /// Fewest periods in the analysis window.
    pub min_periods: f64,
    /// Largest cone body rate ω·sin α allowed, rad/s: above the frequency where
    /// α would exceed it the cone angle declines as asin(max/ω), as the paper
    /// declines its angles at high frequency (its platform's limit; here the
    /// gyro's range). `None`: α at every frequency.
    pub max_rate_rad_s: Option<f64>,
    /// Run on a simulated servo platform (`None`: the sensor rides the exact cone).
    pub platform: Option<PlatformSpec>,
}

impl ConicalConfig {
    /// The cone angle used at `freq_hz`: α, or asin(max_rate/ω) when smaller.
    pub fn alpha_at(&self, freq_hz: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI * freq_hz;
        match self.max_rate_rad_s {
            Some(m) if m < w * self.alpha_rad.sin() => (m / w).min(1.0).asin(),
            _ => self.alpha_rad,
        }
    }

    /// A sweep with the defaults: 200 Hz, seed 1, 2 s settling, window ≥ 10 s
    /// and ≥ 5 periods, cone rate at most 80 % of the gyro's range.
    pub fn new(alpha_rad: f64, freqs_hz: Vec<f64>, sensor: ImuModel, filter: &str) -> Self {
        let range = sensor.gyro.range;
        Self {
            axis: ConeAxis::Z,
            max_rate_rad_s: range.is_finite().then_some(0.8 * range),
            alpha_rad,
            freqs_hz,
            rate_hz: 200.0,
            sensor,
            filter: filter.to_string(),
            seed: 1,
            settle_s: 2.0,
            min_window_s: 10.0,
            min_periods: 5.0,
            platform: None,
        }
    }
}

/// Analysis window for frequency `f`: whole periods, at least `min_s` and `min_periods`.
pub(crate) fn window_s(f: f64, min_s: f64, min_periods: f64) -> f64 {
    (min_s * f).max(min_periods).ceil() / f
}

/// Check a sweep's common settings.
pub(crate) fn check_sweep(freqs: &[f64], rate_hz: f64) -> Result<()> {
    if freqs.is_empty() {
        return Err(Error::new(ErrorKind::InvalidInput, "no frequencies given"));
    }
    if !(rate_hz.is_finite() && rate_hz > 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("sample rate {rate_hz} Hz"),
        ));
    }
    if let Some(f) = freqs
        .iter()
        .find(|f| !(f.is_finite() && **f > 0.0 && **f < rate_hz / 4.0))
    {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "frequency {f} Hz must be positive and below a quarter of the sample rate ({rate_hz} Hz)"
            ),
        ));
    }
    Ok(())
}

/// Run the simulated conical test at every frequency of `cfg`; `progress(done, total)`
/// is called after each frequency.
pub fn run_conical(
    cfg: &ConicalConfig,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<ConicalPoint>> {
    check_sweep(&cfg.freqs_hz, cfg.rate_hz)?;
    cfg.sensor.validate()?;
    let factory = filter_factory(&cfg.filter, cfg.rate_hz)?;
    let mut out = Vec::with_capacity(cfg.freqs_hz.len());
    for (i, &f) in cfg.freqs_hz.iter().enumerate() {
        let alpha = cfg.alpha_at(f);
        let cone = Conical::new(cfg.axis, alpha, f);
        let win = window_s(f, cfg.min_window_s, cfg.min_periods);
        let total = cfg.settle_s + win;
        let seed = cfg.seed + i as u64;
        let (samples, alpha_ref) = match &cfg.platform {
            None => (cfg.sensor.simulate(&cone, cfg.rate_hz, total, seed), alpha),
            Some(p) => {
                let pm = PlatformMotion::new(&p.geometry, &p.servo, &cone, total + 0.1)?;
                let samples = cfg.sensor.simulate(&pm, cfg.rate_hz, total, seed);
                // the reference: the actual cone angle from the actual poses
                let (t, q): (Vec<f64>, Vec<(f64, f64)>) = samples
                    .iter()
                    .filter(|s| s.t_s >= cfg.settle_s)
                    .map(|s| (s.t_s, cone_components(cfg.axis, &pm.pose(s.t_s).attitude)))
                    .unzip();
                let ax = fit3(&t, &q.iter().map(|q| q.0).collect::<Vec<_>>(), f, 1)?.amplitude;
                let ay = fit3(&t, &q.iter().map(|q| q.1).collect::<Vec<_>>(), f, 1)?.amplitude;
                (samples, 2.0 * (0.5 * (ax + ay)).min(1.0).asin())
            }
        };
        let att = run_filter(&factory, &samples, cfg.rate_hz);
        let ch = Channels::from_samples(&samples, Some(att)).window(cfg.settle_s, total + 1e-9);
        out.push(analyze_cone(
            &ch,
            cfg.axis,
            alpha_ref,
            f,
            cfg.sensor.gravity_m_s2,
        )?);
        progress(i + 1, cfg.freqs_hz.len());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(p: &ConicalPoint) -> [f64; 8] {
        [
            p.gyro_x_db,
            p.gyro_y_db,
            p.accel_x_db,
            p.accel_y_db,
            p.tilt_x_db,
            p.tilt_y_db,
            p.sin_phi_db,
            p.tan_theta_db,
        ]
        .map(Option::unwrap)
    }

    #[test]
    fn ideal_sensor_exact_integration_is_zero_db() {
        let cfg = ConicalConfig::new(
            5f64.to_radians(),
            vec![0.1, 1.0, 3.15, 10.0],
            ImuModel::ideal(),
            "poisson",
        );
        let pts = run_conical(&cfg, &mut |_, _| {}).unwrap();
        for p in &pts {
            for v in all(p) {
                assert!(v.abs() <= 0.05, "{p:?}");
            }
        }
    }

    #[test]
    fn first_order_2hz_sensor_is_minus_5_4_db_at_3_15_hz() {
        let expect = 20.0 * (1.0 / (1.0 + (3.15f64 / 2.0).powi(2)).sqrt()).log10();
        assert!((expect + 5.42).abs() < 0.01);
        let cfg = ConicalConfig::new(
            5f64.to_radians(),
            vec![3.15],
            ImuModel::ideal().with_bandwidth(2.0),
            "poisson",
        );
        let p = &run_conical(&cfg, &mut |_, _| {}).unwrap()[0];
        for v in [p.gyro_x_db, p.gyro_y_db, p.accel_x_db, p.accel_y_db].map(Option::unwrap) {
            assert!((v - expect).abs() < 0.2, "{v} vs {expect}");
        }
        // the gyro-only tilt follows the band-limited gyro
        let t = p.tilt_x_db.unwrap();
        assert!(t < -3.0, "{t}");
    }

    #[test]
    fn slow_servo_platform_is_corrected_by_its_actual_pose() {
        // the legs (5 Hz, ζ = 0.5) amplify a 3 Hz cone by about 14 %: referred to
        // the actual cone (as from the encoders), an ideal sensor still reads 0 dB
        let mut cfg =
            ConicalConfig::new(4f64.to_radians(), vec![3.0], ImuModel::ideal(), "poisson");
        cfg.platform = Some(PlatformSpec {
            geometry: Geometry::typical(),
            servo: ServoLegs {
                natural_hz: 5.0,
                damping: 0.5,
            },
        });
        cfg.min_window_s = 5.0;
        let p = &run_conical(&cfg, &mut |_, _| {}).unwrap()[0];
        assert!((p.alpha_deg / 4.0 - 1.0).abs() > 0.05, "{p:?}");
        for v in [
            p.gyro_x_db,
            p.gyro_y_db,
            p.accel_x_db,
            p.accel_y_db,
            p.tilt_x_db,
            p.tilt_y_db,
        ]
        .map(Option::unwrap)
        {
            assert!(v.abs() < 0.05, "{p:?}");
        }
    }

    #[test]
    fn cones_about_x_and_y_give_the_gyro_z_sensitivity() {
        let mut m = ImuModel::ideal().with_bandwidth(2.0);
        m.gyro.scale = clino_core::Vec3::new(0.0, 0.0, 0.05);
        let expect = 20.0 * (1.05 / (1.0 + (3.15f64 / 2.0).powi(2)).sqrt()).log10();
        for axis in [ConeAxis::X, ConeAxis::Y] {
            let mut cfg = ConicalConfig::new(5f64.to_radians(), vec![3.15], m.clone(), "poisson");
            cfg.axis = axis;
            let p = &run_conical(&cfg, &mut |_, _| {}).unwrap()[0];
            assert!((p.gyro_z_db.unwrap() - expect).abs() < 0.2, "{p:?}");
            assert!(p.accel_x_db.is_none() && p.tilt_x_db.is_none());
        }
    }

    #[test]
    fn cone_angle_declines_within_the_gyro_range() {
        let cfg = ConicalConfig::new(
            5f64.to_radians(),
            vec![1.0, 10.0],
            ImuModel::mpu6050(),
            "poisson",
        );
        assert_eq!(cfg.alpha_at(1.0), 5f64.to_radians());
        let a10 = cfg.alpha_at(10.0);
        let rate = 2.0 * std::f64::consts::PI * 10.0 * a10.sin();
        assert!((rate - 0.8 * 250f64.to_radians()).abs() < 1e-12);
    }

    #[test]
    fn bad_sweeps_are_errors() {
        let mut cfg = ConicalConfig::new(0.1, vec![], ImuModel::ideal(), "poisson");
        assert!(run_conical(&cfg, &mut |_, _| {}).is_err());
        cfg.freqs_hz = vec![80.0];
        assert!(run_conical(&cfg, &mut |_, _| {}).is_err());
        cfg.freqs_hz = vec![1.0];
        cfg.filter = "nope".into();
        assert!(run_conical(&cfg, &mut |_, _| {}).is_err());
    }
}
#[cfg(test)]
mod dynamic_rest_tests {
    use super::*;
    use crate::sim::{Motion, Truth};

    /// The cone held still at its starting attitude for `hold_s`, then turning.
    /// (The rate steps at `hold_s`; the sensor sits at the centre of rotation,
    /// so only the rate and attitude matter.)
    struct HeldCone(Conical, f64);

    impl Motion for HeldCone {
        fn truth(&self, t_s: f64) -> Truth {
            let mut tr = self.0.truth((t_s - self.1).max(0.0));
            if t_s < self.1 {
                tr.gyr_rad_s = clino_core::Vec3::zeros();
                tr.ang_acc_rad_s2 = clino_core::Vec3::zeros();
            }
            tr.t_s = t_s;
            tr
        }
    }

    /// A slow cone (5°, 0.1 Hz: the rate vector, 3.1 °/s, turns slowly) started
    /// from power-on, with or without a rest first: `dynamic` must not take it
    /// for rest (its specific force moves by ≈ 0.27 m/s² against the 0.2 m/s²
    /// threshold) nor learn its rotation as gyro bias.
    #[test]
    fn dynamic_follows_a_slow_cone_from_power_on() {
        let m = ImuModel::mpu6050();
        let (f, alpha, win) = (0.1, 5f64.to_radians(), 40.0);
        let tilt_db = |hold: f64| {
            let total = hold + 2.0 + win;
            let s = m.simulate(&HeldCone(Conical::about_z(alpha, f), hold), 200.0, total, 1);
            let att = run_filter(&filter_factory("dynamic", 200.0).unwrap(), &s, 200.0);
            let ch = Channels::from_samples(&s, Some(att)).window(hold + 2.0, total + 1e-9);
            let p = analyze_cone(&ch, ConeAxis::Z, alpha, f, m.gravity_m_s2).unwrap();
            [p.tilt_x_db.unwrap(), p.tilt_y_db.unwrap()]
        };
        let cold = tilt_db(0.0);
        assert!(cold.iter().all(|v| v.abs() < 0.1), "{cold:?}");
        let held = tilt_db(6.0);
        assert!(held.iter().all(|v| v.abs() < 0.1), "{held:?}");
    }
}
