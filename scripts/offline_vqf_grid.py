#!/usr/bin/env python3
"""Offline VQF beside clino's offline smoother on the generalisation grid.

`vqf-rs`, the harness's baseline, has no offline smoother; PyPI `vqf` has
(`offlineVQF`). The harness writes its simulated recordings and its own
scores of them:

    cargo run --release -p clino-bench --example generalise -- --export DIR
    scripts/offline_vqf_grid.py DIR [--json]

For every recording in DIR/index.csv this runs PyPI `vqf` (real-time `VQF`,
6-D, and `offlineVQF`, both with their defaults and the file's sample
period) and scores them as the harness and `clino eval` do: error
quaternion q_est ⊗ q_ref*, inclination error 2·acos(√(w² + z²)), RMSE over
the samples with movement = 1 (and, at rest, over those with rest = 1).
Per condition it prints the means of offline VQF and of clino's offline
smoother, the ratio of the means and the worst per-recording ratio; then
PyPI VQF's real-time figure beside vqf-rs's (the two ports should agree:
a check that the export and the scoring are the harness's).

Installs `vqf` and `numpy` into the scripts' private environment
(scripts/_venv.py, ${CLINO_SCRIPTS_VENV:-/tmp/clino-scripts-venv}).
"""
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from _venv import ensure_venv  # noqa: E402


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    want_json = "--json" in sys.argv
    if len(args) != 1:
        sys.exit("usage: scripts/offline_vqf_grid.py DIR [--json]  (DIR from generalise --export)")
    ensure_venv(["vqf>=2,<3", "numpy"])
    import numpy as np
    from vqf import VQF, offlineVQF

    d = args[0]
    index_path = os.path.join(d, "index.csv")
    with open(index_path, newline="") as f:
        index = list(csv.DictReader(f))
    if not index:
        sys.exit(f"{index_path}: no recordings listed")

    def rmse(q, ref, mask):
        w1, x1, y1, z1 = q.T
        w2, x2, y2, z2 = ref[:, 0], -ref[:, 1], -ref[:, 2], -ref[:, 3]
        w = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2
        z = w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2
        ok = mask & np.all(np.isfinite(ref), axis=1)
        if not ok.any():
            return float("nan")
        e = 2 * np.arccos(np.clip(np.sqrt(w[ok] ** 2 + z[ok] ** 2), -1, 1))
        return float(np.degrees(np.sqrt(np.mean(e ** 2))))

    rows = []
    for i, entry in enumerate(index):
        path = os.path.join(d, entry["file"])
        data = np.genfromtxt(path, delimiter=",", names=True)
        t = data["t_s"]
        gyr = np.ascontiguousarray(np.column_stack([data[f"gyr_{a}_rad_s"] for a in "xyz"]))
        acc = np.ascontiguousarray(np.column_stack([data[f"acc_{a}_m_s2"] for a in "xyz"]))
        ref = np.column_stack([data[f"ref_q{a}"] for a in "wxyz"])
        mov = data["movement"] == 1
        rest = data["rest"] == 1
        # the harness's nominal period: the median interval
        ts = float(np.median(np.diff(t)))
        qo = offlineVQF(gyr, acc, None, ts)["quat6D"]
        v = VQF(ts)
        qr = v.updateBatch(gyr, acc)["quat6D"]
        row = {
            "file": entry["file"],
            "condition": entry["condition"],
            "offline_vqf": rmse(qo, ref, mov),
            "offline_clino": float(entry["offline_deg"]),
            "vqf_pypi": rmse(qr, ref, mov),
            "vqf_rs": float(entry["vqf_rs_deg"]),
            "dynamic": float(entry["dynamic_deg"]),
            "offline_vqf_rest": rmse(qo, ref, rest),
        }
        rows.append(row)
        print(f"\r{i + 1}/{len(index)} {entry['file']:<60}", end="", file=sys.stderr, flush=True)
    print(file=sys.stderr)

    conditions = []
    for r in rows:
        if r["condition"] not in conditions:
            conditions.append(r["condition"])
    table = []
    for c in conditions:
        rs = [r for r in rows if r["condition"] == c]
        m = {k: float(np.mean([r[k] for r in rs])) for k in ("offline_vqf", "offline_clino", "vqf_pypi", "vqf_rs")}
        worst = max(r["offline_clino"] / r["offline_vqf"] for r in rs)
        table.append({"condition": c, "n": len(rs), **m, "ratio": m["offline_clino"] / m["offline_vqf"], "worst": worst})
    if want_json:
        print(json.dumps({"conditions": table, "recordings": rows}, indent=1))
        return
    print(f"{'condition (recordings)':<40}{'offlineVQF °':>13}{'clino off °':>12}{'ratio':>7}{'worst':>7}"
          f"{'VQF PyPI °':>12}{'vqf-rs °':>10}")
    for r in table:
        print(f"{r['condition'] + ' (' + str(r['n']) + ')':<40}{r['offline_vqf']:>13.3f}{r['offline_clino']:>12.3f}"
              f"{r['ratio']:>7.2f}{r['worst']:>7.2f}{r['vqf_pypi']:>12.3f}{r['vqf_rs']:>10.3f}")
    print(f"{'largest ratio of the means':<40}{'':>25}{max(r['ratio'] for r in table):>7.2f}"
          f"{max(r['worst'] for r in table):>7.2f}")


if __name__ == "__main__":
    main()
