//! [`DiagonalPattern`]: a sparse pattern with its whole diagonal and its symbolic analysis,
//! so that every diagonal shift `αA + σI` of a matrix is factorized without a new analysis.

use super::sparse_llt::{cached_entry, cached_permutation, lookup_entry, PermutedUpper, SparseLlt};
use super::symmetric_matvec;
use crate::error::Result;
use faer::sparse::linalg::cholesky::SymbolicCholesky;
use faer::sparse::{SparseColMat, SymbolicSparseColMat, SymbolicSparseColMatRef};
use std::sync::Arc;

/// The pattern of a sparse matrix with every diagonal entry present (inserted as explicit
/// zeros where missing) and its symbolic Cholesky analysis: any matrix with these values
/// changed — shifted `A + σI`, or A with Dirichlet rows/columns replaced by the identity — is
/// factorized numerically without a new analysis.
pub struct DiagonalPattern {
    /// Column pointers and sorted row indices (diagonal included); shared with the symbolic
    /// cache where the pattern is a matrix's own ([`DiagonalPattern::pat`] borrows it).
    pub pattern: Arc<SymbolicSparseColMat<usize>>,
    /// The values of A on that pattern (0 at inserted diagonal positions).
    pub values: Vec<f64>,
    /// `diag[j]`: position of entry (j, j) in `values` (shared like `pattern`).
    pub diag: Arc<Vec<usize>>,
    /// Symbolic Cholesky analysis of the pattern.
    pub symbolic: Arc<SymbolicCholesky<usize>>,
    /// The cached permutation of the pattern (looked up once, not at every factorization).
    pub(super) permuted: Option<Arc<PermutedUpper>>,
}

impl DiagonalPattern {
    /// Copies the pattern of `a` (CSC with sorted row indices), inserting missing diagonals.
    pub fn new(a: &SparseColMat<usize, f64>) -> Result<Self> {
        let n = a.nrows();
        let cp = a.symbolic().col_ptr();
        let ri = a.symbolic().row_idx();
        let av = a.val();
        // Every diagonal stored (the usual case): A's own arrays, copied whole (compact
        // storage from position 0), the analysis and the diagonal's positions from the cache.
        let pat = a.symbolic();
        if pat.col_nnz().is_none() && cp[0] == 0 && n == a.ncols() {
            // A pattern new to the cache is analysed (and kept) only where its diagonal is
            // whole; otherwise the one with the diagonal inserted is, below.
            let entry = match lookup_entry(pat) {
                Some(e) => Some(e),
                None if (0..n).all(|j| crate::system::csc_position(pat, j, j).is_some()) => {
                    cached_entry(pat)?
                }
                None => None,
            };
            if let Some(e) = entry {
                if let Some(diag) = &e.diag {
                    return Ok(DiagonalPattern {
                        pattern: e.pattern.clone(),
                        values: av[..cp[n]].to_vec(),
                        diag: diag.clone(),
                        symbolic: e.symbolic.clone(),
                        permuted: e.permuted.clone(),
                    });
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        let mut row_idx = Vec::with_capacity(ri.len() + n);
        let mut values = Vec::with_capacity(ri.len() + n);
        let mut diag = vec![0; n];
        col_ptr.push(0);
        for j in 0..n {
            let mut have_diag = false;
            for p in cp[j]..cp[j + 1] {
                let i = ri[p];
                if !have_diag && i > j {
                    diag[j] = row_idx.len();
                    row_idx.push(j);
                    values.push(0.0);
                    have_diag = true;
                }
                if i == j {
                    diag[j] = row_idx.len();
                    have_diag = true;
                }
                row_idx.push(i);
                values.push(av[p]);
            }
            if !have_diag {
                diag[j] = row_idx.len();
                row_idx.push(j);
                values.push(0.0);
            }
            col_ptr.push(row_idx.len());
        }
        let pattern = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, row_idx);
        Self::with_pattern(pattern, values, diag)
    }

    /// The analysis of `pattern` (cached) around its values and diagonal positions.
    fn with_pattern(
        pattern: SymbolicSparseColMat<usize>,
        values: Vec<f64>,
        diag: Vec<usize>,
    ) -> Result<Self> {
        let symbolic = SparseLlt::analyze_pattern(pattern.as_ref())?;
        let permuted = cached_permutation(&symbolic, pattern.as_ref());
        Ok(DiagonalPattern {
            pattern: Arc::new(pattern),
            values,
            diag: Arc::new(diag),
            symbolic,
            permuted,
        })
    }

    /// The pattern, borrowed.
    pub fn pat(&self) -> SymbolicSparseColMatRef<'_, usize> {
        (*self.pattern).as_ref()
    }

    /// Numeric Cholesky of the matrix with this pattern and `values` (None if not positive
    /// definite).
    pub fn factor(&self, values: &[f64]) -> Option<SparseLlt> {
        let m = faer::sparse::SparseColMatRef::new(self.pat(), values);
        SparseLlt::factorize_permuted(self.symbolic.clone(), self.permuted.as_deref(), m)
    }

    /// Writes `α·A + σI + β·1_B` on this pattern into `out` (B: the j with `in_b[j]`; no β
    /// term where `in_b` is None), each entry formed as `α·a_ij`, then `+ (σ + β)` on the
    /// diagonal; returns `max_i(|α·a_ii| + |σ| + |β_i|)`, which bounds the diagonal's
    /// formation error (one rounding of each addition). The test matrices of the certified
    /// routes (shifts, inertia tests) are all formed here.
    pub fn fill_shifted(
        &self,
        out: &mut Vec<f64>,
        alpha: f64,
        sigma: f64,
        beta: f64,
        in_b: Option<&[bool]>,
    ) -> f64 {
        out.clear();
        out.extend(self.values.iter().map(|x| alpha * x));
        let mut max_e = 0.0f64;
        for (j, &p) in self.diag.iter().enumerate() {
            let b = match in_b {
                Some(m) if m[j] => beta,
                _ => 0.0,
            };
            max_e = max_e.max(out[p].abs() + sigma.abs() + b.abs());
            out[p] += sigma + b;
        }
        max_e
    }

    /// Row and column `i` of `values` (on this pattern) reduced to their diagonal entry: the
    /// matrix then has the spectrum of the one without row and column i, and that entry
    /// (Cauchy's interlacing tests of `conditioning::temple` and the saddle-point route).
    pub fn pin(&self, values: &mut [f64], i: usize) {
        let (cp, ri) = (self.pattern.col_ptr(), self.pattern.row_idx());
        for j in 0..self.n() {
            let range = cp[j]..cp[j + 1];
            for (&r, v) in ri[range.clone()].iter().zip(&mut values[range]) {
                if (j == i) != (r == i) {
                    *v = 0.0;
                }
            }
        }
    }

    /// `y = A x` with A's values on this pattern (both triangles stored). Every user holds a
    /// symmetric A, so the product is formed as `Aᵀx` column by column (`y_j = Σ_i A_ij x_i`,
    /// a gather: one accumulator per entry of y instead of scattered updates; ≈ 2× faster on
    /// the sweep's Lanczos runs).
    pub fn matvec(&self, x: &[f64], y: &mut [f64]) {
        symmetric_matvec(self.pat(), &self.values, x, y)
    }

    /// Dimension.
    pub fn n(&self) -> usize {
        self.diag.len()
    }

    /// `max_i A_ii` (0 if every diagonal entry is ≤ 0): a lower bound of λ_max, the Rayleigh
    /// quotient of a unit vector.
    pub fn max_diagonal(&self) -> f64 {
        self.diag
            .iter()
            .map(|&p| self.values[p])
            .fold(0.0f64, f64::max)
    }

    /// The smallest diagonal entry (∞ for an empty matrix).
    pub fn min_diagonal(&self) -> f64 {
        self.diag
            .iter()
            .map(|&p| self.values[p])
            .fold(f64::INFINITY, f64::min)
    }
}
