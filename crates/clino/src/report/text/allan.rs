//! Text of `clino allan`: the IEEE 952 readings and the fitted noise model per axis.

use crate::testbench::allan::{AllanReport, ChannelStatus, Reading};
use std::fmt::Write;

/// An estimate with its interval, `value [lo, hi]`, or `-`.
fn term(r: &Reading) -> String {
    r.estimate.map_or("-".to_string(), |e| {
        format!("{:.3e} [{:.3e}, {:.3e}]", e.value, e.lo, e.hi)
    })
}

/// The readings table, the fitted-model table and the notes (why a reading
/// or a part of the fit is missing), all from `r`.
pub fn allan(r: &AllanReport) -> String {
    let mut s = format!(
        "{} samples at {:.3} Hz ({:.1} s); 99 % intervals [lo, hi]\n",
        r.samples, r.rate_hz, r.duration_s
    );
    let mut notes = Vec::new();
    readings(&mut s, r, &mut notes);
    fitted(&mut s, r, &mut notes);
    if !notes.is_empty() {
        s += "\nnotes:\n";
        for n in notes {
            let _ = writeln!(s, "  {n}");
        }
    }
    s
}

fn readings(s: &mut String, r: &AllanReport, notes: &mut Vec<String>) {
    s.push_str(
        "\nIEEE 952 readings: N from the -1/2 line at 1 s, B = min/0.664, K from the +1/2 line at 3 s\n",
    );
    s.push_str(
        "axis   unit    N (u/sqrt(Hz))                       B (u)                                at tau (s)  K (u/sqrt(s))\n",
    );
    for ax in &r.axes {
        let i = &ax.ieee952;
        let _ = writeln!(
            s,
            "{:<6} {:<7} {:<36} {:<36} {:<11} {}",
            ax.axis,
            ax.unit,
            term(&i.n),
            term(&i.b),
            i.b_tau_s.map_or("-".into(), |t| format!("{t:.3}")),
            term(&i.k)
        );
        if ax.status == ChannelStatus::Ok {
            for (name, t) in [("N", &i.n), ("B", &i.b), ("K", &i.k)] {
                if let Some(why) = &t.reason {
                    notes.push(format!("{} reading {name}: {why}", ax.axis));
                }
            }
        }
    }
}

fn fitted(s: &mut String, r: &AllanReport, notes: &mut Vec<String>) {
    s.push_str(
        "\nfitted model sigma^2 = 3Q^2/tau^2 + N^2/tau + 0.664^2 B^2 + K^2 tau/3 + R^2 tau^2/2\n",
    );
    s.push_str(
        "axis   tau range (s)     N (u/sqrt(Hz))                       B (u)                                K (u/sqrt(s))                        other\n",
    );
    for ax in &r.axes {
        let Some(fit) = &ax.fit else {
            let _ = writeln!(s, "{:<6} -", ax.axis);
            continue;
        };
        let mut other = Vec::new();
        for (name, t) in [("Q", &fit.terms[0]), ("R", &fit.terms[4])] {
            if let Some(e) = t.estimate {
                other.push(format!(
                    "{name} {:.3e} [{:.3e}, {:.3e}]",
                    e.value, e.lo, e.hi
                ));
            }
        }
        if fit.inflation > 1.0 {
            other.push(format!(
                "intervals x{:.2} (model misses the curve)",
                fit.inflation
            ));
        }
        let _ = writeln!(
            s,
            "{:<6} {:<17} {:<36} {:<36} {:<36} {}",
            ax.axis,
            format!("{:.3}-{:.4}", fit.tau_from_s, fit.tau_to_s),
            term(&fit.terms[1]),
            term(&fit.terms[2]),
            term(&fit.terms[3]),
            other.join("; ")
        );
        if let Some(x) = &fit.excluded {
            notes.push(format!("{} fit: excluded {x}", ax.axis));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::ImuModel;
    use crate::testbench::allan::allan_simulated;

    #[test]
    fn tables_carry_the_report_numbers() {
        let m = ImuModel::preset("mpu6050").unwrap();
        let r = allan_simulated(&m, 100.0, 600.0, 1).unwrap();
        let s = allan(&r);
        assert!(
            s.starts_with("60000 samples at 100.000 Hz (600.0 s); 99 % intervals [lo, hi]\n\nIEEE 952 readings"),
            "{s}"
        );
        // one row per axis in each table, in the report's order
        for ax in &r.axes {
            let rows: Vec<&str> = s
                .lines()
                .filter(|l| l.starts_with(&format!("{:<6} ", ax.axis)))
                .collect();
            assert_eq!(rows.len(), 2, "{}: {s}", ax.axis);
            if let Some(n) = ax.ieee952.n.estimate {
                assert!(rows[0].contains(&format!("{:.3e} [{:.3e}, {:.3e}]", n.value, n.lo, n.hi)));
            }
            if let Some(f) = &ax.fit {
                assert!(rows[1].contains(&format!("{:.3}-{:.4}", f.tau_from_s, f.tau_to_s)));
            }
        }
    }
}
