//! Calibration files (TOML): models with their units, valid temperature range,
//! the convention that fixed unobservable rotations, and parameter uncertainties.
//!
//! ```toml
//! format = "clino-calibration"
//! version = 1
//!
//! [accel]
//! unit = "m/s^2"                 # calibrated output
//! raw_unit = "m/s^2 (raw reading)"
//! valid_temp_c = [25.0, 80.0]
//! method = "mwd30 multi-position fit, 78 poses"
//! convention = "…"
//!
//! [accel.model.mwd]              # or [accel.model.matrix] with bias, matrix
//! tc_c = 30.0
//! scale = [[1.0, 0.0, 0.0, 0.0], …]   # per axis [SF, SFT1, SFT2, SFT3]
//! bias = [[0.0, 0.0, 0.0, 0.0], …]    # per axis [B, BT1, BT2, BT3], m/s^2 (per °C^k)
//! m = [[0.0, 0.0, 0.0], …]            # non-orthogonality
//!
//! [accel.sigma]                  # 1σ of each estimated parameter
//! SF_x = 1.2e-6
//! ```
//!
//! The models are the [`clino_core::sensor`] types themselves (serialised with
//! clino-core's `serde` feature), so the device and the desktop read the same
//! numbers.

use super::recording::{ACC_COLS, GYR_COLS, MAG_COLS, Recording};
use crate::{Error, ErrorKind, Result};
use clino_core::ImuSample;
use clino_core::sensor::{Calibration, TriadCalibration, TriadKind, TriadModel};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// The `format` string every calibration file carries.
pub const FORMAT: &str = "clino-calibration";

/// One triad's entry in a calibration file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TriadEntry {
    /// Unit of the calibrated output (`m/s^2`, `rad/s`, `uT`).
    pub unit: String,
    /// Unit of the raw reading the model expects.
    pub raw_unit: String,
    /// Temperature range the model is valid for, °C.
    pub valid_temp_c: [f64; 2],
    /// How the model was obtained.
    #[serde(default)]
    pub method: String,
    /// The convention that fixed unobservable parameters.
    #[serde(default)]
    pub convention: String,
    /// The model.
    pub model: TriadModel,
    /// 1σ of each estimated parameter, by name.
    #[serde(default)]
    pub sigma: BTreeMap<String, f64>,
}

impl TriadEntry {
    /// The core calibration of this entry.
    pub fn calibration(&self) -> TriadCalibration {
        TriadCalibration {
            model: self.model,
            valid_temp_c: self.valid_temp_c,
        }
    }
}

/// A calibration file: any of the three triads.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CalibrationFile {
    /// Always [`FORMAT`].
    pub format: String,
    /// File format version (1).
    pub version: u32,
    /// Accelerometer triad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accel: Option<TriadEntry>,
    /// Gyro triad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gyro: Option<TriadEntry>,
    /// Magnetometer triad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mag: Option<TriadEntry>,
    /// Apply models outside their valid temperature range (not stored).
    #[serde(skip)]
    pub extrapolate: bool,
}

impl Default for CalibrationFile {
    fn default() -> Self {
        Self {
            format: FORMAT.into(),
            version: 1,
            accel: None,
            gyro: None,
            mag: None,
            extrapolate: false,
        }
    }
}

fn finite_model(m: &TriadModel) -> bool {
    match m {
        TriadModel::Matrix(x) => x
            .bias
            .iter()
            .chain(x.matrix.iter().flatten())
            .all(|v| v.is_finite()),
        TriadModel::Mwd(x) => {
            x.tc_c.is_finite()
                && x.scale
                    .iter()
                    .flatten()
                    .chain(x.bias.iter().flatten())
                    .chain(x.m.iter().flatten())
                    .all(|v| v.is_finite())
                && x.scale.iter().all(|s| s[0] != 0.0)
        }
    }
}

impl CalibrationFile {
    /// Set one triad's entry.
    pub fn set(&mut self, kind: TriadKind, entry: TriadEntry) {
        match kind {
            TriadKind::Accel => self.accel = Some(entry),
            TriadKind::Gyro => self.gyro = Some(entry),
            TriadKind::Mag => self.mag = Some(entry),
        }
    }

    /// One triad's entry.
    pub fn get(&self, kind: TriadKind) -> Option<&TriadEntry> {
        match kind {
            TriadKind::Accel => self.accel.as_ref(),
            TriadKind::Gyro => self.gyro.as_ref(),
            TriadKind::Mag => self.mag.as_ref(),
        }
    }

    /// Parse and check a calibration file's text.
    pub fn from_toml(text: &str) -> Result<Self> {
        let f: CalibrationFile = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() as u64 + 1);
            let err = Error::new(
                ErrorKind::Parse,
                format!("not a calibration file: {}", e.message()),
            );
            match line {
                Some(l) => err.at_line(l),
                None => err,
            }
        })?;
        if f.format != FORMAT {
            return Err(Error::new(
                ErrorKind::Parse,
                format!("format is '{}', expected '{FORMAT}'", f.format),
            ));
        }
        if f.version != 1 {
            return Err(Error::new(
                ErrorKind::Parse,
                format!("unsupported calibration file version {}", f.version),
            ));
        }
        for kind in [TriadKind::Accel, TriadKind::Gyro, TriadKind::Mag] {
            if let Some(e) = f.get(kind) {
                let name = format!("{kind:?}").to_lowercase();
                if e.unit != kind.unit() {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        format!("[{name}] unit is '{}', expected '{}'", e.unit, kind.unit()),
                    ));
                }
                let [a, b] = e.valid_temp_c;
                if !(a.is_finite() && b.is_finite() && a <= b) {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        format!("[{name}] valid_temp_c must be [min, max] with min ≤ max"),
                    ));
                }
                if !finite_model(&e.model) {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        format!("[{name}] model holds a non-finite number or a zero scale factor"),
                    ));
                }
            }
        }
        Ok(f)
    }

    /// Load a calibration file.
    pub fn load(path: impl AsRef<Path>) -> Result<Self> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path)
            .map_err(|e| Error::new(ErrorKind::Io, format!("cannot read: {e}")).in_file(path))?;
        Self::from_toml(&text).map_err(|e| e.in_file(path))
    }

    /// The file's text.
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string_pretty(self)
            .map_err(|e| Error::new(ErrorKind::InvalidInput, format!("cannot serialise: {e}")))
    }

    /// Write the file.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<()> {
        let path = path.as_ref();
        std::fs::write(path, self.to_toml()?)
            .map_err(|e| Error::new(ErrorKind::Io, format!("cannot write: {e}")).in_file(path))
    }

    /// The core calibration (what a device applies).
    pub fn calibration(&self) -> Calibration {
        Calibration {
            accel: self.accel.as_ref().map(TriadEntry::calibration),
            gyro: self.gyro.as_ref().map(TriadEntry::calibration),
            mag: self.mag.as_ref().map(TriadEntry::calibration),
        }
    }

    /// Check that every temperature-dependent model is valid at `temp_c` (unless the file allows extrapolation).
    pub fn check_temp(&self, temp_c: Option<f64>) -> Result<()> {
        for (kind, e) in [
            (TriadKind::Accel, &self.accel),
            (TriadKind::Gyro, &self.gyro),
            (TriadKind::Mag, &self.mag),
        ] {
            let Some(e) = e else { continue };
            let c = e.calibration();
            match temp_c {
                None if c.model.is_temperature_dependent() => {
                    return Err(Error::new(
                        ErrorKind::MissingColumn,
                        format!("the {kind:?} model depends on temperature; the sample has none"),
                    )
                    .at_column("temp_c"));
                }
                Some(t) if !self.extrapolate && !c.is_valid_at(Some(t)) => {
                    return Err(Error::new(
                        ErrorKind::InvalidInput,
                        format!("temperature {t} °C is outside the {kind:?} calibration's valid range {:?} °C (allow extrapolation to apply anyway)", e.valid_temp_c),
                    )
                    .at_column("temp_c"));
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// Calibrate one sample (checks the temperature against each model's range
    /// unless `extrapolate` is set).
    pub fn apply(&self, s: &ImuSample) -> Result<ImuSample> {
        self.check_temp(s.temp_c)?;
        Ok(self.calibration().apply(s))
    }

    /// Calibrate a stream of samples; an error names the 0-based sample index.
    pub fn apply_iter<'a, I>(&'a self, samples: I) -> impl Iterator<Item = Result<ImuSample>> + 'a
    where
        I: IntoIterator<Item = ImuSample> + 'a,
    {
        let cal = self.calibration();
        samples.into_iter().enumerate().map(move |(i, s)| {
            self.check_temp(s.temp_c).map_err(|e| Error {
                message: format!("sample {i}: {}", e.message),
                ..e
            })?;
            Ok(cal.apply(&s))
        })
    }

    /// Calibrate a recording in place (its triad columns); errors name the
    /// file, line and column. A triad in the file whose columns the recording
    /// lacks is an error; a triad in the recording the file does not calibrate
    /// is left as is.
    pub fn apply_recording(&self, rec: &mut Recording) -> Result<()> {
        let need = [
            (TriadKind::Accel, rec.acc.is_some(), ACC_COLS[0]),
            (TriadKind::Gyro, rec.gyr.is_some(), GYR_COLS[0]),
            (TriadKind::Mag, rec.mag.is_some(), MAG_COLS[0]),
        ];
        if need
            .iter()
            .all(|(k, has, _)| !(*has && self.get(*k).is_some()))
        {
            let (_, _, col) = need
                .iter()
                .find(|(k, _, _)| self.get(*k).is_some())
                .copied()
                .unwrap_or(need[0]);
            return Err(rec
                .error(
                    ErrorKind::MissingColumn,
                    "the recording has none of the triads this calibration file calibrates",
                )
                .at_column(col));
        }
        let cal = self.calibration();
        for i in 0..rec.len() {
            let t = rec.temp_c.as_ref().map(|v| v[i]);
            self.check_temp(t).map_err(|e| {
                let e = Error {
                    file: rec.path.clone(),
                    ..e
                };
                e.at_line(rec.line[i])
            })?;
            let s = cal.apply(&rec.sample(i));
            if let Some(v) = rec.acc.as_mut() {
                v[i] = s.acc_m_s2;
            }
            if let Some(v) = rec.gyr.as_mut() {
                v[i] = s.gyr_rad_s;
            }
            if let (Some(v), Some(m)) = (rec.mag.as_mut(), s.mag_ut) {
                v[i] = m;
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clino_core::Vec3;
    use clino_core::sensor::{MatrixModel, MwdModel};

    fn file() -> CalibrationFile {
        let mut md = MwdModel::identity(30.0);
        md.scale[0] = [1.01, 1e-4, -1e-6, 1e-8];
        md.bias[2] = [0.05, 1e-3, 0.0, 0.0];
        md.m[1][0] = 0.002;
        let mut f = CalibrationFile::default();
        f.set(
            TriadKind::Accel,
            TriadEntry {
                unit: "m/s^2".into(),
                raw_unit: "m/s^2 (raw reading)".into(),
                valid_temp_c: [25.0, 80.0],
                method: "test".into(),
                convention: "lower triangular".into(),
                model: TriadModel::Mwd(md),
                sigma: [("SF_x".to_string(), 1e-6)].into_iter().collect(),
            },
        );
        f.set(
            TriadKind::Mag,
            TriadEntry {
                unit: "uT".into(),
                raw_unit: "uT (raw reading)".into(),
                valid_temp_c: [-40.0, 85.0],
                method: String::new(),
                convention: String::new(),
                model: TriadModel::Matrix(MatrixModel {
                    bias: [1.0, 2.0, 3.0],
                    ..MatrixModel::IDENTITY
                }),
                sigma: BTreeMap::new(),
            },
        );
        f
    }

    #[test]
    fn toml_round_trip() {
        let f = file();
        let text = f.to_toml().unwrap();
        assert!(text.contains("valid_temp_c"), "{text}");
        let back = CalibrationFile::from_toml(&text).unwrap();
        assert_eq!(back, f);
    }

    #[test]
    fn bad_files_are_clear_errors() {
        let text = file().to_toml().unwrap();
        let e = CalibrationFile::from_toml(&text.replace("unit = \"m/s^2\"", "unit = \"g\""))
            .unwrap_err();
        assert!(e.message.contains("expected 'm/s^2'"), "{}", e.message);
        let e =
            CalibrationFile::from_toml(&text.replace("clino-calibration", "other")).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Parse);
        let e = CalibrationFile::from_toml(
            "format = \"clino-calibration\"\nversion = 1\n[accel]\nunit = 3\n",
        )
        .unwrap_err();
        assert_eq!(e.line, Some(4), "{e}");
    }

    #[test]
    fn apply_checks_temperature_and_calibrates() {
        let f = file();
        let mut s = ImuSample::new(0.0, Vec3::zeros(), Vec3::new(1.0, 2.0, 9.0));
        s.mag_ut = Some(Vec3::new(11.0, 12.0, 13.0));
        assert_eq!(f.apply(&s).unwrap_err().column.as_deref(), Some("temp_c"));
        s.temp_c = Some(90.0);
        assert!(f.apply(&s).unwrap_err().message.contains("outside"));
        let f2 = CalibrationFile {
            extrapolate: true,
            ..f.clone()
        };
        assert!(f2.apply(&s).is_ok());
        s.temp_c = Some(50.0);
        let out = f.apply(&s).unwrap();
        assert_eq!(out.mag_ut, Some(Vec3::new(10.0, 10.0, 10.0)));
        assert_eq!(
            out.acc_m_s2,
            f.calibration()
                .accel
                .unwrap()
                .model
                .apply(s.acc_m_s2, Some(50.0))
        );
        let v: Vec<_> = f
            .apply_iter(vec![
                s,
                ImuSample {
                    temp_c: Some(10.0),
                    ..s
                },
            ])
            .collect();
        assert!(v[0].is_ok());
        assert!(v[1].as_ref().unwrap_err().message.starts_with("sample 1"));
    }

    #[test]
    fn apply_recording_names_line() {
        let csv = "t_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,temp_c\n0,1,2,9,30\n0.1,1,2,9,95\n";
        let mut rec = Recording::from_reader(csv.as_bytes()).unwrap();
        let e = file().apply_recording(&mut rec).unwrap_err();
        assert_eq!(e.line, Some(3));
        assert_eq!(e.column.as_deref(), Some("temp_c"));
    }
}
