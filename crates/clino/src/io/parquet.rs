//! Parquet recordings: the same columns, names and rules as CSV.
//!
//! A Parquet file is read column chunk by column chunk (one row group in
//! memory at a time, so memory is bounded by the writer's row-group size, not
//! the file's length) and handed to [`super::TableReader`] row by row: column
//! lookup by name, cell rules and error messages are the CSV ones. Numeric
//! columns may be DOUBLE, FLOAT, INT32, INT64 or BOOLEAN (true = 1); a null
//! reads as an empty CSV cell (NaN); BYTE_ARRAY columns read as text. In
//! errors the "line" of a Parquet row is its 1-based row number plus one (the
//! line it would have in the same table written as CSV, under its header).
//!
//! Files are written with [`ParquetRowWriter`]: DOUBLE columns (and UTF-8
//! text ones), required, uncompressed by default, in row groups of
//! [`ROW_GROUP_ROWS`] rows. Reading accepts uncompressed and Snappy files
//! (the default of pandas and Spark).

use std::fs::File;
use std::path::Path;
use std::sync::Arc;

use parquet::basic::{ConvertedType, Repetition, Type as PhysicalType};
use parquet::column::reader::{ColumnReader, ColumnReaderImpl};
use parquet::data_type::{ByteArray, ByteArrayType, DataType, DoubleType};
use parquet::file::properties::{EnabledStatistics, WriterProperties};
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::file::writer::SerializedFileWriter;
use parquet::schema::types::ColumnPath;
use parquet::schema::types::Type;

use crate::{Error, ErrorKind, Result};

/// Rows per row group written by [`ParquetRowWriter`] (≈ 8 MB for ten DOUBLE columns).
pub const ROW_GROUP_ROWS: usize = 100_000;

/// True when `path` names a Parquet file (by its `.parquet` extension).
pub fn is_parquet(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

fn pq_err(path: &Path, e: impl std::fmt::Display) -> Error {
    Error::new(ErrorKind::Parse, format!("Parquet: {e}")).in_file(path)
}

/// One column of the current row group.
enum Column {
    Num(Vec<f64>),
    Text(Vec<String>),
    /// A type clino does not read (INT96, fixed-length bytes, nested).
    Other(&'static str),
}

/// The rows of a Parquet file, one row group buffered at a time.
pub(crate) struct ParquetRows {
    /// The file's `clino.*` key-value metadata ([`ParquetRows::notes`]).
    notes: Vec<String>,
    path: std::path::PathBuf,
    reader: SerializedFileReader<File>,
    names: Vec<String>,
    group: usize,
    columns: Vec<Column>,
    group_rows: usize,
    pos: usize,
    /// the columns decoded (all unless [`ParquetRows::project`] narrowed them)
    wanted: Vec<bool>,
}

fn read_column<T: DataType>(
    r: &mut ColumnReaderImpl<T>,
    rows: usize,
    max_def: i16,
    conv: impl Fn(&T::T) -> f64,
) -> parquet::errors::Result<Vec<f64>> {
    let mut defs: Vec<i16> = Vec::with_capacity(rows);
    let mut vals: Vec<T::T> = Vec::with_capacity(rows);
    let mut got = 0;
    while got < rows {
        let (records, _, _) = r.read_records(rows - got, Some(&mut defs), None, &mut vals)?;
        if records == 0 {
            break;
        }
        got += records;
    }
    if max_def == 0 {
        return Ok(vals.iter().map(conv).collect());
    }
    let mut it = vals.iter();
    Ok(defs
        .iter()
        .map(|&d| {
            if d == max_def {
                it.next().map_or(f64::NAN, &conv)
            } else {
                f64::NAN
            }
        })
        .collect())
}

impl ParquetRows {
    pub(crate) fn open(path: &Path) -> Result<Self> {
        let f = File::open(path).map_err(|e| Error::from(e).in_file(path))?;
        let reader = SerializedFileReader::new(f).map_err(|e| pq_err(path, e))?;
        let notes = reader
            .metadata()
            .file_metadata()
            .key_value_metadata()
            .map(|kv| {
                kv.iter()
                    .filter(|k| k.key.starts_with("clino."))
                    .filter_map(|k| Some(format!("{} {}", k.key, k.value.as_deref()?)))
                    .take(16)
                    .collect()
            })
            .unwrap_or_default();
        let names = reader
            .metadata()
            .file_metadata()
            .schema_descr()
            .columns()
            .iter()
            .map(|c| c.path().string())
            .collect::<Vec<_>>();
        Ok(Self {
            notes,
            wanted: vec![true; names.len()],
            path: path.to_path_buf(),
            reader,
            names,
            group: 0,
            columns: Vec::new(),
            group_rows: 0,
            pos: 0,
        })
    }

    pub(crate) fn names(&self) -> &[String] {
        &self.names
    }

    /// The file's key-value metadata named `clino.*`, as `clino.NAME VALUE`.
    pub(crate) fn notes(&self) -> &[String] {
        &self.notes
    }

    /// Decode only the columns `cols` from the next row group on (the others
    /// read as [`Cell::Other`]): what a columnar format is for — `clino fuse`
    /// needs 7 of BROAD's 15 columns.
    pub(crate) fn project(&mut self, cols: &[usize]) {
        self.wanted.iter_mut().for_each(|w| *w = false);
        for &i in cols {
            if let Some(w) = self.wanted.get_mut(i) {
                *w = true;
            }
        }
    }

    fn load_group(&mut self) -> Result<bool> {
        let meta = self.reader.metadata();
        if self.group >= meta.num_row_groups() {
            return Ok(false);
        }
        let rows = meta.row_group(self.group).num_rows().max(0) as usize;
        let descr = meta.file_metadata().schema_descr_ptr();
        let rg = self
            .reader
            .get_row_group(self.group)
            .map_err(|e| pq_err(&self.path, e))?;
        let mut columns = Vec::with_capacity(self.names.len());
        for i in 0..self.names.len() {
            if !self.wanted[i] {
                columns.push(Column::Other("a column not read"));
                continue;
            }
            let max_def = descr.column(i).max_def_level();
            if descr.column(i).max_rep_level() > 0 {
                columns.push(Column::Other("a repeated (list) column"));
                continue;
            }
            let cr = rg.get_column_reader(i).map_err(|e| pq_err(&self.path, e))?;
            let e = |e| pq_err(&self.path, e);
            let col = match cr {
                ColumnReader::DoubleColumnReader(mut r) => {
                    Column::Num(read_column(&mut r, rows, max_def, |v| *v).map_err(e)?)
                }
                ColumnReader::FloatColumnReader(mut r) => {
                    Column::Num(read_column(&mut r, rows, max_def, |v| *v as f64).map_err(e)?)
                }
                ColumnReader::Int32ColumnReader(mut r) => {
                    Column::Num(read_column(&mut r, rows, max_def, |v| *v as f64).map_err(e)?)
                }
                ColumnReader::Int64ColumnReader(mut r) => {
                    Column::Num(read_column(&mut r, rows, max_def, |v| *v as f64).map_err(e)?)
                }
                ColumnReader::BoolColumnReader(mut r) => Column::Num(
                    read_column(&mut r, rows, max_def, |v| f64::from(u8::from(*v))).map_err(e)?,
                ),
                ColumnReader::ByteArrayColumnReader(mut r) => {
                    let mut defs: Vec<i16> = Vec::with_capacity(rows);
                    let mut vals: Vec<ByteArray> = Vec::with_capacity(rows);
                    let mut got = 0;
                    while got < rows {
                        let (n, _, _) = r
                            .read_records(rows - got, Some(&mut defs), None, &mut vals)
                            .map_err(e)?;
                        if n == 0 {
                            break;
                        }
                        got += n;
                    }
                    let text = |b: &ByteArray| String::from_utf8_lossy(b.data()).into_owned();
                    let mut it = vals.iter();
                    Column::Text(if max_def == 0 {
                        vals.iter().map(text).collect()
                    } else {
                        defs.iter()
                            .map(|&d| {
                                if d == max_def {
                                    it.next().map(text).unwrap_or_default()
                                } else {
                                    String::new()
                                }
                            })
                            .collect()
                    })
                }
                _ => Column::Other("an INT96 or fixed-length column"),
            };
            columns.push(col);
        }
        self.columns = columns;
        self.group_rows = rows;
        self.pos = 0;
        self.group += 1;
        Ok(true)
    }

    /// Advance to the next row; `Ok(false)` at the end.
    pub(crate) fn next(&mut self) -> Result<bool> {
        while self.pos + 1 > self.group_rows || self.columns.is_empty() {
            if !self.load_group()? {
                return Ok(false);
            }
            if self.group_rows > 0 {
                self.pos = 0;
                return Ok(true);
            }
        }
        self.pos += 1;
        if self.pos < self.group_rows {
            Ok(true)
        } else {
            self.columns.clear();
            self.next()
        }
    }

    /// Cell `i` of the current row: a number, or the text of a text column.
    #[inline]
    pub(crate) fn cell(&self, i: usize) -> Cell<'_> {
        match self.columns.get(i) {
            Some(Column::Num(v)) => Cell::Num(v.get(self.pos).copied().unwrap_or(f64::NAN)),
            Some(Column::Text(v)) => Cell::Text(v.get(self.pos).map_or("", String::as_str)),
            Some(Column::Other(what)) => Cell::Other(what),
            None => Cell::Other("a missing column"),
        }
    }
}

/// One cell of a Parquet row.
pub(crate) enum Cell<'a> {
    Num(f64),
    Text(&'a str),
    Other(&'static str),
}

#[inline]
fn same_text(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x == y)
}

/// Writes rows of numeric (and text) cells to a Parquet file, a row group at
/// a time (memory bounded by [`ROW_GROUP_ROWS`]), through the same calls as
/// [`super::CsvLineWriter`].
pub struct ParquetRowWriter<W: std::io::Write + Send> {
    writer: Option<SerializedFileWriter<W>>,
    text: Vec<bool>,
    num: Vec<Vec<f64>>,
    txt: Vec<Vec<ByteArray>>,
    /// the last text written to each column, shared (a status repeats)
    last_txt: Vec<Option<ByteArray>>,
    col: usize,
    rows: usize,
}

impl<W: std::io::Write + Send> ParquetRowWriter<W> {
    /// A writer of the columns `names`; those named in `text_columns` hold
    /// UTF-8 text, the others DOUBLE.
    pub fn new(out: W, names: &[&str], text_columns: &[&str]) -> Result<Self> {
        let err =
            |e: parquet::errors::ParquetError| Error::new(ErrorKind::Io, format!("Parquet: {e}"));
        let text: Vec<bool> = names.iter().map(|n| text_columns.contains(n)).collect();
        let fields = names
            .iter()
            .zip(&text)
            .map(|(n, &t)| {
                let b = if t {
                    Type::primitive_type_builder(n, PhysicalType::BYTE_ARRAY)
                        .with_converted_type(ConvertedType::UTF8)
                } else {
                    Type::primitive_type_builder(n, PhysicalType::DOUBLE)
                };
                b.with_repetition(Repetition::REQUIRED)
                    .build()
                    .map(Arc::new)
            })
            .collect::<parquet::errors::Result<Vec<_>>>()
            .map_err(err)?;
        let schema = Type::group_type_builder("clino")
            .with_fields(fields)
            .build()
            .map_err(err)?;
        // Dictionary encoding only for the text columns (a status takes a
        // handful of values); for measured doubles a dictionary never pays
        // and building it cost more than the rest of the write. Statistics
        // (min/max) only of the time, per column chunk: enough to skip row
        // groups by time; for the other columns they cost 20 instructions a
        // value and serve no query clino knows of.
        let mut props = WriterProperties::builder()
            .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
            .set_dictionary_enabled(false)
            .set_statistics_enabled(EnabledStatistics::None);
        for (n, &t) in names.iter().zip(&text) {
            if t {
                props = props.set_column_dictionary_enabled(ColumnPath::from(*n), true);
            }
            if n.eq_ignore_ascii_case("t_s") {
                props = props
                    .set_column_statistics_enabled(ColumnPath::from(*n), EnabledStatistics::Chunk);
            }
        }
        let props = props.build();
        let writer =
            SerializedFileWriter::new(out, Arc::new(schema), Arc::new(props)).map_err(err)?;
        Ok(Self {
            writer: Some(writer),
            num: text.iter().map(|_| Vec::new()).collect(),
            txt: text.iter().map(|_| Vec::new()).collect(),
            last_txt: text.iter().map(|_| None).collect(),
            text,
            col: 0,
            rows: 0,
        })
    }

    /// Add `value` to the file's key-value metadata as `clino.KEY` (the
    /// Parquet form of a CSV note, [`crate::io::NOTE_PREFIX`]), written with
    /// the footer; readers take the first of a key.
    pub fn note(&mut self, key: &str, value: &str) {
        if let Some(w) = self.writer.as_mut() {
            w.append_key_value_metadata(parquet::file::metadata::KeyValue::new(
                format!("clino.{key}"),
                value.to_string(),
            ));
        }
    }

    /// Append a number to the current row.
    #[inline]
    pub fn f64(&mut self, x: f64) {
        if let Some(v) = self.num.get_mut(self.col) {
            v.push(x);
        }
        self.col += 1;
    }

    /// Append a text cell to the current row.
    #[inline]
    pub fn str(&mut self, s: &str) {
        if let (Some(v), Some(last)) = (self.txt.get_mut(self.col), self.last_txt.get_mut(self.col))
        {
            // a clone shares the bytes: no allocation for a repeated text
            let b = match last {
                // a short text: compared in line (a memcmp call costs more)
                Some(b) if same_text(b.data(), s.as_bytes()) => b.clone(),
                _ => last.insert(ByteArray::from(s)).clone(),
            };
            v.push(b);
        }
        self.col += 1;
    }

    /// End the row (a row group is written when full).
    pub fn end_row(&mut self) -> std::io::Result<()> {
        if self.col != self.text.len() {
            return Err(std::io::Error::other(format!(
                "row has {} cells for {} columns",
                self.col,
                self.text.len()
            )));
        }
        self.col = 0;
        self.rows += 1;
        if self.rows >= ROW_GROUP_ROWS {
            self.write_group()?;
        }
        Ok(())
    }

    fn write_group(&mut self) -> std::io::Result<()> {
        if self.rows == 0 {
            return Ok(());
        }
        let io = |e: parquet::errors::ParquetError| std::io::Error::other(e);
        let w = self
            .writer
            .as_mut()
            .ok_or_else(|| std::io::Error::other("closed"))?;
        let mut rg = w.next_row_group().map_err(io)?;
        let mut k = 0;
        while let Some(mut c) = rg.next_column().map_err(io)? {
            if self.text[k] {
                c.typed::<ByteArrayType>()
                    .write_batch(&self.txt[k], None, None)
                    .map_err(io)?;
                self.txt[k].clear();
            } else {
                c.typed::<DoubleType>()
                    .write_batch(&self.num[k], None, None)
                    .map_err(io)?;
                self.num[k].clear();
            }
            c.close().map_err(io)?;
            k += 1;
        }
        rg.close().map_err(io)?;
        self.rows = 0;
        Ok(())
    }

    /// Write what is buffered as a row group (rows written so far are then in the file).
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.write_group()
    }

    /// Write the last row group and the footer; give back the sink.
    pub fn finish(mut self) -> std::io::Result<W> {
        self.write_group()?;
        let w = self
            .writer
            .take()
            .ok_or_else(|| std::io::Error::other("closed"))?;
        w.into_inner().map_err(std::io::Error::other)
    }
}
