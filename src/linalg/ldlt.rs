//! Sparse `PBPᵀ = L D Lᵀ` without pivoting, for inertia tests of symmetric matrices that are
//! not positive definite (the cond₂ certificates' bound of λ₂, `conditioning::temple`).
//!
//! By Sylvester's law of inertia the signs of the pivots `d_k` are the signs of the
//! eigenvalues of `L̂D̂L̂ᵀ`; how far that computed product is from B is bounded in
//! `conditioning::temple` from `|L̂||D̂||L̂ᵀ|`, which grows where a pivot is small (no pivoting:
//! the bound, not the factorization, says what the test proves).
//!
//! Why hand-written: faer's sparse LDLᵀ (`factorize_simplicial_numeric_ldlt`) runs the same
//! up-looking algorithm, but the cached permuted pattern of [`DiagonalPattern`] (its row
//! structure precomputed) saves the per-call permutation and elimination-tree walks: the
//! kernel is the Cholesky kernel's (`sparse_llt::simplicial_numeric`) with `L_kj = w_j / d_j`,
//! `d_k = b_kk − Σ_j L_kj w_j` in place of the square roots.

use super::diagonal_pattern::DiagonalPattern;
use super::sparse_llt::simplicial_numeric;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;

/// A computed `PB̃Pᵀ ≈ L̂D̂L̂ᵀ` and its inertia: L̂ unit lower triangular in compressed columns
/// (each column's rows ascending, the diagonal first) with `d_k` stored in place of its unit
/// diagonal; the structure and P borrowed from the pattern's analysis.
pub struct InertiaTest<'a> {
    /// Column pointers (n + 1).
    pub col_ptr: &'a [usize],
    /// Row indices (permuted order).
    pub row_idx: &'a [usize],
    /// `d_k` at each column's first position, `L̂_ik` below.
    pub values: Vec<f64>,
    /// `(PB̃Pᵀ)_ij = B̃_{fwd[i], fwd[j]}`; None: no permutation.
    pub fwd: Option<&'a [usize]>,
    /// The pivots `d_k < 0`.
    pub negative: usize,
}

impl DiagonalPattern {
    /// Whether [`DiagonalPattern::ldlt`] can run: the analysis is simplicial with a cached
    /// permutation.
    pub fn has_ldlt(&self) -> bool {
        self.permuted.is_some() && matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Simplicial(_))
    }

    /// `PB̃Pᵀ = L̂D̂L̂ᵀ` of the matrix with this pattern and `values`, in the ordering of the
    /// pattern's simplicial analysis. None where the analysis is not simplicial with a cached
    /// permutation (large factors: supernodal), or where a pivot is zero or not finite.
    pub fn ldlt(&self, values: &[f64]) -> Option<InertiaTest<'_>> {
        let pu = self.permuted.as_deref()?;
        let SymbolicCholeskyRaw::Simplicial(s) = self.symbolic.raw() else {
            return None;
        };
        let (l_cp, l_ri) = (s.col_ptr(), s.row_idx());
        let mut l = vec![0.0f64; l_ri.len()];
        let negative = simplicial_numeric::<true>(pu, values, l_cp, l_ri, &mut l)?;
        Some(InertiaTest {
            col_ptr: l_cp,
            row_idx: l_ri,
            values: l,
            fwd: self.symbolic.perm().map(|p| p.arrays().0),
            negative,
        })
    }
}

#[cfg(test)]
mod tests {
    /// The inertia of `T − τI` for the second difference T = tridiag(−1, 2, −1) (closed-form
    /// eigenvalues `2 − 2cos(jπ/(n+1))`): the number of negative pivots is the number of
    /// eigenvalues below τ, and `L̂D̂L̂ᵀ` reproduces the permuted matrix to rounding.
    #[test]
    fn pivots_count_the_eigenvalues_below_the_shift() {
        let n = 60;
        let a = crate::linalg::test_matrices::second_difference(n);
        let pattern = super::DiagonalPattern::new(&a).unwrap();
        let th = std::f64::consts::PI / (n as f64 + 1.0);
        let lambda = |j: usize| 2.0 - 2.0 * (j as f64 * th).cos();
        let shifts = [
            (0.5 * (lambda(1) + lambda(2)), 1),
            (0.5 * (lambda(7) + lambda(8)), 7),
        ];
        for (tau, below) in shifts {
            let mut v = pattern.values.clone();
            for &p in pattern.diag.iter() {
                v[p] -= tau;
            }
            let test = pattern.ldlt(&v).expect("simplicial, no zero pivot");
            assert_eq!(test.negative, below, "τ = {tau}");
            // Reconstruct (L̂D̂L̂ᵀ)_ij densely and compare with P(T − τI)Pᵀ.
            let f = &test;
            let mut dense = vec![vec![0.0f64; n]; n];
            let mut abs = vec![vec![0.0f64; n]; n];
            for k in 0..n {
                let (a0, b0) = (f.col_ptr[k], f.col_ptr[k + 1]);
                let d = f.values[a0];
                let col: Vec<(usize, f64)> = std::iter::once((k, 1.0))
                    .chain((a0 + 1..b0).map(|p| (f.row_idx[p], f.values[p])))
                    .collect();
                for &(i, li) in &col {
                    for &(j, lj) in &col {
                        dense[i][j] += li * d * lj;
                        abs[i][j] += (li * d * lj).abs();
                    }
                }
            }
            let fwd: Vec<usize> = f.fwd.map_or_else(|| (0..n).collect(), |p| p.to_vec());
            for i in 0..n {
                for j in 0..n {
                    let (oi, oj) = (fwd[i], fwd[j]);
                    let b = if oi == oj {
                        2.0 - tau
                    } else if oi.abs_diff(oj) == 1 {
                        -1.0
                    } else {
                        0.0
                    };
                    // Backward error of LDLᵀ: γ_{r+4}·(|L̂||D̂||L̂ᵀ|)_ij (r ≤ 3 here), and the
                    // reconstruction's own rounding as much again.
                    let tol = 16.0 * f64::EPSILON * abs[i][j];
                    assert!((dense[i][j] - b).abs() <= tol, "({i},{j})");
                }
            }
        }
    }
}
