//! Augmented Lagrangian (Uzawa iteration).
//!
//! With multipliers λ (contact forces, `K u = q − D λ`) and penalties ε_c, each iteration solves
//! the penalty problem with **shifted limits** `û'_c = û_c − λ_c/ε_c`:
//!
//! `(K + D_A E D_Aᵀ) u = q + D_A E û'_A`, force `r_c = ε_c (u[d_c] − û'_c) = λ_c + ε_c g_c`,
//!
//! (unilateral constraints active while their force has the obstacle's sign), then updates
//! `λ ← r` until `max penetration ≤ tol`. The adaptive variant (in the spirit of
//! Bussetta–Marceau–Ponthot 2012) multiplies ε_c by 10 when a constraint's penetration did not
//! shrink by at least 4× in one update, up to `K_dd / ε_mach` (beyond it `K_dd + ε_c` no longer
//! holds any digit of K_dd, and a tolerance below rounding would drive ε_c to overflow).
//!
//! When to use: penetration driven to any tolerance with a moderate ε (good conditioning), at
//! the price of several solves.

use super::active_set::{newton, Start};
use super::{Context, Glyph, Knob, Knobs, Method, Solution, Strategy, SystemKind};
use crate::error::Result;
use crate::system::ConstraintKind;

/// `augmented`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "augmented",
    summary: "Augmented Lagrangian",
    label: "augmented",
    rule_label: "augmented",
    knob: Knob::EpsTol,
    colour: 6,
    glyph: Glyph::Pentagon,
    needs_k_inverse: false,
    targets_delta: false,
    bilateral: true,
    force_tol: super::force_control::FORCE_TOL,
    solve: run,
};

impl Method {
    /// The augmented Lagrangian with penalty ε (> 0), penetration tolerance `tol` (> 0) and, where `adaptive`, the per-constraint penalty update.
    pub const fn augmented(eps: f64, tol: f64, adaptive: bool) -> Method {
        Method::of(
            &STRATEGY,
            Knobs {
                eps: Some(eps),
                tol: Some(tol),
                adaptive,
                ..Knobs::NONE
            },
        )
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(
        ctx,
        m.value(m.knobs().eps, "--eps")?,
        m.value(m.knobs().tol, "--tol")?,
        m.knobs().adaptive,
    )
}

/// Maximum Uzawa updates.
pub const MAX_UPDATES: usize = 500;

/// Solves with the augmented Lagrangian, penalty `eps`, tolerance `tol` on penetration.
///
/// Each inner problem (fixed λ, ε) is the minimizer of a convex penalized energy with shifted
/// limits, solved by [`newton`]: the first from the set of bilateral constraints, the later
/// ones warm-started from the previous iterate. `converged` is false (with a warning) only
/// when the penetration is still above `tol` after [`MAX_UPDATES`] multiplier updates.
pub fn solve(mut ctx: Context, eps: f64, tol: f64, adaptive: bool) -> Result<Solution> {
    let problem = ctx.problem;
    let method = Method::augmented(eps, tol, adaptive);
    let m = problem.m();
    let mut lambda = vec![0.0; m];
    let mut pen_eps = vec![eps; m];
    let mut prev_pen = vec![f64::INFINITY; m];
    let mut warnings = Vec::new();
    let mut updates = 0;
    let mut start = Start::Set(
        problem
            .constraints
            .iter()
            .map(|c| c.kind == ConstraintKind::Bilateral)
            .collect(),
    );
    loop {
        // Inner problem: the penalty problem with shifted limits ℓ_c = û_c − λ_c/ε_c.
        let limits: Vec<f64> = (0..m)
            .map(|c| problem.constraints[c].limit - lambda[c] / pen_eps[c])
            .collect();
        let inner = newton(&mut ctx, &pen_eps, &limits, start)?;
        if !inner.converged && warnings.is_empty() {
            warnings.push(format!(
                "augmented: NOT CONVERGED: an inner Newton solve reached its iteration cap \
                 (backward error {:.2e})",
                inner.backward_error
            ));
        }
        let (u, e) = (inner.u, inner.penalties);
        // Multiplier update λ ← r.
        for c in 0..m {
            lambda[c] = if e[c] != 0.0 {
                e[c] * (u[problem.constraints[c].dof] - limits[c])
            } else {
                0.0
            };
        }
        let pen = problem.penetrations(&u);
        let maxp = pen.iter().fold(0.0f64, |a, &b| a.max(b));
        updates += 1;
        if maxp <= tol || updates >= MAX_UPDATES {
            ctx.stats.converged = maxp <= tol && inner.converged;
            if maxp > tol {
                warnings.push(format!(
                    "augmented: NOT CONVERGED: max penetration {maxp:.3e} > tol {tol:.3e} after \
                     {MAX_UPDATES} multiplier updates"
                ));
            }
            return Ok(ctx.finish(method, u, e, Some(lambda), SystemKind::Penalized, warnings));
        }
        if adaptive {
            for c in 0..m {
                let cap = problem.k.diag(problem.constraints[c].dof).abs() / f64::EPSILON;
                if pen[c] > tol && pen[c] > 0.25 * prev_pen[c] && pen_eps[c] * 10.0 <= cap {
                    pen_eps[c] *= 10.0;
                }
            }
        }
        prev_pen = pen;
        start = Start::Point {
            u,
            solved_with: None,
        };
    }
}
