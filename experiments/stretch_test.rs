//! `stretch_test`: the paper's first example (classical ε = 1e7: cond 2.705e5, modified
//! δ = 1e-5 in: cond 3.721e2; its geometry figure is lost), rebuilt as the clamped
//! hemispherical-punch stretching test with published geometry (Ghosh–Hecker, forming.md),
//! converted to inches: clamp radius 2.330 in, punch radius 2.0 in, die profile radius
//! 0.25 in, the paper's sheet t = 0.035 in, μ = 0.2, 50 elements, 100 steps to 0.8 in.
//!
//! ```text
//! cargo run --release --bin stretch_test -- --json
//! cargo run --release --bin stretch_test -- --out figures/stretch_test
//! cargo run --release --bin stretch_test -- --render-only --out figures/stretch_test
//! ```
//!
//! `--json` prints `cond2_classical`, `cond2_adaptive` (Eq. 28 on the residual) and
//! `cond2_condensed` at
//! the **representative step = the last step (full punch travel)**, their medians over all
//! steps, and the per-step series of every run. Bad input exits with status 2; a run outside the
//! model's domain with status 3 (`--allow-invalid` keeps it, marked `"valid": false`).

use clap::Parser;
use penalty_lab::study::forming_runs::{self, Cli};
use penalty_lab::study::stretch_test;
use penalty_lab::Error;
use std::process::ExitCode;

#[derive(Parser, Debug)]
#[command(
    name = "stretch_test",
    version = penalty_lab::provenance::VERSION,
    about = "Clamped hemispherical-punch stretching (paper's first example): classical vs adaptive penalty",
    after_help = format!(
        "Default travel 0.8 in. Units: inch, ton-force, second. {}",
        forming_runs::EXIT_STATUSES
    )
)]
struct Args {
    #[command(flatten)]
    cli: Cli,
}

fn run(a: &Args) -> Result<(), Error> {
    let doc = a.cli.execute(stretch_test::EXPERIMENT)?;
    if a.cli.json {
        println!(
            "{}",
            serde_json::to_string(&stretch_test::json_summary(&doc))
                .map_err(|e| Error::Numerical(format!("cannot serialize: {e}")))?
        );
    } else {
        print!("{}", forming_runs::summary_table(&doc));
    }
    Ok(())
}

fn main() -> ExitCode {
    let args = Args::parse();
    penalty_lab::error::run_main(|| run(&args))
}
