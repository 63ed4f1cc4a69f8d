#!/usr/bin/env python3
"""BROAD's recordings at lower sample rates: `dynamic` beside VQF at each.

    scripts/broad_rates.py BROAD_DIR [--factors 1,3,5,11] [--filter SPEC] [--aligned]

BROAD was recorded at 285.7 Hz; clino's defaults must hold from 25 Hz to
1 kHz. This reads each trial of BROAD_DIR (the CSVs of
scripts/broad_to_csv.py), and for each factor k makes a recording at 1/k of
the rate the way a slower sensor would have made it: the gyro and
accelerometer averaged over k consecutive samples (an integrating
anti-alias filter, as a sensor's output data rate below its internal rate),
time-stamped at the mean of their stamps; the optical reference and the
movement flag taken at the middle sample (k odd, so the middle sample's
stamp is that mean). Then it runs `clino fuse` (real time and `--offline`,
the filter SPEC, default `dynamic`) and PyPI `vqf` (`VQF` and `offlineVQF`,
6-D, their defaults, the new period) on it and scores them as the harness
does: error quaternion q_est ⊗ q_ref*, inclination 2·acos(√(w² + z²)),
RMSE over the samples with movement = 1 and a reference. An estimate that
is not finite on such a sample makes the score NaN (never a score over
the samples left).

Per factor it prints each trial's real-time RMSE and ratio, then the means,
the ratio of the means, the worst trial's ratio, and the same offline.

The averaging and BROAD's own lag (its samples 1.19 periods behind the
reference at 285.7 Hz) leave a timing offset between the estimates and the
reference that grows with the period, and at 26 Hz it dominates every
filter's error in fast turns (5–6°). With `--aligned` each filter's
estimates are scored against the reference shifted by the time, within
±2 periods in steps of 0.05, that suits them best (the reference's gravity
direction interpolated linearly), so that what is compared is the tilt
and not each filter's convention for the instant a sample stands for.

Installs `vqf` and `numpy` into the scripts' private environment
(scripts/_venv.py); builds the release `clino` binary if it is missing.
`scripts/test_broad_rates.py` tests it.
"""
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _venv import ROOT, ensure_venv  # noqa: E402

# the columns a trial must have (the magnetometer's are averaged when present)
REQUIRED = ["t_s"] + [f"gyr_{a}_rad_s" for a in "xyz"] + [f"acc_{a}_m_s2" for a in "xyz"] + \
    [f"ref_q{a}" for a in "wxyz"] + ["movement"]


def read_trial(path):
    """A BROAD-format CSV (its `#` comment lines skipped) as a numpy record
    array; exits naming the file when a required column is missing or a
    cell is not a number."""
    import numpy as np

    with open(path) as fh:
        lines = [line for line in fh if not line.startswith("#")]
    if not lines:
        sys.exit(f"{path}: no header line")
    header = lines[0].strip().split(",")
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        sys.exit(f"{path}: no column {', '.join(missing)}")
    rows = []
    for i, line in enumerate(lines[1:]):
        cells = line.strip().split(",")
        if cells == [""]:
            continue
        if len(cells) != len(header):
            sys.exit(f"{path}: data row {i + 1}: {len(cells)} cells, the header has {len(header)}")
        row = []
        for c, v in zip(header, cells):
            try:
                row.append(float(v))
            except ValueError:
                sys.exit(f"{path}: data row {i + 1}, column '{c}': not a number: {v!r}")
        rows.append(row)
    return np.rec.fromrecords(rows, names=header)


def decimate(d, k):
    """The trial `d` at 1/k of its rate (k odd): gyro, accelerometer,
    magnetometer and time averaged over k samples, the rest taken at the
    middle sample; a dict of column arrays."""
    if k < 1 or k % 2 == 0:
        raise ValueError(f"the factor must be odd and positive, not {k}")
    n = len(d) // k * k
    out = {}
    for c in d.dtype.names:
        x = d[c][:n].reshape(-1, k)
        avg = c == "t_s" or c.startswith(("gyr_", "acc_", "mag_"))
        out[c] = x.mean(axis=1) if avg else x[:, k // 2]
    return out


def up(q):
    """The gravity direction (ENU up) in the body frame of each quaternion w, x, y, z."""
    import numpy as np

    w, x, y, z = q.T
    return np.column_stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)])


def rmse(q, ref, mask, aligned=False):
    """Inclination RMSE (degrees) of the estimates `q` against `ref` over the
    samples of `mask` with a reference; NaN if an estimate is not finite
    there. `aligned`: the least over the reference shifted by −2 … +2
    samples in steps of 0.05 (interpolated linearly)."""
    import numpy as np

    has_ref = mask & np.all(np.isfinite(ref), axis=1)
    if not has_ref.any() or not np.all(np.isfinite(q[has_ref])):
        return float("nan")
    if not aligned:
        w1, x1, y1, z1 = q.T
        w2, x2, y2, z2 = ref[:, 0], -ref[:, 1], -ref[:, 2], -ref[:, 3]
        w = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2
        z = w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2
        e = 2 * np.arccos(np.clip(np.sqrt(w[has_ref] ** 2 + z[has_ref] ** 2), -1, 1))
        return float(np.degrees(np.sqrt(np.mean(e ** 2))))
    # the inclination error is the angle between the gravity directions
    # (body frame) of estimate and reference: the same as above
    ue, ur = up(q), up(ref)
    ue /= np.linalg.norm(ue, axis=1, keepdims=True)
    n = len(ur)
    idx = np.arange(n)
    best = float("inf")
    for s in np.arange(-2.0, 2.0001, 0.05):
        i0 = int(np.floor(s + 1e-9))
        f = s - i0
        j = idx + i0
        ok = mask & (j >= 0) & (j + 1 < n)
        a, b = ur[np.clip(j, 0, n - 1)], ur[np.clip(j + 1, 0, n - 1)]
        u = a * (1 - f) + b * f
        u /= np.linalg.norm(u, axis=1, keepdims=True)
        c = np.clip((u * ue).sum(axis=1), -1, 1)
        ok &= np.isfinite(c)
        if ok.any():
            best = min(best, float(np.degrees(np.sqrt(np.mean(np.arccos(c[ok]) ** 2)))))
    return best


def main():
    argv = sys.argv[1:]
    factors, spec, args, aligned = [1, 3, 5, 11], "dynamic", [], False
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--factors" and i + 1 < len(argv):
            factors = [int(x) for x in argv[i + 1].split(",")]
            i += 2
        elif a == "--aligned":
            aligned = True
            i += 1
        elif a == "--filter" and i + 1 < len(argv):
            spec = argv[i + 1]
            i += 2
        else:
            args.append(a)
            i += 1
    if len(args) != 1 or any(k < 1 or k % 2 == 0 for k in factors):
        sys.exit("usage: scripts/broad_rates.py BROAD_DIR [--factors 1,3,5,11 (odd)] [--filter SPEC] [--aligned]")
    ensure_venv(["vqf>=2,<3", "numpy"])
    import numpy as np
    from vqf import VQF, offlineVQF

    clino = os.path.join(ROOT, "target", "release", "clino")
    if not os.path.exists(clino):
        subprocess.run(["cargo", "build", "--release", "-q", "-p", "clino-cli"], cwd=ROOT, check=True)
    if not os.path.isdir(args[0]):
        sys.exit(f"{args[0]}: not a directory")
    files = sorted(f for f in os.listdir(args[0]) if f.endswith(".csv"))
    if not files:
        sys.exit(f"{args[0]}: no CSV recordings")

    def fuse(path, out, *extra):
        r = subprocess.run([clino, "fuse", path, "-f", spec, "-o", out, *extra], capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(r.stderr.strip() or f"clino fuse {path} failed")
        c = np.genfromtxt(out, delimiter=",", names=True, dtype=None, encoding=None)
        return np.column_stack([c[f"q{a}"] for a in "wxyz"])

    data = {f: read_trial(os.path.join(args[0], f)) for f in files}
    summary = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in factors:
            rows = []
            for f, d in data.items():
                out = decimate(d, k)
                cols = list(out)
                path = os.path.join(tmp, f)
                with open(path, "w") as fh:
                    fh.write(",".join(cols) + "\n")
                    np.savetxt(fh, np.column_stack([out[c] for c in cols]), delimiter=",", fmt="%.10g")
                ts = float(np.median(np.diff(out["t_s"])))
                gyr = np.ascontiguousarray(np.column_stack([out[f"gyr_{a}_rad_s"] for a in "xyz"]))
                acc = np.ascontiguousarray(np.column_stack([out[f"acc_{a}_m_s2"] for a in "xyz"]))
                ref = np.column_stack([out[f"ref_q{a}"] for a in "wxyz"])
                mov = out["movement"] == 1
                r = {
                    "trial": f[:-4],
                    "vqf": rmse(VQF(ts).updateBatch(gyr, acc)["quat6D"], ref, mov, aligned),
                    "clino": rmse(fuse(path, os.path.join(tmp, "rt.csv")), ref, mov, aligned),
                    "offline_vqf": rmse(offlineVQF(gyr, acc, None, ts)["quat6D"], ref, mov, aligned),
                    "offline": rmse(fuse(path, os.path.join(tmp, "off.csv"), "--offline"), ref, mov, aligned),
                }
                rows.append(r)
                print(f"k={k:<3} {1 / ts:6.1f} Hz  {r['trial']:<52} VQF {r['vqf']:.3f}  {spec} "
                      f"{r['clino']:.3f} ({r['clino'] / r['vqf']:.2f})   offline VQF {r['offline_vqf']:.3f}"
                      f"  clino {r['offline']:.3f}", flush=True)
            m = {key: float(np.mean([r[key] for r in rows])) for key in ("vqf", "clino", "offline_vqf", "offline")}
            # (np.max: a NaN ratio makes the worst NaN, where max() may skip it)
            worst = float(np.max([r["clino"] / r["vqf"] for r in rows]))
            worst_off = float(np.max([r["offline"] / r["offline_vqf"] for r in rows]))
            summary.append((k, 1 / ts, len(rows), m, worst, worst_off))
    print()
    print(f"{'factor':<7}{'rate Hz':>8}{'trials':>7}{'VQF °':>8}{'clino °':>9}{'ratio':>7}{'worst':>7}"
          f"{'off VQF °':>11}{'off clino °':>12}{'ratio':>7}{'worst':>7}")
    for k, hz, n, m, worst, worst_off in summary:
        print(f"{k:<7}{hz:>8.1f}{n:>7}{m['vqf']:>8.3f}{m['clino']:>9.3f}{m['clino'] / m['vqf']:>7.2f}{worst:>7.2f}"
              f"{m['offline_vqf']:>11.3f}{m['offline']:>12.3f}{m['offline'] / m['offline_vqf']:>7.2f}{worst_off:>7.2f}")


if __name__ == "__main__":
    main()
