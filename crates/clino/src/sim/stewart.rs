//! 6-UPS Stewart platform: geometry, inverse and forward kinematics, servo legs.
//!
//! Source: Liu, Cai, Yang, Zhang, "Testing of a MEMS Dynamic Inclinometer
//! Using the Stewart Platform", Sensors 2019, section 2.1 (figure 2): the leg
//! lengths are computed from the desired pose (t, q) by inverse kinematics,
//! the servo legs follow them with amplitude attenuation and phase lag, and
//! the actual pose is recovered from the encoder lengths by forward
//! kinematics. The paper gives no dimensions; [`Geometry::typical`] is a
//! documented lab-sized layout.
//!
//! Kinematics: leg i joins the base joint b_i (universal joint, base frame) to
//! the platform joint p_i (spherical joint, platform frame). For the pose
//! (t, R) — platform centre t and rotation R (platform → base) — the leg
//! vector is v_i = t + R·p_i − b_i and its length l_i = |v_i| (inverse
//! kinematics). Forward kinematics solves the six equations l_i(t, R) = L_i
//! by Newton–Raphson with the analytic Jacobian row
//! ∂l_i/∂(t, δ) = [n_iᵀ, ((R·p_i) × n_i)ᵀ], n_i = v_i/l_i, for a small rotation
//! δ applied on the left (R ← exp([δ×])·R).
//!
//! ```
//! use clino::sim::stewart::{Geometry, Pose};
//! let g = Geometry::typical();
//! let pose = Pose::from_deg([0.01, -0.02, 0.005], [3.0, -2.0, 1.0], g.home_height_m);
//! let legs = g.inverse(&pose).unwrap();
//! let fk = g.forward(&legs, &g.home()).unwrap();
//! assert!((fk.pose.pos_m - pose.pos_m).norm() < 1e-9);
//! assert!(fk.iterations <= 6);
//! ```

use super::Motion;
use crate::{Error, ErrorKind, Result};
use clino_core::{Attitude, Vec3};
use nalgebra::{SMatrix, SVector};

type Mat6 = SMatrix<f64, 6, 6>;
type Vec6 = SVector<f64, 6>;

/// A platform pose: centre position and attitude (platform → base).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Position of the platform centre in the base frame, m.
    pub pos_m: Vec3,
    /// Rotation of the platform (platform → base frame).
    pub attitude: Attitude,
}

impl Pose {
    /// From a position offset (m) about the home height and aerospace roll,
    /// pitch, yaw in degrees (z-y-x: R = R_z(ψ)·R_y(θ)·R_x(φ)).
    pub fn from_deg(offset_m: [f64; 3], rpy_deg: [f64; 3], home_height_m: f64) -> Self {
        Self {
            pos_m: Vec3::new(offset_m[0], offset_m[1], offset_m[2] + home_height_m),
            attitude: Attitude::from_euler_angles(
                rpy_deg[0].to_radians(),
                rpy_deg[1].to_radians(),
                rpy_deg[2].to_radians(),
            ),
        }
    }
}

/// Joint layout and leg stroke of a 6-UPS platform.
#[derive(Clone, Debug, PartialEq)]
pub struct Geometry {
    /// Base (universal) joints b_i in the base frame, m.
    pub base_m: [Vec3; 6],
    /// Platform (spherical) joints p_i in the platform frame, m.
    pub platform_m: [Vec3; 6],
    /// Height of the platform centre above the base centre at home, m.
    pub home_height_m: f64,
    /// Shortest leg, m.
    pub leg_min_m: f64,
    /// Longest leg, m.
    pub leg_max_m: f64,
}

/// Result of forward kinematics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForwardSolution {
    /// The pose found.
    pub pose: Pose,
    /// Newton–Raphson iterations used.
    pub iterations: usize,
    /// Largest leg-length residual |l_i(pose) − L_i| at the solution, m.
    pub residual_m: f64,
    /// Condition number of the Jacobian at the solution.
    pub condition: f64,
}

impl Geometry {
    /// Largest Jacobian condition number accepted before the pose is called singular.
    pub const MAX_CONDITION: f64 = 1e8;

    /// Semi-regular hexagonal layout: base joints on a circle of radius `rb`
    /// at 120°·k ± `gamma_b`, platform joints on radius `rp` at 60° + 120°·k ± `gamma_p`;
    /// leg i joins the base joint at angle β_i to the neighbouring platform joint
    /// (the usual crossed 6-6 arrangement). Legs may stretch `stroke_m` either side
    /// of their home length.
    pub fn symmetric(
        rb: f64,
        rp: f64,
        gamma_b_rad: f64,
        gamma_p_rad: f64,
        home_height_m: f64,
        stroke_m: f64,
    ) -> Self {
        use std::f64::consts::PI;
        let third = 2.0 * PI / 3.0;
        let mut base_m = [Vec3::zeros(); 6];
        let mut platform_m = [Vec3::zeros(); 6];
        for k in 0..3 {
            let c = third * k as f64;
            let b = [c - gamma_b_rad, c + gamma_b_rad];
            // leg 2k (base c − γb) goes to the platform pair centred at c − 60°,
            // leg 2k+1 (base c + γb) to the pair centred at c + 60°
            let p = [c - PI / 3.0 + gamma_p_rad, c + PI / 3.0 - gamma_p_rad];
            for j in 0..2 {
                base_m[2 * k + j] = Vec3::new(rb * b[j].cos(), rb * b[j].sin(), 0.0);
                platform_m[2 * k + j] = Vec3::new(rp * p[j].cos(), rp * p[j].sin(), 0.0);
            }
        }
        let home_len = (Vec3::new(0.0, 0.0, home_height_m) + platform_m[0] - base_m[0]).norm();
        Self {
            base_m,
            platform_m,
            home_height_m,
            leg_min_m: home_len - stroke_m,
            leg_max_m: home_len + stroke_m,
        }
    }

    /// A typical laboratory platform (our choice; the paper gives no
    /// dimensions): base radius 0.50 m, platform radius 0.35 m, joint pairs
    /// ±10° about their centres, home height 0.60 m, leg stroke ±0.20 m (which
    /// holds every pose within ±50 mm and ±10° on all six axes).
    pub fn typical() -> Self {
        Self::symmetric(
            0.50,
            0.35,
            10f64.to_radians(),
            10f64.to_radians(),
            0.60,
            0.20,
        )
    }

    /// The home pose: level, centred, at the home height.
    pub fn home(&self) -> Pose {
        Pose {
            pos_m: Vec3::new(0.0, 0.0, self.home_height_m),
            attitude: Attitude::identity(),
        }
    }

    fn leg_vectors(&self, pose: &Pose) -> [Vec3; 6] {
        core::array::from_fn(|i| {
            pose.pos_m + pose.attitude.transform_vector(&self.platform_m[i]) - self.base_m[i]
        })
    }

    /// Leg lengths of `pose` without checking the stroke, m.
    pub fn leg_lengths(&self, pose: &Pose) -> [f64; 6] {
        self.leg_vectors(pose).map(|v| v.norm())
    }

    /// Inverse kinematics: the six leg lengths l_i = |t + R·p_i − b_i| of `pose`, m.
    /// Fails (`InvalidInput`) when a leg would leave its stroke or the pose is not finite.
    pub fn inverse(&self, pose: &Pose) -> Result<[f64; 6]> {
        if !(pose.pos_m.iter().all(|v| v.is_finite())
            && pose.attitude.coords.iter().all(|v| v.is_finite()))
        {
            return Err(Error::new(ErrorKind::InvalidInput, "pose is not finite"));
        }
        let l = self.leg_lengths(pose);
        self.check_stroke(&l)?;
        Ok(l)
    }

    fn check_stroke(&self, l: &[f64; 6]) -> Result<()> {
        for (i, li) in l.iter().enumerate() {
            if !li.is_finite() || *li < self.leg_min_m - 1e-12 || *li > self.leg_max_m + 1e-12 {
                return Err(Error::new(
                    ErrorKind::InvalidInput,
                    format!(
                        "leg {} length {:.6} m is outside the stroke [{:.6}, {:.6}] m: pose outside the workspace",
                        i + 1,
                        li,
                        self.leg_min_m,
                        self.leg_max_m
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The 6×6 Jacobian ∂l/∂(t, δ) at `pose`: row i = [n_iᵀ, ((R·p_i) × n_i)ᵀ].
    pub fn jacobian(&self, pose: &Pose) -> Mat6 {
        let mut j = Mat6::zeros();
        for i in 0..6 {
            let rp = pose.attitude.transform_vector(&self.platform_m[i]);
            let v = pose.pos_m + rp - self.base_m[i];
            let n = v / v.norm();
            let m = rp.cross(&n);
            for k in 0..3 {
                j[(i, k)] = n[k];
                j[(i, 3 + k)] = m[k];
            }
        }
        j
    }

    /// Condition number (largest over smallest singular value) of the Jacobian at `pose`.
    pub fn condition(&self, pose: &Pose) -> f64 {
        let sv = self.jacobian(pose).singular_values();
        let (mx, mn) = (sv.max(), sv.min());
        if mn > 0.0 { mx / mn } else { f64::INFINITY }
    }

    /// Forward kinematics: the pose whose legs have `lengths_m`, by Newton–Raphson
    /// from `guess` (the home pose or the previous solution).
    ///
    /// Stops when the largest residual is below 1e-12 m and the step below
    /// 1e-12 (m, rad); at most 50 iterations. Errors: `InvalidInput` for lengths
    /// outside the stroke, `Degenerate` when the Jacobian's condition number
    /// exceeds [`Geometry::MAX_CONDITION`] (near a singularity),
    /// `NotConverged` when the iteration does not settle (outside the workspace)
    /// or settles on the mirror assembly below the base plane.
    pub fn forward(&self, lengths_m: &[f64; 6], guess: &Pose) -> Result<ForwardSolution> {
        self.check_stroke(lengths_m)?;
        let target = Vec6::from_column_slice(lengths_m);
        let mut pose = *guess;
        let mut last_step = f64::INFINITY;
        for it in 0..=50 {
            let l = Vec6::from_column_slice(&self.leg_lengths(&pose));
            let r = target - l;
            let res = r.amax();
            if !res.is_finite() {
                break;
            }
            let j = self.jacobian(&pose);
            let svd = j.svd(true, true);
            let (mx, mn) = (svd.singular_values.max(), svd.singular_values.min());
            let cond = if mn > 0.0 { mx / mn } else { f64::INFINITY };
            if cond > Self::MAX_CONDITION {
                return Err(Error::new(
                    ErrorKind::Degenerate,
                    format!(
                        "forward kinematics: Jacobian condition {cond:.3e} at iteration {it}: too near a singular pose"
                    ),
                ));
            }
            if res < 1e-12 && last_step < 1e-12 {
                if pose.pos_m.z <= 0.0 {
                    return Err(Error::new(
                        ErrorKind::NotConverged,
                        "forward kinematics converged to the mirror assembly below the base: start from a pose above it",
                    ));
                }
                return Ok(ForwardSolution {
                    pose,
                    iterations: it,
                    residual_m: res,
                    condition: cond,
                });
            }
            if it == 50 {
                break;
            }
            let dx = svd.solve(&r, 0.0).map_err(|e| {
                Error::new(ErrorKind::Degenerate, format!("forward kinematics: {e}"))
            })?;
            let dt = Vec3::new(dx[0], dx[1], dx[2]);
            let dr = Vec3::new(dx[3], dx[4], dx[5]);
            pose.pos_m += dt;
            pose.attitude = Attitude::from_scaled_axis(dr) * pose.attitude;
            last_step = dx.amax();
            if last_step > 1.0 {
                break; // diverging: no nearby pose has these legs
            }
        }
        Err(Error::new(
            ErrorKind::NotConverged,
            "forward kinematics did not converge: leg lengths outside the reachable workspace or a poor initial guess",
        ))
    }
}

/// Servo legs modelled as second-order low-pass systems
/// l̈ = ω_n²·(l_cmd − l) − 2ζω_n·l̇ (amplitude attenuation and phase lag of the
/// servo loops of the paper's figure 2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ServoLegs {
    /// Natural frequency f_n, Hz.
    pub natural_hz: f64,
    /// Damping ratio ζ.
    pub damping: f64,
}

impl Default for ServoLegs {
    /// f_n = 20 Hz, ζ = 0.7 (a typical ball-screw servo leg; our choice).
    fn default() -> Self {
        Self {
            natural_hz: 20.0,
            damping: 0.7,
        }
    }
}

impl ServoLegs {
    /// Closed-form amplitude response |H(f)| = 1/√((1 − r²)² + (2ζr)²), r = f/f_n.
    pub fn gain(&self, f_hz: f64) -> f64 {
        let r = f_hz / self.natural_hz;
        1.0 / ((1.0 - r * r).powi(2) + (2.0 * self.damping * r).powi(2)).sqrt()
    }
    /// Closed-form phase lag, rad: atan2(2ζr, 1 − r²).
    pub fn phase_lag(&self, f_hz: f64) -> f64 {
        let r = f_hz / self.natural_hz;
        (2.0 * self.damping * r).atan2(1.0 - r * r)
    }
}

/// One time step of a simulated platform run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlatformSample {
    /// Time, s.
    pub t_s: f64,
    /// Commanded pose (from the motion).
    pub commanded: Pose,
    /// Commanded leg lengths (inverse kinematics), m.
    pub commanded_m: [f64; 6],
    /// Actual ("encoder") leg lengths after the servos, m.
    pub encoder_m: [f64; 6],
    /// Actual pose recovered from the encoder lengths by forward kinematics.
    pub actual: Pose,
    /// Forward-kinematics iterations used for this sample.
    pub fk_iterations: usize,
}

/// Drive the platform along `motion` (attitude, and position about the home
/// point) for `duration_s`, sampled at `rate_hz`: inverse kinematics per
/// instant, servo legs integrated by RK4 on 0.5 ms sub-steps (starting at rest
/// on the first command), forward kinematics of the encoder lengths warm-started
/// from the previous actual pose.
pub fn run_platform<M: Motion + ?Sized>(
    geometry: &Geometry,
    servo: &ServoLegs,
    motion: &M,
    rate_hz: f64,
    duration_s: f64,
) -> Result<Vec<PlatformSample>> {
    if !(rate_hz > 0.0 && duration_s >= 0.0 && rate_hz.is_finite() && duration_s.is_finite()) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "rate and duration must be positive and finite",
        ));
    }
    let n = (duration_s * rate_hz).round() as usize;
    let dt = 1.0 / rate_hz;
    let sub = (dt / 5e-4).ceil().max(1.0) as usize;
    let h = dt / sub as f64;
    let wn = 2.0 * std::f64::consts::PI * servo.natural_hz;
    let z = servo.damping;
    let home = geometry.home();
    let cmd_pose = |t: f64| {
        let tr = motion.truth(t);
        Pose {
            pos_m: home.pos_m + tr.pos_m,
            attitude: tr.attitude,
        }
    };
    let cmd_len = |t: f64| geometry.inverse(&cmd_pose(t));
    let mut x = cmd_len(0.0)?;
    let mut v = [0.0; 6];
    let mut guess = cmd_pose(0.0);
    let mut out = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 * dt;
        if k > 0 {
            let t0 = t - dt;
            for s in 0..sub {
                let ta = t0 + s as f64 * h;
                let (ua, um, ub) = (cmd_len(ta)?, cmd_len(ta + 0.5 * h)?, cmd_len(ta + h)?);
                for i in 0..6 {
                    let f = |u: f64, x: f64, v: f64| wn * wn * (u - x) - 2.0 * z * wn * v;
                    let (x0, v0) = (x[i], v[i]);
                    let k1x = v0;
                    let k1v = f(ua[i], x0, v0);
                    let k2x = v0 + 0.5 * h * k1v;
                    let k2v = f(um[i], x0 + 0.5 * h * k1x, k2x);
                    let k3x = v0 + 0.5 * h * k2v;
                    let k3v = f(um[i], x0 + 0.5 * h * k2x, k3x);
                    let k4x = v0 + h * k3v;
                    let k4v = f(ub[i], x0 + h * k3x, k4x);
                    x[i] = x0 + h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
                    v[i] = v0 + h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
                }
            }
        }
        let commanded = cmd_pose(t);
        let fk = geometry.forward(&x, &guess).map_err(|e| {
            let msg = format!("at t = {t:.4} s: {}", e.message);
            Error::new(e.kind, msg)
        })?;
        guess = fk.pose;
        out.push(PlatformSample {
            t_s: t,
            commanded,
            commanded_m: geometry.inverse(&commanded)?,
            encoder_m: x,
            actual: fk.pose,
            fk_iterations: fk.iterations,
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::motion::Conical;
    use proptest::prelude::*;

    fn pose_err(a: &Pose, b: &Pose) -> (f64, f64) {
        ((a.pos_m - b.pos_m).norm(), a.attitude.angle_to(&b.attitude))
    }

    proptest! {
        #[test]
        fn ik_then_fk_round_trips(
            x in -0.05f64..0.05, y in -0.05f64..0.05, z in -0.05f64..0.05,
            r in -10f64..10.0, p in -10f64..10.0, yaw in -10f64..10.0,
        ) {
            let g = Geometry::typical();
            let pose = Pose::from_deg([x, y, z], [r, p, yaw], g.home_height_m);
            // the whole ±50 mm, ±10° box is inside the stroke of the typical geometry
            let legs = g.inverse(&pose).unwrap();
            let fk = g.forward(&legs, &g.home()).unwrap();
            let (dp, da) = pose_err(&fk.pose, &pose);
            prop_assert!(dp <= 1e-9, "position error {dp}");
            prop_assert!(da <= 1e-9, "angle error {da}");
            prop_assert!(fk.iterations <= 8, "iterations {}", fk.iterations);
        }
    }

    #[test]
    fn fk_iteration_counts() {
        // deterministic grid over the workspace: report the iteration counts
        let g = Geometry::typical();
        let mut hist = [0usize; 10];
        for i in 0..5 {
            for j in 0..5 {
                let a = -10.0 + 5.0 * i as f64;
                let d = -0.05 + 0.025 * j as f64;
                let pose = Pose::from_deg([d, -d, 0.5 * d], [a, -a, 0.5 * a], g.home_height_m);
                let fk = g.forward(&g.inverse(&pose).unwrap(), &g.home()).unwrap();
                hist[fk.iterations.min(9)] += 1;
            }
        }
        eprintln!("FK iterations from home over a 5×5 grid (±10°, ±50 mm): histogram {hist:?}");
        let max = hist.iter().rposition(|&c| c > 0).unwrap();
        assert!(max <= 7, "{hist:?}");
    }

    #[test]
    fn jacobian_matches_finite_differences() {
        let g = Geometry::typical();
        let pose = Pose::from_deg([0.01, 0.02, -0.01], [4.0, -3.0, 7.0], g.home_height_m);
        let j = g.jacobian(&pose);
        let h = 1e-7;
        for k in 0..6 {
            let mut e = Vec3::zeros();
            e[k % 3] = h;
            let (mut pp, mut pm) = (pose, pose);
            if k < 3 {
                pp.pos_m += e;
                pm.pos_m -= e;
            } else {
                pp.attitude = Attitude::from_scaled_axis(e) * pose.attitude;
                pm.attitude = Attitude::from_scaled_axis(-e) * pose.attitude;
            }
            let (lp, lm) = (g.leg_lengths(&pp), g.leg_lengths(&pm));
            for i in 0..6 {
                assert!(((lp[i] - lm[i]) / (2.0 * h) - j[(i, k)]).abs() < 1e-7);
            }
        }
    }

    #[test]
    fn outside_workspace_and_singular_fail_clearly() {
        let g = Geometry::typical();
        let far = Pose::from_deg([0.0, 0.0, 0.5], [0.0, 0.0, 0.0], g.home_height_m);
        assert_eq!(g.inverse(&far).unwrap_err().kind, ErrorKind::InvalidInput);
        let mut legs = g.inverse(&g.home()).unwrap();
        legs[0] = g.leg_max_m + 0.01;
        assert_eq!(
            g.forward(&legs, &g.home()).unwrap_err().kind,
            ErrorKind::InvalidInput
        );
        // a flat platform in the base plane: every leg horizontal, Jacobian singular
        let flat = Pose {
            pos_m: Vec3::zeros(),
            attitude: Attitude::identity(),
        };
        let mut g2 = g.clone();
        g2.leg_min_m = 0.0;
        let l = g2.leg_lengths(&flat);
        let e = g2.forward(&l, &flat).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Degenerate, "{e}");
        // a guess below the base finds the mirror assembly, which is refused
        let below = Pose {
            pos_m: Vec3::new(0.0, 0.0, -g.home_height_m),
            attitude: Attitude::identity(),
        };
        let e = g
            .forward(&g.inverse(&g.home()).unwrap(), &below)
            .unwrap_err();
        assert_eq!(e.kind, ErrorKind::NotConverged, "{e}");
    }

    #[test]
    fn servo_attenuates_as_closed_form() {
        // slow enough that the geometry is nearly linear; the leg amplitude ratio
        // follows the second-order gain
        let g = Geometry::typical();
        let servo = ServoLegs {
            natural_hz: 5.0,
            damping: 0.5,
        };
        let f = 3.0;
        let cone = Conical::about_z(2f64.to_radians(), f);
        let run = run_platform(&g, &servo, &cone, 400.0, 4.0).unwrap();
        let w = 2.0 * std::f64::consts::PI * f;
        let amp = |sel: &dyn Fn(&PlatformSample) -> f64| {
            let pts: Vec<_> = run.iter().filter(|s| s.t_s >= 2.0).collect();
            let (mut c, mut s, mut m) = (0.0, 0.0, 0.0);
            for p in &pts {
                m += sel(p);
            }
            m /= pts.len() as f64;
            for p in &pts {
                c += (sel(p) - m) * (w * p.t_s).cos();
                s += (sel(p) - m) * (w * p.t_s).sin();
            }
            2.0 / pts.len() as f64 * (c * c + s * s).sqrt()
        };
        let a_cmd = amp(&|p| p.commanded_m[0]);
        let a_enc = amp(&|p| p.encoder_m[0]);
        let ratio = a_enc / a_cmd;
        assert!(
            (ratio / servo.gain(f) - 1.0).abs() < 0.01,
            "{ratio} vs {}",
            servo.gain(f)
        );
        assert!(run.iter().all(|s| s.fk_iterations <= 4));
        // the actual pose lags and differs from the commanded one
        let d = run[1000]
            .actual
            .attitude
            .angle_to(&run[1000].commanded.attitude);
        assert!(d > 1e-3);
    }
}
