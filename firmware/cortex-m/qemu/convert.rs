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
