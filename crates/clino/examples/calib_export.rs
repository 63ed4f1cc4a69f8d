//! Write simulated calibration data to CSV files, for trying `clino calibrate`
//! and for the comparison scripts in `scripts/`.
//!
//! `cargo run -p clino --example calib_export -- OUT_DIR` writes:
//! * `accel_poses.csv` — a continuous recording through 84 poses (`synth::calibration_schedule`), 25–80 °C, with
//!   `temp_c` and `ref_inclination_deg` (raw readings of the default poorly
//!   calibrated IMU of `clino::sim::calib`);
//! * `accel_nominal.csv` — the same IMU through 26 poses at 29–31 °C;
//! * `ferraris/*.csv` — the sections of a Ferraris calibration (six static
//!   positions, three 360° rotations) at 29–31 °C, one file per section;
//! * `validation.csv` — 300 check poses: raw reading, temperature, true specific force;
//! * `stations.csv` — survey stations of a build-and-hold well with roll tests;
//! * `stations_truth.csv` — the inclination/azimuth/toolface the stations were made from.
use clino::calib::validation_set;
use clino::core::{Attitude, Vec3};
use clino::sim::calib::{self as synth, SynthOptions};
use std::io::Write;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "calib_data".into());
    let dir = Path::new(&dir);
    std::fs::create_dir_all(dir.join("ferraris"))?;
    let opt = SynthOptions::default();
    let rec = synth::recording(&opt, &synth::calibration_schedule()).recording();
    rec.write_csv(std::fs::File::create(dir.join("accel_poses.csv"))?)?;

    let nominal = SynthOptions {
        temp_range_c: [29.0, 31.0],
        ..opt.clone()
    };
    let rec = synth::recording(
        &nominal,
        &synth::attitudes_from_ups(&synth::cube_directions()),
    )
    .recording();
    rec.write_csv(std::fs::File::create(dir.join("accel_nominal.csv"))?)?;

    // Ferraris sections: static ±x, ±y, ±z up; rotations of 360° about x, y, z
    let st = |u: Vec3| synth::attitudes_from_ups(&[u])[0];
    let sections: [(&str, Vec<Attitude>); 6] = [
        ("x_p", vec![st(Vec3::x())]),
        ("x_a", vec![st(-Vec3::x())]),
        ("y_p", vec![st(Vec3::y())]),
        ("y_a", vec![st(-Vec3::y())]),
        ("z_p", vec![st(Vec3::z())]),
        ("z_a", vec![st(-Vec3::z())]),
    ];
    let static_opt = SynthOptions {
        static_s: 5.0,
        rate_hz: 100.0,
        ..nominal.clone()
    };
    for (name, att) in &sections {
        let r = synth::recording(&static_opt, att).recording();
        r.write_csv(std::fs::File::create(
            dir.join("ferraris").join(format!("{name}.csv")),
        )?)?;
    }
    for (name, axis) in [
        ("x_rot", Vec3::x_axis()),
        ("y_rot", Vec3::y_axis()),
        ("z_rot", Vec3::z_axis()),
    ] {
        // Ferraris: turn about the vertical axis in the axis-up position
        let start = st(axis.into_inner());
        let steps: Vec<Attitude> = (0..=4)
            .map(|k| {
                start * Attitude::from_axis_angle(&axis, k as f64 * std::f64::consts::FRAC_PI_2)
            })
            .collect();
        let rot_opt = SynthOptions {
            static_s: 0.02,
            move_s: 1.5,
            rate_hz: 100.0,
            ..nominal.clone()
        };
        let r = synth::recording(&rot_opt, &steps).recording();
        r.write_csv(std::fs::File::create(
            dir.join("ferraris").join(format!("{name}.csv")),
        )?)?;
    }

    let mut w = std::fs::File::create(dir.join("validation.csv"))?;
    writeln!(
        w,
        "acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,temp_c,true_x_m_s2,true_y_m_s2,true_z_m_s2"
    )?;
    for (raw, t, f) in validation_set(&opt, 300, 5) {
        writeln!(
            w,
            "{},{},{},{},{},{},{}",
            raw.x, raw.y, raw.z, t, f.x, f.y, f.z
        )?;
    }

    // survey stations: vertical to 300 m, build 3°/30 m to 60° at azimuth 75°, hold; roll test at 990 m
    let mut st_csv = std::fs::File::create(dir.join("stations.csv"))?;
    let mut truth = std::fs::File::create(dir.join("stations_truth.csv"))?;
    writeln!(
        st_csv,
        "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT"
    )?;
    writeln!(truth, "md_m,inclination_deg,azimuth_deg,toolface_deg")?;
    let mut k = 0;
    let mut md: f64 = 0.0;
    while md <= 1500.0 {
        let inc: f64 = if md <= 300.0 {
            0.0
        } else {
            ((md - 300.0) / 30.0 * 3.0).min(60.0)
        };
        let azi: f64 = if inc == 0.0 {
            0.0
        } else {
            75.0 + 10.0 * ((md - 300.0) / 600.0).min(1.0)
        };
        let rolls = if (md - 990.0).abs() < 1e-9 { 12 } else { 1 };
        for r in 0..rolls {
            let tf = (k as f64 * 37.0 + r as f64 * 30.0) % 360.0;
            let c = nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), azi.to_radians())
                * nalgebra::Rotation3::from_axis_angle(&Vec3::y_axis(), inc.to_radians())
                * nalgebra::Rotation3::from_axis_angle(&Vec3::z_axis(), tf.to_radians());
            let f = -(c.transpose() * Vec3::new(0.0, 0.0, clino::core::G0));
            let h = c.transpose() * Vec3::new(20.0 * 1.0, 0.0, 45.0);
            writeln!(
                st_csv,
                "{md},{},{},{},{},{},{}",
                f.x, f.y, f.z, h.x, h.y, h.z
            )?;
            writeln!(truth, "{md},{inc},{azi},{tf}")?;
        }
        k += 1;
        md += 30.0;
    }
    eprintln!("wrote simulated data to {}", dir.display());
    Ok(())
}
