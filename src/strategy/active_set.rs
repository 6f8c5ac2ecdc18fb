//! The active-set machinery shared by the penalty strategies: one driver per kind of rule.
//!
//! # Fixed energy: globalized semismooth Newton ([`newton`])
//!
//! For a rule whose penalties do not depend on the active set (`constant`, `scaled`, the inner
//! solves of `augmented`) and a symmetric K, the penalized solution is the unique minimizer of
//! the strictly convex, piecewise quadratic, C¹ energy
//!
//! `J(u) = ½ uᵀK u − qᵀu + ½ Σ_c ε_c p_c(u)²`,  `p_c` = penetration of `d_cᵀu − ℓ_c`
//!
//! (ℓ = û, or the shifted limits of the augmented Lagrangian). Its gradient is
//! `∇J(u) = K u − q + Σ_c ε_c π_c(g_c) e_{d_c}` with `π` = identity (bilateral), `max(0, ·)`
//! (upper) or `min(0, ·)` (lower), and on the set A(u) of penalized constraints
//! (bilateral, or strictly violated) `∇J(u) = H_A u − b_A` with `H_A = K + D_A E D_Aᵀ`,
//! `b_A = q + D_A E ℓ_A`. The semismooth Newton step is therefore `u_N = H_A⁻¹ b_A` — exactly
//! one solve of the classical active-set loop — and `d = u_N − u` is a descent direction,
//! `∇J(u)ᵀd = −dᵀH_A d < 0`. The plain loop (`u ← u_N`) can cycle; here the step is
//! globalized by an **exact line search** on `φ(t) = J(u + t d)`, t ∈ (0, 1]: `φ'` is
//! piecewise linear and non-decreasing with breakpoints where a gap crosses its limit, so its
//! root is found exactly by walking the sorted breakpoints (O(m log m), two products with K).
//!
//! Termination: J decreases strictly at every step that is not at the minimizer, J is strictly
//! convex and has finitely many quadratic pieces, so the iterates converge to the unique
//! minimizer; once the active set of the minimizer is identified, the full step lands on it
//! and the loop stops when `A(u_N)` equals the set `u_N` was solved with (then `∇J(u_N) = 0`
//! up to rounding). A constraint whose gap at the minimizer is at its limit (degenerate: zero
//! force, zero penetration) may flip between sets by rounding; the loop also stops when the
//! normwise backward error `‖∇J(u)‖_∞ / (‖H_A‖_∞ ‖u‖_∞ + ‖b_A‖_∞)` is at the rounding level
//! ([`backward_error_tol`]). An iteration cap (never reached in the tests) is kept as a
//! safeguard and reported as `converged = false`.
//!
//! # Set-dependent rules: fixed point with cycle detection ([`fixed_point`])
//!
//! `spring` (Eq. 17) and `paper` (Eq. 28) compute ε from the active set itself, so there is no
//! energy to descend and the fixed-point iteration "penalize the violated constraints, re-solve"
//! may cycle. Terminating rule: iterate from the set violated by u0; stop at a consistent set
//! (converged); stop when a set repeats or after [`max_iterations`] and return the **visited
//! iterate with the least active-set violation** (the largest penetration of an unpenalized
//! constraint, or the largest separation of a penalized unilateral one), with
//! `converged = false` and a warning naming the rule. The same driver serves a fixed-energy
//! rule on an unsymmetric K (friction), where no energy exists.

use super::{Context, Method, Solution, SystemKind};
use crate::error::{Error, Result};
use crate::system::{ConstraintKind, Problem};
use std::collections::HashSet;

/// Is constraint `c` penalized at `u` for the limit `limit`? Bilateral: always; unilateral:
/// while strictly violated.
fn penalized_at(kind: ConstraintKind, g: f64) -> bool {
    match kind {
        ConstraintKind::Bilateral => true,
        k => k.penetration(g) > 0.0,
    }
}

/// Is constraint `c` to be penalized at the trial solution `u`? Bilateral: always;
/// unilateral: while violated (penetration > 0).
pub fn violated(problem: &Problem, c: usize, u: &[f64]) -> bool {
    let con = &problem.constraints[c];
    penalized_at(con.kind, con.gap(u))
}

/// The starting active set: every constraint violated by u0 = K⁻¹q. u0 is not computed when
/// every constraint is bilateral (all start active), and if K is singular every constraint
/// starts active.
pub fn initial_active_set(ctx: &mut Context) -> Result<Vec<bool>> {
    let problem = ctx.problem;
    let m = problem.m();
    if problem
        .constraints
        .iter()
        .all(|c| c.kind == ConstraintKind::Bilateral)
    {
        return Ok(vec![true; m]);
    }
    match ctx.u0() {
        Ok(u0) => {
            let u0 = u0.to_vec();
            Ok((0..m).map(|c| violated(problem, c, &u0)).collect())
        }
        Err(Error::Singular(_)) => Ok(vec![true; m]),
        Err(e) => Err(e),
    }
}

/// Upper bound on active-set iterations (a safeguard; the drivers report reaching it).
pub fn max_iterations(m: usize) -> usize {
    4 * m + 50
}

/// `π_c(g)`: the signed part of the gap that the penalty acts on (gap if penalized, else 0).
fn pi(kind: ConstraintKind, g: f64) -> f64 {
    match kind {
        ConstraintKind::Bilateral => g,
        ConstraintKind::Upper => g.max(0.0),
        ConstraintKind::Lower => g.min(0.0),
    }
}

/// The gradient `∇J(u) = K u − q + Σ_c ε_c π_c(d_cᵀu − ℓ_c) d_c` of the penalized energy
/// (see the module docs). `eps[c]` is the penalty constraint c gets while penalized.
pub fn energy_gradient(problem: &Problem, eps: &[f64], limits: &[f64], u: &[f64]) -> Vec<f64> {
    let mut grad = problem.k.matvec(u);
    for (gi, qi) in grad.iter_mut().zip(&problem.q) {
        *gi -= qi;
    }
    for ((con, &e), &l) in problem.constraints.iter().zip(eps).zip(limits) {
        con.scatter(&mut grad, e * pi(con.kind, con.value(u) - l));
    }
    grad
}

/// Normwise backward error of `u` as a minimizer of the penalized energy:
/// `‖∇J(u)‖_∞ / (‖H_A‖_∞ ‖u‖_∞ + ‖b_A‖_∞)` with A the penalized set at u (Rigal–Gaches: the
/// smallest relative perturbation of `H_A` and `b_A` for which u is exact). `grad` is
/// [`energy_gradient`] at u, `k_inf` is ‖K‖_∞.
pub fn backward_error(
    problem: &Problem,
    eps: &[f64],
    limits: &[f64],
    u: &[f64],
    grad: &[f64],
    k_inf: f64,
) -> f64 {
    let mut b = problem.q.clone();
    let mut e_max = 0.0f64;
    for ((con, &e), &l) in problem.constraints.iter().zip(eps).zip(limits) {
        if penalized_at(con.kind, con.value(u) - l) {
            con.scatter(&mut b, e * l);
            e_max = e_max.max(e);
        }
    }
    let inf = |v: &[f64]| v.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let denom = (k_inf + e_max) * inf(u) + inf(&b);
    if denom == 0.0 {
        return inf(grad);
    }
    inf(grad) / denom
}

/// The backward error at which [`newton`] accepts an iterate whose active set still flips
/// (a constraint at its limit with zero force): `16 · √N · ε_mach`, the size a backward-stable
/// Cholesky solve leaves (its backward error is bounded by a small multiple of N·ε_mach, and
/// is observed at ε_mach to √N·ε_mach).
pub fn backward_error_tol(n: usize) -> f64 {
    16.0 * (n.max(1) as f64).sqrt() * f64::EPSILON
}

/// Where [`newton`] starts.
pub enum Start {
    /// From a point (e.g. u0 = K⁻¹q, or the previous Uzawa iterate): the first Newton step is
    /// taken from it with a line search. `solved_with`: the penalized set the point is the exact
    /// solution for, if any (u0 solves the empty set), so that a consistent start stops at once.
    Point {
        /// The starting point.
        u: Vec<f64>,
        /// The set u was solved with (`H_A u = b_A`), if it was.
        solved_with: Option<Vec<bool>>,
    },
    /// From an active set: the first iterate is `H_A⁻¹ b_A` (for a singular K, or a set
    /// carried over).
    Set(Vec<bool>),
}

/// Result of [`newton`].
#[derive(Clone, Debug)]
pub struct Newton {
    /// The minimizer of the penalized energy.
    pub u: Vec<f64>,
    /// ε_c on the penalized set at u (0 elsewhere): the penalties of the final system.
    pub penalties: Vec<f64>,
    /// Stopped at the minimizer (consistent active set, or backward error at rounding level).
    pub converged: bool,
    /// Backward error of u (see [`backward_error`]).
    pub backward_error: f64,
}

/// Minimizes `½uᵀKu − qᵀu + ½Σ ε_c p_c(u; ℓ_c)²` by semismooth Newton with an exact line
/// search (module docs). `eps[c] ≥ 0` is constraint c's penalty while penalized, `limits` the
/// ℓ_c. The line search needs a symmetric K (the energy exists); on an unsymmetric K the steps
/// are undamped and only the iteration cap terminates a cycle (`converged = false`). Counts
/// iterations, solves and factorizations in `ctx.stats`.
pub fn newton(ctx: &mut Context, eps: &[f64], limits: &[f64], start: Start) -> Result<Newton> {
    newton_settled(ctx, eps, limits, start, 0)
}

/// [`newton`] that also stops early, once a full Newton step changes the penalized set in at
/// most `settle` constraints (`converged` is then true only if the set did not change or the
/// backward error is at the rounding level). `settle = 0` is [`newton`]. Used where only an
/// approximate minimizer is wanted (the path-following start of the elimination route).
pub fn newton_settled(
    ctx: &mut Context,
    eps: &[f64],
    limits: &[f64],
    start: Start,
    settle: usize,
) -> Result<Newton> {
    let problem = ctx.problem;
    let m = problem.m();
    let n = problem.n();
    let set_at = |u: &[f64]| -> Vec<bool> {
        problem
            .constraints
            .iter()
            .zip(limits)
            .map(|(con, &l)| penalized_at(con.kind, con.value(u) - l))
            .collect()
    };
    let on_set = |a: &[bool]| -> Vec<f64> {
        eps.iter()
            .zip(a)
            .map(|(&e, &on)| if on { e } else { 0.0 })
            .collect()
    };
    let k_inf = problem.k.inf_norm();
    let tol = backward_error_tol(n);
    // ∇J(u) and the backward error of u: one product with K.
    let measure = |u: &[f64]| {
        let grad = energy_gradient(problem, eps, limits, u);
        let be = backward_error(problem, eps, limits, u, &grad, k_inf);
        (grad, be)
    };
    let finish = |u: Vec<f64>, a: &[bool], converged: bool, backward_error: f64| Newton {
        u,
        penalties: on_set(a),
        converged,
        backward_error,
    };
    let solve = |ctx: &mut Context, a: &[bool]| -> Result<Vec<f64>> {
        let e = on_set(a);
        let u = ctx.solve_penalized_with(&e, limits)?;
        ctx.stats.iterations += 1;
        ctx.stats
            .active_set_sizes
            .push(e.iter().filter(|&&x| x != 0.0).count());
        Ok(u)
    };
    let (mut u, mut solved) = match start {
        Start::Point { u, solved_with } => (u, solved_with),
        Start::Set(a) => {
            let u = solve(ctx, &a)?;
            (u, Some(a))
        }
    };
    let (it0, max_it) = (ctx.stats.iterations, max_iterations(m));
    loop {
        let a = set_at(&u);
        let (grad, be) = measure(&u);
        let changed = solved
            .as_ref()
            .map(|s| s.iter().zip(&a).filter(|(x, y)| x != y).count());
        if changed == Some(0) || be <= tol {
            return Ok(finish(u, &a, true, be));
        }
        if changed.is_some_and(|c| c <= settle) {
            return Ok(finish(u, &a, false, be));
        }
        if ctx.stats.iterations - it0 >= max_it {
            return Ok(finish(u, &a, false, be));
        }
        let u_n = solve(ctx, &a)?;
        let d: Vec<f64> = u_n.iter().zip(&u).map(|(x, y)| x - y).collect();
        // An unsymmetric K has no energy: plain (undamped) steps, capped.
        let step = if ctx.symmetric {
            line_search(problem, eps, limits, &u, &d, &grad)
        } else {
            Some(1.0)
        };
        match step {
            Some(t) if t >= 1.0 => {
                u = u_n;
                solved = Some(a);
            }
            Some(t) => {
                for (ui, di) in u.iter_mut().zip(&d) {
                    *ui += t * di;
                }
                solved = None;
            }
            None => {
                // No descent left along d: u is stationary to rounding. Keep the better of u
                // and the Newton point (exact if its own set is consistent).
                let (_, be_n) = measure(&u_n);
                let consistent = set_at(&u_n) == a;
                let (u_f, be_f, exact) = if consistent || be_n <= be {
                    (u_n, be_n, consistent)
                } else {
                    (u, be, false)
                };
                let a_f = set_at(&u_f);
                return Ok(finish(u_f, &a_f, exact || be_f <= tol, be_f));
            }
        }
    }
}

/// Exact minimizer over t ∈ (0, 1] of `φ(t) = J(u + t d)`; `None` if d is not a descent
/// direction to rounding (φ'(0) ≥ 0 or dᵀKd ≤ 0).
///
/// `φ'(t) = dᵀ∇J(u) + t dᵀKd + Σ_c ε_c h_c (π_c(g_c + t h_c) − π_c(g_c))`, `h = Dᵀd`, is
/// piecewise linear and non-decreasing; walk its breakpoints `t_c = −g_c/h_c` in order.
/// `grad` is [`energy_gradient`] at u, so the only product with K is `Kd`.
pub fn line_search(
    problem: &Problem,
    eps: &[f64],
    limits: &[f64],
    u: &[f64],
    d: &[f64],
    grad: &[f64],
) -> Option<f64> {
    let kd = problem.k.matvec(d);
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let a1 = dot(d, &kd);
    // φ'(0) = dᵀ∇J(u): the penalized constraints' e·h·g terms are in the gradient already.
    let mut alpha = dot(d, grad);
    let mut beta = a1;
    // Breakpoints (t, constraint, entering?) inside (0, 1).
    let mut events: Vec<(f64, f64, f64)> = Vec::new(); // (t, Δα, Δβ) when crossing
    for ((con, &e), &l) in problem.constraints.iter().zip(eps).zip(limits) {
        if e == 0.0 {
            continue;
        }
        let g = con.value(u) - l;
        let h = con.value(d);
        let (da, db) = (e * h * g, e * h * h);
        let on_at_0 = match con.kind {
            ConstraintKind::Bilateral => true,
            ConstraintKind::Upper => g > 0.0 || (g == 0.0 && h > 0.0),
            ConstraintKind::Lower => g < 0.0 || (g == 0.0 && h < 0.0),
        };
        if on_at_0 {
            beta += db;
        }
        if con.kind != ConstraintKind::Bilateral && h != 0.0 {
            let t = -g / h;
            if t > 0.0 && t < 1.0 {
                // Crossing toggles the constraint: leaves if it was on, enters otherwise.
                let s = if on_at_0 { -1.0 } else { 1.0 };
                events.push((t, s * da, s * db));
            }
        }
    }
    let descent = a1 > 0.0 && alpha < 0.0; // false for NaN too
    if !descent {
        return None;
    }
    events.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut t_lo = 0.0;
    for (t_e, da, db) in events {
        // φ' on [t_lo, t_e] is α + β t; its root, if inside, is the answer.
        if alpha + beta * t_e >= 0.0 {
            return Some((-alpha / beta).clamp(t_lo, t_e));
        }
        alpha += da;
        beta += db;
        t_lo = t_e;
    }
    if alpha + beta >= 0.0 {
        Some((-alpha / beta).clamp(t_lo, 1.0))
    } else {
        Some(1.0)
    }
}

/// Path following is used when at least this many unilateral constraints are violated by
/// u0 (obstacle-type problems); below it the plain start is cheaper.
pub const PATH_FOLLOWING_MIN_VIOLATED: usize = 256;

/// Ratio between consecutive penalties of the path.
pub const PATH_RATIO: f64 = 100.0;

/// A stage stops once a full Newton step changes at most this fraction of its penalized set.
pub const PATH_SETTLE: f64 = 0.01;

/// Moreau–Yosida path following (Hintermüller & Kunisch, SIAM J. Optim. 17, 2006): a start
/// point for an active-set solve on an obstacle-type problem. Approximate minimizers of
///
/// `J_t(u) = ½uᵀKu − qᵀu + ½ Σ_c min(t·K_dd(c), caps_c) · p_c(u; ℓ_c)²`
///
/// for `t = t₀, 100·t₀, …` up to `t_end`, each stage started from the previous one by
/// [`newton_settled`] (stopped once a full step changes at most 1 % of the penalized set).
/// Returns the last stage's point, or `None` (use the plain start) when fewer than
/// [`PATH_FOLLOWING_MIN_VIOLATED`] unilateral constraints are violated by u0, K is singular,
/// or `t_end ≤ t₀`.
///
/// Why: started from u0, an active-set iteration on an obstacle problem releases only the
/// constraints next to the contact boundary per iteration (inside a too large contact zone the
/// forces are positive), so it needs about as many iterations as elements the boundary must
/// move (53 at 10⁵ DOFs, 162 at 10⁶ on the membranes). A soft penalty lets the structure lift
/// over a length ≈ √(1/t) elements per step, so each stage moves the boundary far, and the
/// stages refine it geometrically. `t₀ = ρ / mean K_dd` with `ρ = qᵀu0 / ‖u0‖²` (the Rayleigh
/// quotient of u0, ≈ the stiffness of the lowest modes): the first stage is as soft as the
/// structure. The point only decides where the caller's own iteration starts.
pub fn path_following(
    ctx: &mut Context,
    caps: &[f64],
    limits: &[f64],
    t_end: f64,
) -> Result<Option<Vec<f64>>> {
    let problem = ctx.problem;
    let m = problem.m();
    if !ctx.symmetric || m == 0 {
        return Ok(None);
    }
    let u0 = match ctx.u0() {
        Ok(u0) => u0.to_vec(),
        Err(Error::Singular(_)) => return Ok(None),
        Err(e) => return Err(e),
    };
    let violated = problem
        .constraints
        .iter()
        .zip(limits)
        .filter(|(c, &l)| {
            c.kind != ConstraintKind::Bilateral && penalized_at(c.kind, c.value(&u0) - l)
        })
        .count();
    if violated < PATH_FOLLOWING_MIN_VIOLATED {
        return Ok(None);
    }
    let kdd: Vec<f64> = problem
        .constraints
        .iter()
        .map(|c| c.stiffness(&problem.k).abs())
        .collect();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let rho = dot(&problem.q, &u0) / dot(&u0, &u0);
    let t0 = rho / (kdd.iter().sum::<f64>() / m as f64);
    if !(t0 > 0.0 && t0.is_finite() && t0 < t_end) {
        return Ok(None);
    }
    let mut u = u0;
    let mut solved = problem
        .constraints
        .iter()
        .all(|c| c.kind != ConstraintKind::Bilateral)
        .then(|| vec![false; m]);
    let mut t = t0;
    loop {
        let t_stage = t.min(t_end);
        let eps: Vec<f64> = kdd
            .iter()
            .zip(caps)
            .map(|(&k, &cap)| (t_stage * k).min(cap))
            .collect();
        let size = ctx
            .stats
            .active_set_sizes
            .last()
            .copied()
            .unwrap_or(violated);
        let settle = (PATH_SETTLE * size as f64) as usize;
        let start = Start::Point {
            u,
            solved_with: solved.take(),
        };
        u = newton_settled(ctx, &eps, limits, start, settle)?.u;
        if t_stage >= t_end {
            break;
        }
        t *= PATH_RATIO;
    }
    ctx.release_penalized();
    Ok(Some(u))
}

/// Drives a fixed-energy rule (ε_c = `eps[c]` while penalized) to the minimizer of its energy
/// with [`newton`], started from the exact contact set where the context carries one
/// ([`super::Prepared::with_contact_set`]: the sweep passes its lagrange row's), else from u0
/// (by path following on obstacle-type problems), or from every constraint active when K is
/// singular or every constraint is bilateral. The energy is strictly convex, so the start
/// changes the iterations, not the minimizer. On an unsymmetric K there is no energy:
/// [`fixed_point`] is used, and the result says so.
pub fn fixed_energy(mut ctx: Context, method: Method, eps: Vec<f64>) -> Result<Solution> {
    if !ctx.symmetric {
        let label = format!("{} (unsymmetric K: no energy to descend)", method.name());
        return fixed_point_labelled(ctx, method, &label, move |active, ctx| {
            Ok(per_active(ctx.problem, active, |c, _| eps[c]))
        });
    }
    let problem = ctx.problem;
    let limits: Vec<f64> = problem.constraints.iter().map(|c| c.limit).collect();
    let all_bilateral = problem
        .constraints
        .iter()
        .all(|c| c.kind == ConstraintKind::Bilateral);
    let none_bilateral = problem
        .constraints
        .iter()
        .all(|c| c.kind != ConstraintKind::Bilateral);
    let contact_set = ctx.contact_set().filter(|_| !all_bilateral);
    let path = if all_bilateral || contact_set.is_some() {
        None
    } else {
        // Obstacle-type problems: a path-following start up to the target penalties.
        let t_end = problem
            .constraints
            .iter()
            .zip(&eps)
            .map(|(c, &e)| e / c.stiffness(&problem.k).abs())
            .fold(0.0f64, f64::max);
        path_following(&mut ctx, &eps, &limits, t_end)?
    };
    let start = if all_bilateral {
        Start::Set(vec![true; problem.m()])
    } else if let Some(set) = contact_set {
        Start::Set(set)
    } else if let Some(u) = path {
        Start::Point {
            u,
            solved_with: None,
        }
    } else {
        match ctx.u0() {
            Ok(u0) => Start::Point {
                u: u0.to_vec(),
                solved_with: none_bilateral.then(|| vec![false; problem.m()]),
            },
            Err(Error::Singular(_)) => Start::Set(vec![true; problem.m()]),
            Err(e) => return Err(e),
        }
    };
    let r = newton(&mut ctx, &eps, &limits, start)?;
    ctx.stats.converged = r.converged;
    let mut warnings = Vec::new();
    if !r.converged {
        warnings.push(format!(
            "{}: NOT CONVERGED: the Newton iteration reached its cap of {} iterations \
             (backward error {:.2e})",
            method.name(),
            max_iterations(problem.m()),
            r.backward_error
        ));
    }
    Ok(ctx.finish(
        method,
        r.u,
        r.penalties,
        None,
        SystemKind::Penalized,
        warnings,
    ))
}

/// The active-set violation of an iterate solved with `active`: the largest penetration of an
/// unpenalized constraint or separation of a penalized unilateral one (0 iff consistent).
fn set_violation(problem: &Problem, active: &[bool], u: &[f64]) -> f64 {
    problem
        .constraints
        .iter()
        .zip(active)
        .map(|(con, &a)| {
            let g = con.gap(u);
            match (a, con.kind) {
                (_, ConstraintKind::Bilateral) => 0.0,
                (false, k) => k.penetration(g),
                (true, ConstraintKind::Upper) => (-g).max(0.0),
                (true, ConstraintKind::Lower) => g.max(0.0),
            }
        })
        .fold(0.0, f64::max)
}

/// The fixed-point driver for rules whose ε depends on the active set (module docs).
///
/// 1. Start from the constraints violated by u0 (all if every constraint is bilateral or K is
///    singular).
/// 2. `rule(active, ctx)` gives ε for every constraint (0 off the active set); negative values
///    are set to 0 with one warning ([`clip_negative`], counted in `Stats::clipped`); solve.
/// 3. New active set = violated at u; stop when it repeats (converged). On a revisited set or
///    the cap, return the visited iterate with the least active-set violation, not converged.
pub fn fixed_point(
    ctx: Context,
    method: Method,
    rule: impl FnMut(&[bool], &mut Context) -> Result<Vec<f64>>,
) -> Result<Solution> {
    let label = method.rule_label();
    fixed_point_labelled(ctx, method, label, rule)
}

fn fixed_point_labelled(
    mut ctx: Context,
    method: Method,
    label: &str,
    mut rule: impl FnMut(&[bool], &mut Context) -> Result<Vec<f64>>,
) -> Result<Solution> {
    let problem = ctx.problem;
    let m = problem.m();
    let mut active = initial_active_set(&mut ctx)?;
    let mut seen: HashSet<Vec<bool>> = HashSet::new();
    let max_it = max_iterations(m);
    // The best non-final iterate: (violation, u, ε, clip warning, clipped).
    type Iterate = (f64, Vec<f64>, Vec<f64>, Option<String>, usize);
    let mut best: Option<Iterate> = None;
    loop {
        let mut eps = rule(&active, &mut ctx)?;
        let (clip_warning, clipped) = clip_negative(problem, &mut eps, method.rule_label());
        let u = ctx.solve_penalized(&eps)?;
        ctx.stats.iterations += 1;
        ctx.stats
            .active_set_sizes
            .push(eps.iter().filter(|&&e| e != 0.0).count());
        let new_active: Vec<bool> = (0..m).map(|c| violated(problem, c, &u)).collect();
        if new_active == active {
            let mut warnings = Vec::new();
            warnings.extend(clip_warning);
            ctx.stats.clipped = clipped;
            ctx.stats.converged = true;
            return Ok(ctx.finish(method, u, eps, None, SystemKind::Penalized, warnings));
        }
        let v = set_violation(problem, &active, &u);
        if best.as_ref().is_none_or(|b| v < b.0) {
            best = Some((v, u, eps, clip_warning, clipped));
        }
        seen.insert(active.clone());
        let cycled = seen.contains(&new_active);
        if cycled || ctx.stats.iterations >= max_it {
            let (v, u, eps, clip_warning, clipped) = best.expect("set above");
            let why = if cycled {
                "the active set cycled"
            } else {
                "the active set did not settle within the iteration cap"
            };
            let mut warnings = vec![format!(
                "{label}: NOT CONVERGED: {why} after {} iterations (ε depends on the active \
                 set, so there is no energy to descend); terminating rule: the visited iterate \
                 with the least active-set violation is returned ({v:.3e} in the units of u)",
                ctx.stats.iterations
            )];
            warnings.extend(clip_warning);
            ctx.stats.clipped = clipped;
            ctx.stats.converged = false;
            return Ok(ctx.finish(method, u, eps, None, SystemKind::Penalized, warnings));
        }
        active = new_active;
    }
}

/// `f(c, constraint)` for every active constraint c, 0 for the inactive ones: the per-constraint
/// penalty rules (Eq. 17, Eq. 28) evaluated over the active set.
pub fn per_active(
    problem: &Problem,
    active: &[bool],
    mut f: impl FnMut(usize, &crate::system::Constraint) -> f64,
) -> Vec<f64> {
    problem
        .constraints
        .iter()
        .enumerate()
        .map(|(c, con)| if active[c] { f(c, con) } else { 0.0 })
        .collect()
}

/// Sets negative penalties to 0 and returns one warning naming the rule, how many
/// constraints it concerns and (up to three of) which, with the count.
pub fn clip_negative(problem: &Problem, eps: &mut [f64], rule: &str) -> (Option<String>, usize) {
    let negative: Vec<(usize, f64)> = eps
        .iter()
        .enumerate()
        .filter(|(_, &e)| e < 0.0)
        .map(|(c, &e)| (c, e))
        .collect();
    for &(c, _) in &negative {
        eps[c] = 0.0;
    }
    let describe = |&(c, e): &(usize, f64)| {
        format!(
            "constraint {c} ({}): ε = {e:.6e}",
            problem.constraints[c].label()
        )
    };
    let warning = match negative.len() {
        0 => None,
        1 => Some(format!(
            "{rule} gives a negative penalty for {}; set to 0 (unpenalized), so this \
             constraint's penetration is not controlled",
            describe(&negative[0])
        )),
        k => {
            let listed: Vec<String> = negative.iter().take(3).map(describe).collect();
            let more = if k > 3 { ", …" } else { "" };
            Some(format!(
                "{rule} gives a negative penalty for {k} constraints ({}{more}); set to 0 \
                 (unpenalized), so their penetration is not controlled",
                listed.join("; ")
            ))
        }
    };
    (warning, negative.len())
}
