//! Stiffness-scaled penalty: `ε_c = f · K[d_c, d_c]` — the "penalty ∝ element stiffness"
//! default of commercial and open codes.
//!
//! When to use: a dimensionless knob that adapts to the units and to the local stiffness; the
//! penetration still depends on the load (it is not a δ).

use super::{fixed_energy, Context, Method, Solution};
use crate::error::Result;

/// Solves with `ε_c = factor · K[d_c, d_c]`: a fixed energy, minimized exactly (see
/// [`super::active_set`]).
pub fn solve(ctx: Context, factor: f64) -> Result<Solution> {
    let k = &ctx.problem.k;
    let eps = ctx
        .problem
        .constraints
        .iter()
        .map(|c| factor * k.diag(c.dof).abs())
        .collect();
    fixed_energy(ctx, Method::Scaled { factor }, eps)
}
