#!/usr/bin/env python3
"""Re-stamp a clino CSV recording as a host receiving it would: each row's
time made late by 0-8 ms (exponential, mean 2 ms, cut at 8 ms), never before
the row before. Comment lines and the header pass through unchanged.

    python3 scripts/host_stamps.py IN.csv OUT.csv [--seed 1]

Used for the BROAD figures of `--stamps` in BENCHMARKS.md (standard library
only; the first column must be the time in seconds).
"""
import argparse
import math
import random


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    random.seed(a.seed)
    last = -1e9
    out = []
    with open(a.src, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for line in lines:
        cells = line.split(",")
        try:
            t = float(cells[0])
        except ValueError:
            out.append(line)  # comment, header, empty last line
            continue
        late = min(-0.002 * math.log(1.0 - random.random()), 0.008)
        stamp = max(t + late, last + 1e-6)
        last = stamp
        cells[0] = repr(stamp)
        out.append(",".join(cells))
    with open(a.dst, "w", encoding="utf-8") as f:
        f.write("\n".join(out))


if __name__ == "__main__":
    main()
