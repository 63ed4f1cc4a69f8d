//! Offline (non-causal) tilt estimation for recordings: the dynamic filter run
//! forwards and backwards in time, combined.
//!
//! A causal filter lags: the accelerometer's evidence about the tilt at time t
//! arrives over the following seconds. With the whole recording at hand the
//! same evidence can be used from both sides. This is the two-filter form of
//! fixed-interval smoothing (Fraser & Potter, 1969): a forward and a backward
//! run of the same filter, combined. Here:
//!
//! 1. a forward pass of [`Dynamic`] over the recording learns the gyro bias at
//!    the end;
//! 2. a backward pass runs on the time-reversed recording (rates negated: the
//!    reversed body turns the other way; sample k's interval is the one ending
//!    at sample k + 1), starting from that bias, and learns the bias at the start;
//! 3. a second forward pass starts from the bias at the start;
//! 4. at every sample the tilt is the mean of the two up vectors (passes 2 and
//!    3, equal weights — their errors are alike and nearly independent); the
//!    heading is the forward pass's.
//!
//! Lever-arm compensation, when asked for, runs inside each pass (the
//! tangential and centripetal terms are even under time reversal).
//!
//! Memory: the recording and one attitude per sample are held (≈ 100 bytes a
//! sample), unlike the streaming real-time path.

use clino_core::compensate::Compensated;
use clino_core::filter::{Dynamic, DynamicParams};
use clino_core::tilt::up_in_body;
use clino_core::{Attitude, AttitudeFilter, Vec3};
use nalgebra::UnitQuaternion;

/// Options of the offline smoother.
#[derive(Clone, Debug, Default)]
pub struct SmoothOptions {
    /// Parameters of the dynamic filter used in every pass.
    pub params: DynamicParams,
    /// Lever arm of the sensor from the rotation axis, m (body frame).
    pub lever_arm_m: Option<Vec3>,
}

fn make(opts: &SmoothOptions, bias: Option<Vec3>) -> Box<dyn AttitudeFilter> {
    let mut f = Dynamic::new(opts.params);
    if let Some(b) = bias {
        f.set_gyro_bias(b);
    }
    match opts.lever_arm_m {
        Some(p) => Box::new(Compensated::new(f, p)),
        None => Box::new(f),
    }
}

/// Run one pass; returns the attitude after each sample.
/// `dt[k]` is the interval that ends at sample k.
fn pass(gyr: &[Vec3], acc: &[Vec3], dt: &[f64], reverse: bool, f: &mut dyn AttitudeFilter) -> Vec<Attitude> {
    let n = gyr.len();
    let mut out = vec![Attitude::identity(); n];
    for k in 0..n {
        if reverse {
            let i = n - 1 - k;
            // going from sample i+1 back to sample i undoes the rotation of interval i+1
            let (g, h) = if i + 1 < n { (gyr[i + 1], dt[i + 1]) } else { (gyr[i], dt[i]) };
            f.update(-g, acc[i], h);
            out[i] = f.attitude();
        } else {
            f.update(gyr[k], acc[k], dt[k]);
            out[k] = f.attitude();
        }
    }
    out
}

/// Offline tilt of a whole recording (see the [module docs](self)).
///
/// `gyr` (rad/s), `acc` (m/s²) and `dt` (s, the interval ending at each sample;
/// the first one is the nominal period) have one entry per sample. Samples
/// the filter rejects (non-finite values, dt ≤ 0) keep the state, as in the
/// real-time path. Returns one attitude per sample.
pub fn smooth(gyr: &[Vec3], acc: &[Vec3], dt: &[f64], opts: &SmoothOptions) -> Vec<Attitude> {
    let n = gyr.len().min(acc.len()).min(dt.len());
    let (gyr, acc, dt) = (&gyr[..n], &acc[..n], &dt[..n]);
    if n == 0 {
        return Vec::new();
    }
    let mut f1 = make(opts, None);
    pass(gyr, acc, dt, false, f1.as_mut());
    // the reversed body sees −ω, so its bias is −b
    let mut f2 = make(opts, Some(-f1.gyro_bias()));
    let backward = pass(gyr, acc, dt, true, f2.as_mut());
    let mut f3 = make(opts, Some(-f2.gyro_bias()));
    let forward = pass(gyr, acc, dt, false, f3.as_mut());
    forward
        .iter()
        .zip(&backward)
        .map(|(qf, qb)| {
            let (uf, ub) = (up_in_body(qf), up_in_body(qb));
            let um = uf + ub;
            if um.norm_squared() < 1e-12 {
                return *qf;
            }
            // turn the forward attitude (in the body) so that its up vector becomes the mean
            let corr = UnitQuaternion::rotation_between(&um, &uf).unwrap_or_else(UnitQuaternion::identity);
            qf * corr
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::{Motion, slewing::SlewingPlatform};
    use clino_core::tilt::up_in_body;

    fn tilt_err(a: &Attitude, b: &Attitude) -> f64 {
        let e = a * b.inverse();
        2.0 * (e.w * e.w + e.k * e.k).sqrt().min(1.0).acos()
    }

    /// Simulated slewing machine with a constant gyro bias and no lever-arm knowledge
    /// in the filter: a hard case for a causal filter (centripetal acceleration).
    fn recording() -> (Vec<Vec3>, Vec<Vec3>, Vec<f64>, Vec<Attitude>) {
        let m = SlewingPlatform::default();
        let rate = 100.0;
        let n = (90.0 * rate) as usize;
        let bias = Vec3::new(0.3, -0.2, 0.1).map(f64::to_radians);
        let (mut g, mut a, mut d, mut q) = (vec![], vec![], vec![], vec![]);
        for k in 0..n {
            let tr = m.truth(k as f64 / rate);
            g.push(tr.gyr_rad_s + bias);
            a.push(tr.specific_force(clino_core::G0));
            d.push(1.0 / rate);
            q.push(tr.attitude);
        }
        (g, a, d, q)
    }

    #[test]
    fn smoother_beats_causal_filter_and_reversal_is_consistent() {
        let (g, a, d, q) = recording();
        let opts = SmoothOptions::default();
        let off = smooth(&g, &a, &d, &opts);
        let mut f = Dynamic::default();
        let on = pass(&g, &a, &d, false, &mut f);
        let rms = |e: &[Attitude]| {
            let s: f64 = e.iter().zip(&q).skip(500).map(|(x, y)| tilt_err(x, y).powi(2)).sum();
            (s / (e.len() - 500) as f64).sqrt().to_degrees()
        };
        let (e_on, e_off) = (rms(&on), rms(&off));
        assert!(e_off < e_on, "offline {e_off}° vs online {e_on}°");
        // with the lever arm known, both become small
        let opts_la = SmoothOptions { lever_arm_m: Some(SlewingPlatform::default().lever_arm_m), ..Default::default() };
        let e_off_la = rms(&smooth(&g, &a, &d, &opts_la));
        assert!(e_off_la < 0.1 && e_off_la < e_off / 5.0, "compensated offline {e_off_la}°");
        // up vectors of the output are unit and finite
        assert!(off.iter().all(|x| (up_in_body(x).norm() - 1.0).abs() < 1e-9));
    }

    #[test]
    fn empty_and_nan_input() {
        assert!(smooth(&[], &[], &[], &SmoothOptions::default()).is_empty());
        let g = vec![Vec3::zeros(); 10];
        let mut a = vec![Vec3::new(0.0, 0.0, 9.81); 10];
        a[5] = Vec3::new(f64::NAN, 0.0, 9.81);
        let out = smooth(&g, &a, &[0.01; 10], &SmoothOptions::default());
        assert_eq!(out.len(), 10);
        assert!(out.iter().all(|q| q.w.is_finite()));
    }
}
