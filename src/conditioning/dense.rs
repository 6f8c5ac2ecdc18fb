//! The dense routes of cond₂: the certified SPD route on the full pattern, symmetric
//! eigenvalues, the SVD, and Kahan's residual bound that proves their brackets.

use super::certify;
use super::{kato_temple, sparse, CondReport, CondRoute, Reuse};
use crate::error::{Error, Result};
use faer::{MatRef, Side};

/// cond₂ of a dense matrix; `symmetric` selects the eigenvalue routes.
///
/// * Symmetric with a positive diagonal: the certified SPD route ([`sparse`], on the full
///   pattern; [`CondRoute::DenseInertia`]) — λ_min from Cholesky solves, as accurate as the
///   equilibrated matrix allows, with proven bounds. An indefinite matrix falls through.
/// * Other symmetric: eigenvalues and eigenvectors, `σ = |λ|` ([`CondRoute::SymmetricEigen`]).
/// * Unsymmetric: the SVD ([`CondRoute::Svd`]).
///
/// The last two are bounded by Kahan's residual theorem ([`residual_radius`]); their extreme
/// values by Kato–Temple where the gap to their neighbours is resolved ([`kato_temple`]): then
/// σ_max and σ_min are the Rayleigh quotients of their vectors, second-order accurate.
pub fn cond2_dense(a: MatRef<'_, f64>, symmetric: bool) -> Result<CondReport> {
    let n = a.nrows();
    if n == 0 || a.ncols() != n {
        return Err(Error::unsupported(
            "cond₂",
            format!("a non-empty square matrix (got {n}×{})", a.ncols()),
        ));
    }
    if !(0..n).all(|j| (0..n).all(|i| a[(i, j)].is_finite())) {
        return Err(Error::Numerical(
            "singular values are not finite (matrix contains NaN/Inf?)".into(),
        ));
    }
    if symmetric && (0..n).all(|i| a[(i, i)] > 0.0) {
        let sp = crate::system::sparse_of_dense(a);
        match sparse::extreme_eigenvalues(&sp, sparse::MAX_LANCZOS_STEPS, Reuse::default()) {
            Ok(s) => {
                return Ok(CondReport::with_certificate(
                    s.lambda_max,
                    s.lambda_min,
                    CondRoute::DenseInertia,
                    s.certificate,
                    true,
                    Some(s.log10_det),
                ))
            }
            Err(Error::Singular(_)) => {}
            Err(e) => return Err(e),
        }
    }
    // θ: the computed |λ| or σ, ascending; radius: Kahan's bound on |θ_i − σ_i|; the
    // extremes refined by Kato–Temple where the gap allows.
    let (mut theta, radius, refined, route) = if symmetric {
        let e = a
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Numerical(format!("symmetric eigenvalues failed: {e:?}")))?;
        let lambda: Vec<f64> = (0..n).map(|i| e.S()[i]).collect();
        let r = residual_radius(a, e.U(), &lambda, e.U(), &lambda, false);
        let refined = kato_temple::symmetric_extremes(a, &lambda, e.U(), r);
        let theta: Vec<f64> = lambda.iter().map(|l| l.abs()).collect();
        (theta, r, refined, CondRoute::SymmetricEigen)
    } else {
        let svd = a
            .svd()
            .map_err(|e| Error::Numerical(format!("singular values failed: {e:?}")))?;
        let sigma: Vec<f64> = (0..n).map(|i| svd.S()[i]).collect();
        let r = residual_radius(a, svd.V(), &sigma, svd.U(), &sigma, true);
        let refined = kato_temple::svd_extremes(a, &sigma, svd.U(), svd.V(), r);
        (sigma, r, refined, CondRoute::Svd)
    };
    theta.sort_by(f64::total_cmp);
    let (smin, smax) = (theta[0], theta[n - 1]);
    if !(smax.is_finite() && smin.is_finite()) {
        return Err(Error::Numerical(
            "singular values are not finite (matrix contains NaN/Inf?)".into(),
        ));
    }
    let up = |x: f64| x * (1.0 + 4.0 * f64::EPSILON);
    let down = |x: f64| x * (1.0 - 4.0 * f64::EPSILON);
    let kahan = |s: f64| kato_temple::Refined {
        lo: down(s - radius).max(0.0),
        hi: up(s + radius),
        value: s,
    };
    let max = refined.max.unwrap_or_else(|| kahan(smax));
    let min = refined.min.unwrap_or_else(|| kahan(smin));
    let certificate = sparse::Certificate {
        lambda_max_lo: max.lo,
        lambda_max_hi: max.hi,
        lambda_min_lo: min.lo,
        lambda_min_hi: min.hi,
        lanczos_steps: 0,
        factorizations: 0,
    };
    Ok(CondReport::with_certificate(
        max.value,
        min.value,
        route,
        certificate,
        radius.is_finite(),
        None,
    ))
}

/// Kahan's residual bound (Parlett, *The Symmetric Eigenvalue Problem*, Thm 11.5.1; Kahan
/// 1967): for a symmetric J and any X of full rank with `R = JX − XΘ`, Θ diagonal, the
/// eigenvalues of J can be paired with the θ_i so that `|λ − θ_i| ≤ ‖R‖₂ / σ_min(X)`, and
/// `σ_min(X)² ≥ 1 − ‖XᵀX − I‖₂`. For a symmetric A, J = A and X = V̂ (eigenvectors), so the
/// sorted |λ| and |θ| differ by at most the radius; for the SVD `A ≈ ÛΣ̂V̂ᵀ`, J is the
/// Jordan–Wielandt matrix `[0 A; Aᵀ 0]` (eigenvalues ±σ_i) with `X = [Û Û; V̂ −V̂]/√2`, whence
/// `‖R‖_F² = ‖AV̂ − ÛΣ̂‖_F² + ‖AᵀÛ − V̂Σ̂‖_F²` and `‖XᵀX − I‖_F ≤ ‖ÛᵀÛ − I‖_F + ‖V̂ᵀV̂ − I‖_F`.
/// Residuals are formed in f64 with their rounding bounded entrywise by
/// `γ_{n+1}(|A||V̂| + |Û||Σ̂|)` (Higham, *Accuracy and Stability*, §3.5). Returns the radius
/// (+∞ if X is not provably of full rank). Cost O(n³); the vectors come with the dense routine.
///
/// `v`, `sv`: right vectors and values; `u`, `su`: left ones (the same for a symmetric A);
/// `svd`: also bound `AᵀÛ − V̂Σ̂`.
pub fn residual_radius(
    a: MatRef<'_, f64>,
    v: MatRef<'_, f64>,
    sv: &[f64],
    u: MatRef<'_, f64>,
    su: &[f64],
    svd: bool,
) -> f64 {
    use faer::Mat;
    let n = a.nrows();
    // Conventional matrix products (any summation order, blocked or not) have
    // |fl(XY) − XY| ≤ γ_n|X||Y| entrywise; one more γ covers the subtraction and the products
    // of the bound itself.
    let g = certify::gamma(n + 3);
    let abs = |x: MatRef<'_, f64>| Mat::from_fn(x.nrows(), x.ncols(), |i, j| x[(i, j)].abs());
    // ‖M X − Y diag(s)‖_F² with its rounding.
    let residual = |m: MatRef<'_, f64>, x: MatRef<'_, f64>, y: MatRef<'_, f64>, s: &[f64]| {
        let mx = m * x;
        let bound = abs(m) * abs(x);
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let ys = y[(i, j)] * s[j];
                let e = (mx[(i, j)] - ys).abs() + g * (bound[(i, j)] + ys.abs());
                sum += e * e;
            }
        }
        sum * (1.0 + certify::gamma(n * n + 2))
    };
    // ‖XᵀX − I‖_F with its rounding.
    let defect = |x: MatRef<'_, f64>| {
        let xtx = x.transpose() * x;
        let bound = abs(x).transpose() * abs(x);
        let mut sum = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let d = xtx[(i, j)] - if i == j { 1.0 } else { 0.0 };
                let e = d.abs() + g * (bound[(i, j)] + 1.0);
                sum += e * e;
            }
        }
        (sum * (1.0 + certify::gamma(n * n + 2))).sqrt()
    };
    let (r2, eta) = if svd {
        (
            residual(a, v, u, su) + residual(a.transpose(), u, v, sv),
            defect(u) + defect(v),
        )
    } else {
        (residual(a, v, u, su), defect(v))
    };
    let eta = eta * (1.0 + 8.0 * f64::EPSILON);
    if !(eta < 1.0 && r2.is_finite()) {
        return f64::INFINITY;
    }
    (r2.sqrt() / (1.0 - eta).sqrt()) * (1.0 + 8.0 * f64::EPSILON)
}
