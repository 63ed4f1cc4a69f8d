//! Accuracy of our Madgwick and Mahony against the `ahrs` crate's (0.8) at the
//! same gains, on the BROAD trials, scored with the BROAD inclination error.
//!
//! `cargo run --release -p clino-bench --example ahrs_compare [-- DIR] [--beta B --kp KP --ki KI]`
//!
//! Both sides start from the same attitude (tilt from the first accelerometer
//! sample, heading 0) and use the same fixed sample period. Differences left:
//! ours takes dt from the time stamps (BROAD's are uniform, so none here) and
//! holds its state through NaN samples (BROAD has none).

use std::path::PathBuf;

use ahrs::Ahrs;
use clino::core::filter::{Madgwick, Mahony};
use clino::core::{Attitude, AttitudeFilter, tilt};
use clino::eval::{Rms, expand_paths, inclination_error};
use clino::io::{ImuCsvReader, ReadOptions};

/// BROAD's sample period, s (285.714286 Hz).
const PERIOD: f64 = 1.0 / 285.714_286;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut take = |flag: &str, default: f64| -> f64 {
        match args.iter().position(|a| a == flag) {
            Some(i) => {
                let v = args[i + 1].parse().expect("number");
                args.drain(i..=i + 1);
                v
            }
            None => default,
        }
    };
    let beta = take("--beta", 0.1);
    let kp = take("--kp", 1.0);
    let ki = take("--ki", 0.02);
    let dir = args
        .first()
        .map(PathBuf::from)
        .or_else(clino_bench::broad_dir)
        .ok_or("no BROAD recordings: give their folder, or set CLINO_BROAD_DIR")?;
    let files = expand_paths(&[dir])?;
    println!("inclination RMSE, degrees; Madgwick beta = {beta}, Mahony kp = {kp}, ki = {ki}");
    println!(
        "{:<46} {:>9} {:>13} {:>9} {:>13}",
        "recording", "madgwick", "ahrs_madgwick", "mahony", "ahrs_mahony"
    );
    let mut sums = [0.0; 4];
    let mut max_q_diff = [0.0f64; 2];
    for f in &files {
        let mut r = ImuCsvReader::from_path(f, &ReadOptions::default())?;
        let mut ours_md = Madgwick::new(beta);
        let mut ours_mh = Mahony::new(kp, ki);
        let mut theirs_md: Option<ahrs::Madgwick<f64>> = None;
        let mut theirs_mh: Option<ahrs::Mahony<f64>> = None;
        let mut rms = [Rms::default(); 4];
        let mut last_t: Option<f64> = None;
        while let Some(row) = r.next_row()? {
            let s = row.sample;
            if row.has_dropout() {
                continue;
            }
            let dt = last_t.map_or(f64::MIN_POSITIVE, |t0| s.t_s - t0);
            last_t = Some(s.t_s);
            ours_md.update(s.gyr_rad_s, s.acc_m_s2, dt);
            ours_mh.update(s.gyr_rad_s, s.acc_m_s2, dt);
            match (&mut theirs_md, &mut theirs_mh) {
                (Some(md), Some(mh)) => {
                    // ahrs integrates with the fixed period set at construction;
                    // ours with the time-stamp difference: check they agree.
                    assert!(
                        (dt - PERIOD).abs() < 1e-6,
                        "{}: non-uniform step {dt} s",
                        f.display()
                    );
                    let _ = md.update_imu(&s.gyr_rad_s, &s.acc_m_s2);
                    let _ = mh.update_imu(&s.gyr_rad_s, &s.acc_m_s2);
                }
                _ => {
                    let q0 = tilt::attitude_from_up(&s.acc_m_s2).unwrap_or_else(Attitude::identity);
                    theirs_md = Some(ahrs::Madgwick::new_with_quat(PERIOD, beta, q0));
                    theirs_mh = Some(ahrs::Mahony::new_with_quat(PERIOD, kp, ki, q0));
                }
            }
            let (md, mh) = (theirs_md.as_ref().unwrap(), theirs_mh.as_ref().unwrap());
            max_q_diff[0] = max_q_diff[0].max(ours_md.attitude().angle_to(&md.quat));
            max_q_diff[1] = max_q_diff[1].max(ours_mh.attitude().angle_to(&mh.quat));
            if let (Some(true), Some(q_ref)) = (row.movement, row.ref_q) {
                for (k, q) in [ours_md.attitude(), md.quat, ours_mh.attitude(), mh.quat]
                    .iter()
                    .enumerate()
                {
                    rms[k].push(inclination_error(q, &q_ref));
                }
            }
        }
        let v: Vec<f64> = rms.iter().map(|r| r.value().to_degrees()).collect();
        for k in 0..4 {
            sums[k] += v[k];
        }
        let name = f.file_stem().unwrap().to_string_lossy();
        println!(
            "{name:<46} {:>9.3} {:>13.3} {:>9.3} {:>13.3}",
            v[0], v[1], v[2], v[3]
        );
    }
    let n = files.len() as f64;
    println!(
        "{:<46} {:>9.3} {:>13.3} {:>9.3} {:>13.3}",
        "mean",
        sums[0] / n,
        sums[1] / n,
        sums[2] / n,
        sums[3] / n
    );
    println!(
        "largest attitude difference ours vs ahrs over all samples: madgwick {:.2e} rad, mahony {:.2e} rad",
        max_q_diff[0], max_q_diff[1]
    );
    Ok(())
}
