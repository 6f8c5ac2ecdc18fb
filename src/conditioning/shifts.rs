//! The shifted test matrices `αA + σI` of the SPD certificate ([`super::sparse`]): one
//! symbolic analysis for every shift, the Cholesky tests and the margins that judge them
//! ([`super::certify`], Lemmas 1, 5, 7 and 7a).

use super::certify::POSTERIOR_MAX_PRODUCTS;
use super::certify::{self, Margin};
use super::lanczos::{lanczos, Keep};
use crate::error::Result;
use crate::linalg::{DiagonalPattern, SparseLlt};
use faer::sparse::SparseColMat;

/// `αA + σI` for many shifts σ, sharing one symbolic Cholesky analysis.
pub(super) struct ShiftFamily {
    pub(super) pattern: DiagonalPattern,
    /// Whether Lemma 7's residual is affordable ([`POSTERIOR_MAX_PRODUCTS`]).
    pub(super) posterior_ok: bool,
    pub(super) factorizations: usize,
    /// Value buffer reused by every factorization.
    work: Vec<f64>,
}

/// Cholesky of `alpha·A + sigma·I` on A's pattern (None if not positive definite), the
/// shifted values written into `work` (kept there for a margin, [`ShiftFamily::margin_of`]).
pub(super) fn shifted_factor(
    pattern: &DiagonalPattern,
    work: &mut Vec<f64>,
    alpha: f64,
    sigma: f64,
) -> Option<SparseLlt> {
    pattern.fill_shifted(work, alpha, sigma, 0.0, None);
    pattern.factor(work)
}

impl ShiftFamily {
    pub(super) fn new(a: &SparseColMat<usize, f64>) -> Result<Self> {
        let pattern = DiagonalPattern::new(a)?;
        Ok(ShiftFamily {
            posterior_ok: certify::factor_products(&pattern.symbolic) <= POSTERIOR_MAX_PRODUCTS,
            pattern,
            factorizations: 0,
            work: Vec::new(),
        })
    }

    /// Cholesky of `alpha·A + sigma·I` (None if not positive definite).
    pub(super) fn factor(&mut self, alpha: f64, sigma: f64) -> Option<SparseLlt> {
        self.factorizations += 1;
        shifted_factor(&self.pattern, &mut self.work, alpha, sigma)
    }

    /// A Cholesky test of `fl(alpha·A + sigma·I)` (alpha = ±1): on success its factor and the
    /// largest diagonal entry of the test matrix as stored, for [`Margin`]'s bounds.
    pub(super) fn test_factor(&mut self, alpha: f64, sigma: f64) -> Option<(SparseLlt, f64)> {
        let f = self.factor(alpha, sigma)?;
        Some((f, self.max_stored_diagonal()))
    }

    /// The margin of a successful test's factor `f` of `fl(alpha·A + sigma·I)` (the test
    /// matrix still in `work`), at most `need` where that can be had: Lemma 1's a-priori `m`,
    /// else the factor's own a-priori margin (certify, Lemma 7a: two products with |L̂|),
    /// else the residual's (Lemma 7: ≈ 5× a factorization), the smallest computed.
    pub(super) fn margin_of(
        &self,
        f: &SparseLlt,
        alpha: f64,
        sigma: f64,
        apriori: Margin,
        need: f64,
    ) -> Margin {
        if apriori.m <= need {
            return apriori;
        }
        let stored: Vec<f64> = self.pattern.diag.iter().map(|&p| self.work[p]).collect();
        let posterior = self.posterior_ok.then(|| {
            (
                self.pattern.pat(),
                self.pattern.values.as_slice(),
                alpha,
                sigma,
            )
        });
        let m = super::residual::own_margin(f, &stored, apriori.m, need, posterior);
        Margin { m }
    }

    /// The largest diagonal entry of the last test matrix as stored (`work`).
    pub(super) fn max_stored_diagonal(&self) -> f64 {
        self.pattern
            .diag
            .iter()
            .map(|&p| self.work[p])
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// A Cholesky test of `fl(H̃ − τI)`, `h̃_ij = fl(fl(a_ij/ŝ_i)/ŝ_j)` (certify, Lemma 5): on
    /// success the largest stored diagonal entry and the largest absolute row sum of H̃.
    pub(super) fn test_scaled(&mut self, s_hat: &[f64], tau: f64) -> Option<(f64, f64)> {
        let (cp, ri) = (
            self.pattern.pattern.col_ptr(),
            self.pattern.pattern.row_idx(),
        );
        let v = &mut self.work;
        v.clear();
        let mut rowsum = 0.0f64;
        for j in 0..self.pattern.n() {
            let mut sum = 0.0;
            for p in cp[j]..cp[j + 1] {
                let h = self.pattern.values[p] / s_hat[ri[p]] / s_hat[j];
                sum += h.abs();
                v.push(h);
            }
            rowsum = rowsum.max(sum);
        }
        for &p in self.pattern.diag.iter() {
            v[p] -= tau;
        }
        self.factorizations += 1;
        let ok = self.pattern.factor(v).is_some();
        let max_c = self.max_stored_diagonal();
        // The row sums were accumulated in f64 over at most n terms.
        ok.then_some((max_c, rowsum * (1.0 + certify::gamma(self.pattern.n() + 2))))
    }
}

/// Lemma 5's proven `h ≤ λ_min(Ŝ⁻¹AŜ⁻¹)` from the estimate `h_est`: Cholesky tests of
/// `fl(H̃ − τI)` at `τ = f·h_est`, f = 0.9, 0.5, 0.125, 0.02 (None where every one fails).
pub(super) fn graded_floor(
    fam: &mut ShiftFamily,
    s_hat: &[f64],
    h_est: Option<f64>,
    margin: Margin,
) -> Option<f64> {
    let h_est = h_est?;
    [0.9, 0.5, 0.125, 0.02].into_iter().find_map(|f| {
        let tau = f * h_est;
        let (max_c, rowsum) = fam.test_scaled(s_hat, tau)?;
        Some(margin.graded_floor(tau, max_c, rowsum)).filter(|&h| h > 0.0)
    })
}

/// A rough λ_min(Ĥ), `Ĥ = Ŝ⁻¹AŜ⁻¹` (wanted within a factor of 2, certified by Lemma 5): a short
/// Lanczos run on `Ĥ⁻¹ = Ŝ A⁻¹ Ŝ` from `z = Ŝy_bottom`, `solve` applying A⁻¹ in place. Returns
/// the estimate (None where the run gives none) and the steps.
pub(super) fn graded_estimate(
    s_hat: &[f64],
    z: &[f64],
    solve: impl Fn(&mut [f64]),
) -> Result<(Option<f64>, usize)> {
    let run = lanczos(
        s_hat.len(),
        GRADED_LANCZOS_STEPS,
        |_| 1e-2,
        Some(z),
        Keep::Never,
        |x, y| {
            for ((yi, xi), si) in y.iter_mut().zip(x).zip(s_hat) {
                *yi = xi * si;
            }
            solve(y);
            for (yi, si) in y.iter_mut().zip(s_hat) {
                *yi *= si;
            }
        },
    )?;
    Ok(((run.theta > 0.0).then(|| 1.0 / run.theta), run.steps))
}

/// Lanczos steps of the rough λ_min(Ŝ⁻¹AŜ⁻¹) estimate (wanted within a factor of 2).
const GRADED_LANCZOS_STEPS: usize = 16;
