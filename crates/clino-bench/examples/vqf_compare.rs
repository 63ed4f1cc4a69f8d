//! Side-by-side accuracy of clino's `dynamic` filter (real time and offline)
//! and VQF (the pure-Rust `vqf-rs` port, real time, 6-D) on BROAD-format
//! recordings and on the simulated slewing excavator, scored as `clino eval`
//! scores. PyPI `vqf` (and its offline variant) is scored by
//! `scripts/vqf_baseline.py` on the same files.
//!
//! ```text
//! cargo run --release -p clino-bench --example vqf_compare -- ../shared/data/broad
//! ```

use clino::core::{Attitude, ImuSample, Vec3};
use clino::eval::inclination_error;
use clino::fusion::{FilterConfig, FilterKind};
use clino::io::{ImuCsvReader, ReadOptions};
use clino::sim::Motion;
use clino::sim::slewing::{self, SlewingPlatform};
use std::path::PathBuf;

struct Rec {
    samples: Vec<ImuSample>,
    t: Vec<f64>,
    gyr: Vec<Vec3>,
    acc: Vec<Vec3>,
    refq: Vec<Option<Attitude>>,
    mov: Vec<bool>,
}

fn load(path: &PathBuf) -> clino::Result<Rec> {
    let mut r = ImuCsvReader::from_path(path, &ReadOptions::default())?;
    let mut rec = Rec {
        samples: vec![],
        t: vec![],
        gyr: vec![],
        acc: vec![],
        refq: vec![],
        mov: vec![],
    };
    while let Some(row) = r.next_row()? {
        rec.samples.push(row.sample);
        rec.t.push(row.sample.t_s);
        rec.gyr.push(row.sample.gyr_rad_s);
        rec.acc.push(row.sample.acc_m_s2);
        rec.refq.push(row.ref_q);
        rec.mov.push(row.movement.unwrap_or(false));
    }
    Ok(rec)
}

fn rmse(rec: &Rec, est: &[Attitude]) -> f64 {
    let (mut s, mut n) = (0.0, 0usize);
    for (k, est) in est.iter().enumerate() {
        if let (true, Some(q)) = (rec.mov[k], rec.refq[k]) {
            let e = inclination_error(est, &q);
            s += e * e;
            n += 1;
        }
    }
    (s / n.max(1) as f64).sqrt().to_degrees()
}

fn dts(t: &[f64]) -> Vec<f64> {
    (0..t.len())
        .map(|k| {
            if k == 0 {
                if t.len() > 1 { t[1] - t[0] } else { 0.01 }
            } else {
                t[k] - t[k - 1]
            }
        })
        .collect()
}

fn run_vqf(gyr: &[Vec3], acc: &[Vec3], ts: f64) -> Vec<Attitude> {
    let mut v = vqf_rs::VQF::new(ts, None, None, None);
    gyr.iter()
        .zip(acc)
        .map(|(g, a)| {
            v.update([g.x, g.y, g.z], [a.x, a.y, a.z], None);
            let q = v.quat_6d();
            Attitude::from_quaternion(nalgebra::Quaternion::new(q.0, q.1, q.2, q.3))
        })
        .collect()
}

/// `dynamic` as `clino fuse` and `clino eval` run it: through the one
/// pipeline (real time) or the offline smoother, defaults of `config`.
fn run_clino(config: &FilterConfig, samples: &[ImuSample]) -> clino::Result<Vec<Attitude>> {
    let or_identity = |q: Option<Attitude>| q.unwrap_or_else(Attitude::identity);
    if config.offline {
        return Ok(config
            .smooth_samples(samples)?
            .into_iter()
            .map(or_identity)
            .collect());
    }
    let mut p = config.pipeline()?;
    Ok(samples
        .iter()
        .map(|s| or_identity(p.update(s).attitude))
        .collect())
}

fn main() -> clino::Result<()> {
    let args: Vec<PathBuf> = std::env::args().skip(1).map(PathBuf::from).collect();
    // no argument: the slewing part alone
    let paths = if args.is_empty() {
        Vec::new()
    } else {
        clino::eval::expand_paths(&args)?
    };
    if !paths.is_empty() {
        println!(
            "{:<48}{:>10}{:>10}{:>10}{:>12}",
            "recording", "vqf-rs", "dynamic", "ratio", "offline"
        );
        let (mut sv, mut sd, mut so, mut worst) = (0.0, 0.0, 0.0, 0.0f64);
        let realtime = FilterConfig::new(FilterKind::Dynamic);
        let offline = realtime.with_offline(true);
        for p in &paths {
            let rec = load(p)?;
            let dt = dts(&rec.t);
            let ts = {
                let mut d = dt.clone();
                d.sort_by(|a, b| a.total_cmp(b));
                d[d.len() / 2]
            };
            let v = rmse(&rec, &run_vqf(&rec.gyr, &rec.acc, ts));
            let d = rmse(&rec, &run_clino(&realtime, &rec.samples)?);
            let o = rmse(&rec, &run_clino(&offline, &rec.samples)?);
            worst = worst.max(d / v);
            sv += v;
            sd += d;
            so += o;
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().to_string())
                .unwrap_or_default();
            println!("{name:<48}{v:>10.3}{d:>10.3}{:>10.2}{o:>12.3}", d / v);
        }
        let n = paths.len() as f64;
        println!(
            "{:<48}{:>10.3}{:>10.3}{:>10}{:>12.3}",
            "MEAN",
            sv / n,
            sd / n,
            "",
            so / n
        );
        println!("worst per-recording ratio dynamic/vqf-rs: {worst:.2}");
    }
    // the slewing excavator: same recording for every filter
    let m = SlewingPlatform::default();
    let model = slewing::sensor();
    let rate = 200.0;
    let samples = model.simulate(&m, rate, 100.0, 1);
    let truth: Vec<Attitude> = samples.iter().map(|s| m.truth(s.t_s).attitude).collect();
    let gyr: Vec<Vec3> = samples.iter().map(|s| s.gyr_rad_s).collect();
    let acc: Vec<Vec3> = samples.iter().map(|s| s.acc_m_s2).collect();
    let score = |est: &[Attitude]| {
        let (mut s, mut n) = (0.0, 0usize);
        for (k, q) in est.iter().enumerate() {
            if samples[k].t_s > m.initial_rest_s {
                s += inclination_error(q, &truth[k]).powi(2);
                n += 1;
            }
        }
        (s / n as f64).sqrt().to_degrees()
    };
    let v = score(&run_vqf(&gyr, &acc, 1.0 / rate));
    let plain = FilterConfig::new(FilterKind::Dynamic);
    let lever = plain.with_lever_arm(Some(m.lever_arm_m));
    let d = score(&run_clino(&plain, &samples)?);
    let dc = score(&run_clino(&lever, &samples)?);
    let no_bias = lever.with_accel_bias(false);
    let dn = score(&run_clino(&no_bias, &samples)?);
    let oc = score(&run_clino(&lever.with_offline(true), &samples)?);
    println!(
        "\nslewing excavator ({}, 200 Hz, 100 s), inclination RMSE after the initial rest:",
        model.name
    );
    println!("  vqf-rs                      {v:.3}°");
    println!("  dynamic, uncompensated      {d:.3}°");
    println!(
        "  dynamic, --lever-arm (as clino fuse: bias estimated) {dc:.3}°   ({:.0}× lower than uncompensated, {:.0}× lower than VQF)",
        d / dc,
        v / dc
    );
    println!("    without the online accelerometer-bias estimate: {dn:.3}°");
    println!("  dynamic --offline --lever-arm {oc:.3}°");
    Ok(())
}
