//! The contact solve engine at scale: full-contact membranes from 10⁴ to 10⁶ DOFs.
//!
//! Scene: [`scalable::membrane_scene`] with one `lower` constraint per node — the 5-point membrane
//! under uniform load on a paraboloid obstacle, in contact over part of the domain. For each
//! size and method ([`ScaleConfig`] knobs, relative to the scene's scales) one complete
//! `strategy::solve` is timed (wall clock, one thread, factorizations included), then the
//! certified cond₂ of the final system matrix (timed separately); cond₂(K) is computed once
//! per size. A row records the solver statistics (active-set iterations, numeric
//! factorizations, CG iterations, `converged`), the wall times, the peak resident memory of
//! the solve and its metrics, and the cond₂ brackets.
//!
//! Peak memory: Linux only — the process's high-water mark (`VmHWM`) is reset before each
//! method by writing `5` to `/proc/self/clear_refs` and read from `/proc/self/status` after
//! it; the scene itself (K, q, constraints) and K's cond₂ are alive during every method and
//! are included. No crate exposes a resettable peak, hence these two small readers.
//!
//! [`EngineScale`] is the study as the shared entry ([`crate::study::shape::main`]) runs it:
//! `rows.csv`, `rows.json`, `manifest.json` (provenance) and the figure `engine_scale`.
//!
//! Use it to measure the engine against the factorization floor (README, Performance):
//! `cargo run --release --bin engine_scale`.

pub mod figures;
pub mod report;

use crate::conditioning;
use crate::error::{Error, Result};
use crate::metrics::{self, MetricSet};
use crate::model::scalable::{self, PerfScene};
use crate::progress::Progress;
use crate::strategy::registry;
use crate::strategy::{self, Knobs, Method, Strategy};
use crate::study::grid::{KnobGrid, Level};
use crate::study::shape::{Drawing, RunContext, Study};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::time::Instant;

/// Methods the study runs (fixed-energy penalties, δ-targeting, exact contact).
pub static SCALE_METHODS: [&Strategy; 4] = [
    &strategy::constant::STRATEGY,
    &strategy::scaled::STRATEGY,
    &strategy::condensed::STRATEGY,
    &strategy::lagrange::STRATEGY,
];

/// The names of [`SCALE_METHODS`].
pub fn scale_method_names() -> Vec<&'static str> {
    SCALE_METHODS.iter().map(|s| s.name).collect()
}

/// Configuration.
#[derive(Clone, Debug, Serialize)]
pub struct ScaleConfig {
    /// Requested DOF counts (the membrane side is `round(√size)`).
    pub sizes: Vec<usize>,
    /// Methods, from [`SCALE_METHODS`] (saved by name).
    #[serde(serialize_with = "registry::serialize_names")]
    pub methods: Vec<&'static Strategy>,
    /// Compute the certified cond₂ of K and of each system.
    pub cond: bool,
    /// `constant`: ε / max_c K\[d_c, d_c\].
    pub eps_rel: f64,
    /// `scaled`: ε_c = factor · K\[d_c, d_c\].
    pub factor: f64,
    /// `condensed`: δ / max_c |u0\[d_c\]|.
    pub delta_rel: f64,
}

impl Default for ScaleConfig {
    fn default() -> Self {
        ScaleConfig {
            sizes: vec![10_000, 100_000],
            methods: SCALE_METHODS.to_vec(),
            cond: true,
            eps_rel: 1e2,
            factor: 1e2,
            delta_rel: 1e-3,
        }
    }
}

impl ScaleConfig {
    /// Rejects unknown methods, empty lists and non-positive knobs.
    pub fn validate(&self) -> Result<()> {
        Error::distinct("--sizes", &self.sizes)?;
        Error::distinct("--methods", self.methods.iter().map(|s| s.name))?;
        if self.sizes.is_empty() {
            return Err(Error::none_given("sizes", " (each ≥ 9)"));
        }
        if let Some(&s) = self.sizes.iter().find(|&&s| !(9..=4_000_000).contains(&s)) {
            return Err(Error::out_of_range("--sizes entry", s, "in 9..=4000000"));
        }
        if let Some(m) = self
            .methods
            .iter()
            .find(|m| !SCALE_METHODS.iter().any(|s| std::ptr::eq(*s, **m)))
        {
            return Err(Error::unknown("method", m.name, &scale_method_names(), ""));
        }
        for (name, v) in [
            ("eps_rel", self.eps_rel),
            ("factor", self.factor),
            ("delta_rel", self.delta_rel),
        ] {
            Error::positive(name, v)?;
        }
        Ok(())
    }
}

/// One method on one scene.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct ScaleRow {
    /// DOFs.
    pub n: usize,
    /// Contact constraints.
    pub m: usize,
    /// Method name.
    pub method: String,
    /// The knob's absolute value (ε, factor or δ; 0 for lagrange).
    pub knob: f64,
    /// Active constraints at the end.
    pub active: usize,
    /// Max penetration of the returned u (units of u).
    pub max_penetration: f64,
    /// Active-set iterations.
    pub iterations: usize,
    /// Numeric factorizations (K's included).
    pub factorizations: usize,
    /// CG iterations (elimination route's reuse of factors).
    pub cg_iterations: usize,
    /// The solver reached its own solution.
    pub converged: bool,
    /// Wall time of the solve (s).
    pub seconds_solve: f64,
    /// Wall time of the system's cond₂ (s); None without cond.
    pub seconds_cond_system: Option<f64>,
    /// Wall time of K's cond₂ at this size (s, shared by the size's rows).
    pub seconds_cond_k: Option<f64>,
    /// Peak resident memory during the solve and its metrics (MB); None off Linux.
    pub peak_rss_mb: Option<f64>,
    /// cond₂(K) and its certified bracket.
    pub cond2_k: Option<f64>,
    /// Lower end of the cond₂(K) bracket.
    pub cond2_k_lo: Option<f64>,
    /// Upper end of the cond₂(K) bracket.
    pub cond2_k_hi: Option<f64>,
    /// cond₂ of the final system matrix.
    pub cond2_system: Option<f64>,
    /// Lower end of its bracket (sparse route).
    pub cond2_system_lo: Option<f64>,
    /// Upper end of its bracket (sparse route).
    pub cond2_system_hi: Option<f64>,
    /// Route of the system's cond₂, or why it was not computed.
    pub cond_route_system: String,
    /// Every cond₂ bracket of the row is proven (empty where none was taken).
    #[serde(default)]
    pub cond2_bounds_proven: Option<bool>,
    /// Every cond₂ value of the row is proven within the accuracy contract
    /// `max(1e-12, 4·ε_mach·cond₂)` ([`crate::conditioning::CondReport::within_contract`]).
    #[serde(default)]
    pub cond2_within_contract: Option<bool>,
}

/// Resets the process's peak resident memory (Linux; false elsewhere).
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// The process's peak resident memory since the last reset, in MB (Linux `VmHWM`).
fn peak_rss_mb() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The method `s` ([`SCALE_METHODS`]) with its knob from `cfg` (ε and δ relative to the
/// scene's scales; [`KnobGrid::points`] at one level each), and the knob's value.
fn method(s: &'static Strategy, scene: &PerfScene, cfg: &ScaleConfig) -> Result<(Method, f64)> {
    let grid = KnobGrid {
        eps: vec![Level::relative(cfg.eps_rel, scene.k_scale)],
        factors: vec![Level::absolute(cfg.factor)],
        deltas: vec![Level::relative(cfg.delta_rel, scene.scale)],
        exact: Some(Level::absolute(0.0)),
        ..KnobGrid::default()
    };
    match grid.points(&[s]).first() {
        Some(p) => Ok((p.method, p.level.value)),
        // No level for its knob: the error of the method built without it.
        None => Method::new(s, Knobs::NONE).map(|m| (m, 0.0)),
    }
}

/// Runs the study; one [`Progress::step`] per finished solve.
pub fn run(cfg: &ScaleConfig, progress: &Progress) -> Result<Vec<ScaleRow>> {
    cfg.validate()?;
    progress.set_total(cfg.sizes.len() * cfg.methods.len());
    let mut rows = Vec::new();
    for &size in &cfg.sizes {
        let scene = scalable::membrane_scene(size, usize::MAX)?;
        let p = &scene.problem;
        let (k_cond, seconds_cond_k) = if cfg.cond {
            let t = Instant::now();
            let c = conditioning::cond2(&p.k)?;
            (Some(c), Some(t.elapsed().as_secs_f64()))
        } else {
            (None, None)
        };
        let bounds = |c: &conditioning::CondReport| {
            c.certificate
                .map(|cert| cert.cond2_bounds())
                .map_or((None, None), |(lo, hi)| (Some(lo), Some(hi)))
        };
        let (k_lo, k_hi) = k_cond.as_ref().map_or((None, None), bounds);
        for &s in &cfg.methods {
            let (m, knob) = method(s, &scene, cfg)?;
            let tracked = reset_peak_rss();
            let t = Instant::now();
            let sol = strategy::solve(p, m)?;
            let seconds_solve = t.elapsed().as_secs_f64();
            let (sys, seconds_cond_system, route) = if cfg.cond {
                let t = Instant::now();
                let met = metrics::compute_with_k(
                    p,
                    &sol,
                    MetricSet {
                        cond: true,
                        det: false,
                        cond_tol: None,
                    },
                    None,
                    None,
                    None,
                )?;
                let route = match (&met.cond2_system, met.unavailable.first()) {
                    (Some(c), _) => c.route.name().to_string(),
                    (None, Some(why)) => format!("not computed: {why}"),
                    (None, None) => "not computed".to_string(),
                };
                (met.cond2_system, Some(t.elapsed().as_secs_f64()), route)
            } else {
                (None, None, "not requested".to_string())
            };
            let (s_lo, s_hi) = sys.as_ref().map_or((None, None), bounds);
            let (cond2_bounds_proven, cond2_within_contract) =
                crate::conditioning::CondReport::flags([k_cond.as_ref(), sys.as_ref()]);
            let row = ScaleRow {
                n: p.n(),
                m: p.m(),
                method: s.name.to_string(),
                knob,
                active: sol.stats.active_set_sizes.last().copied().unwrap_or(0),
                max_penetration: sol.max_penetration,
                iterations: sol.stats.iterations,
                factorizations: sol.stats.factorizations,
                cg_iterations: sol.stats.cg_iterations,
                converged: sol.stats.converged,
                seconds_solve,
                seconds_cond_system,
                seconds_cond_k,
                peak_rss_mb: if tracked { peak_rss_mb() } else { None },
                cond2_k: k_cond.map(|c| c.cond2),
                cond2_k_lo: k_lo,
                cond2_k_hi: k_hi,
                cond2_system: sys.map(|c| c.cond2),
                cond2_system_lo: s_lo,
                cond2_system_hi: s_hi,
                cond_route_system: route,
                cond2_bounds_proven,
                cond2_within_contract,
            };
            progress.step(&format!(
                "N = {:>8} {:<10} {:>3} iterations {:>3} factorizations {:>4} CG  solve {:.2} s",
                row.n,
                row.method,
                row.iterations,
                row.factorizations,
                row.cg_iterations,
                row.seconds_solve
            ));
            rows.push(row);
        }
    }
    progress.finish();
    Ok(rows)
}

/// The `engine_scale` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Requested DOF counts (membrane side = round(√size)).
    #[arg(long, value_delimiter = ',', default_value = "10000,100000")]
    sizes: Vec<usize>,
    /// Methods (default: constant, scaled, condensed, lagrange).
    #[arg(long, value_parser = registry::method_parser_of(&SCALE_METHODS), value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Skip the cond₂ metrics.
    #[arg(long)]
    no_cond: bool,
}

/// The study as the shared entry runs it.
pub struct EngineScale;

impl Study for EngineScale {
    const NAME: &'static str = "engine_scale";
    const ABOUT: &'static str = "The contact solve engine at 1e4-1e6 DOFs";
    const PROGRESS: &'static str = "engine_scale (solves)";
    const DEFAULT_OUT: &'static str = "results/engine_scale";
    const FIGURES_DIR: &'static str = "";
    type Flags = Flags;
    type Config = ScaleConfig;
    type Record = Vec<ScaleRow>;

    fn config(f: &Flags) -> Result<ScaleConfig> {
        let cfg = ScaleConfig {
            sizes: f.sizes.clone(),
            methods: match &f.methods {
                Some(names) => registry::lookup_all(names)?,
                None => SCALE_METHODS.to_vec(),
            },
            cond: !f.no_cond,
            ..Default::default()
        };
        cfg.validate()?;
        Ok(cfg)
    }

    fn run(cfg: &ScaleConfig, ctx: &RunContext) -> Result<Vec<ScaleRow>> {
        run(cfg, ctx.progress)
    }

    /// `rows.csv`, `rows.json` and `manifest.json`.
    fn save(
        out: &Path,
        cfg: &ScaleConfig,
        rows: &Vec<ScaleRow>,
        provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        use crate::provenance;
        std::fs::create_dir_all(out).map_err(|e| Error::io(out.display(), e))?;
        provenance::write_csv(&out.join("rows.csv"), rows)?;
        provenance::write_json(&out.join("rows.json"), rows)?;
        let manifest = provenance.record(serde_json::json!({
            "config": cfg,
            "threads": 1,
            "timing": "wall time (std::time::Instant) of one strategy::solve, release build",
        }));
        provenance::write_json(&out.join("manifest.json"), &manifest)
    }

    fn load(out: &Path) -> Result<Vec<ScaleRow>> {
        crate::provenance::read_json(&out.join("rows.json"))
    }

    fn figures(rows: &Vec<ScaleRow>) -> Result<Vec<Drawing>> {
        Ok(figures::drawings(rows))
    }

    fn report(rows: &Vec<ScaleRow>) -> String {
        report::table(rows)
    }
}
