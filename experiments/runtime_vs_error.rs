//! `runtime_vs_error`: time to solution against error for every strategy as its knob varies,
//! on beam and membrane scenes from 10² to 10⁶ DOFs. Library: [`penalty_lab::study::runtime_vs_error`].
//!
//! ```text
//! cargo run --release --bin runtime_vs_error -- --smoke --json       # seconds
//! cargo run --release --bin runtime_vs_error                         # 10²…10⁶ DOFs, 3 repeats
//! cargo run --release --bin runtime_vs_error -- --sizes 100,10000 --repeats 5 --out results/rve
//! cargo run --release --bin runtime_vs_error -- --render-only --out figures/runtime_vs_error
//! ```
//!
//! Writes `OUT/rows.csv` (for spreadsheets), `OUT/rows.json` (every field, exact),
//! `OUT/manifest.json` (git commit, config, crate versions, wall time) and
//! `OUT/figures/*.{png,svg}`, rendered from `rows.json` once it is written (`--render-only`
//! re-renders from it without measuring); progress goes to stderr. A strategy that errors or would
//! exceed the per-solve budget at some size is recorded as a row with the reason; the run goes
//! on. Bad input exits with status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::progress::Progress;
use penalty_lab::strategy::registry;
use penalty_lab::study::runtime_vs_error::{self, report, PerfConfig};
use penalty_lab::{provenance, Error};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(
    name = "runtime_vs_error",
    version = penalty_lab::provenance::VERSION,
    about = "Time to solution against error for every contact strategy, as its knob varies, at increasing size",
    after_help = "Knobs: ε for constant (relative to max K[d,d]), factor for scaled, δ for \
                  spring/paper/condensed and the tolerance for augmented (relative to the \
                  displacement scale).\nExit status: 0 ok, 2 bad input."
)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = "results/runtime_vs_error")]
    out: PathBuf,
    /// Small and quick: sizes 100 and 1000, 1 repeat, 3 knob values per strategy.
    #[arg(long)]
    smoke: bool,
    /// Print the rows and manifest as one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
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
    /// Skip the figures.
    #[arg(long)]
    no_figures: bool,
    /// Re-render the figures from `OUT/rows.json` without measuring.
    #[arg(long, conflicts_with_all = ["smoke", "json", "no_figures"])]
    render_only: bool,
}

fn config(a: &Args) -> Result<PerfConfig, Error> {
    let mut cfg = PerfConfig::preset(a.smoke);
    cfg.families = a.families.iter().map(|s| s.trim().to_string()).collect();
    if let Some(s) = &a.sizes {
        cfg.sizes = s.clone();
    }
    if let Some(m) = &a.methods {
        cfg.methods = m.clone();
    }
    cfg.repeats = a.repeats.unwrap_or(cfg.repeats);
    cfg.budget_seconds = a.budget;
    cfg.max_constraints = a.max_constraints;
    cfg.memory_limit_bytes = a.memory_gb * 1e9;
    cfg.validate()?;
    Ok(cfg)
}

fn run(a: &Args) -> Result<(), Error> {
    let render = || -> Result<(), Error> {
        let n = report::render(&a.out)?;
        eprintln!(
            "rendered {n} figure files into {}",
            a.out.join("figures").display()
        );
        Ok(())
    };
    if a.render_only {
        return render();
    }
    let cfg = config(a)?;
    let t0 = Instant::now();
    let rows = runtime_vs_error::run(&cfg, &Progress::new("runtime_vs_error (points)", a.quiet))?;
    let wall = t0.elapsed().as_secs_f64();
    let manifest = report::save(&a.out, &cfg, a.smoke, &rows, wall)?;
    if !a.no_figures {
        render()?;
    }
    eprintln!(
        "runtime_vs_error: {} rows ({} ok, {} errors, {} skipped) in {wall:.1} s → {}",
        rows.len(),
        manifest["ok"],
        manifest["errors"],
        manifest["skipped"],
        a.out.display()
    );
    if a.json {
        let all = json!({"manifest": manifest, "rows": rows});
        println!("{}", provenance::json_text("runtime_vs_error", &all)?);
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
