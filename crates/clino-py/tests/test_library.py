"""The rest of the library from Python: each against the CLI on the same file and
against an independent value (closed form, known truth)."""

import math

import numpy as np
import pytest

import clino
from conftest import cli_json

G = clino.G0


def rot(axis, ang):
    """Rotation matrix about unit axis (Rodrigues)."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(ang) * k + (1 - math.cos(ang)) * k @ k


def multi_position(path, k_true, b_true, seed=3, gyro=False):
    """A static multi-position recording: 14 poses of 2.5 s at 100 Hz, 1 s
    rotations between them; raw = K·f + b + noise (m/s²); with ``gyro`` the
    gyro columns too (the rotation rates)."""
    rng = np.random.default_rng(seed)
    dirs = [(0, 0, 1), (0, 0, -1), (1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0),
            (1, 1, 1), (-1, 1, -1), (1, -1, -1), (-1, -1, 1), (1, 0, 1), (0, 1, -1), (-1, 1, 0), (1, -1, 0.5)]
    ups = [np.array(d, float) / np.linalg.norm(d) for d in dirs]
    rows, t = [], 0.0
    dt = 0.01
    for i, u in enumerate(ups):
        for _ in range(250):
            f = G * u
            raw = k_true @ f + b_true + rng.normal(0, 0.002, 3)
            rows.append([t, *rng.normal(0, 1e-4, 3), *raw])
            t += dt
        if i + 1 < len(ups):
            v = ups[i + 1]
            axis = np.cross(u, v)
            ang = math.atan2(np.linalg.norm(axis), u @ v)
            if np.linalg.norm(axis) < 1e-9:
                axis = np.array([1.0, 0, 0]) if abs(u[0]) < 0.9 else np.array([0, 1.0, 0])
            for j in range(100):
                w = ang / 1.0 * axis / np.linalg.norm(axis)
                if gyro:  # a real gyro is noisy while turning too
                    w = w + rng.normal(0, 1e-4, 3)
                f = G * (rot(axis, ang * (j + 1) / 100) @ u)
                raw = k_true @ f + b_true + rng.normal(0, 0.002, 3)
                rows.append([t, *w, *raw])
                t += dt
    a = np.array(rows)
    cols = {"t_s": a[:, 0], "acc_x_m_s2": a[:, 4], "acc_y_m_s2": a[:, 5], "acc_z_m_s2": a[:, 6]}
    if gyro:
        cols.update({"gyr_x_rad_s": a[:, 1], "gyr_y_rad_s": a[:, 2], "gyr_z_rad_s": a[:, 3]})
    clino.write_table(path, cols)
    return ups


def test_calibration_fit_equals_cli_and_recovers_the_truth(cli, tmp_path):
    k_true = np.diag([1.01, 0.99, 1.005])
    k_true[0, 1] = 0.003
    b_true = np.array([0.05, -0.03, 0.02])
    rec = tmp_path / "poses.csv"
    ups = multi_position(rec, k_true, b_true)
    cal_cli = tmp_path / "cal.toml"
    want = cli_json(cli, "calibrate", "accel", rec, "--model", "matrix", "-o", cal_cli)
    fit, cal = clino.calibrate("accel", rec, "matrix")
    assert [p["name"] for p in fit["fit"]["params"]] == [p["name"] for p in want["fit"]["params"]]
    for p, q in zip(fit["fit"]["params"], want["fit"]["params"]):
        assert abs(p["value"] - q["value"]) <= 1e-12 * max(1.0, abs(q["value"]))
        assert abs(p["sigma"] - q["sigma"]) <= 1e-12 * max(1.0, abs(q["sigma"]))
        assert p["sigma"] > 0
    assert clino.Calibration.load(str(cal_cli)).to_json() == cal.to_json()
    # independent check: calibrated static readings have |f| = g and the true direction
    raw = np.array([k_true @ (G * u) + b_true for u in ups])
    _, acc, _ = cal.apply(np.zeros_like(raw), raw)
    assert np.max(np.abs(np.linalg.norm(acc, axis=1) - G)) < 5e-3
    # applied in the pipeline: a recording at rest on pose 0 gives its tilt
    q = clino.fuse(np.zeros((200, 3)), np.tile(raw[0], (200, 1)), rate=100.0, filter="mahony", calibration=cal)
    assert np.all(np.isfinite(q[-1]))


def test_calibrate_chooses_the_method_as_the_cli(cli, tmp_path):
    rec = tmp_path / "poses.csv"
    multi_position(rec, np.eye(3), np.zeros(3), gyro=True)
    # gyro without a rate table: rotations between static poses, as `clino calibrate gyro`
    want = cli_json(cli, "calibrate", "gyro", rec, "--model", "matrix", "-o", tmp_path / "g.toml")
    with pytest.warns(UserWarning, match="uncalibrated accelerometer"):
        got, cal = clino.calibrate("gyro", rec, "matrix")
    assert set(got) == {"static", "rotations"}
    assert got == want
    assert clino.Calibration.load(str(tmp_path / "g.toml")).to_json() == cal.to_json()
    # the CLI's refusals: another model from rotations, the six-position method for the gyro
    with pytest.raises(clino.ClinoError, match="matrix model only"):
        clino.calibrate("gyro", rec, "mwd12")
    with pytest.raises(clino.ClinoError, match="accelerometer only"):
        clino.calibrate("gyro", rec, "six")
    with pytest.raises(clino.ClinoError, match="unknown model 'mwd13'"):
        clino.calibrate("accel", rec, "mwd13")
    # with the accelerometer calibration given, no note
    _, acal = clino.calibrate("accel", rec, "matrix")
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        clino.calibrate("gyro", rec, "matrix", accel_calibration=acal)


def stations(path):
    inc = [0.0, 10.0, 20.0, 30.0, 30.0]
    md = [0.0, 100.0, 200.0, 300.0, 400.0]
    rows = []
    for i, d in zip(inc, md):
        r = math.radians(i)
        # tool frame, z down the hole: a vertical tool at rest reads (0, 0, −g)
        rows.append([d, G * math.sin(r), 0.0, -G * math.cos(r), 20.0, 5.0, 40.0])
    a = np.array(rows)
    clino.write_table(path, {"md_m": a[:, 0], "acc_x_m_s2": a[:, 1], "acc_y_m_s2": a[:, 2], "acc_z_m_s2": a[:, 3],
                             "mag_x_uT": a[:, 4], "mag_y_uT": a[:, 5], "mag_z_uT": a[:, 6]})
    return inc, md


def test_survey_equals_cli_and_minimum_curvature_closed_form(cli, tmp_path):
    p = tmp_path / "stations.csv"
    inc, md = stations(p)
    want = cli_json(cli, "survey", p)
    got = clino.survey(p)
    assert got == want
    assert [round(s["inclination_deg"], 9) for s in got["stations"]] == inc
    df = clino.survey(p, as_frame=True)
    assert list(df["md_m"]) == md
    # a straight hole at 30°: TVD = md·cos 30°, horizontal = md·sin 30°
    traj = clino.minimum_curvature([0.0, 50.0, 150.0], [30.0, 30.0, 30.0], [45.0, 45.0, 45.0])
    last = traj[-1]
    assert abs(last["tvd_m"] - 150 * math.cos(math.radians(30))) < 1e-9
    assert abs(math.hypot(last["north_m"], last["east_m"]) - 75.0) < 1e-9
    assert abs(last["north_m"] - last["east_m"]) < 1e-9


def test_sine_fit_recovers_a_known_sine():
    t = np.arange(0, 10, 0.005)
    y = 2.0 * np.sin(2 * np.pi * 1.5 * t + 0.3) + 0.1
    f = clino.sine_fit(t, y, 1.5)
    assert abs(f["amplitude"] - 2.0) < 1e-9 and abs(f["phase_rad"] - 0.3) < 1e-9
    assert abs(f["trend"][0] - 0.1) < 1e-9 and abs(f["peak_to_peak"] - 4.0) < 1e-9
    f4 = clino.sine_fit(t, y, 1.4, estimate_freq=True)
    assert abs(f4["freq_hz"] - 1.5) < 1e-7


def test_allan_deviation_of_white_noise_and_the_cli_on_a_real_record(cli, static_record):
    rng = np.random.default_rng(5)
    sigma, rate = 0.01, 100.0
    y = rng.normal(0, sigma, 200_000)
    pts = clino.allan_deviation(y, rate)
    for p in pts:
        if p["tau_s"] <= 10:
            # white noise: σ_A(τ) = σ/√(τ·rate), within the 99 % interval
            want = sigma / math.sqrt(p["tau_s"] * rate)
            assert p["adev_lo"] <= want <= p["adev_hi"], p
    want = cli_json(cli, "allan", static_record)
    got = clino.allan(static_record)
    assert got["axes"] == want["axes"]
    assert got["samples"] == want["samples"] and got["rate_hz"] == want["rate_hz"]


def test_static_test_and_simulation():
    s = clino.simulate_static("mpu6050", rate_hz=100.0, duration_s=30.0, seed=2)
    assert s["gyr_rad_s"].shape == (3000, 3)
    assert abs(np.mean(s["acc_m_s2"][:, 2]) - G) < 0.2
    r = clino.static_test(s["t_s"], s["gyr_rad_s"], s["acc_m_s2"])
    assert r["samples"] == 3000 - 500  # after the 5 s settling time
    assert abs(r["roll"]["mean_deg"]) < 2.0


def test_testbench_analyze_equals_cli(cli, tmp_path):
    lab = tmp_path / "lab.csv"
    cli("testbench", "record", lab, "--excitation", "conical", "--freq-hz", "1", "--duration-s", "8")
    want = cli_json(cli, "testbench", "analyze", lab)
    assert clino.testbench_analyze(lab) == want


def test_redundancy_diagnosis_equals_cli(cli, tmp_path):
    rec = tmp_path / "cube.csv"
    cli("redundancy", "simulate", "--faults", "3", "--out", rec)
    want = cli_json(cli, "redundancy", "diagnose", rec)
    got = clino.redundancy_diagnose(rec)
    assert got == want
    assert "3" in got["diagnosed"]


def test_tables_round_trip_csv_and_parquet(tmp_path):
    import pandas as pd

    df = pd.DataFrame({"t_s": [0.0, 0.5, 1.0], "x": [1.5, np.nan, -2.0], "status": ["init", "fused", "dropout"]})
    for name in ("a.csv", "a.parquet"):
        p = tmp_path / name
        assert clino.write_table(p, df) == 3
        back = clino.read_table(p, as_frame=True)
        assert list(back.columns) == ["t_s", "x", "status"]
        assert np.array_equal(back["x"].to_numpy(), df["x"].to_numpy(), equal_nan=True)
        assert list(back["status"]) == list(df["status"])
    with pytest.raises(clino.ClinoError):
        clino.read_table(tmp_path / "missing.csv")
