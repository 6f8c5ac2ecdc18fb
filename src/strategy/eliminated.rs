//! Large sparse route of `condensed` and `lagrange`: the same box problem solved in u-space by
//! eliminating the DOFs at a bound, never forming `S = DᵀK⁻¹D` or `W = K⁻¹D`.
//!
//! For a Boolean D with distinct DOFs, the condensed box QP in gaps,
//! `min ½(g − g0)ᵀS⁻¹(g − g0)` s.t. `lo ≤ g ≤ hi`, is the Schur complement of
//!
//! `min ½uᵀKu − qᵀu` s.t. `lo_c ≤ u[d_c] − û_c ≤ hi_c`,
//!
//! so both have the same solution. For a given state (each constraint free, at `lo` or at
//! `hi`), the DOFs at a bound are prescribed (`u_B = û_B + bound`) and the rest solve
//! `K_FF u_F = q_F − K_FB u_B`. This is done on the full pattern of K with the prescribed rows
//! and columns replaced by `K_jj·e_j` (exact, no penalty), so one symbolic Cholesky analysis
//! serves every iteration. The contact forces are the residuals `r_c = q[d_c] − (K u)[d_c]`
//! (convention `K u = q − D r`). The primal–dual active-set update is the one of
//! [`condensed::box_qp`](super::condensed::box_qp), started from the same state (the bounds
//! violated by u0), so both routes visit the same active sets in exact arithmetic.
//!
//! Cost per iteration: one numeric sparse Cholesky and one solve; memory O(nnz of the factor).
//! `condensed` and `lagrange` take this route for sparse K with `n ≥` [`ELIMINATION_MIN_N`]
//! and distinct constraint DOFs.

use super::condensed::{pdas_update, start_state, BoundState};
use super::Context;
use crate::error::{Error, Result};
use crate::linalg::DiagonalPattern;
use crate::system::{Problem, Stiffness};
use std::collections::HashSet;

/// Smallest n for which `condensed`/`lagrange` use the elimination route on sparse K.
pub const ELIMINATION_MIN_N: usize = 2000;

/// Result of [`box_solve`].
#[derive(Clone, Debug)]
pub struct BoxSolve {
    /// Solution u.
    pub u: Vec<f64>,
    /// Gaps `g_c = u[d_c] − û_c`.
    pub g: Vec<f64>,
    /// Forces `r_c = q[d_c] − (K u)[d_c]` (0 for free constraints).
    pub r: Vec<f64>,
    /// Final state per constraint.
    pub state: Vec<BoundState>,
    /// Iterations (= numeric factorizations = solves).
    pub iterations: usize,
    /// Number of constraints at a bound, per iteration.
    pub sizes: Vec<usize>,
    /// Whether the one-change fallback was needed.
    pub fallback: bool,
}

/// Does the problem qualify for the elimination route?
pub fn applies(problem: &Problem) -> bool {
    if !(problem.k.is_sparse() && problem.n() >= ELIMINATION_MIN_N) {
        return false;
    }
    let mut seen = vec![false; problem.n()];
    problem
        .constraints
        .iter()
        .all(|c| !std::mem::replace(&mut seen[c.dof], true))
}

/// Solves `min ½uᵀKu − qᵀu` s.t. `lo_c ≤ u[d_c] − û_c ≤ hi_c` by a primal–dual active-set
/// iteration with elimination of the DOFs at a bound (K sparse SPD, constraint DOFs distinct).
/// `lo_c = hi_c` pins a constraint (never released). `start`: the initial state (default: the
/// bounds violated by u0), e.g. the final state of a previous solve with nearby bounds.
///
/// A prescribed value is `u[d] = û + b` rounded so that the gap computed from it,
/// `fl(u[d] − û)`, does not lie outside `[lo, hi]`: the bound holds in floating point.
pub fn box_solve(
    ctx: &mut Context,
    lo: &[f64],
    hi: &[f64],
    start: Option<Vec<BoundState>>,
) -> Result<BoxSolve> {
    let problem = ctx.problem;
    let Stiffness::Sparse(kmat) = &problem.k else {
        return Err(Error::input("elimination route needs a sparse K"));
    };
    let (n, m) = (problem.n(), problem.m());
    // Start like box_qp: the bounds violated by the unconstrained solution.
    let g0 = ctx.g0()?;
    let scale = g0
        .iter()
        .chain(lo.iter().filter(|v| v.is_finite()))
        .chain(hi.iter().filter(|v| v.is_finite()))
        .fold(0.0f64, |a, v| a.max(v.abs()));
    let tol = 64.0 * f64::EPSILON * (m as f64).max(1.0) * scale;
    let mut state = start_state(&g0, lo, hi, start);
    let pat = DiagonalPattern::new(kmat)?;
    let rows = pat.pattern.row_idx().to_vec();
    let cols = pat.pattern.col_ptr().to_vec();
    let kdiag: Vec<f64> = pat.diag.iter().map(|&p| pat.values[p]).collect();
    let mut seen: HashSet<Vec<BoundState>> = HashSet::new();
    let mut fallback = false;
    let mut sizes = Vec::new();
    let max_it = super::max_iterations(m);
    for it in 1..=max_it {
        // Prescribed DOFs and values.
        let mut fixed = vec![false; n];
        let mut u_fix = vec![0.0; n];
        let mut at_bound = 0;
        for (c, con) in problem.constraints.iter().enumerate() {
            let b = match state[c] {
                BoundState::Free => continue,
                BoundState::Hi => hi[c],
                BoundState::Lo => lo[c],
            };
            fixed[con.dof] = true;
            u_fix[con.dof] = prescribed(con.limit, b, lo[c], hi[c]);
            at_bound += 1;
        }
        sizes.push(at_bound);
        // Matrix with prescribed rows/columns replaced by K_jj e_j; rhs q_F − K_FB u_B.
        let mut vals = pat.values.clone();
        let mut rhs = problem.q.clone();
        for j in 0..n {
            for p in cols[j]..cols[j + 1] {
                let i = rows[p];
                if fixed[j] && !fixed[i] {
                    rhs[i] -= pat.values[p] * u_fix[j];
                }
                if (fixed[i] || fixed[j]) && i != j {
                    vals[p] = 0.0;
                }
            }
        }
        for j in 0..n {
            if fixed[j] {
                let d = if kdiag[j] > 0.0 { kdiag[j] } else { 1.0 };
                vals[pat.diag[j]] = d;
                rhs[j] = d * u_fix[j];
            }
        }
        let f = pat.factor(vals).ok_or_else(|| {
            Error::singular(
                "K_FF (K without the DOFs at a bound) is not positive definite: K is singular \
                 on the free DOFs"
                    .to_string(),
            )
        })?;
        ctx.stats.factorizations += 1;
        ctx.stats.linear_solves += 1;
        let mut u = rhs;
        f.solve_vec_in_place(&mut u);
        if u.iter().any(|v| !v.is_finite()) {
            return Err(Error::Numerical(
                "elimination route produced a non-finite solution".into(),
            ));
        }
        let ku = problem.k.matvec(&u);
        let g = problem.gaps(&u);
        let r: Vec<f64> = problem
            .constraints
            .iter()
            .enumerate()
            .map(|(c, con)| match state[c] {
                BoundState::Free => 0.0,
                _ => problem.q[con.dof] - ku[con.dof],
            })
            .collect();
        // Changes, weighted in gap units (r / K_dd) for the single-change fallback.
        let mut changes: Vec<(f64, usize, BoundState)> = Vec::new();
        for (c, con) in problem.constraints.iter().enumerate() {
            let w = 1.0 / kdiag[con.dof].abs().max(f64::MIN_POSITIVE);
            match state[c] {
                _ if lo[c] == hi[c] => {}
                BoundState::Hi if r[c] < 0.0 => changes.push((-r[c] * w, c, BoundState::Free)),
                BoundState::Lo if r[c] > 0.0 => changes.push((r[c] * w, c, BoundState::Free)),
                BoundState::Free if g[c] > hi[c] + tol => {
                    changes.push((g[c] - hi[c], c, BoundState::Hi))
                }
                BoundState::Free if g[c] < lo[c] - tol => {
                    changes.push((lo[c] - g[c], c, BoundState::Lo))
                }
                _ => {}
            }
        }
        if changes.is_empty() {
            ctx.stats.iterations += it;
            ctx.stats.active_set_sizes.extend_from_slice(&sizes);
            return Ok(BoxSolve {
                u,
                g,
                r,
                state,
                iterations: it,
                sizes,
                fallback,
            });
        }
        state = pdas_update(&state, &changes, &mut seen, &mut fallback);
    }
    Err(Error::Numerical(format!(
        "elimination route: active set did not converge in {max_it} iterations"
    )))
}

/// `v ≈ û + b` such that the gap recomputed from it, `fl(v − û)`, lies in `[lo, hi]` (one or
/// two ulps of v away from the rounded sum where rounding pushed it out).
pub fn prescribed(limit: f64, b: f64, lo: f64, hi: f64) -> f64 {
    let mut v = limit + b;
    for _ in 0..64 {
        let g = v - limit;
        if g > hi {
            v = v.next_down();
        } else if g < lo {
            v = v.next_up();
        } else {
            break;
        }
    }
    v
}
