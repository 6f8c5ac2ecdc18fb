//! Eq. 17 per constraint, ignoring coupling (the 1-DOF spring of Fig. 1):
//!
//! `ε_c = (q_d − k (û_c + s δ)) / (s δ)`, `k = K[d,d]`, `q_d = q[d]`, `s = sign(g0_c)`,
//!
//! which puts a lone spring exactly at `u = û + sδ`. For `s = −1` this is the paper's Eq. 17,
//! `ε = (k(û − δ) − q) / δ`. For a row `d_c` with several terms the spring is the motion along
//! the row, `u = α d_c`: stationarity of the penalized energy in α with gap `sδ` gives the
//! same formula with `k = d_cᵀKd_c/‖d_c‖⁴` ([`Constraint::stiffness`]) and
//! `q_d = d_cᵀq/‖d_c‖²` (for a unit row, a normal: `d_cᵀKd_c` and `d_cᵀq`). Unilateral constraints use the side of their obstacle
//! (`upper`: s = +1, `lower`: s = −1) whenever they are active; bilateral ones the side of the
//! unconstrained solution (and no penalty when `|g0_c| ≤ δ`).
//!
//! When to use: a sanity baseline. In a coupled system the rest of the structure also carries
//! load, so the penetration is not δ; when `|q_d|` is small the formula goes negative (warned
//! and clipped to 0).
//!
//! [`Constraint::stiffness`]: crate::system::Constraint::stiffness

use super::{
    fixed_point, per_active, Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy,
};
use crate::error::Result;
use crate::system::ConstraintKind;

/// `spring`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "spring",
    summary: "The 1-DOF spring rule for δ (Eq. 17)",
    knob: Knob::Delta,
    needs_k_inverse: true,
    solve: run,
    look: Look {
        label: "spring (Eq. 17)",
        colour: 2,
        glyph: Glyph::Circle,
        ..Look::BASE
    },
    ..Strategy::BASE
};

impl Method {
    /// Eq. 17 per constraint for allowed penetration δ (> 0).
    pub const fn spring(delta: f64) -> Method {
        Method::of(&STRATEGY, Knobs::delta(delta))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.need_delta()?)
}

/// Solves with Eq. 17 penalties for allowed penetration δ.
pub fn solve(ctx: Context, delta: f64) -> Result<Solution> {
    fixed_point(ctx, Method::spring(delta), |active, ctx| {
        let g0 = ctx.g0()?;
        let p = ctx.problem;
        Ok(per_active(p, active, |c, con| {
            let s = match con.kind {
                ConstraintKind::Upper => 1.0,
                ConstraintKind::Lower => -1.0,
                // A bilateral tie already within δ of u0 needs no penalty.
                ConstraintKind::Bilateral if g0[c].abs() <= delta => return 0.0,
                ConstraintKind::Bilateral => g0[c].signum(),
            };
            let k = con.stiffness(&p.k);
            (con.value(&p.q) / con.norm2() - k * (con.limit + s * delta)) / (s * delta)
        }))
    })
}
