//! Lagrange multipliers (exact contact): the saddle-point system
//!
//! `[K  D_A; D_Aᵀ 0] [u; λ_A] = [q; û_A]`,
//!
//! with λ the contact forces in the convention `K u = q − D λ`. Bilateral constraints are
//! always in A. Unilateral ones follow a primal–dual active-set iteration (deal.II step-41
//! style): a constraint leaves A when its force has the wrong sign (`upper` needs λ ≥ 0,
//! `lower` λ ≤ 0), and enters A when violated; single changes are used if the full update
//! cycles. Penetration is 0 to rounding. This is the reference `u_ref` for error measurements.
//!
//! When to use: the exact answer; it costs a larger, indefinite system (`cond2_system` is the
//! saddle-point matrix's) whose size changes with the active set.

use super::{
    initial_active_set, max_iterations, Context, Glyph, Knobs, Look, Method, Solution, Strategy,
    SystemKind,
};
use crate::error::{Error, Result};
use crate::linalg::Factorization;
use crate::system::{ConstraintKind, Problem, Stiffness};
use std::collections::HashSet;

/// `lagrange`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "lagrange",
    summary: "Lagrange multipliers",
    solve: run,
    look: Look {
        colour: 5,
        glyph: Glyph::Plus,
        ..Look::BASE
    },
    ..Strategy::BASE
};

impl Method {
    /// Lagrange multipliers (exact contact).
    pub const fn lagrange() -> Method {
        Method::of(&STRATEGY, Knobs::NONE)
    }
}

fn run(ctx: Context, _: &Method) -> Result<Solution> {
    solve(ctx)
}

/// The saddle-point matrix `[K D_A; D_Aᵀ 0]` for the active constraint indices.
pub fn saddle_matrix(problem: &Problem, active: &[usize]) -> Stiffness {
    let n = problem.n();
    let na = active.len();
    match &problem.k {
        Stiffness::Dense(k) => {
            let mut a = faer::Mat::zeros(n + na, n + na);
            a.as_mut().submatrix_mut(0, 0, n, n).copy_from(k);
            for (j, &c) in active.iter().enumerate() {
                for &(d, v) in &problem.constraints[c].terms {
                    a[(d, n + j)] = v;
                    a[(n + j, d)] = v;
                }
            }
            Stiffness::Dense(a)
        }
        Stiffness::Sparse(_) => {
            let mut t = Vec::with_capacity(problem.k.nnz() + 2 * na);
            problem.k.for_each_entry(|i, j, v| t.push((i, j, v)));
            for (j, &c) in active.iter().enumerate() {
                for &(d, v) in &problem.constraints[c].terms {
                    t.push((d, n + j, v));
                    t.push((n + j, d, v));
                }
            }
            Stiffness::from_triplets(n + na, &t).expect("indices in range")
        }
    }
}

/// Solves the contact problem exactly with Lagrange multipliers: the saddle-point route
/// ([`solve_saddle`]), or for large sparse K the equivalent elimination route
/// ([`solve_eliminated`], see [`super::eliminated`]); the reported system is the saddle-point
/// matrix either way.
pub fn solve(ctx: Context) -> Result<Solution> {
    if super::eliminated::applies(ctx.problem) {
        solve_eliminated(ctx)
    } else {
        solve_saddle(ctx)
    }
}

/// The elimination route: prescribed DOFs at the limits, multipliers from the residuals.
pub fn solve_eliminated(mut ctx: Context) -> Result<Solution> {
    let (lo, hi): (Vec<f64>, Vec<f64>) = ctx
        .problem
        .constraints
        .iter()
        .map(|c| match c.kind {
            ConstraintKind::Bilateral => (0.0, 0.0),
            ConstraintKind::Upper => (f64::NEG_INFINITY, 0.0),
            ConstraintKind::Lower => (0.0, f64::INFINITY),
        })
        .unzip();
    let b = super::eliminated::box_solve(&mut ctx, &lo, &hi, None)?;
    let active: Vec<usize> = (0..b.state.len())
        .filter(|&c| b.state[c] != super::box_qp::BoundState::Free)
        .collect();
    let m = b.state.len();
    ctx.stats.converged = true;
    let warnings = if b.fallback {
        vec!["lagrange: the active-set update cycled; converged with single changes".to_string()]
    } else {
        Vec::new()
    };
    Ok(ctx.finish(
        Method::lagrange(),
        b.last,
        vec![0.0; m],
        Some(b.r),
        SystemKind::SaddlePoint { active },
        warnings,
    ))
}

/// Steps of iterative refinement of each saddle solve where the rows couple DOFs.
const REFINEMENT_STEPS: usize = 2;

/// Rows that couple DOFs get refined saddle solves; single-DOF rows keep theirs as they were,
/// bit for bit.
fn needs_refinement(problem: &Problem) -> bool {
    !problem.is_selection()
}

/// The saddle-point route: one LU of `[K D_A; D_Aᵀ 0]` per active-set iteration (where the
/// rows couple DOFs, each solve refined by two steps with f64 residuals).
pub fn solve_saddle(mut ctx: Context) -> Result<Solution> {
    let problem = ctx.problem;
    let m = problem.m();
    let n = problem.n();
    let mut active = initial_active_set(&mut ctx)?;
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    let mut single = false;
    let max_it = max_iterations(m);
    let scale = problem
        .constraints
        .iter()
        .map(|c| c.limit.abs())
        .fold(0.0f64, f64::max);
    loop {
        let idx: Vec<usize> = (0..m).filter(|&c| active[c]).collect();
        let a = saddle_matrix(problem, &idx);
        let f = Factorization::new(&a, false).map_err(|e| match e {
            Error::Singular(msg) => Error::singular(format!(
                "saddle-point matrix is singular ({msg}): K is singular on the unconstrained \
                 DOFs, or constraints are dependent"
            )),
            e => e,
        })?;
        ctx.stats.factorizations += 1;
        let mut rhs = problem.q.clone();
        rhs.extend(idx.iter().map(|&c| problem.constraints[c].limit));
        let mut x = f.solve(&rhs);
        ctx.stats.linear_solves += 1;
        if needs_refinement(problem) {
            // Rows that couple DOFs: LU of [K D_A; D_Aᵀ 0], whose blocks differ in scale by
            // ≈ ‖K‖, loses digits to that scaling; steps of refinement with f64 residuals
            // recover them (Skeel 1980: componentwise backward stability after one step).
            for _ in 0..REFINEMENT_STEPS {
                let ax = a.matvec(&x);
                let r: Vec<f64> = rhs.iter().zip(&ax).map(|(b, v)| b - v).collect();
                let dx = f.solve(&r);
                ctx.stats.linear_solves += 1;
                for (xi, d) in x.iter_mut().zip(dx) {
                    *xi += d;
                }
            }
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            // A pivot too small for the test of the factorization, yet zero in effect.
            return Err(Error::singular(format!(
                "saddle-point matrix is singular to working precision (unknown {i} of the \
                 solution is {}): K is singular on the unconstrained DOFs, or constraints are \
                 dependent",
                x[i]
            )));
        }
        ctx.stats.iterations += 1;
        ctx.stats.active_set_sizes.push(idx.len());
        let u = x[..n].to_vec();
        let mut lambda = vec![0.0; m];
        for (j, &c) in idx.iter().enumerate() {
            lambda[c] = x[n + j];
        }
        // Changes: wrong-sign forces leave, violated constraints enter.
        let unorm = u.iter().fold(scale, |a, v| a.max(v.abs()));
        let tol = 64.0 * f64::EPSILON * (n as f64) * unorm;
        let mut changes: Vec<(f64, usize)> = Vec::new();
        for c in 0..m {
            let con = &problem.constraints[c];
            let g = con.gap(&u);
            match (active[c], con.kind) {
                (_, ConstraintKind::Bilateral) => {}
                (true, ConstraintKind::Upper) if lambda[c] < 0.0 => changes.push((-lambda[c], c)),
                (true, ConstraintKind::Lower) if lambda[c] > 0.0 => changes.push((lambda[c], c)),
                (false, k) if k.penetration(g) > tol => changes.push((k.penetration(g), c)),
                _ => {}
            }
        }
        let converged = changes.is_empty();
        if converged || ctx.stats.iterations >= max_it {
            let mut warnings = Vec::new();
            ctx.stats.converged = converged;
            if !converged {
                warnings.push(format!(
                    "lagrange: NOT CONVERGED: active set did not settle after {max_it} iterations"
                ));
            }
            return Ok(ctx.finish(
                Method::lagrange(),
                u,
                vec![0.0; m],
                Some(lambda),
                SystemKind::SaddlePoint { active: idx },
                warnings,
            ));
        }
        seen.insert(active.clone());
        let mut next = active.clone();
        for &(_, c) in &changes {
            next[c] = !next[c];
        }
        if single || seen.contains(&next) {
            single = true;
            let &(_, c) = changes
                .iter()
                .max_by(|a, b| a.0.total_cmp(&b.0))
                .expect("non-empty");
            next = active.clone();
            next[c] = !next[c];
        }
        active = next;
    }
}
