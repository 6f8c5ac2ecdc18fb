#!/usr/bin/env python3
"""Issue 10's side-by-side benchmark: `sweep` against a plain NumPy script on a folder of
scene files with every K stored dense, timed in one run.

    cargo build --release --bin sweep && python3 scripts/folder_bench.py [OUT]

1. Writes the folder (scripts/folder.toml: 10 beams of 36–336 DOFs, 10 membranes of
   100–400 DOFs) with `sweep --write-scenes DIR --dense-scenes`.
2. Times, `REPEATS` times each and interleaved, `sweep --scenes-dir` with 1 and 2 threads
   (13 ε, 2 relative δ for constant, paper, condensed; cond and det), and
   scripts/numpy_sweep.py with OpenBLAS's default threads and with one thread.
3. Prints a Markdown table of the medians and writes OUT/folder_bench.json (the scene folder
   and the sweep outputs live in a temporary folder, removed at the end).

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
REPEATS = 5


def sweep(args):
    t = time.perf_counter()
    subprocess.run([SWEEP, "--config", CONFIG, "--no-figures", "--quiet", *args], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t


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
    inner = {}
    for _ in range(REPEATS):
        for t in (1, 2):
            times[f"sweep {t} thread{'s' if t > 1 else ''}"].append(
                sweep(["--scenes-dir", scenes, "--threads", str(t), "--out", os.path.join(scratch, f"t{t}")]))
        for label, threads in (("numpy (OpenBLAS default threads)", None), ("numpy (1 thread)", 1)):
            wall, report = numpy_run(scenes, threads)
            times[label].append(wall)
            inner[label] = report
    med = {k: statistics.median(v) for k, v in times.items()}
    manifest = json.load(open(os.path.join(scratch, "t2", "manifest.json")))
    rows = manifest["rows_written"]
    print(f"| run ({rows} rows, {inner['numpy (1 thread)']['systems']} NumPy systems) | median wall (s) "
          f"of {REPEATS} | NumPy default / this |")
    print("|---|---:|---:|")
    base = med["numpy (OpenBLAS default threads)"]
    for k, v in med.items():
        print(f"| {k} | {v:.3f} | {base / v:.1f}× |")
    print(f"\n2 threads vs 1 thread: {med['sweep 1 thread'] / med['sweep 2 threads']:.2f}×")
    shutil.rmtree(scratch)
    json.dump({"medians_seconds": med, "all_seconds": times, "numpy_inner": inner,
               "sweep_manifest_timing": manifest.get("timing"), "git_commit": manifest.get("git_commit")},
              open(os.path.join(out, "folder_bench.json"), "w"), indent=1)


if __name__ == "__main__":
    main()
