//! `cond_cost`: what an exact cond₂ costs, by route, against one Cholesky of the same matrix.
//!
//! ```text
//! cargo run --release --bin cond_cost                       # default sizes, table on stdout
//! cargo run --release --bin cond_cost -- --sides 20,40,80 --repeats 3 --json
//! cargo run --release --bin cond_cost -- --render-only      # re-render from saved data
//! ```
//!
//! The study is [`penalty_lab::study::cond_cost`]. Writes `cond_cost.csv`, `cond_cost.json` (with
//! provenance) and the figure `cond_cost` (time vs n, log–log, with least-squares slopes in
//! the legend) into `--out` (default `figures/cond_cost`).

use clap::Parser;
use penalty_lab::progress::Progress;
use penalty_lab::study::cond_cost::{self, CostConfig};
use penalty_lab::{provenance, Result};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "cond_cost",
    version = penalty_lab::provenance::VERSION,
    about = "Time of an exact cond2 by route (sparse inertia, dense eigen, dense SVD) against one Cholesky"
)]
struct Args {
    /// Membrane grid sides (n = side²).
    #[arg(long, value_delimiter = ',', default_values_t = [4usize, 6, 10, 14, 20, 45, 100, 224, 316])]
    sides: Vec<usize>,
    /// Cantilever element counts (n = 3·elements).
    #[arg(long, value_delimiter = ',', default_values_t = [4usize, 12, 40, 112, 150, 700, 3300, 33000])]
    elements: Vec<usize>,
    /// Repeats per measurement (the median is reported).
    #[arg(long, default_value_t = 5)]
    repeats: usize,
    /// Largest n for the dense routes.
    #[arg(long, default_value_t = 2100)]
    dense_max: usize,
    /// Output directory.
    #[arg(long, default_value = "figures/cond_cost")]
    out: PathBuf,
    /// Print the rows as JSON on stdout instead of the table.
    #[arg(long)]
    json: bool,
    /// Re-render the figure from `OUT/cond_cost.json` without measuring.
    #[arg(long)]
    render_only: bool,
    /// No progress bar or progress lines on stderr.
    #[arg(long)]
    quiet: bool,
}

fn run(a: &Args) -> Result<()> {
    let rows = if a.render_only {
        cond_cost::load(&a.out)?
    } else {
        let cfg = CostConfig {
            sides: a.sides.clone(),
            elements: a.elements.clone(),
            repeats: a.repeats,
            dense_max: a.dense_max,
        };
        let rows = cond_cost::run(&cfg, &Progress::new("cond_cost (matrices)", a.quiet))?;
        cond_cost::save(&a.out, &cfg, &rows)?;
        rows
    };
    cond_cost::render_figure(&rows, &a.out)?;
    if a.json {
        println!("{}", provenance::json_text("cond_cost rows", &rows)?);
    } else {
        print!("{}", cond_cost::table(&rows));
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
