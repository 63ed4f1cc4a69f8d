//! Text of `clino redundancy analyze|simulate|sweep|diagnose`.

use crate::redundancy::analysis::Analysis;
use crate::redundancy::fault_set::FaultSet;
use crate::redundancy::recording::RecordingDiagnosis;
use crate::redundancy::simulate::{SimReport, SweepSummary};
use std::fmt::Write;
use std::path::Path;

/// The counts table of [`Analysis::summary`], then for each size the sets
/// that are restorable but not isolable
/// ([`Analysis::restorable_not_isolable`]).
pub fn analysis(an: &Analysis) -> String {
    let mut s = an.summary();
    for (k, sets) in an.restorable_not_isolable() {
        let _ = writeln!(
            s,
            "size {k}: restorable but not isolable ({}): {}",
            sets.len(),
            sets.join(" ")
        );
    }
    s
}

/// A set label ("239") written as a list ("2,3,9"); a label that is not a
/// set (e.g. "none") as it is.
fn list(l: &str) -> String {
    FaultSet::from_label(l).map_or_else(|_| l.to_string(), |s| s.to_list())
}

fn ms(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |x| format!("{:.1} ms", x * 1e3))
}

fn pct(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |x| format!("{:.3} %", x * 100.0))
}

/// One simulated run: the faults, the diagnosis, the delays, false alarms
/// and the linear-acceleration errors faulty / restored / fault-free.
pub fn simulation(r: &SimReport) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "faults {} ({}, magnitude {}) from {} s",
        list(&r.faults),
        r.fault_kind.name(),
        r.fault_magnitude,
        r.onset_s
    );
    let _ = writeln!(
        s,
        "diagnosed {} (source scheme: {})",
        list(&r.diagnosed),
        list(&r.diagnosed_source)
    );
    let _ = writeln!(
        s,
        "detection delay {}, isolation delay {}",
        ms(r.detection_delay_s),
        ms(r.isolation_delay_s)
    );
    let _ = writeln!(
        s,
        "false alarms {} of {} windows before the fault",
        r.false_alarm_windows, r.pre_onset_windows
    );
    let restored = match &r.restored_with {
        Some(l) if *l == r.faults => "restored".to_string(),
        Some(l) => format!("restored with the wrong chains {}", list(l)),
        None => "not restored".to_string(),
    };
    let _ = writeln!(
        s,
        "linear acceleration max relative error: faulty {}, {restored} {}, fault-free {}",
        pct(Some(r.faulty_linear_acc_max_rel_error)),
        pct(r.restored_linear_acc_max_rel_error),
        pct(Some(r.fault_free_linear_acc_max_rel_error))
    );
    s
}

/// The sweep table: one row per fault kind (rates, delays, agreement, the
/// worst restored set) and the misdiagnosed sets under it.
pub fn sweep(summaries: &[SweepSummary]) -> String {
    let mut out = String::from(
        "kind   runs  detected  false-alarm  delay mean/max (ms)  isolated  source  agree  source-wrong  max restored err (set)\n",
    );
    for s in summaries {
        let _ = writeln!(
            out,
            "{:<6} {:>4}  {:>7.1}%  {:>10.2e}  {:>8.1} / {:<8.1}  {:>8}  {:>6}  {:>5}  {:>12}  {:>8.3} % ({})",
            s.fault_kind.name(),
            s.runs,
            100.0 * s.detection_rate,
            s.false_alarm_rate,
            1e3 * s.mean_detection_delay_s,
            1e3 * s.max_detection_delay_s,
            s.isolated,
            s.isolated_source,
            s.agree,
            s.source_wrong_set,
            100.0 * s.max_restored_linear_acc_rel_error,
            s.worst_restored_set
        );
        if !s.misdiagnosed.is_empty() {
            let _ = writeln!(out, "       misdiagnosed: {}", s.misdiagnosed.join(" "));
        }
    }
    out
}

/// The diagnosis of the recording `file`: its size, the first alarm, the
/// segments and the columns it did not use.
pub fn diagnosis(file: &Path, d: &RecordingDiagnosis, ignored_columns: &[String]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{}: {} samples, step {:.6} s, {} decisions",
        file.display(),
        d.samples,
        d.step_s,
        d.windows
    );
    match d.first_alarm_s {
        None => s.push_str("no fault detected\n"),
        Some(t) => {
            let _ = writeln!(
                s,
                "first alarm at {t:.4} s; diagnosed {} (source scheme: {})",
                d.diagnosed, d.diagnosed_source
            );
        }
    }
    for g in &d.segments {
        let _ = writeln!(
            s,
            "  {:>9.4} – {:>9.4} s  general {:<12} source {}",
            g.from_s, g.to_s, g.general, g.source
        );
    }
    if !ignored_columns.is_empty() {
        let _ = writeln!(s, "ignored columns: {}", ignored_columns.join(", "));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::redundancy::analysis::analyze;
    use crate::redundancy::diagnose::{DiagnosisConfig, NoiseModel};
    use crate::redundancy::model::SixAxisAccelerometer;
    use crate::redundancy::simulate::{FaultKind, SimConfig, Simulator};

    #[test]
    fn analysis_lists_the_quadruples_restorable_but_not_isolable() {
        let an = analyze(&SixAxisAccelerometer::reference(), 4);
        let s = analysis(&an);
        // 126 restorable quadruples, 96 isolable: 30 restorable only
        assert!(
            s.contains("size 4: restorable but not isolable (30): "),
            "{s}"
        );
        assert!(!s.contains("size 3: restorable but not isolable"), "{s}");
        let line = s.lines().last().unwrap();
        assert_eq!(line.split(": ").nth(2).unwrap().split(' ').count(), 30);
        assert!(s.starts_with("size  restorable  isolable"), "{s}");
    }

    #[test]
    fn simulation_text_comes_from_the_report() {
        let sim =
            Simulator::new(&SixAxisAccelerometer::reference(), &SimConfig::default()).unwrap();
        let r = sim
            .run(FaultSet::from_label("239").unwrap(), FaultKind::Bias, 7)
            .unwrap()
            .report;
        let s = simulation(&r);
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines.len(), 5, "{s}");
        assert_eq!(
            lines[0],
            format!(
                "faults 2,3,9 (bias, magnitude {}) from {} s",
                r.fault_magnitude, r.onset_s
            )
        );
        assert!(
            lines[1].starts_with("diagnosed 2,3,9 (source scheme: "),
            "{s}"
        );
        assert!(lines[2].starts_with(&format!(
            "detection delay {:.1} ms",
            r.detection_delay_s.unwrap() * 1e3
        )));
        assert!(lines[4].contains(&format!(
            "faulty {:.3} %, restored {:.3} %",
            100.0 * r.faulty_linear_acc_max_rel_error,
            100.0 * r.restored_linear_acc_max_rel_error.unwrap()
        )));
    }

    #[test]
    fn diagnosis_without_an_alarm() {
        let d = RecordingDiagnosis {
            samples: 100,
            step_s: 0.001,
            windows: 1,
            first_alarm_s: None,
            restore_from_s: None,
            diagnosed: "none".into(),
            diagnosed_source: "none".into(),
            segments: vec![],
            config: DiagnosisConfig::default(),
            noise: NoiseModel {
                force_sigma_n: 2e-4,
                gyro_sigma_rad_s: 2e-3,
            },
        };
        let s = diagnosis(Path::new("r.csv"), &d, &["temp_c".into()]);
        assert_eq!(
            s,
            "r.csv: 100 samples, step 0.001000 s, 1 decisions\nno fault detected\nignored columns: temp_c\n"
        );
    }
}
