//! The paper's modified penalty, Eq. 26–29, literally:
//!
//! `ε̄_cc = (|K̄ û − q̄|_c − (K̄ δ1)_c) / δ`, `K̄ = DᵀKD`, `q̄ = Dᵀq` (m×m and m, over the active
//! constraints), then `ε = D ε̄ Dᵀ` (Eq. 29).
//!
//! General D (rows with several terms): the same formula with `(K̄x)_c = d_cᵀK(Dx)` and
//! `q̄_c = d_cᵀq`; the paper writes Eq. 28 for a general D and applies it to a Boolean one.
//!
//! On the paper's beam (δ = 0.1) this gives ε = (501.9, 1390, 557) and cond(K + ε) = 513.871.
//! The estimate uses K̄ = DᵀKD, which is stiffer than the true condensed stiffness S⁻¹
//! (`K̄ ⪰ S⁻¹`), so the penalties over-shoot and the gaps come out well below δ — on the beam by
//! an order of magnitude (Eq. 37); see [`super::condensed`] for the exact version. A negative
//! ε̄ (e.g. a tool node with no load of its own) is warned and clipped to 0.

use super::{
    fixed_point, per_active, Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy,
};
use crate::error::Result;
use crate::system::Problem;

/// `paper`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "paper",
    summary: "The paper's rule (Eq. 28–29)",
    knob: Knob::Delta,
    solve: run,
    look: Look {
        label: "paper (Eq. 26–29)",
        rule_label: "paper (Eq. 28)",
        colour: 3,
        glyph: Glyph::Triangle,
    },
    ..Strategy::BASE
};

impl Method {
    /// The paper's Eq. 26–29 for allowed penetration δ (> 0).
    pub const fn paper(delta: f64) -> Method {
        Method::of(&STRATEGY, Knobs::delta(delta))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.need_delta()?)
}

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
            con.scatter(&mut d_u, con.limit);
            con.scatter(&mut d_one, 1.0);
        }
    }
    let (k_du, k_done) = (problem.k.matvec(&d_u), problem.k.matvec(&d_one));
    per_active(problem, active, |_, con| {
        let r = con.value(&k_du) - con.value(&problem.q);
        (r.abs() - delta * con.value(&k_done)) / delta
    })
}

/// Solves with the Eq. 28 penalties for allowed penetration δ.
pub fn solve(ctx: Context, delta: f64) -> Result<Solution> {
    fixed_point(ctx, Method::paper(delta), |active, ctx| {
        Ok(eq28(ctx.problem, active, delta))
    })
}

/// Eq. 28 with the unconstrained DOFs' coupling evaluated at a reference state `u_ref`
/// instead of dropped (the reading a flow-approach code needs, see `forming::solver`).
///
/// Eq. 18–27 estimate the force a constrained DOF carries from its own equation row with the
/// other unknowns at zero: `|K̄û − q̄|`. In an incremental or iterative code the other unknowns
/// are known from the previous iterate, so the row's residual with the constrained DOFs at
/// their limits is `r = K ũ − q`, `ũ = (I − D Dᵀ) u_ref + D û` (u_ref off the active
/// constrained DOFs, û on them), and
///
/// `ε_c = (|d_cᵀr| − (K̄ δ1)_c) / δ`.
///
/// For a row with several terms ũ is u_ref projected orthogonally onto each active row's
/// plane `d_cᵀũ = û_c` in turn (one sweep: exact where active rows share no DOF).
///
/// With `u_ref = 0` this is [`eq28`] exactly. At a fixed point `u = u_ref` of the outer
/// iteration, every constraint whose residual has the sign of its penetration ends with gap
/// exactly δ (the row `(K u)_c + ε_c g_c = q_c` with `u_c = û_c + s δ`), i.e. the reading is
/// δ-targeting without the condensed flexibility `S = DᵀK⁻¹D`.
pub fn eq28_at(problem: &Problem, active: &[bool], delta: f64, u_ref: &[f64]) -> Vec<f64> {
    let n = problem.n();
    let mut u_tilde = u_ref.to_vec();
    let mut d_one = vec![0.0; n];
    for (c, con) in problem.constraints.iter().enumerate() {
        if let (true, Some(d)) = (active[c], con.single_dof()) {
            u_tilde[d] = 0.0;
        }
    }
    for (c, con) in problem.constraints.iter().enumerate() {
        if active[c] {
            match con.single_dof() {
                Some(_) => con.scatter(&mut u_tilde, con.limit),
                None => con.set_value(&mut u_tilde, con.limit),
            }
            con.scatter(&mut d_one, 1.0);
        }
    }
    let (k_u, k_done) = (problem.k.matvec(&u_tilde), problem.k.matvec(&d_one));
    per_active(problem, active, |_, con| {
        let r = con.value(&k_u) - con.value(&problem.q);
        (r.abs() - delta * con.value(&k_done)) / delta
    })
}

/// Solves with the [`eq28_at`] penalties (reference state `u_ref`, length `problem.n()`) for
/// allowed penetration δ; negative penalties are clipped to 0 and counted as for [`solve`].
pub fn solve_at(ctx: Context, delta: f64, u_ref: &[f64]) -> Result<Solution> {
    fixed_point(ctx, Method::paper(delta), |active, ctx| {
        Ok(eq28_at(ctx.problem, active, delta, u_ref))
    })
}

/// Eq. 28 at the residual ([`eq28_at`], the predictor) followed by the corrector passes of
/// Eq. 18–19 solved for ε with the contact force known: the force a constrained DOF carries in
/// the last solve is `|ε_c g_c|`, and holding that force at penetration δ takes
/// `ε_c ← |ε_c g_c| / δ = ε_c |g_c| / δ` (factor clamped to [0.1, 10] per pass).
///
/// A predictor ≤ 0 (Eq. 28 says the DOF at penetration δ carries no compressive force, which
/// the coupling to its constrained neighbours can contradict) starts the DOF from its diagonal
/// stiffness `K_dd` instead of releasing it; such DOFs are counted in `stats.clipped`.
/// Passes stop when every penalized DOF's `|g_c|` is within `rtol · δ` of δ or after
/// `max_passes`; then `stats.converged = false` with a warning giving the worst `|g_c|/δ`.
/// For a DOF decoupled from the others the correction converges at the rate
/// `k/(ε + k)` (k its stiffness), monotonically. Statistics are summed over the passes.
pub fn solve_residual(
    problem: &Problem,
    delta: f64,
    u_ref: &[f64],
    rtol: f64,
    max_passes: usize,
) -> Result<Solution> {
    let m = problem.m();
    let all = vec![true; m];
    let mut eps = eq28_at(problem, &all, delta, u_ref);
    let mut floored = 0;
    for (e, con) in eps.iter_mut().zip(&problem.constraints) {
        if *e <= 0.0 {
            *e = con.stiffness(&problem.k).abs();
            floored += 1;
        }
    }
    let (mut its, mut solves, mut facts) = (0, 0, 0);
    let mut worst = f64::INFINITY;
    let mut sol = None;
    for _ in 0..max_passes.max(1) {
        let given = eps.clone();
        let next = fixed_point(Context::new(problem), Method::paper(delta), |active, _| {
            Ok(given
                .iter()
                .zip(active)
                .map(|(&e, &a)| if a { e } else { 0.0 })
                .collect())
        })?;
        its += next.stats.iterations;
        solves += next.stats.linear_solves;
        facts += next.stats.factorizations;
        worst = next
            .gaps
            .iter()
            .map(|g| (g.abs() / delta - 1.0).abs())
            .fold(0.0, f64::max);
        for (e, g) in eps.iter_mut().zip(&next.gaps) {
            *e *= (g.abs() / delta).clamp(0.1, 10.0);
        }
        sol = Some(next);
        if worst <= rtol {
            break;
        }
    }
    let mut sol = sol.expect("one pass at least");
    sol.stats.iterations = its;
    sol.stats.linear_solves = solves;
    sol.stats.factorizations = facts;
    sol.stats.clipped = floored;
    if worst > rtol {
        sol.stats.converged = false;
        sol.warnings.push(format!(
            "paper (Eq. 28 at the residual + Eq. 18 correction): worst |g|/δ − 1 = {worst:.2e} \
             after {max_passes} passes"
        ));
    }
    Ok(sol)
}
