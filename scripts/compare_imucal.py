#!/usr/bin/env python3
"""Compare clino's accelerometer calibrations with imucal's Ferraris calibration
on the same simulated data (clino::calib::synth, a poorly calibrated triad whose
scale and bias drift with temperature, MWD-paper magnitudes).

  python3 scripts/compare_imucal.py [WORKDIR]

Data (written by `cargo run -p clino --example calib_export`):
  * the nine Ferraris sections (six static axis-up/down holds, three 360° turns) at 29–31 °C;
  * 26 hand-held poses at 29–31 °C (accel_nominal.csv) and 84 poses at 25–80 °C (accel_poses.csv);
  * 300 check poses with their true specific force (validation.csv).
Every calibration is applied to the check poses (clino's through `clino calibrate apply`)
and the maximum tilt error (angle between calibrated and true specific force) and
|G| error are reported, near the nominal temperature (29–31 °C) and over 25–80 °C.
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _venv import ensure_venv, clino, export  # noqa: E402

ensure_venv(["imucal", "numpy", "pandas"])

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from imucal import FerrarisCalibration  # noqa: E402
from imucal.ferraris_calibration import FerrarisSignalRegions  # noqa: E402

G = 9.80665
work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/clino-compare-imucal"
os.makedirs(work, exist_ok=True)
export(work)

ACC = ["acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]
GYR = ["gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s"]
sec = {n: pd.read_csv(os.path.join(work, "ferraris", f"{n}.csv")) for n in
       ["x_p", "x_a", "y_p", "y_a", "z_p", "z_a", "x_rot", "y_rot", "z_rot"]}
kw = {}
for n, d in sec.items():
    kw[f"acc_{n}"] = d[ACC].to_numpy()
    kw[f"gyr_{n}"] = d[GYR].to_numpy()
regions = FerrarisSignalRegions(**kw)
# our turns are positive (counter-clockwise) about each axis: expected angle +360°
cal = FerrarisCalibration(grav=G, expected_angle=360).compute(regions, sampling_rate_hz=100.0, from_acc_unit="m/s^2", from_gyr_unit="rad/s")

val = pd.read_csv(os.path.join(work, "validation.csv"))
raw = val[ACC].to_numpy()
truth = val[["true_x_m_s2", "true_y_m_s2", "true_z_m_s2"]].to_numpy()
temp = val["temp_c"].to_numpy()


def errors(cal_acc):
    cosang = np.sum(cal_acc * truth, axis=1) / (np.linalg.norm(cal_acc, axis=1) * np.linalg.norm(truth, axis=1))
    tilt = np.degrees(np.arccos(np.clip(cosang, -1, 1)))
    gerr = np.abs(np.linalg.norm(cal_acc, axis=1) - G) / G * 1e3
    near = np.abs(temp - 30.0) <= 1.0
    return tilt[near].max(), gerr[near].max(), tilt.max(), gerr.max()


rows = [("uncalibrated", errors(raw))]
rows.append(("imucal Ferraris (9 sections, 29-31 °C)", errors(cal._calibrate_acc(raw))))

# clino on the same data: the six static Ferraris sections as one recording
parts = []
t0 = 0.0
for n in ["x_p", "x_a", "y_p", "y_a", "z_p", "z_a"]:
    d = sec[n].copy()
    d["t_s"] = d["t_s"] - d["t_s"].iloc[0] + t0
    t0 = d["t_s"].iloc[-1] + 2.0
    parts.append(d)
static = pd.concat(parts)
static_path = os.path.join(work, "ferraris_static.csv")
static.to_csv(static_path, index=False)

rec = pd.DataFrame({"t_s": np.arange(len(raw)) * 0.01, ACC[0]: raw[:, 0], ACC[1]: raw[:, 1], ACC[2]: raw[:, 2], "temp_c": temp})
rec_path = os.path.join(work, "validation_recording.csv")
rec.to_csv(rec_path, index=False)


def clino_errors(cal_path):
    out = os.path.join(work, "validation_calibrated.csv")
    clino("calibrate", "apply", cal_path, rec_path, "-o", out, "--extrapolate")
    return errors(pd.read_csv(out)[ACC].to_numpy())


for label, data, model in [
    ("clino six-position (same 6 static sections)", static_path, "six"),
    ("clino mwd12 (26 hand-held poses, 29-31 °C)", os.path.join(work, "accel_nominal.csv"), "mwd12"),
    ("clino mwd30 (84 poses, 25-80 °C)", os.path.join(work, "accel_poses.csv"), "mwd30"),
]:
    cal_path = os.path.join(work, f"cal_{model}.toml")
    clino("calibrate", "accel", data, "--model", model, "-o", cal_path, "--json")
    rows.append((label, clino_errors(cal_path)))

print(f"{'calibration':48} {'tilt 29-31°C':>13} {'|G| 29-31°C':>12} {'tilt 25-80°C':>13} {'|G| 25-80°C':>12}")
for label, (tn, gn, ta, ga) in rows:
    print(f"{label:48} {tn:12.4f}° {gn:9.3f} mg {ta:12.4f}° {ga:9.3f} mg")
