//! The sweep: every requested strategy over its knob on randomized (or file) scenes, one CSV row
//! per (scene, method, parameter), resumable and shardable, deterministic for any thread count.
//!
//! * Knobs: ε on a log grid for `constant`, factors for `scaled`, δ values for `spring`,
//!   `paper`, `condensed` and `augmented` (tolerance), and one `lagrange` row per scene — the
//!   exact reference that `error_vs_exact` is measured against. δ is absolute (`deltas`) or
//!   relative to the scene's displacement scale (`deltas_rel`: δ = R · max_c |u0\[d_c\]|).
//! * Scenes are numbered globally (families in the given order, then index); shard `K/N` takes
//!   the K-th of N contiguous blocks, so shard outputs concatenate into the unsharded output.
//! * Work units: every scene, and every job of a scene after its lagrange reference, is its own
//!   rayon task (`with_max_len(1)`): rayon's adaptive splitting would otherwise run a few
//!   adjacent jobs as one sequential chunk that no idle thread can steal (the default run's
//!   three `optimal` solves of one scene would then run one after the other).
//! * Rows of a scene are written together and flushed, in scene order (a reorder buffer keeps
//!   the order under rayon), so a killed run loses at most the scenes in flight and `--resume`
//!   completes it without losing or duplicating rows.

pub mod cli;
pub mod figures;
pub mod merge;
pub mod rows;

use crate::conditioning::{self, sparse::RitzStarts, Reuse};
use crate::error::{Error, Result};
use crate::metrics::{self, MetricSet};
use crate::model::generate::{self, Family, GeneratorConfig};
use crate::scene;
use crate::strategy::{self, registry, Knob, Knobs, Method, Prepared};
use crate::system::{Problem, Structure};
use rows::Row;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A log-spaced grid `lo..hi` with `n` points, inclusive.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct LogGrid {
    /// First value (> 0).
    pub lo: f64,
    /// Last value (≥ lo).
    pub hi: f64,
    /// Number of points (≥ 1).
    pub n: usize,
}

impl LogGrid {
    /// Parses `LO:HI:N`.
    pub fn parse(s: &str) -> Result<Self> {
        let parts: Vec<&str> = s.split(':').collect();
        let bad = || {
            Error::input(format!(
                "malformed range '{s}': expected LO:HI:N with 0 < LO ≤ HI and N ≥ 1 (e.g. 1e-2:1e12:15)"
            ))
        };
        if parts.len() != 3 {
            return Err(bad());
        }
        let lo: f64 = parts[0].trim().parse().map_err(|_| bad())?;
        let hi: f64 = parts[1].trim().parse().map_err(|_| bad())?;
        let n: usize = parts[2].trim().parse().map_err(|_| bad())?;
        let g = LogGrid { lo, hi, n };
        g.validate().map_err(|_| bad())?;
        Ok(g)
    }

    /// Checks `0 < lo ≤ hi`, finite, `n ≥ 1` (and `lo = hi` when `n = 1`).
    pub fn validate(&self) -> Result<()> {
        if !(self.lo.is_finite() && self.hi.is_finite() && self.lo > 0.0 && self.lo <= self.hi)
            || self.n == 0
            || (self.n == 1 && self.lo != self.hi)
        {
            return Err(Error::input(format!(
                "bad ε grid {}:{}:{}: need 0 < LO ≤ HI, N ≥ 1",
                self.lo, self.hi, self.n
            )));
        }
        Ok(())
    }

    /// The grid values (inclusive ends, exact end points).
    pub fn values(&self) -> Vec<f64> {
        if self.n == 1 {
            return vec![self.lo];
        }
        let (a, b) = (self.lo.log10(), self.hi.log10());
        (0..self.n)
            .map(|i| {
                if i == 0 {
                    self.lo
                } else if i + 1 == self.n {
                    self.hi
                } else {
                    10f64.powf(a + (b - a) * i as f64 / (self.n - 1) as f64)
                }
            })
            .collect()
    }
}

/// Everything that determines the rows (the manifest stores it; `--resume` checks it).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SweepConfig {
    /// Families to generate (ignored with `scenes_dir`).
    pub families: Vec<String>,
    /// Scenes per family.
    pub count: usize,
    /// Master seed.
    pub seed: u64,
    /// ε grid for `constant`.
    pub eps: LogGrid,
    /// Factors for `scaled`.
    pub factors: Vec<f64>,
    /// Absolute δ values.
    pub deltas: Vec<f64>,
    /// Relative δ values (δ = R · max_c |u0\[d_c\]|).
    pub deltas_rel: Vec<f64>,
    /// Methods to run (`lagrange` always runs: it is the reference).
    pub methods: Vec<String>,
    /// Metrics: any of `cond`, `det` (penetration, error and timing are always recorded).
    pub metrics: Vec<String>,
    /// Generator size ranges.
    pub generator: GeneratorConfig,
    /// Run over every `*.scene.json` in this folder instead of generating.
    pub scenes_dir: Option<PathBuf>,
    /// Families on which `optimal` runs (`file` for scene files); its rows on other families
    /// say so in `warnings`. The default, beam and files, keeps the default sweep under a
    /// minute: one optimisation costs tens to hundreds of dense eigendecompositions.
    pub optimal_families: Vec<String>,
    /// Relative accuracy asked of every cond₂ (`--cond-tol`, in (0, 1)); `None` (the default):
    /// the accuracy contract `max(1e-12, 4·ε_mach·cond₂)`. A looser value stops the Lanczos
    /// runs earlier; the bounds stay proven and rows.csv records both (`cond_tol`, the bound
    /// columns).
    pub cond_tol: Option<f64>,
}

impl Default for SweepConfig {
    fn default() -> Self {
        SweepConfig {
            families: generate::FAMILY_NAMES
                .iter()
                .map(|s| s.to_string())
                .collect(),
            count: 8,
            seed: 2011,
            eps: LogGrid {
                lo: 1e-2,
                hi: 1e12,
                n: 15,
            },
            factors: vec![1.0, 10.0, 100.0, 1e3, 1e4],
            deltas: vec![],
            deltas_rel: vec![1e-1, 1e-2, 1e-3],
            methods: registry::BUILT_IN
                .iter()
                .map(|s| s.name.to_string())
                .collect(),
            metrics: vec!["cond".into(), "det".into()],
            generator: GeneratorConfig::default(),
            scenes_dir: None,
            optimal_families: vec!["beam".into(), "file".into()],
            cond_tol: None,
        }
    }
}

/// Metric names accepted in `metrics`.
pub const METRIC_NAMES: [&str; 2] = ["cond", "det"];

impl SweepConfig {
    /// Reads a TOML config (fields as in [`SweepConfig`]; missing fields take defaults).
    pub fn from_toml_file(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path.display(), e))?;
        let cfg: SweepConfig = toml::from_str(&text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            let msg = e.message().replace('\n', " ");
            match line {
                Some(l) => Error::io(path.display(), format!("line {l}: {msg}")),
                None => Error::io(path.display(), msg),
            }
        })?;
        Ok(cfg)
    }

    /// Validates names, ranges and knobs; errors name the problem and the valid choices.
    pub fn validate(&self) -> Result<()> {
        MetricSet::check_cond_tol(self.cond_tol)?;
        if self.scenes_dir.is_none() {
            if self.families.is_empty() {
                return Err(Error::input(format!(
                    "no families given (valid: {})",
                    generate::FAMILY_NAMES.join(", ")
                )));
            }
            for f in &self.families {
                Family::from_name(f)?;
            }
            if self.count == 0 {
                return Err(Error::input("--count must be ≥ 1"));
            }
        }
        for m in &self.methods {
            registry::lookup(m)?;
        }
        for f in &self.optimal_families {
            if f != "file" && Family::from_name(f).is_err() {
                return Err(Error::input(format!(
                    "optimal_families: unknown family '{f}' (valid: {}, file)",
                    generate::FAMILY_NAMES.join(", ")
                )));
            }
        }
        for m in &self.metrics {
            if !METRIC_NAMES.contains(&m.as_str()) {
                return Err(Error::input(format!(
                    "unknown metric '{m}' (valid: {}; penetration, error and time are always recorded)",
                    METRIC_NAMES.join(", ")
                )));
            }
        }
        self.eps.validate()?;
        for (what, v) in [
            ("factor", &self.factors),
            ("δ (--deltas)", &self.deltas),
            ("relative δ (--deltas-rel)", &self.deltas_rel),
        ] {
            if let Some(x) = v.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
                return Err(Error::input(format!(
                    "{what} must be finite and > 0 (got {x})"
                )));
            }
        }
        let with_knob = |knobs: &[Knob]| -> Vec<&str> {
            self.strategies()
                .into_iter()
                .filter(|s| knobs.contains(&s.knob))
                .map(|s| s.name)
                .collect()
        };
        let needs_delta = with_knob(&[Knob::Delta, Knob::EpsTol]);
        if !needs_delta.is_empty() && self.deltas.is_empty() && self.deltas_rel.is_empty() {
            return Err(Error::input(format!(
                "{} need δ values (--deltas or --deltas-rel)",
                needs_delta.join("/")
            )));
        }
        let needs_factors = with_knob(&[Knob::Factor]);
        if !needs_factors.is_empty() && self.factors.is_empty() {
            return Err(Error::input(format!(
                "{} needs --factors",
                needs_factors.join("/")
            )));
        }
        self.generator.validate()
    }

    fn metric_set(&self) -> MetricSet {
        MetricSet {
            cond: self.metrics.iter().any(|m| m == "cond"),
            det: self.metrics.iter().any(|m| m == "det"),
            cond_tol: self.cond_tol,
        }
    }

    /// The strategies of `methods` (unknown names, which [`SweepConfig::validate`] refuses,
    /// left out).
    pub fn strategies(&self) -> Vec<&'static strategy::Strategy> {
        self.methods
            .iter()
            .filter_map(|m| registry::find(m))
            .collect()
    }

    /// Rows produced per scene.
    pub fn rows_per_scene(&self) -> usize {
        let nd = self.deltas.len() + self.deltas_rel.len();
        let mut r = 1; // lagrange reference
        for s in self.strategies() {
            r += match s.knob {
                Knob::Eps => self.eps.n,
                Knob::Factor => self.factors.len(),
                Knob::Delta | Knob::EpsTol => nd,
                Knob::None => 0,
            };
        }
        r
    }
}

/// Where a scene comes from.
#[derive(Clone, Debug)]
pub enum SceneSpec {
    /// Generated from (family, index).
    Generated {
        /// Family.
        family: Family,
        /// Index within the family.
        index: usize,
    },
    /// Read from a scene file.
    File(PathBuf),
}

/// The ordered list of scenes of a config.
pub fn plan(cfg: &SweepConfig) -> Result<Vec<SceneSpec>> {
    if let Some(dir) = &cfg.scenes_dir {
        let rd = std::fs::read_dir(dir).map_err(|e| Error::io(dir.display(), e))?;
        let mut files: Vec<PathBuf> = rd
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| {
                p.file_name()
                    .and_then(|n| n.to_str())
                    .is_some_and(|n| n.ends_with(".scene.json"))
            })
            .collect();
        files.sort();
        if files.is_empty() {
            return Err(Error::io(dir.display(), "no *.scene.json files found"));
        }
        return Ok(files.into_iter().map(SceneSpec::File).collect());
    }
    let mut out = Vec::new();
    for f in &cfg.families {
        let family = Family::from_name(f)?;
        out.extend((0..cfg.count).map(|index| SceneSpec::Generated { family, index }));
    }
    Ok(out)
}

/// The contiguous block of `0..total` that shard `k` of `n` (1-based) owns.
pub fn shard_range(total: usize, k: usize, n: usize) -> std::ops::Range<usize> {
    (total * (k - 1) / n)..(total * k / n)
}

/// Parses `K/N` (1 ≤ K ≤ N).
pub fn parse_shard(s: &str) -> Result<(usize, usize)> {
    let bad = || {
        Error::input(format!(
            "malformed shard '{s}': expected K/N with 1 ≤ K ≤ N"
        ))
    };
    let (a, b) = s.split_once('/').ok_or_else(bad)?;
    let k: usize = a.trim().parse().map_err(|_| bad())?;
    let n: usize = b.trim().parse().map_err(|_| bad())?;
    if k == 0 || n == 0 || k > n {
        return Err(bad());
    }
    Ok((k, n))
}

/// A loaded scene.
pub struct LoadedScene {
    /// Name.
    pub name: String,
    /// Family name.
    pub family: String,
    /// Problem.
    pub problem: Problem,
    /// Provenance.
    pub meta: serde_json::Value,
}

/// Builds or reads a scene.
pub fn load(spec: &SceneSpec, cfg: &SweepConfig) -> Result<LoadedScene> {
    match spec {
        SceneSpec::Generated { family, index } => {
            let g = generate::generate(*family, *index, cfg.seed, &cfg.generator)?;
            Ok(LoadedScene {
                name: g.name,
                family: family.name().to_string(),
                problem: g.problem,
                meta: g.meta,
            })
        }
        SceneSpec::File(path) => {
            let s = scene::read_scene_preferred(path)?;
            let family = s
                .meta
                .as_ref()
                .and_then(|m| m.get("generator"))
                .and_then(|g| g.as_str())
                .unwrap_or("file")
                .to_string();
            Ok(LoadedScene {
                name: s.name,
                family,
                problem: s.problem,
                meta: s.meta.unwrap_or(serde_json::Value::Null),
            })
        }
    }
}

/// One job of a scene: a method with its knob.
#[derive(Clone, Copy, Debug)]
pub struct Job {
    /// The method.
    pub method: Method,
    /// Relative δ if δ was given relatively.
    pub delta_rel: Option<f64>,
}

/// The jobs of a scene, in row order (lagrange first).
pub fn jobs(cfg: &SweepConfig, problem: &Problem, u0: Option<&[f64]>) -> Vec<Job> {
    let scale = u0.map(|u| problem.displacement_scale(u)).unwrap_or(1.0);
    let deltas: Vec<(f64, Option<f64>)> = cfg
        .deltas
        .iter()
        .map(|&d| (d, None))
        .chain(cfg.deltas_rel.iter().map(|&r| (r * scale, Some(r))))
        .collect();
    // Augmented: a moderate ε, the geometric mean of the constrained diagonal of K.
    let aug_eps = {
        let logs: Vec<f64> = problem
            .constraints
            .iter()
            .map(|c| problem.k.diag(c.dof).abs())
            .filter(|v| *v > 0.0)
            .map(f64::ln)
            .collect();
        if logs.is_empty() {
            1.0
        } else {
            (logs.iter().sum::<f64>() / logs.len() as f64).exp()
        }
    };
    let mut out = vec![Job {
        method: Method::lagrange(),
        delta_rel: None,
    }];
    // One job per value of each strategy's knob; a knob value the strategy refuses (an ε
    // grid point ≤ 0 cannot pass `validate`) drops the job.
    let mut push = |s, knobs, delta_rel| {
        if let Ok(method) = Method::new(s, knobs) {
            out.push(Job { method, delta_rel });
        }
    };
    for s in cfg.strategies() {
        match s.knob {
            Knob::Eps => {
                for eps in cfg.eps.values() {
                    push(
                        s,
                        Knobs {
                            eps: Some(eps),
                            ..Knobs::NONE
                        },
                        None,
                    );
                }
            }
            Knob::Factor => {
                for &factor in &cfg.factors {
                    push(
                        s,
                        Knobs {
                            factor: Some(factor),
                            ..Knobs::NONE
                        },
                        None,
                    );
                }
            }
            Knob::Delta => {
                for &(delta, delta_rel) in &deltas {
                    push(
                        s,
                        Knobs {
                            delta: Some(delta),
                            ..Knobs::NONE
                        },
                        delta_rel,
                    );
                }
            }
            Knob::EpsTol => {
                for &(delta, delta_rel) in &deltas {
                    let knobs = Knobs {
                        eps: Some(aug_eps),
                        tol: Some(delta),
                        adaptive: true,
                        ..Knobs::NONE
                    };
                    push(s, knobs, delta_rel);
                }
            }
            // The exact methods: lagrange is the first job already.
            Knob::None => {}
        }
    }
    out
}

/// What every row of a scene shares, computed once per scene: the problem in its preferred
/// storage, K's factorization and u0, cond₂(K) and log10|det K|, and the jobs.
pub struct SceneWork {
    /// The scene (K in the storage its structure prefers).
    pub scene: LoadedScene,
    /// K's structure.
    pub structure: Structure,
    /// K's factorization and u0 (an error where K is singular; every row then says so).
    pub prepared: Result<Prepared>,
    /// cond₂(K), when requested and available.
    pub cond2_k: Option<f64>,
    /// Its bounds `[cond2_lo, cond2_hi]`.
    pub cond2_k_bounds: Option<(f64, f64)>,
    /// log10|det K|, when requested and available.
    pub log10_det_k: Option<f64>,
    /// K's Ritz vectors of λ_max and λ_min (sparse route): every job's cond₂ starts its
    /// Lanczos runs from them. Shared by the scene's jobs rather than passed from one ε to the
    /// next, so each row is computed the same way whatever the thread count and order.
    pub ritz_k: Option<RitzStarts>,
    /// The jobs, in row order (lagrange first).
    pub jobs: Vec<Job>,
    /// Wall time of each shared step (s): `read`, `prepare`, `cond_k`, `det_k`.
    pub seconds: SetupSeconds,
}

/// Wall time of a scene's shared work (s).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct SetupSeconds {
    /// Building or reading the scene and choosing its storage.
    pub read: f64,
    /// K's factorization and u0.
    pub prepare: f64,
    /// cond₂(K).
    pub cond_k: f64,
    /// log10|det K| (near zero where cond₂(K)'s factorization gave it).
    pub det_k: f64,
}

impl SetupSeconds {
    /// The sum of the four.
    pub fn total(&self) -> f64 {
        self.read + self.prepare + self.cond_k + self.det_k
    }
}

fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let t = Instant::now();
    let v = f();
    (v, t.elapsed().as_secs_f64())
}

/// Loads a scene and does its shared work (cond₂(K) beside the factorization of K, on two
/// threads where the pool has them).
pub fn prepare_scene(spec: &SceneSpec, cfg: &SweepConfig) -> Result<SceneWork> {
    let (loaded, read) = timed(|| {
        load(spec, cfg).map(|mut sc| {
            sc.problem = sc.problem.in_preferred_storage();
            sc
        })
    });
    let scene = loaded?;
    let p = &scene.problem;
    let set = cfg.metric_set();
    let ((prepared, prepare), (cond, cond_k)) = rayon::join(
        || timed(|| Prepared::new(p)),
        || {
            timed(|| {
                set.cond
                    .then(|| conditioning::cond2_warm(&p.k, Reuse::keeping_ritz()).ok())
                    .flatten()
            })
        },
    );
    let (cond, ritz_k) = cond.unzip();
    let (log10_det_k, det_k) = timed(|| {
        set.det
            .then(|| conditioning::log10_abs_det_after(&p.k, cond.as_ref()).ok())
            .flatten()
    });
    let jobs = jobs(cfg, p, prepared.as_ref().ok().map(|x| x.u0()));
    Ok(SceneWork {
        structure: p.k.structure(),
        prepared,
        cond2_k: cond.map(|c| c.cond2),
        cond2_k_bounds: cond.map(|c| (c.cond2_lo, c.cond2_hi)),
        log10_det_k,
        ritz_k: ritz_k.flatten(),
        jobs,
        seconds: SetupSeconds {
            read,
            prepare,
            cond_k,
            det_k,
        },
        scene,
    })
}

/// A row with the scene's columns and the job's knobs, before solving.
fn base_row(work: &SceneWork, job: Job) -> Row {
    let sc = &work.scene;
    let p = &sc.problem;
    let mut row = Row {
        scene: sc.name.clone(),
        family: sc.family.clone(),
        n: p.n(),
        m: p.m(),
        storage: if p.k.is_sparse() { "sparse" } else { "dense" }.into(),
        nnz: work.structure.nnz,
        half_bandwidth: work.structure.half_bandwidth,
        method: job.method.name().to_string(),
        delta_rel: job.delta_rel,
        cond2_k: work.cond2_k,
        cond2_k_lo: work.cond2_k_bounds.map(|b| b.0),
        cond2_k_hi: work.cond2_k_bounds.map(|b| b.1),
        ..Default::default()
    };
    // The knob values in their columns: ε, f, δ; `augmented`'s tolerance in `delta`.
    let k = job.method.knobs();
    row.eps = k.eps;
    row.factor = k.factor;
    row.delta = k.delta.or(k.tol);
    row
}

/// The row of an `optimal` job on a family outside `optimal_families`: no solve, the reason
/// in `warnings`.
fn skipped_row(work: &SceneWork, job: Job, cfg: &SweepConfig) -> Row {
    let mut row = base_row(work, job);
    row.seconds = Some(0.0);
    row.seconds_solve = Some(0.0);
    row.warnings = format!(
        "skipped: optimal runs on the families {:?} only (optimal_families)",
        cfg.optimal_families
    );
    row
}

/// What the lagrange row gives the other rows of its scene.
pub struct Reference {
    /// The exact solution (`error_vs_exact`).
    pub u: Vec<f64>,
    /// The scene's [`Prepared`] with the exact contact set
    /// ([`Prepared::with_contact_set`]): where constant, scaled and condensed start.
    pub prepared: Option<Prepared>,
}

/// One row: `job` solved on the scene with its metrics; `reference` is what the lagrange row
/// gave (`error_vs_exact`, the contact set), and the lagrange row returns it. A failing solve
/// or metric becomes the row's warning, never an error.
pub fn run_job(
    work: &SceneWork,
    job: Job,
    set: MetricSet,
    reference: Option<&Reference>,
) -> (Row, Option<Reference>) {
    let t0 = Instant::now();
    let p = &work.scene.problem;
    let mut row = base_row(work, job);
    row.cond_tol = set.cond_tol.filter(|_| set.cond);
    let u_ref = reference.map(|r| r.u.as_slice());
    let prep = reference
        .and_then(|r| r.prepared.as_ref())
        .or(work.prepared.as_ref().ok());
    let (solved, seconds_solve) = timed(|| strategy::solve_prepared(p, job.method, prep));
    row.seconds_solve = Some(seconds_solve);
    let mut u_out = None;
    match solved.and_then(|sol| {
        let m = metrics::compute_with_k(p, &sol, set, work.log10_det_k, work.ritz_k.as_ref())?;
        Ok((sol, m))
    }) {
        Ok((sol, m)) => {
            let pen: Vec<f64> = sol.penalties.iter().copied().filter(|e| *e > 0.0).collect();
            if !pen.is_empty() {
                row.eps_min = Some(pen.iter().copied().fold(f64::INFINITY, f64::min));
                row.eps_max = Some(pen.iter().copied().fold(0.0, f64::max));
            }
            row.active = sol.stats.active_set_sizes.last().copied();
            row.cond2_system = m.cond2_system.map(|c| c.cond2);
            row.cond2_system_lo = m.cond2_system.map(|c| c.cond2_lo);
            row.cond2_system_hi = m.cond2_system.map(|c| c.cond2_hi);
            row.cond_route = m.cond2_system.map(|c| c.route.name().to_string());
            row.log10_det_ratio = m.log10_det_ratio;
            row.max_penetration = Some(sol.max_penetration);
            row.error_vs_exact = u_ref.map(|r| metrics::relative_error(&sol.u, r));
            row.linear_solves = Some(sol.stats.linear_solves);
            row.iterations = Some(sol.stats.iterations);
            row.converged = Some(sol.stats.converged);
            row.seconds_cond = set.cond.then_some(m.seconds_cond);
            row.seconds_det = set.det.then_some(m.seconds_det);
            row.warnings = metrics::warnings(&sol, &m).join("; ");
            if job.method.is(&strategy::lagrange::STRATEGY) {
                row.error_vs_exact = Some(metrics::relative_error(&sol.u, &sol.u));
                let prepared = work
                    .prepared
                    .as_ref()
                    .ok()
                    .zip(sol.contact_set())
                    .map(|(p, set)| p.clone().with_contact_set(set));
                u_out = Some(Reference { u: sol.u, prepared });
            }
        }
        Err(e) => row.warnings = format!("error: {e}"),
    }
    row.seconds = Some(t0.elapsed().as_secs_f64());
    (row, u_out)
}

/// Runs every job of one scene: the shared work, the lagrange reference, then the other jobs
/// as separate work units on the current rayon pool, one task each (rows in job order
/// whatever the thread count). Errors of single jobs become rows with the error in
/// `warnings`; only an unreadable scene is an error.
pub fn run_scene(spec: &SceneSpec, cfg: &SweepConfig) -> Result<(Vec<Row>, SceneWork)> {
    use rayon::prelude::*;
    let work = prepare_scene(spec, cfg)?;
    let set = cfg.metric_set();
    let (first, rest) = work.jobs.split_first().expect("lagrange is always a job");
    let (lag_row, reference) = run_job(&work, *first, set, None);
    let mut rows = Vec::with_capacity(work.jobs.len());
    rows.push(lag_row);
    let others: Vec<Row> = rest
        .par_iter()
        .with_max_len(1)
        .map(|&job| {
            let skip = job.method.is(&strategy::optimal::STRATEGY)
                && !cfg.optimal_families.contains(&work.scene.family);
            if skip {
                skipped_row(&work, job, cfg)
            } else {
                run_job(&work, job, set, reference.as_ref()).0
            }
        })
        .collect();
    rows.extend(others);
    set_ratios_to_optimal(&mut rows);
    Ok((rows, work))
}

/// Fills `cond_ratio_to_optimal` on one scene's rows: every δ-driven row (spring, paper,
/// condensed, optimal) whose δ has an `optimal` row with a cond₂ gets cond₂ / cond₂(optimal).
pub fn set_ratios_to_optimal(rows: &mut [Row]) {
    let optima: Vec<(f64, f64)> = rows
        .iter()
        .filter(|r| r.method == strategy::optimal::STRATEGY.name)
        .filter_map(|r| Some((r.delta?, r.cond2_system?)))
        .filter(|(_, c)| c.is_finite() && *c > 0.0)
        .collect();
    for r in rows.iter_mut() {
        if registry::find(&r.method).is_none_or(|s| s.knob != Knob::Delta) {
            continue;
        }
        let (Some(d), Some(c)) = (r.delta, r.cond2_system) else {
            continue;
        };
        if let Some(&(_, best)) = optima.iter().find(|(od, _)| *od == d) {
            r.cond_ratio_to_optimal = Some(c / best);
        }
    }
}

/// Options of a sweep run that do not change its rows.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Output folder.
    pub out: PathBuf,
    /// Worker threads (`None`: rayon's default).
    pub threads: Option<usize>,
    /// Shard `(k, n)`.
    pub shard: Option<(usize, usize)>,
    /// Continue an interrupted run in `out`.
    pub resume: bool,
    /// Also write every scene as a scene file here.
    pub write_scenes: Option<PathBuf>,
    /// Store K inline as dense rows in those scene files, whatever its structure.
    pub dense_scenes: bool,
    /// Show a progress bar (hidden anyway when stderr is not a terminal).
    pub progress: bool,
}

/// What a run did.
#[derive(Clone, Debug, Serialize)]
pub struct RunSummary {
    /// Scenes in this shard.
    pub scenes: usize,
    /// Scenes skipped because `--resume` found them complete.
    pub resumed_scenes: usize,
    /// Rows written by this invocation.
    pub rows_written: usize,
    /// Wall time (s).
    pub wall_seconds: f64,
    /// Rows per second.
    pub rows_per_second: f64,
}

use crate::provenance::{write_atomic, Provenance};

fn write_manifest(path: &Path, manifest: &serde_json::Value) -> Result<()> {
    let text = serde_json::to_string_pretty(manifest).expect("a JSON value serializes");
    write_atomic(path, text.as_bytes())
}

/// Runs the sweep: writes `out/rows.csv` and `out/manifest.json` (figures are rendered by the
/// caller from rows.csv).
pub fn run(cfg: &SweepConfig, opts: &RunOptions) -> Result<RunSummary> {
    cfg.validate()?;
    let t_start = Instant::now();
    let all = plan(cfg)?;
    let (k, n) = opts.shard.unwrap_or((1, 1));
    let range = shard_range(all.len(), k, n);
    let specs: Vec<(usize, SceneSpec)> = all[range.clone()]
        .iter()
        .cloned()
        .enumerate()
        .map(|(i, s)| (range.start + i, s))
        .collect();
    std::fs::create_dir_all(&opts.out).map_err(|e| Error::io(opts.out.display(), e))?;
    if let Some(d) = &opts.write_scenes {
        std::fs::create_dir_all(d).map_err(|e| Error::io(d.display(), e))?;
    }
    let rows_path = opts.out.join("rows.csv");
    let manifest_path = opts.out.join("manifest.json");
    let config_json = serde_json::to_value(cfg).map_err(|e| Error::Numerical(e.to_string()))?;
    let per_scene = cfg.rows_per_scene();

    // Resume: keep the complete scenes at the head of rows.csv; a fresh run writes its header
    // beside the first scenes (`start` below).
    let resumed = resume_point(opts, &config_json, (k, n), per_scene)?;
    let done = resumed.unwrap_or(0);
    let todo = &specs[done.min(specs.len())..];

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| Error::input(format!("cannot start {:?} threads: {e}", opts.threads)))?;
    faer::set_global_parallelism(faer::Par::Seq);
    let threads = pool.current_num_threads();
    let mut manifest = Provenance::new("sweep").record(serde_json::json!({
        "config": config_json,
        "seed": cfg.seed,
        "threads": threads,
        "shard": [k, n],
        "scenes": specs.len(),
        "rows_per_scene": per_scene,
        "status": "running",
    }));
    let bar = crate::progress::Progress::new("sweep (scenes)", !opts.progress);
    bar.set_total(specs.len());
    bar.set_done(done);

    // rows.csv's header (fresh runs) and the running manifest, both before any row.
    let start = || -> Result<()> {
        if resumed.is_none() {
            write_atomic(&rows_path, rows::header().as_bytes())?;
        }
        write_manifest(&manifest_path, &manifest)
    };
    let mut times = Timing::default();
    let writer = InOrder::new(&rows_path, &mut times);
    let outcome = solve_in_order(todo, cfg, opts, &pool, &bar, writer, start);
    bar.finish();
    let rows_written = outcome?;
    let wall = t_start.elapsed().as_secs_f64();
    let summary = RunSummary {
        scenes: specs.len(),
        resumed_scenes: done.min(specs.len()),
        rows_written,
        wall_seconds: wall,
        rows_per_second: rows_written as f64 / wall.max(1e-9),
    };
    manifest["status"] = "complete".into();
    manifest["wall_seconds"] = wall.into();
    manifest["rows_written"] = rows_written.into();
    manifest["rows_per_second"] = summary.rows_per_second.into();
    manifest["resumed_scenes"] = summary.resumed_scenes.into();
    manifest["timing"] = times.report(wall, threads);
    write_manifest(&manifest_path, &manifest)?;
    Ok(summary)
}

/// Where the time of a run went: per method the sums of the rows' timing columns, and the
/// scenes' shared work ([`SetupSeconds`]).
#[derive(Clone, Debug, Default)]
pub struct Timing {
    per_method: BTreeMap<String, MethodTiming>,
    setup: SetupSeconds,
}

/// Sums of one method's rows.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct MethodTiming {
    /// Rows.
    pub rows: usize,
    /// Σ `seconds`.
    pub seconds: f64,
    /// Σ `seconds_solve`.
    pub seconds_solve: f64,
    /// Σ `seconds_cond`.
    pub seconds_cond: f64,
    /// Σ `seconds_det`.
    pub seconds_det: f64,
}

impl Timing {
    /// Adds a scene's rows and shared work.
    pub fn add(&mut self, rows: &[Row], setup: &SetupSeconds) {
        for r in rows {
            let t = self.per_method.entry(r.method.clone()).or_default();
            t.rows += 1;
            t.seconds += r.seconds.unwrap_or(0.0);
            t.seconds_solve += r.seconds_solve.unwrap_or(0.0);
            t.seconds_cond += r.seconds_cond.unwrap_or(0.0);
            t.seconds_det += r.seconds_det.unwrap_or(0.0);
        }
        self.setup.read += setup.read;
        self.setup.prepare += setup.prepare;
        self.setup.cond_k += setup.cond_k;
        self.setup.det_k += setup.det_k;
    }

    /// The manifest's `timing` object: per-method sums, the scenes' shared work, the busy
    /// time (their total), rows per second of wall time, and the parallel efficiency
    /// busy / (wall · threads) — 1 when every thread was busy all the time (writing rows.csv,
    /// the manifest and waiting for the last scene count as idle).
    pub fn report(&self, wall: f64, threads: usize) -> serde_json::Value {
        let rows: usize = self.per_method.values().map(|t| t.rows).sum();
        let busy: f64 =
            self.per_method.values().map(|t| t.seconds).sum::<f64>() + self.setup.total();
        serde_json::json!({
            "per_method": self.per_method,
            "scene_setup": self.setup,
            "busy_seconds": busy,
            "wall_seconds": wall,
            "threads": threads,
            "rows_per_second": rows as f64 / wall.max(1e-9),
            "parallel_efficiency": busy / (wall.max(1e-9) * threads.max(1) as f64),
        })
    }
}

/// Where a `--resume` run picks up: the number of complete scenes at the head of an existing
/// rows.csv (which is cut back to them), after checking that the manifest was written with
/// the same config and shard; `None` for a fresh run (nothing written).
fn resume_point(
    opts: &RunOptions,
    config_json: &serde_json::Value,
    (k, n): (usize, usize),
    per_scene: usize,
) -> Result<Option<usize>> {
    let rows_path = opts.out.join("rows.csv");
    let manifest_path = opts.out.join("manifest.json");
    if !(opts.resume && rows_path.exists()) {
        return Ok(None);
    }
    let old: serde_json::Value = std::fs::read_to_string(&manifest_path)
        .ok()
        .and_then(|t| serde_json::from_str(&t).ok())
        .ok_or_else(|| {
            Error::io(
                manifest_path.display(),
                "cannot resume: manifest.json missing or unreadable",
            )
        })?;
    if old.get("config") != Some(config_json)
        || old.get("shard") != Some(&serde_json::json!([k, n]))
    {
        return Err(Error::input(format!(
            "cannot resume in {}: it was produced with a different config or shard; use another --out",
            opts.out.display()
        )));
    }
    let (rows, _) = rows::read_rows(&rows_path, true)?;
    let done = rows.len() / per_scene;
    let keep = &rows[..done * per_scene];
    let mut text = rows::header();
    text.push_str(&rows::format_rows(keep));
    write_atomic(&rows_path, text.as_bytes())?;
    Ok(Some(done))
}

/// The reorder buffer: scenes finish in any order on the workers; whichever worker completes
/// the next scene in order appends it and every completed scene after it to rows.csv (one
/// write and flush per scene), so rows land in scene order with no thread of their own.
struct InOrder<'a> {
    /// rows.csv open for appending, once its header and the manifest are written.
    file: Option<std::fs::File>,
    rows_path: &'a Path,
    /// Finished scenes waiting for an earlier one (or for the file).
    pending: BTreeMap<usize, Finished>,
    next: usize,
    rows_written: usize,
    times: &'a mut Timing,
    /// The error of the earliest failed scene (or of a write); nothing is written after it.
    error: Option<(usize, Error)>,
}

/// A solved scene: its rows, their CSV text and its shared work.
type Finished = (Vec<Row>, String, SetupSeconds);

impl<'a> InOrder<'a> {
    /// Nothing written yet; rows go to `rows_path` once it is opened, their timing to `times`.
    fn new(rows_path: &'a Path, times: &'a mut Timing) -> Self {
        InOrder {
            file: None,
            rows_path,
            pending: BTreeMap::new(),
            next: 0,
            rows_written: 0,
            times,
            error: None,
        }
    }

    /// Files scene `i`'s outcome and writes the complete prefix.
    fn finish(&mut self, i: usize, done: Result<Finished>) {
        match done {
            Ok(f) => {
                self.pending.insert(i, f);
            }
            Err(e) => self.fail(i, e),
        }
        self.write_prefix();
    }

    /// Records the error of scene `i` (0 for the start: it precedes every scene's).
    fn fail(&mut self, i: usize, e: Error) {
        if self.error.as_ref().is_none_or(|(j, _)| i < *j) {
            self.error = Some((i, e));
        }
    }

    /// Appends the finished scenes that follow the last written one.
    fn write_prefix(&mut self) {
        let Some(file) = self.file.as_mut() else {
            return;
        };
        while let Some((rows, text, setup)) = self.pending.remove(&self.next) {
            self.times.add(&rows, &setup);
            if self.error.as_ref().is_some_and(|(j, _)| *j <= self.next) {
                break;
            }
            self.next += 1;
            match file.write_all(text.as_bytes()).and_then(|_| file.flush()) {
                Ok(()) => self.rows_written += rows.len(),
                Err(e) => {
                    self.error = Some((0, Error::io(self.rows_path.display(), e)));
                    break;
                }
            }
        }
    }
}

/// Solves `todo` on `pool` and appends each scene's rows to rows.csv in scene order as soon
/// as the prefix is complete ([`InOrder`]), writing scene files where asked; returns the
/// number of rows written or the first error. `start` (rows.csv's header, the running
/// manifest) runs on one worker while the others begin the first scenes; no row is written
/// before it is done. After an error, scenes after the failed one are not started. The rows are
/// formatted on the workers; the calling thread only waits.
fn solve_in_order(
    todo: &[(usize, SceneSpec)],
    cfg: &SweepConfig,
    opts: &RunOptions,
    pool: &rayon::ThreadPool,
    bar: &crate::progress::Progress,
    writer: InOrder<'_>,
    start: impl FnOnce() -> Result<()> + Send,
) -> Result<usize> {
    use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};
    use std::sync::{Mutex, PoisonError};
    let rows_path = writer.rows_path;
    let state = Mutex::new(writer);
    // The earliest failed scene (0 when the start failed): later scenes are not started.
    let failed = AtomicUsize::new(usize::MAX);
    let open = || {
        let opened = start().and_then(|()| {
            std::fs::OpenOptions::new()
                .append(true)
                .open(rows_path)
                .map_err(|e| Error::io(rows_path.display(), e))
        });
        let mut state = state.lock().unwrap_or_else(PoisonError::into_inner);
        match opened {
            Ok(file) => {
                state.file = Some(file);
                state.write_prefix();
            }
            Err(e) => {
                failed.store(0, Relaxed);
                state.fail(0, e);
            }
        }
    };
    let solve = || {
        use rayon::prelude::*;
        todo.par_iter()
            .enumerate()
            .with_max_len(1)
            .for_each(|(i, (_, spec))| {
                if i > failed.load(Relaxed) {
                    return; // nothing after the failed scene would be written
                }
                let done = run_scene(spec, cfg).and_then(|(rows, work)| {
                    if let Some(d) = &opts.write_scenes {
                        write_scene_file(d, &work.scene, opts.dense_scenes)?;
                    }
                    bar.message(work.scene.name.clone());
                    let text = rows::format_rows(&rows);
                    Ok((rows, text, work.seconds))
                });
                if done.is_err() {
                    failed.fetch_min(i, Relaxed);
                }
                state
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .finish(i, done);
                bar.step("");
            });
    };
    pool.install(|| rayon::join(open, solve));
    let state = state.into_inner().unwrap_or_else(PoisonError::into_inner);
    match state.error {
        Some((_, e)) => Err(e),
        None => Ok(state.rows_written),
    }
}

/// Writes `scene` to `DIR/NAME.scene.json`: K as dense rows with `dense`, otherwise dense
/// inline and sparse as Matrix Market beside it.
fn write_scene_file(dir: &Path, sc: &LoadedScene, dense: bool) -> Result<()> {
    let path = dir.join(format!("{}.scene.json", sc.name));
    let storage = if dense {
        scene::Storage::Dense
    } else {
        scene::Storage::Auto {
            mtx_threshold: usize::MAX,
        }
    };
    scene::write_scene_as(&path, &sc.name, &sc.problem, Some(&sc.meta), storage)
}
