//! Linear systems with contact constraints: `K u = q` subject to `Dᵀu ⋚ û`.
//!
//! * [`Stiffness`] — the assembled matrix **K** (N×N), dense or sparse. A sparse input is never
//!   densified unless a metric really needs it; where it is stored and which solve and cond₂
//!   routes it takes is decided by [`crate::route`] from its [`Structure`].
//! * [`Constraint`] — one contact restriction: a row `d_cᵀ` of Dᵀ (terms `(DOF, coefficient)`;
//!   one term with coefficient 1 for a single-DOF constraint), limit `û_c`, and a
//!   [`ConstraintKind`] (`bilateral` / `upper` / `lower`).
//! * [`Problem`] — K, the load **q** and the constraints, validated on construction.
//!
//! Sign conventions (binding, see `shared/notes/methods.md`): the gap is
//! `g_c = d_cᵀu − û_c` (`u[d_c] − û_c` for a single-DOF constraint); the penetration is
//! `|g_c|` (bilateral), `max(0, g_c)` (upper: `d_cᵀu ≤ û_c`) or `max(0, −g_c)` (lower:
//! `d_cᵀu ≥ û_c`).

use crate::error::{Error, Result};
pub use crate::route::{Structure, DENSIFY_LIMIT};
use faer::sparse::{SparseColMat, Triplet};
use faer::Mat;

/// The stiffness matrix **K**: dense (faer `Mat`) or sparse (faer CSC).
#[derive(Clone, Debug)]
pub enum Stiffness {
    /// Dense storage, column-major.
    Dense(Mat<f64>),
    /// Sparse compressed-column storage (duplicates already summed).
    Sparse(SparseColMat<usize, f64>),
}

/// Is the sparse matrix (sorted CSC) structurally symmetric with mirror entries equal bit for
/// bit? The common case of [`Stiffness::is_symmetric`], decided in one pass without a
/// transpose: the upper entries of column i are met in row order as the columns j < i are
/// scanned for their mirrors, so one cursor per column walks them.
pub(crate) fn exactly_symmetric(m: &SparseColMat<usize, f64>) -> bool {
    let n = m.ncols();
    let (cp, ri, v) = (m.symbolic().col_ptr(), m.symbolic().row_idx(), m.val());
    if m.symbolic().col_nnz().is_some() {
        return false;
    }
    let mut next = cp[..n].to_vec();
    for j in 0..n {
        for p in cp[j]..cp[j + 1] {
            let i = ri[p];
            if i > j {
                let q = next[i];
                if q >= cp[i + 1] || ri[q] != j || v[q] != v[p] {
                    return false;
                }
                next[i] = q + 1;
            }
        }
    }
    // Every upper entry was some lower entry's mirror.
    (0..n).all(|i| next[i] == cp[i] + ri[cp[i]..cp[i + 1]].partition_point(|&r| r < i))
}

/// The sparse N×N matrix of the given entries other than ±0.0 (each position at most once,
/// all in range): the conversion [`Stiffness::in_preferred_storage`] makes, whatever order
/// the entries come in.
fn sparse_of_nonzeros(
    n: usize,
    entries: impl IntoIterator<Item = (usize, usize, f64)>,
) -> SparseColMat<usize, f64> {
    let t: Vec<Triplet<usize, usize, f64>> = entries
        .into_iter()
        .filter(|e| e.2 != 0.0)
        .map(|(row, col, val)| Triplet { row, col, val })
        .collect();
    SparseColMat::try_new_from_triplets(n, n, &t).expect("entries of an n×n matrix are in range")
}

/// The square dense `m` in sparse storage: its nonzero entries, every value bit for bit.
pub fn sparse_of_dense(m: faer::MatRef<'_, f64>) -> SparseColMat<usize, f64> {
    let n = m.nrows();
    sparse_of_nonzeros(
        n,
        (0..n).flat_map(|j| (0..n).map(move |i| (i, j, m[(i, j)]))),
    )
}

/// The error for a 0×0 stiffness matrix.
fn empty_stiffness() -> Error {
    Error::out_of_range(
        "the order N of the stiffness matrix",
        "0: K is empty (0×0)",
        "≥ 1",
    )
}

/// N for rows of lengths `row_lens`, all N; errors on an empty or non-square matrix.
fn square_rows(row_lens: &[usize]) -> Result<usize> {
    let n = row_lens.len();
    if n == 0 {
        return Err(empty_stiffness());
    }
    if let Some((i, &len)) = row_lens.iter().enumerate().find(|(_, &l)| l != n) {
        return Err(Error::length_mismatch(
            format!("stiffness matrix is not square: row {i}"),
            len,
            n,
        ));
    }
    Ok(n)
}

impl Stiffness {
    /// Builds a dense matrix from row-major rows. Errors on ragged or non-square input.
    pub fn from_rows(rows: &[Vec<f64>]) -> Result<Self> {
        let lens: Vec<usize> = rows.iter().map(Vec::len).collect();
        let entries = rows
            .iter()
            .enumerate()
            .flat_map(|(i, r)| r.iter().enumerate().map(move |(j, &v)| (i, j, v)));
        Self::from_row_entries(&lens, entries)
    }

    /// A dense matrix from the length of each row and its entries `(row, column, value)`,
    /// where an entry of row i has a column below `row_lens[i]` (entries not given are 0):
    /// [`Stiffness::from_rows`] without the rows themselves (the scene reader keeps only the
    /// nonzeros). Errors on ragged or non-square input.
    pub(crate) fn from_row_entries(
        row_lens: &[usize],
        entries: impl IntoIterator<Item = (usize, usize, f64)>,
    ) -> Result<Self> {
        let n = square_rows(row_lens)?;
        let mut m = Mat::zeros(n, n);
        for (i, j, v) in entries {
            m[(i, j)] = v;
        }
        Ok(Stiffness::Dense(m))
    }

    /// [`Stiffness::from_row_entries`] in the storage its structure prefers: bit for bit
    /// `from_row_entries(..)?.in_preferred_storage()`, without the N×N intermediate where
    /// that is sparse (the same nonzero entries, `v != 0.0`, become the same CSC matrix).
    pub(crate) fn from_row_entries_preferred(
        row_lens: &[usize],
        entries: Vec<(usize, usize, f64)>,
    ) -> Result<Self> {
        let n = square_rows(row_lens)?;
        let mut s = Structure::empty(n);
        for &(i, j, v) in &entries {
            s.count(i, j, v);
        }
        if !s.prefers_sparse() {
            return Self::from_row_entries(row_lens, entries);
        }
        Ok(Stiffness::Sparse(sparse_of_nonzeros(n, entries)))
    }

    /// Builds a sparse matrix from (row, col, value) triplets; duplicates are summed.
    fn assemble(n: usize, triplets: &[(usize, usize, f64)]) -> Result<Self> {
        if n == 0 {
            return Err(empty_stiffness());
        }
        let t: Vec<Triplet<usize, usize, f64>> = triplets
            .iter()
            .map(|&(row, col, val)| Triplet { row, col, val })
            .collect();
        for x in &t {
            if x.row >= n || x.col >= n {
                return Err(Error::out_of_range(
                    "sparse entry (row, column)",
                    format!("({}, {})", x.row, x.col),
                    format!("inside the {n}×{n} matrix (0-based)"),
                ));
            }
        }
        let m = SparseColMat::try_new_from_triplets(n, n, &t)
            .map_err(|e| Error::Numerical(format!("cannot build the sparse matrix: {e:?}")))?;
        Ok(Stiffness::Sparse(m))
    }

    /// A sparse matrix from triplets (duplicates summed), refusing entries that are not
    /// finite after summing (an input file whose duplicates overflow).
    pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> Result<Self> {
        let Stiffness::Sparse(m) = Self::assemble(n, triplets)? else {
            unreachable!("assemble builds a sparse matrix")
        };
        // Duplicates are summed: finite entries can overflow to ±∞.
        let (cp, ri) = (m.symbolic().col_ptr(), m.symbolic().row_idx());
        if let Some(p) = m.val().iter().position(|v| !v.is_finite()) {
            let j = cp.partition_point(|&c| c <= p) - 1;
            return Err(Error::not_finite(format!(
                "sparse entry ({}, {j}) after summing its duplicate entries (overflow)",
                ri[p]
            )));
        }
        Ok(Stiffness::Sparse(m))
    }

    /// The matrix in sparse storage, whatever its storage now (a dense one: its nonzero
    /// entries, every value bit for bit).
    pub fn to_sparse(&self) -> SparseColMat<usize, f64> {
        self.as_sparse().into_owned()
    }

    /// [`Stiffness::to_sparse`] borrowed where the matrix is sparse already.
    pub fn as_sparse(&self) -> std::borrow::Cow<'_, SparseColMat<usize, f64>> {
        match self {
            Stiffness::Sparse(m) => std::borrow::Cow::Borrowed(m),
            Stiffness::Dense(m) => std::borrow::Cow::Owned(sparse_of_dense(m.as_ref())),
        }
    }

    /// The structure of the matrix, whatever its storage: N, the number of nonzero entries
    /// (exact zeros, stored or not, do not count) and the half-bandwidth
    /// `max |i − j|` over them (natural ordering). O(N²) for dense storage, O(nnz) for sparse.
    pub fn structure(&self) -> Structure {
        let mut s = Structure::empty(self.n());
        self.for_each_entry(|i, j, v| s.count(i, j, v));
        s
    }

    /// The same matrix in the storage [`Structure::prefers_sparse`] chooses: a structurally
    /// sparse dense matrix becomes sparse (only exact zeros dropped, so every value is kept bit
    /// for bit), a small or dense-ish sparse one becomes dense (up to
    /// [`DENSIFY_LIMIT`] unknowns). Every later factorization, cond₂ and
    /// determinant then takes the route that fits the matrix rather than its file format.
    pub fn in_preferred_storage(self) -> Stiffness {
        let s = self.structure();
        match (&self, s.prefers_sparse()) {
            (Stiffness::Dense(m), true) => Stiffness::Sparse(sparse_of_dense(m.as_ref())),
            (Stiffness::Sparse(_), false) if s.densify_allowed() => {
                Stiffness::Dense(self.to_dense())
            }
            _ => self,
        }
    }

    /// Power-of-two diagonal equilibration `s_i = 2^round(−log2|a_ii| / 2)` (1 for a zero or
    /// non-finite diagonal): `S A S` ([`Stiffness::scaled`]) has a diagonal in [½, 2) and the
    /// scaling adds no rounding error. Used by the stress study's refinement and by forming's
    /// equilibrated cond₂.
    pub fn equilibration(&self) -> Vec<f64> {
        (0..self.n())
            .map(|i| {
                let d = self.diag(i).abs();
                if d > 0.0 && d.is_finite() {
                    let k = (-d.log2() / 2.0).round().clamp(-500.0, 500.0);
                    2f64.powi(k as i32)
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// `S A S` with `S = diag(s)`, in the same storage. Each entry is rounded as
    /// `(s_k · a_ij) · s_l` with k = max(i, j), l = min(i, j) — the lower triangle's
    /// `(s_i·a_ij)·s_j`, mirrored — so that a symmetric A gives an exactly symmetric result
    /// (`(s_i·a_ij)·s_j` everywhere rounds a_ij and a_ji differently); exact for powers of two.
    pub fn scaled(&self, s: &[f64]) -> Stiffness {
        let entry = |i: usize, j: usize, v: f64| {
            let (k, l) = if i >= j { (i, j) } else { (j, i) };
            s[k] * v * s[l]
        };
        match self {
            Stiffness::Dense(m) => {
                let n = m.nrows();
                Stiffness::Dense(Mat::from_fn(n, n, |i, j| entry(i, j, m[(i, j)])))
            }
            Stiffness::Sparse(_) => {
                let mut t = Vec::with_capacity(self.nnz());
                self.for_each_entry(|i, j, v| t.push((i, j, entry(i, j, v))));
                Stiffness::from_triplets(self.n(), &t).expect("same pattern")
            }
        }
    }

    /// Number of rows (= columns).
    pub fn n(&self) -> usize {
        match self {
            Stiffness::Dense(m) => m.nrows(),
            Stiffness::Sparse(m) => m.nrows(),
        }
    }

    /// Number of stored entries (N² for dense).
    pub fn nnz(&self) -> usize {
        match self {
            Stiffness::Dense(m) => m.nrows() * m.ncols(),
            Stiffness::Sparse(m) => m.val().len(),
        }
    }

    /// `true` for sparse storage.
    pub fn is_sparse(&self) -> bool {
        matches!(self, Stiffness::Sparse(_))
    }

    /// Entry `K[i, j]` (0 if not stored).
    pub fn get(&self, i: usize, j: usize) -> f64 {
        match self {
            Stiffness::Dense(m) => m[(i, j)],
            Stiffness::Sparse(m) => m.as_ref().get(i, j).copied().unwrap_or(0.0),
        }
    }

    /// Diagonal entry `K[i, i]`.
    pub fn diag(&self, i: usize) -> f64 {
        self.get(i, i)
    }

    /// Calls `f(i, j, value)` for every stored entry.
    pub fn for_each_entry(&self, mut f: impl FnMut(usize, usize, f64)) {
        match self {
            Stiffness::Dense(m) => {
                for j in 0..m.ncols() {
                    for i in 0..m.nrows() {
                        f(i, j, m[(i, j)]);
                    }
                }
            }
            Stiffness::Sparse(m) => {
                let m = m.as_ref();
                for j in 0..m.ncols() {
                    for (&i, &v) in m.row_idx_of_col_raw(j).iter().zip(m.val_of_col(j)) {
                        f(i, j, v);
                    }
                }
            }
        }
    }

    /// Largest absolute entry (max-norm).
    pub fn max_abs(&self) -> f64 {
        let mut a = 0.0f64;
        self.for_each_entry(|_, _, v| a = a.max(v.abs()));
        a
    }

    /// `‖K‖_∞`: the largest absolute row sum.
    pub fn inf_norm(&self) -> f64 {
        let mut rows = vec![0.0f64; self.n()];
        self.for_each_entry(|i, _, v| rows[i] += v.abs());
        rows.into_iter().fold(0.0, f64::max)
    }

    /// `true` if every stored entry is finite.
    pub fn all_finite(&self) -> bool {
        let mut ok = true;
        self.for_each_entry(|_, _, v| ok &= v.is_finite());
        ok
    }

    /// `true` if every mirror pair is equal bit for bit ([`Symmetry::Exact`]): the test
    /// that selects Cholesky and the symmetric (eigenvalue, certified) routes, whose proofs
    /// factor one triangle and multiply with both. A matrix unsymmetric only by rounding
    /// ([`Symmetry::Near`]) is not symmetric here: it is solved by LU as stored, and its cond₂
    /// is certified through its symmetric part (the cond₂ routes, see [`Symmetry`]).
    pub fn is_symmetric(&self) -> bool {
        self.symmetry() == Symmetry::Exact
    }

    /// Do both matrices store the same entries (sparse: the same column pointers and row
    /// indices; dense: the same size)?
    pub fn same_pattern(&self, other: &Stiffness) -> bool {
        match (self, other) {
            (Stiffness::Sparse(a), Stiffness::Sparse(b)) => {
                let (a, b) = (a.symbolic(), b.symbolic());
                a.nrows() == b.nrows()
                    && a.col_ptr() == b.col_ptr()
                    && a.col_nnz() == b.col_nnz()
                    && a.row_idx() == b.row_idx()
            }
            (Stiffness::Dense(a), Stiffness::Dense(b)) => a.nrows() == b.nrows(),
            _ => false,
        }
    }

    /// `y = K x`.
    pub fn matvec(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n()];
        self.for_each_entry(|i, j, v| y[i] += v * x[j]);
        y
    }

    /// A dense copy (used only by metrics that need it, and by small models).
    pub fn to_dense(&self) -> Mat<f64> {
        match self {
            Stiffness::Dense(m) => m.clone(),
            Stiffness::Sparse(m) => m.as_ref().to_dense(),
        }
    }

    /// A dense nalgebra copy (duplicate sparse entries summed): for the nalgebra/LAPACK
    /// references and small dense algebra on model problems.
    pub fn to_nalgebra(&self) -> nalgebra::DMatrix<f64> {
        let n = self.n();
        let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
        self.for_each_entry(|i, j, v| m[(i, j)] += v);
        m
    }

    /// `K + Σ_c add_c e_{d_c} e_{d_c}ᵀ` — the penalized matrix `K + D E Dᵀ` (Eq. 19) for a
    /// Boolean D: [`Stiffness::with_entries_added`] on the diagonal.
    pub fn with_diagonal_added(&self, adds: &[(usize, f64)]) -> Stiffness {
        let adds: Vec<(usize, usize, f64)> = adds.iter().map(|&(d, v)| (d, d, v)).collect();
        self.with_entries_added(&adds)
    }

    /// `K + Σ v e_i e_jᵀ` over `adds` `(i, j, v)` (indices already validated; repeated
    /// positions add up) — `K + D E Dᵀ` for a general D. Sparse stays sparse: values added in
    /// place where every touched entry is stored, otherwise reassembled with the missing ones
    /// inserted (the coupled rows' fill).
    pub fn with_entries_added(&self, adds: &[(usize, usize, f64)]) -> Stiffness {
        match self {
            Stiffness::Dense(m) => {
                let mut m = m.clone();
                for &(i, j, v) in adds {
                    m[(i, j)] += v;
                }
                Stiffness::Dense(m)
            }
            Stiffness::Sparse(m) => {
                // Every touched entry present (the diagonal of a stiffness matrix): add in
                // place, O(nnz).
                if let Some(out) = add_in_place(m, adds) {
                    return Stiffness::Sparse(out);
                }
                // Widen the pattern by the missing entries (stored as 0), then add in place
                // in the order of `adds`: (i, j) and (j, i) get the same sums in the same
                // order, so a symmetric K stays symmetric bit for bit.
                let mut t = Vec::with_capacity(self.nnz() + adds.len());
                self.for_each_entry(|i, j, v| t.push((i, j, v)));
                t.extend(adds.iter().map(|&(i, j, _)| (i, j, 0.0)));
                // Unchecked values: an overflowing penalty is reported by the factorization.
                let Stiffness::Sparse(wide) =
                    Stiffness::assemble(self.n(), &t).expect("indices already validated")
                else {
                    unreachable!("assemble builds a sparse matrix")
                };
                Stiffness::Sparse(add_in_place(&wide, adds).expect("every entry is stored"))
            }
        }
    }
}

/// The position of entry (i, j) in the values of a CSC pattern whose columns hold sorted row
/// indices, or None where it is not stored.
pub fn csc_position(
    pattern: faer::sparse::SymbolicSparseColMatRef<'_, usize>,
    i: usize,
    j: usize,
) -> Option<usize> {
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    ri[cp[j]..cp[j + 1]]
        .binary_search(&i)
        .ok()
        .map(|k| cp[j] + k)
}

/// `m` with `adds` added in place, in order, or None where an entry is not stored (or `m` is
/// not compressed).
fn add_in_place(
    m: &SparseColMat<usize, f64>,
    adds: &[(usize, usize, f64)],
) -> Option<SparseColMat<usize, f64>> {
    if m.symbolic().col_nnz().is_some() {
        return None;
    }
    let pos: Option<Vec<usize>> = adds
        .iter()
        .map(|&(i, j, _)| csc_position(m.symbolic(), i, j))
        .collect();
    let pos = pos?;
    let mut out = m.clone();
    let vals = out.val_mut();
    for (&p, &(_, _, v)) in pos.iter().zip(adds) {
        vals[p] += v;
    }
    Some(out)
}

/// A contact problem: `K`, `q` and the constraints, validated.
#[derive(Clone, Debug)]
pub struct Problem {
    /// Stiffness **K** (N×N).
    pub k: Stiffness,
    /// Load **q** (N).
    pub q: Vec<f64>,
    /// Contact constraints (m of them).
    pub constraints: Vec<Constraint>,
    /// The contact surface behind the constraints, where the model knows it (None for a bare
    /// K, q, D as scene files give them). Set by [`Problem::with_surface`].
    pub surface: Option<Surface>,
    /// The near-null space of K for a nodal AMG (rigid-body modes), where the model or the
    /// scene gives it; set by [`Problem::with_near_null`].
    pub near_null: Option<NearNull>,
}

/// What a model knows of its contact surface: the quantities that give a penalty physical
/// units and a barrier its length scale.
#[derive(Clone, Debug, PartialEq)]
pub struct Surface {
    /// Tributary weight ω_c of each constraint: the contact length (plane strain, per unit
    /// thickness) or area (axisymmetric, per radian) its DOF stands for, ω_c = ∫ N_c ds. A
    /// penalty ε per unit contact length/area (pressure per penetration, force/length³)
    /// acts on DOF d_c as the nodal penalty ε·ω_c (force/length).
    pub weights: Vec<f64>,
    /// Diagonal of the model's bounding box (length units of u): the length scale of the
    /// barrier's stiffness rule (`strategy::barrier`, as in ipc-toolkit).
    pub bbox_diagonal: f64,
}

impl Problem {
    /// The displacement scale max_c |d_cᵀu0| used by relative δ (falls back to max |u0|, then 1).
    pub fn displacement_scale(&self, u0: &[f64]) -> f64 {
        let s = self
            .constraints
            .iter()
            .map(|c| c.value(u0).abs())
            .fold(0.0f64, f64::max);
        if s > 0.0 {
            return s;
        }
        let s = u0.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if s > 0.0 {
            s
        } else {
            1.0
        }
    }

    /// The largest |d_cᵀKd_c|/‖d_c‖⁴ (|K\[d, d\]| for a single-DOF constraint on d) over the
    /// constraints (0 without any): the stiffness scale penalties are relative to.
    pub fn max_constraint_stiffness(&self) -> f64 {
        self.constraints
            .iter()
            .map(|c| c.stiffness(&self.k).abs())
            .fold(0.0f64, f64::max)
    }

    /// The geometric mean of |d_cᵀKd_c| over the constraints (1 without any nonzero):
    /// a moderate penalty in the problem's own stiffness units (the augmented Lagrangian's ε
    /// in the sweep and the contact benchmarks).
    pub fn mean_constraint_stiffness(&self) -> f64 {
        let logs: Vec<f64> = self
            .constraints
            .iter()
            .map(|c| c.stiffness(&self.k).abs())
            .filter(|v| *v > 0.0)
            .map(f64::ln)
            .collect();
        if logs.is_empty() {
            1.0
        } else {
            (logs.iter().sum::<f64>() / logs.len() as f64).exp()
        }
    }

    /// Validates sizes, finiteness and DOF indices, then builds the problem.
    ///
    /// Errors: non-finite entries in K, q or û; `q.len() != N`; a constraint without terms, a
    /// DOF out of range, a DOF twice in one row, a non-finite coefficient or a row of zeros; two
    /// single-term constraints on the same DOF (D would not have full column rank).
    pub fn new(k: Stiffness, q: Vec<f64>, constraints: Vec<Constraint>) -> Result<Self> {
        let n = k.n();
        if q.len() != n {
            return Err(Error::length_mismatch(
                format!("load vector q (K is {n}×{n})"),
                q.len(),
                n,
            ));
        }
        if !k.all_finite() {
            return Err(Error::not_finite("a stiffness matrix entry (NaN or Inf)"));
        }
        if let Some(i) = q.iter().position(|v| !v.is_finite()) {
            return Err(Error::not_finite(format!("load entry {i}")));
        }
        check_constraints(&constraints, n)?;
        Ok(Problem {
            k,
            q,
            constraints,
            surface: None,
            near_null: None,
        })
    }

    /// The problem with its contact surface: one finite weight > 0 per constraint and a
    /// finite bounding-box diagonal > 0, else an error naming the bad value.
    pub fn with_surface(self, surface: Surface) -> Result<Problem> {
        if surface.weights.len() != self.m() {
            return Err(Error::length_mismatch(
                "surface weights (one per constraint)",
                surface.weights.len(),
                self.m(),
            ));
        }
        for (c, &w) in surface.weights.iter().enumerate() {
            if !(w.is_finite() && w > 0.0) {
                return Err(Error::NotPositive {
                    name: format!("surface: weight of constraint {c}"),
                    value: w,
                });
            }
        }
        Error::positive("surface: bounding-box diagonal", surface.bbox_diagonal)?;
        Ok(Problem {
            surface: Some(surface),
            ..self
        })
    }

    /// The problem with the near-null space B of K (rows: the N DOFs of K).
    pub fn with_near_null(self, near_null: NearNull) -> Result<Problem> {
        if near_null.n() != self.n() {
            return Err(Error::length_mismatch(
                "near-null space B: rows (one per DOF of K)",
                near_null.n(),
                self.n(),
            ));
        }
        Ok(Problem {
            near_null: Some(near_null),
            ..self
        })
    }

    /// The tributary weight ω_c of constraint `c` (1 without a [`Surface`]).
    pub fn weight(&self, c: usize) -> f64 {
        self.surface.as_ref().map_or(1.0, |s| s.weights[c])
    }

    /// The problem with K in its preferred storage ([`Stiffness::in_preferred_storage`]);
    /// the same values, so the same solution to rounding.
    pub fn in_preferred_storage(self) -> Problem {
        Problem {
            k: self.k.in_preferred_storage(),
            ..self
        }
    }

    /// Number of DOFs N.
    pub fn n(&self) -> usize {
        self.k.n()
    }

    /// Number of constraints m.
    pub fn m(&self) -> usize {
        self.constraints.len()
    }

    /// Is D Boolean (every constraint a single DOF with coefficient 1)?
    pub fn is_selection(&self) -> bool {
        self.constraints.iter().all(|c| c.single_dof().is_some())
    }

    /// The DOF of every constraint, for a method that needs a Boolean D; else an error naming
    /// the method and the first coupled row.
    pub fn single_dofs(&self, method: &str) -> Result<Vec<usize>> {
        self.constraints
            .iter()
            .enumerate()
            .map(|(c, con)| {
                con.single_dof().ok_or_else(|| {
                    let what = match con.terms.as_slice() {
                        [(d, a)] => format!("is {a}·u[{d}] (one term, coefficient ≠ 1)"),
                        t => format!("has {} terms", t.len()),
                    };
                    Error::unsupported(
                        method,
                        format!(
                            "single-DOF constraints (coefficient 1), but constraint {c} {what}"
                        ),
                    )
                })
            })
            .collect()
    }

    /// `K + D E Dᵀ` for the penalties `eps` (zeros skipped).
    pub fn penalized_k(&self, eps: &[f64]) -> Stiffness {
        let adds: Vec<(usize, usize, f64)> = self
            .constraints
            .iter()
            .zip(eps)
            .filter(|(_, &e)| e != 0.0)
            .flat_map(|(c, &e)| c.outer(e))
            .collect();
        self.k.with_entries_added(&adds)
    }

    /// Signed gaps `g_c = d_cᵀu − û_c`.
    pub fn gaps(&self, u: &[f64]) -> Vec<f64> {
        self.constraints.iter().map(|c| c.gap(u)).collect()
    }

    /// Penetrations `p_c` (see module docs).
    pub fn penetrations(&self, u: &[f64]) -> Vec<f64> {
        self.constraints
            .iter()
            .map(|c| c.kind.penetration(c.gap(u)))
            .collect()
    }

    /// `max_c p_c` (0 when m = 0).
    pub fn max_penetration(&self, u: &[f64]) -> f64 {
        self.penetrations(u).into_iter().fold(0.0, f64::max)
    }
}

mod constraint;
mod near_null;
mod symmetry;
pub(crate) use constraint::check_constraints;
pub use constraint::{Constraint, ConstraintKind};
pub use near_null::{check_slots, NearNull};
pub use symmetry::{Asymmetry, Symmetry};
