"""penalty_lab — contact penalty strategies and certified condition numbers, from Python.

``solve(K, q, D, limits, kinds, method, ...)`` runs one strategy of the penalty-lab library on
a contact problem given as NumPy/SciPy arrays and returns the record of ``solve --json``;
``read_scene(path)`` reads a scene file into those arrays.

``cond2(A)`` returns cond₂(A) = σ_max/σ_min with a bracket ``[lo, hi]`` proven for the stored
matrix (every rounding included) and whether the value is proven within the accuracy contract
``max(1e-12, 4·ε_mach·cond₂)`` — the same record as the command-line tool's ``cond --json``,
computed by the same Rust code (the penalty-lab repository, ``python/``).

NumPy's ``numpy.linalg.cond`` densifies and states no error bound; SciPy's
``scipy.sparse.linalg.onenormest`` estimates a 1-norm. ``penalty_lab.cond2`` takes sparse matrices as they are (SPD matrices by
sparse Cholesky and Lanczos with proven bounds; others by a dense SVD up to a size limit).
"""

import json as _json

import numpy as _np

from . import _penalty_lab

__all__ = ["Cond2", "cond2", "solve", "read_scene"]
__version__ = _penalty_lab.version()


class Cond2:
    """The certified cond₂ of one matrix.

    Attributes
    ----------
    value : float
        σ_max/σ_min, the best estimate (``inf`` when σ_min is 0 to working precision).
    lo, hi : float
        The bracket of cond₂ (``hi = inf``: σ_min not bounded away from 0).
    proven : bool
        Whether ``[lo, hi]`` is proven, every rounding included.
    within_contract : bool
        Whether ``value`` is proven within ``max(1e-12, 4·ε_mach·cond₂)`` of the exact cond₂.
    route : str
        How it was computed (``dense-svd``, ``sparse-spd``, …).
    warnings : list of str
        What the numbers do not say by themselves.
    record : dict
        Every field of ``cond --json`` (``n``, ``nnz``, ``symmetry``, ``sigma_max``,
        ``sigma_min``, ``log10_det``, ``cond2_error_bound``, ``seconds``, …).
    """

    __slots__ = ("value", "lo", "hi", "proven", "within_contract", "route", "warnings", "record")

    def __init__(self, record):
        def num(key, missing):
            v = record.get(key)
            return missing if v is None else float(v)

        self.record = record
        self.value = num("cond2", _np.inf)
        self.lo = num("cond2_lo", _np.inf)
        self.hi = num("cond2_hi", _np.inf)
        self.proven = bool(record["cond2_bounds_proven"])
        self.within_contract = bool(record["cond2_within_contract"])
        self.route = record["cond_route"]
        self.warnings = list(record["warnings"])

    def __repr__(self):
        proven = "proven" if self.proven else "not proven"
        return (
            f"Cond2(value={self.value:.12g}, bracket=[{self.lo:.12g}, {self.hi:.12g}] {proven}, "
            f"within_contract={self.within_contract}, route={self.route!r})"
        )


_STORAGES = ("general", "lower", "upper")


def _triplets(a, what):
    """(shape, rows, cols, vals) of a 2-D matrix — a SciPy sparse matrix or array in any format
    (duplicates kept, to be summed; indices need not be sorted) or anything ``numpy.asarray``
    takes (its nonzero and non-finite entries) — as contiguous int64/int64/float64 arrays."""
    if hasattr(a, "tocoo") and hasattr(a, "nnz"):
        shape = a.shape
        c = a.tocoo()
        rows, cols, vals = c.row, c.col, c.data
    else:
        d = _np.asarray(a)
        if d.dtype == object or not (
            _np.issubdtype(d.dtype, _np.floating) or _np.issubdtype(d.dtype, _np.integer)
        ):
            raise ValueError(f"invalid input: {what} must hold real numbers (got dtype {d.dtype})")
        shape = d.shape
        if d.ndim != 2:
            raise ValueError(f"invalid input: {what} must be 2-D (got shape {shape})")
        # Non-finite entries must reach the library's check: keep them as entries.
        rows, cols = _np.nonzero((d != 0) | ~_np.isfinite(d))
        vals = d[rows, cols]
    if len(shape) != 2:  # a 1-D SciPy sparse array
        raise ValueError(f"invalid input: {what} must be 2-D (got shape {tuple(shape)})")
    if _np.iscomplexobj(vals):
        raise ValueError(f"invalid input: {what} must be real (got complex entries)")
    return (
        tuple(shape),
        _np.ascontiguousarray(rows, dtype=_np.int64),
        _np.ascontiguousarray(cols, dtype=_np.int64),
        _np.ascontiguousarray(vals, dtype=_np.float64),
    )


def _coo(a, storage):
    """(n, rows, cols, vals) of a square matrix (:func:`_triplets`). ``storage``: ``general``
    (every entry given), ``lower``/``upper`` (one triangle of a symmetric matrix; the other is
    mirrored)."""
    if storage not in _STORAGES:
        raise ValueError(f"invalid input: storage must be one of {', '.join(_STORAGES)} (got {storage!r})")
    shape, rows, cols, vals = _triplets(a, "the matrix")
    if shape[0] != shape[1]:
        raise ValueError(f"invalid input: the matrix must be square (got shape {shape})")
    if storage != "general":
        keep = rows >= cols if storage == "lower" else rows <= cols
        if not _np.all(keep):
            raise ValueError(f"invalid input: storage={storage!r} but entries lie in the other triangle")
        off = rows != cols
        rows, cols = _np.concatenate([rows, cols[off]]), _np.concatenate([cols, rows[off]])
        vals = _np.concatenate([vals, vals[off]])
    return int(shape[0]), rows, cols, vals


def cond2(a, tol=None, storage="general"):
    """The certified cond₂ of the square matrix ``a`` (a :class:`Cond2`).

    ``a``: a SciPy sparse matrix or array (CSR, CSC, COO, …) or a NumPy array. ``tol``: the
    relative accuracy asked, in (0, 1) (``None``: the contract ``max(1e-12, 4·ε_mach·cond₂)``);
    looser is faster, the bracket stays proven. ``storage``: ``general``, or ``lower``/``upper``
    when ``a`` holds one triangle of a symmetric matrix.

    Raises ``ValueError`` on bad input (NaN/Inf, not square, not real, ``tol`` outside (0, 1))
    and where the matrix is too large for its route (an unsymmetric or indefinite sparse matrix
    above the dense SVD's limit), with the command-line tool's message. The GIL is released
    while it computes.
    """
    n, rows, cols, vals = _coo(a, storage)
    text = _penalty_lab.cond2_coo(n, rows.tobytes(), cols.tobytes(), vals.tobytes(), tol)
    return Cond2(_json.loads(text))


def _bytes(x, dtype, what):
    a = _np.ascontiguousarray(_np.asarray(x, dtype=dtype))
    if a.ndim != 1:
        raise ValueError(f"invalid input: {what} must be 1-D (got shape {a.shape})")
    return a.tobytes()


def _rows(d, n):
    """(m, rows, cols, vals) of D (rows = constraints, columns = DOFs; :func:`_triplets`)."""
    shape, rows, cols, vals = _triplets(d, "D")
    if shape[1] != n:
        raise ValueError(f"invalid input: D has {shape[1]} columns, K is {n} × {n}")
    return shape[0], rows, cols, vals


def solve(K, q, D, limits, kinds, method="condensed", *, eps=None, factor=None, delta=None,
          tol=None, adaptive=False, metrics=True, solver_metrics=None, cond_tol=None,
          exact_start=False, storage="general", name=None):
    """One strategy on the contact problem ``K u = q − Dᵀ r`` (the sign convention of the
    library: r the contact forces, r ≥ 0 pushing an ``upper`` obstacle back).

    ``K``: n×n (SciPy sparse or NumPy; ``storage`` as in :func:`cond2`); ``q``: n loads;
    ``D``: m×n, one row d_cᵀ per constraint (general rows allowed; the transpose of the
    library's N×m D); ``limits``: û_c;
    ``kinds``: ``"upper"`` (d_cᵀu ≤ û_c), ``"lower"`` (≥) or ``"bilateral"`` (=), one per row.
    ``method``: a strategy name (``constant``, ``scaled``, ``spring``, ``paper``,
    ``condensed``, ``lagrange``, ``augmented``, ``optimal``, ``barrier``) with its knob
    (``eps``, ``factor``, ``delta``, ``tol``, ``adaptive``) as the ``solve`` tool's flags.

    Returns a dict with exactly the keys of ``solve --json`` (u, penalties, gaps, forces, cond₂
    with its bracket, log-dets, statistics, the solver-side metrics up to 1 000 unknowns, …),
    computed by the same code. ``ValueError`` on bad input, with the tool's message.
    """
    n, kr, kc, kv = _coo(K, storage)
    m, dr, dc, dv = _rows(D, n)
    kinds = [str(k) for k in kinds]
    text = _penalty_lab.solve_coo(
        n, kr.tobytes(), kc.tobytes(), kv.tobytes(), _bytes(q, _np.float64, "q"),
        dr.tobytes(), dc.tobytes(), dv.tobytes(),
        _bytes(limits, _np.float64, "limits"), kinds, str(method),
        eps=eps, factor=factor, delta=delta, tol=tol, adaptive=bool(adaptive), metrics=bool(metrics),
        solver_metrics=solver_metrics, cond_tol=cond_tol, exact_start=bool(exact_start), name=name,
    )
    return _json.loads(text)


def read_scene(path):
    """A scene file (the ``solve`` tool's JSON format) as the arguments of :func:`solve`: a dict
    with ``K`` (SciPy CSC if SciPy is installed, else a dense NumPy array), ``q``, ``D`` (COO
    triplets as SciPy COO, or dense), ``limits``, ``kinds`` and ``name``."""
    s = _json.loads(_penalty_lab.read_scene_json(str(path)))
    n, m = s["n"], len(s["limits"])
    kr, kc, kv = (_np.asarray(s[k]) for k in ("k_rows", "k_cols", "k_vals"))
    dr, dc, dv = (_np.asarray(s[k]) for k in ("d_rows", "d_cols", "d_vals"))
    try:
        import scipy.sparse as _sp

        K = _sp.coo_matrix((kv.astype(float), (kr, kc)), shape=(n, n))
        D = _sp.coo_matrix((dv.astype(float), (dr, dc)), shape=(m, n))
    except ImportError:
        K = _np.zeros((n, n))
        K[kr, kc] = kv
        D = _np.zeros((m, n))
        D[dr, dc] = dv
    return {
        "K": K, "q": _np.asarray(s["q"], dtype=float), "D": D,
        "limits": _np.asarray(s["limits"], dtype=float), "kinds": list(s["kinds"]), "name": s["name"],
    }
