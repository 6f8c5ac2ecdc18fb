//! The elimination route of `condensed` and `lagrange` (large sparse K) against the dense
//! routes on the same problems: same active sets and iteration counts, same u, penalties and
//! forces to rounding.

use penalty_lab::metrics::relative_error;
use penalty_lab::strategy::{self, condensed, eliminated, lagrange, Context, Method};
use penalty_lab::sweep::generate::{generate, Family, GeneratorConfig};
use penalty_lab::system::{ConstraintKind, Problem, Stiffness};

fn membranes() -> Vec<Problem> {
    let cfg = GeneratorConfig {
        membrane_side: (45, 60),
        ..Default::default()
    };
    (0..3)
        .map(|i| generate(Family::Membrane, i, 4242, &cfg).unwrap().problem)
        .collect()
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
            // Same active sets in exact arithmetic up to the first optimum; the guard's
            // refinements after it (penetration above δ by rounding) depend on rounding.
            let first = |s: &penalty_lab::strategy::Solution| {
                let k = s.stats.active_set_sizes.len() - s.stats.refinements;
                s.stats.active_set_sizes[..k].to_vec()
            };
            assert_eq!(first(&a), first(&b));
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
            let s = strategy::solve(&p, Method::Condensed { delta }).unwrap();
            assert_eq!(s.u, b.u);
        }
    }
}

#[test]
fn lagrange_routes_agree() {
    for p in membranes() {
        let a = lagrange::solve_saddle(Context::new(&p)).unwrap();
        let b = lagrange::solve_eliminated(Context::new(&p)).unwrap();
        assert_eq!(a.stats.active_set_sizes, b.stats.active_set_sizes);
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
        assert!((b.u[c.dof] - c.limit).abs() <= tol_u(&q) * c.limit.abs().max(1e-300));
    }
    let dense = Stiffness::Dense(p.k.to_dense());
    assert!(!eliminated::applies(
        &Problem::new(dense, p.q.clone(), cons).unwrap()
    ));
}
