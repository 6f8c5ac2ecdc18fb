//! The IPC log-barrier (Li et al., "Incremental Potential Contact", SIGGRAPH 2020; the
//! adaptive stiffness of ipc-toolkit's `src/ipc/barrier/adaptive_stiffness.cpp`):
//!
//! `min Π(u) = ½uᵀKu − qᵀu + κ Σ_c b(d_c(u))`, `b(d) = −(d − d̂)² ln(d / d̂)` for 0 < d < d̂,
//! 0 for d ≥ d̂, with the distance `d_c = û_c − u[d_c]` (upper) or `u[d_c] − û_c` (lower) and
//! the knob d̂ (`--delta`: the barrier's activation distance).
//!
//! **Solver.** Newton on Π from a feasible start, each step `H p = −∇Π` with the Hessian
//! `H = K + D diag(κ b''(d)) Dᵀ` (b'' > 0 on (0, d̂): Π is strictly convex on the feasible set
//! for SPD K), solved as a penalized system ([`Context::solve_penalized_with`] with the
//! penalties κ b''(d_c) and shifted limits). The step length starts at min(1, 0.9 × the
//! largest step that keeps every d_c > 0) — the 1D analogue of IPC's conservative continuous
//! collision detection — and halves until Armijo's decrease holds, so **no iterate ever
//! penetrates**. Converged when the Newton decrement `−∇Πᵀp` is below the rounding level of Π
//! (64 ε_mach times the sum of its terms' magnitudes: no smaller decrease is observable) or the
//! step moves no DOF by more than 1e-12 of max(‖u‖∞, d̂).
//!
//! **Stiffness κ.** Initial κ by gradient balance at the start, `κ = −∇Bᵀ∇E / ‖∇B‖²`
//! (E the elastic energy, B = Σ b), clamped to [κ_min, 100 κ_min], where κ_min makes the
//! barrier as stiff as the structure halfway into its band: `κ_min b''(d̂/2) = k̄` (k̄ the
//! geometric mean of K\[d_c, d_c\], [`crate::system::Problem::mean_constraint_stiffness`]; in
//! ipc-toolkit k̄ is the average mass at 1e-8 of the bounding box). After each converged Newton
//! solve, κ doubles (warm-started re-solve, at most up to 100 κ_min) while the smallest
//! distance is below d̂_ε = 1e-2·d̂ and fell since the previous solve — ipc-toolkit's
//! `update_barrier_stiffness`, applied between static solves instead of between time steps.
//!
//! **Where it differs from a quadratic penalty.** A penalty acts only once a constraint is
//! violated and lets it penetrate (∝ 1/ε); the barrier acts before contact, at distances below
//! d̂, and never lets d reach 0: its error is a *gap* of up to d̂ where a penalty's is a
//! penetration. Its force κ|b'(d)| grows without bound as d → 0, so the Hessian's added
//! stiffness κ b''(d) ≈ κ d̂²/d² depends on how close the contact is pressed, not on a chosen ε.
//! ipc-toolkit passes squared distances to b; here d is the distance itself (one DOF per
//! constraint, so d is linear in u and its Hessian term is exactly κ b''(d)).
//!
//! When to use: when no penetration at all is acceptable and a small gap is (the knob d̂ bounds
//! it). Unilateral constraints only: a bilateral tie has no barrier form (it is refused with
//! an error; IPC enforces such conditions as Dirichlet data).

use super::{Context, Glyph, Knob, Knobs, Method, Solution, Strategy, SystemKind};
use crate::error::{Error, Result};
use crate::system::{ConstraintKind, Problem};

/// `barrier`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "barrier",
    summary: "IPC log-barrier with adaptive stiffness κ (activation distance δ = d̂)",
    label: "barrier (IPC, d̂ = δ)",
    rule_label: "barrier",
    knob: Knob::Delta,
    colour: 10,
    glyph: Glyph::Star,
    needs_k_inverse: false,
    targets_delta: true,
    bilateral: false,
    force_tol: super::force_control::FORCE_TOL,
    solve: run,
};

impl Method {
    /// The IPC log-barrier with activation distance d̂ (> 0).
    pub const fn barrier(dhat: f64) -> Method {
        Method::of(&STRATEGY, Knobs::delta(dhat))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.need_delta()?)
}

/// The barrier stiffness κ of a solve: the hidden second knob, recorded in every row.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct KappaReport {
    /// κ of the first Newton solve (gradient balance, clamped to [κ_min, κ_max]).
    pub initial: f64,
    /// κ of the returned solve.
    pub last: f64,
    /// Times κ was doubled (each a warm-started Newton solve).
    pub increases: usize,
    /// The clamp's lower end κ_min.
    pub min: f64,
    /// The clamp's upper end κ_max = 100 κ_min.
    pub max: f64,
}

/// `b(d)`, `b'(d)`, `b''(d)` of the clamped log barrier (0 for d ≥ d̂).
pub fn barrier(d: f64, dhat: f64) -> (f64, f64, f64) {
    if d >= dhat {
        return (0.0, 0.0, 0.0);
    }
    let (r, l) = (d - dhat, (d / dhat).ln());
    (
        -r * r * l,
        -2.0 * r * l - r * r / d,
        -2.0 * l - 4.0 * r / d + r * r / (d * d),
    )
}

/// Signed direction of the distance: d_c = s_c (u[dof] − û_c) with s = −1 (upper), +1 (lower).
fn side(kind: ConstraintKind) -> f64 {
    match kind {
        ConstraintKind::Upper => -1.0,
        _ => 1.0,
    }
}

fn distances(p: &Problem, u: &[f64]) -> Vec<f64> {
    p.constraints
        .iter()
        .map(|c| side(c.kind) * (u[c.dof] - c.limit))
        .collect()
}

/// Π(u) given `ku` = K u (+∞ where some d ≤ 0), and the rounding level of Π: 64 ε_mach times
/// the sum of its terms' magnitudes (no smaller decrease of Π is observable).
fn energy(p: &Problem, u: &[f64], ku: &[f64], kappa: f64, dhat: f64) -> (f64, f64) {
    let dot = |a: &[f64], b: &[f64], f: fn(f64) -> f64| -> f64 {
        a.iter().zip(b).map(|(x, y)| f(x * y)).sum()
    };
    let id = |v: f64| v;
    let e = 0.5 * dot(u, ku, id) - dot(u, &p.q, id);
    let mag = 0.5 * dot(u, ku, f64::abs) + dot(u, &p.q, f64::abs);
    let mut b = 0.0;
    for d in distances(p, u) {
        if d <= 0.0 {
            return (f64::INFINITY, f64::INFINITY);
        }
        b += barrier(d, dhat).0;
    }
    (e + kappa * b, 64.0 * f64::EPSILON * (mag + kappa * b))
}

/// The smallest distance d_c at u.
fn min_distance(p: &Problem, u: &[f64]) -> f64 {
    distances(p, u).into_iter().fold(f64::INFINITY, f64::min)
}

/// Newton's outcome at one κ.
struct NewtonRun {
    u: Vec<f64>,
    converged: bool,
}

/// Cap on Newton iterations per κ.
const MAX_NEWTON: usize = 200;

fn newton(ctx: &mut Context, mut u: Vec<f64>, kappa: f64, dhat: f64) -> Result<NewtonRun> {
    let p = ctx.problem;
    let scale_u = |u: &[f64]| u.iter().fold(dhat, |a, v| a.max(v.abs()));
    let mut ku = p.k.matvec(&u);
    for _ in 0..MAX_NEWTON {
        ctx.stats.iterations += 1;
        let d = distances(p, &u);
        // Penalties κ b''(d) and the limits ℓ with (K + D h Dᵀ) u_new = q + D h ℓ equal to
        // the Newton step: ℓ_c = u[dof] − s_c κ b'(d_c) / h_c.
        let mut h = vec![0.0; p.m()];
        let mut lim: Vec<f64> = p.constraints.iter().map(|c| c.limit).collect();
        let mut grad_b = vec![0.0; p.m()];
        for (c, con) in p.constraints.iter().enumerate() {
            let (_, b1, b2) = barrier(d[c], dhat);
            grad_b[c] = side(con.kind) * kappa * b1;
            if b2 > 0.0 {
                h[c] = kappa * b2;
                lim[c] = u[con.dof] - grad_b[c] / h[c];
            }
        }
        let u_new = ctx.solve_penalized_with(&h, &lim)?;
        let step: Vec<f64> = u_new.iter().zip(&u).map(|(a, b)| a - b).collect();
        // ∇Π = K u − q + D ∇B.
        let mut g: Vec<f64> = ku.iter().zip(&p.q).map(|(a, b)| a - b).collect();
        for (c, con) in p.constraints.iter().enumerate() {
            g[con.dof] += grad_b[c];
        }
        let slope: f64 = g.iter().zip(&step).map(|(a, b)| a * b).sum();
        let (e0, rounding) = energy(p, &u, &ku, kappa, dhat);
        let moved = step.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if -slope <= rounding || moved <= 1e-12 * scale_u(&u) {
            return Ok(NewtonRun { u, converged: true });
        }
        // Largest feasible step, times 0.9.
        let mut alpha = 1.0f64;
        for (c, con) in p.constraints.iter().enumerate() {
            let dd = side(con.kind) * step[con.dof];
            if dd < 0.0 {
                alpha = alpha.min(0.9 * d[c] / -dd);
            }
        }
        loop {
            let trial: Vec<f64> = u.iter().zip(&step).map(|(a, b)| a + alpha * b).collect();
            let k_trial = p.k.matvec(&trial);
            if energy(p, &trial, &k_trial, kappa, dhat).0 <= e0 + 1e-4 * alpha * slope {
                (u, ku) = (trial, k_trial);
                break;
            }
            alpha *= 0.5;
            if alpha < 1e-20 {
                // No decrease representable: the iterate is as good as rounding allows.
                return Ok(NewtonRun { u, converged: true });
            }
        }
    }
    Ok(NewtonRun {
        u,
        converged: false,
    })
}

/// Solves with the IPC log-barrier of activation distance `dhat` (module doc).
pub fn solve(mut ctx: Context, dhat: f64) -> Result<Solution> {
    let p = ctx.problem;
    if let Some(c) = p
        .constraints
        .iter()
        .position(|c| c.kind == ConstraintKind::Bilateral)
    {
        return Err(Error::input(format!(
            "barrier: constraint {c} is bilateral (a tie); the log barrier handles unilateral \
             constraints only — use a penalty rule or lagrange"
        )));
    }
    // Feasible start: u0, with every constraint closer than d̂/2 (or violated) moved to d̂/2.
    let mut u = ctx.u0()?.to_vec();
    for con in &p.constraints {
        let d = side(con.kind) * (u[con.dof] - con.limit);
        if d < 0.5 * dhat {
            u[con.dof] = con.limit + side(con.kind) * 0.5 * dhat;
        }
    }
    let kbar = p.mean_constraint_stiffness();
    let kappa_min = kbar / barrier(0.5 * dhat, dhat).2;
    let kappa_max = 100.0 * kappa_min;
    // Gradient balance at the start.
    let d = distances(p, &u);
    let ku = p.k.matvec(&u);
    let ge: Vec<f64> = ku.iter().zip(&p.q).map(|(a, b)| a - b).collect();
    let mut gb = vec![0.0; p.n()];
    for (c, con) in p.constraints.iter().enumerate() {
        gb[con.dof] += side(con.kind) * barrier(d[c], dhat).1;
    }
    let nb: f64 = gb.iter().map(|v| v * v).sum();
    let mut kappa = if nb > 0.0 {
        -gb.iter().zip(&ge).map(|(a, b)| a * b).sum::<f64>() / nb
    } else {
        kappa_min
    };
    kappa = kappa.clamp(kappa_min, kappa_max);
    let initial = kappa;
    let mut increases = 0;
    let mut run = newton(&mut ctx, u, kappa, dhat)?;
    let mut min_d = min_distance(p, &run.u);
    while min_d < 1e-2 * dhat && kappa < kappa_max {
        kappa = (2.0 * kappa).min(kappa_max);
        increases += 1;
        let next = newton(&mut ctx, run.u.clone(), kappa, dhat)?;
        let d_next = min_distance(p, &next.u);
        run = next;
        if d_next >= min_d {
            break;
        }
        min_d = d_next;
    }
    ctx.stats.converged = run.converged;
    ctx.stats.barrier = Some(KappaReport {
        initial,
        last: kappa,
        increases,
        min: kappa_min,
        max: kappa_max,
    });
    let d = distances(p, &run.u);
    let penalties: Vec<f64> = d.iter().map(|&dc| kappa * barrier(dc, dhat).2).collect();
    // Contact forces r with K u = q − D r: r_c = s_c κ b'(d_c).
    let forces: Vec<f64> = p
        .constraints
        .iter()
        .zip(&d)
        .map(|(con, &dc)| side(con.kind) * kappa * barrier(dc, dhat).1)
        .collect();
    let mut warnings = Vec::new();
    if !run.converged {
        warnings.push(format!(
            "barrier: NOT CONVERGED: Newton reached its cap of {MAX_NEWTON} iterations at κ = {kappa:.3e}"
        ));
    }
    Ok(ctx.finish(
        Method::barrier(dhat),
        run.u,
        penalties,
        Some(forces),
        SystemKind::Penalized,
        warnings,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// b, b', b'' against central differences, and the barrier's shape: positive and
    /// decreasing on (0, d̂), zero with zero slope at d̂.
    #[test]
    fn barrier_derivatives() {
        let dhat = 0.3;
        for &d in &[1e-4, 0.01, 0.1, 0.2, 0.29] {
            let (b, b1, b2) = barrier(d, dhat);
            let h = 1e-6 * d;
            let (bp, b1p, _) = barrier(d + h, dhat);
            let (bm, b1m, _) = barrier(d - h, dhat);
            assert!(b > 0.0 && b1 < 0.0 && b2 > 0.0);
            assert!(((bp - bm) / (2.0 * h) - b1).abs() <= 1e-6 * b1.abs().max(b.abs()));
            assert!(((b1p - b1m) / (2.0 * h) - b2).abs() <= 1e-5 * b2.abs());
        }
        assert_eq!(barrier(dhat, dhat), (0.0, 0.0, 0.0));
        let (b, b1, _) = barrier(dhat * (1.0 - 1e-9), dhat);
        assert!(b.abs() < 1e-18 && b1.abs() < 1e-9);
    }
}
