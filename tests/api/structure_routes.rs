//! Structure-aware routes: the storage a matrix is solved in follows its structure
//! whatever the file stored, every route it then takes agrees with the dense SVD within its
//! certified bracket, and the saddle-point determinant identity |det [K D; Dᵀ 0]| = det K_FF
//! agrees with an LU of the whole matrix.

use penalty_lab::conditioning::{self, reference, sparse::SPARSE_ROUTE_MIN_N, CondRoute, Reuse};
use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::route::SPARSE_MAX_DENSITY;
use penalty_lab::strategy::lagrange::saddle_matrix;
use penalty_lab::system::{Problem, Stiffness};

fn scenes() -> Vec<(String, Problem)> {
    let cfg = GeneratorConfig {
        beam_elements: (3, 40),
        membrane_side: (10, 14),
        spectrum_n: (20, 60),
        ..GeneratorConfig::default()
    };
    let mut out = Vec::new();
    for family in [Family::Beam, Family::Membrane, Family::Spectrum] {
        for i in 0..4 {
            let g = generate(family, i, 11, &cfg).expect("generator");
            out.push((g.name, g.problem));
        }
    }
    out
}

/// The same entries in dense storage (what a scene file with `"dense"` rows holds).
fn as_dense(k: &Stiffness) -> Stiffness {
    Stiffness::Dense(k.to_dense())
}

#[test]
fn storage_follows_structure_and_keeps_every_value() {
    for (name, p) in scenes() {
        let s = p.k.structure();
        let chosen = as_dense(&p.k).in_preferred_storage();
        let expect_sparse = s.n >= SPARSE_ROUTE_MIN_N && s.density() <= SPARSE_MAX_DENSITY;
        assert_eq!(chosen.is_sparse(), expect_sparse, "{name}: {s:?}");
        assert_eq!(chosen.structure(), s, "{name}");
        // Bit for bit the same matrix.
        let (a, b) = (p.k.to_dense(), chosen.to_dense());
        for j in 0..s.n {
            for i in 0..s.n {
                assert_eq!(a[(i, j)].to_bits(), b[(i, j)].to_bits(), "{name} ({i},{j})");
            }
        }
        // The families land where the measured crossover puts them.
        match name.split('-').next().unwrap() {
            "membrane" => assert!(chosen.is_sparse(), "{name}: {s:?}"),
            "spectrum" => assert!(!chosen.is_sparse(), "{name}: {s:?}"),
            _ => assert_eq!(
                chosen.is_sparse(),
                s.n >= SPARSE_ROUTE_MIN_N,
                "{name}: {s:?}"
            ),
        }
    }
}

#[test]
fn a_banded_matrix_reports_its_band() {
    // Tridiagonal 40×40 stored dense: nnz = 3n − 2, half-bandwidth 1, stored sparse.
    let n: usize = 40;
    let rows: Vec<Vec<f64>> = (0..n)
        .map(|i: usize| {
            (0..n)
                .map(|j| match i.abs_diff(j) {
                    0 => 2.0,
                    1 => -1.0,
                    _ => 0.0,
                })
                .collect()
        })
        .collect();
    let k = Stiffness::from_rows(&rows).unwrap();
    let s = k.structure();
    assert_eq!((s.n, s.nnz, s.half_bandwidth), (n, 3 * n - 2, 1));
    let k = k.in_preferred_storage();
    assert!(k.is_sparse());
    // λ = 2 − 2cos(kπ/(n+1)): the sparse route against the closed form.
    let th = std::f64::consts::PI / (n as f64 + 1.0);
    let exact = (2.0 - 2.0 * (n as f64 * th).cos()) / (2.0 - 2.0 * th.cos());
    let r = conditioning::cond2(&k).unwrap();
    assert_eq!(r.route, CondRoute::SparseInertia);
    let (lo, hi) = r.certificate.unwrap().cond2_bounds();
    let t = 8.0 * n as f64 * f64::EPSILON * exact;
    assert!(
        lo * (1.0 - t) <= exact && exact <= hi * (1.0 + t),
        "{lo} {exact} {hi}"
    );
}

/// Every route taken for a scene's K and its penalty and saddle systems agrees with nalgebra's
/// dense SVD within the route's bracket (sparse: the certificate; dense: 8·n·ε·cond).
#[test]
fn every_route_agrees_with_the_dense_svd_within_its_bracket() {
    let mut routes = std::collections::BTreeSet::new();
    for (name, p) in scenes() {
        let p = Problem {
            k: as_dense(&p.k),
            ..p
        }
        .in_preferred_storage();
        let active: Vec<usize> = (0..p.m()).collect();
        let mut eps = vec![0.0; p.m()];
        for (c, e) in eps.iter_mut().enumerate() {
            *e = 1e3 * p.k.diag(p.constraints[c].single_dof().unwrap()).abs() * (1.0 + c as f64);
        }
        let adds: Vec<(usize, f64)> = p
            .constraints
            .iter()
            .zip(&eps)
            .map(|(c, &e)| (c.single_dof().unwrap(), e))
            .collect();
        let mats = [
            ("K", p.k.clone()),
            ("K+DEDᵀ", p.k.with_diagonal_added(&adds)),
            ("saddle", saddle_matrix(&p, &active)),
        ];
        for (what, a) in mats {
            let r = conditioning::cond2(&a).unwrap();
            routes.insert(r.route.name());
            let svd = reference::cond2_nalgebra(&a);
            let n = a.n() as f64;
            let floor = 8.0 * n * f64::EPSILON * svd;
            let (lo, hi) = match r.certificate {
                Some(c) => c.cond2_bounds(),
                None => (r.cond2, r.cond2),
            };
            assert!(
                lo * (1.0 - floor) <= svd && svd <= hi * (1.0 + floor)
                    || (r.cond2 - svd).abs() <= floor * svd,
                "{name} {what} ({}): cond₂ {} ∉ [{lo:e}, {hi:e}] vs SVD {svd:e}",
                r.route.name(),
                r.cond2
            );
        }
    }
    // The three storage outcomes of the families all occur.
    for r in ["sparse_inertia", "dense_inertia"] {
        assert!(routes.contains(r), "route {r} never taken: {routes:?}");
    }
}

#[test]
fn saddle_determinant_is_det_k_ff() {
    for (name, p) in scenes() {
        for p in [
            Problem {
                k: as_dense(&p.k),
                ..p.clone()
            },
            p.clone().in_preferred_storage(),
        ] {
            let active: Vec<usize> = (0..p.m()).collect();
            let dofs: Vec<usize> = p
                .constraints
                .iter()
                .map(|c| c.single_dof().unwrap())
                .collect();
            let a = saddle_matrix(&p, &active);
            let lu = reference::log10_abs_det_nalgebra(&a);
            let ours = conditioning::log10_abs_det_saddle(&p.k, &dofs).unwrap();
            // |Δ log10 det| ≲ n·ε·cond₂(A) / ln 10 (first-order perturbation of every pivot).
            let cond = reference::cond2_nalgebra(&a);
            let t = (64.0 * a.n() as f64 * f64::EPSILON * cond).max(1e-12);
            assert!(
                (ours - lu).abs() <= t * lu.abs().max(1.0),
                "{name} ({}): {ours} vs LU {lu} (tol {t:e})",
                if p.k.is_sparse() { "sparse" } else { "dense" }
            );
            // The sparse saddle cond₂ route reports the same determinant from its K_FF factor.
            if let Stiffness::Sparse(k) = &p.k {
                if p.n() >= SPARSE_ROUTE_MIN_N && dofs.len() < p.n() {
                    let r = conditioning::saddle::cond2_saddle(k, &dofs).unwrap();
                    let d = r.log10_det.expect("the saddle route returns det K_FF");
                    assert!(
                        (d - lu).abs() <= t * lu.abs().max(1.0),
                        "{name}: saddle route {d} vs LU {lu} (tol {t:e})"
                    );
                }
            }
        }
    }
    // Repeated DOFs are refused, not silently wrong.
    let (_, p) = &scenes()[0];
    let d = p.constraints[0].single_dof().unwrap();
    assert!(conditioning::log10_abs_det_saddle(&p.k, &[d, d]).is_err());
}

/// Reuse along the knob grid: K's Ritz vectors (kept by `cond2_warm`) start the
/// Lanczos runs of every `K + εP` of the scene. The certified cond₂ agrees with the cold
/// start's and with the dense SVD within the brackets, in fewer Lanczos steps over the grid.
#[test]
fn warm_starts_from_k_keep_the_certified_value_in_fewer_steps() {
    let (mut cold_steps, mut warm_steps) = (0usize, 0usize);
    for (name, p) in scenes() {
        let p = p.in_preferred_storage();
        if !p.k.is_sparse() {
            continue;
        }
        let (rk, ritz) = conditioning::cond2_warm(&p.k, Reuse::keeping_ritz()).unwrap();
        let ritz = ritz.expect("the sparse route keeps Ritz vectors");
        // K's Ritz vectors are unit vectors whose Rayleigh quotients sit in K's brackets.
        let c = rk.certificate.unwrap();
        for (y, lo, hi) in [
            (&ritz.top, c.lambda_max_lo, c.lambda_max_hi),
            (&ritz.bottom, c.lambda_min_lo, c.lambda_min_hi),
        ] {
            let ky = p.k.matvec(y);
            let rho: f64 = y.iter().zip(&ky).map(|(a, b)| a * b).sum();
            let unit: f64 = y.iter().map(|a| a * a).sum();
            assert!(
                (unit - 1.0).abs() <= 1e3 * f64::EPSILON,
                "{name}: ‖y‖² = {unit}"
            );
            let t = 64.0 * p.n() as f64 * f64::EPSILON * rk.cond2;
            assert!(
                lo * (1.0 - t) <= rho && rho <= hi * (1.0 + t),
                "{name}: ρ {rho} ∉ [{lo}, {hi}]"
            );
        }
        let d = p.k.diag(p.constraints[0].single_dof().unwrap()).abs();
        for eps in [1e-3 * d, d, 1e4 * d] {
            let adds: Vec<(usize, f64)> = p
                .constraints
                .iter()
                .map(|c| (c.single_dof().unwrap(), eps))
                .collect();
            let a = p.k.with_diagonal_added(&adds);
            let cold = conditioning::cond2(&a).unwrap();
            let warm_start = Reuse {
                starts: Some(&ritz),
                ..Reuse::default()
            };
            let (warm, none) = conditioning::cond2_warm(&a, warm_start).unwrap();
            assert!(none.is_none(), "vectors returned though not asked for");
            let (cc, cw) = (cold.certificate.unwrap(), warm.certificate.unwrap());
            cold_steps += cc.lanczos_steps;
            warm_steps += cw.lanczos_steps;
            let (clo, chi) = cc.cond2_bounds();
            let (wlo, whi) = cw.cond2_bounds();
            let svd = reference::cond2_nalgebra(&a);
            let t = 8.0 * a.n() as f64 * f64::EPSILON * svd;
            assert!(
                wlo <= chi * (1.0 + t) && clo <= whi * (1.0 + t),
                "{name} ε {eps:e}: warm [{wlo:e}, {whi:e}] vs cold [{clo:e}, {chi:e}]"
            );
            assert!(
                wlo * (1.0 - t) <= svd && svd <= whi * (1.0 + t),
                "{name} ε {eps:e}: SVD {svd:e} ∉ [{wlo:e}, {whi:e}]"
            );
        }
    }
    eprintln!("Lanczos steps over the grid: {warm_steps} warm, {cold_steps} cold");
    assert!(
        warm_steps * 4 <= cold_steps * 3,
        "warm starts took {warm_steps} Lanczos steps against {cold_steps} cold"
    );
}
