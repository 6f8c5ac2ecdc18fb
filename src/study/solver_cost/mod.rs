//! `solver_cost`: what each penalty rule costs a solver at equal accuracy — the digits a
//! direct solve loses and the iterations a preconditioned Krylov solver needs — over mesh
//! levels with h halving.
//!
//! Families ([`cases`]): one-DOF rows — Hertz plane and axisymmetric (force-controlled), the
//! membrane on an obstacle, the cantilever on a wavy bed, the 3-D block under a sphere
//! (`hertz-3d`); coupled rows — the block on an inclined plane, Hertz with rows along the
//! cylinder's normals, the two-body patch test with node-to-segment rows, an elastic cylinder
//! on a block with mortar rows. On every level, Lagrange once (`exact`), and
//! every other rule twice, its knob searched ([`search`]) so that
//! - `discretization`: its penalty error equals the level's discretization error, or
//! - `penetration`: its largest penetration equals δ = `penetration_rel` · the family's
//!   length scale (`barrier` never penetrates: it runs at d̂ = δ, unmatched).
//!
//! **The ε map** ([`eps_map_rows`]): on one level of every family (`eps_map_level`, 2 by
//! default), `constant` at ε = 10^k·k_scale for k = 0 … 10 (k_scale: the family's stiffness
//! scale, [`cases::Level::k_scale`]; rows with accuracy `eps-map`, unmatched): iterations to the
//! fixed error of u and digits of u lost against ε, per preconditioner, where each one fails
//! (the error-based run misses its target: it hits the iteration limit, or its CG breaks
//! down, pᵀAp ≤ 0 or rᵀz ≤ 0 in floating point; or the preconditioner cannot be built).
//!
//! Each row then holds the solver-cost metrics of its final system
//! ([`crate::metrics::solver`]: cond₂ raw and Jacobi-scaled, CG iterations with Jacobi and
//! IC(0) and their effective condition estimates, MINRES for Lagrange, forward errors of u and
//! of the contact forces, the backward error, seconds of each solve) and the slopes against h
//! ([`record::slopes`]: cond ∝ h^−p, iterations ∝ h^−q) are fitted over the levels.

pub mod cases;
mod figures;
pub mod record;
mod report;
pub mod search;

pub use cases::Family;
pub use record::{slopes, Row, Slope};
pub use search::Accuracy;

use crate::conditioning::sparse::RitzStarts;
use crate::error::{Error, Result};
use crate::metrics::{self, solver::SolverOptions, MetricSet};
use crate::progress::Progress;
use crate::strategy::{self, registry, Knob, Strategy};
use crate::study::checkpoint::Checkpoints;
use crate::study::shape::{Drawing, RunContext, Study};
use crate::system::Stiffness;
use cases::Level;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, OnceLock};

/// What to run.
#[derive(Clone, Debug, Serialize)]
pub struct SolverCostConfig {
    /// Families.
    pub families: Vec<Family>,
    /// Mesh levels per family (h halving), 2–8.
    pub levels: usize,
    /// Coarsest Hertz element size h/a at the contact.
    pub hertz_h0: f64,
    /// Coarsest membrane side (interior nodes per direction); level l has (side₀+1)·2^l − 1.
    pub membrane_side0: usize,
    /// Coarsest beam element count; level l has `beam_el0`·2^l.
    pub beam_el0: usize,
    /// Coarsest `hertz-3d` element size h/a at the contact.
    pub sphere_h0: f64,
    /// Rules (lagrange always runs; saved by name).
    #[serde(serialize_with = "registry::serialize_names")]
    pub methods: Vec<&'static Strategy>,
    /// δ of the `penetration` rows over the family's length scale.
    pub penetration_rel: f64,
    /// Relative tolerance of the knob match.
    pub match_tol: f64,
    /// τ of the residual-stopped Krylov runs.
    pub krylov_tol: f64,
    /// The relative error of u the error-based Krylov counts are taken to.
    pub krylov_err: f64,
    /// Relative accuracy asked of each cond₂.
    pub cond_tol: f64,
    /// The level of the ε map (clamped to the finest).
    pub eps_map_level: usize,
}

/// ε/k_scale of the ε map's rows: 10^k for these k (11 decades).
pub const EPS_MAP_DECADES: std::ops::RangeInclusive<i32> = 0..=10;

/// The accuracy name of the ε map's rows.
pub const EPS_MAP: &str = "eps-map";

impl Default for SolverCostConfig {
    fn default() -> Self {
        SolverCostConfig {
            families: Family::defaults(),
            levels: 5,
            hertz_h0: 0.5,
            membrane_side0: 7,
            beam_el0: 8,
            sphere_h0: 4.0,
            methods: default_methods(),
            penetration_rel: 1e-3,
            match_tol: 0.05,
            krylov_tol: metrics::solver::DEFAULT_TOL,
            krylov_err: metrics::solver::DEFAULT_ERR_TARGET,
            cond_tol: 1e-6,
            eps_map_level: 2,
        }
    }
}

/// Every rule but `optimal` (minutes per solve above a few hundred DOFs; `--methods` adds it).
pub fn default_methods() -> Vec<&'static Strategy> {
    registry::all()
        .into_iter()
        .filter(|s| !std::ptr::eq(*s, &strategy::optimal::STRATEGY))
        .collect()
}

impl SolverCostConfig {
    /// Checks the ranges (each error names its flag).
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--families", self.families.iter().map(|f| f.name()))?;
        Error::distinct("--methods", self.methods.iter().map(|s| s.name))?;
        if !(2..=8).contains(&self.levels) {
            return Err(Error::out_of_range("--levels", self.levels, "in 2..=8"));
        }
        let finest = self.hertz_h0 / (1u64 << (self.levels - 1)) as f64;
        if !(self.hertz_h0 <= 0.5 && finest >= 1e-3) {
            return Err(Error::out_of_range(
                "--hertz-h0",
                format!("{}, finest {finest:e}", self.hertz_h0),
                "such that h/a ∈ [1e-3, 0.5] at every level",
            ));
        }
        let side = (self.membrane_side0 + 1) << (self.levels - 1);
        if self.membrane_side0 < 1 {
            return Err(Error::out_of_range(
                "--membrane-side0",
                self.membrane_side0,
                "≥ 1",
            ));
        }
        if side > 2001 {
            return Err(Error::out_of_range(
                "--membrane-side0",
                format!("{}, whose finest side is {}", self.membrane_side0, side - 1),
                format!(
                    "small enough for a finest side ≤ 2000 at --levels {}",
                    self.levels
                ),
            ));
        }
        let finest = self.sphere_h0 / (1u64 << (self.levels - 1)) as f64;
        if !(self.sphere_h0 <= 4.0 && finest >= 1.0 / 32.0) {
            return Err(Error::out_of_range(
                "--sphere-h0",
                format!("{}, finest {finest:e}", self.sphere_h0),
                "such that h/a ∈ [1/32, 4] at every level (1/32: 320 352 DOFs)",
            ));
        }
        if self.beam_el0 < 2 || self.beam_el0 << (self.levels - 1) > 20_000 {
            return Err(Error::out_of_range(
                "--beam-el0",
                self.beam_el0,
                "≥ 2 with a finest beam of at most 20000 elements",
            ));
        }
        for (flag, v) in [
            ("--penetration-rel", self.penetration_rel),
            ("--match-tol", self.match_tol),
            ("--krylov-tol", self.krylov_tol),
            ("--krylov-err", self.krylov_err),
            ("--cond-tol", self.cond_tol),
        ] {
            Error::fraction(flag, v)?;
        }
        Ok(())
    }

    /// The coarsest sizes of the levels.
    pub fn coarsest(&self) -> cases::Coarsest {
        cases::Coarsest {
            hertz_h0: self.hertz_h0,
            membrane_side0: self.membrane_side0,
            beam_el0: self.beam_el0,
            sphere_h0: self.sphere_h0,
        }
    }

    fn strategies(&self) -> Vec<&'static Strategy> {
        let mut s = vec![&strategy::lagrange::STRATEGY];
        s.extend(
            self.methods
                .iter()
                .copied()
                .filter(|s| s.knob != Knob::None),
        );
        s
    }
}

/// The jobs of a level: lagrange once, every other rule at both accuracies.
fn jobs(cfg: &SolverCostConfig) -> Vec<(&'static Strategy, Accuracy)> {
    let mut out = Vec::new();
    for s in cfg.strategies() {
        if s.knob == Knob::None {
            out.push((s, Accuracy::Exact));
        } else {
            out.push((s, Accuracy::Discretization));
            out.push((s, Accuracy::Penetration));
        }
    }
    out
}

/// What one level leaves: its rows (jobs in job order, then the ε map's where it has one) and
/// each job's start on the next level; checkpointed per level ([`CHECKPOINTS`]).
#[derive(Serialize, Deserialize)]
struct LevelRun {
    rows: Vec<Row>,
    eps_map: Vec<Row>,
    starts: Vec<Option<search::Start>>,
}

/// The checkpoint folder under `--out` (one file per family and level).
pub const CHECKPOINTS: &str = "levels";

/// Runs every family's levels (one progress step per level; jobs of a level in parallel,
/// rows in job order: the same rows for any number of threads, but for the timing columns).
/// With `checkpoints`, each finished level is written at once and, with `--resume`, read back
/// instead of solved ([`crate::study::checkpoint`]; its rows keep their first run's timings).
pub fn run(
    cfg: &SolverCostConfig,
    progress: &Progress,
    checkpoints: Option<&Checkpoints>,
) -> Result<Vec<Row>> {
    cfg.validate()?;
    let jobs = jobs(cfg);
    progress.set_total(cfg.families.len() * cfg.levels);
    let mut rows = Vec::new();
    for &family in &cfg.families {
        progress.message(format!(
            "{}: Lagrange on {} levels",
            family.name(),
            cfg.levels
        ));
        let levels = cases::levels(family, cfg.levels, cfg.coarsest())?;
        // Each job's search starts from its match on the level before (search::Start), and
        // the jobs that took longest there start first.
        let mut starts: Vec<Option<search::Start>> = vec![None; jobs.len()];
        let mut costs = vec![0.0; jobs.len()];
        for level in &levels {
            let solve = || Ok(level_run(cfg, &jobs, level, &starts, &costs, progress));
            let key = format!("{}-level{}", family.name(), level.index);
            let (done, resumed) = Checkpoints::get_or_maybe(checkpoints, &key, solve)?;
            starts = done.starts;
            costs = done
                .rows
                .iter()
                .map(|r| r.seconds_search + r.seconds_metrics)
                .collect();
            rows.extend(done.rows);
            rows.extend(done.eps_map);
            progress.step(&format!(
                "{} level {}: h = {:.4}, {} DOFs{}",
                family.name(),
                level.index,
                level.h,
                level.n_dofs,
                if resumed { " (checkpoint)" } else { "" }
            ));
        }
    }
    progress.finish();
    Ok(rows)
}

/// One level's jobs in parallel (the costliest on the level before first), then its ε map
/// where `cfg.eps_map_level` asks for it.
fn level_run(
    cfg: &SolverCostConfig,
    jobs: &[(&'static Strategy, Accuracy)],
    level: &Level,
    starts: &[Option<search::Start>],
    costs: &[f64],
    progress: &Progress,
) -> LevelRun {
    let k_once = KOnce::default();
    let done = AtomicUsize::new(0);
    let level_rows: Vec<(Row, Option<search::Start>)> = costliest_first(costs, |i| {
        let (s, acc) = jobs[i];
        let row = row_of(cfg, level, &k_once, s, acc, starts[i]);
        let k = 1 + done.fetch_add(1, Ordering::Relaxed);
        progress.message(format!(
            "{} level {} ({} DOFs): {k}/{} rules",
            level.family.name(),
            level.index,
            level.n_dofs,
            jobs.len()
        ));
        row
    });
    let eps_map = if level.index == cfg.eps_map_level.min(cfg.levels - 1) {
        progress.message(format!(
            "{} level {}: the ε map ({} values of ε)",
            level.family.name(),
            level.index,
            EPS_MAP_DECADES.count()
        ));
        eps_map_rows_with(cfg, level, &k_once)
    } else {
        Vec::new()
    };
    let (rows, starts) = level_rows.into_iter().unzip();
    LevelRun {
        rows,
        eps_map,
        starts,
    }
}

/// `f(i)` for every i < `costs.len()` on the rayon pool's threads, the costliest first: each
/// thread takes the next job of one queue, so a level ends on its cheap jobs rather than one
/// long job alone on a thread (rayon's halving of the list would pair them as they come).
/// Results in index order: the same for any number of threads.
fn costliest_first<T: Send>(costs: &[f64], f: impl Fn(usize) -> T + Sync) -> Vec<T> {
    let mut order: Vec<usize> = (0..costs.len()).collect();
    order.sort_by(|&a, &b| costs[b].total_cmp(&costs[a]));
    let next = AtomicUsize::new(0);
    let out: Vec<Mutex<Option<T>>> = (0..costs.len()).map(|_| Mutex::new(None)).collect();
    rayon::scope(|scope| {
        for _ in 0..rayon::current_num_threads().min(costs.len()) {
            scope.spawn(|_| {
                while let Some(&i) = order.get(next.fetch_add(1, Ordering::Relaxed)) {
                    let v = f(i);
                    *out[i].lock().unwrap_or_else(|e| e.into_inner()) = Some(v);
                }
            });
        }
    });
    out.into_iter()
        .map(|m| {
            m.into_inner()
                .unwrap_or_else(|e| e.into_inner())
                .expect("every job ran")
        })
        .collect()
}

/// One rule on one level at one accuracy: the knob search (from `start`, the match on the
/// level before, where there is one), then the metrics of its final system. Failures are
/// recorded in `note`. Returns the row and the next level's start.
fn row_of(
    cfg: &SolverCostConfig,
    level: &Level,
    k_once: &KOnce,
    s: &'static Strategy,
    acc: Accuracy,
    start: Option<search::Start>,
) -> (Row, Option<search::Start>) {
    let mut row = Row {
        family: level.family.name().into(),
        level: level.index,
        h: level.h,
        n_dofs: level.n_dofs,
        method: s.name.into(),
        accuracy: acc.name().into(),
        err_discretization: level.err_discretization,
        err_discretization_extrapolated: level.err_discretization_extrapolated,
        ..Row::default()
    };
    let t0 = std::time::Instant::now();
    let (solved, next) = match solve_row(cfg, level, s, acc, start, &mut row) {
        Ok(x) => x,
        Err(e) => {
            row.note = e.to_string();
            row.seconds_search = t0.elapsed().as_secs_f64();
            return (row, None);
        }
    };
    let t1 = std::time::Instant::now();
    metrics_into(cfg, &solved, k_once, &mut row);
    row.seconds_search = t1.duration_since(t0).as_secs_f64();
    row.seconds_metrics = t1.elapsed().as_secs_f64();
    (row, next)
}

/// K's cond₂ analysis on a level, made once: K is the same matrix, bit for bit, in every row
/// of a level (a Hertz row's scene differs from another's in its lift, which moves q only),
/// and [`metrics::compute`] would repeat its analysis in every row. Its Ritz vectors start
/// each row's system analysis as `compute` starts them ([`metrics::k_analysis`],
/// [`metrics::compute_with_k`]), so the values are those `compute` gives. Kept with K's
/// entries (their bits, read once), against which each row's K is compared without a copy;
/// None where K's analysis failed (each row then reports the failure through `compute`).
#[derive(Default)]
struct KOnce(OnceLock<Option<(Entries, Option<RitzStarts>)>>);

/// A matrix's order and its entries (row, column, value bits) in storage order.
type Entries = (usize, Vec<(usize, usize, u64)>);

impl KOnce {
    /// K's Ritz vectors where `k` is the level's K, bit for bit.
    fn starts(&self, k: &Stiffness, tol: f64) -> Option<Option<&RitzStarts>> {
        let got = self.0.get_or_init(|| {
            let (_, ritz) = metrics::k_analysis(k, Some(tol)).ok()?;
            let mut entries = Vec::with_capacity(k.nnz());
            k.for_each_entry(|i, j, v| entries.push((i, j, v.to_bits())));
            Some(((k.n(), entries), ritz))
        });
        let (entries, ritz) = got.as_ref()?;
        same_entries(entries, k).then_some(ritz.as_ref())
    }
}

/// `b` has exactly `entries` (order, storage order, pattern and value bits).
fn same_entries((n, entries): &Entries, b: &Stiffness) -> bool {
    if b.n() != *n || b.nnz() != entries.len() {
        return false;
    }
    let (mut same, mut k) = (true, 0);
    b.for_each_entry(|i, j, v| {
        same &= entries.get(k) == Some(&(i, j, v.to_bits()));
        k += 1;
    });
    same && k == entries.len()
}

/// The row of `solved`: its errors, cond₂ and solver-cost metrics. Failures go to `note`.
fn metrics_into(cfg: &SolverCostConfig, solved: &cases::Solved, k_once: &KOnce, row: &mut Row) {
    let (problem, sol) = (&solved.problem, &solved.sol);
    row.err_penalty = Some(solved.err_penalty);
    row.max_penetration = Some(sol.max_penetration);
    row.iterations = Some(sol.stats.iterations);
    let set = MetricSet {
        cond: true,
        det: false,
        cond_tol: Some(cfg.cond_tol),
    };
    let m = match k_once.starts(&problem.k, cfg.cond_tol) {
        Some(starts) => metrics::compute_with_k(problem, sol, set, None, starts, None),
        None => metrics::compute(problem, sol, set),
    };
    match m {
        Ok(m) => row.cond2_system = m.cond2_system.map(|c| c.cond2),
        Err(e) => row.note = format!("cond₂: {e}"),
    }
    let opts = SolverOptions {
        tol: cfg.krylov_tol,
        err_target: cfg.krylov_err,
        max_iters: None,
        cond_tol: Some(cfg.cond_tol),
    };
    match metrics::solver::compute(problem, sol, opts) {
        Ok(c) => fill_solver_metrics(row, &c),
        Err(e) => row.note = format!("solver metrics: {e}"),
    }
}

/// The ε map of one level (module doc): `constant` at ε = 10^k·k_scale, k in
/// [`EPS_MAP_DECADES`], in parallel, rows in ε order.
pub fn eps_map_rows(cfg: &SolverCostConfig, level: &Level) -> Vec<Row> {
    eps_map_rows_with(cfg, level, &KOnce::default())
}

/// [`eps_map_rows`] with the level's K analysis.
fn eps_map_rows_with(cfg: &SolverCostConfig, level: &Level, k_once: &KOnce) -> Vec<Row> {
    let decades: Vec<i32> = EPS_MAP_DECADES.collect();
    decades
        .par_iter()
        .map(|&k| {
            let rel = 10f64.powi(k);
            let eps = rel * level.k_scale;
            let mut row = Row {
                family: level.family.name().into(),
                level: level.index,
                h: level.h,
                n_dofs: level.n_dofs,
                method: strategy::constant::STRATEGY.name.into(),
                accuracy: EPS_MAP.into(),
                knob: "eps".into(),
                knob_rel: Some(rel),
                knob_value: Some(eps),
                err_discretization: level.err_discretization,
                err_discretization_extrapolated: level.err_discretization_extrapolated,
                evaluations: 1,
                ..Row::default()
            };
            let t0 = std::time::Instant::now();
            match level.solve(strategy::Method::constant(eps)) {
                Ok(solved) => {
                    row.seconds_search = t0.elapsed().as_secs_f64();
                    let t1 = std::time::Instant::now();
                    metrics_into(cfg, &solved, k_once, &mut row);
                    row.seconds_metrics = t1.elapsed().as_secs_f64();
                }
                Err(e) => row.note = e.to_string(),
            }
            row
        })
        .collect()
}

/// The knob search of one row (lagrange: its one solve), recording the knob and the match;
/// with the next level's start.
fn solve_row(
    cfg: &SolverCostConfig,
    level: &Level,
    s: &'static Strategy,
    acc: Accuracy,
    start: Option<search::Start>,
    row: &mut Row,
) -> Result<(cases::Solved, Option<search::Start>)> {
    if acc == Accuracy::Exact {
        row.matched = true;
        row.evaluations = 1;
        return Ok((level.solve(strategy::Method::lagrange())?, None));
    }
    let delta = cfg.penetration_rel * level.scale;
    let aug_eps = level.aug_eps;
    if acc == Accuracy::Penetration && std::ptr::eq(s, &strategy::barrier::STRATEGY) {
        // The barrier keeps every gap open: no penetration to match; d̂ = δ.
        let (m, knob, value) = search::method_at(s, level, aug_eps, cfg.penetration_rel)?;
        (row.knob, row.knob_rel, row.knob_value) =
            (knob.into(), Some(cfg.penetration_rel), Some(value));
        row.target = Some(delta);
        row.evaluations = 1;
        row.note = "barrier: no penetration to match (run at d̂ = δ)".into();
        let solved = level.solve(m)?;
        row.achieved = Some(solved.sol.max_penetration);
        return Ok((solved, None));
    }
    let target = match acc {
        Accuracy::Penetration => delta,
        _ => level.err_discretization,
    };
    let start = start.unwrap_or(search::Start {
        rel: match s.knob {
            Knob::Eps => 1e3,
            Knob::Factor => 10.0,
            _ => match acc {
                Accuracy::Penetration => cfg.penetration_rel,
                _ => 1e-3,
            },
        },
        slope: None,
    });
    let found = search::find(s, level, aug_eps, acc, target, start, cfg.match_tol)?;
    let next = search::Start {
        rel: found.rel,
        slope: found.slope,
    };
    row.knob = found.knob.into();
    row.knob_rel = Some(found.rel);
    row.knob_value = Some(found.value);
    row.target = Some(target);
    row.achieved = Some(found.achieved);
    row.matched = found.matched;
    row.evaluations = found.evaluations;
    if !found.matched {
        // The rule's own warnings say why, where it has any (e.g. spring's clipped penalties).
        let why = match (&found.failure, found.solved.sol.warnings.first()) {
            _ if found.range_end => format!(
                " (at the end of the {} range: the measure does not reach the target there)",
                found.knob
            ),
            (Some(e), _) => format!(" (then a solve failed: {e})"),
            (None, Some(w)) => format!(" ({w})"),
            (None, None) => String::new(),
        };
        row.note = format!(
            "not matched in {} solves: {:.3e} against {target:.3e}{why}",
            found.evaluations, found.achieved
        );
    }
    Ok((found.solved, Some(next)))
}

fn fill_solver_metrics(row: &mut Row, c: &metrics::solver::SolverMetrics) {
    row.cond2_jacobi = c.cond2_jacobi.map(|r| r.cond2);
    let to_err = |p: &metrics::solver::KrylovPair| {
        let r = p.to_err();
        (r.map(|r| r.iterations), r.map(|r| r.converged))
    };
    (
        row.pcg_iters_jacobi_to_err,
        row.pcg_iters_jacobi_to_err_converged,
    ) = to_err(&c.pcg_jacobi);
    (row.pcg_iters_ic0_to_err, row.pcg_iters_ic0_to_err_converged) = to_err(&c.pcg_ic0);
    (
        row.pcg_iters_amg_scalar_to_err,
        row.pcg_iters_amg_scalar_to_err_converged,
    ) = to_err(&c.pcg_amg_scalar);
    (
        row.pcg_iters_amg_nodal_to_err,
        row.pcg_iters_amg_nodal_to_err_converged,
    ) = to_err(&c.pcg_amg_nodal);
    (row.minres_iters_to_err, row.minres_iters_to_err_converged) = to_err(&c.minres);
    row.seconds_pcg_jacobi = c.pcg_jacobi.to_err.map(|s| s.seconds);
    row.seconds_pcg_ic0 = c.pcg_ic0.to_err.map(|s| s.seconds);
    row.seconds_minres = c.minres.to_err.map(|s| s.seconds);
    if let Some(r) = c.pcg_jacobi.residual() {
        row.pcg_iters_jacobi = Some(r.iterations);
        row.pcg_converged_jacobi = Some(r.converged);
    }
    row.pcg_cond_eff_jacobi = c.pcg_jacobi.effective_cond();
    row.pcg_err_u_at_stop_jacobi = c.pcg_jacobi.err_u_at_stop();
    if let Some(r) = c.pcg_ic0.residual() {
        row.pcg_iters_ic0 = Some(r.iterations);
        row.pcg_converged_ic0 = Some(r.converged);
    }
    row.pcg_cond_eff_ic0 = c.pcg_ic0.effective_cond();
    row.pcg_err_u_at_stop_ic0 = c.pcg_ic0.err_u_at_stop();
    row.ic0_shift = c.ic0_shift;
    if let Some(r) = c.minres.residual() {
        row.minres_iters = Some(r.iterations);
        row.minres_converged = Some(r.converged);
    }
    row.minres_err_u_at_stop = c.minres.err_u_at_stop();
    row.forward_err_u = c.forward_err_u;
    row.forward_err_force = c.forward_err_force;
    row.backward_err = c.backward_err;
    row.seconds_direct = c.seconds_direct;
    if !c.unavailable.is_empty() && row.note.is_empty() {
        row.note = c.unavailable.join("; ");
    }
}

/// The `solver_cost` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Families, comma-separated (default: all but hertz-two-body and hertz-axi).
    #[arg(long, value_delimiter = ',', value_enum)]
    families: Option<Vec<Family>>,
    /// Mesh levels per family (h halving), 2–8.
    #[arg(long, default_value_t = 5)]
    levels: usize,
    /// Coarsest Hertz element size at the contact, over a [default: 0.5]; needs a Hertz
    /// family.
    #[arg(long)]
    hertz_h0: Option<f64>,
    /// Coarsest membrane side (level l: (side0+1)·2^l − 1 interior nodes per direction)
    /// [default: 7]; needs the membrane family.
    #[arg(long)]
    membrane_side0: Option<usize>,
    /// Coarsest beam element count (level l: el0·2^l) [default: 8]; needs the beam family.
    #[arg(long)]
    beam_el0: Option<usize>,
    /// Coarsest hertz-3d element size at the contact, over a [default: 4]; needs hertz-3d.
    /// Level l has h/a = h0/2^l: 42, 120, 260, 798, 2 520, 11 040, 55 458, 320 352 DOFs at
    /// h/a = 4 … 1/32 (h/a ≥ 1 does not resolve the contact zone; a direct solve takes
    /// ≈ 1 s at 11 040 DOFs, growing faster than N²: `--sphere-h0 2` runs to 11 040 DOFs in
    /// ≈ 5 min on 2 cores).
    #[arg(long)]
    sphere_h0: Option<f64>,
    /// Rules, comma-separated (default: every rule but optimal; lagrange always runs).
    #[arg(long, value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// δ of the penetration rows over the family's length scale.
    #[arg(long, default_value_t = 1e-3)]
    penetration_rel: f64,
    /// τ of the residual-stopped Krylov runs (‖r‖ ≤ τ‖b‖ from x₀ = 0), reported beside the
    /// error of u at their stop.
    #[arg(long, default_value_t = metrics::solver::DEFAULT_TOL)]
    krylov_tol: f64,
    /// The relative error of u every reported iteration count is taken to
    /// (‖u_k − u*‖∞ ≤ e‖u*‖∞, u* the refined direct solution of the same system).
    #[arg(long, default_value_t = metrics::solver::DEFAULT_ERR_TARGET)]
    krylov_err: f64,
    /// Relative accuracy asked of each cond₂.
    #[arg(long, default_value_t = 1e-6)]
    cond_tol: f64,
    /// The level of the ε map (constant at ε = 10^0 … 10^10 · the family's stiffness
    /// scale), clamped to the finest.
    #[arg(long, default_value_t = 2)]
    eps_map_level: usize,
}

/// The study as the shared entry runs it ([`crate::study::shape::main`]).
pub struct SolverCost;

impl Study for SolverCost {
    const NAME: &'static str = "solver_cost";
    const ABOUT: &'static str =
        "What each penalty rule costs a direct and an iterative solver at equal accuracy, over mesh levels";
    const PROGRESS: &'static str = "solver_cost (levels)";
    const DEFAULT_OUT: &'static str = "results/solver_cost";
    const RESUMABLE: bool = true;
    type Flags = Flags;
    type Config = SolverCostConfig;
    type Record = Vec<Row>;

    fn after_help() -> String {
        "Writes solver_cost.csv, solver_cost.json (rows with provenance), summary.json (slopes) \
         and the figures; each finished level is kept in OUT/levels/ until then (--resume \
         reuses them after an interruption).\nExit status: 0 ok, 2 bad input."
            .into()
    }

    fn config(f: &Flags) -> Result<SolverCostConfig> {
        let d = SolverCostConfig::default();
        let families = f.families.clone().unwrap_or(d.families);
        // A family's own flag without the family would be ignored: refused instead.
        let force_controlled: Vec<Family> = Family::ALL
            .into_iter()
            .filter(|x| x.hertz_case().is_some())
            .collect();
        for (flag, given, users) in [
            ("--hertz-h0", f.hertz_h0.is_some(), &force_controlled[..]),
            (
                "--membrane-side0",
                f.membrane_side0.is_some(),
                &[Family::Membrane],
            ),
            ("--beam-el0", f.beam_el0.is_some(), &[Family::Beam]),
            ("--sphere-h0", f.sphere_h0.is_some(), &[Family::Hertz3d]),
        ] {
            if given && !families.iter().any(|x| users.contains(x)) {
                let names: Vec<&str> = users.iter().map(|x| x.name()).collect();
                return Err(Error::unsupported(
                    flag,
                    format!("the family {} among --families", names.join(" or ")),
                ));
            }
        }
        let cfg = SolverCostConfig {
            families,
            levels: f.levels,
            hertz_h0: f.hertz_h0.unwrap_or(d.hertz_h0),
            membrane_side0: f.membrane_side0.unwrap_or(d.membrane_side0),
            beam_el0: f.beam_el0.unwrap_or(d.beam_el0),
            sphere_h0: f.sphere_h0.unwrap_or(d.sphere_h0),
            methods: match &f.methods {
                Some(names) => registry::lookup_all(names).map_err(|e| e.for_flag("--methods"))?,
                None => d.methods,
            },
            penetration_rel: f.penetration_rel,
            match_tol: d.match_tol,
            krylov_tol: f.krylov_tol,
            krylov_err: f.krylov_err,
            cond_tol: f.cond_tol,
            eps_map_level: f.eps_map_level,
        };
        cfg.validate()?;
        Ok(cfg)
    }

    /// Runs with the checkpoints of `OUT/levels/` (reused with `--resume`).
    fn run(cfg: &SolverCostConfig, ctx: &RunContext) -> Result<Vec<Row>> {
        let checkpoints = Checkpoints::new(ctx.out, CHECKPOINTS, cfg, ctx.resume)?;
        run(cfg, ctx.progress, Some(&checkpoints))
    }

    fn save(
        out: &Path,
        cfg: &SolverCostConfig,
        rows: &Vec<Row>,
        provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        crate::study::shape::save_rows(
            out,
            provenance,
            serde_json::json!({ "config": cfg }),
            rows,
        )?;
        crate::provenance::write_json(
            &out.join("summary.json"),
            &serde_json::json!({ "slopes": slopes(rows) }),
        )?;
        Checkpoints::remove_in(out, CHECKPOINTS)
    }

    fn load(out: &Path) -> Result<Vec<Row>> {
        crate::study::shape::load_rows(out, Self::NAME)
    }

    fn figures(rows: &Vec<Row>) -> Result<Vec<Drawing>> {
        figures::drawings(rows)
    }

    fn report(rows: &Vec<Row>) -> String {
        report::text(rows)
    }
}
