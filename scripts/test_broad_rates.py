#!/usr/bin/env python3
"""Test scripts/broad_rates.py: its decimation, its scores and its flags.

On the repository's excerpt of BROAD trial 07 (crates/clino/data/
broad_07_excerpt.csv) and on closed forms:
- a factor of 1 gives the trial back; a factor of 3 gives the block means,
  stamped at their mean, and the middle sample's reference;
- the unaligned score is the quaternion inclination error (against the
  angle between gravity directions, computed independently), a reference
  the estimate lags by exactly one sample scores near 0 aligned and not
  unaligned, and an estimate that is not finite on a scored sample makes
  the score NaN instead of a score over the samples left;
- a missing column and a bad cell stop it naming the file, row and column;
- end to end (clino fuse and PyPI vqf), `--aligned` and `--factors` change
  the table.
Runs in the scripts' venv (numpy, vqf). Prints "N passed, 0 failed".
"""
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from _venv import ensure_venv  # noqa: E402

ensure_venv(["vqf>=2,<3", "numpy"])
import numpy as np  # noqa: E402
import broad_rates as br  # noqa: E402

EXCERPT = os.path.join(HERE, "..", "crates", "clino", "data", "broad_07_excerpt.csv")
passed = failed = 0


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
        print(f"FAILED: {what}")


def exits_with(f, *needles):
    try:
        f()
    except SystemExit as e:
        return all(n in str(e.code) for n in needles)
    return False


d = br.read_trial(EXCERPT)
n = len(d)
one = br.decimate(d, 1)
check(all(np.array_equal(one[c], d[c][:n], equal_nan=True) for c in d.dtype.names), "factor 1 is the trial")
three = br.decimate(d, 3)
k = 10
check(abs(three["t_s"][k] - d["t_s"][3 * k:3 * k + 3].mean()) < 1e-12, "stamped at the block's mean")
check(abs(three["gyr_x_rad_s"][k] - d["gyr_x_rad_s"][3 * k:3 * k + 3].mean()) < 1e-12, "the gyro averaged")
check(np.array_equal(three["ref_qw"][k], d["ref_qw"][3 * k + 1], equal_nan=True), "the middle sample's reference")
check(len(three["t_s"]) == n // 3, "a third of the samples")
try:
    br.decimate(d, 2)
    check(False, "an even factor is refused")
except ValueError:
    check(True, "")

# scores against independent values
ref = np.column_stack([one[f"ref_q{a}"] for a in "wxyz"])
ok = np.all(np.isfinite(ref), axis=1)
mask = (one["movement"] == 1) & ok
# the estimate: the reference tilted by 2° about the horizontal east axis
# (left-multiplied: a navigation-frame turn), an inclination error of 2° at
# every sample whatever the attitude
c, s = np.cos(np.radians(1.0)), np.sin(np.radians(1.0))
w, x, y, z = ref.T
est = np.column_stack([c * w - s * x, c * x + s * w, c * y - s * z, c * z + s * y])
got = br.rmse(est, ref, mask)
check(abs(got - 2.0) < 1e-6, f"a 2° tilt about the east axis scores 2° ({got})")
check(abs(br.rmse(est, ref, mask, aligned=True) - 2.0) < 0.05, "and about 2° aligned")
ue, ur = br.up(est), br.up(ref)
indep = np.degrees(np.sqrt(np.mean(np.arccos(np.clip((ue * ur).sum(1), -1, 1))[mask] ** 2)))
check(abs(got - indep) < 1e-6, f"the quaternion error's inclination is the gravity directions' angle ({got}, {indep})")
# an estimate one sample late: near 0 aligned, not unaligned
late = np.vstack([ref[:1], ref[:-1]])
late_ok = mask & np.all(np.isfinite(late), axis=1)
plain, best = br.rmse(late, ref, late_ok), br.rmse(late, ref, late_ok, aligned=True)
check(plain > 0.1 and best < 1e-5, f"one sample late: {plain}° as stamped, {best}° aligned")
# a NaN estimate on a scored sample: NaN, never the rest's score
bad = est.copy()
bad[np.flatnonzero(mask)[5]] = np.nan
check(np.isnan(br.rmse(bad, ref, mask)), "a NaN estimate scores NaN")
check(np.isnan(br.rmse(bad, ref, mask, aligned=True)), "a NaN estimate scores NaN aligned")
check(np.isnan(br.rmse(est, ref, np.zeros(len(ref), bool))), "no scored sample scores NaN")

# bad input names the file, row and column
with tempfile.TemporaryDirectory() as tmp:
    lines = [line for line in open(EXCERPT) if not line.startswith("#")]
    p = os.path.join(tmp, "nocol.csv")
    with open(p, "w") as fh:
        fh.write(lines[0].replace("movement", "moved") + "".join(lines[1:10]))
    check(exits_with(lambda: br.read_trial(p), p, "movement"), "a missing column is named")
    p = os.path.join(tmp, "cell.csv")
    cells = lines[5].split(",")
    cells[4] = "abc"
    with open(p, "w") as fh:
        fh.write("".join(lines[:5]) + ",".join(cells) + "".join(lines[6:10]))
    check(exits_with(lambda: br.read_trial(p), p, "row 5", "acc_x_m_s2", "abc"), "a bad cell is named")
    p = os.path.join(tmp, "empty.csv")
    open(p, "w").close()
    check(exits_with(lambda: br.read_trial(p), p), "an empty file is refused")

    # end to end: the flags change the table
    trials = os.path.join(tmp, "trials")
    os.mkdir(trials)
    with open(os.path.join(trials, "07_excerpt.csv"), "w") as fh:
        fh.write("".join(lines))

    def table(*flags):
        r = subprocess.run([sys.executable, os.path.join(HERE, "broad_rates.py"), trials, *flags],
                           capture_output=True, text=True)
        rows = [line.split() for line in r.stdout.splitlines() if line[:1].isdigit()]
        return r.returncode, rows

    rc, plain_rows = table("--factors", "1,3")
    check(rc == 0 and [r[0] for r in plain_rows] == ["1", "3"], f"two factors, two rows ({rc}, {plain_rows})")
    rc, aligned_rows = table("--factors", "1,3", "--aligned")
    check(rc == 0 and len(aligned_rows) == 2, "aligned: two rows")
    if len(plain_rows) == 2 and len(aligned_rows) == 2:
        # aligned never scores worse than as stamped (the stamped shift is one of those tried)
        for p_row, a_row in zip(plain_rows, aligned_rows):
            check(float(a_row[3]) <= float(p_row[3]) + 1e-3 and float(a_row[4]) <= float(p_row[4]) + 1e-3,
                  f"aligned ≤ as stamped ({a_row} against {p_row})")
        check(plain_rows != aligned_rows, "--aligned changes the table")
        check(abs(float(plain_rows[1][1]) - 285.714286 / 3) < 0.5, "factor 3: a third of the rate")
    rc, _ = table("--factors", "2")
    check(rc != 0, "an even factor is refused")

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
