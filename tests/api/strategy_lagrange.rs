//! `lagrange`: zero penetration on the active set, force signs, complementarity and
//! equilibrium on every scene, hand solutions of the spring chain and the upper beam; and the
//! constant penalty converging to it at rate O(1/ε).

use crate::common::dense::{dense, inf};
use crate::strategy_support::{
    all_scenes, chain, cond_of, limits, matvec, norm_inf_mat, rounding_tol, C_ROUND,
};
use penalty_lab::metrics;
use penalty_lab::model::beam::paper;
use penalty_lab::strategy::{self, Method, Solution, SystemKind};
use penalty_lab::system::{ConstraintKind, Problem};

/// Lagrange's contract on one scene: zero penetration on active constraints, no violation on
/// inactive ones, force signs, complementarity, and equilibrium `K u + D λ = q`.
fn check_lagrange(name: &str, p: &Problem) -> Solution {
    let sol = strategy::solve(p, Method::lagrange()).unwrap();
    assert!(sol.warnings.is_empty(), "{name}: {:?}", sol.warnings);
    let active = match &sol.system {
        SystemKind::SaddlePoint { active } => active.clone(),
        other => panic!("{name}: lagrange system {other:?}"),
    };
    let sys = metrics::system_matrix(p, &sol);
    let cond = cond_of(&sys);
    let scale = inf(&sol.u).max(inf(&limits(p)));
    let tol = rounding_tol(cond, sys.n(), scale);
    for (c, con) in p.constraints.iter().enumerate() {
        let g = sol.gaps[c];
        let lam = sol.forces[c];
        if active.contains(&c) {
            assert!(g.abs() <= tol, "{name}: active {c} gap {g} (tol {tol:e})");
        } else {
            assert_eq!(lam, 0.0, "{name}: inactive {c} carries force {lam}");
            assert_ne!(con.kind, ConstraintKind::Bilateral);
            assert!(
                con.kind.penetration(g) <= tol,
                "{name}: inactive {c} violated by {g}"
            );
        }
        match con.kind {
            ConstraintKind::Upper => assert!(lam >= 0.0, "{name}: upper {c} force {lam}"),
            ConstraintKind::Lower => assert!(lam <= 0.0, "{name}: lower {c} force {lam}"),
            ConstraintKind::Bilateral => {}
        }
    }
    assert!(sol.max_penetration <= tol);
    // Equilibrium K u + D λ = q, a backward-error check of the saddle-point solve.
    let k = dense(&p.k);
    let mut r = matvec(&k, &sol.u);
    for (con, lam) in p.constraints.iter().zip(&sol.forces) {
        r[con.single_dof().unwrap()] += lam;
    }
    let res: Vec<f64> = r.iter().zip(&p.q).map(|(a, b)| a - b).collect();
    let rtol = C_ROUND
        * sys.n() as f64
        * f64::EPSILON
        * (norm_inf_mat(&k) * inf(&sol.u) + inf(&sol.forces) + inf(&p.q));
    assert!(inf(&res) <= rtol, "{name}: ‖Ku + Dλ − q‖ = {}", inf(&res));
    sol
}

#[test]
fn lagrange_exact_signs_and_equilibrium_on_all_scenes() {
    for (name, p) in all_scenes() {
        check_lagrange(name, &p);
    }
}

#[test]
fn lagrange_matches_hand_solution_of_the_spring_chain() {
    // Ground —k1— u0 —k2— u1 ← P, upper obstacle u1 ≤ a. Free tip: u1 = P(1/k1 + 1/k2).
    // In contact: u1 = a, u0 = k2 a/(k1 + k2), λ = P − a·k1k2/(k1 + k2) ≥ 0.
    let (k1, k2, pl, a) = (3.0, 7.0, 5.0, 0.5);
    assert!(pl * (1.0 / k1 + 1.0 / k2) > a);
    let p = chain(k1, k2, pl, a, ConstraintKind::Upper);
    let sol = check_lagrange("chain", &p);
    let tol = rounding_tol(cond_of(&metrics::system_matrix(&p, &sol)), 3, pl / k1);
    assert!((sol.u[1] - a).abs() <= tol);
    assert!((sol.u[0] - k2 * a / (k1 + k2)).abs() <= tol);
    let lam = pl - a * k1 * k2 / (k1 + k2);
    assert!((sol.forces[0] - lam).abs() <= tol * (k1 + k2));
    // Same obstacle as `lower` on the far side (u1 ≥ a with u1 free = 2.38 > a): inactive.
    let p = chain(k1, k2, pl, a, ConstraintKind::Lower);
    let sol = check_lagrange("chain lower", &p);
    assert_eq!(sol.forces[0], 0.0);
    assert!((sol.u[1] - pl * (1.0 / k1 + 1.0 / k2)).abs() <= tol);
}

#[test]
fn lagrange_releases_the_tip_of_the_upper_beam() {
    // Beam, all `upper` (u ≤ û): u0 violates all three (g0 = 23.7, 0.29, 21.4). Closed form
    // (cubic beam elements are exact for nodal loads): cantilever L = 30, EJ = 175, EA = 2100,
    // tip load P = 1 up, axial load −50. Pushing node 3 (x = a = 20) down to 3 needs
    // R = (w_P(a) − 3)/f_aa with w_P(a) = P a²(3L − a)/(6EJ), f_aa = a³/(3EJ); the tip then
    // sits at w_P(L) − R a²(3L − a)/(6EJ) ≈ 10.0 < 30, so the tip obstacle is released
    // (force 0), while the bilateral tie would need a pull there (negative force).
    let (l, a, ej, ea): (f64, f64, f64, f64) = (30.0, 20.0, 175.0, 2100.0);
    let w_pa = a * a * (3.0 * l - a) / (6.0 * ej);
    let r = (w_pa - 3.0) / (a.powi(3) / (3.0 * ej));
    let tip = l.powi(3) / (3.0 * ej) - r * a * a * (3.0 * l - a) / (6.0 * ej);
    assert!(tip < 30.0);
    let p = paper::problem_with_kind(ConstraintKind::Upper);
    let sol = check_lagrange("beam upper", &p);
    let tol = rounding_tol(cond_of(&metrics::system_matrix(&p, &sol)), 11, 60.0);
    assert!((sol.u[7] - tip).abs() <= tol, "tip {} vs {tip}", sol.u[7]);
    assert_eq!(sol.forces[2], 0.0);
    assert!(
        (sol.forces[0] - r).abs() <= tol * ea,
        "R {} vs {r}",
        sol.forces[0]
    );
    // Axial bar (stiffness EA/L at the tip): u0 = −50 L/EA = −0.714 > −1, so the obstacle
    // pushes the tip to −1: (EA/L)(−1) = −50 − λ ⇒ λ = EA/L − 50 = 20 ≥ 0.
    assert!((sol.u[6] + 1.0).abs() <= tol);
    assert!((sol.forces[1] - (ea / l - 50.0)).abs() <= tol * ea);
    let bil = strategy::solve(&paper::problem(), Method::lagrange()).unwrap();
    assert!(bil.forces[2] < 0.0, "bilateral tip force {}", bil.forces[2]);
}

#[test]
fn constant_penalty_converges_to_lagrange_at_rate_one_over_eps() {
    let p = paper::problem();
    let lag = strategy::solve(&p, Method::lagrange()).unwrap();
    let cond_lag = cond_of(&metrics::system_matrix(&p, &lag));
    let mut pts = Vec::new();
    for e in 3..=8 {
        let eps = 10f64.powi(e);
        let sol = strategy::solve(&p, Method::constant(eps)).unwrap();
        let err = metrics::relative_error(&sol.u, &lag.u);
        let cond = cond_of(&metrics::system_matrix(&p, &sol));
        // Relative rounding floor of both solutions; a point is in the asymptotic (truncation)
        // regime only if its error is ≥ 100× that floor.
        let floor = rounding_tol(cond.max(cond_lag), p.n() + p.m(), 1.0);
        if err >= 100.0 * floor {
            pts.push((eps.log10(), err.log10()));
        }
        assert!(err > 0.0);
    }
    assert!(pts.len() >= 4, "too few points above rounding: {pts:?}");
    // Least-squares slope of log10(err) vs log10(ε).
    let n = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / n, sy / n);
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let slope = sxy / sxx;
    eprintln!("log10 ε, log10 error used in the fit: {pts:?}; slope {slope:.4}");
    assert!(
        (-1.1..=-0.9).contains(&slope),
        "slope {slope}, points {pts:?}"
    );
    // Each decade gains ≈ 10×.
    for w in pts.windows(2) {
        let ratio = 10f64.powf(w[0].1 - w[1].1);
        assert!((7.0..=13.0).contains(&ratio), "decade ratio {ratio}");
    }
}
