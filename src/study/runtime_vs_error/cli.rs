//! The `runtime_vs_error` binary's flags and the study as the shared entry runs it
//! ([`crate::study::shape::main`]).

use super::record::{self, Record};
use super::{figures, report, PerfConfig};
use crate::error::Result;
use crate::strategy::registry;
use crate::study::shape::{Drawing, RunContext, Study};
use std::path::Path;
use std::time::Instant;

/// The `runtime_vs_error` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Small and quick: sizes 100 and 1000, 1 repeat, 3 knob values per strategy.
    #[arg(long)]
    smoke: bool,
    /// Requested DOF counts, comma-separated (default 100,1000,10000,100000,1000000; smoke
    /// 100,1000).
    #[arg(long, value_delimiter = ',')]
    sizes: Option<Vec<usize>>,
    /// Families, comma-separated: beam, membrane.
    #[arg(long, value_delimiter = ',', default_value = "beam,membrane")]
    families: Vec<String>,
    /// Methods, comma-separated (default: every built-in one but optimal).
    #[arg(long, value_parser = registry::method_parser(), value_delimiter = ',')]
    methods: Option<Vec<String>>,
    /// Timed repeats per point; the median is reported (default 3; smoke 1).
    #[arg(long)]
    repeats: Option<usize>,
    /// Per-solve time budget in seconds: a method predicted to exceed it at a size is skipped.
    #[arg(long, default_value_t = 30.0)]
    budget: f64,
    /// Maximum contact constraints per scene.
    #[arg(long, default_value_t = 400)]
    max_constraints: usize,
    /// Memory limit for condensed's N×m block, in GB.
    #[arg(long, default_value_t = 4.0)]
    memory_gb: f64,
}

/// The study as the shared entry runs it.
pub struct RuntimeVsError;

impl Study for RuntimeVsError {
    const NAME: &'static str = "runtime_vs_error";
    const ABOUT: &'static str = "Time to solution against error for every contact strategy, as its knob varies, at increasing size";
    const PROGRESS: &'static str = "runtime_vs_error (points)";
    const DEFAULT_OUT: &'static str = "results/runtime_vs_error";
    type Flags = Flags;
    /// The configuration and `--smoke`.
    type Config = (PerfConfig, bool);
    type Record = Record;

    fn after_help() -> String {
        "Knobs: ε for constant (relative to max K[d,d]), factor for scaled, δ for \
         spring/paper/condensed and the tolerance for augmented (relative to the displacement \
         scale).\nExit status: 0 ok, 2 bad input."
            .into()
    }

    fn config(a: &Flags) -> Result<(PerfConfig, bool)> {
        let mut cfg = PerfConfig::preset(a.smoke);
        cfg.families = super::parse_families(&a.families)?;
        if let Some(s) = &a.sizes {
            cfg.sizes = s.clone();
        }
        if let Some(m) = &a.methods {
            cfg.methods = registry::lookup_all(m)?;
        }
        cfg.repeats = a.repeats.unwrap_or(cfg.repeats);
        cfg.budget_seconds = a.budget;
        cfg.max_constraints = a.max_constraints;
        cfg.memory_limit_bytes = a.memory_gb * 1e9;
        cfg.validate()?;
        Ok((cfg, a.smoke))
    }

    fn run((cfg, smoke): &(PerfConfig, bool), ctx: &RunContext) -> Result<Record> {
        let t0 = Instant::now();
        let rows = super::run(cfg, ctx.progress)?;
        Ok(record::record(
            cfg,
            *smoke,
            rows,
            t0.elapsed().as_secs_f64(),
            ctx.provenance,
        ))
    }

    fn save(
        out: &Path,
        _: &(PerfConfig, bool),
        rec: &Record,
        _provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        record::save(out, rec)
    }

    fn load(out: &Path) -> Result<Record> {
        record::load(out)
    }

    fn figures(rec: &Record) -> Result<Vec<Drawing>> {
        Ok(figures::drawings(&rec.rows))
    }

    fn report(rec: &Record) -> String {
        report::text(rec)
    }
}
