//! Attitude filters behind one trait.
//!
//! | filter | idea | source |
//! |---|---|---|
//! | [`Poisson`] | gyro only: strapdown integration of dC/dt = C·[ω×] | Sapegin & Strokach, "Micromechanical inclinometer" (MPU6050 + Arduino), eqs 3–4 |
//! | [`Complementary`] | C_out = (1 − k)·C_gyro + k·C_acc on direction-cosine matrices | same paper, eq 5 |
//! | [`Mahony`] | proportional-integral correction of the rate, gyro-bias integral | Mahony, Hamel, Pflimlin, IEEE TAC 53(5), 2008 |
//! | [`Madgwick`] | gradient-descent step towards the accelerometer direction | Madgwick, Harrison, Vaidyanathan, ICORR 2011 |
//! | [`Dynamic`] | clino's own: bounded-velocity tilt loop with bias, rest and rate adaptation | this crate ([`dynamic`]) |
//!
//! Every filter follows the same contract ([`AttitudeFilter`]):
//!
//! * it starts uninitialised and takes its first attitude from the first
//!   valid accelerometer sample (tilt from gravity, heading zero);
//! * a sample with a non-finite gyro or accelerometer value, or a
//!   non-finite or non-positive `dt`, is rejected ([`Step::Rejected`]) and
//!   leaves the state exactly as it was;
//! * a sample whose accelerometer norm is zero is used for the gyro only
//!   ([`Step::GyroOnly`]);
//! * nothing allocates, nothing panics.

mod complementary;
pub mod dynamic;
mod madgwick;
mod mahony;
mod poisson;
pub mod spec;

pub use complementary::Complementary;
pub use dynamic::{Dynamic, DynamicParams, correct_specific_force};
pub use madgwick::Madgwick;
pub use mahony::Mahony;
pub use poisson::{Integrator, Poisson};
pub use spec::{AnyFilter, Blend, FilterKind, FilterSpec, ParamError, ParamInfo, ParamType, Value};

use crate::math::{cos, sin, sqrt};
use crate::{Attitude, Vec3};
use nalgebra::{Matrix3, Quaternion};

/// What a filter did with one sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// Gyro propagation and accelerometer correction.
    Fused,
    /// Gyro propagation only (accelerometer unusable, e.g. zero norm, or de-weighted to nothing).
    GyroOnly,
    /// The sample initialised the attitude from the accelerometer.
    Initialised,
    /// The sample was rejected (non-finite value or bad dt); the state is unchanged.
    Rejected,
    /// The filter has not been initialised and this sample could not do it (zero accelerometer).
    Waiting,
}

impl Step {
    /// True when the sample changed nothing.
    pub fn is_rejected(self) -> bool {
        matches!(self, Step::Rejected | Step::Waiting)
    }
}

/// One attitude filter: feed it samples, read the attitude.
pub trait AttitudeFilter {
    /// Short lower-case name, as used on the command line (`mahony`, …).
    fn name(&self) -> &'static str;

    /// Process one sample: `gyr` body rate (rad/s), `acc` specific force (m/s²),
    /// `dt` the time since the previous sample (s).
    fn update(&mut self, gyr: Vec3, acc: Vec3, dt: f64) -> Step;

    /// Current attitude (body to East-North-Up). Identity before initialisation.
    fn attitude(&self) -> Attitude;

    /// True once the attitude has been initialised.
    fn is_initialised(&self) -> bool;

    /// Forget everything: back to the uninitialised state, keeping parameters.
    fn reset(&mut self);

    /// Current gyro-bias estimate, rad/s (zero for filters that do not estimate one).
    fn gyro_bias(&self) -> Vec3 {
        Vec3::zeros()
    }
}

/// A mutable reference to a filter is a filter (so wrappers such as
/// [`crate::compensate::Compensated`] can hold a `&mut dyn AttitudeFilter`).
impl<F: AttitudeFilter + ?Sized> AttitudeFilter for &mut F {
    fn name(&self) -> &'static str {
        (**self).name()
    }
    fn update(&mut self, gyr: Vec3, acc: Vec3, dt: f64) -> Step {
        (**self).update(gyr, acc, dt)
    }
    fn attitude(&self) -> Attitude {
        (**self).attitude()
    }
    fn is_initialised(&self) -> bool {
        (**self).is_initialised()
    }
    fn reset(&mut self) {
        (**self).reset()
    }
    fn gyro_bias(&self) -> Vec3 {
        (**self).gyro_bias()
    }
}

/// True when every component is finite.
#[inline(always)]
pub(crate) fn finite3(v: &Vec3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// True when dt is usable.
#[inline(always)]
pub(crate) fn good_dt(dt: f64) -> bool {
    dt.is_finite() && dt > 0.0
}

/// The exact rotation-vector step: q ⊗ exp(φ/2) for the body rotation vector
/// φ = ω·dt (rate constant over the step). Uses the Taylor form of sin(x)/x
/// below 1e-4 rad so it stays exact near zero rate.
#[allow(dead_code)] // used by the dynamic filter
#[inline(always)]
pub(crate) fn rotate_body(q: &Attitude, phi: Vec3) -> Attitude {
    let a2 = phi.norm_squared();
    let a = sqrt(a2);
    let (c, s) = if a < 1e-4 {
        // cos(a/2) and sin(a/2)/a to O(a^4)
        (
            1.0 - a2 * 0.125 + a2 * a2 * (1.0 / 384.0),
            0.5 - a2 * (1.0 / 48.0),
        )
    } else {
        (cos(0.5 * a), sin(0.5 * a) / a)
    };
    let dq = Quaternion::new(c, s * phi.x, s * phi.y, s * phi.z);
    renormalise(q.quaternion() * dq)
}

/// Unit quaternion from a nearly unit one (one division, no checks beyond finiteness).
#[inline(always)]
pub(crate) fn renormalise(q: Quaternion<f64>) -> Attitude {
    let n = q.norm();
    Attitude::new_unchecked(q / n)
}

/// Skew-symmetric matrix [v×], so that [v×]·u = v × u.
#[inline(always)]
pub fn skew(v: &Vec3) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// What the common contract of [`AttitudeFilter`] says about one sample,
/// before a filter's own work: reject it, wait for a usable accelerometer,
/// initialise from it, or run.
pub(crate) enum Admit {
    /// Non-finite value or bad dt: [`Step::Rejected`], state untouched.
    Reject,
    /// Not initialised and the accelerometer cannot initialise: [`Step::Waiting`].
    Wait,
    /// Not initialised: start from this attitude (tilt from gravity, heading zero).
    Init(Attitude),
    /// Initialised and usable: the filter's update runs.
    Run,
}

/// The gate every filter's `update` starts with (one place for the contract
/// in the module docs).
#[inline(always)]
pub(crate) fn admit(gyr: &Vec3, acc: &Vec3, dt: f64, initialised: bool) -> Admit {
    if !(finite3(gyr) && finite3(acc) && good_dt(dt)) {
        Admit::Reject
    } else if initialised {
        Admit::Run
    } else {
        match crate::tilt::attitude_from_up(acc) {
            Some(q) => Admit::Init(q),
            None => Admit::Wait,
        }
    }
}
