//! Multi-position fits of a triad model by Levenberg–Marquardt.
//!
//! One engine serves the accelerometer (gravity magnitude, optional reference
//! inclination), the magnetometer (ellipsoid fit: field magnitude) and the
//! gyro on a rate table (known rate vectors). Each observation (a static pose,
//! a rate-table segment, a magnetometer sample) has a raw reading u, a
//! temperature T and a reference; the model maps u to y, and the residuals are
//!
//! * magnitude: r_g = (|y| − G_ref)/σ_g — the MWD paper's e_g (eq 16) uses
//!   |y|² − G_L²; |y| − G_ref has the same minimiser to first order and keeps
//!   the residual in m/s² (or µT) so that parameter uncertainties come out in
//!   the parameters' own units;
//! * inclination: r_T = (atan2(√(y_x² + y_y²), y_z) − θ_ref)/σ_T — the paper's
//!   e_T (eq 17) with clino's body z up (θ is the angle of the housing's z axis
//!   from up). Poses within 2° of 0° or 180° are left out of E_T: there the
//!   inclination has a kink and carries no first-order information;
//! * vector: r = (y − y_ref)/σ (rate table).
//!
//! E = Σr² is the paper's E = E_g + E_T (eqs 18–20) with the two terms weighted
//! by their noise (σ_T = σ_g/G_ref unless given) instead of 1/N each, so that
//! they add in the same units. The paper minimises E by Newton–Raphson with a
//! line search (eq 21); we use the trust-region Levenberg–Marquardt of the
//! `levenberg-marquardt` crate (MINPACK), which reaches the same minimum and is
//! robust to a poor start. Parameter uncertainties are the 1σ of
//! s²·(JᵀJ)⁻¹ at the solution, s² = E/(m − n).
//!
//! ## Observability and the stated convention
//! From magnitudes alone (E_g) a rotation of the triad against the housing
//! changes nothing, so 3 of the 12 nominal parameters are unobservable. We fix
//! them by convention: the **x axis is the sensor's x sensing axis, and y lies
//! in the plane of the sensor's x and y sensing axes** (the misalignment matrix
//! is lower triangular: m_xy = m_xz = m_yz = 0, or M_xy = M_xz = M_yz = 0).
//! A reference inclination (E_T) makes the tilt of the z axis observable, leaving
//! only the rotation about z: then **z is the housing's z axis and the housing's
//! x axis lies in the plane of the sensor's x and z sensing axes** (m_xy = 0).
//! The magnetometer's ellipsoid fit uses the symmetric soft-iron convention
//! (M = Mᵀ, the rotation closest to none). A rate table gives full vectors, so
//! all twelve are observable. Whatever the convention, the fit refuses to return
//! numbers when the Jacobian is rank-deficient, and says which parameter the
//! data cannot see.

use super::statics::Pose;
use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use clino_core::sensor::{MatrixModel, MwdModel, TriadCalibration, TriadKind, TriadModel};
use levenberg_marquardt::{LeastSquaresProblem, LevenbergMarquardt};
use nalgebra::{DMatrix, DVector, Dyn, Matrix3, Owned};
use serde::Serialize;

/// The model to fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelKind {
    /// Bias vector and scale-and-misalignment matrix (12 numbers).
    Matrix,
    /// MWD model at nominal temperature: SF, B, m (12 numbers).
    Mwd12,
    /// MWD model with cubic temperature terms (30 numbers).
    Mwd30,
}

impl ModelKind {
    /// Name as used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            ModelKind::Matrix => "matrix",
            ModelKind::Mwd12 => "mwd12",
            ModelKind::Mwd30 => "mwd30",
        }
    }
    /// Parse a command-line name.
    pub fn parse(s: &str) -> Result<Self> {
        match s {
            "matrix" => Ok(ModelKind::Matrix),
            "mwd12" => Ok(ModelKind::Mwd12),
            "mwd30" => Ok(ModelKind::Mwd30),
            _ => Err(Error::new(
                ErrorKind::InvalidInput,
                format!("unknown model '{s}' (matrix, mwd12, mwd30)"),
            )),
        }
    }
}

/// How the unobservable rotation is fixed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Gauge {
    /// Magnitudes only: lower-triangular misalignment (x along sensor x, y in sensor x–y plane).
    LowerTriangular,
    /// Magnitudes and reference inclination: only the rotation about z is fixed (M_xy = 0).
    ZFromReference,
    /// Symmetric matrix (magnetometer soft iron).
    Symmetric,
    /// Full vectors known (rate table): nothing fixed.
    Full,
}

impl Gauge {
    /// The convention in words, as written in calibration files and reports.
    pub fn statement(self) -> &'static str {
        match self {
            Gauge::LowerTriangular => {
                "magnitudes cannot see the triad's rotation against the housing: by convention x is the sensor's x sensing axis and y lies in the plane of its x and y sensing axes (misalignment lower triangular: m_xy = m_xz = m_yz = 0)"
            }
            Gauge::ZFromReference => {
                "the reference inclination fixes the z axis to the housing's; the rotation about z is not observable: by convention the housing's x axis lies in the plane of the sensor's x and z sensing axes (m_xy = 0)"
            }
            Gauge::Symmetric => {
                "a field magnitude cannot see the triad's rotation: by convention the soft-iron matrix is symmetric (the smallest rotation); align to another triad separately"
            }
            Gauge::Full => {
                "reference vectors are known: all parameters observable, no convention needed"
            }
        }
    }
}

/// One observation for a fit.
#[derive(Clone, Copy, Debug)]
pub struct Observation {
    /// Raw reading.
    pub raw: Vec3,
    /// Temperature, °C.
    pub temp_c: Option<f64>,
    /// Reference inclination, rad (angle of the housing's z axis from up).
    pub ref_inclination: Option<f64>,
    /// Reference vector (rate table), SI.
    pub ref_vector: Option<Vec3>,
}

impl Observation {
    /// An observation with only a raw reading and temperature.
    pub fn new(raw: Vec3, temp_c: Option<f64>) -> Self {
        Self {
            raw,
            temp_c,
            ref_inclination: None,
            ref_vector: None,
        }
    }
}

/// Settings of a fit.
#[derive(Clone, Debug)]
pub struct FitOptions {
    /// Which triad.
    pub kind: TriadKind,
    /// Model to fit.
    pub model: ModelKind,
    /// Reference magnitude (local g in m/s², or field in µT); None for vector fits.
    pub reference_norm: Option<f64>,
    /// Nominal temperature T_c of the MWD model, °C (the paper's 30 °C).
    pub tc_c: f64,
    /// Use reference inclinations when observations carry them.
    pub use_ref_inclination: bool,
    /// Weight of E_T against E_g: the inclination residual is divided by
    /// σ_T = 1/(weight·G_ref), so weight 1 treats one radian of inclination like
    /// G_ref of magnitude error (equal noise on both).
    pub inclination_weight: f64,
}

impl FitOptions {
    /// Accelerometer defaults: standard gravity, T_c = 30 °C, reference inclination used when present.
    pub fn accel(model: ModelKind) -> Self {
        Self {
            kind: TriadKind::Accel,
            model,
            reference_norm: Some(clino_core::G0),
            tc_c: 30.0,
            use_ref_inclination: true,
            inclination_weight: 1.0,
        }
    }
}

/// One fitted parameter.
#[derive(Clone, Debug, Serialize)]
pub struct ParamEstimate {
    /// Name (`SF_x`, `SFT2_y`, `B_z`, `m_yx`, `M_xy`, `u0_x`).
    pub name: String,
    /// Estimate.
    pub value: f64,
    /// 1σ uncertainty.
    pub sigma: f64,
    /// Unit.
    pub unit: String,
}

/// Residuals of one observation before and after calibration.
#[derive(Clone, Debug, Serialize)]
pub struct ObsResidual {
    /// Observation number.
    pub index: usize,
    /// Temperature, °C.
    pub temp_c: Option<f64>,
    /// |y| − reference with the uncalibrated (identity) model.
    pub norm_error_before: Option<f64>,
    /// |y| − reference after calibration.
    pub norm_error_after: Option<f64>,
    /// Inclination error before, deg (when a reference inclination exists).
    pub inclination_error_before_deg: Option<f64>,
    /// Inclination error after, deg.
    pub inclination_error_after_deg: Option<f64>,
    /// |y − y_ref| before (vector fits).
    pub vector_error_before: Option<f64>,
    /// |y − y_ref| after.
    pub vector_error_after: Option<f64>,
}

/// The result of a triad fit.
#[derive(Clone, Debug, Serialize)]
pub struct TriadFit {
    /// Triad.
    pub kind: TriadKind,
    /// Model fitted.
    pub model: ModelKind,
    /// How the unobservable rotation was fixed.
    pub gauge: Gauge,
    /// The convention in words.
    pub convention: String,
    /// The calibration.
    pub calibration: TriadCalibration,
    /// Estimated parameters with 1σ.
    pub params: Vec<ParamEstimate>,
    /// Parameters fixed by the convention (not estimated).
    pub fixed: Vec<String>,
    /// Residuals per observation.
    pub residuals: Vec<ObsResidual>,
    /// RMS magnitude error before / after (unit of the triad).
    pub rms_norm_before: Option<f64>,
    /// RMS magnitude error after.
    pub rms_norm_after: Option<f64>,
    /// RMS inclination error before, deg.
    pub rms_inclination_before_deg: Option<f64>,
    /// RMS inclination error after, deg.
    pub rms_inclination_after_deg: Option<f64>,
    /// RMS vector error before / after.
    pub rms_vector_before: Option<f64>,
    /// RMS vector error after.
    pub rms_vector_after: Option<f64>,
    /// Residual standard deviation s = √(E/(m − n)) of the weighted residuals.
    pub residual_sigma: f64,
    /// Number of residual evaluations by the solver.
    pub evaluations: usize,
    /// Reference magnitude used.
    pub reference_norm: Option<f64>,
    /// Observations used.
    pub observations: usize,
}

impl TriadFit {
    /// The estimate of a parameter by name.
    pub fn param(&self, name: &str) -> Option<&ParamEstimate> {
        self.params.iter().find(|p| p.name == name)
    }
    /// Short human-readable summary.
    pub fn summary(&self) -> String {
        let u = self.kind.unit();
        let mut s = format!(
            "{} fit ({}), {} observations, {} evaluations\nconvention: {}\n",
            self.model.name(),
            match self.kind {
                TriadKind::Accel => "accelerometer",
                TriadKind::Gyro => "gyro",
                TriadKind::Mag => "magnetometer",
            },
            self.observations,
            self.evaluations,
            self.convention
        );
        if let (Some(a), Some(b)) = (self.rms_norm_before, self.rms_norm_after) {
            s += &format!("rms |{u}| error: before {a:.4e}, after {b:.4e} {u}\n");
        }
        if let (Some(a), Some(b)) = (
            self.rms_inclination_before_deg,
            self.rms_inclination_after_deg,
        ) {
            s += &format!("rms inclination error: before {a:.4}°, after {b:.5}°\n");
        }
        if let (Some(a), Some(b)) = (self.rms_vector_before, self.rms_vector_after) {
            s += &format!("rms vector error: before {a:.4e}, after {b:.4e} {u}\n");
        }
        s += "parameter        value          1σ            unit\n";
        for p in &self.params {
            s += &format!(
                "{:10} {:>14.6e} {:>12.3e}   {}\n",
                p.name, p.value, p.sigma, p.unit
            );
        }
        if !self.fixed.is_empty() {
            s += &format!("fixed by convention: {}\n", self.fixed.join(", "));
        }
        s
    }
}

const AX: [&str; 3] = ["x", "y", "z"];

/// One free parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum P {
    /// Matrix model offset u0_i.
    U0(usize),
    /// Matrix model entry M_ij.
    Mat(usize, usize),
    /// Symmetric matrix entry M_ij = M_ji.
    Sym(usize, usize),
    /// MWD scale coefficient SF (k = 0) or SFTk of axis i.
    Sf(usize, usize),
    /// MWD bias coefficient B (k = 0) or BTk of axis i.
    B(usize, usize),
    /// MWD non-orthogonality m_ij.
    M(usize, usize),
}

/// Internal scale of the temperature terms: the solver works with
/// coefficients per (50 °C)^k so that every parameter is of order one or less.
const TEMP_SCALE_C: f64 = 50.0;

impl P {
    /// Factor from a parameter's value to the solver's variable.
    fn solver_scale(self) -> f64 {
        match self {
            P::Sf(_, k) | P::B(_, k) => TEMP_SCALE_C.powi(k as i32),
            _ => 1.0,
        }
    }
    fn name(self) -> String {
        match self {
            P::U0(i) => format!("u0_{}", AX[i]),
            P::Mat(i, j) | P::Sym(i, j) => format!("M_{}{}", AX[i], AX[j]),
            P::Sf(i, 0) => format!("SF_{}", AX[i]),
            P::Sf(i, k) => format!("SFT{k}_{}", AX[i]),
            P::B(i, 0) => format!("B_{}", AX[i]),
            P::B(i, k) => format!("BT{k}_{}", AX[i]),
            P::M(i, j) => format!("m_{}{}", AX[i], AX[j]),
        }
    }
    fn unit(self, si: &str) -> String {
        let t = |k: usize| match k {
            0 => String::new(),
            1 => "/°C".into(),
            k => format!("/°C^{k}"),
        };
        match self {
            P::U0(_) => format!("{si} (raw)"),
            P::Mat(..) | P::Sym(..) => "1 (SI per raw)".into(),
            P::Sf(_, k) => format!("1 (raw per SI){}", t(k)),
            P::B(_, k) => format!("{si}{}", t(k)),
            P::M(..) => "1".into(),
        }
    }
}

/// The model being fitted, in a form cheap to evaluate with derivatives.
#[derive(Clone, Debug)]
pub(crate) enum State {
    Matrix { m: Matrix3<f64>, b: Vec3 },
    Mwd(MwdModel),
}

impl State {
    fn get(&self, p: P) -> f64 {
        match (self, p) {
            (State::Matrix { b, .. }, P::U0(i)) => b[i],
            (State::Matrix { m, .. }, P::Mat(i, j) | P::Sym(i, j)) => m[(i, j)],
            (State::Mwd(md), P::Sf(i, k)) => md.scale[i][k],
            (State::Mwd(md), P::B(i, k)) => md.bias[i][k],
            (State::Mwd(md), P::M(i, j)) => md.m[i][j],
            _ => f64::NAN,
        }
    }
    fn set(&mut self, p: P, v: f64) {
        match (self, p) {
            (State::Matrix { b, .. }, P::U0(i)) => b[i] = v,
            (State::Matrix { m, .. }, P::Mat(i, j)) => m[(i, j)] = v,
            (State::Matrix { m, .. }, P::Sym(i, j)) => {
                m[(i, j)] = v;
                m[(j, i)] = v;
            }
            (State::Mwd(md), P::Sf(i, k)) => md.scale[i][k] = v,
            (State::Mwd(md), P::B(i, k)) => md.bias[i][k] = v,
            (State::Mwd(md), P::M(i, j)) => md.m[i][j] = v,
            _ => {}
        }
    }

    /// Calibrated reading y and its derivatives dy/dp (3 × params).
    pub(crate) fn eval(
        &self,
        params: &[P],
        o: &Observation,
        jac: Option<&mut DMatrix<f64>>,
    ) -> Vec3 {
        match self {
            State::Matrix { m, b } => {
                let d = o.raw - b;
                let y = m * d;
                if let Some(j) = jac {
                    for (c, p) in params.iter().enumerate() {
                        let col = match *p {
                            P::U0(i) => -m.column(i).into_owned(),
                            P::Mat(i, k) => {
                                let mut v = Vec3::zeros();
                                v[i] = d[k];
                                v
                            }
                            P::Sym(i, k) => {
                                let mut v = Vec3::zeros();
                                v[i] += d[k];
                                if i != k {
                                    v[k] += d[i];
                                }
                                v
                            }
                            _ => Vec3::zeros(),
                        };
                        j.fixed_view_mut::<3, 1>(0, c).copy_from(&col);
                    }
                }
                y
            }
            State::Mwd(md) => {
                let t = o.temp_c.unwrap_or(md.tc_c);
                let dt = t - md.tc_c;
                let c = md.axis_corrected(o.raw, Some(t));
                let y = md.apply(o.raw, Some(t));
                if let Some(j) = jac {
                    let mut a = Matrix3::identity();
                    for r in 0..3 {
                        for k in 0..3 {
                            if r != k {
                                a[(r, k)] = -md.m[r][k];
                            }
                        }
                    }
                    for (col, p) in params.iter().enumerate() {
                        let v = match *p {
                            P::Sf(i, k) => {
                                let (sf, _) = md.scale_bias_at(i, t);
                                a.column(i) * (-o.raw[i] / (sf * sf) * dt.powi(k as i32))
                            }
                            P::B(i, k) => a.column(i) * (-dt.powi(k as i32)),
                            P::M(i, k) => {
                                let mut v = Vec3::zeros();
                                v[i] = -c[k];
                                v
                            }
                            _ => Vec3::zeros(),
                        };
                        j.fixed_view_mut::<3, 1>(0, col).copy_from(&v);
                    }
                }
                y
            }
        }
    }

    fn to_model(&self) -> TriadModel {
        match self {
            State::Matrix { m, b } => TriadModel::Matrix(MatrixModel {
                bias: [b.x, b.y, b.z],
                matrix: std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)])),
            }),
            State::Mwd(md) => TriadModel::Mwd(*md),
        }
    }
}

/// Parameters and the convention they imply.
pub(crate) fn parameter_set(model: ModelKind, gauge: Gauge) -> (Vec<P>, Vec<P>) {
    let mut free = Vec::new();
    let mut fixed = Vec::new();
    let off = [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)];
    let is_fixed = |i: usize, j: usize| match gauge {
        Gauge::LowerTriangular => j > i,
        Gauge::ZFromReference => (i, j) == (0, 1),
        Gauge::Symmetric => j > i, // the mirror entry carries it
        Gauge::Full => false,
    };
    match model {
        ModelKind::Matrix => {
            free.extend((0..3).map(P::U0));
            for i in 0..3 {
                for j in 0..3 {
                    if i == j || !is_fixed(i, j) {
                        free.push(if gauge == Gauge::Symmetric {
                            P::Sym(i, j)
                        } else {
                            P::Mat(i, j)
                        });
                    } else if gauge != Gauge::Symmetric {
                        fixed.push(P::Mat(i, j));
                    }
                }
            }
        }
        ModelKind::Mwd12 | ModelKind::Mwd30 => {
            let kmax = if model == ModelKind::Mwd30 { 4 } else { 1 };
            for i in 0..3 {
                for k in 0..kmax {
                    free.push(P::Sf(i, k));
                }
                for k in 0..kmax {
                    free.push(P::B(i, k));
                }
            }
            for (i, j) in off {
                if gauge == Gauge::Symmetric {
                    // symmetric has no meaning for m; use the lower-triangular convention
                    if j > i {
                        fixed.push(P::M(i, j));
                    } else {
                        free.push(P::M(i, j));
                    }
                } else if is_fixed(i, j) {
                    fixed.push(P::M(i, j));
                } else {
                    free.push(P::M(i, j));
                }
            }
        }
    }
    (free, fixed)
}

/// The least-squares problem handed to the solver.
#[derive(Clone)]
pub(crate) struct Problem<'a> {
    pub state: State,
    pub params: Vec<P>,
    pub obs: &'a [Observation],
    pub reference_norm: Option<f64>,
    pub sigma_norm: f64,
    pub sigma_inc: f64,
    pub use_inc: bool,
}

const INC_EDGE: f64 = 2.0 * std::f64::consts::PI / 180.0;

impl Problem<'_> {
    fn uses_inc(&self, o: &Observation) -> bool {
        self.use_inc
            && o.ref_inclination
                .is_some_and(|t| t > INC_EDGE && t < std::f64::consts::PI - INC_EDGE)
    }
    fn n_residuals(&self) -> usize {
        self.obs
            .iter()
            .map(|o| {
                let mut n = 0;
                if o.ref_vector.is_some() {
                    n += 3;
                } else if self.reference_norm.is_some() {
                    n += 1;
                }
                if self.uses_inc(o) {
                    n += 1;
                }
                n
            })
            .sum()
    }
    fn compute(&self, want_jac: bool) -> (DVector<f64>, Option<DMatrix<f64>>) {
        let np = self.params.len();
        let m = self.n_residuals();
        let mut r = DVector::zeros(m);
        let mut jac = want_jac.then(|| DMatrix::zeros(m, np));
        let mut jy = DMatrix::zeros(3, np);
        let mut row = 0;
        for o in self.obs {
            let y = self
                .state
                .eval(&self.params, o, want_jac.then_some(&mut jy));
            if let Some(v) = o.ref_vector {
                let d = (y - v) / self.sigma_norm;
                for k in 0..3 {
                    r[row + k] = d[k];
                    if let Some(j) = jac.as_mut() {
                        for c in 0..np {
                            j[(row + k, c)] = jy[(k, c)] / self.sigma_norm;
                        }
                    }
                }
                row += 3;
            } else if let Some(g) = self.reference_norm {
                let n = y.norm();
                r[row] = (n - g) / self.sigma_norm;
                if let Some(j) = jac.as_mut() {
                    let u = y / n;
                    for c in 0..np {
                        j[(row, c)] = (u.x * jy[(0, c)] + u.y * jy[(1, c)] + u.z * jy[(2, c)])
                            / self.sigma_norm;
                    }
                }
                row += 1;
            }
            if self.uses_inc(o) {
                let rho = y.x.hypot(y.y);
                let n2 = y.norm_squared();
                let th = rho.atan2(y.z);
                r[row] = (th - o.ref_inclination.unwrap_or(0.0)) / self.sigma_inc;
                if let Some(j) = jac.as_mut() {
                    let g = Vec3::new(y.x * y.z / (rho * n2), y.y * y.z / (rho * n2), -rho / n2);
                    for c in 0..np {
                        j[(row, c)] = (g.x * jy[(0, c)] + g.y * jy[(1, c)] + g.z * jy[(2, c)])
                            / self.sigma_inc;
                    }
                }
                row += 1;
            }
        }
        (r, jac)
    }
}

impl LeastSquaresProblem<f64, Dyn, Dyn> for Problem<'_> {
    type ResidualStorage = Owned<f64, Dyn>;
    type JacobianStorage = Owned<f64, Dyn, Dyn>;
    type ParameterStorage = Owned<f64, Dyn>;

    fn set_params(&mut self, x: &DVector<f64>) {
        for (p, v) in self.params.clone().into_iter().zip(x.iter()) {
            self.state.set(p, *v / p.solver_scale());
        }
    }
    fn params(&self) -> DVector<f64> {
        DVector::from_iterator(
            self.params.len(),
            self.params
                .iter()
                .map(|p| self.state.get(*p) * p.solver_scale()),
        )
    }
    fn residuals(&self) -> Option<DVector<f64>> {
        let (r, _) = self.compute(false);
        r.iter().all(|v| v.is_finite()).then_some(r)
    }
    fn jacobian(&self) -> Option<DMatrix<f64>> {
        let (_, j) = self.compute(true);
        let mut j = j.filter(|j| j.iter().all(|v| v.is_finite()))?;
        for (c, p) in self.params.iter().enumerate() {
            j.column_mut(c).unscale_mut(p.solver_scale());
        }
        Some(j)
    }
}

/// Column-scaled SVD of J: returns (covariance of the unscaled parameters, smallest
/// relative singular value, the parameter that dominates the weakest direction).
pub(crate) fn covariance(j: &DMatrix<f64>) -> (DMatrix<f64>, f64, usize) {
    let n = j.ncols();
    let scale: Vec<f64> = (0..n)
        .map(|c| {
            let s = j.column(c).norm();
            if s > 0.0 { 1.0 / s } else { 1.0 }
        })
        .collect();
    let mut js = j.clone();
    for (c, s) in scale.iter().enumerate() {
        js.column_mut(c).scale_mut(*s);
    }
    let svd = js.svd(false, true);
    let sv = &svd.singular_values;
    let smax = sv.max();
    let (imin, smin) =
        sv.iter().enumerate().fold(
            (0, f64::INFINITY),
            |a, (i, &s)| if s < a.1 { (i, s) } else { a },
        );
    let vt = svd.v_t.as_ref().expect("v_t requested");
    let weakest = (0..n)
        .max_by(|&a, &b| vt[(imin, a)].abs().total_cmp(&vt[(imin, b)].abs()))
        .unwrap_or(0);
    // (JᵀJ)⁻¹ = D V Σ⁻² Vᵀ D
    let mut cov = DMatrix::zeros(n, n);
    for k in 0..sv.len() {
        let s2 = sv[k] * sv[k];
        if s2 <= 0.0 {
            continue;
        }
        for a in 0..n {
            for b in 0..n {
                cov[(a, b)] += vt[(k, a)] * vt[(k, b)] / s2;
            }
        }
    }
    for a in 0..n {
        for b in 0..n {
            cov[(a, b)] *= scale[a] * scale[b];
        }
    }
    (cov, if smax > 0.0 { smin / smax } else { 0.0 }, weakest)
}

/// Half-axes (±x, ±y, ±z) along which no observation's raw reading points
/// (normalised component ≥ 0.5, i.e. within 60°).
pub fn missing_half_axes(obs: &[Observation]) -> Vec<String> {
    let mut out = Vec::new();
    for (i, ax) in AX.iter().enumerate() {
        for sgn in [1.0, -1.0] {
            let seen = obs.iter().any(|o| {
                let n = o.raw.norm();
                n > 0.0 && sgn * o.raw[i] / n >= 0.5
            });
            if !seen {
                out.push(format!("{}{ax}", if sgn > 0.0 { "+" } else { "-" }));
            }
        }
    }
    out
}

/// Observations from static poses (accelerometer or magnetometer mean readings).
pub fn observations_from_poses(poses: &[Pose], kind: TriadKind) -> Vec<Observation> {
    poses
        .iter()
        .map(|p| Observation {
            raw: match kind {
                TriadKind::Mag => p.mag(),
                TriadKind::Gyro => p.gyr(),
                TriadKind::Accel => p.acc(),
            },
            temp_c: p.temp_c,
            ref_inclination: p.ref_inclination_deg.map(f64::to_radians),
            ref_vector: None,
        })
        .collect()
}

/// True when a Levenberg–Marquardt run ended at a usable solution: converged,
/// or stopped at machine precision or the evaluation limit (the covariance
/// check that follows catches a poor one).
pub(crate) fn solver_succeeded(t: &levenberg_marquardt::TerminationReason) -> bool {
    use levenberg_marquardt::TerminationReason as T;
    t.was_successful() || matches!(t, T::NoImprovementPossible(_) | T::LostPatience)
}

/// A clear error for a failed Levenberg–Marquardt run of `what`.
pub(crate) fn solver_error(what: &str, t: &levenberg_marquardt::TerminationReason) -> Error {
    use levenberg_marquardt::TerminationReason as T;
    let why = match t {
        T::User(_) | T::Numerical(_) => {
            "the residuals or their derivatives became non-finite during the iterations \
             (a reading far outside what the model can fit, or poses that cannot determine it): \
             check the recording for outliers and the static poses found"
                .to_string()
        }
        T::NoParameters | T::NoResiduals | T::WrongDimensions(_) => {
            format!("internal error: the problem is malformed ({t:?})")
        }
        other => format!("it stopped without converging ({other:?})"),
    };
    Error::new(ErrorKind::NotConverged, format!("{what} failed: {why}"))
}

/// Fit a triad model to observations. See the module documentation for the
/// residuals, the solver and the convention that fixes unobservable rotations.
///
/// Errors ([`ErrorKind::Degenerate`]) when there are too few observations, when
/// no observation points along some half-axis (the message lists which), when a
/// temperature model has no temperature spread, or when the Jacobian is
/// rank-deficient (the message names the parameter the data cannot see).
pub fn fit_triad(obs: &[Observation], opt: &FitOptions) -> Result<TriadFit> {
    let vector = obs.iter().any(|o| o.ref_vector.is_some());
    if vector && obs.iter().any(|o| o.ref_vector.is_none()) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "either every observation has a reference vector or none",
        ));
    }
    if !vector && opt.reference_norm.is_none() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "a magnitude fit needs a reference magnitude",
        ));
    }
    if obs.is_empty() {
        return Err(Error::new(
            ErrorKind::Degenerate,
            "no observation to fit (no usable pose)",
        ));
    }
    // non-physical readings never reach the solver (the recording's bounds)
    let max = match opt.kind {
        TriadKind::Accel => super::recording::MAX_ACC_M_S2,
        TriadKind::Gyro => super::recording::MAX_GYR_RAD_S,
        TriadKind::Mag => super::recording::MAX_MAG_UT,
    };
    let bad = |v: &Vec3| !v.iter().all(|x| x.abs() <= max);
    if let Some(i) = obs
        .iter()
        .position(|o| bad(&o.raw) || o.ref_vector.as_ref().is_some_and(bad))
    {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!(
                "observation {i} holds a non-finite or non-physical reading {:?} (bound ±{max} {} per axis)",
                obs[i].raw.as_slice(),
                opt.kind.unit()
            ),
        ));
    }
    let use_inc = !vector
        && opt.use_ref_inclination
        && opt.kind == TriadKind::Accel
        && obs
            .iter()
            .filter(|o| {
                o.ref_inclination
                    .is_some_and(|t| t > INC_EDGE && t < std::f64::consts::PI - INC_EDGE)
            })
            .count()
            >= 2;
    let gauge = if vector {
        Gauge::Full
    } else if opt.kind == TriadKind::Mag {
        Gauge::Symmetric
    } else if use_inc {
        Gauge::ZFromReference
    } else {
        Gauge::LowerTriangular
    };
    let (params, fixed) = parameter_set(opt.model, gauge);

    // temperatures
    let temps: Vec<f64> = obs.iter().filter_map(|o| o.temp_c).collect();
    if opt.model == ModelKind::Mwd30 && temps.len() != obs.len() {
        return Err(Error::new(
            ErrorKind::MissingColumn,
            "the mwd30 model needs a temperature for every pose",
        )
        .at_column("temp_c"));
    }
    let (tmin, tmax) = temps
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |a, &t| {
            (a.0.min(t), a.1.max(t))
        });
    if opt.model == ModelKind::Mwd30 && tmax - tmin < 10.0 {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!(
                "the mwd30 model needs poses over a temperature range (at least 10 °C); found {tmin:.1}–{tmax:.1} °C: use mwd12 or heat the sensor between poses"
            ),
        ));
    }

    // coverage and count
    if !vector {
        // a magnetometer's hard iron can exceed the field: judge directions about the centre
        let miss = if opt.kind == TriadKind::Mag {
            let c = obs.iter().fold(Vec3::zeros(), |s, o| s + o.raw) / obs.len() as f64;
            missing_half_axes(
                &obs.iter()
                    .map(|o| Observation {
                        raw: o.raw - c,
                        ..*o
                    })
                    .collect::<Vec<_>>(),
            )
        } else {
            missing_half_axes(obs)
        };
        if !miss.is_empty() {
            return Err(Error::new(
                ErrorKind::Degenerate,
                format!(
                    "{} poses, but the pose set is degenerate: no pose with the {} axis pointing along the reference (within 60°); add poses with {}",
                    obs.len(),
                    miss.join(", "),
                    miss.iter()
                        .map(|m| format!("{m} up"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
    }
    let mut prob = Problem {
        state: initial_state(obs, opt, vector),
        params: params.clone(),
        obs,
        reference_norm: opt.reference_norm,
        sigma_norm: 1.0,
        sigma_inc: 1.0,
        use_inc,
    };
    if let Some(g) = opt.reference_norm {
        prob.sigma_inc = opt.inclination_weight.max(1e-12).recip() / g;
    }
    let m = prob.n_residuals();
    if m <= params.len() {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!(
                "{} observations give {} equations, but the {} model with this convention has {} parameters: add poses",
                obs.len(),
                m,
                opt.model.name(),
                params.len()
            ),
        ));
    }
    // observability at the start
    let j0 = prob.jacobian().ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidInput,
            "non-finite Jacobian at the initial guess",
        )
    })?;
    let (_, rel0, weak0) = covariance(&j0);
    if rel0 < 1e-9 {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!(
                "the poses cannot determine {} (rank-deficient fit): add poses in other orientations{}",
                params[weak0].name(),
                if opt.model == ModelKind::Mwd30 {
                    " and temperatures"
                } else {
                    ""
                }
            ),
        ));
    }

    let (prob, report) = LevenbergMarquardt::new()
        .with_ftol(1e-14)
        .with_xtol(1e-12)
        .with_gtol(1e-14)
        .with_patience(200)
        .minimize(prob);
    if !solver_succeeded(&report.termination) {
        return Err(solver_error("the calibration fit", &report.termination));
    }
    let r = prob.residuals().ok_or_else(|| {
        Error::new(
            ErrorKind::NotConverged,
            "non-finite residuals at the solution",
        )
    })?;
    let j = prob.jacobian().ok_or_else(|| {
        Error::new(
            ErrorKind::NotConverged,
            "non-finite Jacobian at the solution",
        )
    })?;
    let (cov, rel, weak) = covariance(&j);
    if rel < 1e-10 {
        return Err(Error::new(
            ErrorKind::Degenerate,
            format!(
                "the poses cannot determine {}: add poses in other orientations",
                params[weak].name()
            ),
        ));
    }
    let dof = (m - params.len()) as f64;
    let s2 = r.norm_squared() / dof;
    let unit = opt.kind.unit();
    let est: Vec<ParamEstimate> = params
        .iter()
        .enumerate()
        .map(|(k, p)| ParamEstimate {
            name: p.name(),
            value: prob.state.get(*p),
            sigma: (s2 * cov[(k, k)]).sqrt() / p.solver_scale(),
            unit: p.unit(unit),
        })
        .collect();

    // residual table before/after
    let mut res = Vec::with_capacity(obs.len());
    for (i, o) in obs.iter().enumerate() {
        // "before" is the raw reading taken as calibrated
        let yb = o.raw;
        let ya = prob.state.eval(&[], o, None);
        let inc = |y: &Vec3| y.x.hypot(y.y).atan2(y.z);
        res.push(ObsResidual {
            index: i,
            temp_c: o.temp_c,
            norm_error_before: opt
                .reference_norm
                .filter(|_| !vector)
                .map(|g| yb.norm() - g),
            norm_error_after: opt
                .reference_norm
                .filter(|_| !vector)
                .map(|g| ya.norm() - g),
            inclination_error_before_deg: o.ref_inclination.map(|t| (inc(&yb) - t).to_degrees()),
            inclination_error_after_deg: o.ref_inclination.map(|t| (inc(&ya) - t).to_degrees()),
            vector_error_before: o.ref_vector.map(|v| (yb - v).norm()),
            vector_error_after: o.ref_vector.map(|v| (ya - v).norm()),
        });
    }
    let rms = |f: &dyn Fn(&ObsResidual) -> Option<f64>| {
        let v: Vec<f64> = res.iter().filter_map(f).collect();
        (!v.is_empty()).then(|| (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt())
    };
    let valid = super::valid_range(&temps);
    Ok(TriadFit {
        kind: opt.kind,
        model: opt.model,
        gauge,
        convention: gauge.statement().to_string(),
        calibration: TriadCalibration {
            model: prob.state.to_model(),
            valid_temp_c: valid,
        },
        params: est,
        fixed: fixed.iter().map(|p| p.name()).collect(),
        rms_norm_before: rms(&|r| r.norm_error_before),
        rms_norm_after: rms(&|r| r.norm_error_after),
        rms_inclination_before_deg: rms(&|r| r.inclination_error_before_deg),
        rms_inclination_after_deg: rms(&|r| r.inclination_error_after_deg),
        rms_vector_before: rms(&|r| r.vector_error_before),
        rms_vector_after: rms(&|r| r.vector_error_after),
        residuals: res,
        residual_sigma: s2.sqrt(),
        evaluations: report.number_of_evaluations,
        reference_norm: opt.reference_norm.filter(|_| !vector),
        observations: obs.len(),
    })
}

fn initial_state(obs: &[Observation], opt: &FitOptions, vector: bool) -> State {
    // scale guess: mean raw magnitude against the reference (1 for vector fits)
    let (b0, s0) = if opt.kind == TriadKind::Mag && !vector {
        let c = obs.iter().fold(Vec3::zeros(), |s, o| s + o.raw) / obs.len() as f64;
        let r = obs.iter().map(|o| (o.raw - c).norm()).sum::<f64>() / obs.len() as f64;
        (c, opt.reference_norm.unwrap_or(r) / r.max(1e-12))
    } else if vector {
        (Vec3::zeros(), 1.0)
    } else {
        let r = obs.iter().map(|o| o.raw.norm()).sum::<f64>() / obs.len() as f64;
        (
            Vec3::zeros(),
            opt.reference_norm.unwrap_or(r) / r.max(1e-12),
        )
    };
    let s0 = if s0.is_finite() && s0 > 0.0 { s0 } else { 1.0 };
    match opt.model {
        ModelKind::Matrix => State::Matrix {
            m: Matrix3::identity() * s0,
            b: b0,
        },
        ModelKind::Mwd12 | ModelKind::Mwd30 => {
            let mut md = MwdModel::identity(opt.tc_c);
            for i in 0..3 {
                md.scale[i][0] = 1.0 / s0;
                md.bias[i][0] = b0[i] * s0;
            }
            State::Mwd(md)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use levenberg_marquardt::differentiate_numerically;

    fn obs_set() -> Vec<Observation> {
        let mut v = Vec::new();
        for k in 0..30 {
            let a = k as f64 * 0.7;
            let b = k as f64 * 1.3;
            let u = Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * 9.7
                + Vec3::new(0.05, -0.02, 0.1);
            v.push(Observation {
                raw: u,
                temp_c: Some(25.0 + 2.0 * k as f64),
                ref_inclination: Some(b.cos().acos()),
                ref_vector: None,
            });
        }
        v
    }

    #[test]
    fn non_physical_observations_never_reach_the_solver() {
        let mut obs = obs_set();
        obs[7].raw.y = 1e308;
        let opt = FitOptions {
            reference_norm: Some(9.7),
            ..FitOptions::accel(ModelKind::Mwd12)
        };
        let e = fit_triad(&obs, &opt).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput, "{e}");
        assert!(e.message.contains("observation 7"), "{e}");
        obs[7].raw.y = f64::NAN;
        assert!(
            fit_triad(&obs, &opt)
                .unwrap_err()
                .message
                .contains("observation 7")
        );
    }

    #[test]
    fn solver_failures_read_as_sentences() {
        use levenberg_marquardt::TerminationReason as T;
        let e = solver_error("the calibration fit", &T::User("residuals"));
        assert_eq!(e.kind, ErrorKind::NotConverged);
        assert!(!e.message.contains("User"), "{e}");
        assert!(e.message.contains("non-finite"), "{e}");
        assert!(solver_succeeded(&T::LostPatience));
        assert!(!solver_succeeded(&T::Numerical("jacobian")));
    }

    fn check_jac(model: ModelKind, gauge: Gauge, vector: bool) {
        let mut obs = obs_set();
        if vector {
            for o in &mut obs {
                o.ref_vector = Some(o.raw * 0.99);
            }
        }
        let (params, _) = parameter_set(model, gauge);
        let mut state = initial_state(&obs, &FitOptions::accel(model), vector);
        // move away from the identity so every term is exercised
        for (k, p) in params.iter().enumerate() {
            let v = state.get(*p)
                + 1e-3
                    * ((k as f64 + 1.0) * 1.7).sin()
                    * if matches!(p, P::Sf(_, k) | P::B(_, k) if *k > 1) {
                        1e-3
                    } else {
                        1.0
                    };
            state.set(*p, v);
        }
        let mut prob = Problem {
            state,
            params,
            obs: &obs,
            reference_norm: Some(9.80665),
            sigma_norm: 1.0,
            sigma_inc: 0.1,
            use_inc: true,
        };
        let hand = prob.jacobian().unwrap();
        // (a scale factor exactly 1 would hit 0 at the crate's first unit step)
        let num = differentiate_numerically(&mut prob).unwrap();
        for c in 0..hand.ncols() {
            let scale = num.column(c).norm().max(1e-12);
            let err = (hand.column(c) - num.column(c)).norm() / scale;
            assert!(
                err < 1e-5,
                "{model:?} {gauge:?} column {c} ({}): rel err {err}",
                prob.params[c].name()
            );
        }
    }

    #[test]
    fn hand_jacobians_match_numerical_differentiation() {
        for m in [ModelKind::Matrix, ModelKind::Mwd12, ModelKind::Mwd30] {
            check_jac(m, Gauge::LowerTriangular, false);
            check_jac(m, Gauge::ZFromReference, false);
            check_jac(m, Gauge::Full, true);
        }
        check_jac(ModelKind::Matrix, Gauge::Symmetric, false);
    }

    #[test]
    fn parameter_counts_follow_the_convention() {
        let n = |m, g| parameter_set(m, g).0.len();
        assert_eq!(n(ModelKind::Mwd12, Gauge::LowerTriangular), 9);
        assert_eq!(n(ModelKind::Mwd12, Gauge::ZFromReference), 11);
        assert_eq!(n(ModelKind::Mwd12, Gauge::Full), 12);
        assert_eq!(n(ModelKind::Mwd30, Gauge::LowerTriangular), 27);
        assert_eq!(n(ModelKind::Mwd30, Gauge::ZFromReference), 29);
        assert_eq!(n(ModelKind::Mwd30, Gauge::Full), 30);
        assert_eq!(n(ModelKind::Matrix, Gauge::LowerTriangular), 9);
        assert_eq!(n(ModelKind::Matrix, Gauge::Symmetric), 9);
        assert_eq!(n(ModelKind::Matrix, Gauge::Full), 12);
    }

    #[test]
    fn degenerate_pose_sets_say_what_is_missing() {
        // all poses near +z
        let obs: Vec<_> = (0..20)
            .map(|k| {
                Observation::new(
                    Vec3::new(0.1 * (k as f64).sin(), 0.1 * (k as f64).cos(), 9.8),
                    None,
                )
            })
            .collect();
        let e = fit_triad(&obs, &FitOptions::accel(ModelKind::Mwd12)).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Degenerate);
        for h in ["+x", "-x", "+y", "-y", "-z"] {
            assert!(e.message.contains(h), "{}", e.message);
        }
        assert!(!e.message.contains("+z"), "{}", e.message);
        // six poses but twelve parameters
        let six: Vec<_> = [
            Vec3::x(),
            -Vec3::x(),
            Vec3::y(),
            -Vec3::y(),
            Vec3::z(),
            -Vec3::z(),
        ]
        .iter()
        .map(|u| Observation::new(u * 9.8, Some(30.0)))
        .collect();
        let e = fit_triad(&six[..6], &FitOptions::accel(ModelKind::Matrix)).unwrap_err();
        assert!(e.message.contains("add poses"), "{}", e.message);
        // no observation
        assert_eq!(
            fit_triad(&[], &FitOptions::accel(ModelKind::Mwd12))
                .unwrap_err()
                .kind,
            ErrorKind::Degenerate
        );
        // mwd30 without temperature spread
        let e = fit_triad(
            &obs_set()
                .iter()
                .map(|o| Observation {
                    temp_c: Some(30.0),
                    ..*o
                })
                .collect::<Vec<_>>(),
            &FitOptions::accel(ModelKind::Mwd30),
        )
        .unwrap_err();
        assert!(e.message.contains("temperature"), "{}", e.message);
    }
}
