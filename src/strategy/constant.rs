//! Classical penalty (Eq. 7–9): `(K + ε D_A D_Aᵀ) u = q + ε D_A û_A`, one ε for every active
//! constraint A.
//!
//! When to use: when a good ε is known. Too small and contact leaks (penetration ∝ 1/ε), too
//! large and cond(K + εDDᵀ) grows ∝ ε.

use super::{penalty_active_set, Context, Method, Solution};
use crate::error::Result;

/// Solves with the constant penalty ε (> 0, validated by [`Method::from_name`]).
pub fn solve(ctx: Context, eps: f64) -> Result<Solution> {
    penalty_active_set(ctx, Method::Constant { eps }, |active, _| {
        Ok(active.iter().map(|&a| if a { eps } else { 0.0 }).collect())
    })
}
