#!/usr/bin/env python3
"""PyAMG references for penalty-lab's smoothed-aggregation AMG (`src/linalg/amg.rs`):
CG iterations to a fixed error of u with PyAMG's `smoothed_aggregation_solver` (its defaults,
scalar CSR, B = ones) as the preconditioner (one V-cycle per application), on penalized
membranes built here from their formula, which `tests/verification/amg.rs` builds the same
way in Rust:

    K = 5-point Laplacian (stencil 4, -1) on side x side interior nodes of the unit square,
    h = 1/(side+1), node (i, j) -> i*side + j, x_i = (i+1) h;
    eps_c = eps_rel * 4 on the nodes with r^2 = (x-1/2)^2 + (y-1/2)^2 < 0.1, else 0;
    A = K + diag(eps), b = -10 h^2 + eps * (-0.35 - 0.7 r^2).

And nodal smoothed aggregation on plane-strain elasticity with two-term contact rows: the
inclined block of `model::incline_block` (theta = 30 deg, 48 x 24 Q4 elements, N = 2352), its
scene written by `examples/incline_scene` (K, q, the rows d_c = (sin, cos) on a bottom node's
(u_x, u_y), their limits u^_c, and B = the rigid-body modes of the free nodes), penalized
with a constant eps:

    A = K + eps sum_c d_c d_c^T,  b = q + eps sum_c d_c u^_c;

PyAMG with A as BSR 2x2 and that B (its nodal mode: block strength, block Gauss-Seidel), and
scalar CSR with B = ones, for comparison. `tests/verification/amg.rs` builds the same A and b
from the model.

And nodal smoothed aggregation in 3-D with unknowns in slots: the `hertz-3d` block of
`solver_cost` (trilinear hexahedra, h/a = 0.25, N = 2520), its scene written by
`examples/sphere_scene` (K, q, one row u_z <= u^_c per top node, B = the rigid-body modes of
the free nodes over three slots per node and each DOF's slot), penalized with eps = eps_rel *
max K_ii (1, 1e3, 1e6; at 1e8 PyAMG's CG no longer reaches the target); A padded to the slots (each DOF moved to its slot, every empty slot - a symmetry
plane's prescribed component - a decoupled identity row s e e^T, s = mean of diag(A)), PyAMG
on it as BSR 3x3 with that B, and the preconditioner for A the V-cycle restricted to the DOFs'
slots (zeros in, empty slots dropped) - the definition `linalg::amg` implements.

And the same on plane rows that couple DOFs on one node or across bodies: `hertz-normals`
(h/a = 1/8: rows along the cylinder's normals) and `patch-two-body-nts-1` (h/a = 1/16: one-pass
node-to-segment rows between two blocks), their scenes written by `examples/contact_scene`
(B = the plane rigid-body modes over two slots per node; the symmetry line's fixed u_x an
empty slot), eps = 1, 1e4, 1e8 * max K_ii, nodal (BSR 2x2, padded) and scalar. cond(A) reaches
1e14 there, so u* is SciPy's direct solve refined by three steps of iterative refinement with
residuals in long double (an unrefined solve is no reference to 1e-6).

u* = SciPy's direct solve; the count is the first CG iterate (x0 = 0, SciPy's `cg`, its
callback) with ||u_k - u*||_inf <= 1e-6 ||u*||_inf (a run that breaks down or reaches 10 N
iterations is recorded as not converged).

    pip install numpy scipy pyamg
    cargo build --release --example incline_scene --example sphere_scene --example contact_scene
    python3 scripts/amg_reference.py > tests/data/amg/reference.json
"""
import json
import os
import subprocess
import sys
import tempfile
import warnings

import numpy as np
import pyamg
import scipy
import scipy.io
import scipy.sparse as sp
import scipy.sparse.linalg as spla

TARGET = 1e-6


class Reached(Exception):
    pass


def membrane(side, eps_rel):
    t = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(side, side))
    k = (sp.kron(t, sp.identity(side)) + sp.kron(sp.identity(side), t)).tocsr()
    h = 1.0 / (side + 1)
    x = (np.arange(side) + 1) * h
    xx, yy = np.meshgrid(x, x, indexing="ij")
    r2 = ((xx - 0.5) ** 2 + (yy - 0.5) ** 2).ravel()
    eps = np.where(r2 < 0.1, eps_rel * 4.0, 0.0)
    a = (k + sp.diags(eps)).tocsr()
    b = -10 * h * h * np.ones(side * side) + eps * (-0.35 - 0.7 * r2)
    return a, b


def iterations_to_err(a, b, m, u_star):
    top = np.max(np.abs(u_star))
    count = [0]

    def cb(xk):
        count[0] += 1
        if np.max(np.abs(xk - u_star)) <= TARGET * top:
            raise Reached()

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            spla.cg(a, b, x0=np.zeros_like(b), rtol=0.0, atol=0.0, maxiter=10 * len(b), M=m,
                    callback=cb)
    except Reached:
        return count[0], True
    return count[0], False


def scene_system(exe, args, eps_of):
    """K, the penalized A and b, B and the scene of the scene `exe` writes (module doc)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "model.scene.json")
        subprocess.run([exe, path, *args], check=True, capture_output=True)
        with open(path) as fh:
            scene = json.load(fh)
        k = sp.csr_matrix(scipy.io.mmread(os.path.join(tmp, scene["stiffness"]["matrix_market"])))
        bmodes = np.asarray(scipy.io.mmread(
            os.path.join(tmp, scene["near_null_space"]["matrix_market"])))
    n = k.shape[0]
    eps = eps_of(k)
    rows, cols, vals = [], [], []
    b = np.array(scene["load"], dtype=float)
    for c, con in enumerate(scene["constraints"]):
        terms = con["terms"] if "terms" in con else [[con["dof"], 1.0]]
        for d, a in terms:
            rows.append(c)
            cols.append(d)
            vals.append(a)
            b[d] += eps * a * con["limit"]
    dmat = sp.csr_matrix((vals, (rows, cols)), shape=(len(scene["constraints"]), n))
    return (k + eps * (dmat.T @ dmat)).tocsr(), b, bmodes, scene, eps


def incline(theta, nx, eps):
    """A, b and B of the penalized inclined block (module doc)."""
    exe = os.environ.get("INCLINE_SCENE", "target/release/examples/incline_scene")
    a, b, bmodes, scene, _ = scene_system(exe, [repr(theta), str(nx)], lambda k: eps)
    return a, b, bmodes, scene["block_size"]


def sphere(h, eps_rel):
    """A, b, B, slots and eps of the penalized hertz-3d block (module doc)."""
    exe = os.environ.get("SPHERE_SCENE", "target/release/examples/sphere_scene")
    a, b, bmodes, scene, eps = scene_system(
        exe, [repr(h)], lambda k: eps_rel * k.diagonal().max())
    return a, b, bmodes, scene["near_null_space"]["slots"], eps


def contact(case, h, eps_rel):
    """A, b, B, slots and eps of a penalized contact benchmark scene (module doc)."""
    exe = os.environ.get("CONTACT_SCENE", "target/release/examples/contact_scene")
    a, b, bmodes, scene, eps = scene_system(
        exe, [case, repr(h)], lambda k: eps_rel * k.diagonal().max())
    return a, b, bmodes, scene["near_null_space"]["slots"], eps


def refined_solve(a, b, steps=3):
    """spsolve, then `steps` of iterative refinement with long-double residuals."""
    lu = spla.splu(a.tocsc())
    x = lu.solve(b)
    al, bl = a.astype(np.longdouble), b.astype(np.longdouble)
    for _ in range(steps):
        r = bl - al @ x.astype(np.longdouble)
        x = x + lu.solve(np.asarray(r, dtype=float))
    return x


def padded_preconditioner(a, slots, n_slots, bmodes, bs):
    """PyAMG's V-cycle on A padded to its slots, restricted to the DOFs (module doc)."""
    slots = np.asarray(slots)
    n = a.shape[0]
    e = sp.csr_matrix((np.ones(n), (slots, np.arange(n))), shape=(n_slots, n))
    empty = np.setdiff1d(np.arange(n_slots), slots)
    s = a.diagonal().mean()
    pad = sp.csr_matrix((np.full(len(empty), s), (empty, empty)), shape=(n_slots, n_slots))
    a_hat = (e @ a @ e.T + pad).tocsr()
    ml = pyamg.smoothed_aggregation_solver(a_hat.tobsr(blocksize=(bs, bs)), B=bmodes)
    m = ml.aspreconditioner(cycle="V")

    def apply(r):
        z = np.zeros(n_slots)
        z[slots] = r
        return m.matvec(z)[slots]

    return spla.LinearOperator(a.shape, matvec=apply), ml


cases = []
for side in [63, 127]:
    for eps_rel in [1e2, 1e6]:
        a, b = membrane(side, eps_rel)
        u_star = spla.spsolve(a.tocsc(), b)
        ml = pyamg.smoothed_aggregation_solver(a, B=np.ones((a.shape[0], 1)))
        m = ml.aspreconditioner(cycle="V")
        its, ok = iterations_to_err(a, b, m, u_star)
        jac = spla.LinearOperator(a.shape, matvec=lambda r, d=a.diagonal(): r / d)
        jits, jok = iterations_to_err(a, b, jac, u_star)
        cases.append({"side": side, "eps_rel": eps_rel, "n": a.shape[0],
                      "pcg_iters_amg_scalar_to_err": its, "converged": ok,
                      "pcg_iters_jacobi_to_err": jits, "jacobi_converged": jok,
                      "levels": [lv.A.shape[0] for lv in ml.levels]})
        print(cases[-1], file=sys.stderr)
elastic = []
for eps in [1.0, 1e4, 1e8]:
    a, b, bmodes, bs = incline(30.0, 48, eps)
    u_star = spla.spsolve(a.tocsc(), b)
    nodal = pyamg.smoothed_aggregation_solver(a.tobsr(blocksize=(bs, bs)), B=bmodes)
    its, ok = iterations_to_err(a, b, nodal.aspreconditioner(cycle="V"), u_star)
    scalar = pyamg.smoothed_aggregation_solver(a, B=np.ones((a.shape[0], 1)))
    sits, sok = iterations_to_err(a, b, scalar.aspreconditioner(cycle="V"), u_star)
    elastic.append({"theta_deg": 30.0, "nx": 48, "ny": 24, "eps": eps, "n": a.shape[0],
                    "pcg_iters_amg_nodal_to_err": its, "converged": ok,
                    "levels": [lv.A.shape[0] for lv in nodal.levels],
                    "pcg_iters_amg_scalar_to_err": sits, "scalar_converged": sok})
    print(elastic[-1], file=sys.stderr)
solid = []
for eps_rel in [1.0, 1e3, 1e6]:
    a, b, bmodes, slots, eps = sphere(0.25, eps_rel)
    u_star = spla.spsolve(a.tocsc(), b)
    m, ml = padded_preconditioner(a, slots, bmodes.shape[0], bmodes, 3)
    its, ok = iterations_to_err(a, b, m, u_star)
    solid.append({"h_over_a": 0.25, "eps_rel": eps_rel, "eps": eps, "n": a.shape[0],
                  "pcg_iters_amg_nodal_to_err": its, "converged": ok,
                  "levels": [lv.A.shape[0] for lv in ml.levels]})
    print(solid[-1], file=sys.stderr)
coupled = []
for case, h in [("hertz-normals", 0.125), ("patch-two-body-nts-1", 0.0625)]:
    for eps_rel in [1.0, 1e4, 1e8]:
        a, b, bmodes, slots, eps = contact(case, h, eps_rel)
        u_star = refined_solve(a, b)
        m, ml = padded_preconditioner(a, slots, bmodes.shape[0], bmodes, 2)
        its, ok = iterations_to_err(a, b, m, u_star)
        scalar = pyamg.smoothed_aggregation_solver(a, B=np.ones((a.shape[0], 1)))
        sits, sok = iterations_to_err(a, b, scalar.aspreconditioner(cycle="V"), u_star)
        coupled.append({"case": case, "h_over_a": h, "eps_rel": eps_rel, "eps": eps,
                        "n": a.shape[0], "pcg_iters_amg_nodal_to_err": its, "converged": ok,
                        "levels": [lv.A.shape[0] for lv in ml.levels],
                        "pcg_iters_amg_scalar_to_err": sits, "scalar_converged": sok})
        print(coupled[-1], file=sys.stderr)
json.dump({"generator": "scripts/amg_reference.py", "err_target": TARGET,
           "versions": {"pyamg": pyamg.__version__, "scipy": scipy.__version__,
                        "numpy": np.__version__},
           "cases": cases, "elastic": elastic, "solid": solid,
           "coupled": coupled}, sys.stdout, indent=1)
sys.stdout.write("\n")
