//! λ_min from below by Temple's inequality: a bound second order in the residual of an
//! eigenvector estimate, from one inertia test that bounds λ₂ — in place of a Cholesky test
//! judged by its factor's residual ([`super::certify`], Lemma 7: ≈ 5 factorizations).
//!
//! **Theorem 9 (Temple 1928, Kato 1949, for any shift).** Let A be symmetric with eigenvalues
//! λ₁ ≤ λ₂ ≤ …, x ≠ 0, θ any real, `ρ² = ‖(A − θI)x‖²`, `g = xᵀ(A − θI)x`, and μ ≤ λ₂ with
//! `δ = μ − θ > 0` and `δ‖x‖² > |g|`. Then
//!
//! `λ₁ ≥ θ − (ρ² + δ|g|) / (δ‖x‖² − |g|)`.
//!
//! Proof: `(λ_i − λ₁)(λ_i − μ) ≥ 0` for every i (zero for i = 1, both factors ≥ 0 for i ≥ 2),
//! so `xᵀ(A − λ₁I)(A − μI)x ≥ 0`. With `t = θ − λ₁`, `A − λ₁I = (A − θI) + tI` and
//! `A − μI = (A − θI) − δI`, this reads `ρ² + (t − δ)g − tδ‖x‖² ≥ 0`, i.e.
//! `t(δ‖x‖² − g) ≤ ρ² − δg`; bound g by ±|g|. With θ the Rayleigh quotient (g ≈ 0) the loss
//! is `ρ²/(δ‖x‖²)`: squared in the residual, where a Cholesky test's loss is its backward
//! error, first order. x is the inverse iterate `A⁻¹y` of the bottom Ritz vector y (one
//! solve damps the stiff components of its error by λ₁/λ_i).
//!
//! **Lemma 8 (λ₂ from an LDLᵀ inertia test).** Let `L̂D̂L̂ᵀ` be computed without pivoting
//! ([`crate::linalg::InertiaTest`]) from `B̃ = fl(A − τI)` (ordered by P) with exactly one
//! negative pivot. Each entry of `L̂D̂L̂ᵀ − PB̃Pᵀ` is bounded by `γ_{N+4}(|L̂||D̂||L̂ᵀ|)_pq` for
//! its N ≤ min(r_p, r_q) products (the analysis of LU without pivoting, Higham, *Accuracy and
//! Stability*, Thm 9.3, with `w_j = (L̂D̂)_kj` and `L̂_kj = fl(w_j·fl(1/d_j))`: two more
//! roundings per term), ≤ `g_p g_q(|L̂||D̂||L̂ᵀ|)_pq` with `g_i = √γ_{r_i+4}` as in Lemma 7a,
//! and the diagonal's `|b̃_ii − (a_ii − τ)| ≤ u|b̃_ii|`. So `L̂D̂L̂ᵀ = P(A − τI + F)Pᵀ` with
//! `|xᵀFx| ≤ m'‖Ŝx‖²`, m' the largest entry of
//! `Ŝ⁻¹G|L̂||D̂||L̂ᵀ|GŜ⁻¹𝟙 + max_i u|b̃_ii|/ŝ_i²` (Collatz–Wielandt; `ŝ_i = fl(√a_ii)`, permuted)
//! ([`ldlt_margin`]). By Sylvester's law of inertia `A − τI + F` has exactly one negative
//! eigenvalue: on a subspace V of codimension 1, `xᵀAx ≥ τ‖x‖² − m'‖Ŝx‖²`, and by
//! Courant–Fischer `λ₂ ≥ τ − m'·max_i ŝ_i²`, or, with `h ≤ λ_min(Ŝ⁻¹AŜ⁻¹)` (certify,
//! Lemma 5) and `‖Ŝx‖² ≤ xᵀAx/h`, `λ₂ ≥ τ/(1 + m'/h)` ([`lambda2_lower`]). The margin enters
//! Theorem 9 only through δ, so a coarse bound costs little.
//!
//! **Lemma 10 (λ₂ by interlacing, for factors without an LDLᵀ).** A Cholesky test of A with
//! one DOF pinned bounds λ₂ from below (Cauchy's interlacing; [`interlaced_lower`]): the
//! supernodal factors of 10⁵–10⁶ unknowns get Temple's bound too.
//!
//! ρ², g and ‖x‖² are evaluated by compensated sums (Dot2, as Lemma 6) with their rounding
//! bounded, every final operation rounded outwards.

use super::certify::{dot_interval, gamma, residual_dot2, up, U};
use super::residual::perron_bound;
use crate::dd::{two_prod, two_sum};
use crate::linalg::{symmetric_matvec, DiagonalPattern, InertiaTest};
use faer::sparse::SymbolicSparseColMatRef;

fn down(x: f64) -> f64 {
    x * (1.0 - 8.0 * U)
}

/// Lemma 8's margin m' of an LDLᵀ test of `fl(A − τI)`: `|xᵀFx| ≤ m'‖Ŝx‖²` for
/// `F = Pᵀ L̂D̂L̂ᵀ P − (A − τI)`. `s_hat`: `fl(√a_ii)` (original order); `stored_diagonal`: the
/// test matrix's `b̃_ii` as stored. None where an `ŝ_i ≤ 0` or the bound is not finite.
pub fn ldlt_margin(test: &InertiaTest, s_hat: &[f64], stored_diagonal: &[f64]) -> Option<f64> {
    let mut diag_term = 0.0f64;
    for (&s, &b) in s_hat.iter().zip(stored_diagonal) {
        if !(s > 0.0 && s.is_finite() && b.is_finite()) {
            return None;
        }
        diag_term = diag_term.max(U * b.abs() / s / s);
    }
    let weight = |p: usize| Some(s_hat[test.fwd.map_or(p, |f| f[p])]);
    let rho = perron_bound(test.col_ptr, test.row_idx, &test.values, 4, weight, true)?;
    let m = up(rho + up(diag_term * (1.0 + 4.0 * U)));
    m.is_finite().then_some(m)
}

/// Lemma 8: `λ₂ ≥ μ` after an LDLᵀ test of `fl(A − τI)` with exactly one negative pivot and
/// margin `m` ([`ldlt_margin`]): the better of `τ − m·max_i ŝ_i²` and, with h a proven lower
/// bound of λ_min(Ŝ⁻¹AŜ⁻¹), `τ/(1 + m/h)`.
pub fn lambda2_lower(tau: f64, m: f64, max_s2: f64, h: Option<f64>) -> f64 {
    let normwise = down(tau - up(m * max_s2));
    let graded = h
        .filter(|&h| h > 0.0 && tau > 0.0)
        .map_or(f64::NEG_INFINITY, |h| down(tau / up(1.0 + up(m / h))));
    normwise.max(graded)
}

/// Theorem 9: a rigorous lower bound of λ₁(A) from a vector x and a proven `μ ≤ λ₂`
/// (A: `values` on `pattern`, CSC, both triangles). θ is x's Rayleigh quotient, corrected once
/// by the compensated g. None where the hypotheses do not hold as computed (`μ ≤ θ`, or
/// `δ‖x‖² ≤ |g|`).
pub fn temple_lower(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    x: &[f64],
    mu: f64,
) -> Option<f64> {
    let n = x.len();
    let mut ax = vec![0.0; n];
    symmetric_matvec(pattern, values, x, &mut ax);
    let xx: f64 = x.iter().map(|v| v * v).sum();
    let mut theta = x.iter().zip(&ax).map(|(a, b)| a * b).sum::<f64>() / xx;
    let (g, mut g_abs, mut rho) = temple_pass(pattern, values, x, theta);
    // g ≈ −xᵀ(A − θ)x: the Rayleigh quotient is θ − g/‖x‖². θ's offset from it costs the
    // bound |g|/‖x‖² (first order): where the f64 quotient is off by more than a few units,
    // one more pass from the corrected θ.
    if g.abs() > 4.0 * U * theta.abs() * xx {
        theta -= g / xx;
        (_, g_abs, rho) = temple_pass(pattern, values, x, theta);
    }
    let (xx_lo, _) = dot_interval(x, x);
    let delta = down(mu - theta);
    let den = down(down(delta * xx_lo) - g_abs);
    if !(delta > 0.0 && den > 0.0 && rho.is_finite()) {
        return None;
    }
    let t = up(up(up(rho * rho) + up(delta * g_abs)) / den);
    Some(down(theta - t))
}

crate::dd::fma_dispatch! {
    /// One pass of [`temple_lower`] at θ: the compensated `g ≈ −xᵀ(A − θI)x`, a bound of |g| and
    /// of `ρ = ‖(A − θI)x‖`.
    fn temple_pass(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        values: &[f64],
        x: &[f64],
        theta: f64,
    ) -> (f64, f64, f64) => temple_kernel
}

#[inline(always)]
fn temple_kernel(
    pattern: SymbolicSparseColMatRef<'_, usize>,
    values: &[f64],
    x: &[f64],
    theta: f64,
) -> (f64, f64, f64) {
    let n = x.len();
    // r = θx − Ax (the residual, negated), then xᵀr = −g by Dot2 with the error of r̂.
    let r = residual_dot2(pattern, values, x, theta, x);
    let (mut gp, mut gs, mut gabs, mut rerr) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut rr, mut ee) = (0.0f64, 0.0f64);
    for (&xj, &(rj, ej)) in x.iter().zip(&r) {
        let (h, e) = two_prod(xj, rj);
        let (t, q) = two_sum(gp, h);
        gp = t;
        gs += q + e;
        gabs += (xj * rj).abs();
        rerr += xj.abs() * ej;
        rr += rj * rj;
        ee += ej * ej;
    }
    let g = gp + gs;
    let g_abs = up(g.abs() + up(U * g.abs()) + up(gamma(n).powi(2) * gabs) + up(rerr));
    // ρ = ‖r‖ ≤ ‖r̂‖ + ‖r − r̂‖.
    let rho = up(up(rr.sqrt()) + up(ee.sqrt())) * (1.0 + gamma(n + 2));
    (g, g_abs, rho)
}

/// The first inertia test's shift is `τ = θ(1 + f)` above the estimate θ of λ₁, halfway to
/// the estimate of λ₂ where there is one (at most f = [`FIRST_SHIFT`]), else at f =
/// [`FIRST_SHIFT`]; a test that finds k ≥ 2 eigenvalues below τ is followed by one at `f/(2k)`
/// (halfway to the second of k eigenvalues spread evenly over (θ, τ)), at most [`MAX_TESTS`]
/// tests, f no smaller than [`MIN_SHIFT`] (λ₂ closer than that to λ₁ leaves Temple's bound
/// little room: the Cholesky tests follow).
pub const FIRST_SHIFT: f64 = 1.0;
/// See [`FIRST_SHIFT`].
pub const MIN_SHIFT: f64 = 0.01;
/// See [`FIRST_SHIFT`].
pub const MAX_TESTS: usize = 4;

/// λ₁ of the SPD A (`pattern` with its values) from below by Theorem 9 with `x ≈` its
/// eigenvector, `theta ≈ λ₁` and `lambda2 ≈ λ₂`: LDLᵀ inertia tests of `fl(A − τI)` ([`FIRST_SHIFT`]) until
/// one finds exactly one negative pivot (Lemma 8: `μ ≤ λ₂`), then Temple's bound; on a
/// supernodal factor (no LDLᵀ) the gap comes from Lemma 10 ([`interlaced_lower`]). `h`: a
/// proven lower bound of λ_min(Ŝ⁻¹AŜ⁻¹) where there is one. Returns the bound (None where no
/// test found one negative pivot or the hypotheses failed) and the factorizations made.
pub(crate) fn lambda_min_lower(
    pattern: &DiagonalPattern,
    x: &[f64],
    theta: f64,
    lambda2: Option<f64>,
    s_hat: &[f64],
    h: Option<f64>,
) -> (Option<f64>, usize) {
    if !pattern.has_ldlt() {
        return interlaced_lower(pattern, x, theta, h);
    }
    let max_s2 = up(s_hat.iter().fold(0.0f64, |m, s| m.max(s * s)));
    let mut buf = Vec::with_capacity(pattern.values.len());
    let mut tests = 0;
    let mut f = lambda2
        .map(|l2| 0.5 * (l2 / theta - 1.0))
        .filter(|&f| f >= MIN_SHIFT)
        .map_or(FIRST_SHIFT, |f| f.min(FIRST_SHIFT));
    while tests < MAX_TESTS && f >= MIN_SHIFT {
        let tau = theta * (1.0 + f);
        pattern.fill_shifted(&mut buf, 1.0, -tau, 0.0, None);
        tests += 1;
        let Some(test) = pattern.ldlt(&buf) else {
            f *= 0.5;
            continue;
        };
        match test.negative {
            0 => break,
            1 => {
                let stored: Vec<f64> = pattern.diag.iter().map(|&p| buf[p]).collect();
                let lower = ldlt_margin(&test, s_hat, &stored)
                    .map(|m| lambda2_lower(tau, m, max_s2, h))
                    .and_then(|mu| temple_lower(pattern.pat(), &pattern.values, x, mu));
                return (lower.filter(|&l| l > 0.0), tests);
            }
            k => f /= 2.0 * k as f64,
        }
    }
    (None, tests)
}

/// Shifts `τ = θ(1 + f)` of the interlacing test ([`interlaced_lower`]), smallest first: the
/// pinned DOF's lowest eigenvalue lies above λ₁ by a fraction of the gap to λ₂ (≈ 1/ln N on a
/// 2-D membrane), and Temple's loss `ρ²/(δ‖x‖²)` barely needs more than f = 1e-2.
pub const INTERLACED_SHIFTS: [f64; 2] = [1e-2, 1e-3];

/// λ₁ from below by Theorem 9 with its gap from **Lemma 10 (λ₂ by interlacing)**, for factors
/// without an LDLᵀ (supernodal): let `A'` be A without row and column i. By Cauchy's
/// interlacing theorem `λ₁(A') ≤ λ₂(A)`. `A_i`, A with row and column i replaced by
/// `a_ii e_i` (off-diagonal entries 0, the same pattern and symbolic analysis), has the
/// spectrum of A' and a_ii, so a Cholesky test of `fl(A_i − τI)` that succeeds proves
/// `λ₂(A) ≥ λ₁(A') ≥ λ_min(A_i) ≥ μ` by certify's Corollary 3 or Theorem 4
/// (`Margin::lower_from_test`; `Ŝ⁻¹A_iŜ⁻¹ = Ŝ'⁻¹A'Ŝ'⁻¹ ⊕ [1]`, whose λ_min is ≥ h by
/// interlacing and h ≤ 1). i is the DOF where x is largest (pinning it lifts the lowest mode
/// most). Returns the bound and the factorizations made.
pub fn interlaced_lower(
    pattern: &DiagonalPattern,
    x: &[f64],
    theta: f64,
    h: Option<f64>,
) -> (Option<f64>, usize) {
    use super::certify::Margin;
    let n = pattern.n();
    if n < 2 || x.len() != n {
        return (None, 0);
    }
    let i = (0..n).fold(0, |b, k| if x[k].abs() > x[b].abs() { k } else { b });
    let margin = Margin::of(&pattern.symbolic);
    let mut buf = Vec::with_capacity(pattern.values.len());
    let mut tests = 0;
    for f in INTERLACED_SHIFTS {
        let tau = theta * (1.0 + f);
        pattern.fill_shifted(&mut buf, 1.0, -tau, 0.0, None);
        pattern.pin(&mut buf, i);
        let max_b = pattern
            .diag
            .iter()
            .map(|&p| buf[p])
            .fold(f64::NEG_INFINITY, f64::max);
        tests += 1;
        if pattern.factor(&buf).is_none() {
            continue;
        }
        let mu = margin.lower_from_test(tau, max_b, h);
        let lower = temple_lower(pattern.pat(), &pattern.values, x, mu);
        return (lower.filter(|&l| l > 0.0), tests);
    }
    (None, tests)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::conditioning::certify::tests::second_difference;
    use crate::linalg::DiagonalPattern;

    /// On the second difference (closed-form eigenvalues) the inertia test between λ₁ and λ₂
    /// gives μ ≤ λ₂, and Temple's bound from a perturbed eigenvector lies below λ₁ and within
    /// the square of the perturbation of it; a shift above λ₂ gives two negative pivots.
    #[test]
    fn temple_bound_is_below_lambda_min_and_second_order() {
        let n = 200;
        let a = second_difference(n);
        let pattern = DiagonalPattern::new(&a).unwrap();
        let th = std::f64::consts::PI / (n as f64 + 1.0);
        // 4 sin²(jπ/(2(n+1))) = 2 − 2cos(jπ/(n+1)), without the cancellation.
        let lambda = |j: usize| 4.0 * (0.5 * j as f64 * th).sin().powi(2);
        let s_hat: Vec<f64> = vec![2f64.sqrt(); n];
        let tau = 0.5 * (lambda(1) + lambda(2));
        let mut v = pattern.values.clone();
        for &p in pattern.diag.iter() {
            v[p] -= tau;
        }
        let stored: Vec<f64> = pattern.diag.iter().map(|&p| v[p]).collect();
        let test = pattern.ldlt(&v).unwrap();
        assert_eq!(test.negative, 1);
        let m = ldlt_margin(&test, &s_hat, &stored).unwrap();
        let mu = lambda2_lower(tau, m, 2.0, None);
        assert!(mu <= lambda(2) && mu > lambda(1), "μ {mu}");
        for eta in [1e-4, 1e-6, 0.0] {
            // x = v₁ + η v₂ (rounded): Temple's loss ≈ η² (λ₂ − λ₁)² / (μ − λ₁).
            let x: Vec<f64> = (1..=n)
                .map(|i| (i as f64 * th).sin() + eta * (2.0 * i as f64 * th).sin())
                .collect();
            let lo = temple_lower(a.symbolic(), a.val(), &x, mu).unwrap();
            let l1 = lambda(1);
            // The closed form carries a few ulps of its own rounding.
            assert!(
                lo <= l1 * (1.0 + 4.0 * f64::EPSILON),
                "η {eta}: {lo} > {l1}"
            );
            let loss = eta * eta * (lambda(2) - l1).powi(2) / (mu - l1);
            assert!(
                l1 - lo <= 4.0 * loss + 64.0 * f64::EPSILON * l1,
                "η {eta}: λ₁ {l1}, bound {lo}"
            );
        }
        let mut v = pattern.values.clone();
        for &p in pattern.diag.iter() {
            v[p] -= 0.5 * (lambda(2) + lambda(3));
        }
        assert_eq!(pattern.ldlt(&v).unwrap().negative, 2);
    }

    /// Lemma 8 and Theorem 9 against independent references: Lemma 8's margin contains the
    /// true scaled row sum of `L̂D̂L̂ᵀ − P(A − τI)Pᵀ` (formed densely in double-double from the
    /// factor's entries), μ ≤ λ₂, and Temple's bound from nalgebra's eigenvector lies below
    /// nalgebra's λ₁ (both within their rounding, `8nε‖A‖`) and within the target width of it
    /// — on an AMD-permuted graded grid (stiff entries 1e6) and a second difference.
    #[test]
    fn lemma_8_margin_contains_the_true_residual() {
        use crate::conditioning::residual::tests::graded_grid;
        use crate::dd::Dd;
        for a in [graded_grid(12), second_difference(60)] {
            let n = a.nrows();
            let pattern = DiagonalPattern::new(&a).unwrap();
            let dense = nalgebra::DMatrix::from_fn(n, n, |i, j| {
                a.val_of_col(j)
                    .iter()
                    .zip(a.symbolic().row_idx_of_col(j))
                    .find(|(_, r)| *r == i)
                    .map_or(0.0, |(v, _)| *v)
            });
            let norm = dense.row_iter().map(|r| r.abs().sum()).fold(0.0, f64::max);
            let eig = nalgebra::SymmetricEigen::new(dense.clone());
            let mut order: Vec<usize> = (0..n).collect();
            order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
            let (l1, l2) = (eig.eigenvalues[order[0]], eig.eigenvalues[order[1]]);
            let slack = 8.0 * n as f64 * f64::EPSILON * norm;
            let tau = 0.5 * (l1 + l2);
            let mut v = pattern.values.clone();
            for &p in pattern.diag.iter() {
                v[p] -= tau;
            }
            let stored: Vec<f64> = pattern.diag.iter().map(|&p| v[p]).collect();
            let test = pattern.ldlt(&v).expect("simplicial");
            assert_eq!(test.negative, 1, "n {n}");
            let s_hat: Vec<f64> = (0..n).map(|i| dense[(i, i)].sqrt()).collect();
            let m = ldlt_margin(&test, &s_hat, &stored).unwrap();
            // The true residual, densely: F_pq = Σ_k l_pk d_k l_qk − b_pq (l unit diagonal).
            let f = &test;
            let fwd: Vec<usize> = f.fwd.map_or_else(|| (0..n).collect(), |p| p.to_vec());
            let mut l = vec![vec![0.0f64; n]; n];
            let mut d = vec![0.0f64; n];
            for k in 0..n {
                d[k] = f.values[f.col_ptr[k]];
                l[k][k] = 1.0;
                for p in f.col_ptr[k] + 1..f.col_ptr[k + 1] {
                    l[f.row_idx[p]][k] = f.values[p];
                }
            }
            let mut truth = 0.0f64;
            for p in 0..n {
                let mut sum = 0.0;
                for q in 0..n {
                    let (i, j) = (fwd[p], fwd[q]);
                    let b =
                        Dd::from_f64(dense[(i, j)]) - Dd::from_f64(if i == j { tau } else { 0.0 });
                    let mut e = Dd::ZERO - b;
                    for k in 0..n {
                        if l[p][k] != 0.0 && l[q][k] != 0.0 {
                            e = e + Dd::prod(l[p][k], d[k]) * Dd::from_f64(l[q][k]);
                        }
                    }
                    sum += e.to_f64().abs() / (s_hat[i] * s_hat[j]);
                }
                truth = truth.max(sum);
            }
            assert!(
                truth <= m,
                "n {n}: true {:.1} u > margin {:.1} u",
                truth / U,
                m / U
            );
            let max_s2 = s_hat.iter().fold(0.0f64, |x, s| x.max(s * s));
            let mu = lambda2_lower(tau, m, max_s2, None);
            assert!(
                mu <= l2 + slack && mu > l1,
                "n {n}: μ {mu}, λ₁ {l1}, λ₂ {l2}"
            );
            let x: Vec<f64> = eig.eigenvectors.column(order[0]).iter().copied().collect();
            let lo = temple_lower(a.symbolic(), a.val(), &x, mu).unwrap();
            assert!(lo <= l1 + slack, "n {n}: {lo} > λ₁ {l1}");
            assert!(l1 - lo <= 1e-12 * l1 + slack, "n {n}: {lo} vs λ₁ {l1}");
        }
    }

    /// Lemma 10 on the second difference: pinning the DOF where the lowest mode is largest
    /// lifts it far enough for the first shift, and Temple's bound from the perturbed
    /// eigenvector lies below λ₁ and within the square of the perturbation of it.
    #[test]
    fn interlacing_gap_gives_a_second_order_bound() {
        let n = 200;
        let a = second_difference(n);
        let pattern = DiagonalPattern::new(&a).unwrap();
        let th = std::f64::consts::PI / (n as f64 + 1.0);
        let lambda = |j: usize| 4.0 * (0.5 * j as f64 * th).sin().powi(2);
        for eta in [1e-4, 1e-6] {
            let x: Vec<f64> = (1..=n)
                .map(|i| (i as f64 * th).sin() + eta * (2.0 * i as f64 * th).sin())
                .collect();
            let (lo, tests) = interlaced_lower(&pattern, &x, lambda(1), None);
            let lo = lo.expect("a bound");
            assert_eq!(tests, 1);
            assert!(lo <= lambda(1), "η {eta}: {lo} > λ₁ {}", lambda(1));
            // Loss ≈ η²(λ₂ − λ₁)²/(μ − λ₁) with μ − λ₁ ≈ 1e-2·λ₁.
            let loss = eta * eta * (lambda(2) - lambda(1)).powi(2) / (1e-2 * lambda(1));
            assert!(
                lambda(1) - lo <= 4.0 * loss + 1e-12 * lambda(1),
                "η {eta}: {lo}"
            );
        }
    }
}
