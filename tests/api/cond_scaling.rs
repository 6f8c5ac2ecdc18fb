//! cond₂ is scale-free, and so is the engine: a matrix multiplied by 2⁻⁶⁰⁰, 1e±150 or 1e±300
//! gets its unscaled twin's cond₂ within the contract and a bracket of the same relative width
//! (within 2×), by every route (sparse SPD, dense SPD, dense unsymmetric); and a metric of K
//! that cannot be computed never ends a solve.

use crate::common::matrices::laplacian_1d;
use penalty_lab::conditioning::{cond2, CondReport};
use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::strategy::{solve, Method};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};

/// 2⁻⁶⁰⁰ exactly (a power of two: exact products), then decimal scales (rounded products).
fn scales() -> [f64; 5] {
    [2f64.powi(-600), 1e150, 1e-150, 1e300, 1e-300]
}

fn times(a: &Stiffness, t: f64) -> Stiffness {
    let mut e = Vec::new();
    a.for_each_entry(|i, j, v| e.push((i, j, v * t)));
    let s = Stiffness::from_triplets(a.n(), &e).unwrap();
    if a.is_sparse() {
        s
    } else {
        Stiffness::Dense(s.to_dense())
    }
}

/// The twin's cond₂ within the contract of the unscaled one (the scaled entries are rounded
/// products for non-powers of two: a relative perturbation ε_mach per entry moves cond₂ by at
/// most ~2·cond₂·ε_mach, inside the contract's 4·cond₂·ε_mach), its bracket as wide within 2×.
fn assert_twin(name: &str, base: &CondReport, twin: &CondReport) {
    let tol = CondReport::contract_tol(base.cond2) + 2.0 * base.cond2 * f64::EPSILON;
    let rel = (twin.cond2 - base.cond2).abs() / base.cond2;
    assert!(
        rel <= tol,
        "{name}: {} vs {} ({rel:e})",
        twin.cond2,
        base.cond2
    );
    assert_eq!(twin.route, base.route, "{name}");
    assert_eq!(twin.bounds_proven, base.bounds_proven, "{name}");
    let (w0, w1) = (base.relative_width(), twin.relative_width());
    assert!(
        w1 <= 2.0 * w0.max(f64::EPSILON) && w0 <= 2.0 * w1.max(f64::EPSILON),
        "{name}: width {w1:e} vs {w0:e}"
    );
}

#[test]
fn scaled_twins_get_the_same_cond_and_bracket() {
    let dense_spd = Stiffness::Dense(laplacian_1d(40).to_dense());
    let unsym = {
        let mut e = Vec::new();
        laplacian_1d(30)
            .for_each_entry(|i, j, v| e.push((i, j, if j == i + 1 { 3.0 * v } else { v })));
        Stiffness::Dense(Stiffness::from_triplets(30, &e).unwrap().to_dense())
    };
    for (name, a) in [
        ("sparse SPD", laplacian_1d(300)),
        ("dense SPD", dense_spd),
        ("dense unsymmetric", unsym),
    ] {
        let base = cond2(&a).unwrap();
        for t in scales() {
            let twin = cond2(&times(&a, t)).unwrap_or_else(|e| panic!("{name} × {t:e}: {e}"));
            assert_twin(&format!("{name} × {t:e}"), &base, &twin);
            // σ's scale with the matrix.
            let r = twin.sigma_max / (base.sigma_max * t);
            assert!((r - 1.0).abs() < 1e-12, "{name} × {t:e}: σ_max ratio {r}");
        }
    }
}

/// A floating chain of springs (K singular: rigid translation) above the densify limit, held
/// by one bilateral row: lagrange solves it, its saddle point's cond₂ is computed, and cond₂(K)
/// — which no route can take (singular, too large to densify) — is missing with its reason
/// instead of failing the solve's metrics.
#[test]
fn a_metric_of_k_that_fails_does_not_end_the_solve() {
    let n = penalty_lab::conditioning::DENSIFY_LIMIT + 200;
    let mut e = Vec::new();
    for i in 0..n - 1 {
        e.extend([
            (i, i, 1.0),
            (i + 1, i + 1, 1.0),
            (i, i + 1, -1.0),
            (i + 1, i, -1.0),
        ]);
    }
    let k = Stiffness::from_triplets(n, &e).unwrap();
    let mut q = vec![0.0; n];
    q[n - 1] = 1.0;
    let rows = vec![Constraint::on_dof(0, 0.0, ConstraintKind::Bilateral)];
    let p = Problem::new(k, q, rows).unwrap();
    let sol = solve(&p, Method::lagrange()).unwrap();
    assert!((sol.u[n - 1] - (n - 1) as f64).abs() < 1e-6 * n as f64);
    let m = metrics::compute(&p, &sol, MetricSet::ALL).unwrap();
    assert!(m.cond2_k.is_none(), "{:?}", m.cond2_k);
    assert!(
        m.unavailable
            .iter()
            .any(|w| w.starts_with("cond2 of K not computed")),
        "{:?}",
        m.unavailable
    );
    assert!(m.cond2_system.is_some(), "{:?}", m.unavailable);
}

/// A cond₂ whose bracket is not proven (the saddle route's ends resting on a failed Cholesky
/// test) is said to be an estimate in the warnings, with its route and bracket; a proven one
/// is not.
#[test]
fn an_unproven_bracket_is_said_out_loud() {
    use penalty_lab::conditioning::CondRoute;
    let report = |proven: bool| CondReport {
        cond2: 9.187e12,
        cond2_lo: 9.19e12 * (1.0 - 1e-13),
        cond2_hi: 9.19e12,
        bounds_proven: proven,
        sigma_max: 1.0,
        sigma_min: 1.0 / 9.187e12,
        route: CondRoute::SparseSaddleInertia,
        certificate: None,
        log10_det: None,
        asymmetry: None,
    };
    let warned = |proven: bool| {
        let m = metrics::Metrics {
            cond2_system: Some(report(proven)),
            ..Default::default()
        };
        metrics::precision_warnings(&m)
    };
    let w = warned(false);
    assert!(
        w.iter().any(|x| x.contains("is an estimate")
            && x.contains("sparse_saddle_inertia")
            && x.contains("not proven")),
        "{w:?}"
    );
    assert!(!warned(true).iter().any(|x| x.contains("is an estimate")));
}
