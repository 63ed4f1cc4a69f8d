//! The AVR firmware's serial stream, captured in the simavr simulator by
//! `firmware/ci/avr.sh`, decoded by `clino_core::protocol`: every sample the
//! simulated MPU6050 played arrives, in order, with its raw counts, and its
//! SI values equal the harness's own decoding. Needs the capture, which is
//! generated (not in the repository): `.ci/run` runs this after the AVR step,
//! with `CLINO_SIMAVR_OUT=firmware/simavr/out`.

use clino_core::protocol::{Decoder, Frame};
use std::path::PathBuf;

fn out_dir() -> PathBuf {
    let d =
        std::env::var("CLINO_SIMAVR_OUT").unwrap_or_else(|_| "../../firmware/simavr/out".into());
    PathBuf::from(d)
}

fn csv(path: &PathBuf) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect()
}

#[test]
#[ignore = "needs firmware/simavr/out, made by firmware/ci/avr.sh (CLINO_SIMAVR_OUT)"]
fn the_rust_decoder_reads_every_sample_the_board_sent() {
    let dir = out_dir();
    let bytes = std::fs::read(dir.join("400hz_capture.bin")).expect("400hz_capture.bin");
    let played = csv(&dir.join("400hz_played.csv"));
    let decoded = csv(&dir.join("400hz_decoded.csv"));
    let mut dec = Decoder::default();
    let (mut config, mut samples, mut bad) = (None, Vec::new(), 0);
    dec.feed(&bytes, |d| match d.result {
        Ok(Frame::Config(c)) => config = Some(c),
        Ok(Frame::Sample(s)) => samples.push((s, config)),
        Ok(_) => {}
        Err(_) => bad += 1,
    });
    assert_eq!(bad, 0, "bad frames in the capture");
    assert!(
        samples.len() >= played.len() - 1 && samples.len() <= played.len(),
        "{} frames for {} played",
        samples.len(),
        played.len()
    );
    for (k, (s, cfg)) in samples.iter().enumerate() {
        assert_eq!(usize::from(s.seq), k % 65536, "seq of frame {k}");
        // index,cycle,t_s,ax,ay,az,temp,gx,gy,gz,…
        let p = &played[k];
        let counts = [
            s.acc[0], s.acc[1], s.acc[2], s.temp, s.gyr[0], s.gyr[1], s.gyr[2],
        ];
        for (j, c) in counts.iter().enumerate() {
            assert_eq!(f64::from(*c), p[3 + j], "frame {k}, column {}", 3 + j);
        }
        // t_s,gyr xyz,acc xyz,temp_c, as the harness decoded them
        let cfg = cfg.expect("a CONFIG before the first sample");
        let si = s.to_si(&cfg.scales().unwrap(), f64::from(s.t_us) * 1e-6);
        let d = &decoded[k];
        let ours = [
            si.t_s,
            si.gyr_rad_s.x,
            si.gyr_rad_s.y,
            si.gyr_rad_s.z,
            si.acc_m_s2.x,
            si.acc_m_s2.y,
            si.acc_m_s2.z,
        ];
        for (j, (a, b)) in ours.iter().zip(d).enumerate() {
            assert!(
                (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                "frame {k}, column {j}: {a} vs {b}"
            );
        }
        assert!((clino_core::protocol::temp_c(s.temp) - d[7]).abs() < 1e-12);
    }
    eprintln!(
        "{} samples decoded, all equal to the played counts",
        samples.len()
    );
}
