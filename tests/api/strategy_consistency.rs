//! Every solution consistent with its system and its reports (gaps, penetrations, residuals,
//! stats), the stats pinned on the bilateral beam, and dense and sparse storage giving the same
//! answers.

use crate::common::dense::{dense, inf};
use crate::strategy_support::{
    all_methods, all_scenes, beam_mixed, beam_with_kinds, cantilever6, cond_of, diff2, flexibility,
    limits, matvec, norm2, norm_inf_mat, penalized_system, residual_tol, rounding_tol, u0_of,
    C_ROUND,
};
use nalgebra::DVector;
use penalty_lab::metrics;
use penalty_lab::model::beam::paper;
use penalty_lab::strategy::{self, Method, SystemKind};
use penalty_lab::system::{ConstraintKind, Problem};

#[test]
fn every_solution_is_consistent_with_its_system_and_reports() {
    for (name, p) in all_scenes() {
        let cond_k = cond_of(&p.k);
        for method in all_methods(0.1) {
            let sol = strategy::solve(&p, method).unwrap();
            let tag = format!("{name} / {}", method.name());
            // gaps and penetrations as defined in methods.md.
            assert_eq!(sol.gaps.len(), p.m());
            for (c, con) in p.constraints.iter().enumerate() {
                assert_eq!(
                    sol.gaps[c],
                    sol.u[con.single_dof().unwrap()] - con.limit,
                    "{tag}"
                );
            }
            let maxp = p
                .constraints
                .iter()
                .zip(&sol.gaps)
                .map(|(con, &g)| match con.kind {
                    ConstraintKind::Bilateral => g.abs(),
                    ConstraintKind::Upper => g.max(0.0),
                    ConstraintKind::Lower => (-g).max(0.0),
                })
                .fold(0.0, f64::max);
            assert_eq!(sol.max_penetration, maxp, "{tag}");
            assert!(sol.penalties.iter().all(|&e| e >= 0.0), "{tag}");
            assert!(sol.stats.linear_solves >= 1, "{tag}");
            // No penalized solve is needed when u0 = K⁻¹q already violates nothing.
            let u0_feasible = p
                .constraints
                .iter()
                .all(|c| c.kind != ConstraintKind::Bilateral)
                && sol.penalties.iter().all(|&e| e == 0.0);
            assert!(sol.stats.iterations >= 1 || u0_feasible, "{tag}");
            assert!(sol.stats.factorizations >= 1, "{tag}");
            assert!(sol.stats.converged, "{tag}: {:?}", sol.warnings);
            assert_eq!(
                sol.stats.active_set_sizes.len(),
                sol.stats.iterations,
                "{tag}"
            );

            // K u = q − D·forces for every strategy.
            let k = dense(&p.k);
            let mut r = matvec(&k, &sol.u);
            for (con, f) in p.constraints.iter().zip(&sol.forces) {
                r[con.single_dof().unwrap()] += f;
            }
            let res = inf(&r.iter().zip(&p.q).map(|(a, b)| a - b).collect::<Vec<_>>());
            // condensed builds u = u0 − K⁻¹D r (no solve with the final matrix), so its
            // residual carries K's forward error: ‖K‖·ε·cond(K)·‖u‖.
            let amp = if method.is(&strategy::condensed::STRATEGY) {
                cond_k
            } else {
                1.0
            };
            // The solve was with K + D E Dᵀ (E = the penalties; 0 for lagrange), so its
            // norm — not ‖K‖ — sets the backward error; forces ε·g also round at ε·ε_mach·|û|.
            let a_norm = norm_inf_mat(&k) + inf(&sol.penalties);
            let rtol = amp
                * C_ROUND
                * (p.n() + p.m()) as f64
                * f64::EPSILON
                * (a_norm * inf(&sol.u).max(inf(&limits(&p))) + inf(&sol.forces) + inf(&p.q));
            assert!(res <= rtol, "{tag}: ‖Ku − q + Dr‖ = {res:e} > {rtol:e}");

            match method.name() {
                "lagrange" | "augmented" => {}
                _ => {
                    // Penalty strategies: (K + D E Dᵀ) u = q + D E û, and forces = ε g.
                    let (a, b) = penalized_system(&p, &sol.penalties, &limits(&p));
                    let ru = matvec(&a, &sol.u);
                    let res = inf(&ru.iter().zip(&b).map(|(x, y)| x - y).collect::<Vec<_>>());
                    let rtol = amp * residual_tol(&a, &sol.u, &b);
                    assert!(res <= rtol, "{tag}: penalized residual {res:e} > {rtol:e}");
                    for c in 0..p.m() {
                        assert_eq!(sol.forces[c], sol.penalties[c] * sol.gaps[c], "{tag}");
                    }
                    assert!(matches!(sol.system, SystemKind::Penalized));
                }
            }
        }
    }
}

#[test]
fn stats_are_pinned_on_the_bilateral_beam() {
    // All-bilateral: the penalty driver needs no u0 and one pass (the active set is all three
    // and cannot change) — except `spring`, whose rule needs g0 (K factor + u0 solve).
    let p = paper::problem();
    let st = |m: Method| strategy::solve(&p, m).unwrap().stats;
    for m in [
        Method::constant(1e3),
        Method::scaled(10.0),
        Method::paper(0.1),
    ] {
        let s = st(m);
        assert_eq!(
            (s.factorizations, s.linear_solves, s.iterations),
            (1, 1, 1),
            "{}",
            m.name()
        );
        assert_eq!(s.active_set_sizes, vec![3]);
    }
    let s = st(Method::spring(0.1));
    assert_eq!((s.factorizations, s.linear_solves, s.iterations), (2, 2, 1));
    // condensed: one factorization of K, u0 (1 solve) and W = K⁻¹D (m = 3 solves). The box QP
    // (src/strategy/condensed.rs) starts every constraint at the bound on the side of g0 (all
    // g0 > δ: upper bound +δ) and moves a constraint with a wrong-sign force to Free, and a
    // free one outside the box to the violated bound. Its path here, recomputed with nalgebra:
    // (+,+,+) gives the tip a pulling force r₂ < 0 → (+,+,free) leaves the tip below −δ →
    // (+,+,−), which is the KKT point: 3 iterations.
    let u0 = u0_of(&p);
    let g0 = p.gaps(&u0);
    let delta = 0.1;
    let s = flexibility(&p, &[0, 1, 2]);
    let r1 =
        s.clone().try_inverse().unwrap() * DVector::from_iterator(3, g0.iter().map(|g| g - delta));
    assert!(
        r1[0] >= 0.0 && r1[1] >= 0.0 && r1[2] < 0.0,
        "path step 1: {r1}"
    );
    let s2 = s.view((0, 0), (2, 2)).clone_owned();
    let r2 = s2.try_inverse().unwrap() * DVector::from_vec(vec![g0[0] - delta, g0[1] - delta]);
    let g2 = g0[2] - s[(2, 0)] * r2[0] - s[(2, 1)] * r2[1];
    assert!(
        r2[0] >= 0.0 && r2[1] >= 0.0 && g2 < -delta,
        "path step 2: {r2}, {g2}"
    );
    let gstar = DVector::from_vec(vec![delta, delta, -delta]);
    let r3 = s.try_inverse().unwrap() * (DVector::from_column_slice(&g0) - gstar);
    assert!(
        r3[0] >= 0.0 && r3[1] >= 0.0 && r3[2] <= 0.0,
        "path step 3: {r3}"
    );
    let sol = strategy::solve(&p, Method::condensed(delta)).unwrap();
    assert!(sol.gaps[0] > 0.0 && sol.gaps[1] > 0.0 && sol.gaps[2] < 0.0);
    let s = sol.stats;
    // The three steps of the path, plus one re-solve from the final state if rounding put a
    // gap an ulp above δ (the guard: every penetration ≤ δ in floating point).
    assert!(s.refinements <= 1, "{s:?}");
    assert_eq!(
        (s.factorizations, s.linear_solves, s.iterations),
        (1, 4, 3 + s.refinements)
    );
    assert_eq!(s.active_set_sizes[..3], [3, 2, 3]);
    assert!(sol.max_penetration <= delta);
    // lagrange (all bilateral: no u0 needed): one saddle-point factorization, one solve each, one iteration.
    let s = st(Method::lagrange());
    assert_eq!((s.factorizations, s.linear_solves, s.iterations), (1, 1, 1));
    // augmented at fixed ε on bilateral constraints: the penalized matrix never changes, so one
    // factorization and one solve per Uzawa update.
    let s = st(Method::augmented(10.0, 1e-6, false));
    assert_eq!(s.factorizations, 1);
    assert_eq!(s.linear_solves, s.iterations);
    assert!(s.iterations >= 2);
}

#[test]
fn dense_and_sparse_storage_give_the_same_answers() {
    use ConstraintKind::*;
    let pairs: Vec<(&str, Problem, Problem)> = vec![
        (
            "beam bilateral",
            beam_with_kinds([Bilateral; 3], false),
            beam_with_kinds([Bilateral; 3], true),
        ),
        (
            "beam upper",
            beam_with_kinds([Upper; 3], false),
            beam_with_kinds([Upper; 3], true),
        ),
        ("beam mixed", beam_mixed(false), beam_mixed(true)),
        ("cantilever6", cantilever6(false), cantilever6(true)),
    ];
    for (name, pd, ps) in pairs {
        assert!(!pd.k.is_sparse() && ps.k.is_sparse());
        for method in all_methods(0.1) {
            let sd = strategy::solve(&pd, method).unwrap();
            let ss = strategy::solve(&ps, method).unwrap();
            let tag = format!("{name} / {}", method.name());
            let cond = cond_of(&metrics::system_matrix(&pd, &sd)).max(cond_of(&pd.k));
            // Two backward-stable solves of the same system differ by ≲ 2× the forward bound.
            let tol = 2.0 * rounding_tol(cond, pd.n() + pd.m(), 1.0);
            let du = diff2(&sd.u, &ss.u) / norm2(&sd.u);
            assert!(du <= tol, "{tag}: relative Δu = {du:e} > {tol:e}");
            let emax = inf(&sd.penalties).max(1.0);
            for c in 0..pd.m() {
                let de = (sd.penalties[c] - ss.penalties[c]).abs() / emax;
                assert!(de <= tol, "{tag}: Δε[{c}] = {de:e}");
            }
        }
    }
}
