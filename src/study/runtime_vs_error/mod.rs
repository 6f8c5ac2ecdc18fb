//! Run time against error: every strategy's time to solution against its error as its knob
//! varies, on beam and membrane scenes of increasing size (`runtime_vs_error`).
//!
//! For a strategy with knob κ (ε for `constant`, the factor for `scaled`, δ for
//! `spring`/`paper`/`condensed`, the tolerance for `augmented`) and a scene of N DOFs, a row
//! records the median wall time of `repeats` complete solves (`strategy::solve` from scratch:
//! factorizations included) and the errors
//!
//! * `max_penetration` = max_c p_c (absolute, and relative to the displacement scale
//!   max_c |u0\[d_c\]|), and
//! * `error_vs_ref` = ‖u − u_ref‖₂ / ‖u_ref‖₂ with u_ref the exact contact solution
//!   (`lagrange`; where lagrange is refused or over budget, the augmented Lagrangian driven to
//!   a penetration of 1e-12 × scale, and the row says which).
//!
//! Scenes ([`crate::model::scalable`]) are built directly from the model code so that
//! N can reach 10⁶: a cantilever on a Winkler foundation (bounded condition number at any
//! length) pressed by a wavy load onto a flat rigid surface, and the 5-point membrane pressed
//! onto a paraboloid obstacle sampled on a sub-grid (at most `max_constraints` contact DOFs, so
//! that `condensed`'s N×m block solve stays in memory).
//!
//! Budget: a solve cannot be interrupted, so a method is skipped (a row with the reason, never
//! an abort) when its time at the previous size, extrapolated as `t·(N/N_prev)^p`, exceeds
//! the per-solve budget, after it has exceeded the budget once, or when `condensed`'s N×m block
//! would exceed the memory limit. The exponent p is the slope measured between the two
//! previous sizes, clamped to [1, [`MAX_GROWTH`]] (1.5 until two sizes with solves of at least
//! 1 ms exist): sparse factorizations of these scenes grow like N^1.1–1.3, so a fixed 1.5
//! skipped 10⁶-DOF membranes that take 10 s. The cap 1.5 is nested dissection's factorization
//! cost on 2-D grids (O(N^{3/2}) flops; the families here are 1-D and 2-D); slopes above it
//! come from small sizes that still fit in cache (membrane `condensed`: 10⁴→10⁵ 1.55,
//! 10⁵→10⁶ 1.12), and an underestimate costs at most one solve over budget, after which the
//! method stops. Repeats of a point stop early once it has used a third of
//! the budget (`seconds_all` lists the repeats that ran). Errors of a strategy are rows with
//! status `error`.

pub mod cli;
pub mod figures;
pub mod record;
pub mod report;

pub use cli::RuntimeVsError;

use crate::error::{Error, Result};
use crate::generate::Family;
use crate::model::scalable::{self, PerfScene};
use crate::progress::Progress;
use crate::strategy::{self, registry, Method};
use crate::study::grid::{Augmented, KnobGrid, Level};
use serde::Serialize;
use std::collections::HashMap;
use std::time::Instant;

/// Knob values, relative to the scene's scales.
#[derive(Clone, Debug, Serialize)]
pub struct Knobs {
    /// `constant`: ε / max_c K\[d_c,d_c\].
    pub eps_rel: Vec<f64>,
    /// `scaled`: factors.
    pub factors: Vec<f64>,
    /// `spring`, `paper`, `condensed`: δ / scale.
    pub deltas_rel: Vec<f64>,
    /// `augmented`: tolerance / scale (ε = max_c K\[d_c,d_c\]).
    pub tols_rel: Vec<f64>,
}

impl Knobs {
    /// The full grids.
    pub fn full() -> Self {
        Knobs {
            eps_rel: vec![1e-2, 1.0, 1e2, 1e4, 1e6, 1e8],
            factors: vec![1e-2, 1.0, 1e2, 1e4, 1e6, 1e8],
            deltas_rel: vec![0.3, 1e-1, 1e-2, 1e-3, 1e-4, 1e-6],
            tols_rel: vec![1e-1, 1e-2, 1e-4, 1e-6, 1e-8],
        }
    }
    /// Three values each (for `--smoke`).
    pub fn smoke() -> Self {
        Knobs {
            eps_rel: vec![1e-2, 1e2, 1e6],
            factors: vec![1e-2, 1e2, 1e6],
            deltas_rel: vec![1e-1, 1e-3, 1e-6],
            tols_rel: vec![1e-2, 1e-5, 1e-8],
        }
    }
}

/// The families the study runs (scenes of any size: [`scalable`]).
pub const FAMILIES: [Family; 2] = [Family::Beam, Family::Membrane];

/// The error for a family the study does not run.
pub fn unknown_family(name: &str) -> Error {
    Error::unknown("family", name, &FAMILIES.map(Family::name), "")
}

/// The families named, each one of [`FAMILIES`] (names trimmed).
pub fn parse_families<S: AsRef<str>>(names: &[S]) -> Result<Vec<Family>> {
    crate::generate::parse_families(names, &FAMILIES, "")
}

/// Configuration of a run.
#[derive(Clone, Debug, Serialize)]
pub struct PerfConfig {
    /// Families (`beam`, `membrane`).
    pub families: Vec<Family>,
    /// Requested DOF counts.
    pub sizes: Vec<usize>,
    /// Methods to time (saved by name).
    #[serde(serialize_with = "registry::serialize_names")]
    pub methods: Vec<&'static strategy::Strategy>,
    /// Timed repeats per point (the median is reported).
    pub repeats: usize,
    /// Per-solve budget in seconds.
    pub budget_seconds: f64,
    /// Maximum number of contact constraints per scene.
    pub max_constraints: usize,
    /// Memory limit for `condensed`'s N×m block (bytes).
    pub memory_limit_bytes: f64,
    /// Knob grids.
    pub knobs: Knobs,
}

impl PerfConfig {
    /// Checks the configuration; errors name the offending value and the valid range.
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--families", self.families.iter().map(|f| f.name()))?;
        Error::distinct("--methods", self.methods.iter().map(|s| s.name))?;
        Error::distinct("--sizes", &self.sizes)?;
        if self.families.is_empty() {
            return Err(Error::none_given("families", " (valid: beam, membrane)"));
        }
        if let Some(f) = self.families.iter().find(|f| !FAMILIES.contains(f)) {
            return Err(unknown_family(f.name()));
        }
        if self.sizes.is_empty() || self.sizes.iter().any(|&s| !(9..=4_000_000).contains(&s)) {
            return Err(Error::out_of_range(
                "sizes",
                format!("{:?}", self.sizes),
                "at least one, each in 9..=4000000",
            ));
        }
        if self.repeats == 0 || self.repeats > 100 {
            return Err(Error::out_of_range("repeats", self.repeats, "in 1..=100"));
        }
        if !(self.budget_seconds.is_finite() && self.budget_seconds > 0.0) {
            return Err(Error::out_of_range(
                "budget",
                self.budget_seconds,
                "a finite number of seconds > 0",
            ));
        }
        if self.max_constraints == 0 {
            return Err(Error::out_of_range("max constraints", 0, "≥ 1"));
        }
        if !(self.memory_limit_bytes.is_finite() && self.memory_limit_bytes > 0.0) {
            return Err(Error::out_of_range(
                "memory limit (GB)",
                self.memory_limit_bytes / 1e9,
                "a finite number > 0",
            ));
        }
        Ok(())
    }

    /// The default run (sizes 10²…10⁶, every method, 3 repeats, [`Knobs::full`]) or, with
    /// `smoke`, the quick one (sizes 100 and 1000, 1 repeat, [`Knobs::smoke`]); beam and
    /// membrane, 30 s budget per solve, ≤ 400 constraints, 4 GB for condensed's N×m block.
    pub fn preset(smoke: bool) -> PerfConfig {
        PerfConfig {
            families: FAMILIES.to_vec(),
            sizes: if smoke {
                vec![100, 1000]
            } else {
                vec![100, 1_000, 10_000, 100_000, 1_000_000]
            },
            // `optimal` is dense (N ≤ its affordability limit): not a run-time study's method;
            // the beam family has bilateral ties.
            methods: registry::BUILT_IN
                .iter()
                .filter(|s| !std::ptr::eq(**s, &strategy::optimal::STRATEGY) && s.bilateral)
                .copied()
                .collect(),
            repeats: if smoke { 1 } else { 3 },
            budget_seconds: 30.0,
            max_constraints: 400,
            memory_limit_bytes: 4e9,
            knobs: if smoke { Knobs::smoke() } else { Knobs::full() },
        }
    }
}

/// One (scene, method, knob) point.
#[derive(Clone, Debug, Serialize, serde::Deserialize)]
pub struct PerfRow {
    /// Family.
    pub family: String,
    /// Requested size.
    pub size: usize,
    /// N.
    pub n: usize,
    /// m.
    pub m: usize,
    /// Method.
    pub method: String,
    /// Knob name (`eps`, `factor`, `delta`, `tol`, `-`).
    pub knob: String,
    /// Knob value (absolute).
    pub value: f64,
    /// Knob value relative to the scene's scale.
    pub value_rel: f64,
    /// `ok`, `error` or `skipped`.
    pub status: String,
    /// Why skipped / the error message.
    pub reason: String,
    /// Median wall time of the repeats (s).
    pub seconds: Option<f64>,
    /// All repeat times (s).
    pub seconds_all: Vec<f64>,
    /// Max penetration.
    pub max_penetration: Option<f64>,
    /// Max penetration / displacement scale.
    pub penetration_rel: Option<f64>,
    /// `‖u − u_ref‖/‖u_ref‖`.
    pub error_vs_ref: Option<f64>,
    /// Which reference: `lagrange`, `augmented`, or `none`.
    pub reference: String,
    /// Outer iterations.
    pub iterations: Option<usize>,
    /// Factorizations.
    pub factorizations: Option<usize>,
    /// Linear solves (right-hand sides).
    pub linear_solves: Option<usize>,
    /// The strategy converged (`Stats::converged`); absent in files written before it existed.
    #[serde(default)]
    pub converged: Option<bool>,
    /// Warnings of the solve.
    pub warnings: Vec<String>,
}

/// The knob grid of a scene with ε scale `k_scale` (max_c K_dd) and displacement scale
/// `scale`: each relative value times its knob's scale, `augmented` at ε = `k_scale`, the
/// exact methods once.
fn knob_grid(cfg: &PerfConfig, k_scale: f64, scale: f64) -> KnobGrid {
    let k = &cfg.knobs;
    KnobGrid {
        eps: Level::relatives(&k.eps_rel, k_scale),
        factors: Level::relatives(&k.factors, 1.0),
        deltas: Level::relatives(&k.deltas_rel, scale),
        tols: Level::relatives(&k.tols_rel, scale),
        augmented: vec![Augmented {
            eps: k_scale,
            adaptive: false,
            name: "tol",
        }],
        exact: Some(Level::relative(0.0, 0.0)),
    }
}

/// Number of points [`jobs`] gives per scene.
pub fn jobs_per_scene(cfg: &PerfConfig) -> usize {
    knob_grid(cfg, 1.0, 1.0).count(&cfg.methods)
}

/// The jobs `(method, knob name, absolute value, relative value)` of a scene: each relative
/// value times the scene's scale of its knob's quantity ([`KnobGrid::points`]; `augmented` at
/// ε = max_c K_dd); the exact methods once, knob `-`.
pub fn jobs(scene: &PerfScene, cfg: &PerfConfig) -> Vec<(Method, &'static str, f64, f64)> {
    let grid = knob_grid(cfg, scene.k_scale, scene.scale);
    // Knob values are validated with the config (finite, > 0).
    grid.points(&cfg.methods)
        .into_iter()
        .map(|p| {
            let knob = if p.knob.is_empty() { "-" } else { p.knob };
            (p.method, knob, p.level.value, p.level.rel.unwrap_or(0.0))
        })
        .collect()
}

/// Budget bookkeeping across sizes: per method, the single-solve time at the two largest sizes
/// seen, and whether the method has exceeded the budget.
#[derive(Clone, Debug, Default)]
pub struct Budget {
    /// (previous, last) solve; previous is `None` until a second size has run.
    last: HashMap<MethodKey, (Option<Timing>, Timing)>,
    exceeded: HashMap<MethodKey, Timing>,
}

/// (family, method).
type MethodKey = (String, String);
/// One solve: (N, seconds).
type Timing = (usize, f64);

/// Growth exponent assumed until two sizes have been measured.
pub const DEFAULT_GROWTH: f64 = 1.5;

/// Largest growth exponent used: sparse Cholesky with nested dissection on a 2-D grid costs
/// O(N^{3/2}) (George 1973); steeper slopes measured between small sizes are cache effects.
pub const MAX_GROWTH: f64 = 1.5;

impl Budget {
    /// The growth exponent of a method's solve time: the slope between its two largest
    /// measured sizes, clamped to [1, [`MAX_GROWTH`]]; [`DEFAULT_GROWTH`] while unknown or
    /// below timer resolution (t < 1 ms).
    pub fn growth(&self, family: &str, method: &str) -> f64 {
        let key = (family.to_string(), method.to_string());
        match self.last.get(&key) {
            Some(&(Some((n0, t0)), (n1, t1))) if n1 > n0 && t0 >= 1e-3 && t1 >= 1e-3 => {
                ((t1 / t0).ln() / (n1 as f64 / n0 as f64).ln()).clamp(1.0, MAX_GROWTH)
            }
            _ => DEFAULT_GROWTH,
        }
    }

    /// `Some(reason)` if `method` should be skipped on a scene of `n` DOFs.
    pub fn skip_reason(&self, family: &str, method: &str, n: usize, budget: f64) -> Option<String> {
        let key = (family.to_string(), method.to_string());
        if let Some(&(n0, t)) = self.exceeded.get(&key) {
            if n >= n0 {
                return Some(format!(
                    "over budget: a solve took {t:.1} s > {budget} s at N = {n0}"
                ));
            }
        }
        if let Some(&(_, (n0, t))) = self.last.get(&key) {
            let p = self.growth(family, method);
            let predicted = t * (n as f64 / n0 as f64).max(1.0).powf(p);
            if predicted > budget {
                return Some(format!(
                    "predicted {predicted:.1} s > budget {budget} s (took {t:.2} s at N = {n0}, scaled as N^{p:.2})"
                ));
            }
        }
        None
    }

    /// Records one solve of `t` seconds on `n` DOFs (per size, the slowest repeat counts).
    pub fn record(&mut self, family: &str, method: &str, n: usize, t: f64, budget: f64) {
        let key = (family.to_string(), method.to_string());
        let e = self.last.entry(key.clone()).or_insert((None, (n, t)));
        if n > e.1 .0 {
            *e = (Some(e.1), (n, t));
        } else if n == e.1 .0 && t > e.1 .1 {
            e.1 .1 = t;
        }
        if t > budget {
            self.exceeded.entry(key).or_insert((n, t));
        }
    }
}

fn relative_error(u: &[f64], r: &[f64]) -> Option<f64> {
    let e = crate::metrics::relative_error(u, r);
    e.is_finite().then_some(e)
}

/// Up to `cfg.repeats` timed solves of `method` (each recorded in `budget`): the times of
/// those that succeeded and the last outcome; stops at the first error or once the repeats
/// have used a third of the budget.
fn timed_repeats(
    scene: &PerfScene,
    method: Method,
    cfg: &PerfConfig,
    budget: &mut Budget,
) -> (Vec<f64>, Option<Result<strategy::Solution>>) {
    let (fam, name, n) = (scene.family.as_str(), method.name(), scene.problem.n());
    let mut times = Vec::new();
    let mut last = None;
    for _ in 0..cfg.repeats {
        let t0 = Instant::now();
        let r = strategy::solve(&scene.problem, method);
        let t = t0.elapsed().as_secs_f64();
        budget.record(fam, name, n, t, cfg.budget_seconds);
        match r {
            Ok(sol) => {
                times.push(t);
                last = Some(Ok(sol));
                if times.iter().sum::<f64>() > cfg.budget_seconds / 3.0 {
                    break;
                }
            }
            Err(e) => {
                last = Some(Err(e));
                break;
            }
        }
    }
    (times, last)
}

/// Runs every job on one scene; one [`Progress::step`] per point.
pub fn run_scene(
    scene: &PerfScene,
    cfg: &PerfConfig,
    budget: &mut Budget,
    progress: &Progress,
) -> Vec<PerfRow> {
    let p = &scene.problem;
    let (n, m) = (p.n(), p.m());
    let fam = scene.family.as_str();
    let mut jobs = jobs(scene, cfg);
    // lagrange first: its solution is the reference.
    jobs.sort_by_key(|j| !j.0.is(&strategy::lagrange::STRATEGY));
    let mut reference: Option<(Vec<f64>, &'static str)> = None;
    let mut rows = Vec::with_capacity(jobs.len() + 1);
    let mut reference_pending = true;
    for (method, knob, value, value_rel) in jobs {
        let name = method.name();
        if reference_pending && !method.is(&strategy::lagrange::STRATEGY) {
            reference_pending = false;
            if reference.is_none() {
                reference = fallback_reference(scene, cfg, budget);
            }
        }
        let mut row = PerfRow {
            family: scene.family.clone(),
            size: scene.size,
            n,
            m,
            method: name.into(),
            knob: knob.into(),
            value,
            value_rel,
            status: "skipped".into(),
            reason: String::new(),
            seconds: None,
            seconds_all: Vec::new(),
            max_penetration: None,
            penetration_rel: None,
            error_vs_ref: None,
            reference: "none".into(),
            iterations: None,
            factorizations: None,
            linear_solves: None,
            converged: None,
            warnings: Vec::new(),
        };
        let mut skip = budget.skip_reason(fam, name, n, cfg.budget_seconds);
        if skip.is_none() && name == strategy::condensed::STRATEGY.name {
            let bytes = 8.0 * n as f64 * m as f64;
            if bytes > cfg.memory_limit_bytes {
                skip = Some(format!(
                    "condensed needs an N×m block of {:.1} GB > memory limit {:.1} GB",
                    bytes / 1e9,
                    cfg.memory_limit_bytes / 1e9
                ));
            }
        }
        if let Some(reason) = skip {
            row.reason = reason;
            progress.step(&format!(
                "{fam} N={n} {name} {knob}={value:.3e}: skipped ({})",
                row.reason
            ));
            rows.push(row);
            continue;
        }
        let (times, last) = timed_repeats(scene, method, cfg, budget);
        match last {
            Some(Ok(sol)) => {
                if method.is(&strategy::lagrange::STRATEGY) {
                    reference = Some((sol.u.clone(), strategy::lagrange::STRATEGY.name));
                }
                row.status = "ok".into();
                row.seconds = crate::stats::median(&times);
                row.seconds_all = times;
                row.max_penetration = Some(sol.max_penetration).filter(|v| v.is_finite());
                row.penetration_rel = row.max_penetration.map(|v| v / scene.scale);
                if let Some((u_ref, which)) = &reference {
                    row.error_vs_ref = relative_error(&sol.u, u_ref);
                    row.reference = (*which).into();
                }
                row.iterations = Some(sol.stats.iterations);
                row.factorizations = Some(sol.stats.factorizations);
                row.linear_solves = Some(sol.stats.linear_solves);
                row.converged = Some(sol.stats.converged);
                row.warnings = sol.warnings;
                if sol.u.iter().any(|v| !v.is_finite()) {
                    row.status = "error".into();
                    row.reason = "solution contains NaN/Inf".into();
                }
            }
            Some(Err(e)) => {
                row.status = "error".into();
                row.reason = e.to_string();
            }
            None => {
                row.reason = "no repeat ran".into();
            }
        }
        progress.step(&format!(
            "{fam} N={n} m={m} {name} {knob}={value:.3e}: {} {}",
            row.status,
            row.seconds.map_or(row.reason.clone(), |s| format!(
                "{s:.4} s, error {:?}",
                row.error_vs_ref
            ))
        ));
        rows.push(row);
    }
    rows
}

/// The augmented Lagrangian driven to a penetration of 1e-12 × scale: the reference where
/// lagrange was not run, was refused or is over budget.
fn fallback_reference(
    scene: &PerfScene,
    cfg: &PerfConfig,
    budget: &Budget,
) -> Option<(Vec<f64>, &'static str)> {
    if budget
        .skip_reason(
            &scene.family,
            strategy::augmented::STRATEGY.name,
            scene.problem.n(),
            cfg.budget_seconds,
        )
        .is_some()
    {
        return None;
    }
    let m = Method::augmented(scene.k_scale, 1e-12 * scene.scale, true);
    strategy::solve(&scene.problem, m)
        .ok()
        .filter(|s| s.u.iter().all(|v| v.is_finite()))
        .map(|s| (s.u, strategy::augmented::STRATEGY.name))
}

/// The full study: every family × size, one progress step per point.
pub fn run(cfg: &PerfConfig, progress: &Progress) -> Result<Vec<PerfRow>> {
    cfg.validate()?;
    let mut rows = Vec::new();
    // (Distinct: `validate` refuses a size given twice.)
    let mut sizes = cfg.sizes.clone();
    sizes.sort_unstable();
    progress.set_total(cfg.families.len() * sizes.len() * jobs_per_scene(cfg));
    for fam in &cfg.families {
        let mut budget = Budget::default();
        for &size in &sizes {
            let t0 = Instant::now();
            let sc = match fam {
                Family::Beam => scalable::beam_scene(size, cfg.max_constraints)?,
                Family::Membrane => scalable::membrane_scene(size, cfg.max_constraints)?,
                other => return Err(unknown_family(other.name())),
            };
            progress.note(&format!(
                "{}: built N = {}, m = {} in {:.2} s",
                fam.name(),
                sc.problem.n(),
                sc.problem.m(),
                t0.elapsed().as_secs_f64()
            ));
            rows.extend(run_scene(&sc, cfg, &mut budget, progress));
        }
    }
    progress.finish();
    Ok(rows)
}
