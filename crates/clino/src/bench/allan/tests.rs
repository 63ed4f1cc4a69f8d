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
