//! Text of `clino stewart ik|fk`.

use crate::sim::stewart::{ForwardSolution, Pose};

/// The six leg lengths, metres with 12 decimals: `legs_m l1,…,l6`.
pub fn ik(legs_m: &[f64; 6]) -> String {
    let s: Vec<String> = legs_m.iter().map(|l| format!("{l:.12}")).collect();
    format!("legs_m {}\n", s.join(","))
}

/// The pose found by forward kinematics as an offset from `home` (mm) and
/// z-y-x roll, pitch, yaw (degrees), then the solver's effort.
pub fn fk(home: &Pose, sol: &ForwardSolution) -> String {
    let (r, p, y) = sol.pose.attitude.euler_angles();
    let off = sol.pose.pos_m - home.pos_m;
    format!(
        "x_mm {:.6} y_mm {:.6} z_mm {:.6} roll_deg {:.6} pitch_deg {:.6} yaw_deg {:.6}\n\
         iterations {} residual_m {:.3e} condition {:.1}\n",
        off.x * 1e3,
        off.y * 1e3,
        off.z * 1e3,
        r.to_degrees(),
        p.to_degrees(),
        y.to_degrees(),
        sol.iterations,
        sol.residual_m,
        sol.condition
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::stewart::Geometry;

    #[test]
    fn ik_then_fk_of_a_pose() {
        let g = Geometry::typical();
        let pose = Pose::from_deg([0.01, 0.0, 0.0], [2.0, 0.0, 0.0], g.home_height_m);
        let legs = g.inverse(&pose).unwrap();
        let s = ik(&legs);
        assert!(s.starts_with("legs_m ") && s.ends_with('\n'));
        assert_eq!(s.trim_end().split(',').count(), 6);
        let sol = g.forward(&legs, &g.home()).unwrap();
        let f = fk(&g.home(), &sol);
        let v: Vec<&str> = f.split_whitespace().collect();
        let num = |k: &str| -> f64 {
            let i = v.iter().position(|t| *t == k).unwrap();
            v[i + 1].parse().unwrap()
        };
        assert!((num("x_mm") - 10.0).abs() < 1e-5, "{f}");
        assert!((num("roll_deg") - 2.0).abs() < 1e-5, "{f}");
        for k in ["y_mm", "z_mm", "pitch_deg", "yaw_deg"] {
            assert!(num(k).abs() < 1e-5, "{k}: {f}");
        }
        assert_eq!(f.lines().count(), 2);
        assert!(
            f.lines()
                .nth(1)
                .unwrap()
                .starts_with(&format!("iterations {} ", sol.iterations))
        );
    }
}
