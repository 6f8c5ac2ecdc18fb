//! Classical penalty (Eq. 7–9): `(K + ε D_A D_Aᵀ) u = q + ε D_A û_A`, one ε for every active
//! constraint A.
//!
//! When to use: when a good ε is known. Too small and contact leaks (penetration ∝ 1/ε), too
//! large and cond(K + εDDᵀ) grows ∝ ε.

use super::{fixed_energy, Context, Glyph, Knob, Knobs, Method, Solution, Strategy};
use crate::error::Result;

/// `constant`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "constant",
    summary: "Classical constant penalty ε",
    label: "constant",
    rule_label: "constant",
    knob: Knob::Eps,
    colour: 0,
    glyph: Glyph::Square,
    needs_k_inverse: false,
    targets_delta: false,
    bilateral: true,
    force_tol: super::force_control::FORCE_TOL,
    solve: run,
};

impl Method {
    /// The classical penalty ε (> 0).
    pub const fn constant(eps: f64) -> Method {
        Method::of(&STRATEGY, Knobs::eps(eps))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.value(m.knobs().eps, "--eps")?)
}

/// Solves with the constant penalty ε (> 0, validated by [`Method::from_name`]): the unique
/// minimizer of `½uᵀKu − qᵀu + ½ε Σ_c p_c(u)²` (see [`super::active_set`]).
pub fn solve(ctx: Context, eps: f64) -> Result<Solution> {
    let m = ctx.problem.m();
    fixed_energy(ctx, Method::constant(eps), vec![eps; m])
}
