#!/usr/bin/env python3
"""One batch call on 200 000 BROAD rows, for instruction counts under callgrind.

    valgrind --tool=callgrind python scripts/callgrind_python.py fuse [DIR]
    valgrind --tool=callgrind python scripts/callgrind_python.py vqf  [DIR]

Then compare the inclusive cost of `_clino.fuse` (or `Pipeline.update_batch`)
with that of vqf's `updateBatch` in `callgrind_annotate --inclusive=yes`.
Needs a Python with `clino` (crates/clino-py), `vqf` and `numpy` installed,
e.g. the venv of crates/clino-py/ci.sh (target/py-venv) plus `pip install vqf`.
"""
import glob
import os
import sys

import numpy as np

ROWS = 200_000
RATE = 285.714286  # BROAD's sample rate, Hz


def arrays(folder):
    gyr, acc, n = [], [], 0
    for path in sorted(glob.glob(os.path.join(folder, "*.csv"))):
        with open(path) as f:
            lines = [ln for ln in f if not ln.startswith("#")]
        names = lines[0].strip().split(",")
        d = np.loadtxt(lines[1:], delimiter=",")
        col = {n: i for i, n in enumerate(names)}
        gyr.append(d[:, [col[f"gyr_{a}_rad_s"] for a in "xyz"]])
        acc.append(d[:, [col[f"acc_{a}_m_s2"] for a in "xyz"]])
        n += len(d)
        if n >= ROWS:
            break
    g, a = np.concatenate(gyr)[:ROWS], np.concatenate(acc)[:ROWS]
    return np.ascontiguousarray(g), np.ascontiguousarray(a)


def main():
    what = sys.argv[1] if len(sys.argv) > 1 else "fuse"
    folder = sys.argv[2] if len(sys.argv) > 2 else os.path.join(
        os.path.dirname(__file__), "..", "..", "shared", "data", "broad")
    gyr, acc = arrays(folder)
    if what == "fuse":
        import clino
        clino.fuse(gyr, acc, rate=RATE, filter="dynamic")
    elif what == "full":
        import clino
        clino.fuse_full(gyr, acc, rate=RATE)
    elif what == "vqf":
        import vqf
        vqf.VQF(1.0 / RATE).updateBatch(gyr, acc)
    else:
        sys.exit(f"unknown {what!r}: fuse, full or vqf")


if __name__ == "__main__":
    main()
