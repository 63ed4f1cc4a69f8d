//! `clino testbench`, `survey`, `calibrate` and `redundancy` end to end:
//! non-physical input refused with its location, flags that change the result,
//! and warnings where a number cannot be trusted.

use std::path::Path;
use std::process::{Command, Output};
use tempfile::TempDir;

fn clino(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(args)
        .output()
        .expect("run clino")
}

/// A fresh scratch directory for one test, removed when the value is dropped
/// (at the end of the test, passed or failed).
fn scratch(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("clino-cli-bsr-{name}-"))
        .tempdir()
        .unwrap()
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_string_lossy().into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn survey_refuses_a_non_physical_station_with_its_location() {
    let tmp = scratch("survey");
    let d = tmp.path();
    let f = write(
        d,
        "st.csv",
        "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT\n\
         100,0.5,0.2,-9.79,20,1,40\n\
         200,1e308,0.2,-9.79,20,1,40\n",
    );
    let o = clino(&["survey", &f]);
    assert!(!o.status.success(), "{}", stdout(&o));
    let e = stderr(&o);
    assert!(
        e.contains("st.csv:3:") && e.contains("acc_x_m_s2") && e.contains("4 g"),
        "{e}"
    );
    assert!(!e.contains("panicked"), "{e}");
}

#[test]
fn calibrate_refuses_a_non_physical_cell_before_the_solver() {
    let tmp = scratch("calib");
    let d = tmp.path();
    let mut text = String::from("t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n");
    for k in 0..40 {
        let v = if k == 9 {
            "1e308".to_string()
        } else {
            "0.1".into()
        };
        text += &format!("{},{v},0.2,9.8\n", k as f64 * 0.1);
    }
    let f = write(d, "rec.csv", &text);
    let out = d.join("cal.toml");
    let o = clino(&[
        "calibrate",
        "accel",
        &f,
        "--model",
        "matrix",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(
        e.contains("rec.csv:11:") && e.contains("acc_x_m_s2") && e.contains("physical bound"),
        "{e}"
    );
    assert!(!e.contains("User("), "{e}");
}

fn orbit(extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "testbench",
        "orbit",
        "--freq-hz",
        "0.8",
        "--sensor",
        "ideal",
        "--filter",
        "complementary:k=1",
        "--rate-hz",
        "100",
        "--json",
    ];
    args.extend_from_slice(extra);
    let o = clino(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_slice(&o.stdout).unwrap()
}

/// `--platform` runs the orbit on the servo legs' actual motion and
/// `--servo-hz` sets their bandwidth: both change the result.
#[test]
fn orbit_platform_and_servo_flags_change_the_result() {
    let exact = orbit(&[]);
    let fast = orbit(&["--platform"]);
    let slow = orbit(&["--platform", "--servo-hz", "1"]);
    assert_ne!(exact, fast);
    assert_ne!(fast, slow);
    let amp = |v: &serde_json::Value| v[0]["orbit_amplitude_mm"][0].as_f64().unwrap();
    let fit = |v: &serde_json::Value| v[0]["roll_fit_pp_deg"].as_f64().unwrap();
    assert!((amp(&exact) - 20.0).abs() < 0.1, "{exact}");
    // 1-Hz legs (ζ = 0.7) pass 85 % of a 0.8-Hz orbit
    assert!((amp(&slow) / 20.0 - 0.85).abs() < 0.01, "{slow}");
    assert!(
        (fit(&slow) / fit(&exact) - 0.85).abs() < 0.03,
        "{slow} {exact}"
    );
    // servo settings without the platform are refused, not ignored
    let o = clino(&["testbench", "orbit", "--servo-hz", "1", "--freq-hz", "0.8"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--platform"), "{}", stderr(&o));
}

/// Flags that did nothing are gone: `record` writes a CSV (no --json,
/// --plot, --platform: it always runs on the platform), `static` has no
/// platform.
#[test]
fn flags_that_did_nothing_are_refused() {
    let tmp = scratch("flags");
    let d = tmp.path();
    let f = d.join("r.csv");
    for extra in [["--json"].as_slice(), &["--plot", "x.svg"], &["--platform"]] {
        let mut args = vec!["testbench", "record", f.to_str().unwrap()];
        args.extend_from_slice(extra);
        let o = clino(&args);
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr(&o));
        assert!(!f.exists());
    }
    let o = clino(&["testbench", "static", "--platform", "--duration-s", "20"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn analyze_with_the_wrong_excitation_is_an_error() {
    let tmp = scratch("analyze");
    let d = tmp.path();
    let cone = d.join("cone.csv");
    let orb = d.join("orbit.csv");
    let common = [
        "--sensor",
        "ideal",
        "--filter",
        "poisson",
        "--rate-hz",
        "100",
    ];
    for (path, exc, dur) in [(&cone, "conical", "8"), (&orb, "orbit", "12")] {
        let mut args = vec![
            "testbench",
            "record",
            path.to_str().unwrap(),
            "--excitation",
            exc,
            "--freq-hz",
            "1",
            "--duration-s",
            dur,
        ];
        args.extend_from_slice(&common);
        let o = clino(&args);
        assert!(o.status.success(), "{}", stderr(&o));
    }
    // the right excitation works
    let o = clino(&[
        "testbench",
        "analyze",
        cone.to_str().unwrap(),
        "--skip-s",
        "2",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    // a cone read as an orbit, an orbit read as a cone: refused, with a hint
    for (path, wrong, right) in [(&cone, "orbit", "conical"), (&orb, "conical", "orbit")] {
        let o = clino(&[
            "testbench",
            "analyze",
            path.to_str().unwrap(),
            "--excitation",
            wrong,
            "--skip-s",
            "4",
        ]);
        let e = stderr(&o);
        assert!(!o.status.success(), "{wrong}: {}", stdout(&o));
        assert!(
            e.contains(&format!("no {wrong} excitation"))
                && e.contains(&format!("--excitation {right}")),
            "{e}"
        );
    }
}

#[test]
fn fault_lists_are_comma_separated_and_unisolable_sets_warn() {
    // "1234" is chain 1234 or chains 1, 2, 3, 4: refused, with the hint
    let o = clino(&["redundancy", "simulate", "--faults", "1234"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("1,2,3,4"), "{}", stderr(&o));
    let o = clino(&["redundancy", "simulate", "--faults", "1,2,3,4"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (out, e) = (stdout(&o), stderr(&o));
    assert!(out.contains("faults 1,2,3,4"), "{out}");
    assert!(e.contains("warning") && e.contains("not isolable"), "{e}");
    // the source's example: no warning, restored
    let o = clino(&["redundancy", "simulate", "--faults", "2,3,9"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stderr(&o).contains("warning"), "{}", stderr(&o));
    assert!(stdout(&o).contains("diagnosed 2,3,9"), "{}", stdout(&o));
}

/// A recording of an accelerometer on a fixture: each housing axis up, then
/// down (+x −x +y −y +z −z), 3 s still each at 100 Hz with a small
/// deterministic jitter, 1 s of turning between poses. Raw = K·f + u0 with a
/// known scale error, so the six-position method has something to find.
fn six_pose_recording(dir: &Path) -> String {
    let g = 9.80665;
    let ups: [[f64; 3]; 6] = [
        [1.0, 0.0, 0.0],
        [-1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, -1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -1.0],
    ];
    let scale = [1.02, 0.98, 1.01];
    let bias = [0.05, -0.03, 0.08];
    let mut text = String::from("t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n");
    let mut k = 0usize;
    let mut row = |f: [f64; 3], text: &mut String| {
        // jitter: a fixed pseudo-random sequence, about 0.01 m/s²
        let j = |a: usize| ((k * 7919 + a * 104729) % 1000) as f64 / 1000.0 - 0.5;
        let v: Vec<String> = (0..3)
            .map(|i| format!("{:.6}", scale[i] * f[i] * g + bias[i] + 0.02 * j(i)))
            .collect();
        text.push_str(&format!("{:.2},{}\n", k as f64 * 0.01, v.join(",")));
        k += 1;
    };
    for p in 0..6 {
        for _ in 0..300 {
            row(ups[p], &mut text);
        }
        if p + 1 < 6 {
            let (a, b) = (ups[p], ups[p + 1]);
            for s in 1..100 {
                // turn through a third direction so the vector keeps its length
                let t = s as f64 / 100.0 * std::f64::consts::PI;
                let c = [b[1].abs(), b[2].abs(), b[0].abs()];
                let m: [f64; 3] = std::array::from_fn(|i| {
                    (a[i] + b[i]) / 2.0 + (a[i] - b[i]) / 2.0 * t.cos() + c[i] * t.sin()
                });
                let n = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                row([m[0] / n, m[1] / n, m[2] / n], &mut text);
            }
        }
    }
    write(dir, "six.csv", &text)
}

#[test]
fn six_position_prints_parameters_with_one_sigma() {
    let tmp = scratch("six");
    let d = tmp.path();
    let f = six_pose_recording(d);
    let out = d.join("cal.toml");
    let o = clino(&[
        "calibrate",
        "accel",
        &f,
        "--model",
        "six",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = stdout(&o);
    assert!(!s.contains("K = [["), "Debug arrays: {s}");
    assert!(
        s.contains("parameter        value          1σ            unit"),
        "{s}"
    );
    // M = K⁻¹: the diagonal undoes the scale error, with a small 1σ
    let row = |name: &str| -> (f64, f64) {
        let l = s
            .lines()
            .find(|l| l.starts_with(&format!("{name} ")))
            .unwrap_or_else(|| panic!("{name} in {s}"));
        let v: Vec<&str> = l.split_whitespace().collect();
        (v[1].parse().unwrap(), v[2].parse().unwrap())
    };
    for (name, scale) in [("M_xx", 1.02), ("M_yy", 0.98), ("M_zz", 1.01)] {
        let (v, sigma) = row(name);
        assert!((v - 1.0 / scale).abs() < 1e-3, "{name} {v}");
        assert!(sigma > 0.0 && sigma < 1e-3, "{name} σ {sigma}");
    }
    let (u0x, sigma) = row("u0_x");
    assert!((u0x - 0.05).abs() < 5e-3 && sigma > 0.0, "{u0x} {sigma}");
    // the 1σ reach the calibration file too
    let toml = std::fs::read_to_string(&out).unwrap();
    assert!(toml.contains("M_xx") && toml.contains("u0_z"), "{toml}");
}

#[test]
fn a_plot_that_cannot_be_written_keeps_the_calibration() {
    let tmp = scratch("plotpath");
    let d = tmp.path();
    let f = six_pose_recording(d);
    let out = d.join("cal.toml");
    // a name that cannot be a plot is refused before the fit, nothing written
    let missing = d.join("no-such-dir").join("p.svg");
    let o = clino(&[
        "calibrate",
        "accel",
        &f,
        "--model",
        "six",
        "-o",
        out.to_str().unwrap(),
        "--plot",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
    assert!(!out.exists());
    // a plot that fails to write after the fit: the calibration is kept, the error reported
    let dir_as_plot = d.join("taken.svg");
    std::fs::create_dir_all(&dir_as_plot).unwrap();
    let o = clino(&[
        "calibrate",
        "accel",
        &f,
        "--model",
        "six",
        "-o",
        out.to_str().unwrap(),
        "--plot",
        dir_as_plot.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("the calibration was saved to") && e.contains("taken.svg"),
        "{e}"
    );
    assert!(stdout(&o).contains("wrote "), "{}", stdout(&o));
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .contains("six-position method")
    );
    // and a good path writes both
    let good = d.join("ok.svg");
    let o = clino(&[
        "calibrate",
        "accel",
        &f,
        "--model",
        "six",
        "-o",
        out.to_str().unwrap(),
        "--plot",
        good.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read_to_string(&good).unwrap().contains("<svg"));
}

#[test]
fn calibrate_help_lists_only_what_applies() {
    let help = |what: &str| stdout(&clino(&["calibrate", what, "--help"]));
    let (accel, gyro, mag) = (help("accel"), help("gyro"), help("mag"));
    for h in [&accel, &gyro, &mag] {
        assert!(
            h.contains("--output") && h.contains("--json") && h.contains("--plot"),
            "{h}"
        );
    }
    assert!(
        accel.contains("--g-m-s2") && accel.contains("--window-s") && accel.contains("six"),
        "{accel}"
    );
    assert!(
        !accel.contains("--field-ut") && !accel.contains("--accel-calibration"),
        "{accel}"
    );
    assert!(
        gyro.contains("--accel-calibration") && gyro.contains("--min-pose-s"),
        "{gyro}"
    );
    assert!(
        !gyro.contains("--field-ut") && !gyro.contains("--g-m-s2"),
        "{gyro}"
    );
    assert!(
        !gyro.contains("[possible values: matrix, mwd12, mwd30, six]"),
        "{gyro}"
    );
    assert!(mag.contains("--field-ut"), "{mag}");
    assert!(
        !mag.contains("--window-s")
            && !mag.contains("--accel-calibration")
            && !mag.contains("--g-m-s2"),
        "{mag}"
    );
    // six is an accelerometer method: the gyro refuses it with the list of models
    let o = clino(&[
        "calibrate",
        "gyro",
        "x.csv",
        "-o",
        "x.toml",
        "--model",
        "six",
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("[possible values: matrix, mwd12, mwd30]"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_wrong_choice_lists_the_possible_values() {
    let cases: [(&[&str], &str); 6] = [
        (
            &[
                "redundancy",
                "simulate",
                "--faults",
                "2",
                "--fault-kind",
                "wobble",
            ],
            "stuck, bias, drift, noise",
        ),
        (
            &["redundancy", "sweep", "--fault-kind", "wobble"],
            "stuck, bias, drift, noise, all",
        ),
        (&["testbench", "conical", "--axis", "w"], "x, y, z"),
        (
            &["testbench", "static", "--sensor", "bmi160"],
            "ideal, mpu6050, mpu6050-raw",
        ),
        (&["allan", "r.csv", "--gaps", "fill"], "refuse, longest"),
        (
            &["fuse", "in.csv", "--gyro-unit", "furlong"],
            "rad/s, deg/s",
        ),
    ];
    for (args, values) in cases {
        let o = clino(args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let e = stderr(&o);
        assert!(
            e.contains("invalid value") && e.contains(&format!("[possible values: {values}]")),
            "{args:?}: {e}"
        );
    }
    for (args, values) in [
        (&["fuse", "in.csv", "--accel-unit", "ft/s2"][..], "m/s2, g"),
        (
            &["fuse", "in.csv", "--integrator", "euler"][..],
            "exact, rectangle",
        ),
        (
            &["testbench", "analyze", "r.csv", "--excitation", "sine"][..],
            "conical, orbit",
        ),
        (
            &[
                "calibrate",
                "mag",
                "r.csv",
                "-o",
                "c.toml",
                "--model",
                "mwd99",
            ][..],
            "matrix, mwd12, mwd30",
        ),
    ] {
        let e = stderr(&clino(args));
        assert!(
            e.contains(&format!("[possible values: {values}]")),
            "{args:?}: {e}"
        );
    }
}

#[test]
fn the_old_spellings_are_still_accepted() {
    let tmp = scratch("spell");
    let d = tmp.path();
    let mut text = String::from("t_s,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z\n");
    for k in 0..50 {
        text += &format!("{},0,0,0,0,0,1\n", k as f64 * 0.01);
    }
    let f = write(d, "bare.csv", &text);
    let mut outs = Vec::new();
    for (gu, au) in [("deg/s", "g"), ("dps", "G"), ("deg_s", "g"), ("DEG/S", "g")] {
        let o = clino(&[
            "fuse",
            &f,
            "-f",
            "mahony",
            "--gyro-unit",
            gu,
            "--accel-unit",
            au,
            "-o",
            "-",
        ]);
        assert!(o.status.success(), "{gu} {au}: {}", stderr(&o));
        outs.push(stdout(&o));
    }
    assert!(outs.windows(2).all(|w| w[0] == w[1]));
    for u in ["rad/s", "rad_s", "m/s2"] {
        let flag = if u == "m/s2" {
            "--accel-unit"
        } else {
            "--gyro-unit"
        };
        let o = clino(&["fuse", &f, "-f", "mahony", flag, u, "-o", "-"]);
        assert!(o.status.success(), "{u}: {}", stderr(&o));
    }
}
