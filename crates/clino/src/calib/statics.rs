//! Static-interval detection in a continuous recording.
//!
//! The user puts the sensor in N poses by hand (no fixture) and holds each
//! still for a few seconds. A sample is *still* when, over a centred window,
//! the standard deviation of the accelerometer (root of the summed per-axis
//! variances) and, when a gyro is present, of the gyro are below thresholds.
//! Runs of still samples lasting at least `min_duration_s` become poses; each
//! pose reports its time span, sample count and mean readings, so a user sees
//! exactly what a fit used.
//!
//! Thresholds default to a multiple of the quietest windows of the recording
//! itself (4 × the 10th percentile of the window standard deviations, and at
//! least 1e-4 m/s² or 1e-5 rad/s), so they adapt to the sensor's noise.

use super::recording::Recording;
use crate::{ErrorKind, Result};
use clino_core::Vec3;
use serde::Serialize;

/// Settings of the detector.
#[derive(Clone, Debug)]
pub struct StaticOptions {
    /// Window over which the standard deviation is taken, s.
    pub window_s: f64,
    /// Shortest pose kept, s.
    pub min_duration_s: f64,
    /// Accelerometer threshold, m/s² (None: automatic).
    pub acc_threshold: Option<f64>,
    /// Gyro threshold, rad/s (None: automatic).
    pub gyr_threshold: Option<f64>,
    /// Use the magnetometer instead of the accelerometer as the stillness signal
    /// (for magnetometer-only recordings).
    pub use_mag: bool,
}

impl Default for StaticOptions {
    fn default() -> Self {
        Self {
            window_s: 0.5,
            min_duration_s: 1.0,
            acc_threshold: None,
            gyr_threshold: None,
            use_mag: false,
        }
    }
}

/// One static pose found in a recording: what the fit uses.
#[derive(Clone, Debug, Serialize)]
pub struct Pose {
    /// 0-based pose number.
    pub index: usize,
    /// First and last row (0-based) of the pose.
    pub rows: [usize; 2],
    /// 1-based file lines of the first and last row.
    pub lines: [u64; 2],
    /// Start time, s.
    pub start_s: f64,
    /// Duration, s.
    pub duration_s: f64,
    /// Number of samples averaged.
    pub n: usize,
    /// Mean raw accelerometer reading, m/s² (when present).
    pub acc_mean: Option<[f64; 3]>,
    /// Standard deviation of the accelerometer reading, m/s² (root of the summed variances).
    pub acc_std: Option<f64>,
    /// Mean raw gyro reading, rad/s.
    pub gyr_mean: Option<[f64; 3]>,
    /// Mean raw magnetometer reading, µT.
    pub mag_mean: Option<[f64; 3]>,
    /// Mean temperature, °C.
    pub temp_c: Option<f64>,
    /// Mean reference inclination, deg (when the column is present and filled).
    pub ref_inclination_deg: Option<f64>,
}

impl Pose {
    /// Mean accelerometer reading as a vector (zeros when absent).
    pub fn acc(&self) -> Vec3 {
        self.acc_mean.map(Vec3::from).unwrap_or_default()
    }
    /// Mean magnetometer reading as a vector (zeros when absent).
    pub fn mag(&self) -> Vec3 {
        self.mag_mean.map(Vec3::from).unwrap_or_default()
    }
    /// Mean gyro reading as a vector (zeros when absent).
    pub fn gyr(&self) -> Vec3 {
        self.gyr_mean.map(Vec3::from).unwrap_or_default()
    }
}

/// What the detector found.
#[derive(Clone, Debug, Serialize)]
pub struct StaticReport {
    /// The poses, in time order.
    pub poses: Vec<Pose>,
    /// Stillness threshold used for the accelerometer (or magnetometer), in its unit.
    pub acc_threshold: f64,
    /// Threshold used for the gyro, rad/s (when present).
    pub gyr_threshold: Option<f64>,
    /// Total still time, s.
    pub total_static_s: f64,
}

impl StaticReport {
    /// A short human-readable table of the poses.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{} static poses, {:.1} s in total (threshold {:.3e})\n  #   start_s  dur_s     n   acc_mean (m/s²)                    temp_c  ref_inc_deg\n",
            self.poses.len(),
            self.total_static_s,
            self.acc_threshold
        );
        for p in &self.poses {
            let a = p
                .acc_mean
                .map(|a| format!("{:9.4} {:9.4} {:9.4}", a[0], a[1], a[2]))
                .unwrap_or_else(|| "-".into());
            s += &format!(
                "{:3} {:9.2} {:6.2} {:5}   {:32} {:7} {}\n",
                p.index,
                p.start_s,
                p.duration_s,
                p.n,
                a,
                p.temp_c
                    .map(|t| format!("{t:.2}"))
                    .unwrap_or_else(|| "-".into()),
                p.ref_inclination_deg
                    .map(|t| format!("{t:.3}"))
                    .unwrap_or_else(|| "-".into())
            );
        }
        s
    }
}

/// Windowed standard deviation (root of the summed variances of the three axes), centred.
fn window_std(v: &[Vec3], half: usize) -> Vec<f64> {
    let n = v.len();
    let mut s1 = vec![Vec3::zeros(); n + 1];
    let mut s2 = vec![Vec3::zeros(); n + 1];
    // subtract the first value to keep the sums well conditioned
    let o = v[0];
    for i in 0..n {
        let d = v[i] - o;
        s1[i + 1] = s1[i] + d;
        s2[i + 1] = s2[i] + d.component_mul(&d);
    }
    (0..n)
        .map(|i| {
            let a = i.saturating_sub(half);
            let b = (i + half + 1).min(n);
            let k = (b - a) as f64;
            let m = (s1[b] - s1[a]) / k;
            let var = (s2[b] - s2[a]) / k - m.component_mul(&m);
            var.iter().map(|x| x.max(0.0)).sum::<f64>().sqrt()
        })
        .collect()
}

fn percentile(v: &[f64], p: f64) -> f64 {
    let mut s: Vec<f64> = v.to_vec();
    s.sort_by(|a, b| a.total_cmp(b));
    s[((s.len() - 1) as f64 * p).round() as usize]
}

/// Find the static poses of a recording. Errors when the recording has no
/// stillness signal, is too short for one window, or holds no usable pose.
pub fn detect_static(rec: &Recording, opt: &StaticOptions) -> Result<StaticReport> {
    let main = if opt.use_mag {
        rec.mag.as_ref()
    } else {
        rec.acc.as_ref()
    };
    let main = main.ok_or_else(|| {
        let c = if opt.use_mag {
            "mag_x_uT"
        } else {
            "acc_x_m_s2"
        };
        rec.error(
            ErrorKind::MissingColumn,
            "static detection needs this triad",
        )
        .at_column(c)
    })?;
    let n = rec.len();
    let dur = rec.t_s[n - 1] - rec.t_s[0];
    if n < 3 || dur <= 0.0 {
        return Err(rec.error(
            ErrorKind::Degenerate,
            "the recording is too short for static detection",
        ));
    }
    let dt = dur / (n - 1) as f64;
    let half = ((opt.window_s / dt / 2.0).round() as usize).max(1);
    let sa = window_std(main, half);
    let floor_a = if opt.use_mag { 1e-3 } else { 1e-4 };
    let thr_a = opt
        .acc_threshold
        .unwrap_or_else(|| (4.0 * percentile(&sa, 0.1)).max(floor_a));
    let (sg, thr_g) = match rec.gyr.as_ref() {
        Some(g) => {
            let sg = window_std(g, half);
            let t = opt
                .gyr_threshold
                .unwrap_or_else(|| (4.0 * percentile(&sg, 0.1)).max(1e-5));
            (Some(sg), Some(t))
        }
        None => (None, None),
    };
    let still: Vec<bool> = (0..n)
        .map(|i| sa[i] <= thr_a && sg.as_ref().zip(thr_g).is_none_or(|(s, t)| s[i] <= t))
        .collect();
    let mut poses = Vec::new();
    let mut i = 0;
    while i < n {
        if !still[i] {
            i += 1;
            continue;
        }
        let a = i;
        while i < n && still[i] {
            i += 1;
        }
        // a centred window is quiet only a half window away from motion, so the
        // run is already clear of the motion's edges
        let (a2, b2) = (a, i - 1);
        if b2 <= a2 {
            continue;
        }
        let d = rec.t_s[b2] - rec.t_s[a2];
        if d < opt.min_duration_s {
            continue;
        }
        let k = (b2 - a2 + 1) as f64;
        let mean3 = |v: &Vec<Vec3>| {
            let m = v[a2..=b2].iter().fold(Vec3::zeros(), |s, x| s + x) / k;
            [m.x, m.y, m.z]
        };
        let acc_mean = rec.acc.as_ref().map(mean3);
        let acc_std = rec.acc.as_ref().map(|v| {
            let m = Vec3::from(mean3(v));
            (v[a2..=b2]
                .iter()
                .map(|x| (x - m).norm_squared())
                .sum::<f64>()
                / k)
                .sqrt()
        });
        let refi = rec.ref_inclination_deg.as_ref().and_then(|r| {
            let vals: Vec<f64> = r[a2..=b2]
                .iter()
                .copied()
                .filter(|x| x.is_finite())
                .collect();
            (!vals.is_empty()).then(|| vals.iter().sum::<f64>() / vals.len() as f64)
        });
        poses.push(Pose {
            index: poses.len(),
            rows: [a2, b2],
            lines: [rec.line[a2], rec.line[b2]],
            start_s: rec.t_s[a2],
            duration_s: d,
            n: b2 - a2 + 1,
            acc_mean,
            acc_std,
            gyr_mean: rec.gyr.as_ref().map(mean3),
            mag_mean: rec.mag.as_ref().map(mean3),
            temp_c: rec
                .temp_c
                .as_ref()
                .map(|t| t[a2..=b2].iter().sum::<f64>() / k),
            ref_inclination_deg: refi,
        });
    }
    if poses.is_empty() {
        return Err(rec.error(
            ErrorKind::Degenerate,
            format!(
                "no usable static pose: no still interval of at least {} s (threshold {:.3e}); hold the sensor still longer in each pose",
                opt.min_duration_s, thr_a
            ),
        ));
    }
    let total = poses.iter().map(|p| p.duration_s).sum();
    Ok(StaticReport {
        poses,
        acc_threshold: thr_a,
        gyr_threshold: thr_g,
        total_static_s: total,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use clino_core::ImuSample;

    fn rec_with_motion() -> Recording {
        // 3 poses of 2 s separated by 1 s of wobble, 50 Hz, tiny deterministic noise
        let mut s = Vec::new();
        let mut t = 0.0;
        let ups = [
            Vec3::new(0.0, 0.0, 9.8),
            Vec3::new(9.8, 0.0, 0.0),
            Vec3::new(0.0, -9.8, 0.0),
        ];
        for (k, u) in ups.iter().enumerate() {
            for i in 0..100 {
                let e = 1e-3 * ((i * 7 + k) as f64).sin();
                s.push(ImuSample::new(
                    t,
                    Vec3::new(e, -e, e),
                    u + Vec3::new(e, e, -e),
                ));
                t += 0.02;
            }
            if k < 2 {
                for i in 0..50 {
                    let w = (i as f64 * 0.3).sin();
                    s.push(ImuSample::new(
                        t,
                        Vec3::new(w, 0.5 * w, 0.0),
                        u * 0.5 + Vec3::new(w, -w, 2.0 * w),
                    ));
                    t += 0.02;
                }
            }
        }
        Recording::from_samples(&s, None)
    }

    #[test]
    fn finds_each_pose_with_its_mean() {
        let r = detect_static(&rec_with_motion(), &StaticOptions::default()).unwrap();
        assert_eq!(r.poses.len(), 3, "{}", r.table());
        assert!((r.poses[1].acc_mean.unwrap()[0] - 9.8).abs() < 1e-3);
        assert!((r.poses[2].acc_mean.unwrap()[1] + 9.8).abs() < 1e-3);
        for p in &r.poses {
            assert!(p.duration_s > 1.4 && p.duration_s <= 2.0, "{}", r.table());
        }
    }

    #[test]
    fn recording_without_stillness_is_an_error() {
        let s: Vec<_> = (0..500)
            .map(|i| {
                let w = (i as f64 * 0.5).sin();
                ImuSample::new(
                    i as f64 * 0.02,
                    Vec3::new(w, w, w),
                    Vec3::new(w, -w, 9.0 + w),
                )
            })
            .collect();
        let opt = StaticOptions {
            acc_threshold: Some(0.01),
            gyr_threshold: Some(0.01),
            ..Default::default()
        };
        let e = detect_static(&Recording::from_samples(&s, None), &opt).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Degenerate);
        assert!(e.message.contains("no usable static pose"));
    }
}
