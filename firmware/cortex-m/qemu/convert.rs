//! Recording CSV → the compact sample file (`clino_fw::samples`), on the host.
//!
//! Shared, as source, by the QEMU crate's `build.rs` (which embeds the result
//! in the firmware) and by `clino-fw-check` (which runs the host pipeline on
//! the very same bytes). Lines starting with `#` are comments; the header
//! names the columns, found by name: `t_s`, `gyr_{x,y,z}_rad_s`,
//! `acc_{x,y,z}_m_s2` (the columns of `clino fuse`); other columns are
//! ignored. Values are parsed with `str::parse::<f64>`, as clino's readers do.

/// The columns read, in record order.
pub const COLUMNS: [&str; 7] = [
    "t_s",
    "gyr_x_rad_s",
    "gyr_y_rad_s",
    "gyr_z_rad_s",
    "acc_x_m_s2",
    "acc_y_m_s2",
    "acc_z_m_s2",
];

/// Convert the CSV text `csv` (named `name` in errors) to a sample file.
pub fn csv_to_samples(name: &str, csv: &str) -> Result<Vec<u8>, String> {
    let mut lines = csv
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.starts_with('#') && !l.trim().is_empty());
    let (_, header) = lines
        .next()
        .ok_or_else(|| format!("{name}: no header line"))?;
    let names: Vec<&str> = header.split(',').map(str::trim).collect();
    let mut idx = [0usize; 7];
    for (k, col) in COLUMNS.iter().enumerate() {
        idx[k] = names
            .iter()
            .position(|n| n == col)
            .ok_or_else(|| format!("{name}: no column `{col}` in the header"))?;
    }
    let mut body = Vec::new();
    let mut n: u32 = 0;
    for (lineno, line) in lines {
        let cells: Vec<&str> = line.split(',').collect();
        for (k, &i) in idx.iter().enumerate() {
            let cell = cells.get(i).ok_or_else(|| {
                format!(
                    "{name}, line {}: no column {} (`{}`)",
                    lineno + 1,
                    i + 1,
                    COLUMNS[k]
                )
            })?;
            let v: f64 = cell.trim().parse().map_err(|_| {
                format!(
                    "{name}, line {}, column {} (`{}`): `{cell}` is not a number",
                    lineno + 1,
                    i + 1,
                    COLUMNS[k]
                )
            })?;
            body.extend_from_slice(&v.to_le_bytes());
        }
        n = n
            .checked_add(1)
            .ok_or_else(|| format!("{name}: more than 2^32 rows"))?;
    }
    let mut out = Vec::with_capacity(8 + body.len());
    out.extend_from_slice(b"CLS1");
    out.extend_from_slice(&n.to_le_bytes());
    out.extend_from_slice(&body);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::csv_to_samples;

    const HEAD: &str = "# comment\nt_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,extra\n";

    #[test]
    fn columns_are_found_by_name_and_stored_in_record_order() {
        let csv = format!("{HEAD}0.5,1,2,3,4,5,6,x\n\n1.0,-1,-2,-3,-4,-5,NaN,y\n");
        let b = csv_to_samples("f.csv", &csv).unwrap();
        assert_eq!(&b[..4], b"CLS1");
        assert_eq!(u32::from_le_bytes([b[4], b[5], b[6], b[7]]), 2);
        let f = |i: usize| f64::from_le_bytes(b[8 + 8 * i..16 + 8 * i].try_into().unwrap());
        // record order: t, gyr x y z, acc x y z
        assert_eq!(
            [f(0), f(1), f(2), f(3), f(4), f(5), f(6)],
            [0.5, 4.0, 5.0, 6.0, 1.0, 2.0, 3.0]
        );
        assert!(f(7 + 3).is_nan()); // a NaN cell stays NaN (the pipeline counts it a dropout)
        assert_eq!(b.len(), 8 + 2 * 56);
    }

    #[test]
    fn bad_input_names_file_line_and_column() {
        let e = csv_to_samples("f.csv", &format!("{HEAD}0.5,1,2,oops,4,5,6,x\n")).unwrap_err();
        assert_eq!(
            e,
            "f.csv, line 3, column 4 (`acc_z_m_s2`): `oops` is not a number"
        );
        let e = csv_to_samples("f.csv", &format!("{HEAD}0.5,1,2\n")).unwrap_err();
        assert_eq!(e, "f.csv, line 3: no column 5 (`gyr_x_rad_s`)");
        let e = csv_to_samples("g.csv", "t_s,gyr_x_rad_s\n").unwrap_err();
        assert_eq!(e, "g.csv: no column `gyr_y_rad_s` in the header");
        assert_eq!(
            csv_to_samples("h.csv", "# only\n").unwrap_err(),
            "h.csv: no header line"
        );
    }
}
