//! Accuracy and interval coverage of `clino::testbench::allan` on simulated static
//! records with known white noise N, bias instability B and random walk K.
//!
//! ```sh
//! cargo run --release -p clino --example allan_coverage -- [SEEDS] [RATE_HZ] [DURATION_S]
//! ```
//!
//! Defaults: 100 seeds, 10 Hz, 20 000 s; N = 1e-3 u/√Hz, B = 1.5e-3 u (floor
//! 0.664·B from about 1 s to 30 s), K = 3.2e-4 u/√s, on all six axes (the
//! accelerometer's terms ten times the gyro's). The record is simulated at ten
//! times the rate and averaged in blocks of ten (as an integrating ADC does),
//! with flicker over correlation times from one fine sample to 1e6 s, so that
//! its Allan floor is flat to 1 % from 3 samples to the longest τ (point-sampled
//! flicker faster than the sample rate would alias into white noise). For each of the fitted
//! N, B, K and the IEEE 952 readings n, b, k: the mean and RMS of the relative
//! error, the largest, the share within the done-criterion (N 3 %, B 20 %,
//! K 10 %) and the share of 99 % intervals that hold the truth.
use clino::sim::ImuModel;
use clino::sim::motion::Static;
use clino::testbench::allan::{Estimate, allan_imu};

#[derive(Default)]
struct Stats {
    err: Vec<f64>,
    covered: usize,
    missing: usize,
}

impl Stats {
    fn add(&mut self, e: Option<Estimate>, truth: f64) {
        match e {
            Some(e) => {
                self.err.push(e.value / truth - 1.0);
                self.covered += usize::from(e.contains(truth));
            }
            None => self.missing += 1,
        }
    }
    fn print(&self, name: &str, tol: f64) {
        let n = self.err.len().max(1) as f64;
        let mean = self.err.iter().sum::<f64>() / n;
        let rms = (self.err.iter().map(|e| e * e).sum::<f64>() / n).sqrt();
        let max = self.err.iter().fold(0.0f64, |a, e| a.max(e.abs()));
        let within = self.err.iter().filter(|e| e.abs() <= tol).count();
        println!(
            "{name:<12} {:>5} {:>8} {:>+9.2} {:>8.2} {:>8.2} {:>13.1} {:>12.2}",
            self.err.len(),
            self.missing,
            100.0 * mean,
            100.0 * rms,
            100.0 * max,
            100.0 * within as f64 / n,
            100.0 * self.covered as f64 / n
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seeds: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(100);
    let rate: f64 = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(10.0);
    let duration: f64 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(20_000.0);
    let (n, b, k) = (1e-3, 1.5e-3, 3.2e-4);
    let mut m = ImuModel::ideal();
    for (t, s) in [(&mut m.gyro, 1.0), (&mut m.accel, 10.0)] {
        t.noise_density = n * s;
        t.bias_instability = b * s;
        t.random_walk = k * s;
        t.flicker_band_s = (0.1 / rate, 1e6);
    }
    let names = [
        "fit N",
        "fit B",
        "fit K",
        "ieee952 n",
        "ieee952 b",
        "ieee952 k",
    ];
    let mut st: Vec<Stats> = (0..6).map(|_| Stats::default()).collect();
    let t0 = std::time::Instant::now();
    let mut analysis_s = 0.0;
    for seed in 0..seeds {
        let s = m.simulate_averaged(&Static::level(), rate, duration, 1000 + seed, 10);
        let ta = std::time::Instant::now();
        let axes = allan_imu(&s, rate).expect("analysis");
        analysis_s += ta.elapsed().as_secs_f64();
        for ax in &axes {
            let sc = if ax.axis.starts_with("gyr") {
                1.0
            } else {
                10.0
            };
            let fit = ax.fit.as_ref().expect("fit");
            st[0].add(fit.terms[1].estimate, n * sc);
            st[1].add(fit.terms[2].estimate, b * sc);
            st[2].add(fit.terms[3].estimate, k * sc);
            st[3].add(ax.ieee952.n.estimate, n * sc);
            st[4].add(ax.ieee952.b.estimate, b * sc);
            st[5].add(ax.ieee952.k.estimate, k * sc);
        }
    }
    println!(
        "{seeds} seeds x 6 axes, {rate} Hz, {duration} s; N {n:e}, B {b:e}, K {k:e} (gyro; accel x10); \
         {:.1} s ({:.2} s per record in the analysis of six axes)",
        t0.elapsed().as_secs_f64(),
        analysis_s / seeds as f64
    );
    println!(
        "{:<12} {:>5} {:>8} {:>9} {:>8} {:>8} {:>13} {:>12}",
        "term", "count", "missing", "mean %", "rms %", "max %", "within tol %", "coverage %"
    );
    for (i, s) in st.iter().enumerate() {
        let tol = [0.03, 0.2, 0.1][i % 3];
        s.print(names[i], tol);
    }
}
