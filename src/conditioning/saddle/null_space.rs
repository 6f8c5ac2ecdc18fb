//! The smallest eigenvalue of K on the null space of Dᵀ, `λ_min(K_Z) = min_{Dᵀz = 0} zᵀKz/zᵀz`,
//! with a proven upper bound: what the floor of cond₂(K + DEDᵀ) over all penalties needs for
//! rows that couple DOFs (`strategy::optimal::cond2_lower_bound`; for a Boolean D, K_Z is
//! K_FF and the certified SPD route gives it).
//!
//! **Estimate.** Lanczos on `f ↦ x` with `[K D; Dᵀ 0][x; y] = [f; 0]`, i.e. on
//! `Z(ZᵀKZ)⁻¹Zᵀ` (PSD, null space range(D)), each product one solve through `K + ρDDᵀ`
//! ([`super::coupling::AugmentedInverse`]): its top Ritz value is `1/λ_min(K_Z)`.
//!
//! **Proven upper bound.** The Ritz vector is projected, `x̂ = y − D G⁻¹Dᵀy` (G = DᵀD), and
//! whatever `r = Dᵀx̂` rounding leaves is bounded: `z = x̂ − D G⁻¹r` lies in the null space
//! exactly, `‖x̂ − z‖ ≤ ‖r‖/√λ_min(G)`, so with `t = ‖r‖/(√ℓ·‖x̂‖)` (ℓ ≤ λ_min(G) proven by a
//! dense Cholesky of `Ĝ − ℓI` with its rounding and that of Ĝ bounded) and Λ ≥ λ_max(K)
//! (Gershgorin, rounded up),
//! `λ_min(K_Z) ≤ zᵀKz/zᵀz ≤ (√ρ_hi(x̂) + t√Λ)² / (1 − t)²`,
//! ρ_hi the upper end of x̂'s Rayleigh interval (`certify::rayleigh_interval`). t is of the
//! order of u·cond(G): the bound sits a rounding above the Rayleigh quotient.

use super::coupling::{self, AugmentedInverse, Row};
use crate::conditioning::certify::{dot_interval, gamma, rayleigh_interval, up, U};
use crate::conditioning::sparse::{lanczos, Keep, MAX_LANCZOS_STEPS, STAGNATION};
use crate::error::{Error, Result};
use faer::sparse::SparseColMat;
use faer::{Mat, Side};

/// `λ_min(K_Z)`: the Lanczos estimate and a proven upper bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NullSpaceMin {
    /// The converged Lanczos estimate.
    pub estimate: f64,
    /// A proven upper bound (module doc).
    pub upper: f64,
}

/// `λ_min` of K on the null space of Dᵀ (D's columns the `rows`) for symmetric positive
/// semidefinite K (both triangles stored), with K positive definite on that null space.
/// Errors as [`super::cond2_saddle_rows`] on the rows (0 < m < N, distinct DOFs in a row,
/// finite nonzero rows; dependent rows are [`Error::Singular`]), and [`Error::Numerical`]
/// where the bound cannot be proven.
pub fn null_space_lambda_min(k: &SparseColMat<usize, f64>, rows: &[Row]) -> Result<NullSpaceMin> {
    let (pattern, blocks) = coupling::rows_on(k, rows)?;
    let mut inverse = AugmentedInverse::new(&pattern, &blocks)?;
    let (n, m) = (pattern.n(), blocks.m);
    let mut full = vec![0.0; n + m];
    let mut out = vec![0.0; n + m];
    let run = lanczos(
        n,
        MAX_LANCZOS_STEPS,
        |_| STAGNATION,
        None,
        Keep::Always,
        |f, x| {
            full[..n].copy_from_slice(f);
            full[n..].iter_mut().for_each(|v| *v = 0.0);
            inverse.apply(&full, &mut out, 1.0);
            x.copy_from_slice(&out[..n]);
        },
    )?;
    let failed =
        |what: &str| Error::Numerical(format!("λ_min of K on the null space of Dᵀ: {what}"));
    if !(run.theta.is_finite() && run.theta > 0.0) {
        return Err(failed("the Lanczos estimate is not a positive number"));
    }
    let y = run.vector.ok_or_else(|| failed("no Ritz vector"))?;
    // G = DᵀD with its entrywise rounding bound, and its Cholesky for the projection.
    let mut g = Mat::<f64>::zeros(m, m);
    let mut g_err = 0.0f64;
    let mut col = vec![0.0; n];
    for j in 0..m {
        for (d, a) in blocks.column(j) {
            col[d] = a;
        }
        for i in 0..m {
            let (mut v, mut abs, mut len) = (0.0, 0.0, 0usize);
            for (d, a) in blocks.column(i) {
                v += a * col[d];
                abs += (a * col[d]).abs();
                len += 1;
            }
            g[(i, j)] = v;
            g_err += (gamma(len + 1) * abs).powi(2);
        }
        for (d, _) in blocks.column(j) {
            col[d] = 0.0;
        }
    }
    let g = Mat::from_fn(m, m, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
    let g_err = up(up(g_err).sqrt() + U * g.norm_l2());
    let llt = g
        .llt(Side::Lower)
        .map_err(|_| Error::singular("the constraint rows are linearly dependent (DᵀD)"))?;
    // x̂ = y − D G⁻¹ Dᵀ y.
    let mut dty = Mat::<f64>::from_fn(m, 1, |c, _| blocks.dt(&y, c));
    faer::linalg::solvers::Solve::solve_in_place(&llt, dty.as_mut());
    let mut x = y.clone();
    let coef: Vec<f64> = (0..m).map(|c| dty[(c, 0)]).collect();
    blocks.add_d(&coef, -1.0, &mut x);
    // ‖r‖ = ‖Dᵀx̂‖ from above.
    let r2: f64 = (0..m)
        .map(|c| {
            let (v, abs, len) = blocks
                .column(c)
                .fold((0.0, 0.0, 0usize), |(v, a, l), (d, w)| {
                    (v + w * x[d], a + (w * x[d]).abs(), l + 1)
                });
            (v.abs() + gamma(len + 1) * abs).powi(2)
        })
        .sum();
    let r_norm = up(up(r2).sqrt());
    // ℓ ≤ λ_min(G): a dense Cholesky of Ĝ − ℓI, ℓ halving from the smallest pivot.
    let min_pivot = (0..m)
        .map(|i| llt.L()[(i, i)].powi(2))
        .fold(f64::INFINITY, f64::min);
    let mut ell = 0.5 * min_pivot;
    let lambda_g = loop {
        let tm = Mat::from_fn(m, m, |i, j| g[(i, j)] - if i == j { ell } else { 0.0 });
        if let Some(c) = super::schur::cholesky_slack(&tm) {
            let lo = (ell - up(c + g_err)) * (1.0 - 8.0 * U);
            if lo > 0.0 {
                break lo;
            }
        }
        ell *= 1.0 / 16.0;
        if ell.is_nan() || ell <= f64::MIN_POSITIVE {
            return Err(failed("no positive lower bound of λ_min(DᵀD)"));
        }
    };
    // Λ ≥ λ_max(K): Gershgorin, rounded up.
    let cp = pattern.pattern.col_ptr();
    let big = (0..n)
        .map(|j| {
            let (a, b) = (cp[j], cp[j + 1]);
            let len = b - a;
            (1.0 + gamma(len + 1)) * pattern.values[a..b].iter().map(|v| v.abs()).sum::<f64>()
        })
        .fold(0.0, f64::max);
    let (_, rho_hi) = rayleigh_interval(pattern.pat(), &pattern.values, &x)
        .ok_or_else(|| failed("the Rayleigh quotient is not positive"))?;
    let x_norm = dot_interval(&x, &x).0.sqrt() * (1.0 - 4.0 * f64::EPSILON);
    let t = up(r_norm / (lambda_g.sqrt() * (1.0 - 4.0 * U)) / x_norm);
    if t.is_nan() || t >= 0.5 {
        return Err(failed("the projection left too large a residual"));
    }
    let upper = up(up(rho_hi.sqrt() + up(t * big.sqrt())).powi(2) / ((1.0 - t) * (1.0 - t)));
    Ok(NullSpaceMin {
        estimate: 1.0 / run.theta,
        upper,
    })
}
