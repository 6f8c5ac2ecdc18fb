//! The shifted matrices of the saddle-point route ([`super`]): `H = αK + σI + β1_B` on K's
//! pattern, their Cholesky tests (plain and verified) and LDLᵀ inertia tests with their
//! backward error bounded.

use super::coupling::Blocks;
use crate::conditioning::certify::{self, Margin};
use crate::conditioning::residual::perron_bound;
use crate::linalg::{DiagonalPattern, SparseLlt};

/// `α·K + σ·I + β·DDᵀ` (`β·1_B` for a Boolean D) on the pattern of `K + DDᵀ`, factorized
/// with one symbolic analysis.
pub(super) struct Shifts<'a> {
    pub(super) pattern: &'a DiagonalPattern,
    pub(super) blocks: &'a Blocks<'a>,
    pub(super) factorizations: usize,
    /// Value buffer reused by every factorization.
    pub(super) work: Vec<f64>,
}

impl Shifts<'_> {
    pub(super) fn factor(&mut self, alpha: f64, sigma: f64, beta: f64) -> Option<SparseLlt> {
        self.blocks
            .fill(self.pattern, &mut self.work, alpha, sigma, beta);
        self.factorizations += 1;
        self.pattern.factor(&self.work)
    }
    pub(super) fn is_pd(&mut self, alpha: f64, sigma: f64, beta: f64) -> bool {
        self.factor(alpha, sigma, beta).is_some()
    }

    /// A proof that `T = αK + σI + β1_B ≻ 0` (β = ±1/s as passed, its own rounding
    /// included): Cholesky of the matrix shifted further down by
    /// `c = m·max_i b_ii + 6u·max_i(|αk_ii| + |σ| + |β|)` succeeds. By [`certify`]'s Lemma 1
    /// the stored shifted matrix B̃ has `xᵀB̃x ≥ −m·max_i b̃_ii`, and T differs from `B̃ + cI`
    /// by the diagonal roundings of its formation (≤ 6u·max_i(…) with the rounding of β
    /// against the exact ±1/s), so `xᵀTx ≥ c − m·max b − 6u·max(…) > 0`.
    pub(super) fn verified_pd(
        &mut self,
        alpha: f64,
        sigma: f64,
        beta: f64,
        margin: Margin,
    ) -> bool {
        let (mut max_b, mut max_e) = (f64::NEG_INFINITY, 0.0f64);
        if self.blocks.is_selection() {
            let in_b = &self.blocks.in_b;
            for (j, &p) in self.pattern.diag.iter().enumerate() {
                let k = alpha * self.pattern.values[p];
                let b = if in_b[j] { beta } else { 0.0 };
                max_b = max_b.max(k + sigma + b);
                max_e = max_e.max(k.abs() + sigma.abs() + b.abs());
            }
        } else {
            // Coupled rows: the formed matrix's own diagonal (rounded up) and its formation
            // bound (`Blocks::fill`, which covers every entry's rounding in 2-norm).
            max_e = self
                .blocks
                .fill(self.pattern, &mut self.work, alpha, sigma, beta);
            for &p in self.pattern.diag.iter() {
                max_b = max_b.max(certify::up(self.work[p]));
            }
        }
        if max_b.is_nan() || max_b <= 0.0 {
            return false;
        }
        let u = certify::U;
        let c = (margin.m * max_b + 6.0 * u * max_e) * (1.0 + 16.0 * u);
        self.is_pd(alpha, sigma - c, beta)
    }

    /// A posteriori [`Shifts::verified_pd`]: Cholesky of `T̃ = fl(αK + σI + β1_B)` itself;
    /// where it succeeds, its factor and `c` with `T ⪰ −c·I` for the exact T:
    /// `xᵀT̃x ≥ −m Σ_i t̃_ii x_i²` with m the smaller of Lemma 1's and the factor's own
    /// (`certify::factor_margin`, Lemma 7a; where `m·max_i t̃_ii` exceeds `need`, also
    /// Lemma 7's residual margin), plus the diagonal's formation
    /// (≤ 6u·max_i(|αk_ii| + |σ| + |β|)). So `T + cI ⪰ 0`: for `T = ∓H(±s)` that moves the
    /// tested end of A's spectrum by at most c (`proven`). A supernodal factor's Lemma 7a is
    /// read in place, without Lemma 7. None where the Cholesky fails.
    pub(super) fn tested_factor(
        &mut self,
        alpha: f64,
        sigma: f64,
        beta: f64,
        margin: Margin,
        need: f64,
    ) -> Option<(f64, SparseLlt)> {
        let max_e = self
            .blocks
            .fill(self.pattern, &mut self.work, alpha, sigma, beta);
        self.factorizations += 1;
        let f = self.pattern.factor(&self.work)?;
        // Lemma 7's residual only where it needs no copy of a supernodal factor.
        let c = self.margin_of_factor(&f, margin, max_e, need, !f.is_supernodal())?;
        Some((c, f))
    }

    /// σ_max < the returned bound once both ends' tests at s pass ([`Shifts::tested_factor`]
    /// with each margin wanted below 2.5e-13·s, a quarter of the contract's floor):
    /// `−H(s) + c₁I ⪰ 0` gives `−H(s + c₁) ⪰ 0` (its B entries `−1/(s + c₁) ≥ −1/s`), so
    /// λ_max ≤ s + c₁, and `H(−s) + c₂I ⪰ 0` likewise λ_min ≥ −(s + c₂). Also returns the
    /// factor of `−H(s)` (for `SaddleRun::refine_top`).
    pub(super) fn sigma_max_test(&mut self, s: f64, margin: Margin) -> Option<(f64, SparseLlt)> {
        let need = 2.5e-13 * s;
        let (c1, f) = self.tested_factor(-1.0, s, -1.0 / s, margin, need)?;
        let c2 = self.tested_factor(1.0, s, -1.0 / s, margin, need)?.0;
        Some((certify::up(s + c1.max(c2)), f))
    }

    /// The positive side's gap for Temple's bound without an LDLᵀ (supernodal factors), by
    /// Cauchy's interlacing: with the free DOF `pin` (not in B) removed from K, A' has
    /// `#{λ(A) < μ} ≤ #{λ(A') < μ} + 1`, and `#{λ(A') < μ} = m` once `H'(μ) ⪰ 0`. `H(τ)` with
    /// row and column `pin` reduced to its diagonal has the spectrum of `H'(τ)` and
    /// `k_pp − τ`; where its Cholesky succeeds, [`Shifts::tested_factor`]'s c gives
    /// `H'(τ) + cI ⪰ 0`, hence `H'(μ) ⪰ 0` for `μ = τ − c` (its B entries `1/μ ≥ 1/τ`): at
    /// most one eigenvalue of A in (0, μ). The margin is Lemma 7a's, read in place (Lemma 1's
    /// would be first order in the 1/τ of B's diagonal). None where the test fails.
    pub(super) fn pinned_gap(&mut self, tau: f64, pin: usize, margin: Margin) -> Option<f64> {
        let max_e = self
            .blocks
            .fill(self.pattern, &mut self.work, 1.0, -tau, 1.0 / tau);
        self.pattern.pin(&mut self.work, pin);
        self.factorizations += 1;
        let f = self.pattern.factor(&self.work)?;
        let c = self.margin_of_factor(&f, margin, max_e, f64::INFINITY, false)?;
        let mu = (tau - c) * (1.0 - 8.0 * certify::U);
        (mu > 0.0 && mu.is_finite()).then_some(mu)
    }

    /// `c` with `T ⪰ −c·I` for the exact test matrix T of a Cholesky `f` that succeeded on the
    /// stored `T̃` in `work` (`max_e` from its formation): `m·max_i t̃_ii` with m the smaller
    /// of Lemma 1's and Lemma 7a's (and, with `posterior`, where `m·max_i t̃_ii` exceeds `need`,
    /// Lemma 7's on `T̃` itself: α = 1, σ = 0), plus the diagonal's formation.
    fn margin_of_factor(
        &self,
        f: &SparseLlt,
        margin: Margin,
        max_e: f64,
        need: f64,
        posterior: bool,
    ) -> Option<f64> {
        let stored: Vec<f64> = self.pattern.diag.iter().map(|&p| self.work[p]).collect();
        let max_b = stored.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !(max_b > 0.0 && max_b.is_finite()) {
            return None;
        }
        let residual = posterior.then(|| (self.pattern.pat(), self.work.as_slice(), 1.0, 0.0));
        let m =
            crate::conditioning::residual::own_margin(f, &stored, margin.m, need / max_b, residual);
        let c = (m * max_b + 6.0 * certify::U * max_e) * (1.0 + 16.0 * certify::U);
        c.is_finite().then_some(c)
    }

    /// An LDLᵀ inertia test of `T = K + σI + β1_B` (`temple`'s Lemma 8, normwise): the
    /// number of negative pivots of the LDLᵀ of `fl(T)` and η with `L̂D̂L̂ᵀ = T + F`,
    /// `‖F‖₂ ≤ η` (the Collatz–Wielandt bound of `γ|L̂||D̂||L̂ᵀ|`, `residual::perron_bound`,
    /// plus the diagonal's formation, ≤ 4u(|k_ii| + |σ| + |β|)). By Sylvester `T + F` has
    /// exactly that many negative eigenvalues, so `T + ηI ⪰ T + F` has at most as many. None
    /// where the factor has no LDLᵀ (supernodal) or a zero pivot.
    pub(super) fn ldlt_inertia(&mut self, sigma: f64, beta: f64) -> Option<(usize, f64)> {
        let max_e = self
            .blocks
            .fill(self.pattern, &mut self.work, 1.0, sigma, beta);
        self.factorizations += 1;
        let test = self.pattern.ldlt(&self.work)?;
        let rho = perron_bound(
            test.col_ptr,
            test.row_idx,
            &test.values,
            4,
            |_| Some(1.0),
            true,
        )?;
        let eta = certify::up(rho + certify::up(4.0 * certify::U * max_e));
        eta.is_finite().then_some((test.negative, eta))
    }

    /// The fourth end by inertia: where the LDLᵀ test of `H(−t) = K + tI − t⁻¹1_B`
    /// ([`Shifts::ldlt_inertia`]) has exactly m negative pivots, A has no eigenvalue in
    /// `[−t', 0)` for the returned `t' = t − η` (None where it has not, or t' ≤ 0). Proof:
    /// `H(−t) + ηI` has at least m negative eigenvalues, and so has
    /// `H(−t') ⪯ H(−t) − ηI` (their difference is `−(1/t' − 1/t)1_B ⪯ 0`): `#{λ < −t'} ≥ m`.
    /// With `#{λ < s} ≤ m` proven for an `s > 0` (`H(s) ≻ 0` verified, or Temple's bound of
    /// λ⁺_min, [`SaddleRun::positive_min_lower`]), no eigenvalue lies in `[−t', s)`.
    pub(super) fn no_eigenvalue_above(&mut self, t: f64, m: usize) -> Option<f64> {
        let (negative, eta) = self.ldlt_inertia(t, -1.0 / t)?;
        if m == 0 || negative != m {
            return None;
        }
        let t2 = (t - eta) * (1.0 - 8.0 * certify::U);
        (t2 > 0.0 && t2.is_finite()).then_some(t2)
    }

    /// A gap for Temple's bound on one side of 0 (`sign` > 0: the positive eigenvalues, < 0:
    /// the negative ones, as eigenvalues of −A): `μ = τ − η` where the LDLᵀ test
    /// ([`Shifts::ldlt_inertia`]) finds exactly one eigenvalue of `sign·A` in (0, τ), i.e.
    /// `H(τ) = K − τI + τ⁻¹1_B` has one negative pivot (sign > 0), or `H(−τ) = K + τI − τ⁻¹1_B`
    /// has m − 1 (sign < 0). Then at most one eigenvalue of `sign·A` lies in (0, μ): for
    /// sign > 0, `H(μ) ⪰ H(τ) + ηI` (their difference is `(1/μ − 1/τ)1_B ⪰ 0`) has at most one
    /// negative eigenvalue, so `#{λ < μ} = m + #neg H(μ) ≤ m + 1`; for sign < 0,
    /// `H(−μ) ⪯ H(−τ) − ηI` has at least m − 1, so `#{λ < −μ} ≥ m − 1`
    /// ([`Shifts::no_eigenvalue_above`]'s argument). `Err(k)`: the test found k ≠ 1
    /// eigenvalues of `sign·A` in (0, τ); `Err(usize::MAX)`: no test (no LDLᵀ, or μ ≤ 0).
    pub(super) fn side_gap(
        &mut self,
        sign: f64,
        tau: f64,
        m: usize,
    ) -> std::result::Result<f64, usize> {
        let (sigma, beta) = if sign > 0.0 {
            (-tau, 1.0 / tau)
        } else {
            (tau, -1.0 / tau)
        };
        let (negative, eta) = self.ldlt_inertia(sigma, beta).ok_or(usize::MAX)?;
        let inside = if sign > 0.0 {
            negative
        } else {
            m.saturating_sub(negative)
        };
        if inside != 1 {
            return Err(inside);
        }
        let mu = (tau - eta) * (1.0 - 8.0 * certify::U);
        if mu > 0.0 && mu.is_finite() {
            Ok(mu)
        } else {
            Err(usize::MAX)
        }
    }
}
