//! The whole `clino allan` analysis of a recording or a simulated sensor at
//! rest: the samples, their rate, every axis analysed, and the warnings a
//! user must see (the reading rules' notes, channels not analysed).

use super::{AxisAllan, CONFIDENCE, ChannelStatus, MIN_SAMPLES, allan_imu};
use crate::Result;
use crate::sim::ImuModel;
use crate::testbench::static_record::StaticRecord;
use serde::Serialize;

/// The Allan analysis of one record (the `--json` output of `clino allan`).
#[derive(Clone, Debug, Serialize)]
pub struct AllanReport {
    /// The file read (`None` for a simulation).
    pub file: Option<String>,
    /// Sample rate, Hz: from the time stamps of a recording (the kept
    /// segment's), or the simulated rate.
    pub rate_hz: f64,
    /// Samples analysed.
    pub samples: usize,
    /// Samples / rate, s.
    pub duration_s: f64,
    /// Confidence of every interval (0.99).
    pub confidence: f64,
    /// How the recording was read: gaps, segments, notes (`None` for a simulation).
    pub record: Option<StaticRecord>,
    /// What a user must know: the reading rules' notes, then every channel
    /// not analysed with its reason (`axis: reason`).
    pub warnings: Vec<String>,
    /// The six axes.
    pub axes: Vec<AxisAllan>,
}

fn report(
    record: Option<StaticRecord>,
    samples: usize,
    rate_hz: f64,
    axes: Vec<AxisAllan>,
) -> AllanReport {
    let mut warnings: Vec<String> = record.iter().flat_map(|r| r.notes.clone()).collect();
    for ax in &axes {
        if ax.status != ChannelStatus::Ok {
            warnings.push(format!(
                "{}: {}",
                ax.axis,
                ax.reason.clone().unwrap_or_default()
            ));
        }
    }
    AllanReport {
        file: record.as_ref().map(|r| r.file.display().to_string()),
        rate_hz,
        samples,
        duration_s: samples as f64 / rate_hz,
        confidence: CONFIDENCE,
        record,
        warnings,
        axes,
    }
}

/// Analyse a static recording read by
/// [`read_static_record`](crate::testbench::static_record::read_static_record)
/// at its own rate (from its time stamps). At least [`MIN_SAMPLES`] samples;
/// errors name the file. The samples are dropped once analysed.
pub fn allan_record(mut record: StaticRecord) -> Result<AllanReport> {
    record.require(MIN_SAMPLES, "an Allan analysis")?;
    let axes =
        allan_imu(&record.samples, record.rate_hz).map_err(|e| e.or_in_file(&record.file))?;
    let (n, rate) = (record.samples.len(), record.rate_hz);
    record.samples = Vec::new();
    Ok(report(Some(record), n, rate, axes))
}

/// Analyse the sensor `model` simulated at rest (level) for `duration_s` at
/// `rate_hz` with noise seed `seed`.
pub fn allan_simulated(
    model: &ImuModel,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
) -> Result<AllanReport> {
    model.validate()?;
    let samples = model.simulate(
        &crate::sim::motion::Static::level(),
        rate_hz,
        duration_s,
        seed,
    );
    let axes = allan_imu(&samples, rate_hz)?;
    Ok(report(None, samples.len(), rate_hz, axes))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simulated_report_counts_and_warns_nothing() {
        let m = ImuModel::preset("mpu6050").unwrap();
        let r = allan_simulated(&m, 100.0, 120.0, 1).unwrap();
        assert_eq!(r.samples, 12_000);
        assert_eq!(r.duration_s, 120.0);
        assert_eq!(r.axes.len(), 6);
        assert!(r.file.is_none() && r.record.is_none());
        let not_ok = r
            .axes
            .iter()
            .filter(|a| a.status != ChannelStatus::Ok)
            .count();
        assert_eq!(r.warnings.len(), not_ok, "{:?}", r.warnings);
    }
}
