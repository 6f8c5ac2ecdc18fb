#!/usr/bin/env python3
"""Builds the adversarial cond2 panel of tests/data/cond_adversarial/ (read by
tests/verification/cond_adversarial.rs): inputs made to break a certificate, with exact
references from outside this project's code.

Each case is a stored matrix, written as Matrix Market with every entry in shortest round-trip
form (so it reads back bit for bit), and its sigma_max, sigma_min and cond2 of the *stored*
matrix from mpmath at 40 digits: `svd_r` for the unsymmetric and near-symmetric ones, `eigsy`
(sigma = |lambda|) for the exactly symmetric ones. The classes:

* near-symmetric: SPD but for a small-scale block whose off-diagonal entries are unsymmetric
  by 0.3-30 % of themselves, below the normwise test |a_ij - a_ji| <= 8 eps max|a| (sparse and
  dense routes);
* near-double lambda_min: Q diag(lambda) Q^T with lambda_2 - lambda_1 = 1e-10 and 1e-11
  relative (dense, N = 80), and two copies of a chain whose stiffnesses differ by 1e-11
  (sparse: every eigenvalue a near-double);
* clustered: five eigenvalues within 1e-12 at each end (dense, N = 60);
* start-orthogonal: a mirror-symmetric chain whose lowest mode is antisymmetric (a stiff
  ground spring at the centre lifts the symmetric ones), N = 201, sparse;
* unsymmetric: random dense N = 20, convection-diffusion sparse N = 64;
* indefinite: symmetric random dense N = 30 with eigenvalues of both signs, a shifted
  Laplacian sparse N = 64.

Plain Python and mpmath only (pip install mpmath); a seeded generator (random.Random) makes
the matrices, so the output is reproducible. Takes a few minutes:

    python3 scripts/cond_adversarial.py tests/data/cond_adversarial
"""

import json
import math
import os
import random
import sys

import mpmath

mpmath.mp.dps = 40


def write_mtx(path, a, symmetric, comment):
    n = len(a)
    if symmetric:
        entries = [(i, j, a[i][j]) for j in range(n) for i in range(j, n) if a[i][j] != 0.0]
        kind = "symmetric"
    else:
        entries = [(i, j, a[i][j]) for j in range(n) for i in range(n) if a[i][j] != 0.0]
        kind = "general"
    with open(path, "w") as f:
        f.write(f"%%MatrixMarket matrix coordinate real {kind}\n")
        f.write(f"% {comment}\n")
        f.write(f"{n} {n} {len(entries)}\n")
        for i, j, v in entries:
            f.write(f"{i + 1} {j + 1} {v!r}\n")


def zeros(n):
    return [[0.0] * n for _ in range(n)]


def lower_mirror(a):
    """The exactly symmetric matrix of a's lower triangle (what is stored)."""
    n = len(a)
    return [[a[max(i, j)][min(i, j)] for j in range(n)] for i in range(n)]


def random_orthogonal(n, rng):
    """Q of a modified Gram-Schmidt QR of a Gaussian matrix, twice (orthogonal to ~1e-15)."""
    cols = [[rng.gauss(0.0, 1.0) for _ in range(n)] for _ in range(n)]
    for _ in range(2):
        for k in range(n):
            v = cols[k]
            for q in cols[:k]:
                d = sum(x * y for x, y in zip(v, q))
                v = [x - d * y for x, y in zip(v, q)]
            nv = math.sqrt(sum(x * x for x in v))
            cols[k] = [x / nv for x in v]
    return cols  # columns


def spectral(n, lam, rng):
    """Q diag(lam) Q^T in double, stored as its lower triangle mirrored."""
    q = random_orthogonal(n, rng)
    a = zeros(n)
    for i in range(n):
        for j in range(i + 1):
            a[i][j] = math.fsum(q[k][i] * lam[k] * q[k][j] for k in range(n))
    return lower_mirror(a)


def chain(n, k_spring, ground):
    """Springs k_spring between neighbours, ground[i] to the ground: tridiagonal SPD."""
    a = zeros(n)
    for i in range(n - 1):
        for p, q, v in ((i, i, k_spring), (i + 1, i + 1, k_spring), (i, i + 1, -k_spring), (i + 1, i, -k_spring)):
            a[p][q] += v
    for i in range(n):
        a[i][i] += ground[i]
    return a


def near_symmetric(n, m, scale, rel):
    """A chain of n - m unit springs, then m springs of stiffness `scale`, joined by one
    spring of `scale`; the small block's upper off-diagonals multiplied by (1 + rel)."""
    a = zeros(n)
    for i in range(n - 1):
        k = 1.0 if i < n - m - 1 else scale
        a[i][i] += k
        a[i + 1][i + 1] += k
        a[i][i + 1] -= k
        a[i + 1][i] -= k
    a[0][0] += 1.0
    a[n - 1][n - 1] += scale
    for i in range(n - m, n - 1):
        a[i][i + 1] *= 1.0 + rel
    amax = max(abs(x) for row in a for x in row)
    worst = max(abs(a[i][j] - a[j][i]) for i in range(n) for j in range(n))
    assert 0.0 < worst <= 8 * 2.0 ** -52 * amax, (worst, amax)
    return a


def reference(a, symmetric):
    m = mpmath.matrix(a)
    if symmetric:
        s = sorted(abs(x) for x in mpmath.eigsy(m, eigvals_only=True))
    else:
        s = sorted(abs(x) for x in mpmath.svd_r(m, compute_uv=False))
    return s[-1], s[0], s[1] if len(s) > 1 else s[0]


def cases():
    rng = random.Random(44)
    out = []
    # Near-symmetric: the perturbation at the normwise test's edge (3e-15 absolute).
    for name, n, m, scale in [
        ("nearsym-sparse-s1e-14", 64, 8, 1e-14),
        ("nearsym-sparse-s1e-13", 64, 8, 1e-13),
        ("nearsym-sparse-s1e-12", 64, 8, 1e-12),
        ("nearsym-dense-s1e-14", 12, 4, 1e-14),
        ("nearsym-dense-s1e-13", 12, 4, 1e-13),
    ]:
        rel = min(0.3, 3e-15 / scale)
        out.append((name, near_symmetric(n, m, scale, rel), False, "near-symmetric"))
    # Near-double lambda_min, dense.
    for gap in (1e-10, 1e-11):
        n = 80
        lam = [1.0, 1.0 + gap] + [2.0 * 10 ** (3.0 * k / (n - 3)) for k in range(n - 2)]
        out.append((f"neardouble-dense-gap{gap:.0e}", spectral(n, lam, rng), True, "near-double"))
    # Near-double, sparse: two chains whose springs differ by 1e-11 relative.
    n1 = 40
    a = zeros(2 * n1)
    for b, f in ((0, 1.0), (1, 1.0 + 1e-11)):
        c = chain(n1, f, [1e-3 * f] * n1)
        for i in range(n1):
            for j in range(n1):
                a[b * n1 + i][b * n1 + j] = c[i][j]
    out.append(("neardouble-sparse-chains", a, True, "near-double"))
    # Clustered ends, dense.
    n = 60
    lam = [1.0 + k * 1e-12 for k in range(5)] + [1e3 * (1.0 + k * 1e-12) for k in range(5)]
    lam += [1.5 * 10 ** (2.5 * k / (n - 11)) for k in range(n - 10)]
    out.append(("clustered-dense", spectral(n, lam, rng), True, "clustered"))
    # Start-orthogonal: mirror-symmetric chain, stiff ground spring at the centre.
    n = 201
    ground = [1e-3] * n
    ground[n // 2] = 1e3
    out.append(("antisymmetric-lowest-chain", chain(n, 1.0, ground), True, "start-orthogonal"))
    # Unsymmetric.
    n = 20
    a = [[rng.gauss(0.0, 1.0) + (5.0 if i == j else 0.0) for j in range(n)] for i in range(n)]
    out.append(("unsymmetric-dense", a, False, "unsymmetric"))
    n, c = 64, 0.3
    a = zeros(n)
    for i in range(n):
        a[i][i] = 2.0
        if i > 0:
            a[i][i - 1] = -1.0 - c
        if i + 1 < n:
            a[i][i + 1] = -1.0 + c
    out.append(("unsymmetric-sparse-convection", a, False, "unsymmetric"))
    # Indefinite.
    n = 30
    lam = [(-1.0) ** k * (1.0 + k) for k in range(n)]
    out.append(("indefinite-dense", spectral(n, lam, rng), True, "indefinite"))
    n = 64
    a = chain(n, 1.0, [0.0] * n)
    a[0][0] += 1.0
    for i in range(n):
        a[i][i] -= 1.3
    out.append(("indefinite-sparse-shifted", a, True, "indefinite"))
    return out


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "tests/data/cond_adversarial"
    os.makedirs(out, exist_ok=True)
    panel = []
    for name, a, symmetric, kind in cases():
        path = os.path.join(out, name + ".mtx")
        write_mtx(path, a, symmetric, f"cond_adversarial.py: {kind}")
        smax, smin, s2 = reference(a, symmetric)
        nstr = lambda x: mpmath.nstr(x, 30, strip_zeros=False)  # noqa: E731
        panel.append(
            {
                "case": name,
                "class": kind,
                "matrix": name + ".mtx",
                "n": len(a),
                "engine": "mpmath-40 " + ("eigsy" if symmetric else "svd_r"),
                "sigma_max": nstr(smax),
                "sigma_min": nstr(smin),
                "sigma_2": nstr(s2),
                "cond2": nstr(smax / smin),
            }
        )
        print(name, panel[-1]["cond2"], file=sys.stderr, flush=True)
    with open(os.path.join(out, "panel.json"), "w") as f:
        json.dump({"source": "scripts/cond_adversarial.py", "cases": panel}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
