#!/usr/bin/env python3
"""The AMG evaluation, second round: plane-strain elasticity with a contact penalty,
plus the PyAMG reference numbers for every system that `cargo run --release` also solves.

Elasticity systems: bilinear Q4 plane strain (E = 210e3, nu = 0.3, unit thickness, 2x2 Gauss)
on the unit square cut into n x n square elements (n = 32, 64, 128); DOFs (u, v) interleaved
per node, node-major, nodes numbered row by row from the base (node = i + (n+1) j at
x = i/n, y = j/n); the base nodes (y = 0) are clamped and eliminated, which keeps the free
DOFs node-interleaved (block size 2). A penalty eps = 100 max(diag K) is added on the v-DOF
of the top nodes (y = 1) with 1/3 <= x <= 2/3; b is a downward unit load (-1 on v) on every
top node. Written to data/elastic{n}_A.mtx, data/elastic{n}_b.mtx and data/elastic{n}_B.mtx
(the three rigid-body modes (1,0), (0,1), (-y,x) on the free DOFs, one column each).

PyAMG: smoothed_aggregation_solver(A, B=B) with its default options (A passed as CSR, as the
brief asks), then ml.solve(b, x0=0, tol=1e-8, accel='cg'); PyAMG's CG stops on the
unpreconditioned ||r||_2 < 1e-8 ||b||_2 (criteria='rr'). Iterations = len(residuals) - 1.
A second PyAMG row passes A as BSR with 2x2 blocks (PyAMG's nodal mode) for reference.
The membranes (data/membrane*_*.mtx, written by membrane_systems.py) get B = ones.
Results are printed and written to data/pyamg_results.json.

    pip install numpy scipy pyamg
    python3 membrane_systems.py && python3 elasticity_systems.py && cargo run --release
"""
import json
import os
import time

import numpy as np
import pyamg
import scipy.io
import scipy.sparse as sp

E, NU = 210e3, 0.3


def q4_plane_strain_stiffness(h):
    """8x8 stiffness of a square h x h Q4 element, nodes (0,0),(h,0),(h,h),(0,h), DOFs
    (u0,v0,u1,v1,...), unit thickness, 2x2 Gauss."""
    c = E / ((1 + NU) * (1 - 2 * NU))
    d = c * np.array([[1 - NU, NU, 0], [NU, 1 - NU, 0], [0, 0, (1 - 2 * NU) / 2]])
    xi_n = np.array([-1, 1, 1, -1])
    eta_n = np.array([-1, -1, 1, 1])
    g = 1 / np.sqrt(3)
    ke = np.zeros((8, 8))
    for xi in (-g, g):
        for eta in (-g, g):
            dn_dxi = xi_n * (1 + eta_n * eta) / 4
            dn_deta = eta_n * (1 + xi_n * xi) / 4
            # the map is x = h (xi + 1) / 2: J = diag(h/2, h/2)
            dn_dx, dn_dy = dn_dxi * 2 / h, dn_deta * 2 / h
            bm = np.zeros((3, 8))
            bm[0, 0::2] = dn_dx
            bm[1, 1::2] = dn_dy
            bm[2, 0::2] = dn_dy
            bm[2, 1::2] = dn_dx
            ke += bm.T @ d @ bm * (h / 2) ** 2
    return ke


def elastic_system(n):
    h = 1.0 / n
    nn = n + 1
    ke = q4_plane_strain_stiffness(h)
    rows, cols, vals = [], [], []
    for j in range(n):
        for i in range(n):
            nodes = [i + nn * j, i + 1 + nn * j, i + 1 + nn * (j + 1), i + nn * (j + 1)]
            dofs = np.array([[2 * q, 2 * q + 1] for q in nodes]).ravel()
            rows.append(np.repeat(dofs, 8))
            cols.append(np.tile(dofs, 8))
            vals.append(ke.ravel())
    ndof = 2 * nn * nn
    k = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(ndof, ndof)).tocsr()
    k.sum_duplicates()
    node = np.arange(nn * nn)
    x = (node % nn) * h
    y = (node // nn) * h
    top = node // nn == n
    mid = top & (x >= 1 / 3 - 1e-12) & (x <= 2 / 3 + 1e-12)
    eps = 100 * k.diagonal().max()
    pen = np.zeros(ndof)
    pen[2 * node[mid] + 1] = eps
    b = np.zeros(ndof)
    b[2 * node[top] + 1] = -1.0
    rbm = np.zeros((ndof, 3))
    rbm[0::2, 0] = 1.0
    rbm[1::2, 1] = 1.0
    rbm[0::2, 2] = -y
    rbm[1::2, 2] = x
    free_nodes = node[node // nn > 0]
    free = np.sort(np.concatenate([2 * free_nodes, 2 * free_nodes + 1]))
    a = (k + sp.diags(pen)).tocsr()[free][:, free].tocsr()
    a.sort_indices()
    return a, b[free], rbm[free], int(mid.sum()), eps


def run_pyamg(a, b, bmodes):
    res = []
    t0 = time.perf_counter()
    ml = pyamg.smoothed_aggregation_solver(a, B=bmodes)
    t1 = time.perf_counter()
    xs = ml.solve(b, x0=np.zeros_like(b), tol=1e-8, accel="cg", residuals=res, maxiter=1000)
    t2 = time.perf_counter()
    rel = np.linalg.norm(b - a @ xs) / np.linalg.norm(b)
    return {
        "iterations": len(res) - 1,
        "setup_s": t1 - t0,
        "solve_s": t2 - t1,
        "relres": float(rel),
        "levels": len(ml.levels),
        "operator_complexity": float(ml.operator_complexity()),
    }


def main():
    os.makedirs("data", exist_ok=True)
    results = []
    for side in [63, 127, 255]:
        pa = f"data/membrane{side}_A.mtx"
        if not os.path.exists(pa):
            print(f"{pa} missing: run membrane_systems.py first; skipped")
            continue
        a = scipy.io.mmread(pa).tocsr()
        b = scipy.io.mmread(f"data/membrane{side}_b.mtx").ravel()
        r = run_pyamg(a, b, np.ones((a.shape[0], 1)))
        results.append({"system": f"membrane{side}", "N": a.shape[0], "variant": "csr, B=ones", **r})
    for n in [32, 64, 128]:
        a, b, bm, nmid, eps = elastic_system(n)
        scipy.io.mmwrite(f"data/elastic{n}_A.mtx", a, symmetry="general")
        scipy.io.mmwrite(f"data/elastic{n}_b.mtx", b.reshape(-1, 1))
        scipy.io.mmwrite(f"data/elastic{n}_B.mtx", bm)
        asym = abs(a - a.T).max()
        print(f"elastic{n}: N={a.shape[0]} nnz={a.nnz} penalised top nodes={nmid} "
              f"eps={eps:.4g} max|A-A^T|={asym:.1e}")
        r = run_pyamg(a, b, bm)
        results.append({"system": f"elastic{n}", "N": a.shape[0], "variant": "csr, B=RBM", **r})
        r = run_pyamg(a.tobsr(blocksize=(2, 2)), b, bm)
        results.append({"system": f"elastic{n}", "N": a.shape[0], "variant": "bsr 2x2, B=RBM", **r})
    print(f"{'system':<12}{'N':>8}  {'PyAMG variant':<16}{'iters':>6}{'setup s':>9}"
          f"{'solve s':>9}{'relres':>10}{'levels':>7}{'op.cx':>7}")
    for r in results:
        print(f"{r['system']:<12}{r['N']:>8}  {r['variant']:<16}{r['iterations']:>6}"
              f"{r['setup_s']:>9.3f}{r['solve_s']:>9.3f}{r['relres']:>10.1e}"
              f"{r['levels']:>7}{r['operator_complexity']:>7.2f}")
    meta = {"pyamg": pyamg.__version__, "numpy": np.__version__, "scipy": scipy.__version__,
            "tol": 1e-8, "criterion": "unpreconditioned ||r||_2 < tol ||b||_2, x0 = 0"}
    with open("data/pyamg_results.json", "w") as f:
        json.dump({"meta": meta, "results": results}, f, indent=1)


if __name__ == "__main__":
    main()
