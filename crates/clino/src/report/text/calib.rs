//! Text of `clino calibrate accel|gyro|mag`: the poses found and the result.

use crate::calib::fit::ParamEstimate;
use crate::calib::{Calibration, Outcome};
use std::fmt::Write;

/// The parameter table every method prints: name, value, 1σ, unit (the
/// layout of [`TriadFit::summary`](crate::calib::TriadFit::summary)).
pub fn params_table(params: &[ParamEstimate]) -> String {
    let mut s = String::from("parameter        value          1σ            unit\n");
    for p in params {
        let _ = writeln!(
            s,
            "{:10} {:>14.6e} {:>12.3e}   {}",
            p.name, p.value, p.sigma, p.unit
        );
    }
    s
}

/// What `clino calibrate` prints for a calibration (before "wrote FILE").
pub fn calibration(c: &Calibration) -> String {
    match &c.outcome {
        Outcome::SixPosition { statics, six, .. } => {
            let used: usize = six.poses.iter().map(Vec::len).sum();
            format!(
                "{}\nsix-position method: M = K⁻¹ and u0 from {used} poses (+x −x +y −y +z −z)\n{}",
                statics.table(),
                params_table(&six.params)
            )
        }
        Outcome::AccelFit { statics, fit } => format!("{}\n{}", statics.table(), fit.summary()),
        Outcome::MagFit { fit } | Outcome::RateTable { fit } => fit.summary(),
        Outcome::Rotations {
            statics,
            rotations: r,
        } => format!(
            "{}\ngyro from rotations: rms gravity-direction mismatch {:.4}° before, {:.4}° after\nbias {:?} rad/s\n{}",
            statics.table(),
            r.rms_before_deg,
            r.rms_after_deg,
            r.bias,
            r.params
                .iter()
                .map(|p| format!("{} = {:.6} ± {:.2e}\n", p.name, p.value, p.sigma))
                .collect::<String>()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameter_rows_carry_value_and_sigma() {
        let p = [ParamEstimate {
            name: "M_xy".into(),
            value: 0.0125,
            sigma: 3.5e-4,
            unit: "1 (SI per raw)".into(),
        }];
        assert_eq!(
            params_table(&p),
            "parameter        value          1σ            unit\nM_xy          1.250000e-2     3.500e-4   1 (SI per raw)\n"
        );
    }
}
