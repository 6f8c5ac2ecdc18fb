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
//! [`box_qp::box_qp`](super::box_qp::box_qp). Where many bounds are violated by u0
//! (obstacle-type problems) the start comes from a Moreau–Yosida path following
//! ([`active_set::path_following`], up to [`PATH_END`]); otherwise both routes start
//! from the bounds violated by u0 and visit the same active sets in exact arithmetic.
//!
//! Cost per iteration: one numeric sparse Cholesky and one solve — or, when at most
//! [`PCG_MAX_CHANGED`] DOFs changed status since the last factorization and that factor is
//! supernodal, conjugate gradients preconditioned by it (`M⁻¹A = I + rank ≤ 2·changed`),
//! accepted at a normwise backward error ≤ `16√N·ε_mach` and abandoned for a fresh
//! factorization after `2·changed +` [`PCG_EXTRA_ITERATIONS`] iterations
//! (`Stats::cg_iterations`). A simplicial factor (faer's choice below 40 flops per entry of
//! L: the sweep's 36–400-DOF scenes) costs only a few solves to recompute (Σ c_j² against
//! 4 Σ c_j flops for the column counts c_j of L: 3.3 solves on the 400-DOF membrane), less
//! than the ≥ 6 PCG iterations a change allows, so it is always refactorized. One factor is
//! kept at a time; memory O(nnz of the factor). The path following cuts the 10⁶-DOF
//! membrane from ≈ 160 to 19 factorizations (measurements: docs/performance.md).
//!
//! `condensed` and `lagrange` take this route for sparse K with `n ≥` [`ELIMINATION_MIN_N`]
//! and distinct constraint DOFs.

use super::box_qp::{pdas, start_state, BoundState, Pdas, PdasSpec};
use super::{active_set, Context};
use crate::error::{Error, Result};
use crate::linalg::{pcg, DiagonalPattern, SparseLlt};
use crate::system::{Problem, Stiffness};
use faer::sparse::SparseColMatRef;

pub use crate::route::ELIMINATION_MIN_N;

/// At most this many DOFs may have changed status (prescribed ↔ free) since the last
/// factorization for an iteration to try PCG with that factor instead of refactorizing.
pub const PCG_MAX_CHANGED: usize = 16;

/// PCG iterations allowed beyond `2 × changed` (the rank of the change) before refactorizing.
pub const PCG_EXTRA_ITERATIONS: usize = 4;

/// Last penalty of the path following of [`box_solve`], relative to `K_dd`: stiff enough that
/// the penalized contact zone is within a few elements of the exact one.
pub const PATH_END: f64 = 10.0;

/// Result of [`box_solve`]: `last` is the solution u, `g_c = u[d_c] − û_c`, the forces
/// `r_c = q[d_c] − (K u)[d_c]` (0 for free constraints), iterations = numeric
/// factorizations + PCG solves.
pub type BoxSolve = Pdas<Vec<f64>>;

/// Does the problem qualify for the elimination route?
pub fn applies(problem: &Problem) -> bool {
    if !crate::route::elimination_route(problem.n(), problem.k.is_sparse()) {
        return false;
    }
    let mut seen = vec![false; problem.n()];
    problem.constraints.iter().all(|c| {
        c.single_dof()
            .is_some_and(|d| !std::mem::replace(&mut seen[d], true))
    })
}

/// Solves `min ½uᵀKu − qᵀu` s.t. `lo_c ≤ u[d_c] − û_c ≤ hi_c` by a primal–dual active-set
/// iteration with elimination of the DOFs at a bound (K sparse SPD, constraint DOFs distinct).
/// `lo_c = hi_c` pins a constraint (never released). `start`: the initial state, e.g. the
/// final state of a previous solve with nearby bounds (default: from the path following, or
/// the bounds violated by u0; module docs).
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
        return Err(Error::unsupported("the elimination route", "a sparse K"));
    };
    let (n, m) = (problem.n(), problem.m());
    let dofs = problem.single_dofs("the elimination route")?;
    // Start like box_qp: the bounds violated by the unconstrained solution.
    let g0 = ctx.g0()?;
    let tol = super::box_qp::violation_tol(&g0, lo, hi);
    let pat = DiagonalPattern::new(kmat)?;
    let kdiag: Vec<f64> = pat.diag.iter().map(|&p| pat.values[p]).collect();
    let start = match start {
        Some(s) => Some(s),
        None => path_following_start(ctx, lo, hi)?,
    };
    let state = start_state(&g0, lo, hi, start);
    let max_it = super::max_iterations(m);
    // The last factor and the prescribed DOFs it was built for; the last solution.
    let mut last: Option<(SparseLlt, Vec<bool>)> = None;
    let mut u_last: Option<Vec<f64>> = None;
    let cg_tol = super::active_set::backward_error_tol(n);
    // The matrix values of each iteration (buffer reused).
    let mut vals = pat.values.clone();
    // Changes, weighted in gap units (r / K_dd) for the single-change fallback.
    let w = |c: usize| 1.0 / kdiag[dofs[c]].abs().max(f64::MIN_POSITIVE);
    let spec = PdasSpec {
        bounds: (lo, hi),
        tol,
        keep_pinned: true,
        max_it,
        what: "elimination route",
    };
    let out = pdas(state, spec, w, |state| {
        let (fixed, u_fix) = prescribed_dofs(problem, state, lo, hi);
        // Matrix with prescribed rows/columns replaced by K_jj e_j; rhs q_F − K_FB u_B.
        let rhs = eliminate(&pat, &problem.q, &fixed, &u_fix, &kdiag, &mut vals);
        // Few DOFs changed status since the last factorization: PCG with that factor.
        let mut u_cg = None;
        if let (Some((f, f_fixed)), Some(u_prev)) = (&last, &u_last) {
            let changed = f_fixed.iter().zip(&fixed).filter(|(a, b)| a != b).count();
            if changed <= PCG_MAX_CHANGED && f.is_supernodal() {
                let mut x = u_prev.clone();
                for j in 0..n {
                    if fixed[j] {
                        x[j] = u_fix[j];
                    }
                }
                let a = SparseColMatRef::new(pat.pat(), &vals);
                let out = pcg(
                    a,
                    f,
                    &rhs,
                    &mut x,
                    cg_tol,
                    2 * changed + PCG_EXTRA_ITERATIONS,
                );
                ctx.stats.cg_iterations += out.iterations;
                if out.converged {
                    u_cg = Some(x);
                }
            }
        }
        let u = match u_cg {
            Some(x) => x,
            None => {
                drop(last.take()); // one factor in memory at a time
                let f = pat.factor(&vals).ok_or_else(|| {
                    Error::singular(
                        "K_FF (K without the DOFs at a bound) is not positive definite: K is \
                             singular on the free DOFs"
                            .to_string(),
                    )
                })?;
                ctx.stats.factorizations += 1;
                ctx.stats.linear_solves += 1;
                let mut u = rhs;
                f.solve_vec_in_place(&mut u);
                last = Some((f, fixed));
                u
            }
        };
        u_last = Some(u.clone());
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
            .map(|(c, _)| match state[c] {
                BoundState::Free => 0.0,
                _ => problem.q[dofs[c]] - ku[dofs[c]],
            })
            .collect();
        Ok((g, r, u))
    })?;
    ctx.stats.iterations += out.iterations;
    ctx.stats.active_set_sizes.extend_from_slice(&out.sizes);
    Ok(out)
}

/// The DOFs at a bound in `state` and their prescribed values ([`prescribed`]).
fn prescribed_dofs(
    problem: &Problem,
    state: &[BoundState],
    lo: &[f64],
    hi: &[f64],
) -> (Vec<bool>, Vec<f64>) {
    let n = problem.n();
    let mut fixed = vec![false; n];
    let mut u_fix = vec![0.0; n];
    for (c, con) in problem.constraints.iter().enumerate() {
        let b = match state[c] {
            BoundState::Free => continue,
            BoundState::Hi => hi[c],
            BoundState::Lo => lo[c],
        };
        let d = con.lead_dof(); // single-DOF: checked by `box_solve`
        fixed[d] = true;
        u_fix[d] = prescribed(con.limit, b, lo[c], hi[c]);
    }
    (fixed, u_fix)
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

/// The start of [`box_solve`] from the Moreau–Yosida path following
/// ([`active_set::path_following`]: penalties `t·K_dd` on the distance to `[lo, hi]`, t up
/// to [`PATH_END`]): the state whose bounds are violated at its last stage. `None` (plain
/// start) where the path following does not apply.
fn path_following_start(
    ctx: &mut Context,
    lo: &[f64],
    hi: &[f64],
) -> Result<Option<Vec<BoundState>>> {
    use crate::system::ConstraintKind;
    let problem = ctx.problem;
    // Penalties act on the distance to [lo, hi]: the limit is the bound on the penalized side
    // (bilateral: the midpoint, penalized both ways — a start heuristic only).
    let limits: Vec<f64> = problem
        .constraints
        .iter()
        .enumerate()
        .map(|(c, con)| match con.kind {
            ConstraintKind::Lower => con.limit + lo[c],
            ConstraintKind::Upper => con.limit + hi[c],
            ConstraintKind::Bilateral => con.limit + 0.5 * (lo[c] + hi[c]),
        })
        .collect();
    let caps = vec![f64::INFINITY; problem.m()];
    let Some(u) = active_set::path_following(ctx, &caps, &limits, PATH_END)? else {
        return Ok(None);
    };
    let g = problem.gaps(&u);
    Ok(Some(start_state(&g, lo, hi, None)))
}

/// Eliminates the prescribed DOFs (`fixed`, values `u_fix`): writes into `vals` K with their
/// rows and columns replaced by `K_jj e_j` (1 where K_jj ≤ 0) and returns the right-hand side
/// `q_F − K_FB u_B` (and `K_jj u_j` on the prescribed rows), so the solution keeps them.
fn eliminate(
    pat: &DiagonalPattern,
    q: &[f64],
    fixed: &[bool],
    u_fix: &[f64],
    kdiag: &[f64],
    vals: &mut [f64],
) -> Vec<f64> {
    let n = q.len();
    let (rows, cols) = (pat.pattern.row_idx(), pat.pattern.col_ptr());
    vals.copy_from_slice(&pat.values);
    let mut rhs = q.to_vec();
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
    rhs
}
