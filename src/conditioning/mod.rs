//! 2-norm condition numbers, with bounds, and log-determinants.
//!
//! `cond₂(A) = σ_max(A) / σ_min(A)`, computed by the cheapest route for the matrix at hand,
//! and the route is recorded:
//!
//! | matrix | route | cost |
//! |---|---|---|
//! | sparse SPD (by structure: n ≥ 32, ≤ 25 % nonzeros, however stored) | Lanczos + certificate ([`CondRoute::SparseInertia`], [`sparse`]) | a few sparse Cholesky |
//! | dense SPD (n < 32, or denser) | the same on the full pattern ([`CondRoute::DenseInertia`]) | a few dense-pattern Cholesky |
//! | dense symmetric, not SPD | eigenvalues and vectors, `σ_i = |λ_i|` ([`CondRoute::SymmetricEigen`]) | ≈ 4/3 n³ + residual n³ |
//! | dense unsymmetric | SVD ([`CondRoute::Svd`]) | ≈ 3–4× the eigen route |
//! | sparse saddle point `[K D; Dᵀ 0]`, Boolean D | block-structure inertia ([`CondRoute::SparseSaddleInertia`], [`saddle`]) | a few sparse Cholesky |
//! | other sparse | densified, then as above ([`CondRoute::DensifiedSymmetricEigen`] / [`CondRoute::DensifiedSvd`]) | n² memory |
//!
//! **Symmetric means bit for bit** ([`Stiffness::symmetry`]): the symmetric routes factor one
//! triangle and multiply with both, so their proofs hold for the stored matrix only where every
//! mirror pair is equal. A matrix unsymmetric by rounding ([`Symmetry::Near`]: every pair within
//! `8·ε_mach·max|a|`) is certified through its symmetric part, the bracket widened for the skew
//! part by a second-order bound ([`crate::system::Symmetry`]'s module doc), and goes to the SVD
//! where that bracket misses the contract; the report carries the asymmetry
//! ([`CondReport::asymmetry`]). Anything more unsymmetric takes the SVD.
//!
//! **Accuracy contract.** The reported `cond2` is the route's best estimate — the ratio of the
//! converged Lanczos Ritz values, or of the dense routine's values (their vectors' Rayleigh
//! quotients where Kato–Temple applies) — never the midpoint of a
//! bracket. It agrees with the exact cond₂ of the *stored* matrix to
//! `max(1e-12, 4·ε_mach·cond₂)` relative (what a dense LAPACK SVD achieves), and the SPD routes
//! do better on graded matrices such as `K + D E Dᵀ` with a large ε: their λ_min comes from
//! Cholesky solves, accurate to about ε_mach·cond₂ of the diagonally equilibrated matrix
//! (Demmel & Veselić 1992). Tested against outside references: python-flint / mpmath values
//! of stored matrices (`tests/verification/cond_reference.rs`), double-double eigenvalues on random SPD
//! matrices (`tests/properties/cond_properties.rs`), and LAPACK (`tests/cross_check.rs`, feature `lapack`).
//!
//! Whether a value is *proven* within the contract — its proven bracket allows no value
//! farther than the contract's tolerance — is [`CondReport::within_contract`] (in every rows.csv
//! and in `solve --json` as `cond2_within_contract`); where it is false the width is
//! [`CondReport::error_bound`]. The SPD routes aim their brackets at the contract
//! ([`sparse::width_target`]); a λ_min that the Lanczos run leaves inside a near-double or a
//! cluster (its Ritz vector a mixture) is refined by shift-invert with the factor of the first
//! Cholesky test that passes below it, as λ_max is at the top; the Lanczos runs start from
//! seeded random vectors, which share no mesh's symmetry.
//!
//! **Bounds.** Every report carries `cond2_lo ≤ cond₂ ≤ cond2_hi`. On the SPD routes they are
//! proven for the stored matrix including the rounding of the Cholesky factorizations they
//! rest on ([`certify`]); on the dense eigen/SVD routes by Kahan's residual theorem
//! ([`residual_radius`]), the two extreme values sharpened to second order by Kato–Temple
//! ([`kato_temple`]); on the saddle-point route proven where that pins cond₂ within a
//! factor of 2, else the search's inertia brackets with `bounds_proven = false` ([`saddle`]).
//!
//! `log10|det A|` is read off a factorization (never the raw determinant, which overflows at
//! n ≈ 1600): the determinant ratio of the paper is `log10|det(K+DEDᵀ)| − log10|det K|`.
//!
//! The [`reference`](mod@reference) module recomputes cond₂ with nalgebra (and LAPACK behind the `lapack`
//! feature) as an independent cross-check.

pub mod bracket;
pub mod certify;
mod dense;
pub mod kato_temple;
pub mod lanczos;
mod near_symmetric;
pub mod residual;
pub mod saddle;
mod scaling;
pub(crate) mod shifts;
pub mod sparse;
pub mod starts;
pub mod temple;
pub(crate) mod tridiagonal;
pub mod window;

use crate::error::{Error, Result};
use crate::linalg::Factorization;
use crate::route::CondPlan;
use crate::system::{Asymmetry, Stiffness, Symmetry};
pub use dense::{cond2_dense, residual_radius};
use near_symmetric::cond2_near_symmetric;
pub use scaling::prescale;
use serde::Serialize;

/// How a condition number was computed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CondRoute {
    /// Dense symmetric eigenvalues (σ = |λ|).
    SymmetricEigen,
    /// Dense singular values.
    Svd,
    /// Sparse input densified, then symmetric eigenvalues.
    DensifiedSymmetricEigen,
    /// Sparse input densified, then singular values.
    DensifiedSvd,
    /// Sparse SPD: Lanczos estimates certified by inertia (sparse Cholesky of shifted
    /// matrices), see [`sparse`].
    SparseInertia,
    /// Sparse saddle-point `[K D; Dᵀ 0]` (Boolean D): Lanczos estimates of the four extreme
    /// |λ| certified by inertia through the block structure, see [`saddle`].
    SparseSaddleInertia,
    /// Dense SPD: the certified route of [`sparse`] on the full pattern.
    DenseInertia,
}

impl CondRoute {
    /// Stable name used in CSV/JSON output.
    pub fn name(self) -> &'static str {
        match self {
            CondRoute::SymmetricEigen => "symmetric_eigen",
            CondRoute::Svd => "svd",
            CondRoute::DensifiedSymmetricEigen => "densified_symmetric_eigen",
            CondRoute::DensifiedSvd => "densified_svd",
            CondRoute::SparseInertia => "sparse_inertia",
            CondRoute::SparseSaddleInertia => "sparse_saddle_inertia",
            CondRoute::DenseInertia => "dense_inertia",
        }
    }
}

/// A 2-norm condition number: the best estimate, the bounds around it, the extreme singular
/// values and the route taken.
///
/// `cond2` is the ratio of the route's converged estimates (Lanczos Ritz values, or the dense
/// routine's values): tested against outside references to `max(1e-12, 4·ε_mach·cond₂)`
/// relative (module docs). `cond2_lo ≤ cond₂ ≤ cond2_hi` are bounds; where `bounds_proven`
/// they are proven for the stored matrix including every rounding ([`certify`]).
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CondReport {
    /// `σ_max / σ_min` (+∞ if σ_min = 0): the best estimate.
    pub cond2: f64,
    /// Lower bound of cond₂.
    pub cond2_lo: f64,
    /// Upper bound of cond₂ (+∞ where σ_min could not be bounded away from 0).
    pub cond2_hi: f64,
    /// Whether `[cond2_lo, cond2_hi]` is proven ([`certify`]); false where a bracket end
    /// rests on a Cholesky test that *failed* (the saddle-point route's inertia counts).
    pub bounds_proven: bool,
    /// Largest singular value (estimate).
    pub sigma_max: f64,
    /// Smallest singular value (estimate).
    pub sigma_min: f64,
    /// Route taken.
    pub route: CondRoute,
    /// Brackets of σ_max and σ_min (the certified routes).
    pub certificate: Option<sparse::Certificate>,
    /// `log10|det A|` when the route factorized A itself (sparse SPD route: free by-product,
    /// so the metrics do not factorize A again).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub log10_det: Option<f64>,
    /// The stored matrix's asymmetry where it is not exactly symmetric but was certified
    /// through its symmetric part ([`Symmetry::Near`], [`cond2`]): the bracket is widened
    /// for it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub asymmetry: Option<Asymmetry>,
}

impl CondReport {
    /// The report of a certified route: estimates `sigma_max`, `sigma_min` (already inside
    /// the certificate's brackets) and cond₂'s bounds from the brackets, rounded outwards.
    pub fn with_certificate(
        sigma_max: f64,
        sigma_min: f64,
        route: CondRoute,
        certificate: sparse::Certificate,
        bounds_proven: bool,
        log10_det: Option<f64>,
    ) -> Self {
        let (lo, hi) = certificate.cond2_bounds();
        CondReport {
            cond2: ratio(sigma_max, sigma_min),
            cond2_lo: lo,
            cond2_hi: hi,
            bounds_proven,
            sigma_max,
            sigma_min,
            route,
            certificate: Some(certificate),
            log10_det,
            asymmetry: None,
        }
    }

    /// The contract's tolerance at cond₂ = `cond`: `max(1e-12, 4·ε_mach·cond)` relative.
    pub fn contract_tol(cond: f64) -> f64 {
        (4.0 * f64::EPSILON * cond).max(1e-12)
    }

    /// Whether the reported `cond2` is *proven* within the accuracy contract of the exact
    /// value: the bounds are proven and every value they allow is within
    /// `max(1e-12, 4·ε_mach·cond₂)` of `cond2` — i.e. `(cond2 − lo)/lo` and `(hi − cond2)/hi`
    /// are both within the tolerance at `lo`. False where a bracket is unproven or wider
    /// (the point may still be right; it is not proven to be).
    pub fn within_contract(&self) -> bool {
        let (c, lo, hi) = (self.cond2, self.cond2_lo, self.cond2_hi);
        if !(self.bounds_proven && lo > 0.0 && hi.is_finite() && lo <= c && c <= hi) {
            return false;
        }
        let tol = Self::contract_tol(lo);
        (c - lo) / lo <= tol && (hi - c) / hi <= tol
    }

    /// `(cond2_bounds_proven, cond2_within_contract)` of a row that reports the cond₂ values
    /// `reports` (K's, the system's): each the conjunction over the reports present, `None`
    /// where none is.
    pub fn flags<'a>(
        reports: impl IntoIterator<Item = Option<&'a CondReport>>,
    ) -> (Option<bool>, Option<bool>) {
        reports
            .into_iter()
            .flatten()
            .fold((None, None), |(p, w), r| {
                (
                    Some(p.unwrap_or(true) && r.bounds_proven),
                    Some(w.unwrap_or(true) && r.within_contract()),
                )
            })
    }

    /// The largest relative error of `cond2` that its bounds allow (`+∞` where unbounded):
    /// the width that [`CondReport::within_contract`] judges.
    pub fn error_bound(&self) -> f64 {
        let (c, lo, hi) = (self.cond2, self.cond2_lo, self.cond2_hi);
        if !(lo > 0.0 && hi.is_finite()) {
            return f64::INFINITY;
        }
        ((c - lo) / lo).max((hi - c) / hi).max(0.0)
    }

    /// Where the bracket is not proven (the saddle route's ends resting on a failed Cholesky
    /// test) and the value finite: a warning that `name`'s cond₂ is an estimate, naming the
    /// route and the bracket.
    pub fn unproven_caveat(&self, name: &str) -> Option<String> {
        (!self.bounds_proven && self.cond2.is_finite()).then(|| {
            format!(
                "cond2 of {name} ≈ {:.3e} is an estimate, not proven within the contract: route \
                 {}, bracket [{:.3e}, {:.3e}] not proven (an end rests on a failed Cholesky test)",
                self.cond2,
                self.route.name(),
                self.cond2_lo,
                self.cond2_hi
            )
        })
    }

    /// Where σ_min could not be bounded away from 0 (`cond2_hi = ∞`): a warning that `name` may
    /// be singular, with the estimate, the bracket and the route.
    pub fn singular_caveat(&self, name: &str) -> Option<String> {
        (!self.cond2_hi.is_finite()).then(|| {
            format!(
                "{name} may be singular: σ_min could not be bounded away from 0 (cond2 ≈ {:.3e}, \
                 bracket [{:.3e}, ∞], route {})",
                self.cond2,
                self.cond2_lo,
                self.route.name()
            )
        })
    }

    /// Relative width `cond2_hi / cond2_lo − 1` of the bounds (+∞ where unbounded).
    pub fn relative_width(&self) -> f64 {
        if self.cond2_lo > 0.0 {
            self.cond2_hi / self.cond2_lo - 1.0
        } else {
            f64::INFINITY
        }
    }
}

/// `a / b`, +∞ where b = 0.
fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 {
        a / b
    } else {
        f64::INFINITY
    }
}

pub use crate::route::DENSIFY_LIMIT;

/// Exact cond₂ of a [`Stiffness`] by the cheapest exact route for its *structure*, whatever
/// its storage (see module docs): a symmetric matrix that
/// [`crate::route::Structure::cond_plan`] sends to the sparse route (a dense-stored one
/// is converted first, exactly), anything else to the dense routes (a sparse-stored one is
/// densified, up to [`DENSIFY_LIMIT`]). A sparse-route matrix that turns out indefinite falls
/// back to the dense routes too.
pub fn cond2(a: &Stiffness) -> Result<CondReport> {
    cond2_warm(a, Reuse::default()).map(|(r, _)| r)
}

/// What a cond₂ may reuse from work already done ([`cond2_warm`]); nothing by default.
#[derive(Clone, Copy, Debug, Default)]
pub struct Reuse<'a> {
    /// Ritz vectors of a nearby matrix (e.g. K for `K + D E Dᵀ`) to start Lanczos from.
    pub starts: Option<&'a sparse::RitzStarts>,
    /// A sparse Cholesky factor of this very matrix (e.g. the solver's last one): the λ_min
    /// Lanczos run solves with it and `log10 det` is read off it, instead of a new factor.
    pub factor: Option<&'a Factorization>,
    /// Return the Ritz vectors of this matrix (sparse SPD route, `n ≤`
    /// [`sparse::RITZ_VECTOR_MAX_N`]).
    pub keep_ritz: bool,
    /// Relative accuracy asked of the value (`None`: the contract): the SPD routes stop their
    /// Lanczos runs at a stagnation of tol/8 (never below their defaults). The bounds are
    /// proven whatever the tolerance; the dense and saddle routes always run to the contract.
    pub tol: Option<f64>,
    /// Run the two ends of the sparse SPD route one after the other even where they would
    /// run side by side ([`sparse::SIDE_BY_SIDE_ENDS_MIN_N`]): one factor alive at a time,
    /// one thread; the same result bit for bit.
    pub sequential_ends: bool,
    /// The caller knows the matrix is symmetric bit for bit (a solve's `K + D E Dᵀ` with K
    /// exactly symmetric and `D E Dᵀ` on the diagonal, as a solution hands it on): its
    /// symmetry is not checked again (debug builds still check). A wrong claim certifies the
    /// cond₂ of the wrong operator.
    pub exactly_symmetric: bool,
}

impl Reuse<'_> {
    /// Nothing to reuse, but return the Ritz vectors (of K, for its systems to start from).
    pub fn keeping_ritz() -> Self {
        Reuse {
            keep_ritz: true,
            ..Reuse::default()
        }
    }
}

/// [`cond2`] reusing earlier work: the sparse SPD route starts its Lanczos runs from
/// `reuse.starts` (fewer steps, same certified result), solves with `reuse.factor` where it
/// is a sparse Cholesky of `a` (one factorization fewer), and with `reuse.keep_ritz` also
/// returns the Ritz vectors of `a`.
///
/// A matrix whose largest entry lies outside [2⁻¹⁰⁰, 2¹⁰⁰] is first multiplied by a power of two
/// that brings it near 1 ([`prescale`]; exact, unless an entry would leave the normal range,
/// where it is left as it is): cond₂ is scale-free, the routes' margins are not. Its cond₂,
/// bounds and route are then its unscaled twin's; the σ's, brackets and log-det are scaled back.
pub fn cond2_warm(
    a: &Stiffness,
    reuse: Reuse<'_>,
) -> Result<(CondReport, Option<sparse::RitzStarts>)> {
    // A factor of `a` itself cannot serve the scaled matrix: the caller's scale is kept.
    match prescale(a).filter(|_| reuse.factor.is_none()) {
        Some((scaled, k)) => {
            let (r, ritz) = cond2_warm_at_scale(&scaled, reuse)?;
            Ok((r.unscaled(k, a.n()), ritz))
        }
        None => cond2_warm_at_scale(a, reuse),
    }
}

/// [`cond2_warm`] at the matrix's own scale.
fn cond2_warm_at_scale(
    a: &Stiffness,
    reuse: Reuse<'_>,
) -> Result<(CondReport, Option<sparse::RitzStarts>)> {
    let symmetry = if reuse.exactly_symmetric {
        debug_assert!(
            a.is_symmetric(),
            "Reuse::exactly_symmetric on an unsymmetric matrix"
        );
        Symmetry::Exact
    } else {
        a.symmetry()
    };
    if let Symmetry::Near(asym) = symmetry {
        return cond2_near_symmetric(a, asym, reuse);
    }
    cond2_routes(a, symmetry == Symmetry::Exact, reuse)
}

/// The routes of [`cond2_warm`] for a matrix that is exactly symmetric (`symmetric`) or not
/// symmetric at all.
pub(super) fn cond2_routes(
    a: &Stiffness,
    symmetric: bool,
    reuse: Reuse<'_>,
) -> Result<(CondReport, Option<sparse::RitzStarts>)> {
    let structure = a.structure();
    if structure.cond_plan(symmetric) == CondPlan::SparseSpd {
        let converted;
        let m = match a {
            Stiffness::Sparse(m) => m,
            Stiffness::Dense(_) => {
                converted = a.clone().in_preferred_storage();
                match &converted {
                    Stiffness::Sparse(m) => m,
                    Stiffness::Dense(_) => unreachable!("prefers_sparse converts"),
                }
            }
        };
        match cond2_sparse_spd_warm(m, reuse) {
            Ok(r) => return Ok(r),
            // Not positive definite (e.g. a saddle-point matrix): the dense routes below.
            Err(Error::Singular(_)) => {}
            // A numerical failure of the certified route (its Lanczos estimates not usable):
            // the dense routes below where the size allows — a valid matrix is not refused.
            Err(Error::Numerical(_)) if structure.densify_allowed() => {}
            Err(e) => return Err(e),
        }
    }
    match a {
        Stiffness::Dense(m) => Ok((cond2_dense(m.as_ref(), symmetric)?, None)),
        Stiffness::Sparse(_) => {
            if !structure.densify_allowed() {
                return Err(Error::unsupported(
                    format!("exact cond₂ of a sparse {n}×{n} matrix", n = a.n()),
                    format!("densifying, which is limited to n ≤ {DENSIFY_LIMIT}"),
                ));
            }
            let mut r = cond2_dense(a.to_dense().as_ref(), symmetric)?;
            r.route = match r.route {
                CondRoute::SymmetricEigen => CondRoute::DensifiedSymmetricEigen,
                CondRoute::Svd => CondRoute::DensifiedSvd,
                other => other,
            };
            Ok((r, None))
        }
    }
}

/// Exact cond₂ of a sparse SPD matrix by the [`sparse`] route (Lanczos estimates certified by
/// inertia counts), without densifying. Errors with [`Error::Singular`] if A is not positive
/// definite.
pub fn cond2_sparse_spd(a: &faer::sparse::SparseColMat<usize, f64>) -> Result<CondReport> {
    cond2_sparse_spd_warm(a, Reuse::default()).map(|(r, _)| r)
}

fn cond2_sparse_spd_warm(
    a: &faer::sparse::SparseColMat<usize, f64>,
    reuse: Reuse<'_>,
) -> Result<(CondReport, Option<sparse::RitzStarts>)> {
    let s = sparse::extreme_eigenvalues(a, sparse::MAX_LANCZOS_STEPS, reuse)?;
    let report = CondReport::with_certificate(
        s.lambda_max,
        s.lambda_min,
        CondRoute::SparseInertia,
        s.certificate,
        true,
        Some(s.log10_det),
    );
    Ok((report, s.ritz))
}

/// `log10|det A|` read off the factorization a cond₂ route already made of A (`cond`'s
/// `log10_det`, the sparse SPD route), else [`log10_abs_det`]: the determinant never costs a
/// second factorization of a matrix whose cond₂ was taken.
pub fn log10_abs_det_after(a: &Stiffness, cond: Option<&CondReport>) -> Result<f64> {
    match cond.and_then(|c| c.log10_det) {
        Some(v) => Ok(v),
        None => log10_abs_det(a),
    }
}

/// `log10|det A|` from a factorization; `-∞` when A is singular to working precision.
pub fn log10_abs_det(a: &Stiffness) -> Result<f64> {
    let symmetric = a.is_symmetric();
    match Factorization::new(a, symmetric) {
        Ok(f) => match f.log10_abs_det() {
            Some(v) => Ok(v),
            // Sparse LU does not expose its pivots: fall back to a dense LU.
            None => log10_abs_det_dense_lu(a),
        },
        Err(Error::Singular(_)) => Ok(f64::NEG_INFINITY),
        Err(e) => Err(e),
    }
}

/// `log10|det A|` of the saddle-point matrix `A = [K D; Dᵀ 0]` with Boolean D selecting the
/// distinct DOFs `dofs` (B), without factorizing A: ordering the unknowns (F, B, multipliers),
///
/// `A = [K_FF K_FB 0; K_BF K_BB I; 0 I 0]`, and eliminating the identity blocks leaves
/// `|det A| = det K_FF` (F: the unconstrained DOFs),
///
/// so one Cholesky of K_FF (sparse where K is) replaces an LU of the indefinite (N+m)×(N+m)
/// matrix. `-∞` where K_FF is singular; an error for repeated or out-of-range DOFs.
pub fn log10_abs_det_saddle(k: &Stiffness, dofs: &[usize]) -> Result<f64> {
    let n = k.n();
    let constrained =
        saddle::dof_mask(n, dofs).map_err(|d| saddle::dof_error("saddle determinant", n, d))?;
    let free: Vec<usize> = (0..n).filter(|&i| !constrained[i]).collect();
    if free.is_empty() {
        return Ok(0.0); // |det [0 I; I 0]| = 1
    }
    let mut index = vec![usize::MAX; n];
    for (new, &old) in free.iter().enumerate() {
        index[old] = new;
    }
    let kff = match k {
        Stiffness::Dense(m) => {
            Stiffness::Dense(faer::Mat::from_fn(free.len(), free.len(), |i, j| {
                m[(free[i], free[j])]
            }))
        }
        Stiffness::Sparse(_) => {
            let mut t = Vec::with_capacity(k.nnz());
            k.for_each_entry(|i, j, v| {
                if index[i] != usize::MAX && index[j] != usize::MAX {
                    t.push((index[i], index[j], v));
                }
            });
            Stiffness::from_triplets(free.len(), &t)?
        }
    };
    log10_abs_det(&kff)
}

fn log10_abs_det_dense_lu(a: &Stiffness) -> Result<f64> {
    if let Stiffness::Sparse(m) = a {
        return log10_abs_det_sparse_lu(m);
    }
    let d = a.to_dense();
    let lu = d.partial_piv_lu();
    Ok((0..a.n()).map(|i| lu.U()[(i, i)].abs().log10()).sum())
}

/// `log10|det A| = Σ log10|U_jj|` from a simplicial sparse LU with COLAMD column ordering and
/// partial row pivoting (faer's supernodal LU does not expose U's diagonal). Memory
/// O(nnz(L + U)); `-∞` if a pivot is exactly zero.
pub fn log10_abs_det_sparse_lu(a: &faer::sparse::SparseColMat<usize, f64>) -> Result<f64> {
    use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
    use faer::sparse::linalg::{colamd, lu::simplicial};
    let n = a.nrows();
    let sym = a.symbolic();
    let mut perm = vec![0usize; n];
    let mut perm_inv = vec![0usize; n];
    let mut mem = MemBuffer::new(colamd::order_scratch::<usize>(n, n, sym.compute_nnz()));
    colamd::order(
        &mut perm,
        &mut perm_inv,
        sym,
        Default::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| Error::Numerical(format!("COLAMD ordering failed: {e:?}")))?;
    let col_perm = faer::perm::PermRef::new_checked(&perm, &perm_inv, n);
    let mut row_perm = vec![0usize; n];
    let mut row_perm_inv = vec![0usize; n];
    let mut lu = simplicial::SimplicialLu::<usize, f64>::new();
    let mut mem = MemBuffer::new(StackReq::any_of(&[
        simplicial::factorize_simplicial_numeric_lu_scratch::<usize, f64>(n, n),
    ]));
    match simplicial::factorize_simplicial_numeric_lu(
        &mut row_perm,
        &mut row_perm_inv,
        &mut lu,
        a.as_ref(),
        col_perm,
        MemStack::new(&mut mem),
    ) {
        Ok(()) => {}
        Err(faer::sparse::linalg::LuError::SymbolicSingular { .. }) => {
            return Ok(f64::NEG_INFINITY)
        }
        Err(e) => return Err(Error::Numerical(format!("sparse LU failed: {e:?}"))),
    }
    let u = lu.u_factor_unsorted();
    let (cp, ri, v) = (u.symbolic().col_ptr(), u.symbolic().row_idx(), u.val());
    let mut sum = 0.0;
    for j in 0..n {
        let d = (cp[j]..cp[j + 1])
            .find(|&p| ri[p] == j)
            .map(|p| v[p])
            .unwrap_or(0.0);
        sum += d.abs().log10();
    }
    Ok(sum)
}

/// Independent reference implementations for cross-checks.
///
/// Nothing here is used by the library's own metrics: these functions recompute the same
/// quantities with other libraries (nalgebra always; LAPACK through `nalgebra-lapack`, linked
/// to the system OpenBLAS, behind the `lapack` feature) so that `tests/cross_check.rs` can
/// compare them with [`cond2`] and [`log10_abs_det`]. They densify their input and panic when
/// LAPACK reports a failure, which is what a test wants.
///
/// The LAPACK routes are `dgesdd` (`nalgebra_lapack::SVD`), `dsyev`
/// (`nalgebra_lapack::SymmetricEigen::try_new`) and `dgetrf` (`nalgebra_lapack::LU`).
/// nalgebra-lapack 0.28's values-only `SymmetricEigen::eigenvalues` passes an invalid `jobz`
/// to DSYEV and panics, so the eigenvalues come from the full decomposition.
pub mod reference {
    use crate::dd::Dd;
    use crate::system::Stiffness;

    // `lapack-custom`: nalgebra-lapack only declares the Fortran symbols; the system OpenBLAS
    // (libopenblas-dev) provides them.
    #[cfg(feature = "lapack")]
    #[link(name = "openblas")]
    extern "C" {}

    /// `max |x| / min |x|` (+∞ if the minimum is 0).
    fn abs_ratio(x: &[f64]) -> f64 {
        let max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let min = x.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
        max / min
    }

    /// `(λ_max, λ_min)` of a symmetric `a` by bisection with inertia counts in double-double
    /// arithmetic ([`crate::dd`], ≈ 32 digits), to ≈ 1e-25 relative: the high-precision
    /// reference of `tests/properties/cond_properties.rs` and of the `cond_accuracy` study, independent
    /// of every cond₂ route. Sylvester's law: the number of eigenvalues below σ is the number
    /// of negative pivots of LDLᵀ of `A − σI` (no pivoting; fill stays in the band of `a`'s
    /// natural ordering, so one count costs n·b² double-double operations for half-bandwidth
    /// b). Densifies `a` (n² memory); meant for n up to a few thousand with a modest band.
    pub fn extreme_eigenvalues_dd(a: &Stiffness) -> (f64, f64) {
        let n = a.n();
        let d = a.to_dense();
        let m: Vec<f64> = (0..n * n).map(|k| d[(k / n, k % n)]).collect();
        (eigenvalue_dd(n, &m, n - 1), eigenvalue_dd(n, &m, 0))
    }

    /// Number of eigenvalues of the symmetric row-major `a` below σ: the negative pivots of
    /// LDLᵀ of `A − σI` without pivoting, in double-double, within half-bandwidth `bw`.
    fn count_below(n: usize, a: &[f64], bw: usize, sigma: Dd) -> usize {
        let w = bw + 1;
        let mut l = vec![Dd::ZERO; n * w];
        let mut d = vec![Dd::ZERO; n];
        let mut negative = 0;
        for i in 0..n {
            let lo = i.saturating_sub(bw);
            for j in lo..=i {
                // l_ij d_j = a_ij − Σ_{k<j} l_ik d_k l_jk
                let mut s = Dd::from_f64(a[i * n + j]);
                if i == j {
                    s = s - sigma;
                }
                for k in lo.max(j.saturating_sub(bw))..j {
                    s = s - l[i * w + (k + bw - i)] * d[k] * l[j * w + (k + bw - j)];
                }
                if i == j {
                    if s.hi == 0.0 {
                        s = Dd::from_f64(-f64::MIN_POSITIVE);
                    }
                    d[i] = s;
                    if s.hi < 0.0 {
                        negative += 1;
                    }
                } else {
                    l[i * w + (j + bw - i)] = s / d[j];
                }
            }
        }
        negative
    }

    /// The k-th smallest eigenvalue of the symmetric row-major `a` by bisection on
    /// [`count_below`] from the Gershgorin interval (geometric while the ends differ by more
    /// than 4×), to ≈ 1e-25 relative.
    fn eigenvalue_dd(n: usize, a: &[f64], k: usize) -> f64 {
        let bw = (0..n)
            .flat_map(|i| {
                (0..i)
                    .filter(move |&j| a[i * n + j] != 0.0)
                    .map(move |j| i - j)
            })
            .max()
            .unwrap_or(0);
        let radius = |i: usize| {
            (0..n)
                .filter(|&j| j != i)
                .map(|j| a[i * n + j].abs())
                .sum::<f64>()
        };
        let gersh_lo = (0..n)
            .map(|i| a[i * n + i] - radius(i))
            .fold(f64::INFINITY, f64::min);
        let gersh_hi = (0..n)
            .map(|i| a[i * n + i] + radius(i))
            .fold(f64::NEG_INFINITY, f64::max);
        let mut lo = Dd::from_f64(gersh_lo - gersh_lo.abs().max(1.0));
        let mut hi = Dd::from_f64(gersh_hi + gersh_hi.abs().max(1.0));
        // Where the wanted eigenvalue is positive, start from a positive lower end so that the
        // bisection can be geometric (λ_min of an SPD matrix may lie many decades below ‖A‖).
        let mut pos = Dd::from_f64(f64::MIN_POSITIVE.sqrt());
        if count_below(n, a, bw, pos) <= k {
            while pos.hi < hi.hi && count_below(n, a, bw, pos * Dd::from_f64(1e8)) <= k {
                pos = pos * Dd::from_f64(1e8);
            }
            lo = pos;
        }
        for _ in 0..600 {
            let mid = if lo.hi > 0.0 && hi.hi / lo.hi > 4.0 {
                Dd::from_f64((lo.hi * hi.hi).sqrt())
            } else {
                (lo + hi) * Dd::from_f64(0.5)
            };
            if count_below(n, a, bw, mid) > k {
                hi = mid;
            } else {
                lo = mid;
            }
            if (hi - lo).hi <= 1e-25 * hi.hi.abs().max(lo.hi.abs()) {
                break;
            }
        }
        ((lo + hi) * Dd::from_f64(0.5)).to_f64()
    }

    /// cond₂ from nalgebra's SVD (singular values only).
    pub fn cond2_nalgebra(a: &Stiffness) -> f64 {
        let sv = a.to_nalgebra().singular_values();
        abs_ratio(sv.as_slice())
    }

    /// cond₂ = max|λ| / min|λ| from nalgebra's symmetric eigenvalues (lower triangle read).
    /// Only meaningful for a symmetric `a`.
    pub fn cond2_nalgebra_symmetric(a: &Stiffness) -> f64 {
        let ev = a.to_nalgebra().symmetric_eigenvalues();
        abs_ratio(ev.as_slice())
    }

    /// log10|det| from nalgebra's LU.
    pub fn log10_abs_det_nalgebra(a: &Stiffness) -> f64 {
        let n = a.n();
        let lu = a.to_nalgebra().lu();
        let u = lu.u();
        (0..n).map(|i| u[(i, i)].abs().log10()).sum()
    }

    /// Singular values (nonincreasing) from LAPACK `dgesdd` (`nalgebra_lapack::SVD`).
    #[cfg(feature = "lapack")]
    pub fn singular_values_lapack(a: &Stiffness) -> Vec<f64> {
        let svd = nalgebra_lapack::SVD::new(a.to_nalgebra()).expect("dgesdd failed");
        svd.singular_values.as_slice().to_vec()
    }

    /// cond₂ from LAPACK `dgesdd`, system OpenBLAS.
    #[cfg(feature = "lapack")]
    pub fn cond2_lapack(a: &Stiffness) -> f64 {
        abs_ratio(&singular_values_lapack(a))
    }

    /// Eigenvalues (nondecreasing) of a symmetric matrix from LAPACK `dsyev`
    /// (`nalgebra_lapack::SymmetricEigen`), lower triangle read.
    #[cfg(feature = "lapack")]
    pub fn symmetric_eigenvalues_lapack(a: &Stiffness) -> Vec<f64> {
        let eig = nalgebra_lapack::SymmetricEigen::try_new(a.to_nalgebra())
            .expect("dsyev did not converge");
        let mut w = eig.eigenvalues.as_slice().to_vec();
        w.sort_by(f64::total_cmp);
        w
    }

    /// cond₂ = max|λ| / min|λ| from LAPACK `dsyev`. Only meaningful for a
    /// symmetric `a`.
    #[cfg(feature = "lapack")]
    pub fn cond2_lapack_symmetric(a: &Stiffness) -> f64 {
        abs_ratio(&symmetric_eigenvalues_lapack(a))
    }

    /// log10|det| from LAPACK's partial-pivoting LU (`dgetrf`, `nalgebra_lapack::LU`):
    /// `Σ log10|U_ii|`
    /// (−∞ for an exactly singular matrix).
    #[cfg(feature = "lapack")]
    pub fn log10_abs_det_lapack(a: &Stiffness) -> f64 {
        let n = a.n();
        let lu = nalgebra_lapack::LU::new(a.to_nalgebra());
        let u = lu.u();
        // An exactly zero U_ii (dgetrf's info > 0) gives −∞.
        (0..n).map(|i| u[(i, i)].abs().log10()).sum()
    }
}
