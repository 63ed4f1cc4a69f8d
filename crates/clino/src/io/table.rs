//! The one table reader: every recording clino reads goes through it, CSV
//! or Parquet (chosen by the `.parquet` extension, [`super::parquet`]).
//!
//! The rules, in one place:
//!
//! * a UTF-8 byte-order mark at the start is not part of the first name;
//! * lines starting with `#` are comments, before the header and between rows;
//!   blank lines are skipped; lines end with LF or CRLF;
//! * the first other line is the header; columns are found by name, ASCII
//!   case ignored, surrounding spaces and quotes trimmed; other columns are
//!   ignored (their cells are never parsed, so NaN there is no error);
//! * every data row has as many fields as the header;
//! * a numeric cell is a decimal number, `nan`/`inf` in any case, or empty
//!   (read as NaN); anything else is an error;
//! * every error names the file, the 1-based line (comment lines counted) and
//!   the column.
//!
//! Each row is parsed from one reused [`csv::ByteRecord`]: no allocation per
//! row, memory flat in the length of the file.

use std::io::Read;
use std::path::{Path, PathBuf};

use super::parquet::{Cell, ParquetRows};
use crate::{Error, ErrorKind, Result};

/// Wraps the byte source to drop a leading UTF-8 byte-order mark (so that a
/// `#` right after it still starts a comment) and to know where it ends (for
/// exact line numbers of a last row without a trailing newline).
struct Tracked<R> {
    inner: R,
    total: u64,
    last: u8,
    eof: bool,
    /// bytes read ahead while looking for the mark, not yet handed out
    head: [u8; 3],
    head_len: usize,
    started: bool,
    notes: Notes,
}

/// The prefix of a note a recording carries for its readers, on a comment
/// line of its own: `# clino.NAME TEXT` (a CSV recording of `clino stream`
/// names the sensor's timing so, [`crate::stream::SensorTiming`]).
pub const NOTE_PREFIX: &str = "# clino.";

/// Longest note line kept, bytes (a longer one is an ordinary comment).
const NOTE_MAX_BYTES: usize = 512;

/// The notes seen in the bytes a [`Tracked`] hands out: comment lines that
/// start with [`NOTE_PREFIX`], before the first data row (after at most one
/// line of content, the header) or after it.
#[derive(Clone, Debug, Default)]
struct Notes {
    /// At the start of a line.
    line_start: bool,
    /// The comment line being read, when it may be a note.
    note: Option<Vec<u8>>,
    /// The rest of the line is a comment too long to be a note.
    long: bool,
    /// The current line has content (not a comment, not blank).
    content: bool,
    /// Lines with content seen so far.
    content_lines: u64,
    /// Notes before the first data row, without the leading `# `.
    leading: Vec<String>,
    /// A note came after the first data row.
    late: bool,
}

impl Notes {
    fn scan(&mut self, bytes: &[u8]) {
        for &b in bytes {
            if self.line_start {
                self.line_start = false;
                if b == b'#' {
                    self.note = Some(Vec::new());
                }
            }
            match b {
                b'\n' => {
                    if let Some(line) = self.note.take() {
                        self.finish_note(&line);
                    } else if self.content {
                        self.content_lines += 1;
                    }
                    self.content = false;
                    self.long = false;
                    self.line_start = true;
                }
                _ => match self.note.as_mut() {
                    Some(line) if line.len() < NOTE_MAX_BYTES => line.push(b),
                    Some(_) => {
                        self.note = None;
                        self.long = true;
                    }
                    None => self.content |= !self.long && !b.is_ascii_whitespace(),
                },
            }
        }
    }

    fn finish_note(&mut self, line: &[u8]) {
        let text = String::from_utf8_lossy(line);
        let text = text.trim_end_matches('\r');
        if let Some(rest) = text.strip_prefix(NOTE_PREFIX) {
            if self.content_lines <= 1 {
                if self.leading.len() < 16 {
                    self.leading.push(format!("clino.{rest}"));
                }
            } else {
                self.late = true;
            }
        }
    }
}

impl<R: Read> Tracked<R> {
    fn new(inner: R) -> Self {
        Self {
            inner,
            total: 0,
            last: 0,
            eof: false,
            head: [0; 3],
            head_len: 0,
            started: false,
            notes: Notes {
                line_start: true,
                ..Notes::default()
            },
        }
    }
}

impl<R: Read> Read for Tracked<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if !self.started {
            self.started = true;
            let mut got = 0;
            while got < 3 {
                let n = self.inner.read(&mut self.head[got..])?;
                if n == 0 {
                    break;
                }
                got += n;
            }
            self.head_len = if got == 3 && self.head == [0xEF, 0xBB, 0xBF] {
                0
            } else {
                got
            };
        }
        if self.head_len > 0 && !buf.is_empty() {
            let n = self.head_len.min(buf.len());
            buf[..n].copy_from_slice(&self.head[..n]);
            self.head.copy_within(n..self.head_len, 0);
            self.head_len -= n;
            self.total += n as u64;
            self.last = buf[n - 1];
            self.notes.scan(&buf[..n]);
            return Ok(n);
        }
        let n = self.inner.read(buf)?;
        if n == 0 {
            if !buf.is_empty() {
                self.eof = true;
            }
        } else {
            self.total += n as u64;
            self.last = buf[n - 1];
            self.notes.scan(&buf[..n]);
        }
        Ok(n)
    }
}

/// Streaming reader of a CSV table by header name (the rules are in the
/// module docs of `io::table`, repeated in [`crate::io`]).
///
/// ```
/// use clino::io::TableReader;
/// let text = "\u{feff}# exported\r\nT_S, x\r\n0, 1.5\r\n# pause\r\n1,\r\n";
/// let mut t = TableReader::new(text.as_bytes(), "inline.csv").unwrap();
/// let (ti, xi) = (t.require("t_s").unwrap(), t.require("x").unwrap());
/// assert!(t.next_record().unwrap());
/// assert_eq!((t.line(), t.f64(ti).unwrap(), t.f64(xi).unwrap()), (3, 0.0, 1.5));
/// assert!(t.next_record().unwrap());
/// assert_eq!(t.line(), 5);
/// assert!(t.f64(xi).unwrap().is_nan());
/// assert!(!t.next_record().unwrap());
/// ```
pub struct TableReader<R: Read> {
    rdr: Option<csv::Reader<Tracked<R>>>,
    rec: csv::ByteRecord,
    /// a Parquet file instead of CSV (same names, rules and errors)
    parquet: Option<Box<ParquetRows>>,
    file: PathBuf,
    header: Vec<String>,
    line: u64,
    header_line: u64,
    rows: u64,
    done: bool,
}

impl TableReader<std::fs::File> {
    /// Open a file: Parquet when its name ends in `.parquet`, CSV otherwise
    /// (a directory or a missing file is an error naming it).
    pub fn open(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        if path.is_dir() {
            return Err(
                Error::new(ErrorKind::InvalidInput, "is a directory, not a recording")
                    .in_file(path),
            );
        }
        if super::parquet::is_parquet(path) {
            let rows = ParquetRows::open(path)?;
            let header = rows.names().to_vec();
            return Ok(Self {
                rdr: None,
                rec: csv::ByteRecord::new(),
                parquet: Some(Box::new(rows)),
                file: path.to_path_buf(),
                header,
                line: 1,
                header_line: 1,
                rows: 0,
                done: false,
            });
        }
        let f = std::fs::File::open(path).map_err(|e| Error::from(e).in_file(path))?;
        Self::new(f, path)
    }
}

/// Longest part of a cell quoted in an error message, in characters.
pub const QUOTE_MAX_CHARS: usize = 60;

/// A cell as an error message quotes it: trimmed, lossy UTF-8, in quotes,
/// cut to 60 characters (`QUOTE_MAX_CHARS`) with its length in bytes when longer
/// (a corrupted 5 MB cell must not become a 5 MB message).
pub fn quote_cell(cell: &[u8]) -> String {
    let text = String::from_utf8_lossy(cell.trim_ascii());
    if text.chars().count() <= QUOTE_MAX_CHARS {
        return format!("'{text}'");
    }
    let head: String = text.chars().take(QUOTE_MAX_CHARS).collect();
    format!("'{head}…' ({} bytes)", cell.len())
}

/// Parse one numeric cell: empty → NaN; `None` when it is not a number.
pub(crate) fn parse_f64(cell: &[u8]) -> Option<f64> {
    let cell = cell.trim_ascii();
    if cell.is_empty() {
        return Some(f64::NAN);
    }
    std::str::from_utf8(cell).ok()?.parse::<f64>().ok()
}

impl<R: Read> TableReader<R> {
    /// Read the header from `source`; `name` is the file name used in errors.
    pub fn new(source: R, name: impl Into<PathBuf>) -> Result<Self> {
        let rdr = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .comment(Some(b'#'))
            .terminator(csv::Terminator::Any(b'\n'))
            .buffer_capacity(1 << 16)
            .from_reader(Tracked::new(source));
        let mut me = Self {
            rdr: Some(rdr),
            rec: csv::ByteRecord::with_capacity(256, 32),
            parquet: None,
            file: name.into(),
            header: Vec::new(),
            line: 0,
            header_line: 0,
            rows: 0,
            done: false,
        };
        if !me.read_raw()? {
            return Err(me
                .err(
                    ErrorKind::Empty,
                    "the file is empty: no header line (nor data)",
                )
                .at_line(me.line.max(1)));
        }
        me.header = me
            .rec
            .iter()
            .map(|f| {
                String::from_utf8_lossy(f.trim_ascii())
                    .trim_matches('"')
                    .trim()
                    .to_string()
            })
            .collect();
        me.header_line = me.line;
        if me.header.len() == 1 && me.header[0].contains(';') {
            return Err(me
                .err(
                    ErrorKind::Parse,
                    "the header has one column holding ';': fields must be separated by commas",
                )
                .at_line(me.header_line));
        }
        Ok(me)
    }

    /// The recording's notes for its readers ([`NOTE_PREFIX`]: `clino.NAME
    /// TEXT`, without the `# `) that come before its first data row, and
    /// whether one came after it. Complete once the first data row has been
    /// read. A Parquet file's are its key-value metadata `clino.NAME`.
    pub fn notes(&self) -> (&[String], bool) {
        match (&self.rdr, &self.parquet) {
            (Some(r), _) => (&r.get_ref().notes.leading, r.get_ref().notes.late),
            (None, Some(p)) => (p.notes(), false),
            (None, None) => (&[], false),
        }
    }

    /// The header names, in file order.
    pub fn header(&self) -> &[String] {
        &self.header
    }

    /// 1-based line of the header.
    pub fn header_line(&self) -> u64 {
        self.header_line
    }

    /// 1-based line of the current record.
    pub fn line(&self) -> u64 {
        self.line
    }

    /// The file name used in errors.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// Data records returned so far.
    pub fn rows_read(&self) -> u64 {
        self.rows
    }

    /// Index of the first column named any of `names` (ASCII case ignored).
    pub fn find(&self, names: &[&str]) -> Option<usize> {
        names
            .iter()
            .find_map(|n| self.header.iter().position(|h| h.eq_ignore_ascii_case(n)))
    }

    /// Index of column `name`, or an error naming it and the header.
    pub fn require(&self, name: &str) -> Result<usize> {
        self.find(&[name]).ok_or_else(|| self.missing(name, ""))
    }

    /// The header names for a message: at most 30 names of at most 40
    /// characters each and 200 characters in all (a binary file read as CSV
    /// has a "header" of kilobytes).
    fn header_list(&self) -> String {
        const NAMES: usize = 30;
        const CHARS: usize = 40;
        const TOTAL: usize = 200;
        let mut out = String::new();
        let mut chars = 0;
        for (i, h) in self.header.iter().enumerate() {
            let name: String = h.chars().take(CHARS).collect();
            let cut = name.chars().count() < h.chars().count();
            let n = name.chars().count() + usize::from(cut) + 1;
            if i == NAMES || chars + n > TOTAL {
                out.push_str(&format!(",… ({} names in all)", self.header.len()));
                break;
            }
            if i > 0 {
                out.push(',');
            }
            out.push_str(&name);
            if cut {
                out.push('…');
            }
            chars += n;
        }
        out
    }

    /// The error for a missing column `name`, with a hint.
    pub fn missing(&self, name: &str, hint: &str) -> Error {
        let mut msg = format!("missing column '{name}'");
        if !hint.is_empty() {
            msg.push_str(&format!(" ({hint})"));
        }
        msg.push_str(&format!("; header has: {}", self.header_list()));
        self.err(ErrorKind::MissingColumn, msg)
            .at_line(self.header_line)
            .at_column(name)
    }

    /// An error in this file.
    pub fn err(&self, kind: ErrorKind, msg: impl Into<String>) -> Error {
        Error::new(kind, msg).in_file(&self.file)
    }

    /// An error at the current record and column `i`.
    pub fn err_at(&self, i: usize, kind: ErrorKind, msg: impl Into<String>) -> Error {
        self.err(kind, msg)
            .at_line(self.line)
            .at_column(self.header.get(i).cloned().unwrap_or_default())
    }

    /// Read the next non-blank record into `self.rec`, setting `self.line`.
    fn read_raw(&mut self) -> Result<bool> {
        let Some(rdr) = self.rdr.as_mut() else {
            return Ok(false);
        };
        loop {
            let more = rdr.read_byte_record(&mut self.rec).map_err(|e| {
                let line = e.position().map(|p| p.line()).unwrap_or(self.line + 1);
                let kind = if matches!(e.kind(), csv::ErrorKind::Io(_)) {
                    ErrorKind::Io
                } else {
                    ErrorKind::Parse
                };
                Error::new(kind, e.to_string())
                    .in_file(&self.file)
                    .at_line(line)
            })?;
            let end = rdr.position();
            if !more {
                self.line = end.line();
                return Ok(false);
            }
            // csv counts every '\n' it consumed; the record's own terminator is
            // one of them unless the record ends the file without a newline.
            let src = rdr.get_ref();
            let unterminated = src.eof && end.byte() == src.total && src.last != b'\n';
            self.line = end.line() - u64::from(!unterminated);
            // Blank line ("\n" is skipped by csv itself; "\r\n" or spaces arrive as one empty field).
            let blank = self.rec.len() == 1 && self.rec[0].trim_ascii().is_empty();
            if !blank {
                return Ok(true);
            }
        }
    }

    /// Advance to the next data record; `Ok(false)` at the end. A header with
    /// no data row is an error ([`ErrorKind::Empty`]); so is a row whose
    /// number of fields differs from the header's.
    pub fn next_record(&mut self) -> Result<bool> {
        if self.done {
            return Ok(false);
        }
        if let Some(p) = self.parquet.as_mut() {
            if !p.next()? {
                self.done = true;
                if self.rows == 0 {
                    return Err(self
                        .err(ErrorKind::Empty, "the file has columns but no data rows")
                        .at_line(self.header_line));
                }
                return Ok(false);
            }
            self.rows += 1;
            // the line the row would have as CSV under its header
            self.line = self.rows + 1;
            return Ok(true);
        }
        if !self.read_raw()? {
            self.done = true;
            if self.rows == 0 {
                return Err(self
                    .err(ErrorKind::Empty, "the file has a header but no data rows")
                    .at_line(self.header_line));
            }
            return Ok(false);
        }
        if self.rec.len() != self.header.len() {
            self.done = true;
            let col = self.rec.len().min(self.header.len().saturating_sub(1));
            return Err(self.err_at(
                col,
                ErrorKind::Parse,
                format!(
                    "row has {} fields but the header has {}",
                    self.rec.len(),
                    self.header.len()
                ),
            ));
        }
        self.rows += 1;
        Ok(true)
    }

    /// Cell `i` of the current record as a number (empty → NaN; NaN and inf
    /// pass, see [`TableReader::finite`] for columns that must be finite).
    #[inline]
    pub fn f64(&self, i: usize) -> Result<f64> {
        if let Some(p) = &self.parquet {
            if let Cell::Num(x) = p.cell(i) {
                return Ok(x);
            }
            return self.parquet_text_f64(p, i);
        }
        let raw = self.rec.get(i).unwrap_or(b"");
        parse_f64(raw).ok_or_else(|| {
            self.err_at(
                i,
                ErrorKind::Parse,
                format!("not a number: {}", quote_cell(raw)),
            )
        })
    }

    /// A Parquet cell that is not a number column's: text parsed as CSV is.
    #[cold]
    fn parquet_text_f64(&self, p: &ParquetRows, i: usize) -> Result<f64> {
        match p.cell(i) {
            Cell::Num(x) => Ok(x),
            Cell::Text(t) => parse_f64(t.as_bytes()).ok_or_else(|| {
                self.err_at(
                    i,
                    ErrorKind::Parse,
                    format!("not a number: {}", quote_cell(t.as_bytes())),
                )
            }),
            Cell::Other(what) => {
                Err(self.err_at(i, ErrorKind::Parse, format!("not a number: {what}")))
            }
        }
    }

    /// Cell `i` as a finite number (an empty, NaN or infinite cell is an error).
    pub fn finite(&self, i: usize) -> Result<f64> {
        let x = self.f64(i)?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.err_at(
                i,
                ErrorKind::InvalidInput,
                format!(
                    "value must be a finite number, got {}",
                    quote_cell(self.text(i).as_bytes())
                ),
            ))
        }
    }

    /// Cell `i` as text (trimmed; invalid UTF-8 replaced).
    pub fn text(&self, i: usize) -> String {
        if let Some(p) = &self.parquet {
            return match p.cell(i) {
                Cell::Num(x) if x.is_nan() => String::new(),
                Cell::Num(x) => ryu::Buffer::new().format(x).to_string(),
                Cell::Text(t) => t.to_string(),
                Cell::Other(_) => String::new(),
            };
        }
        String::from_utf8_lossy(self.rec.get(i).unwrap_or(b"").trim_ascii()).into_owned()
    }

    /// Only the columns `cols` will be read from now on: a Parquet file then
    /// decodes only those (a CSV line is split whole either way). Reading
    /// another column afterwards is an error naming it, not a wrong value.
    pub fn project(&mut self, cols: &[usize]) {
        if let Some(p) = self.parquet.as_mut() {
            p.project(cols);
        }
    }

    /// Every cell of the current record as text.
    pub fn texts(&self) -> Vec<String> {
        (0..self.header.len()).map(|i| self.text(i)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A source handing out `chunk` bytes a read.
    struct Trickle<'a>(&'a [u8], usize);
    impl Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = self.1.min(buf.len()).min(self.0.len());
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    /// The notes of `text` once its first data row is read, read `chunk`
    /// bytes at a time; and those after the last row.
    fn notes_of(text: &str, chunk: usize) -> (Vec<String>, bool, bool) {
        let mut t = TableReader::new(Trickle(text.as_bytes(), chunk), "n.csv").unwrap();
        assert!(t.next_record().unwrap());
        let (first, _) = t.notes();
        let first = first.to_vec();
        while t.next_record().unwrap() {}
        let (all, late) = t.notes();
        (first.clone(), late, all == first)
    }

    #[test]
    fn notes_before_the_first_row_are_read_and_later_ones_flagged() {
        let text = "\u{feff}# clino.sensor_timing a=1\r\n# an ordinary comment\n\nt_s,x\n\
                    # clino.other b\n0,1\n# clino.sensor_timing late\n1,2\n";
        for chunk in [1, 2, 7, 1 << 16] {
            let (first, late, kept) = notes_of(text, chunk);
            assert_eq!(
                first,
                vec![
                    "clino.sensor_timing a=1".to_string(),
                    "clino.other b".into()
                ],
                "{chunk}"
            );
            assert!(late, "{chunk}");
            assert!(kept, "a late note is not added: {chunk}");
        }
        // none, and a '#' that is not at the start of its line
        let (first, late, _) = notes_of("t_s,x\n0,1 # clino.x y\n", 3);
        assert!(first.is_empty() && !late);
        // an over-long note line is an ordinary comment, not a note cut short
        let long = format!("# clino.x {}\nt_s\n# clino.y z\n0\n", "y".repeat(600));
        for chunk in [5, 1 << 16] {
            let (first, late, _) = notes_of(&long, chunk);
            assert_eq!(first, vec!["clino.y z".to_string()], "{chunk}");
            assert!(!late);
        }
    }
}
