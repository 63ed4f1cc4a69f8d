//! `clino testbench`, `survey`, `calibrate` and `redundancy` end to end:
//! non-physical input refused with its location, flags that change the result,
//! and warnings where a number cannot be trusted.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn clino(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(args)
        .output()
        .expect("run clino")
}

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("clino-cli-bsr-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
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
    let d = scratch("survey");
    let f = write(
        &d,
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
    let d = scratch("calib");
    let mut text = String::from("t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n");
    for k in 0..40 {
        let v = if k == 9 {
            "1e308".to_string()
        } else {
            "0.1".into()
        };
        text += &format!("{},{v},0.2,9.8\n", k as f64 * 0.1);
    }
    let f = write(&d, "rec.csv", &text);
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
    let d = scratch("flags");
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
    let d = scratch("analyze");
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
