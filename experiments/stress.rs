//! `stress`: absurd penalties and near-singular systems — forward error against an
//! extended-precision reference, what iterative refinement and equilibration buy, and every
//! strategy at extreme knobs (no NaN/Inf, no panic, warnings where digits are lost).
//!
//! ```text
//! cargo run --release --bin stress -- --out figures/stress
//! cargo run --release --bin stress -- --families spectrum --count 4 --eps 1e-3:1e20:24 --json
//! ```
//!
//! Writes `OUT/eps_study.csv`, `OUT/strategies.csv` (for spreadsheets), `OUT/eps_study.json`
//! (every field of the ε study, exact), `OUT/stress.json` (git commit, config, seed, summary)
//! and `OUT/figures/*.{png,svg}`, rendered from `eps_study.json` once it is written
//! (`--render-only --out DIR` re-renders from it without running). Library:
//! [`penalty_lab::study::stress`] ([`penalty_lab::study::stress::report`] runs it). Bad input exits with status 2 and one line on stderr.

use clap::Parser;
use penalty_lab::progress::Progress;
use penalty_lab::study::stress::report::{self, StressRun};
use penalty_lab::study::stress::StressConfig;
use penalty_lab::study::sweep::LogGrid;
use penalty_lab::{provenance, Error};
use serde_json::json;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "stress",
    version = penalty_lab::provenance::VERSION,
    about = "Stability stress: forward error vs ε and cond, refinement and scaling, strategies at extreme knobs",
    after_help = "Scenes: the paper's beam (bilateral and upper) plus COUNT generated scenes per \
                  family, small enough for the double-double reference.\nExit status: 0 ok, 2 bad \
                  input."
)]
struct Args {
    /// Output folder.
    #[arg(long, default_value = "results/stress")]
    out: PathBuf,
    /// Print all results as one JSON object on stdout.
    #[arg(long)]
    json: bool,
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
    /// Skip the figures.
    #[arg(long)]
    no_figures: bool,
    /// Re-render the figures from `OUT/eps_study.json` without running.
    #[arg(long, conflicts_with_all = ["json", "no_figures"])]
    render_only: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
}

/// Renders the figures from `OUT/eps_study.json` and says how many it wrote.
fn render(out: &std::path::Path) -> Result<(), Error> {
    let n = report::render(out)?;
    eprintln!(
        "rendered {n} figure files into {}",
        out.join("figures").display()
    );
    Ok(())
}

fn run(a: &Args) -> Result<(), Error> {
    if a.render_only {
        return render(&a.out);
    }
    let r = StressRun {
        seed: a.seed,
        count: a.count,
        families: a
            .families
            .iter()
            .map(|s| s.trim().to_string())
            .filter(|s| !s.is_empty() && s != "none")
            .collect(),
        config: StressConfig {
            eps: LogGrid::parse(&a.eps)?.values(),
            max_steps: a.max_steps,
            ..StressConfig::default()
        },
    };
    let o = report::run(&r, &Progress::new("stress (scenes)", a.quiet))?;
    let record = report::record(&r, &o);
    report::write(&a.out, &o, &record)?;
    if !a.no_figures && !o.eps_rows.is_empty() {
        render(&a.out)?;
    }
    let s = &record["summary"];
    eprintln!(
        "stress: {} scenes, {} ε points, {} strategy runs ({} ok, {} clean errors, {} non-finite, {} panics) in {:.1} s → {}",
        o.scenes.len(),
        o.eps_rows.len(),
        o.strategy_rows.len(),
        s["ok"],
        s["clean_errors"],
        s["non_finite"],
        s["panics"],
        o.wall_seconds,
        a.out.display()
    );
    if a.json {
        let all = json!({
            "manifest": record,
            "eps_study": o.eps_rows,
            "strategies": o.strategy_rows,
        });
        println!("{}", provenance::json_text("stress", &all)?);
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
