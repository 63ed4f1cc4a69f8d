#!/usr/bin/env python3
"""Compare `clino survey` with wellpathpy's minimum curvature on a random well.

  python3 scripts/compare_mincurve.py [WORKDIR]

A random walk in inclination (0–120°) and azimuth (crossing north, all quadrants)
with a vertical top is turned into tool readings (specific force and field in the
tool frame, z down the hole, attitude R_z(azimuth)·R_y(inclination)·R_z(toolface)
in North-East-Down), fed to `clino survey --json`, and compared with
wellpathpy.mincurve.minimum_curvature on the true angles. Also checks clino's
inclination and azimuth against the angles the readings were made from.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _venv import ensure_venv, clino  # noqa: E402

ensure_venv(["wellpathpy", "numpy"])

import numpy as np  # noqa: E402
from wellpathpy.mincurve import minimum_curvature  # noqa: E402

G = 9.80665
work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/clino-compare-mincurve"
os.makedirs(work, exist_ok=True)
rng = np.random.default_rng(42)
n = 300
md = np.concatenate([[0.0], np.cumsum(rng.uniform(5.0, 40.0, n - 1))])
inc = np.zeros(n)
azi = np.zeros(n)
inc[5:] = np.clip(np.cumsum(rng.normal(0.8, 2.0, n - 5)), 0.5, 120.0)
azi[5:] = np.mod(330.0 + np.cumsum(rng.normal(0.5, 4.0, n - 5)), 360.0)
tf = rng.uniform(0, 360, n)


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


dip = np.radians(65.0)
h_ned = 50.0 * np.array([np.cos(dip), 0.0, np.sin(dip)])
lines = ["md_m,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,mag_x_uT,mag_y_uT,mag_z_uT"]
for k in range(n):
    c = rz(np.radians(azi[k])) @ ry(np.radians(inc[k])) @ rz(np.radians(tf[k]))
    f = -(c.T @ np.array([0.0, 0.0, G]))
    h = c.T @ h_ned
    lines.append(",".join(repr(float(v)) for v in [md[k], *f, *h]))
path = os.path.join(work, "stations.csv")
with open(path, "w") as fh:
    fh.write("\n".join(lines) + "\n")

rep = json.loads(clino("survey", path, "--json"))
tr = rep["trajectory"]
st = rep["stations"]
c_inc = np.array([s["inclination_deg"] for s in st])
c_azi = np.array([s["azimuth_deg"] if s["azimuth_deg"] is not None else 0.0 for s in st])
d_azi = np.abs((c_azi - azi + 180.0) % 360.0 - 180.0)[5:]
print(f"stations: {n}, md 0–{md[-1]:.1f} m")
print(f"max |inclination - truth| = {np.max(np.abs(c_inc - inc)):.3e} deg")
print(f"max |azimuth - truth|     = {np.max(d_azi):.3e} deg (non-vertical stations)")

tvd, north, east, dls = minimum_curvature(md, inc, azi, course_length=30)
ours = {k: np.array([p[k] for p in tr]) for k in ["tvd_m", "north_m", "east_m", "dls_deg_per_30m"]}
worst = 0.0
for name, ref in [("tvd_m", tvd), ("north_m", north), ("east_m", east)]:
    ref = np.asarray(ref)
    if len(ref) == n - 1:
        ref = np.concatenate([[0.0], ref])
    d = np.abs(ours[name] - ref)
    scale = np.maximum(np.abs(ref), 1.0)
    rel = np.max(d / scale)
    worst = max(worst, rel)
    print(f"{name:8} max |clino - wellpathpy| = {d.max():.3e} m, max relative = {rel:.3e} (end value {ref[-1]:.3f} m)")
dls = np.asarray(dls)
if len(dls) == n - 1:
    dls = np.concatenate([[0.0], dls])
print(f"dls      max |clino - wellpathpy| = {np.max(np.abs(ours['dls_deg_per_30m'] - dls)):.3e} deg/30 m")
print("PASS" if worst < 1e-6 else "FAIL", f"(worst relative difference {worst:.3e}, limit 1e-6)")
