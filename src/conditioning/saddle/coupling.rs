//! D of `A = [K D; Dᵀ 0]` ([`super`]): Boolean columns `e_d` (a selection, one distinct DOF
//! per constraint) or general constraint rows `d_c = Σ_j a_cj e_j` that couple DOFs
//! (inclined planes, node-to-segment, mortar).
//!
//! Every congruence of the route holds for any D of full column rank: `A − σI ≅ (−σI_m) ⊕
//! H(σ)` with `H(σ) = K − σI + σ⁻¹DDᵀ`, and the monotonicity the proofs use
//! (`H(μ) − H(τ) = (1/μ − 1/τ)DDᵀ ⪰ 0` for 0 < μ < τ) needs only `DDᵀ ⪰ 0`. What changes
//! with coupled rows:
//!
//! * **Pattern.** `DDᵀ` fills the entries `(i, j)` of DOFs that share a row: the shifted
//!   matrices live on the pattern of `K + DDᵀ` (K widened with explicit zeros, one symbolic
//!   analysis), and `β·DDᵀ` is added entry by entry ([`Blocks::fill`]).
//! * **Rounding of the test matrices.** A Boolean D changes only the diagonal (one rounding
//!   per entry, the callers' `4u·max_e` / `6u·max_e`). Coupled rows round off the diagonal
//!   too: each entry `w_ij = Σ_c a_ci a_cj` of `DDᵀ` is formed with `γ_k` relative error
//!   (k rows share the pair), scaled by β and added to `αk_ij` (two roundings). [`Blocks::fill`]
//!   bounds every entry's error by `γ_{k+4}(|t̃_ij| + |β|·Σ_c |a_ci a_cj|)` and the whole error
//!   in 2-norm by its largest row sum (a symmetric nonnegative matrix's spectral radius is at
//!   most its largest row sum), and returns `max_e` scaled so that the callers' `4u·max_e`
//!   bounds it: every proof of the route stands unchanged on that bound.
//! * **A⁻¹** without K_FF: through the augmented block `K_ρ = K + ρDDᵀ` (`ρ` = the largest
//!   `k_ii` over the largest `‖d_c‖²`), positive definite wherever A is nonsingular with
//!   K ⪰ 0 (K ≻ 0 on the null space of Dᵀ). `A [x; y] = [f; g]` ⇔ `[K_ρ D; Dᵀ 0] [x; y] =
//!   [f + ρDg; g]`, solved with the Schur complement `S = DᵀK_ρ⁻¹D` (dense m×m, m solves
//!   once): `z = K_ρ⁻¹(f + ρDg)`, `y = S⁻¹(Dᵀz − g)`, `x = z − K_ρ⁻¹D y`. One sparse solve
//!   and O(N·m) per product; memory N·m ([`MAX_ROWS_ENTRIES`]). `|det A| = det K_ρ · det S`.
//!   The certificates never trust these solves: every bound built on `x̂ = A⁻¹y` uses its
//!   residual.
//! * **What is not available for coupled rows:** the analytic floor s₀ (0: the fourth end
//!   comes from the m×m test `λ_min(Dᵀ(K + sI)⁻¹D) ≥ s` or an LDLᵀ inertia test) and the
//!   Schur complement onto B ([`super::schur`], written for a Boolean D): where Temple's
//!   bounds miss the bracket width, the proof falls back to verified Cholesky tests, or the
//!   inertia brackets are reported unproven.

use super::blocks::dof_error;
use crate::conditioning::certify::{gamma, U};
use crate::error::{Error, Result};
use crate::linalg::{DiagonalPattern, SparseLlt};
use crate::system::{csc_position, Stiffness};
use faer::sparse::SparseColMat;
use faer::{Mat, Side};

/// Largest N·m for coupled rows (the dense `K_ρ⁻¹D` of the block inverse: 8·N·m bytes,
/// 800 MB at the limit).
pub const MAX_ROWS_ENTRIES: usize = 100_000_000;

/// One constraint row: `(DOF, coefficient)` terms.
pub type Row = Vec<(usize, f64)>;

/// An entry of `DDᵀ` on the pattern of `K + DDᵀ`.
pub(super) struct OuterEntry {
    /// Position in the pattern's values.
    pos: usize,
    /// Its row i (for the row sums of the rounding bound).
    row: usize,
    /// `w_ij = Σ_c a_ci a_cj`, summed in row order.
    value: f64,
    /// `Σ_c |a_ci a_cj|`.
    abs: f64,
    /// The number of rows that share the pair (i, j).
    terms: usize,
}

/// D's columns.
pub(super) enum Coupling<'a> {
    /// `e_d` for each DOF (distinct).
    Selection(&'a [usize]),
    /// General rows (terms sorted by DOF, no DOF twice in a row), with `DDᵀ`'s entries on the
    /// pattern of `K + DDᵀ`.
    Rows {
        rows: Vec<Row>,
        outer: Vec<OuterEntry>,
    },
}

/// D of the saddle point, with the mask of the DOFs it touches.
pub(super) struct Blocks<'a> {
    /// m, the number of constraints (columns of D).
    pub(super) m: usize,
    /// Whether DOF i has an entry in D (B for a Boolean D).
    pub(super) in_b: Vec<bool>,
    pub(super) d: Coupling<'a>,
}

impl<'a> Blocks<'a> {
    /// A Boolean D with columns `e_d`, `d ∈ dofs` (checked by the caller).
    pub(super) fn selection(dofs: &'a [usize], in_b: Vec<bool>) -> Self {
        Blocks {
            m: dofs.len(),
            in_b,
            d: Coupling::Selection(dofs),
        }
    }

    /// General rows, checked ([`checked_rows`]: errors on an out-of-range DOF, a DOF twice in
    /// a row, a non-finite or zero row, and unless 0 < m < N), on `pattern` (the pattern of
    /// `K + DDᵀ`, [`rows_on`]).
    fn rows(pattern: &DiagonalPattern, rows: Vec<Row>) -> Result<Blocks<'static>> {
        let n = pattern.n();
        let m = rows.len();
        let mut in_b = vec![false; n];
        for &(d, _) in rows.iter().flatten() {
            in_b[d] = true;
        }
        // Entries keyed by position, accumulated in row order.
        let mut at = std::collections::BTreeMap::<usize, OuterEntry>::new();
        for row in &rows {
            for &(i, a) in row {
                for &(j, b) in row {
                    let pos = csc_position(pattern.pat(), i, j).ok_or_else(|| {
                        Error::Numerical(format!(
                            "saddle-point cond₂: entry ({i}, {j}) of DDᵀ is not in the widened pattern"
                        ))
                    })?;
                    let e = at.entry(pos).or_insert(OuterEntry {
                        pos,
                        row: i,
                        value: 0.0,
                        abs: 0.0,
                        terms: 0,
                    });
                    e.value += a * b;
                    e.abs += (a * b).abs();
                    e.terms += 1;
                }
            }
        }
        Ok(Blocks {
            m,
            in_b,
            d: Coupling::Rows {
                rows,
                outer: at.into_values().collect(),
            },
        })
    }

    /// Whether D is Boolean.
    pub(super) fn is_selection(&self) -> bool {
        matches!(self.d, Coupling::Selection(_))
    }

    /// The terms of column c of D.
    pub(super) fn column(&self, c: usize) -> Box<dyn Iterator<Item = (usize, f64)> + '_> {
        match &self.d {
            Coupling::Selection(dofs) => Box::new(std::iter::once((dofs[c], 1.0))),
            Coupling::Rows { rows, .. } => Box::new(rows[c].iter().copied()),
        }
    }

    /// `x += scale · D g`.
    pub(super) fn add_d(&self, g: &[f64], scale: f64, x: &mut [f64]) {
        for (c, &gc) in g.iter().enumerate().take(self.m) {
            for (d, a) in self.column(c) {
                x[d] += scale * (a * gc);
            }
        }
    }

    /// `(Dᵀx)_c`.
    pub(super) fn dt(&self, x: &[f64], c: usize) -> f64 {
        self.column(c).map(|(d, a)| a * x[d]).sum()
    }

    /// `f⁻¹D` as a dense N×m matrix (m solves with the factor f of an N×N matrix).
    pub(super) fn solved(&self, f: &SparseLlt, n: usize) -> Mat<f64> {
        let mut x = Mat::<f64>::zeros(n, self.m);
        for c in 0..self.m {
            for (d, a) in self.column(c) {
                x[(d, c)] = a;
            }
        }
        f.solve_mat_in_place(x.as_mut());
        x
    }

    /// `(DᵀX)_ij` for a dense N×m X.
    pub(super) fn dt_col(&self, x: &Mat<f64>, i: usize, j: usize) -> f64 {
        self.column(i).map(|(d, a)| a * x[(d, j)]).sum()
    }

    /// Writes `α·K + σI + β·DDᵀ` on `pattern` into `out` and returns `max_e` with
    /// `4u·max_e` ≥ the 2-norm of its formation error (module doc): for a Boolean D
    /// [`DiagonalPattern::fill_shifted`]'s diagonal bound.
    pub(super) fn fill(
        &self,
        pattern: &DiagonalPattern,
        out: &mut Vec<f64>,
        alpha: f64,
        sigma: f64,
        beta: f64,
    ) -> f64 {
        match &self.d {
            Coupling::Selection(_) => {
                pattern.fill_shifted(out, alpha, sigma, beta, Some(&self.in_b))
            }
            Coupling::Rows { outer, .. } => {
                let diag_e = pattern.fill_shifted(out, alpha, sigma, 0.0, None);
                let mut row_e = vec![0.0f64; pattern.n()];
                for e in outer {
                    let before = out[e.pos];
                    out[e.pos] += beta * e.value;
                    row_e[e.row] +=
                        gamma(e.terms + 4) * (before.abs() + beta.abs() * e.abs) * (1.0 + 8.0 * U);
                }
                let worst = row_e.iter().copied().fold(0.0, f64::max);
                // u·diag_e covers the σ on the diagonal, the row sums the rest.
                diag_e + worst / (4.0 * U) * (1.0 + 8.0 * U)
            }
        }
    }
}

/// The rows with their terms sorted by DOF, zero terms dropped; errors on an out-of-range
/// DOF, a DOF twice in a row, a non-finite or zero row, and unless 0 < m < N.
fn checked_rows(n: usize, rows: &[Row]) -> Result<Vec<Row>> {
    let m = rows.len();
    if m == 0 || m >= n {
        return Err(Error::out_of_range(
            "saddle-point cond₂: the number of constraint rows m",
            m,
            format!("0 < m < N = {n}"),
        ));
    }
    let mut out = Vec::with_capacity(m);
    for row in rows {
        // Range and repeats are checked on every term, zero ones included (then dropped).
        let mut r: Row = row.clone();
        r.sort_by_key(|&(d, _)| d);
        if let Some(&(d, _)) = r.iter().find(|&&(d, _)| d >= n) {
            return Err(dof_error("saddle-point cond₂", n, d));
        }
        if let Some(w) = r.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(dof_error("saddle-point cond₂", n, w[0].0));
        }
        r.retain(|&(_, a)| a != 0.0);
        if r.is_empty() || r.iter().any(|&(_, a)| !a.is_finite()) {
            return Err(Error::NotFinite {
                what: "saddle-point cond₂: a constraint row (zero or not finite)".into(),
            });
        }
        out.push(r);
    }
    Ok(out)
}

/// Checks `rows` against K (N×N), widens K with explicit zeros at every entry of `DDᵀ` it
/// does not store (`Stiffness::with_entries_added`, the fill of `K + DEDᵀ`; K's own values
/// unchanged) and sets up D on that pattern. Errors as [`Blocks::rows`].
pub(super) fn rows_on(
    k: &SparseColMat<usize, f64>,
    rows: &[Row],
) -> Result<(DiagonalPattern, Blocks<'static>)> {
    square_and_finite(k)?;
    let rows = checked_rows(k.nrows(), rows)?;
    let zeros: Vec<(usize, usize, f64)> = rows
        .iter()
        .flat_map(|r| {
            r.iter()
                .flat_map(move |&(i, _)| r.iter().map(move |&(j, _)| (i, j, 0.0)))
        })
        .collect();
    let Stiffness::Sparse(wide) = Stiffness::Sparse(k.clone()).with_entries_added(&zeros) else {
        unreachable!("a sparse matrix stays sparse")
    };
    let pattern = DiagonalPattern::new(&wide)?;
    let blocks = Blocks::rows(&pattern, rows)?;
    Ok((pattern, blocks))
}

/// K as the coupled routes take it: square, every stored entry finite (else the input error
/// naming the first entry that is not).
pub(super) fn square_and_finite(k: &SparseColMat<usize, f64>) -> Result<()> {
    if k.nrows() != k.ncols() {
        return Err(Error::Unsupported {
            what: format!("a {}×{} K", k.nrows(), k.ncols()),
            needs: "a square K".into(),
        });
    }
    // Column by column over each column's stored range (storage need not start at 0).
    match k.triplet_iter().find(|t| !t.val.is_finite()) {
        Some(t) => Err(Error::not_finite(format!("K[{}, {}]", t.row, t.col))),
        None => Ok(()),
    }
}

/// `A⁻¹` through the augmented block `K_ρ = K + ρDDᵀ` (module doc).
pub(super) struct AugmentedInverse<'a> {
    blocks: &'a Blocks<'a>,
    rho: f64,
    k_rho: SparseLlt,
    /// `K_ρ⁻¹D`, N×m.
    w: Mat<f64>,
    /// Cholesky of `S = DᵀK_ρ⁻¹D` (symmetrized).
    s: faer::linalg::solvers::Llt<f64>,
    log10_det_s: f64,
    /// Work vector of length m.
    t: Mat<f64>,
}

impl<'a> AugmentedInverse<'a> {
    /// Factors `K_ρ` and `S`; [`Error::Singular`] where either is not positive definite.
    pub(super) fn new(pattern: &DiagonalPattern, blocks: &'a Blocks<'a>) -> Result<Self> {
        let (n, m) = (pattern.n(), blocks.m);
        if n.saturating_mul(m) > MAX_ROWS_ENTRIES {
            return Err(Error::out_of_range(
                "saddle-point cond₂ with coupled rows: N·m",
                n.saturating_mul(m),
                format!("at most {MAX_ROWS_ENTRIES}"),
            ));
        }
        let d_max = (0..m)
            .map(|c| blocks.column(c).map(|(_, a)| a * a).sum::<f64>())
            .fold(0.0, f64::max);
        let rho = pattern.max_diagonal() / d_max;
        let singular = || {
            Error::singular(
                "saddle-point matrix is singular: K + ρDDᵀ or DᵀK_ρ⁻¹D is not positive definite",
            )
        };
        if !(rho.is_finite() && rho > 0.0) {
            return Err(singular());
        }
        let mut values = Vec::new();
        blocks.fill(pattern, &mut values, 1.0, 0.0, rho);
        let k_rho = pattern.factor(&values).ok_or_else(singular)?;
        let w = blocks.solved(&k_rho, n);
        let s = Mat::from_fn(m, m, |i, j| blocks.dt_col(&w, i, j));
        let s = Mat::from_fn(m, m, |i, j| 0.5 * (s[(i, j)] + s[(j, i)]));
        let s = s.llt(Side::Lower).map_err(|_| singular())?;
        // Dependence is a property of the rows' directions, not of their scales: with
        // `N = diag(1/‖d_c‖)`, the Cholesky factor of `N S N` is `N L`, so its pivots are
        // `L_ii²/‖d_i‖²`, each in [λ_min(NSN), λ_max(NSN)]. A spread above 1/(64ε_mach)
        // proves cond₂(NSN) above it: the rows, scaled to unit norm, are dependent to
        // working precision (two-pass node-to-segment; [1, 1] and [2, 2] on two DOFs spread
        // by 2e14). Unnormalized pivots would refuse independent rows of different scales
        // (rows 1e8·e₀ and e₁ on K = I: a spread of 1e16, cond₂(A) = 1.6e8).
        let pivots = (0..m).map(|i| {
            let norm2: f64 = blocks.column(i).map(|(_, a)| a * a).sum();
            s.L()[(i, i)].powi(2) / norm2
        });
        let (lo, hi) = pivots.fold((f64::INFINITY, 0.0f64), |(lo, hi), p| {
            (lo.min(p), hi.max(p))
        });
        if lo * (1.0 / (64.0 * f64::EPSILON)) < hi {
            return Err(Error::singular(
                "saddle-point matrix is singular to working precision: the constraint rows are \
                 linearly dependent (DᵀK_ρ⁻¹D with unit rows spreads its Cholesky pivots by more \
                 than 1/(64ε_mach))",
            ));
        }
        let log10_det_s = (0..m).map(|i| 2.0 * s.L()[(i, i)].log10()).sum();
        Ok(AugmentedInverse {
            blocks,
            rho,
            k_rho,
            w,
            s,
            log10_det_s,
            t: Mat::zeros(m, 1),
        })
    }

    /// `log10|det A| = log10 det K_ρ + log10 det S`.
    pub(super) fn log10_det(&self) -> f64 {
        self.k_rho.log10_det() + self.log10_det_s
    }

    /// `out = sign·A⁻¹v`.
    pub(super) fn apply(&mut self, v: &[f64], out: &mut [f64], sign: f64) {
        let n = self.w.nrows();
        let (f, g) = v.split_at(n);
        let (x, y) = out.split_at_mut(n);
        x.copy_from_slice(f);
        self.blocks.add_d(g, self.rho, x);
        self.k_rho.solve_vec_in_place(x);
        for (c, gc) in g.iter().enumerate() {
            self.t[(c, 0)] = self.blocks.dt(x, c) - gc;
        }
        faer::linalg::solvers::Solve::solve_in_place(&self.s, self.t.as_mut());
        for (c, yc) in y.iter_mut().enumerate() {
            *yc = self.t[(c, 0)];
            let wc = self.w.col(c);
            for (xi, wi) in x.iter_mut().zip(wc.iter()) {
                *xi -= wi * *yc;
            }
        }
        if sign < 0.0 {
            out.iter_mut().for_each(|o| *o = -*o);
        }
    }
}

/// `[K D; Dᵀ 0]` in CSC with both triangles for general rows (K's columns from `pattern`,
/// each followed by its D entries `(N + c, a_cj)` in row order; then D's columns), for
/// products and Rayleigh quotients. A Boolean D takes [`super::blocks::saddle_csc`].
pub(super) fn rows_csc(
    pattern: &DiagonalPattern,
    blocks: &Blocks<'_>,
) -> (faer::sparse::SymbolicSparseColMat<usize>, Vec<f64>) {
    let (n, m) = (pattern.n(), blocks.m);
    let mut by_dof: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
    for c in 0..m {
        for (d, a) in blocks.column(c) {
            by_dof[d].push((n + c, a));
        }
    }
    let (cp, ri) = (pattern.pattern.col_ptr(), pattern.pattern.row_idx());
    let mut col_ptr = Vec::with_capacity(n + m + 1);
    let mut row_idx = Vec::with_capacity(ri.len() + 2 * by_dof.iter().map(Vec::len).sum::<usize>());
    let mut values = Vec::with_capacity(row_idx.capacity());
    col_ptr.push(0);
    for (j, entries) in by_dof.iter().enumerate() {
        row_idx.extend_from_slice(&ri[cp[j]..cp[j + 1]]);
        values.extend_from_slice(&pattern.values[cp[j]..cp[j + 1]]);
        for &(r, a) in entries {
            row_idx.push(r);
            values.push(a);
        }
        col_ptr.push(row_idx.len());
    }
    for c in 0..m {
        for (d, a) in blocks.column(c) {
            row_idx.push(d);
            values.push(a);
        }
        col_ptr.push(row_idx.len());
    }
    let size = n + m;
    (
        faer::sparse::SymbolicSparseColMat::new_checked(size, size, col_ptr, None, row_idx),
        values,
    )
}

/// `±A⁻¹` for either kind of D.
pub(super) enum Inverse<'a> {
    /// Block elimination with K_FF (Boolean D).
    Free(super::blocks::BlockInverse<'a>),
    /// Through `K_ρ = K + ρDDᵀ` (coupled rows).
    Augmented(AugmentedInverse<'a>),
}

impl Inverse<'_> {
    /// `out = sign·A⁻¹v`.
    pub(super) fn apply(&mut self, v: &[f64], out: &mut [f64], sign: f64) {
        match self {
            Inverse::Free(b) => b.apply(v, out, sign),
            Inverse::Augmented(a) => a.apply(v, out, sign),
        }
    }
}
