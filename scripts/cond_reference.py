#!/usr/bin/env python3
"""High-precision reference condition numbers of stored scene matrices (independent of Rust).

For a scene file (the `solve` contract: dense rows or Matrix Market) and optional penalties
(one per constraint, as `solve --json` prints them), forms the *stored* matrix exactly in
IEEE double -- K, K + D E D^T (diagonal entries K_dd + eps_c, one rounding, as the library
assembles them), or the saddle point [K D; D^T 0] of the DOFs given -- and encloses its
eigenvalues with python-flint (Arb ball arithmetic, `acb_mat.eig`, 256-bit working
precision): every printed value is the midpoint of a ball whose radius is printed beside it,
so the reference is proven, not estimated; where Arb cannot isolate clustered eigenvalues
(many penalized DOFs of equal K_dd + eps) it falls back to mpmath's `eigsy` at 40 digits
(`--engine mpmath` forces it; it is what the earlier accuracy measurements used).
sigma = |lambda| (symmetric matrices), and cond2 = max|lambda| / min|lambda|.

    pip install python-flint numpy
    python3 scripts/cond_reference.py SCENE.scene.json [--penalties '[0, 1e11, ...]'] \
        [--saddle-dofs 3,7] [--numpy]

prints one JSON object: n, sigma_max, sigma_min, cond2 (decimal strings, 30 digits), their
radii, and with --numpy the NumPy `cond(A, 2)` (LAPACK SVD) and its relative error.
"""

import argparse
import json
import os
import sys

import flint


def read_matrix_market(path):
    with open(path) as f:
        header = f.readline().lower().split()
        symmetric = "symmetric" in header
        line = f.readline()
        while line.startswith("%"):
            line = f.readline()
        n, ncols, nnz = (int(x) for x in line.split())
        assert n == ncols, "square matrices only"
        a = [[0.0] * n for _ in range(n)]
        for _ in range(nnz):
            i, j, v = f.readline().split()
            i, j, v = int(i) - 1, int(j) - 1, float(v)
            a[i][j] += v
            if symmetric and i != j:
                a[j][i] += v
    return a


def read_scene(path):
    with open(path) as f:
        scene = json.load(f)
    st = scene["stiffness"]
    if "dense" in st:
        k = [[float(x) for x in row] for row in st["dense"]]
    else:
        k = read_matrix_market(os.path.join(os.path.dirname(path), st["matrix_market"]))
    return scene, k


def enclose(a, prec=256):
    """Balls of max|lambda| and min|lambda| of the symmetric matrix a (exact entries), or
    None where Arb cannot isolate the eigenvalues."""
    flint.ctx.prec = prec
    m = flint.acb_mat(flint.arb_mat(a))
    try:
        ev = m.eig(nonstop=True)
    except ValueError:
        return None
    mags = sorted((abs(e.real) for e in ev), key=lambda x: float(x.mid()))
    if not all(x.is_finite() and float(x.rad()) <= 1e-30 * float(abs(x.mid())) for x in mags):
        return None
    return mags[-1], mags[0]


def eigsy_40(a):
    """max|lambda|, min|lambda| from mpmath's symmetric eigensolver at 40 digits."""
    import mpmath

    mpmath.mp.dps = 40
    ev = sorted(abs(x) for x in mpmath.eigsy(mpmath.matrix(a), eigvals_only=True))
    return ev[-1], ev[0]


def dec(x, digits=30):
    if isinstance(x, flint.arb):
        return x.mid().str(digits, radius=False)
    import mpmath

    return mpmath.nstr(x, digits, strip_zeros=False)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--penalties", help="JSON list, one per constraint (0 = unpenalized)")
    ap.add_argument("--saddle-dofs", help="comma-separated DOFs of [K D; D^T 0]")
    ap.add_argument("--numpy", action="store_true", help="also NumPy's cond(A, 2)")
    ap.add_argument("--engine", choices=["flint", "mpmath"], default="flint")
    args = ap.parse_args()
    scene, a = read_scene(args.scene)
    n = len(a)
    if args.penalties:
        eps = json.loads(args.penalties)
        cons = scene["constraints"]
        assert len(eps) == len(cons), "one penalty per constraint"
        for c, e in zip(cons, eps):
            if e:
                d = c["dof"]
                a[d][d] = a[d][d] + float(e)
    if args.saddle_dofs:
        dofs = [int(x) for x in args.saddle_dofs.split(",")]
        m = len(dofs)
        big = [[0.0] * (n + m) for _ in range(n + m)]
        for i in range(n):
            big[i][:n] = a[i]
        for c, d in enumerate(dofs):
            big[d][n + c] = 1.0
            big[n + c][d] = 1.0
        a = big
    balls = enclose(a) if args.engine == "flint" else None
    if balls is not None:
        smax, smin = balls
        cond = smax / smin
        engine, radius = "python-flint (Arb) 256 bits", float(cond.rad()) / float(cond.mid())
    else:
        smax, smin = eigsy_40(a)
        cond = smax / smin
        engine, radius = "mpmath eigsy 40 digits", None
    out = {
        "scene": scene.get("name"),
        "n": len(a),
        "engine": engine,
        "sigma_max": dec(smax),
        "sigma_min": dec(smin),
        "cond2": dec(cond),
        "cond2_radius_rel": radius,
    }
    if args.numpy:
        import numpy as np

        c = float(np.linalg.cond(np.array(a), 2))
        out["numpy_cond2"] = c
        exact = float(cond.mid()) if isinstance(cond, flint.arb) else float(cond)
        out["numpy_rel_error"] = abs(c / exact - 1.0)
    json.dump(out, sys.stdout)
    print()


if __name__ == "__main__":
    main()
