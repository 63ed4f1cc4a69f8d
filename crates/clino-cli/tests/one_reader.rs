//! Issue 10's rule for every command that reads a recording: a comment line,
//! a byte-order mark or CRLF line endings change nothing; one reader, one set
//! of rules.

mod common;

use common::clino;
use std::path::PathBuf;
use std::process::Command;
use tempfile::TempDir;

/// The same content under the same file name in two directories: plain, and
/// with a BOM, comment lines before the header and between rows, and CRLF.
/// Both lie in the returned scratch directory, removed when it is dropped.
fn variants(test: &str, text: &str) -> (TempDir, PathBuf, PathBuf) {
    let base = common::scratch("one-reader", test);
    let (a, b) = (base.path().join("plain"), base.path().join("dressed"));
    for d in [&a, &b] {
        std::fs::create_dir_all(d).unwrap();
    }
    let plain: String = text
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    let mut dressed = String::from("\u{feff}# exported by a spreadsheet\r\n# second comment\r\n");
    for (i, l) in plain.lines().enumerate() {
        dressed.push_str(l);
        dressed.push_str("\r\n");
        if i == 3 {
            dressed.push_str("# a comment between rows\r\n");
        }
    }
    std::fs::write(a.join("rec.csv"), plain).unwrap();
    std::fs::write(b.join("rec.csv"), dressed).unwrap();
    (base, a.join("rec.csv"), b.join("rec.csv"))
}

fn same_output(args: &[&str], a: &PathBuf, b: &PathBuf) {
    let run = |p: &PathBuf| {
        let mut v: Vec<&str> = args.to_vec();
        let s = p.to_str().unwrap().to_string();
        let s: &'static str = Box::leak(s.into_boxed_str());
        let dir = p.parent().unwrap().to_str().unwrap().to_string();
        let out: &'static str = Box::leak(format!("{dir}/out.toml").into_boxed_str());
        for x in v.iter_mut() {
            if *x == "{}" {
                *x = s;
            } else if *x == "{out}" {
                *x = out;
            }
        }
        let o = clino(&v);
        assert!(
            o.status.success(),
            "{args:?} on {}: {}",
            p.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        // line numbers legitimately count the comment lines: drop them
        let text = String::from_utf8_lossy(&o.stdout).replace(&dir, "DIR");
        let mut kept = String::new();
        let mut skipping = false;
        for l in text.lines() {
            if l.contains("\"lines\": [") {
                skipping = !l.contains(']');
                continue;
            }
            if skipping {
                skipping = !l.contains(']');
                continue;
            }
            if l.trim_start().starts_with("\"line\":") {
                continue;
            }
            kept.push_str(l);
            kept.push('\n');
        }
        kept
    };
    assert_eq!(run(a), run(b), "{args:?}");
}

const EXCERPT: &str = include_str!("../../clino/data/broad_07_excerpt.csv");

#[test]
fn fuse_eval_allan_and_static_ignore_comments_bom_and_crlf() {
    let (_base, a, b) = variants("imu", EXCERPT);
    same_output(&["fuse", "{}"], &a, &b);
    same_output(&["fuse", "{}", "--filter", "mahony:kp=0.5"], &a, &b);
    same_output(&["eval", "{}", "-f", "dynamic,madgwick"], &a, &b);
    same_output(&["allan", "{}", "--json"], &a, &b);
}

#[test]
fn calibration_and_survey_recordings_read_comments_too() {
    // a `#` line used to make `calibrate` say "the recording needs a time column"
    let rec = common::accel_poses_csv();
    let (_base, a, b) = variants("calib", &rec);
    same_output(
        &["calibrate", "accel", "{}", "--output", "{out}", "--json"],
        &a,
        &b,
    );
    let stations = "md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT\n\
                    100,0.5,0.3,9.79,20,1,-40\n200,0.9,0.2,9.75,19,3,-41\n300,1.5,0.1,9.68,18,4,-41\n";
    let (_base, a, b) = variants("survey", stations);
    same_output(&["survey", "{}", "--json"], &a, &b);
}

#[test]
fn parquet_in_and_out_equals_the_csv_path_to_the_last_bit() {
    let tmp = common::scratch("parquet", "csv-path");
    let d = tmp.path();
    let csv_in = d.join("in.csv");
    std::fs::write(&csv_in, EXCERPT).unwrap();
    let p = |n: &str| d.join(n).to_str().unwrap().to_string();
    let ok = |args: &[&str]| {
        let o = clino(args);
        assert!(
            o.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    };
    ok(&["convert", csv_in.to_str().unwrap(), &p("in.parquet")]);
    for f in ["dynamic", "mahony", "complementary:tau=0.2"] {
        ok(&["fuse", csv_in.to_str().unwrap(), "-f", f, "-o", &p("a.csv")]);
        ok(&["fuse", &p("in.parquet"), "-f", f, "-o", &p("a.parquet")]);
        ok(&["convert", &p("a.parquet"), &p("b.csv"), "--text", "status"]);
        let (a, b) = (
            std::fs::read(d.join("a.csv")).unwrap(),
            std::fs::read(d.join("b.csv")).unwrap(),
        );
        assert!(a == b, "{f}: Parquet path differs from CSV path");
    }
    // the same rules: eval reads the Parquet recording like the CSV one
    let e1 = clino(&["eval", csv_in.to_str().unwrap(), "-f", "dynamic", "--json"]);
    let e2 = clino(&["eval", &p("in.parquet"), "-f", "dynamic", "--json"]);
    let strip = |o: &std::process::Output| {
        String::from_utf8_lossy(&o.stdout).replace("in.parquet", "in.csv")
    };
    assert_eq!(strip(&e1), strip(&e2));
    // not a Parquet file: a clear error naming it, nothing written
    std::fs::write(d.join("bad.parquet"), "t_s,x\n1,2\n").unwrap();
    let o = clino(&["fuse", &p("bad.parquet"), "-o", &p("out.csv")]);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("bad.parquet") && err.contains("Parquet"),
        "{err}"
    );
    assert!(!d.join("out.csv").exists());
}

#[test]
fn fuse_behind_a_pipe_answers_each_row_as_it_arrives() {
    use std::io::{BufRead, BufReader, Write};
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(["fuse", "-", "-f", "mahony"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    stdin
        .write_all(b"t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n")
        .unwrap();
    let mut line = String::new();
    out.read_line(&mut line).unwrap();
    assert!(line.starts_with("t_s,qw"), "{line}");
    for k in 0..50 {
        // the input stays open: each output row must come before the next input row
        writeln!(stdin, "{},0,0,0,0,0,9.81", k as f64 * 0.01).unwrap();
        stdin.flush().unwrap();
        line.clear();
        out.read_line(&mut line).unwrap();
        assert!(
            line.starts_with(&format!("{}", k as f64 * 0.01)),
            "row {k}: {line}"
        );
    }
    drop(stdin);
    assert!(child.wait().unwrap().success());
}

/// `-o /dev/stdout` with stdout redirected to a file: the rows land in that
/// file (appended, as `>>` expects) and `/dev/stdout` stays what it was —
/// an output under /dev is written in place, never renamed over.
#[cfg(target_os = "linux")]
#[test]
fn an_output_under_dev_is_written_in_place() {
    let tmp = common::scratch("one-reader", "dev-stdout");
    let d = tmp.path();
    let input = d.join("in.csv");
    std::fs::write(&input, "t_s,x\n0,1.5\n1,2.5\n").unwrap();
    let out = d.join("out.csv");
    std::fs::write(&out, "before\n").unwrap();
    let sink = std::fs::OpenOptions::new().append(true).open(&out).unwrap();
    let before = std::fs::symlink_metadata("/dev/stdout").map(|m| m.file_type());
    let status = Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(["convert", input.to_str().unwrap(), "/dev/stdout"])
        .stdout(sink)
        .status()
        .unwrap();
    assert!(status.success());
    let after = std::fs::symlink_metadata("/dev/stdout").map(|m| m.file_type());
    assert_eq!(
        format!("{before:?}"),
        format!("{after:?}"),
        "/dev/stdout was replaced"
    );
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        "before\nt_s,x\n0.0,1.5\n1.0,2.5\n"
    );
}
