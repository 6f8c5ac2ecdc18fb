"""penalty_lab.cond2 against independent references: NumPy's SVD (dense), the closed-form
spectrum of the 2-D Dirichlet Laplacian (sparse, N ≥ 10⁵), and the command-line tool `cond`
on the same matrix (identical records). Tolerances scale with the problem: NumPy's SVD gives
σ_min to about n·ε_mach·σ_max, so its cond₂ is good to ~n·ε_mach·cond₂."""

import json
import subprocess

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

import penalty_lab

EPS = np.finfo(float).eps


def numpy_cond(a):
    s = np.linalg.svd(np.asarray(a.toarray() if sp.issparse(a) else a), compute_uv=False)
    return s[0] / s[-1]


def assert_agrees(c, truth, n):
    """`c` is proven, within the contract of the truth up to the reference's own error, and
    its bracket holds the truth within that error. NumPy's SVD finds σ_min to about
    n·ε_mach·σ_max, so its cond₂ is good to a relative n·ε_mach·cond₂ (8× that allowed)."""
    ref = 8 * n * EPS * truth
    contract = max(1e-12, 4 * EPS * truth)
    assert c.proven, c
    assert abs(c.value - truth) <= (contract + ref) * truth, (c, truth)
    assert c.lo * (1 - ref) <= truth <= c.hi * (1 + ref), (c, truth)
    assert c.lo <= c.value <= c.hi


def test_identity_is_one_and_proven():
    c = penalty_lab.cond2(sp.eye(3))
    assert c.proven and c.within_contract
    assert c.lo <= 1.0 <= c.hi and abs(c.value - 1.0) <= 1e-12
    assert "bracket" in repr(c)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("fmt", ["csr", "csc", "coo", "dense"])
def test_spd_and_graded_against_numpy_svd(seed, fmt):
    rng = np.random.default_rng(seed)
    n = 60
    q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    # Graded spectrum over eight decades, then a sparse banded SPD matrix with a graded diagonal.
    dense = (q * np.logspace(0, 8, n)) @ q.T
    dense = (dense + dense.T) / 2
    band = sp.diags([-1.0, 2.0 + np.logspace(0, 6, n) * (seed + 1), -1.0], [-1, 0, 1], shape=(n, n))
    for a in (dense, band.toarray()):
        m = a if fmt == "dense" else sp.csr_matrix(a).asformat(fmt)
        assert_agrees(penalty_lab.cond2(m), numpy_cond(a), n)


def test_unsymmetric_and_saddle_point_against_numpy_svd():
    rng = np.random.default_rng(7)
    n = 40
    a = rng.standard_normal((n, n)) + n * np.eye(n)
    assert_agrees(penalty_lab.cond2(sp.csr_matrix(a)), numpy_cond(a), n)
    k = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(n, n)).toarray()
    d = np.zeros((n, 2))
    d[3, 0], d[10, 1] = 1.0, 1.0
    saddle = np.block([[k, d], [d.T, np.zeros((2, 2))]])
    assert_agrees(penalty_lab.cond2(sp.csr_matrix(saddle)), numpy_cond(saddle), n + 2)


def test_symmetric_storage_of_one_triangle_equals_the_full_matrix():
    rng = np.random.default_rng(3)
    n = 30
    b = rng.standard_normal((n, n))
    a = b @ b.T + n * np.eye(n)
    full = penalty_lab.cond2(sp.csr_matrix(a))
    lower = penalty_lab.cond2(sp.tril(sp.csr_matrix(a)), storage="lower")
    upper = penalty_lab.cond2(sp.triu(sp.csr_matrix(a)), storage="upper")
    assert lower.record == {**full.record, "seconds": lower.record["seconds"]}
    assert upper.value == full.value and upper.lo == full.lo and upper.hi == full.hi


def test_duplicates_are_summed_and_unsorted_indices_accepted():
    rows = np.array([2, 0, 1, 0, 1, 2, 1])
    cols = np.array([2, 0, 1, 0, 0, 2, 1])
    vals = np.array([1.0, 2.0, 1.5, 2.0, 0.0, 2.0, 1.5])
    coo = sp.coo_matrix((vals, (rows, cols)), shape=(3, 3))  # duplicates, not summed yet
    dense = coo.toarray()  # sums them: diag(4, 3, 3)
    assert penalty_lab.cond2(coo).value == pytest.approx(4.0 / 3.0, rel=1e-14)
    assert penalty_lab.cond2(dense).value == penalty_lab.cond2(coo).value
    # CSR with unsorted column indices within a row and a duplicate: [[2, 0, 1], [0, 3, 0], [1, 0, 2]]
    # stored as row 0 = (col 2: 1, col 0: 2), row 1 = (col 1: 1, col 1: 2), row 2 = (col 2: 2, col 0: 1).
    csr = sp.csr_matrix(
        (np.array([1.0, 2.0, 1.0, 2.0, 2.0, 1.0]), np.array([2, 0, 1, 1, 2, 0]), np.array([0, 2, 4, 6])),
        shape=(3, 3),
    )
    want = np.array([[2.0, 0.0, 1.0], [0.0, 3.0, 0.0], [1.0, 0.0, 2.0]])
    assert_agrees(penalty_lab.cond2(csr), numpy_cond(want), 3)


def test_large_sparse_laplacian_against_its_closed_form_spectrum():
    # 2-D Dirichlet Laplacian on m × m interior nodes: λ = 4 − 2cos(iπ/(m+1)) − 2cos(jπ/(m+1)).
    m = 317  # N = 100 489
    t = sp.diags([-1.0, 2.0, -1.0], [-1, 0, 1], shape=(m, m))
    a = (sp.kron(sp.eye(m), t) + sp.kron(t, sp.eye(m))).tocsr()
    h = np.pi / (m + 1)
    lmin, lmax = 4 - 4 * np.cos(h), 4 + 4 * np.cos(h)
    truth = lmax / lmin
    c = penalty_lab.cond2(a)
    assert c.record["n"] == m * m and c.record["nnz"] == a.nnz
    assert c.proven and c.lo <= truth <= c.hi, (c, truth)
    assert abs(c.value - truth) <= max(1e-12, 4 * EPS * truth) * truth + 64 * EPS * truth


@pytest.mark.parametrize(
    "bad, message",
    [
        (np.array([[1.0, np.nan], [0.0, 1.0]]), "not finite"),
        (np.array([[1.0, np.inf], [0.0, 1.0]]), "not finite"),
        (np.ones((2, 3)), "square"),
        (sp.csr_matrix(np.ones((3, 2))), "square"),
        (np.ones(3), "2-D"),
        (np.array([["a", "b"], ["c", "d"]]), "real numbers"),
        (np.eye(2) * (1 + 1j), "real"),
        (np.zeros((0, 0)), "empty"),
    ],
)
def test_bad_input_raises_value_error_with_a_message(bad, message):
    with pytest.raises(ValueError, match=message):
        penalty_lab.cond2(bad)


def test_bad_options_raise_value_error():
    with pytest.raises(ValueError, match="tol|cond"):
        penalty_lab.cond2(np.eye(2), tol=2.0)
    with pytest.raises(ValueError, match="storage"):
        penalty_lab.cond2(np.eye(2), storage="diagonal")
    with pytest.raises(ValueError, match="other triangle"):
        penalty_lab.cond2(np.ones((2, 2)), storage="lower")


def test_a_singular_matrix_is_reported_not_raised():
    c = penalty_lab.cond2(np.array([[1.0, 1.0], [1.0, 1.0]]))
    assert c.hi == np.inf and c.warnings


@pytest.mark.parametrize("kind", ["spd", "unsymmetric", "singular"])
def test_the_record_equals_the_command_line_tools(tmp_path, kind, cli_binary):
    exe = cli_binary("cond")
    rng = np.random.default_rng(11)
    n = 25
    if kind == "spd":
        b = rng.standard_normal((n, n))
        a = b @ b.T + np.eye(n)
    elif kind == "unsymmetric":
        a = rng.standard_normal((n, n)) + 5 * np.eye(n)
    else:
        a = np.ones((n, n))
    a = sp.coo_matrix(a)
    path = tmp_path / "A.mtx"
    scipy.io.mmwrite(str(path), a, symmetry="general", precision=17)
    cli = json.loads(subprocess.run([exe, str(path), "--json"], check=True, capture_output=True, text=True).stdout)
    py = penalty_lab.cond2(scipy.io.mmread(str(path))).record
    for key in cli:
        if key in ("seconds", "matrix"):
            continue
        assert py[key] == cli[key], key
