//! The bound-constrained QP shared by the δ-targeting routes: its state per constraint, the
//! dense solver in the force variable (for `condensed`'s m×m route), the starting state and
//! the primal–dual active-set update with its anti-cycling fallback (also used by the sparse
//! elimination route, [`super::eliminated`]).
//!
//! `min ½ (g − g0)ᵀ S⁻¹ (g − g0)` s.t. `lo ≤ g ≤ hi`, S SPD: strictly convex, one solution;
//! at-bound constraints carry a force `r = S⁻¹(g0 − g)` of the bound's sign, free ones none.

use crate::error::{Error, Result};
use faer::linalg::solvers::Solve;
use faer::{Mat, MatRef, Side};
use std::collections::HashSet;

/// Where a constraint sits in the box QP.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BoundState {
    /// Inside its bounds, force 0.
    Free,
    /// At the lower bound (`g = lo`).
    Lo,
    /// At the upper bound (`g = hi`).
    Hi,
}

/// Result of a primal–dual active-set iteration ([`pdas`]): the final iterate and how it
/// got there.
#[derive(Clone, Debug)]
pub struct Pdas<T> {
    /// Gaps g.
    pub g: Vec<f64>,
    /// Forces r (at-bound constraints; 0 for the free ones).
    pub r: Vec<f64>,
    /// Final state per constraint.
    pub state: Vec<BoundState>,
    /// Iterations.
    pub iterations: usize,
    /// Active-set size per iteration.
    pub sizes: Vec<usize>,
    /// Whether the one-change fallback was needed.
    pub fallback: bool,
    /// What the caller's step returned with the final iterate (e.g. u).
    pub last: T,
}

/// Result of [`box_qp`]: r = S⁻¹(g0 − g).
pub type BoxQp = Pdas<()>;

/// What a [`pdas`] iteration runs on: the bounds, the violation tolerance, whether pinned
/// constraints (`lo = hi`) stay put, the iteration cap and the route's name for its error.
pub struct PdasSpec<'a> {
    /// Lower and upper bounds per constraint.
    pub bounds: (&'a [f64], &'a [f64]),
    /// Gap tolerance of a violation.
    pub tol: f64,
    /// Pinned constraints never change.
    pub keep_pinned: bool,
    /// Iteration cap.
    pub max_it: usize,
    /// The route, named in the error when the cap is reached.
    pub what: &'a str,
}

/// The primal–dual active-set loop shared by [`box_qp`] and the elimination route
/// ([`super::eliminated`]): from `state`, `step(state)` solves for the gaps, the forces and
/// what the caller keeps; its [`violations`] (weights `w`) give the next state
/// ([`pdas_update`]) until there are none. Errors when `spec.max_it` is reached.
pub fn pdas<T>(
    mut state: Vec<BoundState>,
    spec: PdasSpec<'_>,
    w: impl Fn(usize) -> f64,
    mut step: impl FnMut(&[BoundState]) -> Result<(Vec<f64>, Vec<f64>, T)>,
) -> Result<Pdas<T>> {
    let mut seen: HashSet<Vec<BoundState>> = HashSet::new();
    let mut fallback = false;
    let mut sizes = Vec::new();
    for it in 1..=spec.max_it {
        sizes.push(state.iter().filter(|&&s| s != BoundState::Free).count());
        let (g, r, last) = step(&state)?;
        let changes = violations(&state, &r, &g, spec.bounds, spec.tol, spec.keep_pinned, &w);
        if changes.is_empty() {
            return Ok(Pdas {
                g,
                r,
                state,
                iterations: it,
                sizes,
                fallback,
                last,
            });
        }
        state = pdas_update(&state, &changes, &mut seen, &mut fallback);
    }
    Err(Error::Numerical(format!(
        "{}: active set did not converge in {} iterations",
        spec.what, spec.max_it
    )))
}

/// Violation tolerance of a bound: the rounding level of the gaps g0 and the finite bounds,
/// 64·ε_mach·max(m, 1)·max|·| (m = number of constraints).
pub(super) fn violation_tol(g0: &[f64], lo: &[f64], hi: &[f64]) -> f64 {
    let scale = g0
        .iter()
        .chain(lo.iter().filter(|v| v.is_finite()))
        .chain(hi.iter().filter(|v| v.is_finite()))
        .fold(0.0f64, |a, v| a.max(v.abs()));
    64.0 * f64::EPSILON * (g0.len() as f64).max(1.0) * scale
}

/// Solves `min ½(g − g0)ᵀS⁻¹(g − g0)` s.t. `lo ≤ g ≤ hi` in the force variable
/// `r = S⁻¹(g0 − g)` (only S is needed, never S⁻¹): at-bound rows solve `S_AA r_A = g0_A − g_A`,
/// free rows have `r = 0` and `g_F = g0_F − S_FA r_A`. `start`: the initial state (default:
/// the bounds violated by g0).
pub fn box_qp(
    s: MatRef<'_, f64>,
    g0: &[f64],
    lo: &[f64],
    hi: &[f64],
    start: Option<Vec<BoundState>>,
) -> Result<BoxQp> {
    let m = g0.len();
    let tol = violation_tol(g0, lo, hi);
    let state = start_state(g0, lo, hi, start);
    let spec = PdasSpec {
        bounds: (lo, hi),
        tol,
        keep_pinned: false,
        max_it: 10 * m + 50,
        what: "condensed",
    };
    // Whether some S_AA was not positive definite to working precision (its Cholesky failed
    // and LU solved it): with dependent rows S is singular, and a loop that then fails to
    // converge says so rather than only that it did not converge.
    let not_pd = std::cell::Cell::new(false);
    let out = pdas(
        state,
        spec,
        |c| s[(c, c)],
        |state| {
            let act: Vec<usize> = (0..m).filter(|&c| state[c] != BoundState::Free).collect();
            let target = |c: usize| match state[c] {
                BoundState::Hi => hi[c],
                BoundState::Lo => lo[c],
                BoundState::Free => f64::NAN,
            };
            // r_A = S_AA⁻¹ (g0_A − g*_A).
            let mut r = vec![0.0; m];
            if !act.is_empty() {
                let saa = Mat::from_fn(act.len(), act.len(), |i, j| s[(act[i], act[j])]);
                let mut rhs = Mat::from_fn(act.len(), 1, |i, _| g0[act[i]] - target(act[i]));
                match saa.llt(Side::Lower) {
                    Ok(l) => l.solve_in_place(rhs.as_mut()),
                    Err(_) => {
                        not_pd.set(true);
                        saa.partial_piv_lu().solve_in_place(rhs.as_mut())
                    }
                }
                for (i, &c) in act.iter().enumerate() {
                    r[c] = rhs[(i, 0)];
                }
            }
            if r.iter().any(|v| !v.is_finite()) {
                return Err(Error::Numerical(
                    "condensed: S_AA is singular (constraints on linearly dependent DOFs?)".into(),
                ));
            }
            // g = g0 − S r (exact at bounds up to rounding; recomputed for all).
            let g: Vec<f64> = (0..m)
                .map(|i| g0[i] - act.iter().map(|&c| s[(i, c)] * r[c]).sum::<f64>())
                .collect();
            Ok((g, r, ()))
        },
    );
    match out {
        Err(Error::Numerical(msg)) if not_pd.get() => Err(Error::Numerical(format!(
            "{msg}; S_AA was not positive definite to working precision on the way (constraint \
             rows linearly dependent?)"
        ))),
        other => other,
    }
}

/// The primal–dual violations of a state, as `(weight, constraint, new state)`: a constraint
/// at a bound whose force has the wrong sign goes free (weight `|r_c|·w(c)`, `w` converting
/// force to gap units), a free one outside its bounds by more than `tol` goes to that bound
/// (weight: the excess). With `keep_pinned`, pinned constraints (`lo = hi`) never change.
pub fn violations(
    state: &[BoundState],
    r: &[f64],
    g: &[f64],
    (lo, hi): (&[f64], &[f64]),
    tol: f64,
    keep_pinned: bool,
    w: impl Fn(usize) -> f64,
) -> Vec<(f64, usize, BoundState)> {
    let mut changes = Vec::new();
    for c in 0..state.len() {
        match state[c] {
            _ if keep_pinned && lo[c] == hi[c] => {}
            BoundState::Hi if r[c] < 0.0 => changes.push((-r[c] * w(c), c, BoundState::Free)),
            BoundState::Lo if r[c] > 0.0 => changes.push((r[c] * w(c), c, BoundState::Free)),
            BoundState::Free if g[c] > hi[c] + tol => {
                changes.push((g[c] - hi[c], c, BoundState::Hi))
            }
            BoundState::Free if g[c] < lo[c] - tol => {
                changes.push((lo[c] - g[c], c, BoundState::Lo))
            }
            _ => {}
        }
    }
    changes
}

/// The starting state of the box problem: `start` if given (a warm start), else the bounds
/// violated by g0; a pinned constraint (`lo = hi`) starts at its bound.
pub fn start_state(
    g0: &[f64],
    lo: &[f64],
    hi: &[f64],
    start: Option<Vec<BoundState>>,
) -> Vec<BoundState> {
    match start {
        Some(s) if s.len() == g0.len() => s,
        _ => (0..g0.len())
            .map(|c| {
                if lo[c] == hi[c] || g0[c] > hi[c] {
                    BoundState::Hi
                } else if g0[c] < lo[c] {
                    BoundState::Lo
                } else {
                    BoundState::Free
                }
            })
            .collect(),
    }
}

/// One primal–dual active-set update: every change at once (`(weight, constraint, new
/// state)`), or — once the full update has revisited a state (cycling) — from then on only the
/// change of largest weight. `seen` collects the visited states.
pub fn pdas_update(
    state: &[BoundState],
    changes: &[(f64, usize, BoundState)],
    seen: &mut HashSet<Vec<BoundState>>,
    fallback: &mut bool,
) -> Vec<BoundState> {
    seen.insert(state.to_vec());
    let mut next = state.to_vec();
    for &(_, c, st) in changes {
        next[c] = st;
    }
    if *fallback || seen.contains(&next) {
        *fallback = true;
        if let Some(&(_, c, st)) = changes.iter().max_by(|a, b| a.0.total_cmp(&b.0)) {
            next = state.to_vec();
            next[c] = st;
        }
    }
    next
}
