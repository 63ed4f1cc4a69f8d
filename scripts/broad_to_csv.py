#!/usr/bin/env python3
"""Convert the official BROAD trials (HDF5 or MAT files) into clino's CSV recordings.

BROAD — D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD — A Benchmark for
Robust Inertial Orientation Estimation", Data 6(7), 2021, licensed CC BY 4.0 —
is published as one file per trial in the authors' repository (folders
`data_hdf5/` and `data_mat/`, identical data; `data_mat/trials.json` describes
the trials). Each file holds, for N samples at `sampling_rate` Hz:

    imu_gyr   N×3  gyroscope, rad/s            → gyr_{x,y,z}_rad_s
    imu_acc   N×3  accelerometer, m/s²         → acc_{x,y,z}_m_s2
    imu_mag   N×3  magnetometer, µT            → mag_{x,y,z}_uT
    opt_quat  N×4  optical reference (w,x,y,z), ENU, NaN while occluded → ref_q{w,x,y,z}
    movement  N    1 on the samples the benchmark scores → movement

Written as clino reads it (`clino eval`, `clino fuse`): a `#` comment line
naming the trial, the header, then one row per sample with t_s = k/sampling_rate
(6 decimals) and every value unchanged (9 significant digits, `nan` kept).

Usage:
    scripts/broad_to_csv.py SRC... -o OUT_DIR [--trials 02,05,07,...]
SRC is a trial file (.hdf5, .h5 or .mat) or a folder of them (a clone of the
BROAD repository works: its data_hdf5/ or data_mat/ folder). `--trials`
keeps the trials whose names start with the given numbers; without it every
trial found is converted. The twelve clino's tests and benchmarks use:
    --trials 02,05,07,09,11,15,18,21,25,27,31,33

On first use the script makes its own virtual environment (numpy, scipy,
h5py from PyPI) under ${CLINO_BROAD_VENV:-/tmp/clino-broad-venv} and re-runs
itself there.
"""
import argparse
import json
import os
import subprocess
import sys

VENV = os.environ.get("CLINO_BROAD_VENV", "/tmp/clino-broad-venv")
PACKAGES = ["numpy", "scipy", "h5py"]
TWELVE = "02,05,07,09,11,15,18,21,25,27,31,33"
HEADER = (
    "t_s,gyr_x_rad_s,gyr_y_rad_s,gyr_z_rad_s,acc_x_m_s2,acc_y_m_s2,acc_z_m_s2,"
    "mag_x_uT,mag_y_uT,mag_z_uT,ref_qw,ref_qx,ref_qy,ref_qz,movement"
)
EXTENSIONS = (".hdf5", ".h5", ".mat")


def ensure_venv():
    """Re-execute inside a private venv that has numpy, scipy and h5py."""
    py = os.path.join(VENV, "bin", "python")
    if os.path.realpath(sys.prefix) == os.path.realpath(VENV):
        return
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", VENV])
    probe = subprocess.run([py, "-c", "import numpy, scipy.io, h5py"], stderr=subprocess.DEVNULL)
    if probe.returncode != 0:
        subprocess.check_call([py, "-m", "pip", "install", "-q", *PACKAGES])
    os.execv(py, [py, os.path.abspath(sys.argv[0]), *sys.argv[1:]])


def load(path):
    """The arrays of one trial file as a dict of numpy arrays."""
    import numpy as np

    keys = ("imu_gyr", "imu_acc", "imu_mag", "opt_quat", "movement", "sampling_rate")
    if path.endswith(".mat"):
        import scipy.io as spio

        raw = spio.loadmat(path)
        data = {k: np.asarray(raw[k]) for k in keys if k in raw}
    else:
        import h5py

        with h5py.File(path, "r") as f:
            data = {k: np.asarray(f[k][()]) for k in keys if k in f}
    missing = [k for k in keys if k not in data]
    if missing:
        raise ValueError(f"{path}: not a BROAD trial file (missing {', '.join(missing)})")
    fs = float(np.asarray(data["sampling_rate"]).squeeze())
    n = None
    out = {"sampling_rate": fs}
    for k, width in (("imu_gyr", 3), ("imu_acc", 3), ("imu_mag", 3), ("opt_quat", 4)):
        a = np.asarray(data[k], dtype=float)
        if a.ndim == 2 and a.shape[1] != width and a.shape[0] == width:
            a = a.T  # stored column-major (MATLAB / HDF5 written from MATLAB)
        if a.ndim != 2 or a.shape[1] != width:
            raise ValueError(f"{path}: {k} has shape {a.shape}, expected N×{width}")
        n = a.shape[0] if n is None else n
        if a.shape[0] != n:
            raise ValueError(f"{path}: {k} has {a.shape[0]} rows, expected {n}")
        out[k] = a
    mov = np.asarray(data["movement"]).reshape(-1)
    if mov.shape[0] != n:
        raise ValueError(f"{path}: movement has {mov.shape[0]} rows, expected {n}")
    out["movement"] = mov.astype(bool)
    if not (fs > 0 and np.isfinite(fs)):
        raise ValueError(f"{path}: sampling_rate {fs}")
    return out


def describe(name, fs, trials):
    desc = trials.get(name, {}).get("description")
    what = f" ({desc})" if desc else ""
    return (
        f"# BROAD trial {name}{what}; IMU myon aktos-t at {fs:.6f} Hz; "
        "ref = optical motion capture orientation (ENU), NaN where occluded; "
        "movement=1 marks samples scored"
    )


def g9(v):
    return "%.9g" % v


def write_csv(path, name, d, trials):
    fs = d["sampling_rate"]
    cols = [d["imu_gyr"], d["imu_acc"], d["imu_mag"], d["opt_quat"]]
    n = cols[0].shape[0]
    with open(path, "w", newline="\n") as f:
        f.write(describe(name, fs, trials) + "\n")
        f.write(HEADER + "\n")
        for k in range(n):
            cells = ["%.6f" % (k / fs)]
            for c in cols:
                cells.extend(g9(v) for v in c[k])
            cells.append("1" if d["movement"][k] else "0")
            f.write(",".join(cells) + "\n")
    return n


def find_sources(srcs):
    files = []
    for s in srcs:
        if os.path.isdir(s):
            files += sorted(os.path.join(s, f) for f in os.listdir(s) if f.endswith(EXTENSIONS))
        elif os.path.isfile(s):
            files.append(s)
        else:
            raise FileNotFoundError(f"{s}: no such file or folder")
    # one file per trial (the HDF5 and MAT copies are identical): first one wins
    by_trial = {}
    for f in files:
        by_trial.setdefault(os.path.splitext(os.path.basename(f))[0], f)
    return by_trial


def load_trials_json(srcs):
    for s in srcs:
        d = s if os.path.isdir(s) else os.path.dirname(s)
        for cand in (os.path.join(d, "trials.json"), os.path.join(d, "..", "data_mat", "trials.json")):
            if os.path.isfile(cand):
                with open(cand) as f:
                    return json.load(f).get("trials", {})
    return {}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("src", nargs="+", help="BROAD trial files (.hdf5/.h5/.mat) or folders of them")
    ap.add_argument("-o", "--out", required=True, help="output folder (created)")
    ap.add_argument("--trials", help=f"comma-separated trial numbers to keep, e.g. {TWELVE}")
    a = ap.parse_args(argv)
    by_trial = find_sources(a.src)
    if a.trials:
        want = [t.strip() for t in a.trials.split(",") if t.strip()]
        bad = [t for t in want if not t.isdigit()]
        if bad:
            ap.error(f"--trials takes trial numbers, got {', '.join(bad)}")
        keep = {}
        for t in want:
            hits = [n for n in by_trial if n.split("_")[0] == t.zfill(2)]
            if not hits:
                ap.error(f"trial {t} not found among {len(by_trial)} files")
            keep.update((h, by_trial[h]) for h in hits)
        by_trial = keep
    if not by_trial:
        ap.error("no BROAD trial files (.hdf5, .h5, .mat) found")
    trials = load_trials_json(a.src)
    os.makedirs(a.out, exist_ok=True)
    for name in sorted(by_trial):
        d = load(by_trial[name])
        out = os.path.join(a.out, name + ".csv")
        n = write_csv(out, name, d, trials)
        print(f"{by_trial[name]} -> {out} ({n} rows)")


if __name__ == "__main__":
    ensure_venv()
    main()
