//! The sweep on the command line: flags that override a TOML file or the built-in default
//! (`SweepConfig`, [`ConfigArgs`], shared by every binary that runs a sweep), the `sweep`
//! binary's own flags and `merge` subcommand, and [`Sweep`], the study as the shared entry
//! ([`crate::study::shape::main`]) runs it.

use super::config::Metric;
use super::rows::{self, Row};
use super::{figures, merge, report, LogGrid, RunOptions, SweepConfig};
use crate::error::{Error, Result};
use crate::generate::Family;
use crate::strategy::registry;
use crate::study::shape::{Drawing, RunContext, Study};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Command-line overrides of a [`SweepConfig`] (flattened into a binary's clap arguments).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ConfigArgs {
    /// TOML config (fields of SweepConfig); command-line flags override it.
    #[arg(long)]
    config: Option<PathBuf>,
    /// Run over every *.scene.json in DIR instead of generating scenes.
    #[arg(long, value_name = "DIR")]
    scenes_dir: Option<PathBuf>,
    /// Families, comma-separated: beam, membrane, spectrum (the default), hertz, flat-punch (or patch, its old name), two-body (rows that couple DOFs).
    #[arg(long, value_delimiter = ',')]
    families: Option<Vec<String>>,
    /// Scenes per family.
    #[arg(long)]
    count: Option<usize>,
    /// Master seed (ChaCha8 streams per scene).
    #[arg(long)]
    seed: Option<u64>,
    /// ε grid for `constant`: LO:HI:N, log-spaced, inclusive.
    #[arg(long, value_name = "LO:HI:N")]
    eps: Option<String>,
    /// Factors for `scaled`, comma-separated.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    factors: Option<Vec<f64>>,
    /// Absolute δ values, comma-separated.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    deltas: Option<Vec<f64>>,
    /// Relative δ values R, comma-separated: δ = R times the largest unconstrained gap |d_cᵀu₀ − û_c| over the constraints.
    #[arg(long, value_delimiter = ',', allow_negative_numbers = true)]
    deltas_rel: Option<Vec<f64>>,
    /// Methods, comma-separated (lagrange always runs as the reference).
    #[arg(long, value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Metrics, comma-separated: cond, det, solver ("none" for none). `solver` (not in the
    /// default) adds cond2_jacobi, CG iterations with Jacobi and IC(0), MINRES for lagrange
    /// and the direct solve's forward errors (metrics::solver).
    #[arg(long, value_delimiter = ',')]
    metrics: Option<Vec<String>>,
    /// Relative accuracy asked of every cond₂, in (0, 1) (default: the accuracy contract,
    /// max(1e-12, 4·ε_mach·cond₂)); looser is faster, the bounds stay proven.
    #[arg(long, allow_negative_numbers = true)]
    cond_tol: Option<f64>,
    /// With --metrics solver: the relative error of u the Krylov counts *_to_err are taken to
    /// (‖u_k − u*‖∞ ≤ e‖u*‖∞, u* the refined direct solution), in (0, 1) [default: 1e-6].
    #[arg(long, allow_negative_numbers = true)]
    krylov_err: Option<f64>,
}

impl ConfigArgs {
    /// The configuration: the TOML file (or the default) with every given flag applied,
    /// validated. Absolute δs given alone replace the relative ones and vice versa.
    pub fn config(&self) -> Result<SweepConfig> {
        let a = self;
        let (mut c, text) = match &a.config {
            Some(p) => {
                let (c, text) = crate::provenance::read_toml_with_text(p)?;
                (c, Some(text))
            }
            None => (SweepConfig::default(), None),
        };
        if let Some(v) = &a.families {
            c.families = v
                .iter()
                .map(|s| Family::from_name(s.trim()))
                .collect::<Result<_>>()?;
        }
        if let Some(v) = a.count {
            c.count = v;
        }
        if let Some(v) = a.seed {
            c.seed = v;
        }
        if let Some(v) = &a.eps {
            c.eps = LogGrid::parse(v)?;
        }
        if let Some(v) = &a.factors {
            c.factors = v.clone();
        }
        if let Some(v) = &a.deltas {
            c.deltas = v.clone();
            if a.deltas_rel.is_none() {
                c.deltas_rel.clear();
            }
        }
        if let Some(v) = &a.deltas_rel {
            c.deltas_rel = v.clone();
            if a.deltas.is_none() {
                c.deltas.clear();
            }
        }
        if let Some(v) = &a.methods {
            c.methods = registry::lookup_all(v)?;
        }
        if let Some(v) = &a.metrics {
            c.metrics = v
                .iter()
                .map(|s| s.trim())
                .filter(|s| *s != "none")
                .map(Metric::from_name)
                .collect::<Result<_>>()?;
        }
        if let Some(t) = a.cond_tol {
            c.cond_tol = Some(t);
        }
        if let Some(e) = a.krylov_err {
            c.krylov_err = e;
        }
        if let Some(d) = &a.scenes_dir {
            c.scenes_dir = Some(d.clone());
        }
        if c.scenes_dir.is_some() {
            // Flags that shape generated scenes mean nothing for scene files: refused, not
            // ignored.
            for (flag, given) in [
                ("--families", a.families.is_some()),
                ("--count", a.count.is_some()),
            ] {
                if given {
                    return Err(Error::unsupported(
                        flag,
                        "generated scenes (with --scenes-dir the scenes are the folder's files)",
                    ));
                }
            }
        }
        c.check().map_err(|(field, e)| {
            let Some((table, key)) = field else {
                return e;
            };
            // Set by a flag (which replaces the file's value): the flag.
            if let Some(flag) = table.is_none().then(|| a.flag_of(key)).flatten() {
                return e.for_flag(flag);
            }
            // Else from the file where it sets the key: its key and line.
            match (&a.config, &text) {
                (Some(path), Some(text)) => {
                    crate::provenance::in_toml_file(e, path, text, table, key)
                }
                _ => e,
            }
        })?;
        Ok(c)
    }

    /// The flag that set the top-level configuration field `key`, where one was given (its
    /// value then replaced the file's); giving `--deltas` alone also clears `deltas_rel`, and
    /// vice versa, so either flag sets both.
    fn flag_of(&self, key: &str) -> Option<&'static str> {
        let given = |set: bool, flag: &'static str| set.then_some(flag);
        let deltas = self.deltas.is_some() || self.deltas_rel.is_some();
        match key {
            "families" => given(self.families.is_some(), "--families"),
            "count" => given(self.count.is_some(), "--count"),
            "eps" => given(self.eps.is_some(), "--eps"),
            "factors" => given(self.factors.is_some(), "--factors"),
            "deltas" => given(deltas, "--deltas"),
            "deltas_rel" => given(deltas, "--deltas-rel"),
            "methods" => given(self.methods.is_some(), "--methods"),
            "metrics" => given(self.metrics.is_some(), "--metrics"),
            "cond_tol" => given(self.cond_tol.is_some(), "--cond-tol"),
            "krylov_err" => given(self.krylov_err.is_some(), "--krylov-err"),
            _ => None,
        }
    }
}

/// Most worker threads `--threads` takes (more is a typo: every thread is an OS thread).
pub const MAX_THREADS: usize = 1024;

/// The `sweep` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    #[command(subcommand)]
    merge: Option<Merge>,
    #[command(flatten)]
    config: ConfigArgs,
    /// Worker threads (default: all cores). Results do not depend on it.
    #[arg(long)]
    threads: Option<usize>,
    /// Run shard K of N (contiguous blocks of scenes): K/N.
    #[arg(long, value_name = "K/N")]
    shard: Option<String>,
    /// Also write every scene as a scene file (re-runnable with `solve`).
    #[arg(long, value_name = "DIR")]
    write_scenes: Option<PathBuf>,
    /// With --write-scenes: store every K as dense rows, whatever its structure (benchmarks).
    #[arg(long, requires = "write_scenes")]
    dense_scenes: bool,
}

#[derive(clap::Subcommand, Debug)]
enum Merge {
    /// Merge the shard folders of one run into OUT (rows in scene order, one manifest); refuses
    /// missing, duplicated, incomplete or foreign shards.
    Merge {
        /// Output folder (not one of the shards).
        out: PathBuf,
        /// The shard folders, in any order.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
    },
}

/// What one `sweep` invocation does. As JSON (what identifies the run in `--out`,
/// [`crate::study::out_guard`]): `{"run": {"config": …, "shard": …}}` or `{"merge": [dirs]}`.
#[derive(Debug)]
pub enum SweepJob {
    /// Run the sweep of this configuration (`--out` is [`RunOptions::out`]).
    Run(Box<SweepConfig>, RunOptions),
    /// Merge the shard folders `dirs` into `out`.
    Merge {
        /// The merged folder.
        out: PathBuf,
        /// The shard folders.
        dirs: Vec<PathBuf>,
    },
}

impl Serialize for SweepJob {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::Error as _;
        let v = match self {
            SweepJob::Run(cfg, opts) => merge::run_identity(
                serde_json::to_value(cfg).map_err(S::Error::custom)?,
                opts.shard,
            ),
            SweepJob::Merge { dirs, .. } => serde_json::json!({ "merge": dirs }),
        };
        v.serialize(s)
    }
}

/// What a sweep folder holds: `manifest.json` (provenance, configuration, the run's counts and
/// timing) and the rows of `rows.csv`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct Record {
    /// `manifest.json` (`null` where the folder has none).
    pub manifest: serde_json::Value,
    /// `rows.csv` (empty where only counted, [`load_count`]).
    pub rows: Vec<Row>,
    /// The number of rows in `rows.csv`.
    pub rows_in_file: usize,
    /// The rows solved, failed and skipped per method.
    #[serde(default)]
    pub tally: crate::study::outcomes::Tally,
}

/// Reads `out/rows.csv` and, where present, `out/manifest.json`.
pub fn load(out: &Path) -> Result<Record> {
    let (rows, _) = rows::read_rows(&out.join("rows.csv"), false)?;
    let mut tally = crate::study::outcomes::Tally::default();
    for r in &rows {
        tally.add(&r.method, &r.warnings);
    }
    Ok(Record {
        manifest: read_manifest(out)?,
        rows_in_file: rows.len(),
        rows,
        tally,
    })
}

/// [`load`] for the report alone: the manifest, and the rows of rows.csv counted per method
/// ([`rows::tally_rows`]: the records checked, their values not converted).
pub fn load_count(out: &Path) -> Result<Record> {
    let tally = rows::tally_rows(&out.join("rows.csv"))?;
    Ok(Record {
        rows_in_file: tally.rows(),
        manifest: read_manifest(out)?,
        rows: Vec::new(),
        tally,
    })
}

/// `out/manifest.json`, `null` where there is none.
fn read_manifest(out: &Path) -> Result<serde_json::Value> {
    let m = out.join("manifest.json");
    if m.exists() {
        crate::provenance::read_json(&m)
    } else {
        Ok(serde_json::Value::Null)
    }
}

/// The study as the shared entry runs it. The rows and the manifest are written while the
/// sweep runs (so that `--resume` can complete a killed run), not by [`Study::save`]; its
/// [`Study::run`] returns an empty record, and the entry reads the folder back.
pub struct Sweep;

impl Study for Sweep {
    const NAME: &'static str = "sweep";
    const ABOUT: &'static str =
        "Sweep penalty ε and allowed penetration δ over randomized contact scenes";
    const PROGRESS: &'static str = "sweep";
    const DEFAULT_OUT: &'static str = "results/sweep";
    const RESUMABLE: bool = true;
    type Flags = Flags;
    type Config = SweepJob;
    type Record = Record;

    fn after_help() -> String {
        "Without arguments: the built-in default (beam, membrane, spectrum, 8 scenes each, every \
         method that handles bilateral ties) into results/sweep.\n`sweep merge OUT DIR...` \
         merges the shard folders of one run (--shard K/N) into OUT.\n--json prints the \
         manifest.\nExit status: 0 ok, 2 bad configuration or input, 4 a method failed on \
         every scene it ran on (rows and figures written; the summary names its first error)."
            .into()
    }

    fn config(a: &Flags) -> Result<SweepJob> {
        if let Some(Merge::Merge { out, dirs }) = &a.merge {
            return Ok(SweepJob::Merge {
                out: out.clone(),
                dirs: dirs.clone(),
            });
        }
        let cfg = a.config.config()?;
        let shard = a.shard.as_deref().map(super::parse_shard).transpose()?;
        if let Some(t) = a.threads.filter(|t| !(1..=MAX_THREADS).contains(t)) {
            return Err(Error::out_of_range(
                "--threads",
                t,
                format!("in 1..={MAX_THREADS}"),
            ));
        }
        let opts = RunOptions {
            threads: a.threads,
            shard,
            write_scenes: a.write_scenes.clone(),
            dense_scenes: a.dense_scenes,
            ..RunOptions::default()
        };
        Ok(SweepJob::Run(Box::new(cfg), opts))
    }

    /// `sweep merge` checks OUT itself (it must not exist) and records it as the unsharded
    /// run it is ([`merge::merge`]).
    fn guards_out(job: &SweepJob) -> bool {
        matches!(job, SweepJob::Run(..))
    }

    fn out_override(job: &SweepJob) -> Option<PathBuf> {
        match job {
            SweepJob::Merge { out, .. } => Some(out.clone()),
            SweepJob::Run(..) => None,
        }
    }

    fn run(job: &SweepJob, ctx: &RunContext) -> Result<Record> {
        match job {
            SweepJob::Merge { out, dirs } => {
                merge::merge(out, dirs, ctx.provenance)?;
            }
            SweepJob::Run(cfg, opts) => {
                let opts = RunOptions {
                    out: ctx.out.to_path_buf(),
                    resume: ctx.resume,
                    progress: !ctx.quiet,
                    provenance: Some(ctx.provenance.clone()),
                    ..opts.clone()
                };
                super::run(cfg, &opts)?;
            }
        }
        // The folder is the record: the entry reads it back after `save` (as `--render-only`
        // would), so it is not read here too.
        Ok(Record {
            manifest: serde_json::Value::Null,
            rows: Vec::new(),
            rows_in_file: 0,
            tally: Default::default(),
        })
    }

    /// Nothing: the run wrote its folder.
    fn save(_: &Path, _: &SweepJob, _: &Record, _: &crate::provenance::Provenance) -> Result<()> {
        Ok(())
    }

    fn load(out: &Path) -> Result<Record> {
        load(out)
    }

    fn load_report(out: &Path) -> Result<Record> {
        load_count(out)
    }

    fn figures(rec: &Record) -> Result<Vec<Drawing>> {
        Ok(figures::drawings(&rec.rows))
    }

    fn report(rec: &Record) -> String {
        report::text(&rec.manifest, rec.rows_in_file, &rec.tally)
    }

    /// Exit status 4 where a method failed on every row it ran (skipped rows aside).
    fn failure(rec: &Record) -> Option<String> {
        rec.tally.all_failed()
    }

    fn json(rec: &Record) -> Result<String> {
        crate::provenance::json_text("sweep manifest", &rec.manifest)
    }
}
