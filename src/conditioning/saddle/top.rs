//! σ_max's proven bracket of the saddle-point route ([`super`]): tests just above the estimate
//! judged by their factors' own margins, refined by a shift-invert run where a cluster at the
//! top leaves the Ritz vector short.

use super::coupling::Coupling;
use super::{End, SaddleRun};
use crate::conditioning::certify::{self, Margin};
use crate::conditioning::sparse::{lanczos, Keep, MAX_LANCZOS_STEPS, STAGNATION};
use crate::linalg::{DiagonalPattern, SparseLlt};

impl SaddleRun<'_> {
    /// λ_max from below after a test `−H(s) ≻ 0` passed with factor `f`: Lanczos on
    /// `(sI − A)⁻¹` (positive definite; its top eigenvalue `1/(s − λ_max)` is separated by
    /// the gap at the top over `s − λ_max`), each product one solve with f: for
    /// `(A − sI)[x; y] = [p; g]`, `H(s)x = p + Dg/s` and `y = (Dᵀx − g)/s`. Returns the proven
    /// lower end of its Ritz vector's Rayleigh quotient (compensated, Courant–Fischer).
    fn refine_top(&mut self, f: &SparseLlt, s: f64) -> Option<f64> {
        let (blocks, n) = (self.blocks, self.blocks.in_b.len());
        let run = lanczos(
            self.size,
            MAX_LANCZOS_STEPS,
            |_| STAGNATION,
            None,
            Keep::Always,
            |v, z| {
                let (p, g) = v.split_at(n);
                let (zx, zy) = z.split_at_mut(n);
                zx.copy_from_slice(p);
                if let Coupling::Selection(dofs) = &blocks.d {
                    for (c, &d) in dofs.iter().enumerate() {
                        zx[d] += g[c] / s;
                    }
                } else {
                    blocks.add_d(&g.iter().map(|gc| gc / s).collect::<Vec<_>>(), 1.0, zx);
                }
                // f factors −H(s): x = −f⁻¹(p + Dg/s); z = −[x; y] = (sI − A)⁻¹v.
                f.solve_vec_in_place(zx);
                for (c, zc) in zy.iter_mut().enumerate() {
                    *zc = (blocks.dt(zx, c) + g[c]) / s;
                }
            },
        )
        .ok()?;
        self.lanczos_steps += run.steps;
        let y = run.vector?;
        certify::rayleigh_interval_dot2(self.a_pattern.as_ref(), &self.a_values, &y)
            .map(|(lo, _)| lo)
    }

    /// σ_max's proven bracket `(lo, hi)` ([`Self::proven`]): Cholesky tests stepping out from
    /// the estimate, refined by a shift-invert run where the bracket is wider than wanted; `hi`
    /// is infinite where no test passed.
    pub(super) fn proven_top(
        &mut self,
        pattern: &DiagonalPattern,
        top: &End,
        margin: Margin,
    ) -> (f64, f64) {
        // The tests start from the estimate or, where the inertia search ran, from its upper
        // end (a Cholesky test passed there, unverified): in a cluster at the top (the
        // 10⁶-unknown membrane's λ_max, gaps ≈ 1e-5) the Lanczos estimate stops short and
        // tests stepping out from it would cost a factorization per step.
        let smax_est = top
            .estimate
            .max(top.bracket.0)
            .max(if top.bracket.1.is_finite() {
                top.bracket.1
            } else {
                0.0
            });
        // e_iᵀAe_i = K_ii ≤ σ_max for a unit vector of the N block (K ≻ 0).
        let max_lo = top
            .top_rq
            .map_or(0.0, |(lo, _)| lo)
            .max(pattern.max_diagonal());
        let shifts = &mut self.shifts;
        // Tests just above σ_max's estimate, judged by their factors' own margins
        // (`Shifts::sigma_max_test`). The first sits a few ε above the estimate on a
        // simplicial factor, at Lemma 1's m/64 on a supernodal one (its factorizations cost
        // seconds at 10⁶ unknowns; Lemma 7a is ≈ 300× below Lemma 1 there).
        let w0 = if pattern.has_ldlt() {
            16.0 * f64::EPSILON
        } else {
            (margin.m / 64.0).max(16.0 * f64::EPSILON)
        };
        let top_test = certify::step_outwards_by(w0, 4.0, |w, _| {
            let s = smax_est * (1.0 + w);
            shifts.sigma_max_test(s, margin).map(|(hi, f)| (hi, s, f))
        });
        let mut max_hi = top_test.as_ref().map_or(f64::INFINITY, |t| t.0);
        // Where the bracket is wider than wanted (a Ritz vector stopped short in a cluster at
        // the top, or tests started from the search's upper end), the passing test's factor
        // drives a shift-invert run (`SaddleRun::refine_top`) that raises the lower end, and
        // tests stepping out from it — below the one that passed — lower the upper end.
        let mut max_lo = max_lo;
        if let Some((hi, s_ok, f)) = top_test.filter(|t| t.0 / max_lo - 1.0 > 2.5e-13) {
            max_lo = max_lo.max(self.refine_top(&f, s_ok).unwrap_or(0.0));
            drop(f);
            let shifts = &mut self.shifts;
            let from = max_lo;
            if hi / from - 1.0 > 2.5e-13 {
                if let Some(h) = certify::step_outwards_by(16.0 * f64::EPSILON, 4.0, |w, _| {
                    let s = from * (1.0 + w);
                    if s >= s_ok {
                        return Some(f64::INFINITY);
                    }
                    shifts.sigma_max_test(s, margin).map(|t| t.0)
                }) {
                    max_hi = max_hi.min(h);
                }
            }
        }
        (max_lo, max_hi)
    }
}
