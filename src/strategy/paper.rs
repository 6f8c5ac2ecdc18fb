//! The paper's modified penalty, Eq. 26–29, literally:
//!
//! `ε̄_cc = (|K̄ û − q̄|_c − (K̄ δ1)_c) / δ`, `K̄ = DᵀKD`, `q̄ = Dᵀq` (m×m and m, over the active
//! constraints), then `ε = D ε̄ Dᵀ` (Eq. 29).
//!
//! On the paper's beam (δ = 0.1) this gives ε = (501.9, 1390, 557) and cond(K + ε) = 513.871.
//! The estimate uses K̄ = DᵀKD, which is stiffer than the true condensed stiffness S⁻¹
//! (`K̄ ⪰ S⁻¹`), so the penalties over-shoot and the gaps come out well below δ — on the beam by
//! an order of magnitude (Eq. 37); see [`super::condensed`] for the exact version. A negative
//! ε̄ (e.g. a tool node with no load of its own) is warned and clipped to 0.

use super::{fixed_point, per_active, Context, Method, Solution};
use crate::error::Result;
use crate::system::Problem;

/// Eq. 28 for the active constraints (0 elsewhere), before clipping.
///
/// `K̄x = Dᵀ(K(Dx))`, so `K̄û` and `K̄δ1` are two products with K of the vectors `Dû` and `D1`
/// (entries at the active constrained DOFs, summed where constraints share a DOF): O(nnz K),
/// never the m×m K̄.
pub fn eq28(problem: &Problem, active: &[bool], delta: f64) -> Vec<f64> {
    let n = problem.n();
    let (mut d_u, mut d_one) = (vec![0.0; n], vec![0.0; n]);
    for (c, con) in problem.constraints.iter().enumerate() {
        if active[c] {
            d_u[con.dof] += con.limit;
            d_one[con.dof] += 1.0;
        }
    }
    let (k_du, k_done) = (problem.k.matvec(&d_u), problem.k.matvec(&d_one));
    per_active(problem, active, |_, con| {
        let d = con.dof;
        ((k_du[d] - problem.q[d]).abs() - delta * k_done[d]) / delta
    })
}

/// Solves with the Eq. 28 penalties for allowed penetration δ.
pub fn solve(ctx: Context, delta: f64) -> Result<Solution> {
    fixed_point(ctx, Method::Paper { delta }, |active, ctx| {
        Ok(eq28(ctx.problem, active, delta))
    })
}
