"""clino — gyro-aided dynamic inclinometer toolkit, from Python.

A thin layer over the Rust library (the same code as the ``clino`` command):
the one pipeline (calibrate → lever arm → filter → tilt), the one filter
specification parser, the one recording reader. Conventions: SI units inside
(s, rad/s, m/s², µT, °C); degrees only where a name says so (``*_deg``);
East-North-Up navigation frame; Hamilton quaternions, scalar first
(w, x, y, z), rotating body vectors into the navigation frame; accelerometers
read specific force (level at rest: (0, 0, +g)).

>>> import numpy as np, clino
>>> n = 500
>>> gyr = np.zeros((n, 3)); acc = np.tile([0.0, 0.0, 9.81], (n, 1))
>>> q = clino.fuse(gyr, acc, rate=100.0)          # (N, 4) float64, w x y z
>>> float(q[-1, 0])
1.0

Errors of the library are raised as :class:`ClinoError` (a ``ValueError``)
carrying the CLI's message and ``kind``, ``file``, ``line``, ``column``.
"""

from __future__ import annotations

import json as _json
import os as _os
import warnings as _warnings
from typing import Any, Dict, Iterable, Mapping, Optional, Sequence, Tuple, Union

import numpy as _np

from . import _clino
from ._clino import G0, ClinoError, Calibration

# importable by this name, so that an error raised on a Dask worker unpickles
# on the client as the same class
ClinoError.__module__ = "clino"

__all__ = [
    "G0",
    "ClinoError",
    "Calibration",
    "STATUS_NAMES",
    "fuse",
    "fuse_full",
    "Filter",
    "Poisson",
    "Complementary",
    "Mahony",
    "Madgwick",
    "Dynamic",
    "filter_help",
    "evaluate",
    "score",
    "inclination_error",
    "read_recording",
    "read_table",
    "write_table",
    "summarize",
    "calibrate",
    "survey",
    "minimum_curvature",
    "sine_fit",
    "simulate_static",
    "static_test",
    "testbench_analyze",
    "allan_deviation",
    "allan",
    "redundancy_diagnose",
]

#: Status names of the codes returned per sample (the ``status`` column of ``clino fuse``).
STATUS_NAMES: Tuple[str, ...] = tuple(_clino.status_names())

PathLike = Union[str, "_os.PathLike[str]"]


def _vec3_array(x: Any, name: str) -> _np.ndarray:
    """A float64 (N, 3) array: ``x`` itself when it already is one, C- or
    Fortran-contiguous (read in place by the extension); else a converted copy."""
    a = _np.asarray(x, dtype=_np.float64)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must have shape (N, 3), got {a.shape}")
    if not (a.flags.c_contiguous or a.flags.f_contiguous):
        a = _np.ascontiguousarray(a)
    return a


def _vec1_array(x: Any, name: str) -> Optional[_np.ndarray]:
    if x is None:
        return None
    a = _np.ascontiguousarray(_np.asarray(x, dtype=_np.float64))
    if a.ndim != 1:
        raise ValueError(f"{name} must be one-dimensional, got shape {a.shape}")
    return a


def _param_text(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    return str(v)


def _params(params: Mapping[str, Any]) -> list:
    return [(k, _param_text(v)) for k, v in params.items()]


def _lever(lever_arm: Any) -> Optional[Tuple[float, float, float]]:
    if lever_arm is None:
        return None
    v = [float(x) for x in lever_arm]
    if len(v) != 3:
        raise ValueError("lever_arm must be three numbers (m, body frame)")
    return (v[0], v[1], v[2])


def _range(x: Any) -> Optional[float]:
    # None: not known; anything else is checked (positive, finite) by the extension
    return None if x is None else float(x)


def _stamps(x: Any) -> str:
    # "recover" or "as-given"; anything else is refused, naming both, by the extension
    return str(x)


def _calibration(c: Any) -> Optional[Calibration]:
    if c is None or isinstance(c, Calibration):
        return c
    return Calibration.load(_os.fspath(c))


def _fuse(gyr, acc, rate, t, filter, lever_arm, calibration, offline, temp_c, tilt, gyro_range, acc_range, stamps, params):
    g = _vec3_array(gyr, "gyr")
    a = _vec3_array(acc, "acc")
    q, d, st, counts = _clino.fuse(
        g,
        a,
        t=_vec1_array(t, "t"),
        rate=None if rate is None else float(rate),
        filter=filter,
        lever_arm=_lever(lever_arm),
        calibration=_calibration(calibration),
        offline=bool(offline),
        params=_params(params),
        temp_c=_vec1_array(temp_c, "temp_c"),
        tilt=tilt,
        gyro_range=_range(gyro_range),
        acc_range=_range(acc_range),
        stamps=_stamps(stamps),
    )
    return q, d, st, _json.loads(counts)


def fuse(
    gyr: Any,
    acc: Any,
    rate: Optional[float] = None,
    t: Any = None,
    filter: str = "dynamic",
    lever_arm: Any = None,
    calibration: Any = None,
    offline: bool = False,
    *,
    temp_c: Any = None,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: str = "recover",
    **params: Any,
) -> _np.ndarray:
    """Attitude of every sample: the quaternions ``clino fuse`` writes.

    Parameters
    ----------
    gyr : (N, 3) array, rad/s — body angular rate.
    acc : (N, 3) array, m/s² — specific force (level at rest reads (0, 0, +g)).
    rate : float, Hz — sample rate when there is no ``t`` (row k at k·(1/rate) s).
    t : (N,) array, s — time stamps, finite and strictly increasing.
    filter : str — ``NAME`` or ``NAME:KEY=VALUE,…`` (``poisson``, ``complementary``,
        ``mahony``, ``madgwick``, ``dynamic``); see :func:`filter_help`.
    lever_arm : 3 numbers, m, body frame — sensor position from the rotation axis.
    calibration : :class:`Calibration` or path of a calibration TOML file.
    offline : bool — smooth over the whole recording (dynamic filter only).
    temp_c : (N,) array, °C — temperature, for a temperature-dependent calibration.
    gyro_range : float, °/s — the gyro's full-scale range (an MPU6050 powers on at
        250); a rate read at it is clipped: counted, and the dynamic filter realigns on
        the accelerometer after it and learns no scale error from the clipped turn.
        None (default): not known.
    acc_range : float, g — the accelerometer's full-scale range, likewise (MPU6050: 2);
        a specific force read at it is clipped: counted, and the dynamic filter
        forgets the part beyond the range within a second.
    stamps : str — where each step's time comes from. ``"recover"`` (default): time
        stamps a host made as each sample arrived (off by milliseconds: USB packets,
        scheduling) are put back on the sensor's own clock, recovered from the stamps,
        with lost samples counted; a sensor's own stamps (and ``rate``'s) give their
        steps unchanged, to the bit. ``"as-given"``: the stamps' steps as they are.
    **params : filter parameters by key, with or without unit suffix
        (``bandwidth=0.2`` for ``bandwidth_rad_s``); a key the filter does not read
        is an error.

    Returns
    -------
    (N, 4) float64 array of w, x, y, z (body → ENU); NaN rows before the filter
    has initialised.

    C- and Fortran-ordered float64 inputs are read in place, without a copy;
    any other input (another dtype, a list, a strided view) is converted once
    to a float64 array (a copy) first. The output array is allocated once and
    the library writes each row's quaternion straight into it, with the GIL
    released while the filter runs: nothing is allocated per row.
    """
    q, _, _, _ = _fuse(
        gyr, acc, rate, t, filter, lever_arm, calibration, offline, temp_c, False, gyro_range, acc_range, stamps, params
    )
    return q


def fuse_full(
    gyr: Any,
    acc: Any,
    rate: Optional[float] = None,
    t: Any = None,
    filter: str = "dynamic",
    lever_arm: Any = None,
    calibration: Any = None,
    offline: bool = False,
    *,
    temp_c: Any = None,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: str = "recover",
    **params: Any,
) -> Dict[str, Any]:
    """:func:`fuse` with the tilt outputs and the status of every sample.

    Returns a dict: ``quat`` (N, 4) w x y z; ``roll_deg``, ``pitch_deg``
    (aerospace z-y-x, degrees), ``inclination_deg`` (body z from the vertical,
    degrees), each (N,); ``status`` (N,) str (``waiting``, ``init``, ``fused``,
    ``gyro_only``, ``dropout``, ``saturated``); ``status_code`` (N,) uint8 (index
    in :data:`STATUS_NAMES`); ``counts`` (dict of the pipeline's counts, with
    ``gyro_clipped`` and ``acc_clipped``: samples read at ``gyro_range`` or
    ``acc_range``, and ``retimed``: samples whose step came from the sample clock
    recovered from the stamps, ``stamps="recover"``); ``stamp_jitter_s`` (the
    stamps' own noise about that clock, s RMS, when it gave steps; else None);
    ``sensor_errors`` (dict: what ``dynamic`` learnt from rest to rest, with 1σ
    and probabilities, and the gyro scale its loop learnt in motion
    (``motion_gyro_scale``), as ``clino fuse`` prints it; None offline or for another
    filter); ``mount`` (dict: the online accelerometer bias and lever arm with
    their 1σ, when the configuration estimates them; else None). The same
    numbers as the columns of ``clino fuse``.
    """
    q, d, st, counts = _fuse(
        gyr, acc, rate, t, filter, lever_arm, calibration, offline, temp_c, True, gyro_range, acc_range, stamps, params
    )
    return {
        "quat": q,
        "roll_deg": d[:, 0],
        "pitch_deg": d[:, 1],
        "inclination_deg": d[:, 2],
        "status": _np.array(STATUS_NAMES, dtype=object)[st],
        "status_code": st,
        "counts": counts["counts"],
        "stamp_jitter_s": counts.get("stamp_jitter_s"),
        "sensor_errors": counts.get("sensor_errors"),
        "mount": counts.get("mount"),
    }


class Filter:
    """A filter run sample by sample or batch by batch, like ``vqf.VQF``.

    ``Filter(rate=100.0)`` (or ``Filter(Ts=0.01)``, vqf's sample time in s)
    makes the dynamic filter; ``filter=`` takes any specification and
    ``**params`` its parameters. :meth:`update` takes one sample,
    :meth:`update_batch` (alias :meth:`updateBatch`) an (N, 3) pair of arrays;
    both go through the same pipeline, so any split of a recording into
    batches gives the same numbers as one :func:`fuse` call. ``lever_arm``,
    ``calibration``, ``gyro_range`` (°/s), ``acc_range`` (g) and ``stamps`` are
    those of :func:`fuse`; :attr:`counts` then counts the clipped samples too, and
    the samples whose step came from the recovered sample clock (``retimed``).
    """

    _default_filter = "dynamic"

    def __init__(
        self,
        Ts: Optional[float] = None,
        *,
        rate: Optional[float] = None,
        filter: Optional[str] = None,
        lever_arm: Any = None,
        calibration: Any = None,
        gyro_range: Optional[float] = None,
        acc_range: Optional[float] = None,
        stamps: str = "recover",
        **params: Any,
    ) -> None:
        if Ts is not None and rate is not None:
            raise ValueError("give the sample time Ts (s) or the rate (Hz), not both")
        if Ts is not None:
            if not Ts > 0:
                raise ValueError("Ts must be a positive number of seconds")
            rate = 1.0 / float(Ts)
        self._p = _clino.Pipeline(
            filter=filter or self._default_filter,
            rate=None if rate is None else float(rate),
            lever_arm=_lever(lever_arm),
            calibration=_calibration(calibration),
            params=_params(params),
            gyro_range=_range(gyro_range),
            acc_range=_range(acc_range),
            stamps=_stamps(stamps),
        )
        self._quat: Optional[_np.ndarray] = None

    def update(self, gyr: Any, acc: Any, t: Optional[float] = None, temp_c: Optional[float] = None) -> Optional[_np.ndarray]:
        """One sample (gyr rad/s, acc m/s², t s when no rate was given):
        the attitude after it (w, x, y, z) or None before initialisation."""
        q, d, st = self._p.update(
            [float(x) for x in gyr], [float(x) for x in acc],
            t=None if t is None else float(t), temp_c=temp_c,
        )
        self._last = (d, STATUS_NAMES[st])
        self._quat = None if q is None else _np.array(q)
        return self._quat

    def update_batch(self, gyr: Any, acc: Any, t: Any = None, temp_c: Any = None) -> Dict[str, Any]:
        """A batch: dict with ``quat`` (N, 4), ``quat6D`` (the same array, vqf's
        name), ``roll_deg``, ``pitch_deg``, ``inclination_deg`` (N,) and
        ``status`` (N,) str."""
        q, d, st = self._p.update_batch(
            _vec3_array(gyr, "gyr"), _vec3_array(acc, "acc"),
            t=_vec1_array(t, "t"), temp_c=_vec1_array(temp_c, "temp_c"), tilt=True,
        )
        if len(st):
            self._quat = q[-1].copy() if _np.isfinite(q[-1, 0]) else None
        return {
            "quat": q,
            "quat6D": q,
            "roll_deg": d[:, 0],
            "pitch_deg": d[:, 1],
            "inclination_deg": d[:, 2],
            "status": _np.array(STATUS_NAMES, dtype=object)[st],
        }

    updateBatch = update_batch

    def getQuat6D(self) -> Optional[_np.ndarray]:
        """The current attitude (w, x, y, z), vqf's name."""
        a = self._p.attitude()
        return None if a is None else _np.array(a)

    @property
    def quat(self) -> Optional[_np.ndarray]:
        """The current attitude (w, x, y, z), or None before initialisation."""
        return self.getQuat6D()

    @property
    def counts(self) -> Dict[str, int]:
        """Samples by status so far, the clipped ones (``gyro_clipped``, ``acc_clipped``)
        and those whose step came from the recovered sample clock (``retimed``)."""
        return _json.loads(self._p.counts())

    @property
    def label(self) -> str:
        """The specification in ``clino eval``'s form."""
        return self._p.label()

    def reset(self) -> None:
        """Back to the state before the first sample."""
        self._p.reset()
        self._quat = None


class Poisson(Filter):
    """Gyro-only strapdown integration (``filter="poisson"``)."""

    _default_filter = "poisson"


class Complementary(Filter):
    """DCM complementary filter (``filter="complementary"``)."""

    _default_filter = "complementary"


class Mahony(Filter):
    """Mahony's PI filter (``filter="mahony"``; ``kp`` rad/s, ``ki`` rad/s²)."""

    _default_filter = "mahony"


class Madgwick(Filter):
    """Madgwick's gradient-descent filter (``filter="madgwick"``; ``beta`` rad/s)."""

    _default_filter = "madgwick"


class Dynamic(Filter):
    """clino's dynamic inclinometer filter (``filter="dynamic"``)."""

    _default_filter = "dynamic"


def filter_help() -> str:
    """Every filter and parameter with its unit, default and meaning."""
    return _clino.filter_help()


def _pandas():
    try:
        import pandas as pd
    except ImportError as e:  # pragma: no cover
        raise ImportError("this needs pandas: pip install pandas") from e
    return pd


def evaluate(
    paths: Union[PathLike, Sequence[PathLike]],
    filter: str = "all",
    *,
    lever_arm: Any = None,
    offline: bool = False,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: str = "recover",
    jobs: Optional[int] = None,
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s2",
    rate: Optional[float] = None,
    g: float = G0,
    as_frame: bool = False,
    **params: Any,
) -> Any:
    """``clino eval``: BROAD inclination RMSE (degrees) of filters on recordings.

    ``paths``: files or directories (every ``*.csv``/``*.parquet`` inside).
    Returns the dict ``clino eval --json`` prints (``filters``, ``recordings``
    with per-filter ``rmse_deg``, ``scored``, ``non_finite``, ``dropouts``, the
    recording's ``sensor_delay`` — how far its samples lag the reference,
    ``seconds`` and ``periods``, the value for ``sensor_delay_periods``; None
    when it barely turns — and ``mean_rmse_deg``), or with ``as_frame=True`` a
    pandas DataFrame, one row per (recording, filter), the delay as
    ``sensor_delay_periods``. One task per recording on ``jobs`` threads (all
    cores by default), GIL released. ``lever_arm``, ``offline``, ``gyro_range``
    (°/s), ``acc_range`` (g) and ``stamps`` apply to every filter, as in
    :func:`fuse`.
    """
    if isinstance(paths, (str, _os.PathLike)):
        paths = [paths]
    out = _json.loads(
        _clino.evaluate(
            [_os.fspath(p) for p in paths], filter=filter, params=_params(params),
            lever_arm=_lever(lever_arm), offline=offline, jobs=jobs,
            gyro_unit=gyro_unit, accel_unit=accel_unit, rate=rate, g=g,
            gyro_range=_range(gyro_range), acc_range=_range(acc_range),
            stamps=_stamps(stamps),
        )
    )
    _nan_scores(out)
    if not as_frame:
        return out
    pd = _pandas()
    rows = [
        {
            "file": r["file"],
            "rows": r["rows"],
            "sensor_delay_periods": (
                float("nan") if r.get("sensor_delay") is None else r["sensor_delay"]["periods"]
            ),
            **s,
        }
        for r in out["recordings"]
        for s in r["scores"]
    ]
    return pd.DataFrame(rows)


def _nan_scores(out: Dict[str, Any]) -> None:
    # JSON has no NaN: the CLI writes null for "not a number"
    for r in out["recordings"]:
        for s in r["scores"]:
            if s["rmse_deg"] is None:
                s["rmse_deg"] = float("nan")
    out["mean_rmse_deg"] = [float("nan") if m is None else m for m in out["mean_rmse_deg"]]


def score(estimate: Any, reference: Any, movement: Any) -> Dict[str, Any]:
    """BROAD score of estimates against a reference (the rule of ``clino eval``).

    ``estimate``, ``reference``: (N, 4) w x y z; a NaN estimate row means "not
    initialised" and is scored as the identity; a non-finite reference row is
    not scored. ``movement`` (N,): only rows with movement = 1 are scored.
    Returns ``rmse_deg`` (NaN if nothing was scored, or if an estimate was not
    finite on a scored row), ``scored``, ``non_finite``.
    """
    e = _np.ascontiguousarray(_np.asarray(estimate, dtype=_np.float64))
    r = _np.ascontiguousarray(_np.asarray(reference, dtype=_np.float64))
    m = _vec1_array(movement, "movement")
    rmse, n, nf = _clino.score(e, r, m)
    return {"rmse_deg": rmse, "scored": n, "non_finite": nf}


def inclination_error(estimate: Any, reference: Any) -> _np.ndarray:
    """Inclination error per row, rad: 2·acos(√(w² + z²)) of q_est ⊗ q_ref* (BROAD)."""
    e = _np.ascontiguousarray(_np.asarray(estimate, dtype=_np.float64))
    r = _np.ascontiguousarray(_np.asarray(reference, dtype=_np.float64))
    return _clino.inclination_error(e, r)


def read_recording(
    path: PathLike,
    *,
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s2",
    rate: Optional[float] = None,
    g: float = G0,
    as_frame: bool = False,
) -> Any:
    """Read an IMU recording (CSV or ``.parquet``) with the CLI's reader.

    Returns a dict of NumPy arrays, SI units: ``t_s`` (N,), ``gyr_rad_s`` (N, 3),
    ``acc_m_s2`` (N, 3), and when present ``mag_ut`` (N, 3), ``temp_c`` (N,),
    ``ref_q`` (N, 4, normalised, NaN where the reference is missing),
    ``movement`` (N,, 1/0/NaN); ``line`` (N,) is each row's line in the file.
    A recording of ``clino stream`` notes its sensor's timing: then
    ``sensor_timing`` is a dict of the dynamic filter's parameters
    (``sensor_delay_periods``, ``gyro_lag_s``) that ``clino fuse`` takes from it,
    to pass on: ``clino.fuse(..., **rec["sensor_timing"])``.
    With ``as_frame=True``: a pandas DataFrame with the file's column names
    (``sensor_timing`` in its ``attrs``).
    Errors name the file, line and column.
    """
    cols = dict(_clino.read_imu(_os.fspath(path), gyro_unit=gyro_unit, accel_unit=accel_unit, rate=rate, g=g))
    if not as_frame:
        return cols
    timing = cols.pop("sensor_timing", None)
    pd = _pandas()
    df = {"t_s": cols["t_s"]}
    for key, names in (
        ("gyr_rad_s", ["gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s"]),
        ("acc_m_s2", ["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]),
        ("mag_ut", ["mag_x_uT", "mag_y_uT", "mag_z_uT"]),
        ("ref_q", ["ref_qw", "ref_qx", "ref_qy", "ref_qz"]),
    ):
        if key in cols:
            for j, n in enumerate(names):
                df[n] = cols[key][:, j]
    for key in ("temp_c", "movement"):
        if key in cols:
            df[key] = cols[key]
    frame = pd.DataFrame(df)
    if timing is not None:
        frame.attrs["sensor_timing"] = timing
    return frame


def read_table(path: PathLike, text_columns: Iterable[str] = ("status",), as_frame: bool = False) -> Any:
    """Read any table (CSV or Parquet) with the one table reader: a dict of
    name → float64 array (``text_columns`` as lists of str), or a DataFrame."""
    cols = dict(_clino.read_table(_os.fspath(path), list(text_columns)))
    if as_frame:
        return _pandas().DataFrame(cols)
    return cols


def write_table(path: PathLike, table: Any) -> int:
    """Write a dict of columns or a DataFrame (numbers and str columns) to CSV,
    or Parquet when ``path`` ends in ``.parquet``; the file appears whole or
    not at all. Returns the number of rows."""
    if hasattr(table, "columns") and hasattr(table, "__getitem__") and not isinstance(table, dict):
        items = [(str(c), table[c].to_numpy()) for c in table.columns]
    else:
        items = [(str(k), v) for k, v in table.items()]
    names, cols = [], []
    for k, v in items:
        a = _np.asarray(v)
        if a.dtype.kind in "fiub":
            cols.append(_np.ascontiguousarray(a, dtype=_np.float64))
        else:
            cols.append([str(x) for x in a])
        names.append(k)
    return _clino.write_table(_os.fspath(path), names, cols)


def summarize(
    source: Any,
    filter: str = "dynamic",
    *,
    name: Optional[str] = None,
    lever_arm: Any = None,
    offline: bool = False,
    calibration: Any = None,
    gyro_range: Optional[float] = None,
    acc_range: Optional[float] = None,
    stamps: str = "recover",
    gyro_unit: str = "rad/s",
    accel_unit: str = "m/s2",
    rate: Optional[float] = None,
    g: float = G0,
    **params: Any,
) -> Dict[str, Any]:
    """Per-recording tilt statistics, streaming ``clino fuse``'s run: memory flat
    in the recording's length. ``source``: a path (CSV or Parquet), or a binary
    file object holding CSV (e.g. ``fsspec.open(url, "rb")``). Returns a flat
    dict: ``file``, ``filter``, counts by status (and ``gyro_clipped``,
    ``acc_clipped``: samples read at ``gyro_range`` °/s or ``acc_range`` g, as in
    :func:`fuse`; ``retimed``: samples whose step came from the sample clock
    recovered from the stamps, with ``stamp_jitter_s`` the stamps' own noise about
    it, s RMS, or None), and
    ``{roll,pitch,inclination}_{n,mean_deg,std_deg,min_deg,max_deg}``,
    ``t_first_s``, ``t_last_s``."""
    if isinstance(source, (str, _os.PathLike)):
        source = _os.fspath(source)
    s = _json.loads(
        _clino.summarize(
            source, name=name, filter=filter, params=_params(params), lever_arm=_lever(lever_arm),
            offline=offline, calibration=_calibration(calibration), gyro_unit=gyro_unit,
            accel_unit=accel_unit, rate=rate, g=g, gyro_range=_range(gyro_range),
            acc_range=_range(acc_range), stamps=_stamps(stamps),
        )
    )
    row: Dict[str, Any] = {"file": s["file"], "filter": s["filter"]}
    row.update({k: v for k, v in s["report"]["counts"].items()})
    row["first_dropout_line"] = s["report"]["first_dropout_line"]
    row["stamp_jitter_s"] = s["report"].get("stamp_jitter_s")
    for ang in ("roll", "pitch", "inclination"):
        for k, v in s["tilt"][ang].items():
            row[f"{ang}_{k}"] = float("nan") if v is None else v
    row["t_first_s"] = s["tilt"]["t_first_s"]
    row["t_last_s"] = s["tilt"]["t_last_s"]
    return row


def calibrate(
    kind: str,
    path: PathLike,
    model: str = "mwd12",
    *,
    g: float = G0,
    field_ut: Optional[float] = None,
    window_s: float = 0.5,
    min_pose_s: float = 1.0,
    accel_calibration: Any = None,
) -> Tuple[Dict[str, Any], Calibration]:
    """``clino calibrate accel|gyro|mag``: fit a calibration from a recording.

    The library call behind the CLI (``clino::calib::calibrate``), so the method
    is chosen exactly as ``clino calibrate`` chooses it: accelerometer — static
    poses, then the multi-position fit of ``model`` or, with ``model="six"``, the
    six-position method; gyro — a rate-table fit when the recording has the
    ``ref_gyr_*_rad_s`` columns, else rotations between static poses (``matrix``
    only); magnetometer — the ellipsoid fit.

    Returns (the dict ``--json`` prints — the fit with every parameter's
    ``value`` and 1σ ``sigma``, and the static poses where they were detected —
    and a :class:`Calibration` holding the entry, ready for :func:`fuse` or
    :meth:`Calibration.save`). ``model``: ``matrix``, ``mwd12``, ``mwd30``, or
    ``six`` (accelerometer only). ``g`` m/s² (accelerometer), ``field_ut`` µT
    (magnetometer; default the mean raw magnitude), ``window_s``/``min_pose_s``
    s (static detection), ``accel_calibration`` (gyro from rotations: the
    accelerometer calibration giving the gravity directions). What the CLI
    prints as ``clino: note: …`` (e.g. gravity directions from a raw
    accelerometer) is issued as a :class:`UserWarning`. Errors carry the CLI's
    message.
    """
    js, cal, notes = _clino.calibrate(
        kind, _os.fspath(path), model=model, g=g, field_ut=field_ut, window_s=window_s,
        min_pose_s=min_pose_s, accel_calibration=_calibration(accel_calibration),
    )
    for n in notes:
        _warnings.warn(f"clino: note: {n}", UserWarning, stacklevel=2)
    return _json.loads(js), cal


def survey(path: PathLike, declination_deg: float = 0.0, calibration: Any = None, as_frame: bool = False) -> Any:
    """``clino survey``: inclination, azimuth, toolface, QC and the minimum-curvature
    trajectory of survey stations (the dict ``--json`` prints; with
    ``as_frame=True`` a DataFrame of the stations)."""
    out = _json.loads(_clino.survey(_os.fspath(path), declination_deg=declination_deg, calibration=_calibration(calibration)))
    if as_frame:
        return _pandas().DataFrame(out["stations"])
    return out


def minimum_curvature(md_m: Any, inclination_deg: Any, azimuth_deg: Any) -> Any:
    """Minimum-curvature trajectory: a list of dicts (md_m, tvd_m, north_m,
    east_m, dogleg_deg, dls_deg_per_30m, …), one per station."""
    return _json.loads(
        _clino.minimum_curvature(_vec1_array(md_m, "md_m"), _vec1_array(inclination_deg, "inclination_deg"), _vec1_array(azimuth_deg, "azimuth_deg"))
    )


def sine_fit(t: Any, y: Any, freq_hz: Optional[float] = None, trend_order: int = 0, estimate_freq: bool = False) -> Dict[str, Any]:
    """IEEE Std 1057 sine fit of y(t) (t in s): three-parameter at ``freq_hz`` Hz,
    or four-parameter (frequency estimated) with ``estimate_freq=True``.
    Returns ``freq_hz``, ``amplitude``, ``peak_to_peak``, ``phase_rad`` (of
    Y·sin(ωt + φ)), ``a``, ``b``, ``trend``, ``rms_residual``, ``iterations``."""
    return dict(_clino.sine_fit(_vec1_array(t, "t"), _vec1_array(y, "y"), freq_hz=freq_hz, trend_order=trend_order, estimate_freq=estimate_freq))


def simulate_static(preset: str = "mpu6050", rate_hz: float = 100.0, duration_s: float = 60.0, seed: int = 1) -> Dict[str, _np.ndarray]:
    """A simulated sensor at rest, level (``clino allan --simulate``): ``t_s``
    (N,), ``gyr_rad_s``, ``acc_m_s2`` (N, 3)."""
    t, gy, ac = _clino.simulate_static(preset, rate_hz, duration_s, seed)
    return {"t_s": t, "gyr_rad_s": gy, "acc_m_s2": ac}


def static_test(t: Any, gyr: Any, acc: Any, filter: Optional[str] = None, settle_s: float = 5.0) -> Dict[str, Any]:
    """``clino testbench static`` on arrays: mean, drift, noise of roll and pitch (degrees)."""
    kw = {} if filter is None else {"filter": filter}
    return _json.loads(_clino.static_test(_vec1_array(t, "t"), _vec3_array(gyr, "gyr"), _vec3_array(acc, "acc"), settle_s=settle_s, **kw))


def testbench_analyze(path: PathLike, excitation: str = "conical", freq_hz: Optional[float] = None, skip_s: float = 0.0) -> Dict[str, Any]:
    """``clino testbench analyze``: frequency response (conical) or cross-coupling (orbit) of a lab recording."""
    return _json.loads(_clino.testbench_analyze(_os.fspath(path), excitation, freq_hz, skip_s))


def allan_deviation(y: Any, rate_hz: float, per_decade: int = 10, as_frame: bool = False) -> Any:
    """Overlapping Allan deviation of a series sampled at ``rate_hz`` Hz: one
    point per τ (``tau_s``, ``adev`` in y's unit, 99 % interval ``adev_lo``,
    ``adev_hi``, ``edf``, local ``slope``)."""
    pts = _json.loads(_clino.allan_deviation(_vec1_array(y, "y"), float(rate_hz), per_decade))
    return _pandas().DataFrame(pts) if as_frame else pts


def allan(path: PathLike, gaps: str = "refuse") -> Dict[str, Any]:
    """``clino allan`` on a static recording: IEEE 952 readings and noise terms per axis."""
    return _json.loads(_clino.allan(_os.fspath(path), gaps))


def redundancy_diagnose(path: PathLike, **kw: Any) -> Dict[str, Any]:
    """``clino redundancy diagnose``: fault diagnosis of a nine-chain six-axis
    accelerometer recording (``mass_kg``, ``half_edge_m``, ``stiffness_n_m``
    (N/m, 1 or 9 values), ``force_sigma_n``, ``gyro_sigma_rad_s``, ``alpha``,
    ``block_len``, ``window_blocks`` as the CLI's flags)."""
    if "stiffness_n_m" in kw:
        s = kw["stiffness_n_m"]
        kw["stiffness_n_m"] = [float(s)] if _np.isscalar(s) else [float(x) for x in s]
    return _json.loads(_clino.redundancy_diagnose(_os.fspath(path), **kw))
