//! The IPC log-barrier (Li et al., "Incremental Potential Contact", SIGGRAPH 2020; the
//! adaptive stiffness of ipc-toolkit's `src/ipc/barrier/adaptive_stiffness.cpp`):
//!
//! `min Π(u) = ½uᵀKu − qᵀu + κ Σ_c b(d_c(u))`, `b(d) = −(d − d̂)² ln(d / d̂)` for 0 < d < d̂,
//! 0 for d ≥ d̂, with the distance `d_c = û_c − d_cᵀu` (upper) or `d_cᵀu − û_c` (lower) and
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
//! **Stiffness κ** ([`KappaRule`]). Both adaptive rules start from gradient balance,
//! `κ = −∇Bᵀ∇E / ‖∇B‖²` (E the elastic energy, B = Σ b), clamped to [κ_min, 100 κ_min], and
//! differ in κ_min and in when κ doubles:
//! - `ipc` (the default where the problem knows its contact surface,
//!   [`crate::system::Surface`]): ipc-toolkit's `initial_barrier_stiffness` and
//!   `update_barrier_stiffness` (`src/ipc/barrier/adaptive_stiffness.cpp`). κ_min makes the
//!   barrier's stiffness at the distance d₀ = 1e-8·bbox (bbox the bounding-box diagonal; d̂/√2
//!   if that is not below d̂) equal to a reference stiffness: `κ_min b''(d₀) = k̄`. After every
//!   accepted Newton step κ doubles (up to 100 κ_min) when the smallest distance is below
//!   d_ε = 1e-9·bbox on this and the previous iterate and fell. ipc-toolkit works with squared
//!   distances (d₀² = (1e-8·bbox)², d_ε² = (1e-9·bbox)²) and a mass: its reference is
//!   `min_barrier_stiffness_scale · m̄` = 1e11·m̄, the inertia of its incremental potential. A
//!   static problem has no mass; its stand-in is the structure's own stiffness k̄, the
//!   geometric mean of K\[d_c, d_c\] ([`crate::system::Problem::mean_constraint_stiffness`]).
//!   (For SI solids on centimetre meshes 1e11·m̄ is 1e-4…1 times k̄: rubber ρ = 1e3, E = 1e7 gives
//!   ≈ 1, steel ≈ 4e-4.) The distances being those of the scene's geometry, κ and the gap it
//!   leaves do not depend on how the mesh was scaled.
//! - `balanced` (the former rule, and the default without a surface: a bare K, q, D
//!   has no length but d̂): `κ_min b''(d̂/2) = k̄`, the barrier as stiff as the structure
//!   halfway into its band; after each converged Newton solve κ doubles (warm-started
//!   re-solve, at most up to 100 κ_min) while the smallest distance is below 1e-2·d̂ and fell
//!   since the previous solve — ipc-toolkit's update applied between static solves with a
//!   threshold relative to d̂.
//! - `fixed`: κ as given, never updated (sensitivity studies).
//!
//! Every solve reports its κ ([`KappaReport`]: rule, initial, final, increases, the clamp).
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

use super::{Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy, SystemKind};
use crate::error::{Error, Result};
use crate::system::{ConstraintKind, Problem};

/// `barrier`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "barrier",
    summary: "IPC log-barrier with adaptive stiffness κ (activation distance δ = d̂)",
    knob: Knob::Delta,
    targets_delta: true,
    bilateral: false,
    solve: run,
    look: Look {
        label: "barrier (IPC, d̂ = δ)",
        rule_label: "barrier",
        colour: 10,
        glyph: Glyph::Star,
    },
    ..Strategy::BASE
};

impl Method {
    /// The IPC log-barrier with activation distance d̂ (> 0).
    pub const fn barrier(dhat: f64) -> Method {
        Method::of(&STRATEGY, Knobs::delta(dhat))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve_with(ctx, m.need_delta()?, m.knobs().kappa)
}

/// How the barrier chooses its stiffness κ (module doc).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum KappaRule {
    /// `ipc` where the problem carries its [`crate::system::Surface`], else `balanced`.
    #[default]
    Auto,
    /// ipc-toolkit's κ_min from the bounding box and its in-Newton update.
    Ipc,
    /// κ_min balanced at d̂/2 and doubling between solves (the former rule).
    Balanced,
    /// This κ (> 0), never updated.
    Fixed(f64),
}

impl KappaRule {
    /// The rule if its value is valid (`Fixed` needs a finite κ > 0).
    pub fn validated(self) -> Result<KappaRule> {
        match self {
            KappaRule::Fixed(k) => Error::positive("barrier: fixed κ", k).map(KappaRule::Fixed),
            r => Ok(r),
        }
    }

    /// The rule `p` gets: `Auto` is `Ipc` where `p` carries its surface, else `Balanced`.
    pub fn resolved(self, p: &Problem) -> KappaRule {
        match self {
            KappaRule::Auto if p.surface.is_some() => KappaRule::Ipc,
            KappaRule::Auto => KappaRule::Balanced,
            r => r,
        }
    }

    /// Its name in rows (`ipc`, `balanced`, `fixed`; `auto` before it is resolved).
    pub fn name(self) -> &'static str {
        match self {
            KappaRule::Auto => "auto",
            KappaRule::Ipc => "ipc",
            KappaRule::Balanced => "balanced",
            KappaRule::Fixed(_) => "fixed",
        }
    }
}

/// ipc-toolkit's d₀ over the bounding-box diagonal (`initial_barrier_stiffness`).
pub const IPC_D0: f64 = 1e-8;
/// ipc-toolkit's `dhat_epsilon_scale` (`update_barrier_stiffness`): κ doubles below this
/// distance over the bounding-box diagonal.
pub const IPC_D_EPS: f64 = 1e-9;

/// The clamp [κ_min, κ_max] of `rule` ([`KappaRule::resolved`] on `p`) for activation
/// distance `dhat` on `p`, and the distance below which the `ipc` rule doubles κ inside Newton.
pub fn kappa_bounds(p: &Problem, dhat: f64, rule: KappaRule) -> Result<(f64, f64, Option<f64>)> {
    let kbar = p.mean_constraint_stiffness();
    let rule = rule.resolved(p);
    let (min, below) = match rule {
        KappaRule::Ipc => {
            let Some(surface) = &p.surface else {
                return Err(Error::unsupported(
                    "barrier: the ipc κ rule",
                    "the problem's contact surface (its bounding box); use the balanced rule \
                     for a bare K, q, D",
                ));
            };
            let bbox = surface.bbox_diagonal;
            let mut d0 = IPC_D0 * bbox;
            if d0 >= dhat {
                d0 = dhat / std::f64::consts::SQRT_2;
            }
            (kbar / barrier(d0, dhat).2, Some(IPC_D_EPS * bbox))
        }
        KappaRule::Fixed(k) => (k, None),
        KappaRule::Balanced | KappaRule::Auto => (kbar / barrier(0.5 * dhat, dhat).2, None),
    };
    let max = if matches!(rule, KappaRule::Fixed(_)) {
        min
    } else {
        100.0 * min
    };
    Ok((min, max, below))
}

/// The barrier stiffness κ of a solve: the hidden second knob, recorded in every row.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct KappaReport {
    /// The rule that chose it (resolved: `ipc`, `balanced` or `fixed`).
    pub rule: KappaRule,
    /// κ of the first Newton solve (gradient balance, clamped to [κ_min, κ_max]).
    pub initial: f64,
    /// κ of the returned solve.
    pub last: f64,
    /// Times κ was doubled (`balanced`: each a warm-started Newton solve; `ipc`: inside
    /// Newton).
    pub increases: usize,
    /// The clamp's lower end κ_min (`fixed`: κ).
    pub min: f64,
    /// The clamp's upper end κ_max = 100 κ_min (`fixed`: κ).
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
        .map(|c| side(c.kind) * (c.gap(u)))
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

/// ipc-toolkit's `update_barrier_stiffness` test: the smallest distance is below `eps` on
/// the previous and the current iterate and fell.
pub fn ipc_doubles(prev_min: f64, now_min: f64, eps: f64) -> bool {
    prev_min < eps && now_min < eps && now_min < prev_min
}

/// κ during a solve, and the `ipc` rule's in-Newton update.
struct Kappa {
    now: f64,
    max: f64,
    increases: usize,
    /// `ipc`: double κ when the smallest distance is below this on two consecutive iterates
    /// and fell.
    below: Option<f64>,
}

fn newton(ctx: &mut Context, mut u: Vec<f64>, k: &mut Kappa, dhat: f64) -> Result<NewtonRun> {
    let p = ctx.problem;
    let mut prev_min = min_distance(p, &u);
    let scale_u = |u: &[f64]| u.iter().fold(dhat, |a, v| a.max(v.abs()));
    let mut ku = p.k.matvec(&u);
    for _ in 0..MAX_NEWTON {
        ctx.stats.iterations += 1;
        let kappa = k.now;
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
                lim[c] = con.value(&u) - grad_b[c] / h[c];
            }
        }
        let u_new = ctx.solve_penalized_with(&h, &lim)?;
        let step: Vec<f64> = u_new.iter().zip(&u).map(|(a, b)| a - b).collect();
        // ∇Π = K u − q + D ∇B.
        let mut g: Vec<f64> = ku.iter().zip(&p.q).map(|(a, b)| a - b).collect();
        for (c, con) in p.constraints.iter().enumerate() {
            con.scatter(&mut g, grad_b[c]);
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
            let dd = side(con.kind) * con.value(&step);
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
        // ipc-toolkit's update (`ipc` rule): the barrier struggles to push apart.
        let now_min = min_distance(p, &u);
        if let Some(eps) = k.below {
            if ipc_doubles(prev_min, now_min, eps) && k.now < k.max {
                k.now = (2.0 * k.now).min(k.max);
                k.increases += 1;
            }
        }
        prev_min = now_min;
    }
    Ok(NewtonRun {
        u,
        converged: false,
    })
}

/// Solves with the IPC log-barrier of activation distance `dhat` and the default κ rule
/// ([`KappaRule::Auto`]; module doc).
pub fn solve(ctx: Context, dhat: f64) -> Result<Solution> {
    solve_with(ctx, dhat, KappaRule::Auto)
}

/// Solves with the IPC log-barrier of activation distance `dhat`, κ chosen by `rule`.
pub fn solve_with(mut ctx: Context, dhat: f64, rule: KappaRule) -> Result<Solution> {
    let p = ctx.problem;
    if let Some(c) = p
        .constraints
        .iter()
        .position(|c| c.kind == ConstraintKind::Bilateral)
    {
        return Err(Error::unsupported(
            "barrier",
            format!(
                "unilateral constraints only, but constraint {c} is bilateral (a tie); use a \
                 penalty rule or lagrange"
            ),
        ));
    }
    let rule = rule.validated()?.resolved(p);
    let u = feasible_start(p, ctx.u0()?.to_vec(), dhat)?;
    let (kappa_min, kappa_max, below) = kappa_bounds(p, dhat, rule)?;
    // Gradient balance at the start.
    let d = distances(p, &u);
    let ku = p.k.matvec(&u);
    let ge: Vec<f64> = ku.iter().zip(&p.q).map(|(a, b)| a - b).collect();
    let mut gb = vec![0.0; p.n()];
    for (c, con) in p.constraints.iter().enumerate() {
        con.scatter(&mut gb, side(con.kind) * barrier(d[c], dhat).1);
    }
    let nb: f64 = gb.iter().map(|v| v * v).sum();
    let balanced = if nb > 0.0 {
        -gb.iter().zip(&ge).map(|(a, b)| a * b).sum::<f64>() / nb
    } else {
        kappa_min
    };
    let initial = balanced.clamp(kappa_min, kappa_max);
    let mut k = Kappa {
        now: initial,
        max: kappa_max,
        increases: 0,
        below,
    };
    let mut run = newton(&mut ctx, u, &mut k, dhat)?;
    if rule == KappaRule::Balanced {
        let mut min_d = min_distance(p, &run.u);
        while min_d < 1e-2 * dhat && k.now < kappa_max {
            k.now = (2.0 * k.now).min(kappa_max);
            k.increases += 1;
            let next = newton(&mut ctx, run.u.clone(), &mut k, dhat)?;
            let d_next = min_distance(p, &next.u);
            run = next;
            if d_next >= min_d {
                break;
            }
            min_d = d_next;
        }
    }
    let kappa = k.now;
    ctx.stats.converged = run.converged;
    ctx.stats.barrier = Some(KappaReport {
        rule,
        initial,
        last: kappa,
        increases: k.increases,
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

/// Most sweeps of [`feasible_start`]'s cyclic projections at the first target margin (later
/// margins get a tenth of it).
const START_SWEEPS: usize = 1000;

/// Most halvings of [`feasible_start`]'s target margin.
const START_HALVINGS: usize = 60;

/// A strictly feasible start: `u0` with every constraint closer than a target margin τ (or
/// violated) moved to τ along its row (`set_value`), τ = d̂/2 first. Rows that share DOFs can
/// undo each other's move, so the sweep repeats (cyclic projections onto the half-spaces,
/// which converge where their intersection has an interior) until every row lies above τ/2,
/// at most [`START_SWEEPS`] times; where they do not get there — an `upper` and a `lower` row
/// whose band is narrower than d̂, where no point is d̂/4 from both — τ halves (up to
/// [`START_HALVINGS`] times), so any band with an interior is found. The barrier only needs
/// every gap in (0, d̂). Single-DOF rows on distinct DOFs are done in the first sweep at τ =
/// d̂/2, as before.
fn feasible_start(p: &Problem, mut u: Vec<f64>, dhat: f64) -> Result<Vec<f64>> {
    let mut target = 0.5 * dhat;
    for halving in 0..=START_HALVINGS {
        let sweeps = if halving == 0 {
            START_SWEEPS
        } else {
            START_SWEEPS / 10
        };
        for _ in 0..sweeps {
            for con in &p.constraints {
                if side(con.kind) * con.gap(&u) < target {
                    con.set_value(&mut u, con.limit + side(con.kind) * target);
                }
            }
            let worst = p
                .constraints
                .iter()
                .map(|con| side(con.kind) * con.gap(&u))
                .fold(f64::INFINITY, f64::min);
            if worst > 0.5 * target {
                return Ok(u);
            }
        }
        target *= 0.5;
    }
    Err(Error::Numerical(format!(
        "barrier: no strictly feasible start found by cyclic projections onto the constraint \
         rows with margins from d̂/2 = {:e} down to {target:e} (the rows may admit no point \
         strictly inside every one)",
        0.5 * dhat
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{Constraint, Stiffness, Surface};

    /// Two springs in series, the free end pushed by `q` onto an upper limit at 0: with or
    /// without a surface of bounding-box diagonal `bbox`.
    fn chain(q: f64, bbox: Option<f64>) -> Problem {
        let k =
            Stiffness::from_triplets(2, &[(0, 0, 2e3), (0, 1, -1e3), (1, 0, -1e3), (1, 1, 1e3)])
                .unwrap();
        let p = Problem::new(
            k,
            vec![0.0, q],
            vec![Constraint::on_dof(1, 0.0, ConstraintKind::Upper)],
        )
        .unwrap();
        match bbox {
            Some(b) => p
                .with_surface(Surface {
                    weights: vec![1.0],
                    bbox_diagonal: b,
                })
                .unwrap(),
            None => p,
        }
    }

    /// κ_min of each rule is what the module doc says: `ipc` balances the barrier's stiffness
    /// at d₀ = 1e-8·bbox against k̄ (d̂/√2 when d₀ is not below d̂), `balanced` at d̂/2; κ_max
    /// is 100 κ_min; `ipc` needs the surface.
    #[test]
    fn kappa_bounds_follow_the_rules() {
        let dhat = 1e-3;
        let p = chain(1.0, Some(2.0));
        let kbar = p.mean_constraint_stiffness();
        let (lo, hi, below) = kappa_bounds(&p, dhat, KappaRule::Ipc).unwrap();
        assert!((lo * barrier(2e-8, dhat).2 / kbar - 1.0).abs() <= 1e-14);
        assert_eq!(hi, 100.0 * lo);
        assert_eq!(below, Some(2e-9));
        let (lo, _, below) = kappa_bounds(&p, dhat, KappaRule::Balanced).unwrap();
        assert!((lo * barrier(0.5 * dhat, dhat).2 / kbar - 1.0).abs() <= 1e-14);
        assert_eq!(below, None);
        let huge = chain(1.0, Some(1e6));
        let (lo, _, _) = kappa_bounds(&huge, dhat, KappaRule::Ipc).unwrap();
        let d0 = dhat / std::f64::consts::SQRT_2;
        assert!((lo * barrier(d0, dhat).2 / kbar - 1.0).abs() <= 1e-14);
        let (lo, _, _) = kappa_bounds(&p, dhat, KappaRule::Auto).unwrap();
        assert_eq!(
            lo,
            kappa_bounds(&p, dhat, KappaRule::Ipc).unwrap().0,
            "Auto is ipc here"
        );
        let err = kappa_bounds(&chain(1.0, None), dhat, KappaRule::Ipc).unwrap_err();
        assert!(err.to_string().contains("contact surface"), "{err}");
        assert!(KappaRule::Fixed(f64::NAN).validated().is_err());
        assert!(KappaRule::Fixed(-1.0).validated().is_err());
    }

    /// `Auto` is `ipc` with a surface and `balanced` without; a fixed κ stays put; pressed
    /// hard, the `ipc` rule's gradient balance is clamped at κ_max, where no update can raise
    /// it, and the solve neither fails nor penetrates. The update's test is ipc-toolkit's.
    #[test]
    fn kappa_rules_resolve_and_ipc_clamps() {
        let solve_rule = |p: &Problem, rule| {
            let m = Method::new(
                &STRATEGY,
                Knobs {
                    kappa: rule,
                    ..Knobs::delta(1e-3)
                },
            )
            .unwrap();
            crate::strategy::solve(p, m).unwrap()
        };
        let report = |s: &Solution| s.stats.barrier.unwrap();
        let with = chain(1.0, Some(2.0));
        let without = chain(1.0, None);
        assert_eq!(
            report(&solve_rule(&with, KappaRule::Auto)).rule,
            KappaRule::Ipc
        );
        assert_eq!(
            report(&solve_rule(&without, KappaRule::Auto)).rule,
            KappaRule::Balanced
        );
        let fixed = report(&solve_rule(&with, KappaRule::Fixed(3.0)));
        assert_eq!((fixed.initial, fixed.last, fixed.increases), (3.0, 3.0, 0));
        // κ_max = 100 κ_min ≈ 4e-5 here: under a push q = 10 the balance distance κ d̂²/q is
        // below d_ε = 2e-9 for every κ in the clamp.
        let pressed = chain(10.0, Some(2.0));
        let s = solve_rule(&pressed, KappaRule::Ipc);
        let k = report(&s);
        assert_eq!((k.initial, k.last, k.increases), (k.max, k.max, 0), "{k:?}");
        assert!(s.stats.converged);
        assert!(
            s.u[1] < 0.0 && -s.u[1] < 2e-9,
            "gap below d_ε: u = {}",
            s.u[1]
        );
        assert!(ipc_doubles(1.5e-9, 1e-9, 2e-9));
        assert!(
            !ipc_doubles(3e-9, 1e-9, 2e-9),
            "the previous iterate was above d_ε"
        );
        assert!(!ipc_doubles(1e-9, 1.5e-9, 2e-9), "the distance rose");
        assert!(!ipc_doubles(1e-9, 1e-9, 2e-9), "the distance did not fall");
    }

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
