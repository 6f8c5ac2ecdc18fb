//! The elimination route of `condensed` and `lagrange` (large sparse K) against the dense
//! routes on the same problems: same final active sets, same u, penalties and forces to
//! rounding; from the same start, the same active sets at every iteration. The path-following
//! start, the exact contact set as a start and the PCG reuse of factors change the work, not
//! the answer.

use penalty_lab::generate::{generate, Family, GeneratorConfig};
use penalty_lab::linalg::{pcg, DiagonalPattern};
use penalty_lab::metrics::relative_error;
use penalty_lab::strategy::box_qp::{start_state, BoundState};
use penalty_lab::strategy::{self, condensed, eliminated, lagrange, Context, Method};
use penalty_lab::system::{ConstraintKind, Problem, Stiffness};

fn membranes() -> Vec<Problem> {
    crate::common::matrices::membranes((45, 60), 3, 4242)
}

/// Rounding tolerance for u: c·n·ε·cond(K), with cond(K) ≤ 8/(2π²h²) for these membranes.
fn tol_u(p: &Problem) -> f64 {
    let side = (p.n() as f64).sqrt();
    let cond = 8.0 / (2.0 * std::f64::consts::PI.powi(2)) * (side + 1.0).powi(2);
    64.0 * p.n() as f64 * f64::EPSILON * cond
}

#[test]
fn condensed_routes_agree() {
    for p in membranes() {
        assert!(eliminated::applies(&p), "n {}", p.n());
        let scale = p
            .constraints
            .iter()
            .map(|c| c.limit.abs())
            .fold(0.0, f64::max);
        for rel in [0.1, 0.01] {
            let delta = rel * scale;
            let a = condensed::solve_dense(Context::new(&p), delta).unwrap();
            let b = condensed::solve_eliminated(Context::new(&p), delta).unwrap();
            // Same optimal active set (the guard's refinements after it depend on rounding).
            let optimum = |s: &penalty_lab::strategy::Solution| {
                let k = s.stats.active_set_sizes.len() - s.stats.refinements;
                s.stats.active_set_sizes[k - 1]
            };
            assert_eq!(optimum(&a), optimum(&b));
            assert!(a.max_penetration <= delta && b.max_penetration <= delta);
            let e = relative_error(&b.u, &a.u);
            assert!(e <= tol_u(&p), "n {}: u differs by {e:e}", p.n());
            assert!(b.max_penetration <= delta * (1.0 + tol_u(&p)));
            for c in 0..p.m() {
                let (x, y) = (a.penalties[c], b.penalties[c]);
                assert_eq!(x == 0.0, y == 0.0, "constraint {c}: {x} vs {y}");
                if x > 0.0 {
                    // ε = r/g with |g| = δ: relative error of r, amplified by cond.
                    assert!((x - y).abs() <= 1e3 * tol_u(&p) * x, "ε_{c}: {x} vs {y}");
                }
            }
            // The public entry point takes the elimination route here.
            let s = strategy::solve(&p, Method::condensed(delta)).unwrap();
            assert_eq!(s.u, b.u);
        }
    }
}

#[test]
fn lagrange_routes_agree() {
    for p in membranes() {
        let a = lagrange::solve_saddle(Context::new(&p)).unwrap();
        let b = lagrange::solve_eliminated(Context::new(&p)).unwrap();
        assert_eq!(
            a.stats.active_set_sizes.last(),
            b.stats.active_set_sizes.last()
        );
        let e = relative_error(&b.u, &a.u);
        assert!(e <= tol_u(&p), "u differs by {e:e}");
        let fmax = a.forces.iter().fold(0.0f64, |m, f| m.max(f.abs()));
        for c in 0..p.m() {
            assert!(
                (a.forces[c] - b.forces[c]).abs() <= 1e3 * tol_u(&p) * fmax,
                "λ_{c}: {} vs {}",
                a.forces[c],
                b.forces[c]
            );
        }
        assert!(
            b.max_penetration
                <= tol_u(&p)
                    * p.constraints
                        .iter()
                        .map(|c| c.limit.abs())
                        .fold(0.0, f64::max)
        );
    }
}

/// Bilateral constraints are pinned; a dense K keeps the dense routes.
#[test]
fn route_selection() {
    let p = &membranes()[0];
    let mut cons = p.constraints.clone();
    cons.truncate(50);
    for c in &mut cons {
        c.kind = ConstraintKind::Bilateral;
    }
    let q = Problem::new(p.k.clone(), p.q.clone(), cons.clone()).unwrap();
    let a = lagrange::solve_saddle(Context::new(&q)).unwrap();
    let b = lagrange::solve_eliminated(Context::new(&q)).unwrap();
    assert!(relative_error(&b.u, &a.u) <= tol_u(&q));
    for c in &cons {
        assert!(
            (b.u[c.single_dof().unwrap()] - c.limit).abs() <= tol_u(&q) * c.limit.abs().max(1e-300)
        );
    }
    let dense = Stiffness::Dense(p.k.to_dense());
    assert!(!eliminated::applies(
        &Problem::new(dense, p.q.clone(), cons).unwrap()
    ));
}

/// Gap bounds of `condensed` at δ (lower constraints: `[−δ, ∞)`).
fn lower_bounds(p: &Problem, delta: f64) -> (Vec<f64>, Vec<f64>) {
    assert!(p
        .constraints
        .iter()
        .all(|c| c.kind == ConstraintKind::Lower));
    (vec![-delta; p.m()], vec![f64::INFINITY; p.m()])
}

fn scale(p: &Problem) -> f64 {
    p.constraints
        .iter()
        .map(|c| c.limit.abs())
        .fold(0.0, f64::max)
}

/// From the dense route's start (the bounds violated by u0), the elimination route visits the
/// same active sets as the dense box QP, iteration by iteration (exact arithmetic; the sets
/// are integers, so rounding would have to flip a decision to break it).
#[test]
fn plain_start_visits_the_dense_sets() {
    for p in membranes() {
        let delta = 0.1 * scale(&p);
        let a = condensed::solve_dense(Context::new(&p), delta).unwrap();
        let (lo, hi) = lower_bounds(&p, delta);
        let mut ctx = Context::new(&p);
        let g0 = ctx.g0().unwrap();
        let plain = start_state(&g0, &lo, &hi, None);
        let b = eliminated::box_solve(&mut ctx, &lo, &hi, Some(plain)).unwrap();
        let k = a.stats.active_set_sizes.len() - a.stats.refinements;
        assert_eq!(a.stats.active_set_sizes[..k], b.sizes[..]);
    }
}

/// Path following on an obstacle problem with thousands of violated bounds: the same optimum
/// as the plain start (unique: strictly convex QP), in fewer factorizations.
#[test]
fn path_following_same_optimum_fewer_factorizations() {
    let cfg = GeneratorConfig {
        membrane_side: (100, 100),
        ..Default::default()
    };
    let p = generate(Family::Membrane, 0, 2011, &cfg).unwrap().problem;
    let delta = 1e-3 * scale(&p);
    let (lo, hi) = lower_bounds(&p, delta);
    let mut c1 = Context::new(&p);
    let g0 = c1.g0().unwrap();
    let violated = g0.iter().filter(|&&g| g < -delta).count();
    assert!(
        violated >= strategy::active_set::PATH_FOLLOWING_MIN_VIOLATED,
        "{violated}"
    );
    let plain =
        eliminated::box_solve(&mut c1, &lo, &hi, Some(start_state(&g0, &lo, &hi, None))).unwrap();
    let mut c2 = Context::new(&p);
    let pf = eliminated::box_solve(&mut c2, &lo, &hi, None).unwrap();
    assert_eq!(plain.state, pf.state);
    assert!(relative_error(&pf.last, &plain.last) <= tol_u(&p));
    let (f1, f2) = (c1.stats.factorizations, c2.stats.factorizations);
    assert!(f2 < f1, "path following {f2} factorizations, plain {f1}");
    assert!(pf.state.contains(&BoundState::Lo));
}

/// PCG with the factor of a matrix that differs in a few prescribed rows converges in about
/// 2·(rows changed) iterations to the direct solution.
#[test]
fn pcg_with_a_nearby_factor() {
    let p = &membranes()[0];
    let Stiffness::Sparse(k) = &p.k else {
        panic!("membranes are sparse")
    };
    let pat = DiagonalPattern::new(k).unwrap();
    let n = pat.n();
    // Prescribe (Dirichlet, K_jj·e_j) the rows in `fixed`.
    let values_with = |fixed: &[usize]| {
        let mut v = pat.values.clone();
        let (cp, ri) = (pat.pattern.col_ptr(), pat.pattern.row_idx());
        for j in 0..n {
            for q in cp[j]..cp[j + 1] {
                if ri[q] != j && (fixed.contains(&ri[q]) || fixed.contains(&j)) {
                    v[q] = 0.0;
                }
            }
        }
        v
    };
    let old: Vec<usize> = (0..n).step_by(7).collect();
    let mut new = old.clone();
    new.retain(|j| *j != 7 * 40 && *j != 7 * 41);
    new.push(n / 2 + 1);
    let f_old = pat.factor(&values_with(&old)).unwrap();
    let v_new = values_with(&new);
    let a = faer::sparse::SparseColMatRef::new(pat.pat(), &v_new);
    let b: Vec<f64> = (0..n).map(|i| 1.0 + (i % 5) as f64).collect();
    let mut x_direct = b.clone();
    pat.factor(&v_new)
        .unwrap()
        .solve_vec_in_place(&mut x_direct);
    let mut x = vec![0.0; n];
    let tol = 16.0 * (n as f64).sqrt() * f64::EPSILON;
    let out = pcg(a, &f_old, &b, &mut x, tol, 50);
    assert!(out.converged);
    // 3 rows changed: M⁻¹A − I has rank ≤ 6.
    assert!(out.iterations <= 2 * 3 + 1, "{} iterations", out.iterations);
    assert!(relative_error(&x, &x_direct) <= tol_u(p));
}

/// The exact contact set as a start (`Prepared::with_contact_set`, what every sweep row gets
/// from its lagrange row): constant and condensed reach the same answer — same penalized set,
/// u to rounding (`64·N·ε_mach·cond₂` of the final system, cond₂ ≤ (σ_max(K) + ε)/σ_min(K)
/// for constant, cond₂(K) for condensed's prescribed-DOF system) — in no more iterations,
/// and in fewer over the ε grid.
#[test]
fn exact_contact_start_same_answer_fewer_iterations() {
    use penalty_lab::conditioning;
    use penalty_lab::strategy::Prepared;
    let support = |u: &[f64]| -> Vec<bool> { u.iter().map(|&e| e != 0.0).collect() };
    for p in membranes() {
        let n = p.n() as f64;
        let ck = conditioning::cond2(&p.k).unwrap();
        let prep = Prepared::new(&p).unwrap();
        let lag = strategy::solve_prepared(&p, Method::lagrange(), Some(&prep)).unwrap();
        let warm = prep.clone().with_contact_set(lag.contact_set().unwrap());
        let (mut cold_its, mut warm_its) = (0, 0);
        for eps in [1e-1, 1e1, 1e3, 1e5] {
            let m = Method::constant(eps);
            let a = strategy::solve_prepared(&p, m, Some(&prep)).unwrap();
            let b = strategy::solve_prepared(&p, m, Some(&warm)).unwrap();
            assert!(a.stats.converged && b.stats.converged);
            assert_eq!(support(&a.penalties), support(&b.penalties), "ε = {eps:e}");
            let tol = 64.0 * n * f64::EPSILON * (ck.sigma_max + eps) / ck.sigma_min;
            let err = relative_error(&b.u, &a.u);
            assert!(err <= tol, "ε = {eps:e}: {err:e} > {tol:e}");
            assert!(b.stats.iterations <= a.stats.iterations, "ε = {eps:e}");
            cold_its += a.stats.iterations;
            warm_its += b.stats.iterations;
        }
        assert!(
            warm_its < cold_its,
            "from u0 {cold_its}, from the contact set {warm_its}"
        );
        let delta = 1e-2 * scale(&p);
        let m = Method::condensed(delta);
        let a = strategy::solve_prepared(&p, m, Some(&prep)).unwrap();
        let b = strategy::solve_prepared(&p, m, Some(&warm)).unwrap();
        assert!(b.max_penetration <= delta);
        assert_eq!(support(&a.penalties), support(&b.penalties));
        assert!(relative_error(&b.u, &a.u) <= tol_u(&p));
        assert!(b.stats.iterations <= a.stats.iterations);
    }
}
