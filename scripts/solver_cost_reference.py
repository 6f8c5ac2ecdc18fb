#!/usr/bin/env python3
"""Independent references for the solver-cost metrics of `solve`, from the final
linear system exactly as `solve --write-system DIR` writes it (A.mtx, b.mtx, x_hat.mtx).

For each case (a scene and a method with its knobs) it runs `solve --json --write-system` and
computes, without any of penalty-lab's code:

- cond2_jacobi: NumPy's cond(S A S, 2) (LAPACK SVD), S = diag(A)^(-1/2), each entry rounded
  as (s_k a_ij) s_l with k = max(i, j), l = min(i, j) (an exactly symmetric matrix); for a
  saddle point
  [K D; D^T 0] the matrix [S K S, D; D^T, 0] (Jacobi on u; the multiplier scaling that keeps
  the coupling entries 1), as `metrics::solver` defines it;
- pcg_iters_jacobi: SciPy's `cg` with M^-1 = diag(A)^-1, x0 = 0, rtol = tau, atol = 0,
  maxiter = 10 n, iterations counted by its callback (penalized systems only);
- pcg_iters_ic0: SciPy's `cg` with an IC(0) preconditioner written here from its definition
  (Meijerink & van der Vorst: Cholesky restricted to A's lower pattern; on breakdown
  A + alpha diag(A), alpha = 1e-3 doubled), applied by two SciPy triangular solves;
- pcg_iters_jacobi_to_err, pcg_iters_ic0_to_err (penalized systems), minres_iters_to_err
  (saddle points, SciPy's `minres` with M^-1 = diag(1/K_ii; K_dd) for single-DOF rows): the
  same solvers from x0 = 0, counted by their callback to the first iterate with
  ||u_k - u*||_inf <= e ||u*||_inf (u* the u block of mpmath's 50-digit solve, e = --err,
  1e-6), the run ended there by an exception from the callback; and the error of u at each
  residual stop (pcg_err_u_at_stop_jacobi, pcg_err_u_at_stop_ic0);
- pcg_iters_amg_scalar_to_err: SciPy's `cg` preconditioned by one V-cycle of PyAMG's
  `smoothed_aggregation_solver` (its defaults, CSR, B = ones), counted the same way;
- pcg_iters_amg_nodal_to_err (scenes with "near_null_space" and "block_size"): the same with
  A as BSR in blocks of block_size and B read from the scene's file (PyAMG's nodal mode); with
  "slots", A padded to them first (empty slots identity rows of the mean diagonal) and the
  V-cycle restricted to the DOFs;
- forward_err_u, forward_err_force: the relative inf-norm error of x_hat (u block; contact
  forces: penalties eps_c (x_d - u^_c) + lambda_c, multipliers for lagrange) against mpmath's
  LU solve at 50 digits of the stored A and b.

    pip install numpy scipy mpmath pyamg
    python3 scripts/solver_cost_reference.py --solve target/release/solve \
        --cases tests/data/solver_cost/cases.json --out tests/data/solver_cost/reference.json

cases.json: a list of {"scene": file (relative to cases.json), "method": name, "args": [...]}.
The output lists every case with the reference values only (penalty-lab's own values are
printed beside them on stdout, never stored); `tests/verification/solver_cost.rs` compares.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import mpmath
import numpy as np
import pyamg
import scipy
import scipy.io
import scipy.sparse as sp
import scipy.sparse.linalg as spla


def read(path):
    m = scipy.io.mmread(path)
    return sp.csc_matrix(m) if sp.issparse(m) else np.asarray(m).ravel()


def jacobi_scaled(a, n_u):
    """S A S with S = diag(A)^(-1/2) on the first n_u rows; multiplier rows scaled so that each
    row's largest coupling entry is 1 (single-DOF rows keep D = 1)."""
    a = a.toarray()
    n = a.shape[0]
    d = np.diag(a)[:n_u]
    s = 1.0 / np.sqrt(d)
    out = a.copy()
    # (s_k a_ij) s_l with k = max(i, j), l = min(i, j): the lower triangle's (s_i a_ij) s_j,
    # mirrored, as the library rounds it (an exactly symmetric S A S).
    lower = np.tril(a[:n_u, :n_u] * s[:, None] * s[None, :])
    out[:n_u, :n_u] = lower + np.tril(lower, -1).T
    # The coupling block of a saddle point: a single-DOF row's entry 1 stays 1; a row with
    # several terms becomes (a_j s_j) / max_j |a_j s_j| (its largest coupling entry 1).
    for j in range(n_u, n):
        col = a[:n_u, j]
        if np.count_nonzero(col) > 1:
            sc = col * s
            sc = sc / np.max(np.abs(sc))
            out[:n_u, j] = sc
            out[j, :n_u] = sc
        else:
            assert np.all((col == 0) | (col == 1))
    return out


def cg_iterations(a, b, tau, m_inv, u_star=None):
    """SciPy's cg to rtol = tau: (iterations, converged, error of u at the stop)."""
    count = [0]

    def cb(_):
        count[0] += 1

    op = spla.LinearOperator(a.shape, matvec=m_inv)
    x, info = spla.cg(a, b, x0=np.zeros_like(b), rtol=tau, atol=0.0,
                      maxiter=10 * len(b), M=op, callback=cb)
    err = None if u_star is None else rel_err_u(x, u_star)
    return count[0], info == 0, err


class Reached(Exception):
    pass


def rel_err_u(x, u_star):
    top = np.max(np.abs(u_star))
    e = np.max(np.abs(x[:len(u_star)] - u_star))
    return float(e / top) if top > 0 else float(e)


def iterations_to_err(solver, a, b, m_inv, u_star, target):
    """Iterations of SciPy's `solver` (cg or minres) from x0 = 0 to the first iterate with
    ||u_k - u*||_inf <= target ||u*||_inf: (iterations, reached)."""
    count = [0]
    if rel_err_u(np.zeros_like(b), u_star) <= target:
        return 0, True

    def cb(xk):
        count[0] += 1
        if rel_err_u(xk, u_star) <= target:
            raise Reached()

    op = spla.LinearOperator(a.shape, matvec=m_inv)
    kw = {"rtol": 0.0, "atol": 0.0} if solver is spla.cg else {"rtol": 0.0}
    try:
        solver(a, b, x0=np.zeros_like(b), maxiter=10 * len(b), M=op, callback=cb, **kw)
    except Reached:
        return count[0], True
    return count[0], False


def ic0(a):
    """IC(0) of the SPD sparse A: L on A's lower pattern, shift alpha on breakdown."""
    low = sp.tril(a, format="csc")
    low.sort_indices()
    diag = a.diagonal()
    n = a.shape[0]
    pattern = [set(low.indices[low.indptr[j]:low.indptr[j + 1]]) for j in range(n)]
    shift = 0.0
    while True:
        cols = [dict(zip(low.indices[low.indptr[j]:low.indptr[j + 1]],
                         low.data[low.indptr[j]:low.indptr[j + 1]])) for j in range(n)]
        for j in range(n):
            cols[j][j] = diag[j] + shift * diag[j]
        ok = True
        for k in range(n):
            col = cols[k]
            if not (col[k] > np.finfo(float).eps * diag[k] and np.isfinite(col[k])):
                ok = False
                break
            lkk = np.sqrt(col[k])
            for i in col:
                col[i] = lkk if i == k else col[i] / lkk
            below = sorted(i for i in col if i > k)
            for p, j in enumerate(below):
                for i in below[p:]:
                    if i in pattern[j]:
                        cols[j][i] -= col[i] * col[j]
        if ok:
            trip = [(i, j, v) for j in range(n) for i, v in cols[j].items()]
            rows, cs, vals = zip(*trip)
            return sp.csr_matrix((vals, (rows, cs)), shape=(n, n)), shift
        shift = 1e-3 if shift == 0.0 else 2.0 * shift
        if shift > 1e3:
            raise RuntimeError("IC(0) broke down for every shift")


def mp_solve(a, b):
    mpmath.mp.dps = 50
    am = mpmath.matrix(a.toarray().tolist())
    bm = mpmath.matrix([float(v) for v in b])
    return mpmath.lu_solve(am, bm)


def rel_inf(x_hat, x_ref):
    num = max((abs(mpmath.mpf(float(h)) - r) for h, r in zip(x_hat, x_ref)), default=0)
    den = max((abs(r) for r in x_ref), default=0)
    return float(num / den) if den != 0 else float(num)


def forces(x, scene, out, n):
    """Contact forces of a solution x (a list of mpf or floats) of the final system."""
    cons = scene["constraints"]
    if out["system"] == "penalized":
        f = []
        for c, con in enumerate(cons):
            e, r, g = out["penalties"][c], out["forces"][c], out["gaps"][c]
            lam = r - e * g  # IEEE double, as the library forms it
            terms = con.get("terms") or [[con["dof"], 1.0]]
            v = sum(mpmath.mpf(a) * mpmath.mpf(x[d]) for d, a in terms)
            f.append(mpmath.mpf(e) * (v - mpmath.mpf(con["limit"])) + mpmath.mpf(lam))
        return f
    active = out["system"]["saddle_point"]["active"]
    f = [mpmath.mpf(0)] * len(cons)
    for j, c in enumerate(active):
        f[c] = mpmath.mpf(x[n + j])
    return f


def run_case(solve, base, case, tau, err):
    scene_path = os.path.join(base, case["scene"])
    with open(scene_path) as fh:
        scene = json.load(fh)
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [solve, scene_path, "--method", case["method"], *case.get("args", []),
               "--json", "--quiet", "--krylov-tol", repr(tau), "--write-system", tmp]
        out = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
        a = read(os.path.join(tmp, "A.mtx"))
        b = read(os.path.join(tmp, "b.mtx"))
        x_hat = read(os.path.join(tmp, "x_hat.mtx"))
    n = out["n"]
    ref = {"scene": case["scene"], "method": case["method"], "args": case.get("args", []),
           "n_system": a.shape[0]}
    sas = jacobi_scaled(a, n)
    ref["cond2_jacobi"] = float(np.linalg.cond(sas, 2))
    x_ref = mp_solve(a, b)
    u_star = np.array([float(v) for v in list(x_ref)[:n]])
    if out["system"] == "penalized":
        d = a.diagonal()
        jac = lambda r: r / d  # noqa: E731
        (ref["pcg_iters_jacobi"], ref["pcg_converged_jacobi"],
         ref["pcg_err_u_at_stop_jacobi"]) = cg_iterations(a, b, tau, jac, u_star)
        (ref["pcg_iters_jacobi_to_err"],
         ref["pcg_iters_jacobi_to_err_converged"]) = iterations_to_err(
            spla.cg, a, b, jac, u_star, err)
        l, shift = ic0(a)
        lt = l.T.tocsr()

        def ic_apply(r):
            y = spla.spsolve_triangular(l, r, lower=True)
            return spla.spsolve_triangular(lt, y, lower=False)

        (ref["pcg_iters_ic0"], ref["pcg_converged_ic0"],
         ref["pcg_err_u_at_stop_ic0"]) = cg_iterations(a, b, tau, ic_apply, u_star)
        (ref["pcg_iters_ic0_to_err"],
         ref["pcg_iters_ic0_to_err_converged"]) = iterations_to_err(
            spla.cg, a, b, ic_apply, u_star, err)
        ref["ic0_shift"] = shift
        # PyAMG's smoothed aggregation with its defaults, scalar CSR, B = ones.
        ml = pyamg.smoothed_aggregation_solver(sp.csr_matrix(a), B=np.ones((a.shape[0], 1)))
        amg = ml.aspreconditioner(cycle="V")
        (ref["pcg_iters_amg_scalar_to_err"],
         ref["pcg_iters_amg_scalar_to_err_converged"]) = iterations_to_err(
            spla.cg, a, b, amg.matvec, u_star, err)
        if "near_null_space" in scene:
            bs = scene.get("block_size", 1)
            bmodes = np.asarray(scipy.io.mmread(os.path.join(
                os.path.dirname(scene_path), scene["near_null_space"]["matrix_market"])))
            slots = scene["near_null_space"].get("slots")
            if slots is None:
                ml = pyamg.smoothed_aggregation_solver(
                    sp.csr_matrix(a).tobsr(blocksize=(bs, bs)), B=bmodes)
                amg = ml.aspreconditioner(cycle="V")
            else:
                # B over slots: A padded as `linalg::amg::slots` defines it (empty slots
                # identity rows of the mean diagonal), the V-cycle restricted to the DOFs.
                slots = np.asarray(slots)
                ns, n_a = bmodes.shape[0], a.shape[0]
                e = sp.csr_matrix((np.ones(n_a), (slots, np.arange(n_a))), shape=(ns, n_a))
                empty = np.setdiff1d(np.arange(ns), slots)
                pad = sp.csr_matrix((np.full(len(empty), a.diagonal().mean()), (empty, empty)),
                                    shape=(ns, ns))
                a_hat = (e @ sp.csr_matrix(a) @ e.T + pad).tocsr()
                ml = pyamg.smoothed_aggregation_solver(a_hat.tobsr(blocksize=(bs, bs)),
                                                       B=bmodes)
                m_hat = ml.aspreconditioner(cycle="V")

                def padded(r, m_hat=m_hat, slots=slots, ns=ns):
                    z = np.zeros(ns)
                    z[slots] = r
                    return m_hat.matvec(z)[slots]

                amg = spla.LinearOperator(a.shape, matvec=padded)
            (ref["pcg_iters_amg_nodal_to_err"],
             ref["pcg_iters_amg_nodal_to_err_converged"]) = iterations_to_err(
                spla.cg, a, b, amg.matvec, u_star, err)
    else:
        # M^-1: 1/K_ii on u; on a row d_c's multiplier the inverse of d_c^T diag(K)^-1 d_c
        # (K_dd for a single-DOF row).
        dense = a.toarray()
        kd = np.diag(dense)[:n]
        inv = np.concatenate([1.0 / kd,
                              [1.0 / np.sum(dense[:n, j] ** 2 / kd)
                               for j in range(n, a.shape[0])]])
        (ref["minres_iters_to_err"],
         ref["minres_iters_to_err_converged"]) = iterations_to_err(
            spla.minres, a, b, lambda r: inv * r, u_star, err)
    ref["forward_err_u"] = rel_inf(x_hat[:n], list(x_ref)[:n])
    f_hat = [float(v) for v in forces([mpmath.mpf(float(v)) for v in x_hat], scene, out, n)]
    ref["forward_err_force"] = rel_inf(f_hat, forces(list(x_ref), scene, out, n))
    ours = {k: out.get(k) for k in ref if k not in ("scene", "method", "args", "n_system")}
    print(f"{case['scene']} {case['method']} {' '.join(case.get('args', []))}")
    for k in ours:
        print(f"    {k:34} reference {ref[k]!s:24} penalty-lab {ours[k]}")
    return ref


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--solve", default="target/release/solve")
    ap.add_argument("--cases", required=True)
    ap.add_argument("--out")
    ap.add_argument("--tau", type=float, default=1e-8)
    ap.add_argument("--err", type=float, default=1e-6)
    args = ap.parse_args()
    with open(args.cases) as fh:
        cases = json.load(fh)
    base = os.path.dirname(os.path.abspath(args.cases))
    refs = [run_case(args.solve, base, c, args.tau, args.err) for c in cases]
    doc = {
        "generator": "scripts/solver_cost_reference.py",
        "versions": {"numpy": np.__version__, "scipy": scipy.__version__,
                     "mpmath": mpmath.__version__, "pyamg": pyamg.__version__,
                     "python": sys.version.split()[0]},
        "tau": args.tau,
        "err_target": args.err,
        "cases": refs,
    }
    text = json.dumps(doc, indent=1) + "\n"
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(text)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
