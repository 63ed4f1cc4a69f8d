//! Recordings in and results out.
//!
//! * [`TableReader`] is the one table reader, CSV or Parquet (by the
//!   `.parquet` extension); its rules hold for every recording clino reads:
//!   a byte-order mark is dropped; `#` lines are comments, before the header
//!   and between rows; blank lines are skipped; LF or CRLF; columns are found
//!   by name (ASCII case ignored, spaces and quotes trimmed), others are never
//!   parsed; every row has the header's number of fields; a numeric cell is a
//!   number, `nan`/`inf`, or empty (NaN); every error names the file, the
//!   1-based line (comments counted; a Parquet row's line is its number plus
//!   one) and the column; a comment line `# clino.NAME TEXT` before the
//!   first data row is a note for the readers ([`TableReader::notes`]; in
//!   Parquet, key-value metadata `clino.NAME`): a recording of `clino
//!   stream` notes its sensor's timing so;
//! * [`ImuCsvReader`] streams an IMU recording (CSV or Parquet), one
//!   [`ImuRow`] at a time, in constant memory; units by column name
//!   (`_rad_s`, `_deg_s`, `_m_s2`, `_g`) or, for bare names, by flag;
//! * [`ParquetRowWriter`] and [`CsvLineWriter`] write rows ([`RowSink`]);
//!   [`convert`] copies a table between the formats;
//! * [`source`]: sample sources behind one trait ([`source::SampleSource`]):
//!   a file, a replay at a chosen speed, a serial port speaking clino's protocol,
//!   an MPU6050 on an I²C bus;
//! * [`AtomicFile`] makes an output file appear whole or not at all.
//!
//! The CSV layout is that of the BROAD benchmark files shipped with the
//! project (Laidig, Caruso, Cereatti, Seel, "BROAD — A Benchmark for Robust
//! Inertial Orientation Estimation", Data 6(7), 2021): lines starting with
//! `#` are comments, the first other line is the header, and columns are found
//! by their header name, in any order.

mod atomic;
mod convert;
mod csv_in;
mod csv_out;
pub mod parquet;
pub mod source;
mod table;

pub use atomic::AtomicFile;
pub use convert::convert;
pub use csv_in::{
    AccelUnit, GAP_FACTOR, GyroUnit, ImuCsvReader, ImuRow, ReadOptions, TimeGap, TimeGaps, row_time,
};
pub use csv_out::{CsvLineWriter, RowSink};
pub use parquet::{ParquetRowWriter, is_parquet};
pub(crate) use table::parse_f64 as parse_cell;
pub use table::{NOTE_PREFIX, TableReader, quote_cell};
