//! A rule's knob matched to an accuracy: the knob value at which the rule's penalty error
//! equals the mesh's discretization error, or its largest penetration equals δ.
//!
//! The search runs on t = log₁₀(knob relative to its scale): the measure falls as ε or f grows
//! and rises with δ or the augmented tolerance. From a start it steps a decade at a time until
//! the measure crosses the target, then closes in by regula falsi (Illinois variant) on
//! `ln(measure/target)`, bisecting where a measure is 0 (no penetration) and after two steps
//! that did not halve the bracket. ε and f stay within
//! 10⁻⁶…10¹² of their scales, δ and tolerances within 10⁻¹²…10⁻¹ of the length scale. It
//! stops when the measure is within `tol` (relative) of the target, or after
//! [`MAX_EVALUATIONS`] solves (or at the end of the range), or when the bracket is narrower than
//! [`KNOB_RESOLUTION`] decades — the measure then jumps across the target (an Uzawa count or an
//! active set that changes there; a measure that varies as knob^p with p ≤ 10 is within 5 % at
//! both ends of such a bracket) — and reports the closest solve as unmatched.

use super::cases::{Level, Solved};
use crate::error::Result;
use crate::strategy::{Knob, Knobs, Method, Strategy};
use serde::{Deserialize, Serialize};

/// Largest number of solves of one search.
pub const MAX_EVALUATIONS: usize = 30;

/// The narrowest bracket (decades of the knob) the search closes in on: 0.002, a 0.5 % change of
/// the knob.
pub const KNOB_RESOLUTION: f64 = 0.002;

/// Which accuracy a row is matched at.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Accuracy {
    /// Lagrange: exact contact, no knob.
    Exact,
    /// Penalty error = the mesh's discretization error.
    Discretization,
    /// Largest penetration = δ.
    Penetration,
}

impl Accuracy {
    /// Its name in rows.
    pub fn name(self) -> &'static str {
        match self {
            Accuracy::Exact => "exact",
            Accuracy::Discretization => "discretization",
            Accuracy::Penetration => "penetration",
        }
    }
}

/// The method of `strategy` at knob `rel` (relative to the level's scales) and the knob's
/// name and absolute value: ε = rel·k_scale, f = rel, δ = rel·scale; `augmented` at the
/// constraints' mean K_dd (`aug_eps`) with tol = rel·scale.
pub fn method_at(
    strategy: &'static Strategy,
    level: &Level,
    aug_eps: f64,
    rel: f64,
) -> Result<(Method, &'static str, f64)> {
    let mut k = Knobs::NONE;
    let (name, value) = match strategy.knob {
        Knob::Eps => {
            k.eps = Some(rel * level.k_scale);
            ("eps", rel * level.k_scale)
        }
        Knob::Factor => {
            k.factor = Some(rel);
            ("factor", rel)
        }
        Knob::Delta => {
            k.delta = Some(rel * level.scale);
            ("delta", rel * level.scale)
        }
        Knob::EpsTol => {
            k.eps = Some(aug_eps);
            k.tol = Some(rel * level.scale);
            ("tol", rel * level.scale)
        }
        Knob::None => ("", f64::NAN),
    };
    Ok((Method::new(strategy, k)?, name, value))
}

/// The outcome of a search.
pub struct Found {
    /// Knob name.
    pub knob: &'static str,
    /// Knob value relative to its scale.
    pub rel: f64,
    /// Absolute knob value.
    pub value: f64,
    /// The measure there.
    pub achieved: f64,
    /// Within `tol` of the target.
    pub matched: bool,
    /// Solves of the search.
    pub evaluations: usize,
    /// The closest solve.
    pub solved: Solved,
    /// The error of the last solve that failed, if one did (the search stops there).
    pub failure: Option<String>,
    /// The search reached the end of the knob's range without crossing the target.
    pub range_end: bool,
    /// d ln(measure)/d log₁₀(knob) between the two finite evaluations closest to the target
    /// (None with fewer than two): the next level's first step ([`Start`]).
    pub slope: Option<f64>,
}

/// Where a search starts: the knob (relative to its scale) and, where known, the slope
/// d ln(measure)/d log₁₀(knob) there — the previous mesh level's match, whose knob and slope
/// change little from one level to the next.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Start {
    /// The first knob value, relative to its scale.
    pub rel: f64,
    /// The slope; with it the second solve is a Newton step from the first (at most
    /// [`MAX_NEWTON_STEP`] decades) instead of a decade's step.
    pub slope: Option<f64>,
}

/// The largest first step (decades) taken from a [`Start`]'s slope.
pub const MAX_NEWTON_STEP: f64 = 2.0;

/// The measure of `accuracy` on a solve.
pub fn measure(accuracy: Accuracy, s: &Solved) -> f64 {
    match accuracy {
        Accuracy::Penetration => s.sol.max_penetration,
        _ => s.err_penalty,
    }
}

/// Searches the knob of `strategy` on `level` for `measure = target` from `start` (module
/// doc). Errors only where no solve at all succeeded.
pub fn find(
    strategy: &'static Strategy,
    level: &Level,
    aug_eps: f64,
    accuracy: Accuracy,
    target: f64,
    start: Start,
    tol: f64,
) -> Result<Found> {
    // dir: +1 where the measure grows with the knob (δ, tolerances), −1 where it falls.
    let dir = match strategy.knob {
        Knob::Eps | Knob::Factor => -1.0,
        _ => 1.0,
    };
    let ok = (1.0 + tol).ln();
    let mut best: Option<Found> = None;
    let evaluations = std::cell::Cell::new(0usize);
    let mut last_err = None;
    // Every finite (t, f): the slope near the root for the next level.
    let mut seen: Vec<(f64, f64)> = Vec::new();
    // f(t) = ln(measure/target): −∞ where the measure is 0, NaN where the solve failed.
    let mut eval = |t: f64, best: &mut Option<Found>| -> f64 {
        evaluations.set(evaluations.get() + 1);
        let rel = 10f64.powf(t);
        let solved = method_at(strategy, level, aug_eps, rel)
            .and_then(|(m, knob, value)| level.solve(m).map(|s| (knob, value, s)));
        match solved {
            Ok((knob, value, s)) => {
                let m = measure(accuracy, &s);
                let f = if m > 0.0 {
                    (m / target).ln()
                } else {
                    f64::NEG_INFINITY
                };
                let closer = best.as_ref().is_none_or(|b| {
                    let fb = (b.achieved / target).ln();
                    // Closer, or the best so far is not comparable (NaN).
                    use std::cmp::Ordering::{Equal, Less};
                    !matches!(fb.abs().partial_cmp(&f.abs()), Some(Less | Equal))
                });
                if closer {
                    *best = Some(Found {
                        knob,
                        rel,
                        value,
                        achieved: m,
                        // A solve that did not converge (a cycling active set) is no match.
                        matched: f.abs() <= ok && s.sol.stats.converged,
                        evaluations: 0,
                        solved: s,
                        failure: None,
                        range_end: false,
                        slope: None,
                    });
                }
                if f.is_finite() {
                    seen.push((t, f));
                }
                f
            }
            Err(e) => {
                last_err = Some(e);
                f64::NAN
            }
        }
    };
    // The knob's range: ε and f within 10^±(6…12) of their scales; δ and the tolerance at
    // most a tenth of the length scale (a larger δ is no longer a small penetration).
    let (lo, hi) = match strategy.knob {
        Knob::Eps | Knob::Factor => (-6.0, 12.0),
        _ => (-12.0, -1.0),
    };
    let a = start.rel.log10().clamp(lo, hi);
    let fa = eval(a, &mut best);
    let ((a, fa), bracket, range_end) = bracket_from(
        (a, fa),
        start.slope,
        (dir, ok),
        (lo, hi),
        &evaluations,
        |t| eval(t, &mut best),
    );
    if let Some(b) = bracket {
        close_in((a, fa), b, |c| {
            let go_on =
                evaluations.get() < MAX_EVALUATIONS && best.as_ref().is_some_and(|x| !x.matched);
            go_on.then(|| eval(c, &mut best))
        });
    }
    match best {
        Some(mut f) => {
            f.evaluations = evaluations.get();
            f.failure = last_err.map(|e| e.to_string());
            f.range_end = range_end;
            f.slope = slope_near_root(&mut seen);
            Ok(f)
        }
        None => Err(last_err.unwrap_or_else(|| crate::Error::Numerical("no solve".into()))),
    }
}

/// The search's first phase (module doc) from `(a, f(a))`: a Newton step where `slope` is
/// known and of the right sign (the measure falls with ε and f, grows with δ and the
/// tolerances: `dir`), then a decade at a time towards the target until f changes sign, the
/// knob's range `[lo, hi]` ends, a solve fails or half of [`MAX_EVALUATIONS`] are spent.
/// Returns the last point on the start's side, the bracket's other end (if f changed sign)
/// and whether the range ended.
#[allow(clippy::type_complexity)]
fn bracket_from(
    (mut a, mut fa): (f64, f64),
    slope: Option<f64>,
    (dir, ok): (f64, f64),
    (lo, hi): (f64, f64),
    evaluations: &std::cell::Cell<usize>,
    mut eval: impl FnMut(f64) -> f64,
) -> ((f64, f64), Option<(f64, f64)>, bool) {
    let newton = slope
        .filter(|p| p.is_finite() && p * dir > 0.0)
        .filter(|_| fa.is_finite() && fa.abs() > ok);
    if let Some(p) = newton {
        let t = (a - (fa / p).clamp(-MAX_NEWTON_STEP, MAX_NEWTON_STEP)).clamp(lo, hi);
        if t != a {
            // A failed solve (NaN): go on from the start by decades.
            let f = eval(t);
            if f.is_finite() && (f > 0.0) != (fa > 0.0) {
                return ((a, fa), Some((t, f)), false);
            } else if f.is_finite() {
                (a, fa) = (t, f);
            }
        }
    }
    while fa.is_finite() && fa.abs() > ok || fa == f64::NEG_INFINITY {
        if evaluations.get() >= MAX_EVALUATIONS / 2 {
            break;
        }
        let step = if fa > 0.0 { -dir } else { dir };
        let t = (a + step).clamp(lo, hi);
        if t == a {
            return ((a, fa), None, true);
        }
        let f = eval(t);
        if f.is_nan() {
            break;
        }
        if (f > 0.0) != (fa > 0.0) {
            return ((a, fa), Some((t, f)), false);
        }
        (a, fa) = (t, f);
    }
    ((a, fa), None, false)
}

/// The secant slope between the two evaluations closest to the root (smallest |f|) at
/// distinct t.
fn slope_near_root(seen: &mut [(f64, f64)]) -> Option<f64> {
    seen.sort_by(|x, y| x.1.abs().total_cmp(&y.1.abs()));
    let (t0, f0) = *seen.first()?;
    let &(t1, f1) = seen
        .iter()
        .find(|(t, _)| (t - t0).abs() >= KNOB_RESOLUTION)?;
    Some((f1 - f0) / (t1 - t0)).filter(|p| p.is_finite())
}

/// Closes in on the sign change of f in the bracket `(a, f(a))`, `(b, f(b))` (f of opposite
/// signs) by regula falsi (Illinois variant), bisecting after two steps that did not halve the
/// bracket (a measure that jumps across the target stalls regula falsi), until the bracket is
/// narrower than [`KNOB_RESOLUTION`], `eval` says stop (`None`) or returns NaN (a failed solve).
fn close_in(
    (mut a, mut fa): (f64, f64),
    (mut b, mut fb): (f64, f64),
    mut eval: impl FnMut(f64) -> Option<f64>,
) {
    let mut stalls = 0;
    while (b - a).abs() >= KNOB_RESOLUTION {
        let width = (b - a).abs();
        let c = if fa.is_finite() && fb.is_finite() && stalls < 2 {
            (a * fb - b * fa) / (fb - fa)
        } else {
            stalls = 0;
            0.5 * (a + b)
        };
        let Some(fc) = eval(c) else { break };
        if fc.is_nan() {
            break;
        }
        if (fc > 0.0) != (fb > 0.0) {
            (a, fa) = (b, fb);
        } else {
            fa *= 0.5;
        }
        (b, fb) = (c, fc);
        if (b - a).abs() > 0.5 * width {
            stalls += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A measure that jumps across the target (an Uzawa count changing at t = 0.3) ends in a
    /// bracket of KNOB_RESOLUTION around the jump within a bounded number of solves; a smooth
    /// one gets close to its root long before.
    #[test]
    fn close_in_stops_at_a_jump_and_finds_a_smooth_root() {
        let mut ts = Vec::new();
        close_in((0.0, -1.0), (1.0, 1.0), |t| {
            ts.push(t);
            Some(if t < 0.3 { -1.0 } else { 1.0 })
        });
        assert!(ts.len() <= 20, "{} evaluations", ts.len());
        let (lo, hi) = ts.iter().fold((0.0f64, 1.0f64), |(lo, hi), &t| {
            if t < 0.3 {
                (lo.max(t), hi)
            } else {
                (lo, hi.min(t))
            }
        });
        assert!(
            hi - lo < KNOB_RESOLUTION && lo < 0.3 && hi >= 0.3,
            "[{lo}, {hi}]"
        );

        let mut last = f64::NAN;
        let mut n = 0;
        close_in((0.0, -0.7), (2.0, 1.3), |t| {
            n += 1;
            last = t;
            let f = t - 0.7;
            (f.abs() > 1e-9).then_some(f)
        });
        assert!((last - 0.7).abs() < 1e-6 && n < 12, "{last} after {n}");
    }
}
