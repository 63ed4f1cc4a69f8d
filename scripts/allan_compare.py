#!/usr/bin/env python3
"""Compare `clino allan` with allantools (PyPI) on the shared MPU-6050 record at
rest and on simulated records with known N, B, K.

  scripts/allan_compare.sh [WORKDIR]      (or python3 scripts/allan_compare.py)

For every record and axis:
  * the curve: allantools.oadev(y, rate, data_type="freq", taus=clino's τ)
    against clino's, largest relative difference;
  * the IEEE 952 graphical readings taken here, independently, from
    allantools' curve — n: the −1/2 line through the longest-weighted run of
    at least three points with local slope in [−0.6, −0.45], read at 1 s;
    b: minimum / 0.664 (where clino finds a floor); k: the +1/2 line through
    the longest run with slope in [0.4, 0.6], read at 3 s — against clino's
    `ieee952` (local slope: least squares over ±0.2 decade and the neighbours,
    as clino; weights: white-noise degrees of freedom);
  * the equivalent degrees of freedom of clino's points against allantools'
    Greenhall edf for white rate noise (alpha = 0), where the record is white
    (MPU-6050), for m ≥ 34 (allantools models phase averaging below that);
  * on simulated records, clino's readings and fitted terms against the truth.
Records: ../shared/data/static/mpu6050_rest_100hz.csv (100 Hz, 449 s) and three
seeds of `cargo run --release -p clino --example allan_sim` (100 Hz, 20 000 s,
N = 1e-3, B = 1.5e-3, K = 3.2e-4; accelerometer terms x10).
"""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _venv import ensure_venv, ROOT  # noqa: E402

ensure_venv(["allantools", "numpy"])

import numpy as np  # noqa: E402
import allantools  # noqa: E402
import allantools.ci as atci  # noqa: E402

B_FLOOR = np.sqrt(2 * np.log(2) / np.pi)
AXES = ["gyr_x", "gyr_y", "gyr_z", "acc_x", "acc_y", "acc_z"]
COLS = ["gyr_x_rad_s", "gyr_y_rad_s", "gyr_z_rad_s", "acc_x_m_s2", "acc_y_m_s2", "acc_z_m_s2"]
work = sys.argv[1] if len(sys.argv) > 1 else "/tmp/clino-allan-compare"
os.makedirs(work, exist_ok=True)


def run(*cmd):
    return subprocess.run(cmd, cwd=ROOT, check=True, stdout=subprocess.PIPE, text=True).stdout


run("cargo", "build", "-q", "--release", "-p", "clino-cli", "--bin", "clino")
CLINO = os.path.join(ROOT, "target", "release", "clino")

records = [("MPU-6050 at rest (real)", os.path.join(ROOT, "..", "shared", "data", "static", "mpu6050_rest_100hz.csv"), None)]
if not os.path.exists(records[0][1]):
    records[0] = (records[0][0], "/work/shared/data/static/mpu6050_rest_100hz.csv", None)
TRUTH = (1e-3, 1.5e-3, 3.2e-4)
for seed in (1, 2, 3):
    args = ["100", "20000", *map(str, TRUTH), str(seed)]
    p = os.path.join(work, "sim_" + "_".join(args) + ".csv")
    if not os.path.exists(p):  # the name holds every parameter
        run("cargo", "run", "-q", "--release", "-p", "clino", "--example", "allan_sim", "--", p, *args)
    records.append((f"simulated, seed {seed}", p, TRUTH))


def load(path):
    with open(path) as f:
        skip = 0
        for line in f:
            if line.startswith("#") or not line.strip():
                skip += 1
                continue
            header = [h.strip() for h in line.split(",")]
            break
    data = np.loadtxt(path, delimiter=",", skiprows=skip + 1, comments="#")
    return {h: data[:, i] for i, h in enumerate(header)}


def slopes(tau, ad):
    lt = np.log10(tau)
    out = []
    for i in range(len(tau)):
        idx = [j for j in range(len(tau)) if abs(lt[j] - lt[i]) <= 0.2 + 1e-9 or abs(j - i) == 1]
        out.append(np.polyfit(np.log(tau[idx]), np.log(ad[idx]), 1)[0])
    return np.array(out)


def edf_white(n, m):
    nn = n + 1.0
    return np.maximum((3 * (nn - 1) / (2 * m) - 2 * (nn - 2) / nn) * 4 * m * m / (4 * m * m + 5), 1.0)


def runs(ok):
    out, start = [], None
    for i, v in enumerate(list(ok) + [False]):
        if v and start is None:
            start = i
        elif not v and start is not None:
            out.append((start, i))
            start = None
    return out


def readings(tau, ad, n, rate):
    s = slopes(tau, ad)
    w = edf_white(n, np.round(tau * rate))
    res = {"n": None, "b": None, "k": None}
    cand = [r for r in runs((s >= -0.6) & (s <= -0.45)) if r[1] - r[0] >= 3]
    if cand:
        a, b = max(cand, key=lambda r: w[r[0]:r[1]].sum())
        res["n"] = np.sqrt(np.sum(w[a:b] * ad[a:b] ** 2 * tau[a:b]) / w[a:b].sum())
    res["b"] = ad.min() / B_FLOOR
    cand = runs((s >= 0.4) & (s <= 0.6))
    if cand:
        a, b = max(cand, key=lambda r: r[1] - r[0])
        res["k"] = np.sqrt(3 * np.sum(w[a:b] * ad[a:b] ** 2 / tau[a:b]) / w[a:b].sum())
    return res


def pct(a, b):
    return "-" if a is None or b is None else f"{100 * (a / b - 1):+.2f}"


def fmt(v):
    return "-" if v is None else f"{v:.4e}"


for name, path, truth in records:
    out = json.loads(run(CLINO, "allan", path, "--json"))
    d = load(path)
    rate, nsamp = out["rate_hz"], out["samples"]
    print(f"\n## {name}: {os.path.relpath(path, ROOT)} ({nsamp} samples, {rate:.3f} Hz)")
    print("axis   curve max|diff|  clino n     allantools n  diff %  clino b     at tau s  allantools b  diff %  clino k     allantools k  diff %  edf ratio (m>=34)")
    for ax, col in zip(out["axes"], COLS):
        y = d[col]
        tau = np.array([p["tau_s"] for p in ax["points"]])
        ta, ad, _, _ = allantools.oadev(y, rate=rate, data_type="freq", taus=tau)
        curve = np.max(np.abs(ad / np.array([p["adev"] for p in ax["points"]]) - 1))
        r = readings(ta, ad, len(y), rate)
        c = ax["ieee952"]
        bmin_c = min(p["adev"] for p in ax["points"]) / B_FLOOR
        bmin_a = ad.min() / B_FLOOR
        b_at = "-" if c["b_tau_s"] is None else f"{c['b_tau_s']:.1f}"
        b_ref = r["b"] if c["b"] is not None else None
        k_ref = r["k"] if c["k"] is not None or r["k"] is not None else None
        ms = np.round(tau * rate).astype(int)
        ratio = [p["edf"] / atci.edf_greenhall(0, 2, m, len(y) + 1, overlapping=True)
                 for p, m in zip(ax["points"], ms) if m >= 34]
        edf_txt = f"{min(ratio):.3f}-{max(ratio):.3f}" if truth is None and ratio else "-"
        print(f"{ax['axis']:<6} {curve:>15.1e}  {fmt(c['n']):<11} {fmt(r['n']):<13} {pct(c['n'], r['n']):>6}  "
              f"{fmt(c['b']):<11} {b_at:>8}  {fmt(b_ref):<13} {pct(c['b'], b_ref):>6}  "
              f"{fmt(c['k']):<11} {fmt(k_ref):<13} {pct(c['k'], k_ref):>6}  {edf_txt}")
        if c["b"] is None:
            print(f"       b: none (min/0.664: clino {bmin_c:.4e}, allantools {bmin_a:.4e}, {pct(bmin_c, bmin_a)} %): {c['b_reason']}")
        if c["k"] is None and truth is not None:
            print(f"       k: {c['k_reason']}")
    if truth is not None:
        print("against the truth (gyro N, B, K = %g, %g, %g; accelerometer x10), error %%:" % truth)
        print("axis   ieee952 n  ieee952 b  ieee952 k  fit N   [99 %% holds]  fit B   [holds]  fit K   [holds]")
        for ax in out["axes"]:
            sc = 1.0 if ax["axis"].startswith("gyr") else 10.0
            t = [v * sc for v in truth]
            c, f = ax["ieee952"], ax["fit"]
            cells = []
            for key, tv in zip("nbk", t):
                cells.append(f"{pct(f[key], tv):>6}  [{'yes' if f[key] is not None and f[key + '_lo'] <= tv <= f[key + '_hi'] else 'no '}]")
            print(f"{ax['axis']:<6} {pct(c['n'], t[0]):>9}  {pct(c['b'], t[1]):>9}  {pct(c['k'], t[2]):>9}  " + "  ".join(cells))
