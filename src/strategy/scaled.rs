//! Stiffness-scaled penalty: `ε_c = f · K[d_c, d_c]` — the "penalty ∝ element stiffness"
//! default of commercial and open codes.
//!
//! When to use: a dimensionless knob that adapts to the units and to the local stiffness; the
//! penetration still depends on the load (it is not a δ).

use super::{penalty_active_set, Context, Method, Solution};
use crate::error::Result;

/// Solves with `ε_c = factor · K[d_c, d_c]`.
pub fn solve(ctx: Context, factor: f64) -> Result<Solution> {
    penalty_active_set(ctx, Method::Scaled { factor }, |active, ctx| {
        let k = &ctx.problem.k;
        Ok(ctx
            .problem
            .constraints
            .iter()
            .zip(active)
            .map(|(c, &a)| if a { factor * k.diag(c.dof).abs() } else { 0.0 })
            .collect())
    })
}
