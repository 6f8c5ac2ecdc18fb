//! cond₂ of a matrix unsymmetric by rounding, through its symmetric part.

use super::{cond2_routes, sparse, CondReport, CondRoute, Reuse, DENSIFY_LIMIT};
use crate::error::{Error, Result};
use crate::system::{Asymmetry, Stiffness};

/// cond₂ of a matrix unsymmetric by rounding ([`Symmetry::Near`]): its symmetric part
/// `H = fl((A + Aᵀ)/2)` by the certified SPD routes, the bracket widened for the skew part
/// and for H's own rounding (module doc of [`crate::system::Symmetry`]): with
/// `λ_min(H) ∈ [l₁, h₁]`, `λ_max(H) ∈ [l₂, h₂]`, δ ≥ ‖fl(H) − H‖₂ and ν ≥ ‖(A − Aᵀ)/2‖₂,
///
/// `σ_min(A) ∈ [l₁ − δ, ((h₁ + δ)² + ν²)^{1/2}]`, `σ_max(A) ∈ [l₂ − δ, h₂ + δ + ν]`,
///
/// the estimates H's (second order in ν). Where that bracket misses the contract (a skew part
/// comparable with σ_min) and the matrix can be densified, or H is not positive definite, the
/// SVD of the stored matrix decides instead (its Kahan bounds hold for any matrix); the
/// narrower proven bracket is kept. The report carries the asymmetry either way.
pub(super) fn cond2_near_symmetric(
    a: &Stiffness,
    asym: Asymmetry,
    reuse: Reuse<'_>,
) -> Result<(CondReport, Option<sparse::RitzStarts>)> {
    let (h, delta) = a.symmetric_part();
    let nu = asym.skew_norm_bound;
    let on_h = cond2_routes(
        &h,
        true,
        Reuse {
            factor: None,
            ..reuse
        },
    );
    let widened = match on_h {
        Ok((r, ritz)) if matches!(r.route, CondRoute::SparseInertia | CondRoute::DenseInertia) => {
            let c = r
                .certificate
                .expect("the certified routes carry a certificate");
            let up = |x: f64| x * (1.0 + 4.0 * f64::EPSILON);
            let down = |x: f64| (x * (1.0 - 4.0 * f64::EPSILON)).max(0.0);
            let certificate = sparse::Certificate {
                lambda_max_lo: down(c.lambda_max_lo - delta),
                lambda_max_hi: up(c.lambda_max_hi + delta + nu),
                lambda_min_lo: down(c.lambda_min_lo - delta),
                lambda_min_hi: up((c.lambda_min_hi + delta).hypot(nu)),
                ..c
            };
            let mut w = CondReport::with_certificate(
                r.sigma_max
                    .clamp(certificate.lambda_max_lo, certificate.lambda_max_hi),
                r.sigma_min
                    .clamp(certificate.lambda_min_lo, certificate.lambda_min_hi),
                r.route,
                certificate,
                r.bounds_proven,
                None,
            );
            w.asymmetry = Some(asym);
            Some((w, ritz))
        }
        Ok(_) | Err(Error::Singular(_)) => None,
        Err(e) => return Err(e),
    };
    if let Some((w, _)) = &widened {
        if w.within_contract() {
            return Ok(widened.expect("some"));
        }
    }
    let densifiable = matches!(a, Stiffness::Dense(_)) || a.structure().densify_allowed();
    if !densifiable {
        return widened.ok_or_else(|| {
            Error::unsupported(
                format!(
                    "exact cond₂ of a sparse {n}×{n} matrix that is not symmetric ({}) and whose \
                     symmetric part is not positive definite",
                    asym.describe(),
                    n = a.n()
                ),
                format!("densifying, which is limited to n ≤ {DENSIFY_LIMIT}"),
            )
        });
    }
    let (mut svd, _) = cond2_routes(a, false, Reuse::default())?;
    svd.asymmetry = Some(asym);
    Ok(match widened {
        Some((w, ritz)) if !svd.within_contract() && w.error_bound() < svd.error_bound() => {
            (w, ritz)
        }
        _ => (svd, None),
    })
}
