//! Force control of an indentation scene ([`crate::model::elasticity::indentation`]): the
//! lift w of the block's base at which a rule's own solution carries a total load P,
//!
//! `F(w) = Σ_c ω_c p_c(u(w)) = P` (times 2 or 2π: [`Indentation::total_force`]),
//!
//! so that rules are compared at equal load, as a user loads a model. `contact_bench` solves
//! every rule this way; the `hertz` and `patch` scene families of the `generate` module place
//! their lift where the Lagrange solution carries the drawn load.

use super::{Method, Solution};
use crate::error::{Error, Result};
use crate::model::elasticity::Indentation;

/// A scene solved by one rule under force control: the scene at the lift found, its solution
/// and the number of solves the search took.
pub struct Loaded {
    /// The scene at the lift that carries the load.
    pub scene: Indentation,
    /// The rule's solution on it.
    pub sol: Solution,
    /// Solves of the search.
    pub solves: usize,
    /// (force − load)/load of the returned solution.
    pub mismatch: f64,
}

/// The lift w at which `method`'s solution carries `load`, to `rel_tol` relative: the force
/// grows monotonically with w (piecewise affinely for Lagrange and a fixed-ε penalty,
/// affinely while the contact set stays) and is 0 at w = 0 for the rules that act only on
/// contact (the indenter touches the top at x = 0); a barrier acts before contact, so where
/// the force at w = 0 exceeds the load the bracket extends below 0. Regula falsi (Illinois
/// variant) in a doubling bracket from `guess` converges in a few solves.
///
/// `scene(w)` builds the scene at lift w; `name` names it in errors.
pub fn solve_at_load(
    name: &str,
    scene: impl Fn(f64) -> Result<Indentation>,
    method: Method,
    load: f64,
    guess: f64,
    rel_tol: f64,
) -> Result<Loaded> {
    for (what, v) in [("load", load), ("first lift", guess)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::out_of_range(
                format!("{name}: force control's {what}"),
                format!("{v:e}"),
                "a finite number > 0",
            ));
        }
    }
    let force = |w: f64| -> Result<(f64, Indentation, Solution)> {
        let scene = scene(w)?;
        let sol = super::solve(&scene.problem, method)?;
        let f = scene.total_force(&sol.u);
        Ok((f - load, scene, sol))
    };
    let fail = |what: &str, w: f64, r: f64| {
        Error::Numerical(format!(
            "{name} {}: force control {what} (lift {w:e}, force mismatch {:e})",
            method.name(),
            r / load
        ))
    };
    let (mut lo, mut r_lo) = (0.0, -load);
    let mut hi = guess;
    let mut solves = 1;
    let (mut r_hi, mut scene, mut sol) = force(hi)?;
    let mut flat = 0;
    while r_hi < 0.0 {
        // The force of a rule that loads the contact grows at least in proportion to the lift
        // beyond its contact onset; three doublings without growth mean it puts no load on it.
        if solves >= MAX_FORCE_SOLVES || flat >= 3 {
            let what = format!(
                "found no lift that carries the load (the force stays at {:.3e}·P; {} of {} \
                 penalties clipped to 0)",
                1.0 + r_hi / load,
                sol.penalties.iter().filter(|e| **e == 0.0).count(),
                sol.penalties.len()
            );
            return Err(fail(&what, hi, r_hi));
        }
        (lo, r_lo) = (hi, r_hi);
        hi *= 2.0;
        (r_hi, scene, sol) = force(hi)?;
        solves += 1;
        flat = if r_hi - r_lo <= 1e-6 * load {
            flat + 1
        } else {
            0
        };
    }
    // A rule that pushes before contact (the barrier) can carry more than the load at w = 0:
    // then the lower end moves below 0 until the force falls short of the load.
    if lo == 0.0 {
        let (r0, _, _) = force(0.0)?;
        solves += 1;
        r_lo = r0;
        let mut step = guess.abs().max(f64::MIN_POSITIVE);
        while r_lo >= 0.0 {
            if solves >= MAX_FORCE_SOLVES {
                return Err(fail(
                    "found no lift that carries less than the load",
                    lo,
                    r_lo,
                ));
            }
            lo = -step;
            step *= 2.0;
            (r_lo, _, _) = force(lo)?;
            solves += 1;
        }
    }
    // (scene, sol) is always the latest evaluation, `last` its mismatch.
    let mut last = r_hi;
    let mut side = 0i8;
    while last.abs() > rel_tol * load {
        // A rule whose force jumps with the lift (an optimizer's best-of-starts choice) can
        // leave a gap no lift closes: the bracket collapses, and the mismatch is reported.
        if hi - lo <= 1e-13 * hi {
            break;
        }
        if solves >= MAX_FORCE_SOLVES {
            return Err(fail("did not converge", hi, last));
        }
        let w = (lo * r_hi - hi * r_lo) / (r_hi - r_lo);
        let (r, sc, so) = force(w)?;
        solves += 1;
        (scene, sol, last) = (sc, so, r);
        if r >= 0.0 {
            (hi, r_hi) = (w, r);
            if side == 1 {
                r_lo /= 2.0;
            }
            side = 1;
        } else {
            (lo, r_lo) = (w, r);
            if side == -1 {
                r_hi /= 2.0;
            }
            side = -1;
        }
    }
    Ok(Loaded {
        scene,
        sol,
        solves,
        mismatch: last / load,
    })
}

/// Solves force control may take (a rule that loads the contact converges in ≤ 10 on the
/// default suite).
pub const MAX_FORCE_SOLVES: usize = 40;

/// Relative mismatch of the total force that force control accepts for a rule whose solution
/// is exact for its penalties (each strategy declares its own: `Strategy::force_tol`).
pub const FORCE_TOL: f64 = 1e-10;
