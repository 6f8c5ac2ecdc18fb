//! Property tests over small randomized cantilever scenes, and what they found about the
//! paper's Eq. 28.
//!
//! Scenes: `Frame::cantilever(n_el ∈ 2..=8, L ∈ 10..100, rectangle(E ∈ 1e3..1e5, b, h ∈
//! 0.5..2))`, loads in [−1, 1] on a random subset of the free DOFs, 1–4 constraints on distinct
//! transverse DOFs whose limits are placed relative to the unconstrained displacement u0 so that
//! contact happens (`upper`: û = u0[d] − f|u0[d]|, `lower`: û = u0[d] + f|u0[d]|, bilateral:
//! either side; f ∈ 0.1..0.9), δ = r·max_c |u0[d_c]| with r ∈ 10^(−4..−1).
//!
//! Note that |u0[d]|/|û| ≤ 1/(1 − 0.9) = 10: no scene is "extreme" in the paper's sense
//! ("displacements without contact a few orders greater than the contact limits").
//!
//! Findings (see [`paper_eq28_counterexample`] and [`paper_eq28_fails_one_order_of_magnitude`]):
//! the paper's claim that Eq. 28 keeps the penetration below δ except in extreme cases is false
//! on such scenes; ≈14% of random scenes violate it (a 20 000-scene exploration during
//! development: 2 724 failures, worst penetration 2 558·δ), including single-constraint scenes.
//! For one constraint the exact criterion is proved and property-tested in
//! [`paper_single_constraint_criterion`]; for several constraints no honest characterisation
//! was found, so the generic claim is kept as an ignored property with its shrunk
//! counterexample committed in `proptest-regressions/properties.txt`.

use crate::common;

use common::dense::{dense, inf};
use nalgebra::{DMatrix, DVector};
use penalty_lab::conditioning;
use penalty_lab::metrics;
use penalty_lab::model::beam::{Frame, Section};
use penalty_lab::strategy::{self, Method, SystemKind};
use penalty_lab::system::{Constraint, ConstraintKind, Problem, Stiffness};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

// ----------------------------------------------------------------------------------------
// Tolerances and small dense algebra (nalgebra, independent of the library)
// ----------------------------------------------------------------------------------------

/// Safety constant of the rounding bounds (Higham: Cholesky / partial-pivoting LU have
/// backward error γ_{cn} with small c; 8 also covers right-hand-side assembly and gaps).
const C_ROUND: f64 = 8.0;

/// Forward-error tolerance for a quantity of magnitude `scale` from an n×n solve with 2-norm
/// condition number `cond`: `c · n · ε_mach · cond · scale`.
fn rounding_tol(cond: f64, n: usize, scale: f64) -> f64 {
    C_ROUND * n as f64 * f64::EPSILON * cond * scale
}

fn cond_of(k: &Stiffness) -> f64 {
    conditioning::cond2(k).expect("cond2").cond2
}

fn solve_dense(k: &DMatrix<f64>, b: &[f64]) -> Vec<f64> {
    k.clone()
        .lu()
        .solve(&DVector::from_column_slice(b))
        .expect("nonsingular")
        .iter()
        .copied()
        .collect()
}

// ----------------------------------------------------------------------------------------
// Scenes
// ----------------------------------------------------------------------------------------

/// The random inputs of a scene (everything else is derived from them).
#[derive(Clone, Debug)]
struct Spec {
    n_el: usize,
    length: f64,
    e: f64,
    b: f64,
    h: f64,
    /// Load on every free DOF (3 per node 1..=n_el, in `Frame::dof` order).
    loads: Vec<f64>,
    /// (node, kind 0 bilateral / 1 upper / 2 lower, fraction f, bilateral side: true = below u0)
    cons: Vec<(usize, u8, f64, bool)>,
    /// δ = 10^log10_r · max_c |u0[d_c]|.
    log10_r: f64,
}

struct Scene {
    problem: Problem,
    u0: Vec<f64>,
    delta: f64,
}

fn kind_of(k: u8) -> ConstraintKind {
    match k {
        0 => ConstraintKind::Bilateral,
        1 => ConstraintKind::Upper,
        _ => ConstraintKind::Lower,
    }
}

/// Builds the scene; `None` if every constrained DOF has u0 = 0 (δ would be 0).
fn build(spec: &Spec, sparse: bool) -> Option<Scene> {
    let frame = Frame::cantilever(
        spec.n_el,
        spec.length,
        Section::rectangle(spec.e, spec.b, spec.h),
    )
    .unwrap();
    let k = frame.assemble(sparse).unwrap();
    let q = spec.loads.clone();
    let u0 = solve_dense(&dense(&k), &q);
    let mut cons = Vec::new();
    let mut amax = 0.0f64;
    for &(node, kind, f, below) in &spec.cons {
        let d = frame.dof(node, 1).unwrap();
        let a = u0[d].abs();
        amax = amax.max(a);
        let kind = kind_of(kind);
        let limit = match kind {
            ConstraintKind::Upper => u0[d] - f * a,
            ConstraintKind::Lower => u0[d] + f * a,
            ConstraintKind::Bilateral if below => u0[d] - f * a,
            ConstraintKind::Bilateral => u0[d] + f * a,
        };
        cons.push(Constraint::on_dof(d, limit, kind));
    }
    if amax == 0.0 {
        return None;
    }
    let delta = 10f64.powf(spec.log10_r) * amax;
    Some(Scene {
        problem: Problem::new(k, q, cons).unwrap(),
        u0,
        delta,
    })
}

/// Random scenes with 1..=`max_m` constraints.
fn spec_strategy(max_m: usize) -> impl Strategy<Value = Spec> {
    (2usize..=8).prop_flat_map(move |n_el| {
        let nodes: Vec<usize> = (1..=n_el).collect();
        (
            Just(n_el),
            10.0..100.0f64,
            1e3..1e5f64,
            0.5..2.0f64,
            0.5..2.0f64,
            prop::collection::vec((any::<bool>(), -1.0..1.0f64), 3 * n_el),
            prop::sample::subsequence(nodes, 1..=n_el.min(max_m)).prop_flat_map(|ns| {
                let len = ns.len();
                (
                    Just(ns),
                    prop::collection::vec((0u8..3, 0.1..0.9f64, any::<bool>()), len),
                )
            }),
            -4.0..-1.0f64,
        )
            .prop_map(|(n_el, length, e, b, h, loads, (ns, ks), log10_r)| Spec {
                n_el,
                length,
                e,
                b,
                h,
                loads: loads
                    .into_iter()
                    .map(|(on, v)| if on { v } else { 0.0 })
                    .collect(),
                cons: ns
                    .into_iter()
                    .zip(ks)
                    .map(|(n, (k, f, s))| (n, k, f, s))
                    .collect(),
                log10_r,
            })
    })
}

fn config() -> ProptestConfig {
    ProptestConfig {
        // 128 by default (the whole file runs in well under a second in release);
        // PROPTEST_CASES overrides it for deeper local runs.
        cases: std::env::var("PROPTEST_CASES")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(128),
        // Integration tests have no lib.rs beside them, so proptest's default location would
        // be tests/properties.proptest-regressions; keep the crate-level directory instead
        // (cargo runs tests from the package root).
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "proptest-regressions/properties.txt",
        ))),
        ..ProptestConfig::default()
    }
}

/// Scale of the displacements of a scene (for rounding tolerances).
fn disp_scale(sc: &Scene) -> f64 {
    let lim: Vec<f64> = sc.problem.constraints.iter().map(|c| c.limit).collect();
    inf(&sc.u0).max(inf(&lim)).max(sc.delta)
}

// ----------------------------------------------------------------------------------------
// Properties
// ----------------------------------------------------------------------------------------

proptest! {
    #![proptest_config(config())]

    /// (a) `condensed` never exceeds δ (exactly, in floating point), hits it where it penalizes
    /// (within rounding), and ε ≥ 0.
    #[test]
    fn condensed_never_exceeds_delta(spec in spec_strategy(4)) {
        let Some(sc) = build(&spec, false) else { return Ok(()) };
        let p = &sc.problem;
        let sol = strategy::solve(p, Method::condensed(sc.delta)).unwrap();
        // u = u0 − K⁻¹D r carries K's forward error on top of the contract's relative 1e-9.
        let tol = rounding_tol(cond_of(&p.k), p.n(), disp_scale(&sc));
        let pen = p.penetrations(&sol.u);
        for (c, (&e, &pc)) in sol.penalties.iter().zip(&pen).enumerate() {
            prop_assert!(e >= 0.0, "ε[{}] = {}", c, e);
            // The contract, in floating point: no tolerance.
            prop_assert!(pc <= sc.delta, "c = {}: penetration {} > δ = {}", c, pc, sc.delta);
            if e > 0.0 {
                prop_assert!(
                    (pc - sc.delta).abs() <= 1e-9 * sc.delta + tol,
                    "penalized c = {}: penetration {} ≠ δ = {}", c, pc, sc.delta
                );
            }
        }
        // u solves its penalized system (K + D E Dᵀ) u = q + D E û; u is built as u0 − K⁻¹D r,
        // so the residual carries K's forward error (‖A‖·ε·cond(K)·‖u‖). This also catches a
        // wrong-sign force hidden by clipping ε at 0.
        let mut a = dense(&p.k);
        let mut rhs = p.q.clone();
        for (con, &e) in p.constraints.iter().zip(&sol.penalties) {
            a[(con.single_dof().unwrap(), con.single_dof().unwrap())] += e;
            rhs[con.single_dof().unwrap()] += e * con.limit;
        }
        let au = &a * DVector::from_column_slice(&sol.u);
        let res = (0..p.n()).map(|i| (au[i] - rhs[i]).abs()).fold(0.0, f64::max);
        let anorm = a.abs().row_sum().max();
        let rtol = rounding_tol(cond_of(&p.k), p.n(), anorm * disp_scale(&sc) + inf(&rhs));
        prop_assert!(res <= rtol, "penalized residual {} > {}", res, rtol);
        // The only acceptable warning: the box QP's primal-dual update cycled and the
        // single-change fallback finished the job (the checks above still hold).
        prop_assert!(
            sol.warnings.iter().all(|w| w.contains("converged with single changes")),
            "{:?}", sol.warnings
        );
    }

    /// (b) `lagrange`: zero penetration, reaction signs (K u = q − D λ: upper λ ≥ 0, lower
    /// λ ≤ 0), complementarity, equilibrium.
    #[test]
    fn lagrange_is_exact_with_right_signs(spec in spec_strategy(4)) {
        let Some(sc) = build(&spec, false) else { return Ok(()) };
        let p = &sc.problem;
        let sol = strategy::solve(p, Method::lagrange()).unwrap();
        prop_assert!(sol.warnings.is_empty(), "{:?}", sol.warnings);
        let SystemKind::SaddlePoint { active } = &sol.system else {
            return Err(TestCaseError::fail("lagrange must return a saddle-point system"));
        };
        let sys = metrics::system_matrix(p, &sol);
        let tol = rounding_tol(cond_of(&sys), sys.n(), disp_scale(&sc).max(inf(&sol.u)));
        prop_assert!(sol.max_penetration <= tol, "penetration {} > {}", sol.max_penetration, tol);
        for (c, con) in p.constraints.iter().enumerate() {
            let lam = sol.forces[c];
            match con.kind {
                ConstraintKind::Upper => prop_assert!(lam >= 0.0, "upper {} force {}", c, lam),
                ConstraintKind::Lower => prop_assert!(lam <= 0.0, "lower {} force {}", c, lam),
                ConstraintKind::Bilateral => prop_assert!(active.contains(&c)),
            }
            if active.contains(&c) {
                prop_assert!(sol.gaps[c].abs() <= tol, "active {} gap {}", c, sol.gaps[c]);
            } else {
                prop_assert_eq!(lam, 0.0);
            }
        }
        // Equilibrium: ‖K u + D λ − q‖∞ within the backward error of the saddle-point solve.
        let k = dense(&p.k);
        let ku = &k * DVector::from_column_slice(&sol.u);
        let mut res: Vec<f64> = (0..p.n()).map(|i| ku[i] - p.q[i]).collect();
        for (con, lam) in p.constraints.iter().zip(&sol.forces) {
            res[con.single_dof().unwrap()] += lam;
        }
        let knorm = k.abs().row_sum().max();
        let rtol = C_ROUND * sys.n() as f64 * f64::EPSILON
            * (knorm * inf(&sol.u) + inf(&sol.forces) + inf(&p.q));
        prop_assert!(inf(&res) <= rtol, "residual {} > {}", inf(&res), rtol);
    }

    /// For one constraint the paper's Eq. 28 keeps the penetration ≤ δ **iff**
    /// `ε₂₈⁺ ≥ ε* = S⁻¹(|g0| − δ)/δ`, where `ε₂₈⁺ = max(0, (|K_dd û − q_d| − K_dd δ)/δ)` and
    /// `S = (K⁻¹)_dd` (exact: a single penalized constraint has `g = g0/(1 + S ε)`). With no
    /// load on d this reads `κ(|û| − δ) ≥ |g0| − δ`, `κ = K_dd (K⁻¹)_dd ≥ 1`: Eq. 28 fails when
    /// the obstacle is closer to the rest position than to u0 by more than the factor κ — it
    /// does not take "orders of magnitude". Both directions are checked (cases within rounding
    /// of the threshold are skipped).
    #[test]
    fn paper_single_constraint_criterion(spec in spec_strategy(1)) {
        let Some(sc) = build(&spec, false) else { return Ok(()) };
        let p = &sc.problem;
        let delta = sc.delta;
        let con = p.constraints[0].clone();
        let d = con.single_dof().unwrap();
        let sol = strategy::solve(p, Method::paper(delta)).unwrap();
        let g0 = sc.u0[d] - con.limit;
        if con.kind.penetration(g0) == 0.0 {
            prop_assert_eq!(sol.penalties[0], 0.0);
            return Ok(());
        }
        let kdd = p.k.get(d, d);
        let e_d: Vec<f64> = (0..p.n()).map(|i| f64::from(u8::from(i == d))).collect();
        let s = solve_dense(&dense(&p.k), &e_d)[d];
        let eps28 = (((kdd * con.limit - p.q[d]).abs() - kdd * delta) / delta).max(0.0);
        let eps_star = (g0.abs() - delta) / (s * delta);
        // S carries K's forward error; both penalties are O(K_dd·scale/δ).
        let cond = cond_of(&p.k);
        let margin = rounding_tol(cond, p.n(), kdd * disp_scale(&sc) / delta);
        prop_assume!((eps28 - eps_star).abs() > margin);
        let within = sol.max_penetration <= delta;
        prop_assert_eq!(
            within,
            eps28 > eps_star,
            "ε28 = {}, ε* = {}, penetration/δ = {}", eps28, eps_star, sol.max_penetration / delta
        );
        // And the penetration itself is the Schur prediction |g0|/(1 + S ε28⁺).
        let predicted = g0.abs() / (1.0 + s * eps28);
        let ptol = rounding_tol(cond_of(&metrics::system_matrix(p, &sol)).max(cond), p.n(),
            disp_scale(&sc));
        prop_assert!((sol.max_penetration - predicted).abs() <= ptol,
            "penetration {} vs predicted {}", sol.max_penetration, predicted);
    }

    /// Dense and sparse storage of the same random scene agree for every strategy.
    #[test]
    fn dense_and_sparse_agree(spec in spec_strategy(4)) {
        let (Some(sd), Some(ss)) = (build(&spec, false), build(&spec, true)) else {
            return Ok(());
        };
        prop_assert!(ss.problem.k.is_sparse());
        let delta = sd.delta;
        for method in [
            Method::constant(1e3),
            Method::scaled(10.0),
            Method::spring(delta),
            Method::paper(delta),
            Method::condensed(delta),
            Method::lagrange(),
            Method::augmented(10.0, delta, true),
        ] {
            let a = strategy::solve(&sd.problem, method).unwrap();
            let b = strategy::solve(&ss.problem, method).unwrap();
            let cond = cond_of(&metrics::system_matrix(&sd.problem, &a)).max(cond_of(&sd.problem.k));
            let tol = 2.0 * rounding_tol(cond, sd.problem.n() + sd.problem.m(), 1.0);
            let du = a.u.iter().zip(&b.u).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
            prop_assert!(du <= tol * inf(&a.u), "{}: Δu = {} (‖u‖ = {})", method.name(), du, inf(&a.u));
            let emax = inf(&a.penalties).max(1.0);
            for c in 0..sd.problem.m() {
                prop_assert!((a.penalties[c] - b.penalties[c]).abs() <= tol * emax,
                    "{}: ε[{}] {} vs {}", method.name(), c, a.penalties[c], b.penalties[c]);
            }
        }
    }

    /// The paper's claim, as stated: "Eq. 28 keeps the penetration below δ except in extreme
    /// cases (u0 a few orders of magnitude beyond û)". None of these scenes is extreme
    /// (|u0[d]|/|û| ≤ 10), yet the claim fails on ≈14% of them; proptest's shrunk
    /// counterexample is committed in proptest-regressions/properties.txt and written out in
    /// [`paper_eq28_counterexample`].
    #[test]
    #[ignore = "documents a counterexample to the paper's claim (Eq. 28 can exceed δ on non-extreme scenes), see paper_eq28_counterexample"]
    fn paper_keeps_penetration_below_delta(spec in spec_strategy(4)) {
        let Some(sc) = build(&spec, false) else { return Ok(()) };
        let p = &sc.problem;
        let sol = strategy::solve(p, Method::paper(sc.delta)).unwrap();
        let tol = rounding_tol(cond_of(&metrics::system_matrix(p, &sol)), p.n(), disp_scale(&sc));
        prop_assert!(
            sol.max_penetration <= sc.delta + tol,
            "δ = {}, max penetration = {}, ε = {:?}, gaps = {:?}, g0 = {:?}, warnings = {:?}",
            sc.delta, sol.max_penetration, sol.penalties, sol.gaps, p.gaps(&sc.u0), sol.warnings
        );
    }
}

// ----------------------------------------------------------------------------------------
// Deterministic counterexamples to the paper's claim
// ----------------------------------------------------------------------------------------

/// Eq. 28 over all constraints (all active), clipped at 0, computed here from K, q, û.
fn eq28(p: &Problem, delta: f64) -> Vec<f64> {
    let m = p.m();
    (0..m)
        .map(|i| {
            let di = p.constraints[i].single_dof().unwrap();
            let kbar_u: f64 = (0..m)
                .map(|k| {
                    p.k.get(di, p.constraints[k].single_dof().unwrap()) * p.constraints[k].limit
                })
                .sum();
            let kbar_d: f64 = (0..m)
                .map(|k| p.k.get(di, p.constraints[k].single_dof().unwrap()))
                .sum::<f64>()
                * delta;
            (((kbar_u - p.q[di]).abs() - kbar_d) / delta).max(0.0)
        })
        .collect()
}

/// Penalized gaps predicted by the Schur relation `g = (I + S E)⁻¹ g0`, `S = DᵀK⁻¹D`.
fn predicted_gaps(p: &Problem, u0: &[f64], eps: &[f64]) -> Vec<f64> {
    let m = p.m();
    let kinv = dense(&p.k).try_inverse().unwrap();
    let s = DMatrix::from_fn(m, m, |i, j| {
        kinv[(
            p.constraints[i].single_dof().unwrap(),
            p.constraints[j].single_dof().unwrap(),
        )]
    });
    let a = DMatrix::identity(m, m) + s * DMatrix::from_diagonal(&DVector::from_column_slice(eps));
    let g0 = DVector::from_iterator(m, p.gaps(u0));
    a.lu().solve(&g0).unwrap().iter().copied().collect()
}

/// proptest's minimal counterexample to `paper_keeps_penetration_below_delta` (its inputs,
/// copied from proptest-regressions/properties.txt — inputs, not expected outputs):
///
/// a 2-element cantilever, L = 10, E = 1000, b = h = 0.5 (EJ = 5.208), loaded only by a tip
/// moment M = 0.9371; node 1 has a `lower` obstacle 10% above its rest deflection
/// (f = 0.1), the tip a bilateral tie 33.7% below its deflection; δ = 10^−2.808·max|u0[d]|.
/// u0 and the limits are of the same order (|u0|/|û| = 0.91 and 1.51): not an extreme case.
///
/// Why Eq. 28 fails here: it estimates each constraint's penalty from `K̄ = DᵀKD`, i.e. from
/// the *local* stiffness rows with the neighbouring constrained DOFs held at their limits. For
/// node 1, `(K̄û)₁ = 24EJ/l³·û₁ − 12EJ/l³·û₂` nearly cancels (û₂ ≈ 2.4 û₁), so Eq. 28 asks for a
/// small ε₁ ≈ 36. But the true coupling runs through the free rotations: pushing the tip down
/// by 3.03 to its tie drags node 1 further below its obstacle, and holding it within δ needs
/// the condensed stiffness S⁻¹ — a larger penalty. The node-1 penetration ends ≈1.31·δ.
#[test]
fn paper_eq28_counterexample() {
    let (n_el, length, e, b, h) = (2, 10.0, 1000.0, 0.5, 0.5);
    let moment = 0.9371037401181372;
    let (f_lower, f_tie) = (0.1, 0.33667363965168035);
    let log10_r = -2.8081991506169097;

    let frame = Frame::cantilever(n_el, length, Section::rectangle(e, b, h)).unwrap();
    let k = frame.assemble(false).unwrap();
    let mut q = vec![0.0; frame.n_dofs()];
    q[frame.dof(2, 2).unwrap()] = moment;
    // Closed form for an end moment (cubic elements are exact): w(x) = M x²/(2EJ).
    let ej = e * b * h.powi(3) / 12.0;
    let w = |x: f64| moment * x * x / (2.0 * ej);
    let (w1, w2) = (w(5.0), w(10.0));
    let (d1, d2) = (frame.dof(1, 1).unwrap(), frame.dof(2, 1).unwrap());
    let cons = vec![
        Constraint::on_dof(d1, w1 + f_lower * w1, ConstraintKind::Lower),
        Constraint::on_dof(d2, w2 - f_tie * w2, ConstraintKind::Bilateral),
    ];
    let delta = 10f64.powf(log10_r) * w1.max(w2);
    let p = Problem::new(k, q, cons).unwrap();
    let u0 = solve_dense(&dense(&p.k), &p.q);
    let cond_k = cond_of(&p.k);
    assert!((u0[d1] - w1).abs() <= rounding_tol(cond_k, p.n(), w2));
    assert!((u0[d2] - w2).abs() <= rounding_tol(cond_k, p.n(), w2));
    // Not extreme: u0 and û of the same order.
    for c in &p.constraints {
        let ratio = u0[c.single_dof().unwrap()].abs() / c.limit.abs();
        assert!((0.5..2.0).contains(&ratio), "|u0|/|û| = {ratio}");
    }

    let sol = strategy::solve(&p, Method::paper(delta)).unwrap();
    assert!(
        sol.warnings.is_empty(),
        "no penalty was clipped: {:?}",
        sol.warnings
    );
    // Both constraints stay penalized with Eq. 28's values (recomputed here).
    let want = eq28(&p, delta);
    let scale = w2;
    let etol = rounding_tol(cond_k, p.n(), p.k.max_abs() * scale / delta);
    for (c, (&got, &w)) in sol.penalties.iter().zip(&want).enumerate() {
        assert!(w > 0.0);
        assert!((got - w).abs() <= etol, "ε[{c}] = {got} vs Eq. 28 {w}");
    }
    // How much it exceeds δ, predicted independently by the Schur relation.
    let g = predicted_gaps(&p, &u0, &want);
    let pen0 = ConstraintKind::Lower.penetration(g[0]);
    let ptol = rounding_tol(cond_of(&metrics::system_matrix(&p, &sol)), p.n(), scale);
    assert!((sol.max_penetration - pen0).abs() <= ptol);
    assert!(g[1].abs() < delta, "the tie itself is within δ");
    let excess = sol.max_penetration / delta;
    assert!(
        excess > 1.3 && excess < 1.32,
        "penetration/δ = {excess} (expected ≈ 1.31 from the Schur prediction {})",
        pen0 / delta
    );
    // condensed, on the same scene, needs a larger penalty at node 1 and meets δ.
    let cd = strategy::solve(&p, Method::condensed(delta)).unwrap();
    assert!(cd.penalties[0] > sol.penalties[0]);
    assert!(cd.max_penetration <= delta);
}

/// A closed-form counterexample with ONE constraint and |u0|/|û| = 10 (one order of
/// magnitude, not "a few"): any cantilever with ≥ 2 elements, no load at node 1's transverse
/// DOF d, an `upper` obstacle at û = u0[d]/10 (f = 0.9). Eq. 28 gives
/// `ε = K_dd(û − δ)/δ` with `K_dd = 24EJ/l³`, while the flexibility is `S = l³/(3EJ)`, so
/// `κ = K_dd S = 8` and the penalized gap is `g = g0/(1 + Sε) = 0.9ρδ/(1 + 8(0.1ρ − 1))`
/// with ρ = u0/δ — above δ for every ρ > 10, tending to 1.125·δ as δ → 0.
#[test]
fn paper_eq28_fails_one_order_of_magnitude() {
    for (n_el, length, tip_load, rho) in [
        (2, 10.0, 1.0, 20.0),
        (4, 40.0, 0.3, 100.0),
        (8, 80.0, 2.0, 1e4),
    ] {
        let (e, b, h) = (2100.0, 1.0, 1.0);
        let frame = Frame::cantilever(n_el, length, Section::rectangle(e, b, h)).unwrap();
        let k = frame.assemble(false).unwrap();
        let mut q = vec![0.0; frame.n_dofs()];
        q[frame.dof(n_el, 1).unwrap()] = tip_load;
        // Tip load P on a cantilever: w(x) = P x²(3L − x)/(6EJ) (exact at the nodes).
        let ej = e * b * h.powi(3) / 12.0;
        let l_el = length / n_el as f64;
        let u0d = tip_load * l_el * l_el * (3.0 * length - l_el) / (6.0 * ej);
        let d = frame.dof(1, 1).unwrap();
        let uh = 0.1 * u0d;
        let delta = u0d / rho;
        let p = Problem::new(k, q, vec![Constraint::on_dof(d, uh, ConstraintKind::Upper)]).unwrap();
        // κ = K_dd · S = 8 from the element formulas.
        let kdd = 24.0 * ej / l_el.powi(3);
        let cond_k = cond_of(&p.k);
        assert!((p.k.get(d, d) - kdd).abs() <= 4.0 * f64::EPSILON * kdd);
        let sol = strategy::solve(&p, Method::paper(delta)).unwrap();
        let eps = kdd * (uh - delta) / delta;
        assert!((sol.penalties[0] - eps).abs() <= rounding_tol(1.0, p.n(), eps));
        let ratio = 0.9 * rho / (1.0 + 8.0 * (0.1 * rho - 1.0));
        let got = sol.max_penetration / delta;
        let tol = rounding_tol(
            cond_of(&metrics::system_matrix(&p, &sol)).max(cond_k),
            p.n(),
            rho,
        );
        assert!(
            (got - ratio).abs() <= tol,
            "n_el={n_el}: penetration/δ = {got}, closed form {ratio}"
        );
        assert!(got > 1.0, "Eq. 28 exceeds δ");
    }
}

/// proptest found (seed 3ef2… in proptest-regressions/properties.txt) a scene on which the
/// box QP of `condensed` cycles under the full primal–dual update and needs its single-change
/// fallback. The contract must still hold there: ε ≥ 0, penetration exactly δ where penalized,
/// ≤ δ elsewhere. The scene's inputs (not outputs) are copied from the shrunk case.
#[test]
fn condensed_cycling_scene_still_meets_the_contract() {
    let spec = Spec {
        n_el: 6,
        length: 13.273156109692719,
        e: 1000.0,
        b: 0.5,
        h: 0.5,
        loads: vec![
            0.0,
            0.0,
            0.0,
            0.0,
            -0.3126391550592928,
            0.0,
            0.0,
            -0.9478300144980898,
            0.0,
            0.0,
            0.0,
            0.8548141393088428,
            0.0,
            0.500511289930119,
            -0.7163541779731218,
            0.0,
            0.0,
            -0.42183919124562025,
        ],
        cons: vec![
            (1, 0, 0.6344393215374312, false),
            (4, 2, 0.6166694542273395, false),
            (5, 2, 0.10467321600433817, true),
            (6, 1, 0.6918206139848959, false),
        ],
        log10_r: -2.947171256091501,
    };
    let sc = build(&spec, false).unwrap();
    let p = &sc.problem;
    let sol = strategy::solve(p, Method::condensed(sc.delta)).unwrap();
    assert!(
        sol.warnings.iter().any(|w| w.contains("cycled")),
        "this scene exercises the fallback: {:?}",
        sol.warnings
    );
    let tol = rounding_tol(cond_of(&p.k), p.n(), disp_scale(&sc));
    let pen = p.penetrations(&sol.u);
    let mut penalized = 0;
    for (c, (&e, &pc)) in sol.penalties.iter().zip(&pen).enumerate() {
        assert!(e >= 0.0);
        if e > 0.0 {
            penalized += 1;
            assert!((pc - sc.delta).abs() <= 1e-9 * sc.delta + tol, "c = {c}");
        } else {
            assert!(pc <= sc.delta, "c = {c}");
        }
    }
    assert!(penalized >= 1);
    // The same gaps as the exact QP answer: lagrange-like KKT check through S = DᵀK⁻¹D — the
    // forces r = E g satisfy g = g0 − S r.
    let u0 = &sc.u0;
    let kinv = dense(&p.k).try_inverse().unwrap();
    let g0 = p.gaps(u0);
    for i in 0..p.m() {
        let sr: f64 = (0..p.m())
            .map(|j| {
                kinv[(
                    p.constraints[i].single_dof().unwrap(),
                    p.constraints[j].single_dof().unwrap(),
                )] * sol.forces[j]
            })
            .sum();
        assert!(
            (sol.gaps[i] - (g0[i] - sr)).abs() <= tol,
            "Schur relation at {i}: {} vs {}",
            sol.gaps[i],
            g0[i] - sr
        );
    }
}
