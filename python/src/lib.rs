//! The compiled part of the Python module `penalty_lab` (`penalty_lab._penalty_lab`): thin
//! entry points over the Rust library, each taking plain buffers (the Python package,
//! `penalty_lab/__init__.py`, turns NumPy arrays and SciPy matrices into them) and returning
//! the JSON record the command-line tool prints, so that Python and the CLI give the same
//! numbers from the same code.
//!
//! Errors: the library's error, one line (the CLI's message without its `error: ` prefix), as
//! `ValueError`; a panic is caught by pyo3 and raised as `PanicException`, never a crash of the
//! interpreter. The GIL is released for the numerical work.

use penalty_lab::error::Error;
use penalty_lab::metrics::solver::SolverOptions;
use penalty_lab::metrics::MetricSet;
use penalty_lab::scene::{read_scene, Scene};
use penalty_lab::strategy::{registry, Knobs};
use penalty_lab::study::cond::cond_of_matrix;
use penalty_lab::study::solve::{solve_loaded, SolveOptions};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::Path;

/// The library's error as a Python `ValueError` with the CLI's one-line message.
fn value_error(e: Error) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// Native-endian 8-byte words of `bytes` (`what` names the buffer in the error).
fn words<T>(bytes: &[u8], what: &str, read: impl Fn([u8; 8]) -> T) -> Result<Vec<T>, Error> {
    if bytes.len() % 8 != 0 {
        return Err(Error::input(format!(
            "{what}: {} bytes is not a whole number of 8-byte values",
            bytes.len()
        )));
    }
    Ok(bytes
        .chunks_exact(8)
        .map(|c| read(c.try_into().expect("chunks of 8")))
        .collect())
}

/// The n×n matrix of the COO triplets (row, col: int64; val: float64, native byte order),
/// duplicates summed, in the storage the library prefers for its structure (as `cond` and
/// `solve` read a file), with its stored entries (after summing duplicates).
fn matrix(n: usize, rows: &[u8], cols: &[u8], vals: &[u8]) -> Result<(Stiffness, usize), Error> {
    let r = words(rows, "row indices", i64::from_ne_bytes)?;
    let c = words(cols, "column indices", i64::from_ne_bytes)?;
    let v = words(vals, "values", f64::from_ne_bytes)?;
    if r.len() != v.len() || c.len() != v.len() {
        return Err(Error::input(format!(
            "COO arrays of different lengths: {} rows, {} columns, {} values",
            r.len(),
            c.len(),
            v.len()
        )));
    }
    if n == 0 {
        return Err(Error::input("the matrix is empty (0 × 0)"));
    }
    let index = |x: i64, what: &str, k: usize| -> Result<usize, Error> {
        usize::try_from(x).ok().filter(|&i| i < n).ok_or_else(|| {
            Error::input(format!("entry {k}: {what} index {x} outside 0 … {}", n - 1))
        })
    };
    let mut t = Vec::with_capacity(v.len());
    for (k, ((&i, &j), &x)) in r.iter().zip(&c).zip(&v).enumerate() {
        if !x.is_finite() {
            return Err(Error::not_finite(format!("entry {k} ({i}, {j}) = {x}")));
        }
        t.push((index(i, "row", k)?, index(j, "column", k)?, x));
    }
    let a = Stiffness::from_triplets(n, &t)?;
    let nnz = a.nnz();
    Ok((a.in_preferred_storage(), nnz))
}

/// The certified cond₂ of the n×n COO matrix, as the JSON of `cond --json` (`name`: its
/// `matrix` field; `tol`: the relative accuracy asked, `None` the contract).
#[pyfunction]
#[pyo3(signature = (n, rows, cols, vals, tol=None, name=None))]
fn cond2_coo(
    py: Python<'_>,
    n: usize,
    rows: &[u8],
    cols: &[u8],
    vals: &[u8],
    tol: Option<f64>,
    name: Option<String>,
) -> PyResult<String> {
    let name = name.unwrap_or_else(|| "<python>".into());
    py.detach(|| -> Result<String, Error> {
        MetricSet::check_cond_tol(tol)?;
        let (a, nnz) = matrix(n, rows, cols, vals)?;
        let mut r = cond_of_matrix(&a, name, tol)?;
        r.nnz = nnz;
        serde_json::to_string(&r).map_err(|e| Error::Numerical(format!("JSON: {e}")))
    })
    .map_err(value_error)
}

/// The m constraint rows of the COO matrix D (row = constraint, column = DOF; terms in the
/// order given, duplicates of one (row, DOF) summed), with their limits and kinds
/// (`"upper"`: d_cᵀu ≤ û_c; `"lower"`: d_cᵀu ≥ û_c; `"bilateral"`: d_cᵀu = û_c).
fn constraints(
    n: usize,
    d: (&[u8], &[u8], &[u8]),
    limits: &[u8],
    kinds: &[String],
) -> Result<Vec<Constraint>, Error> {
    let limits = words(limits, "limits", f64::from_ne_bytes)?;
    let m = limits.len();
    if kinds.len() != m {
        return Err(Error::input(format!(
            "{m} limits but {} kinds (one per constraint)",
            kinds.len()
        )));
    }
    let r = words(d.0, "D's row indices", i64::from_ne_bytes)?;
    let c = words(d.1, "D's column indices", i64::from_ne_bytes)?;
    let v = words(d.2, "D's values", f64::from_ne_bytes)?;
    if r.len() != v.len() || c.len() != v.len() {
        return Err(Error::input("D: COO arrays of different lengths"));
    }
    let mut terms: Vec<Vec<(usize, f64)>> = vec![Vec::new(); m];
    for (k, ((&i, &j), &x)) in r.iter().zip(&c).zip(&v).enumerate() {
        let row = usize::try_from(i).ok().filter(|&i| i < m).ok_or_else(|| {
            Error::input(format!(
                "D entry {k}: constraint index {i} outside 0 … {m} − 1"
            ))
        })?;
        let dof = usize::try_from(j).ok().filter(|&j| j < n).ok_or_else(|| {
            Error::input(format!("D entry {k}: DOF index {j} outside 0 … {}", n - 1))
        })?;
        // Non-finite coefficients and limits: `Problem::new` names the constraint.
        match terms[row].iter_mut().find(|t| t.0 == dof) {
            Some(t) => t.1 += x,
            None => terms[row].push((dof, x)),
        }
    }
    terms
        .into_iter()
        .zip(limits)
        .zip(kinds)
        .map(|((t, l), kind)| {
            let kind = ConstraintKind::from_name(kind).ok_or_else(|| {
                Error::input(format!(
                    "constraint kind '{kind}': must be 'upper', 'lower' or 'bilateral'"
                ))
            })?;
            Ok(Constraint::row(t, l, kind))
        })
        .collect()
}

/// One strategy on K u = q − Dᵀ r with the constraint rows of D (COO, m × n), as the JSON object
/// `solve --json` prints for the same scene (same keys, same values bit for bit; `seconds`
/// aside). `metrics`: cond₂ and determinants (`False`: `--no-metrics`); `solver_metrics`:
/// `None` their default (up to 1 000 unknowns), `True`/`False` as `--solver-metrics` /
/// `--no-solver-metrics`.
#[pyfunction]
#[pyo3(signature = (
    n, k_rows, k_cols, k_vals, q, d_rows, d_cols, d_vals, limits, kinds, method,
    eps=None, factor=None, delta=None, tol=None, adaptive=false,
    metrics=true, solver_metrics=None, cond_tol=None, exact_start=false, name=None
))]
#[allow(clippy::too_many_arguments)]
fn solve_coo(
    py: Python<'_>,
    n: usize,
    k_rows: &[u8],
    k_cols: &[u8],
    k_vals: &[u8],
    q: &[u8],
    d_rows: &[u8],
    d_cols: &[u8],
    d_vals: &[u8],
    limits: &[u8],
    kinds: Vec<String>,
    method: String,
    eps: Option<f64>,
    factor: Option<f64>,
    delta: Option<f64>,
    tol: Option<f64>,
    adaptive: bool,
    metrics: bool,
    solver_metrics: Option<bool>,
    cond_tol: Option<f64>,
    exact_start: bool,
    name: Option<String>,
) -> PyResult<String> {
    py.detach(|| -> Result<String, Error> {
        let strategy = registry::lookup(&method)?;
        let (k, _) = matrix(n, k_rows, k_cols, k_vals)?;
        // q's length and finiteness: checked by `Problem::new`, as for a scene.
        let q = words(q, "q", f64::from_ne_bytes)?;
        let cons = constraints(n, (d_rows, d_cols, d_vals), limits, &kinds)?;
        let problem = Problem::new(k, q, cons)?.in_preferred_storage();
        let scene = Scene {
            name: name.unwrap_or_else(|| "<python>".into()),
            description: None,
            problem,
            meta: None,
            nodes: None,
        };
        let knobs = Knobs {
            eps,
            factor,
            delta,
            tol,
            adaptive,
            ..Knobs::NONE
        };
        let opts = SolveOptions {
            no_metrics: !metrics,
            no_solver_metrics: solver_metrics == Some(false),
            solver_metrics: solver_metrics == Some(true),
            exact_start,
            cond_tol,
            krylov: SolverOptions::default(),
            write_system: None,
            vtk: None,
        };
        let v = solve_loaded(&scene, strategy, knobs, &opts)?;
        serde_json::to_string(&v).map_err(|e| Error::Numerical(format!("JSON: {e}")))
    })
    .map_err(value_error)
}

/// The scene file at `path` as JSON of plain arrays: `name`, `n`, K's stored entries
/// (`k_rows`, `k_cols`, `k_vals`, column by column), `q`, D's entries (`d_rows` = the
/// constraint, `d_cols` = the DOF, `d_vals`), `limits` and `kinds`.
#[pyfunction]
fn read_scene_json(py: Python<'_>, path: String) -> PyResult<String> {
    py.detach(|| -> Result<String, Error> {
        let sc = read_scene(Path::new(&path))?;
        let p = &sc.problem;
        let (mut kr, mut kc, mut kv) = (Vec::new(), Vec::new(), Vec::new());
        p.k.for_each_entry(|i, j, v| {
            kr.push(i);
            kc.push(j);
            kv.push(v);
        });
        let (mut dr, mut dc, mut dv) = (Vec::new(), Vec::new(), Vec::new());
        for (c, con) in p.constraints.iter().enumerate() {
            for &(j, a) in &con.terms {
                dr.push(c);
                dc.push(j);
                dv.push(a);
            }
        }
        let v = serde_json::json!({
            "name": sc.name, "n": p.n(),
            "k_rows": kr, "k_cols": kc, "k_vals": kv, "q": p.q,
            "d_rows": dr, "d_cols": dc, "d_vals": dv,
            "limits": p.constraints.iter().map(|c| c.limit).collect::<Vec<_>>(),
            "kinds": p.constraints.iter().map(|c| c.kind).collect::<Vec<_>>(),
        });
        serde_json::to_string(&v).map_err(|e| Error::Numerical(format!("JSON: {e}")))
    })
    .map_err(value_error)
}

/// The library's version (`penalty_lab.__version__`).
#[pyfunction]
fn version() -> &'static str {
    penalty_lab::provenance::VERSION
}

#[pymodule]
fn _penalty_lab(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cond2_coo, m)?)?;
    m.add_function(wrap_pyfunction!(solve_coo, m)?)?;
    m.add_function(wrap_pyfunction!(read_scene_json, m)?)?;
    m.add_function(wrap_pyfunction!(version, m)?)?;
    Ok(())
}
