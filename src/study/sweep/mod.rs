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
//! * Rows of a scene are written together and flushed as soon as it completes, its index
//!   appended to `scenes_done.csv` (the order file); a complete run puts rows.csv in
//!   scene order and removes that file. A killed run loses at most the scenes in flight and
//!   `--resume` completes it without losing or duplicating rows.

pub mod cli;
mod config;
pub mod figures;
mod jobs;
pub mod merge;
mod plan;
pub mod report;
mod resume;
pub mod rows;

pub use cli::Sweep;

pub use config::{LogGrid, SweepConfig, METRIC_NAMES};
pub use jobs::{
    jobs, prepare_scene, run_job, run_scene, set_ratios_to_optimal, Job, Reference, SceneWork,
    SetupSeconds,
};
pub use plan::{load, parse_shard, plan, shard_range, LoadedScene, SceneSpec};

use crate::error::{Error, Result};
use crate::provenance::{remove_if_present, write_atomic, Provenance};
use resume::{
    order_text, put_in_scene_order, resume_point, solve_as_completed, Completed, ORDER_FILE,
};
use rows::Row;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    /// The manifest's provenance (the study entry's); `None`: the running program's, named
    /// `sweep`.
    pub provenance: Option<Provenance>,
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

/// Removes `path` where it exists (an error other than its absence is reported).
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

    // Resume: keep the complete scenes rows.csv holds; a fresh run writes its header beside
    // the first scenes (`start` below).
    let resumed = resume_point(opts, &config_json, (k, n), per_scene)?;
    let fresh = resumed.is_none();
    let kept = resumed.unwrap_or_default();
    let done = kept.done.len();
    let todo: Vec<(usize, &SceneSpec)> = specs
        .iter()
        .enumerate()
        .filter(|(i, _)| !kept.done.contains(i))
        .map(|(i, (_, spec))| (i, spec))
        .collect();

    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads.unwrap_or(0))
        .build()
        .map_err(|e| {
            Error::io(
                "--threads",
                format!("cannot start {:?} threads: {e}", opts.threads),
            )
        })?;
    faer::set_global_parallelism(faer::Par::Seq);
    let threads = pool.current_num_threads();
    let provenance = opts
        .provenance
        .clone()
        .unwrap_or_else(|| Provenance::new("sweep"));
    let mut manifest = provenance.record(serde_json::json!({
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

    // rows.csv's header (fresh runs) and the running manifest, both before any row. A fresh
    // run replaces both files and removes each old one just before writing it, so that neither
    // write renames over a file: on ext4 such a rename flushes the new file, and the final
    // manifest then waited for that flush (0.5 ms of the 25 ms folder sweep,
    // docs/history/performance-log.md). The trade: the start files of a fresh run are not
    // flushed, so a power loss in the seconds before the kernel writes them back can leave them
    // empty (`--resume` then refuses and the run starts over), as for a run into a new folder.
    let start = || -> Result<()> {
        if fresh {
            remove_if_present(&rows_path)?;
            write_atomic(&rows_path, rows::header().as_bytes())?;
            let order_path = opts.out.join(ORDER_FILE);
            remove_if_present(&order_path)?;
            write_atomic(&order_path, order_text(&[]).as_bytes())?;
            remove_if_present(&manifest_path)?;
        }
        write_manifest(&manifest_path, &manifest)
    };
    let mut times = Timing::default();
    let writer = Completed::new(&rows_path, &mut times);
    let outcome = solve_as_completed(&todo, cfg, opts, &pool, &bar, writer, start);
    bar.finish();
    let (order, rows_written) = outcome?;
    let order: Vec<usize> = kept.order.iter().chain(&order).copied().collect();
    put_in_scene_order(&opts.out, &order, per_scene)?;
    let wall = t_start.elapsed().as_secs_f64();
    let summary = RunSummary {
        scenes: specs.len(),
        resumed_scenes: done,
        rows_written,
        wall_seconds: wall,
        rows_per_second: rows_written as f64 / wall.max(1e-9),
    };
    manifest["status"] = "complete".into();
    manifest["wall_seconds"] = wall.into();
    manifest["rows_written"] = rows_written.into();
    // rows.csv as this run leaves it: the complete scenes it kept (`--resume` cut it back to
    // them) and the rows it appended.
    manifest["rows_in_file"] = (done * per_scene + rows_written).into();
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
