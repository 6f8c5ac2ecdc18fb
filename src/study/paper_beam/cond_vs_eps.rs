//! cond₂(K + εDDᵀ) and the max penetration for a uniform ε on a log grid, and the δ-driven
//! strategies at several δ (`cond_vs_eps.csv`, rows [`CondRow`]).

use super::record::CondRow;
use super::solves::solve_with_metrics;
use super::{DELTAS, EPS_HI, EPS_LO, N_EPS};
use crate::conditioning;
use crate::error::Result;
use crate::strategy::{self, condensed, optimal, paper, spring, Knobs, Method, Strategy};
use crate::system::Problem;

/// The rows of `cond_vs_eps.csv`: K alone, the uniform-ε grid, then `paper`, `condensed`,
/// `spring` at every δ of [`DELTAS`].
pub fn cond_rows(p: &Problem) -> Result<Vec<CondRow>> {
    let m = p.m();
    let mut rows = vec![CondRow {
        series: "K".into(),
        delta: None,
        eps: 0.0,
        eps_1: 0.0,
        eps_2: 0.0,
        eps_3: 0.0,
        cond2: conditioning::cond2(&p.k)?.cond2,
        max_penetration: strategy::Context::new(p)
            .g0()?
            .iter()
            .fold(0.0, |a, g| a.max(g.abs())),
        log10_det_ratio: 0.0,
    }];
    let (a, b) = (EPS_LO.log10(), EPS_HI.log10());
    for i in 0..N_EPS {
        let eps = 10f64.powf(a + (b - a) * i as f64 / (N_EPS - 1) as f64);
        let s = solve_with_metrics(p, Method::constant(eps))?;
        rows.push(CondRow {
            series: "uniform".into(),
            delta: None,
            eps,
            eps_1: eps,
            eps_2: eps,
            eps_3: eps,
            cond2: s.cond2,
            max_penetration: s.sol.max_penetration,
            log10_det_ratio: s.log10_det_ratio,
        });
    }
    for s in [&paper::STRATEGY, &condensed::STRATEGY, &spring::STRATEGY] {
        for delta in DELTAS {
            let row = delta_row(p, s, delta)?;
            debug_assert_eq!(m, 3);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// One δ-driven row: strategy `s` (`paper`, `condensed`, `spring` or `optimal`) at δ.
fn delta_row(p: &Problem, s: &'static Strategy, delta: f64) -> Result<CondRow> {
    let name = s.name;
    let knobs = Knobs::delta(delta);
    let method = Method::new(s, knobs)?;
    let s = solve_with_metrics(p, method)?;
    let e = &s.sol.penalties;
    Ok(CondRow {
        series: name.into(),
        delta: Some(delta),
        eps: e.iter().copied().fold(0.0, f64::max),
        eps_1: e[0],
        eps_2: e[1],
        eps_3: e[2],
        cond2: s.cond2,
        max_penetration: s.sol.max_penetration,
        log10_det_ratio: s.log10_det_ratio,
    })
}

/// Number of δ values of `cond_vs_delta.csv`, log-spaced over `[DELTA_LO, DELTA_HI]` (the
/// paper's δ = 0.1 is on the grid).
pub const N_DELTA: usize = 31;
/// Smallest δ of `cond_vs_delta.csv`.
pub const DELTA_LO: f64 = 1e-3;
/// Largest δ of `cond_vs_delta.csv`.
pub const DELTA_HI: f64 = 1.0;

/// The rows of `cond_vs_delta.csv`: `paper` (Eq. 28), `condensed`, `spring` and `optimal` at
/// every δ of the log grid (`series`, `delta`, the penalties, cond₂, max penetration).
pub fn cond_delta_rows(p: &Problem) -> Result<Vec<CondRow>> {
    let (a, b) = (DELTA_LO.log10(), DELTA_HI.log10());
    let mut rows = Vec::new();
    for s in [
        &paper::STRATEGY,
        &condensed::STRATEGY,
        &spring::STRATEGY,
        &optimal::STRATEGY,
    ] {
        for i in 0..N_DELTA {
            let delta = 10f64.powf(a + (b - a) * i as f64 / (N_DELTA - 1) as f64);
            rows.push(delta_row(p, s, delta)?);
        }
    }
    Ok(rows)
}
