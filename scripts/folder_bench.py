#!/usr/bin/env python3
"""The side-by-side benchmark: `sweep` against a plain NumPy script on a folder of
scene files with every K stored dense, timed in one run.

    cargo build --release --bin sweep && python3 scripts/folder_bench.py [OUT]

1. Writes the folder (scripts/folder.toml: 10 beams of 36–336 DOFs, 10 membranes of
   100–400 DOFs) with `sweep --write-scenes DIR --dense-scenes`.
2. Times `ROUNDS` rounds, each of `SWEEPS` runs of `sweep --scenes-dir` with 1 and 2
   threads alternating (13 ε, 2 relative δ for constant, paper, condensed; cond and det),
   then scripts/numpy_sweep.py with OpenBLAS's default threads and with one thread.
3. Prints a Markdown table of the medians over all runs, and the ratios paired by round
   (median over rounds of: 1-thread / 2-thread sweep, NumPy / 2-thread sweep, each sweep
   side the round's median): this VM's speed drifts by up to 40 % over seconds, and runs
   side by side share its state of the moment; the thread ratio is given both for the
   process wall and for the runs' own `wall_seconds` (manifest: without process start and
   exit, ≈ 3 ms of each run); and the fastest run of each kind. Writes OUT/folder_bench.json (the scene
   folder and the sweep outputs live in a temporary folder, removed at the end).

Not part of the build or the tests. Needs numpy.
"""
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SWEEP = os.path.join(ROOT, "target", "release", "sweep")
CONFIG = os.path.join(ROOT, "scripts", "folder.toml")
ROUNDS = 11
SWEEPS = 3


def sweep(args):
    t = time.perf_counter()
    subprocess.run([SWEEP, "--config", CONFIG, "--no-figures", "--quiet", *args], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t


def timed_sweep(scenes, threads, out):
    """(process wall, the run's own `wall_seconds` from its manifest) of one sweep."""
    wall = sweep(["--scenes-dir", scenes, "--threads", str(threads), "--out", out])
    return wall, json.load(open(os.path.join(out, "manifest.json")))["wall_seconds"]


def numpy_run(scenes, threads):
    env = dict(os.environ)
    if threads:
        env["OPENBLAS_NUM_THREADS"] = str(threads)
    t = time.perf_counter()
    out = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "numpy_sweep.py"), scenes],
                         check=True, capture_output=True, text=True, env=env).stdout
    return time.perf_counter() - t, json.loads(out)


def main():
    out = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "results", "folder_bench"))
    os.makedirs(out, exist_ok=True)
    scratch = tempfile.mkdtemp(prefix="folder_bench_")  # scenes and the sweep's outputs
    scenes = os.path.join(scratch, "scenes")
    sweep(["--metrics", "none", "--out", os.path.join(scratch, "gen"), "--write-scenes", scenes,
           "--dense-scenes"])
    times = {"sweep 1 thread": [], "sweep 2 threads": [], "numpy (OpenBLAS default threads)": [],
             "numpy (1 thread)": []}
    own = {"sweep 1 thread": [], "sweep 2 threads": []}  # manifests' wall_seconds
    rounds = []
    inner = {}
    for _ in range(ROUNDS):
        one, two, own1, own2 = [], [], [], []
        for _ in range(SWEEPS):
            for threads, walls, owns in ((1, one, own1), (2, two, own2)):
                wall, inside = timed_sweep(scenes, threads, os.path.join(scratch, f"t{threads}"))
                walls.append(wall)
                owns.append(inside)
        times["sweep 1 thread"] += one
        times["sweep 2 threads"] += two
        own["sweep 1 thread"] += own1
        own["sweep 2 threads"] += own2
        numpy = {}
        for label, threads in (("numpy (OpenBLAS default threads)", None), ("numpy (1 thread)", 1)):
            wall, report = numpy_run(scenes, threads)
            times[label].append(wall)
            numpy[label] = wall
            inner[label] = report
        m1, m2 = statistics.median(one), statistics.median(two)
        rounds.append({"sweep_1_thread": m1, "sweep_2_threads": m2,
                       "threads_speedup": m1 / m2,
                       "threads_speedup_in_process": statistics.median(own1) / statistics.median(own2),
                       "numpy_over_sweep_2_threads": numpy["numpy (OpenBLAS default threads)"] / m2})
    med = {k: statistics.median(v) for k, v in times.items()}
    manifest = json.load(open(os.path.join(scratch, "t2", "manifest.json")))
    rows = manifest["rows_written"]
    print(f"| run ({rows} rows, {inner['numpy (1 thread)']['systems']} NumPy systems) | median wall (s) "
          f"of {len(times['sweep 1 thread'])} / {ROUNDS} | NumPy default / this |")
    print("|---|---:|---:|")
    base = med["numpy (OpenBLAS default threads)"]
    for k, v in med.items():
        print(f"| {k} | {v:.3f} | {base / v:.1f}× |")
    paired = {}
    for key, label in (("numpy_over_sweep_2_threads", "NumPy / 2-thread sweep"),
                       ("threads_speedup", "2 threads vs 1 thread"),
                       ("threads_speedup_in_process",
                        "2 threads vs 1 thread, the runs' own wall_seconds (no process start/exit)")):
        vals = [r[key] for r in rounds]
        paired[key] = {"median": statistics.median(vals), "min": min(vals), "max": max(vals)}
        print(f"\n{label}, paired by round: {statistics.median(vals):.2f}× "
              f"(rounds {min(vals):.2f}–{max(vals):.2f}×)")
    # The fastest run of each: the least disturbed by this VM's neighbours (as `timeit` reports).
    best = {k: min(v) for k, v in times.items()}
    print(f"\nFastest of each: 1 thread {best['sweep 1 thread']:.4f} s, 2 threads "
          f"{best['sweep 2 threads']:.4f} s ({best['sweep 1 thread'] / best['sweep 2 threads']:.2f}×), "
          f"NumPy {best['numpy (OpenBLAS default threads)']:.3f} s "
          f"({best['numpy (OpenBLAS default threads)'] / best['sweep 2 threads']:.1f}× the 2-thread sweep)")
    shutil.rmtree(scratch)
    json.dump({"medians_seconds": med, "fastest_seconds": best, "all_seconds": times,
               "manifest_wall_seconds": own, "rounds": rounds, "paired": paired,
               "numpy_inner": inner,
               "sweep_manifest_timing": manifest.get("timing"), "git_commit": manifest.get("git_commit")},
              open(os.path.join(out, "folder_bench.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
