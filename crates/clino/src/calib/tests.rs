//! Done-when tests of the calibration: simulated truth, recovered.

use super::fit::{FitOptions, ModelKind, Observation, fit_triad};
use super::*;
use clino_core::G0;
use clino_core::sensor::TriadModel;

fn fit_set(opt: &synth::SynthOptions) -> Vec<Observation> {
    let mut ups = synth::cube_directions();
    ups.extend(synth::cube_directions());
    ups.extend(synth::cube_directions());
    let att = synth::attitudes_from_ups(&ups);
    let temps = synth::spread_temperatures(opt.temp_range_c, att.len());
    synth::accel_pose_observations(opt, &att, &temps, 100)
        .into_iter()
        .map(|(o, _)| o)
        .collect()
}

fn max_errors(cal: &clino_core::sensor::TriadCalibration, val: &[(Vec3, f64, Vec3)]) -> (f64, f64) {
    val.iter()
        .fold((0.0f64, 0.0f64), |(a, b), (raw, t, truth)| {
            let (te, ge) = tilt_and_norm_error(cal, *raw, *t, *truth);
            (a.max(te.to_degrees()), b.max(ge.abs() / G0 * 1e3))
        })
}

#[test]
fn mwd30_recovers_truth_within_its_uncertainty_and_meets_the_accuracy() {
    let opt = synth::SynthOptions::default();
    let obs = fit_set(&opt);
    let mut o = FitOptions::accel(ModelKind::Mwd30);
    o.use_ref_inclination = false;
    let fit = fit_triad(&obs, &o).unwrap();
    assert_eq!(fit.params.len(), 27);
    let truth = opt.accel;
    let mut worst: f64 = 0.0;
    for p in &fit.params {
        let t = truth_value(&truth, &p.name);
        let z = (p.value - t) / p.sigma;
        worst = worst.max(z.abs());
        assert!(
            z.abs() < 4.0,
            "{}: estimate {} truth {} σ {} ({z:.1}σ)",
            p.name,
            p.value,
            t,
            p.sigma
        );
    }
    assert!(worst > 0.1, "uncertainties implausibly large");
    let within2 = fit
        .params
        .iter()
        .filter(|p| ((p.value - truth_value(&truth, &p.name)) / p.sigma).abs() < 2.0)
        .count();
    eprintln!(
        "mwd30 (27 params): worst |estimate - truth| = {worst:.2} sigma; {within2}/27 within 2 sigma"
    );
    let val = validation_set(&opt, 300, 5);
    let (tilt, g) = max_errors(&fit.calibration, &val);
    eprintln!(
        "mwd30 on 78 pose means: max tilt error {tilt:.4}°, max |G| error {g:.3} mg over 300 check poses 25–80 °C"
    );
    assert!(tilt <= 0.01, "tilt error {tilt}°");
    assert!(g <= 0.5, "|G| error {g} mg");
    // the 12-parameter fit over the same poses cannot follow the drift
    let f12 = fit_triad(
        &obs,
        &FitOptions {
            use_ref_inclination: false,
            ..FitOptions::accel(ModelKind::Mwd12)
        },
    )
    .unwrap();
    let (t12, g12) = max_errors(&f12.calibration, &val);
    eprintln!("mwd12 on the same poses: max tilt error {t12:.4}°, max |G| error {g12:.3} mg");
    assert!(
        g12 > 2.0 && t12 > 0.01,
        "12-parameter fit should leave temperature error: {t12}° {g12} mg"
    );
    // fitted at the nominal temperature (the paper's 12-parameter case), it is
    // good near 30 °C and the error grows with the distance from it
    let nominal = fit_set(&synth::SynthOptions {
        temp_range_c: [29.0, 31.0],
        ..opt.clone()
    });
    let f12n = fit_triad(
        &nominal,
        &FitOptions {
            use_ref_inclination: false,
            ..FitOptions::accel(ModelKind::Mwd12)
        },
    )
    .unwrap();
    let near: Vec<_> = val
        .iter()
        .filter(|v| (v.1 - 30.0).abs() < 3.0)
        .cloned()
        .collect();
    let far: Vec<_> = val.iter().filter(|v| v.1 > 70.0).cloned().collect();
    let (t_near, g_near) = max_errors(&f12n.calibration, &near);
    let (t_far, g_far) = max_errors(&f12n.calibration, &far);
    eprintln!(
        "mwd12 fitted at 29–31 °C: within 3 °C of 30 °C {t_near:.4}° / {g_near:.3} mg, above 70 °C {t_far:.4}° / {g_far:.3} mg"
    );
    assert!(
        g_near < 1.0 && g_far > 5.0 * g_near,
        "temperature error not visible: near {g_near} far {g_far} mg"
    );
    assert!(
        t_far > 0.01 && t_far > 3.0 * t_near,
        "tilt: near {t_near}° far {t_far}°"
    );
}

fn truth_value(m: &clino_core::sensor::MwdModel, name: &str) -> f64 {
    let ax = |c: char| match c {
        'x' => 0,
        'y' => 1,
        _ => 2,
    };
    let last = name.chars().last().unwrap_or('x');
    if let Some(rest) = name.strip_prefix("SFT") {
        let k: usize = rest[..1].parse().unwrap();
        m.scale[ax(last)][k]
    } else if name.starts_with("SF_") {
        m.scale[ax(last)][0]
    } else if let Some(rest) = name.strip_prefix("BT") {
        let k: usize = rest[..1].parse().unwrap();
        m.bias[ax(last)][k]
    } else if name.starts_with("B_") {
        m.bias[ax(last)][0]
    } else if name.starts_with("m_") {
        let c: Vec<char> = name.chars().collect();
        m.m[ax(c[2])][ax(c[3])]
    } else {
        f64::NAN
    }
}

#[test]
fn reference_inclination_makes_the_z_tilt_observable() {
    // the triad's z axis is tilted against the housing by m_xz, m_yz (upper
    // triangle): magnitudes cannot see it, the reference inclination can
    let mut opt = synth::SynthOptions::default();
    opt.accel.m[0][2] = 0.004;
    opt.accel.m[1][2] = -0.003;
    let obs = fit_set(&opt);
    let fit = fit_triad(&obs, &FitOptions::accel(ModelKind::Mwd30)).unwrap();
    assert_eq!(fit.gauge, fit::Gauge::ZFromReference);
    assert_eq!(fit.fixed, vec!["m_xy".to_string()]);
    for (name, truth) in [("m_xz", 0.004), ("m_yz", -0.003), ("m_yx", 0.0018)] {
        let p = fit.param(name).unwrap();
        assert!(
            ((p.value - truth) / p.sigma).abs() < 4.0,
            "{name}: {} vs {truth} (σ {})",
            p.value,
            p.sigma
        );
    }
    assert!(
        fit.rms_inclination_after_deg.unwrap() < 0.005,
        "{}",
        fit.summary()
    );
    // without the reference the same data is fitted in the lower-triangular
    // convention: magnitudes fine, but the inclination error remains
    let f = fit_triad(
        &obs,
        &FitOptions {
            use_ref_inclination: false,
            ..FitOptions::accel(ModelKind::Mwd30)
        },
    )
    .unwrap();
    assert!(f.rms_norm_after.unwrap() < 1e-3);
    assert!(
        f.rms_inclination_after_deg.unwrap() > 0.1,
        "{}",
        f.summary()
    );
}

#[test]
fn full_pipeline_from_a_continuous_recording() {
    let opt = synth::SynthOptions::default();
    let att = synth::calibration_schedule();
    let sr = synth::recording(&opt, &att);
    let rec = sr.recording();
    let (report, fit) =
        calibrate_accel(&rec, ModelKind::Mwd30, &StaticOptions::default(), G0).unwrap();
    assert_eq!(report.poses.len(), att.len(), "{}", report.table());
    let val = validation_set(&opt, 200, 11);
    let (tilt, g) = max_errors(&fit.calibration, &val);
    eprintln!("continuous recording, mwd30: max tilt error {tilt:.4}°, max |G| error {g:.3} mg");
    assert!(
        tilt <= 0.01 && g <= 0.5,
        "tilt {tilt}° |G| {g} mg\n{}",
        fit.summary()
    );

    // write, load, apply to the recording: static poses now read g
    let mut file = CalibrationFile::default();
    file.set(fit.kind, entry_from_fit(&fit, "test"));
    let file = CalibrationFile::from_toml(&file.to_toml().unwrap()).unwrap();
    let mut rec2 = rec.clone();
    file.apply_recording(&mut rec2).unwrap();
    let acc = rec2.acc.as_ref().unwrap();
    for p in &report.poses {
        let i = (p.rows[0] + p.rows[1]) / 2;
        assert!((acc[i].norm() - G0).abs() < 0.03, "{}", acc[i].norm());
    }
    // gyro from the rotations between the same poses
    let gy = gyro::from_rotations(&rec, &report.poses, Some(&fit.calibration)).unwrap();
    let truth = nalgebra::Matrix3::from_fn(|i, j| opt.gyro.matrix[i][j]);
    let TriadModel::Matrix(m) = gy.calibration.model else {
        panic!()
    };
    let est = nalgebra::Matrix3::from_fn(|i, j| m.matrix[i][j]);
    eprintln!(
        "gyro from rotations: max |M - truth| = {:.2e}, rms mismatch {:.4}° -> {:.4}°",
        (est - truth).abs().max(),
        gy.rms_before_deg,
        gy.rms_after_deg
    );
    assert!((est - truth).abs().max() < 2e-3, "{est} vs {truth}");
    assert!((Vec3::from(gy.bias) - Vec3::from(opt.gyro.bias)).norm() < 1e-3);
    assert!(
        gy.rms_after_deg < 0.2 * gy.rms_before_deg,
        "{} {}",
        gy.rms_after_deg,
        gy.rms_before_deg
    );
}

#[test]
fn magnetometer_ellipsoid_fit_removes_hard_and_soft_iron() {
    let opt = synth::SynthOptions::default();
    let ups = synth::cube_directions();
    let att = synth::attitudes_from_ups(&ups);
    let sr = synth::recording(&opt, &att);
    let rec = sr.recording();
    let field = opt.field_enu_ut.norm();
    let fit = calibrate_mag(&rec, ModelKind::Matrix, Some(field)).unwrap();
    assert_eq!(fit.gauge, fit::Gauge::Symmetric);
    // the true soft iron is symmetric, so the truth is recoverable exactly
    let TriadModel::Matrix(m) = fit.calibration.model else {
        panic!()
    };
    for i in 0..3 {
        assert!(
            (m.bias[i] - opt.mag.bias[i]).abs() < 0.05,
            "{:?} vs {:?}",
            m.bias,
            opt.mag.bias
        );
        for j in 0..3 {
            assert!(
                (m.matrix[i][j] - opt.mag.matrix[i][j]).abs() < 2e-3,
                "{:?}",
                m.matrix
            );
        }
    }
    assert!(fit.rms_norm_after.unwrap() < 0.1, "{}", fit.summary());
    assert!(fit.rms_norm_before.unwrap() > 5.0);
    // a hard iron larger than the field itself still fits (coverage judged about the centre)
    let strong = synth::SynthOptions {
        mag: clino_core::sensor::MatrixModel {
            bias: [80.0, -60.0, 70.0],
            ..opt.mag
        },
        ..opt.clone()
    };
    let rec2 = synth::recording(&strong, &att).recording();
    let f2 = calibrate_mag(&rec2, ModelKind::Matrix, Some(field)).unwrap();
    assert!(f2.rms_norm_after.unwrap() < 0.1, "{}", f2.summary());
    // the MWD form fits the same ellipsoid (its misalignment in the lower-triangular convention)
    let f12 = calibrate_mag(&rec, ModelKind::Mwd12, Some(field)).unwrap();
    assert!(f12.rms_norm_after.unwrap() < 0.1, "{}", f12.summary());
}

#[test]
fn gyro_rate_table_recovers_scale_misalignment_and_bias() {
    use clino_core::ImuSample;
    let opt = synth::SynthOptions::default();
    // runs of 2 s at ±0.5, ±1, ±2 rad/s about each axis, plus rest
    let mut s = Vec::new();
    let mut refs = Vec::new();
    let mut t = 0.0;
    let mut rates = vec![Vec3::zeros()];
    for ax in 0..3 {
        for r in [0.5, -0.5, 1.0, -1.0, 2.0, -2.0] {
            let mut w = Vec3::zeros();
            w[ax] = r;
            rates.push(w);
        }
    }
    for (k, w) in rates.iter().enumerate() {
        for i in 0..100 {
            let noise = 1e-3 * ((i * 13 + k * 7) as f64).sin();
            let mm = nalgebra::Matrix3::from_fn(|a, b| opt.gyro.matrix[a][b]);
            let raw =
                mm.try_inverse().unwrap() * w + Vec3::from(opt.gyro.bias) + Vec3::repeat(noise);
            s.push(ImuSample::new(t, raw, Vec3::new(0.0, 0.0, G0)));
            refs.push(*w);
            t += 0.01;
        }
    }
    let mut rec = Recording::from_samples(&s, None);
    rec.ref_gyr = Some(refs);
    let fit = gyro::rate_table(&rec, ModelKind::Matrix).unwrap();
    assert_eq!(fit.params.len(), 12);
    let TriadModel::Matrix(m) = fit.calibration.model else {
        panic!()
    };
    for i in 0..3 {
        assert!((m.bias[i] - opt.gyro.bias[i]).abs() < 1e-4);
        for j in 0..3 {
            assert!((m.matrix[i][j] - opt.gyro.matrix[i][j]).abs() < 1e-4);
        }
    }
    // the MWD model with all of m free represents any matrix: same answer
    let f12 = gyro::rate_table(&rec, ModelKind::Mwd12).unwrap();
    assert_eq!(f12.params.len(), 12);
    assert!(f12.rms_vector_after.unwrap() < 1e-4, "{}", f12.summary());
    // a table turned only about z: clear error naming the axes
    let only_z: Vec<usize> = (0..rec.len())
        .filter(|&i| {
            rec.ref_gyr.as_ref().unwrap()[i].x == 0.0 && rec.ref_gyr.as_ref().unwrap()[i].y == 0.0
        })
        .collect();
    let sub: Vec<ImuSample> = only_z
        .iter()
        .map(|&i| ImuSample {
            t_s: i as f64,
            ..rec.sample(i)
        })
        .collect();
    let mut r2 = Recording::from_samples(&sub, None);
    r2.ref_gyr = Some(
        only_z
            .iter()
            .map(|&i| rec.ref_gyr.as_ref().unwrap()[i])
            .collect(),
    );
    let e = gyro::rate_table(&r2, ModelKind::Matrix).unwrap_err();
    assert!(e.message.contains("x, y axis"), "{}", e.message);
}

#[test]
fn six_position_from_a_recording() {
    let opt = synth::SynthOptions {
        temp_range_c: [30.0, 30.0],
        ..Default::default()
    };
    let ups = [
        Vec3::x(),
        -Vec3::x(),
        Vec3::y(),
        -Vec3::y(),
        Vec3::z(),
        -Vec3::z(),
    ];
    let att = synth::attitudes_from_ups(&ups);
    let rec = synth::recording(&opt, &att).recording();
    let report = detect_static(&rec, &StaticOptions::default()).unwrap();
    let six = six::six_position(&report.poses, G0).unwrap();
    let val = validation_set(&opt, 100, 3);
    let (tilt, g) = max_errors(&six.calibration, &val);
    assert!(tilt < 0.01 && g < 0.5, "{tilt} {g}");
}

#[test]
fn demo_summary_shows_improvement() {
    let s = demo_summary().unwrap();
    assert!(s.contains("MWD 30 parameters"), "{s}");
}

#[test]
fn method_names_are_the_cli_model_names() {
    use super::method::Method;
    assert_eq!(Method::parse("six").unwrap(), Method::SixPosition);
    for (s, m) in [
        ("matrix", ModelKind::Matrix),
        ("mwd12", ModelKind::Mwd12),
        ("mwd30", ModelKind::Mwd30),
    ] {
        assert_eq!(Method::parse(s).unwrap(), Method::Fit(m));
    }
    let e = Method::parse("mwd13").unwrap_err();
    assert!(
        e.message.contains("mwd13") && e.message.contains("six"),
        "{}",
        e.message
    );
}
