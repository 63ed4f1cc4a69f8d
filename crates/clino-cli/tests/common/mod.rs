//! Helpers shared by the CLI's integration tests (each test binary uses a part).
#![allow(dead_code)]

use std::process::{Command, Output};
use tempfile::TempDir;

/// Run the `clino` binary under test.
pub fn clino(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_clino"))
        .args(args)
        .output()
        .expect("run clino")
}

/// A fresh scratch directory for one test, removed when the value is dropped
/// (at the end of the test, passed or failed): keep it bound for as long as
/// its path is used.
pub fn scratch(suite: &str, name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("clino-{suite}-{name}-"))
        .tempdir()
        .unwrap()
}

/// A continuous accelerometer recording through 12 static poses (2 s each,
/// 1 s apart), from a triad with 1 % scale errors and 20–50 mm/s² biases:
/// enough for `clino calibrate accel`.
pub fn accel_poses_csv() -> String {
    let mut rec = String::from("t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n");
    let g = 9.80665;
    let poses = [
        [g, 0.0, 0.0],
        [-g, 0.0, 0.0],
        [0.0, g, 0.0],
        [0.0, -g, 0.0],
        [0.0, 0.0, g],
        [0.0, 0.0, -g],
        [g * 0.6, g * 0.8, 0.0],
        [0.0, -g * 0.6, g * 0.8],
        [g * 0.8, 0.0, -g * 0.6],
        [-g * 0.48, g * 0.6, g * 0.64],
        [g * 0.36, -g * 0.48, -g * 0.8],
        [-g * 0.8, -g * 0.36, g * 0.48],
    ];
    let mut t = 0.0;
    for p in poses {
        for k in 0..200 {
            let n = 1e-3 * ((k * 7919) % 13) as f64;
            rec.push_str(&format!(
                "{t},{},{},{}\n",
                1.01 * p[0] + 0.05 + n,
                0.99 * p[1] - 0.03,
                p[2] + 0.02 - n
            ));
            t += 0.01;
        }
        t += 1.0;
    }
    rec
}
