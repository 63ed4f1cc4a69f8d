//! Recordings in and results out.
//!
//! * [`TableReader`] is the one CSV reader: its rules (comments, byte-order
//!   mark, CRLF, names, cells, errors) hold for every recording clino reads;
//! * [`ImuCsvReader`] streams an IMU recording from CSV, one [`ImuRow`] at a
//!   time, in constant memory;
//! * [`CsvLineWriter`] writes numeric CSV rows without allocating per row;
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
mod table;

pub use atomic::AtomicFile;
pub use convert::convert;
pub use csv_in::{AccelUnit, GyroUnit, ImuCsvReader, ImuRow, ReadOptions};
pub use csv_out::{CsvLineWriter, RowSink};
pub use parquet::{ParquetRowWriter, is_parquet};
pub use table::TableReader;
