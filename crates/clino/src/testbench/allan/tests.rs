use super::*;
use crate::sim::ImuModel;
use crate::sim::motion::Static;

#[test]
fn white_noise_has_slope_minus_half() {
    let mut m = ImuModel::ideal();
    m.gyro.noise_density = 0.01;
    let s = m.simulate(&Static::level(), 100.0, 600.0, 11);
    let y: Vec<f64> = s.iter().map(|x| x.gyr_rad_s.x).collect();
    let pts = allan_deviation(&y, 100.0, 10).unwrap();
    for p in &pts {
        // σ(τ) = N/√τ within the stated bound
        let expect = 0.01 / p.tau_s.sqrt();
        assert!(
            expect >= p.adev_lo * 0.98 && expect <= p.adev_hi * 1.02,
            "{p:?} {expect}"
        );
    }
    let mid = &pts[pts.len() / 2];
    assert!((mid.slope + 0.5).abs() < 0.15, "{mid:?}");
}

#[test]
fn bad_records_are_errors() {
    assert!(allan_deviation(&[1.0; 5], 100.0, 10).is_err());
    let mut y = vec![0.0; 100];
    y[3] = f64::NAN;
    assert_eq!(
        allan_deviation(&y, 100.0, 10).unwrap_err().kind,
        ErrorKind::InvalidInput
    );
    let e = analyse_axis("gyr_x", "rad/s", &[0.1; 60], 100.0).unwrap_err();
    assert_eq!(e.kind, ErrorKind::Empty);
    assert!(e.message.contains("at least 100"), "{e}");
}

/// A single-axis rate record of `n` samples at interval `tau0`: white noise of
/// density `nd`, flicker of coefficient `b` and random walk `k`, simulated at
/// five times the rate and averaged in blocks of five (flicker components from
/// one fine sample to 10⁵ s, two per decade: a floor flat to 1 % over τ ≥ 5·τ₀).
/// Independent of `crate::sim`.
fn record(n: usize, tau0: f64, nd: f64, b: f64, k: f64, seed: u64) -> Vec<f64> {
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let f = 5usize;
    let dt = tau0 / f as f64;
    let ratio = 10f64.sqrt();
    let mut gm: Vec<(f64, f64, f64)> = Vec::new(); // (φ, innovation σ, state)
    if b > 0.0 {
        let q = b * b * ratio.ln() / std::f64::consts::PI;
        let mut t = dt;
        while t <= 1e5 {
            let phi = (-dt / t).exp();
            let x: f64 = StandardNormal.sample(&mut rng);
            gm.push((phi, (q * (1.0 - phi * phi)).sqrt(), x * q.sqrt()));
            t *= ratio;
        }
    }
    let mut rw = 0.0;
    let mut out = Vec::with_capacity(n);
    for _ in 0..n {
        let mut acc = 0.0;
        for _ in 0..f {
            let w: f64 = StandardNormal.sample(&mut rng);
            let mut y = nd / dt.sqrt() * w + rw;
            for g in gm.iter_mut() {
                y += g.2;
                let e: f64 = StandardNormal.sample(&mut rng);
                g.2 = g.0 * g.2 + g.1 * e;
            }
            if k > 0.0 {
                let e: f64 = StandardNormal.sample(&mut rng);
                rw += k * dt.sqrt() * e;
            }
            acc += y;
        }
        out.push(acc / f as f64);
    }
    out
}

#[test]
fn fitted_terms_are_accurate_and_their_99_percent_intervals_cover_the_truth() {
    // white noise meets the floor at 1 s, the floor meets the random walk at 20 s
    let (nd, b, k) = (1e-3, 1e-3 / B_FLOOR, 1e-3 * (3.0f64 / 20.0).sqrt());
    let truth = [nd, b, k];
    let seeds = 30;
    let (mut miss, mut err, mut z2) = ([0usize; 3], [0.0f64; 3], [0.0f64; 3]);
    for seed in 0..seeds {
        let y = record(30_000, 0.1, nd, b, k, seed);
        let ax = analyse_axis("gyr_x", "rad/s", &y, 10.0).unwrap();
        let fit = ax.fit.as_ref().unwrap();
        for (j, t) in truth.iter().enumerate() {
            let e = fit.terms[j + 1]
                .estimate
                .unwrap_or_else(|| panic!("seed {seed}: term {j} absent: {:?}", fit.terms[j + 1]));
            miss[j] += usize::from(!e.contains(*t));
            err[j] += e.value / t - 1.0;
            // standardised error of the squared term: (ĉ − c)/sd, sd = ĉ·√(2/edf)
            z2[j] += ((e.value.powi(2) - t * t) / (e.value.powi(2) * (2.0 / e.edf).sqrt())).powi(2);
            let tol = [0.03, 0.2, 0.6][j];
            assert!(
                (e.value / t - 1.0).abs() < tol,
                "seed {seed}, term {j}: {e:?} vs {t}"
            );
        }
    }
    for j in 0..3 {
        let mean = err[j] / seeds as f64;
        let z_rms = (z2[j] / seeds as f64).sqrt();
        eprintln!(
            "term {j}: {} of {seeds} outside the 99 % interval, mean error {:+.2} %, rms z {z_rms:.2}",
            miss[j],
            100.0 * mean
        );
        // a 99 % interval misses about 0.3 of 30; an 80 % one would miss 6
        assert!(miss[j] <= 2, "term {j}: {} misses", miss[j]);
        // not absurdly wide either: the standardised errors scatter by about 1
        assert!((0.4..1.6).contains(&z_rms), "term {j}: rms z {z_rms}");
        assert!(
            mean.abs() < [0.005, 0.05, 0.1][j],
            "term {j}: mean error {mean}"
        );
    }
}

#[test]
fn a_short_white_noise_record_has_no_floor_and_no_random_walk() {
    // like the shared MPU-6050 record: 449 s at 100 Hz, white noise only
    let mut m = ImuModel::ideal();
    m.gyro.noise_density = 1.5e-4;
    m.accel.noise_density = 3e-3;
    let s = m.simulate(&Static::level(), 100.0, 449.0, 3);
    for ax in allan_imu(&s, 100.0).unwrap() {
        let truth = if ax.axis.starts_with("gyr") {
            1.5e-4
        } else {
            3e-3
        };
        let n = ax.ieee952.n.estimate.unwrap();
        assert!((n.value / truth - 1.0).abs() < 0.03, "{}: {n:?}", ax.axis);
        assert!(n.contains(truth), "{}: {n:?}", ax.axis);
        let k = &ax.ieee952.k;
        assert!(k.estimate.is_none(), "{}: {k:?}", ax.axis);
        assert!(k.reason.as_ref().unwrap().contains("no +1/2"), "{k:?}");
        let fit = ax.fit.unwrap();
        assert!((fit.terms[1].value().unwrap() / truth - 1.0).abs() < 0.03);
        for j in [2, 3] {
            assert!(
                fit.terms[j].estimate.is_none(),
                "{}: {:?}",
                ax.axis,
                fit.terms[j]
            );
        }
    }
}

#[test]
fn correlated_short_tau_are_left_out_of_the_fit() {
    // white noise through a 4-sample moving average (an internal filter): the
    // shortest τ lie below the −1/2 line; the density at low frequency is unchanged
    let nd = 1e-3;
    let y0 = record(60_000, 0.01, nd, 0.0, 0.0, 7);
    let y: Vec<f64> = (0..y0.len())
        .map(|i| (0..4).map(|j| y0[i.saturating_sub(j)]).sum::<f64>() / 4.0)
        .collect();
    let ax = analyse_axis("gyr_x", "rad/s", &y, 100.0).unwrap();
    // the curve at τ₀ lies well below the line: a fit through it would be low
    assert!(
        ax.points[0].adev * 0.01f64.sqrt() < 0.7 * nd,
        "{:?}",
        ax.points[0]
    );
    let fit = ax.fit.as_ref().unwrap();
    assert!(
        fit.excluded
            .as_ref()
            .unwrap()
            .contains("below the −1/2 line"),
        "{fit:?}"
    );
    assert!(fit.tau_from_s > 0.02, "{fit:?}");
    let n_fit = fit.terms[1].estimate.unwrap();
    let n_read = ax.ieee952.n.estimate.unwrap();
    for e in [n_fit, n_read] {
        assert!((e.value / nd - 1.0).abs() < 0.03, "{e:?}");
    }
}

#[test]
fn random_walk_and_ramp_are_read() {
    let (nd, k) = (1e-3, 1e-4);
    let y = record(100_000, 0.1, nd, 0.0, k, 21);
    let ax = analyse_axis("acc_x", "m/s^2", &y, 10.0).unwrap();
    let kr = ax.ieee952.k.estimate.unwrap();
    assert!((kr.value / k - 1.0).abs() < 0.15, "{kr:?}");
    let kf = ax.fit.as_ref().unwrap().terms[3].estimate.unwrap();
    assert!(
        kf.contains(k) && (kf.value / k - 1.0).abs() < 0.15,
        "{kf:?}"
    );
    // a ramp R: σ = R·τ/√2
    let r = 2e-6;
    let y: Vec<f64> = record(20_000, 0.1, nd, 0.0, 0.0, 5)
        .iter()
        .enumerate()
        .map(|(i, v)| v + r * i as f64 * 0.1)
        .collect();
    let ax = analyse_axis("acc_x", "m/s^2", &y, 10.0).unwrap();
    let rf = ax.fit.as_ref().unwrap().terms[4].estimate.unwrap();
    assert!(
        rf.contains(r) && (rf.value / r - 1.0).abs() < 0.05,
        "{rf:?}"
    );
}

#[test]
fn constant_and_quantised_flat_channels_are_explained() {
    let ax = analyse_axis("gyr_z", "rad/s", &[0.25; 500], 100.0).unwrap();
    assert_eq!(ax.status, ChannelStatus::Constant);
    assert!(ax.reason.as_ref().unwrap().contains("constant channel"));
    assert!(ax.ieee952.n.estimate.is_none() && ax.ieee952.n.reason.is_some());
    assert!(ax.fit.is_none() && ax.points.is_empty());
    // noise far below the step: one value most of the time
    let y: Vec<f64> = (0..1000)
        .map(|i| if i % 40 == 0 { 0.01 } else { 0.0 })
        .collect();
    let ax = analyse_axis("acc_x", "m/s^2", &y, 100.0).unwrap();
    assert_eq!(ax.status, ChannelStatus::QuantisedFlat);
    assert!(
        ax.reason.as_ref().unwrap().contains("97.5 %"),
        "{:?}",
        ax.reason
    );
    assert!(ax.ieee952.b.estimate.is_none());
}

#[test]
fn json_has_the_readings_under_ieee952_and_null_with_reasons() {
    let mut m = ImuModel::ideal();
    m.gyro.noise_density = 1e-3;
    let s = m.simulate(&Static::level(), 100.0, 200.0, 1);
    let y: Vec<f64> = s.iter().map(|x| x.gyr_rad_s.x).collect();
    let ax = analyse_axis("gyr_x", "rad/s", &y, 100.0).unwrap();
    let v = serde_json::to_value(&ax).unwrap();
    let r = &v["ieee952"];
    assert!(r["n"].as_f64().unwrap() > 0.0);
    assert!(r["n_lo"].as_f64().unwrap() < r["n"].as_f64().unwrap());
    assert_eq!(r["n_region_s"].as_array().unwrap().len(), 2);
    assert!(r["k"].is_null() && r["k_reason"].as_str().unwrap().contains("+1/2"));
    assert!(r["b"].is_null() && r["b_tau_s"].is_null() && r["b_reason"].is_string());
    assert_eq!(v["units"]["n"], "rad/s/sqrt(Hz)");
    assert!(v["fit"]["n"].as_f64().is_some() && v["fit"]["k"].is_null());
    assert!(v["fit"]["k_reason"].is_string());
}
