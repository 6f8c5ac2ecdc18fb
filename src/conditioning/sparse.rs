//! Exact, certified extreme eigenvalues of a sparse SPD matrix without densifying it.
//!
//! For A = Aᵀ ≻ 0, `cond₂(A) = λ_max / λ_min`. Both ends are found in two phases:
//!
//! 1. **Estimate** by Lanczos: on A (matrix–vector products) for λ_max, and on A⁻¹ (solves with
//!    the sparse Cholesky factor of A) for λ_min = 1 / λ_max(A⁻¹). The extreme Ritz value of the
//!    tridiagonal `T_k` is found by Sturm bisection; no Lanczos vectors are stored (memory O(n)).
//! 2. **Certify** by inertia (Sylvester's law): a sparse Cholesky factorization of `σI − A`
//!    succeeds iff every eigenvalue of A is below σ, one of `A − σI` iff every eigenvalue is
//!    above σ. Each factorization reuses one symbolic analysis of the pattern of A (with its
//!    diagonal). The estimate is bracketed, `lo ≤ λ ≤ hi`, by one success and one failure, then
//!    the bracket is narrowed by geometric bisection until `hi / lo − 1 ≤ tol`.
//!
//! The bracket is the certificate: it holds up to the backward error of Cholesky,
//! `‖ΔA‖ ≲ c·ε_mach·‖A‖`, so the attainable relative width at λ_min is about
//! `c·ε_mach·cond₂(A)` — the same absolute accuracy `ε_mach·‖A‖` a dense symmetric eigensolver
//! has. The target width of both brackets is therefore `max(tol, 64·ε_mach·cond₂)`
//! (`bracket_tol`; a narrower λ_max bracket would not make cond₂ better known), and the width
//! actually reached is reported in [`Certificate`].
//!
//! Cost: one symbolic analysis, one Cholesky of A (dropped after the λ_min estimate: one factor
//! in memory at a time), `k` products and `k` solves (k ≲ 100–300), one shift-invert factor
//! where the top of the spectrum is clustered, and 2 shifted Cholesky tests per end when the
//! estimate is within the target width (more where it is not). Memory: O(nnz of the factor).
//!
//! Use it for large sparse SPD matrices (membranes, assembled frames); [`super::cond2`] picks it
//! automatically above [`SPARSE_ROUTE_MIN_N`].

use crate::error::{Error, Result};
use crate::linalg::{DiagonalPattern, SparseLlt};
use faer::sparse::SparseColMat;
use serde::Serialize;

/// Below this dimension [`super::cond2`] densifies sparse matrices (dense eigenvalues are cheaper
/// than several sparse factorizations for small n).
pub const SPARSE_ROUTE_MIN_N: usize = 400;

/// Lanczos step limit per end (estimates only: the inertia phase corrects a poor estimate).
pub const MAX_LANCZOS_STEPS: usize = 400;

/// Plain Lanczos steps on A before switching to shift-invert for λ_max.
pub const PLAIN_LANCZOS_STEPS: usize = 120;

/// Target relative width of each eigenvalue bracket (before the rounding floor).
pub const BRACKET_TOL: f64 = 1e-11;

/// The certificate of a sparse exact cond₂: brackets of λ_max and λ_min proven by inertia.
#[derive(Clone, Copy, Debug, Serialize, PartialEq)]
pub struct Certificate {
    /// `λ_max ∈ [lambda_max_lo, lambda_max_hi]`.
    pub lambda_max_lo: f64,
    /// Upper end of the λ_max bracket.
    pub lambda_max_hi: f64,
    /// `λ_min ∈ [lambda_min_lo, lambda_min_hi]`.
    pub lambda_min_lo: f64,
    /// Upper end of the λ_min bracket.
    pub lambda_min_hi: f64,
    /// Lanczos steps (products with A plus solves with A).
    pub lanczos_steps: usize,
    /// Numeric Cholesky factorizations (of A and of the shifted matrices).
    pub factorizations: usize,
}

impl Certificate {
    /// `cond₂ ∈ [cond2_lo, cond2_hi]` (`cond2_hi = +∞` when λ_min could not be bounded away from 0).
    pub fn cond2_bounds(&self) -> (f64, f64) {
        (
            self.lambda_max_lo / self.lambda_min_hi,
            self.lambda_max_hi / self.lambda_min_lo,
        )
    }
}

/// Result of [`extreme_eigenvalues`].
#[derive(Clone, Debug)]
pub struct SparseSpectrum {
    /// Midpoint estimate of λ_max.
    pub lambda_max: f64,
    /// Midpoint estimate of λ_min.
    pub lambda_min: f64,
    /// The brackets and the work done.
    pub certificate: Certificate,
    /// `log10 det A` from the Cholesky factor of A (free by-product).
    pub log10_det: f64,
}

/// `αA + σI` for many shifts σ, sharing one symbolic Cholesky analysis.
struct ShiftFamily {
    pattern: DiagonalPattern,
    factorizations: usize,
    /// Value buffer reused by every factorization.
    work: Vec<f64>,
}

impl ShiftFamily {
    fn new(a: &SparseColMat<usize, f64>) -> Result<Self> {
        Ok(ShiftFamily {
            pattern: DiagonalPattern::new(a)?,
            factorizations: 0,
            work: Vec::new(),
        })
    }

    /// Cholesky of `alpha·A + sigma·I` (None if not positive definite).
    fn factor(&mut self, alpha: f64, sigma: f64) -> Option<SparseLlt> {
        let v = &mut self.work;
        v.clear();
        v.extend(self.pattern.values.iter().map(|x| alpha * x));
        for &p in &self.pattern.diag {
            v[p] += sigma;
        }
        self.factorizations += 1;
        self.pattern.factor(v)
    }

    /// Is `alpha·A + sigma·I` positive definite?
    fn is_pd(&mut self, alpha: f64, sigma: f64) -> bool {
        self.factor(alpha, sigma).is_some()
    }
}

/// Largest eigenvalue of the symmetric tridiagonal matrix (diagonal `a`, off-diagonal `b`) by
/// Sturm-count bisection to the last bit.
fn tridiagonal_max_eigenvalue(a: &[f64], b: &[f64]) -> f64 {
    let k = a.len();
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for i in 0..k {
        let r = if i > 0 { b[i - 1].abs() } else { 0.0 } + if i < k - 1 { b[i].abs() } else { 0.0 };
        lo = lo.min(a[i] - r);
        hi = hi.max(a[i] + r);
    }
    // count(x) = number of eigenvalues < x (LDLᵀ of T − xI).
    let count = |x: f64| {
        let mut c = 0;
        let mut d = 1.0;
        for i in 0..k {
            let off = if i > 0 { b[i - 1] * b[i - 1] } else { 0.0 };
            d = a[i] - x - if i > 0 { off / d } else { 0.0 };
            if d == 0.0 {
                d = -f64::EPSILON * (a[i].abs() + x.abs()).max(f64::MIN_POSITIVE);
            }
            if d < 0.0 {
                c += 1;
            }
        }
        c
    };
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if count(mid) < k {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Largest eigenvalue of a symmetric positive operator by plain Lanczos (no stored vectors):
/// returns (estimate, steps, converged). Stops when the top Ritz value stagnates to `1e-14` relative over
/// 5 steps, on an invariant subspace, or after `max_steps`.
pub(crate) fn lanczos_max(
    n: usize,
    max_steps: usize,
    mut apply: impl FnMut(&[f64], &mut [f64]),
) -> Result<(f64, usize, bool)> {
    // Deterministic start vector with every component nonzero (so no eigenvector is missed).
    let mut q: Vec<f64> = (0..n)
        .map(|i| 1.0 + 0.5 * ((i as f64 * 0.618_033_988_749_895).fract() - 0.5))
        .collect();
    let nq = norm(&q);
    q.iter_mut().for_each(|x| *x /= nq);
    let mut q_prev = vec![0.0; n];
    let mut w = vec![0.0; n];
    let (mut alphas, mut betas) = (Vec::new(), Vec::new());
    let mut beta_prev = 0.0;
    let mut history: Vec<f64> = Vec::new();
    let mut steps = 0;
    for _ in 0..max_steps.min(n).max(1) {
        apply(&q, &mut w);
        steps += 1;
        let alpha = dot(&w, &q);
        if !alpha.is_finite() {
            return Err(Error::Numerical(
                "Lanczos produced a non-finite value (matrix contains NaN/Inf?)".into(),
            ));
        }
        for i in 0..n {
            w[i] -= alpha * q[i] + beta_prev * q_prev[i];
        }
        alphas.push(alpha);
        let beta = norm(&w);
        let theta = tridiagonal_max_eigenvalue(&alphas, &betas);
        history.push(theta);
        let h = history.len();
        let stagnated = h > 5 && (theta - history[h - 6]).abs() <= 1e-14 * theta.abs();
        if stagnated || beta <= 1e-300 || beta <= f64::EPSILON * theta.abs() * 1e-2 {
            return Ok((theta, steps, true));
        }
        betas.push(beta);
        std::mem::swap(&mut q_prev, &mut q);
        for i in 0..n {
            q[i] = w[i] / beta;
        }
        beta_prev = beta;
    }
    Ok((*history.last().unwrap_or(&0.0), steps, false))
}

/// Gershgorin upper bound of the spectrum: `max_j (a_jj + Σ_{i≠j} |a_ij|)` (columns of a
/// symmetric matrix).
fn gershgorin_max(a: &SparseColMat<usize, f64>) -> f64 {
    let cp = a.symbolic().col_ptr();
    let ri = a.symbolic().row_idx();
    let av = a.val();
    (0..a.ncols())
        .map(|j| {
            (cp[j]..cp[j + 1])
                .map(|p| if ri[p] == j { av[p] } else { av[p].abs() })
                .sum::<f64>()
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

fn norm(x: &[f64]) -> f64 {
    dot(x, x).sqrt()
}

/// Target relative width of the eigenvalue brackets of a matrix with `cond₂ ≈ cond_est`:
/// [`BRACKET_TOL`], or the rounding floor `64·ε_mach·cond₂` of λ_min where that is wider (the
/// backward error of a Cholesky test is `≈ ε_mach·‖A‖`, i.e. `ε_mach·cond₂` relative to λ_min).
pub(crate) fn bracket_tol(cond_est: f64) -> f64 {
    BRACKET_TOL.max(64.0 * f64::EPSILON * cond_est)
}

/// Brackets an extreme eigenvalue near the estimate `theta > 0`: `upper(σ)` must return true iff
/// σ is an upper bound of the eigenvalue (from an inertia test). Returns (lo, hi) with
/// `hi / lo − 1 ≤ tol`, or wider if 60 tests did not get there.
pub(crate) fn bracket(theta: f64, tol: f64, mut upper: impl FnMut(f64) -> bool) -> (f64, f64) {
    let mut lo = None;
    let mut hi = None;
    let mut h = 0.5 * tol;
    // Upward search for an upper bound.
    for _ in 0..40 {
        let s = theta * (1.0 + h);
        if upper(s) {
            hi = Some(s);
            break;
        }
        lo = Some(s);
        h *= 8.0;
    }
    // Downward search for a lower bound (if the upward search did not already give one).
    let mut h = 0.5 * tol;
    while lo.is_none() && h < 1.0 {
        let s = theta * (1.0 - h);
        if upper(s) {
            hi = Some(hi.map_or(s, |x: f64| x.min(s)));
            h *= 8.0;
        } else {
            lo = Some(s);
        }
    }
    let (mut lo, mut hi) = (lo.unwrap_or(0.0), hi.unwrap_or(f64::INFINITY));
    for _ in 0..60 {
        if !(lo > 0.0 && hi.is_finite()) || hi / lo - 1.0 <= tol {
            break;
        }
        let mid = (lo * hi).sqrt();
        if upper(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    (lo, hi)
}

/// λ_max and λ_min of the sparse SPD matrix `a` (both triangles stored), certified by inertia.
/// Errors with [`Error::Singular`] if A is not positive definite (its Cholesky fails).
pub fn extreme_eigenvalues(
    a: &SparseColMat<usize, f64>,
    max_steps: usize,
) -> Result<SparseSpectrum> {
    let n = a.nrows();
    if n == 0 {
        return Err(Error::input("empty matrix has no condition number"));
    }
    let mut fam = ShiftFamily::new(a)?;
    let chol = fam.factor(1.0, 0.0).ok_or_else(|| {
        Error::singular("sparse Cholesky of A failed: A is not positive definite".to_string())
    })?;
    let log10_det: f64 = chol.l_diagonal().iter().map(|d| 2.0 * d.log10()).sum();

    // Phase 1: estimates. λ_min = 1/λ_max(A⁻¹) by Lanczos with the factor of A, which is then
    // dropped (one factor in memory at a time). λ_max: plain Lanczos on A (products only); if
    // the top of the spectrum is clustered and it has not settled, shift-invert Lanczos on
    // (σ₀I − A)⁻¹ with σ₀ just above the Gershgorin bound, where λ_max = σ₀ − 1/ν_max is well
    // separated.
    let (inv_max, s2, _) = lanczos_max(n, max_steps, |x, y| {
        y.copy_from_slice(x);
        chol.solve_vec_in_place(y);
    })?;
    drop(chol);
    let lmin_est = 1.0 / inv_max;
    let (mut lmax_est, mut s1, converged) =
        lanczos_max(n, PLAIN_LANCZOS_STEPS, |x, y| fam.pattern.matvec(x, y))?;
    if !converged {
        let sigma0 = gershgorin_max(a) * (1.0 + 1e-8);
        if let Some(f) = fam.factor(-1.0, sigma0) {
            let (nu, s, _) = lanczos_max(n, max_steps, |x, y| {
                y.copy_from_slice(x);
                f.solve_vec_in_place(y);
            })?;
            s1 += s;
            if nu > 0.0 && nu.is_finite() {
                lmax_est = lmax_est.max(sigma0 - 1.0 / nu);
            }
        }
    }
    if !(lmax_est.is_finite() && lmin_est.is_finite() && lmin_est > 0.0) {
        return Err(Error::Numerical(format!(
            "Lanczos estimates are not usable (λ_max ≈ {lmax_est:e}, λ_min ≈ {lmin_est:e})"
        )));
    }

    // Phase 2: inertia brackets. λ_max < σ ⇔ σI − A ≻ 0; λ_min ≤ σ ⇔ A − σI ⊁ 0. Both ends
    // to the same relative width: cond₂ cannot be known better than the rounding floor of
    // λ_min, so a narrower λ_max bracket would only cost factorizations.
    let tol = bracket_tol(lmax_est / lmin_est);
    let (max_lo, max_hi) = bracket(lmax_est, tol, |s| fam.is_pd(-1.0, s));
    let (min_lo, min_hi) = bracket(lmin_est, tol, |s| !fam.is_pd(1.0, -s));
    let certificate = Certificate {
        lambda_max_lo: max_lo,
        lambda_max_hi: max_hi,
        lambda_min_lo: min_lo,
        lambda_min_hi: min_hi,
        lanczos_steps: s1 + s2,
        factorizations: fam.factorizations,
    };
    if !(max_lo > 0.0 && max_hi.is_finite() && min_hi.is_finite()) {
        return Err(Error::Numerical(format!(
            "inertia brackets did not close: λ_max ∈ [{max_lo:e}, {max_hi:e}], \
             λ_min ∈ [{min_lo:e}, {min_hi:e}]"
        )));
    }
    // λ_min below the rounding level of A (cond₂ ≳ 1/ε_mach): no shift can be certified
    // positive, the bracket stays [0, hi] and the Lanczos estimate is reported as the value.
    let lambda_min = if min_lo > 0.0 {
        (min_lo * min_hi).sqrt()
    } else {
        lmin_est.min(min_hi)
    };
    Ok(SparseSpectrum {
        lambda_max: (max_lo * max_hi).sqrt(),
        lambda_min,
        certificate,
        log10_det,
    })
}
