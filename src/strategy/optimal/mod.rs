//! The cond-optimal penalty: the best conditioning any choice of penalties can
//! reach at an allowed penetration δ.
//!
//! # Problem
//!
//! `min cond₂(K + D E Dᵀ)` over `E = diag(ε) ≥ 0` subject to `penetration_c(u(E)) ≤ δ` for
//! every constraint, `u(E) = (K + D E Dᵀ)⁻¹(q + D E û)` (unilateral constraints: only violated
//! ones are penalized, so the system matrix carries the ε of the violated ones only).
//!
//! # Method
//!
//! * **Variables**: `x = ln ε` over the penalized set `A` of a start (every bilateral
//!   constraint, and the unilateral ones the start penalizes); the others keep ε = 0.
//! * **Objective**: `ln cond₂ = ln λ_max − ln λ_min` is nonsmooth where an extreme eigenvalue
//!   is multiple (at the optimum it usually is: the optimiser balances the constrained DOFs'
//!   eigenvalues against each other). It is replaced by the smooth spectral upper bound
//!   `F_t = t⁻¹ ln Σ_k λ_k^t + t⁻¹ ln Σ_k λ_k^(−t)`, with `ln cond₂ ≤ F_t ≤ ln cond₂ + 2 ln n / t`
//!   and the exact gradient `∂F_t/∂ε_c = Σ_k (w⁺_k − w⁻_k) (d_cᵀv_k)² / λ_k` (softmax weights
//!   `w^±` of `±t ln λ`), valid whatever the multiplicities (a spectral function's gradient
//!   is `V f'(Λ) Vᵀ`). t grows to 6·10⁴ (smoothing gap ≤ 2 ln n / t) over the stages.
//!   The sparse route ([`Route`]) sums over windows instead: the [`spectrum::WINDOW`] largest
//!   eigenvalues in the first sum, the [`spectrum::WINDOW`] smallest in the second. Each
//!   truncated sum still contains the extreme eigenvalue, so the truncated `F_t` still lies
//!   between ln cond₂ and the full `F_t` (gap ≤ 2 ln WINDOW / t), and its gradient is the
//!   same formula over the windows; it is smooth except where an eigenvalue crosses a
//!   window's edge, where its weight is `≤ (λ_edge/λ_extreme)^t`.
//! * **Constraints**: the gaps `u = A⁻¹(q + D E û)` and their derivatives
//!   `∂g_i/∂ε_j = −d_iᵀA⁻¹d_j g_j`, which enter the gradient through one adjoint solve
//!   `z = A⁻¹ Σ_i (∂Φ/∂g_i) d_i` (`∂Φ/∂ε_j ∋ −g_j d_jᵀz`), by the route's solver (the
//!   dense eigendecomposition or the sparse Cholesky factor). They enter through a
//!   log barrier `−μ Σ ln(h/δ)` on `h = δ − penetration` (both sides for bilateral ties), plus
//!   `h = s g > 0` for penalized unilateral constraints (they must stay violated, or their ε
//!   would not be in the system). μ falls from 10⁻² to 10⁻⁷ with t. Every iterate is strictly
//!   feasible, so the result is feasible by construction, not to a tolerance.
//! * **Inner solver**: BFGS in x with Armijo backtracking (infeasible trial points are
//!   rejected), steps capped at 2 in ln ε, for t < 2·10³ (`NEWTON_MIN_T`); from there on, when the
//!   penalized set has ≤ 64 constraints (`NEWTON_MAX_D`), Newton with a finite-difference
//!   Hessian of the analytic gradient refreshed every 5th iteration (`model::Newton`). At
//!   large t the smoothed objective is ~t times more curved across an eigenvalue cluster than
//!   along it, and BFGS from the identity crawled: on the 2 211-DOF Hertz mesh it hit the
//!   150-iteration cap in stages 4–6 with ‖∇Φ‖∞ ≈ 10⁻⁴–10⁻³. Newton ends them below 10⁻⁸.
//!   That matters beyond the last digits of cond₂: an unconverged optimum jumps as the lift
//!   moves, and force control then hunts the jump (13–31 solves on the six 2 211-DOF rows
//!   of the a9af79d run whose force jumped; 6 on the one row re-run with Newton stages;
//!   docs/history/performance-log.md).
//! * **Starts**: `condensed` at δ(1 − 10⁻³) (strictly feasible), `paper` at δ, `spring` at δ
//!   when it is feasible, and `scaled` with the smallest factor `2^k f₀` that is strictly
//!   feasible (`f₀` from condensed's largest ε/K_dd). Each optimised point is re-solved by
//!   the exact penalty driver ([`super::fixed_energy`]) and its cond₂ recomputed exactly; the
//!   result is the best **feasible** point among the optimised points and the raw `spring`,
//!   `paper`, `condensed` solutions at δ. So `optimal` is never worse than those rules.
//!   A start whose point at the end of a stage lies within 10⁻⁶ (`MERGE`; ∞-norm in ln ε, same
//!   penalized set) of an earlier start's point there stops: from the same point it would
//!   retrace the same path (on the Hertz meshes measured, every start after the first
//!   merges after stage 1 or 2).
//!
//! # Report ([`OptimalReport`] in [`super::Stats`])
//! * `optimality`: KKT residual at the winning optimised point: `max(‖∇ₓΦ‖∞, μ)`. The barrier
//!   gradient is `Σ_j (μ/h_j)∇h_j`, i.e. multipliers `μ/h_j ≥ 0` with complementarity `μ`, so
//!   `‖∇ₓΦ‖∞` is the stationarity residual of the smoothed problem in ln ε.
//! * `starts_agreeing`: optimised starts whose exact cond₂ is within 10⁻³ (relative) of the best.
//! * `starts_merged`: starts stopped on an earlier start's path (not counted in `starts`).
//! * `cond2_lower_bound`: a certified lower bound of the optimum, `λ_max(K) / λ_min(K_FF)`
//!   (F = the unconstrained DOFs): `λ_max(K + DEDᵀ) ≥ λ_max(K)` since DEDᵀ ⪰ 0, and the
//!   eigenvector of `K_FF` padded with zeros on the constrained DOFs has Rayleigh quotient
//!   `λ_min(K_FF)` for every E, so `λ_min(K + DEDᵀ) ≤ λ_min(K_FF)`. It holds for any penalties,
//!   feasible or not. [`cond2_lower_bound`] computes it from the certified cond₂ routes at any
//!   size (`contact_bench` reports it for every mesh: the floor no penalty rule goes below).
//!
//! # Routes and limits
//! Up to [`DENSE_MAX_N`] DOFs every evaluation takes a dense eigendecomposition of the n×n
//! system; above, the sparse route ([`spectrum`]): a sparse Cholesky factor and Lanczos
//! windows at both ends of the spectrum. n ≤ [`MAX_N`], m ≤ [`MAX_M`]; larger problems are
//! refused with [`Error::Unsupported`]. K must be symmetric positive definite.
//!
//! **Rows that couple DOFs**: `A = K + Σ_c ε_c d_c d_cᵀ`, so every formula above
//! holds with `v_k[d_c]` read as `d_cᵀv_k` and `e_{d_i}` as the row d_i (∂A/∂ε_c = d_c d_cᵀ);
//! the sparse route factors on the pattern of `K + DDᵀ`. The certified floor
//! [`cond2_lower_bound`] needs K on the null space of Dᵀ: a Boolean D's free DOFs (K_FF), and
//! for coupled rows `λ_min(K_Z)` from above by
//! [`crate::conditioning::saddle::null_space_lambda_min`] (NaN in the report where the rows
//! are dependent). Both routes end the
//! same way (exact re-solve, exact cond₂, best feasible candidate), so the route changes the
//! path of the optimiser, never the exactness of the reported numbers; on scenes both take
//! (beams, Hertz and patch scenes of 51–136 DOFs) the optima agree to 5·10⁻⁹ relative
//! (`tests/verification/optimal.rs`). [`solve_by`] picks a route explicitly.
//!
//! # What the optimum looks like
//!
//! On the paper's beam (δ = 0.1, all ties bilateral) the optimum is cond₂ = 219.56 against
//! 222.27 for `condensed` and 513.87 for Eq. 28, with ε = (694.7, 130.0, 688.8) and gaps
//! (0.0128, 0.1000, −0.0061) — the point an outside optimiser reached. The spectrum says
//! why: λ_max = 700.0 is the eigenvalue of the axial tie at node 4 (DOF 6, ∂λ_max/∂ε₂ = 0.18,
//! the other two 0), so ε₂ is kept at the smallest value δ allows (130, gap exactly δ). The
//! two transverse ties feed only the lower end: raising ε₁, ε₃ lifts λ_min (3.149 → 3.188)
//! towards λ_min(K_FF) = 3.193 (the structure with the constrained DOFs clamped, the limit of
//! infinite penalties), and costs nothing in λ_max until their own eigenvalues (≈ K_dd + ε)
//! join the top cluster (690.7, 699.9, 700.0): there the optimum stops. So **the constraints
//! that set λ_max sit at δ; the others are over-stiffened up to λ_max**, because a stiffer
//! support only raises the soft modes. The certified lower bound λ_max(K)/λ_min(K_FF) =
//! 681.9/3.193 = 213.5 is within 2.8 % of the optimum here.
//!
//! `condensed` (smallest penalties, every penalized gap at δ) is close to the optimum when the
//! penalties must be large anyway — small δ, where every penalty ends above K's spectrum and
//! sets λ_max — and far when δ is loose and the structure is soft: then the optimum stiffens
//! the supports to lift λ_min. On the default sweep's beams (8 scenes, δ relative to
//! max_c |u0\[d_c\]|), cond₂(condensed)/cond₂(optimal) has median 1.005 (max 1.19) at δ = 10⁻³,
//! 1.11 (max 1.92) at 10⁻², and 5.1 (max 121) at 10⁻¹; Eq. 28, when feasible, 3.1 / 1.02 / 2.4
//! (max 312 / 31 / 8.1) — sometimes closer than `condensed`, sometimes far worse.
//!
//! # Cost
//!
//! An optimisation takes ≈ 850–2 050 evaluations over its starts on the beams of
//! `optimal_cost` (measured before Newton stages and merging), ≈ 510 on the 990-DOF Hertz
//! mesh, ≈ 880 on the 2 211-DOF one and ≈ 1 600 on the 5 253-DOF one (δ = 10⁻³·a; every
//! start but the first merges).
//! A dense evaluation is one symmetric eigendecomposition (≈ 9n³ flops with vectors); a
//! sparse one is one sparse Cholesky, two solves and two Lanczos windows (≈ 25–75 steps
//! each, fully reorthogonalized): ≈ 4 ms at 990 DOFs and 14 ms at 2 211 on the Hertz
//! plane-strain meshes.
//! `cargo run --release --example optimal_cost` compares the routes on beams;
//! docs/performance.md has its numbers and `contact_bench`'s.

mod model;
pub mod spectrum;

use super::{fixed_energy, Context, Glyph, Knob, Knobs, Look, Method, Solution, Strategy};
use crate::conditioning;
use crate::error::{Error, Result};
use crate::system::{ConstraintKind, Problem, Stiffness};
use model::{descend, Bfgs, Model, Newton};
use serde::Serialize;
pub use spectrum::Route;
use spectrum::Spectrum;

/// `optimal`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "optimal",
    summary: "The cond-optimal penalties for δ",
    knob: Knob::Delta,
    needs_k_inverse: true,
    targets_delta: true,
    force_tol: LOAD_TOL,
    solve: run,
    look: Look {
        label: "optimal (min cond₂ at δ)",
        rule_label: "optimal",
        colour: 9,
        glyph: Glyph::Cross,
    },
    ..Strategy::BASE
};

impl Method {
    /// The cond-optimal penalties for allowed penetration δ (> 0).
    pub const fn optimal(delta: f64) -> Method {
        Method::of(&STRATEGY, Knobs::delta(delta))
    }
}

fn run(ctx: Context, m: &Method) -> Result<Solution> {
    solve(ctx, m.need_delta()?)
}

/// Largest n `optimal` accepts (the sparse route above [`DENSE_MAX_N`]).
pub const MAX_N: usize = 20_000;
/// Largest n of the dense route; larger problems take the sparse one ([`Route::for_size`]).
pub const DENSE_MAX_N: usize = 300;
/// Largest m `optimal` accepts (BFGS keeps a dense inverse Hessian over the penalized set).
pub const MAX_M: usize = 200;

/// Continuation stages (smoothing t, barrier weight μ).
const STAGES: [(f64, f64); 6] = [
    (20.0, 1e-2),
    (100.0, 1e-3),
    (500.0, 1e-4),
    (2.5e3, 1e-5),
    (1.25e4, 1e-6),
    (6e4, 1e-7),
];
/// Iterations (BFGS or Newton) per stage.
const MAX_INNER: usize = 150;
/// Stages from this smoothing t on take Newton steps (`model::Newton`) when the penalized
/// set has at most [`NEWTON_MAX_D`] constraints; the others, and every earlier stage, BFGS.
const NEWTON_MIN_T: f64 = 2e3;
/// Largest penalized set solved by Newton (its finite-difference Hessian costs d evaluations).
const NEWTON_MAX_D: usize = 64;
/// Distance (∞-norm in ln ε) below which a start's point at the end of a stage is the
/// point an earlier start had there: it would retrace that start's path, so it stops.
const MERGE: f64 = 1e-6;
/// Relative cond₂ agreement for `starts_agreeing`.
const AGREE: f64 = 1e-3;
/// Relative force mismatch at which force control accepts an `optimal` solution (its
/// `force_tol`), instead of the 10⁻¹⁰ of the other rules.
///
/// `optimal`'s penalties are an optimiser's output, so its force at a given lift is only as
/// continuous as the optimiser is exact: where the winning start or the penalized set changes
/// with the lift the force jumps, and regula falsi then hunts the jump until the bracket
/// collapses (measured: hertz-plane, 2 211 DOFs, δ = 10⁻²·a: a jump of 1.2·10⁻⁷ found after 15
/// solves where 6 reach 10⁻¹² elsewhere). Each solve is a whole multistart optimisation (131 s
/// at 5 253 DOFs). A load matched to 10⁻⁶ moves the pressures by about as much, over two
/// orders below the smallest penalty error of an `optimal` row measured (2.6·10⁻⁴) and four
/// below the discretization errors; the mismatch reached is reported with every row.
pub const LOAD_TOL: f64 = 1e-6;

/// What `optimal` reports beyond a [`Solution`].
#[derive(Clone, Debug, Default, Serialize, PartialEq)]
pub struct OptimalReport {
    /// Exact cond₂ of the returned system.
    pub cond2: f64,
    /// KKT residual of the winning optimised start (module docs); NaN if a raw rule won.
    pub optimality: f64,
    /// Optimised starts.
    pub starts: usize,
    /// Optimised starts within 10⁻³ of the best cond₂.
    pub starts_agreeing: usize,
    /// Starts stopped because they reached an earlier start's point (not in `starts`).
    pub starts_merged: usize,
    /// Certified lower bound λ_max(K)/λ_min(K_Z) of the optimum (K_Z = K on the null space
    /// of Dᵀ; K_FF for a Boolean D); NaN where it cannot be had (dependent coupled rows).
    pub cond2_lower_bound: f64,
    /// Which candidate won (`optimised from condensed`, `paper`, ...).
    pub winner: String,
    /// Objective evaluations (one eigendecomposition each: dense, or the extreme windows).
    pub evaluations: usize,
    /// The evaluation route (`dense` or `sparse`, [`Route`]).
    pub route: String,
}

/// Refuses problems the dense optimiser cannot afford (and unsymmetric K).
pub fn check_affordable(problem: &Problem) -> Result<()> {
    let (n, m) = (problem.n(), problem.m());
    if n > MAX_N || m > MAX_M {
        return Err(Error::unsupported(
            "optimal",
            format!("n ≤ {MAX_N} and m ≤ {MAX_M} (got n = {n}, m = {m})"),
        ));
    }
    if !problem.k.is_symmetric() {
        return Err(Error::unsupported(
            "optimal",
            "a symmetric K (cond₂ through symmetric eigenvalues)",
        ));
    }
    Ok(())
}

/// Certified lower bound `λ_max(K) / λ_min(K_FF)` of cond₂(K + DEDᵀ) over all E ≥ 0 (module
/// docs), from the proven brackets of the certified cond₂ routes ([`conditioning::cond2`]
/// on K and on K_FF, any size, sparse or dense): the lower end of λ_max(K)'s bracket over
/// the upper end of λ_min(K_FF)'s, rounded down. 1 when every DOF is constrained; +∞ when
/// K_FF is not positive definite (every K + DEDᵀ is then singular). K symmetric positive
/// definite. Rows that couple DOFs: `λ_max(K)/λ_min(K_Z)` with K_Z = K on the null space of
/// Dᵀ, λ_min(K_Z) from above ([`crate::conditioning::saddle::null_space_lambda_min`]; errors
/// on dependent rows).
pub fn cond2_lower_bound(problem: &Problem) -> Result<f64> {
    if !problem.is_selection() {
        return coupled_lower_bound(problem);
    }
    let n = problem.n();
    let mut index = vec![usize::MAX; n];
    for d in problem.single_dofs("the cond₂ lower bound over all E")? {
        index[d] = 0;
    }
    let mut free = 0usize;
    for i in index.iter_mut() {
        if *i == usize::MAX {
            *i = free;
            free += 1;
        } else {
            *i = usize::MAX;
        }
    }
    if free == 0 {
        return Ok(1.0);
    }
    let mut t = Vec::new();
    problem.k.for_each_entry(|i, j, v| {
        if index[i] != usize::MAX && index[j] != usize::MAX {
            t.push((index[i], index[j], v));
        }
    });
    let kff = Stiffness::from_triplets(free, &t)?.in_preferred_storage();
    let top = conditioning::cond2(&problem.k)?;
    let bottom = match conditioning::cond2(&kff) {
        Ok(r) => r,
        Err(Error::Singular(_)) => return Ok(f64::INFINITY),
        Err(e) => return Err(e),
    };
    // The proven ends where the route proves them, else its estimates.
    let lmax = top
        .certificate
        .filter(|_| top.bounds_proven)
        .map_or(top.sigma_max, |c| c.lambda_max_lo);
    let lmin = bottom
        .certificate
        .filter(|_| bottom.bounds_proven)
        .map_or(bottom.sigma_min, |c| c.lambda_min_hi);
    Ok(if lmin > 0.0 {
        (lmax / lmin * (1.0 - 4.0 * f64::EPSILON)).max(1.0)
    } else {
        f64::INFINITY
    })
}

/// [`cond2_lower_bound`] for rows that couple DOFs: `λ_max(K) / λ_min(K_Z)`, K_Z = K on the
/// null space of Dᵀ (the module docs' argument with any `z`, `Dᵀz = 0`, in place of the padded
/// eigenvector of K_FF), λ_min(K_Z) from above by
/// [`conditioning::saddle::null_space_lambda_min`]. 1 when the rows leave no null space
/// (m ≥ N).
fn coupled_lower_bound(problem: &Problem) -> Result<f64> {
    if problem.m() >= problem.n() {
        return Ok(1.0);
    }
    let rows: Vec<conditioning::saddle::Row> = problem
        .constraints
        .iter()
        .map(|c| c.terms.clone())
        .collect();
    let bottom = conditioning::saddle::null_space_lambda_min(&problem.k.as_sparse(), &rows)?;
    let top = conditioning::cond2(&problem.k)?;
    let lmax = top
        .certificate
        .filter(|_| top.bounds_proven)
        .map_or(top.sigma_max, |c| c.lambda_max_lo);
    Ok((lmax / bottom.upper * (1.0 - 4.0 * f64::EPSILON)).max(1.0))
}

/// A feasible candidate: its solution and exact cond₂.
struct Candidate {
    label: String,
    sol: Solution,
    cond2: f64,
    optimality: f64,
    optimised: bool,
}

/// Re-solves with given penalties by the exact driver and measures cond₂ exactly.
fn verify(p: &Problem, delta: f64, eps: Vec<f64>) -> Result<(Solution, f64)> {
    let sol = fixed_energy(Context::new(p), Method::optimal(delta), eps)?;
    let c = conditioning::cond2(&super::penalized_matrix(p, &sol.penalties))?.cond2;
    Ok((sol, c))
}

fn feasible(sol: &Solution, delta: f64) -> bool {
    sol.max_penetration <= delta && sol.u.iter().all(|v| v.is_finite())
}

/// Where a start's continuation ended.
enum Outcome {
    /// Not strictly feasible: not optimised.
    Infeasible,
    /// Reached an earlier start's point at the end of a stage ([`MERGE`]).
    Merged,
    /// Optimised penalties (all m) and the KKT residual.
    Optimised(Vec<f64>, f64),
}

/// The penalized set and the point after each stage, of every start run so far.
type Trail = Vec<(Vec<usize>, Vec<Vec<f64>>)>;

/// Runs the continuation from a start's penalties (BFGS, Newton at large t; module docs).
fn optimise_from(
    p: &Problem,
    spectrum: &Spectrum,
    delta: f64,
    start: &[f64],
    trail: &mut Trail,
    evals: &mut usize,
) -> Result<Outcome> {
    let floor = 1e-8;
    let set: Vec<usize> = (0..p.m())
        .filter(|&c| start[c] > 0.0 || p.constraints[c].kind == ConstraintKind::Bilateral)
        .collect();
    if set.is_empty() {
        return Ok(Outcome::Infeasible);
    }
    let model = Model {
        p,
        spectrum,
        set,
        delta,
    };
    let mut x: Vec<f64> = model
        .set
        .iter()
        .map(|&c| {
            let kdd = p.constraints[c]
                .stiffness(&p.k)
                .abs()
                .max(f64::MIN_POSITIVE);
            start[c].max(floor * kdd).ln()
        })
        .collect();
    *evals += 1;
    if model.eval(&x, STAGES[0].0, STAGES[0].1)?.is_none() {
        return Ok(Outcome::Infeasible);
    }
    let mut opt = f64::NAN;
    let (d, mut path) = (model.set.len(), Vec::with_capacity(STAGES.len()));
    for (stage, (t, mu)) in STAGES.into_iter().enumerate() {
        let (xn, gn) = if t >= NEWTON_MIN_T && d <= NEWTON_MAX_D {
            descend(&model, x, (t, mu), &mut Newton::new(d), evals)?
        } else {
            descend(&model, x, (t, mu), &mut Bfgs::new(d), evals)?
        };
        x = xn;
        opt = gn.max(mu);
        let retraces = trail.iter().any(|(set, points)| {
            *set == model.set
                && points
                    .get(stage)
                    .is_some_and(|q| q.iter().zip(&x).all(|(a, b)| (a - b).abs() <= MERGE))
        });
        if retraces {
            return Ok(Outcome::Merged);
        }
        path.push(x.clone());
    }
    trail.push((model.set.clone(), path));
    let mut eps = vec![0.0; p.m()];
    for (&c, v) in model.set.iter().zip(&x) {
        eps[c] = v.exp();
    }
    Ok(Outcome::Optimised(eps, opt))
}

/// Strictly feasible `scaled` start: ε_c = 2^k f₀ K_dd for the smallest k that works.
fn scaled_start(p: &Problem, delta: f64, f0: f64) -> Result<Option<Vec<f64>>> {
    let mut f = f0.max(1e-6);
    for _ in 0..30 {
        let eps: Vec<f64> = p
            .constraints
            .iter()
            .map(|c| f * c.stiffness(&p.k).abs())
            .collect();
        let s = fixed_energy(Context::new(p), Method::scaled(f), eps)?;
        if s.max_penetration < delta {
            return Ok(Some(s.penalties));
        }
        f *= 2.0;
    }
    Ok(None)
}

/// Solves for the cond-optimal penalties at allowed penetration δ (module docs), by the
/// route [`Route::for_size`] picks.
pub fn solve(ctx: Context, delta: f64) -> Result<Solution> {
    let route = Route::for_size(ctx.problem.n());
    solve_by(ctx, delta, route)
}

/// [`solve`] by a given route (the sparse one needs n ≥ [`spectrum::SPARSE_MIN_N`]).
pub fn solve_by(ctx: Context, delta: f64, route: Route) -> Result<Solution> {
    let p = ctx.problem;
    check_affordable(p)?;
    // The floor over all E: for coupled rows NaN where it cannot be had (dependent rows, K
    // not positive definite on the null space of Dᵀ).
    let lower = if p.is_selection() {
        cond2_lower_bound(p)?
    } else {
        cond2_lower_bound(p).unwrap_or(f64::NAN)
    };
    let spectrum = Spectrum::new(p, route)?;
    let mut cands: Vec<Candidate> = Vec::new();
    let mut starts: Vec<(String, Vec<f64>)> = Vec::new();
    for m in [
        Method::spring(delta),
        Method::paper(delta),
        Method::condensed(delta),
    ] {
        let sol = super::solve(p, m)?;
        if feasible(&sol, delta) {
            let c = conditioning::cond2(&super::penalized_matrix(p, &sol.penalties))?.cond2;
            if !m.is(&super::condensed::STRATEGY) {
                starts.push((m.name().into(), sol.penalties.clone()));
            }
            cands.push(Candidate {
                label: m.name().into(),
                sol,
                cond2: c,
                optimality: f64::NAN,
                optimised: false,
            });
        }
    }
    let inner = super::solve(p, Method::condensed(delta * (1.0 - 1e-3)))?;
    let f0 = p
        .constraints
        .iter()
        .zip(&inner.penalties)
        .map(|(c, e)| e / c.stiffness(&p.k).abs().max(f64::MIN_POSITIVE))
        .fold(0.0f64, f64::max);
    starts.insert(0, (super::condensed::STRATEGY.name.into(), inner.penalties));
    if let Some(e) = scaled_start(p, delta, f0)? {
        starts.push((super::scaled::STRATEGY.name.into(), e));
    }
    let (mut evals, mut n_opt, mut merged) = (0, 0, 0);
    let mut trail = Trail::new();
    for (label, start) in &starts {
        let (eps, opt) = match optimise_from(p, &spectrum, delta, start, &mut trail, &mut evals)? {
            Outcome::Infeasible => continue,
            Outcome::Merged => {
                merged += 1;
                continue;
            }
            Outcome::Optimised(eps, opt) => (eps, opt),
        };
        n_opt += 1;
        let (sol, c) = verify(p, delta, eps)?;
        if feasible(&sol, delta) && c.is_finite() {
            cands.push(Candidate {
                label: format!("optimised from {label}"),
                sol,
                cond2: c,
                optimality: opt,
                optimised: true,
            });
        }
    }
    let best_opt = cands
        .iter()
        .filter(|c| c.optimised)
        .map(|c| c.cond2)
        .fold(f64::INFINITY, f64::min);
    let agreeing = cands
        .iter()
        .filter(|c| c.optimised && c.cond2 <= best_opt * (1.0 + AGREE))
        .count();
    let best = cands
        .into_iter()
        .min_by(|a, b| a.cond2.total_cmp(&b.cond2))
        .ok_or_else(|| {
            Error::Numerical("optimal: no feasible candidate (not even condensed)".into())
        })?;
    let mut warnings = best.sol.warnings.clone();
    if !best.optimised {
        warnings.push(format!(
            "optimal: no optimised start beat the raw {} penalties (cond₂ {:.6e})",
            best.label, best.cond2
        ));
    }
    if agreeing < n_opt {
        warnings.push(format!(
            "optimal: {agreeing} of {n_opt} optimised starts agree within {AGREE:e} of the \
             best cond₂ (local optima)"
        ));
    }
    let mut sol = best.sol;
    sol.method = Method::optimal(delta);
    sol.warnings = warnings;
    sol.stats.converged = true;
    sol.stats.optimal = Some(OptimalReport {
        cond2: best.cond2,
        optimality: best.optimality,
        starts: n_opt,
        starts_agreeing: agreeing,
        starts_merged: merged,
        cond2_lower_bound: lower,
        winner: best.label,
        evaluations: evals,
        route: route.name().into(),
    });
    Ok(sol)
}
