//! Converting recordings between CSV and Parquet.

use std::path::Path;

use super::{AtomicFile, CsvLineWriter, ParquetRowWriter, RowSink, TableReader, is_parquet};
use crate::{Error, Result};

/// Copy the table `input` (CSV or Parquet, by extension) to `output` (CSV or
/// Parquet, by extension), every column as numbers, under the reader's rules
/// (comments dropped but the notes before the first row, which are kept
/// ([`TableReader::notes`]); a non-numeric cell is an error naming its line and
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
    // the notes before the first row (complete once it is read) go before
    // it in a CSV file, into the key-value metadata of a Parquet one
    fn copy<R: std::io::Read, S: RowSink>(
        tb: &mut TableReader<R>,
        out: &mut S,
        text: &[bool],
        notes: &mut dyn FnMut(&[String], &mut S) -> std::io::Result<()>,
    ) -> Result<u64> {
        let mut first = true;
        while tb.next_record()? {
            if std::mem::take(&mut first) {
                let (n, _) = tb.notes();
                notes(n, out).map_err(|e| Error::from(e).in_file(tb.file()))?;
            }
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
        let n = copy(&mut tb, &mut w, &text, &mut |notes, w| {
            for n in notes {
                let n = n.strip_prefix("clino.").unwrap_or(n);
                let (key, value) = n.split_once(' ').unwrap_or((n, ""));
                w.note(key, value);
            }
            Ok(())
        })?;
        w.finish().map_err(io)?;
        n
    } else {
        let mut w = CsvLineWriter::new(&mut file);
        w.header(&refs).map_err(io)?;
        let n = copy(&mut tb, &mut w, &text, &mut |notes, w| {
            notes.iter().try_for_each(|n| w.comment(n))
        })?;
        w.finish().map_err(io)?;
        n
    };
    file.commit()?;
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn notes_before_the_first_row_survive_a_round_trip() {
        let dir = tempfile::Builder::new()
            .prefix("clino-convert-test-")
            .tempdir()
            .unwrap();
        let csv = dir.path().join("a.csv");
        std::fs::write(
            &csv,
            "# an ordinary comment\nt_s,x\n# clino.sensor_timing sensor_delay_periods=0.53,gyro_lag_s=-0.0001\n0,1\n# clino.late y\n1,2\n",
        )
        .unwrap();
        let (pq, back) = (dir.path().join("a.parquet"), dir.path().join("b.csv"));
        assert_eq!(convert(&csv, &pq, &[]).unwrap(), 2);
        assert_eq!(convert(&pq, &back, &[]).unwrap(), 2);
        let want = ["clino.sensor_timing sensor_delay_periods=0.53,gyro_lag_s=-0.0001".to_string()];
        for p in [&pq, &back] {
            let mut t = TableReader::open(p).unwrap();
            assert!(t.next_record().unwrap());
            assert_eq!(t.notes(), (&want[..], false), "{p:?}");
        }
        // the ordinary comment and the late note are dropped
        let text = std::fs::read_to_string(&back).unwrap();
        assert_eq!(
            text.lines().filter(|l| l.starts_with('#')).count(),
            1,
            "{text}"
        );
    }
}
