#!/usr/bin/env python3
"""Baseline for folder_bench.py's benchmark: what a plain NumPy script pays for the work of one
`sweep` over a folder of scene files (scripts/folder_bench.sh runs both in one go and prints the
table).

Per scene: read the JSON (K stored dense), u0 = K⁻¹q, cond₂(K) by `eigvalsh`, log|det K| by
`slogdet`; then per system of the sweep's rows (1 lagrange saddle [K D; Dᵀ 0], 13 `constant`
ε, 2 δ for `paper` and 2 for `condensed`): `np.linalg.solve`, `eigvalsh` (cond₂ = max|λ| /
min|λ|) and `slogdet` of the system matrix. The penalty systems use one solve each with every
constraint active, and simple δ-driven penalties (ε_c = K_cc·max(|g0_c|/δ − 1, 1)), so the
script does *less* work than the sweep (no active-set iterations, no exact δ targeting): the
measured ratio is a lower bound of the real one.

Not part of the build or the tests. Needs numpy (`pip install numpy`).

usage: numpy_sweep.py SCENE_DIR [EPS_LO EPS_HI EPS_N] [DELTA_REL ...]
prints one JSON line: {"scenes": .., "systems": .., "seconds": .., "read_seconds": ..}
"""
import glob
import json
import os
import sys
import time

import numpy as np


def systems_of(k, q, dofs, limits, eps_grid, deltas_rel):
    n, m = k.shape[0], len(dofs)
    u0 = np.linalg.solve(k, q)
    ev = np.linalg.eigvalsh(k)
    cond_k = np.abs(ev).max() / np.abs(ev).min()
    _, logdet_k = np.linalg.slogdet(k)
    d = np.zeros((n, m))
    d[dofs, np.arange(m)] = 1.0
    yield np.block([[k, d], [d.T, np.zeros((m, m))]]), np.concatenate([q, limits])
    for eps in eps_grid:
        a = k.copy()
        a[dofs, dofs] += eps
        b = q.copy()
        b[dofs] += eps * limits
        yield a, b
    g0 = np.abs(u0[dofs] - limits)
    scale = np.abs(u0[dofs]).max() or 1.0
    for _method in ("paper", "condensed"):
        for r in deltas_rel:
            delta = r * scale
            e = np.diag(k)[dofs] * np.maximum(g0 / delta - 1.0, 1.0)
            a = k.copy()
            a[dofs, dofs] += e
            b = q.copy()
            b[dofs] += e * limits
            yield a, b
    del cond_k, logdet_k


def main():
    folder = sys.argv[1]
    lo, hi, npts = (float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4])) if len(sys.argv) > 4 else (1e-2, 1e10, 13)
    deltas_rel = [float(x) for x in sys.argv[5:]] or [1e-2, 1e-3]
    eps_grid = np.logspace(np.log10(lo), np.log10(hi), npts)
    files = sorted(glob.glob(os.path.join(folder, "*.scene.json")))
    if not files:
        sys.exit(f"no *.scene.json in {folder}")
    t0 = time.perf_counter()
    read = 0.0
    systems = 0
    for f in files:
        t = time.perf_counter()
        with open(f) as fh:
            s = json.load(fh)
        k = np.array(s["stiffness"]["dense"], dtype=float)
        q = np.array(s["load"], dtype=float)
        dofs = np.array([c["dof"] for c in s["constraints"]], dtype=int)
        limits = np.array([c["limit"] for c in s["constraints"]], dtype=float)
        read += time.perf_counter() - t
        for a, b in systems_of(k, q, dofs, limits, eps_grid, deltas_rel):
            np.linalg.solve(a, b)
            ev = np.linalg.eigvalsh(a)
            np.abs(ev).max() / np.abs(ev).min()
            np.linalg.slogdet(a)
            systems += 1
    print(json.dumps({"scenes": len(files), "systems": systems,
                      "seconds": time.perf_counter() - t0, "read_seconds": read}))


if __name__ == "__main__":
    main()
