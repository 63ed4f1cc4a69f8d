//! Converting recordings between CSV and Parquet.

use std::path::Path;

use super::{AtomicFile, CsvLineWriter, ParquetRowWriter, RowSink, TableReader, is_parquet};
use crate::{Error, Result};

/// Copy the table `input` (CSV or Parquet, by extension) to `output` (CSV or
/// Parquet, by extension), every column as numbers, under the reader's rules
/// (comments dropped, a non-numeric cell is an error naming its line and
/// column; empty cells become NaN). Columns named in `text_columns` are
/// copied as text. The output appears whole or not at all ([`AtomicFile`]).
/// Returns the number of rows.
pub fn convert(input: &Path, output: &Path, text_columns: &[&str]) -> Result<u64> {
    let mut tb = TableReader::open(input)?;
    let names: Vec<String> = tb.header().to_vec();
    let refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let text: Vec<bool> = names
        .iter()
        .map(|n| text_columns.iter().any(|t| t.eq_ignore_ascii_case(n)))
        .collect();
    let texts: Vec<&str> = refs
        .iter()
        .zip(&text)
        .filter(|(_, t)| **t)
        .map(|(n, _)| *n)
        .collect();
    let mut file = AtomicFile::create(output, &[input])?;
    let io = |e: std::io::Error| Error::from(e).in_file(output);
    fn copy<R: std::io::Read, S: RowSink>(
        tb: &mut TableReader<R>,
        out: &mut S,
        text: &[bool],
    ) -> Result<u64> {
        while tb.next_record()? {
            for (i, t) in text.iter().enumerate() {
                if *t {
                    out.str(&tb.text(i));
                } else {
                    out.f64(tb.f64(i)?);
                }
            }
            out.end_row()
                .map_err(|e| Error::from(e).in_file(tb.file()))?;
        }
        Ok(tb.rows_read())
    }
    let rows = if is_parquet(output) {
        let mut w = ParquetRowWriter::new(&mut file, &refs, &texts)?;
        let n = copy(&mut tb, &mut w, &text)?;
        w.finish().map_err(io)?;
        n
    } else {
        let mut w = CsvLineWriter::new(&mut file);
        w.header(&refs).map_err(io)?;
        let n = copy(&mut tb, &mut w, &text)?;
        w.finish().map_err(io)?;
        n
    };
    file.commit()?;
    Ok(rows)
}
