//! The negative side of the saddle point's spectrum by tests of `M(s) = Dᵀ(K + sI)⁻¹D`
//! ([`super`]): the plain m×m test that brackets |λ⁻_max| in the inertia search, and Lemma R's
//! proven floor for coupled rows.

use super::coupling::Blocks;
use super::shifts::Shifts;
use crate::conditioning::certify::{gamma, Margin, U};
use faer::{Mat, Side};

/// Largest N·m² for [`negative_floor`] (its dense `R̂ᵀX̂`).
pub const MAX_FLOOR_WORK: usize = 2_000_000_000;

/// A proven `t' ≤ t` with at least m eigenvalues of A in `(−∞, −t']`, for any D (the negative
/// side's floor where no LDLᵀ inertia test settles it: coupled rows, whose negative
/// eigenvalues cluster as a Boolean D's do and where [`super::schur`] does not apply). With
/// `#{λ < s} ≤ m` proven for an s > 0 — what every caller has from the positive side
/// (a verified `H(s) ≻ 0`, or Temple's bound of λ⁺_min) — no eigenvalue lies in
/// `(−t', s)`, so σ_min ≥ min(t', s). (The positive side's count is needed: `K + t'I ≻ 0`
/// alone would allow an (m+1)-th negative eigenvalue in (−t', 0) where K is indefinite.)
///
/// **Lemma R.** For t > 0 with `K + tI ≻ 0`, eliminating `K + tI` from
/// `A + tI = [K + tI, D; Dᵀ, tI]` gives `#{λ(A) < −t} = #{eigenvalues of M(t) above t}`,
/// `M(t) = Dᵀ(K + tI)⁻¹D`, so λ_min(M(t)) ≥ t puts all m of M's eigenvalues at or above t,
/// i.e. m eigenvalues of A at or below −t (for λ_min(M(t')) = t' exactly, one at −t'); M
/// decreases with t. For any X̂ and `R = D − (K + tI)X̂`,
/// `M(t) = S' + Rᵀ(K + tI)⁻¹R ⪰ S'`, `S' = X̂ᵀD + RᵀX̂` (symmetric; expand
/// `D = (K + tI)X̂ + R`): the solves' error enters only through a term ⪰ 0 that is dropped.
/// Computed: X̂ by m solves, R̂ by compensated dot products with its bound (the stored
/// `fl(k_ii + t)` off by `u|·|`), `Ŝ = fl(X̂ᵀD + R̂ᵀX̂)` symmetrized with an entrywise bound
/// whose Frobenius norm e bounds `‖Ŝ_sym − S'‖₂`, and a dense Cholesky of `fl(Ŝ_sym − tI)`:
/// where it succeeds with slack c ([`super::schur::cholesky_slack`]),
/// `λ_min(M(t)) ≥ λ_min(S') ≥ t − c − e =: t'`; then `λ_min(M(t')) ≥ λ_min(M(t)) ≥ t'` once
/// `K + t'I ≻ 0` is verified (`Shifts::verified_pd`): m eigenvalues at or below −t'.
/// None where a test fails, t' ≤ 0 or N·m² exceeds [`MAX_FLOOR_WORK`].
pub(super) fn negative_floor(shifts: &mut Shifts<'_>, t: f64, margin: Margin) -> Option<f64> {
    use crate::conditioning::certify::{residual_dot2, up};
    let (pattern, blocks) = (shifts.pattern, shifts.blocks);
    let (n, m) = (pattern.n(), blocks.m);
    if n.saturating_mul(m).saturating_mul(m) > MAX_FLOOR_WORK || t.is_nan() || t <= 0.0 {
        return None;
    }
    let f = shifts.factor(1.0, t, 0.0)?;
    let stored = &shifts.work; // fl(K + tI): the matrix R̂ is formed with
    let x = blocks.solved(&f, n);
    drop(f);
    let mut r = vec![0.0; n * m];
    let mut dr = vec![0.0; n * m];
    let mut dcol = vec![0.0; n];
    for j in 0..m {
        let xj: Vec<f64> = x.col(j).iter().copied().collect();
        for (d, a) in blocks.column(j) {
            dcol[d] = a;
        }
        let res = residual_dot2(pattern.pat(), stored, &xj, 1.0, &dcol);
        for (i, (ri, ei)) in res.into_iter().enumerate() {
            r[j * n + i] = ri;
            dr[j * n + i] = up(ei + U * (stored[pattern.diag[i]] * xj[i]).abs());
        }
        for (d, _) in blocks.column(j) {
            dcol[d] = 0.0;
        }
    }
    // Ŝ = X̂ᵀD + R̂ᵀX̂ with its entrywise bound.
    let mut s_hat = Mat::<f64>::zeros(m, m);
    let mut bound = Mat::<f64>::zeros(m, m);
    for j in 0..m {
        let len = blocks.column(j).count();
        let g = gamma(n + len + 2);
        for i in 0..m {
            let (mut v, mut abs, mut err) = (0.0, 0.0, 0.0);
            for (d, a) in blocks.column(j) {
                v += x[(d, i)] * a;
                abs += (x[(d, i)] * a).abs();
            }
            for k in 0..n {
                let (rk, xk) = (r[i * n + k], x[(k, j)]);
                v += rk * xk;
                abs += (rk * xk).abs();
                err += dr[i * n + k] * xk.abs();
            }
            s_hat[(i, j)] = v;
            bound[(i, j)] = up(g * abs + err);
        }
    }
    let mut e2 = 0.0;
    let sym = Mat::from_fn(m, m, |i, j| 0.5 * (s_hat[(i, j)] + s_hat[(j, i)]));
    for i in 0..m {
        for j in 0..m {
            let b = 0.5 * (bound[(i, j)] + bound[(j, i)]) + U * sym[(i, j)].abs();
            e2 += b * b;
        }
    }
    let e = up(up(e2).sqrt());
    let tm = Mat::from_fn(m, m, |i, j| sym[(i, j)] - if i == j { t } else { 0.0 });
    let c = super::schur::cholesky_slack(&tm)?;
    let t2 = (t - up(c + e)) * (1.0 - 8.0 * U);
    (t2 > 0.0 && shifts.verified_pd(1.0, t2, 0.0, margin)).then_some(t2)
}

/// Is there an eigenvalue of A in [−s, 0)? ⇔ `λ_min(Dᵀ(K + sI)⁻¹D) < s` (None where
/// `K + sI` is not positive definite).
pub(super) fn schur_test_fails(shifts: &mut Shifts, blocks: &Blocks<'_>, s: f64) -> Option<bool> {
    let f = shifts.factor(1.0, s, 0.0)?;
    let n = shifts.pattern.n();
    let m = blocks.m;
    let x = blocks.solved(&f, n);
    // M = DᵀX (for a Boolean D the entries x[(d_i, j)] themselves, bit for bit).
    let dtx = |i: usize, j: usize| blocks.dt_col(&x, i, j);
    // λ_min(M) ≥ s ⇔ M − sI ⪰ 0, tested (strictly) by a dense Cholesky: the same
    // floating-point definiteness test as every inertia test of these routes, at m³/3 flops
    // instead of a symmetric eigendecomposition.
    let shifted = faer::Mat::from_fn(m, m, |i, j| {
        0.5 * (dtx(i, j) + dtx(j, i)) - if i == j { s } else { 0.0 }
    });
    Some(shifted.llt(Side::Lower).is_err())
}
