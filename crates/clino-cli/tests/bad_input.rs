//! Bad input, tested once for every command that reads a file (issue 10,
//! item 6): each case gets its documented result or a clear error naming the
//! file (and the line, for a defect in a row) with a non-zero exit — never a
//! panic, never a message that echoes megabytes, never a half-written output.

use std::path::Path;
mod common;

use common::clino;
use std::process::Output;
use tempfile::TempDir;

fn scratch(name: &str) -> TempDir {
    common::scratch("bad-input", name)
}

const EXCERPT: &str = include_str!("../../clino/data/broad_07_excerpt.csv");

/// One command that reads a file: how to make a valid file for it and how to
/// call it (`{in}` is the recording, `{out}` an output path in a fresh directory).
struct Cmd {
    name: &'static str,
    args: Vec<String>,
    /// The valid recording (CSV, no comments).
    base: String,
    /// A required numeric column to corrupt or remove.
    col: usize,
    /// Whether column 0 must increase strictly (time); measured depth may
    /// repeat (a roll test: several readings at one station).
    strictly_increasing: bool,
}

/// What a case must give.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Expect {
    /// A clear error, non-zero exit.
    Error,
    /// An error that names the line of the defect.
    ErrorAtLine(u64),
    /// The same exit status as the valid file (the reader's rules make it equal).
    AsValid,
    /// Either a result (documented: flagged, skipped, warned) or a clear error.
    ResultOrError,
}

fn strip_comments(text: &str) -> String {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect()
}

fn set_cell(rows: &mut [String], row: usize, col: usize, value: &str) {
    let mut cells: Vec<String> = rows[row].split(',').map(str::to_string).collect();
    cells[col] = value.to_string();
    rows[row] = cells.join(",");
}

/// The cases: a name, the file's bytes (or `None` for a path case) and what it must give.
fn cases(c: &Cmd) -> Vec<(&'static str, Vec<u8>, Expect)> {
    let mut lines = c.base.lines().map(str::to_string);
    let header = lines.next().unwrap();
    let rows: Vec<String> = lines.collect();
    let join = |h: &str, r: &[String], eol: &str| -> Vec<u8> {
        let mut s = format!("{h}{eol}");
        for l in r {
            s.push_str(l);
            s.push_str(eol);
        }
        s.into_bytes()
    };
    // the defect sits in data row 3: line 5 (line 1 is the header)
    let (bad_row, bad_line) = (3usize, 5u64);
    let with = |value: &str| {
        let mut r = rows.clone();
        set_cell(&mut r, bad_row, c.col, value);
        join(&header, &r, "\n")
    };
    let t = |k: usize| rows[k].split(',').next().unwrap().to_string();
    let repeat = if c.strictly_increasing {
        Expect::ErrorAtLine(bad_line)
    } else {
        Expect::ResultOrError
    };
    let mut out = vec![
        ("empty", Vec::new(), Expect::Error),
        (
            "header-only",
            format!("{header}\n").into_bytes(),
            Expect::Error,
        ),
        (
            "comments",
            {
                let mut s = format!("# a comment\n# another\n{header}\n");
                for (i, l) in rows.iter().enumerate() {
                    s.push_str(l);
                    s.push('\n');
                    if i == 2 {
                        s.push_str("# between rows\n");
                    }
                }
                s.into_bytes()
            },
            Expect::AsValid,
        ),
        (
            "bom",
            {
                let mut b = "\u{feff}".as_bytes().to_vec();
                b.extend(join(&header, &rows, "\n"));
                b
            },
            Expect::AsValid,
        ),
        ("crlf", join(&header, &rows, "\r\n"), Expect::AsValid),
        (
            "semicolons",
            join(
                &header.replace(',', ";"),
                &rows.iter().map(|r| r.replace(',', ";")).collect::<Vec<_>>(),
                "\n",
            ),
            Expect::Error,
        ),
        (
            "missing-column",
            {
                let drop = |l: &str| {
                    l.split(',')
                        .enumerate()
                        .filter(|(i, _)| *i != c.col)
                        .map(|(_, x)| x)
                        .collect::<Vec<_>>()
                        .join(",")
                };
                join(
                    &drop(&header),
                    &rows.iter().map(|r| drop(r)).collect::<Vec<_>>(),
                    "\n",
                )
            },
            Expect::Error,
        ),
        ("non-numeric", with("abc"), Expect::ErrorAtLine(bad_line)),
        ("nan", with("NaN"), Expect::ResultOrError),
        ("inf", with("inf"), Expect::ResultOrError),
        ("1e308", with("1e308"), Expect::ResultOrError),
        (
            "megabyte-line",
            with(&"7".repeat(1 << 20).replace('7', "x")),
            Expect::ErrorAtLine(bad_line),
        ),
        (
            "binary",
            (0..4096u32)
                .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
                .collect(),
            Expect::Error,
        ),
    ];
    {
        // time (or depth) going backwards, and repeating
        let mut r = rows.clone();
        let (a, b) = (t(bad_row - 1), t(bad_row));
        set_cell(&mut r, bad_row, 0, &a);
        out.push(("repeated-time", join(&header, &r, "\n"), repeat));
        let mut r = rows.clone();
        set_cell(&mut r, bad_row - 1, 0, &b);
        set_cell(&mut r, bad_row, 0, &a);
        // row 2 now holds row 3's time and row 3 row 2's: backwards at row 3
        out.push((
            "time-backwards",
            join(&header, &r, "\n"),
            Expect::ErrorAtLine(bad_line),
        ));
        // a large gap: 1000 added to the time of every row from row 5 on
        let mut r = rows.clone();
        for (k, row) in r.iter_mut().enumerate().skip(5) {
            let v: f64 = t(k).parse().unwrap();
            let mut cells: Vec<String> = row.split(',').map(str::to_string).collect();
            cells[0] = format!("{}", v + 1000.0);
            *row = cells.join(",");
        }
        out.push(("large-gap", join(&header, &r, "\n"), Expect::ResultOrError));
    }
    out
}

/// Run `c` on `input`; check the universal rules and return the output.
fn run(c: &Cmd, dir: &Path, input: &str, case: &str) -> Output {
    let out_dir = dir.join(format!("out-{case}"));
    let _ = std::fs::remove_dir_all(&out_dir);
    std::fs::create_dir_all(&out_dir).unwrap();
    let out = out_dir.join("result");
    let args: Vec<String> = c
        .args
        .iter()
        .map(|a| {
            a.replace("{in}", input)
                .replace("{out}", out.to_str().unwrap())
        })
        .collect();
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = clino(&args);
    let e = String::from_utf8_lossy(&o.stderr);
    let what = format!("{} on {case}", c.name);
    assert!(o.status.code().is_some(), "{what}: killed by a signal");
    assert_ne!(o.status.code(), Some(101), "{what}: panicked: {e}");
    assert!(!e.contains("panicked"), "{what}: {e}");
    assert!(e.len() < 4000, "{what}: a {}-byte message", e.len());
    if !o.status.success() {
        let name = Path::new(input).file_name().unwrap().to_str().unwrap();
        assert!(
            e.contains(name),
            "{what}: the error does not name {name}: {e}"
        );
        let left: Vec<_> = std::fs::read_dir(&out_dir).unwrap().collect();
        assert!(left.is_empty(), "{what}: failed but left {left:?}");
    }
    o
}

fn check(c: &Cmd, dir: &Path, ext: &str, cases: &[(&'static str, Vec<u8>, Expect)]) {
    let base = dir.join(format!("valid.{ext}"));
    let valid = run(c, dir, base.to_str().unwrap(), "valid");
    assert!(
        valid.status.success(),
        "{} on its valid file: {}",
        c.name,
        String::from_utf8_lossy(&valid.stderr)
    );
    for (case, bytes, expect) in cases {
        let p = dir.join(format!("{case}.{ext}"));
        if ext == "csv" {
            std::fs::write(&p, bytes).unwrap();
        } else if !p.exists() {
            continue;
        }
        let o = run(c, dir, p.to_str().unwrap(), case);
        let e = String::from_utf8_lossy(&o.stderr);
        let what = format!("{} on {case}.{ext}", c.name);
        match expect {
            Expect::Error => assert!(!o.status.success(), "{what}: exit 0"),
            Expect::ErrorAtLine(line) => {
                assert!(!o.status.success(), "{what}: exit 0");
                let at = format!("{case}.{ext}:{line}");
                assert!(e.contains(&at), "{what}: the error does not say {at}: {e}");
            }
            Expect::AsValid => {
                assert_eq!(o.status.success(), valid.status.success(), "{what}: {e}")
            }
            Expect::ResultOrError => {}
        }
    }
    // paths: a directory, a missing file
    let d = dir.join(format!("a-directory-{ext}"));
    std::fs::create_dir_all(&d).unwrap();
    let o = run(c, dir, d.to_str().unwrap(), "directory");
    assert!(!o.status.success(), "{} on a directory: exit 0", c.name);
    let o = run(
        c,
        dir,
        dir.join(format!("missing.{ext}")).to_str().unwrap(),
        "missing",
    );
    assert!(!o.status.success(), "{} on a missing file: exit 0", c.name);
}

/// The Parquet variants: every case `clino convert` can turn into Parquet
/// (a valid one, NaN, inf, 1e308, order and gap defects, a missing column),
/// plus bytes that are not Parquet at all.
fn parquet_cases(dir: &Path, cases: &[(&'static str, Vec<u8>, Expect)]) {
    let csv = dir.join("valid.csv");
    let o = clino(&[
        "convert",
        csv.to_str().unwrap(),
        dir.join("valid.parquet").to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for (case, _, _) in cases {
        let src = dir.join(format!("{case}.csv"));
        let dst = dir.join(format!("{case}.parquet"));
        let _ = std::fs::remove_file(&dst);
        if [
            "nan",
            "inf",
            "1e308",
            "repeated-time",
            "time-backwards",
            "large-gap",
            "missing-column",
        ]
        .contains(case)
        {
            let o = clino(&["convert", src.to_str().unwrap(), dst.to_str().unwrap()]);
            assert!(
                o.status.success(),
                "convert {case}: {}",
                String::from_utf8_lossy(&o.stderr)
            );
        }
    }
    let valid = std::fs::read(dir.join("valid.parquet")).unwrap();
    std::fs::write(dir.join("empty.parquet"), b"").unwrap();
    std::fs::write(dir.join("binary.parquet"), &valid[valid.len() / 3..]).unwrap();
    std::fs::write(dir.join("truncated.parquet"), &valid[..valid.len() / 2]).unwrap();
}

fn commands(dir: &Path) -> Vec<Cmd> {
    let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    let imu: String = strip_comments(EXCERPT)
        .lines()
        .take(3000)
        .map(|l| format!("{l}\n"))
        .collect();
    // accelerometer poses (12 of them), as in the one-reader test
    let accel = common::accel_poses_csv();
    // gyro on a rate table: ±0.5, ±1 rad/s about each axis
    let mut gyro = String::from(
        "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,ref_gyr_x_rad_s,ref_gyr_y_rad_s,ref_gyr_z_rad_s\n",
    );
    let mut k = 0;
    for ax in 0..3 {
        for r in [-1.0, -0.5, 0.5, 1.0] {
            for _ in 0..200 {
                let mut w = [0.0; 3];
                w[ax] = r;
                gyro.push_str(&format!(
                    "{},{},{},{},{},{},{}\n",
                    k as f64 * 0.01,
                    1.01 * w[0] + 0.002,
                    0.99 * w[1] - 0.001 + 0.001 * w[0],
                    1.02 * w[2] + 0.003,
                    w[0],
                    w[1],
                    w[2]
                ));
                k += 1;
            }
        }
    }
    // magnetometer over the sphere, hard and soft iron
    let mut mag = String::from("t_s,mag_x_uT,mag_y_uT,mag_z_uT\n");
    let mut k = 0;
    for i in 0..20 {
        for j in 0..20 {
            let (th, ph) = (
                std::f64::consts::PI * (i as f64 + 0.5) / 20.0,
                std::f64::consts::TAU * j as f64 / 20.0,
            );
            let (x, y, z) = (th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
            mag.push_str(&format!(
                "{},{},{},{}\n",
                k as f64 * 0.01,
                50.4 * x + 3.0,
                46.6 * y - 2.0,
                48.0 * z + 1.0
            ));
            k += 1;
        }
    }
    let mut stations =
        String::from("md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT\n");
    for k in 0..12 {
        let a = 0.1 * k as f64;
        stations.push_str(&format!(
            "{},{},0.3,{},20,{},-40\n",
            100 + 30 * k,
            0.5 + a,
            9.79 - 0.05 * a,
            1.0 + a
        ));
    }
    // a lab recording and a redundant-accelerometer recording, made by clino itself
    let lab = dir.join("lab-source.csv");
    let o = clino(&[
        "testbench",
        "record",
        lab.to_str().unwrap(),
        "--excitation",
        "conical",
        "--freq-hz",
        "1",
        "--duration-s",
        "8",
        "--sensor",
        "ideal",
        "--filter",
        "poisson",
        "--rate-hz",
        "100",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let red = dir.join("red-source.csv");
    let o = clino(&[
        "redundancy",
        "simulate",
        "--faults",
        "2",
        "--out",
        red.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let read = |p: &Path| strip_comments(&std::fs::read_to_string(p).unwrap());
    // a calibration to apply
    let acc_file = dir.join("accel-source.csv");
    std::fs::write(&acc_file, &accel).unwrap();
    let cal = dir.join("cal.toml");
    let o = clino(&[
        "calibrate",
        "accel",
        acc_file.to_str().unwrap(),
        "--model",
        "matrix",
        "-o",
        cal.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let cal = cal.to_str().unwrap().to_string();
    let cmd = |name, args: Vec<String>, base: &str, col| Cmd {
        name,
        args,
        base: base.to_string(),
        col,
        strictly_increasing: name != "survey",
    };
    vec![
        cmd("fuse", s(&["fuse", "{in}", "-o", "{out}.csv"]), &imu, 1),
        cmd(
            "fuse --offline",
            s(&["fuse", "{in}", "--offline", "-o", "{out}.parquet"]),
            &imu,
            1,
        ),
        cmd("eval", s(&["eval", "{in}", "-f", "mahony"]), &imu, 1),
        cmd("allan", s(&["allan", "{in}"]), &imu, 1),
        cmd(
            "testbench static",
            s(&["testbench", "static", "{in}", "--settle-s", "1"]),
            &imu,
            1,
        ),
        cmd(
            "calibrate accel",
            s(&[
                "calibrate",
                "accel",
                "{in}",
                "--model",
                "matrix",
                "-o",
                "{out}.toml",
            ]),
            &accel,
            1,
        ),
        cmd(
            "calibrate gyro",
            s(&["calibrate", "gyro", "{in}", "-o", "{out}.toml"]),
            &gyro,
            1,
        ),
        cmd(
            "calibrate mag",
            s(&["calibrate", "mag", "{in}", "-o", "{out}.toml"]),
            &mag,
            1,
        ),
        cmd(
            "calibrate apply",
            vec![
                "calibrate".into(),
                "apply".into(),
                cal,
                "{in}".into(),
                "-o".into(),
                "{out}.csv".into(),
            ],
            &accel,
            1,
        ),
        cmd("survey", s(&["survey", "{in}"]), &stations, 1),
        cmd(
            "testbench analyze",
            s(&["testbench", "analyze", "{in}", "--skip-s", "2"]),
            &read(&lab),
            7, // q_w: the gyro and accelerometer columns are optional here
        ),
        cmd(
            "redundancy diagnose",
            s(&["redundancy", "diagnose", "{in}"]),
            &read(&red),
            1,
        ),
    ]
}

#[test]
fn every_command_that_reads_a_file_meets_the_bad_input_matrix() {
    let tmp = scratch("matrix");
    let root = tmp.path();
    for c in commands(root) {
        let dir = root.join(c.name.replace(' ', "-"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("valid.csv"), &c.base).unwrap();
        let cs = cases(&c);
        check(&c, &dir, "csv", &cs);
        parquet_cases(&dir, &cs);
        let pq: Vec<_> = cs
            .iter()
            .map(|(n, b, e)| {
                (
                    *n,
                    b.clone(),
                    if *e == Expect::AsValid {
                        Expect::ResultOrError
                    } else {
                        *e
                    },
                )
            })
            .chain([
                ("empty", Vec::new(), Expect::Error),
                ("binary", Vec::new(), Expect::Error),
                ("truncated", Vec::new(), Expect::Error),
            ])
            .collect();
        // in Parquet a defect in a row is named by its line as in CSV (row + 1)
        check(&c, &dir, "parquet", &pq);
    }
}
