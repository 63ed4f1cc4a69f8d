//! Reading recordings: layout, units, and every kind of bad input.

use clino::io::{AccelUnit, GyroUnit, ImuCsvReader, ImuRow, ReadOptions};
use clino::{Error, ErrorKind};

const HEAD: &str = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n";

fn read_all(text: &str, opts: &ReadOptions) -> Result<Vec<ImuRow>, Error> {
    let r = ImuCsvReader::new(text.as_bytes(), "rec.csv", opts)?;
    r.collect()
}

fn err(text: &str) -> Error {
    read_all(text, &ReadOptions::default()).unwrap_err()
}

fn assert_at(e: &Error, kind: ErrorKind, line: u64, column: Option<&str>) {
    assert_eq!(e.kind, kind, "{e}");
    assert_eq!(e.line, Some(line), "{e}");
    assert_eq!(e.column.as_deref(), column, "{e}");
    assert_eq!(
        e.file.as_deref(),
        Some(std::path::Path::new("rec.csv")),
        "{e}"
    );
}

#[test]
fn line_numbers_count_comments_blank_lines_and_crlf() {
    let text = "# trial\n# more\nt_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n\
                0,1,2,3,4,5,6\n# in between\n\n0.1,1,2,3,4,5,6\n0.2,1,2,3,4,5,6";
    let rows = read_all(text, &ReadOptions::default()).unwrap();
    assert_eq!(
        rows.iter().map(|r| r.line).collect::<Vec<_>>(),
        vec![4, 7, 8]
    );
    let crlf = text.replace('\n', "\r\n") + "\r\n";
    let rows = read_all(&crlf, &ReadOptions::default()).unwrap();
    assert_eq!(
        rows.iter().map(|r| r.line).collect::<Vec<_>>(),
        vec![4, 7, 8]
    );
    assert_eq!(rows[2].sample.acc_m_s2.z, 6.0);
}

#[test]
fn columns_are_found_by_name_in_any_order_with_optional_ones() {
    let text = "movement,ref_qz,ref_qy,ref_qx,ref_qw,acc_z_m_s2,acc_y_m_s2,acc_x_m_s2,gyr_z_rad_s,gyr_y_rad_s,gyr_x_rad_s,t_s,temp_c,mag_x_uT,mag_y_uT,mag_z_uT,extra\n\
                1,0,0,0,2,9,8,7,3,2,1,0.5,21.5,10,20,30,whatever\n\
                0,nan,nan,nan,nan,9,8,7,3,2,1,0.6,21.5,10,20,30,x\n";
    let rows = read_all(text, &ReadOptions::default()).unwrap();
    let r = &rows[0];
    assert_eq!(r.sample.t_s, 0.5);
    assert_eq!((r.sample.gyr_rad_s.x, r.sample.gyr_rad_s.z), (1.0, 3.0));
    assert_eq!((r.sample.acc_m_s2.x, r.sample.acc_m_s2.z), (7.0, 9.0));
    assert_eq!(r.sample.mag_ut.unwrap().z, 30.0);
    assert_eq!(r.sample.temp_c, Some(21.5));
    assert_eq!(r.ref_q.unwrap().w, 1.0); // normalised from (2, 0, 0, 0)
    assert_eq!(r.movement, Some(true));
    assert_eq!(rows[1].ref_q, None); // NaN reference is normal
    assert_eq!(rows[1].movement, Some(false));
}

#[test]
fn units_deg_s_and_g_are_converted() {
    let text =
        "t_s,gyr_x_deg_s,gyr_y_deg_s,gyr_z_deg_s,acc_x_g,acc_y_g,acc_z_g\n0,180,0,-90,0,0.5,1\n";
    let opts = ReadOptions {
        gyro_unit: GyroUnit::DegPerS,
        accel_unit: AccelUnit::G,
        ..ReadOptions::default()
    };
    let r = read_all(text, &opts).unwrap()[0];
    assert!((r.sample.gyr_rad_s.x - std::f64::consts::PI).abs() < 1e-15);
    assert!((r.sample.gyr_rad_s.z + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(r.sample.acc_m_s2.z, 9.80665);
    assert_eq!(r.sample.acc_m_s2.y, 0.5 * 9.80665);
    // Bare names take the unit from the options.
    let bare = "t_s,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z\n0,180,0,0,0,0,1\n";
    let r = read_all(bare, &opts).unwrap()[0];
    assert!((r.sample.gyr_rad_s.x - std::f64::consts::PI).abs() < 1e-15);
    assert_eq!("deg/s".parse::<GyroUnit>().unwrap(), GyroUnit::DegPerS);
    assert_eq!("g".parse::<AccelUnit>().unwrap(), AccelUnit::G);
    assert_eq!(
        "furlong/s".parse::<GyroUnit>().unwrap_err().kind,
        ErrorKind::InvalidInput
    );
    assert_eq!(
        "gal".parse::<AccelUnit>().unwrap_err().kind,
        ErrorKind::InvalidInput
    );
}

#[test]
fn the_column_name_says_the_unit_and_the_flag_names_bare_columns() {
    // suffixed columns are read in their own unit whatever the flag
    let opts = ReadOptions {
        gyro_unit: GyroUnit::DegPerS,
        ..ReadOptions::default()
    };
    let rows = read_all(&format!("{HEAD}0,0.5,0,0,0,0,9.8\n"), &opts).unwrap();
    assert_eq!(rows[0].sample.gyr_rad_s.x, 0.5);
    let deg = "t_s,gyr_x_deg_s,gyr_y_deg_s,gyr_z_deg_s,acc_x_g,acc_y_g,acc_z_g\n0,90,0,0,0,0,1\n";
    let rows = read_all(deg, &ReadOptions::default()).unwrap();
    assert!((rows[0].sample.gyr_rad_s.x - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    assert_eq!(rows[0].sample.acc_m_s2.z, clino::core::G0);
    // bare names take the flag's unit
    let bare = "t_s,gyr_x,gyr_y,gyr_z,acc_x,acc_y,acc_z\n0,180,0,0,0,0,9.8\n";
    let rows = read_all(bare, &opts).unwrap();
    assert!((rows[0].sample.gyr_rad_s.x - std::f64::consts::PI).abs() < 1e-15);
    // neither: an error naming the column and the other spellings
    let e = read_all(
        "t_s,gyr_x_rad_s,gyr_y_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,0,0,9.8\n",
        &opts,
    )
    .unwrap_err();
    assert_at(&e, ErrorKind::MissingColumn, 1, Some("gyr_z_deg_s"));
    assert!(e.message.contains("gyr_z_rad_s"), "{e}");
}

#[test]
fn rate_gives_time_when_there_is_no_time_column() {
    let text = "gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,0,0,9.8\n0,0,0,0,0,9.8\n0,0,0,0,0,9.8\n";
    let e = read_all(text, &ReadOptions::default()).unwrap_err();
    assert_at(&e, ErrorKind::MissingColumn, 1, Some("t_s"));
    assert!(e.message.contains("--rate"));
    let opts = ReadOptions {
        rate_hz: Some(200.0),
        ..ReadOptions::default()
    };
    let rows = read_all(text, &opts).unwrap();
    assert_eq!(
        rows.iter().map(|r| r.sample.t_s).collect::<Vec<_>>(),
        vec![0.0, 0.005, 0.01]
    );
    let bad = ReadOptions {
        rate_hz: Some(-1.0),
        ..ReadOptions::default()
    };
    assert_eq!(
        read_all(text, &bad).unwrap_err().kind,
        ErrorKind::InvalidInput
    );
}

#[test]
fn missing_column_names_it() {
    let text = "# c\nt_s,gyr_x_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,0,0,9.8\n";
    assert_at(&err(text), ErrorKind::MissingColumn, 2, Some("gyr_y_rad_s"));
    let partial_ref = format!(
        "{}{}",
        HEAD.trim_end(),
        ",ref_qw,ref_qx\n0,0,0,0,0,0,9.8,1,0\n"
    );
    assert_at(
        &err(&partial_ref),
        ErrorKind::MissingColumn,
        1,
        Some("ref_qy"),
    );
}

#[test]
fn non_numeric_cell_names_line_and_column() {
    let text = format!("# c\n{HEAD}0,0,0,0,0,0,9.8\n0.01,0,0,0,abc,0,9.8\n");
    let e = err(&text);
    assert_at(&e, ErrorKind::Parse, 4, Some("acc_x_m_s2"));
    assert!(e.message.contains("abc"));
    // Also on a last line without a newline, and in the time column.
    let e = err(&format!("{HEAD}0,0,0,0,0,0,9.8\n0.0x1,0,0,0,0,0,9.8"));
    assert_at(&e, ErrorKind::Parse, 3, Some("t_s"));
    // And in an optional column.
    let e = err(
        "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,movement\n0,0,0,0,0,0,9.8,yes\n",
    );
    assert_at(&e, ErrorKind::Parse, 2, Some("movement"));
}

#[test]
fn a_huge_bad_cell_is_quoted_short() {
    // a corrupted 5 MB cell after two blank lines: the line is right and the
    // message quotes 60 characters and says how long the cell was
    let big = "x".repeat(5_000_000);
    let e = err(&format!(
        "{HEAD}0,0,0,0,0,0,9.8\n\n\n0.01,{big},0,0,0,0,9.8\n"
    ));
    assert_at(&e, ErrorKind::Parse, 5, Some("gyr_x_rad_s"));
    let msg = e.to_string();
    assert!(msg.len() < 300, "{} bytes: {}", msg.len(), &msg[..300]);
    assert!(msg.contains("(5000000 bytes)"), "{msg}");
}

#[test]
fn wrong_number_of_fields_is_an_error() {
    let e = err(&format!("{HEAD}0,0,0,0,0,0,9.8\n0.01,0,0,0,0,0\n"));
    assert_at(&e, ErrorKind::Parse, 3, Some("acc_z_m_s2"));
    let e = err(&format!("{HEAD}0,0,0,0,0,0,9.8,7\n"));
    assert_eq!(e.kind, ErrorKind::Parse);
    assert_eq!(e.line, Some(2));
}

#[test]
fn time_going_backwards_or_repeating_is_an_error() {
    let e = err(&format!(
        "{HEAD}0,0,0,0,0,0,9.8\n0.02,0,0,0,0,0,9.8\n0.01,0,0,0,0,0,9.8\n"
    ));
    assert_at(&e, ErrorKind::TimeNotIncreasing, 4, Some("t_s"));
    assert!(e.message.contains("backwards"));
    let e = err(&format!("# c\n{HEAD}0,0,0,0,0,0,9.8\n0,0,0,0,0,0,9.8\n"));
    assert_at(&e, ErrorKind::TimeNotIncreasing, 4, Some("t_s"));
    assert!(e.message.contains("repeats"));
    let e = err(&format!("{HEAD}nan,0,0,0,0,0,9.8\n"));
    assert_at(&e, ErrorKind::InvalidInput, 2, Some("t_s"));
}

#[test]
fn empty_and_header_only_files_are_errors() {
    let e = err("");
    assert_eq!(e.kind, ErrorKind::Empty);
    assert_eq!(e.line, Some(1));
    let e = err("# only a comment\n# and another\n");
    assert_eq!(e.kind, ErrorKind::Empty);
    let e = err(&format!("# c\n{HEAD}"));
    assert_eq!(e.kind, ErrorKind::Empty);
    assert_eq!(e.line, Some(2));
    assert!(e.message.contains("header"));
    let e = err(&format!("{HEAD}\n\n# nothing\n"));
    assert_eq!(e.kind, ErrorKind::Empty);
}

#[test]
fn nan_sensor_values_are_passed_on_and_flagged() {
    let rows = read_all(
        &format!("{HEAD}0,nan,0,0,0,0,9.8\n0.01,0,0,0,0,,9.8\n0.02,0,0,0,0,0,9.8\n"),
        &ReadOptions::default(),
    )
    .unwrap();
    assert_eq!(
        rows.iter().map(|r| r.has_dropout()).collect::<Vec<_>>(),
        vec![true, true, false]
    );
    assert!(rows[1].sample.acc_m_s2.y.is_nan());
}

#[test]
fn missing_file_is_an_io_error_naming_it() {
    let e = ImuCsvReader::from_path("/nonexistent/rec.csv", &ReadOptions::default())
        .err()
        .unwrap();
    assert_eq!(e.kind, ErrorKind::Io);
    assert_eq!(
        e.file.as_deref(),
        Some(std::path::Path::new("/nonexistent/rec.csv"))
    );
}

#[test]
fn reads_the_embedded_broad_excerpt() {
    let r = ImuCsvReader::new(
        clino::demo::BROAD_EXCERPT.as_bytes(),
        "excerpt.csv",
        &ReadOptions::default(),
    )
    .unwrap();
    assert!(r.has_reference() && r.has_movement());
    let rows: Vec<ImuRow> = r.collect::<Result<_, _>>().unwrap();
    assert_eq!(rows.len(), clino::demo::BROAD_EXCERPT.lines().count() - 3);
    assert_eq!(rows[0].line, 4);
    assert!(
        rows.iter()
            .any(|r| r.movement == Some(true) && r.ref_q.is_some())
    );
    // 285.714 Hz
    let dt = rows[1].sample.t_s - rows[0].sample.t_s;
    assert!((dt - 0.0035).abs() < 1e-9);
}

#[test]
fn imu_only_skips_the_other_columns() {
    let text = "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT,ref_qw,ref_qx,ref_qy,ref_qz,movement\n\
                0,0,0,0,0,0,9.8,1,2,3,1,0,0,0,junk\n";
    let opts = ReadOptions {
        imu_only: true,
        ..ReadOptions::default()
    };
    let r = read_all(text, &opts).unwrap()[0];
    assert_eq!((r.ref_q, r.movement, r.sample.mag_ut), (None, None, None));
    assert_eq!(r.sample.acc_m_s2.z, 9.8);
    // Without the option the junk cell is an error.
    let e = read_all(text, &ReadOptions::default()).unwrap_err();
    assert_at(&e, ErrorKind::Parse, 2, Some("movement"));
}

#[test]
fn byte_order_mark_and_quoted_or_spaced_header_names_are_accepted() {
    let text = "\u{feff}\"t_s\", gyr_x_rad_s ,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,1,2,3,4,5,6\n";
    let rows = read_all(text, &ReadOptions::default()).unwrap();
    assert_eq!(rows[0].sample.gyr_rad_s.x, 1.0);
}

mod round_trip {
    use super::*;
    use clino::io::CsvLineWriter;
    use proptest::prelude::*;

    proptest! {
        /// Writing with `CsvLineWriter` (ryu) and reading back gives the same
        /// f64 bit for bit, with comment lines counted in the line numbers.
        #[test]
        fn write_then_read_is_exact(
            rows in proptest::collection::vec(proptest::array::uniform6(-1e6f64..1e6), 1..40),
            comments in 0usize..3,
        ) {
            let mut buf = Vec::new();
            for _ in 0..comments {
                buf.extend_from_slice(b"# comment, with a comma\n");
            }
            {
                let mut w = CsvLineWriter::new(&mut buf);
                w.header(&["t_s", "gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s", "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]).unwrap();
                for (i, r) in rows.iter().enumerate() {
                    w.f64(i as f64 * 0.01);
                    for v in r {
                        w.f64(*v);
                    }
                    w.end_row().unwrap();
                }
                w.finish().unwrap();
            }
            let text = String::from_utf8(buf).unwrap();
            let back = read_all(&text, &ReadOptions::default()).unwrap();
            prop_assert_eq!(back.len(), rows.len());
            for (i, (b, r)) in back.iter().zip(&rows).enumerate() {
                prop_assert_eq!(b.line, (comments + 2 + i) as u64);
                prop_assert_eq!(b.sample.t_s, i as f64 * 0.01);
                let s = &b.sample;
                let got = [s.gyr_rad_s.x, s.gyr_rad_s.y, s.gyr_rad_s.z, s.acc_m_s2.x, s.acc_m_s2.y, s.acc_m_s2.z];
                prop_assert_eq!(&got, r);
            }
        }
    }
}

#[test]
fn gaps_in_time_are_reported_with_size_and_place() {
    // 100 Hz with jitter of ±20 %, then a 0.5 s hole before line 2 + 1 + 40
    let mut text = String::from(HEAD);
    let mut t = 0.0;
    for k in 0..80 {
        if k == 40 {
            t += 0.5;
        } else if k > 0 {
            t += 0.01 * (1.0 + 0.2 * ((k % 3) as f64 - 1.0));
        }
        text.push_str(&format!("{t},0,0,0,0,0,9.8\n"));
    }
    let mut r = ImuCsvReader::new(text.as_bytes(), "rec.csv", &ReadOptions::default()).unwrap();
    while r.next_row().unwrap().is_some() {}
    let g = r.gaps();
    assert_eq!(g.count, 1, "{g:?}");
    let l = g.largest.unwrap();
    assert_eq!(l.line, 42);
    assert!((l.size_s - 0.5).abs() < 1e-12);
    assert!((g.nominal_period_s.unwrap() - 0.01).abs() < 1e-12);
    let d = g.describe().unwrap();
    assert!(d.contains("1 gap in time") && d.contains("line 42"), "{d}");
    // without the hole: no gap (jitter stays below five periods)
    let steady: String = text.lines().take(41).map(|l| format!("{l}\n")).collect();
    let mut r = ImuCsvReader::new(steady.as_bytes(), "rec.csv", &ReadOptions::default()).unwrap();
    while r.next_row().unwrap().is_some() {}
    assert_eq!(r.gaps().count, 0);
    assert!(r.gaps().describe().is_none());
}
