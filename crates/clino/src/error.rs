//! One error type for the library: what went wrong, and where (file, line, column).

use std::fmt;
use std::path::PathBuf;

/// What kind of thing went wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// Reading or writing a file failed.
    Io,
    /// A cell or a file could not be parsed.
    Parse,
    /// A required column is missing from the header.
    MissingColumn,
    /// Time stamps go backwards or repeat.
    TimeNotIncreasing,
    /// The input holds no data rows.
    Empty,
    /// A value is outside what the method accepts (NaN where not allowed, bad unit, bad flag).
    InvalidInput,
    /// The data cannot determine what was asked (too few poses, singular geometry…).
    Degenerate,
    /// An iterative solver did not converge.
    NotConverged,
}

/// A library error: kind, message, and where it happened.
#[derive(Clone, Debug, PartialEq)]
pub struct Error {
    /// What went wrong.
    pub kind: ErrorKind,
    /// Human-readable explanation.
    pub message: String,
    /// File concerned, if any.
    pub file: Option<PathBuf>,
    /// 1-based line in that file, if known.
    pub line: Option<u64>,
    /// Column (header name) concerned, if known.
    pub column: Option<String>,
}

/// Result with [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// A new error with no location.
    pub fn new(kind: ErrorKind, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
            file: None,
            line: None,
            column: None,
        }
    }
    /// Attach a file.
    pub fn in_file(mut self, file: impl Into<PathBuf>) -> Self {
        self.file = Some(file.into());
        self
    }
    /// Attach a file unless the error already names one (an error from a
    /// file read inside keeps the name of that file).
    pub fn or_in_file(self, file: impl Into<PathBuf>) -> Self {
        if self.file.is_none() {
            self.in_file(file)
        } else {
            self
        }
    }
    /// Attach a 1-based line number.
    pub fn at_line(mut self, line: u64) -> Self {
        self.line = Some(line);
        self
    }
    /// Attach a column name.
    pub fn at_column(mut self, column: impl Into<String>) -> Self {
        self.column = Some(column.into());
        self
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{}", file.display())?;
            if let Some(line) = self.line {
                write!(f, ":{line}")?;
            }
            write!(f, ": ")?;
        } else if let Some(line) = self.line {
            write!(f, "line {line}: ")?;
        }
        if let Some(col) = &self.column {
            write!(f, "column '{col}': ")?;
        }
        write!(f, "{}", self.message)
    }
}

impl std::error::Error for Error {}

impl From<std::io::Error> for Error {
    fn from(e: std::io::Error) -> Self {
        Error::new(ErrorKind::Io, e.to_string())
    }
}

/// A number for a message: 4 decimals, or 4 significant digits in
/// exponent form when very large or small (never 309 digits of 1e308).
pub(crate) fn short(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-3..1e6).contains(&v.abs()) {
        format!("{v:.3e}")
    } else {
        format!("{}", (v * 1e4).round() / 1e4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn short_numbers_for_messages() {
        assert_eq!(short(1e308), "1.000e308");
        assert_eq!(short(43.54354142694413), "43.5435");
        assert_eq!(short(-0.2), "-0.2");
        assert_eq!(short(0.0), "0");
        assert_eq!(short(f64::NAN), "NaN");
    }

    #[test]
    fn display_names_file_line_column() {
        let e = Error::new(ErrorKind::Parse, "not a number: 'abc'")
            .in_file("rec.csv")
            .at_line(12)
            .at_column("acc_x_m_s2");
        assert_eq!(
            e.to_string(),
            "rec.csv:12: column 'acc_x_m_s2': not a number: 'abc'"
        );
    }
}
