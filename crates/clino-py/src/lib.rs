//! `clino._clino`: the native layer of the Python package.
//!
//! A thin layer over the `clino` library: every function parses its
//! arguments, calls one library function and converts the result. Arrays
//! come in as NumPy views (read in place when C- or Fortran-contiguous);
//! long work runs with the GIL released; library errors become
//! `clino.ClinoError` carrying the library's message, file, line and column.
//! Results that the CLI prints as JSON (`--json`) cross as the same JSON
//! text, so the Python side sees exactly the CLI's numbers.

use std::io::Read;
use std::path::PathBuf;

use clino::batch::{self, ImuArrays, OutputColumns, Strided};
use clino::calib::{self, CalibOptions, CalibrationFile, Method, Recording, StaticOptions};
use clino::core::{Attitude, ImuSample, Vec3};
use clino::eval::{self, Rms};
use clino::fusion::{
    FilterConfig, FilterSpec, FuseOptions, Pipeline, SensorRange, Status, apply_params, parse_spec,
    parse_spec_list,
};
use clino::io::{
    AtomicFile, CsvLineWriter, ImuCsvReader, ParquetRowWriter, ReadOptions, RowSink, TableReader,
};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2,
    PyReadwriteArray1, PyReadwriteArray2, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyList, PyString};

pyo3::create_exception!(
    _clino,
    ClinoError,
    pyo3::exceptions::PyValueError,
    "An error of the clino library: `str(e)` is the CLI's message; `kind`, `file`, `line` (1-based) and `column` say what and where."
);

/// The library error as a `ClinoError` with its attributes.
fn to_py(py: Python<'_>, e: clino::Error) -> PyErr {
    let err = ClinoError::new_err(e.to_string());
    let v = err.value(py);
    let _ = v.setattr("kind", format!("{:?}", e.kind));
    let _ = v.setattr("message", e.message.clone());
    let _ = v.setattr("file", e.file.as_ref().map(|p| p.display().to_string()));
    let _ = v.setattr("line", e.line);
    let _ = v.setattr("column", e.column.clone());
    err
}

trait OrPy<T> {
    fn py(self, py: Python<'_>) -> PyResult<T>;
}
impl<T> OrPy<T> for clino::Result<T> {
    fn py(self, py: Python<'_>) -> PyResult<T> {
        self.map_err(|e| to_py(py, e))
    }
}

fn json_err(e: serde_json::Error) -> PyErr {
    PyValueError::new_err(format!("JSON: {e}"))
}

fn json<T: serde::Serialize>(v: &T) -> PyResult<String> {
    serde_json::to_string(v).map_err(json_err)
}

/// A `(N, 3)` float64 array where it lies (C or Fortran order).
fn strided<'a>(a: &'a PyReadonlyArray2<'_, f64>, name: &str) -> PyResult<Strided<'a>> {
    let sh = a.shape();
    if sh[1] != 3 {
        return Err(PyValueError::new_err(format!(
            "{name} must have shape (N, 3), got ({}, {})",
            sh[0], sh[1]
        )));
    }
    let n = sh[0];
    let c = a.is_c_contiguous();
    let s = a
        .as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name} must be C- or Fortran-contiguous")))?;
    Ok(if c || n <= 1 {
        Strided::rows(s, n)
    } else {
        Strided::columns(s, n)
    })
}

fn slice<'a>(a: &'a PyReadonlyArray1<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name} must be contiguous")))
}

/// The sensor's full-scale ranges from the Python arguments (`gyro_range`
/// °/s, `acc_range` g; None: not known), as `--gyro-range` and `--acc-range`.
fn sensor_range(gyro_range: Option<f64>, acc_range: Option<f64>) -> PyResult<SensorRange> {
    let check = |v: Option<f64>, name: &str, unit: &str| match v {
        None => Ok(f64::INFINITY),
        Some(x) if x.is_finite() && x > 0.0 => Ok(x),
        Some(x) => Err(PyValueError::new_err(format!(
            "{name} must be a positive, finite full-scale range ({unit}), got {x}"
        ))),
    };
    Ok(SensorRange::from_full_scale(
        check(acc_range, "acc_range", "g")?,
        check(gyro_range, "gyro_range", "°/s")?,
    ))
}

/// Whether each step's time comes from the sensor's sample clock recovered
/// from the stamps (`stamps="recover"`) or from the stamps as they are
/// (`"as-given"`), as `--stamps`.
fn sample_clock(stamps: &str) -> PyResult<bool> {
    match stamps {
        "recover" => Ok(true),
        "as-given" => Ok(false),
        s => Err(PyValueError::new_err(format!(
            "stamps must be 'recover' or 'as-given', got '{s}'"
        ))),
    }
}

/// The filter configuration from the Python arguments, by the CLI's parsers.
fn config(
    filter: &str,
    params: &[(String, String)],
    lever_arm: Option<[f64; 3]>,
    range: SensorRange,
    offline: bool,
    recover: bool,
) -> clino::Result<FilterConfig> {
    let mut spec = [parse_spec(filter)?];
    let p: Vec<(&str, String)> = params
        .iter()
        .map(|(k, v)| (k.as_str(), v.clone()))
        .collect();
    apply_params(&mut spec, &p)?;
    let c = FilterConfig::from_spec(spec[0])
        .with_lever_arm(lever_arm.map(Vec3::from))
        .with_sensor_range(range)
        .with_offline(offline)
        .with_sample_clock(recover)
        .with_timing_given(names_timing(filter, params));
    c.validate()?;
    Ok(c)
}

/// True when the filter's text or its keyword parameters name the dynamic
/// filter's timing: a recording's own note of it is then not taken
/// ([`clino::fusion::names_timing`]).
fn names_timing(filter: &str, params: &[(String, String)]) -> bool {
    clino::fusion::names_timing(filter)
        || params
            .iter()
            .any(|(k, v)| clino::fusion::names_timing(&format!("{k}={v}")))
}

fn read_options(
    gyro_unit: &str,
    accel_unit: &str,
    rate: Option<f64>,
    g: f64,
) -> clino::Result<ReadOptions> {
    Ok(ReadOptions {
        gyro_unit: gyro_unit.parse()?,
        accel_unit: accel_unit.parse()?,
        rate_hz: rate,
        g,
        imu_only: false,
    })
}

type Fused<'py> = (
    Bound<'py, PyArray2<f64>>,
    Option<Bound<'py, PyArray2<f64>>>,
    Bound<'py, PyArray1<u8>>,
);

/// [`Fused`] and the counts JSON.
type FusedWithCounts<'py> = (
    Bound<'py, PyArray2<f64>>,
    Option<Bound<'py, PyArray2<f64>>>,
    Bound<'py, PyArray1<u8>>,
    String,
);

/// One sample's outputs: quaternion and tilt (None before initialisation), status code.
type OneSample = (Option<[f64; 4]>, Option<[f64; 3]>, u8);

/// The output arrays of `n` rows, allocated once (zeroed: `calloc`, pages
/// touched only when written): quaternions (N, 4), tilt in degrees (N, 3,
/// when `tilt`) and status codes (N,).
fn new_outputs<'py>(py: Python<'py>, n: usize, tilt: bool) -> Fused<'py> {
    (
        PyArray2::zeros(py, [n, 4], false),
        tilt.then(|| PyArray2::zeros(py, [n, 3], false)),
        PyArray1::zeros(py, n, false),
    )
}

/// Write access to the output arrays of [`new_outputs`] (C-contiguous, owned
/// by nobody else yet) as the library's [`OutputColumns`].
struct OutBuffers<'py> {
    q: PyReadwriteArray2<'py, f64>,
    d: Option<PyReadwriteArray2<'py, f64>>,
    st: PyReadwriteArray1<'py, u8>,
}

impl<'py> OutBuffers<'py> {
    fn new(o: &Fused<'py>) -> Self {
        Self {
            q: o.0.readwrite(),
            d: o.1.as_ref().map(|d| d.readwrite()),
            st: o.2.readwrite(),
        }
    }

    fn columns(&mut self) -> PyResult<OutputColumns<'_>> {
        Ok(OutputColumns {
            quat: self.q.as_slice_mut()?.as_chunks_mut::<4>().0,
            tilt_deg: match self.d.as_mut() {
                Some(d) => Some(d.as_slice_mut()?.as_chunks_mut::<3>().0),
                None => None,
            },
            status: Some(self.st.as_slice_mut()?),
        })
    }
}

/// Fuse arrays (see `clino.fuse`): returns (quat (N,4), tilt_deg (N,3) or
/// None, status codes (N,), counts JSON). The inputs are read in place; the
/// outputs are allocated once and the library writes every row into them
/// with the GIL released.
#[pyfunction]
#[pyo3(signature = (gyr, acc, t=None, rate=None, filter="dynamic", lever_arm=None, calibration=None, offline=false, params=Vec::new(), temp_c=None, tilt=true, gyro_range=None, acc_range=None, stamps="recover"))]
#[allow(clippy::too_many_arguments)]
fn fuse<'py>(
    py: Python<'py>,
    gyr: PyReadonlyArray2<'py, f64>,
    acc: PyReadonlyArray2<'py, f64>,
    t: Option<PyReadonlyArray1<'py, f64>>,
    rate: Option<f64>,
    filter: &str,
    lever_arm: Option<[f64; 3]>,
    calibration: Option<PyRef<'py, PyCalibration>>,
    offline: bool,
    params: Vec<(String, String)>,
    temp_c: Option<PyReadonlyArray1<'py, f64>>,
    tilt: bool,
    gyro_range: Option<f64>,
    acc_range: Option<f64>,
    stamps: &str,
) -> PyResult<FusedWithCounts<'py>> {
    let range = sensor_range(gyro_range, acc_range)?;
    let recover = sample_clock(stamps)?;
    let cfg = config(filter, &params, lever_arm, range, offline, recover).py(py)?;
    let g = strided(&gyr, "gyr")?;
    let a = strided(&acc, "acc")?;
    let ts = t.as_ref().map(|x| slice(x, "t")).transpose()?;
    let tc = temp_c.as_ref().map(|x| slice(x, "temp_c")).transpose()?;
    let mut arrays = ImuArrays::new(ts, rate, g, a);
    arrays.temp_c = tc;
    let cal = calibration.as_ref().map(|c| &c.file);
    let out = new_outputs(py, arrays.len(), tilt);
    let rep = {
        let mut bufs = OutBuffers::new(&out);
        let mut cols = bufs.columns()?;
        py.detach(|| batch::fuse_arrays_into(&arrays, &cfg, cal, &mut cols))
            .py(py)?
    };
    let (q, d, st) = out;
    Ok((q, d, st, json(&rep)?))
}

/// A pipeline with per-sample `update` and batch `update_batch` (see `clino.Filter`).
#[pyclass(module = "clino._clino", name = "Pipeline")]
struct PyPipeline {
    pipeline: Pipeline,
    config: FilterConfig,
    rate: Option<f64>,
    rows: u64,
    last_t: Option<f64>,
}

impl PyPipeline {
    /// The rows of `g`, `a` (and `t`, `tc`) through the pipeline, each
    /// row's outputs into `out`; with the GIL released when `detach`.
    #[allow(clippy::too_many_arguments)]
    fn run(
        &mut self,
        py: Python<'_>,
        g: Strided<'_>,
        a: Strided<'_>,
        t: Option<&[f64]>,
        tc: Option<&[f64]>,
        out: &mut OutputColumns,
        detach: bool,
    ) -> PyResult<()> {
        let mut arrays = ImuArrays::new(t, if t.is_some() { None } else { self.rate }, g, a);
        arrays.temp_c = tc;
        arrays.first_row = self.rows;
        arrays.prev_t_s = self.last_t;
        let p = &mut self.pipeline;
        if detach {
            py.detach(|| batch::run_arrays_into(p, &arrays, out))
        } else {
            batch::run_arrays_into(p, &arrays, out)
        }
        .py(py)?;
        let n = arrays.len();
        if n > 0 {
            self.last_t = Some(arrays.time(n - 1));
        }
        self.rows += n as u64;
        Ok(())
    }
}

#[pymethods]
impl PyPipeline {
    #[new]
    #[pyo3(signature = (filter="dynamic", rate=None, lever_arm=None, calibration=None, params=Vec::new(), gyro_range=None, acc_range=None, stamps="recover"))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        filter: &str,
        rate: Option<f64>,
        lever_arm: Option<[f64; 3]>,
        calibration: Option<PyRef<'_, PyCalibration>>,
        params: Vec<(String, String)>,
        gyro_range: Option<f64>,
        acc_range: Option<f64>,
        stamps: &str,
    ) -> PyResult<Self> {
        let range = sensor_range(gyro_range, acc_range)?;
        let recover = sample_clock(stamps)?;
        let cfg = config(filter, &params, lever_arm, range, false, recover).py(py)?;
        let pipeline = cfg
            .pipeline()
            .py(py)?
            .with_calibration(calibration.map(|c| c.file.calibration()));
        Ok(Self {
            pipeline,
            config: cfg,
            rate,
            rows: 0,
            last_t: None,
        })
    }

    /// One sample: (quat or None, tilt_deg or None, status code).
    #[pyo3(signature = (gyr, acc, t=None, temp_c=None))]
    fn update(
        &mut self,
        py: Python<'_>,
        gyr: [f64; 3],
        acc: [f64; 3],
        t: Option<f64>,
        temp_c: Option<f64>,
    ) -> PyResult<OneSample> {
        let tt = t.map(|x| [x]);
        let tc = temp_c.map(|x| [x]);
        let (mut q, mut d, mut st) = ([[0.0; 4]], [[0.0; 3]], [0u8]);
        let mut out = OutputColumns {
            quat: &mut q,
            tilt_deg: Some(&mut d),
            status: Some(&mut st),
        };
        // one sample: not worth releasing and taking the GIL again
        self.run(
            py,
            Strided::rows(&gyr, 1),
            Strided::rows(&acc, 1),
            tt.as_ref().map(|x| &x[..]),
            tc.as_ref().map(|x| &x[..]),
            &mut out,
            false,
        )?;
        let q = q[0][0].is_finite().then_some(q[0]);
        let d = q.map(|_| d[0]);
        Ok((q, d, st[0]))
    }

    /// A batch of samples: (quat (N,4), tilt_deg (N,3) or None, status (N,)),
    /// written straight into the arrays with the GIL released.
    #[pyo3(signature = (gyr, acc, t=None, temp_c=None, tilt=true))]
    fn update_batch<'py>(
        &mut self,
        py: Python<'py>,
        gyr: PyReadonlyArray2<'py, f64>,
        acc: PyReadonlyArray2<'py, f64>,
        t: Option<PyReadonlyArray1<'py, f64>>,
        temp_c: Option<PyReadonlyArray1<'py, f64>>,
        tilt: bool,
    ) -> PyResult<Fused<'py>> {
        let g = strided(&gyr, "gyr")?;
        let a = strided(&acc, "acc")?;
        let ts = t.as_ref().map(|x| slice(x, "t")).transpose()?;
        let tc = temp_c.as_ref().map(|x| slice(x, "temp_c")).transpose()?;
        let out = new_outputs(py, g.len(), tilt);
        {
            let mut bufs = OutBuffers::new(&out);
            self.run(py, g, a, ts, tc, &mut bufs.columns()?, true)?;
        }
        Ok(out)
    }

    /// Back to the state before the first sample.
    fn reset(&mut self) {
        self.pipeline.reset();
        self.rows = 0;
        self.last_t = None;
    }

    /// The current attitude (w, x, y, z) or None before initialisation.
    fn attitude(&self) -> Option<[f64; 4]> {
        self.pipeline.attitude().map(|a| [a.w, a.i, a.j, a.k])
    }

    /// Counts of what the pipeline did, JSON.
    fn counts(&self) -> PyResult<String> {
        json(self.pipeline.counts())
    }

    /// The configuration label (`clino eval`'s column name).
    fn label(&self) -> String {
        self.config.label()
    }

    /// Samples seen.
    #[getter]
    fn rows(&self) -> u64 {
        self.rows
    }
}

/// Status names, in the order of the codes.
#[pyfunction]
fn status_names() -> Vec<&'static str> {
    Status::ALL.iter().map(|s| s.as_str()).collect()
}

/// Every filter and parameter with its unit, default and meaning.
#[pyfunction]
fn filter_help() -> String {
    clino::fusion::filter_help()
}

/// The parsed specification, in its canonical text form.
#[pyfunction]
fn spec_text(py: Python<'_>, filter: &str, params: Vec<(String, String)>) -> PyResult<String> {
    let c = config(filter, &params, None, SensorRange::default(), false, true).py(py)?;
    Ok(c.label())
}

/// `clino eval` (JSON of the table, as `clino eval --json` prints it).
#[pyfunction]
#[pyo3(signature = (paths, filter="all", params=Vec::new(), lever_arm=None, offline=false, jobs=None, gyro_unit="rad/s", accel_unit="m/s2", rate=None, g=clino::core::G0, gyro_range=None, acc_range=None, stamps="recover"))]
#[allow(clippy::too_many_arguments)]
fn evaluate(
    py: Python<'_>,
    paths: Vec<PathBuf>,
    filter: &str,
    params: Vec<(String, String)>,
    lever_arm: Option<[f64; 3]>,
    offline: bool,
    jobs: Option<usize>,
    gyro_unit: &str,
    accel_unit: &str,
    rate: Option<f64>,
    g: f64,
    gyro_range: Option<f64>,
    acc_range: Option<f64>,
    stamps: &str,
) -> PyResult<String> {
    let range = sensor_range(gyro_range, acc_range)?;
    let recover = sample_clock(stamps)?;
    let opts = read_options(gyro_unit, accel_unit, rate, g).py(py)?;
    let res = py.detach(|| -> clino::Result<_> {
        let mut specs: Vec<FilterSpec> = parse_spec_list(filter)?;
        let p: Vec<(&str, String)> = params
            .iter()
            .map(|(k, v)| (k.as_str(), v.clone()))
            .collect();
        apply_params(&mut specs, &p)?;
        let configs: Vec<FilterConfig> =
            eval::eval_configs(&specs, lever_arm.map(Vec3::from), offline)?
                .into_iter()
                .map(|c| {
                    c.with_sensor_range(range)
                        .with_sample_clock(recover)
                        .with_timing_given(names_timing(filter, &params))
                })
                .collect();
        eval::evaluate(&paths, &configs, &opts, jobs, |_, _, _| {})
    });
    json(&res.py(py)?)
}

fn attitude_rows(q: &[f64], n: usize, normalise: bool) -> Vec<Option<Attitude>> {
    (0..n)
        .map(|k| {
            let v = nalgebra::Quaternion::new(q[4 * k], q[4 * k + 1], q[4 * k + 2], q[4 * k + 3]);
            if normalise {
                let m = v.norm();
                (m.is_finite() && m > 0.0).then(|| Attitude::new_unchecked(v / m))
            } else {
                let all_nan = [v.w, v.i, v.j, v.k].iter().all(|x| x.is_nan());
                (!all_nan).then(|| Attitude::new_unchecked(v))
            }
        })
        .collect()
}

fn quat_slice<'a>(a: &'a PyReadonlyArray2<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    if a.shape()[1] != 4 || !a.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{name} must be a C-contiguous (N, 4) array of w, x, y, z"
        )));
    }
    a.as_slice()
        .map_err(|_| PyValueError::new_err(format!("{name} must be contiguous")))
}

/// BROAD scoring of estimates against a reference: (rmse_deg, scored, non_finite).
#[pyfunction]
fn score(
    py: Python<'_>,
    estimate: PyReadonlyArray2<'_, f64>,
    reference: PyReadonlyArray2<'_, f64>,
    movement: PyReadonlyArray1<'_, f64>,
) -> PyResult<(f64, u64, u64)> {
    let e = quat_slice(&estimate, "estimate")?;
    let r = quat_slice(&reference, "reference")?;
    let m = slice(&movement, "movement")?;
    let n = m.len();
    if e.len() != 4 * n || r.len() != 4 * n {
        return Err(PyValueError::new_err(
            "estimate, reference and movement differ in length",
        ));
    }
    Ok(py.detach(|| {
        let est = attitude_rows(e, n, false);
        let refs = attitude_rows(r, n, true);
        let mut acc = Rms::default();
        for k in 0..n {
            let mv = m[k].is_finite().then(|| m[k] != 0.0);
            eval::score_sample(&mut acc, est[k], refs[k], mv);
        }
        (acc.value().to_degrees(), acc.count(), acc.non_finite())
    }))
}

/// Inclination error per row, rad (BROAD): NaN where either is not finite.
#[pyfunction]
fn inclination_error<'py>(
    py: Python<'py>,
    estimate: PyReadonlyArray2<'py, f64>,
    reference: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let e = quat_slice(&estimate, "estimate")?;
    let r = quat_slice(&reference, "reference")?;
    if e.len() != r.len() {
        return Err(PyValueError::new_err(
            "estimate and reference differ in length",
        ));
    }
    let n = e.len() / 4;
    let v = py.detach(|| {
        let est = attitude_rows(e, n, false);
        let refs = attitude_rows(r, n, true);
        est.iter()
            .zip(&refs)
            .map(|(a, b)| match (a, b) {
                (Some(a), Some(b)) => eval::inclination_error(a, b),
                _ => f64::NAN,
            })
            .collect::<Vec<f64>>()
    });
    Ok(v.into_pyarray(py))
}

/// Columns of an IMU recording read by the one reader (names → flat arrays, row count).
type Columns = Vec<(String, Vec<f64>, usize)>;

/// Read an IMU recording (CSV or Parquet) with the CLI's reader.
#[pyfunction]
#[pyo3(signature = (path, gyro_unit="rad/s", accel_unit="m/s2", rate=None, g=clino::core::G0))]
fn read_imu(
    py: Python<'_>,
    path: PathBuf,
    gyro_unit: &str,
    accel_unit: &str,
    rate: Option<f64>,
    g: f64,
) -> PyResult<Vec<(String, Py<PyAny>)>> {
    let opts = read_options(gyro_unit, accel_unit, rate, g).py(py)?;
    let res = py.detach(
        || -> clino::Result<(Columns, Option<clino::stream::SensorTiming>)> {
            let mut r = ImuCsvReader::from_path(&path, &opts)?;
            let (has_ref, has_mv) = (r.has_reference(), r.has_movement());
            let (mut t, mut gy, mut ac, mut mag, mut temp, mut rq, mut mv, mut line) = (
                vec![],
                vec![],
                vec![],
                vec![],
                vec![],
                vec![],
                vec![],
                vec![],
            );
            let (mut has_mag, mut has_temp) = (false, false);
            while let Some(row) = r.next_row()? {
                let s = &row.sample;
                t.push(s.t_s);
                gy.extend(s.gyr_rad_s.iter());
                ac.extend(s.acc_m_s2.iter());
                if let Some(m) = s.mag_ut {
                    has_mag = true;
                    mag.extend(m.iter());
                }
                if let Some(x) = s.temp_c {
                    has_temp = true;
                    temp.push(x);
                }
                if has_ref {
                    match row.ref_q {
                        Some(q) => rq.extend([q.w, q.i, q.j, q.k]),
                        None => rq.extend([f64::NAN; 4]),
                    }
                }
                if has_mv {
                    mv.push(row.movement.map_or(f64::NAN, |b| if b { 1.0 } else { 0.0 }));
                }
                line.push(row.line as f64);
            }
            let n = t.len();
            let mut cols = vec![
                ("t_s".to_string(), t, 1),
                ("gyr_rad_s".to_string(), gy, 3),
                ("acc_m_s2".to_string(), ac, 3),
            ];
            if has_mag {
                cols.push(("mag_ut".into(), mag, 3));
            }
            if has_temp {
                cols.push(("temp_c".into(), temp, 1));
            }
            if has_ref {
                cols.push(("ref_q".into(), rq, 4));
            }
            if has_mv {
                cols.push(("movement".into(), mv, 1));
            }
            cols.push(("line".into(), line, 1));
            let _ = n;
            Ok((cols, clino::stream::SensorTiming::from_notes(r.notes().0)))
        },
    );
    let (cols, timing) = res.py(py)?;
    let mut out = Vec::new();
    if let Some(t) = timing {
        let d = pyo3::types::PyDict::new(py);
        d.set_item("sensor_delay_periods", t.sensor_delay_periods)?;
        d.set_item("gyro_lag_s", t.gyro_lag_s)?;
        out.push(("sensor_timing".to_string(), d.into_any().unbind()));
    }
    for (name, v, w) in cols {
        let n = v.len() / w;
        let a = v.into_pyarray(py);
        let obj: Py<PyAny> = if w == 1 {
            a.into_any().unbind()
        } else {
            a.reshape([n, w])?.into_any().unbind()
        };
        out.push((name, obj));
    }
    Ok(out)
}

enum Col {
    Num(Vec<f64>),
    Text(Vec<String>),
}

/// Read any table (CSV or Parquet) with the one table reader: (name, column) pairs;
/// `text_columns` are kept as strings, every other cell must be a number.
#[pyfunction]
#[pyo3(signature = (path, text_columns=vec!["status".to_string()]))]
fn read_table(
    py: Python<'_>,
    path: PathBuf,
    text_columns: Vec<String>,
) -> PyResult<Vec<(String, Py<PyAny>)>> {
    let res = py.detach(|| -> clino::Result<(Vec<String>, Vec<Col>)> {
        let mut tb = TableReader::open(&path)?;
        let names = tb.header().to_vec();
        let is_text: Vec<bool> = names
            .iter()
            .map(|n| text_columns.iter().any(|t| t.eq_ignore_ascii_case(n)))
            .collect();
        let mut cols: Vec<Col> = is_text
            .iter()
            .map(|&t| {
                if t {
                    Col::Text(vec![])
                } else {
                    Col::Num(vec![])
                }
            })
            .collect();
        while tb.next_record()? {
            for (i, c) in cols.iter_mut().enumerate() {
                match c {
                    Col::Num(v) => v.push(tb.f64(i)?),
                    Col::Text(v) => v.push(tb.text(i)),
                }
            }
        }
        Ok((names, cols))
    });
    let (names, cols) = res.py(py)?;
    let mut out = Vec::new();
    for (n, c) in names.into_iter().zip(cols) {
        let obj: Py<PyAny> = match c {
            Col::Num(v) => v.into_pyarray(py).into_any().unbind(),
            Col::Text(v) => PyList::new(py, v)?.into_any().unbind(),
        };
        out.push((n, obj));
    }
    Ok(out)
}

/// Write a table (CSV, or Parquet by the `.parquet` extension), atomically:
/// columns are float64 arrays or lists of strings, all of one length.
#[pyfunction]
fn write_table(
    py: Python<'_>,
    path: PathBuf,
    names: Vec<String>,
    columns: Vec<Bound<'_, PyAny>>,
) -> PyResult<u64> {
    if names.len() != columns.len() || names.is_empty() {
        return Err(PyValueError::new_err(
            "one name per column, at least one column",
        ));
    }
    let mut cols: Vec<Col> = Vec::new();
    for (n, c) in names.iter().zip(&columns) {
        if let Ok(a) = c.extract::<PyReadonlyArray1<f64>>() {
            cols.push(Col::Num(a.as_array().to_vec()));
        } else if let Ok(v) = c.extract::<Vec<String>>() {
            cols.push(Col::Text(v));
        } else {
            return Err(PyTypeError::new_err(format!(
                "column '{n}' must be a float64 array or a list of str"
            )));
        }
    }
    let len = |c: &Col| match c {
        Col::Num(v) => v.len(),
        Col::Text(v) => v.len(),
    };
    let rows = len(&cols[0]);
    if cols.iter().any(|c| len(c) != rows) {
        return Err(PyValueError::new_err("columns differ in length"));
    }
    let res = py.detach(|| -> clino::Result<u64> {
        let text: Vec<&str> = names
            .iter()
            .zip(&cols)
            .filter(|(_, c)| matches!(c, Col::Text(_)))
            .map(|(n, _)| n.as_str())
            .collect();
        let header: Vec<&str> = names.iter().map(String::as_str).collect();
        let mut file = AtomicFile::create(&path, &[])?;
        let io = |e: std::io::Error| clino::Error::from(e).in_file(&path);
        fn rows_into<S: RowSink>(s: &mut S, cols: &[Col], rows: usize) -> std::io::Result<()> {
            for k in 0..rows {
                for c in cols {
                    match c {
                        Col::Num(v) => s.f64(v[k]),
                        Col::Text(v) => s.str(&v[k]),
                    }
                }
                s.end_row()?;
            }
            Ok(())
        }
        if clino::io::is_parquet(&path) {
            let mut w = ParquetRowWriter::new(&mut file, &header, &text)?;
            rows_into(&mut w, &cols, rows).map_err(io)?;
            w.finish().map_err(io)?;
        } else {
            let mut w = CsvLineWriter::new(&mut file);
            w.header(&header).map_err(io)?;
            rows_into(&mut w, &cols, rows).map_err(io)?;
            w.finish().map_err(io)?;
        }
        file.commit()?;
        Ok(rows as u64)
    });
    res.py(py)
}

/// A Python binary file object as a byte stream (for recordings on object
/// stores, read through fsspec): `read(n)` is called with the GIL taken.
struct PyStream {
    obj: Py<PyAny>,
}

impl Read for PyStream {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        Python::attach(|py| {
            let b = self
                .obj
                .call_method1(py, "read", (buf.len(),))
                .map_err(|e: PyErr| std::io::Error::other(e.to_string()))?;
            let bytes: Vec<u8> = b
                .extract(py)
                .map_err(|e: PyErr| std::io::Error::other(e.to_string()))?;
            let n = bytes.len().min(buf.len());
            buf[..n].copy_from_slice(&bytes[..n]);
            Ok(n)
        })
    }
}

/// Per-recording tilt statistics through `clino fuse`'s run (JSON of
/// `clino::batch::RecordingSummary`). `source` is a path, or a binary file
/// object (CSV) named `name`.
#[pyfunction]
#[pyo3(signature = (source, name=None, filter="dynamic", params=Vec::new(), lever_arm=None, offline=false, calibration=None, gyro_unit="rad/s", accel_unit="m/s2", rate=None, g=clino::core::G0, gyro_range=None, acc_range=None, stamps="recover"))]
#[allow(clippy::too_many_arguments)]
fn summarize(
    py: Python<'_>,
    source: Bound<'_, PyAny>,
    name: Option<String>,
    filter: &str,
    params: Vec<(String, String)>,
    lever_arm: Option<[f64; 3]>,
    offline: bool,
    calibration: Option<PyRef<'_, PyCalibration>>,
    gyro_unit: &str,
    accel_unit: &str,
    rate: Option<f64>,
    g: f64,
    gyro_range: Option<f64>,
    acc_range: Option<f64>,
    stamps: &str,
) -> PyResult<String> {
    let range = sensor_range(gyro_range, acc_range)?;
    let recover = sample_clock(stamps)?;
    let cfg = config(filter, &params, lever_arm, range, offline, recover).py(py)?;
    let opts = ReadOptions {
        imu_only: calibration.is_none(),
        ..read_options(gyro_unit, accel_unit, rate, g).py(py)?
    };
    let cal = calibration.as_ref().map(|c| c.file.clone());
    let fopts = FuseOptions {
        strict: false,
        calibration: cal.as_ref(),
        flush_rows: false,
        progress: None,
    };
    let res = if source.is_instance_of::<PyString>() || source.hasattr("__fspath__")? {
        let path: PathBuf = source.extract()?;
        py.detach(|| -> clino::Result<_> {
            let mut r = ImuCsvReader::from_path(&path, &opts)?;
            batch::summarize_reader(&mut r, &cfg, &fopts)
        })
    } else {
        let stream = PyStream {
            obj: source.clone().unbind(),
        };
        let name = name.unwrap_or_else(|| "<stream>".into());
        py.detach(|| -> clino::Result<_> {
            let mut r = ImuCsvReader::new(stream, name, &opts)?;
            batch::summarize_reader(&mut r, &cfg, &fopts)
        })
    };
    json(&res.py(py)?)
}

/// A calibration file (accelerometer, gyro and magnetometer models with 1σ).
#[pyclass(module = "clino._clino", name = "Calibration")]
#[derive(Clone)]
struct PyCalibration {
    file: CalibrationFile,
}

#[pymethods]
impl PyCalibration {
    /// An empty calibration file.
    #[new]
    fn new() -> Self {
        Self {
            file: CalibrationFile::default(),
        }
    }
    /// Load a TOML calibration file.
    #[staticmethod]
    fn load(py: Python<'_>, path: PathBuf) -> PyResult<Self> {
        Ok(Self {
            file: CalibrationFile::load(&path).py(py)?,
        })
    }
    /// Parse the TOML text of a calibration file.
    #[staticmethod]
    fn from_toml(py: Python<'_>, text: &str) -> PyResult<Self> {
        Ok(Self {
            file: CalibrationFile::from_toml(text).py(py)?,
        })
    }
    /// The TOML text.
    fn to_toml(&self, py: Python<'_>) -> PyResult<String> {
        self.file.to_toml().py(py)
    }
    /// Write the TOML file.
    fn save(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        self.file.save(&path).py(py)
    }
    /// The file as JSON.
    fn to_json(&self) -> PyResult<String> {
        json(&self.file)
    }
    /// Allow temperatures outside the calibrated range.
    #[getter]
    fn extrapolate(&self) -> bool {
        self.file.extrapolate
    }
    #[setter]
    fn set_extrapolate(&mut self, v: bool) {
        self.file.extrapolate = v;
    }
    /// Calibrate arrays: (gyr, acc, mag or None), each (N, 3).
    #[pyo3(signature = (gyr, acc, mag=None, temp_c=None))]
    #[allow(clippy::type_complexity)]
    fn apply<'py>(
        &self,
        py: Python<'py>,
        gyr: PyReadonlyArray2<'py, f64>,
        acc: PyReadonlyArray2<'py, f64>,
        mag: Option<PyReadonlyArray2<'py, f64>>,
        temp_c: Option<PyReadonlyArray1<'py, f64>>,
    ) -> PyResult<(
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Option<Bound<'py, PyArray2<f64>>>,
    )> {
        let g = strided(&gyr, "gyr")?;
        let a = strided(&acc, "acc")?;
        let m = mag.as_ref().map(|m| strided(m, "mag")).transpose()?;
        let tc = temp_c.as_ref().map(|x| slice(x, "temp_c")).transpose()?;
        let n = g.len();
        if a.len() != n || m.is_some_and(|m| m.len() != n) || tc.is_some_and(|t| t.len() != n) {
            return Err(PyValueError::new_err("arrays differ in length"));
        }
        let f = &self.file;
        let res = py.detach(|| -> clino::Result<(Vec<f64>, Vec<f64>, Vec<f64>)> {
            let (mut go, mut ao, mut mo) = (vec![], vec![], vec![]);
            let samples = (0..n).map(|k| {
                let mut s = ImuSample::new(0.0, g.row(k), a.row(k));
                s.mag_ut = m.map(|m| m.row(k));
                s.temp_c = tc.map(|t| t[k]);
                s
            });
            for s in f.apply_iter(samples) {
                let s = s?;
                go.extend(s.gyr_rad_s.iter());
                ao.extend(s.acc_m_s2.iter());
                if let Some(x) = s.mag_ut {
                    mo.extend(x.iter());
                }
            }
            Ok((go, ao, mo))
        });
        let (go, ao, mo) = res.py(py)?;
        let mo = if m.is_some() {
            Some(mo.into_pyarray(py).reshape([n, 3])?)
        } else {
            None
        };
        Ok((
            go.into_pyarray(py).reshape([n, 3])?,
            ao.into_pyarray(py).reshape([n, 3])?,
            mo,
        ))
    }
}

/// Fit a calibration from a recording by the library call behind `clino
/// calibrate KIND` (`clino::calib::calibrate`: the same choice of method):
/// (JSON of the result as `--json` prints it, the calibration file holding
/// the entry, the notes the CLI prints as `clino: note: …`).
#[pyfunction]
#[pyo3(signature = (kind, path, model="mwd12", g=clino::core::G0, field_ut=None, window_s=0.5, min_pose_s=1.0, accel_calibration=None))]
#[allow(clippy::too_many_arguments)]
fn calibrate(
    py: Python<'_>,
    kind: &str,
    path: PathBuf,
    model: &str,
    g: f64,
    field_ut: Option<f64>,
    window_s: f64,
    min_pose_s: f64,
    accel_calibration: Option<PyRef<'_, PyCalibration>>,
) -> PyResult<(String, PyCalibration, Vec<String>)> {
    use clino::core::sensor::TriadKind;
    let kind = match kind {
        "accel" => TriadKind::Accel,
        "gyro" => TriadKind::Gyro,
        "mag" => TriadKind::Mag,
        k => {
            return Err(PyValueError::new_err(format!(
                "unknown triad '{k}' (accel, gyro or mag)"
            )));
        }
    };
    let method = Method::parse(model).py(py)?;
    // every triad reads only the settings it needs, as in `clino calibrate`
    let opts = CalibOptions {
        statics: StaticOptions {
            window_s,
            min_duration_s: min_pose_s,
            ..Default::default()
        },
        g_m_s2: g,
        field_ut,
        accel: accel_calibration.and_then(|c| c.file.accel.as_ref().map(|e| e.calibration())),
    };
    let res = py.detach(|| -> clino::Result<calib::Calibration> {
        let rec = Recording::load(&path)?;
        calib::calibrate(kind, method, &rec, &path.display().to_string(), &opts)
    });
    let cal = res.py(py)?;
    let mut file = CalibrationFile::default();
    file.set(kind, cal.entry.clone());
    Ok((cal.to_json().to_string(), PyCalibration { file }, cal.notes))
}

/// `clino survey` (JSON of the report).
#[pyfunction]
#[pyo3(signature = (path, declination_deg=0.0, calibration=None))]
fn survey(
    py: Python<'_>,
    path: PathBuf,
    declination_deg: f64,
    calibration: Option<PyRef<'_, PyCalibration>>,
) -> PyResult<String> {
    let cal = calibration.map(|c| c.file.clone());
    let res = py.detach(|| -> clino::Result<_> {
        let mut readings = clino::survey::read_stations(&path)?;
        if let Some(c) = &cal {
            clino::survey::calibrate_readings(&mut readings, c).map_err(|e| e.in_file(&path))?;
        }
        clino::survey::survey(
            &readings,
            &clino::survey::SurveyOptions {
                declination_deg,
                ..Default::default()
            },
        )
        .map_err(|e| {
            if e.file.is_none() {
                e.in_file(&path)
            } else {
                e
            }
        })
    });
    json(&res.py(py)?)
}

/// Minimum curvature over stations (JSON list of trajectory points).
#[pyfunction]
fn minimum_curvature(
    py: Python<'_>,
    md_m: PyReadonlyArray1<'_, f64>,
    inclination_deg: PyReadonlyArray1<'_, f64>,
    azimuth_deg: PyReadonlyArray1<'_, f64>,
) -> PyResult<String> {
    let (m, i, a) = (
        slice(&md_m, "md_m")?,
        slice(&inclination_deg, "inclination_deg")?,
        slice(&azimuth_deg, "azimuth_deg")?,
    );
    json(&clino::survey::minimum_curvature(m, i, a).py(py)?)
}

/// Sine fit (IEEE Std 1057): three-parameter at `freq_hz`, or four-parameter
/// when `estimate_freq` (freq_hz is then the starting guess, or None).
#[pyfunction]
#[pyo3(signature = (t, y, freq_hz=None, trend_order=0, estimate_freq=false))]
fn sine_fit(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    y: PyReadonlyArray1<'_, f64>,
    freq_hz: Option<f64>,
    trend_order: usize,
    estimate_freq: bool,
) -> PyResult<Vec<(String, Py<PyAny>)>> {
    use clino::testbench::sinefit;
    let (t, y) = (slice(&t, "t")?, slice(&y, "y")?);
    let f = py.detach(|| match (estimate_freq, freq_hz) {
        (true, g) => sinefit::fit4(t, y, g, trend_order),
        (false, Some(f)) => sinefit::fit3(t, y, f, trend_order),
        (false, None) => Err(clino::Error::new(
            clino::ErrorKind::InvalidInput,
            "give freq_hz, or estimate_freq=True",
        )),
    });
    let f = f.py(py)?;
    let num = |x: f64| -> Py<PyAny> { x.into_pyobject(py).unwrap().into_any().unbind() };
    Ok(vec![
        ("freq_hz".into(), num(f.freq_hz)),
        ("amplitude".into(), num(f.amplitude)),
        ("peak_to_peak".into(), num(f.peak_to_peak())),
        ("phase_rad".into(), num(f.phase_rad)),
        ("a".into(), num(f.a)),
        ("b".into(), num(f.b)),
        (
            "trend".into(),
            f.trend.clone().into_pyarray(py).into_any().unbind(),
        ),
        ("rms_residual".into(), num(f.rms_residual)),
        (
            "iterations".into(),
            f.iterations.into_pyobject(py)?.into_any().unbind(),
        ),
    ])
}

/// Simulate a sensor at rest, level: (t, gyr, acc) from a preset (`clino allan --simulate`).
#[pyfunction]
#[pyo3(signature = (preset="mpu6050", rate_hz=100.0, duration_s=60.0, seed=1))]
#[allow(clippy::type_complexity)]
fn simulate_static<'py>(
    py: Python<'py>,
    preset: &str,
    rate_hz: f64,
    duration_s: f64,
    seed: u64,
) -> PyResult<(
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
)> {
    let m = clino::sim::ImuModel::preset(preset).py(py)?;
    m.validate().py(py)?;
    if !(rate_hz.is_finite() && rate_hz > 0.0 && duration_s.is_finite() && duration_s >= 0.0) {
        return Err(PyValueError::new_err(
            "rate_hz must be positive and duration_s non-negative",
        ));
    }
    let s = py.detach(|| {
        m.simulate(
            &clino::sim::motion::Static::level(),
            rate_hz,
            duration_s,
            seed,
        )
    });
    let n = s.len();
    let t: Vec<f64> = s.iter().map(|x| x.t_s).collect();
    let g: Vec<f64> = s
        .iter()
        .flat_map(|x| x.gyr_rad_s.iter().copied().collect::<Vec<_>>())
        .collect();
    let a: Vec<f64> = s
        .iter()
        .flat_map(|x| x.acc_m_s2.iter().copied().collect::<Vec<_>>())
        .collect();
    Ok((
        t.into_pyarray(py),
        g.into_pyarray(py).reshape([n, 3])?,
        a.into_pyarray(py).reshape([n, 3])?,
    ))
}

fn samples_of(t: &[f64], g: Strided<'_>, a: Strided<'_>) -> PyResult<Vec<ImuSample>> {
    if g.len() != t.len() || a.len() != t.len() {
        return Err(PyValueError::new_err("t, gyr and acc differ in length"));
    }
    Ok((0..t.len())
        .map(|k| ImuSample::new(t[k], g.row(k), a.row(k)))
        .collect())
}

/// `clino testbench static` on arrays (JSON of the result).
#[pyfunction]
#[pyo3(signature = (t, gyr, acc, filter=clino::testbench::filters::BEST_FILTER, settle_s=5.0))]
fn static_test(
    py: Python<'_>,
    t: PyReadonlyArray1<'_, f64>,
    gyr: PyReadonlyArray2<'_, f64>,
    acc: PyReadonlyArray2<'_, f64>,
    filter: &str,
    settle_s: f64,
) -> PyResult<String> {
    let s = samples_of(
        slice(&t, "t")?,
        strided(&gyr, "gyr")?,
        strided(&acc, "acc")?,
    )?;
    let r = py.detach(|| clino::testbench::static_test::static_test(&s, filter, settle_s));
    json(&r.py(py)?)
}

/// `clino testbench analyze` on a lab recording (JSON of the analysis).
#[pyfunction]
#[pyo3(signature = (path, excitation="conical", freq_hz=None, skip_s=0.0))]
fn testbench_analyze(
    py: Python<'_>,
    path: PathBuf,
    excitation: &str,
    freq_hz: Option<f64>,
    skip_s: f64,
) -> PyResult<String> {
    use clino::testbench::recording::{Excitation, Table, analyze};
    let exc = match excitation {
        "conical" => Excitation::Conical,
        "orbit" => Excitation::Orbit,
        o => {
            return Err(PyValueError::new_err(format!(
                "unknown excitation '{o}' (conical or orbit)"
            )));
        }
    };
    let r = py.detach(|| -> clino::Result<_> {
        let t = Table::read(&path)?;
        analyze(
            &t,
            exc,
            &clino::sim::stewart::Geometry::typical(),
            freq_hz,
            skip_s,
        )
        .map_err(|e| {
            if e.file.is_none() {
                e.in_file(&path)
            } else {
                e
            }
        })
    });
    json(&r.py(py)?)
}

/// Allan deviation of one series (JSON list of points: tau_s, adev, 99 % interval, …).
#[pyfunction]
#[pyo3(signature = (y, rate_hz, per_decade=10))]
fn allan_deviation(
    py: Python<'_>,
    y: PyReadonlyArray1<'_, f64>,
    rate_hz: f64,
    per_decade: usize,
) -> PyResult<String> {
    let y = slice(&y, "y")?;
    let r = py.detach(|| clino::testbench::allan::allan_deviation(y, rate_hz, per_decade));
    json(&r.py(py)?)
}

/// `clino allan` on a static recording (JSON: record, warnings, axes).
#[pyfunction]
#[pyo3(signature = (path, gaps="refuse"))]
fn allan(py: Python<'_>, path: PathBuf, gaps: &str) -> PyResult<String> {
    use clino::testbench::{allan, static_record};
    let policy: static_record::GapPolicy = gaps.parse().py(py)?;
    let r = py.detach(|| -> clino::Result<serde_json::Value> {
        let rec = static_record::read_static_record(&path, policy)?;
        rec.require(allan::MIN_SAMPLES, "an Allan analysis")?;
        let axes = allan::allan_imu(&rec.samples, rec.rate_hz).map_err(|e| {
            if e.file.is_none() {
                e.in_file(&rec.file)
            } else {
                e
            }
        })?;
        Ok(serde_json::json!({
            "file": rec.file.display().to_string(),
            "rate_hz": rec.rate_hz,
            "samples": rec.samples.len(),
            "confidence": allan::CONFIDENCE,
            "record": rec,
            "axes": axes,
        }))
    });
    Ok(r.py(py)?.to_string())
}

/// `clino redundancy diagnose` (JSON of the diagnosis).
#[pyfunction]
#[pyo3(signature = (path, mass_kg=0.1, half_edge_m=0.012, stiffness_n_m=vec![2e7], force_sigma_n=2.0e-4, gyro_sigma_rad_s=2.0e-3, alpha=1e-6, block_len=10, window_blocks=10))]
#[allow(clippy::too_many_arguments)]
fn redundancy_diagnose(
    py: Python<'_>,
    path: PathBuf,
    mass_kg: f64,
    half_edge_m: f64,
    stiffness_n_m: Vec<f64>,
    force_sigma_n: f64,
    gyro_sigma_rad_s: f64,
    alpha: f64,
    block_len: usize,
    window_blocks: usize,
) -> PyResult<String> {
    use clino::redundancy::{
        diagnose::{DiagnosisConfig, NoiseModel},
        model::SixAxisAccelerometer,
        recording,
    };
    let k: [f64; 9] = match stiffness_n_m.len() {
        1 => [stiffness_n_m[0]; 9],
        9 => std::array::from_fn(|i| stiffness_n_m[i]),
        n => {
            return Err(PyValueError::new_err(format!(
                "stiffness_n_m takes 1 or 9 values, got {n}"
            )));
        }
    };
    let r = py.detach(|| -> clino::Result<_> {
        let acc = SixAxisAccelerometer::new(mass_kg, half_edge_m, k)?;
        let rec = recording::read_csv(&path)?;
        let noise = NoiseModel {
            force_sigma_n,
            gyro_sigma_rad_s,
        };
        let cfg = DiagnosisConfig {
            block_len,
            window_blocks,
            false_alarm_prob: alpha,
            ..DiagnosisConfig::default()
        };
        recording::diagnose_recording(&acc, &noise, &cfg, &rec)
    });
    json(&r.py(py)?)
}

/// The native module.
#[pymodule]
fn _clino(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("ClinoError", m.py().get_type::<ClinoError>())?;
    m.add("G0", clino::core::G0)?;
    // a `maturin develop` build without --release: timings are not representative
    m.add("DEBUG_BUILD", cfg!(debug_assertions))?;
    m.add_class::<PyPipeline>()?;
    m.add_class::<PyCalibration>()?;
    m.add_function(wrap_pyfunction!(fuse, m)?)?;
    m.add_function(wrap_pyfunction!(status_names, m)?)?;
    m.add_function(wrap_pyfunction!(filter_help, m)?)?;
    m.add_function(wrap_pyfunction!(spec_text, m)?)?;
    m.add_function(wrap_pyfunction!(evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(score, m)?)?;
    m.add_function(wrap_pyfunction!(inclination_error, m)?)?;
    m.add_function(wrap_pyfunction!(read_imu, m)?)?;
    m.add_function(wrap_pyfunction!(read_table, m)?)?;
    m.add_function(wrap_pyfunction!(write_table, m)?)?;
    m.add_function(wrap_pyfunction!(summarize, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(survey, m)?)?;
    m.add_function(wrap_pyfunction!(minimum_curvature, m)?)?;
    m.add_function(wrap_pyfunction!(sine_fit, m)?)?;
    m.add_function(wrap_pyfunction!(simulate_static, m)?)?;
    m.add_function(wrap_pyfunction!(static_test, m)?)?;
    m.add_function(wrap_pyfunction!(testbench_analyze, m)?)?;
    m.add_function(wrap_pyfunction!(allan_deviation, m)?)?;
    m.add_function(wrap_pyfunction!(allan, m)?)?;
    m.add_function(wrap_pyfunction!(redundancy_diagnose, m)?)?;
    Ok(())
}
