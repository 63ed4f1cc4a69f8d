//! Lab recordings for the test bench (CSV with a header row).
//!
//! Columns are found by header name; units are in the names:
//!
//! | quantity | columns |
//! |---|---|
//! | time (required, increasing) | `t_s` |
//! | gyro | `gyr_x_rad_s`, `gyr_y_rad_s`, `gyr_z_rad_s` or `gyr_x_deg_s` … |
//! | accelerometer | `acc_x_m_s2` … or `acc_x_g` … |
//! | inclinometer attitude | `q_w, q_x, q_y, q_z` (body → ENU) or `phi_deg, theta_deg` (z-x-y set) or `roll_deg, pitch_deg` (aerospace z-y-x) |
//! | platform encoders | `leg1_m` … `leg6_m` (forward kinematics gives the actual pose) |
//! | reference attitude | `ref_q_w, ref_q_x, ref_q_y, ref_q_z` |
//! | reference position | `ref_x_m, ref_y_m, ref_z_m` |
//!
//! Every cell must parse as a finite number; an error names the file, line and
//! column. Nothing is dropped silently.

use super::conical::{Channels, ConicalPoint, analyze_conical};
use super::orbit::{OrbitPoint, cross_coupling_against};
use super::sinefit::fit4;
use crate::io::TableReader;
use crate::sim::platform::PlatformMotion;
use crate::sim::stewart::{Geometry, Pose, ServoLegs};
use crate::{Error, ErrorKind, Result};
use clino_core::tilt::{QuatTilt, RollPitch, ZxyTilt, attitude_from_up};
use clino_core::{Attitude, G0, ImuSample, Vec3};
use nalgebra::Quaternion;
use serde::Serialize;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A CSV table of numeric columns with its source file.
#[derive(Clone, Debug)]
pub struct Table {
    /// File it was read from.
    pub path: PathBuf,
    /// Column names in file order.
    pub names: Vec<String>,
    columns: HashMap<String, Vec<f64>>,
}

/// Columns that only mean something together: a file has all of a group or none.
const COLUMN_GROUPS: [&[&str]; 5] = [
    &["q_w", "q_x", "q_y", "q_z"],
    &["ref_q_w", "ref_q_x", "ref_q_y", "ref_q_z"],
    &["phi_deg", "theta_deg"],
    &["roll_deg", "pitch_deg"],
    &["leg1_m", "leg2_m", "leg3_m", "leg4_m", "leg5_m", "leg6_m"],
];

impl Table {
    /// Read `path` ([`TableReader`]'s rules): a header row, then numeric rows;
    /// `t_s` must be present and increasing.
    pub fn read(path: &Path) -> Result<Self> {
        Self::from_table(TableReader::open(path)?)
    }

    /// Parse CSV text from `reader`, naming `path` in errors.
    pub fn from_reader<R: std::io::Read>(reader: R, path: &Path) -> Result<Self> {
        Self::from_table(TableReader::new(reader, path)?)
    }

    /// Read every column of a table whose header has been read (every cell a
    /// finite number).
    pub fn from_table<R: std::io::Read>(mut tb: TableReader<R>) -> Result<Self> {
        let names: Vec<String> = tb.header().to_vec();
        let t = tb
            .find(&["t_s"])
            .ok_or_else(|| tb.missing("t_s", "time column is required"))?;
        // a group of columns that only means something whole (a quaternion,
        // a tilt pair, the six legs) is all there or not at all
        for group in COLUMN_GROUPS {
            let have: Vec<&str> = group
                .iter()
                .copied()
                .filter(|c| tb.find(&[c]).is_some())
                .collect();
            if let Some(missing) = group.iter().find(|c| tb.find(&[c]).is_none())
                && !have.is_empty()
            {
                return Err(tb.missing(
                    missing,
                    &format!(
                        "{} {} there but {missing} is missing: these columns go together ({})",
                        have.join(", "),
                        if have.len() == 1 { "is" } else { "are" },
                        group.join(", ")
                    ),
                ));
            }
        }
        let mut cols: Vec<Vec<f64>> = vec![Vec::new(); names.len()];
        while tb.next_record()? {
            for (j, c) in cols.iter_mut().enumerate() {
                c.push(tb.finite(j)?);
            }
            let tc = &cols[t];
            if let [.., a, b] = tc[..]
                && !super::allan::increasing(a, b)
            {
                return Err(tb.err_at(
                    t,
                    ErrorKind::TimeNotIncreasing,
                    format!("time {b} s does not increase (previous row {a} s)"),
                ));
            }
        }
        let columns: HashMap<String, Vec<f64>> = names.iter().cloned().zip(cols).collect();
        Ok(Self {
            path: tb.file().to_path_buf(),
            names,
            columns,
        })
    }

    /// A column by name.
    pub fn col(&self, name: &str) -> Option<&[f64]> {
        self_col(&self.columns, name)
    }

    /// A required column, or a `MissingColumn` error naming it.
    pub fn req(&self, name: &str) -> Result<&[f64]> {
        self.col(name).ok_or_else(|| {
            Error::new(ErrorKind::MissingColumn, "column is required here")
                .in_file(&self.path)
                .at_column(name)
        })
    }

    /// Time stamps, s.
    pub fn t(&self) -> &[f64] {
        self.col("t_s").unwrap_or(&[])
    }

    /// Rows.
    pub fn len(&self) -> usize {
        self.t().len()
    }

    /// True when there are no rows (never, after [`Table::read`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// One axis given in either of two units: the column `a` as is, or `b` times `scale`.
    fn either(&self, a: &str, b: &str, scale: f64) -> Option<Vec<f64>> {
        self.col(a)
            .map(<[f64]>::to_vec)
            .or_else(|| self.col(b).map(|v| v.iter().map(|x| x * scale).collect()))
    }

    /// IMU samples (gyro and accelerometer, all three axes required).
    pub fn imu_samples(&self) -> Result<Vec<ImuSample>> {
        let mut axes = Vec::new();
        for a in ["x", "y", "z"] {
            axes.push(
                self.either(
                    &format!("gyr_{a}_rad_s"),
                    &format!("gyr_{a}_deg_s"),
                    1f64.to_radians(),
                )
                .ok_or_else(|| self.missing(&format!("gyr_{a}_rad_s")))?,
            );
        }
        for a in ["x", "y", "z"] {
            axes.push(
                self.either(&format!("acc_{a}_m_s2"), &format!("acc_{a}_g"), G0)
                    .ok_or_else(|| self.missing(&format!("acc_{a}_m_s2")))?,
            );
        }
        let t = self.t();
        Ok((0..t.len())
            .map(|i| {
                ImuSample::new(
                    t[i],
                    Vec3::new(axes[0][i], axes[1][i], axes[2][i]),
                    Vec3::new(axes[3][i], axes[4][i], axes[5][i]),
                )
            })
            .collect())
    }

    fn missing(&self, name: &str) -> Error {
        Error::new(ErrorKind::MissingColumn, "column is required here")
            .in_file(&self.path)
            .at_column(name)
    }

    /// The inclinometer's attitude output, if any of the accepted column sets is present.
    pub fn attitude(&self) -> Option<Vec<Attitude>> {
        let n = self.len();
        if let (Some(w), Some(x), Some(y), Some(z)) = (
            self.col("q_w"),
            self.col("q_x"),
            self.col("q_y"),
            self.col("q_z"),
        ) {
            return Some(
                (0..n)
                    .map(|i| Attitude::from_quaternion(Quaternion::new(w[i], x[i], y[i], z[i])))
                    .collect(),
            );
        }
        let up = |u: Vec3| attitude_from_up(&u).unwrap_or_else(Attitude::identity);
        if let (Some(p), Some(t)) = (self.col("phi_deg"), self.col("theta_deg")) {
            return Some(
                (0..n)
                    .map(|i| {
                        up(ZxyTilt {
                            phi: p[i].to_radians(),
                            theta: t[i].to_radians(),
                        }
                        .up())
                    })
                    .collect(),
            );
        }
        if let (Some(r), Some(p)) = (self.col("roll_deg"), self.col("pitch_deg")) {
            return Some(
                (0..n)
                    .map(|i| {
                        up(RollPitch {
                            roll: r[i].to_radians(),
                            pitch: p[i].to_radians(),
                        }
                        .up())
                    })
                    .collect(),
            );
        }
        None
    }

    /// Inclinometer channels (whatever the file has).
    pub fn channels(&self) -> Channels {
        Channels {
            t_s: self.t().to_vec(),
            gyr_x: self.either("gyr_x_rad_s", "gyr_x_deg_s", 1f64.to_radians()),
            gyr_y: self.either("gyr_y_rad_s", "gyr_y_deg_s", 1f64.to_radians()),
            gyr_z: self.either("gyr_z_rad_s", "gyr_z_deg_s", 1f64.to_radians()),
            acc_x: self.either("acc_x_m_s2", "acc_x_g", G0),
            acc_y: self.either("acc_y_m_s2", "acc_y_g", G0),
            attitude: self.attitude(),
        }
    }

    /// The platform's reference pose per row: from the encoder legs by forward
    /// kinematics (warm-started row to row; returns the largest iteration count
    /// too), or from `ref_q_*` and `ref_*_m` columns.
    pub fn reference(&self, geometry: &Geometry) -> Result<(Vec<Pose>, Option<usize>)> {
        let legs: Vec<Option<&[f64]>> = (1..=6).map(|i| self.col(&format!("leg{i}_m"))).collect();
        if legs.iter().all(Option::is_some) {
            let legs: Vec<&[f64]> = legs.into_iter().flatten().collect();
            let mut guess = geometry.home();
            let mut out = Vec::with_capacity(self.len());
            let mut max_it = 0;
            for (i, _) in self.t().iter().enumerate() {
                let l: [f64; 6] = core::array::from_fn(|k| legs[k][i]);
                let fk = geometry.forward(&l, &guess).map_err(|e| {
                    e.in_file(&self.path)
                        .at_line(i as u64 + 2)
                        .at_column("leg1_m…leg6_m")
                })?;
                max_it = max_it.max(fk.iterations);
                guess = fk.pose;
                out.push(fk.pose);
            }
            return Ok((out, Some(max_it)));
        }
        let (w, x, y, z) = (
            self.col("ref_q_w"),
            self.col("ref_q_x"),
            self.col("ref_q_y"),
            self.col("ref_q_z"),
        );
        let (Some(w), Some(x), Some(y), Some(z)) = (w, x, y, z) else {
            return Err(Error::new(
                ErrorKind::MissingColumn,
                "a reference is required: leg1_m…leg6_m (encoders) or ref_q_w, ref_q_x, ref_q_y, ref_q_z",
            )
            .in_file(&self.path)
            .at_column("leg1_m"));
        };
        let zero = vec![0.0; self.len()];
        let px = self.col("ref_x_m").unwrap_or(&zero);
        let py = self.col("ref_y_m").unwrap_or(&zero);
        let pz = self.col("ref_z_m").unwrap_or(&zero);
        Ok((
            (0..self.len())
                .map(|i| Pose {
                    pos_m: Vec3::new(px[i], py[i], pz[i]),
                    attitude: Attitude::from_quaternion(Quaternion::new(w[i], x[i], y[i], z[i])),
                })
                .collect(),
            None,
        ))
    }
}

fn self_col<'a>(m: &'a HashMap<String, Vec<f64>>, name: &str) -> Option<&'a [f64]> {
    m.get(name).map(Vec::as_slice)
}

/// What the platform did during a recording.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Excitation {
    /// Conical motion about z (frequency response).
    Conical,
    /// Positional orbit (cross-coupling).
    Orbit,
}

/// Smallest cone angle [`analyze`] accepts as a conical excitation, degrees:
/// ten times the parasitic orientation the source's platform shows under an
/// orbit (< 0.005°, its figure 10b).
pub const MIN_CONE_ANGLE_DEG: f64 = 0.05;
/// Smallest orbit amplitude [`analyze`] accepts as an orbit excitation, mm:
/// about ten times the parasitic position the source's platform shows under
/// a cone (< 0.017 mm, its figure 7a).
pub const MIN_ORBIT_AMPLITUDE_MM: f64 = 0.2;
/// Largest tilt of the platform (half its peak-to-peak, degrees) [`analyze`]
/// accepts under an orbit excitation, a pure translation: twenty times the
/// source's parasitic orientation (< 0.005°). A record that tilts more is a
/// cone or another rotation, whatever its position does.
pub const MAX_ORBIT_TILT_DEG: f64 = 0.1;
/// Smallest ratio of the fitted sine's RMS (A/√2) to the residual's RMS for
/// the reference to count as excited at the fitted frequency.
pub const MIN_REFERENCE_SNR: f64 = 2.0;

/// Half the peak-to-peak, the crudest amplitude (for the hint in errors).
fn half_range(v: impl Iterator<Item = f64>) -> f64 {
    let (lo, hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if hi >= lo { 0.5 * (hi - lo) } else { 0.0 }
}

/// How much the reference moves over the rows `keep`: half the peak-to-peak
/// of the position (largest axis, mm) and of the tilt (largest of the cone
/// angles read from the quaternion x and y components, degrees).
fn reference_motion(reference: &[Pose], keep: &[usize]) -> (f64, f64) {
    let pos_mm = 1e3
        * (0..3)
            .map(|k| half_range(keep.iter().map(|&i| reference[i].pos_m[k])))
            .fold(0.0, f64::max);
    let tilt_deg = [0usize, 1]
        .iter()
        .map(|&k| {
            let h = half_range(keep.iter().map(|&i| {
                let q = QuatTilt::from_attitude(&reference[i].attitude);
                if k == 0 { q.x } else { q.y }
            }));
            2.0 * h.min(1.0).asin().to_degrees()
        })
        .fold(0.0, f64::max);
    (pos_mm, tilt_deg)
}

/// The error for a record whose reference does not show `excitation`, with
/// what the reference does show.
fn not_excited(
    table: &Table,
    excitation: Excitation,
    reference: &[Pose],
    keep: &[usize],
    why: String,
) -> Error {
    let (pos_mm, tilt_deg) = reference_motion(reference, keep);
    let (name, other) = match excitation {
        Excitation::Conical => ("conical", "orbit"),
        Excitation::Orbit => ("orbit", "conical"),
    };
    Error::new(
        ErrorKind::InvalidInput,
        format!(
            "the reference shows no {name} excitation: {why}; over the analysed rows it moves by ±{pos_mm:.3} mm in position and ±{tilt_deg:.3}° in tilt (half the peak-to-peak) — is --excitation {other} meant?"
        ),
    )
    .in_file(&table.path)
}

/// Check that a four-parameter fit of the reference found a real excitation:
/// an amplitude above `min` (in the fit's units) and a sine that stands out
/// of the residual by [`MIN_REFERENCE_SNR`].
fn excited(fit: &super::sinefit::SineFit, min: f64, unit: &str, scale: f64) -> Result<(), String> {
    let snr = fit.amplitude / std::f64::consts::SQRT_2 / fit.rms_residual.max(f64::MIN_POSITIVE);
    // NaN-safe: a NaN amplitude or ratio fails both checks
    if fit.amplitude.is_nan() || fit.amplitude * scale < min {
        Err(format!(
            "fitted amplitude {:.3e} {unit} at {:.4} Hz is below {min} {unit}",
            fit.amplitude * scale,
            fit.freq_hz
        ))
    } else if snr.is_nan() || snr < MIN_REFERENCE_SNR {
        Err(format!(
            "the sine fitted at {:.4} Hz ({:.3e} {unit}) does not stand out of the residual (signal-to-residual RMS ratio {snr:.2}, below {MIN_REFERENCE_SNR})",
            fit.freq_hz,
            fit.amplitude * scale
        ))
    } else {
        Ok(())
    }
}

/// Result of analysing a lab recording.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Analysis {
    /// Reference frequency found by the four-parameter fit, Hz.
    pub freq_hz: f64,
    /// Reference amplitude: cone angle (degrees) or orbit x amplitude (mm).
    pub reference_amplitude: f64,
    /// Largest forward-kinematics iteration count, when encoders were used.
    pub fk_max_iterations: Option<usize>,
    /// Frequency response (conical excitation).
    pub conical: Option<ConicalPoint>,
    /// Cross-coupling (orbit excitation).
    pub orbit: Option<OrbitPoint>,
}

/// Analyse a lab recording: find the excitation's frequency and amplitude from
/// the platform reference (four-parameter fits), then the inclinometer's
/// sensitivities (conical) or cross-coupling (orbit). `freq_hz` overrides the
/// fitted frequency; `skip_s` drops the start of the record. Every error
/// names the table's file.
pub fn analyze(
    table: &Table,
    excitation: Excitation,
    geometry: &Geometry,
    freq_hz: Option<f64>,
    skip_s: f64,
) -> Result<Analysis> {
    analyze_table(table, excitation, geometry, freq_hz, skip_s)
        .map_err(|e| e.or_in_file(&table.path))
}

fn analyze_table(
    table: &Table,
    excitation: Excitation,
    geometry: &Geometry,
    freq_hz: Option<f64>,
    skip_s: f64,
) -> Result<Analysis> {
    let (reference, fk_it) = table.reference(geometry)?;
    let t0 = table.t()[0] + skip_s;
    let keep: Vec<usize> = (0..table.len()).filter(|&i| table.t()[i] >= t0).collect();
    if keep.len() < 16 {
        return Err(Error::new(
            ErrorKind::Empty,
            "fewer than 16 rows after the skipped start",
        )
        .in_file(&table.path));
    }
    let t: Vec<f64> = keep.iter().map(|&i| table.t()[i]).collect();
    let ch = table.channels();
    let ch = ch.window(t0, f64::INFINITY);
    match excitation {
        Excitation::Conical => {
            let qx: Vec<f64> = keep
                .iter()
                .map(|&i| QuatTilt::from_attitude(&reference[i].attitude).x)
                .collect();
            let qy: Vec<f64> = keep
                .iter()
                .map(|&i| QuatTilt::from_attitude(&reference[i].attitude).y)
                .collect();
            let fx = fit4(&t, &qx, freq_hz, 1).map_err(|e| {
                not_excited(table, excitation, &reference, &keep, e.message.to_string())
            })?;
            let f = freq_hz.unwrap_or(fx.freq_hz);
            let fy = super::sinefit::fit3(&t, &qy, f, 1)?;
            let half = 0.5 * (fx.amplitude + fy.amplitude);
            let alpha = 2.0 * half.min(1.0).asin();
            // quaternion x amplitude sin(α/2) ≈ α/2: scale to degrees of cone angle
            for fit in [&fx, &fy] {
                excited(
                    fit,
                    MIN_CONE_ANGLE_DEG,
                    "° of cone angle",
                    2f64.to_degrees(),
                )
                .map_err(|why| not_excited(table, excitation, &reference, &keep, why))?;
            }
            let point = analyze_conical(&ch, alpha, f, G0).map_err(|e| e.in_file(&table.path))?;
            Ok(Analysis {
                freq_hz: f,
                reference_amplitude: alpha.to_degrees(),
                fk_max_iterations: fk_it,
                conical: Some(point),
                orbit: None,
            })
        }
        Excitation::Orbit => {
            let px: Vec<f64> = keep.iter().map(|&i| reference[i].pos_m.x).collect();
            let fx = fit4(&t, &px, freq_hz, 1).map_err(|e| {
                not_excited(table, excitation, &reference, &keep, e.message.to_string())
            })?;
            excited(&fx, MIN_ORBIT_AMPLITUDE_MM, "mm on x", 1e3)
                .map_err(|why| not_excited(table, excitation, &reference, &keep, why))?;
            let (_, tilt) = reference_motion(&reference, &keep);
            if tilt > MAX_ORBIT_TILT_DEG {
                return Err(not_excited(
                    table,
                    excitation,
                    &reference,
                    &keep,
                    format!(
                        "the platform tilts by ±{tilt:.3}°, more than the ±{MAX_ORBIT_TILT_DEG}° an orbit (a pure translation) allows"
                    ),
                ));
            }
            let f = freq_hz.unwrap_or(fx.freq_hz);
            let att = ch.attitude.as_ref().ok_or_else(|| {
                Error::new(ErrorKind::MissingColumn, "an inclinometer attitude is required (q_*, phi_deg/theta_deg or roll_deg/pitch_deg)")
                    .in_file(&table.path)
                    .at_column("roll_deg")
            })?;
            let refs: Vec<Pose> = keep.iter().map(|&i| reference[i]).collect();
            let point = cross_coupling_against(&ch.t_s, att, &refs, f)?;
            Ok(Analysis {
                freq_hz: f,
                reference_amplitude: fx.amplitude * 1e3,
                fk_max_iterations: fk_it,
                conical: None,
                orbit: Some(point),
            })
        }
    }
}

/// Write a lab-style recording of a simulated platform run: time, IMU,
/// inclinometer quaternion and encoder legs (the format [`Table`] reads).
pub fn write_recording(
    path: &Path,
    samples: &[ImuSample],
    attitude: &[Attitude],
    legs: Option<&[[f64; 6]]>,
) -> Result<()> {
    let io = |e: std::io::Error| Error::new(ErrorKind::Io, e.to_string()).in_file(path);
    let mut w = csv::Writer::from_path(path)
        .map_err(|e| Error::new(ErrorKind::Io, e.to_string()).in_file(path))?;
    let mut head: Vec<String> = [
        "t_s",
        "gyr_x_rad_s",
        "gyr_y_rad_s",
        "gyr_z_rad_s",
        "acc_x_m_s2",
        "acc_y_m_s2",
        "acc_z_m_s2",
        "q_w",
        "q_x",
        "q_y",
        "q_z",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    if legs.is_some() {
        head.extend((1..=6).map(|i| format!("leg{i}_m")));
    }
    w.write_record(&head).map_err(|e| io(e.into()))?;
    for (i, s) in samples.iter().enumerate() {
        let q = attitude[i];
        let mut row = vec![
            s.t_s,
            s.gyr_rad_s.x,
            s.gyr_rad_s.y,
            s.gyr_rad_s.z,
            s.acc_m_s2.x,
            s.acc_m_s2.y,
            s.acc_m_s2.z,
            q.w,
            q.i,
            q.j,
            q.k,
        ];
        if let Some(l) = legs {
            row.extend_from_slice(&l[i]);
        }
        w.write_record(row.iter().map(|v| format!("{v:.12e}")))
            .map_err(|e| io(e.into()))?;
    }
    w.flush().map_err(io)
}

/// Simulate a lab recording of one test: the platform (typical geometry,
/// `servo` legs) follows the cone (angle `amplitude`, rad) or the orbit
/// (amplitude `amplitude`, m, on x, y, z, starting from rest after 1 s with a
/// two-period ramp) at `freq_hz`; the sensor model rides the platform's actual
/// motion ([`PlatformMotion`]), the named filter gives the inclinometer
/// quaternion, and the encoder legs are the actual leg lengths. Written with
/// [`write_recording`].
#[allow(clippy::too_many_arguments)]
pub fn simulate_lab_recording(
    path: &Path,
    excitation: Excitation,
    amplitude: f64,
    freq_hz: f64,
    servo: &ServoLegs,
    sensor: &crate::sim::ImuModel,
    filter: &str,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
) -> Result<()> {
    use crate::sim::motion::{Conical, Orbit};
    sensor.validate()?;
    if !(freq_hz.is_finite() && freq_hz > 0.0 && amplitude.is_finite() && amplitude > 0.0) {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("frequency {freq_hz} Hz, amplitude {amplitude}"),
        ));
    }
    let factory = super::filters::filter_factory(filter, rate_hz)?;
    let g = Geometry::typical();
    let pm = match excitation {
        Excitation::Conical => PlatformMotion::new(
            &g,
            servo,
            &Conical::about_z(amplitude, freq_hz),
            duration_s + 0.1,
        )?,
        Excitation::Orbit => {
            let m = Orbit::spatial(amplitude, freq_hz).with_start(1.0, (2.0 / freq_hz).max(1.0));
            PlatformMotion::new(&g, servo, &m, duration_s + 0.1)?
        }
    };
    let samples = sensor.simulate(&pm, rate_hz, duration_s, seed);
    let legs: Vec<[f64; 6]> = samples.iter().map(|s| pm.legs(s.t_s).0).collect();
    let att = super::filters::run_filter(&factory, &samples, rate_hz);
    write_recording(path, &samples, &att, Some(&legs))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ImuModel;

    #[test]
    fn parse_errors_name_line_and_column() {
        let p = Path::new("rec.csv");
        let e = Table::from_reader("t_s,acc_x_g\n0,1\n0.1,abc\n".as_bytes(), p).unwrap_err();
        assert_eq!(
            e.to_string(),
            "rec.csv:3: column 'acc_x_g': not a number: 'abc'"
        );
        let e = Table::from_reader("t_s,a\n0,1\n0,2\n".as_bytes(), p).unwrap_err();
        assert_eq!(e.kind, ErrorKind::TimeNotIncreasing);
        assert_eq!(e.line, Some(3));
        let e = Table::from_reader("a,b\n0,1\n".as_bytes(), p).unwrap_err();
        assert_eq!(e.kind, ErrorKind::MissingColumn);
        let e = Table::from_reader("t_s,a\n0,1\n1,NaN\n".as_bytes(), p).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput);
        let e = Table::from_reader("t_s,a\n0,1\n1\n".as_bytes(), p).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Parse);
        let t = Table::from_reader("t_s,gyr_x_deg_s\n0,1\n".as_bytes(), p).unwrap();
        assert_eq!(t.imu_samples().unwrap_err().kind, ErrorKind::MissingColumn);
    }

    #[test]
    fn analyze_a_simulated_lab_recording_with_encoders() {
        // slow legs (5 Hz, ζ = 0.5) make the actual 3 Hz cone ≈ 14 % larger than
        // commanded; the encoders' forward kinematics recovers it, so an ideal
        // sensor with exact integration reads 0 dB — the paper's method end to end
        let g = Geometry::typical();
        let servo = ServoLegs {
            natural_hz: 5.0,
            damping: 0.5,
        };
        let (f, rate) = (3.0, 200.0);
        let dir = tempfile::Builder::new()
            .prefix("clino-tb-")
            .tempdir()
            .unwrap();
        let path = dir.path().join("cone.csv");
        let m = ImuModel::ideal();
        simulate_lab_recording(
            &path,
            Excitation::Conical,
            4f64.to_radians(),
            f,
            &servo,
            &m,
            "poisson",
            rate,
            8.0,
            0,
        )
        .unwrap();
        let table = Table::read(&path).unwrap();
        let a = analyze(&table, Excitation::Conical, &g, None, 3.0).unwrap();
        assert!((a.freq_hz - f).abs() < 1e-6, "{a:?}");
        assert!(a.reference_amplitude > 4.2, "{a:?}");
        let c = a.conical.unwrap();
        for v in [
            c.gyro_x_db,
            c.gyro_y_db,
            c.accel_x_db,
            c.accel_y_db,
            c.tilt_x_db,
            c.tilt_y_db,
        ]
        .map(Option::unwrap)
        {
            assert!(v.abs() < 0.05, "{c:?}");
        }
        assert!(a.fk_max_iterations.unwrap() <= 4);
        // the cone read as an orbit: refused (it used to give amplitude 0 and numbers)
        let e = analyze(&table, Excitation::Orbit, &g, None, 3.0).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidInput);
        assert!(
            e.message.contains("no orbit excitation") && e.message.contains("conical"),
            "{e}"
        );
    }

    #[test]
    fn analyze_a_simulated_orbit_recording() {
        let dir = tempfile::Builder::new()
            .prefix("clino-tbo-")
            .tempdir()
            .unwrap();
        let path = dir.path().join("orbit.csv");
        let m = ImuModel::ideal();
        simulate_lab_recording(
            &path,
            Excitation::Orbit,
            0.02,
            0.5,
            &ServoLegs::default(),
            &m,
            "complementary:k=1",
            100.0,
            20.0,
            0,
        )
        .unwrap();
        let t = Table::read(&path).unwrap();
        let a = analyze(&t, Excitation::Orbit, &Geometry::typical(), None, 6.0).unwrap();
        assert!((a.freq_hz - 0.5).abs() < 1e-3, "{a:?}");
        assert!((a.reference_amplitude - 20.0).abs() < 0.1, "{a:?}");
        // accelerometer-only tilt: 2·(ω²·Ŝ/g) in degrees
        let expect = 2.0 * ((std::f64::consts::PI).powi(2) * 0.02 / G0).to_degrees();
        let o = a.orbit.unwrap();
        assert!(
            (o.roll_fit_pp_deg / expect - 1.0).abs() < 0.05,
            "{o:?} {expect}"
        );
        // the reference from the encoders: the orbit made, the platform's tiny tilt
        let made = o.orbit_amplitude_mm.unwrap();
        assert!(made.iter().all(|a| (a - 20.0).abs() < 0.1), "{o:?}");
        assert!(
            o.reference_tilt_pp_deg.unwrap().iter().all(|t| *t < 0.01),
            "{o:?}"
        );
        // the orbit read as a cone: refused (it used to print +127 dB)
        let e = analyze(&t, Excitation::Conical, &Geometry::typical(), None, 6.0).unwrap_err();
        assert!(
            e.message.contains("no conical excitation") && e.message.contains("orbit"),
            "{e}"
        );
    }
}
