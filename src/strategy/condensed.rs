//! Exact δ-targeting through the condensed flexibility (not in the paper).
//!
//! With `S = DᵀK⁻¹D` (m×m, the flexibility at the constrained DOFs; `S⁻¹` is the Schur-complement
//! stiffness) and `g0 = DᵀK⁻¹q − û`, the penalized gaps satisfy exactly
//!
//! `g = (I + S E)⁻¹ g0`, equivalently `E g = S⁻¹(g0 − g) =: r` (the contact forces).
//!
//! Choosing targets `g*_c = ±δ` gives `ε = S⁻¹(g0 − g*) ./ g*`. Which constraints to penalize
//! and on which side is decided by the bound-constrained QP
//!
//! `min ½ (g − g0)ᵀ S⁻¹ (g − g0)` s.t. `g_c ≤ δ` (upper), `g_c ≥ −δ` (lower),
//! `−δ ≤ g_c ≤ δ` (bilateral),
//!
//! whose KKT conditions are exactly the requirements: a constraint at a bound has
//! `|g_c| = δ` and `ε_c = r_c/g_c ≥ 0`; a free one has `r_c = 0` (ε_c = 0) and penetration ≤ δ.
//! The QP is strictly convex (S SPD), so the answer is unique; it is found by a primal–dual
//! active-set iteration on the m×m system (drop constraints whose ε would be < 0, add violated
//! ones), with a one-change-per-iteration fallback if the full update cycles.
//!
//! Cost: one factorization of K, one block solve with m right-hand sides (`W = K⁻¹D`), then
//! m-sized dense work; never K⁻¹. `u = u0 − W r`. For large sparse K (n ≥ 2000) the same QP
//! is solved in u-space by elimination ([`super::eliminated`]): one sparse Cholesky per
//! active-set iteration, memory O(nnz of the factor), no N×m block.
//!
//! Contract in floating point: every penetration computed from the returned u is ≤ δ. After
//! the QP, the penetrations are recomputed from u; where rounding left one above δ, the targets
//! of the constraints near δ move inward by a doubling margin and the QP is re-solved from its
//! final state (`Stats::refinements`); penalized constraints end within the rounding level of
//! their gap of δ (a warning says so if that is further than 1e-6·δ).
//!
//! When to use: whenever δ is the physical knob — it gives the smallest penalties that keep
//! every penetration ≤ δ, with no trial-and-error tuning of ε. It is not always the
//! best-conditioned choice at a given accuracy: on the paper's beam a uniform ε = 130 reaches the
//! same max penetration 0.1 with cond 221.1 against 222.3 (see `paper_beam`, note (i)).

use super::box_qp::{box_qp, BoundState};
use super::{Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy, SystemKind};
use crate::error::{Error, Result};
use crate::system::ConstraintKind;
use faer::Mat;

/// `condensed`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "condensed",
    summary: "Exact δ-targeting penalty",
    knob: Knob::Delta,
    needs_k_inverse: true,
    targets_delta: true,
    solve: run,
    look: Look {
        label: "condensed (exact δ)",
        rule_label: "condensed",
        colour: 4,
        glyph: Glyph::Diamond,
    },
    ..Strategy::BASE
};

impl Method {
    /// Exact δ-targeting penalties for allowed penetration δ (> 0).
    pub const fn condensed(delta: f64) -> Method {
        Method::of(&STRATEGY, Knobs::delta(delta))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.need_delta()?)
}

/// Solves with exact δ-targeting penalties: through S = DᵀK⁻¹D ([`solve_dense`]), or for
/// large sparse K by elimination ([`solve_eliminated`], see [`super::eliminated`]).
pub fn solve(ctx: Context, delta: f64) -> Result<Solution> {
    if super::eliminated::applies(ctx.problem) {
        solve_eliminated(ctx, delta)
    } else {
        solve_dense(ctx, delta)
    }
}

/// Gap bounds of the condensed box QP: `[−δ, δ]` (bilateral), `(−∞, δ]` (upper),
/// `[−δ, ∞)` (lower).
fn bounds(problem: &crate::system::Problem, delta: f64) -> (Vec<f64>, Vec<f64>) {
    problem
        .constraints
        .iter()
        .map(|c| match c.kind {
            ConstraintKind::Bilateral => (-delta, delta),
            ConstraintKind::Upper => (f64::NEG_INFINITY, delta),
            ConstraintKind::Lower => (-delta, f64::INFINITY),
        })
        .unzip()
}

/// `ε_c = r_c / g*_c` with the target gap `g*_c` (the bound the constraint sits at, ±δ) and
/// 0 for free constraints. Dividing by the target rather than by the recomputed gap
/// `g = g0 − S r` is the formula itself, and stays finite when δ is below the rounding level
/// of the gaps (there the recomputed gap can round to exactly 0).
fn penalties(state: &[BoundState], r: &[f64], lo: &[f64], hi: &[f64]) -> Vec<f64> {
    state
        .iter()
        .enumerate()
        .map(|(c, st)| match st {
            BoundState::Free => 0.0,
            BoundState::Lo => (r[c] / lo[c]).max(0.0),
            BoundState::Hi => (r[c] / hi[c]).max(0.0),
        })
        .collect()
}

const CYCLED: &str =
    "condensed: the primal-dual active-set update cycled; converged with single changes";

/// Most refinements of the targets by the δ guard (each at least doubles the margin of the
/// constraints it moves; in the tests 0 or 1 are needed).
pub const MAX_REFINEMENTS: usize = 8;

/// One solve of the box problem for given (shrunk) bounds: u, the final state and forces.
struct Attempt {
    u: Vec<f64>,
    state: Vec<BoundState>,
    r: Vec<f64>,
    fallback: bool,
}

/// The guarded result: the last attempt, the bounds it was solved with, refinements used.
struct Guarded {
    attempt: Attempt,
    lo: Vec<f64>,
    hi: Vec<f64>,
    refinements: usize,
    /// Some attempt needed the single-change fallback.
    fallback: bool,
}

/// Enforces the contract "every penetration computed from the returned u is ≤ δ" in floating
/// point. The box problem is solved with bounds `[lo, hi]` (±δ); then the penetration of every
/// constraint is recomputed from u. Where rounding put the largest above δ by `o`, every
/// constraint within `margin_c = 2^(k+1)·max(o, 2·ε_mach·max(|u[d_c]|, |û_c|, δ))` of δ
/// (k-th refinement; the second term is the step in which `fl(u[d] − û)` moves) gets its
/// bound moved to `δ − margin_c`, and the problem is solved again from the final state (warm
/// start), until no penetration exceeds δ. Penalized constraints then sit within
/// the rounding level of their gap (≈ ε_mach·|g0|, times cond for the dense route) of δ.
fn guarded(
    problem: &crate::system::Problem,
    delta: f64,
    lo: Vec<f64>,
    hi: Vec<f64>,
    mut attempt: impl FnMut(&[f64], &[f64], Option<Vec<BoundState>>) -> Result<Attempt>,
) -> Result<Guarded> {
    let (mut lo, mut hi) = (lo, hi);
    let mut start = None;
    let mut fallback = false;
    for refinements in 0..=MAX_REFINEMENTS {
        let a = attempt(&lo, &hi, start.take())?;
        fallback |= a.fallback;
        let pen: Vec<f64> = problem
            .constraints
            .iter()
            .map(|con| con.kind.penetration(con.gap(&a.u)))
            .collect();
        let over = pen.iter().fold(0.0f64, |m, &p| m.max(p - delta));
        if over <= 0.0 {
            return Ok(Guarded {
                attempt: a,
                lo,
                hi,
                refinements,
                fallback,
            });
        }
        // The overshoot is rounding noise that changes with every solve, and the gap
        // `fl(u[d] − û)` moves in steps of the ulp of max(|u[d]|, |û|): move every constraint
        // within its margin of δ inward by that margin, which doubles per round.
        let grow = 2f64.powi(refinements as i32 + 1);
        for (c, con) in problem.constraints.iter().enumerate() {
            let unit = f64::EPSILON * con.value(&a.u).abs().max(con.limit.abs()).max(delta);
            let margin = grow * over.max(2.0 * unit);
            if pen[c] > delta - margin {
                if con.gap(&a.u) > 0.0 {
                    hi[c] = hi[c].min(delta - margin);
                } else {
                    lo[c] = lo[c].max(-(delta - margin));
                }
            }
        }
        start = Some(a.state);
    }
    Err(Error::Numerical(format!(
        "condensed: rounding keeps a penetration above δ = {delta:e} after {MAX_REFINEMENTS} \
         refinements of the targets (δ below the rounding level of the gaps?)"
    )))
}

/// The solution of a guarded solve: `ε_c = r_c / g*_c` at the (moved) bounds, the guard's
/// statistics, and its warnings — how close the penalized constraints ended to δ where
/// rounding kept them further than 1e-6·δ, and the single-change fallback if any.
fn finish_guarded(mut ctx: Context, delta: f64, g: Guarded) -> Solution {
    let problem = ctx.problem;
    let worst = g
        .attempt
        .state
        .iter()
        .enumerate()
        .filter(|(_, st)| **st != BoundState::Free)
        .map(|(c, _)| {
            let con = &problem.constraints[c];
            (delta - con.kind.penetration(con.gap(&g.attempt.u))) / delta
        })
        .fold(0.0f64, f64::max);
    let mut warnings = Vec::new();
    if worst > 1e-6 {
        warnings.push(format!(
            "condensed: rounding of the gaps keeps the penalized constraints within {worst:.1e}·δ \
             of δ (not 1e-6·δ): targets were moved inward {} time(s) so that every penetration \
             stays ≤ δ",
            g.refinements
        ));
    }
    if g.fallback {
        warnings.push(CYCLED.to_string());
    }
    ctx.stats.converged = true;
    ctx.stats.refinements = g.refinements;
    let penalties = penalties(&g.attempt.state, &g.attempt.r, &g.lo, &g.hi);
    ctx.finish(
        Method::condensed(delta),
        g.attempt.u,
        penalties,
        None,
        SystemKind::Penalized,
        warnings,
    )
}

/// The elimination route: the box problem in u-space, `ε_c = r_c / g*_c` at the bounds.
/// Where the context carries the exact contact set ([`super::Prepared::with_contact_set`]),
/// the first attempt starts with those constraints at their bound on the penetration side
/// (bilateral: the side of g0) and the rest free; the box problem has one solution, so the
/// start changes only the iterations.
pub fn solve_eliminated(mut ctx: Context, delta: f64) -> Result<Solution> {
    let problem = ctx.problem;
    let (lo, hi) = bounds(problem, delta);
    let mut first = match ctx.contact_set() {
        Some(set) => {
            let g0 = ctx.g0()?;
            Some(
                problem
                    .constraints
                    .iter()
                    .zip(set)
                    .zip(g0)
                    .map(|((con, on), g)| match (on, con.kind) {
                        (false, _) => BoundState::Free,
                        (true, ConstraintKind::Upper) => BoundState::Hi,
                        (true, ConstraintKind::Lower) => BoundState::Lo,
                        (true, ConstraintKind::Bilateral) if g >= 0.0 => BoundState::Hi,
                        (true, ConstraintKind::Bilateral) => BoundState::Lo,
                    })
                    .collect(),
            )
        }
        None => None,
    };
    let g = guarded(problem, delta, lo, hi, |lo, hi, start| {
        let start = start.or_else(|| first.take());
        let b = super::eliminated::box_solve(&mut ctx, lo, hi, start)?;
        Ok(Attempt {
            u: b.last,
            state: b.state,
            r: b.r,
            fallback: b.fallback,
        })
    })?;
    Ok(finish_guarded(ctx, delta, g))
}

/// The dense route through `S = DᵀK⁻¹D` (m×m) and `W = K⁻¹D` (N×m).
pub fn solve_dense(mut ctx: Context, delta: f64) -> Result<Solution> {
    let problem = ctx.problem;
    let g0 = ctx.g0()?;
    let u0 = ctx.u0()?.to_vec();
    let m = problem.m();
    let n = problem.n();
    // W = K⁻¹ D (N×m, shared by the solves of one `Prepared`), S = Dᵀ W.
    let w = ctx.constraint_columns()?;
    let s = Mat::from_fn(m, m, |i, j| problem.constraints[i].apply(|d| w[(d, j)]));
    let (lo, hi) = bounds(problem, delta);
    let g = guarded(problem, delta, lo, hi, |lo, hi, start| {
        let qp = box_qp(s.as_ref(), &g0, lo, hi, start)?;
        ctx.stats.iterations += qp.iterations;
        ctx.stats.active_set_sizes.extend_from_slice(&qp.sizes);
        // u = u0 − W r.
        let u: Vec<f64> = (0..n)
            .map(|i| u0[i] - (0..m).map(|c| w[(i, c)] * qp.r[c]).sum::<f64>())
            .collect();
        Ok(Attempt {
            u,
            state: qp.state,
            r: qp.r,
            fallback: qp.fallback,
        })
    })?;
    Ok(finish_guarded(ctx, delta, g))
}

#[cfg(test)]
mod tests {
    use crate::model::beam::{bed, paper};
    use crate::strategy::{solve, solve_prepared, Method, Prepared};

    /// W = K⁻¹D is computed by the first `condensed` solve of a [`Prepared`] and shared by the
    /// next ones, which agree bit for bit — u, penalties and statistics — with solves that
    /// compute everything themselves.
    #[test]
    fn constraint_columns_are_shared_and_change_nothing() {
        let bed = bed::Bed {
            n_el: 12,
            load: -1.0,
            amp: 0.5,
            waves: 3.0,
        };
        for p in [paper::problem(), bed::problem(bed).unwrap()] {
            assert!(!super::super::eliminated::applies(&p), "the dense route");
            let prep = Prepared::new(&p).unwrap();
            let scale = p
                .constraints
                .iter()
                .map(|c| c.value(prep.u0()).abs())
                .fold(0.0, f64::max);
            assert!(prep.constraint_columns.get().is_none());
            let mut first = None;
            for r in [1e-1, 1e-2, 1e-4] {
                let m = Method::condensed(r * scale);
                let shared = solve_prepared(&p, m, Some(&prep)).unwrap();
                let own = solve(&p, m).unwrap();
                let w = prep
                    .constraint_columns
                    .get()
                    .expect("filled by the first solve");
                let w = std::sync::Arc::as_ptr(w);
                assert_eq!(*first.get_or_insert(w), w, "computed once");
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&shared.u), bits(&own.u));
                assert_eq!(bits(&shared.penalties), bits(&own.penalties));
                assert_eq!(shared.stats.linear_solves, own.stats.linear_solves);
                assert_eq!(shared.stats.factorizations, own.stats.factorizations);
                assert_eq!(shared.stats.iterations, own.stats.iterations);
            }
        }
    }
}
