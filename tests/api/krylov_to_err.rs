//! The solver-cost Krylov counts taken to a fixed error of u (`metrics::solver`, fifth round
//! of the contract): what the residual test hides, and where a penalty truly costs.
//!
//! - With obstacle limits û ≠ 0 the penalized right-hand side `b = q + D E û` grows with ε, so
//!   the residual test `‖r‖ ≤ τ‖b‖` loosens: at a stiff penalty it stops with u far from u*,
//!   while the error-based run goes on to the target.
//! - Single-DOF rows add `ε e_d e_dᵀ`, a diagonal that Jacobi absorbs: to a fixed error the
//!   Jacobi-CG count barely moves across decades of ε. A row along an inclined normal adds
//!   `ε n nᵀ` on a node's two DOFs, which Jacobi cannot absorb: the count grows with ε.

use penalty_lab::metrics::solver::{self, SolverMetrics, SolverOptions};
use penalty_lab::model::incline_block;
use penalty_lab::strategy::{self, Method};
use penalty_lab::study::solver_cost::cases::membrane_problem;
use penalty_lab::system::Problem;

fn metrics_at(p: &Problem, eps_rel: f64) -> SolverMetrics {
    let eps = eps_rel * p.max_constraint_stiffness();
    let sol = strategy::solve(p, Method::constant(eps)).unwrap();
    solver::compute(p, &sol, SolverOptions::default()).unwrap()
}

fn jacobi_to_err(m: &SolverMetrics) -> usize {
    let r = m
        .pcg_jacobi
        .to_err()
        .unwrap_or_else(|| panic!("no error-based Jacobi run: {:?}", m.unavailable));
    assert!(r.converged, "{r:?}");
    r.iterations
}

#[test]
fn a_stiff_penalty_meets_the_residual_test_far_from_u() {
    let p = membrane_problem(31).unwrap();
    let m = metrics_at(&p, 1e8);
    let target = solver::DEFAULT_ERR_TARGET;
    let stop = m.pcg_jacobi.residual().unwrap();
    assert!(stop.converged);
    let err_at_stop = m.pcg_jacobi.err_u_at_stop().unwrap();
    assert!(err_at_stop > 100.0 * target, "{err_at_stop:e}");
    let to_err = m.pcg_jacobi.to_err.unwrap();
    assert!(to_err.run.converged && to_err.err_u.unwrap() <= target);
    assert!(to_err.run.iterations > stop.iterations, "{m:?}");
}

#[test]
fn jacobi_absorbs_single_dof_penalties_but_not_inclined_rows() {
    // Membrane, one DOF per row: the count to 1e-6 moves by little over six decades of ε.
    let p = membrane_problem(31).unwrap();
    let (soft, stiff) = (
        jacobi_to_err(&metrics_at(&p, 1e2)),
        jacobi_to_err(&metrics_at(&p, 1e8)),
    );
    let ratio = stiff as f64 / soft as f64;
    assert!((0.7..=1.5).contains(&ratio), "{soft} → {stiff}");
    // The block on a plane at 30°, rows sinθ·u_x + cosθ·u_y: Jacobi's count grows with ε.
    let q = incline_block::problem(30.0, 32, 16).unwrap();
    let (soft, stiff) = (
        jacobi_to_err(&metrics_at(&q, 1e2)),
        jacobi_to_err(&metrics_at(&q, 1e8)),
    );
    assert!(stiff as f64 >= 2.0 * soft as f64, "{soft} → {stiff}");
}

#[test]
fn every_run_that_reports_reaching_the_target_is_within_it() {
    let q = incline_block::problem(45.0, 16, 8).unwrap();
    for eps_rel in [1e0, 1e4, 1e8] {
        let m = metrics_at(&q, eps_rel);
        for pair in [&m.pcg_jacobi, &m.pcg_ic0] {
            let run = pair.to_err.unwrap();
            if run.run.converged {
                assert!(run.err_u.unwrap() <= m.err_target, "{eps_rel}: {run:?}");
            }
        }
    }
}

#[test]
fn the_pressed_incline_block_touches_around_the_crown_without_penetrating_under_lagrange() {
    let p = incline_block::problem(30.0, 16, 8).unwrap();
    let sol = strategy::solve(&p, Method::lagrange()).unwrap();
    assert!(sol.stats.converged);
    let active = sol.forces.iter().filter(|&&f| f != 0.0).count();
    // Contact at the crown (node 8 of 16 elements, x = W/2), not everywhere.
    assert!(active >= 3 && active < p.m(), "{active} of {}", p.m());
    assert!(sol.forces[8] != 0.0);
    let scale = incline_block::PRESS * incline_block::HEIGHT;
    assert!(
        sol.max_penetration <= 1e-10 * scale,
        "{}",
        sol.max_penetration
    );
}
