//! Text of `clino survey`: stations, roll tests and the trajectory.

use crate::survey::SurveyReport;

/// The station table (inclination, azimuth, toolfaces, field totals, dip),
/// the roll-test QC verdicts and the minimum-curvature trajectory.
pub fn survey(r: &SurveyReport) -> String {
    let o = |v: Option<f64>, p: usize| v.map(|x| format!("{x:.p$}")).unwrap_or_else(|| "-".into());
    let mut s = String::from(
        "   md_m    inc_deg    azi_deg  gtf_deg  mtf_deg     G_L_g     H_L_uT  dip_deg\n",
    );
    for st in &r.stations {
        s += &format!(
            "{:7.2} {:10.4} {:>10} {:>8} {:>8} {:9.5} {:>10} {:>8}\n",
            st.md_m,
            st.inclination_deg,
            o(st.azimuth_deg, 4),
            o(st.gravity_toolface_deg, 2),
            o(st.magnetic_toolface_deg, 2),
            st.g_total_g,
            o(st.h_total_ut, 3),
            o(st.dip_deg, 3)
        );
    }
    if !r.roll_tests.is_empty() {
        s += "\nroll tests (MWD QC: Δinc < 0.1°, Δazi < 1°, ΔG_L < 0.003 g)\n";
        for r in &r.roll_tests {
            s += &format!(
                "  md {:.2} m, {} readings: Δinc {:.4}° {}, Δazi {} {}, ΔG_L {:.5} g {} → {}\n",
                r.md_m,
                r.n,
                r.inclination_range_deg,
                if r.inclination_ok { "ok" } else { "FAIL" },
                o(r.azimuth_range_deg, 4),
                match r.azimuth_ok {
                    Some(true) => "ok",
                    Some(false) => "FAIL",
                    None => "n/a",
                },
                r.g_total_range_g,
                if r.g_total_ok { "ok" } else { "FAIL" },
                if r.pass { "PASS" } else { "FAIL" }
            );
        }
    }
    s += "\ntrajectory (minimum curvature, tie-on at the first station)\n   md_m    inc_deg    azi_deg     tvd_m    north_m     east_m  dls_deg_30m\n";
    for t in &r.trajectory {
        s += &format!(
            "{:7.2} {:10.4} {:10.4} {:9.3} {:10.3} {:10.3} {:12.4}\n",
            t.md_m,
            t.inclination_deg,
            t.azimuth_deg,
            t.tvd_m,
            t.north_m,
            t.east_m,
            t.dls_deg_per_30m
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::survey::SurveyOptions;
    use crate::survey::stations::parse_stations;

    #[test]
    fn a_vertical_then_tilted_survey() {
        // tool z down the hole (specific force up: -g on z when vertical), then horizontal
        let csv = "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,-9.80665\n30,9.80665,0,0\n";
        let r = crate::survey::survey(
            &parse_stations(csv.as_bytes()).unwrap(),
            &SurveyOptions::default(),
        )
        .unwrap();
        let s = survey(&r);
        let lines: Vec<&str> = s.lines().collect();
        assert!(lines[0].starts_with("   md_m    inc_deg    azi_deg"), "{s}");
        assert!(lines[1].starts_with("   0.00     0.0000          -"), "{s}");
        assert!(
            lines[2].starts_with(&format!(
                "{:7.2} {:10.4}",
                30.0, r.stations[1].inclination_deg
            )),
            "{s}"
        );
        assert!(s.contains("\ntrajectory (minimum curvature, tie-on at the first station)\n"));
        assert!(!s.contains("roll tests"), "{s}");
        assert_eq!(s.lines().count(), 3 + 3 + r.trajectory.len());
    }
}
