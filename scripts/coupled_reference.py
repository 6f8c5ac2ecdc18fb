#!/usr/bin/env python3
"""Scenes with coupled constraint rows and their independent references.

Writes small contact scenes whose constraints are rows g_c = sum_j a_cj u_j - u^_c with several
terms (a normal on an inclined plane, node-to-segment rows between two bodies, mortar-like rows
that share DOFs, and single-DOF rows beside them), and computes for each, with NumPy only and
without any of penalty-lab's code:

- lagrange: the exact contact solution, min 1/2 u^T K u - q^T u subject to the rows, found by
  enumerating every active set (m <= 8) and keeping the one that satisfies the KKT conditions
  (primal feasibility of the inactive rows, multiplier signs of the active ones); its u, the
  active set and cond(A, 2) of its saddle-point matrix [K D_A; D_A^T 0] (LAPACK SVD);
- constant eps: the minimizer of the penalized energy 1/2 u^T K u - q^T u
  + sum_c 1/2 eps pi_c(g_c)^2 (pi_c: the gap if bilateral, its violated part if unilateral),
  found by enumerating the penalized sets and keeping the consistent one; u and
  cond(K + D_P eps D_P^T, 2);
- scaled f: the same with eps_c = f d_c^T K d_c / |d_c|^4 (the penalty's stiffness along the
  row f times K's);
The node-to-segment scene stores K and D as Matrix Market files (D: one row per constraint).

- condensed delta: the exact delta-targeting solution, the QP with every row in the box
  g_c <= delta (upper), g_c >= -delta (lower), |g_c| <= delta (bilateral), by enumerating the
  states (free, at -delta, at +delta); its u.

    pip install numpy
    python3 scripts/coupled_reference.py --out tests/data/coupled

Every number is written in Python's shortest round-trip form, so the Rust test reads K, q and
the rows bit for bit. `tests/verification/coupled.rs` compares.
"""

import argparse
import itertools
import json
import math
import os

import numpy as np

SEED = 20261128


def truss(nx, ny, width, height, k_axial, ground, x0=0.0, y0=0.0):
    """A plane truss of nx x ny nodes (2 DOFs each: x, y) with horizontal, vertical and
    diagonal bars of axial stiffness k_axial; the bottom row (ground='bottom') or the top row
    (ground='top') held by springs of stiffness 10 k_axial in x and y. Returns K, coordinates."""
    n_nodes = nx * ny
    coords = np.array(
        [[x0 + width * i / (nx - 1), y0 + height * j / (ny - 1)] for j in range(ny) for i in range(nx)]
    )
    k = np.zeros((2 * n_nodes, 2 * n_nodes))

    def bar(a, b):
        e = coords[b] - coords[a]
        e = e / np.linalg.norm(e)
        ke = k_axial * np.outer(e, e)
        for (p, sp), (r, sr) in itertools.product([(a, 1.0), (b, -1.0)], repeat=2):
            k[2 * p : 2 * p + 2, 2 * r : 2 * r + 2] += sp * sr * ke

    node = lambda i, j: j * nx + i
    for j in range(ny):
        for i in range(nx):
            if i + 1 < nx:
                bar(node(i, j), node(i + 1, j))
            if j + 1 < ny:
                bar(node(i, j), node(i, j + 1))
            if i + 1 < nx and j + 1 < ny:
                bar(node(i, j), node(i + 1, j + 1))
                bar(node(i + 1, j), node(i, j + 1))
    held = range(nx) if ground == "bottom" else range((ny - 1) * nx, ny * nx)
    for p in held:
        k[2 * p, 2 * p] += 10 * k_axial
        k[2 * p + 1, 2 * p + 1] += 10 * k_axial
    return k, coords


def block_diag(a, b):
    n, m = a.shape[0], b.shape[0]
    out = np.zeros((n + m, n + m))
    out[:n, :n] = a
    out[n:, n:] = b
    return out


def scene_inclined(rng):
    """One truss pushed up against a rigid plane inclined by theta (15, 30, 45 degrees over
    three top nodes): rows n^T u_i <= gap with n = (-sin theta, cos theta), two terms each."""
    nx, ny = 4, 3
    k, xy = truss(nx, ny, 3.0, 2.0, 100.0, "bottom")
    n = k.shape[0]
    q = np.zeros(n)
    top = [(ny - 1) * nx + i for i in range(nx)]
    for p in top:
        q[2 * p + 1] = 40.0 + 10.0 * rng.random()
        q[2 * p] = 5.0 * (rng.random() - 0.5)
    rows = []
    for p, theta in zip(top[1:], [15.0, 30.0, 45.0]):
        t = math.radians(theta)
        rows.append(([(2 * p, -math.sin(t)), (2 * p + 1, math.cos(t))], 0.05, "upper"))
    rows.append(([(2 * top[0] + 1, 1.0)], 0.12, "upper"))  # a single-DOF row beside them
    return "inclined", k, q, rows, False


def scene_nts(rng):
    """Two trusses with non-matching top/bottom node spacing (4 against 3 nodes across): the
    lower body pushed up into the upper one (held at its top). Node-to-segment rows: a slave
    node of the lower body's top against the master segment of the upper body's bottom,
    g = n.(u_s - (1 - xi) u_m1 - xi u_m2) <= gap0, n = (0, 1) or slightly tilted (3 or 6
    terms). K block-diagonal, written as Matrix Market."""
    k1, xy1 = truss(4, 3, 3.0, 1.0, 80.0, "bottom")
    k2, xy2 = truss(3, 2, 3.0, 1.0, 120.0, "top", y0=1.05)
    n1 = k1.shape[0]
    k = block_diag(k1, k2)
    q = np.zeros(k.shape[0])
    slaves = [2 * 4 + i for i in range(4)]  # top row of body 1 (nx = 4, ny = 3)
    masters = [i for i in range(3)]  # bottom row of body 2 (nx = 3)
    for p in slaves:
        q[2 * p + 1] = 30.0 + 10.0 * rng.random()
    rows = []
    for s in slaves:
        x = xy1[s, 0]
        seg = min(int(x // 1.5), 1)
        m1, m2 = masters[seg], masters[seg + 1]
        xi = (x - xy2[m1, 0]) / (xy2[m2, 0] - xy2[m1, 0])
        gap0 = xy2[m1, 1] - xy1[s, 1]
        if s % 2 == 0:
            nrm = (0.0, 1.0)
        else:
            t = math.radians(10.0)
            nrm = (-math.sin(t), math.cos(t))
        terms = []
        for comp in range(2):
            if nrm[comp] == 0.0:
                continue
            terms.append((2 * s + comp, nrm[comp]))
            terms.append((n1 + 2 * m1 + comp, -(1.0 - xi) * nrm[comp]))
            terms.append((n1 + 2 * m2 + comp, -xi * nrm[comp]))
        terms = [(d, a) for d, a in terms if a != 0.0]
        rows.append((terms, gap0, "upper"))
    return "nts", k, q, rows, True


def scene_mixed(rng):
    """One truss with mortar-like rows (weights of overlapping shape-function products, rows
    sharing DOFs), a coupled bilateral tie, a lower row and single-DOF rows, with coefficients
    far from 1."""
    nx, ny = 5, 3
    k, xy = truss(nx, ny, 4.0, 2.0, 60.0, "bottom")
    n = k.shape[0]
    q = 20.0 * (rng.random(n) - 0.3)
    top = [(ny - 1) * nx + i for i in range(nx)]
    rows = []
    for i in range(3):
        a, b, c = top[i], top[i + 1], top[i + 2]
        w = [0.25 + 0.1 * rng.random(), 0.5 + 0.2 * rng.random(), 0.25 + 0.1 * rng.random()]
        rows.append(([(2 * a + 1, w[0]), (2 * b + 1, w[1]), (2 * c + 1, w[2])], 0.02, "upper"))
    mid = nx + 2
    rows.append(([(2 * mid, 3.0), (2 * top[4], -3.0)], 0.01, "bilateral"))
    rows.append(([(2 * (nx + 1) + 1, -2.5), (2 * (nx + 3) + 1, 0.5)], -0.3, "lower"))
    rows.append(([(2 * top[4] + 1, 1.0)], 0.05, "upper"))
    return "mixed", k, q, rows, False


# ---------------------------------------------------------------------------------------------
# References
# ---------------------------------------------------------------------------------------------


def dmat(rows, n):
    d = np.zeros((n, len(rows)))
    for c, (terms, _, _) in enumerate(rows):
        for j, a in terms:
            d[j, c] = a
    return d


def kkt(k, q, d, limits, idx):
    n = k.shape[0]
    na = len(idx)
    a = np.zeros((n + na, n + na))
    a[:n, :n] = k
    a[:n, n:] = d[:, idx]
    a[n:, :n] = d[:, idx].T
    b = np.concatenate([q, limits[idx]])
    x = np.linalg.solve(a, b)
    return x[:n], x[n:], a


def box_qp(k, q, rows, lo, hi):
    """min 1/2 u^T K u - q^T u s.t. lo_c <= g_c <= hi_c, by enumerating the states of every
    row (free, at lo, at hi); the unique KKT point. Returns u, states, saddle matrix."""
    n = k.shape[0]
    d = dmat(rows, n)
    limits = np.array([r[1] for r in rows])
    m = len(rows)
    choices = []
    for c in range(m):
        opts = []
        if lo[c] == hi[c]:
            opts = ["lo"]
        else:
            opts = ["free"] + (["lo"] if np.isfinite(lo[c]) else []) + (["hi"] if np.isfinite(hi[c]) else [])
        choices.append(opts)
    scale = np.abs(np.linalg.solve(k, q)).max() + 1.0
    found = []
    for states in itertools.product(*choices):
        idx = [c for c in range(m) if states[c] != "free"]
        target = np.array([limits[c] + (lo[c] if states[c] == "lo" else hi[c]) for c in idx])
        full = limits.copy()
        full[idx] = target
        u, lam, a = kkt(k, q, d, full, idx) if idx else (np.linalg.solve(k, q), np.zeros(0), k)
        g = d.T @ u - limits
        tol = 1e-10 * scale
        ok = all(lo[c] - tol <= g[c] <= hi[c] + tol for c in range(m))
        for j, c in enumerate(idx):
            if lo[c] == hi[c]:
                continue
            # K u + D lam = q: at the upper bound the force pushes g down (lam >= 0), at the
            # lower bound up (lam <= 0).
            if states[c] == "hi" and lam[j] < -tol:
                ok = False
            if states[c] == "lo" and lam[j] > tol:
                ok = False
        if ok:
            found.append((u, states, a))
    assert found, "no KKT point"
    u0 = found[0][0]
    for u, _, _ in found[1:]:
        assert np.abs(u - u0).max() <= 1e-8 * np.abs(u0).max(), "two different KKT points"
    return found[0]


def penalized(k, q, rows, eps):
    """Minimizer of the penalized energy with per-row penalties eps, by enumerating the
    penalized set of the unilateral rows."""
    n = k.shape[0]
    m = len(rows)
    free = [c for c in range(m) if rows[c][2] != "bilateral"]
    best = None
    for bits in itertools.product([False, True], repeat=len(free)):
        on = [True] * m
        for c, b in zip(free, bits):
            on[c] = b
        a = k.copy()
        b = q.copy()
        for c in range(m):
            if on[c]:
                dc = np.zeros(n)
                for j, v in rows[c][0]:
                    dc[j] = v
                a += eps[c] * np.outer(dc, dc)
                b += eps[c] * rows[c][1] * dc
        u = np.linalg.solve(a, b)
        ok = True
        for c in free:
            g = sum(v * u[j] for j, v in rows[c][0]) - rows[c][1]
            viol = g > 0 if rows[c][2] == "upper" else g < 0
            if viol != on[c] and abs(g) > 1e-12 * (abs(rows[c][1]) + 1):
                ok = False
        if ok:
            assert best is None or np.abs(best[0] - u).max() <= 1e-9 * np.abs(u).max()
            best = (u, a)
    assert best is not None
    return best


def row_stiffness(k, terms):
    dc = np.zeros(k.shape[0])
    for j, v in terms:
        dc[j] = v
    n2 = dc @ dc
    return (dc @ k @ dc) / (n2 * n2)


def shortest(x):
    return float(repr(float(x)))


def write_scene(out, name, k, q, rows, mtx):
    n = k.shape[0]
    scene = {"name": name, "description": "coupled constraint rows (scripts/coupled_reference.py)"}
    if mtx:
        path = os.path.join(out, f"{name}.mtx")
        with open(path, "w") as f:
            entries = [(i, j, k[i, j]) for j in range(n) for i in range(j, n) if k[i, j] != 0.0]
            f.write("%%MatrixMarket matrix coordinate real symmetric\n")
            f.write(f"{n} {n} {len(entries)}\n")
            for i, j, v in entries:
                f.write(f"{i + 1} {j + 1} {repr(float(v))}\n")
        scene["stiffness"] = {"matrix_market": f"{name}.mtx"}
    else:
        scene["stiffness"] = {"dense": [[shortest(v) for v in row] for row in k]}
    scene["load"] = [shortest(v) for v in q]
    if mtx:
        # D as Matrix Market too: row c = constraint c, its terms in order.
        path = os.path.join(out, f"{name}.D.mtx")
        with open(path, "w") as f:
            entries = [(c, j, a) for c, (terms, _, _) in enumerate(rows) for j, a in terms]
            f.write("%%MatrixMarket matrix coordinate real general\n")
            f.write(f"{len(rows)} {n} {len(entries)}\n")
            for c, j, a in entries:
                f.write(f"{c + 1} {j + 1} {repr(float(a))}\n")
        scene["constraints"] = {
            "matrix_market": f"{name}.D.mtx",
            "limits": [shortest(r[1]) for r in rows],
            "kinds": [r[2] for r in rows],
        }
        with open(os.path.join(out, f"{name}.scene.json"), "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")
        return
    scene["constraints"] = []
    for terms, limit, kind in rows:
        if len(terms) == 1 and terms[0][1] == 1.0:
            scene["constraints"].append({"dof": terms[0][0], "limit": shortest(limit), "kind": kind})
        else:
            scene["constraints"].append(
                {"terms": [[j, shortest(a)] for j, a in terms], "limit": shortest(limit), "kind": kind}
            )
    with open(os.path.join(out, f"{name}.scene.json"), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="tests/data/coupled")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rng = np.random.default_rng(SEED)
    refs = []
    for make in [scene_inclined, scene_nts, scene_mixed]:
        name, k, q, rows, mtx = make(rng)
        # Round everything to what the scene file stores.
        k = np.vectorize(shortest)(k)
        k = 0.5 * (k + k.T)  # exactly symmetric already; guards the Matrix Market triangle
        q = np.vectorize(shortest)(q)
        rows = [([(j, shortest(a)) for j, a in t], shortest(l), kind) for t, l, kind in rows]
        write_scene(args.out, name, k, q, rows, mtx)
        m = len(rows)
        inf = float("inf")
        side = {"upper": (-inf, 0.0), "lower": (0.0, inf), "bilateral": (0.0, 0.0)}
        lo = [side[r[2]][0] for r in rows]
        hi = [side[r[2]][1] for r in rows]
        u_l, states, a_l = box_qp(k, q, rows, lo, hi)
        ref = {
            "scene": f"{name}.scene.json",
            "lagrange": {
                "u": u_l.tolist(),
                "active": [c for c in range(m) if states[c] != "free"],
                "cond2": float(np.linalg.cond(a_l, 2)),
            },
        }
        kdiag_scale = float(np.exp(np.mean(np.log([row_stiffness(k, r[0]) for r in rows]))))
        for f in [1e-1, 1e1, 1e3]:
            eps = [f * kdiag_scale] * m
            u, a = penalized(k, q, rows, eps)
            ref.setdefault("constant", []).append(
                {"eps": shortest(eps[0]), "u": u.tolist(), "cond2": float(np.linalg.cond(a, 2))}
            )
        for f in [0.5, 100.0]:
            eps = [f * row_stiffness(k, r[0]) for r in rows]
            u, a = penalized(k, q, rows, eps)
            ref.setdefault("scaled", []).append(
                {"factor": f, "u": u.tolist(), "cond2": float(np.linalg.cond(a, 2))}
            )
        u0 = np.linalg.solve(k, q)
        dscale = max(abs(sum(a * u0[j] for j, a in r[0])) for r in rows)
        for rel in [1e-1, 1e-3]:
            delta = shortest(rel * dscale)
            box = {"upper": (-inf, delta), "lower": (-delta, inf), "bilateral": (-delta, delta)}
            lo = [box[r[2]][0] for r in rows]
            hi = [box[r[2]][1] for r in rows]
            u, _, _ = box_qp(k, q, rows, lo, hi)
            ref.setdefault("condensed", []).append({"delta": delta, "u": u.tolist()})
        refs.append(ref)
        print(name, "n =", k.shape[0], "m =", m, "active (lagrange) =", ref["lagrange"]["active"])
    with open(os.path.join(args.out, "reference.json"), "w") as f:
        json.dump({"generator": "scripts/coupled_reference.py", "seed": SEED, "scenes": refs}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
