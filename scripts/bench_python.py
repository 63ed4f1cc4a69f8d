#!/usr/bin/env python3
"""Python throughput of clino against vqf and imufusion, and clino.dask scaling.

    python scripts/bench_python.py [--broad DIR] [--rows N] [--workers 1,2,4]

Run it with a Python where `clino` is installed (`crates/clino-py/ci.sh`
leaves one in /tmp/clino-py-venv; `pip install ./crates/clino-py`); vqf and
imufusion are pip-installed into that environment when missing. Prints
samples/s of

* `clino.fuse` (dynamic, mahony, madgwick) on the same NumPy arrays as
* `vqf.VQF(Ts).updateBatch` (the C++ VQF, 6-D) and `vqf.BasicVQF`,
* `imufusion.Ahrs.update_no_magnetometer` (no batch API: a Python loop),

on BROAD recordings when found (else a simulated one), best of `--repeat`
runs each, interleaved: every round times each batch method once, in turn,
so that a change of machine load during the run touches all of them alike
and the ratios to vqf stay comparable on a shared machine;
then `clino.dask.process(..., "inclination")` on a LocalCluster of 1, 2 and 4
single-threaded worker processes: rows/s over the BROAD recordings and the
overhead per task (many 100-row recordings). Numbers only, no assertions.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def need(*pkgs):
    import importlib.util

    missing = [p for p, mod in pkgs if importlib.util.find_spec(mod) is None]
    if missing:
        subprocess.check_call([sys.executable, "-m", "pip", "install", "-q", *missing])


def interleaved(fns, rounds, clock=time.perf_counter):
    """Best time of each of `fns` (name -> callable) over `rounds` rounds,
    each round calling every one once, in turn."""
    ts = {k: float("inf") for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            t0 = clock()
            fn()
            ts[k] = min(ts[k], clock() - t0)
    return ts


def best(fn, repeat=3):
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        ts.append(time.perf_counter() - t0)
    return min(ts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--broad", default=os.environ.get("CLINO_BROAD_DIR", str(ROOT.parent / "shared" / "data" / "broad")))
    ap.add_argument("--rows", type=int, default=1_000_000, help="rows of the simulated recording when BROAD is absent")
    ap.add_argument("--workers", default="1,2,4")
    ap.add_argument("--repeat", type=int, default=5, help="rounds of the interleaved batch timings (best is kept)")
    ap.add_argument("--clock", choices=["wall", "cpu"], default="wall",
                    help="batch timings by wall clock, or by the CPU time of the calling thread "
                         "(every batch method runs on it): on a shared machine the time the "
                         "thread waited for a core is then left out")
    ap.add_argument("--skip-dask", action="store_true")
    ap.add_argument("--only-dask", action="store_true", help="skip the filter comparison")
    args = ap.parse_args()

    need(("vqf", "vqf"), ("imufusion", "imufusion"), ("pandas", "pandas"), ("distributed", "distributed"), ("fsspec", "fsspec"))
    import numpy as np
    import vqf
    import imufusion
    import clino

    broad = Path(args.broad)
    files = sorted(broad.glob("*.csv")) if broad.is_dir() else []
    if files:
        recs = [clino.read_recording(f) for f in files]
        gyr = np.ascontiguousarray(np.vstack([r["gyr_rad_s"] for r in recs]))
        acc = np.ascontiguousarray(np.vstack([r["acc_m_s2"] for r in recs]))
        # one long recording at BROAD's rate; NaN dropouts as zero motion for the
        # baselines, which take no NaN (clino holds through them either way)
        bad = ~(np.isfinite(gyr).all(1) & np.isfinite(acc).all(1))
        gyr[bad] = 0.0
        acc[bad] = [0.0, 0.0, 9.81]
        rate = 285.714
        what = f"the {len(files)} BROAD recordings end to end ({len(gyr)} rows at {rate} Hz)"
    else:
        s = clino.simulate_static("mpu6050", rate_hz=200.0, duration_s=args.rows / 200.0, seed=1)
        gyr, acc, rate = s["gyr_rad_s"], s["acc_m_s2"], 200.0
        what = f"a simulated MPU-6050 recording ({len(gyr)} rows at 200 Hz)"
    n = len(gyr)
    ts = 1.0 / rate
    if args.only_dask:
        return dask_part(args, files, recs, broad)
    if getattr(clino._clino, "DEBUG_BUILD", False):
        print("# WARNING: the clino extension is a debug build (maturin develop without --release): not representative")
    clock = time.thread_time if args.clock == "cpu" else time.perf_counter
    print(f"# clino Python benchmark on {what}; {os.cpu_count()} CPUs; batch methods interleaved, best of {args.repeat} rounds, {args.clock} clock")
    print(f"{'method':<44} {'samples/s':>12} {'vs vqf batch':>12}")

    batch = {
        "vqf.VQF(Ts).updateBatch (C++, 6-D)": lambda: vqf.VQF(ts).updateBatch(gyr, acc),
        "vqf.BasicVQF(Ts).updateBatch": lambda: vqf.BasicVQF(ts).updateBatch(gyr, acc),
    }
    for spec in ("dynamic", "mahony", "madgwick"):
        batch[f"clino.fuse(filter={spec!r})"] = lambda spec=spec: clino.fuse(gyr, acc, rate=rate, filter=spec)
    batch["clino.fuse_full (tilt + status too)"] = lambda: clino.fuse_full(gyr, acc, rate=rate)
    batch["clino.Dynamic(Ts).updateBatch"] = lambda: clino.Dynamic(ts).updateBatch(gyr, acc)
    results = {k: n / t for k, t in interleaved(batch, args.repeat, clock).items()}

    m = min(n, 100_000)

    def fusion_loop():
        ahrs = imufusion.Ahrs()
        g_deg = np.degrees(gyr[:m])
        a_g = acc[:m] / 9.80665
        if hasattr(ahrs, "set_sample_period"):  # imufusion >= 1.3: period set once
            ahrs.set_sample_period(ts)
            for k in range(m):
                ahrs.update_no_magnetometer(g_deg[k], a_g[k])
        else:
            for k in range(m):
                ahrs.update_no_magnetometer(g_deg[k], a_g[k], ts)

    results[f"imufusion.Ahrs loop (first {m} rows)"] = m / best(fusion_loop, repeat=1)

    def clino_loop():
        f = clino.Dynamic(ts)
        for k in range(m):
            f.update(gyr[k], acc[k])

    results[f"clino.Dynamic.update loop (first {m} rows)"] = m / best(clino_loop, repeat=1)

    base = results["vqf.VQF(Ts).updateBatch (C++, 6-D)"]
    for k, v in results.items():
        print(f"{k:<44} {v:>12.3e} {v / base:>11.2f}×")

    if args.skip_dask or not files:
        return
    dask_part(args, files, recs, broad)


def dask_part(args, files, recs, broad):
    import time
    import clino
    from distributed import Client, LocalCluster
    import clino.dask as cd

    tiny = Path(tempfile.mkdtemp(prefix="clino-bench-"))
    r0 = clino.read_recording(files[0], as_frame=True)
    for i in range(40):
        clino.write_table(tiny / f"t{i:02d}.csv", r0.iloc[:100])
    rows_total = sum(len(r["t_s"]) for r in recs)
    t0 = time.perf_counter()
    cd.process_local(broad, "inclination")
    single = time.perf_counter() - t0
    print(f"\n# clino.dask.process(BROAD, 'inclination'): {len(files)} tasks, {rows_total} rows")
    print(f"{'workers':>7} {'wall s':>8} {'rows/s':>10} {'overhead/task ms':>17}")
    print(f"{'local':>7} {single:>8.2f} {rows_total / single:>10.3e} {'-':>17}")
    for w in [int(x) for x in args.workers.split(",")]:
        with LocalCluster(n_workers=w, threads_per_worker=1, processes=True, dashboard_address=None) as cl, Client(cl) as c:
            c.run(lambda: __import__("clino"))  # import on every worker first
            cd.process(tiny, "inclination", client=c)  # warm-up
            t0 = time.perf_counter()
            cd.process(broad, "inclination", client=c)
            wall = time.perf_counter() - t0
            t0 = time.perf_counter()
            cd.process(tiny, "inclination", client=c)
            per_task = (time.perf_counter() - t0) / 40 * w
            print(f"{w:>7} {wall:>8.2f} {rows_total / wall:>10.3e} {1e3 * per_task:>17.1f}")


if __name__ == "__main__":
    main()
