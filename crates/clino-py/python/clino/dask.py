"""Fleets of recordings on Dask distributed: one task per recording.

:func:`process` expands a directory, a glob or an object-store prefix
(anything fsspec understands: ``/data/run1``, ``/data/**/*.parquet``,
``s3://bucket/fleet/``) into recordings (``*.csv``, ``*.parquet``), runs one
task per recording on the cluster's workers and gathers the results into one
pandas table, in the order of the recordings:

* ``what="inclination"`` — per-recording tilt statistics (:func:`clino.summarize`:
  counts by status, mean/std/min/max of roll, pitch and inclination, degrees);
* ``what="eval"`` — BROAD scores per (recording, filter) (:func:`clino.evaluate`);
* ``what="calibration"`` — one row per fitted parameter with its 1σ
  (:func:`clino.calibrate`; ``kind=`` and ``model=`` pass through);
* ``what="survey"`` — one row per survey station (:func:`clino.survey`);
* ``what="diagnosis"`` — one row per recording (:func:`clino.redundancy_diagnose`).

Each worker streams its file through the Rust reader (a local path is read
in place; a remote CSV is streamed through the fsspec file object; a remote
Parquet file, which needs random access, is copied to the worker's temporary
directory first), so memory stays flat in the recording's length.

Locally::

    from distributed import Client, LocalCluster
    import clino.dask
    with LocalCluster(n_workers=4, threads_per_worker=1) as cl, Client(cl) as client:
        table = clino.dask.process("../shared/data/broad", what="inclination", client=client)

On a real cluster, the same code with the scheduler's address::

    from distributed import Client
    client = Client("tcp://scheduler.example:8786")
    table = clino.dask.process("s3://fleet/2026-12/", what="inclination", client=client,
                               storage_options={"anon": False})

``client=None`` uses the current client (``distributed.get_client()``) and
``client="tcp://…"`` connects to that scheduler; :func:`process_local` runs the
same tasks in this process (the reference the cluster's table must equal).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from typing import Any, Callable, Dict, List, Optional

import clino

EXTENSIONS = (".csv", ".parquet")


def _fs(source: str, storage_options: Optional[Dict[str, Any]] = None):
    import fsspec

    return fsspec.core.url_to_fs(source, **(storage_options or {}))


def _url(fs, path: str) -> str:
    proto = fs.protocol[0] if isinstance(fs.protocol, (tuple, list)) else fs.protocol
    if proto in ("file", "local"):
        return path
    return fs.unstrip_protocol(path)


def recordings(source: Any, storage_options: Optional[Dict[str, Any]] = None) -> List[str]:
    """The recordings named by ``source`` (a directory or prefix: its ``*.csv``
    and ``*.parquet`` files, not recursive; a glob; a file; or a list of these),
    sorted by name within each item. An item naming nothing is an error."""
    if isinstance(source, (list, tuple)):
        out: List[str] = []
        for s in source:
            out.extend(recordings(s, storage_options))
        return out
    source = os.fspath(source)
    fs, path = _fs(source, storage_options)
    if any(c in path for c in "*?["):
        found = sorted(p for p in fs.glob(path) if p.lower().endswith(EXTENSIONS) and fs.isfile(p))
    elif fs.isdir(path):
        found = sorted(
            p for p in fs.ls(path, detail=False) if p.lower().endswith(EXTENSIONS) and fs.isfile(p)
        )
    elif fs.exists(path):
        found = [path]
    else:
        raise FileNotFoundError(f"{source}: no such file, directory or prefix")
    if not found:
        raise FileNotFoundError(f"{source}: holds no .csv or .parquet recording")
    return [_url(fs, p) for p in found]


class _Local:
    """A recording as a local path for the Rust reader (temporary copy of a remote Parquet file)."""

    def __init__(self, url: str, storage_options: Optional[Dict[str, Any]]):
        self.url = url
        self.fs, self.path = _fs(url, storage_options)
        proto = self.fs.protocol[0] if isinstance(self.fs.protocol, (tuple, list)) else self.fs.protocol
        self.local = proto in ("file", "local")
        self.tmp: Optional[str] = None

    def path_or_stream(self, stream_ok: bool):
        if self.local:
            return self.path, None
        if stream_ok and self.url.lower().endswith(".csv"):
            f = self.fs.open(self.path, "rb")
            return f, f
        self.tmp = tempfile.mkdtemp(prefix="clino-")
        dest = os.path.join(self.tmp, os.path.basename(self.path))
        self.fs.get(self.path, dest)
        return dest, None

    def close(self) -> None:
        if self.tmp:
            shutil.rmtree(self.tmp, ignore_errors=True)


def _inclination(url: str, so, kw) -> List[Dict[str, Any]]:
    loc = _Local(url, so)
    try:
        src, f = loc.path_or_stream(stream_ok=True)
        try:
            row = clino.summarize(src, name=url, **kw)
        finally:
            if f is not None:
                f.close()
        row["file"] = url
        return [row]
    finally:
        loc.close()


def _with_path(fn: Callable[[str], List[Dict[str, Any]]]):
    def run(url: str, so, kw) -> List[Dict[str, Any]]:
        loc = _Local(url, so)
        try:
            p, _ = loc.path_or_stream(stream_ok=False)
            rows = fn(p, **kw)
            for r in rows:
                r["file"] = url
            return rows
        finally:
            loc.close()

    return run


def _eval_rows(path: str, **kw) -> List[Dict[str, Any]]:
    out = clino.evaluate(path, jobs=1, **kw)
    return [{"file": path, "rows": r["rows"], **s} for r in out["recordings"] for s in r["scores"]]


def _calibration_rows(path: str, kind: str = "accel", **kw) -> List[Dict[str, Any]]:
    fit, _ = clino.calibrate(kind, path, **kw)
    rows = []
    for key in ("fit", "rotations"):
        if key in fit:
            for p in fit[key]["params"]:
                rows.append({"file": path, "triad": kind, "method": key, **p})
    if "six_position" in fit:
        s = fit["six_position"]
        rows.append({"file": path, "triad": kind, "method": "six_position", "name": "K", "value": s["k"]})
    return rows


def _survey_rows(path: str, **kw) -> List[Dict[str, Any]]:
    out = clino.survey(path, **kw)
    traj = {round(t["md_m"], 9): t for t in out.get("trajectory", [])}
    rows = []
    for s in out["stations"]:
        r = {"file": path, **s}
        t = traj.get(round(s["md_m"], 9))
        if t:
            r.update({k: v for k, v in t.items() if k not in r})
        rows.append(r)
    return rows


def _diagnosis_rows(path: str, **kw) -> List[Dict[str, Any]]:
    d = clino.redundancy_diagnose(path, **kw)
    keep = ("samples", "step_s", "windows", "first_alarm_s", "restore_from_s", "diagnosed", "diagnosed_source")
    return [{"file": path, **{k: d.get(k) for k in keep}, "segments": len(d.get("segments", []))}]


TASKS: Dict[str, Callable[[str, Any, Dict[str, Any]], List[Dict[str, Any]]]] = {
    "inclination": _inclination,
    "eval": _with_path(_eval_rows),
    "calibration": _with_path(_calibration_rows),
    "survey": _with_path(_survey_rows),
    "diagnosis": _with_path(_diagnosis_rows),
}


def run_one(url: str, what: str = "inclination", storage_options: Optional[Dict[str, Any]] = None, **kw: Any) -> List[Dict[str, Any]]:
    """The task of one recording: its rows of the table (run on a worker)."""
    try:
        task = TASKS[what]
    except KeyError:
        raise ValueError(f"unknown what={what!r} (one of {', '.join(TASKS)})") from None
    return task(url, storage_options, kw)


def _table(parts: List[List[Dict[str, Any]]]):
    import pandas as pd

    return pd.DataFrame([r for rows in parts for r in rows])


def _client(client: Any):
    from distributed import Client, get_client

    if client is None:
        return get_client()
    if isinstance(client, str):
        return Client(client)
    return client


def process(
    source: Any,
    what: str = "inclination",
    client: Any = None,
    storage_options: Optional[Dict[str, Any]] = None,
    **kw: Any,
):
    """Run one task per recording of ``source`` on a Dask cluster and gather
    one pandas DataFrame (rows in the order of :func:`recordings`).

    ``client``: a ``distributed.Client``, a scheduler address, or None for the
    current client. ``**kw`` go to the task (``filter=``, filter parameters,
    ``kind=``/``model=`` for calibration, …). A failing recording raises its
    ``ClinoError`` (file, line, column) here.
    """
    if what not in TASKS:
        raise ValueError(f"unknown what={what!r} (one of {', '.join(TASKS)})")
    urls = recordings(source, storage_options)
    c = _client(client)
    futures = c.map(run_one, urls, what=what, storage_options=storage_options, pure=False, **kw)
    return _table(c.gather(futures))


def process_local(source: Any, what: str = "inclination", storage_options: Optional[Dict[str, Any]] = None, **kw: Any):
    """:func:`process` in this process, one recording after another."""
    urls = recordings(source, storage_options)
    return _table([run_one(u, what=what, storage_options=storage_options, **kw) for u in urls])
