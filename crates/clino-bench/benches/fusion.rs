//! Throughput of the attitude filters' update and of the CSV → CSV fusion run.
//!
//! `cargo bench -p clino-bench --bench fusion`
//!
//! * `update/*`: one filter update per element (M samples/s = elements/s),
//!   on the samples of a BROAD trial; ours (clino's `dynamic` with and without
//!   lever-arm compensation included), the `ahrs` crate's Madgwick and Mahony
//!   (same gains) and VQF (`vqf-rs`) in the same run. PyPI `vqf`'s batch
//!   update is timed by `scripts/vqf_baseline.py`.
//! * `fuse/*`: `clino::fusion::fuse` end to end, CSV text in memory → CSV
//!   text to a sink; elements are rows.

use std::hint::black_box;

use clino::core::filter::{Complementary, Dynamic, Integrator, Madgwick, Mahony, Poisson};
use clino::core::{AttitudeFilter, Vec3, tilt};
use clino::fusion::{FilterConfig, FilterKind, FuseOptions, fuse};
use clino::io::{ImuCsvReader, ReadOptions};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};

use clino_bench as common;

fn samples(text: &str) -> Vec<(Vec3, Vec3)> {
    ImuCsvReader::new(text.as_bytes(), "bench.csv", &ReadOptions::default())
        .unwrap()
        .map(|r| {
            let r = r.unwrap();
            (r.sample.gyr_rad_s, r.sample.acc_m_s2)
        })
        .collect()
}

fn run_ours<F: AttitudeFilter>(mut f: F, data: &[(Vec3, Vec3)], dt: f64) -> f64 {
    for (g, a) in data {
        f.update(*g, *a, dt);
    }
    f.attitude().w
}

fn bench_update(c: &mut Criterion) {
    let (text, what) = common::trial_07_text();
    let data = samples(&text);
    let dt = 1.0 / 285.714_286;
    eprintln!("update benches on {what}: {} samples", data.len());
    let mut g = c.benchmark_group("update");
    g.throughput(Throughput::Elements(data.len() as u64));
    g.sample_size(20);
    g.bench_function("poisson_exact", |b| {
        b.iter(|| run_ours(Poisson::new(Integrator::Exact), black_box(&data), dt))
    });
    g.bench_function("poisson_rectangle", |b| {
        b.iter(|| run_ours(Poisson::new(Integrator::Rectangle), black_box(&data), dt))
    });
    g.bench_function("complementary", |b| {
        b.iter(|| run_ours(Complementary::new(0.05), black_box(&data), dt))
    });
    g.bench_function("mahony", |b| {
        b.iter(|| run_ours(Mahony::new(1.0, 0.02), black_box(&data), dt))
    });
    g.bench_function("madgwick", |b| {
        b.iter(|| run_ours(Madgwick::new(0.1), black_box(&data), dt))
    });
    g.bench_function("dynamic", |b| {
        b.iter(|| run_ours(Dynamic::default(), black_box(&data), dt))
    });
    g.bench_function("dynamic_lever_arm", |b| {
        b.iter(|| {
            run_ours(
                clino::core::compensate::Compensated::new(
                    Dynamic::default(),
                    Vec3::new(0.5, 0.2, 0.1),
                ),
                black_box(&data),
                dt,
            )
        })
    });
    // VQF (vqf-rs, the pure-Rust port of Laidig & Seel's filter), real time, 6-D
    g.bench_function("vqf_rs", |b| {
        b.iter(|| {
            let mut v = vqf_rs::VQF::new(dt, None, None, None);
            for (gy, ac) in black_box(&data) {
                v.update([gy.x, gy.y, gy.z], [ac.x, ac.y, ac.z], None);
            }
            v.quat_6d().0
        })
    });
    let q0 = tilt::attitude_from_up(&data[0].1).unwrap();
    g.bench_function("ahrs_mahony", |b| {
        b.iter(|| {
            use ahrs::Ahrs;
            let mut f = ahrs::Mahony::new_with_quat(dt, 1.0, 0.02, q0);
            for (gy, ac) in black_box(&data) {
                let _ = f.update_imu(gy, ac);
            }
            f.quat.w
        })
    });
    g.bench_function("ahrs_madgwick", |b| {
        b.iter(|| {
            use ahrs::Ahrs;
            let mut f = ahrs::Madgwick::new_with_quat(dt, 0.1, q0);
            for (gy, ac) in black_box(&data) {
                let _ = f.update_imu(gy, ac);
            }
            f.quat.w
        })
    });
    g.finish();
}

fn bench_fuse(c: &mut Criterion) {
    let (text, what) = common::trial_07_text();
    let rows = text.lines().filter(|l| !l.starts_with('#')).count() as u64 - 1;
    eprintln!("fuse benches on {what}: {rows} rows, {} bytes", text.len());
    let mut g = c.benchmark_group("fuse");
    g.throughput(Throughput::Elements(rows));
    g.sample_size(10);
    // As `clino fuse` reads: time, gyro and accelerometer columns only.
    let imu_only = ReadOptions {
        imu_only: true,
        ..ReadOptions::default()
    };
    for kind in FilterKind::ALL {
        let cfg = FilterConfig::new(kind);
        g.bench_function(kind.name(), |b| {
            b.iter(|| {
                let mut r =
                    ImuCsvReader::new(black_box(text.as_bytes()), "bench.csv", &imu_only).unwrap();
                fuse(&mut r, std::io::sink(), &cfg, &FuseOptions::default())
                    .unwrap()
                    .counts
                    .samples
            })
        });
    }
    let offline = FilterConfig::new(FilterKind::Dynamic).with_offline(true);
    g.bench_function("dynamic_offline", |b| {
        b.iter(|| {
            let mut r =
                ImuCsvReader::new(black_box(text.as_bytes()), "bench.csv", &imu_only).unwrap();
            fuse(&mut r, std::io::sink(), &offline, &FuseOptions::default())
                .unwrap()
                .counts
                .samples
        })
    });
    g.bench_function("read_imu_only", |b| {
        b.iter(|| {
            let mut r =
                ImuCsvReader::new(black_box(text.as_bytes()), "bench.csv", &imu_only).unwrap();
            let mut n = 0u64;
            while let Some(row) = r.next_row().unwrap() {
                n += row.line;
            }
            n
        })
    });
    g.bench_function("read_all_columns", |b| {
        b.iter(|| {
            let mut r = ImuCsvReader::new(
                black_box(text.as_bytes()),
                "bench.csv",
                &ReadOptions::default(),
            )
            .unwrap();
            let mut n = 0u64;
            while let Some(row) = r.next_row().unwrap() {
                n += row.line;
            }
            n
        })
    });
    g.finish();
}

criterion_group!(benches, bench_update, bench_fuse);
criterion_main!(benches);
