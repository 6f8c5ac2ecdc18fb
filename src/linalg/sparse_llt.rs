//! Sparse Cholesky `PAPᵀ = LLᵀ` ([`SparseLlt`]) with the symbolic analysis cached per
//! pattern, and the simplicial numeric and solve kernels (also those of
//! [`DiagonalPattern`](super::DiagonalPattern): one analysis for every diagonal shift of a
//! pattern).

use crate::error::{Error, Result};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, LltRef, SymbolicCholesky, SymbolicCholeskyRaw,
};
use faer::sparse::{SparseColMat, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};
use std::sync::{Arc, Mutex};

/// The cached permuted upper triangle of the pattern `pat` analysed as `symbolic` (the same
/// analysis, by pointer, and the same pattern), if any.
pub(super) fn cached_permutation(
    symbolic: &Arc<SymbolicCholesky<usize>>,
    pat: SymbolicSparseColMatRef<'_, usize>,
) -> Option<Arc<PermutedUpper>> {
    if pat.col_nnz().is_some() {
        return None;
    }
    cached(|e| {
        Arc::ptr_eq(&e.symbolic, symbolic)
            && e.pattern.col_ptr() == pat.col_ptr()
            && e.pattern.row_idx() == pat.row_idx()
    })?
    .permuted
    .clone()
}

/// The cached analysis that `hit` accepts: this thread's recent entries first, then the
/// process-wide cache (whose entry is then kept on this thread too). The process-wide cache
/// is behind a lock that every factorization of two threads would otherwise contend for.
pub(super) fn cached(hit: impl Fn(&CachedSymbolic) -> bool) -> Option<Arc<CachedSymbolic>> {
    let local = LOCAL_SYMBOLIC.with(|l| l.borrow().iter().find(|e| hit(e)).cloned());
    if local.is_some() {
        return local;
    }
    let found = {
        let cache = SYMBOLIC_CACHE.lock().unwrap_or_else(|e| e.into_inner());
        cache.iter().find(|e| hit(e)).cloned()
    }?;
    LOCAL_SYMBOLIC.with(|l| push_bounded(&mut l.borrow_mut(), found.clone()));
    Some(found)
}

/// The symbolic analysis of `pat` (AMD ordering), not cached.
pub(super) fn analyse_symbolic(
    pat: SymbolicSparseColMatRef<'_, usize>,
) -> Result<Arc<SymbolicCholesky<usize>>> {
    factorize_symbolic_cholesky(pat, Side::Lower, Default::default(), Default::default())
        .map(Arc::new)
        .map_err(|e| Error::Numerical(format!("sparse symbolic Cholesky failed: {e:?}")))
}

/// The cache's entry of a compressed square pattern, analysed and added where missing;
/// `None` for a pattern the cache does not keep (uncompressed or not square).
pub(super) fn cached_entry(
    pat: SymbolicSparseColMatRef<'_, usize>,
) -> Result<Option<Arc<CachedSymbolic>>> {
    if pat.col_nnz().is_some() || pat.nrows() != pat.ncols() {
        return Ok(None);
    }
    if let Some(e) = lookup_entry(pat) {
        return Ok(Some(e));
    }
    let (n, cp, ri) = (pat.ncols(), pat.col_ptr(), pat.row_idx());
    let symbolic = analyse_symbolic(pat)?;
    let compact_sorted = cp[0] == 0
        && ri.len() == cp[n]
        && (0..n).all(|j| ri[cp[j]..cp[j + 1]].windows(2).all(|w| w[0] < w[1]));
    let diag = compact_sorted
        .then(|| {
            (0..n)
                .map(|j| crate::system::csc_position(pat, j, j))
                .collect()
        })
        .flatten()
        .map(Arc::new);
    let entry = Arc::new(CachedSymbolic {
        pattern: Arc::new(SymbolicSparseColMat::new_unsorted_checked(
            n,
            n,
            cp.to_vec(),
            None,
            ri.to_vec(),
        )),
        permuted: PermutedUpper::new(pat, &symbolic).map(Arc::new),
        symbolic,
        diag,
    });
    let mut cache = SYMBOLIC_CACHE.lock().unwrap_or_else(|e| e.into_inner());
    push_bounded(&mut cache, entry.clone());
    drop(cache);
    LOCAL_SYMBOLIC.with(|l| push_bounded(&mut l.borrow_mut(), entry.clone()));
    Ok(Some(entry))
}

/// The cache's entry of `pat` (compressed, square), if it has one.
pub(super) fn lookup_entry(pat: SymbolicSparseColMatRef<'_, usize>) -> Option<Arc<CachedSymbolic>> {
    let (cp, ri) = (pat.col_ptr(), pat.row_idx());
    cached(|e| e.pattern.col_ptr() == cp && e.pattern.row_idx() == ri)
}

/// Appends `e`, dropping the oldest entry beyond [`SYMBOLIC_CACHE_LEN`].
fn push_bounded(list: &mut Vec<Arc<CachedSymbolic>>, e: Arc<CachedSymbolic>) {
    if list.len() == SYMBOLIC_CACHE_LEN {
        list.remove(0);
    }
    list.push(e);
}

thread_local! {
    /// This thread's recently used entries of [`SYMBOLIC_CACHE`].
    static LOCAL_SYMBOLIC: std::cell::RefCell<Vec<Arc<CachedSymbolic>>> =
        const { std::cell::RefCell::new(Vec::new()) };
}

/// Number of patterns whose symbolic Cholesky analysis [`SparseLlt::analyze`] keeps.
pub const SYMBOLIC_CACHE_LEN: usize = 2;

/// A pattern (compressed, square) and its symbolic analysis.
pub(super) struct CachedSymbolic {
    /// The pattern as analysed (its column pointers and row indices are the cache's key).
    pub(super) pattern: Arc<SymbolicSparseColMat<usize>>,
    pub(super) symbolic: Arc<SymbolicCholesky<usize>>,
    /// The permuted upper triangle, where the analysis is simplicial with a permutation.
    pub(super) permuted: Option<Arc<PermutedUpper>>,
    /// `diag[j]`: the position of entry (j, j), where the pattern is stored from position 0
    /// with sorted columns and every diagonal entry
    /// ([`DiagonalPattern::new`](super::DiagonalPattern::new) of a matrix with this pattern
    /// then shares it and the pattern).
    pub(super) diag: Option<Arc<Vec<usize>>>,
}

/// The last [`SYMBOLIC_CACHE_LEN`] analyses, oldest first.
static SYMBOLIC_CACHE: Mutex<Vec<Arc<CachedSymbolic>>> = Mutex::new(Vec::new());
/// Sparse Cholesky factor with access to its diagonal (for log-det) and a shareable symbolic
/// analysis (same pattern ⇒ reuse across penalty values).
pub struct SparseLlt {
    pub(super) symbolic: Arc<SymbolicCholesky<usize>>,
    pub(super) values: Vec<f64>,
}

impl SparseLlt {
    /// Symbolic analysis of the lower triangle of `a` (AMD ordering, supernodal or simplicial
    /// structure). The analyses of the last [`SYMBOLIC_CACHE_LEN`] patterns are kept
    /// process-wide (and the last ones each thread used, on that thread) and returned for an
    /// identical pattern (compared entry by entry): a solve and the cond₂ of K and of the
    /// penalized system share one analysis. The analysis depends only on the pattern, so a
    /// cached one is the one a new analysis would compute.
    pub fn analyze(a: &SparseColMat<usize, f64>) -> Result<Arc<SymbolicCholesky<usize>>> {
        Self::analyze_pattern(a.symbolic())
    }

    /// [`SparseLlt::analyze`] of a pattern.
    pub fn analyze_pattern(
        pat: SymbolicSparseColMatRef<'_, usize>,
    ) -> Result<Arc<SymbolicCholesky<usize>>> {
        if let Some(e) = cached_entry(pat)? {
            return Ok(e.symbolic.clone());
        }
        analyse_symbolic(pat)
    }

    /// Numeric factorization with a given symbolic analysis (same pattern as `a`).
    pub fn factorize(
        symbolic: Arc<SymbolicCholesky<usize>>,
        a: &SparseColMat<usize, f64>,
    ) -> Option<Self> {
        Self::factorize_ref(symbolic, a.as_ref())
    }

    /// [`SparseLlt::factorize`] of a borrowed matrix.
    pub fn factorize_ref(
        symbolic: Arc<SymbolicCholesky<usize>>,
        a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    ) -> Option<Self> {
        let permuted = cached_permutation(&symbolic, a.symbolic());
        Self::factorize_permuted(symbolic, permuted.as_deref(), a)
    }

    /// [`SparseLlt::factorize_ref`] with the cached permutation of the pattern already looked
    /// up (`permuted`, where there is one).
    pub(super) fn factorize_permuted(
        symbolic: Arc<SymbolicCholesky<usize>>,
        permuted: Option<&PermutedUpper>,
        a: faer::sparse::SparseColMatRef<'_, usize, f64>,
    ) -> Option<Self> {
        let len = symbolic.len_val();
        let (ok, values) = match (permuted, symbolic.raw()) {
            // A cached simplicial pattern: faer's simplicial numeric factorization of the
            // permuted upper triangle, gathered through the cached map (`PermutedUpper`).
            // Our kernel writes every entry of L, so its buffer need not be zeroed first.
            (Some(pu), SymbolicCholeskyRaw::Simplicial(s)) => {
                let mut values = recycled_values(len, false);
                let ok = simplicial_llt_numeric(pu, a.val(), s.col_ptr(), s.row_idx(), &mut values);
                (ok, values)
            }
            _ => {
                let mut values = recycled_values(len, true);
                let par = Par::Seq;
                let req = symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default());
                let ok = with_scratch(req, |stack| {
                    symbolic
                        .factorize_numeric_llt(
                            &mut values,
                            a,
                            Side::Lower,
                            Default::default(),
                            par,
                            stack,
                            Default::default(),
                        )
                        .is_ok()
                });
                (ok, values)
            }
        };
        if ok {
            Some(SparseLlt { symbolic, values })
        } else {
            recycle_values(values);
            None
        }
    }

    /// Is the factor supernodal? faer chooses the supernodal structure where the
    /// factorization costs more than 40 flops per entry of L; below that (simplicial), one
    /// numeric factorization costs only a few solves with the factor (Σ c_j² against
    /// 4 Σ c_j flops for the column counts c_j of L: 3.3 solves on the 400-DOF membrane).
    pub fn is_supernodal(&self) -> bool {
        matches!(self.symbolic.raw(), SymbolicCholeskyRaw::Supernodal(_))
    }

    /// The symbolic analysis (to reuse for a matrix of the same pattern).
    pub fn symbolic(&self) -> Arc<SymbolicCholesky<usize>> {
        self.symbolic.clone()
    }

    /// Diagonal entries of L (in the permuted order; the product is what matters).
    pub fn l_diagonal(&self) -> Vec<f64> {
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let cp = s.col_ptr();
                let ri = s.row_idx();
                (0..s.nrows())
                    .map(|j| {
                        let (a, b) = (cp[j], cp[j + 1]);
                        (a..b)
                            .find(|&p| ri[p] == j)
                            .map(|p| self.values[p])
                            .unwrap_or(0.0)
                    })
                    .collect()
            }
            SymbolicCholeskyRaw::Supernodal(s) => {
                let l = faer::sparse::linalg::cholesky::supernodal::SupernodalLltRef::new(
                    s,
                    &self.values,
                );
                let mut d = Vec::with_capacity(s.nrows());
                for k in 0..s.n_supernodes() {
                    let v = l.supernode(k).val();
                    for i in 0..v.ncols() {
                        d.push(v[(i, i)]);
                    }
                }
                d
            }
        }
    }

    /// `log10 det A = Σ 2 log10 L_ii`.
    pub fn log10_det(&self) -> f64 {
        self.l_diagonal().iter().map(|d| 2.0 * d.log10()).sum()
    }

    /// Solves `A x = b` in place (`x` holds b on entry).
    ///
    /// A simplicial factor is solved here by the same two column sweeps faer runs (same
    /// operations in the same order, so the same bits; `tests/verification/kernels.rs`): faer's solve is
    /// written for any number of right-hand sides through strided matrix views and a
    /// scratch stack, which on the small factors of a sweep costs up to a quarter of the
    /// solve (`cargo bench --bench cond -- one_vector_solve`; docs/performance.md).
    /// Supernodal factors go to faer.
    pub fn solve_vec_in_place(&self, x: &mut [f64]) {
        let n = x.len();
        match self.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => {
                let (cp, ri) = (s.col_ptr(), s.row_idx());
                SOLVE_WORK.with(|w| {
                    let mut w = w.borrow_mut();
                    w.clear();
                    match self.symbolic.perm() {
                        Some(perm) => w.extend(perm.arrays().0.iter().map(|&f| x[f])),
                        None => w.extend_from_slice(x),
                    }
                    simplicial_llt_solve(cp, ri, &self.values, &mut w);
                    match self.symbolic.perm() {
                        Some(perm) => {
                            for (xi, &inv) in x.iter_mut().zip(perm.arrays().1) {
                                *xi = w[inv];
                            }
                        }
                        None => x.copy_from_slice(&w),
                    }
                });
            }
            SymbolicCholeskyRaw::Supernodal(_) => {
                self.solve_in_place(MatMut::from_column_major_slice_mut(x, n, 1))
            }
        }
    }

    /// Solves `A X = B` in place (`rhs` holds B on entry).
    pub fn solve_mat_in_place(&self, rhs: MatMut<'_, f64>) {
        self.solve_in_place(rhs)
    }

    pub(super) fn solve_in_place(&self, rhs: MatMut<'_, f64>) {
        let par = Par::Seq;
        let ncols = rhs.ncols();
        let req = self.symbolic.solve_in_place_scratch::<f64>(ncols, par);
        with_scratch(req, |stack| {
            LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
                Conj::No,
                rhs,
                par,
                stack,
            )
        });
    }
}

impl Drop for SparseLlt {
    fn drop(&mut self) {
        recycle_values(std::mem::take(&mut self.values));
    }
}

thread_local! {
    /// The value buffer of the last dropped sparse factor on this thread. Active-set loops and
    /// inertia bisections factorize the same pattern again and again; reusing the buffer
    /// avoids mapping (and page-faulting) tens of MB of fresh memory per factorization.
    static SPARE_VALUES: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

thread_local! {
    /// The largest scratch buffer used by a sparse factorization or solve on this thread, kept
    /// for the next one (same reason as `SPARE_VALUES`).
    static SPARE_SCRATCH: std::cell::RefCell<Option<(usize, usize, MemBuffer)>> =
        const { std::cell::RefCell::new(None) };
}

/// Runs `f` on a scratch stack of at least `req`, reusing this thread's spare buffer when it
/// is large enough (the buffer's contents are never read before being written by faer).
fn with_scratch<R>(req: faer::dyn_stack::StackReq, f: impl FnOnce(&mut MemStack) -> R) -> R {
    let (size, align) = (req.size_bytes(), req.align_bytes());
    let spare = SPARE_SCRATCH.with(|s| s.borrow_mut().take());
    let (mut buf, cap, cap_align) = match spare {
        Some((c, a, b)) if c >= size && a >= align => (b, c, a),
        _ => (MemBuffer::new(req), size, align),
    };
    let r = f(MemStack::new(&mut buf));
    SPARE_SCRATCH.with(|s| *s.borrow_mut() = Some((cap, cap_align, buf)));
    r
}

thread_local! {
    /// The permuted right-hand side of [`SparseLlt::solve_vec_in_place`].
    static SOLVE_WORK: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// `L Lᵀ w = b` in place for a simplicial factor L in CSC (`cp`, `ri`, `l`; the diagonal entry
/// first in each column): the column-oriented forward sweep and the row-oriented (dot
/// product, entries in reverse) backward sweep of faer's `solve_lower_triangular_in_place`
/// and its transpose, for one vector.
fn simplicial_llt_solve(cp: &[usize], ri: &[usize], l: &[f64], w: &mut [f64]) {
    let n = w.len();
    for j in 0..n {
        let (a, b) = (cp[j], cp[j + 1]);
        let wj = w[j] * l[a].recip();
        w[j] = wj;
        for (&i, &lij) in ri[a + 1..b].iter().zip(&l[a + 1..b]) {
            w[i] -= lij * wj;
        }
    }
    for j in (0..n).rev() {
        let (a, b) = (cp[j], cp[j + 1]);
        let mut acc = 0.0;
        for (&i, &lij) in ri[a + 1..b].iter().zip(&l[a + 1..b]).rev() {
            acc += lij * w[i];
        }
        w[j] = (w[j] - acc) * l[a].recip();
    }
}

/// A value buffer of length `len`, reusing the spare one if it is large enough: zeroed where
/// `zeroed`, else holding whatever the spare held (for a kernel that writes every entry).
fn recycled_values(len: usize, zeroed: bool) -> Vec<f64> {
    let mut v = SPARE_VALUES.with(|s| std::mem::take(&mut *s.borrow_mut()));
    if v.capacity() < len {
        return vec![0.0; len];
    }
    if zeroed {
        v.clear();
    } else {
        v.truncate(len);
    }
    v.resize(len, 0.0);
    v
}

/// Frees this thread's reused buffers — the spare factor values (`SPARE_VALUES`), the
/// factorization's scratch stack (`SPARE_SCRATCH`) and the solves' work vector
/// (`SOLVE_WORK`): for work run on another thread for once, whose buffers would otherwise
/// stay allocated there, unused (at 10⁶ unknowns a factor's values and scratch are hundreds
/// of MB).
pub fn release_thread_buffers() {
    SPARE_VALUES.with(|s| drop(std::mem::take(&mut *s.borrow_mut())));
    SPARE_SCRATCH.with(|s| drop(s.borrow_mut().take()));
    SOLVE_WORK.with(|w| drop(std::mem::take(&mut *w.borrow_mut())));
}

/// Keeps `v` as the spare value buffer (the larger of it and the current spare).
fn recycle_values(v: Vec<f64>) {
    SPARE_VALUES.with(|s| {
        let mut s = s.borrow_mut();
        if v.capacity() > s.capacity() {
            *s = v;
        }
    });
}

/// The pattern of the upper triangle of `PAPᵀ` (columns unsorted, as faer's
/// `permute_self_adjoint_to_unsorted` leaves them) and, for each of its entries, the position
/// of the same entry of A in [`DiagonalPattern::values`](super::DiagonalPattern::values).
///
/// faer's `factorize_numeric_llt` permutes A again at every factorization (a scatter of the
/// whole matrix, ≈ 15 % of a factorization of the sweep's matrices). The symbolic cache
/// ([`SparseLlt::analyze`]) permutes each pattern once, and every numeric factorization of a
/// cached pattern gathers its values through `map` and runs faer's simplicial numeric
/// factorization on the same permuted matrix faer would build, with the row structure
/// precomputed ([`simplicial_llt_numeric`]; the same factor, bit for bit).
pub(super) struct PermutedUpper {
    pub(super) pattern: SymbolicSparseColMat<usize>,
    pub(super) map: Vec<usize>,
    /// Row k of L (the j < k with `L_kj` structurally nonzero) at
    /// `reach[reach_ptr[k]..reach_ptr[k + 1]]`, in the order faer's `ereach` visits it.
    pub(super) reach_ptr: Vec<usize>,
    pub(super) reach: Vec<usize>,
}

/// The rows of the simplicial factor L (`l_cp`, `l_ri`: columns sorted, diagonal first) as
/// faer's up-looking factorization visits them: for each k, the elimination-tree paths from
/// the entries `i < k` of column k of the permuted upper triangle `upper` (in its stored
/// order) up to k, each path pushed on top of the ones before — faer's `ereach`, with the
/// tree read off L (the parent of j is the first row below the diagonal of column j).
fn reach_lists(
    upper: SymbolicSparseColMatRef<'_, usize>,
    l_cp: &[usize],
    l_ri: &[usize],
) -> (Vec<usize>, Vec<usize>) {
    let n = upper.ncols();
    let parent: Vec<usize> = (0..n)
        .map(|j| {
            if l_cp[j + 1] - l_cp[j] > 1 {
                l_ri[l_cp[j] + 1]
            } else {
                usize::MAX
            }
        })
        .collect();
    let (ucp, uri) = (upper.col_ptr(), upper.row_idx());
    let mut visited = vec![usize::MAX; n];
    let mut stack = vec![0usize; n];
    let mut reach_ptr = Vec::with_capacity(n + 1);
    let mut reach = Vec::with_capacity(l_ri.len().saturating_sub(n));
    reach_ptr.push(0);
    for k in 0..n {
        let mut top = n;
        visited[k] = k;
        for &i0 in &uri[ucp[k]..ucp[k + 1]] {
            if i0 >= k {
                continue;
            }
            let (mut i, mut len) = (i0, 0);
            while i < n && visited[i] != k {
                stack[len] = i;
                len += 1;
                visited[i] = k;
                i = parent[i];
            }
            stack.copy_within(..len, top - len);
            top -= len;
        }
        reach.extend_from_slice(&stack[top..]);
        reach_ptr.push(reach.len());
    }
    (reach_ptr, reach)
}

/// Numeric `PAPᵀ = L Lᵀ` of a cached simplicial pattern: faer's up-looking simplicial
/// Cholesky (`factorize_simplicial_numeric_llt`), operation for operation — row k of L by a
/// sparse triangular solve over the precomputed row structure (`PermutedUpper::reach`),
/// `L_kj = x_j · (1/L_jj)`, `x_i −= L_ij L_kj` for the column's rows computed so far,
/// `L_kk = √(a_kk − Σ L_kj²)` — so the same factor bit for bit (`tests/verification/kernels.rs`). What it
/// saves per factorization is faer's `ereach` tree walk of every row, one reciprocal per
/// entry of L (taken once per column here) and the scratch set-up: 1.6–2× faster than faer's
/// `factorize_numeric_llt` with the same analysis on the sweep's matrices (`cargo bench
/// --bench cond -- simplicial_numeric`; docs/performance.md).
/// `a_vals`: A's values, gathered through `pu.map`. False where a pivot is not positive.
fn simplicial_llt_numeric(
    pu: &PermutedUpper,
    a_vals: &[f64],
    l_cp: &[usize],
    l_ri: &[usize],
    l: &mut [f64],
) -> bool {
    simplicial_numeric::<false>(pu, a_vals, l_cp, l_ri, l).is_some()
}

/// The up-looking kernel of [`simplicial_llt_numeric`] (`LDLT = false`) and of the LDLᵀ
/// inertia test (`LDLT = true`, `super::ldlt`): row k of L by a sparse triangular solve, with
/// `w_j` the solve's value at j, `L_kj = w_j/L_jj` and the updates `x_i −= L_ij L_kj`,
/// `d −= L_kj²`, `L_kk = √d` (Cholesky, faer's operations exactly) or `L_kj = w_j/d_j`,
/// `x_i −= L_ij w_j`, `d −= L_kj w_j`, `d_k = d` stored on the diagonal (LDLᵀ without
/// pivoting). Returns the number of negative pivots, or None where Cholesky meets a pivot that
/// is not positive or LDLᵀ one that is zero or not finite.
pub(super) fn simplicial_numeric<const LDLT: bool>(
    pu: &PermutedUpper,
    a_vals: &[f64],
    l_cp: &[usize],
    l_ri: &[usize],
    l: &mut [f64],
) -> Option<usize> {
    let n = pu.pattern.ncols();
    let (ucp, uri) = (pu.pattern.col_ptr(), pu.pattern.row_idx());
    let mut x = vec![0.0f64; n];
    let mut next: Vec<usize> = l_cp[..n].to_vec();
    let mut inv_diag = vec![0.0f64; n];
    let mut negative = 0;
    for k in 0..n {
        for (&i, &p) in uri[ucp[k]..ucp[k + 1]]
            .iter()
            .zip(&pu.map[ucp[k]..ucp[k + 1]])
        {
            x[i] += a_vals[p];
        }
        let mut d = x[k];
        x[k] = 0.0;
        for &j in &pu.reach[pu.reach_ptr[k]..pu.reach_ptr[k + 1]] {
            let start = l_cp[j] + 1;
            next[j] += 1;
            let row = next[j];
            let lkj = x[j] * inv_diag[j];
            // Cholesky updates with L_kj, LDLᵀ with w_j = (L D)_kj.
            let upd = if LDLT { x[j] } else { lkj };
            x[j] = 0.0;
            for (&i, &lij) in l_ri[start..row].iter().zip(&l[start..row]) {
                x[i] -= lij * upd;
            }
            d -= lkj * upd;
            l[row] = lkj;
        }
        let pivot = if LDLT {
            // Zero or not finite: no inertia to read.
            if !(d != 0.0 && d.is_finite()) {
                return None;
            }
            negative += usize::from(d < 0.0);
            d
        } else {
            // Not positive (or NaN): faer's `!(d > 0)`.
            if d.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return None;
            }
            d.sqrt()
        };
        l[l_cp[k]] = pivot;
        inv_diag[k] = pivot.recip();
    }
    Some(negative)
}

impl PermutedUpper {
    /// None unless `symbolic` is simplicial with a permutation.
    pub(super) fn new(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        symbolic: &SymbolicCholesky<usize>,
    ) -> Option<Self> {
        let SymbolicCholeskyRaw::Simplicial(s) = symbolic.raw() else {
            return None;
        };
        let perm = symbolic.perm()?;
        let n = pattern.nrows();
        // The entries' own positions as values (exact in f64 up to 2⁵³) travel through the
        // permutation and come out as the map.
        let positions: Vec<f64> = (0..pattern.row_idx().len()).map(|p| p as f64).collect();
        let a = faer::sparse::SparseColMatRef::new(pattern, &positions);
        let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
        let lower: usize = (0..n)
            .map(|j| ri[cp[j]..cp[j + 1]].iter().filter(|&&i| i >= j).count())
            .sum();
        let mut val = vec![0.0; lower];
        let mut col_ptr = vec![0usize; n + 1];
        let mut row_idx = vec![0usize; lower];
        let req = faer::sparse::utils::permute_self_adjoint_scratch::<usize>(n);
        with_scratch(req, |stack| {
            faer::sparse::utils::permute_self_adjoint_to_unsorted(
                &mut val,
                &mut col_ptr,
                &mut row_idx,
                a,
                perm,
                Side::Lower,
                Side::Upper,
                stack,
            );
        });
        let permuted = SymbolicSparseColMat::new_unsorted_checked(n, n, col_ptr, None, row_idx);
        let (reach_ptr, reach) = reach_lists(permuted.as_ref(), s.col_ptr(), s.row_idx());
        Some(PermutedUpper {
            pattern: permuted,
            map: val.iter().map(|&p| p as usize).collect(),
            reach_ptr,
            reach,
        })
    }
}
