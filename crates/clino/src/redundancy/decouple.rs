//! Decoupling: six-dimensional acceleration from the nine chain forces
//! (Li Chenggang et al., "Fault Diagnosis in a Gyroscope-Based Six-Axis
//! Accelerometer", eqs 3–7).
//!
//! Eqs 3 and 4 need the rotation `A` of the cube, which needs the angular
//! velocity, which is the integral of the angular acceleration the forces
//! give: the equations are coupled. The source breaks the loop with the
//! *auxiliary angular velocity* `ω*`, defined by `ω^O = A·ω*` (eq 5): it is the
//! body-frame angular velocity. Because the cube's inertia is isotropic and
//! `d(Aω*)/dt = A·(ω*×ω*) + A·dω*/dt = A·dω*/dt`, the auxiliary angular
//! acceleration `ε* = dω*/dt` is exactly the body-frame value of eq 4
//! (eq 7: `ε = A·ε*`), so `ω*` follows from the forces alone by integration.
//!
//! The source integrates with the improved Euler (trapezoid) rule, eq 6. Its
//! printed form `h·(Σ_{i=1}^{N−1} ε*_i + (ε*_1 + ε*_N)/2)` counts `ε*_1` one and
//! a half times (PDF garbling or a typo); the trapezoid rule it names is
//! `ω*_N = ω*_1 + h·((ε*_1 + ε*_N)/2 + Σ_{i=2}^{N−1} ε*_i)`, which is what
//! [`auxiliary_rate`] implements (per step, so uneven steps work too).
//!
//! With a gyroscope on board (the source's section 3) `ω*` is measured
//! directly: [`RateSource::Gyro`].

use super::model::{Forces, SixAxisAccelerometer};
use crate::{Error, ErrorKind, Result};
use clino_core::{Attitude, Vec3};

/// Where the auxiliary angular velocity `ω*` comes from.
#[derive(Clone, Copy, Debug)]
pub enum RateSource<'a> {
    /// Integrate `ε*` of the forces (eq 4) with the trapezoid rule (eq 6).
    Forces,
    /// Take `ω*` from a body-frame gyroscope, rad/s, one sample per force sample.
    Gyro(&'a [Vec3]),
}

/// The decoupled six-dimensional acceleration at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Decoupled {
    /// Time, s.
    pub t_s: f64,
    /// Rotation `A` of the cube, body → ENU.
    pub attitude: Attitude,
    /// Auxiliary (body-frame) angular velocity `ω*`, rad/s (eqs 5, 6).
    pub rate_rad_s: Vec3,
    /// Auxiliary (body-frame) angular acceleration `ε*`, rad/s² (eq 4, eq 7).
    pub ang_acc_body_rad_s2: Vec3,
    /// Angular acceleration in the navigation frame `ε^O = A·ε*`, rad/s² (eq 4).
    pub ang_acc_nav_rad_s2: Vec3,
    /// Specific force in the body frame `F/m`, m/s².
    pub specific_force_body_m_s2: Vec3,
    /// Linear acceleration of the cube centre in ENU, `A·F/m − g·e_z`, m/s² (eq 3).
    pub lin_acc_nav_m_s2: Vec3,
}

fn check_times(t_s: &[f64]) -> Result<()> {
    for (i, w) in t_s.windows(2).enumerate() {
        if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) || !w[1].is_finite() {
            return Err(Error::new(
                ErrorKind::TimeNotIncreasing,
                format!(
                    "time must increase: sample {} at {} s follows {} s",
                    i + 2,
                    w[1],
                    w[0]
                ),
            ));
        }
    }
    Ok(())
}

/// Trapezoid (improved Euler) integral of `ε*` starting from `ω*(t_0) = w0`
/// (eq 6, corrected as in the module doc), rad/s.
pub fn auxiliary_rate(t_s: &[f64], eps: &[Vec3], w0: Vec3) -> Result<Vec<Vec3>> {
    if t_s.len() != eps.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "times and angular accelerations differ in length",
        ));
    }
    check_times(t_s)?;
    let mut out = Vec::with_capacity(eps.len());
    let mut w = w0;
    for i in 0..eps.len() {
        if i > 0 {
            w += (t_s[i] - t_s[i - 1]) * 0.5 * (eps[i - 1] + eps[i]);
        }
        out.push(w);
    }
    Ok(out)
}

/// Decouple a record of chain forces into six-dimensional acceleration
/// (eqs 3–7): `ω*` from `source`, the rotation `A` by integrating
/// `dA/dt = A·[ω*×]` (per step with the mean of the end rates), then
/// `a = A·F/m − g·e_z` and `ε = A·ε*`.
///
/// `initial` is `A` at the first sample, `w0` the body rate there (ignored
/// for [`RateSource::Gyro`]), `g` the local gravity, m/s².
pub fn decouple(
    acc: &SixAxisAccelerometer,
    t_s: &[f64],
    forces: &[Forces],
    source: RateSource<'_>,
    initial: Attitude,
    w0: Vec3,
    g: f64,
) -> Result<Vec<Decoupled>> {
    if t_s.len() != forces.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "times and forces differ in length",
        ));
    }
    let eps: Vec<Vec3> = forces.iter().map(|f| acc.angular_acceleration(f)).collect();
    let rates = match source {
        RateSource::Forces => auxiliary_rate(t_s, &eps, w0)?,
        RateSource::Gyro(gyr) => {
            if gyr.len() != t_s.len() {
                return Err(Error::new(
                    ErrorKind::InvalidInput,
                    "gyro and forces differ in length",
                ));
            }
            check_times(t_s)?;
            gyr.to_vec()
        }
    };
    let mut q = initial;
    let mut out = Vec::with_capacity(forces.len());
    for i in 0..forces.len() {
        if i > 0 {
            let h = t_s[i] - t_s[i - 1];
            q *= Attitude::from_scaled_axis(0.5 * h * (rates[i - 1] + rates[i]));
        }
        let sf = acc.specific_force(&forces[i]);
        out.push(Decoupled {
            t_s: t_s[i],
            attitude: q,
            rate_rad_s: rates[i],
            ang_acc_body_rad_s2: eps[i],
            ang_acc_nav_rad_s2: q * eps[i],
            specific_force_body_m_s2: sf,
            lin_acc_nav_m_s2: q * sf - Vec3::new(0.0, 0.0, g),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::simulate::ShakeMotion;
    use super::*;
    use crate::sim::Motion;
    use approx::assert_relative_eq;
    use clino_core::G0;

    #[test]
    fn trapezoid_is_exact_for_linear_eps_and_second_order_otherwise() {
        let t: Vec<f64> = (0..101).map(|i| i as f64 * 0.01).collect();
        let lin: Vec<Vec3> = t.iter().map(|&t| Vec3::new(2.0 * t, -1.0, 0.5)).collect();
        let w = auxiliary_rate(&t, &lin, Vec3::new(0.1, 0.0, 0.0)).unwrap();
        assert_relative_eq!(w[100], Vec3::new(0.1 + 1.0, -1.0, 0.5), epsilon = 1e-12);
        // cos integrates to sin with error h²/12·|Δ(sin')|
        let cosv: Vec<Vec3> = t
            .iter()
            .map(|&t| Vec3::new((5.0 * t).cos(), 0.0, 0.0))
            .collect();
        let w = auxiliary_rate(&t, &cosv, Vec3::zeros()).unwrap();
        let exact = (5.0f64).sin() / 5.0;
        let err = (w[100].x - exact).abs();
        assert!(err < 1e-4 && err > 1e-7, "trapezoid error {err}");
    }

    /// Largest attitude and linear-acceleration errors decoupling 1 s of
    /// the default motion sampled every `h` seconds.
    fn decouple_errors(h: f64, gyro: bool) -> (f64, f64) {
        let acc = SixAxisAccelerometer::reference();
        let motion = ShakeMotion::default();
        let n = (1.0 / h).round() as usize + 1;
        let t: Vec<f64> = (0..n).map(|i| i as f64 * h).collect();
        let truth: Vec<_> = t.iter().map(|&t| motion.truth(t)).collect();
        let forces: Vec<Forces> = truth
            .iter()
            .map(|s| acc.forces(&s.specific_force(G0), &s.ang_acc_rad_s2))
            .collect();
        let gyr: Vec<Vec3> = truth.iter().map(|s| s.gyr_rad_s).collect();
        let src = if gyro {
            RateSource::Gyro(&gyr)
        } else {
            RateSource::Forces
        };
        let d = decouple(
            &acc,
            &t,
            &forces,
            src,
            truth[0].attitude,
            truth[0].gyr_rad_s,
            G0,
        )
        .unwrap();
        let mut e = (0.0f64, 0.0f64);
        for (s, o) in truth.iter().zip(&d) {
            e.0 = e.0.max(o.attitude.angle_to(&s.attitude));
            e.1 = e.1.max((o.lin_acc_nav_m_s2 - s.acc_m_s2).norm());
            assert_relative_eq!(
                o.ang_acc_nav_rad_s2,
                s.attitude * s.ang_acc_rad_s2,
                epsilon = 1e-2
            );
            assert_relative_eq!(
                o.specific_force_body_m_s2,
                s.specific_force(G0),
                epsilon = 1e-9
            );
        }
        e
    }

    #[test]
    fn forward_then_decouple_returns_the_motion_at_second_order() {
        let (att1, acc1) = decouple_errors(1e-3, false);
        let (att2, _) = decouple_errors(5e-4, false);
        // trapezoid (eq 6): error ∝ h²
        assert!(att1 < 2e-4 && acc1 < 3e-3, "{att1} rad, {acc1} m/s²");
        let order = (att1 / att2).log2();
        assert!((1.7..2.3).contains(&order), "convergence order {order}");
        // a perfect gyro removes the rate-integration error
        let (att_g, acc_g) = decouple_errors(1e-3, true);
        assert!(att_g < 1e-5 && acc_g < 1e-4, "{att_g} rad, {acc_g} m/s²");
    }

    #[test]
    fn time_going_backwards_is_an_error() {
        let e = auxiliary_rate(&[0.0, 0.1, 0.05], &[Vec3::zeros(); 3], Vec3::zeros()).unwrap_err();
        assert_eq!(e.kind, ErrorKind::TimeNotIncreasing);
    }
}
