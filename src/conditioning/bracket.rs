//! Brackets of an extreme eigenvalue by inertia tests around an estimate: the search every
//! certified cond₂ route makes ([`super::sparse`], [`super::saddle`]). `upper(σ)` answers
//! whether σ is an upper bound of the eigenvalue (a Cholesky test that proves it, or the
//! search's inertia count); the searches only decide *where* to test.

/// Target relative width of each eigenvalue bracket (before the rounding floor).
pub const BRACKET_TOL: f64 = 1e-11;

/// Target relative width of the eigenvalue brackets of a matrix with `cond₂ ≈ cond_est`:
/// [`BRACKET_TOL`], or the rounding floor `64·ε_mach·cond₂` of λ_min where that is wider (the
/// backward error of a Cholesky test is `≈ ε_mach·‖A‖`, i.e. `ε_mach·cond₂` relative to λ_min).
pub(crate) fn bracket_tol(cond_est: f64) -> f64 {
    BRACKET_TOL.max(64.0 * f64::EPSILON * cond_est)
}

/// Relative offset, in units of the target width, of the first two inertia tests of
/// [`bracket`] from the estimate: `(1 + 0.45 t) / (1 − 0.45 t) − 1 < t` for every t ≤ 0.2.
const FIRST_STEP: f64 = 0.45;

/// Brackets an extreme eigenvalue near the estimate `theta > 0`: `upper(σ)` must return true iff
/// σ is an upper bound of the eigenvalue (from an inertia test). Returns (lo, hi) with
/// `hi / lo − 1 ≤ tol`, or wider if 60 tests did not get there.
pub(crate) fn bracket(theta: f64, tol: f64, mut upper: impl FnMut(f64) -> bool) -> (f64, f64) {
    let mut lo = None;
    let mut hi = None;
    // First tests at θ(1 ± FIRST_STEP·tol): a bracket of relative width < tol when the
    // estimate is good, so two tests settle it (at ±tol/2 the width was just over tol and
    // every bracket paid a third test).
    let mut h = FIRST_STEP * tol;
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
    // Downward search for a lower bound (if the upward search did not already give one),
    // from at most half the estimate: where the rounding floor makes `tol` ≥ 2 (cond₂ ≳
    // 1/(32 ε_mach)) a first step of tol/2 would never be tried and leave no lower bound.
    let mut h = (FIRST_STEP * tol).min(0.5);
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

/// A bracket of an eigenvalue from a proven lower bound `lo` (e.g. a Rayleigh quotient of
/// λ_max): one inertia test at `lo(1 + 0.9 tol)` where the bound is sharp, else [`bracket`]
/// from there (`upper(σ)` true iff σ is an upper bound).
fn bracket_above(lo: f64, tol: f64, mut upper: impl FnMut(f64) -> bool) -> (f64, f64) {
    let s = lo * (1.0 + 0.9 * tol);
    if upper(s) {
        return (lo, s);
    }
    let (l, h) = bracket(s, tol, upper);
    (l.max(s), h)
}

/// The bracket of the top eigenvalue, estimated `est`, with `rq` the certified interval of a
/// Rayleigh quotient of its Ritz vector (a lower bound, Courant–Fischer) where there is one:
/// [`bracket_above`] from it where it is sharp (within `tol` of the estimate), else the
/// two-sided [`bracket`] around the estimate, raised to the quotient (`upper(σ)` true iff σ
/// is an upper bound).
pub(crate) fn bracket_top(
    rq: Option<(f64, f64)>,
    est: f64,
    tol: f64,
    upper: impl FnMut(f64) -> bool,
) -> (f64, f64) {
    match rq {
        Some((lo, _)) if lo * (1.0 + tol) >= est => bracket_above(lo, tol, upper),
        rq => {
            let (l, h) = bracket(est, tol, upper);
            (rq.map_or(l, |(lo, _)| l.max(lo)), h)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::bracket;

    /// A bracket closes around the eigenvalue even when the rounding floor makes the target
    /// width ≥ 2 (cond₂ ≳ 1/(32 ε_mach)): the 9 900-DOF cantilever of `cond_cost` once got
    /// λ_max ∈ [0, 4.8e10] because the downward search started at tol/2 ≥ 1.
    #[test]
    fn bracket_closes_with_a_wide_target() {
        for (lambda, theta, tol) in [
            (1.5, 1.0, 6.6),
            (0.9, 1.0, 6.6),
            (1.0, 1.0, 3e4),
            (1.2, 1.0, 1e-11),
        ] {
            let (lo, hi) = bracket(theta, tol, |s| s >= lambda);
            assert!(
                lo > 0.0 && hi.is_finite(),
                "λ {lambda}, tol {tol}: [{lo}, {hi}]"
            );
            assert!(lo <= lambda && lambda <= hi, "λ {lambda} ∉ [{lo}, {hi}]");
            assert!(
                hi / lo - 1.0 <= tol.max(1e-11) * 1.0001,
                "λ {lambda}, tol {tol}: [{lo}, {hi}]"
            );
        }
    }
    /// With an exact estimate a bracket costs two inertia tests (one each side), not three:
    /// the first tests must land inside the target width.
    #[test]
    fn exact_estimate_costs_two_tests() {
        for tol in [1e-11, 1e-6, 0.1, 0.2] {
            let mut tests = 0;
            let (lo, hi) = bracket(3.0, tol, |s| {
                tests += 1;
                s >= 3.0
            });
            assert_eq!(tests, 2, "tol {tol}: [{lo}, {hi}]");
            assert!(lo <= 3.0 && 3.0 <= hi && hi / lo - 1.0 <= tol);
        }
    }
}
