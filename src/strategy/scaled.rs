//! Stiffness-scaled penalty: `ε_c = f · K[d_c, d_c]` — the "penalty ∝ element stiffness"
//! default of commercial and open codes. For a row `d_c` with several terms
//! `ε_c = f · d_cᵀKd_c/‖d_c‖⁴` ([`Constraint::stiffness`]): the penalty's stiffness along the
//! row is f times K's, whatever the row's scaling (`f · d_cᵀKd_c` for a unit normal).
//!
//! [`Constraint::stiffness`]: crate::system::Constraint::stiffness
//!
//! When to use: a dimensionless knob that adapts to the units and to the local stiffness; the
//! penetration still depends on the load (it is not a δ).

use super::{fixed_energy, Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy};
use crate::error::Result;

/// `scaled`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "scaled",
    summary: "ε = factor · d_cᵀKd_c/‖d_c‖⁴ (K_dd for one DOF) per constraint",
    knob: Knob::Factor,
    solve: run,
    look: Look {
        colour: 1,
        glyph: Glyph::TriangleDown,
        ..Look::BASE
    },
    ..Strategy::BASE
};

impl Method {
    /// The stiffness-scaled penalty ε_c = factor · K[d_c, d_c] (factor > 0).
    pub const fn scaled(factor: f64) -> Method {
        Method::of(&STRATEGY, Knobs::factor(factor))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.value(m.knobs().factor, super::symbol::FACTOR)?)
}

/// Solves with `ε_c = factor · K[d_c, d_c]`: a fixed energy, minimized exactly (see
/// [`super::active_set`]).
pub fn solve(ctx: Context, factor: f64) -> Result<Solution> {
    let k = &ctx.problem.k;
    let eps = ctx
        .problem
        .constraints
        .iter()
        .map(|c| factor * c.stiffness(k).abs())
        .collect();
    fixed_energy(ctx, Method::scaled(factor), eps)
}
