//! The well path by the minimum-curvature method.
//!
//! Between two stations (MD₁, I₁, A₁) and (MD₂, I₂, A₂) the path is a circular
//! arc. With unit tangents t = (sin I·cos A, sin I·sin A, cos I) in
//! North-East-Down, the dogleg is β = 2·asin(|t₂ − t₁|/2) (equal to the
//! textbook acos(cos(I₂ − I₁) − sin I₁·sin I₂·(1 − cos(A₂ − A₁))) but accurate
//! for small angles), the ratio factor RF = (2/β)·tan(β/2) (→ 1 as β → 0), and
//! ΔN = ΔMD/2·(t₁ + t₂)_N·RF, ΔE likewise, ΔTVD = ΔMD/2·(cos I₁ + cos I₂)·RF.
//! Dogleg severity is β per 30 m. (SPE/ISCWSA standard practice; Bourgoyne et
//! al., *Applied Drilling Engineering*, the MWD paper's reference 1.)
//! The tie-on is the first station: TVD, north and east are 0 there.

use super::Station;
use crate::{Error, ErrorKind, Result};
use serde::Serialize;

/// One point of the well path.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrajectoryPoint {
    /// Measured depth, m.
    pub md_m: f64,
    /// Inclination, deg.
    pub inclination_deg: f64,
    /// Azimuth, deg (0 where undefined: vertical hole).
    pub azimuth_deg: f64,
    /// True vertical depth below the tie-on, m.
    pub tvd_m: f64,
    /// North of the tie-on, m.
    pub north_m: f64,
    /// East of the tie-on, m.
    pub east_m: f64,
    /// Dogleg from the previous station, deg.
    pub dogleg_deg: f64,
    /// Dogleg severity, deg per 30 m.
    pub dls_deg_per_30m: f64,
}

/// Minimum curvature over (md_m, inclination_deg, azimuth_deg) stations, with
/// measured depth strictly increasing. Errors name the offending station (0-based).
pub fn minimum_curvature(
    md_m: &[f64],
    inc_deg: &[f64],
    azi_deg: &[f64],
) -> Result<Vec<TrajectoryPoint>> {
    if md_m.len() != inc_deg.len() || md_m.len() != azi_deg.len() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "md, inclination and azimuth must have the same length",
        ));
    }
    let mut out: Vec<TrajectoryPoint> = Vec::with_capacity(md_m.len());
    for k in 0..md_m.len() {
        if !(md_m[k].is_finite() && inc_deg[k].is_finite() && azi_deg[k].is_finite()) {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!("station {k}: non-finite value"),
            ));
        }
        let (i2, a2) = (inc_deg[k].to_radians(), azi_deg[k].to_radians());
        let t2 = [i2.sin() * a2.cos(), i2.sin() * a2.sin(), i2.cos()];
        let Some(p) = out.last() else {
            out.push(TrajectoryPoint {
                md_m: md_m[0],
                inclination_deg: inc_deg[0],
                azimuth_deg: azi_deg[0],
                tvd_m: 0.0,
                north_m: 0.0,
                east_m: 0.0,
                dogleg_deg: 0.0,
                dls_deg_per_30m: 0.0,
            });
            continue;
        };
        let dmd = md_m[k] - p.md_m;
        if dmd <= 0.0 {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "station {k}: measured depth {} m does not increase (previous {} m)",
                    md_m[k], p.md_m
                ),
            )
            .at_column("md_m"));
        }
        let (i1, a1) = (p.inclination_deg.to_radians(), p.azimuth_deg.to_radians());
        let t1 = [i1.sin() * a1.cos(), i1.sin() * a1.sin(), i1.cos()];
        let d =
            ((t2[0] - t1[0]).powi(2) + (t2[1] - t1[1]).powi(2) + (t2[2] - t1[2]).powi(2)).sqrt();
        let beta = 2.0 * (0.5 * d).min(1.0).asin();
        let rf = if beta > 1e-6 {
            2.0 / beta * (0.5 * beta).tan()
        } else {
            1.0 + beta * beta / 12.0
        };
        let h = 0.5 * dmd * rf;
        out.push(TrajectoryPoint {
            md_m: md_m[k],
            inclination_deg: inc_deg[k],
            azimuth_deg: azi_deg[k],
            tvd_m: p.tvd_m + h * (t1[2] + t2[2]),
            north_m: p.north_m + h * (t1[0] + t2[0]),
            east_m: p.east_m + h * (t1[1] + t2[1]),
            dogleg_deg: beta.to_degrees(),
            dls_deg_per_30m: beta.to_degrees() / dmd * 30.0,
        });
    }
    Ok(out)
}

/// Mean of angles, deg (circular).
fn circular_mean_deg(a: &[f64]) -> f64 {
    let (s, c) = a.iter().fold((0.0, 0.0), |(s, c), x| {
        (s + x.to_radians().sin(), c + x.to_radians().cos())
    });
    s.atan2(c).to_degrees().rem_euclid(360.0)
}

/// The trajectory of survey stations: readings at one depth (roll tests) are
/// averaged (inclination arithmetically, azimuth circularly); an undefined
/// azimuth (vertical hole) counts as 0°, which does not affect the path there.
pub fn from_stations(stations: &[Station]) -> Result<Vec<TrajectoryPoint>> {
    let (mut md, mut inc, mut azi) = (Vec::new(), Vec::new(), Vec::new());
    let mut i = 0;
    while i < stations.len() {
        let mut j = i + 1;
        while j < stations.len() && stations[j].md_m == stations[i].md_m {
            j += 1;
        }
        let g = &stations[i..j];
        if let Some(&prev) = md.last()
            && g[0].md_m <= prev
        {
            return Err(Error::new(
                ErrorKind::InvalidInput,
                format!(
                    "measured depth {} m does not increase (previous {prev} m)",
                    g[0].md_m
                ),
            )
            .at_line(g[0].line)
            .at_column("md_m"));
        }
        md.push(g[0].md_m);
        inc.push(g.iter().map(|s| s.inclination_deg).sum::<f64>() / g.len() as f64);
        let a: Vec<f64> = g.iter().filter_map(|s| s.azimuth_deg).collect();
        azi.push(if a.is_empty() {
            0.0
        } else {
            circular_mean_deg(&a)
        });
        i = j;
    }
    minimum_curvature(&md, &inc, &azi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn straight_holes() {
        // vertical: TVD = MD difference
        let t = minimum_curvature(&[0.0, 100.0, 250.0], &[0.0; 3], &[0.0; 3]).unwrap();
        assert_relative_eq!(t[2].tvd_m, 250.0, epsilon = 1e-12);
        // straight slant at 30°, azimuth 90° (east)
        let t = minimum_curvature(&[100.0, 200.0], &[30.0, 30.0], &[90.0, 90.0]).unwrap();
        assert_relative_eq!(
            t[1].tvd_m,
            100.0 * 30f64.to_radians().cos(),
            epsilon = 1e-12
        );
        assert_relative_eq!(t[1].east_m, 50.0, epsilon = 1e-12);
        assert_relative_eq!(t[1].north_m, 0.0, epsilon = 1e-12);
        assert_eq!(t[1].dls_deg_per_30m, 0.0);
    }

    #[test]
    fn build_section_is_a_circular_arc() {
        // from vertical to 90° in 100 m of MD heading north: quarter circle of radius R = 200/π
        let r = 200.0 / std::f64::consts::PI;
        let t = minimum_curvature(&[0.0, 100.0], &[0.0, 90.0], &[0.0, 0.0]).unwrap();
        assert_relative_eq!(t[1].tvd_m, r, epsilon = 1e-9);
        assert_relative_eq!(t[1].north_m, r, epsilon = 1e-9);
        assert_relative_eq!(t[1].dogleg_deg, 90.0, epsilon = 1e-9);
        assert_relative_eq!(t[1].dls_deg_per_30m, 27.0, epsilon = 1e-9);
        // the same arc in 10 steps lands on the same point
        let md: Vec<f64> = (0..=10).map(|k| k as f64 * 10.0).collect();
        let inc: Vec<f64> = (0..=10).map(|k| k as f64 * 9.0).collect();
        let t = minimum_curvature(&md, &inc, &[0.0; 11]).unwrap();
        assert_relative_eq!(t[10].tvd_m, r, epsilon = 1e-9);
        assert_relative_eq!(t[10].north_m, r, epsilon = 1e-9);
    }

    #[test]
    fn dogleg_matches_textbook_formula_and_md_must_increase() {
        let (i1, a1, i2, a2) = (
            20f64.to_radians(),
            40f64.to_radians(),
            25f64.to_radians(),
            55f64.to_radians(),
        );
        let textbook = ((i2 - i1).cos() - i1.sin() * i2.sin() * (1.0 - (a2 - a1).cos())).acos();
        let t = minimum_curvature(&[0.0, 30.0], &[20.0, 25.0], &[40.0, 55.0]).unwrap();
        assert_relative_eq!(t[1].dogleg_deg, textbook.to_degrees(), epsilon = 1e-10);
        let e = minimum_curvature(&[0.0, 30.0, 30.0], &[0.0; 3], &[0.0; 3]).unwrap_err();
        assert!(e.message.contains("station 2"));
    }
}
