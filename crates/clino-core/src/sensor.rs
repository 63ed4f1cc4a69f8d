//! Calibration models applied to raw sensor readings, on the device.
//!
//! Two models of a sensor triad (accelerometer, gyroscope or magnetometer):
//!
//! * [`MatrixModel`] — a bias vector and a scale-and-misalignment matrix,
//!   y = M·(u − u₀). This is the form of the MPU6050 inclinometer paper
//!   ("a micromechanical inclinometer on an MPU 6050 and an Arduino", eqs 1–2:
//!   A = K⁻¹(U_a − U_a0) for accelerometers, W = R⁻¹(U − U₀) for gyros), with
//!   M = K⁻¹ stored directly so that applying it needs no inversion.
//! * [`MwdModel`] — the per-axis model of the measurement-while-drilling paper
//!   ("Error Analysis in Accelerometers Calibration of Measurement while Drilling
//!   Instrument used in Directional Drilling Operations", eqs 1–8): each axis
//!   reads V, and c = V/SF* − B* with SF* and B* cubic in (T − T_c); the axes
//!   are then mixed by the non-orthogonality coefficients m:
//!   y_i = c_i − Σ_{j≠i} m_ij·c_j.
//!
//! The paper's eq 5 writes the third axis with the opposite sign; that is the
//! wiring of its tool's C accelerometer, which this model absorbs in the sign of
//! SF. The models work in whatever frame the triad's axes define; clino's
//! frame conventions apply to the calibrated output (SI units: m/s², rad/s, µT).
//!
//! Everything here is allocation-free and panic-free: a zero scale factor
//! gives an infinite reading, never a panic. Serialisation (TOML/JSON calibration
//! files) comes with the optional `serde` feature, on these same types.

use crate::{ImuSample, Vec3};

#[cfg(feature = "serde")]
use serde::{Deserialize, Serialize};

/// Which triad a model calibrates (fixes the unit of the calibrated output).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum TriadKind {
    /// Accelerometer: specific force, m/s².
    Accel,
    /// Gyroscope: angular rate, rad/s.
    Gyro,
    /// Magnetometer: flux density, µT.
    Mag,
}

impl TriadKind {
    /// The SI unit of the calibrated output, as written in files.
    pub fn unit(self) -> &'static str {
        match self {
            TriadKind::Accel => "m/s^2",
            TriadKind::Gyro => "rad/s",
            TriadKind::Mag => "uT",
        }
    }
}

/// Bias vector and scale-and-misalignment matrix: y = M·(u − u₀).
///
/// MPU6050 inclinometer paper, eqs 1–2 (A = K⁻¹(U_a − U_a0), W = R⁻¹(U − U₀)):
/// `bias` is U₀ (raw units), `matrix` is K⁻¹ (rows; SI units per raw unit).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct MatrixModel {
    /// Zero offset u₀, raw units.
    pub bias: [f64; 3],
    /// M = K⁻¹, row-major: y_i = Σ_j M_ij·(u_j − u₀_j).
    pub matrix: [[f64; 3]; 3],
}

impl MatrixModel {
    /// The identity model (no bias, unit matrix).
    pub const IDENTITY: Self = Self {
        bias: [0.0; 3],
        matrix: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    };

    /// Calibrated reading y = M·(u − u₀).
    ///
    /// ```
    /// use clino_core::sensor::MatrixModel;
    /// use clino_core::Vec3;
    /// let m = MatrixModel { bias: [0.1, 0.0, 0.0], matrix: [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]] };
    /// assert_eq!(m.apply(Vec3::new(1.1, 2.0, 3.0)), Vec3::new(2.0, 2.0, 3.0));
    /// ```
    pub fn apply(&self, u: Vec3) -> Vec3 {
        let d = [u.x - self.bias[0], u.y - self.bias[1], u.z - self.bias[2]];
        let r = |i: usize| {
            self.matrix[i][0] * d[0] + self.matrix[i][1] * d[1] + self.matrix[i][2] * d[2]
        };
        Vec3::new(r(0), r(1), r(2))
    }
}

impl Default for MatrixModel {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// The MWD per-axis model with cubic temperature terms and non-orthogonality.
///
/// MWD calibration paper, eqs 1–2: with ΔT = T − T_c,
/// SF*_i = SF_i + SFT1_i·ΔT + SFT2_i·ΔT² + SFT3_i·ΔT³ and
/// B*_i = B_i + BT1_i·ΔT + BT2_i·ΔT² + BT3_i·ΔT³;
/// eqs 3–8: c_i = V_i/SF*_i − B*_i and y_i = c_i − Σ_{j≠i} m_ij·c_j.
///
/// Units: V in raw units, SF in raw units per SI unit (1 for a sensor that
/// already reports SI units), B in SI units, SFTn in (raw/SI)/°Cⁿ, BTn in
/// SI/°Cⁿ, m dimensionless. Twelve of the numbers are temperature-independent
/// (3 SF, 3 B, 6 m); the 18 SFTn and BTn make the paper's 30.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct MwdModel {
    /// Nominal temperature T_c, °C (the paper uses 30 °C).
    pub tc_c: f64,
    /// Per axis [SF, SFT1, SFT2, SFT3].
    pub scale: [[f64; 4]; 3],
    /// Per axis [B, BT1, BT2, BT3].
    pub bias: [[f64; 4]; 3],
    /// Non-orthogonality m_ij (row i, column j); the diagonal is ignored.
    pub m: [[f64; 3]; 3],
}

#[inline]
fn cubic(c: &[f64; 4], dt: f64) -> f64 {
    c[0] + dt * (c[1] + dt * (c[2] + dt * c[3]))
}

impl MwdModel {
    /// The identity model at nominal temperature `tc_c` (SF = 1, everything else 0).
    pub fn identity(tc_c: f64) -> Self {
        Self {
            tc_c,
            scale: [[1.0, 0.0, 0.0, 0.0]; 3],
            bias: [[0.0; 4]; 3],
            m: [[0.0; 3]; 3],
        }
    }

    /// True when any temperature coefficient is non-zero.
    pub fn is_temperature_dependent(&self) -> bool {
        (0..3).any(|i| (1..4).any(|k| self.scale[i][k] != 0.0 || self.bias[i][k] != 0.0))
    }

    /// Full scale factor SF*_i and bias B*_i of axis `i` (0..3) at temperature `temp_c`
    /// (eqs 1–2 of the MWD paper). An index outside 0..3 is clamped to 2.
    pub fn scale_bias_at(&self, i: usize, temp_c: f64) -> (f64, f64) {
        let i = i.min(2);
        let dt = temp_c - self.tc_c;
        (cubic(&self.scale[i], dt), cubic(&self.bias[i], dt))
    }

    /// The per-axis corrected readings c_i = V_i/SF*_i − B*_i, before the
    /// non-orthogonality mixing. `None` temperature means T = T_c.
    pub fn axis_corrected(&self, v: Vec3, temp_c: Option<f64>) -> Vec3 {
        let t = temp_c.unwrap_or(self.tc_c);
        let mut c = Vec3::zeros();
        for i in 0..3 {
            let (sf, b) = self.scale_bias_at(i, t);
            c[i] = v[i] / sf - b;
        }
        c
    }

    /// Calibrated reading y = (I − m)·c (eqs 3–8). `None` temperature means T = T_c.
    pub fn apply(&self, v: Vec3, temp_c: Option<f64>) -> Vec3 {
        let c = self.axis_corrected(v, temp_c);
        let mut y = c;
        for i in 0..3 {
            for j in 0..3 {
                if i != j {
                    y[i] -= self.m[i][j] * c[j];
                }
            }
        }
        y
    }

    /// The raw reading V that this model maps to the calibrated reading `y` at
    /// `temp_c` (the inverse of [`MwdModel::apply`]), or `None` when I − m is
    /// singular. Used by simulators to make raw data from a true model.
    pub fn invert(&self, y: Vec3, temp_c: f64) -> Option<Vec3> {
        let mut a = nalgebra::Matrix3::identity();
        for i in 0..3 {
            for j in 0..3 {
                if i != j {
                    a[(i, j)] = -self.m[i][j];
                }
            }
        }
        let c = a.try_inverse()? * y;
        let mut v = Vec3::zeros();
        for i in 0..3 {
            let (sf, b) = self.scale_bias_at(i, temp_c);
            v[i] = sf * (c[i] + b);
        }
        Some(v)
    }
}

/// A triad's calibration model: one of the two forms.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "lowercase"))]
pub enum TriadModel {
    /// Bias and scale-and-misalignment matrix (temperature-independent).
    Matrix(MatrixModel),
    /// MWD per-axis model with cubic temperature terms.
    Mwd(MwdModel),
}

impl TriadModel {
    /// Calibrated reading from raw reading `u` at temperature `temp_c` (ignored by
    /// the matrix model; `None` means the MWD model's nominal temperature).
    pub fn apply(&self, u: Vec3, temp_c: Option<f64>) -> Vec3 {
        match self {
            TriadModel::Matrix(m) => m.apply(u),
            TriadModel::Mwd(m) => m.apply(u, temp_c),
        }
    }

    /// True when the model's output depends on temperature.
    pub fn is_temperature_dependent(&self) -> bool {
        match self {
            TriadModel::Matrix(_) => false,
            TriadModel::Mwd(m) => m.is_temperature_dependent(),
        }
    }
}

/// A triad's model together with the temperature range it is valid for.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct TriadCalibration {
    /// The model.
    pub model: TriadModel,
    /// Temperature range the model was fitted over, °C, [min, max].
    pub valid_temp_c: [f64; 2],
}

impl TriadCalibration {
    /// True when `temp_c` lies in the valid range (a missing temperature is
    /// valid only for a temperature-independent model).
    pub fn is_valid_at(&self, temp_c: Option<f64>) -> bool {
        match temp_c {
            Some(t) => t >= self.valid_temp_c[0] && t <= self.valid_temp_c[1],
            None => !self.model.is_temperature_dependent(),
        }
    }
}

/// Calibration of a whole IMU: any of the three triads (a missing one is left as read).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(Serialize, Deserialize))]
pub struct Calibration {
    /// Accelerometer triad.
    pub accel: Option<TriadCalibration>,
    /// Gyroscope triad.
    pub gyro: Option<TriadCalibration>,
    /// Magnetometer triad.
    pub mag: Option<TriadCalibration>,
}

impl Calibration {
    /// The calibrated sample: each triad present in `self` is replaced by its
    /// model's output at the sample's temperature; time, temperature and triads
    /// without a model are unchanged. Range checks are the caller's
    /// ([`TriadCalibration::is_valid_at`]).
    pub fn apply(&self, s: &ImuSample) -> ImuSample {
        let mut out = *s;
        if let Some(c) = &self.accel {
            out.acc_m_s2 = c.model.apply(s.acc_m_s2, s.temp_c);
        }
        if let Some(c) = &self.gyro {
            out.gyr_rad_s = c.model.apply(s.gyr_rad_s, s.temp_c);
        }
        if let (Some(c), Some(m)) = (&self.mag, s.mag_ut) {
            out.mag_ut = Some(c.model.apply(m, s.temp_c));
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn model() -> MwdModel {
        MwdModel {
            tc_c: 30.0,
            scale: [
                [1.02, 1e-4, -2e-6, 3e-8],
                [0.97, -5e-5, 1e-6, 0.0],
                [-1.01, 2e-4, 0.0, -1e-8],
            ],
            bias: [
                [0.05, 1e-3, 1e-5, -1e-7],
                [-0.03, 0.0, -2e-5, 0.0],
                [0.02, -5e-4, 0.0, 2e-7],
            ],
            m: [
                [0.0, 0.002, -0.001],
                [0.003, 0.0, 0.0015],
                [-0.002, 0.001, 0.0],
            ],
        }
    }

    #[test]
    fn mwd_matches_paper_equations_by_hand() {
        let md = model();
        let v = Vec3::new(3.0, -4.0, 8.5);
        let t = 65.0;
        let dt = t - 30.0;
        let c: [f64; 3] = core::array::from_fn(|i| {
            let sf = md.scale[i][0]
                + md.scale[i][1] * dt
                + md.scale[i][2] * dt * dt
                + md.scale[i][3] * dt * dt * dt;
            let b = md.bias[i][0]
                + md.bias[i][1] * dt
                + md.bias[i][2] * dt * dt
                + md.bias[i][3] * dt * dt * dt;
            v[i] / sf - b
        });
        let ga = c[0] - md.m[0][1] * c[1] - md.m[0][2] * c[2];
        let gb = c[1] - md.m[1][0] * c[0] - md.m[1][2] * c[2];
        let gc = c[2] - md.m[2][0] * c[0] - md.m[2][1] * c[1];
        assert_relative_eq!(md.apply(v, Some(t)), Vec3::new(ga, gb, gc), epsilon = 1e-12);
        // no temperature means nominal temperature
        assert_relative_eq!(md.apply(v, None), md.apply(v, Some(30.0)), epsilon = 1e-15);
        assert!(md.is_temperature_dependent());
        assert!(!MwdModel::identity(30.0).is_temperature_dependent());
    }

    #[test]
    fn mwd_invert_round_trip() {
        let md = model();
        for &t in &[25.0, 30.0, 52.5, 80.0] {
            let y = Vec3::new(1.0, -9.0, 3.0);
            let v = md.invert(y, t).unwrap();
            assert_relative_eq!(md.apply(v, Some(t)), y, epsilon = 1e-12);
        }
    }

    #[test]
    fn matrix_model_is_k_inverse_of_offset_reading() {
        // A = K⁻¹(U − U0): build K, U0, a true reading; check the round trip.
        let k = nalgebra::Matrix3::new(1.01, 0.002, -0.003, 0.001, 0.98, 0.004, 0.0, -0.002, 1.03);
        let u0 = Vec3::new(0.1, -0.2, 0.05);
        let a = Vec3::new(0.3, 9.5, -1.2);
        let u = k * a + u0;
        let kinv = k.try_inverse().unwrap();
        let m = MatrixModel {
            bias: [u0.x, u0.y, u0.z],
            matrix: core::array::from_fn(|i| core::array::from_fn(|j| kinv[(i, j)])),
        };
        assert_relative_eq!(m.apply(u), a, epsilon = 1e-12);
        assert_eq!(MatrixModel::default().apply(a), a);
    }

    #[test]
    fn calibration_applies_each_triad_and_keeps_the_rest() {
        let acc = TriadCalibration {
            model: TriadModel::Mwd(model()),
            valid_temp_c: [25.0, 80.0],
        };
        let mag = TriadCalibration {
            model: TriadModel::Matrix(MatrixModel {
                bias: [1.0, 2.0, 3.0],
                ..MatrixModel::IDENTITY
            }),
            valid_temp_c: [-40.0, 85.0],
        };
        let cal = Calibration {
            accel: Some(acc),
            gyro: None,
            mag: Some(mag),
        };
        let mut s = ImuSample::new(1.5, Vec3::new(0.1, 0.2, 0.3), Vec3::new(3.0, -4.0, 8.5));
        s.temp_c = Some(40.0);
        s.mag_ut = Some(Vec3::new(21.0, 2.0, 43.0));
        let out = cal.apply(&s);
        assert_eq!(out.t_s, 1.5);
        assert_eq!(out.gyr_rad_s, s.gyr_rad_s);
        assert_eq!(out.temp_c, Some(40.0));
        assert_relative_eq!(out.acc_m_s2, model().apply(s.acc_m_s2, Some(40.0)));
        assert_eq!(out.mag_ut, Some(Vec3::new(20.0, 0.0, 40.0)));
        assert!(acc.is_valid_at(Some(50.0)));
        assert!(!acc.is_valid_at(Some(90.0)));
        assert!(!acc.is_valid_at(None));
        assert!(mag.is_valid_at(None));
    }

    #[test]
    fn zero_scale_factor_does_not_panic() {
        let mut md = MwdModel::identity(30.0);
        md.scale[0][0] = 0.0;
        let y = md.apply(Vec3::new(1.0, 1.0, 1.0), Some(30.0));
        assert!(!y.x.is_finite());
    }
}
