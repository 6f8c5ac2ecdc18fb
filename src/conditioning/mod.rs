//! Exact 2-norm condition numbers and log-determinants.
//!
//! `cond₂(A) = σ_max(A) / σ_min(A)`, computed exactly (to rounding) by the cheapest exact
//! route for the matrix at hand, and the route is recorded:
//!
//! | matrix | route | cost |
//! |---|---|---|
//! | dense symmetric | eigenvalues, `σ_i = |λ_i|` ([`CondRoute::SymmetricEigen`]) | ≈ 4/3 n³ |
//! | dense unsymmetric | singular values ([`CondRoute::Svd`]) | ≈ 3–4× the eigen route |
//! | sparse SPD | Lanczos + inertia certificate ([`CondRoute::SparseInertia`], [`sparse`]) | a few sparse Cholesky |
//! | sparse saddle point `[K D; Dᵀ 0]`, Boolean D | block-structure inertia ([`CondRoute::SparseSaddleInertia`], [`saddle`]) | a few sparse Cholesky |
//! | other sparse | densified, then as above ([`CondRoute::DensifiedSymmetricEigen`] / [`CondRoute::DensifiedSvd`]) | n² memory |
//!
//! `log10|det A|` is read off a factorization (never the raw determinant, which overflows at
//! n ≈ 1600): the determinant ratio of the paper is `log10|det(K+DEDᵀ)| − log10|det K|`.
//!
//! The [`reference`](mod@reference) module recomputes cond₂ with nalgebra (and LAPACK behind the `lapack`
//! feature) as an independent cross-check.

pub mod saddle;
pub mod sparse;

use crate::error::{Error, Result};
use crate::linalg::Factorization;
use crate::system::Stiffness;
use faer::{MatRef, Side};
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
        }
    }
}

/// An exact 2-norm condition number with the extreme singular values and the route taken.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct CondReport {
    /// `σ_max / σ_min` (+∞ if σ_min = 0).
    pub cond2: f64,
    /// Largest singular value.
    pub sigma_max: f64,
    /// Smallest singular value.
    pub sigma_min: f64,
    /// Route taken.
    pub route: CondRoute,
    /// Inertia brackets of λ_max and λ_min (sparse route only).
    pub certificate: Option<sparse::Certificate>,
    /// `log10|det A|` when the route factorized A itself (sparse SPD route: free by-product,
    /// so the metrics do not factorize A again).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub log10_det: Option<f64>,
}

/// Largest dimension for which a sparse matrix is densified to get an exact condition number.
pub const DENSIFY_LIMIT: usize = 6000;

/// Exact cond₂ of a dense matrix; `symmetric` selects the eigenvalue route.
pub fn cond2_dense(a: MatRef<'_, f64>, symmetric: bool) -> Result<CondReport> {
    let (smax, smin, route) = if symmetric {
        let ev = a
            .self_adjoint_eigenvalues(Side::Lower)
            .map_err(|e| Error::Numerical(format!("symmetric eigenvalues failed: {e:?}")))?;
        let smax = ev.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let smin = ev.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
        (smax, smin, CondRoute::SymmetricEigen)
    } else {
        let sv = a
            .singular_values()
            .map_err(|e| Error::Numerical(format!("singular values failed: {e:?}")))?;
        let smax = sv.first().copied().unwrap_or(0.0);
        let smin = sv.last().copied().unwrap_or(0.0);
        (smax, smin, CondRoute::Svd)
    };
    if !(smax.is_finite() && smin.is_finite()) {
        return Err(Error::Numerical(
            "singular values are not finite (matrix contains NaN/Inf?)".into(),
        ));
    }
    let cond2 = if smin > 0.0 {
        smax / smin
    } else {
        f64::INFINITY
    };
    Ok(CondReport {
        cond2,
        sigma_max: smax,
        sigma_min: smin,
        route,
        certificate: None,
        log10_det: None,
    })
}

/// Exact cond₂ of a [`Stiffness`] by the cheapest exact route (see module docs).
pub fn cond2(a: &Stiffness) -> Result<CondReport> {
    let symmetric = a.is_symmetric();
    match a {
        Stiffness::Dense(m) => cond2_dense(m.as_ref(), symmetric),
        Stiffness::Sparse(m) => {
            if symmetric && a.n() >= sparse::SPARSE_ROUTE_MIN_N {
                match cond2_sparse_spd(m) {
                    Ok(r) => return Ok(r),
                    // Not positive definite (e.g. a saddle-point matrix): densify below.
                    Err(Error::Singular(_)) => {}
                    Err(e) => return Err(e),
                }
            }
            if a.n() > DENSIFY_LIMIT {
                return Err(Error::input(format!(
                    "exact cond₂ of a sparse {n}×{n} matrix needs densifying, which is limited \
                     to n ≤ {DENSIFY_LIMIT}",
                    n = a.n()
                )));
            }
            let mut r = cond2_dense(a.to_dense().as_ref(), symmetric)?;
            r.route = if symmetric {
                CondRoute::DensifiedSymmetricEigen
            } else {
                CondRoute::DensifiedSvd
            };
            Ok(r)
        }
    }
}

/// Exact cond₂ of a sparse SPD matrix by the [`sparse`] route (Lanczos estimates certified by
/// inertia counts), without densifying. Errors with [`Error::Singular`] if A is not positive
/// definite.
pub fn cond2_sparse_spd(a: &faer::sparse::SparseColMat<usize, f64>) -> Result<CondReport> {
    let s = sparse::extreme_eigenvalues(a, sparse::MAX_LANCZOS_STEPS)?;
    Ok(CondReport {
        cond2: s.lambda_max / s.lambda_min,
        sigma_max: s.lambda_max,
        sigma_min: s.lambda_min,
        route: CondRoute::SparseInertia,
        certificate: Some(s.certificate),
        log10_det: Some(s.log10_det),
    })
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
/// quantities with other libraries (nalgebra always; LAPACK — the system OpenBLAS, linked
/// directly — behind the `lapack` feature) so that `tests/cross_check.rs` can compare them
/// with [`cond2`] and [`log10_abs_det`]. They densify their input and panic on a LAPACK error
/// (`info ≠ 0`), which is what a test wants.
///
/// nalgebra-lapack 0.28's `SymmetricEigen::eigenvalues()` panics (it passes an invalid `jobz`
/// to DSYEV) and its `SVD::new` always computes U and Vᵀ, so the LAPACK routes call the
/// `lapack` crate's `dgesdd` / `dsyevd` / `dgetrf` directly, values only.
pub mod reference {
    use crate::system::Stiffness;

    // The `lapack` crate only declares the Fortran symbols: link the system OpenBLAS
    // (libopenblas-dev), which provides them.
    #[cfg(feature = "lapack")]
    #[link(name = "openblas")]
    extern "C" {}

    fn to_nalgebra(a: &Stiffness) -> nalgebra::DMatrix<f64> {
        let n = a.n();
        let mut m = nalgebra::DMatrix::<f64>::zeros(n, n);
        a.for_each_entry(|i, j, v| m[(i, j)] += v);
        m
    }

    /// `max |x| / min |x|` (+∞ if the minimum is 0).
    fn abs_ratio(x: &[f64]) -> f64 {
        let max = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let min = x.iter().fold(f64::INFINITY, |m, v| m.min(v.abs()));
        max / min
    }

    /// cond₂ from nalgebra's SVD (singular values only).
    pub fn cond2_nalgebra(a: &Stiffness) -> f64 {
        let sv = to_nalgebra(a).singular_values();
        abs_ratio(sv.as_slice())
    }

    /// cond₂ = max|λ| / min|λ| from nalgebra's symmetric eigenvalues (lower triangle read).
    /// Only meaningful for a symmetric `a`.
    pub fn cond2_nalgebra_symmetric(a: &Stiffness) -> f64 {
        let ev = to_nalgebra(a).symmetric_eigenvalues();
        abs_ratio(ev.as_slice())
    }

    /// log10|det| from nalgebra's LU.
    pub fn log10_abs_det_nalgebra(a: &Stiffness) -> f64 {
        let n = a.n();
        let lu = to_nalgebra(a).lu();
        let u = lu.u();
        (0..n).map(|i| u[(i, i)].abs().log10()).sum()
    }

    /// Dense column-major copy and its order as a LAPACK integer.
    #[cfg(feature = "lapack")]
    fn to_lapack(a: &Stiffness) -> (Vec<f64>, i32) {
        let n = a.n();
        let mut m = vec![0.0f64; n * n];
        a.for_each_entry(|i, j, v| m[i + j * n] += v);
        let ni = i32::try_from(n).expect("matrix too large for LAPACK's 32-bit integers");
        (m, ni)
    }

    /// Singular values (nonincreasing) from LAPACK `dgesdd` with `jobz = 'N'`.
    #[cfg(feature = "lapack")]
    pub fn singular_values_lapack(a: &Stiffness) -> Vec<f64> {
        let (mut m, ni) = to_lapack(a);
        let n = a.n();
        let mut s = vec![0.0; n];
        let mut iwork = vec![0i32; 8 * n];
        let mut info = 0;
        let mut u = [0.0f64; 1];
        let mut vt = [0.0f64; 1];
        let mut wq = [0.0f64; 1];
        // SAFETY: every slice is at least as long as LAPACK reads/writes for these arguments
        // (a: n·n with lda = n, s: n, iwork: 8n; u/vt are not referenced for jobz = 'N').
        unsafe {
            lapack::dgesdd(
                b'N', ni, ni, &mut m, ni, &mut s, &mut u, 1, &mut vt, 1, &mut wq, -1, &mut iwork,
                &mut info,
            );
        }
        assert_eq!(info, 0, "dgesdd workspace query failed with info = {info}");
        let lwork = (wq[0] as i32).max(1);
        let mut work = vec![0.0; lwork as usize];
        // SAFETY: as above, with work of the queried length.
        unsafe {
            lapack::dgesdd(
                b'N', ni, ni, &mut m, ni, &mut s, &mut u, 1, &mut vt, 1, &mut work, lwork,
                &mut iwork, &mut info,
            );
        }
        assert_eq!(info, 0, "dgesdd failed with info = {info}");
        s
    }

    /// cond₂ from LAPACK `dgesdd` (values only), system OpenBLAS.
    #[cfg(feature = "lapack")]
    pub fn cond2_lapack(a: &Stiffness) -> f64 {
        abs_ratio(&singular_values_lapack(a))
    }

    /// Eigenvalues (nondecreasing) of a symmetric matrix from LAPACK `dsyevd` with
    /// `jobz = 'N'`, lower triangle read.
    #[cfg(feature = "lapack")]
    pub fn symmetric_eigenvalues_lapack(a: &Stiffness) -> Vec<f64> {
        let (mut m, ni) = to_lapack(a);
        let n = a.n();
        let mut w = vec![0.0; n];
        let mut info = 0;
        let mut wq = [0.0f64; 1];
        let mut iwq = [0i32; 1];
        // SAFETY: a is n·n with lda = n, w has n entries; lwork = liwork = -1 is a workspace
        // query that writes one entry of work and iwork.
        unsafe {
            lapack::dsyevd(
                b'N', b'L', ni, &mut m, ni, &mut w, &mut wq, -1, &mut iwq, -1, &mut info,
            );
        }
        assert_eq!(info, 0, "dsyevd workspace query failed with info = {info}");
        let lwork = (wq[0] as i32).max(1);
        let liwork = iwq[0].max(1);
        let mut work = vec![0.0; lwork as usize];
        let mut iwork = vec![0i32; liwork as usize];
        // SAFETY: as above, with work/iwork of the queried lengths.
        unsafe {
            lapack::dsyevd(
                b'N', b'L', ni, &mut m, ni, &mut w, &mut work, lwork, &mut iwork, liwork, &mut info,
            );
        }
        assert_eq!(info, 0, "dsyevd failed with info = {info}");
        w
    }

    /// cond₂ = max|λ| / min|λ| from LAPACK `dsyevd` (values only). Only meaningful for a
    /// symmetric `a`.
    #[cfg(feature = "lapack")]
    pub fn cond2_lapack_symmetric(a: &Stiffness) -> f64 {
        abs_ratio(&symmetric_eigenvalues_lapack(a))
    }

    /// log10|det| from LAPACK's partial-pivoting LU (`dgetrf`): `Σ log10|U_ii|`
    /// (−∞ for an exactly singular matrix).
    #[cfg(feature = "lapack")]
    pub fn log10_abs_det_lapack(a: &Stiffness) -> f64 {
        let (mut m, ni) = to_lapack(a);
        let n = a.n();
        let mut ipiv = vec![0i32; n];
        let mut info = 0;
        // SAFETY: a is n·n with lda = n, ipiv has n entries.
        unsafe {
            lapack::dgetrf(ni, ni, &mut m, ni, &mut ipiv, &mut info);
        }
        assert!(info >= 0, "dgetrf: illegal argument {}", -info);
        // info > 0: U[info-1, info-1] is exactly zero, which the sum turns into −∞.
        (0..n).map(|i| m[i + i * n].abs().log10()).sum()
    }
}
