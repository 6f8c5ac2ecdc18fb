//! The `stress` binary's flags and the study as the shared entry runs it
//! ([`crate::study::shape::main`]).

use super::record::{self, Record, StressRun};
use super::{figures, report, StressConfig};
use crate::error::Result;
use crate::generate::{self, Family};
use crate::study::grid::LogGrid;
use crate::study::shape::{Drawing, RunContext, Study};
use std::path::Path;

/// The `stress` binary's flags.
#[derive(clap::Args, Debug)]
pub struct Flags {
    /// Master seed of the generated scenes.
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Generated scenes per family.
    #[arg(long, default_value_t = 2)]
    count: usize,
    /// Families of generated scenes, comma-separated (beam, membrane, spectrum); "none" for
    /// the paper's beam only.
    #[arg(long, value_delimiter = ',', default_value = "beam,membrane,spectrum")]
    families: Vec<String>,
    /// Uniform-ε grid LO:HI:N (log-spaced, inclusive).
    #[arg(long, value_name = "LO:HI:N", default_value = "1e-3:1e20:47")]
    eps: String,
    /// Maximum iterative-refinement steps.
    #[arg(long, default_value_t = 10)]
    max_steps: usize,
}

/// The study as the shared entry runs it.
pub struct Stress;

impl Study for Stress {
    const NAME: &'static str = "stress";
    const ABOUT: &'static str =
        "Stability stress: forward error vs ε and cond, refinement and scaling, strategies at extreme knobs";
    const PROGRESS: &'static str = "stress (scenes)";
    const DEFAULT_OUT: &'static str = "results/stress";
    type Flags = Flags;
    type Config = StressRun;
    type Record = Record;

    fn after_help() -> String {
        "Scenes: the paper's beam (bilateral and upper) plus COUNT generated scenes per family, \
         small enough for the double-double reference.\nExit status: 0 ok, 2 bad input."
            .into()
    }

    fn config(a: &Flags) -> Result<StressRun> {
        let run = StressRun {
            seed: a.seed,
            count: a.count,
            families: parse_families(&a.families)?,
            config: StressConfig {
                eps: LogGrid::parse(&a.eps)?.values(),
                max_steps: a.max_steps,
                ..StressConfig::default()
            },
        };
        run.validate()?;
        Ok(run)
    }

    fn run(r: &StressRun, ctx: &RunContext) -> Result<Record> {
        let o = record::run(r, ctx.progress)?;
        Ok(Record {
            manifest: record::record(r, &o, ctx.provenance),
            eps_study: o.eps_rows,
            strategies: o.strategy_rows,
        })
    }

    fn save(
        out: &Path,
        _: &StressRun,
        rec: &Record,
        _provenance: &crate::provenance::Provenance,
    ) -> Result<()> {
        record::write(out, rec)
    }

    fn load(out: &Path) -> Result<Record> {
        record::load(out)
    }

    fn figures(rec: &Record) -> Result<Vec<Drawing>> {
        Ok(figures::drawings(&rec.eps_study))
    }

    fn report(rec: &Record) -> String {
        report::text(rec)
    }
}

/// `--families` parsed: every name but `none` (and empty entries) as a family; an unknown one
/// is an error listing the valid names.
fn parse_families(names: &[String]) -> Result<Vec<Family>> {
    let named: Vec<&str> = names
        .iter()
        .map(|s| s.trim())
        .filter(|s| !s.is_empty())
        .collect();
    match named[..] {
        [] => Err(crate::error::Error::none_given(
            "--families",
            format!(" (valid: {}, or none)", generate::FAMILY_NAMES.join(", ")),
        )),
        ["none"] => Ok(Vec::new()),
        _ if named.contains(&"none") => Err(crate::error::Error::unsupported(
            "--families none",
            "to stand alone (it means the paper's beam only)",
        )),
        _ => generate::parse_families(&named, &generate::ALL_FAMILIES, ", or none"),
    }
}
