//! A live stream through the pipeline: a [`SampleSource`] read on its own
//! thread, a bounded buffer, the one [`Pipeline`], and the outputs of
//! `clino stream` (fused rows as `clino fuse` writes them, a recording of
//! the raw samples, the dial angles sent back to the board).
//!
//! * The reader thread owns the source and sends samples into a buffer of
//!   [`StreamConfig::capacity`] samples. A live source (a sensor) cannot
//!   wait: when the buffer is full the sample is dropped and counted
//!   ([`StreamCounts::dropped`]). A file or replay waits for the consumer
//!   instead, so a replay reproduces `clino fuse` exactly.
//! * Notices (faults, CONFIG, connection) travel on their own unbounded
//!   channel: none is ever dropped; each is counted ([`StreamCounts::add`])
//!   and handed to the [`StreamObserver`] once, when it happens.
//! * Every sample goes through [`Pipeline::update`] (its rules for time
//!   steps, dropouts and initialisation hold unchanged).
//! * [`conformance_vector`] makes the protocol's test vector
//!   (`firmware/protocol/frames.bin` and `frames.csv`) from a recording.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use clino_core::filter::DynamicParams;
use clino_core::pipeline::{Output, Pipeline, Status, TiltOutput};
use clino_core::protocol::{self, Frame, FrameError, Notice};
use clino_core::{ImuSample, Vec3};

use crate::fusion::{FUSE_HEADER, FilterConfig, write_attitude};
use crate::io::source::{SampleSource, SourceEvent, SourceNotice};
use crate::io::{AtomicFile, CsvLineWriter, ParquetRowWriter, RowSink, is_parquet};
use crate::{Error, ErrorKind, Result};

/// Columns of a recording of raw samples (what `clino fuse` reads).
pub const RAW_HEADER: [&str; 8] = [
    "t_s",
    "gyr_x_rad_s",
    "gyr_y_rad_s",
    "gyr_z_rad_s",
    "acc_x_m_s2",
    "acc_y_m_s2",
    "acc_z_m_s2",
    "temp_c",
];

/// Write one raw sample as a [`RAW_HEADER`] row (temperature NaN when unknown).
pub fn write_raw<S: RowSink>(out: &mut S, s: &ImuSample) -> std::io::Result<()> {
    out.f64(s.t_s);
    for v in s.gyr_rad_s.iter().chain(s.acc_m_s2.iter()) {
        out.f64(*v);
    }
    out.f64(s.temp_c.unwrap_or(f64::NAN));
    out.end_row()
}

enum RecordSink {
    Csv(CsvLineWriter<AtomicFile>),
    Parquet(Box<ParquetRowWriter<AtomicFile>>),
}

/// A recording of the raw SI samples (CSV, or Parquet by the extension),
/// written under a temporary name ([`AtomicFile`]) and flushed once a second
/// (for CSV every row so far is then on disk; for Parquet a row group);
/// [`Recorder::finish`] completes and renames it.
pub struct Recorder {
    sink: RecordSink,
    path: PathBuf,
    rows: u64,
    last_flush: Instant,
}

impl Recorder {
    /// Start a recording at `path` (refusing to write over one of `inputs`).
    pub fn create(path: &Path, inputs: &[&Path]) -> Result<Self> {
        let file = AtomicFile::create(path, inputs)?;
        let io = |e: std::io::Error| Error::from(e).in_file(path);
        let sink = if is_parquet(path) {
            RecordSink::Parquet(Box::new(ParquetRowWriter::new(file, &RAW_HEADER, &[])?))
        } else {
            let mut w = CsvLineWriter::new(file);
            w.header(&RAW_HEADER).map_err(io)?;
            RecordSink::Csv(w)
        };
        Ok(Self {
            sink,
            path: path.to_path_buf(),
            rows: 0,
            last_flush: Instant::now(),
        })
    }

    /// Append one sample.
    pub fn push(&mut self, s: &ImuSample) -> Result<()> {
        let r = match &mut self.sink {
            RecordSink::Csv(w) => write_raw(w, s),
            RecordSink::Parquet(w) => write_raw(w.as_mut(), s),
        };
        r.map_err(|e| Error::from(e).in_file(&self.path))?;
        self.rows += 1;
        if self.last_flush.elapsed() >= Duration::from_secs(1) {
            self.flush()?;
        }
        Ok(())
    }

    /// Note `text` in the recording: a `#` comment line in a CSV one, which
    /// `clino fuse` skips; false for Parquet, which has no such lines.
    pub fn comment(&mut self, text: &str) -> Result<bool> {
        match &mut self.sink {
            RecordSink::Csv(w) => w
                .comment(text)
                .map(|_| true)
                .map_err(|e| Error::from(e).in_file(&self.path)),
            RecordSink::Parquet(_) => Ok(false),
        }
    }

    /// Note the sensor's timing for the recording's readers: `clino fuse`
    /// and `clino eval` take it where the filter does not name it
    /// ([`crate::fusion::FilterConfig::timing_given`]). A CSV recording
    /// carries it as a note line (`# clino.sensor_timing …`), read where it
    /// comes before the first sample; a Parquet one as its key-value
    /// metadata, whose first value is read: a timing that changes after the
    /// first sample (a board reset to another setting) is the stream's
    /// alone.
    pub fn note_timing(&mut self, t: &SensorTiming) -> Result<()> {
        let text = t.note_text();
        match &mut self.sink {
            RecordSink::Csv(w) => w
                .comment(&format!("clino.{} {text}", SensorTiming::NOTE))
                .map_err(|e| Error::from(e).in_file(&self.path)),
            RecordSink::Parquet(w) => {
                w.note(SensorTiming::NOTE, &text);
                Ok(())
            }
        }
    }

    /// Push what is buffered to the temporary file.
    pub fn flush(&mut self) -> Result<()> {
        self.last_flush = Instant::now();
        let r = match &mut self.sink {
            RecordSink::Csv(w) => w.flush(),
            RecordSink::Parquet(w) => w.flush(),
        };
        r.map_err(|e| Error::from(e).in_file(&self.path))
    }

    /// Finish the file and rename it into place; the number of rows.
    pub fn finish(self) -> Result<u64> {
        let io = |e: std::io::Error| Error::from(e).in_file(&self.path);
        let file = match self.sink {
            RecordSink::Csv(w) => w.finish().map_err(io)?,
            RecordSink::Parquet(w) => w.finish().map_err(io)?,
        };
        file.commit()?;
        Ok(self.rows)
    }
}

/// Fused rows with the columns of `clino fuse` ([`FUSE_HEADER`]), each
/// flushed as soon as it is written.
pub struct FusedCsv<W: Write> {
    w: CsvLineWriter<W>,
}

impl<W: Write> FusedCsv<W> {
    /// Write the header.
    pub fn new(out: W) -> Result<Self> {
        let mut w = CsvLineWriter::new(out);
        w.header(&FUSE_HEADER).map_err(Error::from)?;
        w.flush().map_err(Error::from)?;
        Ok(Self { w })
    }

    /// One row: time, attitude (NaN before initialisation), status.
    pub fn row(&mut self, t_s: f64, o: &Output) -> Result<()> {
        self.w.f64(t_s);
        write_attitude(&mut self.w, o.attitude, t_s, None);
        self.w.str(o.status.as_str());
        self.w.end_row().map_err(Error::from)?;
        self.w.flush().map_err(Error::from)
    }
}

/// The outputs of a stream (all optional).
#[derive(Default)]
pub struct StreamOutputs {
    /// Fused rows (stdout in `clino stream --csv`).
    pub csv: Option<FusedCsv<Box<dyn Write + Send>>>,
    /// The raw samples.
    pub record: Option<Recorder>,
}

/// A sensor's timing as the dynamic filter takes it: the delay behind its
/// time stamps of the instant the gyro's samples stand for, in sample
/// periods ([`DynamicParams::sensor_delay_periods`]), and how much later
/// that is than the accelerometer's ([`DynamicParams::gyro_lag_s`]).
///
/// An MPU6050's are its low-pass filter's delays and the age of its data
/// registers when read ([`clino_mpu6050::Config::data_delays_s`]): at the
/// I²C source's defaults (44 Hz, read at 100 Hz from a 1-kHz sample clock)
/// 0.53 periods and −0.1 ms, near the filter's default half period; read
/// at 1 kHz, 5.3 periods; with the filter off at 1 kHz, 1.48 periods and
/// the gyro 0.98 ms behind. Each millisecond missed is a tilt error of
/// ω·1 ms while turning (0.11° at 2 rad/s), and a lag missed is left as
/// tilt at the stop (`generalise --only lag`, BENCHMARKS.md).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SensorTiming {
    /// The gyro's delay behind the time stamps, sample periods.
    pub sensor_delay_periods: f64,
    /// The gyro's delay beyond the accelerometer's, s.
    pub gyro_lag_s: f64,
}

impl SensorTiming {
    /// An MPU6050 in configuration `config`, its samples stamped at the
    /// instants they are read, `read_rate_hz` times a second (on the
    /// data-ready flag when `synced`).
    pub fn mpu6050(config: &clino_mpu6050::Config, synced: bool, read_rate_hz: f64) -> Self {
        let [acc, gyr] = config.data_delays_s(synced);
        Self {
            sensor_delay_periods: gyr * read_rate_hz,
            gyro_lag_s: gyr - acc,
        }
    }

    /// A board's, from its CONFIG: the MPU6050 at the board's DLPF setting,
    /// read at its rate. clino's Cortex-M firmware samples the chip at that
    /// rate and reads it on the data-ready flag; the Arduino firmware (and
    /// the host simulator of it) runs the chip at divider 0 and reads the
    /// freshest sample on a timer of its own. `None` for a DLPF setting the
    /// chip does not have, or no rate.
    pub fn of_board(b: &protocol::Config) -> Option<Self> {
        use clino_mpu6050::{Config, Dlpf};
        let dlpf = Dlpf::from_cfg(b.dlpf_cfg)?;
        if b.rate_hz == 0 {
            return None;
        }
        let mut c = Config {
            dlpf,
            sample_rate_divider: 0,
            ..Config::default()
        };
        let synced = b.board == 2;
        if synced {
            c.sample_rate_divider = c.divider_for(b.rate_hz)?;
        }
        Some(Self::mpu6050(&c, synced, f64::from(b.rate_hz)))
    }

    /// The filter's text that gives these values (`clino fuse --filter`),
    /// exact: to fuse a recording of the stream as the stream did.
    pub fn filter_text(&self) -> String {
        format!(
            "dynamic:sensor_delay_periods={},gyro_lag_s={}",
            self.sensor_delay_periods, self.gyro_lag_s
        )
    }

    /// What a stream says, and notes in its recording, when it takes this
    /// timing from the sensor's settings (`source`).
    pub fn notice(&self, source: &str, rate_hz: f64) -> String {
        format!(
            "timing from {source}: the gyro {:.2} ms behind the time stamps ({:.2} periods), {:+.2} ms behind the accelerometer; a recording of this stream notes it for `clino fuse`, and `--filter {}` gives it to any other",
            self.sensor_delay_periods / rate_hz * 1e3,
            self.sensor_delay_periods,
            self.gyro_lag_s * 1e3,
            self.filter_text()
        )
    }

    /// The name of the note that carries a timing in a recording
    /// ([`crate::io::NOTE_PREFIX`]; Parquet: the key-value metadata
    /// `clino.sensor_timing`).
    pub const NOTE: &'static str = "sensor_timing";

    /// The note's text: [`SensorTiming::filter_text`]'s parameters,
    /// `sensor_delay_periods=…,gyro_lag_s=…`, exact.
    pub fn note_text(&self) -> String {
        format!(
            "sensor_delay_periods={},gyro_lag_s={}",
            self.sensor_delay_periods, self.gyro_lag_s
        )
    }

    /// The timing a recording's notes carry ([`crate::io::ImuCsvReader::notes`]:
    /// `clino.sensor_timing TEXT`), the first that reads as
    /// [`SensorTiming::note_text`] writes it; `None` if none does.
    pub fn from_notes(notes: &[String]) -> Option<Self> {
        let prefix = format!("clino.{} ", Self::NOTE);
        notes.iter().find_map(|n| {
            let text = n.strip_prefix(&prefix)?;
            let (mut delay, mut lag) = (None, None);
            for kv in text.trim().split(',') {
                let (k, v) = kv.split_once('=')?;
                let v: f64 = v.trim().parse().ok().filter(|v: &f64| v.is_finite())?;
                match k.trim() {
                    "sensor_delay_periods" => delay = Some(v),
                    "gyro_lag_s" => lag = Some(v),
                    _ => return None,
                }
            }
            let t = Self {
                sensor_delay_periods: delay?,
                gyro_lag_s: lag?,
            };
            let mut p = DynamicParams::default();
            t.apply(&mut p);
            clino_core::filter::FilterSpec::Dynamic(p)
                .validate()
                .is_ok()
                .then_some(t)
        })
    }

    /// True when `notes` hold a timing note at all (read or not).
    pub fn is_noted(notes: &[String]) -> bool {
        let prefix = format!("clino.{} ", Self::NOTE);
        notes.iter().any(|n| n.starts_with(&prefix))
    }

    /// These values in the dynamic filter's parameters.
    pub fn apply(&self, p: &mut DynamicParams) {
        p.sensor_delay_periods = self.sensor_delay_periods;
        p.gyro_lag_s = self.gyro_lag_s;
    }
}

/// How to run a stream.
#[derive(Clone, Copy, Debug)]
pub struct StreamConfig<'a> {
    /// The filter and the stages around it (offline smoothing is refused:
    /// a stream has no end to smooth back from).
    pub filter: FilterConfig,
    /// Calibrate every sample with this file.
    pub calibration: Option<&'a crate::calib::CalibrationFile>,
    /// Samples the buffer between the reader and the pipeline holds.
    pub capacity: usize,
    /// Send the filter's roll and pitch to the board's dials (SET_DIALS, 10 per second).
    pub dials: bool,
    /// Take the dynamic filter's timing from a board's CONFIG
    /// ([`SensorTiming::of_board`]); off where the user gave it. Default on.
    pub board_timing: bool,
}

impl StreamConfig<'_> {
    /// A stream through this filter, buffer of 4096 samples, no dials.
    pub fn new(filter: FilterConfig) -> Self {
        Self {
            filter,
            calibration: None,
            capacity: 4096,
            dials: false,
            board_timing: true,
        }
    }
}

/// Bad frames by kind, in the order of [`FrameError`]'s variants.
pub const BAD_FRAME_KINDS: [&str; 6] = [
    "cobs",
    "too short",
    "bad crc",
    "unknown type",
    "bad length",
    "overlong",
];

/// What happened in a stream (the summary at exit).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StreamCounts {
    /// Samples the source delivered (used + dropped).
    pub received: u64,
    /// Samples lost because the buffer was full (a slow consumer).
    pub dropped: u64,
    /// What the pipeline did with the samples it got.
    pub pipeline: clino_core::pipeline::Counts,
    /// Bad frames, by [`BAD_FRAME_KINDS`].
    pub bad_frames: [u64; 6],
    /// Garbage bytes discarded before good frames.
    pub garbage_bytes: u64,
    /// Sequence gaps (events).
    pub gaps: u64,
    /// Samples missing in those gaps.
    pub missing: u64,
    /// Repeated (or stale) frames dropped.
    pub repeated: u64,
    /// Board resets or restarts of the sequence.
    pub resets: u64,
    /// CONFIG frames.
    pub configs: u64,
    /// CONFIG frames that could not be used (unknown range, other version).
    pub bad_configs: u64,
    /// Samples dropped because no CONFIG had arrived.
    pub no_config: u64,
    /// Times the device went away.
    pub disconnects: u64,
    /// Periods without a valid frame.
    pub silences: u64,
    /// Commands the board refused, and frames that should not come from it.
    pub refused: u64,
    /// Samples whose temperature was outside the calibration's range.
    pub temp_outside_calibration: u64,
    /// Dial commands sent.
    pub dials_sent: u64,
    /// Late reads of a sensor on the host's clock ([`SourceNotice::Late`]).
    pub late_reads: u64,
    /// Sample times those late reads skipped.
    pub skipped: u64,
    /// Bus transfers tried again ([`SourceNotice::BusRetry`]).
    pub bus_retries: u64,
}

fn bad_index(e: &FrameError) -> usize {
    match e {
        FrameError::Cobs(_) => 0,
        FrameError::TooShort { .. } => 1,
        FrameError::BadCrc { .. } => 2,
        FrameError::UnknownType(_) => 3,
        FrameError::BadLength { .. } => 4,
        FrameError::Overlong { .. } => 5,
    }
}

impl StreamCounts {
    /// Count one notice.
    pub fn add(&mut self, n: &SourceNotice) {
        match n {
            SourceNotice::BadFrame(e) => self.bad_frames[bad_index(e)] += 1,
            SourceNotice::Garbage { bytes } => self.garbage_bytes += *bytes as u64,
            SourceNotice::Connected { .. } => {}
            SourceNotice::Disconnected { .. } => self.disconnects += 1,
            SourceNotice::Silent { .. } => self.silences += 1,
            SourceNotice::Late { missed } => {
                self.late_reads += 1;
                self.skipped += missed;
            }
            SourceNotice::BusRetry { .. } => self.bus_retries += 1,
            SourceNotice::Link(l) => match l {
                Notice::Config(_) => self.configs += 1,
                Notice::BadConfig(_) | Notice::Version(_) => {
                    self.configs += 1;
                    self.bad_configs += 1;
                }
                Notice::Reset { .. } => self.resets += 1,
                Notice::Gap { missing } => {
                    self.gaps += 1;
                    self.missing += *missing as u64;
                }
                Notice::Repeated { .. } => self.repeated += 1,
                Notice::NoConfig => self.no_config += 1,
                Notice::Ack(a) if a.status == protocol::ack::OK => {}
                Notice::Ack(_) | Notice::Unexpected(_) => self.refused += 1,
            },
        }
    }

    /// All bad frames.
    pub fn bad_total(&self) -> u64 {
        self.bad_frames.iter().sum()
    }

    /// The summary, one fact per line.
    pub fn summary(&self) -> Vec<String> {
        let p = &self.pipeline;
        let bad: Vec<String> = BAD_FRAME_KINDS
            .iter()
            .zip(self.bad_frames)
            .filter(|(_, n)| *n > 0)
            .map(|(k, n)| format!("{n} {k}"))
            .collect();
        let mut v = vec![
            format!(
                "samples: {} received, {} through the filter, {} dropped (buffer full)",
                self.received, p.samples, self.dropped
            ),
            format!(
                "filter: {} initialised, {} fused, {} gyro only, {} waiting, {} dropouts, {} saturated, clipped at the sensor's range: {} gyro, {} accelerometer",
                p.initialised,
                p.fused,
                p.gyro_only,
                p.waiting,
                p.dropouts,
                p.saturated,
                p.gyro_clipped,
                p.acc_clipped
            ) + &if p.retimed > 0 {
                format!(
                    ", {} steps from the sample clock recovered from the stamps",
                    p.retimed
                )
            } else {
                String::new()
            },
            format!(
                "frames: {} bad{}, {} garbage bytes, {} sequence gaps ({} samples missing), {} repeated",
                self.bad_total(),
                if bad.is_empty() {
                    String::new()
                } else {
                    format!(" ({})", bad.join(", "))
                },
                self.garbage_bytes,
                self.gaps,
                self.missing,
                self.repeated
            ),
            format!(
                "link: {} CONFIG ({} unusable), {} resets, {} samples before a CONFIG, {} disconnections, {} silent periods, {} refused commands",
                self.configs,
                self.bad_configs,
                self.resets,
                self.no_config,
                self.disconnects,
                self.silences,
                self.refused
            ),
        ];
        if self.temp_outside_calibration > 0 {
            v.push(format!(
                "calibration: {} samples outside its temperature range",
                self.temp_outside_calibration
            ));
        }
        if self.late_reads + self.bus_retries > 0 {
            v.push(format!(
                "sensor: {} late reads ({} sample times skipped), {} bus retries",
                self.late_reads, self.skipped, self.bus_retries
            ));
        }
        if self.dials_sent > 0 {
            v.push(format!("dials: {} SET_DIALS sent", self.dials_sent));
        }
        v
    }
}

/// The state of a stream, for a live view.
#[derive(Clone, Copy, Debug)]
pub struct LiveStatus {
    /// Tilt of the last sample, `None` before initialisation.
    pub tilt: Option<TiltOutput>,
    /// Status of the last sample.
    pub status: Option<Status>,
    /// Sample rate over the last second (from the samples' time stamps), Hz.
    pub rate_hz: Option<f64>,
    /// The counts so far.
    pub counts: StreamCounts,
    /// Seconds since the last sample.
    pub idle_s: f64,
}

impl LiveStatus {
    /// One line for a terminal: roll, pitch, inclination, rate, drops, bad frames, status.
    pub fn line(&self) -> String {
        let deg = |x: f64| format!("{:+7.2}°", x.to_degrees());
        let (r, p, i) = match self.tilt {
            Some(t) => (deg(t.roll_rad), deg(t.pitch_rad), deg(t.inclination_rad)),
            None => ("    —   ".into(), "    —   ".into(), "    —   ".into()),
        };
        let rate = self
            .rate_hz
            .map_or("  — Hz".to_string(), |h| format!("{h:6.1} Hz"));
        let status = if self.idle_s > 1.0 {
            format!("no samples for {:.0} s", self.idle_s)
        } else {
            self.status.map_or("waiting", |s| s.as_str()).to_string()
        };
        format!(
            "roll {r}  pitch {p}  inclination {i}  {rate}  dropped {}  bad frames {}  gaps {}  {status}",
            self.counts.dropped,
            self.counts.bad_total(),
            self.counts.gaps
        )
    }
}

/// What a person watching is shown: faults as they happen, and the state
/// a few times a second.
pub trait StreamObserver {
    /// A notice of the source (counted already in `counts`).
    fn notice(&mut self, n: &SourceNotice, counts: &StreamCounts);
    /// Something else to report once (a calibration range, a refused command).
    fn message(&mut self, text: &str);
    /// The state, about five times a second.
    fn tick(&mut self, live: &LiveStatus);
}

/// The dial angles of a tilt, centidegrees clamped to ±90°.
pub fn dial_frame(t: &TiltOutput) -> Frame {
    let cdeg = |r: f64| (r.to_degrees() * 100.0).round().clamp(-9000.0, 9000.0) as i16;
    Frame::SetDials {
        roll_cdeg: cdeg(t.roll_rad),
        pitch_cdeg: cdeg(t.pitch_rad),
    }
}

/// What the reader hands the consumer in order: samples, and a board's
/// configuration between them (its notice is also counted and shown with
/// the others).
enum InBand {
    Sample(ImuSample),
    Config(protocol::Config),
}

/// The consumer's side of a run.
struct Consumer<'a, 'o> {
    pipeline: Pipeline,
    cfg: &'a StreamConfig<'a>,
    outputs: &'o mut StreamOutputs,
    counts: StreamCounts,
    last: Option<Output>,
    window: (Option<f64>, f64, u64),
    rate_hz: Option<f64>,
    last_sample: Instant,
    temp_reported: bool,
}

impl Consumer<'_, '_> {
    fn sample(&mut self, s: &ImuSample, obs: &mut dyn StreamObserver) -> Result<()> {
        self.last_sample = Instant::now();
        if let Some(cal) = self.cfg.calibration
            && cal.check_temp(s.temp_c).is_err()
        {
            self.counts.temp_outside_calibration += 1;
            if !self.temp_reported {
                self.temp_reported = true;
                if let Err(e) = cal.check_temp(s.temp_c) {
                    obs.message(&format!("calibration: {e} (reported once, counted)"));
                }
            }
        }
        let o = self.pipeline.update(s);
        self.counts.pipeline.record(o.status);
        self.counts.pipeline.take_pipeline(self.pipeline.counts());
        if let Some(csv) = self.outputs.csv.as_mut() {
            csv.row(s.t_s, &o)?;
        }
        if let Some(r) = self.outputs.record.as_mut() {
            r.push(s)?;
        }
        self.last = Some(o);
        // sample rate from the time stamps over about a second
        let (t0, t1, n) = &mut self.window;
        let first = *t0.get_or_insert(s.t_s);
        *t1 = s.t_s;
        *n += 1;
        if *t1 - first >= 1.0 {
            self.rate_hz = Some((*n - 1) as f64 / (*t1 - first));
            self.window = (Some(s.t_s), s.t_s, 1);
        }
        Ok(())
    }

    /// A board's configuration names its full-scale ranges: a reading at one
    /// is clipped ([`Pipeline::with_sensor_range`]). Ranges given by the
    /// user ([`FilterConfig::sensor_range`]) are kept.
    fn board_ranges(&mut self, b: &protocol::Config) {
        if self.cfg.filter.sensor_range == crate::fusion::SensorRange::default() {
            self.pipeline
                .set_sensor_range(crate::fusion::SensorRange::from_full_scale(
                    f64::from(b.accel_fs_g),
                    f64::from(b.gyro_fs_dps),
                ));
        }
    }

    /// A board's configuration names its DLPF setting and rate: the dynamic
    /// filter's timing follows them ([`SensorTiming::of_board`]), unless the
    /// user gave it ([`StreamConfig::board_timing`]). Said once per change.
    fn board_timing(&mut self, b: &protocol::Config, obs: &mut dyn StreamObserver) -> Result<()> {
        if !self.cfg.board_timing {
            return Ok(());
        }
        let (Some(t), Some(f)) = (
            SensorTiming::of_board(b),
            self.pipeline.filter_mut().as_dynamic_mut(),
        ) else {
            return Ok(());
        };
        let mut p = *f.params();
        if p.sensor_delay_periods == t.sensor_delay_periods && p.gyro_lag_s == t.gyro_lag_s {
            return Ok(());
        }
        t.apply(&mut p);
        f.set_params(p);
        let text = t.notice(
            &format!(
                "the board's CONFIG (DLPF_CFG {}, {} Hz)",
                b.dlpf_cfg, b.rate_hz
            ),
            f64::from(b.rate_hz),
        );
        obs.message(&text);
        if let Some(r) = self.outputs.record.as_mut() {
            r.comment(&format!("clino stream: {text}"))?;
            r.note_timing(&t)?;
        }
        Ok(())
    }

    fn item(&mut self, i: &InBand, obs: &mut dyn StreamObserver) -> Result<()> {
        match i {
            InBand::Sample(s) => self.sample(s, obs),
            InBand::Config(b) => {
                self.board_ranges(b);
                self.board_timing(b, obs)
            }
        }
    }

    fn live(&self) -> LiveStatus {
        LiveStatus {
            tilt: self.last.and_then(|o| o.tilt()),
            status: self.last.map(|o| o.status),
            rate_hz: self.rate_hz,
            counts: self.counts,
            idle_s: self.last_sample.elapsed().as_secs_f64(),
        }
    }
}

/// Run `source` through the pipeline into `outputs` until the source ends,
/// `stop` is set (Ctrl-C) or an error; the counts. The outputs are left for
/// the caller to finish (a recording is complete only after
/// [`Recorder::finish`]).
pub fn run(
    source: Box<dyn SampleSource + Send>,
    cfg: &StreamConfig,
    outputs: &mut StreamOutputs,
    observer: &mut dyn StreamObserver,
    stop: &AtomicBool,
) -> Result<StreamCounts> {
    if cfg.filter.offline {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "offline smoothing needs the whole recording: record the stream (--record) and run `clino fuse --offline` on it",
        ));
    }
    let mut pipeline = cfg.filter.pipeline()?;
    if let Some(cal) = cfg.calibration {
        pipeline = pipeline.with_calibration(Some(cal.calibration()));
    }
    let mut c = Consumer {
        pipeline,
        cfg,
        outputs,
        counts: StreamCounts::default(),
        last: None,
        window: (None, 0.0, 0),
        rate_hz: None,
        last_sample: Instant::now(),
        temp_reported: false,
    };
    let (stx, srx) = mpsc::sync_channel::<InBand>(cfg.capacity.max(1));
    let (ntx, nrx) = mpsc::channel::<SourceNotice>();
    let (ctx, crx) = mpsc::channel::<Frame>();
    let dropped = AtomicU64::new(0);
    let done = AtomicBool::new(false);
    let result = std::thread::scope(|scope| {
        let reader = scope.spawn(|| read_loop(source, stx, ntx, crx, &dropped, &done, stop));
        let consumed = consume(&mut c, &srx, &nrx, &ctx, observer, stop, &dropped);
        done.store(true, Ordering::Relaxed);
        drop(srx); // a reader waiting on a full buffer gives up
        let read = reader
            .join()
            .unwrap_or_else(|_| Err(Error::new(ErrorKind::Io, "the reader thread failed")));
        consumed.and(read)
    });
    while let Ok(n) = nrx.try_recv() {
        c.counts.add(&n);
        observer.notice(&n, &c.counts);
    }
    c.counts.dropped = dropped.load(Ordering::Relaxed);
    c.counts.received = c.counts.pipeline.samples + c.counts.dropped;
    observer.tick(&c.live());
    result.map(|()| c.counts)
}

fn read_loop(
    mut source: Box<dyn SampleSource + Send>,
    stx: mpsc::SyncSender<InBand>,
    ntx: mpsc::Sender<SourceNotice>,
    crx: mpsc::Receiver<Frame>,
    dropped: &AtomicU64,
    done: &AtomicBool,
    stop: &AtomicBool,
) -> Result<()> {
    let live = source.is_live();
    let mut emit = |ev: SourceEvent| match ev {
        SourceEvent::Sample(s) if live => match stx.try_send(InBand::Sample(s)) {
            Ok(()) => {}
            Err(mpsc::TrySendError::Full(_)) => {
                dropped.fetch_add(1, Ordering::Relaxed);
            }
            Err(mpsc::TrySendError::Disconnected(_)) => {}
        },
        SourceEvent::Sample(s) => {
            let _ = stx.send(InBand::Sample(s));
        }
        SourceEvent::Notice(n) => {
            // a board's configuration goes in order with its samples, and is
            // never dropped (it names the ranges they are read at)
            if let SourceNotice::Link(Notice::Config(c)) = &n {
                let _ = stx.send(InBand::Config(*c));
            }
            let _ = ntx.send(n);
        }
    };
    while !done.load(Ordering::Relaxed) && !stop.load(Ordering::Relaxed) {
        while let Ok(cmd) = crx.try_recv() {
            source.send(&cmd)?;
        }
        if !source.poll(&mut emit)? {
            break;
        }
    }
    Ok(())
}

fn consume(
    c: &mut Consumer,
    srx: &mpsc::Receiver<InBand>,
    nrx: &mpsc::Receiver<SourceNotice>,
    ctx: &mpsc::Sender<Frame>,
    obs: &mut dyn StreamObserver,
    stop: &AtomicBool,
    dropped: &AtomicU64,
) -> Result<()> {
    let (mut last_tick, mut last_dials) = (Instant::now(), Instant::now());
    loop {
        match srx.recv_timeout(Duration::from_millis(50)) {
            Ok(i) => {
                c.item(&i, obs)?;
                for _ in 0..1024 {
                    match srx.try_recv() {
                        Ok(i) => c.item(&i, obs)?,
                        Err(_) => break,
                    }
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {}
            Err(mpsc::RecvTimeoutError::Disconnected) => return Ok(()),
        }
        while let Ok(n) = nrx.try_recv() {
            c.counts.add(&n);
            obs.notice(&n, &c.counts);
        }
        if stop.load(Ordering::Relaxed) {
            return Ok(());
        }
        if last_tick.elapsed() >= Duration::from_millis(200) {
            last_tick = Instant::now();
            c.counts.dropped = dropped.load(Ordering::Relaxed);
            c.counts.received = c.counts.pipeline.samples + c.counts.dropped;
            obs.tick(&c.live());
        }
        if c.cfg.dials
            && last_dials.elapsed() >= Duration::from_millis(100)
            && let Some(t) = c.last.and_then(|o| o.tilt())
        {
            last_dials = Instant::now();
            if ctx.send(dial_frame(&t)).is_ok() {
                c.counts.dials_sent += 1;
            }
        }
    }
}

/// The protocol's conformance vector from a recording: one CONFIG (`config`)
/// then one SAMPLE per row, the rows quantised to MPU6050 counts at the
/// CONFIG's ranges (rounded to nearest, saturating); board time
/// `t_us = t0_us + round((t_s − t_s,first) · 10⁶)` modulo 2³², sequence from
/// 0; temperature counts from `temp_c` (25 °C when absent). Returns the wire
/// bytes and the same samples decoded ([`RAW_HEADER`] CSV, exact digits),
/// decoded by the crate's own [`protocol::Decoder`] and [`protocol::Link`].
pub fn conformance_vector(
    samples: &[ImuSample],
    config: &protocol::Config,
    t0_us: u32,
) -> Result<(Vec<u8>, String)> {
    let scales = config
        .scales()
        .map_err(|e| Error::new(ErrorKind::InvalidInput, format!("conformance vector: {e}")))?;
    let mut wire = Vec::new();
    let mut buf = [0u8; protocol::MAX_FRAME];
    let mut put = |f: &Frame, wire: &mut Vec<u8>| {
        let n = protocol::encode(f, &mut buf).unwrap_or(0);
        wire.extend_from_slice(&buf[..n]);
    };
    put(&Frame::Config(*config), &mut wire);
    let t_first = samples.first().map_or(0.0, |s| s.t_s);
    for (k, s) in samples.iter().enumerate() {
        let dt_us = ((s.t_s - t_first) * 1e6).round() as u64;
        let temp = s.temp_c.unwrap_or(25.0);
        let q = |v: &Vec3, f: &dyn Fn(f64) -> i16| [f(v.x), f(v.y), f(v.z)];
        let frame = Frame::Sample(protocol::Sample {
            seq: k as u16,
            t_us: t0_us.wrapping_add(dt_us as u32),
            acc: q(&s.acc_m_s2, &|x| scales.acc_counts(x)),
            temp: ((temp - 36.53) * 340.0).round().clamp(-32768.0, 32767.0) as i16,
            gyr: q(&s.gyr_rad_s, &|x| scales.gyr_counts(x)),
        });
        put(&frame, &mut wire);
    }
    let mut out = CsvLineWriter::new(Vec::new());
    out.header(&RAW_HEADER).map_err(Error::from)?;
    let mut dec = protocol::Decoder::new();
    let mut link = protocol::Link::new();
    let mut fail = None;
    dec.feed(&wire, |d| match d.result {
        Ok(f) => {
            if let Some((_, s)) = link.push(&f).sample
                && let Err(e) = write_raw(&mut out, &s)
            {
                fail = Some(e);
            }
        }
        Err(e) => fail = Some(std::io::Error::other(e.to_string())),
    });
    if let Some(e) = fail {
        return Err(Error::from(e));
    }
    let text = String::from_utf8(out.finish().map_err(Error::from)?).unwrap_or_default();
    Ok((wire, text))
}

/// Rows of the embedded BROAD excerpt in the conformance vector.
pub const VECTOR_ROWS: usize = 2000;

/// Board time of the vector's first sample, µs: 3.5 s before the 32-bit
/// clock wraps (a board up for 71.5 minutes), so the vector crosses the wrap.
pub const VECTOR_T0_US: u32 = u32::MAX - 3_499_999;

/// The CONFIG of the conformance vector: protocol 1, firmware 0.1.0, the
/// host simulator (board 3), 286 Hz (the recording's 285.7 Hz), ±8 g,
/// ±1000 °/s, DLPF_CFG 3, streaming.
pub const VECTOR_CONFIG: protocol::Config = protocol::Config {
    proto_version: protocol::PROTO_VERSION,
    firmware: [0, 1, 0],
    board: 3,
    rate_hz: 286,
    accel_fs_g: 8,
    gyro_fs_dps: 1000,
    dlpf_cfg: 3,
    streaming: 1,
};

/// `firmware/protocol/frames.bin` and `frames.csv`: the first
/// [`VECTOR_ROWS`] rows of the embedded BROAD excerpt
/// ([`crate::demo::BROAD_EXCERPT`], trial 07, fast rotations) through
/// [`conformance_vector`] with [`VECTOR_CONFIG`] and [`VECTOR_T0_US`]
/// (temperature 25 °C). The gyro's x axis exceeds ±1000 °/s in places and
/// is clipped at the i16 limits there, as the chip would.
pub fn reference_vector() -> Result<(Vec<u8>, String)> {
    let mut r = crate::io::ImuCsvReader::new(
        crate::demo::BROAD_EXCERPT.as_bytes(),
        "broad_07_excerpt.csv",
        &crate::io::ReadOptions {
            imu_only: true,
            ..Default::default()
        },
    )?;
    let mut samples = Vec::with_capacity(VECTOR_ROWS);
    while samples.len() < VECTOR_ROWS
        && let Some(row) = r.next_row()?
    {
        samples.push(row.sample);
    }
    conformance_vector(&samples, &VECTOR_CONFIG, VECTOR_T0_US)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fusion::FilterKind;

    /// A live source that makes `n` samples as fast as it can.
    struct Burst {
        n: u64,
        k: u64,
    }
    impl SampleSource for Burst {
        fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
            for _ in 0..64 {
                if self.k == self.n {
                    return Ok(false);
                }
                let t = self.k as f64 * 0.01;
                emit(SourceEvent::Sample(ImuSample::new(
                    t,
                    Vec3::zeros(),
                    Vec3::new(0.0, 0.0, 9.81),
                )));
                self.k += 1;
            }
            Ok(true)
        }
        fn name(&self) -> &str {
            "burst"
        }
    }

    /// An observer that is slow to take each tick and notice.
    struct Slow(u32);
    impl StreamObserver for Slow {
        fn notice(&mut self, _: &SourceNotice, _: &StreamCounts) {}
        fn message(&mut self, _: &str) {}
        fn tick(&mut self, _: &LiveStatus) {
            self.0 += 1;
        }
    }

    /// A board streaming 100 Hz at ±`gyro_fs` °/s: its CONFIG, then samples
    /// at rest whose x rate sits on the gyro's rail for samples 100–109
    /// (its counts of 250.13 °/s at ±250), then a second CONFIG at ±2000 °/s
    /// and the same again (100 samples, 10 of them at 250.13 °/s, now far
    /// from the rail).
    struct Board {
        k: u64,
    }
    impl SampleSource for Board {
        fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
            let config = |gyro_fs_dps| protocol::Config {
                gyro_fs_dps,
                ..VECTOR_CONFIG
            };
            if self.k == 0 || self.k == 200 {
                let c = config(if self.k == 0 { 250 } else { 2000 });
                emit(SourceEvent::Notice(SourceNotice::Link(Notice::Config(c))));
            }
            if self.k == 300 {
                return Ok(false);
            }
            let rail = f64::from(i16::MAX) / 131.0;
            let w = if (100..110).contains(&(self.k % 200)) {
                rail.to_radians()
            } else {
                0.0
            };
            emit(SourceEvent::Sample(ImuSample::new(
                self.k as f64 * 0.01,
                Vec3::new(w, 0.0, 0.0),
                Vec3::new(0.0, 0.0, 9.81),
            )));
            self.k += 1;
            Ok(true)
        }
        fn name(&self) -> &str {
            "board"
        }
    }

    #[test]
    fn a_board_names_the_ranges_its_samples_clip_at() {
        let stop = AtomicBool::new(false);
        let run_with = |range: crate::fusion::SensorRange| {
            let cfg =
                StreamConfig::new(FilterConfig::new(FilterKind::Dynamic).with_sensor_range(range));
            run(
                Box::new(Board { k: 0 }),
                &cfg,
                &mut StreamOutputs::default(),
                &mut Slow(0),
                &stop,
            )
            .unwrap()
        };
        // the board's ranges: the ten samples on the ±250 °/s rail, not the
        // ten read at ±2000 °/s
        let c = run_with(crate::fusion::SensorRange::default());
        assert_eq!((c.pipeline.samples, c.pipeline.gyro_clipped), (300, 10));
        // the user's ranges are kept
        let r = crate::fusion::SensorRange::from_full_scale(16.0, 2000.0);
        assert_eq!(run_with(r).pipeline.gyro_clipped, 0);
    }

    /// A board at 100 Hz with its filter at 5 Hz (DLPF_CFG 6; the Arduino
    /// firmware: divider 0, the chip at 1 kHz, read on a timer): at rest for
    /// 10 s, then turning about x at 1 rad/s. Its samples stand for the
    /// instants the datasheet's delays and half the 1-ms register period
    /// before their stamps: the accelerometer's 19.5 ms, the gyro's 19.1 ms.
    struct SlowFilterBoard {
        k: u64,
    }
    impl SampleSource for SlowFilterBoard {
        // the timing these samples are made with, from the datasheet's
        // table, not from `SensorTiming`
        fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
            if self.k == 0 {
                let c = protocol::Config {
                    board: 1,
                    rate_hz: 100,
                    dlpf_cfg: 6,
                    ..VECTOR_CONFIG
                };
                emit(SourceEvent::Notice(SourceNotice::Link(Notice::Config(c))));
            }
            if self.k == 1500 {
                return Ok(false);
            }
            let t = self.k as f64 * 0.01;
            let (ta, tg) = (t - 0.0195, t - 0.0191);
            let acc =
                nalgebra::UnitQuaternion::from_axis_angle(&Vec3::x_axis(), (ta - 10.0).max(0.0))
                    .inverse_transform_vector(&Vec3::new(0.0, 0.0, 9.80665));
            let w = if tg > 10.0 { 1.0 } else { 0.0 };
            emit(SourceEvent::Sample(ImuSample::new(
                t,
                Vec3::new(w, 0.0, 0.0),
                acc,
            )));
            self.k += 1;
            Ok(true)
        }
        fn name(&self) -> &str {
            "slow-filter board"
        }
    }

    #[test]
    fn sensor_timing_is_the_datasheets_delays_in_the_filters_terms() {
        let close = |t: SensorTiming, periods: f64, lag_ms: f64| {
            (t.sensor_delay_periods - periods).abs() < 1e-9
                && (t.gyro_lag_s * 1e3 - lag_ms).abs() < 1e-9
        };
        // the I²C source's chip: 1 kHz sample clock, read at 100 Hz on a timer
        let mut c = clino_mpu6050::Config::default();
        c.sample_rate_divider = c.divider_for(1000).unwrap();
        let t = SensorTiming::mpu6050(&c, false, 100.0);
        assert!(close(t, 0.53, -0.1), "{t:?}");
        let t = SensorTiming::mpu6050(&c, false, 1000.0);
        assert!(close(t, 5.3, -0.1), "{t:?}");
        // an Arduino board (divider 0) with the filter off, at 1 kHz: the
        // gyro 0.98 ms + 1/16 ms, the accelerometer 0.5 ms
        let board = |board, rate_hz, dlpf_cfg| protocol::Config {
            board,
            rate_hz,
            dlpf_cfg,
            ..VECTOR_CONFIG
        };
        let t = SensorTiming::of_board(&board(1, 1000, 0)).unwrap();
        assert!(close(t, 1.0425, 0.5425), "{t:?}");
        // clino's Cortex-M firmware reads on the data-ready flag: the filter alone
        let t = SensorTiming::of_board(&board(2, 100, 3)).unwrap();
        assert!(close(t, 0.48, -0.1), "{t:?}");
        // no such setting, no rate, a rate the chip cannot divide to
        assert!(SensorTiming::of_board(&board(1, 100, 7)).is_none());
        assert!(SensorTiming::of_board(&board(1, 0, 3)).is_none());
        assert!(SensorTiming::of_board(&board(2, 300, 3)).is_none());
        // a note round trip, exact; malformed or out-of-range notes give none
        let t = SensorTiming::of_board(&board(1, 1000, 0)).unwrap();
        let note = format!("clino.{} {}", SensorTiming::NOTE, t.note_text());
        assert_eq!(
            SensorTiming::from_notes(&["clino.other x".into(), note]),
            Some(t)
        );
        for bad in [
            "sensor_delay_periods=1",
            "sensor_delay_periods=1,gyro_lag_s=x",
            "sensor_delay_periods=1,gyro_lag_s=NaN",
            "sensor_delay_periods=1,gyro_lag_s=0.001,bandwidth=2",
            "sensor_delay_periods=1000,gyro_lag_s=0",
            "sensor_delay_periods=1,gyro_lag_s=0.5",
        ] {
            let n = format!("clino.{} {bad}", SensorTiming::NOTE);
            assert_eq!(SensorTiming::from_notes(&[n]), None, "{bad}");
        }
        let t = SensorTiming::of_board(&board(2, 100, 3)).unwrap();
        // applied: both fields, nothing else
        let mut p = DynamicParams::default();
        t.apply(&mut p);
        assert_eq!((p.sensor_delay_periods, p.gyro_lag_s), (0.48, t.gyro_lag_s));
        assert_eq!(p.bandwidth_rad_s, DynamicParams::default().bandwidth_rad_s);
    }

    /// An observer that keeps what it is told once.
    struct Said(Vec<String>);
    impl StreamObserver for Said {
        fn notice(&mut self, _: &SourceNotice, _: &StreamCounts) {}
        fn message(&mut self, text: &str) {
            self.0.push(text.to_string());
        }
        fn tick(&mut self, _: &LiveStatus) {}
    }

    /// Bytes written to a shared buffer (a stream's CSV output).
    #[derive(Clone, Default)]
    struct Shared(std::sync::Arc<std::sync::Mutex<Vec<u8>>>);
    impl Write for Shared {
        fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
            self.0.lock().unwrap().extend_from_slice(b);
            Ok(b.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_boards_filter_delay_is_made_up_from_its_config() {
        // the roll reported 5 s into the turn against the true 5 rad at the
        // last stamp: with the board's timing (19.1 ms, 1.91 periods) it is
        // the turn's; with the default half period it lags by ω·14.1 ms
        let stop = AtomicBool::new(false);
        let tmp = tempfile::Builder::new()
            .prefix("clino-stream-test-")
            .tempdir()
            .unwrap();
        let roll_error = |board_timing: bool| {
            let cfg = StreamConfig {
                board_timing,
                ..StreamConfig::new(FilterConfig::new(FilterKind::Dynamic))
            };
            let out = Shared::default();
            let rec = tmp.path().join(format!("rec-{board_timing}.csv"));
            let pq = tmp.path().join(format!("rec-{board_timing}.parquet"));
            let mut outputs = StreamOutputs {
                csv: Some(FusedCsv::new(Box::new(out.clone()) as Box<dyn Write + Send>).unwrap()),
                record: Some(Recorder::create(&rec, &[]).unwrap()),
            };
            let mut said = Said(Vec::new());
            run(
                Box::new(SlowFilterBoard { k: 0 }),
                &cfg,
                &mut outputs,
                &mut said,
                &stop,
            )
            .unwrap();
            outputs.record.take().unwrap().finish().unwrap();
            drop(outputs);
            let text = String::from_utf8(out.0.lock().unwrap().clone()).unwrap();
            // the same again into a Parquet recording
            let mut outputs = StreamOutputs {
                record: Some(Recorder::create(&pq, &[]).unwrap()),
                ..Default::default()
            };
            run(
                Box::new(SlowFilterBoard { k: 0 }),
                &cfg,
                &mut outputs,
                &mut Said(Vec::new()),
                &stop,
            )
            .unwrap();
            outputs.record.take().unwrap().finish().unwrap();
            // the CSV recording says so (a comment, and the note), once
            let recorded = std::fs::read_to_string(&rec).unwrap();
            let notes: Vec<&str> = recorded.lines().filter(|l| l.starts_with('#')).collect();
            assert_eq!(notes.len(), 2 * usize::from(board_timing), "{notes:?}");
            assert_eq!(said.0.len(), usize::from(board_timing), "{:?}", said.0);
            // fused as they are, both recordings give the stream's rows to
            // the byte; with the timing named by the user, the note is not
            // taken (and the default half period gives other rows)
            let fuse = |path: &std::path::Path, filter: &FilterConfig| {
                let mut reader =
                    crate::io::ImuCsvReader::from_path(path, &crate::io::ReadOptions::default())
                        .unwrap();
                let mut fused = Vec::new();
                let rep = crate::fusion::fuse(
                    &mut reader,
                    &mut fused,
                    filter,
                    &crate::fusion::FuseOptions::default(),
                )
                .unwrap();
                (String::from_utf8(fused).unwrap(), rep.timing.is_some())
            };
            let plain = FilterConfig::new(FilterKind::Dynamic);
            let first_difference = |a: &str| {
                a.lines()
                    .zip(text.lines())
                    .position(|(x, y)| x != y)
                    .map(|k| (k, a.lines().nth(k).unwrap().to_string()))
            };
            for path in [&rec, &pq] {
                let (rows, taken) = fuse(path, &plain);
                assert_eq!(taken, board_timing, "{path:?}");
                assert_eq!(first_difference(&rows), None, "{path:?}");
                assert_eq!(rows.len(), text.len(), "{path:?}");
                let (rows, taken) = fuse(path, &plain.with_timing_given(true));
                assert!(!taken);
                assert_eq!(first_difference(&rows).is_none(), !board_timing, "{path:?}");
            }
            let last = text.lines().last().unwrap().to_string();
            let cols: Vec<&str> = last.split(',').collect();
            let t: f64 = cols[0].parse().unwrap();
            let roll: f64 = cols[5].parse().unwrap();
            // the true roll at the stamp, wrapped to ±180°
            let truth = (t - 10.0).to_degrees();
            let e = (roll - truth).rem_euclid(360.0);
            e.min(360.0 - e)
        };
        // 0.07° told (the rate's onset between two samples, and the loop),
        // 0.75° not (ω·14.1 ms = 0.81°, less what the loop pulled away)
        let told = roll_error(true);
        let not = roll_error(false);
        assert!(told < 0.15, "{told}°");
        assert!(not > 0.6, "{not}°");
    }

    /// A source whose samples a host stamped as they arrived: 100 Hz for
    /// 120 s, each late by 0–8 ms (exponential, mean 2 ms; a fixed
    /// scrambled sequence), at rest.
    struct HostStamped {
        k: u64,
        last: f64,
    }
    impl SampleSource for HostStamped {
        fn poll(&mut self, emit: &mut dyn FnMut(SourceEvent)) -> Result<bool> {
            if self.k == 12_000 {
                return Ok(false);
            }
            // splitmix64 of k: uniform in [0, 1)
            let mut z = self.k.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
            let t =
                (self.k as f64 * 0.01 + (-0.002 * (1.0 - u).ln()).min(0.008)).max(self.last + 1e-6);
            self.last = t;
            emit(SourceEvent::Sample(ImuSample::new(
                t,
                Vec3::zeros(),
                Vec3::new(0.0, 0.0, 9.81),
            )));
            self.k += 1;
            Ok(true)
        }
        fn name(&self) -> &str {
            "host"
        }
    }

    #[test]
    fn a_stream_stamped_by_its_host_says_it_took_the_recovered_clock() {
        let stop = AtomicBool::new(false);
        // room for every sample: none dropped by a slow consumer
        let cfg = StreamConfig {
            capacity: 20_000,
            ..StreamConfig::new(FilterConfig::new(FilterKind::Dynamic))
        };
        let c = run(
            Box::new(HostStamped { k: 0, last: 0.0 }),
            &cfg,
            &mut StreamOutputs::default(),
            &mut Slow(0),
            &stop,
        )
        .unwrap();
        assert!(
            c.pipeline.retimed > 8000,
            "{}: {:?}",
            c.pipeline.retimed,
            c.summary()
        );
        let said = c.summary().join("\n");
        assert!(
            said.contains(&format!(
                "{} steps from the sample clock recovered from the stamps",
                c.pipeline.retimed
            )),
            "{said}"
        );
    }

    #[test]
    fn a_slow_consumer_loses_samples_and_counts_every_one() {
        // a recording sink that takes 1 ms per row: far slower than the burst
        struct Sleepy;
        impl Write for Sleepy {
            fn write(&mut self, b: &[u8]) -> std::io::Result<usize> {
                std::thread::sleep(Duration::from_millis(1));
                Ok(b.len())
            }
            fn flush(&mut self) -> std::io::Result<()> {
                Ok(())
            }
        }
        let mut cfg = StreamConfig::new(FilterConfig::new(FilterKind::Mahony));
        cfg.capacity = 8;
        let mut outputs = StreamOutputs {
            csv: Some(FusedCsv::new(Box::new(Sleepy) as Box<dyn Write + Send>).unwrap()),
            record: None,
        };
        let stop = AtomicBool::new(false);
        let n = 20_000;
        let counts = run(
            Box::new(Burst { n, k: 0 }),
            &cfg,
            &mut outputs,
            &mut Slow(0),
            &stop,
        )
        .unwrap();
        assert_eq!(counts.received, n);
        assert!(counts.dropped > 0, "{counts:?}");
        assert_eq!(counts.pipeline.samples + counts.dropped, n);
        // a live source without a buffer limit problem loses nothing
        cfg.capacity = 100_000;
        let counts = run(
            Box::new(Burst { n, k: 0 }),
            &cfg,
            &mut StreamOutputs::default(),
            &mut Slow(0),
            &stop,
        )
        .unwrap();
        assert_eq!((counts.dropped, counts.pipeline.samples), (0, n));
    }

    #[test]
    fn the_vector_decodes_to_its_quantised_samples() {
        let cfg = protocol::Config {
            proto_version: 1,
            firmware: [0, 1, 0],
            board: 3,
            rate_hz: 100,
            accel_fs_g: 8,
            gyro_fs_dps: 1000,
            dlpf_cfg: 3,
            streaming: 1,
        };
        let s: Vec<ImuSample> = (0..5)
            .map(|k| {
                ImuSample::new(
                    k as f64 * 0.01,
                    Vec3::new(0.1, -0.2, 20.0), // 20 rad/s saturates ±1000 °/s
                    Vec3::new(0.0, 1.0, 9.8),
                )
            })
            .collect();
        let (wire, csv) = conformance_vector(&s, &cfg, u32::MAX - 15_000).unwrap();
        assert_eq!(wire.len(), 17 + 5 * 25);
        let rows: Vec<Vec<f64>> = csv
            .lines()
            .skip(1)
            .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 5);
        // time unwrapped across 2^32 µs
        assert_eq!(
            rows[2][0],
            (u32::MAX as u64 - 15_000 + 20_000) as f64 * 1e-6
        );
        let sc = cfg.scales().unwrap();
        assert_eq!(rows[0][3], sc.gyr_rad_s(i16::MAX));
        assert!((rows[0][1] - 0.1).abs() < 0.5 / 32.8 * 0.0175);
        assert!((rows[0][6] - 9.8).abs() <= 0.5 / 4096.0 * protocol_g());
        assert!((rows[0][7] - 25.0).abs() < 0.5 / 340.0 + 1e-12);
    }

    fn protocol_g() -> f64 {
        clino_core::G0
    }
}
