//! Each contact strategy's defining property (shared/notes/methods.md), checked on the paper's
//! beam (Eq. 30–34) and on small handmade scenes.
//!
//! Expected values come from closed forms (the 1-DOF spring of Eq. 10–17, a two-spring chain
//! solved by hand), from defining properties (penetration exactly δ, equilibrium, complementarity),
//! from formulas recomputed here independently with nalgebra (Eq. 17, Eq. 28, S = DᵀK⁻¹D), or from
//! numbers printed in methods.md / the paper — never from our own code's output.
//!
//! Tolerances are derived from the problem: a backward-stable solve of an n×n system with 2-norm
//! condition number κ has relative forward error ≲ c·n·ε_mach·κ and relative residual
//! ≲ c·n·ε_mach (Higham, *Accuracy and Stability of Numerical Algorithms*, §7.1 and §9–10); see
//! [`rounding_tol`] and [`residual_tol`].

use crate::common;

use common::dense::{dense, inf};
use nalgebra::{DMatrix, DVector};
use penalty_lab::conditioning;
use penalty_lab::metrics;
use penalty_lab::model::beam::{paper, Frame, Section};
use penalty_lab::model::spring;
use penalty_lab::strategy::{self, registry, Knobs, Method, Solution, SystemKind};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use penalty_lab::Error;

// ----------------------------------------------------------------------------------------
// Tolerances
// ----------------------------------------------------------------------------------------

/// Safety constant `c` in the rounding bounds below. Wilkinson/Higham bounds for Cholesky and
/// partial-pivoting LU are `γ_{cn}` with small c; 8 covers the extra products (right-hand-side
/// assembly, D E û, the gap subtraction) done around the solve.
const C_ROUND: f64 = 8.0;

/// Forward-error tolerance for a quantity of magnitude `scale` obtained from an n×n solve with
/// condition number `cond`: `c · n · ε_mach · cond · scale`.
fn rounding_tol(cond: f64, n: usize, scale: f64) -> f64 {
    C_ROUND * n as f64 * f64::EPSILON * cond * scale
}

/// Residual (backward-error) tolerance of a backward-stable solve of `A x = b`:
/// `‖A x − b‖∞ ≤ c · n · ε_mach · (‖A‖∞ ‖x‖∞ + ‖b‖∞)` — no condition number involved.
fn residual_tol(a: &DMatrix<f64>, x: &[f64], b: &[f64]) -> f64 {
    C_ROUND * a.nrows() as f64 * f64::EPSILON * (norm_inf_mat(a) * inf(x) + inf(b))
}

/// cond₂ of a stiffness (the library's exact route; cross-checked against SVD elsewhere).
fn cond_of(k: &Stiffness) -> f64 {
    conditioning::cond2(k).expect("cond2").cond2
}

// ----------------------------------------------------------------------------------------
// Small dense linear algebra, independent of the library (nalgebra)
// ----------------------------------------------------------------------------------------

fn norm_inf_mat(a: &DMatrix<f64>) -> f64 {
    (0..a.nrows())
        .map(|i| (0..a.ncols()).map(|j| a[(i, j)].abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn diff2(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

/// Unconstrained solution u0 = K⁻¹ q by nalgebra's LU.
fn u0_of(p: &Problem) -> Vec<f64> {
    let k = dense(&p.k);
    let x = k
        .lu()
        .solve(&DVector::from_column_slice(&p.q))
        .expect("K nonsingular");
    x.iter().copied().collect()
}

/// `S = DᵀK⁻¹D` (m×m) for the listed constraint indices.
fn flexibility(p: &Problem, idx: &[usize]) -> DMatrix<f64> {
    let kinv = dense(&p.k).try_inverse().expect("K nonsingular");
    DMatrix::from_fn(idx.len(), idx.len(), |i, j| {
        kinv[(p.constraints[idx[i]].dof, p.constraints[idx[j]].dof)]
    })
}

/// `K + D E Dᵀ` and `q + D E ℓ` built here from the problem data.
fn penalized_system(p: &Problem, eps: &[f64], limits: &[f64]) -> (DMatrix<f64>, Vec<f64>) {
    let mut a = dense(&p.k);
    let mut b = p.q.clone();
    for ((c, &e), &l) in p.constraints.iter().zip(eps).zip(limits) {
        a[(c.dof, c.dof)] += e;
        b[c.dof] += e * l;
    }
    (a, b)
}

fn matvec(a: &DMatrix<f64>, x: &[f64]) -> Vec<f64> {
    (a * DVector::from_column_slice(x))
        .iter()
        .copied()
        .collect()
}

fn limits(p: &Problem) -> Vec<f64> {
    p.constraints.iter().map(|c| c.limit).collect()
}

// ----------------------------------------------------------------------------------------
// Scenes
// ----------------------------------------------------------------------------------------

/// The paper's beam with per-constraint kinds (DOFs 4, 6, 7; limits 3, −1, 30 of Eq. 34).
fn beam_with_kinds(kinds: [ConstraintKind; 3], sparse: bool) -> Problem {
    let k = paper::frame().assemble(sparse).unwrap();
    let cons = paper::DOFS
        .iter()
        .zip(paper::LIMITS)
        .zip(kinds)
        .map(|((&dof, limit), kind)| Constraint { dof, limit, kind })
        .collect();
    Problem::new(k, paper::LOAD.to_vec(), cons).unwrap()
}

/// Node 2 transverse `lower` at −1 (never touched: u0 = 26.7), tip axial bilateral at −1, tip
/// transverse `upper` at 30 (violated by u0 = 51.4).
fn beam_mixed(sparse: bool) -> Problem {
    use ConstraintKind::*;
    beam_with_kinds([Lower, Bilateral, Upper], sparse)
}

/// A 6-element cantilever (L = 60, E = 2100, 1×1.5 section) with a transverse tip load, a
/// moment at node 3 and an axial load; obstacles on three transverse DOFs.
fn cantilever6(sparse: bool) -> Problem {
    let f = Frame::cantilever(6, 60.0, Section::rectangle(2100.0, 1.0, 1.5)).unwrap();
    let k = f.assemble(sparse).unwrap();
    let mut q = vec![0.0; f.n_dofs()];
    q[f.dof(6, 1).unwrap()] = 2.0;
    q[f.dof(3, 2).unwrap()] = -5.0;
    q[f.dof(6, 0).unwrap()] = 10.0;
    let cons = vec![
        Constraint {
            dof: f.dof(2, 1).unwrap(),
            limit: 1.0,
            kind: ConstraintKind::Upper,
        },
        Constraint {
            dof: f.dof(4, 1).unwrap(),
            limit: -3.0,
            kind: ConstraintKind::Lower,
        },
        Constraint {
            dof: f.dof(6, 1).unwrap(),
            limit: 20.0,
            kind: ConstraintKind::Bilateral,
        },
    ];
    Problem::new(k, q, cons).unwrap()
}

/// Ground —k1— u0 —k2— u1, load P at u1, constraint on u1 of the given kind and limit.
fn chain(k1: f64, k2: f64, p: f64, limit: f64, kind: ConstraintKind) -> Problem {
    Problem::new(
        Stiffness::from_rows(&[vec![k1 + k2, -k2], vec![-k2, k2]]).unwrap(),
        vec![0.0, p],
        vec![Constraint {
            dof: 1,
            limit,
            kind,
        }],
    )
    .unwrap()
}

fn all_scenes() -> Vec<(&'static str, Problem)> {
    use ConstraintKind::*;
    vec![
        ("beam bilateral", paper::problem()),
        ("beam upper", paper::problem_with_kind(Upper)),
        ("beam lower", paper::problem_with_kind(Lower)),
        ("beam mixed", beam_mixed(false)),
        ("cantilever6", cantilever6(false)),
        ("chain upper", chain(3.0, 7.0, 5.0, 0.5, Upper)),
    ]
}

fn penalty_methods(delta: f64) -> Vec<Method> {
    vec![
        Method::constant(1e3),
        Method::scaled(10.0),
        Method::spring(delta),
        Method::paper(delta),
        Method::condensed(delta),
    ]
}

fn all_methods(delta: f64) -> Vec<Method> {
    let mut v = penalty_methods(delta);
    v.push(Method::lagrange());
    v.push(Method::augmented(100.0, 1e-6, false));
    v.push(Method::augmented(100.0, 1e-6, true));
    v
}

/// `|a − b| ≤` half a unit in the `sig`-th significant digit of `b` (printed precision).
fn printed_sig(a: f64, b: f64, sig: i32) -> bool {
    let e = b.abs().log10().floor() as i32;
    (a - b).abs() <= 0.5 * 10f64.powi(e - sig + 1) * (1.0 + 1e-12)
}

// ----------------------------------------------------------------------------------------
// 1. Eq. 17 on the 1-DOF spring
// ----------------------------------------------------------------------------------------

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

// ----------------------------------------------------------------------------------------
// 2. condensed
// ----------------------------------------------------------------------------------------

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

// ----------------------------------------------------------------------------------------
// 3. lagrange
// ----------------------------------------------------------------------------------------

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
        r[con.dof] += lam;
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

// ----------------------------------------------------------------------------------------
// 4. constant penalty → Lagrange at rate O(1/ε)
// ----------------------------------------------------------------------------------------

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

// ----------------------------------------------------------------------------------------
// 5. scaled, augmented, spring, paper: their formulas
// ----------------------------------------------------------------------------------------

#[test]
fn scaled_penalty_is_factor_times_diagonal() {
    for (name, p) in all_scenes() {
        for factor in [0.5, 10.0, 1e4] {
            let sol = strategy::solve(&p, Method::scaled(factor)).unwrap();
            let mut any = false;
            for (c, con) in p.constraints.iter().enumerate() {
                let e = sol.penalties[c];
                if e != 0.0 {
                    any = true;
                    assert_eq!(e, factor * p.k.get(con.dof, con.dof), "{name} c={c}");
                } else {
                    // Unpenalized only if not violated at the returned u.
                    assert_ne!(con.kind, ConstraintKind::Bilateral, "{name}");
                    assert_eq!(p.penetrations(&sol.u)[c], 0.0, "{name} c={c}");
                }
            }
            if name != "beam lower" {
                assert!(any, "{name}: nothing penalized");
            }
        }
    }
}

#[test]
fn augmented_reaches_tol_and_approaches_lagrange() {
    for (name, p) in all_scenes() {
        let lag = strategy::solve(&p, Method::lagrange()).unwrap();
        let lag_active = match &lag.system {
            SystemKind::SaddlePoint { active } => active.clone(),
            _ => unreachable!(),
        };
        let mut prev_err = f64::INFINITY;
        for tol in [1e-2, 1e-5, 1e-8] {
            for adaptive in [false, true] {
                let sol = strategy::solve(&p, Method::augmented(10.0, tol, adaptive)).unwrap();
                assert!(sol.warnings.is_empty(), "{name}: {:?}", sol.warnings);
                assert!(
                    sol.max_penetration <= tol,
                    "{name} tol={tol} adaptive={adaptive}: {}",
                    sol.max_penetration
                );
                // Same contact set as the exact solution, u − u_lag = K⁻¹D_A S_AA⁻¹ g_A for
                // the bilateral-like active set A (both satisfy K u = q − D λ; Dᵀu_lag = û on
                // A) — so ‖u − u_lag‖ ≤ ‖K⁻¹ D_A S_AA⁻¹‖·‖g_A‖ ≤ that norm · tol·√|A|.
                if lag_active.is_empty() {
                    let scale = inf(&lag.u);
                    assert!(diff2(&sol.u, &lag.u) <= rounding_tol(cond_of(&p.k), p.n(), scale));
                    continue;
                }
                let kinv = dense(&p.k).try_inverse().unwrap();
                let d = DMatrix::from_fn(p.n(), lag_active.len(), |i, j| {
                    f64::from(u8::from(i == p.constraints[lag_active[j]].dof))
                });
                let w = &kinv * &d;
                let s = d.transpose() * &w;
                let map = w * s.try_inverse().unwrap();
                let bound = map.norm() * tol * (lag_active.len() as f64).sqrt();
                let floor = rounding_tol(
                    cond_of(&metrics::system_matrix(&p, &lag)),
                    p.n() + p.m(),
                    inf(&lag.u),
                );
                let err = diff2(&sol.u, &lag.u);
                assert!(
                    err <= bound + floor,
                    "{name} tol={tol}: ‖u − u_lag‖ = {err:e} > {bound:e}"
                );
                if !adaptive {
                    assert!(err <= prev_err * 1.0001 + floor, "{name}: not approaching");
                    prev_err = err;
                }
            }
        }
    }
}

/// Eq. 17 per constraint (methods.md §3), recomputed from K, q, û and u0: on every penalized
/// constraint, clipped at 0, with the obstacle's side for unilateral constraints.
///
/// `None` where the implementation takes its extra shortcut "penetration(g0) ≤ δ ⇒ ε = 0",
/// which methods.md does not have (on the bilateral beam with δ = 0.5, the tip's axial tie has
/// |g0| = 0.29 ≤ δ: methods.md's formula gives 110, the code 0). Those constraints are not
/// compared here; the shortcut's harmful case is `spring_penalizes_constraints_that_become_violated`.
fn spring_expected(p: &Problem, delta: f64, active: &[bool]) -> Vec<Option<f64>> {
    let u0 = u0_of(p);
    p.constraints
        .iter()
        .enumerate()
        .map(|(c, con)| {
            let g0 = u0[con.dof] - con.limit;
            if !active[c] {
                return Some(0.0);
            }
            if con.kind.penetration(g0) <= delta {
                return None;
            }
            let s = match con.kind {
                ConstraintKind::Upper => 1.0,
                ConstraintKind::Lower => -1.0,
                ConstraintKind::Bilateral => g0.signum(),
            };
            let k = p.k.get(con.dof, con.dof);
            Some(((p.q[con.dof] - k * (con.limit + s * delta)) / (s * delta)).max(0.0))
        })
        .collect()
}

/// Eq. 28 over the active set A: `(|Σ_{k∈A} K̄_ik û_k − q_i| − Σ_{k∈A} K̄_ik δ)/δ`, clipped at 0.
fn eq28_expected(p: &Problem, delta: f64, active: &[bool]) -> Vec<f64> {
    let k = dense(&p.k);
    let idx: Vec<usize> = (0..p.m()).filter(|&c| active[c]).collect();
    let kbar = DMatrix::from_fn(idx.len(), idx.len(), |i, j| {
        k[(p.constraints[idx[i]].dof, p.constraints[idx[j]].dof)]
    });
    let uh = DVector::from_iterator(idx.len(), idx.iter().map(|&c| p.constraints[c].limit));
    let qbar = DVector::from_iterator(idx.len(), idx.iter().map(|&c| p.q[p.constraints[c].dof]));
    let lhs = &kbar * uh - qbar;
    let kd = &kbar * DVector::from_element(idx.len(), delta);
    let mut eps = vec![0.0; p.m()];
    for (i, &c) in idx.iter().enumerate() {
        eps[c] = ((lhs[i].abs() - kd[i]) / delta).max(0.0);
    }
    eps
}

/// The active set a penalty strategy ends with: bilateral + violated at the returned u.
fn final_active(p: &Problem, u: &[f64]) -> Vec<bool> {
    (0..p.m()).map(|c| strategy::violated(p, c, u)).collect()
}

/// Absolute tolerance for a recomputed penalty: the formulas add O(m) products of K entries
/// and limits (magnitude ‖K‖·scale) and divide by δ.
fn formula_tol(p: &Problem, delta: f64, scale: f64) -> f64 {
    C_ROUND * (p.m() as f64 + 1.0) * f64::EPSILON * p.k.max_abs() * scale / delta
}

#[test]
fn spring_and_paper_penalties_match_their_formulas() {
    let mut compared = 0;
    for (name, p) in all_scenes() {
        let u0 = u0_of(&p);
        let scale = inf(&u0).max(inf(&limits(&p))).max(inf(&p.q));
        for delta in [0.5, 0.1, 0.01] {
            let sp = strategy::solve(&p, Method::spring(delta)).unwrap();
            let pa = strategy::solve(&p, Method::paper(delta)).unwrap();
            // u0 enters Eq. 17 through s = sign(g0) and the "already within δ" test; the
            // solver's u0 differs from ours by rounding (cond K), negligible for these scenes.
            let tol = formula_tol(&p, delta, scale);
            let want_sp = spring_expected(&p, delta, &final_active(&p, &sp.u));
            let want_pa = eq28_expected(&p, delta, &final_active(&p, &pa.u));
            for c in 0..p.m() {
                if let Some(w) = want_sp[c] {
                    assert!(
                        (sp.penalties[c] - w).abs() <= tol,
                        "{name} δ={delta} spring c={c}: {} vs Eq. 17 {w}",
                        sp.penalties[c]
                    );
                    compared += usize::from(w > 0.0);
                }
                assert!(
                    (pa.penalties[c] - want_pa[c]).abs() <= tol,
                    "{name} δ={delta} paper c={c}: {} vs Eq. 28 {}",
                    pa.penalties[c],
                    want_pa[c]
                );
                compared += usize::from(want_pa[c] > 0.0);
            }
        }
    }
    assert!(compared >= 20, "only {compared} nonzero penalties compared");
}

/// Ground —k— u₀ —k— u₁ —k— u₂ ← P (k = 1, P = 1; free: u = (1, 2, 3)); `upper` obstacle
/// u₂ ≤ 0.6 (violated by u0) and `lower` obstacle u₁ ≥ 1 (NOT violated by u0: u0₁ = 2).
fn three_spring_chain() -> Problem {
    Problem::new(
        Stiffness::from_rows(&[
            vec![2.0, -1.0, 0.0],
            vec![-1.0, 2.0, -1.0],
            vec![0.0, -1.0, 1.0],
        ])
        .unwrap(),
        vec![0.0, 0.0, 1.0],
        vec![
            Constraint {
                dof: 2,
                limit: 0.6,
                kind: ConstraintKind::Upper,
            },
            Constraint {
                dof: 1,
                limit: 1.0,
                kind: ConstraintKind::Lower,
            },
        ],
    )
    .unwrap()
}

/// Regression (fixed bug): a unilateral constraint that is not violated by u0 but becomes
/// violated once other constraints are penalized enters the active set; an earlier version
/// judged "already within δ" by the *unconstrained* g0 and silently gave it ε = 0.
/// methods.md §3 applies Eq. 17 to every penalized constraint.
///
/// Hand computation (δ = 0.1): iteration 1 penalizes u₂ only, ε₀ = (q₂ − k₂₂(û + δ))/δ
/// = (1 − 0.7)/0.1 = 3; the flexibility at u₂ is S = 3, so g = g0/(1 + Sε) = 2.4/10 = 0.24 and
/// u = (0.28, 0.56, 0.84). Now u₁ = 0.56 < 1 violates its obstacle, so iteration 2 adds it with
/// Eq. 17 (s = −1): ε₁ = (k₁₁(û − δ) − q₁)/δ = 2·0.9/0.1 = 18. The final system
/// `[[2,−1,0],[−1,20,−1],[0,−1,4]] u = (0, 18, 2.8)` gives u = (17, 34, 33)/35.
#[test]
fn spring_penalizes_constraints_that_become_violated() {
    let p = three_spring_chain();
    let delta = 0.1;
    let sol = strategy::solve(&p, Method::spring(delta)).unwrap();
    let eq17 = (p.k.get(1, 1) * (1.0 - delta) - p.q[1]) / delta;
    // Same three flops as the library's formula, on data of size ≤ 2: a few roundings.
    assert!(
        (sol.penalties[1] - eq17).abs() <= C_ROUND * f64::EPSILON * eq17,
        "ε₁ = {} (Eq. 17: {eq17}); warnings = {:?}",
        sol.penalties[1],
        sol.warnings
    );
    assert!((sol.penalties[0] - 3.0).abs() <= C_ROUND * f64::EPSILON * 3.0);
    let tol = rounding_tol(cond_of(&metrics::system_matrix(&p, &sol)), 3, 3.0);
    for (got, want) in sol.u.iter().zip([17.0 / 35.0, 34.0 / 35.0, 33.0 / 35.0]) {
        assert!((got - want).abs() <= tol, "u = {:?}", sol.u);
    }
    assert_eq!(sol.stats.iterations, 2);
    // condensed on the same chain keeps both within δ.
    let cd = strategy::solve(&p, Method::condensed(delta)).unwrap();
    assert!(cd.max_penetration <= delta);
}

#[test]
fn paper_eq28_on_the_beam_recomputed_matches_eq35() {
    // Our independent Eq. 28 reproduces the paper's printed Eq. 35 (so the formula used in the
    // previous test is the paper's).
    let p = paper::problem();
    let e = eq28_expected(&p, 0.1, &[true; 3]);
    assert!((e[0] - 501.9).abs() <= 0.05);
    assert!((e[1] - 1390.0).abs() <= 0.5);
    assert!((e[2] - 557.0).abs() <= 0.5);
}

#[test]
fn clipped_penalties_are_warned() {
    // Beam, tip transverse `upper` at û = 0.45 alone (u0 = 51.4 violates it). K[7,7] = 2.1 and
    // q[7] = 1: Eq. 28 = (|2.1·0.45 − 1| − 2.1·0.1)/0.1 = (0.055 − 0.21)/0.1 < 0 → clipped to 0
    // with a warning.
    let k = paper::frame().assemble(false).unwrap();
    let p = Problem::new(
        k,
        paper::LOAD.to_vec(),
        vec![Constraint {
            dof: 7,
            limit: 0.45,
            kind: ConstraintKind::Upper,
        }],
    )
    .unwrap();
    let sol = strategy::solve(&p, Method::paper(0.1)).unwrap();
    assert_eq!(sol.penalties[0], 0.0);
    assert!(
        sol.warnings.iter().any(|w| w.contains("negative penalty")),
        "{:?}",
        sol.warnings
    );
    // Unpenalized ⇒ u = u0 and the penetration is the unconstrained one (51.4 − 0.45).
    let u0 = u0_of(&p);
    assert!((sol.max_penetration - (u0[7] - 0.45)).abs() <= rounding_tol(cond_of(&p.k), 9, 60.0));
}

// ----------------------------------------------------------------------------------------
// 6. Consistency of every solution
// ----------------------------------------------------------------------------------------

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
                assert_eq!(sol.gaps[c], sol.u[con.dof] - con.limit, "{tag}");
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
                r[con.dof] += f;
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

// ----------------------------------------------------------------------------------------
// 7. Dense vs sparse storage
// ----------------------------------------------------------------------------------------

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

// ----------------------------------------------------------------------------------------
// 8. Error paths
// ----------------------------------------------------------------------------------------

#[test]
fn bad_knobs_are_rejected_with_clear_messages() {
    for name in ["spring", "paper", "condensed"] {
        for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            let e = Method::from_name(
                name,
                Knobs {
                    delta: Some(bad),
                    ..Default::default()
                },
            )
            .unwrap_err();
            let msg = e.to_string();
            assert!(matches!(e, Error::Input(_)), "{name} δ={bad}: {e:?}");
            assert!(msg.contains("--delta") && msg.contains("> 0"), "{msg}");
            assert!(msg.contains(&format!("{bad}")), "{msg} should quote {bad}");
        }
        let e = Method::from_name(name, Knobs::default()).unwrap_err();
        assert!(e.to_string().contains("needs --delta"), "{e}");
    }
    for (name, knobs) in [
        (
            "constant",
            Knobs {
                eps: Some(-1.0),
                ..Default::default()
            },
        ),
        (
            "scaled",
            Knobs {
                factor: Some(0.0),
                ..Default::default()
            },
        ),
        (
            "augmented",
            Knobs {
                eps: Some(1.0),
                tol: Some(f64::NAN),
                ..Default::default()
            },
        ),
    ] {
        assert!(matches!(
            Method::from_name(name, knobs),
            Err(Error::Input(_))
        ));
    }
    let e = Method::from_name("penalty", Knobs::default()).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("unknown method") && msg.contains("'penalty'"),
        "{msg}"
    );
    for valid in registry::names() {
        assert!(msg.contains(valid), "{msg} should list {valid}");
    }
    // Valid knobs round-trip.
    let m = Method::from_name(
        "condensed",
        Knobs {
            delta: Some(0.1),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(m, Method::condensed(0.1));
}

/// Two unit springs in series with no spring to ground: K = k[[1, −1], [−1, 1]] is singular
/// (rigid translation); a bilateral tie of DOF 0 at û removes it.
fn floating_chain(k: f64, q: [f64; 2], uh: f64) -> Problem {
    Problem::new(
        Stiffness::from_rows(&[vec![k, -k], vec![-k, k]]).unwrap(),
        q.to_vec(),
        vec![Constraint {
            dof: 0,
            limit: uh,
            kind: ConstraintKind::Bilateral,
        }],
    )
    .unwrap()
}

#[test]
fn singular_k_fails_for_condensed_but_not_for_lagrange_or_constant() {
    let (k, q, uh) = (4.0, [1.5, -0.5], 0.25);
    let p = floating_chain(k, q, uh);
    for m in [Method::condensed(0.1), Method::spring(0.1)] {
        match strategy::solve(&p, m) {
            Err(Error::Singular(msg)) => assert!(msg.contains("K is singular"), "{msg}"),
            other => panic!("{}: expected Error::Singular, got {other:?}", m.name()),
        }
    }
    // Hand solution: row 1 gives k(u1 − u0) = q1; the tie carries the total load,
    // λ = q0 + q1 (K u = q − D λ); lagrange has u0 = û, the penalty u0 = û + λ/ε.
    let lam = q[0] + q[1];
    let sol = strategy::solve(&p, Method::lagrange()).unwrap();
    let cond = cond_of(&metrics::system_matrix(&p, &sol));
    let tol = rounding_tol(cond, 3, 1.0);
    assert!((sol.u[0] - uh).abs() <= tol);
    assert!((sol.u[1] - (uh + q[1] / k)).abs() <= tol);
    assert!((sol.forces[0] - lam).abs() <= tol * k);
    for eps in [10.0, 1e4] {
        let sol = strategy::solve(&p, Method::constant(eps)).unwrap();
        let cond = cond_of(&metrics::system_matrix(&p, &sol));
        let tol = rounding_tol(cond, 2, 1.0);
        let u0 = uh + lam / eps;
        assert!((sol.u[0] - u0).abs() <= tol, "ε={eps}: {}", sol.u[0]);
        assert!((sol.u[1] - (u0 + q[1] / k)).abs() <= tol);
        assert!((sol.forces[0] - lam).abs() <= tol * eps);
    }
}
