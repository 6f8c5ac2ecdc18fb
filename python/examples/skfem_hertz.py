"""Hertz contact in plane strain, assembled in scikit-fem, solved by penalty_lab.

A rigid cylinder (R = 10) is pressed into an elastic block (E = 210e3, ν = 0.3; a 16a × 16a
block, modelled as its half x ≥ 0 with u_x = 0 on the symmetry line and the base clamped).
Bilinear quadrilaterals, element size h = a/16 on [0, 1.5a] under the contact, growing by 1.25
beyond. The cylinder's surface is y = H − w + x²/(2R); the rows are the top nodes' gaps:

- ``vertical``: one DOF per row, u_y ≤ x²/(2R) − w;
- ``normal``: two terms per row, along the cylinder's normal at the node,
  (−f′·u_x + u_y)/√(1 + f′²) ≤ (f − w)/√(1 + f′²), f = x²/(2R).

For a load P per unit thickness Hertz gives p0 = √(P E*/(π R)), a = √(4 P R/(π E*)),
E* = E/(1 − ν²). The indentation w is set so that Lagrange's load gives a = 1; every rule then
runs at that w, and its p0 (the axis node's force over its tributary length h/2) is compared
with Hertz's p0 for the load it carries. Also cond₂ of K (certified) and of each final system.
Every rule but ``optimal`` runs (``optimal`` takes ≈ 2 min at these 3 157 DOFs: add it to
``rules`` to see it).

    pip install ./python scikit-fem
    python python/examples/skfem_hertz.py            # a table; exit status 1 if p0 misses by > 3 %
"""

import sys

import numpy as np
import scipy.sparse as sp
from skfem import Basis, ElementQuad1, ElementVector, MeshQuad, asm
from skfem.models.elasticity import lame_parameters, linear_elasticity

import penalty_lab

E, NU, R, A = 210e3, 0.3, 10.0, 1.0
E_STAR = E / (1 - NU**2)


def graded(length, h, fine, growth=1.25):
    """Nodes on [0, length]: spacing h on [0, fine], then growing by `growth`."""
    xs = list(np.arange(0.0, fine + 0.5 * h, h))
    step = h
    while xs[-1] < length:
        step *= growth
        xs.append(min(length, xs[-1] + step))
    if length - xs[-2] < 0.5 * (xs[-2] - xs[-3]):
        xs.pop(-2)  # no sliver at the end
    return np.array(xs)


def model(h=A / 16):
    """K (free DOFs), the top nodes' x, their free u_x and u_y indices, and H."""
    width = height = 8.0 * A * 2  # the 16a block: half-width 8a, height 16a
    xs = graded(width / 2, h, 1.5 * A)
    ys_from_top = graded(height, h, 1.5 * A)
    ys = height - ys_from_top[::-1]
    mesh = MeshQuad.init_tensor(xs, ys)
    basis = Basis(mesh, ElementVector(ElementQuad1()))
    lam, mu = lame_parameters(E, NU)
    K = asm(linear_elasticity(lam, mu), basis)
    dofs = basis.get_dofs()
    p = mesh.p
    fixed = np.concatenate([
        basis.get_dofs(lambda x: np.isclose(x[1], 0.0)).all(),  # clamped base
        basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).nodal["u^1"],  # symmetry: u_x = 0
    ])
    free = np.setdiff1d(np.arange(basis.N), fixed)
    index = -np.ones(basis.N, dtype=np.int64)
    index[free] = np.arange(free.size)
    top = np.where(np.isclose(p[1], height))[0]
    top = top[np.argsort(p[0, top])]
    ux, uy = basis.nodal_dofs[0, top], basis.nodal_dofs[1, top]
    K = K[free][:, free].tocsr()
    # scikit-fem's assembly is symmetric up to rounding (|a_ij − a_ji| ≈ 1e-16·max|a|):
    # penalty_lab would take the stored matrix as unsymmetric (LU, a warning, and `optimal`
    # refuses it). The symmetric part is the stiffness meant.
    K = ((K + K.T) * 0.5).tocsr()
    return K, p[0, top], index[ux], index[uy], height, h


def rows(x, iux, iuy, w, kind, n):
    """D (m × n), the limits, for the indentation w."""
    f, fp = x**2 / (2 * R), x / R
    m = x.size
    if kind == "vertical":
        D = sp.coo_matrix((np.ones(m), (np.arange(m), iuy)), shape=(m, n))
        return D, f - w
    s = np.sqrt(1 + fp**2)
    keep = iux >= 0  # the axis node's u_x is fixed by symmetry (f' = 0 there: one term)
    r = np.concatenate([np.arange(m), np.arange(m)[keep]])
    c = np.concatenate([iuy, iux[keep]])
    v = np.concatenate([1 / s, (-fp / s)[keep]])
    return sp.coo_matrix((v, (r, c)), shape=(m, n)), (f - w) / s


def run(kind, K, x, iux, iuy, w, method, **knobs):
    n = K.shape[0]
    D, lim = rows(x, iux, iuy, w, kind, n)
    out = penalty_lab.solve(K, np.zeros(n), D, lim, ["upper"] * x.size, method, **knobs)
    r = np.asarray(out["forces"])
    vertical = r if kind == "vertical" else r / np.sqrt(1 + (x / R) ** 2)
    load = 2 * vertical.sum()  # the half model carries half of every force, the axis node's too
    return out, load, r[0]


def main():
    K, x, iux, iuy, H, h = model()
    n = K.shape[0]
    ck = penalty_lab.cond2(K)
    print(f"scikit-fem Q4 model: N = {n}, {x.size} top nodes, h = a/{A / h:.0f}; cond2(K) = {ck.value:.6e} "
          f"in [{ck.lo:.6e}, {ck.hi:.6e}] ({'proven' if ck.proven else 'not proven'})")
    target = np.pi * A**2 * E_STAR / (4 * R)  # Hertz's load for a = 1
    # The indentation for that load: P grows faster than linearly in w; secant steps on Lagrange.
    w0, w1 = A**2 / (2 * R), A**2 / R
    p0_ = run("vertical", K, x, iux, iuy, w0, "lagrange", metrics=False)[1] - target
    for _ in range(30):
        p1_ = run("vertical", K, x, iux, iuy, w1, "lagrange", metrics=False)[1] - target
        if abs(p1_) <= 1e-10 * target:
            break
        w0, w1, p0_ = w1, w1 - p1_ * (w1 - w0) / (p1_ - p0_), p1_
    w = w1
    delta = 1e-4 * A
    # ε of `constant`: a stiffness per unit area times the tributary length, 1e3·E*·h (stiff).
    rules = [
        ("lagrange", {}),
        ("constant", {"eps": 1e3 * E_STAR * h}),
        ("scaled", {"factor": 1e3}),
        ("spring", {"delta": delta}),
        ("paper", {"delta": delta}),
        ("condensed", {"delta": delta}),
        ("augmented", {}),
        ("barrier", {"delta": delta}),
    ]
    worst = 0.0
    print(f"indentation w = {w:.6e} (Lagrange carries Hertz's load for a = 1: P = {target:.6e})\n")
    print("| rows | rule | P/P_Hertz(a=1) | p0 / Hertz p0(P) | max penetration | cond2 system | converged |")
    print("|---|---|---:|---:|---:|---:|:-:|")
    for kind in ("vertical", "normal"):
        for method, knobs in rules:
            try:
                out, load, r0 = run(kind, K, x, iux, iuy, w, method, solver_metrics=False, **knobs)
            except ValueError as e:
                print(f"| {kind} | {method} | failed: {e} |||||")
                worst = np.inf
                continue
            p0 = r0 / (h / 2)
            hertz = np.sqrt(load * E_STAR / (np.pi * R))
            err = abs(p0 / hertz - 1)
            worst = max(worst, err)
            c = out["cond2_system"]
            print(f"| {kind} | {method} | {load / target:.4f} | {p0 / hertz:.4f} | {out['max_penetration']:.2e} | "
                  f"{c if c is None else format(c, '.3e')} | {out['converged']} |")
    print(f"\nlargest |p0/p0_Hertz − 1| = {worst:.4f} (limit 0.03)")
    return 0 if worst <= 0.03 else 1


if __name__ == "__main__":
    sys.exit(main())
