//! What the cond₂ certificates prove, and the rigorous pieces they are built from.
//!
//! Every bound below holds for the *stored* matrix A (its floating-point entries, exact as
//! given) under the standard model of IEEE double arithmetic with round to nearest,
//! `fl(a ∘ b) = (a ∘ b)(1 + δ)`, `|δ| ≤ u = ε_mach/2`, without underflow (fused multiply–adds
//! only remove roundings). Nothing rests on a converged estimate: estimates choose *where* to
//! test, the theorems below decide *what* the test proves. u, `γ_k = ku/(1 − ku)`.
//!
//! **Lemma 1 (a Cholesky test that succeeds).** Let B̃ be symmetric with floating-point
//! entries and let floating-point Cholesky of B̃ run to completion, L̂ with positive pivots.
//! Then `L̂L̂ᵀ = B̃ + ΔB` with `|ΔB| ≤ γ_{r+1}|L̂||L̂ᵀ|` (Demmel 1989; Higham, *Accuracy and
//! Stability of Numerical Algorithms*, 2nd ed., Thm 10.3, with the inner-product length n
//! replaced by r, the largest row count of L̂: structurally zero terms add exact zeros, and
//! the bound holds for any order of summation, blocked or not). With `c` the largest column
//! count of L̂, Cauchy–Schwarz over each column gives
//! `|x|ᵀ|L̂||L̂ᵀ||x| = Σ_k (Σ_i |l̂_ik||x_i|)² ≤ c Σ_i ‖l̂_i‖² x_i²`, and
//! `‖l̂_i‖² = (B̃ + ΔB)_ii ≤ b̃_ii / (1 − γ_{r+1})`, so for every x
//!
//! `xᵀB̃x ≥ −m₀ Σ_i b̃_ii x_i²`,  `m₀ = c·γ_{r+1}/(1 − γ_{r+1})`.
//!
//! A shifted test matrix is formed in floating point, `b̃_ii = fl(±a_ii + σ)`: one rounding
//! on the diagonal, so the exact `B = ±A + σI` satisfies `xᵀBx ≥ −m Σ_i b̃_ii x_i²` with
//! `m = m₀ + 2u` ([`Margin`]). r and c come from the symbolic factorization
//! ([`Margin::of`]); they are the true counts of the sparse factor (explicit zeros of relaxed
//! supernodes only enlarge them).
//!
//! **Corollary 2 (λ_max from above).** If Cholesky of `fl(σI − A)` succeeds,
//! `λ_max(A) ≤ σ + m·max_i b̃_ii` ([`Margin::upper_from_test`]).
//!
//! **Corollary 3 (λ_min from below, normwise).** If Cholesky of `fl(A − σI)` succeeds,
//! `λ_min(A) ≥ σ − m·max_i b̃_ii`.
//!
//! **Theorem 4 (λ_min from below, graded).** With `ŝ_i = fl(√a_ii)` and `Ĥ = Ŝ⁻¹AŜ⁻¹` (exactly
//! congruent to A), let `h ≤ λ_min(Ĥ)`. If Cholesky of `fl(A − σI)` succeeds, σ > 0, then
//! `λ_min(A) ≥ σ / (1 + (1 + 5u)·m / h)`. Proof: `b̃_ii ≤ (1 + u)a_ii ≤ (1 + 4u)ŝ_i²`, so for a
//! unit x, `xᵀAx − σ ≥ −m(1 + 5u)‖Ŝx‖²` and `xᵀAx = (Ŝx)ᵀĤ(Ŝx) ≥ h‖Ŝx‖²`. This is the
//! Demmel–Veselić observation ("Jacobi's method is more accurate than QR", SIAM J. Matrix
//! Anal. Appl. 13, 1992) made rigorous: the loss relative to λ_min is `≈ m·cond₂(Ĥ)`, not
//! `m·cond₂(A)` — orders of magnitude apart for `K + D E Dᵀ` with a large ε.
//!
//! **Lemma 5 (h).** `h̃_ij = fl(fl(a_ij/ŝ_i)/ŝ_j) = ĥ_ij(1 + θ)`, `|θ| ≤ γ₂`. If Cholesky of
//! `fl(H̃ − τI)` succeeds, Corollary 3 and `‖Ĥ − H̃‖₂ ≤ γ₂/(1 − γ₂)·max_i Σ_j |h̃_ij|` give
//! `λ_min(Ĥ) ≥ τ − m·max_i c̃_ii − γ₂/(1 − γ₂)·max_i Σ_j |h̃_ij|` ([`Margin::graded_floor`]).
//!
//! **Lemma 6 (upper bounds from vectors).** For any y ≠ 0, `λ_min ≤ ρ(y) ≤ λ_max` with
//! `ρ(y) = yᵀAy / yᵀy` (Courant–Fischer), and for any x̂,
//! `yᵀA⁻¹y ≥ 2x̂ᵀy − x̂ᵀAx̂` (expand `(x̂ − A⁻¹y)ᵀA(x̂ − A⁻¹y) ≥ 0`), so
//! `λ_min ≤ yᵀy / (2x̂ᵀy − x̂ᵀAx̂)` where the denominator is positive. With x̂ a computed
//! `A⁻¹y` the gap of this bound is `(x̂ − A⁻¹y)ᵀA(x̂ − A⁻¹y)`, quadratic in the solve error
//! — sharp even where ρ(y) is not (a graded A inflates ρ(y) by the stiff components of the
//! error of y). It is evaluated as `x̂ᵀ(y + r)`, `r = y − Ax̂`, both by compensated dot
//! products (Dot2 of Ogita, Rump & Oishi, SIAM J. Sci. Comput. 26, 2005: every product exact
//! by two_prod, [`crate::dd`], error ≤ u|result| + γ_N²·Σ|terms|) — the rounding of the
//! evaluation is far below the ε_mach level of the bounds. `λ_max ≥ ρ(y_top)` is evaluated in
//! f64 with the standard bounds (Higham §3.1–3.5; at the top of the spectrum they cost only
//! ≈ k·ε relative).
//!
//! **Lemma 7a (the factor's own a-priori margin).** Entry (p, q) of `L̂L̂ᵀ` sums
//! `N_pq ≤ min(r_p, r_q)` products (r_i: the entries of row i of L̂), so Lemma 1 holds entrywise
//! with `γ_{N_pq+1} ≤ g_p g_q`, `g_i = √γ_{r_i+1}`, and with `D = diag(√b̃_ii)` (permuted)
//! `|xᵀ(L̂L̂ᵀ − B̃)x| ≤ ρ(D⁻¹G|L̂||L̂ᵀ|GD⁻¹)‖Dx‖²`; the Perron root is at most the largest entry
//! of `D⁻¹G|L̂||L̂ᵀ|GD⁻¹𝟙` (Collatz–Wielandt), two products with |L̂|. With the 2u of the shift's
//! rounding this is a margin m in the sense of Lemma 1 ([`factor_margin`](super::residual::factor_margin)).
//!
//! **Lemma 7 (the residual's margin).** With `E = L̂L̂ᵀ − PBPᵀ` for the exact `B = αA + σI`,
//! `xᵀBx = ‖L̂ᵀPx‖² − (Px)ᵀE(Px) ≥ −ρ(D⁻¹|E|D⁻¹)‖DPx‖²`. Every entry of E is formed over every
//! position L̂L̂ᵀ or B reaches by compensated sums (products exact by two_prod, `αa_ii + σ`
//! exact by two_sum; Dot2's bound gives `|E_pq| ≤ |ê_pq|(1 + 2u) + 2γ_N²Σ|terms|`, Σ|terms| of
//! the products ≤ ‖l̂_p‖‖l̂_q‖), and the Perron root is bounded by the largest row sum
//! ([`posterior_margin`](super::residual::posterior_margin)). Measured, not bounded: a few u to a few tens of u where Lemma 1 gives
//! thousands. Both replace m in Corollaries 2–3 and Theorem 4 unchanged; the routes use the
//! smallest margin they computed, Lemma 7 only where Lemmas 1 and 7a miss the width target
//! `max(1e-12, 8·ε_mach·cond₂(Ĥ))` and the factor has at most
//! [`POSTERIOR_MAX_PRODUCTS`] products. At λ_min the SPD route tries
//! Temple's bound first (Lemma 8 and Theorem 9, [`super::temple`]): one LDLᵀ inertia test
//! instead of a Cholesky test and its residual.
//!
//! What is *not* proven: that the reported point value (the ratio of the converged Lanczos
//! estimates, or the dense routine's) equals the exact value; it is tested against
//! outside references, and it is clamped into the proven bracket.

use crate::conditioning::lanczos::dot;
use crate::dd::{two_prod, two_sum, Dd};
use crate::linalg::symmetric_matvec;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::sparse::SymbolicSparseColMatRef;

/// Largest factor (products `Σ_k c_k²` of a factorization, [`factor_products`]) for
/// which the tests compute Lemma 7's residual (≈ 5× the factorization; measured 105 µs against
/// 20 µs on the 400-DOF membrane, `cargo bench --bench cond -- posterior_margin`). Above it
/// (the 10⁵–10⁶-DOF membranes: seconds per residual) the bounds rest on Lemmas 1 and 7a and the
/// tests keep Lemma 1's placement (no extra factorization); their widths can exceed the
/// target.
pub const POSTERIOR_MAX_PRODUCTS: f64 = 2e7;

/// Unit roundoff u = ε_mach / 2.
pub const U: f64 = f64::EPSILON / 2.0;

/// `γ_k = ku / (1 − ku)`.
pub fn gamma(k: usize) -> f64 {
    let t = k as f64 * U;
    t / (1.0 - t)
}

/// `x` rounded away from zero by a few units (for bounds computed in plain f64 from
/// non-negative terms: each of the few operations that formed `x` is covered).
pub(crate) fn up(x: f64) -> f64 {
    x * (1.0 + 8.0 * U)
}

fn down(x: f64) -> f64 {
    x * (1.0 - 8.0 * U)
}

/// Cholesky tests per bracket end before it is given up (each ×8 further out).
pub(crate) const TEST_TRIES: usize = 24;

/// The search every proven bracket end makes: `attempt(w, k)` is tried with a relative offset
/// `w = w0·8^k` for k = 0, 1, … until it succeeds (a Cholesky test at `σ(1 ± w)` that passes)
/// or [`TEST_TRIES`] offsets were tried; its result, or None.
pub(crate) fn step_outwards<T>(w0: f64, attempt: impl FnMut(f64, usize) -> Option<T>) -> Option<T> {
    step_outwards_by(w0, 8.0, attempt)
}

/// [`step_outwards`] with offsets `w0·growth^k`, as many as reach `w0·8^TEST_TRIES`: a
/// finer search where the width of the bracket is the offset of the first test that passes
/// (the a-posteriori tests of certify, Lemma 7).
pub(crate) fn step_outwards_by<T>(
    w0: f64,
    growth: f64,
    mut attempt: impl FnMut(f64, usize) -> Option<T>,
) -> Option<T> {
    let tries = (TEST_TRIES as f64 * 8f64.ln() / growth.ln()).ceil() as usize;
    let mut w = w0;
    for k in 0..tries {
        if let Some(t) = attempt(w, k) {
            return Some(t);
        }
        w *= growth;
    }
    None
}

/// The backward-error margin `m` of a successful Cholesky test (Lemma 1 in the module doc).
#[derive(Clone, Copy, Debug)]
pub struct Margin {
    /// `m = c·γ_{r+1}/(1 − γ_{r+1}) + 2u`, rounded up.
    pub m: f64,
}

impl Margin {
    /// The margin for factors with largest row count `r` and column count `c` (diagonal
    /// included).
    pub fn from_counts(r: usize, c: usize) -> Self {
        let g = gamma(r + 1);
        Margin {
            m: up(c as f64 * g / (1.0 - g) + 2.0 * U),
        }
    }

    /// The margin for every factor of one symbolic analysis.
    pub fn of(symbolic: &SymbolicCholesky<usize>) -> Self {
        let (r, c) = factor_counts(symbolic);
        Self::from_counts(r, c)
    }

    /// Corollary 2: `λ_max ≤ σ + m·max_i b̃_ii` after Cholesky of `fl(σI − A)` succeeded
    /// (`max_b`: the largest diagonal entry of the test matrix as stored).
    pub fn upper_from_test(&self, sigma: f64, max_b: f64) -> f64 {
        up(sigma + up(self.m * max_b))
    }

    /// Corollary 3 and Theorem 4: the better lower bound of λ_min after Cholesky of
    /// `fl(A − σI)` succeeded; `h` a proven lower bound of λ_min(Ŝ⁻¹AŜ⁻¹) where there is one.
    pub fn lower_from_test(&self, sigma: f64, max_b: f64, h: Option<f64>) -> f64 {
        let normwise = down(sigma - up(self.m * max_b));
        let graded = h.filter(|&h| h > 0.0).map_or(0.0, |h| {
            down(sigma / up(1.0 + up(self.m * (1.0 + 5.0 * U)) / h))
        });
        normwise.max(graded).max(0.0)
    }

    /// Lemma 5: `λ_min(Ĥ) ≥ τ − m·max_i c̃_ii − γ₂/(1 − γ₂)·rowsum` after Cholesky of
    /// `fl(H̃ − τI)` succeeded (`max_c`: its largest stored diagonal entry; `rowsum`:
    /// `max_i Σ_j |h̃_ij|`).
    pub fn graded_floor(&self, tau: f64, max_c: f64, rowsum: f64) -> f64 {
        let g2 = gamma(2);
        down(tau - up(self.m * max_c) - up(g2 / (1.0 - g2) * rowsum))
    }
}

/// The largest row count r and column count c of the Cholesky factor of a symbolic analysis
/// (diagonal included; permutation-invariant).
pub fn factor_counts(symbolic: &SymbolicCholesky<usize>) -> (usize, usize) {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let (cp, ri) = (s.col_ptr(), s.row_idx());
            let n = s.nrows();
            let mut rows = vec![0usize; n];
            let mut c = 0;
            for j in 0..n {
                c = c.max(cp[j + 1] - cp[j]);
                for &i in &ri[cp[j]..cp[j + 1]] {
                    rows[i] += 1;
                }
            }
            // A simplicial factor may leave the diagonal implicit: count it once more.
            (rows.into_iter().max().unwrap_or(0) + 1, c + 1)
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let n = s.nrows();
            let (begin, end) = (s.supernode_begin(), s.supernode_end());
            let (rp, ri) = (s.col_ptr_for_row_idx(), s.row_idx());
            let mut rows = vec![0usize; n];
            let mut c = 0;
            for k in 0..s.n_supernodes() {
                let (b, e) = (begin[k], end[k]);
                let w = e - b;
                let below = &ri[rp[k]..rp[k + 1]];
                c = c.max(w + below.len());
                for (t, r) in rows[b..e].iter_mut().enumerate() {
                    *r += t + 1;
                }
                for &i in below {
                    rows[i] += w;
                }
            }
            (rows.into_iter().max().unwrap_or(0), c)
        }
    }
}

/// `Σ_k c_k²` over the column counts c_k of the Cholesky factor (diagonal included): the
/// products of a numeric factorization, and of the residual of Lemma 7.
pub fn factor_products(symbolic: &SymbolicCholesky<usize>) -> f64 {
    match symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            let cp = s.col_ptr();
            (0..s.nrows())
                .map(|j| ((cp[j + 1] - cp[j]) as f64).powi(2))
                .sum()
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let (begin, end) = (s.supernode_begin(), s.supernode_end());
            let rp = s.col_ptr_for_row_idx();
            (0..s.n_supernodes())
                .map(|k| {
                    let (w, below) = (end[k] - begin[k], rp[k + 1] - rp[k]);
                    (0..w)
                        .map(|t| ((w - t + below) as f64).powi(2))
                        .sum::<f64>()
                })
                .sum()
        }
    }
}

/// A rigorous interval `[lo, hi]` of a real number computed in double-double with the error
/// bound `err` (absolute).
fn interval(v: Dd, err: f64) -> (f64, f64) {
    let f = v.to_f64();
    // The conversion to f64 is one more rounding (≤ u|f|); the subtraction/addition another.
    let slack = up(err + 2.0 * U * f.abs());
    (
        f - slack - 2.0 * U * (f.abs() + slack),
        f + slack + 2.0 * U * (f.abs() + slack),
    )
}

crate::dd::fma_dispatch! {
    /// `xᵀy` in double-double, as a rigorous interval (FMA build where the CPU has it).
    pub fn dot_interval(x: &[f64], y: &[f64]) -> (f64, f64) => dot_interval_kernel
}

#[inline(always)]
fn dot_interval_kernel(x: &[f64], y: &[f64]) -> (f64, f64) {
    let mut s = Dd::ZERO;
    let mut abs = 0.0f64;
    for (a, b) in x.iter().zip(y) {
        s = s + Dd::prod(*a, *b);
        abs += (a * b).abs();
    }
    let n = x.len().min(y.len());
    interval(s, up(16.0 * (n as f64 + 2.0) * U * U * up(abs)))
}

/// `r_j = c·y_j − Σ_i a_ij x_i` for every column j of the symmetric A by compensated dot
/// products (Dot2 of Ogita, Rump & Oishi 2005; `c·y_j` exact by two_prod), with a bound
/// `e_j ≥ |r̂_j − r_j|`: `e_j = (u|r̂_j| + γ_{k+1}²(|c·y_j| + Σ_i |a_ij x_i|))` rounded up.
/// Inlined into its callers (and so into their FMA builds, `dd::fma_dispatch`).
#[inline(always)]
pub(crate) fn residual_dot2(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    x: &[f64],
    c: f64,
    y: &[f64],
) -> Vec<(f64, f64)> {
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let k = (0..y.len()).map(|j| cp[j + 1] - cp[j]).max().unwrap_or(0);
    let g2 = gamma(k + 1).powi(2);
    // A plain loop (no closures): inlined whole into an FMA build (`crate::dd::fma_dispatch`).
    let mut out = Vec::with_capacity(y.len());
    for (j, &yj) in y.iter().enumerate() {
        let (a, b) = (cp[j], cp[j + 1]);
        let (mut p, mut s) = two_prod(c, yj);
        let mut abs = (c * yj).abs();
        for (&i, &v) in ri[a..b].iter().zip(&values[a..b]) {
            let (h, e) = two_prod(-v, x[i]);
            let (t, q) = two_sum(p, h);
            p = t;
            s += q + e;
            abs += (v * x[i]).abs();
        }
        let r = p + s;
        out.push((r, up(U * r.abs() + g2 * abs)));
    }
    out
}

crate::dd::fma_dispatch! {
    /// Lemma 6: a rigorous upper bound of λ_min(A) from y and an approximate `x̂ ≈ A⁻¹y`:
    /// `yᵀy / g`, `g = 2x̂ᵀy − x̂ᵀAx̂ = x̂ᵀ(y + r)` with the residual `r = y − Ax̂` (None where g is
    /// not certainly positive).
    ///
    /// Both sums are compensated dot products (Dot2 of Ogita, Rump & Oishi, "Accurate sum and dot
    /// product", SIAM J. Sci. Comput. 26, 2005: `|res − xᵀy| ≤ u|xᵀy| + γ_N²|x|ᵀ|y|` for N
    /// terms), so the cancellation in r (|r| ≪ |y| for a good solve; in f64 it would cost
    /// k·ε·cond₂ relative) leaves an error of order u² — the bound is as sharp as the solve.
    ///
    /// Compiled with FMA where the CPU has it (its two_prods).
    pub fn inverse_rayleigh_upper(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
        y: &[f64],
        x_hat: &[f64],
    ) -> Option<f64> => inverse_rayleigh_kernel
}

#[inline(always)]
fn inverse_rayleigh_kernel(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    y: &[f64],
    x_hat: &[f64],
) -> Option<f64> {
    // g = Σ_j (x̂_j y_j + x̂_j r̂_j) by Dot2: |ĝ − x̂ᵀ(y + r̂)| ≤ u|ĝ| + γ_2n² Σ|terms|, and
    // |x̂ᵀ(r̂ − r)| ≤ Σ_j |x̂_j| e_j.
    let n = y.len();
    let (mut gp, mut gs) = (0.0f64, 0.0f64);
    let (mut gabs, mut rerr) = (0.0f64, 0.0f64);
    for ((&xj, &yj), (r, e)) in x_hat
        .iter()
        .zip(y)
        .zip(residual_dot2(pattern, values, x_hat, 1.0, y))
    {
        rerr += xj.abs() * e;
        for (u, v) in [(xj, yj), (xj, r)] {
            let (h, e) = two_prod(u, v);
            let (t, q) = two_sum(gp, h);
            gp = t;
            gs += q + e;
            gabs += (u * v).abs();
        }
    }
    let g = gp + gs;
    let err = up(up(U * g.abs()) + up(gamma(2 * n).powi(2) * gabs) + up(rerr));
    let (_, yy_hi) = dot_interval(y, y);
    let lo = down(g - err);
    (lo > 0.0 && yy_hi.is_finite()).then(|| up(yy_hi / lo))
}

/// A rigorous upper bound of `‖Ax‖₂` for the square A (`values` on `pattern`, CSC, both
/// triangles of a symmetric matrix stored) from a right-hand side y with `x ≈ A⁻¹y`: the
/// residual `r = y − Ax` by compensated dot products (Ogita, Rump & Oishi 2005), then
/// `‖Ax‖ = ‖y − r‖ ≤ ‖y − r̂‖ + ‖r̂ − r‖` with every rounding bounded. Sharp where x is a good
/// solve (|r| ≪ |y|): an f64 product Ax would carry k·ε·‖|A||x|‖ of rounding, ≈ k·ε·cond₂
/// relative for a vector near the bottom of the spectrum.
pub fn image_norm_upper(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    x: &[f64],
    y: &[f64],
) -> f64 {
    let mut err2 = 0.0f64;
    let mut d = Vec::with_capacity(y.len());
    for (&yj, (r, e)) in y.iter().zip(residual_dot2(pattern, values, x, 1.0, y)) {
        // |fl(y_j − r̂_j) − (y_j − r̂_j)| ≤ u|fl(·)|.
        d.push(up((yj - r).abs() * (1.0 + 2.0 * U)));
        err2 += e * e;
    }
    // ‖d‖² in double-double (a plain sum of N squares would carry γ_N, ≈ N·u relative: 1e-10
    // at a million unknowns); the tiny e only in f64.
    let (_, sq) = dot_interval(&d, &d);
    up(up(sq.sqrt()) + up(err2.sqrt() * (1.0 + gamma(y.len() + 2))))
}

/// An interval `[lo, hi]` that contains the exact Rayleigh quotient `ρ(y) = yᵀAy / yᵀy` of the
/// symmetric A (`values` on `pattern`, both triangles stored), from its floating-point
/// evaluation and the standard error bounds (Higham, *Accuracy and Stability*, §3.1–3.5; u = ε_mach/2, γ_k = ku/(1 − ku)):
/// `z = fl(Ay)` has `|z − Ay| ≤ γ_k |A||y|` with k the most entries of a column, and
/// `fl(yᵀz)` is within `γ_n |y|ᵀ|z|` of `yᵀz`, so `yᵀAy` is within
/// `E = γ_n |y|ᵀ|z| + γ_k |y|ᵀ|A||y|` of the computed numerator; `yᵀy` within `γ_n` relative
/// of its computed value. The bound is inflated by 2 and the divisions by 8u for the
/// rounding of the bound itself. None unless the numerator is certainly positive.
pub(crate) fn rayleigh_interval(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    y: &[f64],
) -> Option<(f64, f64)> {
    let n = y.len();
    let (cp, ri) = (pattern.col_ptr(), pattern.row_idx());
    let mut z = vec![0.0; n];
    symmetric_matvec(pattern, values, y, &mut z);
    let mut abs_form = 0.0; // |y|ᵀ|A||y|
    let mut k = 0usize;
    for (j, &yj) in y.iter().enumerate() {
        k = k.max(cp[j + 1] - cp[j]);
        for p in cp[j]..cp[j + 1] {
            abs_form += (values[p] * yj).abs() * y[ri[p]].abs();
        }
    }
    let num = dot(y, &z);
    let den = dot(y, y);
    let abs_num: f64 = y.iter().zip(&z).map(|(a, b)| (a * b).abs()).sum();
    let u = 0.5 * f64::EPSILON;
    let gamma = |m: usize| (m as f64 * u) / (1.0 - m as f64 * u);
    let e = 2.0 * (gamma(n) * abs_num + gamma(k) * abs_form);
    let g = 2.0 * gamma(n);
    let lo = (num - e) / (den * (1.0 + g)) * (1.0 - 8.0 * u);
    let hi = (num + e) / (den * (1.0 - g)) * (1.0 + 8.0 * u);
    (lo > 0.0 && hi.is_finite() && den > 0.0).then_some((lo, hi))
}

crate::dd::fma_dispatch! {
    /// [`rayleigh_interval`] to the u² level: `−Ay` by compensated dot products
    /// ([`residual_dot2`] with c = 0, each entry within `e_j` of the exact one), then
    /// `yᵀAy ∈ −[Σ_j y_j r̂_j] ± Σ_j |y_j| e_j` and `yᵀy` by [`dot_interval`] (double-double). For
    /// the top of a spectrum where the plain bound (`≈ (n + k)·u` relative) is wider than the
    /// bracket wanted; ≈ 3 products' work. None unless the numerator is certainly positive.
    pub(crate) fn rayleigh_interval_dot2(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
        y: &[f64],
    ) -> Option<(f64, f64)> => rayleigh_dot2_kernel
}

#[inline(always)]
fn rayleigh_dot2_kernel(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    y: &[f64],
) -> Option<(f64, f64)> {
    let zero = vec![0.0; y.len()];
    let (r, e): (Vec<f64>, Vec<f64>) = residual_dot2(pattern, values, y, 0.0, &zero)
        .into_iter()
        .unzip();
    let rerr = up(y.iter().zip(&e).map(|(a, b)| a.abs() * b).sum::<f64>()) * (1.0 + gamma(y.len()));
    let (lo_r, hi_r) = dot_interval_kernel(y, &r);
    let (num_lo, num_hi) = (down(-hi_r - rerr), up(-lo_r + rerr));
    let (yy_lo, yy_hi) = dot_interval_kernel(y, y);
    (num_lo > 0.0 && yy_lo > 0.0 && num_hi.is_finite())
        .then(|| (down(num_lo / yy_hi), up(num_hi / yy_lo)))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    pub(crate) use crate::linalg::test_matrices::second_difference;

    /// The rigorous dot product contains the exact value (i128 on integer data scaled by a
    /// power of two) and is a few ulps wide, also under heavy cancellation.
    #[test]
    fn dot_interval_contains_the_exact_value() {
        let n = 500i128;
        let xi: Vec<i128> = (0..n).map(|i| (i * i) % 97 - 48).collect();
        let yi: Vec<i128> = (0..n).map(|i| (i * 7) % 53 - 26).collect();
        let x: Vec<f64> = xi.iter().map(|&v| v as f64 * 1e8).collect();
        let y: Vec<f64> = yi.iter().map(|&v| v as f64 / 64.0).collect();
        let exact: i128 = xi.iter().zip(&yi).map(|(a, b)| a * b).sum();
        let exact = exact as f64 * 1e8 / 64.0;
        let (lo, hi) = dot_interval(&x, &y);
        assert!(lo <= exact && exact <= hi, "{exact} ∉ [{lo}, {hi}]");
        assert!(
            hi - lo <= 64.0 * f64::EPSILON * exact.abs().max(1e8),
            "[{lo}, {hi}]"
        );
    }

    /// Lemma 6 on the second difference: the inverse Rayleigh bound with an exact eigenvector
    /// and a solve contains λ_1 = 2 − 2cos(π/(n+1)) from above, to a few ulps.
    #[test]
    fn inverse_rayleigh_bounds_lambda_min_from_above() {
        let n = 200;
        let a = second_difference(n);
        let th = std::f64::consts::PI / (n as f64 + 1.0);
        let l1 = 2.0 - 2.0 * th.cos();
        let y: Vec<f64> = (1..=n).map(|i| (i as f64 * th).sin()).collect();
        let x: Vec<f64> = y.iter().map(|v| v / l1).collect();
        let hi = inverse_rayleigh_upper(a.symbolic(), a.val(), &y, &x).unwrap();
        assert!(hi >= l1 * (1.0 - 4.0 * f64::EPSILON), "{hi} < {l1}");
        assert!(hi <= l1 * (1.0 + 1e-12), "{hi} vs {l1}");
    }

    /// The counts of a tridiagonal factor: two per row and column, each possibly counted once
    /// more for an implicit diagonal, never fewer.
    #[test]
    fn counts_of_a_tridiagonal_factor() {
        let a = second_difference(40);
        let s = crate::linalg::SparseLlt::analyze(&a).unwrap();
        let (r, c) = factor_counts(&s);
        assert!((2..=4).contains(&r) && (2..=4).contains(&c), "r {r}, c {c}");
    }
}
