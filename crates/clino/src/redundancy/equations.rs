//! The source's diagnosis equations as linear relations (Li Chenggang et
//! al., "Fault Diagnosis in a Gyroscope-Based Six-Axis Accelerometer",
//! eqs 10–14).
//!
//! Every relation the source uses is a linear combination of six *base
//! residuals* `r = P·f − (0, 0, 0, c·ε*)` ([`SixAxisAccelerometer::parity`]):
//! the three compatibility equations (10 a–c) and the three gyro-pair
//! equations (12 g–i, `c = 2mn/3`). The gyro-integral equations (11 d–f) are
//! eqs 12 g–i integrated with the trapezoid rule; the source's printed form
//! drops the factor `3h/(2mn)` and the initial rate, which clino restores:
//! `ω*_N − ω*_1 = 3h/(2mn)·trapz(−f2+f4)` (likewise y, z). Over a block of
//! samples the integral form and the derivative form with the block-mean
//! `ε*` are the same number, so clino evaluates them once per block as
//! "d/g", "e/h", "f/i".
//!
//! The closed forms (13 j–o) solve each gyro pair from its compatibility
//! equation and its gyro equation, e.g. (j)
//! `f2 = −c·k2/(k2+k4)·ε*x − (f1/k1 + f5/k5)·k2k4/(k2+k4)`; as a relation,
//! (j) is `f2 − f̂2 = 0`, which involves chains 1, 2 and 5 only. The source's
//! *replacement method* (its Fig. 3, X axis) substitutes one normal chain of
//! a closed form through that chain's other compatibility equation, e.g.
//! chain 5 of (j) through (c), giving a relation on chains 1, 2, 6, 8, 9.
//! The twelve base relations and these twelve replacements are the 24
//! equations of the source's scheme ([`source_relations`]).

use super::fault_set::FaultSet;
use super::model::{Forces, N_CHAINS, SixAxisAccelerometer};
use clino_core::Vec3;
use nalgebra::{SMatrix, SVector};

/// One linear relation among the chain forces and the gyro.
#[derive(Clone, Debug, PartialEq)]
pub struct Relation {
    /// The source's label: "a".."c", "d/g".."f/i", "j".."o", or a
    /// replacement such as "j[5←c]" (chain 5 of (j) replaced through (c)).
    pub name: String,
    /// Coefficients over the six base residuals (10 a–c, 12 g–i).
    pub lambda: SVector<f64, 6>,
    /// Chains the relation involves (its support).
    pub chains: FaultSet,
}

impl Relation {
    /// The relation's residual for base residuals `r` (zero when fault free).
    pub fn residual(&self, r: &SVector<f64, 6>) -> f64 {
        self.lambda.dot(r)
    }
}

/// Base residuals `r = P·f − (0, 0, 0, c·ε*)` of one sample (eqs 10, 12).
pub fn base_residuals(acc: &SixAxisAccelerometer, f: &Forces, eps: &Vec3) -> SVector<f64, 6> {
    let mut r = acc.parity() * f;
    let c = acc.pair_coefficient();
    for i in 0..3 {
        r[3 + i] -= c * eps[i];
    }
    r
}

fn support(p: &SMatrix<f64, 6, 9>, lambda: &SVector<f64, 6>) -> FaultSet {
    let row = lambda.transpose() * p;
    let scale = row.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    FaultSet(
        (0..N_CHAINS)
            .filter(|&i| row[i].abs() > 1e-9 * scale)
            .fold(0, |m, i| m | (1 << i)),
    )
}

/// The combination of base rows `r1`, `r2` with unit coefficient on chain
/// `target` and zero on chain `elim` (solving a gyro pair, eq 13).
fn pair_solution(
    p: &SMatrix<f64, 6, 9>,
    r1: usize,
    r2: usize,
    target: usize,
    elim: usize,
) -> SVector<f64, 6> {
    // u·p[r1] + v·p[r2]: zero at elim, one at target
    let m = nalgebra::Matrix2::new(
        p[(r1, elim)],
        p[(r2, elim)],
        p[(r1, target)],
        p[(r2, target)],
    );
    let uv =
        m.try_inverse().expect("pair equations are independent") * nalgebra::Vector2::new(0.0, 1.0);
    let mut l = SVector::<f64, 6>::zeros();
    l[r1] = uv[0];
    l[r2] = uv[1];
    l
}

/// The twelve relations the source lists: 10 a–c, 11/12 d/g–f/i, 13 j–o.
pub fn base_relations(acc: &SixAxisAccelerometer) -> Vec<Relation> {
    let p = acc.parity();
    let mut out = Vec::new();
    for (k, name) in ["a", "b", "c", "d/g", "e/h", "f/i"].iter().enumerate() {
        let mut l = SVector::<f64, 6>::zeros();
        l[k] = 1.0;
        out.push(Relation {
            name: name.to_string(),
            lambda: l,
            chains: support(&p, &l),
        });
    }
    // (name, compat row, gyro row, target chain, eliminated partner), zero-based chains
    let forms = [
        ("j", 0, 3, 1, 3),
        ("k", 0, 3, 3, 1),
        ("l", 1, 4, 2, 6),
        ("m", 1, 4, 6, 2),
        ("n", 2, 5, 5, 7),
        ("o", 2, 5, 7, 5),
    ];
    for (name, r1, r2, t, e) in forms {
        let l = pair_solution(&p, r1, r2, t, e);
        out.push(Relation {
            name: name.to_string(),
            lambda: l,
            chains: support(&p, &l),
        });
    }
    out
}

/// The 24 relations of the source's scheme: the twelve base relations and
/// the twelve replacements of a normal chain (1, 5, 9) in a closed form
/// (13 j–o) through that chain's other compatibility equation.
pub fn source_relations(acc: &SixAxisAccelerometer) -> Vec<Relation> {
    let p = acc.parity();
    let base = base_relations(acc);
    let mut out = base.clone();
    let compat_names = ["a", "b", "c"];
    for rel in base.iter().skip(6) {
        // the compat row the closed form was built from
        let own = (0..3)
            .find(|&k| rel.lambda[k] != 0.0)
            .expect("closed form uses a compatibility row");
        for x in [0usize, 4, 8] {
            if !rel.chains.contains(x) {
                continue;
            }
            for w in 0..3 {
                if w == own || p[(w, x)] == 0.0 {
                    continue;
                }
                let coef = (rel.lambda.transpose() * p)[x];
                let mut l = rel.lambda;
                l[w] -= coef / p[(w, x)];
                out.push(Relation {
                    name: format!("{}[{}←{}]", rel.name, x + 1, compat_names[w]),
                    lambda: l,
                    chains: support(&p, &l),
                });
            }
        }
    }
    out
}

/// The source's closed forms (eq 13 j–o): theoretical values of the gyro-pair
/// chains `(f2, f4, f3, f7, f6, f8)` from the normal chains 1, 5, 9 and the
/// auxiliary angular acceleration `ε*` (rad/s²), N.
pub fn closed_forms(acc: &SixAxisAccelerometer, f: &Forces, eps: &Vec3) -> [f64; 6] {
    let k = &acc.stiffness_n_m;
    let c = acc.pair_coefficient();
    let s15 = f[0] / k[0] + f[4] / k[4];
    let s19 = f[0] / k[0] + f[8] / k[8];
    let s59 = f[4] / k[4] + f[8] / k[8];
    let (k2, k4, k3, k7, k6, k8) = (k[1], k[3], k[2], k[6], k[5], k[7]);
    [
        -c * k2 / (k2 + k4) * eps.x - s15 * k2 * k4 / (k2 + k4),
        c * k4 / (k2 + k4) * eps.x - s15 * k2 * k4 / (k2 + k4),
        c * k3 / (k3 + k7) * eps.y - s19 * k3 * k7 / (k3 + k7),
        -c * k7 / (k3 + k7) * eps.y - s19 * k3 * k7 / (k3 + k7),
        -c * k6 / (k6 + k8) * eps.z - s59 * k6 * k8 / (k6 + k8),
        c * k8 / (k6 + k8) * eps.z - s59 * k6 * k8 / (k6 + k8),
    ]
}

/// The source's restoration of chains 2, 3 and 9 (eq 14): `f̂2 = f4 − c·ε*x`,
/// `f̂3 = c·ε*y + f7`, `f̂9 = −k9·(f5/k5 + f6/k6 + f8/k8)`; other chains kept.
pub fn restore_eq14(acc: &SixAxisAccelerometer, f: &Forces, eps: &Vec3) -> Forces {
    let k = &acc.stiffness_n_m;
    let c = acc.pair_coefficient();
    let mut g = *f;
    g[1] = f[3] - c * eps.x;
    g[2] = c * eps.y + f[6];
    g[8] = -k[8] * (f[4] / k[4] + f[5] / k[5] + f[7] / k[7]);
    g
}

/// Residuals of the gyro-derivative equations (eq 12 g–i) of one sample:
/// `(−f2+f4, f3−f7, −f6+f8) − c·ε*`, N, with `c = 2mn/3` and `ε*` the
/// derivative of the gyro (rad/s²).
pub fn gyro_derivative_residuals(acc: &SixAxisAccelerometer, f: &Forces, eps: &Vec3) -> Vec3 {
    let r = base_residuals(acc, f, eps);
    Vec3::new(r[3], r[4], r[5])
}

/// Residuals of the gyro-integral equations (eq 11 d–f) at every sample `N`,
/// rad/s: `ω*_N − ω*_1 − 3/(2mn)·trapz_{1..N}(−f2+f4, f3−f7, −f6+f8)`, the
/// source's equation with the factor `3h/(2mn)` and the initial rate that
/// its printed form drops. A bias `b` on one chain of a gyro pair makes the
/// residual grow as `b·t/c`.
pub fn gyro_integral_residuals(
    acc: &SixAxisAccelerometer,
    t_s: &[f64],
    forces: &[Forces],
    gyr: &[Vec3],
) -> Vec<Vec3> {
    let n = t_s.len().min(forces.len()).min(gyr.len());
    let inv_c = 1.0 / acc.pair_coefficient();
    let pair = |f: &Forces| Vec3::new(-f[1] + f[3], f[2] - f[6], -f[5] + f[7]);
    let mut integral = Vec3::zeros();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        if i > 0 {
            integral += (t_s[i] - t_s[i - 1]) * 0.5 * (pair(&forces[i - 1]) + pair(&forces[i]));
        }
        out.push(gyr[i] - gyr[0] - integral * inv_c);
    }
    out
}

/// Residuals of the closed forms (eq 13 j–o): measured minus theoretical
/// `(f2, f4, f3, f7, f6, f8)`, N.
pub fn closed_form_residuals(acc: &SixAxisAccelerometer, f: &Forces, eps: &Vec3) -> [f64; 6] {
    let cf = closed_forms(acc, f, eps);
    let idx = [1, 3, 2, 6, 5, 7];
    std::array::from_fn(|k| f[idx[k]] - cf[k])
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn uneven() -> SixAxisAccelerometer {
        let k: [f64; 9] =
            std::array::from_fn(|i| 2.0e7 * (1.0 + 0.05 * ((i * 5 % 9) as f64 - 4.0)));
        SixAxisAccelerometer::new(0.08, 0.011, k).unwrap()
    }

    fn digits(rels: &[Relation]) -> Vec<String> {
        rels.iter()
            .map(|r| format!("{}:{}", r.name, r.chains))
            .collect()
    }

    #[test]
    fn supports_match_the_source() {
        let acc = uneven();
        let b = base_relations(&acc);
        assert_eq!(
            digits(&b),
            [
                "a:1245", "b:1379", "c:5689", "d/g:24", "e/h:37", "f/i:68", "j:125", "k:145",
                "l:139", "m:179", "n:569", "o:589"
            ]
        );
        let s = source_relations(&acc);
        assert_eq!(s.len(), 24);
        assert!(digits(&s).contains(&"j[5←c]:12689".to_string()));
        assert!(digits(&s).contains(&"j[1←b]:23579".to_string()));
    }

    #[test]
    fn closed_forms_equal_relations_and_recover_true_forces() {
        let acc = uneven();
        let eps = Vec3::new(30.0, -12.0, 7.0);
        let truth = acc.forces(&Vec3::new(2.0, -1.0, 9.0), &eps);
        let cf = closed_forms(&acc, &truth, &eps);
        for (v, i) in cf.iter().zip([1, 3, 2, 6, 5, 7]) {
            assert_relative_eq!(*v, truth[i], max_relative = 1e-9, epsilon = 1e-12);
        }
        // with arbitrary (inconsistent) forces, (j) = f2 − f̂2
        let f = Forces::from_fn(|i, _| (i as f64 * 1.7).sin());
        let r = base_residuals(&acc, &f, &eps);
        let b = base_relations(&acc);
        let cf = closed_forms(&acc, &f, &eps);
        for (k, i) in [1, 3, 2, 6, 5, 7].iter().enumerate() {
            assert_relative_eq!(b[6 + k].residual(&r), f[*i] - cf[k], max_relative = 1e-9);
        }
    }

    #[test]
    fn eq14_restores_239() {
        let acc = uneven();
        let eps = Vec3::new(-5.0, 22.0, 3.0);
        let truth = acc.forces(&Vec3::new(-1.0, 4.0, 9.5), &eps);
        let mut bad = truth;
        bad[1] += 0.3;
        bad[2] = 0.0;
        bad[8] *= -2.0;
        assert_relative_eq!(
            restore_eq14(&acc, &bad, &eps),
            truth,
            max_relative = 1e-9,
            epsilon = 1e-12
        );
    }

    #[test]
    fn gyro_equations_vanish_for_consistent_data_and_grow_with_a_bias() {
        use super::super::simulate::ShakeMotion;
        use crate::sim::Motion;
        let acc = SixAxisAccelerometer::reference();
        let m = ShakeMotion::default();
        let t: Vec<f64> = (0..501).map(|i| i as f64 * 1e-3).collect();
        let truth: Vec<_> = t.iter().map(|&t| m.truth(t)).collect();
        let mut f: Vec<Forces> = truth
            .iter()
            .map(|s| acc.forces(&s.specific_force(clino_core::G0), &s.ang_acc_rad_s2))
            .collect();
        let gyr: Vec<Vec3> = truth.iter().map(|s| s.gyr_rad_s).collect();
        for (s, fi) in truth.iter().zip(&f) {
            assert!(gyro_derivative_residuals(&acc, fi, &s.ang_acc_rad_s2).norm() < 1e-12);
            assert!(
                closed_form_residuals(&acc, fi, &s.ang_acc_rad_s2)
                    .iter()
                    .all(|r| r.abs() < 1e-12)
            );
        }
        let r = gyro_integral_residuals(&acc, &t, &f, &gyr);
        // trapezoid error only: h²/12·|Δε| over 0.5 s
        assert!(r.iter().all(|v| v.norm() < 2e-4), "{}", r[500].norm());
        // 10 mN bias on chain 2 from t = 0.2 s: x residual grows as b·(t − 0.2)/c
        for (i, fi) in f.iter_mut().enumerate() {
            if t[i] >= 0.2 {
                fi[1] += 0.01;
            }
        }
        let rb = gyro_integral_residuals(&acc, &t, &f, &gyr);
        let expect = 0.01 * 0.3 / acc.pair_coefficient();
        assert_relative_eq!(rb[500].x - r[500].x, expect, max_relative = 1e-2);
        assert!((rb[500].y - r[500].y).abs() < 1e-12 && (rb[500].z - r[500].z).abs() < 1e-12);
    }
}
