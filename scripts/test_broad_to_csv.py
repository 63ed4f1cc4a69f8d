#!/usr/bin/env python3
"""Test scripts/broad_to_csv.py on small synthetic trial files with BROAD's structure.

The BROAD files cannot be downloaded here, so this writes files with the
official layout (imu_gyr, imu_acc, imu_mag N×3; opt_quat N×4 with NaN;
movement; sampling_rate) from the repository's excerpt of trial 07
(crates/clino/data/broad_07_excerpt.csv, converted from the official files),
as .mat (scipy) and .hdf5 (h5py, one copy stored column-major), converts
them back and checks every cell equals the excerpt's, the time column is
k/sampling_rate, and malformed files are refused. Runs in the converter's
venv (made on first use). Prints "N passed, 0 failed".
"""
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import broad_to_csv as conv  # noqa: E402

EXCERPT = os.path.join(HERE, "..", "crates", "clino", "data", "broad_07_excerpt.csv")
NAME = "07_undisturbed_fast_rotation_B"


def read_excerpt(limit=600):
    rows = []
    with open(EXCERPT) as f:
        for line in f:
            if line.startswith("#") or line.startswith("t_s"):
                continue
            rows.append(line.rstrip("\n").split(","))
            if len(rows) == limit:
                break
    return rows


def main():
    conv.ensure_venv()
    import h5py
    import numpy as np
    import scipy.io as spio

    rows = read_excerpt()
    # cells: t_s, gyr×3, acc×3, mag×3, ref_q×4, movement
    rows[5][10:14] = ["nan"] * 4  # an occluded reference sample, kept as nan
    vals = np.array([[float(c) for c in r[1:14]] for r in rows])
    mov = np.array([int(r[14]) for r in rows], dtype=np.uint8)
    fs = 2000.0 / 7.0
    arrays = dict(
        imu_gyr=vals[:, 0:3],
        imu_acc=vals[:, 3:6],
        imu_mag=vals[:, 6:9],
        opt_quat=vals[:, 9:13],
        movement=mov.reshape(-1, 1),
        sampling_rate=np.array([[fs]]),
    )
    passed = failed = 0

    def check(cond, what):
        nonlocal passed, failed
        if cond:
            passed += 1
        else:
            failed += 1
            print("FAIL:", what)

    with tempfile.TemporaryDirectory() as d:
        src_mat = os.path.join(d, "data_mat")
        src_h5 = os.path.join(d, "data_hdf5")
        os.makedirs(src_mat)
        os.makedirs(src_h5)
        spio.savemat(os.path.join(src_mat, NAME + ".mat"), arrays)
        with open(os.path.join(src_mat, "trials.json"), "w") as f:
            f.write('{"trials": {"%s": {"description": "undisturbed, fast rotation movements without translation, no breaks"}}}' % NAME)
        with h5py.File(os.path.join(src_h5, NAME + ".hdf5"), "w") as f:
            for k, v in arrays.items():
                # column-major copy of the triads, as MATLAB writes them
                f[k] = v.T if k.startswith("imu_") else v
        for src in (src_mat, src_h5):
            out = os.path.join(d, "out_" + os.path.basename(src))
            conv.main([src, "-o", out, "--trials", "7"])
            path = os.path.join(out, NAME + ".csv")
            with open(path) as f:
                lines = f.read().splitlines()
            check(lines[0].startswith("# BROAD trial " + NAME), f"{src}: comment line {lines[0]!r}")
            with open(EXCERPT) as f:
                original_comment = f.readlines()[1].rstrip("\n")
            check(lines[0] == original_comment, f"{src}: comment line as in the converted data: {lines[0]!r}")
            check(lines[1] == conv.HEADER, f"{src}: header")
            body = [l.split(",") for l in lines[2:]]
            check(len(body) == len(rows), f"{src}: {len(body)} rows, expected {len(rows)}")
            check(all(b[1:] == r[1:] for b, r in zip(body, rows)), f"{src}: every cell equals the excerpt's")
            check(body[5][10:14] == ["nan"] * 4, f"{src}: occluded reference written as nan")
            times_ok = all(b[0] == "%.6f" % (k * 0.0035) for k, b in enumerate(body))
            check(times_ok, f"{src}: t_s = k/sampling_rate")
        # a file without the BROAD arrays is refused with its name
        bad = os.path.join(d, "bad.mat")
        spio.savemat(bad, {"imu_gyr": np.zeros((3, 3))})
        try:
            conv.load(bad)
            check(False, "a file without opt_quat must be refused")
        except ValueError as e:
            check("missing" in str(e) and "bad.mat" in str(e), f"error names the file: {e}")
        # the converted file is what clino's readers expect: parse it back as CSV
        r = subprocess.run(
            [sys.executable, "-c", "import csv,sys; rows=list(csv.reader(l for l in open(sys.argv[1]) if not l.startswith('#'))); print(len(rows[0]))",
             os.path.join(d, "out_data_mat", NAME + ".csv")],
            capture_output=True, text=True)
        check(r.stdout.strip() == "15", f"15 columns, got {r.stdout!r} {r.stderr}")
    print(f"{passed} passed, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
