//! The cond-optimal penalty (issue 12): the best conditioning any choice of penalties can
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
//!   and the exact gradient `∂F_t/∂ε_c = Σ_k (w⁺_k − w⁻_k) v_k[d_c]² / λ_k` (softmax weights
//!   `w^±` of `±t ln λ`), valid whatever the multiplicities (a spectral function's gradient
//!   is `V f'(Λ) Vᵀ`). t grows to 6·10⁴ (smoothing gap ≤ 2 ln n / t) over the stages.
//! * **Constraints**: the gaps and their derivatives come from the same eigendecomposition:
//!   `u = V Λ⁻¹ Vᵀ (q + D E û)`, `∂g_i/∂ε_j = −(A⁻¹)_{d_i d_j} g_j`. They enter through a
//!   log barrier `−μ Σ ln(h/δ)` on `h = δ − penetration` (both sides for bilateral ties), plus
//!   `h = s g > 0` for penalized unilateral constraints (they must stay violated, or their ε
//!   would not be in the system). μ falls from 10⁻² to 10⁻⁷ with t. Every iterate is strictly
//!   feasible, so the result is feasible by construction, not to a tolerance.
//! * **Inner solver**: BFGS in x with Armijo backtracking (infeasible trial points are
//!   rejected), steps capped at 2 in ln ε.
//! * **Starts**: `condensed` at δ(1 − 10⁻³) (strictly feasible), `paper` at δ, `spring` at δ
//!   when it is feasible, and `scaled` with the smallest factor `2^k f₀` that is strictly
//!   feasible (`f₀` from condensed's largest ε/K_dd). Each optimised point is re-solved by
//!   the exact penalty driver ([`super::fixed_energy`]) and its cond₂ recomputed exactly; the
//!   result is the best **feasible** point among the optimised points and the raw `spring`,
//!   `paper`, `condensed` solutions at δ. So `optimal` is never worse than those rules.
//!
//! # Report ([`OptimalReport`] in [`super::Stats`])
//! * `optimality`: KKT residual at the winning optimised point: `max(‖∇ₓΦ‖∞, μ)`. The barrier
//!   gradient is `Σ_j (μ/h_j)∇h_j`, i.e. multipliers `μ/h_j ≥ 0` with complementarity `μ`, so
//!   `‖∇ₓΦ‖∞` is the stationarity residual of the smoothed problem in ln ε.
//! * `starts_agreeing`: optimised starts whose exact cond₂ is within 10⁻³ (relative) of the best.
//! * `cond2_lower_bound`: a certified lower bound of the optimum, `λ_max(K) / λ_min(K_FF)`
//!   (F = the unconstrained DOFs): `λ_max(K + DEDᵀ) ≥ λ_max(K)` since DEDᵀ ⪰ 0, and the
//!   eigenvector of `K_FF` padded with zeros on the constrained DOFs has Rayleigh quotient
//!   `λ_min(K_FF)` for every E, so `λ_min(K + DEDᵀ) ≤ λ_min(K_FF)`. It holds for any penalties,
//!   feasible or not. [`cond2_lower_bound`] computes it from the certified cond₂ routes at any
//!   size (`contact_bench` reports it for every mesh: the floor no penalty rule goes below).
//!
//! # Limits
//! Dense eigendecompositions of the n×n system at every evaluation: n ≤ [`MAX_N`],
//! m ≤ [`MAX_M`]; larger problems are refused with [`Error::Input`]. K must be symmetric
//! positive definite.
//!
//! # What the optimum looks like
//!
//! On the paper's beam (δ = 0.1, all ties bilateral) the optimum is cond₂ = 219.56 against
//! 222.27 for `condensed` and 513.87 for Eq. 28, with ε = (694.7, 130.0, 688.8) and gaps
//! (0.0128, 0.1000, −0.0061) — the outside optimiser's point of issue 12. The spectrum says
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
//! Each evaluation is one dense symmetric eigendecomposition (≈ 9n³ flops with vectors) plus
//! O(n m²); an optimisation takes ≈ 1 000–1 800 evaluations over its starts, independent of n
//! and weakly of m: the cost grows about like n³ (`cargo run --release --example
//! optimal_cost` measures it; its numbers are in docs/performance.md), so n = 1000 takes
//! minutes.

use super::{fixed_energy, Context, Glyph, Knob, Knobs, Method, Solution, Strategy};
use crate::conditioning;
use crate::error::{Error, Result};
use crate::system::{ConstraintKind, Problem, Stiffness};
use faer::{Mat, Side};
use serde::Serialize;

/// `optimal`: everything the registry knows about this strategy ([`super::registry`]).
pub static STRATEGY: Strategy = Strategy {
    name: "optimal",
    summary: "The cond-optimal penalties for δ",
    label: "optimal (min cond₂ at δ)",
    rule_label: "optimal",
    knob: Knob::Delta,
    colour: 9,
    glyph: Glyph::Cross,
    needs_k_inverse: true,
    targets_delta: true,
    bilateral: true,
    solve: run,
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

/// Largest n the dense optimiser accepts.
pub const MAX_N: usize = 1000;
/// Largest m the dense optimiser accepts.
pub const MAX_M: usize = 100;

/// Continuation stages (smoothing t, barrier weight μ).
const STAGES: [(f64, f64); 6] = [
    (20.0, 1e-2),
    (100.0, 1e-3),
    (500.0, 1e-4),
    (2.5e3, 1e-5),
    (1.25e4, 1e-6),
    (6e4, 1e-7),
];
/// BFGS iterations per stage.
const MAX_INNER: usize = 150;
/// Relative cond₂ agreement for `starts_agreeing`.
const AGREE: f64 = 1e-3;

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
    /// Certified lower bound λ_max(K)/λ_min(K_FF) of the optimum.
    pub cond2_lower_bound: f64,
    /// Which candidate won (`optimised from condensed`, `paper`, ...).
    pub winner: String,
    /// Objective evaluations (one dense eigendecomposition each).
    pub evaluations: usize,
}

/// Refuses problems the dense optimiser cannot afford (and unsymmetric K).
pub fn check_affordable(problem: &Problem) -> Result<()> {
    let (n, m) = (problem.n(), problem.m());
    if n > MAX_N || m > MAX_M {
        return Err(Error::input(format!(
            "optimal: dense optimisation needs n ≤ {MAX_N} and m ≤ {MAX_M} (got n = {n}, m = {m})"
        )));
    }
    if !problem.k.is_symmetric() {
        return Err(Error::input(
            "optimal: K must be symmetric (cond₂ through symmetric eigenvalues)",
        ));
    }
    Ok(())
}

/// Certified lower bound `λ_max(K) / λ_min(K_FF)` of cond₂(K + DEDᵀ) over all E ≥ 0 (module
/// docs), from the proven brackets of the certified cond₂ routes ([`conditioning::cond2`]
/// on K and on K_FF, any size, sparse or dense): the lower end of λ_max(K)'s bracket over
/// the upper end of λ_min(K_FF)'s, rounded down. 1 when every DOF is constrained; +∞ when
/// K_FF is not positive definite (every K + DEDᵀ is then singular). K symmetric positive
/// definite (errors otherwise).
pub fn cond2_lower_bound(problem: &Problem) -> Result<f64> {
    let n = problem.n();
    let mut index = vec![usize::MAX; n];
    for c in &problem.constraints {
        index[c.dof] = 0;
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

/// The smooth model over a fixed penalized set.
struct Model<'a> {
    p: &'a Problem,
    k: Mat<f64>,
    /// Penalized constraint indices (the variables).
    set: Vec<usize>,
    delta: f64,
}

/// One evaluation: Φ and its gradient in x = ln ε, plus the exact ln cond₂.
struct Eval {
    phi: f64,
    grad: Vec<f64>,
}

impl Model<'_> {
    /// Φ = F_t + μ·barrier at x, or None if x is infeasible (or A is not SPD).
    fn eval(&self, x: &[f64], t: f64, mu: f64) -> Result<Option<Eval>> {
        let p = self.p;
        let n = p.n();
        let eps: Vec<f64> = x.iter().map(|v| v.exp()).collect();
        let mut a = self.k.clone();
        let mut rhs = p.q.clone();
        for (&c, &e) in self.set.iter().zip(&eps) {
            let con = p.constraints[c];
            a[(con.dof, con.dof)] += e;
            rhs[con.dof] += e * con.limit;
        }
        let evd = a
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Numerical(format!("symmetric eigen failed: {e:?}")))?;
        let (v, s) = (evd.U(), evd.S().column_vector());
        let lam: Vec<f64> = (0..n).map(|k| s[k]).collect();
        if !lam.iter().all(|l| l.is_finite() && *l > 0.0) {
            return Ok(None);
        }
        // u = V Λ⁻¹ Vᵀ rhs.
        let mut y = vec![0.0; n];
        for (k, yk) in y.iter_mut().enumerate() {
            *yk = (0..n).map(|i| v[(i, k)] * rhs[i]).sum::<f64>() / lam[k];
        }
        let gaps: Vec<f64> = p
            .constraints
            .iter()
            .map(|con| (0..n).map(|k| v[(con.dof, k)] * y[k]).sum::<f64>() - con.limit)
            .collect();
        // Barrier terms h(g_i) > 0 with dh/dg_i.
        let mut terms: Vec<(usize, f64, f64)> = Vec::new();
        for (i, con) in p.constraints.iter().enumerate() {
            let g = gaps[i];
            match con.kind {
                ConstraintKind::Bilateral => {
                    terms.push((i, self.delta - g, -1.0));
                    terms.push((i, self.delta + g, 1.0));
                }
                kind => {
                    let s = if kind == ConstraintKind::Upper {
                        1.0
                    } else {
                        -1.0
                    };
                    terms.push((i, self.delta - s * g, -s));
                    if self.set.contains(&i) {
                        terms.push((i, s * g, s));
                    }
                }
            }
        }
        if !terms.iter().all(|&(_, h, _)| h > 0.0) {
            return Ok(None);
        }
        // Smoothed ln cond and its weights.
        let ll: Vec<f64> = lam.iter().map(|l| l.ln()).collect();
        let (hi, lo) = (ll[n - 1], ll[0]);
        let wp: Vec<f64> = ll.iter().map(|l| (t * (l - hi)).exp()).collect();
        let wm: Vec<f64> = ll.iter().map(|l| (-t * (l - lo)).exp()).collect();
        let (sp, sm) = (wp.iter().sum::<f64>(), wm.iter().sum::<f64>());
        let f = hi + sp.ln() / t - lo + sm.ln() / t;
        let barrier: f64 = terms.iter().map(|&(_, h, _)| -(h / self.delta).ln()).sum();
        let phi = f + mu * barrier;
        // dΦ/dg_i from the barrier.
        let mut dphi_dg = vec![0.0; p.m()];
        for &(i, h, dh) in &terms {
            dphi_dg[i] += -mu * dh / h;
        }
        let grad = self
            .set
            .iter()
            .zip(&eps)
            .map(|(&j, &e)| {
                let dj = p.constraints[j].dof;
                let mut df = 0.0;
                for k in 0..n {
                    df += (wp[k] / sp - wm[k] / sm) * v[(dj, k)] * v[(dj, k)] / lam[k];
                }
                // ∂g_i/∂ε_j = −(A⁻¹)_{d_i d_j} g_j.
                let mut db = 0.0;
                for (i, con) in p.constraints.iter().enumerate() {
                    if dphi_dg[i] != 0.0 {
                        let z: f64 = (0..n).map(|k| v[(con.dof, k)] * v[(dj, k)] / lam[k]).sum();
                        db += dphi_dg[i] * (-z * gaps[j]);
                    }
                }
                e * (df + db)
            })
            .collect();
        Ok(Some(Eval { phi, grad }))
    }
}

fn inf_norm(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// BFGS on Φ(·; t, μ) from a strictly feasible x; returns the final x and ‖∇Φ‖∞.
fn bfgs(
    model: &Model,
    x0: Vec<f64>,
    t: f64,
    mu: f64,
    evals: &mut usize,
) -> Result<(Vec<f64>, f64)> {
    let d = x0.len();
    let mut x = x0;
    *evals += 1;
    let Some(mut cur) = model.eval(&x, t, mu)? else {
        return Ok((x, f64::NAN));
    };
    let mut h = Mat::<f64>::identity(d, d);
    for _ in 0..MAX_INNER {
        let gn = inf_norm(&cur.grad);
        if gn < 1e-10 {
            break;
        }
        let mut dir: Vec<f64> = (0..d)
            .map(|i| -(0..d).map(|j| h[(i, j)] * cur.grad[j]).sum::<f64>())
            .collect();
        let mut slope: f64 = dir.iter().zip(&cur.grad).map(|(a, b)| a * b).sum();
        if slope.is_nan() || slope >= 0.0 {
            h = Mat::identity(d, d);
            dir = cur.grad.iter().map(|g| -g).collect();
            slope = -cur.grad.iter().map(|g| g * g).sum::<f64>();
        }
        let cap = inf_norm(&dir);
        let mut step = if cap > 2.0 { 2.0 / cap } else { 1.0 };
        let mut accepted = None;
        for _ in 0..40 {
            let xt: Vec<f64> = x.iter().zip(&dir).map(|(a, b)| a + step * b).collect();
            *evals += 1;
            if let Some(e) = model.eval(&xt, t, mu)? {
                if e.phi <= cur.phi + 1e-4 * step * slope {
                    accepted = Some((xt, e));
                    break;
                }
            }
            step *= 0.5;
        }
        let Some((xn, en)) = accepted else { break };
        let sv: Vec<f64> = xn.iter().zip(&x).map(|(a, b)| a - b).collect();
        let yv: Vec<f64> = en.grad.iter().zip(&cur.grad).map(|(a, b)| a - b).collect();
        let sy: f64 = sv.iter().zip(&yv).map(|(a, b)| a * b).sum();
        let done = (cur.phi - en.phi).abs() <= 1e-15 * cur.phi.abs().max(1.0);
        x = xn;
        cur = en;
        if sy > 1e-300 {
            // H ← (I − ρ s yᵀ) H (I − ρ y sᵀ) + ρ s sᵀ.
            let rho = 1.0 / sy;
            let hy: Vec<f64> = (0..d)
                .map(|i| (0..d).map(|j| h[(i, j)] * yv[j]).sum())
                .collect();
            let yhy: f64 = yv.iter().zip(&hy).map(|(a, b)| a * b).sum();
            h = Mat::from_fn(d, d, |i, j| {
                h[(i, j)] - rho * (hy[i] * sv[j] + sv[i] * hy[j])
                    + (rho * rho * yhy + rho) * sv[i] * sv[j]
            });
        }
        if done {
            break;
        }
    }
    Ok((x, inf_norm(&cur.grad)))
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

/// Runs the continuation from a start's penalties; None if the start is not strictly feasible.
fn optimise_from(
    p: &Problem,
    k: &Mat<f64>,
    delta: f64,
    start: &[f64],
    evals: &mut usize,
) -> Result<Option<(Vec<f64>, f64)>> {
    let floor = 1e-8;
    let set: Vec<usize> = (0..p.m())
        .filter(|&c| start[c] > 0.0 || p.constraints[c].kind == ConstraintKind::Bilateral)
        .collect();
    if set.is_empty() {
        return Ok(None);
    }
    let model = Model {
        p,
        k: k.clone(),
        set,
        delta,
    };
    let mut x: Vec<f64> = model
        .set
        .iter()
        .map(|&c| {
            let kdd = p.k.diag(p.constraints[c].dof).abs().max(f64::MIN_POSITIVE);
            start[c].max(floor * kdd).ln()
        })
        .collect();
    *evals += 1;
    if model.eval(&x, STAGES[0].0, STAGES[0].1)?.is_none() {
        return Ok(None);
    }
    let mut opt = f64::NAN;
    for (t, mu) in STAGES {
        let (xn, gn) = bfgs(&model, x, t, mu, evals)?;
        x = xn;
        opt = gn.max(mu);
    }
    let mut eps = vec![0.0; p.m()];
    for (&c, v) in model.set.iter().zip(&x) {
        eps[c] = v.exp();
    }
    Ok(Some((eps, opt)))
}

/// Strictly feasible `scaled` start: ε_c = 2^k f₀ K_dd for the smallest k that works.
fn scaled_start(p: &Problem, delta: f64, f0: f64) -> Result<Option<Vec<f64>>> {
    let mut f = f0.max(1e-6);
    for _ in 0..30 {
        let eps: Vec<f64> = p
            .constraints
            .iter()
            .map(|c| f * p.k.diag(c.dof).abs())
            .collect();
        let s = fixed_energy(Context::new(p), Method::scaled(f), eps)?;
        if s.max_penetration < delta {
            return Ok(Some(s.penalties));
        }
        f *= 2.0;
    }
    Ok(None)
}

/// Solves for the cond-optimal penalties at allowed penetration δ (module docs).
pub fn solve(ctx: Context, delta: f64) -> Result<Solution> {
    let p = ctx.problem;
    check_affordable(p)?;
    let lower = cond2_lower_bound(p)?;
    let k = p.k.to_dense();
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
        .map(|(c, e)| e / p.k.diag(c.dof).abs().max(f64::MIN_POSITIVE))
        .fold(0.0f64, f64::max);
    starts.insert(0, (super::condensed::STRATEGY.name.into(), inner.penalties));
    if let Some(e) = scaled_start(p, delta, f0)? {
        starts.push((super::scaled::STRATEGY.name.into(), e));
    }
    let mut evals = 0;
    let mut n_opt = 0;
    for (label, start) in &starts {
        let Some((eps, opt)) = optimise_from(p, &k, delta, start, &mut evals)? else {
            continue;
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
        cond2_lower_bound: lower,
        winner: best.label,
        evaluations: evals,
    });
    Ok(sol)
}
