#!/usr/bin/env python3
"""Score PyPI `vqf` (real-time 6-D and offline) on BROAD-format recordings, exactly as `clino eval` scores.

Usage: scripts/vqf_baseline.py [DIR_OR_CSV ...] [--json]
Installs `vqf` and `numpy` into a private virtual environment under
${CLINO_PYENV:-/tmp/clino-pyenv} on first use (registry access needed once).

Scoring (BROAD's): error quaternion q_est ⊗ q_ref* (navigation frame),
inclination error 2·acos(√(w² + z²)), RMSE in degrees over samples with
movement = 1 and a finite reference.
"""
import json
import os
import subprocess
import sys
import time

ENV = os.environ.get("CLINO_PYENV", "/tmp/clino-pyenv")


def ensure_env():
    py = os.path.join(ENV, "bin", "python")
    if not os.path.exists(py):
        subprocess.check_call([sys.executable, "-m", "venv", ENV])
    try:
        subprocess.check_call([py, "-c", "import vqf, numpy"], stderr=subprocess.DEVNULL)
    except subprocess.CalledProcessError:
        subprocess.check_call([py, "-m", "pip", "install", "-q", "vqf>=2,<3", "numpy"])
    return py


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    want_json = "--json" in sys.argv
    if os.environ.get("CLINO_IN_ENV") != "1":
        py = ensure_env()
        env = dict(os.environ, CLINO_IN_ENV="1")
        os.execve(py, [py, os.path.abspath(__file__)] + sys.argv[1:], env)

    import numpy as np
    from vqf import VQF, offlineVQF

    paths = []
    for a in args or [os.path.join(os.path.dirname(__file__), "..", "..", "shared", "data", "broad")]:
        if os.path.isdir(a):
            paths += sorted(os.path.join(a, f) for f in os.listdir(a) if f.endswith(".csv"))
        else:
            paths.append(a)

    def score(q, ref, mov):
        # q_est ⊗ conj(q_ref)
        w1, x1, y1, z1 = q.T
        w2, x2, y2, z2 = ref[:, 0], -ref[:, 1], -ref[:, 2], -ref[:, 3]
        w = w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2
        z = w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2
        ok = (mov == 1) & np.all(np.isfinite(ref), axis=1)
        e = 2 * np.arccos(np.clip(np.sqrt(w[ok] ** 2 + z[ok] ** 2), -1, 1))
        return float(np.degrees(np.sqrt(np.mean(e ** 2))))

    rows = []
    total_samples = 0
    total_time = 0.0
    for p in paths:
        with open(p) as f:
            lines = [l for l in f if not l.startswith("#")]
        header = lines[0].strip().split(",")
        d = np.genfromtxt(lines[1:], delimiter=",")
        col = {n: i for i, n in enumerate(header)}
        t = d[:, col["t_s"]]
        gyr = np.ascontiguousarray(d[:, [col["gyr_x_rad_s"], col["gyr_y_rad_s"], col["gyr_z_rad_s"]]])
        acc = np.ascontiguousarray(d[:, [col["acc_x_m_s2"], col["acc_y_m_s2"], col["acc_z_m_s2"]]])
        ref = d[:, [col["ref_qw"], col["ref_qx"], col["ref_qy"], col["ref_qz"]]]
        mov = d[:, col["movement"]]
        ts = float(np.median(np.diff(t)))
        t0 = time.perf_counter()
        q = VQF(ts).updateBatch(gyr, acc)["quat6D"]
        total_time += time.perf_counter() - t0
        total_samples += len(t)
        qo = offlineVQF(gyr, acc, None, ts)["quat6D"]
        rows.append({"recording": os.path.basename(p), "vqf": score(q, ref, mov), "offline_vqf": score(qo, ref, mov)})
    mean = {k: float(np.mean([r[k] for r in rows])) for k in ("vqf", "offline_vqf")}
    speed = total_samples / total_time if total_time > 0 else float("nan")
    if want_json:
        print(json.dumps({"recordings": rows, "mean": mean, "vqf_batch_samples_per_s": speed}, indent=2))
    else:
        print(f"{'recording':<48}{'vqf':>10}{'offlineVQF':>12}")
        for r in rows:
            print(f"{r['recording']:<48}{r['vqf']:>10.3f}{r['offline_vqf']:>12.3f}")
        print(f"{'MEAN':<48}{mean['vqf']:>10.3f}{mean['offline_vqf']:>12.3f}")
        print(f"VQF(Ts).updateBatch throughput: {speed / 1e6:.2f} M samples/s")


if __name__ == "__main__":
    main()
