//! L of a sparse Cholesky factor column by column, for the margins of the cond₂ certificates
//! (`conditioning::residual`): as a sorted copy in compressed columns
//! ([`SparseLlt::lower_factor`]), or in place ([`SparseLlt::with_columns`]; a supernodal
//! factor's supernodes, no copy).

use super::SparseLlt;
use faer::sparse::linalg::cholesky::SymbolicCholeskyRaw;

/// L of a sparse Cholesky factor `PAPᵀ = LLᵀ` as plain compressed columns
/// ([`SparseLlt::lower_factor`]).
pub struct LowerFactor {
    /// Column pointers (n + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices (permuted order), ascending within each column, the diagonal first.
    pub row_idx: Vec<usize>,
    /// Entries of L.
    pub values: Vec<f64>,
    /// `(PAPᵀ)_ij = A_{fwd[i], fwd[j]}`; None: no permutation.
    pub fwd: Option<Vec<usize>>,
}

impl SparseLlt {
    /// L of `PAPᵀ = LLᵀ` as compressed columns in the permuted order, each column's rows
    /// ascending (the diagonal first), with the permutation: for the a-posteriori residual
    /// `LLᵀ − PAPᵀ` of the cond₂ certificates (`conditioning::certify::posterior_margin`).
    pub fn lower_factor(&self) -> LowerFactor {
        let fwd = self.symbolic.perm().map(|p| p.arrays().0.to_vec());
        if let SymbolicCholeskyRaw::Simplicial(s) = self.symbolic.raw() {
            // The up-looking factorization fills each column in increasing row order, so the
            // columns normally come sorted and are copied as they are.
            let (cp, ri, m) = (s.col_ptr(), s.row_idx(), s.nrows());
            if cp[0] == 0 && (0..m).all(|j| ri[cp[j]..cp[j + 1]].is_sorted()) {
                return LowerFactor {
                    col_ptr: cp.to_vec(),
                    row_idx: ri[..cp[m]].to_vec(),
                    values: self.values[..cp[m]].to_vec(),
                    fwd,
                };
            }
        }
        let (n, len) = (self.symbolic.nrows(), self.values.len());
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        let (mut row_idx, mut values) = (Vec::with_capacity(len), Vec::with_capacity(len));
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (cp, ri) = (s.col_ptr(), s.row_idx());
                let mut col: Vec<(usize, f64)> = Vec::new();
                for j in 0..s.nrows() {
                    col.clear();
                    col.extend((cp[j]..cp[j + 1]).map(|p| (ri[p], self.values[p])));
                    col.sort_by_key(|e| e.0);
                    row_idx.extend(col.iter().map(|e| e.0));
                    values.extend(col.iter().map(|e| e.1));
                    col_ptr.push(row_idx.len());
                }
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef::new(
                    s,
                    &self.values,
                );
                for k in 0..s.n_supernodes() {
                    let node = l.supernode(k);
                    let (start, v, below) = (node.start(), node.val(), node.pattern());
                    let w = v.ncols();
                    for t in 0..w {
                        for r in t..w {
                            row_idx.push(start + r);
                            values.push(v[(r, t)]);
                        }
                        for (r, &i) in below.iter().enumerate() {
                            row_idx.push(i);
                            values.push(v[(w + r, t)]);
                        }
                        col_ptr.push(row_idx.len());
                    }
                }
            }
        }
        LowerFactor {
            col_ptr,
            row_idx,
            values,
            fwd,
        }
    }

    /// Visits L's columns in the permuted order in place: `f(n, fwd, columns)`, where
    /// `columns(visit)` calls `visit(k, l_kk, rows, values)` for every column k with the
    /// entries below its diagonal. A supernodal factor's columns are its supernodes' columns
    /// (no copy of L); a simplicial one goes through [`SparseLlt::lower_factor`]. `fwd`: the
    /// fill-reducing permutation (position → original index), None for the identity.
    #[allow(clippy::type_complexity)]
    pub fn with_columns<R>(
        &self,
        f: impl FnOnce(
            usize,
            Option<&[usize]>,
            &dyn Fn(&mut dyn FnMut(usize, f64, &[usize], &[f64])),
        ) -> R,
    ) -> R {
        let fwd = self.symbolic.perm().map(|p| p.arrays().0);
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => {
                let l = self.lower_factor();
                let n = l.col_ptr.len() - 1;
                let columns = |visit: &mut dyn FnMut(usize, f64, &[usize], &[f64])| {
                    for k in 0..n {
                        let (a, b) = (l.col_ptr[k], l.col_ptr[k + 1]);
                        visit(k, l.values[a], &l.row_idx[a + 1..b], &l.values[a + 1..b]);
                    }
                };
                f(n, fwd, &columns)
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef::new(
                    s,
                    &self.values,
                );
                let columns = |visit: &mut dyn FnMut(usize, f64, &[usize], &[f64])| {
                    let (mut rows, mut copy) = (Vec::new(), Vec::new());
                    for k in 0..s.n_supernodes() {
                        let node = l.supernode(k);
                        let (start, v, below) = (node.start(), node.val(), node.pattern());
                        let w = v.ncols();
                        rows.clear();
                        rows.extend(start..start + w);
                        rows.extend_from_slice(below);
                        for t in 0..w {
                            let col = v.col(t);
                            let vals: &[f64] = match col.try_as_col_major() {
                                Some(c) => c.as_slice(),
                                None => {
                                    copy.clear();
                                    copy.extend((0..col.nrows()).map(|i| col[i]));
                                    &copy
                                }
                            };
                            visit(start + t, vals[t], &rows[t + 1..], &vals[t + 1..]);
                        }
                    }
                };
                f(s.nrows(), fwd, &columns)
            }
        }
    }
}
