//! Diagnosis of the "slow+vib" condition of the generalisation harness: where
//! (rest or motion) and why the dynamic filter's tilt error exceeds VQF's.
//!
//! ```text
//! cargo run --release -p clino-bench --example slowvib -- [--rate HZ] [--seeds N]
//!     [--vib both|lin|ang|none] [--dynamic SPEC] [--series SEED]
//! ```

use clino::core::filter::{AttitudeFilter, Dynamic, FilterSpec};
use clino::core::{Attitude, Vec3};
use clino::eval::inclination_error;
use clino::fusion::parse_spec;
use clino::sim::hand::{HandMotion, HandParams};
use clino::sim::imu::Bandwidth;
use clino::sim::motion::{ConeAxis, Conical, Orbit, Sum};
use clino::sim::{ImuModel, Motion, slewing};

struct Vib {
    lin: bool,
    ang: bool,
    amp: f64,
}

fn motion(seed: u64, rate: f64, vib: &Vib) -> (HandMotion, Box<dyn Motion>) {
    let hand = HandMotion::new(HandParams::slow(), seed);
    let f = (0.35 * rate).min(30.0);
    let w = 2.0 * std::f64::consts::PI * f;
    let s = |on: bool| if on { vib.amp } else { 0.0 };
    let lin = Orbit {
        amplitude_m: Vec3::new(1.5, 1.0, 1.2) / (w * w) * s(vib.lin),
        phase_rad: Vec3::new(0.0, 1.0, 2.0),
        omega_rad_s: w,
        attitude: Attitude::identity(),
        start_s: f64::NEG_INFINITY,
        ramp_s: 0.0,
    };
    let ang = Conical::new(ConeAxis::Z, 2f64.to_radians() / w * s(vib.ang), f);
    (
        hand,
        Box::new(Sum {
            a: Sum { a: hand, b: lin },
            b: ang,
        }),
    )
}

#[derive(Default, Clone, Copy)]
struct Acc {
    s: f64,
    n: f64,
}
impl Acc {
    fn push(&mut self, e: f64) {
        self.s += e * e;
        self.n += 1.0;
    }
    fn rms_deg(&self) -> f64 {
        (self.s / self.n.max(1.0)).sqrt().to_degrees()
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut rate: f64 = 100.0;
    let mut seeds = 3u64;
    let mut vib = Vib {
        lin: true,
        ang: true,
        amp: 1.0,
    };
    let mut sensor = String::from("cal");
    let mut drop = String::new();
    let mut add = String::new();
    let mut spec = FilterSpec::default();
    let mut series: Option<u64> = None;
    let mut from: Option<f64> = None;
    let mut true_bias = false;
    let mut oracle = false;
    let mut window: Option<(f64, f64)> = None;
    let mut i = 0;
    while i < args.len() {
        let v = args.get(i + 1).cloned().unwrap_or_default();
        match args[i].as_str() {
            "--window" => {
                let (a, b) = v.split_once(',').expect("--window A,B");
                window = Some((a.parse().expect("A"), b.parse().expect("B")));
            }
            "--oracle" => {
                oracle = true;
                i -= 1;
            }
            "--truebias" => {
                true_bias = true;
                i -= 1;
            }
            "--from" => from = Some(v.parse().expect("--from S")),
            "--amp" => vib.amp = v.parse().expect("--amp X"),
            "--add" => add = v.clone(),
            "--drop" => drop = v.clone(),
            "--sensor" => sensor = v.clone(),
            "--rate" => rate = v.parse().expect("--rate HZ"),
            "--seeds" => seeds = v.parse().expect("--seeds N"),
            "--series" => series = Some(v.parse().expect("--series SEED")),
            "--dynamic" => spec = parse_spec(&v).expect("--dynamic SPEC"),
            "--vib" => {
                vib.lin = v == "both" || v == "lin";
                vib.ang = v == "both" || v == "ang";
            }
            a => panic!("unknown argument {a}"),
        }
        i += 2;
    }
    let FilterSpec::Dynamic(params) = spec else {
        panic!("--dynamic needs a dynamic spec")
    };
    // cal: the harness's calibrated MPU6050; ideal: no sensor error, same bandwidth;
    // nobw: the calibrated MPU6050 without band limit
    let model = match sensor.as_str() {
        "cal" => slewing::sensor().with_bandwidth((0.4 * rate).min(98.0)),
        "ideal" => ImuModel::ideal().with_bandwidth((0.4 * rate).min(98.0)),
        "idealnobw" => ImuModel::ideal(),
        "nobw" => {
            let mut m = slewing::sensor();
            m.gyro.bandwidth = Bandwidth::Unlimited;
            m.accel.bandwidth = Bandwidth::Unlimited;
            m
        }
        s => panic!("unknown sensor {s}"),
    };
    // --add noise,proc,scale,bias,lsb: the ideal sensor (with the band limit) plus those
    // errors of the calibrated one
    let mut model = model;
    let cal = slewing::sensor();
    for d in add.split(',').filter(|d| !d.is_empty()) {
        for (t, c) in [(&mut model.gyro, &cal.gyro), (&mut model.accel, &cal.accel)] {
            match d {
                "noise" => t.noise_density = c.noise_density,
                "proc" => {
                    t.bias_instability = c.bias_instability;
                    t.random_walk = c.random_walk;
                }
                "scale" => {
                    t.scale = c.scale;
                    t.cross_axis = c.cross_axis;
                }
                "bias" => t.bias = c.bias,
                "lsb" => t.lsb = c.lsb,
                _ => {}
            }
        }
        match d {
            "gproc" => {
                model.gyro.bias_instability = cal.gyro.bias_instability;
                model.gyro.random_walk = cal.gyro.random_walk;
            }
            "aproc" => {
                model.accel.bias_instability = cal.accel.bias_instability;
                model.accel.random_walk = cal.accel.random_walk;
            }
            "gnoise" => model.gyro.noise_density = cal.gyro.noise_density,
            "anoise" => model.accel.noise_density = cal.accel.noise_density,
            _ => {}
        }
    }
    // --drop noise,proc,scale,bias,lsb: the sensor without those errors
    for d in drop.split(',').filter(|d| !d.is_empty()) {
        for t in [&mut model.gyro, &mut model.accel] {
            match d {
                "noise" => t.noise_density = 0.0,
                "proc" => {
                    t.bias_instability = 0.0;
                    t.random_walk = 0.0;
                }
                "scale" => {
                    t.scale = Vec3::zeros();
                    t.cross_axis = nalgebra::Matrix3::zeros();
                }
                "bias" => t.bias = Vec3::zeros(),
                "lsb" => t.lsb = 0.0,
                "gnoise" => {}
                x => panic!("unknown --drop {x}"),
            }
        }
        if d == "gnoise" {
            model.gyro.noise_density = 0.0;
        }
    }
    // the fixed part of the simulated gyro bias (the bias processes add ≈ 0.005 °/s)
    let b_true = model.gyro.bias;
    println!(
        "rate {rate} Hz, sensor {sensor}, vib lin {} ang {} ×{}; columns: RMSE ° over rests / motion / all (scored from the initial rest on)",
        vib.lin, vib.ang, vib.amp
    );
    println!(
        "{:<5}{:>8}{:>8}{:>8} {:>8}{:>8}{:>8} {:>9}{:>9}{:>10}{:>10}",
        "seed",
        "vqf rst",
        "mov",
        "all",
        "dyn rst",
        "mov",
        "all",
        "rest hit",
        "false",
        "|Δb| °/s",
        "max °/s"
    );
    let mut tot = [Acc::default(); 6];
    for seed in 1..=seeds {
        let (hand, m) = motion(seed, rate, &vib);
        let samples = model.simulate(m.as_ref(), rate, 120.0, seed);
        let dt = 1.0 / rate;
        let mut vqf = vqf_rs::VQF::new(dt, None, None, None);
        let mut dynf = Dynamic::new(params);
        if true_bias {
            // the fixed part of the true bias, not learnt: what is left without bias error
            let mut p = params;
            p.learn_bias = false;
            dynf = Dynamic::new(p);
            dynf.set_gyro_bias(b_true);
        }
        let mut acc = [Acc::default(); 6];
        let (mut rest_n, mut rest_hit, mut mov_n, mut false_rest) = (0.0, 0.0, 0.0, 0.0);
        let mut berr = Acc::default();
        let mut bmax = 0.0f64;
        let mut win = [Acc::default(); 2];
        let t0 = from.unwrap_or(hand.params.initial_rest_s);
        if series == Some(seed) {
            println!(
                "   t    rest  dynRest  vqf °   dyn °  Δb_x °/s Δb_y °/s Δb_z °/s  v_E mm/s v_N mm/s"
            );
        }
        // the rest detector's signals, replicated (same low-passes as the filter)
        let (k_vib, k_lp) = (
            1.0 - (-dt / params.vibration_tau_s).exp(),
            1.0 - (-dt / params.lowpass_tau_s).exp(),
        );
        let (mut gf, mut gl, mut af, mut al) =
            (Vec3::zeros(), Vec3::zeros(), Vec3::zeros(), Vec3::zeros());
        let mut first = true;
        // oracle zero-rate update: the mean raw gyro over each true rest (from 0.6 s in)
        let (mut o_sum, mut o_n, mut o_in) = (Vec3::zeros(), 0.0, 0.0);
        for s in &samples {
            if oracle {
                if hand.at_rest(s.t_s) && s.t_s > hand.params.initial_rest_s {
                    o_in += dt;
                    if o_in > 0.6 {
                        o_sum += s.gyr_rad_s;
                        o_n += 1.0;
                    }
                } else {
                    if o_n > 0.0 {
                        dynf.set_gyro_bias(o_sum / o_n);
                    }
                    (o_sum, o_n, o_in) = (Vec3::zeros(), 0.0, 0.0);
                }
            }
            if first {
                (gf, gl, af, al) = (s.gyr_rad_s, s.gyr_rad_s, s.acc_m_s2, s.acc_m_s2);
                first = false;
            }
            gf += (s.gyr_rad_s - gf) * k_vib;
            af += (s.acc_m_s2 - af) * k_vib;
            gl += (gf - gl) * k_lp;
            al += (af - al) * k_lp;
            if let Some((a, b)) = window
                && series == Some(seed)
                && s.t_s >= a
                && s.t_s <= b
                && ((s.t_s * rate).round() as u64) % ((rate / 20.0).max(1.0) as u64) == 0
            {
                let tr = m.truth(s.t_s).gyr_rad_s.norm().to_degrees();
                println!(
                    "  {:6.2} true|ω| {:7.3}°/s  |ωf-ωlp| {:6.3}°/s  |ωf-b| {:6.3}°/s  |ff-flp| {:6.3} m/s²  rest {}",
                    s.t_s,
                    tr,
                    (gf - gl).norm().to_degrees(),
                    (gf - dynf.gyro_bias()).norm().to_degrees(),
                    (af - al).norm(),
                    dynf.at_rest()
                );
            }
            let g = s.gyr_rad_s;
            let a = s.acc_m_s2;
            vqf.update([g.x, g.y, g.z], [a.x, a.y, a.z], None);
            let qv = vqf.quat_6d();
            let qv = Attitude::from_quaternion(nalgebra::Quaternion::new(qv.0, qv.1, qv.2, qv.3));
            dynf.update(g, a, dt);
            let truth = m.truth(s.t_s).attitude;
            let ev = inclination_error(&qv, &truth);
            let ed = inclination_error(&dynf.attitude(), &truth);
            win[0].push(ev);
            win[1].push(ed);
            let db = dynf.gyro_bias() - b_true;
            if series == Some(seed) && ((s.t_s * rate).round() as u64) % (rate as u64 / 2) == 0 {
                let v = dynf.velocity_residual();
                println!(
                    "{:6.1} {:>5} {:>7} {:7.3} {:7.3} {:9.4}{:9.4}{:9.4} {:9.2}{:9.2}",
                    s.t_s,
                    hand.at_rest(s.t_s),
                    dynf.at_rest(),
                    win[0].rms_deg(),
                    win[1].rms_deg(),
                    db.x.to_degrees(),
                    db.y.to_degrees(),
                    db.z.to_degrees(),
                    v[0] * 1e3,
                    v[1] * 1e3
                );
                win = [Acc::default(); 2];
            }
            if s.t_s < t0 {
                continue;
            }
            let r = hand.at_rest(s.t_s);
            let j = if r { 0 } else { 1 };
            acc[j].push(ev);
            acc[2].push(ev);
            acc[3 + j].push(ed);
            acc[5].push(ed);
            if r {
                rest_n += 1.0;
                if dynf.at_rest() {
                    rest_hit += 1.0;
                }
            } else {
                mov_n += 1.0;
                if dynf.at_rest() {
                    false_rest += 1.0;
                }
            }
            let dbn = Vec3::new(db.x, db.y, 0.0).norm().to_degrees();
            berr.push(dbn.to_radians());
            bmax = bmax.max(dbn);
        }
        for k in 0..6 {
            tot[k].s += acc[k].s;
            tot[k].n += acc[k].n;
        }
        println!(
            "{seed:<5}{:8.3}{:8.3}{:8.3} {:8.3}{:8.3}{:8.3} {:9.2}{:9.3}{:10.4}{:10.4}",
            acc[0].rms_deg(),
            acc[1].rms_deg(),
            acc[2].rms_deg(),
            acc[3].rms_deg(),
            acc[4].rms_deg(),
            acc[5].rms_deg(),
            rest_hit / rest_n,
            false_rest / mov_n,
            berr.rms_deg(),
            bmax
        );
    }
    println!(
        "{:<5}{:8.3}{:8.3}{:8.3} {:8.3}{:8.3}{:8.3}",
        "all",
        tot[0].rms_deg(),
        tot[1].rms_deg(),
        tot[2].rms_deg(),
        tot[3].rms_deg(),
        tot[4].rms_deg(),
        tot[5].rms_deg()
    );
}
