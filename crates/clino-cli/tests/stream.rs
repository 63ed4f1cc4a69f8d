//! `clino stream` without hardware: a pseudo-terminal pair stands in for the
//! board (the test writes the conformance vector, with faults, into the
//! master; `clino stream --port` reads the slave), and replays of files.
#![cfg(target_os = "linux")]

use std::fs::File;
use std::io::{BufRead, BufReader, Read, Write};
use std::os::fd::FromRawFd;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use clino_core::protocol::{self, Frame};
use tempfile::TempDir;

fn vector_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../firmware/protocol")
}

/// A fresh scratch directory for one test, removed when the value is dropped
/// (at the end of the test, passed or failed).
fn tmp(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("clino-stream-test-{name}-"))
        .tempdir()
        .unwrap()
}

/// The frames of frames.bin, each with its delimiter: [CONFIG, SAMPLE 0, SAMPLE 1, …].
fn frames() -> Vec<Vec<u8>> {
    let bin = std::fs::read(vector_dir().join("frames.bin")).unwrap();
    bin.split_inclusive(|&b| b == 0)
        .map(|f| f.to_vec())
        .collect()
}

/// frames.csv: header, then one line per sample.
fn csv_lines() -> Vec<String> {
    let text = std::fs::read_to_string(vector_dir().join("frames.csv")).unwrap();
    text.lines().map(str::to_string).collect()
}

/// A pseudo-terminal pair in raw mode: the master (the "board" side) and the slave's path.
struct Pty {
    master: File,
    slave: File,
    path: String,
}

fn openpty() -> Pty {
    let (mut m, mut s) = (0, 0);
    // SAFETY: out-pointers to two ints; name, termios and winsize may be null.
    let r = unsafe {
        libc::openpty(
            &mut m,
            &mut s,
            std::ptr::null_mut(),
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    assert_eq!(r, 0, "openpty failed");
    // SAFETY: setting close-on-exec on two descriptors we own; without it every
    // `clino stream` started later would hold the board's end open too.
    unsafe {
        libc::fcntl(m, libc::F_SETFD, libc::FD_CLOEXEC);
        libc::fcntl(s, libc::F_SETFD, libc::FD_CLOEXEC);
    }
    // SAFETY: `s` is an open terminal; termios is plain data filled by tcgetattr.
    let path = unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        assert_eq!(libc::tcgetattr(s, &mut t), 0);
        libc::cfmakeraw(&mut t);
        assert_eq!(libc::tcsetattr(s, libc::TCSANOW, &t), 0);
        std::ffi::CStr::from_ptr(libc::ttyname(s))
            .to_string_lossy()
            .into_owned()
    };
    // SAFETY: both descriptors are open and owned by nothing else.
    let (master, slave) = unsafe { (File::from_raw_fd(m), File::from_raw_fd(s)) };
    Pty {
        master,
        slave,
        path,
    }
}

/// `clino stream` running, its stdout and stderr collected by threads.
struct Running {
    child: Child,
    out: Arc<Mutex<Vec<String>>>,
    err: Arc<Mutex<Vec<String>>>,
}

fn collect<R: Read + Send + 'static>(r: R) -> Arc<Mutex<Vec<String>>> {
    let lines = Arc::new(Mutex::new(Vec::new()));
    let l = lines.clone();
    std::thread::spawn(move || {
        for line in BufReader::new(r).lines() {
            let Ok(line) = line else { break };
            l.lock().unwrap().push(line);
        }
    });
    lines
}

fn start(args: &[&str]) -> Running {
    let mut child = Command::new(env!("CARGO_BIN_EXE_clino"))
        .arg("stream")
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let out = collect(child.stdout.take().unwrap());
    let err = collect(child.stderr.take().unwrap());
    Running { child, out, err }
}

impl Running {
    /// Wait until `pred` holds for (stdout, stderr), at most 60 s.
    fn wait_for(&self, what: &str, pred: impl Fn(&[String], &[String]) -> bool) {
        let t = Instant::now();
        while !pred(&self.out.lock().unwrap(), &self.err.lock().unwrap()) {
            assert!(
                t.elapsed() < Duration::from_secs(60),
                "timed out waiting for {what}; stderr: {:?}",
                self.err.lock().unwrap()
            );
            std::thread::sleep(Duration::from_millis(20));
        }
    }

    fn connected(&self, times: usize) {
        self.wait_for("the connection", |_, e| {
            e.iter().filter(|l| l.contains("connected to")).count() >= times
        });
        std::thread::sleep(Duration::from_millis(100));
    }

    /// Ctrl-C, then the exit status, stdout and stderr.
    fn interrupt(mut self) -> (bool, Vec<String>, String) {
        // SAFETY: sending a signal to our own child process.
        unsafe { libc::kill(self.child.id() as i32, libc::SIGINT) };
        let status = self.child.wait().unwrap();
        std::thread::sleep(Duration::from_millis(200));
        let out = self.out.lock().unwrap().clone();
        let err = self.err.lock().unwrap().join("\n");
        (status.success(), out, err)
    }
}

/// Write like a serial line: in small pieces.
fn send(master: &mut File, bytes: &[u8]) {
    for chunk in bytes.chunks(256) {
        master.write_all(chunk).unwrap();
        std::thread::sleep(Duration::from_millis(1));
    }
}

fn fuse(path: &Path, filter: &str) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(["fuse", path.to_str().unwrap(), "--filter", filter])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).unwrap()
}

#[test]
fn the_shipped_vector_is_reproducible_and_decodes_to_frames_csv() {
    let (bin, csv) = clino::stream::reference_vector().unwrap();
    assert_eq!(bin, std::fs::read(vector_dir().join("frames.bin")).unwrap());
    assert_eq!(
        csv,
        std::fs::read_to_string(vector_dir().join("frames.csv")).unwrap()
    );
    let f = frames();
    assert_eq!(f.len(), 2001);
    assert_eq!(f[0].len(), 17);
    assert!(f[1..].iter().all(|x| x.len() <= 25));
    // the worked example of PROTOCOL.md
    let doc = std::fs::read_to_string(vector_dir().join("PROTOCOL.md")).unwrap();
    let hex = |b: &[u8]| {
        b.iter()
            .map(|x| format!("{x:02X}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    assert!(doc.contains(&hex(&f[0])), "CONFIG example {}", hex(&f[0]));
    assert!(doc.contains(&hex(&f[1])), "SAMPLE example {}", hex(&f[1]));
}

#[test]
fn a_pty_board_with_faults_gives_exactly_the_surviving_samples() {
    let f = frames();
    let lines = csv_lines();
    let mut wire = f[0].clone();
    let removed = [100, 101, 102, 500];
    let flipped = [200, 800, 1300];
    let truncated = 1800;
    let mut survivors = vec![lines[0].clone()];
    let mut garbage_total = 0;
    for (k, frame) in f[1..].iter().enumerate() {
        if let Some(n) = [(300, 7), (900, 13), (1500, 40)]
            .iter()
            .find(|(at, _)| *at == k)
            .map(|x| x.1)
        {
            // garbage without a zero right before a frame: the frame survives
            wire.extend((0..n).map(|i| (i as u8).wrapping_mul(37) | 1));
            garbage_total += n;
        }
        if k == 1100 {
            wire.extend_from_slice(&[0x55, 0x66, 0x00]); // a stray chunk: one bad frame
        }
        if removed.contains(&k) {
            continue;
        }
        if flipped.contains(&k) {
            let mut bad = frame.clone();
            bad[10] = if bad[10] == 0x80 {
                0x81
            } else {
                bad[10] ^ 0x80
            };
            wire.extend_from_slice(&bad);
            continue;
        }
        if k == truncated {
            wire.extend_from_slice(&frame[..12]);
            wire.push(0);
            continue;
        }
        wire.extend_from_slice(frame);
        if k == 1700 {
            wire.extend_from_slice(frame); // sent twice
        }
        survivors.push(lines[k + 1].clone());
    }
    let scratch = tmp("pty");
    let dir = scratch.path();
    let expected_csv = dir.join("survivors.csv");
    std::fs::write(&expected_csv, survivors.join("\n") + "\n").unwrap();
    let record = dir.join("rec.csv");

    let mut pty = openpty();
    let run = start(&[
        "--port",
        &pty.path,
        "--filter",
        "mahony",
        "--csv",
        "--record",
        record.to_str().unwrap(),
    ]);
    run.connected(1);
    send(&mut pty.master, &wire);
    let n = survivors.len();
    run.wait_for("every surviving row", |o, _| o.len() >= n);
    let (ok, out, err) = run.interrupt();
    assert!(ok, "{err}");
    let want = fuse(&expected_csv, "mahony");
    assert_eq!(out.join("\n") + "\n", want, "{err}");
    // the recording is complete after Ctrl-C and holds exactly the survivors
    assert_eq!(
        std::fs::read_to_string(&record).unwrap(),
        survivors.join("\n") + "\n"
    );
    assert_eq!(garbage_total, 60);
    for fact in [
        "1992 received, 1992 through the filter, 0 dropped",
        "frames: 5 bad",
        "60 garbage bytes, 6 sequence gaps (8 samples missing), 1 repeated",
        "1 CONFIG (0 unusable), 0 resets",
    ] {
        assert!(err.contains(fact), "missing '{fact}' in:\n{err}");
    }
    // each fault was also reported when it happened
    for msg in [
        "bad frame",
        "garbage bytes discarded",
        "sequence gap",
        "repeated frame",
    ] {
        assert!(err.contains(msg), "no '{msg}' report in:\n{err}");
    }
    drop(pty.slave);
}

fn encoded(frame: &Frame) -> Vec<u8> {
    let mut b = [0u8; protocol::MAX_FRAME];
    let n = protocol::encode(frame, &mut b).unwrap();
    b[..n].to_vec()
}

#[test]
fn a_board_reset_mid_stream_is_reported_and_time_goes_on() {
    let f = frames();
    let mut wire: Vec<u8> = f[..=600].concat();
    // the board reboots: CONFIG, then seq from 0 and its clock from 2 ms
    let Ok(Frame::Config(cfg)) = Frame::parse_body(&{
        let mut body = [0u8; 64];
        let n = protocol::cobs_decode(&f[0][..f[0].len() - 1], &mut body).unwrap();
        body[..n].to_vec()
    }) else {
        panic!("frames.bin does not start with a CONFIG")
    };
    wire.extend(encoded(&Frame::Config(cfg)));
    for k in 0..300u16 {
        wire.extend(encoded(&Frame::Sample(protocol::Sample {
            seq: k,
            t_us: 2_000 + 3_500 * k as u32,
            acc: [0, 0, 4096],
            temp: 0,
            gyr: [10, -10, 0],
        })));
    }
    let mut pty = openpty();
    let run = start(&["--port", &pty.path, "--csv", "--filter", "complementary"]);
    run.connected(1);
    send(&mut pty.master, &wire);
    run.wait_for("all 900 rows", |o, _| o.len() >= 901);
    let (ok, out, err) = run.interrupt();
    assert!(ok, "{err}");
    assert!(err.contains("board reset"), "{err}");
    assert!(err.contains("2 CONFIG (0 unusable), 1 resets"), "{err}");
    let t: Vec<f64> = out[1..]
        .iter()
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(t.len(), 900);
    assert!(
        t.windows(2).all(|w| w[1] > w[0]),
        "host time must keep increasing"
    );
    // one period of 286 Hz (3497 µs, rounded up) across the reset
    assert!(
        (t[600] - t[599] - 3497e-6).abs() < 1e-9,
        "{}",
        t[600] - t[599]
    );
    assert!(out[601].ends_with(",fused"), "{}", out[601]);
    drop(pty.slave);
}

#[test]
fn a_wrong_baud_rate_is_named_and_a_lost_port_is_reopened() {
    let scratch = tmp("baud");
    let dir = scratch.path();
    let link = dir.join("board");
    let pty = openpty();
    std::os::unix::fs::symlink(&pty.path, &link).unwrap();
    let run = start(&[
        "--port",
        link.to_str().unwrap(),
        "--silence",
        "0.5",
        "--csv",
    ]);
    run.connected(1);
    // what a board at another baud rate looks like: bytes, never a frame
    let mut m = pty.master;
    let noise: Vec<u8> = (0..3000u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    send(&mut m, &noise[..1500]);
    std::thread::sleep(Duration::from_millis(700));
    send(&mut m, &noise[1500..]);
    run.wait_for("the baud-rate hint", |_, e| {
        e.iter().any(|l| l.contains("baud rate is probably wrong"))
    });
    // unplug: the pty goes away; plug in again: a new one behind the same name
    drop(m);
    drop(pty.slave);
    run.wait_for("the disconnection", |_, e| {
        e.iter().any(|l| l.contains("went away"))
    });
    let mut pty2 = openpty();
    std::fs::remove_file(&link).unwrap();
    std::os::unix::fs::symlink(&pty2.path, &link).unwrap();
    run.connected(2);
    let f = frames();
    send(&mut pty2.master, &f[..=100].concat());
    run.wait_for("100 rows", |o, _| o.len() >= 101);
    let (ok, out, err) = run.interrupt();
    assert!(ok, "{err}");
    assert_eq!(out.len(), 101);
    assert!(err.contains("1 disconnections"), "{err}");
    assert!(err.contains("100 received"), "{err}");
    drop(pty2.slave);
}

#[test]
fn replay_at_speed_equals_fuse_sample_for_sample() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../clino/data/broad_07_excerpt.csv");
    let vec_csv = vector_dir().join("frames.csv");
    let scratch = tmp("replay");
    let dir = scratch.path();
    // the excerpt as a recording of `clino stream` that notes its timing:
    // replayed, as fused, the note is taken (and carried into the new recording)
    let text = std::fs::read_to_string(&data).unwrap();
    let head = text.lines().position(|l| !l.starts_with('#')).unwrap();
    let mut lines: Vec<&str> = text.lines().collect();
    lines.insert(
        head + 1,
        "# clino.sensor_timing sensor_delay_periods=2,gyro_lag_s=0.002",
    );
    let noted = dir.join("noted.csv");
    std::fs::write(&noted, lines.join("\n") + "\n").unwrap();
    assert_ne!(fuse(&noted, "dynamic"), fuse(&data, "dynamic"));
    for (file, filter) in [
        (&data, "dynamic"),
        (&vec_csv, "mahony:kp=0.5"),
        (&data, "complementary"),
        (&noted, "dynamic"),
    ] {
        let rec = dir.join("rec.parquet");
        let o = Command::new(env!("CARGO_BIN_EXE_clino"))
            .args([
                "stream",
                "--replay",
                file.to_str().unwrap(),
                "--speed",
                "1000",
            ])
            .args([
                "--filter",
                filter,
                "--csv",
                "--record",
                rec.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        let out = String::from_utf8(o.stdout).unwrap();
        assert_eq!(out, fuse(file, filter), "{filter}");
        // the recording is reproduced by `clino fuse` exactly
        assert_eq!(fuse(&rec, filter), out, "{filter} (recording)");
        assert!(err.contains("0 dropped"), "{err}");
    }
    // the pipeline flags are those of `clino fuse`, checked the same way
    let o = Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(["stream", "--replay", data.to_str().unwrap(), "--kp", "1"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("'kp' is a parameter of mahony"));
    let o = Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(["stream", "--port", "/nonexistent/tty", "--csv"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("/nonexistent/tty"));
}

#[test]
fn replay_keeps_the_recordings_clock() {
    let data = vector_dir().join("frames.csv"); // 7.0 s of samples
    let t = Instant::now();
    let o = Command::new(env!("CARGO_BIN_EXE_clino"))
        .args([
            "stream",
            "--replay",
            data.to_str().unwrap(),
            "--speed",
            "10",
            "--csv",
        ])
        .output()
        .unwrap();
    let wall = t.elapsed().as_secs_f64();
    assert!(o.status.success());
    assert_eq!(String::from_utf8(o.stdout).unwrap().lines().count(), 2001);
    // 7.0 s at 10× is 0.70 s at least (never earlier than the recording's clock)
    assert!(wall >= 0.69, "{wall}");
}

/// `clino stream` with arguments, its exit code and stderr.
fn stream_err(args: &[&str]) -> (Option<i32>, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_clino"))
        .arg("stream")
        .args(args)
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn i2c_without_a_sensor_fails_cleanly_naming_the_bus() {
    // a bus that does not exist
    let (code, err) = stream_err(&["--i2c", "/nonexistent/i2c-9", "--csv"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("clino: error: /nonexistent/i2c-9: no such I2C bus"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
    // a device that is no I2C bus
    let (code, err) = stream_err(&["--i2c", "/dev/null", "--address", "105"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(
        err.contains("/dev/null: cannot open the I2C bus: ENOTTY"),
        "{err}"
    );
    assert!(err.contains("not an I2C bus"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    // the options are checked before the bus is opened
    let (code, err) = stream_err(&["--i2c", "/nonexistent/i2c-9", "--rate", "5000"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("at most 1000 Hz"), "{err}");
    let (_, err) = stream_err(&["--i2c", "/nonexistent/i2c-9", "--dlpf", "50"]);
    assert!(err.contains("low-pass bandwidth must be"), "{err}");
}

#[test]
fn the_sources_exclude_each_other_and_dials_need_a_board() {
    let data = vector_dir().join("frames.csv");
    let data = data.to_str().unwrap();
    for args in [
        &["--i2c", "/dev/i2c-1", "--port", "/dev/ttyACM0"][..],
        &["--i2c", "/dev/i2c-1", "--replay", data],
        &["--port", "/dev/ttyACM0", "--replay", data],
    ] {
        let (code, err) = stream_err(args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains("cannot be used with"), "{args:?}: {err}");
    }
    let (code, err) = stream_err(&["--csv"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("required") && err.contains("--port"), "{err}");
    // no dials on a bare sensor or a replay (checked before the device is opened)
    for args in [
        &["--i2c", "/dev/i2c-1", "--dials"][..],
        &["--replay", data, "--dials"],
    ] {
        let (code, err) = stream_err(args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(err.contains("--dials needs a board"), "{args:?}: {err}");
    }
    // the replay speed means nothing for a live source
    for args in [
        &["--port", "/dev/ttyACM0", "--speed", "2"][..],
        &["--i2c", "/dev/i2c-1", "--speed", "2"],
    ] {
        let (code, err) = stream_err(args);
        assert_eq!(code, Some(1), "{args:?}: {err}");
        assert!(
            err.contains("--speed is the replay speed"),
            "{args:?}: {err}"
        );
    }
    // the address: 0x68 or 0x69, hex or decimal, and only with --i2c
    let (code, err) = stream_err(&["--i2c", "/dev/i2c-1", "--address", "0x70"]);
    assert_eq!(code, Some(2), "{err}");
    assert!(
        err.contains("0x68 (AD0 low) or 0x69 (AD0 high), got '0x70'"),
        "{err}"
    );
    for flag in ["--address", "--rate", "--accel-fs", "--gyro-fs", "--dlpf"] {
        let value = if flag == "--address" { "0x69" } else { "4" };
        for source in [["--replay", data], ["--port", "/dev/ttyACM0"]] {
            let (code, err) = stream_err(&[source[0], source[1], flag, value]);
            assert_eq!(code, Some(1), "{flag}: {err}");
            assert!(
                err.contains(&format!(
                    "{flag} is an option of the I2C sensor: it needs --i2c"
                )),
                "{flag}: {err}"
            );
        }
    }
}
