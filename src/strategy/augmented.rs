//! Augmented Lagrangian (Uzawa iteration).
//!
//! With multipliers λ (contact forces, `K u = q − D λ`) and penalties ε_c, each iteration solves
//! the penalty problem with **shifted limits** `û'_c = û_c − λ_c/ε_c`:
//!
//! `(K + D_A E D_Aᵀ) u = q + D_A E û'_A`, force `r_c = ε_c (d_cᵀu − û'_c) = λ_c + ε_c g_c`,
//!
//! (unilateral constraints active while their force has the obstacle's sign), then updates
//! `λ ← r` until `max penetration ≤ tol`.
//!
//! **Adaptive variant** (per-constraint penalties from the gap history, in the spirit of
//! Bussetta–Marceau–Ponthot 2012). For one constraint of condensed stiffness k the Uzawa update
//! contracts the penetration by `ρ = k/(k + ε)`; after each update (from the second on) the
//! observed `ρ_c = p_c^{(j)} / p_c^{(j−1)}` gives `k/ε_c = ρ_c/(1 − ρ_c)`, and the penalty that
//! would bring `p_c` to `tol/2` in one more update is
//! `ε_c' = ε_c · ρ_c/(1 − ρ_c) · (2p_c/tol − 1)` (half the tolerance, so that the stopping test
//! is not decided by rounding, as it would be at a prediction of exactly `tol`).
//! Where the next penetration predicted at the present penalty, `ρ_c·p_c`, is still above
//! `tol`, ε_c grows to that value — at most ×1000 per update (the prediction of a coupled set
//! is rough) and at most `K_dd / ε_mach` (beyond it `K_dd + ε_c` no longer holds any digit of
//! K_dd, and a tolerance below rounding would drive ε_c to overflow). Where the penetration did
//! not shrink (ρ_c ≥ 1: the active set moved) ε_c grows ×10. It trades conditioning for
//! updates: fewer solves where plain Uzawa contracts slowly (a soft ε), a larger final ε.
//!
//! When to use: penetration driven to any tolerance with a moderate ε (good conditioning), at
//! the price of several solves.

use super::active_set::{newton, Start};
use super::{Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy, SystemKind};
use crate::error::Result;
use crate::system::ConstraintKind;

/// `augmented`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "augmented",
    summary: "Augmented Lagrangian",
    knob: Knob::EpsTol,
    solve: run,
    look: Look {
        colour: 6,
        glyph: Glyph::Pentagon,
        ..Look::BASE
    },
    ..Strategy::BASE
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
        m.value(m.knobs().eps, super::symbol::EPS)?,
        m.value(m.knobs().tol, super::symbol::TOL)?,
        m.knobs().adaptive,
    )
}

/// Maximum Uzawa updates.
pub const MAX_UPDATES: usize = 500;

/// The adaptive variant aims the next penetration at this fraction of the tolerance.
pub const TARGET: f64 = 0.5;

/// Largest growth of a penalty in one update of the adaptive variant.
pub const MAX_GROWTH: f64 = 1e3;

/// The adaptive variant's penalty after an update (module doc): `eps` the present penalty,
/// `pen` and `prev` the penetrations after this update and the one before (`prev = ∞` after the
/// first), `tol` the tolerance. Unchanged where the penetration is within `tol`, where there is
/// no history, or where one more update at `eps` is predicted to reach `tol`.
pub fn adapted_penalty(eps: f64, pen: f64, prev: f64, tol: f64) -> f64 {
    if !(pen > tol && prev.is_finite() && prev > 0.0) {
        return eps;
    }
    let rho = pen / prev;
    if rho >= 1.0 {
        return 10.0 * eps;
    }
    if rho * pen <= tol {
        return eps;
    }
    let factor = rho / (1.0 - rho) * (pen / (TARGET * tol) - 1.0);
    eps * factor.clamp(1.0, MAX_GROWTH)
}

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
                e[c] * (problem.constraints[c].value(&u) - limits[c])
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
                let cap = problem.constraints[c].stiffness(&problem.k).abs() / f64::EPSILON;
                pen_eps[c] = adapted_penalty(pen_eps[c], pen[c], prev_pen[c], tol).min(cap);
            }
        }
        prev_pen = pen;
        start = Start::Point {
            u,
            solved_with: None,
        };
    }
}

#[cfg(test)]
mod tests {
    use super::adapted_penalty;

    /// One constraint of condensed stiffness k: Uzawa contracts by ρ = k/(k + ε), and the
    /// penalty the rule picks from the observed ρ brings the next penetration to `tol`.
    #[test]
    fn the_adapted_penalty_reaches_tol_in_one_update_on_one_constraint() {
        let (k, eps, tol) = (1e3, 10.0, 1e-9);
        let rho = k / (k + eps);
        let (prev, pen) = (1e-3, 1e-3 * rho);
        let e2 = adapted_penalty(eps, pen, prev, tol);
        assert!(e2 > eps && e2 <= eps * super::MAX_GROWTH);
        // Unclamped: ε = k (ρ = 1/2), a gap of 20× tol to close (40× its aim).
        let eps = k;
        let pen = 0.5 * prev;
        let tol = pen * 0.05;
        let e2 = adapted_penalty(eps, pen, prev, tol);
        assert!(e2 < eps * super::MAX_GROWTH);
        let next = pen * k / (k + e2);
        let aim = super::TARGET * tol;
        assert!((next / aim - 1.0).abs() < 1e-9, "{next} vs {aim}");
        // No history, within tol, or one more plain update enough: unchanged.
        assert_eq!(adapted_penalty(eps, pen, f64::INFINITY, tol), eps);
        assert_eq!(adapted_penalty(eps, 0.5 * tol, prev, tol), eps);
        assert_eq!(adapted_penalty(eps, 1.5 * tol, 1e6 * tol, tol), eps);
        // A penetration that grew: ×10.
        assert_eq!(adapted_penalty(eps, 2.0 * prev, prev, tol), 10.0 * eps);
    }
}
