//! Classical penalty (Eq. 7–9): `(K + ε D_A D_Aᵀ) u = q + ε D_A û_A`, one ε for every active
//! constraint A.
//!
//! When to use: when a good ε is known. Too small and contact leaks (penetration ∝ 1/ε), too
//! large and cond(K + εDDᵀ) grows ∝ ε.

use super::{fixed_energy, Context, Method, Solution};
use crate::error::Result;

/// Solves with the constant penalty ε (> 0, validated by [`Method::from_name`]): the unique
/// minimizer of `½uᵀKu − qᵀu + ½ε Σ_c p_c(u)²` (see [`super::active_set`]).
pub fn solve(ctx: Context, eps: f64) -> Result<Solution> {
    let m = ctx.problem.m();
    fixed_energy(ctx, Method::Constant { eps }, vec![eps; m])
}
