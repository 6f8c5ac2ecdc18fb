//! Classical penalty (Eq. 7–9): `(K + D_A E_A D_Aᵀ) u = q + D_A E_A û_A` with
//! `E = diag(ε ω_c)`: one ε for every active constraint A, times the constraint's tributary
//! weight ω_c where the problem knows its contact surface ([`crate::system::Surface`]).
//!
//! **Units.** On a bare problem (K, q, D as a scene file gives them; ω_c = 1) ε is a nodal
//! stiffness, force/length. Where the problem carries its surface (the elastic benchmarks),
//! ε is per unit contact length (plane strain) or area (axisymmetric, per radian): pressure
//! per penetration, force/length³, as FEBio, Abaqus and MOOSE define it — the same ε then
//! gives the same contact pressure for the same penetration on every mesh and at every node,
//! including the axis node whose tributary area is small.
//!
//! When to use: when a good ε is known. Too small and contact leaks (penetration ∝ 1/ε), too
//! large and cond(K + εDDᵀ) grows ∝ ε.

use super::{fixed_energy, Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy};
use crate::error::Result;

/// `constant`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "constant",
    summary: "Classical constant penalty ε",
    knob: Knob::Eps,
    solve: run,
    look: Look {
        colour: 0,
        glyph: Glyph::Square,
        ..Look::BASE
    },
    ..Strategy::BASE
};

impl Method {
    /// The classical penalty ε (> 0).
    pub const fn constant(eps: f64) -> Method {
        Method::of(&STRATEGY, Knobs::eps(eps))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.value(m.knobs().eps, super::symbol::EPS)?)
}

/// Solves with the constant penalty ε (> 0, validated by [`Method::from_name`]): the unique
/// minimizer of `½uᵀKu − qᵀu + ½ Σ_c ε ω_c p_c(u)²` (see [`super::active_set`]; ω_c = 1
/// without a surface).
pub fn solve(ctx: Context, eps: f64) -> Result<Solution> {
    let p = ctx.problem;
    let nodal = (0..p.m()).map(|c| eps * p.weight(c)).collect();
    fixed_energy(ctx, Method::constant(eps), nodal)
}
