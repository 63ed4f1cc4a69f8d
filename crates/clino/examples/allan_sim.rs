//! Write a simulated static IMU record with known IEEE 952 terms to CSV (for
//! `clino allan` and `scripts/allan_compare.py`).
//!
//! ```sh
//! cargo run -p clino --example allan_sim -- OUT.csv [RATE_HZ DURATION_S N B K SEED]
//! ```
//!
//! Every axis has white noise N (u/√Hz), bias instability B (u) and rate random
//! walk K (u/√s) — gyro in rad/s, accelerometer in m/s² (on top of gravity on z)
//! with ten times the gyro's terms. Simulated at ten times the rate and
//! averaged in blocks of ten, flicker over correlation times from one fine
//! sample to 10⁶ s: the Allan floor is 0.664·B to 1 % from three samples up.
//! Defaults: 10 Hz, 20 000 s, N = 1e-3, B = 1.5e-3, K = 3.2e-4, seed 1.
use clino::io::CsvLineWriter;
use clino::sim::ImuModel;
use clino::sim::motion::Static;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let a: Vec<String> = std::env::args().skip(1).collect();
    let out = a
        .first()
        .ok_or("usage: allan_sim OUT.csv [RATE_HZ DURATION_S N B K SEED]")?;
    let num = |i: usize, d: f64| a.get(i).and_then(|s| s.parse().ok()).unwrap_or(d);
    let (rate, dur, n, b, k) = (
        num(1, 10.0),
        num(2, 20_000.0),
        num(3, 1e-3),
        num(4, 1.5e-3),
        num(5, 3.2e-4),
    );
    let seed = num(6, 1.0) as u64;
    let mut m = ImuModel::ideal();
    for (t, s) in [(&mut m.gyro, 1.0), (&mut m.accel, 10.0)] {
        t.noise_density = n * s;
        t.bias_instability = b * s;
        t.random_walk = k * s;
        t.flicker_band_s = (0.1 / rate, 1e6);
    }
    let s = m.simulate_averaged(&Static::level(), rate, dur, seed, 10);
    let mut w = CsvLineWriter::new(std::fs::File::create(out)?);
    w.header(&[
        "t_s",
        "gyr_x_rad_s",
        "gyr_y_rad_s",
        "gyr_z_rad_s",
        "acc_x_m_s2",
        "acc_y_m_s2",
        "acc_z_m_s2",
    ])?;
    for x in &s {
        w.f64(x.t_s);
        for v in x.gyr_rad_s.iter().chain(x.acc_m_s2.iter()) {
            w.f64(*v);
        }
        w.end_row()?;
    }
    w.finish()?;
    eprintln!(
        "{out}: {} samples at {rate} Hz; gyro N {n:e} rad/s/sqrt(Hz), B {b:e} rad/s, K {k:e} rad/s/sqrt(s); accelerometer x10",
        s.len()
    );
    Ok(())
}
