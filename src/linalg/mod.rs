//! Factorizations of K (and of K + D E Dᵀ, and of saddle-point matrices): factorize once,
//! solve many times, read `log10|det|` off the factor.
//!
//! Route selection: symmetric matrices try Cholesky (`LLᵀ`) first; if that fails (indefinite,
//! e.g. a saddle-point matrix) or the matrix is unsymmetric, partial-pivoting LU is used. Dense
//! matrices use faer's dense factorizations, sparse ones faer's sparse Cholesky (with the
//! symbolic analysis kept for reuse — process-wide for the last two patterns,
//! [`SparseLlt::analyze`], together with the fill-reducing permutation of a simplicial
//! pattern applied once and its row structure precomputed, so a numeric factorization of a
//! cached pattern skips faer's per-call permutation and elimination-tree walks) or sparse
//! LU. One right-hand side of a simplicial factor is solved
//! by the same sweeps as faer's solve without its multi-RHS bookkeeping
//! ([`SparseLlt::solve_vec_in_place`]). Both give faer's results bit for bit
//! (`tests/verification/kernels.rs`).
//!
//! A factor whose smallest pivot is at the rounding level of the largest
//! (`pivot ≤ ε_mach · max pivot`) is reported as [`Error::Singular`]: K is singular to working
//! precision and `K⁻¹` does not exist numerically.

pub mod amg;
mod diagonal_pattern;
mod factor_columns;
pub mod krylov;
mod ldlt;
mod pcg;
pub mod precond;
pub mod refine;
mod sparse_llt;

pub use diagonal_pattern::DiagonalPattern;
pub use factor_columns::LowerFactor;
pub use ldlt::InertiaTest;
pub use pcg::{pcg, PcgOutcome};
pub use sparse_llt::{release_thread_buffers, SparseLlt, SYMBOLIC_CACHE_LEN};

use crate::error::{Error, Result};
use crate::system::Stiffness;
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::sparse::linalg::cholesky::SymbolicCholesky;
use faer::sparse::linalg::solvers::Lu as SparseLu;
use faer::sparse::SymbolicSparseColMatRef;
use faer::{Mat, MatMut, Side};
use std::sync::Arc;

/// Which factorization was used.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FactorKind {
    /// Dense Cholesky LLᵀ.
    DenseCholesky,
    /// Dense LU with partial pivoting.
    DenseLu,
    /// Sparse supernodal/simplicial Cholesky (AMD ordering).
    SparseCholesky,
    /// Sparse LU (COLAMD ordering).
    SparseLu,
}

/// `y = A x` for a symmetric A stored in CSC with both triangles (`pattern`, `values`), formed
/// as `Aᵀx` column by column: `y_j = Σ_i A_ij x_i`, a gather (one accumulator per entry of y
/// instead of scattered updates).
pub fn symmetric_matvec(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    x: &[f64],
    y: &mut [f64],
) {
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    for (j, yj) in y.iter_mut().enumerate() {
        let (a, b) = (cp[j], cp[j + 1]);
        *yj = ri[a..b]
            .iter()
            .zip(&values[a..b])
            .map(|(&i, &v)| v * x[i])
            .sum();
    }
}

enum Inner {
    DenseLlt(faer::linalg::solvers::Llt<f64>),
    DenseLu(PartialPivLu<f64>),
    SparseLlt(SparseLlt),
    SparseLu(SparseLu<usize, f64>),
}

/// `Σ power·log10|d_i|`: `log10|det|` from a factor's pivots.
fn log10_sum(d: &[f64], power: f64) -> f64 {
    d.iter().map(|v| power * v.abs().log10()).sum()
}

/// A factorization of a square matrix, with solve and `log10|det|`.
pub struct Factorization {
    inner: Inner,
    n: usize,
}

impl std::fmt::Debug for Factorization {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Factorization")
            .field("kind", &self.kind())
            .field("n", &self.n)
            .finish_non_exhaustive()
    }
}

impl Factorization {
    /// Factorizes `a`. `symmetric` selects Cholesky first (pass `a.is_symmetric()` when unsure).
    /// Errors with [`Error::Singular`] when the matrix is singular to working precision.
    pub fn new(a: &Stiffness, symmetric: bool) -> Result<Self> {
        Self::with_symbolic(a, symmetric, None)
    }

    /// Like [`Factorization::new`], reusing a sparse symbolic Cholesky analysis if given
    /// (the pattern must match).
    pub fn with_symbolic(
        a: &Stiffness,
        symmetric: bool,
        symbolic: Option<Arc<SymbolicCholesky<usize>>>,
    ) -> Result<Self> {
        let n = a.n();
        let inner = match a {
            Stiffness::Dense(m) => {
                let llt = if symmetric {
                    m.llt(Side::Lower).ok()
                } else {
                    None
                };
                match llt {
                    Some(l) => Inner::DenseLlt(l),
                    None => Inner::DenseLu(m.partial_piv_lu()),
                }
            }
            Stiffness::Sparse(m) => {
                let llt = if symmetric {
                    let sym = match symbolic {
                        Some(s) => s,
                        None => SparseLlt::analyze(m)?,
                    };
                    SparseLlt::factorize(sym, m)
                } else {
                    None
                };
                match llt {
                    Some(l) => Inner::SparseLlt(l),
                    // faer's sparse LU does not expose U's diagonal: log|det| is then
                    // computed by the metrics module when asked for.
                    None => Inner::SparseLu(m.sp_lu().map_err(|e| {
                        Error::singular(format!("sparse LU failed ({e:?}): matrix is singular"))
                    })?),
                }
            }
        };
        let f = Factorization { inner, n };
        // The pivots, read once: the smallest over the largest, and a sum of logs that is
        // finite unless one is zero, infinite or NaN (formed only then, for the message).
        if let Some((d, power)) = f.pivots() {
            let amax = d.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            let amin = d.iter().fold(f64::INFINITY, |a, v| a.min(v.abs()));
            let ratio = (amin / amax).powf(power);
            if ratio.is_finite() && ratio <= f64::EPSILON {
                return Err(Error::singular(format!(
                    "{n}×{n} matrix is singular to working precision \
                     (smallest/largest pivot = {ratio:.3e})"
                )));
            }
            if !d.iter().all(|v| v.is_finite() && *v != 0.0) {
                let ld = log10_sum(&d, power);
                return Err(Error::singular(format!(
                    "{n}×{n} matrix has a zero pivot (log10|det| = {ld})"
                )));
            }
        }
        Ok(f)
    }

    /// The factor's pivots and the power they enter `|det|` with (2 for Cholesky's L, 1 for
    /// LU's U), read off the factor when asked (not kept: n words per live factor); `None`
    /// for sparse LU.
    fn pivots(&self) -> Option<(Vec<f64>, f64)> {
        let n = self.n;
        match &self.inner {
            Inner::DenseLlt(l) => Some(((0..n).map(|i| l.L()[(i, i)]).collect(), 2.0)),
            Inner::DenseLu(lu) => Some(((0..n).map(|i| lu.U()[(i, i)]).collect(), 1.0)),
            Inner::SparseLlt(l) => Some((l.l_diagonal(), 2.0)),
            Inner::SparseLu(_) => None,
        }
    }

    /// Which factorization was used.
    pub fn kind(&self) -> FactorKind {
        match self.inner {
            Inner::DenseLlt(_) => FactorKind::DenseCholesky,
            Inner::DenseLu(_) => FactorKind::DenseLu,
            Inner::SparseLlt(_) => FactorKind::SparseCholesky,
            Inner::SparseLu(_) => FactorKind::SparseLu,
        }
    }

    /// The sparse symbolic analysis, for reuse on matrices of the same pattern.
    pub fn symbolic(&self) -> Option<Arc<SymbolicCholesky<usize>>> {
        match &self.inner {
            Inner::SparseLlt(l) => Some(l.symbolic()),
            _ => None,
        }
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.n
    }

    /// `log10|det A|` from the factor's pivots (`None` for sparse LU).
    pub fn log10_abs_det(&self) -> Option<f64> {
        self.pivots().map(|(d, power)| log10_sum(&d, power))
    }

    /// Solves `A X = B` in place for a block of right-hand sides.
    pub fn solve_mat_in_place(&self, mut b: MatMut<'_, f64>) {
        match &self.inner {
            Inner::DenseLlt(l) => l.solve_in_place(b.as_mut()),
            Inner::DenseLu(l) => l.solve_in_place(b.as_mut()),
            Inner::SparseLlt(l) => l.solve_in_place(b.as_mut()),
            Inner::SparseLu(l) => l.solve_in_place(b.as_mut()),
        }
    }

    /// Solves `A x = b` in place (`x` holds b on entry).
    pub fn solve_vec_in_place(&self, x: &mut [f64]) {
        if let Inner::SparseLlt(l) = &self.inner {
            return l.solve_vec_in_place(x);
        }
        let n = x.len();
        self.solve_mat_in_place(MatMut::from_column_major_slice_mut(x, n, 1));
    }

    /// Solves `A x = b`.
    pub fn solve(&self, b: &[f64]) -> Vec<f64> {
        let mut x = b.to_vec();
        self.solve_vec_in_place(&mut x);
        x
    }

    /// Solves `A X = E_D` where the columns of `E_D` are unit vectors at `dofs`:
    /// returns `X = A⁻¹ D` (N×m), one block solve.
    pub fn solve_unit_columns(&self, dofs: &[usize]) -> Mat<f64> {
        let cols: Vec<[(usize, f64); 1]> = dofs.iter().map(|&d| [(d, 1.0)]).collect();
        let cols: Vec<&[(usize, f64)]> = cols.iter().map(|c| c.as_slice()).collect();
        self.solve_sparse_columns(&cols)
    }

    /// `A⁻¹ B` for B (n × cols.len()) given column by column as `(row, value)` entries (each
    /// row at most once per column): W = K⁻¹D from the constraint rows.
    pub fn solve_sparse_columns(&self, cols: &[&[(usize, f64)]]) -> Mat<f64> {
        let mut x = Mat::zeros(self.n, cols.len());
        for (c, col) in cols.iter().enumerate() {
            for &(d, v) in col.iter() {
                x[(d, c)] = v;
            }
        }
        self.solve_mat_in_place(x.as_mut());
        x
    }
}

impl Stiffness {
    /// `u0 = K⁻¹ q` by one factorization (Cholesky where K is SPD, else LU): the
    /// unconstrained displacement, e.g. to place obstacles in a generated scene. Errors where
    /// K is singular to working precision.
    pub fn solve(&self, q: &[f64]) -> Result<Vec<f64>> {
        Ok(Factorization::new(self, true)?.solve(q))
    }
}

/// Test matrices shared by the unit tests of `linalg` and `conditioning`.
#[cfg(test)]
pub(crate) mod test_matrices {
    use faer::sparse::{SparseColMat, Triplet};

    /// The n×n second-difference matrix tridiag(−1, 2, −1) (both triangles): the test matrix
    /// with closed-form eigenvalues, shared by the unit tests.
    pub(crate) fn second_difference(n: usize) -> SparseColMat<usize, f64> {
        let mut t = Vec::new();
        for i in 0..n {
            t.push(Triplet::new(i, i, 2.0));
            if i + 1 < n {
                t.push(Triplet::new(i, i + 1, -1.0));
                t.push(Triplet::new(i + 1, i, -1.0));
            }
        }
        SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
    }
}
