"""clino.dask on a local multi-worker cluster against the single-process results."""

import shutil

import numpy as np
import pytest

import clino
import clino.dask as cd
from conftest import EXCERPT

distributed = pytest.importorskip("distributed")
pd = pytest.importorskip("pandas")


@pytest.fixture(scope="module")
def client():
    from distributed import Client, LocalCluster

    with LocalCluster(n_workers=3, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        with Client(cl) as c:
            yield c


def assert_frames_equal(a, b):
    assert list(a.columns) == list(b.columns)
    assert len(a) == len(b)
    pd.testing.assert_frame_equal(a.reset_index(drop=True), b.reset_index(drop=True), check_exact=True)


@pytest.fixture(scope="module")
def fleet(tmp_path_factory):
    """A small fleet: the excerpt as CSV and Parquet, and a shortened copy."""
    d = tmp_path_factory.mktemp("fleet")
    shutil.copy(EXCERPT, d / "a.csv")
    rec = clino.read_recording(EXCERPT, as_frame=True)
    clino.write_table(d / "b.parquet", rec)
    clino.write_table(d / "c.csv", rec.iloc[:2000])
    (d / "notes.txt").write_text("not a recording")
    return d


def test_recordings_expand_directories_globs_and_lists(fleet):
    names = [p.rsplit("/", 1)[-1] for p in cd.recordings(fleet)]
    assert names == ["a.csv", "b.parquet", "c.csv"]
    assert [p.rsplit("/", 1)[-1] for p in cd.recordings(str(fleet / "*.csv"))] == ["a.csv", "c.csv"]
    assert len(cd.recordings([fleet / "a.csv", fleet / "b.parquet"])) == 2
    with pytest.raises(FileNotFoundError):
        cd.recordings(fleet / "nothing")


def test_inclination_statistics_on_the_cluster_equal_single_process(client, fleet):
    got = cd.process(fleet, "inclination", client=client)
    want = cd.process_local(fleet, "inclination")
    assert_frames_equal(got, want)
    assert len(got) == 3
    # each row equals the statistics of the fused arrays
    rec = clino.read_recording(EXCERPT)
    full = clino.fuse_full(rec["gyr_rad_s"], rec["acc_m_s2"], t=rec["t_s"])
    inc = full["inclination_deg"]
    inc = inc[np.isfinite(inc)]
    row = got.iloc[0]
    assert row["inclination_n"] == len(inc)
    assert abs(row["inclination_mean_deg"] - inc.mean()) < 1e-9
    assert abs(row["inclination_std_deg"] - inc.std(ddof=1)) < 1e-9
    assert row["inclination_max_deg"] == inc.max()
    # CSV and Parquet of the same recording: the same numbers
    cols = [c for c in got.columns if c != "file"]
    assert got.iloc[0][cols].equals(got.iloc[1][cols])


def test_a_stream_from_an_fsspec_url_equals_the_path(fleet):
    fsspec = pytest.importorskip("fsspec")
    with fsspec.open(f"file://{fleet / 'a.csv'}", "rb") as f:
        s = clino.summarize(f, name="a.csv")
    p = clino.summarize(fleet / "a.csv")
    s.pop("file"), p.pop("file")
    assert s == p
    # the memory filesystem stands in for an object store
    mem = fsspec.filesystem("memory")
    mem.put(str(fleet / "a.csv"), "/fleet/a.csv")
    mem.put(str(fleet / "b.parquet"), "/fleet/b.parquet")
    rows = cd.process_local("memory://fleet/", "inclination")
    files = list(rows["file"])
    assert [f.startswith("memory://") for f in files] == [True, True]
    assert [f.rsplit("/", 1)[-1] for f in files] == ["a.csv", "b.parquet"]
    assert rows.iloc[0]["inclination_mean_deg"] == p["inclination_mean_deg"]


def test_eval_on_the_cluster(client, fleet):
    got = cd.process(fleet, "eval", client=client, filter="dynamic,mahony")
    want = cd.process_local(fleet, "eval", filter="dynamic,mahony")
    assert_frames_equal(got, want)
    assert len(got) == 6


def test_all_broad_recordings_on_the_cluster(client, broad_dir):
    got = cd.process(broad_dir, "inclination", client=client)
    want = cd.process_local(broad_dir, "inclination")
    assert len(got) == 12
    assert_frames_equal(got, want)
    ev = cd.process(broad_dir, "eval", client=client, filter="dynamic")
    one = clino.evaluate(broad_dir, "dynamic")
    assert np.allclose(ev["rmse_deg"].to_numpy(), [r["scores"][0]["rmse_deg"] for r in one["recordings"]], rtol=0, atol=1e-12)


def test_an_error_on_a_worker_names_the_file(client, tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,0,0,0,9.8\n0.01,0,0,0,0,zz,9.8\n")
    with pytest.raises(clino.ClinoError, match="bad.csv:3"):
        cd.process(tmp_path, "inclination", client=client)
