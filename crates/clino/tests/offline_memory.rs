//! The offline smoother's memory per sample, measured by a counting global
//! allocator (peak bytes live above the level before the run). Deterministic:
//! it counts bytes, it does not time anything.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use clino::fusion::{FilterConfig, FuseOptions, fuse};
use clino::io::{ImuCsvReader, ReadOptions};
use clino::smooth::{SmoothOptions, smooth_in_place};
use clino_core::Vec3;

struct Counting;
static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        let live = LIVE.fetch_add(l.size(), Ordering::SeqCst) + l.size();
        PEAK.fetch_max(live, Ordering::SeqCst);
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        LIVE.fetch_sub(l.size(), Ordering::SeqCst);
        unsafe { System.dealloc(p, l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        // count the old and the new block together, as a copying realloc holds both
        let live = LIVE.fetch_add(new, Ordering::SeqCst) + new;
        PEAK.fetch_max(live, Ordering::SeqCst);
        let q = unsafe { System.realloc(p, l, new) };
        LIVE.fetch_sub(l.size(), Ordering::SeqCst);
        q
    }
}

#[global_allocator]
static A: Counting = Counting;

/// Peak bytes allocated by `f` beyond what was live when it started.
fn peak_of<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let base = LIVE.load(Ordering::SeqCst);
    PEAK.store(base, Ordering::SeqCst);
    let out = f();
    (out, PEAK.load(Ordering::SeqCst) - base)
}

/// A moving recording (turning about a tilted axis, noisy enough to be real).
fn recording(n: usize, rate: f64) -> (Vec<Vec3>, Vec<Vec3>, Vec<f64>) {
    let mut g = Vec::with_capacity(n);
    let mut a = Vec::with_capacity(n);
    for k in 0..n {
        let t = k as f64 / rate;
        let w = Vec3::new(0.3 * (0.7 * t).sin(), 0.2 * (1.1 * t).cos(), 0.1);
        g.push(w);
        a.push(Vec3::new(
            0.5 * (0.3 * t).sin(),
            -0.4 * (0.2 * t).cos(),
            9.78,
        ));
    }
    (g, a, vec![1.0 / rate; n])
}

// One test function: the counters are global, and tests of one binary run in
// parallel threads.
#[test]
fn offline_smoothing_stays_within_its_memory_budget() {
    let n = 60_000;
    // the smoother itself (with the lever arm, which compensates in place):
    // at most 88 bytes of working state a sample and the 32-byte attitudes
    let (g, mut a, dt) = recording(n, 200.0);
    let opts = SmoothOptions {
        lever_arm_m: Some(Vec3::new(1.0, 0.5, 0.0)),
        ..Default::default()
    };
    let (q, peak) = peak_of(|| smooth_in_place(&g, &mut a, &dt, &opts, None));
    assert_eq!(q.len(), n);
    let per = peak as f64 / n as f64;
    assert!(
        per <= 88.0 + 32.0 + 1.0,
        "smoother: {per:.1} bytes a sample"
    );
    drop((g, a, dt, q));

    // `fuse --offline` end to end on a CSV held in memory (its bytes are not
    // counted): the held recording (9 + 56 bytes a row) and the smoother
    let (g, a, _) = recording(n, 200.0);
    let mut text =
        String::from("t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n");
    for k in 0..n {
        use std::fmt::Write;
        let (w, f) = (g[k], a[k]);
        writeln!(
            text,
            "{},{},{},{},{},{},{}",
            k as f64 / 200.0,
            w.x,
            w.y,
            w.z,
            f.x,
            f.y,
            f.z
        )
        .unwrap();
    }
    drop((g, a));
    let config = FilterConfig::new(clino_core::filter::FilterKind::Dynamic).with_offline(true);
    let (rep, peak) = peak_of(|| {
        let mut r = ImuCsvReader::new(text.as_bytes(), "mem.csv", &ReadOptions::default()).unwrap();
        fuse(&mut r, std::io::sink(), &config, &FuseOptions::default()).unwrap()
    });
    assert_eq!(rep.counts.fused, n as u64);
    let per = peak as f64 / n as f64;
    assert!(per <= 200.0, "fuse --offline: {per:.1} bytes a row");
    eprintln!("fuse --offline: {per:.1} bytes a row (peak {peak} bytes for {n} rows)");
    drop(text);

    // a gyro with scale errors on a swaying boom: the scale fitted to the
    // passes' disagreement is taken, and the smoothing runs again on a
    // corrected copy of the rates: 24 bytes a sample more
    use clino::sim::hand::{HandMotion, HandParams};
    use clino::sim::motion::{Sum, vibration};
    let boom = Sum {
        a: HandMotion::new(HandParams::slow(), 1),
        b: vibration(3.0, 2f64.to_radians(), Vec3::new(1.5, 1.0, 1.2)),
    };
    let mut model = clino::sim::slewing::sensor().with_bandwidth(50.0);
    model.gyro.scale = Vec3::new(0.02, -0.015, 0.01);
    let s = model.simulate(&boom, 125.0, 120.0, 1);
    let n = s.len();
    let g: Vec<Vec3> = s.iter().map(|x| x.gyr_rad_s).collect();
    let mut a: Vec<Vec3> = s.iter().map(|x| x.acc_m_s2).collect();
    let dt = vec![1.0 / 125.0; n];
    drop(s);
    let (q, peak) = peak_of(|| smooth_in_place(&g, &mut a, &dt, &SmoothOptions::default(), None));
    assert_eq!(q.len(), n);
    let per = peak as f64 / n as f64;
    assert!(
        per <= 112.0 + 32.0 + 1.0,
        "smoother run twice: {per:.1} bytes a sample"
    );
    eprintln!("smoother run twice: {per:.1} bytes a sample");
}
