//! Writing numeric CSV rows without allocating per row.

use std::io::{BufWriter, Write};

/// A CSV writer for numeric results: one reused line buffer, floats formatted
/// by `ryu` (shortest representation that reads back to the same `f64`; NaN is
/// written `NaN`), no allocation per row.
///
/// ```
/// use clino::io::CsvLineWriter;
/// let mut out = Vec::new();
/// {
///     let mut w = CsvLineWriter::new(&mut out);
///     w.header(&["t_s", "x"]).unwrap();
///     w.f64(0.5);
///     w.f64(f64::NAN);
///     w.end_row().unwrap();
///     w.finish().unwrap();
/// }
/// assert_eq!(String::from_utf8(out).unwrap(), "t_s,x\n0.5,NaN\n");
/// ```
pub struct CsvLineWriter<W: Write> {
    out: BufWriter<W>,
    line: Vec<u8>,
    fmt: ryu::Buffer,
}

impl<W: Write> CsvLineWriter<W> {
    /// Wrap a byte sink (it is buffered here; pass it unbuffered).
    pub fn new(out: W) -> Self {
        Self {
            out: BufWriter::with_capacity(1 << 16, out),
            line: Vec::with_capacity(256),
            fmt: ryu::Buffer::new(),
        }
    }

    /// Write a header line.
    pub fn header(&mut self, names: &[&str]) -> std::io::Result<()> {
        for n in names {
            self.str(n);
        }
        self.end_row()
    }

    fn sep(&mut self) {
        if !self.line.is_empty() {
            self.line.push(b',');
        }
    }

    /// Append a float cell.
    #[inline]
    pub fn f64(&mut self, x: f64) {
        self.sep();
        if x.is_finite() {
            self.line
                .extend_from_slice(self.fmt.format_finite(x).as_bytes());
        } else {
            self.line.extend_from_slice(self.fmt.format(x).as_bytes());
        }
    }

    /// Append a text cell (written as is: it must not hold commas, quotes or newlines).
    #[inline]
    pub fn str(&mut self, s: &str) {
        self.sep();
        self.line.extend_from_slice(s.as_bytes());
    }

    /// End the row: write it out and start a new one.
    #[inline]
    pub fn end_row(&mut self) -> std::io::Result<()> {
        self.line.push(b'\n');
        self.out.write_all(&self.line)?;
        self.line.clear();
        Ok(())
    }

    /// Write a comment line, `# text` (readers skip it; a newline in `text`
    /// becomes a space). Between rows only: the row being built is kept.
    pub fn comment(&mut self, text: &str) -> std::io::Result<()> {
        let line = text.replace(['\n', '\r'], " ");
        writeln!(self.out, "# {line}")
    }

    /// Flush what has been written so far to the sink.
    pub fn flush(&mut self) -> std::io::Result<()> {
        self.out.flush()
    }

    /// Flush everything and give back the sink.
    pub fn finish(self) -> std::io::Result<W> {
        self.out.into_inner().map_err(|e| e.into_error())
    }
}

/// Where rows of cells go: a CSV file ([`CsvLineWriter`]) or a Parquet file
/// ([`super::ParquetRowWriter`]), through the same calls.
pub trait RowSink {
    /// Append a number to the current row.
    fn f64(&mut self, x: f64);
    /// Append a text cell to the current row.
    fn str(&mut self, s: &str);
    /// End the row.
    fn end_row(&mut self) -> std::io::Result<()>;
    /// Push what has been written so far to the sink.
    fn flush(&mut self) -> std::io::Result<()>;
}

impl<W: Write> RowSink for CsvLineWriter<W> {
    fn f64(&mut self, x: f64) {
        CsvLineWriter::f64(self, x)
    }
    fn str(&mut self, s: &str) {
        CsvLineWriter::str(self, s)
    }
    fn end_row(&mut self) -> std::io::Result<()> {
        CsvLineWriter::end_row(self)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        CsvLineWriter::flush(self)
    }
}

impl<W: Write + Send> RowSink for super::ParquetRowWriter<W> {
    fn f64(&mut self, x: f64) {
        super::ParquetRowWriter::f64(self, x)
    }
    fn str(&mut self, s: &str) {
        super::ParquetRowWriter::str(self, s)
    }
    fn end_row(&mut self) -> std::io::Result<()> {
        super::ParquetRowWriter::end_row(self)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        super::ParquetRowWriter::flush(self)
    }
}
