//! The rules that put a penetration of exactly δ: Eq. 17 on the 1-DOF spring (and its mirror
//! for an obstacle on the plus side), reproduced by `spring`, `condensed` and `paper`; and
//! `condensed` on the paper's beam and on every scene, against methods.md and its formula
//! recomputed from the flexibility S = DᵀK⁻¹D.

use crate::common::dense::inf;
use crate::strategy_support::{
    all_scenes, cond_of, diff2, flexibility, limits, printed_sig, rounding_tol, u0_of, C_ROUND,
};
use nalgebra::DVector;
use penalty_lab::metrics;
use penalty_lab::model::beam::paper;
use penalty_lab::model::spring;
use penalty_lab::strategy::{self, Method};
use penalty_lab::system::{ConstraintKind, Problem};

/// (k, q, û, δ) with u0 = q/k < û − δ: a lower obstacle (Fig. 1) that u0 penetrates by more
/// than δ.
const SPRING_CASES: [(f64, f64, f64, f64); 6] = [
    (100.0, 5.0, 1.0, 0.1),
    (2.5, -3.0, 0.7, 0.01),
    (1e4, 1.0, 2.0, 1e-3),
    (0.3, 0.0, 0.5, 0.05),
    (50.0, -200.0, -1.0, 0.2),
    (7.0, 6.0, 1e3, 1e-2),
];

/// Absolute tolerance for a 1-DOF penalty ε ≈ k(|g0| − δ)/δ: perturbing û, u0 or a gap by
/// rounding (ε_mach·scale) moves ε by k·ε_mach·scale/δ, and a formula that divides a computed
/// force by a computed gap (condensed: ε = r/g with g = g0 − S r) loses another factor
/// (1 + |g0|/δ) to cancellation. scale = max(|û|, |u0|, δ).
fn eps_tol_1dof(k: f64, scale: f64, delta: f64) -> f64 {
    C_ROUND * f64::EPSILON * k * (1.0 + scale / delta).powi(2)
}

#[test]
fn eq17_gives_penetration_exactly_delta_on_the_spring() {
    for (k, q, uh, delta) in SPRING_CASES {
        let u0 = q / k;
        assert!(u0 < uh - delta, "case setup: u0 = {u0} must be < û − δ");
        let scale = uh.abs().max(u0.abs()).max(delta);
        let eps = spring::eq17_penalty(k, q, uh, delta);
        assert!(eps > 0.0, "Eq. 17 must be positive when u0 < û − δ: {eps}");
        let u = spring::displacement(k, q, uh, eps);
        // u = (q + εû)/(k + ε): a handful of roundings of quantities ≤ scale (1×1, cond 1).
        let tol = rounding_tol(1.0, 1, scale);
        assert!(
            ((uh - u) - delta).abs() <= tol,
            "(k,q,û,δ)=({k},{q},{uh},{delta}): û − u = {}, δ = {delta}",
            uh - u
        );
        // Eq. 12 holds at that u: (k + ε) u = q + ε û.
        assert!(((k + eps) * u - (q + eps * uh)).abs() <= tol * (k + eps));
    }
}

#[test]
fn spring_condensed_and_paper_reproduce_eq17_on_one_dof() {
    for (k, q, uh, delta) in SPRING_CASES {
        let p = spring::problem(k, q, uh, ConstraintKind::Lower).unwrap();
        let eps17 = spring::eq17_penalty(k, q, uh, delta);
        let u17 = spring::displacement(k, q, uh, eps17);
        let u0 = q / k;
        let scale = uh.abs().max(u0.abs()).max(delta);
        let etol = eps_tol_1dof(k, scale, delta);
        let utol = rounding_tol(1.0, 1, scale);
        // On 1 DOF, Eq. 28 is (|kû − q| − kδ)/δ; it equals Eq. 17 iff kû − q ≥ 0, which the
        // lower-obstacle setting u0 < û − δ guarantees (kû − q > kδ > 0).
        assert!(k * uh - q > k * delta);
        let eq28 = ((k * uh - q).abs() - k * delta) / delta;
        assert!((eq28 - eps17).abs() <= etol);
        for method in [
            Method::spring(delta),
            Method::condensed(delta),
            Method::paper(delta),
        ] {
            let s = strategy::solve(&p, method).unwrap();
            assert!(
                (s.penalties[0] - eps17).abs() <= etol,
                "{}: ε = {} vs Eq. 17 {eps17} (k,q,û,δ)=({k},{q},{uh},{delta})",
                method.name(),
                s.penalties[0]
            );
            assert!((s.u[0] - u17).abs() <= utol, "{}: u", method.name());
            assert!((s.max_penetration - delta).abs() <= utol);
            assert!(s.warnings.is_empty(), "{:?}", s.warnings);
        }
    }
}

#[test]
fn spring_obstacle_on_the_plus_side_mirrors_eq17() {
    // Upper obstacle u ≤ û with u0 > û + δ: the mirrored Eq. 17, ε = (q − k(û + δ))/δ, puts the
    // spring at û + δ: (q + εû)/(k + ε) = û + δ.
    for (k, q, uh, delta) in SPRING_CASES {
        let (q, uh) = (-q, -uh); // mirror x → −x
        let p = spring::problem(k, q, uh, ConstraintKind::Upper).unwrap();
        let eps = (q - k * (uh + delta)) / delta;
        let u0 = q / k;
        let scale = uh.abs().max(u0.abs()).max(delta);
        let etol = eps_tol_1dof(k, scale, delta);
        let utol = rounding_tol(1.0, 1, scale);
        for method in [
            Method::spring(delta),
            Method::condensed(delta),
            Method::paper(delta),
        ] {
            let s = strategy::solve(&p, method).unwrap();
            assert!((s.penalties[0] - eps).abs() <= etol, "{}", method.name());
            assert!((s.u[0] - (uh + delta)).abs() <= utol, "{}", method.name());
        }
    }
}

#[test]
fn condensed_on_paper_beam_matches_methods_md() {
    let p = paper::problem();
    let sol = strategy::solve(&p, Method::condensed(0.1)).unwrap();
    // methods.md: ε = (87.9, 130, 41.4) (3 significant digits), |g| = 0.1, cond 222.
    for (got, want) in sol.penalties.iter().zip([87.9, 130.0, 41.4]) {
        assert!(printed_sig(*got, want, 3), "ε = {got}, methods.md {want}");
    }
    for g in &sol.gaps {
        assert!((g.abs() - 0.1).abs() <= 1e-9 * 0.1, "gap {g}");
    }
    let c = cond_of(&metrics::system_matrix(&p, &sol));
    assert!(printed_sig(c, 222.0, 3), "cond(K + ε) = {c}");
    // … and it is better conditioned than Eq. 28's system (513.871, paper).
    assert!(c < 513.871);
    assert!(sol.warnings.is_empty(), "{:?}", sol.warnings);
}

#[test]
fn condensed_formula_recomputed_from_flexibility() {
    // methods.md: ε = (S⁻¹(g0 − g*)) ./ g* with S = DᵀK⁻¹D and |g*| = δ. Recomputed here with
    // nalgebra's inverse, using the sides the solver chose (the returned gaps' signs).
    let p = paper::problem();
    let delta = 0.1;
    let sol = strategy::solve(&p, Method::condensed(delta)).unwrap();
    let u0 = u0_of(&p);
    let g0 = p.gaps(&u0);
    let s = flexibility(&p, &[0, 1, 2]);
    let gstar: Vec<f64> = sol.gaps.iter().map(|g| delta * g.signum()).collect();
    let r = s.try_inverse().unwrap() * DVector::from_iterator(3, (0..3).map(|c| g0[c] - gstar[c]));
    let cond_k = cond_of(&p.k);
    let scale = inf(&u0).max(inf(&limits(&p)));
    for c in 0..3 {
        let eps = r[c] / gstar[c];
        // ε ≈ r/δ; r carries the forward error of K⁻¹ (cond K) on gaps of size `scale`, and
        // the penalty divides it by δ.
        let tol = rounding_tol(cond_k, p.n(), scale) * eps.abs().max(1.0) / delta;
        assert!(
            (sol.penalties[c] - eps).abs() <= tol,
            "c = {c}: {} vs {eps}",
            sol.penalties[c]
        );
    }
}

/// Checks the condensed contract on one scene; returns the number of penalized constraints.
fn check_condensed_contract(name: &str, p: &Problem, delta: f64) -> usize {
    let sol = strategy::solve(p, Method::condensed(delta)).unwrap();
    let u0 = u0_of(p);
    // Gaps are read off u = u0 − K⁻¹D r: rounding of order ε_mach·cond(K)·scale on top of the
    // contract's relative 1e-9.
    let scale = inf(&u0).max(inf(&limits(p))).max(delta);
    let tol = 1e-9 * delta + rounding_tol(cond_of(&p.k), p.n(), scale);
    let pen = p.penetrations(&sol.u);
    let mut penalized = 0;
    for (c, (&e, &pc)) in sol.penalties.iter().zip(&pen).enumerate() {
        assert!(e >= 0.0, "{name} δ={delta}: ε[{c}] = {e} < 0");
        if e > 0.0 {
            penalized += 1;
            assert!(
                (pc - delta).abs() <= tol,
                "{name} δ={delta}: penalized constraint {c} has penetration {pc} ≠ δ"
            );
        } else {
            assert!(
                pc <= delta + tol,
                "{name} δ={delta}: unpenalized constraint {c} has penetration {pc} > δ"
            );
        }
    }
    assert!(sol.warnings.is_empty(), "{name}: {:?}", sol.warnings);
    penalized
}

#[test]
fn condensed_penetration_is_exactly_delta_where_penalized() {
    let mut total = 0;
    for (name, p) in all_scenes() {
        for delta in [0.5, 0.1, 1e-3] {
            total += check_condensed_contract(name, &p, delta);
        }
    }
    // The scenes do put constraints into contact (otherwise the check above is vacuous).
    assert!(total >= 20, "only {total} penalized constraints overall");
    // Lower obstacles that u0 does not touch: nothing penalized, u = u0.
    let p = paper::problem_with_kind(ConstraintKind::Lower);
    let sol = strategy::solve(&p, Method::condensed(0.1)).unwrap();
    assert!(sol.penalties.iter().all(|&e| e == 0.0));
    let u0 = u0_of(&p);
    let tol = rounding_tol(cond_of(&p.k), p.n(), inf(&u0));
    assert!(diff2(&sol.u, &u0) <= tol);
}
