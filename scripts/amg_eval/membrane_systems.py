#!/usr/bin/env python3
"""The AMG evaluation, first data point: penalized membrane systems (5-point Laplacian
on side x side interior nodes of the unit square, a constant penalty 1e2*K_dd on the nodes
within r^2 < 0.1 of the centre, b as the `constant` rule builds it) written to data/ as Matrix
Market, then solved by PyAMG's smoothed aggregation (CG acceleration, rtol 1e-8, x0 = 0):
iterations, setup and solve seconds, the true relative residual. `cargo run --release` in this
folder then solves the same files with kryst's AMG (its default options) and Jacobi.

    pip install numpy scipy pyamg
    python3 membrane_systems.py && cargo run --release
"""
import os
import time

import numpy as np
import pyamg
import scipy.io
import scipy.sparse as sp

os.makedirs("data", exist_ok=True)
for side in [63, 127, 255]:
    n = side * side
    t = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(side, side))
    k = (sp.kron(t, sp.identity(side)) + sp.kron(sp.identity(side), t)).tocsr()
    h = 1.0 / (side + 1)
    x = (np.arange(side) + 1) * h
    xx, yy = np.meshgrid(x, x, indexing="ij")
    r2 = ((xx - 0.5) ** 2 + (yy - 0.5) ** 2).ravel()
    eps = np.where(r2 < 0.1, 1e2 * 4.0, 0.0)
    a = (k + sp.diags(eps)).tocsr()
    b = -10 * h * h * np.ones(n) + eps * (-0.35 - 0.7 * r2)
    scipy.io.mmwrite(f"data/membrane{side}_A.mtx", a, symmetry="general")
    scipy.io.mmwrite(f"data/membrane{side}_b.mtx", b.reshape(-1, 1))
    res = []
    t0 = time.perf_counter()
    ml = pyamg.smoothed_aggregation_solver(a, max_coarse=10)
    t1 = time.perf_counter()
    xs = ml.solve(b, tol=1e-8, accel="cg", residuals=res, maxiter=1000)
    t2 = time.perf_counter()
    rel = np.linalg.norm(b - a @ xs) / np.linalg.norm(b)
    print(f"{side} n={n} PyAMG SA: iterations {len(res) - 1} setup {t1 - t0:.3f} s "
          f"solve {t2 - t1:.3f} s relres {rel:.2e}")
