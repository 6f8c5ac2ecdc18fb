//! `paper_beam`: the paper's beam example (Sec. 4.2, Eq. 30–37) number by number.
//!
//! ```text
//! cargo run --release --bin paper_beam                      # compute, write data, render, print
//! cargo run --release --bin paper_beam -- --json            # the comparison as JSON on stdout
//! cargo run --release --bin paper_beam -- --render-only     # re-render figures from saved data
//! ```
//!
//! Writes into `--out` (default `figures/paper_beam`) `paper_beam.json` (every number the paper
//! prints next to ours, the `condensed` comparison, one line per strategy, the notes and the
//! computations behind them, provenance), `deflection.csv`, `cond_vs_eps.csv` and the figures
//! `fig3_deflection_free`, `fig4_deflection_contact`, `cond_vs_eps` (PNG + SVG), rendered from
//! the saved files only. The study is `penalty_lab::study::paper_beam`.

use clap::Parser;
use penalty_lab::study::paper_beam::{self, figures, summary};
use penalty_lab::{provenance, Result};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "paper_beam",
    version = penalty_lab::provenance::VERSION,
    about = "The paper's beam example (Eq. 30-37): paper's numbers vs ours, data files and figures"
)]
struct Args {
    /// Output directory for the data files and figures.
    #[arg(long, default_value = "figures/paper_beam")]
    out: PathBuf,
    /// Re-render the figures from the data saved in --out, without recomputing.
    #[arg(long)]
    render_only: bool,
    /// Print the comparison as JSON (the content of paper_beam.json) instead of the table.
    #[arg(long)]
    json: bool,
}

fn run(args: &Args) -> Result<()> {
    if !args.render_only {
        paper_beam::save(&args.out, &paper_beam::run()?)?;
    }
    // Figures are drawn from what was written, exactly as --render-only would.
    let study = paper_beam::load(&args.out)?;
    let written = figures::render_figures(&args.out, &study)?;
    if args.json {
        println!(
            "{}",
            provenance::json_text("paper_beam results", &study.record)?
        );
        return Ok(());
    }
    print!("{}", summary::text(&study.record));
    println!("Data: {}", args.out.display());
    for f in [
        paper_beam::JSON_FILE,
        paper_beam::DEFLECTION_FILE,
        paper_beam::COND_FILE,
    ] {
        println!("  {}", args.out.join(f).display());
    }
    println!("Figures:");
    for f in written {
        println!("  {}", f.display());
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
