//! IMU error model: from truth ([`Truth`]) to sensor readings ([`ImuSample`]).
//!
//! For each triad (gyro, accelerometer) the reading is built in this order:
//!
//! 1. the physical input x (body rate ω_b, or specific force f_b = Cᵀ·(a + g·e_z));
//! 2. scale, misalignment and temperature: x' = (I + diag(s + s_T·ΔT) + M)·x,
//!    with s the scale-factor errors, s_T their temperature coefficients and M
//!    the cross-axis sensitivities (zero diagonal; `M[i][j]` is the response of
//!    axis i to input along j, in rad for small misalignment angles);
//! 3. bias: x' + b + b_T·ΔT + b_F(t) + b_RW(t), where b_F is flicker (1/f)
//!    noise, the IEEE Std 952 bias instability B (two-sided PSD B²/(2πf),
//!    Allan floor B·√(2 ln 2/π) ≈ 0.664·B), synthesised as a sum of first-order
//!    Gauss–Markov processes with correlation times spaced by √10 over
//!    [`TriadErrors::flicker_band_s`], each of variance B²·ln√10/π; and b_RW is
//!    a random walk (IEEE Std 952 rate random walk, coefficient K);
//! 4. sensor bandwidth: a first-order low-pass H(s) = 1/(1 + s/ω_c), integrated
//!    exactly for an input linear between sub-steps, so a sine of frequency f
//!    comes out scaled by 1/√(1 + (f/f_c)²) (to within 0.003 dB up to f_s/30);
//! 5. white noise of density N (σ per sample N·√f_s, i.e. the Allan
//!    deviation N/√τ of IEEE Std 952, the usual reading of a datasheet's
//!    "noise spectral density");
//! 6. quantisation to the LSB, then saturation at ± the full-scale range.
//!
//! ΔT = T − T_ref with the temperature of a [`TempProfile`]. Everything
//! random comes from one ChaCha8 stream seeded by the caller: the same model,
//! motion, rate and seed always give the same samples.
//!
//! ```
//! use clino::sim::{ImuModel, motion::Static};
//! let model = ImuModel::preset("mpu6050").unwrap();
//! let rest = Static::level();
//! let samples = model.simulate(&rest, 100.0, 1.0, 42);
//! assert_eq!(samples.len(), 100);
//! assert!((samples[0].acc_m_s2.z - 9.80665).abs() < 0.5);
//! // streaming form: one sample at a time
//! let mut s = model.stream(&rest, 100.0, 42);
//! assert_eq!(s.next().unwrap(), samples[0]);
//! ```

use super::{Motion, Truth};
use crate::{Error, ErrorKind, Result};
use clino_core::{G0, ImuSample, Vec3};
use nalgebra::Matrix3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// Sensor bandwidth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bandwidth {
    /// No band limit.
    Unlimited,
    /// First-order low-pass with −3 dB cut-off `cutoff_hz`: |H(f)| = 1/√(1 + (f/f_c)²).
    FirstOrder {
        /// Cut-off frequency f_c, Hz.
        cutoff_hz: f64,
    },
}

impl Bandwidth {
    /// Closed-form amplitude response |H(f)| at frequency `f_hz`.
    pub fn gain(&self, f_hz: f64) -> f64 {
        match *self {
            Bandwidth::Unlimited => 1.0,
            Bandwidth::FirstOrder { cutoff_hz } => 1.0 / (1.0 + (f_hz / cutoff_hz).powi(2)).sqrt(),
        }
    }
}

/// Error model of one sensor triad (units: rad/s for the gyro, m/s² for the
/// accelerometer, written `u` below).
#[derive(Clone, Debug, PartialEq)]
pub struct TriadErrors {
    /// Constant bias b, u.
    pub bias: Vec3,
    /// Scale-factor errors s (dimensionless; 0.01 reads 1 % high).
    pub scale: Vec3,
    /// Cross-axis sensitivities M (zero diagonal; the diagonal is ignored).
    pub cross_axis: Matrix3<f64>,
    /// White-noise density N, u/√Hz (Allan deviation N/√τ).
    pub noise_density: f64,
    /// Bias instability B, u (IEEE Std 952 flicker coefficient; Allan floor 0.664·B).
    pub bias_instability: f64,
    /// Range of correlation times (shortest, longest) over which the bias
    /// flicker is 1/f, s. Outside it the flicker PSD flattens (below) or stops (above).
    pub flicker_band_s: (f64, f64),
    /// Random walk of the bias K, u/√s (IEEE Std 952: σ(τ) = K·√(τ/3)).
    pub random_walk: f64,
    /// Bias temperature coefficient b_T, u/°C.
    pub bias_temp_coeff: Vec3,
    /// Scale-factor temperature coefficient s_T, 1/°C.
    pub scale_temp_coeff: Vec3,
    /// Quantisation step (LSB), u; 0 for none.
    pub lsb: f64,
    /// Full-scale range, u (readings saturate at ±range); infinity for none.
    pub range: f64,
    /// Sensor bandwidth.
    pub bandwidth: Bandwidth,
}

impl TriadErrors {
    /// A perfect triad: no error of any kind, infinite range and bandwidth.
    pub fn ideal() -> Self {
        Self {
            bias: Vec3::zeros(),
            scale: Vec3::zeros(),
            cross_axis: Matrix3::zeros(),
            noise_density: 0.0,
            bias_instability: 0.0,
            flicker_band_s: (0.1, 1e4),
            random_walk: 0.0,
            bias_temp_coeff: Vec3::zeros(),
            scale_temp_coeff: Vec3::zeros(),
            lsb: 0.0,
            range: f64::INFINITY,
            bandwidth: Bandwidth::Unlimited,
        }
    }

    fn validate(&self, what: &str) -> Result<()> {
        let bad = |name: &str| {
            Err(Error::new(
                ErrorKind::InvalidInput,
                format!("{what}: {name} must be finite and non-negative"),
            ))
        };
        let finite_v = |v: &Vec3| v.iter().all(|x| x.is_finite());
        if !finite_v(&self.bias)
            || !finite_v(&self.scale)
            || !self.cross_axis.iter().all(|x| x.is_finite())
        {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("{what}: bias, scale and cross-axis must be finite"),
            ));
        }
        if !finite_v(&self.bias_temp_coeff) || !finite_v(&self.scale_temp_coeff) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("{what}: temperature coefficients must be finite"),
            ));
        }
        for (name, v) in [
            ("noise_density", self.noise_density),
            ("bias_instability", self.bias_instability),
            ("random_walk", self.random_walk),
            ("lsb", self.lsb),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(name);
            }
        }
        let (lo, hi) = self.flicker_band_s;
        if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
            return bad("flicker_band_s (0 < shortest ≤ longest)");
        }
        if self.range.is_nan() || self.range <= 0.0 {
            return bad("range (positive)");
        }
        if let Bandwidth::FirstOrder { cutoff_hz } = self.bandwidth
            && !(cutoff_hz.is_finite() && cutoff_hz > 0.0)
        {
            return bad("bandwidth cut-off (positive)");
        }
        Ok(())
    }
}

/// Sensor temperature over time: T(t) = start + rate·t, °C.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TempProfile {
    /// Temperature at t = 0, °C.
    pub start_c: f64,
    /// Rate of change, °C/s.
    pub rate_c_per_s: f64,
    /// Reference temperature of the temperature coefficients, °C.
    pub reference_c: f64,
}

impl TempProfile {
    /// Constant temperature `c` equal to the reference (temperature coefficients inactive).
    pub fn constant(c: f64) -> Self {
        Self {
            start_c: c,
            rate_c_per_s: 0.0,
            reference_c: c,
        }
    }
    /// Temperature at `t_s`, °C.
    pub fn at(&self, t_s: f64) -> f64 {
        self.start_c + self.rate_c_per_s * t_s
    }
}

/// A six-axis IMU error model (gyro and accelerometer triads, temperature, gravity).
#[derive(Clone, Debug, PartialEq)]
pub struct ImuModel {
    /// Name of the preset it came from, or `"custom"`.
    pub name: String,
    /// Gyro errors (u = rad/s).
    pub gyro: TriadErrors,
    /// Accelerometer errors (u = m/s²).
    pub accel: TriadErrors,
    /// Sensor temperature.
    pub temperature: TempProfile,
    /// Local gravity, m/s².
    pub gravity_m_s2: f64,
    /// Low-pass sub-steps per sample (≥ 1): the truth is evaluated this many
    /// times per sample period so the bandwidth filter sees the input finely.
    pub substeps: usize,
}

/// Names accepted by [`ImuModel::preset`].
pub const PRESETS: [&str; 3] = ["ideal", "mpu6050", "mpu6050-raw"];

const DEG: f64 = std::f64::consts::PI / 180.0;

impl ImuModel {
    /// The perfect sensor: reads truth exactly.
    pub fn ideal() -> Self {
        Self {
            name: "ideal".into(),
            gyro: TriadErrors::ideal(),
            accel: TriadErrors::ideal(),
            temperature: TempProfile::constant(25.0),
            gravity_m_s2: G0,
            substeps: 4,
        }
    }

    /// InvenSense MPU-6050 (Product Specification PS-MPU-6000A-00 rev. 3.4),
    /// after a basic calibration.
    ///
    /// From the datasheet: gyro full scale ±250 °/s (FS_SEL = 0) at 131 LSB/(°/s),
    /// rate noise spectral density 0.005 °/s/√Hz; accelerometer ±2 g (AFS_SEL = 0)
    /// at 16384 LSB/g, noise power spectral density 400 µg/√Hz; 16-bit ADCs;
    /// digital low-pass DLPF_CFG = 2 (gyro 98 Hz, accelerometer 94 Hz, modelled
    /// as first order); temperature coefficients from the datasheet's spans:
    /// gyro ZRO ±20 °/s over −40…85 °C (0.32 °/s/°C worst case; we take a quarter,
    /// 0.08 °/s/°C), gyro sensitivity ±2 % over the same span (1.6e-4 /°C),
    /// accelerometer zero-g ±35 mg (x, y) and ±60 mg (z) over 0…70 °C
    /// (0.5 and 0.86 mg/°C), accelerometer sensitivity ±0.02 %/°C. The
    /// temperature is held at the 25 °C reference, so these act only if the
    /// caller sets a [`TempProfile`] ramp.
    ///
    /// Not on the datasheet (assumed, of the order reported for this part in
    /// Allan-variance studies): gyro bias instability B = 0.005 °/s and rate
    /// random walk K = 3e-4 °/s/√s; accelerometer B = 40 µg and K = 20 µg/√s;
    /// flicker over correlation times 0.1 s … 10⁴ s.
    ///
    /// Calibrated residuals (fixed example values): gyro bias (0.05, −0.04,
    /// 0.03) °/s, as a power-on average over a few seconds at rest leaves it;
    /// and a tenth of the untrimmed example values of [`ImuModel::mpu6050_raw`]
    /// for the rest, as a six-position calibration leaves them: gyro scale
    /// (0.3, −0.2, 0.1) %, cross-axis 0.2 %; accelerometer zero-g (5, −4, 8) mg,
    /// scale (0.3, −0.3, 0.2) %, cross-axis 0.2 %.
    pub fn mpu6050() -> Self {
        let mut m = Self::mpu6050_raw();
        m.name = "mpu6050".into();
        for t in [&mut m.gyro, &mut m.accel] {
            t.bias *= 0.1;
            t.scale *= 0.1;
            t.cross_axis *= 0.1;
        }
        m.gyro.bias = Vec3::new(0.05, -0.04, 0.03) * DEG;
        m
    }

    /// The MPU-6050 of [`ImuModel::mpu6050`] with the datasheet's full initial
    /// tolerances as fixed example values (an untrimmed part): gyro bias
    /// (20, −15, 10) °/s within ZRO ±20 °/s; gyro scale (+3, −2, +1) % within
    /// ±3 %; accelerometer zero-g (50, −40, 80) mg within ±50/±80 mg; scale
    /// (+3, −3, +2) %; cross-axis ±2 % (gyro) and ±2 % (accelerometer) in a
    /// fixed sign pattern.
    pub fn mpu6050_raw() -> Self {
        let mg = 1e-3 * G0;
        let ug = 1e-6 * G0;
        let cross = |v: f64| Matrix3::new(0.0, v, -v, -v, 0.0, v, v, -v, 0.0);
        let gyro = TriadErrors {
            bias: Vec3::new(20.0, -15.0, 10.0) * DEG,
            scale: Vec3::new(0.03, -0.02, 0.01),
            cross_axis: cross(0.02),
            noise_density: 0.005 * DEG,
            bias_instability: 0.005 * DEG,
            flicker_band_s: (0.1, 1e4),
            random_walk: 3e-4 * DEG,
            bias_temp_coeff: Vec3::repeat(0.08 * DEG),
            scale_temp_coeff: Vec3::repeat(0.02 / 125.0),
            lsb: DEG / 131.0,
            range: 250.0 * DEG,
            bandwidth: Bandwidth::FirstOrder { cutoff_hz: 98.0 },
        };
        let accel = TriadErrors {
            bias: Vec3::new(50.0, -40.0, 80.0) * mg,
            scale: Vec3::new(0.03, -0.03, 0.02),
            cross_axis: cross(0.02),
            noise_density: 400.0 * ug,
            bias_instability: 40.0 * ug,
            flicker_band_s: (0.1, 1e4),
            random_walk: 20.0 * ug,
            bias_temp_coeff: Vec3::new(0.5, 0.5, 0.86) * mg,
            scale_temp_coeff: Vec3::repeat(2e-4),
            lsb: G0 / 16384.0,
            range: 2.0 * G0,
            bandwidth: Bandwidth::FirstOrder { cutoff_hz: 94.0 },
        };
        Self {
            name: "mpu6050-raw".into(),
            gyro,
            accel,
            temperature: TempProfile::constant(25.0),
            gravity_m_s2: G0,
            substeps: 4,
        }
    }

    /// A preset by name (see [`PRESETS`]).
    pub fn preset(name: &str) -> Result<Self> {
        match name.to_ascii_lowercase().as_str() {
            "ideal" => Ok(Self::ideal()),
            "mpu6050" => Ok(Self::mpu6050()),
            "mpu6050-raw" => Ok(Self::mpu6050_raw()),
            other => Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "unknown sensor preset '{other}' (known: {})",
                    PRESETS.join(", ")
                ),
            )),
        }
    }

    /// This model with both triads band-limited to a first-order low-pass at `cutoff_hz`.
    pub fn with_bandwidth(mut self, cutoff_hz: f64) -> Self {
        self.gyro.bandwidth = Bandwidth::FirstOrder { cutoff_hz };
        self.accel.bandwidth = Bandwidth::FirstOrder { cutoff_hz };
        self
    }

    /// Check every parameter (finite, non-negative where it must be).
    pub fn validate(&self) -> Result<()> {
        self.gyro.validate("gyro")?;
        self.accel.validate("accelerometer")?;
        if !(self.gravity_m_s2.is_finite() && self.gravity_m_s2 > 0.0) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "gravity must be positive",
            ));
        }
        if self.substeps == 0 {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                "substeps must be at least 1",
            ));
        }
        Ok(())
    }

    /// A streaming simulator of this model sampling `motion` at `rate_hz`
    /// from t = 0; see [`ImuStream`].
    pub fn stream<'m, M: Motion + ?Sized>(
        &self,
        motion: &'m M,
        rate_hz: f64,
        seed: u64,
    ) -> ImuStream<'m, M> {
        ImuStream::new(self.clone(), motion, rate_hz, seed)
    }

    /// `round(duration_s·rate_hz)` samples of `motion` at `rate_hz`, starting at t = 0.
    pub fn simulate<M: Motion + ?Sized>(
        &self,
        motion: &M,
        rate_hz: f64,
        duration_s: f64,
        seed: u64,
    ) -> Vec<ImuSample> {
        let n = (duration_s * rate_hz).round().max(0.0) as usize;
        self.stream(motion, rate_hz, seed).take(n).collect()
    }

    /// Like [`ImuModel::simulate`], each sample the mean of `oversample`
    /// samples simulated at `oversample·rate_hz` (an integrating converter):
    /// the time stamp is that of the block's first sample. White noise keeps its
    /// density N; processes faster than the output rate are averaged instead of
    /// aliased (flicker with correlation times below 1/rate_hz stays 1/f).
    pub fn simulate_averaged<M: Motion + ?Sized>(
        &self,
        motion: &M,
        rate_hz: f64,
        duration_s: f64,
        seed: u64,
        oversample: usize,
    ) -> Vec<ImuSample> {
        let k = oversample.max(1);
        let n = (duration_s * rate_hz).round().max(0.0) as usize;
        let mut s = self.stream(motion, rate_hz * k as f64, seed);
        (0..n)
            .map(|_| {
                let mut a = s.next_sample();
                let (mut g, mut f) = (a.gyr_rad_s, a.acc_m_s2);
                for _ in 1..k {
                    let b = s.next_sample();
                    g += b.gyr_rad_s;
                    f += b.acc_m_s2;
                }
                a.gyr_rad_s = g / k as f64;
                a.acc_m_s2 = f / k as f64;
                a
            })
            .collect()
    }
}

/// State of one triad in the stream.
#[derive(Clone, Debug)]
struct TriadState {
    lp: Option<Vec3>,
    prev_in: Vec3,
    /// Gauss–Markov components of the flicker bias: (correlation time, state).
    gm: Vec<(f64, Vec3)>,
    rw: Vec3,
}

/// Ratio between successive flicker correlation times (√10: two per decade).
const FLICKER_RATIO: f64 = 3.162_277_660_168_379_5;

impl TriadState {
    fn new(e: &TriadErrors, rng: &mut ChaCha8Rng) -> Self {
        let mut gm = Vec::new();
        if e.bias_instability > 0.0 {
            let sigma = flicker_sigma(e.bias_instability);
            let mut tc = e.flicker_band_s.0;
            while tc <= e.flicker_band_s.1 * (1.0 + 1e-9) {
                // start in the stationary distribution
                gm.push((tc, normal3(rng) * sigma));
                tc *= FLICKER_RATIO;
            }
        }
        Self {
            lp: None,
            prev_in: Vec3::zeros(),
            gm,
            rw: Vec3::zeros(),
        }
    }
    fn gm_sum(&self) -> Vec3 {
        self.gm.iter().fold(Vec3::zeros(), |a, (_, v)| a + v)
    }
}

/// Standard deviation of each Gauss–Markov component: σ² = B²·ln(ratio)/π, so
/// that their PSDs 2σ²T/(1 + (2πfT)²) sum to B²/(2πf) (two-sided).
fn flicker_sigma(b: f64) -> f64 {
    b * (FLICKER_RATIO.ln() / std::f64::consts::PI).sqrt()
}

/// Per-sample IMU simulation: an iterator of [`ImuSample`]s at a fixed rate.
///
/// Sample k has time stamp k/rate. Also usable one truth at a time with
/// [`ImuStream::next_sample`].
pub struct ImuStream<'m, M: Motion + ?Sized> {
    model: ImuModel,
    motion: &'m M,
    dt: f64,
    k: u64,
    rng: ChaCha8Rng,
    gyro: TriadState,
    accel: TriadState,
}

impl<'m, M: Motion + ?Sized> ImuStream<'m, M> {
    /// A stream of `model` over `motion` at `rate_hz`, seeded by `seed`.
    pub fn new(model: ImuModel, motion: &'m M, rate_hz: f64, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let gyro = TriadState::new(&model.gyro, &mut rng);
        let accel = TriadState::new(&model.accel, &mut rng);
        Self {
            model,
            motion,
            dt: 1.0 / rate_hz,
            k: 0,
            rng,
            gyro,
            accel,
        }
    }

    /// The model being simulated.
    pub fn model(&self) -> &ImuModel {
        &self.model
    }

    /// The next sample (time k/rate).
    pub fn next_sample(&mut self) -> ImuSample {
        let t = self.k as f64 * self.dt;
        self.k += 1;
        let temp = self.model.temperature.at(t);
        let d_t = temp - self.model.temperature.reference_c;
        let g = self.model.gravity_m_s2;
        let n_sub = self.model.substeps.max(1);
        let h = self.dt / n_sub as f64;
        let truth = self.motion.truth(t);
        let (gyr_in, acc_in) = (truth.gyr_rad_s, truth.specific_force(g));
        // band-limit the physical input (sub-stepped, exact for piecewise-linear
        // input); the truth at the sub-steps is evaluated once for both triads
        let limited = |st: &TriadState, e: &TriadErrors| {
            st.lp.is_some() && matches!(e.bandwidth, Bandwidth::FirstOrder { .. })
        };
        let (lg, la) = (
            limited(&self.gyro, &self.model.gyro),
            limited(&self.accel, &self.model.accel),
        );
        let mids: Vec<Truth> = if n_sub > 1 && (lg || la) {
            (1..n_sub)
                .map(|j| self.motion.truth(t - self.dt + h * j as f64))
                .collect()
        } else {
            Vec::new()
        };
        let gm: Vec<Vec3> = if lg {
            mids.iter().map(|m| m.gyr_rad_s).collect()
        } else {
            Vec::new()
        };
        let am: Vec<Vec3> = if la {
            mids.iter().map(|m| m.specific_force(g)).collect()
        } else {
            Vec::new()
        };
        let gyr_f = lowpass(
            &mut self.gyro,
            &self.model.gyro.bandwidth,
            gyr_in,
            &gm,
            self.dt,
        );
        let acc_f = lowpass(
            &mut self.accel,
            &self.model.accel.bandwidth,
            acc_in,
            &am,
            self.dt,
        );
        let dt = self.dt;
        let gyr = apply(
            &self.model.gyro,
            &mut self.gyro,
            gyr_f,
            d_t,
            dt,
            &mut self.rng,
        );
        let acc = apply(
            &self.model.accel,
            &mut self.accel,
            acc_f,
            d_t,
            dt,
            &mut self.rng,
        );
        ImuSample {
            t_s: t,
            gyr_rad_s: gyr,
            acc_m_s2: acc,
            mag_ut: None,
            temp_c: Some(temp),
        }
    }

    /// The truth at the time of the next sample (for comparing filter output with truth).
    pub fn next_truth(&self) -> Truth {
        self.motion.truth(self.k as f64 * self.dt)
    }
}

impl<M: Motion + ?Sized> Iterator for ImuStream<'_, M> {
    type Item = ImuSample;
    fn next(&mut self) -> Option<ImuSample> {
        Some(self.next_sample())
    }
}

fn normal3(rng: &mut ChaCha8Rng) -> Vec3 {
    Vec3::new(
        StandardNormal.sample(rng),
        StandardNormal.sample(rng),
        StandardNormal.sample(rng),
    )
}

/// First-order low-pass y' = (u − y)·ω_c, stepped exactly for u linear over
/// each sub-step of length h: y₁ = a·y₀ + (1 − a)·u₀ + (u₁ − u₀)·(1 − (1 − a)/(ω_c·h)),
/// a = exp(−ω_c·h). The state starts at the first input (steady state at DC).
fn lowpass(st: &mut TriadState, bw: &Bandwidth, u_now: Vec3, mids: &[Vec3], dt: f64) -> Vec3 {
    let Bandwidth::FirstOrder { cutoff_hz } = *bw else {
        return u_now;
    };
    let Some(mut y) = st.lp else {
        st.lp = Some(u_now);
        st.prev_in = u_now;
        return u_now;
    };
    let h = dt / (mids.len() + 1) as f64;
    let wc = 2.0 * std::f64::consts::PI * cutoff_hz;
    let a = (-wc * h).exp();
    let c1 = 1.0 - (1.0 - a) / (wc * h);
    let mut u0 = st.prev_in;
    for &u1 in mids.iter().chain(std::iter::once(&u_now)) {
        y = y * a + u0 * (1.0 - a) + (u1 - u0) * c1;
        u0 = u1;
    }
    st.lp = Some(y);
    st.prev_in = u_now;
    y
}

/// Scale, misalignment, temperature, bias processes, noise, quantisation, saturation.
fn apply(
    e: &TriadErrors,
    st: &mut TriadState,
    x: Vec3,
    d_t: f64,
    dt: f64,
    rng: &mut ChaCha8Rng,
) -> Vec3 {
    let mut m = e.cross_axis;
    for i in 0..3 {
        m[(i, i)] = 1.0 + e.scale[i] + e.scale_temp_coeff[i] * d_t;
    }
    let mut y = m * x + e.bias + e.bias_temp_coeff * d_t + st.gm_sum() + st.rw;
    if e.noise_density > 0.0 {
        y += normal3(rng) * (e.noise_density / dt.sqrt());
    }
    // advance the bias processes to the next sample
    if !st.gm.is_empty() {
        let sigma = flicker_sigma(e.bias_instability);
        for (tc, v) in st.gm.iter_mut() {
            let phi = (-dt / *tc).exp();
            *v = *v * phi + normal3(rng) * (sigma * (1.0 - phi * phi).sqrt());
        }
    }
    if e.random_walk > 0.0 {
        st.rw += normal3(rng) * (e.random_walk * dt.sqrt());
    }
    if e.lsb > 0.0 {
        y = y.map(|v| (v / e.lsb).round() * e.lsb);
    }
    y.map(|v| v.clamp(-e.range, e.range))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::motion::{Conical, Static};
    use approx::assert_relative_eq;

    #[test]
    fn ideal_reads_truth() {
        let c = Conical::about_z(0.2, 1.1);
        let s = ImuModel::ideal().simulate(&c, 100.0, 2.0, 1);
        for smp in &s {
            let tr = c.truth(smp.t_s);
            assert_relative_eq!(smp.gyr_rad_s, tr.gyr_rad_s, epsilon = 1e-15);
            assert_relative_eq!(smp.acc_m_s2, tr.specific_force(G0), epsilon = 1e-14);
        }
    }

    #[test]
    fn seeded_and_reproducible() {
        let m = ImuModel::mpu6050();
        let a = m.simulate(&Static::level(), 100.0, 1.0, 7);
        let b = m.simulate(&Static::level(), 100.0, 1.0, 7);
        let c = m.simulate(&Static::level(), 100.0, 1.0, 8);
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn noise_density_sets_sample_sigma() {
        let mut m = ImuModel::ideal();
        m.gyro.noise_density = 0.01;
        let rate = 200.0;
        let s = m.simulate(&Static::level(), rate, 50.0, 3);
        let var: f64 = s.iter().map(|x| x.gyr_rad_s.x.powi(2)).sum::<f64>() / s.len() as f64;
        let expect = 0.01 * rate.sqrt();
        assert!(
            (var.sqrt() / expect - 1.0).abs() < 0.03,
            "{} vs {}",
            var.sqrt(),
            expect
        );
    }

    #[test]
    fn averaged_simulation_keeps_the_noise_density() {
        let mut m = ImuModel::ideal();
        m.gyro.noise_density = 0.01;
        let rate = 20.0;
        let s = m.simulate_averaged(&Static::level(), rate, 100.0, 3, 10);
        assert_eq!(s.len(), 2000);
        assert_relative_eq!(s[1].t_s, 0.05, epsilon = 1e-12);
        let var: f64 = s.iter().map(|x| x.gyr_rad_s.x.powi(2)).sum::<f64>() / s.len() as f64;
        // σ per output sample N·√rate, as for a sensor sampled at that rate
        let expect = 0.01 * rate.sqrt();
        assert!(
            (var.sqrt() / expect - 1.0).abs() < 0.05,
            "{} vs {expect}",
            var.sqrt()
        );
        assert_relative_eq!(s[7].acc_m_s2.z, G0, epsilon = 1e-12);
    }

    #[test]
    fn scale_bias_cross_axis_quantisation_saturation() {
        let mut m = ImuModel::ideal();
        m.accel.bias = Vec3::new(0.1, 0.0, 0.0);
        m.accel.scale = Vec3::new(0.0, 0.0, 0.01);
        m.accel.cross_axis[(1, 2)] = 0.02;
        m.gyro.lsb = 0.01;
        m.gyro.range = 0.5;
        let c = Conical::about_z(0.1, 2.0); // ω·sin α ≈ 1.25 rad/s > range
        let s = m.simulate(&c, 100.0, 1.0, 0);
        for smp in &s {
            let f = c.truth(smp.t_s).specific_force(G0);
            assert_relative_eq!(smp.acc_m_s2.x, f.x + 0.1, epsilon = 1e-12);
            assert_relative_eq!(smp.acc_m_s2.y, f.y + 0.02 * f.z, epsilon = 1e-12);
            assert_relative_eq!(smp.acc_m_s2.z, 1.01 * f.z, epsilon = 1e-12);
            for v in smp.gyr_rad_s.iter() {
                assert!(v.abs() <= 0.5);
                assert!(((v / 0.01) - (v / 0.01).round()).abs() < 1e-9);
            }
        }
        assert!(
            s.iter()
                .any(|x| x.gyr_rad_s.x == 0.5 || x.gyr_rad_s.x == -0.5)
        );
    }

    #[test]
    fn temperature_ramp_moves_bias() {
        let mut m = ImuModel::ideal();
        m.gyro.bias_temp_coeff = Vec3::new(0.001, 0.0, 0.0);
        m.temperature = TempProfile {
            start_c: 20.0,
            rate_c_per_s: 1.0,
            reference_c: 25.0,
        };
        let s = m.simulate(&Static::level(), 10.0, 2.0, 0);
        assert_relative_eq!(s[0].gyr_rad_s.x, -0.005, epsilon = 1e-15);
        assert_relative_eq!(
            s[19].gyr_rad_s.x,
            0.001 * (20.0 + 1.9 - 25.0),
            epsilon = 1e-12
        );
        assert_eq!(s[19].temp_c, Some(21.9));
    }

    #[test]
    fn first_order_bandwidth_gives_closed_form_gain() {
        // a sine on the gyro through a 2 Hz first-order sensor
        let m = ImuModel::ideal().with_bandwidth(2.0);
        let f = 3.15;
        let c = Conical::about_z(0.05, f);
        let rate = 200.0;
        let s = m.simulate(&c, rate, 6.0, 0);
        // least-squares amplitude over whole periods after the transient
        let w = 2.0 * std::f64::consts::PI * f;
        let (mut scc, mut sss, mut n) = (0.0, 0.0, 0.0);
        for smp in s.iter().filter(|x| x.t_s >= 1.0 && x.t_s < 1.0 + 15.0 / f) {
            scc += smp.gyr_rad_s.y * (w * smp.t_s).cos();
            sss += smp.gyr_rad_s.y * (w * smp.t_s).sin();
            n += 1.0;
        }
        let amp = 2.0 / n * (scc * scc + sss * sss).sqrt();
        let gain = amp / (w * 0.05f64.sin());
        let expect = 1.0 / (1.0 + (f / 2.0f64).powi(2)).sqrt();
        assert!((gain / expect - 1.0).abs() < 1e-3, "{gain} vs {expect}");
        assert_relative_eq!(Bandwidth::FirstOrder { cutoff_hz: 2.0 }.gain(f), expect);
    }

    #[test]
    fn presets_validate_and_unknown_fails() {
        for p in PRESETS {
            ImuModel::preset(p).unwrap().validate().unwrap();
        }
        let e = ImuModel::preset("bogus").unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput);
        let mut m = ImuModel::ideal();
        m.gyro.noise_density = f64::NAN;
        assert!(m.validate().is_err());
    }
}
