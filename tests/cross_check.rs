//! Cross-checks of the exact cond₂ ([`conditioning::cond2`], faer) and of `log10|det|`
//! ([`conditioning::log10_abs_det`], faer Cholesky/LU pivots) against independent
//! implementations: nalgebra always, LAPACK (system OpenBLAS) with `--features lapack`, and
//! closed forms wherever the matrix is built with a known spectrum.
//!
//! # Tolerances
//!
//! All routes are backward stable: each returns the exact answer for `A + E` with
//! `‖E‖ ≲ n ε ‖A‖` (ε = `f64::EPSILON`). A perturbation of that size moves σ_min by up to
//! `n ε σ_max`, so two routes (or a route and the closed form of a matrix that was itself
//! rounded while being built) can differ in cond₂ by a relative
//!
//! ```text
//! |Δcond| / cond ≤ C · n · cond · ε,    C = TOL_C = 4
//! ```
//!
//! and in `log10|det|` (first order: `Δ ln det = tr(A⁻¹E) ≤ ‖A⁻¹‖_F ‖E‖_F`) by
//!
//! ```text
//! |Δ log10|det|| ≤ C · n · ε · σ_max · ‖A⁻¹‖_F / ln 10
//! ```
//!
//! with `‖A⁻¹‖_F = (Σ σ_i⁻²)^½` from the known spectrum (or `√n / σ_min` otherwise). No bare
//! constant tolerances, with two deliberate exceptions that are *requirements*, not error
//! models:
//!
//! * every cond₂ route agrees with a full SVD to `1e-9` relative where both are feasible and
//!   cond₂ ≤ 1e6 ([`SVD_AGREEMENT`]);
//! * a sparse matrix's densified route agrees with the dense route on the same entries to
//!   `1e-14` relative ([`DENSIFIED_AGREEMENT`]; in practice bit for bit).
//!
//! Run with `--nocapture` to see the observed differences.

#[path = "common/mod.rs"]
mod common;

use common::matrices::laplacian_1d;
use faer::Mat;
use penalty_lab::conditioning::{self, reference, CondReport, CondRoute};
use penalty_lab::model::beam::paper;
use penalty_lab::system::Stiffness;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

const EPS: f64 = f64::EPSILON;
/// The constant C of the tolerances `C · n · cond · ε` (see the module docs).
const TOL_C: f64 = 4.0;
/// Binding: every cond₂ route agrees with a full SVD to this relative difference (cond ≤ 1e6).
const SVD_AGREEMENT: f64 = 1e-9;
/// Largest cond₂ at which [`SVD_AGREEMENT`] is required.
const SVD_AGREEMENT_MAX_COND: f64 = 1e6;
/// Densified sparse route vs. dense route on identical entries.
const DENSIFIED_AGREEMENT: f64 = 1e-14;
/// Dimension of the random test matrices.
const N: usize = 64;
/// Seed of every random matrix (fixed: the tests are deterministic).
const SEED: u64 = 0x5EED_C0DE;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// `C · n · cond · ε`: allowed relative difference of two cond₂ values.
fn tol_cond(n: usize, cond: f64) -> f64 {
    TOL_C * n as f64 * cond * EPS
}

/// Allowed absolute difference of two `log10|det|` values for singular values `sigma`.
fn tol_logdet(sigma: &[f64]) -> f64 {
    let n = sigma.len() as f64;
    let smax = sigma.iter().fold(0.0f64, |m, s| m.max(*s));
    let inv_fro = sigma.iter().map(|s| s.powi(-2)).sum::<f64>().sqrt();
    TOL_C * n * EPS * smax * inv_fro / std::f64::consts::LN_10
}

/// Same bound when only cond₂ is known (`‖A⁻¹‖_F ≤ √n / σ_min`).
fn tol_logdet_from_cond(n: usize, cond: f64) -> f64 {
    TOL_C * (n as f64).powf(1.5) * EPS * cond / std::f64::consts::LN_10
}

fn random_matrix(n: usize, rng: &mut ChaCha8Rng) -> Mat<f64> {
    Mat::from_fn(n, n, |_, _| rng.random_range(-1.0..1.0))
}

/// An orthogonal matrix: Q of the QR factorization of a seeded random matrix.
fn random_orthogonal(n: usize, rng: &mut ChaCha8Rng) -> Mat<f64> {
    random_matrix(n, rng).qr().compute_Q()
}

/// `λ_i = cond^(−i/(n−1))`, i = 0..n: from 1 down to 1/cond, geometrically spaced.
fn geometric_spectrum(n: usize, cond: f64) -> Vec<f64> {
    (0..n)
        .map(|i| cond.powf(-(i as f64) / (n - 1) as f64))
        .collect()
}

/// `U diag(s) Vᵀ`, exactly symmetric (upper triangle mirrored) when `u` and `v` are the same.
fn product(u: &Mat<f64>, s: &[f64], v: &Mat<f64>, symmetric: bool) -> Mat<f64> {
    let n = s.len();
    let mut a = Mat::zeros(n, n);
    for j in 0..n {
        let i_end = if symmetric { j + 1 } else { n };
        for i in 0..i_end {
            let x: f64 = (0..n).map(|k| u[(i, k)] * s[k] * v[(j, k)]).sum();
            a[(i, j)] = x;
            if symmetric {
                a[(j, i)] = x;
            }
        }
    }
    a
}

/// SPD `Q diag(λ) Qᵀ` with the spectrum of [`geometric_spectrum`]; returns (A, λ).
fn spd_with_cond(n: usize, cond: f64, seed: u64) -> (Stiffness, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let q = random_orthogonal(n, &mut rng);
    let lam = geometric_spectrum(n, cond);
    (Stiffness::Dense(product(&q, &lam, &q, true)), lam)
}

/// Unsymmetric `U diag(σ) Vᵀ` with two independent orthogonal factors; returns (A, σ).
fn unsymmetric_with_cond(n: usize, cond: f64, seed: u64) -> (Stiffness, Vec<f64>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let u = random_orthogonal(n, &mut rng);
    let v = random_orthogonal(n, &mut rng);
    let s = geometric_spectrum(n, cond);
    (Stiffness::Dense(product(&u, &s, &v, false)), s)
}

/// The same entries in sparse storage (exact zeros dropped, no duplicates).
fn to_sparse(a: &Stiffness) -> Stiffness {
    let mut t = Vec::new();
    a.for_each_entry(|i, j, v| {
        if v != 0.0 {
            t.push((i, j, v))
        }
    });
    Stiffness::from_triplets(a.n(), &t).expect("valid triplets")
}

fn analytic_cond(sigma: &[f64]) -> f64 {
    let max = sigma.iter().fold(0.0f64, |m, s| m.max(s.abs()));
    let min = sigma.iter().fold(f64::INFINITY, |m, s| m.min(s.abs()));
    max / min
}

fn analytic_log10_det(sigma: &[f64]) -> f64 {
    sigma.iter().map(|s| s.abs().log10()).sum()
}

fn cond2(a: &Stiffness) -> CondReport {
    conditioning::cond2(a).expect("cond2")
}

fn log10_abs_det(a: &Stiffness) -> f64 {
    conditioning::log10_abs_det(a).expect("log10_abs_det")
}

/// Faer's SVD route on the dense entries: the "full SVD" every route must agree with.
fn cond2_svd(a: &Stiffness) -> f64 {
    let r = conditioning::cond2_dense(a.to_dense().as_ref(), false).expect("svd");
    assert_eq!(r.route, CondRoute::Svd);
    r.cond2
}

/// Checks one cond₂ value against a reference: the scaled error model always, and the binding
/// 1e-9 SVD agreement when `vs_svd` and cond ≤ 1e6. Returns the relative difference.
fn check_cond(what: &str, got: f64, reference: f64, n: usize, vs_svd: bool) -> f64 {
    let r = rel(got, reference);
    let tol = tol_cond(n, reference);
    assert!(
        r <= tol,
        "{what}: cond₂ {got:e} vs {reference:e}: rel diff {r:.2e} > C·n·cond·ε = {tol:.2e}"
    );
    if vs_svd && reference <= SVD_AGREEMENT_MAX_COND {
        assert!(
            r <= SVD_AGREEMENT,
            "{what}: cond₂ {got:e} vs full SVD {reference:e}: rel diff {r:.2e} > {SVD_AGREEMENT:e}"
        );
    }
    r
}

fn check_logdet(what: &str, got: f64, reference: f64, tol: f64) -> f64 {
    let d = (got - reference).abs();
    assert!(
        d <= tol,
        "{what}: log10|det| {got} vs {reference}: diff {d:.2e} > {tol:.2e}"
    );
    d
}

/// Conditions 1e1, 1e2, …, 1e12.
fn conds() -> impl Iterator<Item = f64> {
    (1..=12).map(|k| 10f64.powi(k))
}

#[test]
fn spd_matrices_with_prescribed_condition_numbers() {
    eprintln!(
        "SPD n={N}: rel diffs of cond₂ (faer eigen route) vs closed form / faer SVD / nalgebra \
         SVD / nalgebra eigen; abs diffs of log10|det| vs closed form / nalgebra LU"
    );
    for (k, cond) in conds().enumerate() {
        let (a, lam) = spd_with_cond(N, cond, SEED + k as u64);
        let exact = analytic_cond(&lam);
        assert!(rel(exact, cond) < 1e-12);
        assert!(a.is_symmetric());

        let r = cond2(&a);
        assert_eq!(r.route, CondRoute::DenseInertia, "cond {cond:e}");
        let svd = cond2_svd(&a);
        let e_exact = check_cond("eigen vs closed form", r.cond2, exact, N, false);
        let e_svd = check_cond("eigen vs faer SVD", r.cond2, svd, N, true);
        let e_svd_exact = check_cond("faer SVD vs closed form", svd, exact, N, false);
        let e_na = check_cond(
            "nalgebra SVD vs eigen",
            reference::cond2_nalgebra(&a),
            r.cond2,
            N,
            true,
        );
        let e_nae = check_cond(
            "nalgebra eigen vs faer SVD",
            reference::cond2_nalgebra_symmetric(&a),
            svd,
            N,
            true,
        );
        // σ_max and σ_min themselves, not only their ratio.
        assert!(rel(r.sigma_max, lam[0]) <= tol_cond(N, 1.0));
        assert!(rel(r.sigma_min, lam[N - 1]) <= tol_cond(N, cond));

        let ld = log10_abs_det(&a);
        let tol = tol_logdet(&lam);
        let d_exact = check_logdet("faer vs Σ log10 λ", ld, analytic_log10_det(&lam), tol);
        let d_na = check_logdet(
            "faer vs nalgebra LU",
            ld,
            reference::log10_abs_det_nalgebra(&a),
            tol,
        );
        eprintln!(
            "  cond {cond:7.0e}: cond₂ {e_exact:.1e} {e_svd:.1e} (svd vs exact {e_svd_exact:.1e}) \
             {e_na:.1e} {e_nae:.1e} | log10det {d_exact:.1e} {d_na:.1e} (tol {tol:.1e})"
        );
    }
}

/// K of the paper's beam (Eq. 31). Its determinant has a closed form: the map from nodal
/// displacements to element deformations is block-unitriangular, so det K is the product of
/// the three elements' cantilever (clamped-free) stiffness determinants,
/// `EA/l · (12EJ/l³ · 4EJ/l − (6EJ/l²)²) = 210 · (2.1 · 70 − 10.5²) = 7717.5`.
#[test]
fn paper_beam_stiffness() {
    let k = paper::problem().k;
    assert!(k.is_symmetric() && !k.is_sparse());
    let n = k.n();
    let r = cond2(&k);
    assert_eq!(r.route, CondRoute::DenseInertia);
    let svd = cond2_svd(&k);
    let e_svd = check_cond("beam: eigen vs faer SVD", r.cond2, svd, n, true);
    let e_na = check_cond(
        "beam: nalgebra SVD vs faer SVD",
        reference::cond2_nalgebra(&k),
        svd,
        n,
        true,
    );
    let e_nae = check_cond(
        "beam: nalgebra eigen vs faer SVD",
        reference::cond2_nalgebra_symmetric(&k),
        svd,
        n,
        true,
    );

    let ld = log10_abs_det(&k);
    let exact = 3.0 * 7717.5f64.log10();
    let tol = tol_logdet_from_cond(n, r.cond2);
    let d_exact = check_logdet("beam vs closed form", ld, exact, tol);
    let d_na = check_logdet(
        "beam vs nalgebra LU",
        ld,
        reference::log10_abs_det_nalgebra(&k),
        tol,
    );
    eprintln!(
        "beam K (n={n}, cond₂ {:.6e}): cond₂ rel diffs {e_svd:.1e} {e_na:.1e} {e_nae:.1e}; \
         log10|det| {ld:.12} diffs {d_exact:.1e} {d_na:.1e} (tol {tol:.1e})",
        r.cond2
    );
}

#[test]
fn unsymmetric_matrices_take_the_svd_route() {
    // U diag(σ) Vᵀ with a known spectrum.
    for (k, cond) in [1e1, 1e4, 1e8, 1e12].into_iter().enumerate() {
        let (a, s) = unsymmetric_with_cond(N, cond, SEED + 100 + k as u64);
        assert!(!a.is_symmetric());
        let r = cond2(&a);
        assert_eq!(r.route, CondRoute::Svd, "cond {cond:e}");
        let exact = analytic_cond(&s);
        let e_exact = check_cond("SVD route vs closed form", r.cond2, exact, N, false);
        let e_na = check_cond(
            "nalgebra SVD vs SVD route",
            reference::cond2_nalgebra(&a),
            r.cond2,
            N,
            true,
        );
        let ld = log10_abs_det(&a);
        let tol = tol_logdet(&s);
        let d_exact = check_logdet("LU vs Σ log10 σ", ld, analytic_log10_det(&s), tol);
        let d_na = check_logdet(
            "LU vs nalgebra LU",
            ld,
            reference::log10_abs_det_nalgebra(&a),
            tol,
        );
        eprintln!(
            "unsymmetric cond {cond:7.0e}: cond₂ {e_exact:.1e} {e_na:.1e} | log10det \
             {d_exact:.1e} {d_na:.1e} (tol {tol:.1e})"
        );
    }

    // A plain random matrix (no closed form): faer vs nalgebra only.
    let mut rng = ChaCha8Rng::seed_from_u64(SEED + 200);
    let a = Stiffness::Dense(random_matrix(N, &mut rng));
    let r = cond2(&a);
    assert_eq!(r.route, CondRoute::Svd);
    let e_na = check_cond(
        "random: nalgebra SVD vs SVD route",
        reference::cond2_nalgebra(&a),
        r.cond2,
        N,
        true,
    );
    let ld = log10_abs_det(&a);
    let d_na = check_logdet(
        "random: LU vs nalgebra LU",
        ld,
        reference::log10_abs_det_nalgebra(&a),
        tol_logdet_from_cond(N, r.cond2),
    );
    eprintln!(
        "random unsymmetric (cond₂ {:.3e}): cond₂ {e_na:.1e} | log10det {d_na:.1e}",
        r.cond2
    );
}

/// Sparse storage of the same entries: the densified routes must reproduce the dense ones.
#[test]
fn sparse_input_takes_the_densified_route() {
    // The beam assembled sparse (duplicate triplets summed by faer) and dense, and sparse
    // storage of dense random matrices.
    let frame = paper::frame();
    let (spd, _) = spd_with_cond(N, 1e6, SEED + 300);
    let (uns, _) = unsymmetric_with_cond(N, 1e6, SEED + 301);
    let cases = [
        (
            "beam",
            frame.assemble(false).unwrap(),
            frame.assemble(true).unwrap(),
            CondRoute::DenseInertia,
        ),
        (
            "SPD cond 1e6",
            spd.clone(),
            to_sparse(&spd),
            CondRoute::DenseInertia,
        ),
        (
            "unsymmetric cond 1e6",
            uns.clone(),
            to_sparse(&uns),
            CondRoute::DensifiedSvd,
        ),
    ];

    for (name, dense, sparse, route) in &cases {
        assert!(sparse.is_sparse());
        // Densifying reproduces the dense entries exactly.
        let (dd, sd) = (dense.to_dense(), sparse.to_dense());
        for j in 0..dense.n() {
            for i in 0..dense.n() {
                assert_eq!(dd[(i, j)], sd[(i, j)], "{name}: entry ({i}, {j})");
            }
        }
        let rd = cond2(dense);
        let rs = cond2(sparse);
        assert_eq!(rs.route, *route, "{name}");
        let d = rel(rs.cond2, rd.cond2);
        assert!(
            d <= DENSIFIED_AGREEMENT,
            "{name}: densified cond₂ {} vs dense {}: rel diff {d:.2e}",
            rs.cond2,
            rd.cond2
        );
        check_cond(name, rs.cond2, cond2_svd(sparse), sparse.n(), true);
        // log10|det|: sparse Cholesky (AMD ordering) or, unsymmetric, the dense-LU fallback.
        let (ldd, lds) = (log10_abs_det(dense), log10_abs_det(sparse));
        let dl = check_logdet(name, lds, ldd, tol_logdet_from_cond(dense.n(), rd.cond2));
        eprintln!(
            "sparse {name}: cond₂ {} (bitwise equal: {}), log10|det| diff {dl:.1e}",
            rs.cond2,
            rs.cond2.to_bits() == rd.cond2.to_bits()
        );
    }
}

/// A genuinely sparse matrix with a closed-form spectrum: the 1D Laplacian tridiag(−1, 2, −1),
/// λ_k = 2 − 2 cos(kπ/(n+1)), det = n + 1.
#[test]
fn sparse_laplacian_matches_closed_form() {
    let n = 200;
    let a = laplacian_1d(n);
    let lam: Vec<f64> = (1..=n)
        .map(|k| 2.0 - 2.0 * (k as f64 * std::f64::consts::PI / (n + 1) as f64).cos())
        .collect();
    let r = cond2(&a);
    // Tridiagonal: 3n − 2 nonzeros, the sparse route by structure.
    assert_eq!(r.route, CondRoute::SparseInertia);
    let e = check_cond(
        "laplacian vs closed form",
        r.cond2,
        analytic_cond(&lam),
        n,
        false,
    );
    check_cond("laplacian vs faer SVD", r.cond2, cond2_svd(&a), n, true);
    check_cond(
        "laplacian: nalgebra vs faer",
        reference::cond2_nalgebra(&a),
        r.cond2,
        n,
        true,
    );
    let ld = log10_abs_det(&a);
    let d = check_logdet(
        "laplacian log10|det| vs log10(n+1)",
        ld,
        ((n + 1) as f64).log10(),
        tol_logdet(&lam),
    );
    eprintln!(
        "laplacian n={n}: cond₂ {:.6e} rel {e:.1e}, log10|det| diff {d:.1e}",
        r.cond2
    );
}

/// The sparse exact route (Lanczos + inertia, no densifying) against nalgebra's dense
/// symmetric eigenvalues on a membrane with penalties (n = 900, above the sparse-route
/// threshold): three independent implementations agree to 1e-9 relative.
fn membrane_with_penalties() -> Stiffness {
    let side = 30;
    let idx = |i: usize, j: usize| i * side + j;
    let mut t = Vec::new();
    for i in 0..side {
        for j in 0..side {
            let r = idx(i, j);
            // Penalties on every 7th node, as a penalized contact system would have.
            t.push((r, r, 4.0 + if r % 7 == 0 { 1e3 } else { 0.0 }));
            if i + 1 < side {
                t.push((r, idx(i + 1, j), -1.0));
                t.push((idx(i + 1, j), r, -1.0));
            }
            if j + 1 < side {
                t.push((r, idx(i, j + 1), -1.0));
                t.push((idx(i, j + 1), r, -1.0));
            }
        }
    }
    Stiffness::from_triplets(side * side, &t).unwrap()
}

#[test]
fn sparse_route_against_nalgebra() {
    let a = membrane_with_penalties();
    let r = cond2(&a);
    assert_eq!(r.route, CondRoute::SparseInertia);
    let na = reference::cond2_nalgebra_symmetric(&a);
    let d = rel(r.cond2, na);
    assert!(
        d <= 1e-9f64.max(tol_cond(a.n(), r.cond2)),
        "sparse {} vs nalgebra {na}: {d:e}",
        r.cond2
    );
    eprintln!(
        "sparse route vs nalgebra (n {}, cond {:.3e}): {d:.1e}",
        a.n(),
        r.cond2
    );
}

/// The same checks against LAPACK (system OpenBLAS): `dgesdd` and `dsyev` values only,
/// `dgetrf` pivots.
#[cfg(feature = "lapack")]
mod against_lapack {
    use super::*;

    #[test]
    fn spd_against_lapack() {
        eprintln!(
            "LAPACK, SPD n={N}: rel diffs of cond₂ dgesdd / dsyev vs faer, abs diff of \
             log10|det| dgetrf vs faer"
        );
        for (k, cond) in conds().enumerate() {
            let (a, lam) = spd_with_cond(N, cond, SEED + k as u64);
            let r = cond2(&a);
            let svd = cond2_svd(&a);
            let e_gesdd = check_cond(
                "dgesdd vs faer eigen",
                reference::cond2_lapack(&a),
                r.cond2,
                N,
                true,
            );
            let e_gesdd_svd = check_cond(
                "dgesdd vs faer SVD",
                reference::cond2_lapack(&a),
                svd,
                N,
                true,
            );
            let e_syevd = check_cond(
                "dsyev vs faer SVD",
                reference::cond2_lapack_symmetric(&a),
                svd,
                N,
                true,
            );
            let e_syevd_exact = check_cond(
                "dsyev vs closed form",
                reference::cond2_lapack_symmetric(&a),
                analytic_cond(&lam),
                N,
                false,
            );
            // The eigenvalues themselves against faer's route (σ = |λ|).
            let ev = reference::symmetric_eigenvalues_lapack(&a);
            assert!(rel(ev[N - 1], r.sigma_max) <= tol_cond(N, 1.0));
            assert!(rel(ev[0], r.sigma_min) <= tol_cond(N, cond));
            let d = check_logdet(
                "dgetrf vs faer",
                reference::log10_abs_det_lapack(&a),
                log10_abs_det(&a),
                tol_logdet(&lam),
            );
            eprintln!(
                "  cond {cond:7.0e}: dgesdd {e_gesdd:.1e} (vs faer SVD {e_gesdd_svd:.1e}) \
                 dsyev {e_syevd:.1e} (vs exact {e_syevd_exact:.1e}) | dgetrf {d:.1e}"
            );
        }
    }

    #[test]
    fn sparse_route_against_lapack() {
        let a = membrane_with_penalties();
        let r = cond2(&a);
        assert_eq!(r.route, CondRoute::SparseInertia);
        let ev = reference::symmetric_eigenvalues_lapack(&a);
        let n = a.n();
        for (got, want) in [(r.sigma_max, ev[n - 1]), (r.sigma_min, ev[0])] {
            let d = rel(got, want);
            assert!(
                d <= 1e-9f64.max(tol_cond(n, r.cond2)),
                "{got} vs dsyev {want}: {d:e}"
            );
        }
        let c = r.certificate.unwrap();
        assert!(
            c.lambda_max_lo <= ev[n - 1] * (1.0 + 1e-12)
                && ev[n - 1] <= c.lambda_max_hi * (1.0 + 1e-12)
        );
        eprintln!(
            "sparse route vs dsyev: cond {:.3e} vs {:.3e}",
            r.cond2,
            ev[n - 1] / ev[0]
        );
    }

    #[test]
    fn beam_unsymmetric_and_sparse_against_lapack() {
        let k = paper::problem().k;
        let kc = cond2(&k).cond2;
        let e1 = check_cond("beam dgesdd", reference::cond2_lapack(&k), kc, k.n(), true);
        let e2 = check_cond(
            "beam dsyev",
            reference::cond2_lapack_symmetric(&k),
            kc,
            k.n(),
            true,
        );
        let d = check_logdet(
            "beam dgetrf vs closed form",
            reference::log10_abs_det_lapack(&k),
            3.0 * 7717.5f64.log10(),
            tol_logdet_from_cond(k.n(), kc),
        );
        eprintln!("LAPACK beam: dgesdd {e1:.1e} dsyev {e2:.1e} dgetrf {d:.1e}");

        let ks = paper::frame().assemble(true).unwrap();
        check_cond(
            "sparse beam dgesdd",
            reference::cond2_lapack(&ks),
            cond2(&ks).cond2,
            ks.n(),
            true,
        );

        for (k, cond) in [1e1, 1e4, 1e8, 1e12].into_iter().enumerate() {
            let (a, s) = unsymmetric_with_cond(N, cond, SEED + 100 + k as u64);
            let r = cond2(&a);
            let e = check_cond(
                "unsymmetric dgesdd",
                reference::cond2_lapack(&a),
                r.cond2,
                N,
                true,
            );
            let sv = reference::singular_values_lapack(&a);
            assert!(rel(sv[0], r.sigma_max) <= tol_cond(N, 1.0));
            assert!(rel(sv[N - 1], r.sigma_min) <= tol_cond(N, cond));
            let d = check_logdet(
                "unsymmetric dgetrf",
                reference::log10_abs_det_lapack(&a),
                log10_abs_det(&a),
                tol_logdet(&s),
            );
            eprintln!("LAPACK unsymmetric cond {cond:7.0e}: dgesdd {e:.1e} | dgetrf {d:.1e}");
        }
    }
}
