//! The nine-chain cube: geometry, dynamics (eqs 1–4), compatibility (eqs 8–10)
//! and the forward model that turns a motion into nine chain forces.
//!
//! Source: Li Chenggang et al., "Fault Diagnosis in a Gyroscope-Based
//! Six-Axis Accelerometer", Transactions of FAMENA XLII-3, 2018.
//!
//! ## Geometry (reconstructed from eqs 1, 2 and 9)
//!
//! A solid cube of mass `m` and half edge `n` hangs in the sensor housing by
//! nine piezoelectric branch chains meeting the cube at three composite
//! spherical joints at the centres of three faces (body frame {M}, origin at
//! the cube centre):
//!
//! | joint | nominal position b | chains (axis, sign) |
//! |---|---|---|
//! | b1 | (0, 0, −n) | 1 (+z), 2 (−y), 3 (−x) |
//! | b2 | (0, −n, 0) | 4 (−z), 5 (+y), 6 (−x) |
//! | b3 | (−n, 0, 0) | 7 (−z), 8 (−y), 9 (+x) |
//!
//! Chain *i* pushes the cube with `sᵢ·fᵢ·e_axis` at its joint, which gives the
//! source's resultant force (eq 1) `F = (−f3−f6+f9, −f2+f5−f8, f1−f4−f7)` and,
//! with `r × F` summed over the joints, its torque (eq 2)
//! `T = n·(−f2+f4, f3−f7, −f6+f8)`. Chains 1, 5 and 9 are the *normal* chains
//! (along the face normal of their joint); (2, 4), (3, 7) and (6, 8) are the
//! *gyro pairs* whose differences carry the three torques.
//!
//! ## Dynamics (eqs 3, 4)
//!
//! Newton: `m·a = A·F + m·g_vec`, so `F/m` is the specific force in the body
//! frame, exactly what an accelerometer reads: a level cube at rest carries
//! `f1 − f4 − f7 = m·g`. The source writes gravity as `+(g, 0, 0)` in its
//! inertial frame; in clino's ENU frame `a = A·F/m − g·e_z`.
//! Euler: the cube's inertia is isotropic, `I = (2/3)·m·n²`, so the
//! gyroscopic term `ω × Iω` vanishes and `ε = T/I = 3/(2mn)·(…)` (eq 4) holds in
//! the body frame and, rotated by `A`, in the inertial frame.
//!
//! ## Compatibility (eqs 8–10)
//!
//! The joints are welded to the cube, so their mutual distances stay `√2·n`
//! (eq 8). A chain of stiffness `kᵢ` deforms by `fᵢ/kᵢ`, which moves its joint
//! along the chain axis (eq 9: `b1 = (−f3/k3, −f2/k2, f1/k1 − n)`,
//! `b2 = (−f6/k6, f5/k5 − n, −f4/k4)`, `b3 = (f9/k9 − n, −f8/k8, −f7/k7)`).
//! Linearising eq 8 gives the three force–deformation compatibility equations
//! (eq 10): (a) `f1/k1 + f2/k2 + f4/k4 + f5/k5 = 0`,
//! (b) `f1/k1 + f3/k3 + f7/k7 + f9/k9 = 0`, (c) `f5/k5 + f6/k6 + f8/k8 + f9/k9 = 0`.
//! They say the nine deformations are a rigid small displacement of the cube.
//! (The source's eq 9 moves the joint *with* the force, a physical spring
//! moves it against; the equations are homogeneous, so the sign is immaterial.)
//!
//! ## Forward model
//!
//! Six dynamic equations (eqs 1–4) plus three compatibility equations (eq 10)
//! are nine linear equations for the nine forces:
//! [`SixAxisAccelerometer::forces`].

use crate::{Error, ErrorKind, Result};
use clino_core::Vec3;
use nalgebra::{SMatrix, SVector, Vector3};

/// Number of branch chains.
pub const N_CHAINS: usize = 9;

/// The nine chain forces `f1..f9`, N (index 0 is chain 1).
pub type Forces = SVector<f64, N_CHAINS>;

/// One branch chain: where it meets the cube and which way it pushes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Chain {
    /// Joint index 0, 1, 2 (the source's b1, b2, b3).
    pub joint: usize,
    /// Body axis the chain acts along: 0 = x, 1 = y, 2 = z.
    pub axis: usize,
    /// Sign of the chain force in the resultant (eq 1): +1 or −1.
    pub sign: f64,
}

/// The nine chains in the source's numbering (index 0 is chain 1); see the module table.
pub const CHAINS: [Chain; N_CHAINS] = [
    Chain {
        joint: 0,
        axis: 2,
        sign: 1.0,
    },
    Chain {
        joint: 0,
        axis: 1,
        sign: -1.0,
    },
    Chain {
        joint: 0,
        axis: 0,
        sign: -1.0,
    },
    Chain {
        joint: 1,
        axis: 2,
        sign: -1.0,
    },
    Chain {
        joint: 1,
        axis: 1,
        sign: 1.0,
    },
    Chain {
        joint: 1,
        axis: 0,
        sign: -1.0,
    },
    Chain {
        joint: 2,
        axis: 2,
        sign: -1.0,
    },
    Chain {
        joint: 2,
        axis: 1,
        sign: -1.0,
    },
    Chain {
        joint: 2,
        axis: 0,
        sign: 1.0,
    },
];

/// The normal chains (1, 5, 9), zero-based.
pub const NORMAL_CHAINS: [usize; 3] = [0, 4, 8];

/// The gyro pairs (2, 4), (3, 7), (6, 8), zero-based, in the order of the
/// torque components x, y, z (eq 2); the first of each pair enters the torque
/// with a minus sign, the second with a plus sign (for y: `f3 − f7`, so 3 is plus).
pub const GYRO_PAIRS: [(usize, usize); 3] = [(1, 3), (2, 6), (5, 7)];

/// Chains of each compatibility equation (10 a, b, c), zero-based.
pub const COMPAT_CHAINS: [[usize; 4]; 3] = [[0, 1, 3, 4], [0, 2, 6, 8], [4, 5, 7, 8]];

/// A parallel-mechanism six-axis accelerometer: the cube and its nine chains.
#[derive(Clone, Debug, PartialEq)]
pub struct SixAxisAccelerometer {
    /// Mass of the cube `m`, kg.
    pub mass_kg: f64,
    /// Half of the cube edge `n`, m.
    pub half_edge_m: f64,
    /// Stiffness `k1..k9` of the piezoelectric chains, N/m.
    pub stiffness_n_m: [f64; N_CHAINS],
}

impl SixAxisAccelerometer {
    /// A cube with validated parameters (all positive and finite).
    pub fn new(mass_kg: f64, half_edge_m: f64, stiffness_n_m: [f64; N_CHAINS]) -> Result<Self> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !ok(mass_kg) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("cube mass must be positive, got {mass_kg} kg"),
            ));
        }
        if !ok(half_edge_m) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("cube half edge must be positive, got {half_edge_m} m"),
            ));
        }
        if let Some(i) = stiffness_n_m.iter().position(|&k| !ok(k)) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "stiffness k{} must be positive, got {} N/m",
                    i + 1,
                    stiffness_n_m[i]
                ),
            ));
        }
        Ok(Self {
            mass_kg,
            half_edge_m,
            stiffness_n_m,
        })
    }

    /// The reference device used by clino's simulations and defaults: a steel
    /// cube of 24 mm edge (`m` = 0.1 kg, `n` = 12 mm) on nine piezo stacks of
    /// 2·10⁷ N/m.
    pub fn reference() -> Self {
        Self {
            mass_kg: 0.1,
            half_edge_m: 0.012,
            stiffness_n_m: [2.0e7; N_CHAINS],
        }
    }

    /// Moment of inertia of the solid cube about any axis through its centre,
    /// `I = (2/3)·m·n²`, kg·m² (the factor behind the source's eq 4).
    pub fn inertia(&self) -> f64 {
        2.0 / 3.0 * self.mass_kg * self.half_edge_m * self.half_edge_m
    }

    /// `c = 2mn/3`, N·s²: the factor linking a gyro-pair difference to the
    /// angular acceleration, `−f2 + f4 = c·ε*x` (eq 12).
    pub fn pair_coefficient(&self) -> f64 {
        2.0 / 3.0 * self.mass_kg * self.half_edge_m
    }

    /// Nominal position of joint `j` (0, 1, 2) in the body frame, m.
    pub fn joint_nominal(&self, j: usize) -> Vec3 {
        let n = self.half_edge_m;
        match j {
            0 => Vec3::new(0.0, 0.0, -n),
            1 => Vec3::new(0.0, -n, 0.0),
            _ => Vec3::new(-n, 0.0, 0.0),
        }
    }

    /// Resultant chain force on the cube in the body frame, N (eq 1 without
    /// the rotation and gravity): `(−f3−f6+f9, −f2+f5−f8, f1−f4−f7)`.
    pub fn force_on_cube(&self, f: &Forces) -> Vec3 {
        Vec3::new(-f[2] - f[5] + f[8], -f[1] + f[4] - f[7], f[0] - f[3] - f[6])
    }

    /// Resultant chain torque about the cube centre in the body frame, N·m
    /// (eq 2 without the rotation): `n·(−f2+f4, f3−f7, −f6+f8)`.
    pub fn torque_on_cube(&self, f: &Forces) -> Vec3 {
        self.half_edge_m * Vec3::new(-f[1] + f[3], f[2] - f[6], -f[5] + f[7])
    }

    /// Specific force of the cube in the body frame, m/s² (eq 3 in the body
    /// frame): `F/m`. A level cube at rest gives `(0, 0, +g)`.
    pub fn specific_force(&self, f: &Forces) -> Vec3 {
        self.force_on_cube(f) / self.mass_kg
    }

    /// Body angular acceleration `ε*`, rad/s² (eq 4 in the body frame, eq 7):
    /// `ε* = 3/(2mn)·(−f2+f4, f3−f7, −f6+f8)`.
    pub fn angular_acceleration(&self, f: &Forces) -> Vec3 {
        self.torque_on_cube(f) / self.inertia()
    }

    /// Residuals of the three compatibility equations (eq 10 a, b, c), m.
    pub fn compatibility(&self, f: &Forces) -> Vector3<f64> {
        let d = |i: usize| f[i] / self.stiffness_n_m[i];
        Vector3::from_fn(|r, _| COMPAT_CHAINS[r].iter().map(|&i| d(i)).sum())
    }

    /// Joint positions `b1, b2, b3` for the chain forces `f` (eq 9), m.
    pub fn joint_positions(&self, f: &Forces) -> [Vec3; 3] {
        let mut b = [
            self.joint_nominal(0),
            self.joint_nominal(1),
            self.joint_nominal(2),
        ];
        for (i, c) in CHAINS.iter().enumerate() {
            b[c.joint][c.axis] += c.sign * f[i] / self.stiffness_n_m[i];
        }
        b
    }

    /// The 9×9 matrix of the forward model: rows 0–2 the resultant force
    /// (eq 1), rows 3–5 the torque divided by the inertia (eq 4), rows 6–8
    /// the compatibility equations (eq 10).
    fn forward_matrix(&self) -> SMatrix<f64, 9, 9> {
        let mut m = SMatrix::<f64, 9, 9>::zeros();
        for i in 0..N_CHAINS {
            let mut e = Forces::zeros();
            e[i] = 1.0;
            let fo = self.force_on_cube(&e);
            let ep = self.angular_acceleration(&e);
            let co = self.compatibility(&e);
            for r in 0..3 {
                m[(r, i)] = fo[r];
                m[(3 + r, i)] = ep[r];
                m[(6 + r, i)] = co[r];
            }
        }
        m
    }

    /// Sensitivity `H` (9×6): chain forces per unit body specific force
    /// (columns 0–2, N per m/s²) and per unit body angular acceleration
    /// (columns 3–5, N per rad/s²); `f = H·(F/m, ε*)`. The inverse of the
    /// forward system of eqs 1–4 and 10.
    pub fn sensitivity(&self) -> SMatrix<f64, 9, 6> {
        let inv = self
            .forward_matrix()
            .try_inverse()
            .expect("the nine-chain forward system is regular for positive stiffnesses");
        let mut h = SMatrix::<f64, 9, 6>::zeros();
        for c in 0..3 {
            h.set_column(c, &(inv.column(c) * self.mass_kg));
            h.set_column(3 + c, &inv.column(3 + c));
        }
        h
    }

    /// Forward model: the nine chain forces for a body specific force
    /// (m/s²) and body angular acceleration (rad/s²), solving eqs 1–4 and 10.
    pub fn forces(&self, specific_force_b: &Vec3, ang_acc_b: &Vec3) -> Forces {
        let x = SVector::<f64, 6>::new(
            specific_force_b.x,
            specific_force_b.y,
            specific_force_b.z,
            ang_acc_b.x,
            ang_acc_b.y,
            ang_acc_b.z,
        );
        self.sensitivity() * x
    }

    /// The 6×9 parity matrix `P`: rows 0–2 the compatibility equations
    /// (eq 10 a–c, in m per N), rows 3–5 the gyro-pair differences
    /// (left sides of eq 12 g–i: `−f2+f4`, `f3−f7`, `−f6+f8`).
    /// Fault-free forces satisfy `P·f = (0, 0, 0, c·ε*)` with `c` = [`Self::pair_coefficient`].
    pub fn parity(&self) -> SMatrix<f64, 6, 9> {
        let mut p = SMatrix::<f64, 6, 9>::zeros();
        for (r, chains) in COMPAT_CHAINS.iter().enumerate() {
            for &i in chains {
                p[(r, i)] = 1.0 / self.stiffness_n_m[i];
            }
        }
        // −f2+f4, f3−f7, −f6+f8
        p[(3, 1)] = -1.0;
        p[(3, 3)] = 1.0;
        p[(4, 2)] = 1.0;
        p[(4, 6)] = -1.0;
        p[(5, 5)] = -1.0;
        p[(5, 7)] = 1.0;
        p
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use clino_core::G0;

    fn uneven() -> SixAxisAccelerometer {
        let mut k = [2.0e7; 9];
        for (i, v) in k.iter_mut().enumerate() {
            *v *= 1.0 + 0.03 * (i as f64 - 4.0);
        }
        SixAxisAccelerometer::new(0.1, 0.012, k).unwrap()
    }

    /// Independent stiffness model: the cube moves rigidly by (u, θ); each
    /// chain deforms by its share of the joint displacement and pushes with kᵢ
    /// times it. Equilibrium with the inertial load fixes (u, θ).
    fn stiffness_model(acc: &SixAxisAccelerometer, sf: &Vec3, eps: &Vec3) -> Forces {
        let mut j = SMatrix::<f64, 9, 6>::zeros();
        for (i, c) in CHAINS.iter().enumerate() {
            let mut e = Vec3::zeros();
            e[c.axis] = c.sign;
            let r = acc.joint_nominal(c.joint);
            let rxe = r.cross(&e);
            for a in 0..3 {
                j[(i, a)] = e[a];
                j[(i, 3 + a)] = rxe[a];
            }
        }
        let k = SMatrix::<f64, 9, 9>::from_diagonal(&Forces::from_row_slice(&acc.stiffness_n_m));
        let load = SVector::<f64, 6>::new(
            acc.mass_kg * sf.x,
            acc.mass_kg * sf.y,
            acc.mass_kg * sf.z,
            acc.inertia() * eps.x,
            acc.inertia() * eps.y,
            acc.inertia() * eps.z,
        );
        let q = (j.transpose() * k * j).lu().solve(&load).unwrap();
        k * j * q
    }

    #[test]
    fn level_at_rest_carries_weight() {
        let acc = SixAxisAccelerometer::reference();
        let f = acc.forces(&Vec3::new(0.0, 0.0, G0), &Vec3::zeros());
        assert_relative_eq!(f[0] - f[3] - f[6], acc.mass_kg * G0, epsilon = 1e-12);
        assert_relative_eq!(
            acc.specific_force(&f),
            Vec3::new(0.0, 0.0, G0),
            epsilon = 1e-12
        );
        assert_relative_eq!(acc.angular_acceleration(&f), Vec3::zeros(), epsilon = 1e-9);
    }

    #[test]
    fn torque_is_sum_of_r_cross_f() {
        let acc = uneven();
        let f = Forces::from_fn(|i, _| (i as f64 * 0.37).sin());
        let mut t = Vec3::zeros();
        let mut fsum = Vec3::zeros();
        for (i, c) in CHAINS.iter().enumerate() {
            let mut v = Vec3::zeros();
            v[c.axis] = c.sign * f[i];
            t += acc.joint_nominal(c.joint).cross(&v);
            fsum += v;
        }
        assert_relative_eq!(acc.torque_on_cube(&f), t, epsilon = 1e-15);
        assert_relative_eq!(acc.force_on_cube(&f), fsum, epsilon = 1e-15);
    }

    #[test]
    fn inertia_of_solid_cube_by_quadrature() {
        // ∫ (y² + z²) ρ dV over the cube [−n, n]³, midpoint rule
        let acc = SixAxisAccelerometer::reference();
        let n = acc.half_edge_m;
        let steps = 40;
        let h = 2.0 * n / steps as f64;
        let rho = acc.mass_kg / (8.0 * n * n * n);
        let mut i_xx = 0.0;
        for a in 0..steps {
            for b in 0..steps {
                let y = -n + (a as f64 + 0.5) * h;
                let z = -n + (b as f64 + 0.5) * h;
                i_xx += (y * y + z * z) * rho * h * h * (2.0 * n);
            }
        }
        assert_relative_eq!(i_xx, acc.inertia(), max_relative = 1e-3);
    }

    #[test]
    fn forward_model_matches_stiffness_model() {
        let acc = uneven();
        let sf = Vec3::new(1.5, -3.0, 9.0);
        let eps = Vec3::new(20.0, -7.0, 3.0);
        let f = acc.forces(&sf, &eps);
        let g = stiffness_model(&acc, &sf, &eps);
        assert_relative_eq!(f, g, max_relative = 1e-9, epsilon = 1e-12);
        assert_relative_eq!(acc.specific_force(&f), sf, epsilon = 1e-9);
        assert_relative_eq!(acc.angular_acceleration(&f), eps, epsilon = 1e-6);
        assert!(acc.compatibility(&f).norm() < 1e-18);
    }

    #[test]
    fn compatibility_is_linearised_distance_constraint() {
        // Eq 8 by finite differences: for rigid-displacement forces the joint
        // distances change only at second order; for arbitrary forces the first
        // order change equals the eq 10 residuals (scaled by the geometry).
        let acc = uneven();
        let n = acc.half_edge_m;
        let rigid = stiffness_model(
            &acc,
            &Vec3::new(3.0, -2.0, 8.0),
            &Vec3::new(50.0, 10.0, -30.0),
        );
        let arbitrary = Forces::from_fn(|i, _| ((i * 7 + 3) as f64).cos());
        for (f, expect_zero) in [(rigid, true), (arbitrary, false)] {
            let s = 1.0e3; // scale so deformations are ~0.05 mm
            let b = acc.joint_positions(&(f * s));
            let d = [
                (b[0] - b[1]).norm(),
                (b[0] - b[2]).norm(),
                (b[1] - b[2]).norm(),
            ];
            let c = acc.compatibility(&(f * s));
            let dmax = (0..9)
                .map(|i| (f[i] * s / acc.stiffness_n_m[i]).abs())
                .fold(0.0, f64::max);
            for r in 0..3 {
                let change = d[r] - 2f64.sqrt() * n;
                // |b_i − b_j| ≈ √2 n − (first-order term) = √2 n − c_r / √2
                if expect_zero {
                    // second order only: ~dmax²/n, far below the first-order dmax
                    assert!(change.abs() < 0.02 * dmax, "rigid: {change} vs {dmax}");
                } else {
                    assert_relative_eq!(change, -c[r] / 2f64.sqrt(), max_relative = 0.02);
                }
            }
        }
    }

    #[test]
    fn parity_annihilates_fault_free_forces() {
        let acc = uneven();
        let eps = Vec3::new(-4.0, 12.0, 0.5);
        let f = acc.forces(&Vec3::new(0.3, 2.0, 9.5), &eps);
        let r = acc.parity() * f;
        for i in 0..3 {
            assert!(r[i].abs() < 1e-18);
            assert_relative_eq!(
                r[3 + i],
                acc.pair_coefficient() * eps[i],
                max_relative = 1e-9
            );
        }
    }

    #[test]
    fn rejects_bad_parameters() {
        assert!(SixAxisAccelerometer::new(0.0, 0.01, [1.0; 9]).is_err());
        assert!(SixAxisAccelerometer::new(0.1, f64::NAN, [1.0; 9]).is_err());
        let mut k = [1.0; 9];
        k[4] = -1.0;
        let e = SixAxisAccelerometer::new(0.1, 0.01, k).unwrap_err();
        assert!(e.message.contains("k5"));
    }
}
