//! The solves of the study: the strategies at the paper's δ, one line per strategy, and the
//! equal-accuracy comparisons (a uniform ε tuned by bisection to a max penetration).

use super::record::StrategyLine;
use super::{DELTA, EPS_HI, EPS_LO};
use crate::error::{Error, Result};
use crate::metrics::{self, MetricSet};
use crate::strategy::{self, Knob, Method, Solution};
use crate::study::text::{fmt_e, fmt_g};
use crate::system::Problem;

/// A solved strategy with its metrics.
#[derive(Clone, Debug)]
pub struct Solved {
    /// The solution.
    pub sol: Solution,
    /// cond₂ of the system matrix (NaN when not computed).
    pub cond2: f64,
    /// log10|det| of the system matrix (NaN when not computed).
    pub log10_det: f64,
    /// log10 det(system)/det K (NaN when not computed).
    pub log10_det_ratio: f64,
}

/// Solves `p` with `method` and computes every metric.
pub fn solve_with_metrics(p: &Problem, method: Method) -> Result<Solved> {
    let sol = strategy::solve(p, method)?;
    let m = metrics::compute(p, &sol, MetricSet::ALL)?;
    Ok(Solved {
        cond2: m.cond2_system.map_or(f64::NAN, |c| c.cond2),
        log10_det: m.log10_det_system.unwrap_or(f64::NAN),
        log10_det_ratio: m.log10_det_ratio.unwrap_or(f64::NAN),
        sol,
    })
}

/// Every solve of the study at the paper's δ.
#[derive(Clone, Debug)]
pub struct Solves {
    /// log10|det K|.
    pub log10_det_k: f64,
    /// cond₂ K.
    pub cond_k: f64,
    /// The solution without contact, `K u0 = q` (Eq. 33).
    pub u0: Vec<f64>,
    /// `lagrange` (the exact bilateral solution).
    pub lag: Solved,
    /// `paper` (Eq. 28) at δ.
    pub pap: Solved,
    /// `condensed` at δ.
    pub con: Solved,
    /// `optimal` (the cond-optimal penalties) at δ.
    pub opt: Solved,
    /// One line per strategy.
    pub strategies: Vec<StrategyLine>,
    /// The uniform ε whose max penetration is δ.
    pub eps_tuned: f64,
    /// `constant` at `eps_tuned`.
    pub tuned: Solved,
    /// The max penetration Eq. 28 reaches.
    pub pen_pap: f64,
    /// The uniform ε whose max penetration is `pen_pap`.
    pub eps_at_pap: f64,
    /// `constant` at `eps_at_pap`.
    pub uni_at_pap: Solved,
    /// `condensed` at δ = `pen_pap`.
    pub con_at_pap: Solved,
}

fn knob_text(m: &Method) -> String {
    let k = m.knobs();
    let nan = f64::NAN;
    match m.strategy().knob {
        Knob::Eps => format!("ε = {}", fmt_e(k.eps.unwrap_or(nan), 1)),
        Knob::Factor => format!("ε_c = {}·K[d,d]", k.factor.unwrap_or(nan)),
        Knob::Delta => format!("δ = {}", k.delta.unwrap_or(nan)),
        Knob::None => "exact".into(),
        Knob::EpsTol => format!(
            "ε = {}, tol = {}{}",
            fmt_g(k.eps.unwrap_or(nan)),
            fmt_e(k.tol.unwrap_or(nan), 1),
            if k.adaptive { ", adaptive" } else { "" }
        ),
    }
}

fn strategy_line(m: &Method, s: &Solved, u_ref: &[f64]) -> StrategyLine {
    StrategyLine {
        name: m.name().into(),
        knob: knob_text(m),
        penalties: s.sol.penalties.clone(),
        gaps: s.sol.gaps.clone(),
        forces: s.sol.forces.clone(),
        max_penetration: s.sol.max_penetration,
        cond2_system: s.cond2,
        log10_det_system: s.log10_det,
        log10_det_ratio: s.log10_det_ratio,
        error_vs_lagrange: metrics::relative_error(&s.sol.u, u_ref),
        linear_solves: s.sol.stats.linear_solves,
        factorizations: s.sol.stats.factorizations,
        iterations: s.sol.stats.iterations,
        warnings: s.sol.warnings.clone(),
        u: s.sol.u.clone(),
    }
}

/// The strategies other than `paper` and `condensed` at δ: two constant ε, scaled, spring,
/// lagrange and augmented (plain and adaptive) with ε = max_c K[d_c, d_c].
fn other_methods(p: &Problem) -> Vec<Method> {
    let max_diag = p
        .constraints
        .iter()
        .map(|c| c.stiffness(&p.k))
        .fold(0.0f64, f64::max);
    let max_limit = p
        .constraints
        .iter()
        .map(|c| c.limit.abs())
        .fold(1.0f64, f64::max);
    let aug_tol = 1e-9 * max_limit;
    let augmented = |adaptive| Method::augmented(max_diag, aug_tol, adaptive);
    vec![
        Method::constant(1e4),
        Method::constant(1e8),
        Method::scaled(100.0),
        Method::spring(DELTA),
        Method::lagrange(),
        augmented(false),
        augmented(true),
    ]
}

/// Solves the beam with every strategy and the equal-accuracy comparisons.
pub fn solve_all(p: &Problem) -> Result<Solves> {
    let log10_det_k = crate::conditioning::log10_abs_det(&p.k)?;
    let cond_k = crate::conditioning::cond2(&p.k)?.cond2;
    let u0 = strategy::Context::new(p).u0()?.to_vec();

    let lag = solve_with_metrics(p, Method::lagrange())?;
    let u_ref = &lag.sol.u;
    let pap = solve_with_metrics(p, Method::paper(DELTA))?;
    let con = solve_with_metrics(p, Method::condensed(DELTA))?;
    let mut strategies = vec![
        strategy_line(&Method::paper(DELTA), &pap, u_ref),
        strategy_line(&Method::condensed(DELTA), &con, u_ref),
    ];
    let opt = solve_with_metrics(p, Method::optimal(DELTA))?;
    strategies.push(strategy_line(&Method::optimal(DELTA), &opt, u_ref));
    for m in &other_methods(p) {
        let s = if *m == Method::lagrange() {
            lag.clone()
        } else {
            solve_with_metrics(p, *m)?
        };
        strategies.push(strategy_line(m, &s, u_ref));
    }
    // Equal-accuracy comparisons: a uniform ε tuned to max penetration δ, and the condensed /
    // uniform penalties at the max penetration Eq. 28 actually reaches.
    let eps_tuned = uniform_eps_for(p, DELTA)?;
    let tuned = solve_with_metrics(p, Method::constant(eps_tuned))?;
    let mut line = strategy_line(&Method::constant(eps_tuned), &tuned, u_ref);
    line.knob = format!("ε = {} (tuned: max pen. = δ)", fmt_g(eps_tuned));
    strategies.insert(2, line);
    let pen_pap = pap.sol.max_penetration;
    let eps_at_pap = uniform_eps_for(p, pen_pap)?;
    let uni_at_pap = solve_with_metrics(p, Method::constant(eps_at_pap))?;
    let con_at_pap = solve_with_metrics(p, Method::condensed(pen_pap))?;
    Ok(Solves {
        log10_det_k,
        cond_k,
        u0,
        lag,
        pap,
        con,
        opt,
        strategies,
        eps_tuned,
        tuned,
        pen_pap,
        eps_at_pap,
        uni_at_pap,
        con_at_pap,
    })
}

/// The uniform ε whose max penetration is `target` (bisection in log ε over the sweep range).
pub fn uniform_eps_for(p: &Problem, target: f64) -> Result<f64> {
    let pen = |log_e: f64| {
        strategy::solve(p, Method::constant(10f64.powf(log_e))).map(|s| s.max_penetration)
    };
    let (mut lo, mut hi) = (EPS_LO.log10(), EPS_HI.log10());
    if !(pen(lo)? > target && pen(hi)? < target) {
        return Err(Error::Numerical(format!(
            "no uniform ε in [{EPS_LO:e}, {EPS_HI:e}] gives max penetration {target}"
        )));
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if pen(mid)? > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(10f64.powf(0.5 * (lo + hi)))
}
