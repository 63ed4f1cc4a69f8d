// throw-away: print dynamic's bias and motion scale over a BROAD trial
use clino::core::filter::AnyFilter;
use clino::core::AttitudeFilter;
use clino::core::pipeline::Pipeline;
fn main() {
    let path = std::env::args().nth(1).unwrap();
    let spec = std::env::args().nth(2);
    let fs = spec.map(|s| clino::fusion::parse_spec(&s).unwrap()).unwrap_or_default();
    let text = std::fs::read_to_string(&path).unwrap();
    let mut p = Pipeline::new(fs);
    let mut next = 0.0;
    for l in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap_or(f64::NAN)).collect();
        let s = clino::core::sample::ImuSample::new(v[0], clino::core::Vec3::new(v[1], v[2], v[3]), clino::core::Vec3::new(v[4], v[5], v[6]));
        p.update(&s);
        if v[0] >= next {
            next += 2.0;
            if let AnyFilter::Dynamic(d) = p.filter() {
                let b = d.gyro_bias().map(|x| x.to_degrees());
                let m = d.motion_gyro_scale() * 100.0;
                println!("{:6.1} bias {:+.3} {:+.3} {:+.3} °/s  ms {:+.3} {:+.3} {:+.3} %  rest {} pairs {}", v[0], b.x, b.y, b.z, m.x, m.y, m.z, d.at_rest() as u8, d.rest_pairs());
            }
        }
    }
}
