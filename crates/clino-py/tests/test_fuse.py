"""clino.fuse and the filter classes against `clino fuse` on the same files."""

import threading

import numpy as np
import pytest

import clino
from conftest import EXCERPT

SPECS = [
    ("dynamic", {}),
    ("mahony:kp=0.5", {}),
    ("madgwick", {"beta": 0.05}),
    ("complementary:tau=0.5", {}),
    ("poisson", {}),
]


def cli_fuse(cli, path, tmp_path, *args):
    out = tmp_path / "out.csv"
    cli("fuse", path, "-o", out, *args)
    return clino.read_table(out)


def assert_same(got, want, tol=1e-9):
    got, want = np.asarray(got, float), np.asarray(want, float)
    assert got.shape == want.shape
    assert np.array_equal(np.isnan(got), np.isnan(want)), "NaN rows differ"
    ok = ~np.isnan(want)
    assert np.max(np.abs(got[ok] - want[ok]), initial=0.0) <= tol


def compare(full, table):
    q = np.column_stack([table[c] for c in ("qw", "qx", "qy", "qz")])
    assert_same(full["quat"], q)
    for c in ("roll_deg", "pitch_deg", "inclination_deg"):
        assert_same(full[c], table[c])
    assert list(full["status"]) == list(table["status"])


@pytest.mark.parametrize("spec,params", SPECS)
def test_fuse_equals_cli_on_the_shipped_excerpt(cli, tmp_path, spec, params):
    rec = clino.read_recording(EXCERPT)
    args = ["-f", spec] + [f"--{k.replace('_', '-')}={v}" for k, v in params.items()]
    table = cli_fuse(cli, EXCERPT, tmp_path, *args)
    full = clino.fuse_full(rec["gyr_rad_s"], rec["acc_m_s2"], t=rec["t_s"], filter=spec, **params)
    compare(full, table)
    # the quaternion-only form is the same array
    q = clino.fuse(rec["gyr_rad_s"], rec["acc_m_s2"], t=rec["t_s"], filter=spec, **params)
    assert np.array_equal(q, full["quat"], equal_nan=True)


def test_stages_offline_and_lever_arm_equal_cli(cli, tmp_path):
    rec = clino.read_recording(EXCERPT)
    g, a, t = rec["gyr_rad_s"], rec["acc_m_s2"], rec["t_s"]
    table = cli_fuse(cli, EXCERPT, tmp_path, "--offline")
    off = clino.fuse_full(g, a, t=t, offline=True)
    compare(off, table)
    assert off["sensor_errors"] is None
    # a real-time dynamic run reports what it learnt from rest to rest
    rt = clino.fuse_full(g, a, t=t)["sensor_errors"]
    assert set(rt) >= {"rest_pairs", "accel_bias_m_s2", "accel_bias_sigma_m_s2", "probability"}
    assert all(0.0 <= p <= 1.0 for p in rt["probability"])
    # and the gyro scale its loop learnt in motion, on top of the pairs'
    assert len(rt["motion_gyro_scale"]) == 3 and all(abs(s) < 0.5 for s in rt["motion_gyro_scale"])
    table = cli_fuse(cli, EXCERPT, tmp_path, "-f", "mahony", "--lever-arm", "0.1,-0.05,0.02")
    compare(clino.fuse_full(g, a, t=t, filter="mahony", lever_arm=(0.1, -0.05, 0.02)), table)


def test_rate_instead_of_time_equals_cli(cli, tmp_path):
    rec = clino.read_recording(EXCERPT)
    src = tmp_path / "no_time.csv"
    clino.write_table(src, {
        "gyr_x_rad_s": rec["gyr_rad_s"][:, 0], "gyr_y_rad_s": rec["gyr_rad_s"][:, 1],
        "gyr_z_rad_s": rec["gyr_rad_s"][:, 2], "acc_x_m_s2": rec["acc_m_s2"][:, 0],
        "acc_y_m_s2": rec["acc_m_s2"][:, 1], "acc_z_m_s2": rec["acc_m_s2"][:, 2],
    })
    table = cli_fuse(cli, src, tmp_path, "--rate", "285.714")
    full = clino.fuse_full(rec["gyr_rad_s"], rec["acc_m_s2"], rate=285.714)
    compare(full, table)
    assert np.array_equal(full["quat"], np.column_stack([table[c] for c in ("qw", "qx", "qy", "qz")]))


def test_parquet_in_and_out(cli, tmp_path):
    rec = clino.read_recording(EXCERPT, as_frame=True)
    pq = tmp_path / "rec.parquet"
    assert clino.write_table(pq, rec) == len(rec)
    back = clino.read_recording(pq)
    assert np.array_equal(back["acc_m_s2"], rec[["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]].to_numpy())
    out = tmp_path / "out.parquet"
    cli("fuse", pq, "-o", out)
    table = clino.read_table(out)
    compare(clino.fuse_full(back["gyr_rad_s"], back["acc_m_s2"], t=back["t_s"]), table)


def test_layouts_are_read_in_place_or_copied_to_the_same_numbers():
    rec = clino.read_recording(EXCERPT)
    g, a, t = rec["gyr_rad_s"], rec["acc_m_s2"], rec["t_s"]
    ref = clino.fuse(g, a, t=t)
    assert np.array_equal(clino.fuse(np.asfortranarray(g), np.asfortranarray(a), t=t), ref, equal_nan=True)
    wide = np.zeros((len(t), 6))
    wide[:, ::2] = g  # a strided view: neither C nor Fortran contiguous
    assert np.array_equal(clino.fuse(wide[:, ::2], a, t=t), ref, equal_nan=True)
    assert np.array_equal(clino.fuse(g.tolist(), a, t=list(t)), ref, equal_nan=True)


def test_filter_class_per_sample_and_batches_equal_one_fuse_call():
    rec = clino.read_recording(EXCERPT)
    g, a, t = rec["gyr_rad_s"], rec["acc_m_s2"], rec["t_s"]
    ref = clino.fuse(g, a, t=t, filter="mahony", kp=0.7)
    f = clino.Mahony(kp=0.7)
    parts = [f.update_batch(g[s:e], a[s:e], t=t[s:e])["quat"] for s, e in ((0, 1000), (1000, 1001), (1001, len(t)))]
    assert np.array_equal(np.vstack(parts), ref, equal_nan=True)
    f.reset()
    one = [f.update(g[k], a[k], t=t[k]) for k in range(300)]
    q = np.vstack([x if x is not None else np.full(4, np.nan) for x in one])
    assert np.array_equal(q, ref[:300], equal_nan=True)
    assert f.counts["samples"] == 300
    assert f.label == "mahony:kp=0.7"
    # vqf-style: sample time and updateBatch
    v = clino.Dynamic(1 / 285.714)
    out = v.updateBatch(g, a)
    assert out["quat6D"].shape == (len(t), 4)
    assert np.allclose(v.getQuat6D(), out["quat6D"][-1])


def test_errors_carry_the_library_message_row_and_column(cli, tmp_path):
    g = np.zeros((5, 3))
    a = np.tile([0, 0, 9.81], (5, 1))
    with pytest.raises(clino.ClinoError) as e:
        clino.fuse(g, a, t=[0, 0.1, 0.1, 0.2, 0.3])
    assert e.value.column == "t_s" and "row 2" in str(e.value) and "repeats" in str(e.value)
    assert e.value.kind == "TimeNotIncreasing"
    with pytest.raises(clino.ClinoError) as e:
        clino.fuse(g, a, rate=100, filter="mahony", beta=0.1)
    assert "'beta' is a parameter of madgwick" in str(e.value)
    with pytest.raises(clino.ClinoError, match="unknown filter 'kalman'"):
        clino.fuse(g, a, rate=100, filter="kalman")
    with pytest.raises(clino.ClinoError, match="offline smoothing is available for the dynamic filter"):
        clino.fuse(g, a, rate=100, filter="mahony", offline=True)
    with pytest.raises(ValueError, match=r"shape \(N, 3\)"):
        clino.fuse(np.zeros((5, 4)), a, rate=100)
    # a file error: the CLI's message, file, line and column
    bad = tmp_path / "bad.csv"
    bad.write_text("# c\nt_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2\n0,0,0,0,0,0,9.8\n0.01,0,x,0,0,0,9.8\n")
    with pytest.raises(clino.ClinoError) as e:
        clino.read_recording(bad)
    assert (e.value.file, e.value.line, e.value.column) == (str(bad), 4, "gyr_y_rad_s")
    r = cli("fuse", bad, "-o", tmp_path / "o.csv", check=False)
    assert r.returncode != 0 and str(e.value) in r.stderr


def test_the_gil_is_released_while_the_filter_runs():
    n = 400_000
    rng = np.random.default_rng(1)
    g = rng.normal(0, 0.1, (n, 3))
    a = np.tile([0.0, 0.0, 9.81], (n, 1)) + rng.normal(0, 0.05, (n, 3))
    count = [0]
    stop = threading.Event()

    def spin():
        while not stop.is_set():
            count[0] += 1

    th = threading.Thread(target=spin)
    th.start()
    try:
        before = count[0]
        clino.fuse(g, a, rate=200.0)
        during = count[0] - before
    finally:
        stop.set()
        th.join()
    # with the GIL held the other thread could not count at all during the call
    assert during > 1000, during


def test_a_recordings_timing_note_is_read_and_matches_the_cli(cli, tmp_path):
    # a recording of `clino stream` notes its sensor's timing before its first
    # sample; read_recording hands it on and `clino fuse` takes it
    text = open(EXCERPT).read().splitlines(keepends=True)
    head = next(i for i, line in enumerate(text) if not line.startswith("#"))
    note = "# clino.sensor_timing sensor_delay_periods=2.5,gyro_lag_s=0.001\n"
    path = tmp_path / "noted.csv"
    path.write_text("".join(text[: head + 1]) + note + "".join(text[head + 1 :]))
    rec = clino.read_recording(path)
    assert rec["sensor_timing"] == {"sensor_delay_periods": 2.5, "gyro_lag_s": 0.001}
    assert "sensor_timing" not in clino.read_recording(EXCERPT)
    table = cli_fuse(cli, path, tmp_path)
    full = clino.fuse_full(rec["gyr_rad_s"], rec["acc_m_s2"], t=rec["t_s"], **rec["sensor_timing"])
    compare(full, table)
    # and it is not the default's
    plain = clino.fuse(rec["gyr_rad_s"], rec["acc_m_s2"], t=rec["t_s"])
    assert not np.allclose(plain, full["quat"], equal_nan=True)
    frame = clino.read_recording(path, as_frame=True)
    assert frame.attrs["sensor_timing"] == rec["sensor_timing"]
