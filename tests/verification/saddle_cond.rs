//! The sparse saddle-point cond₂ route (inertia through the block structure,
//! `conditioning::saddle`) against dense symmetric eigenvalues of the assembled
//! `[K D; Dᵀ 0]`: the dense value lies in the certified bracket (widened by the dense
//! solver's own rounding, 64·n·ε_mach·cond₂), on the elasticity scenes of an outside FE code
//! (where σ_min is the negative eigenvalue closest to 0) and on membranes (σ_min = λ⁺_min).

use penalty_lab::conditioning::certify::Margin;
use penalty_lab::conditioning::saddle::{cond2_saddle, cond2_saddle_with, SCHUR_TEST_MAX};
use penalty_lab::conditioning::{cond2_dense, CondReport, CondRoute};
use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::linalg::SparseLlt;
use penalty_lab::metrics::{self, MetricSet};
use penalty_lab::scene::read_scene;
use penalty_lab::strategy::{self, lagrange, Method, SystemKind};
use penalty_lab::system::{Problem, Stiffness};
use std::path::Path;

fn elasticity() -> Vec<Problem> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/elasticity");
    [
        "elasticity-quad-block",
        "elasticity-p2-strip",
        "elasticity-tet-brick",
    ]
    .iter()
    .map(|s| {
        read_scene(&dir.join(format!("{s}.scene.json")))
            .unwrap()
            .problem
    })
    .collect()
}

fn membranes() -> Vec<Problem> {
    crate::common::matrices::membranes((30, 45), 2, 77)
}

/// The lagrange active set and its DOFs.
fn active(p: &Problem) -> (Vec<usize>, Vec<usize>) {
    let s = strategy::solve(p, Method::lagrange()).unwrap();
    let SystemKind::SaddlePoint { active } = s.system else {
        panic!("lagrange returns a saddle point")
    };
    let dofs = active
        .iter()
        .map(|&c| p.constraints[c].single_dof().unwrap())
        .collect();
    (active, dofs)
}

/// The lagrange active set of `p` (sparse K) and the sparse saddle-point cond₂ of its system.
fn sparse_saddle(p: &Problem, schur_test_max: usize) -> (Vec<usize>, CondReport) {
    let Stiffness::Sparse(k) = &p.k else {
        panic!("the test scenes have a sparse K")
    };
    let (act, dofs) = active(p);
    (act, cond2_saddle_with(k, &dofs, schur_test_max).unwrap())
}

/// The dense eigenvalues of Lagrange's saddle point of `p` on `act` inside `sparse`'s
/// certified brackets (widened by the dense solver's rounding); returns the dense report.
pub(crate) fn check(p: &Problem, act: &[usize], sparse: &CondReport, label: &str) -> CondReport {
    let kkt = lagrange::saddle_matrix(p, act).to_dense();
    let dense = cond2_dense(kkt.as_ref(), true).unwrap();
    let slack = 64.0 * kkt.nrows() as f64 * f64::EPSILON * dense.cond2;
    let cert = sparse.certificate.expect("certificate");
    let (lo, hi) = cert.cond2_bounds();
    assert!(
        dense.cond2 >= lo * (1.0 - slack) && dense.cond2 <= hi * (1.0 + slack),
        "{label}: dense cond₂ {:e} outside [{lo:e}, {hi:e}] (slack {slack:e})",
        dense.cond2
    );
    for (what, d, l, h) in [
        (
            "σ_max",
            dense.sigma_max,
            cert.lambda_max_lo,
            cert.lambda_max_hi,
        ),
        (
            "σ_min",
            dense.sigma_min,
            cert.lambda_min_lo,
            cert.lambda_min_hi,
        ),
    ] {
        // Absolute rounding of the dense eigenvalues: 64·n·ε·σ_max.
        let abs = 64.0 * kkt.nrows() as f64 * f64::EPSILON * dense.sigma_max;
        assert!(
            d >= l - abs && d <= h + abs,
            "{label}: dense {what} {d:e} outside [{l:e}, {h:e}]"
        );
    }
    dense
}

#[test]
fn elasticity_scenes_sparse_bracket_contains_dense() {
    for p in elasticity() {
        let (act, sparse) = sparse_saddle(&p, SCHUR_TEST_MAX);
        assert_eq!(sparse.route, CondRoute::SparseSaddleInertia);
        let (lo, hi) = sparse.certificate.unwrap().cond2_bounds();
        // Proven at the contract's floor of 1e-12 although cond₂ ≈ 1e11–1e12 and the negative
        // eigenvalues cluster within 0.1 %: |λ⁻_max| through the Schur complement onto B
        // (saddle::schur), σ_max by tests judged by their factors' own margins. Before: 0.48
        // wide on the quad block, unproven (64·ε·cond₂ ≈ 1e-4) on the other two.
        assert!(sparse.bounds_proven, "{sparse:?}");
        assert!(hi / lo - 1.0 <= 1e-12, "[{lo:e}, {hi:e}]");
        check(&p, &act, &sparse, "elasticity");
    }
}

#[test]
fn membranes_sparse_bracket_contains_dense() {
    for p in membranes() {
        let (act, sparse) = sparse_saddle(&p, SCHUR_TEST_MAX);
        let (lo, hi) = sparse.certificate.unwrap().cond2_bounds();
        // Every end proven on the membranes, to a few worst-case Cholesky margins times cond₂
        // (m ≈ c·r·u ≈ 1e-13): below s₀ by the analytic floor, above it by the LDLᵀ inertia
        // test of H(−s) (before it, (σ_min − s₀)/σ_min: 1 % on one of these two).
        assert!(sparse.bounds_proven, "{sparse:?}");
        let width = hi / lo - 1.0;
        let Stiffness::Sparse(k) = &p.k else {
            unreachable!()
        };
        let m = Margin::of(&SparseLlt::analyze(k).unwrap()).m;
        eprintln!(
            "membrane: cond₂ {:.3e}, proven width {width:.1e} = {:.1} m·cond₂",
            sparse.cond2,
            width / (m * sparse.cond2)
        );
        // σ_min's end: a first test 4m·cond₂ below the estimate, stepping out ×8 where it fails
        // (4 and 32 m·cond₂ on these two): at most a second step.
        assert!(width <= 64.0 * m * sparse.cond2, "bracket [{lo:e}, {hi:e}]");
        check(&p, &act, &sparse, "membrane");
    }
}

/// Beams (graded K: cond₂ of the saddle point 1e5–1e8): σ_min's lower end by Temple's bound
/// (second order in the residual) instead of Cholesky tests stepping down from the estimate
/// (first order: Lemma 1's margin times cond₂, 1e-9–1e-6 wide on these before), so every
/// bracket is proven and within the contract's floor of 1e-12.
#[test]
fn beams_saddle_brackets_are_second_order() {
    // The benchmark folder's beams (scripts/folder.toml): 36–336 DOFs, stored sparse.
    let cfg = GeneratorConfig {
        beam_elements: (12, 112),
        ..Default::default()
    };
    let mut checked = 0;
    for i in 0..6 {
        let p = generate(Family::Beam, i, 2011, &cfg)
            .unwrap()
            .problem
            .in_preferred_storage();
        let Stiffness::Sparse(_) = &p.k else {
            continue;
        };
        let (act, sparse) = sparse_saddle(&p, SCHUR_TEST_MAX);
        if act.is_empty() {
            continue;
        }
        let (lo, hi) = sparse.certificate.unwrap().cond2_bounds();
        eprintln!(
            "beam {i}: cond₂ {:.3e}, width {:.1e}",
            sparse.cond2,
            hi / lo - 1.0
        );
        assert!(sparse.bounds_proven, "{sparse:?}");
        assert!(hi / lo - 1.0 <= 1e-12, "beam {i}: [{lo:e}, {hi:e}]");
        check(&p, &act, &sparse, "beam");
        checked += 1;
    }
    assert!(checked >= 3, "{checked} beams with contact");
}

/// Without the m×m test (as for m > SCHUR_TEST_MAX), the bracket keeps only certified ends:
/// wider on the elasticity scenes, and still containing the dense value.
#[test]
fn without_the_schur_test_the_bracket_stays_certified() {
    for p in elasticity() {
        let (act, sparse) = sparse_saddle(&p, 0);
        check(&p, &act, &sparse, "elasticity, no Schur test");
    }
}

/// The metrics take the saddle route for a sparse lagrange system, whatever its size.
#[test]
fn metrics_use_the_saddle_route() {
    let p = &elasticity()[1];
    let s = strategy::solve(p, Method::lagrange()).unwrap();
    let m = metrics::compute(
        p,
        &s,
        MetricSet {
            cond: true,
            det: false,
            cond_tol: None,
        },
    )
    .unwrap();
    assert_eq!(
        m.cond2_system.unwrap().route,
        CondRoute::SparseSaddleInertia
    );
}

/// A dense-stored K (the `spectrum` family: dense rotations of a prescribed spectrum) takes
/// the saddle route too, handed to it in compressed columns: σ_min by Temple's bounds, where
/// the dense eigensolver's Kahan bounds were 1e-9–9e-3 wide on the default sweep's dense
/// `lagrange` systems. The bracket holds the dense eigenvalues' cond₂ (`check`), and its width
/// is second order in ε_mach·cond₂ (the residual of x̂ = A⁻¹y is ≈ ε_mach·cond₂ relative,
/// Temple's loss its square over the relative gap, ≥ 1 %) plus a few n·ε_mach, where a
/// first-order bound is ≈ n·ε_mach·cond₂ (cond₂ 1e6–3e10 here).
#[test]
fn dense_k_saddle_points_take_the_saddle_route() {
    let cfg = GeneratorConfig::default();
    let mut checked = 0;
    for i in 0..6 {
        let p = generate(Family::Spectrum, i, 2011, &cfg).unwrap().problem;
        assert!(
            matches!(p.k, Stiffness::Dense(_)),
            "spectrum K is stored dense"
        );
        let s = strategy::solve(&p, Method::lagrange()).unwrap();
        let SystemKind::SaddlePoint { active } = &s.system else {
            panic!("lagrange returns a saddle point")
        };
        if active.is_empty() {
            continue;
        }
        let set = MetricSet {
            cond: true,
            det: false,
            cond_tol: None,
        };
        let r = metrics::compute(&p, &s, set).unwrap().cond2_system.unwrap();
        assert_eq!(r.route, CondRoute::SparseSaddleInertia);
        assert!(r.bounds_proven, "{r:?}");
        let width = r.relative_width();
        let n = (p.n() + active.len()) as f64;
        let e = f64::EPSILON;
        eprintln!("spectrum {i}: cond₂ {:.3e}, width {width:.1e}", r.cond2);
        let second_order = 1e3 * n * e + 1e4 * (e * r.cond2).powi(2);
        assert!(
            width <= second_order && width < n * e * r.cond2,
            "spectrum {i}: width {width:e} (cond₂ {:e})",
            r.cond2
        );
        check(&p, active, &r, "spectrum (dense K)");
        checked += 1;
    }
    assert!(checked >= 3, "{checked} spectrum scenes with contact");
}

/// Bad input: a repeated DOF is refused with a clear error.
#[test]
fn repeated_dof_is_an_input_error() {
    let p = &membranes()[0];
    let Stiffness::Sparse(k) = &p.k else { panic!() };
    let e = cond2_saddle(k, &[3, 3]).unwrap_err().to_string();
    assert!(e.contains("DOF 3 given twice"), "{e}");
}

/// Warm starts that point away from both ends (a smooth mode for the top, an alternating one
/// for the bottom) cost no accuracy: the result is proven, within the width target and within
/// the brackets of the generic-start analysis (the SPD route, which can settle short from a
/// warm start, reruns cold where its bracket misses: `sparse_cond`).
#[test]
fn misleading_warm_starts_do_not_cost_accuracy() {
    use penalty_lab::conditioning::saddle::cond2_saddle_warm;
    use penalty_lab::conditioning::sparse::{width_target, RitzStarts};
    for p in membranes() {
        let Stiffness::Sparse(k) = &p.k else { panic!() };
        let (_, dofs) = active(&p);
        let cold = cond2_saddle_warm(k, &dofs, SCHUR_TEST_MAX, None).unwrap();
        let n = p.n();
        let starts = RitzStarts {
            top: (0..n).map(|i| 1.0 + (i as f64 / n as f64)).collect(),
            bottom: (0..n)
                .map(|i| if i % 2 == 0 { 1.0 } else { -1.0 })
                .collect(),
        };
        let warm = cond2_saddle_warm(k, &dofs, SCHUR_TEST_MAX, Some(&starts)).unwrap();
        let target = width_target(None, warm.cond2, f64::INFINITY);
        eprintln!(
            "n {n}: cold {:.15e} ({:.1e}), misled {:.15e} ({:.1e}, {} steps against {})",
            cold.cond2,
            cold.relative_width(),
            warm.cond2,
            warm.relative_width(),
            warm.certificate.unwrap().lanczos_steps,
            cold.certificate.unwrap().lanczos_steps
        );
        assert!(warm.bounds_proven && warm.relative_width() <= target);
        assert!(
            (warm.cond2 / cold.cond2 - 1.0).abs() <= warm.relative_width() + cold.relative_width()
        );
    }
}
